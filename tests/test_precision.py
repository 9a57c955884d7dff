"""The ``precision=`` tiers of ``brdf_rs.eval`` and ``brdf_rs.Model``: the fast tier's
stated bound (relative error at most 1e-12 in float64 and 2e-6 in float32 on
well-conditioned inputs) against the pure-Python reference on random and adversarial
inputs, against the accurate tier on large random batches, and its handling of bad input
(the accurate tier's, row for row)."""

from __future__ import annotations

import pickle

import brdf_rs
import numpy as np
import pytest
from conftest import (
    MODEL_NAMES,
    REFERENCE_MODELS,
    SPECS,
    condition,
    random_directions,
    random_params,
    reference_rgb,
    required_extras,
    takes_tangent,
)
from test_reference import (
    ATOL32,
    EPS32,
    EPS64,
    _adversarial_geometry,
    check_rows_against_reference,
    close,
    random_case,
)

#: The fast tier's stated bounds (docs/numerics.md).
FAST_RTOL64 = 1e-12
FAST_RTOL32 = 2e-6
# Relative to max(|exact|, smallest normal), as the stress suite measures it: subnormal
# results are held to an absolute error.
ATOL64 = FAST_RTOL64 * np.finfo(np.float64).tiny
# float32 lobes below 2^-100 are flushed to 0 in both tiers: ATOL32 (test_reference.py).
#: The models the fast tier changes (powers, or microfacet length corrections).
FAST_MODELS = [m for m in MODEL_NAMES if SPECS[m]["fast_tier"]]
# Fast-tier models whose kernel keeps the accurate tier's bits in float64 (so with
# normalized=True the fast tier gives the accurate bits; otherwise only the AVX-512
# loops' normalization of the directions differs): charlie_sheen's three powers per row with the fast power's
# table lookups kept the engine's loop scalar, so its fast tier takes the accurate series
# power there (docs/numerics.md).
ACCURATE_IN_FLOAT64 = {"charlie_sheen"}


def f32(v):
    return None if v is None else np.asarray(v, np.float32)


def r32(v):
    """``v`` rounded to float32, as float64 values (the float32 kernel's exact input)."""
    return None if v is None else f32(v).astype(np.float64).tolist()


def _exponents(model: str) -> list[str]:
    names = {p["name"] for p in brdf_rs.models()[model]["params"]}
    return [k for k in ("p", "nu", "nv") if k in names]


def test_unknown_precision_is_a_clear_error():
    wi = np.array([0.0, 0.0, 1.0])
    for call in (
        lambda p: brdf_rs.eval("phong", wi, wi, precision=p),
        lambda p: brdf_rs.eval("phong", [0, 0, 1], [0, 0, 1], precision=p),
        lambda p: brdf_rs.eval("phong", wi, wi, normalization="exact", precision=p),
        lambda p: brdf_rs.Model("phong", precision=p),
    ):
        with pytest.raises(
            ValueError, match=r'^precision: expected "accurate" or "fast"; got "Fast"'
        ):
            call("Fast")
        with pytest.raises(TypeError, match=r"^precision: expected"):
            call(None)


