"""Plots of models, albedo tables and benchmark results (needs matplotlib: ``brdf-rs[plot]``).

Every function returns a :class:`matplotlib.figure.Figure` and, given ``path``, also saves
it there (PNG, SVG, PDF: matplotlib picks the format from the suffix). Figures are built
with matplotlib's object API (``Figure``, not ``pyplot``): no GUI backend is ever
selected, nothing is registered in pyplot's global figure list, so the module works the
same on a headless server, in a script and in a notebook (where a returned Figure shows
itself). Functions that draw one panel also take ``ax=`` to draw into your own axes.

- :func:`polar_lobe`: ``f(wi, wo)`` for ``wo`` in the plane of incidence, as a polar
  plot (like Disney's BRDF Explorer): light arriving from the left, mirror direction on
  the right.
- :func:`albedo_curves`: directional albedo ``R(mu)`` for several values of a parameter,
  with ±2 standard-error bands.
- :func:`table_heatmap`: an albedo or split-sum table as a heat map (a 1-D table as a
  curve).
- :func:`energy_compensation`: ``E(mu, alpha)`` and ``E_avg(alpha)`` of a microfacet model.
- :func:`lut_texels`: an engine LUT (:mod:`brdf_rs.lut`) as the engine samples it: each
  channel's decoded texels over the axes' quantities (a 3-D table's first, middle and
  last slices).
- :func:`convergence`: error against time (``benches/albedo_convergence.py`` results).
- :func:`spheres`: rendered images side by side with labels; :func:`render_sphere`
  renders one model on a sphere, :func:`render_glass_sphere` a transmitting one as a
  solid sphere on a checkerboard (neither needs matplotlib).
"""

from __future__ import annotations

import json
import logging
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, cast

import numpy as np
import numpy.typing as npt

from . import _albedo, _api, _atomic, _spec, _table
from ._optional import matplotlib as _matplotlib

if TYPE_CHECKING:  # pragma: no cover - typing only
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.projections.polar import PolarAxes

__all__ = [
    "albedo_curves",
    "convergence",
    "energy_compensation",
    "lut_texels",
    "polar_lobe",
    "render_glass_sphere",
    "render_sphere",
    "spheres",
    "table_heatmap",
]

log = logging.getLogger("brdf_rs")

#: Line colours for the R, G, B channels when they differ.
_RGB_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")

#: Rec. 709 luminance weights: one curve for a coloured lobe.
_LUMINANCE = np.array([0.2126, 0.7152, 0.0722])

#: Axis labels (with units) for a table's axes.
_AXIS_LABELS = {
    "mu": "μ = cos θi",
    "alpha": "α (roughness)",
    "p": "p (exponent)",
    "phi": "φ (rad)",
    "eta": "η (index of refraction)",
    "sigma": "σ (rad)",
}

#: Default figure sizes (inches): readable at 100 dpi with 9-11 pt text.
LOBE_SIZE = (6.4, 3.2)
CURVES_SIZE = (6.4, 3.8)


def _figure(
    width: float, height: float, layout: Literal["constrained"] | None = "constrained"
) -> Figure:
    _matplotlib()
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout=layout)


def _finish(fig: Figure, path: str | os.PathLike[str] | None, dpi: float) -> Figure:
    if path is not None:
        path = Path(path)
        # The format by the suffix (or matplotlib's default), written atomically: an open
        # file, so matplotlib adds no suffix of its own to the name.
        import matplotlib

        fmt = path.suffix[1:].lower() or matplotlib.rcParams["savefig.format"]
        with _atomic.atomic_write(path) as tmp, open(tmp, "wb") as f:
            fig.savefig(f, dpi=dpi, format=fmt)
        log.debug("wrote %s", path)
    return fig


def _target(ax: Axes | None, width: float, height: float, **subplot: Any) -> tuple[Figure, Axes]:
    if ax is not None:
        return ax.get_figure(), ax  # type: ignore[return-value]
    fig = _figure(width, height)
    return fig, fig.add_subplot(**subplot)


def _distinct_channels(rgb: np.ndarray) -> bool:
    """Whether the three channels of ``(..., 3)`` values differ anywhere."""
    return not (
        np.array_equal(rgb[..., 0], rgb[..., 1]) and np.array_equal(rgb[..., 0], rgb[..., 2])
    )


# ------------------------------------------------------------------------ polar lobe


