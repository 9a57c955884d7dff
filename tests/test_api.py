"""The public API's contract: shapes, dtypes, layouts, parameters, errors, threads."""

from __future__ import annotations

import re
import subprocess
import sys
import threading

import brdf_rs
import numpy as np
import pytest
from conftest import MODEL_NAMES, random_directions, random_params, required_extras

# ---------------------------------------------------------------------------- shapes


def test_broadcasting_shapes_and_defaults():
    wi = np.ones((4, 1, 3))
    wo = np.ones((5, 3))
    assert brdf_rs.eval("lambert", wi, wo).shape == (4, 5, 3)
    assert brdf_rs.eval("lambert", [0, 0, 1], [0, 0, 1]).shape == (3,)
    assert brdf_rs.eval("lambert", wi, wo, [0, 0, 1]).shape == (4, 5, 3)
    kd = np.full((7, 1, 1, 3), 0.5)
    assert brdf_rs.eval("lambert", wi, wo, kd=kd).shape == (7, 4, 5, 3)
    assert brdf_rs.eval("lambert", np.zeros((0, 3)), [0, 0, 1]).shape == (0, 3)


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_any_memory_layout_gives_the_same_result(model, rng):
    base_wi = random_directions(rng, 600)
    base_wo = random_directions(rng, 600)
    extra = required_extras(model)
    want = brdf_rs.eval(model, base_wi, base_wo, **extra)
    fortran = np.asfortranarray(base_wi)
    strided = np.zeros((600, 6))
    strided[:, ::2] = base_wo
    reversed_ = base_wi[::-1].copy()[::-1]
    np.testing.assert_array_equal(brdf_rs.eval(model, fortran, strided[:, ::2], **extra), want)
    np.testing.assert_array_equal(brdf_rs.eval(model, reversed_, base_wo, **extra), want)
    grid = brdf_rs.eval(
        model,
        base_wi.reshape(20, 30, 3).transpose(1, 0, 2),
        base_wo.reshape(20, 30, 3).transpose(1, 0, 2),
        **extra,
    )
    np.testing.assert_array_equal(grid.transpose(1, 0, 2).reshape(600, 3), want)


def test_broadcast_normals_and_parameters_follow_numpy(rng):
    wi = random_directions(rng, 12).reshape(3, 4, 3)
    wo = random_directions(rng, 12).reshape(3, 4, 3)
    n = random_directions(rng, 3).reshape(3, 1, 3)
    p = np.array([1.0, 5.0, 20.0, 80.0])
    got = brdf_rs.eval("torrance_sparrow", wi, wo, n, p=p, ks=0.7)
    full_n = np.broadcast_to(n, wi.shape)
    for i in range(3):
        for j in range(4):
            want = brdf_rs.eval(
                "torrance_sparrow", wi[i, j], wo[i, j], full_n[i, j], p=p[j], ks=0.7
            )
            np.testing.assert_array_equal(got[i, j], want)


# ---------------------------------------------------------------------------- dtypes


def test_dtype_rules(rng):
    wi = random_directions(rng, 8)
    wo = random_directions(rng, 8)
    f32 = brdf_rs.eval("phong", wi.astype(np.float32), wo.astype(np.float32))
    assert f32.dtype == np.float32
    assert brdf_rs.eval("phong", wi, wo).dtype == np.float64
    assert brdf_rs.eval("phong", wi.astype(np.float32), wo).dtype == np.float64
    ints = brdf_rs.eval("lambert", np.array([[0, 0, 1]]), np.array([[1, 0, 1]]))
    assert ints.dtype == np.float64
    big_endian = brdf_rs.eval("phong", wi.astype(">f8"), wo.astype(">f8"))
    np.testing.assert_array_equal(big_endian, brdf_rs.eval("phong", wi, wo))
    # A float32 batch stays float32 with float64 parameters (the kernel casts them).
    assert (
        brdf_rs.eval("phong", wi.astype(np.float32), wo.astype(np.float32), p=np.float64(3)).dtype
        == np.float32
    )


@pytest.mark.parametrize(
    "bad",
    [np.array([[1 + 1j, 0, 1]]), np.array([[True, False, True]]), np.array([["a", "b", "c"]])],
)
def test_unsupported_dtypes_are_type_errors(bad):
    with pytest.raises(TypeError, match=r"^wi: expected real numbers"):
        brdf_rs.eval("lambert", bad, [0, 0, 1])


