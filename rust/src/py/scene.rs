//! Bindings of the scene renderer: plain dicts and lists in, NumPy arrays out.
//!
//! A plain converter. The user's scene is checked once, by the Python schema
//! (`brdf_rs._scene_schema`), which words every error with the file and the key; what
//! arrives here is its plain structure. This module checks nothing of its own: it reads
//! the values into the scene's types, whose constructors ([`Camera::new`],
//! [`Object::sphere`], [`Light::point`], [`Term::new`], [`Scene::background_from`]) and the
//! renderer (material indices, model families) hold the invariants the renderer needs.
//! A caller of the core itself that passes something else gets those errors, or a type
//! error naming the key, never a panic.

use numpy::{
    IntoPyArray, PyArrayDyn, PyReadonlyArray2, PyReadonlyArrayDyn, PyReadwriteArrayDyn,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::param_arrays;
use crate::error::BrdfError;
use crate::models::ModelKind;
use crate::scene::render::{COUNTERS, GBuffer, RenderStats};
use crate::scene::{
    Camera, Component, Light, MaterialDesc, Object, Projection, Scene, SheenLayer, Term, ToneMap,
    tonemap,
};

/// Returns `d[key]` converted, or an error naming `path.key` and what was expected.
fn item<'py, T: FromPyObjectOwned<'py>>(
    d: &Bound<'py, PyDict>,
    key: &str,
    path: &str,
    expected: &str,
) -> PyResult<T> {
    let value = d
        .get_item(key)?
        .ok_or_else(|| PyValueError::new_err(format!("{path}.{key}: missing ({expected})")))?;
    value
        .extract::<T>()
        .map_err(|_| PyTypeError::new_err(format!("{path}.{key}: expected {expected}")))
}

/// Returns `d[key]` converted, `None` if absent or None.
fn optional<'py, T: FromPyObjectOwned<'py>>(
    d: &Bound<'py, PyDict>,
    key: &str,
    path: &str,
    expected: &str,
) -> PyResult<Option<T>> {
    match d.get_item(key)? {
        Some(v) if !v.is_none() => v
            .extract::<T>()
            .map(Some)
            .map_err(|_| PyTypeError::new_err(format!("{path}.{key}: expected {expected}"))),
        _ => Ok(None),
    }
}

/// Returns which of the two `names` `d[key]` is (0 or 1), or an error naming `path.key`,
/// the names and what was given.
fn either(d: &Bound<'_, PyDict>, key: &str, path: &str, names: [&str; 2]) -> PyResult<usize> {
    let expected = format!("{:?} or {:?}", names[0], names[1]);
    let name: String = item(d, key, path, &expected)?;
    names.iter().position(|n| *n == name).ok_or_else(|| {
        PyValueError::new_err(format!("{path}.{key}: expected {expected}; got {name:?}"))
    })
}

/// Prefixes an error with where it happened.
fn at(path: &str) -> impl Fn(BrdfError) -> PyErr + '_ {
    move |e| PyErr::from(BrdfError::InvalidArgument(format!("{path}: {e}")))
}

fn dict<'py>(v: &Bound<'py, PyAny>, path: &str) -> PyResult<Bound<'py, PyDict>> {
    v.cast::<PyDict>()
        .cloned()
        .map_err(|_| PyTypeError::new_err(format!("{path}: expected a table (dict)")))
}

fn term(d: &Bound<'_, PyDict>, path: &str) -> PyResult<Term> {
    let model: String = item(d, "model", path, "a model name")?;
    let kind = ModelKind::from_name(&model).map_err(at(path))?;
    let params = match d.get_item("params")? {
        Some(p) => dict(&p, &format!("{path}.params"))?,
        None => PyDict::new(d.py()),
    };
    let arrays = param_arrays::<f64>(&params)?;
    let views = arrays
        .iter()
        .map(|(k, a)| (k.as_str(), a.as_array()))
        .collect();
    Term::new(kind, views).map_err(at(path))
}

