"""Pure-Python reference implementation of the brdf-rs models (families A and B).

This module is deliberately slow and readable: one function per model, each written
formula by formula after ``docs/models.md`` (same symbols: ``mu_i``, ``mu_o``, ``r``,
``cos_ar``, ``h``, ``cos_th``, ``cos_b``), so a reader can check it against the page.
The Rust kernels are tested against it. It uses only :mod:`math` (no NumPy).

Conventions (the same as in ``docs/models.md``):

- ``wi`` points toward the light and ``wo`` toward the viewer; both point *away* from
  the surface. ``n`` is the surface normal. Vectors need not be unit length: every input
  is normalized here, in a way that survives lengths from 1e-300 to 1e300 and subnormal
  components. Zero-length or non-finite vectors raise :class:`ValueError`.
- Family A (``lambert`` ... ``torrance_sparrow``) returns the radiometric BRDF
  ``f(wi, wo)`` in 1/sr, *without* the cosine of the light; it is exactly 0 unless
  ``mu_i > 0`` and ``mu_o > 0``. The exceptions are the rough dielectrics
  (``ggx_dielectric``, ``beckmann_dielectric``), BSDFs defined on the whole sphere of
  ``wi`` and ``wo`` (reflection on either side, transmission across): 0 only where
  ``mu_i = 0`` or ``mu_o = 0``.
- Family B (``lambert_shading`` ... ``kajiya_kay``) returns the scan-line shading term
  ``s(l, v)`` (``l = wi``, ``v = wo``), which *includes* the light's cosine; every
  specular term is 0 when ``n·l <= 0``.
- Colours (``kd``, ``ks``, ``high``, ``low``, the entries of ``colors``) are a float
  (grey) or a 3-sequence (RGB). Every model returns an RGB tuple of three floats.
- ``x**p`` with ``x = 0`` and ``p = 0`` is 1.
- ``wi + wo = 0`` leaves ``h`` undefined; a model that uses ``h`` then returns 0 for its
  whole value (``docs/models.md``: "every model that uses h returns 0 there"). In family A
  this cannot happen (``mu_i, mu_o > 0`` give ``n·(wi + wo) > 0``), so in practice it
  concerns ``blinn_specular`` alone; the family-A checks are kept for the rule's sake.

Entry point: :func:`eval` (``eval("phong", wi, wo, p=10.0)``); :data:`MODELS` maps each
name to its function and :data:`DEFAULTS` holds each model's default parameters.
"""

import cmath
import decimal
import math
import sys
from collections.abc import Callable, Iterable, Sequence
from typing import Any, SupportsFloat, cast

__all__ = ["DEFAULTS", "MODELS", "eval"]

Vector = tuple[float, float, float]
RGB = tuple[float, float, float]
#: A colour parameter: a number (grey) or an RGB 3-sequence.
Colour = float | Sequence[float]

BLACK: RGB = (0.0, 0.0, 0.0)


# ---------------------------------------------------------------------------------------
# Small helpers: vectors, colours, powers, a product that does not overflow midway
# ---------------------------------------------------------------------------------------


def _normalize(v: Sequence[float]) -> Vector:
    """Returns ``v / |v|``, safe for tiny, huge and subnormal components.

    The vector is first divided by its largest absolute component (exact scaling, so
    subnormal components keep their ratios), then by ``math.hypot`` of the result,
    which lies in [1, sqrt(3)]. A nonzero component too small to survive the division
    (``(1e300, 0, 1e-300)``: 1e-600) becomes the smallest subnormal of its sign, so the
    side of a surface the vector is on stays exact (as in the Rust kernels).
    """
    raw = tuple(float(c) for c in v)
    largest = max(abs(c) for c in raw)
    if not math.isfinite(largest) or largest == 0.0:
        raise ValueError(f"vector must be finite and nonzero, got {tuple(v)!r}")
    x, y, z = (c / largest for c in raw)
    length = math.hypot(x, y, z)
    unit = (x / length, y / length, z / length)
    x, y, z = (
        math.copysign(math.ulp(0.0), c) if u == 0.0 and c != 0.0 else u
        for u, c in zip(unit, raw, strict=True)
    )
    return (x, y, z)


def _dot(a: Vector, b: Vector) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cos(a: Vector, b: Vector) -> float:
    """Returns the cosine between two unit vectors, clamped to [-1, 1].

    Rounding can push a dot product of unit vectors just past 1; the clamp keeps
    ``acos`` in its domain and ``x**p`` at most 1.
    """
    return min(1.0, max(-1.0, _dot(a, b)))


def _cross(a: Vector, b: Vector) -> Vector:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _length(v: Vector) -> float:
    """Returns ``|v|`` (``math.hypot`` scales: no underflow of the squares)."""
    return math.hypot(*v)


def _clamped_cosine(u: Vector, v: Vector) -> tuple[float, float]:
    """Returns ``(max(0, u·v), 1 - max(0, u·v))`` for unit ``u``, ``v``, the complement
    computed as ``|u - v|²/2``: accurate near 1, where ``1 - u·v`` would keep only the
    digits of the rounded cosine (a power ``cos^p`` with ``p = 1e6`` needs them)."""
    c = _cos(u, v)
    if c <= 0.0:
        return 0.0, 1.0
    d = (u[0] - v[0], u[1] - v[1], u[2] - v[2])
    return c, min(1.0, _dot(d, d) / 2.0)


def _mirror(wi: Vector, n: Vector, mu_i: float) -> Vector:
    """Returns ``r = 2 mu_i n - wi``, the mirror of ``wi`` about ``n``."""
    return (
        2.0 * mu_i * n[0] - wi[0],
        2.0 * mu_i * n[1] - wi[1],
        2.0 * mu_i * n[2] - wi[2],
    )


def _half_vector(wi: Vector, wo: Vector) -> Vector | None:
    """Returns ``h = (wi + wo) / |wi + wo|``, or None where ``wi + wo = 0``."""
    s = (wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2])
    if s == (0.0, 0.0, 0.0):
        return None
    return _normalize(s)


def _cos_b(wi: Vector, wo: Vector) -> float:
    """Returns ``cos_b = wi·h`` (= ``wo·h``) as ``|wi + wo| / 2``.

    The two are equal for unit ``wi``, ``wo`` (``wi·(wi + wo) = 1 + wi·wo = |wi + wo|²/2``),
    and ``|wi + wo| / 2 = (wi·h + wo·h) / 2`` holds for any vectors. The dot product
    cancels catastrophically where ``wi`` is close to ``-wo`` (grazing light and view on
    opposite sides) and can even round to 0 or below; the length of the sum keeps full
    relative accuracy there.
    """
    return min(1.0, math.hypot(wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]) / 2.0)


def _one_minus_cos_b(wi: Vector, wo: Vector, cos_b: float) -> float:
    """Returns ``1 - cos_b`` without cancellation: ``(1 - cos_b²)/(1 + cos_b)`` with
    ``1 - cos_b² = |wi - wo|²/4`` (``|wi + wo|² + |wi - wo|² = 4``). Where ``wi ≈ wo``
    the subtraction ``1 - cos_b`` keeps no correct digit, and Schlick's ``(1 - cos_b)^5``
    with ``F0 = 0`` is all there is."""
    d = (wi[0] - wo[0], wi[1] - wo[1], wi[2] - wo[2])
    return min(1.0, _dot(d, d) / 4.0 / (1.0 + cos_b))


def _cos_phi_difference(wi: Vector, wo: Vector, n: Vector) -> float:
    """Returns ``cos(phi_i - phi_o)``: the cosine between the tangent-plane projections
    of ``wi`` and ``wo``; 0 when either projection has zero length (``docs/models.md``).

    The projections are taken as ``n × wi`` and ``n × wo`` (the projections turned by 90°
    about ``n``: same angle between them), which do not cancel near the normal the way
    ``w - (n·w) n`` does."""
    cross_i, cross_o = _cross(n, wi), _cross(n, wo)
    if cross_i == (0.0, 0.0, 0.0) or cross_o == (0.0, 0.0, 0.0):
        return 0.0
    return _cos(_normalize(cross_i), _normalize(cross_o))


def _rgb(colour: Colour) -> RGB:
    """Returns a colour as an RGB triple: a number means grey."""
    try:
        grey = float(cast(SupportsFloat, colour))
    except TypeError:  # not a number: a 3-sequence
        r, g, b = (float(c) for c in cast(Iterable[float], colour))
        return (r, g, b)
    return (grey, grey, grey)


def _three(values: Iterable[float]) -> RGB:
    """Returns three channel values as an RGB tuple."""
    r, g, b = values
    return (r, g, b)


def _log_base(x: float, one_minus: float | None) -> float:
    """Returns ``ln x``, from the complement ``1 - x`` when given and ``x > 1/2``."""
    if one_minus is not None and x > 0.5:
        return math.log1p(-one_minus)
    return math.log(x)


def _pow(x: float, p: float, one_minus: float | None = None) -> float:
    """Returns ``x**p`` for ``0 <= x <= 1`` and ``p >= 0``, with ``0**0 = 1``.

    The base never exceeds 1, so the power cannot overflow; it may underflow to 0. With
    ``one_minus`` (an accurate ``1 - x``) a base near 1 is taken as ``exp(p·log1p(-(1-x)))``:
    ``x`` rounded to the nearest float would put an error of up to ``p·2^-53`` (1e-10 at
    ``p = 1e6``) into the power.
    """
    if p == 0.0:
        return 1.0  # docs/models.md: x^p with x = 0, p = 0 is 1
    if x == 0.0:
        return 0.0
    if one_minus is not None and x > 0.5:
        return math.exp(p * math.log1p(-one_minus))
    return float(x**p)


