//! The inverse error functions `erfinv` and `erfcinv`, to double precision.
//!
//! `libm` (the crate's `erf` / `erfc`) has no inverse. Each value here starts from
//! Giles' single-precision approximation ("Approximating the erfinv function", GPU
//! Computing Gems Jade Edition, 2011, ch. 10; the same one PBRT-v3's `ErfInv` uses,
//! relative error below ~6e-8 on its single-precision range `1 − |x| >= 1e-7`; past it,
//! from the tail's asymptote) and is refined by one Halley step on `libm::erf` (near 0)
//! or `libm::erfc` (in the tails, where `1 − |x|` must keep its digits). Halley's step
//! is cubic: ~4e-7 becomes ~1e-19, so the result is as accurate as `libm`'s `erf` /
//! `erfc` allow (the tests check `erf(erfinv(x)) = x` to a few ulp). A crate with an
//! `erf_inv` (statrs) would bring a dependency tree for one function.

/// `2/sqrt(π)`: the derivative of `erf` at 0.
const TWO_OVER_SQRT_PI: f64 = std::f64::consts::FRAC_2_SQRT_PI;

/// The smallest `q` [`erfcinv`] resolves: `erfcinv(q)` for smaller `q` (and 0) is
/// `erfcinv(1e-300)` ≈ 26.2, finite.
const Q_MIN: f64 = 1e-300;
/// The end of Giles' fit in `w = −ln(q(2 − q))`.
const TAIL_W: f64 = 16.0;

/// Giles' single-precision `erfinv(x)` for `|x| < 1`, given `w = −ln((1 − x)(1 + x))`.
#[inline(always)]
pub fn erfinv_guess(x: f64, w: f64) -> f64 {
    let p = if w < 5.0 {
        let w = w - 2.5;
        let mut p = 2.810_226_36e-08;
        p = 3.432_739_39e-07 + p * w;
        p = -3.523_387_7e-06 + p * w;
        p = -4.391_506_54e-06 + p * w;
        p = 0.000_218_580_87 + p * w;
        p = -0.001_253_725_03 + p * w;
        p = -0.004_177_681_64 + p * w;
        p = 0.246_640_727 + p * w;
        1.501_409_41 + p * w
    } else {
        let w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_257;
        p = 0.000_100_950_558 + p * w;
        p = 0.001_349_343_22 + p * w;
        p = -0.003_673_428_44 + p * w;
        p = 0.005_739_507_73 + p * w;
        p = -0.007_622_461_3 + p * w;
        p = 0.009_438_870_47 + p * w;
        p = 1.001_674_06 + p * w;
        2.832_976_82 + p * w
    };
    p * x
}

/// One Halley step for `g(x) = target` with `g = erf` or `erfc`: both have
/// `g'' = −2x·g'`, so the step is `x − d/(1 + x·d)` with `d = (g(x) − target)/g'(x)`.
#[inline(always)]
fn halley(x: f64, residual: f64, derivative: f64) -> f64 {
    let d = residual / derivative;
    x - d / (1.0 + x * d)
}

/// Returns `x >= 0` with `erfc(x) = q`, for `q` in `(0, 1]`.
#[inline(always)]
fn erfcinv_upper(q: f64) -> f64 {
    let q = q.max(Q_MIN);
    let w = -f64::ln(q * (2.0 - q));
    let mut x = erfinv_guess(1.0 - q, w);
    // Giles' fit covers single precision, w <= −ln(2^-23) ≈ 16; past it (q < 1e-7) start
    // from the asymptote erfc(x) ≈ exp(−x²)/(x·sqrt(π)) (relative error < 1e-3) and
    // take two more steps.
    let tail = w > TAIL_W;
    if tail {
        let q_sqrt_pi = q * std::f64::consts::PI.sqrt();
        let t = (-f64::ln(q_sqrt_pi)).sqrt();
        x = (-f64::ln(q_sqrt_pi * t)).sqrt();
    }
    let steps = if tail { 3 } else { 1 };
    for _ in 0..steps {
        let slope = TWO_OVER_SQRT_PI * (-x * x).exp();
        x = if q < 0.5 {
            // erfc is accurate in the tail, where 1 − q has lost q's digits.
            halley(x, libm::erfc(x) - q, -slope)
        } else {
            // 1 − q is exact here (Sterbenz), and erf is accurate near 0.
            halley(x, libm::erf(x) - (1.0 - q), slope)
        };
    }
    x
}

