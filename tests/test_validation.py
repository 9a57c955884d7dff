"""Input validation at the edges: no NaN from finite input, degenerate input refused with
the argument and first bad index named, documented bounds accepted in both dtypes, and
long calls that answer Ctrl-C."""

from __future__ import annotations

import _thread
import functools
import threading
import time
from pathlib import Path

import brdf_rs
import numpy as np
import pytest
from brdf_rs.scene import TONEMAPS, SceneError, load_scene, parse_scene
from conftest import tiny_scene

SCENES = Path(__file__).resolve().parents[1] / "examples" / "scenes"
DTYPES = (np.float64, np.float32)
EPS = {np.float64: np.finfo(np.float64).eps, np.float32: np.finfo(np.float32).eps}

# ------------------------------------------------------------------------ exposure


def _exact_exposure(x: np.ndarray, exposure: float) -> np.ndarray:
    """``x·2^exposure`` rounded to float32 (2^±1000 is beyond float32 for any nonzero x)."""
    scale = np.exp2(np.clip(exposure, -1000.0, 1000.0))
    with np.errstate(over="ignore", under="ignore"):
        return (x.astype(np.float64) * scale).astype(np.float32)


@pytest.mark.parametrize("kind", TONEMAPS)
@pytest.mark.parametrize("exposure", [127.5, 128.0, 129.0, 300.0, 1e300, -150.0, -1e300, 2.5])
def test_tonemap_never_makes_nan_from_finite_input(kind, exposure):
    image = np.array([[[0.0, -0.0, 1.0], [1e-45, 3e38, -2.0], [0.5, 1e-30, 7.0]]], dtype=np.float32)
    out = brdf_rs.tonemap(image, kind, exposure)
    assert not np.isnan(out).any(), out
    assert out[0, 0, 0] == 0 and out[0, 0, 1] == 0
    if kind == "none":
        np.testing.assert_array_equal(out, _exact_exposure(image, exposure))
    else:
        reference = brdf_rs.tonemap(_exact_exposure(image, exposure), kind, 0.0)
        np.testing.assert_array_equal(out, reference)


def test_tonemap_exposure_huge_but_finite_is_not_called_infinite():
    # 1e39 stops is finite: it must not be refused as "inf" (a float32 cast).
    out = brdf_rs.tonemap(np.ones((1, 1, 3)), "reinhard", 1e39)
    np.testing.assert_array_equal(out, 1.0)


@pytest.mark.parametrize("exposure", [np.nan, np.inf, -np.inf])
def test_tonemap_refuses_non_finite_exposure(exposure):
    with pytest.raises(ValueError, match="exposure"):
        brdf_rs.tonemap(np.zeros((1, 1, 3)), "none", exposure)


def test_render_with_overflowing_exposure_has_no_nan():
    scene = load_scene(SCENES / "gallery.toml").with_resolution(64, 32)
    linear = brdf_rs.render(scene, tonemap="none")
    for exposure in (129.0, 1000.0):
        image = brdf_rs.render(scene, tonemap="none", exposure=exposure)
        assert not np.isnan(image).any()
        np.testing.assert_array_equal(image == 0, linear == 0)
        shown = brdf_rs.render(scene, tonemap="aces", exposure=exposure)
        assert not np.isnan(shown).any()


# ------------------------------------------------------------------------ sample / pdf


@pytest.mark.parametrize(
    ("bad", "problem"),
    [
        (np.nan, "NaN"),
        (np.inf, "infinite"),
        (-np.inf, "infinite"),
        (-1e-300, r"outside \[0, 1\)"),
        (1.0, r"outside \[0, 1\)"),
        (1.5, r"outside \[0, 1\)"),
    ],
)
@pytest.mark.parametrize("component", [0, 1])
def test_sample_refuses_bad_random_numbers(bad, problem, component):
    u = np.full((4, 2), 0.25)
    u[2, component] = bad
    u[3, 0] = bad  # only the first bad index is named
    with pytest.raises(ValueError, match=rf"^u\[2\] is {problem} \(first bad index \[2\]\)"):
        brdf_rs.sample("ggx", [0.3, 0, 1], u, alpha=0.3)


