//! What the rough dielectric BSDFs share (docs/models.md: `ggx_dielectric`,
//! `beckmann_dielectric`; Walter, Marschner, Li & Torrance 2007, pbrt-v4's
//! `DielectricBxDF`): the kernel over a microfacet distribution, the parameter layout and
//! the spec fields.
//!
//! These are the models defined on the whole sphere of `wi` and `wo` (the spec's
//! [`transmission`](super::spec::ModelSpec::transmission)): `n` separates the medium of
//! index 1 (on `n`'s side) from the medium of relative index `eta` (below). With
//! `mu_i = n·wi`, `mu_o = n·wo`, `eta_i`, `eta_o` the indices of the media `wi`, `wo` lie
//! in, and the height-correlated `G2 = 1/(1 + Λ(|mu_i|) + Λ(|mu_o|))` for both lobes:
//!
//! - reflection (`mu_i·mu_o > 0`): `h = ±(wi + wo)/|wi + wo|` with `n·h > 0`,
//!   `f = ks·F(|wi·h|)·D(h)·G2/(4|mu_i||mu_o|)`;
//! - transmission (`mu_i·mu_o < 0`): `h = ∓(eta_i·wi + eta_o·wo)/|…|` with `n·h > 0`, 0
//!   unless `(wi·h)·mu_i > 0` and `(wo·h)·mu_o > 0`, else
//!   `f = kt·|wi·h||wo·h|·eta_o²·(1 − F(|wi·h|))·D(h)·G2 / (|mu_i||mu_o|·(eta_i(wi·h) + eta_o(wo·h))²)`;
//!
//! `F` the exact unpolarized dielectric reflectance at `|wi·h|` for the relative index
//! `eta_o/eta_i` of `wi`'s side (`eta` above, `1/eta` below; total internal reflection
//! gives 1), [`fresnel::conductor`] with `k = 0` ([`reflectance`]: exactly 1 under total
//! internal reflection, `1 − T` near 1), and `1 − F` of a refraction formed directly from
//! `|wi·h|` and `|wo·h|` ([`transmittance`]). `mu_i = 0` or `mu_o = 0` gives 0.
//!
//! The transmission's denominator `(eta_i(wi·h) + eta_o(wo·h))²` is `|eta_i·wi + eta_o·wo|²`
//! exactly (`h` is that vector normalized), the squared length the kernel already has:
//! no cancellation where the two terms nearly cancel. `D·G2/(4|mu_i||mu_o|)` of the
//! cosines' absolute values is [`Microfacets::lobe`]: `ggx`'s own form for GGX, and
//! [`smith_quotient`] with `L = μ·Λ(μ)` in `beckmann`'s bounded form
//! ([`beckmann::mu_lambda`]) for Beckmann.

use std::marker::PhantomData;

use super::fresnel::{self, INDEX_RANGE};
use super::ggx::Facet;
use super::sheen::Dd;
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{self, DiffuseTerm, ModelSpec, ParamKind, ParamSpec, SceneUse, ValidRange};
use super::{Directions, Kernel, ParamSource, Registered, beckmann};
use crate::math::geometry::{
    Cosine, ggx_mu_lambda, half_vector_exact, microfacet_length_correction, smith_quotient,
    weighted,
};
use crate::math::{PowUnit, Real, Vector3, max};
use crate::sampling::Warp;
use crate::sampling::dielectric::DielectricSampler;

crate::param_slots! {
    KS: ColourSlot,
    KT: ColourSlot,
    ETA: ScalarSlot,
    ALPHA: ScalarSlot,
}

/// A microfacet distribution: its NDF and Smith function, of roughness `alpha`.
pub trait Microfacets: 'static {
    /// The constants derived from `alpha`.
    type Prepared<F: Real>: Copy + Send + Sync;
    /// Returns the constants for roughness `alpha`.
    fn prepare<F: Real>(alpha: F) -> Self::Prepared<F>;
    /// Returns `D(h)` at the facet `h` (`cos θh ≥ 0`).
    fn ndf<F: Real>(p: &Self::Prepared<F>, facet: &Facet<F>) -> F;
    /// Returns `μ·Λ(μ)` for `μ ≥ 0` given `sin²θ = |n × w|²`.
    fn mu_lambda<F: Real>(p: &Self::Prepared<F>, mu: F, sin2: F) -> F;
    /// The warp that draws its visible normals at roughness `alpha`.
    fn visible_normals(alpha: f64) -> Warp;

    /// Returns `w·D(h)·G2/(4 mu_i mu_o)` given a weight `w >= 0` (the Fresnel part),
    /// the facet `h` (`cos θh ≥ 0`), the cosines `mu = [mu_i, mu_o]` (positive) and their
    /// `sin²θ = |n × w|²`: [`smith_quotient`] of the weighted NDF and the `μ·Λ(μ)`s (the
    /// NDF flushed as [`Real::flush_subnormal`] does). The weight joins the numerator
    /// before the last division by the larger cosine: at grazing incidence the lobe alone
    /// can exceed the float range where a tiny Fresnel part (`eta` near 1) keeps the value
    /// finite. `w = 0` gives 0.
    #[inline(always)]
    fn lobe<F: Real>(p: &Self::Prepared<F>, w: F, facet: &Facet<F>, mu: [F; 2], sin2: [F; 2]) -> F {
        let ndf = F::flush_subnormal(Self::ndf(p, facet));
        let l_i = Self::mu_lambda(p, mu[0], sin2[0]);
        let l_o = Self::mu_lambda(p, mu[1], sin2[1]);
        smith_quotient(weighted(w, ndf), mu[0], mu[1], l_i, l_o)
    }
}

