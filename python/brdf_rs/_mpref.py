"""High-precision (mpmath) reference for the family-A and family-B models of ``docs/models.md``.

This is the yardstick of the stress suite. It is written from ``docs/models.md`` alone,
independently of :mod:`brdf_rs.reference`, so the two can be checked against each other.

How it stays accurate everywhere, not only at ordinary inputs:

- Every input float is taken exactly. Each direction (``wi``, ``wo``, ``n``, ``tangent``)
  is scaled by a power of two to an integer vector (same direction, exact), and every
  quantity docs/models.md builds from directions is rewritten in terms of exact integer dot
  products: ``a = n·wi``, ``b = n·wo``, ``c = wi·wo``, ``|n|²``, ``|wi|²``, ... For example
  ``mu_i = a / sqrt(|n|²|wi|²)`` and ``r·wo = (2ab − |n|²c) / (|n|² sqrt(|wi|²|wo|²))``.
- So every decision is exact: the signs of ``mu_i``, ``mu_o`` (family-A gate, family-B
  specular gate), ``wi + wo = 0`` (h undefined), a zero tangent-plane projection, and the
  toon comparisons ``n·l ≥ t`` and ``v·r ≥ t`` (compared as ``x + y·sqrt(z)`` against 0
  with integers ``x, y, z``, squaring only when the signs differ).
- Every value is computed to full relative precision: a sum ``x·sqrt(p) + y·sqrt(q)`` whose
  terms have opposite signs is evaluated as ``(x²p − y²q) / (x·sqrt(p) − y·sqrt(q))`` with an
  exact integer numerator, which covers ``n·h`` near 0, ``1 − cos_b`` near ``wi = wo``,
  ``|wi + wo|`` near ``wi = −wo`` and the Kajiya-Kay ``sin_l·sin_v − (l·t)(v·t)``; sines
  come from ``|n × w|² = |n|²|w|² − (n·w)²`` (exact), never from ``1 − mu²``.
- The rest (powers, ``tan``, division, π) runs at ``dps`` decimal digits (50 by default),
  far beyond float64, so :func:`eval_float` is the correctly rounded float64 value.

Public functions: :func:`eval_mp`, :func:`eval_float` and :func:`condition`. Parameters
take the ``docs/models.md`` names and the package defaults; ranges are not checked (so that
:func:`condition` may step a parameter past its bound), only names and required ones are.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import mpmath
from mpmath import mpf
from mpmath.libmp import from_man_exp

from . import reference

__all__ = ["condition", "eval_float", "eval_mp"]

Colour = tuple[mpf, mpf, mpf]
IntVector = tuple[int, int, int]


# ---------------------------------------------------------------------------------------
# Exact inputs
# ---------------------------------------------------------------------------------------


def _man_exp(x: Any) -> tuple[int, int]:
    """Returns ``(m, e)`` with ``x == m·2^e`` exactly (``m`` signed) for a finite binary value."""
    if isinstance(x, mpf):
        if not mpmath.isfinite(x):
            raise ValueError(f"non-finite value {x}")
        sign, man, exp, _ = x._mpf_
        return (-man if sign else man), exp
    if isinstance(x, int):
        return x, 0
    value = float(x)
    if not math.isfinite(value):
        raise ValueError(f"non-finite value {value}")
    numerator, denominator = value.as_integer_ratio()
    return numerator, 1 - denominator.bit_length()


def _exact_mpf(x: Any) -> mpf:
    """The number ``x`` as an mpf, exactly (not rounded to the working precision)."""
    man, exp = _man_exp(x)
    return mpmath.mp.make_mpf(from_man_exp(man, exp))


def _integer_vector(v: Sequence[Any], name: str) -> IntVector:
    """``v`` times a power of two, as integers: the same direction, held exactly."""
    components = [_man_exp(x) for x in v]
    if len(components) != 3:
        raise ValueError(f"{name} must have 3 components, got {len(components)}")
    exponents = [exp for man, exp in components if man]
    if not exponents:
        raise ValueError(f"{name} has zero length")
    lowest = min(exponents)
    x, y, z = (man << (exp - lowest) if man else 0 for man, exp in components)
    return x, y, z


def _dot(u: IntVector, v: IntVector) -> int:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _colour(value: Any, name: str) -> Colour:
    """A colour parameter: a float (grey) or a 3-sequence, as three exact mpf values."""
    if hasattr(value, "__len__"):
        components = [_exact_mpf(x) for x in value]
        if len(components) != 3:
            raise ValueError(f"{name} must be a float or 3 values, got {len(components)}")
        return components[0], components[1], components[2]
    grey = _exact_mpf(value)
    return grey, grey, grey


# ---------------------------------------------------------------------------------------
# Sums of square roots, signed exactly and evaluated without cancellation
# ---------------------------------------------------------------------------------------


def _sign_of_roots(x: int, p: int, y: int, q: int) -> int:
    """The exact sign of ``x·sqrt(p) + y·sqrt(q)`` (integers, ``p, q ≥ 0``)."""
    sign_x = (x > 0) - (x < 0) if p else 0
    sign_y = (y > 0) - (y < 0) if q else 0
    if sign_x == 0 or sign_y == 0 or sign_x == sign_y:
        return sign_x or sign_y
    difference = x * x * p - y * y * q
    if difference == 0:
        return 0
    return sign_x if difference > 0 else sign_y


def _sum_of_roots(x: int, p: int, y: int, q: int) -> mpf:
    """``x·sqrt(p) + y·sqrt(q)`` to full relative precision (integers, ``p, q ≥ 0``)."""
    first = x * mpmath.sqrt(p)
    second = y * mpmath.sqrt(q)
    if x == 0 or y == 0 or p == 0 or q == 0 or (x > 0) == (y > 0):
        return first + second
    numerator = x * x * p - y * y * q
    if numerator == 0:
        return mpf(0)
    return numerator / (first - second)


def _per_channel(function: Callable[..., mpf], *colours: Colour) -> Colour:
    """``function`` applied channel by channel to the given colours."""
    red, green, blue = (function(*values) for values in zip(*colours, strict=True))
    return red, green, blue


def _power(x: mpf, p: mpf) -> mpf:
    """``x^p`` for ``x, p ≥ 0`` with ``0^0 = 1``."""
    if p == 0:
        return mpf(1)
    if x <= 0:
        return mpf(0)
    return mpmath.power(x, p)


# ---------------------------------------------------------------------------------------
# The geometry of one direction pair, in exact integer dot products
# ---------------------------------------------------------------------------------------


class _Geometry:
    """docs/models.md's notation for one (``wi``, ``wo``, ``n``[, tangent]) set.

    Integer attributes are exact; ``mpf`` properties are computed lazily at the working
    precision with full relative accuracy.
    """

    def __init__(self, wi: IntVector, wo: IntVector, n: IntVector) -> None:
        self.n = n
        self.n_n = _dot(n, n)
        self.i_i = _dot(wi, wi)
        self.o_o = _dot(wo, wo)
        self.a = _dot(n, wi)  # sign of mu_i, exactly
        self.b = _dot(n, wo)  # sign of mu_o, exactly
        self.c = _dot(wi, wo)
        self.i_o = self.i_i * self.o_o  # |wi|²|wo|²
        self.wi = wi
        self.wo = wo

    # cosines and sines of θi, θo ------------------------------------------------------

    @cached_property
    def mu_i(self) -> mpf:
        return self.a / mpmath.sqrt(self.n_n * self.i_i)

    @cached_property
    def mu_o(self) -> mpf:
        return self.b / mpmath.sqrt(self.n_n * self.o_o)

    @cached_property
    def cross_i(self) -> int:
        """``|n × wi|² = |n|²|wi|² − (n·wi)²``, exactly."""
        return self.n_n * self.i_i - self.a * self.a

    @cached_property
    def cross_o(self) -> int:
        return self.n_n * self.o_o - self.b * self.b

    @cached_property
    def sin_i(self) -> mpf:
        return mpmath.sqrt(mpf(self.cross_i) / (self.n_n * self.i_i))

    @cached_property
    def sin_o(self) -> mpf:
        return mpmath.sqrt(mpf(self.cross_o) / (self.n_n * self.o_o))

    @cached_property
    def cos_phi(self) -> mpf:
        """cos(φi − φo) between the tangent-plane projections; 0 if one has zero length."""
        if self.cross_i == 0 or self.cross_o == 0:
            return mpf(0)
        numerator = self.n_n * self.c - self.a * self.b
        return numerator / mpmath.sqrt(mpf(self.cross_i) * self.cross_o)

    # the mirror direction r ------------------------------------------------------------

    @cached_property
    def r_dot_wo_numerator(self) -> int:
        """``r·wo = this / (|n|² sqrt(|wi|²|wo|²))``."""
        return 2 * self.a * self.b - self.n_n * self.c

    @cached_property
    def r_dot_wo(self) -> mpf:
        return self.r_dot_wo_numerator / (self.n_n * mpmath.sqrt(self.i_o))

    # the half vector h -----------------------------------------------------------------

    @cached_property
    def h_defined(self) -> bool:
        """False exactly when ``wi + wo = 0`` (after normalization)."""
        return not (self.c < 0 and self.c * self.c == self.i_o)

    @cached_property
    def sum_length(self) -> mpf:
        """``T = |wi||wo| + wi·wo``; ``|ŵi + ŵo|² = 2T / (|wi||wo|)``."""
        return _sum_of_roots(1, self.i_o, self.c, 1)

    @cached_property
    def cos_th(self) -> mpf:
        """``n·h``, signed."""
        n_dot_sum = _sum_of_roots(self.a, self.o_o, self.b, self.i_i)  # a|wo| + b|wi|
        scale = mpmath.sqrt(self.n_n) * mpmath.root(self.i_o, 4) * mpmath.sqrt(2 * self.sum_length)
        return n_dot_sum / scale

    @cached_property
    def cos_b(self) -> mpf:
        """``wi·h = wo·h``."""
        return mpmath.sqrt(self.sum_length / (2 * mpmath.sqrt(self.i_o)))

    @cached_property
    def one_minus_cos_b(self) -> mpf:
        """``1 − cos_b`` without cancellation: ``(1 − cos_b²) / (1 + cos_b)``."""
        difference = _sum_of_roots(1, self.i_o, -self.c, 1)  # |wi||wo| − wi·wo
        one_minus_square = difference / (2 * mpmath.sqrt(self.i_o))
        return one_minus_square / (1 + self.cos_b)

    @cached_property
    def sin2_th(self) -> mpf:
        """``sin²θh = |n × h|²`` without cancellation near ``h = n``.

        With ``s = ŵi + ŵo``: ``|n × s|²·|wi|²|wo|² = X + Y·sqrt(|wi|²|wo|²)`` (integers
        ``X = |n×wi|²|wo|² + |n×wo|²|wi|²``, ``Y = 2(n×wi)·(n×wo)``) and
        ``|s|² = 2T/(|wi||wo|)``, so no digit is lost however close ``h`` is to ``n``.
        """
        cross_dot = self.n_n * self.c - self.a * self.b  # (n × wi)·(n × wo)
        numerator = _sum_of_roots(
            self.cross_i * self.o_o + self.cross_o * self.i_i, 1, 2 * cross_dot, self.i_o
        )
        # |n×s|²/(|n|²|s|²) = numerator / (i_o · n_n · 2T / sqrt(i_o))
        return numerator / (mpmath.sqrt(self.i_o) * self.n_n * 2 * self.sum_length)

    @cached_property
    def unit_h(self) -> tuple[mpf, mpf, mpf]:
        """``h`` as an mp vector (working precision)."""
        li, lo = mpmath.sqrt(self.i_i), mpmath.sqrt(self.o_o)
        s = [self.wi[k] / li + self.wo[k] / lo for k in range(3)]
        length = mpmath.sqrt(sum(x * x for x in s))
        return s[0] / length, s[1] / length, s[2] / length

    # exact comparisons against a threshold t -----------------------------------------

    def mu_i_at_least(self, threshold: mpf) -> bool:
        """``mu_i ≥ t``, decided exactly."""
        man, exp = _man_exp(threshold)
        # sign(a − t·sqrt(|n|²|wi|²)), both sides scaled by 2^max(0, −exp)
        x, y = (self.a << -exp, -man) if exp < 0 else (self.a, -(man << exp))
        return _sign_of_roots(x, 1, y, self.n_n * self.i_i) >= 0

    def r_dot_wo_at_least(self, threshold: mpf) -> bool:
        """``r·wo ≥ t``, decided exactly."""
        man, exp = _man_exp(threshold)
        numerator = self.r_dot_wo_numerator
        x, y = (
            (numerator << -exp, -man * self.n_n)
            if exp < 0
            else (numerator, -(man << exp) * self.n_n)
        )
        return _sign_of_roots(x, 1, y, self.i_o) >= 0


# ---------------------------------------------------------------------------------------
# The models, formula by formula from docs/models.md
# ---------------------------------------------------------------------------------------


def _oren_nayar_factor(g: _Geometry, sigma: mpf) -> mpf:
    """``A + B·max(0, cos(φi−φo))·sin a·tan b`` (needs ``max(mu_i, mu_o) > 0``)."""
    s2 = sigma * sigma
    big_a = 1 - mpf("0.5") * s2 / (s2 + mpf("0.33"))
    big_b = mpf("0.45") * s2 / (s2 + mpf("0.09"))
    azimuth = max(mpf(0), g.cos_phi)
    if azimuth == 0 or big_b == 0:
        return big_a
    # a = max(θi, θo) is the angle with the smaller cosine, b the one with the larger.
    if g.mu_i >= g.mu_o:
        sin_a, tan_b = g.sin_o, g.sin_i / g.mu_i
    else:
        sin_a, tan_b = g.sin_i, g.sin_o / g.mu_o
    return big_a + big_b * azimuth * sin_a * tan_b


def _lambert(g: _Geometry, kd: Colour) -> Colour:
    return _per_channel(lambda k: k / mpmath.pi, kd)


def _oren_nayar(g: _Geometry, kd: Colour, sigma: mpf) -> Colour:
    factor = _oren_nayar_factor(g, sigma)
    return _per_channel(lambda k: k / mpmath.pi * factor, kd)


def _cos_ar(g: _Geometry) -> mpf:
    return max(mpf(0), g.r_dot_wo)


def _phong(g: _Geometry, kd: Colour, ks: Colour, p: mpf) -> Colour:
    lobe = _power(_cos_ar(g), p) / g.mu_i
    return _per_channel(lambda d, s: d + s * lobe, kd, ks)


def _modified_phong(g: _Geometry, kd: Colour, ks: Colour, p: mpf) -> Colour:
    lobe = _power(_cos_ar(g), p)
    return _per_channel(lambda d, s: d + s * lobe, kd, ks)


def _normalized_phong(g: _Geometry, kd: Colour, ks: Colour, p: mpf) -> Colour:
    lobe = (p + 2) / (2 * mpmath.pi) * _power(_cos_ar(g), p)
    return _per_channel(lambda d, s: d / mpmath.pi + s * lobe, kd, ks)


def _blinn_lobe(g: _Geometry, p: mpf) -> mpf:
    """``cos_th^p``; 0 where h is undefined (cannot happen in family A)."""
    if not g.h_defined:
        return mpf(0)
    return _power(max(mpf(0), g.cos_th), p)


def _blinn_phong(g: _Geometry, kd: Colour, ks: Colour, p: mpf) -> Colour:
    lobe = _blinn_lobe(g, p) / g.mu_i
    return _per_channel(lambda d, s: d + s * lobe, kd, ks)


def _modified_blinn_phong(g: _Geometry, kd: Colour, ks: Colour, p: mpf) -> Colour:
    lobe = _blinn_lobe(g, p)
    return _per_channel(lambda d, s: d + s * lobe, kd, ks)


def _normalized_blinn_phong(g: _Geometry, kd: Colour, ks: Colour, p: mpf) -> Colour:
    lobe = (p + 8) / (8 * mpmath.pi) * _blinn_lobe(g, p)
    return _per_channel(lambda d, s: d / mpmath.pi + s * lobe, kd, ks)


def _blinn_phong_fresnel(g: _Geometry, kd: Colour, ks: Colour, p: mpf) -> Colour:
    lobe = (p + 8) / (8 * mpmath.pi) * _blinn_lobe(g, p)
    schlick = g.one_minus_cos_b**5
    return _per_channel(lambda d, f0: d / mpmath.pi + (f0 + (1 - f0) * schlick) * lobe, kd, ks)


def _torrance_sparrow(g: _Geometry, kd: Colour, ks: Colour, p: mpf, eta: mpf) -> Colour:
    distribution = (p + 2) / (2 * mpmath.pi) * _blinn_lobe(g, p)
    r0 = ((eta - 1) / (eta + 1)) ** 2
    fresnel = r0 + (1 - r0) * g.one_minus_cos_b**5
    masking = min(mpf(1), 2 * g.cos_th * g.mu_o / g.cos_b, 2 * g.cos_th * g.mu_i / g.cos_b)
    specular = distribution * fresnel * masking / (4 * g.mu_i * g.mu_o)
    return _per_channel(lambda d, s: d / mpmath.pi + s * specular, kd, ks)


# Beyond the sources: GGX, Beckmann, Ward, Ashikhmin-Shirley ---------------------------


#: exp(-x) for x beyond this is below 1e-43000: 0 in every float format even after a
#: division by the smallest cosines (1e-648 squared) the inputs can produce.
_DEAD = 1e5


def _schlick(g: _Geometry, f0: Colour) -> Colour:
    """Schlick's ``F0 + (1 − F0)(1 − cos_b)^5`` per channel."""
    weight = g.one_minus_cos_b**5
    return _per_channel(lambda f: f + (1 - f) * weight, f0)


