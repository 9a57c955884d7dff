//! Cameras: perspective (a vertical field of view) and orthographic (a view height).
//!
//! The camera sits at `position` looking at `look_at`, with `up` tilted into the view
//! plane. Pixel `(x, y)` (row 0 at the top) is sampled at its centre:
//! `sx = (2(x + ½)/W − 1)·half_width`, `sy = (1 − 2(y + ½)/H)·half_height`. A
//! perspective ray leaves `position` along `forward + sx·right + sy·up` (normalized),
//! with `half_height = tan(fov/2)`; an orthographic ray leaves `position + sx·right +
//! sy·up` along `forward`, with `half_height = height/2`. `half_width` is
//! `half_height·W/H` (square pixels).

use glam::Vec3;

use super::shading::SEGMENT;
use crate::error::BrdfError;

/// How the camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Vertical field of view, radians, in (0, π).
    Perspective { fov: f64 },
    /// Height of the view in world units, > 0.
    Orthographic { height: f64 },
}

/// A pinhole or orthographic camera with its image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub forward: Vec3,
    pub right: Vec3,
    pub up: Vec3,
    pub projection: Projection,
    pub width: usize,
    pub height: usize,
    half_width: f32,
    half_height: f32,
}

/// Most pixels along either side of an image.
pub const MAX_SIDE: usize = 1 << 15;

impl Camera {
    /// Returns a camera, or an error for a degenerate view (position at `look_at`, `up`
    /// along the view direction, bad sizes or angles).
    pub fn new(
        position: [f64; 3],
        look_at: [f64; 3],
        up: [f64; 3],
        projection: Projection,
        width: usize,
        height: usize,
    ) -> Result<Camera, BrdfError> {
        let bad = |msg: String| Err(BrdfError::InvalidArgument(msg));
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return bad(format!(
                "resolution: expected two positive integers up to {MAX_SIDE}; got [{width}, {height}]"
            ));
        }
        let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        let (position, look_at, up) = (v(position), v(look_at), v(up));
        if !(position.is_finite() && look_at.is_finite() && up.is_finite()) {
            return bad("camera: position, look_at and up must be finite".into());
        }
        let forward = (look_at - position).normalize_or_zero();
        if forward == Vec3::ZERO {
            return bad("look_at: must differ from position".into());
        }
        let right = forward.cross(up).normalize_or_zero();
        if right == Vec3::ZERO {
            return bad("up: must not be zero or parallel to the view direction".into());
        }
        let up = right.cross(forward);
        let aspect = width as f32 / height as f32;
        let half_height = match projection {
            Projection::Perspective { fov } => {
                if !(fov > 0.0 && fov < std::f64::consts::PI) {
                    return bad(format!(
                        "fov: expected an angle in (0, 180) degrees; got {}",
                        fov.to_degrees()
                    ));
                }
                (fov * 0.5).tan() as f32
            }
            Projection::Orthographic { height } => {
                if !(height > 0.0 && height.is_finite()) {
                    return bad(format!("height: expected a positive number; got {height}"));
                }
                (height * 0.5) as f32
            }
        };
        Ok(Camera {
            position,
            forward,
            right,
            up,
            projection,
            width,
            height,
            half_width: half_height * aspect,
            half_height,
        })
    }

    /// Writes the rays of pixels `x0 .. x0 + SEGMENT` of row `y` (pixels past the image
    /// edge get rays too; the caller ignores them). Directions are unit vectors.
    #[inline(always)]
    pub fn rays(
        &self,
        y: usize,
        x0: usize,
        origin: &mut [[f32; SEGMENT]; 3],
        dir: &mut [[f32; SEGMENT]; 3],
    ) {
        let sy = (1.0 - 2.0 * (y as f32 + 0.5) / self.height as f32) * self.half_height;
        let scale_x = 2.0 * self.half_width / self.width as f32;
        let (f, r, u, o) = (self.forward, self.right, self.up, self.position);
        match self.projection {
            Projection::Perspective { .. } => {
                let base = f + u * sy;
                for j in 0..SEGMENT {
                    let sx = ((x0 + j) as f32 + 0.5) * scale_x - self.half_width;
                    let d = base + r * sx;
                    let inv = 1.0 / d.length();
                    origin[0][j] = o.x;
                    origin[1][j] = o.y;
                    origin[2][j] = o.z;
                    dir[0][j] = d.x * inv;
                    dir[1][j] = d.y * inv;
                    dir[2][j] = d.z * inv;
                }
            }
            Projection::Orthographic { .. } => {
                let base = o + u * sy;
                for j in 0..SEGMENT {
                    let sx = ((x0 + j) as f32 + 0.5) * scale_x - self.half_width;
                    let p = base + r * sx;
                    origin[0][j] = p.x;
                    origin[1][j] = p.y;
                    origin[2][j] = p.z;
                    dir[0][j] = f.x;
                    dir[1][j] = f.y;
                    dir[2][j] = f.z;
                }
            }
        }
    }
}
