//! The hot loop: blocks of rows in structure-of-arrays scratch, one model per loop,
//! compiled once per instruction set and chosen at run time.
//!
//! Each task takes up to `TASK_BLOCKS` blocks of `BLOCK` rows. Per block it (1) copies the
//! direction rows into scratch, deinterleaved, (2) normalizes them and flags unusable
//! rows (a full block of contiguous rows of ordinary lengths: both in one pass), (3)
//! copies varying parameters into scratch, (4) runs the model over the block (for a
//! kernel with [`Kernel::SPLIT_POWER`], in three passes: the power's base, the power, the
//! rest; the powers the short way where they are ordinary, [`PowUnit::pow_unit_ordinary`])
//! and writes RGB rows into the output. Steps 2 and 4 are straight-line
//! loops over scratch that LLVM vectorizes across elements (8 `f64` / 16 `f32` lanes on
//! AVX-512).

use std::marker::PhantomData;

use rayon::prelude::*;

use super::rows::Rows;
use super::{Plan, Precision};
use crate::math::geometry::{Cosine, tangent_parallel, wide_cosine};
use crate::math::{FastPow, FastPowDivisionFree, PowUnit, Real, TablePow, Vector3};
use crate::models::slots::MAX_VARYING_SLOTS;
use crate::models::{
    Directions, Kernel, KernelVisitor, ParamSource, PowerStage, STAGE_KEEP, WideRow,
};
use crate::parallel;
use crate::simd::{Isa, isa};

/// Rows per block (the scratch stays inside L1).
pub const BLOCK: usize = 128;
/// Most blocks per parallel task.
pub const TASK_BLOCKS: usize = 16;
/// A block of at most this many rows (a small batch, or the last block of one) is
/// computed over this many lanes, not over the whole block: a call with a few rows does
/// not pay for `BLOCK`.
pub const SHORT_BLOCK: usize = 16;
/// A task of uniform parameters with at least this many rows asks a divided kernel for
/// its divisor's cache ([`Kernel::divisor_cache`]): `ggx_dielectric_ms` blends its 194
/// table rows once instead of two per row.
pub const DIVISOR_CACHE_ROWS: usize = BLOCK;
/// Outputs at least this large are written with non-temporal stores: far beyond the
/// per-core caches (2 MiB of L2 here), caching them would only evict the inputs still to
/// be read, and each line stored would first be read from memory. Measured, `out=`,
/// interleaved with the previous build: lambert float64 +15–35% on 1 thread and +5–10% on
/// 2 at 2M–8M rows (48–192 MB), torrance_sparrow float64 +0–8%; no loss at 200k rows.
pub const STREAM_BYTES: usize = 32 << 20;

/// Block scratch: directions (4 vectors × 3 components), a usable flag, parameters,
/// and the RGB results before they are interleaved into the output.
struct Scratch<F> {
    vectors: [[[F; BLOCK]; 3]; 4],
    ok: [bool; BLOCK],
    params: [[F; BLOCK]; MAX_VARYING_SLOTS],
    rgb: [[F; BLOCK]; 3],
}

/// Block scratch of the split evaluation ([`Kernel::SPLIT_POWER`]): the powers' bases,
/// complements and exponents, the powers, and what the stages keep.
struct SplitScratch<F> {
    base: [F; BLOCK],
    one_minus: [F; BLOCK],
    p: [F; BLOCK],
    power: [F; BLOCK],
    keep: [[F; BLOCK]; STAGE_KEEP],
}

/// Per-element parameters read from scratch.
struct BlockParams<'s, F> {
    slots: &'s [[F; BLOCK]; MAX_VARYING_SLOTS],
    j: usize,
}

impl<F: Real> ParamSource<F> for BlockParams<'_, F> {
    #[inline(always)]
    fn scalar(&self, slot: usize) -> F {
        self.slots[slot][self.j]
    }
}

/// Reads row `row` of `rows` (`comps` components, 1 or 3) into `dst`.
pub fn read_row<F: Real>(
    rows: &Rows<'_, F>,
    comps: usize,
    batch: &[usize],
    row: usize,
    dst: &mut [F; 3],
) {
    match rows {
        Rows::Constant(r) => *dst = *r,
        Rows::Contiguous(s) => dst[..comps].copy_from_slice(&s[comps * row..comps * (row + 1)]),
        Rows::Strided(s) => s.for_each(batch, row, 1, comps, |_, c, v| dst[c] = v),
    }
}

