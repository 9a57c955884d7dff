//! What the Fresnel variants of `ggx` and `beckmann` share (docs/models.md:
//! `ggx_conductor`, `beckmann_conductor`, `ggx_f82`, `beckmann_f82`, `ggx_gen_schlick`,
//! `beckmann_gen_schlick`): a kernel over a microfacet lobe and a Fresnel
//! term, the parameter layouts and the albedo terms.
//!
//! Each variant is `f = kd/π + F(cos_b)·lobe`, where `lobe = D·G2/(4 mu_i mu_o)` is
//! exactly the base model's ([`ggx::lobe`], [`beckmann::lobe`]: the same function, so a
//! variant whose `F` is 1 gives the base model's value at `ks = 1` bit for bit) and `F`
//! is one of [`super::fresnel`]'s terms, per colour channel, at `cos_b = wi·h`. A model
//! file holds its spec and names its pair: `pub type GgxConductor = Variant<Ggx,
//! Conductor>`.
//!
//! The integrator and `brdf_rs.sample` draw the lobe from the base model's visible
//! normals ([`Importance::GgxVisible`], [`Importance::BeckmannVisible`]), with the
//! generic weight `f·mu_o/pdf`: the base models' closed-form weights hold Schlick's `F`
//! only. The conductor's and the (clamped) F82-tint terms are not affine in their
//! colours, so the lobe is integrated once per distinct channel (channels with equal
//! parameters share one integral); the generalized Schlick term is affine in `f0` and
//! `f90`, two integrals.

use std::marker::PhantomData;

use super::albedo::{Importance, Integral, Slots, Term, basis};
use super::fresnel::{self, EXTINCTION_RANGE, INDEX_RANGE};
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{self, DiffuseTerm, ModelSpec, ParamKind, ParamSpec, SceneUse, ValidRange};
use super::{Directions, Kernel, ParamSource, Registered, beckmann, ggx};
use crate::math::geometry::{Cosine, above_both, weighted};
use crate::math::{PowUnit, Real, Vector3};

/// A microfacet lobe `D·G2/(4 mu_i mu_o)` of roughness `alpha`, with the cosine its
/// Fresnel term is evaluated at.
pub trait MicrofacetLobe: 'static {
    /// The constants derived from `alpha`.
    type Prepared<F: Real>: Copy + Send + Sync;
    /// Returns the constants for roughness `alpha`.
    fn prepare<F: Real>(alpha: F) -> Self::Prepared<F>;
    /// Returns the lobe, `cos_b = wi·h` and whether the lobe is defined (as
    /// [`ggx::lobe`]).
    fn eval<F: Real, P: PowUnit>(p: &Self::Prepared<F>, d: &Directions<F>) -> (F, Cosine<F>, bool);
    /// The sampler of the lobe at roughness `alpha`.
    fn importance(alpha: f64) -> Importance;
}

/// The GGX lobe of `ggx` ([`ggx::lobe`]).
pub struct Ggx;

impl MicrofacetLobe for Ggx {
    /// The NDF's constants, as `ggx` prepares them.
    type Prepared<F: Real> = ggx::Ndf<F>;

    #[inline(always)]
    fn prepare<F: Real>(alpha: F) -> ggx::Ndf<F> {
        ggx::Ndf::new(alpha)
    }

    #[inline(always)]
    fn eval<F: Real, P: PowUnit>(p: &ggx::Ndf<F>, d: &Directions<F>) -> (F, Cosine<F>, bool) {
        ggx::lobe::<F, P>(d, p)
    }

    fn importance(alpha: f64) -> Importance {
        Importance::GgxVisible { alpha }
    }
}

/// The Beckmann lobe of `beckmann` ([`beckmann::lobe`]).
pub struct Beckmann;

impl MicrofacetLobe for Beckmann {
    /// `α` and `α²`.
    type Prepared<F: Real> = (F, F);

    #[inline(always)]
    fn prepare<F: Real>(alpha: F) -> (F, F) {
        (alpha, alpha * alpha)
    }

    #[inline(always)]
    fn eval<F: Real, P: PowUnit>(p: &(F, F), d: &Directions<F>) -> (F, Cosine<F>, bool) {
        beckmann::lobe::<F, P>(d, p.0, p.1)
    }

