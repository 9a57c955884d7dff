//! Warps from the unit square to directions, each paired with its pdf, and the sample
//! streams (Owen-scrambled Sobol, counter-seeded PCG) the integrator draws from.
//!
//! Every warp here returns a direction in a *local* frame whose +z axis is the warp's
//! axis (the normal, the mirror direction, ...), together with the density of that
//! direction in solid angle. [`Frame`] maps local directions to the world.
//! Densities are in 1/sr on the sphere; a warp never returns a direction its pdf
//! calls impossible.

pub mod beckmann_visible;
pub mod bsdf;
pub mod dielectric;
pub mod sobol;
pub mod streams;

use glam::DVec3;
use std::f64::consts::FRAC_1_PI;

use crate::math::fastmath::{log_f64, pow_unit_f64};
use crate::math::series::{expm1_f64, sin_cos_pi};
pub use beckmann_visible::{BeckmannVisibleNormals, beckmann_visible_pdf};

/// Which sampler draws each lobe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerChoice {
    /// The best measured: the lobe's own importance sampler, except that diffuse
    /// (cosine) lobes are drawn uniformly with Sobol points, which converges faster.
    Auto,
    /// The lobe's own importance sampler.
    Importance,
    /// Cosine-weighted about the normal for every lobe.
    Cosine,
    /// Uniform over the hemisphere for every lobe.
    Uniform,
}

impl SamplerChoice {
    /// Every choice, in the order the interfaces list them.
    pub const ALL: [SamplerChoice; 4] = [
        SamplerChoice::Auto,
        SamplerChoice::Importance,
        SamplerChoice::Cosine,
        SamplerChoice::Uniform,
    ];
    /// Their names, in the same order.
    pub const NAMES: [&'static str; 4] = ["auto", "importance", "cosine", "uniform"];

    /// Returns the name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// Parses `auto`, `importance`, `cosine` or `uniform`.
    pub fn from_name(name: &str) -> Option<SamplerChoice> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }
}

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
/// its density (the same value [`Warp::pdf_local`] returns, computed without a power).
#[derive(Clone, Copy, Debug)]
pub struct Sampled {
    pub dir: DVec3,
    pub one_minus_cos: f64,
    pub pdf: f64,
}

/// Returns `(sin φ, cos φ)` for `φ = π·a` (`full = false`: the half circle) or
/// `φ = 2π·a` (`full = true`), `a` in `[0, 1)`.
#[inline(always)]
fn azimuth(a: f64, full: bool) -> (f64, f64) {
    let x = if full { 2.0 * a } else { a };
    let upper = x >= 1.0;
    let (s, c) = sin_cos_pi(if upper { x - 1.0 } else { x });
    if upper { (-s, -c) } else { (s, c) }
}

/// The direction at azimuth `(sin, cos)` whose lobe cosine `c` has `c^k = v`, drawn with
/// `c^k` uniform on an interval of length `width` (the whole lobe: 1): density
/// `k/(2π)·c^(k−1)/width`, i.e. `k/(2π)·(v/c)/width`.
#[inline(always)]
fn power_cosine(v: f64, k: f64, width: f64, azimuth: (f64, f64)) -> Sampled {
    let omc = one_minus_root(v, k);
    let cos = 1.0 - omc;
    spherical(cos, omc, azimuth, k * 0.5 * FRAC_1_PI * (v / cos) / width)
}

/// The density of a stratum of a power-cosine lobe at lobe cosine `c` (and `1 − c`):
/// `k/(2π)·c^(k−1)/width` where `v = c^k` lies in `(v_lo, v_lo + width]`, else 0;
/// `(k, k − 1)` are given as the lobe computes them.
#[inline(always)]
fn stratum_density(c: f64, one_minus_c: f64, (k, k1): (f64, f64), v_lo: f64, width: f64) -> f64 {
    let v = pow_unit_f64(c, one_minus_c, k);
    let inside = v > v_lo && v <= v_lo + width;
    let density = k * 0.5 * FRAC_1_PI * pow_unit_f64(c, one_minus_c, k1);
    if inside { density / width } else { 0.0 }
}

