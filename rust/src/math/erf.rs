//! A vectorizable complementary error function.
//!
//! `erfc_f64` is FreeBSD's `s_erf.c` (Sun's fdlibm, as ported to Rust by the `libm`
//! crate this crate already depends on: the same rational approximations and
//! coefficients, region by region) rewritten without branches: every region's
//! rational is evaluated on every lane and the region is chosen by selects, and the
//! two `exp` calls are this crate's branch-free [`exp_f64`]. A loop that calls it per
//! element therefore auto-vectorizes like the rest of a kernel, where one call to
//! `libm::erf` kept Beckmann's whole batch loop scalar (13 M evaluations/s against
//! GGX's 91 on the same machine).
//!
//! Regions of `a = |x|` (fdlibm's):
//! - `a < 0.84375`: `erf(a) = a + a·P(a²)/Q(a²)`, `erfc = 1 − erf` (for `a ≥ 1/4` as
//!   `0.5 − (a − 0.5 + a·y)`, which keeps the last bits);
//! - `0.84375 ≤ a < 1.25`: `erfc = 1 − erx − P(a − 1)/Q(a − 1)`;
//! - `1.25 ≤ a < 28`: `erfc = exp(−z² − 0.5625)·exp((z − a)(z + a) + R(1/a²)/S(1/a²))/a`,
//!   `z` = `a` with its low 32 bits cleared (so `z²` is exact), `R/S` one of two
//!   rationals split at `1/0.35`;
//! - `a ≥ 28`: 0.
//!
//! Negative `x`: `erfc(x) = 2 − erfc(−x)`. NaN gives NaN. Accuracy against 40-digit
//! mpmath on 40,000 points (x uniform in [−2, 27] and log-uniform in [1e-10, 30]):
//! max 2.29 ulp, p99 1.35, median 0.30 (glibc's scalar `erfc` on the same points: max
//! 2.32). The unit test keeps it within 5 ulps of `libm::erfc` (both are within about
//! 2.3 of the exact value, with errors that differ lane by lane).

#![allow(clippy::excessive_precision, clippy::unreadable_literal)]

use super::fastmath::exp_f64;

const ERX: f64 = 8.45062911510467529297e-01;
const PP: [f64; 5] = [
    1.28379167095512558561e-01,
    -3.25042107247001499370e-01,
    -2.84817495755985104766e-02,
    -5.77027029648944159157e-03,
    -2.37630166566501626084e-05,
];
const QQ: [f64; 5] = [
    3.97917223959155352819e-01,
    6.50222499887672944485e-02,
    5.08130628187576562776e-03,
    1.32494738004321644526e-04,
    -3.96022827877536812320e-06,
];
const PA: [f64; 7] = [
    -2.36211856075265944077e-03,
    4.14856118683748331666e-01,
    -3.72207876035701323847e-01,
    3.18346619901161753674e-01,
    -1.10894694282396677476e-01,
    3.54783043256182359371e-02,
    -2.16637559486879084300e-03,
];
const QA: [f64; 6] = [
    1.06420880400844228286e-01,
    5.40397917702171048937e-01,
    7.18286544141962662868e-02,
    1.26171219808761642112e-01,
    1.36370839120290507362e-02,
    1.19844998467991074170e-02,
];
const RA: [f64; 8] = [
    -9.86494403484714822705e-03,
    -6.93858572707181764372e-01,
    -1.05586262253232909814e+01,
    -6.23753324503260060396e+01,
    -1.62396669462573470355e+02,
    -1.84605092906711035994e+02,
    -8.12874355063065934246e+01,
    -9.81432934416914548592e+00,
];
const SA: [f64; 8] = [
    1.96512716674392571292e+01,
    1.37657754143519042600e+02,
    4.34565877475229228821e+02,
    6.45387271733267880336e+02,
    4.29008140027567833386e+02,
    1.08635005541779435134e+02,
    6.57024977031928170135e+00,
    -6.04244152148580987438e-02,
];
const RB: [f64; 7] = [
    -9.86494292470009928597e-03,
    -7.99283237680523006574e-01,
    -1.77579549177547519889e+01,
    -1.60636384855821916062e+02,
    -6.37566443368389627722e+02,
    -1.02509513161107724954e+03,
    -4.83519191608651397019e+02,
];
const SB: [f64; 7] = [
    3.03380607434824582924e+01,
    3.25792512996573918826e+02,
    1.53672958608443695994e+03,
    3.19985821950859553908e+03,
    2.55305040643316442583e+03,
    4.74528541206955367215e+02,
    -2.24409524465858183362e+01,
];

