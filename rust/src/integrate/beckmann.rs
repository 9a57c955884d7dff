//! Beckmann's lobe integrated from its visible normals, with closed-form weights.
//!
//! As for GGX (`integrate/ggx.rs`): drawn from the distribution of visible normals
//! (Heitz & d'Eon 2014, `sampling/beckmann_visible.rs`), the lobe `f = D·G2·F/(4·mu_i·
//! mu_o)` has the weight
//!
//! `f·mu_o/pdf = F·G2/G1(wi) = F·(1 + Λ_i)/(1 + Λ_i + Λ_o)`
//!
//! with Beckmann's exact `Λ(c) = (e^{−c²}/(c·sqrt(π)) − erfc(c))/2`, `c = mu/(α·sinθ)`:
//! one `erfc` and one `exp` for `wo` per point, no NDF, no pdf (0 below the horizon).
//!
//! The slope along `wi`'s azimuth has the CDF `u = G(x)/G(x_max)`, and its density
//! `∝ (mu_i − x·α sinθi)·e^{−x²}` vanishes linearly at `x_max = mu_i/(α sinθi)` (the
//! facets seen edge-on): there `x_max − x ∝ sqrt(1 − u)`, a square-root singularity
//! exactly where `wo` leaves the hemisphere (`wi·h → 0` sends `wo` to `−wi`), like GGX's
//! disk rim. The integrator draws `u = 1 − (1 − v)²`, `v` uniform; `u` then has the
//! density `1/(2(1 − v))`, so the weight gains the Jacobian `2(1 − v)` (it is bounded by
//! 2, not 1). In `v` the slope is smooth up to `x_max`, and Sobol points resolve the
//! horizon region.
//!
//! Measured (benches/albedo_convergence.py, beckmann 64×64: mu midpoints, α log-spaced in
//! [0.01, 1], kd = 0, ks = 1; 2 threads on a shared, loaded machine, one round, budget
//! 10 s; benches/results/albedo_convergence_beckmann.md): RMS true error 1e-4 in 6.9 s
//! with `tol` (NDF sampler: 15.4 s), 10.0 s with fixed samples (NDF: not within 10 s);
//! about 620–670 ns per sample against the NDF's 850–870; ~1% of cells beyond 3 standard
//! errors for both. Under tol = 1e-4 the first visible-normal estimator (uniform `u`,
//! generic weights) had an RMS true error of 1.33e-4 and 64 cells off by more than
//! 3·tol, all too high, at 10–140 standard errors (α ≈ mu/4, stopping at 256 samples);
//! this one: 7.7e-5 and 9 cells (the NDF sampler: 7.65e-5 and 11).
//!
//! The slope solve per point is the sampler's safeguarded Halley iteration started from a
//! per-cell table of the same map (65 exact nodes with derivatives, cubic Hermite between
//! them): one `erfc` + `exp` per point in the table's interior, polished to the iteration's
//! full precision (the step test leaves ~1e-21), so the estimator is the untabulated one to
//! rounding. The slope across `wi`'s azimuth is Wichura's AS 241 normal quantile.

use glam::DVec3;

use super::loops::ClosedFormLobe;

use crate::models::beckmann::{lambda_of_c, mu_lambda};
use crate::sampling::beckmann_visible::{BeckmannVisibleNormals, SlopeTable};

/// One cell's Beckmann lobe: the incidence, its Smith term and the visible-normal warp.
pub(super) struct VisibleLobe {
    normals: BeckmannVisibleNormals,
    table: SlopeTable,
    wi: DVec3,
    alpha: f64,
    /// `1 + Λ_i`.
    one_lambda_i: f64,
    /// F = 1 (F0 = 1), else F = (1 − cos_b)^5 (F0 = 0), else the affine mix.
    f0: f64,
    /// `mu_i > 0`: family-A lobes are 0 at grazing incidence `mu_i = 0`.
    lit: bool,
    /// The substitution `u = 1 − (1 − v)²` (QMC); else `u = u0`.
    smooth: bool,
}

impl VisibleLobe {
    /// The lobe at `wi = (sqrt(1 − mu²), 0, mu)` for roughness `alpha` and grey `f0`.
    /// `smooth`: the QMC substitution of the slope CDF (see the module doc).
    pub(super) fn new(alpha: f64, f0: f64, wi: DVec3, smooth: bool) -> Self {
        let mu_i = wi.z;
        let lit = mu_i > 0.0;
        let l_i = mu_lambda(mu_i, wi.x * wi.x + wi.y * wi.y, alpha);
        let normals = BeckmannVisibleNormals::new(alpha, wi);
        VisibleLobe {
            table: normals.table(),
            normals,
            wi,
            alpha,
            one_lambda_i: if lit { (mu_i + l_i) / mu_i } else { 1.0 },
            f0,
            lit,
            smooth,
        }
    }
}

impl ClosedFormLobe for VisibleLobe {
    fn lit(&self) -> bool {
        self.lit
    }

    fn f0(&self) -> f64 {
        self.f0
    }

    fn smooth(&self) -> bool {
        self.smooth
    }

