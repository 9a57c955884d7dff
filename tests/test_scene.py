"""Scenes: rendered pixels against the pure-Python reference, the Figure 7.38 claim,
the work the renderer skips (counted), tone maps and image files, bad scene files, the
CLI and the table cache."""

from __future__ import annotations

import dataclasses
import functools
import itertools
import json
import math
import subprocess
import sys
from pathlib import Path

import brdf_rs
import numpy as np
import pytest
import quadrature
from brdf_rs import reference
from brdf_rs.cli import main as cli_main
from brdf_rs.scene import SceneError, load_scene, parse_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "examples" / "scenes"
EXAMPLES = sorted(SCENES.glob("*.toml"))


# ------------------------------------------------------- an independent reference renderer


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def _perpendicular(n):
    """The same perpendicular as the renderer's (Duff et al. 2017)."""
    sign = 1.0 if n[2] >= 0 else -1.0
    a = -1.0 / (sign + n[2])
    b = n[0] * n[1] * a
    return np.array([1.0 + sign * n[0] * n[0] * a, sign * b, -sign * n[0]])


def camera_ray(camera, x, y):
    """The ray through pixel (x, y)'s centre, float64."""
    width, height = camera["resolution"]
    position = np.array(camera["position"], dtype=float)
    forward = _unit(np.subtract(camera["look_at"], position))
    right = _unit(np.cross(forward, camera["up"]))
    up = np.cross(right, forward)
    if camera["projection"] == "perspective":
        half_h = math.tan(math.radians(camera["fov"]) / 2)
    else:
        half_h = camera["height"] / 2
    half_w = half_h * width / height
    sx = (2 * (x + 0.5) / width - 1) * half_w
    sy = (1 - 2 * (y + 0.5) / height) * half_h
    if camera["projection"] == "perspective":
        return position, _unit(forward + sx * right + sy * up)
    return position + sx * right + sy * up, forward


def intersect(obj, o, d):
    """(t, discriminant margin) of the nearest hit with t > 0, or (inf, inf)."""
    if obj["shape"] == "sphere":
        f = o - np.array(obj["center"])
        r = obj["radius"]
        b = f @ d
        disc = r * r - (f - b * d) @ (f - b * d)
        if disc < 0:
            return math.inf, disc / r**2
        root = math.sqrt(disc)
        for t in sorted([-b - root, -b + root]):
            if t > 0:
                return t, disc / r**2
        return math.inf, math.inf
    n = np.array(obj["normal"], dtype=float)
    denom = n @ d
    if denom == 0:
        return math.inf, math.inf
    t = n @ (np.array(obj["point"]) - o) / denom
    return (t, math.inf) if t > 0 else (math.inf, math.inf)


def tangent_at(obj, n):
    if obj["shape"] == "plane":
        t = obj.get("tangent")
        return _unit(t) if t is not None else _perpendicular(_unit(obj["normal"]))
    axis = _unit(obj["axis"])
    v = axis - (axis @ n) * n if obj["tangent"] == "meridian" else np.cross(axis, n)
    return v / np.linalg.norm(v) if v @ v > 1e-12 else _perpendicular(n)


class Unstable(Exception):
    """The pixel sits on a discontinuity the inputs' float32 rounding can flip."""


def _check_margin(value, edge, what, eps=2e-3):
    if abs(value - edge) < eps:
        raise Unstable(what)


def shade_reference(material, n, v, p, t, lights):
    """Σ over lights of the reference shading, float64, with the discontinuities checked."""
    total = np.zeros(3)
    for light in lights:
        intensity = np.array(light["intensity"])
        if light["type"] == "directional":
            wi = -_unit(light["direction"])
            weight = intensity
        else:
            d = np.array(light["position"]) - p
            dist2 = d @ d
            if light["range"] is not None:
                _check_margin(math.sqrt(dist2) / light["range"], 1.0, "range edge")
                if dist2 > light["range"] ** 2:
                    continue
            wi = d / math.sqrt(dist2)
            weight = intensity / dist2
        cos_l = n @ wi
        _check_margin(cos_l, 0.0, "terminator", eps=1e-4)
        if "brdf" in material:
            term = material["brdf"]
            tangent = t if term["model"] in TAKES_TANGENT else None
            f = reference.eval(term["model"], wi, v, n, tangent, **term["params"])
            layer = material.get("sheen")
            if layer is not None and layer["weight"] > 0:
                sheen = reference.eval(layer["model"], wi, v, n, None, **layer["params"])
                e = sheen_albedo(layer["model"], layer["params"].get("alpha", 0.5), n @ v)
                f = layer["weight"] * np.array(sheen) + (1 - layer["weight"] * e) * np.array(f)
            if cos_l > 0:
                total += weight * np.array(f) * cos_l
            continue
        for slot in ("diffuse", "specular"):
            term = material[slot]
            if term is None:
                continue
            params = term["params"]
            model = term["model"]
            if model == "toon_diffuse":
                for edge in params["thresholds"]:
                    _check_margin(cos_l, edge, "toon band edge")
            if model == "toon_specular":
                r = 2 * cos_l * n - wi
                _check_margin(v @ r, params["threshold"], "toon highlight edge")
            tangent = t if model == "kajiya_kay" else None
            s = reference.eval(model, wi, v, n, tangent, **params)
            total += weight * np.array(s)
    return total


