//! One cell's estimate: blocks of points drawn from the cell's streams, weighed and summed
//! ([`integrate_cell`]), round after round until the error bar or the sample budget says
//! stop; compiled once per instruction set, and the copy the chosen [`Isa`] proves this
//! CPU runs is called ([`integrate_cell_isa`]).

use std::sync::atomic::Ordering;

use super::integrand::CellIntegrand;
use super::loops::{self, DirectionBlock, Loops};
use super::options::{AlbedoOptions, CellResult, Progress, Rounds};
use super::sums::{LobeSums, mean_and_stderr};
use super::{MAX_LOBES, POINTS};
use crate::models::{Kernel, TangentUse};
use crate::sampling::streams::{Sequence, Stream};
use crate::simd::Isa;

/// Point scratch of one block.
pub(super) struct PointBlock {
    pub(super) u0: [f64; POINTS],
    pub(super) u1: [f64; POINTS],
    /// The azimuth of `wi` (the azimuth average only).
    u2: [f64; POINTS],
    pub(super) w: [[f64; POINTS]; MAX_LOBES],
    dirs: DirectionBlock,
}

impl PointBlock {
    fn new() -> Self {
        PointBlock {
            u0: [0.0; POINTS],
            u1: [0.0; POINTS],
            u2: [0.0; POINTS],
            w: [[0.0; POINTS]; MAX_LOBES],
            dirs: DirectionBlock::new(),
        }
    }
}

/// Accumulates the next `count` points of a stream into `sums`.
///
/// # Safety
/// The CPU supports `I`'s instruction set.
#[inline(always)]
unsafe fn accumulate<K: Kernel, I: Loops>(
    integrand: &CellIntegrand<K>,
    stream: &mut Stream,
    count: u64,
    block: &mut PointBlock,
    sums: &mut LobeSums,
    cross: bool,
) {
    // Shifted sums: every lobe for the cross sums, lobes kept in bins, and lobes with a
    // control variate.
    let shifted: [bool; MAX_LOBES] = std::array::from_fn(|k| {
        cross
            || sums.bins.iter().any(|&(b, _)| b == k)
            || integrand.lobes.get(k).is_some_and(|l| l.control.is_some())
    });
    let mut left = count;
    while left > 0 {
        let len = left.min(POINTS as u64) as usize;
        if integrand.average {
            stream.fill3(
                &mut block.u0[..len],
                &mut block.u1[..len],
                &mut block.u2[..len],
            );
        } else {
            stream.fill(&mut block.u0[..len], &mut block.u1[..len]);
        }
        for k in 0..integrand.lobes.len() {
            // SAFETY: `weights` needs the CPU to run `I`'s instructions, as does
            // `accumulate`, whose caller `integrate_cell` promises it.
            unsafe {
                integrand.weights::<I>(
                    k,
                    &block.u0[..len],
                    &block.u1[..len],
                    &block.u2[..len],
                    &mut block.w[k][..len],
                    &mut block.dirs,
                )
            };
        }
        sums.add_block(block, integrand.lobes.len(), len, cross, shifted);
        left -= len as u64;
    }
}

/// Estimates one cell. `cell` keys the sample streams.
///
/// `random` is one stream whose per-point variance gives the error bar; `sobol` is
/// `replicates` streams (independent scrambles) whose means' spread gives it. Each round
/// adds points to every stream, so one loop serves both (and the model's code is
/// compiled once per cell function, not once per estimator).
///
/// # Safety
/// The CPU supports `I`'s instruction set.
#[inline(always)]
unsafe fn integrate_cell<K: Kernel, I: Loops>(
    mu: f64,
    phi: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    let terms = K::albedo_terms(slots, mu).unwrap_or_default();
    // A model with a tangent reads it through anisotropic lobes (family A: Ward and
    // Ashikhmin–Shirley); the rest are isotropic and ignore phi.
    let anisotropic = K::SPEC.tangent != TangentUse::None;
    let (mut integrand, exact) = CellIntegrand::<K>::new(mu, phi, anisotropic, &terms, options);
    if integrand.lobes.is_empty() {
        return CellResult {
            value: exact,
            stderr: [0.0; 3],
            samples: 0,
        };
    }
    let mut block = PointBlock::new();
    let random = options.sequence == Sequence::Random;
    let rounds = Rounds::new(options);
    let streams_count = rounds.streams;
    let mut per_stream = rounds.first(options.samples);
    // The cell's streams from their start, and empty sums for them (the skewed lobes
    // kept in bins for Sobol points).
    let fresh = |integrand: &CellIntegrand<K>| {
        let streams: Vec<Stream> = (0..streams_count)
            .map(|r| Stream::new(options.sequence, options.seed, cell, r))
            .collect();
        let skewed: Vec<usize> = if random {
            Vec::new()
        } else {
            (0..integrand.lobes.len())
                .filter(|&k| integrand.lobes[k].skewed())
                .collect()
        };
        let sums = vec![LobeSums::new(&skewed); streams.len()];
        (streams, sums)
    };
    let (mut streams, mut sums) = fresh(&integrand);
    let mut done_per_stream = 0u64;
    let mut checked_hits = false;
    // The previous round's replicate spread (Sobol points), pooled into the next round's.
    let mut previous: Option<[f64; 3]> = None;
    let (mean, stderr, samples) = loop {
        let count = per_stream - done_per_stream;
        for (stream, s) in streams.iter_mut().zip(sums.iter_mut()) {
            // SAFETY: `accumulate` needs `I`'s instructions; `integrate_cell` is called
            // only from the per-ISA cell functions, each for an `I` the CPU runs.
            unsafe { accumulate::<K, I>(&integrand, stream, count, &mut block, s, random) };
        }
        progress
            .samples_done
            .fetch_add(count * streams_count, Ordering::Relaxed);
        done_per_stream = per_stream;
        let total = per_stream * streams_count;
        if !checked_hits {
            checked_hits = true;
            if integrand.fall_back(&sums, total) {
                // Start again with the new samplers, on fresh streams.
                (streams, sums) = fresh(&integrand);
                done_per_stream = 0;
                previous = None;
                continue;
            }
        }
        let (mean, se) = if random {
            sums[0].rgb(&integrand.lobes)
        } else {
            // Replicate means, then their mean and spread.
            let means: Vec<[f64; 3]> = sums.iter().map(|s| s.rgb(&integrand.lobes).0).collect();
            let (mean, se) = mean_and_stderr(&means);
            let floor = LobeSums::skewed_stderr(&sums, &integrand.lobes);
            let pooled = pooled_with_previous(se, previous);
            previous = Some(se);
            (mean, std::array::from_fn(|c| pooled[c].max(floor[c])))
        };
        let value: [f64; 3] = std::array::from_fn(|c| exact[c] + mean[c]);
        let done = rounds.finished(total, &se, &value);
        if done || progress.cancel.load(Ordering::Relaxed) {
            break (mean, se, total);
        }
        per_stream = rounds.next(per_stream);
    };
    let value: [f64; 3] = std::array::from_fn(|c| exact[c] + mean[c]);
    // An estimated value is never more certain than its own rounding (one ulp), nor than
    // the closed forms of its control variates.
    let stderr = std::array::from_fn(|c| {
        let controls: f64 = integrand
            .lobes
            .iter()
            .filter_map(|l| {
                l.control
                    .map(|(k, _)| (l.colour[c] * k.beta).abs() * k.rounding)
            })
            .sum();
        stderr[c].max(value[c].abs() * f64::EPSILON).max(controls)
    });
    CellResult {
        value,
        stderr,
        samples,
    }
}

