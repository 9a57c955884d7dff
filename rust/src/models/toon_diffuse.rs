//! `toon_diffuse`: banded (cel) diffuse shading from the shading assignment.
//!
//! With ascending `thresholds` t₁..t_k and `colors` c₀..c_k, the term is c_j where j is
//! how many thresholds are ≤ n·l (the signed cosine, so negative thresholds band the
//! unlit side). The assignment's two-colour case is `thresholds=[t_D]`,
//! `colors=[m_D2, m_D1]`; its listing mixes up `C` and `Cd`: this follows the formula.

use super::slots::{ColourListSlot, ScalarListSlot};
use super::spec::{Family, ModelSpec, ParamKind, ParamSpec, SceneUse, ValidRange};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::cosine_at_least;
use crate::math::{PowUnit, Real};

/// Most thresholds a toon ramp may have (so at most `MAX_THRESHOLDS + 1` bands).
pub const MAX_THRESHOLDS: usize = 7;

/// The toon diffuse kernel.
pub struct ToonDiffuse;

crate::param_slots! {
    THRESHOLDS: ScalarListSlot<MAX_THRESHOLDS>,
    COLORS: ColourListSlot<{ MAX_THRESHOLDS + 1 }>,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "toon_diffuse",
    family: Family::B,
    summary: "banded diffuse shading: colour c_j, j = number of thresholds <= n·l",
    formula: "s = colors[j], j = #{k : thresholds[k] <= n·l}",
    source: "scan-line shading assignment (toon diffuse, two or three bands)",
    params: &[
        ParamSpec {
            name: "thresholds",
            kind: ParamKind::ScalarList {
                max_len: MAX_THRESHOLDS,
                ascending: true,
            },
            default: None,
            range: ValidRange::SIGNED_UNIT,
            doc: "ascending band edges in n·l, each in [-1, 1] (1 to 7 of them)",
            slot: THRESHOLDS.first(),
        },
        ParamSpec {
            name: "colors",
            kind: ParamKind::ColourList {
                max_len: MAX_THRESHOLDS + 1,
                one_more_than: "thresholds",
            },
            default: None,
            range: ValidRange::NON_NEGATIVE,
            doc: "band colours c_0..c_k, darkest band first (one more than thresholds)",
            slot: COLORS.first(),
        },
    ],
    reciprocal: false,
    weights: Some(&["colors"]),
    scene: SceneUse::Diffuse,
    ..ModelSpec::PLAIN
};

/// Thresholds (unused ones are +inf) and band colours.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    thresholds: [F; MAX_THRESHOLDS],
    colors: [[F; 3]; MAX_THRESHOLDS + 1],
}

impl Kernel for ToonDiffuse {
    type Prepared<F: Real> = Prepared<F>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        Prepared {
            thresholds: THRESHOLDS.read(p),
            colors: COLORS.read(p),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        // Thresholds ascend, so the last one passed names the band. Each comparison is
        // decided where it is accurate (`n·l` rounds to ±1 near the ends).
        let mut rgb = pp.colors[0];
        for k in 0..MAX_THRESHOLDS {
            let passed = cosine_at_least::<F>(d.n, d.wi, pp.thresholds[k]);
            rgb = [0, 1, 2].map(|c| if passed { pp.colors[k + 1][c] } else { rgb[c] });
        }
        rgb
    }
}
