//! Fresnel terms other than Schlick's for the microfacet lobes (docs/models.md:
//! `ggx_conductor`, `beckmann_conductor`, `ggx_f82`, `beckmann_f82`, `ggx_gen_schlick`,
//! `beckmann_gen_schlick`): each a function of `cos_b = wi·h` given as a
//! [`Cosine`] (the cosine with its accurate complement), per colour channel, with its
//! constants prepared once per parameter set.

use super::spec::ValidRange;
use crate::math::geometry::{Cosine, schlick_weight};
use crate::math::{PowUnit, Real, Vector3, max};

/// The range of a conductor's `eta` and `k` (`k` from 0): wide enough for every measured
/// metal, and narrow enough that every square and quotient of [`conductor`] stays a
/// normal `f32` number (`|η̃|⁴` up to 1e28).
pub const INDEX_RANGE: ValidRange = ValidRange {
    min: 1e-7,
    max: 1e7,
    min_open: false,
    max_open: false,
};

/// `k`'s range: [`INDEX_RANGE`] down to 0 (a dielectric).
pub const EXTINCTION_RANGE: ValidRange = ValidRange {
    min: 0.0,
    ..INDEX_RANGE
};

/// One channel of the conductor Fresnel term, prepared from `η̃ = eta + i·k`: the
/// components of `e = η̃² − 1`, its squared modulus, `Re η̃² = eta² − k²` and `eta²`.
#[derive(Clone, Copy, Debug)]
pub struct Conductor<F> {
    e_re: F,
    e_im: F,
    e2: F,
    eta2_re: F,
    eta2: F,
}

impl<F: Real> Conductor<F> {
    /// The channel of relative index `eta + i·k`. `eta² − 1` is formed as
    /// `(eta − 1)(eta + 1)`, exact to a rounding or two near `eta = 1` (where the whole
    /// value is of the order of `(eta − 1)²`).
    #[inline(always)]
    pub fn new(eta: F, k: F) -> Self {
        let e_re = (eta - F::ONE) * (eta + F::ONE) - k * k;
        let e_im = F::TWO * eta * k;
        Conductor {
            e_re,
            e_im,
            e2: e_re * e_re + e_im * e_im,
            eta2_re: eta * eta - k * k,
            eta2: eta * eta,
        }
    }

    /// The channel of a dielectric (`k = 0`) of relative index `eta` given `eta²` and
    /// `e = eta² − 1`, for a caller that forms them more accurately than
    /// [`Conductor::new`] can from a rounded `eta` (the rough dielectrics' `1/eta`, whose
    /// `e = (1 − eta)(1 + eta)/eta²` near `eta = 1` would otherwise keep only the digits
    /// of `1/eta`'s rounding). With `eta2 = eta·eta` and `e = (eta − 1)(eta + 1)` it is
    /// `Conductor::new(eta, 0)`, bit for bit.
    #[inline(always)]
    pub fn dielectric(eta2: F, e: F) -> Self {
        Conductor {
            e_re: e,
            e_im: F::ZERO,
            e2: e * e,
            eta2_re: eta2,
            eta2,
        }
    }

    /// Returns `a` where `first`, else `b`, field by field (a branch-free select: the
    /// rough dielectrics pick the channel of the side `wi` lies on).
    #[inline(always)]
    pub fn select(first: bool, a: &Self, b: &Self) -> Self {
        let pick = |x: F, y: F| if first { x } else { y };
        Conductor {
            e_re: pick(a.e_re, b.e_re),
            e_im: pick(a.e_im, b.e_im),
            e2: pick(a.e2, b.e2),
            eta2_re: pick(a.eta2_re, b.eta2_re),
            eta2: pick(a.eta2, b.eta2),
        }
    }
}

/// Returns the principal square root `(re, im)` of `x + i·y` for `y ≥ 0` (so `re, im ≥ 0`)
/// and the modulus `|x + i·y|`: the root of the larger of `(|z| ± x)/2` taken directly and
/// the other part as `y/(2·root)`, so neither cancels; 0 for `z = 0`.
#[inline(always)]
fn complex_sqrt<F: Real>(x: F, y: F) -> (F, F, F) {
    let modulus = F::length(F::V3::new(x, y, F::ZERO));
    let root = ((modulus + x.abs()) * F::HALF).sqrt();
    let other = if root > F::ZERO {
        y / (F::TWO * root)
    } else {
        F::ZERO
    };
    if x >= F::ZERO {
        (root, other, modulus)
    } else {
        (other, root, modulus)
    }
}

