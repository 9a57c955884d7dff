//! Vectorizable, accurate `pow` / `exp` / `log` for BRDF hot loops.
//!
//! Public API (f64 and f32 each):
//! * `pow_unit_f64(x, one_minus_x, p)` / `pow_unit_f32`: x^p for x in [0, 1],
//!   accurate even when x is within 1e-12 of 1 (uses the caller's 1 - x).
//! * `pow_unit_table_f64`: the same f64 power from tables, for loops whose table
//!   lookups vectorize (see below), and `pow_unit_fast_f64` / `pow_unit_fast_f32`, the
//!   fast tier's (plain floating point, a stated relative error); the
//!   `_tier_` functions choose among the three ([`crate::math::PowTier`]), `over`
//!   variants included.
//! * `exp_f64` / `exp_f32`: e^x for all x (overflow to +inf, gradual underflow).
//! * `log_f64` / `log_f32`: ln x for x >= 0, subnormals included.
//!
//! Every public function is `#[inline(always)]`, branch-free (only selects
//! that LLVM lowers to blends/masks), table-free (but the `_table_` ones and the fast
//! tier's plain `f64` power) and free of libm calls, so a loop that calls it per element
//! auto-vectorizes for whatever the enclosing function is compiled for (SSE2, AVX2,
//! AVX-512: 8 f64 / 16 f32 lanes). No FMA is required: exact products come from
//! splitting operands with bit masks (the fdlibm `e_pow.c` technique), so the functions
//! give bit-identical results on every ISA. The exception is the fast tier's plain `f64`
//! power (`pow_unit_fast_f64`), written with fused multiply-adds (correctly rounded, so
//! the same bits wherever they run: one instruction where the caller is compiled with
//! FMA, as the eval engine's fast-tier loops are, a libm call elsewhere).
//!
//! Algorithm of `pow_unit_*` (x^p):
//! 1. Reduction: x = 2^k m, m in [1, 2); if m > sqrt(3) use m/2 (k+1);
//!    centre c = 1.5 if m > sqrt(3/2) else 1, f = m - c (exact). For
//!    x > sqrt(3)/2, f = -one_minus_x instead (k = 0, c = 1).
//! 2. log2(x) = k + log2(c) + (2/ln 2) atanh(s), s = f / (2c + f), |s| <= 0.102,
//!    written as (2/3) s (3 + s^2 + s^4 Q(s^2)) (Q: minimax, degree 5 in s^2
//!    for f64, 1 for f32). s, the bracket and the product by 2/(3 ln 2) are
//!    carried in double-double (f32: float-float): log2(x) = t1 + t2 with t1
//!    holding 21 (f32: 12) significant bits, relative error ~2^-66 (2^-33).
//! 3. y = p log2(x) = yh + yl with yh = hi(p) t1 exact (p split at 21 bits).
//! 4. n = round(yh + yl); z + w = (yh - n + yl) ln 2 in double-double;
//!    e^(z+w) = 1 + z + z^2/2 + z^3 P(z) + w (1 + z), P minimax of degree 8
//!    (f32: 3), evaluated by Estrin's scheme.
//! 5. m 2^n: in the normal range one exact product; in the subnormal range the
//!    result's bit pattern is obtained by rounding m 2^(n+1074) to an integer
//!    (f32: 2^(n+149)), so results go through the subnormals to +0 with one
//!    rounding and no floating-point operation ever produces a subnormal
//!    (those cost microcode assists of ~100+ cycles on x86).
//!
//! Because y is carried in double-double, the error does not grow with
//! |y| = |p log2 x|: measured max 0.64 ulp (f64) / 0.68 ulp (f32) over the
//! whole domain; a plain-double version is ~1.8x faster but its error grows to
//! ~1.4 |y| ulp (1400 ulp at |y| = 1000). Accuracy details on each function.
//!
//! `scripts/fastmath_coefficients.py` states where every constant comes from: it
//! recomputes the split and rounded constants bit for bit from their definitions,
//! states the approximation problem each polynomial solves (Sollya fpminimax: Q for
//! the relative error of 3 atanh(s), P for the absolute error of e^z) and measures
//! the coefficients' error on it; with `--sollya` it solves the problems anew (other
//! low-order bits than the ones below, whose Sollya run was not recorded, with the
//! same error to within 2%).

//! Table-driven f64 power (`pow_unit_table_f64`, ARM optimized-routines' `pow`,
//! no-FMA variant; tables and polynomials from `scripts/gen_pow_tables.py`, in
//! `pow_tables.rs`):
//! 1. log x: x = 2^k z, z in [0.705, 1.41) split into 128 entries {1/c, log c
//!    (a multiple of 2^-42), tail}; r = z/c - 1 = rhi + rlo exactly (1/c has 9
//!    bits, z_hi 21); log x = k ln2 + log c + r - r^2/2 + r^3 Q(r) (Q degree 5)
//!    carried in double-double. The entry holding 1.0 has c = 1. For
//!    x > sqrt(3)/2 the reduced argument is z = 1 - one_minus_x taken exactly, so
//!    x = 1 - 1e-20 keeps its digits; below one_minus_x = 2^-330, log x =
//!    -one_minus_x and the product is formed from scaled operands.
//! 2. y = p log x = ehi + elo with ehi exact (26-bit halves).
//! 3. e^y: y = k ln2/128 + r; 2^(i/128) from a 128-entry table {s, tail}, e^r by
//!    a degree-5 polynomial; m 2^n by `scale_f64` as above. Out-of-range y are
//!    clamped to 0 / +inf, tiny y to exactly 1; p below 2^-300 acts as 2^-300.
//!
//! Its five lookups are gathers in a vectorized loop: faster than the series power
//! in the eval engine's block loop, but in a loop LLVM then declines to vectorize
//! (the integrator's per-point lobe loop) much slower. So the caller picks
//! ([`crate::math::PowUnit`]); the test `table_pow_agrees_with_series_pow` keeps the
//! two within an ulp of each other. No FMA: bit-identical on every ISA too.

// The constants below are bit-exact literals (scripts/fastmath_coefficients.py);
// the decimal comments are for humans only.
#![allow(clippy::excessive_precision, clippy::unreadable_literal)]

use super::PowTier;

// ---- f64 ----
const SQRT3_F64: f64 = f64::from_bits(0x3ffbb67ae8584caa); // 1.7320508075688772 sqrt(3)
const SQRT1P5_F64: f64 = f64::from_bits(0x3ff3988e1409212e); // 1.224744871391589 sqrt(3/2)
const DP_H_F64: f64 = f64::from_bits(0x3fe2b80300000000); // 0.5849623680114746 log2(1.5) hi (21 bits)
const DP_L_F64: f64 = f64::from_bits(0x3e81cfdeb43cfd00); // 1.3270968157207873e-07 log2(1.5) lo
const CP_F64: f64 = f64::from_bits(0x3feec709dc3a03fd); // 0.9617966939259756 2/(3 ln2)
const CP_H_F64: f64 = f64::from_bits(0x3feec709dc200000); // 0.9617966937366873 2/(3 ln2) hi (32 bits)
const CP_L_F64: f64 = f64::from_bits(0x3dea03fd749fc155); // 1.8928830231719995e-10 lo
const LN2_F64: f64 = f64::from_bits(0x3fe62e42fefa39ef); // 0.6931471805599453 ln 2
const LN2_H32_F64: f64 = f64::from_bits(0x3fe62e42fee00000); // 0.6931471803691238 ln2 hi (32 bits)
const LN2_L32_F64: f64 = f64::from_bits(0x3dea39ef35793c76); // 1.9082149292705877e-10 lo
const LN2_H42_F64: f64 = f64::from_bits(0x3fe62e42fefa3800); // 0.6931471805598903 ln2 hi (42 bits, n*hi exact for |n|<2^11)
const LN2_L42_F64: f64 = f64::from_bits(0x3d2ef35793c76730); // 5.497923018708371e-14 lo
const LOG2E_F64: f64 = f64::from_bits(0x3ff71547652b82fe); // 1.4426950408889634 log2(e)
// ---- f32 ----
const SQRT3_F32: f32 = f32::from_bits(0x3fddb3d7); // 1.7320507764816284 sqrt(3)
const SQRT1P5_F32: f32 = f32::from_bits(0x3f9cc471); // 1.2247449159622192 sqrt(3/2)
const DP_H_F32: f32 = f32::from_bits(0x3f15c000); // 0.5849609375 log2(1.5) hi (12 bits)
const DP_L_F32: f32 = f32::from_bits(0x35d1cfdf); // 1.5632211898264359e-06 lo
const CP_F32: f32 = f32::from_bits(0x3f76384f); // 0.9617967009544373 2/(3 ln2)
const CP_H_F32: f32 = f32::from_bits(0x3f763000); // 0.961669921875 hi (12 bits)
const CP_L_F32: f32 = f32::from_bits(0x3904ee1d); // 0.00012677205086220056 lo
const LN2_F32: f32 = f32::from_bits(0x3f317218); // 0.6931471824645996 ln 2
const LN2_H12_F32: f32 = f32::from_bits(0x3f317000); // 0.693115234375 ln2 hi (12 bits)
const LN2_L12_F32: f32 = f32::from_bits(0x3805fdf4); // 3.194618329871446e-05 lo
const LN2_H16_F32: f32 = f32::from_bits(0x3f317200); // 0.693145751953125 ln2 hi (16 bits, n*hi exact for |n|<2^8)
const LN2_L16_F32: f32 = f32::from_bits(0x35bfbe8e); // 1.428606765330187e-06 lo
const LOG2E_F32: f32 = f32::from_bits(0x3fb8aa3b); // 1.4426950216293335 log2(e)
// Q64 (Horner order, lowest degree first)
const Q64_0: f64 = f64::from_bits(0x3fe3333333333303); // 0.5999999999999946 
const Q64_1: f64 = f64::from_bits(0x3fdb6db6db6fa95a); // 0.4285714285785126 
const Q64_2: f64 = f64::from_bits(0x3fd5555551936d14); // 0.33333332983393515 
const Q64_3: f64 = f64::from_bits(0x3fd17460a5f96432); // 0.27272812088409915 
const Q64_4: f64 = f64::from_bits(0x3fcd864cb8927745); // 0.23066100132285264 
const Q64_5: f64 = f64::from_bits(0x3fca7de18dc35f69); // 0.2069665853693963 
// Q32 (Horner order, lowest degree first)
const Q32_0: f32 = f32::from_bits(0x3f199844); // 0.5999796390533447 
const Q32_1: f32 = f32::from_bits(0x3ede2c50); // 0.433931827545166 
// P64 (Horner order, lowest degree first)
const P64_0: f64 = f64::from_bits(0x3fc555555555557b); // 0.1666666666666677 
const P64_1: f64 = f64::from_bits(0x3fa5555555552fb1); // 0.0416666666665998 
const P64_2: f64 = f64::from_bits(0x3f8111111110736c); // 0.008333333333263325 
const P64_3: f64 = f64::from_bits(0x3f56c16c17d8f195); // 0.0013888888928611277 
const P64_4: f64 = f64::from_bits(0x3f2a01a01daf3cfb); // 0.00019841270008533876 
const P64_5: f64 = f64::from_bits(0x3efa019a882fa094); // 2.480150625308647e-05 
const P64_6: f64 = f64::from_bits(0x3ec71dd9aab71fa4); // 2.7557137707058143e-06 
const P64_7: f64 = f64::from_bits(0x3e928a2568306e6b); // 2.7626206405989326e-07 
const P64_8: f64 = f64::from_bits(0x3e5afef9893955a4); // 2.5141979677287986e-08 
// P32 (Horner order, lowest degree first)
const P32_0: f32 = f32::from_bits(0x3e2aaa46); // 0.16666516661643982 
const P32_1: f32 = f32::from_bits(0x3d2aaa5e); // 0.04166638106107712 
const P32_2: f32 = f32::from_bits(0x3c091eed); // 0.00836918968707323 
const P32_3: f32 = f32::from_bits(0x3ab6bf81); // 0.0013942570658400655 