def _tan2(cross: int, dot: int) -> mpf:
    """``tan²θ = |n × w|² / (n·w)²`` from the exact integers."""
    return mpf(cross) / (mpf(dot) * dot)


def _microfacet(
    g: _Geometry, kd: Colour, ks: Colour, ndf: mpf, lambda_i: mpf, lambda_o: mpf
) -> Colour:
    """``kd/π + D·G2·F/(4 mu_i mu_o)``, height-correlated ``G2 = 1/(1 + Λ(mu_i) + Λ(mu_o))``."""
    specular = ndf / ((1 + lambda_i + lambda_o) * 4 * g.mu_i * g.mu_o) if g.h_defined else mpf(0)
    fresnel = _schlick(g, ks)
    return _per_channel(lambda d, f: d / mpmath.pi + f * specular, kd, fresnel)


def _ggx_lambda(tan2: mpf, alpha: mpf) -> mpf:
    """``(−1 + sqrt(1 + α² tan²θ))/2``, as ``x / (2(1 + sqrt(1 + x)))``."""
    x = alpha * alpha * tan2
    return x / (2 * (1 + mpmath.sqrt(1 + x)))


def _ggx_ndf(cos_th: mpf, sin2_th: mpf, alpha: mpf) -> mpf:
    """``α²/(π(sin²θh + α² cos²θh)²)`` (= ``α²/(π(cos²θh(α² − 1) + 1)²)``)."""
    a2 = alpha * alpha
    return a2 / (mpmath.pi * (sin2_th + a2 * cos_th * cos_th) ** 2)


