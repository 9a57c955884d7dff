//! Float widths, vectors and the numerically careful helpers every model shares.
//!
//! The crate computes in two widths chosen on purpose: `f64` with [`glam::DVec3`] (the
//! reference precision) and `f32` with [`glam::Vec3`] (the fast path). [`Real`] ties a
//! float to its glam vector so a model is written once; there is no other generic float
//! machinery. `Vec3` (not the SIMD `Vec3A`) is used for `f32` on purpose: the batch loops
//! vectorize *across* elements (8 or 16 lanes), which needs the plain three-float layout.
//!
//! All helpers here are `#[inline(always)]` and branch-free (selects, not jumps) so the
//! loops that call them auto-vectorize.

pub mod erf;
pub mod erfinv;
pub mod fastmath;
pub mod geometry;
pub mod ndtri;
pub mod series;

use glam::{DVec3, Vec3};
use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The operations the models need from a 3-vector; implemented by `DVec3` and `Vec3`.
pub trait Vector3<F>:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<F, Output = Self> + Neg<Output = Self>
{
    /// Returns the vector `(x, y, z)`.
    fn new(x: F, y: F, z: F) -> Self;
    /// Returns the x component.
    fn x(self) -> F;
    /// Returns the y component.
    fn y(self) -> F;
    /// Returns the z component.
    fn z(self) -> F;
    /// Returns the dot product.
    fn dot(self, other: Self) -> F;
    /// Returns the cross product.
    fn cross(self, other: Self) -> Self;
    /// Returns the squared Euclidean length.
    fn length_squared(self) -> F;
    /// Returns a unit vector orthogonal to the unit vector `self` (Duff et al. 2017,
    /// branch-free).
    fn any_orthonormal(self) -> Self;
}

macro_rules! impl_vector3 {
    ($v:ty, $f:ty) => {
        impl Vector3<$f> for $v {
            #[inline(always)]
            fn new(x: $f, y: $f, z: $f) -> Self {
                <$v>::new(x, y, z)
            }
            #[inline(always)]
            fn x(self) -> $f {
                self.x
            }
            #[inline(always)]
            fn y(self) -> $f {
                self.y
            }
            #[inline(always)]
            fn z(self) -> $f {
                self.z
            }
            #[inline(always)]
            fn dot(self, other: Self) -> $f {
                <$v>::dot(self, other)
            }
            #[inline(always)]
            fn cross(self, other: Self) -> Self {
                <$v>::cross(self, other)
            }
            #[inline(always)]
            fn length_squared(self) -> $f {
                <$v>::length_squared(self)
            }
            #[inline(always)]
            fn any_orthonormal(self) -> Self {
                // glam's any_orthonormal_vector, without its debug-build unit assertion.
                let sign = if self.z < 0.0 { -1.0 } else { 1.0 };
                let a = -1.0 / (sign + self.z);
                let b = self.x * self.y * a;
                <$v>::new(b, sign + self.y * self.y * a, -self.y)
            }
        }
    };
}
impl_vector3!(DVec3, f64);
impl_vector3!(Vec3, f32);

