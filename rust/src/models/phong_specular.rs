//! `phong_specular`: the shading assignment's Phong specular term.
//!
//! `s(l, v) = ks·clamp(v·r, 0, 1)^p` (m_S is `ks`, γ is `p`), 0 when `n·l <= 0`;
//! `= mu_i·phong(kd=0)` for mu_i, mu_o > 0.

use super::lobes::mirror_cosine;
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{self, Family, ModelSpec, SceneUse};
use super::{Directions, Kernel, ParamSource, Registered};
use std::marker::PhantomData;
use crate::math::{PowUnit, Real, Vector3};

/// A specular shading term `ks·lobe` where `n·l > 0` (`phong_specular`,
/// [`super::blinn_specular`]): one kernel, the lobe `L` the only difference.
pub struct SpecularTerm<L>(PhantomData<L>);

/// The lobe of a [`SpecularTerm`].
pub trait SpecularLobe: 'static {
    /// The lobe's value for the exponent `p` and whether the term is lit there.
    fn lobe<F: Real, P: PowUnit>(d: &Directions<F>, p: F) -> (F, bool);
}

/// The Phong lobe: `clamp(v·r, 0, 1)^p`, lit where `n·l > 0`.
pub struct MirrorLobe;

impl SpecularLobe for MirrorLobe {
    #[inline(always)]
    fn lobe<F: Real, P: PowUnit>(d: &Directions<F>, p: F) -> (F, bool) {
        let mu_i = d.n.dot(d.wi);
        let cos_ar = mirror_cosine(d, mu_i);
        (cos_ar.powf::<P>(p), mu_i > F::ZERO)
    }
}

/// The Phong specular kernel.
pub type PhongSpecular = SpecularTerm<MirrorLobe>;

crate::param_slots! {
    KS: ColourSlot,
    P: ScalarSlot,
}

/// The spec fields the assignment's two specular terms share (`phong_specular`,
/// [`super::blinn_specular`]): family B, `ks` (default 1) and `p`, `ks` the weight, not
/// reciprocal, the material's specular slot. A model's spec names its own fields and
/// takes these with `..SPECULAR_TERM_SPEC`; the name and texts here are placeholders.
pub const SPECULAR_TERM_SPEC: ModelSpec = ModelSpec {
    family: Family::B,
    params: &[spec::ks(1.0, KS), spec::exponent(P)],
    reciprocal: false,
    weights: Some(&["ks"]),
    scene: SceneUse::Specular,
    ..ModelSpec::PLAIN
};

pub static SPEC: ModelSpec = ModelSpec {
    name: "phong_specular",
    summary: "Phong specular shading term: cosine power about the mirror direction",
    formula: "s = ks·clamp(v·r, 0, 1)^p, 0 when n·l <= 0",
    source: "scan-line shading assignment (Phong specular, m_S = ks, γ = p)",
    ..SPECULAR_TERM_SPEC
};

impl<L: SpecularLobe> Kernel for SpecularTerm<L>
where
    Self: Registered,
{
    type Prepared<F: Real> = ([F; 3], F);
    const POWERS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> ([F; 3], F) {
        (KS.read(p), P.read(p))
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &([F; 3], F), d: &Directions<F>) -> [F; 3] {
        let (ks, p) = *pp;
        let (lobe, lit) = L::lobe::<F, P>(d, p);
        ks.map(|c| if lit { c * lobe } else { F::ZERO })
    }
}
