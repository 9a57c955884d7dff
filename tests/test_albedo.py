"""Directional albedo: closed forms, a deterministic quadrature, honest error bars,
convergence rates, determinism, tables, split-sum tables, energy checks, errors."""

from __future__ import annotations

import math

import brdf_rs
import numpy as np
import pytest
import quadrature


def within(result, want, sigmas=5.0, floor=1e-12):
    err = np.abs(result.value - want)
    return bool(np.all(err <= sigmas * result.stderr + floor))


# ---------------------------------------------------------------------- closed forms


def test_lambert_is_kd_exactly():
    r = brdf_rs.albedo("lambert", [0.1, 0.5, 1.0], kd=[0.2, 0.4, 0.6])
    np.testing.assert_array_equal(r.value, np.tile([0.2, 0.4, 0.6], (3, 1)))
    assert (r.stderr == 0).all() and (r.samples == 0).all()


@pytest.mark.parametrize("p", [1.0, 10.0, 100.0, 1e3, 1e4])
def test_normal_incidence_closed_forms(p):
    base = {"kd": 0.0, "ks": 1.0, "p": p, "samples": 1 << 14}
    r = brdf_rs.albedo("normalized_phong", 1.0, **base)
    assert within(r, 1.0) and r.stderr.max() < 1e-4, r
    r = brdf_rs.albedo("modified_phong", 1.0, **base)
    assert within(r, 2 * math.pi / (p + 2)) and r.stderr.max() < 1e-4, r
    exact = (p + 8) * (p + 2 ** (-p / 2)) / ((p + 2) * (p + 4))
    r = brdf_rs.albedo("normalized_blinn_phong", 1.0, **base)
    assert within(r, exact) and r.stderr.max() < 1e-4, r


@pytest.mark.parametrize("sigma", [0.0, 0.3, 1.0, math.pi / 2])
def test_oren_nayar_at_normal_incidence_is_a(sigma):
    a = 1 - 0.5 * sigma**2 / (sigma**2 + 0.33)
    r = brdf_rs.albedo("oren_nayar", 1.0, kd=0.8, sigma=sigma, samples=4096)
    assert within(r, 0.8 * a), r
    if sigma == 0:
        assert (r.samples == 0).all() and (r.stderr == 0).all()


def test_zero_weight_lobes_are_skipped():
    spec_only = brdf_rs.albedo("torrance_sparrow", 0.5, kd=0.0, ks=1.0, p=20)
    diffuse_only = brdf_rs.albedo("torrance_sparrow", 0.5, kd=0.3, ks=0.0, p=20)
    assert diffuse_only.samples == 0 and (diffuse_only.value == 0.3).all()
    assert spec_only.samples > 0


# ---------------------------------------------------------------------- quadrature

QUADRATURE_CASES = [
    ("torrance_sparrow", {"kd": 0.0, "ks": 1.0, "eta": 1.5}, "p", [1.0, 30.0, 1e3, 1e4]),
    ("torrance_sparrow", {"kd": 0.1, "ks": [0.9, 0.5, 0.2], "eta": 3.0}, "p", [5.0, 300.0]),
    ("normalized_phong", {"kd": 0.0, "ks": 1.0}, "p", [1.0, 10.0, 100.0, 1e4]),
    ("phong", {"kd": 0.05, "ks": 0.5}, "p", [2.5, 60.0]),
    ("modified_blinn_phong", {"kd": 0.0, "ks": 1.0}, "p", [0.5, 40.0]),
    ("normalized_blinn_phong", {"kd": 0.2, "ks": 0.7}, "p", [3.0, 500.0]),
    ("blinn_phong_fresnel", {"kd": 0.1, "ks": [0.04, 0.5, 0.9]}, "p", [8.0, 200.0]),
    ("oren_nayar", {"kd": [0.9, 0.5, 0.1]}, "sigma", [0.2, 0.8, 1.5]),
]
MUS = [0.02, 0.2, 0.5, 0.85, 1.0]


@pytest.fixture(scope="module")
def quadrature_cells():
    """(model, params, mu, exact RGB) for a spread of models, incidences, parameters."""
    cells = []
    for model, fixed, name, values in QUADRATURE_CASES:
        for v in values:
            params = {**fixed, name: v}
            for mu in MUS:
                cells.append(
                    (model, params, mu, quadrature.directional_albedo(model, mu, **params))
                )
    return cells


@pytest.mark.parametrize("sequence", ["sobol", "random"])
def test_monte_carlo_agrees_with_quadrature(quadrature_cells, sequence):
    inside, beyond6 = 0, []
    channels = 0
    for k, (model, params, mu, exact) in enumerate(quadrature_cells):
        r = brdf_rs.albedo(model, mu, samples=1 << 13, sequence=sequence, seed=k, **params)
        err = np.abs(r.value - exact)
        inside += int(np.sum(err <= 4 * r.stderr + 1e-6))
        channels += 3
        if np.any(err > 6 * r.stderr + 1e-12):
            beyond6.append((model, params, mu, r.value, r.stderr, exact))
    assert inside >= 0.99 * channels, (inside, channels)
    assert not beyond6, beyond6