/// A float width the kernels run in (`f64` or `f32`), tied to its glam vector type.
pub trait Real:
    Copy
    + Send
    + Sync
    + Default
    + PartialOrd
    + Debug
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The glam vector of this width.
    type V3: Vector3<Self>;
    const ZERO: Self;
    const ONE: Self;
    const TWO: Self;
    const HALF: Self;
    const PI: Self;
    const FRAC_1_PI: Self;
    const NAN: Self;
    const INFINITY: Self;
    /// Name of the width as NumPy spells it.
    const DTYPE: &'static str;
    /// Whether [`Real::length_error`] computes the length errors of unit vectors (`f64`)
    /// or returns 0 (`f32`, whose goals do not need them): kernels that correct for them
    /// test this constant, so the `f32` loops carry none of the work.
    const EXACT_LENGTHS: bool;
    /// Whether kernels carry a cosine below the normal range with an extended exponent
    /// ([`Real::pow_unit_over_scaled`]; `f64`): `f32` keeps the subnormal cosine.
    const EXTENDED_COSINES: bool;

    /// Converts from `f64` (rounding for `f32`).
    fn from_f64(x: f64) -> Self;
    /// Converts to `f64` (exact).
    fn to_f64(self) -> f64;
    /// Returns the square root.
    fn sqrt(self) -> Self;
    /// Returns `|self|`.
    fn abs(self) -> Self;
    /// Returns `self * a + b` with one rounding.
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// Returns true unless NaN or infinite.
    fn is_finite(self) -> bool;
    /// Returns true for NaN.
    fn is_nan(self) -> bool;
    /// Returns `x^p` for `x` in [0, 1] given `x` and `1 - x` separately (both accurate),
    /// with `0^0 = 1`; see [`fastmath`].
    #[inline(always)]
    fn pow_unit(x: Self, one_minus_x: Self, p: Self) -> Self {
        Self::pow_unit_in(PowTier::Series, x, one_minus_x, p)
    }
    /// Returns `e^x`.
    fn exp(self) -> Self;
    /// Returns the natural logarithm.
    fn ln(self) -> Self;
    /// Returns the complementary error function in parts, `(value, r, tail)`: see
    /// [`erf::erfc_parts_f64`] (branch-free, vectorizable).
    fn erfc_parts(self) -> (Self, Self, bool);
    /// Returns `v / |v|` computed without overflow or underflow for any finite nonzero
    /// `v` (tiny 1e-300 and huge 1e300 vectors included), and whether `v` was usable
    /// (finite and nonzero). Unusable inputs give a non-finite vector.
    ///
    /// A nonzero component whose share of the length is below the smallest subnormal
    /// (`(1e300, 0, 1e-300)`: 1e-600) becomes the smallest subnormal of its sign, not 0:
    /// the sign of every dot product with an axis-aligned normal stays exact, so a
    /// direction just above the surface is never taken for one on it.
    fn normalize(v: Self::V3) -> (Self::V3, bool);
    /// The squared lengths, `[lo, hi]`, of the vectors that [`Real::normalize`] scales by
    /// no power of two (whatever the rounding of the squared length): `[2^-998, 2^999]`
    /// for `f64`, `[2^-78, 2^79]` for `f32` (its largest component is then within
    /// `[2^-500, 2^500]`, `[2^-40, 2^40]`), where no square overflows or underflows
    /// beyond a subnormal that cannot matter.
    const ORDINARY_LENGTH_SQUARED: (Self, Self);
    /// [`Real::normalize`]'s unit vector for a `v` whose squared length lies in
    /// [`Real::ORDINARY_LENGTH_SQUARED`], bit for bit, without the range selects (which
    /// scale no such vector): the normalization of an ordinary block in the accurate tier
    /// (the fast tier's: [`Real::normalize_unscaled_fast`]).
    fn normalize_unscaled(v: Self::V3) -> Self::V3;
    /// `1/√x` for `x >= 0` without a square root or a division, for the fast tier: the
    /// bit-pattern estimate (3.4% off), two third-order Newton steps (`e = 1 − x·y²`,
    /// `y ← y + y·e·(1/2 + 3e/8)`: to 10^-4, then 3·10^-12) and a second-order one whose
    /// `e` comes from the exact square `y²` (fused multiply-adds), which leaves 10^-23
    /// before the last rounding: correctly rounded (measured by
    /// `rsqrt_fast_is_correctly_rounded_everywhere`), so a unit vector such as `(0, 0, 1)`
    /// stays exactly unit. A tiny, subnormal or huge `x` is
    /// scaled by an even power of two first; `x = 0` gives a large finite value.
    fn rsqrt_fast(x: Self) -> Self;
    /// [`Real::rsqrt_fast`] within 4 ulps, cheaper: a fourth-order step (to about
    /// 5·10^-16) after the first third-order one. For the microfacet lobes' half vector and
    /// Smith square roots, where the direction an input has exactly does not arise.
    fn rsqrt_fast_approx(x: Self) -> Self;
    /// [`Real::rsqrt_fast`] (`EXACT`) or [`Real::rsqrt_fast_approx`].
    fn rsqrt_fast_in<const EXACT: bool>(x: Self) -> Self;
    /// [`Real::normalize_unscaled`] in the fast tier: in `f64`, `v·(1/|v|)` by
    /// [`Real::rsqrt_fast`], which keeps the divider free on CPUs where it is the loop's
    /// busiest unit (docs/numerics.md, "The fast tier"); `f32` keeps the square root and
    /// the division (its loops measured no faster without them).
    fn normalize_unscaled_fast(v: Self::V3) -> Self::V3;
    /// `√x` (`x >= 0`) in the fast tier: `x·(1/√x)` by [`Real::rsqrt_fast_approx`] in
    /// `f64` (within 5 ulps), the square root in `f32`.
    fn sqrt_fast(x: Self) -> Self;
    /// [`Real::normalize`] in the fast tier: its scaling with [`Real::rsqrt_fast`] (for an
    /// ordinary `v`, [`Real::normalize_unscaled_fast`]'s bits).
    fn normalize_fast(v: Self::V3) -> (Self::V3, bool);
    /// [`Real::normalize_length`] in the fast tier for a half vector: the same scaling, and
    /// in `f64` the reciprocal length by [`Real::rsqrt_fast_approx`], the length as
    /// `|v|²·(1/|v|)`.
    fn normalize_length_fast(v: Self::V3) -> (Self::V3, Self);
    /// [`Real::normalize_length`] with `recip(|v|²) = (1/|v|, |v|)` of the scaled vector.
    fn normalize_length_with(v: Self::V3, recip: impl Fn(Self) -> (Self, Self))
    -> (Self::V3, Self);
    fn normalize_length(v: Self::V3) -> (Self::V3, Self);
    /// Returns `|v|`, scaled by a power of two before squaring so that it neither
    /// overflows nor underflows (exact to a few ulps, subnormal lengths included).
    fn length(v: Self::V3) -> Self;
    /// Returns `x^p / d` for `x` in [0, 1] (with its complement, as [`Real::pow_unit`])
    /// and `d > 0`, with no underflow of `x^p` before the division: `cos^p / mu_i` at
    /// `mu_i = 1e-300` keeps every digit. `p = 0` (also `0^0`) gives `1/d`.
    #[inline(always)]
    fn pow_unit_over(x: Self, one_minus_x: Self, p: Self, d: Self) -> Self {
        Self::pow_unit_over_scaled(x, one_minus_x, p, Self::ZERO, d)
    }
    /// [`Real::pow_unit_over`] of the base `x·2^-kx` (`kx` an integer in `[0, 600]`, `x`
    /// at most `2^-400` when `kx > 0`): a cosine below the normal range carried with an
    /// extended exponent. `f64` only ([`Real::EXTENDED_COSINES`]); `f32` ignores `kx`.
    #[inline(always)]
    fn pow_unit_over_scaled(x: Self, one_minus_x: Self, p: Self, kx: Self, d: Self) -> Self {
        Self::pow_unit_over_scaled_in(PowTier::Series, x, one_minus_x, p, kx, d)
    }
    /// [`Real::pow_unit`] computed by `tier` (`f32`: every tier is the series power).
    fn pow_unit_in(tier: PowTier, x: Self, one_minus_x: Self, p: Self) -> Self;
    /// [`Real::pow_unit`] computed by `tier` for a lane expected to be ordinary, with
    /// whether it was; where it was, the value is [`Real::pow_unit_in`]'s bit for bit, else
    /// garbage. Only the `f64` table-driven and fast powers have such a path
    /// ([`fastmath::pow_unit_table_ordinary_f64`], [`fastmath::pow_unit_fast_ordinary_f64`]);
    /// the others return their one value and true.
    fn pow_unit_ordinary_in(tier: PowTier, x: Self, one_minus_x: Self, p: Self) -> (Self, bool);
    /// [`Real::pow_unit_over_scaled`] computed by `tier` (`f32`: the series power, `kx`
    /// ignored); `kx = 0` is [`Real::pow_unit_over`] bit for bit.
    fn pow_unit_over_scaled_in(
        tier: PowTier,
        x: Self,
        one_minus_x: Self,
        p: Self,
        kx: Self,
        d: Self,
    ) -> Self;
    /// Returns whether `v` is finite and nonzero, without normalizing it.
    fn usable(v: Self::V3) -> bool;
    /// Returns `|v|² − 1` for a vector of about unit length (components of magnitude at
    /// most 1, as [`Real::normalize`] returns), to within 2^-73 (1e-22; the value itself
    /// is of order 2^-53); 0 in `f32` (see [`Real::EXACT_LENGTHS`]).
    ///
    /// A rounded unit vector is up to a few ulps longer or shorter than 1, and formulas
    /// that take `|w| = 1` for granted turn that into errors of several ulps (GGX: a
    /// `|n|` off by `ε` moves the lobe by `6ε`), or, through `wi + wo` where the two nearly
    /// cancel, into a wrong direction of `h`. `fl(|v|²) − 1` is all rounding error at
    /// that size, so the squares are split instead (no FMA, which the baseline loops do
    /// not have): `x = xh + xl` with `xh = (x + C) − C` a multiple of 2^-25, so that
    /// `xh²` and the sum `xh² + yh² + zh² − 1` are exact, and
    /// `x² − xh² = xl·(x + xh)` is below 2^-25, its rounding below 2^-77. The true unit vector is
    /// then `v·(1 − e/2)` to first order, which is how the kernels use it.
    fn length_error(v: Self::V3) -> Self;
    /// Returns `x`, or 0 for an `f32` below 2^-100 ≈ 7.9e-31; identity for `f64`.
    ///
    /// `f32` lobes `cos^p` underflow for ordinary exponents, and every later product of
    /// a subnormal costs a ~100-cycle microcode assist per vector instruction on x86
    /// (measured: Torrance-Sparrow `f32` at p = 200 ran at 48 M/s instead of 103).
    /// Flushing at 2^-100 keeps the products that follow in the normal range too. The
    /// `f64` kernels keep gradual underflow (below 2.2e-308, rare there).
    fn flush_subnormal(x: Self) -> Self;
}

