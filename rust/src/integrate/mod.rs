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
//! near 1 for a smooth lobe with a rare region near 0: their per-point variance counts a
//! pseudo-point at each bound, so that a cell whose few points missed that region still
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
//! With `tol`, a cell doubles its sample count until the largest channel's standard
//! error is at most `tol` (or `max_samples` is reached): cells that converge early stop
//! early.
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

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use glam::DVec3;
use rayon::prelude::*;

use crate::error::BrdfError;
use crate::eval::engine::{self, Isa};
use crate::models::albedo::{Control, Importance, Integral, StratumLobe, Term};
use crate::models::{Directions, Kernel, KernelVisitor, ModelKind, TangentUse};
use crate::parallel;
use crate::sampling::streams::{SOBOL_MAX_POINTS, Sequence, Stream};
use crate::sampling::{Frame, ONE_BELOW, Warp};
use loops::{DirectionBlock, Loops};

mod beckmann;
pub mod cells;
mod ggx;
mod loops;

/// The largest sample count one cell may use (2^40 ≈ 1.1e12).
pub const MAX_SAMPLES_PER_CELL: u64 = 1 << 40;
/// The largest total sample count one request may ask for (2^44 ≈ 1.8e13: days of work).
pub const MAX_SAMPLES_PER_REQUEST: f64 = 17_592_186_044_416.0;

/// Which sampler draws each lobe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerChoice {
    /// The best measured: the lobe's own importance sampler, except that diffuse
    /// (cosine) lobes are drawn uniformly with Sobol points, which converges faster.
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
    /// Use the integrand's evenness in azimuth: draw azimuths on `[0, π)` only. Off, the
    /// points cover the full circle (the same estimator with half the point density
    /// per unit of azimuth); kept switchable so benchmarks can show what it buys. Used
    /// only where valid (see the module docs).
    pub fold_azimuth: bool,
    /// Estimate the average over the azimuth of `wi` (the cells' `phi` is then unused).
    pub average_azimuth: bool,
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
            fold_azimuth: true,
            average_azimuth: false,
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
        let per_cell = if self.tol.is_some() {
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

/// Points per block: the unit of vectorized work.
const POINTS: usize = 256;
/// Most scalar integrals one cell estimates together.
const MAX_LOBES: usize = 4;
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
/// An importance sampler must give a nonzero weight to at least one point in this many
/// of its first round, or its lobe falls back to cosine sampling
/// ([`CellIntegrand::fall_back`]).
const MIN_HIT_RATE: u64 = 32;
/// Partial sums per reduction: a fixed pattern, so the bits do not depend on the ISA.
const LANES: usize = 8;
/// Pseudo-points at each bound, 0 and 1, in the per-point variance of a bounded lobe
/// ([`LobeSums::rgb`]). Weights that are 1 but for a rare region of 0 (hit `λ` times on
/// average in a cell) make a cell that saw none of that region read `λ/n` high; with `a`
/// pseudo-points its error bar is `√a/n`, so such cells are beyond 3 standard errors
/// wherever `λ > 3√a`, which happens with probability `e^−λ`. One pseudo-point (Agresti
/// and Coull's count for a 2σ interval of a proportion) put 2.4% of cells beyond 3
/// standard errors where λ ≈ 3 (GGX at mu = 0.7, alpha = 0.1, 256 random points); three
/// bound that share by `e^−5.2` and cost under 3% of the error bar where the rare region
/// is not rare (a rough lobe, 256 points) and nothing measurable from a few thousand.
const PSEUDO_POINTS: f64 = 3.0;
/// The end regions of a lobe's sampler numbers ([`Lobe::ends`]): `mask` bit `2d` for
/// `u_d → 0`, bit `2d + 1` for `u_d → 1`, each region `width` wide.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Ends {
    mask: u8,
    width: f64,
}

impl Ends {
    const NONE: Ends = Ends {
        mask: 0,
        width: 0.0,
    };
}

/// The ends of Ward's and Ashikhmin-Shirley's first number (`u0 → 1`), logarithmic all
/// the way: one Sobol stratum of replicates of 16 points (cells of 256 samples) wide.
/// Measured (`scripts/stderr_calibration.py --grid half_vector`): 1/32 leaves replicates
/// of 16 points skewed (Ward at normal incidence: mean z 0.1, 1.6% beyond 3 standard
/// errors).
const LOG_ENDS: Ends = Ends {
    mask: 0b10,
    width: 1.0 / 16.0,
};

/// The ends of Beckmann's visible slopes, normal quantiles: both ends of the slope along
/// `wi`'s azimuth (`u0`) and, across it, the end of the folded quantile (`u1 → 0`), or
/// both of the full one. Measured as for [`LOG_ENDS`]: 1/64 leaves Beckmann at alpha 0.3
/// and normal incidence skewed (2.0% beyond 3 standard errors at 4096 samples, mean z
/// 0.16); 1/16 does not (0.4%, 0.02).
const SLOPE_ENDS: Ends = Ends {
    mask: 0b0111,
    width: 1.0 / 16.0,
};