def test_out_parameter(rng):
    wi = random_directions(rng, 50)
    out = np.empty((50, 3))
    result = brdf_rs.eval("phong", wi, [0, 0, 1], out=out)
    assert result is out
    np.testing.assert_array_equal(out, brdf_rs.eval("phong", wi, [0, 0, 1]))
    with pytest.raises(ValueError, match=r"out: expected shape \(50, 3\); got \(49, 3\)"):
        brdf_rs.eval("phong", wi, [0, 0, 1], out=np.empty((49, 3)))


# ---------------------------------------------------------------------- parameters


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_spatially_varying_parameters_match_per_row_calls(model, rng):
    if model == "toon_diffuse":
        pytest.skip("list parameters are uniform by design")
    n = 64
    wi = random_directions(rng, n)
    wo = random_directions(rng, n)
    params = random_params(rng, model, size=n)
    extra = {k: v for k, v in required_extras(model).items() if k not in params}
    got = brdf_rs.eval(model, wi, wo, **params, **extra)
    for i in range(n):
        row = {k: v[i] for k, v in params.items()}
        np.testing.assert_array_equal(got[i], brdf_rs.eval(model, wi[i], wo[i], **row, **extra))


def test_scalar_colour_is_grey_and_trailing_one_broadcasts(rng):
    wi = random_directions(rng, 10)
    grey = brdf_rs.eval("lambert", wi, [0, 0, 1], kd=0.3)
    rgb = brdf_rs.eval("lambert", wi, [0, 0, 1], kd=[0.3, 0.3, 0.3])
    column = brdf_rs.eval("lambert", wi, [0, 0, 1], kd=np.full((10, 1), 0.3))
    np.testing.assert_array_equal(grey, rgb)
    np.testing.assert_array_equal(grey, column)


def test_model_object_matches_eval(rng):
    wi = random_directions(rng, 100)
    wo = random_directions(rng, 100)
    m = brdf_rs.Model("torrance_sparrow", kd=[0.1, 0.2, 0.3], ks=0.8, p=50, eta=1.5)
    want = brdf_rs.eval("torrance_sparrow", wi, wo, kd=[0.1, 0.2, 0.3], ks=0.8, p=50, eta=1.5)
    np.testing.assert_array_equal(m.eval(wi, wo), want)
    np.testing.assert_array_equal(m(wi, wo), want)
    assert m.eval(wi.astype(np.float32), wo.astype(np.float32)).dtype == np.float32
    assert "torrance_sparrow" in repr(m)
    with pytest.raises(ValueError, match=r"eta = -1.0 is out of range"):
        brdf_rs.Model("torrance_sparrow", eta=-1)


def test_models_table_is_complete():
    specs = brdf_rs.models()
    # Every model of the reference, and the two that interpolate tables (docs/models.md).
    assert set(specs) == set(brdf_rs.reference.MODELS) | {"ggx_ms", "beckmann_ms"}
    ts = specs["torrance_sparrow"]
    assert ts["family"] == "A"
    assert "Summary eqs. 10" in ts["source"]
    names = [p["name"] for p in ts["params"]]
    assert names == ["kd", "ks", "p", "eta"]
    eta = ts["params"][3]
    assert eta["default"] == 1.5 and eta["kind"] == "scalar" and eta["range"] == "> 0 and finite"
    for name, spec in specs.items():
        assert spec["family"] in ("A", "B") and spec["summary"] and spec["source"], name
        for p in spec["params"]:
            assert p["doc"] and p["kind"] in ("scalar", "colour", "scalar list", "colour list")