    fn importance(alpha: f64) -> Importance {
        Importance::BeckmannVisible { alpha }
    }
}

/// A Fresnel term with its parameters: their layout (`kd` first, the roughness `alpha`
/// last), the per-channel constants and the decomposition of the lobe's albedo.
pub trait FresnelTerm: 'static {
    /// The constants of one colour channel.
    type Channel<F: Real>: Copy + Send + Sync;
    /// Whether [`FresnelTerm::eval`] raises anything to a power ([`Kernel::POWERS`]).
    const POWERS: bool;
    /// The diffuse colour's slots.
    const KD: ColourSlot;
    /// The roughness's slot.
    const ALPHA: ScalarSlot;
    /// Returns the three channels' constants.
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> [Self::Channel<F>; 3];
    /// Returns `F` of one channel at `cos_b`.
    fn eval<F: Real, P: PowUnit>(ch: &Self::Channel<F>, cos_b: Cosine<F>) -> F;
    /// Returns `F` of the three channels at `cos_b`: [`FresnelTerm::eval`] of each, written
    /// out. (Mapped over the channels by a closure, a term as long as the conductor's is
    /// left as a call per lane, and the block's loop no longer vectorizes: measured, the
    /// conductor variants ran 2.4–2.9× slower in `f64` and 5× in `f32`.)
    #[inline(always)]
    fn eval_rgb<F: Real, P: PowUnit>(ch: &[Self::Channel<F>; 3], cos_b: Cosine<F>) -> [F; 3] {
        [
            Self::eval::<F, P>(&ch[0], cos_b),
            Self::eval::<F, P>(&ch[1], cos_b),
            Self::eval::<F, P>(&ch[2], cos_b),
        ]
    }
    /// The specular lobe's albedo as `Σ colour_k · I_k`: each colour with the parameters
    /// (`kd` = 0) whose lobe integral `I_k` it multiplies.
    fn lobe_terms(slots: &[f64]) -> Vec<([f64; 3], Slots)>;
}

/// The lobe terms of a Fresnel term that is not affine in its colours: one integral per
/// distinct channel, the model evaluated with that channel's values as grey colours
/// (`colours`: the Fresnel term's colour parameters), for the channels that share them.
fn per_channel_terms(
    slots: &[f64],
    kd: ColourSlot,
    colours: &[ColourSlot],
) -> Vec<([f64; 3], Slots)> {
    let values = |c: usize| -> Vec<f64> { colours.iter().map(|s| s.read(slots)[c]).collect() };
    let mut out = Vec::new();
    let mut done = [false; 3];
    for c in 0..3 {
        if done[c] {
            continue;
        }
        let mut colour = [0.0; 3];
        for d in c..3 {
            if !done[d] && values(d) == values(c) {
                colour[d] = 1.0;
                done[d] = true;
            }
        }
        let mut grey = vec![(kd, 0.0)];
        grey.extend(colours.iter().map(|&s| (s, s.read(slots)[c])));
        out.push((colour, basis(slots, &grey)));
    }
    out
}

/// The kernel of a lobe `L` with a Fresnel term `R`; its spec is the model file's, where
/// the model is registered ([`Registered`]).
pub struct Variant<L, R>(PhantomData<(L, R)>);

/// Derived constants of a [`Variant`].
#[derive(Clone, Copy)]
pub struct Prepared<F, L, C> {
    kd_over_pi: [F; 3],
    lobe: L,
    fresnel: [C; 3],
}