/// A sheen layer: `{"model", "params", "weight"}` (`weight` 1 when absent).
fn sheen_layer(d: &Bound<'_, PyDict>, path: &str) -> PyResult<SheenLayer> {
    let weight: f64 = optional(d, "weight", path, "a number in [0, 1]")?.unwrap_or(1.0);
    let term = term(d, path)?;
    SheenLayer::new(term, weight).map_err(|e| {
        // The layer's messages name the key from `sheen.`: the material's path goes first.
        let text = e.to_string();
        let text = text.strip_prefix("sheen").unwrap_or(&text);
        PyErr::from(BrdfError::InvalidArgument(format!("{path}{text}")))
    })
}

fn material(d: &Bound<'_, PyDict>, path: &str) -> PyResult<MaterialDesc> {
    let sheen = match d.get_item("sheen")? {
        Some(v) if !v.is_none() => {
            let p = format!("{path}.sheen");
            Some(sheen_layer(&dict(&v, &p)?, &p)?)
        }
        _ => None,
    };
    Ok(if let Some(brdf) = d.get_item("brdf")? {
        let base = term(&dict(&brdf, path)?, path)?;
        match sheen {
            Some(sheen) => MaterialDesc::Layered { base, sheen },
            None => MaterialDesc::Brdf(base),
        }
    } else if sheen.is_some() {
        return Err(PyValueError::new_err(format!(
            "{path}.sheen: a sheen layer goes over a family-A model (brdf); family-B \
             shading terms take none"
        )));
    } else {
        let part = |role: &str| -> PyResult<Option<Term>> {
            match d.get_item(role)? {
                Some(v) if !v.is_none() => {
                    let p = format!("{path}.{role}");
                    Ok(Some(term(&dict(&v, &p)?, &p)?))
                }
                _ => Ok(None),
            }
        };
        MaterialDesc::Shading {
            diffuse: part("diffuse")?,
            specular: part("specular")?,
        }
    })
}

fn light(d: &Bound<'_, PyDict>, path: &str) -> PyResult<Light> {
    let directional = either(d, "type", path, ["directional", "point"])? == 0;
    let intensity: [f64; 3] = item(d, "intensity", path, "an RGB triple")?;
    let light = if directional {
        Light::directional(item(d, "direction", path, "a vector [x, y, z]")?, intensity)
    } else {
        Light::point(
            item(d, "position", path, "a point [x, y, z]")?,
            intensity,
            optional(d, "range", path, "a positive number")?,
        )
    };
    light.map_err(at(path))
}

