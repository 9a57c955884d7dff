"""Bad arguments of every public function: a ``TypeError`` or ``ValueError`` naming the
argument (or the scene file and key) and what is expected, never an ``OverflowError``
from a conversion, a NumPy message or warning, or a silently wrong result. Also: NumPy
numbers in dict scenes, the command line's checks before any work, and the float32 rule
for big-endian input."""

from __future__ import annotations

import os
import subprocess
import sys
import warnings

import brdf_rs
import numpy as np
import pytest
from brdf_rs import _brdf_rs as core

HUGE = 10**400  # a Python int no float can hold
WI, WO = [0.0, 0.0, 1.0], [0.3, 0.0, 1.0]


@pytest.fixture(autouse=True)
def _no_warnings():
    """Every call here must raise cleanly or succeed without a warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yield


# ------------------------------------------------- numbers beyond what a conversion holds


@pytest.mark.parametrize(
    ("params", "pattern"),
    [
        ({"p": HUGE}, r"^p = 1000\d+\.\.\. is out of range: beyond float64's"),
        ({"p": -HUGE}, r"^p = -1000\d+\.\.\. is out of range"),
        ({"kd": [0.0, HUGE, 0.0]}, r"^kd\[1\] = 1000\d+\.\.\. is out of range"),
        ({"kd": [[0.1, 0.1, 0.1], [0.2, 0.2, HUGE]]}, r"^kd\[1, 2\] = 1000"),
        ({"eta": [1.5, "x"]}, r"^eta: expected real numbers"),
    ],
)
def test_eval_parameters_beyond_float64_name_the_parameter(params, pattern):
    error = TypeError if "x" in str(params) else ValueError
    with pytest.raises(error, match=pattern):
        brdf_rs.eval("torrance_sparrow", WI, WO, **params)


def test_every_parameter_path_names_a_huge_integer():
    with pytest.raises(ValueError, match=r"^p = 1000"):
        brdf_rs.Model("torrance_sparrow", p=HUGE)
    with pytest.raises(ValueError, match=r"^p = 1000"):
        brdf_rs.eval("normalized_blinn_phong", WI, WO, p=HUGE, normalization="exact")
    with pytest.raises(ValueError, match=r"^kd = 1000"):
        brdf_rs.sample("lambert", WI, [0.5, 0.5], kd=HUGE)
    with pytest.raises(ValueError, match=r"^u\[0\] = 1000"):
        brdf_rs.sample("lambert", WI, [HUGE, 0.5])
    with pytest.raises(ValueError, match=r"^kd = 1000"):
        brdf_rs.pdf("lambert", WI, WO, kd=HUGE)
    with pytest.raises(ValueError, match=r"^wi\[2\] = 1000"):
        brdf_rs.eval("lambert", [0, 0, HUGE], WO)
    with pytest.raises(ValueError, match=r"^mu = 1000"):
        brdf_rs.albedo("lambert", HUGE)
    with pytest.raises(ValueError, match=r"^phi = 1000"):
        brdf_rs.albedo("lambert", 0.5, phi=HUGE)
    with pytest.raises(ValueError, match=r"^tol: expected a positive number .*1000"):
        brdf_rs.albedo("lambert", 0.5, tol=HUGE)
    with pytest.raises(ValueError, match=r"^n\[2\] = 1000"):
        brdf_rs.shade({"model": "lambert"}, [0, 0, HUGE], WI, [_sun()])
    with pytest.raises(ValueError, match=r"^exposure: expected a finite number"):
        brdf_rs.tonemap(np.ones((1, 1, 3)), "clamp", HUGE)
    with pytest.raises(ValueError, match=r"^image\[0, 0, 0\] = 1000"):
        brdf_rs.tonemap([[[HUGE, 0, 0]]])


@pytest.mark.parametrize(
    ("option", "value", "error", "pattern"),
    [
        ("replicates", 2**32, ValueError, r"^replicates: expected an integer from 2 to 4096, got"),
        ("replicates", 1, ValueError, r"^replicates: expected an integer from 2 to"),
        ("samples", 2**64, ValueError, r"^samples: expected an integer from 1 to 2\*\*40, got"),
        ("samples", np.uint64(0), ValueError, r"^samples: expected an integer from 1 to"),
        ("samples", 1.5, TypeError, r"^samples: expected an integer"),
        ("samples", True, TypeError, r"^samples: expected an integer"),
        ("samples", float("inf"), TypeError, r"^samples: expected an integer"),
        ("seed", -1, ValueError, r"^seed: expected an integer from 0 to"),
        ("seed", 2**64, ValueError, r"^seed: expected an integer from 0 to"),
        ("seed", "1", TypeError, r"^seed: expected an integer"),
        ("max_samples", 2**70, ValueError, r"^max_samples: expected an integer from 1 to 2\*\*40"),
        ("tol", "a", TypeError, r"^tol: expected a positive number"),
        ("tol", float("nan"), ValueError, r"^tol: expected a positive number"),
        ("rtol", "a", TypeError, r"^rtol: expected a positive number"),
        ("rtol", float("inf"), ValueError, r"^rtol: expected a positive number"),
        ("rtol", -0.01, ValueError, r"^rtol: must be a positive number; got -0.01"),
        ("sampler", 3, TypeError, r'^sampler: expected "auto", "importance"'),
        ("sequence", None, TypeError, r'^sequence: expected "sobol" or "random"'),
    ],
)
def test_albedo_integer_and_option_arguments_name_their_range(option, value, error, pattern):
    with pytest.raises(error, match=pattern):
        brdf_rs.albedo("lambert", 0.5, **{option: value})


_BAD_OPTIONS = [
    ("samples", 1.5),
    ("samples", 2**41),
    ("samples", np.float32(1e30)),
    ("seed", -1),
    ("seed", "1"),
    ("replicates", np.int64(1)),
    ("max_samples", np.float64(2.5)),
    ("tol", -1e-5),
    ("tol", 0.0),
    ("tol", 10**400),
    ("tol", True),
    ("rtol", 0.0),
    ("rtol", float("nan")),
    ("rtol", "1%"),
    ("sampler", "x" * 80),
    ("sampler", 3),
    ("sequence", "sobol\ud800"),
    ("sequence", None),
    ("samples", None),
]


@pytest.mark.parametrize(("option", "value"), _BAD_OPTIONS)
def test_an_option_is_refused_in_the_same_words_by_every_route(option, value):
    """One converter words the options: the public API, the early check the command line
    and dask use, and the core's own entry point called directly all give its error."""
    given = {
        "samples": 64,
        "sampler": "auto",
        "sequence": "sobol",
        "seed": 0,
        "tol": None,
        "max_samples": None,
        "replicates": 16,
        option: value,
    }
    errors = []
    for route in (
        lambda: brdf_rs.albedo("lambert", 0.5, **{option: value}),
        lambda: core.check_albedo_options(given),
        lambda: core.albedo("lambert", np.array(0.5), {}, given),
    ):
        with pytest.raises((TypeError, ValueError)) as caught:
            route()
        errors.append((type(caught.value), str(caught.value)))
    assert errors[0][1].startswith(f"{option}: ")
    assert errors[1] == errors[0]
    assert errors[2] == errors[0]


