"""normalization="exact" for torrance_sparrow and ward (normalized_blinn_phong's closed
form is tested in test_microfacet.py).

The references are independent of the tables: the library's albedo integrator run afresh
(other seeds than the generator's), tests/quadrature.py, and a 1-D quadrature of Ward's
albedo at normal incidence (scipy).
"""

from __future__ import annotations

import brdf_rs
import numpy as np
import pytest
import quadrature
from brdf_rs import _normalization
from quadrature import ward_albedo_at_normal_incidence

#: Interpolation error of the Ward factor (relative), as measured by
#: ``scripts/gen_tables.py exact-check`` at the cell midpoints, with a margin.
WARD_INTERPOLATION = 3e-5


@pytest.mark.parametrize("alpha", [0.013, 0.2, 0.77, 3.1])
def test_the_one_dimensional_ward_reference_matches_the_general_quadrature(alpha):
    general = quadrature.directional_albedo("ward", 1.0, kd=0, ks=1, alpha_x=alpha, alpha_y=alpha)
    assert ward_albedo_at_normal_incidence(alpha, alpha) == pytest.approx(general[0], rel=1e-8)


# ------------------------------------------------------------------------------ ward

#: (alpha_x, alpha_y) off the table's nodes (16 per decade from 1e-2): isotropic,
#: anisotropic both ways, and beyond the table's ends.
OFF_NODE = [
    (0.013, 0.013),
    (0.071, 0.31),
    (0.31, 0.071),
    (0.55, 0.55),
    (1.7, 0.23),
    (5.3, 41.0),
    (0.003, 0.6),
    (250.0, 0.05),
    (1e-5, 1e-5),
    (700.0, 900.0),
]


def test_ward_factor_matches_the_quadrature_off_the_nodes():
    ax, ay = np.array(OFF_NODE).T
    c = _normalization.factor("ward", {"alpha_x": ax, "alpha_y": ay})
    a = np.array([ward_albedo_at_normal_incidence(x, y) for x, y in OFF_NODE])
    np.testing.assert_allclose(c * a, 1.0, rtol=WARD_INTERPOLATION)


def test_ward_factor_is_symmetric_in_the_roughnesses():
    rng = np.random.default_rng(7)
    ax, ay = np.exp(rng.uniform(np.log(1e-3), np.log(1e3), (2, 200)))
    c = _normalization.factor("ward", {"alpha_x": ax, "alpha_y": ay})
    d = _normalization.factor("ward", {"alpha_x": ay, "alpha_y": ax})
    np.testing.assert_allclose(c, d, rtol=1e-13)


@pytest.mark.parametrize("alpha_x, alpha_y", OFF_NODE[:8])
def test_exact_ward_albedo_at_normal_incidence_is_one(alpha_x, alpha_y):
    # The integrator's better sampler: Ward's own for narrow lobes, uniform for wide ones.
    sampler = "uniform" if min(alpha_x, alpha_y) >= 0.3 else "importance"
    r = brdf_rs.albedo(
        "ward",
        1.0,
        kd=0,
        ks=1,
        alpha_x=alpha_x,
        alpha_y=alpha_y,
        normalization="exact",
        sampler=sampler,
        samples=1 << 18,
        seed=12345,
    )
    assert abs(r.value[0] - 1) < 5 * r.stderr[0] + WARD_INTERPOLATION, (r.value, r.stderr)


def test_ward_albedo_is_unbounded_at_grazing_incidence():
    # Why the factor is defined at normal incidence: A(mu)·sqrt(mu) tends to a positive
    # limit, so A grows without bound (the approximate lobe; the factor only scales it).
    mu = np.array([1e-4, 1e-6, 1e-8])
    r = brdf_rs.albedo("ward", mu, kd=0, ks=1, alpha_x=0.2, alpha_y=0.2, samples=1 << 16)
    scaled = r.value[:, 0] * np.sqrt(mu)
    np.testing.assert_allclose(scaled, scaled[-1], rtol=2e-3)
    assert r.value[-1, 0] > 200


# ------------------------------------------------------------------ torrance_sparrow


@pytest.mark.parametrize("p", [0.0, 0.37, 7.3, 93.0, 2.2e3, 4.1e4])
def test_exact_torrance_sparrow_albedo_peaks_at_one(p):
    # F = 1: R0 = ((eta − 1)/(eta + 1))² rounds to exactly 1 at eta = 1e20.
    mu = np.array([1e-6, 1e-3, 0.05, 0.2, 0.5, 0.8, 1.0])
    r = brdf_rs.albedo(
        "torrance_sparrow",
        mu,
        kd=0,
        ks=1,
        p=p,
        eta=1e20,
        normalization="exact",
        samples=1 << 18,
        seed=4321,
    )
    v, e = r.value[:, 0], r.stderr[:, 0]
    # Never above 1 (the V-cavity G conserves projected area) ...
    assert np.all(v <= 1 + 5 * e + 1e-12), (v, e)
    # ... and 1 at the best incidence: grazing for small p, anywhere but grazing for large.
    best = int(np.argmax(v))
    assert abs(v[best] - 1) <= 5 * e[best] + 1e-6, (v, e)


def test_torrance_sparrow_projected_area_is_conserved():
    # The identity behind c(p) = 1, by the general quadrature: the F = 1 albedo tends to 1
    # at grazing incidence and stays below 1 elsewhere.
    for p in (0.0, 4.0):
        grazing = quadrature.directional_albedo(
            "torrance_sparrow", 1e-6, kd=0, ks=1, p=p, eta=1e20, tol=1e-8
        )
        assert grazing[0] == pytest.approx(1.0, abs=1e-5)
        for mu in (0.3, 1.0):
            a = quadrature.directional_albedo(
                "torrance_sparrow", mu, kd=0, ks=1, p=p, eta=1e20, tol=1e-8
            )
            assert a[0] < 1