#: A sheen layer's albedo table: the sheen lobe's albedo at unit colour seen from the view
#: (brdf_rs.albedo with 2^12 samples for reciprocal lobes, a cubature over the light for
#: the others) at 64 view cosines evenly spaced in sqrt(mu) from 0 (taken at 1e-6) to 1,
#: interpolated linearly.
SHEEN_NODES = np.maximum(np.arange(64) / 63, 1e-3) ** 2


@functools.cache
def _sheen_table(model, alpha):
    if not brdf_rs.models()[model]["reciprocal"]:
        # A lobe fitted in the view's frame: its albedo over the light, not the
        # integrator's over the view.
        return quadrature.view_albedo(model, SHEEN_NODES, kd=0.0, ks=1.0, alpha=alpha)[:, 0]
    r = brdf_rs.albedo(model, SHEEN_NODES, kd=0.0, ks=1.0, alpha=alpha, samples=1 << 12)
    return r.value[:, 0]


def sheen_albedo(model, alpha, mu):
    table = _sheen_table(model, float(alpha))
    x = min(max(math.sqrt(min(max(mu, 0.0), 1.0)) * 63, 0.0), 63.0)
    i = min(int(x), 62)
    return table[i] + (x - i) * (table[i + 1] - table[i])


def reference_pixel(scene, x, y):
    o, d = camera_ray(scene.camera, x, y)
    best, hit = math.inf, None
    for obj in scene.objects:
        t, margin = intersect(obj, o, d)
        _check_margin(margin, 0.0, "silhouette", eps=2e-3)
        if t < math.inf and best < math.inf:
            _check_margin(t / best, 1.0, "two objects at the same depth", eps=1e-4)
        if t < best:
            best, hit = t, obj
    if hit is None:
        return np.array(scene.output["background"])
    p = o + best * d
    if hit["shape"] == "sphere":
        n = _unit(p - np.array(hit["center"]))
    else:
        n = _unit(hit["normal"])
        n = -n if n @ d > 0 else n
    material = scene.materials[hit["material"]]
    return shade_reference(material, n, -d, p, tangent_at(hit, n), scene.lights)


LOW_RES = {
    "gallery.toml": (128, 64),
    "rtr_fig_7_38.toml": (128, 64),
    "hdr.toml": (128, 72),
    "sheen.toml": (104, 40),
}


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_rendered_pixels_match_the_reference(path):
    scene = load_scene(path).with_resolution(*LOW_RES[path.name])
    image = brdf_rs.render(scene, tonemap="none")
    width, height = scene.resolution
    assert image.shape == (height, width, 3) and image.dtype == np.float32
    rng = np.random.default_rng(5)
    checked = hits = 0
    for _ in range(400):
        x, y = int(rng.integers(width)), int(rng.integers(height))
        try:
            want = reference_pixel(scene, x, y)
        except Unstable:
            continue
        got = image[y, x].astype(np.float64)
        scale = max(1.0, float(np.max(want)))
        np.testing.assert_allclose(got, want, rtol=2e-4, atol=2e-5 * scale, err_msg=f"{x, y}")
        checked += 1
        hits += not np.array_equal(want, scene.output["background"])
    assert checked > 300 and hits > 100, (checked, hits)


FAMILY_A = [
    "lambert",
    "oren_nayar",
    "phong",
    "modified_phong",
    "normalized_phong",
    "blinn_phong",
    "modified_blinn_phong",
    "normalized_blinn_phong",
    "blinn_phong_fresnel",
    "torrance_sparrow",
    "ggx",
    "beckmann",
    "ward",
    "ashikhmin_shirley",
]

#: Family-A models that read the object's tangent field.
TAKES_TANGENT = {k for k, m in brdf_rs.models().items() if m["tangent"] or m["tangent_optional"]}


def _random_material(rng):
    if rng.random() < 0.5:
        m = {"model": str(rng.choice(FAMILY_A)), "kd": rng.uniform(0, 0.5, 3).tolist()}
        if m["model"] == "oren_nayar":
            m["sigma"] = float(rng.uniform(0, 1.5))
        elif m["model"] in ("ggx", "beckmann"):
            m["ks"] = rng.uniform(0, 1, 3).tolist()
            m["alpha"] = float(rng.uniform(0.05, 1))
        elif m["model"] == "ward":
            m["ks"] = rng.uniform(0, 0.5, 3).tolist()
            m["alpha_x"], m["alpha_y"] = rng.uniform(0.05, 0.6, 2).tolist()
        elif m["model"] == "ashikhmin_shirley":
            m = {"model": m["model"], "Rd": m["kd"], "Rs": rng.uniform(0, 0.9, 3).tolist()}
            m["nu"], m["nv"] = rng.uniform(1, 200, 2).tolist()
        elif m["model"] != "lambert":
            m["ks"] = rng.uniform(0, 0.9, 3).tolist()
            m["p"] = float(rng.uniform(1, 80))
        return m
    diffuse = [
        {"model": "lambert_shading", "kd": 0.6},
        {"model": "oren_nayar_shading", "sigma": 0.7},
        {
            "model": "toon_diffuse",
            "thresholds": sorted(rng.uniform(-1, 1, 2).tolist()),
            "colors": rng.uniform(0, 1, (3, 3)).tolist(),
        },
        {"model": "kajiya_kay", "ks": 0.0},
    ][rng.integers(4)]
    specular = [
        {"model": "phong_specular", "p": 20.0},
        {"model": "blinn_specular", "p": 50.0},
        {"model": "toon_specular", "threshold": float(rng.uniform(-1, 1)), "low": 0.1},
        {"model": "kajiya_kay", "kd": 0.0, "p": 30.0},
        None,
    ][rng.integers(5)]
    return {"diffuse": diffuse} | ({"specular": specular} if specular else {})


