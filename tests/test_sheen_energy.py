"""Energy tables of the sheen models (``brdf_rs.energy_compensation_table``).

A table's ``E`` is the albedo seen from the view, ``∫ f(wi, wo)·mu_i dωi`` over the light.
For a reciprocal lobe that is the directional albedo the integrator computes; for a lobe
that is not reciprocal and whose kernel gives it in closed form (``models()[name]
["view_albedo_closed_form"]``: the LTC sheen) the table takes the closed form, exact,
and ``E_avg`` by a quadrature of it whose error bar must bound its error. Checked here
against a cubature over the light (an integral the library does not compute) and a
closed form of ``E_avg`` written with the error function at 40 digits.
"""

from __future__ import annotations

import brdf_rs
import numpy as np
import pytest
import quadrature
from brdf_rs import _spec
from conftest import script

CHECK = script("zeltner_energy_check")
SPECS = _spec.specs()
CLOSED = [n for n, s in SPECS.items() if s["energy_table"] and s["view_albedo_closed_form"]]
MODEL = "zeltner_sheen"
# Small and large roughness; 0.05 and 0.1 are where the fit is held at 0 (a kink in E).
ALPHAS = [0.01, 0.02, 0.05, 0.1, 0.3, 0.7, 1.0]
# Grazing views to normal incidence.
MUS = [0.001, 0.01, 0.05, 0.2, 0.5, 0.9, 1.0]


@pytest.fixture(scope="module")
def table():
    return brdf_rs.energy_compensation_table(MODEL, MUS, ALPHAS)


def test_the_models_with_closed_forms_are_the_lobes_that_are_not_reciprocal():
    assert MODEL in CLOSED
    for name, s in SPECS.items():
        if s["energy_table"] and not s["reciprocal"]:
            assert s["view_albedo_closed_form"], name
    # The integrated sheen tables keep the integrator.
    assert not SPECS["charlie_sheen"]["view_albedo_closed_form"]


def test_e_is_the_albedo_over_the_light(table):
    """E against a cubature over the light's hemisphere (nodes crowded toward grazing
    light, where the lobe lies for small roughness), at grazing views too."""
    assert np.all(table.stderr == 0.0)
    assert "closed form" in table.estimator
    for j, alpha in enumerate(ALPHAS):
        cubature = quadrature.view_albedo(
            MODEL, MUS, n_mu=256, n_phi=256, grade=4.0, kd=0.0, ks=1.0, alpha=alpha
        )[:, 0]
        np.testing.assert_allclose(table.e[:, j], cubature, rtol=1e-10, atol=1e-15, err_msg=alpha)
    # The albedo over the view's direction (what brdf_rs.albedo integrates) is another
    # integral for this lobe: the table must not be it.
    over_wo = brdf_rs.albedo(MODEL, [0.02, 0.1], kd=0, ks=1, alpha=[0.1, 0.3], tol=1e-4)
    e = brdf_rs.energy_compensation_table(MODEL, [0.02, 0.1], [0.1, 0.3]).e
    assert over_wo.value[0, 0] - e[0, 0] > 0.5 and over_wo.value[1, 0] - e[1, 1] > 0.1


def test_e_is_zero_at_grazing_view_as_f_is():
    e = brdf_rs.energy_compensation_table(MODEL, [0.0, 1e-12], [0.3]).e[:, 0]
    assert e[0] == 0.0 and e[1] > 0.5


@pytest.mark.parametrize("alpha", CHECK.ALPHAS)
def test_e_avg_is_within_its_bound_of_the_exact_average(alpha):
    """The bound covers the quadrature's actual error against E_avg in closed form (the
    error function at 40 digits: scripts/zeltner_energy_check.py), and is not vacuous: at
    0.01 the lobe's E is a Gaussian tail of width 0.007 at grazing views, which a fixed
    32-point rule misses by far more."""
    got = brdf_rs.energy_compensation_table(MODEL, [0.5], [alpha])
    exact = CHECK.e_avg_reference(alpha)
    error = abs(float(got.e_avg[0]) - exact)
    bound = float(got.e_avg_stderr[0])
    assert 0.0 < bound < 1e-12, bound
    assert error <= bound, (error, bound, exact)
    x, w = np.polynomial.legendre.leggauss(32)
    mu = 0.5 * (x + 1)
    e = brdf_rs.energy_compensation_table(MODEL, mu, [alpha]).e[:, 0]
    fixed = float(np.sum(0.5 * w * 2 * mu * e))
    if alpha <= 0.02:
        assert abs(fixed - exact) > 1e3 * bound, (fixed, exact)


def test_e_avg_is_the_average_of_the_albedo_over_the_light(table):
    """E_avg against ``2 ∫ E(mu) mu dmu`` with E from the cubature over the light, the
    outer integral by Gauss-Legendre in ``sqrt(mu)`` (E changes fastest at grazing views).
    Where the fit is held at 0 (α = 0.05 and 0.1 here) E has a kink, across which the
    outer rule converges slowly (2.5e-9 and 1.7e-8 off with 48 nodes); elsewhere it
    agrees to 7e-15."""
    x, w = np.polynomial.legendre.leggauss(48)
    u, wu = 0.5 * (x + 1), 0.5 * w
    mu, wmu = u**2, wu * 2 * u
    for j, alpha in enumerate(ALPHAS):
        e = quadrature.view_albedo(
            MODEL, mu, n_mu=128, n_phi=128, grade=3.0, kd=0.0, ks=1.0, alpha=alpha
        )[:, 0]
        cubature = float(np.sum(wmu * 2 * mu * e))
        tol = 5e-8 if alpha in (0.05, 0.1) else 1e-13
        assert abs(cubature - table.e_avg[j]) < tol, (alpha, cubature, table.e_avg[j])


