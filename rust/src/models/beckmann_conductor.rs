//! `beckmann_conductor`: the Beckmann lobe of `beckmann` with the exact Fresnel reflectance of a
//! conductor of complex relative index `eta + i·k` (per RGB channel) in place of
//! Schlick's.
//!
//! `f = kd/π + D·G2·F/(4·mu_i·mu_o)` with `beckmann`'s `D` and exact Smith `G2`
//! ([`beckmann::lobe`](super::beckmann::lobe)) and `F = (|r_s|² + |r_p|²)/2` at `cos_b = wi·h`
//! ([`conductor`](super::fresnel::conductor)). The kernel and layout are the family's
//! ([`super::microfacet_fresnel`]).

use super::microfacet_fresnel::{
    Beckmann, Conductor, VARIANT_SPEC, Variant, conductor_params,
};
use super::spec::ModelSpec;
// The conductor variants' layout (`kd`, `eta`, `k`, `alpha`).
pub use super::microfacet_fresnel::conductor::SLOTS;

/// The Beckmann conductor kernel.
pub type BeckmannConductor = Variant<Beckmann, Conductor>;

pub static SPEC: ModelSpec = ModelSpec {
    name: "beckmann_conductor",
    summary: "Beckmann microfacet BRDF (beckmann's lobe) with the exact Fresnel term of a conductor \
              of complex index eta + i·k",
    formula: "f = kd/π + D·G2·F/(4·mu_i·mu_o), D, G2 as beckmann, \
              F = (|r_s|² + |r_p|²)/2, r_s = (cos_b − w)/(cos_b + w), \
              r_p = (η̃²cos_b − w)/(η̃²cos_b + w), w = sqrt(η̃² − 1 + cos_b²), η̃ = eta + i·k",
    source: "Beckmann & Spizzichino 1963; Walter et al. 2007 (Smith Λ); Heitz 2014 (height-correlated G2); \
             Pharr, Jakob & Humphreys, pbrt-v4 (FrComplex)",
    params: &conductor_params(super::beckmann::ALPHA_DOC),
    ..VARIANT_SPEC
};

