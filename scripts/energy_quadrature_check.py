"""How far the energy tables' E_avg quadrature is from a finer one.

    python scripts/energy_quadrature_check.py [--model ggx_dielectric] [--tol 1e-5]
    python scripts/energy_quadrature_check.py --model ggx --tol 1e-8

``brdf_rs.energy_compensation_table`` integrates ``E_avg = 2 ∫ E(mu) mu dmu`` with a
32-point Gauss-Legendre rule in ``mu`` over cells of its own, and ``e_avg_stderr`` is the
Monte Carlo part only. This prints, at a few roughnesses (and, for the transmitting
models, indices on both sides of 1), the 32-point value minus a 64-point one (other
nodes, other seed) next to their combined standard error: where the difference stays
within a few standard errors, the rule's error is below the noise. E is computed as the
table computes it: ``kd = 0, ks = 1`` for a conductor's lobe, the white interface's total
albedo (``ks = kt = 1``) for a transmitting model.
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import brdf_rs
import numpy as np


def e_avg(model: str, n: int, tol: float, seed: int, **params: Any) -> tuple[float, float]:
    """``(E_avg, stderr)`` by ``n``-point Gauss-Legendre over direct albedo calls."""
    x, w = np.polynomial.legendre.leggauss(n)
    x, w = (x + 1) / 2, w / 2
    a = brdf_rs.albedo(model, x, tol=tol, seed=seed, **params)
    value = 2 * np.sum(w * x * a.value[:, 0])
    return float(value), float(2 * np.sqrt(np.sum((w * x * a.stderr[:, 0]) ** 2)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default="ggx_dielectric")
    parser.add_argument("--tol", type=float, default=1e-5)
    parser.add_argument(
        "--alpha", type=float, nargs="+", default=None, help="roughnesses (a default set)"
    )
    args = parser.parse_args()
    spec = brdf_rs.models()[args.model]
    transmitting = spec["transmission"]
    if not (spec["energy_table"] or transmitting):
        parser.error(f"--model: {args.model} has no energy table")
    if transmitting:
        alphas = args.alpha or [0.05, 0.2, 0.8]
        cases = [
            ({"eta": eta, "ks": 1.0, "kt": 1.0}, f"{eta:<7g}") for eta in (0.67, 0.95, 1.05, 1.5)
        ]
    else:
        alphas = args.alpha or [0.005, 0.02, 0.1, 0.4, 1.0]
        cases = [({"kd": 0.0, "ks": 1.0}, "")]
    print(f"{args.model}, tol {args.tol:g}")
    print(f"alpha   {'eta     ' if transmitting else ''}E_avg(GL32)  GL32 - GL64   combined stderr")
    for alpha in alphas:
        for params, label in cases:
            t = time.perf_counter()
            v32, s32 = e_avg(args.model, 32, args.tol, 7, alpha=alpha, **params)
            v64, s64 = e_avg(args.model, 64, args.tol, 8, alpha=alpha, **params)
            print(
                f"{alpha:<7g} {label}{v32:.7f}    {v32 - v64:+.2e}     "
                f"{np.hypot(s32, s64):.1e}   ({time.perf_counter() - t:.1f} s)"
            )


if __name__ == "__main__":
    main()
