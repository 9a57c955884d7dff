//! What the sheen and cloth models share (docs/models.md: `charlie_sheen`,
//! `charlie_sheen_neubelt`, `ashikhmin_cloth`): the half vector's angle, Estevez and
//! Kulla's Charlie distribution and their fit of its Smith `Λ`, Neubelt and Pettineo's
//! visibility term, the parameters and the albedo terms.
//!
//! All three are family A, `f = kd/π + ks·lobe`, with a lobe that has no Fresnel term and
//! peaks where the half vector lies near the surface (grazing angles), so the integrator
//! and `brdf_rs.sample` draw it uniformly over the hemisphere: its weight `lobe·mu_o·2π`
//! is bounded, where cosine sampling's `lobe·π` grows like `1/mu_o` for `charlie_sheen`.

use super::albedo::{Importance, Integral, Term, basis};
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{self, DiffuseTerm, ModelSpec, ParamKind, ParamSpec, SceneUse, ValidRange};
use super::{Directions, ParamSource, WideRow};
use crate::math::geometry::{WideCosine, above_both, half_vector, weighted};
use crate::math::{PowUnit, Real, SeriesPow, Vector3, max, min};

/// The roughness range of the sheen models: Estevez and Kulla's `r` in (0, 1], down to
/// where the lobe is a sliver at the horizon.
pub const SHEEN_ROUGHNESS: ValidRange = ValidRange {
    min: 1e-3,
    max: 1.0,
    min_open: false,
    max_open: false,
};

// The sheen models' parameters: `kd`, `ks` and the roughness `alpha`.
crate::param_slots! {
    KD: ColourSlot,
    KS: ColourSlot,
    ALPHA: ScalarSlot,
}

/// `ks`, the sheen colour, as every sheen model takes it.
pub const SHEEN_COLOUR: ParamSpec = ParamSpec {
    name: "ks",
    kind: ParamKind::Colour,
    default: Some(1.0),
    range: ValidRange::NON_NEGATIVE,
    doc: "sheen colour: the lobe's scale (RGB, >= 0; no Fresnel term)",
    slot: KS.first(),
};

/// The spec fields the sheen and cloth models share: family A, the parameters `kd`
/// (default 0), `ks` (the sheen colour, default 1) and `alpha` in [1e-3, 1], both colours
/// weights, reciprocal, no tangent, no split-sum table, energy tables (`E(mu, alpha)` at
/// `kd = 0`, `ks = 1`), no exact normalization. A model's spec names its own fields and
/// takes these with `..SHEEN_SPEC`; the name and texts here are placeholders.
pub const SHEEN_SPEC: ModelSpec = ModelSpec {
    params: &[
        spec::kd(0.0, KD),
        SHEEN_COLOUR,
        ParamSpec {
            name: "alpha",
            kind: ParamKind::Scalar,
            default: Some(0.5),
            range: SHEEN_ROUGHNESS,
            doc: "roughness in [1e-3, 1]: the lobe's width (glTF and Filament pass ρ² for a \
                  perceptual roughness ρ)",
            slot: ALPHA.first(),
        },
    ],
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    energy_table: true,
    sheen_layer: true,
    ..ModelSpec::PLAIN
};

/// The colours every sheen model prepares: `kd/π` and `ks`.
#[derive(Clone, Copy)]
pub struct Colours<F> {
    kd_over_pi: [F; 3],
    ks: [F; 3],
}

impl<F: Real> Colours<F> {
    #[inline(always)]
    pub fn read<P: ParamSource<F> + ?Sized>(p: &P) -> Self {
        Colours {
            kd_over_pi: KD.read(p).map(|c| c * F::FRAC_1_PI),
            ks: KS.read(p),
        }
    }

    /// `kd/π + ks·lobe` above the surface (0 below, and the lobe 0 where `h` is
    /// undefined).
    #[inline(always)]
    pub fn rgb(&self, lobe: F, a: &Angles<F>) -> [F; 3] {
        let lobe = if a.defined { lobe } else { F::ZERO };
        let rgb = [0, 1, 2].map(|c| weighted(self.ks[c], lobe) + self.kd_over_pi[c]);
        above_both(a.mu_i, a.mu_o, rgb)
    }

