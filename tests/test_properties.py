"""Property tests (hypothesis): shapes, strides, dtypes and parameter ranges."""

from __future__ import annotations

import math

import brdf_rs
import numpy as np
from conftest import MODEL_NAMES, SPECS, takes_tangent
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
CONTINUOUS = [m for m in MODEL_NAMES if not m.startswith("toon")]


def _batch_shapes():
    return hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4)


@st.composite
def direction_arrays(draw, batch, dtype):
    """A (broadcastable) direction array of ``dtype`` in a random memory layout."""
    shape = tuple(draw(st.sampled_from([1, s])) for s in batch)
    shape = (*shape[draw(st.integers(0, len(shape))) :], 3)
    values = draw(
        hnp.arrays(
            np.float64,
            shape,
            elements=st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False),
        )
    )
    array = values.astype(dtype)
    # Keep vectors usable: replace vectors that are (near) zero after the cast by +z.
    norms = np.linalg.norm(array.astype(np.float64), axis=-1, keepdims=True)
    array = np.where(norms > 1e-6, array, np.array([0, 0, 1], dtype=dtype))
    layout = draw(st.sampled_from(["C", "F", "strided", "reversed"]))
    if layout == "F":
        array = np.asfortranarray(array)
    elif layout == "strided":
        wide = np.zeros((*array.shape[:-1], 6), dtype=array.dtype)
        wide[..., ::2] = array
        array = wide[..., ::2]
    elif layout == "reversed" and array.ndim > 1:
        array = array[::-1].copy()[::-1]
    return array


def _params(draw, model, batch):
    out = {}
    if model == "toon_diffuse":
        k = draw(st.integers(0, 7))
        t = sorted(draw(st.lists(st.floats(-1, 1), min_size=k, max_size=k)))
        out["thresholds"] = t
        out["colors"] = draw(
            hnp.arrays(np.float64, (k + 1, 3), elements=st.floats(0, 10, allow_nan=False))
        )
        return out
    for p in SPECS[model]["params"]:
        lo = p["min"]
        hi = min(p["max"], 1e3 if p["name"] == "p" else 10.0)
        if p["min_open"]:
            lo = max(lo, 1e-3)
        elements = st.floats(lo, hi, allow_nan=False, allow_infinity=False)
        if draw(st.booleans()) and p["default"] is not None:
            continue
        vary = draw(st.booleans())
        if p["kind"] == "colour":
            shape = (*batch, 3) if vary else (3,)
        else:
            shape = batch if vary else ()
        out[p["name"]] = draw(hnp.arrays(np.float64, shape, elements=elements))
    return out


def _off_the_normal(tangent, n):
    """Replaces tangents (nearly) parallel to the normal, which ``eval`` refuses for the
    models that project them onto the tangent plane, by a perpendicular of ``n``."""
    t = tangent.astype(np.float64)
    normal = np.array([0.0, 0.0, 1.0]) if n is None else n.astype(np.float64)
    shape = np.broadcast_shapes(t.shape, normal.shape)
    t, normal = np.broadcast_to(t, shape), np.broadcast_to(normal, shape)
    unit = [v / np.linalg.norm(v, axis=-1, keepdims=True) for v in (t, normal)]
    parallel = np.linalg.norm(np.cross(*unit), axis=-1) <= 1e-3
    if not parallel.any():
        return tangent
    across = np.cross(normal, [1.0, 0.0, 0.0])
    along_x = np.linalg.norm(across, axis=-1, keepdims=True) < 1e-3 * np.linalg.norm(
        normal, axis=-1, keepdims=True
    )
    across = np.where(along_x, np.cross(normal, [0.0, 1.0, 0.0]), across)
    return np.where(parallel[..., None], across, t).astype(tangent.dtype)


@st.composite
def calls(draw, models=MODEL_NAMES):
    model = draw(st.sampled_from(models))
    batch = draw(_batch_shapes())
    dtype = draw(st.sampled_from([np.float64, np.float32, np.int32, ">f8"]))
    wi = draw(direction_arrays(batch, dtype))
    wo = draw(direction_arrays(batch, dtype))
    n = draw(st.one_of(st.none(), direction_arrays(batch, dtype)))
    tangent = draw(direction_arrays(batch, dtype)) if takes_tangent(model) else None
    if tangent is not None and SPECS[model]["tangent_optional"]:
        tangent = _off_the_normal(tangent, n)
    params = _params(draw, model, batch)
    if model == "toon_specular" and "threshold" not in params:
        params["threshold"] = draw(st.floats(-1, 1))
    return model, wi, wo, n, tangent, params


