"""Engine LUTs (brdf_rs.lut): layouts against the engines' conventions as read from their
sources, values against the library's own integrals, files read back by independent
readers (OpenEXR, pypng and Pillow) or, where no independent reader of the format exists
on PyPI (KTX2 and DDS with float and 16-bit formats: Pillow and OpenImageIO read neither),
their headers checked field by field against the published specifications; the C header
compiled and run; the error budget checked against fresh integrals at off-grid points."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import re
import shutil
import struct
import subprocess
from pathlib import Path

import brdf_rs
import numpy as np
import pytest
from brdf_rs import lut
from conftest import run_cli

SMALL = {"samples": 256}


def small(preset: str, n: int = 8, **changes):
    spec = lut.preset(preset, **SMALL, **changes)
    cols = lut.Axis(spec.columns.quantity, n, spec.columns.placement, floor=spec.columns.floor)
    rows = lut.Axis(spec.rows.quantity, n, spec.rows.placement, floor=spec.rows.floor)
    return dataclasses.replace(spec, columns=cols, rows=rows)


@pytest.fixture(scope="module")
def filament():
    return lut.build(small("filament"), interp_limit=8)


def ggx_b_and_a_plus_b(mu, alpha, samples: int, seed: int):
    """GGX's split-sum channels (B, A + B) at each ``(mu, alpha)``, integrated apart from
    any table (``brdf_rs.albedo`` at F0 = 0 and 1), and their standard errors."""
    one = brdf_rs.albedo("ggx", mu, alpha=alpha, kd=0, ks=1, samples=samples, seed=seed)
    zero = brdf_rs.albedo("ggx", mu, alpha=alpha, kd=0, ks=0, samples=samples, seed=seed)
    value = np.stack([zero.value[:, 0], one.value[:, 0]], -1)
    return value, np.stack([zero.stderr[:, 0], one.stderr[:, 0]], -1)


def compile_and_run(tmp_path, source: str) -> str:
    """Compiles the C99 ``source`` in ``tmp_path`` (warnings as errors), runs it and
    returns its stdout; skips the test where there is no C compiler."""
    cc = shutil.which("cc")
    if cc is None:
        pytest.skip("no C compiler")
    (tmp_path / "m.c").write_text(source)
    subprocess.run(
        [cc, "-std=c99", "-Wall", "-Werror", "-o", str(tmp_path / "m"), "m.c", "-lm"],
        check=True,
        cwd=tmp_path,
    )
    return subprocess.run([str(tmp_path / "m")], check=True, capture_output=True, text=True).stdout


def c_lookups(tmp_path, header: str, function: str, pts) -> np.ndarray:
    """Calls ``function(mu, roughness, o)`` of the C ``header`` in ``tmp_path`` at each
    ``(mu, roughness)`` of ``pts``; returns the two outputs per point."""
    calls = "\n".join(
        f'    {function}({m}f, {a}f, o); printf("%.9g %.9g\\n", o[0], o[1]);' for m, a in pts
    )
    out = compile_and_run(
        tmp_path,
        f'#include <stdio.h>\n#include "{header}"\nint main(void) {{\n    float o[2];\n'
        + calls
        + "\n    return 0;\n}\n",
    )
    return np.array([[float(v) for v in line.split()] for line in out.splitlines()])


# ------------------------------------------------------------------------------ layouts


def test_presets_reproduce_the_engines_layouts():
    f = lut.preset("filament")
    # Filament's cmgen: NoV = (x + 0.5) / width, linear roughness = coord^2, 128 x 128 RG16F.
    assert (f.columns.size, f.rows.size, f.format) == (128, 128, "R16G16_SFLOAT")
    np.testing.assert_allclose(f.columns.positions(), (np.arange(128) + 0.5) / 128)
    np.testing.assert_allclose(
        f.rows.physical(f.rows.positions()), ((np.arange(128) + 0.5) / 128) ** 2
    )
    assert f.channel_names == ("B", "A+B")
    c = lut.preset("cycles")
    # Cycles: data[y * nx + x], x = roughness i / 31, y = mu j / 31.
    assert c.columns.quantity == "perceptual" and c.rows.quantity == "mu"
    np.testing.assert_allclose(c.columns.positions(), np.arange(32) / 31)
    np.testing.assert_allclose(c.rows.physical(c.rows.positions())[1:], np.arange(1, 32) / 31)
    assert c.rows.physical(np.array(0.0)) == 1e-4
    assert lut.preset("ue5").format == "R16G16_UNORM"
    assert lut.preset("gltf").columns.size == 1024


def test_dfg_channels_are_the_split_sum_integrals_in_image_order(filament):
    spec = filament.spec
    mu = (np.arange(8) + 0.5) / 8
    rough = ((np.arange(8) + 0.5) / 8) ** 2
    # dfg_table keys cell (mu i, roughness j) by i * n + j: the same streams, the same bits.
    ids = np.arange(64, dtype=np.uint64).reshape(8, 8).T  # [j, i]
    common = {"alpha": rough[:, None], "kd": 0, "samples": 256, "cell_ids": ids}
    one = brdf_rs.albedo("ggx", mu[None, :], ks=1, **common)
    zero = brdf_rs.albedo("ggx", mu[None, :], ks=0, **common)
    # rows = roughness, columns = mu: channel B = I(F0 = 0), A + B = I(F0 = 1).
    assert spec.rows.role == "roughness"
    np.testing.assert_allclose(filament.image[..., 0], zero.value[..., 0], atol=1e-15)
    np.testing.assert_allclose(filament.image[..., 1], one.value[..., 0], atol=1e-15)


def test_ue5_table_is_unreals_layout_r_the_albedo_g_the_schlick_share():
    # Unreal's BuildEnergyTableCS: texel (x, y) of N at NoV = (x + 0.5)/N and Roughness =
    # (y + 0.5)/N, alpha = max(Roughness, 0.01)^2; R = E with F = 1, G = E weighted by
    # (1 - v.h)^5; GGXEnergyLookup samples float2(NoV, Roughness): x = n.v, y = roughness.
    u = lut.preset("ue5")
    assert (u.columns.size, u.rows.size, u.format) == (32, 32, "R16G16_UNORM")
    assert (u.columns.quantity, u.rows.quantity) == ("mu", "perceptual")
    assert u.channel_names == ("A+B", "B") and lut.PRESETS["ue5"].container == ".dds"
    centres = (np.arange(32) + 0.5) / 32
    np.testing.assert_allclose(u.columns.physical(u.columns.positions()), centres)
    np.testing.assert_allclose(u.rows.physical(u.rows.positions()), centres**2)
    # the builder's floor: r = 0.01, which a 128-texel axis's first texel is below
    fine = dataclasses.replace(u.rows, size=128)
    assert fine.physical(fine.positions())[0] == pytest.approx(1e-4)

    t = lut.build(small("ue5", 6), interp_limit=4)
    mu = (np.arange(6) + 0.5) / 6
    alpha = ((np.arange(6) + 0.5) / 6) ** 2
    ids = np.arange(36, dtype=np.uint64).reshape(6, 6).T  # [roughness j, mu i]
    common = {"alpha": alpha[:, None], "kd": 0, "samples": 256, "cell_ids": ids}
    one = brdf_rs.albedo("ggx", mu[None, :], ks=1, **common)  # F = 1: E = A + B
    zero = brdf_rs.albedo("ggx", mu[None, :], ks=0, **common)  # F = (1 - v.h)^5: B
    assert t.spec.rows.role == "roughness"  # image rows = roughness, columns = n.v
    np.testing.assert_allclose(t.image[..., 0], one.value[..., 0], atol=1e-15)
    np.testing.assert_allclose(t.image[..., 1], zero.value[..., 0], atol=1e-15)
    # and against the split sum: R = A + B, G = B, so F0 * R + (1 - F0) * G = F0 * A + B
    dfg = brdf_rs.dfg_table("ggx", mu, alpha, samples=256)
    a, b = np.swapaxes(dfg.value, 0, 1)[..., 0], np.swapaxes(dfg.value, 0, 1)[..., 1]
    np.testing.assert_allclose(t.image[..., 0], a + b, atol=1e-12)
    np.testing.assert_allclose(t.image[..., 1], b, atol=1e-12)


def test_published_e_avg_values_place_their_last_row_at_the_end_or_the_centre():
    """Cycles' last ggx_Eavg entry (0.409137) and Enterprise PBR's (0.42276) disagree by 3%.
    Their grids explain it: GGX's E_avg at r = 1 (alpha = 1, Cycles' ends) is Cycles'
    value, and at the last texel centre of 32, r = 31.5/32 (the enterprise preset's
    layout), Enterprise's; each value excludes the other placement."""
    r = np.array([1.0, 31.5 / 32])
    e = brdf_rs.energy_compensation_table("ggx", [0.5], r**2)
    at_end, at_centre = e.e_avg
    assert abs(at_end - 0.409137) < 2e-5  # 6 printed decimals and Cycles' noise
    assert abs(at_centre - 0.42276) < 5e-4  # 5 digits, Monte Carlo of unknown size
    assert abs(at_end - 0.42276) > 0.01 and abs(at_centre - 0.409137) > 0.01
    spec = lut.preset("enterprise")
    last = spec.rows.physical(spec.rows.positions()[-1:])
    assert spec.rows.quantity == "perceptual" and last == pytest.approx((31.5 / 32) ** 2)