def test_closed_form_tables_check_the_options_they_do_not_use():
    with pytest.raises(TypeError, match=r"^colour: energy_compensation_table takes no such"):
        brdf_rs.energy_compensation_table(MODEL, [0.5], [0.5], colour=1)
    with pytest.raises(ValueError, match="sampler"):
        brdf_rs.energy_compensation_table(MODEL, [0.5], [0.5], sampler="bogus")
    with pytest.raises(TypeError, match=r"^progress: expected a function"):
        brdf_rs.energy_compensation_table(MODEL, [0.5], [0.5], progress=3)
    with pytest.raises(ValueError, match=r"alpha"):
        brdf_rs.energy_compensation_table(MODEL, [0.5], [0.005])
    # Seeds and sample counts change nothing: nothing is sampled.
    a = brdf_rs.energy_compensation_table(MODEL, [0.2, 0.8], [0.1, 0.6], seed=1, samples=64)
    b = brdf_rs.energy_compensation_table(MODEL, [0.2, 0.8], [0.1, 0.6], seed=2, tol=None)
    np.testing.assert_array_equal(a.e, b.e)
    np.testing.assert_array_equal(a.e_avg, b.e_avg)


@pytest.mark.parametrize("model", ["charlie_sheen", "ggx"])
def test_integrated_tables_are_the_integrators_albedo(model):
    """The other models' tables are still brdf_rs.albedo's cells, bit for bit."""
    mu, alpha = np.array([0.1, 0.6, 1.0]), np.array([0.3, 0.9])
    got = brdf_rs.energy_compensation_table(model, mu, alpha, samples=256, tol=None)
    want = brdf_rs.albedo(
        model, mu[:, None], alpha=alpha[None, :], kd=0.0, ks=1.0, samples=256, tol=None
    )
    np.testing.assert_array_equal(got.e, want.value[..., 0])
    np.testing.assert_array_equal(got.stderr, want.stderr[..., 0])
    assert np.all(got.stderr > 0) and "randomized QMC" in got.estimator


#: Blender Cycles' published ``table_sheen_ltc``, its albedo plane (the tabulated fit of
#: Zeltner et al. that Cycles ships, 32 x 32 at the ends: ``cos = i/31``, ``alpha =
#: j/31``) at six interior cells, as Blender 5.2 prints them: ``(i, j, albedo)``
#: (``python scripts/sheen_published_compare.py --blender ...`` reads them all).
CYCLES_SHEEN_ALBEDO = [
    (16, 16, 0.13153),
    (8, 24, 0.50671),
    (24, 31, 0.37756),
    (4, 16, 0.50616),
    (31, 31, 0.31508),
    (2, 28, 0.68481),
]


def test_e_is_near_cycles_published_albedo_table():
    """``E(mu, alpha)`` (the paper's closed-form fit of the albedo, which OpenPBR and
    MaterialX evaluate) against Cycles' tabulated albedo: within 0.035 at interior cells
    (the closed form lies 0.015 to 0.03 above the table there). The axes swapped (the
    table read as ``[cos][alpha]``) miss by more than 0.1: the test tells them apart."""
    mu = np.array([i / 31 for i, _, _ in CYCLES_SHEEN_ALBEDO])
    alpha = np.array([j / 31 for _, j, _ in CYCLES_SHEEN_ALBEDO])
    published = np.array([v for _, _, v in CYCLES_SHEEN_ALBEDO])

    def e(mus: np.ndarray, alphas: np.ndarray) -> np.ndarray:
        cells = zip(mus, alphas, strict=True)
        return np.array(
            [brdf_rs.energy_compensation_table(MODEL, [m], [a]).e[0][0] for m, a in cells]
        )

    ours = e(mu, alpha)
    np.testing.assert_array_less(np.abs(ours - published), 0.035)
    assert np.abs(e(alpha, mu) - published).max() > 0.1


@pytest.mark.parametrize(("mu", "alpha"), [(0.3, 0.4), (0.8, 0.9)])
def test_the_ltc_fitter_recovers_the_papers_own_ltc(mu, alpha):
    """``scripts/ltc_sheen_fit.py`` fits the paper's LTC to a lobe from ``brdf_rs.eval``;
    given ``zeltner_sheen`` (an LTC itself) it must find the closed form's ``a``, ``b`` and
    ``R`` with an error at the quadrature's floor, which is what makes its error for the
    Charlie lobe a property of that lobe."""
    fit = script("ltc_sheen_fit")
    w, weight = fit.hemisphere()
    a, b, albedo, error = fit.fit_cell(MODEL, mu, alpha, w, weight)
    a0, b0 = fit.paper_ab(mu, alpha)
    assert a == pytest.approx(a0, rel=2e-3)
    assert b == pytest.approx(b0, abs=2e-3 * a0)
    exact = brdf_rs.energy_compensation_table(MODEL, [mu], [alpha]).e[0][0]
    assert albedo == pytest.approx(exact, rel=1e-3)
    assert error < 1e-3
