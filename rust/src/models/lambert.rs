//! `lambert`: the perfectly diffuse BRDF.
//!
//! `f(wi, wo) = kd / π` (RTR §7.6; BRDF Summary, diffuse term). Its directional albedo is
//! exactly `kd` for every incidence, so the integrator uses that closed form.

use super::albedo::{Integral, Term};
use super::slots::ColourSlot;
use super::spec::{self, DiffuseTerm, ModelSpec, SceneUse};
use super::{Directions, Kernel, ParamSource};
use crate::math::Vector3;
use crate::math::geometry::above_both;
use crate::math::{PowUnit, Real};

/// The Lambert kernel.
pub struct Lambert;

crate::param_slots! {
    KD: ColourSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "lambert",
    summary: "perfectly diffuse reflection",
    formula: "f = kd/π",
    source: "RTR 3rd ed. §7.6; BRDF Summary (diffuse term)",
    params: &[spec::kd(0.5, KD)],
    weights: Some(&["kd"]),
    scene: SceneUse::Brdf(DiffuseTerm::Whole),
    ..ModelSpec::PLAIN
};

impl Kernel for Lambert {
    /// `kd / π`.
    type Prepared<F: Real> = [F; 3];

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> [F; 3] {
        KD.read(p).map(|kd| kd * F::FRAC_1_PI)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(kd_over_pi: &[F; 3], d: &Directions<F>) -> [F; 3] {
        above_both(d.n.dot(d.wi), d.n.dot(d.wo), *kd_over_pi)
    }

    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(vec![Term {
            colour: KD.read(slots),
            integral: Integral::Exact(1.0),
        }])
    }
}