    /// [`Colours::rgb`] on a row of [`Kernel::eval_wide`](super::Kernel::eval_wide): the
    /// side of the surface from the wide cosines' signs (normalization may round a cosine
    /// of the other sign, or 0, to a tiny positive one).
    pub fn rgb_wide(&self, lobe: f64, a: &Angles<F>, w: &WideRow) -> [F; 3] {
        let a = Angles {
            mu_i: F::from_f64(w.mu_i.m),
            mu_o: F::from_f64(w.mu_o.m),
            ..*a
        };
        self.rgb(F::from_f64(lobe), &a)
    }
}

/// The albedo terms of every sheen model: `kd` exactly, the lobe at `ks = 1` drawn
/// with `importance` (uniformly over the hemisphere for the Charlie sheens: measured,
/// `benches/sheen_sampling.py`).
pub fn albedo_terms(slots: &[f64], importance: Importance) -> Vec<Term> {
    vec![
        Term {
            colour: KD.read(slots),
            integral: Integral::Exact(1.0),
        },
        Term {
            colour: KS.read(slots),
            integral: Integral::Lobe {
                basis: basis(slots, &[(KD, 0.0), (KS, 1.0)]),
                importance,
            },
        },
    ]
}

/// The cosines a sheen lobe needs: of `wi`, `wo` and the half vector, the latter as
/// `sin²θh` and `cos²θh` (quotients by `|n|²|h|²`, so the lengths' rounding does not
/// enter), and whether the half vector is defined (`wi ≠ −wo`). The half vector is that
/// of [`half_vector`]: its sum is scaled before squaring, so grazing directions on
/// opposite sides (a sum of 1e-300) keep a direction.
#[derive(Clone, Copy)]
pub struct Angles<F> {
    pub mu_i: F,
    pub mu_o: F,
    pub sin2_th: F,
    pub cos2_th: F,
    pub defined: bool,
}

/// Returns the [`Angles`] of a direction pair.
#[inline(always)]
pub fn angles<F: Real>(d: &Directions<F>) -> Angles<F> {
    let hv = half_vector::<F>(d.wi, d.wo);
    let scale = d.n.length_squared() * hv.h.length_squared();
    let nh = d.n.dot(hv.h);
    Angles {
        mu_i: d.n.dot(d.wi),
        mu_o: d.n.dot(d.wo),
        sin2_th: d.n.cross(hv.h).length_squared() / scale,
        cos2_th: nh * nh / scale,
        defined: hv.defined,
    }
}

/// `1 − cos θ` of the angle between `n` and `w` given `mu = n·w`: `sin²θ/(1 + mu)` with
/// `sin²θ = |n × w|²/(|n|²|w|²)`, so the lengths' rounding does not enter and a `w`
/// along `n` gives exactly 0 (`1 − mu` would give the rounding of `|w|`), for `mu >=
/// 1/2` (below, `1 − mu` itself).
#[inline(always)]
pub fn cosine_complement<F: Real>(n: F::V3, w: F::V3, mu: F) -> F {
    let sin2 = n.cross(w).length_squared() / (n.length_squared() * w.length_squared());
    if mu < F::HALF {
        F::ONE - mu
    } else {
        sin2 / (F::ONE + mu)
    }
}

/// Estevez and Kulla's distribution `D = (2 + 1/α)·sin(θh)^(1/α)/(2π)`.
#[derive(Clone, Copy)]
pub struct Charlie<F> {
    /// `1/(2α)`: the power of `sin²θh`.
    half_inverse: F,
    /// `(2 + 1/α)/(2π)`.
    scale: F,
}

impl<F: Real> Charlie<F> {
    pub fn new(alpha: F) -> Self {
        let inverse = F::ONE / alpha;
        Charlie {
            half_inverse: F::HALF * inverse,
            scale: (F::TWO + inverse) * (F::HALF * F::FRAC_1_PI),
        }
    }

    /// `D/q` at the half vector's angle for a `q > 0`, the power divided before it can
    /// underflow (`0.2^500` at α = 1e-3 is below the `f64` range, `D` over two cosines of
    /// 1e-200 is not).
    #[inline(always)]
    pub fn d_over<P: PowUnit>(&self, a: &Angles<F>, q: F) -> F {
        P::pow_unit_over(a.sin2_th, a.cos2_th, self.half_inverse, q / self.scale)
    }

