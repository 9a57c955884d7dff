//! Directional albedo by (quasi-)Monte Carlo, cell by cell, with honest error bars.
//!
//! A *cell* is one incidence `mu = cos θi` at azimuth `phi` with one parameter set. Its
//! albedo `R = ∫ f(wi, wo)·mu_o dωo` is computed as the model's decomposition
//! `Σ colour_k · I_k` ([`crate::models::albedo`]): exact terms are added, zero-colour
//! terms skipped, and the remaining scalar integrals estimated together from the same
//! points, each with its lobe's own importance sampler (or the uniform / cosine sampler
//! the caller asks for). GGX's lobes, drawn from their visible normals, are weighted in
//! closed form on a smoothed disk radius (`integrate/ggx.rs`); Beckmann's likewise, on a
//! smoothed slope CDF (`integrate/beckmann.rs`).
//!
//! Estimators:
//! - `sobol`: randomized QMC. `replicates` independent Owen scrambles, each a prefix of
//!   `M = 2^k` points; the estimate is the mean of the replicate means and its standard
//!   error their spread, `sd / sqrt(replicates)`: an honest error bar for RQMC.
//! - `random`: plain Monte Carlo with the per-sample variance.
//!
//! GGX's and Beckmann's closed-form lobes substitute the sampler's first number to smooth
//! the visible normals' rim for Sobol points (the Jacobian enters the weight); plain Monte
//! Carlo takes the sampler's own numbers, as the Jacobian's spread would only add
//! variance there (12× the per-sample spread of `brdf_rs.sample`'s weights for GGX at
//! alpha 0.05, mu 0.9, before this was split).
//!
//! Without the substitution the closed-form weights are `F·G2/G1`, in `[0, 1]`, mostly
//! near 1 for a smooth lobe with a rare region near 0: their per-point variance counts
//! pseudo-points at each bound, so that a cell whose few points missed that region still
//! reports an honest error bar (`scripts/stderr_calibration.py` measures it).
//!
//! Sharp Schlick lobes drawn with Blinn half vectors near normal incidence
//! (`torrance_sparrow`, `blinn_phong_fresnel`) come as strata of one lobe, each
//! integrated on all points, with a control variate for Schlick's excess in the bulk
//! ([`crate::models::strata`]); strata fall back to cosine sampling together. The sums of
//! a lobe with a control are shifted by its first block's mean for Sobol points too (its
//! weights are nearly constant), and its error bar is never below the rounding of the
//! control's closed form ([`Control::rounding`]).
//!
//! A lobe whose importance sampler gives a nonzero weight to fewer than one point in
//! [`MIN_HIT_RATE`] of the first round (a very rough lobe: its half vectors send nearly
//! every point below the horizon) is estimated again with cosine sampling, so that no
//! cell reports 0 ± 0 for a lobe its sampler never reached. Every error bar is at least
//! one ulp of its value, and is formed in scaled colours so that colours near the float
//! range give a finite one.
//!
//! With `tol` (absolute) or `rtol` (relative to the value), a cell doubles its sample
//! count until every channel's standard error is at most `tol + rtol·|value|` (or
//! `max_samples` is reached): cells that converge early stop early.
//!
//! Azimuth: `wi = (sin θ cos φ, sin θ sin φ, mu)` with `n = +z` and the tangent `+x` (φ is
//! measured from the tangent, counterclockwise about `n`). Isotropic models (no tangent)
//! do not depend on φ: they always integrate at φ = 0, so `phi` changes no bit. For the
//! anisotropic ones (Ward, Ashikhmin–Shirley: a tangent, and a lobe anisotropic in the
//! tangent frame) φ places `wi`; the half-vector warps live in the tangent frame (so they
//! are right for any φ) and the mirror frame's `y` is the normal of the plane of incidence.
//! With [`AlbedoOptions::average_azimuth`] an anisotropic cell estimates the azimuth
//! average `(1/2π) ∫ R(mu, φ) dφ` instead, drawing φ per point from a third Sobol
//! dimension (or a third random number) on `[0, π/2)`: the models are even under
//! `y → −y` and `x → −x` of the tangent frame, so `R(φ) = R(−φ) = R(π − φ)` and the
//! quarter carries the whole average. The φ quadrature is part of the (randomized)
//! estimator, so the replicate spread covers its error too.
//!
//! Fold: where the integrand is even in azimuth about the plane of incidence (isotropic
//! models, and the anisotropic ones when the plane of incidence is the tangent frame's
//! xz plane, `sin φ = 0`), the samplers draw azimuths on `[0, π)` only (twice the
//! density on the half that carries the whole integral). Elsewhere they draw the full
//! circle.
//!
//! Everything about a cell depends on (seed, cell id) only: results are bitwise
//! identical for any thread count, chunking or machine split.
//!
//! The parts: `options` (what is asked and returned), `integrand` (a cell's lobes and
//! their weights), `ends` (the end regions of the sampler numbers), `sums` (weights
//! summed into means and error bars), `cell` (one cell's rounds, per instruction set),
//! `loops` (the model-independent warps and closed-form lobes, per instruction set),
//! `ggx` and `beckmann` (the closed-form visible-normal lobes), [`cells`] (a request's
//! cells from broadcast arrays).
//!
//! [`Control::rounding`]: crate::models::albedo::Control::rounding
//! [`MIN_HIT_RATE`]: integrand::MIN_HIT_RATE

