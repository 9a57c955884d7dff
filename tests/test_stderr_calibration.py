"""scripts/stderr_calibration.py: its reference cubature against closed forms and
independent integrals, its z statistics, and a quick end-to-end run (so the script
cannot silently rot)."""

from __future__ import annotations

import importlib.util
import itertools
import json
import math
import sys
from pathlib import Path

import brdf_rs
import numpy as np
import pytest
import quadrature
from conftest import fresnel

SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "stderr_calibration.py"
_spec = importlib.util.spec_from_file_location("stderr_calibration", SCRIPT)
assert _spec is not None and _spec.loader is not None
sc = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = sc  # dataclasses look their module up there
_spec.loader.exec_module(sc)


def gauss_panels(f, edges, n=32):
    """∫ f over the union of the panels ``edges`` by n-node Gauss-Legendre each."""
    x, w = np.polynomial.legendre.leggauss(n)
    total = 0.0
    for a, b in itertools.pairwise(edges):
        t = 0.5 * (a + b) + 0.5 * (b - a) * x
        total += 0.5 * (b - a) * float(f(t) @ w)
    return total


# ------------------------------------------------------------- cubature: closed forms


@pytest.mark.parametrize("mu", [1.0, 0.6, 0.05])
def test_lambert_albedo_is_kd(mu):
    assert sc.reference_albedo("lambert", mu, {"kd": 0.3}) == pytest.approx(0.3, abs=1e-14)


@pytest.mark.parametrize("mu", [1.0, 0.3, 0.02])
def test_oren_nayar_at_sigma_zero_is_lambert(mu):
    got = sc.reference_albedo("oren_nayar", mu, {"kd": 0.7, "sigma": 0.0})
    assert got == pytest.approx(0.7, abs=1e-14)


@pytest.mark.parametrize("sigma", [0.5, 1.2])
def test_oren_nayar_normal_incidence_is_kd_times_a(sigma):
    # θi = 0: b = min(θi, θo) = 0, tan b = 0, f = kd·A/π.
    a = 1 - 0.5 * sigma**2 / (sigma**2 + 0.33)
    got = sc.reference_albedo("oren_nayar", 1.0, {"kd": 1.0, "sigma": sigma})
    assert got == pytest.approx(a, abs=1e-14)


@pytest.mark.parametrize("mu", [0.3, 0.8])
def test_oren_nayar_against_its_one_dimensional_form(mu):
    # ∫_0^2π max(0, cos φ) dφ = 2 reduces the B term to one integral over θo, split at
    # θi (where max/min switch): R = kd·A + kd·B·(2/π)·∫ sin a·tan b·cos θo·sin θo dθo.
    sigma = 0.5
    a_coef = 1 - 0.5 * sigma**2 / (sigma**2 + 0.33)
    b_coef = 0.45 * sigma**2 / (sigma**2 + 0.09)
    ti = math.acos(mu)

    def g(t):
        return np.sin(np.maximum(t, ti)) * np.tan(np.minimum(t, ti)) * np.cos(t) * np.sin(t)

    edges = np.concatenate([np.linspace(0, ti, 9), np.linspace(ti, math.pi / 2, 9)[1:]])
    want = a_coef + b_coef * 2 / math.pi * gauss_panels(g, edges)
    got = sc.reference_albedo("oren_nayar", mu, {"kd": 1.0, "sigma": sigma})
    assert got == pytest.approx(want, abs=1e-13)


def test_ggx_alpha_one_normal_incidence_is_one_minus_ln2():
    # α = 1: D = 1/π, G2 = 2 mu_o/(1 + mu_o): R = ∫_0^1 mu/(1 + mu) dmu = 1 − ln 2.
    got = sc.reference_albedo("ggx", 1.0, {"kd": 0.0, "ks": 1.0, "alpha": 1.0})
    assert got == pytest.approx(1 - math.log(2), abs=1e-14)


@pytest.mark.parametrize(
    ("model", "params"),
    [
        ("torrance_sparrow", {"kd": 0.0, "ks": 1.0, "eta": 1.5, "p": 100.0}),
        ("ggx", {"kd": 0.0, "ks": 1.0, "alpha": 0.05}),
    ],
)
def test_normal_incidence_against_a_one_dimensional_rule(model, params):
    # At mu = 1 the integrand does not depend on φo: R = 2π ∫ f cos θo sin θo dθo.
    def g(t):
        wo = np.stack([np.sin(t), np.zeros_like(t), np.cos(t)], axis=-1)
        f = brdf_rs.eval(model, (0.0, 0.0, 1.0), wo, **params)[:, 0]
        return f * np.cos(t) * np.sin(t)

    edges = np.unique(np.concatenate([np.geomspace(1e-4, math.pi / 2, 200), [0.0]]))
    want = 2 * math.pi * gauss_panels(g, edges, n=40)
    got = sc.reference_albedo(model, 1.0, params)
    assert got == pytest.approx(want, abs=1e-13)


