"""3-D engine LUTs (brdf_rs.lut with a layers axis): a rough dielectric's energy table
over (roughness, mu, eta) in Blender Cycles' glass layout, against the library's own
integrals; its trilinear lookup against a hand interpolation; its files read back (KTX2
and DDS by the independent reader, EXR by OpenEXR, the C header compiled and run)."""

from __future__ import annotations

import dataclasses
import json
import math
import re
import subprocess

import brdf_rs
import numpy as np
import pytest
from brdf_rs import lut
from conftest import run_cli
from test_lut import compile_and_run, compile_with_glslang, validate_with_naga
from test_lut import texture_reader as texture_reader  # the fixture, shared

#: Cycles' floors: perceptual roughness (alpha >= 1e-7, the model's smallest), mu.
R_FLOOR, MU_FLOOR = 3.1623e-4, 1e-4


def small(preset: str = "cycles_glass", n=(5, 4, 3), samples: int = 64, **changes):
    """The preset with ``n`` = (columns, rows, layers) texels and few samples."""
    spec = lut.preset(preset, samples=samples, **changes)
    nc, nr, nl = n
    return dataclasses.replace(
        spec,
        columns=dataclasses.replace(spec.columns, size=nc),
        rows=dataclasses.replace(spec.rows, size=nr),
        layers=dataclasses.replace(spec.layers, size=nl),
    )


@pytest.fixture(scope="module")
def glass():
    return lut.build(small(), interp_limit=4)


def ior_from_f0(f0):
    """Cycles' ior_from_F0, written out: the index whose normal-incidence reflectance is f0."""
    s = np.sqrt(f0)
    return (1 + s) / (1 - s)


# ------------------------------------------------------------------------------ layouts


def test_cycles_glass_presets_are_cycles_grid():
    for name, inside in (("cycles_glass", False), ("cycles_glass_inv", True)):
        s = lut.preset(name)
        assert s.shape == (16, 16, 16) and s.format == "R32G32_SFLOAT"
        assert s.model == "ggx_dielectric" and s.kind == "energy"
        k = np.arange(16)
        # rough = clamp(x / 15, 1e-4, 1) (ours: the model's smallest alpha), mu likewise
        assert s.columns.quantity == "perceptual"
        np.testing.assert_allclose(
            s.columns.physical(s.columns.positions()), np.maximum(k / 15, R_FLOOR) ** 2
        )
        np.testing.assert_allclose(s.rows.physical(s.rows.positions()), np.maximum(k / 15, 1e-4))
        # ior = ior_from_F0(z^4), z = clamp(k / 15, 1e-4, 0.99); the inverse table at 1/ior
        z = np.clip(k / 15, 1e-4, 0.99)
        ior = ior_from_f0(z**4)
        eta = s.layers.physical(s.layers.positions())
        np.testing.assert_allclose(eta, 1 / ior if inside else ior, rtol=1e-12)
        # and Cycles' lookup coordinate z = sqrt(|ior - 1| / (ior + 1)) finds them again
        # (to 1e-12: eta - 1 near z = 1e-4 keeps 8 digits)
        np.testing.assert_allclose(s.layers.quantity_of(eta), z, rtol=0, atol=1e-12)


def test_texels_are_the_energy_table_slices_by_eta_rows_mu_columns_roughness(glass):
    s = glass.spec
    r = s.columns.physical(s.columns.positions())
    mu = s.rows.physical(s.rows.positions())
    eta = s.layers.physical(s.layers.positions())
    e = brdf_rs.energy_compensation_table(
        "ggx_dielectric", mu, r, eta=eta, samples=64, tol=None, seed=0
    )
    assert glass.image.shape == (3, 4, 5, 2)  # layers, rows, columns, channels
    want = np.transpose(e.e, (2, 0, 1))  # e[mu, alpha, eta] -> [eta, mu, alpha]
    assert glass.image[..., 0].tobytes() == np.ascontiguousarray(want).tobytes()
    avg = np.broadcast_to(e.e_avg.T[:, None, :], want.shape)
    assert glass.image[..., 1].tobytes() == np.ascontiguousarray(avg).tobytes()
    np.testing.assert_array_equal(glass.stderr[..., 0], np.transpose(e.stderr, (2, 0, 1)))