/// Copies rows `row0 .. row0 + len` of a direction source into scratch, deinterleaved.
#[inline(always)]
fn load_vector<F: Real>(
    rows: &Rows<'_, F>,
    batch: &[usize],
    row0: usize,
    len: usize,
    dst: &mut [[F; BLOCK]; 3],
) {
    match rows {
        Rows::Constant(r) => {
            for (c, lane) in dst.iter_mut().enumerate() {
                lane[..len].fill(r[c]);
            }
        }
        Rows::Contiguous(s) => {
            let s = &s[3 * row0..3 * (row0 + len)];
            // A full block as an array: a fixed trip count that the vectorized loop
            // covers with no scalar remainder.
            match <&[F; 3 * BLOCK]>::try_from(s) {
                Ok(full) => deinterleave(full, dst),
                Err(_) => deinterleave(s, dst),
            }
        }
        Rows::Strided(s) => s.for_each(batch, row0, len, 3, |j, c, v| dst[c][j] = v),
    }
}

/// Copies rows of 3 into three lanes.
#[inline(always)]
fn deinterleave<F: Real>(rows: &[F], dst: &mut [[F; BLOCK]; 3]) {
    let [x, y, z] = dst;
    for (j, row) in rows.chunks_exact(3).enumerate() {
        x[j] = row[0];
        y[j] = row[1];
        z[j] = row[2];
    }
}

/// Copies three lanes into rows of 3.
#[inline(always)]
fn interleave<F: Real>(src: &[[F; BLOCK]; 3], rows: &mut [F]) {
    let [x, y, z] = src;
    for (j, row) in rows.chunks_exact_mut(3).enumerate() {
        row[0] = x[j];
        row[1] = y[j];
        row[2] = z[j];
    }
}

/// Hints the CPU to fetch rows `row0 .. row0 + len` of a contiguous source into cache.
#[inline(always)]
fn prefetch_rows<F: Real>(rows: &Rows<'_, F>, row0: usize, len: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Rows::Contiguous(s) = rows {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let Some(block) = s.get(3 * row0..3 * (row0 + len)) else {
            return;
        };
        let step = 64 / std::mem::size_of::<F>();
        for k in (0..block.len()).step_by(step) {
            // SAFETY: `_mm_prefetch` needs SSE, which every x86-64 CPU has (this code is
            // compiled for x86-64 only); a prefetch is a hint that never faults, and the
            // address is inside the slice anyway.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(block[k..].as_ptr().cast()) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (rows, row0, len);
}

/// Copies rows of a varying parameter (1 or 3 components) into its scratch slots.
#[inline(always)]
fn load_param<F: Real>(
    rows: &Rows<'_, F>,
    comps: usize,
    batch: &[usize],
    row0: usize,
    len: usize,
    dst: &mut [[F; BLOCK]],
) {
    match rows {
        Rows::Constant(r) => {
            for (c, lane) in dst.iter_mut().enumerate().take(comps) {
                lane[..len].fill(r[c]);
            }
        }
        Rows::Contiguous(s) => {
            let s = &s[comps * row0..comps * (row0 + len)];
            for (j, row) in s.chunks_exact(comps).enumerate() {
                for c in 0..comps {
                    dst[c][j] = row[c];
                }
            }
        }
        Rows::Strided(s) => s.for_each(batch, row0, len, comps, |j, c, v| dst[c][j] = v),
    }
}

/// Runs `body` for the lanes `j` of a block: `0..SHORT_BLOCK` when `lanes` is
/// [`SHORT_BLOCK`], else `0..BLOCK`. Either loop has a fixed trip count, which the
/// compiler vectorizes whole (a loop to a run-time bound leaves its last lanes to scalar
/// code, as slow for a few rows as a whole block in vectors).
macro_rules! for_lanes {
    ($lanes:expr, |$j:ident| $body:block) => {
        if $lanes == SHORT_BLOCK {
            for $j in 0..SHORT_BLOCK $body
        } else {
            for $j in 0..BLOCK $body
        }
    };
}

/// Normalizes one scratch vector in place (unless `normalized`), and clears `ok` for
/// rows that are NaN, infinite or zero-length.
///
/// A block whose rows all have squared lengths in [`Real::ORDINARY_LENGTH_SQUARED`] is
/// normalized without [`Real::normalize`]'s range selects, which scale no such row:
/// [`Real::normalize_unscaled`], the same bits. Any other block (a NaN,
/// infinite, zero, tiny or huge row among its first `len`) takes [`Real::normalize`]
/// whole, so bad rows are flagged and extreme ones normalized; both in `P`'s tier
/// ([`unit_ordinary`], [`unit`]: the AVX-512 fast tier's `f64` goes without square roots
/// or divisions, and its two agree in the same way).
#[inline(always)]
fn normalize_block<F: Real, P: PowUnit>(
    v: &mut [[F; BLOCK]; 3],
    ok: &mut [bool; BLOCK],
    normalized: bool,
    lanes: usize,
    len: usize,
) {
    let [x, y, z] = v;
    if normalized {
        for_lanes!(lanes, |j| {
            ok[j] &= F::usable(F::V3::new(x[j], y[j], z[j]));
        });
        return;
    }
    let mut all_ordinary = true;
    for_lanes!(lanes, |j| {
        // Lanes past `len` hold stale scratch.
        all_ordinary &= ordinary_length::<F>(F::V3::new(x[j], y[j], z[j])) | (j >= len);
    });
    if all_ordinary {
        // Every row is usable: `ok` stays as it is.
        for_lanes!(lanes, |j| {
            let u = unit_ordinary::<F, P>(F::V3::new(x[j], y[j], z[j]));
            x[j] = u.x();
            y[j] = u.y();
            z[j] = u.z();
        });
        return;
    }
    for_lanes!(lanes, |j| {
        let (u, usable) = unit::<F>(F::V3::new(x[j], y[j], z[j]), P::DIVISION_FREE);
        x[j] = u.x();
        y[j] = u.y();
        z[j] = u.z();
        ok[j] &= usable;
    });
}

