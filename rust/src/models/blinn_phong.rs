//! `blinn_phong`: the Blinn-Phong BRDF as the BRDF Summary writes it (eq. 7).
//!
//! `f = kd + ks·cos_th^p / mu_i`, `cos_th = n·h`. Not reciprocal (the `1/mu_i`); `kd`
//! without `1/π` (the Summary's convention). 0 where the half vector is undefined.

use super::albedo::{StratumLobe, Term, diffuse_and_power_lobe, diffuse_and_whole_power_lobe};
use super::lobes::{DiffuseSpecular, half_cosine_pow_over};
use super::spec::{self, DiffuseTerm, Family, ModelSpec, SceneUse, TangentUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::{KD, KS, P, SLOTS};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::above_both;
use crate::math::{PowUnit, Real, Vector3};

/// The Blinn-Phong kernel.
pub struct BlinnPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "blinn_phong",
    family: Family::A,
    summary: "Blinn-Phong: diffuse plus a cosine-power lobe of the half vector, over mu_i",
    formula: "f = kd + ks·cos_th^p / mu_i",
    source: "BRDF Summary eq. 7",
    params: &[spec::kd(0.0, KD), spec::ks(1.0, KS), spec::exponent(P)],
    tangent: TangentUse::None,
    reciprocal: false,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(std::f64::consts::PI)),
    dfg: None,
    energy_table: false,
    exact: None,
};

impl Kernel for BlinnPhong {
    type Prepared<F: Real> = DiffuseSpecular<F>;
    const POWERS: bool = true;

    fn spec() -> &'static ModelSpec {
        &SPEC
    }

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> DiffuseSpecular<F> {
        DiffuseSpecular::read(p, F::ONE, |_| F::ONE)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &DiffuseSpecular<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        // cos_th^p / mu_i in one step: cos_th^p may underflow where the quotient does not
        let (lobe, defined) = half_cosine_pow_over::<F, P>(d, pp.p, mu_i);
        let rgb = pp.combine(if defined { lobe } else { F::ZERO });
        above_both(mu_i, mu_o, rgb)
    }

    /// The diffuse term and the lobe; where the lobe is sharp or `wi` near the normal,
    /// the lobe in strata with its bulk exact ([`super::strata::blinn_terms`]).
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_power_lobe(
            slots,
            std::f64::consts::PI,
            1.0 / mu,
            mu,
            StratumLobe::Blinn,
        ))
    }

    fn sampling_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_whole_power_lobe(
            slots,
            std::f64::consts::PI,
            StratumLobe::Blinn,
        ))
    }
}
