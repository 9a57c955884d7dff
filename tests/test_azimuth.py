"""The albedo of anisotropic models at any azimuth of ``wi``, and azimuth-averaged.

Convention: ``wi = (sin θ cos φ, sin θ sin φ, mu)`` with ``n = +z`` and the tangent
``+x`` (φ from the tangent, counterclockwise about ``n``).

The reference is an independent adaptive quadrature (``scipy.integrate.quad_vec`` over
the half vector's azimuth, Gauss-Legendre panels in its polar angle) of ``brdf_rs.eval``
over the hemisphere; it places ``wi`` itself and uses no symmetry of the models.
"""

from __future__ import annotations

import functools
import math

import brdf_rs
import numpy as np
import pytest

integrate = pytest.importorskip("scipy.integrate")
optimize = pytest.importorskip("scipy.optimize")

WARD = {"kd": 0.0, "ks": 1.0, "alpha_x": 0.12, "alpha_y": 0.45}
AS = {"Rd": 0.4, "Rs": 0.15, "nu": 12.0, "nv": 600.0}
CASES = [("ward", WARD), ("ashikhmin_shirley", AS)]

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(24)


def _wi(mu: float, phi: float) -> np.ndarray:
    s = math.sqrt((1 - mu) * (1 + mu))
    return np.array([s * math.cos(phi), s * math.sin(phi), mu])


def _kink(wi: np.ndarray, b: float, a_max: float) -> list[float]:
    """Polar angles of the half vector (azimuth b) where mu_o = mu_i, inside (0, a_max):
    Ashikhmin-Shirley's max(mu_i, mu_o) has a kink there."""
    cb, sb = math.cos(b), math.sin(b)

    def g(a: float) -> float:
        h = np.array([math.sin(a) * cb, math.sin(a) * sb, math.cos(a)])
        return float(2 * wi @ h * h[2] - 2 * wi[2])

    grid = np.linspace(0, a_max, 129)[1:-1]
    vals = [g(a) for a in grid]
    return [
        optimize.brentq(g, grid[k], grid[k + 1], xtol=1e-14)
        for k in range(len(grid) - 1)
        if vals[k] * vals[k + 1] < 0
    ]


def _inner(model: str, params: dict, wi: np.ndarray, width: float, b: float) -> np.ndarray:
    """∫ f(wi, wo) mu_o 4(wi·h) sin a da over the half vector's polar angle a at
    azimuth b, up to the horizon a_max(b) (Gauss-Legendre on graded panels)."""
    sin_t = math.hypot(wi[0], wi[1])
    c = (wi[0] * math.cos(b) + wi[1] * math.sin(b)) / sin_t if sin_t > 0 else 0.0
    a_max = 0.5 * (math.pi / 2 + math.atan2(sin_t * c, wi[2]))
    cuts = {0.0, a_max}
    cuts |= {width * 2.0**k for k in range(-3, 6) if width * 2.0**k < a_max}
    cuts |= {a_max * (1 - 2.0**-k) for k in range(1, 12)}
    if model == "ashikhmin_shirley":
        cuts |= set(_kink(wi, b, a_max))
    edges = np.array(sorted(cuts))
    lo, hi = edges[:-1, None], edges[1:, None]
    a = (0.5 * (hi - lo) * _NODES + 0.5 * (hi + lo)).ravel()
    w = (0.5 * (hi - lo) * _WEIGHTS).ravel()
    h = np.stack([np.sin(a) * math.cos(b), np.sin(a) * math.sin(b), np.cos(a)], axis=-1)
    wi_h = h @ wi
    wo = 2 * wi_h[:, None] * h - wi
    f = brdf_rs.eval(model, np.broadcast_to(wi, wo.shape), wo, **params)
    weight = np.where((wo[:, 2] > 0) & (wi_h > 0), wo[:, 2] * 4 * wi_h * np.sin(a) * w, 0.0)
    return np.asarray(weight @ f)


@functools.cache
def quadrature(model: str, mu: float, phi: float) -> tuple[np.ndarray, float]:
    """R(mu, φ) (RGB) and its error estimate, by quad_vec over the half vector's azimuth."""
    params = dict(CASES)[model]
    wi = _wi(mu, phi)
    if model == "ward":
        width = min(params["alpha_x"], params["alpha_y"])
    else:
        width = 1 / math.sqrt(max(params["nu"], params["nv"]) + 1)
    value, err = integrate.quad_vec(
        functools.partial(_inner, model, params, wi, width),
        0.0,
        2 * math.pi,
        epsabs=1e-8,
        epsrel=1e-8,
        points=[k * math.pi / 4 for k in range(1, 8)],
    )
    return np.asarray(value), float(err)


