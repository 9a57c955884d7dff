//! `ggx`: the GGX (Trowbridge-Reitz) microfacet BRDF with height-correlated Smith
//! shadowing and Schlick's Fresnel (Walter et al. 2007; Heitz 2014 for the Smith form).
//!
//! `f = kd/π + D·G2·F/(4·mu_i·mu_o)` with `D = α²/(π·(cos_th²(α²−1)+1)²)`,
//! `G2 = 1/(1 + Λ(mu_i) + Λ(mu_o))`, `Λ(μ) = (−1 + sqrt(1 + α²(1−μ²)/μ²))/2` and
//! `F = F0 + (1−F0)(1−cos_b)^5`, `F0 = ks` (RGB). `ks = 1` gives F = 1.
//!
//! Evaluated without cancellation or overflow: the NDF's denominator is
//! `α² + (1 − α²)sin²θh` (`α ≤ 1`; [`Ndf`]), with `sin²θh` from `|n − h|²` and the
//! lengths ([`Facet::sin2`]), and
//! `G2/(4 mu_i mu_o) = 1/(4(mu_i mu_o + mu_o·L_i + mu_i·L_o))` with `L = μ·Λ(μ)` in the
//! bounded form of [`ggx_mu_lambda`](crate::math::geometry::ggx_mu_lambda) (finite at
//! grazing angles, where `Λ` overflows), as one quotient: see [`lobe`].

use super::albedo::{Integral, Slots, Term, basis, diffuse_and_schlick_lobe};
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{self, DfgAxis, DiffuseTerm, ModelSpec, ParamSpec, SceneUse};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::{
    Cosine, HalfVector, above_both, half_vector_exact, half_vector_in, microfacet_length_correction,
    schlick_rgb, schlick_weight, weighted,
};
use crate::math::{PowUnit, Real, Vector3, max, min};

/// The GGX kernel.
pub struct Ggx;

crate::param_slots! {
    KD: ColourSlot,
    KS: ColourSlot,
    ALPHA: ScalarSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "ggx",
    summary: "GGX / Trowbridge-Reitz microfacet BRDF, height-correlated Smith G2, Schlick F",
    formula: "f = kd/π + D·G2·F/(4·mu_i·mu_o), D = α²/(π(cos_th²(α²−1)+1)²), \
              G2 = 1/(1+Λ(mu_i)+Λ(mu_o)), Λ(μ) = (−1+sqrt(1+α²(1−μ²)/μ²))/2, \
              F = ks + (1−ks)(1−cos_b)^5",
    source: "Walter et al. 2007 (GGX); Heitz 2014 (height-correlated Smith)",
    params: &schlick_microfacet_params(ALPHA_DOC),
    ..SCHLICK_MICROFACET_SPEC
};

/// The spec fields of the microfacet models with Schlick's Fresnel (`ggx`,
/// [`super::beckmann`]): a Lambert diffuse term in scenes, a split-sum table over `alpha`
/// in [0, 1] and energy tables. A model's spec names its own fields, its parameters from
/// [`schlick_microfacet_params`], and takes these with `..SCHLICK_MICROFACET_SPEC`.
pub const SCHLICK_MICROFACET_SPEC: ModelSpec = ModelSpec {
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    dfg: Some(DfgAxis {
        param: "alpha",
        axis: "mid:0:1:32",
    }),
    energy_table: true,
    ..ModelSpec::PLAIN
};

/// The parameters of a microfacet model with Schlick's Fresnel in this layout: `kd`
/// (default 0), `ks` as F0 (default 1) and `alpha` (default 0.5) with the lobe's doc line.
pub const fn schlick_microfacet_params(alpha_doc: &'static str) -> [ParamSpec; 3] {
    [
        spec::kd(0.0, KD),
        spec::f0(1.0, KS),
        spec::roughness("alpha", 0.5, ALPHA, alpha_doc),
    ]
}

/// The roughness parameter's doc line (shared with the models on this lobe).
pub const ALPHA_DOC: &str = "roughness α: the NDF's width (α = r² for a perceptual roughness r)";

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    kd_over_pi: [F; 3],
    f0: [F; 3],
    ndf: Ndf<F>,
}

