//! Checking user parameters against a model's spec and laying them out in kernel slots.

use ndarray::ArrayViewD;

use super::rows::Rows;
use crate::error::{BrdfError, closest, format_float, format_shape};
use crate::math::Real;
use crate::models::{ModelSpec, ParamKind, ParamSpec};

/// A parameter as given: its spec and its array (any shape; checked here).
pub struct GivenParam<'a, F> {
    pub spec: &'static ParamSpec,
    pub view: ArrayViewD<'a, F>,
}

/// A parameter that takes part in broadcasting: which spec, its array, its own batch
/// shape and whether its last axis is a colour axis.
pub struct BatchParam<'a, F> {
    pub spec: &'static ParamSpec,
    pub view: ArrayViewD<'a, F>,
    pub own_batch: Vec<usize>,
    pub has_component_axis: bool,
}

/// A parameter that varies over the batch, ready to be read block by block.
#[derive(Clone, Debug)]
pub struct VaryingParam<'a, F> {
    pub slot: usize,
    pub comps: usize,
    pub rows: Rows<'a, F>,
}

/// Parameters resolved against the spec: every slot's uniform value (defaults filled
/// in), the batch-broadcasting parameters, and list values written into their slots.
pub struct Resolved<'a, F> {
    pub uniform: Vec<F>,
    pub batch: Vec<BatchParam<'a, F>>,
}

impl<'a, F: Real> Resolved<'a, F> {
    /// Broadcasts the batch parameters together with `others` (the named batch shapes of
    /// the other inputs) and splits them into uniform and varying ones.
    pub fn broadcast(
        self,
        mut others: Vec<(&'static str, Vec<usize>)>,
    ) -> Result<ParamRows<'a, F>, BrdfError> {
        for p in &self.batch {
            others.push((p.spec.name, p.own_batch.clone()));
        }
        let batch = super::rows::broadcast_shapes(&others)?;
        let mut uniform = self.uniform;
        let mut varying = Vec::new();
        for BatchParam {
            spec: p,
            view,
            has_component_axis,
            ..
        } in self.batch
        {
            let comps = p.kind.slots();
            let rows = Rows::new(view, has_component_axis, comps, &batch);
            match rows.constant() {
                Some(row) => uniform[p.slot..p.slot + comps].copy_from_slice(&row[..comps]),
                None => varying.push(VaryingParam {
                    slot: p.slot,
                    comps,
                    rows,
                }),
            }
        }
        Ok(ParamRows {
            batch,
            uniform,
            varying,
        })
    }
}

/// Refuses the first of `names` that is not one of the model's parameters (with the
/// closest known name, if one is close).
pub fn check_known<'n>(
    spec: &'static ModelSpec,
    names: impl IntoIterator<Item = &'n str>,
) -> Result<(), BrdfError> {
    for name in names {
        if spec.param(name).is_none() {
            let known = spec.param_names();
            return Err(BrdfError::UnknownParameter {
                model: spec.name,
                name: name.to_string(),
                suggestion: closest(name, &known).map(str::to_string),
                known,
            });
        }
    }
    Ok(())
}

/// Matches `names` to the spec: unknown names, missing required parameters.
pub fn match_names<'n>(
    spec: &'static ModelSpec,
    names: impl IntoIterator<Item = &'n str>,
) -> Result<Vec<&'static ParamSpec>, BrdfError> {
    let names: Vec<&str> = names.into_iter().collect();
    check_known(spec, names.iter().copied())?;
    let found: Vec<&'static ParamSpec> = names.iter().filter_map(|n| spec.param(n)).collect();
    for p in spec.params {
        if p.default.is_none() && !found.iter().any(|f| f.name == p.name) {
            return Err(BrdfError::MissingParameter {
                model: spec.name,
                name: p.name,
            });
        }
    }
    Ok(found)
}

