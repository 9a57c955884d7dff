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

``--steps`` also replays the GGX lobe's float64 arithmetic step by step, in the order
``rust/src/models/ggx.rs`` computes it (``lobe`` and ``smith_lobe``, before the
length-error factor), and prints each step's rounding error in units of ``u = 2^-53``
against the same formula in exact arithmetic on the same rounded unit vectors: where
the lobe's error comes from. It is a replay, not the kernel: keep it in step with that
file.

    python scripts/ms_error_budget.py [--min-ulps 3] [--steps]

Needs mpmath (``pip install 'brdf-rs[stress]'``).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Sequence
from typing import Any

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


def _relative_quotient(got: list[float], ref: list, num: int, den: int) -> float | None:
    """The relative error of ``got[num]/got[den]`` against ``ref[num]/ref[den]``."""
    if ref[num] == 0 or ref[den] == 0 or got[den] == 0:
        return None  # a transmission: no ggx lobe to compare with
    want = ref[num] / ref[den]
    return float((mpmath.mpf(got[num]) / got[den] - want) / want)


def _show(x: float | None) -> str:
    return f"{'-':>9s}" if x is None else f"{x:+9.2e}"


def _unit(v: Sequence[float]) -> list[float]:
    """``v/|v|`` rounded as the kernels round it: scaled by a power of two (exact), then
    times the rounded reciprocal of the rounded length."""
    e = math.frexp(max(abs(x) for x in v))[1]
    s = [math.ldexp(x, -e) for x in v]
    r = 1.0 / math.sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2])
    return [x * r for x in s]


def _length_error(v: Sequence[float]) -> float:
    """``|v|² − 1`` as ``Real::length_error`` computes it (to well under an ulp)."""
    c = 201326592.0  # 1.5·2^27: (x + c) − c keeps the high half of |x| <= 1

    def hi(x: float) -> float:
        return (x + c) - c

    h = [hi(x) for x in v]
    exact = ((h[0] * h[0] + h[1] * h[1]) - 1.0) + h[2] * h[2]
    rest = sum((x - xh) * (x + xh) for x, xh in zip(v, h, strict=True))
    return exact + rest


def _lobe_steps(
    wi: Sequence[Any], wo: Sequence[Any], n: Sequence[Any], alpha: Any, exact: bool
) -> dict[str, Any]:
    """The GGX lobe's intermediate values, in floats (``exact=False``, the kernel's order
    of operations) or in mpmath (the same formula, exact to 50 digits)."""
    sqrt: Callable[[Any], Any] = mpmath.sqrt if exact else math.sqrt

    def dot(a: Sequence[Any], b: Sequence[Any]) -> Any:
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

    def cross(a: Sequence[Any], b: Sequence[Any]) -> list[Any]:
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    alpha2 = alpha * alpha
    d_scale = alpha2 * (1 / mpmath.pi if exact else 1 / math.pi)
    mu_i, mu_o = dot(n, wi), dot(n, wo)
    e_n = dot(n, n) - 1 if exact else _length_error(n)
    e_i = dot(wi, wi) - 1 if exact else _length_error(wi)
    e_o = dot(wo, wo) - 1 if exact else _length_error(wo)
    # The half vector of the exact unit vectors: the sum less half the length errors.
    s = [(a + b) - (a * e_i + b * e_o) * 0.5 for a, b in zip(wi, wo, strict=True)]
    h = [x / sqrt(dot(s, s)) for x in s] if exact else _unit(s)
    cos_th = dot(n, h)
    # |n|²|h|² = 1 + e_n + e_h (the exact h has e_h = 0); |n + h|² = 2(1 + nh2) − |n − h|².
    nh2 = 1 + (e_n + (0 if exact else _length_error(h)))
    minus = [a - b for a, b in zip(n, h, strict=True)]
    m2 = dot(minus, minus)
    c2 = cos_th * cos_th
    sin2 = m2 * ((2 * (1 + nh2) - m2) * 0.25) if c2 > 0.5 else nh2 - c2
    # The denominator's two forms.
    one_minus = (1 - alpha) * (1 + alpha)
    if alpha <= 1:
        den = alpha2 * nh2 + one_minus * sin2
    else:
        den = nh2 + (-one_minus) * c2
    ndf = d_scale / (den * den)
    a_i = alpha2 * dot(cross(n, wi), cross(n, wi))
    a_o = alpha2 * dot(cross(n, wo), cross(n, wo))
    p_i = 2 * (sqrt(mu_i * mu_i + a_i) + mu_i)
    p_o = 2 * (sqrt(mu_o * mu_o + a_o) + mu_o)
    m, least = max(mu_i, mu_o), min(mu_i, mu_o)
    ratio = least / m
    r_i, r_o = (ratio, 1) if mu_i < mu_o else (1, ratio)
    pp = p_i * p_o
    q = least * pp + r_o * a_i * p_o + r_i * a_o * p_i
    return {
        "cos_th": cos_th,
        "sin2": sin2,
        "den": den,
        "D": ndf,
        "a_i": a_i,
        "a_o": a_o,
        "P_i": p_i,
        "P_o": p_o,
        "q": q,
        "G2/4mm": pp / (4 * q) / m,
        "lobe": ndf * pp / (4 * q) / m,
    }


def _steps_line(case: _stress._Case) -> str:
    """Each lobe step's rounding error, in u = 2^-53."""
    wi, wo, n = (_unit(v) for v in (case.wi, case.wo, case.n))
    alpha = case.params["alpha"]
    got = _lobe_steps(wi, wo, n, alpha, exact=False)
    with mpmath.workdps(50):
        mp = [[mpmath.mpf(x) for x in v] for v in (wi, wo, n)]
        want = _lobe_steps(*mp, mpmath.mpf(alpha), exact=True)
        u = mpmath.mpf(2) ** -53
        return "  ".join(f"{k} {float((got[k] - want[k]) / want[k] / u):+.2f}" for k in want)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--min-ulps", type=float, default=3.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--steps", action="store_true", help="replay the GGX lobe's steps (errors in u = 2^-53)"
    )
    args = parser.parse_args()
    fmt = _stress._FORMATS["float64"]
    print(
        f"{'case':>4s} {'label':28s} {'eta':>8s} {'kappa':>5s} | ulps: {'ggx':>4s} "
        f"{'diel':>4s} {'ms':>4s} | rel. error: {'F':>9s} {'E':>9s}"
    )
    e_errors: list[float] = []
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
        f_err = _relative_quotient(got, ref, 1, 0)
        e_err = _relative_quotient(got, ref, 1, 2)
        if e_err is not None:
            e_errors.append(abs(e_err))
        print(
            f"{i:4d} {case.label[:28]:28s} {case.params['eta']:8.3g} {result.kappa:5.2f} | "
            f"{'':6s}{ulps[0]:4.0f} {ulps[1]:4.0f} {ulps[2]:4.0f} | {'':12s}"
            f"{_show(f_err)} {_show(e_err)}"
        )
        if args.steps:
            print(f"{'':5s}lobe steps (u): {_steps_line(case)}")
    if e_errors:
        print(
            f"E over the {len(e_errors)} cases shown: largest |relative error| "
            f"{max(e_errors):.3g}, mean {sum(e_errors) / len(e_errors):.3g}"
        )


if __name__ == "__main__":
    main()
