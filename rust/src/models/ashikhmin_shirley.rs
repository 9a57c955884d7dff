//! `ashikhmin_shirley`: Ashikhmin & Shirley's anisotropic Phong BRDF (JGT 2000).
//!
//! Specular: `ρs = sqrt((nu+1)(nv+1))/(8π) · (n·h)^e / ((h·k)·max(n·k1, n·k2)) · F(k·h)`
//! with `e = (nu (h·u)² + nv (h·v)²)/(1 − (n·h)²)` and Schlick's
//! `F = Rs + (1 − Rs)(1 − k·h)^5`; diffuse (energy-preserving, coupled to the specular):
//! `ρd = 28·Rd/(23π) · (1 − Rs) · (1 − (1 − n·k1/2)^5) · (1 − (1 − n·k2/2)^5)`;
//! `f = ρs + ρd`. `u` is the unit tangent (projected onto the tangent plane; +x without
//! one), `v = n × u`, `k1 = wi`, `k2 = wo`, `k·h = wi·h = wo·h`.
//!
//! The exponent is evaluated as `(nu a² + nv b²)/(a² + b²)` with `a = h·u`, `b = h·v`
//! (`a² + b² = 1 − (n·h)²` without cancellation); at `h = n` it is `(nu + nv)/2` and the
//! power is 1 whatever it is. The diffuse term's albedo is exactly
//! `Rd·(1 − Rs)·(1 − (1 − mu_i/2)^5)` (the 28/23 normalizes it).

use super::albedo::{Importance, Integral, Term, basis, diffuse_and_schlick_lobe};
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{
    DiffuseTerm, ModelSpec, ParamKind, ParamSpec, SceneUse, TangentUse, ValidRange,
};
use super::{Directions, Kernel, ParamSource};
use crate::math::geometry::{
    above_both, clamped_cosine, half_vector_exact, schlick_weight, tangent_frame, weighted,
};
use crate::math::{PowUnit, Real, Vector3, max};

/// The Ashikhmin-Shirley kernel.
pub struct AshikhminShirley;

const fn exponent(name: &'static str, slot: ScalarSlot, doc: &'static str) -> ParamSpec {
    ParamSpec {
        name,
        kind: ParamKind::Scalar,
        default: Some(100.0),
        range: ValidRange::NON_NEGATIVE,
        doc,
        slot: slot.first(),
    }
}

crate::param_slots! {
    RD: ColourSlot,
    RS: ColourSlot,
    NU: ScalarSlot,
    NV: ScalarSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "ashikhmin_shirley",
    summary: "Ashikhmin-Shirley anisotropic Phong: Fresnel-weighted specular, coupled diffuse",
    formula: "f = sqrt((nu+1)(nv+1))/(8π)·(n·h)^((nu(h·u)²+nv(h·v)²)/(1−(n·h)²))/((h·k)·max(mu_i,mu_o))·F \
              + 28·Rd/(23π)·(1−Rs)·(1−(1−mu_i/2)^5)·(1−(1−mu_o/2)^5), F = Rs + (1−Rs)(1−k·h)^5",
    source: "Ashikhmin & Shirley 2000, An Anisotropic Phong BRDF Model (JGT 5(2)), eqs. 4-5",
    params: &[
        ParamSpec {
            name: "Rd",
            kind: ParamKind::Colour,
            default: Some(0.5),
            range: ValidRange::NON_NEGATIVE,
            doc: "diffuse reflectance Rd (RGB)",
            slot: RD.first(),
        },
        ParamSpec {
            name: "Rs",
            kind: ParamKind::Colour,
            default: Some(0.05),
            range: ValidRange::UNIT,
            doc: "specular reflectance at normal incidence Rs (RGB, in [0, 1])",
            slot: RS.first(),
        },
        exponent("nu", NU, "Phong exponent along the tangent u"),
        exponent("nv", NV, "Phong exponent along the bitangent v = n × u"),
    ],
    tangent: TangentUse::Optional,
    scene: SceneUse::Brdf(DiffuseTerm::Coupled),
    ..ModelSpec::PLAIN
};

