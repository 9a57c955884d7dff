"""Run time against error for albedo tables: every sampler x sequence, adaptive `tol`,
the azimuth fold, a natural NumPy Monte Carlo baseline and, for GGX, Mitsuba 3.

Samplers: "importance" is each lobe's own sampler; "auto" is the library's default (the
same, except that diffuse lobes are drawn uniformly with Sobol points, measured faster).

Tables:
- torrance_sparrow 64x64: mu_j = (j+0.5)/64, p log-spaced in [1, 1e4], kd=0, ks=1, eta=1.5
- normalized_phong 64x64: the same grid, kd=0, ks=1
- oren_nayar 32x32: mu_j = (j+0.5)/32, sigma in [0, pi/2], kd=1
- ggx 64x64: mu_j = (j+0.5)/64 (0.0078 to 0.992), alpha log-spaced in [0.01, 1],
  kd=0, ks=1 (F = 1): the table of Kulla-Conty energy compensation. Methods: the
  library's VNDF sampler with Sobol points (fixed samples and adaptive `tol`), random
  points, no azimuth fold, the uniform sampler, and Mitsuba 3 (below); no NumPy baseline.
- beckmann 64x64: the same grid and parameters. Methods: the library's visible-normal
  sampler with Sobol points, with fixed samples and adaptive `tol`. Also reported per
  method: ns per sample (wall time x threads / samples) and the fraction of cells whose
  |error| exceeds 3 standard errors at its most accurate point (an honest error bar
  leaves ~0.3%).

The error is the RMS over the table against a converged deterministic quadrature
(tests/quadrature.py, refined until successive resolutions agree to 1e-9; cached in
benches/results/). Every method doubles its samples per cell until it passes the time
budget or RMS 1e-5/2. Prints "time to RMS <= 1e-3 / 1e-4 / 1e-5" (log-log interpolation
between measured points) and writes benches/results/albedo_convergence.{md,json,png}.
`--repeat N` runs the brdf-rs methods in N interleaved rounds (round 1 finds each
method's points; rounds 2..N run them again, method after method) and keeps each point's
fastest time: the results are bitwise identical, and on a shared, noisy machine the
rounds spread the noise over every method.

    python benches/albedo_convergence.py                    # all tables
    python benches/albedo_convergence.py --tables torrance_sparrow --budget 10
    python benches/albedo_convergence.py --tables ggx --repeat 3 \
        --mitsuba-python /path/to/venv/bin/python --out benches/results/albedo_convergence_ggx

Mitsuba 3 (GGX only; optional, not a brdf-rs dependency): `pip install mitsuba` into the
benchmark's Python or into a venv of its own, named by `--mitsuba-python` (default: this
Python). It runs in a subprocess (benches/mitsuba_ggx.py: `roughconductor`, GGX,
`material: none` so F = 1, visible-normal `BSDF.sample` on vectorized lanes from Python,
variant `--mitsuba-variant`, default llvm_ad_rgb, which needs libLLVM 16 or later, e.g.
Debian's libllvm19; see that file). When mitsuba cannot be imported the column is skipped
with a note. Mitsuba's GGX uses the separable Smith G1(wi)·G1(wo), not brdf-rs's
height-correlated G2, so its error is measured against the quadrature reference of the
separable model (the same quadrature, the BRDF multiplied by G1·G1/G2): each method is
measured against the function it computes.
"""

from __future__ import annotations

import argparse
import functools
import hashlib
import itertools
import json
import os
import platform
import subprocess
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
from brdf_rs._bench import cpu_model  # noqa: E402

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
        "ggx": {
            "axes": {"mu": mu64, "alpha": np.geomspace(0.01, 1.0, 64)},
            "fixed": {"kd": 0.0, "ks": 1.0},
        },
        "beckmann": {
            "axes": {"mu": mu64, "alpha": np.geomspace(0.01, 1.0, 64)},
            "fixed": {"kd": 0.0, "ks": 1.0},
        },
    }


