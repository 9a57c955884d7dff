//! `normalized_blinn_phong`: the normalized Blinn-Phong BRDF (BRDF Summary eq. 9, RTR 7.48).
//!
//! `f = kd/π + ks·(p+8)/(8π)·cos_th^p`. The Summary prints `cos^n(α_r)`; that is a typo
//! for `cos_th` (RTR 7.48 confirms). `(p+8)/(8π)` is an approximation: the albedo at
//! normal incidence is `(p+8)(p+2^(−p/2))/((p+2)(p+4))`, slightly above 1.

use super::albedo::{StratumLobe, Term, diffuse_and_power_lobe, diffuse_and_whole_power_lobe};
use super::lobes::{DiffuseSpecular, half_cosine};
use super::spec::{
    self, DiffuseTerm, ExactFactor, ExactNormalization, Family, ModelSpec, SceneUse, TangentUse,
};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::{KD, KS, P, SLOTS};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::above_both;
use crate::math::{PowUnit, Real, Vector3};

/// The normalized Blinn-Phong kernel.
pub struct NormalizedBlinnPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "normalized_blinn_phong",
    family: Family::A,
    summary: "Blinn-Phong lobe with the approximate (p+8)/(8π) normalization, plus Lambert",
    formula: "f = kd/π + ks·(p+8)/(8π)·cos_th^p",
    source: "BRDF Summary eq. 9 (cos_th, not cos_ar: typo fixed); RTR 3rd ed. eq. 7.48",
    params: &[spec::kd(0.0, KD), spec::ks(1.0, KS), spec::exponent(P)],
    tangent: TangentUse::None,
    reciprocal: true,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    dfg: None,
    energy_table: false,
    exact: Some(ExactNormalization {
        factor: ExactFactor::BlinnClosedForm,
        params: &["p"],
        scales: "ks",
    }),
};

impl Kernel for NormalizedBlinnPhong {
    type Prepared<F: Real> = DiffuseSpecular<F>;
    const POWERS: bool = true;

    fn spec() -> &'static ModelSpec {
        &SPEC
    }

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> DiffuseSpecular<F> {
        let eighth = F::from_f64(0.125);
        DiffuseSpecular::read(p, F::FRAC_1_PI, |e| (e * eighth + F::ONE) * F::FRAC_1_PI)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &DiffuseSpecular<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let (cos_th, defined) = half_cosine(d);
        let lobe = cos_th.powf::<P>(pp.p);
        let rgb = pp.combine(if defined { lobe } else { F::ZERO });
        above_both(mu_i, mu_o, rgb)
    }

    /// The diffuse term and the lobe; where the lobe is sharp or `wi` near the normal,
    /// the lobe in strata with its bulk exact ([`super::strata::blinn_terms`]).
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_power_lobe(
            slots,
            1.0,
            (P.read(slots) + 8.0) / (8.0 * std::f64::consts::PI),
            mu,
            StratumLobe::Blinn,
        ))
    }

    fn sampling_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_whole_power_lobe(slots, 1.0, StratumLobe::Blinn))
    }
}