/// The three ways to compute `x^p` ([`Real::pow_unit`] and its `over` variants), one per
/// [`PowUnit`]. `f32` has no table-driven power (the series one serves there).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PowTier {
    /// Table-free, within well under an ulp ([`fastmath::pow_unit_f64`]): vectorizes in
    /// any loop.
    Series,
    /// Table-driven, within well under an ulp ([`fastmath::pow_unit_table_f64`]): faster
    /// where its table lookups vectorize as gathers.
    Table,
    /// The fast tier's (`precision="fast"`): `exp(p·ln x)` in plain floating point
    /// ([`fastmath::pow_unit_fast_f64`]), within a stated relative error.
    Fast,
}

/// How a kernel computes `x^p` ([`Real::pow_unit`] and its `over` variants): chosen by the
/// kernel's caller, since the fastest one depends on the loop around the kernel.
///
/// [`SeriesPow`] is table-free (the polynomial scheme of [`fastmath`]): it vectorizes in
/// any loop, and is what [`crate::models::Kernel::eval`] uses. [`TablePow`] is the
/// table-driven `f64` power (`f32`: the series one), faster where its table lookups
/// vectorize as gathers, which the eval engine's block loop does and the integrator's
/// per-point lobe loop does not (there it stops the loop from vectorizing). Both are
/// accurate to well under an ulp; their results differ in the last bit here and there.
/// [`FastPow`] is the fast tier's.
pub trait PowUnit: 'static {
    /// How the powers are computed.
    const TIER: PowTier;
    /// Whether this is the fast tier's power ([`FastPow`]), which also selects the fast
    /// tier's handling around the kernels in the eval engine. Follows from
    /// [`PowUnit::TIER`]; not set by the implementations.
    const FAST: bool = matches!(Self::TIER, PowTier::Fast);
    /// Whether the fast tier's `f64` normalizations and square roots go without the
    /// divider ([`Real::rsqrt_fast`]): only in the AVX-512 loops
    /// ([`FastPowDivisionFree`]), where the divider is the busiest unit; in the AVX2 loops
    /// the Newton steps cost more than the division they save (`benches/eval_ab.py` with
    /// `BRDF_RS_ISA=avx2`).
    const DIVISION_FREE: bool = false;

    /// Returns `x^p`, as [`Real::pow_unit`].
    #[inline(always)]
    fn pow_unit<F: Real>(x: F, one_minus_x: F, p: F) -> F {
        F::pow_unit_in(Self::TIER, x, one_minus_x, p)
    }

    /// Returns [`PowUnit::pow_unit`] for a lane expected to be ordinary (a normal base,
    /// exponent and result), and whether it was: the value is then the same bits, else
    /// garbage ([`Real::pow_unit_ordinary_in`]). A loop over many powers computes them this
    /// way, shorter, and again with [`PowUnit::pow_unit`] if any lane was not ordinary.
    #[inline(always)]
    fn pow_unit_ordinary<F: Real>(x: F, one_minus_x: F, p: F) -> (F, bool) {
        F::pow_unit_ordinary_in(Self::TIER, x, one_minus_x, p)
    }

    /// Returns `x^p / d`, as [`Real::pow_unit_over`].
    #[inline(always)]
    fn pow_unit_over<F: Real>(x: F, one_minus_x: F, p: F, d: F) -> F {
        F::pow_unit_over_scaled_in(Self::TIER, x, one_minus_x, p, F::ZERO, d)
    }

    /// Returns `(x·2^-kx)^p / d`, as [`Real::pow_unit_over_scaled`].
    #[inline(always)]
    fn pow_unit_over_scaled<F: Real>(x: F, one_minus_x: F, p: F, kx: F, d: F) -> F {
        F::pow_unit_over_scaled_in(Self::TIER, x, one_minus_x, p, kx, d)
    }
}

