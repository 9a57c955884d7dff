"""Numba kernels of two brdf-rs models: the compiled-Python baseline for the benchmarks.

``torrance_sparrow`` and ``ggx`` written as a Numba user would: one loop over the rows of
``(N, 3)`` float64 ``wi`` and ``wo`` (normalized in the loop, as ``brdf_rs.eval`` does
by default), the normal +z, RGB rows out, the formulas of
``rust/src/models/torrance_sparrow.rs`` and ``rust/src/models/ggx.rs`` (the same
cancellation-free forms of ``1 − cos_b`` and ``μΛ(μ)``, so that regular rows agree with
brdf-rs to about 1e-15). Each model has a serial kernel (``@njit``) and a parallel one
(``@njit(parallel=True)``, ``prange`` over the rows).

Numba is optional (``pip install numba``, or the ``bench`` extra): ``available()`` says
whether it imported, and ``KERNELS`` is empty without it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

try:
    import numba
except ImportError:  # the benchmarks skip their Numba columns
    numba = None

__all__ = ["KERNELS", "available", "check_agreement", "kernel_args", "num_threads", "version"]


def available() -> bool:
    """Whether Numba imported."""
    return numba is not None


def version() -> str | None:
    return None if numba is None else str(numba.__version__)


def num_threads() -> int | None:
    """The threads Numba's parallel kernels use."""
    return None if numba is None else int(numba.get_num_threads())


def _torrance_sparrow_row(a, b, kd, ks, d_scale, p, r0, out):
    """One row of ``f = kd/π + ks·D·F·G/(4 mu_i mu_o)`` (torrance_sparrow.rs), n = +z;
    ``d_scale = (p+2)/(2π)``, ``r0 = ((eta−1)/(eta+1))²``."""
    la = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    lb = math.sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2])
    ix, iy, iz = a[0] / la, a[1] / la, a[2] / la
    ox, oy, oz = b[0] / lb, b[1] / lb, b[2] / lb
    mu_i, mu_o = iz, oz
    if not (mu_i > 0.0 and mu_o > 0.0):
        out[0] = 0.0
        out[1] = 0.0
        out[2] = 0.0
        return
    sx, sy, sz = ix + ox, iy + oy, iz + oz
    length = math.sqrt(sx * sx + sy * sy + sz * sz)
    cos_th = max(0.0, min(sz / length, 1.0))
    cos_b = min(length * 0.5, 1.0)
    # 1 − cos_b = |wi − wo|²/4/(1 + cos_b): no cancellation near the mirror direction
    dx, dy, dz = ix - ox, iy - oy, iz - oz
    one_minus_b = min((dx * dx + dy * dy + dz * dz) * 0.25 / (1.0 + cos_b), 1.0)
    fresnel = r0 + (1.0 - r0) * one_minus_b**5
    g_over = min(1.0 / (4.0 * mu_i * mu_o), cos_th / cos_b * 0.5 / max(mu_i, mu_o))
    spec = cos_th**p * fresnel * g_over
    for c in range(3):
        out[c] = ks[c] * d_scale * spec + kd[c] / math.pi


def _ggx_row(a, b, kd, ks, a2, out):
    """One row of ``f = kd/π + D·G2·F/(4 mu_i mu_o)`` (ggx.rs), height-correlated Smith
    G2, Schlick F with F0 = ``ks``, n = +z; ``a2 = α²``."""
    la = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    lb = math.sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2])
    ix, iy, iz = a[0] / la, a[1] / la, a[2] / la
    ox, oy, oz = b[0] / lb, b[1] / lb, b[2] / lb
    mu_i, mu_o = iz, oz
    if not (mu_i > 0.0 and mu_o > 0.0):
        out[0] = 0.0
        out[1] = 0.0
        out[2] = 0.0
        return
    sx, sy, sz = ix + ox, iy + oy, iz + oz
    length = math.sqrt(sx * sx + sy * sy + sz * sz)
    hx, hy, hz = sx / length, sy / length, sz / length
    # D = α²/(π(sin²θh + α²cos²θh)²), sin²θh = |n × h|²
    denom = (hx * hx + hy * hy) + a2 * hz * hz
    ndf = a2 / (math.pi * denom * denom)
    # μΛ(μ) = s/(2(sqrt(μ² + s) + μ)), s = α²|n × w|²: no cancellation
    s_i = a2 * (ix * ix + iy * iy)
    s_o = a2 * (ox * ox + oy * oy)
    l_i = s_i / (2.0 * (math.sqrt(mu_i * mu_i + s_i) + mu_i))
    l_o = s_o / (2.0 * (math.sqrt(mu_o * mu_o + s_o) + mu_o))
    # G2/(4 mu_i mu_o) = 1/(4(mu_i mu_o + mu_o l_i + mu_i l_o)), the larger cosine out
    m = max(mu_i, mu_o)
    inner = min(mu_i, mu_o) + mu_o / m * l_i + mu_i / m * l_o
    spec = ndf / (4.0 * inner) / m
    cos_b = min(length * 0.5, 1.0)
    dx, dy, dz = ix - ox, iy - oy, iz - oz
    one_minus_b = min((dx * dx + dy * dy + dz * dz) * 0.25 / (1.0 + cos_b), 1.0)
    w = one_minus_b**5
    for c in range(3):
        out[c] = (ks[c] + (1.0 - ks[c]) * w) * spec + kd[c] / math.pi


