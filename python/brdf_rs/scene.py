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

import dataclasses
import difflib
import hashlib
import json
import logging
import math
import os
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, overload

import numpy as np

from . import _arrays, _atomic, _options, _png, _spec
from . import _brdf_rs as _core
from ._brdf_rs import __version__

if TYPE_CHECKING:  # pragma: no cover - typing only
    from ._albedo import Table

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

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

log = logging.getLogger("brdf_rs")

TONEMAPS = ("clamp", "reinhard", "aces", "none")


class SceneError(ValueError):
    """A bad scene: the message names the file, the key and what was expected."""


# ------------------------------------------------------------------------ validation


class _Where:
    """Where in a scene a value sits, for error messages: ``file: key.path``."""

    def __init__(self, source: str, path: str = "") -> None:
        self.source = source
        self.path = path

    def __truediv__(self, key: str | int) -> _Where:
        if isinstance(key, int):
            return _Where(self.source, f"{self.path}[{key}]")
        return _Where(self.source, f"{self.path}.{key}" if self.path else key)

    def error(self, message: str) -> SceneError:
        where = f"{self.source}: {self.path}" if self.path else self.source
        return SceneError(f"{where}: {message}")

    def expected(self, what: str, got: Any, *, float32: bool = False) -> SceneError:
        """``float32``: the value goes to the renderer, which holds float32 numbers."""
        note = _range_note(got) if float32 else ""
        return self.error(f"expected {what}, got {_arrays.show(got)}{note}")


#: The renderer computes in float32: every number of a scene must be within its range.
FLOAT32_MAX = float(np.finfo(np.float32).max)


def _is_number(x: Any) -> bool:
    """A real number: a Python or NumPy int or float, not a bool."""
    return _arrays.is_real(x)


def _fits(x: Any) -> bool:
    """A number the renderer can hold: finite and within float32's range. Compared
    without a conversion, so a 400-digit integer is simply too large."""
    return _is_number(x) and bool(abs(x) <= FLOAT32_MAX)


def _range_note(got: Any) -> str:
    """Says why a number that looks fine is refused: it is beyond float32's range."""
    values = got if isinstance(got, (list, tuple)) else [got]
    if any(_is_number(x) and not _fits(x) and bool(x == x) and abs(x) != math.inf for x in values):
        return f" (beyond float32's range: the renderer takes |x| <= {FLOAT32_MAX:.4g})"
    return ""


def _plain(value: Any) -> Any:
    """A NumPy array of real numbers reads as (nested) lists of numbers, as in a scene
    file (Python callers pass arrays)."""
    if isinstance(value, np.ndarray) and value.dtype.kind in "iuf":
        return value.tolist()
    return value


def _table(where: _Where, value: Any, allowed: Sequence[str]) -> dict[str, Any]:
    """Checks that ``value`` is a table whose keys are all in ``allowed``."""
    if not isinstance(value, Mapping):
        raise where.expected("a table", value)
    for key in value:
        if key not in allowed:
            close = difflib.get_close_matches(str(key), allowed, n=1, cutoff=0.6)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise (where / str(key)).error(
                f"unknown key{hint}; {where.path or 'a scene'} takes: {', '.join(allowed)}"
            )
    return dict(value)


def _required(where: _Where, table: Mapping[str, Any], key: str, what: str) -> Any:
    if key not in table:
        raise (where / key).error(f"missing ({what})")
    return table[key]


def _number(
    where: _Where, value: Any, *, positive: bool = False, non_negative: bool = False
) -> float:
    what = "a positive number" if positive else "a number >= 0" if non_negative else "a number"
    value = _plain(value)
    if not _fits(value):
        raise where.expected(what, value, float32=True)
    if (positive and not value > 0) or (non_negative and not value >= 0):
        raise where.expected(what, value)
    return float(value)


def _vector(where: _Where, value: Any, *, nonzero: bool = False) -> list[float]:
    what = "a nonzero vector [x, y, z]" if nonzero else "[x, y, z] (three numbers)"
    value = _plain(value)
    if not isinstance(value, (list, tuple)) or len(value) != 3 or not all(map(_fits, value)):
        raise where.expected(what, value, float32=True)
    if nonzero and not any(value):
        raise where.expected(what, value)
    return [float(x) for x in value]


