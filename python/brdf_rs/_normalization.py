"""``normalization="exact"``: lobes scaled so their directional albedo peaks at exactly 1.

The exact normalization multiplies ``ks`` by a factor ``c`` of the lobe's shape parameters,
applied to the parameters before the kernel runs (elementwise, so spatially varying
parameters work). The albedo meant is the lobe's alone (``kd = 0``, ``ks = 1``) with its
Fresnel factor at 1 where it has one. Which models have one comes from the model spec
(``brdf_rs.models()[name]["exact"]``), with how the factor is computed (``factor``, one
of the kinds below), the parameters it takes and the colour it scales.

``"blinn_closed_form"`` (``normalized_blinn_phong``)
    RTR's approximate factor ``(p+8)/(8π)`` gives an albedo at normal incidence (where it
    peaks, for every p > 0) of ``(p+8)(p+2^(−p/2))/((p+2)(p+4))``, slightly above 1. The
    exact factor is ``c(p) = (p+2)(p+4) / (8π (p + 2^(−p/2)))``: a closed form, applied as
    ``ks·c(p)/((p+8)/(8π))``.

``"one"`` (``torrance_sparrow``)
    "F = 1" is ``R0 = 1`` (Schlick's F is then 1 for every angle: the limit eta → ∞ or
    eta → 0; ``eta = 1e20`` rounds R0 to exactly 1 in float64), the lobe
    ``D·G/(4 mu_i mu_o)``. Its albedo never exceeds 1, and tends to 1 as ``mu_i → 0``,
    for every p: the V-cavity ``G = min(G1(wi), G1(wo))``,
    ``G1(w) = min(1, 2 cos_th (n·w)/(w·h))``, conserves projected area —
    ``∫ D G1(wi) max(0, wi·h) dω_h = mu_i`` exactly, for any D unchanged by turning the
    azimuth by π (a facet and its mirror image form a V whose aperture projects to
    ``2 cos_th mu_i``) — so ``A(mu_i) ≤ ∫ D G1(wi) max(0, cos_b)/mu_i dω_h = 1``; at
    grazing incidence ``G1(wi) → 0`` is the smaller factor except where wo is grazing too,
    and ``A → 1``. The supremum is 1 (approached, not reached: mu_i = 0 is excluded), so
    ``c(p) = 1`` for every p and the exact lobe is the lobe as written. The library's
    integrator agrees (``scripts/gen_tables.py exact``): over 24 incidences in
    ``[1e-6, 1]`` and p in ``[0, 1e5]`` the largest albedo is ``1 ± 2 stderr``
    (stderr ≤ 9e-7), at ``mu = 1e-6`` for p ≤ 31.6 and at moderate mu for larger p (whose
    albedo is 1 − O(e^−p) there). Normalizing at normal incidence instead would give
    ``c = 1/0.375`` at p = 0: a lobe reflecting 2.67 times its input at grazing.

``"table"`` (``ward``)
    A largest albedo does not exist: as ``mu_i → 0``, ``A(mu_i)·sqrt(mu_i)`` tends to a
    positive limit ``K(αx, αy) = (1/(4π αx αy)) ∫ exp(−E(h)) sqrt(mu_o) dωo`` (wi on the
    horizon), so A grows like ``K/sqrt(mu_i)`` without bound: ``K = 0.0276`` at
    αx = αy = 0.2 (A = 276 at mu_i = 1e-8), ``K = 1.14e-5`` at α = 1e-3 (A passes 1 below
    mu_i ≈ 1.3e-10). The exact normalization is therefore defined at **normal incidence**:
    ``c = 1/A(mu_i = 1)``, which does not depend on the azimuth of wi, and equals
    ``A(1) = (2/(αx αy)) ∫_0^1 exp(−a s²) I0(b s²) sqrt((1−s²)/(1+s²)) s/(1+s²)² ds``,
    ``a = (αx⁻² + αy⁻²)/2``, ``b = |αx⁻² − αy⁻²|/2``. For narrow lobes this is the largest
    albedo away from grazing (for α ≲ 0.05 Ward's albedo is ≈ mu_i for mu_i ≥ 0.1); the
    normalized lobe's albedo (isotropic α) exceeds 1 only below mu_i ≈ 1e-3 at α = 0.2,
    below some mu_i in (0.01, 0.05) at α = 0.5 and in (0.05, 0.1) at α = 1, and for
    α ≥ 2 (A decreasing in mu_i) at every incidence but normal. The factor is tabulated by
    ``scripts/gen_tables.py exact`` with the library's own integrator and interpolated
    (Catmull-Rom in ``log αx``, ``log αy``) as ``r = log c − log s(αx) − log s(αy)``,
    ``s(α) = sqrt(1 + 3α²)``: c ≈ 1 + 1.5(αx² + αy²) for small α, 3 αx αy for large ones,
    so ``|r| < 0.031`` everywhere and r tends to constants in every tail; beyond the table
    ``[1e-2, 1e2]`` the coordinates are clamped (r there is within 7e-6 of its value at the
    edge). c runs from 1 (α → 0; 1.0003 at αx = αy = 1e-2) to 3.0e4 at αx = αy = 1e2 and
    3.0e14 at the largest valid roughness, 1e7.

    Accuracy (``python scripts/gen_tables.py exact-check``): the table's cells have
    standard errors (of r) up to 2.3e-6, median 2.9e-7. At all 2080 cell midpoints the
    interpolated factor's relative error against the 1-D quadrature is at most 9.7e-6
    (median 3.6e-7; the largest near αx = αy = 0.6, where r bends most), against fresh
    integrations (253 midpoints, other seeds) at most 7.8e-6; beyond the table at most
    6.7e-6 (checked for α from 1e-7 to 1e7).
"""

