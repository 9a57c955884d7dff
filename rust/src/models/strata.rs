//! Strata and control variates for lobes drawn from power-cosine densities (Blinn half
//! vectors: `torrance_sparrow`, the Blinn-Phong family; the Phong lobe about the mirror
//! direction: the Phong family): the integrator's decomposition of those lobes.
//!
//! With the incidence `wi` fixed (`mu = cos θi`) and the half vector `h` drawn from the
//! Blinn density `pdf_h = (p+2)/(2π)·cos^(p+1) θh` (`Warp::BlinnHalf`: `v = cos^(p+2) θh`
//! uniform), the lobe's weight `f·mu_o/pdf` is
//!
//! - Torrance-Sparrow: `F·G·cos_b/(mu·c)`, with `c = cos θh`, `cos_b = wi·h`,
//!   `F = R0 + (1 − R0)·X^5`, `X = 1 − cos_b` (Schlick);
//! - Blinn-Phong with Fresnel, the F0 = 0 integral: `κ·X^5·cos_b·mu_o/c`,
//!   `κ = (p+8)/(p+2)`, `mu_o = 2·cos_b·c − mu`;
//!
//! and 0 where `wo` lies below the surface. Two things make its error bar fail when the
//! lobe is sharp (large `p`) and `wi` near the normal:
//!
//! 1. *Schlick's excess is heavy-tailed.* `X ≈ (1 − mu) + mu·t − B cos φ` (`t = 1 − c`,
//!    `B = sin θi·sin θh`) is tiny near the lobe's centre and `X^5 ∝ θh^10` at normal
//!    incidence, while `θh²` is about exponentially distributed: a cell of a few hundred
//!    points rarely sees the part of the tail that carries the mean, and its sample
//!    variance is too small.
//! 2. *The rare region where the weight has a kink.* The V-cavity `G` is 1 for every
//!    azimuth while `θh < θc = (90° − θi)/3` (with `h` tilted away from `wi`, `G < 1`
//!    once `θi + 3θh > 90°`; tilted towards it, once `θh > 90° − θi`; `wo` leaves the
//!    hemisphere once `θi + 2θh > 90°`). Beyond `θc` the weight drops; the region's
//!    probability `q = cos^(p+2) θc` is 4e-7 at normal incidence and p = 100, so most
//!    cells never see it. For Blinn-Phong the only kink is the horizon, from
//!    `θh = (90° − θi)/2`.
//!
//! The remedy, where `q` is below [`SPLIT_BELOW`] (`θe` is `θc` for Torrance-Sparrow,
//! `(90° − θi)/2` for Blinn-Phong):
//!
//! - **Two strata of the Blinn sampler**, the *bulk* `θh ≤ θe` (`v ∈ [q, 1]`) and the
//!   *tail* `θe < θh < (90° + θi)/2` (beyond which every `wo` is below the surface and the
//!   weight is 0), each integrated on all points of the cell (a linear map of the first
//!   number into its range of `v`; the weight carries the stratum's probability). They are
//!   two lobes of one cell, so the integrator's cross sums give the variance of their sum
//!   for both estimators (per point, and over Sobol replicates). A fixed allocation: a
//!   random choice between the strata would add their between-strata variance, of the
//!   order of the value squared. Where the tail cannot matter (its weight is at most
//!   `2q`, below 2^-60 of the bulk's mean) it is left out.
//! - **A control variate in the bulk** that is the bulk's whole weight, so the bulk is
//!   integrated exactly: with `G = 1` there, Torrance-Sparrow's weight is `F·J/mu`,
//!   `J = cos_b/c`, and `C = F·J` (Schlick's `F` for the lobe's `R0`, [`Control::r0`])
//!   has the closed-form mean `R0·mu + (1 − R0)·E[X^5·J]` ([`Bulk::expect`]); with
//!   `β = 1/mu` the bulk's weight becomes the constant `E[C]/mu`. Blinn-Phong's Schlick
//!   term likewise: `C = X^5·cos_b·mu_o/c`, `β = κ = (p+8)/(p+2)`. At exactly normal
//!   incidence the tail's weight is `F·2·mu_o` and the control `X^5·mu_o` removes its
//!   Schlick excess too ([`Bulk::tail_expect`]). The estimate of a constant is exact up
//!   to the rounding of the weights and of the closed form (`rounding`).
//! - **A flatter tail for Sobol points**, as the tail carries the cell's error: see
//!   [`Bulk::flat_tail`]. With few points per Sobol replicate the tail's error bar is
//!   also bounded from all points of the cell (`integrate`'s `skewed_stderr`).
//!
//! The plain power-cosine lobes (the Phong and Blinn-Phong families, and Blinn-Phong with
//! Fresnel's F0 term) are split the same way ([`blinn_terms`], [`phong_terms`]): their
//! weight is a constant times `cos_b·mu_o/c` (Blinn) or `mu_o` (Phong) wherever `wo` is
//! above the surface, so the bulk is exact and the tail alone is sampled. Drawn whole,
//! the weight runs to its horizon value along a logarithmic end of the sampler's first
//! number, which skews Sobol replicates even where nothing else would.
//!
//! Elsewhere (`q ≥ SPLIT_BELOW`: wide lobes, or `wi` far from the normal) the lobe is
//! the plain lobe (`Integral::Lobe`), and so are the lobes of the other models.

use std::f64::consts::FRAC_PI_2;

use super::albedo::{Control, Integral, Slots, StratumLobe, Term};

/// Split a lobe into strata where the tail's probability `q` is below this. Unsplit, a
/// Sobol replicate of 16 points (256 samples per cell) has its last point in `u0` in the
/// tail, where `G`'s kinks and the horizon make the weights differ most; where `q` is
/// small that point's share of the replicate's error skews the replicate means:
/// unsplit, Torrance-Sparrow at mu = 0.5, p = 100 (`q = 0.21`) put 3.6% of its cells
/// beyond 3 standard errors (0.9% is honest), at mu = 1, p = 5 (`q = 0.37`) 2.0%, at
/// mu = 0.7, p = 10 (`q = 0.67`) 0.5% (`scripts/stderr_calibration.py`, with `--grid`).
/// The split costs a second evaluation per point where the tail is kept.
pub const SPLIT_BELOW: f64 = 0.4;

