//! Pieces the Phong and Blinn-Phong families share: the lobe cosines of docs/models.md, the
//! parameter layout "diffuse colour + specular colour + exponent" and its prepared triple,
//! and the [`Kernel`] of the six models that are just that ([`PowerLobeModel`]).

use super::albedo::{StratumLobe, Term, diffuse_and_power_lobe, diffuse_and_whole_power_lobe};
use super::spec::{self, DiffuseTerm, ModelSpec, SceneUse};
use super::{Directions, Kernel, ParamSource, PowerStage, Registered};
use crate::math::geometry::{Cosine, above_both, clamped_cosine, half_vector, mirror, weighted};
use crate::math::{PowUnit, Real, Vector3};
use crate::models::slots::{ColourSlot, ScalarSlot};

// The power-lobe models' parameters: `kd`, `ks` and the exponent `p`.
crate::param_slots! {
    KD: ColourSlot,
    KS: ColourSlot,
    P: ScalarSlot,
}

/// The spec fields the six models of the Phong and Blinn-Phong families share: family A,
/// the parameters `kd` (default 0), `ks` (default 1) and `p`, both colours weights, no
/// tangent, no split-sum table, no energy table, no exact normalization, reciprocal
/// unless the model says otherwise. A model's spec names its own fields and takes these
/// with `..POWER_LOBE_SPEC`; the name, texts and scene use here are placeholders that
/// every model sets.
pub const POWER_LOBE_SPEC: ModelSpec = ModelSpec {
    params: &[spec::kd(0.0, KD), spec::ks(1.0, KS), spec::exponent(P)],
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    ..ModelSpec::PLAIN
};

/// A model of the Phong and Blinn-Phong families, `f = kd·c + ks·A·lobe` in the layout
/// above, above both directions and 0 elsewhere: the model states its spec, its constant
/// factors and its lobe, and the [`Kernel`] follows (the albedo and sampling terms from
/// [`diffuse_and_power_lobe`] and [`diffuse_and_whole_power_lobe`]).
///
/// The model's spec ([`Registered`]) has the scene use `Brdf(Lambert(c))`, `c` the
/// diffuse term's albedo for a unit `kd` (π where `kd` enters without `1/π`).
pub trait PowerLobeModel: Registered + 'static {
    /// Which cosine the lobe raises to `p`: about the mirror direction or of the half
    /// vector (also how the integrator splits the lobe).
    const LOBE: StratumLobe;
    /// Reads the parameters with the model's constant factors ([`DiffuseSpecular::read`]);
    /// by default none (`kd` and `ks` as given, the Summary's non-normalized models).
    #[inline(always)]
    fn read_params<F: Real, S: ParamSource<F> + ?Sized>(p: &S) -> DiffuseSpecular<F> {
        DiffuseSpecular::read(p, F::ONE, |_| F::ONE)
    }
    /// Returns the lobe for a unit `ks` at `d`, given `mu_i = n·wi`; 0 where it is
    /// undefined (the half vector of opposite directions). By default the plain power
    /// [`plain_power_lobe`] of [`PowerLobeModel::lobe_base`]: a model whose lobe is not
    /// that ([`PowerLobeModel::PLAIN_POWER`] false) writes its own.
    #[inline(always)]
    fn lobe<F: Real, P: PowUnit>(pp: &DiffuseSpecular<F>, d: &Directions<F>, mu_i: F) -> F {
        plain_power_lobe::<F, P>(Self::lobe_base(pp, d, mu_i), pp.p)
    }
    /// Whether the lobe is the plain power `base^p` of [`PowerLobeModel::lobe_base`]'s
    /// cosine (flushed, [`Cosine::powf`]), 0 where that is undefined: then the model's
    /// kernel evaluates a block in three passes ([`Kernel::SPLIT_POWER`]), and keeps
    /// the default [`PowerLobeModel::lobe`].
    const PLAIN_POWER: bool = false;
    /// For a [`PowerLobeModel::PLAIN_POWER`] lobe: the cosine raised to `p` and whether
    /// the lobe is defined. A placeholder for the other lobes, which write their own
    /// [`PowerLobeModel::lobe`].
    #[inline(always)]
    fn lobe_base<F: Real>(
        _pp: &DiffuseSpecular<F>,
        _d: &Directions<F>,
        _mu_i: F,
    ) -> (Cosine<F>, bool) {
        (
            Cosine {
                cos: F::ZERO,
                one_minus: F::ONE,
            },
            false,
        )
    }
    /// Returns the lobe's factor `A` (of `A·cos^p`) in the albedo at incidence `mu`; by
    /// default 1.
    fn lobe_scale(_slots: &[f64], _mu: f64) -> f64 {
        1.0
    }
}

