//! The models the package's tools pick when the user names none: the CLI's default table
//! and split-sum model, the plain diffuse term under a specular-only preview, the
//! benchmark's models. These are the tools' choices, not facts of the models; they live
//! here, once, and reach Python through `tool_defaults()`, so that no Python module names
//! a model.

use super::ModelKind;

/// `brdf-rs table`'s recipe when no model is named.
#[derive(Clone, Copy, Debug)]
pub struct TableDefault {
    pub model: ModelKind,
    /// The axes beyond `mu`, as `name=spec` (`brdf-rs table --axis`).
    pub axes: &'static [&'static str],
    /// The parameters, as `name=value` (`brdf-rs table --param`).
    pub params: &'static [&'static str],
}

/// The benchmark's albedo table: a model whose directional albedo at normal incidence is
/// exactly 1 with `kd = 0`, `ks = 1` over a logarithmic axis of its parameter `param`
/// from `lo` to `hi`, so that the table checks itself.
#[derive(Clone, Copy, Debug)]
pub struct AlbedoCheck {
    pub model: ModelKind,
    pub param: &'static str,
    pub lo: f64,
    pub hi: f64,
}

/// The tools' default models.
#[derive(Clone, Copy, Debug)]
pub struct ToolDefaults {
    pub table: TableDefault,
    /// `brdf-rs dfg`'s model when none is named.
    pub dfg: ModelKind,
    /// The diffuse shading term a sphere preview puts under a specular-only term so the
    /// sphere's shape shows (`brdf_rs.plot`).
    pub plain_diffuse: ModelKind,
    /// `brdf-rs bench`'s models: one per family of kernels (constant, Phong lobe,
    /// microfacet, rough diffuse).
    pub bench: &'static [ModelKind],
    pub albedo_check: AlbedoCheck,
}

/// The tools' default models.
pub const TOOL_DEFAULTS: ToolDefaults = ToolDefaults {
    table: TableDefault {
        model: ModelKind::TorranceSparrow,
        axes: &["p=log:1:10000:32"],
        params: &["kd=0", "ks=1", "eta=1.5"],
    },
    dfg: ModelKind::Ggx,
    plain_diffuse: ModelKind::LambertShading,
    bench: &[
        ModelKind::Lambert,
        ModelKind::NormalizedPhong,
        ModelKind::TorranceSparrow,
        ModelKind::Ggx,
        ModelKind::OrenNayar,
    ],
    albedo_check: AlbedoCheck {
        model: ModelKind::NormalizedPhong,
        param: "p",
        lo: 1.0,
        hi: 1e4,
    },
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::Family;
    use crate::models::spec::SceneUse;

    /// Returns the parameter name of a `name=...` entry.
    fn name_of(entry: &str) -> &str {
        entry.split_once('=').expect("name=value").0
    }

    #[test]
    fn the_defaults_fit_their_models() {
        let d = TOOL_DEFAULTS;
        let table = d.table.model.spec();
        assert_eq!(table.family, Family::A, "{}", table.name);
        for entry in d.table.axes.iter().chain(d.table.params) {
            assert!(
                table.param(name_of(entry)).is_some(),
                "{}: {entry}",
                table.name
            );
        }
        assert!(d.dfg.spec().dfg.is_some(), "{}", d.dfg.name());
        let plain = d.plain_diffuse.spec();
        assert_eq!(plain.scene, SceneUse::Diffuse, "{}", plain.name);
        assert!(plain.param("kd").is_some(), "{}: a grey kd", plain.name);
        let check = d.albedo_check.model.spec();
        assert!(
            check.param(d.albedo_check.param).is_some(),
            "{}",
            check.name
        );
        assert!(check.param("kd").is_some() && check.param("ks").is_some());
        assert!(d.albedo_check.lo < d.albedo_check.hi);
        for (i, kind) in d.bench.iter().enumerate() {
            assert!(!d.bench[..i].contains(kind), "{}", kind.name());
        }
    }
}