@SETTINGS
@given(calls())
def test_shape_dtype_and_no_nan(call):
    model, wi, wo, n, tangent, params = call
    got = brdf_rs.eval(model, wi, wo, n, tangent=tangent, **params)
    shapes = [wi.shape[:-1], wo.shape[:-1]]
    shapes += [a.shape[:-1] for a in (n, tangent) if a is not None]
    spec = {p["name"]: p["kind"] for p in SPECS[model]["params"]}
    for name, value in params.items():
        a = np.asarray(value)
        if spec[name] == "colour" and a.ndim:
            shapes.append(a.shape[:-1])
        elif spec[name] == "scalar":
            shapes.append(a.shape)
    assert got.shape == (*np.broadcast_shapes(*shapes), 3)
    directions = [a for a in (wi, wo, n, tangent) if a is not None]
    all32 = all(a.dtype == np.float32 for a in directions)
    assert got.dtype == (np.float32 if all32 else np.float64)
    assert not np.isnan(got).any()


@SETTINGS
@given(calls(CONTINUOUS))
def test_float32_close_to_float64_where_well_conditioned(call):
    model, wi, wo, n, tangent, params = call
    f32 = [None if a is None else np.asarray(a, np.float32) for a in (wi, wo, n, tangent)]
    f64 = [None if a is None else a.astype(np.float64) for a in f32]
    # Both see the same (float32-representable) parameters: p = 6e-127 is 0 in float32,
    # and 0^p jumps at p = 0.
    params = {k: np.asarray(v, np.float32).astype(np.float64) for k, v in params.items()}
    got32 = brdf_rs.eval(model, *f32[:3], tangent=f32[3], **params)
    got64 = brdf_rs.eval(model, *f64[:3], tangent=f64[3], **params)
    # Rows far from the horizon, from wi = -wo and with moderate exponents.
    w = [np.broadcast_to(a, (*got64.shape[:-1], 3)) for a in f64[:2]]
    nn = np.broadcast_to(f64[2] if f64[2] is not None else [0, 0, 1.0], w[0].shape)
    unit = [v / np.linalg.norm(v, axis=-1, keepdims=True) for v in (*w, nn)]
    mu_i = np.einsum("...k,...k", unit[0], unit[2])
    mu_o = np.einsum("...k,...k", unit[1], unit[2])
    half = np.linalg.norm(unit[0] + unit[1], axis=-1)
    good = (np.abs(mu_i) > 1e-2) & (np.abs(mu_o) > 1e-2) & (half > 1e-2)
    scale = np.max(np.abs(got64), initial=0.0)
    p = np.broadcast_to(np.asarray(params.get("p", 32.0)), good.shape)
    # float32 kernels flush lobe values below 2^-100 to 0: absolute slack for those.
    tol = 1e-4 * (1.0 + p[..., None] / 10.0) * np.abs(got64) + 1e-6 * scale + 2.0**-100 * 1e8
    err = np.abs(got32.astype(np.float64) - got64)
    assert np.all(err[good] <= tol[good]), (model, err[good].max())


garbage = st.one_of(
    st.none(),
    st.text(max_size=3),
    st.floats(),
    st.lists(st.floats(), max_size=4),
    st.just(object()),
    st.just([[1, 2], [3]]),
    st.just(np.array([1 + 2j])),
    st.just(-math.inf),
)


@SETTINGS
@given(
    st.sampled_from(MODEL_NAMES), st.sampled_from(["kd", "ks", "p", "eta", "sigma", "zz"]), garbage
)
def test_garbage_parameters_raise_clean_errors(model, name, value):
    try:
        out = brdf_rs.eval(model, [0.1, 0.2, 1.0], [0.0, 0.3, 1.0], **{name: value})
    except (TypeError, ValueError) as exc:
        assert str(exc)
    else:
        assert out.shape[-1] == 3 and not np.isnan(out).any()


@SETTINGS
@given(garbage, garbage)
def test_garbage_directions_raise_clean_errors(wi, wo):
    try:
        brdf_rs.eval("phong", wi, wo)
    except (TypeError, ValueError) as exc:
        assert str(exc)
