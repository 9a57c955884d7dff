"""Run time against error for albedo tables: every sampler x sequence, adaptive `tol`,
the azimuth fold, and a natural NumPy Monte Carlo baseline.

Samplers: "importance" is each lobe's own sampler; "auto" is the library's default (the
same, except that diffuse lobes are drawn uniformly with Sobol points, measured faster).

Tables (as the albedo issue specifies):
- torrance_sparrow 64x64: mu_j = (j+0.5)/64, p log-spaced in [1, 1e4], kd=0, ks=1, eta=1.5
- normalized_phong 64x64: the same grid, kd=0, ks=1
- oren_nayar 32x32: mu_j = (j+0.5)/32, sigma in [0, pi/2], kd=1

The error is the RMS over the table against a converged deterministic quadrature
(tests/quadrature.py, refined until successive resolutions agree to 1e-9; cached in
benches/results/). Every method doubles its samples per cell until it passes the time
budget or RMS 1e-5/2. Prints "time to RMS <= 1e-3 / 1e-4 / 1e-5" (log-log interpolation
between measured points) and writes benches/results/albedo_convergence.{md,json,png}.

    python benches/albedo_convergence.py                    # all tables
    python benches/albedo_convergence.py --tables torrance_sparrow --budget 10
"""

from __future__ import annotations

import argparse
import functools
import hashlib
import itertools
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))

import brdf_rs  # noqa: E402
import numpy_models  # noqa: E402
import quadrature  # noqa: E402

RESULTS = HERE / "results"
TARGETS = (1e-3, 1e-4, 1e-5)


def tables() -> dict:
    mu64 = (np.arange(64) + 0.5) / 64
    mu32 = (np.arange(32) + 0.5) / 32
    p64 = np.geomspace(1.0, 1e4, 64)
    return {
        "torrance_sparrow": {
            "axes": {"mu": mu64, "p": p64},
            "fixed": {"kd": 0.0, "ks": 1.0, "eta": 1.5},
        },
        "normalized_phong": {"axes": {"mu": mu64, "p": p64}, "fixed": {"kd": 0.0, "ks": 1.0}},
        "oren_nayar": {
            "axes": {"mu": mu32, "sigma": np.linspace(0.0, np.pi / 2, 32)},
            "fixed": {"kd": 1.0},
        },
    }


def reference(model: str, spec: dict) -> np.ndarray:
    """The converged quadrature table (channel 0), cached by a hash of its definition."""
    key = json.dumps(
        {
            "model": model,
            **{k: np.asarray(v).tolist() for k, v in spec["axes"].items()},
            **spec["fixed"],
        },
        sort_keys=True,
    )
    digest = hashlib.sha256(key.encode()).hexdigest()[:12]
    path = RESULTS / f"reference_{model}_{digest}.npy"
    if path.exists():
        return np.load(path)
    (_, a), (name_b, b) = spec["axes"].items()
    print(f"computing the quadrature reference for {model} (cached in {path.name}) ...", flush=True)
    t = time.perf_counter()
    ref = np.array(
        [
            [quadrature.directional_albedo(model, mu, **{name_b: v}, **spec["fixed"])[0] for v in b]
            for mu in a
        ]
    )
    print(f"  {time.perf_counter() - t:.1f} s", flush=True)
    RESULTS.mkdir(parents=True, exist_ok=True)
    np.save(path, ref)
    return ref


def run_brdf_rs(model, spec, ref, **options):
    t = time.perf_counter()
    table = brdf_rs.albedo_table(model, spec["axes"], **spec["fixed"], **options)
    seconds = time.perf_counter() - t
    err = table.value[..., 0] - ref
    return {
        "seconds": seconds,
        "rms": float(np.sqrt(np.mean(err**2))),
        "rms_stderr": float(np.sqrt(np.mean(table.stderr[..., 0] ** 2))),
        "samples": float(table.samples.sum()),
    }


# ------------------------------------------------------------- NumPy baseline