def _ggx(g: _Geometry, kd: Colour, ks: Colour, alpha: mpf) -> Colour:
    ndf = _ggx_ndf(g.cos_th, g.sin2_th, alpha)
    lambda_i = _ggx_lambda(_tan2(g.cross_i, g.a), alpha)
    lambda_o = _ggx_lambda(_tan2(g.cross_o, g.b), alpha)
    return _microfacet(g, kd, ks, ndf, lambda_i, lambda_o)


def _beckmann_lambda(cross: int, dot: int, alpha: mpf) -> mpf:
    """``(erf(c) − 1)/2 + exp(−c²)/(2c·sqrt(π))``, ``c = μ/(α sqrt(1 − μ²))``; 0 at ``μ = 1``."""
    if cross == 0:
        return mpf(0)
    c = dot / (alpha * mpmath.sqrt(cross))
    if c > 1e8:  # Λ < exp(-1e16): 0 to any precision that matters next to 1 + Λ
        return mpf(0)
    return -mpmath.erfc(c) / 2 + mpmath.exp(-c * c) / (2 * c * mpmath.sqrt(mpmath.pi))


def _beckmann_ndf(cos_th: mpf, sin2_th: mpf, alpha: mpf) -> mpf:
    """``exp(−tan²θh/α²)/(π α² cos⁴θh)``; 0 at ``cos_th = 0``."""
    a2 = alpha * alpha
    cos2 = cos_th * cos_th
    exponent = sin2_th / (cos2 * a2) if cos2 != 0 else mpf(0)
    if cos2 == 0 or exponent > _DEAD:
        return mpf(0)  # exp(-exponent) is below every float format, whatever divides it
    return mpmath.exp(-exponent) / (mpmath.pi * a2 * cos2 * cos2)


def _beckmann(g: _Geometry, kd: Colour, ks: Colour, alpha: mpf) -> Colour:
    ndf = _beckmann_ndf(g.cos_th, g.sin2_th, alpha)
    lambda_i = _beckmann_lambda(g.cross_i, g.a, alpha)
    lambda_o = _beckmann_lambda(g.cross_o, g.b, alpha)
    return _microfacet(g, kd, ks, ndf, lambda_i, lambda_o)


# Rough dielectrics: the whole sphere -----------------------------------------------------


def _dielectric_fresnel(c: mpf, r: mpf) -> mpf:
    """The exact unpolarized dielectric reflectance ``F(c, r)`` as docs/models.md writes
    it: ``g² = r² − 1 + c²``, ``F = 1`` if ``g² < 0`` (total internal reflection), else
    ``½((g − c)/(g + c))²(1 + ((c(g + c) − 1)/(c(g − c) + 1))²)``, at 40 more digits than
    the working precision (``g − c`` cancels as ``r → 1``)."""
    with mpmath.extradps(40):
        g2 = r * r - 1 + c * c
        if g2 < 0:
            return mpf(1)
        g = mpmath.sqrt(g2)
        if g + c == 0:
            return mpf(1)
        first = ((g - c) / (g + c)) ** 2
        second = ((c * (g + c) - 1) / (c * (g - c) + 1)) ** 2
        value = first * (1 + second) / 2
    return +value


def _index_integers(eta: mpf) -> tuple[int, int]:
    """``(A, B)``: integers with ``A/B = eta`` exactly (``eta`` a binary float): the two
    media's indices, 1 and ``eta``, as ``B`` and ``A`` over a common scale ``B``."""
    man, exp = _man_exp(eta)
    return (man << exp, 1) if exp >= 0 else (man, 1 << -exp)


