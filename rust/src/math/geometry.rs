//! The angles of docs/models.md, computed so they stay accurate where naive formulas lose
//! digits.
//!
//! Every cosine that is raised to a large power comes with its complement `1 - cos`
//! computed from a vector difference, `1 - u·v = |u - v|^2 / 2` for unit `u`, `v`. That
//! keeps `cos^p` accurate for `p` up to 1e8 (forming `1 - cos` from `cos` would lose all
//! digits within 1e-16 of the peak) and makes Schlick's `(1 - cos_b)^5` free of
//! cancellation. All inputs are unit vectors.

use glam::DVec3;

use super::{PowUnit, Real, Vector3, clamp, max, min};

/// A cosine together with its accurately computed complement `1 - cos`.
#[derive(Clone, Copy, Debug)]
pub struct Cosine<F> {
    /// The cosine, clamped to `[0, 1]`.
    pub cos: F,
    /// `1 - cos`, accurate relative to itself, in `[0, 1]`.
    pub one_minus: F,
}

impl<F: Real> Cosine<F> {
    /// Returns `cos^p` (with `0^0 = 1`), accurate even for huge `p` near the peak.
    /// In `f32`, results below 2^-100 ≈ 7.9e-31 are returned as 0: carried through the
    /// model they would become subnormals, each costing ~100-cycle microcode assists
    /// (see [`Real::flush_subnormal`]).
    /// `P` chooses how the power is computed ([`PowUnit`]).
    #[inline(always)]
    pub fn powf<P: PowUnit>(self, p: F) -> F {
        F::flush_subnormal(P::pow_unit(self.cos, self.one_minus, p))
    }

    /// Returns `cos^p / d` for `d > 0` without forming `cos^p` first, which may
    /// underflow where the quotient does not (`cos^p / mu_i` at grazing `mu_i`); see
    /// [`Real::pow_unit_over`]. The `f32` flush applies to the quotient.
    #[inline(always)]
    pub fn powf_over<P: PowUnit>(self, p: F, d: F) -> F {
        F::flush_subnormal(P::pow_unit_over(self.cos, self.one_minus, p, d))
    }
}

/// Returns `max(0, u·v)` and `1 - max(0, u·v)` for unit `u`, `v`.
#[inline(always)]
pub fn clamped_cosine<F: Real>(u: F::V3, v: F::V3) -> Cosine<F> {
    let d = u.dot(v);
    let diff = u - v;
    let one_minus = min(diff.length_squared() * F::HALF, F::ONE);
    // Below the horizon of `u` the clamped cosine is 0 and its complement exactly 1.
    let above = d > F::ZERO;
    Cosine {
        cos: if above { min(d, F::ONE) } else { F::ZERO },
        one_minus: if above { one_minus } else { F::ONE },
    }
}

/// Returns whether `u·v >= t` for unit `u`, `v`, decided where it is accurate: for
/// `t > 1/2` as `|u − v|²/2 <= 1 − t` (both sides exact or nearly, where `u·v` would round
/// to 1 within 1e-16 of it), for `t < −1/2` as `|u + v|²/2 >= 1 + t`, else directly.
#[inline(always)]
pub fn cosine_at_least<F: Real>(u: F::V3, v: F::V3, t: F) -> bool {
    let near_one = (u - v).length_squared() * F::HALF <= F::ONE - t;
    let near_minus_one = (u + v).length_squared() * F::HALF >= F::ONE + t;
    let direct = u.dot(v) >= t;
    if t > F::HALF {
        near_one
    } else if t < -F::HALF {
        near_minus_one
    } else {
        direct
    }
}

/// Returns `r = 2 (n·wi) n - wi`, the mirror direction of `wi` about `n`.
#[inline(always)]
pub fn mirror<F: Real>(wi: F::V3, n: F::V3, mu_i: F) -> F::V3 {
    n * (F::TWO * mu_i) - wi
}

