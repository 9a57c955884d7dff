//! The integrand of one cell: its lobes ready to sample ([`Lobe`]), and the per-point
//! weights `f·mu_o/pdf` of each ([`CellIntegrand`]), with the control variates
//! ([`control_value`]) and the end regions' change of variables applied.

use glam::DVec3;

use super::ends::{Ends, LOG_ENDS, Leaves, SLOPE_ENDS, end_split};
use super::loops::{DirectionBlock, Loops};
use super::options::AlbedoOptions;
use super::sums::LobeSums;
use super::{MAX_LOBES, POINTS, beckmann, ggx};
use crate::models::albedo::{Control, Importance, Integral, StratumLobe, Term};
use crate::models::{Directions, Kernel};
use crate::sampling::streams::Sequence;
use crate::sampling::{Frame, SamplerChoice, Warp};

/// An importance sampler must give a nonzero weight to at least one point in this many
/// of its first round, or its lobe falls back to cosine sampling
/// ([`CellIntegrand::fall_back`]).
const MIN_HIT_RATE: u64 = 32;

/// A lobe ready to sample: the prepared basis evaluation and its warp. The warp also
/// says where it points: half vectors reflected into `wo` (Blinn), about the mirror
/// direction (Phong), about the normal (cosine, uniform).
pub(super) struct Lobe<P> {
    pub(super) colour: [f64; 3],
    prepared: P,
    warp: Warp,
    /// GGX's lobe from its visible normals, weighted in closed form (then `prepared` and
    /// `warp` are unused).
    ggx: Option<ggx::VisibleLobe>,
    /// Beckmann's lobe from its visible normals, likewise.
    beckmann: Option<beckmann::VisibleLobe>,
    /// The weights are known to lie in `[0, 1]` (a closed-form lobe without the QMC
    /// substitution: `F·G2/G1`): the per-point variance then counts pseudo-points at
    /// each bound ([`LobeSums::rgb`]; how many: `PSEUDO_POINTS` in `sums.rs`).
    pub(super) bounded: bool,
    /// A control variate subtracted from the weights (a stratum's, [`Control`]), with
    /// `beta` already multiplied by the stratum's probability, and where the stratum is
    /// drawn with another exponent than its control's (a flattened tail), the factor and
    /// the power of `cos θh` of the ratio of the two densities.
    pub(super) control: Option<(Control, Option<(f64, f64)>)>,
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
    /// The sampler's first number from which the weight is 0 for some points (a Blinn
    /// tail's `wo` below the surface, [`Integral::Stratum`]'s `zeros_below`), where that
    /// region begins inside the stratum: [`LobeSums::skewed_stderr`] counts a pseudo-point
    /// at 0 in the bins that reach into it.
    pub(super) zeros_from: Option<f64>,
}

