"""The albedo table: its arrays and axes, and its files (``.npz`` read back whole;
``.exr`` and a 16-bit ``.png`` preview, which :class:`TablePreview` reads)."""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _arrays, _atomic, _display, _png

if TYPE_CHECKING:  # pragma: no cover - typing only (xarray is optional)
    import xarray

__all__ = [
    "PNG_AXES_KEY",
    "PNG_META_KEY",
    "PNG_SCALE_KEY",
    "Table",
    "TableFileError",
    "TablePreview",
]


@dataclasses.dataclass
class Table:
    """An albedo table: ``value``/``stderr`` of shape ``axes lengths + (3,)``.

    ``axes`` maps each axis name (``mu`` or a parameter) to its coordinates, in order;
    ``meta`` records how it was made (model, fixed parameters, sampler, sequence, seed,
    samples, library version).

    In Jupyter a table shows itself: a curve (one axis) or a heat map (two axes) with the
    axes labelled, the model and the largest standard error; without matplotlib, a
    summary table of the axes and each channel's range.
    """

    value: np.ndarray
    stderr: np.ndarray
    samples: np.ndarray
    axes: dict[str, np.ndarray]
    meta: dict[str, Any]

    def save(self, path: str | Path) -> Path:
        """Writes ``.npz`` (everything), ``.exr`` (float32 value and stderr, needs the
        ``exr`` extra) or ``.png`` (a 16-bit RGB preview of a 2-D table's value, needs
        pypng: the ``png`` extra).

        The file is replaced in one step: ``path`` holds either its old content or the
        whole table, never part of it, even when the write fails or is interrupted or
        several processes save to the same path at once (the last one wins). Only
        ``.npz`` is read back whole (:meth:`load`).

        The ``.png`` preview: its rows are the first axis (top: the first coordinate),
        its columns the second, its channels the value's three (RGB; a split-sum table's
        A and B). Pixels map ``[min, max]`` linearly onto
        ``0..65535``, ``min`` being 0 unless the table has negative values and ``max`` the
        largest value; the file records the range in a ``tEXt`` chunk with the key
        ``brdf-rs:scale`` (JSON ``{"min": ..., "max": ..., "pixel_max": 65535}``), the axes
        under ``brdf-rs:axes`` (names and coordinates of rows and columns, what the
        channels hold) and ``meta`` under ``brdf-rs:meta``. So ``value = min + (max −
        min) · pixel / 65535`` recovers the table to within half a step of ``(max − min)
        / 65535``: :meth:`TablePreview.load` does this, or any PNG reader that keeps
        16 bits and text chunks.

        Raises:
            ValueError: an unknown suffix, or a table whose arrays, axes and ``meta``
                disagree (the checks :meth:`load` makes: such a file could not be read).
            OSError: ``path`` cannot be written; the message names ``path``.
        """
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix not in (".npz", ".exr", ".png"):
            raise ValueError(f"path: unknown table format {suffix!r}; use .npz, .exr or .png")
        meta = json.loads(_meta_json(self.meta))  # what the file will hold
        names = meta.get("axis_names") if isinstance(meta, dict) else None
        if isinstance(names, list) and names != list(self.axes):
            raise ValueError(
                f"table: meta['axis_names'] is {names} but the axes are {list(self.axes)}"
            )
        problem = _table_problem(
            {
                "value": np.asarray(self.value),
                "stderr": np.asarray(self.stderr),
                "samples": np.asarray(self.samples),
                **{f"axis_{k}": np.asarray(v) for k, v in self.axes.items()},
            },
            meta,
        )
        if problem is not None:
            raise ValueError(f"table: {problem}")
        if suffix == ".npz":
            _save_npz(self, path, meta)
        elif suffix == ".exr":
            _save_exr(self, path, meta)
        else:
            _save_png(self, path, meta)
        return path

    @classmethod
    def load(cls, path: str | Path) -> Table:
        """Reads a table written by :meth:`save` as ``.npz``.

        Nothing in the file is trusted: it must be an ``.npz`` archive (no pickled data
        is ever read) holding ``value`` and ``stderr`` (floats, shape ``axes lengths +
        (3,)``, finite, ``stderr`` ≥ 0), ``samples`` (non-negative integers, shape ``axes
        lengths``), one ``axis_<name>`` per axis (finite real numbers, 1-D, non-empty)
        and ``meta`` (a JSON object with ``model``, a string, and ``axis_names``, a list
        of distinct strings, one per axis, plus the library's other keys with their
        types: strings, numbers, ``fixed`` an object).

        Raises:
            TableFileError: (a ``ValueError``) the file is not a table: not an ``.npz``
                archive (``.exr`` and ``.png`` are previews and cannot be read back),
                damaged or cut short, or with contents missing, of the wrong type or
                inconsistent (an array whose shape does not match the axes). The message
                names the file and what is wrong.
            OSError: the file cannot be opened (missing, a directory, no permission).
        """
        path = Path(path)
        with open(path, "rb") as f:
            head = f.read(4)
            if not head:
                raise TableFileError(f"{path}: not a table: an empty file")
            if head not in (b"PK\x03\x04", b"PK\x05\x06"):
                raise TableFileError(
                    f"{path}: not a table: not an .npz archive (tables are read back from the"
                    " .npz that Table.save writes; .exr and .png are not read back whole:"
                    " TablePreview.load reads a .png preview's values)"
                )
            f.seek(0)
            try:
                with np.load(f, allow_pickle=False) as data:
                    arrays = {name: data[name] for name in data.files}
            except Exception as exc:  # any damage: a bad CRC, a cut-off member, a bad header
                raise TableFileError(
                    f"{path}: damaged or truncated .npz archive ({type(exc).__name__}: {exc})"
                ) from exc
        meta: Any = None
        problem = None
        raw = arrays.get("meta")
        if raw is None:
            problem = "no 'meta' array"
        elif raw.ndim != 0 or raw.dtype.kind != "U":
            problem = f"'meta' must be a JSON string; got a {raw.dtype} array of shape {raw.shape}"
        else:
            try:
                meta = json.loads(str(raw))
            except ValueError as exc:
                problem = f"'meta' is not valid JSON ({exc})"
        if problem is None:
            problem = _table_problem(arrays, meta)
        if problem is not None:
            raise TableFileError(f"{path}: not a valid table: {problem}")
        axes = {name: arrays[f"axis_{name}"] for name in meta["axis_names"]}
        return cls(arrays["value"], arrays["stderr"], arrays["samples"], axes, meta)

    def to_xarray(self) -> xarray.DataArray:
        """Returns ``value`` as an ``xarray.DataArray`` with named coordinates (needs xarray)."""
        import xarray as xr

        coords = {**self.axes, "channel": ["R", "G", "B"]}
        dims = [*self.axes, "channel"]
        return xr.DataArray(self.value, coords=coords, dims=dims, attrs=_flat_meta(self.meta))

    def __repr__(self) -> str:
        axes = ", ".join(f"{k}[{len(v)}]" for k, v in self.axes.items())
        return f"Table({self.meta.get('model')!r}, axes={axes})"

    def _repr_png_(self) -> bytes | None:
        return _display.table_png(self)

    def _repr_html_(self) -> str:
        return _display.table_html(self)