def test_models_carry_every_per_model_fact_python_uses():
    """The spec owns what scenes, split-sum and energy tables need to know of a model: no
    Python module keeps its own list of model names."""
    specs = brdf_rs.models()
    params = {name: {p["name"] for p in s["params"]} for name, s in specs.items()}
    for name, s in specs.items():
        if s["family"] == "A":
            assert s["scene_slot"] == "brdf", name
            assert s["diffuse"] in ("whole", "lambert", "absent", "coupled"), name
        else:
            assert s["scene_slot"] in ("diffuse", "specular", "both") and s["diffuse"] is None
        assert s["weights"] is None or set(s["weights"]) <= params[name], name
        if s["dfg"] is not None:
            assert s["dfg"]["param"] in params[name] and "ks" in params[name], name
            assert s["dfg"]["axis"].split(":")[0] in ("mid", "log"), name
    # Energy tables are E(mu, alpha) at kd = 0, ks = 1 (brdf_rs.energy_compensation_table).
    compensated = [n for n, s in specs.items() if s["energy_table"]]
    assert {"ggx", "beckmann"} <= set(compensated)
    for name in compensated:
        assert specs[name]["family"] == "A" and {"kd", "ks", "alpha"} <= params[name], name
    for name, s in specs.items():
        for p in s["params"]:
            if p["one_more_than"] is not None:
                assert p["kind"] == "colour list", (name, p["name"])
                other = next(q for q in s["params"] if q["name"] == p["one_more_than"])
                assert other["kind"] == "scalar list", (name, p["name"])
                assert p["max_len"] == other["max_len"] + 1, (name, p["name"])
            else:
                assert p["kind"] != "colour list", (name, p["name"])
        exact = s["exact"]
        if exact is not None:
            assert s["family"] == "A" and exact["scales"] in params[name], name
            assert set(exact["params"]) <= params[name], name
            assert (exact["factor"] == "table") == (exact["table"] is not None), name
    exact = {n: s["exact"]["factor"] for n, s in specs.items() if s["exact"] is not None}
    assert exact == {
        "normalized_blinn_phong": "blinn_closed_form",
        "torrance_sparrow": "one",
        "ward": "table",
    }
    assert specs["ashikhmin_shirley"]["diffuse"] == "coupled"
    assert specs["kajiya_kay"]["scene_slot"] == "both"
    # One table, read once; callers get copies they may change.
    from brdf_rs import _spec

    assert _spec.specs() is _spec.specs()
    specs["ggx"]["energy_table"] = False
    assert brdf_rs.models()["ggx"]["energy_table"] is True


# -------------------------------------------------------------------------- errors


def test_unknown_model_lists_names_and_suggests():
    with pytest.raises(
        ValueError,
        match=r'unknown model "torrance_sparow" \(did you mean "torrance_sparrow"\?\); known models: lambert, oren_nayar',
    ):
        brdf_rs.eval("torrance_sparow", [0, 0, 1], [0, 0, 1])


def test_unknown_and_missing_parameters_are_type_errors():
    with pytest.raises(
        TypeError, match=r'phong: unknown parameter "shininess"; phong takes: kd, ks, p'
    ):
        brdf_rs.eval("phong", [0, 0, 1], [0, 0, 1], shininess=3)
    with pytest.raises(TypeError, match=r'toon_specular: missing required parameter "threshold"'):
        brdf_rs.eval("toon_specular", [0, 0, 1], [0, 0, 1])
    with pytest.raises(TypeError, match=r'kajiya_kay: missing required parameter "tangent"'):
        brdf_rs.eval("kajiya_kay", [0, 0, 1], [0, 0, 1])
    with pytest.raises(TypeError, match=r'lambert: unknown parameter "tangent"'):
        brdf_rs.eval("lambert", [0, 0, 1], [0, 0, 1], tangent=[1, 0, 0])


@pytest.mark.parametrize(
    ("model", "params", "message"),
    [
        ("phong", {"p": -1.0}, r"p = -1.0 is out of range: must be >= 0 and finite"),
        ("torrance_sparrow", {"eta": 0.0}, r"eta = 0.0 is out of range: must be > 0 and finite"),
        (
            "oren_nayar",
            {"sigma": 2.0},
            r"sigma = 2.0 is out of range: must be in \[0, 1.5707963267948966\]",
        ),
        ("lambert", {"kd": [0.5, -0.1, 0.2]}, r"kd\[1\] = -0.1 is out of range: must be >= 0"),
        ("phong", {"p": np.array([1.0, np.nan])}, r"p\[1\] = nan is out of range"),
        ("blinn_phong_fresnel", {"ks": 1.5}, r"ks = 1.5 is out of range: must be in \[0, 1\]"),
        (
            "lambert",
            {"kd": [0.5, 0.5]},
            r"kd: a colour is a number, an RGB triple or an array whose last axis has length 3",
        ),
        (
            "toon_diffuse",
            {"thresholds": [0.5, 0.1], "colors": [0, 0.5, 1]},
            r"thresholds must be ascending: thresholds\[1\] = 0.1 is below thresholds\[0\] = 0.5",
        ),
        (
            "toon_diffuse",
            {"thresholds": [0.5], "colors": [0, 0.5, 1]},
            r"colors: needs len\(thresholds\) \+ 1 = 2 colours; got 3",
        ),
    ],
)
def test_out_of_range_parameters_are_value_errors(model, params, message):
    with pytest.raises(ValueError, match=message):
        brdf_rs.eval(model, [0, 0, 1], [0, 0, 1], **params)


