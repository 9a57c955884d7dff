//! Model and parameter specs: the one table behind validation, `brdf_rs.models()`, the
//! CLI and the docs.

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
    /// First float slot of the parameter in the kernel's raw parameter vector.
    pub slot: usize,
}

/// `kd`: the diffuse colour.
pub const fn kd(default: f64, slot: usize) -> ParamSpec {
    ParamSpec {
        name: "kd",
        kind: ParamKind::Colour,
        default: Some(default),
        range: ValidRange::NON_NEGATIVE,
        doc: "diffuse colour (RGB, >= 0)",
        slot,
    }
}

/// `ks`: the specular colour.
pub const fn ks(default: f64, slot: usize) -> ParamSpec {
    ParamSpec {
        name: "ks",
        kind: ParamKind::Colour,
        default: Some(default),
        range: ValidRange::NON_NEGATIVE,
        doc: "specular colour (RGB, >= 0)",
        slot,
    }
}

/// `p`: the cosine exponent.
pub const fn exponent(slot: usize) -> ParamSpec {
    ParamSpec {
        name: "p",
        kind: ParamKind::Scalar,
        default: Some(32.0),
        range: ValidRange::NON_NEGATIVE,
        doc: "cosine exponent (shininess); larger is a narrower lobe",
        slot,
    }
}

/// `sigma`: the Oren-Nayar roughness.
pub const fn sigma(slot: usize) -> ParamSpec {
    ParamSpec {
        name: "sigma",
        kind: ParamKind::Scalar,
        default: Some(0.5),
        range: ValidRange::QUARTER_TURN,
        doc: "roughness: standard deviation of the facet slope angle, radians",
        slot,
    }
}

/// `alpha`: a microfacet roughness.
pub const fn roughness(
    name: &'static str,
    default: f64,
    slot: usize,
    doc: &'static str,
) -> ParamSpec {
    ParamSpec {
        name,
        kind: ParamKind::Scalar,
        default: Some(default),
        range: ValidRange::ROUGHNESS,
        doc,
        slot,
    }
}

/// `ks` as Schlick's F0: a colour in [0, 1].
pub const fn f0(default: f64, slot: usize) -> ParamSpec {
    ParamSpec {
        name: "ks",
        kind: ParamKind::Colour,
        default: Some(default),
        range: ValidRange::UNIT,
        doc: "F0: specular reflectance at normal incidence (RGB, in [0, 1]; 1 gives F = 1)",
        slot,
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
}

impl ModelSpec {
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
}
