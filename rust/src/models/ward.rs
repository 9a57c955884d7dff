//! `ward`: Ward's anisotropic Gaussian BRDF (Ward 1992, as RTR §7.6 mentions it).
//!
//! `f = kd/π + ks·exp(−((h·x/αx)² + (h·y/αy)²)/cos_th²) / (4π·αx·αy·sqrt(mu_i·mu_o))`,
//! `x` the unit tangent (the given tangent projected onto the tangent plane and
//! normalized: Gram-Schmidt; +x without one), `y = n × x`. Isotropic when αx = αy (the
//! tangent then does not matter).

use super::albedo::{Importance, Term, diffuse_and_lobe};
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{
    self, DiffuseTerm, ExactFactor, ExactNormalization, ModelSpec, SceneUse, TangentUse,
};
use super::{Directions, Kernel, ParamSource, WideRow};
use crate::math::geometry::{above_both, half_vector, tangent_frame, weighted};
use crate::math::{PowUnit, Real, Vector3};

/// The Ward kernel.
pub struct Ward;

crate::param_slots! {
    KD: ColourSlot,
    KS: ColourSlot,
    ALPHA_X: ScalarSlot,
    ALPHA_Y: ScalarSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "ward",
    summary: "Ward's anisotropic Gaussian lobe of the half vector, plus Lambert",
    formula: "f = kd/π + ks·exp(−((h·x/αx)² + (h·y/αy)²)/cos_th²)/(4π·αx·αy·sqrt(mu_i·mu_o))",
    source: "Ward 1992 (SIGGRAPH), anisotropic form; RTR 3rd ed. §7.6",
    params: &[
        spec::kd(0.0, KD),
        spec::ks(1.0, KS),
        spec::roughness(
            "alpha_x",
            0.2,
            ALPHA_X,
            "roughness along the tangent x (RMS slope)",
        ),
        spec::roughness(
            "alpha_y",
            0.2,
            ALPHA_Y,
            "roughness along the bitangent y = n × x",
        ),
    ],
    tangent: TangentUse::Optional,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    exact: Some(ExactNormalization {
        factor: ExactFactor::Table("ward"),
        params: &["alpha_x", "alpha_y"],
        scales: "ks",
    }),
    ..ModelSpec::PLAIN
};

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    kd_over_pi: [F; 3],
    ks: [F; 3],
    inv_ax: F,
    inv_ay: F,
    /// `1/(4π αx αy)`.
    norm: F,
}

impl Kernel for Ward {
    type Prepared<F: Real> = Prepared<F>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let (ax, ay) = (ALPHA_X.read(p), ALPHA_Y.read(p));
        Prepared {
            kd_over_pi: KD.read(p).map(|c| c * F::FRAC_1_PI),
            ks: KS.read(p),
            inv_ax: F::ONE / ax,
            inv_ay: F::ONE / ay,
            norm: F::from_f64(0.25) * F::FRAC_1_PI / (ax * ay),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let root = mu_i.sqrt() * mu_o.sqrt();
        // f64: exp(−e) ≥ 1e-304 and 2.2e-308 ≤ root ≤ 1 here (smaller cosines take
        // `eval_wide`), so the quotient is normal and the product by `norm` is the one
        // rounding that may underflow (forming exp(−e)·norm first underflowed before the
        // division for large α: 1e-11 relative at cosθ = 1e-200, α = 1e7). f32 keeps its
        // subnormal cosines, where exp(−e)/root could overflow: norm first.
        value(pp, d, mu_i, mu_o, |g| {
            if F::EXTENDED_COSINES {
                g / root * pp.norm
            } else {
                g * pp.norm / root
            }
        })
    }

    /// The cosines can be below the normal range (`wi = (1e300, 0, 1e-300)` has
    /// `mu_i = 1e-600`) while `1/sqrt(mu_i·mu_o)` is not.
    const WIDE_COSINES: bool = true;

    /// `sqrt(mu_i·mu_o) = sqrt(m_i·m_o·2^r)·2^h` with `k_i + k_o = 2h + r`, `norm =
    /// n_m·2^n_e`: the lobe is `exp(−e)/sqrt(m_i·m_o·2^r)·n_m` (normal) scaled by
    /// `2^(n_e − h)` with one rounding. The side of the surface comes from the wide
    /// cosines' signs: normalization may round a cosine of the other sign, or an exact
    /// 0, to a tiny positive one.
    fn eval_wide<F: Real>(pp: &Prepared<F>, d: &Directions<F>, w: &WideRow) -> [F; 3] {
        let (mu_i, mu_o) = (w.mu_i, w.mu_o);
        let k = mu_i.k + mu_o.k;
        let r = k.rem_euclid(2);
        let root = (mu_i.m * mu_o.m * f64::from(1 + r)).sqrt();
        let h = (k - r) / 2;
        let (norm_m, norm_e) = libm::frexp(pp.norm.to_f64());
        let (sign_i, sign_o) = (F::from_f64(mu_i.m), F::from_f64(mu_o.m));
        value(pp, d, sign_i, sign_o, |g| {
            let lobe = g.to_f64() / root * norm_m;
            F::from_f64(libm::scalbn(lobe, norm_e - h))
        })
    }

    /// `kd·1 + ks·I`, the lobe drawn with Walter's sampling of the Gaussian NDF.
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        let importance = Importance::BeckmannHalf {
            alpha_x: ALPHA_X.read(slots),
            alpha_y: ALPHA_Y.read(slots),
        };
        Some(diffuse_and_lobe(slots, KD, KS, 1.0, importance))
    }
}

/// Ward's value given the cosines that decide the side of the surface and `lobe`, which
/// turns `exp(−e)` into the lobe `exp(−e)·norm/sqrt(mu_i·mu_o)`.
#[inline(always)]
fn value<F: Real>(
    pp: &Prepared<F>,
    d: &Directions<F>,
    mu_i: F,
    mu_o: F,
    lobe: impl Fn(F) -> F,
) -> [F; 3] {
    let (x, y) = tangent_frame::<F>(d.n, d.t);
    let hv = half_vector::<F>(d.wi, d.wo);
    let cos_th = d.n.dot(hv.h);
    let hx = hv.h.dot(x) * pp.inv_ax;
    let hy = hv.h.dot(y) * pp.inv_ay;
    let e = (hx * hx + hy * hy) / (cos_th * cos_th);
    let lobe = lobe((-e).exp());
    let lobe = if e < F::from_f64(700.0) && hv.defined {
        F::flush_subnormal(lobe)
    } else {
        F::ZERO
    };
    let rgb = [0, 1, 2].map(|c| weighted(pp.ks[c], lobe) + pp.kd_over_pi[c]);
    above_both(mu_i, mu_o, rgb)
}
