"""The identities docs/models.md lists, and reciprocity where (and only where) it holds."""

from __future__ import annotations

import brdf_rs
import numpy as np
import pytest
from conftest import FAMILY_A, SPECS, TRANSMISSION, random_params, upper_directions


@pytest.fixture
def pairs(rng):
    return upper_directions(rng, 20_000), upper_directions(rng, 20_000)


@pytest.mark.parametrize(
    ("shading", "brdf", "extra"),
    [
        ("lambert_shading", "lambert", {}),
        ("oren_nayar_shading", "oren_nayar", {}),
        ("phong_specular", "phong", {"kd": 0.0}),
        ("blinn_specular", "blinn_phong", {"kd": 0.0}),
    ],
)
def test_shading_terms_are_brdfs_times_cosine(shading, brdf, extra, pairs, rng):
    wi, wo = pairs
    params = random_params(rng, shading)
    scale = np.pi if shading in ("lambert_shading", "oren_nayar_shading") else 1.0
    s = brdf_rs.eval(shading, wi, wo, **params)
    f = brdf_rs.eval(brdf, wi, wo, **params, **extra)
    np.testing.assert_allclose(s, scale * wi[:, 2:3] * f, rtol=1e-13, atol=1e-300)


# The rough dielectrics are reciprocal with their index factor, f(wi, wo)/eta_o² =
# f(wo, wi)/eta_i²: tests/test_dielectric.py.
@pytest.mark.parametrize("model", [m for m in FAMILY_A if m not in TRANSMISSION])
def test_reciprocity_holds_exactly_where_the_spec_says(model, pairs, rng):
    wi, wo = pairs
    params = random_params(rng, model)
    if not SPECS[model]["reciprocal"]:
        params["kd"] = 0.0  # the diffuse term is reciprocal; look at the lobe alone
    forward = brdf_rs.eval(model, wi, wo, **params)
    backward = brdf_rs.eval(model, wo, wi, **params)
    relative = np.abs(forward - backward) / np.maximum(np.abs(forward), 1e-300)
    if SPECS[model]["reciprocal"]:
        assert np.quantile(relative, 0.999) < 1e-12, model
    else:
        # phong and blinn_phong divide by mu_i: swapping the directions changes them.
        assert np.median(relative) > 1e-3, model


def test_lambert_is_kd_over_pi(pairs):
    wi, wo = pairs
    got = brdf_rs.eval("lambert", wi, wo, kd=[0.2, 0.5, 0.9])
    np.testing.assert_array_equal(
        got, np.broadcast_to(np.array([0.2, 0.5, 0.9]) / np.pi, got.shape)
    )


@pytest.mark.parametrize("alpha", [0.02, 0.1, 1.0])
@pytest.mark.parametrize("mu_o", [0.03, 0.6, 1.0])
def test_zeltner_sheen_integrates_to_its_fitted_albedo_over_the_light(alpha, mu_o):
    """The transformed cosine is a distribution over ``wi`` for a given view: by
    Gauss-Legendre cubature over the light's hemisphere (an integral the library does not
    compute), ``∫ f·mu_i dωi = kd + ks·R(mu_o, α)``, with ``R`` the paper's fit (held at 0
    where the fit dips below), and ``R`` is never negative."""
    from brdf_rs.reference import _zeltner_albedo

    x, w = np.polynomial.legendre.leggauss(400)
    theta = (x + 1) * np.pi / 4  # [0, π/2]
    phi = (x + 1) * np.pi  # [0, 2π]
    t, p = np.meshgrid(theta, phi, indexing="ij")
    weight = np.outer(w * np.pi / 4, w * np.pi) * np.sin(t)
    wi = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    wo = np.array([np.sqrt(1 - mu_o**2), 0.0, mu_o])
    f = brdf_rs.eval("zeltner_sheen", wi, wo, kd=0.25, ks=[1.0, 0.5, 0.0], alpha=alpha)
    total = np.einsum("ijc,ij->c", f * wi[..., 2:], weight)
    r = _zeltner_albedo(mu_o, alpha)
    assert r >= 0.0
    np.testing.assert_allclose(total, 0.25 + np.array([1.0, 0.5, 0.0]) * r, rtol=0, atol=2e-5)
