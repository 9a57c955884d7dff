"""Sheen layers in scenes: a sheen model stacked over a material's family-A model by
albedo scaling, ``f = weight·f_sheen + (1 − weight·E_sheen(n·v))·f_base``."""

from __future__ import annotations

import math

import brdf_rs
import numpy as np
import pytest
import quadrature
from brdf_rs import _spec

LAYERS = _spec.sheen_layers()


def _layer(model, **params):
    return {"model": model, **params}


def _scene(sheen=None, base=None, resolution=(48, 32)):
    material = dict(base or {"model": "lambert", "kd": [0.3, 0.05, 0.05]})
    if sheen is not None:
        material["sheen"] = sheen
    return {
        "camera": {"position": [0, 0, 6], "fov": 30, "resolution": list(resolution)},
        "materials": {"velvet": material},
        "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.2, "material": "velvet"}],
        "lights": [
            {"type": "directional", "direction": [-0.3, -0.4, -1], "intensity": 2.5},
            {"type": "directional", "direction": [0.5, 0.2, 1], "intensity": 1.5},
        ],
    }


def test_the_layer_models_come_from_the_core():
    assert len(LAYERS) >= 3
    specs = _spec.specs()
    for name in LAYERS:
        assert specs[name]["family"] == "A" and specs[name]["sheen_layer"]
        assert [p["name"] for p in specs[name]["params"]] == ["kd", "ks", "alpha"]


@pytest.mark.parametrize("model", LAYERS)
def test_a_layer_without_coverage_renders_exactly_the_base(model):
    base, base_stats = brdf_rs.render(_scene(), stats=True)
    layered, stats = brdf_rs.render(
        _scene(_layer(model, weight=0.0, ks=0.9, alpha=0.3)), stats=True
    )
    np.testing.assert_array_equal(layered, base)
    assert stats["parts"] == base_stats["parts"]
    assert base.max() > 0.05


@pytest.mark.parametrize("model", LAYERS)
def test_the_layer_brightens_grazing_pixels_more_than_the_centre(model):
    linear = {"tonemap": "none"}
    base = brdf_rs.render(_scene(), **linear)
    layered, stats = brdf_rs.render(
        _scene(_layer(model, ks=[1.0, 0.8, 0.8], alpha=0.35)), stats=True, **linear
    )
    assert [p["role"] for p in stats["parts"]] == ["sheen", "brdf"]
    # The view cosine of each pixel of the sphere (camera far enough: nearly orthographic).
    h, w, _ = base.shape
    y, x = np.mgrid[0:h, 0:w]
    lit = base.sum(-1) > 0
    centre = np.array([h / 2 - 0.5, w / 2 - 0.5])
    r = np.hypot(y - centre[0], x - centre[1])
    rim = lit & (r > 0.8 * r[lit].max())
    middle = lit & (r < 0.2 * r[lit].max())
    assert rim.sum() > 20 and middle.sum() > 4
    rim_gain = layered[rim].sum() / base[rim].sum()
    middle_gain = layered[middle].sum() / base[middle].sum()
    assert rim_gain > 1.5 and rim_gain > middle_gain, (rim_gain, middle_gain)


def test_only_diffuse_and_only_specular_add_up_to_the_layered_material():
    scene = _scene(_layer(LAYERS[0], ks=0.8, alpha=0.4), base={"model": "ggx", "kd": 0.4})
    linear = {"tonemap": "none"}
    both = brdf_rs.render(scene, **linear)
    parts = brdf_rs.render(scene, only="diffuse", **linear) + brdf_rs.render(
        scene, only="specular", **linear
    )
    np.testing.assert_allclose(parts, both, rtol=1e-5, atol=1e-7)


