//! `ggx`: the GGX (Trowbridge-Reitz) microfacet BRDF with height-correlated Smith
//! shadowing and Schlick's Fresnel (Walter et al. 2007; Heitz 2014 for the Smith form).
//!
//! `f = kd/π + D·G2·F/(4·mu_i·mu_o)` with `D = α²/(π·(cos_th²(α²−1)+1)²)`,
//! `G2 = 1/(1 + Λ(mu_i) + Λ(mu_o))`, `Λ(μ) = (−1 + sqrt(1 + α²(1−μ²)/μ²))/2` and
//! `F = F0 + (1−F0)(1−cos_b)^5`, `F0 = ks` (RGB). `ks = 1` gives F = 1.
//!
//! Evaluated without cancellation or overflow: the NDF's denominator is
//! `sin²θh + α²cos²θh` (with `sin²θh` from the accurate complement of `cos_th`), and
//! `G2/(4 mu_i mu_o) = 1/(4(mu_i mu_o + mu_o·L_i + mu_i·L_o))` with `L = μ·Λ(μ)` in the
//! bounded form of [`ggx_mu_lambda`] (finite at grazing angles, where `Λ` overflows).

use super::albedo::{Integral, Term, basis, colour};
use super::spec::{self, Family, ModelSpec, TangentUse};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::{
    above_both, clamped_cosine, ggx_mu_lambda, half_vector, schlick_rgb, schlick_weight,
    smith_quotient, weighted,
};
use crate::math::{Real, Vector3};

/// The GGX kernel.
pub struct Ggx;

pub static SPEC: ModelSpec = ModelSpec {
    name: "ggx",
    family: Family::A,
    summary: "GGX / Trowbridge-Reitz microfacet BRDF, height-correlated Smith G2, Schlick F",
    formula: "f = kd/π + D·G2·F/(4·mu_i·mu_o), D = α²/(π(cos_th²(α²−1)+1)²), \
              G2 = 1/(1+Λ(mu_i)+Λ(mu_o)), Λ(μ) = (−1+sqrt(1+α²(1−μ²)/μ²))/2, \
              F = ks + (1−ks)(1−cos_b)^5",
    source: "Walter et al. 2007 (GGX); Heitz 2014 (height-correlated Smith); MODELS.md",
    params: &[
        spec::kd(0.0, 0),
        spec::f0(1.0, 3),
        spec::roughness(
            "alpha",
            0.5,
            6,
            "roughness α: the NDF's width (α = r² for a perceptual roughness r)",
        ),
    ],
    tangent: TangentUse::None,
    reciprocal: true,
};

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    kd_over_pi: [F; 3],
    f0: [F; 3],
    alpha2: F,
    /// `α²/π`.
    d_scale: F,
}

/// Returns the scalar GGX lobe `D·G2/(4 mu_i mu_o)` (F = 1) and whether it is defined.
#[inline(always)]
pub fn lobe<F: Real>(d: &Directions<F>, alpha2: F, d_scale: F) -> (F, F, bool) {
    let mu_i = d.n.dot(d.wi);
    let mu_o = d.n.dot(d.wo);
    let hv = half_vector::<F>(d.wi, d.wo);
    let cos_th = clamped_cosine::<F>(d.n, hv.h);
    let sin2_th = cos_th.one_minus * (F::ONE + cos_th.cos);
    let denom = sin2_th + alpha2 * cos_th.cos * cos_th.cos;
    let ndf = d_scale / (denom * denom);
    let sin2_i = d.n.cross(d.wi).length_squared();
    let sin2_o = d.n.cross(d.wo).length_squared();
    let l_i = ggx_mu_lambda(mu_i, sin2_i, alpha2);
    let l_o = ggx_mu_lambda(mu_o, sin2_o, alpha2);
    let spec = smith_quotient(ndf, mu_i, mu_o, l_i, l_o);
    (spec, schlick_weight(hv.cos_b), hv.defined)
}

impl Kernel for Ggx {
    type Prepared<F: Real> = Prepared<F>;

    fn spec() -> &'static ModelSpec {
        &SPEC
    }

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let alpha = p.scalar(6);
        let alpha2 = alpha * alpha;
        Prepared {
            kd_over_pi: p.colour(0).map(|c| c * F::FRAC_1_PI),
            f0: p.colour(3),
            alpha2,
            d_scale: alpha2 * F::FRAC_1_PI,
        }
    }

    #[inline(always)]
    fn eval<F: Real>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let (spec, w, defined) = lobe(d, pp.alpha2, pp.d_scale);
        let spec = if defined { spec } else { F::ZERO };
        let fresnel = schlick_rgb(pp.f0, w);
        let rgb = [0, 1, 2].map(|c| weighted(fresnel[c], spec) + pp.kd_over_pi[c]);
        above_both(d.n.dot(d.wi), d.n.dot(d.wo), rgb)
    }

    /// `kd·1 + F0·I(F0 = 1) + (1 − F0)·I(F0 = 0)`, lobes drawn from the visible normals
    /// with their closed-form weights ([`Integral::GgxVisible`]).
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        let f0 = colour(slots, 3);
        let alpha = slots[6];
        let lobe = |f0: f64| Integral::GgxVisible {
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