impl<L: MicrofacetLobe, R: FresnelTerm> Kernel for Variant<L, R>
where
    Self: Registered,
{
    type Prepared<F: Real> = Prepared<F, L::Prepared<F>, R::Channel<F>>;
    const POWERS: bool = R::POWERS;
    const LENGTH_CORRECTIONS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Self::Prepared<F> {
        Prepared {
            kd_over_pi: R::KD.read(p).map(|c| c * F::FRAC_1_PI),
            lobe: L::prepare(R::ALPHA.read(p)),
            fresnel: R::prepare(p),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Self::Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let (spec, cos_b, defined) = L::eval::<F, P>(&pp.lobe, d);
        let spec = if defined { spec } else { F::ZERO };
        let fresnel = R::eval_rgb::<F, P>(&pp.fresnel, cos_b);
        let rgb = [0, 1, 2].map(|c| weighted(fresnel[c], spec) + pp.kd_over_pi[c]);
        above_both(d.n.dot(d.wi), d.n.dot(d.wo), rgb)
    }

    /// `kd·1` and the lobe's terms ([`FresnelTerm::lobe_terms`]), drawn from the lobe's
    /// visible normals.
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        let importance = L::importance(R::ALPHA.read(slots));
        let mut terms = vec![Term {
            colour: R::KD.read(slots),
            integral: Integral::Exact(1.0),
        }];
        terms.extend(
            R::lobe_terms(slots)
                .into_iter()
                .map(|(colour, basis)| Term {
                    colour,
                    integral: Integral::Lobe { basis, importance },
                }),
        );
        Some(terms)
    }
}

/// The spec fields every variant shares: family A, reciprocal, no tangent, no weights
/// (`F` does not vanish with any set of colours), a Lambert diffuse term in scenes, no
/// split-sum or energy tables (both assume Schlick's `F`), no exact normalization. A
/// model's spec names its own fields and takes these with `..VARIANT_SPEC`.
pub const VARIANT_SPEC: ModelSpec = ModelSpec {
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    ..ModelSpec::PLAIN
};

/// `f0`, the reflectance at normal incidence, of the F82-tint and generalized Schlick
/// terms (`ggx` and `beckmann` call theirs `ks`: [`spec::f0`]).
const fn f0(default: f64, slot: ColourSlot) -> ParamSpec {
    ParamSpec {
        name: "f0",
        kind: ParamKind::Colour,
        default: Some(default),
        range: ValidRange::UNIT,
        doc: "F0: reflectance at normal incidence (RGB, in [0, 1])",
        slot: slot.first(),
    }
}

/// The roughness parameter `alpha` (default 0.5) with the lobe's doc line.
const fn alpha(slot: ScalarSlot, doc: &'static str) -> ParamSpec {
    spec::roughness("alpha", 0.5, slot, doc)
}

/// The conductor Fresnel term ([`fresnel::conductor`]): parameters `kd`, `eta`, `k`,
/// `alpha`.
pub struct Conductor;

/// The conductor variants' layout.
pub mod conductor {
    use super::super::slots::{ColourSlot, ScalarSlot};
    crate::param_slots! {
        KD: ColourSlot,
        ETA: ColourSlot,
        K: ColourSlot,
        ALPHA: ScalarSlot,
    }
}

/// The default `eta` and `k`: a grey metal (spec defaults are grey levels), with
/// normal-incidence reflectance `((η − 1)² + k²)/((η + 1)² + k²) = 9.25/11.25 ≈ 0.82`.
const CONDUCTOR_ETA: f64 = 0.5;
const CONDUCTOR_K: f64 = 3.0;

/// The conductor variants' parameters, `alpha` documented as `alpha_doc`.
pub const fn conductor_params(alpha_doc: &'static str) -> [ParamSpec; 4] {
    [
        spec::kd(0.0, conductor::KD),
        ParamSpec {
            name: "eta",
            kind: ParamKind::Colour,
            default: Some(CONDUCTOR_ETA),
            range: INDEX_RANGE,
            doc: "real part η of the conductor's relative index of refraction η + i·k \
                  (RGB, in [1e-7, 1e7])",
            slot: conductor::ETA.first(),
        },
        ParamSpec {
            name: "k",
            kind: ParamKind::Colour,
            default: Some(CONDUCTOR_K),
            range: EXTINCTION_RANGE,
            doc: "extinction coefficient k, the imaginary part of the relative index \
                  (RGB, in [0, 1e7]; 0 is a dielectric)",
            slot: conductor::K.first(),
        },
        alpha(conductor::ALPHA, alpha_doc),
    ]
}

impl FresnelTerm for Conductor {
    type Channel<F: Real> = fresnel::Conductor<F>;
    const POWERS: bool = false;
    const KD: ColourSlot = conductor::KD;
    const ALPHA: ScalarSlot = conductor::ALPHA;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> [fresnel::Conductor<F>; 3] {
        let (eta, k) = (conductor::ETA.read(p), conductor::K.read(p));
        [0, 1, 2].map(|c| fresnel::Conductor::new(eta[c], k[c]))
    }