def test_cycles_energy_table_rows_are_mu_columns_roughness():
    t = lut.build(small("cycles", 6), interp_limit=4)
    r = np.maximum(np.arange(6) / 5, 3.1623e-4)
    mu = np.maximum(np.arange(6) / 5, 1e-4)
    e = brdf_rs.energy_compensation_table("ggx", mu, r**2, samples=256, tol=None)
    np.testing.assert_allclose(t.image[..., 0], e.e, atol=1e-12)  # rows mu, columns r
    np.testing.assert_allclose(t.image[..., 1], np.broadcast_to(e.e_avg, (6, 6)), atol=1e-12)


# ------------------------------------------------------------------------------- budget


def test_quantization_budget_is_exact_against_an_independent_half_rounding(filament):
    halves = np.array(
        [struct.unpack("<e", struct.pack("<e", v))[0] for v in filament.image.reshape(-1)]
    ).reshape(filament.image.shape)
    np.testing.assert_array_equal(filament.decoded, halves)
    err = np.abs(halves - filament.image).reshape(-1, 2)
    assert filament.budget.quant_worst == err.max(axis=0).tolist()
    np.testing.assert_allclose(filament.budget.quant_rms, np.sqrt((err**2).mean(axis=0)))


def test_unorm_quantization_is_round_to_65535ths():
    t = lut.build(small("ue5", 4), interp_limit=4)
    expected = np.round(np.clip(t.image, 0, 1) * 65535) / 65535
    np.testing.assert_array_equal(t.decoded, expected)


def test_lookup_off_grid_is_within_the_budget_of_fresh_integrals():
    spec = lut.LutSpec(
        "dfg",
        "ggx",
        lut.Axis("mu", 16),
        lut.Axis("perceptual", 16),
        "R16G16_SFLOAT",
        samples=4096,
    )
    t = lut.build(spec, interp_limit=16)
    rng = np.random.default_rng(3)
    # between the first and last texels (1/32 and 31/32), off the grid
    mu = rng.uniform(0.05, 0.95, 40)
    r = rng.uniform(0.1, 0.95, 40)
    one = brdf_rs.albedo("ggx", mu, alpha=r**2, kd=0, ks=1, samples=1 << 14, seed=9)
    zero = brdf_rs.albedo("ggx", mu, alpha=r**2, kd=0, ks=0, samples=1 << 14, seed=9)
    exact = np.stack([one.value[:, 0] - zero.value[:, 0], zero.value[:, 0]], -1)
    got = t.lookup(mu, r**2)
    slack = 3 * np.stack([np.hypot(one.stderr[:, 0], zero.stderr[:, 0]), zero.stderr[:, 0]], -1)
    b = t.budget
    # The interior's own budget, not the total (which the clamped grazing margin dominates):
    # a lookup off by a fraction of a texel exceeds it.
    interior = np.asarray(b.quant_worst) + np.asarray(b.interp_worst_interior)
    interior += 3 * np.asarray(b.interp_ref_stderr)
    assert np.all(interior < 0.5 * np.asarray(b.total))
    assert np.all(np.abs(got - exact) <= interior + slack)
    assert max(b.interp_worst) > 0  # measured, not assumed away
    # the total counts the reference integrals' noise too, and says it is per point
    parts = [np.asarray(v) for v in (b.quant_worst, b.interp_worst, b.interp_ref_stderr)]
    expected = parts[0] + parts[1] + 3 * parts[2] + 3 * np.asarray(b.mc_max_stderr)
    np.testing.assert_allclose(b.total, expected, rtol=1e-15)
    assert "per point" in b.confidence and "not a bound over the whole table" in b.confidence