def _hemisphere_lights(n_mu=48, n_phi=96):
    """Directional lights whose intensities are the weights of a product quadrature over
    the hemisphere of light directions (Gauss-Legendre in cos θ, midpoints in φ): summed
    by the renderer, ``Σ L·f·(n·l)`` is the directional albedo at the view direction."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mus, wmu = 0.5 * (x + 1), 0.5 * w
    phis = (np.arange(n_phi) + 0.5) * 2 * math.pi / n_phi
    lights = []
    for mu, wm in zip(mus, wmu, strict=True):
        s = math.sqrt(1 - mu * mu)
        for phi in phis:
            toward = [s * math.cos(phi), s * math.sin(phi), mu]
            lights.append(
                {
                    "type": "directional",
                    "direction": [-c for c in toward],
                    "intensity": float(wm * 2 * math.pi / n_phi),
                }
            )
    return lights


VIEW_MUS = [0.05, 0.2, 0.5, 0.8, 1.0]


@pytest.mark.parametrize("model", LAYERS)
@pytest.mark.parametrize("alpha", [0.1, 0.4, 1.0])
def test_the_layered_albedo_over_a_white_lambert_base_stays_at_most_one(model, alpha):
    """White furnace: a white sheen (ks = 1) over a white Lambert base reflects what the
    layer lets through plus what it reflects, 1 at every view direction in the albedo
    scaling; a grey sheen (ks = 0.5) less."""
    lights = _hemisphere_lights()
    n = np.array([0.0, 0.0, 1.0])
    v = np.array([[math.sqrt(1 - m * m), 0.0, m] for m in VIEW_MUS])
    base = {"model": "lambert", "kd": 1.0}
    lambert = brdf_rs.shade(base, n, v, lights)[:, 0]
    np.testing.assert_allclose(lambert, 1.0, atol=1e-4)  # the quadrature itself
    for ks, bound in [(1.0, 1.0), (0.5, 1.0)]:
        layered = {**base, "sheen": _layer(model, ks=ks, alpha=alpha)}
        albedo = brdf_rs.shade(layered, n, v, lights)[:, 0]
        assert np.all(albedo <= bound + 0.01), (ks, albedo)
        if ks == 1.0:
            # Equal to 1 up to the quadrature's error on the sheen lobe.
            assert np.all(albedo >= 0.97), albedo
    # The lobe's albedo seen from the view, where the quadrature resolves it: the layered
    # albedo with ks = 0.5 is 1 − 0.5·E.
    e = quadrature.view_albedo(model, VIEW_MUS, kd=0.0, ks=1.0, alpha=alpha)
    half = brdf_rs.shade({**base, "sheen": _layer(model, ks=0.5, alpha=alpha)}, n, v, lights)
    np.testing.assert_allclose(half[1:, 0], 1 - 0.5 * e[1:, 0], atol=0.01)


@pytest.mark.parametrize("model", LAYERS)
def test_the_layer_takes_e_at_every_view_up_to_normal_incidence(model):
    """A black layer (ks = 0, full coverage) over a white Lambert base under one light at
    the zenith: the base is scaled by ``1 − E(n·v)``, so the shading recovers the table's
    E, which must follow the lobe's albedo seen from the view (a cubature over the light)
    up to and at normal incidence (and not stand still over the last interval)."""
    mu = np.array([0.6, 0.9, 0.97, 0.985, 0.99, 0.995, 1.0])
    n = np.tile([0.0, 0.0, 1.0], (len(mu), 1))
    v = np.stack([np.sqrt(1 - mu**2), 0 * mu, mu], 1)
    lights = [{"type": "directional", "direction": [0, 0, -1.0], "intensity": 1.0}]
    for alpha in (0.2, 1.0):
        material = {
            "model": "lambert",
            "kd": 1.0,
            "sheen": _layer(model, ks=0.0, alpha=alpha, weight=1.0),
        }
        used = 1 - brdf_rs.shade(material, n, v, lights)[:, 0] * np.pi
        e = quadrature.view_albedo(model, mu, kd=0, ks=1, alpha=alpha)
        np.testing.assert_allclose(used, np.minimum(e[:, 0], 1.0), rtol=3e-3, atol=3e-4)


@pytest.mark.parametrize(
    ("sheen", "pattern"),
    [
        (3, r"materials\.velvet\.sheen: expected a table"),
        ({"ks": 1}, r"materials\.velvet\.sheen\.model: missing \(a sheen model: "),
        ({"model": "ggx"}, r"materials\.velvet\.sheen\.model: 'ggx' is not a sheen model; "),
        (
            {"model": "charlie_shen"},
            r"materials\.velvet\.sheen\.model: .* \(did you mean 'charlie_sheen'\?\)",
        ),
        ({"model": "charlie_sheen", "kd": 0.5}, r"materials\.velvet\.sheen\.kd: a sheen layer"),
        (
            {"model": "charlie_sheen", "alpha": 0},
            r"materials\.velvet\.sheen\.alpha: expected a number in \[0\.001, 1\]",
        ),
        (
            {"model": "charlie_sheen", "alpha": 1e300},
            r"materials\.velvet\.sheen\.alpha: .*beyond float32's range",
        ),
        (
            {"model": "charlie_sheen", "alpha": "0.3"},
            r"materials\.velvet\.sheen\.alpha: expected a number",
        ),
        ({"model": "charlie_sheen", "ks": -1}, r"materials\.velvet\.sheen\.ks: expected a col"),
        ({"model": "charlie_sheen", "ks": [1, 1]}, r"materials\.velvet\.sheen\.ks: expected"),
        (
            {"model": "charlie_sheen", "weight": 1.5},
            r"materials\.velvet\.sheen\.weight: expected a number in \[0, 1\]",
        ),
        (
            {"model": "charlie_sheen", "weight": True},
            r"materials\.velvet\.sheen\.weight: expected a number in",
        ),
        (
            {"model": "charlie_sheen", "weight": math.nan},
            r"materials\.velvet\.sheen\.weight: expected a number",
        ),
        (
            {"model": "charlie_sheen", "colour": 1},
            r"materials\.velvet\.sheen\.colour: unknown key; .* takes: model, weight, ks, alpha",
        ),
        (
            {"model": "charlie_sheen", "wieght": 1},
            r"materials\.velvet\.sheen\.wieght: unknown key \(did you mean",
        ),
    ],
)
def test_sheen_layer_keys_are_checked_by_key_path(sheen, pattern):
    with pytest.raises(brdf_rs.SceneError, match=r"^<scene>: " + pattern):
        brdf_rs.parse_scene(_scene(sheen))


def test_a_sheen_layer_goes_over_a_family_a_model_only():
    base = {"diffuse": {"model": "lambert_shading", "kd": 0.5}}
    with pytest.raises(
        brdf_rs.SceneError, match=r"^<scene>: materials\.velvet\.sheen: a sheen layer goes over"
    ):
        brdf_rs.parse_scene(_scene(_layer("charlie_sheen"), base=base))


def test_a_toml_sheen_layer_reads_like_a_dict(tmp_path):
    path = tmp_path / "velvet.toml"
    path.write_text(
        "[camera]\nposition = [0, 0, 6]\nfov = 30\nresolution = [8, 6]\n"
        '[materials.velvet]\nmodel = "lambert"\nkd = [0.3, 0.05, 0.05]\n'
        'sheen = { model = "charlie_sheen", ks = 0.9, alpha = 0.3 }\n'
        '[[objects]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = 1.2\nmaterial = "velvet"\n'
        '[[lights]]\ntype = "directional"\ndirection = [0, 0, -1]\n'
    )
    scene = brdf_rs.load_scene(path)
    layer = scene.materials["velvet"]["sheen"]
    assert layer == {"model": "charlie_sheen", "params": {"ks": 0.9, "alpha": 0.3}, "weight": 1.0}
    as_dict = _scene(_layer("charlie_sheen", ks=0.9, alpha=0.3), resolution=(8, 6))
    as_dict["lights"] = [{"type": "directional", "direction": [0, 0, -1]}]
    np.testing.assert_array_equal(brdf_rs.render(scene), brdf_rs.render(as_dict))


def test_the_sheen_example_scene_renders_quickly():
    scene = brdf_rs.load_scene("sheen")
    layered = [name for name, m in scene.materials.items() if m.get("sheen") is not None]
    assert len(layered) >= 2
    models = {scene.materials[name]["sheen"]["model"] for name in layered}
    assert len(models) >= 2
    image = brdf_rs.render(scene.with_resolution(64, 32))
    assert image.shape == (32, 64, 3) and image.max() > 0.1


def test_where_the_lobe_reflects_more_than_one_the_base_goes_dark_not_negative():
    """A sharp Charlie lobe's albedo passes 1 at grazing views: the base's factor
    ``1 − weight·E`` stops at 0 there, so a red base under a cyan layer keeps a red
    channel of 0, never below."""
    mus = np.array([0.002, 0.005, 0.01, 0.02])
    model = LAYERS[1]
    e = brdf_rs.albedo(model, mus, kd=0.0, ks=1.0, alpha=0.01, samples=1 << 12)
    assert e.value[:, 0].max() > 1.2
    layered = {
        "model": "lambert",
        "kd": [1.0, 0.0, 0.0],
        "sheen": _layer(model, ks=[0.0, 1.0, 1.0], alpha=0.01),
    }
    n = np.array([0.0, 0.0, 1.0])
    v = np.array([[math.sqrt(1 - m * m), 0.0, m] for m in mus])
    out = brdf_rs.shade(layered, n, v, _hemisphere_lights(16, 32))
    assert np.all(out >= 0), out
    assert out[0, 0] == 0.0 and out[0, 1] > 0.5