def _parallel(t: Sequence[float], n: Sequence[float]) -> bool:
    """Whether the sine of the angle between ``t`` and ``n`` is at most 64 float32
    epsilons (the renderer's precision), as ``eval`` refuses a tangent for float32."""
    a = np.asarray(t, dtype=np.float64)
    b = np.asarray(n, dtype=np.float64)
    a, b = a / np.max(np.abs(a)), b / np.max(np.abs(b))
    sine = np.linalg.norm(np.cross(a, b)) / (np.linalg.norm(a) * np.linalg.norm(b))
    return bool(sine <= 64 * np.finfo(np.float32).eps)


def _colour(where: _Where, value: Any) -> list[float]:
    what = "a colour: a number >= 0 or an RGB triple [r, g, b] of numbers >= 0"
    given = value = _plain(value)
    if _is_number(value):
        value = [value] * 3
    if (
        not isinstance(value, (list, tuple))
        or len(value) != 3
        or not all(_fits(x) and x >= 0 for x in value)
    ):
        raise where.expected(what, given, float32=True)
    return [float(x) for x in value]


def _choice(where: _Where, value: Any, choices: Sequence[str]) -> str:
    if value not in choices:
        options = " or ".join(repr(c) for c in choices)
        raise where.expected(options, value)
    return str(value)


def _param_value(where: _Where, model: str, spec: Mapping[str, Any], value: Any) -> Any:
    """Checks one parameter of ``model``: its type here, its range by eval's check."""
    kind = spec["kind"]
    rng = spec["range"]

    def in_range(x: float) -> bool:
        return _fits(x) and _spec.admits(model, spec["name"], float(x))

    def scalar(w: _Where, x: Any, what: str) -> float:
        if not _is_number(x) or not in_range(x):
            raise w.expected(what, x, float32=True)
        return float(x)

    value = _plain(value)

    if kind == "scalar":
        return scalar(where, value, f"a number {rng}")
    if kind == "colour":
        if _is_number(value):
            return scalar(where, value, f"a colour (a number or an RGB triple) {rng}")
        if not isinstance(value, (list, tuple)) or len(value) != 3:
            raise where.expected(f"a colour: a number or an RGB triple [r, g, b] {rng}", value)
        return [scalar(where / i, x, f"a number {rng}") for i, x in enumerate(value)]
    if kind == "scalar list":
        if not isinstance(value, (list, tuple)) or not 1 <= len(value) <= spec["max_len"]:
            raise where.expected(f"a list of 1 to {spec['max_len']} numbers {rng}", value)
        return [scalar(where / i, x, f"a number {rng}") for i, x in enumerate(value)]
    # A colour list: colours, each a number (grey) or an RGB triple.
    if not isinstance(value, (list, tuple)) or not 1 <= len(value) <= spec["max_len"]:
        raise where.expected(f"a list of up to {spec['max_len']} colours", value)
    out = []
    for i, c in enumerate(value):
        c = _plain(c)
        if _is_number(c):
            c = [c] * 3
        if not isinstance(c, (list, tuple)) or len(c) != 3:
            raise (where / i).expected(f"a colour: a number or an RGB triple {rng}", c)
        out.append([scalar(where / i, x, f"a number {rng}") for x in c])
    return out


def _term(where: _Where, value: Any, *, family: str, slot: str | None) -> dict[str, Any]:
    """Validates ``{model = ..., params...}``: returns ``{"model", "params"}``."""
    specs = _spec.specs()
    if not isinstance(value, Mapping):
        raise where.expected("a table with model = ... and the model's parameters", value)
    model = _required(where, value, "model", 'a model name, e.g. model = "lambert"')
    if model not in specs:
        close = difflib.get_close_matches(str(model), list(specs), n=1, cutoff=0.6)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise (where / "model").error(
            f"unknown model {_arrays.show(model)}{hint}; known models: {', '.join(specs)}"
        )
    spec = specs[model]
    if spec["family"] != family:
        if family == "A":
            raise (where / "model").error(
                f"{model} is a family-B shading term: give it as diffuse = {{...}} or"
                " specular = {...}, not as a material's model"
            )
        raise (where / "model").error(
            f"{model} is a family-A BRDF: give it as the material's model = ..., not in"
            f" {slot} = {{...}}"
        )
    if slot is not None:
        allowed = _spec.in_slot(slot)
        if model not in allowed:
            raise (where / "model").error(
                f"{model} is not a {slot} term; {slot} takes: {', '.join(allowed)}"
            )
    param_specs = {p["name"]: p for p in spec["params"]}
    table = _table(where, value, ["model", *param_specs])
    params = {}
    for name, p in param_specs.items():
        if name in table:
            params[name] = _param_value(where / name, model, p, table[name])
        elif p["default"] is None:
            raise (where / name).error(f"missing (required by {model}: {p['doc']})")
    arrays = {k: np.asarray(v, dtype=np.float64) for k, v in params.items()}
    try:  # list rules (ascending thresholds, one more colour than thresholds)
        _core.check_params(model, arrays)
    except (TypeError, ValueError) as exc:
        raise where.error(str(exc)) from None
    return {"model": model, "params": params}


