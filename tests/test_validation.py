"""Input validation at the edges: no NaN from finite input, degenerate input refused with
the argument and first bad index named, documented bounds accepted in both dtypes, and
long calls that answer Ctrl-C."""

from __future__ import annotations

import re
from pathlib import Path

import brdf_rs
import numpy as np
import pytest
from brdf_rs.scene import TONEMAPS, load_scene

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


# ------------------------------------------------------------------------ cell ids


@pytest.mark.parametrize(
    ("ids", "index", "shown"),
    [
        ([-1, 2], "[0]", "-1"),
        ([0, -2], "[1]", "-2"),
        ([0.5, 2.7], "[0]", "0.5"),
        ([1.0, 2.7], "[1]", "2.7"),
        ([0.0, np.nan], "[1]", "nan"),
        ([0.0, np.inf], "[1]", "inf"),
        ([0.0, 2.0**64], "[1]", str(2.0**64)),
    ],
)
def test_albedo_refuses_cell_ids_that_are_not_non_negative_integers(ids, index, shown):
    pattern = rf"^cell_ids{re.escape(index)} = {re.escape(shown)} .*first bad index"
    with pytest.raises(ValueError, match=pattern):
        brdf_rs.albedo("lambert", [0.5, 0.7], samples=64, cell_ids=ids)


def test_albedo_cell_ids_as_integers_or_integral_floats_key_the_same_streams():
    mu = [0.3, 0.8]
    ref = brdf_rs.albedo("ggx", mu, samples=64, cell_ids=np.array([7, 9], np.uint64))
    for ids in ([7, 9], np.array([7, 9], np.int32), [7.0, 9.0]):
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
