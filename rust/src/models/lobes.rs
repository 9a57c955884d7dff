//! Pieces the Phong and Blinn-Phong families share: the lobe cosines of docs/models.md, the
//! parameter layout "diffuse colour + specular colour + exponent" and its prepared triple.

use super::{Directions, ParamSource};
use crate::math::geometry::{Cosine, clamped_cosine, half_vector, mirror, weighted};
use crate::math::{PowUnit, Real, Vector3};
use crate::models::slots::{ColourSlot, ScalarSlot};

// The power-lobe models' parameters: `kd`, `ks` and the exponent `p`.
crate::param_slots! {
    KD: ColourSlot,
    KS: ColourSlot,
    P: ScalarSlot,
}

/// Prepared constants of a diffuse + cosine-power lobe: `kd` and `ks` already carry the
/// model's constant factors (1/π, (p+2)/(2π), ...).
#[derive(Clone, Copy)]
pub struct DiffuseSpecular<F> {
    pub kd: [F; 3],
    pub ks: [F; 3],
    pub p: F,
}

impl<F: Real> DiffuseSpecular<F> {
    /// Reads `kd`, `ks` and `p` ([`KD`], [`KS`], [`P`]), and scales them.
    #[inline(always)]
    pub fn read<S: ParamSource<F> + ?Sized>(p: &S, kd_scale: F, ks_scale: impl Fn(F) -> F) -> Self {
        let exponent = P.read(p);
        let s = ks_scale(exponent);
        DiffuseSpecular {
            kd: KD.read(p).map(|c| c * kd_scale),
            ks: KS.read(p).map(|c| c * s),
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

/// `cos_th^p / div` (`div > 0`: `mu_i` for the Blinn-Phong lobe, 1 for a plain power)
/// and whether the half vector is defined: `half_cosine(d).0.powf_over(p, div)`, except
/// where `n·h` lies below the normal range. That happens in float64 when both directions
/// are within ~1e-308 of the horizon on opposite sides: `n·h = (mu_i + mu_o)/|wi + wo|` is
/// a subnormal with as few as 10 significant bits, which `p < 1` or the division by
/// `mu_i` brings back to the normal range. There `n·h` is formed from `wi + wo` scaled by
/// 2^600 (exact) and the power takes the exponent back inside its logarithm, so the
/// result keeps full precision (docs/numerics.md). Elsewhere bitwise the plain power.
#[inline(always)]
pub fn half_cosine_pow_over<F: Real, P: PowUnit>(d: &Directions<F>, p: F, div: F) -> (F, bool) {
    let hv = half_vector::<F>(d.wi, d.wo);
    let cos = clamped_cosine::<F>(d.n, hv.h);
    if !F::EXTENDED_COSINES {
        return (cos.powf_over::<P>(p, div), hv.defined);
    }
    // 2^600, and |wi + wo| = 2·cos_b (at most 2: its clamp at 1 never bites here).
    let up = F::from_f64(4.149_515_568_880_993e180);
    let scaled = d.n.dot((d.wi + d.wo) * up) / (F::TWO * hv.cos_b.cos);
    // The scaled cosine must be that of a tiny n·h (at most 2^-400, the power's domain):
    // where the two disagree, cancellation in n·h decides, as in the plain power.
    let tiny = cos.cos < F::from_f64(f64::MIN_POSITIVE)
        && scaled > F::ZERO
        && scaled <= F::from_f64(3.872_591_914_849_318_3e-121);
    let lobe = P::pow_unit_over_scaled(
        if tiny { scaled } else { cos.cos },
        if tiny { F::ONE } else { cos.one_minus },
        p,
        if tiny { F::from_f64(600.0) } else { F::ZERO },
        div,
    );
    (F::flush_subnormal(lobe), hv.defined)
}
