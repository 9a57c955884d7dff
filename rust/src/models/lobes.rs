//! Pieces the Phong and Blinn-Phong families share: the lobe cosines of MODELS.md and the
//! prepared "diffuse colour + specular colour + exponent" triple.

use super::{Directions, ParamSource};
use crate::math::geometry::{Cosine, clamped_cosine, half_vector, mirror, weighted};
use crate::math::{Real, Vector3};

/// Prepared constants of a diffuse + cosine-power lobe: `kd` and `ks` already carry the
/// model's constant factors (1/π, (p+2)/(2π), ...).
#[derive(Clone, Copy)]
pub struct DiffuseSpecular<F> {
    pub kd: [F; 3],
    pub ks: [F; 3],
    pub p: F,
}

impl<F: Real> DiffuseSpecular<F> {
    /// Reads `kd` (slots 0..3), `ks` (3..6) and `p` (6), and scales them.
    #[inline(always)]
    pub fn read<P: ParamSource<F> + ?Sized>(p: &P, kd_scale: F, ks_scale: impl Fn(F) -> F) -> Self {
        let exponent = p.scalar(6);
        let s = ks_scale(exponent);
        DiffuseSpecular {
            kd: p.colour(0).map(|c| c * kd_scale),
            ks: p.colour(3).map(|c| c * s),
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

/// Returns `mu_i = n·wi` and `cos_ar = max(0, r·wo)` with `r` the mirror of `wi` about `n`.
#[inline(always)]
pub fn mirror_cosine<F: Real>(d: &Directions<F>) -> (F, Cosine<F>) {
    let mu_i = d.n.dot(d.wi);
    let r = mirror::<F>(d.wi, d.n, mu_i);
    (mu_i, clamped_cosine::<F>(r, d.wo))
}

/// Returns `cos_th = max(0, n·h)` and whether `h` is defined (`wi + wo ≠ 0`).
#[inline(always)]
pub fn half_cosine<F: Real>(d: &Directions<F>) -> (Cosine<F>, bool) {
    let hv = half_vector::<F>(d.wi, d.wo);
    (clamped_cosine::<F>(d.n, hv.h), hv.defined)
}
