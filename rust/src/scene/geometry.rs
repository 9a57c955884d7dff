//! Objects: spheres and infinite planes, their ray tests, normals and tangent fields.
//!
//! Ray tests run over a whole segment of pixels at once (structure of arrays, selects,
//! no branches) so they vectorize. The sphere test is the numerically careful one of
//! Haines et al., *Ray Tracing Gems* ch. 7: the discriminant comes from the distance of
//! the centre to the ray, `r² − |f − (f·d)d|²`, and the near root from `c/q`, so float32
//! stays accurate for small spheres far from the camera.
//!
//! Normals: a sphere's points outward (a camera inside a sphere sees its inside with the
//! normal facing away, which family-A models shade black); a plane is two-sided, its
//! normal turned toward the viewer.
//!
//! Tangents (for models that need one, such as `kajiya_kay`): a sphere's field runs along
//! its meridians, from the south pole toward the north pole of `axis`
//! (`t ∝ axis − (axis·n)n`), or along its parallels (`t ∝ axis × n`, eastward); at the
//! poles, where the field is undefined, any unit vector perpendicular to `n` is used. A
//! plane's tangent is a fixed vector.

use glam::Vec3;

use super::camera::SegmentBounds;
use super::shading::SEGMENT;
use crate::error::BrdfError;

/// A shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// An infinite plane through `point` with unit `normal`.
    Plane {
        point: Vec3,
        normal: Vec3,
    },
}

/// How an object's tangents are laid out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TangentField {
    /// Along the meridians of a sphere, toward the pole of `axis` (unit).
    Meridian { axis: Vec3 },
    /// Along the parallels of a sphere, `axis × n` (unit `axis`).
    Parallel { axis: Vec3 },
    /// The same unit vector everywhere.
    Fixed(Vec3),
}

/// An object: a shape, the index of its material and its tangent field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Object {
    pub shape: Shape,
    pub material: usize,
    pub tangent: TangentField,
}

/// Converts to the renderer's float32, refusing what is not finite there (|x| above
/// `f32::MAX` ≈ 3.4e38 rounds to infinity).
pub(crate) fn vector(v: [f64; 3], what: &str) -> Result<Vec3, BrdfError> {
    let f = Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
    if f.is_finite() {
        Ok(f)
    } else {
        Err(BrdfError::InvalidArgument(format!(
            "{what}: expected finite numbers within float32's range (|x| <= 3.4e38); got {v:?}"
        )))
    }
}

fn unit(v: [f64; 3], what: &str) -> Result<Vec3, BrdfError> {
    let u = vector(v, what)?.normalize_or_zero();
    if u == Vec3::ZERO {
        return Err(BrdfError::InvalidArgument(format!(
            "{what}: expected a nonzero vector"
        )));
    }
    Ok(u)
}

/// Returns a unit vector perpendicular to unit `n` (Duff et al. 2017, branch-free).
#[inline(always)]
pub fn perpendicular(n: Vec3) -> Vec3 {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x)
}

impl Object {
    /// Returns a sphere; `tangent` is `"meridian"` or `"parallel"` about `axis`.
    pub fn sphere(
        center: [f64; 3],
        radius: f64,
        material: usize,
        tangent: &str,
        axis: [f64; 3],
    ) -> Result<Object, BrdfError> {
        if !(radius > 0.0 && (radius as f32).is_finite()) {
            return Err(BrdfError::InvalidArgument(format!(
                "radius: expected a positive number within float32's range (<= 3.4e38); \
                 got {radius:?}"
            )));
        }
        let axis = unit(axis, "axis")?;
        let tangent = match tangent {
            "meridian" => TangentField::Meridian { axis },
            "parallel" => TangentField::Parallel { axis },
            _ => {
                return Err(BrdfError::InvalidArgument(format!(
                    "tangent: expected \"meridian\" or \"parallel\"; got {tangent:?}"
                )));
            }
        };
        Ok(Object {
            shape: Shape::Sphere {
                center: vector(center, "center")?,
                radius: radius as f32,
            },
            material,
            tangent,
        })
    }

    /// Returns a plane; without a tangent, one perpendicular to the normal is chosen.
    pub fn plane(
        point: [f64; 3],
        normal: [f64; 3],
        material: usize,
        tangent: Option<[f64; 3]>,
    ) -> Result<Object, BrdfError> {
        let normal = unit(normal, "normal")?;
        let tangent = match tangent {
            Some(t) => unit(t, "tangent")?,
            None => perpendicular(normal),
        };
        Ok(Object {
            shape: Shape::Plane {
                point: vector(point, "point")?,
                normal,
            },
            material,
            tangent: TangentField::Fixed(tangent),
        })
    }