class TableFileError(ValueError):
    """A file that :meth:`Table.load` cannot read as a table: not an ``.npz`` archive,
    damaged or cut short, or with missing, mistyped or inconsistent contents. The
    message names the file and what is wrong with it."""


#: Types of the ``meta`` keys the library writes (other keys are free): the first two
#: are required.
_META_TYPES: dict[str, tuple[str, tuple[type, ...]]] = {
    "model": ("a string", (str,)),
    "axis_names": ("a list of strings", (list,)),
    "quantity": ("a string", (str,)),
    "brdf_rs": ("a string", (str,)),
    "sampler": ("a string", (str,)),
    "sequence": ("a string", (str,)),
    "samples": ("a number", (int, float)),
    "seed": ("a number", (int, float)),
    "replicates": ("a number", (int, float)),
    "tol": ("a number or null", (int, float, type(None))),
    "rtol": ("a number or null", (int, float, type(None))),
    "max_samples": ("a number or null", (int, float, type(None))),
    "component": ("a string", (str,)),
    "fixed": ("an object", (dict,)),
    "cache_key": ("an object", (dict,)),
}


def _table_problem(arrays: Mapping[str, np.ndarray], meta: Any) -> str | None:
    """What is wrong with a table's arrays (``value``, ``stderr``, ``samples``,
    ``axis_<name>``) and ``meta``, or None: the checks of :meth:`Table.load`."""
    if not isinstance(meta, dict):
        return f"'meta' must be a JSON object; got {type(meta).__name__}"
    for key in ("model", "axis_names"):
        if key not in meta:
            return f"meta has no {key!r}"
    for key, (what, types) in _META_TYPES.items():
        v = meta.get(key)
        if key in meta and (isinstance(v, bool) or not isinstance(v, types)):
            return f"meta[{key!r}] must be {what}; got {v!r}"
    names = meta["axis_names"]
    if not names or not all(isinstance(n, str) for n in names) or len(set(names)) != len(names):
        return f"meta['axis_names'] must be a non-empty list of distinct strings; got {names!r}"
    for key in ("value", "stderr", "samples", *(f"axis_{n}" for n in names)):
        if key not in arrays:
            return f"no {key!r} array"
    lengths = []
    for name in names:
        a = arrays[f"axis_{name}"]
        if a.dtype.kind not in "fiu" or a.ndim != 1 or a.size == 0:
            return (
                f"axis_{name}: expected a non-empty 1-D array of real numbers; got a"
                f" {a.dtype} array of shape {a.shape}"
            )
        bad = _arrays.first_bad(np.isfinite(a))
        if bad is not None:
            return f"axis_{name}{bad} is {a[tuple(bad)]}: coordinates must be finite"
        lengths.append(a.size)
    expected = (*lengths, 3)
    axes = " x ".join(f"{n}[{k}]" for n, k in zip(names, lengths, strict=True))
    for key, shape, kinds in (
        ("value", expected, "f"),
        ("stderr", expected, "f"),
        ("samples", expected[:-1], "iu"),
    ):
        a = arrays[key]
        kind = "floats" if kinds == "f" else "integers"
        if a.dtype.kind not in kinds:
            return f"{key}: expected {kind}; got dtype {a.dtype}"
        if a.shape != shape:
            return f"{key}: shape {a.shape} does not match the axes {axes} (expected {shape})"
    for key, ok, what in (
        ("value", np.isfinite(arrays["value"]), "finite"),
        ("stderr", arrays["stderr"] >= 0, "non-negative and finite"),
        ("stderr", np.isfinite(arrays["stderr"]), "non-negative and finite"),
        ("samples", arrays["samples"] >= 0, "non-negative"),
    ):
        bad = _arrays.first_bad(ok)
        if bad is not None:
            return f"{key}{bad} is {arrays[key][tuple(bad)]}: must be {what}"
    return None