from __future__ import annotations

import functools
import json
from importlib import resources
from typing import Any

import numpy as np

from . import _spec


def _blinn_closed_form(p: np.ndarray) -> np.ndarray:
    # c(p)/((p+8)/(8π)), in factors that neither overflow (p up to 1e308) nor cancel.
    return np.asarray((p + 2) / (p + 8) * ((p + 4) / (p + 2.0 ** (-p / 2))), dtype=np.float64)


def _one(p: np.ndarray) -> np.ndarray:
    return np.ones_like(p, dtype=np.float64)


@functools.cache
def _table(name: str) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """The r table ``name`` padded with one ghost node per side (linear extrapolation),
    log α of the nodes and the table's metadata."""
    source = resources.files("brdf_rs").joinpath("exact_normalization.npz")
    with source.open("rb") as f, np.load(f, allow_pickle=False) as data:
        alpha = np.asarray(data[f"{name}_alpha"], dtype=np.float64)
        r = np.asarray(data[f"{name}_r"], dtype=np.float64)
        meta = json.loads(str(data["meta"]))
    for axis in (0, 1):
        lo = 2 * np.take(r, [0], axis) - np.take(r, [1], axis)
        hi = 2 * np.take(r, [-1], axis) - np.take(r, [-2], axis)
        r = np.concatenate([lo, r, hi], axis=axis)
    return r, np.log(alpha), meta


def _catmull_rom(t: np.ndarray) -> tuple[np.ndarray, ...]:
    """Weights of nodes i−1, i, i+1, i+2 at fraction t of [i, i+1] (Keys' cubic
    convolution with a = −1/2: interpolating, C¹, third-order accurate)."""
    t2 = t * t
    t3 = t2 * t
    return (
        0.5 * (-t3 + 2 * t2 - t),
        0.5 * (3 * t3 - 5 * t2 + 2),
        0.5 * (-3 * t3 + 4 * t2 + t),
        0.5 * (t3 - t2),
    )


def _node(log_alpha: np.ndarray, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Interval index (into the unpadded table) and fraction, clamped to the table."""
    n = nodes.size
    x = np.clip((log_alpha - nodes[0]) / (nodes[1] - nodes[0]), 0.0, n - 1.0)
    i = np.minimum(np.floor(x), n - 2).astype(np.intp)
    return i, x - i


def _tabulated(name: str, ax: np.ndarray, ay: np.ndarray) -> np.ndarray:
    ax, ay = np.broadcast_arrays(ax, ay)
    valid = np.isfinite(ax) & np.isfinite(ay) & (ax > 0) & (ay > 0)
    # Invalid values are left to the kernel's range check (which names the argument).
    ax = np.where(valid, ax, 1.0)
    ay = np.where(valid, ay, 1.0)
    r_table, nodes, _ = _table(name)
    i, tx = _node(np.log(ax), nodes)
    j, ty = _node(np.log(ay), nodes)
    wx, wy = _catmull_rom(tx), _catmull_rom(ty)
    r = np.zeros(ax.shape)
    for a in range(4):
        for b in range(4):
            r = r + wx[a] * wy[b] * r_table[i + a, j + b]
    log_c = r + 0.5 * (np.log1p(3 * ax * ax) + np.log1p(3 * ay * ay))
    return np.asarray(np.where(valid, np.exp(log_c), 1.0), dtype=np.float64)


def _exact(model: str, normalization: str) -> _spec.ExactNormalization | None:
    """The model's exact normalization if asked for (None for "approximate"); an error
    for another value, or for "exact" where the model has none."""
    if normalization not in ("approximate", "exact"):
        raise ValueError(f'normalization: expected "approximate" or "exact"; got {normalization!r}')
    if normalization == "approximate":
        return None
    spec = _spec.specs().get(model)
    exact = None if spec is None else spec["exact"]
    if exact is None:
        known = ", ".join(_spec.with_exact())
        raise ValueError(f"normalization='exact' exists for {known}; {model} has none")
    return exact


def factor(model: str, params: dict[str, Any]) -> np.ndarray:
    """Returns the factor ``c`` the exact normalization multiplies ``ks`` by (relative to
    the model as written), shaped like the broadcast shape parameters."""
    exact = _exact(model, "exact")
    assert exact is not None
    defaults = {p["name"]: p["default"] for p in _spec.specs()[model]["params"]}
    with np.errstate(all="ignore"):
        shape = [np.asarray(params.get(n, defaults[n]), dtype=np.float64) for n in exact["params"]]
        if exact["factor"] == "table":
            assert exact["table"] is not None
            return _tabulated(exact["table"], *shape)
        if exact["factor"] == "blinn_closed_form":
            return _blinn_closed_form(*shape)
        return _one(*shape)


def apply(model: str, params: dict[str, Any], normalization: str) -> dict[str, Any]:
    """Returns the parameters that evaluate ``model`` with the requested normalization."""
    exact = _exact(model, normalization)
    if exact is None:
        return params
    c = factor(model, params)
    if exact["factor"] == "one":
        return params  # c ≡ 1 (see the module docstring)
    scales = exact["scales"]
    defaults = {p["name"]: p["default"] for p in _spec.specs()[model]["params"]}
    colour = np.asarray(params.get(scales, defaults[scales]), dtype=np.float64)
    # The colour has a trailing axis of 3 (or 1) against the shape parameters' batch
    # shape; a scalar becomes one grey value per element.
    if colour.ndim == 0:
        colour = colour[None]
    return {**params, scales: colour * c[..., None]}