/// GGX: `D = α²/(π(sin²θh + α²cos²θh)²)` ([`super::ggx::Ndf`]) and `ggx`'s Smith
/// function.
pub struct Ggx;

impl Microfacets for Ggx {
    /// The NDF's constants, as `ggx` prepares them.
    type Prepared<F: Real> = super::ggx::Ndf<F>;

    #[inline(always)]
    fn prepare<F: Real>(alpha: F) -> Self::Prepared<F> {
        super::ggx::Ndf::new(alpha)
    }

    #[inline(always)]
    fn ndf<F: Real>(p: &Self::Prepared<F>, facet: &Facet<F>) -> F {
        p.eval(facet)
    }

    #[inline(always)]
    fn mu_lambda<F: Real>(p: &Self::Prepared<F>, mu: F, sin2: F) -> F {
        ggx_mu_lambda(mu, sin2, p.alpha2)
    }

    fn visible_normals(alpha: f64) -> Warp {
        Warp::GgxVisible { alpha }
    }

    /// `ggx`'s lobe ([`super::ggx::lobe`]) after its half vector: the weighted NDF into
    /// the same Smith quotient ([`super::ggx::smith_lobe`]), fewer roundings than the
    /// `μ·Λ(μ)` quotient.
    #[inline(always)]
    fn lobe<F: Real>(p: &Self::Prepared<F>, w: F, facet: &Facet<F>, mu: [F; 2], sin2: [F; 2]) -> F {
        let ndf = weighted(w, p.eval(facet));
        let alpha2 = p.alpha2;
        super::ggx::smith_lobe(ndf, mu[0], mu[1], alpha2 * sin2[0], alpha2 * sin2[1])
    }
}

/// Beckmann: `D = exp(−tan²θh/α²)/(π α² cos⁴θh)` and `beckmann`'s exact Smith function.
pub struct Beckmann;

impl Microfacets for Beckmann {
    /// `α` and `α²`.
    type Prepared<F: Real> = (F, F);

    #[inline(always)]
    fn prepare<F: Real>(alpha: F) -> (F, F) {
        (alpha, alpha * alpha)
    }

    #[inline(always)]
    fn ndf<F: Real>(p: &(F, F), facet: &Facet<F>) -> F {
        let c2 = facet.cos * facet.cos;
        let t = facet.sin2_product() / (p.1 * c2);
        let ndf = (-t).exp() / (F::PI * p.1 * c2 * c2);
        // Far from the peak exp(−t) is 0 before cos⁴ underflows: 0/0 is 0 there.
        if ndf.is_nan() { F::ZERO } else { ndf }
    }

    #[inline(always)]
    fn mu_lambda<F: Real>(p: &(F, F), mu: F, sin2: F) -> F {
        beckmann::mu_lambda(mu, sin2, p.0)
    }

    fn visible_normals(alpha: f64) -> Warp {
        Warp::BeckmannVisible { alpha }
    }
}

/// The kernel of a rough dielectric over the distribution `M`; its spec is the model
/// file's, where the model is registered ([`Registered`]).
pub struct Dielectric<M>(PhantomData<M>);

/// Derived constants of a [`Dielectric`].
#[derive(Clone, Copy)]
pub struct Prepared<F, L> {
    ks: [F; 3],
    kt: [F; 3],
    eta: F,
    /// The Fresnel term seen from above (relative index `eta`) and from below (`1/eta`).
    above: fresnel::Conductor<F>,
    below: fresnel::Conductor<F>,
    /// `(r², r² − 1)` of each side, for [`reflectance`].
    r_above: (F, F),
    r_below: (F, F),
    lobe: L,
}