const SQRT3_HALF_F64: f64 = SQRT3_F64 * 0.5; // exact halving: consistent with `m > SQRT3_F64`
const SQRT3_HALF_F32: f32 = SQRT3_F32 * 0.5;
/// 1.5 * 2^52: adding it rounds |v| < 2^51 to an integer held in the low mantissa bits.
const SHIFT_F64: f64 = 6755399441055744.0;
const SHIFT_BITS_F64: u64 = 0x4338_0000_0000_0000;
/// 1.5 * 2^23.
const SHIFT_F32: f32 = 12582912.0;
const SHIFT_BITS_F32: u32 = 0x4B40_0000;
const TWO52_F64: f64 = 4503599627370496.0;
const TWO52_BITS_F64: u64 = 0x4330_0000_0000_0000;
const TWO23_F32: f32 = 8388608.0;
const TWO23_BITS_F32: u32 = 0x4B00_0000;
const TWO54_F64: f64 = 18014398509481984.0;
const TWO24_F32: f32 = 16777216.0;
const TWO64_F32: f32 = 18446744073709551616.0;
const TWO_M64_F32: f32 = 1.0 / 18446744073709551616.0;
const TWO_M90_F32: f32 = 8.077935669463161e-28; // 2^-90
const TWO_M500_F64: f64 = 3.054936363499605e-151; // 2^-500
const TWO_M60_F32: f32 = 8.673617379884035e-19; // 2^-60
const ONE_BITS_F64: u64 = 0x3FF0_0000_0000_0000;
const ONE_BITS_F32: u32 = 0x3F80_0000;
const TWO_M30_F64: f64 = f64::from_bits(993 << 52); // 2^-30
const TWO_M200_F64: f64 = f64::from_bits(823 << 52); // 2^-200
const TWO_M300_F64: f64 = f64::from_bits(723 << 52); // 2^-300
const TWO_M330_F64: f64 = f64::from_bits(693 << 52); // 2^-330
const TWO_M400_F64: f64 = f64::from_bits(623 << 52); // 2^-400
const TWO_M600_F64: f64 = f64::from_bits(423 << 52); // 2^-600
const TWO600_F64: f64 = f64::from_bits(1623 << 52); // 2^600
/// Start of the logarithm table's reduced range (z in [OFF, 2 OFF), OFF ~ 0.7051).
const LOG_OFF_BITS: u64 = 0x3FE6_9555_0000_0000;

include!("pow_tables.rs");

// ------------------------------------------------------------------ helpers

/// `x` with the low 32 mantissa bits cleared: at most 21 significant bits, so
/// the product of two such values (or of one and a 32-bit constant) is exact.
#[inline(always)]
fn hi21(x: f64) -> f64 {
    f64::from_bits(x.to_bits() & 0xFFFF_FFFF_0000_0000)
}

/// `x` with the low 12 mantissa bits cleared: at most 12 significant bits.
#[inline(always)]
fn hi12(x: f32) -> f32 {
    f32::from_bits(x.to_bits() & 0xFFFF_F000)
}

/// a * b + c: one fused multiply-add if `FMA`, else a rounded product and sum.
/// Only used where either rounding is fine (polynomials, small corrections).
#[inline(always)]
fn mla<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

/// f32 version of [`mla`].
#[inline(always)]
fn mla32<const FMA: bool>(a: f32, b: f32, c: f32) -> f32 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

// ---------------------------------------------------------------------- f64

/// Reduction of x >= 0 (subnormals included): returns (k, f, c15) with
/// x = 2^k * (c + f), c = 1.5 if `c15` else 1, f exact, |f/(2c+f)| <= 0.102.
#[inline(always)]
fn reduce_f64(x: f64) -> (f64, f64, bool) {
    let (m, e) = split_f64(x);
    let big = m > SQRT3_F64;
    let c15 = !big & (m > SQRT1P5_F64);
    let m = if big { m * 0.5 } else { m };
    let c = if c15 { 1.5 } else { 1.0 };
    let k = e + if big { 1.0 } else { 0.0 };
    (k, m - c, c15)
}

/// log2(2^k (c + f)) as t1 + t2 (t1 has <= 21 significant bits), relative
/// error about 2^-66. `f` must be exact and |f / (2c + f)| <= 0.102.
#[inline(always)]
fn log2_dd_f64<const FMA: bool>(k: f64, f: f64, c15: bool) -> (f64, f64) {
    let two_c = if c15 { 3.0 } else { 2.0 };
    let dp_h = if c15 { DP_H_F64 } else { 0.0 };
    let dp_l = if c15 { DP_L_F64 } else { 0.0 };
    // s = f / (2c + f) as s_h + s_l
    let d = two_c + f;
    let d_h = hi21(d);
    let d_l = (two_c - d_h) + f;
    let inv = 1.0 / d;
    let ss = f * inv;
    let s_h = hi21(ss);
    let s_l = inv * ((f - s_h * d_h) - s_h * d_l);
    // ln(1 + f/c) = 2 atanh(s) = (2/3) s (3 + s^2 + s^4 Q(s^2))
    let s2 = ss * ss;
    // s^4 Q is negligible below this; the clamp keeps s2 * s2 out of the
    // subnormal range (subnormal results cost a microcode assist).
    let s2 = if s2 < TWO_M500_F64 { TWO_M500_F64 } else { s2 };
    // Q(s2) by Estrin's scheme (shorter dependency chain than Horner)
    let s4 = s2 * s2;
    let q01 = mla::<FMA>(s2, Q64_1, Q64_0);
    let q23 = mla::<FMA>(s2, Q64_3, Q64_2);
    let q45 = mla::<FMA>(s2, Q64_5, Q64_4);
    let q = mla::<FMA>(s4, mla::<FMA>(s4, q45, q23), q01);
    let r = mla::<FMA>(s4, q, s_l * (s_h + ss));
    let sh2 = s_h * s_h;
    let t_h = hi21(3.0 + sh2 + r);
    let t_l = r - ((t_h - 3.0) - sh2);
    // s * t = u + v  (u exact)
    let u = s_h * t_h;
    let v = mla::<FMA>(s_l, t_h, t_l * ss);
    let p_h = hi21(u + v);
    let p_l = v - (p_h - u);
    // times 2/(3 ln 2), plus log2(c) and k
    let z_h = CP_H_F64 * p_h;
    let z_l = mla::<FMA>(CP_L_F64, p_h, mla::<FMA>(p_l, CP_F64, dp_l));
    let t1 = hi21(((z_h + z_l) + dp_h) + k);
    let t2 = z_l - (((t1 - k) - dp_h) - z_h);
    (t1, t2)
}

/// e^(z + w) in [0.7, 1.42] for |z| <= 0.3487, |w| <= 2^-40 |z| + 2^-60.
#[inline(always)]
fn exp_mant_f64<const FMA: bool>(z: f64, w: f64) -> f64 {
    // e^z - 1 - z - z^2/2 = z^3 P(z)
    // P(z) by Estrin's scheme (shorter dependency chain than Horner)
    let z2 = z * z;
    let z4 = z2 * z2;
    let p01 = mla::<FMA>(z, P64_1, P64_0);
    let p23 = mla::<FMA>(z, P64_3, P64_2);
    let p45 = mla::<FMA>(z, P64_5, P64_4);
    let p67 = mla::<FMA>(z, P64_7, P64_6);
    let p03 = mla::<FMA>(z2, p23, p01);
    let p47 = mla::<FMA>(z2, p67, p45);
    let p48 = mla::<FMA>(z4, P64_8, p47);
    let pz = mla::<FMA>(z4, p48, p03);
    let q = z2 * mla::<FMA>(z, pz, 0.5); // z^2/2 + z^3 P(z)
    let c = q + mla::<FMA>(z, w, w);
    let s = 1.0 + z;
    let e = (1.0 - s) + z; // exact (Fast2Sum)
    s + (e + c)
}

/// m * 2^n, rounded once, for m in [0.7, 1.42] and n in [-1100, 1024] given
/// as `kd` = 1.5 * 2^52 + n. Overflows to +inf, underflows through the
/// subnormals to +0 without any floating-point operation producing a
/// subnormal (those cost ~100+ cycle microcode assists on x86).
#[inline(always)]
fn scale_f64(m: f64, kd: f64) -> f64 {
    scale_in_f64::<false>(m, kd)
}

/// [`scale_f64`]; with `NORMAL`, for an `n` known to be at least -1021 (the normal range),
/// without the subnormal range's path (the same bits there).
#[inline(always)]
fn scale_in_f64<const NORMAL: bool>(m: f64, kd: f64) -> f64 {
    let kbits = kd.to_bits();
    let sub = !NORMAL && kd - SHIFT_F64 < -1021.5; // n <= -1022
    // normal range, n in [-1021, 1024]: (2m) * 2^(n-1) (exact, or overflow);
    // lanes in the subnormal range use n = 0 here.
    let kb = if sub { SHIFT_BITS_F64 } else { kbits };
    let rn = (m * 2.0) * f64::from_bits((kb << 52).wrapping_add(1022 << 52));
    // subnormal range, n in [-1100, -1022]: r = m * 2^(n+1074) is exact and
    // r rounded to an integer is the bit pattern of the subnormal result.
    let kb = if sub { kbits } else { SHIFT_BITS_F64 - 1100 };
    let r = m * f64::from_bits((kb << 52).wrapping_add((1074 + 1023) << 52));
    let rb = if r < TWO52_F64 {
        (r + TWO52_F64).to_bits().wrapping_sub(TWO52_BITS_F64)
    } else {
        r.to_bits().wrapping_sub(1074 << 52) // n = -1022, m >= 1: normal result
    };
    if sub { f64::from_bits(rb) } else { rn }
}

/// 2^-e, exactly, for an integer |e| <= 1100: +inf beyond the float range (e < -1024), the
/// subnormals and 0 below it. The value of the `f64` powers' special cases (x = 1, p = 0)
/// in their scaled forms, without evaluating an exponential for it.
#[inline(always)]
fn pow2_neg_f64(e: f64) -> f64 {
    // scale_f64 takes n = -e up to 1024; n = 1025 gives +inf.
    scale_f64(1.0, SHIFT_F64 - if e < -1025.0 { -1025.0 } else { e })
}

/// 2^(yh + yl - e) for an integer |e| <= 1100 (pow path; `e` = 0 for a plain power);
/// exactly 0 below 2^-1100 and +inf beyond the float range.
#[inline(always)]
fn exp2_dd_f64<const FMA: bool>(yh: f64, yl: f64, e: f64) -> f64 {
    // far below the subnormal range: replace by 2^-1100 (rounds to +0) so
    // that garbage in yl cannot reach the arithmetic; far above: by 2^1025 (+inf)
    let dead = yh - e < -1090.0;
    let huge = yh - e > 1024.0;
    let yh = if dead { e - 1100.0 } else { yh };
    let yh = if huge { e + 1025.0 } else { yh };
    let yl = if dead | huge { 0.0 } else { yl };
    // n = round(yh + yl): |yl| can reach 2^-10 (f32: 0.15), so rounding yh
    // alone could push |y - n| past the polynomial's range.
    let kd = (yh + yl) + SHIFT_F64;
    let n = kd - SHIFT_F64;
    let rh = yh - n; // exact
    let t = hi21(rh + yl);
    let u = t * LN2_H32_F64; // exact
    let v = mla::<FMA>(yl - (t - rh), LN2_F64, t * LN2_L32_F64);
    let z = u + v;
    let w = v - (z - u);
    // kd - e = 1.5 * 2^52 + n - e, exact: the scaling by 2^-e is folded into 2^n
    scale_f64(exp_mant_f64::<FMA>(z, w), kd - e)
}

/// x^p 2^-e for x in [0, 1] and an integer e with |e| <= 1100 (`e` = 0: plain x^p,
/// bit for bit); see [`pow_unit_f64`]. Results beyond the float range are +inf.
#[inline(always)]
fn pow_unit_scaled_f64<const FMA: bool>(x: f64, one_minus_x: f64, p: f64, e: f64, kx: f64) -> f64 {
    // The base is x·2^-kx: its exponent enters the double-double log2 exactly.
    let (k, f, c15) = reduce_f64(x);
    let k = k - kx;
    let f = if x > SQRT3_HALF_F64 { -one_minus_x } else { f };
    let (t1, t2) = log2_dd_f64::<FMA>(k, f, c15);
    // y = p * (t1 + t2) = yh + yl, yh exact
    let p1 = hi21(p);
    let yh = p1 * t1;
    let yl = mla::<FMA>(p - p1, t1, p * t2);
    let r = exp2_dd_f64::<FMA>(yh, yl, e);
    let one = pow2_neg_f64(e);
    special_cases_f64(x, one_minus_x, p, r, one)
}

#[inline(always)]
fn pow_unit_impl_f64<const FMA: bool>(x: f64, one_minus_x: f64, p: f64) -> f64 {
    pow_unit_scaled_f64::<FMA>(x, one_minus_x, p, 0.0, 0.0)
}

/// Splits d > 0 (subnormal included) as m 2^e, m in [1, 2); e as an f64. (d = 0 gives
/// m = 1, e = -1077; callers select such lanes away.)
#[inline(always)]
fn split_f64(d: f64) -> (f64, f64) {
    let tiny = d < f64::MIN_POSITIVE;
    let ds = if tiny { d * TWO54_F64 } else { d };
    let bits = ds.to_bits();
    // biased exponent -> f64 without an int->float conversion instruction
    let e = f64::from_bits((bits >> 52) | TWO52_BITS_F64) - 4503599627371519.0; // 2^52+1023
    let m = f64::from_bits((bits & 0x000F_FFFF_FFFF_FFFF) | ONE_BITS_F64);
    (m, e - if tiny { 54.0 } else { 0.0 })
}

/// The divisor of the `over` powers, d = m 2^e ([`split_f64`]). An e outside the
/// exponent range (d = 0, inf, NaN: callers select those away) would corrupt the bit
/// tricks: it is kept in range.
#[inline(always)]
fn split_divisor_f64(d: f64) -> (f64, f64) {
    let (m, e) = split_f64(d);
    (m, if e > -1100.0 && e < 1100.0 { e } else { 0.0 })
}

