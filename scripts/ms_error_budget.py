"""Where ``ggx_dielectric_ms``'s float64 error comes from, on the stress suite's worst
well-conditioned cases: the GGX lobe, the dielectric's Fresnel factor and the energy
table ``E`` it is divided by.

``ggx_dielectric_ms = ggx_dielectric / E``, and ``ggx_dielectric``'s reflection is
``F·lobe`` with ``lobe`` the value of ``ggx`` at ``ks = 1`` (the same ``alpha``). For each
well-conditioned case of ``brdf-rs stress --cases all`` (seed 0) at or above
``--min-ulps`` this prints each model's error in ulps against the 50-digit reference,
and the relative errors of the implied factors: ``F = ggx_dielectric / ggx`` and
``E = ggx_dielectric / ggx_dielectric_ms`` (each a quotient of two rounded values: to
about an ulp). It shows how the ms term's error adds up: a few ulps of the lobe, one
of ``F``, one or two of ``E``, and the division.

    python scripts/ms_error_budget.py [--min-ulps 3]

Needs mpmath (``pip install 'brdf-rs[stress]'``).
"""

from __future__ import annotations

import argparse

import brdf_rs
import mpmath
import numpy as np
from brdf_rs import _mpref, _stress

MODEL = "ggx_dielectric_ms"


def _rust(model: str, case: _stress._Case, params: dict) -> float:
    rows = [np.asarray([v], dtype=np.float64) for v in (case.wi, case.wo, case.n)]
    return float(brdf_rs.eval(model, *rows, **params)[0][0])


def _exact(model: str, case: _stress._Case, params: dict) -> mpmath.mpf:
    return _mpref.eval_mp(model, case.wi, case.wo, case.n, case.tangent, **params)[0]


def _relative_quotient(got: list[float], ref: list, num: int, den: int) -> str:
    """The relative error of ``got[num]/got[den]`` against ``ref[num]/ref[den]``."""
    if ref[num] == 0 or ref[den] == 0 or got[den] == 0:
        return f"{'-':>9s}"  # a transmission: no ggx lobe to compare with
    want = ref[num] / ref[den]
    return f"{float((mpmath.mpf(got[num]) / got[den] - want) / want):+9.2e}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--min-ulps", type=float, default=3.0)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    fmt = _stress._FORMATS["float64"]
    print(
        f"{'case':>4s} {'label':28s} {'eta':>8s} {'kappa':>5s} | ulps: {'ggx':>4s} "
        f"{'diel':>4s} {'ms':>4s} | rel. error: {'F':>9s} {'E':>9s}"
    )
    for i, case in enumerate(_stress._cases(MODEL, fmt, False, args.seed)):
        result = _stress._measure(MODEL, case, fmt, _mpref)
        if result.kappa is None or result.kappa > _stress.WELL_CONDITIONED:
            continue
        if result.ulps < args.min_ulps:
            continue
        runs = [
            ("ggx", {"ks": 1.0, "kd": 0.0, "alpha": case.params["alpha"]}),
            ("ggx_dielectric", case.params),
            (MODEL, case.params),
        ]
        got = [_rust(model, case, params) for model, params in runs]
        ref = [_exact(model, case, params) for model, params in runs]
        ulps = [fmt.ulps(g, fmt.nearest(r)) for g, r in zip(got, ref, strict=True)]
        print(
            f"{i:4d} {case.label[:28]:28s} {case.params['eta']:8.3g} {result.kappa:5.2f} | "
            f"{'':6s}{ulps[0]:4.0f} {ulps[1]:4.0f} {ulps[2]:4.0f} | {'':12s}"
            f"{_relative_quotient(got, ref, 1, 0)} {_relative_quotient(got, ref, 1, 2)}"
        )


if __name__ == "__main__":
    main()