/// Returns the reflectance `F` at `cos_b = |wi·h|` (with its complement) seen from `wi`'s
/// side, of relative index `r` (`r2 = r²`, `e = r² − 1`, `channel` its
/// [`fresnel::Conductor`] with `k = 0`):
///
/// - 1 exactly under total internal reflection (`g² = e + c² < 0`), where the conductor
///   form's `|r_s|²` is a quotient of equal numbers, 1 within a few roundings;
/// - where `F > 1/2`, `1 − T` with the transmittance
///   `T = 2cg(1/(c + g)² + r²/(r²c + g)²)`, `g = sqrt(g²)` (the two polarizations'
///   `1 − r²`, sums of positive terms): `T`'s rounding errors are of `T`'s size, so `F`
///   near 1 (grazing, a large or small `r`) keeps its last digits;
/// - else the conductor form ([`fresnel::conductor`]).
#[inline(always)]
fn reflectance<F: Real>(channel: &fresnel::Conductor<F>, cos_b: Cosine<F>, r2: F, e: F) -> F {
    let c = cos_b.cos;
    let g2 = e + c * c;
    let g = max(g2, F::ZERO).sqrt();
    let (a, b) = (c + g, r2 * c + g);
    let t = F::TWO * c * g * (F::ONE / (a * a) + r2 / (b * b));
    let f = fresnel::conductor(channel, cos_b);
    if g2 < F::ZERO {
        F::ONE
    } else if f > F::HALF {
        F::ONE - t
    } else {
        f
    }
}

/// Returns `1 − F` of a refraction from the cosines on the two sides of the facet,
/// `c_i = |wi·h|` in the medium of index `eta_i` and `c_o = |wo·h|` in that of `eta_o`
/// (Snell's law holds between them), as the two polarizations' `1 − r²`:
/// `2·eta_i c_i·eta_o c_o·(1/(eta_i c_i + eta_o c_o)² + 1/(eta_o c_i + eta_i c_o)²)`.
/// Every sum adds positive terms: no cancellation where `F → 1`, nor near the critical
/// angle, where `g = sqrt(r² − 1 + c_i²)` would keep only the absolute digits of `c_i²`.
#[inline(always)]
pub fn transmittance<F: Real>(c_i: F, c_o: F, eta_i: F, eta_o: F) -> F {
    let (a, b) = (eta_i * c_i, eta_o * c_o);
    let (p, q) = (eta_o * c_i, eta_i * c_o);
    let (s, t) = (a + b, p + q);
    F::TWO * a * b * (F::ONE / (s * s) + F::ONE / (t * t))
}

/// Returns `v` or `−v` (a multiplication by ±1: exact and branch-free).
#[inline(always)]
fn flipped<F: Real>(v: F::V3, flip: bool) -> F::V3 {
    v * if flip { -F::ONE } else { F::ONE }
}

type V64 = <f64 as Real>::V3;

/// The transmission's generalized half vector, in `f64` whatever `F`: `h = s/|s|` turned
/// to `n`'s side, `s = eta_i·wi + eta_o·wo` of the exact unit vectors `w·(1 − e/2)`
/// ([`Real::length_error`]; 0 in `f32`), and `|s|`; `k` is `[eta_i, eta_o, e_i, e_o]`.
/// The sampler's density forms the same vector.
///
/// Where the two terms nearly cancel (`eta` near 1, `wo` near `−wi`) `s` is short and its
/// direction is all that matters: the products are formed in double width (Dekker's
/// [`Dd::two_prod`]: exact for `f32` inputs, to about a rounding of their low parts for
/// `f64` ones, see its doc), summed with their errors and the length corrections, and
/// rounded once, so `s` keeps most of its relative precision however short it is.
#[inline(always)]
pub fn refraction_half_vector(wi: [f64; 3], wo: [f64; 3], n: [f64; 3], k: [f64; 4]) -> (V64, f64) {
    let [eta_i, eta_o, e_i, e_o] = k;
    let (half_i, half_o) = (0.5 * eta_i * e_i, 0.5 * eta_o * e_o);
    let s: [f64; 3] = std::array::from_fn(|j| {
        let (a, a_lo) = Dd::two_prod(eta_i, wi[j]).parts();
        let (b, b_lo) = Dd::two_prod(eta_o, wo[j]).parts();
        let (t, t_lo) = Dd::two_sum(a, b).parts();
        t + (((t_lo + a_lo) + b_lo) - (half_i * wi[j] + half_o * wo[j]))
    });
    let (h, len) = <f64 as Real>::normalize_length(V64::new(s[0], s[1], s[2]));
    let towards_n = h.x * n[0] + h.y * n[1] + h.z * n[2];
    (flipped::<f64>(h, towards_n < 0.0), len)
}