def test_accurate_is_the_default_bit_for_bit(rng):
    wi, wo = random_directions(rng, 1000), random_directions(rng, 1000)
    for model in MODEL_NAMES:
        extra = required_extras(model)
        a = brdf_rs.eval(model, wi, wo, **extra)
        b = brdf_rs.eval(model, wi, wo, precision="accurate", **extra)
        assert a.tobytes() == b.tobytes(), model


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_fast_tier_changes_exactly_the_models_it_names(rng, dtype):
    """The fast tier runs the accurate loops for models whose ``fast_tier`` is false
    (same bits) and its own for the others (different last bits somewhere): the list above
    must be the engine's. In float64 it changes every one of them, except the kernels that
    keep the accurate bits there, which change only where the AVX-512 loops normalize the
    directions their own way; in float32 the models with powers only (float32 carries no
    length corrections and keeps the accurate normalization), and gives the others the
    accurate bits."""
    count = 20_000
    wi = random_directions(rng, count).astype(dtype)
    wo = random_directions(rng, count).astype(dtype)
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    for model in MODEL_NAMES:
        extra = required_extras(model)
        if "tangent" in extra:
            extra["tangent"] = np.asarray(extra["tangent"], dtype)
        # Exponents whose powers leave the normal range in every block: there the models
        # with a separate power pass take the fast power too, not only the accurate
        # tier's table power for ordinary lanes.
        if _exponents(model):
            extra.update({k: 2000.5 for k in _exponents(model)})
        a = brdf_rs.eval(model, wi, wo, **extra)
        b = brdf_rs.eval(model, wi, wo, precision="fast", **extra)
        changed = model in FAST_MODELS and (dtype == np.float64 or SPECS[model]["powers"])
        # The baseline loops are the accurate ones (no fused multiply-add to build on).
        changed &= brdf_rs.isa() != "baseline"
        # Only the AVX-512 loops normalize differently in the fast tier.
        changed &= not (
            dtype == np.float64 and model in ACCURATE_IN_FLOAT64 and brdf_rs.isa() != "avx512"
        )
        assert (a.tobytes() != b.tobytes()) == changed, model


@pytest.mark.parametrize("model", FAST_MODELS)
def test_fast_tier_is_within_its_bound_of_accurate_on_large_batches(rng, model):
    """With unit inputs and ``normalized=True`` the tiers differ in the power, and in the
    microfacet lobes' length corrections and division-free half vector and square roots
    (a few ulps) alone: per row, the fast value is within the fast power's bound (at most
    5e-13 relative for a quotient cos^p/mu in float64) of the accurate one, over exponents
    from 1e-3 to 1e8.
    In float32 the models without powers give the same bits in both tiers; for the others
    the fast power is within (4 + 3|y|)·2^-25 of the exact one (y = p·ln x, at most about
    70 for a power above the 2^-100 flush, and about 140 where a model multiplies two such
    powers): 1e-5 relative, or the flush's absolute slack."""
    count = 200_000
    wi, wo, n, tangent = random_case(rng, model, count)
    unit = lambda a: None if a is None else a / np.linalg.norm(a, axis=-1, keepdims=True)  # noqa: E731
    wi, wo, n, tangent = unit(wi), unit(wo), unit(n), unit(tangent)
    params = random_params(rng, model, size=count)
    for k in _exponents(model):
        params[k] = 10.0 ** rng.uniform(-3, 8, size=count)
    args = (wi, wo, n)
    acc = brdf_rs.eval(model, *args, tangent=tangent, normalized=True, **params)
    fast = brdf_rs.eval(model, *args, tangent=tangent, normalized=True, precision="fast", **params)
    assert not np.isnan(fast).any()
    both_inf = np.isinf(acc) & (acc == fast)
    rel = np.abs(fast - acc) / np.maximum(np.abs(acc), np.finfo(np.float64).tiny)
    assert np.all(both_inf | (rel <= 6e-13)), float(np.max(np.where(both_inf, 0.0, rel)))
    if model in ACCURATE_IN_FLOAT64:
        assert acc.tobytes() == fast.tobytes()
    else:
        assert np.any(rel > 0), "the fast tier was not used"
    p32 = {k: np.asarray(v, np.float32) for k, v in params.items()}
    a32 = [f32(a) for a in (wi, wo, n)]
    t32 = f32(tangent)
    acc32 = brdf_rs.eval(model, *a32, tangent=t32, normalized=True, **p32)
    fast32 = brdf_rs.eval(model, *a32, tangent=t32, normalized=True, precision="fast", **p32)
    if not SPECS[model]["powers"]:
        assert acc32.tobytes() == fast32.tobytes()
        return
    assert not np.isnan(fast32).any()
    acc32, fast32 = acc32.astype(np.float64), fast32.astype(np.float64)
    both_inf = np.isinf(acc32) & (acc32 == fast32)
    err = np.where(both_inf, 0.0, np.abs(fast32 - acc32))
    assert np.all(err <= 1e-5 * np.abs(acc32) + ATOL32), float(np.max(err / np.abs(acc32)))
    assert np.any(err > 0), "the fast tier was not used in float32"


