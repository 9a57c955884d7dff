"""Measures the multiple-scattering lobes against the white furnace.

For ``ggx`` and ``beckmann`` with F = 1, the single-scattering albedo (integrated to a
standard error of ``--tol``) plus the ``*_ms`` lobe's albedo should be 1 at every
incidence and roughness; the difference is the energy table's interpolation error. The
grid is off the table's nodes in alpha and reaches grazing incidence.
It also counts negative ``*_ms`` values on random direction pairs (half of them within
1e-3 of the horizon) over the table's whole alpha range, in both dtypes.

    python scripts/furnace_check.py [--tol 2e-6] [--out benches/results/furnace.md]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import brdf_rs
import numpy as np

MU = np.array([0.001, 0.01, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 0.95, 1.0])


def furnace(model: str, tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    # Off the table's nodes (97, log-uniform): 0.37 of the way through every other
    # interval, and through the last one.
    k = np.append(np.arange(0, 96, 2), 95) + 0.37
    alpha = 1e-3 * 1e3 ** (k / 96)
    single = brdf_rs.albedo(
        model, MU[:, None], kd=0, ks=1, alpha=alpha[None, :], samples=1 << 12, tol=tol
    )
    multiple = brdf_rs.albedo(f"{model}_ms", MU[:, None], ks=1, alpha=alpha[None, :])
    total = single.value[..., 0] + multiple.value[..., 0]
    return alpha, total - 1, single.stderr[..., 0]


def negatives(model: str, n: int = 200_000) -> dict[str, int]:
    rng = np.random.default_rng(1)

    def draw() -> np.ndarray:
        v = rng.normal(size=(n, 3))
        v[:, 2] = np.abs(v[:, 2])
        v[: n // 2, 2] *= 1e-3 * rng.random(n // 2)
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    wi, wo = draw(), draw()
    alpha = np.exp(rng.uniform(np.log(1e-3), 0.0, n))
    out = {}
    for dtype in (np.float64, np.float32):
        f = brdf_rs.eval(f"{model}_ms", wi.astype(dtype), wo.astype(dtype), ks=1, alpha=alpha)
        out[np.dtype(dtype).name] = int((f[:, 0] < 0).sum())
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tol", type=float, default=2e-6)
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args()
    lines = [
        "| model | largest \\|E + E_ms − 1\\| | at (mu, alpha) | largest for mu ≥ 0.1 | "
        "largest stderr of E | negative *_ms values (f64 / f32, of 200k) |",
        "|---|---:|---|---:|---:|---|",
    ]
    for model in ("ggx", "beckmann"):
        t0 = time.perf_counter()
        alpha, err, se = furnace(model, args.tol)
        i, j = np.unravel_index(np.argmax(np.abs(err)), err.shape)
        neg = negatives(model)
        lines.append(
            f"| {model} | {np.abs(err).max():.2e} | ({MU[i]:g}, {alpha[j]:.3g}) | "
            f"{np.abs(err[MU >= 0.1]).max():.2e} | {se.max():.1e} | "
            f"{neg['float64']} / {neg['float32']} |"
        )
        print(f"{model}: {time.perf_counter() - t0:.1f} s", flush=True)
    text = "\n".join(lines)
    print(text)
    if args.out:
        args.out.write_text(
            "White furnace of the multiple-scattering lobes (`python scripts/furnace_check.py"
            f" --tol {args.tol:g}`): {len(MU)} incidences from 0.001 to 1 × 49 alphas in"
            " [1e-3, 1], off the table's nodes.\n\n" + text + "\n"
        )


if __name__ == "__main__":
    main()