# ------------------------------------------------------------- honest error bars


@pytest.mark.parametrize("sequence", ["sobol", "random"])
@pytest.mark.parametrize(
    ("model", "params", "mu"),
    [
        ("torrance_sparrow", {"kd": 0.0, "ks": 1.0, "p": 40.0, "eta": 1.5}, 0.3),
        ("normalized_phong", {"kd": 0.0, "ks": 1.0, "p": 20.0}, 0.7),
        ("oren_nayar", {"kd": 1.0, "sigma": 1.0}, 0.4),
    ],
)
def test_error_bars_cover_the_truth(model, params, mu, sequence):
    exact = quadrature.directional_albedo(model, mu, **params)[0]
    seeds = 400
    # One call: 400 cells with distinct ids are 400 independent estimates.
    r = brdf_rs.albedo(model, np.full(seeds, mu), samples=1024, sequence=sequence, **params)
    z = np.abs(r.value[:, 0] - exact) / r.stderr[:, 0]
    coverage = np.mean(z <= 2)
    assert 0.90 <= coverage <= 0.99, coverage


# ------------------------------------------------------------------ convergence


def _rms_error(model, params, mu, exact, samples, sequence, sampler="auto", seeds=64):
    r = brdf_rs.albedo(
        model, np.full(seeds, mu), samples=samples, sequence=sequence, sampler=sampler, **params
    )
    return float(np.sqrt(np.mean((r.value[:, 0] - exact) ** 2))), float(np.mean(r.stderr[:, 0]))


def _slope(ns, errs):
    return float(np.polyfit(np.log(ns), np.log(errs), 1)[0])


def test_random_error_falls_as_inverse_square_root():
    model, params, mu = "normalized_phong", {"kd": 0.0, "ks": 1.0, "p": 30.0}, 0.6
    exact = quadrature.directional_albedo(model, mu, **params)[0]
    ns = [256, 1024, 4096, 16384]
    stderrs = [_rms_error(model, params, mu, exact, n, "random")[1] for n in ns]
    assert -0.55 < _slope(ns, stderrs) < -0.45


def test_sobol_error_falls_faster_on_a_smooth_integrand():
    # Oren-Nayar with cosine sampling: smooth in the sample coordinates.
    model, params, mu = "oren_nayar", {"kd": 1.0, "sigma": 0.7}, 0.6
    exact = quadrature.directional_albedo(model, mu, **params)[0]
    ns = [512, 2048, 8192, 32768]
    rms = [_rms_error(model, params, mu, exact, n, "sobol")[0] for n in ns]
    slope = _slope(ns, rms)
    assert slope < -0.8, (slope, rms)


def test_importance_sampling_beats_cosine_and_uniform_on_glossy_lobes():
    model, params, mu = "torrance_sparrow", {"kd": 0.0, "ks": 1.0, "p": 200.0}, 0.5
    errs = {
        s: _rms_error(model, params, mu, 0.0, 4096, "random", sampler=s)[1]
        for s in ("importance", "cosine", "uniform")
    }
    assert errs["importance"] < 0.2 * errs["cosine"], errs
    assert errs["importance"] < 0.2 * errs["uniform"], errs


# ------------------------------------------------------------------ determinism


def test_same_seed_same_bits_for_any_thread_count_and_chunking():
    mu = np.linspace(0.05, 1.0, 12)
    p = np.geomspace(1, 1e3, 9)
    args = {"kd": 0.0, "ks": 1.0, "eta": 1.5, "samples": 2048, "seed": 3}
    before = brdf_rs.num_threads()
    try:
        results = []
        for threads in (1, 2):
            brdf_rs.set_num_threads(threads)
            results.append(brdf_rs.albedo("torrance_sparrow", mu[:, None], p=p, **args))
    finally:
        brdf_rs.set_num_threads(before)
    np.testing.assert_array_equal(results[0].value, results[1].value)
    np.testing.assert_array_equal(results[0].stderr, results[1].stderr)
    # A chunk computed alone, keyed by its global cell ids, gives the same bits.
    ids = np.arange(mu.size * p.size, dtype=np.uint64).reshape(mu.size, p.size)
    chunk = brdf_rs.albedo(
        "torrance_sparrow", mu[3:7, None], p=p[2:5], cell_ids=ids[3:7, 2:5].copy(), **args
    )
    np.testing.assert_array_equal(chunk.value, results[0].value[3:7, 2:5])
    # And adaptive stopping is per cell, so also chunk-independent.
    full = brdf_rs.albedo(
        "normalized_phong", mu[:, None], p=p, tol=2e-4, samples=256, seed=1, kd=0, ks=1
    )
    part = brdf_rs.albedo(
        "normalized_phong",
        mu[:4, None],
        p=p,
        tol=2e-4,
        samples=256,
        seed=1,
        kd=0,
        ks=1,
        cell_ids=ids[:4].copy(),
    )
    np.testing.assert_array_equal(part.value, full.value[:4])
    np.testing.assert_array_equal(part.samples, full.samples[:4])


