//! `ggx_dielectric_ms`: `ggx_dielectric` with the energy its single scattering loses
//! restored by Turquin's scaling (Turquin 2019, "Practical multiple scattering
//! compensation for microfacet models"; Blender Cycles' glass BSDF does the same with
//! its `ggx_glass_E` tables).
//!
//! `f(wi, wo) = f_ggx_dielectric(wi, wo) / E(|mu_i|, alpha, r_i)`, where `E` is the total
//! albedo (reflection + transmission) of `ggx_dielectric`'s white interface
//! (`ks = kt = 1`) for light arriving at `wi`, and `r_i` the relative index seen from
//! `wi`'s side (`eta` above, `1/eta` below). So the albedo from every incidence is
//! `(ks·R + kt·T)/E`: with `ks = kt = 1` it is 1 (the white furnace) up to the table's
//! interpolation error, and the split between reflection and transmission is the single
//! scattering's. `E` is read from a table computed by brdf-rs itself
//! ([`super::tables::DielectricEnergy`]). The factor depends on `wi` alone, so the
//! model is not reciprocal even in the dielectrics' form with the `eta²` factors, and
//! sampling it is sampling `ggx_dielectric` (the same directions and densities, the
//! weights divided by `E`). `eta = 1` is the straight-through delta, as for
//! `ggx_dielectric` (`E = 1` there). `alpha` in [1e-3, 1].

use super::dielectric::{self, ALPHA, DIELECTRIC_SPEC, ETA};
use super::ggx_dielectric::GgxDielectric;
use super::ggx_ms::TABLE_ALPHA;
use super::spec::{ModelSpec, ParamSpec};
use super::tables::{DielectricNode, GGX_DIELECTRIC};
use super::{Directions, Kernel, ParamSource};
use crate::math::{PowUnit, Real, Vector3};
use crate::sampling::dielectric::DielectricSampler;
// The rough dielectrics' layout (`ks`, `kt`, `eta`, `alpha`).
pub use super::dielectric::SLOTS;

/// The cosine `n·wi` and sine `|n × wi|` of the light's incidence, in `f64`.
#[inline(always)]
fn incidence<F: Real>(d: &Directions<F>) -> (f64, f64) {
    let sin_i = d.n.cross(d.wi).length_squared().sqrt();
    (d.n.dot(d.wi).to_f64(), sin_i.to_f64())
}

/// `ggx_dielectric` divided by its white interface's albedo.
pub struct GgxDielectricMs;

/// The rough dielectrics' parameters with `alpha` in the table's range.
const PARAMS: [ParamSpec; 4] = {
    let mut params = dielectric::params(
        "roughness α of the ggx_dielectric interface it completes (table range [1e-3, 1])",
    );
    params[3].range = TABLE_ALPHA;
    params
};

pub static SPEC: ModelSpec = ModelSpec {
    name: "ggx_dielectric_ms",
    summary: "Rough GGX dielectric (ggx_dielectric) with the energy its single scattering \
              loses restored by Turquin's scaling: f/E(mu_i), E the white interface's \
              total albedo",
    formula: "f = f_ggx_dielectric(wi, wo)/E(|mu_i|, alpha, r_i), E = R + T of \
              ggx_dielectric with ks = kt = 1 for light at wi, r_i = eta above, 1/eta below \
              (tabulated); E = 1 at eta = 1",
    source: "Turquin 2019 (Practical multiple scattering compensation for microfacet \
             models); Walter, Marschner, Li & Torrance 2007 (rough dielectrics)",
    params: &PARAMS,
    ..DIELECTRIC_SPEC
};

/// Derived constants: `ggx_dielectric`'s, and the node of `alpha` and `eta` on the table.
#[derive(Clone, Copy)]
pub struct Prepared<F: Real> {
    interface: <GgxDielectric as Kernel>::Prepared<F>,
    node: DielectricNode,
}

impl Kernel for GgxDielectricMs {
    type Prepared<F: Real> = Prepared<F>;

    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        Prepared {
            interface: GgxDielectric::prepare(p),
            node: GGX_DIELECTRIC.node(ALPHA.read(p).to_f64(), ETA.read(p).to_f64()),
        }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let e = Self::divisor(pp, d);
        Self::eval_undivided::<F, P>(pp, d).map(|v| v / e)
    }

    const DIVIDED: bool = true;

    /// The interface's value.
    #[inline(always)]
    fn eval_undivided<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        GgxDielectric::eval_with::<F, P>(&pp.interface, d)
    }

    /// `E` for light at `wi`, from the table.
    #[inline(always)]
    fn divisor<F: Real>(pp: &Prepared<F>, d: &Directions<F>) -> F {
        let (mu_i, sin_i) = incidence(d);
        F::from_f64(GGX_DIELECTRIC.energy(&pp.node, mu_i, sin_i))
    }

    /// The table's rows blended at the node of `alpha` and `eta`, once.
    fn divisor_cache<F: Real>(pp: &Prepared<F>) -> Vec<f64> {
        GGX_DIELECTRIC.column(&pp.node)
    }

    /// The incidence coordinate on the table, in double width.
    #[inline(always)]
    fn divisor_stage<F: Real>(pp: &Prepared<F>, d: &Directions<F>) -> [f64; 2] {
        let (mu_i, sin_i) = incidence(d);
        let (hi, lo) = GGX_DIELECTRIC.incidence(&pp.node, mu_i, sin_i);
        [hi, lo]
    }

    /// `E` at the incidence coordinate, read from the blended rows.
    #[inline(always)]
    fn divisor_in<F: Real>(
        pp: &Prepared<F>,
        cache: &[f64],
        d: &Directions<F>,
        stage: [f64; 2],
    ) -> F {
        let mu_i = d.n.dot(d.wi).to_f64();
        F::from_f64(GGX_DIELECTRIC.energy_at(cache, &pp.node, mu_i, (stage[0], stage[1])))
    }

    /// `ggx_dielectric`'s sampler: the factor is the same for every `wo`.
    fn transmission_sampler(slots: &[f64]) -> Option<DielectricSampler> {
        GgxDielectric::transmission_sampler(slots)
    }

    /// `1/E` for light from above at cosine `mu`.
    fn interface_scale(slots: &[f64], mu: f64) -> f64 {
        let node = GGX_DIELECTRIC.node(ALPHA.read(slots), ETA.read(slots));
        1.0 / GGX_DIELECTRIC.energy(&node, mu, ((1.0 - mu) * (1.0 + mu)).sqrt())
    }
}
