"""White furnace of ``ggx_dielectric_ms``: how far its total albedo is from 1.

``ggx_dielectric_ms`` divides ``ggx_dielectric`` by the white interface's albedo E, read
from a table: with ``ks = kt = 1`` its albedo is ``E/E_table``, so the furnace measures
the table's interpolation error (and its cells' noise, stderr 1e-4). For random
(mu, alpha, eta) over the whole parameter range (alpha log-uniform in [1e-3, 1], mu
down to 1e-12, eta from an ulp of 1 out to 1e7 and 1e-7), this script integrates
the model's albedo (light from above at cosine mu; ``eta < 1`` is light from the denser
side) to a standard error of ``--tol`` and prints ``|A − 1|`` by region: how far
``eta`` is from 1, grazing incidence or not.

    python scripts/dielectric_furnace.py [--cells 4000] [--tol 2e-5] [--seed 0]
"""

from __future__ import annotations

import argparse
import time

import brdf_rs
import numpy as np


def cases(n: int, seed: int) -> dict[str, np.ndarray]:
    """A quarter of the cells each with |ln eta| log-uniform in [1e-16, 1e-6] (the last
    ulps before 1) and in [1e-6, 0.1], uniform in [0.1, 2.5] and in [2.5, ln 1e7] (the
    parameter range's end), either side of 1; mu log-uniform in [1e-4, 1] for half the
    cells (the grazing layers; down to 1e-12 in the first band), v² for uniform v (at
    least 1e-4) for the others."""
    rng = np.random.default_rng(seed)
    band = rng.integers(0, 4, n)
    size = np.select(
        [band == 0, band == 1, band == 2],
        [
            10.0 ** rng.uniform(-16.0, -6.0, n),
            10.0 ** rng.uniform(-6.0, -1.0, n),
            rng.uniform(0.1, 2.5, n),
        ],
        rng.uniform(2.5, np.log(1e7), n),
    )
    eta = np.exp(np.where(rng.uniform(size=n) < 0.5, 1.0, -1.0) * size)
    lowest = np.where(band == 0, -12.0, -4.0)
    mu = np.where(
        rng.uniform(size=n) < 0.5,
        10.0 ** rng.uniform(lowest, 0.0, n),
        np.maximum(rng.uniform(0, 1, n) ** 2, 1e-4),
    )
    alpha = 10.0 ** rng.uniform(-3.0, 0.0, n)
    return {"mu": mu, "alpha": alpha, "eta": eta, "band": band}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cells", type=int, default=4000)
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
    regions = {}
    # The layer of grazing incidence an index near 1 opens: E changes within mu of about
    # |ln eta|/alpha of grazing.
    # (eta may round to 1 in the first band: no interface, A = 1 exactly.)
    depth = c["mu"] * c["alpha"] / np.maximum(np.abs(np.log(c["eta"])), 1e-300)
    layer = depth < 100
    first = c["band"] == 0
    regions["abs(log eta) < 1e-6, mu >= 100 abs(log eta)/alpha"] = first & ~layer
    regions["abs(log eta) < 1e-6, mu < 100 abs(log eta)/alpha"] = first & layer
    names = ("1e-6 <= abs(log eta) < 0.1", "0.1 <= abs(log eta) < 2.5", "abs(log eta) >= 2.5")
    for band, name in enumerate(names, start=1):
        regions[f"{name}, mu >= 0.05"] = (c["band"] == band) & ~grazing
        regions[f"{name}, mu < 0.05"] = (c["band"] == band) & grazing
    regions["all"] = np.ones_like(grazing)
    for name, m in regions.items():
        e = err[m]
        print(
            f"| {name} | {m.sum()} | {e.max():.4f} | {np.quantile(e, 0.99):.4f} | "
            f"{np.median(e):.5f} | {np.mean(e > 0.01):.3f} |"
        )
    print()
    over = err > 0.01
    if over.any():
        print(
            f"{over.sum()} cells more than 1% from 1: mu at most {c['mu'][over].max():.2g}, "
            f"|ln eta| at most {np.abs(np.log(c['eta'][over])).max():.2g}, "
            f"mu·alpha/|ln eta| at most {depth[over].max():.2g}; "
            f"largest error with mu >= 1e-3: {err[c['mu'] >= 1e-3].max():.4f}"
        )
    print("Cells furthest from 1:")
    for q in np.argsort(-err)[:5]:
        print(
            f"  mu {c['mu'][q]:.4g}  alpha {c['alpha'][q]:.4g}  eta {c['eta'][q]:.6g}: "
            f"A = {r.value[q, 0]:.5f} ± {r.stderr[q, 0]:.1e}"
        )


if __name__ == "__main__":
    main()