    #[inline(always)]
    fn eval<F: Real, P: PowUnit>(ch: &fresnel::Conductor<F>, cos_b: Cosine<F>) -> F {
        fresnel::conductor(ch, cos_b)
    }

    fn lobe_terms(slots: &[f64]) -> Vec<([f64; 3], Slots)> {
        per_channel_terms(slots, conductor::KD, &[conductor::ETA, conductor::K])
    }
}

/// The F82-tint Fresnel term ([`fresnel::f82`]): parameters `kd`, `f0`, `f82`, `alpha`.
pub struct F82Tint;

/// The F82-tint variants' layout.
pub mod f82 {
    use super::super::slots::{ColourSlot, ScalarSlot};
    crate::param_slots! {
        KD: ColourSlot,
        F0: ColourSlot,
        F82: ColourSlot,
        ALPHA: ScalarSlot,
    }
}

/// The F82-tint variants' parameters, `alpha` documented as `alpha_doc`.
pub const fn f82_params(alpha_doc: &'static str) -> [ParamSpec; 4] {
    [
        spec::kd(0.0, f82::KD),
        f0(0.8, f82::F0),
        ParamSpec {
            name: "f82",
            kind: ParamKind::Colour,
            default: Some(1.0),
            range: ValidRange::UNIT,
            doc: "F82 tint: the reflectance at cos_b = 1/7 (about 82°) as a fraction of \
                  Schlick's there (RGB, in [0, 1]; 1 is Schlick's F)",
            slot: f82::F82.first(),
        },
        alpha(f82::ALPHA, alpha_doc),
    ]
}

impl FresnelTerm for F82Tint {
    type Channel<F: Real> = fresnel::F82<F>;
    const POWERS: bool = false;
    const KD: ColourSlot = f82::KD;
    const ALPHA: ScalarSlot = f82::ALPHA;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> [fresnel::F82<F>; 3] {
        let (f0, tint) = (f82::F0.read(p), f82::F82.read(p));
        [0, 1, 2].map(|c| fresnel::F82::new(f0[c], tint[c]))
    }

    #[inline(always)]
    fn eval<F: Real, P: PowUnit>(ch: &fresnel::F82<F>, cos_b: Cosine<F>) -> F {
        fresnel::f82(ch, cos_b)
    }

    /// Per distinct channel: the clamp at 0 makes `F` other than affine in `f0`, `f82`.
    fn lobe_terms(slots: &[f64]) -> Vec<([f64; 3], Slots)> {
        per_channel_terms(slots, f82::KD, &[f82::F0, f82::F82])
    }
}

/// The generalized Schlick Fresnel term ([`fresnel::gen_schlick`]): parameters `kd`, `f0`,
/// `f90`, `exponent`, `alpha`.
pub struct GenSchlick;

/// The generalized Schlick variants' layout.
pub mod gen_schlick {
    use super::super::slots::{ColourSlot, ScalarSlot};
    crate::param_slots! {
        KD: ColourSlot,
        F0: ColourSlot,
        F90: ColourSlot,
        EXPONENT: ScalarSlot,
        ALPHA: ScalarSlot,
    }
}

/// The generalized Schlick variants' parameters, `alpha` documented as `alpha_doc`.
pub const fn gen_schlick_params(alpha_doc: &'static str) -> [ParamSpec; 5] {
    [
        spec::kd(0.0, gen_schlick::KD),
        f0(0.04, gen_schlick::F0),
        ParamSpec {
            name: "f90",
            kind: ParamKind::Colour,
            default: Some(1.0),
            range: ValidRange::UNIT,
            doc: "F90: reflectance at grazing incidence (RGB, in [0, 1])",
            slot: gen_schlick::F90.first(),
        },
        ParamSpec {
            name: "exponent",
            kind: ParamKind::Scalar,
            default: Some(5.0),
            range: ValidRange::POSITIVE,
            doc: "the power of (1 − cos_b) that blends F0 into F90 (5: Schlick's)",
            slot: gen_schlick::EXPONENT.first(),
        },
        alpha(gen_schlick::ALPHA, alpha_doc),
    ]
}

