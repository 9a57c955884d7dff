//! `modified_phong`: the reciprocal "modified" Phong BRDF (BRDF Summary eq. 3).
//!
//! `f = kd + ks·cos_ar^p`. Reciprocal; `kd` without `1/π` as the Summary writes it.
//! Directional albedo at normal incidence with kd = 0, ks = 1: `2π/(p+2)`.

use super::albedo::{StratumLobe, Term, diffuse_and_power_lobe, diffuse_and_whole_power_lobe};
use super::lobes::{DiffuseSpecular, mirror_cosine};
use super::spec::{self, DiffuseTerm, Family, ModelSpec, SceneUse, TangentUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::{KD, KS, P, SLOTS};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::above_both;
use crate::math::{PowUnit, Real, Vector3};

/// The modified Phong kernel.
pub struct ModifiedPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "modified_phong",
    family: Family::A,
    summary: "reciprocal Phong: diffuse plus a cosine-power lobe about the mirror direction",
    formula: "f = kd + ks·cos_ar^p",
    source: "BRDF Summary eq. 3",
    params: &[spec::kd(0.0, KD), spec::ks(1.0, KS), spec::exponent(P)],
    tangent: TangentUse::None,
    reciprocal: true,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(std::f64::consts::PI)),
    dfg: None,
    energy_table: false,
    exact: None,
};

impl Kernel for ModifiedPhong {
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
        let (mu_i, cos_ar) = mirror_cosine(d);
        let mu_o = d.n.dot(d.wo);
        above_both(mu_i, mu_o, pp.combine(cos_ar.powf::<P>(pp.p)))
    }

    /// The diffuse term and the lobe; where the lobe is sharp or `wi` near the normal,
    /// the lobe in strata with its bulk exact ([`super::strata::phong_terms`]).
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_power_lobe(
            slots,
            std::f64::consts::PI,
            1.0,
            mu,
            StratumLobe::Phong,
        ))
    }

    fn sampling_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_whole_power_lobe(
            slots,
            std::f64::consts::PI,
            StratumLobe::Phong,
        ))
    }
}