impl<M: Microfacets> Kernel for Dielectric<M>
where
    Self: Registered,
{
    type Prepared<F: Real> = Prepared<F, M::Prepared<F>>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Self::Prepared<F> {
        let eta = ETA.read(p);
        let eta2 = eta * eta;
        let above = (eta2, (eta - F::ONE) * (eta + F::ONE));
        // (1/eta)² − 1 from eta itself: 1/eta − 1 would cancel to the rounding of 1/eta
        // near eta = 1.
        let below = (F::ONE / eta2, (F::ONE - eta) * (F::ONE + eta) / eta2);
        Prepared {
            ks: KS.read(p),
            kt: KT.read(p),
            eta,
            above: fresnel::Conductor::dielectric(above.0, above.1),
            below: fresnel::Conductor::dielectric(below.0, below.1),
            r_above: above,
            r_below: below,
            lobe: M::prepare(ALPHA.read(p)),
        }
    }

    /// `f64`: the value of the exact unit vectors, as `ggx`'s lobe is
    /// ([`super::ggx::lobe`]): the rounded vectors' length errors `e = |w|² − 1`
    /// ([`Real::length_error`]) are taken out of both half vectors
    /// ([`half_vector_exact`], [`refraction_half_vector`]), of the cosines `wi·h`, `wo·h`
    /// and of `D·G2/(4|mu_i||mu_o|)` ([`microfacet_length_correction`]).
    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Self::Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let i_above = mu_i > F::ZERO;
        let o_above = mu_o > F::ZERO;
        let reflect = i_above == o_above;
        let eta_i = if i_above { F::ONE } else { pp.eta };
        let eta_o = if o_above { F::ONE } else { pp.eta };
        let [e_n, e_i, e_o] = [d.n, d.wi, d.wo].map(F::length_error);
        // Reflection: h ∥ wi + wo, with cos_b = |wi + wo|/2 = |wi·h| and its complement.
        let hv = half_vector_exact::<F>(d.wi, d.wo, e_i, e_o);
        // Transmission: h ∥ eta_i·wi + eta_o·wo, and the cosines wi·h, wo·h of the exact
        // unit vectors (f32: from the f64 sum, as they cancel at the edges of the
        // physical refractions and scale the transmitted lobe).
        let wide = |v: F::V3| [v.x(), v.y(), v.z()].map(F::to_f64);
        let (wi64, wo64) = (wide(d.wi), wide(d.wo));
        let k = [eta_i, eta_o, e_i, e_o].map(F::to_f64);
        let (h64, len) = refraction_half_vector(wi64, wo64, wide(d.n), k);
        let e_h = if F::EXACT_LENGTHS {
            <f64 as Real>::length_error(h64)
        } else {
            0.0
        };
        let dot = |w: [f64; 3], e: f64| {
            (w[0] * h64.x + w[1] * h64.y + w[2] * h64.z) * (1.0 - 0.5 * (e + e_h))
        };
        let (c_i, c_o) = (dot(wi64, k[2]), dot(wo64, k[3]));
        let (ci, co) = (c_i.abs(), c_o.abs());
        // 4|wi·h||wo·h|·eta_o²/(eta_i(wi·h) + eta_o(wo·h))², the denominator being |s|²,
        // times 1 − F.
        let scale = (2.0 * ci * k[1] / len) * (2.0 * co * k[1] / len);
        let refracted = F::from_f64(scale * transmittance(ci, co, k[0], k[1]));
        let physical = c_i * mu_i.to_f64() > 0.0 && c_o * mu_o.to_f64() > 0.0;
        let h_t = F::V3::new(F::from_f64(h64.x), F::from_f64(h64.y), F::from_f64(h64.z));
        let h_r = flipped::<F>(hv.h, d.n.dot(hv.h) < F::ZERO);
        let h = if reflect { h_r } else { h_t };
        let nh2 = super::ggx::lengths_squared(Some([e_n, e_i, e_o]), h);
        let mut facet = Facet::new(d.n, h, nh2);
        let cos_th = facet.cos;
        facet.cos = max(cos_th, F::ZERO);
        let sin2 = [d.wi, d.wo].map(|w| d.n.cross(w).length_squared());
        let mu = [mu_i.abs(), mu_o.abs()];
        // F at |wi·h| from wi's side.
        let channel = fresnel::Conductor::select(i_above, &pp.above, &pp.below);
        let (r2, e) = if i_above { pp.r_above } else { pp.r_below };
        let fr = reflectance(&channel, hv.cos_b, r2, e);
        // The Fresnel part times D·G2/(4|mu_i||mu_o|), of the exact unit vectors.
        let part = if reflect { fr } else { refracted };
        let lobe = M::lobe(&pp.lobe, part, &facet, mu, sin2);
        let lobe = microfacet_length_correction(lobe, e_n, e_i, e_o, h);
        // eta = 1: no interface, the transmission is the delta wo = −wi (0 as a function
        // value, also where rounding leaves wi + wo a little off 0). h in the tangent
        // plane cannot be turned to n's side: no facet refracts the pair.
        let interface = pp.eta != F::ONE;
        let transmits = len > 0.0 && physical && interface && cos_th > F::ZERO;
        let valid =
            mu_i != F::ZERO && mu_o != F::ZERO && if reflect { hv.defined } else { transmits };
        [0, 1, 2].map(|c| {
            let v = weighted(if reflect { pp.ks[c] } else { pp.kt[c] }, lobe);
            if valid { v } else { F::ZERO }
        })
    }

    /// The visible normals of the distribution, reflection or refraction by Fresnel
    /// ([`crate::sampling::dielectric`]).
    fn transmission_sampler(slots: &[f64]) -> Option<DielectricSampler> {
        Some(DielectricSampler {
            warp: M::visible_normals(ALPHA.read(slots)),
            eta: ETA.read(slots),
        })
    }
}