/// GGX's NDF `D = α²/(π(sin²θh + α²cos²θh)²)` at roughness `α`, with its denominator
/// written so that the term carrying the rounding of the cosines vanishes at the peak:
///
/// - `α ≤ 1`: `α²·|n|²|h|² + (1 − α²)·|n × h|²`,
/// - `α > 1`: `|n|²|h|² + (α² − 1)·(n·h)²`,
///
/// both `|n|²|h|²·(sin²θh + α²cos²θh)`, with `1 ∓ α²` formed as `(1 − α)(1 + α)` (no
/// cancellation of `α²`'s rounding near `α = 1`). The plain `sin²θh + α²(n·h)²` is
/// dominated at the peak by `α²(n·h)²`, and `D ∝ 1/(n·h)⁴` there turns the dot product's
/// rounding into four times as much error in `D` (up to 4 ulps in `f64`); here the
/// dominant term is the constant `α²` (or 1), and the dot product's part shrinks with
/// the distance from the peak. `|n|²|h|²` is `1 + e_n + e_h` of the length errors
/// ([`Real::length_error`]; 1 where they are left out), so the denominator stays
/// homogeneous of degree 2 in `|n|` and `|h|` as the lobes' length corrections take it.
/// The sine is [`Facet::sin2`]'s.
#[derive(Clone, Copy)]
pub struct Ndf<F> {
    /// `α²`.
    pub alpha2: F,
    /// `α²/π`.
    d_scale: F,
    /// The coefficient of `|n|²|h|²`: `α²` (`α ≤ 1`) or 1.
    peak: F,
    /// `|1 − α²|`, the coefficient of `|n × h|²` (`α ≤ 1`) or `(n·h)²`.
    slope: F,
    /// `α ≤ 1`.
    narrow: bool,
}

impl<F: Real> Ndf<F> {
    /// The constants for roughness `alpha`.
    #[inline(always)]
    pub fn new(alpha: F) -> Self {
        let alpha2 = alpha * alpha;
        let narrow = alpha <= F::ONE;
        let one_minus = (F::ONE - alpha) * (F::ONE + alpha);
        Ndf {
            alpha2,
            d_scale: alpha2 * F::FRAC_1_PI,
            peak: if narrow { alpha2 } else { F::ONE },
            slope: if narrow { one_minus } else { -one_minus },
            narrow,
        }
    }

    /// `D` at the facet `h` ([`Facet`]).
    #[inline(always)]
    pub fn eval(&self, facet: &Facet<F>) -> F {
        let c2 = facet.cos * facet.cos;
        let sin2 = facet.sin2();
        let t = if self.narrow { sin2 } else { c2 };
        let denom = self.peak * facet.nh2 + self.slope * t;
        self.d_scale / (denom * denom)
    }
}

/// Where a facet normal `h` stands from `n`: `cos θh = n·h`, `|n ∓ h|²` and
/// `nh2 = |n|²|h|²` ([`lengths_squared`]: to first order in the length errors, 1 where
/// they are left out).
#[derive(Clone, Copy)]
pub struct Facet<F> {
    pub cos: F,
    pub minus2: F,
    pub plus2: F,
    pub nh2: F,
}

impl<F: Real> Facet<F> {
    #[inline(always)]
    pub fn new(n: F::V3, h: F::V3, nh2: F) -> Self {
        Facet {
            cos: n.dot(h),
            minus2: (n - h).length_squared(),
            plus2: (n + h).length_squared(),
            nh2,
        }
    }

    /// `sin²θh = |n × h|²` as `(1 − cos θh)(1 + cos θh) = |n − h|²·|n + h|²/4`.
    #[inline(always)]
    pub fn sin2_product(&self) -> F {
        self.minus2 * (self.plus2 * F::from_f64(0.25))
    }

    /// `sin²θh` within about an ulp on either side of `cos²θh = 1/2`: above,
    /// `|n − h|²·|n + h|²/4` with `|n + h|² = 2(|n|² + |h|²) − |n − h|² = 2(1 + nh2) −
    /// |n − h|²` (one rounding where the sum of squares takes three; no cancellation for
    /// `n·h ≥ 0`, `|n − h|² ≤ 2`); below, `nh2 − cos²θh`.
    #[inline(always)]
    pub fn sin2(&self) -> F {
        let c2 = self.cos * self.cos;
        let plus2 = F::TWO * (F::ONE + self.nh2) - self.minus2;
        let product = self.minus2 * (plus2 * F::from_f64(0.25));
        if c2 > F::HALF { product } else { self.nh2 - c2 }
    }
}