/// The half vector of docs/models.md with the angle β between it and `wi` (and `wo`).
#[derive(Clone, Copy, Debug)]
pub struct HalfVector<F: Real> {
    /// `h = (wi + wo) / |wi + wo|`.
    pub h: F::V3,
    /// `cos_b = wi·h = wo·h = |wi + wo| / 2`, with
    /// `1 - cos_b = (|wi - wo|^2 / 4) / (1 + cos_b)`.
    pub cos_b: Cosine<F>,
    /// False when `wi = -wo` exactly: `h` is undefined and the caller returns 0.
    pub defined: bool,
}

/// Returns the half vector of unit `wi`, `wo` and the angle it makes with them.
///
/// `wi + wo` is exact where the two nearly cancel (Sterbenz), so `h` and
/// `cos_b = |wi + wo| / 2` stay accurate for tiny sums, where `wi·h` would cancel. The
/// sum is scaled by a power of two before it is squared ([`Real::normalize`],
/// [`Real::length`]), so a sum of 1e-300 (grazing `wi`, `wo` on opposite sides) still has
/// a direction: `h` is undefined only when `wi + wo` is exactly 0. The complement comes
/// from `|wi + wo|² + |wi − wo|² = 4`: `1 − cos_b = (1 − cos_b²)/(1 + cos_b)` with
/// `1 − cos_b² = |wi − wo|²/4`, accurate at both ends (`wi ≈ wo`: the difference is
/// exact; `wi ≈ −wo`: nothing cancels), where `|wi − h|²/2` lost the digits of `h`'s
/// rounding as `h` turned perpendicular to `wi`.
///
/// The sum is exact, but of the rounded unit vectors: their lengths are off by an ulp or
/// so, which moves `wi + wo` by about 1e-16 and, where the sum is small, `h`'s direction
/// by `1e-16/|wi + wo|`. [`half_vector_exact`] removes that.
#[inline(always)]
pub fn half_vector<F: Real>(wi: F::V3, wo: F::V3) -> HalfVector<F> {
    half_vector_of_sum(wi + wo, wi, wo)
}

/// [`half_vector`] in `P`'s tier: with `P::DIVISION_FREE` (the AVX-512 fast tier) normalized with
/// [`Real::normalize_length_fast`] (no square root, no division).
#[inline(always)]
pub fn half_vector_in<F: Real, P: PowUnit>(wi: F::V3, wo: F::V3) -> HalfVector<F> {
    if !P::DIVISION_FREE {
        return half_vector(wi, wo);
    }
    let (h, len) = F::normalize_length_fast(wi + wo);
    half_vector_from(h, len, wi, wo)
}

/// Returns [`half_vector`] of the exact unit vectors `wi·(1 − e_i/2)`, `wo·(1 − e_o/2)`
/// (to first order) given the rounded ones and their length errors `e = |w|² − 1`
/// ([`Real::length_error`]): the sum becomes `wi + wo − (wi·e_i + wo·e_o)/2`, whose
/// correction is formed before it is subtracted, so a sum of 1e-3 keeps its direction to
/// the last digits (the rounded vectors' sum is off by 1e-16 there, 1e-13 relative), and
/// `1 − cos_b` from `|wi − wo|²` is scaled by `1 − (e_i + e_o)/2`. `h` itself is rounded
/// again: its own length error is the caller's to take into account. With `e = 0` (as
/// `f32` gives) this is [`half_vector`].
#[inline(always)]
pub fn half_vector_exact<F: Real>(wi: F::V3, wo: F::V3, e_i: F, e_o: F) -> HalfVector<F> {
    if !F::EXACT_LENGTHS {
        return half_vector(wi, wo);
    }
    // wi = −wo exactly gives e_i = e_o and a correction of exactly 0: still undefined.
    let correction = (wi * e_i + wo * e_o) * F::HALF;
    let mut hv = half_vector_of_sum((wi + wo) - correction, wi, wo);
    // |wi − wo|² is first-order homogeneous in |wi| and |wo|.
    let one_minus = hv.cos_b.one_minus;
    hv.cos_b.one_minus = min(one_minus - one_minus * (F::HALF * (e_i + e_o)), F::ONE);
    hv
}

