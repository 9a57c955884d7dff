//! `normalized_blinn_phong`: the normalized Blinn-Phong BRDF (BRDF Summary eq. 9, RTR 7.48).
//!
//! `f = kd/π + ks·(p+8)/(8π)·cos_th^p`. The Summary prints `cos^n(α_r)`; that is a typo
//! for `cos_th` (RTR 7.48 confirms). `(p+8)/(8π)` is an approximation: the albedo at
//! normal incidence is `(p+8)(p+2^(−p/2))/((p+2)(p+4))`, slightly above 1.

use super::albedo::StratumLobe;
use super::lobes::{DiffuseSpecular, P, POWER_LOBE_SPEC, PowerLobeModel, half_cosine};
use super::spec::{DiffuseTerm, ExactFactor, ExactNormalization, ModelSpec, SceneUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::SLOTS;
use super::{Directions, ParamSource};
use crate::math::geometry::Cosine;
use crate::math::Real;

/// The normalized Blinn-Phong kernel.
pub struct NormalizedBlinnPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "normalized_blinn_phong",
    summary: "Blinn-Phong lobe with the approximate (p+8)/(8π) normalization, plus Lambert",
    formula: "f = kd/π + ks·(p+8)/(8π)·cos_th^p",
    source: "BRDF Summary eq. 9 (cos_th, not cos_ar: typo fixed); RTR 3rd ed. eq. 7.48",
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    exact: Some(ExactNormalization {
        factor: ExactFactor::BlinnClosedForm,
        params: &["p"],
        scales: "ks",
    }),
    ..POWER_LOBE_SPEC
};

impl PowerLobeModel for NormalizedBlinnPhong {
    const LOBE: StratumLobe = StratumLobe::Blinn;

    #[inline(always)]
    fn read_params<F: Real, S: ParamSource<F> + ?Sized>(p: &S) -> DiffuseSpecular<F> {
        let eighth = F::from_f64(0.125);
        DiffuseSpecular::read(p, F::FRAC_1_PI, |e| (e * eighth + F::ONE) * F::FRAC_1_PI)
    }

    const PLAIN_POWER: bool = true;

    #[inline(always)]
    fn lobe_base<F: Real>(_pp: &DiffuseSpecular<F>, d: &Directions<F>, _mu_i: F) -> (Cosine<F>, bool) {
        half_cosine(d)
    }

    fn lobe_scale(slots: &[f64], _mu: f64) -> f64 {
        (P.read(slots) + 8.0) / (8.0 * std::f64::consts::PI)
    }
}
