"""Adaptive stopping (``tol``) with Sobol points: are the error bars of the cells that
stop honest, and what does the stopping rule cost in samples?

Under ``tol`` a cell runs rounds of doubling size and stops at the first round whose
error bar is at most ``tol``. With Sobol points the error bar is the spread of 16
replicates, itself uncertain by about ±18%, so the cells that stop at a round are more
often those whose spread read small there. The integrator therefore pools a round's
variance with the previous round's spread, halved (never below the round's own), and
decides and reports with that error bar.

For each case the script runs ``brdf_rs.albedo`` on N independent cells at fixed sample
counts 256, 512, ..., 65536 (a fixed count runs a single round: each is exactly what an
adaptive run computes at that round, since every round extends the same replicate
streams) and replays from them the rule without pooling (``spread``: stop at the first
round whose own error bar is at most ``tol``); then it runs ``brdf_rs.albedo(...,
tol=...)`` itself (``library``). It prints P(|z| > 3) (0.9% is honest for Student's t
with 15 degrees of freedom), the median |z| (0.691) and the mean samples per cell,
against the calibration script's reference (scripts/stderr_calibration.py). ``--table``
does the same over the command line's default table (Torrance-Sparrow, 32 × 32 over mu
and p) and a 32 × 32 GGX table over mu and alpha, and prints the total samples of each.

    python scripts/adaptive_stopping.py                  # the calibration's tol cases
    python scripts/adaptive_stopping.py --cells 4000 --cases ward ashikhmin_shirley
    python scripts/adaptive_stopping.py --table
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from collections.abc import Sequence
from pathlib import Path

import brdf_rs
import numpy as np

ROUNDS = tuple(256 << k for k in range(9))  # 256 .. 65536


def _calibration():  # type: ignore[no-untyped-def]
    name = "stderr_calibration"
    if name not in sys.modules:
        path = Path(__file__).resolve().parent / f"{name}.py"
        spec = importlib.util.spec_from_file_location(name, path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def replay(
    values: np.ndarray, stderrs: np.ndarray, tol: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The value, error bar and samples each cell stops with under the rule without
    pooling, from its fixed-count rounds (``values[k]``, ``stderrs[k]`` at ``ROUNDS[k]``;
    cells on the trailing axes)."""
    shape = values.shape[1:]
    value = np.full(shape, np.nan)
    stderr = np.full(shape, np.nan)
    samples = np.zeros(shape)
    stopped = np.zeros(shape, dtype=bool)
    for k in range(len(values)):
        stop = ~stopped & ((stderrs[k] <= tol) | (k == len(values) - 1))
        value[stop], stderr[stop], samples[stop] = values[k][stop], stderrs[k][stop], ROUNDS[k]
        stopped |= stop
    return value, stderr, samples


def rounds(run, count: int) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    """Channel 0 of ``run(samples)`` at each of the first ``count`` fixed round sizes."""
    values, stderrs = [], []
    for n in ROUNDS[:count]:
        r = run(n)
        values.append(np.asarray(r.value)[..., 0])
        stderrs.append(np.asarray(r.stderr)[..., 0])
    return np.array(values), np.array(stderrs)


def cases_report(cells: int, tol: float, names: Sequence[str]) -> None:
    cal = _calibration()
    cases = cal.select(names) if names else cal.CASES
    print(f"{cells} cells per case, Sobol points, tol = {tol:g}, first round 256, cap 65536")
    print(f"{'case':40s} {'rule':8s} {'P(|z|>3)':>9s} {'med |z|':>8s} {'samples':>8s}")
    for case in cases:
        ref, _, _ = cal.reference_with_check(case)
        mu = np.full(cells, case.mu)
        ids = np.arange(cells, dtype=np.uint64)

        def run(n: int, mu=mu, ids=ids, case=case):  # type: ignore[no-untyped-def]
            return brdf_rs.albedo(case.model, mu, cell_ids=ids, samples=n, **case.params)

        values, stderrs = rounds(run, len(ROUNDS))
        live = brdf_rs.albedo(
            case.model, mu, cell_ids=ids, tol=tol, samples=256, max_samples=65536, **case.params
        )
        rows = {
            "spread": replay(values, stderrs, tol),
            "library": (
                np.asarray(live.value)[:, 0],
                np.asarray(live.stderr)[:, 0],
                np.asarray(live.samples, dtype=float),
            ),
        }
        for rule, (value, stderr, samples) in rows.items():
            z = np.abs(value - ref) / stderr
            print(
                f"{case.label:40s} {rule:8s} {np.mean(z > 3):9.4f} {np.median(z):8.3f} "
                f"{np.mean(samples):8.0f}"
            )


def table_report(tol: float) -> None:
    tables = {
        "torrance_sparrow (mu × p)": (
            "torrance_sparrow",
            {"mu": (np.arange(32) + 0.5) / 32, "p": np.geomspace(1, 10000, 32)},
            {"kd": 0.0, "ks": 1.0, "eta": 1.5},
        ),
        "ggx (mu × alpha)": (
            "ggx",
            {"mu": (np.arange(32) + 0.5) / 32, "alpha": (np.arange(32) + 0.5) / 32},
            {"kd": 0.0, "ks": 1.0},
        ),
    }
    print(f"32 × 32 tables, Sobol points, tol = {tol:g}: total samples of each rule")
    for label, (model, axes, params) in tables.items():

        def run(n: int, model=model, axes=axes, params=params):  # type: ignore[no-untyped-def]
            return brdf_rs.albedo_table(model, axes, samples=n, **params)

        values, stderrs = rounds(run, len(ROUNDS))
        spread = replay(values, stderrs, tol)[2].sum()
        live = brdf_rs.albedo_table(model, axes, tol=tol, samples=256, max_samples=65536, **params)
        pooled = np.sum(live.samples, dtype=float)
        print(
            f"{label:28s} spread {spread:14,.0f}  library {pooled:14,.0f}  "
            f"ratio {pooled / spread:.3f}  max stderr {live.stderr.max():.2e}"
        )


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, default=2000, help="cells per case (2000)")
    parser.add_argument("--tol", type=float, default=1e-4, help="the adaptive budget (1e-4)")
    parser.add_argument("--cases", nargs="+", default=[], help="model names or case labels")
    parser.add_argument("--table", action="store_true", help="sample cost over two tables")
    args = parser.parse_args(argv)
    if args.table:
        table_report(args.tol)
    else:
        cases_report(args.cells, args.tol, args.cases)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