_SCENE_KEYS = ("description", "camera", "materials", "objects", "lights", "output")
_CAMERA_KEYS = ("type", "position", "look_at", "up", "fov", "height", "resolution")
_SPHERE_KEYS = ("type", "center", "radius", "material", "tangent", "axis")
_PLANE_KEYS = ("type", "point", "normal", "material", "tangent")
_DIRECTIONAL_KEYS = ("type", "direction", "intensity")
_POINT_KEYS = ("type", "position", "intensity", "range")
_OUTPUT_KEYS = ("tonemap", "exposure", "background")


def _camera(where: _Where, value: Any) -> dict[str, Any]:
    table = _table(where, value, _CAMERA_KEYS)
    projection = _choice(
        where / "type", table.get("type", "perspective"), ("perspective", "orthographic")
    )
    if projection == "perspective" and "height" in table:
        raise (where / "height").error("applies to orthographic cameras; use fov for perspective")
    if projection == "orthographic" and "fov" in table:
        raise (where / "fov").error("applies to perspective cameras; use height for orthographic")
    fov = _plain(table.get("fov", 40.0))
    if not _is_number(fov) or not 0 < fov < 180:
        raise (where / "fov").expected("an angle in degrees, between 0 and 180", fov)
    resolution = _plain(_required(where, table, "resolution", "[width, height] in pixels"))
    if (
        not isinstance(resolution, (list, tuple))
        or len(resolution) != 2
        or not all(
            isinstance(x, (int, np.integer)) and not isinstance(x, (bool, np.bool_))
            for x in resolution
        )
        or not all(1 <= x <= 32768 for x in resolution)
    ):
        raise (where / "resolution").expected(
            "[width, height]: two integers from 1 to 32768", resolution
        )
    camera: dict[str, Any] = {
        "projection": projection,
        "position": _vector(where / "position", _required(where, table, "position", "[x, y, z]")),
        "look_at": _vector(where / "look_at", table.get("look_at", [0, 0, 0])),
        "up": _vector(where / "up", table.get("up", [0, 1, 0]), nonzero=True),
        "fov": float(fov),
        "height": _number(where / "height", table.get("height", 2.0), positive=True),
        "resolution": [int(resolution[0]), int(resolution[1])],
    }
    forward = np.subtract(camera["look_at"], camera["position"])
    if not np.any(forward):
        raise (where / "look_at").error("must differ from camera.position")
    if np.linalg.norm(np.cross(forward, camera["up"])) <= 1e-9 * np.linalg.norm(forward):
        raise (where / "up").error(
            "must not be parallel to the view direction (look_at - position)"
        )
    return camera


def _material(where: _Where, value: Any) -> dict[str, Any]:
    if not isinstance(value, Mapping):
        raise where.expected("a table: model = ... (family A) or diffuse/specular = {...}", value)
    if "model" in value:
        for key in ("diffuse", "specular"):
            if key in value:
                raise (where / key).error(
                    "a material is either one family-A model (model = ...) or family-B"
                    " terms (diffuse = {...}, specular = {...}), not both"
                )
        return {"brdf": _term(where, value, family="A", slot=None)}
    table = _table(where, value, ["model", "diffuse", "specular"])
    if not table:
        raise where.error(
            "empty material: give model = ... (family A) or diffuse = {...} and/or"
            " specular = {...} (family B)"
        )
    return {
        slot: _term(where / slot, table[slot], family="B", slot=slot) if slot in table else None
        for slot in ("diffuse", "specular")
    }


