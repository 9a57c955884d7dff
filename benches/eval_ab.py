"""Two or more builds of brdf-rs side by side on brdf_rs.eval, in one run.

Each build is a Python that imports it (as for benches/ab_builds.py: its own virtual
environment, or a wrapper script that sets PYTHONPATH). For every round, each build runs
in a subprocess of its own, one after the other, and times `brdf_rs.eval` of one model on
N random direction pairs (written with ``out=``, so only the kernel is timed) for
`--seconds`; the table keeps each build's best round and its ratio to the first build's.
Rounds alternate the builds, which spreads a shared machine's noise over all of them.
With one build it is also a steady load to profile (``perf record -- python ...``).
``--precision LABEL=TIER`` evaluates that build with ``precision=TIER`` (default
"accurate"): one Python under two labels compares the tiers, interleaved the same way.

    python benches/eval_ab.py --model torrance_sparrow --dtype float64 --n 16384 \\
        --build "main=/path/to/main/bin/python" --build "this tree=.venv/bin/python"
    python benches/eval_ab.py --build "accurate=.venv/bin/python" \\
        --build "fast=.venv/bin/python" --precision fast=fast
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
from _builds import add_build_option, parse_builds, run_worker


def extra_args(model: str) -> dict:
    """The parameters of benches/eval_throughput.py's table (a typical material)."""
    if model in ("torrance_sparrow", "blinn_phong_fresnel"):
        return {"kd": [0.2, 0.1, 0.05], "p": 50.0}
    return {}


def worker(
    model: str,
    dtype: str,
    n: int,
    threads: int,
    seconds: float,
    precision: str = "accurate",
    p: float | None = None,
) -> None:
    """Times eval here (the build this Python imports); JSON on stdout. Models that need
    a tangent get eval_throughput.py's (1, 0, 0); `p`, where given, is the exponent."""
    import brdf_rs

    brdf_rs.set_num_threads(threads)
    rng = np.random.default_rng(1)

    def directions() -> np.ndarray:
        v = rng.normal(size=(n, 3))
        v[:, 2] = np.abs(v[:, 2])
        return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(dtype)

    wi, wo = directions(), directions()
    out = np.empty((n, 3), dtype=dtype)
    extra = extra_args(model)
    if brdf_rs.models()[model]["tangent"]:
        extra["tangent"] = np.array([1.0, 0.0, 0.0], dtype=dtype)
    if precision != "accurate":
        extra["precision"] = precision
    if p is not None:
        extra["p"] = p
    brdf_rs.eval(model, wi, wo, out=out, **extra)  # warm-up
    best = float("inf")
    start = time.perf_counter()
    while time.perf_counter() - start < seconds:
        t = time.perf_counter()
        brdf_rs.eval(model, wi, wo, out=out, **extra)
        best = min(best, time.perf_counter() - t)
    print(json.dumps({"mevals": n / best / 1e6}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_build_option(parser)
    parser.add_argument("--model", default="torrance_sparrow")
    parser.add_argument("--dtype", default="float64", choices=["float64", "float32"])
    parser.add_argument("--n", type=int, default=16384, help="direction pairs per call")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--seconds", type=float, default=2.0, help="per build and round")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument(
        "--p", type=float, help="the exponent, for models that take one (default: the table's)"
    )
    parser.add_argument(
        "--precision",
        action="append",
        default=[],
        metavar="LABEL=TIER",
        help="evaluate build LABEL with precision=TIER (accurate or fast; default accurate)",
    )
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        tier = args.precision[0] if args.precision else "accurate"
        worker(args.model, args.dtype, args.n, args.threads, args.seconds, tier, args.p)
        return
    builds = parse_builds(parser, args.build, 1)
    tiers = dict(t.split("=", 1) for t in args.precision)
    rounds: dict[str, list[float]] = {label: [] for label in builds}
    for r in range(args.rounds):
        for label, python in builds.items():
            cmd = ["--model", args.model, "--dtype", args.dtype]
            cmd += ["--n", str(args.n), "--threads", str(args.threads)]
            cmd += ["--seconds", str(args.seconds)]
            cmd += ["--precision", tiers.get(label, "accurate")]
            cmd += [] if args.p is None else ["--p", repr(args.p)]
            rounds[label].append(run_worker(python, __file__, cmd)["mevals"])
            print(f"round {r + 1}, {label}: {rounds[label][-1]:.1f} M evals/s", flush=True)
    base = max(rounds[next(iter(builds))])
    print(
        f"\n{args.model} {args.dtype}, N = {args.n:,}, {args.threads} thread(s), "
        + ("" if args.p is None else f"p = {args.p:g}, ")
        + f"best of {args.rounds} interleaved rounds of {args.seconds} s"
    )
    print("| build | M evals/s (best) | rounds | vs first |")
    print("|---|---:|---|---:|")
    for label, values in rounds.items():
        runs = ", ".join(f"{v:.1f}" for v in values)
        print(f"| {label} | {max(values):.1f} | {runs} | {max(values) / base:.2f}x |")


if __name__ == "__main__":
    main()