impl<P> Lobe<P> {
    /// A tail stratum ([`crate::models::strata`]): its weights are skewed (they grow
    /// towards the far end of the tail, where `G` and the horizon cut them per azimuth),
    /// and a Sobol replicate of a few points has one point there, so the replicates'
    /// means are skewed and their spread understates the error (Torrance-Sparrow near the
    /// normal with `R0` near 0: 4–6% of the cells of 256 samples beyond 3 standard errors
    /// against 0.9%, `scripts/stderr_calibration.py`). [`LobeSums::skewed_stderr`]
    /// bounds its error from every point of the cell.
    pub(super) fn skewed(&self) -> bool {
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
pub(super) struct CellIntegrand<K: Kernel> {
    pub(super) lobes: Vec<Lobe<K::Prepared<f64>>>,
    wi: DVec3,
    mirror_frame: Frame,
    fold: bool,
    /// Draw the azimuth of `wi` per point (`φ = (π/2)·u2`): the azimuth average.
    pub(super) average: bool,
    sin_theta: f64,
}

impl<K: Kernel> CellIntegrand<K> {
    /// `anisotropic`: the model's albedo depends on `phi` (else `phi` and the average
    /// are ignored: the cell is integrated at φ = 0).
    pub(super) fn new(
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
                        zeros_from: None,
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
                        zeros_from: None,
                    });
                }
                Integral::Lobe { basis, importance } => {
                    let prepared = K::prepare::<f64, [f64]>(&basis[..]);
                    let warp = match (sampler, importance) {
                        (SamplerChoice::Uniform, _)
                        | (SamplerChoice::Auto | SamplerChoice::Importance, Importance::Uniform) => {
                            Warp::UniformHemisphere
                        }
                        // Measured (benches/albedo_convergence.py, oren_nayar 32x32): with
                        // Sobol points the uniform warp reaches RMS 1e-5 in 0.10 s where
                        // the cosine warp needs 1.4 s; its sqrt(1 - u) corner makes the
                        // integrand rougher in the unit square. Random points prefer cosine.
                        (SamplerChoice::Auto, Importance::Cosine) if sobol => {
                            Warp::UniformHemisphere
                        }
                        // Likewise the cosine/uniform mixture, whose switch between its
                        // warps adds a jump in the square: with Sobol points uniform
                        // draws of ashikhmin_cloth tables reach 3x smaller RMS errors at
                        // 4096 samples (benches/sheen_sampling.py); random points and
                        // brdf_rs.sample keep the mixture.
                        (SamplerChoice::Auto, Importance::CosineUniform { .. }) if sobol => {
                            Warp::UniformHemisphere
                        }
                        (SamplerChoice::Cosine, _) | (_, Importance::Cosine) => {
                            Warp::CosineHemisphere
                        }
                        (_, Importance::CosineUniform { cosine }) => Warp::CosineUniform { cosine },
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
                        zeros_from: None,
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
                    zeros_below,
                } => {
                    // Strata belong to the lobe's own sampler: another sampler integrates
                    // the whole lobe once, through the stratum that stands for it.
                    let offset = lobe.offset();
                    let (warp, control, stratum, zeros_from) = match sampler {
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
                            // Points are drawn with `v = cos^(p_draw + offset)` uniform
                            // from `v_lo + width` (u0 = 0) down to `v_lo` (u0 → 1), so
                            // the region of zeros is u0 beyond that of its edge. Only
                            // for weights without a control (which is not 0 there).
                            let zeros_from = zeros_below.filter(|_| control.is_none()).map(|c| {
                                let v = c.powf(p_draw + offset);
                                (1.0 - (v - v_lo) / width).clamp(0.0, 1.0)
                            });
                            (
                                warp,
                                control.map(|c| (c, tilt)),
                                Some((group, whole)),
                                zeros_from,
                            )
                        }
                        _ if !whole => continue,
                        SamplerChoice::Cosine => (Warp::CosineHemisphere, None, None, None),
                        SamplerChoice::Uniform => (Warp::UniformHemisphere, None, None, None),
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
                        zeros_from,
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
    pub(super) fn fall_back(&mut self, sums: &[LobeSums], total: u64) -> bool {
        if self.wi.z <= 0.0 {
            return false;
        }
        let mut changed = false;
        // The lobes whose strata fall back: all their strata go, but the one that stands
        // for the whole lobe, which becomes the whole lobe under cosine sampling.
        let mut stratified = Vec::new();
        for (k, lobe) in self.lobes.iter_mut().enumerate() {
            let hits: u64 = sums.iter().map(|s| s.hits[k]).sum();
            let plain = matches!(
                lobe.warp,
                Warp::CosineHemisphere | Warp::UniformHemisphere | Warp::CosineUniform { .. }
            ) && lobe.ggx.is_none()
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
                lobe.zeros_from = None;
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
    pub(super) unsafe fn weights<I: Loops>(
        &self,
        k: usize,
        u0: &[f64],
        u1: &[f64],
        u2: &[f64],
        w: &mut [f64],
        dirs: &mut DirectionBlock,
    ) {
        // SAFETY: `raw_weights` needs the CPU to run `I`'s instructions, which is what
        // this function's callers promise (`integrate_cell_isa` picks `I` from an `Isa`).
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
                        // SAFETY: `add_leaves` asks what `weights` is given: the CPU
                        // runs `I`'s instructions.
                        unsafe { self.add_leaves::<I>(k, &mut leaves, w, dirs) };
                    }
                    leaves.push(j, [x, y, u2.get(j).copied().unwrap_or(0.0)], coef);
                }
            }
        }
        // SAFETY: as for the batches above, `weights`' own requirement on `I` covers it.
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
        // SAFETY: `raw_weights` needs the CPU to run `I`'s instructions; so does this
        // function, whose callers (`weights`) promise it.
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
            // SAFETY: `Loops` methods run `I`'s instructions; this function's callers
            // promise the CPU has them (the `Isa` token `integrate_cell_isa` matched).
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
            // SAFETY: `I::closed_form` runs `I`'s instructions, which this function's
            // own contract says the CPU has.
            unsafe { I::closed_form(ggx, self.fold, u0, u1, w) };
            return;
        }
        if let Some(beckmann) = &lobe.beckmann {
            // SAFETY: as for GGX's lobe: `I::closed_form` needs `I`'s instructions, which
            // this function's contract guarantees.
            unsafe { I::closed_form(beckmann, self.fold, u0, u1, w) };
            return;
        }
        let wi = self.wi;
        // SAFETY: `I::directions` runs `I`'s instructions; this function is only called
        // where the CPU has them (its `# Safety` contract).
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
