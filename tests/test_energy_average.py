"""``E_avg = 2 ∫ E(mu) mu dmu`` of the energy tables: the adaptive Gauss-Kronrod rule
(``_albedo._kronrod_average``) that integrates it over ``E`` cells of its own.

The rule is checked on functions whose integral is known exactly (smooth, with a bend,
with a jump), with noise-free and with noisy "cells"; its constants against NumPy's
Gauss-Legendre rule and against the degree a 15-point Kronrod rule integrates exactly;
then the tables' ``E_avg`` against a separate fine quadrature of ``albedo`` cells
where the 32-point rule the tables used to have was off by many standard errors.
"""

from __future__ import annotations

import itertools

import brdf_rs
import numpy as np
import pytest
from brdf_rs import _albedo


def test_gauss_kronrod_constants():
    x, wk, wg = _albedo._GK15
    xg, wgg = np.polynomial.legendre.leggauss(7)
    np.testing.assert_allclose(x[1::2], xg, rtol=0, atol=4e-16)
    np.testing.assert_allclose(wg[1::2], wgg, rtol=0, atol=4e-16)
    assert np.all(wg[::2] == 0) and np.all(np.diff(x) > 0)
    # The Kronrod rule integrates polynomials up to degree 22 (23 by symmetry) exactly,
    # the Gauss rule up to 13, and neither degree 24 / 14.
    for d in range(24):
        exact = (1 - (-1) ** (d + 1)) / (d + 1)
        assert abs(x**d @ wk - exact) < 1e-15, d
        if d < 14:
            assert abs(x**d @ wg - exact) < 1e-15, d
    assert abs(x**24 @ wk - 2 / 25) > 1e-9 and abs(x**14 @ wg - 2 / 15) > 1e-6


def synthetic(e, se=0.0, rng=None):
    """Cells of a known ``E(mu, column)``: the exact value (plus Gaussian noise of
    ``se`` when ``rng`` is given) and ``se`` as its standard error. Records the ids."""
    seen = []

    def cells(mu, ids, col):
        seen.append(ids.copy())
        value = e(mu, col[:, None])
        if rng is not None:
            value = value + se * rng.standard_normal(mu.shape)
        return value, np.full(mu.shape, se)

    return cells, seen


def kink(mu, col):
    """A bend at the critical cosine of eta = 0.67 (and 0.9 in column 1): E falls
    linearly below it, as a dielectric's from the denser side bends there."""
    c = np.where(col == 0, np.sqrt(1 - 0.67**2), np.sqrt(1 - 0.9**2))
    return 1 - 0.7 * np.maximum(c - mu, 0)


def kink_average(c):
    # 2 ∫_0^c (1 − 0.7 (c − mu)) mu dmu + (1 − c²) = 1 − 0.7 c³/3
    return 1 - 0.7 * c**3 / 3


@pytest.mark.parametrize("se", [0.0, 1e-9, 1e-6])
def test_a_bend_is_integrated_to_within_the_error_bar(se):
    """Noise-free, the halving closes in on the bend until the rule's error is rounding;
    with noise of se per cell, the value lands within its error bar (the noise of the
    sum, plus any rule error left) where 32-point Gauss-Legendre is many se off."""
    rng = np.random.default_rng(5) if se else None
    cells, seen = synthetic(kink, se, rng)
    value, bar = _albedo._kronrod_average(cells, 2, 100)
    exact = kink_average(np.sqrt(1 - np.array([0.67, 0.9]) ** 2))
    err = np.abs(value - exact)
    if se == 0:
        assert np.all(err <= 1e-13) and np.all(bar <= 1e-13), (err, bar)
    else:
        assert np.all(err <= 4 * bar), (err, bar)
        assert np.all(bar < 2 * se) and np.all(bar > se / 10)
    # 32-point Gauss-Legendre, noise-free, is off by far more than these bars.
    x, w = np.polynomial.legendre.leggauss(32)
    mu, w = (x + 1) / 2, w / 2
    gl = np.array([2 * (w * mu) @ kink(mu, np.array([c])) for c in (0, 1)])
    assert np.all(np.abs(gl - exact) > 1e-6)
    # Ids: unique, from first_id on, each column's within its own block.
    ids = np.concatenate([i.ravel() for i in seen])
    assert np.unique(ids).size == ids.size and ids.min() >= 100


