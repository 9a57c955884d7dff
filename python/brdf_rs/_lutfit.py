"""Analytic fits of a LUT, emitted as shader code: each channel a polynomial of total
degree ``n`` in the table's two axis fractions ``s, t`` in [0, 1] (``s = (q − lo)/(hi −
lo)`` of the column quantity, ``t`` of the row quantity), or a rational function ``P/Q``
of total degrees ``n`` over ``m`` (``Q``'s constant term 1). The coefficients minimise the
largest error over the float64 texels (a minimax fit), and that error is measured, not
assumed: against the texels, against the fresh integrals between the texels that the
table's own interpolation budget used, and against fresh integrals on a grid several
times denser than the texels, which gives the fit's stated maximum error."""

from __future__ import annotations

import dataclasses
import json
import math
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


def _poly(
    coefficients: np.ndarray, x: np.ndarray, y: np.ndarray, dtype: Any = np.float64
) -> np.ndarray:
    """``sum c[i, j] x^i y^j`` over the triangle ``i + j <= degree``, by Horner in ``y``
    inside and ``x`` outside (the emitted code's order), in ``dtype``."""
    degree = coefficients.shape[0] - 1
    c = coefficients.astype(dtype)
    x, y = x.astype(dtype), y.astype(dtype)
    out = np.zeros(np.broadcast_shapes(x.shape, y.shape), dtype=dtype)
    for i in reversed(range(degree + 1)):
        inner = np.zeros_like(out)
        for j in reversed(range(degree + 1 - i)):
            inner = inner * y + c[i, j]
        out = out * x + inner
    return out


#: Each axis of the dense check grid has this many times the table's texels, ...
DENSE_FACTOR = 4
#: ... and at most this many points.
DENSE_LIMIT = 256
#: A denominator must stay above this on [0, 1]² (checked on a grid of this many points
#: per axis), so the fit has no pole and no near-pole in its domain.
_Q_FLOOR = 1e-3
_Q_GRID = 257
#: A table with more texels than this is fitted on a regular subset of about as many.
_FIT_TEXELS = 1 << 14
#: Minimax iterations (Lawson's reweighting, with the rational linearisation redone in
#: each).
_ITERATIONS = 200


