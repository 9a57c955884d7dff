"""Is ``brdf_rs.albedo``'s standard error honest? The distribution of z = (value − ref)/stderr
over many independent cells, against an accurate deterministic reference.

For each case (model, mu, parameters) the script

1. computes the reference albedo R(mu) = ∫ f(wi, wo)·cos θo dωo, wi = (sin θi, 0, mu), by
   deterministic cubature with ``brdf_rs.eval`` (the kernel the integrator samples, so the
   comparison measures the integrator, not the kernel) — an iterated Gauss-Legendre rule
   over (θo, φo): R = 2 ∫_0^π I(φ) dφ, I(φ) = ∫_0^{π/2} f·cos θo·sin θo dθo (the models are
   even in φo: the azimuth symmetry halves the domain). Each 1-D integral is a sum of
   Gauss-Legendre panels, starting from panels graded about the lobe (θo = θi, φo = 0, on
   the scale of the lobe width) with edges at θi, π/2 in φ (Oren-Nayar's kinks), and
   bisected until each panel's n-node rule agrees with the sum over its halves to a
   tolerance proportional to its width (so kinks that no panel edge knows about, such as
   Torrance-Sparrow's G = min(1, ...), are found by refinement). It runs at two
   resolutions (n = 10 nodes, tolerance 1e-11; n = 16, 1e-13): the difference is printed
   and stored as ``cubature_diff``, and must be far below the standard errors tested.
   At normal incidence Torrance-Sparrow and Blinn-Phong with Fresnel have a 1-D form,
   integrated in 40-digit arithmetic (:func:`normal_incidence_albedo`): that is the
   reference there, and ``cubature_diff`` is the cubature's distance from it. The rough
   dielectrics (``ggx_dielectric``, ``beckmann_dielectric``) integrate over the whole
   sphere, per ``component`` (total, reflection, transmission): their reference is a
   cubature over the half vector instead (:func:`sphere_reference_albedo`; each ``wo``
   is the mirror or the refraction of ``wi`` about one ``h``), in the distribution's own
   cumulative mass so that the lobe is evenly spread at any roughness, with the kinks
   where a ``wo`` crosses the horizon located per ``φh`` and made panel edges; at the
   same two resolutions.
2. runs ``brdf_rs.albedo`` over N cells with the same mu and parameters (``cell_ids`` =
   0..N−1: N independent estimates) for each sequence (``sobol``, ``random``) and budget
   (``samples`` = 256 and 4096 fixed, ``--samples``; ``tol`` = 1e-4 adaptive, ``--tol``,
   with a first round of 256 samples, ``--first``, capped at ``--max-samples``), and
   reports for channel 0 the distribution of z: P(|z| > 3) (0.27% for an honest Gaussian
   error bar), P(|z| > 2) (4.55%), mean z (0 ± 1/sqrt(N) if unbiased), median |z| (0.674
   for a unit Gaussian), the fraction of cells whose stderr is 0, and the median stderr.

A cell with stderr 0 counts as |z| = inf unless its value equals the reference exactly.

    python scripts/stderr_calibration.py                 # all cases, 1000 cells
    python scripts/stderr_calibration.py --quick         # 200 cells, three cases
    python scripts/stderr_calibration.py --cells 4000 --out calibration
    python scripts/stderr_calibration.py --cases torrance_sparrow "ggx mu=1 alpha=0.05"
    python scripts/stderr_calibration.py --grid dielectric --samples 256 4096
    python scripts/stderr_calibration.py --grid torrance_sparrow --samples 256 --confirm 8

The deep run (benches/results/stderr_calibration_deep.md): 2^20 samples per cell, and
tol = 1e-10 from a first round of 2^20, where the rare region G < 1 of Torrance-Sparrow
at normal incidence (probability 4e-7 per point) decides the error bar:

    python scripts/stderr_calibration.py --cases "torrance_sparrow mu=1 p=100" \
        --cells 256 --samples 1048576 --tol 1e-10 --first 1048576 \
        --max-samples 16777216 --out benches/results/stderr_calibration_deep

Writes ``<out>.json`` and ``<out>.md`` (default benches/results/stderr_calibration).
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import platform
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import brdf_rs
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "benches" / "results" / "stderr_calibration"
HALF_PI = 0.5 * math.pi

TS = {"kd": 0.0, "ks": 1.0, "eta": 1.5}
GGX = {"kd": 0.0, "ks": 1.0}
ON = {"kd": 1.0, "sigma": 0.5}
#: blinn_phong_fresnel with F0 = 0: the lobe is Schlick's excess alone.
BPF = {"kd": 0.0, "ks": 0.0}
#: The rough dielectrics: their albedo is over the whole sphere (reflection and
#: transmission), and their reference is :func:`sphere_reference_albedo`.
DIELECTRICS = ("ggx_dielectric", "beckmann_dielectric")
DIEL = {"ks": 1.0, "kt": 1.0}


@dataclass(frozen=True)
class Case:
    model: str
    mu: float
    params: dict[str, float] = field(default_factory=dict)
    #: The part of a transmitting model's albedo (``albedo``'s ``component=``).
    component: str = "total"

    @property
    def label(self) -> str:
        dielectric = self.model in DIELECTRICS
        shown = {
            k: v
            for k, v in self.params.items()
            if k in ("p", "alpha", "alpha_x", "nu", "sigma")
            or (k == "ks" and v != 1.0)
            or (k == "eta" and (v != 1.5 or dielectric))
        }
        extra = " ".join(f"{k}={v:g}" for k, v in shown.items())
        if self.component != "total":
            extra += f" {self.component}"
        return f"{self.model} mu={self.mu:g} {extra}".strip()


CASES = (
    Case("torrance_sparrow", 1.0, {**TS, "p": 100.0}),
    Case("torrance_sparrow", 0.5, {**TS, "p": 100.0}),
    Case("torrance_sparrow", 0.7, {**TS, "p": 10.0}),
    Case("torrance_sparrow", 0.9, {**TS, "p": 1000.0}),
    Case("torrance_sparrow", 1.0, {**TS, "p": 20.0}),
    Case("torrance_sparrow", 0.99, {**TS, "eta": 1.0, "p": 20.0}),
    Case("torrance_sparrow", 0.99, {**TS, "eta": 1.05, "p": 50.0}),
    Case("torrance_sparrow", 0.997, {**TS, "eta": 1.0, "p": 1000.0}),
    Case("blinn_phong_fresnel", 1.0, {**BPF, "p": 100.0}),
    Case("blinn_phong_fresnel", 0.5, {**BPF, "p": 100.0}),
    Case("normalized_blinn_phong", 1.0, {**GGX, "p": 20.0}),
    Case("phong", 1.0, {**GGX, "p": 20.0}),
    Case("phong", 0.99, {**GGX, "p": 20.0}),
    Case("phong", 0.5, {**GGX, "p": 1.0}),
    Case("ward", 1.0, {**GGX, "alpha_x": 0.1, "alpha_y": 0.1}),
    Case("ashikhmin_shirley", 1.0, {"Rd": 0.0, "Rs": 1.0, "nu": 100.0, "nv": 100.0}),
    Case("ggx", 1.0, {**GGX, "alpha": 0.05}),
    Case("ggx", 0.7, {**GGX, "alpha": 0.1}),
    Case("ggx", 0.2, {**GGX, "alpha": 0.05}),
    Case("ggx", 0.7, {**GGX, "alpha": 0.3}),
    Case("ggx", 0.2, {**GGX, "alpha": 1.0}),
    Case("ggx", 1.0, {**GGX, "alpha": 1.0}),
    Case("oren_nayar", 1.0, ON),
    Case("oren_nayar", 0.3, ON),
    Case("ggx_dielectric", 0.3, {**DIEL, "eta": 1.1, "alpha": 0.02}),
    Case("ggx_dielectric", 0.9, {**DIEL, "eta": 1.5, "alpha": 0.1}, "reflection"),
    Case("ggx_dielectric", 0.9, {**DIEL, "eta": 1.5, "alpha": 0.1}, "transmission"),
    Case("beckmann_dielectric", 0.3, {**DIEL, "eta": 1 / 1.5, "alpha": 0.1}),
)


def select(names: Sequence[str]) -> tuple[Case, ...]:
    """The cases named: a model name selects all its cases, anything else must be a case's
    label (``"torrance_sparrow mu=1 p=100"``). Raises ``ValueError`` naming the unknown."""
    chosen = []
    for name in names:
        found = [c for c in CASES if name in (c.model, c.label)]
        if not found:
            labels = ", ".join(repr(c.label) for c in CASES)
            raise ValueError(f"unknown case {name!r}; the cases: {labels}")
        chosen += [c for c in found if c not in chosen]
    return tuple(chosen)


#: Grids of cases (``--grid``): where the error bars of sharp lobes near the normal were
#: once too small. Torrance-Sparrow over R0 (eta), incidence and exponent; the Phong and
#: Blinn-Phong families, and Blinn-Phong with Fresnel over F0.
GRIDS = {
    "torrance_sparrow": tuple(
        Case("torrance_sparrow", mu, {**TS, "eta": eta, "p": p})
        for eta in (1.0, 1.05, 1.5)
        for mu in (0.5, 0.9, 0.97, 0.99, 0.997, 0.999, 1.0)
        for p in (5.0, 20.0, 50.0, 100.0, 1000.0)
    ),
    "power_cosine": tuple(
        Case(model, mu, {**GGX, "p": p})
        for model in (
            "phong",
            "modified_phong",
            "normalized_phong",
            "blinn_phong",
            "modified_blinn_phong",
            "normalized_blinn_phong",
        )
        for mu in (1.0, 0.99, 0.9, 0.5, 0.2)
        for p in (1.0, 5.0, 20.0, 1000.0)
    )
    + tuple(
        Case("blinn_phong_fresnel", mu, {"kd": 0.0, "ks": ks, "p": p})
        for ks in (0.0, 0.04, 0.5)
        for mu in (1.0, 0.99, 0.9, 0.5)
        for p in (5.0, 20.0, 100.0, 1000.0)
    ),
    # Half-vector lobes whose sampler's first number u has a logarithmic end: Ward
    # (tan²θh = −α²·ln u), Ashikhmin-Shirley (cos θh = u^(1/(n+1))); and Beckmann.
    "half_vector": tuple(
        Case("ward", mu, {**GGX, "alpha_x": ax, "alpha_y": ay})
        for mu in (1.0, 0.99, 0.9, 0.5)
        for ax, ay in ((0.02, 0.02), (0.1, 0.1), (0.3, 0.3), (0.05, 0.2))
    )
    + tuple(
        Case("ashikhmin_shirley", mu, {"Rd": 0.0, "Rs": 1.0, "nu": nu, "nv": nv})
        for mu in (1.0, 0.99, 0.9, 0.5)
        for nu, nv in ((5000.0, 5000.0), (100.0, 100.0), (10.0, 10.0), (1000.0, 50.0))
    )
    + tuple(
        Case("beckmann", mu, {**GGX, "alpha": alpha})
        for mu in (1.0, 0.99, 0.9, 0.5)
        for alpha in (0.02, 0.1, 0.3, 1.0)
    ),
    # The rough dielectrics over the whole sphere: near-smooth interfaces with eta near
    # 1, where the weights G2/G1 are about 1 but for rare drops in the distribution's
    # tail (a reflection below the horizon, a refraction at grazing angles); and the
    # components apart at a few points.
    "dielectric": tuple(
        Case(model, mu, {**DIEL, "eta": eta, "alpha": alpha})
        for model in DIELECTRICS
        for alpha in (0.02, 0.1, 0.5)
        for eta in (1.05, 1.1, 1.5, 1 / 1.5)
        for mu in (0.3, 0.9)
    )
    + tuple(
        Case("ggx_dielectric", mu, {**DIEL, "eta": eta, "alpha": 0.02}, component)
        for component in ("reflection", "transmission")
        for mu, eta in ((0.3, 1.1), (0.9, 1 / 1.5))
    ),
}

QUICK_CASES = select(
    ["torrance_sparrow mu=1 p=100", "ggx mu=0.7 alpha=0.3", "oren_nayar mu=0.3 sigma=0.5"]
)

#: Sobol scrambles per cell (the library's default): z then follows t with 15 d.o.f.
REPLICATES = 16

#: The goal for P(|z| > 3) in every row (0.9% is honest for Sobol points, 0.27% for
#: random ones). Over 1000 cells an honest Sobol row reads 0.9 ± 0.3%, so over a grid of
#: hundreds of rows a few land above the goal by chance: ``--confirm K`` reruns each such
#: row on K times as many fresh cells (other cell ids, so independent of the first run
#: and of its selection) and judges the row by that rerun alone.
GOAL = 0.015

#: The two cubature resolutions: (Gauss-Legendre nodes per panel, absolute tolerance).
COARSE = (10, 1e-11)
FINE = (16, 1e-13)

# ------------------------------------------------------------------------------------
# Reference cubature
# ------------------------------------------------------------------------------------


def _lobe_width(model: str, params: dict[str, float]) -> float:
    """The angular scale of the lobe in wo (initial panels are graded on it)."""
    if "alpha" in params:
        return float(min(params["alpha"], 1.0))
    if "p" in params:
        return float(min(1.0 / math.sqrt(max(params["p"], 1.0)), 1.0))
    return 1.0


def _graded(centre: float, width: float, lo: float, hi: float) -> np.ndarray:
    """Panel edges in [lo, hi]: the ends, ``centre`` and centre ± width·(1/4 … 64)."""
    steps = width * np.array([0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 16.0, 32.0, 64.0])
    edges = np.concatenate([[lo, hi, centre], centre - steps, centre + steps])
    edges = np.unique(np.clip(edges, lo, hi))
    return edges


def _adaptive(
    f: Callable[[np.ndarray, np.ndarray], np.ndarray],
    lo: np.ndarray,
    hi: np.ndarray,
    tag: np.ndarray,
    ntags: int,
    n: int,
    tol_per_length: float,
    min_width: float = 1e-7,
) -> np.ndarray:
    """Adaptive composite Gauss-Legendre, vectorized over many 1-D integrals at once.

    ``f(tag, x)`` evaluates integrand number ``tag[k]`` at ``x[k]``. The panels
    ``[lo[j], hi[j]]`` belong to integral ``tag[j]``; each is bisected until the n-node
    rule on the panel and the sum of the rules on its halves differ by at most
    ``tol_per_length × width`` or by the rounding floor 64·eps·∫|f| (a tolerance below
    the rounding error of the panel's own sum could never be met), or the panel is
    narrower than ``min_width``. Returns the ``ntags`` integrals (the halves' sums of the
    accepted panels).
    """
    x, w = np.polynomial.legendre.leggauss(n)
    floor = 64.0 * np.finfo(float).eps

    def rule(a: np.ndarray, b: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        half = 0.5 * (b - a)
        nodes = (0.5 * (a + b))[:, None] + half[:, None] * x[None, :]
        values = f(np.repeat(t, n), nodes.ravel()).reshape(nodes.shape)
        return half * (values @ w), half * (np.abs(values) @ w)

    total = np.zeros(ntags)
    coarse, _ = rule(lo, hi, tag)
    while lo.size:
        mid = 0.5 * (lo + hi)
        left, left_abs = rule(lo, mid, tag)
        right, right_abs = rule(mid, hi, tag)
        fine = left + right
        allowed = np.maximum(tol_per_length * (hi - lo), floor * (left_abs + right_abs))
        done = (np.abs(fine - coarse) <= allowed) | (hi - lo < min_width)
        total += np.bincount(tag[done], weights=fine[done], minlength=ntags)
        keep = ~done
        lo, mid, hi, tag = lo[keep], mid[keep], hi[keep], tag[keep]
        left, right = left[keep], right[keep]
        lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
        tag = np.concatenate([tag, tag])
        coarse = np.concatenate([left, right])
    return total


def reference_albedo(
    model: str, mu: float, params: dict[str, float], n: int = FINE[0], tol: float = FINE[1]
) -> float:
    """R(mu), channel 0, by the iterated adaptive Gauss-Legendre rule over (θo, φo).

    The outer integral over φ ∈ [0, π] and each inner one over θ ∈ [0, π/2] are built to
    absolute tolerances tol/2 and tol/(4π). The error estimate is that of the coarser
    rule of each accepted panel, so the result is usually far better than ``tol``; but
    it is an estimate, not a bound (a kink can fool it), hence the check against a
    second resolution in :func:`reference_with_check`.
    """
    if not 0.0 < mu <= 1.0:
        raise ValueError(f"mu: expected a value in (0, 1], got {mu!r}")
    sin_i = math.sqrt(max(0.0, 1.0 - mu * mu))
    wi = np.array([sin_i, 0.0, mu])
    theta_i = math.acos(mu)
    width = _lobe_width(model, params)
    theta_edges = _graded(theta_i, width, 0.0, HALF_PI)
    phi_width = min(1.0, width / max(sin_i, width))
    phi_edges = np.union1d(_graded(0.0, phi_width, 0.0, math.pi), [HALF_PI])

    def integrand(phi: np.ndarray, theta: np.ndarray) -> np.ndarray:
        st, ct = np.sin(theta), np.cos(theta)
        wo = np.stack([st * np.cos(phi), st * np.sin(phi), ct], axis=-1)
        f = brdf_rs.eval(model, wi, wo, **params)[:, 0]
        return f * ct * st

    inner_tol = tol / (4.0 * math.pi)

    def inner(_tag: np.ndarray, phi: np.ndarray) -> np.ndarray:
        m = phi.size
        lo = np.tile(theta_edges[:-1], m)
        hi = np.tile(theta_edges[1:], m)
        tag = np.repeat(np.arange(m), theta_edges.size - 1)
        return _adaptive(
            lambda t, th: integrand(phi[t], th), lo, hi, tag, m, n, inner_tol / HALF_PI
        )

    lo, hi = phi_edges[:-1], phi_edges[1:]
    outer = _adaptive(inner, lo, hi, np.zeros(lo.size, dtype=np.intp), 1, n, tol / (2 * math.pi))
    return float(2.0 * outer[0])


def _tan2_of(model: str, alpha: float, t: np.ndarray) -> np.ndarray:
    """``tan²θh`` at the cumulative mass ``xi = sin²(πt/2)`` of ``D(h)·cos θh`` (its
    inverse CDF), from ``sin(πt/2)`` and ``cos(πt/2)`` so that neither end cancels."""
    s, c = np.sin(0.5 * math.pi * t), np.cos(0.5 * math.pi * t)
    if model.startswith("ggx"):
        return (alpha * s / c) ** 2
    return -alpha * alpha * np.log1p(-s * s)


def _ndf_cos(model: str, alpha: float, cos_h: np.ndarray, tan2: np.ndarray) -> np.ndarray:
    """``D(h)·cos θh``, the density of the half vectors that ``xi`` and ``φh/2π`` map."""
    a2 = alpha * alpha
    if model.startswith("ggx"):
        return a2 / (math.pi * cos_h**3 * (a2 + tan2) ** 2)
    return np.exp(-tan2 / a2) / (math.pi * a2 * cos_h**3)


def sphere_reference_albedo(
    model: str,
    mu: float,
    params: dict[str, float],
    component: str = "total",
    n: int = FINE[0],
    tol: float = FINE[1],
) -> float:
    """The albedo of a rough dielectric over the whole sphere (channel 0, ``component``
    ``total``, ``reflection`` or ``transmission``) by an adaptive cubature over the half
    vector ``h`` of ``brdf_rs.eval``: independent of the integrator's sampler, weights
    and streams.

    Each ``wo`` comes from exactly one ``h`` with ``n·h > 0`` and ``wi·h > 0``: its mirror
    about ``h`` (reflection, ``dωo = 4(wo·h) dωh``) or its refraction through ``h``
    (transmission, ``dωo = (wi·h + eta(wo·h))²/(eta²|wo·h|) dωh``), so
    ``A = ∫ f(wi, wo(h))·|n·wo|·dωo/dωh dωh`` over the hemisphere of ``h``. ``h`` is
    parametrized by ``xi``, the cumulative mass of ``D(h)·cos θh`` in ``tan²θh`` (its
    inverse CDF: the lobe is spread evenly over ``xi``, at any roughness), with
    ``xi = sin²(πt/2)`` (``sin θh`` is then smooth in ``t`` at the normal, where it goes
    as ``sqrt(xi)``, and the ``1/sqrt(1 − xi)`` growth where ``h`` tilts to the horizon
    is taken out), and by ``φh``: ``dωh = dxi dφh/(2π·D(h)·cos θh)``. The
    integrand is even in ``φh`` (``wi`` in the xz plane): ``φh ∈ [0, π]``, doubled. Where
    a ``wo`` crosses the horizon (``G2`` takes the integrand to 0 there) and at the edge
    of total internal reflection the integrand has kinks that no panel edge knows about:
    the iterated rule of :func:`_adaptive` (outer ``φh``, inner ``t``) bisects until they
    are resolved, with the same tolerances as :func:`reference_albedo`.
    """
    if not 0.0 < mu <= 1.0:
        raise ValueError(f"mu: expected a value in (0, 1], got {mu!r}")
    if component not in ("total", "reflection", "transmission"):
        raise ValueError(
            f"component: expected total, reflection or transmission, got {component!r}"
        )
    eta, alpha = params["eta"], params["alpha"]
    wi = np.array([math.sqrt(max(0.0, 1.0 - mu * mu)), 0.0, mu])
    reflect = component in ("total", "reflection")
    transmit = component in ("total", "transmission")

    def geometry(phi: np.ndarray, t: np.ndarray) -> dict[str, np.ndarray]:
        """At each ``(φh, t)``: ``h``, the measure ``node`` (``dωh`` per ``dt dφh``),
        ``c = wi·h``, the mirror ``wr``, the refraction ``wt`` and ``k = cos²θt``."""
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            tan2 = _tan2_of(model, alpha, t)
            cos_h = 1.0 / np.sqrt(1.0 + tan2)
            sin_h = np.sqrt(tan2) * cos_h
            dxi_dt = 0.5 * math.pi * np.sin(math.pi * t)
            node = dxi_dt / (2.0 * math.pi * _ndf_cos(model, alpha, cos_h, tan2))
        h = np.stack([sin_h * np.cos(phi), sin_h * np.sin(phi), cos_h], axis=-1)
        c = h @ wi
        k = 1.0 - (1.0 - c * c) / (eta * eta)
        cos_t = np.sqrt(np.maximum(k, 0.0))
        wt = -wi / eta + (c / eta - cos_t)[..., None] * h
        wt /= np.linalg.norm(wt, axis=-1, keepdims=True)
        return {"h": h, "node": node, "c": c, "wr": 2.0 * c[..., None] * h - wi, "wt": wt, "k": k}

    def edges_of(g: dict[str, np.ndarray]) -> list[np.ndarray]:
        """The functions whose sign changes are the integrand's kinks: ``wi·h`` (where a
        half vector stops facing ``wi``), the mirror's and the refraction's heights (the
        horizon) and ``cos²θt`` (total internal reflection)."""
        return [g["c"], g["wr"][..., 2], g["wt"][..., 2], g["k"]]

    def integrand(phi: np.ndarray, t: np.ndarray) -> np.ndarray:
        g = geometry(phi, t)
        h, node, c = g["h"], g["node"], g["c"]
        out = np.zeros_like(t)
        ok = (c > 0.0) & np.isfinite(node) & (node > 0.0)
        if reflect:
            wo = g["wr"]
            up = ok & (wo[:, 2] > 0.0)
            if up.any():
                f = brdf_rs.eval(model, wi, wo[up], **params)[:, 0]
                out[up] += f * wo[up, 2] * 4.0 * c[up] * node[up]
        if transmit:
            wo = g["wt"]
            down = ok & (g["k"] > 0.0) & (wo[:, 2] < 0.0)
            if down.any():
                ct = np.einsum("ij,ij->i", wo[down], h[down])
                jacobian = (c[down] + eta * ct) ** 2 / (eta * eta * np.abs(ct))
                f = brdf_rs.eval(model, wi, wo[down], **params)[:, 0]
                out[down] += f * np.abs(wo[down, 2]) * jacobian * node[down]
        return out

    # The kinks along each φh: sign changes of edges_of on a grid of t, bisected.
    grid = np.linspace(0.0, 1.0, 257)
    base = np.linspace(0.0, 1.0, 9)

    def inner(_tag: np.ndarray, phi: np.ndarray) -> np.ndarray:
        m = phi.size
        values = edges_of(geometry(np.repeat(phi, grid.size), np.tile(grid, m)))
        # Brackets [a, b] of every sign change, for all φh and kinds at once, bisected.
        rows, a, b, kind, sign = [], [], [], [], []
        for j, v in enumerate(values):
            v = np.sign(v.reshape(m, grid.size))
            r, i = np.nonzero(v[:, :-1] * v[:, 1:] < 0)
            rows.append(r)
            a.append(grid[i])
            b.append(grid[i + 1])
            kind.append(np.full(r.size, j))
            sign.append(v[r, i])
        r, lo_t, hi_t = np.concatenate(rows), np.concatenate(a), np.concatenate(b)
        kind, sign = np.concatenate(kind), np.concatenate(sign)
        for _ in range(60):
            mid = 0.5 * (lo_t + hi_t)
            at_mid = edges_of(geometry(phi[r], mid))
            v = np.choose(kind, [np.sign(x) for x in at_mid]) if r.size else mid
            same = v == sign
            lo_t, hi_t = np.where(same, mid, lo_t), np.where(same, hi_t, mid)
        roots = 0.5 * (lo_t + hi_t)
        per = [np.unique(np.concatenate([base, roots[r == j]])) for j in range(m)]
        lo = np.concatenate([e[:-1] for e in per])
        hi = np.concatenate([e[1:] for e in per])
        tag = np.concatenate([np.full(e.size - 1, j) for j, e in enumerate(per)])
        return _adaptive(lambda j, t: integrand(phi[j], t), lo, hi, tag, m, n, tol / 2.0)

    phi_edges = np.linspace(0.0, math.pi, 9)
    lo, hi = phi_edges[:-1], phi_edges[1:]
    outer = _adaptive(inner, lo, hi, np.zeros(lo.size, dtype=np.intp), 1, n, tol / 2.0)
    return float(2.0 * outer[0])


def normal_incidence_albedo(model: str, params: dict[str, float]) -> float | None:
    """R(1) of ``torrance_sparrow`` or ``blinn_phong_fresnel`` (channel 0) as a 1-D integral
    in 40-digit arithmetic, or None for other models.

    At normal incidence the half vector is at θo/2 and ``wi·h = cos θh = c``; with the
    Blinn density of c, ``(p+2)·c^(p+1) dc``, the albedo is ``∫ w(c)·(p+2)·c^(p+1) dc``
    with the weight w = F·G, ``G = min(1, 2(2c² − 1))`` (Torrance-Sparrow) or
    ``w = (p+8)/(p+2)·F·(2c² − 1)`` (Blinn-Phong with Fresnel), for ``c > cos 45°`` (wo
    above the surface), plus ``kd``. ``F`` is Schlick's, with R0 (or F0) rounded to a
    double as the kernel rounds it. Accurate far below the standard errors of cells whose
    weights are nearly constant, where the cubature's 1e-15 is not enough.
    """
    import mpmath

    if model not in ("torrance_sparrow", "blinn_phong_fresnel"):
        return None
    p = params["p"]
    if model == "torrance_sparrow":
        r = (params["eta"] - 1.0) / (params["eta"] + 1.0)
        f0, ks = r * r, params["ks"]
    else:
        f0, ks = params["ks"], 1.0
    with mpmath.workdps(40):
        mp = mpmath.mpf

        def weight(c: Any) -> Any:
            fresnel = mp(f0) + (1 - mp(f0)) * (1 - c) ** 5
            mu_o = 2 * c * c - 1
            if model == "torrance_sparrow":
                w = fresnel * min(mp(1), 2 * mu_o)
            else:
                w = (mp(p) + 8) / (mp(p) + 2) * fresnel * mu_o
            return w * (mp(p) + 2) * c ** (mp(p) + 1)

        edges = [mpmath.cos(mpmath.pi / 4), mpmath.cos(mpmath.pi / 6), mp(1)]
        # Panels graded towards c = 1, where a sharp lobe lives.
        width = min(mp(1) / (mp(p) + 2), mp(1) / 64)
        edges += [1 - width * 2**k for k in range(12) if 1 - width * 2**k > edges[0]]
        edges = sorted(set(edges))
        value = ks * mpmath.quad(weight, edges) + params["kd"]
        return float(value)


def reference_with_check(case: Case) -> tuple[float, float, float]:
    """The reference, a check of it, and the seconds taken: the fine cubature and
    |fine − coarse| (its convergence check), or at normal incidence where
    :func:`normal_incidence_albedo` applies, that value and |fine cubature − it|."""
    t = time.perf_counter()
    if case.model in DIELECTRICS:
        fine = sphere_reference_albedo(case.model, case.mu, case.params, case.component, *FINE)
        coarse = sphere_reference_albedo(case.model, case.mu, case.params, case.component, *COARSE)
        return fine, abs(fine - coarse), time.perf_counter() - t
    fine = reference_albedo(case.model, case.mu, case.params, *FINE)
    exact = normal_incidence_albedo(case.model, case.params) if case.mu == 1.0 else None
    if exact is not None:
        return exact, abs(fine - exact), time.perf_counter() - t
    coarse = reference_albedo(case.model, case.mu, case.params, *COARSE)
    return fine, abs(fine - coarse), time.perf_counter() - t


# ------------------------------------------------------------------------------------
# Calibration
# ------------------------------------------------------------------------------------


def t_abs_cdf(x: float, dof: float) -> float:
    """P(|T| <= x) for Student's t with ``dof`` degrees of freedom (``inf``: the normal),
    by 8 panels of 32-node Gauss-Legendre on [0, x] (the density is smooth)."""
    if math.isinf(dof):
        return math.erf(x / math.sqrt(2.0))
    log_c = math.lgamma((dof + 1) / 2) - math.lgamma(dof / 2) - 0.5 * math.log(dof * math.pi)
    nodes, weights = np.polynomial.legendre.leggauss(32)
    edges = np.linspace(0.0, x, 9)
    total = 0.0
    for a, b in itertools.pairwise(edges):
        t = 0.5 * (a + b) + 0.5 * (b - a) * nodes
        pdf = np.exp(log_c - 0.5 * (dof + 1) * np.log1p(t * t / dof))
        total += 0.5 * (b - a) * float(pdf @ weights)
    return float(2.0 * total)


def honest(dof: float) -> dict[str, float]:
    """What an honest error bar gives: z then follows Student's t with the degrees of
    freedom of the stderr estimate (replicates − 1 for Sobol, samples − 1 for random)."""
    lo, hi = 0.0, 10.0
    for _ in range(60):  # median of |T| by bisection
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if t_abs_cdf(mid, dof) < 0.5 else (lo, mid)
    return {
        "p_abs_z_gt_3": 1.0 - t_abs_cdf(3.0, dof),
        "p_abs_z_gt_2": 1.0 - t_abs_cdf(2.0, dof),
        "median_abs_z": 0.5 * (lo + hi),
    }


@dataclass(frozen=True)
class Budget:
    samples: int
    tol: float | None = None

    @property
    def label(self) -> str:
        return f"tol={self.tol:g}" if self.tol is not None else f"n={self.samples}"


def z_statistics(value: np.ndarray, stderr: np.ndarray, ref: float) -> dict[str, float]:
    """Summary of z = (value − ref)/stderr; stderr 0 gives |z| = inf unless value == ref."""
    err = value - ref
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(stderr > 0, err / np.where(stderr > 0, stderr, 1.0), np.sign(err) * np.inf)
    z = np.where((stderr == 0) & (err == 0), 0.0, z)
    absz = np.abs(z)
    finite = np.isfinite(z)
    return {
        "p_abs_z_gt_3": float(np.mean(absz > 3)),
        "p_abs_z_gt_2": float(np.mean(absz > 2)),
        "mean_z": float(np.mean(z[finite])) if finite.any() else float("nan"),
        "median_abs_z": float(np.median(absz)),
        "frac_stderr_zero": float(np.mean(stderr == 0)),
        "median_stderr": float(np.median(stderr)),
        "rms_error": float(np.sqrt(np.mean(err**2))),
    }


def calibrate(
    case: Case,
    ref: float,
    sequence: str,
    budget: Budget,
    cells: int,
    seed: int = 0,
    max_samples: int = 1 << 16,
    replicates: int = REPLICATES,
    first_cell: int = 0,
) -> dict[str, Any]:
    """Runs ``brdf_rs.albedo`` on ``cells`` independent cells of one case (cell ids from
    ``first_cell`` on); z statistics, with what an honest error bar would give
    (``honest_*``) beside them."""
    options: dict[str, Any] = {"samples": budget.samples, "sequence": sequence, "seed": seed}
    if case.component != "total":
        options["component"] = case.component
    if sequence == "sobol":
        options["replicates"] = replicates
    if budget.tol is not None:
        options.update(tol=budget.tol, max_samples=max_samples)
    t = time.perf_counter()
    result = brdf_rs.albedo(
        case.model,
        np.full(cells, case.mu),
        cell_ids=np.arange(first_cell, first_cell + cells, dtype=np.uint64),
        **options,
        **case.params,
    )
    seconds = time.perf_counter() - t
    stats = z_statistics(result.value[:, 0], result.stderr[:, 0], ref)
    dof = replicates - 1 if sequence == "sobol" else float(result.samples.min()) - 1
    if dof < 1:  # exact cells (a closed form, no samples): no estimate to compare with
        dof = math.inf
    stats.update({f"honest_{k}": v for k, v in honest(dof).items()})
    stats.update(
        seconds=seconds,
        mean_samples=float(result.samples.mean()),
        frac_at_max_samples=(
            float(np.mean(result.samples >= max_samples)) if budget.tol is not None else 0.0
        ),
    )
    return stats


def run(
    cases: Sequence[Case],
    cells: int,
    budgets: Sequence[Budget],
    sequences: Sequence[str] = ("sobol", "random"),
    seed: int = 0,
    max_samples: int = 1 << 16,
    echo: Callable[[str], None] = print,
    confirm: int = 0,
) -> list[dict[str, Any]]:
    rows = []
    for sequence in sequences:
        dof = REPLICATES - 1 if sequence == "sobol" else math.inf
        h = honest(dof)
        echo(
            f"honest {sequence}: P(|z|>3) = {h['p_abs_z_gt_3']:.4f}, "
            f"P(|z|>2) = {h['p_abs_z_gt_2']:.4f}, median |z| = {h['median_abs_z']:.3f}"
            f" (Student t, {dof:g} d.o.f.)"
        )
    echo(HEADER)
    for case in cases:
        ref, diff, ref_seconds = reference_with_check(case)
        echo(f"# {case.label}: ref = {ref:.15g}, cubature diff = {diff:.1e}")
        echo(f"#   ({ref_seconds:.1f} s)")
        for sequence in sequences:
            for budget in budgets:
                stats = calibrate(case, ref, sequence, budget, cells, seed, max_samples)
                row = {
                    "model": case.model,
                    "mu": case.mu,
                    "params": case.params,
                    "case": case.label,
                    "reference": ref,
                    "cubature_diff": diff,
                    "sequence": sequence,
                    "budget": budget.label,
                    "cells": cells,
                    **stats,
                }
                rows.append(row)
                echo(format_row(row))
                if confirm > 0 and over_goal(row):
                    again = calibrate(
                        case,
                        ref,
                        sequence,
                        budget,
                        confirm * cells,
                        seed,
                        max_samples,
                        first_cell=cells,
                    )
                    row["confirm"] = {"cells": confirm * cells, **again}
                    echo("  " + format_rerun(row))
    return rows


HEADER = (
    f"{'case':<32} {'seq':<6} {'budget':<9} {'P|z|>3':>7} {'P|z|>2':>7} {'mean z':>7} "
    f"{'med|z|':>7} {'se=0':>6} {'med se':>8} {'samples':>8} {'time':>6}"
)


def resolved(r: dict[str, Any]) -> bool:
    """Whether the reference is accurate enough to judge a row's error bars: its check
    (``cubature_diff``) at most a tenth of the median stderr. Exact cells (stderr 0)
    are judged by exact agreement."""
    return r["median_stderr"] == 0 or r["cubature_diff"] <= 0.1 * r["median_stderr"]


def over_goal(r: dict[str, Any]) -> bool:
    """A row with more cells beyond 3 standard errors than the goal, whose reference is
    accurate enough to say so."""
    return r["p_abs_z_gt_3"] > GOAL and resolved(r)


def confirmed_over_goal(r: dict[str, Any]) -> bool:
    """Over the goal, and (where it was rerun on fresh cells) over it in the rerun too."""
    return over_goal(r) and ("confirm" not in r or r["confirm"]["p_abs_z_gt_3"] > GOAL)


def format_rerun(r: dict[str, Any]) -> str:
    """A row's rerun on fresh cells (``--confirm``), formatted as a row."""
    return f"rerun on {r['confirm']['cells']} fresh cells: " + format_row({**r, **r["confirm"]})


