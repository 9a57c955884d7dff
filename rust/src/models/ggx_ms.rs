//! `ggx_ms`: Kulla & Conty's multiple-scattering lobe for `ggx` (SIGGRAPH 2017 course,
//! "Revisiting Physically Based Shading at Imageworks").
//!
//! `f_ms = (1 − E(mu_i))(1 − E(mu_o)) / (π (1 − E_avg)) · F_ms`, where `E(mu, alpha)` is
//! GGX's directional albedo with F = 1, `E_avg = 2 ∫ E(mu) mu dmu`, and for a Schlick
//! F0 = `ks` the colour factor `F_ms = F_avg² E_avg / (1 − F_avg (1 − E_avg))`,
//! `F_avg = F0 + (1 − F0)/21` (1 for F = 1). `ggx + ggx_ms` with `ks = 1` has albedo 1 at
//! every incidence (the white furnace), up to the table's interpolation error. The loss
//! `1 − E` and `1 − E_avg` are interpolated from a table computed by brdf-rs itself
//! (`scripts/gen_tables.py`; layout and accuracy in [`super::tables::EnergyTable`]):
//! never negative, and the lobe's albedo is exactly `(1 − E(mu))·F_ms` of the
//! interpolated `E`. `alpha` in [1e-3, 1].

use super::albedo::{Integral, Term};
use super::slots::{ColourSlot, ScalarSlot};
use super::spec::{
    self, DiffuseTerm, ModelSpec, ParamKind, ParamSpec, SceneUse, ValidRange,
};
use super::tables::{EnergyTable, GGX};
use super::{Directions, Kernel, ParamSource, Registered};
use std::marker::PhantomData;
use crate::math::geometry::above_both;
use crate::math::{PowUnit, Real, Vector3};

/// The multiple-scattering lobe on the energy table `T` reads (`ggx_ms`,
/// [`super::beckmann_ms`]): one kernel, the table the only difference.
pub struct MultipleScattering<T>(PhantomData<T>);

/// The energy table of a [`MultipleScattering`] lobe.
pub trait LossTable: 'static {
    const TABLE: &'static EnergyTable;
}

/// GGX's energy table.
pub struct GgxLoss;

impl LossTable for GgxLoss {
    const TABLE: &'static EnergyTable = &GGX;
}

/// The GGX multiple-scattering kernel.
pub type GgxMs = MultipleScattering<GgxLoss>;

/// The table roughness range.
pub const TABLE_ALPHA: ValidRange = ValidRange {
    min: 1e-3,
    max: 1.0,
    min_open: false,
    max_open: false,
};

crate::param_slots! {
    KS: ColourSlot,
    ALPHA: ScalarSlot,
}

pub static SPEC: ModelSpec = ModelSpec {
    name: "ggx_ms",
    summary: "Kulla-Conty multiple-scattering lobe restoring the energy ggx loses",
    params: &params("roughness α of the ggx lobe it completes (table range [1e-3, 1])"),
    ..MULTIPLE_SCATTERING_SPEC
};

/// The spec fields both multiple-scattering lobes share: the formula, the source and no
/// diffuse term. A model's spec names its own fields (its parameters from [`params`])
/// and takes these with `..MULTIPLE_SCATTERING_SPEC`.
pub const MULTIPLE_SCATTERING_SPEC: ModelSpec = ModelSpec {
    formula: "f = (1−E(mu_i))(1−E(mu_o))/(π(1−E_avg))·F_avg²E_avg/(1−F_avg(1−E_avg)), \
              F_avg = ks + (1−ks)/21",
    source: "Kulla & Conty 2017 (Revisiting Physically Based Shading at Imageworks)",
    scene: SceneUse::Brdf(DiffuseTerm::Absent),
    ..ModelSpec::PLAIN
};

/// The parameters of a multiple-scattering lobe: `ks` as F0 (default 1) and `alpha` in
/// the table's range, with its doc line.
pub const fn params(alpha_doc: &'static str) -> [ParamSpec; 2] {
    [
        spec::f0(1.0, KS),
        ParamSpec {
            name: "alpha",
            kind: ParamKind::Scalar,
            default: Some(0.5),
            range: TABLE_ALPHA,
            doc: alpha_doc,
            slot: ALPHA.first(),
        },
    ]
}

/// Prepared constants of a multiple-scattering lobe on a table.
#[derive(Clone, Copy)]
pub struct Prepared<F> {
    alpha: super::tables::AlphaNode<F>,
    /// `F_ms / (π (1 − E_avg))` per channel.
    scale: [F; 3],
}

impl<T: LossTable> Kernel for MultipleScattering<T>
where
    Self: Registered,
{
    type Prepared<F: Real> = Prepared<F>;

    /// The alpha node on the table and the channel scale.
    #[inline(always)]
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Prepared<F> {
        let f0 = KS.read(p);
        let alpha = T::TABLE.alpha_node(ALPHA.read(p));
        let avg_loss = T::TABLE.avg_loss(alpha);
        let e_avg = F::ONE - avg_loss;
        let norm = F::FRAC_1_PI / avg_loss;
        let scale = f0.map(|f| {
            let f_avg = f + (F::ONE - f) * F::from_f64(1.0 / 21.0);
            f_avg * f_avg * e_avg / (F::ONE - f_avg * avg_loss) * norm
        });
        Prepared { alpha, scale }
    }

    #[inline(always)]
    fn eval_with<F: Real, P: PowUnit>(pp: &Prepared<F>, d: &Directions<F>) -> [F; 3] {
        let mu_i = d.n.dot(d.wi);
        let mu_o = d.n.dot(d.wo);
        // sinθ from the cross product: exactly 0 for a direction along n, whatever its
        // rounding to unit length (see `loss_sine`).
        let sin_i = d.n.cross(d.wi).length_squared().sqrt();
        let sin_o = d.n.cross(d.wo).length_squared().sqrt();
        let loss = T::TABLE.loss_sine(mu_i, sin_i, pp.alpha)
            * T::TABLE.loss_sine(mu_o, sin_o, pp.alpha);
        above_both(mu_i, mu_o, pp.scale.map(|s| s * loss))
    }

    /// `(1 − E(mu))·F_ms`, exactly.
    fn albedo_terms(slots: &[f64], mu: f64) -> Option<Vec<Term>> {
        let pp = Self::prepare::<f64, [f64]>(slots);
        let avg_loss = T::TABLE.avg_loss(pp.alpha);
        let loss = T::TABLE.loss(mu, pp.alpha);
        // scale·π(1 − E_avg) is F_ms; the lobe's albedo is (1 − E(mu))·F_ms.
        let f_ms = pp.scale.map(|s| s * std::f64::consts::PI * avg_loss);
        Some(vec![Term {
            colour: f_ms,
            integral: Integral::Exact(loss),
        }])
    }
}
