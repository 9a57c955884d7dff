"""Two or more builds of brdf-rs side by side on an albedo table, in one run.

Each build is a Python that imports it (its own virtual environment, or a small wrapper
script that sets PYTHONPATH to a directory holding the package). The script runs the
same series of tables (a 64x64 table of benches/albedo_convergence.py: GGX or Beckmann
over mu x alpha, or Torrance-Sparrow over mu x p; fixed sample counts and adaptive `tol`) in a
subprocess per build, alternating the builds for `--rounds` rounds, and keeps each
point's fastest time (the machine is shared and noisy; interleaving spreads the noise
over both). The error is the RMS against the cached quadrature reference of
albedo_convergence.py (benches/results/reference_<model>_*.npy, computed on first use).
Prints the time to RMS 1e-4 and 1e-5 of each build and the ratio, and writes
benches/results/ab_builds_<model>.{md,json,png} (or `--out`).

    python benches/ab_builds.py --model torrance_sparrow \\
        --build "release 0.1.0=/path/to/old/bin/python" --build "this tree=.venv/bin/python"
"""

from __future__ import annotations

import argparse
import itertools
import json
import time
from pathlib import Path

import numpy as np
from _builds import add_build_option, parse_builds, run_worker
from _plot import pyplot

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
TARGETS = (1e-4, 1e-5)


def series() -> dict:
    return {
        "sobol, fixed samples": [{"samples": 256 * 2**k} for k in range(10)],
        "sobol, adaptive tol": [
            {"samples": 256, "tol": 1e-3 / 2**k, "max_samples": 1 << 24} for k in range(12)
        ],
    }


def table_spec(model: str) -> dict:
    """The table's axes and fixed parameters (benches/albedo_convergence.py's)."""
    from albedo_convergence import tables

    return tables()[model]


def worker(model: str, reference: str, budget: float) -> None:
    """Runs every series with the brdf_rs importable here; JSON on stdout."""
    import brdf_rs

    ref = np.load(reference)
    spec = table_spec(model)
    grid, fixed = spec["axes"], spec["fixed"]
    brdf_rs.albedo_table(model, grid, **fixed, samples=64)  # warm-up
    out = {}
    for name, runs in series().items():
        points = []
        for options in runs:
            t = time.perf_counter()
            table = brdf_rs.albedo_table(model, grid, **fixed, **options)
            seconds = time.perf_counter() - t
            err = table.value[..., 0] - ref
            points.append(
                {
                    **options,
                    "seconds": seconds,
                    "rms": float(np.sqrt(np.mean(err**2))),
                    "rms_stderr": float(np.sqrt(np.mean(table.stderr[..., 0] ** 2))),
                    "samples_total": float(table.samples.sum()),
                }
            )
            if seconds > budget or points[-1]["rms"] < TARGETS[-1] / 2:
                break
        out[name] = points
    print(json.dumps(out))


def time_to(points, target):
    """Seconds to reach RMS <= target, log-log interpolated; None if never reached."""
    pts = sorted((p["seconds"], p["rms"]) for p in points)
    best = None
    for (t0, e0), (t1, e1) in itertools.pairwise(pts):
        if e0 <= target:
            best = t0
            break
        if e1 <= target:
            f = (np.log(target) - np.log(e0)) / (np.log(e1) - np.log(e0))
            best = float(np.exp(np.log(t0) + f * (np.log(t1) - np.log(t0))))
            break
    if best is None and pts and pts[0][1] <= target:
        best = pts[0][0]
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_build_option(parser)
    parser.add_argument(
        "--model",
        default="ggx",
        choices=["ggx", "beckmann", "torrance_sparrow"],
        help="the table (benches/albedo_convergence.py's)",
    )
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--budget", type=float, default=8.0, help="seconds per table")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--reference", default=None, help=argparse.SUPPRESS)
    parser.add_argument("--out", type=Path, default=None, help="path without suffix")
    args = parser.parse_args()
    if args.worker:
        worker(args.model, args.reference, args.budget)
        return
    builds = parse_builds(parser, args.build, 2)
    out = args.out or RESULTS / f"ab_builds_{args.model}"
    from albedo_convergence import reference as converged

    np.save(out.with_suffix(".reference.npy"), converged(args.model, table_spec(args.model)))
    reference = str(out.with_suffix(".reference.npy"))
    base = next(iter(builds))
    best: dict[str, dict[str, list[dict]]] = {}
    for r in range(args.rounds):
        for label, python in builds.items():
            run = run_worker(
                python,
                __file__,
                ["--model", args.model, "--reference", reference, "--budget", str(args.budget)],
            )
            print(f"round {r + 1}, {label}: done", flush=True)
            if label not in best:
                best[label] = run
                continue
            for name, points in run.items():
                known = best[label][name]
                for old, new in zip(known, points, strict=False):
                    old["seconds"] = min(old["seconds"], new["seconds"])
                known.extend(points[len(known) :])
    lines = [
        f"# Builds compared on the 64x64 {args.model} albedo table",
        "",
        f"{time.strftime('%Y-%m-%d %H:%M:%S')}; {args.rounds} interleaved rounds, fastest time "
        "per point; RMS against the converged quadrature. Seconds to reach each RMS "
        f"(speed-up over {base}).",
        "",
        "| series | build | RMS 1e-4 | RMS 1e-5 |",
        "|---|---|---:|---:|",
    ]
    ratios = {}
    for name in series():
        times = {}
        for label in builds:
            times[label] = [time_to(best[label][name], t) for t in TARGETS]
            cells = ["—" if t is None else f"{t:.3f} s" for t in times[label]]
            if label != base:
                ratio = [
                    x / y if x and y else None
                    for x, y in zip(times[base], times[label], strict=True)
                ]
                ratios[f"{name}: {label}"] = ratio
                cells = [
                    c if q is None else f"{c} ({q:.1f}x)" for c, q in zip(cells, ratio, strict=True)
                ]
            lines.append(f"| {name} | {label} | {' | '.join(cells)} |")
    print("\n".join(lines))
    out.with_suffix(".reference.npy").unlink()
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    out.with_suffix(".json").write_text(
        json.dumps({"builds": list(builds), "results": best, "speedup": ratios}, indent=1)
    )
    plt = pyplot()
    if plt is None:
        return
    fig, axs = plt.subplots(1, len(series()), figsize=(12, 5), squeeze=False)
    for ax, name in zip(axs[0], series(), strict=True):
        for label in builds:
            pts = sorted((p["seconds"], p["rms"]) for p in best[label][name])
            ax.loglog(*zip(*pts, strict=True), "-o", markersize=3, label=label)
        for t in TARGETS:
            ax.axhline(t, color="grey", lw=0.5)
        ax.set_title(f"{args.model} 64x64, {name}")
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel("RMS error over the table")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=110)
    print(f"wrote {out.with_suffix('.md')}, .json, .png")


if __name__ == "__main__":
    main()
