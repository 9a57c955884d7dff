//! `modified_blinn_phong`: the reciprocal Blinn-Phong BRDF (BRDF Summary eq. 8).
//!
//! `f = kd + ks·cos_th^p`, `cos_th = n·h`; `kd` without `1/π` (the Summary's convention).

use super::albedo::StratumLobe;
use super::lobes::{DiffuseSpecular, POWER_LOBE_SPEC, PowerLobeModel, half_cosine};
use super::spec::{DiffuseTerm, ModelSpec, SceneUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::SLOTS;
use super::Directions;
use crate::math::geometry::Cosine;
use crate::math::Real;

/// The modified Blinn-Phong kernel.
pub struct ModifiedBlinnPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "modified_blinn_phong",
    summary: "reciprocal Blinn-Phong: diffuse plus a cosine-power lobe of the half vector",
    formula: "f = kd + ks·cos_th^p",
    source: "BRDF Summary eq. 8",
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(std::f64::consts::PI)),
    ..POWER_LOBE_SPEC
};

impl PowerLobeModel for ModifiedBlinnPhong {
    const LOBE: StratumLobe = StratumLobe::Blinn;

    const PLAIN_POWER: bool = true;

    #[inline(always)]
    fn lobe_base<F: Real>(_pp: &DiffuseSpecular<F>, d: &Directions<F>, _mu_i: F) -> (Cosine<F>, bool) {
        half_cosine(d)
    }
}
