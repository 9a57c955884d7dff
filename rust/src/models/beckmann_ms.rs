//! `beckmann_ms`: Kulla & Conty's multiple-scattering lobe for `beckmann`; the same
//! construction as [`super::ggx_ms`] on Beckmann's energy table.

use super::ggx_ms::{LossTable, MULTIPLE_SCATTERING_SPEC, MultipleScattering, params};
use super::spec::ModelSpec;
// The layout of `ggx_ms`, which this model shares.
pub use super::ggx_ms::SLOTS;
use super::tables::{BECKMANN, EnergyTable};

/// Beckmann's energy table.
pub struct BeckmannLoss;

impl LossTable for BeckmannLoss {
    const TABLE: &'static EnergyTable = &BECKMANN;
}

/// The Beckmann multiple-scattering kernel.
pub type BeckmannMs = MultipleScattering<BeckmannLoss>;

pub static SPEC: ModelSpec = ModelSpec {
    name: "beckmann_ms",
    summary: "Kulla-Conty multiple-scattering lobe restoring the energy beckmann loses",
    params: &params("roughness α of the beckmann lobe it completes (table range [1e-3, 1])"),
    ..MULTIPLE_SCATTERING_SPEC
};