@pytest.mark.parametrize(
    ("model", "mu", "params"),
    [
        ("ggx", 0.7, {"kd": 0.0, "ks": 1.0, "alpha": 0.3}),
        ("ggx", 0.2, {"kd": 0.0, "ks": 1.0, "alpha": 0.05}),
        ("torrance_sparrow", 0.7, {"kd": 0.0, "ks": 1.0, "eta": 1.5, "p": 10.0}),
    ],
)
def test_cubature_matches_the_half_vector_quadrature(model, mu, params):
    # tests/quadrature.py integrates in the lobe's own polar frame with the kinks located
    # explicitly: a different method, so agreement checks both.
    want = quadrature.directional_albedo(model, mu, tol=1e-12, **params)[0]
    fine, diff, _ = sc.reference_with_check(sc.Case(model, mu, params))
    assert fine == pytest.approx(want, abs=5e-12)
    assert diff < 1e-9


@pytest.mark.parametrize("mu", [0.0, -0.5, 1.5, math.nan])
def test_reference_rejects_mu_outside_the_range(mu):
    with pytest.raises(ValueError, match="mu"):
        sc.reference_albedo("lambert", mu, {"kd": 0.5})


# ------------------------------------------------------------ against brdf_rs.albedo


@pytest.mark.parametrize(
    "case",
    sc.select(["ggx mu=0.7 alpha=0.3", "oren_nayar mu=0.3 sigma=0.5"]),
    ids=lambda c: c.label,
)
def test_albedo_agrees_with_the_cubature(case):
    ref = sc.reference_albedo(case.model, case.mu, case.params)
    r = brdf_rs.albedo(case.model, case.mu, samples=1 << 16, **case.params)
    err, se = abs(r.value[0] - ref), r.stderr[0]
    assert 0 < se < 1e-4 and err <= 5 * se, (err, se)


# ---------------------------------------------------------------------- statistics


def test_z_statistics_counts_zero_stderr_as_infinite_unless_exact():
    ref = 1.0
    value = np.array([1.0, 1.0 + 1e-9, 0.25, 1.25])  # binary fractions: exact z
    stderr = np.array([0.0, 0.0, 0.25, 0.25])
    s = sc.z_statistics(value, stderr, ref)
    # |z| = 0, inf, 3 (not > 3), 1
    assert s["p_abs_z_gt_3"] == 0.25
    assert s["p_abs_z_gt_2"] == 0.5
    assert s["frac_stderr_zero"] == 0.5
    assert s["mean_z"] == pytest.approx((0 - 3 + 1) / 3)
    assert s["median_abs_z"] == pytest.approx(2.0)


def test_honest_fractions():
    normal = sc.honest(math.inf)
    assert normal["p_abs_z_gt_3"] == pytest.approx(math.erfc(3 / math.sqrt(2)), rel=1e-12)
    assert normal["median_abs_z"] == pytest.approx(0.6744897501960817, rel=1e-9)
    assert sc.honest(1e7)["p_abs_z_gt_2"] == pytest.approx(normal["p_abs_z_gt_2"], rel=1e-5)
    # t with 1 d.o.f. is Cauchy: P(|T| > x) = 1 − (2/π)·atan x.
    cauchy = sc.honest(1.0)
    assert cauchy["p_abs_z_gt_3"] == pytest.approx(1 - 2 / math.pi * math.atan(3), rel=1e-9)
    assert cauchy["median_abs_z"] == pytest.approx(1.0, rel=1e-9)


# ------------------------------------------------------------------------ end to end


def test_quick_run_writes_json_and_markdown(tmp_path, capsys):
    out = tmp_path / "calibration"
    assert sc.main(["--quick", "--cells", "40", "--out", str(out)]) == 0
    data = json.loads(out.with_suffix(".json").read_text())
    rows = data["rows"]
    assert len(rows) == len(sc.QUICK_CASES) * 2 * 3
    assert {r["sequence"] for r in rows} == {"sobol", "random"}
    assert {r["budget"] for r in rows} == {"n=256", "n=4096", "tol=0.0001"}
    for r in rows:
        assert r["cells"] == 40 and 0 <= r["p_abs_z_gt_3"] <= r["p_abs_z_gt_2"] <= 1
        assert r["cubature_diff"] < 1e-9
    md = out.with_suffix(".md").read_text()
    assert md.count("\n| ") == 1 + len(rows)
    assert "P(|z|>3)" in capsys.readouterr().out