/// A direction at polar cosine `cos` (with `1 - cos` given accurately) and azimuth with
/// cosine and sine `(c, s)`, of density `pdf`.
#[inline(always)]
fn spherical(cos: f64, one_minus_cos: f64, (s, c): (f64, f64), pdf: f64) -> Sampled {
    let sin = (one_minus_cos * (1.0 + cos)).max(0.0).sqrt();
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

/// Returns `(c, s)` normalized (an azimuth's cosine and sine from a scaled pair).
#[inline(always)]
fn unit_pair(c: f64, s: f64) -> (f64, f64) {
    let inv = 1.0 / (c * c + s * s).sqrt();
    (s * inv, c * inv)
}

/// The GGX NDF `α²/(π (sin²θ + α² cos²θ)²)` of a local unit direction.
#[inline(always)]
pub fn ggx_ndf(alpha2: f64, cos: f64, one_minus_cos: f64) -> f64 {
    let sin2 = one_minus_cos * (1.0 + cos);
    let d = sin2 + alpha2 * cos * cos;
    alpha2 * FRAC_1_PI / (d * d)
}

/// `G1(wi) / wi.z = 1/(mu + μΛ(μ))` of GGX, for the visible-normal density.
#[inline(always)]
fn ggx_g1_over_mu(alpha2: f64, wi: DVec3) -> f64 {
    let sin2 = wi.x * wi.x + wi.y * wi.y;
    1.0 / (wi.z + crate::math::geometry::ggx_mu_lambda(wi.z, sin2, alpha2))
}

/// Heitz's (2018) warp from the projected disk to GGX's visible normals for one incident
/// direction, with the constants that depend only on `wi` computed once: warp `wi` to
/// the hemisphere configuration (α = 1), sample the projected disk, warp back.
#[derive(Clone, Copy, Debug)]
pub struct GgxVisibleNormals {
    alpha: f64,
    /// `wi` in the hemisphere configuration, and the disk's axes.
    vh: DVec3,
    t1v: DVec3,
    t2v: DVec3,
    /// The weight of the disk's lower half in the warp that makes it the visible part.
    s_mix: f64,
}

impl GgxVisibleNormals {
    /// The warp for roughness `alpha` and the local unit incident direction `wi`.
    #[inline(always)]
    pub fn new(alpha: f64, wi: DVec3) -> Self {
        let vh = DVec3::new(alpha * wi.x, alpha * wi.y, wi.z).normalize();
        let lensq = vh.x * vh.x + vh.y * vh.y;
        let t1v = if lensq > 0.0 {
            DVec3::new(-vh.y, vh.x, 0.0) * (1.0 / lensq.sqrt())
        } else {
            DVec3::X
        };
        GgxVisibleNormals {
            alpha,
            vh,
            t1v,
            t2v: vh.cross(t1v),
            s_mix: 0.5 * (1.0 + vh.z),
        }
    }

    /// Returns the half vector at radius `r` in [0, 1] of the projected disk and azimuth
    /// `a` in [0, 1): the full circle, or (`full = false`) the half `t1 >= 0`, which for
    /// `wi` in the xz plane is the side `h.y >= 0` (the azimuth fold).
    #[inline(always)]
    pub fn half_vector(&self, r: f64, a: f64, full: bool) -> DVec3 {
        self.scaled_half_vector(r, a, full).normalize()
    }

    /// Returns the half vector of [`Self::half_vector`] before normalization: a positive
    /// multiple of it (for callers that need only ratios and can spare the square root).
    #[inline(always)]
    pub fn scaled_half_vector(&self, r: f64, a: f64, full: bool) -> DVec3 {
        let (s_phi, c_phi) = if full {
            azimuth(a, true)
        } else {
            let (s, c) = sin_cos_pi(a);
            (-c, s) // φ in [−π/2, π/2): cos φ >= 0
        };
        let t1 = r * c_phi;
        let s_mix = self.s_mix;
        let t2 = (1.0 - s_mix) * (1.0 - t1 * t1).max(0.0).sqrt() + s_mix * r * s_phi;
        let nh =
            self.t1v * t1 + self.t2v * t2 + self.vh * (1.0 - t1 * t1 - t2 * t2).max(0.0).sqrt();
        let alpha = self.alpha;
        DVec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0))
    }
}

