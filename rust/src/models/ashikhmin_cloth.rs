//! `ashikhmin_cloth`: Ashikhmin's velvet distribution (Ashikhmin and Premože 2007) with
//! Neubelt and Pettineo's visibility term, a cloth model of real-time engines.
//!
//! `f = kd/π + ks·D·V`, `D = (1 + 4·exp(−cot²θh/α²)/sin⁴θh)/(π(1 + 4α²))`,
//! `V = 1/(4(mu_i + mu_o − mu_i·mu_o))` ([`sheen::neubelt`]). The inverted Gaussian's
//! share is taken as 0 where `cot²θh/α²` is beyond 700 (the exponential is below 1e-304
//! there, and would underflow before `1/sin⁴θh` could overflow) and where `h = n`.

use super::albedo::{Importance, Term};
use super::sheen::{self, Colours, SHEEN_SPEC, Angles};
use super::spec::ModelSpec;
use super::{Directions, Kernel, ParamSource, WideRow};
use crate::math::{PowUnit, Real};

/// The Ashikhmin cloth kernel.
pub struct AshikhminCloth;

// The sheen models' layout (`kd`, `ks`, `alpha`).
pub use super::sheen::{ALPHA, KD, KS, SLOTS};

pub static SPEC: ModelSpec = ModelSpec {
    name: "ashikhmin_cloth",
    summary: "Ashikhmin's cloth (velvet) distribution with Neubelt and Pettineo's visibility term",
    formula: "f = kd/π + ks·D·V, D = (1 + 4·exp(−cot²θh/α²)/sin⁴θh)/(π(1 + 4α²)), \
              V = 1/(4(mu_i + mu_o − mu_i·mu_o))",
    source: "Ashikhmin & Premože 2007 (the distribution); Neubelt & Pettineo 2013 (the visibility)",
    ..SHEEN_SPEC
};

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    colours: Colours<F>,
    /// `1/α²`.
    inv_alpha2: F,
    /// `1/(π(1 + 4α²))`.
    scale: F,
}

/// Where `exp(−x)` is taken as 0.
const CUT: f64 = 700.0;

/// `D` at the half vector's angle.
#[inline(always)]
fn distribution<F: Real>(pp: &Prepared<F>, a: &Angles<F>) -> F {
    let x = a.cos2_th * pp.inv_alpha2 / a.sin2_th;
    // x is NaN (0/0 cannot happen: sin² + cos² = 1) or +inf at h = n: both cut.
    let alive = x < F::from_f64(CUT);
    let x = if alive { x } else { F::ZERO };
    let gaussian = F::from_f64(4.0) * (-x).exp() / (a.sin2_th * a.sin2_th);
    let gaussian = if alive { gaussian } else { F::ZERO };
    (F::ONE + gaussian) * pp.scale
}

impl Kernel for AshikhminCloth {
    type Prepared<F: Real> = Prepared<F>;

    const WIDE_COSINES: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let alpha = ALPHA.read(p);
        let alpha2 = alpha * alpha;
        Prepared {
            colours: Colours::read(p),
            inv_alpha2: F::ONE / alpha2,
            scale: F::FRAC_1_PI / (F::ONE + F::from_f64(4.0) * alpha2),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let a = sheen::angles(d);
        let lobe = sheen::neubelt(distribution(pp, &a), a.mu_i, a.mu_o);
        pp.colours.rgb(lobe, &a)
    }

    /// Cosines below the `f64` range: `V` divides by their sum ([`sheen::neubelt_wide`]).
    fn eval_wide<F: Real>(pp: &Prepared<F>, d: &Directions<F>, w: &WideRow) -> [F; 3] {
        let a = sheen::angles(d);
        let lobe = sheen::neubelt_wide((distribution(pp, &a).to_f64(), 0), w);
        pp.colours.rgb_wide(lobe, &a, w)
    }

    /// The lobe drawn from a mixture of cosine and uniform draws, mostly cosine near
    /// normal incidence (where a narrow lobe is nearly flat and cosine draws nearly
    /// exact) and mostly uniform near grazing incidence (where it peaks at grazing
    /// `wo`); for alpha above 1/2 the lobe is no longer flat at normal incidence and the
    /// cosine share falls to half of that at alpha = 1. `benches/sheen_sampling.py`
    /// measures the three samplers.
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        let wide = (2.0 * ALPHA.read(slots) - 1.0).clamp(0.0, 1.0);
        let cosine = (0.05 + 0.9 * mu.clamp(0.0, 1.0)) * (1.0 - 0.5 * wide);
        Some(sheen::albedo_terms(
            slots,
            Importance::CosineUniform { cosine },
        ))
    }
}