def test_shape_errors_name_both_shapes():
    with pytest.raises(
        ValueError,
        match=r"shapes do not broadcast: wi has batch shape \(5,\) and wo has batch shape \(4,\)",
    ):
        brdf_rs.eval("lambert", np.ones((5, 3)), np.ones((4, 3)))
    with pytest.raises(
        ValueError,
        match=r"wo: expected an array of shape \(\.\.\., 3\) \(x, y, z components\); got shape \(4, 2\)",
    ):
        brdf_rs.eval("lambert", np.ones((4, 3)), np.ones((4, 2)))
    with pytest.raises(
        ValueError,
        match=r"shapes do not broadcast: wi has batch shape \(5,\) and p has batch shape \(2,\)",
    ):
        brdf_rs.eval("phong", np.ones((5, 3)), [0, 0, 1], p=[1.0, 2.0])


@pytest.mark.parametrize(
    ("arg", "value", "problem"),
    [("wi", np.nan, "NaN"), ("wo", np.inf, "infinite"), ("n", 0.0, "a zero-length vector")],
)
def test_bad_vectors_name_argument_and_first_index(arg, value, problem):
    arrays = {"wi": np.ones((3, 4, 3)), "wo": np.ones((3, 4, 3)), "n": np.ones((3, 4, 3))}
    arrays[arg][1, 2] = value
    arrays[arg][2, 3] = value
    pattern = re.escape(f"{arg}[1, 2] is {problem} (first bad index [1, 2])")
    with pytest.raises(ValueError, match=pattern):
        brdf_rs.eval("lambert", arrays["wi"], arrays["wo"], arrays["n"])
    # check=False: no error, NaN in exactly the bad rows.
    got = brdf_rs.eval("lambert", arrays["wi"], arrays["wo"], arrays["n"], check=False)
    bad = np.zeros((3, 4), bool)
    bad[1, 2] = bad[2, 3] = True
    assert np.isnan(got[bad]).all() and not np.isnan(got[~bad]).any()


def test_bad_vector_in_a_broadcast_argument_reports_its_own_index():
    n = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=re.escape("n[1] is a zero-length vector")):
        brdf_rs.eval("lambert", np.ones((4, 1, 3)), np.ones((2, 3)), n)


# ------------------------------------------------------------------------- threads


def test_results_are_bitwise_identical_for_any_thread_count(rng):
    wi = random_directions(rng, 300_001)
    wo = random_directions(rng, 300_001)
    p = 10 ** rng.uniform(0, 3, size=300_001)
    before = brdf_rs.num_threads()
    try:
        results = []
        for threads in (1, 2, 3):
            brdf_rs.set_num_threads(threads)
            results.append(brdf_rs.eval("torrance_sparrow", wi, wo, p=p))
            results.append(
                brdf_rs.eval("normalized_phong", wi.astype(np.float32), wo.astype(np.float32), p=50)
            )
        for later in results[2:]:
            first = results[0] if later.dtype == np.float64 else results[1]
            np.testing.assert_array_equal(later, first)
    finally:
        brdf_rs.set_num_threads(before)
    with pytest.raises(ValueError, match="n: expected an integer from 1 to 65535"):
        brdf_rs.set_num_threads(0)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("precision", ["accurate", "fast"])