def _frexp_power(x: float, p: float, one_minus: float | None = None) -> tuple[float, int]:
    """Returns ``(m, e)`` with ``x**p = m·2**e``, for ``0 < x <= 1`` and ``p >= 0``.

    Where ``x**p`` is a normal float it is split exactly; where it underflows (below
    ~2.2e-308) it is taken in the log domain, ``p·log2(x)``, with an integer exponent,
    so a later division by a tiny ``mu`` can still bring it back into range.
    """
    y = _pow(x, p, one_minus)
    if y >= sys.float_info.min:
        return math.frexp(y)
    log2_y = p * _log_base(x, one_minus) / math.log(2.0)
    e = math.floor(log2_y)
    m, e2 = math.frexp(2.0 ** (log2_y - e))
    return m, e + e2


def _product_quotient(
    numerators: Sequence[float],
    denominators: Sequence[float],
    power: tuple[float, float] | tuple[float, float, float] = (1.0, 1.0),
) -> float:
    """Returns ``prod(numerators)·x**p / prod(denominators)``, ``(x, p) = power``, for
    finite factors >= 0, ``0 <= x <= 1`` and ``p >= 0`` (``0**0 = 1``). ``power`` may
    carry a third element, an accurate ``1 - x`` (see :func:`_pow`).

    Each factor is split into mantissa and exponent (``math.frexp``) and the exponents
    are summed as integers, so no intermediate product overflows or underflows: the
    result is 0 if a numerator is 0, and inf only if the exact value is beyond the float
    range (or a denominator is 0 with all numerators nonzero). Never 0*inf or inf/inf.
    """
    x, p = power[0], power[1]
    one_minus = power[2] if len(power) > 2 else None
    if x == 0.0:
        if p != 0.0:
            return 0.0
        x, one_minus = 1.0, 0.0  # docs/models.md: x^p with x = 0, p = 0 is 1
    if any(factor == 0.0 for factor in numerators):
        return 0.0
    if any(factor == 0.0 for factor in denominators):
        return math.inf
    mantissa, exponent = _frexp_power(x, p, one_minus)
    for factor in numerators:
        m, e = math.frexp(factor)
        mantissa, e2 = math.frexp(mantissa * m)
        exponent += e + e2
    for factor in denominators:
        m, e = math.frexp(factor)
        mantissa, e2 = math.frexp(mantissa / m)
        exponent += e2 - e
    try:
        return math.ldexp(mantissa, exponent)
    except OverflowError:
        return math.inf


def _oren_nayar_factor(
    sigma: float,
    mu_i: float,
    mu_o: float,
    sin_i: float,
    sin_o: float,
    cos_phi: float,
    weight: float = 1.0,
) -> float:
    """Returns ``weight·(A + B·max(0, cos(phi_i - phi_o))·sin a·tan b)`` (``docs/models.md``).

    ``a = max(theta_i, theta_o)``, ``b = min(theta_i, theta_o)``,
    ``A = 1 - 0.5 sigma²/(sigma² + 0.33)``, ``B = 0.45 sigma²/(sigma² + 0.09)``.
    The angle with the smaller cosine is ``a``: ``sin a`` is its sine and ``tan b`` the
    other's sine over its cosine, sines from ``|n × w|``. No ``acos``/``tan``:
    ``tan(acos(1e-300))`` is ``tan`` of the float nearest π/2, about 1.6e16, not 1e300.
    ``weight`` (at most the larger cosine: the shading term's ``n·l``) divides ``cos b``
    first, so ``weight·tan b`` stays finite where ``tan b`` alone overflows.
    """
    sigma2 = sigma * sigma
    big_a = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33)
    big_b = 0.45 * sigma2 / (sigma2 + 0.09)
    g = max(0.0, cos_phi)
    if big_b == 0.0 or g == 0.0:
        # The second term is 0 whatever tan b is: never form 0 * tan(b).
        return weight * big_a
    # Callers guarantee max(mu_i, mu_o) > 0, so tan b is finite (or beyond the range,
    # where the exact value is).
    if mu_i >= mu_o:
        sin_a, sin_b, cos_b = sin_o, sin_i, mu_i
    else:
        sin_a, sin_b, cos_b = sin_i, sin_o, mu_o
    return weight * big_a + big_b * g * sin_a * sin_b * (weight / cos_b)


def _frame(
    wi: Sequence[float], wo: Sequence[float], n: Sequence[float]
) -> tuple[Vector, Vector, Vector]:
    """Returns ``wi``, ``wo``, ``n`` normalized."""
    return _normalize(wi), _normalize(wo), _normalize(n)


# ---------------------------------------------------------------------------------------
# Family A: radiometric BRDFs f(wi, wo), units 1/sr, 0 unless mu_i > 0 and mu_o > 0
# ---------------------------------------------------------------------------------------


def lambert(wi: Sequence[float], wo: Sequence[float], n: Sequence[float], *, kd: Colour) -> RGB:
    """Lambert: ``f = kd/π``."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    return _three(kd_c / math.pi for kd_c in _rgb(kd))


def oren_nayar(
    wi: Sequence[float], wo: Sequence[float], n: Sequence[float], *, kd: Colour, sigma: float
) -> RGB:
    """Oren-Nayar (qualitative model): ``f = (kd/π)·(A + B·max(0, cos(φi-φo))·sin a·tan b)``."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    cos_phi = _cos_phi_difference(wi, wo, n)
    sin_i, sin_o = _length(_cross(n, wi)), _length(_cross(n, wo))
    factor = _oren_nayar_factor(sigma, mu_i, mu_o, sin_i, sin_o, cos_phi)
    # A kd channel of 0 is 0 even where the factor is infinite (both directions within
    # 1e-308 of the horizon).
    return _three(0.0 if kd_c == 0.0 else kd_c / math.pi * factor for kd_c in _rgb(kd))