impl FresnelTerm for GenSchlick {
    /// The channel's `f0`, `f90 − f0`, and the exponent.
    type Channel<F: Real> = (fresnel::GenSchlick<F>, F);
    const POWERS: bool = true;
    const KD: ColourSlot = gen_schlick::KD;
    const ALPHA: ScalarSlot = gen_schlick::ALPHA;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> [(fresnel::GenSchlick<F>, F); 3] {
        let (f0, f90) = (gen_schlick::F0.read(p), gen_schlick::F90.read(p));
        let exponent = gen_schlick::EXPONENT.read(p);
        [0, 1, 2].map(|c| (fresnel::GenSchlick::new(f0[c], f90[c]), exponent))
    }

    #[inline(always)]
    fn eval<F: Real, P: PowUnit>(ch: &(fresnel::GenSchlick<F>, F), cos_b: Cosine<F>) -> F {
        fresnel::gen_schlick::<F, P>(&ch.0, cos_b, ch.1)
    }

    /// The weight once for the three channels (they share the one exponent): the same
    /// bits as [`FresnelTerm::eval`] of each, a third of the powers.
    #[inline(always)]
    fn eval_rgb<F: Real, P: PowUnit>(
        ch: &[(fresnel::GenSchlick<F>, F); 3],
        cos_b: Cosine<F>,
    ) -> [F; 3] {
        let w = fresnel::gen_schlick_weight::<F, P>(cos_b, ch[0].1);
        [ch[0].0.blend(w), ch[1].0.blend(w), ch[2].0.blend(w)]
    }