def test_progress_counts_each_run_of_a_3d_build():
    spec = small(n=(3, 3, 2))
    calls = []
    lut.build(spec, interp_limit=2, progress=lambda done, _: calls.append(done))
    # E on the grid, E_avg's first round (30 cells per roughness and index), the same
    # between the texels (ends placement: 2 midpoints per axis); where E_avg halves
    # panels its run counts on past its first round
    runs = lut.passes(spec, 2)
    assert runs == [18, 30 * 3 * 2, 2 * 2 * 1, 30 * 2 * 1]
    assert calls[:4] == runs and all(c > runs[-1] for c in calls[4:])


def test_the_inverse_table_is_the_light_from_the_denser_side():
    t = lut.build(small("cycles_glass_inv", n=(3, 3, 3)), interp_limit=2)
    s = t.spec
    eta = s.layers.physical(s.layers.positions())
    assert np.all(eta <= 1)
    one = brdf_rs.albedo(
        "ggx_dielectric",
        float(s.rows.physical(s.rows.positions())[1]),
        alpha=float(s.columns.physical(s.columns.positions())[2]),
        eta=float(eta[2]),
        ks=1,
        kt=1,
        component="total",
        samples=1 << 14,
        seed=9,
    )
    assert abs(t.image[2, 1, 2, 0] - one.value[0]) <= 4 * math.hypot(
        t.stderr[2, 1, 2, 0], one.stderr[0]
    )


def test_ue5_glass_preset_is_unreals_layout_both_sides_of_the_interface_in_one_texel():
    s = lut.preset("ue5_glass")
    assert s.shape == (32, 32, 32) and s.format == "R16G16_UNORM"
    assert s.channel_names == ("E", "E_inv")
    k = np.arange(32)
    # Index = (id + 0.5)/N: NoV along x, Roughness along y (alpha = max(r, 0.01)^2), EtaIn =
    # 1 + 2 Index.z along z; x the light entering the denser side (eta), y leaving (1/eta)
    assert (s.columns.quantity, s.rows.quantity, s.layers.quantity) == ("mu", "perceptual", "eta")
    np.testing.assert_allclose(s.columns.physical(s.columns.positions()), (k + 0.5) / 32)
    np.testing.assert_allclose(s.rows.physical(s.rows.positions()), ((k + 0.5) / 32) ** 2)
    np.testing.assert_allclose(s.layers.physical(s.layers.positions()), 1 + 2 * (k + 0.5) / 32)
    small_spec = small("ue5_glass", n=(4, 3, 2), samples=64)
    t = lut.build(small_spec, interp_limit=2)
    mu = small_spec.columns.physical(small_spec.columns.positions())
    alpha = small_spec.rows.physical(small_spec.rows.positions())
    eta = small_spec.layers.physical(small_spec.layers.positions())
    for channel, index in ((0, eta), (1, 1 / eta)):
        e = brdf_rs.energy_compensation_table(
            "ggx_dielectric", mu, alpha, eta=index, samples=64, tol=None, seed=0
        )
        want = np.transpose(e.e, (2, 1, 0))  # [mu, alpha, eta] -> [eta, alpha (rows), mu]
        assert t.image[..., channel].tobytes() == np.ascontiguousarray(want).tobytes()
    # E alone on each side: no E_avg run (the two sides' grids, then both checked between
    # the texels: 2 midpoints and the 2 range ends per texel-centre axis)
    calls = []
    lut.build(small_spec, interp_limit=2, progress=lambda done, _: calls.append(done))
    assert calls == lut.passes(small_spec, 2) == [24, 24, 4 * 4 * 4, 4 * 4 * 4]