/// A lobe ready to sample: the prepared basis evaluation and its warp. The warp also
/// says where it points: half vectors reflected into `wo` (Blinn), about the mirror
/// direction (Phong), about the normal (cosine, uniform).
struct Lobe<P> {
    colour: [f64; 3],
    prepared: P,
    warp: Warp,
    /// GGX's lobe from its visible normals, weighted in closed form (then `prepared` and
    /// `warp` are unused).
    ggx: Option<ggx::VisibleLobe>,
    /// Beckmann's lobe from its visible normals, likewise.
    beckmann: Option<beckmann::VisibleLobe>,
    /// The weights are known to lie in `[0, 1]` (a closed-form lobe without the QMC
    /// substitution: `F·G2/G1`): the per-point variance then counts
    /// [`PSEUDO_POINTS`] pseudo-points at each bound ([`LobeSums::rgb`]).
    bounded: bool,
    /// A control variate subtracted from the weights (a stratum's, [`Control`]), with
    /// `beta` already multiplied by the stratum's probability, and where the stratum is
    /// drawn with another exponent than its control's (a flattened tail), the factor and
    /// the power of `cos θh` of the ratio of the two densities.
    control: Option<(Control, Option<(f64, f64)>)>,
    /// The lobe a stratum belongs to (the term index of the stratum that stands for the
    /// whole lobe), and whether it is that stratum ([`Integral::Stratum`]): strata
    /// fall back together.
    stratum: Option<(usize, bool)>,
    /// The end regions of the sampler's numbers where, with Sobol points, the weight
    /// runs off along a logarithm or a normal quantile ([`LOG_ENDS`], [`SLOPE_ENDS`]):
    /// every replicate has one point there, and its skewed error is not reduced by more
    /// points. There the weight is integrated after a change of variables that vanishes
    /// at the end, against a control ([`CellIntegrand::weights`]).
    ends: Ends,
}

impl<P> Lobe<P> {
    /// A tail stratum ([`crate::models::strata`]): its weights are skewed (they grow
    /// towards the far end of the tail, where `G` and the horizon cut them per azimuth),
    /// and a Sobol replicate of a few points has one point there, so the replicates'
    /// means are skewed and their spread understates the error (Torrance-Sparrow near the
    /// normal with `R0` near 0: 4–6% of the cells of 256 samples beyond 3 standard errors
    /// against 0.9%, `scripts/stderr_calibration.py`). [`LobeSums::skewed_stderr`]
    /// bounds its error from every point of the cell.
    fn skewed(&self) -> bool {
        matches!(
            self.warp,
            Warp::BlinnStratum { .. } | Warp::PhongStratum { .. }
        ) && matches!(self.stratum, Some((_, false)))
    }
}

/// Returns `(sin φ, cos φ)`, exact at the multiples of π/2 (as `φ` rounds them), so
/// that `phi = np.pi` puts `wi` exactly in the xz plane.
fn azimuth_sin_cos(phi: f64) -> (f64, f64) {
    let half_turns = 2.0 * (phi / std::f64::consts::PI);
    if half_turns == half_turns.round() && half_turns.abs() < 1e15 {
        match (half_turns as i64).rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        }
    } else {
        phi.sin_cos()
    }
}

/// The per-sample weights `f·mu_o/pdf` of every lobe of a cell.
struct CellIntegrand<K: Kernel> {
    lobes: Vec<Lobe<K::Prepared<f64>>>,
    wi: DVec3,
    mirror_frame: Frame,
    fold: bool,
    /// Draw the azimuth of `wi` per point (`φ = (π/2)·u2`): the azimuth average.
    average: bool,
    sin_theta: f64,
}

