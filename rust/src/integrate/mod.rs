//! Directional albedo by (quasi-)Monte Carlo, cell by cell, with honest error bars.
//!
//! A *cell* is one incidence `mu = cos θi` with one parameter set. Its albedo
//! `R = ∫ f(wi, wo)·mu_o dωo` is computed as the model's decomposition
//! `Σ colour_k · I_k` ([`crate::models::albedo`]): exact terms are added, zero-colour
//! terms skipped, and the remaining scalar integrals estimated together from the same
//! points, each with its lobe's own importance sampler (or the uniform / cosine sampler
//! the caller asks for).
//!
//! Estimators:
//! - `sobol`: randomized QMC. `replicates` independent Owen scrambles, each a prefix of
//!   `M = 2^k` points; the estimate is the mean of the replicate means and its standard
//!   error their spread, `sd / sqrt(replicates)`: an honest error bar for RQMC.
//! - `random`: plain Monte Carlo with the per-sample variance.
//!
//! With `tol`, a cell doubles its sample count until the largest channel's standard
//! error is at most `tol` (or `max_samples` is reached): cells that converge early stop
//! early. The integrands are even in azimuth about the plane of incidence, so
//! the samplers draw azimuths on `[0, π)` only (twice the density on the half that
//! carries the whole integral).
//!
//! Everything about a cell depends on (seed, cell id) only: results are bitwise
//! identical for any thread count, chunking or machine split.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use glam::DVec3;
use rayon::prelude::*;

use crate::error::BrdfError;
use crate::models::albedo::{Importance, Integral, Term};
use crate::models::{Directions, Kernel, KernelVisitor, ModelKind};
use crate::parallel;
use crate::sampling::streams::{SOBOL_MAX_POINTS, Sequence, Stream};
use crate::sampling::{Frame, Warp, reflect, reflected_pdf};

pub mod cells;

/// The largest sample count one cell may use (2^40 ≈ 1.1e12).
pub const MAX_SAMPLES_PER_CELL: u64 = 1 << 40;
/// The largest total sample count one request may ask for (2^44 ≈ 1.8e13: days of work).
pub const MAX_SAMPLES_PER_REQUEST: f64 = 17_592_186_044_416.0;

/// Which sampler draws each lobe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerChoice {
    /// The best available: the lobe's own importance sampler.
    Auto,
    /// The lobe's own importance sampler.
    Importance,
    /// Cosine-weighted about the normal for every lobe.
    Cosine,
    /// Uniform over the hemisphere for every lobe.
    Uniform,
}

impl SamplerChoice {
    /// Parses `auto`, `importance`, `cosine` or `uniform`.
    pub fn from_name(name: &str) -> Option<SamplerChoice> {
        match name {
            "auto" => Some(SamplerChoice::Auto),
            "importance" => Some(SamplerChoice::Importance),
            "cosine" => Some(SamplerChoice::Cosine),
            "uniform" => Some(SamplerChoice::Uniform),
            _ => None,
        }
    }
}

/// Options of an albedo computation.
#[derive(Clone, Copy, Debug)]
pub struct AlbedoOptions {
    /// Samples per cell (the first round when `tol` is set).
    pub samples: u64,
    pub sampler: SamplerChoice,
    pub sequence: Sequence,
    pub seed: u64,
    /// Stop a cell once every channel's standard error is at most this.
    pub tol: Option<f64>,
    /// Upper bound on a cell's samples when `tol` is set.
    pub max_samples: u64,
    /// Independent scrambles per cell for `sobol` (the error bar's degrees of freedom + 1).
    pub replicates: u32,
}

impl Default for AlbedoOptions {
    fn default() -> Self {
        AlbedoOptions {
            samples: 4096,
            sampler: SamplerChoice::Auto,
            sequence: Sequence::Sobol,
            seed: 0,
            tol: None,
            max_samples: 1 << 24,
            replicates: 16,
        }
    }
}