def _dielectric(
    g: _Geometry,
    ks: Colour,
    kt: Colour,
    eta: mpf,
    alpha: mpf,
    ndf: Callable[[mpf, mpf, mpf], mpf],
    lambda_of: Callable[[int, int, mpf], mpf],
) -> Colour:
    """docs/models.md's rough dielectric, defined on the whole sphere.

    Reflection (``wi``, ``wo`` on one side): ``ks·F(|wi·h|, r_i)·D·G2/(4|mu_i||mu_o|)``.
    Transmission: ``kt·|wi·h||wo·h|/(|mu_i||mu_o|)·eta_o²(1 − F(|wi·h|, eta_o/eta_i))·D·G2
    / (eta_i(wi·h) + eta_o(wo·h))²`` with ``h`` along ``s = eta_i ŵi + eta_o ŵo`` turned
    to ``n``'s side. Every sign the definition branches on (the side of each direction,
    ``n·s``, ``wi·s``, ``wo·s``, ``s = 0``) is decided exactly from the integer inputs:
    with ``eta = A/B``, ``eta_i = I/B``, ``eta_o = O/B`` (``I, O`` each ``A`` or ``B``):

    - ``n·s·B|n||wi||wo| = I·(n·wi)|wo| + O·(n·wo)|wi|``,
    - ``wi·s·B|wi||wo| = I·|wi||wo| + O·(wi·wo)``, ``wo·s·B|wi||wo| = I·(wi·wo) + O·|wi||wo|``,
    - ``|s|²B²|wi||wo| = (I² + O²)|wi||wo| + 2IO·(wi·wo)``,

    each a sum ``x·sqrt(p) + y·sqrt(q)`` of integers. So at ``eta = 1`` the refraction
    test fails exactly for every pair (``wi·s`` and ``wo·s`` are then the same number),
    and ``(eta_i(wi·h) + eta_o(wo·h))² = |s|²`` keeps its digits where ``s`` is short.
    """
    zero = (mpf(0), mpf(0), mpf(0))
    if g.a == 0 or g.b == 0:
        return zero
    abs_mu_i, abs_mu_o = abs(g.mu_i), abs(g.mu_o)
    g2 = 1 / (1 + lambda_of(g.cross_i, abs(g.a), alpha) + lambda_of(g.cross_o, abs(g.b), alpha))
    above_i, above_o = g.a > 0, g.b > 0
    if above_i == above_o:
        # h = normalize(wi + wo), n·h of either sign: D depends on cos²θh and sin²θh only.
        ndf_value = ndf(g.cos_th, g.sin2_th, alpha)
        r_i = eta if above_i else 1 / eta
        fresnel = _dielectric_fresnel(g.cos_b, r_i)
        lobe = fresnel * ndf_value * g2 / (4 * abs_mu_i * abs_mu_o)
        return _per_channel(lambda k: k * lobe, ks)

    big_a, big_b = _index_integers(eta)
    index_i = big_b if above_i else big_a  # eta_i·B
    index_o = big_b if above_o else big_a  # eta_o·B
    # n·s, wi·s, wo·s and |s|², each times a positive factor (see above)
    n_s = (index_i * g.a, g.o_o, index_o * g.b, g.i_i)
    wi_s = (index_i, g.i_o, index_o * g.c, 1)
    wo_s = (index_o, g.i_o, index_i * g.c, 1)
    s_s = (index_i * index_i + index_o * index_o, g.i_o, 2 * index_i * index_o * g.c, 1)
    if _sign_of_roots(*s_s) == 0:
        return zero  # s = 0: wo = −wi with eta_i = eta_o, no h
    side = _sign_of_roots(*n_s)  # h = side·s/|s|
    if side == 0:
        return zero  # n·h = 0: h cannot be turned to n's side
    sign_a = 1 if above_i else -1
    sign_b = 1 if above_o else -1
    if side * _sign_of_roots(*wi_s) * sign_a <= 0 or side * _sign_of_roots(*wo_s) * sign_b <= 0:
        return zero  # (wi·h)·mu_i > 0 and (wo·h)·mu_o > 0 fail: not a refraction through h
    root_io = mpmath.sqrt(g.i_o)  # |wi||wo|
    s_scaled = _sum_of_roots(*s_s)  # |s|²·B²·|wi||wo|
    # |v·h| = |v·s|/|s| for v = wi, wo, n (each with its scale divided out)
    length = mpmath.sqrt(s_scaled * root_io)  # |s|·B·|wi||wo|
    cos_i = abs(_sum_of_roots(*wi_s)) / length
    cos_o = abs(_sum_of_roots(*wo_s)) / length
    cos_th = abs(_sum_of_roots(*n_s)) / (mpmath.sqrt(g.n_n) * length)
    with mpmath.extradps(40):
        sin2_th = +(1 - cos_th * cos_th)
    eta_i, eta_o = mpf(index_i) / big_b, mpf(index_o) / big_b
    denominator = s_scaled / (mpf(big_b) * big_b * root_io)  # (eta_i(wi·h) + eta_o(wo·h))²
    transmitted = 1 - _dielectric_fresnel(cos_i, eta_o / eta_i)
    lobe = (
        cos_i
        * cos_o
        / (abs_mu_i * abs_mu_o)
        * eta_o
        * eta_o
        * transmitted
        * ndf(cos_th, sin2_th, alpha)
        * g2
        / denominator
    )
    return _per_channel(lambda k: k * lobe, kt)


def _ggx_lambda_of(cross: int, dot: int, alpha: mpf) -> mpf:
    return _ggx_lambda(_tan2(cross, dot), alpha)


def _ggx_dielectric(g: _Geometry, ks: Colour, kt: Colour, eta: mpf, alpha: mpf) -> Colour:
    return _dielectric(g, ks, kt, eta, alpha, _ggx_ndf, _ggx_lambda_of)


def _ggx_dielectric_ms(g: _Geometry, ks: Colour, kt: Colour, eta: mpf, alpha: mpf) -> Colour:
    """``ggx_dielectric`` over the library's table of its white albedo at ``wi``, the
    table read exactly (its values are floats) and blended at the working precision."""
    e = reference.dielectric_energy(g.mu_i, g.sin_i, alpha, eta, mpmath.sqrt, mpmath.log)
    red, green, blue = _ggx_dielectric(g, ks, kt, eta, alpha)
    return (red / e, green / e, blue / e)


def _beckmann_dielectric(g: _Geometry, ks: Colour, kt: Colour, eta: mpf, alpha: mpf) -> Colour:
    return _dielectric(g, ks, kt, eta, alpha, _beckmann_ndf, _beckmann_lambda)


def _conductor_fresnel(g: _Geometry, eta: mpf, k: mpf) -> mpf:
    """pbrt-v4's ``FrComplex`` at ``cos_b``, as it is written (complex Snell's law, the
    average of the s- and p-reflectances), at 40 more digits than the working precision:
    the differences in ``r_s`` and ``r_p`` cancel as ``eta + i·k → 1``."""
    with mpmath.extradps(40):
        cos_i = g.cos_b
        sin2_i = g.one_minus_cos_b * (1 + cos_i)
        eta_c = mpmath.mpc(eta, k)
        cos_t = mpmath.sqrt(1 - sin2_i / (eta_c * eta_c))
        r_parl = (eta_c * cos_i - cos_t) / (eta_c * cos_i + cos_t)
        r_perp = (cos_i - eta_c * cos_t) / (cos_i + eta_c * cos_t)
        value = (abs(r_parl) ** 2 + abs(r_perp) ** 2) / 2
    return +value


def _conductor_channel(g: _Geometry, c: int, eta: Colour, k: Colour) -> mpf:
    return _conductor_fresnel(g, eta[c], k[c])


def _fresnel_variant(
    g: _Geometry, kd: Colour, lobe: Colour, fresnel: Callable[[int], mpf]
) -> Colour:
    """``kd/π + F·lobe`` per channel: ``lobe`` the base model's value at ``kd = 0``,
    ``ks = 1`` (F = 1), ``fresnel(channel)`` its Fresnel term."""
    red, green, blue = (
        d / mpmath.pi + (fresnel(c) * x if x != 0 else mpf(0))
        for c, (d, x) in enumerate(zip(kd, lobe, strict=True))
    )
    return red, green, blue


_ONE = (mpf(1), mpf(1), mpf(1))
_ZERO = (mpf(0), mpf(0), mpf(0))


def _with_fresnel(
    lobe: Callable[[_Geometry, Colour, Colour, mpf], Colour],
    fresnel: Callable[..., mpf],
) -> Callable[..., Colour]:
    """The model ``kd/π + F·lobe``: ``lobe`` (``_ggx`` or ``_beckmann``) at ``kd = 0``,
    ``ks = 1``, and ``F = fresnel(g, channel, **its parameters)``; called as
    ``(g, kd=..., alpha=..., **the Fresnel term's parameters)``."""

    def model(g: _Geometry, kd: Colour, alpha: mpf, **terms: Any) -> Colour:
        base = lobe(g, _ZERO, _ONE, alpha)
        return _fresnel_variant(g, kd, base, lambda c: fresnel(g, c, **terms))

    return model


