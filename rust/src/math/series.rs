//! Branch-free `sin(πx)`, `cos(πx)` and `expm1` for the samplers' vectorized loops
//! (libm's versions are calls that stop auto-vectorization).

use super::fastmath::exp_f64;

/// Coefficients of `sin(πt) = t·Σ s_k (t²)^k` and `cos(πt) = Σ c_k (t²)^k` (Taylor
/// series, enough terms for |t| <= 1/2, where the first omitted term is below 2^-60).
const SIN_PI: [f64; 11] = taylor_pi::<11>(1);
const COS_PI: [f64; 12] = taylor_pi::<12>(0);

/// `(−1)^k π^(2k+first) / (2k+first)!` for k = 0..N.
const fn taylor_pi<const N: usize>(first: u32) -> [f64; N] {
    let mut out = [0.0; N];
    let mut term = if first == 1 {
        std::f64::consts::PI
    } else {
        1.0
    };
    let mut k = 0;
    while k < N {
        out[k] = term;
        let n = (2 * k as u32 + first) as f64;
        // Next term: multiply by -π² / ((n+1)(n+2)).
        term = -term * std::f64::consts::PI * std::f64::consts::PI / ((n + 1.0) * (n + 2.0));
        k += 1;
    }
    out
}

#[inline(always)]
fn horner<const N: usize>(c: &[f64; N], z: f64) -> f64 {
    let mut acc = c[N - 1];
    let mut k = N - 1;
    while k > 0 {
        k -= 1;
        acc = acc * z + c[k];
    }
    acc
}

/// Returns `(sin(πx), cos(πx))` for `x` in `[0, 1)` (absolute error below 6e-16).
#[inline(always)]
pub fn sin_cos_pi(x: f64) -> (f64, f64) {
    // x = t + 1/2 with |t| <= 1/2: sin(πx) = cos(πt), cos(πx) = −sin(πt).
    let t = x - 0.5;
    let z = t * t;
    (horner(&COS_PI, z), -t * horner(&SIN_PI, z))
}

/// Coefficients `1/k!` for k = 1..=14 (expm1's Taylor series).
const INV_FACTORIAL: [f64; 14] = {
    let mut out = [0.0; 14];
    let mut f = 1.0;
    let mut k = 0;
    while k < 14 {
        f *= (k + 1) as f64;
        out[k] = 1.0 / f;
        k += 1;
    }
    out
};

/// Returns `e^y − 1`, accurate relative to itself also for tiny `y` (y <= 0 ... any
/// finite y; below 2 ulp). The series is used for |y| < 1/4, `exp(y) − 1` beyond.
#[inline(always)]
pub fn expm1_f64(y: f64) -> f64 {
    let small = y * horner(&INV_FACTORIAL, y);
    let large = exp_f64(y) - 1.0;
    if y.abs() < 0.25 { small } else { large }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sin_cos_pi_matches_libm() {
        let mut worst: f64 = 0.0;
        for i in 0..100_000 {
            let x = i as f64 / 100_000.0;
            let (s, c) = sin_cos_pi(x);
            let (es, ec) = (std::f64::consts::PI * x).sin_cos();
            worst = worst.max((s - es).abs()).max((c - ec).abs());
        }
        // libm sees π·x already rounded (1 ulp of up to π): 2 ulp of slack.
        assert!(worst < 6e-16, "{worst}");
    }

    #[test]
    fn expm1_is_relatively_accurate() {
        for &y in &[
            -1e-300, -1e-17, -1e-9, -1e-4, -0.1, -0.2499, -0.25, -0.7, -3.0, -700.0, 0.1, 2.0,
        ] {
            let got = expm1_f64(y);
            let want = y.exp_m1();
            assert!(
                (got - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
                "{y}: {got} {want}"
            );
        }
    }
}
