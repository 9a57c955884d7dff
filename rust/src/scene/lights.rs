//! Lights: directional and point lights with RGB intensity.
//!
//! A directional light of intensity `L` travelling along `direction` reaches every point
//! with `wi = −direction` and weight `L`. A point light at `position` reaches a point `x`
//! with `wi = (position − x)/d`, `d = |position − x|`, and weight `L/d²` (inverse-square
//! falloff); with a `range`, points farther than `range` receive nothing (a hard cutoff,
//! so such pairs are culled before any kernel runs), and so does a point at `d = 0`.

use glam::Vec3;

use super::geometry::vector;
use super::shading::SEGMENT;
use crate::error::BrdfError;

/// A light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Parallel light travelling along `direction` (unit), from the light into the scene.
    Directional {
        direction: Vec3,
        intensity: [f32; 3],
    },
    /// A point light with inverse-square falloff, cut off beyond `range` (may be +inf).
    Point {
        position: Vec3,
        intensity: [f32; 3],
        range: f32,
    },
}

fn check_intensity(i: [f64; 3]) -> Result<[f32; 3], BrdfError> {
    if i.iter().any(|&x| !((x as f32).is_finite() && x >= 0.0)) {
        return Err(BrdfError::InvalidArgument(format!(
            "intensity: expected an RGB triple of numbers >= 0 within float32's range \
             (<= 3.4e38); got {i:?}"
        )));
    }
    Ok(i.map(|x| x as f32))
}

impl Light {
    /// Returns a directional light travelling along `direction` (any nonzero length).
    pub fn directional(direction: [f64; 3], intensity: [f64; 3]) -> Result<Light, BrdfError> {
        let d = vector(direction, "direction")?;
        if d.length_squared() == 0.0 || !d.normalize().is_finite() {
            return Err(BrdfError::InvalidArgument(
                "direction: expected a nonzero vector (the way the light travels)".into(),
            ));
        }
        Ok(Light::Directional {
            direction: d.normalize(),
            intensity: check_intensity(intensity)?,
        })
    }

    /// Returns a point light; `range` `None` means unlimited.
    pub fn point(
        position: [f64; 3],
        intensity: [f64; 3],
        range: Option<f64>,
    ) -> Result<Light, BrdfError> {
        let range = match range {
            None => f32::INFINITY,
            Some(r) if r > 0.0 && (r as f32).is_finite() => r as f32,
            Some(r) => {
                return Err(BrdfError::InvalidArgument(format!(
                    "range: expected a positive number within float32's range (<= 3.4e38); \
                     got {r:?}"
                )));
            }
        };
        Ok(Light::Point {
            position: vector(position, "position")?,
            intensity: check_intensity(intensity)?,
            range,
        })
    }

    /// Returns the light's RGB intensity.
    pub fn intensity(&self) -> [f32; 3] {
        match self {
            Light::Directional { intensity, .. } | Light::Point { intensity, .. } => *intensity,
        }
    }

    /// Returns whether the light can never contribute (black).
    pub fn is_black(&self) -> bool {
        self.intensity().iter().all(|&c| c == 0.0)
    }

    /// Returns whether the light needs surface positions (a point light does).
    pub fn needs_positions(&self) -> bool {
        matches!(self, Light::Point { .. })
    }
}

/// One light seen from every pixel of a segment: `wi`, the falloff, `n·l`, and whether
/// the pixel is within the light's reach. A directional light is the same everywhere:
/// its `wi` is kept once (`constant`) and only `n·l` is computed per pixel.
pub struct LightField {
    pub constant: Option<Vec3>,
    pub wi: [[f32; SEGMENT]; 3],
    pub falloff: [f32; SEGMENT],
    pub cos_l: [f32; SEGMENT],
    pub in_range: [bool; SEGMENT],
}

impl LightField {
    /// Returns an empty field.
    pub fn new() -> LightField {
        LightField {
            constant: None,
            wi: [[0.0; SEGMENT]; 3],
            falloff: [1.0; SEGMENT],
            cos_l: [0.0; SEGMENT],
            in_range: [true; SEGMENT],
        }
    }

    /// Returns `wi` at pixel `j`.
    #[inline(always)]
    pub fn wi(&self, j: usize) -> Vec3 {
        match self.constant {
            Some(wi) => wi,
            None => Vec3::new(self.wi[0][j], self.wi[1][j], self.wi[2][j]),
        }
    }

    /// Returns the falloff at pixel `j` (1 for a directional light).
    #[inline(always)]
    pub fn falloff(&self, j: usize) -> f32 {
        if self.constant.is_some() {
            1.0
        } else {
            self.falloff[j]
        }
    }

    /// Returns whether pixel `j` is within reach (always, for a directional light).
    #[inline(always)]
    pub fn in_range(&self, j: usize) -> bool {
        self.constant.is_some() || self.in_range[j]
    }

    /// Computes the light at pixels `span` (positions `p`, unit normals `n`) and returns
    /// how many pixels with `hit` set it reaches, and how many of those it lights from
    /// the front (`n·l > 0`). Every hit pixel must lie in `span`. Straight loops: they
    /// vectorize.
    #[inline(always)]
    pub fn compute(
        &mut self,
        light: &Light,
        p: &[[f32; SEGMENT]; 3],
        n: &[[f32; SEGMENT]; 3],
        hit: &[bool; SEGMENT],
        span: std::ops::Range<usize>,
    ) -> (u32, u32) {
        let span = span.start.min(SEGMENT)..span.end.min(SEGMENT);
        let (mut reached, mut lit) = (0u32, 0u32);
        match *light {
            Light::Directional { direction, .. } => {
                let wi = -direction;
                self.constant = Some(wi);
                for j in span.clone() {
                    let c = n[0][j] * wi.x + n[1][j] * wi.y + n[2][j] * wi.z;
                    self.cos_l[j] = c;
                    reached += hit[j] as u32;
                    lit += (hit[j] & (c > 0.0)) as u32;
                }
            }
            Light::Point {
                position, range, ..
            } => {
                self.constant = None;
                let range2 = range * range;
                for j in span.clone() {
                    let dx = position.x - p[0][j];
                    let dy = position.y - p[1][j];
                    let dz = position.z - p[2][j];
                    let d2 = dx * dx + dy * dy + dz * dz;
                    let inv = 1.0 / d2.sqrt();
                    let (x, y, z) = (dx * inv, dy * inv, dz * inv);
                    self.wi[0][j] = x;
                    self.wi[1][j] = y;
                    self.wi[2][j] = z;
                    self.falloff[j] = 1.0 / d2;
                    // NaN (an unused pixel) fails every comparison.
                    let reach = (d2 > 0.0) & (d2 <= range2) & (d2 < f32::INFINITY);
                    let c = n[0][j] * x + n[1][j] * y + n[2][j] * z;
                    self.in_range[j] = reach;
                    self.cos_l[j] = c;
                    reached += (hit[j] & reach) as u32;
                    lit += (hit[j] & reach & (c > 0.0)) as u32;
                }
            }
        }
        (reached, lit)
    }
}

impl Default for LightField {
    fn default() -> Self {
        LightField::new()
    }
}
