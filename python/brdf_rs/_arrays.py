"""Arrays cleaned at the edge: dtype and kind settled here, once, before the Rust core.

The core reads float64 or float32 arrays of any shape and memory layout in place; it
checks shapes, broadcasting and values itself. This module only decides the dtype and
converts what is not already a float array of that dtype (ints, lists, big-endian
floats, mixed widths). Float arrays of the chosen dtype pass through without a copy.
"""

from __future__ import annotations

from typing import Any

import numpy as np

_NUMERIC_KINDS = frozenset("fiu")


def _as_numeric(name: str, value: Any) -> np.ndarray:
    """Returns ``value`` as a NumPy array of real numbers, or raises ``TypeError``."""
    try:
        array = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise TypeError(f"{name}: expected an array of numbers ({exc})") from None
    kind = array.dtype.kind
    if kind in _NUMERIC_KINDS:
        return array
    if kind == "b":
        raise TypeError(f"{name}: expected real numbers, got a boolean array")
    if kind == "c":
        raise TypeError(f"{name}: expected real numbers, got complex values")
    if kind == "O":
        try:
            return np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"{name}: expected an array of numbers ({exc})") from None
    raise TypeError(f"{name}: expected real numbers, got dtype {array.dtype}")


def compute_dtype(arrays: dict[str, np.ndarray]) -> type[np.floating]:
    """Returns float32 if every direction array is float32, else float64."""
    if arrays and all(a.dtype == np.float32 for a in arrays.values()):
        return np.float32
    return np.float64


def directions(**given: Any) -> tuple[type[np.floating], dict[str, np.ndarray | None]]:
    """Converts the direction arguments; returns the compute dtype and the arrays."""
    numeric = {k: _as_numeric(k, v) for k, v in given.items() if v is not None}
    dtype = compute_dtype(numeric)
    out: dict[str, np.ndarray | None] = dict.fromkeys(given)
    for k, a in numeric.items():
        out[k] = np.asarray(a, dtype=dtype)
    return dtype, out


def given(arrays: dict[str, np.ndarray | None], name: str) -> np.ndarray:
    """The array of a direction argument that must be given (``wi``, ``wo``)."""
    a = arrays[name]
    if a is None:
        raise TypeError(f"{name}: expected an array of directions, got None")
    return a


def parameters(params: dict[str, Any], dtype: type[np.floating]) -> dict[str, np.ndarray]:
    """Converts parameter values to arrays of ``dtype`` (values are checked in Rust)."""
    out: dict[str, np.ndarray] = {}
    with np.errstate(over="ignore", invalid="ignore"):
        for k, v in params.items():
            out[k] = np.asarray(_as_numeric(k, v), dtype=dtype)
    return out