impl<K: Kernel> CellIntegrand<K> {
    /// `anisotropic`: the model's albedo depends on `phi` (else `phi` and the average
    /// are ignored: the cell is integrated at φ = 0).
    fn new(
        mu: f64,
        phi: f64,
        anisotropic: bool,
        terms: &[Term],
        options: &AlbedoOptions,
    ) -> (Self, [f64; 3]) {
        let sampler = options.sampler;
        let average = anisotropic && options.average_azimuth;
        let (sin_phi, cos_phi) = if anisotropic && !average {
            azimuth_sin_cos(phi)
        } else {
            (0.0, 1.0)
        };
        // The fold maps the tangent frame's y to −y: valid for the anisotropic models
        // only when wi lies in the xz plane.
        let fold = options.fold_azimuth && !average && sin_phi == 0.0;
        let sobol = options.sequence == Sequence::Sobol;
        let sin = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
        let wi = DVec3::new(sin * cos_phi, sin * sin_phi, mu);
        // The mirror direction's frame keeps y normal to the plane of incidence, so the
        // azimuth fold maps the integrand onto itself. (`0.0 - x` keeps zeros positive:
        // at φ = 0 the frame is bitwise the one of `wi` in the xz plane.)
        let mirror_frame = Frame::with_y(
            DVec3::new(0.0 - wi.x, 0.0 - wi.y, mu),
            DVec3::new(0.0 - sin_phi, cos_phi, 0.0),
        );
        let mut exact = [0.0; 3];
        let mut lobes = Vec::new();
        // The strata of one lobe follow the stratum that stands for it: they share its
        // term index as their group.
        let mut group = 0;
        for (index, term) in terms.iter().enumerate() {
            if term.colour.iter().all(|&c| c == 0.0) {
                continue;
            }
            match term.integral {
                Integral::Exact(v) => {
                    for (e, c) in exact.iter_mut().zip(term.colour) {
                        *e += c * v;
                    }
                }
                Integral::GgxVisible { alpha, f0, basis } => {
                    let importance =
                        matches!(sampler, SamplerChoice::Auto | SamplerChoice::Importance);
                    // The closed-form weights hold one wi: a per-point wi (the azimuth
                    // average) takes the generic visible-normal warp instead.
                    let ggx = (importance && !average)
                        .then(|| ggx::VisibleLobe::new(alpha, f0, wi, sobol));
                    let warp = match sampler {
                        SamplerChoice::Cosine => Warp::CosineHemisphere,
                        _ if importance && average => Warp::GgxVisible { alpha },
                        _ => Warp::UniformHemisphere,
                    };
                    lobes.push(Lobe {
                        colour: term.colour,
                        prepared: K::prepare::<f64, [f64]>(&basis[..]),
                        warp,
                        bounded: ggx.is_some() && !sobol,
                        ggx,
                        beckmann: None,
                        control: None,
                        stratum: None,
                        ends: Ends::NONE,
                    });
                }
                Integral::BeckmannVisible { alpha, f0, basis } => {
                    let importance =
                        matches!(sampler, SamplerChoice::Auto | SamplerChoice::Importance);
                    // Isotropic: never averaged over azimuth (kept for completeness).
                    let closed_form = importance && !average;
                    let beckmann =
                        closed_form.then(|| beckmann::VisibleLobe::new(alpha, f0, wi, sobol));
                    let warp = match sampler {
                        SamplerChoice::Cosine => Warp::CosineHemisphere,
                        SamplerChoice::Uniform => Warp::UniformHemisphere,
                        _ => Warp::BeckmannVisible { alpha },
                    };
                    lobes.push(Lobe {
                        colour: term.colour,
                        prepared: K::prepare::<f64, [f64]>(&basis[..]),
                        warp,
                        ggx: None,
                        bounded: beckmann.is_some() && !sobol,
                        ends: match (sobol && beckmann.is_some(), fold) {
                            (false, _) => Ends::NONE,
                            (true, true) => SLOPE_ENDS,
                            (true, false) => Ends {
                                mask: 0b1111,
                                ..SLOPE_ENDS
                            },
                        },
                        beckmann,
                        control: None,
                        stratum: None,
                    });
                }
                Integral::Lobe { basis, importance } => {
                    let prepared = K::prepare::<f64, [f64]>(&basis[..]);
                    let warp = match (sampler, importance) {
                        (SamplerChoice::Uniform, _) => Warp::UniformHemisphere,
                        // Measured (benches/albedo_convergence.py, oren_nayar 32x32): with
                        // Sobol points the uniform warp reaches RMS 1e-5 in 0.10 s where
                        // the cosine warp needs 1.4 s; its sqrt(1 - u) corner makes the
                        // integrand rougher in the unit square. Random points prefer cosine.
                        (SamplerChoice::Auto, Importance::Cosine) if sobol => {
                            Warp::UniformHemisphere
                        }
                        (SamplerChoice::Cosine, _) | (_, Importance::Cosine) => {
                            Warp::CosineHemisphere
                        }
                        (_, Importance::PhongLobe { p }) => Warp::PhongLobe { p },
                        (_, Importance::BlinnHalf { p }) => Warp::BlinnHalf { p },
                        (_, Importance::GgxVisible { alpha }) => Warp::GgxVisible { alpha },
                        (_, Importance::BeckmannHalf { alpha_x, alpha_y }) => {
                            Warp::BeckmannHalf { alpha_x, alpha_y }
                        }
                        (_, Importance::BeckmannVisible { alpha }) => {
                            Warp::BeckmannVisible { alpha }
                        }
                        (_, Importance::AnisotropicPhongHalf { nu, nv }) => {
                            Warp::AnisotropicPhongHalf { nu, nv }
                        }
                    };
                    let log_end = matches!(
                        warp,
                        Warp::BeckmannHalf { .. } | Warp::AnisotropicPhongHalf { .. }
                    );
                    lobes.push(Lobe {
                        colour: term.colour,
                        prepared,
                        warp,
                        ggx: None,
                        beckmann: None,
                        bounded: false,
                        control: None,
                        stratum: None,
                        ends: if sobol && log_end {
                            LOG_ENDS
                        } else {
                            Ends::NONE
                        },
                    });
                }
                Integral::Stratum {
                    lobe,
                    basis,
                    p,
                    p_sobol,
                    c_lo,
                    c_hi,
                    whole,
                    control,
                } => {
                    // Strata belong to the lobe's own sampler: another sampler integrates
                    // the whole lobe once, through the stratum that stands for it.
                    let offset = lobe.offset();
                    let (warp, control, stratum) = match sampler {
                        SamplerChoice::Auto | SamplerChoice::Importance => {
                            let range = |p: f64| {
                                let v = |c: f64| if c >= 1.0 { 1.0 } else { c.powf(p + offset) };
                                (v(c_lo), v(c_hi) - v(c_lo))
                            };
                            let (v_lo_p, width_p) = range(p);
                            let (p_draw, (v_lo, width)) = if sobol && p_sobol != p {
                                (p_sobol, range(p_sobol))
                            } else {
                                (p, (v_lo_p, width_p))
                            };
                            // The control's mean is under the lobe's own density: drawn
                            // with another exponent, C is weighted by the ratio of the
                            // two densities, `(p+2)/(p'+2)·(width'/width)·c^(p − p')`
                            // (Blinn tails only: `c` is `cos θh`).
                            let control = control.map(|c| Control {
                                beta: c.beta * width_p,
                                ..c
                            });
                            if !(width > 0.0) {
                                // An empty stratum integrates to 0.
                                continue;
                            }
                            // The ratio's `c` is `cos θh`: only Blinn strata have controls
                            // drawn with another exponent.
                            let tilt = (p_draw != p && control.is_some()).then(|| {
                                debug_assert_eq!(lobe, StratumLobe::Blinn);
                                (
                                    (p + offset) / (p_draw + offset) * width / width_p,
                                    p - p_draw,
                                )
                            });
                            let warp = match lobe {
                                StratumLobe::Blinn => Warp::BlinnStratum {
                                    p: p_draw,
                                    v_lo,
                                    width,
                                },
                                StratumLobe::Phong => Warp::PhongStratum {
                                    p: p_draw,
                                    v_lo,
                                    width,
                                },
                            };
                            if whole {
                                group = index;
                            }
                            (warp, control.map(|c| (c, tilt)), Some((group, whole)))
                        }
                        _ if !whole => continue,
                        SamplerChoice::Cosine => (Warp::CosineHemisphere, None, None),
                        SamplerChoice::Uniform => (Warp::UniformHemisphere, None, None),
                    };
                    lobes.push(Lobe {
                        colour: term.colour,
                        prepared: K::prepare::<f64, [f64]>(&basis[..]),
                        warp,
                        ggx: None,
                        beckmann: None,
                        bounded: false,
                        control,
                        stratum,
                        ends: Ends::NONE,
                    });
                }
            }
        }
        debug_assert!(lobes.len() <= MAX_LOBES);
        (
            CellIntegrand {
                lobes,
                wi,
                mirror_frame,
                fold,
                average,
                sin_theta: sin,
            },
            exact,
        )
    }

