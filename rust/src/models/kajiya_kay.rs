//! `kajiya_kay`: the Kajiya-Kay hair/fibre shading term (RTR eq. 7.50).
//!
//! `s(l, v) = kd·sin_l + ks·max(0, sin_l·sin_v − (l·t)(v·t))^p`,
//! `sin_l = sqrt(max(0, 1−(l·t)²))`, `sin_v` likewise, `t` the unit fibre tangent
//! (normalized, not projected); 0 when `n·l <= 0`. The sign `−(l·t)(v·t)` is right for
//! directions pointing away from the surface.
//!
//! Sines are `|l × t|` (accurate near 0; the cross product is scaled before it is
//! squared, so a fibre within 1e-200 of the light still has its sine), and with
//! `A = (−l·t, sin_l)`, `B = (v·t, sin_v)` the lobe cosine is `A·B`, so
//! `1 − A·B = |A − B|²/2 = (a² + b²)/2` stays accurate near the highlight peak for large
//! `p`: `a = l·t + v·t = (l + v)·t` (the sum formed before the dot product, exact where
//! `l ≈ −v`) and `b = sin_l − sin_v = a·((v − l)·t)/(sin_l + sin_v)` (from
//! `sin_l² − sin_v² = (v·t)² − (l·t)²`; the difference of two rounded sines would cancel).

use super::spec::{self, Family, ModelSpec, SceneUse, TangentUse};
// The power-lobe models' layout (`kd`, `ks`, `p`).
pub use super::lobes::SLOTS;
use super::lobes::{DiffuseSpecular, KD, KS, P};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::Cosine;
use crate::math::{PowUnit, Real, Vector3, min};

/// The Kajiya-Kay kernel.
pub struct KajiyaKay;

pub static SPEC: ModelSpec = ModelSpec {
    name: "kajiya_kay",
    family: Family::B,
    summary: "Kajiya-Kay fibre shading: diffuse sin_l plus a cosine-power cone highlight",
    formula: "s = kd·sin_l + ks·max(0, sin_l·sin_v − (l·t)(v·t))^p, 0 when n·l <= 0",
    source: "Kajiya & Kay 1989; RTR 3rd ed. eq. 7.50",
    params: &[spec::kd(0.5, KD), spec::ks(0.5, KS), spec::exponent(P)],
    tangent: TangentUse::Required,
    reciprocal: false,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Both,
    ..ModelSpec::PLAIN
};

impl Kernel for KajiyaKay {
    type Prepared<F: Real> = DiffuseSpecular<F>;
    const POWERS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Self::Prepared<F> {
        DiffuseSpecular::read(p, F::ONE, |_| F::ONE)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Self::Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let cos_l = d.wi.dot(d.t);
        let cos_v = d.wo.dot(d.t);
        let sin_l = F::length(d.wi.cross(d.t));
        let sin_v = F::length(d.wo.cross(d.t));
        let x = sin_l * sin_v - cos_l * cos_v;
        // a = l·t + v·t; where l·t ≈ ±1 and v·t ≈ ∓1 the two cosines cancel and a is the
        // difference of their complements, 1 − w·t = |w − t|²/2 and 1 + w·t = |w + t|²/2
        // (accurate however close w is to ±t); elsewhere the sum of the vectors first.
        // f64: of the exact unit vectors l·(1 − e_l/2), v·(1 − e_v/2) (`e = |w|² − 1`,
        // [`Real::length_error`]): where l ≈ −v the rounded vectors' length errors are
        // otherwise all of a's last digits (39 ulps at |l + v| = 1e-3, p = 1e6). The
        // complements need nothing: |v + t|² moves with |v| by 2(1 + v·t), 0 at v = −t.
        let (e_l, e_v) = (F::length_error(d.wi), F::length_error(d.wo));
        let half_sq = |w: F::V3| w.length_squared() * F::HALF;
        let sum = if F::EXACT_LENGTHS {
            (d.wi + d.wo) - (d.wi * e_l + d.wo * e_v) * F::HALF
        } else {
            d.wi + d.wo
        };
        let a_direct = sum.dot(d.t);
        let a_l_up = half_sq(d.wo + d.t) - half_sq(d.wi - d.t);
        let a_l_down = half_sq(d.wi + d.t) - half_sq(d.wo - d.t);
        let a = if cos_l > F::HALF && cos_v < -F::HALF {
            a_l_up
        } else if cos_l < -F::HALF && cos_v > F::HALF {
            a_l_down
        } else {
            a_direct
        };
        let sines = sin_l + sin_v;
        // Both sines 0 (l and v along the fibre): then b = 0 exactly.
        let b = a * (d.wo - d.wi).dot(d.t) / if sines > F::ZERO { sines } else { F::ONE };
        let one_minus = min((a * a + b * b) * F::HALF, F::ONE);
        let positive = x > F::ZERO;
        let lobe = Cosine {
            cos: if positive { min(x, F::ONE) } else { F::ZERO },
            one_minus: if positive { one_minus } else { F::ONE },
        }
        .powf::<P>(pp.p);
        let lit = d.n.dot(d.wi) > F::ZERO;
        [0, 1, 2].map(|c| {
            let s = pp.kd[c] * sin_l + pp.ks[c] * lobe;
            if lit { s } else { F::ZERO }
        })
    }
}