/// The table-free power: vectorizes in every loop (see [`PowUnit`]).
pub struct SeriesPow;

impl PowUnit for SeriesPow {
    const TIER: PowTier = PowTier::Series;
}

/// The table-driven `f64` power, for loops whose gathers vectorize (see [`PowUnit`]).
pub struct TablePow;

impl PowUnit for TablePow {
    const TIER: PowTier = PowTier::Table;
}

/// The fast tier's power (`precision="fast"`): `exp(p·ln x)` in plain floating point,
/// vectorizable, within a stated relative error instead of an ulp: in `f64` (the
/// table-driven scheme with fused multiply-adds) at most 2.5e-13 for a normal result
/// ([`fastmath::pow_unit_fast_f64`]); in `f32`
/// `(4 + 3|y|)·2^-25` with `y = p·ln x`, the power's own condition number with respect to
/// `p` ([`fastmath::pow_unit_fast_f32`]).
pub struct FastPow;

impl PowUnit for FastPow {
    const TIER: PowTier = PowTier::Fast;
}

/// [`FastPow`] with the `f64` normalizations and square roots done without the divider
/// ([`PowUnit::DIVISION_FREE`]): the fast tier of the AVX-512 loops.
pub struct FastPowDivisionFree;

impl PowUnit for FastPowDivisionFree {
    const TIER: PowTier = PowTier::Fast;
    const DIVISION_FREE: bool = true;
}

/// Returns the larger of `a` and `b` (the second if they compare unordered).
///
/// Written as a comparison so it compiles to one `max` instruction when vectorized.
#[inline(always)]
pub fn max<F: Real>(a: F, b: F) -> F {
    if a > b { a } else { b }
}

/// Returns the smaller of `a` and `b` (the second if they compare unordered).
#[inline(always)]
pub fn min<F: Real>(a: F, b: F) -> F {
    if a < b { a } else { b }
}

/// Returns `x` clamped to `[lo, hi]`.
#[inline(always)]
pub fn clamp<F: Real>(x: F, lo: F, hi: F) -> F {
    min(max(x, lo), hi)
}

/// Returns the largest absolute component of `v`.
#[inline(always)]
pub fn max_abs<F: Real>(v: F::V3) -> F {
    max(max(v.x().abs(), v.y().abs()), v.z().abs())
}

/// `u`, with each component that underflowed to 0 where `raw`'s is nonzero replaced by
/// the smallest subnormal of `raw`'s sign (see [`Real::normalize`]).
macro_rules! keep_signs {
    ($f:ident, $v:ty, $u:expr, $raw:expr) => {{
        let (u, raw) = ($u, $raw);
        let keep = |u: $f, raw: $f| {
            if u == 0.0 && raw != 0.0 {
                $f::from_bits(1).copysign(raw)
            } else {
                u
            }
        };
        <$v>::new(keep(u.x, raw.x), keep(u.y, raw.y), keep(u.z, raw.z))
    }};
}

/// Returns whether every component of `v` is finite and at least one is nonzero.
#[inline(always)]
fn finite_nonzero<F: Real>(v: F::V3) -> bool {
    let (x, y, z) = (v.x().abs(), v.y().abs(), v.z().abs());
    // NaN fails every comparison, so it fails `< INFINITY`.
    let finite = x < F::INFINITY && y < F::INFINITY && z < F::INFINITY;
    finite && (x > F::ZERO || y > F::ZERO || z > F::ZERO)
}

/// [`Real::normalize_length_with`] with `1/|v|` from [`Real::rsqrt_fast_in`] and
/// `|v| = |v|²·(1/|v|)`: the fast tier's normalizations.
#[inline(always)]
fn normalize_length_rsqrt<F: Real, const EXACT: bool>(v: F::V3) -> (F::V3, F) {
    F::normalize_length_with(v, |l2| {
        let y = F::rsqrt_fast_in::<EXACT>(l2);
        (y, l2 * y)
    })
}

