"""Why the plain half-vector estimator's error bar fails for Torrance-Sparrow at normal
incidence with few samples (the reason ``brdf_rs.albedo`` integrates such lobes in strata
with a control variate for Schlick's excess: rust/src/models/strata.rs, docs/error_bars.md).

At mu = 1 the lobe's own half-vector sampler gives the weight F·G (Schlick's F grows as
θh^10 in the far tail of the lobe). This script draws those weights directly (θh from the
Blinn half-vector distribution, f from ``brdf_rs.eval``), groups them into cells of
``--samples`` points, and reports the fraction of cells more than 3 standard errors
from the true albedo, the median standard error, and the weights' quantiles; then the
same for defensive mixtures (a fraction ``eps`` of points from a wider Blinn lobe,
weights under the one-sample mixture density), a remedy that does not work here.

    python scripts/torrance_sparrow_tail.py [--p 100] [--samples 256] [--cells 3000]
"""

from __future__ import annotations

import argparse

import brdf_rs
import numpy as np
from stderr_calibration import reference_albedo


def weights(p: float, eps: float, wide: float, n: int, rng: np.random.Generator) -> np.ndarray:
    u0 = rng.random(n)
    phi = 2 * np.pi * rng.random(n)
    from_wide = u0 < eps
    v = 1 - np.where(from_wide, u0 / max(eps, 1e-300), (u0 - eps) / (1 - eps))
    k = np.where(from_wide, wide, p)
    c = np.maximum(v, 1e-300) ** (1 / (k + 2))
    theta = np.arccos(c)

    def density(exponent: float) -> np.ndarray:
        return (exponent + 2) / (2 * np.pi) * c ** (exponent + 1)

    pdf_h = (1 - eps) * density(p) + eps * density(wide)
    pdf_wo = pdf_h / (4 * c)  # wo·h = cos θh at normal incidence
    to = 2 * theta
    wo = np.stack([np.sin(to) * np.cos(phi), np.sin(to) * np.sin(phi), np.cos(to)], -1)
    wi = np.broadcast_to([0.0, 0.0, 1.0], wo.shape)
    f = brdf_rs.eval("torrance_sparrow", wi, wo, kd=0, ks=1, p=p, eta=1.5)[:, 0]
    return np.where(wo[:, 2] > 0, f * wo[:, 2], 0.0) / pdf_wo


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--p", type=float, default=100.0)
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--cells", type=int, default=3000)
    args = ap.parse_args()
    ref = reference_albedo("torrance_sparrow", 1.0, {"kd": 0.0, "ks": 1.0, "p": args.p, "eta": 1.5})
    rng = np.random.default_rng(1)
    print(f"{'eps':>8s} {'wide p':>7s} {'P(|z|>3)':>9s} {'median se':>10s} {'rms error':>10s}")
    for eps, wide in [
        (0.0, args.p),
        (1 / 64, args.p / 4),
        (1 / 32, args.p / 4),
        (1 / 16, args.p / 4),
        (1 / 32, args.p / 2),
    ]:
        w = weights(args.p, eps, wide, args.cells * args.samples, rng)
        if eps == 0.0:
            rel = (w - ref) / ref
            q = np.quantile(rel, [0.5, 0.99, 0.999, 0.9999, 1.0])
            print(
                "relative weight deviation quantiles (50%, 99%, 99.9%, 99.99%, max):",
                " ".join(f"{x:.2e}" for x in q),
            )
        cells = w.reshape(args.cells, args.samples)
        mean = cells.mean(1)
        se = cells.std(1, ddof=1) / np.sqrt(args.samples)
        z = (mean - ref) / se
        print(
            f"{eps:8.4f} {wide:7.1f} {np.mean(np.abs(z) > 3):9.3f} {np.median(se):10.2e} "
            f"{np.sqrt(np.mean((mean - ref) ** 2)):10.2e}"
        )


if __name__ == "__main__":
    main()
