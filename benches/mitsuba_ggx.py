"""Mitsuba 3's GGX albedo table, for the side-by-side in benches/albedo_convergence.py.

Run by that benchmark in a subprocess (a JIT failure inside Dr.Jit aborts the process;
it must not take the benchmark with it), with any Python that has mitsuba and numpy:

    pip install mitsuba        # e.g. into its own venv; not a brdf-rs dependency

The LLVM variants need a libLLVM that Dr.Jit can use (LLVM 14 and 15 fail to compile its
kernels: "Cannot select ... fmaximum"; Debian's libllvm19 works). Dr.Jit picks the
library up from DRJIT_LIBLLVM_PATH; if that is unset, the newest
/usr/lib/*/libLLVM*.so* of version 16 or later is used.

Reads a JSON request on stdin: {"variant", "mu": [...], "alpha": [...],
"samples": [n0, n1, ...], "budget": seconds, "seed": int, "repeat": int}. For each n,
estimates every cell's albedo with n samples per cell: `roughconductor` with
`distribution: ggx`, `material: none` (eta = 0, k = 1, so the conductor Fresnel term is
exactly 1) and visible-normal sampling (its default), `BSDF.sample` on one vectorized
batch of lanes per alpha (the mu of each lane in `si.wi`, uniforms from Mitsuba's
`independent` sampler), the weights summed in float64. Mitsuba's GGX uses the
*separable* Smith G = G1(wi)·G1(wo) (brdf-rs uses the height-correlated form), so its
table converges to a different function: the caller compares it with that function's
own reference.

Writes one JSON line per n to stdout: {"samples", "seconds", "table": [[...]]}, the
time the fastest of `repeat` identical runs (Dr.Jit compiles a kernel for each new lane
count on its first use, seconds for the 64 alphas; a warm-up pass comes first). Runs
longer than 10 s are not repeated (the compilation is then a few % of them). Stops
after the first n whose time passes the budget.
"""

from __future__ import annotations

import glob
import json
import os
import re
import sys
import time

import numpy as np


def _libllvm() -> str | None:
    best = None
    paths = glob.glob("/usr/lib/*/libLLVM*.so*") + glob.glob("/usr/lib/llvm-*/lib/libLLVM*.so*")
    for path in paths:
        m = re.search(r"libLLVM[-.]?(?:so\.)?(\d+)", os.path.basename(path))
        if m and int(m.group(1)) >= 16 and (best is None or int(m.group(1)) > best[0]):
            best = (int(m.group(1)), path)
    return best[1] if best else None


def main() -> None:
    request = json.load(sys.stdin)
    variant = request.get("variant", "llvm_ad_rgb")
    if variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ:
        path = _libllvm()
        if path:
            os.environ["DRJIT_LIBLLVM_PATH"] = path
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(variant)
    mus = np.asarray(request["mu"], dtype=np.float64)
    alphas = np.asarray(request["alpha"], dtype=np.float64)
    budget = float(request.get("budget", 60.0))
    seed = int(request.get("seed", 0))
    bsdfs = [
        mi.load_dict(
            {"type": "roughconductor", "distribution": "ggx", "alpha": float(a), "material": "none"}
        )
        for a in alphas
    ]
    ctx = mi.BSDFContext()
    # Mitsuba's own independent sampler: each lane's PCG32 state and stream are hashed
    # (TEA) from the seed and the lane index. (Raw mi.PCG32 lanes with consecutive
    # stream ids are correlated: the error then fell faster than 1/sqrt(n).)
    sampler = mi.load_dict({"type": "independent"})
    chunk_lanes = 1 << 22

    def table(n: int, stream: int) -> np.ndarray:
        """Every cell's mean weight over n samples; `stream` keys the random numbers."""
        out = np.zeros((mus.size, alphas.size))
        per_call = max(1, min(n, chunk_lanes // mus.size))
        calls = -(-n // per_call)
        for j, bsdf in enumerate(bsdfs):
            total = np.zeros(mus.size)
            for call in range(calls):
                m = min(per_call, n - call * per_call)
                lanes = m * mus.size
                key = ((seed * 1_000 + stream) * alphas.size + j) * calls + call
                sampler.seed(key % (1 << 32), lanes)
                mu = dr.repeat(mi.Float(mus.astype(np.float32)), m)
                si = dr.zeros(mi.SurfaceInteraction3f, lanes)
                si.wi = mi.Vector3f(dr.safe_sqrt(1.0 - mu * mu), 0.0, mu)
                sample1 = sampler.next_1d()
                _, weight = bsdf.sample(ctx, si, sample1, sampler.next_2d())
                sums = dr.block_sum(mi.Float64(weight.x), m)
                total += np.asarray(sums, dtype=np.float64)
            out[:, j] = total / n
        return out

    repeat = int(request.get("repeat", 2))
    table(64, stream=0)  # warm-up: trace and compile every kernel
    for k, n in enumerate(request["samples"]):
        # The kernels of a new lane count compile on first use: the fastest of `repeat`
        # identical runs (same streams, same table) is the sampling itself.
        seconds = float("inf")
        for _ in range(repeat):
            t = time.perf_counter()
            values = table(int(n), stream=k + 1)
            seconds = min(seconds, time.perf_counter() - t)
            if seconds > 10.0:
                break
        print(json.dumps({"samples": int(n), "seconds": seconds, "table": values.tolist()}))
        sys.stdout.flush()
        if seconds > budget:
            break


if __name__ == "__main__":
    main()