/// The exact special cases of x^p 2^-e on top of the computed `r`: `one` = 2^-e where
/// p == 0 (also 0^0) or one_minus_x == 0, and 0 where x == 0 (p > 0).
#[inline(always)]
fn special_cases_f64(x: f64, one_minus_x: f64, p: f64, r: f64, one: f64) -> f64 {
    let r = if one_minus_x == 0.0 { one } else { r };
    let r = if x == 0.0 { 0.0 } else { r };
    if p == 0.0 { one } else { r }
}

/// x^p 2^-e / m from the logarithm's product y = p ln x (`ln_y`, about: it decides the
/// halves) and `exp(e)` = e^y 2^-e, as the table-driven and the fast powers form it:
/// with `OVER`, a quotient above 1 is formed as (x^p 2^-(e+1)) / (m/2) so that the
/// dividend cannot overflow while the quotient is below 2^1024; without, `m` is 1.
#[inline(always)]
fn over_from_halves_f64<const OVER: bool>(
    x: f64,
    one_minus_x: f64,
    p: f64,
    ln_y: f64,
    e: f64,
    m: f64,
    exp: impl Fn(f64) -> f64,
) -> f64 {
    let big = OVER && ln_y - e * LN2_F64 > 0.0; // (p = 0 lanes: y ~ 0, big iff e < 0)
    let e = if big { e + 1.0 } else { e };
    let m = if big { m * 0.5 } else { m };
    let r = exp(e);
    let one = pow2_neg_f64(e);
    let r = special_cases_f64(x, one_minus_x, p, r, one);
    if OVER { r / m } else { r }
}

/// x^p / d for x in [0, 1] (given with `one_minus_x`, as [`pow_unit_f64`]) and finite
/// d > 0, without underflow of x^p before the division: d = m 2^e is split exactly and
/// the result is (x^p 2^-e) / m, so `x^p` below the float range still counts when `d`
/// is tiny (`cos^p / mu_i` at mu_i = 1e-300). p == 0 gives 1/d; beyond the float range,
/// +inf. Two roundings (about 1 ulp more than [`pow_unit_f64`]).
#[inline(always)]
pub fn pow_unit_over_f64(x: f64, one_minus_x: f64, p: f64, d: f64) -> f64 {
    pow_unit_over_scaled_f64(x, one_minus_x, p, 0.0, d)
}

/// `(x·2^-kx)^p / d`: [`pow_unit_over_f64`] of a base below the float range, carried
/// as `x` in `(0, 2^-400]` with the extra exponent `kx` (an integer, `0 <= kx <= 600`;
/// `kx = 0` is [`pow_unit_over_f64`] bit for bit). The exponent enters the logarithm
/// exactly, so a cosine of 1e-320 (10 significant bits as a subnormal) keeps all 53.
#[inline(always)]
pub fn pow_unit_over_scaled_f64(x: f64, one_minus_x: f64, p: f64, kx: f64, d: f64) -> f64 {
    pow_unit_over_scaled_tier_f64(PowTier::Series, x, one_minus_x, p, kx, d)
}

/// x^p for x in [0, 1], given both x and `one_minus_x` = 1 - x.
///
/// * For x > sqrt(3)/2 the result is (1 - one_minus_x)^p: `one_minus_x` is
///   taken as exact and `x` only selects the path. For x <= sqrt(3)/2, x is
///   used and `one_minus_x` is ignored. So x = 1 - 1e-12 with
///   `one_minus_x` = 1e-12 keeps full accuracy.
/// * Domain: 0 <= x <= 1 (subnormal x fine), 0 <= one_minus_x <= 1
///   (subnormal fine), p finite, 0 <= p <= 1e300.
/// * Exact special cases: p == 0 -> 1 (also 0^0), x == 0 (p > 0) -> 0,
///   one_minus_x == 0 -> 1. Underflow goes through the subnormals to +0.
///   Never NaN inside the domain.
/// * Accuracy, measured against 72-digit mpmath on 462k vectors (uniform and
///   log-uniform x, x = 1 - 2^-k for k = 1..60, one_minus_x = 1e-9 with p up
///   to 1.5e12, one_minus_x down to 1e-320 with p up to 1e300, subnormal x,
///   |y| = |p log2 x| up to 1100): max 0.64 ulp on normal results (median
///   0.25, p99 0.52), i.e. <= 0.2x the (4 + |y|) 2^-53 budget, with no growth
///   in |y|; max 0.79 ulp of 2^-1074 on subnormal results.
/// * Branch-free, table-free, no libm, no FMA needed; results are identical
///   bit for bit on SSE2, AVX2 and AVX-512 builds.
#[inline(always)]
pub fn pow_unit_f64(x: f64, one_minus_x: f64, p: f64) -> f64 {
    pow_unit_impl_f64::<false>(x, one_minus_x, p)
}

/// e^x for every f64 x: overflows to +inf above ~709.78, goes through the
/// subnormals to +0 below ~-708.4 (0 below ~-745.13), NaN -> NaN.
/// Accuracy vs mpmath (110k points over [-745, 710] and |x| in [1e-20, 1]):
/// max 0.63 ulp on normal results, 0.76 ulp of 2^-1074 on subnormal ones.
/// Branch-free, table-free, no libm.
#[inline(always)]
pub fn exp_f64(x: f64) -> f64 {
    let xc = if x < -760.0 { -760.0 } else { x };
    let xc = if xc > 710.0 { 710.0 } else { xc };
    let kd = xc * LOG2E_F64 + SHIFT_F64;
    let n = kd - SHIFT_F64;
    let zh = xc - n * LN2_H42_F64; // exact (Cody-Waite, |n| < 2^11)
    let zl = n * -LN2_L42_F64;
    let z = zh + zl;
    let w = (zh - z) + zl;
    scale_f64(exp_mant_f64::<false>(z, w), kd)
}

/// ln x for x > 0, subnormals included; ln 0 = -inf, ln +inf = +inf,
/// x < 0 or NaN -> NaN. Accuracy vs mpmath (100k points over the whole
/// positive range, near 1, subnormal x): max 0.50 ulp.
/// Branch-free, table-free, no libm.
#[inline(always)]
pub fn log_f64(x: f64) -> f64 {
    let (k, f, c15) = reduce_f64(x);
    let (t1, t2) = log2_dd_f64::<false>(k, f, c15);
    let r = t1 * LN2_H32_F64 + (t1 * LN2_L32_F64 + t2 * LN2_F64);
    let r = if x == 0.0 { f64::NEG_INFINITY } else { r };
    let r = if x == f64::INFINITY { x } else { r };
    if x >= 0.0 { r } else { f64::NAN }
}

// ------------------------------------------------------- table-driven pow (f64)

/// ln x as `(hi, lo)`, `hi + lo` within about 2^-68 of ln x relatively, for a normal
/// positive finite `x` (the double-width logarithm of the table-driven pow below).
#[inline]
pub fn log_dd_f64(x: f64) -> (f64, f64) {
    log_dd_in_f64::<true>(x, 0.0, false, 0.0)
}

/// log(x 2^-kx) as hi + lo (|lo| <~ 2^-52 |hi|), relative error about 2^-68, for
/// 0 < xr < inf (subnormal fine). With `near`, the reduced argument is taken as
/// 1 - `omc` exactly (xr must then be 1 - omc rounded, in [0.705, 1], and kx = 0).
/// The table-driven logarithm's reduction of x >= 0: x = 2^k z with z in [OFF, 2 OFF),
/// returned as the table entry `i` of z, k (as an `f64`) and z. A subnormal x is scaled by
/// 2^52 first (k counts it); with `NORMAL`, for an x known to be normal, without that
/// scaling (the same bits there).
#[inline(always)]
fn log_reduce_f64<const NORMAL: bool>(x: f64) -> (usize, f64, f64) {
    let sub = !NORMAL && x < f64::MIN_POSITIVE;
    let xs = if sub { x * TWO52_F64 } else { x };
    let ix = xs.to_bits();
    // entry i from the top mantissa bits of ix - OFF
    let tmp = ix.wrapping_sub(LOG_OFF_BITS);
    let i = ((tmp >> 45) & 127) as usize;
    // k = tmp >> 52 (arithmetic), as an f64 without a 64-bit int -> float conversion
    let kb = (tmp ^ (1 << 63)) >> 52; // k + 2048
    let k = f64::from_bits(kb | TWO52_BITS_F64) - (TWO52_F64 + 2048.0);
    let k = k - if sub { 52.0 } else { 0.0 };
    (i, k, f64::from_bits(ix.wrapping_sub(tmp & (0xfff << 52))))
}

/// ARM optimized-routines' `log_inline` of `pow` (no-FMA variant), with a split of
/// r = z/c - 1 into rhi + rlo that stays exact for z = 1 - omc.
///
/// With `NORMAL`, for an `xr` known to be in the normal range, without the subnormal
/// scaling (the same bits there).
#[inline(always)]
fn log_dd_in_f64<const NORMAL: bool>(xr: f64, omc: f64, near: bool, kx: f64) -> (f64, f64) {
    let (i, k, z) = log_reduce_f64::<NORMAL>(xr);
    let k = k - kx;
    let iz = z.to_bits();
    let invc = LOG_INVC[i];
    let logc = LOG_LOGC[i];
    let logctail = LOG_LOGCTAIL[i];
    // r = z invc - 1 = rhi + rlo, both exact: zhi has 21 bits, invc 9, and zlo
    // (<= 2^-22) at most 41 bits; near 1, zlo = (1 - zhi) - omc is exact (Sterbenz)
    // and has at most 41 bits wherever invc != 1.
    let zhi = f64::from_bits((iz + (1 << 31)) & (u64::MAX << 32));
    let zlo = if near { (1.0 - zhi) - omc } else { z - zhi };
    let rhi = zhi * invc - 1.0;
    let rlo = zlo * invc;
    let r = rhi + rlo;
    // k ln2 + log(c) + r: t1 and t2 are exact (multiples of 2^-42 below 2^11)
    let t1 = k * LN2_HI + logc;
    let t2 = t1 + rhi;
    let s = t2 + rlo;
    let lo2 = (t2 - s) + rlo; // Fast2Sum: t2 = 0 or |t2| >= |rlo|
    let lo1 = k * LN2_LO + logctail;
    // + log1p(r) - r = -r^2/2 + r^3 Q(r)
    let ar = -0.5 * r;
    let ar2 = r * ar;
    let ar3 = r * ar2;
    let arhi = -0.5 * rhi;
    let arhi2 = rhi * arhi; // exact
    let hi = s + arhi2;
    let lo3 = rlo * (ar + arhi);
    let lo4 = (s - hi) + arhi2;
    let q = ar3
        * (LOG_A[0]
            + r * LOG_A[1]
            + ar2 * (LOG_A[2] + r * LOG_A[3] + ar2 * (LOG_A[4] + r * LOG_A[5])));
    let lo = lo1 + lo2 + lo3 + lo4 + q;
    let y = hi + lo;
    (y, (hi - y) + lo)
}

/// e^(xh + xl) 2^-e for an integer |e| <= 1100, |xl| <= 2^-24 |xh| (the pow product);
/// exactly 0 below 2^-1100 (through the subnormals with one rounding), +inf beyond
/// the float range. ARM's `exp_inline` with a 2^(i/128) table and degree-5 polynomial,
/// made branch-free: out-of-range arguments are clamped, and tiny ones replaced by 0
/// (result 1) so that r^4 cannot underflow.
#[inline(always)]
fn exp_dd_f64(xh: f64, xl: f64, e: f64) -> f64 {
    exp_dd_in_f64::<false>(xh, xl, e)
}

/// [`exp_dd_f64`]; with `ORDINARY`, for an `xh - e ln 2` known to be in
/// [`ORDINARY_POW_Y`] (the same bits there: no clamp applies, the result is normal).
#[inline(always)]
fn exp_dd_in_f64<const ORDINARY: bool>(xh: f64, xl: f64, e: f64) -> f64 {
    let eln2 = e * LN2_F64;
    let dead = !ORDINARY && xh - eln2 < -1090.0 * LN2_F64;
    let huge = !ORDINARY && xh - eln2 > 1024.01 * LN2_F64;
    let small = !ORDINARY && xh.abs() < TWO_M200_F64;
    let xh = if small { 0.0 } else { xh };
    let xh = if dead { eln2 - 1100.0 * LN2_F64 } else { xh };
    let xh = if huge { eln2 + 1024.5 * LN2_F64 } else { xh };
    let xl = if dead | huge | small { 0.0 } else { xl };
    // x = k ln2/128 + r, |r| <= ln2/256 (+ |xl|)
    let kd = xh * INV_LN2_N + SHIFT_F64;
    let ki = kd.to_bits();
    let kf = kd - SHIFT_F64;
    let r = (xh - kf * LN2_N_HI) - kf * LN2_N_LO; // xh - kf hi: exact (Sterbenz)
    let r = r + xl;
    let i = (ki & 127) as usize;
    let s = EXP_S[i];
    let tail = EXP_TAIL[i];
    let r2 = r * r;
    let tmp = tail + r + r2 * (EXP_C[0] + r * EXP_C[1]) + r2 * r2 * (EXP_C[2] + r * EXP_C[3]);
    let m = s + s * tmp; // 2^(i/128) e^r in [0.997, 2.006)
    // 1.5 * 2^52 + floor(k / 128), then - e (exact)
    let nb = (ki >> 7).wrapping_add(SHIFT_BITS_F64 - (SHIFT_BITS_F64 >> 7));
    scale_in_f64::<ORDINARY>(m, f64::from_bits(nb) - e)
}

