//! Sums of lobe weights over the points of a cell's streams ([`LobeSums`]), and the means
//! and standard errors formed from them: per point, over replicates
//! ([`mean_and_stderr`]), and stratified for skewed lobes.

use super::MAX_LOBES;
use super::cell::PointBlock;
use super::integrand::Lobe;

/// Bins of the unit square for the stratified variance of a skewed lobe, and the
/// partitions of the square into them ([`LobeSums::skewed_stderr`]).
const BINS: usize = 16;
const SHAPES: usize = 5;
/// The bins of one lobe: `[points, Σ(w − shift), Σ(w − shift)²]` per bin, per partition.
type Bins = [[[f64; 3]; BINS]; SHAPES];
/// Replicates of this many points or more have means that are not skewed, and their
/// spread alone is the error bar (`scripts/stderr_calibration.py`: the stratified bound
/// is then several times the error).
const SKEWED_FROM: u64 = 64;
/// Pseudo-points at 0 in each bin of a skewed lobe that reaches into its region of zeros
/// ([`Lobe::zeros_from`], [`LobeSums::skewed_stderr`]). Torrance-Sparrow's tail near the
/// normal (mu = 0.999, eta = 1.05, p = 20) has its zeros, where `wo` leaves the surface,
/// in the last 1% of the sampler's first number: in the last of 16 rows, whose one point
/// per replicate carries the cell's error, the zeros and the weights' fall to them are
/// 16% of the row (its weights' skewness is −1.25). A cell of 256 samples sees none of
/// them with probability about 6%, and then reads high by about 3 of its error bars:
/// 1.6–2.6% of cells were beyond 3 standard errors over three seeds, mean z +0.14 to
/// +0.18, where 0.9% is honest (`scripts/stderr_calibration.py --grid torrance_sparrow`,
/// 1000 cells). With one pseudo-point: 0.0–0.2%, mean z +0.05 to +0.08, median |z|
/// 0.57–0.58 (0.63–0.65 before; 0.69 is honest).
const ZERO_PSEUDO_POINTS: f64 = 1.0;
/// Partial sums per reduction: a fixed pattern, so the bits do not depend on the ISA.
const LANES: usize = 8;
/// Pseudo-points at each bound, 0 and 1, in the per-point variance of a bounded lobe
/// ([`LobeSums::rgb`]). Weights that are 1 but for a rare region of 0 (hit `λ` times on
/// average in a cell of `n` points) make a cell that saw none of that region read `λ/n`
/// high; with `a` pseudo-points its error bar is `√a/n`, so such cells are beyond 3
/// standard errors wherever `λ > 3√a`, which happens with probability `e^−λ`. One
/// pseudo-point (Agresti and Coull's count for a 2σ interval of a proportion) put 1.8–2.4%
/// of cells beyond 3 standard errors where `λ` ≈ 3 (GGX at mu = 0.7, alpha = 0.1, 256
/// random points; `scripts/stderr_calibration.py`); three bound that share by `e^−5.2`.
pub(super) const PSEUDO_POINTS: f64 = 3.0;

/// Sums of lobe weights over points: `Σ (w_k − c_k)` and `Σ (w_k − c_k)(w_l − c_l)`,
/// accumulated in `LANES` fixed partial sums (deterministic, and free to run in SIMD
/// lanes). The shift `c_k` (the first block's mean) keeps the variance free of the
/// cancellation of `Σw² − n·mean²` when the weights are nearly constant. Lobes with a
/// control variate are shifted for Sobol points too (no cross sums there): their weights
/// are nearly constant by design, and a plain running sum of 2^16 such weights per
/// replicate is off by about 1e-13 of the mean (each addition rounds the same way),
/// the same for every replicate, far above the replicates' spread.
#[derive(Clone)]
pub(super) struct LobeSums {
    n: u64,
    /// Points with a nonzero weight, per lobe.
    pub(super) hits: [u64; MAX_LOBES],
    shift: [f64; MAX_LOBES],
    sum: [[f64; LANES]; MAX_LOBES],
    cross: [[[f64; LANES]; MAX_LOBES]; MAX_LOBES],
    /// Per skewed lobe ([`Lobe::skewed`]), its index and its weights in bins of the unit
    /// square of `(u0, u1)`: for each of the [`SHAPES`] partitions into [`BINS`] equal
    /// rectangles, per bin, the points and the sums of the shifted weights and of their
    /// squares. Kept while the replicates have fewer than [`SKEWED_FROM`] points.
    pub(super) bins: Vec<(usize, Bins)>,
}

impl LobeSums {
    /// Empty sums; `skewed` lists the lobes kept in bins.
    pub(super) fn new(skewed: &[usize]) -> Self {
        LobeSums {
            n: 0,
            hits: [0; MAX_LOBES],
            shift: [0.0; MAX_LOBES],
            sum: [[0.0; LANES]; MAX_LOBES],
            cross: [[[0.0; LANES]; MAX_LOBES]; MAX_LOBES],
            bins: skewed
                .iter()
                .map(|&k| (k, [[[0.0; 3]; BINS]; SHAPES]))
                .collect(),
        }
    }