@pytest.mark.parametrize(("quantity", "floor"), [("mu", "0.0001"), ("sqrt_mu", "0.01")])
def test_a_mu_axis_with_a_texel_at_mu_zero_needs_a_floor(quantity, floor):
    with pytest.raises(ValueError, match=f"axis floor: {quantity} with texels at the range ends"):
        lut.Axis(quantity, 8, "ends")
    err = run_cli("lut", "--preset", "cycles", "--rows", f"{quantity}:ends:8", code=2).stderr
    assert f"--rows: axis floor: {quantity} with texels" in err
    assert f"e.g. {quantity}:ends:8:0:1.0:{floor}" in err
    fixed = lut.parse_axis(f"{quantity}:ends:8:0:1.0:{floor}")
    assert fixed.physical(fixed.positions())[0] == pytest.approx(1e-4)
    lut.Axis(quantity, 8, "ends", 0.1)  # a range above mu = 0 needs none
    lut.Axis(quantity, 8, "centres")  # nor do texel centres


@pytest.mark.parametrize("quantity", ["mu", "sqrt_mu"])
def test_the_grazing_end_is_checked_at_mu_1e_4_on_either_mu_quantity(quantity):
    spec = lut.LutSpec("dfg", "ggx", lut.Axis(quantity, 4), lut.Axis("perceptual", 4), samples=16)
    t = lut.build(spec, interp_limit=4)
    assert t.checks is not None
    mu = spec.mu_axis.physical(t.checks.mu_q)
    assert mu.min() == pytest.approx(1e-4, rel=1e-12)


def test_bilinear_matches_a_hand_interpolation_between_four_texels():
    img = np.arange(12, dtype=float).reshape(3, 4, 1)
    cols, rows = lut.Axis("mu", 4), lut.Axis("perceptual", 3, "ends")
    # column texel coordinate 1.25 -> mu = (1.25 + 0.5) / 4; row 0.5 -> q = 0.25
    v = lut.bilinear(img, cols, rows, (1.25 + 0.5) / 4, 0.25)
    expected = 0.5 * (img[0, 1] * 0.75 + img[0, 2] * 0.25) + 0.5 * (
        img[1, 1] * 0.75 + img[1, 2] * 0.25
    )
    np.testing.assert_allclose(v, expected)
    np.testing.assert_allclose(lut.bilinear(img, cols, rows, 0.0, 0.0), img[0, 0])  # clamped


# -------------------------------------------------------------------------------- files


def test_exr_read_by_openexr_has_named_half_channels_and_the_meta(filament, tmp_path):
    OpenEXR = pytest.importorskip("OpenEXR")
    path = filament.save(tmp_path / "dfg.exr")
    with OpenEXR.File(str(path)) as f:
        chans = f.channels()
        # red and green, as a reader shows them: not A (alpha) and B (blue)
        assert set(chans) == {"R", "G"}
        for k, name in enumerate(("R", "G")):
            px = chans[name].pixels
            assert px.dtype == np.float16 and px.shape == (8, 8)
            np.testing.assert_array_equal(px.astype(float), filament.decoded[..., k])
        assert f.header()["brdf-rs:channels"] == "R = B, G = A+B"
        meta = json.loads(f.header()["brdf-rs:lut"])
    assert meta["content_hash"] == filament.content_hash
    assert "texel centres" in meta["columns"]
    values, _ = lut.read(path)
    np.testing.assert_array_equal(values, filament.decoded)


def test_ktx2_header_fields_follow_the_specification(filament, tmp_path):
    raw = filament.save(tmp_path / "dfg.ktx2").read_bytes()
    assert raw[:12] == bytes(
        [0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A]
    )
    fields = struct.unpack_from("<9I", raw, 12)
    # vkFormat VK_FORMAT_R16G16_SFLOAT = 83, typeSize 2, 8 x 8, depth 0, layers 0,
    # faces 1, levels 1, no supercompression.
    assert fields == (83, 2, 8, 8, 0, 0, 1, 1, 0)
    dfd_off, dfd_len, kvd_off, kvd_len, sgd_off, sgd_len = struct.unpack_from("<4I2Q", raw, 48)
    assert (sgd_off, sgd_len) == (0, 0) and dfd_off == 80 + 24
    level_off, level_len, level_unc = struct.unpack_from("<3Q", raw, 80)
    assert level_off % 4 == 0 and level_len == level_unc == 8 * 8 * 2 * 2
    assert level_off + level_len == len(raw)
    # DFD: total size, then the basic block (KDF version 2), RGBSDA, BT.709, linear.
    (total,) = struct.unpack_from("<I", raw, dfd_off)
    assert total == dfd_len == 4 + 24 + 2 * 16
    _, version, block_size = struct.unpack_from("<IHH", raw, dfd_off + 4)
    assert (version, block_size) == (2, 24 + 32)
    assert tuple(raw[dfd_off + 12 : dfd_off + 16]) == (1, 1, 1, 0)
    assert raw[dfd_off + 20] == 4  # bytesPlane0
    for ch in range(2):
        off = dfd_off + 28 + 16 * ch
        bit_offset, bit_length, channel_type = struct.unpack_from("<HBB", raw, off)
        assert (bit_offset, bit_length, channel_type) == (16 * ch, 15, ch | 0x80 | 0x40)
    keys = []
    pos = kvd_off
    while pos < kvd_off + kvd_len:
        (n,) = struct.unpack_from("<I", raw, pos)
        keys.append(raw[pos + 4 : pos + 4 + n].split(b"\0")[0])
        pos += 4 + n + (-n) % 4
    assert keys == sorted(keys) and b"KTXorientation" in keys and b"brdf-rs:lut" in keys
    texels = np.frombuffer(raw, "<f2", 128, level_off).reshape(8, 8, 2)
    np.testing.assert_array_equal(texels.astype(float), filament.decoded)


def test_dds_header_fields_follow_the_specification(tmp_path):
    t = lut.build(small("ue5", 4), interp_limit=4)
    raw = t.save(tmp_path / "e.dds").read_bytes()
    assert raw[:4] == b"DDS "
    size, flags, height, width, pitch = struct.unpack_from("<5I", raw, 4)
    assert (size, height, width, pitch) == (124, 4, 4, 4 * 4)
    assert flags & 0x100F == 0x100F  # CAPS | HEIGHT | WIDTH | PITCH | PIXELFORMAT
    pf_size, pf_flags, fourcc = struct.unpack_from("<II4s", raw, 76)
    assert (pf_size, pf_flags, fourcc) == (32, 0x4, b"DX10")
    (caps,) = struct.unpack_from("<I", raw, 108)
    assert caps == 0x1000
    # DXGI_FORMAT_R16G16_UNORM = 35, D3D10_RESOURCE_DIMENSION_TEXTURE2D = 3, array size 1.
    assert struct.unpack_from("<5I", raw, 128) == (35, 3, 0, 1, 0)
    texels = np.frombuffer(raw, "<u2", 32, 148).reshape(4, 4, 2)
    np.testing.assert_array_equal(texels / 65535, t.decoded)
    assert raw[148 + 64 :].startswith(b"brdf-rs:lut\0")


