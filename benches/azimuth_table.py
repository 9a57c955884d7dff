"""Time and error bars of 32x32 Ward albedo tables with an azimuth axis and averaged.

Tables over (mu, alpha_x) with alpha_y = 0.3, kd = 0, ks = 1, at the default 4096
samples per cell (16 Sobol replicates): at phi = 0 (the plain table), with a phi axis of
8 values evenly over [0, 2π) (R(φ) = R(−φ) = R(π − φ): 3 distinct cells per (mu,
alpha_x)), and the azimuth average (phi="average"). Prints a table; writes
``benches/results/azimuth_table.md``. One run of each, wall-clock, after a warm-up.

    python benches/azimuth_table.py
"""

from __future__ import annotations

import time
from pathlib import Path

import brdf_rs
import numpy as np

MU = (np.arange(32) + 0.5) / 32
ALPHA_X = np.geomspace(0.02, 1.0, 32)
FIXED = {"alpha_y": 0.3, "kd": 0.0, "ks": 1.0}
PHI = np.linspace(0, 2 * np.pi, 8, endpoint=False)


def run(label: str, axes: dict[str, np.ndarray], **kwargs: object) -> str:
    start = time.perf_counter()
    table = brdf_rs.albedo_table("ward", axes, **FIXED, **kwargs)  # type: ignore[arg-type]
    seconds = time.perf_counter() - start
    se = table.stderr[..., 0]
    cells = table.value[..., 0].size
    return (
        f"| {label} | {cells} | {seconds:.2f} | {float(np.median(se)):.2e} | "
        f"{float(se.max()):.2e} | {int(np.median(table.samples))} |"
    )


def run_every_cell() -> str:
    """The phi axis without the symmetry: all 8192 cells by one brdf_rs.albedo call."""
    start = time.perf_counter()
    r = brdf_rs.albedo(
        "ward",
        MU[:, None, None],
        phi=PHI[None, None, :],
        alpha_x=ALPHA_X[None, :, None],
        **FIXED,  # type: ignore[arg-type]
    )
    seconds = time.perf_counter() - start
    se = r.stderr[..., 0]
    return (
        f"| 32x32x8, every cell computed (albedo) | {se.size} | {seconds:.2f} | "
        f"{float(np.median(se)):.2e} | {float(se.max()):.2e} | {int(np.median(r.samples))} |"
    )


def main() -> None:
    brdf_rs.albedo_table("ward", {"mu": MU[:4], "alpha_x": ALPHA_X[:4]}, **FIXED)  # warm-up
    rows = [
        "| table | cells | seconds | median stderr | max stderr | samples per cell |",
        "|---|---|---|---|---|---|",
        run("32x32, phi = 0", {"mu": MU, "alpha_x": ALPHA_X}),
        run("32x32x8, phi axis", {"mu": MU, "alpha_x": ALPHA_X, "phi": PHI}),
        run_every_cell(),
        run("32x32, phi = 'average'", {"mu": MU, "alpha_x": ALPHA_X}, phi="average"),
    ]
    text = "\n".join(rows)
    threads = brdf_rs.num_threads()
    header = (
        "# Ward albedo tables with an azimuth axis\n\n"
        f"32 mu x 32 alpha_x (0.02..1, log), alpha_y = 0.3, 4096 samples per cell, "
        f"{threads} threads, brdf_rs {brdf_rs.__version__}. stderr: channel 0 (grey). "
        "The phi axis computes 3 of its 8 azimuths and copies the symmetric ones.\n\n"
    )
    print(text)
    out = Path(__file__).parent / "results" / "azimuth_table.md"
    out.write_text(header + text + "\n")


if __name__ == "__main__":
    main()