/// A tail whose weight is at most this fraction of the bulk's mean is left out (its
/// contribution is far below the value's rounding).
const NEGLIGIBLE: f64 = 1.0 / (1u64 << 60) as f64;

/// The flattened tail's range in units of its exponential scale (`L'`), and the most its
/// exponent may be flattened (`(p+2)/(p'+2)`); see [`Bulk::flat_tail`]. A flatter tail
/// trades importance for smoothness in `u0`: `L' = 8` keeps the error bar of 4096
/// samples at normal incidence, p = 100, that of the unflattened tail; a longer tail
/// flattened without limit (mu = 0.5–0.7, p = 300) sends the points away from where the
/// weight is, and the limit keeps them there.
const TAIL_L: f64 = 8.0;
const TAIL_FLATTEST: f64 = 3.0;

/// A control's [`Control::rounding`], in units of `f64::EPSILON` times the magnitudes of
/// the closed form's terms: the closed forms are within a few ulps (the unit tests'
/// quadrature: 5e-15 of their scale), and the estimates of cells whose weights the
/// control makes constant scatter by a few ulps about the exact value.
const ROUNDING_ULPS: f64 = 16.0;

/// A control's [`Control::rounding`] for a closed form whose Schlick-excess terms have
/// magnitudes summing to `excess` and the rest to `other`, with `x5 = E[X^5]`. `X =
/// 1 − wi·h` comes from unit vectors as `|wi − h|²/2`, whose absolute error is about
/// `ε·|wi − h|`: a relative error of `sqrt(2)·ε/sqrt(X)`, five times that in `X^5`. For
/// sharp lobes near the normal (`X` about 1e-3) the weights and the control then differ
/// by far more than a few ulps (torrance_sparrow with R0 = 0 at mu = 0.997, p = 1000:
/// 70 ulps, `scripts/stderr_calibration.py`), so the excess's share is scaled by
/// `1 + 1/sqrt(X)` at the typical `X = E[X^5]^(1/5)`.
fn rounding(excess: f64, other: f64, x5: f64) -> f64 {
    let conditioning = 1.0 + 1.0 / x5.powf(0.2).sqrt();
    let conditioning = if conditioning.is_finite() {
        conditioning
    } else {
        1.0
    };
    ROUNDING_ULPS * f64::EPSILON * (excess * conditioning + other)
}

/// Polynomials in `t = 1 − cos θh` of degree below this.
const N: usize = 16;

/// A polynomial in `t`, coefficients from the constant term up.
#[derive(Clone, Copy, Debug)]
struct Poly([f64; N]);

impl Poly {
    const ZERO: Poly = Poly([0.0; N]);

    fn constant(v: f64) -> Poly {
        let mut p = Poly::ZERO;
        p.0[0] = v;
        p
    }

    fn mul(&self, other: &Poly) -> Poly {
        let mut out = Poly::ZERO;
        for (i, &a) in self.0.iter().enumerate() {
            if a == 0.0 {
                continue;
            }
            for (j, &b) in other.0.iter().enumerate().take(N - i) {
                out.0[i + j] += a * b;
            }
        }
        out
    }

    fn pow(&self, n: u32) -> Poly {
        (0..n).fold(Poly::constant(1.0), |acc, _| acc.mul(self))
    }

    fn add_scaled(&mut self, other: &Poly, s: f64) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a += s * b;
        }
    }
}

/// `E[cos^k φ]` over the circle: `(k−1)!!/k!!` for even `k`, 0 for odd.
fn cos_moment(k: u32) -> f64 {
    if k % 2 == 1 {
        return 0.0;
    }
    (1..k)
        .step_by(2)
        .fold(1.0, |r, i| r * i as f64 / (i + 1) as f64)
}

/// `C(n, k)`.
fn binomial(n: u32, k: u32) -> f64 {
    (0..k).fold(1.0, |r, i| r * (n - i) as f64 / (i + 1) as f64)
}

/// The bulk `θh ≤ θe` of a Blinn lobe (`cos θh ∈ [ce, 1]`) at incidence `mu`, and the
/// closed-form means over it.
#[derive(Clone, Copy, Debug)]
pub struct Bulk {
    mu: f64,
    /// `sin² θi`.
    s2: f64,
    p: f64,
    /// `cos θe` and `1 − cos θe`.
    pub ce: f64,
    te: f64,
    /// `cos^(p+2) θe`: the tail's probability, and the bulk's, `1 − q`.
    pub q: f64,
    bulk: f64,
    /// `cos θ` of the horizon edge `θ = (90° + θi)/2`, beyond which every `wo` is below
    /// the surface, and `1 − cos θ`.
    pub c_horizon: f64,
    t_horizon: f64,
    /// `cos θ` of `θ = (90° − θi)/2`, beyond which `wo` is below the surface for some
    /// azimuths (`h` tilted away from `wi`), where that lies strictly inside the tail
    /// (`θe < θ < (90° + θi)/2`): Torrance-Sparrow's edge away from the normal. `None`
    /// for Blinn-Phong's (the tail begins there) and at normal incidence (the two horizon
    /// edges meet at 45°).
    pub zeros_below: Option<f64>,
}

impl Bulk {
    /// The bulk of the Blinn lobe of exponent `p` at incidence `mu`, up to `θe` given as
    /// a function of `θi`; `None` where the split does not apply (`q ≥ SPLIT_BELOW`, or
    /// `mu` outside `(0, 1]`, or `p` not finite).
    pub fn new(mu: f64, p: f64, edge: impl Fn(f64) -> f64) -> Option<Bulk> {
        Bulk::with_edge(mu, p, edge).filter(|b| b.q < SPLIT_BELOW)
    }