impl AlbedoOptions {
    /// Checks the options for `cells` cells; refuses absurd requests up front.
    pub fn validate(&self, cells: usize) -> Result<(), BrdfError> {
        let bad = |m: String| Err(BrdfError::InvalidArgument(m));
        if self.samples == 0 || self.samples > MAX_SAMPLES_PER_CELL {
            return bad(format!(
                "samples: must be between 1 and 2^40 = {MAX_SAMPLES_PER_CELL} per cell; got {}",
                self.samples
            ));
        }
        if let Some(tol) = self.tol {
            if !(tol > 0.0 && tol.is_finite()) {
                return bad(format!("tol: must be a positive number; got {tol}"));
            }
            if self.max_samples < self.samples || self.max_samples > MAX_SAMPLES_PER_CELL {
                return bad(format!(
                    "max_samples: must be between samples ({}) and 2^40; got {}",
                    self.samples, self.max_samples
                ));
            }
        }
        if self.replicates < 2 || self.replicates > 4096 {
            return bad(format!(
                "replicates: must be between 2 and 4096 (independent scrambles per cell); got {}",
                self.replicates
            ));
        }
        let per_cell = if self.tol.is_some() { self.max_samples } else { self.samples };
        let total = per_cell as f64 * cells as f64;
        if total > MAX_SAMPLES_PER_REQUEST {
            return bad(format!(
                "the request asks for up to {total:.3e} samples ({cells} cells x {per_cell}); \
                 the limit is 2^44 = {MAX_SAMPLES_PER_REQUEST:.3e} (days of computing): \
                 use fewer cells, fewer samples or a tolerance"
            ));
        }
        Ok(())
    }
}

/// One cell's result.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CellResult {
    pub value: [f64; 3],
    pub stderr: [f64; 3],
    /// Samples drawn (per lobe; 0 when the albedo is known exactly).
    pub samples: u64,
}

/// Progress counters shared with the caller (polled while a table builds) and a stop flag.
#[derive(Debug, Default)]
pub struct Progress {
    pub cells_done: AtomicU64,
    pub samples_done: AtomicU64,
    pub cancel: AtomicBool,
}

/// A lobe ready to sample: the prepared basis evaluation and its warp.
struct Lobe<P> {
    colour: [f64; 3],
    prepared: P,
    warp: Warp,
    /// Whether the warp samples half vectors (reflected into `wo`).
    half_vector: bool,
    /// Whether the warp's axis is the mirror direction (else the normal).
    about_mirror: bool,
}

/// The per-sample contribution of every lobe of a cell.
struct CellIntegrand<K: Kernel> {
    lobes: Vec<Lobe<K::Prepared<f64>>>,
    wi: DVec3,
    mirror_frame: Frame,
}

const NORMAL_FRAME: Frame = Frame { x: DVec3::X, y: DVec3::Y, z: DVec3::Z };

impl<K: Kernel> CellIntegrand<K> {
    fn new(mu: f64, terms: &[Term], sampler: SamplerChoice) -> (Self, [f64; 3]) {
        let sin = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
        let wi = DVec3::new(sin, 0.0, mu);
        // The mirror direction's frame keeps y normal to the plane of incidence, so the
        // azimuth fold maps the integrand onto itself.
        let mirror_frame = Frame::with_y(DVec3::new(-sin, 0.0, mu), DVec3::Y);
        let mut exact = [0.0; 3];
        let mut lobes = Vec::new();
        for term in terms {
            if term.colour.iter().all(|&c| c == 0.0) {
                continue;
            }
            match term.integral {
                Integral::Exact(v) => {
                    for (e, c) in exact.iter_mut().zip(term.colour) {
                        *e += c * v;
                    }
                }
                Integral::Lobe { basis, importance } => {
                    let prepared = K::prepare::<f64, [f64]>(&basis[..]);
                    let (warp, half_vector, about_mirror) = match (sampler, importance) {
                        (SamplerChoice::Uniform, _) => (Warp::UniformHemisphere, false, false),
                        (SamplerChoice::Cosine, _) | (_, Importance::Cosine) => {
                            (Warp::CosineHemisphere, false, false)
                        }
                        (_, Importance::PhongLobe { p }) => (Warp::PhongLobe { p }, false, true),
                        (_, Importance::BlinnHalf { p }) => (Warp::BlinnHalf { p }, true, false),
                    };
                    lobes.push(Lobe { colour: term.colour, prepared, warp, half_vector, about_mirror });
                }
            }
        }
        (CellIntegrand { lobes, wi, mirror_frame }, exact)
    }

