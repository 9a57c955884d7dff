"""Arrays cleaned at the edge: dtype and kind settled here, once, before the Rust core.

The core reads float64 or float32 arrays of any shape and memory layout in place; it
checks shapes, broadcasting and values itself. This module only decides the dtype and
converts what is not already a float array of that dtype (ints, lists, big-endian
floats, mixed widths). Float arrays of the chosen dtype pass through without a copy.

It also holds the checks every public function shares for arguments that are not arrays
(a model name, an integer option, a name from a list): each error names the
argument. Integers and names are worded once, in the core (``rust/src/py/options.rs``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from . import _brdf_rs as _core

_NUMERIC_KINDS = frozenset("fiu")


def show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


#: The largest finite float64, for messages.
FLOAT64_MAX = float(np.finfo(np.float64).max)


def _first_unconvertible(array: np.ndarray) -> tuple[tuple[int, ...], Any]:
    """The index and value of the first element of an object array that is not a float64."""
    for index in np.ndindex(array.shape):
        if array[index] is None:
            return index, None
        try:
            float(array[index])
        except (TypeError, ValueError, OverflowError):
            return index, array[index]
    return (), array  # pragma: no cover - only called after a conversion failed


#: The most dimensions an array may have: the core's array views take at most 32 (NumPy 2
#: allows 64).
MAX_NDIM = 32


def as_numeric(name: str, value: Any) -> np.ndarray:
    """Returns ``value`` as a NumPy array of real numbers, or raises ``TypeError`` (not
    numbers) or ``ValueError`` (a number beyond float64's range), naming ``name``."""
    try:
        array = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise TypeError(f"{name}: expected an array of numbers ({exc})") from None
    if array.ndim > MAX_NDIM:
        raise ValueError(
            f"{name}: an array of {array.ndim} dimensions; at most {MAX_NDIM} are supported"
        )
    kind = array.dtype.kind
    if kind in _NUMERIC_KINDS:
        return array
    if kind == "b":
        raise TypeError(f"{name}: expected real numbers, got a boolean array")
    if kind == "c":
        raise TypeError(f"{name}: expected real numbers, got complex values")
    if kind == "O":
        try:
            # NumPy converts None to NaN; a missing value is not a number.
            if any(x is None for x in array.flat):
                raise TypeError("None")
            return np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError, OverflowError) as exc:
            index, bad = _first_unconvertible(array)
            where = f"{name}{list(index)}" if index else name
            if isinstance(bad, bool) or isinstance(bad, np.bool_):
                raise TypeError(f"{where}: expected a real number, got {bad!r}") from None
            if isinstance(bad, int) or isinstance(exc, OverflowError):
                raise ValueError(
                    f"{where} = {show(bad)} is out of range: beyond float64's {FLOAT64_MAX:.4g}"
                ) from None
            raise TypeError(
                f"{where}: expected a real number, got {type(bad).__name__} {show(bad)}"
            ) from None
    raise TypeError(f"{name}: expected real numbers, got dtype {array.dtype}")


def first_bad(ok: np.ndarray) -> list[int] | None:
    """The index of the first false entry of ``ok`` (C order), or None if all are true."""
    if ok.all():
        return None
    return [int(i) for i in np.unravel_index(int(np.argmin(ok)), ok.shape)]


def flags(**given: Any) -> None:
    """Raises ``TypeError`` naming the first of ``given`` that is not a bool (or NumPy
    bool)."""
    for name, value in given.items():
        if not isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{name}: expected True or False, got {type(value).__name__}")


def model_name(model: Any, params: Mapping[str, Any] | None = None) -> str:
    """Checks that ``model`` is a model name (a string; the core checks that it exists);
    with ``params``, also that the model exists and takes every one of their names, so an
    unknown name is reported as such before any value is converted."""
    if not isinstance(model, str):
        raise TypeError(
            "model: expected a model name (a string; brdf_rs.models() lists them), got"
            f" {type(model).__name__} {show(model)}"
        )
    if params is not None:
        _core.check_param_names(model, list(params))
    return model


def choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    """Checks a string option: one of ``choices`` (``TypeError`` if not a string)."""
    return _core.choice_option(name, value, list(choices))


def is_real(value: Any) -> bool:
    """Whether ``value`` is one real number: a Python or NumPy int or float (not a bool)."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )


#: The largest value of an unsigned 64-bit integer (seeds, sample counts, cell ids).
U64_MAX = 2**64 - 1


def integer(name: str, value: Any, lo: int, hi: int = U64_MAX, hi_text: str = "") -> int:
    """An integer option from ``lo`` to ``hi`` (an integral float such as 1e6 is accepted);
    ``hi_text`` spells ``hi`` in messages (``"2**40"``)."""
    return _core.integer_option(name, value, lo, hi, hi_text)


def compute_dtype(arrays: dict[str, np.ndarray]) -> type[np.floating]:
    """Returns float32 if every direction array is float32 (in either byte order), else
    float64."""
    if arrays and all(_is_float32(a.dtype) for a in arrays.values()):
        return np.float32
    return np.float64


def _is_float32(dtype: np.dtype) -> bool:
    """Whether ``dtype`` is a 32-bit float, whatever its byte order (``>f4`` too)."""
    return dtype.kind == "f" and dtype.itemsize == 4


def directions(**given: Any) -> tuple[type[np.floating], dict[str, np.ndarray | None]]:
    """Converts the direction arguments; returns the compute dtype and the arrays."""
    arrays = {k: as_numeric(k, v) for k, v in given.items() if v is not None}
    dtype = compute_dtype(arrays)
    out: dict[str, np.ndarray | None] = dict.fromkeys(given)
    for k, a in arrays.items():
        out[k] = np.asarray(a, dtype=dtype)
    return dtype, out


def given(arrays: dict[str, np.ndarray | None], name: str) -> np.ndarray:
    """The array of a direction argument that must be given (``wi``, ``wo``)."""
    a = arrays[name]
    if a is None:
        raise TypeError(f"{name}: expected an array of directions, got None")
    return a


def numeric(params: dict[str, Any]) -> dict[str, np.ndarray]:
    """The parameters as arrays of numbers (not converted further), checked as such."""
    return {k: as_numeric(k, v) for k, v in params.items()}


def parameters(params: dict[str, Any], dtype: type[np.floating]) -> dict[str, np.ndarray]:
    """Converts parameter values to arrays of ``dtype`` (values are checked in Rust)."""
    out: dict[str, np.ndarray] = {}
    with np.errstate(over="ignore", invalid="ignore"):
        for k, v in params.items():
            out[k] = np.asarray(as_numeric(k, v), dtype=dtype)
    return out
