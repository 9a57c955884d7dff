"""Prints a hash of ``brdf_rs.eval``'s bits per model, dtype and precision tier, of
``brdf_rs.sample`` and ``brdf_rs.pdf`` per model, of each model's spec as
``brdf_rs.models()`` gives it, and of a few tables, to compare two builds.

The inputs are fixed (seeded): random directions above and below the surface, near
the horizon, tilted normals and tangents, and each model's parameters drawn inside their
ranges. Run it with two builds and diff the output: a changed line is a model whose
values changed.

    python scripts/eval_hashes.py > after.txt
    PYTHONPATH=/path/to/other/build/python python scripts/eval_hashes.py > before.txt
    diff before.txt after.txt
"""

from __future__ import annotations

import hashlib
import itertools
import json

import brdf_rs
import numpy as np

N = 50_000
#: The tiers of ``brdf_rs.eval``'s ``precision=``.
PRECISIONS = ("accurate", "fast")
#: Parameters without defaults.
EXTRA = {
    "toon_diffuse": {"thresholds": [-0.2, 0.4], "colors": [[0.1, 0, 0], [0.5, 0.5, 0], [1, 1, 1]]}
}


def directions(rng: np.random.Generator) -> np.ndarray:
    v = rng.normal(size=(N, 3))
    v[: N // 4, 2] *= 1e-3  # near the horizon
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def parameters(rng: np.random.Generator, spec: dict) -> dict:
    out = {}
    for p in spec["params"]:
        if p["kind"] == "colour":
            out[p["name"]] = rng.uniform(0.0, 1.0, size=(N, 3))
        elif p["kind"] == "scalar" and p.get("varies", True):
            lo = max(p["min"], 1e-3)
            hi = min(p["max"], 1e3)
            values = np.exp(rng.uniform(np.log(lo), np.log(hi), size=N))
            out[p["name"]] = np.clip(values, p["min"], p["max"])
    return out


def main() -> None:
    models = brdf_rs.models()
    for name in sorted(models):
        spec = models[name]
        rng = np.random.default_rng(7)
        wi, wo = directions(rng), directions(rng)
        n = directions(rng)
        n[: N // 2] = [0.0, 0.0, 1.0]
        t = np.cross(n, directions(rng))
        t /= np.linalg.norm(t, axis=1, keepdims=True)
        params = {**parameters(rng, spec), **EXTRA.get(name, {})}
        for dtype, precision in itertools.product((np.float64, np.float32), PRECISIONS):
            try:
                takes_tangent = spec["tangent"] or spec["tangent_optional"]
                tangent = t.astype(dtype) if takes_tangent else None
                f = brdf_rs.eval(
                    name,
                    wi.astype(dtype),
                    wo.astype(dtype),
                    n.astype(dtype),
                    tangent=tangent,
                    precision=precision,
                    **params,
                )
                digest = hashlib.sha256(np.ascontiguousarray(f).tobytes()).hexdigest()[:16]
            except (ValueError, TypeError) as exc:
                digest = f"error: {type(exc).__name__}"
            label = np.dtype(dtype).name + ("" if precision == "accurate" else f" {precision}")
            print(f"{name:24s} {label:13s} {digest}")
        print(f"{name:24s} sample   {sampling(name, spec, wi, wo, n, t, params, rng)}")
        spec_text = json.dumps(spec, sort_keys=True, default=repr).encode()
        print(f"{name:24s} spec     {hashlib.sha256(spec_text).hexdigest()[:16]}")
    tables()


def sampling(
    name: str,
    spec: dict,
    wi: np.ndarray,
    wo: np.ndarray,
    n: np.ndarray,
    t: np.ndarray,
    params: dict,
    rng: np.random.Generator,
) -> str:
    """A digest of ``brdf_rs.sample``'s directions, weights and pdfs and of ``brdf_rs.pdf``
    (float64; the refusal's type where the model has no sampler)."""
    u = rng.uniform(0.0, 1.0, size=(N, 2))
    tangent = t if spec["tangent"] or spec["tangent_optional"] else None
    try:
        drawn = brdf_rs.sample(name, wi, u, n, tangent=tangent, **params)
        density = brdf_rs.pdf(name, wi, wo, n, tangent=tangent, **params)
    except (ValueError, TypeError) as exc:
        return f"error: {type(exc).__name__}"
    return digest_of(*drawn, density)


def digest_of(*arrays: np.ndarray) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()[:16]


#: Small albedo tables that exercise each sampler family, the end regions, strata,
#: the random sequence and adaptive stopping (the transmitting models: the integrator
#: over the whole sphere).
TABLES = [
    ("ggx", {"alpha": [0.05, 0.3, 1.0]}, {}),
    ("beckmann", {"alpha": [0.05, 0.3, 1.0]}, {}),
    ("torrance_sparrow", {"p": [1.0, 30.0, 300.0]}, {}),
    ("ward", {"alpha_x": [0.05, 0.3]}, {"alpha_y": 0.2}),
    ("ashikhmin_shirley", {"nu": [1.0, 100.0]}, {"nv": 10.0}),
    ("oren_nayar", {"sigma": [0.1, 1.0]}, {}),
    ("ggx_ms", {"alpha": [0.1, 0.8]}, {}),
    ("ggx_dielectric", {"alpha": [0.02, 0.3]}, {"eta": 1.5}),
    ("beckmann_dielectric", {"alpha": [0.05, 0.4]}, {"eta": 0.7}),
]


def tables() -> None:
    mu = [0.05, 0.5, 0.99, 1.0]
    for name, axes, fixed in TABLES:
        for options in ({"samples": 256}, {"sequence": "random", "samples": 256}, {"tol": 1e-3}):
            t = brdf_rs.albedo_table(name, {"mu": mu, **axes}, seed=3, **options, **fixed)
            label = "+".join(f"{k}={v}" for k, v in options.items())
            print(f"{name:24s} table    {label:24s} {digest_of(t.value, t.stderr, t.samples)}")


if __name__ == "__main__":
    main()
