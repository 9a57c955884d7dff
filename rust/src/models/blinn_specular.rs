//! `blinn_specular`: the shading assignment's Blinn specular term.
//!
//! `s(l, v) = ks·clamp(n·h, 0, 1)^p`, 0 when `n·l <= 0` or when `h` is undefined
//! (`l = −v`); `= mu_i·blinn_phong(kd=0)` for mu_i, mu_o > 0.

use super::lobes::half_cosine_pow_over;
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{self, Family, ModelSpec, SceneUse};
use super::{Directions, Kernel, ParamSource};
use crate::math::{PowUnit, Real, Vector3};

/// The Blinn specular kernel.
pub struct BlinnSpecular;

crate::param_slots! {
    KS: ColourSlot,
    P: ScalarSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "blinn_specular",
    family: Family::B,
    summary: "Blinn specular shading term: cosine power of the half vector",
    formula: "s = ks·clamp(n·h, 0, 1)^p, 0 when n·l <= 0",
    source: "scan-line shading assignment (Blinn specular)",
    params: &[spec::ks(1.0, KS), spec::exponent(P)],
    reciprocal: false,
    weights: Some(&["ks"]),
    scene: SceneUse::Specular,
    ..ModelSpec::PLAIN
};

impl Kernel for BlinnSpecular {
    type Prepared<F: Real> = ([F; 3], F);
    const POWERS: bool = true;

    const SPEC: &'static ModelSpec = &SPEC;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> ([F; 3], F) {
        (KS.read(p), P.read(p))
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &([F; 3], F), d: &Directions<F>) -> [F; 3] {
        let (ks, p) = *pp;
        let (lobe, defined) = half_cosine_pow_over::<F, P>(d, p, F::ONE);
        let lit = d.n.dot(d.wi) > F::ZERO && defined;
        ks.map(|c| if lit { c * lobe } else { F::ZERO })
    }
}
