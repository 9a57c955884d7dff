//! The closed set of models: one file per model, the [`Kernel`] trait they implement, the
//! [`ModelKind`] enum that names them and the parameter specs that drive validation,
//! `brdf_rs.models()`, the CLI and the docs.
//!
//! A model file holds the model's whole definition: its spec (parameters, ranges,
//! defaults, source), the derived constants it prepares once per parameter set, and its
//! evaluation. The batch engine calls [`Kernel::eval`] per element inside loops that are
//! compiled per instruction set; models therefore write straight-line, branch-free code
//! (selects, not early returns).

pub mod albedo;
pub mod defaults;
pub mod dielectric;
pub mod fresnel;
pub mod lobes;
pub mod microfacet_fresnel;
pub mod sheen;
pub mod slots;
pub mod spec;
pub mod strata;
pub mod tables;

pub use spec::{Family, ModelSpec, ParamKind, ParamSpec, TangentUse, ValidRange};

use crate::error::{BrdfError, closest};
use crate::math::geometry::{Cosine, WideCosine};
use crate::math::{PowUnit, Real, SeriesPow};

/// The unit directions one evaluation sees. `wi` points toward the light, `wo` toward the
/// viewer, both away from the surface; `n` is the unit normal; `t` the unit tangent (for
/// models that take one, otherwise unspecified).
#[derive(Clone, Copy, Debug)]
pub struct Directions<F: Real> {
    pub wi: F::V3,
    pub wo: F::V3,
    pub n: F::V3,
    pub t: F::V3,
}

/// What [`Kernel::eval_wide`] gets beyond the normalized directions: the cosines with
/// extended exponents and the input vectors as given (`f64`).
#[derive(Clone, Copy, Debug)]
pub struct WideRow {
    pub mu_i: WideCosine,
    pub mu_o: WideCosine,
    pub wi: [f64; 3],
    pub wo: [f64; 3],
}

/// Where a kernel reads its raw parameter values: the spec's slots, one float each
/// (a colour takes three consecutive slots).
pub trait ParamSource<F: Real> {
    /// Returns the value in `slot`.
    fn scalar(&self, slot: usize) -> F;
    /// Returns the colour starting at `slot`.
    #[inline(always)]
    fn colour(&self, slot: usize) -> [F; 3] {
        [
            self.scalar(slot),
            self.scalar(slot + 1),
            self.scalar(slot + 2),
        ]
    }
}

impl<F: Real> ParamSource<F> for [F] {
    #[inline(always)]
    fn scalar(&self, slot: usize) -> F {
        self[slot]
    }
}

/// A registered model's spec: [`declare_models!`] implements it for each model's kernel
/// with the `SPEC` of the model's file, so the registration line ties the kernel to its
/// spec and no file writes that twice.
pub trait Registered {
    /// The model's spec.
    const SPEC: &'static ModelSpec;
}

