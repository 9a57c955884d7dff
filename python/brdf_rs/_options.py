"""The integrator's options at the edge of the Rust core.

:func:`brdf_rs.albedo`, :func:`brdf_rs.albedo_table`, ``brdf_rs.dask``, scene tables and
the command line take the same options (samples, sampler, sequence, seed, tol, rtol,
max_samples, replicates, cell ids, the azimuth ``phi``). The scalar options are converted
and their errors worded once, in the core (``rust/src/py/options.rs``): :func:`check`
calls that converter for callers that must refuse bad options before any work starts.
The arrays (``cell_ids``, ``phi``) are converted here, before crossing.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _arrays
from . import _brdf_rs as _core

__all__ = [
    "DEFAULT_REPLICATES",
    "SAMPLERS",
    "SEQUENCES",
    "azimuth",
    "cell_ids",
    "check",
]

#: Independent scrambles per cell for ``sequence="sobol"`` (the error bar's basis).
DEFAULT_REPLICATES: int = _core.DEFAULT_REPLICATES
#: The names ``sampler=`` and ``sequence=`` accept.
SAMPLERS: tuple[str, ...] = tuple(_core.SAMPLERS)
SEQUENCES: tuple[str, ...] = tuple(_core.SEQUENCES)


def cell_ids(ids: Any) -> np.ndarray | None:
    """``cell_ids`` as a C-contiguous uint64 array: integers from 0 to 2**64 - 1."""
    if ids is None:
        return None
    expected = f"integers from 0 to {_arrays.U64_MAX}"
    # Python numbers are read one by one: NumPy would turn [5, 2**63] into floats.
    given = ids if isinstance(ids, np.ndarray) else np.asarray(ids, dtype=object)
    try:
        a = np.asarray(given)
    except Exception as exc:  # ragged lists and the like
        raise TypeError(f"cell_ids: expected an array of {expected} ({exc})") from None
    if a.dtype.kind == "O":
        for index in np.ndindex(a.shape):
            x = a[index]
            if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
                raise TypeError(f"cell_ids{list(index)}: expected {expected}, got {x!r}")
            if not 0 <= x <= _arrays.U64_MAX:
                raise ValueError(
                    f"cell_ids{list(index)} = {x} is out of range: expected {expected}"
                )
        return np.ascontiguousarray(a, dtype=np.uint64)
    if a.dtype.kind not in "iu":
        raise TypeError(f"cell_ids: expected {expected}, got dtype {a.dtype}")
    if a.size and a.min() < 0:
        flat = a.ravel()
        i = int(np.flatnonzero(flat < 0)[0])
        index = [int(k) for k in np.unravel_index(i, a.shape)]
        raise ValueError(f"cell_ids{index} = {flat[i]} is out of range: expected {expected}")
    return np.ascontiguousarray(a, dtype=np.uint64)


def check(given: dict[str, Any]) -> dict[str, Any]:
    """The options of :func:`brdf_rs.albedo` (a dict of ``samples``, ``sampler``,
    ``sequence``, ``seed``, ``replicates``, ``tol``, ``rtol``, ``max_samples``,
    ``component``; absent: the default; ``tol``, ``rtol`` and ``max_samples`` may be None),
    converted (integers as ``int``, ``tol`` and ``rtol`` as ``float``; ``tol``, ``rtol``
    and ``max_samples`` None when not given) or refused with an error naming the option.
    The core converts them the same way when it is handed them: this is for callers
    that check before any work starts."""
    return _core.check_albedo_options(given)


def azimuth(phi: Any) -> tuple[np.ndarray | None, bool]:
    """Checks ``phi``: returns ``(array or None, average)``."""
    if isinstance(phi, str):
        if phi == "average":
            return None, True
        raise ValueError(f'phi: expected radians (a number or an array) or "average"; got {phi!r}')
    if phi is None or isinstance(phi, (bool, np.bool_)):
        raise TypeError(f'phi: expected radians (a number or an array) or "average"; got {phi!r}')
    a = np.asarray(_arrays.as_numeric("phi", phi), dtype=np.float64)
    if not np.all(np.isfinite(a)):
        bad = np.flatnonzero(~np.isfinite(a.ravel()))[0]
        raise ValueError(f"phi: must be finite (radians); got {a.ravel()[bad]} at flat index {bad}")
    return a, False  # any layout (the core reads strides); 0-d stays 0-d
