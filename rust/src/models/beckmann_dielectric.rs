//! `beckmann_dielectric`: a rough dielectric interface (reflection and transmission) with
//! the Beckmann distribution and `beckmann`'s exact height-correlated Smith shadowing
//! (Walter et al. 2007).
//!
//! The kernel, layout and shared spec fields are the rough dielectrics'
//! ([`super::dielectric`]); this file names the distribution.

use super::dielectric::{self, Beckmann, DIELECTRIC_SPEC, Dielectric};
use super::spec::ModelSpec;
// The rough dielectrics' layout (`ks`, `kt`, `eta`, `alpha`).
pub use super::dielectric::SLOTS;

/// The Beckmann rough dielectric kernel.
pub type BeckmannDielectric = Dielectric<Beckmann>;

pub static SPEC: ModelSpec = ModelSpec {
    name: "beckmann_dielectric",
    summary: "Beckmann rough dielectric BSDF: reflection and refraction through a rough \
              interface of relative index eta, exact dielectric Fresnel",
    formula: concat!(
        "D = exp(−tan²θh/α²)/(π α² cos⁴θh), Λ(μ) = (erf(c)−1)/2 + exp(−c²)/(2c·sqrt(π)), c = μ/(α·sqrt(1−μ²)); ",
        dielectric::dielectric_formula!()
    ),
    params: &dielectric::params(super::beckmann::ALPHA_DOC),
    ..DIELECTRIC_SPEC
};

