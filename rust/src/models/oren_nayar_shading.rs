//! `oren_nayar_shading`: the shading assignment's Oren-Nayar term, cosine included.
//!
//! `s(l, v) = kd·clamp(n·l, 0, 1)·(A + B·G·sin a·tan b)` with A, B, a, b and
//! `G = max(0, cos(φi−φo))` as in `oren_nayar`; `= π·mu_i·oren_nayar` for mu_i, mu_o > 0.
//! The viewer may be below the surface; the light below gives 0.

// The layout and the derived constants of `oren_nayar` (`kd·A`, `kd·B`), unscaled here.
pub use super::oren_nayar::{KD, Prepared, SIGMA, SLOTS};
use super::spec::{self, Family, ModelSpec, SceneUse};
use super::{Directions, Kernel, ParamSource, WideRow};
use crate::math::{PowUnit, Real, Vector3, clamp, max};

/// The Oren-Nayar shading kernel.
pub struct OrenNayarShading;

pub static SPEC: ModelSpec = ModelSpec {
    name: "oren_nayar_shading",
    family: Family::B,
    summary: "Oren-Nayar rough diffuse shading term (includes the light cosine)",
    formula: "s = kd·clamp(n·l, 0, 1)·(A + B·max(0, cos(φi−φo))·sin a·tan b)",
    source: "scan-line shading assignment (Oren-Nayar term)",
    params: &[spec::kd(0.5, KD), spec::sigma(SIGMA)],
    reciprocal: false,
    weights: Some(&["kd"]),
    scene: SceneUse::Diffuse,
    ..ModelSpec::PLAIN
};

impl Kernel for OrenNayarShading {
    type Prepared<F: Real> = Prepared<F>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        Prepared::read(p, F::ONE)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let cos_l = clamp(mu_i, F::ZERO, F::ONE);
        // cos_l·sin a·tan b·G = max(0, (n × l)·(n × v))·cos_l/max(mu_i, mu_o): the ratio
        // is at most 1, so the product stays finite where tan b alone overflows (light and
        // viewer within 1e-308 of the horizon).
        let cos_b = max(mu_i, mu_o);
        let ratio = cos_l / if cos_b > F::ZERO { cos_b } else { F::ONE };
        let g = max(d.n.cross(d.wi).dot(d.n.cross(d.wo)), F::ZERO) * ratio;
        let g = if mu_i > F::ZERO { g } else { F::ZERO };
        [0, 1, 2].map(|c| pp.kd_b[c] * g + pp.kd_a[c] * cos_l)
    }

    /// `cos_l/max(mu_i, mu_o)` is a ratio of cosines that may both be below the range
    /// (then 1 for any ratio, before).
    const WIDE_COSINES: bool = true;

    /// The ratio and `cos_l` from the wide cosines, each rounded once.
    fn eval_wide<F: Real>(pp: &Prepared<F>, d: &Directions<F>, w: &WideRow) -> [F; 3] {
        let (mu_i, mu_o) = (w.mu_i, w.mu_o);
        let (cos_l, g) = if mu_i.m > 0.0 {
            let cos_b = mu_i.max_positive(mu_o);
            let ratio = mu_i.over(cos_b);
            let proj = d.n.cross(d.wi).dot(d.n.cross(d.wo)).to_f64().max(0.0);
            (mu_i.value().min(1.0), proj * ratio)
        } else {
            (0.0, 0.0)
        };
        let (cos_l, g) = (F::from_f64(cos_l), F::from_f64(g));
        [0, 1, 2].map(|c| pp.kd_b[c] * g + pp.kd_a[c] * cos_l)
    }
}