def phong(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
) -> RGB:
    """Phong (BRDF Summary eq. 2): ``f = kd + ks·cos_ar^p / mu_i``.

    Infinite only where the exact value is (mu_i -> 0+): the lobe is formed by
    :func:`_product_quotient`, so a zero numerator gives 0, never 0/0 or 0*inf, and a
    ``cos_ar^p`` below the float range still counts when ``mu_i`` is tiny.
    """
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    r = _mirror(wi, n, mu_i)
    cos_ar, one_minus = _clamped_cosine(r, wo)
    return _three(
        kd_c + _product_quotient((ks_c,), (mu_i,), power=(cos_ar, p, one_minus))
        for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


def modified_phong(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
) -> RGB:
    """Modified Phong (BRDF Summary eq. 3): ``f = kd + ks·cos_ar^p``."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    r = _mirror(wi, n, mu_i)
    cos_ar, one_minus = _clamped_cosine(r, wo)
    lobe = _pow(cos_ar, p, one_minus)
    return _three(kd_c + ks_c * lobe for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True))


def normalized_phong(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
) -> RGB:
    """Normalized Phong (BRDF Summary eq. 5, RTR 7.47): ``f = kd/π + ks·(p+2)/(2π)·cos_ar^p``."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    r = _mirror(wi, n, mu_i)
    cos_ar, one_minus = _clamped_cosine(r, wo)
    lobe = (p + 2.0) / (2.0 * math.pi) * _pow(cos_ar, p, one_minus)
    return _three(
        kd_c / math.pi + ks_c * lobe for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


def blinn_phong(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
) -> RGB:
    """Blinn-Phong (BRDF Summary eq. 7): ``f = kd + ks·cos_th^p / mu_i``.

    Infinite only where the exact value is (mu_i -> 0+), as in :func:`phong`.
    """
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK  # h undefined; unreachable with mu_i, mu_o > 0 (see module doc)
    cos_th, one_minus = _clamped_cosine(n, h)
    return _three(
        kd_c + _product_quotient((ks_c,), (mu_i,), power=(cos_th, p, one_minus))
        for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


def modified_blinn_phong(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
) -> RGB:
    """Modified Blinn-Phong (BRDF Summary eq. 8): ``f = kd + ks·cos_th^p``."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK  # h undefined; unreachable with mu_i, mu_o > 0 (see module doc)
    cos_th, one_minus = _clamped_cosine(n, h)
    lobe = _pow(cos_th, p, one_minus)
    return _three(kd_c + ks_c * lobe for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True))


def normalized_blinn_phong(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
) -> RGB:
    """Normalized Blinn-Phong (Summary eq. 9 with cos_th, RTR 7.48):
    ``f = kd/π + ks·(p+8)/(8π)·cos_th^p``."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK  # h undefined; unreachable with mu_i, mu_o > 0 (see module doc)
    cos_th, one_minus = _clamped_cosine(n, h)
    lobe = (p + 8.0) / (8.0 * math.pi) * _pow(cos_th, p, one_minus)
    return _three(
        kd_c / math.pi + ks_c * lobe for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


def blinn_phong_fresnel(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
) -> RGB:
    """Blinn-Phong with Schlick Fresnel (RTR 7.49):
    ``f = kd/π + (p+8)/(8π)·F·cos_th^p``, ``F = ks + (1-ks)(1-cos_b)^5`` per channel
    (``ks`` is F0)."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK  # h undefined; unreachable with mu_i, mu_o > 0 (see module doc)
    cos_th, one_minus = _clamped_cosine(n, h)
    cos_b = _cos_b(wi, wo)
    lobe = (p + 8.0) / (8.0 * math.pi) * _pow(cos_th, p, one_minus)
    schlick = _one_minus_cos_b(wi, wo, cos_b) ** 5
    return _three(
        kd_c / math.pi + (f0_c + (1.0 - f0_c) * schlick) * lobe
        for kd_c, f0_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


def torrance_sparrow(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
    eta: float,
) -> RGB:
    """Torrance-Sparrow (BRDF Summary eqs. 10-14, RTR 7.51):
    ``f = kd/π + ks·D·F·G / (4·mu_i·mu_o)`` with
    ``D = (p+2)/(2π)·cos_th^p``, ``F = R0 + (1-R0)(1-cos_b)^5``, ``R0 = ((eta-1)/(eta+1))²``,
    ``G = min(1, 2·cos_th·mu_o/cos_b, 2·cos_th·mu_i/cos_b)``.
    """
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK  # h undefined; unreachable with mu_i, mu_o > 0 (see module doc)
    cos_th, one_minus = _clamped_cosine(n, h)
    cos_b = _cos_b(wi, wo)
    d_scale = (p + 2.0) / (2.0 * math.pi)  # D = d_scale·cos_th^p
    r0 = ((eta - 1.0) / (eta + 1.0)) ** 2
    f = r0 + (1.0 - r0) * _one_minus_cos_b(wi, wo, cos_b) ** 5

    # G / (4 mu_i mu_o) is distributed over the min of G:
    #     min(1/(4 mu_i mu_o), cos_th/(2 cos_b mu_i), cos_th/(2 cos_b mu_o)).
    # For grazing directions 4·mu_i·mu_o underflows to 0 (and 2·cos_th·mu/cos_b too), so
    # forming G first and dividing afterwards would give 0/0 or 0*inf. Each candidate is
    # instead the whole product ks·D·F·(...) computed by _product_quotient (cos_th^p
    # passed as its power, as it may underflow where the quotient does not), which gives
    # 0 for a zero factor and inf only for a value beyond the float range.
    def specular(ks_c: float) -> float:
        d_power = (cos_th, p, one_minus)
        return min(
            _product_quotient((ks_c, d_scale, f), (4.0, mu_i, mu_o), power=d_power),
            _product_quotient((ks_c, d_scale, f, cos_th), (2.0, cos_b, mu_i), power=d_power),
            _product_quotient((ks_c, d_scale, f, cos_th), (2.0, cos_b, mu_o), power=d_power),
        )

    return _three(
        kd_c / math.pi + specular(ks_c) for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


# ---------------------------------------------------------------------------------------
# Family A beyond the sources: GGX, Beckmann, Ward, Ashikhmin-Shirley
# ---------------------------------------------------------------------------------------


def _tangent_frame(n: Vector, t: Sequence[float] | None) -> tuple[Vector, Vector]:
    """Returns ``(x, y)``: the tangent projected onto the tangent plane and normalized
    (Gram-Schmidt; +x when no tangent is given), and ``y = n × x``. A given tangent
    parallel to ``n`` (the sine of their angle at most 64 machine epsilons, as ``eval``)
    is refused; the default +x parallel to ``n`` has no projection: then any unit
    vector perpendicular to ``n`` (Duff et al.)."""
    if t is not None:
        t = _normalize(t)
        if math.sqrt(_sin2(n, t)) <= 64 * sys.float_info.epsilon:
            raise ValueError(
                f"tangent {tuple(t)!r} is parallel to the normal n {tuple(n)!r}: it gives no"
                " direction in the tangent plane"
            )
    t = (1.0, 0.0, 0.0) if t is None else t
    d = _dot(t, n)
    p = (t[0] - d * n[0], t[1] - d * n[1], t[2] - d * n[2])
    length = math.hypot(*p)
    if length > 1e-15:
        x = (p[0] / length, p[1] / length, p[2] / length)
    else:
        sign = -1.0 if n[2] < 0.0 else 1.0
        a = -1.0 / (sign + n[2])
        b = n[0] * n[1] * a
        x = (b, sign + n[1] * n[1] * a, -n[1])
    y = (n[1] * x[2] - n[2] * x[1], n[2] * x[0] - n[0] * x[2], n[0] * x[1] - n[1] * x[0])
    return x, y


def _sin2(n: Vector, w: Vector) -> float:
    """``sin²θ`` of unit ``w`` about unit ``n``, as ``|n × w|²`` (no cancellation)."""
    c = (n[1] * w[2] - n[2] * w[1], n[2] * w[0] - n[0] * w[2], n[0] * w[1] - n[1] * w[0])
    return _dot(c, c)


def _microfacet(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    kd: Colour,
    ks: Colour,
    ndf: Callable[[float, float], float],
    mu_lambda: Callable[[float, float], float],
) -> RGB:
    """``kd/π + D·G2·F/(4 mu_i mu_o)`` with height-correlated Smith
    ``G2 = 1/(1 + Λ(mu_i) + Λ(mu_o))`` and Schlick's F (``ks`` is F0).

    ``G2/(4 mu_i mu_o)`` is written ``1/(4(mu_i mu_o + mu_o·mu_iΛ(mu_i) + mu_i·mu_oΛ(mu_o)))``
    with ``mu_lambda(μ, sin²θ) = μ·Λ(μ)``, which stays finite at grazing angles where
    ``Λ`` itself overflows; the larger cosine ``m`` is divided out of the sum first
    (``min(mu_i, mu_o) + (mu_o/m)·l_i + (mu_i/m)·l_o``), whose products then do not
    underflow when both cosines are tiny."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK
    cos_th = max(0.0, _cos(n, h))
    d = ndf(cos_th, _sin2(n, h))
    l_i = mu_lambda(mu_i, _sin2(n, wi))
    l_o = mu_lambda(mu_o, _sin2(n, wo))
    m = max(mu_i, mu_o)
    inner = min(mu_i, mu_o) + mu_o / m * l_i + mu_i / m * l_o
    specular = 0.0 if d == 0.0 else d / (4.0 * inner) / m  # D·G2/(4 mu_i mu_o)
    schlick = _one_minus_cos_b(wi, wo, _cos_b(wi, wo)) ** 5
    fresnel = [f0_c + (1.0 - f0_c) * schlick for f0_c in _rgb(ks)]
    return _three(
        kd_c / math.pi + (0.0 if f_c == 0.0 else f_c * specular)
        for kd_c, f_c in zip(_rgb(kd), fresnel, strict=True)
    )


#: A microfacet distribution as two functions: ``ndf(cos_th, sin²θh)`` is ``D`` and
#: ``mu_lambda(μ, sin²θ)`` is ``μ·Λ(μ)`` for ``0 < μ <= 1``.
Distribution = tuple[Callable[[float, float], float], Callable[[float, float], float]]


def _ggx_terms(alpha: float) -> Distribution:
    """GGX's ``D`` and ``μΛ(μ)`` (see :func:`ggx`)."""
    a2 = alpha * alpha

    def ndf(cos_th: float, sin2_th: float) -> float:
        return a2 / (math.pi * (sin2_th + a2 * cos_th * cos_th) ** 2)

    def mu_lambda(mu: float, sin2: float) -> float:
        # μΛ(μ) = (−μ + sqrt(μ² + α²(1−μ²)))/2
        return (math.sqrt(mu * mu + a2 * sin2) - mu) / 2.0

    return ndf, mu_lambda


def _beckmann_terms(alpha: float) -> Distribution:
    """Beckmann's ``D`` and ``μΛ(μ)`` (see :func:`beckmann`)."""
    a2 = alpha * alpha

    def ndf(cos_th: float, sin2_th: float) -> float:
        # tan²θh/α² beyond 745 makes exp underflow (before cos⁴ does): D = 0, never 0/0.
        if sin2_th > 745.0 * a2 * cos_th * cos_th:
            return 0.0
        exponent = sin2_th / (a2 * cos_th * cos_th)
        return math.exp(-exponent) / (math.pi * a2 * cos_th**4)

    def mu_lambda(mu: float, sin2: float) -> float:
        s = math.sqrt(sin2)
        if s == 0.0:
            return 0.0  # c = ∞: Λ = 0
        c = mu / (alpha * s)
        # μΛ(μ) = μ(erf(c)−1)/2 + α·s·exp(−c²)/(2 sqrt(π))
        return mu * (math.erf(c) - 1.0) / 2.0 + alpha * s * math.exp(-c * c) / (
            2.0 * math.sqrt(math.pi)
        )

    return ndf, mu_lambda


def ggx(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    alpha: float,
) -> RGB:
    """GGX: ``D = α²/(π(cos_th²(α²−1)+1)²)``, ``Λ(μ) = (−1+sqrt(1+α²(1−μ²)/μ²))/2``.

    The NDF's denominator ``cos_th²(α²−1)+1`` is written ``sin²θh + α²cos²θh`` (equal).
    """
    ndf, mu_lambda = _ggx_terms(alpha)
    return _microfacet(wi, wo, n, kd, ks, ndf, mu_lambda)


def beckmann(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    alpha: float,
) -> RGB:
    """Beckmann: ``D = exp(−tan²θh/α²)/(π α² cos⁴θh)``,
    ``Λ(μ) = (erf(c)−1)/2 + exp(−c²)/(2c·sqrt(π))``, ``c = μ/(α·sqrt(1−μ²))``."""
    ndf, mu_lambda = _beckmann_terms(alpha)
    return _microfacet(wi, wo, n, kd, ks, ndf, mu_lambda)


def _conductor_fresnel(cos_b: float, one_minus_cos_b: float, eta: float, k: float) -> float:
    """The unpolarized Fresnel reflectance ``(|r_s|² + |r_p|²)/2`` of a conductor of
    relative index ``η̃ = eta + i·k`` at ``cos_b`` (pbrt-v4's ``FrComplex``).

    With ``w = sqrt(η̃² − sin²θb)`` and ``e = η̃² − 1`` (so ``w² = e + cos_b²``):
    ``r_s = (cos_b − w)/(cos_b + w) = −e/(cos_b + w)²`` and
    ``r_p = (η̃² cos_b − w)/(η̃² cos_b + w) = e·(cos_b² η̃² − sin²θb)/(η̃² cos_b + w)²``,
    which keep their digits as ``η̃ → 1`` (``e`` is formed without cancellation)."""
    sin2 = one_minus_cos_b * (1.0 + cos_b)
    eta_c = complex(eta, k)
    e = complex((eta - 1.0) * (eta + 1.0) - k * k, 2.0 * eta * k)
    if e == 0:
        return 0.0
    # Re w² summed where it rounds least: from e where cos_b < eta, else from η̃² − sin².
    w2 = e + cos_b * cos_b if cos_b < eta else complex(eta * eta - k * k - sin2, 2.0 * eta * k)
    w = cmath.sqrt(w2)
    r_s = -e / (cos_b + w) ** 2
    r_p = e * (cos_b * cos_b * eta_c * eta_c - sin2) / (eta_c * eta_c * cos_b + w) ** 2
    return (abs(r_s) ** 2 + abs(r_p) ** 2) / 2.0


def _microfacet_fresnel(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    kd: Colour,
    fresnel: Callable[[float, float, int], float],
    lobe_model: Callable[..., RGB],
    alpha: float,
) -> RGB:
    """``kd/π + F·lobe``: the lobe of ``lobe_model`` (``ggx`` or ``beckmann`` at
    ``kd = 0``, ``ks = 1``), times ``fresnel(cos_b, 1 − cos_b, channel)``."""
    wi_u, wo_u, n_u = _frame(wi, wo, n)
    if not (_cos(n_u, wi_u) > 0.0 and _cos(n_u, wo_u) > 0.0):
        return BLACK
    lobe = lobe_model(wi, wo, n, kd=0.0, ks=1.0, alpha=alpha)[0]
    if lobe == 0.0:
        return _three(kd_c / math.pi for kd_c in _rgb(kd))
    cos_b = _cos_b(wi_u, wo_u)
    one_minus = _one_minus_cos_b(wi_u, wo_u, cos_b)
    return _three(
        kd_c / math.pi + fresnel(cos_b, one_minus, c) * lobe for c, kd_c in enumerate(_rgb(kd))
    )


def ggx_conductor(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    eta: Colour,
    k: Colour,
    alpha: float,
) -> RGB:
    """``ggx``'s lobe with a conductor's Fresnel term (per channel ``eta + i·k``)."""
    eta_rgb, k_rgb = _rgb(eta), _rgb(k)

    def fresnel(cos_b: float, one_minus: float, c: int) -> float:
        return _conductor_fresnel(cos_b, one_minus, eta_rgb[c], k_rgb[c])

    return _microfacet_fresnel(wi, wo, n, kd, fresnel, ggx, alpha)


def beckmann_conductor(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    eta: Colour,
    k: Colour,
    alpha: float,
) -> RGB:
    """``beckmann``'s lobe with a conductor's Fresnel term (per channel ``eta + i·k``)."""
    eta_rgb, k_rgb = _rgb(eta), _rgb(k)

    def fresnel(cos_b: float, one_minus: float, c: int) -> float:
        return _conductor_fresnel(cos_b, one_minus, eta_rgb[c], k_rgb[c])

    return _microfacet_fresnel(wi, wo, n, kd, fresnel, beckmann, alpha)


def _f82_fresnel(cos_b: float, one_minus_cos_b: float, f0: float, f82: float) -> float:
    """The F82-tint Fresnel term: Schlick's ``F_S`` for ``f0`` less ``a·μ(1 − μ)^6``, with ``a``
    such that ``F(1/7) = f82·F_S(1/7)``; clamped at 0 (docs/models.md)."""
    mu_bar = 1.0 / 7.0
    schlick_bar = f0 + (1.0 - f0) * (1.0 - mu_bar) ** 5
    a = (1.0 - f82) * schlick_bar / (mu_bar * (1.0 - mu_bar) ** 6)
    schlick = f0 + (1.0 - f0) * one_minus_cos_b**5
    return max(0.0, schlick - a * cos_b * one_minus_cos_b**6)


def ggx_f82(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    f0: Colour,
    f82: Colour,
    alpha: float,
) -> RGB:
    """``ggx``'s lobe with the F82-tint Fresnel term (per channel ``f0``, ``f82``)."""
    f0_rgb, f82_rgb = _rgb(f0), _rgb(f82)

    def fresnel(cos_b: float, one_minus: float, c: int) -> float:
        return _f82_fresnel(cos_b, one_minus, f0_rgb[c], f82_rgb[c])

    return _microfacet_fresnel(wi, wo, n, kd, fresnel, ggx, alpha)


def beckmann_f82(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    f0: Colour,
    f82: Colour,
    alpha: float,
) -> RGB:
    """``beckmann``'s lobe with the F82-tint Fresnel term (per channel ``f0``, ``f82``)."""
    f0_rgb, f82_rgb = _rgb(f0), _rgb(f82)

    def fresnel(cos_b: float, one_minus: float, c: int) -> float:
        return _f82_fresnel(cos_b, one_minus, f0_rgb[c], f82_rgb[c])

    return _microfacet_fresnel(wi, wo, n, kd, fresnel, beckmann, alpha)


def _gen_schlick_fresnel(
    cos_b: float, one_minus_cos_b: float, f0: float, f90: float, exponent: float
) -> float:
    """The generalized Schlick term ``f0 + (f90 − f0)(1 − cos_b)^exponent``."""
    return f0 + (f90 - f0) * _pow(one_minus_cos_b, exponent, cos_b)


def ggx_gen_schlick(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    f0: Colour,
    f90: Colour,
    exponent: float,
    alpha: float,
) -> RGB:
    """``ggx``'s lobe with the generalized Schlick term ``f0 + (f90 − f0)(1 − cos_b)^exponent``."""
    f0_rgb, f90_rgb = _rgb(f0), _rgb(f90)

    def fresnel(cos_b: float, one_minus: float, c: int) -> float:
        return _gen_schlick_fresnel(cos_b, one_minus, f0_rgb[c], f90_rgb[c], exponent)

    return _microfacet_fresnel(wi, wo, n, kd, fresnel, ggx, alpha)


def beckmann_gen_schlick(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    f0: Colour,
    f90: Colour,
    exponent: float,
    alpha: float,
) -> RGB:
    """``beckmann``'s lobe with the generalized Schlick term (as ``ggx_gen_schlick``)."""
    f0_rgb, f90_rgb = _rgb(f0), _rgb(f90)

    def fresnel(cos_b: float, one_minus: float, c: int) -> float:
        return _gen_schlick_fresnel(cos_b, one_minus, f0_rgb[c], f90_rgb[c], exponent)

    return _microfacet_fresnel(wi, wo, n, kd, fresnel, beckmann, alpha)


def ward(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    tangent: Sequence[float] | None = None,
    *,
    kd: Colour,
    ks: Colour,
    alpha_x: float,
    alpha_y: float,
) -> RGB:
    """Ward: ``kd/π + ks·exp(−((h·x/αx)² + (h·y/αy)²)/cos_th²)/(4π·αx·αy·sqrt(mu_i·mu_o))``."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK
    x, y = _tangent_frame(n, tangent)
    cos_th = _cos(n, h)
    numerator = (_dot(h, x) / alpha_x) ** 2 + (_dot(h, y) / alpha_y) ** 2
    if numerator > 745.0 * cos_th * cos_th:
        lobe = 0.0  # exp underflows (also where cos_th² does): never 0/0
    else:
        exponent = numerator / (cos_th * cos_th)
        # The denominator's product may underflow at grazing angles (and tiny α):
        # _product_quotient keeps it exact, inf only beyond the float range.
        denominator = (4.0 * math.pi, alpha_x, alpha_y, math.sqrt(mu_i), math.sqrt(mu_o))
        lobe = _product_quotient((math.exp(-exponent),), denominator)
    return _three(
        kd_c / math.pi + (0.0 if ks_c == 0.0 else ks_c * lobe)
        for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


def ashikhmin_shirley(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    tangent: Sequence[float] | None = None,
    *,
    Rd: Colour,
    Rs: Colour,
    nu: float,
    nv: float,
) -> RGB:
    """Ashikhmin-Shirley (JGT 2000, eqs. 4-5): specular
    ``sqrt((nu+1)(nv+1))/(8π)·(n·h)^((nu(h·u)²+nv(h·v)²)/(1−(n·h)²))/((h·k)·max(n·k1,n·k2))·F``,
    ``F = Rs + (1−Rs)(1−h·k)^5``; diffuse
    ``28·Rd/(23π)·(1−Rs)·(1−(1−n·k1/2)^5)·(1−(1−n·k2/2)^5)``.

    ``1 − (n·h)²`` is written ``(h·u)² + (h·v)²`` (equal for an orthonormal frame).
    """
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK
    u, v = _tangent_frame(n, tangent)
    a, b = _dot(h, u), _dot(h, v)
    s2 = a * a + b * b
    exponent = (nu * a * a + nv * b * b) / s2 if s2 > 0.0 else (nu + nv) / 2.0
    cos_th, one_minus = _clamped_cosine(n, h)
    k_dot_h = _cos_b(wi, wo)
    norm = math.sqrt(nu + 1.0) * math.sqrt(nv + 1.0) / (8.0 * math.pi)
    lobe = _product_quotient(
        (norm,), (k_dot_h, max(mu_i, mu_o)), power=(cos_th, exponent, one_minus)
    )
    schlick = _one_minus_cos_b(wi, wo, k_dot_h) ** 5

    def coupling(mu: float) -> float:
        # 1 - (1 - mu/2)^5 = (mu/2)(1 + z + z² + z³ + z⁴), z = 1 - mu/2: no cancellation
        z = 1.0 - mu / 2.0
        return mu / 2.0 * (1.0 + z * (1.0 + z * (1.0 + z * (1.0 + z))))

    diffuse = 28.0 / (23.0 * math.pi) * coupling(mu_i) * coupling(mu_o)
    fresnel = [rs_c + (1.0 - rs_c) * schlick for rs_c in _rgb(Rs)]
    return _three(
        (0.0 if f_c == 0.0 else f_c * lobe) + rd_c * (1.0 - rs_c) * diffuse
        for rd_c, rs_c, f_c in zip(_rgb(Rd), _rgb(Rs), fresnel, strict=True)
    )


# ---------------------------------------------------------------------------------------
# Rough dielectrics (Walter et al. 2007): defined on the whole sphere of wi and wo
# ---------------------------------------------------------------------------------------


def _dielectric_fresnel(c: float, r: float, e: float | None = None) -> tuple[float, float]:
    """Returns ``(F, 1 − F)``: the exact unpolarized Fresnel reflectance of a dielectric
    interface for the cosine ``c`` (in [0, 1]) on the incident side and the relative index
    ``r`` = index beyond the interface / index on the incident side (``docs/models.md``).

    ``g² = r² − 1 + c²``; ``g² < 0`` is total internal reflection (``F = 1``). Otherwise
    ``F = ½((g − c)/(g + c))²(1 + ((c(g + c) − 1)/(c(g − c) + 1))²)`` (Walter et al.'s
    eq. 22), with ``r² − 1`` formed as ``(r − 1)(r + 1)`` and ``g − c`` as
    ``(r² − 1)/(g + c)``, so ``F`` keeps its digits as ``r → 1`` (``F = 0`` at ``r = 1``).
    ``1 − F`` is :func:`_dielectric_transmittance` with ``g = r·c_t``. ``e``: ``r² − 1``
    where the caller has it more accurately than ``r`` gives it (``r = 1/eta``: the
    rounding of ``1/eta`` would be all of ``r − 1``'s digits near ``eta = 1``).
    """
    if e is None:
        e = (r - 1.0) * (r + 1.0)
    if e == 0.0:
        return 0.0, 1.0  # r = 1: no interface
    g2 = e + c * c
    if g2 < 0.0:
        return 1.0, 0.0
    g = math.sqrt(g2)
    if g + c == 0.0:
        return 1.0, 0.0  # c = 0 and r = 1: the grazing limit of every r
    g_minus_c = e / (g + c)
    ratio = (c * (g + c) - 1.0) / (c * g_minus_c + 1.0)
    fresnel = min(1.0, 0.5 * (g_minus_c / (g + c)) ** 2 * (1.0 + ratio * ratio))
    return fresnel, _dielectric_transmittance(c, g / r, 1.0, r)


def _dielectric_transmittance(c_i: float, c_t: float, eta_i: float, eta_t: float) -> float:
    """Returns ``1 − F``, the transmittance of the interface, from the cosines ``c_i``
    (incident side, index ``eta_i``) and ``c_t`` (refracted side, index ``eta_t``) of a
    pair that obeys Snell's law: ``½(1 − r_s²) + ½(1 − r_p²)`` with
    ``1 − r_s² = 4 eta_i c_i eta_t c_t/(eta_i c_i + eta_t c_t)²`` and
    ``1 − r_p² = 4 eta_i c_i eta_t c_t/(eta_t c_i + eta_i c_t)²``.

    With ``r = eta_t/eta_i`` and ``g = r·c_t`` this is ``1 − F(c_i, r)`` of
    :func:`_dielectric_fresnel` (``r_s = (c − g)/(c + g)``, ``r_p = (r²c − g)/(r²c + g)``),
    without its cancellations: neither ``1 − F`` where ``F → 1`` nor ``g² = r² − 1 + c²``
    near the critical angle, where ``c_t`` (known directly for a refracted pair) is
    small.
    """
    a = eta_i * c_i * eta_t * c_t
    return min(
        1.0,
        2.0 * a * (1.0 / (eta_i * c_i + eta_t * c_t) ** 2 + 1.0 / (eta_t * c_i + eta_i * c_t) ** 2),
    )


def _dielectric(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    ks: Colour,
    kt: Colour,
    eta: float,
    distribution: Distribution,
) -> RGB:
    """A rough dielectric interface: reflection ``f_r`` where ``wi``, ``wo`` lie on the
    same side of the surface, transmission ``f_t`` where they lie on opposite sides
    (``docs/models.md``, radiance transport). ``eta`` = index below / index above ("below"
    is the side opposite ``n``); the medium a direction lies in has index 1 above and
    ``eta`` below.

    ``f_r = ks·F(|wi·h|, r_i)·D(h)·G2/(4|mu_i||mu_o|)``, ``h = normalize(wi + wo)`` on
    ``n``'s side, ``r_i`` = index of the side opposite ``wi`` / index of ``wi``'s side.

    ``f_t = kt·|wi·h||wo·h|/(|mu_i||mu_o|)·eta_o²·(1 − F(|wi·h|, eta_o/eta_i))·D(h)·G2
    / (eta_i(wi·h) + eta_o(wo·h))²``, ``h`` = ``−(eta_i wi + eta_o wo)`` normalized and
    turned to ``n``'s side; 0 unless ``(wi·h)mu_i > 0`` and ``(wo·h)mu_o > 0``.

    ``G2 = 1/(1 + Λ(|mu_i|) + Λ(|mu_o|))`` for both. As in :func:`_microfacet`, ``G2``
    over ``|mu_i||mu_o|`` is ``1/(m·inner)`` with ``m`` the larger cosine and
    ``inner = min + (|mu_o|/m)·|mu_i|Λ_i + (|mu_i|/m)·|mu_o|Λ_o`` (finite at grazing
    angles). The refraction denominator ``(eta_i(wi·h) + eta_o(wo·h))²`` equals
    ``|eta_i wi + eta_o wo|²`` (``h`` is that vector's direction up to sign), which is
    computed without cancellation.
    """
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if mu_i == 0.0 or mu_o == 0.0:
        return BLACK
    ndf, mu_lambda = distribution
    abs_i, abs_o = abs(mu_i), abs(mu_o)
    l_i = mu_lambda(abs_i, _sin2(n, wi))
    l_o = mu_lambda(abs_o, _sin2(n, wo))
    m = max(abs_i, abs_o)
    inner = min(abs_i, abs_o) + abs_o / m * l_i + abs_i / m * l_o
    eta_i = 1.0 if mu_i > 0.0 else eta
    eta_o = 1.0 if mu_o > 0.0 else eta

    if (mu_i > 0.0) == (mu_o > 0.0):
        # Reflection on wi's side: wi + wo is never 0 here (both on one side of n).
        h = _half_vector(wi, wo)
        if h is None:
            return BLACK
        d = ndf(abs(_cos(n, h)), _sin2(n, h))  # D(h) = D(−h): the flip changes nothing
        if mu_i > 0.0:
            r_i, e_i = eta, (eta - 1.0) * (eta + 1.0)
        else:  # (1/eta)² − 1 from eta itself
            r_i, e_i = 1.0 / eta, (1.0 - eta) * (1.0 + eta) / (eta * eta)
        fresnel, _ = _dielectric_fresnel(_cos_b(wi, wo), r_i, e_i)
        lobe = 0.0 if d == 0.0 else d / (4.0 * inner) / m  # D·G2/(4|mu_i||mu_o|)
        return _three(
            0.0 if ks_c == 0.0 or fresnel == 0.0 else ks_c * fresnel * lobe for ks_c in _rgb(ks)
        )

    # Transmission. At eta = 1 the rough lobe is the delta wo = −wi: (wi·h) and (wo·h)
    # are then equal, so the test below fails for every other pair; returned here at
    # once so that rounding near wo = −wi cannot let a value through.
    if eta == 1.0:
        return BLACK
    s = (
        eta_i * wi[0] + eta_o * wo[0],
        eta_i * wi[1] + eta_o * wo[1],
        eta_i * wi[2] + eta_o * wo[2],
    )
    if s == (0.0, 0.0, 0.0):
        return BLACK
    h = _normalize(s)
    cos_th = _cos(n, h)
    if cos_th == 0.0:
        return BLACK  # h cannot be turned to n's side: no microfacet refracts the pair
    if cos_th < 0.0:
        h, cos_th = (-h[0], -h[1], -h[2]), -cos_th
    c_i, c_o = _cos(wi, h), _cos(wo, h)
    if not (c_i * mu_i > 0.0 and c_o * mu_o > 0.0):
        return BLACK  # not a refraction through h (a microfacet seen from behind)
    d = ndf(cos_th, _sin2(n, h))
    # 1 − F(|wi·h|, eta_o/eta_i): for a refraction through h, g = (eta_o/eta_i)|wo·h|
    # (Snell's law), so the transmittance is taken from the two cosines.
    transmitted = _dielectric_transmittance(abs(c_i), abs(c_o), eta_i, eta_o)
    denominator = _length(s) ** 2  # (eta_i(wi·h) + eta_o(wo·h))²
    lobe = _product_quotient(
        (d, abs(c_i), abs(c_o), eta_o * eta_o, transmitted), (inner, m, denominator)
    )
    return _three(0.0 if kt_c == 0.0 else kt_c * lobe for kt_c in _rgb(kt))


def ggx_dielectric(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    ks: Colour,
    kt: Colour,
    eta: float,
    alpha: float,
) -> RGB:
    """A rough dielectric interface with GGX's ``D`` and ``Λ`` (see :func:`_dielectric`);
    nonzero on the whole sphere of ``wi`` and ``wo``."""
    return _dielectric(wi, wo, n, ks, kt, eta, _ggx_terms(alpha))


def beckmann_dielectric(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    ks: Colour,
    kt: Colour,
    eta: float,
    alpha: float,
) -> RGB:
    """A rough dielectric interface with Beckmann's ``D`` and ``Λ`` (see
    :func:`_dielectric`); nonzero on the whole sphere of ``wi`` and ``wo``."""
    return _dielectric(wi, wo, n, ks, kt, eta, _beckmann_terms(alpha))


_ENERGY_TABLE: list[list[list[list[float]]]] = []


def _energy_table() -> list[list[list[list[float]]]]:
    """``ggx_dielectric``'s total albedo ``E[side][i][j][k]``, the table embedded in the
    library (read once; its values are the data, the interpolation below is this
    module's own)."""
    if not _ENERGY_TABLE:
        from ._brdf_rs import ggx_dielectric_energy_table

        _ENERGY_TABLE.extend(ggx_dielectric_energy_table().astype(float).tolist())
    return _ENERGY_TABLE


def _cubic_weights(x: Any, last: int) -> list[tuple[int, Any]]:
    """Catmull-Rom nodes and weights about ``x`` on ``[0, last]`` (clamped); at the ends
    the missing outer node is the linear extrapolation of the inner two."""
    x = min(max(x, 0 * x), last + 0 * x)
    j = min(int(x), last - 1)
    w = x - j
    weights = [
        (2 * w**2 - w**3 - w) / 2,
        (3 * w**3 - 5 * w**2 + 2) / 2,
        (4 * w**2 - 3 * w**3 + w) / 2,
        (w**3 - w**2) / 2,
    ]
    if j == 0:
        weights = [0 * w, weights[1] + 2 * weights[0], weights[2] - weights[0], weights[3]]
    if j + 2 > last:
        weights = [weights[0], weights[1] - weights[3], weights[2] + 2 * weights[3], 0 * w]
    return list(zip([max(j - 1, 0), j, j + 1, min(j + 2, last)], weights, strict=True))


def dielectric_energy(
    mu_i: Any,
    sin_i: Any,
    alpha: Any,
    eta: Any,
    sqrt: Callable[[Any], Any] = math.sqrt,
    log: Callable[[Any], Any] = math.log,
) -> Any:
    """``E(|mu_i|, alpha, r_i)`` of ``ggx_dielectric_ms``'s table (docs/models.md): the
    total albedo of ``ggx_dielectric``'s white interface for light at ``mu_i = n·wi``
    (its sign the side: ``r_i = eta`` above, ``1/eta`` below; ``sin_i = |n × wi|``), 1 at
    ``eta = 1``.

    Linear in ``x = q^(1/4)/2 + (sqrt(t) + t)/4``, ``t = mu/(mu + alpha·sin_i)``,
    ``q = mu/(mu + w·sin_i)``, ``w = y/(alpha + y)``; Catmull-Rom in ``log alpha`` over
    [1e-3, 1] and in ``v = ln(1 + 2^50·y)/(2 ln(1 + 2^50·Y)) + y/(2Y)``,
    ``y = |ln eta|``, ``Y = ln 1e7``; held within the values blended. ``sqrt``, ``log``
    (and the arithmetic of the arguments) choose the precision: floats here, mpmath in
    the 50-digit reference."""
    if eta == 1:
        return 1 + 0 * eta
    table = _energy_table()
    nt, na, ns = len(table[0]), len(table[0][0]), len(table[0][0][0])
    side = table[0] if (mu_i > 0) == (eta > 1) else table[1]
    one = 1 + 0 * mu_i
    mu = min(abs(mu_i), one)
    sin = min(sin_i, one)
    alpha = min(max(alpha, 1e-3 + 0 * alpha), 1 + 0 * alpha)
    top = log(10_000_000 + 0 * eta)
    y = min(abs(log(eta)), top)
    t = mu / (mu + alpha * sin)
    q = mu * (alpha + y) / (mu * (alpha + y) + y * sin)
    x = (sqrt(sqrt(q)) / 2 + (sqrt(t) + t) / 4) * (nt - 1)
    x = min(max(x, 0 * x), nt - 1 + 0 * x)
    i = min(int(x), nt - 2)
    rows = [(i, 1 - (x - i)), (i + 1, x - i)]
    columns = _cubic_weights(log(alpha * 1000) / log(1000 + 0 * alpha) * (na - 1), na - 1)
    index = log(1 + 2**50 * y) / (2 * log(1 + 2**50 * top)) + y / (2 * top)
    depths = _cubic_weights(index * (ns - 1), ns - 1)
    total = 0 * mu
    values = []
    for a, wa in rows:
        for b, wb in columns:
            for c, wc in depths:
                v = side[a][b][c]
                values.append(v)
                total += wa * wb * wc * v
    return min(max(total, min(values) + 0 * mu), max(values) + 0 * mu)


def ggx_dielectric_ms(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    ks: Colour,
    kt: Colour,
    eta: float,
    alpha: float,
) -> RGB:
    """:func:`ggx_dielectric` divided by :func:`dielectric_energy` of ``wi``'s side
    (Turquin's scaling; docs/models.md)."""
    f = ggx_dielectric(wi, wo, n, ks=ks, kt=kt, eta=eta, alpha=alpha)
    n_unit, wi_unit = _normalize(n), _normalize(wi)
    mu_i = _dot(n_unit, wi_unit)
    e = dielectric_energy(mu_i, _length(_cross(n_unit, wi_unit)), alpha, eta)
    return _three(v / e for v in f)


# ---------------------------------------------------------------------------------------
# Sheen and cloth
# ---------------------------------------------------------------------------------------

#: Estevez & Kulla's fit of the Charlie sheen's ``Λ`` (their Table 1): the coefficients
#: ``(a, b, c, d, e)`` at roughness 1 and at roughness 0, as the paper's decimals.
_CHARLIE_AT_1 = ("21.5473", "3.82987", "0.19823", "-1.97760", "-4.32054")
_CHARLIE_AT_0 = ("25.3245", "3.32435", "0.16801", "-1.27393", "-4.85967")


def _charlie_lambda(mu: float, alpha: float) -> float:
    """The fitted ``Λ(μ)``: ``exp(L(μ))`` below 1/2, ``exp(2L(1/2) − L(1 − μ))`` above,
    with ``L(x) = a/(1 + b·x^c) + d·x + e`` blended with ``t = (1 − α)²``.

    ``L`` reaches 20 and ``exp`` turns its absolute error into ``Λ``'s relative error, so
    ``L`` is computed in 34-digit decimal arithmetic and only ``exp`` in floats."""
    with decimal.localcontext() as ctx:
        ctx.prec = 34
        t = (1 - decimal.Decimal(alpha)) ** 2
        a, b, c, d, e = (
            decimal.Decimal(p1) + t * (decimal.Decimal(p0) - decimal.Decimal(p1))
            for p1, p0 in zip(_CHARLIE_AT_1, _CHARLIE_AT_0, strict=True)
        )

        def fit(x: decimal.Decimal) -> decimal.Decimal:
            return a / (1 + b * x**c) + d * x + e

        x = decimal.Decimal(mu)
        big = fit(x) if mu < 0.5 else 2 * fit(decimal.Decimal("0.5")) - fit(1 - x)
        hi = float(big)
        return math.exp(hi) * (1.0 + float(big - decimal.Decimal(hi)))


def _charlie_ndf(alpha: float, sin2_th: float) -> float:
    """``D = (2 + 1/α)·sin(θh)^(1/α)/(2π)``, the sine's power as ``(sin²θh)^(1/(2α))``."""
    return (2.0 + 1.0 / alpha) * float(sin2_th ** (0.5 / alpha)) / (2.0 * math.pi)


def _ashikhmin_ndf(alpha: float, cos_th: float, sin2_th: float) -> float:
    """``D = (1 + 4·exp(−cot²θh/α²)/sin⁴θh)/(π(1 + 4α²))``; the Gaussian's share is 0
    where ``cot²θh/α²`` is beyond 700 (and at ``h = n``)."""
    a2 = alpha * alpha
    if sin2_th == 0.0:
        gaussian = 0.0
    else:
        x = cos_th * cos_th / (a2 * sin2_th)
        gaussian = 0.0 if x > 700.0 else 4.0 * math.exp(-x) / (sin2_th * sin2_th)
    return (1.0 + gaussian) / (math.pi * (1.0 + 4.0 * a2))


def _sheen(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    kd: Colour,
    ks: Colour,
    lobe: Callable[[float, float, float, float], float],
) -> RGB:
    """``kd/π + ks·lobe(mu_i, mu_o, cos_th, sin²θh)`` above the surface, 0 below."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    h = _half_vector(wi, wo)
    if h is None:
        return BLACK
    value = lobe(mu_i, mu_o, max(0.0, _cos(n, h)), _sin2(n, h))
    return _three(
        kd_c / math.pi + (0.0 if ks_c == 0.0 else ks_c * value)
        for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


def _neubelt(mu_i: float, mu_o: float) -> float:
    """Neubelt and Pettineo's visibility ``V = 1/(4(mu_i + mu_o − mu_i·mu_o))``."""
    return 1.0 / (4.0 * (mu_i + mu_o - mu_i * mu_o))


def charlie_sheen(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    alpha: float,
) -> RGB:
    """Estevez & Kulla's sheen: ``kd/π + ks·D·G2/(4 mu_i mu_o)``, the Charlie ``D`` and
    ``G2 = 1/(1 + Λ(mu_i) + Λ(mu_o))`` with their fitted ``Λ``."""

    def lobe(mu_i: float, mu_o: float, cos_th: float, sin2_th: float) -> float:
        # Divided by the larger cosine, then the smaller: no product of two tiny cosines
        # underflows to 0 before the quotient would overflow anyway.
        g = 1.0 + _charlie_lambda(mu_i, alpha) + _charlie_lambda(mu_o, alpha)
        return _charlie_ndf(alpha, sin2_th) / (4.0 * g * max(mu_i, mu_o)) / min(mu_i, mu_o)

    return _sheen(wi, wo, n, kd, ks, lobe)


def charlie_sheen_neubelt(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    alpha: float,
) -> RGB:
    """The Charlie ``D`` with Neubelt and Pettineo's visibility: ``kd/π + ks·D·V``."""

    def lobe(mu_i: float, mu_o: float, cos_th: float, sin2_th: float) -> float:
        return _charlie_ndf(alpha, sin2_th) * _neubelt(mu_i, mu_o)

    return _sheen(wi, wo, n, kd, ks, lobe)


def ashikhmin_cloth(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    alpha: float,
) -> RGB:
    """Ashikhmin's cloth ``D`` with Neubelt and Pettineo's visibility: ``kd/π + ks·D·V``."""

    def lobe(mu_i: float, mu_o: float, cos_th: float, sin2_th: float) -> float:
        return _ashikhmin_ndf(alpha, cos_th, sin2_th) * _neubelt(mu_i, mu_o)

    return _sheen(wi, wo, n, kd, ks, lobe)


def _zeltner_albedo(mu_o: float, alpha: float) -> float:
    """The paper's fit of the sheen layer's directional albedo ``R(mu_o, α)``, held at 0
    where it dips below (for α in about (0.041, 0.132))."""
    a = alpha
    s = a * (0.0206607 + 1.58491 * a) / (0.0379424 + a * (1.32227 + a))
    m = a * (-0.193854 + a * (-1.14885 + a * (1.7932 - 0.95943 * a * a))) / (0.046391 + a)
    o = a * (0.000654023 + (-0.0207818 + 0.119681 * a) * a) / (1.26264 + a * (-1.92021 + a))
    return max(0.0, math.exp(-0.5 * ((mu_o - m) / s) ** 2) / (s * math.sqrt(2.0 * math.pi)) + o)


def zeltner_sheen(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    alpha: float,
) -> RGB:
    """Zeltner et al.'s LTC sheen: ``kd/π + ks·R(mu_o, α)·D(wi)/mu_i``, the transformed
    cosine built in the view's frame as the paper writes it."""
    wi, wo, n = _frame(wi, wo, n)
    mu_i, mu_o = _cos(n, wi), _cos(n, wo)
    if not (mu_i > 0.0 and mu_o > 0.0):
        return BLACK
    tangential = (wo[0] - mu_o * n[0], wo[1] - mu_o * n[1], wo[2] - mu_o * n[2])
    if _length(tangential) > 0.0:
        x_axis = _normalize(tangential)
    else:  # wo = n: the lobe is symmetric about n (b = 0), any tangent serves
        helper = (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)
        x_axis = _normalize(_cross(helper, n))
    y_axis = _cross(n, x_axis)
    x, y, z = _dot(wi, x_axis), _dot(wi, y_axis), mu_i
    a = (
        (2.58126 * mu_o + 0.813703 * alpha)
        * alpha
        / (1.0 + 0.310327 * mu_o * mu_o + 2.60994 * mu_o * alpha)
    )
    b = (
        math.sqrt(max(0.0, 1.0 - mu_o))
        * (alpha - 1.0)
        * alpha**3
        / (0.0000254053 + 1.71228 * mu_o - 1.71506 * mu_o * alpha + 1.34174 * alpha * alpha)
    )
    # w' = M^-1 w; D(w) = D_o(w'/|w'|)·|M^-1|/|w'|^3 = max(z, 0)/π·(a/|w'|²)².
    length2 = (a * x + b * z) ** 2 + (a * y) ** 2 + z * z
    # D(wi)/mu_i with z = mu_i cancelled (z/π would underflow for a subnormal mu_i).
    lobe = _zeltner_albedo(mu_o, alpha) / math.pi * (a / length2) ** 2
    return _three(
        kd_c / math.pi + (0.0 if ks_c == 0.0 else ks_c * lobe)
        for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True)
    )


# ---------------------------------------------------------------------------------------
# Family B: scan-line shading terms s(l, v), including the light's cosine
# ---------------------------------------------------------------------------------------


def lambert_shading(
    wi: Sequence[float], wo: Sequence[float], n: Sequence[float], *, kd: Colour
) -> RGB:
    """Lambert shading: ``s = kd·max(n·l, 0)``."""
    l, _v, n = _frame(wi, wo, n)  # noqa: E741 - l is the source's name for the light
    n_dot_l = _cos(n, l)
    return _three(kd_c * max(n_dot_l, 0.0) for kd_c in _rgb(kd))


def oren_nayar_shading(
    wi: Sequence[float], wo: Sequence[float], n: Sequence[float], *, kd: Colour, sigma: float
) -> RGB:
    """Oren-Nayar shading: ``s = kd·clamp(n·l, 0, 1)·(A + B·G·sin a·tan b)``,
    ``G = max(0, cos(φi-φo))``; 0 for a light at ``n·l <= 0``."""
    l, v, n = _frame(wi, wo, n)  # noqa: E741 - l is the source's name for the light
    mu_i, mu_o = _cos(n, l), _cos(n, v)
    if mu_i <= 0.0:
        return BLACK  # clamp(n·l, 0, 1) = 0; skip tan b, which grows as n·l -> 0
    cos_phi = _cos_phi_difference(l, v, n)
    sin_i, sin_o = _length(_cross(n, l)), _length(_cross(n, v))
    shaded = _oren_nayar_factor(sigma, mu_i, mu_o, sin_i, sin_o, cos_phi, weight=min(1.0, mu_i))
    return _three(kd_c * shaded for kd_c in _rgb(kd))


def toon_diffuse(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    thresholds: Sequence[float],
    colors: Sequence[Colour],
) -> RGB:
    """Toon diffuse: colour ``c_j`` with ``j`` = how many thresholds are ``<= n·l``
    (signed ``n·l``; thresholds ascending, ``len(colors) = len(thresholds) + 1``)."""
    l, _v, n = _frame(wi, wo, n)  # noqa: E741 - l is the source's name for the light
    thresholds = [float(t) for t in thresholds]
    colors = list(colors)
    if len(colors) != len(thresholds) + 1:
        raise ValueError("toon_diffuse needs len(colors) == len(thresholds) + 1")
    n_dot_l = _cos(n, l)
    j = sum(1 for t in thresholds if t <= n_dot_l)
    return _rgb(colors[j])


def phong_specular(
    wi: Sequence[float], wo: Sequence[float], n: Sequence[float], *, ks: Colour, p: float
) -> RGB:
    """Phong specular: ``s = ks·clamp(v·r, 0, 1)^p``; 0 when ``n·l <= 0``."""
    l, v, n = _frame(wi, wo, n)  # noqa: E741 - l is the source's name for the light
    n_dot_l = _cos(n, l)
    if n_dot_l <= 0.0:
        return BLACK
    r = _mirror(l, n, n_dot_l)
    cos_vr, one_minus = _clamped_cosine(v, r)
    lobe = _pow(cos_vr, p, one_minus)
    return _three(ks_c * lobe for ks_c in _rgb(ks))


def blinn_specular(
    wi: Sequence[float], wo: Sequence[float], n: Sequence[float], *, ks: Colour, p: float
) -> RGB:
    """Blinn specular: ``s = ks·clamp(n·h, 0, 1)^p``; 0 when ``n·l <= 0`` or ``h`` is
    undefined (``l + v = 0``)."""
    l, v, n = _frame(wi, wo, n)  # noqa: E741 - l is the source's name for the light
    n_dot_l = _cos(n, l)
    if n_dot_l <= 0.0:
        return BLACK
    h = _half_vector(l, v)
    if h is None:
        return BLACK  # l = -v: h undefined, the model returns 0 (docs/models.md)
    cos_th, one_minus = _clamped_cosine(n, h)
    lobe = _pow(cos_th, p, one_minus)
    return _three(ks_c * lobe for ks_c in _rgb(ks))


def toon_specular(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    *,
    high: Colour,
    low: Colour,
    threshold: float,
) -> RGB:
    """Toon specular: ``high`` if ``v·r >= threshold`` else ``low``; 0 when ``n·l <= 0``."""
    l, v, n = _frame(wi, wo, n)  # noqa: E741 - l is the source's name for the light
    n_dot_l = _cos(n, l)
    if n_dot_l <= 0.0:
        return BLACK
    r = _mirror(l, n, n_dot_l)
    return _rgb(high) if _cos(v, r) >= threshold else _rgb(low)


def kajiya_kay(
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float],
    tangent: Sequence[float],
    *,
    kd: Colour,
    ks: Colour,
    p: float,
) -> RGB:
    """Kajiya-Kay hair (RTR 7.50): ``s = kd·sin_l + ks·max(0, sin_l·sin_v - (l·t)(v·t))^p``,
    ``sin_l = sqrt(max(0, 1 - (l·t)²))``, ``sin_v`` likewise; 0 when ``n·l <= 0``.

    ``t`` is the fibre tangent, normalized but not projected onto the tangent plane.
    Sines are ``|l × t|`` (``sqrt(1 - (l·t)²)`` keeps no digit of a sine below 1e-8).
    With ``A = (-l·t, sin_l)`` and ``B = (v·t, sin_v)`` the lobe's cosine is ``A·B`` and
    its complement ``|A - B|²/2 = (a² + b²)/2``, ``a = l·t + v·t``,
    ``b = sin_l - sin_v = a·((v - l)·t)/(sin_l + sin_v)``: accurate at the highlight's
    peak, where ``p = 1e6`` needs every digit of ``1 - A·B``. Where the two cosines cancel
    at ±1, ``a`` is the difference of their complements ``1 ∓ w·t = |w ∓ t|²/2``
    (accurate however close ``w`` is to ``±t``), elsewhere ``(l + v)·t``.
    """
    l, v, n = _frame(wi, wo, n)  # noqa: E741 - l is the source's name for the light
    t = _normalize(tangent)
    if _cos(n, l) <= 0.0:
        return BLACK
    l_dot_t, v_dot_t = _cos(l, t), _cos(v, t)
    sin_l, sin_v = _length(_cross(l, t)), _length(_cross(v, t))
    # sin_l·sin_v - (l·t)(v·t) is the cosine of an angle difference: at most 1 exactly.
    x = min(1.0, max(0.0, sin_l * sin_v - l_dot_t * v_dot_t))

    def half_square(u: Vector, s: float) -> float:
        d = (u[0] + s * t[0], u[1] + s * t[1], u[2] + s * t[2])
        return _dot(d, d) / 2.0

    if l_dot_t > 0.5 and v_dot_t < -0.5:
        a = half_square(v, 1.0) - half_square(l, -1.0)  # (1 + v·t) - (1 - l·t)
    elif l_dot_t < -0.5 and v_dot_t > 0.5:
        a = half_square(l, 1.0) - half_square(v, -1.0)
    else:
        a = _dot((l[0] + v[0], l[1] + v[1], l[2] + v[2]), t)
    sines = sin_l + sin_v
    b = a * _dot((v[0] - l[0], v[1] - l[1], v[2] - l[2]), t) / sines if sines > 0.0 else 0.0
    lobe = _pow(x, p, min(1.0, (a * a + b * b) / 2.0)) if x > 0.0 else _pow(0.0, p)
    return _three(kd_c * sin_l + ks_c * lobe for kd_c, ks_c in zip(_rgb(kd), _rgb(ks), strict=True))


# ---------------------------------------------------------------------------------------
# Registry and entry point
# ---------------------------------------------------------------------------------------

MODELS: dict[str, Callable[..., RGB]] = {
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
        ggx,
        beckmann,
        ggx_conductor,
        beckmann_conductor,
        ggx_f82,
        beckmann_f82,
        ggx_gen_schlick,
        beckmann_gen_schlick,
        ggx_dielectric,
        ggx_dielectric_ms,
        beckmann_dielectric,
        ward,
        ashikhmin_shirley,
        charlie_sheen,
        charlie_sheen_neubelt,
        ashikhmin_cloth,
        zeltner_sheen,
        lambert_shading,
        oren_nayar_shading,
        toon_diffuse,
        phong_specular,
        blinn_specular,
        toon_specular,
        kajiya_kay,
    )
}

_PHONG_DEFAULTS = {"kd": 0.0, "ks": 1.0, "p": 32.0}

DEFAULTS: dict[str, dict[str, object]] = {
    "lambert": {"kd": 0.5},
    "oren_nayar": {"kd": 0.5, "sigma": 0.5},
    "phong": dict(_PHONG_DEFAULTS),
    "modified_phong": dict(_PHONG_DEFAULTS),
    "normalized_phong": dict(_PHONG_DEFAULTS),
    "blinn_phong": dict(_PHONG_DEFAULTS),
    "modified_blinn_phong": dict(_PHONG_DEFAULTS),
    "normalized_blinn_phong": dict(_PHONG_DEFAULTS),
    "blinn_phong_fresnel": {"kd": 0.0, "ks": 0.04, "p": 32.0},
    "torrance_sparrow": {"kd": 0.0, "ks": 1.0, "p": 32.0, "eta": 1.5},
    "ggx": {"kd": 0.0, "ks": 1.0, "alpha": 0.5},
    "beckmann": {"kd": 0.0, "ks": 1.0, "alpha": 0.5},
    "ggx_conductor": {"kd": 0.0, "eta": 0.5, "k": 3.0, "alpha": 0.5},
    "beckmann_conductor": {"kd": 0.0, "eta": 0.5, "k": 3.0, "alpha": 0.5},
    "ggx_f82": {"kd": 0.0, "f0": 0.8, "f82": 1.0, "alpha": 0.5},
    "beckmann_f82": {"kd": 0.0, "f0": 0.8, "f82": 1.0, "alpha": 0.5},
    "ggx_gen_schlick": {"kd": 0.0, "f0": 0.04, "f90": 1.0, "exponent": 5.0, "alpha": 0.5},
    "beckmann_gen_schlick": {"kd": 0.0, "f0": 0.04, "f90": 1.0, "exponent": 5.0, "alpha": 0.5},
    "ggx_dielectric": {"ks": 1.0, "kt": 1.0, "eta": 1.5, "alpha": 0.5},
    "ggx_dielectric_ms": {"ks": 1.0, "kt": 1.0, "eta": 1.5, "alpha": 0.5},
    "beckmann_dielectric": {"ks": 1.0, "kt": 1.0, "eta": 1.5, "alpha": 0.5},
    "ward": {"kd": 0.0, "ks": 1.0, "alpha_x": 0.2, "alpha_y": 0.2},
    "ashikhmin_shirley": {"Rd": 0.5, "Rs": 0.05, "nu": 100.0, "nv": 100.0},
    "charlie_sheen": {"kd": 0.0, "ks": 1.0, "alpha": 0.5},
    "charlie_sheen_neubelt": {"kd": 0.0, "ks": 1.0, "alpha": 0.5},
    "ashikhmin_cloth": {"kd": 0.0, "ks": 1.0, "alpha": 0.5},
    "zeltner_sheen": {"kd": 0.0, "ks": 1.0, "alpha": 0.5},
    "lambert_shading": {"kd": 0.5},
    "oren_nayar_shading": {"kd": 0.5, "sigma": 0.5},
    "toon_diffuse": {},
    "phong_specular": {"ks": 1.0, "p": 32.0},
    "blinn_specular": {"ks": 1.0, "p": 32.0},
    "toon_specular": {"high": 1.0, "low": 0.0},
    "kajiya_kay": {"kd": 0.5, "ks": 0.5, "p": 32.0},
}

# Parameters without a default: the caller must give them.
_REQUIRED: dict[str, tuple[str, ...]] = {
    "toon_diffuse": ("thresholds", "colors"),
    "toon_specular": ("threshold",),
}

# Models that take the fibre tangent as a fourth positional argument.
_NEEDS_TANGENT = frozenset({"kajiya_kay"})
# Anisotropic models: a tangent when given (+x otherwise).
_TAKES_TANGENT = frozenset({"ward", "ashikhmin_shirley"})


def eval(
    model: str,
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float] = (0.0, 0.0, 1.0),
    tangent: Sequence[float] | None = None,
    **params: object,
) -> RGB:
    """Returns the RGB value of ``model`` for light direction ``wi`` and view ``wo``.

    Family A gives ``f(wi, wo)`` in 1/sr (no cosine); family B gives the shading term
    (with the light's cosine). ``tangent`` is used only by ``kajiya_kay`` (where it is
    required) and ignored otherwise. Parameters not given take :data:`DEFAULTS`.

    Raises ValueError for an unknown model, TypeError for an unknown or missing
    parameter (or a missing tangent for ``kajiya_kay``).
    """
    if model not in MODELS:
        raise ValueError(f"unknown model {model!r}; known: {', '.join(MODELS)}")
    required = _REQUIRED.get(model, ())
    unknown = sorted(set(params) - set(DEFAULTS[model]) - set(required))
    if unknown:
        raise TypeError(f"{model}: unknown parameter(s) {', '.join(unknown)}")
    missing = [name for name in required if name not in params]
    if missing:
        raise TypeError(f"{model}: missing required parameter(s) {', '.join(missing)}")
    kwargs = {**DEFAULTS[model], **params}
    function = MODELS[model]
    if model in _NEEDS_TANGENT:
        if tangent is None:
            raise TypeError(f"{model}: missing required argument 'tangent'")
        return function(wi, wo, n, tangent, **kwargs)
    if model in _TAKES_TANGENT:
        return function(wi, wo, n, tangent, **kwargs)
    return function(wi, wo, n, **kwargs)
