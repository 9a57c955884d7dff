"""The fast path of ``brdf_rs.eval`` and ``Model.eval`` against the general path.

The fast path reads float arrays, 3-lists and numbers straight from the Python objects
in Rust; every other argument takes the general path (``_eval_general``), which converts
it first. Here each fast-path call is checked to have taken the fast path (the core's
entry points return None where they decline) and to give the general path's result bit
for bit, or its error, type and message, over many shapes, dtypes and layouts.
"""

from __future__ import annotations

import pickle

import brdf_rs
import numpy as np
import pytest
from brdf_rs import _api
from brdf_rs import _brdf_rs as core
from conftest import MODEL_NAMES, random_directions, required_extras

PARAMS = {"kd": [0.2, 0.1, 0.05], "p": 50.0, "eta": 1.5}


def _outcome(call):
    """The result of ``call()``, or the type and message of what it raised."""
    try:
        return call()
    except Exception as exc:
        return (type(exc), str(exc))


def _assert_same(fast, general):
    if isinstance(general, tuple):
        assert isinstance(fast, tuple) and fast == general, fast
        return
    assert isinstance(fast, np.ndarray), fast
    assert fast.dtype == general.dtype and fast.shape == general.shape
    np.testing.assert_array_equal(fast, general, strict=True)


def _eval_both(model, wi, wo, n=None, *, tangent=None, out=None, general_out=None, **kw):
    """``brdf_rs.eval`` (asserting it took the fast path, unless it raised) and the general
    path, each with its own ``out`` when one is given."""
    normalized = kw.pop("normalized", False)
    check = kw.pop("check", True)
    fast = _outcome(lambda: core.eval_fast(model, wi, wo, n, tangent, kw, normalized, check, out))
    assert fast is not None, "the fast path declined"
    general = _outcome(
        lambda: _api._eval_general(
            model, wi, wo, n, tangent, normalized, check, general_out, "approximate", kw
        )
    )
    _assert_same(fast, general)
    # The public function gives the same (through the fast path).
    public = _outcome(
        lambda: brdf_rs.eval(
            model, wi, wo, n, tangent=tangent, normalized=normalized, check=check, out=out, **kw
        )
    )
    _assert_same(public, general)
    return fast


def _model_both(m, wi, wo, n=None, *, tangent=None, normalized=False, check=True, out=None):
    fast = _outcome(lambda: m._fast.eval(wi, wo, n, tangent, normalized, check, out))
    assert fast is not None, "the fast path declined"
    general = _outcome(lambda: m._eval_general(wi, wo, n, tangent, normalized, check, out))
    _assert_same(fast, general)
    return fast


def _layouts(a):
    """The same (N, 3) values in several memory layouts and container types."""
    yield a
    yield np.asfortranarray(a)
    yield a[::-1][::-1]  # negative strides twice: a view of the same order
    backing = np.empty((2 * len(a), 6), a.dtype)
    backing[::2, ::2] = a
    yield backing[::2, ::2]  # strided rows and components
    yield np.ascontiguousarray(a[:, ::-1])[:, ::-1]  # negative component stride


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_layouts_and_broadcasting_match_the_general_path(rng, dtype):
    wi = random_directions(rng, 37).astype(dtype)
    wo = random_directions(rng, 37).astype(dtype)
    for a in _layouts(wi):
        for b in _layouts(wo):
            _eval_both("torrance_sparrow", a, b, **PARAMS)
    # (3,) against (N, 3), (N, 1, 3) against (M, 3), a (1, 3) row, a 0-size batch.
    _eval_both("torrance_sparrow", wi[0], wo, **PARAMS)
    _eval_both("torrance_sparrow", wi[:5, None, :], wo[:4], **PARAMS)
    _eval_both("torrance_sparrow", wi[:1], wo, **PARAMS)
    _eval_both("torrance_sparrow", wi[:0], wo[:1], **PARAMS)
    _eval_both("torrance_sparrow", np.broadcast_to(wi[0], (6, 3)), wo[:6], **PARAMS)
    # A normal, normalized=True, check=False.
    n = random_directions(rng, 37).astype(dtype)
    _eval_both("ggx", wi, wo, n, alpha=0.3)
    _eval_both("ggx", wi, wo, n[0], alpha=0.3, normalized=True)
    _eval_both("ggx", wi, wo, n, alpha=0.3, check=False)