def test_sample_refuses_the_reported_nan():
    with pytest.raises(ValueError, match=r"^u is NaN"):
        brdf_rs.sample("ggx", [0.3, 0, 1], [np.nan, 0.5])


def test_sample_accepts_the_ends_of_the_unit_interval():
    u = np.array([[0.0, 0.0], [np.nextafter(1.0, 0.0), np.nextafter(1.0, 0.0)], [0.0, 0.999]])
    wo, weight, pdf = brdf_rs.sample("ggx", [0.3, 0, 1], u, alpha=0.3)
    assert np.isfinite(wo).all() and np.isfinite(weight).all() and np.isfinite(pdf).all()


def test_sample_index_is_in_the_arguments_own_array():
    # u broadcasts against wi: the index named is u's own.
    wi = np.tile([0.3, 0.0, 1.0], (5, 3, 1))
    u = np.full((3, 2), 0.5)
    u[1, 1] = 2.0
    with pytest.raises(ValueError, match=r"^u\[1\] is outside"):
        brdf_rs.sample("lambert", wi, u)


@pytest.mark.parametrize("function", ["sample", "pdf"])
@pytest.mark.parametrize(
    ("argument", "value", "problem"),
    [
        ("wi", [np.nan, 0, 1], "NaN"),
        ("wi", [0, 0, 0], "a zero-length vector"),
        ("n", [0, np.inf, 1], "infinite"),
        ("n", [0, 0, 0], "a zero-length vector"),
        ("tangent", [np.nan, 1, 0], "NaN"),
    ],
)
def test_sample_and_pdf_refuse_bad_directions(function, argument, value, problem):
    given = {"wi": [0.3, 0.0, 1.0], "n": None, "tangent": [1.0, 0.0, 0.0]}
    rows = np.tile(given[argument] or [0.0, 0.0, 1.0], (3, 1))
    rows[1] = value
    given[argument] = rows
    second = np.full((3, 2), 0.5) if function == "sample" else np.tile([0.0, 0.3, 1.0], (3, 1))
    with pytest.raises(ValueError, match=rf"^{argument}\[1\] is {problem}"):
        getattr(brdf_rs, function)(
            "ward", given["wi"], second, given["n"], tangent=given["tangent"]
        )


def test_pdf_refuses_a_bad_wo():
    wo = np.tile([0.0, 0.3, 1.0], (3, 1))
    wo[2] = np.nan
    with pytest.raises(ValueError, match=r"^wo\[2\] is NaN"):
        brdf_rs.pdf("ggx", [0.3, 0, 1], wo, alpha=0.3)


# ------------------------------------------------------------------------ tangents


def _tilted_normal():
    n = np.array([0.3, -0.2, 0.9])
    return n / np.linalg.norm(n)


