//! The angles of MODELS.md, computed so they stay accurate where naive formulas lose digits.
//!
//! Every cosine that is raised to a large power comes with its complement `1 - cos`
//! computed from a vector difference, `1 - u·v = |u - v|^2 / 2` for unit `u`, `v`. That
//! keeps `cos^p` accurate for `p` up to 1e8 (forming `1 - cos` from `cos` would lose all
//! digits within 1e-16 of the peak) and makes Schlick's `(1 - cos_b)^5` free of
//! cancellation. All inputs are unit vectors.

use super::{Real, Vector3, clamp, max, min};

/// A cosine together with its accurately computed complement `1 - cos`.
#[derive(Clone, Copy, Debug)]
pub struct Cosine<F> {
    /// The cosine, clamped to `[0, 1]`.
    pub cos: F,
    /// `1 - cos`, accurate relative to itself, in `[0, 1]`.
    pub one_minus: F,
}

impl<F: Real> Cosine<F> {
    /// Returns `cos^p` (with `0^0 = 1`), accurate even for huge `p` near the peak.
    /// In `f32`, results below 2^-100 ≈ 7.9e-31 are returned as 0: carried through the
    /// model they would become subnormals, each costing ~100-cycle microcode assists
    /// (see [`Real::flush_subnormal`]).
    #[inline(always)]
    pub fn powf(self, p: F) -> F {
        F::flush_subnormal(F::pow_unit(self.cos, self.one_minus, p))
    }
}

/// Returns `max(0, u·v)` and `1 - max(0, u·v)` for unit `u`, `v`.
#[inline(always)]
pub fn clamped_cosine<F: Real>(u: F::V3, v: F::V3) -> Cosine<F> {
    let d = u.dot(v);
    let diff = u - v;
    let one_minus = min(diff.length_squared() * F::HALF, F::ONE);
    // Below the horizon of `u` the clamped cosine is 0 and its complement exactly 1.
    let above = d > F::ZERO;
    Cosine {
        cos: if above { min(d, F::ONE) } else { F::ZERO },
        one_minus: if above { one_minus } else { F::ONE },
    }
}

/// Returns `r = 2 (n·wi) n - wi`, the mirror direction of `wi` about `n`.
#[inline(always)]
pub fn mirror<F: Real>(wi: F::V3, n: F::V3, mu_i: F) -> F::V3 {
    n * (F::TWO * mu_i) - wi
}

/// The half vector of MODELS.md with the angle β between it and `wi` (and `wo`).
#[derive(Clone, Copy, Debug)]
pub struct HalfVector<F: Real> {
    /// `h = (wi + wo) / |wi + wo|`.
    pub h: F::V3,
    /// `cos_b = wi·h = wo·h = |wi + wo| / 2`, with `1 - cos_b = |wi - h|^2 / 2`.
    pub cos_b: Cosine<F>,
    /// False when `wi = -wo` exactly: `h` is undefined and the caller returns 0.
    pub defined: bool,
}

/// Returns the half vector of unit `wi`, `wo` and the angle it makes with them.
///
/// `wi + wo` is exact where the two nearly cancel (Sterbenz), so `h` and
/// `cos_b = |wi + wo| / 2` stay accurate for tiny sums, where `wi·h` would cancel.
#[inline(always)]
pub fn half_vector<F: Real>(wi: F::V3, wo: F::V3) -> HalfVector<F> {
    let s = wi + wo;
    let len2 = s.length_squared();
    let defined = len2 > F::ZERO;
    // When undefined, divide by 1 to keep the lane finite (the caller zeroes it).
    let len = if defined { len2.sqrt() } else { F::ONE };
    let h = s * (F::ONE / len);
    let one_minus = min((wi - h).length_squared() * F::HALF, F::ONE);
    HalfVector {
        h,
        cos_b: Cosine {
            cos: min(len * F::HALF, F::ONE),
            one_minus,
        },
        defined,
    }
}

/// Returns Schlick's `(1 - cos)^5` from an accurate complement.
#[inline(always)]
pub fn schlick_weight<F: Real>(c: Cosine<F>) -> F {
    let x = c.one_minus;
    let x2 = x * x;
    x2 * x2 * x
}

/// Returns `sin a · tan b · max(0, cos(φi − φo))` of Oren-Nayar, `a = max(θi, θo)`,
/// `b = min(θi, θo)`, without any trigonometric function.
///
/// With `sin θ = |n × w|` and `cos(φi − φo) = (n × wi)·(n × wo) / (sin θi sin θo)`:
/// `sin a · sin b = sin θi sin θo` cancels the projections' lengths and
/// `cos b = max(mu_i, mu_o)`, so the product is `max(0, (n × wi)·(n × wo)) / max(mu_i, mu_o)`.
/// A zero-length projection gives 0, as MODELS.md requires. Valid whenever
/// `max(mu_i, mu_o) > 0`; returns 0 otherwise.
#[inline(always)]
pub fn oren_nayar_angular<F: Real>(wi: F::V3, wo: F::V3, n: F::V3, mu_i: F, mu_o: F) -> F {
    let proj = n.cross(wi).dot(n.cross(wo));
    let cos_b = max(mu_i, mu_o);
    let value = max(proj, F::ZERO) / cos_b;
    if cos_b > F::ZERO { value } else { F::ZERO }
}