def test_png_offset_and_scale_recover_the_texels(filament, tmp_path):
    png = pytest.importorskip("png")
    PIL = pytest.importorskip("PIL.Image")
    path = filament.save(tmp_path / "dfg.png")
    width, height, rows, info = png.Reader(filename=str(path)).asDirect()
    assert info["bitdepth"] == 16 and info["planes"] == 3
    pixels = np.array([list(r) for r in rows], dtype=float).reshape(height, width, 3)
    with PIL.open(path) as im:
        meta = json.loads(im.text["brdf-rs:lut"])
    p = meta["png"]
    values = np.asarray(p["offset"]) + np.asarray(p["scale"]) * pixels[..., :2] / 65535
    assert np.all(np.abs(values - filament.decoded) <= np.asarray(p["step"]) / 2 + 1e-12)
    assert np.all(pixels[..., 2] == 0)


def test_c_header_compiles_and_its_lookup_is_the_python_lookup(filament, tmp_path):
    filament.save(tmp_path / "dfg.h")
    # the last three in the clamped margins, the others between the first and last texels
    pts = [
        (0.3, 0.04),
        (0.77, 0.5),
        (0.45, 0.2),
        (0.6, 0.7),
        (0.01, 0.001),
        (0.999, 0.9),
        (0.5, 1.0),
    ]
    got = c_lookups(tmp_path, "dfg.h", "filament_dfg_lookup", pts)
    mu, alpha = np.array(pts).T
    np.testing.assert_allclose(got, filament.lookup(mu, alpha), atol=2e-6)
    # and against the integrals themselves, within the budget the file states
    exact, se = ggx_b_and_a_plus_b(mu, alpha, 1 << 14, 5)
    slack = 3 * se
    b = filament.budget
    assert np.all(np.abs(got - exact) <= np.asarray(b.total) + slack)
    # between the first and last texels, the interior's budget (well under the total,
    # which the grazing margin dominates): a lookup mapping mu or roughness wrongly fails
    interior = np.asarray(b.quant_worst) + np.asarray(b.interp_worst_interior)
    interior += 3 * np.asarray(b.interp_ref_stderr) + 2e-6  # float32 arithmetic
    assert np.all(interior < 0.5 * np.asarray(b.total))
    assert np.all(np.abs(got - exact)[:4] <= interior + slack[:4])


def test_whole_number_axis_bounds_write_the_same_files_as_floats_and_compile(tmp_path):
    def spec(lo, hi, floor):
        return lut.LutSpec(
            "dfg",
            "ggx",
            lut.Axis("mu", 4, "centres", lo, hi),
            lut.Axis("perceptual", 4, "centres", lo, hi, floor),
            "R32G32_SFLOAT",
            samples=16,
            name="w",
        )

    whole, real = spec(0, 1, 0), spec(0.0, 1.0, 0.0)
    assert whole == real and whole.content_hash() == real.content_hash()
    assert isinstance(whole.columns.lo, float) and isinstance(whole.rows.hi, float)
    a, b = lut.build(spec(0, 1, 0), interp_limit=4), lut.build(real, interp_limit=4)
    (tmp_path / "f").mkdir()
    for suffix in (".h", ".glsl", ".hlsl", ".wgsl"):
        written = a.save(tmp_path / f"i{suffix}").read_bytes()
        assert written == b.save(tmp_path / "f" / f"i{suffix}").read_bytes()
    lut.fit(a, 2).save(tmp_path / "fit.h")
    assert (tmp_path / "fit.h").read_text() == lut.fit(b, 2).save(
        tmp_path / "f" / "fit.h"
    ).read_text()
    code = (tmp_path / "i.h").read_text()
    assert "(mu_q - 0.0f) / 1.0f" in code and " 0f" not in code and "(0f" not in code
    for bad, field in (("0", "lo"), (math.nan, "hi"), (None, "floor")):
        args = {"lo": 0.0, "hi": 1.0, "floor": 0.0, field: bad}
        with pytest.raises(ValueError, match=f"axis {field}: expected a"):
            lut.Axis("mu", 4, "centres", **args)
    out = compile_and_run(
        tmp_path,
        '#include <stdio.h>\n#include "i.h"\n#include "fit.h"\nint main(void) {\n'
        "    float o[2], p[2];\n    w_lookup(0.5f, 0.25f, o);\n    w_fit(0.5f, 0.25f, p);\n"
        '    printf("%.9g %.9g\\n", o[0], p[0]);\n    return 0;\n}\n',
    )
    got = [float(v) for v in out.split()]
    assert got[0] == pytest.approx(float(a.lookup(0.5, 0.25)[0]), abs=2e-6)


@pytest.mark.parametrize("suffix", [".wgsl", ".glsl"])
def test_shader_source_validates_with_naga(filament, tmp_path, suffix):
    path = filament.save(tmp_path / f"dfg{suffix}")
    validate_with_naga(tmp_path, path, "filament_dfg_lookup(0.3, 0.2), filament_dfg_uv(0.3, 0.2)")


@pytest.mark.parametrize("suffix", [".hlsl", ".glsl"])
def test_shader_source_compiles_with_glslang(filament, tmp_path, suffix):
    """The HLSL (glslang's HLSL front end, as for Vulkan: a pixel shader that calls the
    lookup and the texture-coordinate function) and the GLSL compile to SPIR-V, which
    spirv-val validates."""
    path = filament.save(tmp_path / f"dfg{suffix}")
    compile_with_glslang(tmp_path, path, "filament_dfg_lookup(0.3, 0.2), filament_dfg_uv(0.3, 0.2)")


def shader_main(suffix: str, values: str) -> str:
    """A fragment (GLSL) or pixel (HLSL) shader entry point returning ``float4(values)``:
    four floats from the lookups it calls."""
    if suffix == ".hlsl":
        return (
            "float4 main(float4 pos : SV_Position) : SV_Target {\n"
            f"    return float4({values});\n}}\n"
        )
    return f"layout(location = 0) out vec4 o;\nvoid main() {{\n    o = vec4({values});\n}}\n"