    /// Adds the weights of the first `len` points of `block` (its `u0`, `u1` for the
    /// bins) for `lobes` lobes.
    #[inline(always)]
    pub(super) fn add_block(
        &mut self,
        block: &PointBlock,
        lobes: usize,
        len: usize,
        cross: bool,
        shifted: [bool; MAX_LOBES],
    ) {
        let (w, u0, u1) = (&block.w, &block.u0[..len], &block.u1[..len]);
        if self.n == 0 {
            for k in (0..lobes).filter(|&k| shifted[k]) {
                self.shift[k] = w[k][..len].iter().sum::<f64>() / len as f64;
            }
        }
        if self.n < SKEWED_FROM {
            for (k, shapes) in self.bins.iter_mut() {
                let (k, ck) = (*k, self.shift[*k]);
                for (shape, bins) in shapes.iter_mut().enumerate() {
                    // 2^(4 − shape) rows in u0 by 2^shape columns in u1.
                    let rows = BINS >> shape;
                    let columns = 1usize << shape;
                    for ((&x, &u), &v) in w[k][..len].iter().zip(u0).zip(u1) {
                        let row = ((u * rows as f64) as usize).min(rows - 1);
                        let column = ((v * columns as f64) as usize).min(columns - 1);
                        let bin = &mut bins[row * columns + column];
                        bin[0] += 1.0;
                        bin[1] += x - ck;
                        bin[2] += (x - ck) * (x - ck);
                    }
                }
            }
        }
        self.n += len as u64;
        for k in 0..lobes {
            self.hits[k] += w[k][..len].iter().filter(|&&x| x != 0.0).count() as u64;
            let ck = self.shift[k];
            // Point j goes to lane j % LANES, written as whole chunks so that the loop
            // vectorizes (the same additions in the same order as one point at a time).
            let lanes = &mut self.sum[k];
            let chunks = w[k][..len].chunks_exact(LANES);
            let rest = chunks.remainder();
            for chunk in chunks {
                for (acc, x) in lanes.iter_mut().zip(chunk) {
                    *acc += x - ck;
                }
            }
            for (acc, x) in lanes.iter_mut().zip(rest) {
                *acc += x - ck;
            }
            if cross {
                for l in 0..=k {
                    let cl = self.shift[l];
                    for j in 0..len {
                        self.cross[k][l][j % LANES] += (w[k][j] - ck) * (w[l][j] - cl);
                    }
                }
            }
        }
    }

    fn total(lanes: &[f64; LANES]) -> f64 {
        lanes.iter().sum()
    }

    /// The standard error of the skewed lobes' sum ([`Lobe::skewed`]) as a sample
    /// stratified over the points of all `replicates`: per lobe, the least over the
    /// [`SHAPES`] partitions of the unit square into [`BINS`] equal rectangles (16 × 1,
    /// 8 × 2, …, 1 × 16 in `(u0, u1)`) of `sqrt(Σ_b s_b²/n_b)/BINS`, with `s_b²` the
    /// variance of the weights in bin `b` pooled over the replicates; the lobes' errors
    /// added (a bound whatever their correlation). A replicate of `2^k ≥ BINS` Sobol
    /// points puts the same number in every rectangle of every such partition (and is more
    /// finely stratified still), so each bounds its error; it pools every point of the
    /// cell where the replicates' spread rests on one point per replicate near the
    /// skewed end. A bin that reaches into the lobe's region of zeros
    /// ([`Lobe::zeros_from`]) counts [`ZERO_PSEUDO_POINTS`] at 0: a rare region there
    /// that the cell's points missed would leave the bin's variance too small. Zero where
    /// no lobe is skewed, from [`SKEWED_FROM`] points per replicate on, and for a lobe
    /// with a bin of fewer than two points.
    pub(super) fn skewed_stderr<P>(replicates: &[LobeSums], lobes: &[Lobe<P>]) -> [f64; 3] {
        let mut se = [0.0; 3];
        if replicates[0].n >= SKEWED_FROM {
            return se;
        }
        for (i, &(k, _)) in replicates[0].bins.iter().enumerate() {
            // Pool the bins about one shift (the first replicate's).
            let c0 = replicates[0].shift[k];
            let mut bins = [[[0.0f64; 3]; BINS]; SHAPES];
            for s in replicates {
                let d = s.shift[k] - c0;
                for (pooled, own) in bins.iter_mut().zip(&s.bins[i].1) {
                    for (p, b) in pooled.iter_mut().zip(own) {
                        p[0] += b[0];
                        p[1] += b[1] + b[0] * d;
                        p[2] += b[2] + 2.0 * d * b[1] + b[0] * d * d;
                    }
                }
            }
            // A bin that reaches into the lobe's region of zeros counts pseudo-points at 0
            // (about the bin's unshifted mean `s1/n + c0`), as a bounded lobe's variance
            // does at its bounds ([`LobeSums::rgb`]).
            let zeros_from = lobes[k].zeros_from;
            let var = |[n, s1, s2]: [f64; 3], zeros: bool| {
                let squares = (s2 - s1 * s1 / n).max(0.0);
                if zeros {
                    let a = ZERO_PSEUDO_POINTS;
                    let m = s1 / n + c0;
                    (squares + a * n / (n + a) * m * m) / (n - 1.0 + a)
                } else {
                    squares / (n - 1.0)
                }
            };
            let Some(var_mean) = bins
                .iter()
                .enumerate()
                .filter(|(_, shape)| shape.iter().all(|b| b[0] >= 2.0))
                .map(|(shape, bins)| {
                    let (rows, columns) = (BINS >> shape, 1usize << shape);
                    bins.iter()
                        .enumerate()
                        .map(|(b, &bin)| {
                            // The bin's rows in u0 end at (row + 1)/rows.
                            let top = (b / columns + 1) as f64 / rows as f64;
                            let zeros = zeros_from.is_some_and(|z| top > z);
                            var(bin, zeros) / bin[0]
                        })
                        .sum::<f64>()
                })
                .min_by(f64::total_cmp)
            else {
                continue;
            };
            let sd = var_mean.sqrt() / BINS as f64;
            for (e, c) in se.iter_mut().zip(lobes[k].colour) {
                *e += c.abs() * sd;
            }
        }
        se
    }

