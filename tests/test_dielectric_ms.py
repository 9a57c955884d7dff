"""``ggx_dielectric_ms``: ``ggx_dielectric`` divided by its white interface's albedo.

The model is ``f_ggx_dielectric(wi, wo)/E(|mu_i|, alpha, r_i)``, ``E`` the total albedo of
the white interface (``ks = kt = 1``) for light at ``wi``, read from an embedded table,
``r_i`` the relative index seen from ``wi``'s side. What these tests hold it to:

- the white furnace: with ``ks = kt = 1`` its albedo is 1 within 1% for alpha up to 1,
  from above (grazing incidence and an index near 1 included) and (by sampling) from
  below the surface;
- the factor depends on ``wi`` alone and is ``1/albedo(ggx_dielectric)`` of ``wi``'s
  side (within the table's error), in both dtypes and both precision tiers;
- sampling is ``ggx_dielectric``'s (same directions and densities, weights times the
  factor), and the albedo's parts are ``ggx_dielectric``'s times the factor;
- ``eta = 1`` is the straight-through delta; ``alpha`` outside the table is refused.
"""

from __future__ import annotations

import math

import brdf_rs
import numpy as np
import pytest
from conftest import random_directions

MODEL = "ggx_dielectric_ms"
BASE = "ggx_dielectric"
WHITE = {"ks": 1.0, "kt": 1.0}


def _wi(mu: float) -> np.ndarray:
    return np.array([math.sqrt(1.0 - mu * mu), 0.0, mu])


@pytest.mark.parametrize("eta", [1.5, 1 / 1.5, 1.33, 2.4, 1 / 2.4, 1.05, 1 / 1.05, 20.0])
def test_white_furnace_from_above_within_one_percent(eta):
    mu = np.array([0.05, 0.2, 0.5, 0.8, 1.0])[:, None]
    alpha = np.array([1e-3, 0.01, 0.1, 0.3, 0.6, 1.0])[None, :]
    single = brdf_rs.albedo(BASE, mu, alpha=alpha, eta=eta, tol=5e-5, **WHITE)
    r = brdf_rs.albedo(MODEL, mu, alpha=alpha, eta=eta, tol=5e-5, **WHITE)
    # The test has teeth: the single scattering loses more than 1% somewhere here.
    assert single.value.min() < 0.97
    assert np.abs(r.value - 1.0).max() <= 0.01, r.value[..., 0]


@pytest.mark.parametrize("eta", [1.001, 1 / 1.001, 1 + 1e-5, 1 / (1 + 1e-5), 1e3, 1e-3, 1e7])
def test_white_furnace_at_grazing_incidence_near_and_far_from_one(eta):
    """Where the table's grazing layers are: an index near 1 (light from the denser side
    turned back across the surface, from the rarer side reflected whole) and far from it."""
    mu = np.array([1e-3, 3e-3, 0.01, 0.03, 0.1])[:, None]
    alpha = np.array([1e-3, 0.03, 0.3, 0.6, 1.0])[None, :]
    single = brdf_rs.albedo(BASE, mu, alpha=alpha, eta=eta, tol=5e-5, **WHITE)
    r = brdf_rs.albedo(MODEL, mu, alpha=alpha, eta=eta, tol=5e-5, **WHITE)
    assert single.value.min() < 0.97
    assert np.abs(r.value - 1.0).max() <= 0.01, r.value[..., 0]


@pytest.mark.parametrize(
    ("mu", "eta", "alpha"), [(-0.7, 1.5, 0.8), (-0.3, 1.5, 0.5), (-0.9, 1 / 1.5, 1.0)]
)
def test_white_furnace_from_below_by_sampling(mu, eta, alpha):
    """Light from the far side of the interface (the factor reads the table for 1/eta):
    the mean sample weight of the white interface is its albedo."""
    count = 1 << 18
    u = np.random.default_rng(7).random((count, 2))
    wi = np.broadcast_to(_wi(mu), (count, 3))
    _, single, _ = brdf_rs.sample(BASE, wi, u, eta=eta, alpha=alpha, **WHITE)
    _, weight, _ = brdf_rs.sample(MODEL, wi, u, eta=eta, alpha=alpha, **WHITE)
    assert single[:, 0].mean() < 0.97
    mean, stderr = weight[:, 0].mean(), weight[:, 0].std() / math.sqrt(count)
    assert abs(mean - 1.0) <= 0.01 + 4 * stderr, (mean, stderr)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("precision", ["accurate", "fast"])