def _tangents_near(n, sine):
    """A tangent at angle asin(sine) from n (and its opposite)."""
    side = np.cross(n, [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    t = np.sqrt(1 - sine**2) * n + sine * side
    return t, -t


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("model", ["ward", "ashikhmin_shirley"])
def test_eval_refuses_a_tangent_parallel_to_the_normal(model, dtype):
    n = _tilted_normal()
    wi = np.array([0.5, 0.1, 1.0])
    wo = np.array([-0.2, 0.4, 1.0])
    for sine in (0.0, 1e-17, 8 * EPS[dtype]):
        for t in _tangents_near(n, sine):
            tangent = np.tile([1.0, 0.0, 0.0], (4, 1))
            tangent[1] = t
            args = [np.asarray(a, dtype) for a in (wi, wo, n, tangent)]
            with pytest.raises(ValueError, match=r"^tangent\[1\] is parallel to the normal n"):
                brdf_rs.eval(model, *args[:3], tangent=args[3])
            # check=False: the row is NaN like any unusable row; the others are computed.
            out = brdf_rs.eval(model, *args[:3], tangent=args[3], check=False)
            assert np.isnan(out[1]).all() and np.isfinite(np.delete(out, 1, axis=0)).all()
            with pytest.raises(ValueError, match=r"^tangent\[1\] is parallel"):
                brdf_rs.Model(model).eval(*args[:3], tangent=args[3])


def test_eval_refuses_the_reported_tangent():
    with pytest.raises(ValueError, match=r"^tangent is parallel to the normal n"):
        brdf_rs.eval("ward", [0.3, 0, 1], [0, 0.2, 1], tangent=[0, 0, 1])
    with pytest.raises(ValueError, match=r"^tangent is parallel"):
        brdf_rs.eval("ward", [0.3, 0, 1], [0, 0.2, 1], tangent=[0, 0, 1], normalized=True)


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("model", ["ward", "ashikhmin_shirley"])
def test_eval_accepts_a_tangent_just_beyond_the_threshold(model, dtype):
    n = _tilted_normal()
    for sine in (256 * EPS[dtype], 1e-3, 1.0):
        t, _ = _tangents_near(n, sine)
        out = brdf_rs.eval(
            model,
            np.asarray([0.5, 0.1, 1.0], dtype),
            np.asarray([-0.2, 0.4, 1.0], dtype),
            np.asarray(n, dtype),
            tangent=np.asarray(t, dtype),
        )
        assert np.isfinite(out).all()


def test_kajiya_kay_fibre_along_the_normal_is_valid():
    # The fibre tangent is used as given, not projected: along n is a hair standing up.
    out = brdf_rs.eval("kajiya_kay", [0.3, 0, 1], [0, 0.2, 1], tangent=[0, 0, 1])
    assert np.isfinite(out).all()


@pytest.mark.parametrize("model", ["ward", "ashikhmin_shirley"])
def test_the_reference_refuses_a_tangent_parallel_to_the_normal(model):
    for t in ([0, 0, 1], [1e-17, 0, -1]):
        with pytest.raises(ValueError, match=r"^tangent .* is parallel to the normal n"):
            brdf_rs.reference.eval(model, [0.3, 0, 1], [0, 0.2, 1], tangent=t)
    assert np.isfinite(
        brdf_rs.reference.eval(model, [0.3, 0, 1], [0, 0.2, 1], tangent=[1e-3, 0, 1])
    ).all()


def test_sampling_refuses_a_tangent_parallel_to_the_normal():
    tangent = np.array([[1.0, 0, 0], [0, 0, -2.0]])
    with pytest.raises(ValueError, match=r"^tangent\[1\] is parallel"):
        brdf_rs.sample("ward", [0.3, 0, 1], [0.5, 0.5], tangent=tangent)
    with pytest.raises(ValueError, match=r"^tangent\[1\] is parallel"):
        brdf_rs.pdf("ashikhmin_shirley", [0.3, 0, 1], [0, 0.2, 1], tangent=tangent)


def test_shade_refuses_a_tangent_parallel_to_the_normal():
    n = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    tangent = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 1e-9]])
    lights = [{"type": "directional", "direction": [0, 0, -1]}]
    with pytest.raises(ValueError, match=r"^tangent\[1\] is parallel to the normal"):
        brdf_rs.shade({"model": "ward"}, n, [0, 0, 1], lights, tangent=tangent)
    # kajiya_kay's fibre may lie along the normal.
    material = {"specular": {"model": "kajiya_kay"}}
    out = brdf_rs.shade(material, n, [0, 0, 1], lights, tangent=tangent)
    assert np.isfinite(out).all()


def test_scene_plane_tangent_parallel_to_its_normal_is_refused():
    plane = (
        '[[objects]]\ntype = "plane"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n'
        'tangent = [0, 0, -3]\nmaterial = "m"\n'
    )
    text = tiny_scene('model = "ward"', objects=plane)
    with pytest.raises(SceneError, match=r"objects\[0\]\.tangent: .*parallel to the plane"):
        parse_scene(text, "plane.toml")
    parse_scene(text.replace("[0, 0, -3]", "[1, 0, -3]"), "plane.toml")


# ------------------------------------------------------------------------ cell ids


