//! The albedo of a transmitting model (the rough dielectrics) over the whole sphere:
//! `A(mu) = ∫_{S²} f(wi, wo)·|n·wo| dωo`, as its reflected part (`wo` above), its
//! transmitted part (`wo` below) or both ([`Component`]).
//!
//! Each point `u` draws one half vector `h` from the distribution's visible normals seen
//! from `wi` ([`DielectricSampler::warp`]), and both of its directions are scored (a split
//! estimator, with no random choice between them): the reflection `wo_r` of `wi` about
//! `h`, with weight `f(wi, wo_r)·|n·wo_r| / (D_wi(h)/(4|wo_r·h|))` where `wo_r` is above,
//! and the refraction `wo_t` through `h`, with weight
//! `f(wi, wo_t)·|n·wo_t| / (D_wi(h)·eta²|wo_t·h|/((wi·h) + eta(wo_t·h))²)` where `wo_t`
//! is below. These are `ks·F·G2/G1(wi)` and `kt·(1 − F)·G2/G1(wi)`, each at most its
//! colour, so the estimator is bounded. For GGX and Beckmann they are computed in that
//! closed form from the visible normal alone ([`GgxGlass`], [`BeckmannGlass`]), over
//! blocks of points with a loop compiled per instruction set; [`weights`], from the
//! model's own kernel at grey unit colours, is the general form (for a warp without a
//! closed form) that the tests hold them to. The colours multiply the two parts.
//!
//! The error bar is the one of the hemisphere integrator: the per-point spread for random
//! points, the spread of the replicates' means for Sobol points (pooled with the previous
//! round's, [`pooled_with_previous`]), in rounds that double until `tol` is met. Both
//! count [`PSEUDO_POINTS`] at each bound of the weights ([`Bounds`]): near a smooth
//! interface the weights are `G2/G1` ≈ 1 but for rare drops in the distribution's tail
//! (a mirror direction below the horizon, a grazing `wo` where `G2/G1` falls), and a
//! cell that drew none of them reports the spread of the smooth part alone, far below
//! what it missed. At `eta = 1` the albedo is exact: the reflection is 0 and the
//! transmission `kt` (the straight-through delta).

use std::sync::atomic::Ordering;

use glam::DVec3;

use super::POINTS;
use super::cell::pooled_with_previous;
use super::loops::{self, Loops};
use super::options::{AlbedoOptions, CellResult, Component, Progress, Rounds};
use super::sums::{PSEUDO_POINTS, mean_and_stderr};
use crate::math::geometry::ggx_mu_lambda;
use crate::models::beckmann::{lambda_of_c, mu_lambda};
use crate::models::{Directions, Kernel};
use crate::sampling::beckmann_visible::{BeckmannVisibleNormals, SlopeTable};
use crate::sampling::dielectric::DielectricSampler;
use crate::sampling::streams::{Sequence, Stream};
use crate::sampling::{GgxVisibleNormals, Warp, reflect};
use crate::simd::Isa;

/// The grey weights `(reflection, transmission)` of one point `u` at `wi` (`n = +z`).
fn weights<K: Kernel>(
    sampler: &DielectricSampler,
    prepared: &K::Prepared<f64>,
    wi: DVec3,
    u: [f64; 2],
) -> (f64, f64) {
    let s = sampler.warp.sample(wi, u);
    let pdf_h = s.pdf;
    if !(pdf_h > 0.0) {
        return (0.0, 0.0);
    }
    let h = s.dir.normalize();
    let c = wi.dot(h);
    if !(c > 0.0) {
        return (0.0, 0.0);
    }
    let eval = |wo: DVec3| {
        K::eval::<f64>(
            prepared,
            &Directions {
                wi,
                wo,
                n: DVec3::Z,
                t: DVec3::X,
            },
        )[0]
    };
    let wo_r = reflect(wi, h).normalize();
    let r = if wo_r.z > 0.0 {
        let pdf = pdf_h / (4.0 * wo_r.dot(h).abs());
        eval(wo_r) * wo_r.z / pdf
    } else {
        0.0
    };
    let eta = sampler.eta;
    let sin2_t = (1.0 - c * c).max(0.0) / (eta * eta);
    let t = if sin2_t < 1.0 {
        let cos_t = (1.0 - sin2_t).sqrt();
        let wo_t = (-wi / eta + h * (c / eta - cos_t)).normalize();
        if wo_t.z < 0.0 {
            let co = wo_t.dot(h);
            let denom = c + eta * co;
            let pdf = pdf_h * eta * eta * co.abs() / (denom * denom);
            eval(wo_t) * -wo_t.z / pdf
        } else {
            0.0
        }
    } else {
        0.0
    };
    let ok = |x: f64| if x.is_finite() { x } else { 0.0 };
    (ok(r), ok(t))
}

