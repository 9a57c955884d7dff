"""Splits a Fresnel variant's stress errors between its lobe and its Fresnel term.

    python scripts/stress_lobe_share.py beckmann_gen_schlick beckmann

Runs the stress set of ``variant`` (float64, all cases, seed 0, as ``brdf-rs stress``) and,
for each well-conditioned case (κ ≤ 4), measures the base model's lobe alone on the same
directions (``kd = 0``, ``ks = 1``, the case's ``alpha``) against its own 50-digit value.
Prints the worst cases: the variant's error in ulps, the lobe's, κ, the case and its
parameters. Needs mpmath.
"""

from __future__ import annotations

import argparse

from brdf_rs import _mpref, _stress


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("variant", help="e.g. beckmann_gen_schlick")
    parser.add_argument("base", help="the model whose lobe it uses, e.g. beckmann")
    parser.add_argument("--top", type=int, default=12)
    args = parser.parse_args()
    fmt = _stress._FORMATS["float64"]
    rows = []
    for case in _stress._cases(args.variant, fmt, False, 0):
        result = _stress._measure(args.variant, case, fmt, _mpref)
        if result.kappa is None or result.kappa > _stress.WELL_CONDITIONED:
            continue
        lobe_params = {"kd": 0.0, "ks": 1.0, "alpha": case.params["alpha"]}
        lobe_case = _stress._Case(
            label=case.label, wi=case.wi, wo=case.wo, n=case.n, tangent=None, params=lobe_params
        )
        lobe = _stress._measure(args.base, lobe_case, fmt, _mpref)
        params = {k: v for k, v in case.params.items() if k != "kd"}
        rows.append((result.ulps, lobe.ulps, result.kappa, case.label, params))
    rows.sort(key=lambda r: -r[0])
    print(f"{len(rows)} well-conditioned cases; worst {args.top}:")
    print("variant ulps  lobe ulps  kappa  case  parameters")
    for ulps, lobe_ulps, kappa, label, params in rows[: args.top]:
        print(f"{ulps:12g} {lobe_ulps:10g} {kappa:6.2f}  {label}  {params}")


if __name__ == "__main__":
    main()
