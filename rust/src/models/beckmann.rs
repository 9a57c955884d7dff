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

use super::albedo::{Integral, Term};
// The layout of the microfacet models with Schlick's Fresnel (`kd`, `ks`, `alpha`).
pub use super::ggx::SLOTS;
use super::ggx::{
    ALPHA, KD, KS, SCHLICK_MICROFACET_SPEC, schlick_microfacet_params, schlick_microfacet_terms,
    schlick_microfacet_value,
};
use super::spec::ModelSpec;
use super::{Directions, Kernel, ParamSource, ggx};
use crate::math::geometry::{
    Cosine, clamped_cosine, smith_quotient,
};
use crate::math::{PowUnit, Real, Vector3, max};

/// The Beckmann kernel.
pub struct Beckmann;

pub static SPEC: ModelSpec = ModelSpec {
    name: "beckmann",
    summary: "Beckmann microfacet BRDF, exact height-correlated Smith G2, Schlick F",
    formula: "f = kd/π + D·G2·F/(4·mu_i·mu_o), D = exp(−tan²θh/α²)/(π α² cos⁴θh), \
              G2 = 1/(1+Λ(mu_i)+Λ(mu_o)), Λ(μ) = (erf(c)−1)/2 + exp(−c²)/(2c·sqrt(π)), \
              c = μ/(α·sqrt(1−μ²)), F = ks + (1−ks)(1−cos_b)^5",
    source: "Beckmann & Spizzichino 1963; Walter et al. 2007 (Smith Λ); Heitz 2014 (height-correlated G2)",
    params: &schlick_microfacet_params(ALPHA_DOC),
    ..SCHLICK_MICROFACET_SPEC
};

/// The roughness parameter's doc line (shared with the models on this lobe).
pub const ALPHA_DOC: &str = "roughness α: RMS slope of the microfacets";

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    kd_over_pi: [F; 3],
    f0: [F; 3],
    alpha: F,
    alpha2: F,
}

/// The parts of `2Λ(c) = e·d/c − v` that [`mu_lambda`] and [`lambda_of_c`] share:
/// `e = exp(−c²)`, `d = 1/sqrt(π) − exp(r − 0.5625)` (the exponential only in erfc's tails)
/// and `v`, with `erfc(c) = v + e·exp(r − 0.5625)/c` ([`Real::erfc_parts`]).
#[inline(always)]
fn smith_parts<F: Real>(c: F) -> (F, F, F) {
    let e = (-(c * c)).exp();
    let (v, r, tail) = c.erfc_parts();
    let frac_1_sqrt_pi = F::from_f64(0.564_189_583_547_756_3);
    let tail_term = (r - F::from_f64(0.5625)).exp();
    let tail_term = if tail { tail_term } else { F::ZERO };
    (e, frac_1_sqrt_pi - tail_term, v)
}

/// `μ·Λ(μ)` of the Beckmann Smith function, from `μ` and `sin²θ`.
///
/// `μ·Λ = α·s·e/(2√π) − μ·erfc(c)/2` (`s = sinθ`, `c = μ/(α s)`, `e = exp(−c²)`; docs/models.md's
/// `(erf(c) − 1)/2` as `−erfc(c)/2`, which does not cancel as `c` grows). For `|c| ≥ 1.25`
/// erfc comes in parts, `erfc(c) = v + exp(−c² − 0.5625 + r)/c`, and `μ/c = α s` turns
/// its exponential term into `α s·e·exp(r − 0.5625)`: with the `e` already at hand, one
/// exponential more instead of erfc's two, and no division by `c`.
#[inline(always)]
pub fn mu_lambda<F: Real>(mu: F, sin2: F, alpha: F) -> F {
    let s = sin2.sqrt();
    let c = mu / (alpha * s);
    let (e, d, v) = smith_parts(c);
    let value = alpha * s * e * d * F::HALF - mu * v * F::HALF;
    // At normal incidence (s = 0) c is infinite and every term vanishes.
    if s > F::ZERO { value } else { F::ZERO }
}

