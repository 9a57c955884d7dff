//! `oren_nayar`: the qualitative Oren-Nayar model of rough diffuse reflection.
//!
//! `f = (kd/π)·(A + B·max(0, cos(φi−φo))·sin a·tan b)`, `a = max(θi, θo)`,
//! `b = min(θi, θo)`, `A = 1 − 0.5σ²/(σ²+0.33)`, `B = 0.45σ²/(σ²+0.09)` (the shading
//! assignment). The angular factor is computed without trigonometry, see
//! [`oren_nayar_angular`]; `cos(φi−φo)` is 0 when a tangent-plane projection has zero length.

use super::albedo::{Importance, Integral, Term, basis};
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{self, DiffuseTerm, ModelSpec, SceneUse};
use super::{Directions, Kernel, ParamSource, WideRow};
use crate::math::Vector3;
use crate::math::geometry::{
    WideCosine, above_both, oren_nayar_ab, oren_nayar_angular, weighted, wide_dot,
};
use crate::math::{PowUnit, Real};

/// The Oren-Nayar BRDF kernel.
pub struct OrenNayar;

crate::param_slots! {
    KD: ColourSlot,
    SIGMA: ScalarSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "oren_nayar",
    summary: "rough diffuse reflection (qualitative Oren-Nayar)",
    formula: "f = (kd/π)·(A + B·max(0, cos(φi−φo))·sin a·tan b), a = max(θi,θo), b = min(θi,θo), \
              A = 1 − 0.5σ²/(σ²+0.33), B = 0.45σ²/(σ²+0.09)",
    source: "Oren & Nayar 1994 (qualitative model), as in the shading assignment",
    params: &[spec::kd(0.5, KD), spec::sigma(SIGMA)],
    weights: Some(&["kd"]),
    scene: SceneUse::Brdf(DiffuseTerm::Whole),
    ..ModelSpec::PLAIN
};

/// Derived constants: `kd·A` and `kd·B` times a constant factor (here `1/π`;
/// [`super::oren_nayar_shading`]: 1).
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    pub kd_a: [F; 3],
    pub kd_b: [F; 3],
}

impl<F: Real> Prepared<F> {
    /// Reads `kd` and `sigma` ([`KD`], [`SIGMA`]) and scales `kd·A` and `kd·B` by `scale`.
    #[inline(always)]
    pub fn read<S: ParamSource<F> + ?Sized>(p: &S, scale: F) -> Self {
        let kd = KD.read(p);
        let (a, b) = oren_nayar_ab(SIGMA.read(p));
        Prepared {
            kd_a: kd.map(|c| c * a * scale),
            kd_b: kd.map(|c| c * b * scale),
        }
    }
}

impl Kernel for OrenNayar {
    type Prepared<F: Real> = Prepared<F>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        Prepared::read(p, F::FRAC_1_PI)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let g = oren_nayar_angular::<F>(d.wi, d.wo, d.n, mu_i, mu_o);
        value(pp, mu_i, mu_o, g)
    }

    /// `sin a·tan b·max(0, cos(φi − φo)) = max(0, (n × wi)·(n × wo))/max(mu_i, mu_o)`
    /// depends on the size of the larger cosine (both below the range: 2.9e222 for a
    /// value beyond it, before).
    const WIDE_COSINES: bool = true;

    /// `(n × wi)·(n × wo) = wi·wo − mu_i·mu_o` (unit vectors) from the raw vectors: with
    /// both cosines below the range the normalized vectors hold it as a multiple of
    /// 2^-1074 (1.2e275 for 0.15 before). Each channel's `kd·B` multiplies before
    /// the division by the larger cosine, which is then one scaling (rounded once): `g`
    /// alone can overflow where `kd·B·g` does not. The wide cosines' signs decide the
    /// side of the surface.
    fn eval_wide<F: Real>(pp: &Prepared<F>, _d: &Directions<F>, w: &WideRow) -> [F; 3] {
        let above = w.mu_i.m > 0.0 && w.mu_o.m > 0.0;
        let max = w.mu_i.max_positive(w.mu_o);
        let proj = wide_dot(w.wi, w.wo).over_length(w.wi).over_length(w.wo) + -(w.mu_i * w.mu_o);
        let rgb = [0, 1, 2].map(|c| {
            let g = if above && proj.m > 0.0 {
                WideCosine::of(pp.kd_b[c].to_f64() * proj.m, proj.k).over(max)
            } else {
                0.0
            };
            F::from_f64(g) + pp.kd_a[c]
        });
        above_both(F::from_f64(w.mu_i.m), F::from_f64(w.mu_o.m), rgb)
    }

    /// One term: `kd·∫(A + B·g)/π·mu_o`, integrated with cosine sampling (the constant `A`
    /// part then adds no variance); exactly `kd·A` when `B = 0` (σ = 0).
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        let (a, b) = oren_nayar_ab(SIGMA.read(slots));
        let integral = if b == 0.0 {
            Integral::Exact(a)
        } else {
            Integral::Lobe {
                basis: basis(slots, &[(KD, 1.0)]),
                importance: Importance::Cosine,
            }
        };
        Some(vec![Term {
            colour: KD.read(slots),
            integral,
        }])
    }
}

/// The model's value given `g = sin a·tan b·max(0, cos(φi − φo))` and the cosines that
/// decide the side of the surface.
#[inline(always)]
fn value<F: Real>(pp: &Prepared<F>, mu_i: F, mu_o: F, g: F) -> [F; 3] {
    // g is infinite where the exact value is beyond the float range (both directions
    // within 1e-308 of the horizon); a channel with kd·B = 0 stays kd·A there.
    let rgb = [0, 1, 2].map(|c| weighted(pp.kd_b[c], g) + pp.kd_a[c]);
    above_both(mu_i, mu_o, rgb)
}