def test_smooth_e_takes_two_panels():
    cells, seen = synthetic(lambda mu, col: 1 - 0.3 * mu**2 + 0 * col)
    value, bar = _albedo._kronrod_average(cells, 3, 0)
    np.testing.assert_allclose(value, 1 - 0.3 / 2, rtol=0, atol=1e-15)
    assert len(seen) == 1 and seen[0].shape == (6, 15)
    assert np.all(bar <= 1e-15)


def test_a_jump_is_kept_at_the_narrowest_panel_with_its_error_in_the_bar():
    """A jump is not smooth at any width: the panel holding it is halved down to the
    narrowest and kept there with |K − G| in the bar, which covers the error."""
    cells, seen = synthetic(lambda mu, col: np.where(mu < 0.3, 1.0, 0.5) + 0 * col)
    value, bar = _albedo._kronrod_average(cells, 1, 0)
    exact = 0.3**2 + 0.5 * (1 - 0.3**2)
    assert abs(value[0] - exact) <= bar[0] < 1e-6, (value - exact, bar)
    assert len(seen) == _albedo._GK_DEPTH


def test_each_column_is_reproducible_whatever_the_rest_of_the_grid():
    """A column's cells and value depend only on its own index: the same column alone
    or among others gets the same ids and bits."""

    def cells(mu, ids, col):
        # noise keyed by the id, as a cell's stream is
        noise = 1e-7 * np.sin(ids.astype(float) * 12.9898)
        return kink(mu, np.zeros_like(mu)) + noise, np.full(mu.shape, 1e-7)

    one, _ = _albedo._kronrod_average(cells, 1, 7)
    many, _ = _albedo._kronrod_average(cells, 4, 7)
    assert one[0] == many[0]


def test_dielectric_e_avg_from_the_denser_side_matches_a_fine_quadrature():
    """eta = 0.67, alpha = 0.8 at tol 3e-6: the 32-point rule the tables used was
    4.2e-6 off here (bend at the critical cosine; scripts/energy_quadrature_check.py),
    beyond its standard error. The adaptive rule's E_avg against 128-point
    Gauss-Legendre over direct albedo cells (other nodes, other streams): within 4
    combined standard errors."""
    model, alpha, eta, tol = "ggx_dielectric", 0.8, 0.67, 3e-6
    ec = brdf_rs.energy_compensation_table(model, [0.5], [alpha], eta=[eta], tol=tol, seed=2)
    x, w = np.polynomial.legendre.leggauss(128)
    mu, w = (x + 1) / 2, w / 2
    a = brdf_rs.albedo(model, mu, alpha=alpha, eta=eta, ks=1, kt=1, component="total", tol=tol)
    fine = 2 * np.sum(w * mu * a.value[:, 0])
    fine_se = 2 * np.sqrt(np.sum((w * mu * a.stderr[:, 0]) ** 2))
    se = np.hypot(fine_se, ec.e_avg_stderr[0, 0])
    assert abs(ec.e_avg[0, 0] - fine) <= 4 * se, (ec.e_avg[0, 0] - fine, se)


def test_progress_counts_carry_on_across_the_rounds():
    """The E_avg rounds report as one run: counts never fall back within it."""
    calls = []
    brdf_rs.energy_compensation_table(
        "ggx_dielectric",
        [0.5],
        [0.2],
        eta=[0.67],
        tol=1e-5,
        progress=lambda done, samples: calls.append((done, samples)),
    )
    # The E grid's run (one cell), then E_avg's rounds (30 cells and more).
    start = next(i for i, (done, _) in enumerate(calls) if done > 1)
    tail = calls[start:]
    assert all(b[0] >= a[0] and b[1] >= a[1] for a, b in itertools.pairwise(tail))
    assert tail[-1][0] > 30  # the bend from the denser side halves panels
