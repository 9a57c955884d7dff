//! Sampling the rough dielectrics (`ggx_dielectric`, `beckmann_dielectric`) over the whole
//! sphere: `brdf_rs.sample` and `brdf_rs.pdf` for the models whose spec says
//! `transmission`.
//!
//! Given `wi` (either side), a half vector `h` is drawn from the distribution's visible
//! normals seen from `w' = wi` (above) or `−wi` (below) ([`Warp::GgxVisible`],
//! [`Warp::BeckmannVisible`]); with `F = F(|wi·h|)` from `wi`'s side, `wo` is the
//! reflection of `wi` about `h` with probability `F`, else its refraction through `h`
//! (past the critical angle `F = 1`). The density of `wo` is
//! `D_w'(h)·|dh/dwo|` times `F` or `1 − F`, with `|dh/dwo| = 1/(4|wo·h|)` for a reflection
//! and `eta_o²|wo·h|/(eta_i(wi·h) + eta_o(wo·h))²` for a refraction, `h` being the
//! generalized half vector of the pair (as the kernel forms it); a draw that lands on the
//! wrong side of the surface (a reflection across it, a refraction back) is invalid.
//!
//! The two numbers `u` draw `h`; the choice between reflection and refraction needs a
//! third, independent one, which is derived from the bits of `u` by a 64-bit mixing
//! function ([`third_number`]): deterministic, and uniform and independent of `u` for
//! independent uniform `u` to the accuracy of a good hash (which Sobol points, whose low
//! bits are structured, do not have: their choices are those of a hash of them).
//!
//! At `eta = 1` there is no interface: the light goes straight through, `wo = −wi` with
//! weight `kt`, a Dirac density reported as `inf` by [`DielectricSampler::sample`] and 0
//! by [`DielectricSampler::pdf`] for every direction.

use glam::DVec3;

use super::{Frame, Warp, one_minus_dot, reflect};
use crate::math::Real;
use crate::math::geometry::Cosine;
use crate::models::dielectric::{refraction_half_vector, transmittance};
use crate::models::fresnel;

/// The sampler of one parameter set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricSampler {
    /// The visible-normal warp of the distribution at the model's roughness.
    pub warp: Warp,
    /// The relative index `eta_below/eta_above`.
    pub eta: f64,
}