/// The unit vector of a row whose squared length is in [`Real::ORDINARY_LENGTH_SQUARED`],
/// in `P`'s tier: [`Real::normalize_unscaled`], or [`Real::normalize_unscaled_fast`] where
/// `P::DIVISION_FREE` (the same bits as [`unit`]'s there).
#[inline(always)]
fn unit_ordinary<F: Real, P: PowUnit>(v: F::V3) -> F::V3 {
    if P::DIVISION_FREE {
        F::normalize_unscaled_fast(v)
    } else {
        F::normalize_unscaled(v)
    }
}

/// A row's unit vector and whether it is usable: [`Real::normalize`], or
/// [`Real::normalize_fast`] where `division_free` (the loops of [`FastPowDivisionFree`];
/// for a plan, [`normalizes_division_free`]).
#[inline(always)]
pub fn unit<F: Real>(v: F::V3, division_free: bool) -> (F::V3, bool) {
    if division_free {
        F::normalize_fast(v)
    } else {
        F::normalize(v)
    }
}

/// Whether a row's squared length is in [`Real::ORDINARY_LENGTH_SQUARED`], where
/// [`Real::normalize_unscaled`] gives [`Real::normalize`]'s bits (NaN is not).
#[inline(always)]
fn ordinary_length<F: Real>(raw: F::V3) -> bool {
    let (lo, hi) = F::ORDINARY_LENGTH_SQUARED;
    let l2 = raw.length_squared();
    (l2 >= lo) & (l2 <= hi)
}

/// Copies a full block of rows of a contiguous direction source into scratch and
/// normalizes them in the same pass, as [`normalize_block`] does a block whose rows are all
/// ordinary (the same bits): one pass over the rows instead of three (copy, range test,
/// normalization). Returns whether every row was ordinary; if not, the scratch holds
/// garbage and the caller loads and normalizes the block the general way. In `P`'s tier,
/// as [`normalize_block`].
#[inline(always)]
fn load_normalize_ordinary<F: Real, P: PowUnit>(
    rows: &[F; 3 * BLOCK],
    dst: &mut [[F; BLOCK]; 3],
) -> bool {
    let [x, y, z] = dst;
    let mut all_ordinary = true;
    for (j, row) in rows.chunks_exact(3).enumerate() {
        let raw = F::V3::new(row[0], row[1], row[2]);
        all_ordinary &= ordinary_length::<F>(raw);
        let u = unit_ordinary::<F, P>(raw);
        x[j] = u.x();
        y[j] = u.y();
        z[j] = u.z();
    }
    all_ordinary
}

