"""Very rough lobes: the albedo the integrator reports against a cubature of ``eval``.

A lobe far rougher than alpha = 1 sends almost every half vector its importance sampler
draws to a reflected direction below the horizon. The integrator must still estimate it
(falling back to cosine sampling), never report 0 ± 0. The reference is
``scripts/stderr_calibration.py``'s adaptive cubature of ``eval`` at normal incidence.

    python scripts/rough_lobes.py
"""

from __future__ import annotations

import brdf_rs
from stderr_calibration import reference_albedo

CASES = [
    ("ggx", {"alpha": 100.0}),
    ("ggx", {"alpha": 1e3}),
    ("beckmann", {"alpha": 30.0}),
    ("beckmann", {"alpha": 1e3}),
    ("ward", {"alpha_x": 1e3, "alpha_y": 1e3}),
]


def main() -> None:
    print(
        f"{'model':10s} {'params':28s} {'cubature':>12s} {'sequence':8s} {'value':>12s} "
        f"{'stderr':>10s} {'z':>6s}"
    )
    for model, params in CASES:
        ref = reference_albedo(model, 1.0, {"kd": 0.0, "ks": 1.0, **params})
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