/// The density of [`Warp::CosineUniform`] at a direction of cosine `cos` (> 0).
#[inline(always)]
fn mixture_density(cosine: f64, cos: f64) -> f64 {
    (cosine * cos + 0.5 * (1.0 - cosine)) * FRAC_1_PI
}

/// A warp of the unit square onto directions about the local +z axis (the normal or
/// the mirror direction); the half-vector warps return the half vector `h`, to be
/// reflected into `wo` (density `pdf_h / (4 |wo·h|)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Warp {
    /// Uniform on the upper hemisphere: pdf `1/(2π)`.
    UniformHemisphere,
    /// Cosine-weighted on the upper hemisphere: pdf `cos θ/π`.
    CosineHemisphere,
    /// Cosine-weighted with probability `cosine`, else uniform (`u0` below `cosine`
    /// picks the cosine warp and is stretched back onto `[0, 1)`): pdf
    /// `cosine·cos θ/π + (1 − cosine)/(2π)`, the mixture's, whichever drew the point.
    CosineUniform { cosine: f64 },
    /// The Phong lobe `(p+1)/(2π)·cos^p α` about the axis, over the whole sphere's
    /// upper half about the axis (the caller rejects directions below the surface).
    PhongLobe { p: f64 },
    /// A half vector from the Blinn NDF: pdf_h `= (p+2)/(2π)·cos^(p+1) θh`, i.e.
    /// `D(h)·cos θh` with `D = (p+2)/(2π)·cos^p θh`.
    BlinnHalf { p: f64 },
    /// [`Warp::BlinnHalf`] restricted to one stratum, `v = cos^(p+2) θh` in
    /// `(v_lo, v_lo + width]`: `v = v_lo + (1 − u0)·width` (with `v_lo = 0`, `width = 1`
    /// bitwise `BlinnHalf`'s `v = 1 − u0`), pdf_h `= (p+2)/(2π)·cos^(p+1) θh / width`
    /// inside the stratum.
    BlinnStratum { p: f64, v_lo: f64, width: f64 },
    /// [`Warp::PhongLobe`] restricted to one stratum, `v = cos^(p+1) α` in
    /// `(v_lo, v_lo + width]`, as [`Warp::BlinnStratum`] restricts the Blinn half vectors.
    PhongStratum { p: f64, v_lo: f64, width: f64 },
    /// A half vector from GGX's distribution of visible normals for `wi` (Heitz 2018,
    /// "Sampling the GGX Distribution of Visible Normals"): pdf_h `= G1(wi)·(wi·h)·D(h)/mu_i`.
    GgxVisible { alpha: f64 },
    /// A half vector from the anisotropic Beckmann NDF times `cos θh` (Walter 2005):
    /// pdf_h `= exp(−tan²θh (cos²φ/αx² + sin²φ/αy²)) / (π αx αy cos³θh)`.
    BeckmannHalf { alpha_x: f64, alpha_y: f64 },
    /// A half vector from the isotropic Beckmann distribution of visible normals for `wi`
    /// (Heitz & d'Eon 2014; [`beckmann_visible`]): pdf_h `= G1(wi)·(wi·h)·D(h)/mu_i`
    /// with the exact Beckmann `G1`.
    BeckmannVisible { alpha: f64 },
    /// A half vector from Ashikhmin & Shirley's distribution (2000, §3):
    /// pdf_h `= sqrt((nu+1)(nv+1))/(2π) · cos θh^(nu cos²φ + nv sin²φ)`.
    AnisotropicPhongHalf { nu: f64, nv: f64 },
}

