"""Time 32x32x32 albedo tables of a rough dielectric over (mu, alpha, eta) against
their error, at several per-cell tolerances.

    python benches/dielectric_table.py [--model ggx_dielectric] [--n 32]
        [--tols 4e-4 2e-4 1.5e-4 1e-4 5e-5] [--out benches/results/dielectric_table]

The table: mu_j = (j+0.5)/n, alpha log-spaced in [0.02, 1], eta log-spaced in
[1/2.5, 2.5] (light from inside glass and from outside), ks = kt = 1, the total albedo
over the whole sphere, built by ``brdf_rs.albedo_table`` with randomized Sobol points
(16 replicates), 1024 samples per cell in the first round and ``tol`` per cell after
(``--tols 0``: no tol, ``--samples`` per cell). Each table is timed once, one after the
other. Its error is measured on ``--check`` cells drawn at random against the same
cells recomputed once with another seed and 2^18 samples each: the RMS of the
differences (the reference's own error is included, so the figure is slightly
pessimistic; its RMS standard error is printed), the RMS of the table's reported
standard errors there, and the share of those cells whose difference exceeds 3 combined
standard errors (an honest error bar leaves about 0.3%). Writes ``OUT.md``,
``OUT.json`` and ``OUT.png`` (RMS error against seconds).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import brdf_rs
import numpy as np
from brdf_rs._bench import cpu_model


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default="ggx_dielectric")
    parser.add_argument("--n", type=int, default=32)
    parser.add_argument("--samples", type=int, default=1024)
    parser.add_argument("--tols", type=float, nargs="+", default=[4e-4, 2e-4, 1.5e-4, 1e-4, 5e-5])
    parser.add_argument("--check", type=int, default=256)
    parser.add_argument("--out", type=Path, default=None, help="write OUT.md/.json/.png")
    args = parser.parse_args()
    n = args.n
    axes = {
        "mu": (np.arange(n) + 0.5) / n,
        "alpha": np.geomspace(0.02, 1.0, n),
        "eta": np.geomspace(1 / 2.5, 2.5, n),
    }
    rng = np.random.default_rng(0)
    cells = rng.integers(0, n, size=(args.check, 3))
    mu, alpha, eta = (axes[k][cells[:, i]] for i, k in enumerate(axes))
    start = time.perf_counter()
    ref = brdf_rs.albedo(args.model, mu, alpha=alpha, eta=eta, samples=1 << 18, seed=2)
    ref_seconds = time.perf_counter() - start
    ref_value, ref_se = ref.value[:, 0], ref.stderr[:, 0]
    print(
        f"reference: {args.check} cells, 2^18 samples each, {ref_seconds:.1f} s;"
        f" its RMS standard error {np.sqrt(np.mean(ref_se**2)):.1e}"
    )
    rows = []
    header = "| tol | seconds | G samples | M samples/s | RMS error | RMS stderr | beyond 3 se |"
    print(header)
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for tol in args.tols:
        start = time.perf_counter()
        table = brdf_rs.albedo_table(
            args.model,
            axes,
            samples=args.samples,
            tol=tol if tol > 0 else None,
            seed=1,
            ks=1.0,
            kt=1.0,
        )
        seconds = time.perf_counter() - start
        value, stderr = table.value[..., 0], table.stderr[..., 0]
        got, se = value[tuple(cells.T)], stderr[tuple(cells.T)]
        diff = got - ref_value
        row = {
            "tol": tol,
            "seconds": seconds,
            "samples": int(table.samples.sum()),
            "rms_error": float(np.sqrt(np.mean(diff**2))),
            "rms_stderr": float(np.sqrt(np.mean(se**2))),
            "beyond_3se": float(np.mean(np.abs(diff) > 3 * np.hypot(se, ref_se))),
        }
        rows.append(row)
        print(
            f"| {tol:g} | {seconds:.1f} | {row['samples'] / 1e9:.2f} |"
            f" {row['samples'] / seconds / 1e6:.1f} | {row['rms_error']:.1e} |"
            f" {row['rms_stderr']:.1e} | {row['beyond_3se']:.1%} |"
        )
    if args.out is not None:
        write(args, rows, header, ref_seconds, float(np.sqrt(np.mean(ref_se**2))))


def write(args: argparse.Namespace, rows: list[dict], header: str, ref_s: float, ref_se: float):
    out: Path = args.out
    out.parent.mkdir(parents=True, exist_ok=True)
    n = args.n
    tols = " ".join(f"{r['tol']:g}" for r in rows)
    about = (
        f"`python benches/dielectric_table.py --n {n} --tols {tols}` ({args.model}, brdf-rs"
        f" {brdf_rs.__version__}, {brdf_rs.num_threads()} threads, ISA {brdf_rs.isa()},"
        f" {cpu_model()}; {time.strftime('%Y-%m-%d')}): a"
        f" {n}x{n}x{n} table of the total albedo over mu (texel centres), alpha in"
        f" [0.02, 1] and eta in [1/2.5, 2.5] (both log-spaced), each tolerance timed once;"
        f" the error on {args.check} random cells against 2^18 samples each (another seed,"
        f" {ref_s:.0f} s, RMS standard error {ref_se:.1e}, included in the RMS error)."
    )
    lines = [f"# {args.model}: {n}^3 albedo tables, time against error", "", about, ""]
    lines += [header, "|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(
            f"| {r['tol']:g} | {r['seconds']:.1f} | {r['samples'] / 1e9:.2f} |"
            f" {r['samples'] / r['seconds'] / 1e6:.1f} | {r['rms_error']:.1e} |"
            f" {r['rms_stderr']:.1e} | {r['beyond_3se']:.1%} |"
        )
    out.with_suffix(".md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    out.with_suffix(".json").write_text(
        json.dumps({"about": about, "rows": rows}, indent=1) + "\n", encoding="utf-8"
    )
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.4, 3.6))
    ax = fig.add_subplot()
    ax.loglog([r["seconds"] for r in rows], [r["rms_error"] for r in rows], "o-")
    for r in rows:
        ax.annotate(f"tol {r['tol']:g}", (r["seconds"], r["rms_error"]), fontsize=8)
    ax.axhline(1e-4, color="grey", linestyle=":", linewidth=1)
    ax.axvline(10, color="grey", linestyle=":", linewidth=1)
    ax.set_xlabel("seconds")
    ax.set_ylabel("RMS error")
    ax.set_title(f"{args.model}, {n}³ cells", fontsize=10)
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=100)
    print(f"wrote {out.with_suffix('.md')}, .json, .png")


if __name__ == "__main__":
    main()