def polar_lobe(
    model: str,
    theta_i: float | Sequence[float] = 45.0,
    *,
    cosine: bool = False,
    resolution: int = 1441,
    tangent: Sequence[float] | None = None,
    normalization: str = "approximate",
    channel: int | str | None = None,
    ax: Axes | None = None,
    path: str | os.PathLike[str] | None = None,
    dpi: float = 100,
    size: tuple[float, float] = LOBE_SIZE,
    **params: Any,
) -> Figure:
    """Polar plot of the lobe ``f(wi, wo)`` for ``wo`` in the plane of incidence.

    The light arrives from the left at ``theta_i`` degrees from the normal (``wi`` =
    (−sin θi, 0, cos θi), drawn as a dotted line); ``wo`` = (sin θo, 0, cos θo) sweeps θo
    from −90° to 90°, so the mirror direction is at +θi. The radius is ``f`` in 1/sr
    (family A) or the shading term ``s`` (family B, which includes the light's cosine;
    no unit); ``cosine=True`` multiplies by cos θo (the reflected radiance under a unit
    irradiance, as in BRDF Explorer's "multiply by N·L" toggle, here for the outgoing
    side). One curve per ``theta_i``: the value itself when the three channels agree,
    else their luminance ``0.2126 R + 0.7152 G + 0.0722 B`` (the axis label says so);
    ``channel`` picks 0, 1 or 2 (R, G, B) instead, or ``"rgb"`` draws all three.

    Args:
        model: any model of ``brdf_rs.models()``.
        theta_i: incidence angle(s) in degrees, in [0, 90].
        resolution: outgoing angles per curve.
        tangent: the tangent for models that need one (default (1, 0, 0), in the plane).
        **params: the model's parameters.
    """
    angles = np.atleast_1d(np.asarray(theta_i, dtype=np.float64))
    if angles.ndim != 1 or angles.size == 0 or not np.all((angles >= 0) & (angles <= 90)):
        raise ValueError(f"theta_i: expected angles in degrees from 0 to 90, got {theta_i!r}")
    if isinstance(resolution, bool) or not isinstance(resolution, int) or resolution < 3:
        raise ValueError(f"resolution: expected an integer of at least 3, got {resolution!r}")
    if channel not in (None, 0, 1, 2, "rgb") or isinstance(channel, bool):
        raise ValueError(f"channel: expected 0, 1, 2 (R, G, B), 'rgb' or None, got {channel!r}")
    specs = _spec.specs()
    if model in specs and specs[model]["tangent"] and tangent is None:
        tangent = (1.0, 0.0, 0.0)
    # Cell midpoints: never exactly grazing, where 1/mu_o factors (ward) blow up.
    theta_o = np.radians(-90.0 + 180.0 * (np.arange(resolution) + 0.5) / resolution)
    wo = np.stack([np.sin(theta_o), np.zeros_like(theta_o), np.cos(theta_o)], axis=-1)
    curves = []
    for angle in angles:
        t = np.radians(angle)
        wi = np.array([-np.sin(t), 0.0, np.cos(t)])
        f = _api.eval(model, wi, wo, tangent=tangent, normalization=normalization, **params)
        if cosine:
            f = f * np.cos(theta_o)[:, None]
        curves.append(np.where(np.isfinite(f), f, np.nan))
    values = np.stack(curves)
    own_figure = ax is None
    if ax is None:
        # Placed by hand (the layout engines keep room for the whole circle): a polar
        # axes box of side 2r draws the half disc, r high, centred in it. The disc's
        # base sits 0.6 in above the bottom (radial ticks and their label), 0.7 in are
        # kept above it for the angle labels and the title, the legend goes to its right.
        fig = _figure(*size, layout=None)
        width, height = size
        radius = min(height - 1.3, 0.33 * width)  # inches
        bottom = 0.6 - radius / 2
        box = (0.4 / width, bottom / height, 2 * radius / width, 2 * radius / height)
        axes: Axes = fig.add_axes(box, projection="polar")
    else:
        fig, axes = ax.get_figure(), ax  # type: ignore[assignment]
    ax = cast("PolarAxes", axes)
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_thetamin(-90)
    ax.set_thetamax(90)
    distinct = _distinct_channels(values)
    which = ""
    if channel == "rgb":
        shown = values
    elif channel is not None:
        c = int(channel)
        shown, which = values[..., c : c + 1], f", {'RGB'[c]}"
    elif distinct:
        shown, which = values @ _LUMINANCE[:, None], ", luminance of RGB"
    else:
        shown = values[..., :1]
    styles = ["-", "--", ":", "-."]
    cycle = [f"C{k}" for k in range(10)]
    for k, (angle, f) in enumerate(zip(angles, shown, strict=True)):
        label = f"θi = {angle:g}°"
        if f.shape[-1] == 3:
            for c in range(3):
                ax.plot(
                    theta_o,
                    f[:, c],
                    styles[k % len(styles)],
                    color=_RGB_COLOURS[c],
                    lw=1.5,
                    label=f"{label}, {'RGB'[c]}",
                )
        else:
            ax.plot(theta_o, f[:, 0], color=cycle[k % len(cycle)], lw=1.8, label=label)
    top = float(np.nanmax(shown)) if np.any(np.isfinite(shown)) else 1.0
    top = top if top > 0 else 1.0
    ax.set_rmax(top * 1.05)
    rgb = shown.shape[-1] == 3
    for k, angle in enumerate(angles):
        colour = "grey" if rgb else cycle[k % len(cycle)]
        ax.plot([-np.radians(angle)] * 2, [0, top * 1.05], ":", color=colour, lw=1.2)
    family = specs[model]["family"] if model in specs else "A"
    quantity = "s(l, v)" if family == "B" else "f(wi, wo)"
    if cosine:
        quantity += "·cos θo"
    unit = "no unit" if family == "B" else "1/sr"
    single = f", θi = {angles[0]:g}°" if len(angles) == 1 else ""
    title = f"{model}: {quantity}{single}"
    if own_figure:  # above the half disc (the axes box reaches beyond the figure)
        centre = box[0] + box[2] / 2
        fig.text(centre, 1 - 0.1 / size[1], title, ha="center", va="top", fontsize=11)
    else:
        ax.set_title(title, fontsize=11, pad=6)
    ax.tick_params(labelsize=9, pad=2)
    ax.set_thetagrids(np.arange(-90, 91, 30), [f"{t}°" for t in np.arange(-90, 91, 30)])
    from matplotlib.ticker import MaxNLocator

    ax.yaxis.set_major_locator(MaxNLocator(4))
    ax.yaxis.set_major_formatter("{x:.3g}")
    ax.set_rlabel_position(-90)
    # The radial axis runs along the left horizon (the −90° line): its label below it.
    ax.annotate(
        f"{quantity.split('(')[0]}{which} ({unit})",
        xy=(-np.pi / 2, top * 0.55),
        xytext=(0, -20),
        textcoords="offset points",
        ha="center",
        va="top",
        fontsize=9,
        annotation_clip=False,
    )
    from matplotlib.lines import Line2D

    if rgb:  # one entry per angle (line style) and per channel (colour)
        handles = [
            Line2D([], [], color="0.3", ls=styles[k % len(styles)], label=f"θi = {a:g}°")
            for k, a in enumerate(angles)
        ] + [Line2D([], [], color=_RGB_COLOURS[c], label="RGB"[c]) for c in range(3)]
    else:
        handles = [
            Line2D([], [], color=cycle[k % len(cycle)], lw=1.8, label=f"θi = {a:g}°")
            for k, a in enumerate(angles)
        ]
    handles.append(Line2D([], [], color="grey", ls=":", lw=1.2, label="light direction"))
    # Beside the half disc, in the space at its upper right: it covers no curve.
    legend: dict[str, Any] = {"fontsize": 9, "frameon": False, "handlelength": 1.8}
    if own_figure:
        fig.legend(handles=handles, loc="upper right", bbox_to_anchor=(0.99, 0.86), **legend)
    else:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.0, 1.0), **legend)
    return _finish(fig, path, dpi)