def test_the_cores_option_converter_refuses_an_unknown_option_and_fills_defaults():
    with pytest.raises(TypeError, match=r"^unknown albedo option 'sample'; expected samples,"):
        core.check_albedo_options({"sample": 64})
    filled = core.check_albedo_options({})
    assert filled == {
        "samples": 4096,
        "sampler": "auto",
        "sequence": "sobol",
        "seed": 0,
        "replicates": brdf_rs._options.DEFAULT_REPLICATES,
        "tol": None,
        "rtol": None,
        "max_samples": None,
        "component": "total",
    }


def test_albedo_checks_its_options_before_the_cell_ids():
    with pytest.raises(ValueError, match=r"^samples: expected an integer from 1 to 2\*\*40"):
        brdf_rs.albedo("ggx", 0.5, samples=0, cell_ids=[-1])


@pytest.mark.parametrize("sampler", [3, None, "magic"])
def test_sample_and_pdf_name_a_bad_sampler(sampler):
    error = TypeError if not isinstance(sampler, str) else ValueError
    pattern = r'^sampler: expected "auto", "importance", "cosine" or "uniform"; got'
    with pytest.raises(error, match=pattern):
        brdf_rs.sample("ggx", [0.3, 0, 1], [0.2, 0.5], sampler=sampler)
    with pytest.raises(error, match=pattern):
        brdf_rs.pdf("ggx", [0.3, 0, 1], [0, 0, 1], sampler=sampler)


def test_integer_options_accept_numpy_integers_and_integral_floats():
    a = brdf_rs.albedo("lambert", 0.5, samples=np.int64(64), seed=np.uint64(2**64 - 1))
    b = brdf_rs.albedo("lambert", 0.5, samples=64.0, seed=2**64 - 1, replicates=np.int32(16))
    np.testing.assert_array_equal(a.value, b.value)


@pytest.mark.parametrize(
    ("ids", "error", "pattern"),
    [
        (np.array([0, -1]), ValueError, r"^cell_ids\[1\] = -1 is out of range"),
        (2**64, ValueError, r"^cell_ids\[\] = 18446744073709551616 is out of range"),
        ([1, 2**65], ValueError, r"^cell_ids\[1\] = 3689\d+ is out of range"),
        (np.array([0.0, 1.5]), TypeError, r"^cell_ids: expected integers .* got dtype float64"),
        (np.array([True, False]), TypeError, r"^cell_ids: expected integers .* got dtype bool"),
        (["a", "b"], TypeError, r"^cell_ids\[0\]: expected integers .* got 'a'"),
    ],
)
def test_cell_ids_are_integers_from_0_to_2_64(ids, error, pattern):
    mu = np.array([0.2, 0.7])
    with pytest.raises(error, match=pattern):
        brdf_rs.albedo("lambert", mu if np.ndim(ids) else 0.5, cell_ids=ids, samples=64)


def test_cell_ids_of_any_integer_dtype_key_the_same_streams():
    mu = np.array([0.2, 0.7])
    ids = [5, 2**63 + 1]
    a = brdf_rs.albedo("ggx", mu, cell_ids=np.array(ids, dtype=np.uint64), samples=64)
    b = brdf_rs.albedo("ggx", mu, cell_ids=ids, samples=64)
    np.testing.assert_array_equal(a.value, b.value)


@pytest.mark.parametrize(
    ("n", "error", "pattern"),
    [
        (2**64, ValueError, r"^n: expected an integer from 1 to 65535, got 18446744073709551616"),
        (2**40, ValueError, r"^n: expected an integer from 1 to 65535"),
        (65536, ValueError, r"^n: expected an integer from 1 to 65535"),
        (0, ValueError, r"^n: expected an integer from 1 to 65535"),
        (-3, ValueError, r"^n: expected an integer from 1 to 65535"),
        (2.0, TypeError, r"^n: expected an integer thread count"),
        (True, TypeError, r"^n: expected an integer thread count"),
        ("4", TypeError, r"^n: expected an integer thread count"),
    ],
)
def test_thread_counts_beyond_the_pool_are_refused_and_change_nothing(n, error, pattern):
    before = brdf_rs.num_threads()
    with pytest.raises(error, match=pattern):
        brdf_rs.set_num_threads(n)
    assert brdf_rs.num_threads() == before


def test_the_core_refuses_more_threads_than_the_pool_can_have():
    """Rayon would silently start fewer; the core says so instead."""
    before = brdf_rs.num_threads()
    with pytest.raises(ValueError, match=r"^n: expected a thread count from 1 to 65535, got"):
        core.set_num_threads(core.max_num_threads() + 1)
    assert brdf_rs.num_threads() == before


# ------------------------------------------------------------------------------ scenes


def _sun(**extra):
    return {"type": "directional", "direction": [0, 0, -1], **extra}