def format_row(r: dict[str, Any]) -> str:
    return (
        f"{r['case']:<32} {r['sequence']:<6} {r['budget']:<9} {r['p_abs_z_gt_3']:>7.3f} "
        f"{r['p_abs_z_gt_2']:>7.3f} {r['mean_z']:>7.2f} {r['median_abs_z']:>7.3f} "
        f"{r['frac_stderr_zero']:>6.3f} {r['median_stderr']:>8.1e} {r['mean_samples']:>8.0f} "
        f"{r['seconds']:>5.1f}s"
    )


def markdown(rows: list[dict[str, Any]], meta: dict[str, Any]) -> str:
    lines = [
        "# Standard-error calibration of `brdf_rs.albedo`",
        "",
        f"{meta['cells']} independent cells per row (seed {meta['seed']}), channel 0; "
        "z = (value − reference)/stderr. An honest error bar makes z follow Student's t "
        "with the degrees of freedom of the stderr estimate: for `sobol` "
        f"({REPLICATES} scrambles) t with {REPLICATES - 1} d.o.f., "
        f"P(|z|>3) = {honest(REPLICATES - 1)['p_abs_z_gt_3']:.4f}, "
        f"P(|z|>2) = {honest(REPLICATES - 1)['p_abs_z_gt_2']:.4f}, "
        f"median |z| = {honest(REPLICATES - 1)['median_abs_z']:.3f}; for `random` "
        "(per-sample variance) about the normal, 0.0027, 0.0455, 0.674; mean z ≈ 0 "
        "(± 1/sqrt(cells)). Binomial noise on a fraction P over N cells: "
        f"sqrt(P(1−P)/N). `tol` rows: first round {meta['first']} samples, at most "
        f"{meta['max_samples']} per cell; 'samples' is the mean per cell. Reference: "
        "iterated adaptive Gauss-Legendre cubature over (θo, φo) with `brdf_rs.eval`; "
        "'cubature diff' is |fine − coarse| of its two resolutions. At mu = 1 "
        "(Torrance-Sparrow, Blinn-Phong with Fresnel) the reference is the albedo as a 1-D "
        "integral in 40-digit arithmetic, and 'cubature diff' is |cubature − it|. "
        f"brdf-rs {meta['version']}, {meta['threads']} threads, "
        f"total {meta['seconds']:.0f} s.",
        "",
        "| case | reference | cubature diff | sequence | budget | P(\\|z\\|>3) | "
        "P(\\|z\\|>2) | mean z | median \\|z\\| | stderr = 0 | median stderr | samples |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['reference']:.12g} | {r['cubature_diff']:.1e} | "
            f"{r['sequence']} | {r['budget']} | {r['p_abs_z_gt_3']:.3f} | "
            f"{r['p_abs_z_gt_2']:.3f} | {r['mean_z']:.2f} | {r['median_abs_z']:.3f} | "
            f"{r['frac_stderr_zero']:.3f} | {r['median_stderr']:.1e} | "
            f"{r['mean_samples']:.0f} |"
        )
    over = [r for r in rows if over_goal(r)]
    coarse = sum(not resolved(r) for r in rows)
    lines += ["", f"{len(over)} of {len(rows)} rows with P(|z|>3) above {GOAL}."]
    rerun = [r for r in over if "confirm" in r]
    if rerun:
        lines += [
            "",
            f"Rerun on fresh cells (other cell ids; `--confirm`), judged by the rerun alone: "
            f"{sum(confirmed_over_goal(r) for r in rerun)} of {len(rerun)} above {GOAL} there.",
            "",
            "| case | sequence | budget | cells | P(\\|z\\|>3) | P(\\|z\\|>2) | mean z | "
            "median \\|z\\| |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for r in rerun:
            c = r["confirm"]
            lines.append(
                f"| {r['case']} | {r['sequence']} | {r['budget']} | {c['cells']} | "
                f"{c['p_abs_z_gt_3']:.4f} | {c['p_abs_z_gt_2']:.4f} | {c['mean_z']:.2f} | "
                f"{c['median_abs_z']:.3f} |"
            )
    if coarse:
        lines += [
            f"{coarse} rows have a reference too coarse to judge them (cubature diff above "
            "a tenth of the median stderr): not counted."
        ]
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, default=None, help="cells per row (1000)")
    parser.add_argument("--quick", action="store_true", help="200 cells, three cases")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--samples",
        type=int,
        nargs="+",
        default=[256, 4096],
        help="the fixed budgets, samples per cell (256 4096)",
    )
    parser.add_argument("--tol", type=float, default=1e-4, help="the adaptive budget")
    parser.add_argument(
        "--first", type=int, default=256, help="first round of the adaptive budget (256)"
    )
    parser.add_argument(
        "--cases",
        nargs="+",
        default=None,
        help="model names or case labels ('torrance_sparrow mu=1 p=100'); default: all",
    )
    parser.add_argument(
        "--max-samples", type=int, default=1 << 16, help="cap per cell in tol mode (65536)"
    )
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="path without suffix")
    parser.add_argument(
        "--confirm",
        type=int,
        default=0,
        metavar="K",
        help=f"rerun each row above P(|z|>3) = {GOAL} on K times as many fresh cells and "
        "judge it by that rerun (0: no rerun)",
    )
    parser.add_argument(
        "--grid",
        choices=sorted(GRIDS),
        help="run a grid of cases instead (with --samples only, no tol budget); writes "
        "<out> = benches/results/stderr_calibration_grid_<grid> unless --out is given",
    )
    args = parser.parse_args(argv)
    cells = args.cells if args.cells is not None else (200 if args.quick else 1000)
    if cells < 1:
        parser.error(f"--cells: expected a positive integer, got {cells}")
    if args.confirm < 0:
        parser.error(f"--confirm: expected a non-negative integer, got {args.confirm}")
    for n in args.samples:
        if n < 2:
            parser.error(f"--samples: expected integers >= 2, got {n}")
    if args.first < 2:
        parser.error(f"--first: expected an integer >= 2, got {args.first}")
    if args.max_samples < args.first:
        parser.error(
            f"--max-samples: expected at least --first ({args.first}), got {args.max_samples}"
        )
    if not (args.tol > 0 and math.isfinite(args.tol)):
        parser.error(f"--tol: expected a positive number, got {args.tol}")
    try:
        cases = select(args.cases) if args.cases else QUICK_CASES if args.quick else CASES
    except ValueError as e:
        parser.error(f"--cases: {e}")
    budgets: tuple[Budget, ...] = (*(Budget(n) for n in args.samples), Budget(args.first, args.tol))
    if args.grid is not None:
        cases = GRIDS[args.grid]
        budgets = tuple(Budget(n) for n in args.samples)
        if args.out == DEFAULT_OUT:
            args.out = DEFAULT_OUT.with_name(f"{DEFAULT_OUT.name}_grid_{args.grid}")
    t = time.perf_counter()
    rows = run(
        cases,
        cells,
        budgets,
        seed=args.seed,
        max_samples=args.max_samples,
        confirm=args.confirm,
    )
    seconds = time.perf_counter() - t
    meta = {
        "cells": cells,
        "first": args.first,
        "seed": args.seed,
        "max_samples": args.max_samples,
        "replicates": REPLICATES,
        "version": brdf_rs.__version__,
        "threads": brdf_rs.num_threads(),
        "platform": platform.platform(),
        "seconds": seconds,
        "cubature": {"coarse": COARSE, "fine": FINE},
        "confirm": args.confirm,
    }
    print(f"total {seconds:.1f} s")
    over = [r for r in rows if over_goal(r)]
    coarse = [r for r in rows if not resolved(r)]
    print(f"{len(over)} of {len(rows)} rows with P(|z|>3) above {GOAL}")
    for r in over:
        print("  " + format_row(r))
        if "confirm" in r:
            print("    " + format_rerun(r))
    if any("confirm" in r for r in over):
        confirmed = sum(confirmed_over_goal(r) for r in over)
        print(f"{confirmed} of {len(over)} above {GOAL} in their rerun on fresh cells")
    if coarse:
        print(f"{len(coarse)} rows whose reference is too coarse for their error bars:")
        for r in coarse:
            print("  " + format_row(r) + f"  (cubature diff {r['cubature_diff']:.1e})")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    json_path = args.out.with_name(args.out.name + ".json")
    md_path = args.out.with_name(args.out.name + ".md")
    json_path.write_text(json.dumps({"meta": meta, "rows": rows}, indent=1) + "\n")
    md_path.write_text(markdown(rows, meta))
    print(f"wrote {json_path} and {md_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
