"""Deterministic, high-accuracy directional albedo of the family-A models (test reference).

``directional_albedo(model, mu)`` computes

    R(mu_i) = ∫_hemisphere f(wi, wo)·mu_o dωo,   wi = (sqrt(1 − mu_i²), 0, mu_i),

by a product Gauss-Legendre rule in polar coordinates (a, b) centred on the model's lobe,
with panels placed so that no Gauss-Legendre panel straddles a discontinuity or a kink of
the integrand, and refines until two successive resolutions agree to ``tol``. It is the
converged reference for the Monte Carlo integrator tests and benchmarks.

Method
------
Coordinate frames (``b`` is the azimuth about the frame's axis, measured from the plane
of incidence; the integrand is even in ``b``, so ``b`` runs over [0, π] and the result is
doubled):

- ``normal`` (lambert, oren_nayar): ``wo = (sin a cos b, sin a sin b, cos a)``,
  dωo = sin a da db; the horizon is a = π/2.
- ``mirror`` (the Phong family, lobe ``cos_ar^p`` about r = 2 mu_i n − wi):
  ``wo = cos a·r + sin a·(cos b·u + sin b·y)``, u = (mu_i, 0, sin θi); dωo = sin a da db.
  The horizon is ``a_max(b) = π/2 + atan2(sin θi cos b, mu_i)``; ``cos_ar`` is clipped at
  a = π/2 (a panel boundary, graded geometrically from below when p is not an integer,
  as ``cos^p`` then has an endpoint singularity there).
- ``half`` (the Blinn family, torrance_sparrow; ggx, beckmann, ward when they exist):
  the half vector is ``h = (sin a cos b, sin a sin b, cos a)``, ``wo = 2(wi·h)h − wi``,
  dωo = 4(wi·h)·sin a da db; the horizon is ``a_max(b) = (π/2 + atan2(sin θi cos b,
  mu_i))/2``.

In these coordinates the lobe's peak sits at a = 0 and is isotropic in b, so the inner
integral I(b) = ∫ F(a, b) da is smooth on the scale O(1) in b. Panels in a: 0, the lobe
width w (w = 1/sqrt(p) for cosine powers, α for microfacet widths) times
0.25, 0.5, …, 16 and then doubling, the horizon a_max(b), the clip at π/2 (Phong
family), θi (Oren-Nayar's max/min switch), and the kinks of piecewise-defined factors.
A kink is given as the zero set of a continuous "kink function" (Torrance-Sparrow's
G = min(1, x, y): x − 1, y − 1 and x − y); the roots of each are found per b by a scan
(graded towards both ends of [0, a_max]) and bisection, each function on its own, so two
close kinks of different branches are never lost. Panels in b: 0, π/2, π; the points
where the ordered sequence of kinks along a changes (kink curves crossing each other or
the ends of the range, e.g. Torrance-Sparrow's triple point x = y = 1 at a = π/4,
cos b = mu_i/sin θi), found by a scan of 256 intervals and bisection; and, for the lobe
frames, panels graded geometrically towards b = π/2 down to the scale
ε = asinh(mu_i/sin θi), the distance of the complex singularity of a_max(b) (at grazing
incidence the horizon sweeps from a ≈ mu_i/2 to a ≈ π/2 within |b − π/2| ≈ mu_i).

Each panel carries n Gauss-Legendre nodes in a and in b; n runs through 8, 12, 16, 24,
32, 48, 64, 96 until two successive results agree to ``tol`` (max over RGB, absolute).
The nodes of one resolution are evaluated in one ``brdf_rs.eval`` call. The geometry
that does not depend on the model's parameters (kinks, b-events) is cached per (model,
mu_i, n).

Parameters are passed to ``brdf_rs.eval`` unchanged (scalars or RGB triples), so the
result is RGB directly.

Limits: mu_i in (0, 1] (validated for [0.01, 1]); scalar/RGB parameters only (no
per-cell arrays); isotropic models only; "converged" means two successive resolutions
agree, which is not a proof (a kink curve shorter than the b scan spacing, 0.012 rad,
could be missed and would show up only as slower convergence). The entries for ggx,
beckmann and ward are prepared but untested until those models exist.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import brdf_rs
import numpy as np

__all__ = [
    "AlbedoResult",
    "QuadratureWarning",
    "albedo_grid",
    "directional_albedo",
    "directional_albedo_info",
    "supported_models",
    "ward_albedo_at_normal_incidence",
]

HALF_PI = 0.5 * math.pi
LEVELS = (8, 12, 16, 24, 32, 48, 64, 96)
MAX_CHUNK = 4_000_000  # nodes per brdf_rs.eval call

# Lobe grading, in units of the lobe width w: fine near the peak, then doubling.
_LOBE_STEPS = np.concatenate(
    [
        [0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0],
        16.0 * 2.0 ** np.arange(0, 30),
    ]
)
# Geometric grading towards a singular point, distances from it.
_SINGULAR_STEPS = 0.5 * 0.3 ** np.arange(0, 28)
# Relative scan positions in [0, a_max] for locating kinks.
_SCAN_T = np.unique(
    np.concatenate(
        [
            np.linspace(0.0, 1.0, 129),
            np.geomspace(1e-6, 0.1, 41),
            1.0 - np.geomspace(1e-6, 0.1, 41),
        ]
    )
)
_B_SCAN = 256  # b intervals scanned for changes of the kink sequence


class QuadratureWarning(RuntimeWarning):
    """The quadrature did not reach the requested tolerance."""


@dataclass(frozen=True)
class AlbedoResult:
    """A directional albedo with its convergence record."""

    value: np.ndarray  # RGB, shape (3,)
    diff: float  # max |R_n − R_previous| over RGB at the last refinement
    n: int  # Gauss-Legendre nodes per panel and direction at the last level
    evaluations: int  # BRDF evaluations over all levels
    converged: bool  # diff <= tol


# ---------------------------------------------------------------------------------------
# Model set-ups
# ---------------------------------------------------------------------------------------

# (mu, a, b) -> (k, *a.shape): continuous functions whose sign changes are the kinks.
KinkFn = Callable[[float, np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class _Setup:
    frame: str  # "normal", "mirror" or "half"
    width: Callable[[dict[str, Any]], float] | None = None  # lobe width in a (radians)
    a_breaks: Callable[[float, dict[str, Any]], list[float]] | None = None  # fixed in b
    kinks: KinkFn | None = None  # kink functions of piecewise factors (param-free)
    power_singular: bool = False  # cos^p of a with p non-integer: singular at a = π/2
    horizon_singular: bool = False  # f·mu_o singular at the horizon (Ward, sqrt)
    check: Callable[[dict[str, Any]], None] | None = None


def _scalar(params: dict[str, Any], name: str) -> float:
    value = np.asarray(params[name], dtype=np.float64)
    if value.ndim != 0:
        raise ValueError(f"{name} must be a scalar for the albedo quadrature")
    return float(value)


def _width_power(params: dict[str, Any]) -> float:
    p = _scalar(params, "p")
    return 1.0 if p <= 1.0 else 1.0 / math.sqrt(p)


def _width_alpha(params: dict[str, Any]) -> float:
    return min(1.0, _scalar(params, "alpha"))


def _width_ward(params: dict[str, Any]) -> float:
    return min(1.0, math.sqrt(_scalar(params, "alpha_x") * _scalar(params, "alpha_y")))


def _check_ward(params: dict[str, Any]) -> None:
    if _scalar(params, "alpha_x") != _scalar(params, "alpha_y"):
        raise ValueError("anisotropic ward: the albedo depends on the azimuth of wi")


def _breaks_oren_nayar(mu: float, params: dict[str, Any]) -> list[float]:
    return [math.acos(min(1.0, mu))]  # a = max(θi, θo), b = min(θi, θo) switch at θo = θi


def _breaks_phong(mu: float, params: dict[str, Any]) -> list[float]:
    return [HALF_PI]  # cos_ar = max(0, cos a)


def _half_vector_terms(mu: float, a: np.ndarray, b: np.ndarray):
    s = math.sqrt(max(0.0, 1.0 - mu * mu))
    ca = np.cos(a)
    cos_b = s * np.sin(a) * np.cos(b) + mu * ca  # wi·h
    mu_o = 2.0 * cos_b * ca - mu
    return ca, cos_b, mu_o


def _kinks_torrance_sparrow(mu: float, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """G = min(1, x, y), x = 2 cos_th mu_o/cos_b, y = 2 cos_th mu_i/cos_b (cos_b > 0):
    its kinks lie on the zero sets of x − 1, y − 1 and x − y, given here without the
    positive factor 1/cos_b (x − y ∝ mu_o − mu_i)."""
    ca, cos_b, mu_o = _half_vector_terms(mu, a, b)
    return np.stack([2.0 * ca * mu_o - cos_b, 2.0 * ca * mu - cos_b, mu_o - mu])


_POWER = {"width": _width_power, "power_singular": True}
_SETUPS: dict[str, _Setup] = {
    "lambert": _Setup("normal"),
    "oren_nayar": _Setup("normal", a_breaks=_breaks_oren_nayar),
    "phong": _Setup("mirror", a_breaks=_breaks_phong, **_POWER),
    "modified_phong": _Setup("mirror", a_breaks=_breaks_phong, **_POWER),
    "normalized_phong": _Setup("mirror", a_breaks=_breaks_phong, **_POWER),
    "blinn_phong": _Setup("half", **_POWER),
    "modified_blinn_phong": _Setup("half", **_POWER),
    "normalized_blinn_phong": _Setup("half", **_POWER),
    "blinn_phong_fresnel": _Setup("half", **_POWER),
    "torrance_sparrow": _Setup("half", kinks=_kinks_torrance_sparrow, **_POWER),
    # Prepared for the models still to come (not validated until they exist):
    # smooth Smith G2 / Ward factors, widths alpha; the horizon grading covers the
    # near-horizon singularities (Ward's 1/sqrt(mu_o), Smith's Λ near complex mu_o ~ iα).
    "ggx": _Setup("half", width=_width_alpha, horizon_singular=True),
    "beckmann": _Setup("half", width=_width_alpha, horizon_singular=True),
    # The same lobes with other Fresnel terms (smooth in the half vector).
    "ggx_conductor": _Setup("half", width=_width_alpha, horizon_singular=True),
    "beckmann_conductor": _Setup("half", width=_width_alpha, horizon_singular=True),
    "ggx_f82": _Setup("half", width=_width_alpha, horizon_singular=True),
    "beckmann_f82": _Setup("half", width=_width_alpha, horizon_singular=True),
    "ggx_gen_schlick": _Setup("half", width=_width_alpha, horizon_singular=True),
    "beckmann_gen_schlick": _Setup("half", width=_width_alpha, horizon_singular=True),
    "ward": _Setup("half", width=_width_ward, horizon_singular=True, check=_check_ward),
}


def supported_models() -> list[str]:
    """Family-A models that both brdf_rs and this quadrature know."""
    available = brdf_rs.models()
    return [m for m in _SETUPS if m in available]


def _full_params(model: str, params: dict[str, Any]) -> dict[str, Any]:
    specs = brdf_rs.models()
    if model not in specs or model not in _SETUPS:
        raise ValueError(f"no albedo quadrature for {model!r}; supported: {supported_models()}")
    full = dict(params)
    for spec in specs[model]["params"]:
        if spec["name"] not in full and spec["default"] is not None:
            full[spec["name"]] = spec["default"]
    return full


# ---------------------------------------------------------------------------------------
# Frames
# ---------------------------------------------------------------------------------------


def _sin_theta(mu: float) -> float:
    return math.sqrt(max(0.0, 1.0 - mu * mu))


def _a_max(frame: str, mu: float, b: np.ndarray) -> np.ndarray:
    if frame == "normal":
        return np.full(np.shape(b), HALF_PI)
    delta = np.arctan2(_sin_theta(mu) * np.cos(b), mu)
    return HALF_PI + delta if frame == "mirror" else 0.5 * (HALF_PI + delta)


def _directions(frame: str, mu: float, a: np.ndarray, b: np.ndarray):
    """wo (…, 3), the Jacobian dωo/(da db) and mu_o for coordinates (a, b)."""
    s = _sin_theta(mu)
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    if frame == "normal":
        wo = np.stack([sa * cb, sa * sb, ca], axis=-1)
        jac = sa
    elif frame == "mirror":
        # r = (−s, 0, mu), u = (mu, 0, s), y = (0, 1, 0)
        wo = np.stack([-s * ca + mu * sa * cb, sa * sb, mu * ca + s * sa * cb], axis=-1)
        jac = sa
    else:
        hx, hy = sa * cb, sa * sb
        c = s * hx + mu * ca  # wi·h
        wo = np.stack([2.0 * c * hx - s, 2.0 * c * hy, 2.0 * c * ca - mu], axis=-1)
        jac = 4.0 * c * sa
    return wo, jac, wo[..., 2]


# ---------------------------------------------------------------------------------------
# Kinks (changes of the active branch) along a, and events in b
# ---------------------------------------------------------------------------------------


def _roots(kink_fn: KinkFn, frame: str, mu: float, b: np.ndarray):
    """Roots in (0, a_max(b)) of each kink function, per b (scan, then bisection).

    Returns (row, function index, position) arrays, sorted by row then position. Roots
    within 1e-9·a_max of 0 or a_max are dropped (kink functions may vanish identically
    there, e.g. mu_o − mu_i at h = n; a kink so close to an end does not matter)."""
    amax = _a_max(frame, mu, b)
    a = amax[:, None] * _SCAN_T[None, :]
    vals = kink_fn(mu, a, np.broadcast_to(b[:, None], a.shape)) > 0.0  # (k, Nb, M)
    func, rows, cols = np.nonzero(vals[:, :, 1:] != vals[:, :, :-1])
    lo, hi = a[rows, cols], a[rows, cols + 1]
    sign_lo, bb = vals[func, rows, cols], b[rows]
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        if not np.any((mid > lo) & (mid < hi)):
            break
        v = kink_fn(mu, mid, bb)[func, np.arange(func.size)] > 0.0
        same = v == sign_lo
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    pos = 0.5 * (lo + hi)
    keep = (pos > 1e-9 * amax[rows]) & (pos < (1.0 - 1e-9) * amax[rows])
    rows, func, pos = rows[keep], func[keep], pos[keep]
    order = np.lexsort((pos, rows))
    return rows[order], func[order], pos[order]


def _kinks(kink_fn: KinkFn, frame: str, mu: float, b: np.ndarray) -> np.ndarray:
    """Kink positions in a per b: (len(b), K), NaN-padded."""
    rows, _, pos = _roots(kink_fn, frame, mu, b)
    if rows.size == 0:
        return np.empty((b.size, 0))
    counts = np.bincount(rows, minlength=b.size)
    out = np.full((b.size, counts.max()), np.nan)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    out[rows, np.arange(rows.size) - starts[rows]] = pos
    return out


def _signatures(kink_fn: KinkFn, frame: str, mu: float, b: np.ndarray) -> list[tuple]:
    """Per b, which kink functions vanish along a, in order of a."""
    rows, func, _ = _roots(kink_fn, frame, mu, b)
    bounds = np.searchsorted(rows, np.arange(b.size + 1))
    return [tuple(func[bounds[i] : bounds[i + 1]].tolist()) for i in range(b.size)]


@functools.lru_cache(maxsize=4096)
def _b_events(model: str, mu: float) -> tuple[float, ...]:
    """b where the kink curves cross each other or the ends of [0, a_max] (the sequence of
    kinks along a changes), by scanning b and bisecting."""
    setup = _SETUPS[model]
    if setup.kinks is None:
        return ()
    grid = np.linspace(0.0, math.pi, _B_SCAN + 1)
    sig = _signatures(setup.kinks, setup.frame, mu, grid)
    idx = [i for i in range(_B_SCAN) if sig[i] != sig[i + 1]]
    if not idx:
        return ()
    lo, hi = grid[idx], grid[np.array(idx) + 1]
    sig_lo = [sig[i] for i in idx]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if not np.any((mid > lo) & (mid < hi)):
            break
        sig_mid = _signatures(setup.kinks, setup.frame, mu, mid)
        same = np.array([s == t for s, t in zip(sig_mid, sig_lo, strict=True)])
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    return tuple(float(v) for v in 0.5 * (lo + hi))


@functools.lru_cache(maxsize=64)
def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w  # on [0, 1]


def _b_breaks(model: str, mu: float) -> np.ndarray:
    frame = _SETUPS[model].frame
    pts = [0.0, HALF_PI, math.pi, *_b_events(model, mu)]
    s = _sin_theta(mu)
    if frame != "normal" and s > 0.0:
        eps = math.asinh(mu / s)  # complex singularity of a_max(b) at π/2 ± i·eps
        off = 0.5 * eps * 2.0 ** np.arange(0, 64)
        off = off[off < HALF_PI - 1e-3]
        pts += [*(HALF_PI - off), *(HALF_PI + off)]
    pts = np.unique(np.clip(pts, 0.0, math.pi))
    keep = np.concatenate([[True], np.diff(pts) > 1e-12])
    return pts[keep]


@functools.lru_cache(maxsize=2048)
def _b_structure(model: str, mu: float, n: int):
    """b nodes, b weights (doubled for symmetry), a_max(b), kinks(b) for one level."""
    setup = _SETUPS[model]
    breaks = _b_breaks(model, mu)
    t, w = _gauss_legendre(n)
    lengths = np.diff(breaks)
    b = (breaks[:-1, None] + lengths[:, None] * t[None, :]).ravel()
    bw = (2.0 * lengths[:, None] * w[None, :]).ravel()
    amax = _a_max(setup.frame, mu, b)
    kinks = (
        _kinks(setup.kinks, setup.frame, mu, b)
        if setup.kinks is not None
        else np.empty((b.size, 0))
    )
    for arr in (b, bw, amax, kinks):
        arr.setflags(write=False)
    return b, bw, amax, kinks


# ---------------------------------------------------------------------------------------
# One resolution
# ---------------------------------------------------------------------------------------


def _a_breaks(model: str, mu: float, params: dict[str, Any], amax, kinks) -> np.ndarray:
    setup = _SETUPS[model]
    fixed: list[float] = [0.0]
    if setup.width is not None:
        width = setup.width(params)
        steps = width * _LOBE_STEPS
        fixed += steps[steps < math.pi].tolist()
    if setup.a_breaks is not None:
        fixed += setup.a_breaks(mu, params)
    if setup.power_singular:
        p = _scalar(params, "p")
        if p != round(p) and p < 60.0:  # cos^p ~ (π/2 − a)^p; negligible beyond p ~ 60
            fixed += (HALF_PI - _SINGULAR_STEPS).tolist()
    cols = [np.broadcast_to(np.asarray(fixed)[None, :], (amax.size, len(fixed))), kinks]
    if setup.horizon_singular:
        cols.append(amax[:, None] * (1.0 - _SINGULAR_STEPS[None, :]))
    cols.append(amax[:, None])
    pts = np.concatenate(cols, axis=1)
    pts = np.where(np.isnan(pts), amax[:, None], pts)
    return np.sort(np.clip(pts, 0.0, amax[:, None]), axis=1)


def _integrate(model: str, mu: float, n: int, params: dict[str, Any]) -> tuple[np.ndarray, int]:
    setup = _SETUPS[model]
    b, bw, amax, kinks = _b_structure(model, mu, n)
    pts = _a_breaks(model, mu, params, amax, kinks)
    lo, length = pts[:, :-1], np.diff(pts, axis=1)
    row, col = np.nonzero(length > 0.0)
    lo, length = lo[row, col], length[row, col]
    t, w = _gauss_legendre(n)
    a = (lo[:, None] + length[:, None] * t[None, :]).ravel()
    bb = np.repeat(b[row], n)
    weight = (bw[row, None] * length[:, None] * w[None, :]).ravel()

    wi = np.array([_sin_theta(mu), 0.0, mu])
    total = np.zeros(3)
    for start in range(0, a.size, MAX_CHUNK):
        sl = slice(start, start + MAX_CHUNK)
        wo, jac, mu_o = _directions(setup.frame, mu, a[sl], bb[sl])
        f = brdf_rs.eval(model, wi, wo, check=False, **params)
        total += (weight[sl] * jac * np.maximum(mu_o, 0.0)) @ f
    return total, a.size


# ---------------------------------------------------------------------------------------
# Public API
# ---------------------------------------------------------------------------------------


def _albedo(model: str, mu: float, tol: float, params: dict, stacklevel: int) -> AlbedoResult:
    mu = float(mu)
    if not 0.0 < mu <= 1.0:
        raise ValueError(f"mu must be in (0, 1], got {mu}")
    full = _full_params(model, params)
    setup = _SETUPS[model]
    if setup.check is not None:
        setup.check(full)
    prev, diff, evaluations = None, math.inf, 0
    value, n = np.zeros(3), LEVELS[0]
    for n in LEVELS:
        value, count = _integrate(model, mu, n, full)
        evaluations += count
        if prev is not None:
            diff = float(np.max(np.abs(value - prev)))
            if diff <= tol:
                return AlbedoResult(value, diff, n, evaluations, True)
        prev = value
    warnings.warn(
        f"{model} albedo at mu={mu}: successive resolutions differ by {diff:.3g} > tol={tol:.3g}",
        QuadratureWarning,
        stacklevel=stacklevel,
    )
    return AlbedoResult(value, diff, n, evaluations, False)


def directional_albedo_info(
    model: str, mu: float, *, tol: float = 1e-9, **params: Any
) -> AlbedoResult:
    """Like :func:`directional_albedo`, with the convergence record (``converged`` is
    False, with a :class:`QuadratureWarning`, if ``tol`` was not reached)."""
    return _albedo(model, mu, tol, params, stacklevel=3)


def directional_albedo(model: str, mu: float, *, tol: float = 1e-9, **params: Any) -> np.ndarray:
    """Directional albedo R(mu) = ∫ f(wi, wo)·mu_o dωo of a family-A model, RGB (3,).

    ``wi = (sqrt(1 − mu²), 0, mu)``, n = +z. ``params`` are the model's parameters as
    ``brdf_rs.eval`` takes them (scalars or RGB triples; missing ones take the model's
    defaults). Refines until two successive resolutions agree to ``tol`` (absolute, max
    over RGB); warns with :class:`QuadratureWarning` if that is not reached.
    """
    return _albedo(model, mu, tol, params, stacklevel=3).value


def albedo_grid(
    model: str, mus: Sequence[float] | np.ndarray, *, tol: float = 1e-9, **params: Any
) -> np.ndarray:
    """``directional_albedo`` for each mu: shape (len(mus), 3)."""
    mus = np.asarray(mus, dtype=np.float64).ravel()
    out = np.empty((mus.size, 3))
    for i, mu in enumerate(mus):
        out[i] = _albedo(model, mu, tol, params, stacklevel=3).value
    return out


def ward_albedo_at_normal_incidence(alpha_x: float, alpha_y: float) -> float:
    """A(mu = 1) of ward (kd = 0, ks = 1) by 1-D quadrature (scipy).

    With wi = n, wo = 2(n·h)h − n and s = tan θh, the azimuth integral of the Gaussian is
    2π e^(−a s²) I0(b s²), leaving A = (2/(αx αy)) ∫_0^1 e^(−a s²) I0(b s²)
    sqrt((1−s²)/(1+s²)) s/(1+s²)² ds, a = (αx⁻² + αy⁻²)/2, b = |αx⁻² − αy⁻²|/2.
    Used by tests/test_normalization.py and by ``scripts/gen_tables.py exact-check``.
    """
    import itertools

    from scipy import integrate, special

    b = 0.5 * abs(alpha_x**-2 - alpha_y**-2)
    a_minus_b = 1.0 / max(alpha_x, alpha_y) ** 2

    def integrand(s: float) -> float:
        s2 = s * s
        return float(
            special.i0e(b * s2)
            * np.exp(-a_minus_b * s2)
            * np.sqrt((1 - s2) / (1 + s2))
            * s
            / (1 + s2) ** 2
        )

    marks = [k * m for m in (alpha_x, alpha_y) for k in (0.5, 1, 2, 4, 8) if k * m < 1]
    edges = np.unique([0.0, *marks, 1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        total = sum(
            integrate.quad(integrand, lo, hi, epsabs=0, epsrel=1e-12, limit=200)[0]
            for lo, hi in itertools.pairwise(edges)
        )
    return 2 * total / (alpha_x * alpha_y)


def view_albedo(
    model: str,
    mu_o: Sequence[float] | np.ndarray,
    n_mu: int = 64,
    n_phi: int = 128,
    grade: float = 1.0,
    **params,
) -> np.ndarray:
    """The albedo seen from the view, ``∫ f(wi, wo)·mu_i dωi`` over the light's
    hemisphere at ``wo = (sqrt(1 − mu_o²), 0, mu_o)``, by a product rule: Gauss-Legendre
    in ``mu_i``, midpoints in the azimuth. Equal to the directional albedo for reciprocal
    models; for the others (a lobe fitted in the view's frame) it is the integral a layer
    above a base takes out of the light. For smooth, wide lobes only (no panels);
    ``grade > 1`` takes the Gauss-Legendre nodes in ``u`` with ``mu_i = u**grade``, which
    crowds them toward grazing light (for lobes that lie there)."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    u, wu = 0.5 * (x + 1), 0.5 * w
    mus, wmu = u**grade, wu * grade * u ** (grade - 1)
    phis = (np.arange(n_phi) + 0.5) * 2 * math.pi / n_phi
    m, p = np.meshgrid(mus, phis, indexing="ij")
    s = np.sqrt(1 - m * m)
    wi = np.stack([s * np.cos(p), s * np.sin(p), m], -1).reshape(-1, 3)
    weight = (np.repeat(wmu * mus, n_phi) * 2 * math.pi / n_phi)[:, None]
    out = []
    for mu in np.asarray(mu_o, dtype=np.float64):
        wo = np.array([math.sqrt(1 - mu * mu), 0.0, mu])
        out.append((brdf_rs.eval(model, wi, wo, **params) * weight).sum(axis=0))
    return np.array(out)
