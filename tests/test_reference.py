"""Every model against the pure-Python reference: random and adversarial inputs, float64
and float32, uniform and per-element (spatially varying) parameters."""

from __future__ import annotations

import math

import brdf_rs
import numpy as np
import pytest
from conftest import (
    FAMILY_A,
    REFERENCE_MODELS,
    SPECS,
    TRANSMISSION,
    condition,
    random_directions,
    random_params,
    reference_rgb,
    row_params,
    takes_tangent,
)

EPS64 = np.finfo(np.float64).eps
EPS32 = np.finfo(np.float32).eps
N_RANDOM = 5_000
# float32 lobes below 2^-100 are flushed to 0 (a lobe feeds at most a normalization
# factor ~1e4 and G/(4 mu_i mu_o) ~1e3 before the output): absolute slack.
ATOL32 = 2.0**-100 * 1e8
# Below the normal range a float64 has fewer than 53 bits and 1e-12 of a value is less
# than one unit in its last place: 1e-12 of the smallest normal as an absolute floor (the
# stress suite's relative errors are against max(|exact|, smallest normal) as well).
ATOL64 = 1e-12 * float(np.finfo(np.float64).tiny)


def hemisphere_biased(rng, n_vectors, count):
    """Random directions, 75% of them on the side of their normal."""
    w = random_directions(rng, count)
    flip = (np.einsum("ij,ij->i", w, n_vectors) < 0) & (rng.random(count) < 0.75)
    w[flip] *= -1
    return w


