"""The numerical stress suite: every model over an adversarial input set, against 50 digits.

:func:`stress` generates (seeded, not hand-listed) the inputs where floating-point
formulas break: grazing angles down to the smallest subnormal, directions a few units in
the last place (ulps) either side of the horizon, ``wi == wo``, ``wi == mirror(wo)``,
``wi + wo ≈ 0``, ``wi == n``, vectors from 1e-300 to 1e300 long (float32: 1e-38 to
1e38), components of wildly different magnitudes, subnormal components, non-unit normals,
exponents up to 1e8, ``eta`` at and next to 1, toon thresholds at ±1 and exactly at the
computed ``n·l``, plus random well-conditioned cases. Each case is evaluated by the Rust
kernel (:func:`brdf_rs.eval`, float64 or float32) and by :mod:`brdf_rs._mpref`, an
independent mpmath evaluation at 50 digits from the exact float inputs, which also gives
the case's condition number κ.

What the report counts, per model and dtype:

- NaN outputs (inputs are always finite and nonzero, parameters valid: any NaN is a bug)
  and infinities, each legitimate only where the exact value rounds to infinity in that
  dtype (the ``1/mu_i`` models at ``mu_i → 0+``);
- the error in ulps of the dtype (median, 99th percentile, max) and the relative error
  ``|got − exact| / max(|exact|, smallest normal)``, the maximum over RGB per case,
  separately for well-conditioned cases (``κ ≤ 4``: one rounding of every input moves
  the value by at most 4 ulps) and ill-conditioned ones, where it also reports the
  largest ``error / (κ·u)`` (``u`` the unit roundoff: ``2^-53``, ``2^-24``), i.e. how
  much of the error the inputs' own precision explains.

A discontinuity within 64 ulps of the inputs (the horizon under a tilted normal, a toon
band edge next to ``n·l``, ``wi + wo`` vanishing) gives ``κ = inf``: such a value is not
determined by its inputs' precision, and the case only counts for NaN and infinities.

The goals (:data:`GOALS`, checked by :attr:`StressReport.ok`): no NaN and no illegitimate
infinity anywhere; float64: 99th percentile ≤ 4 ulps on well-conditioned cases, relative
error ≤ 1e-12 except where ``8·κ·u`` is larger (then within it); float32: relative error
≤ 1e-5 on well-conditioned cases. ``ggx_ms`` and ``beckmann_ms`` interpolate embedded
tables and have no 50-digit reference: they count for NaN and infinities only.

``precision="fast"`` runs the same cases through ``brdf_rs.eval(..., precision="fast")``
and checks that tier's own goals (:data:`FAST_GOALS`): no NaN and no illegitimate
infinity; float64: relative error ≤ 1e-12 on well-conditioned cases and within
``max(1e-12, 8·κ·u)`` on ill-conditioned ones (no ulp goal); float32: relative error ≤ 2e-6
on well-conditioned cases.

mpmath is an optional dependency: ``pip install 'brdf-rs[stress]'``.
"""

from __future__ import annotations

import functools
import json
import math
import struct
import time
import zlib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from . import _api, _arrays, _spec

__all__ = ["FAST_GOALS", "GOALS", "StressReport", "stress"]

#: κ at most this: well-conditioned.
WELL_CONDITIONED = 4.0
#: An ill-conditioned case passes when its relative error is at most this many κ·u.
KAPPA_FACTOR = 8.0
#: How far (in ulps of the inputs' format) a discontinuity counts as within reach.
REACH_ULPS = 64

GOALS: dict[str, dict[str, float]] = {
    "float64": {
        "nan": 0,
        "illegitimate_inf": 0,
        "well_ulp_p99": 4.0,
        "rel_max": 1e-12,
        "kappa_factor": KAPPA_FACTOR,
    },
    "float32": {
        "nan": 0,
        "illegitimate_inf": 0,
        "well_rel_max": 1e-5,
    },
}

#: The goals of the fast tier (``precision="fast"``): relative errors, no ulp goal.
FAST_GOALS: dict[str, dict[str, float]] = {
    "float64": {
        "nan": 0,
        "illegitimate_inf": 0,
        "rel_max": 1e-12,
        "kappa_factor": KAPPA_FACTOR,
    },
    "float32": {
        "nan": 0,
        "illegitimate_inf": 0,
        "well_rel_max": 2e-6,
    },
}

#: The goals of each tier.
TIER_GOALS = {"accurate": GOALS, "fast": FAST_GOALS}


def _require_mpmath() -> Any:
    """Returns :mod:`brdf_rs._mpref`, or raises ImportError saying how to get mpmath."""
    try:
        from . import _mpref
    except ImportError as exc:  # mpmath missing
        raise ImportError(
            "brdf_rs.stress needs mpmath (the 50-digit reference): "
            "pip install 'brdf-rs[stress]' (or pip install 'mpmath>=1.3')"
        ) from exc
    return _mpref