/// Evaluates rows `first_row .. first_row + out.len()/3` of the plan with kernel `K`,
/// its powers computed by `P` ([`TablePow`]; [`FastPow`] for the fast tier, which also
/// leaves out the microfacet lobes' length errors, [`Kernel::LENGTH_CORRECTIONS`]).
/// Returns whether any row had an unusable input vector.
#[inline(always)]
fn run_range<F: Real, K: Kernel, P: PowUnit, const MODE: u8>(
    plan: &Plan<'_, F>,
    first_row: usize,
    out: &mut [F],
) -> bool {
    // MODE_UNIFORM: one parameter set; MODE_NORMAL_Z: that, and n = +z for every row
    // (dot products with n fold to a component); MODE_VARYING: parameters per row.
    let vary = MODE == MODE_VARYING;
    let rows = out.len() / 3;
    // Constant directions are normalized (and checked) once, not per row.
    let constant: [Option<([F; 3], bool)>; 4] = std::array::from_fn(|i| {
        plan.vectors[i].constant().map(|r| {
            let v = F::V3::new(r[0], r[1], r[2]);
            let (u, ok) = if plan.options.normalized {
                (v, F::usable(v))
            } else {
                unit::<F>(v, P::DIVISION_FREE)
            };
            ([u.x(), u.y(), u.z()], ok)
        })
    });
    let uses_tangent = plan.kind.spec().tangent != crate::models::TangentUse::None;
    let check_tangent = plan.checks_tangent_direction();
    let uniform = K::prepare::<F, [F]>(&plan.uniform);
    let mut scratch = Scratch {
        vectors: [[[F::ZERO; BLOCK]; 3]; 4],
        ok: [true; BLOCK],
        params: [[F::ZERO; BLOCK]; MAX_VARYING_SLOTS],
        rgb: [[F::ZERO; BLOCK]; 3],
    };
    let mut split = SplitScratch {
        base: [F::ZERO; BLOCK],
        one_minus: [F::ONE; BLOCK],
        p: [F::ZERO; BLOCK],
        power: [F::ZERO; BLOCK],
        keep: [[F::ZERO; BLOCK]; STAGE_KEEP],
    };
    for (i, c) in constant.iter().enumerate() {
        if let Some((row, _)) = c {
            for (lane, value) in scratch.vectors[i].iter_mut().zip(row) {
                lane.fill(*value);
            }
        }
    }
    let constant_ok = constant.iter().all(|c| c.is_none_or(|(_, ok)| ok));
    if vary {
        for (slot, lane) in scratch
            .params
            .iter_mut()
            .enumerate()
            .take(plan.uniform.len())
        {
            lane.fill(plan.uniform[slot]);
        }
    }
    // Rows whose cosine the kernel needs beyond `f64`'s range (see `wide_cosine_rows`);
    // a compile-time constant (a run-time one here lost the loop's vectorization).
    let wide = K::WIDE_COSINES && F::EXTENDED_COSINES;
    let stream = plan.rows * 3 * std::mem::size_of::<F>() >= STREAM_BYTES;
    // A divided kernel's per-parameter-set work, once for a task of uniform parameters
    // long enough to repay it (the divided pass below).
    let divisor_cache = if K::DIVIDED && !vary && rows >= DIVISOR_CACHE_ROWS {
        K::divisor_cache(&uniform)
    } else {
        Vec::new()
    };
    let mut divisor_stage = [[0.0f64; 2]; BLOCK];
    let mut staged = Staged([F::ZERO; 3 * BLOCK]);
    let mut any_bad = false;
    // Whether the next block's powers are tried the short way (see the split passes).
    let mut try_ordinary = true;
    for block_start in (0..rows).step_by(BLOCK) {
        let len = BLOCK.min(rows - block_start);
        let row0 = first_row + block_start;
        // The lanes computed (see `for_lanes`).
        let lanes = if len <= SHORT_BLOCK {
            SHORT_BLOCK
        } else {
            BLOCK
        };
        scratch.ok = [constant_ok; BLOCK];
        // Ask for the next block's input now: it arrives while this block computes.
        let next = row0 + len;
        for (i, source) in plan.vectors.iter().enumerate() {
            if i != 3 || uses_tangent {
                prefetch_rows(
                    source,
                    next,
                    BLOCK.min(first_row + rows - next.min(first_row + rows)),
                );
            }
        }
        for (i, source) in plan.vectors.iter().enumerate() {
            if (i == 3 && !uses_tangent) || constant[i].is_some() {
                continue;
            }
            if len == BLOCK
                && !plan.options.normalized
                && let Rows::Contiguous(s) = source
                && let Some(full) = s
                    .get(3 * row0..3 * (row0 + BLOCK))
                    .and_then(|s| <&[F; 3 * BLOCK]>::try_from(s).ok())
                && load_normalize_ordinary::<F, P>(full, &mut scratch.vectors[i])
            {
                continue;
            }
            load_vector(source, &plan.batch, row0, len, &mut scratch.vectors[i]);
            normalize_block::<F, P>(
                &mut scratch.vectors[i],
                &mut scratch.ok,
                plan.options.normalized,
                lanes,
                len,
            );
        }
        if check_tangent {
            let [_, _, n, t] = &scratch.vectors;
            for_lanes!(lanes, |j| {
                let nj = F::V3::new(n[0][j], n[1][j], n[2][j]);
                let tj = F::V3::new(t[0][j], t[1][j], t[2][j]);
                scratch.ok[j] &= !tangent_parallel::<F>(nj, tj);
            });
        }
        if vary {
            for p in &plan.varying {
                let lanes = &mut scratch.params[p.slot..p.slot + p.comps];
                load_param(&p.rows, p.comps, &plan.batch, row0, len, lanes);
            }
        }
        let [wi, wo, n, t] = &scratch.vectors;
        let [r, g, b] = &mut scratch.rgb;
        let mut any_tiny = false;
        let mut bad_in_block = false;
        // The model over the block's lanes (lanes past `len` compute on stale, harmless
        // scratch and are never written out), into structure-of-arrays RGB.
        if K::SPLIT_POWER {
            // Three passes: the powers' bases, the powers, the rest. Measured on
            // Torrance-Sparrow (benches/eval_ab.py, 1 thread, 16k rows), 1.2x the single
            // loop in float32 and float64, the same bits: the power's long chain no
            // longer shares a loop body (and its registers) with the geometry.
            for_lanes!(lanes, |j| {
                let d = block_directions::<F, MODE>(wi, wo, n, t, j);
                let stage = if vary {
                    let params = BlockParams {
                        slots: &scratch.params,
                        j,
                    };
                    K::power_stage(&K::prepare(&params), &d)
                } else {
                    K::power_stage(&uniform, &d)
                };
                split.base[j] = stage.base.cos;
                split.one_minus[j] = stage.base.one_minus;
                split.p[j] = stage.p;
                for (lane, value) in split.keep.iter_mut().zip(stage.keep) {
                    lane[j] = value;
                }
            });
            // The block's powers the short way for ordinary lanes
            // ([`PowUnit::pow_unit_ordinary`]), and again in full if a lane was not: the
            // same bits either way. A block with such a lane (a power below the normal
            // range: a high exponent) is likely followed by more, so after one the task's
            // later blocks go the full way at once.
            let mut done = false;
            if try_ordinary {
                let mut all_ordinary = true;
                for_lanes!(lanes, |j| {
                    let (power, ordinary) =
                        P::pow_unit_ordinary(split.base[j], split.one_minus[j], split.p[j]);
                    split.power[j] = power;
                    // Lanes past `len` hold stale scratch.
                    all_ordinary &= ordinary | (j >= len);
                });
                done = all_ordinary;
                try_ordinary = all_ordinary;
            }
            if !done {
                for_lanes!(lanes, |j| {
                    split.power[j] = P::pow_unit(split.base[j], split.one_minus[j], split.p[j]);
                });
            }
            for_lanes!(lanes, |j| {
                let stage = PowerStage {
                    base: Cosine {
                        cos: split.base[j],
                        one_minus: split.one_minus[j],
                    },
                    p: split.p[j],
                    keep: std::array::from_fn(|k| split.keep[k][j]),
                };
                let rgb = if vary {
                    let params = BlockParams {
                        slots: &scratch.params,
                        j,
                    };
                    K::finish_power(&K::prepare(&params), &stage, split.power[j])
                } else {
                    K::finish_power(&uniform, &stage, split.power[j])
                };
                let ok = scratch.ok[j];
                bad_in_block |= !ok & (j < len);
                if wide {
                    let d = block_directions::<F, MODE>(wi, wo, n, t, j);
                    any_tiny |= ok & (needs_wide::<F>(d.n, d.wi) | needs_wide::<F>(d.n, d.wo));
                }
                r[j] = if ok { rgb[0] } else { F::NAN };
                g[j] = if ok { rgb[1] } else { F::NAN };
                b[j] = if ok { rgb[2] } else { F::NAN };
            });
        } else {
            // A divided kernel with uniform parameters: the value before the division here
            // (a loop that vectorizes), the division in a pass of its own below. (The split
            // branch above has no such pass: a kernel may not declare both.)
            const { assert!(!(K::DIVIDED && K::SPLIT_POWER)) };
            let divided = K::DIVIDED && !vary;
            for_lanes!(lanes, |j| {
                let d = block_directions::<F, MODE>(wi, wo, n, t, j);
                let rgb = if vary {
                    let params = BlockParams {
                        slots: &scratch.params,
                        j,
                    };
                    K::eval_with::<F, P>(&K::prepare(&params), &d)
                } else if divided {
                    K::eval_undivided::<F, P>(&uniform, &d)
                } else {
                    K::eval_with::<F, P>(&uniform, &d)
                };
                let ok = scratch.ok[j];
                bad_in_block |= !ok & (j < len);
                if wide {
                    // The kernel's own dot products (the same expressions, merged by the
                    // compiler); a stale lane past `len` at most costs a look at the block.
                    any_tiny |= ok & (needs_wide::<F>(d.n, d.wi) | needs_wide::<F>(d.n, d.wo));
                }
                r[j] = if ok { rgb[0] } else { F::NAN };
                g[j] = if ok { rgb[1] } else { F::NAN };
                b[j] = if ok { rgb[2] } else { F::NAN };
            });
            if divided {
                // Rows past `len` are never written out, and a bad row is NaN already.
                if divisor_cache.is_empty() {
                    for j in (0..len).filter(|&j| scratch.ok[j]) {
                        let d = block_directions::<F, MODE>(wi, wo, n, t, j);
                        let e = K::divisor(&uniform, &d);
                        (r[j], g[j], b[j]) = (r[j] / e, g[j] / e, b[j] / e);
                    }
                } else {
                    // The divisor's costly part over every lane (a loop that vectorizes),
                    // then the rest per row.
                    for_lanes!(lanes, |j| {
                        let d = block_directions::<F, MODE>(wi, wo, n, t, j);
                        divisor_stage[j] = K::divisor_stage(&uniform, &d);
                    });
                    for j in (0..len).filter(|&j| scratch.ok[j]) {
                        let d = block_directions::<F, MODE>(wi, wo, n, t, j);
                        let e = K::divisor_in(&uniform, &divisor_cache, &d, divisor_stage[j]);
                        (r[j], g[j], b[j]) = (r[j] / e, g[j] / e, b[j] / e);
                    }
                }
            }
        }
        if wide && any_tiny {
            wide_cosine_rows::<F, K>(plan, &mut scratch, row0, len, &uniform, vary);
        }
        let out_block = &mut out[3 * block_start..3 * (block_start + len)];
        match <&mut [F; 3 * BLOCK]>::try_from(&mut *out_block) {
            Ok(full) if stream => {
                interleave(&scratch.rgb, &mut staged.0);
                stream_copy(&staged, full);
            }
            Ok(full) => interleave(&scratch.rgb, full),
            Err(_) => interleave(&scratch.rgb, out_block),
        }
        any_bad |= bad_in_block;
    }
    // Non-temporal stores are weakly ordered: make them visible before the task ends.
    #[cfg(target_arch = "x86_64")]
    if stream {
        // SAFETY: `_mm_sfence` needs SSE, which every x86-64 CPU has (this line is
        // compiled for x86-64 only).
        unsafe { std::arch::x86_64::_mm_sfence() };
    }
    any_bad
}

