//! `beckmann`: the Beckmann microfacet BRDF with the exact Smith shadowing of its NDF and
//! Schlick's Fresnel (Walter et al. 2007).
//!
//! `f = kd/π + D·G2·F/(4·mu_i·mu_o)` with `D = exp(−tan²θh/α²)/(π α² cos⁴θh)`,
//! height-correlated `G2 = 1/(1 + Λ(mu_i) + Λ(mu_o))`, the exact Beckmann
//! `Λ(μ) = (erf(c) − 1)/2 + exp(−c²)/(2c·sqrt(π))`, `c = μ/(α·sqrt(1 − μ²))`, and
//! `F = F0 + (1−F0)(1−cos_b)^5`, `F0 = ks`.
//!
//! `G2/(4 mu_i mu_o)` is evaluated through `L = μ·Λ(μ) = μ(erf(c) − 1)/2 +
//! α·sinθ·exp(−c²)/(2 sqrt(π))`, bounded at grazing angles. `erf` is the `libm` crate's
//! (scalar: this model's loop does not vectorize).

use super::albedo::{Integral, Term, basis, colour};
use super::spec::{self, Family, ModelSpec, TangentUse};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::{
    above_both, clamped_cosine, half_vector, schlick_rgb, schlick_weight, smith_quotient, weighted,
};
use crate::math::{Real, Vector3};

/// The Beckmann kernel.
pub struct Beckmann;

pub static SPEC: ModelSpec = ModelSpec {
    name: "beckmann",
    family: Family::A,
    summary: "Beckmann microfacet BRDF, exact height-correlated Smith G2, Schlick F",
    formula: "f = kd/π + D·G2·F/(4·mu_i·mu_o), D = exp(−tan²θh/α²)/(π α² cos⁴θh), \
              G2 = 1/(1+Λ(mu_i)+Λ(mu_o)), Λ(μ) = (erf(c)−1)/2 + exp(−c²)/(2c·sqrt(π)), \
              c = μ/(α·sqrt(1−μ²)), F = ks + (1−ks)(1−cos_b)^5",
    source: "Beckmann & Spizzichino 1963; Walter et al. 2007; MODELS.md",
    params: &[
        spec::kd(0.0, 0),
        spec::f0(1.0, 3),
        spec::roughness("alpha", 0.5, 6, "roughness α: RMS slope of the microfacets"),
    ],
    tangent: TangentUse::None,
    reciprocal: true,
};

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    kd_over_pi: [F; 3],
    f0: [F; 3],
    alpha: F,
    alpha2: F,
}

/// `μ·Λ(μ)` of the Beckmann Smith function, from `μ` and `sin²θ`.
///
/// `μ·Λ = α·s·e/(2√π) − μ·erfc(c)/2` (`s = sinθ`, `c = μ/(α s)`, `e = exp(−c²)`; MODELS.md's
/// `(erf(c) − 1)/2` as `−erfc(c)/2`, which does not cancel as `c` grows). For `|c| ≥ 1.25`
/// erfc comes in parts, `erfc(c) = v + exp(−c² − 0.5625 + r)/c`, and `μ/c = α s` turns
/// its exponential term into `α s·e·exp(r − 0.5625)`: with the `e` already at hand, one
/// exponential more instead of erfc's two, and no division by `c`.
#[inline(always)]
pub fn mu_lambda<F: Real>(mu: F, sin2: F, alpha: F) -> F {
    let s = sin2.sqrt();
    let c = mu / (alpha * s);
    let e = (-(c * c)).exp();
    let (v, r, tail) = c.erfc_parts();
    let frac_1_sqrt_pi = F::from_f64(0.564_189_583_547_756_3);
    let tail_term = (r - F::from_f64(0.5625)).exp();
    let tail_term = if tail { tail_term } else { F::ZERO };
    let value = alpha * s * e * (frac_1_sqrt_pi - tail_term) * F::HALF - mu * v * F::HALF;
    // At normal incidence (s = 0) c is infinite and every term vanishes.
    if s > F::ZERO { value } else { F::ZERO }
}

impl Kernel for Beckmann {
    type Prepared<F: Real> = Prepared<F>;

    fn spec() -> &'static ModelSpec {
        &SPEC
    }

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let alpha = p.scalar(6);
        Prepared {
            kd_over_pi: p.colour(0).map(|c| c * F::FRAC_1_PI),
            f0: p.colour(3),
            alpha,
            alpha2: alpha * alpha,
        }
    }

    #[inline(always)]
    fn eval<F: Real>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let hv = half_vector::<F>(d.wi, d.wo);
        let cos_th = clamped_cosine::<F>(d.n, hv.h);
        let c2 = cos_th.cos * cos_th.cos;
        let sin2_th = cos_th.one_minus * (F::ONE + cos_th.cos);
        let t = sin2_th / (pp.alpha2 * c2);
        let ndf = (-t).exp() / (F::PI * pp.alpha2 * c2 * c2);
        // Far from the peak exp(−t) is 0 before cos⁴ underflows: never 0/0.
        let ndf = if t < F::from_f64(700.0) { ndf } else { F::ZERO };
        let l_i = mu_lambda(mu_i, d.n.cross(d.wi).length_squared(), pp.alpha);
        let l_o = mu_lambda(mu_o, d.n.cross(d.wo).length_squared(), pp.alpha);
        // D is 0 far from the peak, where G2/(4 mu_i mu_o) alone may be infinite.
        let spec = smith_quotient(F::flush_subnormal(ndf), mu_i, mu_o, l_i, l_o);
        let spec = if hv.defined { spec } else { F::ZERO };
        let fresnel = schlick_rgb(pp.f0, schlick_weight(hv.cos_b));
        let rgb = [0, 1, 2].map(|c| weighted(fresnel[c], spec) + pp.kd_over_pi[c]);
        above_both(mu_i, mu_o, rgb)
    }

    /// `kd·1 + F0·I(F0 = 1) + (1 − F0)·I(F0 = 0)`, lobes drawn from the visible normals
    /// (Heitz & d'Eon 2014) with their closed-form weights `F·G2/G1(wi)`, bounded by 1
    /// ([`Integral::BeckmannVisible`]).
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        let f0 = colour(slots, 3);
        let alpha = slots[6];
        let lobe = |f0: f64| Integral::BeckmannVisible {
            alpha,
            f0,
            basis: basis(slots, &[(0, 0.0), (3, f0)]),
        };
        Some(vec![
            Term {
                colour: colour(slots, 0),
                integral: Integral::Exact(1.0),
            },
            Term {
                colour: f0,
                integral: lobe(1.0),
            },
            Term {
                colour: f0.map(|c| 1.0 - c),
                integral: lobe(0.0),
            },
        ])
    }
}