/// Returns the unpolarized Fresnel reflectance `(|r_s|² + |r_p|²)/2` of a conductor with
/// relative index `η̃ = eta + i·k` at `μ = cos_b` (pbrt-v4's `FrComplex`), in a form that
/// neither cancels nor leaves the `f32` range.
///
/// With `w = η̃·cos θt = sqrt(η̃² − s²)` (principal root, `s² = 1 − μ²`), the
/// reflectances are `r_s = (μ − w)/(μ + w)` and `r_p = (η̃²μ − w)/(η̃²μ + w)`, and
/// `|r_p|² = |r_s|²·|μw − s²|²/|μw + s²|²` (Lagarde's form of the conductor equations, as
/// pbrt's `FrConductor`), so
///
/// `F = |r_s|²·(μ²|w|² + s⁴)/|μw + s²|²`.
///
/// `r_s`'s numerator cancels as `η̃ → 1`; with `e = η̃² − 1` (exact to a rounding or two,
/// [`Conductor::new`]) and `w² = e + μ²`, `μ − w = −e/(μ + w)`, so
/// `|r_s|² = |e|²/|μ + w|⁴`. Every other sum adds terms of one sign (`Re w, Im w ≥ 0`),
/// `|w|²` is the modulus of `w²`, and the largest intermediate is `|e|² ≈ |η̃|⁴` (1e28 for
/// `eta`, `k` in [`INDEX_RANGE`]). `e = 0` (`η̃ = 1`, no interface) gives 0 at every `μ`.
///
/// `μ = 1` gives `|η̃ − 1|²/|η̃ + 1|²`; `μ → 0` gives 1 (unless `η̃ = 1`); `k = 0` is the
/// exact dielectric reflectance for every `eta`: below 1, past the critical angle
/// (`w² < 0`, `w` imaginary) both moduli are exactly 1 in exact arithmetic, total internal
/// reflection (the rough dielectrics' Fresnel term).
#[inline(always)]
pub fn conductor<F: Real>(ch: &Conductor<F>, cos_b: Cosine<F>) -> F {
    let mu = cos_b.cos;
    let mu2 = mu * mu;
    let s2 = cos_b.one_minus * (F::ONE + mu);
    // Re w² = eta² − k² − 1 + μ², summed where its rounding is smallest: as
    // `(eta² − 1 − k²) + μ²` (error ~ u·(|eta² − 1| + k² + μ²)) where μ < eta, else as
    // `(eta² − k²) − s²` (error ~ u·(eta² + k² + s²)); the first keeps `eta ≈ 1` at grazing
    // `μ`, the second a small `eta` near normal incidence (Re w² = eta² at μ = 1).
    let w2_re = if mu2 < ch.eta2 {
        ch.e_re + mu2
    } else {
        ch.eta2_re - s2
    };
    let (w_re, w_im, w_abs2) = complex_sqrt(w2_re, ch.e_im);
    let a_re = mu + w_re;
    let a = a_re * a_re + w_im * w_im;
    let r_s2 = (ch.e2 / a) / a;
    let d_re = mu * w_re + s2;
    let d_im = mu * w_im;
    let f = r_s2 * ((mu2 * w_abs2 + s2 * s2) / (d_re * d_re + d_im * d_im));
    if ch.e2 > F::ZERO { f } else { F::ZERO }
}

/// `μ̄(1 − μ̄)^6` at `μ̄ = 1/7` is `6^6/7^7`: its reciprocal, and Schlick's weight there over
/// it, `(6/7)^5·7^7/6^6 = 49/6`.
const F82_SCALE_F0: f64 = 823_543.0 / 46_656.0;
const F82_SCALE_EXCESS: f64 = 49.0 / 6.0;

/// One channel of the F82-tint Fresnel term: `f0`, `1 − f0` and the coefficient
/// `a = (1 − f82)·Schlick(f0, 1/7)/(μ̄(1 − μ̄)^6)`, `μ̄ = 1/7`.
#[derive(Clone, Copy, Debug)]
pub struct F82<F> {
    f0: F,
    one_minus_f0: F,
    a: F,
}

impl<F: Real> F82<F> {
    /// The channel of normal-incidence reflectance `f0` and tint `f82`:
    /// `a = (1 − f82)·(f0·7^7/6^6 + (1 − f0)·49/6)`.
    #[inline(always)]
    pub fn new(f0: F, f82: F) -> Self {
        let one_minus_f0 = F::ONE - f0;
        let schlick_over =
            f0 * F::from_f64(F82_SCALE_F0) + one_minus_f0 * F::from_f64(F82_SCALE_EXCESS);
        F82 {
            f0,
            one_minus_f0,
            a: (F::ONE - f82) * schlick_over,
        }
    }
}