# ---------------------------------------------------------------------------------------
# Float formats: rounding an exact value, ulps
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Format:
    name: str
    dtype: type[np.floating]
    bits: int  # significand bits
    min_exp: int  # exponent of the smallest subnormal
    pack: str  # struct codes: float, signed integer of the same width
    unpack: str

    @property
    def unit_roundoff(self) -> float:
        return 2.0**-self.bits

    @property
    def tiny(self) -> float:
        return float(np.finfo(self.dtype).tiny)

    @property
    def max(self) -> float:
        return float(np.finfo(self.dtype).max)

    def cast(self, x: float) -> float:
        """``x`` rounded to this format, as a Python float (exact)."""
        with np.errstate(over="ignore", under="ignore"):
            return float(self.dtype(x))

    def nearest(self, x: Any) -> float:
        """An exact mpmath value rounded to nearest (ties to even) in this format."""
        return float(_require_mpmath()._nearest_float(x, self.bits, self.min_exp, self.max))

    def ordinal(self, x: float) -> int:
        """The float's position on the line of representable values (±0 both 0)."""
        (i,) = struct.unpack(self.unpack, struct.pack(self.pack, x))
        return int(i if i >= 0 else -(i & ((1 << (8 * struct.calcsize(self.pack) - 1)) - 1)))

    def ulps(self, got: float, exact: float) -> float:
        if math.isnan(got) or math.isnan(exact):
            return math.inf
        if got == exact:
            return 0.0
        if math.isinf(got) or math.isinf(exact):
            return math.inf
        return float(abs(self.ordinal(got) - self.ordinal(exact)))

    def relative(self, got: float, exact: float) -> float:
        if got == exact:
            return 0.0
        if math.isnan(got) or math.isinf(got) or math.isinf(exact):
            return math.inf
        return abs(got - exact) / max(abs(exact), self.tiny)


_FORMATS = {
    "float64": _Format("float64", np.float64, 53, -1074, "<d", "<q"),
    "float32": _Format("float32", np.float32, 24, -149, "<f", "<i"),
}


# ---------------------------------------------------------------------------------------
# The adversarial set
# ---------------------------------------------------------------------------------------


@dataclass
class _Case:
    label: str
    wi: list[float]
    wo: list[float]
    n: list[float]
    tangent: list[float] | None
    params: dict[str, Any]


@dataclass(frozen=True)
class _Extremes:
    """The special magnitudes of a format that the geometry generators use."""

    grazing: tuple[float, ...]  # cosθ values at (and either side of) the horizon
    lengths: tuple[float, ...]  # vector lengths
    huge: float  # mixed-magnitude components: huge and tiny in one vector
    tiny: float
    subnormal_scale: float  # unit vector × this: every component subnormal
    power_of_two: float  # a large exact scale (same direction, another length)
    near_parallel: float  # tangent offsets whose |l × t|² underflows


_EXTREMES = {
    "float64": _Extremes(
        grazing=(0.0, -0.0, 5e-324, 1e-300, -1e-300, 1e-16, -1e-16, 1e-8),
        lengths=(1e-300, 1e-150, 1e-20, 1e20, 1e150, 1e300),
        huge=1e300,
        tiny=1e-300,
        subnormal_scale=2.0**-1060,
        power_of_two=2.0**300,
        near_parallel=1e-200,
    ),
    "float32": _Extremes(
        grazing=(0.0, -0.0, 1.4e-45, 1e-38, -1e-38, 1e-7, -1e-7, 1e-4),
        lengths=(1e-38, 1e-30, 1e-10, 1e10, 1e30, 1e38),
        huge=1e38,
        tiny=1e-38,
        subnormal_scale=2.0**-140,
        power_of_two=2.0**60,
        near_parallel=1e-25,
    ),
}

_Z = np.array([0.0, 0.0, 1.0])


def _unit(v: np.ndarray) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    v = v / np.max(np.abs(v))
    return np.asarray(v / np.linalg.norm(v))