/// [`half_vector`] from the sum `s` of `wi` and `wo` (corrected or not).
#[inline(always)]
fn half_vector_of_sum<F: Real>(s: F::V3, wi: F::V3, wo: F::V3) -> HalfVector<F> {
    let (h, len) = F::normalize_length(s);
    half_vector_from(h, len, wi, wo)
}

/// [`half_vector_of_sum`] given the sum's direction `h` and length `len`.
#[inline(always)]
fn half_vector_from<F: Real>(h: F::V3, len: F, wi: F::V3, wo: F::V3) -> HalfVector<F> {
    let defined = len > F::ZERO;
    // When undefined, use n-free finite values (the caller zeroes the lane).
    let h = F::V3::new(
        if defined { h.x() } else { wi.x() },
        if defined { h.y() } else { wi.y() },
        if defined { h.z() } else { wi.z() },
    );
    let cos = min(len * F::HALF, F::ONE);
    let d = wi - wo;
    let one_minus = d.length_squared() * F::from_f64(0.25) / (F::ONE + cos);
    HalfVector {
        h,
        cos_b: Cosine {
            cos,
            one_minus: min(one_minus, F::ONE),
        },
        defined,
    }
}

/// Returns Schlick's `(1 - cos)^5` from an accurate complement.
#[inline(always)]
pub fn schlick_weight<F: Real>(c: Cosine<F>) -> F {
    let x = c.one_minus;
    let x2 = x * x;
    x2 * x2 * x
}

/// Returns `sin a · tan b · max(0, cos(φi − φo))` of Oren-Nayar, `a = max(θi, θo)`,
/// `b = min(θi, θo)`, without any trigonometric function.
///
/// With `sin θ = |n × w|` and `cos(φi − φo) = (n × wi)·(n × wo) / (sin θi sin θo)`:
/// `sin a · sin b = sin θi sin θo` cancels the projections' lengths and
/// `cos b = max(mu_i, mu_o)`, so the product is `max(0, (n × wi)·(n × wo)) / max(mu_i, mu_o)`.
/// A zero-length projection gives 0, as docs/models.md requires. Valid whenever
/// `max(mu_i, mu_o) > 0`; returns 0 otherwise.
#[inline(always)]
pub fn oren_nayar_angular<F: Real>(wi: F::V3, wo: F::V3, n: F::V3, mu_i: F, mu_o: F) -> F {
    let proj = n.cross(wi).dot(n.cross(wo));
    let cos_b = max(mu_i, mu_o);
    let value = max(proj, F::ZERO) / cos_b;
    if cos_b > F::ZERO { value } else { F::ZERO }
}

/// Returns the Oren-Nayar coefficients `(A, B)` for roughness `sigma`.
#[inline(always)]
pub fn oren_nayar_ab<F: Real>(sigma: F) -> (F, F) {
    let s2 = sigma * sigma;
    let a = F::ONE - F::HALF * s2 / (s2 + F::from_f64(0.33));
    let b = F::from_f64(0.45) * s2 / (s2 + F::from_f64(0.09));
    (a, b)
}

/// Returns `sqrt(max(0, 1 - c^2))` for a cosine `c` in `[-1, 1]`, as `sqrt((1-c)(1+c))`.
#[inline(always)]
pub fn sine_from_cosine<F: Real>(c: F) -> F {
    let c = clamp(c, -F::ONE, F::ONE);
    max((F::ONE - c) * (F::ONE + c), F::ZERO).sqrt()
}

/// How close to the normal a given tangent may be, in units of the float type's machine
/// epsilon: a tangent with `|t̂ × n̂|` (the sine of its angle to the normal) at most this
/// many epsilons is refused, since its projection onto the tangent plane, a few
/// roundings long, points wherever those roundings do.
pub const PARALLEL_TANGENT_EPSILONS: f64 = 64.0;