/// A reflectance model the batch engine can evaluate.
pub trait Kernel: Registered + 'static {
    /// Constants derived once per parameter set (normalizations, Fresnel R0, ...).
    type Prepared<F: Real>: Copy + Send + Sync;
    /// Returns the derived constants for the parameters in `p`.
    fn prepare<F: Real, P: ParamSource<F> + ?Sized>(p: &P) -> Self::Prepared<F>;
    /// Returns the model's RGB value for one set of unit directions: `f(wi, wo)` in 1/sr
    /// for family A (cosine excluded), the shading term `s(l, v)` for family B; powers
    /// `x^p` from the table-free [`SeriesPow`], which vectorizes in any loop.
    #[inline(always)]
    fn eval<F: Real>(prepared: &Self::Prepared<F>, d: &Directions<F>) -> [F; 3] {
        Self::eval_with::<F, SeriesPow>(prepared, d)
    }
    /// [`Kernel::eval`] with powers computed by `P` ([`PowUnit`]): the caller chooses the
    /// one that is fastest in its loop (the eval engine: [`crate::math::TablePow`]).
    fn eval_with<F: Real, P: PowUnit>(prepared: &Self::Prepared<F>, d: &Directions<F>) -> [F; 3];

    /// Whether [`Kernel::eval_with`] raises anything to a power through its `P`: the eval
    /// engine compiles the fast tier's loops (`precision="fast"`, [`crate::math::FastPow`])
    /// only for such models, and evaluates the others, which it would not change, with the
    /// accurate loops.
    const POWERS: bool = false;

    /// Whether [`Kernel::eval_with`] divides out the rounded unit vectors' length errors
    /// in the accurate tier and leaves them out under [`crate::math::FastPow`] (the
    /// microfacet lobes, [`ggx::length_errors`]): the eval engine then compiles fast-tier
    /// loops for the model even without powers.
    const LENGTH_CORRECTIONS: bool = false;

    /// Whether the kernel's one power can be computed apart from the rest
    /// ([`Kernel::power_stage`], [`Kernel::finish_power`]): the eval engine then runs the
    /// model over a block in three passes (the bases, the powers, the rest), which
    /// computes [`Kernel::eval_with`]'s bits, and faster (the power's long chain does not
    /// share a loop body, and its registers, with the geometry). The stage functions'
    /// defaults are placeholders for kernels without it.
    const SPLIT_POWER: bool = false;

    /// The first part of [`Kernel::eval_with`] for a [`Kernel::SPLIT_POWER`] kernel: the
    /// power's base and exponent, and what [`Kernel::finish_power`] needs of the rest.
    #[inline(always)]
    fn power_stage<F: Real>(_prepared: &Self::Prepared<F>, _d: &Directions<F>) -> PowerStage<F> {
        PowerStage {
            base: Cosine {
                cos: F::ZERO,
                one_minus: F::ONE,
            },
            p: F::ZERO,
            keep: [F::ZERO; STAGE_KEEP],
        }
    }

    /// The rest of [`Kernel::eval_with`] given [`Kernel::power_stage`]'s stage and the
    /// power `stage.base^stage.p` (as [`PowUnit::pow_unit`] returns it, before any flush):
    /// `finish_power(pp, &stage, P::pow_unit(..))` is `eval_with::<F, P>` bit for bit.
    #[inline(always)]
    fn finish_power<F: Real>(
        _prepared: &Self::Prepared<F>,
        _stage: &PowerStage<F>,
        _power: F,
    ) -> [F; 3] {
        [F::ZERO; 3]
    }

    /// Whether [`Kernel::eval_with`] is [`Kernel::eval_undivided`] divided by
    /// [`Kernel::divisor`] (a factor of `wi` alone whose scalar code, a table lookup, would
    /// keep the loop it sits in from vectorizing): the eval engine then computes the two
    /// in separate passes over a block of uniform parameters, the same bits. The two
    /// functions' defaults are placeholders for kernels without it. For a kernel without
    /// [`Kernel::SPLIT_POWER`] (whose passes are the power's).
    const DIVIDED: bool = false;

    /// [`Kernel::eval_with`] before the division by [`Kernel::divisor`], for a
    /// [`Kernel::DIVIDED`] kernel.
    #[inline(always)]
    fn eval_undivided<F: Real, P: PowUnit>(
        _prepared: &Self::Prepared<F>,
        _d: &Directions<F>,
    ) -> [F; 3] {
        [F::ZERO; 3]
    }

    /// What a [`Kernel::DIVIDED`] kernel divides [`Kernel::eval_undivided`] by:
    /// `eval_with` is `eval_undivided(..).map(|v| v / divisor(..))` bit for bit.
    #[inline(always)]
    fn divisor<F: Real>(_prepared: &Self::Prepared<F>, _d: &Directions<F>) -> F {
        F::ONE
    }

    /// What [`Kernel::divisor`] can compute once for many rows of one parameter set (a
    /// table's rows blended at the parameters' node), for [`Kernel::divisor_in`]; the
    /// engine asks for it per task of uniform parameters. Empty by default: the engine
    /// then calls [`Kernel::divisor`].
    fn divisor_cache<F: Real>(_prepared: &Self::Prepared<F>) -> Vec<f64> {
        Vec::new()
    }

    /// The part of [`Kernel::divisor`] to compute for every lane of a block in a loop
    /// that vectorizes (branch-free), before [`Kernel::divisor_in`] finishes it.
    #[inline(always)]
    fn divisor_stage<F: Real>(_prepared: &Self::Prepared<F>, _d: &Directions<F>) -> [f64; 2] {
        [0.0; 2]
    }

    /// [`Kernel::divisor`] given a non-empty [`Kernel::divisor_cache`] and the row's
    /// [`Kernel::divisor_stage`], bit for bit.
    #[inline(always)]
    fn divisor_in<F: Real>(
        prepared: &Self::Prepared<F>,
        _cache: &[f64],
        d: &Directions<F>,
        _stage: [f64; 2],
    ) -> F {
        Self::divisor(prepared, d)
    }

    /// Whether the value depends on the size of a cosine `n·wi` or `n·wo` below the
    /// normal range (2^-1022) in `f64`, so that [`Kernel::eval_wide`] is needed where one
    /// is (Ward's `1/sqrt(mu_i·mu_o)`). Most models only need its sign, which
    /// normalization keeps (up to the limits in docs/numerics.md).
    const WIDE_COSINES: bool = false;

    /// [`Kernel::eval`] given `mu_i = n·wi` and `mu_o = n·wo` with extended exponents
    /// ([`wide_cosine`](crate::math::geometry::wide_cosine) of the input vectors as given,
    /// with the normalized `n`). The batch engine calls it for `f64` rows where one of
    /// them is nonzero and below 2^-1022, or rounded to 0 from such a value, if
    /// [`Kernel::WIDE_COSINES`]; `d`
    /// holds the normalized vectors as usual, and the wide cosines' signs decide the side
    /// of the surface.
    fn eval_wide<F: Real>(prepared: &Self::Prepared<F>, d: &Directions<F>, _w: &WideRow) -> [F; 3] {
        Self::eval(prepared, d)
    }

    /// Returns the model's directional albedo at incidence `mu` as `Σ colour_k · I_k` for
    /// the raw parameter slots (see [`albedo`]); `None` for family-B shading terms, which
    /// are not integrated.
    fn albedo_terms(_slots: &[f64], _mu: f64) -> Option<Vec<albedo::Term>> {
        None
    }

    /// The sampler of a transmitting model ([`ModelSpec::transmission`]) for the raw
    /// parameter slots: `brdf_rs.sample` and `brdf_rs.pdf` draw from it over the whole
    /// sphere instead of the mixture of [`Kernel::sampling_terms`]. `None` for the rest.
    fn transmission_sampler(
        _slots: &[f64],
    ) -> Option<crate::sampling::dielectric::DielectricSampler> {
        None
    }

    /// For a transmitting model: the factor its value carries over the single-scattering
    /// interface of its sampler for light arriving at cosine `mu` from above, the same
    /// for every `wo` (the albedo integrator multiplies the interface's closed-form
    /// weights by it). 1 for the interfaces themselves.
    fn interface_scale(_slots: &[f64], _mu: f64) -> f64 {
        1.0
    }

    /// For a sheen layer's model: the lobe's albedo seen from the view at unit colour
    /// (`kd = 0`, `ks = 1`, roughness `alpha`), `∫ f(wi, wo)·(n·wi) dωi` over the light at
    /// `n·wo = mu_o`, where the model gives it in closed form; `None` where it must be
    /// integrated (for a reciprocal model that is the directional albedo). A kernel
    /// answers `Some` for every `alpha` and `mu_o` or `None` for all
    /// ([`ModelKind::view_albedo_closed_form`]).
    fn sheen_view_albedo(_alpha: f64, _mu_o: f64) -> Option<f64> {
        None
    }

    /// The decomposition `brdf_rs.sample` draws from: [`Kernel::albedo_terms`], except
    /// for models whose albedo terms split a lobe into strata for the integrator
    /// ([`strata`]); those return the whole lobes here (a sampler draws whole lobes).
    fn sampling_terms(slots: &[f64], mu: f64) -> Option<Vec<albedo::Term>> {
        Self::albedo_terms(slots, mu)
    }
}

