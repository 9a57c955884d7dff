//! `beckmann_gen_schlick`: the Beckmann lobe of `beckmann` with MaterialX's generalized Schlick Fresnel
//! term `F = f0 + (f90 − f0)(1 − cos_b)^exponent` in place of Schlick's.
//!
//! `f = kd/π + D·G2·F/(4·mu_i·mu_o)` with `beckmann`'s `D` and exact Smith `G2`
//! ([`beckmann::lobe`](super::beckmann::lobe)) and `F` per channel
//! ([`gen_schlick`](super::fresnel::gen_schlick)). The kernel and layout are the family's
//! ([`super::microfacet_fresnel`]).

use super::microfacet_fresnel::{
    Beckmann, GenSchlick, VARIANT_SPEC, Variant, gen_schlick_params,
};
use super::spec::ModelSpec;
// The generalized Schlick variants' layout (`kd`, `f0`, `f90`, `exponent`, `alpha`).
pub use super::microfacet_fresnel::gen_schlick::SLOTS;

/// The Beckmann generalized Schlick kernel.
pub type BeckmannGenSchlick = Variant<Beckmann, GenSchlick>;

pub static SPEC: ModelSpec = ModelSpec {
    name: "beckmann_gen_schlick",
    summary: "Beckmann microfacet BRDF (beckmann's lobe) with MaterialX's generalized Schlick Fresnel \
              term (F0, F90, exponent)",
    formula: "f = kd/π + D·G2·F/(4·mu_i·mu_o), D, G2 as beckmann, \
              F = f0 + (f90 − f0)(1 − cos_b)^exponent",
    source: "Beckmann & Spizzichino 1963; Walter et al. 2007 (Smith Λ); Heitz 2014 (height-correlated G2); \
             MaterialX (mx_fresnel_schlick); Schlick 1994",
    params: &gen_schlick_params(super::beckmann::ALPHA_DOC),
    // F is affine in f0 and f90 with no constant term: kd = f0 = f90 = 0 gives 0.
    weights: Some(&["kd", "f0", "f90"]),
    ..VARIANT_SPEC
};