/// `Λ(c)` of the Beckmann Smith function from `c = μ/(α·sinθ) > 0`:
/// `(e^{−c²}/(c·sqrt(π)) − erfc(c))/2`, [`mu_lambda`] over `μ` with erfc in parts as there
/// (infinite as `c → 0`; 0 for `c = ∞`, and clamped at 0 past `c ≈ 27`, where both terms
/// underflow). For callers that hold `c` rather than `μ` and `sin²θ` (the integrator's
/// closed-form weights).
#[inline(always)]
pub fn lambda_of_c<F: Real>(c: F) -> F {
    let (e, d, v) = smith_parts(c);
    let value = (e * d / c - v) * F::HALF;
    if value > F::ZERO { value } else { F::ZERO }
}

/// Returns the scalar Beckmann lobe `D·G2/(4 mu_i mu_o)` (F = 1), the cosine
/// `cos_b = wi·h` its Fresnel term is evaluated at (with its complement) and whether the
/// lobe is defined (`wi ≠ −wo`; the caller gives 0 where it is not).
///
/// `f64`: written as `ggx`'s lobe is ([`super::ggx::lobe`]), every factor first-order
/// homogeneous in the lengths of `n`, `wi`, `wo` and `h`: `tan²θh = sin²θh/cos²θh` with
/// `sin²θh = |n − h|²·|n + h|²/4` is of degree 0 (`(1 − cos θh)(1 + cos θh)` from `n·h`
/// was not, and `exp(−tan²θh/α²)` carried that error times `tan²θh/α²`), `cos⁴θh` of
/// degree 4 in `|n|` and `|h|`, and `G2/(4 mu_i mu_o)` (a quotient of `μ`s and
/// `μ·Λ(μ)`s, each of degree 1 in `|n|` and its direction) of degree −2 in `|n|` and −1
/// in `|wi|`, `|wo|`. The value computed from the rounded unit vectors, whose length
/// errors are `e = |w|² − 1` ([`Real::length_error`]), then carries the factor
/// `1 − (3e_n + (e_i + e_o)/2 + 2e_h)`, and the lobe is multiplied by
/// `1 + 3e_n + (e_i + e_o)/2 + 2e_h` ([`microfacet_length_correction`]); `h` is the
/// corrected half vector ([`half_vector_exact`]).
/// `f32` keeps `sin²θh = (1 − cos θh)(1 + cos θh)` of the clamped cosine.
///
/// The fast tier leaves the length errors out, as `ggx`'s does ([`ggx::length_errors`]).
#[inline(always)]
pub fn lobe<F: Real, P: PowUnit>(d: &Directions<F>, alpha: F, alpha2: F) -> (F, Cosine<F>, bool) {
    let errors = ggx::length_errors::<F, P>(d);
    let mu_i = d.n.dot(d.wi);
    let mu_o = d.n.dot(d.wo);
    let hv = ggx::lobe_half_vector::<F, P>(d, errors);
    let (c2, sin2_th) = if F::EXACT_LENGTHS {
        // Below the horizon of n (only by rounding, with both cosines positive) D is 0.
        let cos_th = max(d.n.dot(hv.h), F::ZERO);
        let sin2_th =
            (d.n - hv.h).length_squared() * ((d.n + hv.h).length_squared() * F::from_f64(0.25));
        (cos_th * cos_th, sin2_th)
    } else {
        // `f32` (no length errors to divide out): the clamped cosine and its complement.
        // The form above measured worse there (`brdf-rs stress`, 99th percentile of
        // `beckmann_f82` 8 ulps against 5).
        let cos_th = clamped_cosine::<F>(d.n, hv.h);
        (
            cos_th.cos * cos_th.cos,
            cos_th.one_minus * (F::ONE + cos_th.cos),
        )
    };
    let t = sin2_th / (alpha2 * c2);
    let ndf = (-t).exp() / (F::PI * alpha2 * c2 * c2);
    // Far from the peak exp(−t) is 0 before cos⁴ underflows: never 0/0 (nor inf/inf at
    // cos θh = 0, where t is infinite or NaN).
    let ndf = if t < F::from_f64(700.0) { ndf } else { F::ZERO };
    let l_i = mu_lambda(mu_i, d.n.cross(d.wi).length_squared(), alpha);
    let l_o = mu_lambda(mu_o, d.n.cross(d.wo).length_squared(), alpha);
    // D is 0 far from the peak, where G2/(4 mu_i mu_o) alone may be infinite.
    let spec = smith_quotient(F::flush_subnormal(ndf), mu_i, mu_o, l_i, l_o);
    (ggx::corrected(spec, errors, hv.h), hv.cos_b, hv.defined)
}