@pytest.mark.parametrize(
    ("ids", "error", "pattern"),
    [
        ([-1, 2], ValueError, r"^cell_ids\[0\] = -1 is out of range"),
        ([0, -2], ValueError, r"^cell_ids\[1\] = -2 is out of range"),
        ([0.5, 2.7], TypeError, r"^cell_ids\[0\]: expected integers"),
        ([1.0, 2.7], TypeError, r"^cell_ids\[0\]: expected integers"),
        (np.array([0.0, np.nan]), TypeError, r"^cell_ids: expected integers .* dtype float64"),
        (np.array([0.0, 2.0**64]), TypeError, r"^cell_ids: expected integers .* dtype float64"),
    ],
)
def test_albedo_refuses_cell_ids_that_are_not_non_negative_integers(ids, error, pattern):
    """A wrapped -1 or a truncated 2.7 would silently key another cell's stream."""
    with pytest.raises(error, match=pattern):
        brdf_rs.albedo("lambert", [0.5, 0.7], samples=64, cell_ids=ids)


def test_albedo_cell_ids_of_any_integer_type_key_the_same_streams():
    mu = [0.3, 0.8]
    ref = brdf_rs.albedo("ggx", mu, samples=64, cell_ids=np.array([7, 9], np.uint64))
    for ids in ([7, 9], np.array([7, 9], np.int32), (np.int64(7), 9)):
        got = brdf_rs.albedo("ggx", mu, samples=64, cell_ids=ids)
        np.testing.assert_array_equal(got.value, ref.value)


# ------------------------------------------------------------------------ energy axis


@pytest.mark.parametrize(
    ("model", "params"),
    [
        ("ggx", {"alpha": 0.5}),  # maximum at grazing
        ("ggx", {"alpha": 0.05, "ks": 1.0}),
        ("lambert", {"kd": 0.5}),
        ("normalized_blinn_phong", {"kd": 0, "ks": 1, "p": 2.0}),  # maximum at mu = 1
        ("torrance_sparrow", {"p": 20.0}),
        ("ward", {"alpha_x": 0.3, "alpha_y": 0.3}),
    ],
)
@pytest.mark.parametrize("samples", [64, 256, 1024])
def test_energy_axis_is_strictly_increasing_with_one_value_per_node(model, params, samples):
    e = brdf_rs.energy(model, samples=samples, **params)
    assert e.mu.ndim == 1 and e.value.shape == (e.mu.size, 3)
    assert np.all(np.diff(e.mu) > 0), e.mu
    coarse = np.concatenate([[0.005], np.arange(1, 65) / 64.0])
    assert np.isin(coarse, e.mu).all()
    assert 65 < e.mu.size <= 65 + 15
    k = int(np.argmax(e.value.max(axis=-1)))
    assert e.mu_at_max == e.mu[k]
    np.testing.assert_array_equal(e.max, e.value[k])


# ------------------------------------------------------------------------ closed bounds


def _valid_params(spec):
    """A valid value for every required parameter (the list models need matching lists)."""
    if spec["name"] == "toon_diffuse":
        return {"thresholds": [0.0], "colors": [[0.1, 0.1, 0.1], [0.9, 0.9, 0.9]]}
    if spec["name"] == "toon_specular":
        return {"threshold": 0.5}
    return {}


def _closed_bounds():
    for name, spec in brdf_rs.models().items():
        for p in spec["params"]:
            for end, value, is_open in (
                ("min", p["min"], p["min_open"]),
                ("max", p["max"], p["max_open"]),
            ):
                if not is_open and np.isfinite(value):
                    yield pytest.param(name, p["name"], value, id=f"{name}-{p['name']}-{end}")


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize(("model", "param", "bound"), list(_closed_bounds()))
def test_documented_closed_bounds_are_accepted_in_both_dtypes(model, param, bound, dtype):
    spec = brdf_rs.models()[model]
    params = _valid_params(spec)
    kind = next(p["kind"] for p in spec["params"] if p["name"] == param)
    rounded = float(np.asarray(bound, dtype))  # the bound as the dtype holds it
    for value in {bound, rounded}:
        params[param] = [value] if kind == "scalar list" else value
        if kind == "colour list":
            params[param] = [[value] * 3] * 2
        directions = [np.asarray(v, dtype) for v in ([0.3, 0.1, 1.0], [-0.2, 0.4, 1.0])]
        tangent = np.asarray([1.0, 0.0, 0.0], dtype) if spec["tangent"] else None
        out = brdf_rs.eval(model, *directions, tangent=tangent, **params)
        assert out.dtype == dtype and not np.isnan(out).any()
        out = brdf_rs.Model(model, **params).eval(*directions, tangent=tangent)
        assert out.dtype == dtype and not np.isnan(out).any()