# ---------------------------------------------------------------------- albedo curves


def _curve_channel(value: np.ndarray, channel: int | None) -> tuple[np.ndarray, str]:
    if channel is not None:
        if channel not in (0, 1, 2):
            raise ValueError(f"channel: expected 0, 1 or 2 (R, G, B), got {channel!r}")
        return value[..., channel], f" ({'RGB'[channel]})"
    if _distinct_channels(value):
        return value.mean(axis=-1), " (mean of R, G, B)"
    return value[..., 0], ""


def albedo_curves(
    model: str,
    param: str,
    values: Sequence[float] | np.ndarray,
    *,
    mu: Sequence[float] | np.ndarray | None = None,
    samples: int = 4096,
    tol: float | None = None,
    seed: int = 0,
    channel: int | None = None,
    ax: Axes | None = None,
    path: str | os.PathLike[str] | None = None,
    dpi: float = 100,
    size: tuple[float, float] = CURVES_SIZE,
    log: bool | None = None,
    **params: Any,
) -> Figure:
    """Directional albedo ``R(mu)`` of a family-A model, one curve per value of ``param``.

    Each curve is computed by :func:`brdf_rs.albedo_table` (with its honest standard
    errors, drawn as ±2σ bands); a dotted line marks R = 1 (energy conservation).
    ``channel`` picks R, G or B; by default grey tables show their one value and coloured
    ones the mean of the three channels. The albedo axis is logarithmic when ``log`` is
    true, or by default when the curves span more than a factor of 30 (un-normalized
    Phong at grazing incidence, next to curves below 1).

    Args:
        model: a family-A model.
        param: the parameter that varies (e.g. ``"p"``, ``"alpha"``, ``"sigma"``).
        values: its values, one curve each.
        mu: incidences (default 48 points from 0.02 to 1).
        **params: the other parameters, fixed.
    """
    if param == "mu":
        raise ValueError("param: mu is the curve's x axis; choose a model parameter")
    mu_axis = np.linspace(0.02, 1.0, 48) if mu is None else np.asarray(mu, dtype=np.float64)
    table = _albedo.albedo_table(
        model,
        {param: values, "mu": mu_axis},
        samples=samples,
        tol=tol,
        seed=seed,
        **params,
    )
    value, suffix = _curve_channel(table.value, channel)
    stderr, _ = _curve_channel(table.stderr, channel)
    fig, ax = _target(ax, *size)
    for k, v in enumerate(table.axes[param]):
        colour = f"C{k % 10}"
        ax.plot(mu_axis, value[k], color=colour, lw=1.8, label=f"{param} = {v:.4g}")
        ax.fill_between(
            mu_axis, value[k] - 2 * stderr[k], value[k] + 2 * stderr[k], color=colour, alpha=0.25
        )
    ax.axhline(1.0, color="grey", ls=":", lw=1.0, label="R = 1")
    ax.set_xlim(0, 1)
    positive = value[value > 0]
    if log is None:
        log = bool(positive.size and positive.max() > 30 * positive.min())
    if log:
        ax.set_yscale("log")
        ax.set_ylim(bottom=0.5 * float(positive.min()) if positive.size else None)
        ax.grid(True, which="minor", lw=0.2)
    else:
        ax.set_ylim(bottom=0)
    ax.set_xlabel("μ = cos θi", fontsize=10)
    ax.set_ylabel(f"directional albedo R(μ){suffix}" + (", log" if log else ""), fontsize=10)
    ax.set_title(f"{model}: directional albedo", fontsize=11)
    ax.tick_params(labelsize=9)
    # Outside the axes, to the right: it covers no curve.
    ax.legend(fontsize=9, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.grid(True, lw=0.3)
    return _finish(fig, path, dpi)


# ----------------------------------------------------------------------------- tables


def _edges(coords: np.ndarray) -> tuple[np.ndarray, bool]:
    """Cell edges around coordinates (in log space when they are geometric)."""
    c = np.asarray(coords, dtype=np.float64)
    geometric = bool(
        c.size > 2
        and np.all(c > 0)
        and np.allclose(np.diff(np.log(c)), np.log(c[1] / c[0]), rtol=1e-6)
        and not np.allclose(np.diff(c), c[1] - c[0], rtol=1e-6)
    )
    x = np.log(c) if geometric else c
    if x.size == 1:
        edges = np.array([x[0] - 0.5, x[0] + 0.5])
    else:
        mid = 0.5 * (x[1:] + x[:-1])
        edges = np.concatenate([[2 * x[0] - mid[0]], mid, [2 * x[-1] - mid[-1]]])
    return (np.exp(edges) if geometric else edges), geometric


def _panels(table: _table.Table, channel: int | None) -> list[tuple[int, str]]:
    quantity = str(table.meta.get("quantity", ""))
    sheen = table.meta.get("sheen")
    cloth = None if sheen is None else f"cloth ({sheen})"
    if channel is not None:
        if channel not in (0, 1, 2):
            raise ValueError(f"channel: expected 0, 1 or 2, got {channel!r}")
        third = "(zero)" if cloth is None else cloth
        names = ("scale A", "bias B", third) if quantity.startswith("split-sum") else "RGB"
        return [(channel, names[channel])]
    if quantity.startswith("split-sum"):
        return [(0, "scale A"), (1, "bias B")] + ([] if cloth is None else [(2, cloth)])
    if _distinct_channels(table.value):
        return [(0, "R"), (1, "G"), (2, "B")]
    return [(0, "albedo")]


def table_heatmap(
    table: _table.Table,
    *,
    channel: int | None = None,
    ax: Axes | None = None,
    path: str | os.PathLike[str] | None = None,
    dpi: float = 100,
    cmap: str = "viridis",
) -> Figure:
    """A 2-D table as a heat map (first axis across, second up; a log axis where the
    coordinates are geometric), a 1-D table as a curve with its ±2σ band.

    A split-sum (DFG) table shows its scale A and bias B side by side (and its cloth term
    when it has one); an albedo table
    with grey parameters shows one panel, a coloured one R, G and B. ``channel`` picks
    one panel (and is required with ``ax=`` when there would be several).
    """
    if not isinstance(table, _table.Table):
        raise TypeError(f"table: expected a brdf_rs.Table, got {type(table).__name__}")
    names = list(table.axes)
    if len(names) not in (1, 2):
        raise ValueError(
            f"table: can draw 1-D and 2-D tables; this one has {len(names)} axes"
            f" ({', '.join(names)})"
        )
    panels = _panels(table, channel)
    if ax is not None and len(panels) > 1:
        raise ValueError(f"ax: this table has {len(panels)} panels; give channel= to draw one")
    model = table.meta.get("model", "")
    if ax is not None:
        fig, axes = ax.get_figure(), [ax]
    else:
        fig = _figure(4.8 * len(panels), 3.8)
        axes = [fig.add_subplot(1, len(panels), k + 1) for k in range(len(panels))]
    x_name = names[0]
    x = table.axes[x_name]
    for a, (c, label) in zip(axes, panels, strict=True):
        if len(names) == 1:
            v, se = table.value[:, c], table.stderr[:, c]
            a.plot(x, v, lw=1.4)
            a.fill_between(x, v - 2 * se, v + 2 * se, alpha=0.25)
            a.set_ylabel(label, fontsize=10)
            _, geometric = _edges(x)
            if geometric:
                a.set_xscale("log")
            a.grid(True, lw=0.3)
        else:
            y_name = names[1]
            xe, x_log = _edges(x)
            ye, y_log = _edges(table.axes[y_name])
            mesh = a.pcolormesh(xe, ye, table.value[:, :, c].T, cmap=cmap, shading="flat")
            bar = fig.colorbar(mesh, ax=a, shrink=0.9)  # type: ignore[union-attr]
            bar.set_label("directional albedo R" if label == "albedo" else label, fontsize=10)
            if x_log:
                a.set_xscale("log")
            if y_log:
                a.set_yscale("log")
        a.set_xlabel(_AXIS_LABELS.get(x_name, x_name), fontsize=10)
        if len(names) == 2:
            a.set_ylabel(_AXIS_LABELS.get(names[1], names[1]), fontsize=10)
        a.set_title(f"{model} {label}".strip(), fontsize=11)
    return _finish(fig, path, dpi)  # type: ignore[arg-type]


#: Axis labels of a LUT's quantities (:data:`brdf_rs.lut.QUANTITIES`).
_LUT_QUANTITY_LABELS = {
    "mu": "n·v",
    "sqrt_mu": "sqrt(n·v)",
    "alpha": "α",
    "perceptual": "perceptual roughness r (α = r²)",
    "eta": "η",
    "eta_z": "z (η = (1 + z²)/(1 − z²))",
    "eta_z_inside": "z (η = (1 − z²)/(1 + z²))",
    "exponent": "exponent",
    "exponent_z": "z (exponent = 5(1 − z)/z)",
}


def lut_texels(
    table: Any,
    *,
    path: str | os.PathLike[str] | None = None,
    dpi: float = 100,
    cmap: str = "viridis",
) -> Figure:
    """An engine LUT (a :class:`brdf_rs.lut.Lut`) as the engine reads it: one panel per
    channel of its decoded texels (what the stored format decodes to), each texel a cell
    centred on its sample position in the axis quantity (texel centres or range ends, as
    the spec places them), columns across and rows up (row 0 at the bottom). A 3-D
    table's panels are its first, middle and last slices, one row of panels per slice,
    titled with the slice's quantity."""
    from . import lut as _lut

    if not isinstance(table, _lut.Lut):
        raise TypeError(f"table: expected a brdf_rs.lut.Lut, got {type(table).__name__}")
    spec = table.spec
    names = spec.channel_names
    decoded = np.asarray(table.decoded, dtype=np.float64)
    if spec.layers is None:
        slices: list[tuple[np.ndarray, str]] = [(decoded, "")]
    else:
        layers = spec.layers
        q = layers.positions()
        value = layers.physical(q)
        role = "η" if layers.role == "eta" else "exponent"
        slices = [
            (
                decoded[k],
                f" at {role} = {value[k]:.4g}"
                + (f" (z = {q[k]:.4g})" if layers.quantity.endswith(("_z", "_inside")) else ""),
            )
            for k in sorted({0, layers.size // 2, layers.size - 1})
        ]
    fig = _figure(max(4.2 * len(names), 5.6), 3.4 * len(slices))
    xq, yq = spec.columns.positions(), spec.rows.positions()
    xe, _ = _edges(xq)
    ye, _ = _edges(yq)
    for i, (image, where) in enumerate(slices):
        for c, name in enumerate(names):
            a = fig.add_subplot(len(slices), len(names), i * len(names) + c + 1)
            mesh = a.pcolormesh(xe, ye, image[:, :, c], cmap=cmap, shading="flat")
            fig.colorbar(mesh, ax=a, shrink=0.9)
            a.set_xlabel(_LUT_QUANTITY_LABELS[spec.columns.quantity], fontsize=9)
            a.set_ylabel(_LUT_QUANTITY_LABELS[spec.rows.quantity], fontsize=9)
            a.set_title(f"{name}{where}", fontsize=10)
            a.tick_params(labelsize=8)
    fig.suptitle(
        f"{spec.kind} of {spec.model}: {' x '.join(str(s) for s in spec.shape[::-1])}"
        f" {spec.format}",
        fontsize=11,
    )
    return _finish(fig, path, dpi)


def energy_compensation(
    result: _albedo.EnergyCompensation,
    *,
    path: str | os.PathLike[str] | None = None,
    dpi: float = 100,
) -> Figure:
    """Two panels: ``E(mu, alpha)`` as a heat map, and ``E_avg(alpha)`` with the energy
    ``1 − E_avg`` that single scattering loses (what the compensation lobe restores)."""
    if not isinstance(result, _albedo.EnergyCompensation):
        raise TypeError(
            f"result: expected a brdf_rs.EnergyCompensation, got {type(result).__name__}"
        )
    if result.eta is not None:
        raise ValueError(
            f"result: the plot draws E(mu, alpha) tables; {result.model}'s is over (mu, alpha,"
            f" eta): plot a slice (e[:, :, k]) yourself"
        )
    fig = _figure(10.0, 3.8)
    left, right = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    xe, x_log = _edges(result.mu)
    ye, y_log = _edges(result.alpha)
    mesh = left.pcolormesh(xe, ye, result.e.T, cmap="viridis", shading="flat", vmin=0, vmax=1)
    fig.colorbar(mesh, ax=left, shrink=0.9).set_label("E(μ, α)", fontsize=10)
    if y_log:
        left.set_yscale("log")
    if x_log:
        left.set_xscale("log")
    # A lobe that is not reciprocal has its E taken from the view (the albedo seen from
    # the view, docs/models.md), so μ is the view's cosine there.
    view = bool(_spec.specs()[result.model]["view_albedo_closed_form"])
    left.set_xlabel("μ = cos θo (view)" if view else "μ = cos θi", fontsize=10)
    left.set_ylabel("α (roughness)", fontsize=10)
    left.set_title(f"{result.model}: single-scattering albedo E(μ, α), F = 1", fontsize=11)
    se = result.e_avg_stderr
    right.plot(result.alpha, result.e_avg, lw=1.4, label="E_avg(α)")
    right.fill_between(result.alpha, result.e_avg - 2 * se, result.e_avg + 2 * se, alpha=0.25)
    right.plot(result.alpha, 1 - result.e_avg, lw=1.4, ls="--", label="1 − E_avg (lost)")
    right.set_xlabel("α (roughness)", fontsize=10)
    right.set_ylabel("energy fraction", fontsize=10)
    right.set_ylim(0, 1.02)
    right.grid(True, lw=0.3)
    right.legend(fontsize=9, loc="center left")
    right.set_title("cosine-weighted average albedo E_avg(α)", fontsize=11)
    return _finish(fig, path, dpi)


# ------------------------------------------------------------------------ convergence


def _convergence_tables(results: Any) -> dict[str, dict[str, list[dict[str, float]]]]:
    if isinstance(results, (str, os.PathLike)):
        with open(results, encoding="utf-8") as f:
            results = json.load(f)
    if isinstance(results, Mapping) and "results" in results:
        results = results["results"]
    if not isinstance(results, Mapping) or not results:
        raise ValueError(
            "results: expected {table: {method: [points]}}, {method: [points]} or the"
            " JSON that benches/albedo_convergence.py writes"
        )
    first = next(iter(results.values()))
    tables = {"": results} if isinstance(first, Sequence) else results
    for name, methods in tables.items():
        if not isinstance(methods, Mapping):
            raise ValueError(f"results[{name!r}]: expected {{method: [points]}}")
        for method, points in methods.items():
            if not isinstance(points, Sequence) or not points:
                raise ValueError(f"results[{name!r}][{method!r}]: expected a list of points")
            for point in points:
                if "seconds" not in point or not ("rms" in point or "error" in point):
                    raise ValueError(
                        f"results[{name!r}][{method!r}]: each point needs 'seconds' and"
                        f" 'rms' (or 'error'); got keys {sorted(point)}"
                    )
    return dict(tables)


def convergence(
    results: Any,
    *,
    targets: Sequence[float] = (),
    title: str | None = None,
    path: str | os.PathLike[str] | None = None,
    dpi: float = 100,
) -> Figure:
    """Error against wall time, log-log, one panel per table and one line per method.

    Args:
        results: ``{table: {method: [{"seconds", "rms"}, ...]}}`` (one table may drop
            the outer level), the JSON dict ``benches/albedo_convergence.py`` writes, or
            the path of that JSON file. ``"error"`` may stand for ``"rms"``.
        targets: error levels to mark with horizontal lines.
    """
    tables = _convergence_tables(results)
    fig = _figure(max(7.0, 5.5 * len(tables)), 4.8 + (0.3 if title and "\n" in title else 0))
    axes = [fig.add_subplot(1, len(tables), k + 1) for k in range(len(tables))]
    for ax, (name, methods) in zip(axes, tables.items(), strict=True):
        for label, points in methods.items():
            pts = sorted((p["seconds"], p.get("rms", p.get("error"))) for p in points)
            style = "--" if "NumPy" in label else ("-o" if "adaptive" in label else "-")
            xs, ys = zip(*pts, strict=True)
            ax.loglog(xs, ys, style, label=label, markersize=3)
        for target in targets:
            ax.axhline(target, color="grey", lw=0.5)
        ax.set_xlabel("wall time (s)", fontsize=10)
        ax.set_ylabel("RMS error over the table", fontsize=10)
        if name:
            ax.set_title(name, fontsize=11)
        ax.grid(True, which="both", lw=0.3)
    # One legend for every panel, below them: it covers no line.
    handles, labels = axes[0].get_legend_handles_labels()
    for ax in axes[1:]:
        for h, label in zip(*ax.get_legend_handles_labels(), strict=True):
            if label not in labels:
                handles.append(h)
                labels.append(label)
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncol=min(len(labels), 3 if len(tables) > 1 else 2),
        fontsize=9,
        frameon=False,
    )
    if title:
        fig.suptitle(title, fontsize=12)
    return _finish(fig, path, dpi)


# ---------------------------------------------------------------------------- spheres


def _display_image(name: str, image: Any) -> np.ndarray:
    a = np.asarray(image)
    if a.ndim != 3 or a.shape[2] not in (3, 4):
        raise ValueError(f"{name}: expected an (H, W, 3) image, got shape {a.shape}")
    if a.dtype == np.uint8:
        return a
    if a.dtype.kind != "f":
        raise TypeError(f"{name}: expected float (0..1) or uint8 pixels, got {a.dtype}")
    return np.clip(np.nan_to_num(a.astype(np.float32)), 0.0, 1.0)


def spheres(
    images: Sequence[Any],
    labels: Sequence[str] | None = None,
    *,
    ncols: int | None = None,
    title: str | None = None,
    path: str | os.PathLike[str] | None = None,
    dpi: float = 100,
    panel_inches: float = 1.8,
) -> Figure:
    """Rendered images (``(H, W, 3)``, float display values in [0, 1] or uint8) side by
    side, each labelled below; ``ncols`` wraps them into rows."""
    if len(images) == 0:
        raise ValueError("images: expected at least one image")
    if labels is not None and len(labels) != len(images):
        raise ValueError(f"labels: expected {len(images)} labels, got {len(labels)}")
    pictures = [_display_image(f"images[{k}]", im) for k, im in enumerate(images)]
    cols = len(pictures) if ncols is None else max(1, min(int(ncols), len(pictures)))
    rows = -(-len(pictures) // cols)
    fig = _figure(panel_inches * cols, (panel_inches + 0.25) * rows + (0.3 if title else 0))
    for k, picture in enumerate(pictures):
        ax = fig.add_subplot(rows, cols, k + 1)
        ax.imshow(picture, interpolation="nearest")
        ax.set_xticks([])
        ax.set_yticks([])
        for spine in ax.spines.values():
            spine.set_visible(False)
        if labels is not None:
            ax.set_xlabel(labels[k], fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    return _finish(fig, path, dpi)


def render_sphere(
    model: str,
    *,
    size: int = 160,
    tonemap: str = "aces",
    exposure: float = 0.0,
    base: float = 0.0,
    **params: Any,
) -> npt.NDArray[np.float32]:
    """Renders one model on a sphere: a ``(size, size, 3)`` float32 display image.

    Orthographic view down −z, a white key light from the upper right front and a fill
    light (30%) from the left. A family-A model is the sphere's material; a family-B
    term goes in its diffuse or specular slot (``kajiya_kay`` with meridian fibres), and
    ``base`` adds a grey ``lambert_shading`` diffuse under a specular-only term so the
    sphere's shape shows. Light intensities are π (family A) and 1 (family B), so a
    white Lambert surface looks the same in both families.
    """
    from . import scene as scenes

    specs = _spec.specs()
    if model not in specs:
        raise ValueError(f"model: unknown model {model!r}; known models: {', '.join(specs)}")
    family = specs[model]["family"]
    term = {"model": model, **params}
    material: dict[str, Any]
    if family == "A":
        material = term
    elif specs[model]["scene_slot"] == "specular":
        material = {"specular": term}
        if base > 0:
            plain = _spec.tool_defaults()["plain_diffuse"]
            material["diffuse"] = {"model": plain, "kd": float(base)}
    else:
        material = {"diffuse": term}
    scale = np.pi if family == "A" else 1.0
    scene = {
        "camera": {
            "type": "orthographic",
            "position": [0, 0, 10],
            "height": 2.2,
            "resolution": [int(size), int(size)],
        },
        "materials": {model: material},
        "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.0, "material": model}],
        "lights": [
            {"type": "directional", "direction": [-1, -1, -1.2], "intensity": scale},
            {"type": "directional", "direction": [1, 0.3, -0.5], "intensity": 0.3 * scale},
        ],
        "output": {"tonemap": tonemap, "exposure": exposure},
    }
    return scenes.render(scene)


def render_glass_sphere(
    model: str,
    *,
    size: int = 160,
    samples: int = 64,
    bounces: int = 12,
    seed: int = 0,
    furnace: bool = False,
    tonemap: str = "aces",
    exposure: float = 0.0,
    **params: Any,
) -> npt.NDArray[np.float32]:
    """Renders a transmitting model (a rough dielectric) as a solid sphere on a
    checkerboard: a ``(size, size, 3)`` float32 display image.

    The picture users expect of glass, which the scan-line scenes cannot draw (they shade
    reflection only): each pixel averages ``samples`` paths traced with the model's own
    :func:`brdf_rs.sample`, reflecting off or refracting through the sphere's surface
    (whose normal points out, so ``eta`` is the sphere's index relative to the air) up
    to ``bounces`` times; a path that leaves the sphere ends on the floor (a
    checkerboard, its own light source) or in the sky (a gradient, brightest at the
    horizon); one still inside after ``bounces`` scatterings adds nothing. Perspective
    view from above the floor; no light sources, so no shadows or caustics.
    ``furnace=True`` replaces floor and sky by a uniform white environment of radiance 1
    (a white furnace): a sphere that neither loses nor adds energy disappears into it,
    and how dark it looks is the energy its model loses (with ``tonemap="none"`` the
    pixels are the radiance itself).

    A sample's weight is ``f(wo, wi)·|cos|/pdf`` with ``wi`` toward the camera: ``f``
    from the light's direction ``wo`` to the viewer, by the reciprocity the dielectrics
    obey (``f(wi, wo)/eta_o² = f(wo, wi)/eta_i²``). ``eta`` is a scalar here (one
    sphere), the other parameters as :func:`brdf_rs.sample` takes them. Deterministic
    for a given ``seed``.
    """
    from . import _images, _sampling

    specs = _spec.specs()
    if model not in specs:
        raise ValueError(f"model: unknown model {model!r}; known models: {', '.join(specs)}")
    if not specs[model]["transmission"]:
        raise ValueError(f"model: {model!r} does not transmit; use render_sphere")
    size, samples, bounces = (
        _positive_int("size", size),
        _positive_int("samples", samples),
        _positive_int("bounces", bounces),
    )
    defaults = {p["name"]: p["default"] for p in specs[model]["params"]}
    eta = np.asarray(params.get("eta", defaults.get("eta", 1.0)), dtype=np.float64)
    if eta.ndim != 0:
        raise ValueError(f"eta: expected a scalar (one sphere), got shape {eta.shape}")
    pixels = size * size
    # Two streams: the pixels' jitter does not depend on what the paths do.
    jitter_rng, path_rng = (np.random.default_rng([int(seed), k]) for k in (0, 1))
    image = np.zeros((pixels, 3))
    for _ in range(samples):
        o, d = _glass_camera(size, jitter_rng)
        weight = np.ones((pixels, 3))
        alive = np.arange(pixels)
        for _ in range(bounces):
            t = _sphere_hit(o, d)
            gone = ~np.isfinite(t)
            image[alive[gone]] += weight[gone] * _backdrop(o[gone], d[gone], furnace)
            alive, o, d, weight, t = alive[~gone], o[~gone], d[~gone], weight[~gone], t[~gone]
            if alive.size == 0:
                break
            p = o + t[:, None] * d
            n = p - _GLASS_CENTRE  # radius 1
            n /= np.linalg.norm(n, axis=1, keepdims=True)
            wi = -d
            u = path_rng.random((alive.size, 2))
            wo, w, _ = _sampling.sample(model, wi, u, n, **params)
            cos_i, cos_o = np.einsum("ij,ij->i", wi, n), np.einsum("ij,ij->i", wo, n)
            # f(wo, wi) = f(wi, wo)·(eta_i/eta_o)²: each direction's medium's index.
            ratio = np.where(cos_i > 0, 1.0, eta) / np.where(cos_o > 0, 1.0, eta)
            weight = weight * w * (ratio * ratio)[:, None]
            keep = np.any(weight > 0, axis=1)
            alive, p, n, d, weight = alive[keep], p[keep], n[keep], wo[keep], weight[keep]
            # Leave the surface on the side the new direction points to.
            side = np.sign(np.einsum("ij,ij->i", d, n))
            o = p + (1e-9 * side)[:, None] * n
    linear = (image / samples).reshape(size, size, 3)
    return _images.tonemap(linear, tonemap, exposure)


#: The glass sphere's scene: a unit sphere resting on the floor y = 0, seen from above
#: the floor with a 40° field of view.
_GLASS_CENTRE = np.array([0.0, 1.0, 0.0])
_GLASS_EYE = np.array([0.0, 1.8, 4.8])
_GLASS_HALF_FOV = np.tan(np.radians(20.0))


def _glass_camera(size: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """One jittered camera ray per pixel (row-major, top row first): origins, unit
    directions."""
    forward = _GLASS_CENTRE - _GLASS_EYE + np.array([0.0, -0.1, 0.0])
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rows, cols = np.divmod(np.arange(size * size), size)
    jitter = rng.random((size * size, 2))
    x = (2 * (cols + jitter[:, 0]) / size - 1) * _GLASS_HALF_FOV
    y = (1 - 2 * (rows + jitter[:, 1]) / size) * _GLASS_HALF_FOV
    d = forward + x[:, None] * right + y[:, None] * up
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.broadcast_to(_GLASS_EYE, d.shape).copy(), d


def _sphere_hit(o: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Distance along each ray to the glass sphere's surface (the nearer crossing ahead
    of the origin), inf for a ray that misses it."""
    oc = o - _GLASS_CENTRE
    b = np.einsum("ij,ij->i", oc, d)
    disc = b * b - (np.einsum("ij,ij->i", oc, oc) - 1.0)
    root = np.sqrt(np.maximum(disc, 0.0))
    near, far = -b - root, -b + root
    t = np.where(near > 1e-9, near, far)
    return np.where((disc > 0) & (t > 1e-9), t, np.inf)


def _positive_int(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name}: expected a positive integer, got {value!r}")
    return int(value)


def _backdrop(o: np.ndarray, d: np.ndarray, furnace: bool) -> np.ndarray:
    """Radiance seen along rays that leave the sphere: a checkerboard floor at y = 0
    (squares of 2/3, fading into the horizon's haze far from the sphere) below a sky; or 1
    everywhere in the furnace."""
    if furnace:
        return np.ones_like(d)
    horizon, zenith = np.array([0.95, 0.93, 0.9]), np.array([0.15, 0.3, 0.7])
    sky = horizon + (zenith - horizon) * np.clip(d[:, 1], 0.0, 1.0)[:, None] ** 0.4
    down = d[:, 1] < -1e-12
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(down, -o[:, 1] / d[:, 1], 0.0)
    floor = down & (t > 0)
    q = o + np.where(floor, t, 0.0)[:, None] * d
    checker = (np.floor(q[:, 0] * 1.5) + np.floor(q[:, 2] * 1.5)) % 2
    albedo = np.where(checker[:, None] > 0, [0.8, 0.8, 0.75], [0.05, 0.05, 0.06])
    haze = np.exp(-np.hypot(q[:, 0], q[:, 2]) / 25.0)[:, None]
    ground = albedo * haze + horizon * (1 - haze)
    return np.asarray(np.where(floor[:, None], ground, sky))