use std::sync::atomic::Ordering;

use rayon::prelude::*;

use crate::error::BrdfError;
use crate::models::{Kernel, KernelVisitor, ModelKind};
use crate::parallel;
pub use crate::sampling::SamplerChoice;
use crate::simd;
use cell::integrate_cell_isa;
pub use options::{
    AlbedoOptions, CellResult, Component, DEFAULT_REPLICATES, MAX_REPLICATES, MAX_SAMPLES_PER_CELL,
    MAX_SAMPLES_PER_REQUEST, MIN_REPLICATES, Progress,
};

mod beckmann;
mod cell;
pub mod cells;
mod ends;
mod ggx;
mod integrand;
mod loops;
mod options;
mod sphere;
mod sums;

/// Points per block: the unit of vectorized work.
const POINTS: usize = 256;
/// Most scalar integrals one cell estimates together.
const MAX_LOBES: usize = 4;

/// The cells of a request: `mu`, `phi` and the parameter slots of each cell, and its id.
pub trait Cells: Sync {
    /// Number of cells.
    fn count(&self) -> usize;
    /// Returns `(mu, phi, cell id)` of cell `i`, writing the slots into `slots`.
    fn cell(&self, i: usize, slots: &mut Vec<f64>) -> (f64, f64, u64);
}

struct RunAlbedo<'a, C: Cells> {
    cells: &'a C,
    options: &'a AlbedoOptions,
    progress: &'a Progress,
    out: &'a mut [CellResult],
}

impl<C: Cells> KernelVisitor for RunAlbedo<'_, C> {
    type Output = ();

    fn visit<K: Kernel>(self) {
        let RunAlbedo {
            cells,
            options,
            progress,
            out,
        } = self;
        let isa = simd::isa();
        let work = |(i, result): (usize, &mut CellResult)| {
            if progress.cancel.load(Ordering::Relaxed) {
                return;
            }
            let mut slots = Vec::new();
            let (mu, phi, id) = cells.cell(i, &mut slots);
            // At mu = 0 the light is in the surface's plane, where every family-A `f` is 0
            // (as `eval` returns): the albedo is exactly 0, whatever the model's terms
            // would give as a limit.
            *result = if mu == 0.0 {
                CellResult::default()
            } else {
                integrate_cell_isa::<K>(isa, mu, phi, &slots, id, options, progress)
            };
            progress.cells_done.fetch_add(1, Ordering::Relaxed);
        };
        parallel::install(|| {
            out.par_iter_mut()
                .enumerate()
                .with_max_len(1)
                .for_each(work)
        });
    }
}

