"""Source code for a LUT: a C/C++ header, GLSL, HLSL or WGSL with the table as an array
(the format's decoded texels, as float literals), the grid convention and error budget in
a comment, ``NAME_lookup(mu, roughness)`` sampling the array bilinearly with the table's
texel mapping (clamp to the edge texels, as a GPU's sampler) and ``NAME_uv(mu,
roughness)`` giving the texture coordinate at which a hardware bilinear filter reads the
same value from a texture holding the table as stored (row 0 at v = 0). A 3-D table
(layers over eta or an exponent) has ``NAME_lookup(mu, roughness, eta)`` (or ``exponent``),
trilinear, and ``NAME_uvw``,
the 3-D texture coordinate (slice 0 at w = 0)."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from .lut import Axis, Lut


def _literal(v: float, suffix: str) -> str:
    return f"{v:.9e}{suffix}"


def float_literal(v: float, suffix: str) -> str:
    """``v`` exactly (its shortest repr) as a float literal valid in C, GLSL, HLSL and
    WGSL: always with a decimal point or an exponent, so ``0`` is ``0.0``."""
    text = repr(float(v))
    if not any(c in text for c in ".eE"):
        text += ".0"
    return text + suffix


def _comment(lut: Lut, meta: dict[str, Any], prefix: str) -> str:
    s = lut.spec
    b = lut.budget
    if s.layers is None:
        layout = (
            f"Layout: {s.rows.size} rows x {s.columns.size} columns x"
            f" {len(s.channel_names)} channel(s), row-major, channels interleaved:"
            " DATA[(row * WIDTH + column) * CHANNELS + channel]."
        )
    else:
        layout = (
            f"Layout: {s.layers.size} layers x {s.rows.size} rows x {s.columns.size} columns"
            f" x {len(s.channel_names)} channel(s), layers outermost, channels interleaved:"
            " DATA[((layer * HEIGHT + row) * WIDTH + column) * CHANNELS + channel]."
        )
    lines = [
        f"{s.name}: {s.kind} lookup table of {s.model}, made by brdf-rs (do not edit).",
        layout,
        f"Columns: {s.columns.describe(s.param)}.",
        f"Rows: {s.rows.describe(s.param)}.",
    ]
    if s.layers is not None:
        lines.append(f"Layers: {s.layers.describe(s.param)}.")
    for c in s.channel_names:
        lines.append(f"Channel {c}: {meta['channels'][c]}.")
    how = (
        f"lookup(mu, {s.param}) is bilinear"
        if s.layers is None
        else f"lookup(mu, {s.param}, {s.layers.role}) is trilinear"
    )
    lines.append(
        f"Values: {s.format} texels, decoded. {how} between texel samples and clamps to the"
        " edge texels."
    )
    for k, c in enumerate(b.channels):
        lines.append(
            f"Error budget {c}: Monte Carlo stderr <= {b.mc_max_stderr[k]:.3g}, quantization"
            f" worst {b.quant_worst[k]:.3g} (RMS {b.quant_rms[k]:.3g}),"
            f" {'bilinear' if s.layers is None else 'trilinear'}"
            f" interpolation worst {b.interp_worst[k]:.3g} ({b.interp_points} points between"
            f" texels, against integrals of stderr <= {b.interp_ref_stderr[k]:.3g}), total"
            f" {b.total[k]:.3g} ({b.confidence})."
        )
    lines.append(f"Content hash: {meta['content_hash']}.")
    lines.append(f"Rebuild: {meta['command']}")
    lines.append(f"Check: brdf-rs lut --verify {meta['recipe']['name']}.<suffix>")
    text = "\n".join(f"{prefix} {line}" for line in lines)
    return text + f"\n{prefix} brdf-rs:lut {json.dumps(meta, sort_keys=True)}\n"


def _data(values: np.ndarray, suffix: str, per_line: int) -> str:
    flat = [_literal(float(v), suffix) for v in values.reshape(-1)]
    rows = [", ".join(flat[i : i + per_line]) for i in range(0, len(flat), per_line)]
    return ",\n".join(f"    {r}" for r in rows)


def _axis_code(axis: Axis, var: str, lang: str) -> list[str]:
    """Statements turning the physical input ``var`` into ``{var}_x`` (the continuous
    texel coordinate) and ``{var}_t`` (the texture coordinate in [0, 1])."""
    f = "f" if lang in ("c", "hlsl") else ""
    fl = "float" if lang != "wgsl" else "f32"
    let = "let" if lang == "wgsl" else fl
    var_kw = "var" if lang == "wgsl" else fl
    sqrt = "sqrtf" if lang == "c" else "sqrt"
    fmax = "fmaxf" if lang == "c" else "max"
    fmin = "fminf" if lang == "c" else "min"
    square = axis.quantity in ("sqrt_mu", "perceptual")
    q = f"{sqrt}({fmax}({var}, 0.0{f}))" if square else var
    if axis.quantity in ("eta_z", "eta_z_inside"):
        fabs = "fabsf" if lang == "c" else "abs"
        q = f"{sqrt}({fabs}({var} - 1.0{f}) / ({var} + 1.0{f}))"
    elif axis.quantity == "exponent_z":
        q = f"1.0{f} / (1.0{f} + {var} / 5.0{f})"
    n = axis.size
    lo = float_literal(axis.lo, f)
    span = float_literal(axis.hi - axis.lo, f)
    if axis.placement == "centres":
        x = f"({var}_q - {lo}) / {span} * {n}.0{f} - 0.5{f}"
    else:
        x = f"({var}_q - {lo}) / {span} * {n - 1}.0{f}"
    return [
        f"{let} {var}_q = {q};",
        f"{var_kw} {var}_x = {x};",
        f"{var}_x = {fmin}({fmax}({var}_x, 0.0{f}), {n - 1}.0{f});",
        f"{let} {var}_t = ({var}_x + 0.5{f}) / {n}.0{f};",
    ]


def _bilinear(name: str, w: int, nc: int, k: int, let: str, u: str, f: str) -> str:
    """Statements blending channel ``k``'s four texels around ``(x0, y0)`` by ``(fx, fy)``
    into ``r{k}``: ``let`` declares a value, ``u`` suffixes the integer literals and ``f``
    the float ones (GLSL and HLSL: ``float``, no suffix; WGSL: ``let``, ``u``)."""

    def texel(row: str, col: str) -> str:
        return f"{name}_data[({row} * {w}{u} + {col}) * {nc}{u} + {k}{u}]"

    below, right = f"(y0 + 1{u})", f"x0 + 1{u}"
    return (
        f"{let} a{k} = {texel('y0', 'x0')};\n"
        f"    {let} b{k} = {texel('y0', right)};\n"
        f"    {let} d{k} = {texel(below, 'x0')};\n"
        f"    {let} e{k} = {texel(below, right)};\n"
        f"    {let} r{k} = (a{k} * (1.0{f} - fx) + b{k} * fx) * (1.0{f} - fy)"
        f" + (d{k} * (1.0{f} - fx) + e{k} * fx) * fy;"
    )


#: What a 3-D table's third input is, by the layers axis' role.
_LAYER_TEXT = {"eta": "the relative index eta", "exponent": "generalized Schlick's exponent"}


def _inputs_3d(lut: Lut, lang: str) -> tuple[list[str], list[str], list[str]]:
    """A 3-D table's inputs (``mu``, ``roughness`` and the layer's ``eta`` or
    ``exponent``) in the order of its axes, the statements turning them into texel
    coordinates and cells (for the lookup), and into texture coordinates too (for
    ``uvw``)."""
    s = lut.spec
    assert s.layers is not None
    d, h, w, _ = lut.decoded.shape
    names = ["mu" if a.role == "mu" else "roughness" for a in (s.columns, s.rows)]
    names.append(s.layers.role)
    per_axis = [
        _axis_code(a, v, lang) for a, v in zip((s.columns, s.rows, s.layers), names, strict=True)
    ]
    cells = [
        (f"{v}_x", i, fr, n)
        for v, i, fr, n in zip(
            names, ("x0", "y0", "z0"), ("fx", "fy", "fz"), (w, h, d), strict=True
        )
    ]
    # The lookup needs no texture coordinate, each axis' last statement.
    lookup = [line for code in per_axis for line in code[:-1]] + _cell_code(lang, cells)
    return names, lookup, [line for code in per_axis for line in code]


def _source_3d(lut: Lut, meta: dict[str, Any]) -> str:
    """A 3-D table as a C/C++ header: the array, a trilinear lookup and the 3-D texture
    coordinate."""
    s = lut.spec
    name = s.name
    d, h, w, nc = lut.decoded.shape
    (col_in, row_in, lay), lookup, uvw = _inputs_3d(lut, "c")
    upper = name.upper()
    block = f"// BEGIN DATA\n{_data(lut.decoded, 'f', 6)}\n// END DATA\n"
    body = "\n    ".join(lookup)
    texel = f"{name}_data[(((z0 + dz) * {h} + y0 + dy) * {w} + x0 + dx) * {nc} + c]"
    return (
        _comment(lut, meta, "//")
        + f"#ifndef {upper}_H\n#define {upper}_H\n#include <math.h>\n\n"
        + f"#define {upper}_WIDTH {w}\n#define {upper}_HEIGHT {h}\n#define {upper}_DEPTH {d}\n"
        + f"#define {upper}_CHANNELS {nc}\n\n"
        + f"static const float {name}_data[{d * h * w * nc}] = {{\n{block}}};\n\n"
        + f"/* Trilinear lookup at mu = cos(theta_v), {s.param} and {_LAYER_TEXT[lay]};"
        + f" writes {nc} value(s). */\n"
        + f"static inline void {name}_lookup(float mu, float roughness, float {lay},"
        + f" float out[{nc}]) {{\n"
        + f"    {body}\n"
        + f"    for (int c = 0; c < {nc}; ++c) {{\n"
        + "        float v = 0.0f;\n"
        + "        for (int dz = 0; dz < 2; ++dz)\n"
        + "            for (int dy = 0; dy < 2; ++dy)\n"
        + "                for (int dx = 0; dx < 2; ++dx)\n"
        + "                    v += (dx ? fx : 1.0f - fx) * (dy ? fy : 1.0f - fy)"
        + f" * (dz ? fz : 1.0f - fz)\n                         * {texel};\n"
        + "        out[c] = v;\n"
        + "    }\n}\n\n"
        + "/* The 3-D texture coordinate (u, v, w) a hardware trilinear filter reads it at. */\n"
        + f"static inline void {name}_uvw(float mu, float roughness, float {lay},"
        + " float uvw[3]) {\n    "
        + "\n    ".join(uvw)
        + f"\n    uvw[0] = {col_in}_t;\n    uvw[1] = {row_in}_t;\n    uvw[2] = {lay}_t;\n}}\n\n"
        + "#endif\n"
    )


def _shader_data(lang: str, name: str, total: int, block: str) -> str:
    """The table's array declaration in GLSL, HLSL or WGSL."""
    if lang == "glsl":
        return f"const float {name}_data[{total}] = float[{total}](\n{block});\n\n"
    if lang == "hlsl":
        return f"static const float {name}_data[{total}] = {{\n{block}}};\n\n"
    return f"var<private> {name}_data: array<f32, {total}> = array<f32, {total}>(\n{block});\n\n"