impl Warp {
    /// Returns whether the warp draws half vectors (to be reflected into `wo`).
    #[inline(always)]
    pub fn half_vector(&self) -> bool {
        matches!(
            self,
            Warp::BlinnHalf { .. }
                | Warp::BlinnStratum { .. }
                | Warp::GgxVisible { .. }
                | Warp::BeckmannHalf { .. }
                | Warp::BeckmannVisible { .. }
                | Warp::AnisotropicPhongHalf { .. }
        )
    }

    /// Returns the local direction for `u` in `[0, 1)²` (the warp's own density); `wi`
    /// is the incident direction in the same local frame (only the visible-normal warp
    /// reads it).
    #[inline(always)]
    pub fn sample(&self, wi: DVec3, u: [f64; 2]) -> Sampled {
        self.sample_azimuth(wi, u[0], u[1], true)
    }

    /// Returns the local direction for `u` with the azimuth folded onto half the circle
    /// (the side `y >= 0`, or `x·y`-symmetric equivalent for the visible normals): for
    /// integrands symmetric about the frame's xz plane this covers the same integral with
    /// twice the point density; the density is `2·pdf` on that half.
    #[inline(always)]
    pub fn sample_folded(&self, wi: DVec3, u: [f64; 2]) -> Sampled {
        self.sample_azimuth(wi, u[0], u[1], false)
    }

    #[inline(always)]
    fn sample_azimuth(&self, wi: DVec3, u0: f64, a: f64, full: bool) -> Sampled {
        // 1 - u0 lies in (0, 1]: no log(0), no zero-length directions.
        let v = 1.0 - u0;
        // The lobes draw cos^k = v, so the density's cos^(k−1) is v / cos: no power.
        match *self {
            Warp::UniformHemisphere => spherical(v, u0, azimuth(a, full), 0.5 * FRAC_1_PI),
            Warp::CosineHemisphere => {
                // cos θ = sqrt(1 - u0) = sqrt(v); 1 - cos θ = u0 / (1 + sqrt(v)).
                let cos = v.sqrt();
                spherical(cos, u0 / (1.0 + cos), azimuth(a, full), cos * FRAC_1_PI)
            }
            Warp::CosineUniform { cosine } => {
                let picked = u0 < cosine;
                let (warp, u) = if picked {
                    (Warp::CosineHemisphere, u0 / cosine)
                } else {
                    (Warp::UniformHemisphere, (u0 - cosine) / (1.0 - cosine))
                };
                // Rounding may land the stretched number on 1: keep it below.
                let u = u.min(ONE_BELOW);
                let s = warp.sample_azimuth(wi, u, a, full);
                let pdf = mixture_density(cosine, s.dir.z);
                Sampled { pdf, ..s }
            }
            Warp::PhongLobe { p } => power_cosine(v, p + 1.0, 1.0, azimuth(a, full)),
            Warp::BlinnHalf { p } => power_cosine(v, p + 2.0, 1.0, azimuth(a, full)),
            Warp::BlinnStratum { p, v_lo, width } => {
                power_cosine(v_lo + v * width, p + 2.0, width, azimuth(a, full))
            }
            Warp::PhongStratum { p, v_lo, width } => {
                power_cosine(v_lo + v * width, p + 1.0, width, azimuth(a, full))
            }
            Warp::BeckmannHalf { alpha_x, alpha_y } => {
                // φ with tan φ = (αy/αx) tan ψ, then tan²θ = −ln v / A(φ).
                let (s_psi, c_psi) = azimuth(a, full);
                let (s, c) = unit_pair(alpha_x * c_psi, alpha_y * s_psi);
                let big_a = c * c / (alpha_x * alpha_x) + s * s / (alpha_y * alpha_y);
                let tan2 = -log_f64(v) / big_a;
                let cos = 1.0 / (1.0 + tan2).sqrt();
                let omc = tan2 / ((1.0 + tan2) + (1.0 + tan2).sqrt());
                let pdf = v * FRAC_1_PI / (alpha_x * alpha_y * cos * cos * cos);
                spherical(cos, omc, (s, c), pdf)
            }
            Warp::AnisotropicPhongHalf { nu, nv } => {
                let (s_psi, c_psi) = azimuth(a, full);
                let (s, c) = unit_pair((nv + 1.0).sqrt() * c_psi, (nu + 1.0).sqrt() * s_psi);
                let e = nu * c * c + nv * s * s;
                let omc = one_minus_root(v, e + 1.0);
                let cos = 1.0 - omc;
                let pdf = ((nu + 1.0).sqrt() * (nv + 1.0).sqrt()) * 0.5 * FRAC_1_PI * (v / cos);
                spherical(cos, omc, (s, c), pdf)
            }
            Warp::BeckmannVisible { alpha } => {
                BeckmannVisibleNormals::new(alpha, wi).sample(u0, a, full)
            }
            Warp::GgxVisible { alpha } => {
                let h = GgxVisibleNormals::new(alpha, wi).half_vector(u0.sqrt(), a, full);
                let omc = 0.5 * (h - DVec3::Z).length_squared();
                let alpha2 = alpha * alpha;
                let pdf =
                    ggx_g1_over_mu(alpha2, wi) * wi.dot(h).max(0.0) * ggx_ndf(alpha2, h.z, omc);
                Sampled {
                    dir: h,
                    one_minus_cos: omc,
                    pdf,
                }
            }
        }
    }

