//! Sheen layers: a sheen model stacked over a material's family-A model by albedo
//! scaling (docs/scenes.md, "Sheen layers").
//!
//! A layer is a sheen model (`ks`, its colour, and `alpha`, its roughness; no diffuse
//! term of its own) and a coverage `weight` in [0, 1]. The layered BRDF is
//!
//! `f = weight·f_sheen(l, v) + (1 − weight·E(mu_o, alpha))·f_base(l, v)`
//!
//! with `E(mu, alpha)` the sheen lobe's directional albedo at unit colour and `mu_o = n·v`
//! the cosine of the view direction: OpenPBR's fuzz layer in its albedo-scaling form.
//! The transmission through the layer is grey (the sheen colour tints only what the
//! layer reflects), and at each view direction the layered albedo is
//! `weight·ks·E + (1 − weight·E)·A_base`, at most 1 when `ks <= 1` and `A_base <= 1`.
//!
//! `E` is integrated by the library's own albedo integrator at [`NODES`] values of `mu`
//! (spaced evenly in `sqrt(mu)` from 0 to 1, both ends included, denser toward grazing
//! angles where `E` changes fastest)
//! once per model and roughness, kept in a process-wide cache, and interpolated linearly
//! per pixel-light pair.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use crate::error::BrdfError;
use crate::integrate::cells::CellGrid;
use crate::integrate::{AlbedoOptions, CellResult, Progress, albedo};
use crate::models::ModelKind;

use super::shading::Term;

/// The models a sheen layer takes: those whose spec says `sheen_layer` (the sheen and
/// cloth models, whose parameters are `kd`, `ks` and `alpha`, and whose albedo seen from
/// the view is integrated or known in closed form).
pub fn layer_models() -> impl Iterator<Item = ModelKind> {
    ModelKind::ALL
        .iter()
        .copied()
        .filter(|k| k.spec().sheen_layer)
}

/// Values of `mu` at which a layer's albedo table is integrated.
pub const NODES: usize = 64;

/// Samples per node of a layer's albedo table (randomized QMC: standard errors of a few
/// 1e-4, far below the table's interpolation error at grazing angles).
pub const SAMPLES: u64 = 1 << 12;

/// Tables kept at most in the process-wide cache (it is emptied when full).
const CACHE_LIMIT: usize = 256;

/// A sheen layer as described in a scene: the sheen model's term (its `kd` is 0) and the
/// layer's coverage weight.
#[derive(Clone, Debug, PartialEq)]
pub struct SheenLayer {
    pub term: Term,
    pub weight: f64,
}

impl SheenLayer {
    /// Checks that the model is a sheen model ([`layer_models`]), that its `kd` is 0 (the
    /// base's diffuse term lies under the layer) and that `weight` is in [0, 1].
    pub fn new(term: Term, weight: f64) -> Result<SheenLayer, BrdfError> {
        if !term.kind.spec().sheen_layer {
            let names: Vec<&str> = layer_models().map(|k| k.name()).collect();
            return Err(BrdfError::InvalidArgument(format!(
                "sheen.model: {} is not a sheen model; a sheen layer takes: {}",
                term.kind.name(),
                names.join(", ")
            )));
        }
        let kd = term.param_slots("kd");
        if term.slots[kd].iter().any(|&x| x != 0.0) {
            return Err(BrdfError::InvalidArgument(
                "sheen.kd: a sheen layer has no diffuse term of its own (the base's lies \
                 under it)"
                    .into(),
            ));
        }
        if !(0.0..=1.0).contains(&weight) {
            return Err(BrdfError::InvalidArgument(format!(
                "sheen.weight: expected a number in [0, 1] (the layer's coverage); got {weight:?}"
            )));
        }
        Ok(SheenLayer { term, weight })
    }

    /// The layer's roughness.
    pub fn alpha(&self) -> f64 {
        self.term.slots[self.term.param_slots("alpha")][0]
    }

    /// Whether the layer changes nothing: no coverage.
    pub fn is_absent(&self) -> bool {
        self.weight == 0.0
    }

    /// The sheen term weighted by the coverage: `weight·ks`.
    pub fn weighted_term(&self) -> Term {
        let mut t = self.term.clone();
        let ks = t.param_slots("ks");
        for x in &mut t.slots[ks] {
            *x *= self.weight;
        }
        t
    }
}

/// A layer ready to scale its base: `1 − weight·E(mu_o)` per pixel-light pair.
#[derive(Clone, Debug)]
pub struct Scaling {
    weight: f32,
    table: Arc<[f32]>,
}

impl Scaling {
    /// Builds (or takes from the cache) the layer's albedo table.
    pub fn prepare(layer: &SheenLayer) -> Result<Scaling, BrdfError> {
        Ok(Scaling {
            weight: layer.weight as f32,
            table: table(layer.term.kind, layer.alpha())?,
        })
    }

    /// `E(mu)` interpolated (linearly in `sqrt(mu)`); `mu` is clamped to [0, 1] (NaN
    /// reads as 0).
    #[inline(always)]
    pub fn albedo(&self, mu: f32) -> f32 {
        let mu = if mu > 0.0 { mu.min(1.0) } else { 0.0 };
        let x = (mu.sqrt() * (NODES - 1) as f32).clamp(0.0, (NODES - 1) as f32);
        let i = (x as usize).min(NODES - 2);
        let t = x - i as f32;
        let (a, b) = (self.table[i], self.table[i + 1]);
        a + t * (b - a)
    }

    /// The factor of the base: `1 − weight·E(mu_o)`.
    #[inline(always)]
    pub fn factor(&self, mu_o: f32) -> f32 {
        1.0 - self.weight * self.albedo(mu_o)
    }
}

