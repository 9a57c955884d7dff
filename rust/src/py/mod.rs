//! The Python bindings: the only code that touches PyO3 and NumPy.
//!
//! Each function converts its arguments to core types, releases the GIL around the work
//! and maps [`BrdfError`] to a Python exception in one place. The Python package
//! (`python/brdf_rs`) settles dtypes before calling here: arrays arrive as float64 or
//! float32 NumPy arrays of any shape and layout, read in place.

use std::sync::atomic::Ordering;
use std::time::Duration;

use numpy::{Element, IntoPyArray, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::exceptions::{PyMemoryError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::error::{BrdfError, ErrorClass, try_filled_vec};
use crate::eval::{self, EvalInputs, EvalOptions, Plan, Precision};
use crate::integrate::cells::CellGrid;
use crate::integrate::{self, AlbedoOptions, CellResult, Cells, Progress, SamplerChoice};
use crate::math::Real;
use crate::models::spec::{ExactFactor, SceneUse};
use crate::models::{ModelKind, ParamKind, TangentUse};

mod fast;
mod options;
mod scene;

impl From<BrdfError> for PyErr {
    fn from(e: BrdfError) -> PyErr {
        if e == BrdfError::Interrupted {
            return pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string());
        }
        match e.class() {
            ErrorClass::Type => PyTypeError::new_err(e.to_string()),
            ErrorClass::Value => PyValueError::new_err(e.to_string()),
            ErrorClass::Memory => PyMemoryError::new_err(e.to_string()),
        }
    }
}

type Arr<'py, F> = PyReadonlyArrayDyn<'py, F>;

/// Checks for Ctrl-C from inside work that runs without the GIL, as the albedo builds do
/// (`Python::check_signals`), but from the calling thread between parts of the work:
/// [`SignalPoll::poll`] takes the GIL back at most every [`SignalPoll::INTERVAL`], so a
/// call shorter than that never does. A raised exception (the handler's
/// `KeyboardInterrupt`) is kept for [`SignalPoll::finish`] to return.
pub(crate) struct SignalPoll {
    last: std::time::Instant,
    raised: Option<PyErr>,
}

impl SignalPoll {
    /// The most time between two checks.
    const INTERVAL: Duration = Duration::from_millis(20);

    pub(crate) fn new() -> SignalPoll {
        SignalPoll {
            last: std::time::Instant::now(),
            raised: None,
        }
    }

    /// Returns false (stop) once a signal handler has raised.
    pub(crate) fn poll(&mut self) -> bool {
        if self.last.elapsed() < Self::INTERVAL {
            return true;
        }
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            self.raised = Some(e);
            return false;
        }
        self.last = std::time::Instant::now();
        true
    }

    /// The result of work polled by `self`: the handler's exception if the work was
    /// interrupted, else the work's own result.
    pub(crate) fn finish<T>(self, result: Result<T, BrdfError>) -> PyResult<T> {
        match (result, self.raised) {
            (Err(BrdfError::Interrupted), Some(e)) => Err(e),
            (result, _) => Ok(result?),
        }
    }
}

/// Extracts the `{name: array}` parameter dict as read-only arrays.
pub(crate) fn param_arrays<'py, F: Real + Element>(
    params: &Bound<'py, PyDict>,
) -> PyResult<Vec<(String, Arr<'py, F>)>> {
    params
        .iter()
        .map(|(k, v)| {
            let name: String = k.extract()?;
            let array: Arr<'py, F> = v.extract().map_err(|_| {
                PyTypeError::new_err(format!("{name}: expected a {} array", F::DTYPE))
            })?;
            Ok((name, array))
        })
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn eval_impl<'py, F: Real + Element>(
    py: Python<'py>,
    model: &str,
    wi: Arr<'py, F>,
    wo: Arr<'py, F>,
    n: Option<Arr<'py, F>>,
    tangent: Option<Arr<'py, F>>,
    params: &Bound<'py, PyDict>,
    options: EvalOptions,
    out: Option<Bound<'py, PyArrayDyn<F>>>,
) -> PyResult<Bound<'py, PyArrayDyn<F>>> {
    let kind = ModelKind::from_name(model)?;
    let params = param_arrays::<F>(params)?;
    let inputs = EvalInputs {
        wi: wi.as_array(),
        wo: wo.as_array(),
        n: n.as_ref().map(|a| a.as_array()),
        tangent: tangent.as_ref().map(|a| a.as_array()),
        params: params
            .iter()
            .map(|(name, a)| (name.as_str(), a.as_array()))
            .collect(),
    };
    let plan = eval::plan(kind, inputs, options)?;
    run_plan(py, &plan, out)
}