/// x^p 2^-e / m for x 2^-kx with x in [0, 1] (given with `one_minus_x` as in
/// [`pow_unit_f64`]), integers |e| <= 1100 and 0 <= kx <= 600 (kx > 0 only for
/// x <= 2^-400), m in [1, 2). `e = kx = 0, m = 1`: plain x^p, bit for bit.
/// With `OVER`, a quotient above 1 is formed as (x^p 2^-(e+1)) / (m/2) so that
/// the dividend cannot overflow while the quotient is below 2^1024.
#[inline(always)]
fn pow_scaled_f64<const OVER: bool>(
    x: f64,
    one_minus_x: f64,
    p: f64,
    e: f64,
    kx: f64,
    m: f64,
) -> f64 {
    pow_scaled_in_f64::<OVER, false>(x, one_minus_x, p, e, kx, m).0
}

/// The logarithm products `y = p ln x` (`ehi`, the high half) for which the table-driven
/// power's special cases and clamps are all idle, given an ordinary base and exponent
/// (see [`pow_unit_table_ordinary_f64`]): a normal result above 2^-1000, and `|y|` at
/// least 2^-200.
const ORDINARY_POW_Y: (f64, f64) = (-1000.0 * LN2_F64, -TWO_M200_F64);

/// Whether a power's lane is ordinary, given its logarithm product `y = p ln x` (the
/// table-driven power's high half, or the fast power's rounded `y`): `x` in the normal
/// range, `1 − x` at least 2^-330, `p` at least 2^-300 and `y` in [`ORDINARY_POW_Y`].
/// The test of both powers' short ways ([`pow_unit_table_ordinary_f64`],
/// [`pow_unit_fast_ordinary_f64`]).
#[inline(always)]
fn ordinary_lane_f64(x: f64, one_minus_x: f64, p: f64, y: f64) -> bool {
    let (lo, hi) = ORDINARY_POW_Y;
    (x >= f64::MIN_POSITIVE)
        & (one_minus_x >= TWO_M330_F64)
        & (p >= TWO_M300_F64)
        & (y > lo)
        & (y <= hi)
}

/// [`pow_scaled_f64`], and with `ORDINARY` its arithmetic for an ordinary lane only (see
/// [`pow_unit_table_ordinary_f64`]): every select that such a lane leaves idle is left
/// out, so its bits are the same. Also returns `ehi`.
#[inline(always)]
fn pow_scaled_in_f64<const OVER: bool, const ORDINARY: bool>(
    x: f64,
    one_minus_x: f64,
    p: f64,
    e: f64,
    kx: f64,
    m: f64,
) -> (f64, f64) {
    let near = x > SQRT3_HALF_F64;
    // one_minus_x < 2^-330: log x = -one_minus_x to 2^-330 relative, and the
    // polynomial's r^3 would underflow: y = -(p 2^-600)(one_minus_x 2^600) instead.
    let tiny = !ORDINARY && near & (one_minus_x < TWO_M330_F64);
    let omc = if tiny { TWO_M30_F64 } else { one_minus_x };
    let xr = if near { 1.0 - omc } else { x };
    let xr = if !ORDINARY && x == 0.0 { 1.0 } else { xr };
    let (lh, ll) = log_dd_in_f64::<ORDINARY>(xr, omc, near, kx);
    // p below 2^-300 gives |y| < 2^-289 (result 1, as for 2^-300): keeps products normal
    let pc = if !ORDINARY && p < TWO_M300_F64 {
        TWO_M300_F64
    } else {
        p
    };
    let ps = pc * TWO_M600_F64;
    let ps = if ps < TWO_M400_F64 { TWO_M400_F64 } else { ps }; // then |y| < 2^-130
    let pp = if tiny { ps } else { pc };
    let lh = if tiny {
        -(one_minus_x * TWO600_F64)
    } else {
        lh
    };
    let ll = if tiny { 0.0 } else { ll };
    // y = pp (lh + ll) = ehi + elo, ehi exact (26-bit halves)
    let p_hi = f64::from_bits(pp.to_bits() & (u64::MAX << 27));
    let p_lo = pp - p_hi;
    let l_hi = f64::from_bits(lh.to_bits() & (u64::MAX << 27));
    let l_lo = (lh - l_hi) + ll;
    let ehi = p_hi * l_hi;
    let elo = p_lo * l_hi + pp * l_lo;
    if ORDINARY {
        // No special case applies (x, 1 − x and p are nonzero, OVER is off): the power.
        return (exp_dd_in_f64::<true>(ehi, elo, e), ehi);
    }
    let r = over_from_halves_f64::<OVER>(x, one_minus_x, p, ehi, e, m, |e| exp_dd_f64(ehi, elo, e));
    (r, ehi)
}

/// [`pow_unit_table_f64`] for a lane whose inputs and result are ordinary, and whether
/// they were: `x` in the normal range, `1 − x` at least 2^-330, `p` at least 2^-300 and
/// `y = p ln x` in [`ORDINARY_POW_Y`] (a normal result, no clamp). For such a lane the
/// value is [`pow_unit_table_f64`]'s bit for bit, computed without the selects that its
/// special cases need (about a fifth of the arithmetic); for any other lane it is
/// garbage, and the flag false. The eval engine runs a block's powers this way and
/// again the general way if a lane was not ordinary.
#[inline(always)]
pub fn pow_unit_table_ordinary_f64(x: f64, one_minus_x: f64, p: f64) -> (f64, bool) {
    let (r, ehi) = pow_scaled_in_f64::<false, true>(x, one_minus_x, p, 0.0, 0.0, 1.0);
    (r, ordinary_lane_f64(x, one_minus_x, p, ehi))
}

/// [`pow_unit_f64`] from tables: the same contract, table-driven (ARM
/// optimized-routines' `pow` scheme, no FMA; the module doc's second part). Faster
/// where its five table lookups vectorize (gathers: the eval engine's block loop),
/// much slower where they stop a loop from vectorizing (the integrator's per-point
/// lobe loop): the caller chooses, through [`crate::math::PowUnit`].
#[inline(always)]
pub fn pow_unit_table_f64(x: f64, one_minus_x: f64, p: f64) -> f64 {
    pow_scaled_f64::<false>(x, one_minus_x, p, 0.0, 0.0, 1.0)
}

// ---------------------------------------------------------------------- f32

/// f32 analogue of [`reduce_f64`].
#[inline(always)]
fn reduce_f32(x: f32) -> (f32, f32, bool) {
    let (m, e) = split_f32(x);
    let big = m > SQRT3_F32;
    let c15 = !big & (m > SQRT1P5_F32);
    let m = if big { m * 0.5 } else { m };
    let c = if c15 { 1.5 } else { 1.0 };
    let k = e + if big { 1.0 } else { 0.0 };
    (k, m - c, c15)
}

/// f32 analogue of [`log2_dd_f64`] (float-float, t1 has <= 12 bits).
/// `fs` is `f` times a power of two 2^j (j = 0, or j = 64 for |f| < 2^-90 and
/// k = 0, c = 1: then the result is 2^j log2(1 + f) to ~2^-33 relative and
/// no intermediate becomes subnormal).
#[inline(always)]
fn log2_dd_f32<const FMA: bool>(k: f32, f: f32, fs: f32, c15: bool) -> (f32, f32) {
    let two_c = if c15 { 3.0 } else { 2.0 };
    let dp_h = if c15 { DP_H_F32 } else { 0.0 };
    let dp_l = if c15 { DP_L_F32 } else { 0.0 };
    let d = two_c + f;
    let d_h = hi12(d);
    let d_l = (two_c - d_h) + f;
    let inv = 1.0 / d;
    let ss = fs * inv;
    let s_h = hi12(ss);
    let s_l = inv * ((fs - s_h * d_h) - s_h * d_l);
    let s2 = ss * ss;
    let s2 = if s2 < TWO_M60_F32 { TWO_M60_F32 } else { s2 };
    let q = mla32::<FMA>(s2, Q32_1, Q32_0);
    let r = mla32::<FMA>(s2 * s2, q, s_l * (s_h + ss));
    let sh2 = s_h * s_h;
    let t_h = hi12(3.0 + sh2 + r);
    let t_l = r - ((t_h - 3.0) - sh2);
    let u = s_h * t_h;
    let v = mla32::<FMA>(s_l, t_h, t_l * ss);
    let p_h = hi12(u + v);
    let p_l = v - (p_h - u);
    let z_h = CP_H_F32 * p_h;
    let z_l = mla32::<FMA>(CP_L_F32, p_h, mla32::<FMA>(p_l, CP_F32, dp_l));
    let t1 = hi12(((z_h + z_l) + dp_h) + k);
    let t2 = z_l - (((t1 - k) - dp_h) - z_h);
    (t1, t2)
}

/// f32 analogue of [`exp_mant_f64`].
#[inline(always)]
fn exp_mant_f32<const FMA: bool>(z: f32, w: f32) -> f32 {
    let z2 = z * z;
    let p01 = mla32::<FMA>(z, P32_1, P32_0);
    let p23 = mla32::<FMA>(z, P32_3, P32_2);
    let pz = mla32::<FMA>(z2, p23, p01);
    let q = z2 * mla32::<FMA>(z, pz, 0.5);
    let c = q + mla32::<FMA>(z, w, w);
    let s = 1.0 + z;
    let e = (1.0 - s) + z;
    s + (e + c)
}

/// f32 analogue of [`scale_f64`]: m * 2^n for n in [-170, 128],
/// `kd` = 1.5 * 2^23 + n.
#[inline(always)]
fn scale_f32(m: f32, kd: f32) -> f32 {
    let kbits = kd.to_bits();
    let sub = kd - SHIFT_F32 < -125.5; // n <= -126
    let kb = if sub { SHIFT_BITS_F32 } else { kbits };
    let rn = (m * 2.0) * f32::from_bits((kb << 23).wrapping_add(126 << 23));
    let kb = if sub { kbits } else { SHIFT_BITS_F32 - 170 };
    let r = m * f32::from_bits((kb << 23).wrapping_add((149 + 127) << 23));
    let rb = if r < TWO23_F32 {
        (r + TWO23_F32).to_bits().wrapping_sub(TWO23_BITS_F32)
    } else {
        r.to_bits().wrapping_sub(149 << 23)
    };
    if sub { f32::from_bits(rb) } else { rn }
}

/// 2^-e, exactly, for an integer |e| < 160: +inf beyond the float range (e < -128), the
/// subnormals and 0 below it. The value of the `f32` powers' special cases (x = 1, p = 0)
/// in their scaled forms, without evaluating an exponential for it.
#[inline(always)]
fn pow2_neg_f32(e: f32) -> f32 {
    // scale_f32 takes n = -e up to 128; n = 129 gives +inf.
    scale_f32(1.0, SHIFT_F32 - e.max(-129.0))
}

/// f32 analogue of [`exp2_dd_f64`]: 2^(yh + yl - e), |e| <= 160; exactly 0 below
/// 2^-170, +inf beyond the float range.
#[inline(always)]
fn exp2_dd_f32<const FMA: bool>(yh: f32, yl: f32, e: f32) -> f32 {
    let dead = yh - e < -160.0;
    let huge = yh - e > 128.0;
    let yh = if dead { e - 170.0 } else { yh };
    let yh = if huge { e + 129.0 } else { yh };
    let yl = if dead | huge { 0.0 } else { yl };
    let kd = (yh + yl) + SHIFT_F32;
    let n = kd - SHIFT_F32;
    let rh = yh - n; // exact
    let t = hi12(rh + yl);
    let u = t * LN2_H12_F32;
    let v = mla32::<FMA>(yl - (t - rh), LN2_F32, t * LN2_L12_F32);
    let z = u + v;
    let w = v - (z - u);
    scale_f32(exp_mant_f32::<FMA>(z, w), kd - e)
}

/// f32 analogue of [`pow_unit_scaled_f64`]: x^p 2^-e, |e| <= 160.
#[inline(always)]
fn pow_unit_scaled_f32<const FMA: bool>(x: f32, one_minus_x: f32, p: f32, e: f32) -> f32 {
    let (k, f, c15) = reduce_f32(x);
    let near1 = x > SQRT3_HALF_F32;
    let f = if near1 { -one_minus_x } else { f };
    // Tiny one_minus_x with huge p: compute 2^64 log2(x) and use p 2^-64, so
    // that no intermediate of the log goes subnormal (f32 p reaches 2^128).
    let tiny = near1 & (one_minus_x < TWO_M90_F32);
    let fs = if tiny { f * TWO64_F32 } else { f };
    let p = if tiny { p * TWO_M64_F32 } else { p };
    let (t1, t2) = log2_dd_f32::<FMA>(k, f, fs, c15);
    let p1 = hi12(p);
    let yh = p1 * t1;
    let yl = mla32::<FMA>(p - p1, t1, p * t2);
    let r = exp2_dd_f32::<FMA>(yh, yl, e);
    let one = pow2_neg_f32(e);
    let r = if one_minus_x == 0.0 { one } else { r };
    let r = if x == 0.0 { 0.0 } else { r };
    if p == 0.0 { one } else { r }
}