def _agree(r: brdf_rs.Albedo, want: np.ndarray, want_err: float, label: str) -> None:
    err = np.abs(r.value - want)
    bound = 5 * r.stderr + 2 * want_err + 1e-9
    assert np.all(err <= bound), f"{label}: {r.value} vs {want} (stderr {r.stderr})"


POINTS = [(0.9, 0.0), (0.5, 0.6), (0.3, math.pi / 2), (0.7, 2.2), (0.2, -1.0), (0.6, math.pi)]


@pytest.mark.parametrize(("model", "params"), CASES)
def test_albedo_at_any_azimuth_matches_quadrature(model: str, params: dict) -> None:
    mus = np.array([m for m, _ in POINTS])
    phis = np.array([p for _, p in POINTS])
    r = brdf_rs.albedo(model, mus, phi=phis, samples=1 << 16, **params)
    for k, (mu, phi) in enumerate(POINTS):
        want, err = quadrature(model, mu, phi)
        one = brdf_rs.Albedo(r.value[k], r.stderr[k], r.samples[k])
        _agree(one, want, err, f"{model} mu={mu} phi={phi}")
    # The test has teeth: the albedo really depends on φ here, by many error bars.
    at_0, at_90 = quadrature(model, 0.3, 0.0)[0], quadrature(model, 0.3, math.pi / 2)[0]
    se = float(r.stderr.max())
    assert np.max(np.abs(at_0 - at_90)) > 50 * se, (at_0, at_90, se)


@pytest.mark.parametrize(("model", "params"), CASES)
def test_the_models_symmetries_in_azimuth(model: str, params: dict) -> None:
    """R(φ) = R(−φ) = R(π − φ) = R(φ + π): first by the quadrature (which uses none of
    them), then by the integrator at independent seeds (it does not reduce φ itself)."""
    mu, phi = 0.45, 0.7
    want, err = quadrature(model, mu, phi)
    for other in (-phi, math.pi - phi, phi + math.pi, phi - 2 * math.pi):
        got, got_err = quadrature(model, mu, other)
        assert np.max(np.abs(got - want)) <= 2 * (err + got_err) + 1e-9, (other, got, want)
    base = brdf_rs.albedo(model, mu, phi=phi, samples=1 << 14, seed=1, **params)
    for seed, other in enumerate((-phi, math.pi - phi, phi + math.pi), start=2):
        r = brdf_rs.albedo(model, mu, phi=other, samples=1 << 14, seed=seed, **params)
        bound = 5 * np.hypot(base.stderr, r.stderr)
        assert np.all(np.abs(r.value - base.value) <= bound), (other, r.value, base.value)


@pytest.mark.parametrize(("model", "params"), CASES)
def test_fold_at_zero_and_pi_agrees_with_the_full_circle(model: str, params: dict) -> None:
    mus = np.array([0.25, 0.8])
    for phi in (0.0, math.pi):
        folded = brdf_rs.albedo(model, mus, phi=phi, samples=1 << 14, seed=3, **params)
        full = brdf_rs.albedo(
            model, mus, phi=phi, samples=1 << 14, seed=4, fold_azimuth=False, **params
        )
        bound = 5 * np.hypot(folded.stderr, full.stderr)
        assert np.all(np.abs(folded.value - full.value) <= bound), (phi, folded, full)


@pytest.mark.parametrize(("model", "params"), CASES)
def test_phi_zero_is_the_default_bit_for_bit(model: str, params: dict) -> None:
    # Scalars stay scalars: a 0-d phi adds no cell dimension.
    for phi in (0.0, np.float64(0.3), np.array(1.0)):
        r = brdf_rs.albedo(model, 0.5, phi=phi, samples=64, **params)
        assert r.value.shape == (3,) and r.samples.shape == ()
    r = brdf_rs.albedo(model, 0.5, phi=np.array([0.0, 1.0])[::-1], samples=64, **params)
    assert r.value.shape == (2, 3)
    mus = np.linspace(0.05, 1.0, 7)
    plain = brdf_rs.albedo(model, mus, samples=1024, **params)
    zero = brdf_rs.albedo(model, mus, phi=np.zeros(7), samples=1024, **params)
    assert np.array_equal(plain.value, zero.value)
    assert np.array_equal(plain.stderr, zero.stderr)