/// Unravels a flat C-order position into an index of `shape`.
pub fn unravel(mut pos: usize, shape: &[usize]) -> Vec<usize> {
    let mut idx = vec![0; shape.len()];
    for k in (0..shape.len()).rev() {
        idx[k] = pos % shape[k];
        pos /= shape[k];
    }
    idx
}

/// Returns the index (in `view`'s shape) of the first element, in C order, for which
/// `bad` holds. Broadcast axes (stride 0, as `numpy.broadcast_to` makes them) are looked
/// at once, with index 0: their elements are the same memory, and a broadcast view of
/// 10^12 elements is checked as fast as the array behind it.
pub fn first_bad<T: Copy>(view: &ArrayViewD<'_, T>, bad: impl Fn(T) -> bool) -> Option<Vec<usize>> {
    let mut distinct = view.view();
    for k in 0..view.ndim() {
        if view.strides()[k] == 0 && view.shape()[k] > 1 {
            distinct.collapse_axis(ndarray::Axis(k), 0);
        }
    }
    let pos = distinct.iter().position(|&x| bad(x))?;
    Some(unravel(pos, distinct.shape()))
}

/// Checks every element of `view` against the parameter's range, closed bounds widened
/// to their `f32` roundings ([`crate::models::ValidRange::admitting_f32_bounds`]).
fn check_range<F: Real>(spec: &ParamSpec, view: &ArrayViewD<'_, F>) -> Result<(), BrdfError> {
    let range = spec.range.admitting_f32_bounds();
    if let Some(index) = first_bad(view, |x: F| !range.contains(x.to_f64())) {
        let value = view[ndarray::IxDyn(&index)].to_f64();
        return Err(BrdfError::OutOfRange {
            name: spec.name.to_string(),
            value,
            index,
            valid: spec.range.describe(),
        });
    }
    Ok(())
}

