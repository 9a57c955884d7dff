//! Model and parameter specs: the one table behind validation, `brdf_rs.models()`, the
//! CLI and the docs.

use super::slots::{ColourSlot, ScalarSlot};

/// Which kind of function a model computes (docs/models.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// A radiometric BRDF `f(wi, wo)` in 1/sr, cosine excluded, zero unless both
    /// directions are above the surface. These are integrated.
    A,
    /// A scan-line shading term `s(l, v)` that already includes the light's cosine.
    B,
}

impl Family {
    /// Returns `"A"` or `"B"`.
    pub fn letter(self) -> &'static str {
        match self {
            Family::A => "A",
            Family::B => "B",
        }
    }
}

/// Whether a model reads a tangent direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TangentUse {
    /// The model has no tangent; passing one is an error.
    None,
    /// The model needs `tangent=`.
    Required,
    /// The model uses a tangent when given (anisotropic models); without one it is +x
    /// (projected onto the tangent plane).
    Optional,
}

/// The shape of a parameter's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamKind {
    /// One number; may vary per element (an array broadcasting against the batch).
    Scalar,
    /// An RGB colour: a number (grey), a triple, or an array with a trailing axis of 3
    /// (or 1) broadcasting against the batch.
    Colour,
    /// A list of up to `max_len` numbers, the same for the whole batch; `ascending`
    /// requires a non-decreasing list. Unused slots are filled with `+inf`.
    ScalarList { max_len: usize, ascending: bool },
    /// A list of colours, the same for the whole batch, with exactly one more entry
    /// than the list parameter named `one_more_than`.
    ColourList {
        max_len: usize,
        one_more_than: &'static str,
    },
}

impl ParamKind {
    /// Returns how many float slots the parameter occupies.
    pub const fn slots(self) -> usize {
        match self {
            ParamKind::Scalar => 1,
            ParamKind::Colour => 3,
            ParamKind::ScalarList { max_len, .. } => max_len,
            ParamKind::ColourList { max_len, .. } => 3 * max_len,
        }
    }

    /// Returns whether the value may vary per element.
    pub const fn may_vary(self) -> bool {
        matches!(self, ParamKind::Scalar | ParamKind::Colour)
    }

    /// Returns the kind's name as `brdf_rs.models()` reports it.
    pub fn name(self) -> &'static str {
        match self {
            ParamKind::Scalar => "scalar",
            ParamKind::Colour => "colour",
            ParamKind::ScalarList { .. } => "scalar list",
            ParamKind::ColourList { .. } => "colour list",
        }
    }
}

/// A closed, open or half-open interval of valid values (always finite values).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValidRange {
    pub min: f64,
    pub max: f64,
    pub min_open: bool,
    pub max_open: bool,
}

impl ValidRange {
    /// `[0, inf)`, finite.
    pub const NON_NEGATIVE: ValidRange = ValidRange {
        min: 0.0,
        max: f64::INFINITY,
        min_open: false,
        max_open: true,
    };
    /// `(0, inf)`, finite.
    pub const POSITIVE: ValidRange = ValidRange {
        min: 0.0,
        max: f64::INFINITY,
        min_open: true,
        max_open: true,
    };
    /// `[0, 1]`.
    pub const UNIT: ValidRange = ValidRange {
        min: 0.0,
        max: 1.0,
        min_open: false,
        max_open: false,
    };
    /// `[-1, 1]`.
    pub const SIGNED_UNIT: ValidRange = ValidRange {
        min: -1.0,
        max: 1.0,
        min_open: false,
        max_open: false,
    };
    /// `[1e-7, 1e7]`: a microfacet roughness (α² stays a normal number in `f32`).
    pub const ROUGHNESS: ValidRange = ValidRange {
        min: 1e-7,
        max: 1e7,
        min_open: false,
        max_open: false,
    };
    /// `[0, pi/2]`.
    pub const QUARTER_TURN: ValidRange = ValidRange {
        min: 0.0,
        max: std::f64::consts::FRAC_PI_2,
        min_open: false,
        max_open: false,
    };

    /// Returns whether `x` is a valid value (never true for NaN or infinity).
    pub fn contains(&self, x: f64) -> bool {
        if !x.is_finite() {
            return false;
        }
        let above = if self.min_open {
            x > self.min
        } else {
            x >= self.min
        };
        let below = if self.max_open {
            x < self.max
        } else {
            x <= self.max
        };
        above && below
    }

