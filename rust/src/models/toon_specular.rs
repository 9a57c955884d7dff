//! `toon_specular`: the shading assignment's two-level specular highlight.
//!
//! `s(l, v) = high` if `v·r >= threshold` else `low` (the assignment's m_S1, m_S0, t_S),
//! 0 when `n·l <= 0`. The comparison is decided from `1 ∓ v·r` near the ends of the
//! range (see [`cosine_at_least`]): at `threshold = 1` only the exact mirror direction is inside.

use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{Family, ModelSpec, ParamKind, ParamSpec, SceneUse, ValidRange};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::{cosine_at_least, mirror};
use crate::math::{PowUnit, Real, Vector3};

/// The toon specular kernel.
pub struct ToonSpecular;

crate::param_slots! {
    THRESHOLD: ScalarSlot,
    HIGH: ColourSlot,
    LOW: ColourSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "toon_specular",
    family: Family::B,
    summary: "two-level specular highlight: high where v·r >= threshold, else low",
    formula: "s = high if v·r >= threshold else low, 0 when n·l <= 0",
    source: "scan-line shading assignment (toon specular: m_S1 = high, m_S0 = low, t_S)",
    params: &[
        ParamSpec {
            name: "threshold",
            kind: ParamKind::Scalar,
            default: None,
            range: ValidRange::SIGNED_UNIT,
            doc: "highlight edge t_S in v·r, in [-1, 1]",
            slot: THRESHOLD.first(),
        },
        ParamSpec {
            name: "high",
            kind: ParamKind::Colour,
            default: Some(1.0),
            range: ValidRange::NON_NEGATIVE,
            doc: "colour inside the highlight (m_S1)",
            slot: HIGH.first(),
        },
        ParamSpec {
            name: "low",
            kind: ParamKind::Colour,
            default: Some(0.0),
            range: ValidRange::NON_NEGATIVE,
            doc: "colour outside the highlight (m_S0)",
            slot: LOW.first(),
        },
    ],
    reciprocal: false,
    weights: Some(&["high", "low"]),
    scene: SceneUse::Specular,
    ..ModelSpec::PLAIN
};

/// Threshold, high and low colours.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    threshold: F,
    high: [F; 3],
    low: [F; 3],
}

impl Kernel for ToonSpecular {
    type Prepared<F: Real> = Prepared<F>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        Prepared {
            threshold: THRESHOLD.read(p),
            high: HIGH.read(p),
            low: LOW.read(p),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let r = mirror::<F>(d.wi, d.n, mu_i);
        let inside = cosine_at_least::<F>(d.wo, r, pp.threshold);
        let lit = mu_i > F::ZERO;
        [0, 1, 2].map(|c| {
            let s = if inside { pp.high[c] } else { pp.low[c] };
            if lit { s } else { F::ZERO }
        })
    }
}