/// Returns a number in `[0, 1)` from the bits of `u` (splitmix64's finalizer of both).
pub fn third_number(u: [f64; 2]) -> f64 {
    let mut x = u[0].to_bits() ^ u[1].to_bits().rotate_left(29) ^ 0x9E37_79B9_7F4A_7C15;
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^= x >> 31;
    (x >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

impl DielectricSampler {
    /// The relative index across the interface seen from `wi`'s side.
    fn relative(&self, above: bool) -> f64 {
        if above { self.eta } else { 1.0 / self.eta }
    }

    /// Draws `wo` for unit `wi` in the shading frame `frame` from `u` in `[0, 1)²`.
    /// Returns `(wo, pdf, valid)`: `pdf` is [`DielectricSampler::pdf`] of `wo` (`inf` at
    /// `eta = 1`, `wo = −wi`); `valid` is false for a draw that landed on the wrong side
    /// of the surface (its weight is 0).
    pub fn sample(&self, wi: DVec3, frame: &Frame, u: [f64; 2]) -> (DVec3, f64, bool) {
        if self.eta == 1.0 {
            return (-wi, f64::INFINITY, true);
        }
        let n = frame.z;
        let mu_i = wi.dot(n);
        let above = mu_i > 0.0;
        let w = if above { wi } else { -wi };
        let s = self.warp.sample(frame.to_local(w), u);
        let h = frame.to_world(s.dir).normalize();
        // h on wi's side: its cosine with wi is positive.
        let hs = if above { h } else { -h };
        let cos_i = wi.dot(hs);
        let r = self.relative(above);
        let f = fresnel::conductor(
            &fresnel::Conductor::new(r, 0.0),
            Cosine {
                cos: cos_i.clamp(0.0, 1.0),
                one_minus: one_minus_dot(wi, hs).min(1.0),
            },
        );
        let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (r * r);
        let reflection = third_number(u) < f || sin2_t >= 1.0;
        let wo = if reflection {
            reflect(wi, hs)
        } else {
            let cos_t = (1.0 - sin2_t).sqrt();
            -wi / r + hs * (cos_i / r - cos_t)
        };
        let wo = wo.normalize();
        let mu_o = wo.dot(n);
        let valid = mu_o != 0.0 && (mu_o > 0.0) == (above == reflection) && cos_i > 0.0;
        let pdf = self.pdf(wi, wo, frame);
        (wo, pdf, valid && pdf > 0.0)
    }

    /// Returns the density of unit `wo` given unit `wi` in the shading frame `frame` (0 at
    /// `eta = 1`, where the density is a Dirac at `wo = −wi`).
    pub fn pdf(&self, wi: DVec3, wo: DVec3, frame: &Frame) -> f64 {
        let n = frame.z;
        let (mu_i, mu_o) = (wi.dot(n), wo.dot(n));
        if self.eta == 1.0 || !(mu_i != 0.0 && mu_o != 0.0) {
            return 0.0;
        }
        let (i_above, o_above) = (mu_i > 0.0, mu_o > 0.0);
        let reflection = i_above == o_above;
        let side = |above: bool| if above { 1.0 } else { self.eta };
        let (eta_i, eta_o) = (side(i_above), side(o_above));
        let (h, len, c_i, c_o) = if reflection {
            let sum = wi + wo;
            let len = sum.length();
            let h = sum / len;
            let h = if h.dot(n) < 0.0 { -h } else { h };
            (h, len, wi.dot(h), wo.dot(h))
        } else {
            // The refraction's half vector and cosines as the kernel forms them (of the
            // exact unit vectors, the sum in double width), so that f/pdf keeps its
            // digits where the sum is short (eta near 1, wo near −wi).
            let (e_i, e_o) = (f64::length_error(wi), f64::length_error(wo));
            let k = [eta_i, eta_o, e_i, e_o];
            let (h, len) = refraction_half_vector(wi.to_array(), wo.to_array(), n.to_array(), k);
            let e_h = f64::length_error(h);
            let cosine = |w: DVec3, e: f64| w.dot(h) * (1.0 - 0.5 * (e + e_h));
            (h, len, cosine(wi, e_i), cosine(wo, e_o))
        };
        if !(len > 0.0) || !len.is_finite() {
            return 0.0;
        }
        let physical = c_i * mu_i > 0.0 && c_o * mu_o > 0.0;
        if !(reflection || physical) {
            return 0.0;
        }
        // The visible normals are seen from w' = ±wi on n's side.
        let w = if i_above { wi } else { -wi };
        if !(w.dot(h) > 0.0) {
            return 0.0;
        }
        let d = frame.to_local(h);
        let pdf_h = self
            .warp
            .pdf_local(frame.to_local(w), d, d.z, one_minus_dot(h, n));
        let hs = if i_above { h } else { -h };
        let cos = Cosine {
            cos: c_i.abs().min(1.0),
            one_minus: one_minus_dot(wi, hs).min(1.0),
        };
        let r = self.relative(i_above);
        if reflection {
            let f = fresnel::conductor(&fresnel::Conductor::new(r, 0.0), cos);
            pdf_h / (4.0 * c_o.abs()) * f
        } else {
            let t = transmittance(c_i.abs(), c_o.abs(), eta_i, eta_o);
            pdf_h * (eta_o * eta_o * c_o.abs() / (len * len)) * t
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_third_number_is_uniform() {
        let mut counts = [0u32; 16];
        let n = 1 << 16;
        for i in 0..n {
            let u = [
                (f64::from(i) + 0.5) / f64::from(n),
                (f64::from(i) * 0.618_033_988_749_895) % 1.0,
            ];
            let x = third_number(u);
            assert!((0.0..1.0).contains(&x));
            counts[(x * 16.0) as usize] += 1;
        }
        for c in counts {
            assert!((f64::from(c) - 4096.0).abs() < 5.0 * 64.0, "{counts:?}");
        }
    }

    /// The density integrates to at most 1 over the sphere (the share of valid draws),
    /// and the draws' valid share agrees.
    #[test]
    fn the_density_integrates_to_the_share_of_valid_draws() {
        for (warp, eta, mu) in [
            (Warp::GgxVisible { alpha: 0.3 }, 1.5, 0.6_f64),
            (Warp::BeckmannVisible { alpha: 0.4 }, 1.0 / 1.5, 0.9),
            (Warp::GgxVisible { alpha: 0.5 }, 1.5, -0.7),
        ] {
            let sampler = DielectricSampler { warp, eta };
            let frame = Frame {
                x: DVec3::X,
                y: DVec3::Y,
                z: DVec3::Z,
            };
            let wi = DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            let (nt, np) = (800, 400);
            let mut integral = 0.0;
            crate::sampling::sphere_midpoints(nt, np, |wo, dw| {
                integral += sampler.pdf(wi, wo, &frame) * dw;
            });
            let count = 40_000;
            let mut valid = 0;
            for k in 0..count {
                let u = [
                    (k as f64 + 0.5) / count as f64,
                    (k as f64 * 0.754_877_666_246_692_8) % 1.0,
                ];
                let (_, _, ok) = sampler.sample(wi, &frame, u);
                if ok {
                    valid += 1;
                }
            }
            let share = valid as f64 / count as f64;
            assert!(integral <= 1.0 + 2e-3 && integral > 0.5, "{integral}");
            assert!((integral - share).abs() < 0.01, "{integral} vs {share}");
        }
    }
}