/// The `mu` of node `k`: evenly spaced in `sqrt(mu)` from 0 to 1, so that normal
/// incidence is a node rather than a clamp. Node 0 integrates at `mu` = 1e-6, the limit
/// toward grazing incidence (at exactly 0 the albedo is 0 by definition, as `f` is).
pub fn node(k: usize) -> f64 {
    let u = (k as f64 / (NODES - 1) as f64).max(1e-3);
    u * u
}

type Key = (ModelKind, u64);

fn cache() -> &'static Mutex<HashMap<Key, Arc<[f32]>>> {
    static CACHE: std::sync::OnceLock<Mutex<HashMap<Key, Arc<[f32]>>>> = std::sync::OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Returns the albedo table of `kind` at roughness `alpha` (`kd = 0`, `ks = 1`), from the
/// cache or integrated now, each value held to [0, 1]: the Charlie lobes' albedo exceeds
/// 1 at grazing angles for small roughness (docs/models.md), and the base's factor
/// `1 − weight·E` stops at 0 there rather than turning negative.
pub fn table(kind: ModelKind, alpha: f64) -> Result<Arc<[f32]>, BrdfError> {
    let key = (kind, alpha.to_bits());
    if let Some(t) = cache().lock().ok().and_then(|c| c.get(&key).cloned()) {
        return Ok(t);
    }
    // The closed form where the model has one (a non-reciprocal lobe's albedo over the
    // light is not the integrator's, which is over the view).
    let closed: Option<Vec<f64>> = (0..NODES)
        .map(|k| kind.sheen_view_albedo(alpha, node(k)))
        .collect();
    let values = match closed {
        Some(values) => values,
        None => integrate_table(kind, alpha)?,
    };
    let held = |x: f64| if x > 0.0 { x.min(1.0) } else { 0.0 };
    let t: Arc<[f32]> = values.iter().map(|&x| held(x) as f32).collect();
    if let Ok(mut c) = cache().lock() {
        if c.len() >= CACHE_LIMIT {
            c.clear();
        }
        c.insert(key, t.clone());
    }
    Ok(t)
}

/// Integrates `E(mu)` at the [`NODES`] nodes with the library's albedo integrator.
pub fn integrate_table(kind: ModelKind, alpha: f64) -> Result<Vec<f64>, BrdfError> {
    use ndarray::{ArrayD, IxDyn};
    let mu = ArrayD::from_shape_vec(IxDyn(&[NODES]), (0..NODES).map(node).collect())
        .map_err(|e| BrdfError::InvalidArgument(e.to_string()))?;
    let kd = ArrayD::from_elem(IxDyn(&[]), 0.0);
    let ks = ArrayD::from_elem(IxDyn(&[]), 1.0);
    let alpha = ArrayD::from_elem(IxDyn(&[]), alpha);
    let given = vec![
        ("kd", kd.view()),
        ("ks", ks.view()),
        ("alpha", alpha.view()),
    ];
    let grid = CellGrid::new(kind, mu.view(), None, given, None)?;
    let options = AlbedoOptions {
        samples: SAMPLES,
        ..Default::default()
    };
    let mut out = vec![CellResult::default(); NODES];
    albedo(kind, &grid, &options, &Progress::default(), &mut out)?;
    Ok(out.iter().map(|r| r.value[0]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::Family;

    #[test]
    fn layer_models_share_the_sheen_parameters() {
        assert!(layer_models().count() >= 3);
        for kind in layer_models() {
            let spec = kind.spec();
            assert_eq!(spec.family, Family::A);
            // The layer's E: integrated (reciprocal lobes with energy tables) or known.
            assert!(
                (spec.energy_table && spec.reciprocal) || kind.view_albedo_closed_form(),
                "{}",
                kind.name()
            );
            assert_eq!(spec.param_names(), ["kd", "ks", "alpha"], "{}", kind.name());
        }
    }

    #[test]
    fn tables_are_albedos_held_to_one_and_cached() {
        // The Charlie lobe's own albedo passes 1 at grazing angles when it is sharp.
        let raw = integrate_table(ModelKind::CharlieSheen, 1e-3).unwrap();
        assert!(raw[0] > 1.0, "{raw:?}");
        for kind in layer_models() {
            for alpha in [1e-3, 0.05, 0.5, 1.0] {
                let t = table(kind, alpha).unwrap();
                assert_eq!(t.len(), NODES);
                assert!(t.iter().all(|&e| (0.0..=1.0).contains(&e)), "{t:?}");
                assert!(Arc::ptr_eq(&t, &table(kind, alpha).unwrap()));
            }
        }
        let s = Scaling {
            weight: 1.0,
            table: table(ModelKind::CharlieSheen, 0.3).unwrap(),
        };
        for mu in [f32::NAN, -1.0, 0.0, 1e-30, 0.5, 1.0, 2.0, f32::INFINITY] {
            let f = s.factor(mu);
            assert!((0.0..=1.0).contains(&f), "{mu}: {f}");
        }
        let sharp = Scaling {
            weight: 1.0,
            table: table(ModelKind::CharlieSheen, 1e-3).unwrap(),
        };
        assert_eq!(sharp.factor(1e-6), 0.0);
        // At the nodes the interpolation returns the table (normal incidence included).
        for k in 1..NODES {
            let mu = node(k) as f32;
            assert!((s.albedo(mu) - s.table[k]).abs() < 1e-5, "{k}");
        }
        assert_eq!(s.albedo(1.0), s.table[NODES - 1]);
        assert_eq!(node(NODES - 1), 1.0);
        assert_eq!(s.albedo(0.0), s.table[0]);
    }
}