    /// [`Bulk::new`] for any `q`.
    fn with_edge(mu: f64, p: f64, edge: impl Fn(f64) -> f64) -> Option<Bulk> {
        if !(mu > 0.0 && mu <= 1.0 && p.is_finite() && p >= 0.0) {
            return None;
        }
        let s2 = (1.0 - mu) * (1.0 + mu);
        let theta_i = s2.sqrt().atan2(mu);
        let theta_e = edge(theta_i);
        let ce = theta_e.cos();
        let half = (0.5 * theta_e).sin();
        let te = 2.0 * half * half;
        let ln_q = (p + 2.0) * (-te).ln_1p();
        let theta_h = 0.5 * (FRAC_PI_2 + theta_i);
        let half_h = (0.5 * theta_h).sin();
        let theta_z = 0.5 * (FRAC_PI_2 - theta_i);
        Some(Bulk {
            mu,
            s2,
            p,
            ce,
            te,
            q: ln_q.exp(),
            bulk: -ln_q.exp_m1(),
            c_horizon: theta_h.cos(),
            t_horizon: 2.0 * half_h * half_h,
            zeros_below: (theta_e < theta_z && theta_z < theta_h).then(|| theta_z.cos()),
        })
    }

    /// `∫_ce^1 t^k c^m dc = ∫_0^te t^k (1 − t)^m dt`, the incomplete beta function
    /// `B(te; k+1, m+1)`, in one of two forms with positive terms only:
    ///
    /// - where the bulk is narrow on the lobe's scale (`te·(m+k+2) ≤ 40`), its series
    ///   `te^a (1−te)^b / a · Σ_n (a+b)_n/(a+1)_n te^n` (`a = k+1`, `b = m+1`, rising
    ///   factorials; the ratio of terms falls to `te < 1`);
    /// - elsewhere the whole range's `B(k+1, m+1) = k!/((m+1)…(m+1+k))` less the tail's
    ///   `∫_0^ce`, expanded about `ce` (`c = ce(1 − r)`, `t = te + ce·r`):
    ///   `ce^(m+1) Σ_j C(k,j) te^(k−j) ce^j B(j+1, m+1)`. There `ce^(m+1) < e^−40`
    ///   relative, so the difference loses nothing.
    fn integral(&self, m: f64, k: usize) -> f64 {
        let (a, b) = (k as f64 + 1.0, m + 1.0);
        if self.te * (a + b) <= 40.0 {
            let x = self.te;
            let (mut term, mut sum, mut n) = (1.0, 1.0, 0.0);
            while term > 1e-17 * sum {
                term *= (a + b + n) / (a + 1.0 + n) * x;
                sum += term;
                n += 1.0;
            }
            return (a * x.ln() + b * (-x).ln_1p()).exp() / a * sum;
        }
        // r_j = j!/((m+1)(m+2)…(m+1+j)) = B(j+1, m+1).
        let mut r = [0.0; N];
        r[0] = 1.0 / b;
        for j in 1..=k {
            r[j] = r[j - 1] * j as f64 / (b + j as f64);
        }
        let below: f64 = (0..=k)
            .map(|j| {
                binomial(k as u32, j as u32)
                    * self.te.powi((k - j) as i32)
                    * self.ce.powi(j as i32)
                    * r[j]
            })
            .sum();
        let ce_pow = (b * (-self.te).ln_1p()).exp();
        r[k] - ce_pow * below
    }

    /// `E_φ[X^a·(B cos φ)^j]` over the azimuth, a polynomial in `t`, with
    /// `X = A − B cos φ`, `A = (1 − mu) + mu·t`, `B² = sin²θi·t(2 − t)`.
    fn azimuth_mean(&self, a: u32, j: u32) -> Poly {
        let mut big_a = Poly::ZERO;
        big_a.0[0] = 1.0 - self.mu;
        big_a.0[1] = self.mu;
        let mut b2 = Poly::ZERO;
        b2.0[1] = 2.0 * self.s2;
        b2.0[2] = -self.s2;
        let mut out = Poly::ZERO;
        // X^a (B cos)^j = Σ_i C(a,i) A^(a−i) (−1)^i B^(i+j) cos^(i+j) φ.
        for i in 0..=a {
            let k = i + j;
            if k % 2 == 1 {
                continue;
            }
            let term = big_a.pow(a - i).mul(&b2.pow(k / 2));
            let sign = if i % 2 == 1 { -1.0 } else { 1.0 };
            out.add_scaled(&term, sign * binomial(a, i) * cos_moment(k));
        }
        out
    }

    /// `E[X^a·(B cos φ)^j·c^e]` over the bulk under the Blinn density (`e ≥ −2`).
    pub fn expect(&self, a: u32, j: u32, e: i32) -> f64 {
        let mut poly = self.azimuth_mean(a, j);
        if e > 0 {
            let mut c = Poly::ZERO;
            c.0[0] = 1.0;
            c.0[1] = -1.0;
            poly = poly.mul(&c.pow(e as u32));
        }
        let m = self.p + 1.0 + f64::from(e.min(0));
        let sum: f64 = (0..N)
            .filter(|&k| poly.0[k] != 0.0)
            .map(|k| poly.0[k] * self.integral(m, k))
            .sum();
        (self.p + 2.0) / self.bulk * sum
    }

    /// `∫_0^x t^k c^m dc` for `x = cos θ` (`t_x = 1 − x`), expanded about `x` with
    /// positive terms only (`c = x(1 − r)`, `t = t_x + x·r`):
    /// `x^(m+1) Σ_j C(k,j) t_x^(k−j) x^j B(j+1, m+1)`.
    fn below(x: f64, t_x: f64, m: f64, k: usize) -> f64 {
        let b = m + 1.0;
        let mut r = 1.0 / b;
        let mut sum = 0.0;
        for j in 0..=k {
            if j > 0 {
                r *= j as f64 / (b + j as f64);
            }
            sum += binomial(k as u32, j as u32) * t_x.powi((k - j) as i32) * x.powi(j as i32) * r;
        }
        (b * (-t_x).ln_1p()).exp() * sum
    }

