//! `ward`: Ward's anisotropic Gaussian BRDF (Ward 1992, as RTR §7.6 mentions it).
//!
//! `f = kd/π + ks·exp(−((h·x/αx)² + (h·y/αy)²)/cos_th²) / (4π·αx·αy·sqrt(mu_i·mu_o))`,
//! `x` the unit tangent (the given tangent projected onto the tangent plane and
//! normalized: Gram-Schmidt; +x without one), `y = n × x`. Isotropic when αx = αy (the
//! tangent then does not matter).

use super::albedo::{Importance, Integral, Term, basis, colour};
use super::spec::{self, Family, ModelSpec, TangentUse};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::{above_both, half_vector, tangent_frame, weighted};
use crate::math::{Real, Vector3};

/// The Ward kernel.
pub struct Ward;

pub static SPEC: ModelSpec = ModelSpec {
    name: "ward",
    family: Family::A,
    summary: "Ward's anisotropic Gaussian lobe of the half vector, plus Lambert",
    formula: "f = kd/π + ks·exp(−((h·x/αx)² + (h·y/αy)²)/cos_th²)/(4π·αx·αy·sqrt(mu_i·mu_o))",
    source: "Ward 1992 (SIGGRAPH), anisotropic form; RTR 3rd ed. §7.6; MODELS.md",
    params: &[
        spec::kd(0.0, 0),
        spec::ks(1.0, 3),
        spec::roughness(
            "alpha_x",
            0.2,
            6,
            "roughness along the tangent x (RMS slope)",
        ),
        spec::roughness("alpha_y", 0.2, 7, "roughness along the bitangent y = n × x"),
    ],
    tangent: TangentUse::Optional,
    reciprocal: true,
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

    fn spec() -> &'static ModelSpec {
        &SPEC
    }

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let (ax, ay) = (p.scalar(6), p.scalar(7));
        Prepared {
            kd_over_pi: p.colour(0).map(|c| c * F::FRAC_1_PI),
            ks: p.colour(3),
            inv_ax: F::ONE / ax,
            inv_ay: F::ONE / ay,
            norm: F::from_f64(0.25) * F::FRAC_1_PI / (ax * ay),
        }
    }

    #[inline(always)]
    fn eval<F: Real>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let (x, y) = tangent_frame::<F>(d.n, d.t);
        let hv = half_vector::<F>(d.wi, d.wo);
        let cos_th = d.n.dot(hv.h);
        let hx = hv.h.dot(x) * pp.inv_ax;
        let hy = hv.h.dot(y) * pp.inv_ay;
        let e = (hx * hx + hy * hy) / (cos_th * cos_th);
        let lobe = (-e).exp() * pp.norm / (mu_i.sqrt() * mu_o.sqrt());
        let lobe = if e < F::from_f64(700.0) && hv.defined {
            F::flush_subnormal(lobe)
        } else {
            F::ZERO
        };
        let rgb = [0, 1, 2].map(|c| weighted(pp.ks[c], lobe) + pp.kd_over_pi[c]);
        above_both(mu_i, mu_o, rgb)
    }

    /// `kd·1 + ks·I`, the lobe drawn with Walter's sampling of the Gaussian NDF.
    fn albedo_terms(slots: &[f64], _mu: f64) -> Option<Vec<Term>> {
        let importance = Importance::BeckmannHalf {
            alpha_x: slots[6],
            alpha_y: slots[7],
        };
        Some(vec![
            Term {
                colour: colour(slots, 0),
                integral: Integral::Exact(1.0),
            },
            Term {
                colour: colour(slots, 3),
                integral: Integral::Lobe {
                    basis: basis(slots, &[(0, 0.0), (3, 1.0)]),
                    importance,
                },
            },
        ])
    }
}