/// `c[0] + t·(c[1] + t·(…))`, Horner's scheme (fdlibm's order of operations).
#[inline(always)]
fn horner<const N: usize>(t: f64, c: &[f64; N]) -> f64 {
    let mut acc = c[N - 1];
    for k in (0..N - 1).rev() {
        acc = c[k] + t * acc;
    }
    acc
}

/// `1 + t·(c[0] + t·(…))`: fdlibm's denominators.
#[inline(always)]
fn one_plus<const N: usize>(t: f64, c: &[f64; N]) -> f64 {
    1.0 + t * horner(t, c)
}

/// Returns `(value, r, tail)` with `erfc(x) = value` where `tail` is false (`|x| < 1.25`,
/// or NaN), and `erfc(x) = value + exp(−x² − 0.5625 + r)/x` where it is true (`value` is
/// then 0 for `x > 0` and 2 for `x < 0`; `r` is fdlibm's `R/S`, computed at `|x|`
/// clamped to 28 beyond which the exponential is 0). Callers that already hold
/// `exp(−x²)` need only `exp(r − 0.5625)` more ([`crate::models::beckmann::mu_lambda`]);
/// [`erfc_f64`] splits the exponential for full accuracy. Branch-free, one division
/// for the region's rational (selected before dividing) and one for `1/x²`.
#[inline(always)]
pub fn erfc_parts_f64(x: f64) -> (f64, f64, bool) {
    let a = x.abs();
    let negative = x < 0.0;
    // NaN fails both comparisons and ends in the first region (NaN through `a + a·q`).
    let tail = a >= 1.25;
    let mid = a >= 0.84375;

    // Each region's rational, numerator and denominator, selected before the division.
    let z = a * a;
    let s = a - 1.0;
    let b = clamped(a);
    let t = 1.0 / (b * b);
    let near = b < 1.0 / 0.35;
    let (num, den) = if tail {
        if near {
            (horner(t, &RA), one_plus(t, &SA))
        } else {
            (horner(t, &RB), one_plus(t, &SB))
        }
    } else if mid {
        (horner(s, &PA), one_plus(s, &QA))
    } else {
        (horner(z, &PP), one_plus(z, &QQ))
    };
    let q = num / den;

    // a < 0.84375: erf = a + a·q.
    let small = if a < 0.25 {
        1.0 - (a + a * q)
    } else {
        0.5 - (a - 0.5 + a * q)
    };
    let small_neg = 1.0 + (a + a * q);
    // 0.84375 <= a < 1.25: erf = erx + q.
    let middle = 1.0 - ERX - q;
    let middle_neg = 1.0 + ERX + q;

    let value = if tail {
        if negative { 2.0 } else { 0.0 }
    } else if mid {
        if negative { middle_neg } else { middle }
    } else if negative {
        small_neg
    } else {
        small
    };
    (value, q, tail)
}

/// `|x|` clamped to the tail's range `[1.25, 28]` (no `1/0`, no `inf/inf`).
#[inline(always)]
fn clamped(a: f64) -> f64 {
    let b = if a > 1.25 { a } else { 1.25 };
    if b < 28.0 { b } else { 28.0 }
}

/// Returns `erfc(x)` for every `f64` (see the module doc); branch-free.
#[inline(always)]
pub fn erfc_f64(x: f64) -> f64 {
    let (value, r, tail) = erfc_parts_f64(x);
    let a = x.abs();
    let b = clamped(a);
    // fdlibm's split: z has 21 significant bits, so z² is exact.
    let zb = f64::from_bits(b.to_bits() & 0xFFFF_FFFF_0000_0000);
    let e = exp_f64(-zb * zb - 0.5625) * exp_f64((zb - b) * (zb + b) + r) / b;
    let e = if a >= 28.0 { 0.0 } else { e };
    if !tail {
        value
    } else if x < 0.0 {
        2.0 - e
    } else {
        e
    }
}