class _Geometry:
    """Direction sets ``(label, wi, wo, n)`` (float64 arrays) for one format, seeded."""

    def __init__(self, rng: np.random.Generator, extremes: _Extremes) -> None:
        self.rng = rng
        self.x = extremes

    def random_unit(self) -> np.ndarray:
        return _unit(self.rng.normal(size=3))

    def above(self, n: np.ndarray, min_cos: float = 0.05) -> np.ndarray:
        """A random unit direction with ``n̂·d ≥ min_cos``."""
        nn = _unit(n)
        while True:
            d = self.random_unit()
            c = float(d @ nn)
            if c < 0:
                d, c = d - 2 * c * nn, -c
            if c >= min_cos:
                return d

    def frame(self, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Two unit vectors orthogonal to ``n`` (float64, so orthogonal to ~1e-16)."""
        nn = _unit(n)
        e1 = _unit(np.cross(nn, self.random_unit()))
        return e1, np.cross(nn, e1)

    def random_cases(
        self, count: int, family: str, transmission: bool = False
    ) -> list[tuple[str, Any, Any, Any]]:
        """Random directions above the surface; for family B a quarter of ``wo`` below it
        (shading terms), for a transmitting model half (its transmitted lobe)."""
        out = []
        for _ in range(count):
            n = _Z if self.rng.random() < 0.5 else self.random_unit()
            if self.rng.random() < 0.5:
                n = n * 10 ** self.rng.uniform(-3, 3)
            share = 0.5 if transmission else 0.25 if family == "B" else 0.0
            below = share > 0 and self.rng.random() < share
            wi = self.above(n) * 10 ** self.rng.uniform(-3, 3)
            wo = self.above(n) * (-1.0 if below else 1.0) * 10 ** self.rng.uniform(-3, 3)
            out.append(("random", wi, wo, n))
        return out

    def adversarial_cases(self) -> list[tuple[str, Any, Any, Any]]:
        x, rng = self.x, self.rng
        out: list[tuple[str, Any, Any, Any]] = []
        phi = rng.uniform(0, 2 * math.pi)
        c, s = math.cos(phi), math.sin(phi)
        for g in x.grazing:
            graze = np.array([c, s, g])
            out.append((f"grazing wi cos={g:g}", graze, self.above(_Z), _Z))
            out.append((f"grazing wo cos={g:g}", self.above(_Z), graze, _Z))
            # wi + wo = (0, 0, 2g): h = n however small g is
            out.append((f"grazing both opposite cos={g:g}", graze, np.array([-c, -s, g]), _Z))
            turn = np.array([math.cos(phi + 1e-3), math.sin(phi + 1e-3), g])
            out.append((f"grazing both forward cos={g:g}", graze, turn, _Z))
            back = np.array([-math.cos(phi + 1e-3), -math.sin(phi + 1e-3), g])
            out.append((f"grazing both near-opposite cos={g:g}", graze, back, _Z))
        # A few ulps either side of the horizon of a tilted normal.
        n = self.random_unit()
        e1, _ = self.frame(n)
        for k in (-3, -1, 1, 3):
            w = e1.copy()
            axis = int(np.argmax(np.abs(n)))
            for _ in range(abs(k)):
                w[axis] = np.nextafter(w[axis], math.copysign(math.inf, k * n[axis]))
            out.append((f"horizon {k:+d} ulp", w, self.above(n), n))
            out.append((f"horizon {k:+d} ulp (wo)", self.above(n), w, n))
        for n in (_Z, self.random_unit() * 3.0):
            tag = "n=z" if n is _Z else "tilted n"
            d = self.above(n)
            nn = _unit(n)
            out.append((f"wi == wo ({tag})", d, d.copy(), n))
            out.append((f"wi == wo, other lengths ({tag})", d, d * x.power_of_two, n))
            mirror = 2 * (d @ nn) * nn - d
            if n is _Z:
                mirror = np.array([-d[0], -d[1], d[2]])  # exact
            out.append((f"wi == mirror(wo) ({tag})", d, mirror, n))
            e1, e2 = self.frame(n)
            for delta in (1e-4, 1e-8, 1e-12):
                out.append((f"near mirror {delta:g} ({tag})", d, mirror + delta * e1, n))
            out.append((f"wi + wo = 0 ({tag})", d, -d, n))
            for delta in (1e-4, 1e-8, 1e-12):
                out.append((f"wi + wo ≈ 0, {delta:g} ({tag})", d, -d + delta * e2, n))
            out.append((f"wi == n ({tag})", n.copy(), d, n))
            out.append((f"wo == n ({tag})", d, n.copy(), n))
            out.append((f"wi == wo == n ({tag})", n.copy(), n.copy(), n))
        lengths = x.lengths
        for k, length in enumerate(lengths):
            other = lengths[-1 - k]
            d1, d2, nz = self.above(_Z), self.above(_Z), self.random_unit()
            nz[2] = abs(nz[2]) + 0.5
            out.append((f"lengths wi {length:g}", d1 * length, d2, _Z))
            out.append((f"lengths wi {length:g} wo {other:g}", d1 * length, d2 * other, _Z))
            out.append((f"lengths all {length:g}", d1 * length, d2 * length, nz * length))
            out.append((f"lengths n {length:g}", d1, d2, nz * length))
        big, small = x.huge, x.tiny
        out.append(
            ("mixed magnitudes", np.array([big, 0.0, small]), np.array([small, small, big]), _Z)
        )
        out.append(
            (
                "mixed magnitudes, both",
                np.array([big, small, small]),
                np.array([-big, 0, small]),
                _Z,
            )
        )
        out.append(
            ("mixed magnitudes n", self.above(_Z), self.above(_Z), np.array([small, 0, big]))
        )
        sub = x.subnormal_scale
        out.append(("subnormal components", self.above(_Z) * sub, self.above(_Z) * sub, _Z))
        out.append(
            ("subnormal components, all", self.above(_Z) * sub, self.above(_Z) * sub, _Z * sub)
        )
        return out


def _tangent_variants(
    rng: np.random.Generator, wi: np.ndarray, n: np.ndarray, extremes: _Extremes
) -> list[tuple[str, np.ndarray]]:
    """Fibre tangents for Kajiya-Kay: random, along wi, next to wi, along n, across wi."""
    perp = _unit(np.cross(wi, rng.normal(size=3)))
    return [
        ("t random", _unit(rng.normal(size=3))),
        ("t == wi", wi.copy()),
        ("t next to wi", _unit(wi) + extremes.near_parallel * perp),
        ("t == n", n.copy()),
        ("t ⟂ wi", perp),
    ]


# ---------------------------------------------------------------------------------------
# Parameters
# ---------------------------------------------------------------------------------------

_AT_N_DOT_L = "at n·l"  # a toon threshold placed at the computed n·l of the case
_AT_V_DOT_R = "at v·r"

_SPECIAL_VALUES: dict[str, list[Any]] = {
    "kd": [0.5, [0.3, 0.0, 1.0], 0.0],
    "ks": [1.0, [1.0, 0.0, 0.5]],
    "p": [32.0, 0.0, 0.5, 1.0, 1e4, 1e6, 1e8],
    "eta": [1.5, 1.0, 1.0 + 1e-12, 1.0 - 1e-12, 0.5, 2.5, 1e6],
    "k": [3.0, 0.0, 1e-8, 0.5, 1e4, [3.0, 0.0, 1e-3]],
    "f0": [0.8, 0.0, 1.0, 0.04, [0.95, 0.6, 0.1]],
    "f82": [0.7, 1.0, 0.0, [0.9, 0.3, 1.0]],
    "f90": [1.0, 0.0, 0.5, [1.0, 0.2, 0.8]],
    "exponent": [5.0, 1.0, 0.2, 1e-6, 40.0, 1e4],
    "sigma": [0.5, 0.0, 1e-8, math.pi / 2],
    "alpha": [0.5, 1e-7, 1e-3, 1.0, 1e7],
    "alpha_x": [0.2, 1e-7, 1.0],
    "alpha_y": [0.2, 1e-3, 1e7],
    "nu": [100.0, 0.0, 1.0, 1e4],
    "nv": [100.0, 0.0, 1e6],
    "Rd": [0.5, 0.0],
    "Rs": [0.05, 0.0, 1.0],
    "high": [1.0, [1.0, 0.5, 0.0]],
    "low": [0.0, 0.3],
    "threshold": [0.9, 1.0, -1.0, 0.0, _AT_V_DOT_R],
    "thresholds": [[0.0], [-1.0], [1.0], [-1.0, 0.0, 1.0], [0.5, 0.9], [_AT_N_DOT_L]],
}


def _parameter_variants(model: str) -> list[dict[str, Any]]:
    """The base parameter set, then one special value at a time (within the spec range)."""
    spec = _spec.specs()[model]
    base: dict[str, Any] = {}
    alternatives: list[tuple[str, Any]] = []
    # A colour list sized by another list (a toon ramp's band colours, one more than its
    # thresholds) is filled in to match each variant's list, below.
    sized_by = {p["name"]: p["one_more_than"] for p in spec["params"] if p["one_more_than"]}
    for p in spec["params"]:
        name = p["name"]
        if name in sized_by:
            continue
        values = _SPECIAL_VALUES.get(name)
        if values is None:
            values = [p["default"]]
        allowed = []
        for v in values:
            numbers = v if isinstance(v, list) else [v]
            if all(isinstance(x, str) or _spec.admits(model, name, float(x)) for x in numbers):
                allowed.append(v)
        base[name] = allowed[0]
        alternatives.extend((name, v) for v in allowed[1:])
    variants = [base] + [{**base, name: value} for name, value in alternatives]
    for name, other in sized_by.items():
        for v in variants:
            k = len(v[other])
            v[name] = [[0.1 * (j + 1), 0.05 * j, 1.0 - 0.1 * j] for j in range(k + 1)]
    return variants


def _normalized(v: Sequence[float], dtype: type[np.floating]) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    a = a / np.max(np.abs(a))
    return np.asarray((a / np.linalg.norm(a)).astype(dtype))


def _resolve(params: dict[str, Any], case: _Case, fmt: _Format) -> dict[str, Any]:
    """Places thresholds marked "at n·l" / "at v·r" at the case's value, computed in the
    format (what a kernel computes, give or take its rounding), and rounds every
    parameter to the format (float32 kernels see float32 parameters)."""
    out: dict[str, Any] = {}
    n = _normalized(case.n, fmt.dtype)
    wi = _normalized(case.wi, fmt.dtype)
    wo = _normalized(case.wo, fmt.dtype)
    n_dot_l = float(np.dot(n, wi))
    r = (2 * n_dot_l) * n - wi
    v_dot_r = float(np.dot(wo, r.astype(fmt.dtype)))

    def fit(x: Any) -> float:
        """A threshold: the marker resolved, clipped to the valid [-1, 1]."""
        x = {_AT_N_DOT_L: n_dot_l, _AT_V_DOT_R: v_dot_r}.get(x, x)
        return fmt.cast(min(1.0, max(-1.0, float(x))))

    for name, value in params.items():
        if name in ("thresholds", "threshold"):
            values = [fit(x) for x in (value if isinstance(value, list) else [value])]
            out[name] = sorted(values) if name == "thresholds" else values[0]
        elif name == "colors":
            out[name] = [[fmt.cast(x) for x in c] for c in value]
        elif isinstance(value, list):
            out[name] = [fmt.cast(x) for x in value]
        else:
            out[name] = fmt.cast(value)
    if fmt.name == "float32" and "sigma" in out and out["sigma"] > math.pi / 2:
        out["sigma"] = float(np.nextafter(np.float32(math.pi / 2), np.float32(0)))
    return out


def _cases(model: str, fmt: _Format, quick: bool, seed: int) -> list[_Case]:
    """The model's stress cases in this format: random and adversarial geometry, each
    paired with a few parameter variants (rotating, so every variant appears), and every
    variant on a few anchor geometries."""
    spec = _spec.specs()[model]
    rng = np.random.default_rng([seed, zlib.crc32(f"{model}/{fmt.name}".encode())])
    extremes = _EXTREMES[fmt.name]
    geometry = _Geometry(rng, extremes)
    variants = _parameter_variants(model)
    # A transmitting model's exact Fresnel term leaves few random directions
    # well-conditioned (κ ≤ 4): its quick run takes more of them, so that some are.
    transmits = bool(spec.get("transmission"))
    randoms = geometry.random_cases(
        (12 if transmits else 3) if quick else 60, spec["family"], transmits
    )
    adversarial = geometry.adversarial_cases()
    pairs: list[tuple[tuple[str, Any, Any, Any], dict[str, Any]]] = []
    if quick:
        # A stratified sample: categories rotate with the model, so that the quick runs
        # over all models between them cover every category and every variant.
        offset = zlib.crc32(model.encode())
        picks = [adversarial[(offset + 7 * k) % len(adversarial)] for k in range(6)]
        for k, g in enumerate(randoms + picks):
            pairs.append((g, variants[(offset + k) % len(variants)]))
    else:
        for k, g in enumerate(randoms):
            pairs.append((g, variants[k % len(variants)]))
        for k, g in enumerate(adversarial):
            pairs.append((g, variants[0]))
            pairs.append((g, variants[(k + 1) % len(variants)]))
            if len(variants) > 2:
                pairs.append((g, variants[(k + 1 + len(variants) // 2) % len(variants)]))
        anchors = [randoms[0], *(a for a in adversarial if a[0].startswith("near mirror 1e-08"))]
        anchors += [a for a in adversarial if a[0] == "grazing both forward cos=1e-300"]
        for g in anchors:
            pairs.extend((g, v) for v in variants[1:])
    cases = []
    for (label, wi, wo, n), params in pairs:
        tangents: list[tuple[str, Any]] = [("", None)]
        if spec["tangent"]:
            options = _tangent_variants(rng, wi, n, extremes)
            tangents = [options[0]] if label == "random" else options[: 2 if quick else 5]
        elif spec.get("tangent_optional") and rng.random() < 0.5:
            tangents = [("t random", _unit(rng.normal(size=3)))]
        for tag, t in tangents:
            case = _Case(
                label=f"{label}, {tag}" if tag else label,
                wi=[fmt.cast(v) for v in wi],
                wo=[fmt.cast(v) for v in wo],
                n=[fmt.cast(v) for v in n],
                tangent=None if t is None else [fmt.cast(v) for v in t],
                params={},
            )
            vectors = [case.wi, case.wo, case.n] + ([case.tangent] if case.tangent else [])
            if not all(any(c != 0 for c in v) and all(map(math.isfinite, v)) for v in vectors):
                continue  # a vector that rounded to zero (or overflowed) in this format
            case.params = _resolve(params, case, fmt)
            cases.append(case)
    return cases


# ---------------------------------------------------------------------------------------
# Evaluation and measurement
# ---------------------------------------------------------------------------------------


@dataclass
class _Result:
    case: _Case
    got: tuple[float, float, float]
    exact: tuple[float, float, float] | None  # rounded to the format; None: no reference
    kappa: float | None
    ulps: float
    rel: float
    nan: bool
    inf: int
    inf_legitimate: int
    error: str | None = None


def _kernel(
    model: str, case: _Case, fmt: _Format, precision: str = "accurate"
) -> tuple[float, float, float]:
    def arr(v: Any) -> np.ndarray | None:
        return None if v is None else np.asarray(v, dtype=fmt.dtype)

    params = dict(case.params)
    value = _api.eval(
        model,
        arr(case.wi),
        arr(case.wo),
        arr(case.n),
        tangent=arr(case.tangent),
        precision=precision,
        **params,
    )
    red, green, blue = (float(x) for x in value)
    return red, green, blue


def _measure(
    model: str,
    case: _Case,
    fmt: _Format,
    mpref: Any,
    evaluate: Callable[[str, _Case, _Format], tuple[float, float, float]] = _kernel,
) -> _Result:
    try:
        got = evaluate(model, case, fmt)
    except (ValueError, TypeError) as exc:
        nans = (math.nan, math.nan, math.nan)
        return _Result(case, nans, None, None, math.inf, math.inf, False, 0, 0, str(exc))
    nan = any(math.isnan(g) for g in got)
    inf = sum(math.isinf(g) for g in got)
    if mpref is None or model not in mpref._MODELS:
        return _Result(case, got, None, None, math.nan, math.nan, nan, inf, 0)
    exact_mp = mpref.eval_mp(model, case.wi, case.wo, case.n, case.tangent, **case.params)
    exact = tuple(fmt.nearest(x) for x in exact_mp)
    legit = sum(math.isinf(g) and g == e for g, e in zip(got, exact, strict=True))
    kappa = mpref.condition(
        model,
        case.wi,
        case.wo,
        case.n,
        case.tangent,
        dps=40,
        reach=REACH_ULPS * fmt.unit_roundoff * 2,
        **case.params,
    )
    ulps = max(fmt.ulps(g, e) for g, e in zip(got, exact, strict=True))
    rel = max(fmt.relative(g, e) for g, e in zip(got, exact, strict=True))
    return _Result(case, got, exact, kappa, ulps, rel, nan, inf, legit)  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------
# The report
# ---------------------------------------------------------------------------------------


@dataclass
class ErrorStats:
    """Errors over a set of cases: ulps (median, 99th percentile, max) and relative."""

    cases: int = 0
    ulp_median: float = 0.0
    ulp_p99: float = 0.0
    ulp_max: float = 0.0
    rel_max: float = 0.0
    kappa_max: float = 0.0

    @classmethod
    def of(cls, results: Sequence[_Result]) -> ErrorStats:
        if not results:
            return cls()
        ulps = np.array([r.ulps for r in results])
        return cls(
            cases=len(results),
            ulp_median=float(np.percentile(ulps, 50, method="higher")),
            ulp_p99=float(np.percentile(ulps, 99, method="higher")),
            ulp_max=float(ulps.max()),
            rel_max=max(r.rel for r in results),
            kappa_max=max(r.kappa for r in results if r.kappa is not None),
        )


@dataclass
class ModelSummary:
    """One model in one dtype: counts, errors and the goals it misses."""

    model: str
    dtype: str
    reference: bool
    cases: int
    nan: int
    inf: int
    inf_legitimate: int
    rejected: int
    well: ErrorStats
    ill: ErrorStats
    discontinuous: int  # κ = inf: a jump within rounding distance
    worst_kappa_ratio: float  # max over ill, finite κ of rel / (κ·u)
    failures: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.failures


def _summarize(
    model: str, fmt: _Format, results: list[_Result], precision: str = "accurate"
) -> ModelSummary:
    reference = any(r.exact is not None for r in results)
    measured = [r for r in results if r.exact is not None and r.error is None]
    well = [r for r in measured if r.kappa is not None and r.kappa <= WELL_CONDITIONED]
    ill = [r for r in measured if r.kappa is not None and WELL_CONDITIONED < r.kappa < math.inf]
    discontinuous = sum(r.kappa == math.inf for r in measured)
    u = fmt.unit_roundoff
    ratio = max((r.rel / (float(r.kappa or 0.0) * u) for r in ill), default=0.0)
    summary = ModelSummary(
        model=model,
        dtype=fmt.name,
        reference=reference,
        cases=len(results),
        nan=sum(r.nan for r in results),
        inf=sum(r.inf for r in results),
        inf_legitimate=sum(r.inf_legitimate for r in results),
        rejected=sum(r.error is not None for r in results),
        well=ErrorStats.of(well),
        ill=ErrorStats.of(ill),
        discontinuous=discontinuous,
        worst_kappa_ratio=ratio,
    )
    f = summary.failures
    if summary.rejected:
        f.append(f"{summary.rejected} valid case(s) rejected")
    if summary.nan:
        f.append(f"{summary.nan} NaN output(s)")
    bad_inf = summary.inf - summary.inf_legitimate
    if bad_inf:
        f.append(f"{bad_inf} illegitimate infinit{'y' if bad_inf == 1 else 'ies'}")
    goals = TIER_GOALS[precision]
    if fmt.name == "float64":
        goal = goals["float64"]
        if "well_ulp_p99" in goal and summary.well.ulp_p99 > goal["well_ulp_p99"]:
            f.append(
                f"well-conditioned p99 {summary.well.ulp_p99:g} ulp > {goal['well_ulp_p99']:g}"
            )
        over = [
            r
            for r in well + ill
            if r.rel > max(goal["rel_max"], goal["kappa_factor"] * r.kappa * u)  # type: ignore[operator]
        ]
        if over:
            worst = max(over, key=lambda r: r.rel)
            f.append(
                f"{len(over)} case(s) with relative error > max(1e-12, 8·κ·u), worst "
                f"{worst.rel:.3g} at κ = {worst.kappa:.3g} ({worst.case.label})"
            )
    else:
        goal = goals["float32"]
        if summary.well.rel_max > goal["well_rel_max"]:
            f.append(
                f"well-conditioned relative error {summary.well.rel_max:.3g} > "
                f"{goal['well_rel_max']:g}"
            )
    return summary


def _case_dict(result: _Result, fmt: _Format) -> dict[str, Any]:
    c = result.case
    return {
        "label": c.label,
        "wi": c.wi,
        "wo": c.wo,
        "n": c.n,
        "tangent": c.tangent,
        "params": c.params,
        "got": list(result.got),
        "exact": None if result.exact is None else list(result.exact),
        "kappa": result.kappa,
        "ulps": result.ulps,
        "rel": result.rel,
        "error": result.error,
    }


def _finite(x: Any) -> Any:
    """JSON has no inf or NaN: they become strings."""
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite(v) for v in x]
    return x


@dataclass
class StressReport:
    """The result of :func:`stress`: per model and dtype, counts and errors.

    ``ok`` says whether every goal of :data:`GOALS` is met; ``table()`` prints it for
    people, ``to_dict()`` / ``to_json()`` for machines. ``worst`` holds, per model and
    dtype, the cases that missed a goal or came closest (inputs exactly, as floats).
    """

    summaries: list[ModelSummary]
    cases: str
    seed: int
    seconds: float
    worst: dict[str, list[dict[str, Any]]] = field(default_factory=dict)
    precision: str = "accurate"

    @property
    def ok(self) -> bool:
        return all(s.ok for s in self.summaries)

    def summary(self, model: str, dtype: str = "float64") -> ModelSummary:
        for s in self.summaries:
            if s.model == model and s.dtype == dtype:
                return s
        raise KeyError(f"no summary for {model} in {dtype}")

    def to_dict(self) -> dict[str, Any]:
        return dict(
            _finite(
                {
                    "ok": self.ok,
                    "cases": self.cases,
                    "seed": self.seed,
                    "seconds": self.seconds,
                    "precision": self.precision,
                    "goals": TIER_GOALS[self.precision],
                    "well_conditioned": f"kappa <= {WELL_CONDITIONED:g}",
                    "reach_ulps": REACH_ULPS,
                    "models": [{**asdict(s), "ok": s.ok} for s in self.summaries],
                    "worst": self.worst,
                }
            )
        )

    def to_json(self, **kwargs: Any) -> str:
        return json.dumps(self.to_dict(), **kwargs)

    def table(self) -> str:
        def g(x: float) -> str:
            if math.isinf(x):
                return "inf"
            return f"{x:.3g}" if x < 1e4 else f"{x:.1e}"

        header = (
            f"{'model':23s} {'dtype':7s} {'cases':>5s} {'NaN':>3s} {'inf':>7s} | "
            f"{'well':>4s} {'ulp med':>7s} {'p99':>5s} {'max':>7s} {'rel max':>8s} | "
            f"{'ill':>4s} {'κ max':>7s} {'rel max':>8s} {'err/κu':>6s} {'jump':>4s} | ok"
        )
        lines = [header, "-" * len(header)]
        for s in self.summaries:
            bad = s.inf - s.inf_legitimate
            inf = f"{s.inf}" if not bad else f"{s.inf}({bad}!)"
            if s.reference:
                well = (
                    f"{s.well.cases:4d} {g(s.well.ulp_median):>7s} {g(s.well.ulp_p99):>5s} "
                    f"{g(s.well.ulp_max):>7s} {g(s.well.rel_max):>8s}"
                )
                ill = (
                    f"{s.ill.cases:4d} {g(s.ill.kappa_max):>7s} {g(s.ill.rel_max):>8s} "
                    f"{g(s.worst_kappa_ratio):>6s} {s.discontinuous:4d}"
                )
            else:
                well = f"{'no 50-digit reference: NaN/inf only':>36s}"
                ill = " " * 33
            lines.append(
                f"{s.model:23s} {s.dtype:7s} {s.cases:5d} {s.nan:3d} {inf:>7s} | {well} | "
                f"{ill} | {'yes' if s.ok else 'NO'}"
            )
        lines.append("")
        lines.append(
            f"well-conditioned: κ ≤ {WELL_CONDITIONED:g}; err/κu: largest relative error over "
            f"κ·u on ill-conditioned cases (goal ≤ {KAPPA_FACTOR:g}); jump: cases within "
            f"{REACH_ULPS} ulps of a discontinuity (κ = inf)"
        )
        for s in self.summaries:
            for failure in s.failures:
                lines.append(f"FAILED {s.model} ({s.dtype}): {failure}")
        lines.append(
            f"{'all goals met' if self.ok else 'goals NOT met'} "
            f"(precision {self.precision!r}, {self.cases} cases, seed {self.seed}, "
            f"{self.seconds:.1f} s)"
        )
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.table()


def _worst(results: list[_Result], fmt: _Format, count: int = 3) -> list[dict[str, Any]]:
    """The cases that missed a goal, else those with the largest errors."""
    u = fmt.unit_roundoff

    def badness(r: _Result) -> float:
        if r.nan or r.error or (r.inf > r.inf_legitimate):
            return math.inf
        if r.exact is None or r.kappa is None or r.kappa == math.inf:
            return -1.0
        return r.rel / max(1e-12 if fmt.name == "float64" else 1e-5, KAPPA_FACTOR * r.kappa * u)

    ranked = sorted(results, key=badness, reverse=True)
    return [_case_dict(r, fmt) for r in ranked[:count] if badness(r) >= 0]


def _dtypes(dtype: str | Iterable[str]) -> list[str]:
    if dtype == "both":
        return ["float64", "float32"]
    names = [dtype] if isinstance(dtype, str) else list(dtype)
    for name in names:
        if name not in _FORMATS:
            raise ValueError(f"dtype: expected 'float64', 'float32' or 'both', got {name!r}")
    return names


def stress(
    models: Sequence[str] | str | None = None,
    dtype: str | Sequence[str] = "float64",
    cases: str = "all",
    seed: int = 0,
    progress: Callable[[str, str, int, int], None] | None = None,
    precision: str = "accurate",
) -> StressReport:
    """Runs every model (or ``models``) over the adversarial input set; see the module doc.

    Args:
        models: model names (default: every model).
        dtype: ``"float64"``, ``"float32"`` or ``"both"``.
        cases: ``"all"`` (a few hundred cases per model and dtype; minutes) or
            ``"quick"`` (a stratified sample of about ten per model: seconds).
        seed: the generator's seed (same seed, same cases, same report).
        progress: called as ``progress(model, dtype, done, total)`` after each model.
        precision: the tier evaluated (``brdf_rs.eval``'s ``precision=``), whose goals
            are checked: :data:`GOALS` for ``"accurate"``, :data:`FAST_GOALS` for
            ``"fast"``.

    Returns:
        A :class:`StressReport`; ``report.ok`` says whether every goal is met.

    Raises:
        ImportError: mpmath is not installed.
        ValueError: an unknown model, dtype, case set or precision.
    """
    _arrays.choice("precision", precision, _api.PRECISIONS)
    mpref = _require_mpmath()
    known = list(_spec.specs())
    if models is None:
        names = known
    else:
        names = [models] if isinstance(models, str) else list(models)
        for name in names:
            if name not in known:
                raise ValueError(f"models: unknown model {name!r}; known: {', '.join(known)}")
    if cases not in ("all", "quick"):
        raise ValueError(f"cases: expected 'all' or 'quick', got {cases!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed: expected a non-negative integer, got {seed!r}")
    formats = [_FORMATS[d] for d in _dtypes(dtype)]
    start = time.perf_counter()
    summaries = []
    worst = {}
    total = len(names) * len(formats)
    for fmt in formats:
        for name in names:
            evaluate = functools.partial(_kernel, precision=precision)
            results = [
                _measure(name, case, fmt, mpref, evaluate)
                for case in _cases(name, fmt, cases == "quick", int(seed))
            ]
            summaries.append(_summarize(name, fmt, results, precision))
            worst[f"{name}/{fmt.name}"] = _worst(results, fmt)
            if progress is not None:
                progress(name, fmt.name, len(summaries), total)
    return StressReport(summaries, cases, int(seed), time.perf_counter() - start, worst, precision)