def _meta_json(meta: Any) -> str:
    """``meta`` as JSON text, NumPy scalars and arrays as numbers and lists."""

    def default(x: Any) -> Any:
        if isinstance(x, (np.generic, np.ndarray)):
            return x.tolist()
        raise TypeError(f"{type(x).__name__} {x!r} is not a JSON value")

    try:
        return json.dumps(meta, default=default)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"table: meta cannot be written as JSON: {exc}") from None


def _flat_meta(meta: Mapping[str, Any]) -> dict[str, str]:
    return {k: v if isinstance(v, str) else json.dumps(v) for k, v in meta.items()}


def _save_npz(table: Table, path: Path, meta: dict[str, Any]) -> None:
    arrays: dict[str, Any] = {f"axis_{k}": np.asarray(v) for k, v in table.axes.items()}
    _atomic.save_npz(
        path,
        value=table.value,
        stderr=table.stderr,
        samples=table.samples,
        meta=np.array(json.dumps(meta)),
        **arrays,
    )


def _save_exr(table: Table, path: Path, meta: dict[str, Any]) -> None:
    from . import _exr

    value = table.value.astype(np.float32)
    if value.ndim == 2:
        value = value[None]
    if value.ndim != 3:
        raise ValueError(f"table: .exr holds 1-D or 2-D tables; this one has {value.ndim - 1} axes")
    stderr = table.stderr.astype(np.float32).reshape(value.shape)
    attributes = {f"brdf_rs_{k}": v for k, v in _flat_meta(meta).items()}
    _exr.write(path, {"RGB": value, "stderr.RGB": stderr}, attributes)


#: Text keys of a table's .png preview (read back by :meth:`TablePreview.load`).
PNG_SCALE_KEY = "brdf-rs:scale"
PNG_AXES_KEY = "brdf-rs:axes"
PNG_META_KEY = "brdf-rs:meta"
_PNG_MAX = 65535