#[inline(always)]
fn pow_unit_impl_f32<const FMA: bool>(x: f32, one_minus_x: f32, p: f32) -> f32 {
    pow_unit_scaled_f32::<FMA>(x, one_minus_x, p, 0.0)
}

/// f32 analogue of [`split_f64`].
#[inline(always)]
fn split_f32(d: f32) -> (f32, f32) {
    let tiny = d < f32::MIN_POSITIVE;
    let ds = if tiny { d * TWO24_F32 } else { d };
    let bits = ds.to_bits();
    let e = f32::from_bits((bits >> 23) | TWO23_BITS_F32) - 8388735.0; // 2^23+127
    let m = f32::from_bits((bits & 0x007F_FFFF) | ONE_BITS_F32);
    (m, e - if tiny { 24.0 } else { 0.0 })
}

/// The divisor of the `f32` `over` powers, d = m·2^e, as (m, e) with m in [1, 2), or as
/// (m/2, e + 1) where d < 2^-120: x^p·2^-e (at most 2^-e) can only overflow there, and
/// x^p·2^-(e+1) is below the quotient x^p/d, so it does not overflow where the quotient
/// does not (a quotient within a factor 2 of `f32::MAX` over a subnormal d). An e outside
/// (-160, 160) (d = 0, inf, NaN: callers select those away) is taken as 0.
#[inline(always)]
fn split_divisor_f32(d: f32) -> (f32, f32) {
    let (m, e) = split_f32(d);
    let e = if e > -160.0 && e < 160.0 { e } else { 0.0 };
    let low = e < -120.0;
    (if low { m * 0.5 } else { m }, if low { e + 1.0 } else { e })
}

/// f32 analogue of [`pow_unit_over_f64`]: x^p / d without underflow of x^p first.
#[inline(always)]
pub fn pow_unit_over_f32(x: f32, one_minus_x: f32, p: f32, d: f32) -> f32 {
    let (m, e) = split_divisor_f32(d);
    pow_unit_scaled_f32::<false>(x, one_minus_x, p, e) / m
}

/// f32 x^p for x in [0, 1]; same contract as [`pow_unit_f64`], computed in
/// f32 only (16 lanes on AVX-512); p finite, 0 <= p <= f32::MAX.
/// Accuracy vs an f64 reference on the f32 inputs (2.4M random vectors of the
/// same kinds as for f64, |y| up to 150): max 0.68 ulp on normal results
/// (median 0.25, p99 0.53, <= 0.2x the (4 + |y|) 2^-24 budget), max 0.79 ulp
/// of 2^-149 on subnormal results.
#[inline(always)]
pub fn pow_unit_f32(x: f32, one_minus_x: f32, p: f32) -> f32 {
    pow_unit_impl_f32::<false>(x, one_minus_x, p)
}

/// f32 e^x for every x: +inf above ~88.72, subnormals then +0 below
/// ~-87.34 (0 below ~-103.97), NaN -> NaN. Exhaustive check over every f32
/// in [-104, 89] against f64 exp: max 0.672 ulp on normal results, 0.780 ulp
/// of 2^-149 on subnormal ones.
#[inline(always)]
pub fn exp_f32(x: f32) -> f32 {
    let xc = if x < -110.0 { -110.0 } else { x };
    let xc = if xc > 89.0 { 89.0 } else { xc };
    let kd = xc * LOG2E_F32 + SHIFT_F32;
    let n = kd - SHIFT_F32;
    let zh = xc - n * LN2_H16_F32; // exact, |n| < 2^8
    let zl = n * -LN2_L16_F32;
    let z = zh + zl;
    let w = (zh - z) + zl;
    scale_f32(exp_mant_f32::<false>(z, w), kd)
}

/// f32 ln x for x > 0, subnormals included; ln 0 = -inf, ln +inf = +inf,
/// x < 0 or NaN -> NaN. Exhaustive check over every positive finite f32
/// against f64 ln: max 0.502 ulp.
#[inline(always)]
pub fn log_f32(x: f32) -> f32 {
    let (k, f, c15) = reduce_f32(x);
    let (t1, t2) = log2_dd_f32::<false>(k, f, f, c15);
    let r = t1 * LN2_H12_F32 + (t1 * LN2_L12_F32 + t2 * LN2_F32);
    let r = if x == 0.0 { f32::NEG_INFINITY } else { r };
    let r = if x == f32::INFINITY { x } else { r };
    if x >= 0.0 { r } else { f32::NAN }
}

// ----------------------------------------------------------- the fast tier

// fdlibm's `e_log.c` minimax coefficients of (log(1+f) - 2s)/s - ... in s^2 (relative
// error below 2^-58.45 on |s| <= 0.1716), and its split of ln 2 (the high part has 32
// significant bits: k * LN2_HI is exact for |k| < 2^21).
const LG1: f64 = f64::from_bits(0x3FE5555555555593); // 6.666666666666735130e-01
const LG2: f64 = f64::from_bits(0x3FD999999997FA04); // 3.999999999940941908e-01
const LG3: f64 = f64::from_bits(0x3FD2492494229359); // 2.857142874366239149e-01
const LG4: f64 = f64::from_bits(0x3FCC71C51D8E78AF); // 2.222219843214978396e-01
const LG5: f64 = f64::from_bits(0x3FC7466496CB03DE); // 1.818357216161805012e-01
const LG6: f64 = f64::from_bits(0x3FC39A09D078C69F); // 1.531383769920937332e-01
const LG7: f64 = f64::from_bits(0x3FC2F112DF3E5244); // 1.479819860511658591e-01
const SQRT2_F64: f64 = std::f64::consts::SQRT_2;

/// ln(x·2^-kx) for x in [0, 1] given with `one_minus_x` (used for x > √3/2, where it is
/// the reduced argument, exactly as given), in plain `f64`: fdlibm's `log` scheme,
/// x = 2^k (1 + f) with 1 + f in [1/√2, √2], s = f/(2 + f), ln(1 + f) = f − (f²/2 −
/// s (f²/2 + R(s²))). Within about 1 ulp of the exact logarithm; x = 0 gives a finite
/// value (the caller selects the result).
#[inline(always)]
fn ln_fast_f64(x: f64, one_minus_x: f64, kx: f64) -> f64 {
    let (m, e) = split_f64(x);
    let big = m > SQRT2_F64;
    let m = if big { m * 0.5 } else { m };
    // From √3/2 on the complement is the base, as for the accurate powers (the caller's x
    // and 1 − x may disagree in their last bits); below, f = x − 1 is exact.
    let near = x > SQRT3_HALF_F64;
    let k = e + if big { 1.0 } else { 0.0 } - kx;
    let k = if near { 0.0 } else { k };
    let f = if near { -one_minus_x } else { m - 1.0 }; // m − 1: exact (Sterbenz)
    // A division, not Newton's reciprocal (three steps from a linear estimate, 2.5e-15):
    // measured with benches/eval_ab.py, the division's shorter latency ran Torrance-Sparrow
    // float64 4% faster, though the divider is the loop's busiest unit.
    let s = f / (2.0 + f);
    let z = s * s;
    // Below 2^-500, R(z) is negligible next to f; the clamp keeps z² out of the
    // subnormal range (a subnormal result costs a microcode assist).
    let z = if z < TWO_M500_F64 { TWO_M500_F64 } else { z };
    let w = z * z;
    let t1 = w * (LG2 + w * (LG4 + w * LG6));
    let t2 = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7)));
    let r = t2 + t1;
    let fc = if f.abs() < TWO_M400_F64 { 0.0 } else { f };
    let hfsq = 0.5 * fc * fc;
    k * LN2_H32_F64 - ((hfsq - (s * (hfsq + r) + k * LN2_L32_F64)) - f)
}

/// e^y·2^-e for an integer |e| <= 1100: exactly 0 below 2^-1100 (through the
/// subnormals with one rounding, [`scale_f64`]) and +inf beyond the float range. The
/// reduction y = n ln 2 + r takes n·ln2 in two parts (n·LN2_H32 exact), e^r (|r| <=
/// ln2/2) is [`exp_mant_f64`]'s polynomial: about 1 ulp, plus the error y carries in.
#[inline(always)]
fn exp_fast_f64(y: f64, e: f64) -> f64 {
    let lo = (e - 1100.0) * LN2_F64;
    let hi = (e + 1025.0) * LN2_F64;
    let y = if y < lo { lo } else { y };
    let y = if y > hi { hi } else { y };
    let kd = y * LOG2E_F64 + SHIFT_F64;
    let n = kd - SHIFT_F64;
    let r = (y - n * LN2_H32_F64) - n * LN2_L32_F64;
    // e^r − 1 − r = r²/2 + r³ P(r), Estrin's scheme.
    let r2 = r * r;
    let r4 = r2 * r2;
    let p01 = r * P64_1 + P64_0;
    let p23 = r * P64_3 + P64_2;
    let p45 = r * P64_5 + P64_4;
    let p67 = r * P64_7 + P64_6;
    let p03 = r2 * p23 + p01;
    let p47 = r2 * p67 + p45;
    let p48 = r4 * P64_8 + p47;
    let pr = r4 * p48 + p03;
    let q = r2 * (r * pr + 0.5);
    scale_f64(1.0 + (r + q), kd - e)
}

/// x^p·2^-e / m for x·2^-kx (x in [0, 1] with `one_minus_x`, integers |e| <= 1100 and
/// 0 <= kx <= 600, m in [1, 2)): e^(p·ln x) in plain `f64`. A quotient above 1 is formed
/// from halves, so it does not overflow below 2^1024. Special cases as [`pow_unit_f64`].
#[inline(always)]
fn pow_fast_scaled_f64(x: f64, one_minus_x: f64, p: f64, e: f64, kx: f64, m: f64) -> f64 {
    let y = p * ln_fast_f64(x, one_minus_x, kx);
    over_from_halves_f64::<true>(x, one_minus_x, p, y, e, m, |e| exp_fast_f64(y, e))
}

/// The fast tier's x^p (`brdf_rs.eval(..., precision="fast")`): the contract of
/// [`pow_unit_f64`] (domain, the complement, special cases, no NaN, underflow through
/// the subnormals) in plain `f64` with fused multiply-adds: the table-driven power's
/// scheme with four lookups instead of five and no double-double. `r = z/c − 1` in one
/// rounding (from the complement where `x > √3/2`: `z = 1 − omc` exactly,
/// `r = (invc − 1) − omc·invc`), `ln x = (k·ln2_hi + log c) + (r + (k·ln2_lo + tail +
/// log1p(r) − r))` (the first sum exact), `y = p·ln x` rounded once, and `e^y` from
/// `2^(i/128)` rounded (without its tail).
///
/// Error: ln x is within about 1.5 ulps and the product rounds once more, so the result
/// is within `(3 + 3|y|)·2^-53` relative. A normal result has |y| < 745, so at most
/// 2.5e-13 (measured by `fast_pow_is_within_its_bound` against [`pow_unit_f64`], itself
/// within 0.64 ulp of the exact power); the subnormal results are within that relative
/// error plus one unit of 2^-1074.
///
/// Fused multiply-adds are single instructions only where the caller is compiled with
/// FMA: the eval engine compiles the fast tier's loops for AVX2 and AVX-512 only.
#[inline(always)]
pub fn pow_unit_fast_f64(x: f64, one_minus_x: f64, p: f64) -> f64 {
    pow_fast_fma_in_f64::<false>(x, one_minus_x, p).0
}

/// [`pow_unit_fast_f64`] for a lane expected to be ordinary, and whether it was (the
/// conditions of [`pow_unit_table_ordinary_f64`]): for such a lane the same bits,
/// computed without the selects of the special cases and clamps; for any other lane
/// garbage, and the flag false.
#[inline(always)]
pub fn pow_unit_fast_ordinary_f64(x: f64, one_minus_x: f64, p: f64) -> (f64, bool) {
    let (value, y) = pow_fast_fma_in_f64::<true>(x, one_minus_x, p);
    (value, ordinary_lane_f64(x, one_minus_x, p, y))
}

