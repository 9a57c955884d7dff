//! Beckmann's distribution of visible normals (Heitz & d'Eon 2014, "Importance Sampling
//! Microfacet-Based BSDFs using the Distribution of Visible Normals", §4 and appendix).
//!
//! The half vector `h` is drawn with density `pdf_h = G1(wi)·max(0, wi·h)·D(h)/mu_i`,
//! `D = exp(−tan²θh/α²)/(π α² cos⁴θh)` and `G1(wi) = mu_i/(mu_i + L_i)`, `L = μ·Λ(μ)` the
//! exact Beckmann Smith term of [`crate::models::beckmann::mu_lambda`]. In slope space
//! (`h ∝ (−α·x, −α·y, 1)`, `(x, y)` the slopes of the α = 1 surface in the frame whose x
//! axis is `wi`'s azimuth) the visible slopes have density `∝ (mu_i − x·α sinθi)·e^{−x²−y²}`
//! on `x < x_max = mu_i/(α sinθi)`: `y` is an independent Gaussian, and `x` has the CDF
//! `G(x)/G(x_max)` with
//!
//! `G(x) = mu_i·erfc(−x) + α sinθi·exp(−x²)/sqrt(π)`, `G(x_max) = 2(mu_i + L_i)`.
//!
//! `x` is found by Halley's method on `G(x) = u·G(x_max)` in `x` itself (PBRT-v3's
//! `BeckmannSample11` and Mitsuba 3 iterate in the `erf` domain, which loses the left
//! tail to `1 + erf(x)` cancelling), safeguarded by bisection on a bracket, from
//! PBRT-v3's fitted initial guess `erf(x₀) = c − (1 + c)(1 − u)^fit(θ)` (`c = erf(x_max)`),
//! to a step below `1e-7(1 + |x|)` (whose cubic convergence leaves ~1e-21) or a zero
//! residual: 2 to 3 evaluations of `erfc`, never more than 64.
//! Slopes are confined to `|x|, |y| <= 9` (the mass outside is below 1e-35): `u = 0` and
//! `u → 1` give finite directions.
//!
//! The map from the unit square: `u` itself for the CDF along `wi`'s azimuth and
//! `y = Φ⁻¹(a)/sqrt(2)` by Wichura's AS 241 (`math/ndtri.rs`) across it. The integrator
//! (`integrate/beckmann.rs`) draws `u = 1 − (1 − v)²` instead, with the Jacobian
//! `2(1 − v)` in its weights (the density vanishes linearly at `x_max`, so
//! `x_max − x ∝ sqrt(1 − u)` but `∝ 1 − v`: the horizon region is smooth and a few
//! percent wide in `v`), and starts the iteration from a per-cell table of that map
//! ([`SlopeTable`]), usually stopping after one step. At normal incidence (`sinθi = 0`, `x_max = ∞`) the
//! same iteration samples the Gaussian itself; at grazing incidence (`mu_i = 0`) the
//! density `∝ −x·e^{−x²}` on `x < 0` stays proper. No special cases, no discontinuity
//! in `wi` (PBRT-v3's switch to the normal-incidence formula at `mu_i > 0.9999` has one).

use glam::DVec3;
use std::f64::consts::{FRAC_1_PI, FRAC_1_SQRT_2};

use super::Sampled;
use crate::math::erfinv::erfinv_guess;
use crate::math::ndtri::{ndtri, ndtri_pair};

use crate::models::beckmann::mu_lambda;

/// `1/sqrt(π)`.
const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;
/// The largest slope magnitude drawn (α = 1 units): `erfc(9) ≈ 4e-37`.
const SLOPE_BOUND: f64 = 9.0;
/// Newton / bisection steps at most: bisection alone shrinks the bracket of width
/// at most 18 below 1e-15 in 55 steps.
const MAX_STEPS: usize = 64;

/// Returns the visible-normal density of the unit half vector `h` (with `1 − h.z`),
/// given `1/(mu_i + L_i)`.
#[inline(always)]
fn density(alpha: f64, g1_over_mu: f64, wi: DVec3, h: DVec3, one_minus_cos: f64) -> f64 {
    let c = h.z;
    let sin2 = one_minus_cos * (1.0 + c);
    let e = sin2 / (alpha * alpha * c * c);
    let ndf = (-e).exp() * FRAC_1_PI / (alpha * alpha * (c * c) * (c * c));
    // Far from the peak exp(−e) is 0 before cos⁴ underflows: never 0/0.
    let ndf = if e < 700.0 && c > 0.0 { ndf } else { 0.0 };
    ndf * wi.dot(h).max(0.0) * g1_over_mu
}

