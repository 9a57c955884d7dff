//! `blinn_phong_fresnel`: normalized Blinn-Phong with Schlick's Fresnel term (RTR eq. 7.49).
//!
//! `f = kd/π + (p+8)/(8π)·F·cos_th^p`, `F = ks + (1−ks)(1−cos_b)^5` per channel, where
//! `ks` is the normal-incidence reflectance F0 and `cos_b = wi·h`. `(1 − cos_b)` comes
//! from a vector difference, so Schlick's weight has no cancellation near normal incidence.

use super::albedo::{Importance, Integral, Term, basis, diffuse_and_schlick_lobe};
use super::lobes::{DiffuseSpecular, KD, KS, P};
use super::spec::{
    self, DfgAxis, DiffuseTerm, ModelSpec, ParamKind, ParamSpec, SceneUse,
    ValidRange,
};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::SLOTS;
use super::{Directions, Kernel, ParamSource, PowerStage};
use crate::math::geometry::{clamped_cosine, half_vector, schlick_weight};
use crate::math::{PowUnit, Real, Vector3};

/// The Blinn-Phong-with-Fresnel kernel.
pub struct BlinnPhongFresnel;

pub static SPEC: ModelSpec = ModelSpec {
    name: "blinn_phong_fresnel",
    summary: "normalized Blinn-Phong lobe weighted by Schlick's Fresnel term, plus Lambert",
    formula: "f = kd/π + (p+8)/(8π)·F·cos_th^p, F = ks + (1−ks)(1−cos_b)^5 (ks is F0)",
    source: "RTR 3rd ed. eq. 7.49",
    params: &[
        spec::kd(0.0, KD),
        ParamSpec {
            name: "ks",
            kind: ParamKind::Colour,
            default: Some(0.04),
            range: ValidRange::UNIT,
            doc: "F0: specular reflectance at normal incidence (RGB, in [0, 1])",
            slot: KS.first(),
        },
        spec::exponent(P),
    ],
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    dfg: Some(DfgAxis {
        param: "p",
        axis: "log:1:10000:32",
    }),
    ..ModelSpec::PLAIN
};

impl Kernel for BlinnPhongFresnel {
    /// `kd/π`, `F0` (as given) and `p`, with the lobe normalization `(p+8)/(8π)`.
    type Prepared<F: Real> = (DiffuseSpecular<F>, F);
    const POWERS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> (DiffuseSpecular<F>, F) {
        let lobe = DiffuseSpecular::read(p, F::FRAC_1_PI, |_| F::ONE);
        let norm = (lobe.p * F::from_f64(0.125) + F::ONE) * F::FRAC_1_PI;
        (lobe, norm)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &(DiffuseSpecular<F>, F), d: &Directions<F>) -> [F; 3] {
        let stage = Self::power_stage(pp, d);
        let power = P::pow_unit(stage.base.cos, stage.base.one_minus, stage.p);
        Self::finish_power(pp, &stage, power)
    }

    const SPLIT_POWER: bool = true;

    /// `cos_th` and `p`; keeps Schlick's weight, whether `h` is defined and whether both
    /// directions are above the surface (1 or 0).
    #[inline(always)]
    fn power_stage<F: Real>(pp: &(DiffuseSpecular<F>, F), d: &Directions<F>) -> PowerStage<F> {
        let (lobe, _) = pp;
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let hv = half_vector::<F>(d.wi, d.wo);
        let cos_th = clamped_cosine::<F>(d.n, hv.h);
        let w = schlick_weight(hv.cos_b);
        let flag = |x: bool| if x { F::ONE } else { F::ZERO };
        let above = mu_i > F::ZERO && mu_o > F::ZERO;
        PowerStage {
            base: cos_th,
            p: lobe.p,
            keep: [w, flag(hv.defined), flag(above), F::ZERO],
        }
    }

    #[inline(always)]
    fn finish_power<F: Real>(
        pp: &(DiffuseSpecular<F>, F),
        stage: &PowerStage<F>,
        power: F,
    ) -> [F; 3] {
        let (lobe, norm) = pp;
        let [w, defined, above, _] = stage.keep;
        let spec = *norm * F::flush_subnormal(power);
        let spec = if defined != F::ZERO { spec } else { F::ZERO };
        let rgb = [0, 1, 2].map(|c| {
            let fresnel = lobe.ks[c] + (F::ONE - lobe.ks[c]) * w;
            fresnel * spec + lobe.kd[c]
        });
        // Zero unless both directions are above the surface (family A).
        let above = above != F::ZERO;
        rgb.map(|c| if above { c } else { F::ZERO })
    }

    /// As [`Kernel::sampling_terms`]; where the lobe is sharp or `wi` near the normal,
    /// `I(F0 = 1)` and `I(F0 = 0)` (Schlick's excess alone) each in strata with their
    /// bulks exact ([`super::strata`]), so that the error bar holds.
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        let mut terms = Self::sampling_terms(slots, mu)?;
        let p = P.read(slots);
        let excess = basis(slots, &[(KD, 0.0), (KS, 0.0)]);
        let colour_excess = KS.read(slots).map(|c| 1.0 - c);
        let excess = super::strata::blinn_phong_fresnel_terms(colour_excess, excess, mu, p);
        let lobe = basis(slots, &[(KD, 0.0), (KS, 1.0)]);
        let scale = (p + 8.0) / (8.0 * std::f64::consts::PI);
        let f0 = super::strata::blinn_terms(KS.read(slots), lobe, mu, p, scale);
        let [diffuse, whole_f0, whole_excess]: [Term; 3] = terms.try_into().ok()?;
        terms = vec![diffuse];
        terms.extend(f0.unwrap_or_else(|| vec![whole_f0]));
        terms.extend(excess.unwrap_or_else(|| vec![whole_excess]));
        Some(terms)
    }

    /// `kd·1 + F0·I(F0 = 1) + (1 − F0)·I(F0 = 0)`: F is affine in F0, so two scalar
    /// integrals (the lobe, and the lobe times Schlick's weight) give every RGB F0.
    fn sampling_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        let f0 = KS.read(slots);
        let importance = Importance::BlinnHalf { p: P.read(slots) };
        let diffuse = Term {
            colour: KD.read(slots),
            integral: Integral::Exact(1.0),
        };
        Some(diffuse_and_schlick_lobe(diffuse, f0, |f0| Integral::Lobe {
            basis: basis(slots, &[(KD, 0.0), (KS, f0)]),
            importance,
        }))
    }
}