def _random_scene(rng):
    perspective = rng.random() < 0.5
    camera = {
        "type": "perspective" if perspective else "orthographic",
        "position": rng.uniform(-6, 6, 3).tolist(),
        "look_at": rng.uniform(-1, 1, 3).tolist(),
        "resolution": [int(rng.integers(20, 60)), int(rng.integers(20, 60))],
    }
    if perspective:
        camera["fov"] = float(rng.uniform(20, 100))
    else:
        camera["height"] = float(rng.uniform(2, 8))
    objects = []
    for _ in range(int(rng.integers(1, 6))):
        material = f"m{rng.integers(3)}"
        if rng.random() < 0.8:
            objects.append(
                {
                    "type": "sphere",
                    "center": rng.uniform(-3, 3, 3).tolist(),
                    "radius": float(rng.uniform(0.2, 2)),
                    "material": material,
                    "tangent": str(rng.choice(["meridian", "parallel"])),
                    "axis": rng.normal(size=3).tolist(),
                }
            )
        else:
            objects.append(
                {
                    "type": "plane",
                    "point": rng.uniform(-3, 3, 3).tolist(),
                    "normal": rng.normal(size=3).tolist(),
                    "material": material,
                }
            )
    lights = []
    for _ in range(int(rng.integers(0, 4))):
        if rng.random() < 0.5:
            lights.append(
                {
                    "type": "directional",
                    "direction": rng.normal(size=3).tolist(),
                    "intensity": rng.uniform(0, 2, 3).tolist(),
                }
            )
        else:
            light = {
                "type": "point",
                "position": rng.uniform(-4, 4, 3).tolist(),
                "intensity": float(rng.uniform(0, 10)),
            }
            if rng.random() < 0.5:
                light["range"] = float(rng.uniform(1, 6))
            lights.append(light)
    return parse_scene(
        {
            "camera": camera,
            "materials": {f"m{i}": _random_material(rng) for i in range(3)},
            "objects": objects,
            "lights": lights,
            "output": {"background": [0.1, 0.2, 0.3]},
        }
    )


def test_random_scenes_match_the_reference():
    """Both cameras, spheres and planes, both light types with and without range, every
    family-A model and family-B term, against the float64 reference renderer."""
    rng = np.random.default_rng(20261122)
    checked = 0
    for _ in range(12):
        scene = _random_scene(rng)
        image = brdf_rs.render(scene, tonemap="none")
        assert np.isfinite(image).all()
        width, height = scene.resolution
        for _ in range(30):
            x, y = int(rng.integers(width)), int(rng.integers(height))
            try:
                want = reference_pixel(scene, x, y)
            except Unstable:
                continue
            scale = max(1.0, float(np.max(want)))
            np.testing.assert_allclose(image[y, x], want, rtol=2e-4, atol=2e-5 * scale)
            checked += 1
    assert checked > 250


def test_tone_mapped_render_is_the_tone_map_of_radiance():
    scene = load_scene(SCENES / "hdr.toml").with_resolution(64, 36)
    linear = brdf_rs.render(scene, tonemap="none")
    for kind in ("clamp", "reinhard", "aces"):
        got = brdf_rs.render(scene, tonemap=kind, exposure=0.5)
        x = linear.astype(np.float64) * 2**0.5
        want = {
            "clamp": np.clip(x, 0, 1),
            "reinhard": x / (1 + x),
            "aces": np.clip(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0, 1),
        }[kind]
        np.testing.assert_allclose(got, want, rtol=1e-5, atol=1e-6)
    # The scene is over-bright: clamping loses what the tone maps keep.
    assert linear.max() > 4.0


