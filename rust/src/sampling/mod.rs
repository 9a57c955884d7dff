//! Warps from the unit square to directions, each paired with its pdf, and the sample
//! streams (Owen-scrambled Sobol, counter-seeded PCG) the integrator draws from.
//!
//! Every warp here returns a direction in a *local* frame whose +z axis is the warp's
//! axis (the normal, the mirror direction, ...), together with the density of that
//! direction in solid angle. [`Frame`] maps local directions to the world.
//! Densities are in 1/sr on the sphere; a warp never returns a direction its pdf
//! calls impossible.

pub mod bsdf;
pub mod sobol;
pub mod streams;

use glam::DVec3;
use std::f64::consts::FRAC_1_PI;

use crate::math::fastmath::{log_f64, pow_unit_f64};
use crate::math::series::{expm1_f64, sin_cos_pi};

/// An orthonormal frame: `z` is the axis, `x`, `y` complete it (right-handed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub x: DVec3,
    pub y: DVec3,
    pub z: DVec3,
}

impl Frame {
    /// Returns a frame around the unit vector `z` (glam's branch-free construction of
    /// Duff et al. 2017).
    pub fn around(z: DVec3) -> Frame {
        let (x, y) = z.any_orthonormal_pair();
        Frame { x, y, z }
    }

    /// Returns the frame around unit `z` whose `y` axis is the unit `y` given (which must
    /// be perpendicular to `z`).
    pub fn with_y(z: DVec3, y: DVec3) -> Frame {
        Frame {
            x: y.cross(z),
            y,
            z,
        }
    }

    /// Returns the world direction of local `v`.
    #[inline(always)]
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }

    /// Returns the local coordinates of world `v`.
    #[inline]
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        DVec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }
}

/// A sampled local direction, its polar cosine's accurate complement `1 - dir.z`, and
/// its density (the same value [`Warp::pdf`] returns, computed without a power).
#[derive(Clone, Copy, Debug)]
pub struct Sampled {
    pub dir: DVec3,
    pub one_minus_cos: f64,
    pub pdf: f64,
}

/// A direction at polar cosine `cos` (with `1 - cos` given accurately) and azimuth
/// `φ = π·a` (`a` in `[0, 1)`: the half range), of density `pdf`.
#[inline(always)]
fn spherical(cos: f64, one_minus_cos: f64, a: f64, pdf: f64) -> Sampled {
    let sin = (one_minus_cos * (1.0 + cos)).max(0.0).sqrt();
    let (s, c) = sin_cos_pi(a);
    Sampled {
        dir: DVec3::new(sin * c, sin * s, cos),
        one_minus_cos,
        pdf,
    }
}

/// Returns `1 - u^(1/k)` accurately for `u` in (0, 1] (it is tiny for large `k`).
#[inline(always)]
fn one_minus_root(u: f64, k: f64) -> f64 {
    -expm1_f64(log_f64(u) / k)
}

/// A warp of the unit square onto directions about the local +z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Warp {
    /// Uniform on the upper hemisphere: pdf `1/(2π)`.
    UniformHemisphere,
    /// Cosine-weighted on the upper hemisphere: pdf `cos θ/π`.
    CosineHemisphere,
    /// The Phong lobe `(p+1)/(2π)·cos^p α` about the axis, over the whole sphere's
    /// upper half about the axis (the caller rejects directions below the surface).
    PhongLobe { p: f64 },
    /// A half vector from the Blinn NDF: pdf_h `= (p+2)/(2π)·cos^(p+1) θh`, i.e.
    /// `D(h)·cos θh` with `D = (p+2)/(2π)·cos^p θh`.
    BlinnHalf { p: f64 },
}

impl Warp {
    /// Returns the local direction for `u` in `[0, 1)²` (the warp's own density).
    #[inline(always)]
    pub fn sample(&self, u: [f64; 2]) -> Sampled {
        // φ = 2π·u1: the half-range direction, turned by π on the upper half of u1.
        let upper = u[1] >= 0.5;
        let s = self.sample_folded([u[0], if upper { 2.0 * u[1] - 1.0 } else { 2.0 * u[1] }]);
        let flip = if upper { -1.0 } else { 1.0 };
        Sampled {
            dir: DVec3::new(flip * s.dir.x, flip * s.dir.y, s.dir.z),
            ..s
        }
    }

    /// Returns the local direction for `u` with the azimuth folded onto `[0, π)`: for
    /// integrands even in azimuth (about the frame's xz plane) this covers the same
    /// integral with twice the point density; the density is `2·pdf` on that half.
    #[inline(always)]
    pub fn sample_folded(&self, u: [f64; 2]) -> Sampled {
        self.sample_azimuth(u[0], u[1])
    }