def test_adaptive_cells_stop_where_they_converge():
    r = brdf_rs.albedo(
        "torrance_sparrow", [0.05, 0.9], p=1000.0, kd=0, ks=1, tol=1e-4, samples=256, seed=0
    )
    assert (r.stderr <= 1e-4).all()
    assert r.samples[0] > r.samples[1]  # the grazing cell needs more


def test_relative_tolerance_holds_each_cell_to_its_own_value():
    """``rtol``: each cell stops once every channel's standard error is within ``rtol`` of
    its own value. Over albedos that span decades (a near-matched interface: 0.29 at
    grazing incidence, 0.02 at mu = 0.5) one absolute ``tol`` overspends on the bright
    cell and leaves the dim one at a larger relative error; ``rtol`` does neither. With
    both, the bound is ``tol + rtol·|value|`` (looser than either: no more samples than
    either). The table records ``rtol``; same seed, same bits."""
    mu = [0.05, 0.5]
    args = {"p": 10.0, "eta": 1.05, "kd": 0, "ks": [1.0, 0.5, 0.25], "samples": 256, "seed": 0}
    rel = brdf_rs.albedo("torrance_sparrow", mu, rtol=0.01, **args)
    assert (rel.stderr <= 0.01 * rel.value).all()
    assert rel.value[0, 0] > 10 * rel.value[1, 0]
    absolute = brdf_rs.albedo("torrance_sparrow", mu, tol=1e-3, **args)
    assert absolute.stderr[1, 0] > 0.01 * absolute.value[1, 0]  # the dim cell's error
    assert rel.samples[0] < absolute.samples[0]  # the bright cell's cost
    both = brdf_rs.albedo("torrance_sparrow", mu, tol=1e-3, rtol=0.01, **args)
    assert (both.stderr <= 1e-3 + 0.01 * both.value).all()
    assert (both.samples <= np.minimum(rel.samples, absolute.samples)).all()
    again = brdf_rs.albedo("torrance_sparrow", mu, rtol=0.01, **args)
    np.testing.assert_array_equal(again.value, rel.value)
    table = brdf_rs.albedo_table("torrance_sparrow", {"mu": mu}, rtol=0.01, **args)
    np.testing.assert_array_equal(table.value, rel.value)
    assert table.meta["rtol"] == 0.01
    assert "rtol" not in brdf_rs.albedo_table("lambert", {"mu": mu}, samples=64).meta


# ---------------------------------------------------------------------- tables


