//! `normalized_phong`: the energy-normalized Phong BRDF (BRDF Summary eq. 5, RTR eq. 7.47).
//!
//! `f = kd/π + ks·(p+2)/(2π)·cos_ar^p` (the Summary's `n` is `p`). With kd = 0, ks = 1
//! its directional albedo at normal incidence is exactly 1 and lower elsewhere.

use super::albedo::StratumLobe;
use super::lobes::{DiffuseSpecular, P, POWER_LOBE_SPEC, PowerLobeModel, mirror_cosine};
use super::spec::{DiffuseTerm, ModelSpec, SceneUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::SLOTS;
use super::{Directions, ParamSource};
use crate::math::geometry::Cosine;
use crate::math::Real;

/// The normalized Phong kernel.
pub struct NormalizedPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "normalized_phong",
    summary: "energy-normalized Phong lobe about the mirror direction, plus Lambert",
    formula: "f = kd/π + ks·(p+2)/(2π)·cos_ar^p",
    source: "BRDF Summary eq. 5; RTR 3rd ed. eq. 7.47",
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    ..POWER_LOBE_SPEC
};

impl PowerLobeModel for NormalizedPhong {
    const LOBE: StratumLobe = StratumLobe::Phong;

    #[inline(always)]
    fn read_params<F: Real, S: ParamSource<F> + ?Sized>(p: &S) -> DiffuseSpecular<F> {
        DiffuseSpecular::read(p, F::FRAC_1_PI, |e| (e + F::TWO) * F::HALF * F::FRAC_1_PI)
    }

    const PLAIN_POWER: bool = true;

    #[inline(always)]
    fn lobe_base<F: Real>(_pp: &DiffuseSpecular<F>, d: &Directions<F>, mu_i: F) -> (Cosine<F>, bool) {
        (mirror_cosine(d, mu_i), true)
    }

    fn lobe_scale(slots: &[f64], _mu: f64) -> f64 {
        (P.read(slots) + 2.0) / (2.0 * std::f64::consts::PI)
    }
}
