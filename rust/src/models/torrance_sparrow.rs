//! `torrance_sparrow`: the Torrance-Sparrow microfacet BRDF with a cosine-power NDF
//! (BRDF Summary eqs. 10–14; RTR eq. 7.51 is the same function).
//!
//! `f = kd/π + ks·D·F·G / (4·mu_i·mu_o)` with `D = (p+2)/(2π)·cos_th^p`,
//! `F = R0 + (1−R0)(1−cos_b)^5`, `R0 = ((eta−1)/(eta+1))²` (grey), and
//! `G = min(1, 2·cos_th·mu_o/cos_b, 2·cos_th·mu_i/cos_b)`.
//!
//! `G/(4 mu_i mu_o)` is evaluated as `min(1/(4 mu_i mu_o), cos_th/(2 cos_b mu_i),
//! cos_th/(2 cos_b mu_o))`: the same value, but finite at grazing angles where
//! `4 mu_i mu_o` underflows (no 0·∞).

use super::albedo::{Importance, Term, basis, diffuse_and_lobe};
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{
    self, DiffuseTerm, ExactFactor, ExactNormalization, ModelSpec, ParamKind, ParamSpec,
    SceneUse, ValidRange,
};
use super::{Directions, Kernel, ParamSource, PowerStage};
use crate::math::geometry::{clamped_cosine, half_vector, schlick_weight, weighted};
use crate::math::{PowUnit, Real, Vector3};

/// The Torrance-Sparrow kernel.
pub struct TorranceSparrow;

crate::param_slots! {
    KD: ColourSlot,
    KS: ColourSlot,
    P: ScalarSlot,
    ETA: ScalarSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "torrance_sparrow",
    summary: "microfacet BRDF: cosine-power NDF, Schlick Fresnel from eta, V-cavity shadowing",
    formula: "f = kd/π + ks·D·F·G/(4·mu_i·mu_o), D = (p+2)/(2π)·cos_th^p, \
              F = R0 + (1−R0)(1−cos_b)^5, R0 = ((eta−1)/(eta+1))², \
              G = min(1, 2·cos_th·mu_o/cos_b, 2·cos_th·mu_i/cos_b)",
    source: "BRDF Summary eqs. 10–14; RTR 3rd ed. eq. 7.51",
    params: &[
        spec::kd(0.0, KD),
        spec::ks(1.0, KS),
        spec::exponent(P),
        ParamSpec {
            name: "eta",
            kind: ParamKind::Scalar,
            default: Some(1.5),
            range: ValidRange::POSITIVE,
            doc: "relative index of refraction (scalar: the Fresnel term is grey)",
            slot: ETA.first(),
        },
    ],
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    exact: Some(ExactNormalization {
        factor: ExactFactor::One,
        params: &["p"],
        scales: "ks",
    }),
    ..ModelSpec::PLAIN
};

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    kd_over_pi: [F; 3],
    /// `ks·(p+2)/(2π)`.
    ks_norm: [F; 3],
    p: F,
    r0: F,
}

impl Kernel for TorranceSparrow {
    type Prepared<F: Real> = Prepared<F>;
    const POWERS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let exponent = P.read(p);
        let eta = ETA.read(p);
        let norm = (exponent + F::TWO) * F::HALF * F::FRAC_1_PI;
        let r = (eta - F::ONE) / (eta + F::ONE);
        Prepared {
            kd_over_pi: KD.read(p).map(|c| c * F::FRAC_1_PI),
            ks_norm: KS.read(p).map(|c| c * norm),
            p: exponent,
            r0: r * r,
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let stage = Self::power_stage(pp, d);
        let power = P::pow_unit(stage.base.cos, stage.base.one_minus, stage.p);
        Self::finish_power(pp, &stage, power)
    }

    const SPLIT_POWER: bool = true;

    /// `cos_th` and `p`; keeps the Fresnel factor, `G/(4 mu_i mu_o)`, whether `h` is
    /// defined and whether both directions are above the surface (1 or 0).
    #[inline(always)]
    fn power_stage<F: Real>(pp: &Prepared<F>, d: &Directions<F>) -> PowerStage<F> {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let hv = half_vector::<F>(d.wi, d.wo);
        let cos_th = clamped_cosine::<F>(d.n, hv.h);
        let cos_b = hv.cos_b;
        let fresnel = pp.r0 + (F::ONE - pp.r0) * schlick_weight(cos_b);
        // G/(4 mu_i mu_o) = min(1/a, c/b) with a = 4 mu_i mu_o, c = cos_th and
        // b = 2 cos_b max(mu_i, mu_o) (the two shadowing terms share the larger cosine).
        // For a, b > 0, 1/a < c/b exactly when b < c·a: one division of the chosen pair
        // instead of three (the comparison's rounding only matters where the two are
        // within an ulp). a = 0 (underflow at grazing angles) picks c/b, as the min of
        // an infinite 1/a did; c = 0 gives 0, as before, even where b underflows.
        let mu_max = if mu_i > mu_o { mu_i } else { mu_o };
        let a = F::from_f64(4.0) * mu_i * mu_o;
        let b = F::TWO * cos_b.cos * mu_max;
        let c = cos_th.cos;
        let first = b < c * a;
        let quotient = if first { F::ONE } else { c } / if first { a } else { b };
        let g_over = if c == F::ZERO { F::ZERO } else { quotient };
        let flag = |x: bool| if x { F::ONE } else { F::ZERO };
        let above = mu_i > F::ZERO && mu_o > F::ZERO;
        PowerStage {
            base: cos_th,
            p: pp.p,
            keep: [fresnel, g_over, flag(hv.defined), flag(above)],
        }
    }

    #[inline(always)]
    fn finish_power<F: Real>(pp: &Prepared<F>, stage: &PowerStage<F>, power: F) -> [F; 3] {
        let [fresnel, g_over, defined, above] = stage.keep;
        let d_lobe = F::flush_subnormal(power);
        // D·F is 0 where cos_th^p underflows; G/(4 mu_i mu_o) is infinite where the
        // exact value is (grazing): never multiply the two into NaN.
        let spec = weighted(d_lobe * fresnel, g_over);
        let spec = if defined != F::ZERO { spec } else { F::ZERO };
        let rgb = [0, 1, 2].map(|c| weighted(pp.ks_norm[c], spec) + pp.kd_over_pi[c]);
        // Zero unless both directions are above the surface (family A).
        let above = above != F::ZERO;
        rgb.map(|c| if above { c } else { F::ZERO })
    }

    /// The diffuse term and the specular lobe; where the lobe is sharp and `wi` near the
    /// normal, the lobe in two strata with a control variate for Schlick's excess
    /// ([`super::strata`]), so that its error bar holds.
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        let mut terms = Self::sampling_terms(slots, mu)?;
        let eta = ETA.read(slots);
        let r = (eta - 1.0) / (eta + 1.0);
        let lobe = basis(slots, &[(KD, 0.0), (KS, 1.0)]);
        if let Some(strata) =
            super::strata::torrance_sparrow_terms(KS.read(slots), lobe, mu, P.read(slots), r * r)
        {
            terms.truncate(1);
            terms.extend(strata);
        }
        Some(terms)
    }

    fn sampling_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(diffuse_and_lobe(
            slots,
            KD,
            KS,
            1.0,
            Importance::BlinnHalf { p: P.read(slots) },
        ))
    }
}
