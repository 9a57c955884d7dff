//! `zeltner_sheen`: Zeltner, Burley and Chiang's sheen (2022), a linearly transformed
//! cosine fitted to a volumetric fibre layer, scaled by the layer's directional albedo,
//! with the paper's analytic fits of both (OpenPBR's fuzz, MaterialX's Zeltner sheen).
//!
//! `f = kd/π + ks·R(mu_o, α)·D(wi)/mu_i`, `D` the clamped cosine carried by `M⁻¹ = [[a, 0,
//! b], [0, a, 0], [0, 0, 1]]` in the frame of the view `wo`. Above both directions the
//! kernel computes `ks·R·a²/(π·q²)` with `q = |M⁻¹·wi|²` written without the frame
//! (docs/models.md): `q = a²(1 − mu_i²) + 2a·g·c·mu_i/sqrt(1 + mu_o) + (1 + (1 − mu_o)g²)·mu_i²`,
//! `c = wi·wo − mu_i·mu_o`, `b = sqrt(1 − mu_o)·g`.

use super::albedo::{Importance, Term};
use super::sheen::{self, ALPHA, Dd, KD, KS};
use super::spec::{
    self, DiffuseTerm, ModelSpec, ParamKind, ParamSpec, SceneUse, ValidRange,
};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::{above_both, weighted};
use crate::math::{PowUnit, Real, Vector3, max};

/// The Zeltner sheen kernel.
pub struct ZeltnerSheen;

// The sheen models' layout (`kd`, `ks`, `alpha`).
pub use super::sheen::SLOTS;

/// The roughness range of the paper's fits.
const FIT_ROUGHNESS: ValidRange = ValidRange {
    min: 0.01,
    max: 1.0,
    min_open: false,
    max_open: false,
};

pub static SPEC: ModelSpec = ModelSpec {
    name: "zeltner_sheen",
    summary: "Zeltner et al.'s sheen: a linearly transformed cosine fitted to a volumetric \
              fibre layer, scaled by its albedo (OpenPBR's fuzz)",
    formula: "f = kd/π + ks·R(mu_o, α)·D(wi)/mu_i, D(w) = max(z, 0)/π·(a/|w′|²)², \
              w′ = (a·x + b·z, a·y, z) in the frame of wo, a, b, R: the paper's fits in \
              (mu_o, α)",
    source: "Zeltner, Burley & Chiang 2022 (the model and its fits); MaterialX \
             mx_zeltner_sheen_brdf, OpenPBR fuzz",
    params: &[
        spec::kd(0.0, KD),
        sheen::SHEEN_COLOUR,
        ParamSpec {
            name: "alpha",
            kind: ParamKind::Scalar,
            default: Some(0.5),
            range: FIT_ROUGHNESS,
            doc: "roughness in [0.01, 1], the domain of the paper's fits",
            slot: ALPHA.first(),
        },
    ],
    reciprocal: false,
    weights: Some(&["kd", "ks"]),
    scene: SceneUse::Brdf(DiffuseTerm::Lambert(1.0)),
    // Its table holds the albedo seen from the view, `R` in closed form
    // ([`Kernel::sheen_view_albedo`]): the lobe is not reciprocal, and `brdf_rs.albedo`
    // (over the other direction) is not the albedo a layer takes out of the light.
    energy_table: true,
    sheen_layer: true,
    ..ModelSpec::PLAIN
};

/// The fit's decimals as the nearest `f64` and the rest, for [`Dd`]:
/// `s = α(S0 + S1·α)/(S2 + α(S3 + α))`, `m = α(M0 + α(M1 + α(M2 − M3·α²)))/(M4 + α)`,
/// `o = α(O0 + (O1 + O2·α)α)/(O3 + α(O4 + α))`.
const S0: (f64, f64) = (0.0206607, -5.9237059701899855e-19);
const S1: (f64, f64) = (1.58491, -4.099831585335778e-17);
const S2: (f64, f64) = (0.0379424, -1.1256773291279386e-18);
const S3: (f64, f64) = (1.32227, -5.641709321935195e-17);
const M0: (f64, f64) = (-0.193854, -1.461941678826406e-18);
const M1: (f64, f64) = (-1.14885, -7.318590178329032e-17);
const M2: (f64, f64) = (1.7932, 9.485745522397338e-17);
const M3: (f64, f64) = (0.95943, -5.0448534238967115e-18);
const M4: (f64, f64) = (0.046391, -1.679545391652937e-18);
const O0: (f64, f64) = (0.000654023, 4.1498471325951415e-21);
const O1: (f64, f64) = (-0.0207818, -4.2139625122672443e-19);
const O2: (f64, f64) = (0.119681, 4.280131804534904e-18);
const O3: (f64, f64) = (1.26264, 1.5418777365994174e-17);
const O4: (f64, f64) = (-1.92021, -2.756905814749189e-17);
/// `sqrt(2π)`.
const SQRT_2PI: (f64, f64) = (2.5066282746310007, -1.8328579980459167e-16);