/// The albedo of a power-lobe model's diffuse term for a unit `kd`: its scene spec's
/// Lambert factor.
fn diffuse_albedo(spec: &ModelSpec) -> f64 {
    match spec.scene {
        SceneUse::Brdf(DiffuseTerm::Lambert(factor)) => factor,
        _ => unreachable!(
            "{}: a power-lobe model's diffuse term is Lambert's",
            spec.name
        ),
    }
}

impl<K: PowerLobeModel> Kernel for K {
    type Prepared<F: Real> = DiffuseSpecular<F>;
    const POWERS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, S: ParamSource<F> + ?Sized>(p: &S) -> DiffuseSpecular<F> {
        K::read_params(p)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &DiffuseSpecular<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        above_both(mu_i, mu_o, pp.combine(K::lobe::<F, P>(pp, d, mu_i)))
    }

    const SPLIT_POWER: bool = K::PLAIN_POWER;

    /// The lobe's cosine and `p`; keeps whether the lobe is defined and whether both
    /// directions are above the surface (1 or 0).
    #[inline(always)]
    fn power_stage<F: Real>(pp: &DiffuseSpecular<F>, d: &Directions<F>) -> PowerStage<F> {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let (base, defined) = K::lobe_base(pp, d, mu_i);
        let flag = |x: bool| if x { F::ONE } else { F::ZERO };
        let above = mu_i > F::ZERO && mu_o > F::ZERO;
        PowerStage {
            base,
            p: pp.p,
            keep: [flag(defined), flag(above), F::ZERO, F::ZERO],
        }
    }

    #[inline(always)]
    fn finish_power<F: Real>(pp: &DiffuseSpecular<F>, stage: &PowerStage<F>, power: F) -> [F; 3] {
        let lobe = F::flush_subnormal(power);
        let lobe = if stage.keep[0] != F::ZERO {
            lobe
        } else {
            F::ZERO
        };
        let rgb = pp.combine(lobe);
        let above = stage.keep[1] != F::ZERO;
        rgb.map(|c| if above { c } else { F::ZERO })
    }

    /// The diffuse term and the lobe; where the lobe is sharp or `wi` near the normal,
    /// the lobe in strata with its bulk exact ([`super::strata::blinn_terms`],
    /// [`super::strata::phong_terms`]).
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_power_lobe(
            slots,
            diffuse_albedo(K::SPEC),
            K::lobe_scale(slots, mu),
            mu,
            K::LOBE,
        ))
    }

    fn sampling_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_whole_power_lobe(
            slots,
            diffuse_albedo(K::SPEC),
            K::LOBE,
        ))
    }
}

/// Prepared constants of a diffuse + cosine-power lobe: `kd` and `ks` already carry the
/// model's constant factors (1/π, (p+2)/(2π), ...).
#[derive(Clone, Copy)]
pub struct DiffuseSpecular<F> {
    pub kd: [F; 3],
    pub ks: [F; 3],
    pub p: F,
}

impl<F: Real> DiffuseSpecular<F> {
    /// Reads `kd`, `ks` and `p` ([`KD`], [`KS`], [`P`]), and scales them.
    #[inline(always)]
    pub fn read<S: ParamSource<F> + ?Sized>(p: &S, kd_scale: F, ks_scale: impl Fn(F) -> F) -> Self {
        let exponent = P.read(p);
        let s = ks_scale(exponent);
        DiffuseSpecular {
            kd: KD.read(p).map(|c| c * kd_scale),
            ks: KS.read(p).map(|c| c * s),
            p: exponent,
        }
    }