    /// Switches every lobe whose importance sampler gave a nonzero weight to fewer than
    /// one point in [`MIN_HIT_RATE`] of the first round (`sums`, `total` points over all
    /// streams) to cosine sampling, and returns whether any did. A sampler that sends
    /// nearly every point where the lobe is 0 (below the horizon: the half vectors of a
    /// very rough lobe) sees the lobe through a handful of points, or none, and its error
    /// bar is then meaningless (0 ± 0 where the albedo is 1e-6); cosine sampling covers
    /// the hemisphere, where such a lobe is spread. Lobes that are 0 everywhere (grazing
    /// incidence) keep their sampler.
    fn fall_back(&mut self, sums: &[LobeSums], total: u64) -> bool {
        if self.wi.z <= 0.0 {
            return false;
        }
        let mut changed = false;
        // The lobes whose strata fall back: all their strata go, but the one that stands
        // for the whole lobe, which becomes the whole lobe under cosine sampling.
        let mut stratified = Vec::new();
        for (k, lobe) in self.lobes.iter_mut().enumerate() {
            let hits: u64 = sums.iter().map(|s| s.hits[k]).sum();
            let plain = matches!(lobe.warp, Warp::CosineHemisphere | Warp::UniformHemisphere)
                && lobe.ggx.is_none()
                && lobe.beckmann.is_none();
            if !plain && hits * MIN_HIT_RATE < total {
                lobe.warp = Warp::CosineHemisphere;
                lobe.ggx = None;
                lobe.beckmann = None;
                lobe.bounded = false;
                lobe.ends = Ends::NONE;
                changed = true;
                if let Some((group, _)) = lobe.stratum {
                    stratified.push(group);
                }
            }
        }
        self.lobes.retain_mut(|lobe| match lobe.stratum {
            Some((group, whole)) if stratified.contains(&group) => {
                lobe.warp = Warp::CosineHemisphere;
                lobe.control = None;
                lobe.stratum = None;
                whole
            }
            _ => true,
        });
        changed
    }