/// [`pow_unit_fast_f64`], and with `ORDINARY` its arithmetic for an ordinary lane only
/// (see [`pow_unit_fast_ordinary_f64`]): every select such a lane leaves idle is left
/// out, so its bits are the same. Also returns `y = p·ln x`.
#[inline(always)]
fn pow_fast_fma_in_f64<const ORDINARY: bool>(x: f64, one_minus_x: f64, p: f64) -> (f64, f64) {
    let near = x > SQRT3_HALF_F64;
    let xr = if near { 1.0 - one_minus_x } else { x };
    // A zero base takes any finite logarithm (its value is selected below); a subnormal
    // one is scaled into the normal range.
    let xr = if !ORDINARY && x == 0.0 { 1.0 } else { xr };
    // x = 2^k z (k = 0 where `near`).
    let (i, k, z) = log_reduce_f64::<ORDINARY>(xr);
    let invc = LOG_INVC[i];
    // invc − 1 is exact (invc in [0.7, 1.42], Sterbenz).
    let r = if near {
        (-one_minus_x).mul_add(invc, invc - 1.0)
    } else {
        z.mul_add(invc, -1.0)
    };
    // log1p(r) − r = ar2 + ar3·Q(r), ar2 = −r²/2, ar3 = −r³/2 (the accurate table's Q).
    let ar2 = -0.5 * r * r;
    let ar3 = r * ar2;
    let q_hi = LOG_A[5].mul_add(r, LOG_A[4]);
    let q_mid = LOG_A[3].mul_add(r, LOG_A[2]);
    let q_lo = LOG_A[1].mul_add(r, LOG_A[0]);
    let q = ar2.mul_add(ar2.mul_add(q_hi, q_mid), q_lo);
    // k·ln2_hi + log c is exact (multiples of 2^-42 below 2^11), as in `log_dd_in_f64`.
    let t = k.mul_add(LN2_HI, LOG_LOGC[i]);
    let lo = ar3.mul_add(q, ar2) + k.mul_add(LN2_LO, LOG_LOGCTAIL[i]);
    let ln = t + (r + lo);
    let y = p * ln;
    // A complement below 2^-330: ln x = −omc to 2^-330 relative (finite: omc ≤ 2^-330).
    let tiny = !ORDINARY && near & (one_minus_x < TWO_M330_F64);
    let y = if tiny { -(p * one_minus_x) } else { y };
    // |y| < 2^-200 gives 1 (and keeps r⁴ normal); below 2^-1090, 0 through the
    // subnormals (y ≤ 0: x ≤ 1).
    let ye = if !ORDINARY && y.abs() < TWO_M200_F64 {
        0.0
    } else {
        y
    };
    let ye = if !ORDINARY && ye < -1090.0 * LN2_F64 {
        -1100.0 * LN2_F64
    } else {
        ye
    };
    // e^y: y = n ln2/128 + r2 (both reductions exact with FMA), 2^(n/128) = 2^(n >> 7)
    // · s, s = 2^((n & 127)/128) rounded, e^r2 by the accurate table's polynomial.
    let kd = ye.mul_add(INV_LN2_N, SHIFT_F64);
    let ki = kd.to_bits();
    let kf = kd - SHIFT_F64;
    let r = kf.mul_add(-LN2_N_LO, kf.mul_add(-LN2_N_HI, ye));
    let s = EXP_S[(ki & 127) as usize];
    let r2 = r * r;
    let tail = r2.mul_add(
        r2.mul_add(EXP_C[3].mul_add(r, EXP_C[2]), EXP_C[1].mul_add(r, EXP_C[0])),
        r,
    );
    let m = s.mul_add(tail, s);
    let nb = (ki >> 7).wrapping_add(SHIFT_BITS_F64 - (SHIFT_BITS_F64 >> 7));
    let value = scale_in_f64::<ORDINARY>(m, f64::from_bits(nb));
    if ORDINARY {
        return (value, y);
    }
    let value = if one_minus_x == 0.0 { 1.0 } else { value };
    let value = if x == 0.0 { 0.0 } else { value };
    (if p == 0.0 { 1.0 } else { value }, y)
}

// fdlibm's `e_logf.c` minimax coefficients of the same scheme in `f32` (|(ln(1 + s) −
// ln(1 − s))/s − Lg(s)| < 2^-34.24 on |s| <= 0.1716, as FreeBSD and musl give them).
const LGF1: f32 = f32::from_bits(0x3f2aaaaa); // 0.66666662693
const LGF2: f32 = f32::from_bits(0x3eccce13); // 0.40000972152
const LGF3: f32 = f32::from_bits(0x3e91e9ee); // 0.28498786688
const LGF4: f32 = f32::from_bits(0x3e789e26); // 0.24279078841
const SQRT2_F32: f32 = std::f32::consts::SQRT_2;
const TWO_M30_F32: f32 = 9.313225746154785e-10; // 2^-30

/// ln x for x in [0, 1] given with `one_minus_x` (the reduced argument from √3/2 on, as
/// for the accurate powers), in plain `f32`: fdlibm's `logf` scheme (see
/// [`ln_fast_f64`]), within about 1 ulp. For a complement below 2^-30, ln(1 − c) = −c to
/// within 2^-31 relative, which keeps every intermediate out of the subnormal range.
/// x = 0 gives a finite value (the caller selects the result).
#[inline(always)]
fn ln_fast_f32(x: f32, one_minus_x: f32) -> f32 {
    let (m, e) = split_f32(x);
    let big = m > SQRT2_F32;
    let m = if big { m * 0.5 } else { m };
    let near = x > SQRT3_HALF_F32;
    let k = e + if big { 1.0 } else { 0.0 };
    let k = if near { 0.0 } else { k };
    let f = if near { -one_minus_x } else { m - 1.0 }; // m − 1: exact (Sterbenz)
    // Only the complement can be that small (k = 0 then); m − 1 is 0 or at least 2^-24.
    let tiny = near & (one_minus_x < TWO_M30_F32);
    let fc = if tiny { -TWO_M30_F32 } else { f };
    let s = fc / (2.0 + fc);
    let z = s * s;
    let z = if z < TWO_M60_F32 { TWO_M60_F32 } else { z };
    let w = z * z;
    let t1 = w * (LGF2 + w * LGF4);
    let t2 = z * (LGF1 + w * LGF3);
    let r = t2 + t1;
    let hfsq = 0.5 * fc * fc;
    // k·LN2_H12 is exact (|k| < 2^8, 12 significant bits).
    let ln = k * LN2_H12_F32 - ((hfsq - (s * (hfsq + r) + k * LN2_L12_F32)) - fc);
    if tiny { f } else { ln }
}

/// e^y·2^-e for an integer |e| < 160 and y <= 0 (the logarithm's product): exactly 0
/// below 2^-170 (through the subnormals with one rounding, [`scale_f32`]) and +inf
/// beyond the float range. y = n ln 2 + r with n·LN2_H12 exact (|n| < 2^9), e^r
/// (|r| <= ln2/2) is [`exp_mant_f32`]'s polynomial: about 1 ulp, plus the error y
/// carries in.
#[inline(always)]
fn exp_fast_f32(y: f32, e: f32) -> f32 {
    let lo = (e - 170.0) * LN2_F32;
    let hi = (e + 129.0) * LN2_F32;
    let y = if y < lo { lo } else { y };
    let y = if y > hi { hi } else { y };
    let kd = y * LOG2E_F32 + SHIFT_F32;
    let n = kd - SHIFT_F32;
    let r = (y - n * LN2_H12_F32) - n * LN2_L12_F32;
    scale_f32(exp_mant_f32::<false>(r, 0.0), kd - e)
}

/// x^p·2^-e for x in [0, 1] with `one_minus_x` and an integer |e| < 160: e^(p·ln x) in
/// plain `f32`. Special cases as [`pow_unit_f32`].
#[inline(always)]
fn pow_fast_scaled_f32(x: f32, one_minus_x: f32, p: f32, e: f32) -> f32 {
    let y = p * ln_fast_f32(x, one_minus_x);
    let r = exp_fast_f32(y, e);
    let one = pow2_neg_f32(e);
    let r = if one_minus_x == 0.0 { one } else { r };
    let r = if x == 0.0 { 0.0 } else { r };
    if p == 0.0 { one } else { r }
}

/// The fast tier's `f32` x^p (`brdf_rs.eval(..., precision="fast")`): the contract of
/// [`pow_unit_f32`] (domain, the complement, special cases, no NaN, underflow through the
/// subnormals) with the logarithm, the product p·ln x and the exponential in plain `f32`.
///
/// Error: ln x is within about 1 ulp and the product rounds once more, so y = p·ln x is
/// off by about 1.5·|y|·2^-24 absolute, which e^y turns into the same relative error,
/// plus about 2 ulps of its own: relative error <= (4 + 3|y|)·2^-25 (measured by
/// `fast_pow_f32_is_within_its_bound`). |y| is the power's own condition number with
/// respect to p (a change of p by one ulp moves x^p by |y| ulps), so the error is within
/// what the inputs' rounding explains: about 2e-7 where |y| <= 1, and 4e-6 at the
/// largest |y| above the flush of the `f32` lobes (|y| = 70).
#[inline(always)]
pub fn pow_unit_fast_f32(x: f32, one_minus_x: f32, p: f32) -> f32 {
    pow_fast_scaled_f32(x, one_minus_x, p, 0.0)
}

// ------------------------------------------------------------- the tiers

/// x^p in `tier`: [`pow_unit_f64`], [`pow_unit_table_f64`] or [`pow_unit_fast_f64`].
#[inline(always)]
pub fn pow_unit_tier_f64(tier: PowTier, x: f64, one_minus_x: f64, p: f64) -> f64 {
    match tier {
        PowTier::Series => pow_unit_f64(x, one_minus_x, p),
        PowTier::Table => pow_unit_table_f64(x, one_minus_x, p),
        PowTier::Fast => pow_unit_fast_f64(x, one_minus_x, p),
    }
}

/// [`pow_unit_tier_f64`] for a lane expected to be ordinary, and whether it was: the
/// table-driven power's [`pow_unit_table_ordinary_f64`], the fast tier's
/// [`pow_unit_fast_ordinary_f64`] (whose lanes that are not ordinary then take
/// [`pow_unit_fast_f64`]); the series power's one value and true.
#[inline(always)]
pub fn pow_unit_ordinary_tier_f64(tier: PowTier, x: f64, one_minus_x: f64, p: f64) -> (f64, bool) {
    match tier {
        PowTier::Table => pow_unit_table_ordinary_f64(x, one_minus_x, p),
        PowTier::Fast => pow_unit_fast_ordinary_f64(x, one_minus_x, p),
        PowTier::Series => (pow_unit_tier_f64(tier, x, one_minus_x, p), true),
    }
}

/// `(x·2^-kx)^p / d` in `tier` ([`pow_unit_over_scaled_f64`]'s contract; `kx = 0`:
/// [`pow_unit_over_f64`]'s). The table-driven and the fast quotients are formed from
/// halves, so they do not overflow below 2^1024; the fast one's |y| stays below about
/// 1460 for a quotient in the normal range, hence a relative error of at most about
/// 5e-13 (see [`pow_unit_fast_f64`]).
#[inline(always)]
pub fn pow_unit_over_scaled_tier_f64(
    tier: PowTier,
    x: f64,
    one_minus_x: f64,
    p: f64,
    kx: f64,
    d: f64,
) -> f64 {
    let (m, e) = split_divisor_f64(d);
    match tier {
        PowTier::Series => pow_unit_scaled_f64::<false>(x, one_minus_x, p, e, kx) / m,
        PowTier::Table => pow_scaled_f64::<true>(x, one_minus_x, p, e, kx, m),
        PowTier::Fast => pow_fast_scaled_f64(x, one_minus_x, p, e, kx, m),
    }
}

/// x^p in `tier`: [`pow_unit_f32`], or [`pow_unit_fast_f32`] in the fast tier (`f32`
/// has no table-driven power: the series one serves [`PowTier::Table`]).
#[inline(always)]
pub fn pow_unit_tier_f32(tier: PowTier, x: f32, one_minus_x: f32, p: f32) -> f32 {
    match tier {
        PowTier::Series | PowTier::Table => pow_unit_f32(x, one_minus_x, p),
        PowTier::Fast => pow_unit_fast_f32(x, one_minus_x, p),
    }
}

/// [`pow_unit_tier_f32`] and true, whatever the tier (see [`pow_unit_ordinary_tier_f64`]):
/// an ordinary path measured slower in `f32`, whose powers fall below the normal range
/// (and out of such a path) in most blocks of an ordinary lobe (`cos^50` at `cos < 0.19`).
#[inline(always)]
pub fn pow_unit_ordinary_tier_f32(tier: PowTier, x: f32, one_minus_x: f32, p: f32) -> (f32, bool) {
    (pow_unit_tier_f32(tier, x, one_minus_x, p), true)
}

