//! `beckmann_ms`: Kulla & Conty's multiple-scattering lobe for `beckmann`; the same
//! construction as [`super::ggx_ms`] on Beckmann's energy table.

use super::albedo::Term;
use super::ggx_ms::{Prepared, TABLE_ALPHA, albedo_ms, eval_ms, prepare_ms};
use super::spec::{
    self, DiffuseTerm, ModelSpec, ParamKind, ParamSpec, SceneUse,
};
// `prepare_ms` reads the layout of `ggx_ms`, which this model shares.
pub use super::ggx_ms::{ALPHA, KS, SLOTS};
use super::tables::BECKMANN;
use super::{Directions, Kernel, ParamSource};
use crate::math::{PowUnit, Real};

/// The Beckmann multiple-scattering kernel.
pub struct BeckmannMs;

pub static SPEC: ModelSpec = ModelSpec {
    name: "beckmann_ms",
    summary: "Kulla-Conty multiple-scattering lobe restoring the energy beckmann loses",
    formula: "f = (1−E(mu_i))(1−E(mu_o))/(π(1−E_avg))·F_avg²E_avg/(1−F_avg(1−E_avg)), \
              F_avg = ks + (1−ks)/21",
    source: "Kulla & Conty 2017 (Revisiting Physically Based Shading at Imageworks)",
    params: &[
        spec::f0(1.0, KS),
        ParamSpec {
            name: "alpha",
            kind: ParamKind::Scalar,
            default: Some(0.5),
            range: TABLE_ALPHA,
            doc: "roughness α of the beckmann lobe it completes (table range [1e-3, 1])",
            slot: ALPHA.first(),
        },
    ],
    scene: SceneUse::Brdf(DiffuseTerm::Absent),
    ..ModelSpec::PLAIN
};

impl Kernel for BeckmannMs {
    type Prepared<F: Real> = Prepared<F>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        prepare_ms(&BECKMANN, p)
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        eval_ms(&BECKMANN, pp, d)
    }

    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        Some(albedo_ms(&BECKMANN, slots, mu))
    }
}