def _object(where: _Where, value: Any, materials: Mapping[str, Any]) -> dict[str, Any]:
    if not isinstance(value, Mapping):
        raise where.expected("a table ([[objects]])", value)
    shape = _choice(
        where / "type", _required(where, value, "type", '"sphere" or "plane"'), ("sphere", "plane")
    )
    table = _table(where, value, _SPHERE_KEYS if shape == "sphere" else _PLANE_KEYS)
    name = _required(where, table, "material", "the name of a [materials.NAME] table")
    if not isinstance(name, str) or name not in materials:
        known = list(materials)
        close = difflib.get_close_matches(str(name), known, n=1, cutoff=0.6)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        defined = ", ".join(known) if known else "none"
        raise (where / "material").error(
            f"unknown material {_arrays.show(name)}{hint}; defined materials: {defined}"
        )
    out: dict[str, Any] = {"shape": shape, "material": name}
    if shape == "sphere":
        out["center"] = _vector(where / "center", _required(where, table, "center", "[x, y, z]"))
        out["radius"] = _number(
            where / "radius", _required(where, table, "radius", "a positive number"), positive=True
        )
        out["tangent"] = _choice(
            where / "tangent", table.get("tangent", "meridian"), ("meridian", "parallel")
        )
        out["axis"] = _vector(where / "axis", table.get("axis", [0, 1, 0]), nonzero=True)
    else:
        out["point"] = _vector(where / "point", _required(where, table, "point", "[x, y, z]"))
        out["normal"] = _vector(
            where / "normal", _required(where, table, "normal", "a nonzero vector"), nonzero=True
        )
        if "tangent" in table:
            out["tangent"] = _vector(where / "tangent", table["tangent"], nonzero=True)
            if _parallel(out["tangent"], out["normal"]):
                raise (where / "tangent").error(
                    f"{_arrays.show(table['tangent'])} is parallel to the plane's normal"
                    f" {_arrays.show(table['normal'])}: it gives no direction in the plane"
                )
        else:
            out["tangent"] = None
    return out


def _light(where: _Where, value: Any) -> dict[str, Any]:
    if not isinstance(value, Mapping):
        raise where.expected("a table ([[lights]])", value)
    kind = _choice(
        where / "type",
        _required(where, value, "type", '"directional" or "point"'),
        ("directional", "point"),
    )
    table = _table(where, value, _DIRECTIONAL_KEYS if kind == "directional" else _POINT_KEYS)
    out: dict[str, Any] = {
        "type": kind,
        "intensity": _colour(where / "intensity", table.get("intensity", 1.0)),
    }
    if kind == "directional":
        out["direction"] = _vector(
            where / "direction",
            _required(where, table, "direction", "the way the light travels, [x, y, z]"),
            nonzero=True,
        )
    else:
        out["position"] = _vector(
            where / "position", _required(where, table, "position", "[x, y, z]")
        )
        out["range"] = (
            _number(where / "range", table["range"], positive=True) if "range" in table else None
        )
    return out


def _output(where: _Where, value: Any) -> dict[str, Any]:
    table = _table(where, value, _OUTPUT_KEYS)
    return {
        "tonemap": _choice(where / "tonemap", table.get("tonemap", "clamp"), TONEMAPS),
        "exposure": _number(where / "exposure", table.get("exposure", 0.0)),
        "background": _colour(where / "background", table.get("background", 0.0)),
    }


def _lights(where: _Where, value: Any) -> list[dict[str, Any]]:
    if not isinstance(value, (list, tuple)):
        raise where.expected("an array of tables ([[lights]])", value)
    return [_light(where / i, v) for i, v in enumerate(value)]


# ----------------------------------------------------------------------------- scenes