/// The directions of lane `j` of a block's scratch (`n = +z` in `MODE_NORMAL_Z`).
#[inline(always)]
fn block_directions<F: Real, const MODE: u8>(
    wi: &[[F; BLOCK]; 3],
    wo: &[[F; BLOCK]; 3],
    n: &[[F; BLOCK]; 3],
    t: &[[F; BLOCK]; 3],
    j: usize,
) -> Directions<F> {
    Directions::<F> {
        wi: F::V3::new(wi[0][j], wi[1][j], wi[2][j]),
        wo: F::V3::new(wo[0][j], wo[1][j], wo[2][j]),
        n: if MODE == MODE_NORMAL_Z {
            F::V3::new(F::ZERO, F::ZERO, F::ONE)
        } else {
            F::V3::new(n[0][j], n[1][j], n[2][j])
        },
        t: F::V3::new(t[0][j], t[1][j], t[2][j]),
    }
}

/// A block of interleaved RGB rows, aligned for [`stream_copy`].
#[repr(align(64))]
struct Staged<F>([F; 3 * BLOCK]);

/// Copies a block to `dst` with non-temporal stores (bypassing the caches) where `dst`
/// is 16-byte aligned, else with ordinary ones. The caller fences before returning.
#[inline(always)]
fn stream_copy<F: Real>(src: &Staged<F>, dst: &mut [F; 3 * BLOCK]) {
    let src = &src.0;
    #[cfg(target_arch = "x86_64")]
    if (dst.as_ptr() as usize) % 16 == 0 {
        use std::arch::x86_64::{__m128i, _mm_load_si128, _mm_stream_si128};
        let n = std::mem::size_of_val(src) / 16;
        let s = src.as_ptr().cast::<__m128i>();
        let d = dst.as_mut_ptr().cast::<__m128i>();
        for k in 0..n {
            // SAFETY: the two intrinsics need SSE2, part of every x86-64 CPU (x86-64
            // only code); both blocks are n·16 bytes long, so `k < n` stays inside them;
            // `dst` was checked to be 16-byte aligned and `Staged` is 64-byte aligned.
            unsafe { _mm_stream_si128(d.add(k), _mm_load_si128(s.add(k))) };
        }
        return;
    }
    dst.copy_from_slice(src);
}