    /// `E[X^a·(B cos φ)^j·c^e]` over the tail (`cos θh` from `c_horizon` to `ce`) under
    /// the Blinn density of exponent `p_draw` (the lobe's, or the flatter one Sobol
    /// points draw the tail with), `e ≥ 0`. The tail's integral is the difference of
    /// [`Bulk::below`] at its two edges, the lower one smaller by about
    /// `(c_horizon/ce)^(p_draw+2)`.
    pub fn tail_expect(&self, p_draw: f64, a: u32, j: u32, e: u32) -> f64 {
        let mut poly = self.azimuth_mean(a, j);
        if e > 0 {
            let mut c = Poly::ZERO;
            c.0[0] = 1.0;
            c.0[1] = -1.0;
            poly = poly.mul(&c.pow(e));
        }
        let m = p_draw + 1.0;
        let (hi, lo) = ((self.ce, self.te), (self.c_horizon, self.t_horizon));
        let sum: f64 = (0..N)
            .filter(|&k| poly.0[k] != 0.0)
            .map(|k| poly.0[k] * (Bulk::below(hi.0, hi.1, m, k) - Bulk::below(lo.0, lo.1, m, k)))
            .sum();
        let mass = Bulk::below(hi.0, hi.1, m, 0) - Bulk::below(lo.0, lo.1, m, 0);
        sum / mass
    }

    /// A stratum term of the lobe at `basis`: the bulk (`cos θh ∈ [ce, 1]`, which stands
    /// for the whole lobe where strata do not apply) or the tail, with `control`, drawn
    /// with the exponent `p_sobol` for Sobol points.
    fn term(
        &self,
        colour: [f64; 3],
        basis: Slots,
        bulk: bool,
        control: Option<Control>,
        p_sobol: f64,
    ) -> Term {
        let (c_lo, c_hi, zeros_below) = if bulk {
            (self.ce, 1.0, None)
        } else {
            (self.c_horizon, self.ce, self.zeros_below)
        };
        Term {
            colour,
            integral: Integral::Stratum {
                lobe: StratumLobe::Blinn,
                basis,
                p: self.p,
                p_sobol,
                c_lo,
                c_hi,
                whole: bulk,
                control,
                zeros_below,
            },
        }
    }

    /// The strata of a lobe whose weight is at most `bound` in the tail and whose bulk
    /// has mean `bulk_mean`: the bulk with `control`, and the tail with `tail_control`
    /// unless empty or negligible, flattened for Sobol points if `flatten` ([`Bulk::flat_tail`]).
    /// `None` if neither the control nor the tail is needed (the plain lobe is the same).
    #[allow(clippy::too_many_arguments)]
    pub fn terms(
        &self,
        colour: [f64; 3],
        basis: Slots,
        control: Option<Control>,
        bound: f64,
        bulk_mean: f64,
        flatten: bool,
        tail_control: Option<Control>,
    ) -> Option<Vec<Term>> {
        // No tail where it is empty (Blinn-Phong at normal incidence: every wo of the
        // lobe is above the surface up to 45°, where the tail would start) or negligible.
        let tail = self.c_horizon < self.ce && !(bound * self.q <= NEGLIGIBLE * bulk_mean);
        if !tail && control.is_none() {
            return None;
        }
        let mut terms = vec![self.term(colour, basis, true, control, self.p)];
        if tail {
            let p_sobol = if flatten { self.flat_tail() } else { self.p };
            terms.push(self.term(colour, basis, false, tail_control, p_sobol));
        }
        Some(terms)
    }

    /// The exponent that draws the tail for Sobol points where the tail carries the
    /// cell's error (the bulk's weights nearly constant). Drawn with the lobe's own
    /// exponent, `s = (p+2)·ln(ce/c)` is exponentially distributed on `[0, L]`,
    /// `L = (p+2)·ln(ce/c_horizon)`, and `u0 ↦ s` has a logarithmic end: each replicate's
    /// last point lies in an exponential tail of `s` where the weight runs down to 0 at
    /// the horizon, whatever the number of points: that point dominates the replicate's
    /// error and skews the replicate means (at normal incidence, p = 100, about 3% of
    /// cells beyond 3 standard errors at 256 and at 4096 samples, against 0.9%). A flatter
    /// exponent, `L' = max(TAIL_L, L/TAIL_FLATTEST)`, makes the weights (which carry the
    /// ratio of the two densities) a smooth function of `u0` on the whole range.
    fn flat_tail(&self) -> f64 {
        let l = (self.p + 2.0) * (self.ce / self.c_horizon).ln();
        if !(l > TAIL_L) {
            return self.p;
        }
        (self.p + 2.0) * (TAIL_L / l).max(1.0 / TAIL_FLATTEST) - 2.0
    }
}

/// Torrance-Sparrow's bulk: `θh ≤ (90° − θi)/3`, where `G = 1` for every azimuth.
pub fn torrance_sparrow_bulk(mu: f64, p: f64) -> Option<Bulk> {
    Bulk::new(mu, p, |theta_i| (FRAC_PI_2 - theta_i) / 3.0)
}

/// Blinn-Phong's bulk: `θh ≤ (90° − θi)/2`, where `wo` is above the surface for every
/// azimuth.
pub fn blinn_phong_bulk(mu: f64, p: f64) -> Option<Bulk> {
    Bulk::new(mu, p, |theta_i| (FRAC_PI_2 - theta_i) / 2.0)
}

