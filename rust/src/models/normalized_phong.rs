//! `normalized_phong`: the energy-normalized Phong BRDF (BRDF Summary eq. 5, RTR eq. 7.47).
//!
//! `f = kd/π + ks·(p+2)/(2π)·cos_ar^p` (the Summary's `n` is `p`). With kd = 0, ks = 1
//! its directional albedo at normal incidence is exactly 1 and lower elsewhere.

use super::albedo::{StratumLobe, Term, diffuse_and_power_lobe, diffuse_and_whole_power_lobe};
use super::lobes::{DiffuseSpecular, mirror_cosine};
use super::spec::{self, DiffuseTerm, Family, ModelSpec, SceneUse, TangentUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::{KD, KS, P, SLOTS};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::above_both;
use crate::math::{PowUnit, Real, Vector3};

/// The normalized Phong kernel.
pub struct NormalizedPhong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "normalized_phong",
    family: Family::A,
    summary: "energy-normalized Phong lobe about the mirror direction, plus Lambert",
    formula: "f = kd/π + ks·(p+2)/(2π)·cos_ar^p",
    source: "BRDF Summary eq. 5; RTR 3rd ed. eq. 7.47",
    params: &[spec::kd(0.0, KD), spec::ks(1.0, KS), spec::exponent(P)],
    tangent: TangentUse::None,
    reciprocal: true,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    dfg: None,
    energy_table: false,
    exact: None,
};

impl Kernel for NormalizedPhong {
    type Prepared<F: Real> = DiffuseSpecular<F>;
    const POWERS: bool = true;

    fn spec() -> &'static ModelSpec {
        &SPEC
    }

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> DiffuseSpecular<F> {
        DiffuseSpecular::read(p, F::FRAC_1_PI, |e| (e + F::TWO) * F::HALF * F::FRAC_1_PI)
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
            1.0,
            (P.read(slots) + 2.0) / (2.0 * std::f64::consts::PI),
            mu,
            StratumLobe::Phong,
        ))
    }

    fn sampling_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_whole_power_lobe(slots, 1.0, StratumLobe::Phong))
    }
}
