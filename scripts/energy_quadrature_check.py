"""How far the energy tables' E_avg is from a fine quadrature, and how rules with a fixed
number of cells would do.

    python scripts/energy_quadrature_check.py [--model ggx_dielectric] [--tol 1e-5]
    python scripts/energy_quadrature_check.py --model ggx --tol 1e-8
    python scripts/energy_quadrature_check.py --eta 0.67 --alpha 0.05 0.8 --tol 1e-6

``brdf_rs.energy_compensation_table`` integrates ``E_avg = 2 ∫ E(mu) mu dmu`` by adaptive
Gauss-Kronrod in ``sqrt(mu)`` over cells of its own, halving panels until the rule's error
is within the noise, so that ``e_avg_stderr`` covers it. This prints, at a few roughnesses
(and, for the transmitting models, indices on both sides of 1), each rule's value minus a
128-point Gauss-Legendre one (other nodes, other seed), the combined standard error, their
ratio z and the seconds each rule took: where z stays within a few units, the rule's error
is below the noise. The rules:

- ``table``: the table's own ``E_avg`` and ``e_avg_stderr`` (a one-cell table);
- ``gl32``: 32-point Gauss-Legendre in ``mu``, the rule the tables used before, whose
  error ``e_avg_stderr`` left out;
- ``gl32_sqrt``: 32-point Gauss-Legendre in ``t = sqrt(mu)`` (``mu = t²``), whose nodes
  crowd towards grazing incidence, where ``E`` of a smooth lobe falls within ``mu`` of
  about ``alpha``;
- ``split``: for a transmitting model with ``eta < 1``, 16-point Gauss-Legendre on each
  side of the critical cosine ``sqrt(1 − eta²)`` of total internal reflection, where
  ``E`` bends (not run for ``eta >= 1``).

E is computed as the table computes it: ``kd = 0, ks = 1`` for a conductor's lobe, the
white interface's total albedo (``ks = kt = 1``) for a transmitting model.
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import brdf_rs
import numpy as np


def gauss(n: int, a: float = 0.0, b: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """``n``-point Gauss-Legendre nodes and weights on ``[a, b]``."""
    x, w = np.polynomial.legendre.leggauss(n)
    return a + (b - a) * (x + 1) / 2, w * (b - a) / 2


def rule(name: str, eta: float | None) -> tuple[np.ndarray, np.ndarray]:
    """Nodes ``mu`` and weights ``v`` with ``E_avg ≈ 2 Σ v·E(mu)`` (the weights hold the
    factor ``mu`` and the change of variables). ``split`` needs ``eta < 1``."""
    if name == "gl32_sqrt":
        t, w = gauss(32)
        return t * t, w * 2 * t * t * t
    if name == "split":
        if eta is None or not eta < 1:
            raise ValueError(f"split: needs eta < 1, got {eta}")
        c = float(np.sqrt(1 - eta * eta))
        (x1, w1), (x2, w2) = gauss(16, 0.0, c), gauss(16, c, 1.0)
        x, w = np.r_[x1, x2], np.r_[w1, w2]
    else:
        x, w = gauss({"gl32": 32, "gl128": 128}[name])
    return x, w * x


def e_avg(model: str, name: str, tol: float, seed: int, **params: Any) -> tuple[float, float]:
    """``(E_avg, stderr)`` by rule ``name`` over direct albedo calls, or for ``table``
    the table's own ``E_avg`` and ``e_avg_stderr`` (a one-cell table at the case)."""
    if name == "table":
        axes = {"eta": [params["eta"]]} if "eta" in params else {}
        ec = brdf_rs.energy_compensation_table(
            model, [0.5], [params["alpha"]], tol=tol, seed=seed, **axes
        )
        return float(ec.e_avg.flat[0]), float(ec.e_avg_stderr.flat[0])
    mu, v = rule(name, params.get("eta"))
    a = brdf_rs.albedo(model, mu, tol=tol, seed=seed, **params)
    value = 2 * np.sum(v * a.value[:, 0])
    return float(value), float(2 * np.sqrt(np.sum((v * a.stderr[:, 0]) ** 2)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default="ggx_dielectric")
    parser.add_argument("--tol", type=float, default=1e-5)
    parser.add_argument(
        "--alpha", type=float, nargs="+", default=None, help="roughnesses (a default set)"
    )
    parser.add_argument(
        "--eta", type=float, nargs="+", default=None, help="indices (a default set)"
    )
    args = parser.parse_args()
    spec = brdf_rs.models()[args.model]
    transmitting = spec["transmission"]
    if not (spec["energy_table"] or transmitting):
        parser.error(f"--model: {args.model} has no energy table")
    if transmitting:
        alphas = args.alpha or [0.05, 0.2, 0.8]
        cases = [{"eta": eta, "ks": 1.0, "kt": 1.0} for eta in args.eta or (0.67, 0.95, 1.05, 1.5)]
        rules = ("table", "gl32", "gl32_sqrt", "split")
    else:
        if args.eta is not None:
            parser.error(f"--eta: {args.model} has no eta")
        alphas = args.alpha or [0.005, 0.02, 0.1, 0.4, 1.0]
        cases = [{"kd": 0.0, "ks": 1.0}]
        rules = ("table", "gl32", "gl32_sqrt")
    print(f"{args.model}, tol {args.tol:g}; error: the rule's E_avg minus 128-point Gauss-Legendre")
    print(
        f"{'alpha':<7} {'eta':<7} {'rule':<10} {'E_avg':<10} {'error':>10} {'comb. stderr':>13}"
        f" {'z':>6} {'seconds':>7}"
    )
    for alpha in alphas:
        for params in cases:
            ref, ref_se = e_avg(args.model, "gl128", args.tol, 9, alpha=alpha, **params)
            eta = f"{params['eta']:g}" if "eta" in params else "-"
            for name in rules:
                if name == "split" and params["eta"] >= 1:
                    continue
                t = time.perf_counter()
                v, se = e_avg(args.model, name, args.tol, 7, alpha=alpha, **params)
                print(
                    f"{alpha:<7g} {eta:<7} {name:<10} {v:.7f}  {v - ref:>+10.2e} "
                    f"{np.hypot(se, ref_se):>13.1e} {(v - ref) / np.hypot(se, ref_se):>+6.1f}"
                    f" {time.perf_counter() - t:>7.2f}"
                )


if __name__ == "__main__":
    main()