/// Returns `erfcinv(q)`: the `x` with `erfc(x) = q`, for `q` in `[0, 2]`. The ends are
/// finite: `q <= 1e-300` gives ≈ 26.2 and `q >= 2 − 1e-300`, i.e. 2, gives ≈ −26.2 (no
/// infinities for samplers to propagate); NaN gives NaN.
#[inline(always)]
pub fn erfcinv(q: f64) -> f64 {
    if q.is_nan() {
        q
    } else if q <= 1.0 {
        erfcinv_upper(q)
    } else {
        // erfc(−x) = 2 − erfc(x); 2 − q is exact for q in [1, 2].
        -erfcinv_upper(2.0 - q)
    }
}

/// Returns `erfinv(x)` for `x` in `[−1, 1]` (finite at ±1: ±26.2, see [`erfcinv`]).
#[inline(always)]
pub fn erfinv(x: f64) -> f64 {
    let a = x.abs();
    if a.is_nan() {
        return x;
    }
    // 1 − a is exact for a in [1/2, 1]; below, erf's branch of erfcinv_upper is used and
    // reads 1 − q = a back (to an ulp of 1).
    let y = if a < 0.5 {
        let w = -f64::ln((1.0 - a) * (1.0 + a));
        let x0 = erfinv_guess(a, w);
        halley(x0, libm::erf(x0) - a, TWO_OVER_SQRT_PI * (-x0 * x0).exp())
    } else {
        erfcinv_upper(1.0 - a)
    };
    if x < 0.0 { -y } else { y }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values from `scipy.special.erfinv` / `erfcinv` (Boost's rational approximations).
    #[test]
    fn known_values() {
        let cases = [
            (0.5, 0.476_936_276_204_469_9),
            (1e-10, 8.862_269_254_527_581e-11),
            (0.9, 1.163_087_153_676_674_3),
            (-0.999, -2.326_753_765_513_524),
            (0.999_999_999_999, 5.042_031_898_572_696),
        ];
        for (x, want) in cases {
            let got = erfinv(x);
            assert!(
                (got - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
                "erfinv({x}) = {got}, want {want}"
            );
        }
        // scipy.special.erfcinv(1e-100).
        let got = erfcinv(1e-100);
        assert!((got - 15.065_574_702_592_647).abs() < 1e-13, "{got}");
    }

    #[test]
    fn round_trips_through_libm() {
        for i in 1..2000 {
            let x = -1.0 + i as f64 / 1000.0;
            let back = libm::erf(erfinv(x));
            assert!((back - x).abs() <= 4.0 * f64::EPSILON, "{x}: {back}");
        }
        for k in 1..300 {
            let q = 10f64.powi(-k);
            let x = erfcinv(q);
            let back = libm::erfc(x);
            // erfc's condition number at x is ~2x²: an ulp of x moves erfc by 2x² ulp.
            let tol = 4.0 * f64::EPSILON * (2.0 * x * x + 2.0) * q;
            assert!((back - q).abs() <= tol, "erfcinv({q}) = {x}: erfc = {back}");
            let upper = 2.0 - q;
            let back = libm::erfc(erfcinv(upper));
            assert!(
                (back - upper).abs() <= 4.0 * f64::EPSILON,
                "{upper}: {back}"
            );
        }
    }

    #[test]
    fn ends_are_finite() {
        for q in [0.0, 1e-320, 2.0, 2.0 - f64::EPSILON] {
            assert!(erfcinv(q).is_finite(), "{q}");
        }
        for x in [-1.0, 1.0, 1.0 - f64::EPSILON / 2.0] {
            assert!(erfinv(x).is_finite(), "{x}");
        }
        assert_eq!(erfinv(0.0), 0.0);
        assert!(erfinv(f64::NAN).is_nan());
    }
}
