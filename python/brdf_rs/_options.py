"""The integrator's options, checked at the edge before the Rust core.

:func:`brdf_rs.albedo`, :func:`brdf_rs.albedo_table`, ``brdf_rs.dask``, scene tables and
the command line take the same options (samples, sampler, sequence, seed, tol,
max_samples, replicates, cell ids, the azimuth ``phi``): this module converts them and
words their errors, once, for all of them. The core checks the values again (its own
callers are not all Python).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _arrays

__all__ = [
    "DEFAULT_REPLICATES",
    "MAX_REPLICATES",
    "MAX_SAMPLES",
    "SAMPLERS",
    "SEQUENCES",
    "azimuth",
    "cell_ids",
    "check",
]

#: Independent scrambles per cell for ``sequence="sobol"`` (the error bar's basis).
DEFAULT_REPLICATES = 16

#: The integrator's limits (the core checks them again): samples per cell, scrambles.
MAX_SAMPLES = 2**40
MAX_REPLICATES = 4096
SAMPLERS = ("auto", "importance", "cosine", "uniform")
SEQUENCES = ("sobol", "random")


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


def check(
    samples: Any,
    sampler: Any,
    sequence: Any,
    seed: Any,
    tol: Any,
    max_samples: Any,
    replicates: Any,
) -> dict[str, Any]:
    """The options of :func:`brdf_rs.albedo`, converted (integers as ``int``, ``tol`` as
    ``float``) or refused with an error naming the option; ``tol`` and ``max_samples``
    stay None when not given."""
    integer = _arrays.integer
    options: dict[str, Any] = {
        "samples": integer("samples", samples, 1, MAX_SAMPLES, "2**40"),
        "sampler": _arrays.choice("sampler", sampler, SAMPLERS),
        "sequence": _arrays.choice("sequence", sequence, SEQUENCES),
        "seed": integer("seed", seed, 0, _arrays.U64_MAX),
        "tol": None,
        "max_samples": None,
        "replicates": integer("replicates", replicates, 2, MAX_REPLICATES),
    }
    if tol is not None:
        tol = _arrays.real("tol", tol, "a positive number (a standard error)")
        if not tol > 0:
            raise ValueError(f"tol: must be a positive number; got {tol}")
        options["tol"] = tol
    if max_samples is not None:
        options["max_samples"] = integer("max_samples", max_samples, 1, MAX_SAMPLES, "2**40")
    return options


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