    /// Returns false only if no ray of a segment can hit the object (spheres outside the
    /// region the rays sweep); planes are always tested.
    #[inline]
    pub fn may_hit(&self, bounds: &SegmentBounds) -> bool {
        match self.shape {
            Shape::Sphere { center, radius } => bounds.may_reach(center, radius),
            Shape::Plane { .. } => true,
        }
    }

    /// Lowers `t_best` to this object's nearest hit distance `t > 0` for every ray of
    /// the segment that hits it closer, recording `id` there.
    #[inline(always)]
    pub fn intersect(
        &self,
        id: u32,
        origin: &[[f32; SEGMENT]; 3],
        dir: &[[f32; SEGMENT]; 3],
        t_best: &mut [f32; SEGMENT],
        id_best: &mut [u32; SEGMENT],
    ) {
        match self.shape {
            Shape::Sphere { center, radius } => {
                let r2 = radius * radius;
                for j in 0..SEGMENT {
                    let f = Vec3::new(
                        origin[0][j] - center.x,
                        origin[1][j] - center.y,
                        origin[2][j] - center.z,
                    );
                    let d = Vec3::new(dir[0][j], dir[1][j], dir[2][j]);
                    let b = f.dot(d);
                    let l = f - d * b;
                    let disc = r2 - l.dot(l);
                    let c = f.dot(f) - r2;
                    let root = disc.max(0.0).sqrt();
                    let q = -b - if b >= 0.0 { root } else { -root };
                    let t0 = c / q;
                    let t1 = q;
                    let near = t0.min(t1);
                    let far = t0.max(t1);
                    let t = if near > 0.0 { near } else { far };
                    let hit = disc >= 0.0 && t > 0.0 && t < t_best[j];
                    t_best[j] = if hit { t } else { t_best[j] };
                    id_best[j] = if hit { id } else { id_best[j] };
                }
            }
            Shape::Plane { point, normal } => {
                for j in 0..SEGMENT {
                    let o = Vec3::new(origin[0][j], origin[1][j], origin[2][j]);
                    let d = Vec3::new(dir[0][j], dir[1][j], dir[2][j]);
                    let t = normal.dot(point - o) / normal.dot(d);
                    // Parallel rays give ±inf or NaN, which fail the test.
                    let hit = t > 0.0 && t < t_best[j];
                    t_best[j] = if hit { t } else { t_best[j] };
                    id_best[j] = if hit { id } else { id_best[j] };
                }
            }
        }
    }

    /// Writes the unit normal at the hit points `p` of rays `dir` for the pixels whose
    /// `id_best` is `id` (other pixels are left as they are).
    #[inline(always)]
    pub fn normals(
        &self,
        id: u32,
        id_best: &[u32; SEGMENT],
        p: &[[f32; SEGMENT]; 3],
        dir: &[[f32; SEGMENT]; 3],
        n: &mut [[f32; SEGMENT]; 3],
    ) {
        match self.shape {
            Shape::Sphere { center, .. } => {
                for j in 0..SEGMENT {
                    let v = Vec3::new(p[0][j] - center.x, p[1][j] - center.y, p[2][j] - center.z);
                    let u = v * (1.0 / v.length());
                    let mine = id_best[j] == id;
                    n[0][j] = if mine { u.x } else { n[0][j] };
                    n[1][j] = if mine { u.y } else { n[1][j] };
                    n[2][j] = if mine { u.z } else { n[2][j] };
                }
            }
            Shape::Plane { normal, .. } => {
                for j in 0..SEGMENT {
                    let d = Vec3::new(dir[0][j], dir[1][j], dir[2][j]);
                    let u = if normal.dot(d) > 0.0 { -normal } else { normal };
                    let mine = id_best[j] == id;
                    n[0][j] = if mine { u.x } else { n[0][j] };
                    n[1][j] = if mine { u.y } else { n[1][j] };
                    n[2][j] = if mine { u.z } else { n[2][j] };
                }
            }
        }
    }

    /// Writes the unit tangent at normals `n` for the pixels whose `id_best` is `id`.
    #[inline(always)]
    pub fn tangents(
        &self,
        id: u32,
        id_best: &[u32; SEGMENT],
        n: &[[f32; SEGMENT]; 3],
        t: &mut [[f32; SEGMENT]; 3],
    ) {
        for j in 0..SEGMENT {
            let nj = Vec3::new(n[0][j], n[1][j], n[2][j]);
            let u = tangent_at(self.tangent, nj);
            let mine = id_best[j] == id;
            t[0][j] = if mine { u.x } else { t[0][j] };
            t[1][j] = if mine { u.y } else { t[1][j] };
            t[2][j] = if mine { u.z } else { t[2][j] };
        }
    }
}

