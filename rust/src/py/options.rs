//! Options that are not arrays (integers, numbers, names from a list), converted from
//! Python objects here, once for every caller: `albedo` and the table builders, scenes,
//! `dask`, the command line, `set_num_threads`, `precision=`. Each error names the
//! option, says what it accepts and shows what it got (its `repr`, cut at 60 characters).
//!
//! The Python package calls these before any work starts (the command line before its
//! progress bar, `dask` before it builds a graph), and the core's entry points take the
//! same Python objects through the same converters, so no option is worded twice. The
//! joint checks of the integrator (a sample count that passes the Sobol sequence, a
//! request too large in total) stay with [`AlbedoOptions::validate`], which Rust callers
//! share.

use pyo3::exceptions::{PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString, PyType};

use crate::integrate::{
    AlbedoOptions, Component, MAX_REPLICATES, MAX_SAMPLES_PER_CELL, MIN_REPLICATES,
};
use crate::sampling::SamplerChoice;
use crate::sampling::streams::Sequence;

/// The largest value of an unsigned 64-bit integer (seeds, sample counts, cell ids).
const U64_MAX: u64 = u64::MAX;

static NP_BOOL: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static NP_INTEGER: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static NP_FLOATING: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// `repr(value)`, cut to 57 characters and "..." beyond 60.
pub(crate) fn show(value: &Bound<'_, PyAny>) -> PyResult<String> {
    let text = value.repr()?.to_string();
    Ok(if text.chars().count() <= 60 {
        text
    } else {
        text.chars().take(57).collect::<String>() + "..."
    })
}

/// `type(value).__name__`.
fn type_name(value: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(value.get_type().name()?.to_string())
}

/// A Python or NumPy boolean.
fn is_bool(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    Ok(value.is_instance_of::<PyBool>()
        || value.is_instance(NP_BOOL.import(value.py(), "numpy", "bool_")?)?)
}

/// A Python or NumPy integer (booleans included: callers refuse those first).
fn is_int(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    Ok(value.is_instance_of::<PyInt>()
        || value.is_instance(NP_INTEGER.import(value.py(), "numpy", "integer")?)?)
}

/// A Python or NumPy float.
fn is_float(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    Ok(value.is_instance_of::<PyFloat>()
        || value.is_instance(NP_FLOATING.import(value.py(), "numpy", "floating")?)?)
}

/// An integer option from `lo` to `hi`: a Python or NumPy integer, or an integral float
/// (1e6); `hi_text` spells `hi` in messages (`"2**40"`) where given.
pub(crate) fn integer(
    name: &str,
    value: &Bound<'_, PyAny>,
    lo: u64,
    hi: u64,
    hi_text: &str,
) -> PyResult<u64> {
    let py = value.py();
    let range = if hi_text.is_empty() {
        format!("an integer from {lo} to {hi}")
    } else {
        format!("an integer from {lo} to {hi_text}")
    };
    let mut value = value.clone();
    if is_float(&value)? {
        let x: f64 = value.extract()?;
        if x.is_finite() && x.fract() == 0.0 {
            value = py.get_type::<PyInt>().call1((&value,))?;
        }
    }
    if is_bool(&value)? || !is_int(&value)? {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected {range}, got {} {}",
            type_name(&value)?,
            show(&value)?
        )));
    }
    match value.extract::<i128>() {
        Ok(x) if (i128::from(lo)..=i128::from(hi)).contains(&x) => Ok(x as u64),
        _ => Err(PyValueError::new_err(format!(
            "{name}: expected {range}, got {}",
            show(&value)?
        ))),
    }
}