def reference(model: str, spec: dict, variant: str | None = None) -> np.ndarray:
    """The converged quadrature table (channel 0), cached by a hash of its definition.

    `variant="separable"` (ggx only): the GGX with the separable Smith G1(wi)·G1(wo)
    that Mitsuba implements."""
    definition = {
        "model": model,
        **{k: np.asarray(v).tolist() for k, v in spec["axes"].items()},
        **spec["fixed"],
    }
    if variant:
        definition["variant"] = variant
    key = json.dumps(definition, sort_keys=True)
    digest = hashlib.sha256(key.encode()).hexdigest()[:12]
    name = f"{model}_{variant}" if variant else model
    path = RESULTS / f"reference_{name}_{digest}.npy"
    if path.exists():
        return np.load(path)
    (_, a), (name_b, b) = spec["axes"].items()
    print(f"computing the quadrature reference for {name} (cached in {path.name}) ...", flush=True)
    t = time.perf_counter()
    saved = quadrature.brdf_rs
    if variant == "separable":
        quadrature.brdf_rs = _SeparableGgx()
    elif variant is not None:
        raise ValueError(variant)
    try:
        ref = np.array(
            [
                [
                    quadrature.directional_albedo(model, mu, **{name_b: v}, **spec["fixed"])[0]
                    for v in b
                ]
                for mu in a
            ]
        )
    finally:
        quadrature.brdf_rs = saved
    print(f"  {time.perf_counter() - t:.1f} s", flush=True)
    RESULTS.mkdir(parents=True, exist_ok=True)
    np.save(path, ref)
    return ref


class _SeparableGgx:
    """brdf_rs, except that `eval("ggx", ...)` is GGX with the separable Smith term
    G1(wi)·G1(wo) in place of the height-correlated G2 = 1/(1 + Λi + Λo): the BRDF times
    G1·G1/G2 = (1 + Λi + Λo)/((1 + Λi)(1 + Λo)) = (1 + Λi/(1 + Λo))/(1 + Λi)."""

    def __getattr__(self, name):
        return getattr(brdf_rs, name)

    @staticmethod
    def eval(model, wi, wo, **params):
        if model != "ggx":
            raise ValueError(model)
        f = brdf_rs.eval(model, wi, wo, **params)
        a2 = float(params["alpha"]) ** 2
        wi, wo = np.broadcast_arrays(np.asarray(wi, float), np.asarray(wo, float))

        def smith_lambda(w):
            mu = w[..., 2] / np.linalg.norm(w, axis=-1)
            with np.errstate(divide="ignore", invalid="ignore"):
                lam = 0.5 * (np.sqrt(1.0 + a2 * (1.0 - mu * mu) / (mu * mu)) - 1.0)
            return np.where(mu > 0, lam, np.inf), mu > 0

        li, up_i = smith_lambda(wi)
        lo, up_o = smith_lambda(wo)
        with np.errstate(invalid="ignore"):
            ratio = (1.0 + li / (1.0 + lo)) / (1.0 + li)
        return f * np.where(up_i & up_o, ratio, 0.0)[..., None]


_OPTIONS = ("samples", "sampler", "sequence", "tol", "max_samples", "fold_azimuth")


