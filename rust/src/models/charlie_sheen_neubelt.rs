//! `charlie_sheen_neubelt`: the Charlie sheen distribution (Estevez and Kulla 2017) with
//! Neubelt and Pettineo's visibility term (2013) in place of the Smith shadowing, as
//! Filament's cloth model and many real-time engines evaluate sheen.
//!
//! `f = kd/π + ks·D·V`, `D = (2 + 1/α)·sin(θh)^(1/α)/(2π)`,
//! `V = 1/(4(mu_i + mu_o − mu_i·mu_o))` ([`sheen::neubelt`], bounded).

use super::albedo::{Importance, Term};
use super::sheen::{self, Colours, SHEEN_SPEC, Charlie};
use super::spec::ModelSpec;
use super::{Directions, Kernel, ParamSource, WideRow};
use crate::math::{PowUnit, Real};

/// The Charlie sheen kernel with Neubelt and Pettineo's visibility.
pub struct CharlieSheenNeubelt;

// The sheen models' layout (`kd`, `ks`, `alpha`).
pub use super::sheen::{ALPHA, KD, KS, SLOTS};

pub static SPEC: ModelSpec = ModelSpec {
    name: "charlie_sheen_neubelt",
    summary: "Charlie sheen distribution with Neubelt and Pettineo's visibility term",
    formula: "f = kd/π + ks·D·V, D = (2 + 1/α)·sin(θh)^(1/α)/(2π), \
              V = 1/(4(mu_i + mu_o − mu_i·mu_o))",
    source: "Estevez & Kulla 2017 (the distribution); Neubelt & Pettineo 2013 (the visibility)",
    ..SHEEN_SPEC
};

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    colours: Colours<F>,
    charlie: Charlie<F>,
}

impl Kernel for CharlieSheenNeubelt {
    type Prepared<F: Real> = Prepared<F>;

    const POWERS: bool = true;
    const WIDE_COSINES: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        Prepared {
            colours: Colours::read(p),
            charlie: Charlie::new(ALPHA.read(p)),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let a = sheen::angles(d);
        let lobe = sheen::charlie_neubelt::<F, P>(&pp.charlie, &a);
        pp.colours.rgb(lobe, &a)
    }

    /// Cosines below the `f64` range: `V` divides by their sum, and `D` may be below the
    /// range too ([`sheen::neubelt_wide`]).
    fn eval_wide<F: Real>(pp: &Prepared<F>, d: &Directions<F>, w: &WideRow) -> [F; 3] {
        let a = sheen::angles(d);
        let lobe = sheen::neubelt_wide(pp.charlie.d_wide(a.sin2_th.to_f64()), w);
        pp.colours.rgb_wide(lobe, &a, w)
    }

    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(sheen::albedo_terms(slots, Importance::Uniform))
    }
}