def test_exact_torrance_sparrow_is_the_lobe_as_written():
    wi = np.array([[0.3, 0.0, 0.95], [0.0, 0.6, 0.8]])
    wo = np.array([[-0.2, 0.1, 0.97], [0.1, -0.5, 0.86]])
    a = brdf_rs.eval("torrance_sparrow", wi, wo, p=[3.0, 300.0], ks=0.7, eta=1.4)
    b = brdf_rs.eval(
        "torrance_sparrow", wi, wo, p=[3.0, 300.0], ks=0.7, eta=1.4, normalization="exact"
    )
    np.testing.assert_array_equal(a, b)


# --------------------------------------------------------------------- factor, wiring


def test_factors_are_positive_and_finite_over_the_valid_range():
    alphas = np.array([1e-7, 1e-4, 1e-2, 0.3, 1.0, 1e2, 1e4, 1e7])
    ax, ay = np.meshgrid(alphas, alphas)
    c = _normalization.factor("ward", {"alpha_x": ax, "alpha_y": ay})
    assert np.all(np.isfinite(c)) and np.all(c > 0)
    # The tails: c → 1 + 1.5(αx² + αy²) for small α, 3 αx αy for large ones (beyond the
    # table the coordinates are clamped: r at the edge differs from its limit by 2e-8 at
    # the small end, 4.6e-6 at the large one).
    assert c[0, 0] == pytest.approx(1.0, abs=1e-7)
    assert c[-1, -1] == pytest.approx(3e14, rel=1e-5)
    p = np.array([0.0, 1e-300, 1e-3, 1.0, 1e6, 1e154, 1.7e308])
    for model in ("normalized_blinn_phong", "torrance_sparrow"):
        c = _normalization.factor(model, {"p": p})
        assert np.all(np.isfinite(c)) and np.all(c > 0), (model, c)
    blinn = _normalization.factor("normalized_blinn_phong", {"p": p})
    assert blinn[0] == 1.0 and blinn[-1] == 1.0


def test_spatially_varying_parameters_are_elementwise():
    wi = np.tile([0.3, 0.0, 0.954], (4, 1))
    wo = np.tile([-0.25, 0.05, 0.967], (4, 1))
    cases = [
        ("ward", {"alpha_x": np.array([0.05, 0.2, 1.0, 7.0]), "alpha_y": 0.3}),
        ("normalized_blinn_phong", {"p": np.array([1.0, 10.0, 100.0, 1000.0])}),
        ("normalized_blinn_phong", {"p": np.array([1.0, 10.0, 100.0])}),  # 3 elements
    ]
    for model, params in cases:
        n = len(next(v for v in params.values() if np.ndim(v)))
        batch = brdf_rs.eval(model, wi[:n], wo[:n], ks=0.8, normalization="exact", **params)
        for k in range(n):
            one = {name: (v[k] if np.ndim(v) else v) for name, v in params.items()}
            single = brdf_rs.eval(model, wi[k], wo[k], ks=0.8, normalization="exact", **one)
            np.testing.assert_allclose(batch[k], single, rtol=1e-15)
        # And the factor really is applied (against the approximate lobe).
        approx = brdf_rs.eval(model, wi[:n], wo[:n], ks=0.8, **params)
        c = _normalization.factor(model, params)
        np.testing.assert_allclose(batch, approx * np.asarray(c)[:, None], rtol=1e-14)


def test_model_takes_the_normalization():
    wi, wo = [0.3, 0.0, 0.954], [-0.25, 0.05, 0.967]
    m = brdf_rs.Model("ward", alpha_x=0.1, alpha_y=0.4, ks=[0.5, 0.6, 0.7], normalization="exact")
    expected = brdf_rs.eval(
        "ward", wi, wo, alpha_x=0.1, alpha_y=0.4, ks=[0.5, 0.6, 0.7], normalization="exact"
    )
    np.testing.assert_array_equal(m.eval(wi, wo), expected)
    np.testing.assert_array_equal(m.params["ks"], [0.5, 0.6, 0.7])  # as given
    assert "normalization='exact'" in repr(m)
    with pytest.raises(ValueError, match="normalization='exact' exists for"):
        brdf_rs.Model("ggx", normalization="exact")


def test_albedo_table_takes_the_normalization():
    alpha = np.array([0.02, 0.05, 0.12])
    t = brdf_rs.albedo_table(
        "ward",
        {"mu": [1.0], "alpha_x": alpha},
        alpha_y=0.1,
        kd=0,
        ks=1,
        normalization="exact",
        samples=1 << 16,
    )
    v, e = t.value[0, :, 0], t.stderr[0, :, 0]
    assert np.all(np.abs(v - 1) < 5 * e + WARD_INTERPOLATION), (v, e)


def test_exact_normalization_elsewhere_names_the_models_that_have_it():
    message = (
        "normalization='exact' exists for normalized_blinn_phong, torrance_sparrow, ward; "
        "ggx has none"
    )
    with pytest.raises(ValueError, match=message):
        brdf_rs.eval("ggx", [0, 0, 1], [0, 0, 1], normalization="exact")
    with pytest.raises(ValueError, match="normalization: expected"):
        brdf_rs.albedo("ward", 1.0, normalization="Exact")


def test_bad_roughness_is_still_named_with_exact_normalization():
    with pytest.raises(ValueError, match="alpha_x"):
        brdf_rs.eval("ward", [0, 0, 1], [0, 0, 1], alpha_x=-1.0, normalization="exact")
    with pytest.raises(ValueError, match="alpha_y"):
        brdf_rs.eval("ward", [0, 0, 1], [0, 0, 1], alpha_y=np.nan, normalization="exact")