    /// Returns the RGB estimate `Σ colour·f·mu_o/pdf` for one point `u`.
    #[inline]
    fn sample(&self, u: [f64; 2]) -> [f64; 3] {
        let mut rgb = [0.0; 3];
        for lobe in &self.lobes {
            // Points on the half azimuth range [0, π) have density 2·pdf there, and the
            // integral is twice the half's: the two factors cancel in f·mu_o/pdf.
            let s = lobe.warp.sample_folded(u);
            let (wo, pdf) = if lobe.half_vector {
                let h = s.dir;
                let wo = reflect(self.wi, h);
                let pdf_h = lobe.warp.pdf(h.z, s.one_minus_cos);
                (wo, reflected_pdf(pdf_h, wo.dot(h)))
            } else {
                let frame = if lobe.about_mirror { &self.mirror_frame } else { &NORMAL_FRAME };
                (frame.to_world(s.dir), lobe.warp.pdf(s.dir.z, s.one_minus_cos))
            };
            if !(wo.z > 0.0 && pdf > 0.0) {
                continue;
            }
            let d = Directions::<f64> { wi: self.wi, wo, n: DVec3::Z, t: DVec3::X };
            let f = K::eval::<f64>(&lobe.prepared, &d)[0];
            let w = f * wo.z / pdf;
            for (c, colour) in rgb.iter_mut().zip(lobe.colour) {
                *c += colour * w;
            }
        }
        rgb
    }
}

/// Running sums of RGB values and their squares.
#[derive(Clone, Copy, Default)]
struct Sums {
    n: u64,
    sum: [f64; 3],
    sum_sq: [f64; 3],
}

impl Sums {
    fn add(&mut self, x: [f64; 3]) {
        self.n += 1;
        for c in 0..3 {
            self.sum[c] += x[c];
            self.sum_sq[c] += x[c] * x[c];
        }
    }

    fn mean(&self) -> [f64; 3] {
        self.sum.map(|s| s / self.n as f64)
    }

    /// Standard error of the mean of the added values.
    fn stderr(&self) -> [f64; 3] {
        let n = self.n as f64;
        std::array::from_fn(|c| {
            let mean = self.sum[c] / n;
            let var = ((self.sum_sq[c] - n * mean * mean) / (n - 1.0)).max(0.0);
            (var / n).sqrt()
        })
    }
}