/// Whether `t` is parallel to `n` to within [`PARALLEL_TANGENT_EPSILONS`]:
/// `|n × t| <= k·ε·|n|·|t|` (exactly parallel, opposite or zero included). NaN gives false.
#[inline(always)]
pub fn tangent_parallel<F: Real>(n: F::V3, t: F::V3) -> bool {
    let eps = if std::mem::size_of::<F>() == 4 {
        f32::EPSILON as f64
    } else {
        f64::EPSILON
    };
    let k = F::from_f64(PARALLEL_TANGENT_EPSILONS * eps);
    n.cross(t).length_squared() <= k * k * n.length_squared() * t.length_squared()
}

/// Returns the unit tangent `x` (tangent projected onto the plane normal to `n` and
/// normalized: Gram-Schmidt) and `y = n × x`. A tangent parallel to `n` has no
/// projection; then any unit vector perpendicular to `n` is used.
#[inline(always)]
pub fn tangent_frame<F: Real>(n: F::V3, t: F::V3) -> (F::V3, F::V3) {
    let p = t - n * n.dot(t);
    let len2 = p.length_squared();
    let ok = len2 > F::from_f64(1e-30);
    let scale = F::ONE / if ok { len2.sqrt() } else { F::ONE };
    let fallback = n.any_orthonormal();
    let x = F::V3::new(
        if ok { p.x() * scale } else { fallback.x() },
        if ok { p.y() * scale } else { fallback.y() },
        if ok { p.z() * scale } else { fallback.z() },
    );
    (x, n.cross(x))
}

/// Returns Schlick's `F = F0 + (1 − F0)·w` per channel, `w = (1 − cos)^5`.
#[inline(always)]
pub fn schlick_rgb<F: Real>(f0: [F; 3], w: F) -> [F; 3] {
    f0.map(|c| c + (F::ONE - c) * w)
}

/// `μ·Λ(μ)` of the GGX (Trowbridge-Reitz) Smith function, `Λ(μ) =
/// (−1 + sqrt(1 + α²(1 − μ²)/μ²))/2`, written as `α² s²/(2(r + μ))` with
/// `r = sqrt(μ² + α² s²)`, `s² = 1 − μ²`: finite and accurate at grazing angles (where
/// `Λ` itself overflows) and near normal incidence (where `−1 + sqrt(1 + x)` cancels).
#[inline(always)]
pub fn ggx_mu_lambda<F: Real>(mu: F, sin2: F, alpha2: F) -> F {
    let a2s2 = alpha2 * sin2;
    let r = (mu * mu + a2s2).sqrt();
    a2s2 / (F::TWO * (r + mu))
}

/// Returns `weight·x`, or 0 when `weight` is 0 whatever `x` is: a colour channel (or a
/// Fresnel factor, a distribution value) of 0 times a lobe that is infinite where the
/// exact value is (`1/mu_i` at grazing) is 0, never `0·inf = NaN`.
#[inline(always)]
pub fn weighted<F: Real>(weight: F, x: F) -> F {
    if weight == F::ZERO {
        F::ZERO
    } else {
        weight * x
    }
}

/// Returns `x / (4 (mu_i mu_o + mu_o l_i + mu_i l_o))`, `l = mu·Λ(mu)`: a distribution
/// value `x` times the height-correlated Smith `G2/(4 mu_i mu_o)`.
///
/// The larger cosine `m` is factored out first, `(mu_i mu_o + mu_o l_i + mu_i l_o)/m =
/// min(mu_i, mu_o) + (mu_o/m) l_i + (mu_i/m) l_o`, whose terms are no smaller than the
/// result needs: with both cosines at 1e-38 in `f32` (or 1e-320 in `f64`) the products
/// `mu_o l_i` underflowed to 0 and gave an infinity where the exact value is finite. A
/// zero `x` gives 0. Valid for `mu_i, mu_o > 0` (other lanes are finite garbage).
#[inline(always)]
pub fn smith_quotient<F: Real>(x: F, mu_i: F, mu_o: F, l_i: F, l_o: F) -> F {
    let m = max(mu_i, mu_o);
    let m = if m > F::ZERO { m } else { F::ONE };
    let inner = min(mu_i, mu_o) + mu_o / m * l_i + mu_i / m * l_o;
    x / (F::from_f64(4.0) * inner) / m
}

