//! `charlie_sheen`: Estevez and Kulla's "Charlie" sheen (2017), a microfacet lobe whose
//! distribution is an inverted power of the sine, with the Smith shadowing of their fit
//! of `Λ`.
//!
//! `f = kd/π + ks·D·G2/(4·mu_i·mu_o)`, `D = (2 + 1/α)·sin(θh)^(1/α)/(2π)`,
//! `G2 = 1/(1 + Λ(mu_i) + Λ(mu_o))` with the fitted `Λ` of [`sheen::LambdaFit`]; no
//! Fresnel term and no terminator softening (which would break reciprocity).

use super::albedo::{Importance, Term};
use super::sheen::{self, Colours, SHEEN_SPEC, Charlie, LambdaFit};
use super::spec::ModelSpec;
use super::{Directions, Kernel, ParamSource, WideRow};
use crate::math::geometry::WideCosine;
use crate::math::{PowTier, PowUnit, Real, SeriesPow};

/// The Charlie sheen kernel.
pub struct CharlieSheen;

// The sheen models' layout (`kd`, `ks`, `alpha`).
pub use super::sheen::{ALPHA, KD, KS, SLOTS};

pub static SPEC: ModelSpec = ModelSpec {
    name: "charlie_sheen",
    summary: "Charlie sheen: inverted-sine microfacet distribution with the fitted Smith shadowing",
    formula: "f = kd/π + ks·D·G2/(4·mu_i·mu_o), D = (2 + 1/α)·sin(θh)^(1/α)/(2π), \
              G2 = 1/(1 + Λ(mu_i) + Λ(mu_o)), Λ = Estevez & Kulla's fit",
    source: "Estevez & Kulla 2017 (Production Friendly Microfacet Sheen BRDF)",
    ..SHEEN_SPEC
};

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    colours: Colours<F>,
    charlie: Charlie<F>,
    fit: LambdaFit<F>,
}

/// The kernel's value with powers computed by `P`.
#[inline(always)]
fn eval_in<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
    let a = sheen::angles(d);
    let c_i = sheen::cosine_complement::<F>(d.n, d.wi, a.mu_i);
    let c_o = sheen::cosine_complement::<F>(d.n, d.wo, a.mu_o);
    let lambda_i = pp.fit.lambda_with::<P>(a.mu_i, c_i);
    let lambda_o = pp.fit.lambda_with::<P>(a.mu_o, c_o);
    let lobe = sheen::charlie_smith::<F, P>(&pp.charlie, &a, lambda_i, lambda_o);
    pp.colours.rgb(lobe, &a)
}

impl Kernel for CharlieSheen {
    type Prepared<F: Real> = Prepared<F>;

    const POWERS: bool = true;
    const WIDE_COSINES: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let alpha = ALPHA.read(p);
        Prepared {
            colours: Colours::read(p),
            charlie: Charlie::new(alpha),
            fit: LambdaFit::new(alpha),
        }
    }

    /// With a table-driven power (the eval engine's accurate tier,
    /// [`TablePow`](crate::math::TablePow), and its fast tier in `f64`) the powers are
    /// the series ones instead, as accurate: the tables' lookups, four or five per power
    /// and three powers per row, made LLVM keep the engine's block loop scalar (`f64` ran
    /// at a sixth of `f32`'s rate; the fast tier's at 0.43× the table-free power it had
    /// before, which ran as fast as the series one).
    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let tables = match P::TIER {
            PowTier::Table => true,
            PowTier::Fast => std::mem::size_of::<F>() == 8, // f64
            PowTier::Series => false,
        };
        if tables {
            eval_in::<F, SeriesPow>(pp, d)
        } else {
            eval_in::<F, P>(pp, d)
        }
    }

    /// Cosines below the `f64` range: the lobe divides by both, and `D` may be below the
    /// range too ([`sheen::smith_wide`]).
    fn eval_wide<F: Real>(pp: &Prepared<F>, d: &Directions<F>, w: &WideRow) -> [F; 3] {
        let a = sheen::angles(d);
        let lambda = |c: WideCosine| pp.fit.lambda::<SeriesPow>(F::from_f64(c.value())).to_f64();
        let g = 1.0 + lambda(w.mu_i) + lambda(w.mu_o);
        let lobe = sheen::smith_wide(pp.charlie.d_wide(a.sin2_th.to_f64()), g, w);
        pp.colours.rgb_wide(lobe, &a, w)
    }

    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(sheen::albedo_terms(slots, Importance::Uniform))
    }
}
