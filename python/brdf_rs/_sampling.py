"""Importance sampling of family-A models: ``sample`` and ``pdf``."""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _arrays
from . import _brdf_rs as _core

__all__ = ["pdf", "sample"]


def sample(
    model: str,
    wi: Any,
    u: Any,
    n: Any = None,
    *,
    tangent: Any = None,
    sampler: str = "auto",
    **params: Any,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Draws one outgoing direction per element from the model's sampler.

    The sampler is a mixture of the model's lobes (cosine-weighted for diffuse terms,
    Phong-lobe sampling about the mirror direction for the Phong family, Blinn NDF
    half-vector sampling for the Blinn family and Torrance-Sparrow), each chosen with
    probability proportional to its weight; ``sampler="cosine"`` or ``"uniform"`` uses
    that warp alone.

    Args:
        wi: directions toward the light, shape ``(..., 3)`` (normalized here).
        u: uniform random numbers in ``[0, 1)``, shape ``(..., 2)``.
        n: normals (default +z).
        tangent: tangents of anisotropic models (projected onto the tangent plane).

    Raises:
        ValueError: naming the argument and its first bad index, for a ``u`` outside
            ``[0, 1)`` (NaN and infinities included), a NaN, infinite or zero-length
            ``wi``, ``n`` or ``tangent`` (and ``wo`` of :func:`pdf`), or a tangent
            parallel to the normal (as :func:`brdf_rs.eval`).
        **params: the model's parameters, broadcasting against the batch.

    Returns:
        ``(wo, weight, pdf)``, float64 whatever the inputs' dtype: unit directions
        ``(..., 3)``, the RGB estimator weight
        ``f(wi, wo)·cos θo / pdf`` (0 for a draw below the surface), and the mixture's
        density of ``wo`` in 1/sr (the same value :func:`pdf` returns).
    """
    _arrays.model_name(model, params)
    _, v = _arrays.directions(wi=wi, n=n, tangent=tangent)
    return _core.sample(
        model,
        np.asarray(_arrays.given(v, "wi"), np.float64),
        _f64("u", u),
        _f64v(v["n"]),
        _f64v(v["tangent"]),
        _arrays.parameters(params, np.float64),
        sampler,
    )


def pdf(
    model: str,
    wi: Any,
    wo: Any,
    n: Any = None,
    *,
    tangent: Any = None,
    sampler: str = "auto",
    **params: Any,
) -> np.ndarray:
    """Returns the density (1/sr) with which :func:`sample` draws ``wo`` given ``wi``."""
    _arrays.model_name(model, params)
    _, v = _arrays.directions(wi=wi, wo=wo, n=n, tangent=tangent)
    return _core.pdf(
        model,
        np.asarray(_arrays.given(v, "wi"), np.float64),
        np.asarray(_arrays.given(v, "wo"), np.float64),
        _f64v(v["n"]),
        _f64v(v["tangent"]),
        _arrays.parameters(params, np.float64),
        sampler,
    )


def _f64v(value: np.ndarray | None) -> np.ndarray | None:
    return None if value is None else np.asarray(value, np.float64)


def _f64(name: str, value: Any) -> np.ndarray:
    return _arrays.parameters({name: value}, np.float64)[name]
