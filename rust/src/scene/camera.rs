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

/// The part of space a segment's rays sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SegmentBounds {
    /// Rays from `apex` within the wedge of the plane through `apex` with unit normal
    /// `plane`, bounded by the half-spaces `(x − apex)·side >= 0`.
    Wedge {
        apex: Vec3,
        plane: Vec3,
        side_a: Vec3,
        side_b: Vec3,
    },
    /// Parallel rays starting at `origin + s·right`, `s` in `[s0, s1]`, in the plane
    /// through `origin` with unit normal `plane`.
    Strip {
        origin: Vec3,
        plane: Vec3,
        right: Vec3,
        s0: f32,
        s1: f32,
    },
}

impl SegmentBounds {
    /// Returns false only if no ray of the segment can come within `radius` of `center`
    /// (with a margin for rounding).
    #[inline]
    pub fn may_reach(&self, center: Vec3, radius: f32) -> bool {
        match *self {
            SegmentBounds::Wedge {
                apex,
                plane,
                side_a,
                side_b,
            } => {
                let c = center - apex;
                let r = radius * (1.0 + 1e-3) + 1e-4 * c.length();
                c.dot(plane).abs() <= r && c.dot(side_a) >= -r && c.dot(side_b) >= -r
            }
            SegmentBounds::Strip {
                origin,
                plane,
                right,
                s0,
                s1,
            } => {
                let c = center - origin;
                let r = radius * (1.0 + 1e-3) + 1e-4 * c.length();
                let s = c.dot(right);
                c.dot(plane).abs() <= r && s >= s0 - r && s <= s1 + r
            }
        }
    }
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

    /// Returns the region of space the rays of pixels `x0 .. x0 + len` of row `y` sweep
    /// (every ray of a row lies in one plane; a segment's rays fill a wedge or a strip of
    /// it), so objects that cannot meet any of them are not tested.
    pub fn segment_bounds(&self, y: usize, x0: usize, len: usize) -> SegmentBounds {
        let sy = (1.0 - 2.0 * (y as f32 + 0.5) / self.height as f32) * self.half_height;
        let scale_x = 2.0 * self.half_width / self.width as f32;
        let sx = |x: usize| (x as f32 + 0.5) * scale_x - self.half_width;
        let (s0, s1) = (sx(x0), sx(x0 + len.max(1) - 1));
        match self.projection {
            Projection::Perspective { .. } => {
                let toward = self.forward + self.up * sy;
                // The row's plane holds the eye and every direction toward + s·right.
                let plane = self.right.cross(toward).normalize();
                let a = (toward + self.right * s0).normalize();
                let b = (toward + self.right * s1).normalize();
                // Inward normals of the wedge's sides: toward b from a, toward a from b.
                let side_a = plane.cross(a);
                let side_a = if side_a.dot(b) >= 0.0 {
                    side_a
                } else {
                    -side_a
                };
                let side_b = plane.cross(b);
                let side_b = if side_b.dot(a) >= 0.0 {
                    side_b
                } else {
                    -side_b
                };
                SegmentBounds::Wedge {
                    apex: self.position,
                    plane,
                    side_a: side_a.normalize(),
                    side_b: side_b.normalize(),
                }
            }
            Projection::Orthographic { .. } => SegmentBounds::Strip {
                origin: self.position + self.up * sy,
                plane: self.up,
                right: self.right,
                s0,
                s1,
            },
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::geometry::Object;

    /// Every sphere some ray of a segment hits passes the segment's bounds test.
    #[test]
    fn segment_bounds_never_drop_a_hit() {
        let mut seed = 1u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 40) as f64 / (1u64 << 24) as f64
        };
        let projections = [
            Projection::Perspective { fov: 0.9 },
            Projection::Orthographic { height: 6.0 },
        ];
        let (mut tested, mut skipped) = (0, 0);
        for projection in projections {
            let camera = Camera::new(
                [0.3, 1.0, 7.0],
                [0.0, 0.2, 0.0],
                [0.1, 1.0, 0.0],
                projection,
                600,
                90,
            )
            .unwrap();
            for _ in 0..300 {
                let center = [8.0 * next() - 4.0, 5.0 * next() - 2.5, 6.0 * next() - 4.0];
                let sphere =
                    Object::sphere(center, 0.05 + next(), 0, "meridian", [0.0, 1.0, 0.0]).unwrap();
                let y = (next() * 90.0) as usize;
                for x0 in (0..600).step_by(SEGMENT) {
                    let len = SEGMENT.min(600 - x0);
                    let mut origin = [[0.0; SEGMENT]; 3];
                    let mut dir = [[0.0; SEGMENT]; 3];
                    camera.rays(y, x0, &mut origin, &mut dir);
                    let mut t = [f32::INFINITY; SEGMENT];
                    let mut id = [u32::MAX; SEGMENT];
                    sphere.intersect(0, &origin, &dir, &mut t, &mut id);
                    let hit = id[..len].contains(&0);
                    let may = sphere.may_hit(&camera.segment_bounds(y, x0, len));
                    assert!(may || !hit, "{projection:?} {center:?} row {y} from {x0}");
                    tested += 1;
                    skipped += !may as usize;
                }
            }
        }
        // The test is not vacuous: most segments miss most spheres.
        assert!(skipped > tested / 2, "{skipped} of {tested}");
    }
}