def test_figure_7_38_normalized_highlights_brighten_original_ones_do_not():
    scene = load_scene(SCENES / "rtr_fig_7_38.toml").with_resolution(1920, 960)
    # The green channel is the specular lobe alone (kd is pure red).
    green = brdf_rs.render(scene, tonemap="none")[..., 1]
    height = green.shape[0]
    peaks = {}
    for row, name in ((0, "original"), (1, "normalized")):
        rows = green[row * height // 2 : (row + 1) * height // 2]
        peaks[name] = [float(c.max()) for c in np.array_split(rows, 4, axis=1)]
    original, normalized = peaks["original"], peaks["normalized"]
    assert all(b > 1.25 * a for a, b in itertools.pairwise(normalized)), normalized
    assert max(original) / min(original) < 1.01, original
    # And the ratio is the normalization: (p + 2)/(2π) at the mirror direction.
    for p, o, nrm in zip((25, 50, 75, 100), original, normalized, strict=True):
        assert nrm / o == pytest.approx((p + 2) / (2 * math.pi), rel=0.02)


def test_rendering_is_deterministic_across_threads():
    scene = load_scene(SCENES / "gallery.toml").with_resolution(300, 150)
    before = brdf_rs.num_threads()
    try:
        brdf_rs.set_num_threads(1)
        one = brdf_rs.render(scene, tonemap="none")
        brdf_rs.set_num_threads(2)
        two = brdf_rs.render(scene, tonemap="none")
    finally:
        brdf_rs.set_num_threads(before)
    np.testing.assert_array_equal(one, two)


# -------------------------------------------------------------------- skipping, counted

ONE_SPHERE = """
[camera]
type = "orthographic"
position = [0, 0, 5]
height = 3
resolution = [60, 40]

[materials.m]
{material}

[materials.unused]
model = "torrance_sparrow"

[[objects]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "m"

{lights}
"""

KEY = '[[lights]]\ntype = "directional"\ndirection = [1, -1, -1]\n'
BEHIND = '[[lights]]\ntype = "directional"\ndirection = [0, 0, 1]\nintensity = {i}\n'


def _scene(material, lights=KEY):
    return parse_scene(ONE_SPHERE.format(material=material, lights=lights), "test.toml")


def test_zero_weight_lobes_are_never_evaluated():
    lambert = _scene('diffuse = { model = "lambert_shading", kd = 0.5 }')
    phong_ks0 = _scene(
        'diffuse = { model = "lambert_shading", kd = 0.5 }\n'
        'specular = { model = "phong_specular", ks = 0, p = 30 }'
    )
    a, sa = brdf_rs.render(lambert, tonemap="none", stats=True)
    b, sb = brdf_rs.render(phong_ks0, tonemap="none", stats=True)
    np.testing.assert_array_equal(a, b)
    assert [(p["role"], p["model"]) for p in sb["parts"]] == [("diffuse", "lambert_shading")]
    assert sb["evaluations"] == sa["evaluations"] > 0
    # A family-A model whose specular colour is 0 is evaluated as its diffuse term.
    family_a = _scene('model = "phong"\nkd = 0.2\nks = 0')
    image, stats = brdf_rs.render(family_a, tonemap="none", stats=True)
    assert [(p["role"], p["model"]) for p in stats["parts"]] == [("diffuse", "lambert")]
    full = _scene('model = "phong"\nkd = 0.2\nks = 1e-30')
    np.testing.assert_allclose(image, brdf_rs.render(full, tonemap="none"), rtol=1e-6)
    # A black material prepares nothing and runs nothing.
    black = _scene('diffuse = { model = "oren_nayar_shading", kd = 0 }')
    image, stats = brdf_rs.render(black, tonemap="none", stats=True)
    assert stats["parts"] == [] and stats["evaluations"] == 0 and not image.any()


def test_only_the_materials_present_are_prepared():
    _, stats = brdf_rs.render(_scene('model = "lambert"'), stats=True)
    assert stats["materials_prepared"] == 1
    assert {p["material"] for p in stats["parts"]} == {"m"}


def test_culled_lights_are_not_evaluated():
    material = (
        'diffuse = { model = "lambert_shading", kd = 0.5 }\n'
        'specular = { model = "blinn_specular", ks = 0.5, p = 50 }'
    )
    one = _scene(material)
    behind = KEY + "".join(BEHIND.format(i=k + 1) for k in range(7))
    black = '[[lights]]\ntype = "directional"\ndirection = [-1, 0, -1]\nintensity = 0\n'
    eight = _scene(material, behind + black)
    a, sa = brdf_rs.render(one, tonemap="none", stats=True)
    b, sb = brdf_rs.render(eight, tonemap="none", stats=True)
    np.testing.assert_array_equal(a, b)
    assert sb["evaluations"] == sa["evaluations"]
    assert sb["lights"] == 8 and sb["lights_dropped"] == 1
    assert sb["pairs"] == 8 * sb["hits"]
    assert sb["pairs_backfacing"] == sa["pairs_backfacing"] + 7 * sb["hits"]
    # Each part ran once per lit pixel of the key light.
    lit = sa["hits"] - sa["pairs_backfacing"]
    assert [p["evaluations"] for p in sb["parts"]] == [lit, lit]
    # The global debug counter saw the same work.
    before = brdf_rs._brdf_rs.scene_counters()
    brdf_rs.render(eight, stats=False)
    after = brdf_rs._brdf_rs.scene_counters()
    assert after["evaluations"] - before["evaluations"] == sb["evaluations"]
    assert after["renders"] == before["renders"] + 1


def test_toon_dark_bands_are_added_for_lights_behind_without_a_kernel():
    # toon_diffuse counts thresholds against the signed n·l: a light behind the surface
    # shows the darkest band (docs/models.md). With no threshold in (-1, 0] that band is one
    # constant colour, added as L·colour without running the kernel.
    toon = (
        'diffuse = { model = "toon_diffuse", thresholds = [0.5], colors = [[0.1, 0.2, 0.3], 0.8] }'
    )
    key_only, s1 = brdf_rs.render(_scene(toon), tonemap="none", stats=True)
    behind = KEY + BEHIND.format(i=2)
    image, stats = brdf_rs.render(_scene(toon, behind), tonemap="none", stats=True)
    assert stats["evaluations"] == s1["evaluations"] == s1["hits"] - s1["pairs_backfacing"]
    # Every visible pixel faces away from the back light (it travels toward the camera).
    assert stats["pairs_constant"] == s1["pairs_constant"] + stats["hits"]
    hit = np.any(key_only != 0, axis=-1)
    assert hit.sum() == stats["hits"]
    np.testing.assert_allclose(
        (image - key_only)[hit], np.broadcast_to([0.2, 0.4, 0.6], (hit.sum(), 3)), rtol=1e-6
    )
    # Black dark bands: the light is culled; a threshold in (-1, 0]: the kernel runs.
    dark = 'diffuse = { model = "toon_diffuse", thresholds = [0.5], colors = [0, 0.8] }'
    _, stats = brdf_rs.render(_scene(dark, behind), tonemap="none", stats=True)
    assert stats["evaluations"] == s1["evaluations"] and stats["pairs_constant"] == 0
    varies = (
        'diffuse = { model = "toon_diffuse", thresholds = [-0.5, 0.5], colors = [0.1, 0.5, 0.8] }'
    )
    _, stats = brdf_rs.render(_scene(varies, behind), tonemap="none", stats=True)
    assert stats["evaluations"] == 2 * stats["hits"] and stats["pairs_constant"] == 0


def test_point_lights_beyond_their_range_are_culled():
    near = '[[lights]]\ntype = "point"\nposition = [0, 0, 2]\nintensity = 4\nrange = 1.5\n'
    scene = _scene('model = "lambert"', near)
    image, stats = brdf_rs.render(scene, tonemap="none", stats=True)
    assert 0 < stats["pairs_out_of_range"] < stats["hits"]
    assert (
        stats["evaluations"]
        == stats["hits"] - stats["pairs_out_of_range"] - stats["pairs_backfacing"]
    )
    # Pixels beyond the range are black, inside they are not.
    width, height = scene.resolution
    assert image[height // 2, width // 2].sum() > 0


def test_pixels_that_miss_cost_only_the_ray_test():
    _, stats = brdf_rs.render(_scene('model = "lambert"'), stats=True)
    # Rows and segments that cannot reach the sphere skip its ray test.
    assert stats["hits"] < stats["ray_tests"] < stats["pixels"] == 60 * 40
    assert 0 < stats["hits"] < stats["pixels"]
    assert stats["pairs"] == stats["hits"]
    assert stats["evaluations"] <= stats["hits"]
    empty = parse_scene(
        "[camera]\nposition = [0, 0, 5]\nresolution = [8, 4]\n[output]\nbackground = [0.5, 0.25, 0]\n"
    )
    image, stats = brdf_rs.render(empty, tonemap="none", stats=True)
    assert stats["hits"] == 0 and stats["evaluations"] == 0
    assert np.all(image == np.array([0.5, 0.25, 0], dtype=np.float32))


def _black_background(scene):
    """The scene with a black background, so that components add up everywhere."""
    return dataclasses.replace(scene, output={**scene.output, "background": [0.0, 0.0, 0.0]})


def test_only_renders_one_component_without_the_other():
    scene = _black_background(load_scene(SCENES / "gallery.toml").with_resolution(200, 100))
    full, sf = brdf_rs.render(scene, tonemap="none", stats=True)
    diffuse, sd = brdf_rs.render(scene, only="diffuse", tonemap="none", stats=True)
    specular, ss = brdf_rs.render(scene, only="specular", tonemap="none", stats=True)
    np.testing.assert_allclose(diffuse + specular, full, rtol=1e-6, atol=1e-7)
    assert {p["role"] for p in sd["parts"]} == {"diffuse"}
    assert {p["role"] for p in ss["parts"]} == {"specular"}
    assert sd["evaluations"] + ss["evaluations"] == sf["evaluations"]
    # Family A splits into the kd term (lambert) and the rest (the model with kd = 0).
    hdr = _black_background(load_scene(SCENES / "hdr.toml").with_resolution(120, 68))
    full = brdf_rs.render(hdr, tonemap="none")
    parts = brdf_rs.render(hdr, tonemap="none", only="diffuse") + brdf_rs.render(
        hdr, tonemap="none", only="specular"
    )
    np.testing.assert_allclose(parts, full, rtol=2e-5, atol=1e-6)


# ------------------------------------------------------------------------------ shade


def test_shade_matches_the_reference(rng):
    count = 200
    n = rng.normal(size=(count, 3))
    v = rng.normal(size=(count, 3))
    v = np.where((np.sum(n * v, axis=1) < 0)[:, None], -v, v)
    positions = rng.normal(size=(count, 3))
    tangent = rng.normal(size=(count, 3))
    lights = [
        {"type": "directional", "direction": [0.3, -1, 0.2], "intensity": [1, 0.5, 0.25]},
        {"type": "point", "position": [0, 3, 0], "intensity": 5, "range": 4},
    ]
    materials = [
        {"model": "torrance_sparrow", "kd": [0.1, 0.2, 0.3], "ks": 0.8, "p": 40},
        {
            "diffuse": {"model": "oren_nayar_shading", "sigma": 0.4},
            "specular": {"model": "phong_specular", "p": 20},
        },
        {"specular": {"model": "kajiya_kay", "ks": 0.5, "p": 30}},
    ]
    checked = lights_checked = 0
    scene_lights = parse_scene(
        {"camera": {"position": [0, 0, 1], "resolution": [1, 1]}, "lights": lights}
    ).lights
    for material in materials:
        got = brdf_rs.shade(material, n, v, lights, positions, tangent=tangent)
        assert got.shape == (count, 3) and got.dtype == np.float32
        desc = parse_scene(
            {"camera": {"position": [0, 0, 1], "resolution": [1, 1]}, "materials": {"m": material}}
        ).materials["m"]
        for i in range(count):
            try:
                want = shade_reference(
                    desc, _unit(n[i]), _unit(v[i]), positions[i], _unit(tangent[i]), scene_lights
                )
            except Unstable:
                continue
            np.testing.assert_allclose(got[i], want, rtol=3e-4, atol=1e-5 * max(1, want.max()))
            checked += 1
            lights_checked += bool(want.any())
    assert checked > 500 and lights_checked > 200


def test_shade_broadcasts_its_inputs():
    n = np.array([0.0, 0.0, 2.0])
    v = np.array([[0.0, 0.0, 1.0], [0.0, 0.6, 0.8]])
    lights = [{"type": "directional", "direction": [0, 0, -1], "intensity": 2}]
    out = brdf_rs.shade({"diffuse": {"model": "lambert_shading", "kd": 0.5}}, n, v, lights)
    np.testing.assert_allclose(out, np.ones((2, 3)))
    grid = brdf_rs.shade({"model": "lambert"}, np.ones((4, 1, 3)), np.ones((5, 3)), lights)
    assert grid.shape == (4, 5, 3)
    with pytest.raises(ValueError, match="shapes do not broadcast"):
        brdf_rs.shade({"model": "lambert"}, np.ones((4, 3)), np.ones((5, 3)), lights)


def test_shade_errors_name_the_argument():
    n = np.array([[0, 0, 1.0]])
    point = [{"type": "point", "position": [0, 0, 1]}]
    with pytest.raises(ValueError, match="positions: point lights need the surface positions"):
        brdf_rs.shade({"model": "lambert"}, n, n, point)
    with pytest.raises(TypeError, match="tangent"):
        brdf_rs.shade({"diffuse": {"model": "kajiya_kay"}}, n, n, [])
    with pytest.raises(ValueError, match=r"v\[1\] is a zero-length vector"):
        brdf_rs.shade({"model": "lambert"}, np.ones((2, 3)), [[0, 0, 1], [0, 0, 0]], [])
    with pytest.raises(SceneError, match=r"shade: material.kd: expected a colour"):
        brdf_rs.shade({"model": "lambert", "kd": "red"}, n, n, [])
    with pytest.raises(SceneError, match=r"shade: lights\[0\].direction: missing"):
        brdf_rs.shade({"model": "lambert"}, n, n, [{"type": "directional"}])


# ------------------------------------------------------------------ images and tone maps


def test_save_image_png_exr_npy(tmp_path):
    from PIL import Image

    image = np.zeros((2, 3, 3), dtype=np.float32)
    image[0, 0] = [1.0, 0.5, 0.0]
    image[1, 2] = [0.2159, 2.0, -1.0]
    brdf_rs.save_image(tmp_path / "a.png", image)
    png = np.asarray(Image.open(tmp_path / "a.png"))
    assert png.dtype == np.uint8 and png.shape == (2, 3, 3)
    assert png[0, 0].tolist() == [255, 188, 0] and png[1, 2].tolist() == [128, 255, 0]
    brdf_rs.save_image(tmp_path / "a.npy", image)
    np.testing.assert_array_equal(np.load(tmp_path / "a.npy"), image)
    pytest.importorskip("OpenEXR")
    import OpenEXR

    brdf_rs.save_image(tmp_path / "a.exr", image)
    with OpenEXR.File(str(tmp_path / "a.exr")) as f:
        np.testing.assert_array_equal(f.channels()["RGB"].pixels, image)
    with pytest.raises(ValueError, match=r"unknown image format '\.jpg'"):
        brdf_rs.save_image(tmp_path / "a.jpg", image)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.exr", "a.npy", "a.png"]


def test_tonemap_function():
    x = np.array([0.0, 0.5, 1.0, 3.0, -1.0], dtype=np.float32)
    np.testing.assert_allclose(brdf_rs.tonemap(x, "reinhard"), [0, 1 / 3, 0.5, 0.75, 0])
    np.testing.assert_allclose(brdf_rs.tonemap(x, "clamp", exposure=1), [0, 1, 1, 1, 0])
    with pytest.raises(ValueError, match="tonemap: expected one of"):
        brdf_rs.tonemap(x, "filmic")
    # A NaN pixel is refused by index, not painted black.
    with pytest.raises(ValueError, match=r"^image\[4\] = nan"):
        brdf_rs.tonemap(np.insert(x, 4, np.nan), "reinhard")


# ----------------------------------------------------------------------- bad scene files

GOOD = {
    "camera": {"position": [0, 0, 5], "resolution": [8, 8]},
    "materials": {"red": {"model": "lambert", "kd": [1, 0, 0]}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "red"}],
    "lights": [{"type": "directional", "direction": [0, 0, -1]}],
}

BAD = [
    (
        "[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\nfovv = 30\n",
        r"camera\.fovv: unknown key \(did you mean 'fov'\?\); camera takes: type, position",
    ),
    ("[materials.a]\nmodel = 'lambert'\n", r"camera: missing: a scene needs a \[camera\] table"),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = "640x480"\n',
        r"camera\.resolution: expected \[width, height\]: two integers from 1 to 32768, got '640x480'",
    ),
    (
        "[camera]\nposition = [0, 0]\nresolution = [8, 8]\n",
        r"camera\.position: expected \[x, y, z\] \(three numbers\), got \[0, 0\]",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[[objects]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = -1\nmaterial = "red"\n[materials.red]\nmodel = "lambert"\n',
        r"objects\[0\]\.radius: expected a positive number, got -1",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[[objects]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = "rde"\n[materials.red]\nmodel = "lambert"\n',
        r"objects\[0\]\.material: unknown material 'rde' \(did you mean 'red'\?\); defined materials: red",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[materials.red]\nmodel = "lambert"\nkd = "red"\n',
        r"materials\.red\.kd: expected a colour: a number or an RGB triple \[r, g, b\] >= 0 and finite, got 'red'",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[materials.red]\nmodel = "phong"\np = -2\n',
        r"materials\.red\.p: expected a number >= 0 and finite, got -2",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[materials.red]\nmodel = "torrance_sparow"\n',
        r"materials\.red\.model: unknown model 'torrance_sparow' \(did you mean 'torrance_sparrow'\?\)",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[materials.red]\nmodel = "phong"\nkss = 1\n',
        r"materials\.red\.kss: unknown key \(did you mean 'ks'\?\); materials\.red takes: model, kd, ks, p",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[materials.red]\nmodel = "lambert_shading"\n',
        r"materials\.red\.model: lambert_shading is a family-B shading term",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[materials.red]\ndiffuse = { model = "phong_specular" }\n',
        r"materials\.red\.diffuse\.model: phong_specular is not a diffuse term; diffuse takes: lambert_shading",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[materials.t]\ndiffuse = { model = "toon_diffuse", thresholds = [0.5, 0.2], colors = [0, 0.5, 1] }\n',
        r"materials\.t\.diffuse: thresholds must be ascending",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[materials.t]\ndiffuse = { model = "toon_diffuse", colors = [0, 1] }\n',
        r"materials\.t\.diffuse\.thresholds: missing \(required by toon_diffuse",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[[lights]]\ntype = "spot"\n',
        r"lights\[0\]\.type: expected 'directional' or 'point', got 'spot'",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[[lights]]\ntype = "point"\nposition = [0, 1, 0]\nrange = 0\n',
        r"lights\[0\]\.range: expected a positive number, got 0",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[[lights]]\ntype = "directional"\ndirection = [0, 0, 0]\n',
        r"lights\[0\]\.direction: expected a nonzero vector",
    ),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[output]\ntonemap = "filmic"\n',
        r"output\.tonemap: expected 'clamp' or 'reinhard' or 'aces' or 'none', got 'filmic'",
    ),
    (
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 5]\nresolution = [8, 8]\n",
        r"camera\.look_at: must differ from camera\.position",
    ),
    (
        "[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\nheight = 3\n",
        r"camera\.height: applies to orthographic cameras",
    ),
    ("[camera\nposition = 1\n", r"not valid TOML: .*line 1"),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[[objects]]\ntype = "plane"\nnormal = [0, 1, 0]\nmaterial = "m"\n[materials.m]\nmodel = "lambert"\n',
        r"objects\[0\]\.point: missing",
    ),
    (
        "[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\nlights = 3\n",
        r"camera\.lights: unknown key",
    ),
    ("camera = 3\n", r"camera: expected a table, got 3"),
    (
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[[objects]]\ntype = "sphere"\ncenter = [0, 0, true]\nradius = 1\nmaterial = "m"\n[materials.m]\nmodel = "lambert"\n',
        r"objects\[0\]\.center: expected \[x, y, z\]",
    ),
]