def _f82_fresnel(g: _Geometry, f0: mpf, f82: mpf) -> mpf:
    """The F82-tint term: ``max(0, F_S(μ) − a·μ(1 − μ)^6)``, ``F_S`` Schlick's for ``f0`` and
    ``a = (1 − f82)·F_S(1/7)/((1/7)(6/7)^6)``, at ``μ = cos_b``."""
    mu_bar = mpf(1) / 7
    schlick_bar = f0 + (1 - f0) * (1 - mu_bar) ** 5
    a = (1 - f82) * schlick_bar / (mu_bar * (1 - mu_bar) ** 6)
    x = g.one_minus_cos_b
    value = f0 + (1 - f0) * x**5 - a * g.cos_b * x**6
    return max(mpf(0), value)


def _f82_channel(g: _Geometry, c: int, f0: Colour, f82: Colour) -> mpf:
    return _f82_fresnel(g, f0[c], f82[c])


def _gen_schlick_fresnel(g: _Geometry, f0: mpf, f90: mpf, exponent: mpf) -> mpf:
    """``f0 + (f90 − f0)(1 − cos_b)^exponent``."""
    return f0 + (f90 - f0) * _power(g.one_minus_cos_b, exponent)


def _gen_schlick_channel(g: _Geometry, c: int, f0: Colour, f90: Colour, exponent: mpf) -> mpf:
    return _gen_schlick_fresnel(g, f0[c], f90[c], exponent)


#: Estevez & Kulla's fit of the Charlie sheen's ``Λ``: ``(a, b, c, d, e)`` at roughness 1
#: and at roughness 0 (docs/models.md), taken as exact decimals.
_CHARLIE_AT_1 = ("21.5473", "3.82987", "0.19823", "-1.97760", "-4.32054")
_CHARLIE_AT_0 = ("25.3245", "3.32435", "0.16801", "-1.27393", "-4.85967")


def _charlie_lambda(mu: mpf, alpha: mpf) -> mpf:
    """``exp(L(μ))`` below 1/2, ``exp(2L(1/2) − L(1 − μ))`` from 1/2 on."""
    t = (1 - alpha) ** 2
    a, b, c, d, e = (
        (1 - t) * mpf(p1) + t * mpf(p0) for p1, p0 in zip(_CHARLIE_AT_1, _CHARLIE_AT_0, strict=True)
    )

    def fit(x: mpf) -> mpf:
        return a / (1 + b * x**c) + d * x + e

    if mu < mpf(1) / 2:
        return mpmath.exp(fit(mu))
    return mpmath.exp(2 * fit(mpf(1) / 2) - fit(1 - mu))


def _charlie_ndf(g: _Geometry, alpha: mpf) -> mpf:
    """``(2 + 1/α)·(sin²θh)^(1/(2α))/(2π)``."""
    return (2 + 1 / alpha) * g.sin2_th ** (1 / (2 * alpha)) / (2 * mpmath.pi)


def _neubelt(g: _Geometry) -> mpf:
    """``1/(4(mu_i + mu_o − mu_i·mu_o))``."""
    return 1 / (4 * (g.mu_i + g.mu_o - g.mu_i * g.mu_o))


def _sheen(g: _Geometry, kd: Colour, ks: Colour, lobe: mpf) -> Colour:
    specular = lobe if g.h_defined else mpf(0)
    return _per_channel(lambda d, k: d / mpmath.pi + k * specular, kd, ks)


def _charlie_sheen(g: _Geometry, kd: Colour, ks: Colour, alpha: mpf) -> Colour:
    g2 = 1 + _charlie_lambda(g.mu_i, alpha) + _charlie_lambda(g.mu_o, alpha)
    return _sheen(g, kd, ks, _charlie_ndf(g, alpha) / (4 * g.mu_i * g.mu_o * g2))


def _charlie_sheen_neubelt(g: _Geometry, kd: Colour, ks: Colour, alpha: mpf) -> Colour:
    return _sheen(g, kd, ks, _charlie_ndf(g, alpha) * _neubelt(g))


def _ashikhmin_cloth(g: _Geometry, kd: Colour, ks: Colour, alpha: mpf) -> Colour:
    a2 = alpha * alpha
    sin2 = g.sin2_th
    x = g.cos_th * g.cos_th / (a2 * sin2) if sin2 != 0 else mpf(0)
    gaussian = mpf(0) if sin2 == 0 or x > _DEAD else 4 * mpmath.exp(-x) / (sin2 * sin2)
    ndf = (1 + gaussian) / (mpmath.pi * (1 + 4 * a2))
    return _sheen(g, kd, ks, ndf * _neubelt(g))


def _zeltner_sheen(g: _Geometry, kd: Colour, ks: Colour, alpha: mpf) -> Colour:
    """Zeltner et al.'s LTC sheen, in the view's frame: ``wi = (sin_i·cos φ, sin_i·sin φ,
    mu_i)`` with φ the azimuth from ``wo``'s, and ``D(w) = z/π·(a/|M⁻¹w|²)²``."""
    a_, mu_o = alpha, g.mu_o
    s = (
        a_
        * (mpf("0.0206607") + mpf("1.58491") * a_)
        / (mpf("0.0379424") + a_ * (mpf("1.32227") + a_))
    )
    m = (
        a_
        * (
            mpf("-0.193854")
            + a_ * (mpf("-1.14885") + a_ * (mpf("1.7932") - mpf("0.95943") * a_ * a_))
        )
        / (mpf("0.046391") + a_)
    )
    o = (
        a_
        * (mpf("0.000654023") + (mpf("-0.0207818") + mpf("0.119681") * a_) * a_)
        / (mpf("1.26264") + a_ * (mpf("-1.92021") + a_))
    )
    r = max(mpf(0), mpmath.exp(-(((mu_o - m) / s) ** 2) / 2) / (s * mpmath.sqrt(2 * mpmath.pi)) + o)
    a = (
        (mpf("2.58126") * mu_o + mpf("0.813703") * a_)
        * a_
        / (1 + mpf("0.310327") * mu_o * mu_o + mpf("2.60994") * mu_o * a_)
    )
    b = (
        mpmath.sqrt(mpf(g.cross_o) / (g.n_n * g.o_o) / (1 + mu_o))
        * (a_ - 1)
        * a_**3
        / (
            mpf("0.0000254053")
            + mpf("1.71228") * mu_o
            - mpf("1.71506") * mu_o * a_
            + mpf("1.34174") * a_ * a_
        )
    )
    cos_phi = g.cos_phi
    x = g.sin_i * cos_phi
    y2 = g.sin_i**2 * (1 - cos_phi * cos_phi)
    z = g.mu_i
    length2 = (a * x + b * z) ** 2 + a * a * y2 + z * z
    lobe = r * (a / length2) ** 2 / mpmath.pi  # D(wi)/mu_i: z cancels
    return _per_channel(lambda d, k: d / mpmath.pi + k * lobe, kd, ks)