/// Batches of at least this many rows are evaluated with the GIL released (other Python
/// threads run meanwhile, and Ctrl-C is polled); a smaller one keeps it: releasing and
/// taking it back costs more than such a batch takes.
pub const DETACH_ROWS: usize = 1 << 12;

/// Runs `plan` into `out`, or into a new array of its output shape.
pub(crate) fn run_plan<'py, F: Real + Element>(
    py: Python<'py>,
    plan: &Plan<'_, F>,
    out: Option<Bound<'py, PyArrayDyn<F>>>,
) -> PyResult<Bound<'py, PyArrayDyn<F>>> {
    let out = match out {
        Some(out) => out,
        // Every element is written by `execute`.
        None => empty::<F>(py, &plan.output_shape())
            .map_err(|e| too_big_result::<F>(py, &plan.output_shape(), e))?,
    };
    {
        let mut guard = out.try_readwrite().map_err(|e| {
            PyValueError::new_err(format!(
                "out: cannot write into it ({e}); is it an input too?"
            ))
        })?;
        let view = guard.as_array_mut();
        if plan.rows < DETACH_ROWS {
            plan.execute(view)?;
        } else {
            let mut signals = SignalPoll::new();
            let result = py.detach(|| plan.execute_polled(view, &mut || signals.poll()));
            signals.finish(result)?;
        }
    }
    Ok(out)
}

/// The error for a result array that cannot be allocated: names the result, its shape
/// and size, and what to do (NumPy's own message names neither the call nor a remedy).
/// Other errors pass through.
fn too_big_result<F: Element>(py: Python<'_>, shape: &[usize], e: PyErr) -> PyErr {
    if !e.is_instance_of::<PyMemoryError>(py) && !e.is_instance_of::<PyValueError>(py) {
        return e;
    }
    let bytes = shape
        .iter()
        .fold(std::mem::size_of::<F>() as f64, |b, &d| b * d as f64);
    let (size, unit) = [("TiB", 40), ("GiB", 30), ("MiB", 20), ("KiB", 10)]
        .iter()
        .find(|(_, p)| bytes >= (1u64 << p) as f64)
        .map_or((bytes, "bytes"), |&(u, p)| (bytes / (1u64 << p) as f64, u));
    PyMemoryError::new_err(format!(
        "the result of shape {} ({size:.1} {unit}) cannot be allocated: evaluate in \
         smaller batches, or pass out= an array of that shape",
        crate::error::format_shape(shape)
    ))
}

