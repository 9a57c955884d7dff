"""Time a 32x32x32 albedo table of a rough dielectric over (mu, alpha, eta), and its error.

    python benches/dielectric_table.py [--model ggx_dielectric] [--n 32] [--tol 1e-4]

The table: mu_j = (j+0.5)/n, alpha log-spaced in [0.02, 1], eta log-spaced in
[1/2.5, 2.5] (light from inside glass and from outside), ks = kt = 1, the total albedo
over the whole sphere, built by ``brdf_rs.albedo_table`` with randomized Sobol points
(16 replicates), 1024 samples per cell in the first round and ``tol`` per cell after
(``--tol 0``: no tol, ``--samples`` per cell). Timed once. Its error is measured on
``--check`` cells drawn at random against the same cells recomputed with another seed
and 2^18 samples each: the RMS of the differences (the reference's own error is
included, so the figure is slightly pessimistic), the RMS of the table's reported
standard errors there, and the share of those cells whose difference exceeds 3 combined
standard errors (an honest error bar leaves about 0.3%).
"""

from __future__ import annotations

import argparse
import time

import brdf_rs
import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default="ggx_dielectric")
    parser.add_argument("--n", type=int, default=32)
    parser.add_argument("--samples", type=int, default=1024)
    parser.add_argument("--tol", type=float, default=1e-4)
    parser.add_argument("--check", type=int, default=256)
    args = parser.parse_args()
    n = args.n
    axes = {
        "mu": (np.arange(n) + 0.5) / n,
        "alpha": np.geomspace(0.02, 1.0, n),
        "eta": np.geomspace(1 / 2.5, 2.5, n),
    }
    tol = args.tol if args.tol > 0 else None
    start = time.perf_counter()
    table = brdf_rs.albedo_table(
        args.model, axes, samples=args.samples, tol=tol, seed=1, ks=1.0, kt=1.0
    )
    seconds = time.perf_counter() - start
    value, stderr = table.value[..., 0], table.stderr[..., 0]
    rng = np.random.default_rng(0)
    cells = rng.integers(0, n, size=(args.check, 3))
    mu, alpha, eta = (axes[k][cells[:, i]] for i, k in enumerate(axes))
    start = time.perf_counter()
    ref = brdf_rs.albedo(args.model, mu, alpha=alpha, eta=eta, samples=1 << 18, seed=2)
    ref_seconds = time.perf_counter() - start
    got = value[tuple(cells.T)]
    se = stderr[tuple(cells.T)]
    diff = got - ref.value[:, 0]
    combined = np.hypot(se, ref.stderr[:, 0])
    print(
        f"{args.model} {n}^3 table (tol {tol}, first round {args.samples}):"
        f" {seconds:.1f} s on {brdf_rs.num_threads()} threads,"
        f" {table.samples.sum() / 1e9:.2f} G samples;"
        f" stderr RMS {np.sqrt(np.mean(stderr**2)):.2e}, max {stderr.max():.2e};"
        f" on {args.check} cells against 2^18 samples ({ref_seconds:.1f} s):"
        f" RMS error {np.sqrt(np.mean(diff**2)):.2e}, beyond 3 se"
        f" {np.mean(np.abs(diff) > 3 * combined):.1%}; max total {value.max():.4f}"
    )


if __name__ == "__main__":
    main()