/// The bounds of a point's value per channel, `[lo, hi]`: the colours weigh `ks·r + kt·t`
/// with `r = F·G2/G1 ≤ F` and `t = (1 − F)·G2/G1 ≤ 1 − F` (0 where the direction is not
/// on its side), so the value lies between `min(0, ks, kt)` and `max(0, ks, kt)` (of the
/// parts integrated).
struct Bounds {
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Bounds {
    /// The bounds for the colours `ks`, `kt`, each weight scaled by at most `scale` (the
    /// smooth radius's Jacobian, and the model's factor over its interface).
    fn new(ks: [f64; 3], kt: [f64; 3], scale: f64) -> Self {
        Bounds {
            lo: std::array::from_fn(|c| scale * ks[c].min(kt[c]).min(0.0)),
            hi: std::array::from_fn(|c| scale * ks[c].max(kt[c]).max(0.0)),
        }
    }

    /// The squared deviations from `mean` of [`PSEUDO_POINTS`] points at each bound of
    /// channel `c`, as [`super::sums::LobeSums::rgb`] adds them for a bounded lobe:
    /// weights near one bound but for a rare region near the other make a cell that saw
    /// none of that region read high by its share, with a spread near 0; with `a`
    /// pseudo-points its error bar is at least `√a·(hi − lo)/n` or so, which covers a
    /// region hit `λ > 3√a` times on average only with probability `e^−λ`.
    fn pseudo(&self, c: usize, mean: f64) -> f64 {
        let (lo, hi) = (self.lo[c], self.hi[c]);
        PSEUDO_POINTS * ((mean - lo).powi(2) + (hi - mean).powi(2))
    }

    /// The standard error of the mean of `n` points with the squared deviations
    /// `squares` about their mean `mean`, counting the pseudo-points (where the bounds
    /// differ).
    fn stderr(&self, c: usize, n: f64, mean: f64, squares: f64) -> f64 {
        let pseudo = self.pseudo(c, mean);
        let var = if pseudo > 0.0 {
            (squares.max(0.0) + pseudo) / (n - 1.0 + 2.0 * PSEUDO_POINTS)
        } else {
            squares.max(0.0) / (n - 1.0)
        };
        (var / n).sqrt()
    }
}

/// GGX's two weights in closed form, from the visible normal alone (no kernel, no pdf):
/// with `L = μ·Λ(μ)` ([`ggx_mu_lambda`]) and `G2/G1(wi) = (mu_i + L_i)·mu_o/(mu_o·(mu_i +
/// L_i) + mu_i·L_o)` (the height-correlated `G2` of both lobes), the reflection's weight is
/// `F·G2/G1` and the refraction's `(1 − F)·G2/G1`, with the exact dielectric `F` of
/// `c = wi·h` (1 past the critical angle). The same estimator as [`weights`] up to
/// roundings, at a fraction of its cost.
///
/// For scrambled Sobol points the disk's radius is drawn as `r² = 1 − s²`, `s = 1 − u0`,
/// with the Jacobian `2s` in the weights (the hemisphere integrator's substitution,
/// `integrate/ggx.rs`): the rim of the projected disk, where the normal's height has a
/// square-root singularity in `u0` and the weights change fastest, becomes smooth in `s`.
/// Random points keep Heitz's `r² = u0` (the Jacobian's own spread would cost more than the
/// smoothness gains them).
pub(super) struct GgxGlass {
    normals: GgxVisibleNormals,
    wi: DVec3,
    alpha2: f64,
    /// `mu_i + L_i`.
    mu_l_i: f64,
    eta: f64,
    smooth: bool,
    /// Draw azimuths on one half of the disk (the integrand is even about the plane of
    /// incidence).
    fold: bool,
}

impl GgxGlass {
    fn new(alpha: f64, eta: f64, wi: DVec3, smooth: bool, fold: bool) -> Self {
        let alpha2 = alpha * alpha;
        let l_i = ggx_mu_lambda(wi.z, wi.x * wi.x + wi.y * wi.y, alpha2);
        GgxGlass {
            normals: GgxVisibleNormals::new(alpha, wi),
            wi,
            alpha2,
            mu_l_i: wi.z + l_i,
            eta,
            smooth,
            fold,
        }
    }

    /// `G2/G1(wi)` for an outgoing cosine of size `mu_o > 0`.
    #[inline(always)]
    fn g(&self, mu_o: f64) -> f64 {
        let l_o = ggx_mu_lambda(mu_o, (1.0 - mu_o) * (1.0 + mu_o), self.alpha2);
        self.mu_l_i * mu_o / (mu_o * self.mu_l_i + self.wi.z * l_o)
    }
}

impl ClosedFormGlass for GgxGlass {
    fn smooth(&self) -> bool {
        self.smooth
    }

