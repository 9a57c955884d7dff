"""White furnace of ``ggx_dielectric_ms``: how far its total albedo is from 1.

``ggx_dielectric_ms`` divides ``ggx_dielectric`` by the white interface's albedo E, read
from a table: with ``ks = kt = 1`` its albedo is ``E/E_table``, so the furnace measures
the table's interpolation error (and its cells' noise, stderr 1e-4). For random
(mu, alpha, eta), alpha log-uniform in [1e-3, 1], this script integrates the model's
albedo (light from above at cosine mu; ``eta < 1`` is light from the denser side) to a
standard error of ``--tol`` and prints ``|A − 1|`` by region: ``eta`` near 1 or not,
grazing incidence or not.

    python scripts/dielectric_furnace.py [--cells 2000] [--tol 2e-5] [--seed 0]
"""

from __future__ import annotations

import argparse
import time

import brdf_rs
import numpy as np


def cases(n: int, seed: int) -> dict[str, np.ndarray]:
    """Half the cells with eta within 1e-5..0.1 of 1 (in log), half with |log eta| in
    [0.1, 2.5]; mu = v² (dense near grazing), at least 1e-3."""
    rng = np.random.default_rng(seed)
    mu = np.maximum(rng.uniform(0.0, 1.0, n) ** 2, 1e-3)
    alpha = 10.0 ** rng.uniform(-3.0, 0.0, n)
    near = rng.uniform(size=n) < 0.5
    size = np.where(near, 10.0 ** rng.uniform(-5.0, -1.0, n), rng.uniform(0.1, 2.5, n))
    eta = np.exp(np.where(rng.uniform(size=n) < 0.5, 1.0, -1.0) * size)
    return {"mu": mu, "alpha": alpha, "eta": eta, "near": near}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cells", type=int, default=2000)
    parser.add_argument("--tol", type=float, default=2e-5)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    c = cases(args.cells, args.seed)
    start = time.perf_counter()
    r = brdf_rs.albedo(
        "ggx_dielectric_ms",
        c["mu"],
        ks=1.0,
        kt=1.0,
        alpha=c["alpha"],
        eta=c["eta"],
        samples=1024,
        tol=args.tol,
        seed=args.seed,
    )
    seconds = time.perf_counter() - start
    err = np.abs(r.value[:, 0] - 1.0)
    print(
        f"ggx_dielectric_ms white furnace: {args.cells} cells, tol {args.tol:g}, "
        f"seed {args.seed}, {seconds:.1f} s; largest stderr {r.stderr.max():.1e}"
    )
    print()
    print("| region | cells | max abs(A - 1) | p99 | median | share above 1% |")
    print("|---|---:|---:|---:|---:|---:|")
    grazing = c["mu"] < 0.05
    regions = {
        "abs(log eta) >= 0.1, every mu": ~c["near"],
        "abs(log eta) < 0.1, mu >= 0.05": c["near"] & ~grazing,
        "abs(log eta) < 0.1, mu < 0.05": c["near"] & grazing,
        "all": np.ones_like(grazing),
    }
    for name, m in regions.items():
        e = err[m]
        print(
            f"| {name} | {m.sum()} | {e.max():.4f} | {np.quantile(e, 0.99):.4f} | "
            f"{np.median(e):.5f} | {np.mean(e > 0.01):.3f} |"
        )
    print()
    print("Cells furthest from 1:")
    for q in np.argsort(-err)[:5]:
        print(
            f"  mu {c['mu'][q]:.4g}  alpha {c['alpha'][q]:.4g}  eta {c['eta'][q]:.6g}: "
            f"A = {r.value[q, 0]:.5f} ± {r.stderr[q, 0]:.1e}"
        )


if __name__ == "__main__":
    main()