impl Kernel for Beckmann {
    type Prepared<F: Real> = Prepared<F>;
    const LENGTH_CORRECTIONS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let alpha = ALPHA.read(p);
        Prepared {
            kd_over_pi: KD.read(p).map(|c| c * F::FRAC_1_PI),
            f0: KS.read(p),
            alpha,
            alpha2: alpha * alpha,
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let lobe = lobe::<F, P>(d, pp.alpha, pp.alpha2);
        schlick_microfacet_value(lobe, pp.f0, pp.kd_over_pi, d)
    }

    /// Lobes drawn from the visible normals (Heitz & d'Eon 2014) with their closed-form
    /// weights `F·G2/G1(wi)`, bounded by 1 ([`Integral::BeckmannVisible`]).
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        schlick_microfacet_terms(slots, |alpha, f0, basis| Integral::BeckmannVisible {
            alpha,
            f0,
            basis,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `lambda_of_c` is libm's erfc form of `Λ(c)` and `mu_lambda/μ` at the same `c`, to
    /// the rounding both forms share: their difference of terms cancels as `c` grows
    /// (`Λ ≈ e^{−c²}/(4c³·sqrt(π))`, relative error ~2c²·u), and `c` itself is rounded.
    /// (Against 50-digit mpmath at c = 6.0256: this form 2.0e-15, libm's 2.7e-13.)
    #[test]
    fn lambda_of_c_is_mu_lambda_over_mu() {
        let alpha = 0.7_f64;
        for i in 0..4000 {
            let c = 10f64.powf(-6.0 + 7.5 * f64::from(i) / 4000.0);
            let got = lambda_of_c(c);
            let libm_form =
                (0.5 * ((-c * c).exp() * 0.564_189_583_547_756_3 / c - libm::erfc(c))).max(0.0);
            // libm's form also carries the rounding of c² through e^{−c²} into the
            // cancellation (ours scales both terms by the same e): another factor c².
            let tol = 16.0 * (1.0 + 2.0 * c * c) * (1.0 + c * c) * f64::EPSILON * libm_form;
            assert!(
                (got - libm_form).abs() <= tol + 1e-300,
                "c={c}: {got} vs libm {libm_form}"
            );
            // mu/(alpha·s) = c with s = sqrt(1 − mu²).
            let s = 1.0 / (1.0 + (alpha * c).powi(2)).sqrt();
            let mu = alpha * c * s;
            let from_mu = mu_lambda(mu, s * s, alpha) / mu;
            let c_rounded = mu / (alpha * (s * s).sqrt());
            let want = lambda_of_c(c_rounded);
            assert!(
                (from_mu - want).abs() <= 64.0 * (1.0 + 2.0 * c * c) * f64::EPSILON * want + 1e-300,
                "c={c}: mu_lambda/mu {from_mu} vs {want}"
            );
        }
        assert_eq!(lambda_of_c(f64::INFINITY), 0.0);
        assert_eq!(lambda_of_c(40.0_f64), 0.0);
    }
}
