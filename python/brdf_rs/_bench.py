"""A short benchmark shipped with the package (``brdf-rs bench``).

Two measurements a user can run anywhere the wheel installs, in a few seconds:

- **eval throughput**: million evaluations per second of a few models on ``n`` random
  direction pairs, float64 and float32 (NumPy arrays in, written into a preallocated
  array with ``out=``), the best of ``repeat`` timed calls after a warm-up.
- **albedo table**: the tool defaults' self-checking model (kd = 0, ks = 1) over mu × its
  parameter to a standard-error tolerance, timed, with a correctness
  check: at mu = 1 its albedo is exactly 1 (docs/models.md), so the largest ``|R − 1|`` is
  reported against the stated standard error; the check passes when it is within
  ``CHECK_STDERRS`` standard errors.

The models come from the spec's tool defaults (``brdf_rs._spec.tool_defaults``).

The full benchmarks (every model, NumPy baselines, convergence against a quadrature)
live in the repository's ``benches/``.
"""

from __future__ import annotations

import functools
import os
import platform
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from . import _albedo, _api, _spec

__all__ = ["CHECK_STDERRS", "run"]

#: The albedo check passes when every ``|R(1) − 1|`` is within this many standard errors.
#: The errors are Student-t with 15 degrees of freedom (docs/error_bars.md):
#: P(|z| > 5) ≈ 1.6e-4 per cell, 0.25% for any of 16 cells by chance.
CHECK_STDERRS = 5.0


def cpu_model() -> str:
    """The CPU's model name (Linux), else what the platform module says."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _best_seconds(fn: Callable[[], object], repeat: int) -> float:
    fn()  # warm-up: page faults, thread pool start
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def _directions(rng: np.random.Generator, n: int) -> np.ndarray:
    v = rng.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2])  # upper hemisphere: the kernels do their full work
    return v


def eval_throughput(
    models: Sequence[str], n: int, repeat: int, seed: int = 0
) -> list[dict[str, Any]]:
    """Returns one row per (model, dtype): ``seconds`` (best call) and ``mevals_per_s``."""
    specs = _spec.specs()
    for model in models:
        if model not in specs:
            raise ValueError(f"models: unknown model {model!r}; see brdf-rs models")
    rng = np.random.default_rng(seed)
    wi64, wo64 = _directions(rng, n), _directions(rng, n)
    rows = []
    for model in models:
        m = _api.Model(model)
        for dtype in (np.float64, np.float32):
            wi, wo = wi64.astype(dtype), wo64.astype(dtype)
            tangent = np.array([1, 0, 0], dtype=dtype) if specs[model]["tangent"] else None
            out = np.empty((n, 3), dtype=dtype)

            call = functools.partial(m.eval, wi, wo, tangent=tangent, out=out)
            seconds = _best_seconds(call, repeat)
            rows.append(
                {
                    "model": model,
                    "dtype": np.dtype(dtype).name,
                    "n": n,
                    "seconds": seconds,
                    "mevals_per_s": n / seconds / 1e6,
                }
            )
    return rows


def albedo_table_benchmark(size: int, tol: float, seed: int = 0) -> dict[str, Any]:
    """Builds a ``size`` × ``size`` table of the spec's self-checking model to ``tol``;
    times and checks it."""
    check = _spec.tool_defaults()["albedo_check"]
    mu = np.arange(1, size + 1) / size  # includes mu = 1, where R = 1 exactly
    shape = np.geomspace(check["lo"], check["hi"], size)
    start = time.perf_counter()
    table = _albedo.albedo_table(
        check["model"], {"mu": mu, check["param"]: shape}, kd=0.0, ks=1.0, tol=tol, seed=seed
    )
    seconds = time.perf_counter() - start
    samples = int(table.samples.sum())
    at_one = table.value[-1, :, 0]
    se_at_one = table.stderr[-1, :, 0]
    error = np.abs(at_one - 1.0)
    return {
        "model": check["model"],
        "shape": [size, size],
        "tol": tol,
        "seconds": seconds,
        "samples": samples,
        "msamples_per_s": samples / seconds / 1e6,
        "max_stderr": float(table.stderr.max()),
        "max_error_at_mu_1": float(error.max()),
        "max_error_in_stderr_at_mu_1": float(np.max(error / np.maximum(se_at_one, 1e-300))),
        "check_limit_in_stderr": CHECK_STDERRS,
        "check_passed": bool(np.all(error <= CHECK_STDERRS * se_at_one)),
    }


def run(
    models: Sequence[str] | None = None,
    *,
    n: int = 1_000_000,
    repeat: int = 3,
    table_size: int = 16,
    tol: float = 1e-4,
    seed: int = 0,
) -> dict[str, Any]:
    """Runs both measurements; returns ``{"machine", "eval", "albedo_table"}``.
    ``models``: the models to time (default: the spec's, one per family of kernels)."""
    if models is None:
        models = _spec.tool_defaults()["bench"]
    if n < 1 or repeat < 1 or table_size < 1:
        raise ValueError(
            f"n, repeat, table_size: must be at least 1; got {n}, {repeat}, {table_size}"
        )
    if not (tol > 0 and np.isfinite(tol)):
        raise ValueError(f"tol: must be a positive number; got {tol}")
    from ._brdf_rs import __version__

    machine = {
        "brdf_rs": __version__,
        "cpu": cpu_model(),
        "cpus": os.cpu_count(),
        "threads": _api.num_threads(),
        "isa": _api.isa(),
        "python": platform.python_version(),
        "numpy": np.__version__,
    }
    return {
        "machine": machine,
        "eval": eval_throughput(models, n, repeat, seed),
        "albedo_table": albedo_table_benchmark(table_size, tol, seed),
    }