/// Converts each table of `list` (named `name[i]` in errors) with `convert`.
fn each<T>(
    list: &Bound<'_, PyList>,
    name: &str,
    convert: impl Fn(&Bound<'_, PyDict>, &str) -> PyResult<T>,
) -> PyResult<Vec<T>> {
    list.iter()
        .enumerate()
        .map(|(i, v)| {
            let path = format!("{name}[{i}]");
            convert(&dict(&v, &path)?, &path)
        })
        .collect()
}

fn lights(list: &Bound<'_, PyList>) -> PyResult<Vec<Light>> {
    each(list, "lights", light)
}

fn camera(d: &Bound<'_, PyDict>) -> PyResult<Camera> {
    let path = "camera";
    let projection = if either(d, "projection", path, ["perspective", "orthographic"])? == 0 {
        Projection::Perspective {
            fov: item::<f64>(d, "fov", path, "an angle in degrees")?.to_radians(),
        }
    } else {
        Projection::Orthographic {
            height: item(d, "height", path, "a positive number")?,
        }
    };
    let [width, height]: [usize; 2] =
        item(d, "resolution", path, "[width, height], positive integers")?;
    Camera::new(
        item(d, "position", path, "a point [x, y, z]")?,
        item(d, "look_at", path, "a point [x, y, z]")?,
        item(d, "up", path, "a vector [x, y, z]")?,
        projection,
        width,
        height,
    )
    .map_err(at(path))
}

fn object(d: &Bound<'_, PyDict>, path: &str) -> PyResult<Object> {
    let sphere = either(d, "shape", path, ["sphere", "plane"])? == 0;
    let material: usize = item(d, "material", path, "a material index")?;
    let object = if sphere {
        Object::sphere(
            item(d, "center", path, "a point [x, y, z]")?,
            item(d, "radius", path, "a positive number")?,
            material,
            &optional::<String>(d, "tangent", path, "\"meridian\" or \"parallel\"")?
                .unwrap_or_else(|| "meridian".into()),
            optional(d, "axis", path, "a vector [x, y, z]")?.unwrap_or([0.0, 1.0, 0.0]),
        )
    } else {
        Object::plane(
            item(d, "point", path, "a point [x, y, z]")?,
            item(d, "normal", path, "a vector [x, y, z]")?,
            material,
            optional(d, "tangent", path, "a vector [x, y, z]")?,
        )
    };
    object.map_err(at(path))
}

fn scene(d: &Bound<'_, PyDict>) -> PyResult<Scene> {
    let get_list = |key: &str| -> PyResult<Bound<'_, PyList>> {
        d.get_item(key)?
            .ok_or_else(|| PyValueError::new_err(format!("{key}: missing")))?
            .cast_into::<PyList>()
            .map_err(|_| PyTypeError::new_err(format!("{key}: expected a list")))
    };
    let camera_dict = dict(
        &d.get_item("camera")?
            .ok_or_else(|| PyValueError::new_err("camera: missing"))?,
        "camera",
    )?;
    let materials = each(&get_list("materials")?, "materials", material)?;
    let objects = each(&get_list("objects")?, "objects", object)?;
    let background = optional(d, "background", "scene", "an RGB triple")?.unwrap_or([0.0; 3]);
    Ok(Scene {
        camera: camera(&camera_dict)?,
        materials,
        objects,
        lights: lights(&get_list("lights")?)?,
        background: Scene::background_from(background)?,
    })
}

fn stats_dict<'py>(py: Python<'py>, stats: &RenderStats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("pixels", stats.pixels)?;
    d.set_item("ray_tests", stats.ray_tests)?;
    d.set_item("hits", stats.hits)?;
    d.set_item("lights", stats.lights)?;
    d.set_item("lights_dropped", stats.lights_dropped)?;
    d.set_item("materials_prepared", stats.materials_prepared)?;
    d.set_item("pairs", stats.pairs)?;
    d.set_item("pairs_out_of_range", stats.pairs_out_of_range)?;
    d.set_item("pairs_backfacing", stats.pairs_backfacing)?;
    d.set_item("pairs_constant", stats.pairs_constant)?;
    d.set_item("evaluations", stats.evaluations())?;
    let parts = PyList::empty(py);
    for p in &stats.parts {
        let e = PyDict::new(py);
        e.set_item("material", p.material)?;
        e.set_item("role", p.role.name())?;
        e.set_item("model", p.model.name())?;
        e.set_item("evaluations", p.evaluations)?;
        parts.append(e)?;
    }
    d.set_item("parts", parts)?;
    Ok(d)
}

type ImageAndStats<'py> = (Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyDict>);

/// Renders a scene (see `brdf_rs.render`): linear radiance `(H, W, 3)` float32 and the
/// counts of the work done.
#[pyfunction]
pub fn render_scene<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyDict>,
    only: &str,
) -> PyResult<ImageAndStats<'py>> {
    let scene = self::scene(scene)?;
    let component = Component::from_name(only)?;
    let mut signals = super::SignalPoll::new();
    let result =
        py.detach(|| crate::scene::render_polled(&scene, component, &mut || signals.poll()));
    let (image, stats) = signals.finish(result)?;
    let shape = vec![scene.camera.height, scene.camera.width, 3];
    let array = numpy::ndarray::Array::from_shape_vec(shape, image)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((array.into_pyarray(py), stats_dict(py, &stats)?))
}

