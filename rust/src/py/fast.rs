//! The fast path of `brdf_rs.eval` and `brdf_rs.Model.eval`: the common call, read
//! straight from the Python objects with none of the Python layer's conversions.
//!
//! It takes directions that are float64 or float32 NumPy arrays (any shape and layout,
//! native byte order) or lists and tuples of three Python floats or ints, parameters
//! that are Python numbers, flat lists of them or float64 arrays, and an `out` of the
//! result's dtype. Anything else (other dtypes, mixed widths, nested lists, NumPy
//! scalars, huge ints) returns `None`, and the caller takes the general path, which
//! converts it. What the fast path takes converts there without an error and to the
//! same values, so both paths reach the core with the same arrays: every result and
//! every error is the general path's.

use ndarray::{ArrayD, ArrayViewD, IxDyn};
use numpy::{Element, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use super::run_plan;
use crate::error::BrdfError;
use crate::eval::{self, EvalInputs, EvalOptions, Precision};
use crate::math::Real;
use crate::models::ModelKind;

/// Integers up to 2^53 in size convert to `f64` exactly, as NumPy converts them.
const EXACT_INT: i64 = 1 << 53;

/// One Python float, or an int that converts to `f64` exactly; `None` for anything else
/// (a bool, a NumPy scalar, a float subclass, a huge int).
fn number(obj: &Bound<'_, PyAny>) -> Option<f64> {
    if obj.is_exact_instance_of::<PyFloat>() {
        return Some(obj.cast::<PyFloat>().ok()?.value());
    }
    if obj.is_exact_instance_of::<PyInt>() {
        let v: i64 = obj.extract().ok()?;
        return (-EXACT_INT..=EXACT_INT).contains(&v).then_some(v as f64);
    }
    None
}

/// A flat list or tuple of numbers (see [`number`]), at most `max_len` long.
fn numbers(obj: &Bound<'_, PyAny>, max_len: usize) -> Option<Vec<f64>> {
    let mut values = Vec::new();
    if let Ok(list) = obj.cast::<PyList>() {
        if list.len() > max_len {
            return None;
        }
        for item in list.iter() {
            values.push(number(&item)?);
        }
    } else if let Ok(tuple) = obj.cast::<PyTuple>() {
        if tuple.len() > max_len {
            return None;
        }
        for item in tuple.iter() {
            values.push(number(&item)?);
        }
    } else {
        return None;
    }
    Some(values)
}

/// A direction argument as the fast path takes it.
enum Direction<'py> {
    Absent,
    F64(PyReadonlyArrayDyn<'py, f64>),
    F32(PyReadonlyArrayDyn<'py, f32>),
    /// A list or tuple of three numbers (float64, as NumPy reads it).
    Row([f64; 3]),
}

impl<'py> Direction<'py> {
    fn of(obj: &Bound<'py, PyAny>) -> Option<Direction<'py>> {
        if obj.is_none() {
            return Some(Direction::Absent);
        }
        if let Ok(a) = obj.cast::<PyArrayDyn<f64>>() {
            return viewable(a).then(|| a.try_readonly().ok().map(Direction::F64))?;
        }
        if let Ok(a) = obj.cast::<PyArrayDyn<f32>>() {
            return viewable(a).then(|| a.try_readonly().ok().map(Direction::F32))?;
        }
        let row = numbers(obj, 3)?;
        <[f64; 3]>::try_from(row).ok().map(Direction::Row)
    }
}

/// The four direction arguments (`wi`, `wo`, `n`, `tangent`), if the fast path takes
/// them, with the compute dtype: float32 when every given one is a float32 array.
/// `wi` and `wo` must be given (the general path names the missing one).
struct Directions<'py> {
    given: [Direction<'py>; 4],
    float32: bool,
}

impl<'py> Directions<'py> {
    fn of(args: [&Bound<'py, PyAny>; 4]) -> Option<Directions<'py>> {
        let mut given = [const { Direction::Absent }; 4];
        for (slot, arg) in given.iter_mut().zip(args) {
            *slot = Direction::of(arg)?;
        }
        if matches!(given[0], Direction::Absent) || matches!(given[1], Direction::Absent) {
            return None;
        }
        let f32s = given
            .iter()
            .filter(|d| matches!(d, Direction::F32(_)))
            .count();
        let absent = given
            .iter()
            .filter(|d| matches!(d, Direction::Absent))
            .count();
        match f32s {
            0 => Some(Directions {
                given,
                float32: false,
            }),
            k if k + absent == 4 => Some(Directions {
                given,
                float32: true,
            }),
            _ => None, // mixed widths: NumPy's promotion, in the general path
        }
    }

    fn views_f64(&self) -> [Option<ArrayViewD<'_, f64>>; 4] {
        std::array::from_fn(|i| match &self.given[i] {
            Direction::F64(a) => Some(a.as_array()),
            Direction::Row(r) => Some(ArrayViewD::from_shape(IxDyn(&[3]), &r[..]).ok()?),
            _ => None,
        })
    }

    fn views_f32(&self) -> [Option<ArrayViewD<'_, f32>>; 4] {
        std::array::from_fn(|i| match &self.given[i] {
            Direction::F32(a) => Some(a.as_array()),
            _ => None,
        })
    }
}

/// The `out` argument, if the fast path takes it: `None` or an array of dtype `F`
/// (any other object, and an array of another dtype, are refused by the general path).
fn out_array<'py, F: Element>(
    out: &Bound<'py, PyAny>,
) -> Option<Option<Bound<'py, PyArrayDyn<F>>>> {
    if out.is_none() {
        return Some(None);
    }
    let a = out.cast::<PyArrayDyn<F>>().ok()?;
    viewable(a).then(|| Some(a.clone()))
}

/// Whether rust-numpy can view the array: at most 32 dimensions (NumPy 2 allows 64, and a
/// view of more panics). The general path refuses larger ones, naming the argument.
fn viewable<T: Element>(a: &Bound<'_, PyArrayDyn<T>>) -> bool {
    a.ndim() <= 32
}

/// `normalized` and `check` as the general path reads them, and the tier (`precision`,
/// checked by the Python layer: an unknown name is the general path's error).
fn options(
    normalized: &Bound<'_, PyAny>,
    check: &Bound<'_, PyAny>,
    precision: &str,
) -> Option<EvalOptions> {
    Some(EvalOptions {
        normalized: normalized.extract().ok()?,
        check: check.extract().ok()?,
        check_params: true,
        precision: Precision::from_name(precision).ok()?,
    })
}

/// A parameter value as the fast path takes it.
enum Param<'py> {
    /// A number or a flat list of numbers: float64 values of that shape.
    Values(ArrayD<f64>),
    Array(PyReadonlyArrayDyn<'py, f64>),
}

fn param<'py>(value: &Bound<'py, PyAny>) -> Option<Param<'py>> {
    if let Some(x) = number(value) {
        return Some(Param::Values(ArrayD::from_elem(IxDyn(&[]), x)));
    }
    if let Ok(a) = value.cast::<PyArrayDyn<f64>>() {
        return viewable(a).then(|| a.try_readonly().ok().map(Param::Array))?;
    }
    // Lists of parameters are short (colours, toon thresholds): a long list is an array
    // of per-element values, converted by the general path.
    let values = numbers(value, 64)?;
    Some(Param::Values(
        ArrayD::from_shape_vec(IxDyn(&[values.len()]), values).ok()?,
    ))
}

impl Param<'_> {
    fn view(&self) -> ArrayViewD<'_, f64> {
        match self {
            Param::Values(a) => a.view(),
            Param::Array(a) => a.as_array(),
        }
    }
}