    fn fold(&self) -> bool {
        self.fold
    }

    #[inline(always)]
    fn fill_case<const FOLD: bool>(
        &self,
        u0: &[f64],
        u1: &[f64],
        refl: &mut [f64],
        trans: &mut [f64],
    ) {
        let smooth = self.smooth;
        let points = u0.iter().zip(u1).zip(refl.iter_mut().zip(trans.iter_mut()));
        for ((&u, &a), (refl, trans)) in points {
            let s = 1.0 - u;
            let (r, jacobian) = if smooth {
                ((u * (1.0 + s)).sqrt(), 2.0 * s)
            } else {
                (u.sqrt(), 1.0)
            };
            let h = self.normals.half_vector(r, a, !FOLD);
            (*refl, *trans) = interface(self.wi, self.eta, h, jacobian, |mu_o| self.g(mu_o));
        }
    }
}

/// A rough interface whose two weights are known in closed form from the visible normal
/// alone ([`GgxGlass`], [`BeckmannGlass`]): `F·G2/G1(wi)` for the reflection and
/// `(1 − F)·G2/G1(wi)` for the refraction ([`interface`]).
pub(super) trait ClosedFormGlass {
    /// Whether the first number is substituted for QMC (a Jacobian of at most 2 in the
    /// weights).
    fn smooth(&self) -> bool;
    /// Whether azimuths are drawn on one half (the integrand is even about the plane of
    /// incidence).
    fn fold(&self) -> bool;
    /// The weights of a block of points for one fold: `refl[j]` and `trans[j]` those of
    /// `(u0[j], u1[j])`.
    fn fill_case<const FOLD: bool>(
        &self,
        u0: &[f64],
        u1: &[f64],
        refl: &mut [f64],
        trans: &mut [f64],
    );

    /// The weights of a block of points. One loop per fold, its body straight-line code
    /// where the warp allows (every branch a select), so that it runs across the vector
    /// lanes of the instruction set it is compiled for ([`Loops::glass`]); the same
    /// arithmetic in every lane and instruction set, so the same bits.
    #[inline(always)]
    fn fill(&self, u0: &[f64], u1: &[f64], refl: &mut [f64], trans: &mut [f64]) {
        if self.fold() {
            self.fill_case::<true>(u0, u1, refl, trans);
        } else {
            self.fill_case::<false>(u0, u1, refl, trans);
        }
    }