/// How many values [`PowerStage::keep`] holds.
pub const STAGE_KEEP: usize = 4;

/// What [`Kernel::power_stage`] hands on: the power's base and exponent, and values of
/// the rest of the evaluation ([`Kernel::finish_power`] reads them).
#[derive(Clone, Copy, Debug)]
pub struct PowerStage<F> {
    pub base: Cosine<F>,
    pub p: F,
    pub keep: [F; STAGE_KEEP],
}

/// Something done with a kernel type chosen at run time: `ModelKind::visit` calls
/// `visit::<K>()` for the model's kernel, giving static dispatch once per batch.
pub trait KernelVisitor {
    type Output;
    fn visit<K: Kernel>(self) -> Self::Output;
}

/// Registers the models: one line per model, `Variant => module::Kernel`, declares its
/// module (the file `models/<module>.rs`) and its place in [`ModelKind`].
macro_rules! declare_models {
    ($($variant:ident => $module:ident :: $ty:ident),* $(,)?) => {
        $(pub mod $module;)*

        $(impl Registered for $module::$ty {
            const SPEC: &'static ModelSpec = &$module::SPEC;
        })*

        /// Every model brdf-rs knows, in the order `brdf_rs.models()` lists them.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum ModelKind { $($variant),* }

        impl ModelKind {
            /// All models.
            pub const ALL: &'static [ModelKind] = &[$(ModelKind::$variant),*];

            /// Returns the model's spec.
            pub fn spec(self) -> &'static ModelSpec {
                match self { $(ModelKind::$variant => <$module::$ty as Registered>::SPEC),* }
            }

            /// Returns the model's slot layout as its file declares it.
            #[cfg(test)]
            fn slot_decls(self) -> &'static [slots::SlotDecl] {
                match self { $(ModelKind::$variant => $module::SLOTS),* }
            }

            /// Returns whether the model's kernel raises anything to a power
            /// ([`Kernel::POWERS`]).
            pub fn powers(self) -> bool {
                match self { $(ModelKind::$variant => <$module::$ty as Kernel>::POWERS),* }
            }

            /// Returns whether `precision="fast"` computes the model differently from the
            /// accurate tier: it has powers ([`Kernel::POWERS`], in either width) or length
            /// corrections the fast tier leaves out ([`Kernel::LENGTH_CORRECTIONS`], in
            /// `f64`).
            pub fn fast_tier(self) -> bool {
                match self {
                    $(ModelKind::$variant => {
                        <$module::$ty as Kernel>::POWERS
                            || <$module::$ty as Kernel>::LENGTH_CORRECTIONS
                    }),*
                }
            }

            /// [`Kernel::sheen_view_albedo`] of the model's kernel.
            pub fn sheen_view_albedo(self, alpha: f64, mu_o: f64) -> Option<f64> {
                match self {
                    $(ModelKind::$variant => {
                        <$module::$ty as Kernel>::sheen_view_albedo(alpha, mu_o)
                    }),*
                }
            }

            /// Returns whether the kernel gives its albedo seen from the view in closed form
            /// ([`Kernel::sheen_view_albedo`], which answers for every argument or none):
            /// its energy tables and sheen layers use it rather than integrate.
            pub fn view_albedo_closed_form(self) -> bool {
                self.sheen_view_albedo(0.5, 0.5).is_some()
            }

            /// Calls the visitor with the model's kernel type.
            pub fn visit<V: KernelVisitor>(self, visitor: V) -> V::Output {
                match self { $(ModelKind::$variant => visitor.visit::<$module::$ty>()),* }
            }
        }
    };
}