/// Returns `1/(mu_i + L_i) = G1(wi)/mu_i` for roughness `alpha`.
#[inline(always)]
fn g1_over_mu(alpha: f64, wi: DVec3) -> f64 {
    let mu = wi.z.max(0.0);
    1.0 / (mu + mu_lambda(mu, wi.x * wi.x + wi.y * wi.y, alpha))
}

/// Returns the density of the unit half vector `h` (with `1 − h.z`) drawn from Beckmann's
/// visible normals for the unit incident direction `wi` and roughness `alpha`.
#[inline(always)]
pub fn beckmann_visible_pdf(alpha: f64, wi: DVec3, h: DVec3, one_minus_cos: f64) -> f64 {
    density(alpha, g1_over_mu(alpha, wi), wi, h, one_minus_cos)
}

/// Intervals of the per-cell inverse-CDF table ([`SlopeTable`]).
pub const TABLE_INTERVALS: usize = 64;

/// The map `v → x` of [`BeckmannVisibleNormals::slope_along_v`] at the nodes
/// `v_k = k/TABLE_INTERVALS`, with its derivatives: built once per cell by the integrator.
#[derive(Clone, Debug)]
pub struct SlopeTable {
    x: [f64; TABLE_INTERVALS + 1],
    d: [f64; TABLE_INTERVALS + 1],
    /// Interval `k` lies strictly inside the slope bounds with finite derivatives.
    usable: [bool; TABLE_INTERVALS],
}

/// The sampler for one roughness and incident direction, with the constants that depend
/// only on `wi` computed once.
#[derive(Clone, Copy, Debug)]
pub struct BeckmannVisibleNormals {
    alpha: f64,
    wi: DVec3,
    /// `wi`'s azimuth (`(1, 0)` at normal incidence).
    cos_phi: f64,
    sin_phi: f64,
    /// `G(x) = mu·erfc(−x) + s·exp(−x²)/sqrt(π)` with `s = α sinθi`.
    mu: f64,
    s: f64,
    /// `min(x_max, 9)`, `G` there and `erf` there (the initial guess's `c`).
    x_hi: f64,
    total: f64,
    erf_hi: f64,
    /// PBRT-v3's exponent `1 + θ(−0.876 + θ(0.4265 − 0.0594θ))`, θ the stretched polar
    /// angle of `wi`.
    fit: f64,
    /// `1/(mu_i + L_i)`.
    g1_over_mu: f64,
}