/// [`pow_unit_over_f32`] in `tier` (the fast tier's with [`pow_unit_fast_f32`]'s power);
/// `f32` carries no extended cosine exponent, so `kx` is ignored
/// ([`crate::math::Real::EXTENDED_COSINES`]).
#[inline(always)]
pub fn pow_unit_over_scaled_tier_f32(
    tier: PowTier,
    x: f32,
    one_minus_x: f32,
    p: f32,
    _kx: f32,
    d: f32,
) -> f32 {
    match tier {
        PowTier::Series | PowTier::Table => pow_unit_over_f32(x, one_minus_x, p, d),
        PowTier::Fast => {
            let (m, e) = split_divisor_f32(d);
            pow_fast_scaled_f32(x, one_minus_x, p, e) / m
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    //! Spot checks against libm. The exhaustive accuracy runs quoted above (mpmath
    //! vectors at 72 digits, every f32) were made when the functions were written and
    //! are not part of this repository; these keep the properties from regressing.
    use super::*;

    fn pow_unit_over_table_f64(x: f64, one_minus_x: f64, p: f64, d: f64) -> f64 {
        pow_unit_over_scaled_tier_f64(PowTier::Table, x, one_minus_x, p, 0.0, d)
    }

    fn pow_unit_over_scaled_table_f64(x: f64, one_minus_x: f64, p: f64, kx: f64, d: f64) -> f64 {
        pow_unit_over_scaled_tier_f64(PowTier::Table, x, one_minus_x, p, kx, d)
    }

    fn pow_unit_over_fast_f64(x: f64, one_minus_x: f64, p: f64, d: f64) -> f64 {
        pow_unit_over_scaled_tier_f64(PowTier::Fast, x, one_minus_x, p, 0.0, d)
    }

    fn pow_unit_over_scaled_fast_f64(x: f64, one_minus_x: f64, p: f64, kx: f64, d: f64) -> f64 {
        pow_unit_over_scaled_tier_f64(PowTier::Fast, x, one_minus_x, p, kx, d)
    }

    /// Distance of `got` from `want` in ulps of `want` (shared with `math::erf`'s tests).
    pub(crate) fn ulps(got: f64, want: f64) -> f64 {
        if got == want {
            return 0.0;
        }
        let ulp = f64::from_bits(want.abs().to_bits() + 1) - want.abs();
        (got - want).abs() / ulp
    }

    /// A small deterministic generator (SplitMix64) for test inputs.
    pub(crate) fn uniform(state: &mut u64) -> f64 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn special_cases_are_exact() {
        assert_eq!(pow_unit_f64(0.0, 1.0, 0.0), 1.0);
        assert_eq!(pow_unit_f64(0.0, 1.0, 3.0), 0.0);
        assert_eq!(pow_unit_f64(1.0, 0.0, 1e300), 1.0);
        assert_eq!(pow_unit_f64(0.3, 0.7, 0.0), 1.0);
        assert_eq!(pow_unit_f32(0.0, 1.0, 0.0), 1.0);
        assert_eq!(pow_unit_f32(0.0, 1.0, 2.0), 0.0);
        assert_eq!(pow_unit_f32(1.0, 0.0, 1e30), 1.0);
        // Gradual underflow: 0.5^1074 is the smallest subnormal, 0.5^1075 rounds to 0.
        assert_eq!(pow_unit_f64(0.5, 0.5, 1074.0), f64::from_bits(1));
        assert_eq!(pow_unit_f64(0.5, 0.5, 1076.0), 0.0);
    }

    /// The extended-exponent power is the plain one where both can hold the base: `kx = 0`
    /// bitwise, and a base `x·2^-600` in the normal range bitwise too (the same reduced
    /// mantissa, the exponent moved exactly); below the range, a subnormal base's power
    /// is right to an ulp.
    #[test]
    fn scaled_power_is_the_power_of_the_scaled_base() {
        let two_600 = 2f64.powi(600);
        let mut s = 7;
        for _ in 0..20_000 {
            let x = uniform(&mut s).max(1e-300);
            let p = 10f64.powf(uniform(&mut s) * 4.0 - 2.0);
            let d = 10f64.powf(uniform(&mut s) * 600.0 - 320.0);
            let plain = pow_unit_over_f64(x, 1.0 - x, p, d);
            let scaled = pow_unit_over_scaled_f64(x, 1.0 - x, p, 0.0, d);
            assert_eq!(plain.to_bits(), scaled.to_bits(), "x={x} p={p} d={d}");
            // A base in [2^-1000, 2^-990): carried as x·2^600 in [2^-400, 2^-390).
            let tiny = 2f64.powi(-1000) * (1.0 + 1023.0 * uniform(&mut s));
            let plain = pow_unit_over_f64(tiny, 1.0, p, d);
            let scaled = pow_unit_over_scaled_f64(tiny * two_600, 1.0, p, 600.0, d);
            assert_eq!(plain.to_bits(), scaled.to_bits(), "tiny={tiny} p={p} d={d}");
        }
        // The base 3·2^-1070 (a subnormal): its square root over 2^-1074 is sqrt(3)·2^539.
        // (From bits: powi would form 2^1074 and divide, 0 in a debug build.)
        let x = f64::from_bits(3 << 4) * two_600;
        let got = pow_unit_over_scaled_f64(x, 1.0, 0.5, 600.0, f64::from_bits(1));
        let want = 3f64.sqrt() * 2f64.powi(539);
        assert!(ulps(got, want) <= 1.0, "{got} vs {want}");
    }

    #[test]
    fn pow_matches_libm_within_two_ulp() {
        let mut s = 1;
        for _ in 0..200_000 {
            let x = uniform(&mut s);
            let p = 10f64.powf(uniform(&mut s) * 5.0 - 2.0);
            let want = x.powf(p);
            if want < f64::MIN_POSITIVE || x == 0.0 {
                continue;
            }
            let got = pow_unit_f64(x, 1.0 - x, p);
            assert!(ulps(got, want) <= 2.0, "{x}^{p}: {got} vs {want}");
            let x32 = x as f32;
            let got32 = pow_unit_f32(x32, 1.0 - x32, p as f32);
            let want32 = (x as f32 as f64).powf(p as f32 as f64);
            if want32 > 1e-30 {
                let rel = (f64::from(got32) - want32).abs() / want32;
                assert!(
                    rel < 4.0 * f64::from(f32::EPSILON),
                    "f32 {x}^{p}: {got32} vs {want32}"
                );
            }
        }
    }

    #[test]
    fn complement_keeps_accuracy_next_to_one() {
        // x = 1 − d with d = 2^-k exact: (1 − d)^p = exp(p·log1p(−d)). That libm
        // composition is itself off by up to ~|y| ulp (the roundings of log1p and of the
        // product are magnified by exp); the fast pow is within 1 ulp of the truth.
        for k in 10..60 {
            let d = 2f64.powi(-k);
            for p in [1.0, 7.3, 1e3, 1e6, 1e9, 1e12] {
                let y = p * (-d).ln_1p();
                if y < -700.0 {
                    continue;
                }
                let want = y.exp();
                let got = pow_unit_f64(1.0 - d, d, p);
                assert!(
                    ulps(got, want) <= 4.0 + 2.0 * y.abs(),
                    "k={k} p={p}: {got} vs {want}"
                );
            }
        }
    }

    /// The table-driven power keeps the series power's contract: the same special cases,
    /// no NaN over the domain, and values within an ulp of it (each is within 0.65 ulp of
    /// the exact power), next to 1 with huge exponents and for `over` with tiny divisors
    /// included.
    #[test]
    fn table_pow_agrees_with_series_pow() {
        for &(x, omc) in &[
            (0.0, 1.0),
            (1.0, 0.0),
            (0.5, 0.5),
            (1.0, 1e-320),
            (1e-320, 1.0),
        ] {
            assert_eq!(pow_unit_table_f64(x, omc, 0.0), 1.0);
        }
        assert_eq!(pow_unit_table_f64(1.0, 0.0, 1e300), 1.0);
        assert_eq!(pow_unit_table_f64(0.0, 1.0, 3.0), 0.0);
        assert_eq!(pow_unit_table_f64(0.5, 0.5, 1074.0), f64::from_bits(1));
        assert_eq!(pow_unit_table_f64(0.5, 0.5, 1076.0), 0.0);
        assert_eq!(
            pow_unit_over_table_f64(0.5, 0.5, 1100.0, 2f64.powi(-100)),
            2f64.powi(-1000)
        );
        let mut s = 11;
        let mut worst = 0f64;
        for _ in 0..300_000 {
            let x = match (uniform(&mut s) * 4.0) as u32 {
                0 => uniform(&mut s),
                1 => 10f64.powf(-300.0 * uniform(&mut s)),
                _ => 1.0 - 10f64.powf(-16.0 * uniform(&mut s)),
            };
            let omc = 1.0 - x; // exact where it matters (x >= 1/2, Sterbenz)
            let p = 10f64.powf(uniform(&mut s) * 12.0 - 4.0);
            let d = 10f64.powf(uniform(&mut s) * 600.0 - 310.0);
            let (a, b) = (pow_unit_table_f64(x, omc, p), pow_unit_f64(x, omc, p));
            assert!(!a.is_nan(), "{x} {omc} {p}");
            if b >= f64::MIN_POSITIVE {
                worst = worst.max(ulps(a, b));
            } else {
                assert!(
                    (a - b).abs() <= 2.0 * f64::from_bits(1),
                    "{x}^{p}: {a} vs {b}"
                );
            }
            let (a, b) = (
                pow_unit_over_table_f64(x, omc, p, d),
                pow_unit_over_f64(x, omc, p, d),
            );
            assert!(!a.is_nan(), "{x} {omc} {p} {d}");
            if (f64::MIN_POSITIVE..f64::MAX / 2.0).contains(&b) {
                assert!(ulps(a, b) <= 2.5, "{x}^{p}/{d}: {a} vs {b}");
            }
            let kx = 600.0;
            let xs = 10f64.powf(-400.0 - 300.0 * uniform(&mut s));
            let (a, b) = (
                pow_unit_over_scaled_table_f64(xs, 1.0, p.min(2.0), kx, d),
                pow_unit_over_scaled_f64(xs, 1.0, p.min(2.0), kx, d),
            );
            if (f64::MIN_POSITIVE..f64::MAX / 2.0).contains(&b) {
                assert!(ulps(a, b) <= 2.5, "({xs}·2^-600)^{p}/{d}: {a} vs {b}");
            }
        }
        assert!(worst <= 1.0, "table vs series power: {worst} ulp");
    }

    /// The table-driven power's ordinary path gives the general path's bits wherever it
    /// says a lane is ordinary, says so for the everyday lanes, and refuses the special
    /// cases and the ends of the range.
    #[test]
    fn ordinary_table_pow_is_the_table_pow() {
        let mut s = 5;
        let (mut ordinary, mut total) = (0, 0);
        for _ in 0..300_000 {
            let x = match (uniform(&mut s) * 5.0) as u32 {
                0 => uniform(&mut s),
                1 => 10f64.powf(-310.0 * uniform(&mut s)),
                2 => 1.0 - 10f64.powf(-16.0 * uniform(&mut s)),
                _ => 0.5 + 0.5 * uniform(&mut s),
            };
            let omc = if uniform(&mut s) < 0.01 {
                10f64.powf(-330.0 * uniform(&mut s) - 10.0)
            } else {
                1.0 - x
            };
            let p = 10f64.powf(uniform(&mut s) * 14.0 - 6.0);
            let (got, ok) = pow_unit_table_ordinary_f64(x, omc, p);
            let want = pow_unit_table_f64(x, omc, p);
            if ok {
                assert_eq!(got.to_bits(), want.to_bits(), "{x} {omc} {p}");
                ordinary += 1;
            }
            total += 1;
        }
        assert!(ordinary > total / 2, "{ordinary} of {total}");
        for (x, omc, p) in [
            (0.0, 1.0, 2.0),
            (1.0, 0.0, 2.0),
            (0.5, 0.5, 0.0),
            (0.5, 0.5, 1e-301),
            (1e-310, 1.0, 2.0),
            (1.0, 1e-331, 2.0),
            (0.5, 0.5, 1022.0),
            (1.0 - 1e-16, 1e-16, 1e-190),
            (0.5, 0.5, f64::NAN),
        ] {
            assert!(!pow_unit_table_ordinary_f64(x, omc, p).1, "{x} {omc} {p}");
        }
        assert!(pow_unit_table_ordinary_f64(0.5, 0.5, 50.0).1);
    }

    /// The fast tier's power keeps the contract's special cases and never gives NaN.
    #[test]
    fn fast_pow_special_cases_are_exact() {
        for &(x, omc) in &[
            (0.0, 1.0),
            (1.0, 0.0),
            (0.5, 0.5),
            (1.0, 1e-320),
            (1e-320, 1.0),
        ] {
            assert_eq!(pow_unit_fast_f64(x, omc, 0.0), 1.0);
        }
        assert_eq!(pow_unit_fast_f64(1.0, 0.0, 1e300), 1.0);
        assert_eq!(pow_unit_fast_f64(0.0, 1.0, 3.0), 0.0);
        assert_eq!(pow_unit_fast_f64(0.5, 0.5, 1074.0), f64::from_bits(1));
        assert_eq!(pow_unit_fast_f64(0.5, 0.5, 1076.0), 0.0);
        assert_eq!(pow_unit_fast_f64(0.5, 0.5, 1e300), 0.0);
        assert_eq!(pow_unit_fast_f64(1e-300, 1.0, 1e300), 0.0);
        // 0.5^1100 is below the float range; over 2^-100 it is 2^-1000 (to the bound).
        let got = pow_unit_over_fast_f64(0.5, 0.5, 1100.0, 2f64.powi(-100));
        let bound = (4.0 + 3.0 * 1100.0 * 2f64.ln()) * f64::EPSILON / 2.0;
        assert!((got / 2f64.powi(-1000) - 1.0).abs() <= bound, "{got:e}");
        assert_eq!(pow_unit_over_fast_f64(0.0, 1.0, 0.0, 0.25), 4.0);
        assert_eq!(
            pow_unit_over_fast_f64(0.3, 0.7, 0.0, f64::from_bits(1)),
            f64::INFINITY
        );
        assert_eq!(pow_unit_over_fast_f64(1.0, 0.0, 1e6, 1e-320), f64::INFINITY);
        assert_eq!(pow_unit_over_fast_f64(0.0, 1.0, 2.0, 1e-300), 0.0);
    }

    /// The fast tier's power against the accurate one (within 0.64 ulp of the exact
    /// power) over its whole domain: bases uniform, log-uniform down to 1e-300 and within
    /// 1e-16 of 1 (with the exact complement), exponents from 1e-4 to 1e8, divisors from
    /// 1e-310 to 1e290. Relative error at most (4 + 3|y|)·2^-53 (y = p·ln x, the stated
    /// bound plus the reference's own error) wherever the result is normal, so at most
    /// 2.6e-13 for a plain power and 5e-13 for a quotient; subnormal results within
    /// that relative error plus 2 units of 2^-1074.
    #[test]
    fn fast_pow_is_within_its_bound() {
        let u = f64::EPSILON / 2.0;
        let mut s = 23;
        let (mut worst_plain, mut worst_over) = (0f64, 0f64);
        for _ in 0..300_000 {
            let x = match (uniform(&mut s) * 4.0) as u32 {
                0 => uniform(&mut s),
                1 => 10f64.powf(-300.0 * uniform(&mut s)),
                _ => 1.0 - 10f64.powf(-16.0 * uniform(&mut s)),
            };
            let omc = 1.0 - x; // exact where it matters (x >= 1/2, Sterbenz)
            let p = 10f64.powf(uniform(&mut s) * 12.0 - 4.0);
            let d = 10f64.powf(uniform(&mut s) * 600.0 - 310.0);
            let y = (p * x.ln()).abs();
            let bound = (4.0 + 3.0 * y) * u;
            let (got, want) = (pow_unit_fast_f64(x, omc, p), pow_unit_f64(x, omc, p));
            assert!(!got.is_nan(), "{x} {omc} {p}");
            if want >= f64::MIN_POSITIVE {
                let rel = (got - want).abs() / want;
                assert!(rel <= bound, "{x}^{p}: {got} vs {want} ({rel:e})");
                worst_plain = worst_plain.max(rel);
            } else {
                let tol = bound * want + 2.0 * f64::from_bits(1);
                assert!((got - want).abs() <= tol, "{x}^{p}: {got} vs {want}");
            }
            let (got, want) = (
                pow_unit_over_fast_f64(x, omc, p, d),
                pow_unit_over_f64(x, omc, p, d),
            );
            assert!(!got.is_nan(), "{x} {omc} {p} {d}");
            let y_over = (p * x.ln() - d.ln()).abs().max(y);
            if (f64::MIN_POSITIVE..f64::MAX / 2.0).contains(&want) {
                let rel = (got - want).abs() / want;
                assert!(
                    rel <= (5.0 + 3.0 * y_over) * u,
                    "{x}^{p}/{d}: {got} vs {want} ({rel:e})"
                );
                worst_over = worst_over.max(rel);
            }
            let kx = 600.0;
            let xs = 10f64.powf(-400.0 - 300.0 * uniform(&mut s));
            let (got, want) = (
                pow_unit_over_scaled_fast_f64(xs, 1.0, p.min(2.0), kx, d),
                pow_unit_over_scaled_f64(xs, 1.0, p.min(2.0), kx, d),
            );
            if (f64::MIN_POSITIVE..f64::MAX / 2.0).contains(&want) {
                let rel = (got - want).abs() / want;
                assert!(rel <= 5e-13, "({xs}·2^-600)^{p}/{d}: {got} vs {want}");
            }
        }
        assert!(worst_plain <= 2.6e-13, "plain: {worst_plain:e}");
        assert!(worst_over <= 5e-13, "over: {worst_over:e}");
        eprintln!("fast pow: plain {worst_plain:e}, over {worst_over:e}");
    }

    /// The fast tier's ordinary power: its flag set where the table-driven power's is (the
    /// same conditions, but for `y` within the two logarithms' rounding of a bound), and on
    /// those lanes the full fast power's bits, within the bound `(3 + 3|y|)·2^-53` of the
    /// accurate power; bases near 1 given by their complement and subnormal bases
    /// included, and every table entry reached.
    #[test]
    fn fast_ordinary_pow_is_the_fast_pows_bits() {
        let u = f64::EPSILON / 2.0;
        let mut s = 31;
        let (mut worst, mut ordinary_lanes) = (0f64, 0usize);
        for _ in 0..300_000 {
            let x = match (uniform(&mut s) * 6.0) as u32 {
                0 => uniform(&mut s),
                1 => 10f64.powf(-300.0 * uniform(&mut s)),
                2 => 0.7 + 0.3 * uniform(&mut s),
                3 => f64::MIN_POSITIVE * 10f64.powf(-16.0 * uniform(&mut s)),
                _ => 1.0 - 10f64.powf(-16.0 * uniform(&mut s)),
            };
            let omc = 1.0 - x; // exact where it matters (x >= 1/2, Sterbenz)
            let p = 10f64.powf(uniform(&mut s) * 12.0 - 4.0);
            let (short, ordinary) = pow_unit_fast_ordinary_f64(x, omc, p);
            let (_, table_ordinary) = pow_unit_table_ordinary_f64(x, omc, p);
            let full = pow_unit_fast_f64(x, omc, p);
            assert!(!full.is_nan(), "{x} {omc} {p}");
            let y = (p * x.ln()).abs();
            if ordinary {
                ordinary_lanes += 1;
                assert_eq!(short.to_bits(), full.to_bits(), "{x}^{p}");
                let want = pow_unit_f64(x, omc, p);
                let rel = (full - want).abs() / want;
                assert!(
                    rel <= (3.0 + 3.0 * y) * u,
                    "{x}^{p}: {full} vs {want} ({rel:e})"
                );
                worst = worst.max(rel / ((3.0 + 3.0 * y) * u));
            }
            if ordinary != table_ordinary {
                let (lo, hi) = ORDINARY_POW_Y;
                let edge = |b: f64| (y + b).abs() <= 1e-12 * b.abs().max(y);
                assert!(
                    edge(lo) || edge(hi),
                    "{x}^{p}: flags {ordinary} {table_ordinary}"
                );
            }
        }
        assert!(ordinary_lanes > 100_000, "{ordinary_lanes}");
        eprintln!("fast ordinary pow: at most {worst:.3} of its bound");
    }

    #[test]
    fn fast_pow_f32_is_within_its_bound() {
        // Against the accurate `f64` power of the same `f32` inputs (within 0.64 ulp of
        // `f64`: exact at this width).
        let u = f64::from(f32::EPSILON) / 2.0;
        let mut s = 29;
        let (mut worst_plain, mut worst_over) = (0f64, 0f64);
        let mut accurate_misses = 0;
        for _ in 0..300_000 {
            let x = match (uniform(&mut s) * 4.0) as u32 {
                0 => uniform(&mut s) as f32,
                1 => 10f64.powf(-45.0 * uniform(&mut s)) as f32,
                _ => (1.0 - 10f64.powf(-7.5 * uniform(&mut s))) as f32,
            };
            // Complements of every size: exact, and far below what `x` resolves.
            let omc = if uniform(&mut s) < 0.2 && x > 0.9 {
                10f64.powf(-8.0 - 30.0 * uniform(&mut s)) as f32
            } else {
                1.0 - x
            };
            let x = if omc < 1e-8 { 1.0 - omc } else { x };
            let p = 10f64.powf(uniform(&mut s) * 10.0 - 4.0) as f32;
            // Divisors down to the subnormals (a grazing cosine), exponents of 0 among them.
            let d = 10f64.powf(uniform(&mut s) * 83.0 - 45.0) as f32;
            let d = if d == 0.0 { f32::from_bits(1) } else { d };
            let p = if uniform(&mut s) < 0.05 { 0.0 } else { p };
            let (xd, od, pd, dd) = (f64::from(x), f64::from(omc), f64::from(p), f64::from(d));
            let want = pow_unit_f64(xd, od, pd);
            let y = (pd * if xd > 0.75 { (-od).ln_1p() } else { xd.ln() }).abs();
            let got = f64::from(pow_unit_fast_f32(x, omc, p));
            assert!(!got.is_nan(), "{x} {omc} {p}");
            if want >= f64::from(f32::MIN_POSITIVE) {
                let rel = (got - want).abs() / want;
                assert!(
                    rel <= (4.0 + 3.0 * y) * u,
                    "{x}^{p}: {got} vs {want} ({rel:e})"
                );
                worst_plain = worst_plain.max(rel / ((4.0 + 3.0 * y) * u));
            } else {
                let tol = (4.0 + 3.0 * y) * u * want + 2.0 * f64::from(f32::from_bits(1));
                assert!((got - want).abs() <= tol, "{x}^{p}: {got} vs {want}");
            }
            let want = pow_unit_over_f64(xd, od, pd, dd);
            let got = f64::from(pow_unit_over_scaled_tier_f32(
                PowTier::Fast,
                x,
                omc,
                p,
                0.0,
                d,
            ));
            assert!(!got.is_nan(), "{x} {omc} {p} {d}");
            let y_over = (pd * xd.ln() - dd.ln()).abs().max(y);
            if (f64::from(f32::MIN_POSITIVE)..f64::from(f32::MAX)).contains(&want) {
                let rel = (got - want).abs() / want;
                let bound = (5.0 + 3.0 * y_over) * u;
                // A unit of 2^-149 more where x^p·2^-e is subnormal.
                let tol = bound * want + 2.0 * f64::from(f32::from_bits(1));
                assert!(
                    (got - want).abs() <= tol,
                    "{x}^{p}/{d}: {got} vs {want} ({rel:e})"
                );
                if want >= 1e-36 {
                    worst_over = worst_over.max(rel / bound);
                }
            } else if want > f64::from(f32::MAX) {
                assert!(
                    got >= f64::from(f32::MAX) * 0.99,
                    "{x}^{p}/{d}: {got} vs {want}"
                );
            }
            // The accurate `f32` quotient, on the same arguments.
            let acc = f64::from(pow_unit_over_f32(x, omc, p, d));
            if (f64::from(f32::MIN_POSITIVE)..f64::from(f32::MAX)).contains(&want) {
                // Within 2 ulps, or a unit of 2^-149 where x^p·2^-e is subnormal.
                let rel = (acc - want).abs() / want;
                let tol = 2.0 * u * want + 2.0 * f64::from(f32::from_bits(1));
                if (acc - want).abs() > tol {
                    eprintln!("accurate {x}^{p}/{d}: {acc} vs {want} ({rel:e})");
                    accurate_misses += 1;
                }
            }
        }
        eprintln!("fast f32 pow: plain {worst_plain:.3}, over {worst_over:.3} of the bound");
        assert_eq!(accurate_misses, 0, "accurate quotients beyond 2 ulps");
        for (x, omc, p) in [
            (0.0f32, 1.0f32, 0.0f32),
            (0.0, 1.0, 2.0),
            (1.0, 0.0, 1e30),
            (0.5, 0.5, 0.0),
        ] {
            assert_eq!(
                pow_unit_fast_f32(x, omc, p),
                pow_unit_f32(x, omc, p),
                "{x}^{p} special case"
            );
        }
    }

    #[test]
    fn exp_and_log_match_libm() {
        let mut s = 7;
        for _ in 0..100_000 {
            let x = (uniform(&mut s) - 0.5) * 1400.0;
            let want = x.exp();
            if want.is_finite() && want > f64::MIN_POSITIVE {
                assert!(ulps(exp_f64(x), want) <= 2.0, "exp({x})");
            }
            let y = 10f64.powf((uniform(&mut s) - 0.5) * 600.0);
            assert!(ulps(log_f64(y), y.ln()) <= 2.0, "log({y})");
            let yf = y as f32;
            if yf > 0.0 && yf.is_finite() {
                let rel = (f64::from(log_f32(yf)) - f64::from(yf).ln()).abs();
                assert!(rel <= 4.0 * f64::from(f32::EPSILON) * f64::from(yf).ln().abs().max(1.0));
            }
        }
    }

    #[test]
    fn pow2_neg_f64_is_exact() {
        // As below, for the f64 powers (|e| <= 1100).
        for e in -1100..=1100 {
            let ef = e as f64;
            let want = if e < -1023 {
                f64::INFINITY
            } else if e > 1074 {
                // 2^-1075 rounds to even (0); below it, 0.
                0.0
            } else {
                2f64.powi(-e.min(1022)) * 2f64.powi(-(e - e.min(1022)))
            };
            assert_eq!(pow2_neg_f64(ef).to_bits(), want.to_bits(), "2^-({e})");
            assert_eq!(exp2_dd_f64::<false>(0.0, 0.0, ef).to_bits(), want.to_bits());
        }
    }

    #[test]
    fn pow2_neg_f32_is_exact() {
        // The special cases' 2^-e of the scaled f32 powers: exact, through the subnormals
        // to 0 and to +inf beyond the range, and the value the exponentials gave for it.
        for e in -159..=159 {
            let ef = e as f32;
            let want = 2f64.powi(-e) as f32;
            assert_eq!(pow2_neg_f32(ef).to_bits(), want.to_bits(), "2^-({e})");
            assert_eq!(exp2_dd_f32::<false>(0.0, 0.0, ef).to_bits(), want.to_bits());
            assert_eq!(exp_fast_f32(0.0, ef).to_bits(), want.to_bits());
        }
    }
}