/// `erfc` for `f32`: [`erfc_f64`] of the widened argument, rounded once (vectorizes
/// as well; float32 kernels stay within 1 ulp).
#[inline(always)]
pub fn erfc_f32(x: f32) -> f32 {
    erfc_f64(f64::from(x)) as f32
}

/// [`erfc_parts_f64`] for `f32`, from the widened argument.
#[inline(always)]
pub fn erfc_parts_f32(x: f32) -> (f32, f32, bool) {
    let (value, r, tail) = erfc_parts_f64(f64::from(x));
    (value as f32, r as f32, tail)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::fastmath::tests::ulps;

    /// Within 5 ulps of libm's scalar erfc (the same approximations, another `exp`; each
    /// within ~2.3 ulps of the exact value) at every region, its edges and both signs;
    /// the tails through the subnormals.
    #[test]
    fn matches_libm_erfc() {
        let mut xs: Vec<f64> = vec![
            0.0,
            -0.0,
            1e-300,
            5e-324,
            1e-20,
            2.0f64.powi(-56),
            0.25,
            0.84375,
            1.25,
            1.0 / 0.35,
            6.0,
            26.5,
            27.2,
            27.99,
            28.0,
            30.0,
            1e10,
            1e300,
        ];
        for edge in [0.25, 0.84375, 1.25, 1.0 / 0.35, 28.0] {
            let mut v: f64 = edge;
            for _ in 0..4 {
                v = f64::from_bits(v.to_bits() - 1);
                xs.push(v);
            }
            let mut v: f64 = edge;
            for _ in 0..4 {
                v = f64::from_bits(v.to_bits() + 1);
                xs.push(v);
            }
        }
        let n = 200_000;
        for i in 0..n {
            xs.push(-1.5 + 31.0 * (i as f64 + 0.5) / n as f64);
            xs.push(10f64.powf(-20.0 + 21.5 * (i as f64 + 0.5) / n as f64));
        }
        let mut worst = (0.0, 0.0);
        for &x0 in &xs {
            for x in [x0, -x0] {
                let (got, want) = (erfc_f64(x), libm::erfc(x));
                // Below the normal range compare in units of the smallest subnormal.
                let err = if want < f64::MIN_POSITIVE {
                    (got - want).abs() / 5e-324
                } else {
                    ulps(got, want)
                };
                if err > worst.0 {
                    worst = (err, x);
                }
            }
        }
        assert!(worst.0 <= 5.0, "{} ulps at x = {:e}", worst.0, worst.1);
    }

    /// The parts recombine to erfc: `value` alone below 1.25, `value + exp(−x² − 0.5625 +
    /// r)/x` beyond (the form `mu_lambda` uses, with one rounding of x² more).
    #[test]
    fn parts_recombine_to_erfc() {
        for i in 0..20_001 {
            let x = -27.0 + 54.0 * i as f64 / 20_000.0;
            let (value, r, tail) = erfc_parts_f64(x);
            assert_eq!(tail, x.abs() >= 1.25);
            let got = if tail {
                value + (-x * x - 0.5625 + r).exp() / x
            } else {
                value
            };
            let want = erfc_f64(x);
            let scale = if x < 0.0 { 2.0 } else { want };
            // The rounding of x² moves exp(−x²) by up to x²·2^-53 relatively.
            // Subnormal results (x > 26.5) keep fewer digits: an absolute floor.
            let tol = 1e-15 * (1.0 + x * x) * scale + 1e-310;
            assert!((got - want).abs() <= tol, "{x}: {got} {want}");
        }
    }

    #[test]
    fn special_values() {
        assert_eq!(erfc_f64(0.0), 1.0);
        assert_eq!(erfc_f64(f64::INFINITY), 0.0);
        assert_eq!(erfc_f64(f64::NEG_INFINITY), 2.0);
        assert_eq!(erfc_f64(28.0), 0.0);
        assert!(erfc_f64(f64::NAN).is_nan());
        assert!(erfc_f64(27.0) > 0.0 && erfc_f64(27.0) < 1e-300);
        assert_eq!(erfc_f32(0.0), 1.0);
        assert_eq!(erfc_f32(f32::INFINITY), 0.0);
        assert_eq!(erfc_f32(-f32::INFINITY), 2.0);
    }
}