def _shader_vec(lang: str, n: int) -> str:
    """The type of ``n`` floats in GLSL, HLSL or WGSL (a scalar for one)."""
    if lang == "wgsl":
        return "f32" if n == 1 else f"vec{n}<f32>"
    if n == 1:
        return "float"
    return ("vec" if lang == "glsl" else "float") + str(n)


def _cell_code(lang: str, cells: list[tuple[str, str, str, int]]) -> list[str]:
    """Statements giving, per axis ``(coordinate, index, fraction, texels)``, the first
    texel ``index`` of the cell the continuous ``coordinate`` falls in (at most ``texels
    − 2``) and the ``fraction`` of the way to the next."""
    if lang == "wgsl":
        out = [f"let {i} = min(u32({x}), {n - 2}u);" for x, i, _, n in cells]
        return out + [f"let {fr} = {x} - f32({i});" for x, i, fr, _ in cells]
    cast_int = "int" if lang == "glsl" else "(int)"
    cast_float = "float" if lang == "glsl" else "(float)"
    out = [f"int {i} = {cast_int}({x}); if ({i} > {n - 2}) {i} = {n - 2};" for x, i, _, n in cells]
    return out + [f"float {fr} = {x} - {cast_float}({i});" for x, i, fr, _ in cells]


def _trilinear(name: str, h: int, w: int, nc: int, k: int, let: str, u: str, f: str) -> str:
    """Statements blending channel ``k``'s eight texels around ``(x0, y0, z0)`` by ``(fx,
    fy, fz)`` into ``r{k}``: bilinear in slices ``z0`` and ``z0 + 1``, then between them
    (``let``, ``u`` and ``f`` as for :func:`_bilinear`)."""

    def texel(dz: int, dy: int, dx: int) -> str:
        z = f"(z0 + 1{u})" if dz else "z0"
        y = f"(y0 + 1{u})" if dy else "y0"
        x = f"(x0 + 1{u})" if dx else "x0"
        return f"{name}_data[(({z} * {h}{u} + {y}) * {w}{u} + {x}) * {nc}{u} + {k}{u}]"

    lines = []
    for dz, slab in ((0, "n"), (1, "m")):
        lines.append(
            f"{let} {slab}{k} = ({texel(dz, 0, 0)} * (1.0{f} - fx) + {texel(dz, 0, 1)} * fx)"
            f" * (1.0{f} - fy)\n        + ({texel(dz, 1, 0)} * (1.0{f} - fx)"
            f" + {texel(dz, 1, 1)} * fx) * fy;"
        )
    lines.append(f"{let} r{k} = n{k} * (1.0{f} - fz) + m{k} * fz;")
    return "\n    ".join(lines)


