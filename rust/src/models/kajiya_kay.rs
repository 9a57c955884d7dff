//! `kajiya_kay`: the Kajiya-Kay hair/fibre shading term (RTR eq. 7.50).
//!
//! `s(l, v) = kd·sin_l + ks·max(0, sin_l·sin_v − (l·t)(v·t))^p`,
//! `sin_l = sqrt(max(0, 1−(l·t)²))`, `sin_v` likewise, `t` the unit fibre tangent
//! (normalized, not projected); 0 when `n·l <= 0`. The sign `−(l·t)(v·t)` is right for
//! directions pointing away from the surface.
//!
//! Sines are `|l × t|` (accurate near 0), and with `A = (−l·t, sin_l)`,
//! `B = (v·t, sin_v)` the lobe cosine is `A·B`, so `1 − A·B = |A − B|²/2` stays accurate
//! near the highlight peak for large `p`.

use super::spec::{self, Family, ModelSpec, TangentUse};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::Cosine;
use crate::math::{Real, Vector3, min};

/// The Kajiya-Kay kernel.
pub struct KajiyaKay;

pub static SPEC: ModelSpec = ModelSpec {
    name: "kajiya_kay",
    family: Family::B,
    summary: "Kajiya-Kay fibre shading: diffuse sin_l plus a cosine-power cone highlight",
    formula: "s = kd·sin_l + ks·max(0, sin_l·sin_v − (l·t)(v·t))^p, 0 when n·l <= 0",
    source: "Kajiya & Kay 1989; RTR 3rd ed. eq. 7.50",
    params: &[spec::kd(0.5, 0), spec::ks(0.5, 3), spec::exponent(6)],
    tangent: TangentUse::Required,
    reciprocal: false,
};

impl Kernel for KajiyaKay {
    type Prepared<F: Real> = super::lobes::DiffuseSpecular<F>;

    fn spec() -> &'static ModelSpec {
        &SPEC
    }

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Self::Prepared<F> {
        super::lobes::DiffuseSpecular::read(p, F::ONE, |_| F::ONE)
    }

    #[inline(always)]
    fn eval<F: Real>(pp: &Self::Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let cos_l = d.wi.dot(d.t);
        let cos_v = d.wo.dot(d.t);
        let sin_l = d.wi.cross(d.t).length_squared().sqrt();
        let sin_v = d.wo.cross(d.t).length_squared().sqrt();
        let x = sin_l * sin_v - cos_l * cos_v;
        let (a, b) = (cos_l + cos_v, sin_l - sin_v);
        let one_minus = min((a * a + b * b) * F::HALF, F::ONE);
        let positive = x > F::ZERO;
        let lobe = Cosine {
            cos: if positive { min(x, F::ONE) } else { F::ZERO },
            one_minus: if positive { one_minus } else { F::ONE },
        }
        .powf(pp.p);
        let lit = d.n.dot(d.wi) > F::ZERO;
        [0, 1, 2].map(|c| {
            let s = pp.kd[c] * sin_l + pp.ks[c] * lobe;
            if lit { s } else { F::ZERO }
        })
    }
}
