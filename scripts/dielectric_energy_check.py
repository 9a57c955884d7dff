"""How far the rough dielectrics' E_avg quadrature is from a finer one.

    python scripts/dielectric_energy_check.py [--model ggx_dielectric] [--tol 1e-5]

``brdf_rs.energy_compensation_table(model, mu, alpha, eta=...)`` integrates
``E_avg(alpha, eta) = 2 ∫ E(mu) mu dmu`` with a 32-point Gauss-Legendre rule over cells of
its own; ``e_avg_stderr`` is the Monte Carlo part only. This prints, at a few roughnesses
and indices on both sides of 1, the 32-point value minus a 64-point one (other nodes,
other seed) next to their combined standard error: where the difference stays within a
few standard errors, the rule's error is below the noise.
"""

from __future__ import annotations

import argparse

import brdf_rs
import numpy as np


def e_avg(model: str, n: int, alpha: float, eta: float, tol: float, seed: int):
    """``(E_avg, stderr)`` by ``n``-point Gauss-Legendre over direct albedo calls."""
    x, w = np.polynomial.legendre.leggauss(n)
    x, w = (x + 1) / 2, w / 2
    a = brdf_rs.albedo(model, x, alpha=alpha, eta=eta, ks=1, kt=1, tol=tol, seed=seed)
    value = 2 * np.sum(w * x * a.value[:, 0])
    return value, 2 * np.sqrt(np.sum((w * x * a.stderr[:, 0]) ** 2))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default="ggx_dielectric")
    parser.add_argument("--tol", type=float, default=1e-5)
    args = parser.parse_args()
    print("alpha   eta     E_avg(GL32)  GL32 - GL64   combined stderr")
    for alpha in (0.05, 0.2, 0.8):
        for eta in (0.67, 0.95, 1.05, 1.5):
            v32, s32 = e_avg(args.model, 32, alpha, eta, args.tol, 7)
            v64, s64 = e_avg(args.model, 64, alpha, eta, args.tol, 8)
            print(
                f"{alpha:<7g} {eta:<7g} {v32:.6f}     {v32 - v64:+.2e}     {np.hypot(s32, s64):.1e}"
            )


if __name__ == "__main__":
    main()
