"""The scene schema: a scene file (TOML) or dict checked into a :class:`Scene`.

The format is described in ``brdf_rs.scene``. The schema is checked here, once: every
check a user meets is made here, with messages naming the file, the key and what was
expected (:class:`SceneError`). The core's binding is a plain converter of the checked,
plain structure of :meth:`Scene.to_core`; the core's own limits (the largest image side,
the tone maps, the parameter ranges) are read from it rather than restated. The renderer's
types keep the invariants it needs in their constructors, so a caller of the core itself
gets an error (in plainer words), never a panic or an infinite value.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import os
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from . import _arrays, _spec
from . import _brdf_rs as _core
from ._images import TONEMAPS

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = [
    "Scene",
    "SceneError",
    "SceneLike",
    "Where",
    "as_scene",
    "check_lights",
    "check_material",
    "example_scenes",
    "load_scene",
    "material_core",
    "parse_scene",
    "tomllib",
]


class SceneError(ValueError):
    """A bad scene: the message names the file, the key and what was expected."""


class Where:
    """Where in a scene a value sits, for error messages: ``file: key.path``."""

    def __init__(self, source: str, path: str = "") -> None:
        self.source = source
        self.path = path

    def __truediv__(self, key: str | int) -> Where:
        if isinstance(key, int):
            return Where(self.source, f"{self.path}[{key}]")
        return Where(self.source, f"{self.path}.{key}" if self.path else key)

    def error(self, message: str) -> SceneError:
        where = f"{self.source}: {self.path}" if self.path else self.source
        return SceneError(f"{where}: {message}")

    def expected(self, what: str, got: Any, *, float32: bool = False) -> SceneError:
        """``float32``: the value goes to the renderer, which holds float32 numbers."""
        note = _range_note(got) if float32 else ""
        return self.error(f"expected {what}, got {_arrays.show(got)}{note}")


#: The most pixels along either side of an image (the core's limit).
MAX_SIDE = _core.MAX_IMAGE_SIDE

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


def _table(where: Where, value: Any, allowed: Sequence[str]) -> dict[str, Any]:
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


def _required(where: Where, table: Mapping[str, Any], key: str, what: str) -> Any:
    if key not in table:
        raise (where / key).error(f"missing ({what})")
    return table[key]


def _number(
    where: Where, value: Any, *, positive: bool = False, non_negative: bool = False
) -> float:
    what = "a positive number" if positive else "a number >= 0" if non_negative else "a number"
    value = _plain(value)
    if not _fits(value):
        raise where.expected(what, value, float32=True)
    if (positive and not value > 0) or (non_negative and not value >= 0):
        raise where.expected(what, value)
    return float(value)


def _vector(where: Where, value: Any, *, nonzero: bool = False) -> list[float]:
    what = "a nonzero vector [x, y, z]" if nonzero else "[x, y, z] (three numbers)"
    value = _plain(value)
    if not isinstance(value, (list, tuple)) or len(value) != 3 or not all(map(_fits, value)):
        raise where.expected(what, value, float32=True)
    if nonzero and not any(value):
        raise where.expected(what, value)
    return [float(x) for x in value]


#: A tangent is parallel to its normal where the sine of their angle is at most this:
#: the core's count of epsilons, of float32 (the renderer's precision), as ``eval``
#: refuses a tangent for float32.
PARALLEL_SINE = _core.PARALLEL_TANGENT_EPSILONS * float(np.finfo(np.float32).eps)


def _parallel(t: Sequence[float], n: Sequence[float]) -> bool:
    """Whether the sine of the angle between ``t`` and ``n`` is at most
    :data:`PARALLEL_SINE`."""
    a = np.asarray(t, dtype=np.float64)
    b = np.asarray(n, dtype=np.float64)
    a, b = a / np.max(np.abs(a)), b / np.max(np.abs(b))
    sine = np.linalg.norm(np.cross(a, b)) / (np.linalg.norm(a) * np.linalg.norm(b))
    return bool(sine <= PARALLEL_SINE)


def _colour(where: Where, value: Any) -> list[float]:
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


def _choice(where: Where, value: Any, choices: Sequence[str]) -> str:
    if value not in choices:
        options = " or ".join(repr(c) for c in choices)
        raise where.expected(options, value)
    return str(value)


def _param_value(where: Where, model: str, spec: Mapping[str, Any], value: Any) -> Any:
    """Checks one parameter of ``model``: its type here, its range by eval's check."""
    kind = spec["kind"]
    rng = spec["range"]

    def in_range(x: float) -> bool:
        return _fits(x) and _spec.admits(model, spec["name"], float(x))

    def scalar(w: Where, x: Any, what: str) -> float:
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


def _term(where: Where, value: Any, *, family: str, slot: str | None) -> dict[str, Any]:
    """Validates ``{model = ..., params...}``: returns ``{"model", "params"}``."""
    specs = _spec.specs()
    if not isinstance(value, Mapping):
        raise where.expected("a table with model = ... and the model's parameters", value)
    model = _required(where, value, "model", f'a model name, e.g. model = "{next(iter(specs))}"')
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