def _scene(**changes):
    """A small dict scene; ``changes`` maps ``"a.b.0.c"`` paths to new values."""
    scene = {
        "camera": {"position": [0, 0, 5], "resolution": [6, 4]},
        "materials": {
            "m": {"model": "ggx", "kd": 0.5, "alpha": 0.3},
            "toon": {
                "diffuse": {"model": "toon_diffuse", "thresholds": [0.3], "colors": [0.1, 0.6]}
            },
        },
        "objects": [
            {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"},
            {"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "toon"},
        ],
        "lights": [_sun(intensity=1), {"type": "point", "position": [2, 2, 2], "intensity": 3}],
        "output": {"tonemap": "clamp", "exposure": 0, "background": 0},
    }
    for path, value in changes.items():
        *parents, last = path.split(".")
        node = scene
        for key in parents:
            node = node[int(key)] if key.isdigit() else node[key]
        node[int(last) if last.isdigit() else last] = value
    return scene


NUMPY_SCENES = {
    "camera.resolution": [np.int64(6), np.int32(4)],
    "camera.resolution.0": np.uint16(6),
    "camera.position": np.array([0.0, 0.0, 5.0], dtype=np.float32),
    "camera.fov": np.float32(40),
    "materials.m.kd": np.float32(0.5),
    "materials.m.alpha": np.float64(0.3),
    "materials.m.ks": np.array([1, 1, 1]),
    "materials.toon.diffuse.thresholds": np.array([0.3], dtype=np.float32),
    "materials.toon.diffuse.colors": np.array([0.1, 0.6]),
    "objects.0.radius": np.int64(1),
    "objects.0.center": np.zeros(3, dtype=np.int8),
    "objects.1.normal": (np.int64(0), np.float32(1), 0),
    "lights.0.intensity": np.int64(1),
    "lights.1.intensity": np.array([3, 3, 3], dtype=np.float32),
    "lights.1.range": np.float32(100),
    "output.exposure": np.int64(0),
    "output.background": np.array([0.0, 0.0, 0.0]),
}


@pytest.mark.parametrize(("path", "value"), NUMPY_SCENES.items(), ids=list(NUMPY_SCENES))
def test_dict_scenes_take_numpy_numbers_and_arrays_like_python_numbers(path, value):
    expected = brdf_rs.render(_scene())
    if path == "lights.1.range":
        expected = brdf_rs.render(_scene(**{path: 100}))
    np.testing.assert_array_equal(brdf_rs.render(_scene(**{path: value})), expected)


def test_a_colour_list_may_hold_numpy_triples():
    colors = [np.array([0.1, 0.1, 0.1]), np.float32(0.6)]
    image = brdf_rs.render(_scene(**{"materials.toon.diffuse.colors": colors}))
    np.testing.assert_array_equal(image, brdf_rs.render(_scene()))


@pytest.mark.parametrize(
    ("path", "value", "pattern"),
    [
        ("objects.0.radius", np.bool_(True), r"objects\[0\]\.radius: expected a positive number"),
        ("objects.0.radius", True, r"objects\[0\]\.radius: expected a positive number"),
        ("objects.0.radius", np.float32("nan"), r"objects\[0\]\.radius: expected a positive"),
        ("objects.0.radius", "1", r"objects\[0\]\.radius: expected a positive number"),
        ("objects.0.center", np.array([True, False, True]), r"objects\[0\]\.center: expected"),
        ("objects.0.center", np.zeros((1, 3)), r"objects\[0\]\.center: expected \[x, y, z\]"),
        ("objects.0.center", np.array([0.0, np.inf, 0.0]), r"objects\[0\]\.center: expected"),
        ("camera.resolution", [np.float64(6), 4], r"camera\.resolution: expected \[width"),
        ("camera.resolution", [np.bool_(True), 4], r"camera\.resolution: expected \[width"),
        ("camera.resolution", np.array([6, 4, 1]), r"camera\.resolution: expected \[width"),
        ("camera.fov", np.float32(180), r"camera\.fov: expected an angle"),
        ("materials.m.kd", np.array(["a", "b", "c"]), r"materials\.m\.kd: expected a colour"),
        ("materials.m.alpha", np.float32(-1), r"materials\.m\.alpha: expected a number in"),
        ("lights.0.intensity", np.int64(-1), r"lights\[0\]\.intensity: expected a colour"),
        ("lights.0.intensity", np.array([1, 1]), r"lights\[0\]\.intensity: expected a colour"),
        ("output.exposure", np.float64("nan"), r"output\.exposure: expected a number"),
    ],
)
def test_dict_scenes_still_refuse_bools_nan_and_strings_naming_the_key(path, value, pattern):
    with pytest.raises(brdf_rs.SceneError, match=r"^<scene>: " + pattern):
        brdf_rs.render(_scene(**{path: value}))


FLOAT32_TOO_BIG = [
    ("objects.0.radius", HUGE),
    ("objects.0.radius", 1e300),
    ("objects.0.center", [1e39, 0, 0]),
    ("objects.1.point", [0, -HUGE, 0]),
    ("camera.position", [0, 0, 1e300]),
    ("materials.m.kd", 1e300),
    ("materials.m.kd", [1, 1e39, 1]),
    ("lights.0.intensity", 1e300),
    ("lights.1.position", [HUGE, 0, 0]),
    ("lights.1.range", 1e39),
    ("output.exposure", HUGE),
    ("output.background", [0, 0, 1e300]),
]


@pytest.mark.parametrize(("path", "value"), FLOAT32_TOO_BIG, ids=[p for p, _ in FLOAT32_TOO_BIG])
def test_scene_numbers_beyond_the_renderers_float32_are_refused_by_key(path, value):
    key = path.replace(".0.", "[0].").replace(".1.", "[1].")
    key = key.replace("objects.", "objects").replace("lights.", "lights")
    with pytest.raises(brdf_rs.SceneError, match=r"beyond float32's range") as info:
        brdf_rs.render(_scene(**{path: value}))
    assert str(info.value).startswith(f"<scene>: {key}")
    assert ": expected " in str(info.value)


def test_a_400_digit_integer_in_a_scene_file_names_the_file_and_key(tmp_path):
    path = tmp_path / "big.toml"
    path.write_text(
        "[camera]\nposition = [0, 0, 5]\nresolution = [4, 4]\n"
        '[materials.m]\nmodel = "lambert"\n'
        '[[objects]]\ntype = "sphere"\ncenter = [0, 0, 0]\nmaterial = "m"\n'
        f"radius = 1{'0' * 400}\n"
    )
    with pytest.raises(brdf_rs.SceneError, match=r"^.*big\.toml: objects\[0\]\.radius: expected"):
        brdf_rs.load_scene(path)
    result = _cli("render", str(path), "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "objects[0].radius" in result.stderr
    assert "Traceback" not in result.stderr and "OverflowError" not in result.stderr


def test_the_core_refuses_what_float32_cannot_hold_when_called_directly():
    """The Python layer checks first; the core checks again, so nothing becomes inf."""
    base = brdf_rs.parse_scene(_scene()).to_core()

    def with_object(**changes):
        objects = [dict(base["objects"][0], **changes)]
        return {**base, "objects": objects}

    cases = [
        (with_object(radius=1e300), r"radius: expected a positive number within float32"),
        (with_object(center=[0.0, 1e39, 0.0]), r"center: expected finite numbers within"),
        ({**base, "background": [0.0, 1e300, 0.0]}, r"^background: expected an RGB triple"),
        (
            {**base, "lights": [dict(base["lights"][0], intensity=[1e300] * 3)]},
            r"intensity: expected an RGB triple of numbers >= 0 within float32",
        ),
        (
            {**base, "lights": [dict(base["lights"][1], range=1e300)]},
            r"range: expected a positive number within float32",
        ),
    ]
    brdf = {"brdf": {"model": "lambert", "params": {"kd": np.array(1e300)}}}
    cases.append(({**base, "materials": [brdf, brdf]}, r"kd = 1e300 is out of range"))
    for scene, pattern in cases:
        with pytest.raises(ValueError, match=pattern):
            core.render_scene(scene, "both")


#: Values a caller of the core may put anywhere in a scene's plain structure.
ODD_VALUES = [
    None, True, "x", -1, 0, 3, 2**70, float("nan"), float("inf"), -1e300, [], [1.0],
    [float("nan")] * 3, [1e300] * 3, [-1.0] * 3, [0.0] * 3, [2**70] * 3, {}, {"x": 1},
]  # fmt: skip


def _core_scene_variants(base):
    """Every key of ``base``'s plain structure, in turn removed or set to each odd value."""

    def walk(node, path):
        keys = range(len(node)) if isinstance(node, list) else list(node)
        for key in keys:
            yield node, key, (*path, key)
            if isinstance(node[key], (dict, list)):
                yield from walk(node[key], (*path, key))

    for node, key, path in list(walk(base, ())):
        original = node[key]
        for value in [*ODD_VALUES, "remove"]:
            if value == "remove" and isinstance(node, dict):
                del node[key]
            else:
                node[key] = np.asarray(value) if path[-2:-1] == ("params",) else value
            yield path, value
            node[key] = original


def test_the_core_converts_a_scene_without_ever_panicking():
    """The core's scene binding converts what the schema checked; given anything else it
    raises a TypeError or ValueError naming the problem, never a panic (the renderer's
    types hold their invariants)."""
    base = brdf_rs.parse_scene(_scene()).to_core()
    base["camera"]["resolution"] = [3, 2]
    refused = 0
    for path, value in _core_scene_variants(base):
        try:
            image, _ = core.render_scene(base, "both")
        except (TypeError, ValueError):
            refused += 1
        else:
            assert image.shape[2] == 3, (path, value)
    assert refused > 100
    # Models in the wrong place: the renderer checks their families.
    brdf, shading = base["materials"]
    for swapped in ({"brdf": shading["diffuse"]}, {"diffuse": brdf["brdf"], "specular": None}):
        scene = {**base, "materials": [swapped, shading]}
        with pytest.raises(ValueError, match=r"is a family-. model; expected family"):
            core.render_scene(scene, "both")


def test_the_core_converts_a_sheen_layer_without_ever_panicking():
    """The same for a material's sheen layer: every key of ``{"model", "params",
    "weight"}`` removed or set to each odd value."""
    layer = {"model": "charlie_sheen", "ks": [0.9, 0.5, 0.5], "alpha": 0.3, "weight": 0.8}
    base = brdf_rs.parse_scene(_scene(**{"materials.m.sheen": layer})).to_core()
    base["camera"]["resolution"] = [3, 2]
    sheen = base["materials"][0]["sheen"]
    assert sheen["weight"] == 0.8
    refused = 0
    for path, value in _core_scene_variants(sheen):
        try:
            image, _ = core.render_scene(base, "both")
        except (TypeError, ValueError):
            refused += 1
        else:
            assert image.shape[2] == 3 and np.isfinite(image).all(), (path, value)
    assert refused > 30
    cases = [
        ({**sheen, "model": "ggx"}, r"materials\[0\]\.sheen\.model: ggx is not a sheen model"),
        ({**sheen, "weight": 2.0}, r"materials\[0\]\.sheen\.weight: expected a number in"),
        (
            {**sheen, "params": {**sheen["params"], "kd": np.array(0.5)}},
            r"materials\[0\]\.sheen\.kd: a sheen layer has no diffuse term",
        ),
    ]
    for layer, pattern in cases:
        materials = [{**base["materials"][0], "sheen": layer}, base["materials"][1]]
        with pytest.raises(ValueError, match=pattern):
            core.render_scene({**base, "materials": materials}, "both")
    # Over family-B terms, a layer is refused by name.
    materials = [base["materials"][0], {**base["materials"][1], "sheen": sheen}]
    with pytest.raises(ValueError, match=r"materials\[1\]\.sheen: a sheen layer goes over"):
        core.render_scene({**base, "materials": materials}, "both")


def test_scene_tables_checks_its_numbers_first(tmp_path):
    scene = _scene()
    with pytest.raises(ValueError, match=r"^mu_count: expected an integer from 1 to 1048576"):
        brdf_rs.scene_tables(scene, cache_dir=tmp_path, mu_count=2**64)
    with pytest.raises(ValueError, match=r"^samples: expected an integer from 1"):
        brdf_rs.scene_tables(scene, cache_dir=tmp_path, samples=0)
    with pytest.raises(TypeError, match=r"^tol: expected a positive number"):
        brdf_rs.scene_tables(scene, cache_dir=tmp_path, tol="small")
    # NumPy integers are numbers like any other (the cache key is JSON).
    (result,) = brdf_rs.scene_tables(
        scene, cache_dir=tmp_path, mu_count=np.int64(2), samples=np.int64(64), seed=np.uint8(1)
    )
    assert result.model == "ggx"


# ------------------------------------------------- wrong types and shapes, by argument


@pytest.mark.parametrize(
    "call",
    [
        lambda m: brdf_rs.eval(m, WI, WO),
        lambda m: brdf_rs.Model(m),
        lambda m: brdf_rs.sample(m, WI, [0.5, 0.5]),
        lambda m: brdf_rs.pdf(m, WI, WO),
        lambda m: brdf_rs.albedo(m, 0.5),
        lambda m: brdf_rs.albedo_table(m, {"mu": [0.5]}),
        lambda m: brdf_rs.dfg_table(m, [0.5], [0.5]),
        lambda m: brdf_rs.energy(m),
        lambda m: brdf_rs.energy_compensation_table(m, [0.5], [0.5]),
    ],
    ids=["eval", "Model", "sample", "pdf", "albedo", "albedo_table", "dfg", "energy", "ec"],
)
@pytest.mark.parametrize("model", [3, None, b"ggx", ["ggx"]], ids=["int", "None", "bytes", "list"])
def test_a_model_that_is_not_a_string_is_a_type_error_naming_model(call, model):
    with pytest.raises(TypeError, match=r"^model: expected a model name \(a string"):
        call(model)


def test_albedo_table_axes_must_be_a_mapping():
    with pytest.raises(TypeError, match=r"^axes: expected a mapping \{name: coordinates\}"):
        brdf_rs.albedo_table("ggx", [0.1, 0.5])
    with pytest.raises(TypeError, match=r"^axes: expected a mapping .* got ndarray"):
        brdf_rs.albedo_table("ggx", np.linspace(0, 1, 4))


@pytest.mark.parametrize(
    ("axes", "fixed", "error", "pattern"),
    [
        ({"mu": [0.5]}, {"alpha": [0.1, 0.2]}, ValueError, r"^alpha: a value held fixed .* \(2,\)"),
        (
            {"mu": [0.5]},
            {"kd": [[0.1] * 3] * 2},
            ValueError,
            r"^kd: a value held fixed .* \(2, 3\)",
        ),
        ({"alpha": [0.5]}, {"mu": [0.1, 0.2]}, ValueError, r"^mu: a value held fixed"),
        ({"alpha": [0.5]}, {"mu": 2.0}, ValueError, r"^mu = 2\.0 is out of range"),
        ({"mu": [0.5]}, {"alpha": "rough"}, TypeError, r"^alpha: expected real numbers"),
        ({"mu": [0.5]}, {"alpha": -1}, ValueError, r"^alpha = -1\.0 is out of range"),
        ({"mu": [0.5]}, {"samples_": 3}, TypeError, r"^samples_: unknown keyword; ggx takes"),
        ({"foo": [1, 2]}, {}, ValueError, r"^axes\['foo'\]: unknown axis; ggx tabulates over mu"),
        ({"mu": [0.5], "foo": [1]}, {}, ValueError, r"^axes\['foo'\]: unknown axis"),
        ({"mu": [0.5, 2.0]}, {}, ValueError, r"^axes\['mu'\]\[1\] = 2\.0 is out of range"),
        ({"mu": [0.5], "alpha": [0.1, -1]}, {}, ValueError, r"^axes\['alpha'\]\[1\]: alpha = -1"),
        ({"mu": [0.5], "kd": [0.1, np.nan]}, {}, ValueError, r"^axes\['kd'\]\[1\]: kd = nan"),
        ({"mu": [[0.5]]}, {}, ValueError, r"^axes\['mu'\]: expected a non-empty 1-D list"),
        ({"mu": ["a"]}, {}, TypeError, r"^axes\['mu'\]: expected real numbers"),
        ({"mu": [0.5], "phi": [0, np.inf]}, {}, ValueError, r"^axes\['phi'\]\[1\] = inf is not"),
        ({"mu": [0.5]}, {"alpha": HUGE}, ValueError, r"^alpha = 1000\d+\.\.\. is out of range"),
    ],
)
def test_albedo_table_names_the_bad_axis_or_fixed_value(axes, fixed, error, pattern):
    with pytest.raises(error, match=pattern):
        brdf_rs.albedo_table("ggx", axes, samples=64, **fixed)


def test_albedo_table_refuses_a_shading_term_before_any_work():
    with pytest.raises(ValueError, match=r"^lambert_shading: a family-B shading term"):
        brdf_rs.albedo_table("lambert_shading", {"mu": [0.5]})
    with pytest.raises(ValueError, match=r'^unknown model "gxx" \(did you mean "ggx"\?\)'):
        brdf_rs.albedo_table("gxx", {"mu": [0.5]})


@pytest.mark.parametrize(
    ("call", "error", "pattern"),
    [
        (lambda: brdf_rs.dfg_table("ggx", ["a"], [0.5]), TypeError, r"^mu: expected real numbers"),
        (lambda: brdf_rs.dfg_table("ggx", [0.5], [[0.5]]), ValueError, r"^roughness: expected a"),
        (lambda: brdf_rs.dfg_table("ggx", [0.5], []), ValueError, r"^roughness: expected a non"),
        (
            lambda: brdf_rs.dfg_table("ggx", [0.5], [0.2, -1]),
            ValueError,
            r"^roughness\[1\]: alpha = -1\.0 is out of range",
        ),
        (
            lambda: brdf_rs.dfg_table("blinn_phong_fresnel", [0.5, 1.5], [1]),
            ValueError,
            r"^mu\[1\] = 1\.5 is out of range",
        ),
        (
            lambda: brdf_rs.energy_compensation_table("ggx", [0.5], [0.1, 0.0]),
            ValueError,
            r"^alpha\[1\]: alpha = 0\.0 is out of range",
        ),
        (
            lambda: brdf_rs.energy_compensation_table("ggx", [0.5], "rough"),
            TypeError,
            r"^alpha: expected real numbers",
        ),
        (lambda: brdf_rs.energy("ggx", seed=2**64 - 1), ValueError, r"^seed: expected an integer"),
    ],
)
def test_dfg_and_energy_tables_name_their_arguments(call, error, pattern):
    with pytest.raises(error, match=pattern):
        call()


@pytest.mark.parametrize(
    ("image", "error", "pattern"),
    [
        (
            np.ones((2, 2, 3), dtype=complex),
            TypeError,
            r"^image: expected real numbers, got complex",
        ),
        (np.full((2, 2, 3), "x"), TypeError, r"^image: expected real numbers, got dtype <U1"),
        (np.ones((2, 2, 3), dtype=bool), TypeError, r"^image: expected real numbers, got a bool"),
        ([[[1, 2, 3]], [[1, 2]]], TypeError, r"^image: expected an array of numbers"),
        (np.ones((2, 2, 4)), ValueError, r"^image: expected shape \(height, width, 3\)"),
    ],
)
def test_save_image_and_tonemap_refuse_what_is_not_an_image(tmp_path, image, error, pattern):
    with pytest.raises(error, match=pattern):
        brdf_rs.save_image(tmp_path / "x.npy", image)
    assert list(tmp_path.iterdir()) == []
    if image.__class__ is np.ndarray and image.shape == (2, 2, 4):
        return  # tonemap takes any shape
    with pytest.raises(error, match=pattern):
        brdf_rs.tonemap(image)


def test_save_image_path_must_be_a_file_name(tmp_path):
    with pytest.raises(TypeError, match=r"^path: expected a file name"):
        brdf_rs.save_image(3, np.zeros((1, 1, 3)))  # type: ignore[arg-type]


def test_render_and_tonemap_options_name_themselves():
    with pytest.raises(ValueError, match=r"^tonemap: expected one of clamp"):
        brdf_rs.render(_scene(), tonemap=["clamp"])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^exposure: expected a finite number"):
        brdf_rs.render(_scene(), exposure="2")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^exposure: expected a finite number"):
        brdf_rs.tonemap(np.ones((1, 1, 3)), "clamp", 10**400)
    with pytest.raises(TypeError, match=r"^scene: expected a Scene, a path or a dict"):
        brdf_rs.render(3)  # type: ignore[arg-type]


def test_shade_names_bad_vectors():
    with pytest.raises(TypeError, match=r"^v: expected real numbers, got complex"):
        brdf_rs.shade({"model": "lambert"}, [0, 0, 1], [0, 0, 1j], [_sun()])
    with pytest.raises(TypeError, match=r"^positions: expected an array of numbers"):
        brdf_rs.shade({"model": "lambert"}, [0, 0, 1], WI, [_sun()], positions=[[0, 1], [1]])


# ---------------------------------------------------------------- the command line


def _cli(*args: str, code: str | None = None) -> subprocess.CompletedProcess:
    env = {**os.environ, "BRDF_RS_NUM_THREADS": "2"}
    command = [sys.executable, "-c", code, *args] if code else [sys.executable, "-m", "brdf_rs"]
    if not code:
        command += list(args)
    return subprocess.run(command, capture_output=True, text=True, env=env, check=False)


def _one_line_error(result: subprocess.CompletedProcess, code: int = 2) -> str:
    """The command failed with ``code`` and one line on stderr: no warning, no progress
    bar, no traceback, no usage block (argparse's own errors included)."""
    assert result.returncode == code, (result.returncode, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    for noise in ("Warning", "Traceback", "%|", "it/s", "cell/s", "model/s", "model ["):
        assert noise not in result.stderr, result.stderr
    return lines[0]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["table", "ggx", "--axis", "alpha=log:-1:1:8"], "axis alpha: a log axis needs positive"),
        (
            ["table", "ggx", "--axis", "mu=mid:0:1:4", "--axis", "alpha=log:0:1:8"],
            "axis alpha: a log axis needs positive ends (start and stop > 0), got 0 and 1",
        ),
        (
            ["table", "ggx", "--axis", "mu=mid:0:1:4", "--axis", "alpha=-1,0.5"],
            "axes['alpha'][0]: alpha = -1.0 is out of range",
        ),
        (["table", "ggx", "--axis", "foo=0:1:3"], "axes['foo']: unknown axis"),
        (["table", "ggx", "--axis", "mu=0:1:3", "--axis", "foo=1"], "axes['foo']: unknown axis"),
        (["table", "gxx"], 'unknown model "gxx" (did you mean "ggx"?)'),
        (["table", "ggx", "--axis", "mu=0:1:1e30"], "count: expected an integer"),
        (["table", "ggx", "--axis", "mu=0:1:99999999999999"], "count must be from 1 to"),
        (["table", "ggx", "--axis", "mu=lin:-1e308:1e308:3"], "the values overflow float64"),
        (["table", "ggx", "--axis", "mu=inf:1:3"], "start and stop must be finite"),
        (["table", "ggx", "--samples", "99999999999999999999999"], "samples: expected an integer"),
        (["table", "ggx", "--seed", "-1"], "seed: expected an integer from 0"),
        (["table", "ggx", "-p", "alpha=1e400"], "alpha: 1e400 is beyond float64's range"),
        (["table", "ggx", "-p", "alpha=0.1,0.2"], "alpha: a value held fixed over the table"),
        (["table", "ggx", "--phi", "nan"], "phi: must be a finite number of degrees"),
        (["dfg", "ggx", "--roughness", "log:-1:1:4"], "a log axis needs positive ends"),
        (["dfg", "ggx", "--samples", "0"], "samples: expected an integer from 1"),
        (["dfg", "ggx", "--roughness", "0:2:3"], "roughness[0]: alpha = 0.0 is out of range"),
        (["energy", "ggx", "--alpha", "0:2:4"], "alpha[0]: alpha = 0.0 is out of range"),
        (["bench", "--threads", "99999999999999999999"], "n: expected an integer from 1 to"),
        (["eval", "ggx", "--wi", "0,0,1", "--wo", "0,0,1", "-p", "alpha=1e999"], "beyond float64"),
        (
            ["eval", "ggx", "--wi", "0,0,1", "--wo", "0,0,1", "-p", "alpha=0.1", "-p", "alpha=0.2"],
            "--param alpha= is given twice",
        ),
        (["table", "ggx", "-p", "alpha=0.1", "-p", "alpha=0.2"], "--param alpha= is given twice"),
        (["table", "ggx", "--axis", "mu=0:1:3", "--axis", "mu=0:1:4"], "--axis mu= is given twice"),
    ],
)
def test_cli_checks_everything_before_any_work_in_one_line(tmp_path, args, message):
    result = _cli(*args, "-o", str(tmp_path / "t.npz")) if args[0] != "eval" else _cli(*args)
    if args[0] == "bench":
        result = _cli(*args)
    line = _one_line_error(result)
    assert message in line, line
    assert list(tmp_path.iterdir()) == []


def test_cli_eval_prints_one_rgb_line_per_value_of_a_list_parameter():
    result = _cli("eval", "ggx", "--wi", "0,0,1", "--wo", "0,0,1", "-p", "alpha=0.1,0.2,0.3")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.strip().splitlines()
    expected = brdf_rs.eval("ggx", [0, 0, 1], [0, 0, 1], alpha=[0.1, 0.2, 0.3])
    assert [[float(x) for x in line.split()] for line in lines] == expected.tolist()


@pytest.mark.parametrize("value", [None, [0.1, None], np.array([None, 0.2], dtype=object)])
def test_none_is_not_a_number(value):
    """NumPy converts None to NaN; a missing value is a type error naming the argument,
    not an out-of-range NaN."""
    with pytest.raises(TypeError, match=r"^alpha(\[\d\])?: expected a real number, got NoneType"):
        brdf_rs.eval("ggx", [0, 0, 1], [0, 0, 1], alpha=value)
    with pytest.raises(TypeError, match=r"^alpha(\[\d\])?: expected a real number, got NoneType"):
        brdf_rs.albedo("ggx", 0.5, alpha=value)


def test_cli_stress_without_mpmath_says_so_before_a_progress_bar():
    code = (
        "import sys; sys.modules['mpmath'] = None\n"
        "from brdf_rs.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n"
    )
    line = _one_line_error(_cli("stress", "--models", "lambert", code=code), code=1)
    assert line.startswith("brdf-rs stress: brdf_rs.stress needs mpmath")


def test_cli_progress_bar_still_shows_for_real_work(tmp_path):
    pytest.importorskip("tqdm")
    result = _cli("table", "lambert", "--axis", "mu=0:1:3", "-o", str(tmp_path / "t.npz"))
    assert result.returncode == 0, result.stderr
    assert "3/3" in result.stderr and "cell" in result.stderr


def test_cli_turns_a_numpy_warning_into_its_one_line_error(tmp_path):
    code = (
        "import sys, numpy as np\n"
        "from brdf_rs import cli\n"
        "def run(args):\n"
        "    np.log(np.array([-1.0]))\n"
        "    return 0\n"
        "cli.cmd_models = run\n"
        "sys.exit(cli.main(sys.argv[1:]))\n"
    )
    line = _one_line_error(_cli("models", code=code))
    assert line == "brdf-rs models: invalid value encountered in log"


# ------------------------------------------------------------------ dtype and byte order


@pytest.mark.parametrize(
    ("wi_dtype", "wo_dtype", "expected"),
    [
        (">f4", ">f4", np.float32),
        ("<f4", ">f4", np.float32),
        (">f4", "<f4", np.float32),
        (">f8", ">f8", np.float64),
        (">f4", ">f8", np.float64),
        (">f4", np.float16, np.float64),
        (">i4", ">f4", np.float64),
    ],
)
def test_byte_order_does_not_change_the_dtype_rule(rng, wi_dtype, wo_dtype, expected):
    wi = 10 * rng.normal(size=(16, 3))  # no zero vector once cast to integers
    wo = 10 * rng.normal(size=(16, 3))
    wi[:, 2], wo[:, 2] = 10 + np.abs(wi[:, 2]), 10 + np.abs(wo[:, 2])
    a, b = wi.astype(wi_dtype), wo.astype(wo_dtype)
    params = {"ks": 0.8, "p": 20.0}
    result = brdf_rs.eval("phong", a, b, **params)
    assert result.dtype == expected
    native = brdf_rs.eval(
        "phong", a.astype(a.dtype.newbyteorder("=")), b.astype(b.dtype.newbyteorder("=")), **params
    )
    np.testing.assert_array_equal(result, native)
    model = brdf_rs.Model("phong", **params)
    assert model.eval(a, b).dtype == expected
    np.testing.assert_array_equal(model.eval(a, b), native)


def test_big_endian_float32_normals_and_tangents_keep_float32(rng):
    v = rng.normal(size=(8, 3)).astype(">f4")
    t = np.tile(np.array([1, 0, 0], dtype=">f4"), (8, 1))
    n = np.tile(np.array([0, 0, 1], dtype=">f4"), (8, 1))
    out = brdf_rs.eval("ward", v, v[::-1], n, tangent=t, alpha_x=0.2, alpha_y=0.4)
    assert out.dtype == np.float32


def test_out_must_be_native_float32_for_big_endian_float32_input(rng):
    wi = rng.normal(size=(4, 3)).astype(">f4")
    out = np.empty((4, 3), dtype=np.float32)
    assert brdf_rs.eval("lambert", wi, wi, out=out) is out
    with pytest.raises(TypeError, match=r"^out: expected dtype float32 in native byte order"):
        brdf_rs.eval("lambert", wi, wi, out=np.empty((4, 3), dtype=">f4"))


def test_dtype_rules_of_the_other_functions_ignore_byte_order(rng):
    """sample, pdf and albedo compute in float64 whatever the input; tonemap returns
    float32: the same for either byte order."""
    wi = np.array([[0.1, 0.2, 1.0]])
    u = np.array([[0.3, 0.7]])
    for order in ("<", ">"):
        wo, weight, density = brdf_rs.sample("ggx", wi.astype(order + "f4"), u.astype(order + "f4"))
        assert wo.dtype == weight.dtype == density.dtype == np.float64
        assert brdf_rs.pdf("ggx", wi.astype(order + "f4"), wo).dtype == np.float64
        assert (
            brdf_rs.albedo("ggx", np.array([0.5], order + "f4"), samples=64).value.dtype
            == np.float64
        )
        assert brdf_rs.tonemap(np.ones((1, 1, 3), order + "f8")).dtype == np.float32
        assert brdf_rs.tonemap(np.ones((1, 1, 3), order + "f4")).dtype == np.float32


def test_arrays_of_more_than_32_dimensions_are_refused_by_name():
    """NumPy 2 allows 64 dimensions, the core's array views 32: every entry point refuses
    more with a ValueError naming the argument (a view of more panicked)."""
    deep = np.ones((1,) * 63 + (3,))
    w = [0.2, -0.3, 1.0]
    calls = {
        "wi": lambda: brdf_rs.eval("ggx", deep, w),
        "wo": lambda: brdf_rs.Model("ggx").eval(w, deep, check=False),
        "n": lambda: brdf_rs.eval("ggx", w, w, deep.astype(np.float32)),
        "alpha": lambda: brdf_rs.eval("ggx", w, w, alpha=np.full((1,) * 64, 0.3)),
        "out": lambda: brdf_rs.eval("ggx", w, w, out=np.empty((1,) * 63 + (3,))),
        "mu": lambda: brdf_rs.albedo("ggx", np.full((1,) * 64, 0.5), samples=64),
    }
    for name, call in calls.items():
        with pytest.raises(ValueError, match=rf"^{name}: an array of 64 dimensions"):
            call()
    with pytest.raises(ValueError, match=r"^wi: an array of 64 dimensions"):
        brdf_rs.sample("ggx", deep, np.full((1,) * 63 + (2,), 0.5))
    with pytest.raises(ValueError, match=r"^wi: an array of 64 dimensions"):
        brdf_rs.pdf("ggx", deep, w)
    # 32 dimensions still work.
    assert brdf_rs.eval("ggx", np.ones((1,) * 31 + (3,)), w).shape == (1,) * 31 + (3,)


def test_check_and_normalized_must_be_bools_named_in_the_error():
    w, v = [0.0, 0.3, 1.0], [0.2, -0.3, 1.0]
    with pytest.raises(TypeError, match=r"^check: expected True or False, got str"):
        brdf_rs.eval("ggx", w, v, check="no")
    with pytest.raises(TypeError, match=r"^normalized: expected True or False, got float"):
        brdf_rs.eval("ggx", w, v, normalized=1.5)
    with pytest.raises(TypeError, match=r"^check: expected True or False, got str"):
        brdf_rs.Model("ggx").eval(w, v, check="x")
    # NumPy bools are bools.
    assert brdf_rs.eval("ggx", w, v, check=np.bool_(True)).shape == (3,)


def test_ashikhmin_shirley_takes_the_largest_exponents():
    """nu and nv may be any finite value: the normalization takes two square roots, not
    the root of (nu + 1)(nv + 1), which overflowed into NaN from about 1e154 each."""
    w, v = [0.0, 0.3, 1.0], [0.2, -0.3, 1.0]
    for dtype, big in ((np.float64, 1e200), (np.float32, 2e19)):
        got = brdf_rs.eval(
            "ashikhmin_shirley", np.asarray(w, dtype), np.asarray(v, dtype), nu=big, nv=big
        )
        want = brdf_rs.reference.eval("ashikhmin_shirley", w, v, nu=big, nv=big)
        np.testing.assert_allclose(got, want, rtol=1e-6)
    mirror = brdf_rs.eval(
        "ashikhmin_shirley", [0.3, 0.4, 0.5], [-0.3, -0.4, 0.5], nu=1e200, nv=1e200
    )
    assert np.all(np.isfinite(mirror)) and np.all(mirror > 1e197)
    table = brdf_rs.albedo("ashikhmin_shirley", [0.5], nu=1e200, nv=1e200, samples=64)
    assert np.all(np.isfinite(table.value)) and np.all(np.isfinite(table.stderr))
    _, weight, pdf = brdf_rs.sample("ashikhmin_shirley", w, [0.5, 0.5], nu=1e200, nv=1e200)
    assert np.isfinite(pdf) and np.all(np.isfinite(weight))


@pytest.mark.parametrize(
    ("build", "name"),
    [
        ("energy_compensation_table", "ks"),
        ("energy_compensation_table", "kd"),
        ("dfg_table", "ks"),
        ("dfg_table", "kd"),
        ("dfg_table", "alpha"),
        ("dfg_table", "cell_ids"),
    ],
)
def test_tables_refuse_the_arguments_they_set_themselves(build, name):
    """E is the albedo at kd = 0, ks = 1; A and B come from ks = 0 and 1: a caller's kd or
    ks would silently change what the table holds (E = 0.35 for ks = 0.5, E > 1 for
    kd = 1), or reach an internal call twice."""
    value = np.arange(1, dtype=np.uint64) if name == "cell_ids" else 0.5
    with pytest.raises(TypeError, match=rf"^{name}: {build} sets it"):
        getattr(brdf_rs, build)("ggx", [0.5], [0.5], **{name: value})


def test_nan_pixels_are_refused_by_index_not_painted_black(tmp_path):
    image = np.zeros((2, 3, 3), np.float32)
    image[1, 2, 0] = np.nan
    for call in (
        lambda: brdf_rs.tonemap(image, "clamp"),
        lambda: brdf_rs.encode_png(image),
        lambda: brdf_rs.save_image(tmp_path / "x.png", image),
    ):
        with pytest.raises(ValueError, match=r"^image\[1, 2, 0\] = nan"):
            call()
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ValueError, match=r"^image: expected shape \(height, width, 3\) with at"):
        brdf_rs.encode_png(np.zeros((0, 0, 3)))
    # Infinities stay valid (a tone map takes them to 1).
    assert brdf_rs.tonemap(np.full((1, 1, 3), np.inf, np.float32), "clamp").tolist() == [
        [[1.0, 1.0, 1.0]]
    ]