/// `brdf_rs.eval` with `normalization="approximate"` (the Python layer checks that), or
/// `None` where the general path must convert an argument.
#[pyfunction]
#[pyo3(signature = (model, wi, wo, n, tangent, params, normalized, check, out, precision="accurate"))]
#[allow(clippy::too_many_arguments)]
pub fn eval_fast<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyAny>,
    wi: &Bound<'py, PyAny>,
    wo: &Bound<'py, PyAny>,
    n: &Bound<'py, PyAny>,
    tangent: &Bound<'py, PyAny>,
    params: &Bound<'py, PyDict>,
    normalized: &Bound<'py, PyAny>,
    check: &Bound<'py, PyAny>,
    out: &Bound<'py, PyAny>,
    precision: &str,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let Ok(model) = model.cast::<PyString>() else {
        return Ok(None);
    };
    let Some(dirs) = Directions::of([wi, wo, n, tangent]) else {
        return Ok(None);
    };
    let Some(options) = options(normalized, check, precision) else {
        return Ok(None);
    };
    let mut values = Vec::with_capacity(params.len());
    for (k, v) in params.iter() {
        let (Ok(name), Some(p)) = (k.cast::<PyString>(), param(&v)) else {
            return Ok(None);
        };
        values.push((name.to_str()?.to_owned(), p));
    }
    if dirs.float32 {
        let Some(out) = out_array::<f32>(out) else {
            return Ok(None);
        };
        let kind = ModelKind::from_name(model.to_str()?)?;
        // NumPy's float64 → float32 cast (`astype`): to nearest, overflow to infinity.
        let cast: Vec<(&str, ArrayD<f32>)> = values
            .iter()
            .map(|(k, p)| (k.as_str(), p.view().mapv(|x| x as f32)))
            .collect();
        let [wi, wo, n, tangent] = dirs.views_f32();
        let inputs = EvalInputs {
            wi: wi.expect("given"),
            wo: wo.expect("given"),
            n,
            tangent,
            params: cast.iter().map(|(k, a)| (*k, a.view())).collect(),
        };
        let plan = eval::plan(kind, inputs, options)?;
        Ok(Some(run_plan(py, &plan, out)?.into_any()))
    } else {
        let Some(out) = out_array::<f64>(out) else {
            return Ok(None);
        };
        let kind = ModelKind::from_name(model.to_str()?)?;
        let [wi, wo, n, tangent] = dirs.views_f64();
        let inputs = EvalInputs {
            wi: wi.expect("given"),
            wo: wo.expect("given"),
            n,
            tangent,
            params: values.iter().map(|(k, p)| (k.as_str(), p.view())).collect(),
        };
        let plan = eval::plan(kind, inputs, options)?;
        Ok(Some(run_plan(py, &plan, out)?.into_any()))
    }
}