/// Estimates one cell. `cell` keys the sample streams.
fn integrate_cell<K: Kernel>(
    mu: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    let terms = K::albedo_terms(slots).unwrap_or_default();
    let (integrand, exact) = CellIntegrand::<K>::new(mu, &terms, options.sampler);
    if integrand.lobes.is_empty() {
        return CellResult { value: exact, stderr: [0.0; 3], samples: 0 };
    }
    let target = |n: u64| match options.tol {
        Some(_) => n.min(options.max_samples),
        None => n,
    };
    let (mean, stderr, samples) = match options.sequence {
        Sequence::Random => {
            let mut stream = Stream::new(Sequence::Random, options.seed, cell, 0);
            let mut sums = Sums::default();
            let mut goal = target(options.samples).max(2);
            loop {
                while sums.n < goal {
                    sums.add(integrand.sample(stream.next_point()));
                }
                progress.samples_done.fetch_add(goal, Ordering::Relaxed);
                let se = sums.stderr();
                let done = match options.tol {
                    None => true,
                    Some(tol) => se.iter().all(|&s| s <= tol) || goal >= options.max_samples,
                };
                if done || progress.cancel.load(Ordering::Relaxed) {
                    break (sums.mean(), se, sums.n);
                }
                goal = (goal * 2).min(options.max_samples);
            }
        }
        Sequence::Sobol => {
            let reps = options.replicates as u64;
            // Points per replicate: a power of two, at most the Sobol limit; beyond it,
            // more replicates.
            let mut per_rep = (target(options.samples).div_ceil(reps)).next_power_of_two();
            let mut n_reps = reps;
            if per_rep > SOBOL_MAX_POINTS {
                n_reps = reps * (per_rep / SOBOL_MAX_POINTS);
                per_rep = SOBOL_MAX_POINTS;
            }
            let mut replicate_sums: Vec<[f64; 3]> = Vec::new();
            let mut streams: Vec<Stream> = Vec::new();
            let mut done_per_rep = 0u64;
            loop {
                while streams.len() < n_reps as usize {
                    let r = streams.len() as u64;
                    streams.push(Stream::new(Sequence::Sobol, options.seed, cell, r));
                    replicate_sums.push([0.0; 3]);
                    // A new replicate must catch up with the others' point count.
                    let catch_up = done_per_rep;
                    let (s, acc) = (streams.last_mut().unwrap(), replicate_sums.last_mut().unwrap());
                    for _ in 0..catch_up {
                        let x = integrand.sample(s.next_point());
                        for c in 0..3 {
                            acc[c] += x[c];
                        }
                    }
                }
                for (s, acc) in streams.iter_mut().zip(replicate_sums.iter_mut()) {
                    for _ in done_per_rep..per_rep {
                        let x = integrand.sample(s.next_point());
                        for c in 0..3 {
                            acc[c] += x[c];
                        }
                    }
                }
                progress.samples_done.fetch_add((per_rep - done_per_rep) * n_reps, Ordering::Relaxed);
                done_per_rep = per_rep;
                let mut sums = Sums::default();
                for acc in &replicate_sums {
                    sums.add(acc.map(|s| s / per_rep as f64));
                }
                let se = sums.stderr();
                let total = per_rep * n_reps;
                let done = match options.tol {
                    None => true,
                    Some(tol) => se.iter().all(|&s| s <= tol) || total * 2 > options.max_samples,
                };
                if done || progress.cancel.load(Ordering::Relaxed) {
                    break (sums.mean(), se, total);
                }
                if per_rep < SOBOL_MAX_POINTS {
                    per_rep *= 2;
                } else {
                    n_reps *= 2;
                }
            }
        }
    };
    let value = std::array::from_fn(|c| exact[c] + mean[c]);
    CellResult { value, stderr, samples }
}

/// The cells of a request: `mu` and the parameter slots of each cell, and its id.
pub trait Cells: Sync {
    /// Number of cells.
    fn len(&self) -> usize;
    /// Returns `(mu, slots, cell id)` of cell `i`, writing the slots into `slots`.
    fn cell(&self, i: usize, slots: &mut Vec<f64>) -> (f64, u64);
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
        let RunAlbedo { cells, options, progress, out } = self;
        let work = |(i, result): (usize, &mut CellResult)| {
            if progress.cancel.load(Ordering::Relaxed) {
                return;
            }
            let mut slots = Vec::new();
            let (mu, id) = cells.cell(i, &mut slots);
            *result = integrate_cell::<K>(mu, &slots, id, options, progress);
            progress.cells_done.fetch_add(1, Ordering::Relaxed);
        };
        parallel::install(|| out.par_iter_mut().enumerate().with_max_len(1).for_each(work));
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
    options.validate(cells.len())?;
    kind.visit(RunAlbedo { cells, options, progress, out });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use cells::CellGrid;
    use ndarray::{ArrayD, IxDyn};