@pytest.mark.parametrize("model", [m for m in FAST_MODELS if m in REFERENCE_MODELS])
def test_fast_random_inputs_match_reference(model, rng):
    """As test_reference.py's random test, with the fast tier's bound: within 1e-12
    (float64) and 2e-6 (float32) of the reference, or within what the inputs' own
    precision allows where the reference is ill-conditioned."""
    count = 3000
    case = random_case(rng, model, count)
    params = random_params(rng, model, size=count)
    for k in _exponents(model):
        params[k] = 10.0 ** rng.uniform(-2, 6, size=count)
    check_rows_against_reference(
        model,
        rng,
        case,
        params,
        precision="fast",
        tol64=(FAST_RTOL64, ATOL64),
        tol32=(FAST_RTOL32, ATOL32),
        excusable=0.05,
    )


@pytest.mark.parametrize("model", [m for m in FAST_MODELS if m in REFERENCE_MODELS])
def test_fast_adversarial_inputs_match_reference(model):
    """Grazing angles down to 1e-300, the mirror direction and next to it, wi = -wo, tiny,
    huge and subnormal vectors, exponents up to 1e8: never NaN, within the bound."""
    rng = np.random.default_rng(3)
    tangent = (0.6, 0.0, 0.8) if takes_tangent(model) else None
    base = random_params(np.random.default_rng(7), model)
    variants = [("random", base)]
    for k in _exponents(model):
        variants += [(f"{k}={p}", {**base, k: p}) for p in (0.0, 0.5, 1e4, 1e6, 1e8)]
    for plabel, params in variants:
        for glabel, wi, wo, n in _adversarial_geometry():
            label = f"{glabel}, {plabel}"
            got = brdf_rs.eval(model, wi, wo, n, tangent=tangent, precision="fast", **params)
            assert not np.isnan(got).any(), f"{model}: NaN for {label}"
            plain = {k: np.asarray(v).tolist() for k, v in params.items()}
            want = reference_rgb(model, wi, wo, n, tangent, **plain)
            if not close(got, want, 0.0, FAST_RTOL64, EPS64, ATOL64):
                cond = condition(model, list(wi), list(wo), list(n), tangent, plain, rng, want)
                assert close(got, want, cond, FAST_RTOL64, EPS64, ATOL64), (
                    f"{model} {label}: {got} vs {want}, condition {cond:.3g}"
                )
            if glabel in ("tiny vectors", "huge vectors", "subnormal"):
                continue  # beyond float32's range: NaN-free is all that is asked
            got32 = brdf_rs.eval(
                model, f32(wi), f32(wo), f32(n), tangent=f32(tangent), precision="fast", **params
            )
            assert not np.isnan(got32).any(), f"{model}: float32 NaN for {label}"
            p32 = {
                k: np.asarray(v, np.float32).astype(np.float64).tolist() for k, v in params.items()
            }
            want32 = reference_rgb(model, r32(wi), r32(wo), r32(n), r32(tangent), **p32)
            if np.all(np.isfinite(want32)) and np.max(np.abs(want32)) < 1e30:
                if not close(got32, want32, 0.0, FAST_RTOL32, EPS32, ATOL32):
                    cond = condition(
                        model, r32(wi), r32(wo), r32(n), r32(tangent), p32, rng, want32
                    )
                    assert close(got32, want32, cond, FAST_RTOL32, EPS32, ATOL32), (
                        f"{model} float32 {label}: {got32} vs {want32}, condition {cond:.3g}"
                    )


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_bad_rows_behave_as_in_the_accurate_tier(dtype):
    """NaN, infinite, zero, tiny and huge rows in a block of ordinary ones: the same NaN
    rows (check=False) and the same error (check=True) in both tiers; the ordinary rows
    of such a block are the accurate tier's normalization too."""
    rng = np.random.default_rng(5)
    wi = random_directions(rng, 300).astype(dtype)
    wo = random_directions(rng, 300).astype(dtype)
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    big = 1e300 if dtype == np.float64 else 1e30
    wi[7] = [np.nan, 0, 1]
    wi[140] = [0, 0, 0]
    wo[141] = [np.inf, 0, 1]
    wo[142] = [big, 0, big]
    wi[143] = [1 / big, 1 / big, 1 / big]
    for precision in ("accurate", "fast"):
        got = brdf_rs.eval("torrance_sparrow", wi, wo, p=40.0, check=False, precision=precision)
        bad = np.isnan(got).any(axis=1)
        assert np.flatnonzero(bad).tolist() == [7, 140, 141], precision
        with pytest.raises(ValueError, match=r"^wi\[7\] is NaN \(first bad index \[7\]\)"):
            brdf_rs.eval("torrance_sparrow", wi, wo, p=40.0, precision=precision)
    acc = brdf_rs.eval("torrance_sparrow", wi, wo, p=40.0, check=False)
    fast = brdf_rs.eval("torrance_sparrow", wi, wo, p=40.0, check=False, precision="fast")
    ok = ~np.isnan(acc).any(axis=1)
    # The fast power's bounds: 5e-13 in float64; (4 + 3|y|)·2^-25 in float32, with
    # |y| = p·|ln cos| at most about 70 above the 2^-100 flush.
    rtol = 6e-13 if dtype == np.float64 else 1e-5
    assert np.allclose(fast[ok], acc[ok], rtol=rtol, atol=0), precision


