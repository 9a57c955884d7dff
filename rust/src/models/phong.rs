//! `phong`: the original Phong BRDF as the BRDF Summary writes it (eq. 2).
//!
//! `f = kd + ks·cos_ar^p / mu_i`. Not reciprocal (the `1/mu_i`) and not energy
//! conserving; `kd` enters without `1/π`, so the diffuse albedo is `π·kd` (the source's
//! convention, kept on purpose). Infinite only where the exact value is: mu_i → 0+.

use super::albedo::StratumLobe;
use super::lobes::{DiffuseSpecular, POWER_LOBE_SPEC, PowerLobeModel, mirror_cosine};
use super::spec::{DiffuseTerm, ModelSpec, SceneUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::SLOTS;
use super::Directions;
use crate::math::{PowUnit, Real};

/// The original Phong kernel.
pub struct Phong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "phong",
    summary: "original Phong: diffuse plus a cosine-power lobe about the mirror direction, over mu_i",
    formula: "f = kd + ks·cos_ar^p / mu_i",
    source: "BRDF Summary eq. 2",
    reciprocal: false,
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(std::f64::consts::PI)),
    ..POWER_LOBE_SPEC
};

impl PowerLobeModel for Phong {
    const LOBE: StratumLobe = StratumLobe::Phong;

    #[inline(always)]
    fn lobe<F: Real, P: PowUnit>(pp: &DiffuseSpecular<F>, d: &Directions<F>, mu_i: F) -> F {
        // cos_ar^p / mu_i in one step: cos_ar^p may underflow where the quotient does not
        mirror_cosine(d, mu_i).powf_over::<P>(pp.p, mu_i)
    }

    fn lobe_scale(_slots: &[f64], mu: f64) -> f64 {
        1.0 / mu
    }
}