    /// Returns the range the parameter checks apply (`eval`'s, a scene file's): a closed
    /// bound taken as the widest of itself and its rounding to `f32` (the same in both
    /// dtypes, so that a value valid in one is valid in the other): `float32(π/2)` is above
    /// π/2, and must pass where π/2 is the documented maximum.
    pub fn admitting_f32_bounds(self) -> ValidRange {
        let mut range = self;
        let rounded = |b: f64| f64::from(b as f32);
        if !range.min_open && range.min.is_finite() {
            range.min = range.min.min(rounded(range.min));
        }
        if !range.max_open && range.max.is_finite() {
            range.max = range.max.max(rounded(range.max));
        }
        range
    }

    /// Returns whether the parameter checks admit `x` ([`ValidRange::admitting_f32_bounds`]).
    pub fn admits(&self, x: f64) -> bool {
        self.admitting_f32_bounds().contains(x)
    }

    /// Returns the range as a phrase: `">= 0 and finite"`, `"in [0, 1]"`.
    pub fn describe(&self) -> String {
        if self.max == f64::INFINITY {
            let op = if self.min_open { ">" } else { ">=" };
            format!("{op} {} and finite", self.min)
        } else {
            let lo = if self.min_open { '(' } else { '[' };
            let hi = if self.max_open { ')' } else { ']' };
            format!("in {lo}{}, {}{hi}", self.min, self.max)
        }
    }
}

/// One parameter of a model.
#[derive(Clone, Copy, Debug)]
pub struct ParamSpec {
    /// The docs/models.md name (`kd`, `ks`, `p`, `eta`, `sigma`, ...).
    pub name: &'static str,
    pub kind: ParamKind,
    /// Default value (a grey level for colours); `None` means required.
    pub default: Option<f64>,
    pub range: ValidRange,
    /// One line: what the parameter means.
    pub doc: &'static str,
    /// First float slot of the parameter in the kernel's raw parameter vector (from the
    /// model's [`param_slots!`](crate::param_slots) layout).
    pub slot: usize,
}

/// `kd`: the diffuse colour.
pub const fn kd(default: f64, slot: ColourSlot) -> ParamSpec {
    ParamSpec {
        name: "kd",
        kind: ParamKind::Colour,
        default: Some(default),
        range: ValidRange::NON_NEGATIVE,
        doc: "diffuse colour (RGB, >= 0)",
        slot: slot.first(),
    }
}

/// `ks`: the specular colour.
pub const fn ks(default: f64, slot: ColourSlot) -> ParamSpec {
    ParamSpec {
        name: "ks",
        kind: ParamKind::Colour,
        default: Some(default),
        range: ValidRange::NON_NEGATIVE,
        doc: "specular colour (RGB, >= 0)",
        slot: slot.first(),
    }
}

/// `p`: the cosine exponent.
pub const fn exponent(slot: ScalarSlot) -> ParamSpec {
    ParamSpec {
        name: "p",
        kind: ParamKind::Scalar,
        default: Some(32.0),
        range: ValidRange::NON_NEGATIVE,
        doc: "cosine exponent (shininess); larger is a narrower lobe",
        slot: slot.first(),
    }
}

/// `sigma`: the Oren-Nayar roughness.
pub const fn sigma(slot: ScalarSlot) -> ParamSpec {
    ParamSpec {
        name: "sigma",
        kind: ParamKind::Scalar,
        default: Some(0.5),
        range: ValidRange::QUARTER_TURN,
        doc: "roughness: standard deviation of the facet slope angle, radians",
        slot: slot.first(),
    }
}

/// `alpha`: a microfacet roughness.
pub const fn roughness(
    name: &'static str,
    default: f64,
    slot: ScalarSlot,
    doc: &'static str,
) -> ParamSpec {
    ParamSpec {
        name,
        kind: ParamKind::Scalar,
        default: Some(default),
        range: ValidRange::ROUGHNESS,
        doc,
        slot: slot.first(),
    }
}

/// `ks` as Schlick's F0: a colour in [0, 1].
pub const fn f0(default: f64, slot: ColourSlot) -> ParamSpec {
    ParamSpec {
        name: "ks",
        kind: ParamKind::Colour,
        default: Some(default),
        range: ValidRange::UNIT,
        doc: "F0: specular reflectance at normal incidence (RGB, in [0, 1]; 1 gives F = 1)",
        slot: slot.first(),
    }
}

