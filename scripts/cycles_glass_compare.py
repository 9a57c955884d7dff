"""Compares Blender Cycles' rough-glass albedo tables with ``brdf_rs.albedo`` of
``ggx_dielectric`` over the same grid.

Cycles (Blender 4.x) ships precomputed directional albedos of its GGX glass closure in
``intern/cycles/scene/shader.tables``, written by its generator
``intern/cycles/app/cycles_precompute.cpp``. The file is Blender's, under its own licence,
and is not part of this repository: give its path on the command line.

    python scripts/cycles_glass_compare.py path/to/shader.tables [--samples 65536]
        [--slices 1,4,8,12,15] [--atol 2e-4] [--skip-grazing]

The tables and their grid, as the generator defines them:

- ``table_ggx_glass_E`` and ``table_ggx_glass_inv_E``: 16 × 16 × 16 floats each, laid out
  ``[z][y][x]`` (``x`` fastest; the file prints one ``y`` row per line and a blank line
  between ``z`` slices).
- ``x``: the perceptual roughness ``r = clamp(x/15, 1e-4, 1)``, and the microfacet
  roughness is ``alpha = r²``. The nodes are the ends of the interval, not texel centres.
- ``y``: the cosine of incidence ``mu = clamp(y/15, 1e-4, 1)``, same convention.
- ``z``: ``t = clamp(z/15, 1e-4, 0.99)``, ``F0 = t⁴`` and the index
  ``ior = (1 + sqrt(F0))/(1 − sqrt(F0)) = (1 + t²)/(1 − t²)`` (from 1 to about 99.5;
  denser near 1).
- Each value is the average of ``eval/pdf`` over 2^23 samples of the GGX glass closure
  (reflection and refraction: the whole sphere), with the normal +z and the fixed
  direction ``(sqrt(1 − mu²), 0, mu)`` above the surface, clamped to [0, 1] and printed
  with 6 decimals. ``_E`` is for the relative index ``ior``; ``_inv_E`` for ``1/ior``
  (the same interface lit from the dense side).

In brdf-rs terms each value is the **total** directional albedo of ``ggx_dielectric``
with ``ks = kt = 1``, ``alpha = r²``, ``eta = ior`` (``_E``) or ``1/ior`` (``_inv_E``):
the reflected plus the transmitted energy fraction, ``R + T``, which is what the mean of
``eval/pdf`` of a sampler measures. (A cubature of ``brdf_rs.reference`` over the half
vector reproduces cells of the ``ior ≈ 1.0089`` slice of ``_E`` to about 5e-6; ``R`` plus
``T/ior²`` would be 1.8% off there.) ``alpha`` below brdf-rs's range (``x = 0``:
``alpha = 1e-8``) is raised to its minimum, 1e-7: both are the smooth interface to far
better than the tables' 6 decimals.

A cell agrees when ``|Cycles − brdf_rs| ≤ 5·stderr + atol``: ``stderr`` is brdf-rs's own
standard error, ``atol`` covers Cycles' Monte Carlo error (not published with the
tables), its float32 arithmetic and its 6 printed decimals. The script prints, per table
and slice, the index, the largest difference and where it is, and the cells beyond the
bound; it exits with 1 if any cell is beyond it.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import brdf_rs
import numpy as np

MODEL = "ggx_dielectric"
TABLES = ("ggx_glass_E", "ggx_glass_inv_E")
SIZE = 16
#: brdf-rs's smallest roughness alpha.
ALPHA_MIN = 1e-7


def read_table(text: str, name: str) -> np.ndarray:
    """The table ``table_<name>`` of a ``shader.tables`` text, as an array ``[z, y, x]``."""
    match = re.search(
        rf"static\s+const\s+float\s+table_{re.escape(name)}\s*\[\s*(\d+)\s*\]\s*=\s*\{{(.*?)\}};",
        text,
        re.S,
    )
    if match is None:
        raise ValueError(f"no table_{name} in the file")
    count = int(match.group(1))
    values = [
        float(v) for v in re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", match.group(2))
    ]
    if len(values) != count or count != SIZE**3:
        raise ValueError(
            f"table_{name}: {len(values)} values, declared {count}, expected {SIZE**3}"
        )
    return np.array(values).reshape(SIZE, SIZE, SIZE)


def grid() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(roughness r, mu, ior)`` at the table's nodes (x, y, z), as Cycles computes them
    (in float32, then widened)."""
    k = np.arange(SIZE, dtype=np.float32) / np.float32(SIZE - 1)
    rough = np.clip(k, np.float32(1e-4), np.float32(1.0))
    mu = np.clip(k, np.float32(1e-4), np.float32(1.0))
    t = np.clip(k, np.float32(1e-4), np.float32(0.99))
    f0 = np.minimum(t**4, np.float32(0.99))
    root = np.sqrt(f0)
    ior = (np.float32(1) + root) / (np.float32(1) - root)
    return rough.astype(np.float64), mu.astype(np.float64), ior.astype(np.float64)