/// Returns the unit tangent of a field at unit normal `n`.
#[inline(always)]
pub fn tangent_at(field: TangentField, n: Vec3) -> Vec3 {
    let v = match field {
        TangentField::Meridian { axis } => axis - n * axis.dot(n),
        TangentField::Parallel { axis } => axis.cross(n),
        TangentField::Fixed(t) => return t,
    };
    let len2 = v.length_squared();
    // At a pole the field is undefined: any perpendicular will do.
    if len2 > 1e-12 {
        v * (1.0 / len2.sqrt())
    } else {
        perpendicular(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_ray(o: Vec3, d: Vec3) -> ([[f32; SEGMENT]; 3], [[f32; SEGMENT]; 3]) {
        let mut origin = [[0.0; SEGMENT]; 3];
        let mut dir = [[0.0; SEGMENT]; 3];
        for c in 0..3 {
            origin[c].fill(o[c]);
            dir[c].fill(d[c]);
        }
        (origin, dir)
    }

    #[test]
    fn sphere_hits_near_side_and_inside() {
        let s = Object::sphere([0.0, 0.0, 0.0], 1.0, 0, "meridian", [0.0, 1.0, 0.0]).unwrap();
        let (o, d) = one_ray(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let mut t = [f32::INFINITY; SEGMENT];
        let mut id = [u32::MAX; SEGMENT];
        s.intersect(3, &o, &d, &mut t, &mut id);
        assert_eq!((t[0], id[0]), (4.0, 3));
        // From inside: the far wall.
        let (o, d) = one_ray(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0));
        let mut t = [f32::INFINITY; SEGMENT];
        s.intersect(0, &o, &d, &mut t, &mut id);
        assert_eq!(t[0], 1.0);
        // A miss, and a sphere behind the camera.
        let (o, d) = one_ray(Vec3::new(0.0, 2.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let mut t = [f32::INFINITY; SEGMENT];
        s.intersect(0, &o, &d, &mut t, &mut id);
        assert_eq!(t[0], f32::INFINITY);
        let (o, d) = one_ray(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, 1.0));
        s.intersect(0, &o, &d, &mut t, &mut id);
        assert_eq!(t[0], f32::INFINITY);
    }

    #[test]
    fn small_far_sphere_is_accurate_in_f32() {
        let s = Object::sphere([0.0, 0.0, -1e4], 1e-2, 0, "meridian", [0.0, 1.0, 0.0]).unwrap();
        let (o, d) = one_ray(Vec3::ZERO, Vec3::new(0.0, 0.005, -1.0).normalize());
        let mut t = [f32::INFINITY; SEGMENT];
        let mut id = [u32::MAX; SEGMENT];
        s.intersect(0, &o, &d, &mut t, &mut id);
        // The ray passes 0.005·1e4/|d| ≈ 50 units off: a miss.
        assert_eq!(t[0], f32::INFINITY);
        let (o, d) = one_ray(Vec3::ZERO, Vec3::new(0.0, 0.5e-6, -1.0).normalize());
        s.intersect(0, &o, &d, &mut t, &mut id);
        let want = 1e4 - (1e-4f64 - 0.005f64.powi(2)).sqrt();
        assert!((t[0] as f64 - want).abs() < 2e-3, "{} vs {want}", t[0]);
    }

    #[test]
    fn tangent_fields_are_unit_and_perpendicular() {
        for field in [
            TangentField::Meridian { axis: Vec3::Y },
            TangentField::Parallel { axis: Vec3::Y },
        ] {
            for n in [
                Vec3::X,
                Vec3::Y,
                -Vec3::Y,
                Vec3::new(0.3, 0.4, -0.5).normalize(),
            ] {
                let t = tangent_at(field, n);
                assert!((t.length() - 1.0).abs() < 1e-6, "{field:?} {n}");
                assert!(t.dot(n).abs() < 1e-6, "{field:?} {n}");
            }
        }
        // Meridians point north.
        let t = tangent_at(TangentField::Meridian { axis: Vec3::Y }, Vec3::Z);
        assert!((t - Vec3::Y).length() < 1e-6);
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.6, 0.0, 0.8)] {
            let p = perpendicular(n);
            assert!(p.dot(n).abs() < 1e-6 && (p.length() - 1.0).abs() < 1e-6);
        }
    }
}