    /// `D` as `m·2^e` ([`Kernel::eval_wide`](super::Kernel::eval_wide)'s rows): the
    /// power through its base-2 logarithm, split into an integer and a fraction, so that a
    /// power below the `f64` range (`0.2^500` at α = 1e-3) keeps its digits for a division
    /// by cosines below that range.
    pub fn d_wide(&self, sin2_th: f64) -> (f64, i64) {
        if sin2_th <= 0.0 {
            return (0.0, 0);
        }
        let l = self.half_inverse.to_f64() * libm::log2(sin2_th);
        let whole = l.floor();
        (self.scale.to_f64() * libm::exp2(l - whole), whole as i64)
    }
}

/// A double-width number `hi + lo` (`|lo|` at most half an ulp of `hi`), with the
/// error-free sums and products of Dekker and Knuth (no fused multiply-add, so every
/// instruction set gives the same bits). The products are error-free in `f32` only: in
/// `f64`, [`Dd::two_prod`] takes `f32`'s split constant and its low part is good to about
/// one rounding (docs/numerics.md, "Double-width products in float64").
#[derive(Clone, Copy, Debug)]
pub struct Dd<F> {
    hi: F,
    lo: F,
}

impl<F: Real> Dd<F> {
    pub const fn new(hi: F, lo: F) -> Self {
        Dd { hi, lo }
    }

    /// `a + b` exactly, as a [`Dd`].
    #[inline(always)]
    pub fn two_sum(a: F, b: F) -> Self {
        let s = a + b;
        let bb = s - a;
        Dd::new(s, (a - (s - bb)) + (b - bb))
    }

    /// `a·b` as a [`Dd`] (Veltkamp's split; the factors here are far from overflow):
    /// exact in `f32`; in `f64` the width test below never holds (`Real::DTYPE` reads
    /// `"f64"`), so the split is `f32`'s and the low part is off by about a rounding. The
    /// exact split waits for a more accurate `f64` GGX lobe (docs/numerics.md, "Double-width
    /// products in float64").
    #[inline(always)]
    pub fn two_prod(a: F, b: F) -> Self {
        let split = F::from_f64(if F::DTYPE == "float64" {
            134_217_729.0 // 2^27 + 1
        } else {
            4097.0 // 2^12 + 1
        });
        let halves = |x: F| {
            let c = split * x;
            let hi = c - (c - x);
            (hi, x - hi)
        };
        let p = a * b;
        let (ah, al) = halves(a);
        let (bh, bl) = halves(b);
        Dd::new(p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
    }

    #[inline(always)]
    fn renormalized(self) -> Self {
        let s = self.hi + self.lo;
        Dd::new(s, self.lo - (s - self.hi))
    }

    #[inline(always)]
    pub fn plus(self, other: Self) -> Self {
        let s = Dd::two_sum(self.hi, other.hi);
        Dd::new(s.hi, s.lo + (self.lo + other.lo)).renormalized()
    }

    #[inline(always)]
    pub fn times(self, other: Self) -> Self {
        let p = Dd::two_prod(self.hi, other.hi);
        Dd::new(p.hi, p.lo + (self.hi * other.lo + self.lo * other.hi)).renormalized()
    }

    #[inline(always)]
    pub fn over(self, other: Self) -> Self {
        let q = self.hi / other.hi;
        // The remainder self − q·other, exactly to first order.
        let p = Dd::two_prod(q, other.hi);
        let r = ((self.hi - p.hi) - p.lo + self.lo) - q * other.lo;
        Dd::new(q, r / other.hi).renormalized()
    }

    /// The square root, to about the width (one Newton step from the rounded root; 0 for
    /// 0).
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        let s = self.hi.sqrt();
        if s == F::ZERO {
            return Dd::new(F::ZERO, F::ZERO);
        }
        let r = self.plus(Dd::two_prod(s, s).negated());
        Dd::two_sum(s, r.hi / (F::TWO * s))
    }

    #[inline(always)]
    pub fn negated(self) -> Self {
        Dd::new(F::ZERO - self.hi, F::ZERO - self.lo)
    }

    /// The value rounded to the width (`hi`).
    #[inline(always)]
    pub fn value(self) -> F {
        self.hi
    }

    /// The two parts `(hi, lo)`.
    #[inline(always)]
    pub fn parts(self) -> (F, F) {
        (self.hi, self.lo)
    }

    /// `e^(hi + lo)` rounded once more: `e^hi·(1 + lo)`.
    #[inline(always)]
    pub fn exp(self) -> F {
        let e = self.hi.exp();
        e + e * self.lo
    }
}