    /// `F = f0·(1 − w) + f90·w` is affine in the two colours: the lobe at `f0 = 1, f90 = 0`
    /// with the colour `f0`, and at `f0 = 0, f90 = 1` with the colour `f90`.
    fn lobe_terms(slots: &[f64]) -> Vec<([f64; 3], Slots)> {
        use gen_schlick::{F0, F90, KD};
        vec![
            (
                F0.read(slots),
                basis(slots, &[(KD, 0.0), (F0, 1.0), (F90, 0.0)]),
            ),
            (
                F90.read(slots),
                basis(slots, &[(KD, 0.0), (F0, 0.0), (F90, 1.0)]),
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::SeriesPow;
    use crate::models::beckmann::Beckmann as BeckmannKernel;
    use crate::models::beckmann_conductor::BeckmannConductor;
    use crate::models::beckmann_f82::BeckmannF82;
    use crate::models::beckmann_gen_schlick::BeckmannGenSchlick;
    use crate::models::ggx::Ggx as GgxKernel;
    use crate::models::ggx_conductor::GgxConductor;
    use crate::models::ggx_f82::GgxF82;
    use crate::models::ggx_gen_schlick::GgxGenSchlick;
    use glam::DVec3;

    /// Direction pairs over the hemisphere, grazing and near-mirror ones included.
    fn directions() -> Vec<Directions<f64>> {
        let mut out = Vec::new();
        let n = DVec3::new(0.1, -0.2, 0.97).normalize();
        let t = n.any_orthonormal_vector();
        let b = n.cross(t);
        let at = |theta: f64, phi: f64| {
            (n * theta.cos() + (t * phi.cos() + b * phi.sin()) * theta.sin()).normalize()
        };
        for (i, ti) in [0.0, 0.3, 1.0, 1.4, 1.5706].iter().enumerate() {
            for to in [0.0, 0.2, 0.8, 1.3, 1.5706] {
                for phi in [0.0, 1.0, 3.0, 3.1] {
                    out.push(Directions {
                        wi: at(*ti, 0.5 * i as f64),
                        wo: at(to, 0.5 * i as f64 + phi),
                        n,
                        t,
                    });
                }
            }
        }
        out
    }

    fn slots_of(pairs: &[(usize, f64)], width: usize) -> Vec<f64> {
        let mut s = vec![0.0; width];
        for &(i, v) in pairs {
            s[i] = v;
        }
        s
    }

    /// A variant is `F(cos_b)` times the base model's value at `ks = 1`, `kd = 0`, bit
    /// for bit (the same lobe function; `F` at the cosine the kernel sees), in both
    /// widths; with `kd`, `kd/π` more.
    fn check_against_base<V: Kernel, B: Kernel, L: MicrofacetLobe>(
        variant_slots: &[f64],
        base_slots: &[f64],
        alpha: f64,
        fresnel: impl Fn(Cosine<f64>, usize) -> f64,
    ) {
        let pv = V::prepare::<f64, [f64]>(variant_slots);
        let pb = B::prepare::<f64, [f64]>(base_slots);
        for d in directions() {
            let got = V::eval::<f64>(&pv, &d);
            let base = B::eval::<f64>(&pb, &d);
            let cos_b = L::eval::<f64, SeriesPow>(&L::prepare(alpha), &d).1;
            for c in 0..3 {
                let want = weighted(fresnel(cos_b, c), base[c]);
                assert_eq!(
                    got[c].to_bits(),
                    want.to_bits(),
                    "{}: {got:?} vs {base:?}",
                    V::SPEC.name
                );
            }
        }
        let v32: Vec<f32> = variant_slots.iter().map(|&x| x as f32).collect();
        let b32: Vec<f32> = base_slots.iter().map(|&x| x as f32).collect();
        let (pv, pb) = (
            V::prepare::<f32, [f32]>(&v32),
            B::prepare::<f32, [f32]>(&b32),
        );
        for d in directions() {
            let d32 = Directions::<f32> {
                wi: d.wi.as_vec3(),
                wo: d.wo.as_vec3(),
                n: d.n.as_vec3(),
                t: d.t.as_vec3(),
            };
            let got = V::eval::<f32>(&pv, &d32);
            let base = B::eval::<f32>(&pb, &d32);
            for c in 0..3 {
                // F is at most 1: the variant never exceeds the base lobe.
                assert!(got[c] <= base[c] * (1.0 + 1e-6), "{got:?} vs {base:?}");
            }
        }
    }

    #[test]
    fn conductor_variants_are_fresnel_times_the_base_lobe() {
        use conductor::{ALPHA, ETA, K};
        let eta = [0.18, 1.5, 1.0 + 1e-9];
        let k = [3.4, 0.0, 0.0];
        for alpha in [0.05, 0.5, 1.3] {
            let mut v = vec![0.0; 10];
            ETA.write(&mut v, eta);
            K.write(&mut v, k);
            ALPHA.write(&mut v, alpha);
            let base = slots_of(&[(3, 1.0), (4, 1.0), (5, 1.0), (6, alpha)], 7);
            let f = |c: Cosine<f64>, ch: usize| {
                fresnel::conductor(&fresnel::Conductor::new(eta[ch], k[ch]), c)
            };
            check_against_base::<GgxConductor, GgxKernel, Ggx>(&v, &base, alpha, f);
            check_against_base::<BeckmannConductor, BeckmannKernel, Beckmann>(&v, &base, alpha, f);
        }
    }

    #[test]
    fn f82_variants_are_fresnel_times_the_base_lobe_and_the_base_at_f_one() {
        use f82::{ALPHA, F0, F82};
        let f0 = [0.9, 0.04, 1.0];
        let tint = [0.6, 0.0, 1.0];
        for alpha in [0.05, 0.5, 1.3] {
            let mut v = vec![0.0; 10];
            F0.write(&mut v, f0);
            F82.write(&mut v, tint);
            ALPHA.write(&mut v, alpha);
            let base = slots_of(&[(3, 1.0), (4, 1.0), (5, 1.0), (6, alpha)], 7);
            let f =
                |c: Cosine<f64>, ch: usize| fresnel::f82(&fresnel::F82::new(f0[ch], tint[ch]), c);
            check_against_base::<GgxF82, GgxKernel, Ggx>(&v, &base, alpha, f);
            check_against_base::<BeckmannF82, BeckmannKernel, Beckmann>(&v, &base, alpha, f);
            // f0 = f82 = 1 (blue above) gives F = 1: the base model at ks = 1, bit for bit.
            let (pv, pb) = (
                GgxF82::prepare::<f64, [f64]>(&v[..]),
                GgxKernel::prepare::<f64, [f64]>(&base[..]),
            );
            let (qv, qb) = (
                BeckmannF82::prepare::<f64, [f64]>(&v[..]),
                BeckmannKernel::prepare::<f64, [f64]>(&base[..]),
            );
            for d in directions() {
                let (a, b) = (
                    GgxF82::eval::<f64>(&pv, &d),
                    GgxKernel::eval::<f64>(&pb, &d),
                );
                assert_eq!(a[2].to_bits(), b[2].to_bits());
                let (a, b) = (
                    BeckmannF82::eval::<f64>(&qv, &d),
                    BeckmannKernel::eval::<f64>(&qb, &d),
                );
                assert_eq!(a[2].to_bits(), b[2].to_bits());
            }
        }
    }

    #[test]
    fn gen_schlick_variants_are_fresnel_times_the_base_lobe_and_the_base_at_f_one() {
        use crate::math::SeriesPow;
        use gen_schlick::{ALPHA, EXPONENT, F0, F90};
        let f0 = [0.04, 0.5, 1.0];
        let f90 = [1.0, 0.2, 1.0];
        let exponent = 3.5;
        for alpha in [0.05, 0.5, 1.3] {
            let mut v = vec![0.0; 11];
            F0.write(&mut v, f0);
            F90.write(&mut v, f90);
            EXPONENT.write(&mut v, exponent);
            ALPHA.write(&mut v, alpha);
            let base = slots_of(&[(3, 1.0), (4, 1.0), (5, 1.0), (6, alpha)], 7);
            let f = |c: Cosine<f64>, ch: usize| {
                fresnel::gen_schlick::<f64, SeriesPow>(
                    &fresnel::GenSchlick::new(f0[ch], f90[ch]),
                    c,
                    exponent,
                )
            };
            check_against_base::<GgxGenSchlick, GgxKernel, Ggx>(&v, &base, alpha, f);
            check_against_base::<BeckmannGenSchlick, BeckmannKernel, Beckmann>(&v, &base, alpha, f);
        }
    }

    #[test]
    fn gen_schlick_lobe_terms_are_its_two_colours() {
        use gen_schlick::{ALPHA, EXPONENT, F0, F90, KD};
        let mut v = vec![0.0; 11];
        KD.write(&mut v, [0.1, 0.2, 0.3]);
        F0.write(&mut v, [0.04, 0.5, 0.9]);
        F90.write(&mut v, [1.0, 0.7, 0.2]);
        EXPONENT.write(&mut v, 2.0);
        ALPHA.write(&mut v, 0.3);
        let terms = GenSchlick::lobe_terms(&v);
        assert_eq!(terms.len(), 2);
        assert_eq!(terms[0].0, [0.04, 0.5, 0.9]);
        assert_eq!(terms[1].0, [1.0, 0.7, 0.2]);
        assert_eq!(
            (F0.read(&terms[0].1[..]), F90.read(&terms[0].1[..])),
            ([1.0; 3], [0.0; 3])
        );
        assert_eq!(
            (F0.read(&terms[1].1[..]), F90.read(&terms[1].1[..])),
            ([0.0; 3], [1.0; 3])
        );
        assert_eq!(KD.read(&terms[1].1[..]), [0.0; 3]);
        assert_eq!(EXPONENT.read(&terms[1].1[..]), 2.0);
    }

    #[test]
    fn channels_with_equal_parameters_share_one_integral() {
        use conductor::{ALPHA, ETA, K, KD};
        let mut v = vec![0.0; 10];
        KD.write(&mut v, [0.1, 0.2, 0.3]);
        ETA.write(&mut v, [0.2, 0.5, 0.2]);
        K.write(&mut v, [3.0, 3.0, 3.0]);
        ALPHA.write(&mut v, 0.3);
        let terms = Conductor::lobe_terms(&v);
        assert_eq!(terms.len(), 2);
        assert_eq!(terms[0].0, [1.0, 0.0, 1.0]);
        assert_eq!(terms[1].0, [0.0, 1.0, 0.0]);
        assert_eq!(KD.read(&terms[1].1[..]), [0.0; 3]);
        assert_eq!(ETA.read(&terms[1].1[..]), [0.5; 3]);
        assert_eq!(K.read(&terms[1].1[..]), [3.0; 3]);
        K.write(&mut v, [3.0, 3.0, 2.0]);
        assert_eq!(Conductor::lobe_terms(&v).len(), 3);
    }
}