def test_factor_depends_on_wi_alone_and_is_one_over_the_albedo(dtype, precision):
    rng = np.random.default_rng(11)
    k, per = 24, 16
    mu = np.concatenate([rng.uniform(0.1, 1.0, k // 2), -rng.uniform(0.1, 1.0, k // 2)])
    wi = np.repeat(np.stack([np.sqrt(1 - mu**2), np.zeros(k), mu], axis=-1), per, axis=0)
    wo = random_directions(rng, k * per)
    params = {"eta": 1.5, "alpha": 0.5, "ks": [1.0, 0.5, 0.2], "kt": [0.3, 1.0, 0.6]}
    args = (wi.astype(dtype), wo.astype(dtype))
    f = brdf_rs.eval(MODEL, *args, precision=precision, **params)
    g = brdf_rs.eval(BASE, *args, precision=precision, **params)
    valid = g[:, 0] > 0
    ratio = np.where(valid, f[:, 0] / np.where(valid, g[:, 0], 1.0), np.nan).reshape(k, per)
    assert (f[~valid] == 0).all()
    rtol = 1e-13 if dtype == np.float64 else 1e-6
    factor = np.nanmedian(ratio, axis=1)
    spread = np.nan_to_num(np.abs(ratio - factor[:, None]), nan=0.0)
    assert (spread <= rtol * factor[:, None]).all()
    # Every channel carries the same factor.
    np.testing.assert_allclose(f[valid], g[valid] * f[valid, :1] / g[valid, :1], rtol=rtol)
    # 1/E of wi's side: light from below sees the relative index 1/eta.
    eta_side = np.where(mu > 0, 1.5, 1 / 1.5)
    e = brdf_rs.albedo(BASE, np.abs(mu), eta=eta_side, alpha=0.5, tol=5e-5, **WHITE)
    np.testing.assert_allclose(factor * e.value[:, 0], 1.0, atol=0.01)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("precision", ["accurate", "fast"])
def test_uniform_and_per_row_parameters_give_the_same_bits(dtype, precision):
    """With uniform parameters the engine divides by E in a pass of its own; with
    parameters per row it evaluates the whole kernel per row: the same bits, including
    bad rows (NaN), rows below the surface, tilted normals and cosines below the float64
    range (which take the wide path)."""
    rng = np.random.default_rng(5)
    count = 3000
    wi, wo = random_directions(rng, count), random_directions(rng, count)
    n = random_directions(rng, count, unnormalized=False)
    wi[:5] = [[1, 0, 1e-310], [1, 0, -1e-310], [0, 0, 0], [np.nan, 0, 1], [1e-200, 0, 1e-200]]
    wo[5] = [1, 0, 1e-300]
    n[:6] = [0, 0, 1]
    params = {"eta": 1.33, "alpha": 0.3, "ks": [1.0, 0.5, 0.2], "kt": [0.3, 1.0, 0.6]}
    per_row = {**params, "eta": np.full(count, 1.33), "alpha": np.full(count, 0.3)}
    args = [a.astype(dtype) for a in (wi, wo, n)]
    kw = {"precision": precision, "check": False}
    uniform = brdf_rs.eval(MODEL, *args, **params, **kw)
    varying = brdf_rs.eval(MODEL, *args, **per_row, **kw)
    assert uniform.tobytes() == varying.tobytes()
    # A zero and a NaN vector are bad rows; in float32, 1e-200 rounds to 0 and is too.
    bad = 5 if dtype == np.float32 else 4
    assert np.isnan(uniform[2:bad]).all() and np.isfinite(uniform[bad:]).all()


def test_sampling_is_the_interface_s_with_scaled_weights():
    rng = np.random.default_rng(5)
    count = 4096
    wi = random_directions(rng, count)
    n = random_directions(rng, count, unnormalized=False)
    u = rng.random((count, 2))
    params = {
        "eta": 10 ** rng.uniform(-0.7, 0.7, count),
        "alpha": 10 ** rng.uniform(-3, 0, count),
        "ks": [1.0, 0.5, 0.25],
        "kt": [0.3, 1.0, 0.6],
    }
    wo, weight, pdf = brdf_rs.sample(MODEL, wi, u, n, **params)
    wo_b, weight_b, pdf_b = brdf_rs.sample(BASE, wi, u, n, **params)
    np.testing.assert_array_equal(wo, wo_b)
    np.testing.assert_array_equal(pdf, pdf_b)
    np.testing.assert_array_equal(
        brdf_rs.pdf(MODEL, wi, wo, n, **params), brdf_rs.pdf(BASE, wi, wo, n, **params)
    )
    valid = weight_b[:, 0] > 0
    assert valid.mean() > 0.5
    f = brdf_rs.eval(MODEL, wi, wo, n, **params)
    mu_o = np.abs(np.einsum("ij,ij->i", wo, n))
    want = f[valid] * mu_o[valid, None] / pdf[valid, None]
    rtol = 1e-10 + 4.0 * np.finfo(float).eps / mu_o[valid, None]
    assert (np.abs(weight[valid] - want) <= rtol * np.abs(want)).all()
    # The factor is at least 1 (E <= 1) and the same in every channel.
    ratio = weight[valid] / weight_b[valid]
    assert (ratio >= 1 - 1e-12).all()
    np.testing.assert_allclose(ratio, ratio[:, :1] * np.ones(3), rtol=1e-13)


@pytest.mark.parametrize("component", ["reflection", "transmission", "total"])
def test_albedo_parts_are_the_interface_s_times_the_factor(component):
    mu = np.array([0.1, 0.4, 0.9])
    params = {"eta": 1 / 1.4, "alpha": 0.4, "ks": [1.0, 0.5, 0.0], "kt": [0.2, 1.0, 0.7]}
    a = brdf_rs.albedo(MODEL, mu, component=component, samples=4096, **params)
    b = brdf_rs.albedo(BASE, mu, component=component, samples=4096, **params)
    wi = np.stack([np.sqrt(1 - mu**2), np.zeros(3), mu], axis=-1)
    wo = np.array([0.1, 0.2, 0.97])
    wo = wo / np.linalg.norm(wo)
    factor = (
        brdf_rs.eval(MODEL, wi, wo, **params)[:, 0] / brdf_rs.eval(BASE, wi, wo, **params)[:, 0]
    )
    np.testing.assert_allclose(a.value, b.value * factor[:, None], rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(a.stderr, b.stderr * factor[:, None], rtol=1e-12, atol=1e-300)


def test_eta_one_is_the_delta_unscaled(rng):
    wi = random_directions(rng, 500)
    wo = random_directions(rng, 500)
    kt = [0.2, 0.5, 1.0]
    assert (brdf_rs.eval(MODEL, wi, wo, eta=1.0, alpha=0.5) == 0.0).all()
    _, weight, pdf = brdf_rs.sample(MODEL, wi, rng.random((500, 2)), eta=1.0, alpha=0.5, kt=kt)
    np.testing.assert_array_equal(weight, np.broadcast_to(kt, weight.shape))
    assert np.isposinf(pdf).all()
    r = brdf_rs.albedo(MODEL, [0.2, 1.0], eta=1.0, alpha=0.5, kt=kt)
    np.testing.assert_array_equal(r.value, np.broadcast_to(kt, (2, 3)))


@pytest.mark.parametrize("alpha", [0.0, 5e-4, 1.01, 2.0])
def test_alpha_outside_the_table_is_refused(alpha):
    with pytest.raises(ValueError, match="alpha"):
        brdf_rs.eval(MODEL, [0, 0, 1], [0, 0, 1], alpha=alpha)
    with pytest.raises(ValueError, match="alpha"):
        brdf_rs.albedo(MODEL, 0.5, alpha=alpha)


def test_spec_facts():
    spec = brdf_rs.models()[MODEL]
    assert spec["transmission"] is True
    assert spec["reciprocal"] is False
    assert [p["name"] for p in spec["params"]] == ["ks", "kt", "eta", "alpha"]


def test_energy_table_is_the_furnace():
    """Its energy table over (mu, alpha, eta) is its white furnace: E = 1 within 1%, and
    E_avg likewise."""
    mu = np.array([0.1, 0.5, 0.9])
    alpha = np.array([0.05, 0.5, 1.0])
    eta = np.array([1 / 1.5, 1.5, 2.4])
    ec = brdf_rs.energy_compensation_table(MODEL, mu, alpha, eta=eta, tol=1e-4)
    single = brdf_rs.energy_compensation_table(BASE, mu, alpha, eta=eta, tol=1e-4)
    assert single.e.min() < 0.97
    assert np.abs(ec.e - 1.0).max() <= 0.01
    assert np.abs(ec.e_avg - 1.0).max() <= 0.01
