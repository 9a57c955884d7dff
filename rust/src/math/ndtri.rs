//! The standard normal quantile `Φ⁻¹(p)`, without iteration.
//!
//! Wichura's rational approximations, Algorithm AS 241 (`PPND16`): M. J. Wichura, "The
//! Percentage Points of the Normal Distribution", Applied Statistics 37(3), 477–484,
//! 1988. Three degree-7/7 rational functions (the centre `|p − 1/2| <= 0.425` in
//! `0.180625 − q²`, then `r = sqrt(−ln min(p, 1 − p))` up to 5 and beyond); the published
//! coefficients below, relative error about 1e-16. No libm function inverts `erf`, and a
//! statistics crate (statrs) would be a dependency tree for one function; the test checks
//! the values against scipy's `ndtri` (Cephes, an independent implementation).

// The coefficients as published (20 significant digits), so they can be checked against
// the paper; the compiler rounds them to the nearest f64.
#![allow(clippy::excessive_precision)]

/// Centre: `q·A(r)/B(r)`, `r = 0.180625 − q²`.
const A: [f64; 8] = [
    3.387_132_872_796_366_608,
    1.331_416_678_917_843_774_5e2,
    1.971_590_950_306_551_442_7e3,
    1.373_169_376_550_946_112_5e4,
    4.592_195_393_154_987_145_7e4,
    6.726_577_092_700_870_085_3e4,
    3.343_057_558_358_812_810_5e4,
    2.509_080_928_730_122_672_7e3,
];
const B: [f64; 8] = [
    1.0,
    4.231_333_070_160_091_125_2e1,
    6.871_870_074_920_579_083e2,
    5.394_196_021_424_751_107_7e3,
    2.121_379_430_158_659_586_7e4,
    3.930_789_580_009_271_061e4,
    2.872_908_573_572_194_267_4e4,
    5.226_495_278_852_854_561e3,
];
/// Tails with `r = sqrt(−ln p) <= 5`: `C(r − 1.6)/D(r − 1.6)`.
const C: [f64; 8] = [
    1.423_437_110_749_683_577_34,
    4.630_337_846_156_545_295_9,
    5.769_497_221_460_691_405_5,
    3.647_848_324_763_204_605_04,
    1.270_458_252_452_368_382_58,
    2.417_807_251_774_506_117_7e-1,
    2.272_384_498_926_918_458_33e-2,
    7.745_450_142_783_414_076_4e-4,
];
const D: [f64; 8] = [
    1.0,
    2.053_191_626_637_758_821_87,
    1.676_384_830_183_803_849_4,
    6.897_673_349_851_000_045_5e-1,
    1.481_039_764_274_800_745_9e-1,
    1.519_866_656_361_645_719_66e-2,
    5.475_938_084_995_344_946e-4,
    1.050_750_071_644_416_843_24e-9,
];
/// Far tails, `r > 5` (`p < 1.4e-11`): `E(r − 5)/F(r − 5)`.
const E: [f64; 8] = [
    6.657_904_643_501_103_777_2,
    5.463_784_911_164_114_369_9,
    1.784_826_539_917_291_335_8,
    2.965_605_718_285_048_912_3e-1,
    2.653_218_952_657_612_309_3e-2,
    1.242_660_947_388_078_438_6e-3,
    2.711_555_568_743_487_578_15e-5,
    2.010_334_399_292_288_132_65e-7,
];
const F: [f64; 8] = [
    1.0,
    5.998_322_065_558_879_376_9e-1,
    1.369_298_809_227_358_053_1e-1,
    1.487_536_129_085_061_485_25e-2,
    7.868_691_311_456_132_591e-4,
    1.846_318_317_510_054_681_8e-5,
    1.421_511_758_316_445_888_7e-7,
    2.044_263_103_389_939_785_64e-15,
];

/// The smallest tail probability resolved: `ndtri(p)` for `0 <= p < 1e-300` is
/// `ndtri(1e-300)` ≈ −37.0 (finite: no infinities for samplers to propagate).
const P_MIN: f64 = 1e-300;

#[inline(always)]
fn ratio(c: &[f64; 8], d: &[f64; 8], r: f64) -> f64 {
    let mut num = c[7];
    let mut den = d[7];
    for k in (0..7).rev() {
        num = num * r + c[k];
        den = den * r + d[k];
    }
    num / den
}

/// Returns `Φ⁻¹(p)` for `p` in `[0, 1]`, given `p` and its complement `1 − p` (pass
/// `1.0 - p` when it is exact, or the complement kept by the caller: the upper tail's
/// digits come from it). The ends are finite (about ±37); NaN gives NaN.
#[inline(always)]
pub fn ndtri_pair(p: f64, one_minus_p: f64) -> f64 {
    if p.is_nan() {
        return p;
    }
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180_625 - q * q;
        return q * ratio(&A, &B, r);
    }
    let tail = if q < 0.0 { p } else { one_minus_p };
    let r = (-tail.max(P_MIN).ln()).sqrt();
    let x = if r <= 5.0 {
        ratio(&C, &D, r - 1.6)
    } else {
        ratio(&E, &F, r - 5.0)
    };
    if q < 0.0 { -x } else { x }
}

/// Returns `Φ⁻¹(p)` for `p` in `[0, 1]` (see [`ndtri_pair`]; `1 − p` is exact for `p`
/// in `[1/2, 1]`, so the upper tail keeps its digits).
#[inline(always)]
pub fn ndtri(p: f64) -> f64 {
    ndtri_pair(p, 1.0 - p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values from `scipy.special.ndtri` (Cephes), printed with `repr`.
    #[test]
    fn matches_scipy_ndtri() {
        let cases = [
            (0.5, 0.0),
            (0.6, 0.253_347_103_135_799_7),
            (0.9, 1.281_551_565_544_600_4),
            (0.075, -1.439_531_470_938_456_3),
            (0.925, 1.439_531_470_938_456_3),
            (0.01, -2.326_347_874_040_840_8),
            (0.999, 3.090_232_306_167_813),
            (1e-10, -6.361_340_902_404_056),
            (1e-20, -9.262_340_089_798_409),
            (1e-300, -37.047_096_299_361_2),
        ];
        for (p, want) in cases {
            let got = ndtri(p);
            assert!(
                (got - want).abs() <= 4.0 * f64::EPSILON * want.abs().max(1e-300),
                "ndtri({p}) = {got}, scipy {want}"
            );
        }
        assert_eq!(ndtri(0.0), ndtri(1e-300));
        assert_eq!(ndtri(1.0), -ndtri(1e-300));
        assert!(ndtri(f64::NAN).is_nan());
    }

    /// `Φ(Φ⁻¹(p)) = p` through libm's `erfc` over the whole range, to the accuracy the
    /// problem's condition allows (`Φ` multiplies a relative error in `x` by
    /// `|x|·φ(x)/Φ(x) ≈ x²` in the tail).
    #[test]
    fn inverts_the_normal_cdf() {
        for k in 0..=2000 {
            let p = (k as f64 + 0.5) / 2001.0;
            let x = ndtri(p);
            let back = 0.5 * libm::erfc(-x / std::f64::consts::SQRT_2);
            assert!((back - p).abs() <= 1e-14 * p, "{p}: {x} -> {back}");
        }
        for e in 1..300 {
            let p = 10f64.powi(-e);
            let x = ndtri(p);
            let back = 0.5 * libm::erfc(-x / std::f64::consts::SQRT_2);
            assert!((back - p).abs() <= 1e-12 * p, "{p}: {x} -> {back}");
        }
    }
}