@pytest.mark.parametrize(("text", "message"), BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_scene_files_name_the_file_the_key_and_what_was_expected(tmp_path, text, message):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    with pytest.raises(SceneError, match=message) as info:
        load_scene(path)
    assert str(info.value).startswith(f"{path}: ")
    assert isinstance(info.value, ValueError)


def test_a_good_scene_as_dict_renders():
    image = brdf_rs.render(GOOD)
    assert image.shape == (8, 8, 3) and image[4, 4, 0] > 0 and image[4, 4, 1] == 0


# -------------------------------------------------------------------------------- CLI


def test_cli_render_writes_png_and_exr(tmp_path, capsys):
    png = tmp_path / "out.png"
    npy = tmp_path / "out.npy"
    code = cli_main(
        [
            "render",
            str(SCENES / "hdr.toml"),
            "-o",
            str(png),
            "--npy",
            str(npy),
            "--tonemap",
            "reinhard",
            "--resolution",
            "64x36",
            "--json",
        ]
    )
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["tonemap"] == "reinhard" and summary["resolution"] == [64, 36]
    assert summary["stats"]["hits"] > 0 and png.exists()
    linear = np.load(npy)
    assert linear.shape == (36, 64, 3) and linear.max() > 1.0  # radiance, not tone-mapped
    code = cli_main(
        [
            "render",
            str(SCENES / "gallery.toml"),
            "-o",
            str(png),
            "--only",
            "specular",
            "--resolution",
            "64x32",
            "-q",
        ]
    )
    assert code == 0


def test_cli_errors_are_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(
        '[camera]\nposition = [0, 0, 5]\nresolution = [8, 8]\n[[objects]]\ntype = "cube"\n'
    )
    assert cli_main(["render", str(bad), "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert (
        err == f"brdf-rs render: {bad}: objects[0].type: expected 'sphere' or 'plane', got 'cube'"
    )
    assert cli_main(["render", str(tmp_path / "missing.toml"), "-o", "x.png"]) == 2
    assert "cannot read the scene" in capsys.readouterr().err
    assert cli_main(["render", str(SCENES / "gallery.toml"), "-o", str(tmp_path / "x.jpg")]) == 2
    assert "unknown image format" in capsys.readouterr().err


def test_cli_tables_are_cached_by_content(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(
        ONE_SPHERE.format(
            material='model = "normalized_blinn_phong"\nkd = 0\nks = 1\np = 2',
            lights=KEY,
        )
        + '\n[materials.same]\nmodel = "normalized_blinn_phong"\nks = [1, 1, 1]\np = 2.0\nkd = 0\n'
        + '[[objects]]\ntype = "plane"\npoint = [0, -1, 0]\nnormal = [0, 1, 0]\nmaterial = "same"\n'
        + '[materials.toon]\ndiffuse = { model = "lambert_shading" }\n'
        + '[[objects]]\ntype = "sphere"\ncenter = [3, 0, 0]\nradius = 1\nmaterial = "toon"\n'
    )
    cache = tmp_path / "cache"
    args = [
        "tables",
        str(scene),
        "--cache-dir",
        str(cache),
        "--mu-count",
        "32",
        "--samples",
        "512",
        "--json",
    ]
    assert cli_main(args) == 0
    first = json.loads(capsys.readouterr().out)["tables"]
    # Two family-A materials with the same parameters spelled differently share a table;
    # the unused torrance_sparrow and the family-B material get none.
    assert [(t["material"], t["cached"]) for t in first] == [("m", False), ("same", True)]
    assert first[0]["path"] == first[1]["path"]
    # normalized_blinn_phong's (p+8)/(8π) gains energy near normal incidence (docs/models.md).
    assert first[0]["gains_energy"]
    mtime = Path(first[0]["path"]).stat().st_mtime_ns
    assert cli_main(args) == 0
    second = json.loads(capsys.readouterr().out)["tables"]
    assert all(t["cached"] for t in second)
    assert Path(second[0]["path"]).stat().st_mtime_ns == mtime
    # Another sample count is another table.
    assert cli_main([*args[:-2], "1024", "--json"]) == 0
    third = json.loads(capsys.readouterr().out)["tables"]
    assert not third[0]["cached"] and third[0]["path"] != first[0]["path"]
    assert len(list(cache.iterdir())) == 2


def test_cli_render_runs_as_a_module(tmp_path):
    out = tmp_path / "g.png"
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "brdf_rs",
            "render",
            str(SCENES / "gallery.toml"),
            "-o",
            str(out),
            "--resolution",
            "32x16",
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert "kernel evaluations" in result.stdout and out.exists()


@pytest.mark.parametrize("model", ["ggx_ms", "beckmann_ms", "ashikhmin_shirley", "ward"])
def test_shade_agrees_with_eval_for_the_newer_models(rng, model):
    """shade with one directional light is L·f(l, v)·(n·l), f from brdf_rs.eval (the
    multiple-scattering lobes have no pure-Python reference; eval is checked elsewhere)."""
    count = 300
    n = rng.normal(size=(count, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    v = rng.normal(size=(count, 3))
    v = np.where((np.sum(n * v, axis=1) < 0)[:, None], -v, v)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    tangent = np.cross(n, rng.normal(size=(count, 3)))
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    direction = np.array([0.3, -1.0, 0.2])
    wi = -direction / np.linalg.norm(direction)
    intensity = np.array([1.0, 0.5, 0.25])
    params = {"alpha": 0.4, "ks": [0.9, 0.5, 0.2]} if model.endswith("_ms") else {}
    if model == "ward":
        params = {"kd": 0.2, "ks": 0.3, "alpha_x": 0.1, "alpha_y": 0.4}
    material = {"model": model, **params}
    lights = [{"type": "directional", "direction": direction.tolist(), "intensity": intensity}]
    got = brdf_rs.shade(material, n, v, lights, tangent=tangent)
    take = {"tangent": tangent} if model in TAKES_TANGENT else {}
    f = brdf_rs.eval(model, np.broadcast_to(wi, n.shape), v, n, **take, **params)
    want = intensity * f * np.maximum(n @ wi, 0)[:, None]
    assert np.count_nonzero(want.any(axis=1)) > 50
    np.testing.assert_allclose(got, want, rtol=2e-4, atol=1e-6)


def test_only_diffuse_is_refused_for_ashikhmin_shirley():
    material = {"model": "ashikhmin_shirley", "Rd": 0.5, "Rs": 0.1}
    lights = [{"type": "directional", "direction": [0, 0, -1], "intensity": 1}]
    with pytest.raises(ValueError, match="only: material 'material' uses ashikhmin_shirley"):
        brdf_rs.shade(material, [0, 0, 1], [0, 0, 1], lights, only="diffuse")
    spec = brdf_rs.shade(material, [0, 0, 1], [0.6, 0, 0.8], lights, only="specular")
    want = brdf_rs.eval("ashikhmin_shirley", [0, 0, 1], [0.6, 0, 0.8], Rd=0.0, Rs=0.1)
    np.testing.assert_allclose(spec, want, rtol=2e-5)