    #[inline(always)]
    fn sample_azimuth(&self, u0: f64, phi: f64) -> Sampled {
        // 1 - u0 lies in (0, 1]: no log(0), no zero-length directions.
        let v = 1.0 - u0;
        // The lobes draw cos^k = v, so the density's cos^(k−1) is v / cos: no power.
        match *self {
            Warp::UniformHemisphere => spherical(v, u0, phi, 0.5 * FRAC_1_PI),
            Warp::CosineHemisphere => {
                // cos θ = sqrt(1 - u0) = sqrt(v); 1 - cos θ = u0 / (1 + sqrt(v)).
                let cos = v.sqrt();
                spherical(cos, u0 / (1.0 + cos), phi, cos * FRAC_1_PI)
            }
            Warp::PhongLobe { p } => {
                let omc = one_minus_root(v, p + 1.0);
                let cos = 1.0 - omc;
                spherical(cos, omc, phi, (p + 1.0) * 0.5 * FRAC_1_PI * (v / cos))
            }
            Warp::BlinnHalf { p } => {
                let omc = one_minus_root(v, p + 2.0);
                let cos = 1.0 - omc;
                spherical(cos, omc, phi, (p + 2.0) * 0.5 * FRAC_1_PI * (v / cos))
            }
        }
    }

    /// Returns the density of local direction `w` (unit), given `w.z` and `1 - w.z`.
    #[inline(always)]
    pub fn pdf(&self, cos: f64, one_minus_cos: f64) -> f64 {
        let density = match *self {
            Warp::UniformHemisphere => 0.5 * FRAC_1_PI,
            Warp::CosineHemisphere => cos * FRAC_1_PI,
            Warp::PhongLobe { p } => {
                (p + 1.0) * 0.5 * FRAC_1_PI * pow_unit_f64(cos.max(0.0), one_minus_cos, p)
            }
            Warp::BlinnHalf { p } => {
                (p + 2.0) * 0.5 * FRAC_1_PI * pow_unit_f64(cos.max(0.0), one_minus_cos, p + 1.0)
            }
        };
        if cos > 0.0 { density } else { 0.0 }
    }
}

/// Returns the mirror of unit `w` about unit `h`: `2 (w·h) h − w`.
#[inline(always)]
pub fn reflect(w: DVec3, h: DVec3) -> DVec3 {
    h * (2.0 * w.dot(h)) - w
}

/// Returns `1 − u·v` for unit `u`, `v`, accurately: `|u − v|² / 2`.
#[inline(always)]
pub fn one_minus_dot(u: DVec3, v: DVec3) -> f64 {
    0.5 * (u - v).length_squared()
}

/// Returns the pdf in solid angle of `wo` for a direction sampled as the reflection of
/// `wi` about a half vector drawn from `half_pdf` (pdf_h / (4 |wo·h|)).
#[inline(always)]
pub fn reflected_pdf(half_pdf: f64, wo_dot_h: f64) -> f64 {
    if wo_dot_h <= 0.0 {
        0.0
    } else {
        half_pdf / (4.0 * wo_dot_h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    /// Integrates a warp's pdf over the sphere by a fine midpoint rule.
    fn pdf_integral(w: Warp) -> f64 {
        let (nt, np) = (4000, 8);
        let mut sum = 0.0;
        for i in 0..nt {
            let theta = (i as f64 + 0.5) / nt as f64 * PI;
            let cos = theta.cos();
            let omc = 2.0 * (theta / 2.0).sin().powi(2);
            sum += w.pdf(cos, omc) * theta.sin() * (PI / nt as f64) * TAU;
        }
        let _ = np;
        sum
    }

    #[test]
    fn pdfs_integrate_to_one() {
        for w in [
            Warp::UniformHemisphere,
            Warp::CosineHemisphere,
            Warp::PhongLobe { p: 0.0 },
            Warp::PhongLobe { p: 7.5 },
            Warp::PhongLobe { p: 300.0 },
            Warp::BlinnHalf { p: 1.0 },
            Warp::BlinnHalf { p: 300.0 },
        ] {
            let total = pdf_integral(w);
            assert!((total - 1.0).abs() < 1e-5, "{w:?}: {total}");
        }
    }

    #[test]
    fn sampled_densities_equal_the_pdf() {
        for w in [
            Warp::UniformHemisphere,
            Warp::CosineHemisphere,
            Warp::PhongLobe { p: 3.5 },
            Warp::PhongLobe { p: 1e5 },
            Warp::BlinnHalf { p: 0.0 },
            Warp::BlinnHalf { p: 700.0 },
        ] {
            for i in 0..200 {
                let u = [(i as f64 + 0.5) / 200.0, (i * 37 % 200) as f64 / 200.0];
                let s = w.sample(u);
                let want = w.pdf(s.dir.z, s.one_minus_cos);
                assert!(
                    (s.pdf - want).abs() <= 1e-12 * want,
                    "{w:?} {u:?}: {} {want}",
                    s.pdf
                );
            }
        }
    }

    #[test]
    fn samples_are_unit_and_above_the_axis_plane() {
        for w in [
            Warp::CosineHemisphere,
            Warp::PhongLobe { p: 1e6 },
            Warp::BlinnHalf { p: 0.0 },
        ] {
            for i in 0..100 {
                let u = [i as f64 / 100.0, (i * 37 % 100) as f64 / 100.0];
                let d = w.sample(u).dir;
                assert!((d.length() - 1.0).abs() < 1e-14, "{w:?} {u:?} {d}");
                assert!(d.z >= 0.0);
            }
        }
    }
}