/// A model's spec: everything a user or a tool needs to know about it.
#[derive(Debug)]
pub struct ModelSpec {
    /// The name users pass (`"torrance_sparrow"`).
    pub name: &'static str,
    pub family: Family,
    /// One line: what the model is.
    pub summary: &'static str,
    /// The formula, as docs/models.md writes it.
    pub formula: &'static str,
    /// Where it comes from (book / paper equation numbers).
    pub source: &'static str,
    pub params: &'static [ParamSpec],
    pub tangent: TangentUse,
    /// Whether `f(wi, wo) = f(wo, wi)` (family A only; family-B terms are not BRDFs).
    pub reciprocal: bool,
    /// The parameters the model's value is linear in with no constant term: the value is
    /// exactly 0 when they are all 0 (a scene skips such a term). `None` where no such set
    /// exists (`blinn_phong_fresnel` and the microfacet models: `ks` is F0, and
    /// `F = F0 + (1 − F0)(1 − cos_b)^5` does not vanish at F0 = 0; Ashikhmin-Shirley's
    /// diffuse term is scaled by `1 − Rs`).
    pub weights: Option<&'static [&'static str]>,
    /// How a scene material uses the model.
    pub scene: SceneUse,
    /// The roughness axis of its split-sum (DFG) table, for models with Schlick's F0.
    pub dfg: Option<DfgAxis>,
    /// Whether it has energy tables `E(mu, alpha)`, `E_avg(alpha)` at `kd = 0`, `ks = 1`:
    /// Kulla and Conty's (`F = 1`) for the microfacet models, albedo-scaling tables for
    /// the sheen models. `E` is the albedo seen from the view: the directional albedo
    /// for a reciprocal lobe, the closed form [`super::Kernel::sheen_view_albedo`] for a
    /// lobe that is not reciprocal (which must have one).
    pub energy_table: bool,
    /// Whether a scene may stack it over a base as a sheen layer: a sheen lobe whose
    /// parameters are `kd`, `ks` (the colour) and `alpha` (the roughness), whose albedo
    /// seen from the view is the layer's `E` (the base is scaled by `1 − E`): integrated
    /// for a reciprocal lobe, the kernel's closed form for one that is not.
    pub sheen_layer: bool,
    /// Its `normalization="exact"`, for models that have one.
    pub exact: Option<ExactNormalization>,
    /// Whether the model transmits: defined on the whole sphere of `wi` and `wo` (the
    /// rough dielectrics), not zero unless both directions are above the surface as
    /// every other family-A model is. Its albedo integrates over the whole sphere, and
    /// scenes (which shade reflection only) refuse it.
    pub transmission: bool,
}

/// A model's `normalization="exact"`: a factor `c` of the lobe's shape parameters
/// multiplies a colour so that the lobe's directional albedo (no diffuse term, unit
/// colour, Fresnel factor 1) peaks at exactly 1. The factors are computed in Python
/// (`brdf_rs._normalization`, which derives each and gives its accuracy), elementwise
/// on the parameters before the kernel runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactNormalization {
    pub factor: ExactFactor,
    /// The shape parameters `c` is a function of, in the order the factor takes them (its
    /// shape is theirs, broadcast).
    pub params: &'static [&'static str],
    /// The colour parameter `c` multiplies.
    pub scales: &'static str,
}

/// How an exact normalization's factor is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExactFactor {
    /// The lobe as written already peaks at 1: `c = 1`, the parameters are left alone.
    One,
    /// The Blinn-Phong lobe `(p+8)/(8π)·cos^p θh`, whose albedo peaks at normal incidence:
    /// `c(p) = (p+2)(p+4)/((p+8)(p + 2^(−p/2)))` relative to `(p+8)/(8π)`.
    BlinnClosedForm,
    /// Defined at normal incidence and interpolated in the shipped table of that name
    /// (over the logarithms of two roughnesses).
    Table(&'static str),
}

impl ExactFactor {
    /// The name `brdf_rs.models()` gives it (`"one"`, `"blinn_closed_form"`, `"table"`).
    pub fn name(self) -> &'static str {
        match self {
            ExactFactor::One => "one",
            ExactFactor::BlinnClosedForm => "blinn_closed_form",
            ExactFactor::Table(_) => "table",
        }
    }
}

