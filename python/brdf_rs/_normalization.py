"""``normalization="exact"``: lobes normalized so their largest albedo is exactly 1.

``normalized_blinn_phong`` uses RTR's approximate factor ``(p+8)/(8π)``, whose albedo at
normal incidence (where it peaks, for every p > 0) is ``(p+8)(p+2^(−p/2))/((p+2)(p+4))``,
slightly above 1. The exact factor is therefore
``c(p) = (p+2)(p+4) / (8π (p + 2^(−p/2)))``, and the exact lobe is the approximate one
with ``ks`` scaled by ``c(p) / ((p+8)/(8π))`` — a closed form, applied to the parameters
before the kernel runs (elementwise, so spatially varying ``p`` works).
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: Models with an exact normalization, and how their ks is rescaled.
EXACT = ("normalized_blinn_phong",)


def _blinn_ratio(p: np.ndarray) -> np.ndarray:
    exact = (p + 2) * (p + 4) / (8 * np.pi * (p + 2.0 ** (-p / 2)))
    approximate = (p + 8) / (8 * np.pi)
    return np.asarray(exact / approximate, dtype=np.float64)


def apply(model: str, params: dict[str, Any], normalization: str) -> dict[str, Any]:
    """Returns the parameters that evaluate ``model`` with the requested normalization."""
    if normalization == "approximate":
        return params
    if normalization != "exact":
        raise ValueError(f'normalization: expected "approximate" or "exact"; got {normalization!r}')
    if model not in EXACT:
        raise ValueError(
            f"normalization='exact' exists for {', '.join(EXACT)}; {model} has none yet "
            "(torrance_sparrow and ward need a tabulated factor: not implemented)"
        )
    from ._api import models

    defaults = {p["name"]: p["default"] for p in models()[model]["params"]}
    p = np.asarray(params.get("p", defaults["p"]), dtype=np.float64)
    ks = np.asarray(params.get("ks", defaults["ks"]), dtype=np.float64)
    ratio = _blinn_ratio(p)
    # ks is a colour: a trailing axis of 3 (or a scalar) against p's batch shape.
    scaled = ks * (ratio[..., None] if ks.ndim and ratio.ndim else ratio)
    return {**params, "ks": scaled}
