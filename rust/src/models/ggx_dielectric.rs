//! `ggx_dielectric`: a rough dielectric interface (reflection and transmission) with the
//! GGX distribution and `ggx`'s height-correlated Smith shadowing (Walter et al. 2007).
//!
//! The kernel, layout and shared spec fields are the rough dielectrics'
//! ([`super::dielectric`]); this file names the distribution.

use super::dielectric::{self, DIELECTRIC_SPEC, Dielectric, Ggx};
use super::spec::ModelSpec;
// The rough dielectrics' layout (`ks`, `kt`, `eta`, `alpha`).
pub use super::dielectric::SLOTS;

/// The GGX rough dielectric kernel.
pub type GgxDielectric = Dielectric<Ggx>;

pub static SPEC: ModelSpec = ModelSpec {
    name: "ggx_dielectric",
    summary: "GGX rough dielectric BSDF: reflection and refraction through a rough \
              interface of relative index eta, exact dielectric Fresnel",
    formula: concat!(
        "D = α²/(π(cos_th²(α²−1)+1)²), Λ(μ) = (−1+sqrt(1+α²(1−μ²)/μ²))/2; ",
        dielectric::dielectric_formula!()
    ),
    params: &dielectric::params(super::ggx::ALPHA_DOC),
    ..DIELECTRIC_SPEC
};