def test_every_models_bits_do_not_depend_on_the_thread_count(rng, dtype, precision):
    # Directions well above the horizon give ordinary powers (a normal base and result),
    # which the engine computes the short way block by block; a row with a huge exponent
    # every few thousand rows underflows its power, and the block holding it, and the
    # later ones of its task, take the full power. Tasks, and with them which blocks go
    # which way and which task is short, depend on the thread count: no row's bits may.
    # 25,093 rows: with three threads the last task holds 5 rows (no per-task caches).
    rows = 25_093
    wi, wo = (random_directions(rng, rows, unnormalized=False) for _ in range(2))
    for v in (wi, wo):
        v[:, 2] = np.abs(v[:, 2]) + 0.5
    p = np.full(rows, 50.0)
    p[rng.integers(0, rows, size=rows // 3001)] = 1e5
    args = [a.astype(dtype) for a in (wi, wo)]
    before = brdf_rs.num_threads()
    try:
        for name, spec in brdf_rs.models().items():
            # The defaults (uniform parameters, with the per-task caches) and random
            # parameters per row; the exponent as above.
            for params in ({}, random_params(rng, name, size=rows)):
                params = {**required_extras(name), **params, "precision": precision}
                if any(q["name"] == "p" for q in spec["params"]):
                    params["p"] = p
                results = []
                for threads in (1, 2, 3):
                    brdf_rs.set_num_threads(threads)
                    results.append(brdf_rs.eval(name, *args, **params))
                for later in results[1:]:
                    np.testing.assert_array_equal(later, results[0], err_msg=name)
    finally:
        brdf_rs.set_num_threads(before)


def test_large_outputs_written_past_the_caches_are_the_same_bits(rng):
    # Outputs of 32 MiB and more are written with non-temporal stores (16-byte aligned
    # blocks) and ordinary ones elsewhere: the same bits as calls on slices below that
    # size, for an aligned output and for one offset by a single element, in 1 and 2
    # threads (1,500,007 rows: the last task ends in a partial block).
    rows = 1_500_007  # 36 MB of float64 output
    wi = random_directions(rng, rows)
    wo = random_directions(rng, rows)
    want = np.concatenate(
        [
            brdf_rs.eval("torrance_sparrow", wi[k : k + 500_000], wo[k : k + 500_000], p=40.0)
            for k in range(0, rows, 500_000)
        ]
    )
    backing = np.empty(3 * rows + 1)
    before = brdf_rs.num_threads()
    try:
        for threads in (1, 2):
            brdf_rs.set_num_threads(threads)
            got = brdf_rs.eval("torrance_sparrow", wi, wo, p=40.0)
            assert got.ctypes.data % 16 == 0  # the streamed path
            np.testing.assert_array_equal(got, want)
            skip = 1 if backing.ctypes.data % 16 == 0 else 0
            shifted = backing[skip : skip + 3 * rows].reshape(rows, 3)
            assert shifted.ctypes.data % 16 == 8  # ordinary stores
            brdf_rs.eval("torrance_sparrow", wi, wo, p=40.0, out=shifted)
            np.testing.assert_array_equal(shifted, want)
    finally:
        brdf_rs.set_num_threads(before)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("precision", ["accurate", "fast"])
def test_a_row_has_the_same_bits_whatever_else_its_block_holds(rng, dtype, precision):
    # A block (128 rows) of ordinary lengths is normalized without the range selects; one
    # holding a row of extreme length (or a zero row) takes the robust normalization
    # whole. Every other row of that block must come out as it does on its own (in the
    # accurate tier bit for bit).
    rows = 300
    wi = random_directions(rng, rows).astype(dtype)
    wo = random_directions(rng, rows).astype(dtype)
    tiny, huge = (1e-160, 1e160) if dtype == np.float64 else (1e-25, 1e25)
    scaled_wi, scaled_wo = wi.copy(), wo.copy()
    scaled_wi[5] *= tiny  # first block
    scaled_wo[140] *= huge  # second block
    scaled_wi[260] = 0.0  # third block: a zero row gives NaN there
    for model in ("torrance_sparrow", "ggx", "ward", "lambert"):
        extras = required_extras(model)
        alone = np.concatenate(
            [
                brdf_rs.eval(model, wi[k : k + 1], wo[k : k + 1], precision=precision, **extras)
                for k in range(rows)
            ]
        )
        got = brdf_rs.eval(model, scaled_wi, scaled_wo, check=False, precision=precision, **extras)
        others = np.setdiff1d(np.arange(rows), [5, 140, 260])
        if precision == "fast" and dtype == np.float64:
            # The fast tier's Newton normalization serves ordinary blocks only: the rest
            # of such a block is normalized exactly, within the tier's bound of the other.
            np.testing.assert_allclose(got[others], alone[others], rtol=1e-12, err_msg=model)
        else:
            np.testing.assert_array_equal(got[others], alone[others], err_msg=model)
        assert np.all(np.isnan(got[260]))
        if precision == "accurate":
            # Scaling by a power of two changes no bit of the normalized row.
            np.testing.assert_array_equal(got[[5, 140]], alone[[5, 140]], err_msg=model)


def test_concurrent_calls_match_serial_calls(rng):
    wi = random_directions(rng, 50_000)
    wo = random_directions(rng, 50_000)
    want = {m: brdf_rs.eval(m, wi, wo, **required_extras(m)) for m in MODEL_NAMES}
    failures = []

    def worker(model):
        for _ in range(3):
            if not np.array_equal(
                brdf_rs.eval(model, wi, wo, **required_extras(model)), want[model]
            ):
                failures.append(model)

    threads = [threading.Thread(target=worker, args=(m,)) for m in MODEL_NAMES]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not failures


def test_environment_sets_thread_count_and_isa():
    code = "import brdf_rs; print(brdf_rs.num_threads(), brdf_rs.isa())"
    env = {"BRDF_RS_NUM_THREADS": "3", "BRDF_RS_ISA": "baseline", "PATH": ""}
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    assert out.stdout.split() == ["3", "baseline"]


def test_instruction_set_paths_agree(rng):
    """The AVX-512, AVX2 and baseline loops compute the same values (to rounding)."""
    code = """
import sys, numpy as np, brdf_rs
rng = np.random.default_rng(5)
wi = rng.normal(size=(5000, 3)); wo = rng.normal(size=(5000, 3))
out = [brdf_rs.eval(m, wi, wo, **kw) for m, kw in [("torrance_sparrow", {"p": 40.0}), ("oren_nayar", {}), ("kajiya_kay", {"tangent": [1.0, 0.0, 0.0]})]]
np.save(sys.argv[1], np.stack(out))
"""
    results = {}
    for isa in ("baseline", "avx2", "avx512"):
        path = f"{np.random.default_rng().integers(1 << 60)}_{isa}.npy"
        import os
        import tempfile

        path = os.path.join(tempfile.gettempdir(), path)
        subprocess.run(
            [sys.executable, "-c", code, path], env={**os.environ, "BRDF_RS_ISA": isa}, check=True
        )
        results[isa] = np.load(path)
        os.remove(path)
    for isa in ("avx2", "avx512"):
        np.testing.assert_allclose(results[isa], results["baseline"], rtol=1e-13, atol=1e-300)


def test_out_of_the_wrong_dtype_or_type_is_a_clear_type_error():
    wi = np.tile([0.0, 0.0, 1.0], (4, 1))
    with pytest.raises(TypeError, match=r"^out: expected dtype float64 .* got float32$"):
        brdf_rs.eval("ggx", wi, wi, out=np.empty((4, 3), np.float32))
    with pytest.raises(TypeError, match=r"^out: expected dtype float32 .* got float64$"):
        brdf_rs.Model("ggx").eval(
            wi.astype(np.float32), wi.astype(np.float32), out=np.empty((4, 3))
        )
    with pytest.raises(TypeError, match=r"^out: expected a NumPy array, got list$"):
        brdf_rs.eval("ggx", wi, wi, out=[0.0] * 12)


def test_missing_directions_are_type_errors_naming_them():
    with pytest.raises(TypeError, match=r"^wi: expected an array of directions, got None$"):
        brdf_rs.eval("lambert", None, [0, 0, 1])
    with pytest.raises(TypeError, match=r"^wo: expected an array of directions, got None$"):
        brdf_rs.pdf("lambert", [0, 0, 1], None)
    with pytest.raises(TypeError, match=r"^n, v: expected arrays of normals and view"):
        brdf_rs.shade({"model": "lambert"}, None, [0, 0, 1], [])