def test_confirm_reruns_rows_over_the_goal_on_fresh_cells(tmp_path, monkeypatch):
    # Every row over the goal (made negative here) is rerun on K times the cells, with
    # cell ids after the first run's: the same cells again would give the same z.
    monkeypatch.setattr(sc, "GOAL", -1.0)
    case = sc.select(["ggx mu=0.7 alpha=0.3"])[0]
    out = tmp_path / "calibration"
    argv = ["--cases", case.label, "--cells", "30", "--samples", "256", "--confirm", "2"]
    assert sc.main([*argv, "--out", str(out)]) == 0
    rows = json.loads(out.with_suffix(".json").read_text())["rows"]
    assert rows and all("confirm" in r for r in rows)
    for r in rows:
        again = r["confirm"]
        assert again["cells"] == 60
        budget = sc.Budget(256) if r["budget"] == "n=256" else sc.Budget(256, 1e-4)
        fresh = sc.calibrate(case, r["reference"], r["sequence"], budget, 60, first_cell=30)
        assert again["rms_error"] == fresh["rms_error"]
        first = sc.calibrate(case, r["reference"], r["sequence"], budget, 30)
        assert first["rms_error"] == r["rms_error"] != again["rms_error"]
    md = out.with_suffix(".md").read_text()
    assert f"{len(rows)} of {len(rows)} above -1.0 there" in md


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["--confirm", "-1"], "--confirm"),
        (["--cells", "0"], "--cells"),
        (["--samples", "1"], "--samples"),
        (["--tol", "0"], "--tol"),
        (["--tol", "nan"], "--tol"),
        (["--max-samples", "16"], "--max-samples"),
        (["--first", "1"], "--first"),
        (["--cases", "no_such_model"], "--cases"),
    ],
)
def test_bad_arguments_name_the_option(argv, name, capsys, tmp_path):
    with pytest.raises(SystemExit):
        sc.main([*argv, "--out", str(tmp_path / "x")])
    assert name in capsys.readouterr().err


# ------------------------------------------------- the rough dielectrics' reference


@pytest.mark.parametrize("model", sc.DIELECTRICS)
@pytest.mark.parametrize(("mu", "eta"), [(0.3, 1.5), (0.9, 1 / 1.5), (0.5, 1.05)])
def test_sphere_reference_of_a_near_smooth_interface_is_fresnel(model, mu, eta):
    # alpha = 1e-3: the interface is smooth but for a share of the light of order alpha.
    params = {**sc.DIEL, "eta": eta, "alpha": 1e-3}
    f = fresnel(mu, eta)
    r = sc.sphere_reference_albedo(model, mu, params, "reflection")
    t = sc.sphere_reference_albedo(model, mu, params, "transmission")
    assert r == pytest.approx(f, abs=2e-3)
    assert t == pytest.approx(1.0 - f, abs=2e-3)


@pytest.mark.parametrize(
    ("model", "mu", "eta", "alpha"),
    [("ggx_dielectric", 0.3, 1.1, 0.02), ("beckmann_dielectric", 0.7, 1 / 1.5, 0.5)],
)
def test_sphere_reference_components_add_up_and_converge(model, mu, eta, alpha):
    # The two components converge (fine against coarse, each), and at the coarse
    # resolution they add up to the total: then so does the total. (The fine total of
    # the Beckmann case alone takes about as long as the rest of this test.)
    params = {**sc.DIEL, "eta": eta, "alpha": alpha}
    parts = {}
    for component in ("reflection", "transmission"):
        coarse = sc.sphere_reference_albedo(model, mu, params, component, *sc.COARSE)
        fine = sc.sphere_reference_albedo(model, mu, params, component, *sc.FINE)
        assert abs(fine - coarse) < 1e-11, (component, fine, coarse)
        parts[component] = coarse
    total = sc.sphere_reference_albedo(model, mu, params, "total", *sc.COARSE)
    assert total == pytest.approx(parts["reflection"] + parts["transmission"], abs=1e-13)


@pytest.mark.parametrize("model", sc.DIELECTRICS)
@pytest.mark.parametrize("component", ["reflection", "transmission"])
def test_sphere_reference_agrees_with_a_long_albedo_run(model, component):
    # A rough interface (no rare drops): 2^18 Sobol points give an honest error bar of
    # about 1e-5; the reference is far more accurate than that.
    params = {**sc.DIEL, "eta": 1.5, "alpha": 0.3}
    ref = sc.sphere_reference_albedo(model, 0.6, params, component)
    r = brdf_rs.albedo(model, 0.6, samples=1 << 18, component=component, **params)
    assert abs(r.value[0] - ref) <= 4 * r.stderr[0], (r.value[0], ref, r.stderr[0])
