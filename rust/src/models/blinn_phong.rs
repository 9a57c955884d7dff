//! `blinn_phong`: the Blinn-Phong BRDF as the BRDF Summary writes it (eq. 7).
//!
//! `f = kd + ks·cos_th^p / mu_i`, `cos_th = n·h`. Not reciprocal (the `1/mu_i`); `kd`
//! without `1/π` (the Summary's convention). 0 where the half vector is undefined.

use super::albedo::StratumLobe;
use super::lobes::{DiffuseSpecular, POWER_LOBE_SPEC, PowerLobeModel, half_cosine_pow_over};
use super::spec::{DiffuseTerm, ModelSpec, SceneUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::SLOTS;
use super::Directions;
use crate::math::{PowUnit, Real};

/// The Blinn-Phong kernel.
pub struct BlinnPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "blinn_phong",
    summary: "Blinn-Phong: diffuse plus a cosine-power lobe of the half vector, over mu_i",
    formula: "f = kd + ks·cos_th^p / mu_i",
    source: "BRDF Summary eq. 7",
    reciprocal: false,
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(std::f64::consts::PI)),
    ..POWER_LOBE_SPEC
};

impl PowerLobeModel for BlinnPhong {
    const LOBE: StratumLobe = StratumLobe::Blinn;

    #[inline(always)]
    fn lobe<F: Real, P: PowUnit>(pp: &DiffuseSpecular<F>, d: &Directions<F>, mu_i: F) -> F {
        // cos_th^p / mu_i in one step: cos_th^p may underflow where the quotient does not
        let (lobe, defined) = half_cosine_pow_over::<F, P>(d, pp.p, mu_i);
        if defined { lobe } else { F::ZERO }
    }

    fn lobe_scale(_slots: &[f64], mu: f64) -> f64 {
        1.0 / mu
    }
}
