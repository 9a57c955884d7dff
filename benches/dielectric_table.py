"""Time a 32x32x32 albedo table of a rough dielectric over (mu, alpha, eta), and its error.

    python benches/dielectric_table.py [--model ggx_dielectric] [--n 32] [--samples 4096]

The table: mu_j = (j+0.5)/n, alpha log-spaced in [0.02, 1], eta log-spaced in [1/2.5, 2.5]
(light from inside glass and from outside), ks = kt = 1, total albedo (the component
over the whole sphere). It is built twice: once with ``--samples`` per cell and the
default randomized Sobol points (16 replicates), timed, and once with a different seed
and 16x the samples as the reference. Reported: the build time, the RMS over the table
of the difference to the reference (its own error is about 4x smaller, and is included
in the figure, which is therefore slightly pessimistic), the RMS of the reported
standard errors, and the share of cells whose difference exceeds 3 combined standard
errors (an honest error bar leaves about 0.3%).
"""

from __future__ import annotations

import argparse
import time

import brdf_rs
import numpy as np


def table(model: str, n: int, samples: int, seed: int) -> tuple[brdf_rs.Table, float]:
    axes = {
        "mu": (np.arange(n) + 0.5) / n,
        "alpha": np.geomspace(0.02, 1.0, n),
        "eta": np.geomspace(1 / 2.5, 2.5, n),
    }
    start = time.perf_counter()
    t = brdf_rs.albedo_table(model, axes, samples=samples, seed=seed, ks=1.0, kt=1.0)
    return t, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default="ggx_dielectric")
    parser.add_argument("--n", type=int, default=32)
    parser.add_argument("--samples", type=int, default=4096)
    args = parser.parse_args()
    got, seconds = table(args.model, args.n, args.samples, seed=1)
    ref, ref_seconds = table(args.model, args.n, 16 * args.samples, seed=2)
    diff = got.value[..., 0] - ref.value[..., 0]
    combined = np.hypot(got.stderr[..., 0], ref.stderr[..., 0])
    print(
        f"{args.model} {args.n}^3 table, {args.samples} samples/cell:"
        f" {seconds:.2f} s ({brdf_rs.num_threads()} threads);"
        f" RMS vs reference {np.sqrt(np.mean(diff**2)):.2e},"
        f" RMS stderr {np.sqrt(np.mean(got.stderr[..., 0] ** 2)):.2e},"
        f" beyond 3 se {np.mean(np.abs(diff) > 3 * combined):.2%},"
        f" max total {got.value[..., 0].max():.4f};"
        f" reference ({16 * args.samples} samples/cell) {ref_seconds:.1f} s"
    )


if __name__ == "__main__":
    main()