def _save_png(table: Table, path: Path, meta: dict[str, Any]) -> None:
    value = np.asarray(table.value, dtype=np.float64)
    if value.ndim != 3:
        raise ValueError(
            f"table: the .png preview is for 2-D tables; this one has {value.ndim - 1} axes"
        )
    lo = min(0.0, float(np.min(value)))
    hi = float(np.max(value))
    if not hi > lo:
        hi = lo + 1.0
    pixels = np.round((value - lo) / (hi - lo) * _PNG_MAX).astype(np.uint16)
    (rows, r), (columns, c) = table.axes.items()
    axes = {
        "rows": {"name": rows, "values": np.asarray(r, dtype=np.float64).tolist()},
        "columns": {"name": columns, "values": np.asarray(c, dtype=np.float64).tolist()},
        "channels": _display.channel_names(meta),
    }
    text = {
        "Software": f"brdf-rs {meta.get('brdf_rs', '')}".strip(),
        "Description": (
            f"{meta.get('model')} table preview: rows are {rows} (top: first value), columns"
            f" are {columns}; value = min + (max - min) * pixel / {_PNG_MAX} with min and max"
            f" in the {PNG_SCALE_KEY!r} text chunk"
        ),
        PNG_SCALE_KEY: json.dumps({"min": lo, "max": hi, "pixel_max": _PNG_MAX}),
        PNG_AXES_KEY: json.dumps(axes),
        PNG_META_KEY: json.dumps(meta),
    }
    _png.write(path, pixels, text)


@dataclasses.dataclass(frozen=True)
class TablePreview:
    """A 2-D table read back from the 16-bit ``.png`` preview :meth:`Table.save` writes.

    ``value`` (float64, shape ``(rows, columns, 3)``) is the table's value to within
    ``step / 2`` (the preview's quantization: ``step = (max − min) / 65535``, with ``min``
    and ``max`` the range the file records, ``min`` = 0 unless the table has negative
    values); ``axes`` maps the two axis names to their coordinates (rows first), ``meta``
    is the table's metadata. The preview holds no standard errors: :meth:`Table.load`
    reads everything back from ``.npz``.
    """

    value: np.ndarray
    axes: dict[str, np.ndarray]
    meta: dict[str, Any]
    step: float

    @classmethod
    def load(cls, path: str | Path) -> TablePreview:
        """Reads a ``.png`` written by :meth:`Table.save`.

        Raises:
            TableFileError: (a ``ValueError``) not a PNG, or a PNG without the preview's
                text chunks (``brdf-rs:scale``, ``brdf-rs:axes``, ``brdf-rs:meta``), or
                with chunks that do not match its pixels; the message names the file.
            ImportError: pypng (the ``png`` extra) is not installed.
            OSError: the file cannot be opened.
        """
        path = Path(path)
        data = path.read_bytes()
        try:
            pixels, text = _png.decode(data)
        except ValueError as exc:  # any damage: a bad CRC, a cut-off chunk, bad zlib data
            raise TableFileError(f"{path}: not a table preview: {exc}") from None
        missing = [k for k in (PNG_SCALE_KEY, PNG_AXES_KEY, PNG_META_KEY) if k not in text]
        if missing:
            raise TableFileError(
                f"{path}: not a table preview: no {', '.join(map(repr, missing))} text chunk"
                " (Table.save writes them)"
            )
        try:
            scale = json.loads(text[PNG_SCALE_KEY])
            axes = json.loads(text[PNG_AXES_KEY])
            meta = json.loads(text[PNG_META_KEY])
            lo, hi, top = float(scale["min"]), float(scale["max"]), int(scale["pixel_max"])
            names = [axes["rows"]["name"], axes["columns"]["name"]]
            coords = [np.asarray(axes[k]["values"], dtype=np.float64) for k in ("rows", "columns")]
        except (ValueError, KeyError, TypeError) as exc:
            raise TableFileError(f"{path}: damaged table preview text chunks ({exc})") from None
        shape = (coords[0].size, coords[1].size, 3)
        if pixels.dtype != np.uint16 or pixels.shape != shape or top != _PNG_MAX:
            raise TableFileError(
                f"{path}: the preview's pixels ({pixels.dtype}, shape {pixels.shape}) do not"
                f" match its axes (16-bit RGB, shape {shape})"
            )
        value = lo + (hi - lo) * pixels.astype(np.float64) / _PNG_MAX
        return cls(value, dict(zip(names, coords, strict=True)), meta, (hi - lo) / _PNG_MAX)