/// The paper's fits at one roughness: `R`'s Gaussian in `mu_o` and the factors of `a` and
/// `g` that do not depend on `mu_o`.
///
/// `R = exp(−t²/2)/(s·sqrt(2π)) + o`, `t = (mu_o − m)/s`, reaches `t²/2` of several
/// hundred, and `exp` turns the absolute error of `t²/2` into `R`'s relative error; `o`
/// is negative for some α, where the sum cancels. So the constants (from their decimals),
/// `s`, `m`, `o`, `t²/2` and the sum are carried in double width ([`Dd`]).
#[derive(Clone, Copy)]
pub struct Fits<F> {
    alpha: F,
    /// `R`'s centre `m`, `1/s`, `1/(s·sqrt(2π))` and offset `o`.
    m: Dd<F>,
    inv_s: Dd<F>,
    peak: Dd<F>,
    o: Dd<F>,
    /// `g`'s numerator `(α − 1)α³`, and its denominator's parts `0.0000254053 + 1.34174α²`
    /// and `1.71228 − 1.71506α` (the factor of `mu_o`).
    g_num: F,
    g_den0: F,
    g_den1: F,
}

impl<F: Real> Fits<F> {
    pub fn new(alpha: F) -> Self {
        // The decimal as the width's nearest value and the rest (f32 keeps the part of
        // the f64 value it rounds away).
        let dd = |(hi, lo): (f64, f64)| {
            let h = F::from_f64(hi);
            Dd::new(h, F::from_f64((hi - h.to_f64()) + lo))
        };
        let a = Dd::new(alpha, F::ZERO);
        let s = a
            .times(dd(S0).plus(dd(S1).times(a)))
            .over(dd(S2).plus(a.times(dd(S3).plus(a))));
        let m = a
            .times(dd(M0).plus(a.times(dd(M1).plus(a.times(dd(M2).plus(dd(M3).times(a).times(a).negated()))))))
            .over(dd(M4).plus(a));
        let o = a
            .times(dd(O0).plus(dd(O1).plus(dd(O2).times(a)).times(a)))
            .over(dd(O3).plus(a.times(dd(O4).plus(a))));
        let one = Dd::new(F::ONE, F::ZERO);
        let c = F::from_f64;
        Fits {
            alpha,
            m,
            inv_s: one.over(s),
            peak: one.over(s.times(dd(SQRT_2PI))),
            o,
            g_num: (alpha - F::ONE) * alpha * alpha * alpha,
            g_den0: c(0.0000254053) + c(1.34174) * alpha * alpha,
            g_den1: c(1.71228) - c(1.71506) * alpha,
        }
    }

    /// `R(mu_o, α)`: the lobe's albedo seen from the view, held at 0 where the fit dips
    /// below (its offset `o` is negative for α in about (0.041, 0.132), down to −2.1e-5).
    #[inline(always)]
    pub fn albedo(&self, mu_o: F) -> F {
        let t = Dd::new(mu_o, F::ZERO).plus(self.m.negated()).times(self.inv_s);
        let gaussian = t.times(t).times(Dd::new(F::ZERO - F::HALF, F::ZERO)).exp();
        let r = Dd::new(gaussian, F::ZERO).times(self.peak).plus(self.o);
        max(r.value(), F::ZERO)
    }

    /// `a(mu_o, α)`.
    #[inline(always)]
    pub fn a(&self, mu_o: F) -> F {
        let c = F::from_f64;
        let al = self.alpha;
        (c(2.58126) * mu_o + c(0.813703) * al) * al
            / (F::ONE + c(0.310327) * mu_o * mu_o + c(2.60994) * mu_o * al)
    }

    /// `g(mu_o, α) = b/sqrt(1 − mu_o)`.
    #[inline(always)]
    pub fn g(&self, mu_o: F) -> F {
        self.g_num / (self.g_den0 + self.g_den1 * mu_o)
    }
}

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    kd_over_pi: [F; 3],
    ks: [F; 3],
    fits: Fits<F>,
}