    /// Writes the weight of lobe `k` for every point `(u0[j], u1[j])` into `w` (and,
    /// for the azimuth average, `u2[j]` places `wi`): [`Self::raw_weights`], then, for
    /// the points in the lobe's [`Lobe::ends`], the weight after the change of variables
    /// there.
    ///
    /// With `s` the distance of a number from its end (in `[0, X)`, `X` the lobe's
    /// [`Ends::width`]), the end region's integral is taken in the variable `s` of
    /// `u = φ(s) = s·t·(2 − t)`, `t = s/X` (`φ(0) = 0`, `φ(X) = X`, `φ'(X) = 1`,
    /// `φ'(s) = t·(4 − 3t)`), against the control `c = w(X)` (the weight at the region's
    /// edge, the other number unchanged), whose integral `∫ c·φ' ds = ∫ c ds` is known:
    ///
    /// `∫_0^X w(u) du = ∫_0^X [(w(φ(s)) − c)·φ'(s) + c] ds = ∫_0^X [φ'·w(φ(s)) + (1 − φ')·c] ds`.
    ///
    /// The new integrand vanishes to first order at the end, where the old one ran off
    /// logarithmically, is continuously differentiable where it meets the rest, and
    /// differs from `w` only by `w − c`, so the variance stays that of `w`. A point is
    /// thus two weighted points (four in a corner of two regions), evaluated in batches.
    ///
    /// # Safety
    /// The CPU supports `I`'s instruction set.
    #[inline(always)]
    unsafe fn weights<I: Loops>(
        &self,
        k: usize,
        u0: &[f64],
        u1: &[f64],
        u2: &[f64],
        w: &mut [f64],
        dirs: &mut DirectionBlock,
    ) {
        // SAFETY: the caller's contract.
        unsafe { self.raw_weights::<I>(k, u0, u1, u2, w, dirs) };
        let ends = self.lobes[k].ends;
        if ends.mask == 0 {
            return;
        }
        let mut leaves = Leaves::new();
        for j in 0..w.len() {
            let u = [u0[j], u1[j]];
            let (a, b) = (end_split(ends, u, 0), end_split(ends, u, 1));
            if a.is_none() && b.is_none() {
                continue;
            }
            w[j] = 0.0;
            let a = a.unwrap_or([(u[0], 1.0), (0.0, 0.0)]);
            let b = b.unwrap_or([(u[1], 1.0), (0.0, 0.0)]);
            for &(x, cx) in &a {
                for &(y, cy) in &b {
                    let coef = cx * cy;
                    if coef == 0.0 {
                        continue;
                    }
                    if leaves.len == POINTS {
                        // SAFETY: the caller's contract.
                        unsafe { self.add_leaves::<I>(k, &mut leaves, w, dirs) };
                    }
                    leaves.push(j, [x, y, u2.get(j).copied().unwrap_or(0.0)], coef);
                }
            }
        }
        // SAFETY: the caller's contract.
        unsafe { self.add_leaves::<I>(k, &mut leaves, w, dirs) };
    }

    /// Evaluates the pending `leaves` of lobe `k` and adds each, times its coefficient,
    /// to its point's weight in `w`; empties `leaves`.
    ///
    /// # Safety
    /// The CPU supports `I`'s instruction set.
    #[inline(always)]
    unsafe fn add_leaves<I: Loops>(
        &self,
        k: usize,
        leaves: &mut Leaves,
        w: &mut [f64],
        dirs: &mut DirectionBlock,
    ) {
        let n = leaves.len;
        let Leaves {
            u,
            point,
            coef,
            w: lw,
            ..
        } = leaves;
        // SAFETY: the caller's contract.
        unsafe { self.raw_weights::<I>(k, &u[0][..n], &u[1][..n], &u[2][..n], &mut lw[..n], dirs) };
        for i in 0..n {
            w[point[i]] += coef[i] * lw[i];
        }
        leaves.len = 0;
    }

    /// Writes the weight of lobe `k` for every point `(u0[j], u1[j])` into `w` (and,
    /// for the azimuth average, `u2[j]` places `wi`): the model-independent loops of `I`
    /// draw the directions into `dirs`, then one loop evaluates the model.
    ///
    /// Folded, points cover the half azimuth range `[0, π)` (density 2·pdf there) and the
    /// integral is twice the half's: the two factors cancel in `f·mu_o/pdf`.
    ///
    /// # Safety
    /// The CPU supports `I`'s instruction set.
    #[inline(always)]
    unsafe fn raw_weights<I: Loops>(
        &self,
        k: usize,
        u0: &[f64],
        u1: &[f64],
        u2: &[f64],
        w: &mut [f64],
        dirs: &mut DirectionBlock,
    ) {
        let lobe = &self.lobes[k];
        let n = w.len();
        let weight = |wi: DVec3, wo: DVec3, pdf: f64| {
            let d = Directions::<f64> {
                wi,
                wo,
                n: DVec3::Z,
                t: DVec3::X,
            };
            let x = K::eval::<f64>(&lobe.prepared, &d)[0] * wo.z / pdf;
            if wo.z > 0.0 && pdf > 0.0 { x } else { 0.0 }
        };
        if self.average {
            let (sin, mu) = (self.sin_theta, self.wi.z);
            // SAFETY: the caller's contract.
            unsafe { I::directions_averaged(lobe.warp, sin, mu, u0, u1, u2, dirs) };
            let points = dirs.wi[..n].iter().zip(&dirs.wo[..n]).zip(&dirs.pdf[..n]);
            for (w, ((&wi, &wo), &pdf)) in w.iter_mut().zip(points) {
                *w = weight(wi, wo, pdf);
            }
            if let Some((control, tilt)) = lobe.control {
                let points = dirs.wi[..n].iter().zip(&dirs.wo[..n]);
                for (w, (&wi, &wo)) in w.iter_mut().zip(points) {
                    *w -= control.beta * (control_value(control, tilt, wi, wo) - control.mean);
                }
            }
            return;
        }
        if let Some(ggx) = &lobe.ggx {
            // SAFETY: the caller's contract.
            unsafe { I::closed_form(ggx, self.fold, u0, u1, w) };
            return;
        }
        if let Some(beckmann) = &lobe.beckmann {
            // SAFETY: the caller's contract.
            unsafe { I::closed_form(beckmann, self.fold, u0, u1, w) };
            return;
        }
        let wi = self.wi;
        // SAFETY: the caller's contract.
        unsafe { I::directions(lobe.warp, self.fold, wi, &self.mirror_frame, u0, u1, dirs) };
        for (w, (&wo, &pdf)) in w.iter_mut().zip(dirs.wo[..n].iter().zip(&dirs.pdf[..n])) {
            *w = weight(wi, wo, pdf);
        }
        if let Some((control, tilt)) = lobe.control {
            for (w, &wo) in w.iter_mut().zip(&dirs.wo[..n]) {
                *w -= control.beta * (control_value(control, tilt, wi, wo) - control.mean);
            }
        }
    }
}