    /// The RGB mean `Σ colour_k · mean(w_k)` and, if cross sums were kept, the standard
    /// error of that mean from the per-point variance.
    pub(super) fn rgb<P>(&self, lobes: &[Lobe<P>]) -> ([f64; 3], [f64; 3]) {
        let n = self.n as f64;
        // The variance is formed with each channel's colours divided by their largest
        // magnitude (then scaled back), so colours near the float range (kd = 1e300)
        // give a finite error bar wherever the value is finite.
        let scale: [f64; 3] = std::array::from_fn(|c| {
            let m = lobes.iter().map(|l| l.colour[c].abs()).fold(0.0, f64::max);
            if m > 0.0 && m.is_finite() { m } else { 1.0 }
        });
        // Shifted mean and second moment about the shift; the variance's mean in
        // scaled colours.
        let mut mean = [0.0; 3];
        let mut scaled_mean = [0.0; 3];
        let mut second = [0.0; 3];
        let mut shift = [0.0; 3];
        // Each lobe's mean weight about its shift.
        let shifted: [f64; MAX_LOBES] = std::array::from_fn(|k| Self::total(&self.sum[k]) / n);
        for (k, lk) in lobes.iter().enumerate() {
            let sk = shifted[k];
            for c in 0..3 {
                mean[c] += lk.colour[c] * sk;
                scaled_mean[c] += lk.colour[c] / scale[c] * sk;
                shift[c] += lk.colour[c] * self.shift[k];
            }
            for (l, ll) in lobes.iter().enumerate().take(k + 1) {
                let x = Self::total(&self.cross[k][l]) / n;
                let twice = if l == k { 1.0 } else { 2.0 };
                for c in 0..3 {
                    second[c] += twice * (lk.colour[c] / scale[c]) * (ll.colour[c] / scale[c]) * x;
                }
            }
        }
        // Bounded lobes add pseudo-points at each bound, 0 and 1, to the squared
        // deviations (as Agresti and Coull's interval does for a proportion): weights
        // that are nearly all 1 with a rare region of 0 (the rim of a smooth lobe's
        // visible normals, hit once in 1/alpha² points) would otherwise give a cell that
        // saw no such point a variance near 0 ([`PSEUDO_POINTS`]).
        let pseudo: [f64; 3] = std::array::from_fn(|c| {
            let mut extra = 0.0;
            for (k, lk) in lobes.iter().enumerate() {
                if lk.bounded {
                    let m = self.shift[k] + shifted[k];
                    let w = lk.colour[c] / scale[c];
                    extra += PSEUDO_POINTS * w * w * (m * m + (1.0 - m) * (1.0 - m));
                }
            }
            extra
        });
        let se = std::array::from_fn(|c| {
            let m = scaled_mean[c];
            let squares = (second[c] - m * m).max(0.0) * n;
            let var = if pseudo[c] > 0.0 {
                (squares + pseudo[c]) / (n - 1.0 + 2.0 * PSEUDO_POINTS)
            } else {
                squares / (n - 1.0)
            };
            (var / n).sqrt() * scale[c]
        });
        (std::array::from_fn(|c| shift[c] + mean[c]), se)
    }
}

/// The mean of RGB values and its standard error, computed in two passes.
pub(super) fn mean_and_stderr(values: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let n = values.len() as f64;
    let mean: [f64; 3] = std::array::from_fn(|c| values.iter().map(|v| v[c]).sum::<f64>() / n);
    let se = std::array::from_fn(|c| {
        // Deviations divided by the largest one, so that squares cannot overflow.
        let big = values
            .iter()
            .map(|v| (v[c] - mean[c]).abs())
            .fold(0.0, f64::max);
        if !(big > 0.0 && big.is_finite()) {
            return if big == 0.0 { 0.0 } else { big };
        }
        let ss: f64 = values
            .iter()
            .map(|v| ((v[c] - mean[c]) / big).powi(2))
            .sum();
        (ss / (n - 1.0) / n).sqrt() * big
    });
    (mean, se)
}