def _tangent_frame(g: _Geometry, tangent: IntVector | None) -> tuple[list[mpf], list[mpf]]:
    """``x``: the tangent (default +x) projected on the tangent plane and normalized;
    ``y = n × x``. A tangent along ``n`` has no projection: then Duff et al.'s unit vector
    perpendicular to ``n`` (as the kernels)."""
    length = mpmath.sqrt(g.n_n)
    n = [mpf(c) / length for c in g.n]
    t = tangent if tangent is not None else (1, 0, 0)
    cross = (
        g.n[1] * t[2] - g.n[2] * t[1],
        g.n[2] * t[0] - g.n[0] * t[2],
        g.n[0] * t[1] - g.n[1] * t[0],
    )
    if cross == (0, 0, 0):
        sign = -1 if n[2] < 0 else 1
        a = -1 / (sign + n[2])
        b = n[0] * n[1] * a
        x = [b, sign + n[1] * n[1] * a, -n[1]]
    else:
        t_dot_n = sum(t[k] * n[k] for k in range(3))
        p = [t[k] - t_dot_n * n[k] for k in range(3)]
        p_length = mpmath.sqrt(sum(c * c for c in p))
        x = [c / p_length for c in p]
    y = [n[1] * x[2] - n[2] * x[1], n[2] * x[0] - n[0] * x[2], n[0] * x[1] - n[1] * x[0]]
    return x, y


def _ward(
    g: _Geometry, tangent: IntVector | None, kd: Colour, ks: Colour, alpha_x: mpf, alpha_y: mpf
) -> Colour:
    lobe = mpf(0)
    if g.h_defined and g.cos_th != 0:
        if alpha_x == alpha_y:  # isotropic: (h·x)² + (h·y)² = sin²θh, whatever the frame
            numerator = g.sin2_th / (alpha_x * alpha_x)
        else:
            x, y = _tangent_frame(g, tangent)
            h = g.unit_h
            hx = sum(h[k] * x[k] for k in range(3)) / alpha_x
            hy = sum(h[k] * y[k] for k in range(3)) / alpha_y
            numerator = hx * hx + hy * hy
        exponent = numerator / (g.cos_th * g.cos_th)
        if exponent <= _DEAD:
            lobe = mpmath.exp(-exponent) / (
                4 * mpmath.pi * alpha_x * alpha_y * mpmath.sqrt(g.mu_i * g.mu_o)
            )
    return _per_channel(lambda d, s: d / mpmath.pi + s * lobe, kd, ks)


def _coupling(mu: mpf) -> mpf:
    """``1 − (1 − mu/2)^5`` as ``y(5 − 10y + 10y² − 5y³ + y⁴)``, ``y = mu/2``."""
    y = mu / 2
    return y * (5 + y * (-10 + y * (10 + y * (-5 + y))))


def _ashikhmin_shirley(
    g: _Geometry, tangent: IntVector | None, Rd: Colour, Rs: Colour, nu: mpf, nv: mpf
) -> Colour:
    specular = mpf(0)
    if g.h_defined:
        # a = h·u, b = h·v; near h = n they cancel: 40 more digits for them, and where
        # even those cancel (h within ~1e-90 of n) the exponent no longer matters and is
        # taken as (nu + nv)/2, as at h = n.
        a = b = mpf(0)
        if g.sin2_th != 0:
            with mpmath.extradps(40):
                u, v = _tangent_frame(g, tangent)
                h = _Geometry(g.wi, g.wo, g.n).unit_h
                a = sum(h[k] * u[k] for k in range(3))
                b = sum(h[k] * v[k] for k in range(3))
        if a == 0 and b == 0:
            exponent = (nu + nv) / 2
        else:
            exponent = (nu * a * a + nv * b * b) / (a * a + b * b)
        specular = (
            mpmath.sqrt((nu + 1) * (nv + 1))
            / (8 * mpmath.pi)
            * _power(max(mpf(0), g.cos_th), exponent)
            / (g.cos_b * max(g.mu_i, g.mu_o))
        )
    fresnel = _schlick(g, Rs)
    coupling = _coupling(g.mu_i) * _coupling(g.mu_o)
    return _per_channel(
        lambda rd, rs, f: f * specular + 28 * rd / (23 * mpmath.pi) * (1 - rs) * coupling,
        Rd,
        Rs,
        fresnel,
    )


def _lambert_shading(g: _Geometry, kd: Colour) -> Colour:
    cosine = max(mpf(0), g.mu_i)
    return _per_channel(lambda k: k * cosine, kd)


def _oren_nayar_shading(g: _Geometry, kd: Colour, sigma: mpf) -> Colour:
    if g.a <= 0:  # clamp(n·l, 0, 1) = 0, and the factor stays bounded as n·l → 0+
        return mpf(0), mpf(0), mpf(0)
    weight = min(mpf(1), g.mu_i) * _oren_nayar_factor(g, sigma)
    return _per_channel(lambda k: k * weight, kd)


def _toon_diffuse(g: _Geometry, thresholds: tuple[mpf, ...], colors: tuple[Colour, ...]) -> Colour:
    if len(colors) != len(thresholds) + 1:
        raise ValueError(
            f"toon_diffuse needs len(colors) == len(thresholds) + 1, "
            f"got {len(colors)} and {len(thresholds)}"
        )
    band = sum(1 for t in thresholds if g.mu_i_at_least(t))
    return colors[band]


def _phong_specular(g: _Geometry, ks: Colour, p: mpf) -> Colour:
    if g.a <= 0:
        return mpf(0), mpf(0), mpf(0)
    lobe = _power(min(mpf(1), max(mpf(0), g.r_dot_wo)), p)
    return _per_channel(lambda s: s * lobe, ks)


def _blinn_specular(g: _Geometry, ks: Colour, p: mpf) -> Colour:
    if g.a <= 0 or not g.h_defined:
        return mpf(0), mpf(0), mpf(0)
    lobe = _power(min(mpf(1), max(mpf(0), g.cos_th)), p)
    return _per_channel(lambda s: s * lobe, ks)


def _toon_specular(g: _Geometry, threshold: mpf, high: Colour, low: Colour) -> Colour:
    if g.a <= 0:
        return mpf(0), mpf(0), mpf(0)
    return high if g.r_dot_wo_at_least(threshold) else low


def _kajiya_kay(g: _Geometry, tangent: IntVector, kd: Colour, ks: Colour, p: mpf) -> Colour:
    if g.a <= 0:
        return mpf(0), mpf(0), mpf(0)
    t_t = _dot(tangent, tangent)
    l_t = _dot(g.wi, tangent)
    v_t = _dot(g.wo, tangent)
    cross_l = g.i_i * t_t - l_t * l_t  # |l × t|², so sin_l = sqrt(cross_l / (|l|²|t|²))
    cross_v = g.o_o * t_t - v_t * v_t
    sin_l = mpmath.sqrt(mpf(cross_l) / (g.i_i * t_t))
    # sin_l·sin_v − (l·t)(v·t) = (sqrt(cross_l·cross_v) − l_t·v_t) / (|t|² |l||v|)
    difference = _sum_of_roots(1, cross_l * cross_v, -l_t * v_t, 1)
    lobe = _power(max(mpf(0), difference / (t_t * mpmath.sqrt(g.i_o))), p)
    return _per_channel(lambda d, s: d * sin_l + s * lobe, kd, ks)


# ---------------------------------------------------------------------------------------
# The model table
# ---------------------------------------------------------------------------------------

_COLOUR = "colour"
_SCALAR = "scalar"
_SCALARS = "scalar list"
_COLOURS = "colour list"

_KINDS = {
    "kd": _COLOUR,
    "ks": _COLOUR,
    "kt": _COLOUR,
    "high": _COLOUR,
    "low": _COLOUR,
    "p": _SCALAR,
    "eta": _SCALAR,
    "sigma": _SCALAR,
    "threshold": _SCALAR,
    "alpha": _SCALAR,
    "k": _COLOUR,
    "f0": _COLOUR,
    "f82": _COLOUR,
    "f90": _COLOUR,
    "exponent": _SCALAR,
    "alpha_x": _SCALAR,
    "alpha_y": _SCALAR,
    "nu": _SCALAR,
    "nv": _SCALAR,
    "Rd": _COLOUR,
    "Rs": _COLOUR,
    "thresholds": _SCALARS,
    "colors": _COLOURS,
}


