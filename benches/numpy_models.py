"""Plain vectorized NumPy versions of the brdf-rs models: the baseline for the benchmark.

Each function is what a competent NumPy user would write in an afternoon from
``docs/models.md``: dot products with ``np.einsum``, ``np.power``, ``np.where``, ``np.maximum``,
``np.arccos``/``np.tan`` for Oren-Nayar as the formula reads, RGB broadcast with
``[:, None]``. No numexpr, numba, in-place buffer reuse or other micro-optimization, and
no Python loops over rows.

Conventions:

- ``wi``, ``wo`` are ``(N, 3)`` arrays of *unit* vectors (no normalization is done);
  ``n`` (and ``tangent`` for ``kajiya_kay``) is ``(N, 3)`` or a ``(3,)`` vector that
  broadcasts. The dtype of ``wi`` (float32 or float64) is the compute dtype: float32 is
  not upcast.
- Parameters are Python scalars; colours (``kd``, ``ks``, ``high``, ``low``, the entries
  of ``colors``) are a float (grey) or an RGB triple. Names and defaults match
  ``brdf_rs.reference``.
- Every function returns an ``(N, 3)`` RGB array. Family A returns 0 unless
  ``mu_i > 0`` and ``mu_o > 0``; family-B specular terms return 0 when ``n·l <= 0``.
  ``np.power`` already gives ``0**0 = 1``.
- NumPy warnings are suppressed. This baseline does not guard every degenerate case the
  Rust core handles (e.g. underflow in ``cos^p / mu_i`` at grazing angles), so degenerate
  geometry may give NaN or inf; regular rows agree with the reference to rounding.
"""

from collections.abc import Callable

import numpy as np

__all__ = ["MODELS", "evaluate"]


