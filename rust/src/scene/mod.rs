//! Scenes: scan-line shading and rendering of spheres and planes under directional and
//! point lights, with the models of [`crate::models`] as materials.
//!
//! A pixel's radiance is `Σ_lights L·s(l, v)` for a family-B material (its diffuse and
//! specular terms, each including the light's cosine) and `Σ_lights L·f(l, v)·(n·l)` for
//! a family-A BRDF (docs/models.md, "Scenes"), with `l = wi` toward the
//! light and `v = wo` toward the camera. One sample per pixel, no shadows, no
//! interreflection: the shading assignment's scan-line model.
//!
//! The renderer skips what a scene does not need, and counts what it did
//! ([`render::RenderStats`]): zero-weight lobes are never evaluated, lights that cannot
//! reach a pixel (black, out of range, behind the surface for parts that are zero there)
//! are culled before any kernel runs, pixels that hit nothing cost only the ray test,
//! and only the materials some object uses are prepared. See [`shading`] for the rules.
//!
//! Everything runs in `f32` (the kernels' fast path), in parallel over rows.

pub mod camera;
pub mod geometry;
pub mod lights;
pub mod render;
pub mod shading;
pub mod sheen;
pub mod tonemap;

pub use camera::{Camera, Projection};
pub use geometry::{Object, Shape, TangentField};
pub use lights::Light;
pub use render::{GBuffer, PartStats, RenderStats, Scene, render, render_polled, shade};
pub use shading::{Component, MaterialDesc, Role, Term};
pub use sheen::SheenLayer;
pub use tonemap::ToneMap;