/// Estevez and Kulla's fit of the Charlie distribution's Smith `Λ` (their Table 1):
/// `Λ(μ) = exp(L(μ))` below 1/2 and `exp(2L(1/2) − L(1 − μ))` from 1/2 on, with
/// `L(x) = a/(1 + b·x^c) + d·x + e` and the coefficients at roughness 1 and 0 blended
/// with `t = (1 − α)²`.
///
/// `L` is about 20 at grazing angles, and `exp` turns its absolute error into `Λ`'s
/// relative error: every rounding of a term of that size would cost `Λ` (and the lobe,
/// where `Λ ≫ 1`) ten ulps. So the coefficients (from their decimals), the blend and
/// `L` are carried in double width ([`Dd`]); only `x^c` is rounded (an error of at most
/// `a·b·x^c/(1 + b·x^c)² ≤ a/4` times its own), and `c`'s low part enters as
/// `x^c·c_lo·ln x`.
#[derive(Clone, Copy)]
pub struct LambdaFit<F> {
    a: Dd<F>,
    b: Dd<F>,
    c: Dd<F>,
    d: Dd<F>,
    e: Dd<F>,
    /// `2L(1/2)`.
    twice_half: Dd<F>,
}

/// The fit's `(a, b, c, d, e)` at roughness 1: the nearest `f64` to each decimal and the
/// rest.
const AT_1: [(f64, f64); 5] = [
    (21.5473, 1.0231815394945442e-16),
    (3.82987, -1.0757617019407917e-16),
    (0.19823, 1.0453859999870473e-17),
    (-1.9776, 2.4513724383723456e-17),
    (-4.32054, 2.6915358830592593e-16),
];
/// The fit's `(a, b, c, d, e)` at roughness 0, likewise.
const AT_0: [(f64, f64); 5] = [
    (25.3245, -4.547473508864641e-16),
    (3.32435, 8.384404281969182e-17),
    (0.16801, 7.318590178329033e-18),
    (-1.27393, 6.821210263296962e-18),
    (-4.85967, 3.7829295251867736e-16),
];

impl<F: Real> LambdaFit<F> {
    pub fn new(alpha: F) -> Self {
        let u = Dd::two_sum(F::ONE, F::ZERO - alpha);
        let t = u.times(u);
        // The decimal as the width's nearest value and the rest (f32 keeps the part of
        // the f64 value it rounds away).
        let dd = |(hi, lo): (f64, f64)| {
            let h = F::from_f64(hi);
            Dd::new(h, F::from_f64((hi - h.to_f64()) + lo))
        };
        // p1 + t·(p0 − p1).
        let [a, b, c, d, e] = std::array::from_fn(|k| {
            let p1 = dd(AT_1[k]);
            p1.plus(t.times(dd(AT_0[k]).plus(p1.negated())))
        });
        let mut fit = LambdaFit {
            a,
            b,
            c,
            d,
            e,
            twice_half: Dd::new(F::ZERO, F::ZERO),
        };
        let half = fit.l::<SeriesPow>(F::HALF, F::HALF);
        fit.twice_half = half.plus(half);
        fit
    }

    /// `L(x)` for `x` in [0, 1/2] (with `1 − x`).
    #[inline(always)]
    fn l<P: PowUnit>(&self, x: F, one_minus_x: F) -> Dd<F> {
        let x_c = P::pow_unit(x, one_minus_x, self.c.hi);
        // x^(c_hi + c_lo) = x^c_hi·(1 + c_lo·ln x); 0 at x = 0.
        let log = if x > F::ZERO { x.ln() } else { F::ZERO };
        let x_c = Dd::new(x_c, x_c * self.c.lo * log).renormalized();
        let one = Dd::new(F::ONE, F::ZERO);
        let x = Dd::new(x, F::ZERO);
        self.a
            .over(one.plus(self.b.times(x_c)))
            .plus(self.d.times(x))
            .plus(self.e)
    }

    /// `Λ(μ)`, with `μ` clamped to [0, 1] (a rounded cosine may be 1 + ε; below the
    /// surface the value is not used).
    #[inline(always)]
    pub fn lambda<P: PowUnit>(&self, mu: F) -> F {
        self.lambda_with::<P>(mu, F::ONE - mu)
    }