/// Returns the Oren-Nayar coefficients `(A, B)` for roughness `sigma`.
#[inline(always)]
pub fn oren_nayar_ab<F: Real>(sigma: F) -> (F, F) {
    let s2 = sigma * sigma;
    let a = F::ONE - F::HALF * s2 / (s2 + F::from_f64(0.33));
    let b = F::from_f64(0.45) * s2 / (s2 + F::from_f64(0.09));
    (a, b)
}

/// Returns `sqrt(max(0, 1 - c^2))` for a cosine `c` in `[-1, 1]`, as `sqrt((1-c)(1+c))`.
#[inline(always)]
pub fn sine_from_cosine<F: Real>(c: F) -> F {
    let c = clamp(c, -F::ONE, F::ONE);
    max((F::ONE - c) * (F::ONE + c), F::ZERO).sqrt()
}

/// Returns the unit tangent `x` (tangent projected onto the plane normal to `n` and
/// normalized: Gram-Schmidt) and `y = n × x`. A tangent parallel to `n` has no
/// projection; then any unit vector perpendicular to `n` is used.
#[inline(always)]
pub fn tangent_frame<F: Real>(n: F::V3, t: F::V3) -> (F::V3, F::V3) {
    let p = t - n * n.dot(t);
    let len2 = p.length_squared();
    let ok = len2 > F::from_f64(1e-30);
    let scale = F::ONE / if ok { len2.sqrt() } else { F::ONE };
    let fallback = n.any_orthonormal();
    let x = F::V3::new(
        if ok { p.x() * scale } else { fallback.x() },
        if ok { p.y() * scale } else { fallback.y() },
        if ok { p.z() * scale } else { fallback.z() },
    );
    (x, n.cross(x))
}

/// Returns Schlick's `F = F0 + (1 − F0)·w` per channel, `w = (1 − cos)^5`.
#[inline(always)]
pub fn schlick_rgb<F: Real>(f0: [F; 3], w: F) -> [F; 3] {
    f0.map(|c| c + (F::ONE - c) * w)
}

/// `μ·Λ(μ)` of the GGX (Trowbridge-Reitz) Smith function, `Λ(μ) =
/// (−1 + sqrt(1 + α²(1 − μ²)/μ²))/2`, written as `α² s²/(2(r + μ))` with
/// `r = sqrt(μ² + α² s²)`, `s² = 1 − μ²`: finite and accurate at grazing angles (where
/// `Λ` itself overflows) and near normal incidence (where `−1 + sqrt(1 + x)` cancels).
#[inline(always)]
pub fn ggx_mu_lambda<F: Real>(mu: F, sin2: F, alpha2: F) -> F {
    let a2s2 = alpha2 * sin2;
    let r = (mu * mu + a2s2).sqrt();
    a2s2 / (F::TWO * (r + mu))
}

/// Zeroes an RGB value unless both directions are above the surface (family A).
#[inline(always)]
pub fn above_both<F: Real>(mu_i: F, mu_o: F, rgb: [F; 3]) -> [F; 3] {
    let above = mu_i > F::ZERO && mu_o > F::ZERO;
    rgb.map(|c| if above { c } else { F::ZERO })
}

/// Returns `a·x + b` per channel.
#[inline(always)]
pub fn rgb_affine<F: Real>(a: [F; 3], x: F, b: [F; 3]) -> [F; 3] {
    [a[0] * x + b[0], a[1] * x + b[1], a[2] * x + b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn complement_is_accurate_near_the_peak() {
        let n = DVec3::Z;
        let t = 1e-9_f64;
        let w = DVec3::new(t.sin(), 0.0, t.cos());
        let c = clamped_cosine::<f64>(n, w);
        // 1 - cos t = t^2/2 - t^4/24...
        let exact = t * t / 2.0;
        assert!(
            (c.one_minus - exact).abs() <= 1e-15 * exact,
            "{} vs {exact}",
            c.one_minus
        );
    }

    #[test]
    fn oren_nayar_identity_matches_trigonometry() {
        let n = DVec3::Z;
        let (ti, to, dphi) = (0.7_f64, 1.1_f64, 0.4_f64);
        let wi = DVec3::new(ti.sin(), 0.0, ti.cos());
        let wo = DVec3::new(to.sin() * dphi.cos(), to.sin() * dphi.sin(), to.cos());
        let got = oren_nayar_angular::<f64>(wi, wo, n, wi.z, wo.z);
        let want = to.sin() * ti.tan() * dphi.cos();
        assert!((got - want).abs() < 1e-15, "{got} {want}");
    }

    #[test]
    fn half_vector_of_opposite_directions_is_undefined() {
        let w = DVec3::new(0.3, 0.4, 0.5).normalize();
        assert!(!half_vector::<f64>(w, -w).defined);
        assert!(half_vector::<f64>(w, w).defined);
        let v = DVec3::new(-0.3, 0.4001, 0.5).normalize();
        let hv = half_vector::<f64>(w, v);
        assert!((hv.cos_b.cos - w.dot(hv.h)).abs() < 1e-15);
    }
}