    /// The grey weights `(reflection, transmission)` of the point `u` (the block loop's
    /// for one point: what the tests hold the other estimators to).
    #[cfg(test)]
    fn weights(&self, u: [f64; 2]) -> (f64, f64) {
        let (mut r, mut t) = ([0.0], [0.0]);
        self.fill(&[u[0]], &[u[1]], &mut r, &mut t);
        (r[0], t[0])
    }
}

/// The two weights of the unit half vector `h` at `wi` (`n = +z`) for the relative index
/// `eta`, times `jacobian`: `F·G2/G1` where the reflection is above the surface and
/// `(1 − F)·G2/G1` where the refraction is below, `g` giving `G2/G1(wi)` for an outgoing
/// cosine of size `mu_o` in (0, 1]; F is the exact dielectric reflectance at `c = wi·h`
/// (1 past the critical angle). Both are 0 unless `c > 0` and `h.z > 0`. Every branch is
/// a select: the values not chosen may be NaN.
#[inline(always)]
fn interface(wi: DVec3, eta: f64, h: DVec3, jacobian: f64, g: impl Fn(f64) -> f64) -> (f64, f64) {
    let mu_i = wi.z;
    let c = wi.dot(h);
    let facing = c > 0.0 && h.z > 0.0;
    // The refraction: sin²θt = (1 − c²)/eta²; past the critical angle F = 1 (the square
    // root's argument is then negative: its NaN is not selected).
    let sin2_t = (1.0 - c) * (1.0 + c) / (eta * eta);
    let refracts = sin2_t < 1.0;
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (c - eta * cos_t) / (c + eta * cos_t);
    let rp = (eta * c - cos_t) / (eta * c + cos_t);
    let f = if refracts {
        0.5 * (rs * rs + rp * rp)
    } else {
        1.0
    };
    // wo_t = −wi/eta + h·(c/eta − cos_t), a unit vector; its n-component.
    let t_mu = if refracts {
        -mu_i / eta + h.z * (c / eta - cos_t)
    } else {
        0.0
    };
    let r_mu = 2.0 * c * h.z - mu_i;
    let reflected = if r_mu > 0.0 {
        f * g(r_mu.min(1.0))
    } else {
        0.0
    };
    let transmitted = if t_mu < 0.0 && f < 1.0 {
        (1.0 - f) * g((-t_mu).min(1.0))
    } else {
        0.0
    };
    (
        if facing { jacobian * reflected } else { 0.0 },
        if facing { jacobian * transmitted } else { 0.0 },
    )
}

/// Beckmann's two weights in closed form, as [`GgxGlass`]'s: the half vector from the
/// visible-normal warp of the conductor's integrator (`integrate/beckmann.rs`: the slope
/// along `wi`'s azimuth solved from a per-cell table and polished, the one across it
/// from the normal quantile), and `G2/G1(wi) = (1 + Λ_i)/(1 + Λ_i + Λ_o)` with
/// Beckmann's exact `Λ`: no kernel, no pdf. The slope's CDF value is the point's first
/// number for every sequence: the conductor's substitution `u = 1 − (1 − v)²` for Sobol
/// points (a smoother horizon, at the price of a Jacobian `2(1 − v)` in the weights) made
/// the whole sphere's error larger, not smaller (measured with
/// `scripts/stderr_calibration.py --grid dielectric`: 25% more RMS error at alpha = 0.5
/// from the denser side, and error bars too narrow for 3% of cells at 256 samples).
pub(super) struct BeckmannGlass {
    normals: BeckmannVisibleNormals,
    table: SlopeTable,
    wi: DVec3,
    alpha: f64,
    /// `1 + Λ_i`.
    one_lambda_i: f64,
    eta: f64,
    fold: bool,
}

impl BeckmannGlass {
    /// The interface at `wi = (sqrt(1 − mu²), 0, mu)`, `mu > 0`.
    fn new(alpha: f64, eta: f64, wi: DVec3, fold: bool) -> Self {
        let mu_i = wi.z;
        let l_i = mu_lambda(mu_i, wi.x * wi.x + wi.y * wi.y, alpha);
        let normals = BeckmannVisibleNormals::new(alpha, wi);
        BeckmannGlass {
            table: normals.table(),
            normals,
            wi,
            alpha,
            one_lambda_i: (mu_i + l_i) / mu_i,
            eta,
            fold,
        }
    }

    /// `G2/G1(wi)` for an outgoing cosine of size `mu_o` in (0, 1].
    #[inline(always)]
    fn g(&self, mu_o: f64) -> f64 {
        let c_o = mu_o / (self.alpha * ((1.0 - mu_o) * (1.0 + mu_o)).sqrt());
        // c_o = ∞ (wo along the normal): Λ_o = 0.
        let lambda_o = if c_o < f64::INFINITY {
            lambda_of_c(c_o)
        } else {
            0.0
        };
        self.one_lambda_i / (self.one_lambda_i + lambda_o)
    }
}

impl ClosedFormGlass for BeckmannGlass {
    fn smooth(&self) -> bool {
        false
    }

    fn fold(&self) -> bool {
        self.fold
    }

    #[inline(always)]
    fn fill_case<const FOLD: bool>(
        &self,
        u0: &[f64],
        u1: &[f64],
        refl: &mut [f64],
        trans: &mut [f64],
    ) {
        let points = u0.iter().zip(u1).zip(refl.iter_mut().zip(trans.iter_mut()));
        for ((&u, &a), (refl, trans)) in points {
            // The CDF value is u0: v = 1 − sqrt(1 − u0) = u0/(1 + sqrt(1 − u0)) in the
            // table's variable.
            let v = u / (1.0 + (1.0 - u).sqrt());
            let x = self.normals.slope_along_v_tabulated(&self.table, v);
            let y = BeckmannVisibleNormals::slope_across(a, !FOLD);
            let h = self.normals.scaled_half_vector(x, y).normalize();
            (*refl, *trans) = interface(self.wi, self.eta, h, 1.0, |mu_o| self.g(mu_o));
        }
    }
}

/// The closed-form interface of a cell, when its warp has one.
enum Closed {
    Ggx(GgxGlass),
    /// Boxed: its slope table makes it far larger than GGX's.
    Beckmann(Box<BeckmannGlass>),
}

impl Closed {
    fn smooth(&self) -> bool {
        match self {
            Closed::Ggx(g) => g.smooth(),
            Closed::Beckmann(b) => b.smooth(),
        }
    }