    /// Returns the density of local direction `w` (unit), given `w.z` and `1 - w.z`:
    /// for the warps that depend only on the polar angle.
    #[inline(always)]
    pub fn pdf(&self, cos: f64, one_minus_cos: f64) -> f64 {
        self.pdf_local(DVec3::Z, DVec3::new(0.0, 0.0, cos), cos, one_minus_cos)
    }

    /// Returns the density of the local unit direction `d` (for half-vector warps, of
    /// `h`), given `cos = d.z`, `1 − d.z` and the local incident direction `wi`.
    #[inline(always)]
    pub fn pdf_local(&self, wi: DVec3, d: DVec3, cos: f64, one_minus_cos: f64) -> f64 {
        let c = cos.max(0.0);
        let density = match *self {
            Warp::UniformHemisphere => 0.5 * FRAC_1_PI,
            Warp::CosineHemisphere => cos * FRAC_1_PI,
            Warp::CosineUniform { cosine } => mixture_density(cosine, cos),
            Warp::PhongLobe { p } => {
                (p + 1.0) * 0.5 * FRAC_1_PI * pow_unit_f64(c, one_minus_cos, p)
            }
            Warp::BlinnHalf { p } => {
                (p + 2.0) * 0.5 * FRAC_1_PI * pow_unit_f64(c, one_minus_cos, p + 1.0)
            }
            Warp::BlinnStratum { p, v_lo, width } => {
                stratum_density(c, one_minus_cos, (p + 2.0, p + 1.0), v_lo, width)
            }
            Warp::PhongStratum { p, v_lo, width } => {
                stratum_density(c, one_minus_cos, (p + 1.0, p), v_lo, width)
            }
            Warp::BeckmannHalf { alpha_x, alpha_y } => {
                let e = ((d.x / alpha_x).powi(2) + (d.y / alpha_y).powi(2)) / (c * c);
                let value = (-e).exp() * FRAC_1_PI / (alpha_x * alpha_y * c * c * c);
                if e < 700.0 { value } else { 0.0 }
            }
            Warp::AnisotropicPhongHalf { nu, nv } => {
                let s2 = d.x * d.x + d.y * d.y;
                let e = if s2 > 0.0 {
                    (nu * d.x * d.x + nv * d.y * d.y) / s2
                } else {
                    0.5 * (nu + nv)
                };
                ((nu + 1.0).sqrt() * (nv + 1.0).sqrt())
                    * 0.5
                    * FRAC_1_PI
                    * pow_unit_f64(c, one_minus_cos, e)
            }
            Warp::BeckmannVisible { alpha } => beckmann_visible_pdf(alpha, wi, d, one_minus_cos),
            Warp::GgxVisible { alpha } => {
                let alpha2 = alpha * alpha;
                ggx_g1_over_mu(alpha2, wi) * wi.dot(d).max(0.0) * ggx_ndf(alpha2, c, one_minus_cos)
            }
        };
        if cos > 0.0 { density } else { 0.0 }
    }
}