    fn albedo_one(model: &str, mu: f64, params: &[(&str, f64)], options: AlbedoOptions) -> CellResult {
        let kind = ModelKind::from_name(model).unwrap();
        let mu = ArrayD::from_elem(IxDyn(&[]), mu);
        let arrays: Vec<(&str, ArrayD<f64>)> =
            params.iter().map(|(k, v)| (*k, ArrayD::from_elem(IxDyn(&[]), *v))).collect();
        let views = arrays.iter().map(|(k, a)| (*k, a.view())).collect();
        let grid = CellGrid::new(kind, mu.view(), views, None).unwrap();
        let mut out = [CellResult::default()];
        albedo(kind, &grid, &options, &Progress::default(), &mut out).unwrap();
        out[0]
    }

    fn assert_within(r: CellResult, want: f64, sigmas: f64, label: &str) {
        for c in 0..3 {
            let err = (r.value[c] - want).abs();
            assert!(err <= sigmas * r.stderr[c] + 1e-12, "{label}: {r:?} vs {want}");
        }
    }

    #[test]
    fn closed_forms() {
        let opts = AlbedoOptions { samples: 1 << 16, ..Default::default() };
        let r = albedo_one("lambert", 0.3, &[("kd", 0.7)], opts);
        assert_eq!(r.value, [0.7; 3]);
        assert_eq!((r.stderr, r.samples), ([0.0; 3], 0));
        for p in [1.0, 10.0, 100.0, 1e3, 1e4] {
            let base = [("kd", 0.0), ("ks", 1.0), ("p", p)];
            let r = albedo_one("normalized_phong", 1.0, &base, opts);
            assert_within(r, 1.0, 5.0, "normalized_phong");
            assert!(r.stderr[0] < 1e-3, "{r:?}");
            let r = albedo_one("modified_phong", 1.0, &base, opts);
            assert_within(r, 2.0 * std::f64::consts::PI / (p + 2.0), 5.0, "modified_phong");
            let exact = (p + 8.0) * (p + 2f64.powf(-p / 2.0)) / ((p + 2.0) * (p + 4.0));
            let r = albedo_one("normalized_blinn_phong", 1.0, &base, opts);
            assert_within(r, exact, 5.0, "normalized_blinn_phong");
        }
        let sigma = 0.6_f64;
        let a = 1.0 - 0.5 * sigma * sigma / (sigma * sigma + 0.33);
        let r = albedo_one("oren_nayar", 1.0, &[("kd", 1.0), ("sigma", sigma)], opts);
        assert_within(r, a, 5.0, "oren_nayar");
    }

    #[test]
    fn sequences_and_samplers_agree() {
        let base = [("kd", 0.0), ("ks", 1.0), ("p", 30.0), ("eta", 1.5)];
        let want = albedo_one(
            "torrance_sparrow",
            0.4,
            &base,
            AlbedoOptions { samples: 1 << 20, ..Default::default() },
        );
        for sequence in [Sequence::Sobol, Sequence::Random] {
            for sampler in [SamplerChoice::Uniform, SamplerChoice::Cosine, SamplerChoice::Importance] {
                let opts = AlbedoOptions { samples: 1 << 16, sequence, sampler, ..Default::default() };
                let r = albedo_one("torrance_sparrow", 0.4, &base, opts);
                assert_within(r, want.value[0], 5.0, &format!("{sequence:?} {sampler:?}"));
            }
        }
    }

    #[test]
    fn adaptive_stopping_reaches_the_tolerance() {
        let base = [("kd", 0.0), ("ks", 1.0), ("p", 200.0)];
        for sequence in [Sequence::Sobol, Sequence::Random] {
            let opts = AlbedoOptions {
                samples: 256,
                tol: Some(1e-4),
                max_samples: 1 << 22,
                sequence,
                ..Default::default()
            };
            let r = albedo_one("normalized_phong", 0.5, &base, opts);
            assert!(r.stderr.iter().all(|&s| s <= 1e-4), "{r:?}");
            assert!(r.samples > 256 && r.samples < 1 << 22, "{r:?}");
        }
    }
}
