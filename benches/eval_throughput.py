"""Throughput of brdf_rs.eval for every model against a natural NumPy implementation.

Million evaluations per second, float64 and float32, 1 and 2 threads, N random direction
pairs (NumPy arrays in, a fresh NumPy array out, as a user calls it; the 'out=' column
writes into a preallocated array with ``out=`` instead, which saves the kernel's first
touch of fresh pages; the 'fast' columns are ``precision="fast"`` on the same threads, a
fresh array out and ``out=``).
Every number in one table comes from the same run, so the ratios compare like with like
on a noisy machine; a row's brdf-rs columns (and its Numba column) are timed interleaved,
call by call.

The Numba column (``torrance_sparrow`` and ``ggx``): an ``@njit(parallel=True)`` kernel of
the same formula (benches/numba_models.py) on the row's arrays (float32 arrays in and out
for the float32 rows, the arithmetic in float64 as Python's floats make it), returning a
fresh array ('Numba') or a preallocated one ('Numba out='), checked to agree with brdf_rs
to 1e-12 (float32: 1e-5) relative first; skipped when Numba is not installed. The ratios
to Numba compare the kernels, both writing into preallocated arrays ('out=' and 'fast out='
over 'Numba out='): with fresh arrays, the first touch of 100 MB of new pages per call
bounds every column alike.

    python benches/eval_throughput.py                 # all models, N = 4,000,000
    python benches/eval_throughput.py --models torrance_sparrow --repeat 9

Writes benches/results/eval_throughput.{md,json,png}.
"""

from __future__ import annotations

import argparse
import functools
import json
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import brdf_rs  # noqa: E402
import numba_models  # noqa: E402
import numpy_models  # noqa: E402
from _plot import pyplot  # noqa: E402
from brdf_rs._bench import cpu_model  # noqa: E402

RESULTS = HERE / "results"


def extra_args(model: str) -> dict:
    """Parameters a model needs beyond its defaults (a typical material)."""
    if model == "toon_diffuse":
        return {"thresholds": [-0.2, 0.4], "colors": [[0.1, 0, 0], [0.5, 0.5, 0], [1, 1, 1]]}
    if model == "toon_specular":
        return {"threshold": 0.9}
    if model in ("torrance_sparrow", "blinn_phong_fresnel"):
        return {"kd": [0.2, 0.1, 0.05], "p": 50.0}
    if "p" in {p["name"] for p in brdf_rs.models()[model]["params"]}:
        return {"p": 50.0}
    return {}


def directions(rng: np.random.Generator, n: int) -> np.ndarray:
    v = rng.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2])
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    return v


def interleaved_times(columns: dict, repeat: int) -> dict[str, tuple[float, float]]:
    """(minimum, median) wall time of `repeat` calls of each column, one call of each per
    round, after one warm-up call each. A column is ``(threads or None, fn)``: brdf-rs
    runs with that many threads (set before each call)."""

    current = [brdf_rs.num_threads()]

    def call(threads, fn):
        if threads is not None and threads != current[0]:
            brdf_rs.set_num_threads(threads)
            current[0] = threads
        start = time.perf_counter()
        fn()
        return time.perf_counter() - start

    for threads, fn in columns.values():
        call(threads, fn)
    times: dict[str, list[float]] = {key: [] for key in columns}
    for _ in range(repeat):
        for key, (threads, fn) in columns.items():
            times[key].append(call(threads, fn))
    return {key: (min(t), statistics.median(t)) for key, t in times.items()}


def numba_call(model: str, wi: np.ndarray, wo: np.ndarray, extra: dict, out=None):
    """The Numba parallel kernel of `model` as a call returning a fresh array (or writing
    into `out`), after checking it against brdf_rs (None where there is no such kernel)."""
    if model not in numba_models.KERNELS:
        return None
    check = slice(0, 100_000)
    rtol = 1e-12 if wi.dtype == np.float64 else 1e-5
    numba_models.check_agreement(model, wi[check], wo[check], extra, rtol=rtol)
    kernel = numba_models.KERNELS[model]["parallel"]
    args = numba_models.kernel_args(model, extra)
    if out is not None:
        return lambda: kernel(wi, wo, *args, out)
    return lambda: kernel(wi, wo, *args, np.empty((len(wi), 3), dtype=wi.dtype))


