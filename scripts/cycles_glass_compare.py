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

Where the file is not at hand, ``scripts/cycles_tables_from_binary.py`` writes the same
tables from an installed Blender executable.

For the cells beyond the bound the script prints an independent NumPy estimate of the
same model twice: once scoring 0 for a refraction that leaves on the light's side of the
surface (as Walter et al., pbrt-v4 and brdf-rs do: a single-scattering model has no
such path), once scoring it like any other (Cycles' sampler has that test commented out,
``// valid = valid && (dot(Ng, *wo) < 0);`` in ``bsdf_microfacet.h``). Where light
arrives from the dense side (``_inv_E``), refraction bends toward the surface and the two
differ by up to 0.93 at grazing incidence; the second reproduces Cycles' values.

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


def _visible_normals(wi: np.ndarray, alpha: float, u1: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """Heitz's (2018) GGX visible normals seen from ``wi`` (in the xz plane), written out
    here in NumPy, apart from the library's sampler."""
    vh = np.array([alpha * wi[0], alpha * wi[1], wi[2]])
    vh /= np.linalg.norm(vh)
    t1 = np.array([-vh[1], vh[0], 0.0]) / np.hypot(vh[0], vh[1]) if vh[2] < 1 else np.eye(3)[0]
    t2 = np.cross(vh, t1)
    r, phi = np.sqrt(u1), 2 * np.pi * u2
    p1 = r * np.cos(phi)
    s = 0.5 * (1 + vh[2])
    p2 = (1 - s) * np.sqrt(np.maximum(0, 1 - p1 * p1)) + s * r * np.sin(phi)
    p3 = np.sqrt(np.maximum(0, 1 - p1 * p1 - p2 * p2))
    nh = p1[:, None] * t1 + p2[:, None] * t2 + p3[:, None] * vh
    h = np.stack([alpha * nh[:, 0], alpha * nh[:, 1], np.maximum(nh[:, 2], 1e-7)], axis=1)
    return h / np.linalg.norm(h, axis=1, keepdims=True)


def side_check_estimate(
    mu: float, rough: float, eta: float, side_check: bool, samples: int = 1 << 20
) -> tuple[float, float]:
    """An independent Monte Carlo estimate of the GGX glass albedo, in NumPy: visible
    normals, the exact dielectric F, and the weights ``F·G2/G1`` and ``(1 − F)·G2/G1``
    (Walter et al.'s model with the height-correlated ``G2``). With ``side_check`` a
    refraction that leaves on the light's side of the surface scores 0 (Walter et al.,
    pbrt-v4, brdf-rs); without it, it scores like any other (Cycles: its sampler leaves
    that test commented out). Returns the mean and its standard error."""
    rng = np.random.default_rng(0)
    alpha = max(rough * rough, ALPHA_MIN)
    a2 = alpha * alpha
    wi = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
    h = _visible_normals(wi, alpha, rng.random(samples), rng.random(samples))
    c = h @ wi

    def lam(cos: np.ndarray | float) -> np.ndarray:
        c2 = np.maximum(np.square(cos), 1e-300)
        return 0.5 * (np.sqrt(1 + a2 * (1 - c2) / c2) - 1)

    sin2_t = (1 - c * c) / (eta * eta)
    tir = sin2_t >= 1
    cos_t = np.sqrt(np.maximum(0, 1 - sin2_t))
    rs = (c - eta * cos_t) / (c + eta * cos_t)
    rp = (eta * c - cos_t) / (eta * c + cos_t)
    f = np.where(tir, 1.0, 0.5 * (rs * rs + rp * rp))
    li = lam(mu)
    mu_r = 2 * c * h[:, 2] - mu
    reflected = np.where(mu_r > 0, f * (1 + li) / (1 + li + lam(mu_r)), 0.0)
    mu_t = -mu / eta + h[:, 2] * (c / eta - cos_t)
    leaves = (mu_t < 0) if side_check else np.ones_like(mu_t, dtype=bool)
    transmitted = np.where(~tir & leaves, (1 - f) * (1 + li) / (1 + li + lam(mu_t)), 0.0)
    x = reflected + transmitted
    return float(x.mean()), float(x.std() / np.sqrt(samples))


def explain(table: np.ndarray, inverse: bool, cells: list[tuple[int, int, int]]) -> None:
    """For cells beyond the bound: the independent NumPy estimate with and without the
    test that a refraction leaves on the far side."""
    rough, mu, ior = grid()
    print("  independent NumPy estimates (2^20 samples) of the cells furthest apart:")
    for z, y, x in cells:
        eta = 1.0 / ior[z] if inverse else ior[z]
        with_check = side_check_estimate(mu[y], rough[x], eta, True)
        without = side_check_estimate(mu[y], rough[x], eta, False)
        print(
            f"    eta={eta:.6g} mu={mu[y]:.4g} r={rough[x]:.4g}: Cycles {table[z, y, x]:.6f};"
            f" refractions to the light's side scored 0: {with_check[0]:.6f} ± {with_check[1]:.0e},"
            f" scored: {without[0]:.6f} ± {without[1]:.0e}"
        )


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
    worst: list[tuple[float, tuple[int, int, int]]] = []
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
        for yy, xx in zip(*np.nonzero(bad), strict=True):
            worst.append(
                (
                    abs(float(diff[yy, xx])),
                    (z, int(yy) + rows.start if rows.start else int(yy), int(xx)),
                )
            )
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
    if worst:
        worst.sort(reverse=True)
        picks = worst[:3] + worst[-2:] if len(worst) > 5 else worst
        explain(table, inverse, [cell for _, cell in picks])
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