def validate_with_naga(tmp_path, path: Path, values: str) -> None:
    """naga validates a WGSL file as it is, a GLSL one in a fragment shader returning
    ``vec4(values)``; skips the test without naga."""
    naga = shutil.which("naga")
    if naga is None:
        pytest.skip("naga (a WGSL/GLSL validator) is not installed")
    if path.suffix == ".wgsl":
        subprocess.run([naga, str(path)], check=True, capture_output=True)
        return
    frag = tmp_path / "main.glsl"
    frag.write_text("#version 450\n" + path.read_text() + shader_main(".glsl", values))
    subprocess.run(
        [naga, "--input-kind", "glsl", "--shader-stage", "frag", str(frag)],
        check=True,
        capture_output=True,
    )


def compile_with_glslang(tmp_path, path: Path, values: str) -> None:
    """glslang compiles a GLSL or HLSL file, in a shader returning ``float4(values)``, to
    SPIR-V, which spirv-val validates where installed; skips the test without glslang."""
    glslang = shutil.which("glslangValidator")
    if glslang is None:
        pytest.skip("glslangValidator (Debian's glslang-tools) is not installed")
    suffix = path.suffix
    head, flags = ("", ["-D", "-e", "main"]) if suffix == ".hlsl" else ("#version 450\n", [])
    shader = tmp_path / f"main{suffix}"
    shader.write_text(head + path.read_text() + shader_main(suffix, values))
    spv = tmp_path / "main.spv"
    result = subprocess.run(
        [glslang, *flags, "-V", "-S", "frag", str(shader), "-o", str(spv)],
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    validator = shutil.which("spirv-val")
    if validator is not None:
        subprocess.run([validator, str(spv)], check=True, capture_output=True)


READER = Path(__file__).resolve().parent / "texture_reader"


@pytest.fixture(scope="module")
def texture_reader():
    """The KTX2/DDS reader built on the ``ktx2`` and ``ddsfile`` crates (tests/
    texture_reader): built with cargo on first use; the tests skip without cargo."""
    cargo = shutil.which("cargo")
    if cargo is None:
        pytest.skip("cargo is not installed (it builds the independent KTX2/DDS reader)")
    built = subprocess.run(
        [cargo, "build", "--release", "--quiet", "--manifest-path", str(READER / "Cargo.toml")],
        capture_output=True,
        text=True,
    )
    assert built.returncode == 0, built.stderr
    return READER / "target" / "release" / "texture_reader"


#: DXGI's names for the formats, as the ddsfile crate spells them.
DXGI_NAMES = {
    "R16_UNORM": "R16_UNorm",
    "R16_SFLOAT": "R16_Float",
    "R32_SFLOAT": "R32_Float",
    "R16G16_UNORM": "R16G16_UNorm",
    "R16G16_SFLOAT": "R16G16_Float",
    "R32G32_SFLOAT": "R32G32_Float",
    "R32G32B32_SFLOAT": "R32G32B32_Float",
}


@pytest.mark.parametrize("fmt", sorted(lut.FORMATS))
@pytest.mark.parametrize("suffix", [".ktx2", ".dds"])
def test_ktx2_and_dds_read_back_with_readers_we_did_not_write(
    texture_reader, tmp_path, fmt, suffix
):
    """Every pixel format in both containers, read by the ``ktx2`` and ``ddsfile`` crates:
    the format they see (by the container's own code), the size, and every texel equal to
    the table's decoded values."""
    if suffix == ".dds" and lut.FORMATS[fmt].dxgi == 0:
        pytest.skip(f"DXGI has no {fmt}")
    channels = lut.FORMATS[fmt].channels
    chosen = ("A", "B", "cloth")[:channels]
    sheen = "charlie_sheen" if channels == 3 else None
    spec = dataclasses.replace(
        small("filament", n=6), kind="dfg", format=fmt, channels=chosen, sheen=sheen
    )
    table = lut.build(spec, interp_limit=4)
    path = table.save(tmp_path / f"t{suffix}")
    result = subprocess.run([str(texture_reader), str(path)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    head, *rows = result.stdout.splitlines()
    name, width, height, n, depth = head.split()
    assert name == (fmt if suffix == ".ktx2" else DXGI_NAMES[fmt]) and depth == "1"
    expected = np.asarray(table.decoded, np.float64).reshape(table.decoded.shape[0], -1)
    assert (int(height), int(width) * int(n)) == expected.shape
    assert int(n) == channels
    got = np.array([[float(v) for v in row.split()] for row in rows])
    np.testing.assert_array_equal(got, expected)


# --------------------------------------------------------------- provenance, verify, CLI


def test_every_file_carries_the_hash_and_reads_back(filament, tmp_path):
    for suffix in (".ktx2", ".dds", ".h", ".hlsl", ".wgsl"):
        values, meta = lut.read(filament.save(tmp_path / f"t{suffix}"))
        assert meta["content_hash"] == filament.content_hash
        assert "brdf-rs lut" in meta["command"]
        np.testing.assert_allclose(values, filament.decoded, atol=1e-9)
    other = lut.build(small("filament", seed=1), interp_limit=4)
    assert other.content_hash != filament.content_hash


def test_verify_passes_a_fresh_file_and_fails_a_changed_texel(tmp_path):
    path = tmp_path / "u.dds"
    r = run_cli(
        "lut",
        "--preset",
        "ue5",
        "--columns",
        "mu:centres:4",
        "--rows",
        "perceptual:centres:4",
        "--samples",
        "64",
        "--interp-limit",
        "4",
        "-o",
        str(path),
        "--json",
    )
    assert json.loads(r.stdout)["output"] == str(path.resolve())
    r = run_cli("lut", "--verify", str(path), "--json")
    assert json.loads(r.stdout)["ok"]
    raw = bytearray(path.read_bytes())
    raw[148] ^= 0xFF  # the first texel's low byte
    path.write_bytes(bytes(raw))
    r = run_cli("lut", "--verify", str(path), "--json", code=1)
    assert not json.loads(r.stdout)["ok"]


def _as_if_written_by(path, version, rehash=True):
    """Rewrites the library version a file records (and its content hash with it, as
    that version would have written them)."""
    from brdf_rs import _png

    _, meta = lut.read(path)
    old = json.dumps(meta, sort_keys=True)
    meta["recipe"]["brdf_rs"] = version
    if rehash:
        canonical = json.dumps(meta["recipe"], sort_keys=True, separators=(",", ":"))
        meta["content_hash"] = hashlib.sha256(canonical.encode()).hexdigest()
        assert meta["content_hash"] == lut.recipe_hash(meta["recipe"])
    if path.suffix == ".png":
        pixels, text = _png.read(path)
        text["brdf-rs:lut"] = json.dumps(meta, sort_keys=True)
        _png.write(path, pixels, text)
    else:
        text = path.read_text()
        assert old in text
        path.write_text(text.replace(old, json.dumps(meta, sort_keys=True)))


@pytest.mark.parametrize("suffix", [".png", ".h"])
def test_verify_a_file_from_another_library_version(tmp_path, suffix):
    pytest.importorskip("png")
    spec = lut.preset("ue5", samples=64)
    spec = dataclasses.replace(
        spec, columns=lut.Axis("mu", 4), rows=lut.Axis("perceptual", 4), format="R32G32_SFLOAT"
    )
    path = lut.build(spec, interp_limit=4).save(tmp_path / f"t{suffix}")
    _as_if_written_by(path, "0.0.1")
    result = lut.verify(path)
    assert result.hash_ok and result.ok
    assert result.versions == ("0.0.1", brdf_rs.__version__)
    if suffix == ".png":  # float32 texels: the PNG's half step is what the tolerance needs
        step = np.asarray(lut.read(path)[1]["png"]["step"]) / 2
        assert np.all(np.asarray(result.tolerance) >= step)
    # a version rewritten without its hash is caught
    _as_if_written_by(path, "0.0.2", rehash=False)
    assert not lut.verify(path).hash_ok


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--preset", "unreal4"], "--preset: unknown 'unreal4'"),
        (["--preset", "ue5", "--format", "RGBA8"], "format: unknown 'RGBA8'"),
        (["--preset", "ue5", "-o", "x.tga"], "-o x.tga: unknown LUT file type '.tga'"),
        (["--preset", "ue5", "-o", "x.exr"], "format: .exr holds half or float"),
        (
            ["--kind", "dfg", "--columns", "mu:centres:1", "--rows", "alpha:ends:4"],
            "--columns: axis size",
        ),
        (["--kind", "dfg", "--model", "ggx", "--columns", "mu:centres:8"], "missing --rows"),
        (
            ["--kind", "dfg", "--columns", "mu:centres:8", "--rows", "alpha:centres:8"],
            "missing --model",
        ),
        (["--preset", "filament", "--channels", "B"], "format: R16G16_SFLOAT holds 2 channel(s)"),
        (
            [
                "--kind",
                "dfg",
                "--model",
                "ggx",
                "--columns",
                "mu:centres:4",
                "--rows",
                "alpha:ends:4",
            ],
            "rows: alpha = 0.0",
        ),
    ],
)
def test_bad_options_are_refused_before_any_work(args, message, tmp_path):
    err = run_cli("lut", *args, cwd=tmp_path, code=2).stderr
    assert message in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_lookup_refuses_non_finite_inputs_naming_the_argument_and_index(filament):
    with pytest.raises(ValueError, match=r"mu: expected a finite number, got nan"):
        filament.lookup(math.nan, 0.5)
    with pytest.raises(ValueError, match=r"roughness: expected finite numbers, got inf at index 2"):
        filament.lookup(0.5, [0.1, 0.2, math.inf])
    with pytest.raises(ValueError, match=r"mu: expected finite numbers, got nan at index \(1, 0\)"):
        filament.lookup([[0.5], [math.nan]], 0.5)


def test_spec_errors_name_the_argument_and_the_right_fix(tmp_path):
    base = lut.preset("ue5", samples=16)
    with pytest.raises(ValueError, match="name: expected a C identifier, got None"):
        dataclasses.replace(base, name=None)
    # both ends of the roughness axis are checked: ggx takes alpha up to 1e7
    with pytest.raises(ValueError, match=r"rows: alpha = .* at the last texel .*; lower hi"):
        dataclasses.replace(base, rows=lut.Axis("alpha", 4, "ends", 1.0, 2e7))
    with pytest.raises(ValueError, match=r"rows: alpha = 0.0 at the first texel .*; raise lo"):
        dataclasses.replace(base, rows=lut.Axis("alpha", 4, "ends", 0.0, 1.0))
    # a shader's constant array is refused above 65536 values, before any work
    big = dataclasses.replace(
        base, columns=lut.Axis("mu", 256), rows=lut.Axis("perceptual", 256), samples=1
    )
    for suffix in (".glsl", ".wgsl"):
        err = run_cli(
            "lut",
            "--preset",
            "ue5",
            "--columns",
            "mu:centres:256",
            "--rows",
            "perceptual:centres:256",
            "-o",
            str(tmp_path / f"t{suffix}"),
            code=2,
        ).stderr
        assert f"t{suffix}: a {suffix} table is a constant array, and 131072 values" in err
        assert "Traceback" not in err
    small_table = lut.build(
        dataclasses.replace(base, columns=lut.Axis("mu", 4), rows=lut.Axis("perceptual", 4)),
        interp_limit=2,
    )
    tiny = dataclasses.replace(small_table, spec=big, decoded=np.zeros((256, 256, 2)))
    with pytest.raises(ValueError, match=r"path: a \.glsl table is a constant array"):
        tiny.save(tmp_path / "t.glsl")
    assert list(tmp_path.iterdir()) == []


def test_single_channel_unorm_energy_table(tmp_path):
    spec = lut.LutSpec(
        "energy",
        "ggx",
        lut.Axis("mu", 4),
        lut.Axis("perceptual", 4),
        "R16_UNORM",
        channels=("E",),
        samples=64,
    )
    t = lut.build(spec, interp_limit=4)
    raw = t.save(tmp_path / "e.ktx2").read_bytes()
    assert struct.unpack_from("<2I", raw, 12) == (70, 2)  # VK_FORMAT_R16_UNORM
    assert t.decoded.shape == (4, 4, 1)


def test_the_budget_of_a_table_computed_without_sampling_says_so():
    """An energy table whose E is in closed form samples nothing: its budget's confidence
    does not speak of Monte Carlo errors, and its texels have no Monte Carlo error."""
    views = [m for m, s in brdf_rs.models().items() if s["view_albedo_closed_form"]]
    assert views
    axes = (lut.Axis("mu", 4), lut.Axis("perceptual", 4))
    closed = lut.build(lut.LutSpec("energy", views[0], *axes), interp_limit=4)
    assert "closed form" in closed.budget.confidence
    assert "Monte Carlo" not in closed.budget.confidence
    assert closed.budget.channels[0] == "E" and closed.budget.mc_max_stderr[0] == 0.0
    sampled = lut.build(lut.LutSpec("energy", "ggx", *axes, samples=64), interp_limit=4)
    assert "Monte Carlo" in sampled.budget.confidence


def test_meet_error_picks_the_first_size_and_format_whose_total_fits():
    spec = lut.LutSpec(
        "energy",
        "ggx",
        lut.Axis("mu", 4, "ends", 0.2, 1.0),
        lut.Axis("perceptual", 4, "ends", 0.3, 1.0),
        "R32G32_SFLOAT",
        samples=1024,
    )
    choice = lut.meet_error(spec, 0.02, sizes=(2, 4, 8, 16), interp_limit=8)
    assert choice.lut is not None
    assert max(choice.lut.budget.total) <= 0.02
    # everything tried before the answer missed the error; the answer is the last tried
    assert all(total > 0.02 for _, _, total in choice.tried[:-1])
    n, fmt, total = choice.tried[-1]
    assert (choice.lut.spec.columns.size, choice.lut.spec.format) == (n, fmt)
    assert max(choice.lut.budget.total) == total
    # the answer's budget is the one compared: measured at the same interp_limit's points
    # (fewer than the 15 midpoints of a 16-texel axis), not rebuilt with the default
    coarse = lut.meet_error(spec, 0.05, sizes=(16,), interp_limit=4)
    assert coarse.lut is not None
    assert max(coarse.lut.budget.total) == coarse.tried[-1][2] <= 0.05
    trial = lut.build(coarse.lut.spec, interp_limit=4)
    assert coarse.lut.budget == trial.budget
    np.testing.assert_array_equal(coarse.lut.stored, trial.stored)
    assert choice.lut.spec.columns.lo == 0.2  # the axes' ranges are kept
    impossible = lut.meet_error(spec, 1e-7, sizes=(2, 4), interp_limit=4)
    assert impossible.lut is None and len(impossible.tried) == 2 * 3


def test_cli_max_error_says_when_it_cannot(tmp_path):
    err = run_cli(
        "lut",
        "--kind",
        "energy",
        "--model",
        "ggx",
        "--columns",
        "mu:ends:4:0.2:1",
        "--rows",
        "perceptual:ends:4:0.3:1",
        "--samples",
        "16",
        "--max-error",
        "1e-9",
        "--interp-limit",
        "4",
        "-o",
        str(tmp_path / "e.h"),
        code=1,
    ).stderr
    assert "no resolution up to 512" in err and "--max-error 1e-09" in err
    assert not (tmp_path / "e.h").exists()
    err = run_cli("lut", "--preset", "ue5", "--max-error", "-1", code=2).stderr
    assert "--max-error: expected a positive number" in err


def test_polynomial_fit_is_minimax_and_its_errors_are_measured(filament):
    """The fit minimises the worst texel error: no worse than the least-squares fit of the
    same degree (solved independently), and its reported errors are its own."""
    scipy_linalg = pytest.importorskip("scipy.linalg")
    f = lut.fit(filament, 3)
    s = filament.spec
    x, y = np.meshgrid(s.columns.fractions(), s.rows.fractions())
    # an independent least-squares fit: full 2-D Vandermonde, degree > 3 columns dropped
    v = np.polynomial.polynomial.polyvander2d(x.ravel(), y.ravel(), [3, 3])
    keep = [i + j <= 3 for i in range(4) for j in range(4)]
    mine = f(
        s.mu_axis.physical(s.mu_axis.positions())[None, :],
        s.roughness_axis.physical(s.roughness_axis.positions())[:, None],
    )
    for c in range(2):
        coef, *_ = scipy_linalg.lstsq(v[:, keep], filament.image[..., c].ravel())
        least_squares = np.abs(v[:, keep] @ coef - filament.image[..., c].ravel()).max()
        worst = np.abs(mine[..., c] - filament.image[..., c]).max()
        assert f.worst_texels[c] == pytest.approx(worst, abs=1e-12)
        assert worst < 0.9 * least_squares, (worst, least_squares)
    assert all(w > 0 for w in f.worst_between)
    assert f.terms == 10 and f.denominator == 0 and f.den_coefficients is None
    with pytest.raises(ValueError, match="degree: expected an integer from 1 to 12"):
        lut.fit(filament, 0)
    with pytest.raises(ValueError, match="denominator: expected an integer from 0 to 12"):
        lut.fit(filament, 2, -1)


def test_rational_minimax_recovers_a_rational_function_and_refuses_poles():
    from brdf_rs import _lutfit

    x, y = (g.ravel() for g in np.meshgrid(np.linspace(0, 1, 24), np.linspace(0, 1, 24)))
    u, v = 2 * x - 1, 2 * y - 1
    f = (1 + 0.3 * u - 0.2 * v * v) / (1.4 + 0.6 * u + 0.3 * u * v)
    p, q = _lutfit._minimax(x, y, f, 2, 2)
    got = _lutfit._poly(p, u, v) / _lutfit._poly(q, u, v)
    assert np.abs(got - f).max() < 1e-10
    # a pole inside [0, 1]²: the only fits that follow it have a vanishing denominator
    pole = 1 / (0.5 - x + 1e-3 * (y + 1))
    with pytest.raises(ValueError, match="denominator: no degree-1/1 rational fit"):
        _lutfit._minimax(x, y, pole, 1, 1)


def test_fit_maximum_error_holds_at_random_points(filament):
    """A fit's stated maximum error (dense grid + 3 stderr + float32 rounding) against
    fresh integrals at random points of the domain, integrated apart (other seed, more
    samples): within it, up to those integrals' own 3 stderr."""
    for denominator in (0, 2):
        f = lut.fit(filament, 4, denominator)
        assert f.dense_points == 32 * 31  # roughness 0 (alpha 0) is out of ggx's range
        rng = np.random.default_rng(11)
        mu = 1e-4 + (1 - 1e-4) * rng.random(200)
        r = rng.random(200)
        alpha = np.maximum(r, 1e-3) ** 2
        exact, se = ggx_b_and_a_plus_b(mu, alpha, 1 << 13, 17)
        err = np.abs(f(mu, alpha) - exact) - 3 * se
        assert np.all(err.max(axis=0) <= np.asarray(f.max_error)), (err.max(0), f.max_error)
        assert np.all(np.asarray(f.max_error_interior) <= np.asarray(f.max_error))


@pytest.mark.parametrize("degrees", [(4, 0), (3, 2)])
def test_fit_as_c_code_evaluates_the_fit(filament, tmp_path, degrees):
    f = lut.fit(filament, *degrees, dense=False)
    assert f.worst_dense == [] and f.max_error_interior == []
    f.save(tmp_path / "fit.h")
    text = (tmp_path / "fit.h").read_text()
    assert (" / (" in text) == (degrees[1] > 0)
    pts = [(0.05, 0.01), (0.4, 0.3), (0.9, 0.8)]
    got = c_lookups(tmp_path, "fit.h", "filament_dfg_fit", pts)
    mu, alpha = np.array(pts).T
    np.testing.assert_allclose(got, f(mu, alpha), atol=1e-5)
    assert max(f.float32_worst) < 1e-5
    with pytest.raises(ValueError, match="not a table"):
        lut.read(tmp_path / "fit.h")


def test_filament_cloth_preset_adds_the_sheen_albedo_as_a_third_channel(tmp_path):
    spec = small("filament_cloth", 4)
    assert lut.preset("filament_cloth").format == "R16G16B16_SFLOAT"
    t = lut.build(spec, interp_limit=4)
    mu = (np.arange(4) + 0.5) / 4
    r = (np.arange(4) + 0.5) / 4
    # dfg_table's cloth cells are albedo_table's cells for the sheen model: same bits.
    cloth = brdf_rs.albedo_table(
        spec.sheen, {"mu": mu, "alpha": r**2}, kd=0, ks=1, samples=spec.samples
    )
    np.testing.assert_allclose(t.image[..., 2], cloth.value[..., 0].T, atol=1e-15)
    raw = t.save(tmp_path / "c.ktx2").read_bytes()
    assert struct.unpack_from("<2I", raw, 12) == (90, 2)  # VK_FORMAT_R16G16B16_SFLOAT
    with pytest.raises(ValueError, match="DXGI has no R16G16B16_SFLOAT"):
        t.save(tmp_path / "c.dds")
    with pytest.raises(ValueError, match="the cloth channel needs a sheen model"):
        lut.preset("filament", format="R16G16B16_SFLOAT", channels=None)
    # the progress bar's passes count the cloth run too (each tiny run reports its end)
    calls = []
    lut.build(spec, interp_limit=4, progress=lambda done, _: calls.append(done))
    assert calls == lut.passes(spec, 4) == [16, 16, 16, 30, 30, 30]


def test_every_axis_quantity_lands_on_its_texels_in_python_and_in_c(tmp_path):
    spec = lut.LutSpec(
        "dfg",
        "ggx",
        lut.Axis("alpha", 5, "ends", 0.05, 0.9),
        lut.Axis("sqrt_mu", 6, "centres", 0.1, 1.0),
        "R32G32_SFLOAT",
        samples=64,
        name="q",
    )
    t = lut.build(spec, interp_limit=4)
    alpha = 0.05 + 0.85 * np.arange(5) / 4  # ends: k / (n - 1)
    mu = (0.1 + 0.9 * (np.arange(6) + 0.5) / 6) ** 2  # centres of sqrt(mu)
    np.testing.assert_allclose(t.lookup(mu[:, None], alpha[None, :]), t.decoded, atol=1e-12)
    t.save(tmp_path / "q.h")
    got = c_lookups(tmp_path, "q.h", "q_lookup", [(float(m), float(a)) for m in mu for a in alpha])
    np.testing.assert_allclose(got.reshape(6, 5, 2), t.decoded, atol=2e-6)


def test_cli_lists_presets_and_writes_a_fit(tmp_path):
    listed = json.loads(run_cli("lut", "--list", "--json").stdout)
    assert set(listed) == set(lut.PRESETS)
    assert all(row["source"] and "brdf-rs lut" in row["command"] for row in listed.values())
    out = json.loads(
        run_cli(
            "lut",
            "--preset",
            "ue5",
            "--columns",
            "mu:centres:8",
            "--rows",
            "perceptual:centres:8",
            "--samples",
            "64",
            "--interp-limit",
            "4",
            "--fit",
            "3/2",
            "-o",
            str(tmp_path / "f.wgsl"),
            "--json",
        ).stdout
    )
    assert (out["degree"], out["denominator"], out["terms"]) == (3, 2, 15)
    assert len(out["worst_texels"]) == 2 and out["dense_points"] == 32 * 31
    assert all(m >= d for m, d in zip(out["max_error"], out["worst_dense"], strict=True))
    text = (tmp_path / "f.wgsl").read_text()
    assert "fn ue5_ggx_spec_energy_fit(mu: f32, roughness: f32)" in text
    assert "degree-3/2 rational minimax fit" in text
    err = run_cli(
        "lut", "--preset", "ue5", "--fit", "3", "-o", str(tmp_path / "f.dds"), code=2
    ).stderr
    assert "a --fit is source code" in err
    for bad in ("3/x", "1/2/3"):
        err = run_cli("lut", "--preset", "ue5", "--fit", bad, code=2).stderr
        assert "expected N or N/M" in err
    err = run_cli("lut", "--preset", "ue5", "--fit", "3/13", "-o", str(tmp_path / "f.h"), code=2)
    assert "--fit: expected N from 1 to 12 and M from 0 to 12, got 3/13" in err.stderr


@pytest.mark.parametrize("suffix", [".exr", ".ktx2", ".dds", ".png"])
@pytest.mark.parametrize("damage", ["truncated", "empty"])
def test_a_damaged_lut_file_is_refused_naming_its_path(filament, tmp_path, suffix, damage):
    """One error type for every container and every kind of damage (a truncated EXR made
    OpenEXR raise RuntimeError), naming the path the user gave."""
    if suffix == ".exr":
        pytest.importorskip("OpenEXR")
    if suffix == ".png":
        pytest.importorskip("png")
    path = filament.save(tmp_path / f"t{suffix}")
    raw = path.read_bytes()
    path.write_bytes(raw[: len(raw) // 2] if damage == "truncated" else b"")
    with pytest.raises(ValueError, match=rf"^{re.escape(str(path))}: not a LUT file"):
        lut.read(path)


def test_lut_helpers_refuse_bad_input_by_name():
    columns, rows = lut.parse_axis("mu:centres:8"), lut.parse_axis("alpha:ends:4")
    image = np.zeros((4, 8, 2))
    with pytest.raises(ValueError, match=r"^col_q = nan: must be finite"):
        lut.bilinear(image, columns, rows, np.nan, 0.5)
    with pytest.raises(ValueError, match=r"^row_q\[1\] = inf: must be finite"):
        lut.bilinear(image, columns, rows, 0.5, [0.5, np.inf])
    with pytest.raises(ValueError, match=r"^image: expected shape \(4, 8, channels\)"):
        lut.bilinear(np.zeros((3, 3, 2)), columns, rows, 0.5, 0.5)
    with pytest.raises(ValueError, match=r"^values\[0\] = nan: must be finite"):
        lut.quantize(np.array([np.nan, 0.5]), "R16_UNORM")
    with pytest.raises(ValueError, match=r"^format: unknown 'RGBA8'"):
        lut.quantize(np.array([0.5]), "RGBA8")


def test_fit_refuses_a_dense_check_of_another_spec(filament):
    other = lut.dense_check(small("filament", 4))
    with pytest.raises(ValueError, match="dense: expected True, False or the DenseCheck"):
        lut.fit(filament, 2, dense=other)