/// A new, uninitialized C-ordered array, as `numpy.empty` makes it: NumPy allocates and
/// raises `MemoryError` (or `ValueError` for a size beyond its index type) when it cannot,
/// where `PyArrayDyn::new` would panic on the null pointer.
fn empty<'py, F: Element>(py: Python<'py>, shape: &[usize]) -> PyResult<Bound<'py, PyArrayDyn<F>>> {
    use numpy::PyArrayDescrMethods;
    use numpy::npyffi::{NpyTypes, PY_ARRAY_API, get_type_object, npy_intp};
    let mut dims = shape
        .iter()
        .map(|&d| npy_intp::try_from(d))
        .collect::<Result<Vec<npy_intp>, _>>()
        .map_err(|_| PyValueError::new_err("array is too big"))?;
    let ndim = std::os::raw::c_int::try_from(dims.len())
        .map_err(|_| PyValueError::new_err("too many dimensions"))?;
    // SAFETY: the arguments are those `PyArray::new` passes (array type, a new reference
    // to the dtype, which NumPy steals, no strides, data or base: NumPy allocates), and a
    // null result, NumPy's error set, becomes that error; a non-null one is a new
    // reference to an array of `F`'s dtype (the descriptor passed), so the unchecked cast
    // to `PyArrayDyn<F>` holds.
    unsafe {
        let ptr = PY_ARRAY_API.PyArray_NewFromDescr(
            py,
            get_type_object(py, NpyTypes::PyArray_Type),
            F::get_dtype(py).into_dtype_ptr(),
            ndim,
            dims.as_mut_ptr(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            0,
            std::ptr::null_mut(),
        );
        Ok(Bound::from_owned_ptr_or_err(py, ptr)?.cast_into_unchecked())
    }
}

/// Defines the `#[pyfunction]` that evaluates a model on arrays of `$float` (`eval_f64`,
/// `eval_f32`): the two differ only in their float type and docstring.
macro_rules! eval_function {
    ($(#[doc = $doc:literal])* $name:ident, $float:ty) => {
        $(#[doc = $doc])*
        #[pyfunction]
        #[pyo3(signature = (model, wi, wo, n, tangent, params, normalized, check, check_params, out=None, precision="accurate"))]
        #[allow(clippy::too_many_arguments)]
        fn $name<'py>(
            py: Python<'py>,
            model: &str,
            wi: Arr<'py, $float>,
            wo: Arr<'py, $float>,
            n: Option<Arr<'py, $float>>,
            tangent: Option<Arr<'py, $float>>,
            params: &Bound<'py, PyDict>,
            normalized: bool,
            check: bool,
            check_params: bool,
            out: Option<Bound<'py, PyArrayDyn<$float>>>,
            precision: &str,
        ) -> PyResult<Bound<'py, PyArrayDyn<$float>>> {
            let options = EvalOptions {
                normalized,
                check,
                check_params,
                precision: Precision::from_name(precision)?,
            };
            eval_impl(py, model, wi, wo, n, tangent, params, options, out)
        }
    };
}

eval_function!(
    /// Evaluates a model on float64 arrays (see `brdf_rs.eval`).
    eval_f64,
    f64
);
eval_function!(
    /// Evaluates a model on float32 arrays with the float32 kernels (see `brdf_rs.eval`).
    eval_f32,
    f32
);

/// Checks parameter names, shapes and values for a model (float64 arrays), without
/// evaluating: `brdf_rs.Model` calls this once.
#[pyfunction]
fn check_params<'py>(model: &str, params: &Bound<'py, PyDict>) -> PyResult<()> {
    let kind = ModelKind::from_name(model)?;
    let params = param_arrays::<f64>(params)?;
    let views: Vec<(&str, _)> = params
        .iter()
        .map(|(name, a)| (name.as_str(), a.as_array()))
        .collect();
    eval::check_params(kind, views)?;
    Ok(())
}

/// Checks that `model` exists and that every one of `names` is one of its parameters,
/// before any value is converted: an unknown name is reported as such, not as a bad value.
#[pyfunction]
fn check_param_names(model: &str, names: Vec<String>) -> PyResult<()> {
    let spec = ModelKind::from_name(model)?.spec();
    eval::params::check_known(spec, names.iter().map(String::as_str))?;
    Ok(())
}

/// Returns whether `value` passes the range check of `model`'s parameter `param` (the
/// check `eval` makes), for callers that word their own errors (scene files).
#[pyfunction]
fn param_admits(model: &str, param: &str, value: f64) -> PyResult<bool> {
    let spec = ModelKind::from_name(model)?.spec();
    let Some(p) = spec.param(param) else {
        return Err(PyValueError::new_err(format!(
            "{model} has no parameter {param:?}"
        )));
    };
    Ok(p.range.admits(value))
}