/// The lobe `R·D(wi)/mu_i` for a unit `ks` above both directions (`mu_i > 0`).
///
/// The cosines and `q` are quotients by the squared lengths of the (rounded) unit vectors,
/// `mu_o = n·wo/sqrt(|n|²|wo|²)` and `q`'s sum of squares over `|n|²|wi|²`: homogeneous, so
/// the lengths' rounding does not enter (`q` is squared and `D` goes as `1/mu_i⁴` near the
/// normal).
#[inline(always)]
fn lobe<F: Real>(fits: &Fits<F>, d: &Directions<F>) -> F {
    let nn = d.n.length_squared();
    let ii = d.wi.length_squared();
    let oo = d.wo.length_squared();
    let n_i = d.n.dot(d.wi);
    let n_o = d.n.dot(d.wo);
    let mu_o = n_o / (nn * oo).sqrt();
    let mu_i = n_i / (nn * ii).sqrt();
    let a = fits.a(mu_o);
    let g = fits.g(mu_o);
    let sin2_i = d.n.cross(d.wi).length_squared();
    let sin2_o = d.n.cross(d.wo).length_squared() / (nn * oo);
    let one_plus_o = F::ONE + mu_o;
    // 1 − mu_o without cancellation.
    let one_minus_o = sin2_o / one_plus_o;
    let c = d.wi.dot(d.wo) / (ii * oo).sqrt() - mu_i * mu_o;
    let q = (a * a * sin2_i + (F::ONE + one_minus_o * g * g) * (n_i * n_i)) / (nn * ii)
        + F::TWO * a * g * c * mu_i / one_plus_o.sqrt();
    fits.albedo(mu_o) * a * a * F::FRAC_1_PI / (q * q)
}

impl Kernel for ZeltnerSheen {
    type Prepared<F: Real> = Prepared<F>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        Prepared {
            kd_over_pi: KD.read(p).map(|c| c * F::FRAC_1_PI),
            ks: KS.read(p),
            fits: Fits::new(ALPHA.read(p)),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let l = lobe(&pp.fits, d);
        let rgb = [0, 1, 2].map(|c| weighted(pp.ks[c], l) + pp.kd_over_pi[c]);
        above_both(mu_i, mu_o, rgb)
    }

    /// `R(mu_o, α)` for `mu_o > 0`: this very integral, exactly (the transformed cosine
    /// `D` keeps `z`, so it integrates to 1 over the light's hemisphere; `R` is the
    /// paper's fit of the volumetric layer's albedo, which the kernel multiplies by).
    /// 0 at `mu_o <= 0` (and NaN), where `f` is 0: at grazing view the integral jumps
    /// from `R(0, α)` to 0.
    fn sheen_view_albedo(alpha: f64, mu_o: f64) -> Option<f64> {
        Some(if mu_o > 0.0 {
            Fits::new(alpha).albedo(mu_o)
        } else {
            0.0
        })
    }

    /// Drawn uniformly over the hemisphere, as the other sheens (the LTC draws `wi` for a
    /// given view, not the `wo` the integrator needs for a given `wi`).
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        Some(sheen::albedo_terms(slots, Importance::Uniform))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hook is `R` above the surface and 0 where the view is not (as `f` is).
    #[test]
    fn view_albedo_is_the_fit_above_the_surface_and_zero_below() {
        for alpha in [0.01, 0.08, 0.5, 1.0] {
            let fits = Fits::<f64>::new(alpha);
            for mu in [1e-9, 0.3, 1.0] {
                assert_eq!(ZeltnerSheen::sheen_view_albedo(alpha, mu), Some(fits.albedo(mu)));
            }
            assert!(fits.albedo(0.0) > 0.0 || (0.041..0.132).contains(&alpha));
            for mu in [0.0, -0.5, f64::NAN] {
                assert_eq!(ZeltnerSheen::sheen_view_albedo(alpha, mu), Some(0.0));
            }
        }
    }

    /// The kernel's frame-free `q` against `|M⁻¹·w|²` built in the view's frame, as the
    /// paper writes it.
    #[test]
    fn frame_free_form_matches_the_transformed_cosine() {
        use glam::DVec3;
        let fits = Fits::<f64>::new(0.3);
        for (wi, wo) in [
            (DVec3::new(0.3, -0.2, 0.9), DVec3::new(-0.5, 0.1, 0.4)),
            (DVec3::new(-0.7, 0.5, 0.2), DVec3::new(0.2, 0.3, 0.9)),
            (DVec3::new(0.1, 0.9, 0.3), DVec3::new(0.8, -0.1, 0.05)),
        ] {
            let (wi, wo, n) = (wi.normalize(), wo.normalize(), DVec3::Z);
            let d = Directions::<f64> { wi, wo, n, t: DVec3::X };
            let (mu_i, mu_o) = (wi.z, wo.z);
            let x_axis = (wo - n * mu_o).normalize();
            let y_axis = n.cross(x_axis);
            let w = DVec3::new(wi.dot(x_axis), wi.dot(y_axis), wi.z);
            let (a, b) = (fits.a(mu_o), (1.0 - mu_o).sqrt() * fits.g(mu_o));
            let wp = DVec3::new(a * w.x + b * w.z, a * w.y, w.z);
            let dist = w.z / std::f64::consts::PI * (a / wp.length_squared()).powi(2);
            let expected = fits.albedo(mu_o) * dist / mu_i;
            let got = lobe(&fits, &d);
            assert!((got - expected).abs() <= 1e-13 * expected, "{got} {expected}");
        }
    }
}