declare_models! {
    Lambert => lambert::Lambert,
    OrenNayar => oren_nayar::OrenNayar,
    Phong => phong::Phong,
    ModifiedPhong => modified_phong::ModifiedPhong,
    NormalizedPhong => normalized_phong::NormalizedPhong,
    BlinnPhong => blinn_phong::BlinnPhong,
    ModifiedBlinnPhong => modified_blinn_phong::ModifiedBlinnPhong,
    NormalizedBlinnPhong => normalized_blinn_phong::NormalizedBlinnPhong,
    BlinnPhongFresnel => blinn_phong_fresnel::BlinnPhongFresnel,
    TorranceSparrow => torrance_sparrow::TorranceSparrow,
    Ggx => ggx::Ggx,
    GgxMs => ggx_ms::GgxMs,
    Beckmann => beckmann::Beckmann,
    BeckmannMs => beckmann_ms::BeckmannMs,
    GgxConductor => ggx_conductor::GgxConductor,
    BeckmannConductor => beckmann_conductor::BeckmannConductor,
    GgxF82 => ggx_f82::GgxF82,
    BeckmannF82 => beckmann_f82::BeckmannF82,
    GgxGenSchlick => ggx_gen_schlick::GgxGenSchlick,
    BeckmannGenSchlick => beckmann_gen_schlick::BeckmannGenSchlick,
    GgxDielectric => ggx_dielectric::GgxDielectric,
    GgxDielectricMs => ggx_dielectric_ms::GgxDielectricMs,
    BeckmannDielectric => beckmann_dielectric::BeckmannDielectric,
    Ward => ward::Ward,
    AshikhminShirley => ashikhmin_shirley::AshikhminShirley,
    CharlieSheen => charlie_sheen::CharlieSheen,
    CharlieSheenNeubelt => charlie_sheen_neubelt::CharlieSheenNeubelt,
    AshikhminCloth => ashikhmin_cloth::AshikhminCloth,
    ZeltnerSheen => zeltner_sheen::ZeltnerSheen,
    LambertShading => lambert_shading::LambertShading,
    OrenNayarShading => oren_nayar_shading::OrenNayarShading,
    ToonDiffuse => toon_diffuse::ToonDiffuse,
    PhongSpecular => phong_specular::PhongSpecular,
    BlinnSpecular => blinn_specular::BlinnSpecular,
    ToonSpecular => toon_specular::ToonSpecular,
    KajiyaKay => kajiya_kay::KajiyaKay,
}