    /// The weights, with `h̃ = (−α·x, −α·y, 1)` the unnormalized half vector
    /// (`q = |h̃|²`): `M = 2(wi·h̃) − mu_i·q = q·mu_o` and `q²sin²θo = (q − M)(q + M)`, so
    /// `c_o = M/(α·sqrt((q − M)(q + M)))` without normalizing `h̃`; the Jacobian of
    /// `u = 1 − (1 − v)²` relative to uniform `u` is `2(1 − v)`.
    #[inline(always)]
    fn fill<const FOLD: bool, const F_ONE: bool, const SMOOTH: bool>(
        &self,
        u0: &[f64],
        u1: &[f64],
        w: &mut [f64],
    ) {
        let (wi, mu_i) = (self.wi, self.wi.z);
        let (alpha, one_lambda_i) = (self.alpha, self.one_lambda_i);
        for ((w, &u), &a) in w.iter_mut().zip(u0).zip(u1) {
            // Smooth: v = u0, Jacobian 2(1 − v). Else the CDF value is u0 itself:
            // v = 1 − sqrt(1 − u0) = u0/(1 + sqrt(1 − u0)), Jacobian 1.
            let (v, jacobian) = if SMOOTH {
                (u, 2.0 * (1.0 - u))
            } else {
                (u / (1.0 + (1.0 - u).sqrt()), 1.0)
            };
            let x = self.normals.slope_along_v_tabulated(&self.table, v);
            let y = BeckmannVisibleNormals::slope_across(a, !FOLD);
            let h = self.normals.scaled_half_vector(x, y);
            let q = h.length_squared();
            let c = wi.dot(h);
            let m = 2.0 * c - mu_i * q;
            let q2_sin2 = (q - m) * (q + m);
            let c_o = m / (alpha * q2_sin2.sqrt());
            // c_o = ∞ (wo along the normal): Λ_o = 0.
            let lambda_o = if c_o < f64::INFINITY {
                lambda_of_c(c_o)
            } else {
                0.0
            };
            let g = one_lambda_i / (one_lambda_i + lambda_o);
            let fresnel = if F_ONE {
                1.0
            } else {
                let x = 1.0 - c / q.sqrt();
                let x2 = x * x;
                self.f0 + (1.0 - self.f0) * (x2 * x2 * x)
            };
            let x = jacobian * fresnel * g;
            *w = if m > 0.0 { x } else { 0.0 };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::beckmann::Beckmann;
    use crate::models::ggx::{ALPHA, KS};
    use crate::models::{Directions, Kernel};
    use crate::sampling::{Warp, reflect, reflected_pdf};

    /// The closed form equals the generic `f·mu_o/pdf` of the same half vector (the
    /// warp's own sample at `u = 1 − (1 − v)²`), times the Jacobian `2(1 − v)`; without
    /// the substitution, the warp's sample at `u = v` and no Jacobian.
    #[test]
    fn closed_form_weight_is_f_mu_over_pdf() {
        let cases: [(f64, f64); 6] = [
            (0.01, 0.3),
            (0.2, 0.05),
            (0.5, 0.7),
            (1.0, 1.0),
            (0.8, 0.999),
            (1.5, 0.01),
        ];
        for (alpha, mu) in cases {
            for (f0, smooth) in [(1.0, true), (0.0, true), (1.0, false), (0.0, false)] {
                let sin = ((1.0 - mu) * (1.0 + mu)).sqrt();
                let wi = DVec3::new(sin, 0.0, mu);
                let lobe = VisibleLobe::new(alpha, f0, wi, smooth);
                let mut slots = [0.0; 7];
                KS.write(&mut slots, [f0; 3]);
                ALPHA.write(&mut slots, alpha);
                let prepared = Beckmann::prepare::<f64, [f64]>(&slots[..]);
                let warp = Warp::BeckmannVisible { alpha };
                for i in 0..256 {
                    let v = (i as f64 + 0.5) / 256.0;
                    let a = (i * 29 % 256) as f64 / 256.0 + 0.001;
                    let mut w = [0.0];
                    lobe.weights(true, &[v], &[a], &mut w);
                    // Smooth: the warp's u = 1 − (1 − v)², Jacobian 2(1 − v); else u = v.
                    let (u, jacobian) = if smooth {
                        (v * (2.0 - v), 2.0 * (1.0 - v))
                    } else {
                        (v, 1.0)
                    };
                    let sample = warp.sample_folded(wi, [u, a]);
                    let wo = reflect(wi, sample.dir);
                    let pdf = reflected_pdf(sample.pdf, wo.dot(sample.dir));
                    let d = Directions::<f64> {
                        wi,
                        wo,
                        n: DVec3::Z,
                        t: DVec3::X,
                    };
                    let f = Beckmann::eval::<f64>(&prepared, &d)[0];
                    let want = if wo.z > 0.0 && pdf > 0.0 {
                        jacobian * f * wo.z / pdf
                    } else {
                        0.0
                    };
                    assert!(
                        (w[0] - want).abs() <= 1e-11 * want.abs().max(1e-3),
                        "alpha={alpha} mu={mu} f0={f0} smooth={smooth} v={v} a={a}: {} vs {want}",
                        w[0]
                    );
                }
            }
        }
    }

    /// The tabulated slope is the untabulated one to 1e-12 (both polish to the same
    /// root), at every incidence and roughness and across the whole of `v`.
    #[test]
    fn tabulated_slope_is_the_exact_map() {
        for mu in [1e-6_f64, 0.01, 0.2, 0.5, 0.9, 0.999, 1.0] {
            for alpha in [0.005, 0.01, 0.1, 0.5, 1.0, 1.5] {
                let sin = ((1.0 - mu) * (1.0 + mu)).sqrt();
                let normals = BeckmannVisibleNormals::new(alpha, DVec3::new(sin, 0.0, mu));
                let table = normals.table();
                for i in 0..4096 {
                    let v = (i as f64 + 0.37) / 4096.0;
                    let exact = normals.slope_along_v(v);
                    let fast = normals.slope_along_v_tabulated(&table, v);
                    assert!(
                        (exact - fast).abs() <= 1e-12 * (1.0 + exact.abs()),
                        "mu={mu} alpha={alpha} v={v}: {exact} vs {fast}"
                    );
                }
            }
        }
    }
}