/// For a point `u` whose number `d` lies in an end region of `ends` ([`Lobe::ends`]):
/// that number at the two points that replace it, `φ(s)` and the region's edge, with
/// their coefficients `φ'(s)` and `1 − φ'(s)` ([`CellIntegrand::weights`]); `None`
/// elsewhere.
#[inline(always)]
fn end_split(ends: Ends, u: [f64; 2], d: usize) -> Option<[(f64, f64); 2]> {
    let x = ends.width;
    let low = if ends.mask >> (2 * d) & 1 != 0 && u[d] < x {
        true
    } else if ends.mask >> (2 * d + 1) & 1 != 0 && u[d] > 1.0 - x {
        false
    } else {
        return None;
    };
    let s = if low { u[d] } else { 1.0 - u[d] };
    let t = s / x;
    let slope = t * (4.0 - 3.0 * t);
    let v = s * t * (2.0 - t);
    let (inner, edge) = if low {
        (v, x)
    } else {
        ((1.0 - v).min(ONE_BELOW), 1.0 - x)
    };
    Some([(inner, slope), (edge, 1.0 - slope)])
}

/// Points that stand in for the points of end regions ([`CellIntegrand::weights`]):
/// their numbers `(u0, u1, u2)`, the point each belongs to, its coefficient, and room
/// for its weight.
struct Leaves {
    len: usize,
    u: [[f64; POINTS]; 3],
    point: [usize; POINTS],
    coef: [f64; POINTS],
    w: [f64; POINTS],
}

impl Leaves {
    fn new() -> Self {
        Leaves {
            len: 0,
            u: [[0.0; POINTS]; 3],
            point: [0; POINTS],
            coef: [0.0; POINTS],
            w: [0.0; POINTS],
        }
    }

    #[inline(always)]
    fn push(&mut self, point: usize, u: [f64; 3], coef: f64) {
        let i = self.len;
        for (lane, x) in self.u.iter_mut().zip(u) {
            lane[i] = x;
        }
        self.point[i] = point;
        self.coef[i] = coef;
        self.len += 1;
    }
}

/// The control variate's `C` at one point ([`Control`]): Schlick's `r0 + (1 − r0)·X^5`
/// (1 where `r0` is 1), times `cos_b/cos θh` and `mu_o` as asked, with `h` the half
/// vector of `wi` and `wo`, `cos_b = wi·h` and `X = 1 − cos_b = |wi − h|²/2` (no
/// cancellation), times `tilt = (a, k)`'s density ratio `a·cos^k θh` if given; `h` is
/// formed only where one of these reads it. A point without a half vector gives
/// `C = mean` (no correction).
#[inline(always)]
fn control_value(control: Control, tilt: Option<(f64, f64)>, wi: DVec3, wo: DVec3) -> f64 {
    let needs_h = control.r0 != 1.0 || control.over_cos || tilt.is_some();
    let h = if needs_h {
        (wi + wo).normalize()
    } else {
        DVec3::Z
    };
    let c = if control.r0 == 1.0 {
        1.0
    } else {
        let x = 0.5 * (wi - h).length_squared();
        let x2 = x * x;
        let x5 = x2 * x2 * x;
        if control.r0 != 0.0 {
            control.r0 + (1.0 - control.r0) * x5
        } else {
            x5
        }
    };
    let c = if control.over_cos {
        c * wi.dot(h) / h.z
    } else {
        c
    };
    let c = if control.mu_o { c * wo.z } else { c };
    let c = match tilt {
        Some((a, k)) => c * a * h.z.powf(k),
        None => c,
    };
    if c.is_finite() { c } else { control.mean }
}

