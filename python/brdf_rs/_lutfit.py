"""Analytic fits of a LUT, emitted as shader code: each channel a polynomial of total
degree ``d`` in the table's two axis fractions ``s, t`` in [0, 1] (``s = (q − lo)/(hi −
lo)`` of the column quantity, ``t`` of the row quantity), least squares on the float64
texels. Its error is measured, not assumed: against the texels, and against the fresh
integrals between the texels that the table's own interpolation budget used."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _atomic

if TYPE_CHECKING:  # pragma: no cover
    from .lut import Axis, Lut, LutSpec


def _terms(degree: int) -> list[tuple[int, int]]:
    return [(i, j) for i in range(degree + 1) for j in range(degree + 1 - i)]


def _fractions(axis: Axis, q: Any) -> np.ndarray:
    t = (np.asarray(q, dtype=np.float64) - axis.lo) / (axis.hi - axis.lo)
    return np.clip(t, 0.0, 1.0)


@dataclasses.dataclass(frozen=True)
class Fit:
    """A polynomial fit of a LUT's channels. ``coefficients[c][i][j]`` multiplies
    ``s^i t^j`` (``i + j <= degree``, zero elsewhere) for channel ``c``; ``worst_texels``
    / ``rms_texels`` its error against the table's texels, ``worst_between`` against the
    integrals at the table's interpolation check points (standard error up to
    ``between_stderr``), per channel."""

    spec: LutSpec
    degree: int
    coefficients: np.ndarray
    worst_texels: list[float]
    rms_texels: list[float]
    worst_between: list[float]
    between_stderr: list[float]

    def __call__(self, mu: Any, roughness: Any) -> np.ndarray:
        """The fit at incidence cosines ``mu`` and roughness parameter values (float64)."""
        s = self.spec
        m = s.mu_axis.quantity_of(mu)
        r = s.roughness_axis.quantity_of(roughness)
        col, row = (m, r) if s.columns.role == "mu" else (r, m)
        return self._at(_fractions(s.columns, col), _fractions(s.rows, row))

    def _at(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        out = np.zeros((*x.shape, self.coefficients.shape[0]))
        for c in range(self.coefficients.shape[0]):
            for i, j in _terms(self.degree):
                out[..., c] += self.coefficients[c, i, j] * x**i * y**j
        return out

    def meta(self) -> dict[str, Any]:
        return {
            "brdf_rs_lut_fit": 1,
            "degree": self.degree,
            "variables": "s = (q_col - lo)/(hi - lo), t = (q_row - lo)/(hi - lo), each clamped"
            " to [0, 1], q the axis quantities of the table the fit approximates",
            "table_content_hash": self.spec.content_hash(),
            "command": self.spec.command("OUT") + f" --fit {self.degree}",
            "recipe": self.spec.recipe(),
            "worst_texels": self.worst_texels,
            "rms_texels": self.rms_texels,
            "worst_between": self.worst_between,
            "between_stderr": self.between_stderr,
        }

    def save(self, path: str | Path) -> Path:
        """Writes the fit as ``.h``, ``.glsl``, ``.hlsl`` or ``.wgsl`` (atomically)."""
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix not in (".h", ".glsl", ".hlsl", ".wgsl"):
            raise ValueError(
                f"path: a fit is written as source code: .h, .glsl, .hlsl or .wgsl, not {suffix!r}"
            )
        with _atomic.atomic_write(path) as tmp, open(tmp, "w") as f:
            f.write(source(self, suffix))
        return path


def fit(lut: Lut, degree: int = 6) -> Fit:
    if isinstance(degree, bool) or not isinstance(degree, int) or not 1 <= degree <= 12:
        raise ValueError(f"degree: expected an integer from 1 to 12, got {degree!r}")
    s = lut.spec
    x, y = np.meshgrid(s.columns.fractions(), s.rows.fractions())
    terms = _terms(degree)
    if len(terms) > x.size:
        raise ValueError(
            f"degree: {len(terms)} coefficients need at least as many texels; the table has"
            f" {x.size}"
        )
    basis = np.stack([x.ravel() ** i * y.ravel() ** j for i, j in terms], -1)
    nc = lut.image.shape[-1]
    coefficients = np.zeros((nc, degree + 1, degree + 1))
    for c in range(nc):
        solved, *_ = np.linalg.lstsq(basis, lut.image[..., c].ravel(), rcond=None)
        for (i, j), v in zip(terms, solved, strict=True):
            coefficients[c, i, j] = v
    result = Fit(s, degree, coefficients, [], [], [], [])
    err = np.abs(result._at(x, y) - lut.image).reshape(-1, nc)
    between = np.zeros(nc)
    between_se = np.zeros(nc)
    if lut.checks is not None:
        ch = lut.checks
        col, row = (
            (ch.mu_q, ch.roughness_q) if s.columns.role == "mu" else (ch.roughness_q, ch.mu_q)
        )
        got = result._at(_fractions(s.columns, col), _fractions(s.rows, row))
        between = np.abs(got - ch.value).reshape(-1, nc).max(axis=0)
        between_se = ch.stderr.reshape(-1, nc).max(axis=0)
    return dataclasses.replace(
        result,
        worst_texels=err.max(axis=0).tolist(),
        rms_texels=np.sqrt((err**2).mean(axis=0)).tolist(),
        worst_between=between.tolist(),
        between_stderr=between_se.tolist(),
    )


def _axis_lines(axis: Axis, var: str, out: str, lang: str) -> list[str]:
    f = "f" if lang in ("c", "hlsl") else ""
    let = "let" if lang == "wgsl" else ("float" if lang != "wgsl" else "f32")
    sqrt = "sqrtf" if lang == "c" else "sqrt"
    fmax = "fmaxf" if lang == "c" else "max"
    fmin = "fminf" if lang == "c" else "min"
    q = f"{sqrt}({fmax}({var}, 0.0{f}))" if axis.quantity in ("sqrt_mu", "perceptual") else var
    from ._lutcode import float_literal

    lo = float_literal(axis.lo, f)
    span = float_literal(axis.hi - axis.lo, f)
    return [f"{let} {out} = {fmin}({fmax}(({q} - {lo}) / {span}, 0.0{f}), 1.0{f});"]


def source(result: Fit, suffix: str) -> str:
    lang = {".h": "c", ".glsl": "glsl", ".hlsl": "hlsl", ".wgsl": "wgsl"}[suffix]
    s = result.spec
    name = f"{s.name}_fit"
    nc = result.coefficients.shape[0]
    lit = "f" if lang in ("c", "hlsl", "glsl") else ""
    col_in = "mu" if s.columns.role == "mu" else "roughness"
    row_in = "mu" if s.rows.role == "mu" else "roughness"
    lines = _axis_lines(s.columns, col_in, "s", lang) + _axis_lines(s.rows, row_in, "t", lang)
    let = "let" if lang == "wgsl" else "float"
    names = []
    for c in range(nc):
        # Horner in t inside, in s outside: sum_i s^i (sum_j c_ij t^j).
        outer = []
        for i in range(result.degree + 1):
            coeffs = [result.coefficients[c, i, j] for j in range(result.degree + 1 - i)]
            inner = f"{coeffs[-1]:.9e}{lit}"
            for v in reversed(coeffs[:-1]):
                inner = f"({v:.9e}{lit} + t * {inner})"
            outer.append(inner)
        expr = outer[-1]
        for v in reversed(outer[:-1]):
            expr = f"({v} + s * {expr})"
        lines.append(f"{let} v{c} = {expr};")
        names.append(f"v{c}")
    header = [
        f"{name}: a degree-{result.degree} polynomial fit of the {s.kind} table of {s.model}"
        " (brdf-rs; do not edit).",
        f"Table columns: {s.columns.describe(s.param)}.",
        f"Table rows: {s.rows.describe(s.param)}.",
        f"Returns the channels {', '.join(s.channel_names)} at mu = cos(theta_v) and {s.param}.",
    ]
    for c, ch in enumerate(s.channel_names):
        header.append(
            f"Error {ch}: worst {result.worst_texels[c]:.3g} (RMS {result.rms_texels[c]:.3g})"
            f" against the texels, worst {result.worst_between[c]:.3g} against integrals"
            f" between them (their stderr up to {result.between_stderr[c]:.2g})."
        )
    header.append(f"Table content hash: {s.content_hash()}.")
    text = "\n".join(f"// {h}" for h in header)
    text += f"\n// brdf-rs:lut-fit {json.dumps(result.meta(), sort_keys=True)}\n"
    body = "\n    ".join(lines)
    if lang == "c":
        outs = "\n    ".join(f"out[{c}] = v{c};" for c in range(nc))
        return (
            text
            + f"#ifndef {name.upper()}_H\n#define {name.upper()}_H\n#include <math.h>\n\n"
            + f"static inline void {name}(float mu, float roughness, float out[{nc}]) {{\n"
            + f"    {body}\n    {outs}\n}}\n\n#endif\n"
        )
    if lang == "wgsl":
        ret = "f32" if nc == 1 else f"vec{nc}<f32>"
        value = "v0" if nc == 1 else f"{ret}({', '.join(names)})"
        return (
            text
            + f"fn {name}(mu: f32, roughness: f32) -> {ret} {{\n    {body}\n"
            + f"    return {value};\n}}\n"
        )
    vec = "float" if nc == 1 else ("vec" if lang == "glsl" else "float") + str(nc)
    value = "v0" if nc == 1 else f"{vec}({', '.join(names)})"
    return (
        text + f"{vec} {name}(float mu, float roughness) {{\n    {body}\n    return {value};\n}}\n"
    )