macro_rules! impl_real {
    ($f:ident, $v:ty, $pow:ident, $pow_ord:ident, $pow_over:ident, $exp:ident, $log:ident, $erfc:path, flush = $flush:expr,
     exact_lengths = $exact_lengths:expr, small = $small:expr, big = $big:expr, up = $up:expr,
     down = $down:expr, ordinary = $ordinary:expr, magic = $magic:expr,
     rsqrt_range = $rsqrt_range:expr, fast_norm = $fast_norm:expr) => {
        impl Real for $f {
            type V3 = $v;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const TWO: Self = 2.0;
            const HALF: Self = 0.5;
            const PI: Self = std::$f::consts::PI;
            const FRAC_1_PI: Self = std::$f::consts::FRAC_1_PI;
            const NAN: Self = $f::NAN;
            const INFINITY: Self = $f::INFINITY;
            const DTYPE: &'static str = stringify!($f);
            const EXACT_LENGTHS: bool = $exact_lengths;
            const EXTENDED_COSINES: bool = $exact_lengths;
            const ORDINARY_LENGTH_SQUARED: (Self, Self) = $ordinary;

            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $f
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $f::sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $f::abs(self)
            }
            #[inline(always)]
            fn mul_add(self, a: Self, b: Self) -> Self {
                $f::mul_add(self, a, b)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                $f::is_finite(self)
            }
            #[inline(always)]
            fn is_nan(self) -> bool {
                $f::is_nan(self)
            }
            #[inline(always)]
            fn pow_unit_in(tier: PowTier, x: Self, one_minus_x: Self, p: Self) -> Self {
                fastmath::$pow(tier, x, one_minus_x, p)
            }
            #[inline(always)]
            fn pow_unit_ordinary_in(
                tier: PowTier,
                x: Self,
                one_minus_x: Self,
                p: Self,
            ) -> (Self, bool) {
                fastmath::$pow_ord(tier, x, one_minus_x, p)
            }
            #[inline(always)]
            fn pow_unit_over_scaled_in(
                tier: PowTier,
                x: Self,
                one_minus_x: Self,
                p: Self,
                kx: Self,
                d: Self,
            ) -> Self {
                fastmath::$pow_over(tier, x, one_minus_x, p, kx, d)
            }
            #[inline(always)]
            fn exp(self) -> Self {
                fastmath::$exp(self)
            }
            #[inline(always)]
            fn ln(self) -> Self {
                fastmath::$log(self)
            }
            #[inline(always)]
            fn erfc_parts(self) -> (Self, Self, bool) {
                $erfc(self)
            }
            #[inline(always)]
            fn flush_subnormal(x: Self) -> Self {
                // 2^-100 for f32.
                if $flush && x < 7.888609e-31 { 0.0 } else { x }
            }
            #[inline(always)]
            fn usable(v: Self::V3) -> bool {
                finite_nonzero::<$f>(v)
            }
            #[inline(always)]
            fn length_error(v: Self::V3) -> Self {
                if !$exact_lengths {
                    return 0.0;
                }
                // 1.5·2^27: (x + C) − C rounds |x| <= 1 to a multiple of 2^-25.
                const C: $f = 201326592.0;
                let hi = |x: $f| (x + C) - C;
                let (xh, yh, zh) = (hi(v.x), hi(v.y), hi(v.z));
                let exact = ((xh * xh + yh * yh) - 1.0) + zh * zh;
                let rest =
                    (v.x - xh) * (v.x + xh) + (v.y - yh) * (v.y + yh) + (v.z - zh) * (v.z + zh);
                exact + rest
            }
            #[inline(always)]
            fn normalize(v: Self::V3) -> (Self::V3, bool) {
                // Scaling by a power of two keeps a vector finite and nonzero exactly
                // when it was: test the raw one. The unused length folds away.
                let (u, _) = Self::normalize_length(v);
                (u, finite_nonzero::<$f>(v))
            }
            #[inline(always)]
            fn rsqrt_fast(x: Self) -> Self {
                Self::rsqrt_fast_in::<true>(x)
            }
            #[inline(always)]
            fn rsqrt_fast_approx(x: Self) -> Self {
                Self::rsqrt_fast_in::<false>(x)
            }
            #[inline(always)]
            fn rsqrt_fast_in<const EXACT: bool>(x: Self) -> Self {
                // A subnormal or tiny x, or a huge one (whose y² = y2 + y2_lo below would lose
                // y2_lo's bits in the subnormals), scaled by an even power of two first.
                let (tiny, huge, up, up_back, down, down_back) = $rsqrt_range;
                let small = x < tiny;
                let big = x > huge;
                let x = x * if small {
                    up
                } else if big {
                    down
                } else {
                    1.0
                };
                // 0 as the smallest subnormal: a finite result, which 0 turns into 0.
                let x = if small {
                    x.max($f::from_bits(1) * up)
                } else {
                    x
                };
                let y = $f::from_bits($magic.wrapping_sub(x.to_bits() >> 1));
                // Two third-order steps (y·(1 + e/2 + 3e²/8), e = 1 − x·y²: 3.4% → 10^-4 →
                // 3·10^-12), then a second-order one with e formed from the exact square
                // y² = y2 + y2_lo: its error is (3/2)e² (10^-23) and the final rounding, so
                // the result is 1/√x correctly rounded but for halfway cases within 10^-23.
                let cubic = |y: $f| {
                    let e = (-(x * y)).mul_add(y, 1.0);
                    (y * e).mul_add((0.375 as $f).mul_add(e, 0.5), y)
                };
                let y = if EXACT {
                    let y = cubic(cubic(y));
                    let y2 = y * y;
                    let y2_lo = y.mul_add(y, -y2);
                    let e = (-x).mul_add(y2, 1.0) - x * y2_lo;
                    (y * 0.5).mul_add(e, y)
                } else {
                    // A fourth-order step instead (+ 5e³/16: 10^-4 → 5·10^-16).
                    let y = cubic(y);
                    let e = (-(x * y)).mul_add(y, 1.0);
                    let p = (0.3125 as $f).mul_add(e, 0.375).mul_add(e, 0.5);
                    (y * e).mul_add(p, y)
                };
                y * if small {
                    up_back
                } else if big {
                    down_back
                } else {
                    1.0
                }
            }
            #[inline(always)]
            fn sqrt_fast(x: Self) -> Self {
                if $fast_norm {
                    x * Self::rsqrt_fast_approx(x)
                } else {
                    x.sqrt()
                }
            }
            #[inline(always)]
            fn normalize_unscaled_fast(v: Self::V3) -> Self::V3 {
                if !$fast_norm {
                    return Self::normalize_unscaled(v);
                }
                keep_signs!($f, $v, v * Self::rsqrt_fast(v.length_squared()), v)
            }
            #[inline(always)]
            fn normalize_fast(v: Self::V3) -> (Self::V3, bool) {
                if !$fast_norm {
                    return Self::normalize(v);
                }
                let (u, _) = normalize_length_rsqrt::<$f, true>(v);
                (u, finite_nonzero::<$f>(v))
            }
            #[inline(always)]
            fn normalize_length_fast(v: Self::V3) -> (Self::V3, Self) {
                if !$fast_norm {
                    return Self::normalize_length(v);
                }
                normalize_length_rsqrt::<$f, false>(v)
            }
            #[inline(always)]
            fn normalize_unscaled(v: Self::V3) -> Self::V3 {
                // `normalize_length`'s arithmetic without its selects: bit for bit.
                keep_signs!($f, $v, v * (1.0 / v.length_squared().sqrt()), v)
            }
            #[inline(always)]
            fn normalize_length(v: Self::V3) -> (Self::V3, Self) {
                Self::normalize_length_with(v, |l2| {
                    let len = l2.sqrt();
                    (1.0 / len, len)
                })
            }
            #[inline(always)]
            fn normalize_length_with(
                v: Self::V3,
                recip: impl Fn(Self) -> (Self, Self),
            ) -> (Self::V3, Self) {
                // Scale by an exact power of two so that squaring neither overflows nor
                // underflows, then divide by the length. Both selects are exact.
                let s = max_abs::<$f>(v);
                let raw = v;
                let small = s < $small;
                let big = s > $big;
                // One scaling by the factor chosen (at most one of the two applies, and
                // a product by 1 is exact: the bits of scaling by each in turn).
                let v = v * if small {
                    $up
                } else if big {
                    $down
                } else {
                    1.0
                };
                let (inv, len) = recip(v.length_squared());
                let u = keep_signs!($f, $v, v * inv, raw);
                let back = if small {
                    $down
                } else if big {
                    $up
                } else {
                    1.0
                };
                (u, len * back)
            }
            #[inline(always)]
            fn length(v: Self::V3) -> Self {
                let s = max_abs::<$f>(v);
                let small = s < $small;
                let big = s > $big;
                let v = if small { v * $up } else { v };
                let v = if big { v * $down } else { v };
                let len = v.length_squared().sqrt();
                let len = if small { len * $down } else { len };
                if big { len * $up } else { len }
            }
        }
    };
}