def compare(
    table: np.ndarray,
    inverse: bool,
    slices: list[int],
    samples: int,
    atol: float,
    skip_grazing: bool,
) -> int:
    """Prints the comparison of the slices ``slices`` of one table; returns how many cells
    are beyond the bound."""
    rough, mu, ior = grid()
    alpha = np.maximum(rough**2, ALPHA_MIN)
    rows = slice(1, None) if skip_grazing else slice(None)
    beyond = 0
    for z in slices:
        eta = 1.0 / ior[z] if inverse else ior[z]
        result = brdf_rs.albedo(
            MODEL,
            mu[rows, None],
            samples=samples,
            component="total",
            ks=1.0,
            kt=1.0,
            eta=eta,
            alpha=alpha[None, :],
        )
        ours = result.value[..., 0]
        stderr = result.stderr[..., 0]
        theirs = table[z, rows, :]
        diff = theirs - ours
        bound = 5.0 * stderr + atol
        bad = np.abs(diff) > bound
        beyond += int(bad.sum())
        y, x = np.unravel_index(int(np.argmax(np.abs(diff))), diff.shape)
        y_index = y + (1 if skip_grazing else 0)
        print(
            f"  z={z:2d} eta={eta:<10.6g} max |diff| {abs(diff[y, x]):.2e} at "
            f"mu={mu[y_index]:.4g} r={rough[x]:.4g} (Cycles {theirs[y, x]:.6f}, "
            f"brdf-rs {ours[y, x]:.6f} ± {stderr[y, x]:.1e}); beyond the bound: {int(bad.sum())}"
        )
        for yy, xx in zip(*np.nonzero(bad), strict=True):
            yi = yy + (1 if skip_grazing else 0)
            print(
                f"      mu={mu[yi]:.4g} r={rough[xx]:.4g}: Cycles {theirs[yy, xx]:.6f}, "
                f"brdf-rs {ours[yy, xx]:.6f} ± {stderr[yy, xx]:.1e}"
            )
    return beyond


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("tables", type=Path, help="Cycles' intern/cycles/scene/shader.tables")
    parser.add_argument("--samples", type=int, default=1 << 16, help="albedo samples per cell")
    parser.add_argument(
        "--slices",
        default="1,4,8,12,15",
        help="comma-separated z indices (0-15) of the index axis to compare",
    )
    parser.add_argument("--atol", type=float, default=2e-4, help="allowance for Cycles' own error")
    parser.add_argument(
        "--skip-grazing",
        action="store_true",
        help="leave out the row mu = 1e-4 (where float32 sampling is least reliable)",
    )
    args = parser.parse_args(argv)
    text = args.tables.read_text(encoding="utf-8")
    slices = [int(s) for s in args.slices.split(",") if s.strip()]
    if not all(0 <= z < SIZE for z in slices):
        parser.error(f"--slices: indices must be in [0, {SIZE - 1}]")
    beyond = 0
    for name in TABLES:
        table = read_table(text, name)
        print(f"table_{name} ({'1/ior' if name.endswith('inv_E') else 'ior'}):")
        beyond += compare(
            table, name.endswith("inv_E"), slices, args.samples, args.atol, args.skip_grazing
        )
    print(f"{beyond} cell(s) beyond 5·stderr + {args.atol:g}" if beyond else "all cells agree")
    return 1 if beyond else 0


if __name__ == "__main__":
    sys.exit(main())