/// Returns the scalar GGX lobe `D·G2/(4 mu_i mu_o)` (F = 1), the cosine `cos_b = wi·h`
/// its Fresnel term is evaluated at (with its complement) and whether the lobe is defined.
///
/// In terms of `L = μ·Λ(μ) = a/P`, `a = α²|n × w|²` (`α² sin²θ`),
/// `P = 2(sqrt(μ² + a) + μ)`: `G2/(4 mu_i mu_o) = P_i P_o/(4 q m)` with the larger cosine
/// `m` factored out, `q = min(mu_i, mu_o)·P_i P_o + (mu_o/m)·a_i P_o + (mu_i/m)·a_o P_i`
/// (one of the two ratios is exactly 1), so the lobe is `D·P_i P_o/(4q)/m`: four
/// divisions where the separate `L_i`, `L_o` and the quotient took seven, with no term
/// smaller than the result needs (both cosines at 1e-38 in `f32`: see
/// [`smith_quotient`](crate::math::geometry::smith_quotient)).
///
/// `f64`: every factor is written first-order homogeneous in the lengths of `n`, `wi`,
/// `wo` and `h` (`1 ∓ n·h` as `|n ∓ h|²/2`), of degrees −6, −1, −1 and −4, so the
/// rounded unit vectors' length errors `e = |w|² − 1` ([`Real::length_error`]), which
/// moved the value by up to 5 ulps, come out as the factor `1 + 3e_n + (e_i + e_o)/2 +
/// 2e_h`; `h` is the corrected half vector ([`half_vector_exact`]).
///
/// The fast tier (`P` is [`crate::math::FastPow`]) leaves the length errors out
/// ([`length_errors`]).
#[inline(always)]
pub fn lobe<F: Real, P: PowUnit>(d: &Directions<F>, ndf: &Ndf<F>) -> (F, Cosine<F>, bool) {
    let errors = length_errors::<F, P>(d);
    let mu_i = d.n.dot(d.wi);
    let mu_o = d.n.dot(d.wo);
    let hv = lobe_half_vector::<F, P>(d, errors);
    // With both cosines positive n·h > 0.
    let facet = Facet::new(d.n, hv.h, lengths_squared(errors, hv.h));
    let ndf_value = ndf.eval(&facet);
    let alpha2 = ndf.alpha2;
    let a_i = alpha2 * d.n.cross(d.wi).length_squared();
    let a_o = alpha2 * d.n.cross(d.wo).length_squared();
    let sqrt = |x: F| if P::DIVISION_FREE { F::sqrt_fast(x) } else { x.sqrt() };
    let spec = smith_lobe_with(ndf_value, mu_i, mu_o, a_i, a_o, sqrt);
    (corrected(spec, errors, hv.h), hv.cos_b, hv.defined)
}

/// `ndf·G2/(4 mu_i mu_o)` with GGX's height-correlated Smith `G2`, from the NDF's value
/// (times any weight), the two cosines and `a = α² sin²θ` of each direction: `ndf·P_i
/// P_o/(4q)/m` in the form [`lobe`] explains (`m` the larger cosine, `q = min·P_i P_o +
/// (mu_o/m)·a_i P_o + (mu_i/m)·a_o P_i`). The rough dielectrics' reflection and
/// refraction lobes use it too.
#[inline(always)]
pub fn smith_lobe<F: Real>(ndf: F, mu_i: F, mu_o: F, a_i: F, a_o: F) -> F {
    smith_lobe_with(ndf, mu_i, mu_o, a_i, a_o, F::sqrt)
}

/// [`smith_lobe`] with the square roots taken by `sqrt` (the fast tier's
/// [`Real::sqrt_fast`]).
#[inline(always)]
fn smith_lobe_with<F: Real>(ndf: F, mu_i: F, mu_o: F, a_i: F, a_o: F, sqrt: impl Fn(F) -> F) -> F {
    let p_i = F::TWO * (sqrt(mu_i * mu_i + a_i) + mu_i);
    let p_o = F::TWO * (sqrt(mu_o * mu_o + a_o) + mu_o);
    let m = max(mu_i, mu_o);
    let least = min(mu_i, mu_o);
    let ratio = least / m;
    let i_smaller = mu_i < mu_o;
    let r_i = if i_smaller { ratio } else { F::ONE };
    let r_o = if i_smaller { F::ONE } else { ratio };
    let pp = p_i * p_o;
    let q = least * pp + r_o * a_i * p_o + r_i * a_o * p_i;
    ndf * pp / (F::from_f64(4.0) * q) / m
}