/// Divides the rounded unit vectors' length errors `e = |w|² − 1` ([`Real::length_error`])
/// out of a microfacet lobe `D·G2/(4 mu_i mu_o)` written first-order homogeneous in the
/// lengths of `n`, `wi`, `wo` and `h`, of degrees −6, −1, −1 and −4: the value computed
/// from the rounded vectors carries the factor `1 − (3e_n + (e_i + e_o)/2 + 2e_h)`.
/// Identity where lengths are not tracked (`f32`).
#[inline(always)]
pub fn microfacet_length_correction<F: Real>(spec: F, e_n: F, e_i: F, e_o: F, h: F::V3) -> F {
    if !F::EXACT_LENGTHS {
        return spec;
    }
    let e_h = F::length_error(h);
    let k = F::from_f64(3.0) * e_n + F::HALF * (e_i + e_o) + F::TWO * e_h;
    // An infinite lobe (both cosines 1e-300) stays infinite: inf·k would be NaN.
    if spec < F::INFINITY {
        spec + spec * k
    } else {
        spec
    }
}

/// Zeroes an RGB value unless both directions are above the surface (family A).
#[inline(always)]
pub fn above_both<F: Real>(mu_i: F, mu_o: F, rgb: [F; 3]) -> [F; 3] {
    let above = mu_i > F::ZERO && mu_o > F::ZERO;
    rgb.map(|c| if above { c } else { F::ZERO })
}

/// A cosine `m·2^k` (`|m|` in [0.5, 1) with the cosine's sign, or `m` = 0 and `k` = 0)
/// carried with an exponent wider than `f64`'s: see [`wide_cosine`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WideCosine {
    pub m: f64,
    pub k: i32,
}

impl WideCosine {
    /// Returns the larger of two cosines of which at least one is positive.
    pub fn max_positive(self, other: WideCosine) -> WideCosine {
        let larger = if other.m <= 0.0 {
            true
        } else if self.m <= 0.0 {
            false
        } else {
            (self.k, self.m) > (other.k, other.m)
        };
        if larger { self } else { other }
    }

    /// Returns `self / other` as an `f64` (overflowing to ±inf, underflowing to 0) for a
    /// nonzero `other`: the mantissas' quotient, then one scaling.
    pub fn over(self, other: WideCosine) -> f64 {
        libm::scalbn(self.m / other.m, self.k - other.k)
    }

    /// Returns `self/|w|` for a finite nonzero `w` (one rounding).
    pub fn over_length(self, w: [f64; 3]) -> WideCosine {
        let (lm, le) = libm::frexp(f64::length(DVec3::from_array(w)));
        WideCosine::of(self.m / lm, self.k - le)
    }

    /// The cosine as an `f64` (0 below the subnormal range).
    pub fn value(self) -> f64 {
        libm::scalbn(self.m, self.k)
    }

    /// `m·2^k` for a nonzero finite `x` (subnormal included), 0 for 0.
    pub fn of(x: f64, k: i32) -> WideCosine {
        let (m, e) = libm::frexp(x);
        if m == 0.0 {
            WideCosine { m: 0.0, k: 0 }
        } else {
            WideCosine { m, k: e + k }
        }
    }
}

/// The sum, rescaled to the larger of the two (one rounding).
impl std::ops::Add for WideCosine {
    type Output = WideCosine;
    fn add(self, other: WideCosine) -> WideCosine {
        if other.m == 0.0 {
            return self;
        }
        if self.m == 0.0 {
            return other;
        }
        let top = self.k.max(other.k);
        WideCosine::of(
            libm::scalbn(self.m, self.k - top) + libm::scalbn(other.m, other.k - top),
            top,
        )
    }
}

