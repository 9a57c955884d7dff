"""Fits a linearly transformed cosine (LTC) to a sheen lobe, as Zeltner, Burley and Chiang
fitted theirs, and reports how well it fits.

``zeltner_sheen`` evaluates the paper's LTC: for a view at ``n·v = mu`` and roughness
``alpha``, the light's distribution ``D(w) = max(z, 0)/π·(a/|w′|²)²`` with ``w′ = (a·x +
b·z, a·y, z)`` in the view's frame (x towards the view), scaled by the albedo ``R``. The
paper fits ``a``, ``b`` and ``R`` to a volumetric layer of fibre-like microflakes, a
reference brdf-rs does not have. This script fits the same two-parameter LTC to a lobe
brdf-rs does have, the Charlie sheen (``charlie_sheen`` by default), from ``brdf_rs.eval``:
for each (mu, alpha) of a grid, ``R`` is the lobe's albedo seen from the view and ``(a,
b)`` minimize the L1 distance between the LTC and the lobe's normalized light
distribution ``f(wi, wo)·mu_i/R`` (Nelder-Mead, from the paper's closed-form ``a`` and
``b`` and from ``(1, 0)``, the better kept), both on a midpoint quadrature of the
hemisphere of the light.

    python scripts/ltc_sheen_fit.py [--model charlie_sheen] [--size 16] [-o fit.npz]

Prints, per cell, the fitted ``a``, ``b``, the albedo and the fit's error: half the L1
distance, the share of the lobe's energy the LTC puts in the wrong place (0: a perfect
fit, 1: disjoint). A cell whose lobe is 0 (``zeltner_sheen``'s clamped albedo) has no
fit (NaN). The quadrature's resolution (``--theta``: midpoints in theta, twice as many
in phi) bounds what the error can resolve: fitted to itself (``--model zeltner_sheen``)
the LTC's error is at most 2e-4 for alpha >= 0.5, but up to 0.066 where alpha and mu are
smallest and the lobe is narrower than the quadrature's cells (0.019 at ``--theta 192``).
Rerun at a higher ``--theta`` to see whether a figure is the lobe's or the quadrature's.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import brdf_rs
import numpy as np
from scipy.optimize import minimize


def hemisphere(n_theta: int = 96) -> tuple[np.ndarray, np.ndarray]:
    """Unit directions ``(N, 3)`` and their solid-angle weights: midpoints of ``n_theta``
    intervals in theta and ``2·n_theta`` in phi."""
    n_phi = 2 * n_theta
    theta = (np.arange(n_theta) + 0.5) * (np.pi / 2 / n_theta)
    phi = (np.arange(n_phi) + 0.5) * (2 * np.pi / n_phi)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    w = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)
    weight = np.sin(t) * (np.pi / 2 / n_theta) * (2 * np.pi / n_phi)
    return w.reshape(-1, 3), weight.ravel()


def ltc(w: np.ndarray, a: float, b: float) -> np.ndarray:
    """The paper's LTC over the light directions ``w`` (view frame: the view in the x-z
    plane, x > 0)."""
    x, y, z = w[:, 0], w[:, 1], w[:, 2]
    length2 = (a * x + b * z) ** 2 + (a * y) ** 2 + z * z
    return np.maximum(z, 0) / np.pi * (a / length2) ** 2


def paper_ab(mu: float, alpha: float) -> tuple[float, float]:
    """The paper's closed-form ``a`` and ``b`` (``zeltner_sheen``, docs/models.md)."""
    a = (2.58126 * mu + 0.813703 * alpha) * alpha / (1 + 0.310327 * mu**2 + 2.60994 * mu * alpha)
    g = (
        (alpha - 1)
        * alpha**3
        / (0.0000254053 + 1.71228 * mu - 1.71506 * mu * alpha + 1.34174 * alpha**2)
    )
    return a, np.sqrt(1 - mu) * g


def fit_cell(
    model: str, mu: float, alpha: float, w: np.ndarray, weight: np.ndarray
) -> tuple[float, float, float, float]:
    """``(a, b, albedo, error)`` of one cell; error = half the L1 distance. A lobe that is
    0 has no LTC: NaN for ``a``, ``b`` and the error."""
    wo = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
    f = brdf_rs.eval(model, w, np.broadcast_to(wo, w.shape), kd=0, ks=1, alpha=alpha)[:, 0]
    g = f * w[:, 2]
    albedo = float(np.sum(g * weight))
    if not albedo > 0:
        return np.nan, np.nan, albedo, np.nan
    target = g / albedo

    def distance(ab: np.ndarray) -> float:
        a, b = ab
        if a <= 1e-4:
            return 2.0 + (1e-4 - a)
        return float(np.sum(np.abs(ltc(w, a, b) - target) * weight))

    best = None
    for start in (paper_ab(mu, alpha), (1.0, 0.0)):
        result = minimize(
            distance,
            np.array(start, dtype=np.float64),
            method="Nelder-Mead",
            options={"xatol": 1e-5, "fatol": 1e-7, "maxiter": 2000},
        )
        if best is None or result.fun < best.fun:
            best = result
    assert best is not None
    return float(best.x[0]), float(best.x[1]), albedo, float(best.fun) / 2


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", default="charlie_sheen")
    parser.add_argument("--size", type=int, default=16, help="cells per axis (mu, alpha)")
    parser.add_argument("--theta", type=int, default=96, help="quadrature intervals in theta")
    parser.add_argument("-o", "--out", type=Path, help="write the fit (.npz)")
    args = parser.parse_args(argv)
    w, weight = hemisphere(args.theta)
    k = np.arange(1, args.size + 1) / args.size
    mus, alphas = k, k
    fit = np.zeros((args.size, args.size, 4))
    for i, mu in enumerate(mus):
        for j, alpha in enumerate(alphas):
            fit[i, j] = fit_cell(args.model, float(mu), float(alpha), w, weight)
    np.set_printoptions(precision=4, suppress=True, linewidth=140)
    print(f"# LTC fitted to {args.model} (rows mu, columns alpha = k/{args.size})\n")
    print(f"mu = alpha = {k}\n")
    for c, name in enumerate(("a", "b", "albedo over the light", "error (half the L1 distance)")):
        print(f"{name}:\n{fit[:, :, c]}\n")
    err = fit[:, :, 3]
    i, j = np.unravel_index(np.nanargmax(err), err.shape)
    print(
        f"error: median {np.nanmedian(err):.4f}, worst {np.nanmax(err):.4f} at mu ="
        f" {mus[i]:.3g}, alpha = {alphas[j]:.3g}; alpha >= 0.5: worst"
        f" {np.nanmax(err[:, alphas >= 0.5]):.4f} ({int(np.isnan(err).sum())} cells without a"
        " lobe)"
    )
    if args.out is not None:
        np.savez(
            args.out,
            mu=mus,
            alpha=alphas,
            a=fit[..., 0],
            b=fit[..., 1],
            albedo=fit[..., 2],
            error=err,
        )
        print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