def _shader_3d(lut: Lut, meta: dict[str, Any], lang: str) -> str:
    """A 3-D table in GLSL, HLSL or WGSL: the array, a trilinear lookup and the 3-D texture
    coordinate."""
    s = lut.spec
    name = s.name
    d, h, w, nc = lut.decoded.shape
    total = d * h * w * nc
    (col_in, row_in, lay), lookup_code, uvw = _inputs_3d(lut, lang)
    f = "f" if lang == "hlsl" else ""
    suffix = "f" if lang != "wgsl" else ""
    block = f"// BEGIN DATA\n{_data(lut.decoded, suffix, 6)}\n// END DATA\n"
    data = _shader_data(lang, name, total, block)
    vec, v3 = _shader_vec(lang, nc), _shader_vec(lang, 3)
    if lang in ("glsl", "hlsl"):
        fetch = [_trilinear(name, h, w, nc, k, "float", "", f) for k in range(nc)]
        lookup = f"{vec} {name}_lookup(float mu, float roughness, float {lay})"
        uv = f"{v3} {name}_uvw(float mu, float roughness, float {lay})"
    else:  # WGSL
        fetch = [_trilinear(name, h, w, nc, k, "let", "u", "") for k in range(nc)]
        lookup = f"fn {name}_lookup(mu: f32, roughness: f32, {lay}: f32) -> {vec}"
        uv = f"fn {name}_uvw(mu: f32, roughness: f32, {lay}: f32) -> {v3}"
    result = "r0" if nc == 1 else f"{vec}({', '.join(f'r{k}' for k in range(nc))})"
    return (
        _comment(lut, meta, "//")
        + data
        + f"// Trilinear lookup at mu = cos(theta_v), {s.param} and {_LAYER_TEXT[lay]}.\n"
        + f"{lookup} {{\n    "
        + "\n    ".join(lookup_code + fetch)
        + f"\n    return {result};\n}}\n\n"
        + "// The 3-D texture coordinate a hardware trilinear filter reads the same value at.\n"
        + f"{uv} {{\n    "
        + "\n    ".join(uvw)
        + f"\n    return {v3}({col_in}_t, {row_in}_t, {lay}_t);\n}}\n"
    )


