"""Very rough lobes: the albedo the integrator reports against a cubature of ``eval``.

A lobe far rougher than alpha = 1 sends almost every half vector its importance sampler
draws to a reflected direction below the horizon. The integrator must still estimate it
(falling back to cosine sampling), never report 0 ± 0. The reference is a product
Gauss-Legendre rule over (cos θo, φo) at normal incidence.

    python scripts/rough_lobes.py
"""

from __future__ import annotations

import itertools

import brdf_rs
import numpy as np

CASES = [
    ("ggx", {"alpha": 100.0}),
    ("ggx", {"alpha": 1e3}),
    ("beckmann", {"alpha": 30.0}),
    ("beckmann", {"alpha": 1e3}),
    ("ward", {"alpha_x": 1e3, "alpha_y": 1e3}),
]


def cubature(model: str, mu: float, panels: int = 96, **params: float) -> float:
    """``∫ f cos θo dωo`` by 24-point Gauss-Legendre panels in cos θo (clustered at both
    ends) × 64 points in φ over [0, π] (the integrand is even in φ)."""
    x, w = np.polynomial.legendre.leggauss(24)
    edges = 0.5 - 0.5 * np.cos(np.pi * np.linspace(0.0, 1.0, panels + 1))
    mu_o = np.concatenate([0.5 * (a + b) + 0.5 * (b - a) * x for a, b in itertools.pairwise(edges)])
    w_mu = np.concatenate([0.5 * (b - a) * w for a, b in itertools.pairwise(edges)])
    xp, wp = np.polynomial.legendre.leggauss(64)
    phi, w_phi = 0.5 * np.pi * (xp + 1), 0.5 * np.pi * wp
    m, p = np.meshgrid(mu_o, phi, indexing="ij")
    s = np.sqrt((1 - m) * (1 + m))
    wo = np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1).reshape(-1, 3)
    wi = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
    f = brdf_rs.eval(model, np.broadcast_to(wi, wo.shape), wo, **params)[:, 0]
    return float(2.0 * np.einsum("ij,i,j->", (f * wo[:, 2]).reshape(m.shape), w_mu, w_phi))


def main() -> None:
    print(
        f"{'model':10s} {'params':28s} {'cubature':>12s} {'sequence':8s} {'value':>12s} "
        f"{'stderr':>10s} {'z':>6s}"
    )
    for model, params in CASES:
        ref = cubature(model, 1.0, kd=0.0, ks=1.0, **params)
        for sequence in ("sobol", "random"):
            r = brdf_rs.albedo(model, 1.0, kd=0.0, ks=1.0, sequence=sequence, **params)
            v, se = float(r.value[0]), float(r.stderr[0])
            z = (v - ref) / se if se > 0 else float("inf")
            label = ", ".join(f"{k}={v:g}" for k, v in params.items())
            print(
                f"{model:10s} {label:28s} {ref:12.5e} {sequence:8s} {v:12.5e} {se:10.2e} {z:6.2f}"
            )


if __name__ == "__main__":
    main()