def test_table_shapes_metadata_and_round_trip(tmp_path):
    table = brdf_rs.albedo_table(
        "torrance_sparrow",
        {"mu": np.linspace(0.1, 1, 5), "p": [1.0, 10.0, 100.0]},
        kd=0.0,
        ks=[1.0, 0.5, 0.25],
        samples=512,
    )
    assert table.value.shape == (5, 3, 3) and table.stderr.shape == (5, 3, 3)
    assert list(table.axes) == ["mu", "p"]
    assert (
        table.meta["model"] == "torrance_sparrow" and table.meta["brdf_rs"] == brdf_rs.__version__
    )
    np.testing.assert_allclose(table.value[..., 1], 0.5 * table.value[..., 0], rtol=1e-12)
    path = table.save(tmp_path / "t.npz")
    back = brdf_rs.Table.load(path)
    np.testing.assert_array_equal(back.value, table.value)
    np.testing.assert_array_equal(back.axes["p"], table.axes["p"])
    assert back.meta == table.meta
    png = table.save(tmp_path / "t.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="unknown table format"):
        table.save(tmp_path / "t.txt")


def test_exr_output(tmp_path):
    OpenEXR = pytest.importorskip("OpenEXR")
    table = brdf_rs.albedo_table(
        "normalized_phong", {"mu": [0.2, 0.6, 1.0], "p": [2.0, 20.0]}, samples=256
    )
    path = table.save(tmp_path / "t.exr")
    with OpenEXR.File(str(path)) as f:
        rgb = f.channels()["RGB"].pixels
    np.testing.assert_allclose(rgb, table.value.astype(np.float32))


def test_progress_and_interrupt_leave_the_process_usable():
    calls = []

    def progress(cells, samples):
        calls.append((cells, samples))
        if len(calls) == 2:
            raise KeyboardInterrupt

    mu = np.linspace(0.01, 1, 64)
    with pytest.raises(KeyboardInterrupt):
        brdf_rs.albedo(
            "torrance_sparrow",
            mu[:, None],
            p=np.geomspace(1, 1e4, 64),
            samples=1 << 16,
            progress=progress,
        )
    assert len(calls) == 2
    r = brdf_rs.albedo("lambert", 0.5, kd=0.25)
    assert (r.value == 0.25).all()


# --------------------------------------------------------------- DFG and energy


def test_dfg_scale_and_bias_reproduce_the_specular_albedo():
    mu = np.array([0.1, 0.5, 1.0])
    p = np.array([4.0, 64.0])
    dfg = brdf_rs.dfg_table("blinn_phong_fresnel", mu, p, samples=1 << 14)
    for f0 in (0.04, 0.5):
        direct = brdf_rs.albedo(
            "blinn_phong_fresnel", mu[:, None], kd=0, ks=f0, p=p, samples=1 << 14
        )
        split = f0 * dfg.value[..., 0] + dfg.value[..., 1]
        tol = 5 * (direct.stderr[..., 0] + dfg.stderr[..., 0] + dfg.stderr[..., 1]) + 1e-9
        assert np.all(np.abs(split - direct.value[..., 0]) <= tol)
    with pytest.raises(ValueError, match="Schlick-Fresnel"):
        brdf_rs.dfg_table("phong", mu, p)


def test_energy_finds_the_normalized_blinn_phong_gain():
    gain = brdf_rs.energy("normalized_blinn_phong", kd=0, ks=1, p=2.0)
    assert gain.gains_energy and gain.mu_at_max == 1.0
    exact = (2 + 8) * (2 + 2**-1) / ((2 + 2) * (2 + 4))
    assert abs(gain.max[0] - exact) < 5 * gain.stderr[0] + 1e-9
    none = brdf_rs.energy("normalized_phong", kd=0, ks=1, p=2.0)
    assert not none.gains_energy
    assert none.max[0] <= 1.0 + 5 * none.stderr[0]


# ---------------------------------------------------------------------- errors


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"mu": 1.5}, ValueError, r"mu = 1.5 is out of range: must be in \[0, 1\]"),
        ({"mu": [0.5, -0.1]}, ValueError, r"mu\[1\] = -0.1 is out of range"),
        ({"p": float("nan")}, ValueError, r"p = nan is out of range"),
        ({"samples": 0}, ValueError, r"samples: expected an integer from 1 to 2\*\*40, got 0"),
        ({"samples": 2**41}, ValueError, r"samples: expected an integer from 1 to 2\*\*40"),
        ({"samples": 2.5}, TypeError, r"samples: expected an integer"),
        ({"tol": 0.0}, ValueError, r"tol: must be a positive number"),
        (
            {"sampler": "magic"},
            ValueError,
            r'sampler: expected "auto", "importance", "cosine" or "uniform"; got "magic"',
        ),
        (
            {"sequence": "halton"},
            ValueError,
            r'sequence: expected "sobol" or "random"; got "halton"',
        ),
        ({"replicates": 1}, ValueError, r"replicates: expected an integer from 2 to 4096"),
    ],
)
def test_bad_albedo_arguments(kwargs, error, message):
    args = {"mu": 0.5, **kwargs}
    mu = args.pop("mu")
    with pytest.raises(error, match=message):
        brdf_rs.albedo("torrance_sparrow", mu, **args)


def test_absurd_requests_are_refused_up_front():
    with pytest.raises(ValueError, match=r"the request asks for up to .* samples"):
        brdf_rs.albedo("torrance_sparrow", np.linspace(0, 1, 100_000), samples=2**30)


def test_family_b_terms_have_no_albedo():
    with pytest.raises(ValueError, match="albedo is defined for family-A BRDFs"):
        brdf_rs.albedo("phong_specular", 0.5)


def test_the_albedo_at_exactly_mu_0_is_0_for_every_model():
    """At mu = 0 the light lies in the surface's plane, where ``f`` is 0 (``eval`` says
    so): the albedo is 0 exactly, not the limit of one term (the diffuse ones gave kd, the
    lobes 0, Oren-Nayar either depending on sigma), and the table's row at 0 agrees."""
    from conftest import FAMILY_A

    for model in FAMILY_A:
        result = brdf_rs.albedo(model, [0.0, 1e-9])
        assert result.value[0].tolist() == [0.0, 0.0, 0.0], model
        assert result.stderr[0].tolist() == [0.0, 0.0, 0.0], model
        wi = [1.0, 0.0, 0.0]
        assert brdf_rs.eval(model, wi, [0.3, 0.2, 0.9]).tolist() == [0.0, 0.0, 0.0], model
    assert brdf_rs.albedo("lambert", 1e-9, kd=0.2).value[0] == pytest.approx(0.2)