/// Returns the albedo seen from the view at unit colour, `kd = 0`, `ks = 1`
/// ([`ModelKind::sheen_view_albedo`]), elementwise over `mu_o` and `alpha` (same shape; the
/// package broadcasts and checks the ranges), for a model that gives it in closed form.
#[pyfunction]
fn view_albedo<'py>(
    py: Python<'py>,
    model: &str,
    mu_o: PyReadonlyArrayDyn<'py, f64>,
    alpha: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let kind = ModelKind::from_name(model)?;
    if !kind.view_albedo_closed_form() {
        return Err(PyValueError::new_err(format!(
            "{model}: its albedo seen from the view has no closed form"
        )));
    }
    let (mu_o, alpha) = (mu_o.as_array(), alpha.as_array());
    if mu_o.shape() != alpha.shape() {
        return Err(PyValueError::new_err(format!(
            "view_albedo: mu_o and alpha differ in shape: {:?} and {:?}",
            mu_o.shape(),
            alpha.shape()
        )));
    }
    let out = ndarray::Zip::from(&mu_o)
        .and(&alpha)
        .map_collect(|&m, &a| kind.sheen_view_albedo(a, m).unwrap_or(f64::NAN));
    Ok(out.into_pyarray(py))
}

/// Returns the table of the rough GGX dielectric's total albedo that its compensated form
/// divides by ([`crate::models::tables::DielectricEnergy`]): `E[side, i, j, k]` as float32
/// of shape `(2, NT, NA, NS)`, for the references, which interpolate it themselves.
#[pyfunction]
fn ggx_dielectric_energy_table<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    use crate::models::tables::{DielectricEnergy, GGX_DIELECTRIC};
    let shape = ndarray::IxDyn(&DielectricEnergy::SHAPE);
    let table = ndarray::ArrayD::from_shape_vec(shape, GGX_DIELECTRIC.values())
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(table.into_pyarray(py))
}

/// Returns the spec table: one dict per model.
#[pyfunction]
fn models<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for kind in ModelKind::ALL {
        let spec = kind.spec();
        let params = PyList::empty(py);
        for p in spec.params {
            let d = PyDict::new(py);
            d.set_item("name", p.name)?;
            d.set_item("kind", p.kind.name())?;
            d.set_item("default", p.default)?;
            d.set_item("min", p.range.min)?;
            d.set_item("max", p.range.max)?;
            d.set_item("min_open", p.range.min_open)?;
            d.set_item("max_open", p.range.max_open)?;
            d.set_item("range", p.range.describe())?;
            d.set_item("doc", p.doc)?;
            d.set_item("varies", p.kind.may_vary())?;
            let max_len = match p.kind {
                ParamKind::ScalarList { max_len, .. } | ParamKind::ColourList { max_len, .. } => {
                    Some(max_len)
                }
                _ => None,
            };
            d.set_item("max_len", max_len)?;
            let one_more_than = match p.kind {
                ParamKind::ColourList { one_more_than, .. } => Some(one_more_than),
                _ => None,
            };
            d.set_item("one_more_than", one_more_than)?;
            params.append(d)?;
        }
        let d = PyDict::new(py);
        d.set_item("name", spec.name)?;
        d.set_item("family", spec.family.letter())?;
        d.set_item("summary", spec.summary)?;
        d.set_item("formula", spec.formula)?;
        d.set_item("source", spec.source)?;
        d.set_item("reciprocal", spec.reciprocal)?;
        d.set_item("tangent", spec.tangent == TangentUse::Required)?;
        d.set_item("tangent_optional", spec.tangent == TangentUse::Optional)?;
        d.set_item("weights", spec.weights)?;
        d.set_item("scene_slot", spec.scene.slot())?;
        let diffuse = match spec.scene {
            SceneUse::Brdf(diffuse) => Some(diffuse.name()),
            _ => None,
        };
        d.set_item("diffuse", diffuse)?;
        let dfg = match spec.dfg {
            Some(axis) => {
                let a = PyDict::new(py);
                a.set_item("param", axis.param)?;
                a.set_item("axis", axis.axis)?;
                Some(a)
            }
            None => None,
        };
        d.set_item("dfg", dfg)?;
        d.set_item("energy_table", spec.energy_table)?;
        d.set_item("view_albedo_closed_form", kind.view_albedo_closed_form())?;
        d.set_item("transmission", spec.transmission)?;
        d.set_item("sheen_layer", spec.sheen_layer)?;
        d.set_item("powers", kind.powers())?;
        d.set_item("fast_tier", kind.fast_tier())?;
        let exact = match spec.exact {
            Some(exact) => {
                let e = PyDict::new(py);
                e.set_item("factor", exact.factor.name())?;
                e.set_item("params", exact.params)?;
                e.set_item("scales", exact.scales)?;
                let table = match exact.factor {
                    ExactFactor::Table(name) => Some(name),
                    _ => None,
                };
                e.set_item("table", table)?;
                Some(e)
            }
            None => None,
        };
        d.set_item("exact", exact)?;
        d.set_item("params", params)?;
        list.append(d)?;
    }
    Ok(list)
}