# ------------------------------------------------------------------------------- lookup


def test_trilinear_lookup_lands_on_texels_and_blends_eight_between_them(glass):
    s = glass.spec
    r = s.columns.physical(s.columns.positions())
    mu = s.rows.physical(s.rows.positions())
    eta = s.layers.physical(s.layers.positions())
    got = glass.lookup(mu[None, :, None], r[None, None, :], eta[:, None, None])
    # (the first texel of each axis is evaluated at its floor and the last layer at its
    # ceiling, so a lookup at those values reads a little of the neighbour: left out)
    inner = (slice(1, -1), slice(1, None), slice(1, None))
    np.testing.assert_allclose(got[inner], glass.decoded[inner], rtol=0, atol=1e-12)
    # between texels: fractions (0.25, 0.5, 0.75) of the way along columns, rows, layers
    q = [ax.positions() for ax in (s.columns, s.rows, s.layers)]
    f = (0.25, 0.5, 0.75)
    at = [q[a][1] + f[a] * (q[a][2] - q[a][1]) for a in range(3)]
    v = glass.decoded
    hand = sum(
        (f[0] if dx else 1 - f[0])
        * (f[1] if dy else 1 - f[1])
        * (f[2] if dz else 1 - f[2])
        * v[1 + dz, 1 + dy, 1 + dx]
        for dx in (0, 1)
        for dy in (0, 1)
        for dz in (0, 1)
    )
    phys = [
        ax.physical(np.array(x)) for ax, x in zip((s.columns, s.rows, s.layers), at, strict=True)
    ]
    np.testing.assert_allclose(glass.lookup(phys[1], phys[0], phys[2]), hand, atol=1e-12)


def test_lookup_needs_eta_on_a_3d_table_and_refuses_it_on_a_2d_one(glass):
    with pytest.raises(ValueError, match=r"layer: a 3-D table \(layers over eta\) needs its eta"):
        glass.lookup(0.5, 0.3)
    with pytest.raises(ValueError, match=r"layer: expected finite numbers, got nan at index 1"):
        glass.lookup(0.5, 0.3, [1.5, math.nan])
    flat = lut.build(
        lut.preset(
            "cycles",
            samples=16,
            columns=lut.Axis("perceptual", 3, "ends", floor=R_FLOOR),
            rows=lut.Axis("mu", 3, "ends", floor=MU_FLOOR),
        ),
        interp_limit=2,
    )
    with pytest.raises(ValueError, match="layer: this table is 2-D"):
        flat.lookup(0.5, 0.3, 1.5)


def test_off_grid_lookups_are_within_the_budget_of_fresh_integrals():
    t = lut.build(small(n=(6, 6, 4), samples=1024), interp_limit=6)
    rng = np.random.default_rng(4)
    mu = rng.uniform(0.05, 1, 12)
    r = rng.uniform(0.05, 1, 12)
    eta = (1 + (z := rng.uniform(0.05, 0.9, 12)) ** 2) / (1 - z**2)
    got = t.lookup(mu, r**2, eta)[:, 0]
    ref = brdf_rs.albedo(
        "ggx_dielectric",
        mu,
        alpha=r**2,
        eta=eta,
        ks=1,
        kt=1,
        component="total",
        samples=1 << 14,
        seed=3,
    )
    err = np.abs(got - ref.value[:, 0])
    assert np.all(err <= t.budget.total[0] + 3 * ref.stderr[:, 0])
    # the budget is not vacuous: a table of another index would miss it
    wrong = t.lookup(mu, r**2, np.full(12, 1.02))[:, 0]
    assert np.max(np.abs(wrong - ref.value[:, 0])) > t.budget.total[0]


# -------------------------------------------------------------------------------- files