def _camera(where: Where, value: Any) -> dict[str, Any]:
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
        or not all(1 <= x <= MAX_SIDE for x in resolution)
    ):
        raise (where / "resolution").expected(
            f"[width, height]: two integers from 1 to {MAX_SIDE}", resolution
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


def _sheen_layer(where: Where, value: Any) -> dict[str, Any]:
    """Validates a sheen layer ``{model = ..., weight = ..., ks = ..., alpha = ...}``:
    returns ``{"model", "params", "weight"}``."""
    layers = _spec.sheen_layers()
    if not isinstance(value, Mapping):
        raise where.expected(
            "a table: sheen = {model = ..., weight = ..., and the model's ks and alpha}", value
        )
    model = _required(where, value, "model", f"a sheen model: {', '.join(layers)}")
    if model not in layers:
        close = difflib.get_close_matches(str(model), list(layers), n=1, cutoff=0.6)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise (where / "model").error(
            f"{_arrays.show(model)} is not a sheen model{hint}; a sheen layer takes: "
            + ", ".join(layers)
        )
    if "kd" in value:
        raise (where / "kd").error(
            "a sheen layer has no diffuse term of its own: the base's diffuse term lies"
            " under it (give kd to the material's model)"
        )
    params = [p["name"] for p in _spec.specs()[model]["params"] if p["name"] != "kd"]
    table = _table(where, value, ["model", "weight", *params])
    weight = _plain(table.pop("weight", 1.0))
    if not _is_number(weight) or not 0 <= weight <= 1:
        raise (where / "weight").expected("a number in [0, 1] (the layer's coverage)", weight)
    return {**_term(where, table, family="A", slot=None), "weight": float(weight)}


def check_material(where: Where, value: Any) -> dict[str, Any]:
    """A ``[materials.NAME]`` table checked: ``{"brdf": term, "sheen": layer | None}``
    (family A, with an optional sheen layer) or ``{"diffuse": term | None, "specular":
    term | None}`` (family B)."""
    if not isinstance(value, Mapping):
        raise where.expected("a table: model = ... (family A) or diffuse/specular = {...}", value)
    if "model" in value:
        for key in ("diffuse", "specular"):
            if key in value:
                raise (where / key).error(
                    "a material is either one family-A model (model = ...) or family-B"
                    " terms (diffuse = {...}, specular = {...}), not both"
                )
        base = {k: v for k, v in value.items() if k != "sheen"}
        brdf = _term(where, base, family="A", slot=None)
        sheen = _sheen_layer(where / "sheen", value["sheen"]) if "sheen" in value else None
        return {"brdf": brdf, "sheen": sheen}
    if "sheen" in value:
        raise (where / "sheen").error(
            "a sheen layer goes over a family-A model (model = ...); family-B shading terms"
            " (diffuse = {...}, specular = {...}) take none"
        )
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


def _term_core(t: Mapping[str, Any] | None) -> dict[str, Any] | None:
    if t is None:
        return None
    params = {k: np.asarray(v, dtype=np.float64) for k, v in t["params"].items()}
    return {"model": t["model"], "params": params}


def material_core(m: Mapping[str, Any]) -> dict[str, Any]:
    """A checked material (:func:`check_material`) as the plain structure the core
    renders."""
    if "brdf" in m:
        sheen = m.get("sheen")
        layer = None
        if sheen is not None:
            layer = {**(_term_core(sheen) or {}), "weight": sheen["weight"]}
        return {"brdf": _term_core(m["brdf"]), "sheen": layer}
    return {"diffuse": _term_core(m["diffuse"]), "specular": _term_core(m["specular"])}


def _object(where: Where, value: Any, materials: Mapping[str, Any]) -> dict[str, Any]:
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


def _light(where: Where, value: Any) -> dict[str, Any]:
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


def _output(where: Where, value: Any) -> dict[str, Any]:
    table = _table(where, value, _OUTPUT_KEYS)
    return {
        "tonemap": _choice(where / "tonemap", table.get("tonemap", "clamp"), TONEMAPS),
        "exposure": _number(where / "exposure", table.get("exposure", 0.0)),
        "background": _colour(where / "background", table.get("background", 0.0)),
    }


def check_lights(where: Where, value: Any) -> list[dict[str, Any]]:
    """An array of light tables (``[[lights]]``), each checked."""
    if not isinstance(value, (list, tuple)):
        raise where.expected("an array of tables ([[lights]])", value)
    return [_light(where / i, v) for i, v in enumerate(value)]


# ----------------------------------------------------------------------------- scenes


@dataclasses.dataclass(frozen=True)
class Scene:
    """A checked scene. Build one with :func:`load_scene` or :func:`parse_scene`.

    ``materials`` maps each name to ``{"brdf": {"model", "params"}, "sheen": layer |
    None}`` (family A; a layer is ``{"model", "params", "weight"}``) or ``{"diffuse":
    term | None, "specular": term | None}`` (family B); ``objects`` and
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
            if (
                isinstance(v, bool)
                or not isinstance(v, (int, np.integer))
                or not 1 <= v <= MAX_SIDE
            ):
                raise ValueError(f"{name}: expected an integer from 1 to {MAX_SIDE}, got {v!r}")
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

        materials = [material_core(self.materials[name]) for name in names]
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
    where = Where(name)
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
        str(k): check_material(where / "materials" / str(k), v) for k, v in raw_materials.items()
    }
    raw_objects = table.get("objects", [])
    if not isinstance(raw_objects, (list, tuple)):
        raise (where / "objects").expected("an array of tables ([[objects]])", raw_objects)
    objects = [_object(where / "objects" / i, v, materials) for i, v in enumerate(raw_objects)]
    lights = check_lights(where / "lights", table.get("lights", []))
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
    ``"hdr"``, ``"rtr_fig_7_38"``, ``"sheen"``) in place of a path; the files are a starting point
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


def as_scene(scene: SceneLike) -> Scene:
    """A checked :class:`Scene` from a Scene, a dict, a TOML path or an example's name."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return parse_scene(scene)
    if isinstance(scene, (str, os.PathLike)):
        return load_scene(scene)
    raise TypeError(f"scene: expected a Scene, a path or a dict, got {type(scene).__name__}")