@dataclass(frozen=True)
class _Model:
    family: str
    function: Callable[..., Colour]
    defaults: dict[str, Any]
    required: tuple[str, ...] = ()
    tangent: bool = False  # required
    tangent_optional: bool = False
    #: Parameter kinds that differ from ``_KINDS`` (a conductor's ``eta`` is a colour).
    kinds: dict[str, str] = field(default_factory=dict)
    #: Defined on the whole sphere of ``wi`` and ``wo`` (a BSDF that transmits), not 0
    #: below the surface as the rest of family A.
    sphere: bool = False


_LOBE = {"kd": 0.0, "ks": 1.0, "p": 32.0}
_CONDUCTOR_DEFAULTS = {"kd": 0.0, "eta": 0.5, "k": 3.0, "alpha": 0.5}
_F82_DEFAULTS = {"kd": 0.0, "f0": 0.8, "f82": 1.0, "alpha": 0.5}
_GEN_SCHLICK_DEFAULTS = {"kd": 0.0, "f0": 0.04, "f90": 1.0, "exponent": 5.0, "alpha": 0.5}
_DIELECTRIC_DEFAULTS = {"ks": 1.0, "kt": 1.0, "eta": 1.5, "alpha": 0.5}

_MODELS: dict[str, _Model] = {
    "lambert": _Model("A", _lambert, {"kd": 0.5}),
    "oren_nayar": _Model("A", _oren_nayar, {"kd": 0.5, "sigma": 0.5}),
    "phong": _Model("A", _phong, _LOBE),
    "modified_phong": _Model("A", _modified_phong, _LOBE),
    "normalized_phong": _Model("A", _normalized_phong, _LOBE),
    "blinn_phong": _Model("A", _blinn_phong, _LOBE),
    "modified_blinn_phong": _Model("A", _modified_blinn_phong, _LOBE),
    "normalized_blinn_phong": _Model("A", _normalized_blinn_phong, _LOBE),
    "blinn_phong_fresnel": _Model("A", _blinn_phong_fresnel, {"kd": 0.0, "ks": 0.04, "p": 32.0}),
    "torrance_sparrow": _Model("A", _torrance_sparrow, {**_LOBE, "eta": 1.5}),
    "ggx": _Model("A", _ggx, {"kd": 0.0, "ks": 1.0, "alpha": 0.5}),
    "beckmann": _Model("A", _beckmann, {"kd": 0.0, "ks": 1.0, "alpha": 0.5}),
    "ggx_conductor": _Model(
        "A", _with_fresnel(_ggx, _conductor_channel), _CONDUCTOR_DEFAULTS, kinds={"eta": _COLOUR}
    ),
    "beckmann_conductor": _Model(
        "A",
        _with_fresnel(_beckmann, _conductor_channel),
        _CONDUCTOR_DEFAULTS,
        kinds={"eta": _COLOUR},
    ),
    "ggx_f82": _Model("A", _with_fresnel(_ggx, _f82_channel), _F82_DEFAULTS),
    "beckmann_f82": _Model("A", _with_fresnel(_beckmann, _f82_channel), _F82_DEFAULTS),
    "ggx_gen_schlick": _Model(
        "A", _with_fresnel(_ggx, _gen_schlick_channel), _GEN_SCHLICK_DEFAULTS
    ),
    "beckmann_gen_schlick": _Model(
        "A", _with_fresnel(_beckmann, _gen_schlick_channel), _GEN_SCHLICK_DEFAULTS
    ),
    "ggx_dielectric": _Model("A", _ggx_dielectric, _DIELECTRIC_DEFAULTS, sphere=True),
    "ggx_dielectric_ms": _Model("A", _ggx_dielectric_ms, _DIELECTRIC_DEFAULTS, sphere=True),
    "beckmann_dielectric": _Model("A", _beckmann_dielectric, _DIELECTRIC_DEFAULTS, sphere=True),
    "ward": _Model(
        "A",
        _ward,
        {"kd": 0.0, "ks": 1.0, "alpha_x": 0.2, "alpha_y": 0.2},
        tangent_optional=True,
    ),
    "ashikhmin_shirley": _Model(
        "A",
        _ashikhmin_shirley,
        {"Rd": 0.5, "Rs": 0.05, "nu": 100.0, "nv": 100.0},
        tangent_optional=True,
    ),
    "charlie_sheen": _Model("A", _charlie_sheen, {"kd": 0.0, "ks": 1.0, "alpha": 0.5}),
    "charlie_sheen_neubelt": _Model(
        "A", _charlie_sheen_neubelt, {"kd": 0.0, "ks": 1.0, "alpha": 0.5}
    ),
    "ashikhmin_cloth": _Model("A", _ashikhmin_cloth, {"kd": 0.0, "ks": 1.0, "alpha": 0.5}),
    "zeltner_sheen": _Model("A", _zeltner_sheen, {"kd": 0.0, "ks": 1.0, "alpha": 0.5}),
    "lambert_shading": _Model("B", _lambert_shading, {"kd": 0.5}),
    "oren_nayar_shading": _Model("B", _oren_nayar_shading, {"kd": 0.5, "sigma": 0.5}),
    "toon_diffuse": _Model("B", _toon_diffuse, {}, ("thresholds", "colors")),
    "phong_specular": _Model("B", _phong_specular, {"ks": 1.0, "p": 32.0}),
    "blinn_specular": _Model("B", _blinn_specular, {"ks": 1.0, "p": 32.0}),
    "toon_specular": _Model("B", _toon_specular, {"high": 1.0, "low": 0.0}, ("threshold",)),
    "kajiya_kay": _Model("B", _kajiya_kay, {"kd": 0.5, "ks": 0.5, "p": 32.0}, tangent=True),
}


def _spec(model: str) -> _Model:
    try:
        return _MODELS[model]
    except KeyError:
        raise ValueError(f"unknown model {model!r}; known: {', '.join(_MODELS)}") from None


def _raw_parameters(model: str, params: dict[str, Any]) -> dict[str, Any]:
    """The caller's parameters over the defaults, names checked, values untouched."""
    spec = _spec(model)
    unknown = sorted(set(params) - set(spec.defaults) - set(spec.required))
    if unknown:
        raise TypeError(f"{model}: unknown parameter(s) {', '.join(unknown)}")
    missing = [name for name in spec.required if name not in params]
    if missing:
        raise TypeError(f"{model}: missing required parameter(s) {', '.join(missing)}")
    return {**spec.defaults, **params}


def _convert(name: str, value: Any, kinds: dict[str, str]) -> Any:
    kind = kinds.get(name, _KINDS[name])
    if kind == _COLOUR:
        return _colour(value, name)
    if kind == _SCALAR:
        return _exact_mpf(value)
    if kind == _SCALARS:
        values = [value] if not hasattr(value, "__len__") else list(value)
        return tuple(_exact_mpf(x) for x in values)
    return tuple(_colour(x, name) for x in value)


def _evaluate(
    model: str,
    wi: Any,
    wo: Any,
    n: Any,
    tangent: Any,
    params: dict[str, Any],
    cache: dict[tuple[IntVector, ...], _Geometry] | None = None,
) -> Colour:
    """The model's RGB value at the current mpmath precision; ``params`` complete.

    ``cache`` (optional) keeps each direction set's geometry, whose derived quantities
    are computed once: :func:`condition` steps parameters without moving directions.
    """
    spec = _spec(model)
    vectors = (_integer_vector(wi, "wi"), _integer_vector(wo, "wo"), _integer_vector(n, "n"))
    geometry = None if cache is None else cache.get(vectors)
    if geometry is None:
        geometry = _Geometry(*vectors)
        if cache is not None:
            cache[vectors] = geometry
    zero = (mpf(0), mpf(0), mpf(0))
    if spec.family == "A" and not spec.sphere and not (geometry.a > 0 and geometry.b > 0):
        return zero
    values = {name: _convert(name, value, spec.kinds) for name, value in params.items()}
    if spec.tangent:
        if tangent is None:
            raise TypeError(f"{model}: missing required argument 'tangent'")
        values["tangent"] = _integer_vector(tangent, "tangent")
    elif spec.tangent_optional:
        values["tangent"] = None if tangent is None else _integer_vector(tangent, "tangent")
    red, green, blue = spec.function(geometry, **values)
    return +red, +green, +blue