/// The length errors `e = |w|² − 1` of `n`, `wi` and `wo` ([`Real::length_error`]) that the
/// microfacet lobes divide out, or `None` in the fast tier (`P::FAST`): they move the
/// value by a few ulps, far inside that tier's bound, and cost about a quarter of the
/// lobe. `f32`'s are zero ([`Real::EXACT_LENGTHS`]) and fold away either way.
#[inline(always)]
pub fn length_errors<F: Real, P: PowUnit>(d: &Directions<F>) -> Option<[F; 3]> {
    if P::FAST {
        None
    } else {
        Some([d.n, d.wi, d.wo].map(F::length_error))
    }
}

/// The half vector of a microfacet lobe: of the exact unit vectors
/// ([`half_vector_exact`]) given their length errors, else of the rounded ones.
#[inline(always)]
pub fn lobe_half_vector<F: Real, P: PowUnit>(
    d: &Directions<F>,
    errors: Option<[F; 3]>,
) -> HalfVector<F> {
    match errors {
        Some([_, e_i, e_o]) => half_vector_exact::<F>(d.wi, d.wo, e_i, e_o),
        None => half_vector_in::<F, P>(d.wi, d.wo),
    }
}

/// `|n|²|h|²` to first order in the length errors, `1 + e_n + e_h`, or 1 where they were
/// left out (the fast tier, and `f32`'s are 0).
#[inline(always)]
pub fn lengths_squared<F: Real>(errors: Option<[F; 3]>, h: F::V3) -> F {
    match errors {
        Some([e_n, _, _]) => F::ONE + (e_n + F::length_error(h)),
        None => F::ONE,
    }
}

/// A microfacet lobe multiplied by its length-error factor
/// ([`microfacet_length_correction`]), unless the errors were left out.
#[inline(always)]
pub fn corrected<F: Real>(spec: F, errors: Option<[F; 3]>, h: F::V3) -> F {
    match errors {
        Some([e_n, e_i, e_o]) => microfacet_length_correction(spec, e_n, e_i, e_o, h),
        None => spec,
    }
}

impl Kernel for Ggx {
    type Prepared<F: Real> = Prepared<F>;
    const LENGTH_CORRECTIONS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        Prepared {
            kd_over_pi: KD.read(p).map(|c| c * F::FRAC_1_PI),
            f0: KS.read(p),
            ndf: Ndf::new(ALPHA.read(p)),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let lobe = lobe::<F, P>(d, &pp.ndf);
        schlick_microfacet_value(lobe, pp.f0, pp.kd_over_pi, d)
    }

    /// Lobes drawn from the visible normals with their closed-form weights
    /// ([`Integral::GgxVisible`]).
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        schlick_microfacet_terms(slots, |alpha, f0, basis| Integral::GgxVisible {
            alpha,
            f0,
            basis,
        })
    }
}

/// The value of a microfacet model with Schlick's Fresnel in this layout (`ggx`,
/// [`super::beckmann`]): `kd/π + F·lobe` above both directions, from the lobe as [`lobe`]
/// returns it (0 where it is undefined) and `F0 = f0`.
#[inline(always)]
pub fn schlick_microfacet_value<F: Real>(
    (spec, cos_b, defined): (F, Cosine<F>, bool),
    f0: [F; 3],
    kd_over_pi: [F; 3],
    d: &Directions<F>,
) -> [F; 3] {
    let spec = if defined { spec } else { F::ZERO };
    let fresnel = schlick_rgb(f0, schlick_weight(cos_b));
    let rgb = [0, 1, 2].map(|c| weighted(fresnel[c], spec) + kd_over_pi[c]);
    above_both(d.n.dot(d.wi), d.n.dot(d.wo), rgb)
}

/// The albedo terms of such a model: `kd·1 + F0·I(F0 = 1) + (1 − F0)·I(F0 = 0)`, each
/// lobe the integral `visible(alpha, f0, basis)` gives (`basis`: the slots with `kd = 0`
/// and `ks = f0`).
pub fn schlick_microfacet_terms(
    slots: &[f64],
    visible: impl Fn(f64, f64, Slots) -> Integral,
) -> Option<Vec<Term>> {
    let alpha = ALPHA.read(slots);
    let diffuse = Term {
        colour: KD.read(slots),
        integral: Integral::Exact(1.0),
    };
    Some(diffuse_and_schlick_lobe(diffuse, KS.read(slots), |f0| {
        visible(alpha, f0, basis(slots, &[(KD, 0.0), (KS, f0)]))
    }))
}