/// Resolves the given parameters of `spec`: checks shapes and ranges, writes defaults
/// and list values into the uniform slots and returns the batch parameters.
pub fn resolve<'a, F: Real>(
    spec: &'static ModelSpec,
    given: Vec<GivenParam<'a, F>>,
    check_values: bool,
) -> Result<Resolved<'a, F>, BrdfError> {
    let mut uniform = vec![F::ZERO; spec.slot_count()];
    for p in spec.params {
        if let Some(d) = p.default {
            uniform[p.slot..p.slot + p.kind.slots()].fill(F::from_f64(d));
        }
    }
    let mut batch = Vec::new();
    let mut list_lengths: Vec<(&'static str, usize)> = Vec::new();
    // Lists first, so colour lists can check their length against them.
    let mut given = given;
    given.sort_by_key(|g| matches!(g.spec.kind, ParamKind::ColourList { .. }));
    for GivenParam { spec: p, view } in given {
        let shape = view.shape().to_vec();
        if check_values {
            check_range(p, &view)?;
        }
        match p.kind {
            ParamKind::Scalar => batch.push(BatchParam {
                spec: p,
                view,
                own_batch: shape,
                has_component_axis: false,
            }),
            ParamKind::Colour => {
                let last = shape.last().copied();
                match last {
                    None => batch.push(BatchParam {
                        spec: p,
                        view,
                        own_batch: vec![],
                        has_component_axis: false,
                    }),
                    Some(1) | Some(3) => batch.push(BatchParam {
                        spec: p,
                        view,
                        own_batch: shape[..shape.len() - 1].to_vec(),
                        has_component_axis: true,
                    }),
                    Some(_) => {
                        return Err(BrdfError::Shape(format!(
                            "{}: a colour is a number, an RGB triple or an array whose last \
                             axis has length 3 (or 1); got shape {} (for one grey value per \
                             element, add a trailing axis: {}[..., None])",
                            p.name,
                            format_shape(&shape),
                            p.name
                        )));
                    }
                }
            }
            ParamKind::ScalarList { max_len, ascending } => {
                if shape.len() > 1 || shape.first().is_some_and(|&n| n > max_len) {
                    return Err(BrdfError::Shape(format!(
                        "{}: expected a list of at most {max_len} numbers; got shape {}",
                        p.name,
                        format_shape(&shape)
                    )));
                }
                let values: Vec<F> = view.iter().copied().collect();
                if ascending {
                    if let Some(k) = values.windows(2).position(|w| w[1] < w[0]) {
                        return Err(BrdfError::InvalidArgument(format!(
                            "{} must be ascending: {}[{}] = {} is below {}[{}] = {}",
                            p.name,
                            p.name,
                            k + 1,
                            format_float(values[k + 1].to_f64()),
                            p.name,
                            k,
                            format_float(values[k].to_f64())
                        )));
                    }
                }
                let slots = &mut uniform[p.slot..p.slot + max_len];
                slots.fill(F::INFINITY);
                slots[..values.len()].copy_from_slice(&values);
                list_lengths.push((p.name, values.len()));
            }
            ParamKind::ColourList {
                max_len,
                one_more_than,
            } => {
                let (count, comps) = match shape.as_slice() {
                    [k] => (*k, 1),
                    [k, c] if *c == 3 || *c == 1 => (*k, *c),
                    _ => {
                        return Err(BrdfError::Shape(format!(
                            "{}: expected a list of colours, shape (k, 3) or (k,) for greys; \
                             got shape {}",
                            p.name,
                            format_shape(&shape)
                        )));
                    }
                };
                let want = list_lengths
                    .iter()
                    .find(|(name, _)| *name == one_more_than)
                    .map(|(_, len)| len + 1);
                if want != Some(count) || count > max_len {
                    return Err(BrdfError::InvalidArgument(format!(
                        "{}: needs len({one_more_than}) + 1 = {} colours; got {count}",
                        p.name,
                        want.map_or("?".to_string(), |w| w.to_string()),
                    )));
                }
                let values: Vec<F> = view.iter().copied().collect();
                for k in 0..count {
                    for c in 0..3 {
                        uniform[p.slot + 3 * k + c] =
                            values[k * comps + if comps == 1 { 0 } else { c }];
                    }
                }
            }
        }
    }
    Ok(Resolved { uniform, batch })
}

/// Parameters resolved against a batch: its shape, the uniform slots (every parameter
/// whose rows are all one value written in) and the rows of every parameter that varies.
/// The eval plan reads the varying rows block by block; [`ParamRows::slots`] reads them
/// per element (the integrator, the samplers and scenes).
pub struct ParamRows<'a, F> {
    pub batch: Vec<usize>,
    pub(super) uniform: Vec<F>,
    pub(super) varying: Vec<VaryingParam<'a, F>>,
}