def test_lists_and_tuples_of_numbers_are_read_as_float64(rng):
    wi = random_directions(rng, 8)
    for a in ([0.3, 0.2, 0.9], (0.3, 0.2, 0.9), [0, 0, 1], (1, 2, 3), [0.5, 1, -2]):
        fast = _eval_both("torrance_sparrow", a, wi, **PARAMS)
        assert fast.dtype == np.float64
        _eval_both("torrance_sparrow", wi, a, a, **PARAMS)
    # A list against a float32 array: float64, as NumPy promotes (the general path).
    got = brdf_rs.eval("lambert", [0, 0, 1], wi.astype(np.float32))
    assert got.dtype == np.float64


@pytest.mark.parametrize("model", MODEL_NAMES)
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_every_model_matches_the_general_path(rng, model, dtype):
    wi = random_directions(rng, 150).astype(dtype)
    wo = random_directions(rng, 150).astype(dtype)
    extra = required_extras(model)
    tangent = extra.pop("tangent", None)
    if brdf_rs.models()[model].get("tangent_optional"):
        tangent = random_directions(rng, 150).astype(dtype)
    if tangent is not None:
        tangent = np.asarray(tangent, dtype)
    if model != "toon_diffuse":  # a nested list (its colours): the general path
        _eval_both(model, wi, wo, tangent=tangent, **extra)
    m = brdf_rs.Model(model, **extra)
    assert m._fast is not None
    _model_both(m, wi, wo, tangent=tangent)
    _model_both(m, wi[3], wo, tangent=tangent)
    # Lists of Python floats (float64, as NumPy reads them).
    t_list = None if tangent is None else np.reshape(tangent, (-1, 3))[0].tolist()
    _model_both(m, wi[3].tolist(), wo[4].tolist(), tangent=t_list)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_model_parameters_laid_out_once_match_the_general_path(rng, dtype):
    wi = random_directions(rng, 20).astype(dtype)
    wo = random_directions(rng, 20).astype(dtype)
    for m in (
        brdf_rs.Model("torrance_sparrow", **PARAMS),
        brdf_rs.Model("torrance_sparrow", kd=0.5, ks=[0.1, 0.2, 0.3], p=7, eta=2),
        brdf_rs.Model("normalized_blinn_phong", ks=0.5, p=20.0, normalization="exact"),
        brdf_rs.Model("lambert", kd=np.array([0.5])),  # a grey (1,) colour
        brdf_rs.Model("toon_specular", threshold=0.9, high=[1, 0.5, 0.25]),
    ):
        _model_both(m, wi, wo)
        out = np.empty((20, 3), dtype)
        assert _model_both(m, wi, wo, out=out) is out
    # Parameters with batch axes broadcast with the directions: the general path.
    m = brdf_rs.Model("phong", p=np.array([[10.0], [20.0]]))
    assert m._fast is None
    assert m.eval(wi, wo).shape == (2, 20, 3)
    assert brdf_rs.Model("lambert", kd=np.ones((1, 3)))._fast is None


def test_parameter_values_of_eval_match_the_general_path(rng):
    wi = random_directions(rng, 10)
    wo = random_directions(rng, 10)
    for params in (
        {"kd": 0.5},
        {"kd": [0.5, 0.25, 1]},
        {"kd": (0.5,)},
        {"kd": rng.uniform(size=(10, 3))},  # per element
        {"kd": rng.uniform(size=(10, 1))},
    ):
        _eval_both("lambert", wi, wo, **params)
    _eval_both("toon_specular", wi, wo, threshold=1)
    _eval_both("phong", wi, wo, p=rng.uniform(1, 50, size=10))
    _eval_both("phong", wi.astype(np.float32), wo.astype(np.float32), p=rng.uniform(1, 50, 10))