/// Torrance-Sparrow's specular lobe (basis `ks = 1`, `R0` from `eta`) at incidence `mu`
/// in strata, the bulk integrated exactly by its control; `None` where the plain lobe is
/// used.
///
/// In the bulk `G = 1`, so the weight is `F·J/mu` with `J = cos_b/c = mu + B cos φ/c`:
/// the control `C = F·J` (Schlick's `F` for `R0`) with `β = 1/mu` leaves the constant
/// `E[C]/mu`, `E[C] = R0·mu + (1 − R0)·E[X^5·J]` (`E[J] = mu`: `B cos φ` averages to 0).
pub fn torrance_sparrow_terms(
    colour: [f64; 3],
    basis: Slots,
    mu: f64,
    p: f64,
    r0: f64,
) -> Option<Vec<Term>> {
    if colour.iter().all(|&c| c == 0.0) {
        return None;
    }
    let bulk = torrance_sparrow_bulk(mu, p)?;
    // E[X^5·J] as the sum of its two parts, mu·E[X^5] and E[X^5·B cos φ/c].
    let excess = [mu * bulk.expect(5, 0, 0), bulk.expect(5, 1, -1)];
    let mean = r0 * mu + (1.0 - r0) * (excess[0] + excess[1]);
    let control = Control {
        beta: 1.0 / mu,
        mean,
        r0,
        over_cos: true,
        mu_o: false,
        rounding: rounding(
            (1.0 - r0) * (excess[0].abs() + excess[1].abs()),
            r0 * mu,
            bulk.expect(5, 0, 0),
        ),
    };
    // The bulk's mean weight; in the tail F ≤ 1 and G·cos_b/(mu·c) ≤ 2. The bulk's
    // weights are constant: the tail carries the cell's error, and Sobol points draw it
    // flatter.
    let bulk_mean = bulk.bulk * mean / mu;
    // At normal incidence the tail's weight is F·2·mu_o (G = 2·mu_o, every wo above the
    // surface up to the horizon edge): the control C = X^5·mu_o with β = 2(1 − R0)
    // removes its Schlick excess too, which otherwise grows 50× across the tail (X^5 from
    // θh = 30° to 45°).
    // Away from the normal it would not: there wo leaves the surface inside the tail for
    // some azimuths, where the weight is 0 and the control is not (a rare point then
    // carries a large residual).
    let tail_control = (mu == 1.0).then(|| {
        let parts = [
            2.0 * bulk.tail_expect(bulk.p, 5, 0, 2),
            2.0 * bulk.tail_expect(bulk.p, 5, 1, 1),
            -bulk.tail_expect(bulk.p, 5, 0, 0),
        ];
        Control {
            beta: 2.0 * (1.0 - r0),
            mean: parts.iter().sum(),
            r0: 0.0,
            over_cos: false,
            mu_o: true,
            rounding: rounding(
                parts.iter().map(|t| t.abs()).sum(),
                0.0,
                bulk.tail_expect(bulk.p, 5, 0, 0),
            ),
        }
    });
    bulk.terms(
        colour,
        basis,
        Some(control),
        2.0,
        bulk_mean,
        true,
        tail_control,
    )
}

/// Blinn-Phong-with-Fresnel's F0 = 0 lobe (Schlick's excess alone, basis `ks = 0`) at
/// incidence `mu` in strata, its bulk integrated exactly by the control; `None` where the
/// plain lobe is used.
pub fn blinn_phong_fresnel_terms(
    colour: [f64; 3],
    basis: Slots,
    mu: f64,
    p: f64,
) -> Option<Vec<Term>> {
    blinn_lobe_terms(colour, basis, mu, p, (p + 8.0) / (p + 2.0), true, false)
}

/// A Blinn-Phong lobe `f = A·cos^p θh` (for a unit colour at `basis`), drawn with Blinn
/// half vectors, at incidence `mu`, in strata with its bulk integrated exactly; `None`
/// where the plain lobe is used (`q ≥ SPLIT_BELOW`) or the colour is 0.
///
/// Its weight is `f·mu_o/pdf = β·C` with `β = A·8π/(p+2)` and `C = cos_b·mu_o/c`
/// wherever `wo` is above the surface, so in the bulk (every `wo` above) the control
/// `C` with its closed-form mean leaves the constant `β·E[C]`, and only the tail, where
/// the horizon cuts the lobe, is sampled. Drawn whole, the weight runs to its horizon
/// value along a logarithmic end of the sampler's first number, and Sobol replicates
/// of a few points are skewed by it (at normal incidence 2% of cells of 256 samples
/// beyond 3 standard errors, against 0.9%).
pub fn blinn_terms(colour: [f64; 3], basis: Slots, mu: f64, p: f64, a: f64) -> Option<Vec<Term>> {
    let beta = a * 8.0 * std::f64::consts::PI / (p + 2.0);
    blinn_lobe_terms(colour, basis, mu, p, beta, false, true)
}

/// A Blinn lobe whose weight is `β·C` in its bulk, `C = X^a·cos_b·mu_o/c` with `a = 5`
/// (Schlick's excess: `schlick`) or 0, in strata with its bulk integrated exactly by the
/// control `C` (closed-form mean); the tail drawn flatter for Sobol points if `flatten`.
fn blinn_lobe_terms(
    colour: [f64; 3],
    basis: Slots,
    mu: f64,
    p: f64,
    beta: f64,
    schlick: bool,
    flatten: bool,
) -> Option<Vec<Term>> {
    if colour.iter().all(|&c| c == 0.0) {
        return None;
    }
    let bulk = blinn_phong_bulk(mu, p)?;
    let a = if schlick { 5 } else { 0 };
    // C = X^a·cos_b·mu_o/c = 2·X^a·cos_b² − mu·X^a·cos_b/c, cos_b = mu·c + B cos φ (for
    // a = 0 the terms odd in cos φ are exactly 0).
    let terms = [
        2.0 * mu * mu * bulk.expect(a, 0, 2),
        4.0 * mu * bulk.expect(a, 1, 1),
        2.0 * bulk.expect(a, 2, 0),
        -mu * mu * bulk.expect(a, 0, 0),
        -mu * bulk.expect(a, 1, -1),
    ];
    let e_c: f64 = terms.iter().sum();
    let magnitude = terms.iter().map(|t| t.abs()).sum();
    let control = Control {
        beta,
        mean: e_c,
        r0: if schlick { 0.0 } else { 1.0 },
        over_cos: true,
        mu_o: true,
        rounding: if schlick {
            rounding(magnitude, 0.0, bulk.expect(5, 0, 0))
        } else {
            rounding(0.0, magnitude, 1.0)
        },
    };
    // In the tail X^a ≤ 1 and cos_b·mu_o/c ≤ 2·cos_b² ≤ 2.
    let bulk_mean = bulk.bulk * beta * e_c;
    bulk.terms(
        colour,
        basis,
        Some(control),
        2.0 * beta,
        bulk_mean,
        flatten,
        None,
    )
}