impl<'a, F: Real> ParamRows<'a, F> {
    /// Checks `given` against `spec` and broadcasts the parameters together with the
    /// `others` (named batch shapes of the other inputs).
    pub fn new(
        spec: &'static ModelSpec,
        given: Vec<(&'a str, ArrayViewD<'a, F>)>,
        others: &[(&'static str, Vec<usize>)],
    ) -> Result<ParamRows<'a, F>, BrdfError> {
        let matched = match_names(spec, given.iter().map(|(name, _)| *name))?;
        let given: Vec<GivenParam<'a, F>> = matched
            .into_iter()
            .zip(given)
            .map(|(spec, (_, view))| GivenParam { spec, view })
            .collect();
        resolve(spec, given, true)?.broadcast(others.to_vec())
    }

    /// Returns the number of elements of the batch.
    pub fn count(&self) -> usize {
        self.batch.iter().product()
    }

    /// Writes the parameter slots of element `i` into `slots`.
    pub fn slots(&self, i: usize, slots: &mut Vec<F>) {
        slots.clear();
        slots.extend_from_slice(&self.uniform);
        let mut row = [F::ZERO; 3];
        for VaryingParam { slot, comps, rows } in &self.varying {
            super::engine::read_row(rows, *comps, &self.batch, i, &mut row);
            slots[*slot..*slot + *comps].copy_from_slice(&row[..*comps]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::ModelKind;
    use ndarray::{ArrayD, IxDyn};

    fn scalar(x: f64) -> ArrayD<f64> {
        ArrayD::from_elem(IxDyn(&[]), x)
    }

    #[test]
    fn unknown_and_missing_names() {
        let spec = ModelKind::TorranceSparrow.spec();
        let err = match_names(spec, ["kd", "etta"]).unwrap_err();
        assert!(
            err.to_string()
                .contains("unknown parameter \"etta\" (did you mean \"eta\"?)")
        );
        let spec = ModelKind::ToonDiffuse.spec();
        let err = match_names(spec, ["thresholds"]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "toon_diffuse: missing required parameter \"colors\""
        );
    }

    #[test]
    fn range_errors_name_value_and_index() {
        let spec = ModelKind::TorranceSparrow.spec();
        let p = ArrayD::from_shape_vec(IxDyn(&[2, 2]), vec![1.0, 2.0, -3.0, 4.0]).unwrap();
        let given = vec![GivenParam {
            spec: spec.param("p").unwrap(),
            view: p.view(),
        }];
        let err = resolve::<f64>(spec, given, true).err().unwrap();
        assert_eq!(
            err.to_string(),
            "p[1, 0] = -3.0 is out of range: must be >= 0 and finite"
        );
        let eta = scalar(0.0);
        let given = vec![GivenParam {
            spec: spec.param("eta").unwrap(),
            view: eta.view(),
        }];
        let err = resolve::<f64>(spec, given, true).err().unwrap();
        assert_eq!(
            err.to_string(),
            "eta = 0.0 is out of range: must be > 0 and finite"
        );
    }

    #[test]
    fn toon_lists_fill_slots_and_are_checked() {
        let spec = ModelKind::ToonDiffuse.spec();
        let c = ArrayD::from_shape_vec(IxDyn(&[3]), vec![0.1, 0.5, 0.9]).unwrap();
        let resolve_with = |thresholds: Vec<f64>| {
            let t = ArrayD::from_shape_vec(IxDyn(&[thresholds.len()]), thresholds).unwrap();
            let given = vec![
                GivenParam {
                    spec: spec.param("colors").unwrap(),
                    view: c.view(),
                },
                GivenParam {
                    spec: spec.param("thresholds").unwrap(),
                    view: t.view(),
                },
            ];
            resolve::<f64>(spec, given, true).map(|r| r.uniform)
        };
        let uniform = resolve_with(vec![0.2, 0.6]).ok().unwrap();
        assert_eq!(&uniform[..3], &[0.2, 0.6, f64::INFINITY]);
        assert_eq!(&uniform[7..13], &[0.1, 0.1, 0.1, 0.5, 0.5, 0.5]);
        let err = resolve_with(vec![0.6, 0.2]).err().unwrap();
        assert_eq!(
            err.to_string(),
            "thresholds must be ascending: thresholds[1] = 0.2 is below thresholds[0] = 0.6"
        );
        let err = resolve_with(vec![0.5]).err().unwrap();
        assert_eq!(
            err.to_string(),
            "colors: needs len(thresholds) + 1 = 2 colours; got 3"
        );
    }

    #[test]
    fn colour_shapes() {
        let spec = ModelKind::Lambert.spec();
        let bad = ArrayD::from_elem(IxDyn(&[4, 5]), 0.5);
        let given = vec![GivenParam {
            spec: spec.param("kd").unwrap(),
            view: bad.view(),
        }];
        let err = resolve::<f64>(spec, given, true).err().unwrap();
        assert!(
            err.to_string().starts_with("kd: a colour is a number"),
            "{err}"
        );
    }
}