/// The spec fields both models share: family A on the whole sphere (`transmission`), not
/// reciprocal as `f(wi, wo) = f(wo, wi)` (`f(wi, wo)/eta_o² = f(wo, wi)/eta_i²` instead),
/// no tangent, 0 when `ks` and `kt` are, no tables nor exact normalization, and no place
/// in a scene yet (scenes shade reflection only: a transmitting model is refused there).
pub const DIELECTRIC_SPEC: ModelSpec = ModelSpec {
    source: "Walter, Marschner, Li & Torrance 2007 (rough dielectrics); \
              Pharr, Jakob & Humphreys, pbrt-v4 (DielectricBxDF)",
    reciprocal: false,
    weights: Some(&["ks", "kt"]),
    scene: SceneUse::Brdf(DiffuseTerm::Absent),
    transmission: true,
    ..ModelSpec::PLAIN
};

/// The formula both models' specs share after their `D` and `Λ` (a literal, for
/// `concat!`).
macro_rules! dielectric_formula {
    () => {
        "reflection (mu_i·mu_o > 0): f = ks·F·D·G2/(4|mu_i||mu_o|), h ∥ wi + wo; \
         transmission (mu_i·mu_o < 0): \
         f = kt·|wi·h||wo·h|·eta_o²·(1 − F)·D·G2/(|mu_i||mu_o|(eta_i wi·h + eta_o wo·h)²), \
         h ∥ −(eta_i wi + eta_o wo), 0 unless (wi·h)·mu_i > 0 and (wo·h)·mu_o > 0; \
         n·h > 0; eta_w = 1 above, eta below; G2 = 1/(1+Λ(|mu_i|)+Λ(|mu_o|)); \
         F = exact dielectric reflectance at |wi·h| for the relative index eta_o/eta_i \
         of wi's side (1 past the critical angle)"
    };
}
pub(crate) use dielectric_formula;