/// The product (one rounding).
impl std::ops::Mul for WideCosine {
    type Output = WideCosine;
    fn mul(self, other: WideCosine) -> WideCosine {
        WideCosine::of(self.m * other.m, self.k + other.k)
    }
}

impl std::ops::Neg for WideCosine {
    type Output = WideCosine;
    fn neg(self) -> WideCosine {
        WideCosine {
            m: -self.m,
            k: self.k,
        }
    }
}

/// Returns `n·w/|w|` for a unit `n` and a raw (unnormalized, finite, nonzero) `w`, as
/// `m·2^k`, without the underflow of normalizing `w` first.
///
/// A vector like `(1e300, 0, 1e-300)` has a unit vector `(1, 0, 1e-600)` whose last
/// component is below even the subnormal range: normalization keeps only its sign
/// (±2^-1074). Its cosine with `+z` is still `1e-300/1e300` exactly, here `m·2^k` with
/// `k` = -1994. Each product `n_c·w_c` is split into mantissa and exponent (one
/// rounding), and the products are added largest first into a running `m·2^k`, each
/// addition rescaled to the larger of the two: a sum that cancels, such as
/// `(1e300, −1e300, 1e-300)` under `n = (½, ½, √½)`, keeps the small term whole. The sum
/// is then divided by `|w|` the same way. `n` is taken as given (normalized).
pub fn wide_cosine(n: [f64; 3], w: [f64; 3]) -> WideCosine {
    wide_dot(n, w).over_length(w)
}

/// Returns `a·b` as `m·2^k`: each product split into mantissa and exponent (one
/// rounding), added largest first (`WideCosine`'s `+`).
pub fn wide_dot(a: [f64; 3], b: [f64; 3]) -> WideCosine {
    let mut parts = [0, 1, 2].map(|c| {
        let (am, ae) = libm::frexp(a[c]);
        let (bm, be) = libm::frexp(b[c]);
        WideCosine::of(am * bm, ae + be)
    });
    parts.sort_by_key(|p| std::cmp::Reverse(if p.m == 0.0 { i32::MIN } else { p.k }));
    parts
        .iter()
        .fold(WideCosine { m: 0.0, k: 0 }, |acc, p| acc + *p)
}

