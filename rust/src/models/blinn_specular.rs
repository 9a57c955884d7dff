//! `blinn_specular`: the shading assignment's Blinn specular term.
//!
//! `s(l, v) = ks·clamp(n·h, 0, 1)^p`, 0 when `n·l <= 0` or when `h` is undefined
//! (`l = −v`); `= mu_i·blinn_phong(kd=0)` for mu_i, mu_o > 0.

use super::lobes::half_cosine_pow_over;
// The specular terms' layout (`ks`, `p`).
pub use super::phong_specular::SLOTS;
use super::phong_specular::{SPECULAR_TERM_SPEC, SpecularLobe, SpecularTerm};
use super::spec::ModelSpec;
use super::Directions;
use crate::math::{PowUnit, Real, Vector3};

/// The Blinn specular kernel.
pub type BlinnSpecular = SpecularTerm<HalfVectorLobe>;

pub static SPEC: ModelSpec = ModelSpec {
    name: "blinn_specular",
    summary: "Blinn specular shading term: cosine power of the half vector",
    formula: "s = ks·clamp(n·h, 0, 1)^p, 0 when n·l <= 0",
    source: "scan-line shading assignment (Blinn specular)",
    ..SPECULAR_TERM_SPEC
};

/// The Blinn lobe: `clamp(n·h, 0, 1)^p`, lit where `n·l > 0` and `h` is defined.
pub struct HalfVectorLobe;

impl SpecularLobe for HalfVectorLobe {
    #[inline(always)]
    fn lobe<F: Real, P: PowUnit>(d: &Directions<F>, p: F) -> (F, bool) {
        let (lobe, defined) = half_cosine_pow_over::<F, P>(d, p, F::ONE);
        (lobe, d.n.dot(d.wi) > F::ZERO && defined)
    }
}