@dataclasses.dataclass(frozen=True)
class Scene:
    """A checked scene. Build one with :func:`load_scene` or :func:`parse_scene`.

    ``materials`` maps each name to ``{"brdf": {"model", "params"}}`` (family A) or
    ``{"diffuse": term | None, "specular": term | None}`` (family B); ``objects`` and
    ``lights`` are lists of dicts; ``output`` holds ``tonemap``, ``exposure`` and
    ``background``; ``source`` names the file (for messages).
    """

    camera: dict[str, Any]
    materials: dict[str, dict[str, Any]]
    objects: list[dict[str, Any]]
    lights: list[dict[str, Any]]
    output: dict[str, Any]
    source: str = "<scene>"
    description: str = ""

    @property
    def resolution(self) -> tuple[int, int]:
        """``(width, height)`` in pixels."""
        w, h = self.camera["resolution"]
        return int(w), int(h)

    def with_resolution(self, width: int, height: int) -> Scene:
        """Returns the same scene rendered at another resolution."""
        for name, v in (("width", width), ("height", height)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 1 <= v <= 32768:
                raise ValueError(f"{name}: expected an integer from 1 to 32768, got {v!r}")
        camera = {**self.camera, "resolution": [int(width), int(height)]}
        return dataclasses.replace(self, camera=camera)

    def used_materials(self) -> list[str]:
        """Returns the names of the materials some object uses, in definition order."""
        used = {o["material"] for o in self.objects}
        return [name for name in self.materials if name in used]

    def to_core(self) -> dict[str, Any]:
        """Returns the plain structure the Rust core renders."""
        names = list(self.materials)
        index = {name: i for i, name in enumerate(names)}

        def term(t: dict[str, Any] | None) -> dict[str, Any] | None:
            if t is None:
                return None
            params = {k: np.asarray(v, dtype=np.float64) for k, v in t["params"].items()}
            return {"model": t["model"], "params": params}

        materials = []
        for name in names:
            m = self.materials[name]
            if "brdf" in m:
                materials.append({"brdf": term(m["brdf"])})
            else:
                materials.append({"diffuse": term(m["diffuse"]), "specular": term(m["specular"])})
        objects = [{**o, "material": index[o["material"]]} for o in self.objects]
        return {
            "camera": self.camera,
            "materials": materials,
            "objects": objects,
            "lights": self.lights,
            "background": self.output["background"],
        }


def parse_scene(source: str | Mapping[str, Any], name: str = "<scene>") -> Scene:
    """Checks a scene given as TOML text or as a dict; ``name`` labels error messages."""
    where = _Where(name)
    if isinstance(source, str):
        try:
            data: Any = tomllib.loads(source)
        except tomllib.TOMLDecodeError as exc:
            raise where.error(f"not valid TOML: {exc}") from None
    else:
        data = source
    table = _table(where, data, _SCENE_KEYS)
    if "camera" not in table:
        raise (where / "camera").error(
            "missing: a scene needs a [camera] table (position and resolution at least)"
        )
    camera = _camera(where / "camera", table["camera"])
    raw_materials = table.get("materials", {})
    if not isinstance(raw_materials, Mapping):
        raise (where / "materials").expected("a table of [materials.NAME] tables", raw_materials)
    materials = {
        str(k): _material(where / "materials" / str(k), v) for k, v in raw_materials.items()
    }
    raw_objects = table.get("objects", [])
    if not isinstance(raw_objects, (list, tuple)):
        raise (where / "objects").expected("an array of tables ([[objects]])", raw_objects)
    objects = [_object(where / "objects" / i, v, materials) for i, v in enumerate(raw_objects)]
    lights = _lights(where / "lights", table.get("lights", []))
    output = _output(where / "output", table.get("output", {}))
    description = table.get("description", "")
    if not isinstance(description, str):
        raise (where / "description").expected("a string", description)
    return Scene(camera, materials, objects, lights, output, name, description)


#: Where the example scenes ship: inside the package, so an installed wheel has them.
_EXAMPLES = Path(__file__).resolve().parent / "example_scenes"


def example_scenes() -> dict[str, Path]:
    """The example scenes that ship with the package: ``{name: path of its TOML file}``.

    :func:`load_scene`, :func:`render` and ``brdf-rs render`` take a name (``"gallery"``,
    ``"hdr"``, ``"rtr_fig_7_38"``) in place of a path; the files are a starting point
    for scenes of your own."""
    return {p.stem: p for p in sorted(_EXAMPLES.glob("*.toml"))}


def _scene_path(path: str | os.PathLike[str]) -> Path:
    """``path``, or the example scene of that name when ``path`` is a bare name (no
    folder, no suffix) that is not a file."""
    given = Path(path)
    if given.exists() or given.suffix or len(given.parts) != 1:
        return given
    return example_scenes().get(str(given), given)


def load_scene(path: str | os.PathLike[str]) -> Scene:
    """Reads and checks a scene file (TOML), or an example scene by its name (see
    :func:`example_scenes`)."""
    path = _scene_path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        hint = ""
        if not path.suffix and len(path.parts) == 1:
            names = list(example_scenes())
            close = difflib.get_close_matches(str(path), names, n=1)
            hint = f" (nor an example scene: {', '.join(names)})"
            hint += f"; did you mean {close[0]!r}?" if close else ""
        raise SceneError(f"{path}: cannot read the scene: {exc.strerror or exc}{hint}") from None
    except UnicodeDecodeError:
        raise SceneError(f"{path}: not a text file (a scene is TOML, UTF-8)") from None
    return parse_scene(text, str(path))


#: What :func:`render` accepts as a scene: a checked Scene, a TOML path, or a dict.
SceneLike = Scene | str | os.PathLike[str] | Mapping[str, Any]


def _as_scene(scene: SceneLike) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return parse_scene(scene)
    if isinstance(scene, (str, os.PathLike)):
        return load_scene(scene)
    raise TypeError(f"scene: expected a Scene, a path or a dict, got {type(scene).__name__}")


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
            kernels never run); a family-A model's diffuse term is its ``kd`` term.
        tonemap: ``"clamp"``, ``"reinhard"``, ``"aces"`` or ``"none"``.
        exposure: stops, any finite number (default: the scene's, or 0 with
            ``tonemap="none"``); as in :func:`tonemap`, 0 stays 0 and nothing is NaN.
        stats: also return a dict counting the work done: ``pixels``, ``ray_tests``,
            ``hits``, ``lights`` (and ``lights_dropped``: black ones),
            ``materials_prepared``, pixel-light ``pairs`` with those
            ``pairs_out_of_range`` and ``pairs_backfacing`` (culled unless a term is
            nonzero there) and ``pairs_constant`` (shaded by a constant, no kernel),
            ``evaluations`` of kernels, and ``parts``: per material part its
            ``material``, ``role``, ``model`` and ``evaluations``.
    """
    scene = _as_scene(scene)
    core = scene.to_core()
    image, counts = _core.render_scene(core, _only(only, scene.materials))
    tonemap = scene.output["tonemap"] if tonemap is None else tonemap
    if exposure is None:
        exposure = 0.0 if tonemap == "none" else scene.output["exposure"]
    image = _apply_tonemap(image, tonemap, exposure)
    if stats:
        return image, _named_stats(counts, list(scene.materials))
    return image


def _apply_tonemap(image: np.ndarray, kind: str, exposure: float) -> np.ndarray:
    if not isinstance(kind, str) or kind not in TONEMAPS:
        raise ValueError(f"tonemap: expected one of {', '.join(TONEMAPS)}, got {kind!r}")
    # Any finite float64 number of stops: the scale is applied in float64 and rounded
    # once, so 0 stays 0 and an overflow is ±inf (compared without a conversion, so a
    # 400-digit integer is refused, not an OverflowError).
    if not (_is_number(exposure) and bool(abs(exposure) <= sys.float_info.max)):
        raise ValueError(
            f"exposure: expected a finite number of stops, got {_arrays.show(exposure)}"
        )
    if kind == "none" and exposure == 0:
        return image
    _core.tonemap_inplace(image, kind, float(exposure))
    return image


def tonemap(image: Any, kind: str = "reinhard", exposure: float = 0.0) -> np.ndarray:
    """Returns ``image × 2^exposure`` through a tone map (a new float32 array).

    ``"clamp"``: min(max(x, 0), 1); ``"reinhard"``: x/(1 + x); ``"aces"``: Narkowicz's
    fit of the ACES filmic curve; ``"none"``: exposure only. Any finite ``exposure`` is
    valid: the product is rounded to float32 as computed exactly, so 0 stays 0 however
    large the exposure, a product beyond float32's range is ±inf (1 after a tone map),
    and finite input never gives NaN.
    """
    with np.errstate(over="ignore"):  # beyond float32's range is inf, as in any float32 image
        out = np.array(_arrays.as_numeric("image", image), dtype=np.float32, order="C", copy=True)
    return _apply_tonemap(out, kind, exposure)


def _material_core(where: _Where, material: Mapping[str, Any]) -> dict[str, Any]:
    m = _material(where, material)
    if "brdf" in m:
        t = m["brdf"]
        return {
            "brdf": {
                "model": t["model"],
                "params": {k: np.asarray(v, dtype=np.float64) for k, v in t["params"].items()},
            }
        }
    out: dict[str, Any] = {}
    for slot in ("diffuse", "specular"):
        t = m[slot]
        out[slot] = (
            None
            if t is None
            else {
                "model": t["model"],
                "params": {k: np.asarray(v, dtype=np.float64) for k, v in t["params"].items()},
            }
        )
    return out


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
    angle at most 64 float32 epsilons (the shading precision), as ``eval`` does."""
    sine = np.linalg.norm(np.cross(t.astype(np.float64), n.astype(np.float64)), axis=1)
    bad = sine <= 64 * np.finfo(np.float32).eps
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
        material: as a ``[materials.NAME]`` table: ``{"model": ..., params}`` (family A)
            or ``{"diffuse": {...}, "specular": {...}}`` (family B).
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
    where = _Where("shade")
    core_material = _material_core(where / "material", material)
    core_lights = _lights(where / "lights", lights)
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