impl ModelKind {
    /// Returns the model called `name`, or an error listing the known names with a
    /// close-match suggestion.
    pub fn from_name(name: &str) -> Result<ModelKind, BrdfError> {
        if let Some(kind) = ModelKind::ALL.iter().find(|k| k.spec().name == name) {
            return Ok(*kind);
        }
        let known: Vec<&'static str> = ModelKind::ALL.iter().map(|k| k.spec().name).collect();
        Err(BrdfError::UnknownModel {
            name: name.to_string(),
            suggestion: closest(name, &known).map(str::to_string),
            known,
        })
    }

    /// Returns the model's name.
    pub fn name(self) -> &'static str {
        self.spec().name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_resolve() {
        for kind in ModelKind::ALL {
            assert_eq!(ModelKind::from_name(kind.name()).unwrap(), *kind);
        }
        let err = ModelKind::from_name("torrance_sparow").unwrap_err();
        assert!(
            err.to_string()
                .contains("did you mean \"torrance_sparrow\""),
            "{err}"
        );
    }

    /// An energy table's `E` is the albedo seen from the view: the integrator's
    /// directional albedo only for a reciprocal lobe, otherwise the kernel's closed form.
    #[test]
    fn energy_tables_of_lobes_that_are_not_reciprocal_have_a_closed_form() {
        for kind in ModelKind::ALL {
            let spec = kind.spec();
            if spec.energy_table && !spec.reciprocal {
                assert!(kind.view_albedo_closed_form(), "{}", spec.name);
            }
        }
        assert!(ModelKind::ZeltnerSheen.view_albedo_closed_form());
        assert!(!ModelKind::CharlieSheen.view_albedo_closed_form());
    }

    /// [`ModelSpec::PLAIN`]'s placeholders are set by every model, and a model's family
    /// and scene use agree (family A is a BRDF in a scene, family B a shading term).
    #[test]
    fn every_spec_sets_what_the_plain_spec_leaves_open() {
        for kind in ModelKind::ALL {
            let spec = kind.spec();
            for (field, text) in [
                ("name", spec.name),
                ("summary", spec.summary),
                ("formula", spec.formula),
                ("source", spec.source),
            ] {
                assert!(!text.is_empty(), "{:?}: no {field}", kind);
            }
            assert!(!spec.params.is_empty(), "{}: no parameters", spec.name);
            assert_eq!(
                spec.family == spec::Family::A,
                matches!(spec.scene, spec::SceneUse::Brdf(_)),
                "{}: family and scene use disagree",
                spec.name
            );
        }
    }

    #[test]
    fn slot_layouts_match_the_specs() {
        for kind in ModelKind::ALL {
            let spec = kind.spec();
            let decls = kind.slot_decls();
            assert_eq!(decls.len(), spec.params.len(), "{}", spec.name);
            let mut next = 0;
            for (p, decl) in spec.params.iter().zip(decls) {
                let at = format!("{}.{} ({})", spec.name, p.name, decl.name);
                assert!(
                    decl.name.eq_ignore_ascii_case(p.name),
                    "{at}: named after another"
                );
                assert_eq!(decl.first, next, "{at}: not where the previous one ends");
                assert_eq!(
                    p.slot, decl.first,
                    "{at}: the spec's slot is not the layout's"
                );
                assert_eq!(
                    decl.width,
                    p.kind.slots(),
                    "{at}: a slot type of another kind"
                );
                if p.kind == ParamKind::Colour {
                    assert_eq!(decl.width, 3, "{at}");
                }
                next += decl.width;
            }
            assert_eq!(spec.slot_count(), next, "{}", spec.name);
        }
    }
}