/// Sums of lobe weights over points: `Σ (w_k − c_k)` and `Σ (w_k − c_k)(w_l − c_l)`,
/// accumulated in `LANES` fixed partial sums (deterministic, and free to run in SIMD
/// lanes). The shift `c_k` (the first block's mean) keeps the variance free of the
/// cancellation of `Σw² − n·mean²` when the weights are nearly constant. Lobes with a
/// control variate are shifted for Sobol points too (no cross sums there): their weights
/// are nearly constant by design, and a plain running sum of 2^16 such weights per
/// replicate is off by about 1e-13 of the mean (each addition rounds the same way),
/// the same for every replicate, far above the replicates' spread.
#[derive(Clone)]
struct LobeSums {
    n: u64,
    /// Points with a nonzero weight, per lobe.
    hits: [u64; MAX_LOBES],
    shift: [f64; MAX_LOBES],
    sum: [[f64; LANES]; MAX_LOBES],
    cross: [[[f64; LANES]; MAX_LOBES]; MAX_LOBES],
    /// Per skewed lobe ([`Lobe::skewed`]), its index and its weights in bins of the unit
    /// square of `(u0, u1)`: for each of the [`SHAPES`] partitions into [`BINS`] equal
    /// rectangles, per bin, the points and the sums of the shifted weights and of their
    /// squares. Kept while the replicates have fewer than [`SKEWED_FROM`] points.
    bins: Vec<(usize, Bins)>,
}