    /// Returns `kd + ks·lobe` per channel; a channel with `ks = 0` is `kd` whatever the
    /// lobe (an infinite `cos^p / mu_i` must not make `0·inf = NaN` there).
    #[inline(always)]
    pub fn combine(&self, lobe: F) -> [F; 3] {
        [0, 1, 2].map(|c| weighted(self.ks[c], lobe) + self.kd[c])
    }
}

/// The lobe of a [`PowerLobeModel::PLAIN_POWER`] model: `base^p` ([`Cosine::powf`]) where
/// `defined`, else 0.
#[inline(always)]
pub fn plain_power_lobe<F: Real, P: PowUnit>((base, defined): (Cosine<F>, bool), p: F) -> F {
    let lobe = base.powf::<P>(p);
    if defined { lobe } else { F::ZERO }
}

/// Returns `cos_ar = max(0, r·wo)` with `r` the mirror of `wi` about `n`, given
/// `mu_i = n·wi`.
#[inline(always)]
pub fn mirror_cosine<F: Real>(d: &Directions<F>, mu_i: F) -> Cosine<F> {
    let r = mirror::<F>(d.wi, d.n, mu_i);
    clamped_cosine::<F>(r, d.wo)
}

/// Returns `cos_th = max(0, n·h)` and whether `h` is defined (`wi + wo ≠ 0`).
#[inline(always)]
pub fn half_cosine<F: Real>(d: &Directions<F>) -> (Cosine<F>, bool) {
    let hv = half_vector::<F>(d.wi, d.wo);
    (clamped_cosine::<F>(d.n, hv.h), hv.defined)
}

/// `cos_th^p / div` (`div > 0`: `mu_i` for the Blinn-Phong lobe, 1 for a plain power)
/// and whether the half vector is defined: `half_cosine(d).0.powf_over(p, div)`, except
/// where `n·h` lies below the normal range. That happens in float64 when both directions
/// are within ~1e-308 of the horizon on opposite sides: `n·h = (mu_i + mu_o)/|wi + wo|` is
/// a subnormal with as few as 10 significant bits, which `p < 1` or the division by
/// `mu_i` brings back to the normal range. There `n·h` is formed from `wi + wo` scaled by
/// 2^600 (exact) and the power takes the exponent back inside its logarithm, so the
/// result keeps full precision (docs/numerics.md). Elsewhere bitwise the plain power.
#[inline(always)]
pub fn half_cosine_pow_over<F: Real, P: PowUnit>(d: &Directions<F>, p: F, div: F) -> (F, bool) {
    let hv = half_vector::<F>(d.wi, d.wo);
    let cos = clamped_cosine::<F>(d.n, hv.h);
    if !F::EXTENDED_COSINES {
        return (cos.powf_over::<P>(p, div), hv.defined);
    }
    // 2^600, and |wi + wo| = 2·cos_b (at most 2: its clamp at 1 never bites here).
    let up = F::from_f64(4.149_515_568_880_993e180);
    let scaled = d.n.dot((d.wi + d.wo) * up) / (F::TWO * hv.cos_b.cos);
    // The scaled cosine must be that of a tiny n·h (at most 2^-400, the power's domain):
    // where the two disagree, cancellation in n·h decides, as in the plain power.
    let tiny = cos.cos < F::from_f64(f64::MIN_POSITIVE)
        && scaled > F::ZERO
        && scaled <= F::from_f64(3.872_591_914_849_318_3e-121);
    let lobe = P::pow_unit_over_scaled(
        if tiny { scaled } else { cos.cos },
        if tiny { F::ONE } else { cos.one_minus },
        p,
        if tiny { F::from_f64(600.0) } else { F::ZERO },
        div,
    );
    (F::flush_subnormal(lobe), hv.defined)
}
