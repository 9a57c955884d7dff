"""Measures zeltner_sheen's energy table against independent references.

The table (``brdf_rs.energy_compensation_table``) takes ``E`` from the closed form of the
lobe's albedo seen from the view and ``E_avg`` from an adaptive quadrature of it, with
``e_avg_stderr`` a bound on that quadrature's error. This script prints, per roughness,

- ``E_avg``, the same average in closed form (the paper's fit of ``R`` is a Gaussian in
  ``mu`` plus an offset, held at 0: its moment is written with the error function and
  evaluated at 40 digits from the fit's decimals), the error and the bound;
- the largest relative difference between the table's ``E`` and a cubature of
  ``∫ f(wi, wo)·mu_i dωi`` over the light (``tests/quadrature.py``'s ``view_albedo``,
  Gauss-Legendre nodes crowded toward grazing light) at views from 0.001 to 1 where
  ``E > 0``, and the cubature's largest value where ``E = 0`` (the fit held at 0).

    python scripts/zeltner_energy_check.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import brdf_rs
import mpmath
import numpy as np

MODEL = "zeltner_sheen"
ALPHAS = [0.01, 0.013, 0.02, 0.05, 0.08, 0.1, 0.13, 0.3, 0.7, 1.0]
MUS = [0.001, 0.01, 0.05, 0.2, 0.5, 0.9, 1.0]


def e_avg_reference(alpha: float) -> float:
    """``2 ∫_0^1 mu·max(0, φ((mu − m)/s)/s + o) dmu`` of the paper's fit (its decimals)
    in closed form with the error function, at 40 digits."""
    mp = mpmath.mp
    with mpmath.workdps(40):
        a = mpmath.mpf(alpha)
        f = mpmath.mpf
        s = a * (f("0.0206607") + f("1.58491") * a) / (f("0.0379424") + a * (f("1.32227") + a))
        m = (
            a
            * (f("-0.193854") + a * (f("-1.14885") + a * (f("1.7932") - f("0.95943") * a * a)))
            / (f("0.046391") + a)
        )
        o = (
            a
            * (f("0.000654023") + (f("-0.0207818") + f("0.119681") * a) * a)
            / (f("1.26264") + a * (f("-1.92021") + a))
        )
        lo, hi = mp.zero, mp.one
        if o < 0:  # the fit is positive where φ(t)/s > −o: |t| < t_max
            t_max = mpmath.sqrt(2 * mpmath.log(1 / (s * mpmath.sqrt(2 * mp.pi) * -o)))
            lo, hi = max(lo, m - s * t_max), min(hi, m + s * t_max)

        def pdf(t):
            return mpmath.exp(-t * t / 2) / mpmath.sqrt(2 * mp.pi)

        def cdf(t):
            return mpmath.erfc(-t / mpmath.sqrt(2)) / 2

        # ∫ x φ((x − m)/s)/s dx = m·ΔΦ − s·Δφ over t = (x − m)/s.
        t0, t1 = (lo - m) / s, (hi - m) / s
        total = m * (cdf(t1) - cdf(t0)) - s * (pdf(t1) - pdf(t0)) + o * (hi**2 - lo**2) / 2
        return float(2 * total)


def main() -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    import quadrature

    table = brdf_rs.energy_compensation_table(MODEL, MUS, ALPHAS)
    print(
        f"{'alpha':>6} {'E_avg':>23} {'error':>9} {'bound':>9} {'E vs cubature':>14}"
        f" {'at E = 0':>9}"
    )
    for j, alpha in enumerate(ALPHAS):
        exact = e_avg_reference(alpha)
        error = abs(float(table.e_avg[j]) - exact)
        cubature = quadrature.view_albedo(
            MODEL, MUS, n_mu=256, n_phi=256, grade=4.0, kd=0.0, ks=1.0, alpha=alpha
        )[:, 0]
        e = table.e[:, j]
        positive = e > 0
        relative = np.max(np.abs(e - cubature)[positive] / e[positive])
        # Where the fit is held at 0, E = 0 and the cubature of the lobe is 0 too.
        at_zero = np.max(np.abs(cubature[~positive]), initial=0.0)
        print(
            f"{alpha:>6} {table.e_avg[j]:>23.16e} {error:>9.2e} {table.e_avg_stderr[j]:>9.2e}"
            f" {relative:>14.1e} {at_zero:>9.1e}"
        )


if __name__ == "__main__":
    main()
