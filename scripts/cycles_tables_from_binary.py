"""Writes Cycles' rough-glass albedo tables, read out of a Blender executable, as a
``shader.tables``-style text file that ``scripts/cycles_glass_compare.py`` reads.

Blender compiles ``intern/cycles/scene/shader.tables`` into its executable; where the
source text is not at hand, an installed Blender (for example Debian's ``blender``
package: ``ar x blender_*.deb data.tar.xz && tar -xJf data.tar.xz ./usr/bin/blender``)
carries the same float32 arrays. This script finds them:

- ``table_ggx_glass_E`` and ``table_ggx_glass_inv_E`` (16³ floats each) both begin with
  their ``ior = 1`` slice, which is 1 up to the generator's Monte Carlo noise. The search
  key is that slice's first row as Blender 4.x and 5.x print it (``--key``); the script
  finds every 16³ block that begins with it and whose values all lie in [0, 1] and whose
  first slice is within 1e-4 of 1.
- Two such blocks must exist, with a block of 16² values in [0, 1] (``table_ggx_glass_Eavg``)
  between them. The source declares ``_E``, ``_Eavg``, ``_inv_E`` in that order; the
  compiler may lay them out in either direction, so the script tells the two apart by a
  fact of the tables themselves: ``_Eavg[z][x]`` is the cosine-weighted average over mu
  of ``_E[z][·][x]`` (the generator's own definition), and only the true ``_E`` matches it
  (the script prints both distances).

    python scripts/cycles_tables_from_binary.py path/to/blender -o shader.tables

The tables are Blender's (Apache-2.0) and stay out of this repository: write the output
outside it.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

SIZE = 16
#: The first row of the ior = 1 slice of both glass tables, as Blender 4.x/5.x print it.
KEY = (0.999985, 1.0, 0.999989, 0.99999, 1.0, 0.999999)


def blocks(data: bytes, key: tuple[float, ...]) -> list[int]:
    """Byte offsets of the 16³ float32 blocks that begin with ``key`` and look like a
    glass table (values in [0, 1], the first slice within 1e-4 of 1)."""
    pattern = np.array(key, dtype="<f4").tobytes()
    found, start = [], 0
    while (at := data.find(pattern, start)) >= 0:
        start = at + 1
        if at % 4 or at + 4 * SIZE**3 > len(data):
            continue
        block = np.frombuffer(data, "<f4", SIZE**3, at)
        if np.all((block >= 0) & (block <= 1)) and np.all(np.abs(block[: SIZE**2] - 1) < 1e-4):
            found.append(at)
    return found


def eavg_of(e: np.ndarray) -> np.ndarray:
    """``E_avg[z][x] = 2 ∫ E(mu)·mu dmu`` over the 16 mu nodes ``y/15`` (trapezoids), the
    generator's cosine-weighted average, for telling ``_E`` from ``_inv_E``."""
    mu = np.arange(SIZE) / (SIZE - 1)
    return 2 * np.trapezoid(e * mu[None, :, None], mu, axis=1)


def write(path: Path, tables: dict[str, np.ndarray]) -> None:
    lines = ["/* Cycles' glass albedo tables, read out of a Blender executable. */", ""]
    for name, table in tables.items():
        flat = table.reshape(-1, SIZE)
        body = ",\n".join("  " + ", ".join(f"{v:.6f}f" for v in row) for row in flat)
        lines += [f"static const float table_{name}[{table.size}] = {{", body, "};", ""]
    path.write_text("\n".join(lines))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("binary", type=Path, help="a Blender executable (4.x or 5.x)")
    parser.add_argument("-o", "--out", type=Path, required=True, help="the text file to write")
    parser.add_argument(
        "--key",
        default=",".join(f"{v:g}" for v in KEY),
        help="the first values of both tables, comma-separated",
    )
    args = parser.parse_args(argv)
    data = args.binary.read_bytes()
    key = tuple(float(v) for v in args.key.split(","))
    found = blocks(data, key)
    if len(found) != 2:
        print(f"expected 2 glass tables, found {len(found)} at {found}", file=sys.stderr)
        return 1
    first, second = sorted(found)
    gap = (second - first) // 4 - SIZE**3
    if gap != SIZE**2:
        print(
            f"expected the 16² E_avg table between the two; the gap is {gap} floats",
            file=sys.stderr,
        )
        return 1
    a = np.frombuffer(data, "<f4", SIZE**3, first).reshape(SIZE, SIZE, SIZE)
    b = np.frombuffer(data, "<f4", SIZE**3, second).reshape(SIZE, SIZE, SIZE)
    eavg = np.frombuffer(data, "<f4", SIZE**2, first + 4 * SIZE**3).reshape(SIZE, SIZE)
    da, db = (float(np.max(np.abs(eavg_of(t.astype(np.float64)) - eavg))) for t in (a, b))
    print(f"E_avg against the two blocks' averages over mu: {da:.2e} (first), {db:.2e} (second)")
    if min(da, db) > 0.02 or max(da, db) < 2 * min(da, db):
        print("cannot tell _E from _inv_E by their E_avg", file=sys.stderr)
        return 1
    e, inv_e = (a, b) if da < db else (b, a)
    write(args.out, {"ggx_glass_E": e, "ggx_glass_Eavg": eavg, "ggx_glass_inv_E": inv_e})
    print(f"wrote {args.out}: ggx_glass_E, ggx_glass_Eavg, ggx_glass_inv_E")
    return 0


if __name__ == "__main__":
    sys.exit(main())