type Rows<'py> = PyReadonlyArray2<'py, f32>;

fn contiguous<'a>(a: &'a Rows<'_>, name: &str) -> PyResult<&'a [f32]> {
    a.as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name}: expected a C-contiguous (N, 3) array")))
}

/// Shades a G-buffer with one material (see `brdf_rs.shade`): `n`, `v` and the optional
/// `positions`, `tangent` are C-contiguous float32 `(N, 3)` arrays of unit vectors.
#[pyfunction]
#[pyo3(signature = (material, lights, n, v, positions, tangent, only))]
#[allow(clippy::too_many_arguments)]
pub fn shade_gbuffer<'py>(
    py: Python<'py>,
    material: &Bound<'py, PyDict>,
    lights: &Bound<'py, PyList>,
    n: Rows<'py>,
    v: Rows<'py>,
    positions: Option<Rows<'py>>,
    tangent: Option<Rows<'py>>,
    only: &str,
) -> PyResult<ImageAndStats<'py>> {
    let desc = self::material(material, "material")?;
    let lights = self::lights(lights)?;
    let component = Component::from_name(only)?;
    for (name, a) in [
        ("n", Some(&n)),
        ("v", Some(&v)),
        ("positions", positions.as_ref()),
        ("tangent", tangent.as_ref()),
    ] {
        if let Some(a) = a {
            if a.shape()[1] != 3 || a.shape()[0] != n.shape()[0] {
                return Err(PyValueError::new_err(format!(
                    "{name}: expected shape ({}, 3); got {:?}",
                    n.shape()[0],
                    a.shape()
                )));
            }
        }
    }
    let g = GBuffer {
        n: contiguous(&n, "n")?,
        v: contiguous(&v, "v")?,
        positions: positions
            .as_ref()
            .map(|a| contiguous(a, "positions"))
            .transpose()?,
        tangents: tangent
            .as_ref()
            .map(|a| contiguous(a, "tangent"))
            .transpose()?,
    };
    let (out, stats) = py.detach(|| crate::scene::shade(&desc, &lights, &g, component))?;
    let array = numpy::ndarray::Array::from_shape_vec(vec![out.len() / 3, 3], out)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((array.into_pyarray(py), stats_dict(py, &stats)?))
}

/// Applies `2^exposure` and a tone map to a float32 array, in place.
#[pyfunction]
pub fn tonemap_inplace<'py>(
    py: Python<'py>,
    mut image: PyReadwriteArrayDyn<'py, f32>,
    tonemap: &str,
    exposure: f64,
) -> PyResult<()> {
    let kind = ToneMap::from_name(tonemap)?;
    let values = image
        .as_slice_mut()
        .map_err(|_| PyValueError::new_err("image: expected a C-contiguous float32 array"))?;
    py.detach(|| tonemap::apply(values, kind, exposure))?;
    Ok(())
}

/// Encodes display values in [0, 1] (clamped) as 8-bit sRGB.
#[pyfunction]
pub fn encode_srgb8<'py>(
    py: Python<'py>,
    image: PyReadonlyArrayDyn<'py, f32>,
) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
    let values = image
        .as_slice()
        .map_err(|_| PyValueError::new_err("image: expected a C-contiguous float32 array"))?;
    let mut out = vec![0u8; values.len()];
    py.detach(|| tonemap::encode_srgb8(values, &mut out));
    let array = numpy::ndarray::Array::from_shape_vec(image.shape().to_vec(), out)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(array.into_pyarray(py))
}

/// Returns the counts of work done by every render and shade call so far (since the last
/// reset): renders, pixels, ray_tests, hits, pairs, pairs_backfacing,
/// pairs_out_of_range, evaluations.
#[pyfunction]
#[pyo3(signature = (reset=false))]
pub fn scene_counters<'py>(py: Python<'py>, reset: bool) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, value) in COUNTERS.snapshot(reset) {
        d.set_item(name, value)?;
    }
    Ok(d)
}