def best_time(fn, repeat: int) -> tuple[float, float]:
    """(minimum, median) wall time of `repeat` calls after one warm-up call."""
    fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times), statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=4_000_000, help="direction pairs per call")
    parser.add_argument("--repeat", type=int, default=5, help="timed calls per cell")
    parser.add_argument("--models", nargs="*", default=list(brdf_rs.models()))
    parser.add_argument("--threads", nargs="*", type=int, default=[1, 2])
    parser.add_argument("--out", type=Path, default=RESULTS / "eval_throughput")
    parser.add_argument(
        "--update",
        action="store_true",
        help="re-time only --models and keep every other row of the existing results "
        "(each rerun row records its own date, and the table says which rows were rerun)",
    )
    parser.add_argument(
        "--replot", action="store_true", help="redraw the plot from the saved JSON; no timing"
    )
    args = parser.parse_args()
    if args.replot:
        saved = json.loads(args.out.with_suffix(".json").read_text())
        write_plot(args.out.with_suffix(".png"), saved["meta"], saved["rows"], args.threads)
        return
    if not numba_models.available():
        print("numba is not installed: the Numba column is skipped (pip install numba)")

    rng = np.random.default_rng(1)
    wi64, wo64 = directions(rng, args.n), directions(rng, args.n)
    inputs = {
        "float64": (wi64, wo64),
        "float32": (wi64.astype(np.float32), wo64.astype(np.float32)),
    }
    tangent = np.array([1.0, 0.0, 0.0])
    rows = []
    header = (
        f"{'model':24s} {'dtype':8s} {'numpy':>8s}"
        + "".join(f" {f'{t} thr':>8s} {f'{t} thr n':>9s}" for t in args.threads)
        + f" {'out=':>8s} {'fast':>8s} {'fast o=':>8s} {'numba':>8s} {'numba o=':>8s}"
        + f" {'x numba':>8s} {'fast x':>7s}"
        + f" {'x numpy':>8s}"
    )
    print(f"N = {args.n:,}, best of {args.repeat}; M evals/s ('n': normalized=True)")
    print(header)
    outs = {dtype: np.empty((args.n, 3), dtype=wi.dtype) for dtype, (wi, _) in inputs.items()}
    for model in args.models:
        extra = extra_args(model)
        t_arg = {"tangent": tangent} if brdf_rs.models()[model]["tangent"] else {}
        for dtype, (wi, wo) in inputs.items():
            row = {"model": model, "dtype": dtype, "date": time.strftime("%Y-%m-%d %H:%M:%S")}
            nz = np.array([0.0, 0.0, 1.0], dtype=wi.dtype)
            # The tangent in the batch's dtype: a float64 tangent would make a float32 batch
            # run (and be timed) in float64.
            tn = {k: v.astype(wi.dtype) for k, v in t_arg.items()}
            # The NumPy baselines cover the sources' models (benches/numpy_models.py); the
            # newer ones have none, and their rows leave the column empty.
            row["numpy"] = None
            if model in numpy_models.MODELS:
                numpy_call = functools.partial(
                    numpy_models.evaluate, model, wi, wo, nz, **tn, **extra
                )
                best, _ = best_time(numpy_call, max(1, args.repeat // 2))
                row["numpy"] = args.n / best / 1e6
            columns = {}
            for threads in args.threads:
                for normalized in (False, True):
                    key = f"{threads}t" + ("_normalized" if normalized else "")
                    columns[key] = (
                        threads,
                        functools.partial(
                            brdf_rs.eval, model, wi, wo, normalized=normalized, **tn, **extra
                        ),
                    )
            top = max(args.threads)
            columns["out"] = (
                top,
                functools.partial(brdf_rs.eval, model, wi, wo, out=outs[dtype], **tn, **extra),
            )
            columns["fast"] = (
                top,
                functools.partial(brdf_rs.eval, model, wi, wo, precision="fast", **tn, **extra),
            )
            columns["fast_out"] = (
                top,
                functools.partial(
                    brdf_rs.eval, model, wi, wo, out=outs[dtype], precision="fast", **tn, **extra
                ),
            )
            numba_fn = numba_call(model, wi, wo, extra)
            if numba_fn is not None:
                columns["numba"] = (None, numba_fn)
                columns["numba_out"] = (None, numba_call(model, wi, wo, extra, outs[dtype]))
            timed = interleaved_times(columns, args.repeat)
            for key, (best, median) in timed.items():
                row[key] = args.n / best / 1e6
                row[key + "_median"] = args.n / median / 1e6
            row.setdefault("numba", None)
            row.setdefault("numba_out", None)
            brdf_rs.set_num_threads(top)
            row["speedup"] = row[f"{top}t"] / row["numpy"] if row["numpy"] else None
            numba = row["numba_out"]
            row["vs_numba"] = row["out"] / numba if numba else None
            row["fast_vs_numba"] = row["fast_out"] / numba if numba else None
            rows.append(row)
            line = f"{model:24s} {dtype:8s} {_cell(row['numpy'], 8)}"
            for threads in args.threads:
                line += f" {row[f'{threads}t']:8.1f} {row[f'{threads}t_normalized']:9.1f}"
            ratio = f"{row['speedup']:7.1f}x" if row["speedup"] else f"{'—':>8s}"
            print(
                line + f" {row['out']:8.1f} {row['fast']:8.1f} {row['fast_out']:8.1f}"
                f" {_cell(row['numba'], 8)} {_cell(row['numba_out'], 8)}"
                f" {_cell(row['vs_numba'], 7, 2)}x {_cell(row['fast_vs_numba'], 6, 2)}x {ratio}",
                flush=True,
            )

    meta = {
        "cpu": cpu_model(),
        "isa": brdf_rs.isa(),
        "brdf_rs": brdf_rs.__version__,
        "numpy": np.__version__,
        "numba": numba_models.version(),
        "numba_threads": numba_models.num_threads(),
        "python": platform.python_version(),
        "n": args.n,
        "repeat": args.repeat,
        "date": time.strftime("%Y-%m-%d %H:%M:%S"),
    }
    if args.update:
        meta, rows = merged(args.out.with_suffix(".json"), meta, rows)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.with_suffix(".json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1))
    write_markdown(args.out.with_suffix(".md"), meta, rows, args.threads)
    write_plot(args.out.with_suffix(".png"), meta, rows, args.threads)
    print(f"wrote {args.out.with_suffix('.md')}, .json, .png")


def _cell(value: float | None, width: int = 0, digits: int = 1) -> str:
    """A number for the table, or a dash where there is none."""
    return f"{value:{width}.{digits}f}" if value is not None else f"{'—':>{width}s}"


def merged(path: Path, meta: dict, rows: list) -> tuple[dict, list]:
    """The results in `path` with `rows` in place of the rows they rerun (same model and
    dtype; new ones appended), under the old run's meta plus a note of the rerun."""
    old = json.loads(path.read_text())
    fresh = {(r["model"], r["dtype"]): r for r in rows}
    kept = [fresh.pop((r["model"], r["dtype"]), r) for r in old["rows"]]
    rerun = {"date": meta["date"], "models": sorted({r["model"] for r in rows})}
    reruns = [*old["meta"].get("reruns", []), rerun]
    # The rerun's Numba, when it had one: the table's header says which rows it timed.
    numba = {k: meta[k] for k in ("numba", "numba_threads") if meta.get("numba")}
    return {**old["meta"], **numba, "reruns": reruns}, kept + list(fresh.values())


def write_markdown(path: Path, meta: dict, rows: list, threads: list) -> None:
    lines = [
        "# brdf_rs.eval throughput",
        "",
        f"CPU: {meta['cpu']} (kernels: {meta['isa']}); N = {meta['n']:,} pairs; "
        f"best of {meta['repeat']} calls; NumPy {meta['numpy']}; {meta['date']}.",
        "Million evaluations per second, NumPy arrays in and a new array out. "
        "'normalized' = `normalized=True` (inputs promised unit length); "
        f"'out=' = {max(threads)} threads writing into a preallocated array; "
        + (
            f"'Numba' = Numba {meta['numba']}'s parallel kernel of the same formula "
            f"({meta['numba_threads']} threads, the row's dtype in and out, a fresh array; "
            "torrance_sparrow and ggx), timed interleaved with the brdf-rs columns; "
            f"'fast' = `precision=\"fast\"` on {max(threads)} threads (a fresh array; 'fast "
            "out=': preallocated); 'x Numba' = 'out=' over 'Numba out=' and 'fast x Numba' = "
            "'fast out=' over 'Numba out=': the kernels compared, each writing into a "
            "preallocated array (with fresh arrays the first touch of new pages bounds "
            "every column alike)."
            if meta.get("numba")
            else "'Numba': not installed."
        ),
        "",
        "| model | dtype | NumPy |"
        + "".join(f" {t} thread{'s' if t > 1 else ''} | normalized |" for t in threads)
        + " out= | fast | fast out= | Numba | Numba out= | x Numba | fast x Numba | vs NumPy |",
        "|---|---|---:|" + "---:|---:|" * len(threads) + "---:|" * 8 + "---:|",
    ]
    for r in rows:
        cells = "".join(f" {r[f'{t}t']:.1f} | {r[f'{t}t_normalized']:.1f} |" for t in threads)
        lines.append(
            f"| {r['model']} | {r['dtype']} | {_cell(r['numpy'])} |{cells} {r['out']:.1f} |"
            f" {_cell(r.get('fast'))} | {_cell(r.get('fast_out'))} | {_cell(r.get('numba'))} |"
            f" {_cell(r.get('numba_out'))} |"
            f" {_cell(r.get('vs_numba'), digits=2)} | {_cell(r.get('fast_vs_numba'), digits=2)} |"
            f" {_cell(r['speedup'], digits=0)}{'x' if r['speedup'] else ''} |"
        )
    for rerun in meta.get("reruns", []):
        lines.append("")
        lines.append(
            f"Rerun alone on {rerun['date']} (`--update`; the other rows are from the "
            f"run above): {', '.join(rerun['models'])}."
        )
    path.write_text("\n".join(lines) + "\n")


def write_plot(path: Path, meta: dict, rows: list, threads: list) -> None:
    plt = pyplot()
    if plt is None:
        return
    models = list(dict.fromkeys(r["model"] for r in rows))
    series = [("numpy", "NumPy")] + [(f"{t}t", f"brdf-rs, {t} thread(s)") for t in threads]
    if any(r.get("fast") for r in rows):
        series.append(("fast", f'brdf-rs, precision="fast", {max(threads)} thread(s)'))
    if any(r.get("numba") for r in rows):
        series.append(("numba", "Numba, parallel"))
    fig, axes = plt.subplots(1, 2, figsize=(14, 0.45 * len(models) + 2.5), sharey=True)
    h = 0.8 / len(series)
    for ax, dtype in zip(axes, ("float64", "float32"), strict=True):
        sub = {r["model"]: r for r in rows if r["dtype"] == dtype}
        y = np.arange(len(models))
        for k, (key, label) in enumerate(series):
            ax.barh(y + k * h, [sub[m].get(key) or 0.0 for m in models], height=h, label=label)
        ax.set_xscale("log")
        ax.set_yticks(y + 0.4 - h / 2, models)
        ax.set_xlabel("million evaluations / s (log)")
        ax.set_title(dtype)
        ax.invert_yaxis()
    # One legend for both panels, below them, where it covers no bar.
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(series), frameon=False)
    fig.suptitle(f"brdf_rs.eval throughput, N = {meta['n']:,}, {meta['cpu']}")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