def test_model_takes_precision_and_keeps_it():
    m = brdf_rs.Model("torrance_sparrow", p=300.0, kd=0.1, precision="fast")
    assert m.precision == "fast"
    assert "precision='fast'" in repr(m)
    rng = np.random.default_rng(2)
    wi, wo = random_directions(rng, 5000), random_directions(rng, 5000)
    want = brdf_rs.eval("torrance_sparrow", wi, wo, p=300.0, kd=0.1, precision="fast")
    assert m.eval(wi, wo).tobytes() == want.tobytes()
    assert m(wi.tolist()[0], wo.tolist()[0]).tobytes() == want[0].tobytes()
    assert m.eval(wi.astype(np.float32), wo.astype(np.float32)).dtype == np.float32
    again = pickle.loads(pickle.dumps(m))
    assert again.precision == "fast" and again.eval(wi, wo).tobytes() == want.tobytes()
    assert brdf_rs.Model("torrance_sparrow", p=300.0).precision == "accurate"
    assert "precision" not in repr(brdf_rs.Model("phong"))


@pytest.mark.parametrize("model", FAST_MODELS)
def test_fast_tier_keeps_axis_directions_exact(rng, model):
    """Directions along an axis, of any length and as given (not ``normalized=True``),
    normalize to exactly ±1 in both tiers: with ``wi`` (and ``wo`` in half the rows)
    along the normal, the fast value is within the tier's bound of the accurate one.
    A fast normalization a few ulps off unit length made ``charlie_sheen`` at ``wi == n``
    1e-9 off: the direction is exact, so the result must be too."""
    count = 512
    lengths = 10.0 ** rng.uniform(-200, 200, size=(count, 1))
    axes = np.eye(3)[rng.integers(0, 3, size=count)] * np.where(rng.random((count, 1)) < 0.5, -1, 1)
    n = axes * lengths
    wi = axes * 10.0 ** rng.uniform(-200, 200, size=(count, 1))
    wo = random_directions(rng, count) + 2.0 * axes
    wo[::2] = axes[::2] * 3.0
    extra = required_extras(model)
    params = random_params(rng, model)
    tangent = random_directions(rng, count) if takes_tangent(model) else None
    kw = {**params, **extra}
    if tangent is not None:
        kw["tangent"] = tangent
    acc = brdf_rs.eval(model, wi, wo, n, **kw)
    fast = brdf_rs.eval(model, wi, wo, n, precision="fast", **kw)
    assert np.isnan(fast).sum() == np.isnan(acc).sum()
    ok = ~np.isnan(acc)
    rel = np.abs(fast[ok] - acc[ok]) / np.maximum(np.abs(acc[ok]), np.finfo(np.float64).tiny)
    assert rel.max(initial=0.0) <= FAST_RTOL64, float(rel.max())