/// Whether the cosine `n·w` of a normalized `w` may have lost what a wide cosine keeps:
/// it is nonzero and below 2^-1022, or it is 0 while a component of `w` is (normalization
/// rounded it there: `(0, 1e300, 1e-300)` under a tilted normal). A direction exactly on
/// the horizon, with components in the normal range, does not qualify.
#[inline(always)]
fn needs_wide<F: Real>(n: F::V3, w: F::V3) -> bool {
    let min_normal = F::from_f64(f64::MIN_POSITIVE);
    let tiny = |c: F| (c != F::ZERO) & (c.abs() < min_normal);
    let c = n.dot(w);
    tiny(c) | ((c == F::ZERO) & (tiny(w.x()) | tiny(w.y()) | tiny(w.z())))
}

/// Re-evaluates with [`Kernel::eval_wide`] the rows of a block whose cosine `n·wi` or
/// `n·wo` [`needs_wide`] (`f64`): their cosines are taken from the raw
/// input vectors with [`wide_cosine`], which keeps what normalization rounds away. Rare,
/// so the rows are read again one by one and the block's loop carries none of it. With
/// `normalized=True` the given vectors are the raw ones; `n` is used normalized.
#[cold]
#[inline(never)]
fn wide_cosine_rows<F: Real, K: Kernel>(
    plan: &Plan<'_, F>,
    scratch: &mut Scratch<F>,
    row0: usize,
    len: usize,
    uniform: &K::Prepared<F>,
    vary: bool,
) {
    for j in 0..len {
        let [wi, wo, n, t] = &scratch.vectors;
        let v = |a: &[[F; BLOCK]; 3]| F::V3::new(a[0][j], a[1][j], a[2][j]);
        let d = Directions::<F> {
            wi: v(wi),
            wo: v(wo),
            n: v(n),
            t: v(t),
        };
        if !scratch.ok[j] || !(needs_wide::<F>(d.n, d.wi) || needs_wide::<F>(d.n, d.wo)) {
            continue;
        }
        let raw = |i: usize| {
            let mut r = [F::ZERO; 3];
            read_row(&plan.vectors[i], 3, &plan.batch, row0 + j, &mut r);
            r.map(F::to_f64)
        };
        let unit_n = [d.n.x(), d.n.y(), d.n.z()].map(F::to_f64);
        let (wi, wo) = (raw(0), raw(1));
        let w = WideRow {
            mu_i: wide_cosine(unit_n, wi),
            mu_o: wide_cosine(unit_n, wo),
            wi,
            wo,
        };
        let rgb = if vary {
            let params = BlockParams {
                slots: &scratch.params,
                j,
            };
            K::eval_wide(&K::prepare(&params), &d, &w)
        } else {
            K::eval_wide(uniform, &d, &w)
        };
        for (c, channel) in scratch.rgb.iter_mut().enumerate() {
            channel[j] = rgb[c];
        }
    }
}