def test_arguments_the_fast_path_declines_go_the_general_path(rng):
    wi = random_directions(rng, 4)
    m = brdf_rs.Model("torrance_sparrow", **PARAMS)
    declined = [
        (wi.tolist(), wi),  # nested lists
        (wi.astype(np.int64), wi),
        (wi.astype(">f8"), wi),
        (wi.astype(np.float32), wi),  # mixed widths
        (wi.astype(np.float16), wi),
        ([np.float64(0.3), 0.2, 0.9], wi),  # NumPy scalars
        ([True, 0, 1], wi),
        ([2**60, 0, 1], wi),
        ([0.0, 0.0, 1.0, 0.0], wi),
        (None, wi),
    ]
    for a, b in declined:
        assert core.eval_fast("lambert", a, b, None, None, {}, False, True, None) is None
        assert m._fast.eval(a, b, None, None, False, True, None) is None
    for params in ({"kd": np.float32(0.5)}, {"kd": True}, {"kd": [[0.5]]}, {"kd": 10**30}):
        assert core.eval_fast("lambert", wi, wi, None, None, params, False, True, None) is None
    for out in ([0.0] * 12, np.empty((4, 3), np.float32), np.empty((4, 3), ">f8")):
        assert core.eval_fast("lambert", wi, wi, None, None, {}, False, True, out) is None
        assert m._fast.eval(wi, wi, None, None, False, True, out) is None
    for flag in (1, None, "yes"):
        assert core.eval_fast("lambert", wi, wi, None, None, {}, flag, True, None) is None
    assert core.eval_fast(1, wi, wi, None, None, {}, False, True, None) is None
    # ... and the public functions still give the general path's results and errors.
    want = brdf_rs.eval("torrance_sparrow", wi, wi, **PARAMS)
    np.testing.assert_array_equal(brdf_rs.eval("torrance_sparrow", wi.tolist(), wi, **PARAMS), want)
    np.testing.assert_array_equal(m.eval(wi.astype(">f8"), wi), want)
    with pytest.raises(TypeError, match=r"^out: expected a NumPy array, got list$"):
        m.eval(wi, wi, out=[0.0] * 12)


def _bad_vectors(dtype):
    good = np.tile(np.array([0.1, 0.2, 1.0], dtype), (5, 1))
    cases = []
    for bad in ([np.nan, 0, 1], [np.inf, 0, 1], [0, 0, 0]):
        for row in (0, 3):
            a = good.copy()
            a[row] = bad
            cases.append((a, good))
            cases.append((good, a))
    if dtype == np.float64:  # lists are float64
        cases.append((good, [0.0, 0.0, 0.0]))
        cases.append(([0, 0, 0], good))
    return cases


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_errors_are_the_general_paths(dtype):
    good = np.tile(np.array([0.1, 0.2, 1.0], dtype), (5, 1))
    for wi, wo in _bad_vectors(dtype):
        _eval_both("torrance_sparrow", wi, wo, **PARAMS)
        _eval_both("torrance_sparrow", wi, wo, check=False, **PARAMS)  # NaN rows
        _model_both(brdf_rs.Model("torrance_sparrow", **PARAMS), wi, wo)
    bad_n = good.copy()
    bad_n[2] = 0
    _eval_both("lambert", good, good, bad_n)
    cases = [
        ("lambert", good[:, :2], good, {}),  # not (..., 3)
        ("lambert", good, np.ones((4, 3), dtype), {}),  # does not broadcast
        ("lambert", good, np.ones(3, dtype)[None, None, :2], {}),
        ("lambert", good, good, {"kd": -0.5}),  # out of range
        ("lambert", good, good, {"kd": [0.5, np.nan, 0.5]}),
        ("lambert", good, good, {"kd": [0.5, 0.5]}),  # not a colour
        ("lambert", good, good, {"kd": np.ones((4, 3))}),  # does not broadcast
        ("lambert", good, good, {"colour": 0.5}),  # unknown parameter
        ("toon_specular", good, good, {}),  # missing parameter
        ("no_such_model", good, good, {}),
        ("phong", good, good, {"p": 1e300}),
    ]
    for model, wi, wo, params in cases:
        _eval_both(model, wi, wo, **params)
    # Tangents: missing, not taken, parallel to the normal.
    _eval_both("ward", good, good, alpha_x=0.2, alpha_y=0.3, tangent=good)
    _eval_both("kajiya_kay", good, good)
    _eval_both("lambert", good, good, tangent=np.array([1, 0, 0], dtype))
    m = brdf_rs.Model("ward", alpha_x=0.2, alpha_y=0.3)
    _model_both(m, good, good, tangent=good)
    _model_both(m, good, good, tangent=np.array([1, 0, 0], dtype))
    _model_both(brdf_rs.Model("kajiya_kay"), good, good)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_out_errors_are_the_general_paths(dtype):
    good = np.tile(np.array([0.1, 0.2, 1.0], dtype), (5, 1))
    m = brdf_rs.Model("torrance_sparrow", **PARAMS)
    outs = [
        np.empty((4, 3), dtype),  # wrong shape
        np.empty((5, 3, 1), dtype),
        np.empty((3, 5), dtype).T,  # not C-contiguous
        np.empty((5, 6), dtype)[:, ::2],
    ]
    readonly = np.empty((5, 3), dtype)
    readonly.flags.writeable = False
    outs.append(readonly)
    for out in outs:
        _eval_both("torrance_sparrow", good, good, out=out, general_out=out, **PARAMS)
        _model_both(m, good, good, out=out)
    # An out that is also an input.
    a = good.copy()
    _eval_both("torrance_sparrow", a, good, out=a, general_out=a, **PARAMS)
    fast = _outcome(lambda: m._fast.eval(a, good, None, None, False, True, a))
    general = _outcome(lambda: m._eval_general(a, good, None, None, False, True, a))
    assert isinstance(fast, tuple) and fast == general
    # A bad vector with out=: the error, and NaN in its row of out.
    bad = good.copy()
    bad[1, 0] = np.nan
    out = np.zeros((5, 3), dtype)
    with pytest.raises(ValueError, match=r"^wi\[1\] is NaN"):
        m.eval(bad, good, out=out)
    assert np.isnan(out[1]).all() and not np.isnan(out[[0, 2, 3, 4]]).any()