@pytest.mark.parametrize(
    ("option", "value", "pattern"),
    [
        ("fold_azimuth", "False", r"^fold_azimuth: expected True or False, got str"),
        ("fold_azimuth", None, r"^fold_azimuth: expected True or False, got NoneType"),
        ("progress", 3, r"^progress: expected a function"),
    ],
)
def test_albedo_flags_and_callbacks_are_checked_not_coerced(option, value, pattern):
    """``bool("False")`` is True: a string or None must not pick an estimator silently."""
    with pytest.raises(TypeError, match=pattern):
        brdf_rs.albedo("ward", 0.5, **{option: value})


@pytest.mark.parametrize("thresholds", [[-0.2, 0.4], [0.5, 0.99], [0.995, 0.999]])
def test_a_colour_list_may_mix_greys_and_rgb_triples_in_eval_as_in_scenes(thresholds):
    colours = [[0.1, 0.2, 0.3], 0.5, [0.9, 0.8, 0.7]]
    wi, wo = [0.3, 0.1, 0.9], [-0.2, 0.3, 0.8]
    got = brdf_rs.eval("toon_diffuse", wi, wo, thresholds=thresholds, colors=colours)
    want = brdf_rs.reference.eval(
        "toon_diffuse", wi, wo, [0, 0, 1], thresholds=thresholds, colors=colours
    )
    np.testing.assert_allclose(got, want, rtol=1e-15)