/// One finite real number (a Python or NumPy int or float, not a boolean); `what` says
/// what the option is (`"a number"`).
pub(crate) fn real(name: &str, value: &Bound<'_, PyAny>, what: &str) -> PyResult<f64> {
    if is_bool(value)? || !(is_int(value)? || is_float(value)?) {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected {what}, got {} {}",
            type_name(value)?,
            show(value)?
        )));
    }
    let x: f64 = match value.extract() {
        Ok(x) => x,
        Err(e) if e.is_instance_of::<PyOverflowError>(value.py()) => {
            return Err(PyValueError::new_err(format!(
                "{name}: expected {what}, got {} (beyond float64's {:.4})",
                show(value)?,
                Float(f64::MAX)
            )));
        }
        Err(e) => return Err(e),
    };
    if !x.is_finite() {
        return Err(PyValueError::new_err(format!(
            "{name}: expected {what} (finite), got {}",
            Float(x)
        )));
    }
    Ok(x)
}

/// One of `choices` (a string; `TypeError` if not one).
pub(crate) fn choice<'a>(
    name: &str,
    value: &Bound<'_, PyAny>,
    choices: &[&'a str],
) -> PyResult<&'a str> {
    let quoted: Vec<String> = choices.iter().map(|c| format!("\"{c}\"")).collect();
    let options = match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => quoted.concat(),
    };
    let Ok(text) = value.cast::<PyString>() else {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected {options}; got {} {}",
            type_name(value)?,
            show(value)?
        )));
    };
    // A string Rust cannot hold (a lone surrogate) is no choice either.
    if let Ok(s) = text.to_str() {
        if let Some(c) = choices.iter().find(|c| **c == s) {
            return Ok(c);
        }
    }
    let py = value.py();
    let shown = if text.len()? <= 60 {
        text.clone().into_any()
    } else {
        text.get_item(pyo3::types::PySlice::new(py, 0, 57, 1))?
            .add("...")?
    };
    let quoted = py.import("json")?.call_method1("dumps", (shown,))?;
    Err(PyValueError::new_err(format!(
        "{name}: expected {options}; got {quoted}"
    )))
}

/// A float written as Python writes it (`repr`: `1e-05`, `inf`), or with a `{:.4}`
/// precision as Python's `{:.4g}`.
struct Float(f64);

impl std::fmt::Display for Float {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        Python::attach(|py| {
            let x = PyFloat::new(py, self.0);
            let text = match f.precision() {
                Some(p) => x.call_method1("__format__", (format!(".{p}g"),)),
                None => x.repr().map(Bound::into_any),
            };
            match text {
                Ok(t) => write!(f, "{t}"),
                Err(_) => write!(f, "{}", self.0),
            }
        })
    }
}

/// The names of the options [`albedo_options`] reads, in the order it checks them.
const ALBEDO_OPTIONS: [&str; 9] = [
    "samples",
    "sampler",
    "sequence",
    "seed",
    "replicates",
    "tol",
    "rtol",
    "max_samples",
    "component",
];