def _compile() -> dict[str, dict[str, Callable[..., None]]]:
    """The serial and parallel kernels of each model, compiled on first call."""
    if numba is None:
        return {}
    ts_row = numba.njit(inline="always")(_torrance_sparrow_row)
    ggx_row = numba.njit(inline="always")(_ggx_row)

    def ts_prepare(p, eta):
        r = (eta - 1.0) / (eta + 1.0)
        return (p + 2.0) / (2.0 * math.pi), r * r

    ts_prepare = numba.njit(inline="always")(ts_prepare)

    @numba.njit
    def ts_serial(wi, wo, kd, ks, p, eta, out):
        d_scale, r0 = ts_prepare(p, eta)
        for k in range(wi.shape[0]):
            ts_row(wi[k], wo[k], kd, ks, d_scale, p, r0, out[k])

    @numba.njit(parallel=True)
    def ts_parallel(wi, wo, kd, ks, p, eta, out):
        d_scale, r0 = ts_prepare(p, eta)
        for k in numba.prange(wi.shape[0]):
            ts_row(wi[k], wo[k], kd, ks, d_scale, p, r0, out[k])

    @numba.njit
    def ggx_serial(wi, wo, kd, ks, alpha, out):
        for k in range(wi.shape[0]):
            ggx_row(wi[k], wo[k], kd, ks, alpha * alpha, out[k])

    @numba.njit(parallel=True)
    def ggx_parallel(wi, wo, kd, ks, alpha, out):
        for k in numba.prange(wi.shape[0]):
            ggx_row(wi[k], wo[k], kd, ks, alpha * alpha, out[k])

    return {
        "torrance_sparrow": {"serial": ts_serial, "parallel": ts_parallel},
        "ggx": {"serial": ggx_serial, "parallel": ggx_parallel},
    }


#: ``KERNELS[model]["serial" | "parallel"](wi, wo, *kernel_args(model, params), out)``.
KERNELS = _compile()


def _rgb(value: Any) -> np.ndarray:
    return np.ascontiguousarray(np.broadcast_to(np.asarray(value, dtype=np.float64), (3,)))


def kernel_args(model: str, params: dict[str, Any]) -> tuple[Any, ...]:
    """The kernel's parameter arguments for brdf_rs-style ``params`` (defaults filled)."""
    if model == "torrance_sparrow":
        return (
            _rgb(params.get("kd", 0.0)),
            _rgb(params.get("ks", 1.0)),
            float(params["p"]),
            float(params.get("eta", 1.5)),
        )
    if model == "ggx":
        return (
            _rgb(params.get("kd", 0.0)),
            _rgb(params.get("ks", 1.0)),
            float(params.get("alpha", 0.5)),
        )
    raise ValueError(f"no Numba kernel for {model!r}")


def check_agreement(
    model: str, wi: np.ndarray, wo: np.ndarray, params: dict[str, Any], rtol: float = 1e-12
) -> float:
    """Runs both kernels on ``wi``, ``wo`` and compares them with ``brdf_rs.eval``; returns
    the largest relative difference, or raises ``AssertionError`` above ``rtol``."""
    import brdf_rs

    want = brdf_rs.eval(model, wi, wo, **params)
    worst = 0.0
    for kind, kernel in KERNELS[model].items():
        got = np.empty_like(want)
        kernel(wi, wo, *kernel_args(model, params), got)
        scale = np.maximum(np.abs(want), np.finfo(np.float64).tiny)
        rel = float(np.max(np.abs(got - want) / scale))
        if not rel <= rtol:
            raise AssertionError(
                f"Numba {kind} {model} differs from brdf_rs.eval by {rel:.3g} relative"
                f" (allowed {rtol:g})"
            )
        worst = max(worst, rel)
    return worst
