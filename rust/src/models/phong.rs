//! `phong`: the original Phong BRDF as the BRDF Summary writes it (eq. 2).
//!
//! `f = kd + ks·cos_ar^p / mu_i`. Not reciprocal (the `1/mu_i`) and not energy
//! conserving; `kd` enters without `1/π`, so the diffuse albedo is `π·kd` (the source's
//! convention, kept on purpose). Infinite only where the exact value is: mu_i → 0+.

use super::albedo::{StratumLobe, Term, diffuse_and_power_lobe, diffuse_and_whole_power_lobe};
use super::lobes::{DiffuseSpecular, mirror_cosine};
use super::spec::{self, DiffuseTerm, Family, ModelSpec, SceneUse, TangentUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::{KD, KS, P, SLOTS};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::above_both;
use crate::math::{PowUnit, Real, Vector3};

/// The original Phong kernel.
pub struct Phong;

pub static SPEC: ModelSpec = ModelSpec {
    name: "phong",
    family: Family::A,
    summary: "original Phong: diffuse plus a cosine-power lobe about the mirror direction, over mu_i",
    formula: "f = kd + ks·cos_ar^p / mu_i",
    source: "BRDF Summary eq. 2",
    params: &[spec::kd(0.0, KD), spec::ks(1.0, KS), spec::exponent(P)],
    tangent: TangentUse::None,
    reciprocal: false,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(std::f64::consts::PI)),
    dfg: None,
    energy_table: false,
    exact: None,
};

impl Kernel for Phong {
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
        // cos_ar^p / mu_i in one step: cos_ar^p may underflow where the quotient does not
        let lobe = cos_ar.powf_over::<P>(pp.p, mu_i);
        above_both(mu_i, mu_o, pp.combine(lobe))
    }

    /// The diffuse term and the lobe; where the lobe is sharp or `wi` near the normal,
    /// the lobe in strata with its bulk exact ([`super::strata::phong_terms`]).
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_power_lobe(
            slots,
            std::f64::consts::PI,
            1.0 / mu,
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