// f64: |v| in [2^-500, 2^500] squares safely; outside, rescale by 2^(+-600).
impl_real!(
    f64,
    DVec3,
    pow_unit_tier_f64,
    pow_unit_ordinary_tier_f64,
    pow_unit_over_scaled_tier_f64,
    exp_f64,
    log_f64,
    erf::erfc_parts_f64,
    flush = false,
    exact_lengths = true,
    small = 3.054936363499605e-151, // 2^-500
    big = 3.273390607896142e150,    // 2^500
    up = 4.149515568880993e180,     // 2^600
    down = 2.409919865102884e-181,  // 2^-600
    ordinary = (
        f64::from_bits((1023 - 998) << 52), // 2^-998
        f64::from_bits((1023 + 999) << 52)  // 2^999
    ),
    magic = 0x5FE6EB50C7B537A9u64,
    rsqrt_range = (
        f64::from_bits((1023 - 900) << 52), // 2^-900
        f64::from_bits((1023 + 900) << 52), // 2^900
        f64::from_bits((1023 + 200) << 52), // 2^200
        f64::from_bits((1023 + 100) << 52), // 2^100
        f64::from_bits((1023 - 200) << 52), // 2^-200
        f64::from_bits((1023 - 100) << 52)  // 2^-100
    ),
    fast_norm = true
);
// f32: |v| in [2^-40, 2^40] squares safely; outside, rescale by 2^(+-100).
impl_real!(
    f32,
    Vec3,
    pow_unit_tier_f32,
    pow_unit_ordinary_tier_f32,
    pow_unit_over_scaled_tier_f32,
    exp_f32,
    log_f32,
    erf::erfc_parts_f32,
    flush = true,
    exact_lengths = false,
    small = 9.094947e-13, // 2^-40
    big = 1.0995116e12,   // 2^40
    up = 1.2676506e30,    // 2^100
    down = 7.888609e-31,  // 2^-100
    ordinary = (
        f32::from_bits((127 - 78) << 23), // 2^-78
        f32::from_bits((127 + 79) << 23)  // 2^79
    ),
    magic = 0x5F375A86u32,
    rsqrt_range = (
        f32::from_bits((127 - 90) << 23), // 2^-90
        f32::from_bits((127 + 90) << 23), // 2^90
        f32::from_bits((127 + 40) << 23), // 2^40
        f32::from_bits((127 + 20) << 23), // 2^20
        f32::from_bits((127 - 40) << 23), // 2^-40
        f32::from_bits((127 - 20) << 23)  // 2^-20
    ),
    fast_norm = false
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_constants_are_exact_powers_of_two() {
        assert_eq!(3.054936363499605e-151_f64, 2f64.powi(-500));
        assert_eq!(3.273390607896142e150_f64, 2f64.powi(500));
        assert_eq!(4.149515568880993e180_f64, 2f64.powi(600));
        assert_eq!(2.409919865102884e-181_f64, 2f64.powi(-600));
        assert_eq!(9.094947e-13_f32, 2f32.powi(-40));
        assert_eq!(1.0995116e12_f32, 2f32.powi(40));
        assert_eq!(1.2676506e30_f32, 2f32.powi(100));
        assert_eq!(7.888609e-31_f32, 2f32.powi(-100));
    }

    #[test]
    fn length_error_is_exact_to_its_last_bits() {
        // Components that are multiples of 2^-60 (magnitudes in [2^-8, 1]) square to
        // multiples of 2^-120: |v|² − 1 exactly in 128-bit integers.
        let mut state = 0x9e3779b97f4a7c15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut nonzero = 0;
        for _ in 0..2000 {
            let raw = DVec3::new(next() + 0.1, -(next() + 0.1), next() + 0.1);
            let (v, ok) = f64::normalize(raw);
            assert!(ok);
            let scaled = |x: f64| {
                let m = x * 2f64.powi(60);
                assert_eq!(m, m.trunc(), "{x}");
                m as i128
            };
            let (x, y, z) = (scaled(v.x), scaled(v.y), scaled(v.z));
            let exact = (x * x + y * y + z * z - (1i128 << 120)) as f64 / 2f64.powi(120);
            let got = f64::length_error(v);
            // The products x_l·(x + x_h) (below 2^-25) round by 2^-77 each.
            let tol = 2f64.powi(-73) + f64::EPSILON * exact.abs();
            assert!((got - exact).abs() <= tol, "{v}: {got:e} vs {exact:e}");
            nonzero += usize::from(exact != 0.0);
        }
        assert!(
            nonzero > 1000,
            "rounded unit vectors are rarely exactly unit"
        );
        assert_eq!(f32::length_error(Vec3::new(0.6, 0.0, 0.8)), 0.0);
    }

    #[test]
    fn normalize_survives_extreme_lengths() {
        for scale in [1e-305, 1e-300, 1e-200, 1.0, 1e200, 1e300, 1.7e308] {
            let v = DVec3::new(3.0, -4.0, 12.0) * (scale / 13.0);
            let (u, ok) = f64::normalize(v);
            assert!(ok, "{scale}");
            assert!((u.length() - 1.0).abs() < 1e-15, "{scale}: {u}");
            assert!(u.x > 0.0 && u.y < 0.0 && u.z > 0.0);
        }
        for scale in [1e-44_f32, 1e-38, 1e-20, 1.0, 1e20, 3e38] {
            let v = Vec3::new(0.0, scale, -scale);
            let (u, ok) = f32::normalize(v);
            assert!(ok);
            assert!((u.length() - 1.0).abs() < 1e-6, "{scale}: {u}");
        }
    }

    /// Checks that [`Real::normalize_unscaled`] is [`Real::normalize`] bit for bit on
    /// vectors whose squared length lies in the ordinary range: random ones at each of
    /// `scales` and, at each of `ends`, one whose other components underflow in the
    /// quotient. The eval engine takes it for whole blocks of such rows.
    fn check_normalize_unscaled<T: Real>(scales: &[f64], ends: &[f64]) -> usize {
        let mut state = 0x2545_F491_4F6C_DD1D_u64;
        let mut vectors = Vec::new();
        for &scale in scales {
            for _ in 0..200 {
                let c = [(); 3].map(|_| {
                    T::from_f64((2.0 * fastmath::tests::uniform(&mut state) - 1.0) * scale)
                });
                vectors.push(T::V3::new(c[0], c[1], c[2]));
            }
        }
        let tiny = T::from_f64(f64::MIN_POSITIVE * 1e-10);
        vectors.extend(
            ends.iter()
                .map(|&end| T::V3::new(T::from_f64(end), tiny, -tiny)),
        );
        let (lo, hi) = T::ORDINARY_LENGTH_SQUARED;
        vectors.retain(|v| v.length_squared() >= lo && v.length_squared() <= hi);
        let bits = |v: T::V3| [v.x(), v.y(), v.z()].map(|c| c.to_f64().to_bits());
        for &v in &vectors {
            let (want, ok) = T::normalize(v);
            assert!(ok);
            assert_eq!(bits(T::normalize_unscaled(v)), bits(want), "{:?}", bits(v));
        }
        vectors.len()
    }

    #[test]
    fn normalize_unscaled_is_normalize_on_ordinary_vectors() {
        let scales = [1e-150, 1e-100, 1e-3, 1.0, 1e3, 1e100, 1e150];
        let ends = [2f64.powi(-499), 2f64.powi(499), 1e-300, 1.0];
        assert!(check_normalize_unscaled::<f64>(&scales, &ends) > 1000);
        let scales = [1e-12, 1e-5, 1.0, 1e5, 1e12];
        let ends = [2f64.powi(-39), 2f64.powi(39), 1.0];
        assert!(check_normalize_unscaled::<f32>(&scales, &ends) > 500);
    }

    /// The fast tier's reciprocal square root, over every binade (subnormals included) and
    /// within each: correctly rounded in `f64` (against `1/√x` to about 2^-100) and `f32`
    /// (against `f64`'s); axis vectors of these lengths normalize to the accurate tier's
    /// bits, exactly ±1. 0 gives a finite value, which a zero vector's components (all 0)
    /// turn into 0.
    #[test]
    fn rsqrt_fast_is_correctly_rounded_everywhere() {
        let mut s = 11u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let ulp = |y: f64| f64::from_bits(y.to_bits() + 1) - y;
        let mut worst = 0.0f64;
        for e in -1074..1024 {
            for _ in 0..64 {
                // Subnormal binades through a normal power of two (2^e itself is 0 there).
                let x = if e < -1000 {
                    (1.0 + next()) * 2f64.powi(e + 200) * 2f64.powi(-200)
                } else {
                    2f64.powi(e) * (1.0 + next())
                };
                if !(x.is_finite() && x > 0.0) {
                    continue;
                }
                let y = f64::rsqrt_fast(x);
                // 1/√x = r + lo to about 2^-100: r = 1/√x rounded, then one Newton
                // correction in double width (x·r² − 1 from the exact square r² = rr + rr_lo).
                // The reference from x·4^-k in [1, 4) (exact), so no square leaves the range.
                let k = (e + 1074).div_euclid(2) - 537;
                let xs = x * 2f64.powi(-k) * 2f64.powi(-k);
                let r = 1.0 / xs.sqrt();
                let rr = r * r;
                let rr_lo = r.mul_add(r, -rr);
                let e1 = xs.mul_add(rr, -1.0) + xs * rr_lo;
                let lo = -0.5 * r * e1;
                let ys = y * 2f64.powi(k);
                let err = ((ys - r) - lo).abs() / ulp(ys);
                assert!(x > 0.0 && err.is_finite(), "{x:e}");
                worst = worst.max(err);
            }
        }
        assert!(worst <= 0.5 + 1e-6, "f64 rsqrt_fast: {worst} ulps");
        let ulp32 = |y: f32| f64::from(f32::from_bits(y.to_bits() + 1) - y);
        let mut worst32 = 0.0f64;
        for e in -149..128 {
            for _ in 0..64 {
                let x = (2f64.powi(e) * (1.0 + next())) as f32;
                if !(x.is_finite() && x > 0.0) {
                    continue;
                }
                let want = 1.0 / f64::from(x).sqrt();
                let y = f32::rsqrt_fast(x);
                worst32 = worst32.max((f64::from(y) - want).abs() / ulp32(y));
            }
        }
        assert!(worst32 <= 0.5 + 1e-6, "f32 rsqrt_fast: {worst32} ulps");
        assert!(f64::rsqrt_fast(0.0).is_finite() && f32::rsqrt_fast(0.0).is_finite());
        for c in [
            1.0,
            2.0,
            3.0,
            5.0,
            0.7,
            1e-3,
            7e10,
            1e-200,
            3e250,
            5e-320,
            2.81666816e100,
        ] {
            for v in [DVec3::new(0.0, 0.0, c), DVec3::new(-c, 0.0, 0.0)] {
                assert_eq!(f64::normalize_fast(v), f64::normalize(v), "{v}");
            }
        }
    }

    #[test]
    fn length_survives_extreme_and_subnormal_vectors() {
        for scale in [5e-324, 1e-320, 1e-300, 1e-160, 1.0, 1e160, 1e300] {
            let v = DVec3::new(0.0, 3.0 * scale, -4.0 * scale);
            let want = 5.0 * scale;
            let got = f64::length(v);
            // subnormal lengths are rounded to the subnormal grid
            let tol = (4.0 * f64::EPSILON * want).max(f64::from_bits(1));
            assert!((got - want).abs() <= tol, "{scale}: {got} vs {want}");
        }
        let v = Vec3::new(3e-40, 0.0, 4e-40);
        assert!((f32::length(v) - 5e-40).abs() <= 2e-45);
        assert_eq!(f64::length(DVec3::ZERO), 0.0);
    }

    #[test]
    fn normalize_keeps_the_sign_of_components_below_the_range() {
        // 1e-300 / 1e300 = 1e-600 is below the smallest subnormal: it becomes ±2^-1074,
        // not 0, so the side of the xy-plane stays exact.
        let (u, ok) = f64::normalize(DVec3::new(1e300, 0.0, 1e-300));
        assert!(ok);
        assert_eq!(u, DVec3::new(1.0, 0.0, f64::from_bits(1)));
        let (u, _) = f64::normalize(DVec3::new(-1e300, 0.0, -1e-300));
        assert_eq!(u.z, -f64::from_bits(1));
        assert_eq!(u.y.to_bits(), 0, "a zero component stays +0");
        let (u, _) = f32::normalize(Vec3::new(1e38, 1e-38, 0.0));
        assert_eq!(u, Vec3::new(1.0, f32::from_bits(1), 0.0));
    }

    #[test]
    fn pow_unit_over_does_not_underflow_before_dividing() {
        // 0.5^1100 / 2^-100 = 2^-1000 exactly, though 0.5^1100 is below the float range.
        let got = f64::pow_unit_over(0.5, 0.5, 1100.0, 2f64.powi(-100));
        assert_eq!(got, 2f64.powi(-1000));
        // The same with a subnormal divisor and a non-power-of-two mantissa.
        let d = 3.0 * f64::from_bits(1);
        let got = f64::pow_unit_over(0.5, 0.5, 1060.0, d);
        let want = 2f64.powi(14) / 3.0; // 2^-1060 / (3·2^-1074)
        assert!(
            (got - want).abs() <= 2.0 * f64::EPSILON * want,
            "{got} vs {want}"
        );
        // p = 0 (also 0^0) gives 1/d; beyond the range +inf, never NaN.
        assert_eq!(f64::pow_unit_over(0.0, 1.0, 0.0, 0.25), 4.0);
        assert_eq!(
            f64::pow_unit_over(0.3, 0.7, 0.0, f64::from_bits(1)),
            f64::INFINITY
        );
        assert_eq!(f64::pow_unit_over(1.0, 0.0, 1e6, 1e-320), f64::INFINITY);
        assert_eq!(f64::pow_unit_over(0.0, 1.0, 2.0, 1e-300), 0.0);
        // Ordinary arguments: the plain power over d, within two roundings.
        for (x, p, d) in [(0.7, 3.5, 0.3), (0.999, 1e4, 1e-10), (0.1, 0.5, 7.0)] {
            let want = f64::pow_unit(x, 1.0 - x, p) / d;
            let got = f64::pow_unit_over(x, 1.0 - x, p, d);
            assert!(
                (got - want).abs() <= 2.0 * f64::EPSILON * want,
                "{x} {p} {d}"
            );
        }
        // f32: 0.5^140 / 2^-20 = 2^-120 (a normal f32) though 0.5^140 underflows.
        assert_eq!(
            f32::pow_unit_over(0.5, 0.5, 140.0, 2f32.powi(-20)),
            2f32.powi(-120)
        );
        assert_eq!(f32::pow_unit_over(0.5, 0.5, 0.0, 1e-45), f32::INFINITY);
    }

    #[test]
    fn unusable_vectors_are_flagged() {
        assert!(!f64::normalize(DVec3::ZERO).1);
        assert!(!f64::normalize(DVec3::new(f64::NAN, 0.0, 1.0)).1);
        assert!(!f64::normalize(DVec3::new(f64::INFINITY, 0.0, 1.0)).1);
        assert!(!f64::usable(DVec3::new(0.0, -0.0, 0.0)));
        assert!(f64::usable(DVec3::new(0.0, 5e-324, 0.0)));
        let (u, ok) = f64::normalize(DVec3::new(0.0, -5e-324, 0.0));
        assert!(ok && u == DVec3::new(0.0, -1.0, 0.0));
    }
}