/// Returns the F82-tint Fresnel term (Kutz et al. 2021; Hoffman 2023; OpenPBR's metal, as
/// MaterialX's `mx_fresnel_hoffman_schlick` with `F90 = 1`, exponent 5) at `μ = cos_b`:
///
/// `F = max(0, Schlick(f0, μ) − a·μ·(1 − μ)^6) = max(0, f0 + x^5·((1 − f0) − a·μ·x))`,
/// `x = 1 − μ` (the accurate complement), with `a` from [`F82::new`], so that
/// `F(1/7) = f82·Schlick(f0, 1/7)`. `f0 = f82 = 1` gives exactly 1.
#[inline(always)]
pub fn f82<F: Real>(ch: &F82<F>, cos_b: Cosine<F>) -> F {
    let x5 = schlick_weight(cos_b);
    let f = ch.f0 + x5 * (ch.one_minus_f0 - ch.a * cos_b.cos * cos_b.one_minus);
    max(f, F::ZERO)
}

/// One channel of the generalized Schlick term: `f0` and `f90 − f0`.
#[derive(Clone, Copy, Debug)]
pub struct GenSchlick<F> {
    f0: F,
    rise: F,
}

impl<F: Real> GenSchlick<F> {
    #[inline(always)]
    pub fn new(f0: F, f90: F) -> Self {
        GenSchlick { f0, rise: f90 - f0 }
    }

    /// Returns `f0 + (f90 − f0)·w`, the term at the weight `w` ([`gen_schlick_weight`]).
    #[inline(always)]
    pub fn blend(&self, w: F) -> F {
        self.f0 + self.rise * w
    }
}

/// Returns the generalized Schlick term of MaterialX (`mx_fresnel_schlick(cosTheta, F0,
/// F90, exponent)`, `mix(F0, F90, pow(1 − cosTheta, exponent))`) at `μ = cos_b`:
/// `F = f0 + (f90 − f0)·(1 − μ)^exponent`, the power of the accurate complement through `P`.
/// `f0 = f90 = 1` gives exactly 1.
#[inline(always)]
pub fn gen_schlick<F: Real, P: PowUnit>(ch: &GenSchlick<F>, cos_b: Cosine<F>, exponent: F) -> F {
    ch.blend(gen_schlick_weight::<F, P>(cos_b, exponent))
}