/// A model with its parameters checked and laid out in kernel slots once, for both
/// dtypes: what `brdf_rs.Model` evaluates with when every parameter is one value.
#[pyclass(frozen, module = "brdf_rs._brdf_rs")]
pub struct PreparedModel {
    kind: ModelKind,
    slots_f64: Vec<f64>,
    /// The float32 slots, or the error their check gave (a value beyond float32's
    /// range): raised by a float32 evaluation, as the general path does.
    slots_f32: Result<Vec<f32>, BrdfError>,
}

/// Prepares `model` with float64 `params` (checked: the errors of `brdf_rs.Model`), or
/// returns `None` when a parameter has batch axes (it broadcasts with the directions).
#[pyfunction]
pub fn prepare_model(model: &str, params: &Bound<'_, PyDict>) -> PyResult<Option<PreparedModel>> {
    let kind = ModelKind::from_name(model)?;
    let arrays = super::param_arrays::<f64>(params)?;
    let views = arrays
        .iter()
        .map(|(k, a)| (k.as_str(), a.as_array()))
        .collect();
    let Some(slots_f64) = eval::uniform_params(kind, views)? else {
        return Ok(None);
    };
    let cast: Vec<(&str, ArrayD<f32>)> = arrays
        .iter()
        .map(|(k, a)| (k.as_str(), a.as_array().mapv(|x| x as f32)))
        .collect();
    let views = cast.iter().map(|(k, a)| (*k, a.view())).collect();
    let slots_f32 = eval::uniform_params(kind, views)
        .map(|slots| slots.expect("the same shapes as in float64"));
    Ok(Some(PreparedModel {
        kind,
        slots_f64,
        slots_f32,
    }))
}

#[pymethods]
impl PreparedModel {
    /// `Model.eval`, or `None` where the general path must convert an argument.
    #[pyo3(signature = (wi, wo, n, tangent, normalized, check, out, precision="accurate"))]
    #[allow(clippy::too_many_arguments)]
    fn eval<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
        n: &Bound<'py, PyAny>,
        tangent: &Bound<'py, PyAny>,
        normalized: &Bound<'py, PyAny>,
        check: &Bound<'py, PyAny>,
        out: &Bound<'py, PyAny>,
        precision: &str,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(dirs) = Directions::of([wi, wo, n, tangent]) else {
            return Ok(None);
        };
        let Some(options) = options(normalized, check, precision) else {
            return Ok(None);
        };
        if dirs.float32 {
            let Some(out) = out_array::<f32>(out) else {
                return Ok(None);
            };
            let slots = self.slots_f32.as_deref();
            self.run(py, slots, dirs.views_f32(), options, out)
        } else {
            let Some(out) = out_array::<f64>(out) else {
                return Ok(None);
            };
            self.run(py, Ok(&self.slots_f64), dirs.views_f64(), options, out)
        }
    }
}

impl PreparedModel {
    fn run<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        slots: Result<&[F], &BrdfError>,
        vectors: [Option<ArrayViewD<'_, F>>; 4],
        options: EvalOptions,
        out: Option<Bound<'py, PyArrayDyn<F>>>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        let plan = eval::plan_uniform(self.kind, slots, vectors, options)?;
        Ok(Some(run_plan(py, &plan, out)?.into_any()))
    }
}