/// Returns the models the package's tools pick when the user names none
/// ([`crate::models::defaults`]).
#[pyfunction]
fn tool_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let defaults = crate::models::defaults::TOOL_DEFAULTS;
    let table = PyDict::new(py);
    table.set_item("model", defaults.table.model.name())?;
    table.set_item("axes", defaults.table.axes)?;
    table.set_item("params", defaults.table.params)?;
    let check = PyDict::new(py);
    check.set_item("model", defaults.albedo_check.model.name())?;
    check.set_item("param", defaults.albedo_check.param)?;
    check.set_item("lo", defaults.albedo_check.lo)?;
    check.set_item("hi", defaults.albedo_check.hi)?;
    let d = PyDict::new(py);
    d.set_item("table", table)?;
    d.set_item("dfg", defaults.dfg.name())?;
    d.set_item("plain_diffuse", defaults.plain_diffuse.name())?;
    let bench: Vec<&str> = defaults.bench.iter().map(|k| k.name()).collect();
    d.set_item("bench", bench)?;
    d.set_item("albedo_check", check)?;
    Ok(d)
}

/// Runs `work` on a scoped thread while this thread polls every 100 ms: it reports
/// progress to `callback(cells_done, samples_done)` and checks for Ctrl-C (a
/// `KeyboardInterrupt` cancels the work, waits for it to stop and is raised).
fn run_interruptible<'py, T: Send>(
    py: Python<'py>,
    progress: &Progress,
    callback: Option<&Bound<'py, PyAny>>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    std::thread::scope(|scope| {
        let handle = scope.spawn(work);
        loop {
            let finished = py.detach(|| {
                let start = std::time::Instant::now();
                while !handle.is_finished() && start.elapsed() < Duration::from_millis(100) {
                    std::thread::sleep(Duration::from_millis(2));
                }
                handle.is_finished()
            });
            let mut polled = py.check_signals();
            if polled.is_ok() {
                if let Some(cb) = callback {
                    let cells = progress.cells_done.load(Ordering::Relaxed);
                    let samples = progress.samples_done.load(Ordering::Relaxed);
                    polled = cb.call1((cells, samples)).map(|_| ());
                }
            }
            if let Err(e) = polled {
                progress.cancel.store(true, Ordering::Relaxed);
                let _ = py.detach(|| handle.join());
                return Err(e);
            }
            if finished {
                return py
                    .detach(|| handle.join())
                    .map_err(|_| PyRuntimeError::new_err("internal error: the worker panicked"));
            }
        }
    })
}