impl LobeSums {
    /// Empty sums; `skewed` lists the lobes kept in bins.
    fn new(skewed: &[usize]) -> Self {
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
    fn add_block(
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
    /// skewed end. Zero where no lobe is skewed, from [`SKEWED_FROM`] points per replicate
    /// on, and for a lobe with a bin of fewer than two points.
    fn skewed_stderr<P>(replicates: &[LobeSums], lobes: &[Lobe<P>]) -> [f64; 3] {
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
            let var = |[n, s1, s2]: [f64; 3]| ((s2 - s1 * s1 / n) / (n - 1.0)).max(0.0);
            let Some(var_mean) = bins
                .iter()
                .filter(|shape| shape.iter().all(|b| b[0] >= 2.0))
                .map(|shape| shape.iter().map(|&b| var(b) / b[0]).sum::<f64>())
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
    fn rgb<P>(&self, lobes: &[Lobe<P>]) -> ([f64; 3], [f64; 3]) {
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

/// Point scratch of one block.
struct PointBlock {
    u0: [f64; POINTS],
    u1: [f64; POINTS],
    /// The azimuth of `wi` (the azimuth average only).
    u2: [f64; POINTS],
    w: [[f64; POINTS]; MAX_LOBES],
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
    // Shifted sums: every lobe for the cross sums, and lobes with a control variate.
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
            // SAFETY: the caller's contract.
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
    let anisotropic = K::spec().tangent != TangentUse::None;
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
    let streams_count = if random {
        1
    } else {
        u64::from(options.replicates)
    };
    let cap = if options.tol.is_some() {
        options.max_samples
    } else {
        u64::MAX
    };
    // Points per stream in the first round: at least 2 for a variance (random); a power
    // of two per replicate, as every such prefix is a net (Sobol).
    let first = options.samples.min(cap);
    let mut per_stream = if random {
        first.max(2)
    } else {
        first.div_ceil(streams_count).next_power_of_two()
    };
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
    let (mean, stderr, samples) = loop {
        let count = per_stream - done_per_stream;
        for (stream, s) in streams.iter_mut().zip(sums.iter_mut()) {
            // SAFETY: the caller's contract.
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
            (mean, std::array::from_fn(|c| se[c].max(floor[c])))
        };
        let done = match options.tol {
            None => true,
            Some(tol) => {
                let capped = if random {
                    total >= options.max_samples
                } else {
                    total * 2 > options.max_samples
                };
                se.iter().all(|&s| s <= tol) || capped
            }
        };
        if done || progress.cancel.load(Ordering::Relaxed) {
            break (mean, se, total);
        }
        per_stream = if random {
            (per_stream * 2).min(options.max_samples)
        } else {
            per_stream * 2
        };
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

/// The mean of RGB values and its standard error, computed in two passes.
fn mean_and_stderr(values: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
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

type CellFn = fn(f64, f64, &[f64], u64, &AlbedoOptions, &Progress) -> CellResult;

fn cell_baseline<K: Kernel>(
    mu: f64,
    phi: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    // SAFETY: baseline instructions only.
    unsafe { integrate_cell::<K, loops::Baseline>(mu, phi, slots, cell, options, progress) }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn cell_avx2<K: Kernel>(
    mu: f64,
    phi: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    // SAFETY: this function's own features (its caller checked the CPU).
    unsafe { integrate_cell::<K, loops::Avx2>(mu, phi, slots, cell, options, progress) }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn cell_avx512<K: Kernel>(
    mu: f64,
    phi: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    // SAFETY: as above.
    unsafe { integrate_cell::<K, loops::Avx512>(mu, phi, slots, cell, options, progress) }
}

/// Integrates one cell with the loop compiled for `isa` (which the CPU must support).
fn integrate_cell_isa<K: Kernel>(
    isa: Isa,
    mu: f64,
    phi: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: `isa` comes from `engine::isa()`, which checked the CPU's features.
        match isa {
            Isa::Avx512 => {
                return unsafe { cell_avx512::<K>(mu, phi, slots, cell, options, progress) };
            }
            Isa::Avx2 => {
                return unsafe { cell_avx2::<K>(mu, phi, slots, cell, options, progress) };
            }
            Isa::Baseline => {}
        }
    }
    let f: CellFn = cell_baseline::<K>;
    f(mu, phi, slots, cell, options, progress)
}

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
        let isa = engine::isa();
        let work = |(i, result): (usize, &mut CellResult)| {
            if progress.cancel.load(Ordering::Relaxed) {
                return;
            }
            let mut slots = Vec::new();
            let (mu, phi, id) = cells.cell(i, &mut slots);
            *result = integrate_cell_isa::<K>(isa, mu, phi, &slots, id, options, progress);
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
            for sequence in [Sequence::Sobol, Sequence::Random] {
                for sampler in [
                    SamplerChoice::Auto,
                    SamplerChoice::Uniform,
                    SamplerChoice::Cosine,
                ] {
                    let opts = AlbedoOptions {
                        samples: 1 << 16,
                        sequence,
                        sampler,
                        ..Default::default()
                    };
                    let got = albedo_one("torrance_sparrow", 1.0, &base, opts);
                    let label = format!("p={p} eta={eta} {sequence:?} {sampler:?}");
                    assert!(got.stderr[0] > 0.0, "{label}: {got:?}");
                    assert_within(got, want, 5.0, &label);
                    if sampler == SamplerChoice::Auto && p == 100.0 && eta == 1.5 {
                        // The control leaves the spread of the tail, of probability 4e-7.
                        assert!(got.stderr[0] < 1e-8 * want, "{label}: {got:?} vs {want}");
                    }
                }
            }
        }
    }

    /// Strata fall back together: when one stratum of a lobe falls back to cosine
    /// sampling, the stratum that stands for the lobe becomes the whole lobe (cosine warp,
    /// no control) and the others are dropped.
    #[test]
    fn strata_fall_back_together() {
        use crate::models::torrance_sparrow::{ETA, KS, P, TorranceSparrow};
        let mut slots = [0.0; 8];
        KS.write(&mut slots, [1.0; 3]);
        P.write(&mut slots, 100.0);
        ETA.write(&mut slots, 1.5);
        let terms = TorranceSparrow::albedo_terms(&slots, 1.0).unwrap();
        let (mut integrand, _) =
            CellIntegrand::<TorranceSparrow>::new(1.0, 0.0, false, &terms, &Default::default());
        assert_eq!(integrand.lobes.len(), 2, "bulk and tail");
        assert!(integrand.lobes[0].control.is_some());
        let mut sums = LobeSums::new(&[]);
        sums.hits = [1000, 0, 0, 0];
        assert!(integrand.fall_back(&[sums], 1000));
        assert_eq!(integrand.lobes.len(), 1);
        let lobe = &integrand.lobes[0];
        assert_eq!(lobe.warp, Warp::CosineHemisphere);
        assert!(lobe.control.is_none() && lobe.stratum.is_none());
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
        for sequence in [Sequence::Sobol, Sequence::Random] {
            for sampler in [
                SamplerChoice::Uniform,
                SamplerChoice::Cosine,
                SamplerChoice::Importance,
            ] {
                let opts = AlbedoOptions {
                    samples: 1 << 16,
                    sequence,
                    sampler,
                    ..Default::default()
                };
                let r = albedo_one("torrance_sparrow", 0.4, &base, opts);
                assert_within(r, want.value[0], 5.0, &format!("{sequence:?} {sampler:?}"));
            }
        }
    }

    #[test]
    fn adaptive_stopping_reaches_the_tolerance() {
        // A lobe without a closed-form bulk (power-cosine lobes now have one).
        let base = [("kd", 1.0), ("sigma", 0.5)];
        for sequence in [Sequence::Sobol, Sequence::Random] {
            let opts = AlbedoOptions {
                samples: 256,
                tol: Some(1e-3),
                max_samples: 1 << 22,
                sequence,
                ..Default::default()
            };
            let r = albedo_one("oren_nayar", 0.5, &base, opts);
            assert!(r.stderr.iter().all(|&s| s <= 1e-3), "{r:?}");
            assert!(r.samples > 256 && r.samples < 1 << 22, "{r:?}");
        }
    }

    #[test]
    fn quarter_turns_are_exact() {
        use std::f64::consts::{FRAC_PI_2, PI};
        assert_eq!(azimuth_sin_cos(0.0), (0.0, 1.0));
        assert_eq!(azimuth_sin_cos(FRAC_PI_2), (1.0, 0.0));
        assert_eq!(azimuth_sin_cos(PI), (0.0, -1.0));
        assert_eq!(azimuth_sin_cos(-FRAC_PI_2), (-1.0, 0.0));
        assert_eq!(azimuth_sin_cos(4.0 * PI), (0.0, 1.0));
        let (s, c) = azimuth_sin_cos(0.3);
        assert_eq!((s, c), 0.3f64.sin_cos());
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