/// The largest `f64` below 1: the top of the range `[0, 1)` of the sampler's numbers.
pub const ONE_BELOW: f64 = 1.0 - f64::EPSILON / 2.0;

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

/// Calls `f(w, dω)` at the midpoints of an `nt` × `np` grid of the whole sphere (θ in
/// [0, π], φ in [0, 2π]) with each cell's solid angle `dω`: the midpoint rule the tests
/// integrate densities and lobes over the sphere with.
#[cfg(test)]
pub(crate) fn sphere_midpoints(nt: usize, np: usize, mut f: impl FnMut(DVec3, f64)) {
    use std::f64::consts::PI;
    for i in 0..nt {
        let th = PI * (i as f64 + 0.5) / nt as f64;
        for j in 0..np {
            let ph = 2.0 * PI * (j as f64 + 0.5) / np as f64;
            let w = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
            f(w, th.sin() * (PI / nt as f64) * (2.0 * PI / np as f64));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    #[test]
    fn sampler_and_sequence_names_parse_back() {
        for c in SamplerChoice::ALL {
            assert_eq!(SamplerChoice::from_name(c.name()), Some(c));
        }
        for name in streams::Sequence::NAMES {
            assert_eq!(
                streams::Sequence::from_name(name).map(|s| s.name()),
                Some(name)
            );
        }
        assert_eq!(SamplerChoice::from_name("Auto"), None);
        assert_eq!(streams::Sequence::from_name("halton"), None);
    }

    /// Integrates a warp's pdf over the sphere by a fine midpoint rule.
    fn pdf_integral(w: Warp) -> f64 {
        let (nt, np) = (3000, 96);
        let wi = DVec3::new(0.6, 0.0, 0.8);
        let mut sum = 0.0;
        for i in 0..nt {
            let theta = (i as f64 + 0.5) / nt as f64 * PI;
            let (st, ct) = theta.sin_cos();
            let omc = 2.0 * (theta / 2.0).sin().powi(2);
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * TAU;
                let d = DVec3::new(st * phi.cos(), st * phi.sin(), ct);
                sum += w.pdf_local(wi, d, ct, omc) * st * (PI / nt as f64) * (TAU / np as f64);
            }
        }
        sum
    }

    #[test]
    fn pdfs_integrate_to_one() {
        for w in [
            Warp::UniformHemisphere,
            Warp::CosineHemisphere,
            Warp::CosineUniform { cosine: 0.05 },
            Warp::CosineUniform { cosine: 0.7 },
            Warp::PhongLobe { p: 0.0 },
            Warp::PhongLobe { p: 7.5 },
            Warp::PhongLobe { p: 300.0 },
            Warp::BlinnHalf { p: 1.0 },
            Warp::BlinnHalf { p: 300.0 },
            Warp::BlinnStratum {
                p: 0.0,
                v_lo: 0.0,
                width: 1.0,
            },
            Warp::PhongStratum {
                p: 7.5,
                v_lo: 0.0,
                width: 1.0,
            },
            Warp::GgxVisible { alpha: 0.5 },
            Warp::BeckmannVisible { alpha: 0.5 },
            Warp::BeckmannHalf {
                alpha_x: 0.3,
                alpha_y: 0.6,
            },
            Warp::AnisotropicPhongHalf {
                nu: 20.0,
                nv: 200.0,
            },
        ] {
            let total = pdf_integral(w);
            // Midpoint-rule error for the narrowest lobe (p = 300) is ~1.4e-5; a wrong
            // normalization (p instead of p + 1) would be off by 3e-3.
            assert!((total - 1.0).abs() < 5e-5, "{w:?}: {total}");
        }
    }

    /// Integrates `g(h)` over the upper hemisphere (θ, φ midpoint rule, graded in θ).
    fn hemisphere_integral(g: impl Fn(DVec3, f64) -> f64) -> f64 {
        let (nt, np) = (20_000, 64);
        let mut sum = 0.0;
        for i in 0..nt {
            // θ = (π/2)·t² concentrates nodes near the normal, where narrow NDFs live.
            let t = (i as f64 + 0.5) / nt as f64;
            let theta = 0.5 * PI * t * t;
            let dtheta = PI * t / nt as f64;
            let (st, ct) = theta.sin_cos();
            let omc = 2.0 * (theta / 2.0).sin().powi(2);
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * TAU;
                let h = DVec3::new(st * phi.cos(), st * phi.sin(), ct);
                sum += g(h, omc) * st * dtheta * (TAU / np as f64);
            }
        }
        sum
    }

    #[test]
    fn ndfs_integrate_to_one_and_match_their_smith_functions() {
        use crate::math::geometry::ggx_mu_lambda;
        use crate::models::beckmann::mu_lambda as beckmann_mu_lambda;
        for alpha in [0.05_f64, 0.3, 1.0] {
            let a2 = alpha * alpha;
            let ggx = |h: DVec3, omc: f64| ggx_ndf(a2, h.z, omc);
            let beck = |h: DVec3, _omc: f64| {
                let c2 = h.z * h.z;
                let t = (h.x * h.x + h.y * h.y) / (a2 * c2);
                (-t).exp() / (PI * a2 * c2 * c2)
            };
            // ∫ D cos θh dωh = 1.
            let one = hemisphere_integral(|h, omc| ggx(h, omc) * h.z);
            assert!((one - 1.0).abs() < 2e-4, "ggx alpha={alpha}: {one}");
            let one = hemisphere_integral(|h, omc| beck(h, omc) * h.z);
            assert!((one - 1.0).abs() < 2e-4, "beckmann alpha={alpha}: {one}");
            // ∫ D ⟨wo·h⟩ dωh = (1 + Λ(mu_o))·mu_o = mu_o + μΛ(mu_o).
            for mu in [0.2_f64, 0.7] {
                let wo = DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                let s2 = 1.0 - mu * mu;
                let lhs = hemisphere_integral(|h, omc| ggx(h, omc) * wo.dot(h).max(0.0));
                let rhs = mu + ggx_mu_lambda(mu, s2, a2);
                assert!(
                    (lhs - rhs).abs() < 2e-4 * rhs,
                    "ggx alpha={alpha} mu={mu}: {lhs} {rhs}"
                );
                let lhs = hemisphere_integral(|h, omc| beck(h, omc) * wo.dot(h).max(0.0));
                let rhs = mu + beckmann_mu_lambda(mu, s2, alpha);
                assert!(
                    (lhs - rhs).abs() < 2e-4 * rhs,
                    "beckmann alpha={alpha} mu={mu}: {lhs} {rhs}"
                );
            }
        }
    }

    #[test]
    fn sampled_densities_equal_the_pdf() {
        for w in [
            Warp::UniformHemisphere,
            Warp::CosineHemisphere,
            Warp::CosineUniform { cosine: 0.05 },
            Warp::CosineUniform { cosine: 0.5 },
            Warp::CosineUniform { cosine: 0.95 },
            Warp::PhongLobe { p: 3.5 },
            Warp::PhongLobe { p: 1e5 },
            Warp::BlinnHalf { p: 0.0 },
            Warp::BlinnHalf { p: 700.0 },
            Warp::BlinnStratum {
                p: 100.0,
                v_lo: 4e-7,
                width: 1.0 - 4e-7,
            },
            Warp::BlinnStratum {
                p: 40.0,
                v_lo: 1e-6,
                width: 3e-3,
            },
            Warp::PhongStratum {
                p: 40.0,
                v_lo: 1e-6,
                width: 3e-3,
            },
            Warp::PhongStratum {
                p: 3.5,
                v_lo: 0.3,
                width: 0.7,
            },
            Warp::GgxVisible { alpha: 0.3 },
            Warp::BeckmannVisible { alpha: 0.3 },
            Warp::BeckmannVisible { alpha: 1e-3 },
            Warp::BeckmannHalf {
                alpha_x: 0.2,
                alpha_y: 0.5,
            },
            Warp::AnisotropicPhongHalf {
                nu: 10.0,
                nv: 300.0,
            },
        ] {
            for i in 0..200 {
                let u = [(i as f64 + 0.5) / 200.0, (i * 37 % 200) as f64 / 200.0];
                let wi = DVec3::new(0.6, 0.0, 0.8);
                let s = w.sample(wi, u);
                let want = w.pdf_local(wi, s.dir, s.dir.z, s.one_minus_cos);
                assert!(
                    (s.pdf - want).abs() <= 1e-12 * want,
                    "{w:?} {u:?}: {} {want}",
                    s.pdf
                );
            }
        }
    }

    /// The mixture draws its share of points from each warp, each as that warp draws its
    /// own (stretched) number, with the mixture's density.
    #[test]
    fn the_cosine_uniform_mixture_draws_from_both_warps() {
        let cosine = 0.25;
        let w = Warp::CosineUniform { cosine };
        for (u0, warp, stretched) in [
            (0.2, Warp::CosineHemisphere, 0.8),
            (0.625, Warp::UniformHemisphere, 0.5),
        ] {
            let s = w.sample(DVec3::Z, [u0, 0.3]);
            let t = warp.sample(DVec3::Z, [stretched, 0.3]);
            assert!((s.dir - t.dir).length() < 1e-15, "{s:?} {t:?}");
            let want = (cosine * s.dir.z + 0.5 * (1.0 - cosine)) / PI;
            assert!((s.pdf - want).abs() < 1e-15);
        }
        // u0 just below 1 still gives a direction above the plane.
        let s = w.sample(DVec3::Z, [1.0 - f64::EPSILON / 2.0, 0.5]);
        assert!(s.dir.z >= 0.0 && s.pdf.is_finite() && s.pdf > 0.0);
    }

    /// A stratum draws the lobe restricted to its range of `v = cos^(p+k)` (`k` = 2 for
    /// Blinn half vectors, 1 for the Phong lobe); the whole range is bitwise the whole
    /// lobe's warp.
    #[test]
    fn strata_are_the_lobe_restricted() {
        let (p, v_lo, width) = (30.0, 0.25, 0.5);
        for (k, lobe, stratum, whole) in [
            (
                2.0,
                Warp::BlinnHalf { p },
                Warp::BlinnStratum { p, v_lo, width },
                Warp::BlinnStratum {
                    p,
                    v_lo: 0.0,
                    width: 1.0,
                },
            ),
            (
                1.0,
                Warp::PhongLobe { p },
                Warp::PhongStratum { p, v_lo, width },
                Warp::PhongStratum {
                    p,
                    v_lo: 0.0,
                    width: 1.0,
                },
            ),
        ] {
            for i in 0..500 {
                let u = [(i as f64 + 0.5) / 500.0, (i * 37 % 500) as f64 / 500.0];
                let a = lobe.sample(DVec3::Z, u);
                let b = whole.sample(DVec3::Z, u);
                assert_eq!((a.dir, a.pdf), (b.dir, b.pdf));
                let s = stratum.sample(DVec3::Z, u);
                let v = s.dir.z.powf(p + k);
                assert!(v > v_lo * (1.0 - 1e-12) && v <= (v_lo + width) * (1.0 + 1e-12));
                let ratio = (s.dir.z / a.dir.z).powf(p + k - 1.0);
                assert!((s.pdf * width - a.pdf * ratio).abs() < 1e-9 * s.pdf);
            }
        }
    }

    #[test]
    fn samples_are_unit_and_above_the_axis_plane() {
        for w in [
            Warp::CosineHemisphere,
            Warp::CosineUniform { cosine: 0.3 },
            Warp::PhongLobe { p: 1e6 },
            Warp::BlinnHalf { p: 0.0 },
        ] {
            for i in 0..100 {
                let u = [i as f64 / 100.0, (i * 37 % 100) as f64 / 100.0];
                let d = w.sample(DVec3::Z, u).dir;
                assert!((d.length() - 1.0).abs() < 1e-14, "{w:?} {u:?} {d}");
                assert!(d.z >= 0.0);
            }
        }
    }
}