def _numpy_sample(model, params, wi, u0, u1):
    """A natural NumPy importance sampler: (wo, pdf) for rows of wi and uniforms."""
    phi = 2 * np.pi * u1
    if model == "oren_nayar":
        cos = np.sqrt(1 - u0)
        sin = np.sqrt(u0)
        wo = np.stack([sin * np.cos(phi), sin * np.sin(phi), cos], axis=-1)
        return wo, cos / np.pi
    p = params["p"]
    k = p + (2.0 if model == "torrance_sparrow" else 1.0)
    cos = (1 - u0) ** (1 / k)
    sin = np.sqrt(np.maximum(0.0, 1 - cos * cos))
    local = np.stack([sin * np.cos(phi), sin * np.sin(phi), cos], axis=-1)
    if model == "torrance_sparrow":
        h = local
        wo = 2 * np.sum(wi * h, axis=-1, keepdims=True) * h - wi
        pdf_h = k / (2 * np.pi) * cos ** (p + 1)
        return wo, pdf_h / (4 * np.abs(np.sum(wo * h, axis=-1)))
    # Phong lobe about the mirror direction r, frame with y normal to the incidence plane.
    r = wi * np.array([-1.0, -1.0, 1.0])
    y = np.array([0.0, 1.0, 0.0])
    x = np.cross(y, r)
    wo = local[..., :1] * x + local[..., 1:2] * y + local[..., 2:] * r
    return wo, k / (2 * np.pi) * cos**p


def run_numpy(model, spec, ref, samples, rng):
    """Plain Monte Carlo with the lobe's importance sampler, vectorized over samples."""
    (_, mus), (name_b, values) = spec["axes"].items()
    t = time.perf_counter()
    out = np.zeros((mus.size, values.size))
    chunk = 1 << 16
    for i, mu in enumerate(mus):
        wi = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
        for j, v in enumerate(values):
            params = {**spec["fixed"], name_b: float(v)}
            total, done = 0.0, 0
            while done < samples:
                m = min(chunk, samples - done)
                u = rng.random((2, m))
                wo, pdf = _numpy_sample(model, params, wi, u[0], u[1])
                f = numpy_models.evaluate(model, np.broadcast_to(wi, wo.shape), wo, **params)[:, 0]
                w = np.where(
                    (wo[:, 2] > 0) & (pdf > 0), f * wo[:, 2] / np.where(pdf > 0, pdf, 1), 0.0
                )
                total += w.sum()
                done += m
            out[i, j] = total / samples
    seconds = time.perf_counter() - t
    return {
        "seconds": seconds,
        "rms": float(np.sqrt(np.mean((out - ref) ** 2))),
        "samples": float(samples * out.size),
    }


# ------------------------------------------------------------------- driver


def series(label, runs, run_one, budget):
    """Doubles the work until the budget is spent or the error is far below 1e-5."""
    points = []
    for kwargs in runs:
        point = run_one(**kwargs)
        point.update({k: v for k, v in kwargs.items() if isinstance(v, (int, float, str, bool))})
        points.append(point)
        print(
            f"  {label:34s} {json.dumps({k: v for k, v in kwargs.items() if k != 'rng'}):40s} "
            f"{point['seconds']:8.2f} s  RMS {point['rms']:.2e}",
            flush=True,
        )
        if point["seconds"] > budget or point["rms"] < TARGETS[-1] / 2:
            break
    return points