/// Returns `a·x + b` per channel.
#[inline(always)]
pub fn rgb_affine<F: Real>(a: [F; 3], x: F, b: [F; 3]) -> [F; 3] {
    [a[0] * x + b[0], a[1] * x + b[1], a[2] * x + b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wide_cosine_keeps_what_normalization_loses() {
        let z = [0.0, 0.0, 1.0];
        // 1e-300/1e300: 2^1000 times that is one rounding of 1e-300/(1e300·2^-1000).
        for (w, sign) in [([1e300, 0.0, 1e-300], 1.0), ([0.0, -1e300, -1e-300], -1.0)] {
            let c = wide_cosine(z, w);
            assert!((0.5..1.0).contains(&c.m.abs()) && c.m.signum() == sign);
            let want = sign * 1e-300 / libm::scalbn(1e300, -1000);
            assert_eq!(libm::scalbn(c.m, c.k + 1000), want, "{w:?}");
        }
        assert_eq!(wide_cosine(z, [1.0, 2.0, 0.0]), WideCosine { m: 0.0, k: 0 });
        // The largest products cancel exactly: the small one is the whole sum.
        let n = [0.5, 0.5, 0.5f64.sqrt()];
        let c = wide_cosine(n, [1e300, -1e300, 1e-300]);
        let want = 0.5f64.sqrt() * 1e-300 / libm::scalbn(1e300 * 2f64.sqrt(), -1000);
        assert!(
            (libm::scalbn(c.m, c.k + 1000) / want - 1.0).abs() < 4e-16,
            "{c:?}"
        );
        // The larger of two wide cosines, and a division by one.
        let (a, b) = (
            wide_cosine(z, [1e300, 0.0, 1e-300]),
            wide_cosine(z, [1.0, 0.0, 1e-300]),
        );
        assert_eq!(a.max_positive(b), b);
        assert_eq!(b.max_positive(a), b);
        assert_eq!(a.max_positive(wide_cosine(z, [1.0, 0.0, -1.0])), a);
        assert_eq!(wide_cosine(z, [1.0, 0.0, 0.0]).max_positive(a), a);
        assert_eq!(WideCosine::of(1e-301, 0).over(b), 0.1);
        assert_eq!(WideCosine::of(1.0, 0).over(a), f64::INFINITY);
        // Components of very different exponents in both vectors.
        let n = DVec3::new(1e-200, 0.6, 0.8).normalize().to_array();
        let c = wide_cosine(n, [0.0, 1e300, -1e-300]);
        let want = n[1] * 1e300 / 1e300 - n[2] * 1e-300 / 1e300;
        assert!((c.value() / want - 1.0).abs() < 4e-16, "{c:?}");
        // In the normal range it is the cosine of the normalized vector, within its
        // rounding, for unit normals and vectors of any length.
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..10_000 {
            let n = DVec3::new(uniform(), uniform(), uniform()).normalize();
            let scale = 10f64.powf(300.0 * uniform());
            let w = DVec3::new(uniform(), uniform(), uniform()) * scale;
            let want = n.dot(w / f64::length(w));
            let c = wide_cosine(n.to_array(), w.to_array());
            let got = c.value();
            assert!((got - want).abs() <= 1e-15, "{n} {w}: {got} {want}");
        }
    }

    #[test]
    fn complement_is_accurate_near_the_peak() {
        let n = DVec3::Z;
        let t = 1e-9_f64;
        let w = DVec3::new(t.sin(), 0.0, t.cos());
        let c = clamped_cosine::<f64>(n, w);
        // 1 - cos t = t^2/2 - t^4/24...
        let exact = t * t / 2.0;
        assert!(
            (c.one_minus - exact).abs() <= 1e-15 * exact,
            "{} vs {exact}",
            c.one_minus
        );
    }

    #[test]
    fn oren_nayar_identity_matches_trigonometry() {
        let n = DVec3::Z;
        let (ti, to, dphi) = (0.7_f64, 1.1_f64, 0.4_f64);
        let wi = DVec3::new(ti.sin(), 0.0, ti.cos());
        let wo = DVec3::new(to.sin() * dphi.cos(), to.sin() * dphi.sin(), to.cos());
        let got = oren_nayar_angular::<f64>(wi, wo, n, wi.z, wo.z);
        let want = to.sin() * ti.tan() * dphi.cos();
        assert!((got - want).abs() < 1e-15, "{got} {want}");
    }

    #[test]
    fn half_vector_of_grazing_opposite_directions_is_the_normal() {
        // wi + wo = (0, 0, 2e-300): its square underflows, its direction does not.
        let hv = half_vector::<f64>(DVec3::new(1.0, 0.0, 1e-300), DVec3::new(-1.0, 0.0, 1e-300));
        assert!(hv.defined);
        assert!(hv.h.x == 0.0 && hv.h.y == 0.0 && (hv.h.z - 1.0).abs() <= f64::EPSILON);
        assert!((hv.cos_b.cos - 1e-300).abs() <= 2.0 * f64::EPSILON * 1e-300);
        assert_eq!(hv.cos_b.one_minus, 1.0);
        let hv = half_vector::<f64>(DVec3::X, -DVec3::X);
        assert!(!hv.defined);
    }

    #[test]
    fn cos_b_complement_is_accurate_for_nearly_opposite_directions() {
        // wi = (c, s, 0), wo = (-c, s, 0) up to rounding: cos_b = |s|, 1 − cos_b needs
        // no cancellation, while |wi − h|²/2 carried h's rounding (1e-13 here).
        for t in [1e-3_f64, 1e-6, 1e-9] {
            let wi = DVec3::new(t.cos(), t.sin(), 0.0);
            let wo = DVec3::new(-t.cos(), t.sin(), 1e-7).normalize();
            let hv = half_vector::<f64>(wi, wo);
            let want = 1.0 - hv.cos_b.cos; // cos_b <= 1/2: the subtraction is exact-ish
            let got = hv.cos_b.one_minus;
            assert!(
                (got - want).abs() <= 2.0 * f64::EPSILON * want,
                "{t}: {got} vs {want}"
            );
        }
        // Nearly equal directions: the complement from the exact difference.
        let wi = DVec3::new(0.6, 0.0, 0.8);
        let wo = DVec3::new(0.6 + 1e-9, 0.0, 0.8).normalize();
        let d = (wi - wo).length();
        let hv = half_vector::<f64>(wi, wo);
        let want = d * d / 4.0 / (1.0 + hv.cos_b.cos);
        assert!((hv.cos_b.one_minus - want).abs() <= 4.0 * f64::EPSILON * want);
    }

    #[test]
    fn cosine_comparisons_at_the_ends_are_exact() {
        // u·v is within an ulp of 1 for v one ulp away from u; only u itself is at
        // cosine 1 (for unit vectors).
        let u = DVec3::new(0.6, 0.0, 0.8);
        let v = DVec3::new(f64::from_bits(0.6f64.to_bits() + 1), 0.0, 0.8);
        assert!(u.dot(v) >= 1.0 - f64::EPSILON);
        assert!(cosine_at_least::<f64>(u, u, 1.0));
        assert!(!cosine_at_least::<f64>(u, v, 1.0));
        assert!(cosine_at_least::<f64>(u, -u, -1.0));
        assert!(cosine_at_least::<f64>(u, DVec3::X, 0.5) == (u.dot(DVec3::X) >= 0.5));
        assert!(
            !cosine_at_least::<f64>(u, u, f64::INFINITY),
            "unused toon thresholds"
        );
    }

    #[test]
    fn smith_quotient_does_not_underflow_at_grazing_angles() {
        // f32, both cosines 1e-38, mu·Λ(mu) = 5e-8, D = 1e-15: the exact value is
        // 1e-15/(4e-7·1e-38) = 2.5e30, while mu_o·l_i = 5e-46 underflows to 0 in f32.
        let (mu, l) = (1e-38_f32, 5e-8_f32);
        let got = smith_quotient::<f32>(1e-15, mu, mu, l, l);
        let want = 1e-15 / (4.0 * (1e-38_f64 * 1e-38 + 2.0 * 1e-38 * 5e-8));
        assert!(
            ((f64::from(got) - want) / want).abs() < 1e-6,
            "{got} vs {want}"
        );
        // Ordinary cosines: the plain formula.
        let (mi, mo, li, lo) = (0.3, 0.7, 0.05, 0.02);
        let plain = 0.8 / (4.0 * (mi * mo + mo * li + mi * lo));
        let got = smith_quotient::<f64>(0.8, mi, mo, li, lo);
        assert!((got - plain).abs() <= 4.0 * f64::EPSILON * plain);
        assert_eq!(smith_quotient::<f64>(0.0, 5e-324, 5e-324, 0.25, 0.25), 0.0);
    }

    #[test]
    fn half_vector_of_opposite_directions_is_undefined() {
        let w = DVec3::new(0.3, 0.4, 0.5).normalize();
        assert!(!half_vector::<f64>(w, -w).defined);
        assert!(half_vector::<f64>(w, w).defined);
        let v = DVec3::new(-0.3, 0.4001, 0.5).normalize();
        let hv = half_vector::<f64>(w, v);
        assert!((hv.cos_b.cos - w.dot(hv.h)).abs() < 1e-15);
    }
}
