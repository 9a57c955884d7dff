//! `modified_blinn_phong`: the reciprocal Blinn-Phong BRDF (BRDF Summary eq. 8).
//!
//! `f = kd + ks·cos_th^p`, `cos_th = n·h`; `kd` without `1/π` (the Summary's convention).

use super::albedo::{StratumLobe, Term, diffuse_and_power_lobe, diffuse_and_whole_power_lobe};
use super::lobes::{DiffuseSpecular, half_cosine};
use super::spec::{self, DiffuseTerm, Family, ModelSpec, SceneUse, TangentUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::{KD, KS, P, SLOTS};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::above_both;
use crate::math::{PowUnit, Real, Vector3};

/// The modified Blinn-Phong kernel.
pub struct ModifiedBlinnPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "modified_blinn_phong",
    family: Family::A,
    summary: "reciprocal Blinn-Phong: diffuse plus a cosine-power lobe of the half vector",
    formula: "f = kd + ks·cos_th^p",
    source: "BRDF Summary eq. 8",
    params: &[spec::kd(0.0, KD), spec::ks(1.0, KS), spec::exponent(P)],
    tangent: TangentUse::None,
    reciprocal: true,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(std::f64::consts::PI)),
    dfg: None,
    energy_table: false,
    exact: None,
};

impl Kernel for ModifiedBlinnPhong {
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
            std::f64::consts::PI,
            1.0,
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