def _trapezoid_average(model: str, mu: float, n: int) -> tuple[np.ndarray, float]:
    """(1/2π) ∫ R(mu, φ) dφ by the periodic trapezoid rule on n nodes (n a multiple of
    4), each node's R computed at its azimuth folded onto [0, π/2] by the symmetries
    that test_the_models_symmetries_in_azimuth checks by quadrature."""
    values = []
    for k in range(n):
        j = k % (n // 2)  # R(φ + π) = R(φ)
        j = min(j, n // 2 - j)  # R(π − φ) = R(φ)
        values.append(quadrature(model, mu, 2 * math.pi * j / n))
    return np.mean([v for v, _ in values], axis=0), max(e for _, e in values)


@pytest.mark.parametrize(("model", "params"), CASES)
def test_azimuth_average_matches_quadrature(model: str, params: dict) -> None:
    mus = [0.3, 0.75]
    r = brdf_rs.albedo(model, np.array(mus), phi="average", samples=1 << 16, **params)
    for k, mu in enumerate(mus):
        coarse, _ = _trapezoid_average(model, mu, 24)
        fine, err = _trapezoid_average(model, mu, 48)
        # The periodic trapezoid rule converges geometrically: the halving is its error.
        rule = float(np.max(np.abs(fine - coarse)))
        one = brdf_rs.Albedo(r.value[k], r.stderr[k], r.samples[k])
        _agree(one, fine, err + rule, f"{model} mu={mu} average")
        # The average is not the value at φ = 0 (the option does something).
        at_0 = quadrature(model, mu, 0.0)[0]
        assert np.max(np.abs(at_0 - fine)) > 10 * float(r.stderr[k].max())


ISOTROPIC = [
    ("ggx", {"kd": 0.2, "ks": 1.0, "alpha": 0.3}),
    ("oren_nayar", {"kd": 0.8, "sigma": 0.5}),
    ("torrance_sparrow", {"kd": 0.0, "ks": 1.0, "p": 40.0, "eta": 1.5}),
    ("normalized_phong", {"kd": 0.0, "ks": 1.0, "p": 30.0}),
]


@pytest.mark.parametrize(("model", "params"), ISOTROPIC)
def test_isotropic_models_ignore_phi_bit_for_bit(model: str, params: dict) -> None:
    mus = np.linspace(0.05, 1.0, 5)
    plain = brdf_rs.albedo(model, mus, samples=2048, **params)
    for phi in (0.7, np.linspace(-3, 9, 5), "average"):
        r = brdf_rs.albedo(model, mus, phi=phi, samples=2048, **params)
        assert np.array_equal(r.value, plain.value), phi
        assert np.array_equal(r.stderr, plain.stderr), phi
        assert np.array_equal(r.samples, plain.samples), phi


@pytest.mark.parametrize(
    ("phi", "error"),
    [
        (float("nan"), ValueError),
        (float("inf"), ValueError),
        (np.array([0.0, -np.inf]), ValueError),
        (np.zeros(3), ValueError),  # does not broadcast with mu's (2,)
        ("avg", ValueError),
        (None, TypeError),
        ([[0.0], ["x"]], TypeError),
    ],
)
def test_bad_phi_is_an_error_naming_phi(phi: object, error: type) -> None:
    for model, params in (CASES[0], ISOTROPIC[0]):
        with pytest.raises(error, match="phi"):
            brdf_rs.albedo(model, np.array([0.2, 0.5]), phi=phi, samples=64, **params)


def test_table_with_a_phi_axis_and_the_average() -> None:
    mu = np.array([0.3, 0.8])
    phi = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    args = {"samples": 1 << 14, "alpha_y": 0.45, "kd": 0.0, "ks": 1.0}
    table = brdf_rs.albedo_table("ward", {"mu": mu, "phi": phi, "alpha_x": [0.12]}, **args)
    assert table.value.shape == (2, 8, 1, 3)
    assert np.array_equal(table.axes["phi"], phi)
    # Symmetric azimuths share a computed cell; every cell agrees with the quadrature.
    assert np.array_equal(table.value[:, 1], table.value[:, 3])  # π/4 and 3π/4
    assert np.array_equal(table.value[:, 0], table.value[:, 4])  # 0 and π
    for i, m in enumerate(mu):
        for j, p in enumerate(phi):
            want, err = quadrature("ward", float(m), float(p))
            one = brdf_rs.Albedo(table.value[i, j, 0], table.stderr[i, j, 0], 0)
            _agree(one, want, err, f"table mu={m} phi={p}")
    average = brdf_rs.albedo_table("ward", {"mu": mu}, phi="average", alpha_x=0.12, **args)
    assert average.meta["fixed"]["phi"] == "average"
    direct = brdf_rs.albedo("ward", mu, phi="average", alpha_x=0.12, **args)
    assert np.array_equal(average.value, direct.value)


def test_isotropic_table_phi_axis_costs_one_cell() -> None:
    axes = {"mu": [0.2, 0.6], "p": [5.0, 50.0]}
    args = {"samples": 1024, "kd": 0.0, "ks": 1.0}
    plain = brdf_rs.albedo_table("normalized_phong", axes, **args)
    with_phi = brdf_rs.albedo_table("normalized_phong", {**axes, "phi": [0.0, 1.0, 2.0]}, **args)
    assert with_phi.value.shape == (2, 2, 3, 3)
    for k in range(3):
        # One computed cell per (mu, p), copied along phi (its cell id is the first
        # phi entry's in the full grid, so it is not the plain table's cell).
        assert np.array_equal(with_phi.value[:, :, k], with_phi.value[:, :, 0])
        bound = 5 * np.hypot(with_phi.stderr[:, :, k], plain.stderr)
        assert np.all(np.abs(with_phi.value[:, :, k] - plain.value) <= bound)


def test_cli_phi_in_degrees_and_average(tmp_path) -> None:
    import json
    import os
    import subprocess
    import sys

    common = ["-q", "--json", "-p", "alpha_x=0.12", "-p", "alpha_y=0.45", "--samples", "1024"]

    def table(*args: str) -> tuple[dict, brdf_rs.Table]:
        out = tmp_path / f"t{len(list(tmp_path.iterdir()))}.npz"
        result = subprocess.run(
            [sys.executable, "-m", "brdf_rs", "table", "ward", *args, "-o", str(out), *common],
            capture_output=True,
            text=True,
            env={**os.environ, "BRDF_RS_NUM_THREADS": "2"},
            check=True,
        )
        return json.loads(result.stdout), brdf_rs.Table.load(out)

    mu = np.array([0.3, 0.8])
    args = {"alpha_x": 0.12, "alpha_y": 0.45, "samples": 1024}
    _, t = table("--axis", "mu=0.3,0.8", "--axis", "phi=0,30,90")
    np.testing.assert_allclose(t.axes["phi"], np.radians([0, 30, 90]))
    want = brdf_rs.albedo_table("ward", {"mu": mu, "phi": np.radians([0, 30, 90])}, **args)
    np.testing.assert_array_equal(t.value, want.value)
    _, t = table("--axis", "mu=0.3,0.8", "--phi", "average")
    want = brdf_rs.albedo_table("ward", {"mu": mu}, phi="average", **args)
    np.testing.assert_array_equal(t.value, want.value)
    _, t = table("--axis", "mu=0.3,0.8", "--phi", "60")
    want = brdf_rs.albedo_table("ward", {"mu": mu}, phi=np.radians(60), **args)
    np.testing.assert_array_equal(t.value, want.value)
    bad = subprocess.run(
        [sys.executable, "-m", "brdf_rs", "table", "ward", "--phi", "sideways"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert bad.returncode != 0 and "phi" in bad.stderr


def test_dask_blocks_of_a_phi_axis_have_the_local_bits() -> None:
    """brdf_rs.dask's blocks (computed here without a scheduler, so without dask) use
    the local build's azimuth cells and ids: the same bits for any chunking."""
    from brdf_rs import _grid
    from brdf_rs import dask as brdf_dask

    axes = {
        "mu": np.array([0.2, 0.5, 0.9]),
        "phi": np.linspace(0, 2 * np.pi, 8, endpoint=False),
        "alpha_x": np.array([0.1, 0.3]),
    }
    fixed = {"alpha_y": 0.4}
    options = {"samples": 512, "sampler": "auto", "sequence": "sobol", "seed": 3}
    options |= {"tol": None, "max_samples": None, "replicates": 16}
    local = brdf_rs.albedo_table("ward", axes, **fixed, samples=512, seed=3)
    names, coords, colour = _grid.table_axes("ward", axes, fixed)
    for chunks in [((3,), (8,), (2,)), ((1, 2), (3, 3, 2), (1, 1))]:
        plan = brdf_dask._Plan("ward", names, colour, coords, fixed, options, chunks, "t")
        value = np.full_like(local.value, np.nan)
        for _, block in plan.blocks():
            value[block.region()] = brdf_dask._compute_block(block)[0]
        assert np.array_equal(value, local.value), chunks
