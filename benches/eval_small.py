"""Time per call of brdf_rs.eval from one pair of directions to a million, against Numba.

The workload users loop over (per object, per light, inside an optimizer):
``torrance_sparrow`` in float64, ``(N, 3)`` float64 ``wi`` and ``wo`` in, RGB out, with
kd = [0.2, 0.1, 0.05], ks = 1, p = 50, eta = 1.5, for N = 1 to 1e6. Columns:

- ``brdf_rs.eval``: the function, a fresh array out;
- ``Model.eval``: a ``brdf_rs.Model`` made once, a fresh array out (``check=True``);
- ``Model.eval out=``: the same with ``check=False`` and a preallocated ``out=``;
- Numba ``parallel`` / ``serial``: ``@njit(parallel=True)`` and ``@njit`` kernels of the
  same formula (benches/numba_models.py) writing into a preallocated array; checked to
  agree with brdf_rs to 1e-12 relative before timing. Skipped, with a message, when Numba
  is not installed (``pip install numba``, or the ``bench`` extra).

Every call of every column is timed in the same run, interleaved round by round, and
each cell is the median over the rounds (the machine may be shared and noisy). With
``--baseline DIR`` a second build of brdf-rs (a ``brdf_rs`` package folder with its
compiled module, e.g. an earlier commit's ``python/`` after a release build) is loaded
beside this one and its ``brdf_rs.eval`` and ``Model.eval`` columns are timed in the same
rounds.

    python benches/eval_small.py
    python benches/eval_small.py --rounds 15 --baseline ../old/python --baseline-label "..."

Writes benches/results/eval_small.{md,json,png}.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import platform
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import brdf_rs  # noqa: E402
import numba_models  # noqa: E402
from _plot import pyplot  # noqa: E402
from eval_throughput import cpu_model  # noqa: E402

RESULTS = HERE / "results"
MODEL = "torrance_sparrow"
PARAMS = {"kd": [0.2, 0.1, 0.05], "p": 50.0, "eta": 1.5}
SIZES = (1, 10, 100, 1_000, 10_000, 100_000, 1_000_000)
#: Wall time one timed sample aims at: many calls of a small N, one call of a large one.
SAMPLE_SECONDS = 0.02


def load_baseline(folder: Path) -> ModuleType:
    """Imports the ``brdf_rs`` package in ``folder`` under the name ``brdf_rs_baseline``."""
    init = folder / "brdf_rs" / "__init__.py"
    if not init.exists():
        raise SystemExit(f"--baseline: no brdf_rs package in {folder}")
    spec = importlib.util.spec_from_file_location(
        "brdf_rs_baseline", init, submodule_search_locations=[str(init.parent)]
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["brdf_rs_baseline"] = module
    spec.loader.exec_module(module)
    return module


def directions(rng: np.random.Generator, n: int) -> np.ndarray:
    """Random unit directions in the upper hemisphere, (n, 3) float64."""
    v = rng.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2])
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def calls(
    wi: np.ndarray, wo: np.ndarray, baseline: ModuleType | None
) -> dict[str, Callable[[], object]]:
    """The timed callables for one N, by column name."""
    n = len(wi)
    out = np.empty((n, 3))
    columns: dict[str, Callable[[], object]] = {}
    builds = [("", brdf_rs)] + ([("baseline ", baseline)] if baseline is not None else [])
    for prefix, module in builds:
        model = module.Model(MODEL, **PARAMS)
        columns[prefix + "brdf_rs.eval"] = lambda m=module: m.eval(MODEL, wi, wo, **PARAMS)
        columns[prefix + "Model.eval"] = lambda model=model: model.eval(wi, wo)
        columns[prefix + "Model.eval out="] = lambda model=model: model.eval(
            wi, wo, check=False, out=out
        )
    if numba_models.available():
        args = numba_models.kernel_args(MODEL, PARAMS)
        for kind in ("parallel", "serial"):
            kernel = numba_models.KERNELS[MODEL][kind]
            columns[f"Numba {kind}"] = lambda k=kernel: k(wi, wo, *args, out)
    return columns


def time_sample(fn: Callable[[], object], number: int) -> float:
    """Seconds per call over `number` calls."""
    start = time.perf_counter()
    for _ in range(number):
        fn()
    return (time.perf_counter() - start) / number


def measure(n: int, rounds: int, baseline: ModuleType | None) -> dict[str, float]:
    """Median seconds per call of every column at N = n, the columns interleaved."""
    rng = np.random.default_rng(n)
    wi, wo = directions(rng, n), directions(rng, n)
    columns = calls(wi, wo, baseline)
    numbers = {}
    for name, fn in columns.items():
        fn()  # warm-up: compilation, first touch, thread start
        single = time_sample(fn, 1)
        numbers[name] = max(1, min(100_000, int(SAMPLE_SECONDS / max(single, 1e-7))))
    samples: dict[str, list[float]] = {name: [] for name in columns}
    for _ in range(rounds):
        for name, fn in columns.items():
            samples[name].append(time_sample(fn, numbers[name]))
    return {name: statistics.median(times) for name, times in samples.items()}


def check_numba(rng: np.random.Generator) -> float:
    """Largest relative difference of the Numba kernels from brdf_rs (raises above 1e-12)."""
    wi, wo = directions(rng, 100_000), directions(rng, 100_000)
    return numba_models.check_agreement(MODEL, wi, wo, PARAMS)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, default=9, help="interleaved rounds per N")
    parser.add_argument("--sizes", type=int, nargs="*", default=list(SIZES))
    parser.add_argument("--baseline", type=Path, help="folder holding another brdf_rs build")
    parser.add_argument(
        "--baseline-label",
        default="another build of brdf-rs",
        help="what the baseline is, for the table (e.g. 'the previous release')",
    )
    parser.add_argument("--out", type=Path, default=RESULTS / "eval_small")
    args = parser.parse_args()

    baseline = load_baseline(args.baseline) if args.baseline else None
    meta = {
        "cpu": cpu_model(),
        "isa": brdf_rs.isa(),
        "threads": brdf_rs.num_threads(),
        "brdf_rs": brdf_rs.__version__,
        "numpy": np.__version__,
        "numba": numba_models.version(),
        "python": platform.python_version(),
        "model": MODEL,
        "params": PARAMS,
        "rounds": args.rounds,
        "baseline": args.baseline_label if args.baseline else None,
        "date": time.strftime("%Y-%m-%d %H:%M:%S"),
        "load_before": os.getloadavg()[0],
    }
    if numba_models.available():
        worst = check_numba(np.random.default_rng(0))
        meta["numba_threads"] = numba_models.num_threads()
        meta["numba_max_rel_diff"] = worst
        print(f"Numba {meta['numba']} agrees with brdf_rs to {worst:.2g} relative")
    else:
        print("numba is not installed: its columns are skipped (pip install numba)")

    rows = []
    for n in args.sizes:
        seconds = measure(n, args.rounds, baseline)
        rows.append({"n": n, "us_per_call": {k: s * 1e6 for k, s in seconds.items()}})
        print(f"N = {n:>9,}: " + ", ".join(f"{k} {s * 1e6:.3g} µs" for k, s in seconds.items()))

    meta["load_after"] = os.getloadavg()[0]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.with_suffix(".json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1))
    table = markdown(meta, rows)
    args.out.with_suffix(".md").write_text(table)
    print()
    print(table)
    write_plot(args.out.with_suffix(".png"), meta, rows)
    print(f"wrote {args.out.with_suffix('.md')}, .json, .png")


def _us(us: float) -> str:
    """Microseconds for the table: three significant digits, thousands separated."""
    return f"{us:,.0f}" if us >= 100 else f"{us:.3g}"


def markdown(meta: dict, rows: list) -> str:
    columns = list(rows[0]["us_per_call"])
    lines = [
        "# brdf_rs.eval for small and large batches",
        "",
        f"CPU: {meta['cpu']} (kernels: {meta['isa']}); brdf-rs {meta['threads']} threads"
        + (
            f", Numba {meta['numba']} ({meta['numba_threads']} threads)"
            if meta.get("numba")
            else "; Numba not installed"
        )
        + f"; NumPy {meta['numpy']}; Python {meta['python']}; {meta['date']}.",
        f"`{meta['model']}` in float64, {json.dumps(meta['params'])}: (N, 3) float64 `wi`,"
        " `wo` in, RGB out. Microseconds per call, median of "
        f"{meta['rounds']} interleaved rounds (M evaluations/s in brackets).",
        "`Model.eval out=` is `check=False` with a preallocated `out=`; the Numba kernels "
        "write into a preallocated array. Load average (1 min) "
        f"{meta['load_before']:.2f} before, {meta['load_after']:.2f} after: above 0, other "
        "work shared the machine's cores (Numba's parallel kernels suffer most from that).",
        "",
        "| N | " + " | ".join(columns) + " |",
        "|---:|" + "---:|" * len(columns),
    ]
    for r in rows:
        n = r["n"]
        cells = [
            f"{_us(us)} ({n / us:.3g})" if n >= 1000 else _us(us)
            for us in r["us_per_call"].values()
        ]
        lines.append(f"| {n:,} | " + " | ".join(cells) + " |")
    if meta.get("baseline"):
        lines += ["", f"'baseline' columns: {meta['baseline']}, timed in the same rounds."]
    return "\n".join(lines) + "\n"


def write_plot(path: Path, meta: dict, rows: list) -> None:
    plt = pyplot()
    if plt is None:
        return
    ns = np.array([r["n"] for r in rows], dtype=float)
    columns = list(rows[0]["us_per_call"])
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 5.2))
    # A column and its baseline twin share a colour; the baseline is dotted, Numba dashed.
    kinds = list(dict.fromkeys(name.removeprefix("baseline ") for name in columns))
    for name in columns:
        us = np.array([r["us_per_call"][name] for r in rows])
        linestyle = (
            ":" if name.startswith("baseline") else "--" if name.startswith("Numba") else "-"
        )
        style = {
            "linestyle": linestyle,
            "color": f"C{kinds.index(name.removeprefix('baseline '))}",
            "marker": "o",
            "markersize": 4,
            "label": name,
        }
        left.loglog(ns, us, **style)
        right.loglog(ns, ns / us, **style)
    left.set_xlabel("N (direction pairs per call)")
    left.set_ylabel("time per call (µs, log)")
    left.set_title("time per call")
    right.set_xlabel("N (direction pairs per call)")
    right.set_ylabel("million evaluations / s (log)")
    right.set_title("throughput")
    for ax in (left, right):
        ax.grid(True, which="major", alpha=0.3)
    handles, labels = left.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 4), frameon=False)
    fig.suptitle(
        f"{meta['model']} float64, brdf-rs vs Numba, {meta['cpu']}, {meta['threads']} threads"
    )
    fig.tight_layout(rect=(0, 0.1 if len(labels) <= 4 else 0.15, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
