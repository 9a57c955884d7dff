//! What a caller asks of an albedo computation ([`AlbedoOptions`], checked up front) and
//! what it gets back ([`CellResult`], and the [`Progress`] counters it can poll).

use std::sync::atomic::{AtomicBool, AtomicU64};

use crate::error::BrdfError;
use crate::sampling::SamplerChoice;
use crate::sampling::streams::{SOBOL_MAX_POINTS, Sequence};

/// The largest sample count one cell may use (2^40 ≈ 1.1e12).
pub const MAX_SAMPLES_PER_CELL: u64 = 1 << 40;
/// The largest total sample count one request may ask for (2^44 ≈ 1.8e13: days of work).
pub const MAX_SAMPLES_PER_REQUEST: f64 = 17_592_186_044_416.0;
/// Independent scrambles per Sobol cell: the fewest and most allowed, and the default.
pub const MIN_REPLICATES: u32 = 2;
pub const MAX_REPLICATES: u32 = 4096;
pub const DEFAULT_REPLICATES: u32 = 16;

/// Which part of a transmitting model's albedo over the whole sphere is integrated: `wo`
/// above the surface (reflection), below it (transmission), or both. For the models that
/// do not transmit, `Total` and `Reflection` are the same integral (over the hemisphere)
/// and `Transmission` is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Component {
    Total,
    Reflection,
    Transmission,
}

