"""Scenes: scan-line shading and rendering with the models as materials.

A scene is a TOML file (or the same structure as a dict)::

    [camera]
    type = "perspective"          # or "orthographic" (then `height`, the view height)
    position = [0, 1, 6]
    look_at = [0, 0, 0]           # default [0, 0, 0]
    up = [0, 1, 0]                # default [0, 1, 0]
    fov = 40                      # vertical field of view, degrees (default 40)
    resolution = [640, 480]       # width, height

    [materials.red_plastic]       # a family-A BRDF: a light adds L·f(l, v)·(n·l)
    model = "normalized_phong"
    kd = [0.95, 0, 0]
    ks = 0.05
    p = 50

    [materials.velvet]            # a family-A BRDF under a sheen layer (optional):
    model = "lambert"             # weight·f_sheen + (1 − weight·E_sheen(n·v))·f_base
    kd = [0.12, 0.01, 0.02]
    sheen = { model = "charlie_sheen", ks = [1, 0.35, 0.4], alpha = 0.2, weight = 1 }

    [materials.toon]              # family-B terms: a light adds L·s(l, v) for each
    diffuse = { model = "toon_diffuse", thresholds = [0.3], colors = [0.1, 0.6] }
    specular = { model = "toon_specular", threshold = 0.95 }

    [[objects]]
    type = "sphere"               # center, radius; tangent = "meridian" | "parallel"
    center = [0, 0, 0]            # about `axis` (default [0, 1, 0]), for kajiya_kay
    radius = 1
    material = "red_plastic"

    [[objects]]
    type = "plane"                # point, normal (two-sided); optional fixed tangent
                                  # (not parallel to the normal)
    point = [0, -1, 0]
    normal = [0, 1, 0]
    material = "toon"

    [[lights]]
    type = "directional"          # direction: the way the light travels
    direction = [-1, -1, -1]
    intensity = [1, 1, 1]         # RGB (or one number), default 1

    [[lights]]
    type = "point"                # inverse-square falloff, optional hard `range`
    position = [2, 3, 2]
    intensity = 20
    range = 10

    [output]
    tonemap = "clamp"             # "clamp" | "reinhard" | "aces" | "none" (linear)
    exposure = 0.0                # stops: radiance × 2^exposure before the tone map
    background = [0, 0, 0]        # radiance where no object is hit

Directions follow the library's conventions (``l = wi`` toward the light, ``v = wo``
toward the camera). One sample per pixel, no shadows, no interreflection.

A dict scene may hold NumPy numbers and 1-D NumPy arrays wherever a number or a list of
numbers goes. The renderer computes in float32, so every number must be within its range
(|x| <= 3.4e38). Errors in a scene raise :class:`SceneError` (a ``ValueError``) naming the
file, the key and what was expected.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Literal, overload

import numpy as np

from . import _arrays, _images, _scene_schema, _spec
from . import _brdf_rs as _core
from ._images import TONEMAPS as TONEMAPS
from ._images import encode_png, save_image, tonemap
from ._scene_cache import TableResult, scene_tables
from ._scene_cache import default_cache_dir as default_cache_dir
from ._scene_schema import (
    PARALLEL_SINE,
    Scene,
    SceneError,
    SceneLike,
    example_scenes,
    load_scene,
    parse_scene,
)
from ._scene_schema import tomllib as tomllib  # tomllib, or tomli on Python 3.10

__all__ = [
    "Scene",
    "SceneError",
    "TableResult",
    "encode_png",
    "example_scenes",
    "load_scene",
    "parse_scene",
    "render",
    "save_image",
    "scene_tables",
    "shade",
    "tonemap",
]

# The public classes keep the module they are documented under (and pickled by).
for _public in (Scene, SceneError, TableResult):
    _public.__module__ = __name__
del _public


def _only(only: str | None, materials: Mapping[str, Mapping[str, Any]] | None = None) -> str:
    if only is None:
        return "both"
    if only not in ("diffuse", "specular"):
        raise ValueError(f"only: expected 'diffuse', 'specular' or None, got {only!r}")
    for name, m in (materials or {}).items():
        brdf = m.get("brdf")
        if brdf is None:
            continue
        if only == "diffuse" and _spec.specs()[brdf["model"]]["diffuse"] == "coupled":
            raise ValueError(
                f"only: material {name!r} uses {brdf['model']}, whose diffuse term depends on"
                " Rs and cannot be rendered alone; render only='specular' or both"
            )
    return only


def _named_stats(stats: dict[str, Any], names: Sequence[str]) -> dict[str, Any]:
    for part in stats["parts"]:
        part["material"] = names[part["material"]]
    return stats


@overload
def render(
    scene: SceneLike,
    *,
    only: str | None = None,
    tonemap: str | None = None,
    exposure: float | None = None,
    stats: Literal[False] = False,
) -> np.ndarray: ...
@overload
def render(
    scene: SceneLike,
    *,
    only: str | None = None,
    tonemap: str | None = None,
    exposure: float | None = None,
    stats: Literal[True],
) -> tuple[np.ndarray, dict[str, Any]]: ...
@overload
def render(
    scene: SceneLike,
    *,
    only: str | None = None,
    tonemap: str | None = None,
    exposure: float | None = None,
    stats: bool = False,
) -> np.ndarray | tuple[np.ndarray, dict[str, Any]]: ...
def render(
    scene: SceneLike,
    *,
    only: str | None = None,
    tonemap: str | None = None,
    exposure: float | None = None,
    stats: bool = False,
) -> np.ndarray | tuple[np.ndarray, dict[str, Any]]:
    """Renders a scene: a float32 array of shape ``(height, width, 3)``, row 0 at the top.

    A pixel is ``Σ_lights L·s(l, v)`` for family-B materials and ``Σ_lights
    L·f(l, v)·(n·l)`` for family-A ones, scaled by ``2^exposure`` and passed through the
    tone map (both from the scene's ``[output]`` unless given here); ``tonemap="none"``
    returns linear radiance (with no exposure unless ``exposure`` is given). The work
    runs in Rust, in parallel, without the GIL.

    Args:
        scene: a :class:`Scene`, a path to a TOML file, the name of an example scene
            (:func:`example_scenes`), or a dict of the same structure.
        only: ``"diffuse"`` or ``"specular"`` renders that component alone (the other's
            kernels never run); a family-A model's diffuse term is its ``kd`` term. A
            sheen layer's lobe counts as specular; the base's terms stay under the layer.
        tonemap: ``"clamp"``, ``"reinhard"``, ``"aces"`` or ``"none"``.
        exposure: stops, any finite number (default: the scene's, or 0 with
            ``tonemap="none"``); as in :func:`tonemap`, 0 stays 0 and nothing is NaN.
        stats: also return a dict counting the work done: ``pixels``, ``ray_tests``,
            ``hits``, ``lights`` (and ``lights_dropped``: black ones),
            ``materials_prepared``, pixel-light ``pairs`` with those
            ``pairs_out_of_range`` and ``pairs_backfacing`` (culled unless a term is
            nonzero there) and ``pairs_constant`` (shaded by a constant, no kernel),
            ``evaluations`` of kernels, and ``parts``: per material part its
            ``material``, ``role`` (``"brdf"``, ``"diffuse"``, ``"specular"`` or
            ``"sheen"``: a sheen layer's lobe), ``model`` and ``evaluations``.
    """
    scene = _scene_schema.as_scene(scene)
    core = scene.to_core()
    image, counts = _core.render_scene(core, _only(only, scene.materials))
    tonemap = scene.output["tonemap"] if tonemap is None else tonemap
    if exposure is None:
        exposure = 0.0 if tonemap == "none" else scene.output["exposure"]
    image = _images.apply_tonemap(image, tonemap, exposure)
    if stats:
        return image, _named_stats(counts, list(scene.materials))
    return image


def _material_core(where: _scene_schema.Where, material: Mapping[str, Any]) -> dict[str, Any]:
    return _scene_schema.material_core(_scene_schema.check_material(where, material))


def _vectors(name: str, value: Any) -> np.ndarray:
    a = np.asarray(_arrays.as_numeric(name, value), dtype=np.float64)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ValueError(f"{name}: expected an array of shape (..., 3), got shape {a.shape}")
    return a


def _unit_rows(name: str, a: np.ndarray) -> np.ndarray:
    """Normalizes rows (float64, scaled first so tiny and huge vectors survive)."""
    flat = a.reshape(-1, 3)
    scale = np.max(np.abs(flat), axis=1, keepdims=True)
    bad = ~np.isfinite(flat).all(axis=1) | (scale[:, 0] == 0)
    if bad.any():
        i = int(np.argmax(bad))
        index = [int(k) for k in np.unravel_index(i, a.shape[:-1])] if a.ndim > 1 else []
        problem = "not finite" if not np.isfinite(flat[i]).all() else "a zero-length vector"
        raise ValueError(f"{name}{index} is {problem}")
    with np.errstate(invalid="ignore", divide="ignore"):
        scaled = flat / scale
        unit = scaled / np.linalg.norm(scaled, axis=1, keepdims=True)
    return np.ascontiguousarray(unit, dtype=np.float32)


def _projects_tangent(material: Mapping[str, Any]) -> bool:
    """Whether a term of the material projects its tangent onto the tangent plane (the
    anisotropic models, which take it optionally; ``kajiya_kay`` uses its fibre as is)."""
    specs = _spec.specs()
    terms = [material.get("brdf"), material.get("diffuse"), material.get("specular")]
    return any(t is not None and specs[t["model"]]["tangent_optional"] for t in terms)


def _check_tangent_rows(t: np.ndarray, n: np.ndarray, shape: tuple[int, ...]) -> None:
    """Refuses unit tangents (nearly) parallel to their unit normals: the sine of their
    angle at most :data:`PARALLEL_SINE` (the shading precision), as ``eval`` does."""
    sine = np.linalg.norm(np.cross(t.astype(np.float64), n.astype(np.float64)), axis=1)
    bad = sine <= PARALLEL_SINE
    if bad.any():
        i = int(np.argmax(bad))
        index = [int(k) for k in np.unravel_index(i, shape)] if shape else []
        raise ValueError(
            f"tangent{index} is parallel to the normal n{index} (first bad index {index}):"
            " it gives no direction in the tangent plane"
        )


@overload
def shade(
    material: Mapping[str, Any],
    n: Any,
    v: Any,
    lights: Sequence[Mapping[str, Any]],
    positions: Any = None,
    *,
    tangent: Any = None,
    only: str | None = None,
    stats: Literal[False] = False,
) -> np.ndarray: ...
@overload
def shade(
    material: Mapping[str, Any],
    n: Any,
    v: Any,
    lights: Sequence[Mapping[str, Any]],
    positions: Any = None,
    *,
    tangent: Any = None,
    only: str | None = None,
    stats: Literal[True],
) -> tuple[np.ndarray, dict[str, Any]]: ...
@overload
def shade(
    material: Mapping[str, Any],
    n: Any,
    v: Any,
    lights: Sequence[Mapping[str, Any]],
    positions: Any = None,
    *,
    tangent: Any = None,
    only: str | None = None,
    stats: bool = False,
) -> np.ndarray | tuple[np.ndarray, dict[str, Any]]: ...
def shade(
    material: Mapping[str, Any],
    n: Any,
    v: Any,
    lights: Sequence[Mapping[str, Any]],
    positions: Any = None,
    *,
    tangent: Any = None,
    only: str | None = None,
    stats: bool = False,
) -> np.ndarray | tuple[np.ndarray, dict[str, Any]]:
    """Shades your own G-buffer with one material: linear radiance, float32 ``(..., 3)``.

    Args:
        material: as a ``[materials.NAME]`` table: ``{"model": ..., params}`` (family A,
            with an optional ``"sheen": {"model": ..., "weight": ..., params}`` layer) or
            ``{"diffuse": {...}, "specular": {...}}`` (family B).
        n: surface normals, shape ``(..., 3)`` (normalized here).
        v: directions toward the viewer; ``n``, ``v``, ``positions`` and ``tangent``
            broadcast together (NumPy rules) and the result has their shape.
        lights: a list of light tables as in a scene file (``type``, ``direction`` or
            ``position``, ``intensity``, ``range``).
        positions: surface points, needed by point lights.
        tangent: unit tangents: required by ``kajiya_kay``; the anisotropic models (``ward``,
            ``ashikhmin_shirley``) take +x projected onto the tangent plane without them.
        only: ``"diffuse"`` or ``"specular"``.
        stats: also return the counts of the work done.
    """
    where = _scene_schema.Where("shade")
    core_material = _material_core(where / "material", material)
    core_lights = _scene_schema.check_lights(where / "lights", lights)
    given = {"n": n, "v": v, "positions": positions, "tangent": tangent}
    arrays = {k: _vectors(k, a) for k, a in given.items() if a is not None}
    try:
        shape = np.broadcast_shapes(*(a.shape[:-1] for a in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in arrays.items())
        raise ValueError(f"n, v, positions, tangent: shapes do not broadcast: {shapes}") from None
    arrays = {k: np.broadcast_to(a, (*shape, 3)) for k, a in arrays.items()}
    args: dict[str, np.ndarray | None] = dict.fromkeys(given)
    for k, a in arrays.items():
        if k == "positions":
            flat = a.reshape(-1, 3)
            if not np.isfinite(flat).all():
                i = int(np.argmax(~np.isfinite(flat).all(axis=1)))
                index = [int(x) for x in np.unravel_index(i, shape)] if shape else []
                raise ValueError(f"positions{index} is not finite")
            args[k] = np.ascontiguousarray(flat, dtype=np.float32)
        else:
            args[k] = _unit_rows(k, a)
    if args["n"] is None or args["v"] is None:
        raise TypeError("n, v: expected arrays of normals and view directions, got None")
    if args["tangent"] is not None and _projects_tangent(core_material):
        _check_tangent_rows(args["tangent"], args["n"], shape)
    out, counts = _core.shade_gbuffer(
        core_material,
        core_lights,
        args["n"],
        args["v"],
        args["positions"],
        args["tangent"],
        _only(only, {"material": core_material}),
    )
    out = out.reshape(*shape, 3)
    if stats:
        return out, _named_stats(counts, ["material"])
    return out