/// The replicates' spread in a Sobol round after the first: the spread of 16
/// replicates is itself uncertain (about ±18%), and under `tol` the cells that stop at
/// a round are more often those whose spread read small there, so their error bars were
/// too small (up to 2% of cells beyond 3 standard errors, where 0.9% is honest). The
/// previous round's spread, halved (the error of scrambled Sobol points at least halves
/// when their number doubles, for the integrands the samplers make smooth), is a second
/// estimate of this round's: the variance is pooled with it, never below this round's
/// own. The spreads pooled are the replicates' own, before the floor of skewed lobes
/// (a bound for small replicates, not an estimate). The same error bar decides the stop
/// and is reported, so `tol` still bounds it.
pub(super) fn pooled_with_previous(se: [f64; 3], previous: Option<[f64; 3]>) -> [f64; 3] {
    match previous {
        None => se,
        Some(prev) => std::array::from_fn(|c| {
            let projected = 0.5 * prev[c];
            let pooled = se[c].hypot(projected) * std::f64::consts::FRAC_1_SQRT_2;
            se[c].max(pooled)
        }),
    }
}

type CellFn = fn(f64, f64, &[f64], u64, &AlbedoOptions, &Progress) -> CellResult;

/// Defines `$name`: [`integrate_cell`] with the loops of `loops::$isa`, compiled with the
/// attributes given (the instruction set's `target_feature`, none for the baseline).
macro_rules! isa_cell {
    ($(#[$attr:meta])* $name:ident => $isa:ident) => {
        $(#[$attr])*
        fn $name<K: Kernel>(
            mu: f64,
            phi: f64,
            slots: &[f64],
            cell: u64,
            options: &AlbedoOptions,
            progress: &Progress,
        ) -> CellResult {
            // SAFETY: `loops::$isa` runs the instruction set this function is compiled
            // with (the target's baseline, or the features of its `target_feature`, the
            // `simd` list of that variant). The baseline runs on every CPU the crate was
            // compiled for; the others have one caller, `integrate_cell_isa`, which calls
            // them only holding the `Isa` token of their instruction set.
            unsafe { integrate_cell::<K, loops::$isa>(mu, phi, slots, cell, options, progress) }
        }
    };
}

isa_cell!(cell_baseline => Baseline);
isa_cell!(
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    cell_avx2 => Avx2
);
isa_cell!(
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    cell_avx512 => Avx512
);

/// Integrates one cell with the loop compiled for `isa` (whose token proves the CPU
/// supports it).
pub(super) fn integrate_cell_isa<K: Kernel>(
    isa: Isa,
    mu: f64,
    phi: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    // A transmitting model integrates over the whole sphere with its own sampler.
    if let Some(sampler) = K::transmission_sampler(slots) {
        return super::sphere::integrate_cell::<K>(
            isa, sampler, mu, slots, cell, options, progress,
        );
    }
    #[cfg(target_arch = "x86_64")]
    {
        match isa {
            Isa::Avx512(_) => {
                // SAFETY: an `Isa::Avx512` token is made only in `simd`, after `detected`
                // found every feature `cell_avx512` enables on this CPU.
                return unsafe { cell_avx512::<K>(mu, phi, slots, cell, options, progress) };
            }
            Isa::Avx2(_) => {
                // SAFETY: likewise, `Isa::Avx2` proves the features of `cell_avx2`.
                return unsafe { cell_avx2::<K>(mu, phi, slots, cell, options, progress) };
            }
            Isa::Baseline => {}
        }
    }
    let f: CellFn = cell_baseline::<K>;
    f(mu, phi, slots, cell, options, progress)
}