# ---------------------------------------------------------------------------------------
# Public API
# ---------------------------------------------------------------------------------------


def eval_mp(
    model: str,
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float] = (0.0, 0.0, 1.0),
    tangent: Sequence[float] | None = None,
    *,
    dps: int = 50,
    **params: Any,
) -> tuple[mpf, mpf, mpf]:
    """Returns the RGB value of ``model`` at ``dps`` decimal digits, as three mpf.

    Inputs are taken exactly (any binary64 value, subnormal or huge, not normalized).
    Family A gives ``f(wi, wo)`` in 1/sr, family B the shading term ``s(l, v)``. Values
    beyond the float range (``1/mu_i`` models at tiny ``mu_i``) are returned as they are.

    Raises ValueError for an unknown model or a zero-length / non-finite vector, and
    TypeError for an unknown or missing parameter (or a missing tangent for
    ``kajiya_kay``).
    """
    with mpmath.workdps(dps):
        return _evaluate(model, wi, wo, n, tangent, _raw_parameters(model, params))


def _nearest_float(
    x: mpf, bits: int = 53, min_exp: int = -1074, max_value: float = sys.float_info.max
) -> float:
    """``x`` rounded to the nearest float of a binary format (ties to even, subnormals,
    overflow to inf), returned as a Python float: binary64 by default; ``bits``
    significand bits, ``min_exp`` the exponent of the smallest subnormal and
    ``max_value`` the largest finite value of another format (float32: 24, -149)."""
    if not mpmath.isfinite(x):
        return float(x)
    sign, man, exp, count = x._mpf_
    if man == 0 or exp + count < min_exp - 1:
        return -0.0 if sign and man else 0.0  # below half the smallest subnormal
    if exp + count > 1030:
        return -math.inf if sign else math.inf
    dropped = max(exp + count - bits, min_exp) - exp  # low bits below the format's quantum
    if dropped > 0:
        man, rest = divmod(man, 1 << dropped)
        half = 1 << (dropped - 1)
        if rest > half or (rest == half and man & 1):
            man += 1
        exp += dropped
    try:
        value = math.ldexp(man, exp)
    except OverflowError:
        value = math.inf
    if value > max_value:
        value = math.inf
    return -value if sign else value


def eval_float(
    model: str,
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float] = (0.0, 0.0, 1.0),
    tangent: Sequence[float] | None = None,
    **params: Any,
) -> tuple[float, float, float]:
    """Returns :func:`eval_mp` (50 digits) rounded to the nearest float64, per channel.

    Values beyond the float range become ``inf``.
    """
    red, green, blue = eval_mp(model, wi, wo, n, tangent, **params)
    return _nearest_float(red), _nearest_float(green), _nearest_float(blue)


def _leaf_paths(value: Any, path: tuple[Any, ...]) -> list[tuple[Any, ...]]:
    """Paths to every number inside nested dicts and sequences (the inputs to perturb)."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"unexpected string {value!r}")
    if hasattr(value, "__len__"):
        items = value.items() if isinstance(value, dict) else enumerate(value)
        paths = []
        for index, item in items:
            paths.extend(_leaf_paths(item, (*path, index)))
        return paths
    return [path]


def _replaced(value: Any, path: tuple[Any, ...], leaf: Any) -> Any:
    """A copy of nested ``value`` (lists/tuples/dicts) with the number at ``path`` set."""
    if not path:
        return leaf
    head, rest = path[0], path[1:]
    if isinstance(value, dict):
        return {**value, head: _replaced(value[head], rest, leaf)}
    items = list(value)
    items[head] = _replaced(items[head], rest, leaf)
    return items


def _leaf(value: Any, path: tuple[Any, ...]) -> Any:
    for key in path:
        value = value[key]
    return value


def condition(
    model: str,
    wi: Sequence[float],
    wo: Sequence[float],
    n: Sequence[float] = (0.0, 0.0, 1.0),
    tangent: Sequence[float] | None = None,
    *,
    dps: int = 60,
    reach: float | None = None,
    **params: Any,
) -> float:
    """Returns the relative condition number κ of ``model`` at these inputs.

    κ = max over channels of Σ_k |x_k·∂f/∂x_k| / |f| over every input float ``x_k``
    (each component of ``wi``, ``wo``, ``n``, of ``tangent`` when the model uses it, and of
    every parameter value). Each term is a one-sided difference under the relative steps
    ``x_k·(1 ± 1e-20)``, the larger side (so a kink counts its steeper side). The same
    differences at ``1e-30`` detect a discontinuity (a toon threshold, the horizon) or an
    infinite slope: the slope growing as the step shrinks gives ``inf``. A channel whose
    value is exactly 0 contributes 0 if every perturbation keeps it 0, else ``inf``.
    Inputs equal to 0 stay 0 under relative perturbation and are skipped.

    ``reach`` (a relative distance, e.g. 64 units in the last place of the inputs' float
    format) replaces the ``1e-30`` probe by steps of ``±reach``: a value that moves there
    by far more than its slope at ``1e-20`` explains (on the same side) has a
    discontinuity within rounding distance of the inputs, which a probe at the point
    itself cannot see (the horizon at ``mu = 1e-17`` under a general normal, a toon
    threshold a few ulps from ``n·l``); κ is then ``inf``. Otherwise the steeper of the
    two slopes counts, so a value that curves strongly within ``reach`` counts as steep.

    A float64 kernel can at best be off by about ``κ·2^-53`` relative.
    """
    spec = _spec(model)
    inputs: dict[str, Any] = {"wi": wi, "wo": wo, "n": n, **_raw_parameters(model, params)}
    if spec.tangent:
        if tangent is None:
            raise TypeError(f"{model}: missing required argument 'tangent'")
        inputs["tangent"] = tangent
    elif spec.tangent_optional and tangent is not None:
        inputs["tangent"] = tangent
    cache: dict[tuple[IntVector, ...], _Geometry] = {}

    def value(arguments: dict[str, Any]) -> Colour:
        arguments = dict(arguments)
        return _evaluate(
            model,
            arguments.pop("wi"),
            arguments.pop("wo"),
            arguments.pop("n"),
            arguments.pop("tangent", None),
            arguments,
            cache,
        )

    with mpmath.workdps(dps):
        base = value(inputs)
        fine_step = mpf(10) ** -20
        probe = mpf(10) ** -30 if reach is None else _exact_mpf(reach)
        totals = [mpf(0)] * 3
        moved_from_zero = [False] * 3
        for path in _leaf_paths(inputs, ()):
            x = _exact_mpf(_leaf(inputs, path))
            if x == 0:
                continue
            # slopes[step][side][channel], side 0: x·(1 + step), side 1: x·(1 − step)
            slopes = []
            for step in (fine_step, probe):
                sides = []
                for sign in (1, -1):
                    moved = value(_replaced(inputs, path, x * (1 + sign * step)))
                    slope = []
                    for channel in range(3):
                        if base[channel] == 0 and moved[channel] != 0:
                            moved_from_zero[channel] = True
                        slope.append(abs(moved[channel] - base[channel]) / step)
                    sides.append(slope)
                slopes.append(sides)
            for channel in range(3):
                fine = max(slopes[0][0][channel], slopes[0][1][channel])
                if base[channel] != 0:
                    floor = abs(base[channel]) * mpf(10) ** -10
                    for side in (0, 1):
                        fine_side = slopes[0][side][channel] if reach is not None else fine
                        if slopes[1][side][channel] > 10 * fine_side + floor:
                            return math.inf  # a jump (or an infinite slope) within the probe
                coarse = max(slopes[1][0][channel], slopes[1][1][channel])
                totals[channel] += max(fine, coarse)
        worst = 0.0
        for channel in range(3):
            if base[channel] == 0:
                if moved_from_zero[channel]:
                    return math.inf
                continue
            worst = max(worst, float(totals[channel] / abs(base[channel])))
        return worst