@dataclasses.dataclass(frozen=True)
class Fit:
    """A fit of a LUT's channels, in ``u = 2s − 1`` and ``v = 2t − 1`` of the axis
    fractions ``s, t``. ``coefficients[c][i][j]`` multiplies ``u^i v^j`` in
    channel ``c``'s numerator (``i + j <= degree``, zero elsewhere);
    ``den_coefficients[c][i][j]`` likewise in its denominator (``i + j <=
    denominator``, the constant 1; a polynomial fit has ``denominator`` 0 and ``Q = 1``).

    Errors per channel: ``worst_texels`` / ``rms_texels`` against the table's texels,
    ``worst_between`` against the integrals at the table's interpolation check points
    (standard error up to ``between_stderr``), and ``worst_dense`` against fresh integrals
    on ``dense_points`` points of a grid :data:`DENSE_FACTOR` times denser than the
    texels along each axis (at most :data:`DENSE_LIMIT`, both range ends included;
    standard error up to ``dense_stderr``), all in float64; ``float32_worst`` the largest
    difference between the fit evaluated in float32, as the emitted code does it, and in
    float64, over the texels and the dense grid. ``max_error`` is the stated maximum: the
    largest of ``worst_texels``, ``worst_dense`` and ``worst_between``, each plus 3 of its
    reference's largest standard error (``texel_stderr``, the table's own, for the
    texels), plus ``float32_worst``. (The texels count where they are denser than the
    dense grid: a table over 64 texels per axis.)"""

    spec: LutSpec
    degree: int
    coefficients: np.ndarray
    worst_texels: list[float]
    rms_texels: list[float]
    worst_between: list[float]
    between_stderr: list[float]
    denominator: int = 0
    den_coefficients: np.ndarray | None = None
    worst_dense: list[float] = dataclasses.field(default_factory=list)
    dense_stderr: list[float] = dataclasses.field(default_factory=list)
    dense_points: int = 0
    float32_worst: list[float] = dataclasses.field(default_factory=list)
    worst_dense_interior: list[float] = dataclasses.field(default_factory=list)
    texel_stderr: list[float] = dataclasses.field(default_factory=list)

    @property
    def terms(self) -> int:
        """The number of free coefficients per channel."""
        return len(_terms(self.degree)) + len(_terms(self.denominator)) - 1

    @property
    def max_error(self) -> list[float]:
        return self._stated(self.worst_dense, self.worst_between)

    @property
    def max_error_interior(self) -> list[float]:
        """:attr:`max_error` between the first and last texels of both axes (where the
        table itself interpolates rather than clamps), from ``worst_dense_interior``;
        empty without the dense check."""
        if not self.worst_dense_interior:
            return []
        return self._stated(self.worst_dense_interior, [])

    def _stated(self, dense: list[float], between: list[float]) -> list[float]:
        """The largest of each measured error plus 3 of its reference's standard errors
        (the texels' own for ``worst_texels``), plus ``float32_worst``."""
        nc = len(self.worst_texels)
        parts = [(self.worst_texels, self.texel_stderr or [0.0] * nc)]
        if dense:
            parts.append((dense, self.dense_stderr))
        if between:
            parts.append((between, self.between_stderr))
        worst = np.max([np.asarray(w) + 3 * np.asarray(se) for w, se in parts], axis=0)
        rounding = np.asarray(self.float32_worst or [0.0] * nc)
        return [float(v) for v in worst + rounding]

    def __call__(self, mu: Any, roughness: Any) -> np.ndarray:
        """The fit at incidence cosines ``mu`` and roughness parameter values (float64)."""
        s = self.spec
        return self._at_quantities(
            s.mu_axis.quantity_of(mu), s.roughness_axis.quantity_of(roughness)
        )

    def _at_quantities(self, mu_q: Any, rough_q: Any, dtype: Any = np.float64) -> np.ndarray:
        """:meth:`_at` at the mu and roughness axes' quantities (either may be the columns)."""
        s = self.spec
        col, row = (mu_q, rough_q) if s.columns.role == "mu" else (rough_q, mu_q)
        return self._at(_fractions(s.columns, col), _fractions(s.rows, row), dtype)

    def _at(self, x: np.ndarray, y: np.ndarray, dtype: Any = np.float64) -> np.ndarray:
        """The fit at axis fractions ``x, y`` in [0, 1], evaluated in ``dtype`` (float32:
        as the emitted code does it, in ``u = 2x − 1``, ``v = 2y − 1`` by Horner in the
        same order), returned as float64."""
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        x = (2 * x.astype(dtype) - 1).astype(np.float64)
        y = (2 * y.astype(dtype) - 1).astype(np.float64)
        out = np.zeros((*x.shape, self.coefficients.shape[0]))
        for c in range(self.coefficients.shape[0]):
            value = _poly(self.coefficients[c], x, y, dtype)
            if self.den_coefficients is not None:
                value = value / _poly(self.den_coefficients[c], x, y, dtype)
            out[..., c] = value
        return out

    @property
    def form(self) -> str:
        if self.denominator == 0:
            return f"degree-{self.degree} polynomial"
        return f"degree-{self.degree}/{self.denominator} rational"

    def meta(self) -> dict[str, Any]:
        fit_arg = f"{self.degree}" + (f"/{self.denominator}" if self.denominator else "")
        return {
            "brdf_rs_lut_fit": 2,
            "degree": self.degree,
            "denominator": self.denominator,
            "variables": "u = 2 s - 1, v = 2 t - 1 with s = (q_col - lo)/(hi - lo), t = (q_row"
            " - lo)/(hi - lo), each clamped to [0, 1], q the axis quantities of the table the"
            " fit approximates",
            "table_content_hash": self.spec.content_hash(),
            "command": self.spec.command("OUT") + f" --fit {fit_arg}",
            "recipe": self.spec.recipe(),
            "worst_texels": self.worst_texels,
            "rms_texels": self.rms_texels,
            "worst_between": self.worst_between,
            "between_stderr": self.between_stderr,
            "worst_dense": self.worst_dense,
            "dense_stderr": self.dense_stderr,
            "dense_points": self.dense_points,
            "float32_worst": self.float32_worst,
            "texel_stderr": self.texel_stderr,
            "max_error": self.max_error,
            "worst_dense_interior": self.worst_dense_interior,
            "max_error_interior": self.max_error_interior,
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


def _basis(terms: list[tuple[int, int]], x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Columns ``T_i(2x − 1)·T_j(2y − 1)`` (Chebyshev: well conditioned on [0, 1]²)."""
    cx = np.polynomial.chebyshev.chebvander(2 * x - 1, max(i for i, _ in terms))
    cy = np.polynomial.chebyshev.chebvander(2 * y - 1, max(j for _, j in terms))
    return np.stack([cx[:, i] * cy[:, j] for i, j in terms], -1)


def _monomial(terms: list[tuple[int, int]], c: np.ndarray, degree: int) -> np.ndarray:
    """Chebyshev coefficients over ``terms`` to power-basis ones in the same variables
    ``u = 2x − 1``, ``v = 2y − 1`` (in [−1, 1], where powers stay well conditioned):
    ``out[i, j]`` multiplies ``u^i v^j``."""
    power = [
        np.polynomial.chebyshev.cheb2poly(np.eye(degree + 1)[k][: k + 1]) for k in range(degree + 1)
    ]
    out = np.zeros((degree + 1, degree + 1))
    for (i, j), v in zip(terms, c, strict=True):
        out[: i + 1, : j + 1] += v * np.outer(power[i], power[j])
    return out


def _minimax(
    x: np.ndarray, y: np.ndarray, f: np.ndarray, degree: int, denominator: int
) -> tuple[np.ndarray, np.ndarray | None]:
    """Power-basis coefficients (in ``2x − 1``, ``2y − 1``) of ``P`` (and ``Q``)
    minimising ``max |P/Q − f|`` over the points: Lawson's iteratively reweighted least
    squares (each point's weight times its error, renormalised), the rational problem
    linearised as ``P − f·Q`` over the last ``Q`` (Loeb, Sanathanan-Koerner). A ridge on
    ``Q``'s coefficients, shrinking from iteration to iteration, starts the rational fit
    from the polynomial one and keeps ``Q`` near 1 while the weights settle. Keeps the
    best iterate whose ``Q`` stays above :data:`_Q_FLOOR` on [0, 1]²."""
    num = _terms(degree)
    den = _terms(denominator)[1:]
    a_p = _basis(num, x, y)
    a_q = _basis(den, x, y) if den else np.zeros((x.size, 0))
    g_q = None
    if den:
        grid = np.linspace(0.0, 1.0, _Q_GRID)
        gx, gy = (g.ravel() for g in np.meshgrid(grid, grid))
        g_q = _basis(den, gx, gy)
    weights = np.full(x.size, 1.0 / x.size)
    q = np.ones(x.size)
    ridge = np.zeros((len(den), len(num) + len(den)))
    ridge[:, len(num) :] = np.eye(len(den))
    best: tuple[float, np.ndarray, np.ndarray] | None = None
    for k in range(_ITERATIONS):
        scale = np.sqrt(weights) / q
        system = np.concatenate([a_p, -f[:, None] * a_q], axis=1) * scale[:, None]
        rhs = f * scale
        if den:
            strength = np.sqrt(weights.max()) * 0.8**k
            system = np.concatenate([system, strength * ridge])
            rhs = np.concatenate([rhs, np.zeros(len(den))])
        c, *_ = np.linalg.lstsq(system, rhs, rcond=None)
        cp, cq = c[: len(num)], c[len(num) :]
        if g_q is not None and (g_q @ cq).min() + 1 <= _Q_FLOOR:
            continue  # a pole (or near one) in the domain: not kept, weights as they were
        q_new = 1 + a_q @ cq
        err = a_p @ cp / q_new - f
        worst = float(np.abs(err).max())
        if best is None or worst < best[0]:
            best = (worst, cp, cq)
        updated = weights * np.abs(err)
        total = updated.sum()
        if not total > 0:
            break
        weights = updated / total
        q = q_new
    if best is None:
        raise ValueError(
            f"denominator: no degree-{degree}/{denominator} rational fit keeps its denominator"
            " away from 0 on the table's domain; use a smaller denominator or 0"
        )
    _, cp, cq = best
    p_mono = _monomial(num, cp, degree)
    if not den:
        return p_mono, None
    q_mono = _monomial([(0, 0), *den], np.concatenate([[1.0], cq]), denominator)
    return p_mono, q_mono


def _dense_grid(spec: LutSpec) -> tuple[np.ndarray, np.ndarray]:
    """Mu and roughness quantities of the dense check: evenly spaced over each axis's range
    (ends included), :data:`DENSE_FACTOR` times its texels, at most :data:`DENSE_LIMIT`;
    mu from 1e-4 up and roughness values the model takes (as the interpolation check)."""
    from .lut import _checkable

    def points(axis: Axis) -> np.ndarray:
        n = min(DENSE_FACTOR * axis.size, DENSE_LIMIT)
        return np.unique(
            np.maximum(axis.lo + (axis.hi - axis.lo) * np.linspace(0, 1, n), axis.floor)
        )

    return _checkable(spec, points(spec.mu_axis), points(spec.roughness_axis))


@dataclasses.dataclass(frozen=True)
class DenseCheck:
    """Fresh integrals of a table's channels (kept ones) on its dense check grid
    (:func:`dense_check`): at axis quantities ``mu_q`` x ``roughness_q`` (2-D, mu first),
    ``value`` and ``stderr`` (channels last). Computed once, it serves any number of fits
    of tables with that ``spec``."""

    spec: LutSpec
    mu_q: np.ndarray
    roughness_q: np.ndarray
    value: np.ndarray
    stderr: np.ndarray


def dense_check(spec: LutSpec) -> DenseCheck:
    """The integrals a fit's maximum error is measured against (seed ``spec.seed + 2``,
    the spec's samples per point)."""
    from .lut import _integrate

    mu_q, r_q = _dense_grid(spec)
    value, stderr = _integrate(spec, mu_q, r_q, spec.seed + 2)
    keep = [spec.kind_channels.index(ch) for ch in spec.channel_names]
    mq, rq = np.meshgrid(mu_q, r_q, indexing="ij")
    return DenseCheck(spec, mq, rq, value[..., keep], stderr[..., keep])


def fit(lut: Lut, degree: int = 6, denominator: int = 0, dense: bool | DenseCheck = True) -> Fit:
    for name, given, low in (("degree", degree, 1), ("denominator", denominator, 0)):
        if isinstance(given, bool) or not isinstance(given, int) or not low <= given <= 12:
            raise ValueError(f"{name}: expected an integer from {low} to 12, got {given!r}")
    s = lut.spec
    x, y = np.meshgrid(s.columns.fractions(), s.rows.fractions())
    count = len(_terms(degree)) + len(_terms(denominator)) - 1
    if count > x.size:
        raise ValueError(
            f"degree: {count} coefficients need at least as many texels; the table has {x.size}"
        )
    nc = lut.image.shape[-1]
    coefficients = np.zeros((nc, degree + 1, degree + 1))
    den = np.zeros((nc, denominator + 1, denominator + 1)) if denominator else None
    # A large table is fitted on every k-th row and column (at most about _FIT_TEXELS
    # texels, the last row and column kept); its errors are measured on all of them.
    k = max(1, math.ceil(math.sqrt(x.size / _FIT_TEXELS)))
    rows = np.unique(np.r_[np.arange(0, x.shape[0], k), x.shape[0] - 1])
    cols = np.unique(np.r_[np.arange(0, x.shape[1], k), x.shape[1] - 1])
    sub = np.ix_(rows, cols)
    for c in range(nc):
        image = lut.image[..., c]
        p, q = _minimax(x[sub].ravel(), y[sub].ravel(), image[sub].ravel(), degree, denominator)
        coefficients[c] = p
        if den is not None and q is not None:
            den[c] = q
    result = Fit(s, degree, coefficients, [], [], [], [], denominator, den)
    at_texels = result._at(x, y)
    err = np.abs(at_texels - lut.image).reshape(-1, nc)
    between = np.zeros(nc)
    between_se = np.zeros(nc)
    if lut.checks is not None:
        ch = lut.checks
        got = result._at_quantities(ch.mu_q, ch.roughness_q)
        between = np.abs(got - ch.value).reshape(-1, nc).max(axis=0)
        between_se = ch.stderr.reshape(-1, nc).max(axis=0)
    worst_dense: list[float] = []
    worst_interior: list[float] = []
    dense_se: list[float] = []
    points = 0
    rounding = np.abs(result._at(x, y, np.float32) - at_texels).reshape(-1, nc).max(0)
    if dense is not False:
        from .lut import _worst_inside

        check = dense_check(s) if dense is True else dense
        if not isinstance(check, DenseCheck) or check.spec != s:
            raise ValueError("dense: expected True, False or the DenseCheck of this table's spec")
        mq, rq = check.mu_q, check.roughness_q
        got = result._at_quantities(mq, rq)
        dense_err = np.abs(got - check.value).reshape(-1, nc)
        worst_dense = dense_err.max(axis=0).tolist()
        worst_interior = _worst_inside(s, mq, rq, dense_err).tolist()
        dense_se = check.stderr.reshape(-1, nc).max(axis=0).tolist()
        points = int(mq.size)
        off = np.abs(result._at_quantities(mq, rq, np.float32) - got).reshape(-1, nc).max(0)
        rounding = np.maximum(rounding, off)
    return dataclasses.replace(
        result,
        worst_texels=err.max(axis=0).tolist(),
        rms_texels=np.sqrt((err**2).mean(axis=0)).tolist(),
        worst_between=between.tolist(),
        between_stderr=between_se.tolist(),
        worst_dense=worst_dense,
        dense_stderr=dense_se,
        dense_points=points,
        float32_worst=rounding.tolist(),
        worst_dense_interior=worst_interior,
        texel_stderr=lut.stderr.reshape(-1, nc).max(axis=0).tolist(),
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
    power = {"s": "u", "t": "v"}[out]
    return [
        f"{let} {out} = {fmin}({fmax}(({q} - {lo}) / {span}, 0.0{f}), 1.0{f});",
        f"{let} {power} = 2.0{f} * {out} - 1.0{f};",
    ]


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

    def horner(coefficients: np.ndarray) -> str:
        # Horner in v inside, in u outside: sum_i u^i (sum_j c_ij v^j).
        degree = coefficients.shape[0] - 1
        outer = []
        for i in range(degree + 1):
            coeffs = [coefficients[i, j] for j in range(degree + 1 - i)]
            inner = f"{coeffs[-1]:.9e}{lit}"
            for v in reversed(coeffs[:-1]):
                inner = f"({v:.9e}{lit} + v * {inner})"
            outer.append(inner)
        expr = outer[-1]
        for v in reversed(outer[:-1]):
            expr = f"({v} + u * {expr})"
        return expr

    for c in range(nc):
        expr = horner(result.coefficients[c])
        if result.den_coefficients is not None:
            expr = f"{expr} / {horner(result.den_coefficients[c])}"
        lines.append(f"{let} v{c} = {expr};")
        names.append(f"v{c}")
    header = [
        f"{name}: a {result.form} minimax fit of the {s.kind} table of {s.model}"
        " (brdf-rs; do not edit).",
        f"Table columns: {s.columns.describe(s.param)}.",
        f"Table rows: {s.rows.describe(s.param)}.",
        f"Returns the channels {', '.join(s.channel_names)} at mu = cos(theta_v) and {s.param}.",
    ]
    for c, ch in enumerate(s.channel_names):
        dense = (
            f", worst {result.worst_dense[c]:.3g} against {result.dense_points} integrals on a"
            f" dense grid (stderr up to {result.dense_stderr[c]:.2g}; float32 evaluation"
            f" within {result.float32_worst[c]:.2g} of float64); maximum error"
            f" {result.max_error[c]:.3g}, {result.max_error_interior[c]:.3g} between the first"
            " and last texels"
            if result.worst_dense
            else ""
        )
        header.append(
            f"Error {ch}: worst {result.worst_texels[c]:.3g} (RMS {result.rms_texels[c]:.3g})"
            f" against the texels, worst {result.worst_between[c]:.3g} against integrals"
            f" between them (their stderr up to {result.between_stderr[c]:.2g}){dense}."
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