def random_case(rng, model, count):
    n = random_directions(rng, count)
    n[: count // 4] = [0.0, 0.0, 1.0]
    wi = hemisphere_biased(rng, n, count)
    wo = hemisphere_biased(rng, n, count)
    tangent = random_directions(rng, count) if takes_tangent(model) else None
    return wi, wo, n, tangent


def close(got, want, cond, rtol, eps, atol):
    """|got - want| <= (rtol + 32 eps cond) |want| + atol, exact for zeros and infinities
    (an equal channel is close whatever cond is: cond = inf times a zero channel is NaN)."""
    with np.errstate(invalid="ignore"):  # inf·0, where the channels' equality decides
        tol = (rtol + 32 * eps * cond) * np.abs(want) + atol
    both_inf = np.isinf(got) & np.isinf(want) & (np.sign(got) == np.sign(want))
    with np.errstate(invalid="ignore"):  # inf − inf where both_inf already decides
        return bool(np.all(both_inf | (got == want) | (np.abs(got - want) <= tol)))


def assert_close(model, got, want, cond, rtol, eps, atol, label):
    assert close(got, want, cond, rtol, eps, atol), (
        f"{model} {label}: got {got}, reference {want}, condition {cond:.3g}, "
        f"error {np.max(np.abs(got - want) / np.maximum(np.abs(want), np.finfo(float).tiny)):.3g}"
    )


def check_rows_against_reference(
    model,
    rng,
    case,
    params,
    *,
    precision="accurate",
    tol64=(1e-12, ATOL64),
    tol32=(1e-5, ATOL32),
    excusable=0.02,
    delta=1e-7,
):
    """Evaluates ``model`` at ``case`` (``wi, wo, n, tangent``, as :func:`random_case`
    returns them) in float64 and in float32 (inputs and parameters rounded to
    float32) and holds each row to the reference: within ``rtol·|want| + atol`` (``tol64``,
    ``tol32``: ``(rtol, atol)``; float32 against the reference on the rounded inputs), or,
    where not, within what the inputs' precision allows. At most a share ``excusable`` of
    the rows may need that allowance (an ill-conditioned reference), and most must be
    nonzero, so that the comparison has teeth. ``delta``: the nudge of :func:`condition`.
    The defaults are the accurate tier's bounds."""
    wi, wo, n, tangent = case
    count = len(wi)
    got64 = brdf_rs.eval(model, wi, wo, n, tangent=tangent, precision=precision, **params)
    f32 = {k: np.asarray(v, np.float32) for k, v in params.items()}
    as32 = lambda a: None if a is None else a.astype(np.float32)  # noqa: E731
    got32 = brdf_rs.eval(
        model, as32(wi), as32(wo), as32(n), tangent=as32(tangent), precision=precision, **f32
    )
    assert got64.dtype == np.float64 and got32.dtype == np.float32
    assert not np.isnan(got64).any() and not np.isnan(got32).any()
    (rtol64, atol64), (rtol32, atol32) = tol64, tol32

    excused = 0  # rows that needed more than the plain tolerance and were ill-conditioned
    nonzero = 0
    for i in range(count):
        t = None if tangent is None else tangent[i].tolist()
        p = row_params(model, params, i)
        want = reference_rgb(model, wi[i], wo[i], n[i], t, **p)
        nonzero += bool(np.any(want != 0))
        # float32: against the reference on the float32-rounded inputs.
        p32 = row_params(model, f32, i)
        t32 = None if tangent is None else as32(tangent[i]).astype(np.float64).tolist()
        want32 = reference_rgb(
            model, as32(wi[i]).tolist(), as32(wo[i]).tolist(), as32(n[i]).tolist(), t32, **p32
        )
        # Near zero only an absolute error is meaningful: float32 kernels flush lobe
        # values below 2^-100 (~7.9e-31) to 0 (see Real::flush_subnormal).
        check32 = np.all(np.isfinite(want32)) and np.max(np.abs(want32)) < 1e30
        if close(got64[i], want, 0.0, rtol64, EPS64, atol64) and (
            not check32 or close(got32[i], want32, 0.0, rtol32, EPS32, atol32)
        ):
            continue
        # Not within the plain tolerance: allow what the inputs' precision allows.
        cond = condition(
            model, wi[i].tolist(), wo[i].tolist(), n[i].tolist(), t, p, rng, want, delta=delta
        )
        excused += cond > 1e4
        assert_close(model, got64[i], want, cond, rtol64, EPS64, atol64, f"float64 row {i}")
        if check32:
            assert_close(model, got32[i], want32, cond, rtol32, EPS32, atol32, f"float32 row {i}")
    assert excused < excusable * count, excused
    assert nonzero > 0.3 * count, nonzero


@pytest.mark.parametrize("model", REFERENCE_MODELS)
def test_random_inputs_match_reference(model, rng):
    case = random_case(rng, model, N_RANDOM)
    params = random_params(rng, model, size=N_RANDOM)
    check_rows_against_reference(model, rng, case, params)


def _adversarial_geometry():
    """(label, wi, wo, n) cases where naive formulas break."""
    z = (0.0, 0.0, 1.0)
    cases = []
    for c in (1e-300, 1e-16, 0.0, -0.0):
        s = math.sqrt(1.0 - c * c) if c > 1e-8 else 1.0
        graze = (s, 0.0, c)
        cases.append((f"grazing wi n.wi={c}", graze, (0.3, -0.2, 0.9), z))
        cases.append((f"grazing wo n.wo={c}", (0.3, -0.2, 0.9), (-s, 0.0, c), z))
        cases.append((f"both grazing {c}", graze, (0.0, s, c), z))
    w = (0.48, -0.36, 0.8)
    mirror = (-0.48, 0.36, 0.8)
    cases += [
        ("wi == wo", w, w, z),
        ("wi == mirror(wo)", w, mirror, z),
        ("wi == -wo", w, tuple(-x for x in w), z),
        ("wi == n", z, w, z),
        ("wi == wo == n", z, z, z),
        ("tiny vectors", tuple(1e-200 * x for x in w), tuple(3e-201 * x for x in mirror), z),
        ("huge vectors", tuple(1e200 * x for x in w), tuple(7e199 * x for x in mirror), z),
        ("subnormal", (5e-324, 0.0, 1e-323), (0.0, -5e-324, 1e-323), z),
        ("tilted normal", (1.0, 2.0, 3.0), (-2.0, 1.0, 3.0), (0.1, 0.2, 1.0)),
        ("near mirror", w, (-0.48, 0.36 + 1e-9, 0.8), z),
        ("near opposite", w, (-0.48 + 1e-12, 0.36, -0.8), z),
        # Both normal but tiny, on opposite sides: a sharp sheen's power is below the
        # float range while its quotient by the cosines is not.
        ("both grazing opposite 1e-200", (1.0, 0.0, 1e-200), (-1.0, 1e-200, 1e-200), z),
    ]
    return cases


def _adversarial_params(model):
    base = random_params(np.random.default_rng(7), model)
    names = {p["name"] for p in SPECS[model]["params"]}
    variants = [("random", base)]
    if "p" in names:
        variants += [(f"p={p}", {**base, "p": p}) for p in (0.0, 1e4, 1e6)]
    if "eta" in names:
        variants.append(("eta=1", {**base, "eta": 1.0}))
    if "alpha" in names:
        smallest = next(p["min"] for p in SPECS[model]["params"] if p["name"] == "alpha")
        variants.append(("alpha=min", {**base, "alpha": smallest}))
    if "sigma" in names:
        variants += [(f"sigma={s}", {**base, "sigma": s}) for s in (0.0, math.pi / 2)]
    if model == "toon_specular":
        variants.append(("threshold=1", {**base, "threshold": 1.0}))
    return variants


@pytest.mark.parametrize("model", REFERENCE_MODELS)
def test_adversarial_inputs_never_nan_and_match_reference(model):
    rng = np.random.default_rng(3)
    tangent = (0.6, 0.0, 0.8) if takes_tangent(model) else None
    for plabel, params in _adversarial_params(model):
        for glabel, wi, wo, n in _adversarial_geometry():
            got = brdf_rs.eval(model, wi, wo, n, tangent=tangent, **params)
            label = f"{glabel}, {plabel}"
            assert not np.isnan(got).any(), f"{model}: NaN for {label}"
            plain = {k: np.asarray(v).tolist() for k, v in params.items()}
            want = reference_rgb(model, wi, wo, n, tangent, **plain)
            if close(got, want, 0.0, 1e-12, EPS64, 0.0):
                continue
            cond = condition(model, list(wi), list(wo), list(n), tangent, plain, rng, want)
            assert_close(model, got, want, cond, 1e-12, EPS64, 0.0, label)


def test_family_a_is_zero_below_the_surface(rng):
    n = 1000
    wi = random_directions(rng, n)
    wo = random_directions(rng, n)
    wo[:, 2] = -np.abs(wo[:, 2])
    for model in FAMILY_A:
        if model in TRANSMISSION:
            continue  # defined on the whole sphere (tests/test_dielectric.py)
        assert (brdf_rs.eval(model, wi, wo) == 0).all(), model
        assert (brdf_rs.eval(model, wo, wi) == 0).all(), model