/// A Phong lobe `f = A·cos^p α` about the mirror direction (for a unit colour at
/// `basis`), drawn from its own density, at incidence `mu`, in strata with its bulk
/// integrated exactly; `None` where the plain lobe is used or the colour is 0.
///
/// The weight is `f·mu_o/pdf = β·mu_o`, `β = A·2π/(p+1)`, wherever `wo` is above the
/// surface: in the bulk `α ≤ 90° − θi` (every `wo` above) the control `C = mu_o`, whose
/// mean is `mu·E[cos α]` (the rest of `mu_o` is odd in the azimuth) with
/// `E[cos α] = (p+1)/(p+2)·(1 − ce^(p+2))/(1 − ce^(p+1))` over `cos α ≥ ce = sin θi`,
/// leaves the constant `β·E[C]`. The tail `α > 90° − θi` (probability `q = ce^(p+1)`),
/// where the horizon cuts the lobe, is sampled; its far end `α → 90°` is a logarithmic
/// end of the sampler's first number, so Sobol points draw it flatter (`cos^(p'+1) α`
/// uniform, `p' + 1 = (p+1)/TAIL_FLATTEST`), which makes the weights vanish smoothly
/// there. Drawn whole, Sobol replicates of a few points are skewed by that end (at
/// normal incidence 2.4% of cells of 256 samples beyond 3 standard errors, 2.7% of
/// cells of 4096, against 0.9%).
pub fn phong_terms(colour: [f64; 3], basis: Slots, mu: f64, p: f64, a: f64) -> Option<Vec<Term>> {
    if colour.iter().all(|&c| c == 0.0) || !(mu > 0.0 && mu <= 1.0 && p.is_finite() && p >= 0.0) {
        return None;
    }
    let ce = ((1.0 - mu) * (1.0 + mu)).sqrt();
    let ln_ce = ce.ln();
    let q = ((p + 1.0) * ln_ce).exp();
    if !(q < SPLIT_BELOW) {
        return None;
    }
    // 1 − ce^k without cancellation (ce = 0 at normal incidence: 1).
    let one_minus = |k: f64| -(k * ln_ce).exp_m1();
    let mean_cos = (p + 1.0) / (p + 2.0) * one_minus(p + 2.0) / one_minus(p + 1.0);
    let beta = a * 2.0 * std::f64::consts::PI / (p + 1.0);
    let e_c = mu * mean_cos;
    let control = Control {
        beta,
        mean: e_c,
        r0: 1.0,
        over_cos: false,
        mu_o: true,
        rounding: rounding(0.0, e_c, 1.0),
    };
    let stratum = |c_lo: f64, c_hi: f64, whole: bool, p_sobol: f64, control| Term {
        colour,
        integral: Integral::Stratum {
            lobe: StratumLobe::Phong,
            basis,
            p,
            p_sobol,
            c_lo,
            c_hi,
            whole,
            control,
            // The tail α > 90° − θi begins where wo first leaves the surface.
            zeros_below: None,
        },
    };
    let mut terms = vec![stratum(ce, 1.0, true, p, Some(control))];
    // The tail's weight is at most β (mu_o ≤ 1); left out where negligible.
    let bulk_mean = one_minus(p + 1.0) * beta * e_c;
    if q > 0.0 && !(beta * q <= NEGLIGIBLE * bulk_mean) {
        let p_sobol = (p + 1.0) / TAIL_FLATTEST - 1.0;
        terms.push(stratum(0.0, ce, false, p_sobol, None));
    }
    Some(terms)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// `∫ g(c, φ)` over the bulk under the normalized Blinn density, by Gauss-Legendre
    /// panels in `s = (p+2)·ln(1/c)` on `[0, (p+2)·ln(1/ce)]` (the density is `e^(−s)`
    /// there, up to normalization; panels of width doubling from 1/4, each cut in 8),
    /// and midpoints in `φ`.
    fn quadrature(b: &Bulk, g: impl Fn(f64, f64, f64) -> f64) -> f64 {
        let (x, w) = gauss_legendre_16();
        let s_max = -(b.p + 2.0) * (-b.te).ln_1p();
        let mut edges = vec![0.0];
        let mut e = 0.25;
        while e < s_max {
            edges.push(e);
            e *= 2.0;
        }
        edges.push(s_max);
        let mut sum = 0.0;
        for pair in edges.windows(2) {
            for k in 0..8 {
                let s0 = pair[0] + (pair[1] - pair[0]) * k as f64 / 8.0;
                let s1 = pair[0] + (pair[1] - pair[0]) * (k + 1) as f64 / 8.0;
                for (xs, ws) in x.iter().zip(w) {
                    let s = 0.5 * (s0 + s1) + 0.5 * (s1 - s0) * xs;
                    // c = cos θh and t = 1 − c, accurately (t is tiny for wide bulks).
                    let t = -(-s / (b.p + 2.0)).exp_m1();
                    let c = 1.0 - t;
                    // Midpoints in φ: exact for the trigonometric polynomials here
                    // (even in φ, of degree below 64).
                    let inner: f64 = (0..32)
                        .map(|k| g(c, t, PI * (k as f64 + 0.5) / 32.0))
                        .sum::<f64>()
                        / 32.0;
                    sum += 0.5 * (s1 - s0) * ws * (-s).exp() * inner;
                }
            }
        }
        sum / b.bulk
    }

    fn gauss_legendre_16() -> ([f64; 16], [f64; 16]) {
        // Nodes by Newton's method on P_16.
        let n = 16;
        let mut x = [0.0; 16];
        let mut w = [0.0; 16];
        for i in 0..n {
            let mut z = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, z);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                let dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
                let dz = p1 / dp;
                z -= dz;
                if dz.abs() < 1e-16 {
                    let dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
                    x[i] = z;
                    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
                    break;
                }
            }
        }
        (x, w)
    }

    /// The closed-form means over the bulk against quadrature, over p from 0 to 1e4 and mu
    /// from 0.01 to 1, for the Torrance-Sparrow edge, relative to the integrand's scale
    /// (the mean of its magnitude).
    #[test]
    fn bulk_means_match_quadrature() {
        for mu in [1.0, 0.999, 0.97, 0.9, 0.7, 0.5, 0.2, 0.05, 0.01] {
            for p in [0.0, 1.0, 5.0, 20.0, 100.0, 1e3, 1e4] {
                let b = Bulk::with_edge(mu, p, |ti| (FRAC_PI_2 - ti) / 3.0).unwrap();
                let s = (1.0 - mu) * (1.0 + mu);
                for (a, j, e) in [
                    (5, 0, 0),
                    (5, 1, -1),
                    (5, 2, -2),
                    (5, 0, 2),
                    (5, 1, 1),
                    (5, 2, 0),
                    (0, 2, -2),
                ] {
                    let g = |c: f64, t: f64, phi: f64| {
                        let bcos = (s * t * (2.0 - t)).sqrt() * phi.cos();
                        let x = 1.0 - mu * c - bcos;
                        x.powi(a as i32) * bcos.powi(j as i32) * c.powi(e)
                    };
                    let want = quadrature(&b, g);
                    let scale = quadrature(&b, |c, t, phi| g(c, t, phi).abs());
                    let got = b.expect(a, j, e);
                    // Measured: at most 5e-15 of the scale.
                    assert!(
                        (got - want).abs() <= 1e-14 * scale,
                        "mu={mu} p={p} ({a},{j},{e}): {got} vs {want} (scale {scale})"
                    );
                }
            }
        }
    }

    /// The tail's means against quadrature in `s = (p_draw+2)·ln(ce/c)` (density
    /// `e^(−s)` on `[0, L]`) and midpoints in `φ`.
    #[test]
    fn tail_means_match_quadrature() {
        let (x, w) = gauss_legendre_16();
        for mu in [1.0, 0.999, 0.9, 0.5] {
            for p in [20.0, 100.0, 1e3] {
                let Some(b) = torrance_sparrow_bulk(mu, p) else {
                    continue;
                };
                let s2 = (1.0 - mu) * (1.0 + mu);
                for p_draw in [p, 0.4 * p] {
                    let l = (p_draw + 2.0) * (b.ce / b.c_horizon).ln();
                    for (a, j, e) in [(5, 0, 0), (5, 0, 2), (5, 1, 1), (0, 0, 0)] {
                        let g = |c: f64, phi: f64| {
                            let bcos = (s2 * (1.0 - c * c)).sqrt() * phi.cos();
                            let xx = 1.0 - mu * c - bcos;
                            xx.powi(a as i32) * bcos.powi(j as i32) * c.powi(e as i32)
                        };
                        let (mut num, mut den, mut abs) = (0.0, 0.0, 0.0);
                        let panels = 256;
                        for i in 0..panels {
                            let (s0, s1) = (
                                l * i as f64 / panels as f64,
                                l * (i + 1) as f64 / panels as f64,
                            );
                            for (xs, ws) in x.iter().zip(w) {
                                let sv = 0.5 * (s0 + s1) + 0.5 * (s1 - s0) * xs;
                                let c = b.ce * (-sv / (p_draw + 2.0)).exp();
                                let d = 0.5 * (s1 - s0) * ws * (-sv).exp();
                                let inner: f64 = (0..32)
                                    .map(|k| g(c, PI * (k as f64 + 0.5) / 32.0))
                                    .sum::<f64>()
                                    / 32.0;
                                num += d * inner;
                                abs += d * inner.abs();
                                den += d;
                            }
                        }
                        let (want, scale) = (num / den, abs / den);
                        let got = b.tail_expect(p_draw, a, j, e);
                        assert!(
                            (got - want).abs() <= 1e-12 * scale,
                            "mu={mu} p={p} p_draw={p_draw} ({a},{j},{e}): {got} vs {want}"
                        );
                    }
                }
            }
        }
    }

    /// The controls' means are those of their defining `C` over the bulk, and the
    /// strata apply where they should.
    #[test]
    fn controls_and_strata() {
        let basis = [0.0; crate::models::slots::MAX_VARYING_SLOTS];
        let grey = [1.0; 3];
        let stratum = |t: &Term| match t.integral {
            Integral::Stratum {
                p,
                p_sobol,
                c_lo,
                c_hi,
                whole,
                control,
                ..
            } => (p, p_sobol, c_lo, c_hi, whole, control),
            _ => panic!("{t:?}"),
        };
        for mu in [1.0, 0.999, 0.99, 0.9, 0.7, 0.5] {
            for p in [20.0, 100.0, 1000.0] {
                let s2 = (1.0 - mu) * (1.0 + mu);
                let cos_b =
                    |c: f64, t: f64, phi: f64| mu * c + (s2 * t * (2.0 - t)).sqrt() * phi.cos();
                if let Some(terms) = torrance_sparrow_terms(grey, basis, mu, p, 0.0) {
                    let b = torrance_sparrow_bulk(mu, p).unwrap();
                    let (_, _, c_lo, c_hi, whole, control) = stratum(&terms[0]);
                    assert!(whole && c_lo == b.ce && c_hi == 1.0);
                    // R0 = 0: the control is Schlick's excess times J = cos_b/c.
                    let k = control.unwrap();
                    assert_eq!((k.beta, k.r0), (1.0 / mu, 0.0));
                    let want = quadrature(&b, |c, t, phi| {
                        let cb = cos_b(c, t, phi);
                        (1.0 - cb).powi(5) * cb / c
                    });
                    assert!(
                        (k.mean - want).abs() <= 1e-13 * want,
                        "{mu} {p}: {k:?} {want}"
                    );
                    // R0 = 0.04: Schlick's F times J, the whole weight of the bulk.
                    let terms = torrance_sparrow_terms(grey, basis, mu, p, 0.04).unwrap();
                    let k = stratum(&terms[0]).5.unwrap();
                    assert_eq!((k.beta, k.r0), (1.0 / mu, 0.04));
                    let want = quadrature(&b, |c, t, phi| {
                        let cb = cos_b(c, t, phi);
                        (0.04 + 0.96 * (1.0 - cb).powi(5)) * cb / c
                    });
                    assert!(
                        (k.mean - want).abs() <= 1e-13 * want,
                        "{mu} {p}: {k:?} {want}"
                    );
                }
                if let Some(terms) = blinn_terms(grey, basis, mu, p, 2.0) {
                    let b = blinn_phong_bulk(mu, p).unwrap();
                    let k = stratum(&terms[0]).5.unwrap();
                    assert_eq!((k.beta, k.r0), (2.0 * 8.0 * PI / (p + 2.0), 1.0));
                    let want = quadrature(&b, |c, t, phi| {
                        let cb = cos_b(c, t, phi);
                        cb * (2.0 * cb * c - mu) / c
                    });
                    assert!(
                        (k.mean - want).abs() <= 1e-13 * want,
                        "{mu} {p}: {k:?} {want}"
                    );
                }
                if let Some(terms) = phong_terms(grey, basis, mu, p, 2.0) {
                    // E[mu_o] = mu·E[cos α] over cos α ≥ sin θi under the density
                    // ∝ cos^p α in c = cos α, by the midpoint rule in c.
                    let k = stratum(&terms[0]).5.unwrap();
                    assert_eq!(k.beta, 2.0 * 2.0 * PI / (p + 1.0));
                    let ce = ((1.0 - mu) * (1.0 + mu)).sqrt();
                    let n = 200_000;
                    let (num, den) = (0..n)
                        .map(|i| ce + (1.0 - ce) * (i as f64 + 0.5) / n as f64)
                        .fold((0.0, 0.0), |(a, b), c| (a + c.powf(p + 1.0), b + c.powf(p)));
                    let want = mu * num / den;
                    assert!(
                        (k.mean - want).abs() <= 1e-8 * want,
                        "{mu} {p}: {k:?} {want}"
                    );
                }
                if let Some(terms) = blinn_phong_fresnel_terms(grey, basis, mu, p) {
                    let b = blinn_phong_bulk(mu, p).unwrap();
                    let k = stratum(&terms[0]).5.unwrap();
                    assert_eq!(k.beta, (p + 8.0) / (p + 2.0));
                    let want = quadrature(&b, |c, t, phi| {
                        let cb = cos_b(c, t, phi);
                        (1.0 - cb).powi(5) * cb * (2.0 * cb * c - mu) / c
                    });
                    assert!(
                        (k.mean - want).abs() <= 1e-13 * want,
                        "{mu} {p}: {k:?} {want}"
                    );
                }
            }
        }
        let ts = |mu, p, r0| torrance_sparrow_terms(grey, basis, mu, p, r0);
        // Normal incidence, p = 100: bulk and tail with controls, the tail flattened for
        // Sobol points; the tail's control is the mean of X^5·mu_o over the tail.
        let terms = ts(1.0, 100.0, 0.04).unwrap();
        assert_eq!(terms.len(), 2);
        assert!(stratum(&terms[0]).5.is_some());
        let (p, p_sobol, c_lo, c_hi, whole, control) = stratum(&terms[1]);
        assert!(!whole && p_sobol < p);
        let k = control.unwrap();
        assert_eq!((k.beta, k.over_cos, k.mu_o), (2.0 * 0.96, false, true));
        let b = torrance_sparrow_bulk(1.0, 100.0).unwrap();
        let want = b.tail_expect(100.0, 5, 0, 2) * 2.0 - b.tail_expect(100.0, 5, 0, 0);
        assert!((k.mean - want).abs() <= 1e-15 * want, "{k:?} {want}");
        // Away from the normal the tail has no control.
        assert!(stratum(&ts(0.999, 100.0, 0.04).unwrap()[1]).5.is_none());
        assert!((c_lo - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
        assert!((c_hi - 0.75_f64.sqrt()).abs() < 1e-15);
        // p = 1000: the tail (probability 6e-63) is left out.
        assert_eq!(ts(1.0, 1000.0, 0.04).unwrap().len(), 1);
        // Away from the normal too the bulk is exact and the tail drawn flatter.
        let terms = ts(0.7, 100.0, 0.04).unwrap();
        assert!(stratum(&terms[0]).5.is_some());
        assert!(stratum(&terms[1]).1 < 100.0);
        // Wide lobes: the plain lobe.
        assert!(ts(0.7, 10.0, 0.04).is_none());
        // A sharp lobe away from the normal: the tail is negligible, the bulk exact.
        let terms = ts(0.9, 1000.0, 0.04).unwrap();
        assert!(terms.len() == 1 && stratum(&terms[0]).5.is_some());
        // Blinn-Phong at normal incidence: the bulk is the whole lobe (no empty tail).
        let bpf = blinn_phong_fresnel_terms(grey, basis, 1.0, 100.0).unwrap();
        assert_eq!(bpf.len(), 1);
        assert_eq!(
            blinn_phong_fresnel_terms(grey, basis, 0.9, 100.0)
                .unwrap()
                .len(),
            2
        );
        // A zero colour: nothing to split.
        assert!(torrance_sparrow_terms([0.0; 3], basis, 1.0, 100.0, 0.04).is_none());
    }
}