/// Integrates every cell into `out` (one result per cell), in parallel over cells.
///
/// # Errors
/// A model without an albedo decomposition (family B), or invalid options.
pub fn albedo<C: Cells>(
    kind: ModelKind,
    cells: &C,
    options: &AlbedoOptions,
    progress: &Progress,
    out: &mut [CellResult],
) -> Result<(), BrdfError> {
    if kind.spec().family != crate::models::Family::A {
        return Err(BrdfError::InvalidArgument(format!(
            "{}: albedo is defined for family-A BRDFs; {} is a family-B shading term",
            kind.name(),
            kind.name()
        )));
    }
    if options.component == Component::Transmission && !kind.spec().transmission {
        return Err(BrdfError::InvalidArgument(format!(
            "component: {} does not transmit (zero below the surface); \
             component=\"transmission\" is for the models that do",
            kind.name()
        )));
    }
    options.validate(cells.count())?;
    kind.visit(RunAlbedo {
        cells,
        options,
        progress,
        out,
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::streams::Sequence;
    use cells::CellGrid;
    use ndarray::{ArrayD, IxDyn};

    fn albedo_one(
        model: &str,
        mu: f64,
        params: &[(&str, f64)],
        options: AlbedoOptions,
    ) -> CellResult {
        albedo_at(model, mu, 0.0, params, options)
    }

    fn albedo_at(
        model: &str,
        mu: f64,
        phi: f64,
        params: &[(&str, f64)],
        options: AlbedoOptions,
    ) -> CellResult {
        let kind = ModelKind::from_name(model).unwrap();
        let mu = ArrayD::from_elem(IxDyn(&[]), mu);
        let phi = ArrayD::from_elem(IxDyn(&[]), phi);
        let arrays: Vec<(&str, ArrayD<f64>)> = params
            .iter()
            .map(|(k, v)| (*k, ArrayD::from_elem(IxDyn(&[]), *v)))
            .collect();
        let views = arrays.iter().map(|(k, a)| (*k, a.view())).collect();
        let grid = CellGrid::new(kind, mu.view(), Some(phi.view()), views, None).unwrap();
        let mut out = [CellResult::default()];
        albedo(kind, &grid, &options, &Progress::default(), &mut out).unwrap();
        out[0]
    }

    fn assert_within(r: CellResult, want: f64, sigmas: f64, label: &str) {
        for c in 0..3 {
            let err = (r.value[c] - want).abs();
            assert!(
                err <= sigmas * r.stderr[c] + 1e-12,
                "{label}: {r:?} vs {want}"
            );
        }
    }

    /// The options of a 2^16-sample run for each sequence (outer) and each of `samplers`.
    fn each_sequence_with(samplers: &[SamplerChoice]) -> impl Iterator<Item = AlbedoOptions> + '_ {
        [Sequence::Sobol, Sequence::Random]
            .into_iter()
            .flat_map(move |sequence| {
                samplers.iter().map(move |&sampler| AlbedoOptions {
                    samples: 1 << 16,
                    sequence,
                    sampler,
                    ..Default::default()
                })
            })
    }

    #[test]
    fn closed_forms() {
        let opts = AlbedoOptions {
            samples: 1 << 16,
            ..Default::default()
        };
        let r = albedo_one("lambert", 0.3, &[("kd", 0.7)], opts);
        assert_eq!(r.value, [0.7; 3]);
        assert_eq!((r.stderr, r.samples), ([0.0; 3], 0));
        for p in [1.0, 10.0, 100.0, 1e3, 1e4] {
            let base = [("kd", 0.0), ("ks", 1.0), ("p", p)];
            let r = albedo_one("normalized_phong", 1.0, &base, opts);
            assert_within(r, 1.0, 5.0, "normalized_phong");
            assert!(r.stderr[0] < 1e-3, "{r:?}");
            let r = albedo_one("modified_phong", 1.0, &base, opts);
            assert_within(
                r,
                2.0 * std::f64::consts::PI / (p + 2.0),
                5.0,
                "modified_phong",
            );
            let exact = (p + 8.0) * (p + 2f64.powf(-p / 2.0)) / ((p + 2.0) * (p + 4.0));
            let r = albedo_one("normalized_blinn_phong", 1.0, &base, opts);
            assert_within(r, exact, 5.0, "normalized_blinn_phong");
        }
        let sigma = 0.6_f64;
        let a = 1.0 - 0.5 * sigma * sigma / (sigma * sigma + 0.33);
        let r = albedo_one("oren_nayar", 1.0, &[("kd", 1.0), ("sigma", sigma)], opts);
        assert_within(r, a, 5.0, "oren_nayar");
    }

    /// Torrance-Sparrow's albedo at normal incidence, `∫ F·G·(p+2)·c^(p+1) dc` with
    /// `G = min(1, 2(2c² − 1))` for `c > cos 45°` (the half vector is at θo/2), by
    /// Gauss-Legendre panels: 16 on `[cos 30°, 1]`, 16 on `[cos 45°, cos 30°]`.
    fn torrance_sparrow_normal(p: f64, r0: f64) -> f64 {
        let (x, w) = (
            [
                -0.960_289_856_497_536,
                -0.796_666_477_413_627,
                -0.525_532_409_916_329,
                -0.183_434_642_495_65,
                0.183_434_642_495_65,
                0.525_532_409_916_329,
                0.796_666_477_413_627,
                0.960_289_856_497_536,
            ],
            [
                0.101_228_536_290_376,
                0.222_381_034_453_374,
                0.313_706_645_877_887,
                0.362_683_783_378_362,
                0.362_683_783_378_362,
                0.313_706_645_877_887,
                0.222_381_034_453_374,
                0.101_228_536_290_376,
            ],
        );
        let f = |c: f64| {
            let fresnel = r0 + (1.0 - r0) * (1.0 - c).powi(5);
            fresnel * (2.0 * (2.0 * c * c - 1.0)).min(1.0) * (p + 2.0) * c.powf(p + 1.0)
        };
        let (c45, c30) = (std::f64::consts::FRAC_1_SQRT_2, 0.75_f64.sqrt());
        let mut sum = 0.0;
        for (a, b) in [(c30, 1.0), (c45, c30)] {
            for i in 0..16 {
                let (lo, hi) = (
                    a + (b - a) * i as f64 / 16.0,
                    a + (b - a) * (i + 1) as f64 / 16.0,
                );
                for (xi, wi) in x.iter().zip(w) {
                    sum += 0.5 * (hi - lo) * wi * f(0.5 * (lo + hi) + 0.5 * (hi - lo) * xi);
                }
            }
        }
        sum
    }

    /// The strata and control of Torrance-Sparrow's lobe at normal incidence: the
    /// estimate is within its (small, nonzero) error bar of the exact value for both
    /// sequences, and the uniform and cosine samplers, which integrate the whole lobe
    /// through its bulk stratum, agree with it.
    #[test]
    fn torrance_sparrow_strata_at_normal_incidence() {
        for (p, eta) in [(100.0, 1.5), (20.0, 1.5), (100.0, 1.0)] {
            let r = (eta - 1.0) / (eta + 1.0);
            let want = torrance_sparrow_normal(p, r * r);
            let base = [("kd", 0.0), ("ks", 1.0), ("p", p), ("eta", eta)];
            let samplers = [
                SamplerChoice::Auto,
                SamplerChoice::Uniform,
                SamplerChoice::Cosine,
            ];
            for opts in each_sequence_with(&samplers) {
                let got = albedo_one("torrance_sparrow", 1.0, &base, opts);
                let label = format!("p={p} eta={eta} {:?} {:?}", opts.sequence, opts.sampler);
                assert!(got.stderr[0] > 0.0, "{label}: {got:?}");
                assert_within(got, want, 5.0, &label);
                if opts.sampler == SamplerChoice::Auto && p == 100.0 && eta == 1.5 {
                    // The control leaves the spread of the tail, of probability 4e-7.
                    assert!(got.stderr[0] < 1e-8 * want, "{label}: {got:?} vs {want}");
                }
            }
        }
    }

    #[test]
    fn sequences_and_samplers_agree() {
        let base = [("kd", 0.0), ("ks", 1.0), ("p", 30.0), ("eta", 1.5)];
        let want = albedo_one(
            "torrance_sparrow",
            0.4,
            &base,
            AlbedoOptions {
                samples: 1 << 20,
                ..Default::default()
            },
        );
        let samplers = [
            SamplerChoice::Uniform,
            SamplerChoice::Cosine,
            SamplerChoice::Importance,
        ];
        for opts in each_sequence_with(&samplers) {
            let r = albedo_one("torrance_sparrow", 0.4, &base, opts);
            let label = format!("{:?} {:?}", opts.sequence, opts.sampler);
            assert_within(r, want.value[0], 5.0, &label);
        }
    }

    #[test]
    fn adaptive_stopping_reaches_the_tolerance() {
        // A lobe without a closed-form bulk (power-cosine lobes now have one). Under tol,
        // every error bar within tol; under rtol, each within rtol of its own value, so a
        // dim albedo stops at a smaller error bar than a bright one; with both, within
        // their sum.
        let (bright, dim) = (
            [("kd", 1.0), ("sigma", 0.5)],
            [("kd", 0.01), ("sigma", 0.5)],
        );
        for sequence in [Sequence::Sobol, Sequence::Random] {
            let opts = AlbedoOptions {
                samples: 256,
                tol: Some(1e-3),
                max_samples: 1 << 22,
                sequence,
                ..Default::default()
            };
            let relative = AlbedoOptions {
                tol: None,
                rtol: Some(2e-3),
                ..opts
            };
            let both = AlbedoOptions {
                rtol: Some(2e-3),
                ..opts
            };
            let r = albedo_one("oren_nayar", 0.5, &bright, opts);
            assert!(r.stderr.iter().all(|&s| s <= 1e-3), "{r:?}");
            assert!(r.samples > 256 && r.samples < 1 << 22, "{r:?}");
            let [b, d, r] = [(&bright, relative), (&dim, relative), (&dim, both)]
                .map(|(params, o)| albedo_one("oren_nayar", 0.5, params, o));
            for (x, t) in [(&b, 0.0), (&d, 0.0), (&r, 1e-3)] {
                assert!(x.samples < 1 << 22, "{x:?}");
                assert!(
                    (0..3).all(|c| x.stderr[c] <= t + 2e-3 * x.value[c]),
                    "{x:?}"
                );
            }
            assert!(b.samples > 256 && d.samples > 256, "{b:?} {d:?}");
            assert!(d.stderr[0] < 0.1 * b.stderr[0], "{b:?} {d:?}");
            assert!(r.samples < d.samples, "{r:?} {d:?}");
        }
    }

    /// Ward with equal roughnesses is isotropic: the albedo at any azimuth (no fold:
    /// frames at a general φ) and the azimuth average equal the value at φ = 0.
    #[test]
    fn isotropic_ward_does_not_depend_on_the_azimuth() {
        let params = [("kd", 0.0), ("ks", 1.0), ("alpha_x", 0.3), ("alpha_y", 0.3)];
        let opts = AlbedoOptions {
            samples: 1 << 16,
            ..Default::default()
        };
        for mu in [0.2, 0.7] {
            let base = albedo_at("ward", mu, 0.0, &params, opts);
            for phi in [0.4, 2.0, -1.0] {
                let r = albedo_at("ward", mu, phi, &params, AlbedoOptions { seed: 1, ..opts });
                let se = (base.stderr[0].powi(2) + r.stderr[0].powi(2)).sqrt();
                assert_within(r, base.value[0], 5.0 * se / r.stderr[0], "ward phi");
            }
            let avg = AlbedoOptions {
                average_azimuth: true,
                seed: 2,
                ..opts
            };
            let r = albedo_at("ward", mu, 0.0, &params, avg);
            let se = (base.stderr[0].powi(2) + r.stderr[0].powi(2)).sqrt();
            assert_within(r, base.value[0], 5.0 * se / r.stderr[0], "ward average");
        }
    }

    /// The azimuth average of anisotropic Ward equals the average of fixed-φ estimates
    /// over a Gauss-Legendre rule in φ on [0, π/2] (the fixed-φ path, a different code).
    #[test]
    fn azimuth_average_is_the_mean_over_phi() {
        // 8-point Gauss-Legendre nodes and weights on [-1, 1].
        const X: [f64; 4] = [
            0.183_434_642_495_65,
            0.525_532_409_916_329,
            0.796_666_477_413_627,
            0.960_289_856_497_536,
        ];
        const W: [f64; 4] = [
            0.362_683_783_378_362,
            0.313_706_645_877_887,
            0.222_381_034_453_374,
            0.101_228_536_290_376,
        ];
        let params = [
            ("kd", 0.0),
            ("ks", 1.0),
            ("alpha_x", 0.15),
            ("alpha_y", 0.5),
        ];
        let opts = AlbedoOptions {
            samples: 1 << 15,
            ..Default::default()
        };
        let mu = 0.4;
        let (mut mean, mut var) = (0.0, 0.0);
        let quarter = std::f64::consts::FRAC_PI_4;
        for (x, w) in X.iter().zip(W) {
            for sign in [-1.0, 1.0] {
                let phi = quarter * (1.0 + sign * x);
                let r = albedo_at("ward", mu, phi, &params, opts);
                mean += 0.5 * w * r.value[0];
                var += (0.5 * w * r.stderr[0]).powi(2);
            }
        }
        let avg = albedo_at(
            "ward",
            mu,
            0.0,
            &params,
            AlbedoOptions {
                average_azimuth: true,
                ..opts
            },
        );
        let at_0 = albedo_at("ward", mu, 0.0, &params, opts);
        let se = (var + avg.stderr[0].powi(2)).sqrt();
        assert!(
            (avg.value[0] - mean).abs() <= 5.0 * se + 1e-4,
            "{avg:?} vs {mean} ± {se}"
        );
        // The average differs from the value at φ = 0 (the test can tell them apart).
        assert!(
            (at_0.value[0] - mean).abs() > 20.0 * se,
            "{at_0:?} vs {mean}"
        );
    }
}