@pytest.mark.parametrize("dtype", DTYPES)
def test_the_reported_sigma_bound(dtype):
    d = [np.asarray(v, dtype) for v in ([0.3, 0, 1], [0, 0.2, 1])]
    for model in ("oren_nayar", "oren_nayar_shading"):
        assert np.isfinite(brdf_rs.eval(model, *d, sigma=np.pi / 2)).all()
        assert np.isfinite(brdf_rs.eval(model, *d, sigma=np.float32(np.pi / 2))).all()
    # Beyond the bound's rounding is still refused.
    above = float(np.nextafter(np.float32(np.pi / 2), np.float32(2)))
    with pytest.raises(ValueError, match="sigma"):
        brdf_rs.eval("oren_nayar", *d, sigma=above)


def test_a_scene_accepts_the_float32_rounding_of_a_closed_bound():
    material = f'model = "oren_nayar"\nsigma = {float(np.float32(np.pi / 2))!r}'
    text = tiny_scene(material, lights='[[lights]]\ntype = "directional"\ndirection = [0, 0, -1]\n')
    assert np.isfinite(brdf_rs.render(parse_scene(text, "bound.toml"))).all()


# ------------------------------------------------------------------------ Ctrl-C


def _interrupted_after(call, delay):
    """Runs ``call`` with a KeyboardInterrupt sent to this (main) thread after ``delay``
    seconds; returns the seconds until the interrupt arrived, or None if it did not."""
    timer = threading.Timer(delay, _thread.interrupt_main)
    start = time.perf_counter()
    try:
        timer.start()
        call()
        timer.join()
        time.sleep(0.05)
    except KeyboardInterrupt:
        return time.perf_counter() - start
    finally:
        timer.cancel()
    return None


def _timed(call):
    start = time.perf_counter()
    call()
    return time.perf_counter() - start


def _check_answers_ctrl_c(call, full, what):
    """Interrupts ``call``, whose uninterrupted run took ``full`` seconds, after 0.05 s and
    checks it stops within half its run. Skips where ``what`` took under 0.3 s (too short
    to tell an answer from an ordinary return)."""
    if full < 0.3:
        pytest.skip(f"{what} took only {full:.3f} s here")
    elapsed = _interrupted_after(call, 0.05)
    assert elapsed is not None
    assert elapsed < 0.05 + 0.5 * full, (elapsed, full)


def test_a_long_eval_answers_ctrl_c():
    # (k, 1) × (1, m) directions broadcast into a large batch with little input memory.
    rng = np.random.default_rng(1)
    m = 1 << 16
    wo = rng.normal(size=(1, m, 3)).astype(np.float32)
    wi = np.abs(rng.normal(size=(1 << 9, 1, 3))).astype(np.float32)
    k, full = 1 << 5, 0.0
    while True:  # one call of at least 0.3 s (a loop of calls would stop between them)
        out = np.empty((k, m, 3), np.float32)
        call = functools.partial(
            brdf_rs.eval, "ashikhmin_shirley", wi[:k], wo, nu=30, nv=300, out=out
        )
        full = min(_timed(call) for _ in range(2))
        if full >= 0.3 or k >= wi.shape[0]:
            break
        k *= 2
    _check_answers_ctrl_c(call, full, f"an eval of {k * m} rows")
    # Results are bitwise those of calls too small to be split.
    call()
    for i in range(0, k, 7):
        alone = brdf_rs.eval("ashikhmin_shirley", wi[i], wo[0], nu=30, nv=300)
        np.testing.assert_array_equal(out[i], alone)


