//! `beckmann_f82`: the Beckmann lobe of `beckmann` with the F82-tint Fresnel term of the Adobe Standard
//! Material and OpenPBR (Schlick's curve for `f0`, bent toward `f82` times Schlick's at
//! `cos_b = 1/7`) in place of Schlick's.
//!
//! `f = kd/π + D·G2·F/(4·mu_i·mu_o)` with `beckmann`'s `D` and exact Smith `G2`
//! ([`beckmann::lobe`](super::beckmann::lobe)) and `F = max(0, F_S − a·cos_b·(1 − cos_b)^6)` per
//! channel ([`f82`](super::fresnel::f82)). The kernel and layout are the family's
//! ([`super::microfacet_fresnel`]).

use super::microfacet_fresnel::{Beckmann, F82Tint, VARIANT_SPEC, Variant, f82_params};
use super::spec::ModelSpec;
// The F82-tint variants' layout (`kd`, `f0`, `f82`, `alpha`).
pub use super::microfacet_fresnel::f82::SLOTS;

/// The Beckmann F82-tint kernel.
pub type BeckmannF82 = Variant<Beckmann, F82Tint>;

pub static SPEC: ModelSpec = ModelSpec {
    name: "beckmann_f82",
    summary: "Beckmann microfacet BRDF (beckmann's lobe) with the F82-tint Fresnel term of OpenPBR's \
              metal",
    formula: "f = kd/π + D·G2·F/(4·mu_i·mu_o), D, G2 as beckmann, \
              F = max(0, F_S − a·cos_b·(1 − cos_b)^6), F_S = f0 + (1 − f0)(1 − cos_b)^5, \
              a = (1 − f82)·(f0·7⁷/6⁶ + (1 − f0)·49/6)",
    source: "Beckmann & Spizzichino 1963; Walter et al. 2007 (Smith Λ); Heitz 2014 (height-correlated G2); \
             Kutz et al. 2021 (Adobe Standard Material, F82 tint); Hoffman 2023",
    params: &f82_params(super::beckmann::ALPHA_DOC),
    ..VARIANT_SPEC
};