# ---------------------------------------------------------------------------- images


def encode_png(image: np.ndarray) -> bytes:
    """The bytes of the PNG file :func:`save_image` writes for ``image`` (display values
    in [0, 1], shape ``(height, width, 3)``): 8-bit sRGB, encoded by pypng (the ``png``
    extra). In a notebook, ``IPython.display.Image(brdf_rs.encode_png(image))`` shows a
    rendered image."""
    return _png.encode(_core.encode_srgb8(_image("image", image)))


def _image(name: str, image: Any) -> np.ndarray:
    with np.errstate(over="ignore"):  # beyond float32's range is inf, as in any float32 image
        a = np.ascontiguousarray(_arrays.as_numeric(name, image), dtype=np.float32)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"{name}: expected shape (height, width, 3), got {a.shape}")
    return a


def save_image(path: str | os.PathLike[str], image: np.ndarray) -> Path:
    """Writes an image by its suffix: ``.png`` (8-bit sRGB of display values in [0, 1],
    needs pypng: the ``png`` extra), ``.exr`` (float32 RGB, needs OpenEXR: the ``exr``
    extra) or ``.npy`` (float32).

    The file is replaced in one step: ``path`` holds either its old content or the whole
    image, never part of it, even when the write fails or is interrupted or several
    processes write the same path at once. An ``OSError`` names ``path``."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: expected a file name (str or path), got {type(path).__name__}")
    path = Path(path)
    image = _image("image", image)
    suffix = path.suffix.lower()
    if suffix == ".png":
        _png.write(path, _core.encode_srgb8(image))
    elif suffix == ".exr":
        try:
            import OpenEXR
        except ImportError:
            raise ImportError("writing .exr needs OpenEXR: pip install brdf-rs[exr]") from None
        header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
        with _atomic.atomic_write(path) as tmp, OpenEXR.File(header, {"RGB": image}) as f:
            f.write(str(tmp))
    elif suffix == ".npy":
        with _atomic.atomic_write(path) as tmp, open(tmp, "wb") as f:
            np.save(f, image)
    else:
        raise ValueError(f"path: unknown image format {suffix!r}; use .png, .exr or .npy")
    return path


# ---------------------------------------------------------------------------- tables


@dataclasses.dataclass(frozen=True)
class TableResult:
    """One material's albedo table: where it is, whether it was built or found in the
    cache, and what it says (the largest albedo over mu, RGB, and whether it exceeds 1
    by more than 3 standard errors)."""

    material: str
    model: str
    path: Path
    cached: bool
    max_albedo: list[float]
    mu_at_max: float
    gains_energy: bool
    seconds: float


def default_cache_dir() -> Path:
    """``$BRDF_RS_CACHE``, else ``$XDG_CACHE_HOME/brdf-rs/tables``, else
    ``~/.cache/brdf-rs/tables``."""
    if os.environ.get("BRDF_RS_CACHE"):
        return Path(os.environ["BRDF_RS_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "brdf-rs" / "tables"


def _canonical_params(model: str, params: Mapping[str, Any]) -> dict[str, Any]:
    """Every parameter, defaults filled in, colours as RGB triples: equal materials hash
    equal however they were spelled."""
    out = {}
    for p in _spec.specs()[model]["params"]:
        value = params.get(p["name"], p["default"])
        if p["kind"] == "colour":
            value = [float(x) for x in np.broadcast_to(np.asarray(value, dtype=float), (3,))]
        elif p["kind"] == "scalar":
            value = float(value)
        else:
            value = np.asarray(value, dtype=float).tolist()
        out[p["name"]] = value
    return out


def _cached_table(path: Path, key: Mapping[str, Any]) -> Table | None:
    """The table cached at ``path`` if it is whole and is the one ``key`` asks for, else
    None (the caller builds it again); a file that fails is logged as a warning."""
    from ._albedo import Table, TableFileError

    try:
        table = Table.load(path)
    except (OSError, TableFileError) as exc:
        log.warning("albedo table cache: %s; building it again", exc)
        return None
    # The name holds a prefix of the key's hash: check the whole key and the grid too.
    want = json.loads(json.dumps(key))
    if (
        table.meta.get("cache_key") != want
        or list(table.axes) != ["mu"]
        or not np.array_equal(table.axes["mu"], np.asarray(key["mu"], dtype=np.float64))
    ):
        log.warning(
            "albedo table cache: %s holds another table than its name says; building it again",
            path,
        )
        return None
    return table


def scene_tables(
    scene: Scene | str | os.PathLike[str] | Mapping[str, Any],
    *,
    cache_dir: str | os.PathLike[str] | None = None,
    mu_count: int = 32,
    samples: int = 4096,
    tol: float | None = None,
    seed: int = 0,
    progress: Callable[[str, int, int], None] | None = None,
) -> list[TableResult]:
    """Builds the albedo tables a scene's materials need for energy checks.

    For every family-A material some object uses, the directional albedo ``R(mu)`` over
    ``mu_count`` cell midpoints of [0, 1] (:func:`brdf_rs.albedo_table`). Each table is
    cached in ``cache_dir`` (default :func:`default_cache_dir`) under a hash of the model,
    its parameters (defaults filled in), the sampler settings and the library version; a
    table already there is read, not rebuilt, once it has been checked: a cached file that
    is damaged, cut short or holds another table is built again (with a warning on the
    ``brdf_rs`` logger), never used. Tables are written atomically, so processes sharing
    a cache never see a half-written one. Family-B shading terms are not BRDFs and
    have no albedo: they are skipped.

    ``progress(material, cells_done, cells)`` is called while a table is built.
    """
    from ._albedo import albedo_table

    scene = _as_scene(scene)
    mu_count = _arrays.integer("mu_count", mu_count, 1, 1 << 20)
    checked = _options.check(samples, "auto", "sobol", seed, tol, None, _options.DEFAULT_REPLICATES)
    samples, seed, tol = checked["samples"], checked["seed"], checked["tol"]
    directory = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    directory.mkdir(parents=True, exist_ok=True)
    mu = (np.arange(mu_count) + 0.5) / mu_count
    results = []
    for name in scene.used_materials():
        material = scene.materials[name]
        if "brdf" not in material:
            continue
        model = material["brdf"]["model"]
        params = _canonical_params(model, material["brdf"]["params"])
        key = {
            "model": model,
            "params": params,
            "mu": mu.tolist(),
            "samples": samples,
            "sampler": "auto",
            "sequence": "sobol",
            "seed": seed,
            "tol": tol,
            "replicates": _options.DEFAULT_REPLICATES,
            "brdf_rs": __version__,
        }
        digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()
        path = directory / f"{model}-{digest[:24]}.npz"
        start = time.perf_counter()
        table = _cached_table(path, key) if path.exists() else None
        cached = table is not None
        if table is None:
            callback = None
            if progress is not None:

                def callback(done: int, _samples: int, _name: str = name) -> None:
                    progress(_name, done, mu_count)

            table = albedo_table(
                model,
                {"mu": mu},
                samples=samples,
                tol=tol,
                seed=seed,
                progress=callback,
                **params,
            )
            table.meta["cache_key"] = key
            table.save(path)
        peak_channel = table.value.max(axis=0)
        k = int(np.argmax(table.value.max(axis=1)))
        gains = bool(np.any(table.value - 3 * table.stderr > 1.0))
        results.append(
            TableResult(
                material=name,
                model=model,
                path=path,
                cached=cached,
                max_albedo=[float(x) for x in peak_channel],
                mu_at_max=float(mu[k]),
                gains_energy=gains,
                seconds=time.perf_counter() - start,
            )
        )
    return results