impl Component {
    /// Every component, in the order of [`Component::NAMES`].
    pub const ALL: [Component; 3] = [
        Component::Total,
        Component::Reflection,
        Component::Transmission,
    ];
    /// Their names, as `component=` takes them.
    pub const NAMES: [&'static str; 3] = ["total", "reflection", "transmission"];

    /// Returns the name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// Parses `total`, `reflection` or `transmission`.
    pub fn from_name(name: &str) -> Option<Component> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// How a cell's rounds proceed, the same for the hemisphere's and the sphere's
/// integrators: how many streams, how many points each takes in the first round, when a
/// round is the last, and how many points each has after the next.
#[derive(Clone, Copy, Debug)]
pub struct Rounds {
    /// One stream of random points, or `replicates` independently scrambled Sobol streams.
    pub streams: u64,
    random: bool,
    tol: Option<f64>,
    rtol: Option<f64>,
    max_samples: u64,
}

impl Rounds {
    pub fn new(options: &AlbedoOptions) -> Self {
        let random = options.sequence == Sequence::Random;
        Rounds {
            streams: if random {
                1
            } else {
                u64::from(options.replicates)
            },
            random,
            tol: options.tol,
            rtol: options.rtol,
            max_samples: options.max_samples,
        }
    }

    /// Points per stream in the first round: `samples` (at most the cap under `tol` or
    /// `rtol`), at least 2 for a variance (random); a power of two per replicate, as every
    /// such prefix is a net (Sobol).
    pub fn first(&self, samples: u64) -> u64 {
        let cap = if self.tol.is_some() || self.rtol.is_some() {
            self.max_samples
        } else {
            u64::MAX
        };
        let first = samples.min(cap);
        if self.random {
            first.max(2)
        } else {
            first.div_ceil(self.streams).next_power_of_two()
        }
    }

    /// Whether the round that brought the cell to `total` points is its last: always
    /// without `tol` and `rtol`; with either, once every channel's error bar `se` is within
    /// `tol + rtol·|value|` (an absent one counting 0) or the next round would pass
    /// `max_samples`.
    pub fn finished(&self, total: u64, se: &[f64; 3], value: &[f64; 3]) -> bool {
        if self.tol.is_none() && self.rtol.is_none() {
            return true;
        }
        let capped = if self.random {
            total >= self.max_samples
        } else {
            total * 2 > self.max_samples
        };
        let tol = self.tol.unwrap_or(0.0);
        // Without rtol the value stays out of the rule (as before it existed: no 0·inf).
        let bound = |v: f64| self.rtol.map_or(tol, |r| tol + r * v.abs());
        se.iter().zip(value).all(|(&s, &v)| s <= bound(v)) || capped
    }

    /// Points per stream after the next round: twice as many (random: at most the cap).
    pub fn next(&self, per_stream: u64) -> u64 {
        if self.random {
            (per_stream * 2).min(self.max_samples)
        } else {
            per_stream * 2
        }
    }
}

/// Options of an albedo computation.
#[derive(Clone, Copy, Debug)]
pub struct AlbedoOptions {
    /// Samples per cell (the first round when `tol` or `rtol` is set).
    pub samples: u64,
    pub sampler: SamplerChoice,
    pub sequence: Sequence,
    pub seed: u64,
    /// Stop a cell once every channel's standard error is at most this (plus `rtol` times
    /// the channel's value, when `rtol` is set too).
    pub tol: Option<f64>,
    /// Stop a cell once every channel's standard error is at most this times the
    /// channel's absolute value (plus `tol`, when set too).
    pub rtol: Option<f64>,
    /// Upper bound on a cell's samples when `tol` or `rtol` is set.
    pub max_samples: u64,
    /// Independent scrambles per cell for `sobol` (the error bar's degrees of freedom + 1).
    pub replicates: u32,
    /// Use the integrand's evenness in azimuth: draw azimuths on `[0, π)` only. Off, the
    /// points cover the full circle (the same estimator with half the point density
    /// per unit of azimuth); kept switchable so benchmarks can show what it buys. Used
    /// only where valid (see the module docs).
    pub fold_azimuth: bool,
    /// Estimate the average over the azimuth of `wi` (the cells' `phi` is then unused).
    pub average_azimuth: bool,
    /// The part of a transmitting model's albedo integrated ([`Component`]).
    pub component: Component,
}

impl Default for AlbedoOptions {
    fn default() -> Self {
        AlbedoOptions {
            samples: 4096,
            sampler: SamplerChoice::Auto,
            sequence: Sequence::Sobol,
            seed: 0,
            tol: None,
            rtol: None,
            max_samples: 1 << 24,
            replicates: DEFAULT_REPLICATES,
            fold_azimuth: true,
            average_azimuth: false,
            component: Component::Total,
        }
    }
}

impl AlbedoOptions {
    /// Whether cells stop on their own error bars (`tol` or `rtol` set), doubling their
    /// samples up to `max_samples`.
    pub fn adaptive(&self) -> bool {
        self.tol.is_some() || self.rtol.is_some()
    }

    /// Checks the options for `cells` cells; refuses absurd requests up front.
    pub fn validate(&self, cells: usize) -> Result<(), BrdfError> {
        let bad = |m: String| Err(BrdfError::InvalidArgument(m));
        if self.samples == 0 || self.samples > MAX_SAMPLES_PER_CELL {
            return bad(format!(
                "samples: must be between 1 and 2^40 = {MAX_SAMPLES_PER_CELL} per cell; got {}",
                self.samples
            ));
        }
        for (name, value) in [("tol", self.tol), ("rtol", self.rtol)] {
            if let Some(t) = value
                && !(t > 0.0 && t.is_finite())
            {
                return bad(format!("{name}: must be a positive number; got {t}"));
            }
        }
        if self.adaptive()
            && (self.max_samples < self.samples || self.max_samples > MAX_SAMPLES_PER_CELL)
        {
            return bad(format!(
                "max_samples: must be between samples ({}) and 2^40; got {}",
                self.samples, self.max_samples
            ));
        }
        if !(MIN_REPLICATES..=MAX_REPLICATES).contains(&self.replicates) {
            return bad(format!(
                "replicates: must be between {MIN_REPLICATES} and {MAX_REPLICATES} \
                 (independent scrambles per cell); got {}",
                self.replicates
            ));
        }
        let per_cell = if self.adaptive() {
            self.max_samples
        } else {
            self.samples
        };
        if self.sequence == Sequence::Sobol
            && per_cell
                .div_ceil(u64::from(self.replicates))
                .next_power_of_two()
                > SOBOL_MAX_POINTS
        {
            return bad(format!(
                "samples: {per_cell} samples over {} replicates passes 2^32 Sobol points per \
                 replicate; use more replicates",
                self.replicates
            ));
        }
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