/// Derived constants.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    /// `28·Rd·(1 − Rs)/(23π)`.
    diffuse: [F; 3],
    rs: [F; 3],
    nu: F,
    nv: F,
    /// `sqrt((nu+1)(nv+1))/(8π)`.
    norm: F,
}

/// `1 − (1 − x/2)^5`, as `(x/2)(1 + z + z² + z³ + z⁴)` with `z = 1 − x/2`: every term
/// positive, so grazing `x` (1e-300) keeps its digits where `1 − z⁵` would give 0.
#[inline(always)]
fn coupling<F: Real>(x: F) -> F {
    let y = F::HALF * x;
    let z = F::ONE - y;
    y * (F::ONE + z * (F::ONE + z * (F::ONE + z * (F::ONE + z))))
}

impl Kernel for AshikhminShirley {
    type Prepared<F: Real> = Prepared<F>;
    const POWERS: bool = true;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let (rd, rs) = (RD.read(p), RS.read(p));
        let (nu, nv) = (NU.read(p), NV.read(p));
        let k = F::from_f64(28.0 / 23.0) * F::FRAC_1_PI;
        Prepared {
            diffuse: [0, 1, 2].map(|c| k * rd[c] * (F::ONE - rs[c])),
            rs,
            nu,
            nv,
            // Two roots, not the root of the product, which overflows from nu·nv ≈ 1.8e308.
            norm: (nu + F::ONE).sqrt() * (nv + F::ONE).sqrt() * F::from_f64(0.125) * F::FRAC_1_PI,
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        let (u, v) = tangent_frame::<F>(d.n, d.t);
        // h from the exact unit vectors: nearly opposite directions (|wi + wo| = 1e-3)
        // otherwise turn the rounded vectors' length errors into h's azimuth, which sets
        // the exponent (1.4e-11 at κ = 4.6e3 before).
        let hv = half_vector_exact::<F>(d.wi, d.wo, F::length_error(d.wi), F::length_error(d.wo));
        let cos_th = clamped_cosine::<F>(d.n, hv.h);
        let (a, b) = (hv.h.dot(u), hv.h.dot(v));
        let s2 = a * a + b * b;
        let e = (pp.nu * a * a + pp.nv * b * b) / s2;
        let e = if s2 > F::ZERO {
            e
        } else {
            F::HALF * (pp.nu + pp.nv)
        };
        // (n·h)^e / max(mu_i, mu_o) in one step: the power may underflow where the
        // quotient does not (grazing), and 0/0 must not come of a product that underflows.
        let lobe = pp.norm * cos_th.powf_over::<P>(e, max(mu_i, mu_o)) / hv.cos_b.cos;
        let lobe = if hv.defined { lobe } else { F::ZERO };
        let w = schlick_weight(hv.cos_b);
        let diffuse = coupling(mu_i) * coupling(mu_o);
        let rgb = [0, 1, 2].map(|c| {
            let fresnel = pp.rs[c] + (F::ONE - pp.rs[c]) * w;
            weighted(fresnel, lobe) + pp.diffuse[c] * diffuse
        });
        above_both(mu_i, mu_o, rgb)
    }

    /// `Rd(1 − Rs)·(1 − (1 − mu/2)^5)` exactly, plus `Rs·I(Rs = 1) + (1 − Rs)·I(Rs = 0)`
    /// drawn with the paper's half-vector sampling.
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        let (rd, rs) = (RD.read(slots), RS.read(slots));
        let importance = Importance::AnisotropicPhongHalf {
            nu: NU.read(slots),
            nv: NV.read(slots),
        };
        let diffuse = Term {
            colour: [0, 1, 2].map(|c| rd[c] * (1.0 - rs[c])),
            integral: Integral::Exact(coupling(mu)),
        };
        Some(diffuse_and_schlick_lobe(diffuse, rs, |rs_value| {
            Integral::Lobe {
                basis: basis(slots, &[(RD, 0.0), (RS, rs_value)]),
                importance,
            }
        }))
    }
}