const MODE_UNIFORM: u8 = 0;
const MODE_NORMAL_Z: u8 = 1;
const MODE_VARYING: u8 = 2;

/// The signature of a compiled range loop.
type RangeFn<F> = for<'p, 'a, 'o> unsafe fn(&'p Plan<'a, F>, usize, &'o mut [F]) -> bool;

fn range_baseline<F: Real, K: Kernel, P: PowUnit, const MODE: u8>(
    plan: &Plan<'_, F>,
    first_row: usize,
    out: &mut [F],
) -> bool {
    run_range::<F, K, P, MODE>(plan, first_row, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn range_avx2<F: Real, K: Kernel, P: PowUnit, const MODE: u8>(
    plan: &Plan<'_, F>,
    first_row: usize,
    out: &mut [F],
) -> bool {
    run_range::<F, K, P, MODE>(plan, first_row, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn range_avx512<F: Real, K: Kernel, P: PowUnit, const MODE: u8>(
    plan: &Plan<'_, F>,
    first_row: usize,
    out: &mut [F],
) -> bool {
    run_range::<F, K, P, MODE>(plan, first_row, out)
}

/// Whether the fast tier has loops of its own for kernel `K` in width `F`: where it has
/// powers ([`Kernel::POWERS`]) or length-error corrections in this width
/// ([`Kernel::LENGTH_CORRECTIONS`]; `f32` carries none). The others run the accurate loops.
fn has_fast_loop<F: Real, K: Kernel>() -> bool {
    K::POWERS || (K::LENGTH_CORRECTIONS && F::EXACT_LENGTHS)
}

/// Whether `plan`'s loop normalizes its directions the fast tier's division-free way
/// ([`FastPowDivisionFree`]: the fast tier's AVX-512 loops), so that a row found bad by
/// the loop (a tangent parallel to the normal) is looked for again the same way.
pub fn normalizes_division_free<F: Real>(plan: &Plan<'_, F>) -> bool {
    struct FastLoop<F>(PhantomData<F>);
    impl<F: Real> KernelVisitor for FastLoop<F> {
        type Output = bool;
        fn visit<K: Kernel>(self) -> bool {
            has_fast_loop::<F, K>()
        }
    }
    plan.options.precision == Precision::Fast
        && matches!(isa(), Isa::Avx512(_))
        && plan.kind.visit(FastLoop::<F>(PhantomData))
}

/// Picks the compiled loop for a model, an instruction set, a mode and a tier.
struct SelectLoop<F> {
    isa: Isa,
    mode: u8,
    /// The fast tier: its loops where the model has powers ([`Kernel::POWERS`]) or
    /// length-error corrections ([`Kernel::LENGTH_CORRECTIONS`]).
    fast: bool,
    _float: PhantomData<F>,
}

impl<F: Real> KernelVisitor for SelectLoop<F> {
    type Output = RangeFn<F>;

    fn visit<K: Kernel>(self) -> RangeFn<F> {
        macro_rules! pick_mode {
            ($f:ident, $p:ty) => {
                match self.mode {
                    MODE_NORMAL_Z => $f::<F, K, $p, MODE_NORMAL_Z> as RangeFn<F>,
                    MODE_VARYING => $f::<F, K, $p, MODE_VARYING> as RangeFn<F>,
                    _ => $f::<F, K, $p, MODE_UNIFORM> as RangeFn<F>,
                }
            };
        }
        // `K::POWERS`, `K::LENGTH_CORRECTIONS` and `F::EXACT_LENGTHS` are constants: models
        // the fast tier would not change (no powers, and no length corrections in this
        // width: `f32` carries none) compile no fast-tier loops, nor does the baseline
        // instruction set (x86-64 CPUs without AVX2 are rare, and the accurate loops meet
        // the fast tier's bound).
        macro_rules! pick {
            ($f:ident, $fast:ty) => {
                if has_fast_loop::<F, K>() && self.fast {
                    pick_mode!($f, $fast)
                } else {
                    pick_mode!($f, TablePow)
                }
            };
        }
        #[cfg(target_arch = "x86_64")]
        match self.isa {
            Isa::Avx512(_) => return pick!(range_avx512, FastPowDivisionFree),
            Isa::Avx2(_) => return pick!(range_avx2, FastPow),
            Isa::Baseline => {}
        }
        pick_mode!(range_baseline, TablePow)
    }
}

/// Rows between two calls of the `poll` of [`run_polled`] (a multiple of the block size,
/// so that blocks, and with them every row's instructions, are those of one undivided run).
pub const POLL_ROWS: usize = 128 * TASK_BLOCKS * BLOCK;

/// Runs the plan into `out` (C order, `rows × 3`), in parallel for large batches.
/// Returns whether any row had an unusable input vector.
pub fn run<F: Real>(plan: &Plan<'_, F>, out: &mut [F]) -> bool {
    run_polled(plan, out, &mut || true).unwrap_or(true)
}

/// [`run`], calling `poll` after every [`POLL_ROWS`] rows (never for a smaller batch) and
/// stopping early, with `None`, when it returns false; the rows not reached are left as
/// they were. The rows are computed as by [`run`], bit for bit.
pub fn run_polled<F: Real>(
    plan: &Plan<'_, F>,
    out: &mut [F],
    poll: &mut dyn FnMut() -> bool,
) -> Option<bool> {
    if plan.rows == 0 {
        return Some(false);
    }
    let isa = isa();
    let z = [F::ZERO, F::ZERO, F::ONE];
    let mode = if !plan.varying.is_empty() {
        MODE_VARYING
    } else if plan.vectors[2].constant() == Some(z) {
        MODE_NORMAL_Z
    } else {
        MODE_UNIFORM
    };
    let range = plan.kind.visit(SelectLoop::<F> {
        isa,
        mode,
        fast: plan.options.precision == Precision::Fast,
        _float: PhantomData,
    });
    let task_rows = TASK_BLOCKS * BLOCK;
    let threads = parallel::num_threads();
    let serial = plan.rows <= 2 * task_rows || threads == 1;
    let mut any_bad = false;
    for (k, part) in out.chunks_mut(3 * POLL_ROWS).enumerate() {
        if k > 0 && !poll() {
            return None;
        }
        let first = k * POLL_ROWS;
        // Tasks of at most `task_rows` rows, as many as a multiple of the thread count, so
        // that the threads share the rows evenly (10,000 rows in tasks of 2048 made 5 tasks:
        // 3 for one thread, 2 for the other); each a whole number of blocks, so that every
        // row is computed in the same block, by the same instructions, whatever the split.
        let tasks = (part.len() / 3)
            .div_ceil(task_rows)
            .next_multiple_of(threads);
        let per = (part.len() / 3).div_ceil(tasks).next_multiple_of(BLOCK);
        any_bad |= if serial {
            // SAFETY: `range` is the loop `SelectLoop` picked for `isa`: `range_avx512` or
            // `range_avx2` only for an `Isa::Avx512` / `Isa::Avx2` token, which `simd`
            // makes after finding their `target_feature`s on this CPU; else the baseline.
            unsafe { range(plan, first, part) }
        } else {
            parallel::install(|| {
                part.par_chunks_mut(3 * per)
                    .enumerate()
                    .map(|(i, chunk)| {
                        // SAFETY: the same `range` as in the serial branch above: compiled
                        // for the instruction set whose `Isa` token `isa()` returned.
                        unsafe { range(plan, first + i * per, chunk) }
                    })
                    .reduce(|| false, |a, b| a || b)
            })
        };
    }
    Some(any_bad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::ModelKind;

    #[test]
    fn varying_parameters_fit_the_scratch() {
        for kind in ModelKind::ALL {
            for p in kind.spec().params {
                if p.kind.may_vary() {
                    assert!(
                        p.slot + p.kind.slots() <= MAX_VARYING_SLOTS,
                        "{}",
                        kind.name()
                    );
                }
            }
        }
    }
}
