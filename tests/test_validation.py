"""Input validation at the edges: no NaN from finite input, degenerate input refused with
the argument and first bad index named, documented bounds accepted in both dtypes, and
long calls that answer Ctrl-C."""

from __future__ import annotations

import re

import brdf_rs
import numpy as np
import pytest

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
