"""Measures a scene's sheen layer against the white furnace.

A white sheen layer (``ks = 1``, full coverage) over a white Lambert base reflects, in
the albedo scaling the renderer uses, exactly 1 at every view direction: what the layer
reflects, ``E``, plus what it lets through, ``1 − E``. This script shades one pixel under
directional lights whose intensities are the weights of a product quadrature over the
hemisphere (Gauss-Legendre in cos θ, midpoints in φ), so the pixel's radiance is the
layered BRDF's directional albedo at the view direction, and prints its range over view
cosines for each sheen model and roughness. The departure from 1 is the quadrature's
error on the sheen lobe plus the layer's table interpolation, except where the lobe's own
albedo seen from the view, ``E`` (the lobe alone under the same lights, last column),
passes 1: the base's factor ``1 − E`` stops at 0 there and the layered albedo is the
lobe's.

    python scripts/sheen_layer_furnace.py [--n-mu 64] [--n-phi 128]
"""

from __future__ import annotations

import argparse
import math

import brdf_rs
import numpy as np
from brdf_rs import _spec

VIEW_MUS = [0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 1.0]
ALPHAS = [0.05, 0.1, 0.2, 0.4, 0.7, 1.0]


def hemisphere_lights(n_mu: int, n_phi: int) -> list[dict[str, object]]:
    x, w = np.polynomial.legendre.leggauss(n_mu)
    lights: list[dict[str, object]] = []
    for mu, wm in zip(0.5 * (x + 1), 0.5 * w, strict=True):
        s = math.sqrt(1 - mu * mu)
        for k in range(n_phi):
            phi = (k + 0.5) * 2 * math.pi / n_phi
            lights.append(
                {
                    "type": "directional",
                    "direction": [-s * math.cos(phi), -s * math.sin(phi), -mu],
                    "intensity": float(wm * 2 * math.pi / n_phi),
                }
            )
    return lights


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n-mu", type=int, default=64)
    parser.add_argument("--n-phi", type=int, default=128)
    args = parser.parse_args()
    lights = hemisphere_lights(args.n_mu, args.n_phi)
    n = np.array([0.0, 0.0, 1.0])
    v = np.array([[math.sqrt(1 - m * m), 0.0, m] for m in VIEW_MUS])
    base = {"model": "lambert", "kd": 1.0}
    print(f"view cosines {VIEW_MUS}; quadrature {args.n_mu} x {args.n_phi} lights")
    print(f"base alone: albedo {brdf_rs.shade(base, n, v, lights)[:, 0].round(5).tolist()}")
    print("| sheen model | alpha | min albedo | max albedo | lobe's max E |")
    print("|---|---|---|---|---|")
    for model in _spec.sheen_layers():
        for alpha in ALPHAS:
            layered = {**base, "sheen": {"model": model, "ks": 1.0, "alpha": alpha}}
            a = brdf_rs.shade(layered, n, v, lights)[:, 0]
            lobe = {"model": model, "kd": 0.0, "ks": 1.0, "alpha": alpha}
            e = brdf_rs.shade(lobe, n, v, lights)[:, 0]
            print(f"| {model} | {alpha:g} | {a.min():.4f} | {a.max():.4f} | {e.max():.4f} |")


if __name__ == "__main__":
    main()