def test_a_long_render_answers_ctrl_c():
    scene = load_scene(SCENES / "gallery.toml")
    width, height = 2048, 2048
    while True:
        scene = scene.with_resolution(width, height)
        call = functools.partial(brdf_rs.render, scene, tonemap="none")
        full = min(_timed(call) for _ in "ab")
        if full >= 0.3 or width >= 16384:
            break
        width *= 2
    _check_answers_ctrl_c(call, full, f"a {width}x{height} render")


@pytest.mark.parametrize("what", ["sample", "pdf"])
def test_long_sampling_answers_ctrl_c(what):
    rng = np.random.default_rng(2)
    rows = 1 << 17
    while True:  # one call of at least 0.3 s
        wi = np.abs(rng.normal(size=(rows, 3)))
        second = rng.random((rows, 2)) if what == "sample" else rng.normal(size=(rows, 3))
        call = functools.partial(getattr(brdf_rs, what), "ggx", wi, second, alpha=0.3, kd=0.5)
        full = min(_timed(call) for _ in range(2))
        if full >= 0.3 or rows >= 1 << 24:
            break
        rows *= 2
    _check_answers_ctrl_c(call, full, f"a {what} of {rows} rows")


@pytest.mark.parametrize("what", ["sample", "pdf", "albedo", "eval"])
def test_a_broadcast_batch_too_large_to_hold_is_refused_at_once(what):
    """A broadcast view of 10^12 rows costs no memory to pass, but its results could never
    be held: the call is refused before any row is read (not after minutes of checks)."""
    big = (10**6, 10**6)
    wi = np.broadcast_to(np.array([0.3, 0.0, 1.0]), (*big, 3))
    calls = {
        "sample": lambda: brdf_rs.sample(
            "ggx", wi, np.broadcast_to(np.array([0.3, 0.5]), (*big, 2)), alpha=0.3
        ),
        "pdf": lambda: brdf_rs.pdf("ggx", wi, wi, alpha=0.3),
        "albedo": lambda: brdf_rs.albedo("ggx", np.broadcast_to(np.array(0.5), big), alpha=0.3),
        "eval": lambda: brdf_rs.eval("ggx", wi, wi, alpha=0.3),
    }
    start = time.perf_counter()
    with pytest.raises((MemoryError, ValueError)):
        calls[what]()
    assert time.perf_counter() - start < 5.0


def test_a_bad_value_in_a_broadcast_parameter_is_found_at_its_first_index():
    """The range checks look at a broadcast axis once, and name the first bad index as
    the check of the full array would."""
    alpha = np.full((3, 1), 0.3)
    alpha[1, 0] = -1.0
    view = np.broadcast_to(alpha, (3, 10**7))
    with pytest.raises(ValueError, match=r"alpha\[1, 0\] = -1"):
        brdf_rs.eval("ggx", [0, 0, 1], [0, 0, 1], alpha=view)
    mu = np.broadcast_to(np.array([0.5, 2.0]), (10**7, 2))
    with pytest.raises(ValueError, match=r"mu\[0, 1\] = 2"):
        brdf_rs.albedo("ggx", mu, alpha=0.3)


def test_scenes_and_stress_use_evals_range_check():
    """One range check (the Rust spec's), for eval and for the callers that word their own
    errors: closed bounds admit their float32 roundings in both."""
    from brdf_rs import _spec

    half_pi_f32 = float(np.float32(np.pi / 2))
    beyond = float(np.nextafter(half_pi_f32, 4.0))
    assert _spec.admits("oren_nayar", "sigma", half_pi_f32)
    brdf_rs.eval("oren_nayar", [0, 0, 1], [0, 0, 1], sigma=half_pi_f32)
    assert not _spec.admits("oren_nayar", "sigma", beyond)
    with pytest.raises(ValueError, match="sigma"):
        brdf_rs.eval("oren_nayar", [0, 0, 1], [0, 0, 1], sigma=beyond)
    assert not _spec.admits("ggx", "alpha", float("nan"))
    with pytest.raises(ValueError, match="ggx has no parameter"):
        _spec.admits("ggx", "p", 1.0)