def test_shade_names_its_tangent_argument_when_the_model_needs_one():
    lights = [{"type": "directional", "direction": [0, 0, -1]}]
    n = np.array([0.0, 0.0, 1.0])
    with pytest.raises(TypeError, match=r'^shade: missing required parameter "tangent"'):
        brdf_rs.shade({"diffuse": {"model": "kajiya_kay"}}, n, n, lights)


_NAME_FIRST_CALLS = {
    "eval": lambda m, **p: brdf_rs.eval(m, [0, 0, 1], [0, 0.6, 0.8], **p),
    "Model": lambda m, **p: brdf_rs.Model(m, **p),
    "sample": lambda m, **p: brdf_rs.sample(m, [0, 0, 1], [0.3, 0.6], **p),
    "pdf": lambda m, **p: brdf_rs.pdf(m, [0, 0, 1], [0, 0.6, 0.8], **p),
    "albedo": lambda m, **p: brdf_rs.albedo(m, 0.5, samples=64, **p),
    "energy": lambda m, **p: brdf_rs.energy(m, samples=64, **p),
}


@pytest.mark.parametrize("call", list(_NAME_FIRST_CALLS))
@pytest.mark.parametrize("value", ["float32", np.float32, None, [1, "x"]])
def test_an_unknown_name_is_reported_before_its_value_is_read(call, value):
    """A keyword the model does not take (``dtype=`` is the usual one) is an unknown
    parameter, whatever its value; an unknown model is named before any parameter value."""
    run = _NAME_FIRST_CALLS[call]
    with pytest.raises(TypeError, match=r'ggx: unknown parameter "dtype"; ggx takes: kd'):
        run("ggx", alpha=0.3, dtype=value)
    with pytest.raises(TypeError, match=r'unknown parameter "alhpa" \(did you mean "alpha"\?\)'):
        run("ggx", alhpa=value)
    with pytest.raises(ValueError, match=r'unknown model "gxx".*did you mean "ggx"'):
        run("gxx", alpha=value)


def test_a_result_too_large_to_allocate_is_named_with_its_shape_and_size():
    """NumPy's MemoryError names neither the call's result nor what to do; ours does."""
    wi = np.broadcast_to(np.array([0.3, 0.0, 1.0]), (10**6, 1, 3))
    wo = np.broadcast_to(np.array([0.0, 0.6, 0.8]), (1, 10**6, 3))
    for dtype, size in [(np.float64, "21.8 TiB"), (np.float32, "10.9 TiB")]:
        with pytest.raises(
            MemoryError, match=rf"result of shape \(1000000, 1000000, 3\) \({size}\).*out="
        ):
            brdf_rs.eval("ggx", wi.astype(dtype), wo.astype(dtype), alpha=0.3)
    with pytest.raises(MemoryError, match=r"result of shape \(1000000, 1000000, 3\)"):
        brdf_rs.Model("ggx", alpha=0.3).eval(wi, wo)
