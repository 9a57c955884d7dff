//! `modified_phong`: the reciprocal "modified" Phong BRDF (BRDF Summary eq. 3).
//!
//! `f = kd + ks·cos_ar^p`. Reciprocal; `kd` without `1/π` as the Summary writes it.
//! Directional albedo at normal incidence with kd = 0, ks = 1: `2π/(p+2)`.

use super::albedo::StratumLobe;
use super::lobes::{DiffuseSpecular, POWER_LOBE_SPEC, PowerLobeModel, mirror_cosine};
use super::spec::{DiffuseTerm, ModelSpec, SceneUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::SLOTS;
use super::Directions;
use crate::math::geometry::Cosine;
use crate::math::Real;

/// The modified Phong kernel.
pub struct ModifiedPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "modified_phong",
    summary: "reciprocal Phong: diffuse plus a cosine-power lobe about the mirror direction",
    formula: "f = kd + ks·cos_ar^p",
    source: "BRDF Summary eq. 3",
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(std::f64::consts::PI)),
    ..POWER_LOBE_SPEC
};

impl PowerLobeModel for ModifiedPhong {
    const LOBE: StratumLobe = StratumLobe::Phong;

    const PLAIN_POWER: bool = true;

    #[inline(always)]
    fn lobe_base<F: Real>(_pp: &DiffuseSpecular<F>, d: &Directions<F>, mu_i: F) -> (Cosine<F>, bool) {
        (mirror_cosine(d, mu_i), true)
    }
}