/// Directional albedo of every cell of `mu` broadcast with `params` (see
/// `brdf_rs.albedo`). Returns `(value, stderr, samples)`.
/// `options` is the dict of the integrator's options, converted by
/// [`options::albedo_options`] as `check_albedo_options` converts it.
#[pyfunction]
#[pyo3(signature = (model, mu, params, options, cell_ids=None, progress=None, fold_azimuth=true, phi=None, average_azimuth=false))]
#[allow(clippy::too_many_arguments)]
fn albedo<'py>(
    py: Python<'py>,
    model: &str,
    mu: Arr<'py, f64>,
    params: &Bound<'py, PyDict>,
    options: &Bound<'py, PyDict>,
    cell_ids: Option<PyReadonlyArrayDyn<'py, u64>>,
    progress: Option<Bound<'py, PyAny>>,
    fold_azimuth: bool,
    phi: Option<Arr<'py, f64>>,
    average_azimuth: bool,
) -> PyResult<AlbedoArrays<'py>> {
    let kind = ModelKind::from_name(model)?;
    let options = AlbedoOptions {
        fold_azimuth,
        average_azimuth,
        ..options::albedo_options(options)?.0
    };
    let params = param_arrays::<f64>(params)?;
    let views = params
        .iter()
        .map(|(name, a)| (name.as_str(), a.as_array()))
        .collect();
    let ids =
        match &cell_ids {
            Some(a) => Some(a.as_slice().map_err(|_| {
                PyValueError::new_err("cell_ids: must be a C-contiguous uint64 array")
            })?),
            None => None,
        };
    let grid = CellGrid::new(
        kind,
        mu.as_array(),
        phi.as_ref().map(|p| p.as_array()),
        views,
        ids,
    )?;
    let cells = grid.count();
    options.validate(cells)?;
    let counters = Progress::default();
    let mut out = try_filled_vec::<CellResult>(cells, "albedo cells")?;
    run_interruptible(py, &counters, progress.as_ref(), || {
        integrate::albedo(kind, &grid, &options, &counters, &mut out)
    })??;
    let mut shape = grid.batch.clone();
    let n = out.len();
    let samples = numpy::ndarray::Array::from_iter(out.iter().map(|r| r.samples))
        .into_shape_with_order(shape.clone())
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    shape.push(3);
    let value = numpy::ndarray::Array::from_iter(out.iter().flat_map(|r| r.value))
        .into_shape_with_order(shape.clone())
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let stderr = numpy::ndarray::Array::from_iter(out.iter().flat_map(|r| r.stderr))
        .into_shape_with_order(shape)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    debug_assert_eq!(value.len(), 3 * n);
    Ok((
        value.into_pyarray(py),
        stderr.into_pyarray(py),
        samples.into_pyarray(py),
    ))
}

fn sampler_choice(name: &Bound<'_, PyAny>) -> PyResult<SamplerChoice> {
    Ok(SamplerChoice::ALL[options::index("sampler", name, &SamplerChoice::NAMES)?])
}

#[allow(clippy::too_many_arguments)]
fn sampling_call<'py>(
    py: Python<'py>,
    model: &str,
    wi: Arr<'py, f64>,
    second: Arr<'py, f64>,
    n: Option<Arr<'py, f64>>,
    tangent: Option<Arr<'py, f64>>,
    params: &Bound<'py, PyDict>,
    sampler: &Bound<'py, PyAny>,
    sampling: bool,
) -> PyResult<eval::sample::Output> {
    let kind = ModelKind::from_name(model)?;
    let sampler = sampler_choice(sampler)?;
    let params = param_arrays::<f64>(params)?;
    let inputs = eval::sample::Inputs {
        wi: wi.as_array(),
        second: second.as_array(),
        n: n.as_ref().map(|a| a.as_array()),
        tangent: tangent.as_ref().map(|a| a.as_array()),
        params: params
            .iter()
            .map(|(k, a)| (k.as_str(), a.as_array()))
            .collect(),
    };
    let mut signals = SignalPoll::new();
    let result = py.detach(|| {
        let poll = &mut || signals.poll();
        if sampling {
            eval::sample::sample(kind, inputs, sampler, poll)
        } else {
            eval::sample::pdf(kind, inputs, sampler, poll)
        }
    });
    signals.finish(result)
}