/// The parameters, `alpha` documented as `alpha_doc`.
pub const fn params(alpha_doc: &'static str) -> [ParamSpec; 4] {
    [
        ParamSpec {
            name: "ks",
            kind: ParamKind::Colour,
            default: Some(1.0),
            range: ValidRange::NON_NEGATIVE,
            doc: "tint of the reflected lobe (RGB, >= 0; 1 for a clear interface)",
            slot: KS.first(),
        },
        ParamSpec {
            name: "kt",
            kind: ParamKind::Colour,
            default: Some(1.0),
            range: ValidRange::NON_NEGATIVE,
            doc: "tint of the transmitted lobe (RGB, >= 0; 1 for a clear interface)",
            slot: KT.first(),
        },
        ParamSpec {
            name: "eta",
            kind: ParamKind::Scalar,
            default: Some(1.5),
            range: INDEX_RANGE,
            doc: "relative index of refraction eta_below/eta_above (below: the side opposite \
                  n; in [1e-7, 1e7]; 1.5 is glass under air, below 1 the denser medium is on \
                  n's side, 1 no interface: the transmission is a delta, 0 as a function)",
            slot: ETA.first(),
        },
        spec::roughness("alpha", 0.5, ALPHA, alpha_doc),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::ModelKind;
    use crate::models::beckmann_dielectric::BeckmannDielectric;
    use crate::models::ggx_dielectric::GgxDielectric;
    use glam::DVec3;

    /// The spec's definition written out directly (f64, `ks = kt = 1`), and the Fresnel
    /// term's `|g²| = |r² − 1 + c²|`, whose square root makes `F` ill-conditioned near
    /// the critical angle.
    fn reference_and_g2(
        ggx: bool,
        alpha: f64,
        eta: f64,
        wi: DVec3,
        wo: DVec3,
        n: DVec3,
    ) -> (f64, f64) {
        let (mu_i, mu_o) = (n.dot(wi), n.dot(wo));
        if mu_i == 0.0 || mu_o == 0.0 {
            return (0.0, 1.0);
        }
        let side = |mu: f64| if mu > 0.0 { 1.0 } else { eta };
        let (eta_i, eta_o) = (side(mu_i), side(mu_o));
        let lambda = |mu: f64| {
            let mu = mu.abs();
            if ggx {
                (-1.0 + (1.0 + alpha * alpha * (1.0 - mu * mu) / (mu * mu)).sqrt()) / 2.0
            } else {
                let c = mu / (alpha * (1.0 - mu * mu).sqrt());
                (libm::erf(c) - 1.0) / 2.0
                    + (-c * c).exp() / (2.0 * c * std::f64::consts::PI.sqrt())
            }
        };
        let ndf = |c: f64| {
            let a2 = alpha * alpha;
            if ggx {
                let k = c * c * (a2 - 1.0) + 1.0;
                a2 / (std::f64::consts::PI * k * k)
            } else {
                (-(1.0 - c * c) / (c * c * a2)).exp() / (std::f64::consts::PI * a2 * c.powi(4))
            }
        };
        let fresnel = |c: f64, r: f64| {
            let g2 = r * r - 1.0 + c * c;
            if g2 < 0.0 {
                return 1.0;
            }
            let g = g2.sqrt();
            let a = (g - c) / (g + c);
            let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
            0.5 * a * a * (1.0 + b * b)
        };
        let g2 = 1.0 / (1.0 + lambda(mu_i) + lambda(mu_o));
        let r_i = if mu_i > 0.0 { eta } else { 1.0 / eta };
        let g2_at = |c: f64| (r_i * r_i - 1.0 + c * c).abs();
        if mu_i * mu_o > 0.0 {
            let mut h = (wi + wo).normalize();
            if n.dot(h) < 0.0 {
                h = -h;
            }
            let f = fresnel(wi.dot(h).abs(), r_i) * ndf(n.dot(h)) * g2
                / (4.0 * mu_i.abs() * mu_o.abs());
            (f, g2_at(wi.dot(h)))
        } else {
            let mut h = -(wi * eta_i + wo * eta_o);
            if h.length() == 0.0 {
                return (0.0, 1.0);
            }
            h = h.normalize();
            if n.dot(h) < 0.0 {
                h = -h;
            }
            let (ci, co) = (wi.dot(h), wo.dot(h));
            if ci * mu_i <= 0.0 || co * mu_o <= 0.0 {
                return (0.0, 1.0);
            }
            let denom = eta_i * ci + eta_o * co;
            let f = ci.abs() * co.abs() / (mu_i.abs() * mu_o.abs())
                * eta_o
                * eta_o
                * (1.0 - fresnel(ci.abs(), r_i))
                * ndf(n.dot(h))
                * g2
                / (denom * denom);
            (f, g2_at(ci))
        }
    }

    fn slots(alpha: f64, eta: f64) -> Vec<f64> {
        let mut s = vec![0.0; 8];
        KS.write(&mut s, [1.0, 0.5, 0.0]);
        KT.write(&mut s, [1.0, 0.25, 0.0]);
        ETA.write(&mut s, eta);
        ALPHA.write(&mut s, alpha);
        s
    }

    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn sphere(&mut self) -> DVec3 {
            let z = 2.0 * self.next() - 1.0;
            let phi = 2.0 * std::f64::consts::PI * self.next();
            let r = (1.0 - z * z).max(0.0).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        }
    }

    fn eval<K: Kernel>(s: &[f64], wi: DVec3, wo: DVec3, n: DVec3) -> [f64; 3] {
        let p = K::prepare::<f64, [f64]>(s);
        K::eval::<f64>(
            &p,
            &Directions {
                wi,
                wo,
                n,
                t: n.any_orthonormal_vector(),
            },
        )
    }

    fn eval32<K: Kernel>(s: &[f64], wi: DVec3, wo: DVec3, n: DVec3) -> [f32; 3] {
        let s32: Vec<f32> = s.iter().map(|&x| x as f32).collect();
        let p = K::prepare::<f32, [f32]>(&s32);
        K::eval::<f32>(
            &p,
            &Directions {
                wi: wi.as_vec3().normalize(),
                wo: wo.as_vec3().normalize(),
                n: n.as_vec3().normalize(),
                t: n.any_orthonormal_vector().as_vec3(),
            },
        )
    }

    /// Both kernels, in both widths, against the definition over the whole sphere.
    fn check_against_reference<K: Kernel>(ggx: bool) {
        let mut rng = Lcg(5);
        let n = DVec3::new(0.1, -0.2, 0.97).normalize();
        for eta in [1.5, 1.0 / 1.5, 1.02, 2.4, 0.3] {
            for alpha in [0.08, 0.5, 1.3] {
                let s = slots(alpha, eta);
                for _ in 0..3000 {
                    let (wi, wo) = (rng.sphere(), rng.sphere());
                    let (want, g2) = reference_and_g2(ggx, alpha, eta, wi, wo, n);
                    let got = eval::<K>(&s, wi, wo, n);
                    let reflect = n.dot(wi) * n.dot(wo) > 0.0;
                    let tint = if reflect { 0.5 } else { 0.25 };
                    let at = format!("{eta} {alpha} {wi} {wo}: {got:?} vs {want}");
                    let tol = 1e-10 + 1e-15 / g2;
                    // Beckmann's far tail is 0 below exp(−700).
                    assert!((got[0] - want).abs() <= tol * want + 1e-290, "{at}");
                    assert_eq!(got[1], got[0] * tint, "{at}");
                    assert_eq!(got[2], 0.0, "{at}");
                    // f32 against the definition at the f32 directions.
                    let r = |w: DVec3| w.as_vec3().normalize().as_dvec3();
                    let exact = want;
                    let (want, g2) = reference_and_g2(ggx, alpha, eta, r(wi), r(wo), r(n));
                    let got32 = eval32::<K>(&s, wi, wo, n);
                    let err = (f64::from(got32[0]) - want).abs();
                    // g² is formed to about 1e-7 in f32: F's square root near the
                    // critical angle passes on 1e-7/g² relative; where rounding the
                    // directions to f32 moves the value itself (the edges of the
                    // physical refractions), a hundred times that move.
                    let moved = (want - exact).abs() / want.max(exact).max(1e-300);
                    let tol = 1e-3 + 1e-6 / g2 + 100.0 * moved;
                    let scale = want.max(exact);
                    // (f32 flushes values below 2^-100 in the NDF.)
                    assert!(err <= tol * scale + 1e-25, "f32 {at}: {got32:?} vs {want}");
                }
            }
        }
    }

    #[test]
    fn kernels_match_the_definition() {
        check_against_reference::<GgxDielectric>(true);
        check_against_reference::<BeckmannDielectric>(false);
    }

    /// `f(wi, wo)/eta_o² = f(wo, wi)/eta_i²`.
    fn check_reciprocity<K: Kernel>() {
        let mut rng = Lcg(9);
        let n = DVec3::Z;
        for eta in [1.5, 0.7] {
            let s = slots(0.4, eta);
            for _ in 0..3000 {
                let (wi, wo) = (rng.sphere(), rng.sphere());
                let side = |w: DVec3| if w.z > 0.0 { 1.0 } else { eta };
                let a = eval::<K>(&s, wi, wo, n)[0] / (side(wo) * side(wo));
                let b = eval::<K>(&s, wo, wi, n)[0] / (side(wi) * side(wi));
                assert!((a - b).abs() <= 1e-10 * a.max(b), "{wi} {wo}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn kernels_are_reciprocal_with_the_eta_squared_factors() {
        check_reciprocity::<GgxDielectric>();
        check_reciprocity::<BeckmannDielectric>();
    }

    #[test]
    fn eta_one_has_no_reflection_and_no_rough_transmission() {
        let mut rng = Lcg(13);
        let s = slots(0.5, 1.0);
        for _ in 0..5000 {
            let (wi, wo) = (rng.sphere(), rng.sphere());
            assert_eq!(eval::<GgxDielectric>(&s, wi, wo, DVec3::Z), [0.0; 3]);
            assert_eq!(eval::<BeckmannDielectric>(&s, wi, wo, DVec3::Z), [0.0; 3]);
        }
        let wi = DVec3::new(0.3, 0.1, 0.8).normalize();
        assert_eq!(eval::<GgxDielectric>(&s, wi, -wi, DVec3::Z), [0.0; 3]);
    }

    /// `∫ f·|n·wo| dωo` over the sphere by a midpoint rule: reflection and transmission
    /// add to at most 1 (no absorption; the single-scattering loss is small at `α = 0.3`).
    #[test]
    fn energy_is_conserved() {
        let (nt, np) = (1200, 600);
        for eta in [1.5, 1.0 / 1.5] {
            let s = slots(0.3, eta);
            let mu: f64 = 0.8;
            let wi = DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            let (mut r, mut t) = (0.0, 0.0);
            crate::sampling::sphere_midpoints(nt, np, |wo, dw| {
                let f = eval::<GgxDielectric>(&s, wi, wo, DVec3::Z)[0] * wo.z.abs() * dw;
                if wo.z > 0.0 { r += f } else { t += f }
            });
            // Inside the denser medium near the critical angle much of the light is
            // reflected twice or more, which single scattering leaves out.
            let least = if eta > 1.0 { 0.95 } else { 0.8 };
            assert!(r + t <= 1.0 && r + t > least, "eta={eta}: R={r} T={t}");
            assert!(r > 0.02, "eta={eta}: R={r}");
        }
    }

    #[test]
    fn transmittance_is_one_minus_the_reflectance() {
        for r in [1.5, 1.0 / 1.5, 1.02, 1e-3, 1e3] {
            let ch = fresnel::Conductor::new(r, 0.0);
            for i in 1..=400 {
                let c = f64::from(i) / 400.0;
                // The refracted cosine (Snell's law), where there is one.
                let c_t2 = 1.0 - (1.0 - c * c) / (r * r);
                if c_t2 <= 0.0 {
                    continue;
                }
                let cos = crate::math::geometry::Cosine {
                    cos: c,
                    one_minus: 1.0 - c,
                };
                let t = transmittance(c, c_t2.sqrt(), 1.0, r);
                let f = fresnel::conductor(&ch, cos);
                assert!((t + f - 1.0).abs() <= 1e-13, "r={r} c={c}: {t} + {f}");
            }
        }
    }

    /// `reflectance` is the conductor form's `F` (within rounding), 1 exactly past the
    /// critical angle, and keeps `1 − F`'s digits where `F` is near 1.
    #[test]
    fn reflectance_is_exact_under_total_internal_reflection() {
        for r in [1.5, 1.0 / 1.5, 0.3, 1e3, 1e-3] {
            let (r2, e) = (r * r, (r - 1.0) * (r + 1.0));
            let ch = fresnel::Conductor::new(r, 0.0);
            for i in 0..=400 {
                let c = f64::from(i) / 400.0;
                let cos = Cosine {
                    cos: c,
                    one_minus: 1.0 - c,
                };
                let (f, want) = (reflectance(&ch, cos, r2, e), fresnel::conductor(&ch, cos));
                if e + c * c < 0.0 {
                    assert_eq!(f, 1.0, "r={r} c={c}");
                } else {
                    assert!((f - want).abs() <= 1e-14, "r={r} c={c}: {f} vs {want}");
                }
                // 1 − F = T of the refraction, where there is one.
                let c_t2 = 1.0 - (1.0 - c * c) / r2;
                if c > 0.0 && c_t2 > 0.0 {
                    let t = transmittance(c, c_t2.sqrt(), 1.0, r);
                    assert!(((1.0 - f) - t).abs() <= 1e-15 + 1e-13 * t, "r={r} c={c}");
                }
            }
        }
    }

    /// The channel below from `eta` itself matches `new(1/eta, 0)` where `1/eta` is exact,
    /// and keeps `F`'s digits next to `eta = 1`, where `F ≈ ((eta − 1)/2)²`.
    #[test]
    fn fresnel_from_below_keeps_its_digits_next_to_one() {
        let c = crate::math::geometry::Cosine {
            cos: 1.0,
            one_minus: 0.0,
        };
        let below = |eta: f64| {
            fresnel::Conductor::dielectric(
                1.0 / (eta * eta),
                (1.0 - eta) * (1.0 + eta) / (eta * eta),
            )
        };
        let (exact, half) = (fresnel::Conductor::new(0.5, 0.0), below(2.0));
        assert_eq!(fresnel::conductor(&exact, c), fresnel::conductor(&half, c));
        for eta in [1.0_f64 + 1e-6, 1.0 - 1e-6, 1.0 + 1e-12, 1.0 - 1e-12] {
            // At normal incidence F = ((1 − r)/(1 + r))² for r = 1/eta, = ((eta − 1)/(eta + 1))².
            let want = ((eta - 1.0) / (eta + 1.0)).powi(2);
            let got = fresnel::conductor(&below(eta), c);
            assert!((got - want).abs() <= 1e-14 * want, "{eta}: {got} vs {want}");
        }
    }

    #[test]
    fn specs_say_they_transmit() {
        for kind in ModelKind::ALL {
            let name = kind.name();
            // The interfaces and the compensated `ggx_dielectric_ms`.
            let dielectric = name.ends_with("_dielectric") || name.ends_with("_dielectric_ms");
            assert_eq!(kind.spec().transmission, dielectric, "{name}");
        }
    }
}
