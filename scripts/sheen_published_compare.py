"""Compares the sheen models' directional albedo E(mu, alpha) with the published values
that could be found:

- ``charlie_sheen_neubelt`` against three.js' published fit of the same lobe's albedo
  (``IBLSheenBRDF`` in three.js' ``lights_physical_pars_fragment``: the Charlie
  distribution with the visibility term of Neubelt and Pettineo, ``alpha = r²`` for the
  material's sheen roughness ``r``, integrated over the hemisphere and fitted by
  ``exp(a·n·v + b)`` with ``a``, ``b`` quadratics in ``r`` plus a ``1/(r + 0.1)`` term);
- ``zeltner_sheen`` against the albedo plane of Blender Cycles' ``table_sheen_ltc`` (the
  tabulated fit of Zeltner, Burley and Chiang that Cycles ships: 3 planes of 32 x 32, the
  LTC's ``a`` and ``b`` and the albedo, over ``cos = i/31`` and ``alpha = j/31`` at the
  ends), read out of a Blender executable with ``--blender`` (Debian's ``blender``
  package carries one: ``ar x blender_*.deb data.tar.xz && tar -xJf data.tar.xz
  ./usr/bin/blender``). Blender's values stay out of this repository.

    python scripts/sheen_published_compare.py [--blender path/to/blender]

Prints each comparison's grid, brdf-rs' values, the published ones and their largest and
RMS differences. brdf-rs' E of ``charlie_sheen_neubelt`` is a Monte Carlo estimate
(``tol`` 2e-4); ``zeltner_sheen``'s is its closed form.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import brdf_rs
import numpy as np

#: Plane ``b``'s first row in Cycles' ``table_sheen_ltc`` (alpha = 0), as Blender 4.x and
#: 5.x print it: the search key of the table in an executable.
CYCLES_KEY = (0.72363, 0.74617, 0.76908, 0.78618, 0.79981, 0.8111)
CYCLES_SIZE = 32


def three_js_sheen_albedo(nv: np.ndarray, r: np.ndarray) -> np.ndarray:
    """three.js' published fit of the Charlie sheen's albedo (Neubelt's visibility) at
    ``n·v`` and sheen roughness ``r`` (``alpha = r²``), clamped to [0, 1] as it is there."""
    r2 = r * r
    r_inv = 1.0 / (r + 0.1)
    a = -1.9362 + 1.0678 * r + 0.4573 * r2 - 0.8469 * r_inv
    b = -0.6014 + 0.5538 * r - 0.4670 * r2 - 0.1255 * r_inv
    return np.clip(np.exp(a * nv + b), 0.0, 1.0)


def charlie_vs_three_js(tol: float = 2e-4) -> dict[str, np.ndarray]:
    """brdf-rs' E of ``charlie_sheen_neubelt`` at ``alpha = r²`` and three.js' fit on a
    grid of ``mu`` x ``r``; also E at ``alpha = r`` (the other reading of the roughness)."""
    mu = np.array([0.05, 0.1, 0.2, 0.4, 0.6, 0.8, 1.0])
    r = np.array([0.2, 0.3, 0.5, 0.7, 0.9, 1.0])
    ours = brdf_rs.albedo_table(
        "charlie_sheen_neubelt", {"mu": mu, "alpha": r * r}, kd=0, tol=tol, seed=1
    )
    linear = brdf_rs.albedo_table("charlie_sheen_neubelt", {"mu": mu, "alpha": r}, kd=0, tol=tol)
    m, rr = np.meshgrid(mu, r, indexing="ij")
    return {
        "mu": mu,
        "r": r,
        "ours": ours.value[:, :, 0],
        "stderr": ours.stderr[:, :, 0],
        "alpha_r": linear.value[:, :, 0],
        "published": three_js_sheen_albedo(m, rr),
    }


def cycles_sheen_table(binary: Path) -> np.ndarray:
    """Cycles' ``table_sheen_ltc`` as ``[plane][alpha j][cos i]`` (planes a, b, albedo),
    found in a Blender executable by its plane ``b``'s first row."""
    data = binary.read_bytes()
    pattern = np.array(CYCLES_KEY, dtype="<f4").tobytes()
    n = 3 * CYCLES_SIZE**2
    found = []
    start = 0
    while (at := data.find(pattern, start)) >= 0:
        start = at + 1
        table_at = at - 4 * CYCLES_SIZE**2
        if table_at < 0 or table_at % 4 or table_at + 4 * n > len(data):
            continue
        t = np.frombuffer(data, "<f4", n, table_at).reshape(3, CYCLES_SIZE, CYCLES_SIZE)
        if np.all(np.isfinite(t)) and t[2].min() > -1e-3 and t[2].max() <= 1 and t[0].min() >= 0:
            found.append(t.astype(np.float64))
    if len(found) != 1:
        raise SystemExit(f"expected one sheen table in {binary}, found {len(found)}")
    return found[0]


def zeltner_vs_cycles(binary: Path) -> dict[str, np.ndarray]:
    """zeltner_sheen's closed-form E and Cycles' albedo plane on Cycles' grid (its first
    column, cos = 0, where brdf-rs' f is 0, and first row, alpha = 0, below the model's
    range, left out)."""
    table = cycles_sheen_table(binary)
    k = np.arange(1, CYCLES_SIZE) / (CYCLES_SIZE - 1)
    ours = brdf_rs.energy_compensation_table("zeltner_sheen", k, np.maximum(k, 0.01))
    return {
        "mu": k,
        "alpha": k,
        "ours": np.asarray(ours.e),  # [mu][alpha]
        "published": table[2, 1:, 1:].T,  # [cos][alpha]
    }


def _compare(
    c: dict[str, np.ndarray], col: str, name: str, cut: float, pick: slice | np.ndarray
) -> np.ndarray:
    """Prints brdf-rs' values, the published ones and their difference at the rows and
    columns ``pick`` (indices, or a slice), the largest and RMS difference over every
    cell, and the largest where mu and the column's quantity are at least ``cut``; returns
    where they are (a mask of the cells)."""
    ours, pub = c["ours"], c["published"]
    d = np.abs(ours - pub)
    rows, cols = (np.arange(n)[pick] for n in d.shape)
    cells = np.ix_(rows, cols)
    print(f"\nrows mu = {c['mu'][rows]}, columns {col} = {c[col][cols]}")
    print(
        f"\nbrdf-rs:\n{ours[cells]}\n\n{name}:\n{pub[cells]}\n\ndifference:\n{(ours - pub)[cells]}"
    )
    i, j = np.unravel_index(d.argmax(), d.shape)
    print(
        f"\nmax |difference| {d.max():.4f} at mu = {c['mu'][i]:.3g}, {col} = {c[col][j]:.3g};"
        f" RMS {float(np.sqrt(np.mean(d * d))):.4f}"
    )
    inner = (c["mu"] >= cut)[:, None] & (c[col] >= cut)[None, :]
    print(f"mu >= {cut} and {col} >= {cut}: max |difference| {d[inner].max():.4f}")
    return inner


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--blender", type=Path, help="a Blender executable (4.x or 5.x)")
    args = parser.parse_args(argv)
    np.set_printoptions(precision=4, suppress=True, linewidth=120)

    c = charlie_vs_three_js()
    print("# charlie_sheen_neubelt against three.js' fit (alpha = r²)")
    print(f"\nbrdf-rs' largest standard error: {c['stderr'].max():.1e}")
    inner = _compare(c, "r", "three.js' fit", 0.5, slice(None))
    d_lin = np.abs(c["alpha_r"] - c["published"])
    print(f"the same cells with alpha = r instead: max |difference| {d_lin[inner].max():.4f}")

    if args.blender is not None:
        z = zeltner_vs_cycles(args.blender)
        print("\n# zeltner_sheen against Cycles' table_sheen_ltc albedo (cos, alpha = k/31)")
        _compare(z, "alpha", "Cycles", 0.2, np.array([0, 3, 7, 15, 23, 30]))
        signed = z["ours"] - z["published"]
        lit = z["published"] > 0.05
        band = np.mean((signed[lit] >= 0.01) & (signed[lit] <= 0.035))
        print(
            f"where Cycles' albedo exceeds 0.05 ({lit.sum()} of {lit.size} cells): brdf-rs minus"
            f" Cycles from {signed[lit].min():.4f} to {signed[lit].max():.4f}, median"
            f" {np.median(signed[lit]):.4f}, {band:.0%} of them between 0.01 and 0.035"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