/// How a family-A model's diffuse term is evaluated on its own (a scene's diffuse or
/// specular component alone).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DiffuseTerm {
    /// The whole model is diffuse (`lambert`, `oren_nayar`).
    Whole,
    /// The diffuse term is `lambert` with `kd` scaled by this factor: 1 for the models
    /// that add `kd/π`, π for the BRDF Summary's non-normalized models that add `kd`.
    Lambert(f64),
    /// The model has no diffuse term (`ggx_ms`, `beckmann_ms`): all of it is specular.
    Absent,
    /// The diffuse term depends on the specular parameters (`ashikhmin_shirley`: `Rd` is
    /// scaled by `1 − Rs`): the specular term alone is the model with `Rd = 0`, the
    /// diffuse term alone is not one kernel.
    Coupled,
}

impl DiffuseTerm {
    /// The name `brdf_rs.models()` gives it.
    pub fn name(self) -> &'static str {
        match self {
            DiffuseTerm::Whole => "whole",
            DiffuseTerm::Lambert(_) => "lambert",
            DiffuseTerm::Absent => "absent",
            DiffuseTerm::Coupled => "coupled",
        }
    }
}

/// Where a model goes in a scene material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SceneUse {
    /// Family A: the material's `brdf`, with its diffuse term split off as given.
    Brdf(DiffuseTerm),
    /// Family B: a shading term in the material's `diffuse` slot, its `specular` slot,
    /// or either (`both`).
    Diffuse,
    Specular,
    Both,
}

impl SceneUse {
    /// The slot's name in `brdf_rs.models()` (`"brdf"`, `"diffuse"`, `"specular"`,
    /// `"both"`).
    pub fn slot(self) -> &'static str {
        match self {
            SceneUse::Brdf(_) => "brdf",
            SceneUse::Diffuse => "diffuse",
            SceneUse::Specular => "specular",
            SceneUse::Both => "both",
        }
    }
}

/// The roughness axis of a split-sum table: the parameter, and the CLI's default axis
/// (`"mid:lo:hi:n"` for cell midpoints of a linear range, `"log:lo:hi:n"` for a
/// logarithmic one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DfgAxis {
    pub param: &'static str,
    pub axis: &'static str,
}

impl ModelSpec {
    /// What a model is unless its spec says otherwise: family A, no tangent, reciprocal,
    /// no weight set, no split-sum axis, no energy tables, no sheen layer, no exact
    /// normalization, not transmitting. A spec names its own facts and takes the rest
    /// with `..ModelSpec::PLAIN`. The name, the texts, the parameters and the scene use
    /// here are placeholders that every model sets (a test checks the first four).
    pub const PLAIN: ModelSpec = ModelSpec {
        name: "",
        family: Family::A,
        summary: "",
        formula: "",
        source: "",
        params: &[],
        tangent: TangentUse::None,
        reciprocal: true,
        weights: None,
        scene: SceneUse::Brdf(DiffuseTerm::Absent),
        dfg: None,
        energy_table: false,
        sheen_layer: false,
        exact: None,
        transmission: false,
    };

    /// Returns the number of float slots of the raw parameter vector.
    pub fn slot_count(&self) -> usize {
        self.params.iter().map(|p| p.kind.slots()).sum()
    }

    /// Returns the parameter called `name`.
    pub fn param(&self, name: &str) -> Option<&'static ParamSpec> {
        self.params.iter().find(|p| p.name == name)
    }

    /// Returns the parameter names.
    pub fn param_names(&self) -> Vec<&'static str> {
        self.params.iter().map(|p| p.name).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_reject_non_finite_and_describe_themselves() {
        assert!(ValidRange::NON_NEGATIVE.contains(0.0));
        assert!(!ValidRange::NON_NEGATIVE.contains(f64::INFINITY));
        assert!(!ValidRange::POSITIVE.contains(0.0));
        assert!(!ValidRange::UNIT.contains(f64::NAN));
        assert_eq!(ValidRange::POSITIVE.describe(), "> 0 and finite");
        assert_eq!(ValidRange::UNIT.describe(), "in [0, 1]");
    }

    #[test]
    fn checks_admit_the_f32_roundings_of_closed_bounds() {
        let half_pi_f32 = f64::from(std::f64::consts::FRAC_PI_2 as f32);
        assert!(half_pi_f32 > std::f64::consts::FRAC_PI_2);
        assert!(!ValidRange::QUARTER_TURN.contains(half_pi_f32));
        assert!(ValidRange::QUARTER_TURN.admits(half_pi_f32));
        assert!(!ValidRange::QUARTER_TURN.admits(half_pi_f32 * (1.0 + f64::EPSILON)));
        // Open and infinite bounds are as written.
        assert!(!ValidRange::POSITIVE.admits(0.0));
        assert!(!ValidRange::NON_NEGATIVE.admits(f64::INFINITY));
    }
}