def run_brdf_rs(model, spec, ref, **options):
    """One table."""
    t = time.perf_counter()
    table = brdf_rs.albedo_table(model, spec["axes"], **spec["fixed"], **options)
    seconds = time.perf_counter() - t
    err = table.value[..., 0] - ref
    stderr = table.stderr[..., 0]
    samples = float(table.samples.sum())
    return {
        "seconds": seconds,
        "rms": float(np.sqrt(np.mean(err**2))),
        "rms_stderr": float(np.sqrt(np.mean(stderr**2))),
        "samples_total": samples,
        "ns_per_sample": seconds * brdf_rs.num_threads() * 1e9 / samples,
        "outside_3se": float(np.mean(np.abs(err) > 3 * stderr)),
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


# ------------------------------------------------------------------- Mitsuba


def run_mitsuba(spec, python, variant, budget, repeat):
    """Mitsuba's GGX table (benches/mitsuba_ggx.py in `python`), against the separable-
    Smith reference; [] with a printed note if mitsuba is not available there."""
    label = f"Mitsuba 3 {variant}"
    probe = subprocess.run(
        [python, "-c", "import mitsuba, numpy"], capture_output=True, text=True, check=False
    )
    if probe.returncode != 0:
        print(
            f"  {label:34s} skipped: mitsuba is not importable by {python} "
            "(pip install mitsuba, or pass --mitsuba-python)",
            flush=True,
        )
        return []
    ref = reference("ggx", spec, variant="separable")
    request = {
        "variant": variant,
        "mu": spec["axes"]["mu"].tolist(),
        "alpha": spec["axes"]["alpha"].tolist(),
        "samples": [64 * 2**k for k in range(16)],
        "budget": budget,
        "seed": 0,
        "repeat": max(2, repeat),
    }
    points = []
    with subprocess.Popen(
        [python, str(HERE / "mitsuba_ggx.py")],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    ) as proc:
        proc.stdin.write(json.dumps(request))
        proc.stdin.close()
        for line in proc.stdout:
            result = json.loads(line)
            table = np.asarray(result["table"])
            point = {
                "seconds": result["seconds"],
                "rms": float(np.sqrt(np.mean((table - ref) ** 2))),
                "samples": float(result["samples"] * table.size),
                "samples_per_cell": result["samples"],
            }
            points.append(point)
            print(
                f"  {label:34s} {json.dumps({'samples': result['samples']}):40s} "
                f"{point['seconds']:8.2f} s  RMS {point['rms']:.2e}",
                flush=True,
            )
            if point["rms"] < TARGETS[-1] / 2:
                proc.kill()
                break
        err = proc.stderr.read()
    if proc.returncode not in (0, -9) or not points:
        tail = "\n    ".join(err.strip().splitlines()[-5:])
        print(f"  {label}: stopped with exit code {proc.returncode}:\n    {tail}", flush=True)
    return points


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
    parser.add_argument("--repeat", type=int, default=1, help="best of N runs per point")
    parser.add_argument("--no-numpy", action="store_true", help="skip the NumPy baseline")
    parser.add_argument(
        "--mitsuba-python",
        default=sys.executable,
        help="a Python with mitsuba installed (GGX side-by-side; default: this one)",
    )
    parser.add_argument("--mitsuba-variant", default="llvm_ad_rgb")
    parser.add_argument("--mitsuba-budget", type=float, default=None, help="default: --budget")
    parser.add_argument("--no-mitsuba", action="store_true", help="skip Mitsuba")
    parser.add_argument("--out", type=Path, default=RESULTS / "albedo_convergence")
    parser.add_argument(
        "--replot",
        action="store_true",
        help="run nothing: rewrite OUT.md and OUT.png from the measurements in OUT.json",
    )
    args = parser.parse_args()
    if args.replot:
        saved = json.loads(args.out.with_suffix(".json").read_text())
        lines = report(saved["meta"], saved["results"])
        args.out.with_suffix(".md").write_text("\n".join(lines) + "\n")
        plot(args.out.with_suffix(".png"), saved["meta"], saved["results"])
        print(f"wrote {args.out.with_suffix('.md')}, .png from {args.out.with_suffix('.json')}")
        return
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
        run = functools.partial(run_brdf_rs, model, spec, ref)
        tols = [1e-3 / 2**k for k in range(16)]
        if model == "beckmann":
            # The visible-normal sampler (the default), Sobol points only.
            label = "VNDF + sobol"
            runs = [{"samples": n} for n in sizes]
            methods[label] = series(label, runs, run, args.budget)
            label = "VNDF + sobol + adaptive tol"
            runs = [{"samples": 256, "tol": t, "max_samples": 1 << 24} for t in tols]
            methods[label] = series(label, runs, run, args.budget)
            combos = []
        elif model == "ggx":
            # GGX has no diffuse lobe: "auto" is "importance" (VNDF); cosine is uniform's
            # story again. Fewer, slower-to-converge combinations keep the run short.
            combos = [("auto", "sobol"), ("auto", "random"), ("uniform", "sobol")]
        else:
            combos = [
                (sampler, sequence)
                for sequence in ("sobol", "random")
                for sampler in ("auto", "importance", "cosine", "uniform")
            ]
        for sampler, sequence in combos:
            label = f"{sampler} + {sequence}"
            runs = [{"samples": n, "sampler": sampler, "sequence": sequence} for n in sizes]
            methods[label] = series(label, runs, run, args.budget)
        if model != "beckmann":
            label = "auto + sobol + adaptive tol"
            runs = [{"samples": 256, "tol": t, "max_samples": 1 << 24} for t in tols]
            methods[label] = series(label, runs, run, args.budget)
            label = "auto + sobol, no azimuth fold"
            runs = [{"samples": n, "fold_azimuth": False} for n in sizes]
            methods[label] = series(label, runs, run, args.budget)
        for r in range(2, args.repeat + 1):
            print(f"  round {r} of {args.repeat}: the same points again", flush=True)
            for points in methods.values():
                for point in points:
                    again = run(**{k: point[k] for k in _OPTIONS if k in point})
                    point["seconds"] = min(point["seconds"], again["seconds"])
        if not args.no_numpy and model not in ("ggx", "beckmann"):
            rng = np.random.default_rng(0)
            label = "NumPy Monte Carlo (importance)"
            runs = [{"samples": n, "rng": rng} for n in [16, 64, 256, 1024, 4096, 16384]]
            methods[label] = series(
                label, runs, functools.partial(run_numpy, model, spec, ref), args.budget
            )
        if model == "ggx" and not args.no_mitsuba:
            budget = args.mitsuba_budget if args.mitsuba_budget is not None else args.budget
            points = run_mitsuba(
                spec, args.mitsuba_python, args.mitsuba_variant, budget, args.repeat
            )
            if points:
                methods[f"Mitsuba 3 {args.mitsuba_variant} (separable G)"] = points
        results[model] = methods

    meta = {
        "cpu": cpu_model(),
        "threads": brdf_rs.num_threads(),
        "isa": brdf_rs.isa(),
        "brdf_rs": brdf_rs.__version__,
        "python": platform.python_version(),
        "budget_seconds": args.budget,
        "repeat": args.repeat,
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
        f"# Albedo tables of {', '.join(results)}: run time against error",
        "",
        f"CPU: {meta['cpu']}, {meta['threads']} threads ({meta['isa']}); {meta['date']}; "
        f"budget {meta['budget_seconds']:.0f} s per method; the fastest of "
        f"{meta.get('repeat', 1)} interleaved rounds per point. RMS error over the table against "
        "a quadrature converged to 1e-9. Seconds to reach each RMS (— = not within budget).",
    ]
    for model, methods in results.items():
        lines += [
            "",
            f"## {model}",
            "",
            "| method | RMS 1e-3 | RMS 1e-4 | RMS 1e-5 | best RMS |"
            + (" ns/sample | cells > 3 se |" if model == "beckmann" else ""),
            "|---|---:|---:|---:|---:|" + ("---:|---:|" if model == "beckmann" else ""),
        ]
        for label, points in methods.items():
            cells = []
            for target in TARGETS:
                t = time_to(points, target)
                cells.append("—" if t is None else f"{t:.2f} s")
            best = min(points, key=lambda p: p["rms"])
            extra = ""
            if model == "beckmann":
                # At the most accurate point: cost per sample, and how often the error
                # bar is exceeded threefold.
                extra = f" {best['ns_per_sample']:.0f} | {100 * best['outside_3se']:.1f}% |"
            lines.append(f"| {label} | {' | '.join(cells)} | {best['rms']:.1e} |{extra}")
        if any(label.startswith("Mitsuba") for label in methods):
            lines += [
                "",
                "Mitsuba's GGX has the separable Smith term G1(wi)·G1(wo): its RMS is measured "
                "against that model's own converged quadrature. Its times exclude the "
                "interpreter start and the import; the JIT compilation (seconds per new sample "
                "count) is excluded by a warm-up pass and the best of 2 identical runs, for "
                "runs under 10 s.",
            ]
    return lines


def plot(path, meta, results):
    from brdf_rs.plot import convergence

    title = (
        f"Albedo tables of {', '.join(results)}: error against time\n"
        f"({meta['cpu']}, {meta['threads']} threads)"
    )
    try:
        convergence(results, targets=TARGETS, title=title, path=path, dpi=110)
    except ImportError:
        print("matplotlib not installed: no plot")


if __name__ == "__main__":
    main()
