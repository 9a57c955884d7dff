//! `lambert_shading`: the shading assignment's Lambert term, cosine included.
//!
//! `s(l, v) = kd·max(n·l, 0)` (the assignment's m_D is `kd`); `= π·mu_i·lambert`.

use super::slots::ColourSlot;
use super::spec::{self, Family, ModelSpec, SceneUse};
use super::{Directions, Kernel, ParamSource};
use crate::math::{PowUnit, Real, Vector3, max};

/// The Lambert shading kernel.
pub struct LambertShading;

crate::param_slots! {
    KD: ColourSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "lambert_shading",
    family: Family::B,
    summary: "Lambert diffuse shading term (includes the light cosine)",
    formula: "s = kd·max(n·l, 0)",
    source: "scan-line shading assignment (Lambert term, m_D = kd)",
    params: &[spec::kd(0.5, KD)],
    reciprocal: false,
    weights: Some(&["kd"]),
    scene: SceneUse::Diffuse,
    ..ModelSpec::PLAIN
};

impl Kernel for LambertShading {
    type Prepared<F: Real> = [F; 3];

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> [F; 3] {
        KD.read(p)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(kd: &[F; 3], d: &Directions<F>) -> [F; 3] {
        let cos_l = max(d.n.dot(d.wi), F::ZERO);
        kd.map(|c| c * cos_l)
    }
}