impl BeckmannVisibleNormals {
    /// The sampler for roughness `alpha` and the local unit incident direction `wi`
    /// (`wi.z < 0` is treated as grazing: the caller rejects such directions).
    #[inline(always)]
    pub fn new(alpha: f64, wi: DVec3) -> Self {
        let sin = (wi.x * wi.x + wi.y * wi.y).sqrt();
        let (cos_phi, sin_phi) = if sin > 0.0 {
            (wi.x / sin, wi.y / sin)
        } else {
            (1.0, 0.0)
        };
        let mu = wi.z.max(0.0);
        let s = alpha * sin;
        // x_max = mu/s is +inf at normal incidence; f64::min ignores a NaN (0/0).
        let x_hi = (mu / s).min(SLOPE_BOUND);
        let total = mu * libm::erfc(-x_hi) + s * (-x_hi * x_hi).exp() * FRAC_1_SQRT_PI;
        let theta = s.atan2(mu);
        BeckmannVisibleNormals {
            alpha,
            wi,
            cos_phi,
            sin_phi,
            mu,
            s,
            x_hi,
            total,
            erf_hi: libm::erf(x_hi),
            fit: 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta)),
            g1_over_mu: g1_over_mu(alpha, wi),
        }
    }

    /// Returns the slope `x` along `wi`'s azimuth with CDF `G(x)/G(x_max)` equal to `u`
    /// (in `[0, 1]`).
    #[inline(always)]
    pub fn slope_along(&self, u: f64) -> f64 {
        self.slope_along_pair(u, 1.0 - u)
    }

    /// [`Self::slope_along`] given `u` and its complement `1 − u` (kept exactly by the
    /// caller: the initial guess reads the upper tail from it).
    #[inline(always)]
    pub fn slope_along_pair(&self, u: f64, one_minus_u: f64) -> f64 {
        // The initial guess, erf(x0) = b = c − (1 + c)(1 − u)^fit, with 1 ± b kept
        // accurate for Giles' approximation of erfinv.
        let c = self.erf_hi;
        let t = f64::exp(self.fit * f64::ln(one_minus_u));
        let b = c - (1.0 + c) * t;
        let w = -f64::ln(((1.0 + c) * (1.0 - t)) * ((1.0 - c) + (1.0 + c) * t));
        self.solve(u * self.total, erfinv_guess(b, w), -SLOPE_BOUND, self.x_hi)
    }

    /// Returns the slope of CDF `u(v) = 1 − (1 − v)²` (`v` in `[0, 1)`), the map the
    /// integrator and [`Self::sample`] use: near the top of the CDF, where the density
    /// vanishes linearly at `x_max` and `x_max − x ∝ sqrt(1 − u)`, the slope is smooth in
    /// `v` (`x_max − x ∝ 1 − v`). See `integrate/beckmann.rs`.
    #[inline(always)]
    pub fn slope_along_v(&self, v: f64) -> f64 {
        let s = 1.0 - v;
        self.slope_along_pair(v * (1.0 + s), s * s)
    }

    /// [`Self::slope_along_v`] from a per-cell table of the same map: a cubic Hermite
    /// guess between the table's exact nodes, polished by the same safeguarded Halley
    /// iteration (bracketed by the two nodes), which usually stops after one step. The
    /// first and last intervals (the Gaussian tail and the top of the CDF) take the
    /// untabulated solve.
    #[inline(always)]
    pub fn slope_along_v_tabulated(&self, table: &SlopeTable, v: f64) -> f64 {
        let s = 1.0 - v;
        let (u, one_minus_u) = (v * (1.0 + s), s * s);
        let t = v * TABLE_INTERVALS as f64;
        let k = t as usize;
        if k == 0 || k >= TABLE_INTERVALS - 1 || !table.usable[k] {
            return self.slope_along_pair(u, one_minus_u);
        }
        let f = t - k as f64;
        let (x0, x1) = (table.x[k], table.x[k + 1]);
        let (d0, d1) = (table.d[k], table.d[k + 1]);
        // Hermite basis on [0, 1] with derivatives scaled by the node spacing h.
        let h = 1.0 / TABLE_INTERVALS as f64;
        let f2 = f * f;
        let f3 = f2 * f;
        let guess = (2.0 * f3 - 3.0 * f2 + 1.0) * x0
            + (f3 - 2.0 * f2 + f) * h * d0
            + (-2.0 * f3 + 3.0 * f2) * x1
            + (f3 - f2) * h * d1;
        self.solve(u * self.total, guess, x0, x1)
    }

    /// Builds the table of [`Self::slope_along_v_tabulated`] (`TABLE_INTERVALS + 1`
    /// untabulated solves).
    pub fn table(&self) -> SlopeTable {
        let n = TABLE_INTERVALS;
        let mut x = [0.0; TABLE_INTERVALS + 1];
        let mut d = [0.0; TABLE_INTERVALS + 1];
        for k in 0..=n {
            let v = k as f64 / n as f64;
            x[k] = self.slope_along_v(v);
            // dx/dv = (du/dv)·G(x_max)/G'(x), du/dv = 2(1 − v).
            let g1 = 2.0 * FRAC_1_SQRT_PI * (-x[k] * x[k]).exp() * (self.mu - x[k] * self.s);
            d[k] = 2.0 * (1.0 - v) * self.total / g1;
        }
        let usable = std::array::from_fn(|k| {
            x[k] > -SLOPE_BOUND
                && x[k + 1] < self.x_hi
                && x[k] < x[k + 1]
                && d[k].is_finite()
                && d[k + 1].is_finite()
        });
        SlopeTable { x, d, usable }
    }

    /// Returns `x` with `G(x) = target` by Halley's method from `x0`, safeguarded by
    /// bisection on the bracket `[lo, hi]` that holds the root.
    #[inline(always)]
    fn solve(&self, target: f64, x0: f64, mut lo: f64, mut hi: f64) -> f64 {
        let (mu, s) = (self.mu, self.s);
        let mut x = if x0 > lo && x0 < hi {
            x0
        } else {
            0.5 * (lo + hi)
        };
        for _ in 0..MAX_STEPS {
            let e = f64::exp(-x * x);
            let residual = mu * libm::erfc(-x) + s * e * FRAC_1_SQRT_PI - target;
            // No residual test: a guess whose residual is already tiny (the table's) still
            // takes its Halley step, which costs no evaluation, so the tabulated and the
            // untabulated maps agree to rounding even where G' is small.
            if residual == 0.0 {
                break;
            }
            if residual > 0.0 {
                hi = x;
            } else {
                lo = x;
            }
            // Halley's step: G' = k·e·(mu − x·s), G'' = k·e·(−2x(mu − x·s) − s).
            let slope = mu - x * s;
            let d1 = 2.0 * FRAC_1_SQRT_PI * e * slope;
            let d2 = 2.0 * FRAC_1_SQRT_PI * e * (-2.0 * x * slope - s);
            let step = 2.0 * residual * d1 / (2.0 * d1 * d1 - residual * d2);
            let next = x - step;
            if next > lo && next < hi {
                x = next;
                // Cubic convergence: a step this small leaves an error ~step³, far
                // below the tolerance; no evaluation to confirm it.
                if step.abs() <= 1e-7 * (1.0 + x.abs()) {
                    break;
                }
            } else {
                // Outside the bracket (or NaN: a vanished derivative): bisect.
                x = 0.5 * (lo + hi);
            }
            if hi - lo <= 4.0 * f64::EPSILON * (1.0 + x.abs()) {
                break;
            }
        }
        x
    }

    /// Returns the slope across `wi`'s azimuth: a Gaussian `e^{−y²}/sqrt(π)` (variance
    /// 1/2), `y = Φ⁻¹(a)/sqrt(2)` for `a` in `[0, 1)` (Wichura's AS 241, no iteration),
    /// or (`full = false`) its half `y <= 0`, `y = Φ⁻¹(a/2)/sqrt(2)`, which puts `h` on
    /// the side `h·(−sin φi, cos φi, 0) >= 0`: for `wi` in the xz plane, `h.y >= 0` (the
    /// fold).
    #[inline(always)]
    pub fn slope_across(a: f64, full: bool) -> f64 {
        let y = if full {
            ndtri(a)
        } else {
            // a/2 is exact and 1 − a/2 is at least 1/2: both keep their digits.
            ndtri_pair(0.5 * a, 1.0 - 0.5 * a)
        };
        (y * FRAC_1_SQRT_2).clamp(-SLOPE_BOUND, SLOPE_BOUND)
    }

    /// Returns the unnormalized half vector `(−α·x', −α·y', 1)` of the slopes `(x, y)`
    /// (along and across `wi`'s azimuth), `(x', y')` rotated into the local frame.
    #[inline(always)]
    pub fn scaled_half_vector(&self, x: f64, y: f64) -> DVec3 {
        let (c, s) = (self.cos_phi, self.sin_phi);
        DVec3::new(
            -self.alpha * (c * x - s * y),
            -self.alpha * (s * x + c * y),
            1.0,
        )
    }

    /// Returns the half vector for `u` (the CDF along `wi`'s azimuth, uniform: this is a
    /// sampler of the visible normals; the integrator's `u = 1 − (1 − v)²` carries its
    /// Jacobian in its weights) and `a` (across it; `full = false`: the folded half), with
    /// its density.
    #[inline(always)]
    pub fn sample(&self, u: f64, a: f64, full: bool) -> Sampled {
        let x = self.slope_along(u);
        let y = Self::slope_across(a, full);
        let p = self.scaled_half_vector(x, y);
        let p2 = p.x * p.x + p.y * p.y;
        let n = (1.0 + p2).sqrt();
        let h = DVec3::new(p.x / n, p.y / n, 1.0 / n);
        // 1 − 1/n = p²/(n(n + 1)), without cancellation.
        let one_minus_cos = p2 / (n * (n + 1.0));
        Sampled {
            dir: h,
            one_minus_cos,
            pdf: self.pdf(h, one_minus_cos),
        }
    }

    /// Returns the density of the unit half vector `h` (with `1 − h.z`).
    #[inline(always)]
    pub fn pdf(&self, h: DVec3, one_minus_cos: f64) -> f64 {
        density(self.alpha, self.g1_over_mu, self.wi, h, one_minus_cos)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn wi_at(mu: f64) -> DVec3 {
        DVec3::new(((1.0 - mu) * (1.0 + mu)).sqrt(), 0.0, mu)
    }

    /// The CDF along `wi`'s azimuth is inverted: `G(x(u)) = u·G(x_max)` to 1e-13, at
    /// every incidence from grazing to normal and every roughness, `u` from 0 to 1 − ε.
    #[test]
    fn slope_inverts_the_cdf_everywhere() {
        let mus = [0.0, 1e-12, 1e-6, 0.01, 0.3, 0.7, 0.9999, 1.0 - 1e-12, 1.0];
        let alphas = [1e-7, 1e-3, 0.01, 0.1, 0.5, 1.0, 2.0, 5.0, 1e7];
        let us = [
            0.0,
            1e-300,
            1e-12,
            1e-6,
            0.1,
            0.5,
            0.9,
            1.0 - 1e-9,
            1.0 - f64::EPSILON / 2.0,
        ];
        for mu in mus {
            for alpha in alphas {
                let warp = BeckmannVisibleNormals::new(alpha, wi_at(mu));
                for u in us {
                    let x = warp.slope_along(u);
                    assert!(x.is_finite() && x <= warp.x_hi, "{mu} {alpha} {u}: {x}");
                    let g = warp.mu * libm::erfc(-x) + warp.s * (-x * x).exp() * FRAC_1_SQRT_PI;
                    // The bounds clip the mass beyond |x| = 9 only.
                    let inside = x > -SLOPE_BOUND && x < SLOPE_BOUND;
                    if inside {
                        assert!(
                            (g - u * warp.total).abs() <= 1e-13 * warp.total,
                            "mu={mu} alpha={alpha} u={u}: x={x}, G={g}, want {}",
                            u * warp.total
                        );
                    }
                    let h = warp.sample(u, 0.3, true);
                    assert!(h.dir.is_finite() && h.pdf.is_finite(), "{h:?}");
                    assert!((h.dir.length() - 1.0).abs() < 1e-15);
                }
            }
        }
    }

    /// `G(x_max) = 2(mu_i + L_i)`: the sampler's normalization is the Smith term's.
    #[test]
    fn total_mass_is_the_smith_projected_area() {
        for mu in [0.0, 0.05, 0.5, 0.95, 1.0] {
            for alpha in [0.01, 0.3, 1.0] {
                let warp = BeckmannVisibleNormals::new(alpha, wi_at(mu));
                let want = 2.0 / warp.g1_over_mu;
                assert!(
                    (warp.total - want).abs() <= 1e-15 * want,
                    "{mu} {alpha}: {} {want}",
                    warp.total
                );
            }
        }
    }

    /// `∫ pdf_h dωh = 1` over the hemisphere (the visible normals are normalized) at
    /// grazing, oblique and normal incidence.
    #[test]
    fn pdf_integrates_to_one() {
        for (mu, alpha) in [(0.0, 0.5), (0.02, 0.2), (0.5, 0.05), (0.8, 1.0), (1.0, 0.3)] {
            let wi = wi_at(mu);
            let (nt, np) = (6000, 256);
            let mut sum = 0.0;
            // θh = atan(α·t/(1 − t)): nodes follow the lobe's width.
            for i in 0..nt {
                let t = (i as f64 + 0.5) / nt as f64;
                let tan = alpha * t / (1.0 - t) * 3.0;
                let theta = tan.atan();
                let dtheta = alpha * 3.0 / ((1.0 - t) * (1.0 - t)) / (1.0 + tan * tan) / nt as f64;
                let (st, ct) = theta.sin_cos();
                let omc = 2.0 * (theta / 2.0).sin().powi(2);
                for j in 0..np {
                    let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
                    let h = DVec3::new(st * phi.cos(), st * phi.sin(), ct);
                    sum += beckmann_visible_pdf(alpha, wi, h, omc)
                        * st
                        * dtheta
                        * (2.0 * PI / np as f64);
                }
            }
            // The quadrature's error (the pdf has a kink where wi·h = 0) is ~3e-5; a
            // normalization by G1 of a wrong Λ would be off by percents.
            assert!((sum - 1.0).abs() < 1e-4, "mu={mu} alpha={alpha}: {sum}");
        }
    }
}
