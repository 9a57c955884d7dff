//! brdf-rs: evaluate, integrate and tabulate reflectance models (BRDFs), fast and
//! accurately, from Rust or from Python on NumPy arrays.
//!
//! # Conventions
//!
//! - Directions are unit vectors pointing **away** from the surface: `wi` toward the
//!   light, `wo` toward the viewer; `n` is the unit surface normal (+z by default).
//!   `mu_i = n·wi`, `mu_o = n·wo`.
//! - Family-A models return the BRDF `f(wi, wo)` in 1/sr, **excluding** the cosine
//!   factor; they are 0 unless both directions are above the surface. Directional albedo
//!   is `R(wi) = ∫ f(wi, wo)·mu_o dωo`.
//! - Family-B models return the scan-line shading term `s(l, v)` with `l = wi`,
//!   `v = wo`, which already **includes** the light's cosine.
//! - `docs/models.md` defines every model exactly (formulas, parameters, degenerate
//!   cases, published sources); each model's file in [`models`] cites its source
//!   equation.
//!
//! # Layout
//!
//! - [`math`]: float widths ([`math::Real`] ties `f64`/`f32` to glam's `DVec3`/`Vec3`),
//!   robust normalization, accurate angle complements, vectorizable `pow`.
//! - [`models`]: one model per file, the [`models::Kernel`] trait, the spec table.
//! - [`eval`]: the batch engine (broadcasting, strided inputs, blocks, per-ISA loops).
//! - [`simd`]: the instruction set the loops run with, detected once; only it can make
//!   an [`simd::Isa`] above the baseline.
//! - [`scene`]: cameras, spheres and planes, lights, materials made of models, and the
//!   scan-line renderer that skips what a scene does not need.
//! - `py` (feature `python`): the only place that touches PyO3 / NumPy.

// Numeric loops index several parallel arrays at once; iterator chains would hide that
// (and vectorize no better).
#![allow(clippy::needless_range_loop)]
// `!(x > 0.0)` is deliberate throughout: it is true for NaN, where `x <= 0.0` is not.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Every `unsafe` block says, in a `// SAFETY:` comment, why it is sound where it is.
#![warn(clippy::undocumented_unsafe_blocks)]

pub mod error;
pub mod eval;
pub mod integrate;
pub mod math;
pub mod models;
pub mod parallel;
pub mod sampling;
pub mod scene;
pub mod simd;

#[cfg(feature = "python")]
mod py;

pub use error::BrdfError;
pub use models::ModelKind;

/// The library version (the crate's, which is also the Python package's).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