def test_float32_parameters_beyond_float32s_range_raise_at_evaluation():
    # p = 1e39 is a valid float64 exponent; in float32 it rounds to inf, out of range.
    wi = np.array([[0.1, 0.2, 1.0]], np.float32)
    m = brdf_rs.Model("phong", p=1e39)
    assert m._fast is not None
    m.eval(wi.astype(np.float64), wi.astype(np.float64))
    for _ in range(2):  # every call, as the general path
        _model_both(m, wi, wi)
    with pytest.raises(ValueError, match=r"^p = inf is out of range"):
        m.eval(wi, wi)
    # The directions' shape errors come first, as in the general path.
    _model_both(m, wi[:, :2], wi)
    _eval_both("phong", wi, wi, p=1e39)


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_a_short_batch_gives_the_bits_of_a_long_one(rng, model):
    # A batch of at most 16 rows is computed over 16 lanes, a longer one over blocks of
    # 128 (with a short last block): every row gets the same value either way.
    extra = required_extras(model)
    tangent = extra.pop("tangent", None)
    if brdf_rs.models()[model].get("tangent_optional"):
        tangent = [0.3, 1.0, 0.2]
    for dtype in (np.float64, np.float32):
        wi = random_directions(rng, 300).astype(dtype)
        wo = random_directions(rng, 300).astype(dtype)
        t = None if tangent is None else np.asarray(tangent, dtype)
        whole = brdf_rs.eval(model, wi, wo, tangent=t, **extra)
        for start, stop in ((0, 1), (5, 21), (7, 23), (0, 16), (128, 129), (100, 230), (1, 300)):
            part = brdf_rs.eval(model, wi[start:stop], wo[start:stop], tangent=t, **extra)
            np.testing.assert_array_equal(part, whole[start:stop])


def test_models_pickle_and_copy():
    import copy

    m = brdf_rs.Model("torrance_sparrow", normalization="exact", **PARAMS)
    wi = np.array([0.1, 0.2, 1.0])
    for twin in (pickle.loads(pickle.dumps(m)), copy.copy(m), copy.deepcopy(m)):
        assert repr(twin) == repr(m)
        np.testing.assert_array_equal(twin.eval(wi, wi), m.eval(wi, wi))