    /// [`LambdaFit::lambda`] given also `1 − μ` ([`cosine_complement`]), which it takes
    /// from `μ = 1/2` on: the fit's powers of `1 − μ` there turn a length error of the
    /// rounded unit vectors (`μ = 1 − ε` for a direction exactly along `n`) into 10^-9
    /// of `Λ`, where the complement from the cross product is exactly 0.
    #[inline(always)]
    pub fn lambda_with<P: PowUnit>(&self, mu: F, one_minus_mu: F) -> F {
        let mu = max(F::ZERO, min(mu, F::ONE));
        let one_minus_mu = max(F::ZERO, min(one_minus_mu, F::ONE));
        let low = mu < F::HALF;
        let x = if low { mu } else { one_minus_mu };
        let one_minus_x = if low { F::ONE - mu } else { mu };
        let l = self.l::<P>(x, one_minus_x);
        let l = if low {
            l
        } else {
            self.twice_half.plus(l.negated())
        };
        l.exp()
    }
}

/// `D·V` with Neubelt and Pettineo's visibility `V = 1/(4(mu_i + mu_o − mu_i·mu_o))`,
/// the sum written `mu_i + mu_o·(1 − mu_i)` (no cancellation; `V` is at most
/// `1/(4·max(mu_i, mu_o))`), as one quotient: `D = 0` gives 0 where `V` overflows.
#[inline(always)]
pub fn neubelt<F: Real>(d: F, mu_i: F, mu_o: F) -> F {
    d / neubelt_denominator(mu_i, mu_o)
}

/// `4(mu_i + mu_o·(1 − mu_i))`, [`neubelt`]'s divisor.
#[inline(always)]
pub fn neubelt_denominator<F: Real>(mu_i: F, mu_o: F) -> F {
    F::from_f64(4.0) * (mu_i + mu_o * (F::ONE - mu_i))
}

/// The Charlie `D` times Neubelt and Pettineo's `V`, the power divided by `V`'s divisor
/// before it can underflow ([`Charlie::d_over`]).
#[inline(always)]
pub fn charlie_neubelt<F: Real, P: PowUnit>(charlie: &Charlie<F>, a: &Angles<F>) -> F {
    charlie.d_over::<P>(a, neubelt_denominator(a.mu_i, a.mu_o))
}

/// `D·G2/(4·mu_i·mu_o)` with `G2 = 1/(1 + Λ(mu_i) + Λ(mu_o))`: the power divided by
/// `4(1 + Λ_i + Λ_o)` and the larger cosine before it can underflow
/// ([`Charlie::d_over`]), then by the smaller cosine, so that no product of two small
/// cosines underflows before the quotient would overflow anyway.
#[inline(always)]
pub fn charlie_smith<F: Real, P: PowUnit>(
    charlie: &Charlie<F>,
    a: &Angles<F>,
    lambda_i: F,
    lambda_o: F,
) -> F {
    let m = max(a.mu_i, a.mu_o);
    let least = min(a.mu_i, a.mu_o);
    let q = F::from_f64(4.0) * (F::ONE + lambda_i + lambda_o) * m;
    charlie.d_over::<P>(a, q) / least
}

/// `m·2^e` as an `f64`, overflowing to infinity and underflowing to 0.
fn scaled(m: f64, e: i64) -> f64 {
    libm::scalbn(m, e.clamp(-8000, 8000) as i32)
}

/// [`charlie_smith`] for cosines with extended exponents: `D/(4·g·mu_i·mu_o)` with `D = m·2^e`
/// ([`Charlie::d_wide`]) and `g = 1 + Λ_i + Λ_o`.
pub fn smith_wide(d: (f64, i64), g: f64, w: &WideRow) -> f64 {
    let m = d.0 / (4.0 * g * w.mu_i.m * w.mu_o.m);
    scaled(m, d.1 - i64::from(w.mu_i.k) - i64::from(w.mu_o.k))
}

/// `D·V` with [`neubelt`]'s `V` for cosines with extended exponents:
/// `D/(4(mu_i + mu_o·(1 − mu_i)))`, `D = m·2^e`.
pub fn neubelt_wide(d: (f64, i64), w: &WideRow) -> f64 {
    let rest = w.mu_o * WideCosine::of(1.0 - w.mu_i.value(), 0);
    let sum = w.mu_i + rest;
    scaled(d.0 / (4.0 * sum.m), d.1 - i64::from(sum.k))
}