fn shaped<'py>(
    py: Python<'py>,
    data: Vec<f64>,
    shape: Vec<usize>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let a = numpy::ndarray::Array::from_shape_vec(shape, data)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// Draws directions from a model's sampler (see `brdf_rs.sample`): `(wo, weight, pdf)`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn sample<'py>(
    py: Python<'py>,
    model: &str,
    wi: Arr<'py, f64>,
    u: Arr<'py, f64>,
    n: Option<Arr<'py, f64>>,
    tangent: Option<Arr<'py, f64>>,
    params: &Bound<'py, PyDict>,
    sampler: &Bound<'py, PyAny>,
) -> PyResult<Arrays3<'py>> {
    let out = sampling_call(py, model, wi, u, n, tangent, params, sampler, true)?;
    let mut vec_shape = out.batch.clone();
    vec_shape.push(3);
    Ok((
        shaped(py, out.wo, vec_shape.clone())?,
        shaped(py, out.weight, vec_shape)?,
        shaped(py, out.pdf, out.batch)?,
    ))
}

/// The sampler's density of `wo` (see `brdf_rs.pdf`).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn pdf<'py>(
    py: Python<'py>,
    model: &str,
    wi: Arr<'py, f64>,
    wo: Arr<'py, f64>,
    n: Option<Arr<'py, f64>>,
    tangent: Option<Arr<'py, f64>>,
    params: &Bound<'py, PyDict>,
    sampler: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let out = sampling_call(py, model, wi, wo, n, tangent, params, sampler, false)?;
    shaped(py, out.pdf, out.batch)
}

type Arrays3<'py> = (
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
);

type AlbedoArrays<'py> = (
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<u64>>,
);

/// Sets the number of worker threads.
#[pyfunction]
fn set_num_threads(n: usize) -> PyResult<()> {
    Ok(crate::parallel::set_num_threads(n)?)
}

/// Returns the largest thread count `set_num_threads` accepts.
#[pyfunction]
fn max_num_threads() -> usize {
    crate::parallel::max_num_threads()
}

/// Returns the number of worker threads.
#[pyfunction]
fn num_threads() -> usize {
    crate::parallel::num_threads()
}

/// Returns the instruction set the kernels run with (`avx512`, `avx2`, `baseline`).
#[pyfunction]
fn isa() -> &'static str {
    crate::simd::isa().name()
}

/// The compiled core of brdf-rs. Use the `brdf_rs` package, not this module.
#[pymodule]
#[pyo3(name = "_brdf_rs")]
mod brdf_rs_ext {
    #[pymodule_export]
    use super::{
        albedo, check_param_names, check_params, eval_f32, eval_f64, ggx_dielectric_energy_table,
        isa, max_num_threads, models, num_threads, param_admits, pdf, sample, set_num_threads,
        tool_defaults, view_albedo,
    };

    #[pymodule_export]
    use super::fast::{PreparedModel, eval_fast, prepare_model};

    #[pymodule_export]
    use super::options::{check_albedo_options, choice_option, integer_option};

    #[pymodule_export]
    const SAMPLERS: [&str; 4] = crate::sampling::SamplerChoice::NAMES;

    #[pymodule_export]
    const SEQUENCES: [&str; 2] = crate::sampling::streams::Sequence::NAMES;

    #[pymodule_export]
    const DEFAULT_REPLICATES: u32 = crate::integrate::DEFAULT_REPLICATES;

    #[pymodule_export]
    const TONEMAPS: [&str; 4] = crate::scene::ToneMap::NAMES;

    #[pymodule_export]
    const MAX_IMAGE_SIDE: usize = crate::scene::camera::MAX_SIDE;

    #[pymodule_export]
    const PARALLEL_TANGENT_EPSILONS: f64 = crate::math::geometry::PARALLEL_TANGENT_EPSILONS;

    #[pymodule_export]
    use super::scene::{
        encode_srgb8, render_scene, scene_counters, shade_gbuffer, tonemap_inplace,
    };

    #[pymodule_export]
    #[allow(non_upper_case_globals)]
    const __version__: &str = crate::VERSION;
}