@pytest.mark.parametrize("precision", ["accurate", "fast"])
def test_tangents_at_the_parallel_threshold_give_a_clear_answer(rng, precision):
    """A tangent whose angle to the normal is near the refusal threshold (64 epsilons) is
    either used or refused with the parallel-tangent message, in both tiers: the check
    that names the bad row normalizes as the loop did (the fast tier's AVX-512 loops
    normalize their own way), so it never reports a bad row it cannot find again."""
    count = 4000
    n = random_directions(rng, count) * 10.0 ** rng.uniform(-1, 1, size=(count, 1))
    side = np.cross(n, random_directions(rng, count))
    side /= np.linalg.norm(side, axis=1, keepdims=True)
    unit_n = n / np.linalg.norm(n, axis=1, keepdims=True)
    angle = 64 * np.finfo(np.float64).eps * rng.uniform(0.9, 1.1, size=(count, 1))
    tangent = (unit_n + angle * side) * 10.0 ** rng.uniform(-1, 1, size=(count, 1))
    wi = unit_n + 0.5 * side
    wo = unit_n - 0.3 * side
    refused = 0
    for model in ("ashikhmin_shirley", "ward"):
        for k in range(count):
            rows = slice(k, k + 1)
            try:
                brdf_rs.eval(
                    model, wi[rows], wo[rows], n[rows], tangent=tangent[rows], precision=precision
                )
            except ValueError as e:
                assert "parallel to the normal" in str(e), str(e)
                refused += 1
    assert 0 < refused < 2 * count


@pytest.mark.parametrize("precision", ["accurate", "fast"])
def test_a_direction_along_n_does_not_depend_on_its_length(rng, precision):
    """``wi = c·n`` is the direction ``n`` whatever ``c > 0``: every model gives the value
    of ``wi = n`` to within rounding (1e-13 relative) for lengths from 1e-5 to 1e5, in
    both tiers. The normalized ``c·n`` may be an ulp off unit length; a kernel that read
    that as an angle (``charlie_sheen``'s Λ took ``1 − mu`` from the cosine) was 1e-9
    off there."""
    count = 256
    n = np.tile([0.0, 0.0, 1.0], (count, 1))
    wi = n * 10.0 ** rng.uniform(-5, 5, size=(count, 1))
    wo = np.tile(random_directions(rng, 1) * [1, 1, 0] + [0, 0, 1.5], (count, 1))
    for model in MODEL_NAMES:
        kw = {**random_params(rng, model), **required_extras(model)}
        if takes_tangent(model):
            kw["tangent"] = np.tile([1.0, 0.0, 0.0], (count, 1))
        got = brdf_rs.eval(model, wi, wo, n, precision=precision, **kw)
        want = brdf_rs.eval(model, n, wo, n, precision=precision, **kw)
        rel = np.abs(got - want) / np.maximum(np.abs(want), np.finfo(np.float64).tiny)
        assert rel.max() <= 1e-13, (model, float(rel.max()))