def source(lut: Lut, meta: dict[str, Any], suffix: str) -> str:
    lang = {".h": "c", ".glsl": "glsl", ".hlsl": "hlsl", ".wgsl": "wgsl"}[suffix]
    if lut.spec.layers is not None:
        return _source_3d(lut, meta) if lang == "c" else _shader_3d(lut, meta, lang)
    s = lut.spec
    name = s.name
    h, w, nc = lut.decoded.shape
    total = h * w * nc
    col_in = "mu" if s.columns.role == "mu" else "roughness"
    row_in = "mu" if s.rows.role == "mu" else "roughness"
    col_uv = _axis_code(s.columns, col_in, lang)
    row_uv = _axis_code(s.rows, row_in, lang)
    col_code, row_code = col_uv[:-1], row_uv[:-1]  # the lookups need no texture coordinate
    f = "f" if lang in ("c", "hlsl") else ""
    fsuffix = "f" if lang in ("c", "hlsl", "glsl") else ""
    data = _data(lut.decoded, fsuffix, 6)
    block = f"// BEGIN DATA\n{data}\n// END DATA\n"
    head = _comment(lut, meta, "//")
    upper = name.upper()
    interp = _cell_code(lang, [(f"{col_in}_x", "x0", "fx", w), (f"{row_in}_x", "y0", "fy", h)])
    if lang == "c":
        body = "\n    ".join(col_code + row_code + interp)
        return (
            head
            + f"#ifndef {upper}_H\n#define {upper}_H\n#include <math.h>\n\n"
            + f"#define {upper}_WIDTH {w}\n#define {upper}_HEIGHT {h}\n"
            + f"#define {upper}_CHANNELS {nc}\n\n"
            + f"static const float {name}_data[{total}] = {{\n{block}}};\n\n"
            + f"/* Bilinear lookup at mu = cos(theta_v) and {s.param}; writes {nc} value(s). */\n"
            + f"static inline void {name}_lookup(float mu, float roughness, float out[{nc}]) {{\n"
            + f"    {body}\n"
            + f"    for (int c = 0; c < {nc}; ++c) {{\n"
            + f"        float a = {name}_data[(y0 * {w} + x0) * {nc} + c];\n"
            + f"        float b = {name}_data[(y0 * {w} + x0 + 1) * {nc} + c];\n"
            + f"        float d = {name}_data[((y0 + 1) * {w} + x0) * {nc} + c];\n"
            + f"        float e = {name}_data[((y0 + 1) * {w} + x0 + 1) * {nc} + c];\n"
            + "        out[c] = (a * (1.0f - fx) + b * fx) * (1.0f - fy)"
            + " + (d * (1.0f - fx) + e * fx) * fy;\n"
            + "    }\n}\n\n"
            + "/* The texture coordinate (u, v) a hardware bilinear filter reads it at. */\n"
            + f"static inline void {name}_uv(float mu, float roughness, float uv[2]) {{\n"
            + "    "
            + "\n    ".join(col_uv + row_uv)
            + f"\n    uv[0] = {col_in}_t;\n    uv[1] = {row_in}_t;\n}}\n\n#endif\n"
        )
    data = _shader_data(lang, name, total, block)
    vec, v2 = _shader_vec(lang, nc), _shader_vec(lang, 2)
    if lang in ("glsl", "hlsl"):
        fetch = [_bilinear(name, w, nc, k, "float", "", f) for k in range(nc)]
        lookup = f"{vec} {name}_lookup(float mu, float roughness)"
        uv = f"{v2} {name}_uv(float mu, float roughness)"
    else:  # WGSL
        fetch = [_bilinear(name, w, nc, k, "let", "u", "") for k in range(nc)]
        lookup = f"fn {name}_lookup(mu: f32, roughness: f32) -> {vec}"
        uv = f"fn {name}_uv(mu: f32, roughness: f32) -> {v2}"
    result = "r0" if nc == 1 else f"{vec}({', '.join(f'r{k}' for k in range(nc))})"
    return (
        head
        + data
        + f"// Bilinear lookup at mu = cos(theta_v) and {s.param}.\n"
        + f"{lookup} {{\n    "
        + "\n    ".join(col_code + row_code + interp + fetch)
        + f"\n    return {result};\n}}\n\n"
        + "// The texture coordinate a hardware bilinear filter reads the same value at.\n"
        + f"{uv} {{\n    "
        + "\n    ".join(col_uv + row_uv)
        + f"\n    return {v2}({col_in}_t, {row_in}_t);\n}}\n"
    )
