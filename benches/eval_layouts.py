"""Throughput of brdf_rs.eval by input layout: contiguous rows against broadcasts.

Every light against every pixel is an outer product, ``eval(m, wi[None, :, :],
wo[:, None, :])``: no row is stored, each input is read through broadcast axes. This
bench times that layout (and a Fortran-ordered and a reversed input) against the same
number of contiguous rows, in one run, interleaved, and reports the ratio.

    python benches/eval_layouts.py [--models torrance_sparrow lambert] [--side 2000]
    python benches/eval_layouts.py --replot     # redraw the plot from the saved results

Writes benches/results/eval_layouts.{md,json,png}.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import brdf_rs
import numpy as np
from _plot import pyplot

RESULTS = Path(__file__).resolve().parent / "results"


def unit(rng: np.random.Generator, n: int, dtype: type) -> np.ndarray:
    v = rng.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2])
    return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(dtype)


def layouts(side: int, dtype: type) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(0)
    a, b = unit(rng, side, dtype), unit(rng, side, dtype)
    wi = np.ascontiguousarray(np.broadcast_to(a[None, :, :], (side, side, 3)))
    wo = np.ascontiguousarray(np.broadcast_to(b[:, None, :], (side, side, 3)))
    return {
        "contiguous (side², 3)": (wi.reshape(-1, 3), wo.reshape(-1, 3)),
        "outer product (1, side, 3) × (side, 1, 3)": (a[None, :, :], b[:, None, :]),
        "Fortran order (side², 3)": (np.asfortranarray(wi.reshape(-1, 3)), wo.reshape(-1, 3)),
        "reversed rows (side², 3)[::-1]": (wi.reshape(-1, 3)[::-1], wo.reshape(-1, 3)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", nargs="+", default=["torrance_sparrow", "lambert", "ggx"])
    ap.add_argument("--side", type=int, default=2000, help="side² pairs per call")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", type=Path, default=RESULTS / "eval_layouts")
    ap.add_argument(
        "--replot", action="store_true", help="redraw the plot from the saved JSON; no timing"
    )
    args = ap.parse_args()
    if args.replot:
        saved = json.loads(args.out.with_suffix(".json").read_text())
        write_plot(args.out.with_suffix(".png"), saved)
        return
    rows = []
    n = args.side**2
    for dtype in (np.float64, np.float32):
        cases = layouts(args.side, dtype)
        for model in args.models:
            times: dict[str, list[float]] = {name: [] for name in cases}
            for _ in range(args.repeat):  # interleaved: one of each per round
                for name, (wi, wo) in cases.items():
                    t0 = time.perf_counter()
                    brdf_rs.eval(model, wi, wo)
                    times[name].append(time.perf_counter() - t0)
            base = statistics.median(times["contiguous (side², 3)"])
            for name, ts in times.items():
                t = statistics.median(ts)
                rows.append(
                    {
                        "model": model,
                        "dtype": np.dtype(dtype).name,
                        "layout": name,
                        "m_per_s": n / t / 1e6,
                        "vs_contiguous": base / t,
                        "pairs": n,
                        "threads": brdf_rs.num_threads(),
                    }
                )
                print(
                    f"{model:18s} {np.dtype(dtype).name:8s} {name:44s} "
                    f"{n / t / 1e6:8.1f} M/s  {base / t:5.2f}× contiguous",
                    flush=True,
                )
    lines = [
        f"`brdf_rs.eval` by input layout, {n:,} pairs per call, median of {args.repeat} "
        f"interleaved rounds, {brdf_rs.num_threads()} threads "
        "(`python benches/eval_layouts.py`).",
        "",
        "| model | dtype | layout | M evals/s | × contiguous |",
        "|---|---|---|---:|---:|",
    ]
    lines += [
        f"| {r['model']} | {r['dtype']} | {r['layout']} | {r['m_per_s']:.1f} | "
        f"{r['vs_contiguous']:.2f} |"
        for r in rows
    ]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    args.out.with_suffix(".json").write_text(json.dumps(rows, indent=1))
    write_plot(args.out.with_suffix(".png"), rows)


def write_plot(path: Path, rows: list[dict]) -> None:
    plt = pyplot()
    if plt is None:
        return
    labels = sorted({r["layout"] for r in rows}, key=lambda s: not s.startswith("contig"))
    keys = sorted({(r["model"], r["dtype"]) for r in rows})
    fig, ax = plt.subplots(figsize=(10, 5.2))
    width = 0.8 / len(labels)
    for i, label in enumerate(labels):
        values = [
            next(
                r["m_per_s"] for r in rows if (r["model"], r["dtype"]) == k and r["layout"] == label
            )
            for k in keys
        ]
        ax.bar(np.arange(len(keys)) + i * width, values, width, label=label)
    ax.set_xticks(np.arange(len(keys)) + 0.4 - width / 2)
    ax.set_xticklabels([f"{m}\n{d}" for m, d in keys], fontsize=10)
    ax.set_ylabel("million evaluations / s")
    title = "brdf_rs.eval throughput by input layout"
    if "pairs" in rows[0]:
        title += f", {rows[0]['pairs']:,} pairs per call, {rows[0]['threads']} threads"
    ax.set_title(title)
    # Below the axes, where it covers no bar.
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=10, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