@pytest.mark.parametrize("suffix", [".ktx2", ".dds"])
def test_ktx2_and_dds_are_3d_textures_read_back_by_the_independent_reader(
    glass,
    texture_reader,
    tmp_path,
    suffix,
):
    path = glass.save(tmp_path / f"g{suffix}")
    result = subprocess.run([str(texture_reader), str(path)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    head, *rows = result.stdout.splitlines()
    name, width, height, n, depth = head.split()
    assert name == ("R32G32_SFLOAT" if suffix == ".ktx2" else "R32G32_Float")
    assert (int(width), int(height), int(n), int(depth)) == (5, 4, 2, 3)
    got = np.array([[float(v) for v in row.split()] for row in rows])
    np.testing.assert_array_equal(got.reshape(glass.decoded.shape), glass.decoded)


def test_exr_stacks_the_slices_top_to_bottom(glass, tmp_path):
    OpenEXR = pytest.importorskip("OpenEXR")
    path = glass.save(tmp_path / "g.exr")
    with OpenEXR.File(str(path)) as f:
        chans = f.channels()
        meta = json.loads(f.header()["brdf-rs:lut"])
        red = np.asarray(chans["R"].pixels, dtype=np.float64)
    assert red.shape == (3 * 4, 5) and meta["depth"] == 3
    np.testing.assert_array_equal(red.reshape(3, 4, 5), glass.decoded[..., 0])


def test_every_3d_file_reads_back_and_verifies(glass, tmp_path):
    for suffix in (".ktx2", ".dds", ".exr", ".png", ".h"):
        path = glass.save(tmp_path / f"g{suffix}")
        values, meta = lut.read(path)
        assert values.shape == glass.decoded.shape, suffix
        assert meta["content_hash"] == glass.content_hash
        assert "--layers eta_z:ends:3" in meta["command"]
        result = lut.verify(path, interp_limit=4)
        assert result.ok and result.hash_ok, (suffix, result)


def test_c_header_trilinear_lookup_is_the_python_lookup(glass, tmp_path):
    glass.save(tmp_path / "g.h")
    pts = [(0.3, 0.04, 1.5), (0.77, 0.5, 1.1), (0.45, 0.2, 3.0), (0.01, 0.9, 20.0), (1.0, 0.0, 1.0)]
    calls = "\n".join(
        f'    cycles_ggx_glass_E_lookup({m}f, {a}f, {e}f, o); printf("%.9g %.9g\\n", o[0], o[1]);'
        for m, a, e in pts
    )
    out = compile_and_run(
        tmp_path,
        '#include <stdio.h>\n#include "g.h"\nint main(void) {\n    float o[2];\n'
        + calls
        + "\n    return 0;\n}\n",
    )
    got = np.array([[float(v) for v in line.split()] for line in out.splitlines()])
    mu, alpha, eta = np.array(pts, dtype=np.float64).T
    np.testing.assert_allclose(got, glass.lookup(mu, alpha, eta), atol=2e-6)


#: What the shaders return: the 3-D lookup and two of the texture coordinates.
CALLS = "cycles_ggx_glass_E_lookup(0.3, 0.2, 1.5), cycles_ggx_glass_E_uvw(0.3, 0.2, 1.5).xy"


@pytest.mark.parametrize("suffix", [".wgsl", ".glsl"])
def test_3d_shader_source_validates_with_naga(glass, tmp_path, suffix):
    validate_with_naga(tmp_path, glass.save(tmp_path / f"g{suffix}"), CALLS)


@pytest.mark.parametrize("suffix", [".hlsl", ".glsl"])
def test_3d_shader_source_compiles_with_glslang(glass, tmp_path, suffix):
    compile_with_glslang(tmp_path, glass.save(tmp_path / f"g{suffix}"), CALLS)


def test_3d_shader_lookups_are_the_c_lookup_written_in_each_language(glass, tmp_path):
    """The GLSL, HLSL and WGSL lookups blend the same eight texels with the same weights as
    the C header's (compiled and run above): their statements, turned into C, compute the
    Python lookup."""
    pts = [(0.3, 0.04, 1.5), (0.77, 0.5, 1.1), (0.01, 0.9, 20.0)]
    for suffix in (".glsl", ".hlsl", ".wgsl"):
        text = glass.save(tmp_path / f"g{suffix}").read_text()
        body = text[text.index("_lookup(") :]
        body = body[body.index("{") + 1 : body.index("return")]
        # to C: declarations as float / int, WGSL's u32 casts and suffixes dropped
        c = re.sub(
            r"\blet (\w+) = min\(u32\(([^)]*)\), (\d+)u\);",
            r"int \1 = (int)(\2); if (\1 > \3) \1 = \3;",
            body,
        )
        c = re.sub(r"\b(let|var)\b", "float", c)
        c = re.sub(r"(\d)u\b", r"\1", c).replace("f32(", "(float)(")
        c = re.sub(r"\b(int|float)\((\w+)\)", r"(\1)(\2)", c)  # GLSL's casts
        c = c.replace("sqrt(", "sqrtf(").replace("abs(", "fabsf(")
        c = c.replace("max(", "fmaxf(").replace("min(", "fminf(")
        data = text[text.index("BEGIN DATA") : text.index("END DATA")]
        numbers = re.findall(r"[-+]?\d+\.\d*(?:[eE][-+]?\d+)?", re.sub(r"//.*", "", data))
        program = (
            "#include <math.h>\n#include <stdio.h>\n"
            f"static const float cycles_ggx_glass_E_data[] = {{{', '.join(n + 'f' for n in numbers)}}};\n"
            "static void lookup(float mu, float roughness, float eta) {\n"
            + c
            + '    printf("%.9g %.9g\\n", r0, r1);\n}\nint main(void) {\n'
            + "".join(f"    lookup({m}f, {a}f, {e}f);\n" for m, a, e in pts)
            + "    return 0;\n}\n"
        )
        out = compile_and_run(tmp_path, program)
        got = np.array([[float(v) for v in line.split()] for line in out.splitlines()])
        mu, alpha, eta = np.array(pts, dtype=np.float64).T
        np.testing.assert_allclose(got, glass.lookup(mu, alpha, eta), atol=2e-6, err_msg=suffix)


# ------------------------------------------------------------------------------- errors


def test_spec_errors_name_the_layers_and_the_fix():
    s = lut.preset("cycles_glass", samples=16)
    with pytest.raises(
        ValueError, match=r"layers: the energy table of ggx_dielectric is a 3-D texture over eta"
    ):
        dataclasses.replace(s, layers=None)
    with pytest.raises(ValueError, match="layers: only a transmitting model's energy table"):
        dataclasses.replace(lut.preset("cycles"), layers=s.layers)
    with pytest.raises(
        ValueError, match=r"layers: this table's third axis is eta \(eta, eta_z, eta_z_inside\)"
    ):
        dataclasses.replace(s, layers=lut.Axis("mu", 4, "centres"))
    # z = 1 is an infinite index: the last texel needs a ceiling below 1
    with pytest.raises(ValueError, match=r"layers: eta = inf at the last texel .*give a ceiling"):
        dataclasses.replace(s, layers=lut.Axis("eta_z", 4, "ends", floor=1e-4))
    with pytest.raises(ValueError, match="axis ceiling: expected floor < ceiling <= hi"):
        lut.Axis("eta_z", 4, "ends", floor=0.5, ceiling=0.2)
    with pytest.raises(ValueError, match="axis range: eta_z is at most 1"):
        lut.Axis("eta_z", 4, "ends", 0.0, 2.0)
    with pytest.raises(ValueError, match="meet_error: handles 2-D tables"):
        lut.meet_error(s, 1e-3)


def test_2d_recipes_have_no_layers_or_ceiling_so_their_hashes_are_unchanged():
    for name, p in lut.PRESETS.items():
        recipe = p.spec.recipe()
        assert ("layers" in recipe) == (p.spec.layers is not None), name
        for axis in ("columns", "rows"):
            assert "ceiling" not in recipe[axis], name
    assert lut.parse_axis("eta_z:ends:16:0:1:0.0001:0.99") == lut.preset("cycles_glass").layers


def test_cli_builds_a_3d_table_and_refuses_a_shader_array_too_large(tmp_path):
    args = [
        "--preset",
        "cycles_glass",
        "--samples",
        "16",
        "--columns",
        "perceptual:ends:3:0:1:0.00031623",
        "--rows",
        "mu:ends:3:0:1:0.0001",
        "--layers",
        "eta_z:ends:2:0:1:0.0001:0.99",
        "--interp-limit",
        "2",
    ]
    out = json.loads(run_cli("lut", *args, "-o", "g.ktx2", "--json", cwd=tmp_path).stdout)
    assert (out["width"], out["height"], out["depth"]) == (3, 3, 2)
    run_cli("lut", *args, "-o", "g.wgsl", "-q", cwd=tmp_path)
    assert (
        "fn cycles_ggx_glass_E_lookup(mu: f32, roughness: f32, eta: f32)"
        in (tmp_path / "g.wgsl").read_text()
    )
    # 33 x 32 x 32 texels of 2 channels: more than a constant array may hold, refused
    # before any work (counting the layers)
    big = ["--preset", "ue5_glass", "--columns", "mu:centres:33", "-o", "big.glsl"]
    err = run_cli("lut", *big, cwd=tmp_path, code=2).stderr
    assert "67584 values is more than 65536" in err and "Traceback" not in err
    assert not (tmp_path / "big.glsl").exists()
    for option in (["--fit", "4"], ["--max-error", "0.01"]):
        err = run_cli("lut", *args, *option, "-o", "f.h", cwd=tmp_path, code=2).stderr
        assert f"{option[0]}: takes 2-D tables" in err and "cell" not in err  # before any work
    listed = run_cli("lut", "--list", cwd=tmp_path).stdout
    for name in ("cycles_glass", "cycles_glass_inv", "ue5_glass"):
        assert f"{name}:" in listed


# ----------------------------------------------------------------- generalized Schlick


@pytest.fixture(scope="module")
def blend():
    return lut.build(small("cycles_gen_schlick", n=(4, 5, 3), samples=256), interp_limit=4)


def test_cycles_gen_schlick_preset_is_cycles_grid():
    s = lut.preset("cycles_gen_schlick")
    assert s.shape == (16, 16, 16) and s.channel_names == ("s",) and s.format == "R32_SFLOAT"
    # exponent = 5 (1 - z)/z, z = clamp(k/15, 1e-4, 0.99); looked up at z = 1/(0.2 e + 1)
    z = np.clip(np.arange(16) / 15, 1e-4, 0.99)
    exponent = s.layers.physical(s.layers.positions())
    np.testing.assert_allclose(exponent, 5 * (1 - z) / z, rtol=1e-12)
    np.testing.assert_allclose(1 / (0.2 * exponent + 1), z, rtol=1e-12)
    np.testing.assert_allclose(s.layers.quantity_of(exponent), z, rtol=1e-12)
    # Schlick's own exponent, 5, sits at z = 0.5, between slices 7 and 8
    assert s.layers.quantity_of(5.0) == 0.5


def test_blend_is_the_ratio_of_the_two_albedos_in_cycles_order(blend):
    s = blend.spec
    r = s.columns.physical(s.columns.positions())
    mu = s.rows.physical(s.rows.positions())
    exponent = s.layers.physical(s.layers.positions())
    axes = {"mu": mu, "alpha": r, "exponent": exponent}
    common = {"samples": 256, "seed": 0, "kd": 0.0}
    x = brdf_rs.albedo_table(s.model, axes, f0=0.0, f90=1.0, **common).value[..., 0]
    e = brdf_rs.albedo_table(s.model, axes, f0=1.0, f90=1.0, **common).value[..., 0]
    want = np.where(e > 0, x / np.where(e > 0, e, 1), 0.0)
    assert blend.image.shape == (3, 5, 4, 1)  # slices of exponent, rows mu, columns r
    assert blend.image[..., 0].tobytes() == np.ascontiguousarray(want.transpose(2, 0, 1)).tobytes()


def test_blend_recovers_the_albedo_at_any_f0_and_f90(blend):
    """E(F0, F90) = E * mix(F0, F90, s): checked against the albedo integrated at those
    F0 and F90 directly, off the table's own samples."""
    s = blend.spec
    spec = dataclasses.replace(s, channels=("s", "E"), format="R32G32_SFLOAT")
    t = lut.build(spec, interp_limit=2)
    mu = s.rows.physical(s.rows.positions())[2]
    alpha = s.columns.physical(s.columns.positions())[2]
    exponent = s.layers.physical(s.layers.positions())[1]
    f0, f90 = 0.04, 0.8
    direct = brdf_rs.albedo(
        s.model,
        mu,
        alpha=alpha,
        exponent=exponent,
        f0=f0,
        f90=f90,
        kd=0,
        samples=1 << 14,
        seed=4,
    )
    blend_s, e = t.image[1, 2, 2]
    se_s, se_e = t.stderr[1, 2, 2]
    from_table = e * (f0 + (f90 - f0) * blend_s)
    se_table = math.hypot((f0 + (f90 - f0) * blend_s) * se_e, e * (f90 - f0) * se_s)
    assert abs(from_table - direct.value[0]) <= 4 * math.hypot(se_table, direct.stderr[0])
    # not vacuous: the blend matters here (F0 alone, s = 0, is far off)
    assert abs(e * f0 - direct.value[0]) > 10 * math.hypot(se_table, direct.stderr[0])


def test_gen_schlick_c_header_takes_the_exponent(blend, tmp_path):
    blend.save(tmp_path / "s.h")
    text = (tmp_path / "s.h").read_text()
    assert "cycles_ggx_gen_schlick_s_lookup(float mu, float roughness, float exponent," in text
    pts = [(0.3, 0.04, 5.0), (0.8, 0.5, 1.0), (0.05, 0.2, 40.0)]
    calls = "\n".join(
        f'    cycles_ggx_gen_schlick_s_lookup({m}f, {a}f, {e}f, o); printf("%.9g\\n", o[0]);'
        for m, a, e in pts
    )
    out = compile_and_run(
        tmp_path,
        '#include <stdio.h>\n#include "s.h"\nint main(void) {\n    float o[1];\n'
        + calls
        + "\n    return 0;\n}\n",
    )
    got = np.array([float(line) for line in out.splitlines()])
    mu, alpha, exponent = np.array(pts).T
    np.testing.assert_allclose(got, blend.lookup(mu, alpha, exponent)[:, 0], atol=2e-6)
    calls = "cycles_ggx_gen_schlick_s_lookup(0.3, 0.2, 5.0), cycles_ggx_gen_schlick_s_uvw(0.3, 0.2, 5.0)"
    validate_with_naga(tmp_path, blend.save(tmp_path / "s.glsl"), calls)


def test_gen_schlick_spec_errors():
    s = lut.preset("cycles_gen_schlick", samples=16)
    with pytest.raises(ValueError, match="model: 'ggx' has no gen_schlick table; use ggx_gen_sc"):
        dataclasses.replace(s, model="ggx")
    with pytest.raises(ValueError, match=r"layers: the gen_schlick table of ggx_gen_schlick is"):
        dataclasses.replace(s, layers=None)
    with pytest.raises(ValueError, match=r"third axis is exponent \(exponent, exponent_z\)"):
        dataclasses.replace(s, layers=lut.preset("cycles_glass").layers)
    # z = 0 is an infinite exponent: the first texel needs a floor
    with pytest.raises(ValueError, match=r"layers: exponent = inf at the first texel"):
        dataclasses.replace(s, layers=lut.Axis("exponent_z", 4, "ends", ceiling=0.99))