/// The options of an albedo computation, given as the Python API takes them: a dict of
/// `samples`, `sampler`, `sequence`, `seed`, `replicates`, `tol`, `rtol`, `max_samples`
/// and `component` (absent: the default; `tol`, `rtol` and `max_samples` may also be
/// None, for not given), checked in that order.
/// Returns the options and `max_samples` as given.
pub(crate) fn albedo_options(given: &Bound<'_, PyDict>) -> PyResult<(AlbedoOptions, Option<u64>)> {
    for key in given.keys() {
        let known = key
            .extract::<String>()
            .is_ok_and(|k| ALBEDO_OPTIONS.contains(&k.as_str()));
        if !known {
            return Err(PyTypeError::new_err(format!(
                "unknown albedo option {}; expected {}",
                show(&key)?,
                ALBEDO_OPTIONS.join(", ")
            )));
        }
    }
    let get = |key: &str| given.get_item(key);
    // `tol`, `rtol` and `max_samples` are None where not given; None is no value for the
    // rest.
    let optional = |key: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
        Ok(given.get_item(key)?.filter(|v| !v.is_none()))
    };
    let mut o = AlbedoOptions::default();
    if let Some(v) = get("samples")? {
        o.samples = integer("samples", &v, 1, MAX_SAMPLES_PER_CELL, "2**40")?;
    }
    if let Some(v) = get("sampler")? {
        o.sampler = SamplerChoice::ALL[index("sampler", &v, &SamplerChoice::NAMES)?];
    }
    if let Some(v) = get("sequence")? {
        o.sequence = Sequence::ALL[index("sequence", &v, &Sequence::NAMES)?];
    }
    if let Some(v) = get("seed")? {
        o.seed = integer("seed", &v, 0, U64_MAX, "")?;
    }
    if let Some(v) = get("replicates")? {
        let (lo, hi) = (MIN_REPLICATES.into(), MAX_REPLICATES.into());
        o.replicates = integer("replicates", &v, lo, hi, "")? as u32;
    }
    for (name, what) in [
        ("tol", "a positive number (a standard error)"),
        (
            "rtol",
            "a positive number (a standard error relative to the value)",
        ),
    ] {
        if let Some(v) = optional(name)? {
            let t = real(name, &v, what)?;
            if !(t > 0.0) {
                return Err(PyValueError::new_err(format!(
                    "{name}: must be a positive number; got {}",
                    Float(t)
                )));
            }
            *if name == "tol" {
                &mut o.tol
            } else {
                &mut o.rtol
            } = Some(t);
        }
    }
    let max_given = match optional("max_samples")? {
        Some(v) => Some(integer(
            "max_samples",
            &v,
            1,
            MAX_SAMPLES_PER_CELL,
            "2**40",
        )?),
        None => None,
    };
    o.max_samples = max_given.unwrap_or_else(|| o.samples.max(1 << 24));
    if let Some(v) = get("component")? {
        o.component = Component::ALL[index("component", &v, &Component::NAMES)?];
    }
    Ok((o, max_given))
}

/// The index in `choices` of a string option (see [`choice`]).
pub(crate) fn index(name: &str, value: &Bound<'_, PyAny>, choices: &[&str]) -> PyResult<usize> {
    let c = choice(name, value, choices)?;
    Ok(choices.iter().position(|x| *x == c).unwrap_or(0))
}

/// Checks and converts the options of `brdf_rs.albedo` (see [`albedo_options`]; the
/// core's `albedo` converts them the same way): the same dict, every option present,
/// converted (`tol`, `rtol` and `max_samples` None where not given).
#[pyfunction]
pub(crate) fn check_albedo_options<'py>(
    given: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyDict>> {
    let (o, max_given) = albedo_options(given)?;
    let d = PyDict::new(given.py());
    d.set_item("samples", o.samples)?;
    d.set_item("sampler", o.sampler.name())?;
    d.set_item("sequence", o.sequence.name())?;
    d.set_item("seed", o.seed)?;
    d.set_item("replicates", o.replicates)?;
    d.set_item("tol", o.tol)?;
    d.set_item("rtol", o.rtol)?;
    d.set_item("max_samples", max_given)?;
    d.set_item("component", o.component.name())?;
    Ok(d)
}

/// An integer option (see [`integer`]); `hi` defaults to 2**64 − 1.
#[pyfunction]
#[pyo3(name = "integer_option", signature = (name, value, lo, hi = None, hi_text = ""))]
pub(crate) fn integer_option(
    name: &str,
    value: &Bound<'_, PyAny>,
    lo: u64,
    hi: Option<u64>,
    hi_text: &str,
) -> PyResult<u64> {
    integer(name, value, lo, hi.unwrap_or(U64_MAX), hi_text)
}

/// A string option, one of `choices` (see [`choice`]).
#[pyfunction]
#[pyo3(name = "choice_option")]
pub(crate) fn choice_option(
    name: &str,
    value: &Bound<'_, PyAny>,
    choices: Vec<String>,
) -> PyResult<String> {
    let refs: Vec<&str> = choices.iter().map(String::as_str).collect();
    choice(name, value, &refs).map(str::to_owned)
}