/// The generalized Schlick weight `(1 − μ)^exponent` at `μ = cos_b`, through `P`: shared
/// by the channels of one exponent ([`GenSchlick::blend`]).
#[inline(always)]
pub fn gen_schlick_weight<F: Real, P: PowUnit>(cos_b: Cosine<F>, exponent: F) -> F {
    P::pow_unit(cos_b.one_minus, cos_b.cos, exponent)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cosine(mu: f64) -> Cosine<f64> {
        Cosine {
            cos: mu,
            one_minus: 1.0 - mu,
        }
    }

    /// pbrt-v4's `FrDielectric` for `eta > 1` seen from outside: an independent form.
    fn dielectric(mu: f64, eta: f64) -> f64 {
        let sin2_t = (1.0 - mu * mu) / (eta * eta);
        let cos_t = (1.0 - sin2_t).sqrt();
        let r_parl = (eta * mu - cos_t) / (eta * mu + cos_t);
        let r_perp = (mu - eta * cos_t) / (mu + eta * cos_t);
        (r_parl * r_parl + r_perp * r_perp) / 2.0
    }

    /// pbrt-v4's `FrComplex` as written, in `f64` complex arithmetic (written out): the
    /// value to compare with where it does not cancel.
    fn fr_complex(mu: f64, eta: f64, k: f64) -> f64 {
        type C = (f64, f64);
        let mul = |a: C, b: C| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let div = |a: C, b: C| {
            let d = b.0 * b.0 + b.1 * b.1;
            ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let norm = |a: C| a.0 * a.0 + a.1 * a.1;
        let eta_c = (eta, k);
        let sin2_t = div((1.0 - mu * mu, 0.0), mul(eta_c, eta_c));
        let z = (1.0 - sin2_t.0, -sin2_t.1);
        let r = (z.0 * z.0 + z.1 * z.1).sqrt();
        let re = ((r + z.0) / 2.0).sqrt();
        let im = ((r - z.0) / 2.0).sqrt().copysign(z.1);
        let cos_t = (re, im);
        let e_mu = (eta * mu, k * mu);
        let r_parl = div(
            (e_mu.0 - cos_t.0, e_mu.1 - cos_t.1),
            (e_mu.0 + cos_t.0, e_mu.1 + cos_t.1),
        );
        let e_cos = mul(eta_c, cos_t);
        let r_perp = div((mu - e_cos.0, -e_cos.1), (mu + e_cos.0, e_cos.1));
        (norm(r_parl) + norm(r_perp)) / 2.0
    }

    #[test]
    fn k_zero_is_the_dielectric_reflectance() {
        for eta in [1.05, 1.33, 1.5, 2.4, 10.0] {
            for i in 0..=200 {
                let mu = f64::from(i) / 200.0;
                let got = conductor(&Conductor::new(eta, 0.0), cosine(mu));
                let want = dielectric(mu, eta);
                assert!(
                    (got - want).abs() <= 1e-13 * want,
                    "eta={eta} mu={mu}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn k_zero_below_one_is_the_dielectric_reflectance_with_total_internal_reflection() {
        for eta in [1.0 / 1.5, 1.0 / 1.05, 0.1] {
            for i in 0..=200 {
                let mu = f64::from(i) / 200.0;
                let got = conductor(&Conductor::new(eta, 0.0), cosine(mu));
                let sin2_t = (1.0 - mu * mu) / (eta * eta);
                if sin2_t >= 1.0 + 1e-12 {
                    assert!((got - 1.0).abs() <= 1e-14, "eta={eta} mu={mu}: {got}");
                } else if sin2_t < 1.0 - 1e-9 {
                    let want = dielectric(mu, eta);
                    assert!(
                        (got - want).abs() <= 1e-12 * want.max(1e-3),
                        "eta={eta} mu={mu}: {got} vs {want}"
                    );
                }
            }
        }
        // eta = 1: no interface.
        assert_eq!(conductor(&Conductor::new(1.0, 0.0), cosine(0.3)), 0.0);
    }

    #[test]
    fn matches_fr_complex_for_metals() {
        // (eta, k) of gold, silver, aluminium-like and extreme channels.
        let metals = [
            (0.18, 3.4),
            (0.05, 4.2),
            (1.2, 7.0),
            (3.0, 3.0),
            (0.5, 0.01),
        ];
        for (eta, k) in metals {
            for i in 0..=200 {
                let mu = f64::from(i) / 200.0;
                let got = conductor(&Conductor::new(eta, k), cosine(mu));
                let want = fr_complex(mu, eta, k);
                assert!(
                    (got - want).abs() <= 1e-12 * want,
                    "eta={eta} k={k} mu={mu}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn normal_incidence_grazing_and_no_interface() {
        for (eta, k) in [
            (0.18, 3.4),
            (1.5, 0.0),
            (1e7, 1e7),
            (1e-7, 0.0),
            (1e-7, 1e7),
        ] {
            let at_normal = conductor(&Conductor::new(eta, k), cosine(1.0));
            let want = ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k);
            assert!((at_normal - want).abs() <= 1e-14 * want, "{eta} {k}");
            // μ → 0: every interface reflects everything.
            let grazing = conductor(&Conductor::new(eta, k), cosine(1e-300));
            assert!((grazing - 1.0).abs() < 1e-12, "{eta} {k}: {grazing}");
            let zero = conductor(&Conductor::new(eta, k), cosine(0.0));
            assert!((zero - 1.0).abs() < 1e-12, "{eta} {k}: {zero}");
        }
        for mu in [0.0, 1e-300, 0.3, 1.0] {
            assert_eq!(conductor(&Conductor::new(1.0, 0.0), cosine(mu)), 0.0);
        }
    }

    /// Near `eta = 1` the value is of the order of `(eta − 1)²`, and keeps its digits: at
    /// normal incidence `((eta − 1)/(eta + 1))²`, at `μ = 0.6` against the series of the
    /// exact reflectance in `δ = eta − 1` (the leading term, then the relative correction
    /// of order δ).
    #[test]
    fn no_cancellation_near_eta_one() {
        for delta in [1e-12, -1e-12, 1e-6, 2f64.powi(-52)] {
            let eta = 1.0 + delta;
            let d = eta - 1.0;
            let got = conductor(&Conductor::new(eta, 0.0), cosine(1.0));
            let want = (d / (eta + 1.0)).powi(2);
            assert!(
                (got - want).abs() <= 1e-14 * want,
                "{delta}: {got} vs {want}"
            );
            // F = δ²·(1 + (2μ² − 1)²)/(8μ⁴)·(1 + O(δ)).
            let mu = 0.6;
            let lead = d * d * (1.0 + (2.0 * mu * mu - 1.0_f64).powi(2)) / (8.0 * mu.powi(4));
            let got = conductor(&Conductor::new(eta, 0.0), cosine(mu));
            assert!(
                (got - lead).abs() <= 64.0 * d.abs() * lead,
                "{delta}: {got} vs {lead}"
            );
        }
    }

    /// `f32` keeps to the `f64` value within a few of its roundings over the whole range,
    /// extreme cosines included, and never gives NaN or infinity.
    #[test]
    fn f32_is_finite_and_close_over_the_range() {
        let values = [1e-7, 1e-3, 0.2, 1.0, 1.0 + 1e-6, 3.0, 1e3, 1e7];
        for &eta in &values {
            for &k in [0.0].iter().chain(&values) {
                for mu in [1e-38, 1e-20, 1e-3, 0.1, 0.5, 0.9, 1.0] {
                    let c32 = Cosine {
                        cos: mu as f32,
                        one_minus: (1.0 - mu) as f32,
                    };
                    let got = conductor(&Conductor::new(eta as f32, k as f32), c32);
                    let ch64 = Conductor::new(f64::from(eta as f32), f64::from(k as f32));
                    let want = conductor(&ch64, cosine(f64::from(mu as f32)));
                    assert!(got.is_finite(), "eta={eta} k={k} mu={mu}: {got}");
                    let tol = 1e-5 * want + 1e-30;
                    assert!(
                        (f64::from(got) - want).abs() <= tol,
                        "eta={eta} k={k} mu={mu}: {got} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn f82_meets_its_tint_at_one_seventh_and_its_ends() {
        let schlick = |f0: f64, mu: f64| f0 + (1.0 - f0) * (1.0 - mu).powi(5);
        for f0 in [0.0, 0.04, 0.5, 0.9, 1.0] {
            for tint in [0.0, 0.3, 0.8, 1.0] {
                let ch = F82::new(f0, tint);
                let at = |mu: f64| f82(&ch, cosine(mu));
                let want = tint * schlick(f0, 1.0 / 7.0);
                assert!((at(1.0 / 7.0) - want).abs() <= 1e-14, "{f0} {tint}");
                assert_eq!(at(1.0), f0);
                assert_eq!(at(0.0), 1.0);
                for i in 0..=100 {
                    let mu = f64::from(i) / 100.0;
                    // The closed form of a against the formula written out.
                    let a = (1.0 - tint) * schlick(f0, 1.0 / 7.0)
                        / ((1.0 / 7.0) * (6.0f64 / 7.0).powi(6));
                    let direct = (schlick(f0, mu) - a * mu * (1.0 - mu).powi(6)).max(0.0);
                    assert!((at(mu) - direct).abs() <= 1e-14, "{f0} {tint} {mu}");
                    assert!((0.0..=1.0).contains(&at(mu)));
                }
            }
        }
        // Untinted: Schlick's F; f0 = f82 = 1: exactly 1.
        let ch = F82::new(0.3, 1.0);
        assert_eq!(
            f82(&ch, cosine(0.4)),
            0.3 + 0.7 * (0.6f64 * 0.6 * 0.6 * 0.6 * 0.6)
        );
        for i in 0..=100 {
            assert_eq!(f82(&F82::new(1.0, 1.0), cosine(f64::from(i) / 100.0)), 1.0);
        }
        // The formula goes negative for small f0 and f82: clamped.
        assert_eq!(f82(&F82::new(0.0, 0.0), cosine(0.5)), 0.0);
        let unclamped = 0.5f64.powi(5) * (1.0 - 49.0 / 24.0);
        assert!(unclamped < -0.03);
    }

    #[test]
    fn gen_schlick_blends_f0_into_f90() {
        use crate::math::SeriesPow;
        let ch = GenSchlick::new(0.2, 0.9);
        let at = |mu: f64, e: f64| gen_schlick::<f64, SeriesPow>(&ch, cosine(mu), e);
        assert_eq!(at(1.0, 5.0), 0.2);
        assert!((at(0.0, 5.0) - 0.9).abs() <= 1e-15);
        for e in [0.2, 1.0, 5.0, 40.0] {
            for i in 0..=50 {
                let mu = f64::from(i) / 50.0;
                let want = 0.2 + 0.7 * (1.0 - mu).powf(e);
                assert!((at(mu, e) - want).abs() <= 1e-15, "{mu} {e}");
            }
        }
        let one = GenSchlick::new(1.0, 1.0);
        for i in 0..=50 {
            let mu = f64::from(i) / 50.0;
            assert_eq!(gen_schlick::<f64, SeriesPow>(&one, cosine(mu), 3.7), 1.0);
        }
    }
}