# ---------------------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------------------


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot product; either argument may be a single (3,) vector."""
    return np.einsum("...j,...j->...", a, b)


def _arrays(wi, wo, n, *extra):
    """Returns the inputs as arrays of one float dtype (that of ``wi``)."""
    wi = np.asarray(wi)
    dtype = wi.dtype if wi.dtype in (np.float32, np.float64) else np.float64
    return tuple(np.asarray(v, dtype=dtype) for v in (wi, wo, n, *extra))


def _rgb(colour, dtype) -> np.ndarray:
    """Returns a colour as a (3,) array: a number means grey."""
    return np.broadcast_to(np.asarray(colour, dtype=dtype), (3,))


def _mirror_cos(wi, wo, n, mu_i):
    """Returns ``r·wo`` with ``r = 2 mu_i n - wi``."""
    r = 2.0 * mu_i[:, None] * n - wi
    return _dot(r, wo)


def _half(wi, wo, n):
    """Returns ``(cos_th, cos_b, length)``: ``n·h``, ``wi·h = |wi + wo|/2`` and ``|wi + wo|``."""
    s = wi + wo
    length = np.sqrt(_dot(s, s))
    h = s / length[:, None]
    return _dot(n, h), 0.5 * length, length


def _oren_nayar_factor(wi, wo, n, mu_i, mu_o, sigma):
    """Returns ``A + B·max(0, cos(phi_i - phi_o))·sin a·tan b`` per row."""
    sigma2 = sigma * sigma
    big_a = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33)
    big_b = 0.45 * sigma2 / (sigma2 + 0.09)
    proj_i = wi - mu_i[:, None] * n
    proj_o = wo - mu_o[:, None] * n
    denom = np.sqrt(_dot(proj_i, proj_i) * _dot(proj_o, proj_o))
    cos_phi = np.where(denom > 0.0, _dot(proj_i, proj_o) / denom, 0.0)
    theta_i = np.arccos(np.clip(mu_i, -1.0, 1.0))
    theta_o = np.arccos(np.clip(mu_o, -1.0, 1.0))
    a = np.maximum(theta_i, theta_o)
    b = np.minimum(theta_i, theta_o)
    return big_a + big_b * np.maximum(cos_phi, 0.0) * np.sin(a) * np.tan(b)


# ---------------------------------------------------------------------------------------
# Family A: radiometric BRDFs f(wi, wo), 0 unless mu_i > 0 and mu_o > 0
# ---------------------------------------------------------------------------------------


def lambert(wi, wo, n, *, kd=0.5) -> np.ndarray:
    """``f = kd/π``."""
    wi, wo, n = _arrays(wi, wo, n)
    kd = _rgb(kd, wi.dtype)
    mask = (_dot(wi, n) > 0) & (_dot(wo, n) > 0)
    return np.where(mask[:, None], kd / np.pi, 0.0)


def oren_nayar(wi, wo, n, *, kd=0.5, sigma=0.5) -> np.ndarray:
    """``f = (kd/π)·(A + B·max(0, cos(φi-φo))·sin a·tan b)``."""
    wi, wo, n = _arrays(wi, wo, n)
    kd = _rgb(kd, wi.dtype)
    with np.errstate(all="ignore"):
        mu_i, mu_o = _dot(wi, n), _dot(wo, n)
        factor = _oren_nayar_factor(wi, wo, n, mu_i, mu_o, float(sigma))
        value = kd / np.pi * factor[:, None]
        return np.where(((mu_i > 0) & (mu_o > 0))[:, None], value, 0.0)


def _power_lobe(wi, wo, n, kd, ks, p, cosine, lobe, kd_over_pi: bool) -> np.ndarray:
    """The Phong and Blinn-Phong families: ``f = kd + ks·lobe(c, p, mu_i)`` (``kd/π`` with
    ``kd_over_pi``), ``c`` the cosine clamped to [0, 1]: ``"mirror"`` ``cos_ar``, ``"half"``
    ``cos_th``."""
    wi, wo, n = _arrays(wi, wo, n)
    kd, ks = _rgb(kd, wi.dtype), _rgb(ks, wi.dtype)
    with np.errstate(all="ignore"):
        mu_i, mu_o = _dot(wi, n), _dot(wo, n)
        c = _mirror_cos(wi, wo, n, mu_i) if cosine == "mirror" else _half(wi, wo, n)[0]
        diffuse = kd / np.pi if kd_over_pi else kd
        value = diffuse + ks * lobe(np.clip(c, 0.0, 1.0), float(p), mu_i)[:, None]
        return np.where(((mu_i > 0) & (mu_o > 0))[:, None], value, 0.0)


def phong(wi, wo, n, *, kd=0.0, ks=1.0, p=32.0) -> np.ndarray:
    """``f = kd + ks·cos_ar^p / mu_i``."""

    def lobe(c, p, mu_i):
        return np.power(c, p) / mu_i

    return _power_lobe(wi, wo, n, kd, ks, p, "mirror", lobe, kd_over_pi=False)


def modified_phong(wi, wo, n, *, kd=0.0, ks=1.0, p=32.0) -> np.ndarray:
    """``f = kd + ks·cos_ar^p``."""

    def lobe(c, p, mu_i):
        return np.power(c, p)

    return _power_lobe(wi, wo, n, kd, ks, p, "mirror", lobe, kd_over_pi=False)


def normalized_phong(wi, wo, n, *, kd=0.0, ks=1.0, p=32.0) -> np.ndarray:
    """``f = kd/π + ks·(p+2)/(2π)·cos_ar^p``."""

    def lobe(c, p, mu_i):
        return (p + 2.0) / (2.0 * np.pi) * np.power(c, p)

    return _power_lobe(wi, wo, n, kd, ks, p, "mirror", lobe, kd_over_pi=True)


def blinn_phong(wi, wo, n, *, kd=0.0, ks=1.0, p=32.0) -> np.ndarray:
    """``f = kd + ks·cos_th^p / mu_i``."""

    def lobe(c, p, mu_i):
        return np.power(c, p) / mu_i

    return _power_lobe(wi, wo, n, kd, ks, p, "half", lobe, kd_over_pi=False)


def modified_blinn_phong(wi, wo, n, *, kd=0.0, ks=1.0, p=32.0) -> np.ndarray:
    """``f = kd + ks·cos_th^p``."""

    def lobe(c, p, mu_i):
        return np.power(c, p)

    return _power_lobe(wi, wo, n, kd, ks, p, "half", lobe, kd_over_pi=False)


def normalized_blinn_phong(wi, wo, n, *, kd=0.0, ks=1.0, p=32.0) -> np.ndarray:
    """``f = kd/π + ks·(p+8)/(8π)·cos_th^p``."""

    def lobe(c, p, mu_i):
        return (p + 8.0) / (8.0 * np.pi) * np.power(c, p)

    return _power_lobe(wi, wo, n, kd, ks, p, "half", lobe, kd_over_pi=True)


def blinn_phong_fresnel(wi, wo, n, *, kd=0.0, ks=0.04, p=32.0) -> np.ndarray:
    """``f = kd/π + (p+8)/(8π)·F·cos_th^p``, ``F = ks + (1-ks)(1-cos_b)^5`` per channel."""
    wi, wo, n = _arrays(wi, wo, n)
    kd, f0 = _rgb(kd, wi.dtype), _rgb(ks, wi.dtype)
    p = float(p)
    with np.errstate(all="ignore"):
        mu_i, mu_o = _dot(wi, n), _dot(wo, n)
        cos_th, cos_b, _ = _half(wi, wo, n)
        lobe = (p + 8.0) / (8.0 * np.pi) * np.power(np.clip(cos_th, 0.0, 1.0), p)
        schlick = np.power(1.0 - cos_b, 5)
        fresnel = f0 + (1.0 - f0) * schlick[:, None]
        value = kd / np.pi + fresnel * lobe[:, None]
        return np.where(((mu_i > 0) & (mu_o > 0))[:, None], value, 0.0)


def torrance_sparrow(wi, wo, n, *, kd=0.0, ks=1.0, p=32.0, eta=1.5) -> np.ndarray:
    """``f = kd/π + ks·D·F·G / (4·mu_i·mu_o)`` (Summary eqs. 10-14)."""
    wi, wo, n = _arrays(wi, wo, n)
    kd, ks = _rgb(kd, wi.dtype), _rgb(ks, wi.dtype)
    p, eta = float(p), float(eta)
    with np.errstate(all="ignore"):
        mu_i, mu_o = _dot(wi, n), _dot(wo, n)
        cos_th, cos_b, _ = _half(wi, wo, n)
        cos_th = np.clip(cos_th, 0.0, 1.0)
        d = (p + 2.0) / (2.0 * np.pi) * np.power(cos_th, p)
        r0 = ((eta - 1.0) / (eta + 1.0)) ** 2
        f = r0 + (1.0 - r0) * np.power(1.0 - cos_b, 5)
        g = np.minimum(
            1.0,
            np.minimum(2.0 * cos_th * mu_o / cos_b, 2.0 * cos_th * mu_i / cos_b),
        )
        spec = d * f * g / (4.0 * mu_i * mu_o)
        value = kd / np.pi + ks * spec[:, None]
        return np.where(((mu_i > 0) & (mu_o > 0))[:, None], value, 0.0)


# ---------------------------------------------------------------------------------------
# Family B: scan-line shading terms s(l, v), including the light's cosine
# ---------------------------------------------------------------------------------------


def lambert_shading(wi, wo, n, *, kd=0.5) -> np.ndarray:
    """``s = kd·max(n·l, 0)``."""
    wi, wo, n = _arrays(wi, wo, n)
    kd = _rgb(kd, wi.dtype)
    return kd * np.maximum(_dot(wi, n), 0.0)[:, None]


def oren_nayar_shading(wi, wo, n, *, kd=0.5, sigma=0.5) -> np.ndarray:
    """``s = kd·clamp(n·l, 0, 1)·(A + B·G·sin a·tan b)``."""
    wi, wo, n = _arrays(wi, wo, n)
    kd = _rgb(kd, wi.dtype)
    with np.errstate(all="ignore"):
        mu_i, mu_o = _dot(wi, n), _dot(wo, n)
        factor = _oren_nayar_factor(wi, wo, n, mu_i, mu_o, float(sigma))
        value = kd * (np.clip(mu_i, 0.0, 1.0) * factor)[:, None]
        return np.where((mu_i > 0)[:, None], value, 0.0)


def toon_diffuse(wi, wo, n, *, thresholds, colors) -> np.ndarray:
    """Colour ``c_j``, ``j`` = how many (ascending) thresholds are ``<= n·l``."""
    wi, wo, n = _arrays(wi, wo, n)
    thresholds = np.asarray(thresholds, dtype=np.float64)
    if len(colors) != len(thresholds) + 1:
        raise ValueError("toon_diffuse needs len(colors) == len(thresholds) + 1")
    palette = np.stack([_rgb(c, wi.dtype) for c in colors])
    band = np.searchsorted(thresholds, _dot(wi, n), side="right")
    return palette[band]


def phong_specular(wi, wo, n, *, ks=1.0, p=32.0) -> np.ndarray:
    """``s = ks·clamp(v·r, 0, 1)^p``; 0 when ``n·l <= 0``."""
    wi, wo, n = _arrays(wi, wo, n)
    ks = _rgb(ks, wi.dtype)
    with np.errstate(all="ignore"):
        n_dot_l = _dot(wi, n)
        cos_vr = np.clip(_mirror_cos(wi, wo, n, n_dot_l), 0.0, 1.0)
        lobe = np.where(n_dot_l > 0, np.power(cos_vr, float(p)), 0.0)
        return ks * lobe[:, None]


def blinn_specular(wi, wo, n, *, ks=1.0, p=32.0) -> np.ndarray:
    """``s = ks·clamp(n·h, 0, 1)^p``; 0 when ``n·l <= 0`` or ``l + v = 0``."""
    wi, wo, n = _arrays(wi, wo, n)
    ks = _rgb(ks, wi.dtype)
    with np.errstate(all="ignore"):
        n_dot_l = _dot(wi, n)
        cos_th, _, length = _half(wi, wo, n)
        lobe = np.power(np.clip(cos_th, 0.0, 1.0), float(p))
        lobe = np.where((n_dot_l > 0) & (length > 0), lobe, 0.0)
        return ks * lobe[:, None]


def toon_specular(wi, wo, n, *, high=1.0, low=0.0, threshold) -> np.ndarray:
    """``high`` if ``v·r >= threshold`` else ``low``; 0 when ``n·l <= 0``."""
    wi, wo, n = _arrays(wi, wo, n)
    high, low = _rgb(high, wi.dtype), _rgb(low, wi.dtype)
    n_dot_l = _dot(wi, n)
    cos_vr = _mirror_cos(wi, wo, n, n_dot_l)
    value = np.where((cos_vr >= threshold)[:, None], high, low)
    return np.where((n_dot_l > 0)[:, None], value, 0.0)


def kajiya_kay(wi, wo, n, tangent, *, kd=0.5, ks=0.5, p=32.0) -> np.ndarray:
    """``s = kd·sin_l + ks·max(0, sin_l·sin_v - (l·t)(v·t))^p``; 0 when ``n·l <= 0``."""
    wi, wo, n, t = _arrays(wi, wo, n, tangent)
    kd, ks = _rgb(kd, wi.dtype), _rgb(ks, wi.dtype)
    with np.errstate(all="ignore"):
        l_dot_t, v_dot_t = _dot(wi, t), _dot(wo, t)
        sin_l = np.sqrt(np.maximum(0.0, 1.0 - l_dot_t * l_dot_t))
        sin_v = np.sqrt(np.maximum(0.0, 1.0 - v_dot_t * v_dot_t))
        lobe = np.power(np.clip(sin_l * sin_v - l_dot_t * v_dot_t, 0.0, 1.0), float(p))
        value = kd * sin_l[:, None] + ks * lobe[:, None]
        return np.where((_dot(wi, n) > 0)[:, None], value, 0.0)


# ---------------------------------------------------------------------------------------
# Registry and entry point
# ---------------------------------------------------------------------------------------

MODELS: dict[str, Callable[..., np.ndarray]] = {
    f.__name__: f
    for f in (
        lambert,
        oren_nayar,
        phong,
        modified_phong,
        normalized_phong,
        blinn_phong,
        modified_blinn_phong,
        normalized_blinn_phong,
        blinn_phong_fresnel,
        torrance_sparrow,
        lambert_shading,
        oren_nayar_shading,
        toon_diffuse,
        phong_specular,
        blinn_specular,
        toon_specular,
        kajiya_kay,
    )
}


def evaluate(model, wi, wo, n=(0.0, 0.0, 1.0), tangent=None, **params) -> np.ndarray:
    """Evaluates ``model`` on ``(N, 3)`` arrays and returns ``(N, 3)`` RGB.

    ``tangent`` is required by ``kajiya_kay`` and ignored otherwise; parameters not given
    take the same defaults as ``brdf_rs.reference``.
    """
    if model not in MODELS:
        raise ValueError(f"unknown model {model!r}; known: {', '.join(MODELS)}")
    function = MODELS[model]
    if model == "kajiya_kay":
        if tangent is None:
            raise TypeError("kajiya_kay: missing required argument 'tangent'")
        return function(wi, wo, n, tangent, **params)
    return function(wi, wo, n, **params)