def time_to(points, target):
    """Seconds to reach RMS <= target, interpolated in log-log; None if never reached."""
    pts = sorted((p["seconds"], p["rms"]) for p in points)
    for (t0, e0), (t1, e1) in itertools.pairwise(pts):
        if e0 <= target:
            return t0
        if e1 <= target:
            f = (np.log(target) - np.log(e0)) / (np.log(e1) - np.log(e0))
            return float(np.exp(np.log(t0) + f * (np.log(t1) - np.log(t0))))
    if pts and pts[0][1] <= target:
        return pts[0][0]
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tables", nargs="*", default=list(tables()))
    parser.add_argument("--budget", type=float, default=20.0, help="seconds per method")
    parser.add_argument("--threads", type=int, default=None)
    parser.add_argument("--no-numpy", action="store_true", help="skip the NumPy baseline")
    parser.add_argument("--out", type=Path, default=RESULTS / "albedo_convergence")
    args = parser.parse_args()
    if args.threads:
        brdf_rs.set_num_threads(args.threads)
    results = {}
    for model in args.tables:
        spec = tables()[model]
        ref = reference(model, spec)
        print(
            f"\n{model}: table {'x'.join(str(len(a)) for a in spec['axes'].values())}", flush=True
        )
        # Warm-up (thread pool, page faults) outside the timings.
        brdf_rs.albedo_table(model, spec["axes"], **spec["fixed"], samples=64)
        methods = {}
        sizes = [256 * 2**k for k in range(14)]
        for sequence in ("sobol", "random"):
            for sampler in ("auto", "importance", "cosine", "uniform"):
                label = f"{sampler} + {sequence}"
                runs = [{"samples": n, "sampler": sampler, "sequence": sequence} for n in sizes]
                methods[label] = series(
                    label, runs, functools.partial(run_brdf_rs, model, spec, ref), args.budget
                )
        tols = [1e-3 / 2**k for k in range(16)]
        label = "auto + sobol + adaptive tol"
        runs = [{"samples": 256, "tol": t, "max_samples": 1 << 24} for t in tols]
        methods[label] = series(
            label, runs, functools.partial(run_brdf_rs, model, spec, ref), args.budget
        )
        label = "auto + sobol, no azimuth fold"
        runs = [{"samples": n, "fold_azimuth": False} for n in sizes]
        methods[label] = series(
            label, runs, functools.partial(run_brdf_rs, model, spec, ref), args.budget
        )
        if not args.no_numpy:
            rng = np.random.default_rng(0)
            label = "NumPy Monte Carlo (importance)"
            runs = [{"samples": n, "rng": rng} for n in [16, 64, 256, 1024, 4096, 16384]]
            methods[label] = series(
                label, runs, functools.partial(run_numpy, model, spec, ref), args.budget
            )
        results[model] = methods

    meta = {
        "cpu": _cpu(),
        "threads": brdf_rs.num_threads(),
        "isa": brdf_rs.isa(),
        "brdf_rs": brdf_rs.__version__,
        "python": platform.python_version(),
        "budget_seconds": args.budget,
        "date": time.strftime("%Y-%m-%d %H:%M:%S"),
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    clean = {
        m: {k: [{kk: vv for kk, vv in p.items() if kk != "rng"} for p in v] for k, v in ms.items()}
        for m, ms in results.items()
    }
    args.out.with_suffix(".json").write_text(json.dumps({"meta": meta, "results": clean}, indent=1))
    lines = report(meta, results)
    print("\n".join(lines))
    args.out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    plot(args.out.with_suffix(".png"), meta, results)
    print(f"wrote {args.out.with_suffix('.md')}, .json, .png")


def report(meta, results):
    lines = [
        "# Albedo tables: run time against error",
        "",
        f"CPU: {meta['cpu']}, {meta['threads']} threads ({meta['isa']}); {meta['date']}; "
        f"budget {meta['budget_seconds']:.0f} s per method. RMS error over the table against "
        "a quadrature converged to 1e-9. Seconds to reach each RMS (— = not within budget).",
    ]
    for model, methods in results.items():
        lines += [
            "",
            f"## {model}",
            "",
            "| method | RMS 1e-3 | RMS 1e-4 | RMS 1e-5 | best RMS |",
            "|---|---:|---:|---:|---:|",
        ]
        for label, points in methods.items():
            cells = []
            for target in TARGETS:
                t = time_to(points, target)
                cells.append("—" if t is None else f"{t:.2f} s")
            best = min(p["rms"] for p in points)
            lines.append(f"| {label} | {' | '.join(cells)} | {best:.1e} |")
    return lines


def plot(path, meta, results):
    from brdf_rs.plot import convergence

    title = f"Albedo tables: error against time ({meta['cpu']}, {meta['threads']} threads)"
    try:
        convergence(results, targets=TARGETS, title=title, path=path, dpi=110)
    except ImportError:
        print("matplotlib not installed: no plot")


def _cpu() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


if __name__ == "__main__":
    main()