    /// The block's weights with the loop compiled for `isa`.
    fn weights(&self, isa: Isa, u0: &[f64], u1: &[f64], refl: &mut [f64], trans: &mut [f64]) {
        match self {
            Closed::Ggx(g) => glass_weights(isa, g, u0, u1, refl, trans),
            Closed::Beckmann(b) => glass_weights(isa, b.as_ref(), u0, u1, refl, trans),
        }
    }
}

/// Point scratch of one block: the points and their two weights.
struct GlassBlock {
    u0: [f64; POINTS],
    u1: [f64; POINTS],
    refl: [f64; POINTS],
    trans: [f64; POINTS],
}

impl GlassBlock {
    fn new() -> Self {
        GlassBlock {
            u0: [0.0; POINTS],
            u1: [0.0; POINTS],
            refl: [0.0; POINTS],
            trans: [0.0; POINTS],
        }
    }
}

/// [`ClosedFormGlass::fill`] with the loop compiled for `isa` (whose token proves the CPU runs
/// it).
fn glass_weights<G: ClosedFormGlass>(
    isa: Isa,
    glass: &G,
    u0: &[f64],
    u1: &[f64],
    refl: &mut [f64],
    trans: &mut [f64],
) {
    #[cfg(target_arch = "x86_64")]
    {
        match isa {
            Isa::Avx512(_) => {
                // SAFETY: an `Isa::Avx512` token is made only in `simd`, after `detected`
                // found every feature `loops::Avx512` enables on this CPU.
                return unsafe { loops::Avx512::glass(glass, u0, u1, refl, trans) };
            }
            Isa::Avx2(_) => {
                // SAFETY: likewise, `Isa::Avx2` proves the features of `loops::Avx2`.
                return unsafe { loops::Avx2::glass(glass, u0, u1, refl, trans) };
            }
            Isa::Baseline => {}
        }
    }
    // SAFETY: the baseline loops enable no feature beyond the target's own.
    unsafe { loops::Baseline::glass(glass, u0, u1, refl, trans) }
}

/// Integrates one cell of a transmitting model at incidence `mu` (the model's sampler
/// `sampler`, its raw parameter `slots`, whose colours `ks` and `kt` weigh the two parts).
pub(super) fn integrate_cell<K: Kernel>(
    isa: Isa,
    sampler: DielectricSampler,
    mu: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    let spec = K::SPEC;
    let colour = |name: &str| -> [f64; 3] {
        spec.param(name).map_or([0.0; 3], |p| {
            [slots[p.slot], slots[p.slot + 1], slots[p.slot + 2]]
        })
    };
    let (reflection, transmission) = match options.component {
        Component::Total => (true, true),
        Component::Reflection => (true, false),
        Component::Transmission => (false, true),
    };
    let ks = if reflection { colour("ks") } else { [0.0; 3] };
    let kt = if transmission { colour("kt") } else { [0.0; 3] };
    if sampler.eta == 1.0 || !(mu > 0.0) || ks.iter().chain(&kt).all(|&c| c == 0.0) {
        // No interface: the delta straight through (exact); grazing incidence: 0.
        let value = if sampler.eta == 1.0 && mu > 0.0 {
            kt
        } else {
            [0.0; 3]
        };
        return CellResult {
            value,
            stderr: [0.0; 3],
            samples: 0,
        };
    }
    // Grey unit colours: the kernel's value is one part, the colours weigh them.
    let mut grey = slots.to_vec();
    for name in ["ks", "kt"] {
        if let Some(p) = spec.param(name) {
            grey[p.slot..p.slot + 3].fill(1.0);
        }
    }
    let prepared = K::prepare::<f64, [f64]>(&grey);
    let mu = mu.min(1.0);
    let wi = DVec3::new(((1.0 - mu) * (1.0 + mu)).sqrt(), 0.0, mu);
    let random = options.sequence == Sequence::Random;
    let (eta, fold) = (sampler.eta, options.fold_azimuth);
    let closed = match sampler.warp {
        Warp::GgxVisible { alpha } => {
            Some(Closed::Ggx(GgxGlass::new(alpha, eta, wi, !random, fold)))
        }
        Warp::BeckmannVisible { alpha } => Some(Closed::Beckmann(Box::new(BeckmannGlass::new(
            alpha, eta, wi, fold,
        )))),
        _ => None,
    };
    // The model's factor over the interface's closed-form weights (the kernel's own
    // weights include it); every weight is at most the colour times it.
    let scale = K::interface_scale(slots, mu);
    // The smooth radius's Jacobian 2s (at most 2) widens the range of a point's value.
    let smooth = closed.as_ref().is_some_and(Closed::smooth);
    let bounds = Bounds::new(ks, kt, scale * if smooth { 2.0 } else { 1.0 });
    // A point's value: the colours weigh its two parts.
    let value = |r: f64, t: f64| -> [f64; 3] {
        std::array::from_fn(|c| {
            let a = if ks[c] == 0.0 { 0.0 } else { ks[c] * r };
            let b = if kt[c] == 0.0 { 0.0 } else { kt[c] * t };
            a + b
        })
    };
    let mut block = GlassBlock::new();
    let rounds = Rounds::new(options);
    let streams_count = rounds.streams;
    let mut per_stream = rounds.first(options.samples);
    let mut streams: Vec<Stream> = (0..streams_count)
        .map(|r| Stream::new(options.sequence, options.seed, cell, r))
        .collect();
    // Per stream: the sums of the values, and of the values and their squares about a
    // shift (the stream's first value: no cancellation in the squares' sum when the
    // values are nearly constant).
    let mut sums = vec![([0.0; 3], [0.0; 3], [0.0; 3]); streams.len()];
    let mut shifts = vec![None::<[f64; 3]>; streams.len()];
    let mut done = 0u64;
    // The previous round's replicate spread (Sobol points), pooled into the next round's.
    let mut previous: Option<[f64; 3]> = None;
    loop {
        let count = per_stream - done;
        for ((stream, (sum, shifted, squares)), shift) in streams
            .iter_mut()
            .zip(sums.iter_mut())
            .zip(shifts.iter_mut())
        {
            let mut left = count;
            while left > 0 {
                let len = left.min(POINTS as u64) as usize;
                let (u0, u1) = (&mut block.u0[..len], &mut block.u1[..len]);
                let (refl, trans) = (&mut block.refl[..len], &mut block.trans[..len]);
                stream.fill(u0, u1);
                match &closed {
                    Some(glass) => {
                        glass.weights(isa, u0, u1, refl, trans);
                        refl.iter_mut().for_each(|r| *r *= scale);
                        trans.iter_mut().for_each(|t| *t *= scale);
                    }
                    None => {
                        for (j, (r, t)) in refl.iter_mut().zip(trans.iter_mut()).enumerate() {
                            (*r, *t) = weights::<K>(&sampler, &prepared, wi, [u0[j], u1[j]]);
                        }
                    }
                }
                for (&r, &t) in refl.iter().zip(trans.iter()) {
                    let x = value(r, t);
                    let shift = *shift.get_or_insert(x);
                    for c in 0..3 {
                        let d = x[c] - shift[c];
                        sum[c] += x[c];
                        shifted[c] += d;
                        squares[c] += d * d;
                    }
                }
                left -= len as u64;
            }
        }
        progress
            .samples_done
            .fetch_add(count * streams_count, Ordering::Relaxed);
        done = per_stream;
        let total = per_stream * streams_count;
        let n = per_stream as f64;
        let (mean, se): ([f64; 3], [f64; 3]) = if random {
            let (sum, shifted, squares) = sums[0];
            let mean: [f64; 3] = std::array::from_fn(|c| sum[c] / n);
            let se: [f64; 3] = std::array::from_fn(|c| {
                let deviations = squares[c] - shifted[c] * shifted[c] / n;
                bounds.stderr(c, n, mean[c], deviations)
            });
            (mean, se)
        } else {
            let means: Vec<[f64; 3]> = sums
                .iter()
                .map(|(s, _, _)| std::array::from_fn(|c| s[c] / n))
                .collect();
            let (mean, se) = mean_and_stderr(&means);
            let pooled = pooled_with_previous(se, previous);
            previous = Some(se);
            // The replicates' means share what none of their points saw: the
            // pseudo-points bound it from below. Their own error bar over all the cell's
            // `N` points, `√(P/((N − 1 + 2a)·N))` with `P` their squared deviations, is
            // counted at their share `P/(S + P)` of the per-point variance (`S` the
            // points' squared deviations): whole where the points saw nothing but one
            // value, and little where they span the bounds (a rough interface, whose
            // replicates see its whole range: their spread is then the error bar, far
            // below the plain Monte Carlo one that the pseudo-points belong to).
            let all = total as f64;
            let floor: [f64; 3] = std::array::from_fn(|c| {
                let squares: f64 = sums
                    .iter()
                    .zip(&shifts)
                    .map(|((_, shifted, squares), shift)| {
                        let shift = shift.map_or(0.0, |s| s[c]);
                        let own = shifted[c] / n;
                        let between = shift + own - mean[c];
                        (squares[c] - shifted[c] * own).max(0.0) + n * between * between
                    })
                    .sum();
                let pseudo = bounds.pseudo(c, mean[c]);
                if pseudo > 0.0 {
                    let share = pseudo / (squares + pseudo);
                    share * (pseudo / (all - 1.0 + 2.0 * PSEUDO_POINTS) / all).sqrt()
                } else {
                    0.0
                }
            });
            (mean, std::array::from_fn(|c| pooled[c].max(floor[c])))
        };
        let finished = rounds.finished(total, &se, &mean);
        if finished || progress.cancel.load(Ordering::Relaxed) {
            let stderr = std::array::from_fn(|c| se[c].max(mean[c].abs() * f64::EPSILON));
            return CellResult {
                value: mean,
                stderr,
                samples: total,
            };
        }
        per_stream = rounds.next(per_stream);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::beckmann_dielectric::BeckmannDielectric;
    use crate::models::ggx_dielectric::GgxDielectric;
    use crate::simd::isa;

    fn slots(eta: f64, alpha: f64) -> Vec<f64> {
        use crate::models::dielectric::{ALPHA, ETA, KS, KT};
        let mut s = vec![0.0; 8];
        KS.write(&mut s, [1.0; 3]);
        KT.write(&mut s, [1.0; 3]);
        ETA.write(&mut s, eta);
        ALPHA.write(&mut s, alpha);
        s
    }

    fn albedo(eta: f64, alpha: f64, mu: f64, component: Component) -> CellResult {
        let s = slots(eta, alpha);
        let sampler = GgxDielectric::transmission_sampler(&s).unwrap();
        let options = AlbedoOptions {
            samples: 1 << 14,
            component,
            ..AlbedoOptions::default()
        };
        integrate_cell::<GgxDielectric>(isa(), sampler, mu, &s, 7, &options, &Progress::default())
    }

    /// Near-smooth interfaces: R → F(mu), T → 1 − F(mu).
    #[test]
    fn small_roughness_gives_the_smooth_interface() {
        let mu: f64 = 0.7;
        let eta: f64 = 1.5;
        let g = (eta * eta - 1.0 + mu * mu).sqrt();
        let a = (g - mu) / (g + mu);
        let b = (mu * (g + mu) - 1.0) / (mu * (g - mu) + 1.0);
        let fresnel = 0.5 * a * a * (1.0 + b * b);
        let r = albedo(eta, 1e-3, mu, Component::Reflection);
        let t = albedo(eta, 1e-3, mu, Component::Transmission);
        let total = albedo(eta, 1e-3, mu, Component::Total);
        assert!((r.value[0] - fresnel).abs() < 1e-3, "{r:?} vs {fresnel}");
        assert!((t.value[0] - (1.0 - fresnel)).abs() < 1e-3, "{t:?}");
        assert!((total.value[0] - 1.0).abs() < 1e-3, "{total:?}");
        assert!((total.value[0] - r.value[0] - t.value[0]).abs() < 1e-12);
    }

    /// The closed form gives the generic `f·|n·wo|/pdf` of the kernel for the same point
    /// (with the warp's own first number and the full disk), on both sides of 1 and past
    /// the critical angle: to 1e-9, as near the critical angle `cos θt = sqrt(1 −
    /// sin²θt)` turns a rounding of `sin²θt` into a larger one of `F` (the kernel forms `F`
    /// differently).
    fn closed_form_weights_are_the_kernel<K: Kernel, G: ClosedFormGlass>(
        make: impl Fn(f64, f64, DVec3) -> G,
    ) {
        let mut checked = 0;
        let cases: [(f64, f64, f64); 6] = [
            (1.5, 0.3, 0.7),
            (1.0 / 1.5, 0.3, 0.7),
            (1.05, 0.02, 0.95),
            (1.0 / 1.33, 0.8, 0.2),
            (2.4, 1.0, 0.05),
            (1.0 + 1e-4, 0.5, 0.5),
        ];
        for (eta, alpha, mu) in cases {
            let s = slots(eta, alpha);
            let sampler = K::transmission_sampler(&s).unwrap();
            let prepared = K::prepare::<f64, [f64]>(&s);
            let wi = DVec3::new(((1.0 - mu) * (1.0 + mu)).sqrt(), 0.0, mu);
            let glass = make(alpha, eta, wi);
            for i in 0..4000 {
                let u = [
                    (f64::from(i) + 0.5) / 4000.0,
                    (f64::from(i) * 0.618_033_988_749_895) % 1.0,
                ];
                let (r, t) = glass.weights(u);
                let (r0, t0) = weights::<K>(&sampler, &prepared, wi, u);
                assert!(
                    (r - r0).abs() <= 1e-9 * r0.abs().max(1e-3),
                    "{eta} {alpha} {mu} {u:?}: {r} {r0}"
                );
                assert!(
                    (t - t0).abs() <= 1e-9 * t0.abs().max(1e-3),
                    "{eta} {alpha} {mu} {u:?}: {t} {t0}"
                );
                checked += usize::from(r0 > 0.0) + usize::from(t0 > 0.0);
            }
        }
        assert!(checked > 20_000, "{checked}");
    }

    #[test]
    fn ggx_closed_form_weights_are_the_kernels() {
        closed_form_weights_are_the_kernel::<GgxDielectric, _>(|alpha, eta, wi| {
            GgxGlass::new(alpha, eta, wi, false, false)
        });
    }

    #[test]
    fn beckmann_closed_form_weights_are_the_kernels() {
        closed_form_weights_are_the_kernel::<BeckmannDielectric, _>(|alpha, eta, wi| {
            BeckmannGlass::new(alpha, eta, wi, false)
        });
    }

    /// Sobol points (with GGX's smooth radius) and the folded azimuth estimate the same
    /// albedo as random points with neither.
    fn smooth_and_fold_keep_the_albedo<K: Kernel>() {
        for (eta, alpha, mu) in [(1.5, 0.1, 0.8), (1.0 / 1.5, 0.4, 0.3), (1.1, 0.02, 0.6)] {
            let s = slots(eta, alpha);
            let sampler = K::transmission_sampler(&s).unwrap();
            let run = |sequence| {
                let options = AlbedoOptions {
                    samples: 1 << 16,
                    sequence,
                    ..AlbedoOptions::default()
                };
                integrate_cell::<K>(isa(), sampler, mu, &s, 3, &options, &Progress::default())
            };
            let (q, p) = (run(Sequence::Sobol), run(Sequence::Random));
            let bound = 5.0 * q.stderr[0].hypot(p.stderr[0]) + 1e-12;
            assert!((q.value[0] - p.value[0]).abs() < bound, "{q:?} {p:?}");
        }
    }

    #[test]
    fn ggx_smooth_radius_and_fold_keep_the_albedo() {
        smooth_and_fold_keep_the_albedo::<GgxDielectric>();
    }

    #[test]
    fn beckmann_sobol_and_fold_keep_the_albedo() {
        smooth_and_fold_keep_the_albedo::<BeckmannDielectric>();
    }

    /// The block loop of every instruction set gives the bits of the one-point weights
    /// (the cells' values do not depend on the CPU), over points that cover the disk's
    /// rim, its centre and the critical angle of both sides.
    fn block_weights_are_the_point_weights<G: ClosedFormGlass>(
        make: impl Fn(f64, f64, DVec3, bool, bool) -> G,
    ) {
        let n = POINTS;
        let u0: Vec<f64> = (0..n)
            .map(|j| ((j as f64 + 0.5) / n as f64).powi(3))
            .collect();
        let u1: Vec<f64> = (0..n)
            .map(|j| (j as f64 * 0.618_033_988_75).fract())
            .collect();
        for (alpha, eta, mu) in [
            (0.3, 1.5, 0.6_f64),
            (0.05, 1.0 / 1.5, 0.2),
            (1.0, 1.1, 0.01),
        ] {
            for (smooth, fold) in [(true, true), (false, false), (true, false)] {
                let wi = DVec3::new(((1.0 - mu) * (1.0 + mu)).sqrt(), 0.0, mu);
                let glass = make(alpha, eta, wi, smooth, fold);
                let (mut r, mut t) = (vec![0.0; n], vec![0.0; n]);
                glass_weights(isa(), &glass, &u0, &u1, &mut r, &mut t);
                let (mut rb, mut tb) = (vec![0.0; n], vec![0.0; n]);
                // SAFETY: the baseline runs on every CPU of the target.
                unsafe { loops::Baseline::glass(&glass, &u0, &u1, &mut rb, &mut tb) };
                for j in 0..n {
                    let (pr, pt) = glass.weights([u0[j], u1[j]]);
                    let case = (alpha, eta, mu, smooth, fold, j);
                    assert_eq!(r[j].to_bits(), pr.to_bits(), "{case:?}");
                    assert_eq!(t[j].to_bits(), pt.to_bits(), "{case:?}");
                    assert_eq!(
                        (rb[j].to_bits(), tb[j].to_bits()),
                        (pr.to_bits(), pt.to_bits())
                    );
                }
                assert!(r.iter().chain(&t).any(|&x| x > 0.0));
            }
        }
    }

    #[test]
    fn block_weights_are_the_point_weights_in_every_instruction_set() {
        block_weights_are_the_point_weights(GgxGlass::new);
        block_weights_are_the_point_weights(|alpha, eta, wi, _, fold| {
            BeckmannGlass::new(alpha, eta, wi, fold)
        });
    }

    #[test]
    fn eta_one_is_exact() {
        let t = albedo(1.0, 0.5, 0.4, Component::Transmission);
        assert_eq!((t.value, t.stderr, t.samples), ([1.0; 3], [0.0; 3], 0));
        let r = albedo(1.0, 0.5, 0.4, Component::Reflection);
        assert_eq!(r.value, [0.0; 3]);
    }
}
