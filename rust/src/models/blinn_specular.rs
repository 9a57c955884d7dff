//! `blinn_specular`: the shading assignment's Blinn specular term.
//!
//! `s(l, v) = ks·clamp(n·h, 0, 1)^p`, 0 when `n·l <= 0` or when `h` is undefined
//! (`l = −v`); `= mu_i·blinn_phong(kd=0)` for mu_i, mu_o > 0.

use super::lobes::half_cosine_pow_over;
// The specular terms' layout (`ks`, `p`).
pub use super::phong_specular::SLOTS;
use super::phong_specular::{KS, P, SPECULAR_TERM_SPEC};
use super::spec::ModelSpec;
use super::{Directions, Kernel, ParamSource};
use crate::math::{PowUnit, Real, Vector3};

/// The Blinn specular kernel.
pub struct BlinnSpecular;

pub static SPEC: ModelSpec = ModelSpec {
    name: "blinn_specular",
    summary: "Blinn specular shading term: cosine power of the half vector",
    formula: "s = ks·clamp(n·h, 0, 1)^p, 0 when n·l <= 0",
    source: "scan-line shading assignment (Blinn specular)",
    ..SPECULAR_TERM_SPEC
};

impl Kernel for BlinnSpecular {
    type Prepared<F: Real> = ([F; 3], F);
    const POWERS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> ([F; 3], F) {
        (KS.read(p), P.read(p))
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &([F; 3], F), d: &Directions<F>) -> [F; 3] {
        let (ks, p) = *pp;
        let (lobe, defined) = half_cosine_pow_over::<F, P>(d, p, F::ONE);
        let lit = d.n.dot(d.wi) > F::ZERO && defined;
        ks.map(|c| if lit { c * lobe } else { F::ZERO })
    }
}
