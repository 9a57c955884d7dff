"""How tables, albedos and energy checks show themselves in Jupyter.

``_repr_png_`` draws a small figure with matplotlib (a curve for one axis, a heat map for
two; the model and the largest standard error in the title) and returns ``None``, which
Jupyter skips, when matplotlib is missing or there is nothing to draw. ``_repr_html_``
embeds that figure under a one-line summary, or falls back to a compact HTML table of
the axes and each channel's range and largest standard error.
"""

from __future__ import annotations

import base64
import html
import io
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover - typing only
    from ._albedo import Albedo, Energy
    from ._table import Table

__all__ = [
    "albedo_html",
    "albedo_png",
    "channel_names",
    "energy_html",
    "energy_png",
    "table_html",
    "table_png",
]

#: How axes are labelled: the cosine of incidence and the azimuth get their meaning.
_AXIS_LABELS = {"mu": "μ = cos θi", "phi": "φ (radians)"}


def _figure(width: float, height: float) -> Any:
    """A matplotlib ``Figure`` (no pyplot, no global state), or None without matplotlib."""
    try:
        import matplotlib  # noqa: F401
        from matplotlib.figure import Figure
    except ImportError:
        return None
    return Figure(figsize=(width, height), layout="constrained")


def _png(fig: Any) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    return buffer.getvalue()


def _largest(stderr: Any) -> float:
    a = np.asarray(stderr, dtype=np.float64)
    return float(np.max(a)) if a.size else 0.0


def _channels(value: np.ndarray, names: Sequence[str]) -> list[tuple[int, str]]:
    """The channels worth drawing: one when all three are equal (a grey), else each
    named one (a split-sum table's unused third channel is left out)."""
    if all(np.array_equal(value[..., 0], value[..., k]) for k in (1, 2)):
        return [(0, "R = G = B" if names[0] == "R" else names[0])]
    return [(k, n) for k, n in enumerate(names) if not n.startswith("unused")]


def _log_scale(x: np.ndarray, label: str) -> bool:
    """A log axis for a parameter's positive coordinates spanning more than two decades
    (never for the angles: ``mu``, ``phi``)."""
    if label in _AXIS_LABELS.values() or label.startswith(("cell", "index")):
        return False
    return bool(x.size > 2 and np.all(x > 0) and x.max() / x.min() > 100)


def _monotonic(x: np.ndarray) -> bool:
    return bool(x.size == 1 or np.all(np.diff(x) > 0))


def _curve(
    ax: Any,
    x: np.ndarray,
    xlabel: str,
    value: np.ndarray,
    stderr: np.ndarray | None,
    channels: Sequence[tuple[int, str]],
    ylabel: str,
) -> None:
    colours = {"R": "tab:red", "G": "tab:green", "B": "tab:blue"}
    for k, name in channels:
        line = ax.plot(x, value[:, k], label=name, color=colours.get(name), lw=1.5)[0]
        if stderr is not None:
            band = 2 * stderr[:, k]
            ax.fill_between(
                x, value[:, k] - band, value[:, k] + band, alpha=0.25, lw=0, color=line.get_color()
            )
    if _log_scale(x, xlabel):
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    if len(channels) > 1:
        ax.legend(fontsize=8, loc="best")


def _heat_maps(
    fig: Any,
    axes: Mapping[str, np.ndarray],
    value: np.ndarray,
    channels: Sequence[tuple[int, str]],
    quantity: str,
) -> list[Any]:
    (ny, y), (nx, x) = axes.items()
    panels = fig.subplots(1, len(channels), squeeze=False)[0]
    for ax, (k, name) in zip(panels, channels, strict=True):
        if _monotonic(x) and _monotonic(y):
            mesh = ax.pcolormesh(x, y, value[..., k], shading="nearest", cmap="viridis")
            xlabel, ylabel = _AXIS_LABELS.get(nx, nx), _AXIS_LABELS.get(ny, ny)
            if _log_scale(x, xlabel):
                ax.set_xscale("log")
            if _log_scale(y, ylabel):
                ax.set_yscale("log")
            ax.set_xlabel(xlabel)
            ax.set_ylabel(ylabel)
        else:  # coordinates in no order: draw by index
            mesh = ax.imshow(value[..., k], origin="lower", aspect="auto", cmap="viridis")
            ax.set_xlabel(f"index of {nx}")
            ax.set_ylabel(f"index of {ny}")
        label = quantity if len(channels) == 1 and name == "R = G = B" else f"{quantity}, {name}"
        fig.colorbar(mesh, ax=ax, label=label)
    return list(panels)


def channel_names(meta: Mapping[str, Any]) -> list[str]:
    """What the three channels of a table hold: R, G, B, or a split-sum table's A, B (and
    its cloth term when it has a sheen model)."""
    if str(meta.get("quantity", "")).startswith("split-sum"):
        sheen = meta.get("sheen")
        return ["A (scale)", "B (bias)", "unused (0)" if sheen is None else f"cloth ({sheen})"]
    return ["R", "G", "B"]


def _quantity(meta: Mapping[str, Any]) -> str:
    """A table's quantity in a few words: the part of ``meta['quantity']`` before ':'."""
    text = str(meta.get("quantity") or "value")
    return text.split(":")[0].strip()


def _title(model: Any, stderr: Any, what: str = "") -> str:
    head = f"{model}" if model else "brdf-rs"
    return f"{head}{what}: largest standard error {_largest(stderr):.2g}"


# ------------------------------------------------------------------------------ Table


def table_png(table: Table) -> bytes | None:
    value = np.asarray(table.value)
    if value.ndim not in (2, 3) or value.shape[-1] != 3 or not np.all(np.isfinite(value)):
        return None
    fig = _figure(5.5 if value.ndim == 2 else 4.2 * _width(table), 3.4)
    if fig is None:
        return None
    channels = _channels(value, channel_names(table.meta))
    quantity = _quantity(table.meta)
    if value.ndim == 2:
        (name, x) = next(iter(table.axes.items()))
        ax = fig.subplots()
        stderr = np.asarray(table.stderr)
        _curve(ax, np.asarray(x), _AXIS_LABELS.get(name, name), value, stderr, channels, quantity)
        if stderr.any():
            ax.set_title("band: ±2 standard errors", fontsize=8, loc="right")
    else:
        _heat_maps(fig, table.axes, value, channels, quantity)
    fig.suptitle(_title(table.meta.get("model"), table.stderr), fontsize=10)
    return _png(fig)


def _width(table: Table) -> int:
    return len(_channels(np.asarray(table.value), channel_names(table.meta)))


def _summary_rows(value: np.ndarray, stderr: np.ndarray, names: Sequence[str]) -> list[str]:
    rows = []
    for k, name in enumerate(names):
        v, e = value[..., k], stderr[..., k]
        if name.startswith("unused"):
            continue
        rows.append(
            f"<tr><td>{html.escape(name)}</td><td>{np.min(v):.6g}</td><td>{np.max(v):.6g}</td>"
            f"<td>{np.max(e) if e.size else 0:.3g}</td></tr>"
        )
    return rows


def _html(summary: str, image: bytes | None, details: str) -> str:
    if image is not None:
        data = base64.b64encode(image).decode("ascii")
        return (
            f'<div class="brdf-rs"><div>{summary}</div>'
            f'<img src="data:image/png;base64,{data}" alt="{html.escape(summary, quote=True)}"/>'
            "</div>"
        )
    return f'<div class="brdf-rs"><div>{summary}</div>{details}</div>'


def _table_html(head: Sequence[str], rows: Sequence[str]) -> str:
    cells = "".join(f"<th>{html.escape(h)}</th>" for h in head)
    return f"<table><tr>{cells}</tr>{''.join(rows)}</table>"


def table_html(table: Table) -> str:
    value, stderr = np.asarray(table.value), np.asarray(table.stderr)
    model = html.escape(str(table.meta.get("model")))
    shape = " × ".join(f"{html.escape(k)}[{len(v)}]" for k, v in table.axes.items())
    summary = (
        f"<b>Table</b> <code>{model}</code>: {html.escape(_quantity(table.meta))} over"
        f" {shape}; largest standard error {_largest(stderr):.3g}"
    )
    axes = [
        f"<tr><td>{html.escape(k)}</td><td>{len(v)}</td><td>{np.min(v):.6g}</td>"
        f"<td>{np.max(v):.6g}</td></tr>"
        for k, v in table.axes.items()
    ]
    details = _table_html(["axis", "points", "from", "to"], axes) + _table_html(
        ["channel", "min", "max", "largest stderr"],
        _summary_rows(value, stderr, channel_names(table.meta)),
    )
    return _html(summary, table_png(table), details)


# ----------------------------------------------------------------------------- Albedo


def albedo_png(result: Albedo) -> bytes | None:
    value, stderr = np.asarray(result.value), np.asarray(result.stderr)
    if value.ndim not in (2, 3) or value.shape[-1] != 3 or not np.all(np.isfinite(value)):
        return None
    channels = _channels(value, ["R", "G", "B"])
    fig = _figure(5.5 if value.ndim == 2 else 4.2 * len(channels), 3.4)
    if fig is None:
        return None
    if value.ndim == 2:
        mu = None if result.mu is None else np.asarray(result.mu)
        use_mu = mu is not None and mu.shape == value.shape[:-1] and _monotonic(mu)
        x = mu if use_mu and mu is not None else np.arange(value.shape[0])
        label = _AXIS_LABELS["mu"] if use_mu else "cell"
        ax = fig.subplots()
        _curve(ax, x, label, value, stderr, channels, "directional albedo R")
        if stderr.any():
            ax.set_title("band: ±2 standard errors", fontsize=8, loc="right")
    else:
        axes = {"cell axis 0": np.arange(value.shape[0]), "cell axis 1": np.arange(value.shape[1])}
        _heat_maps(fig, axes, value, channels, "directional albedo R")
    fig.suptitle(_title(result.model, stderr), fontsize=10)
    return _png(fig)


def albedo_html(result: Albedo) -> str:
    value, stderr = np.asarray(result.value), np.asarray(result.stderr)
    cells = "×".join(str(n) for n in value.shape[:-1]) or "1"
    model = html.escape(str(result.model)) if result.model else "a model"
    summary = (
        f"<b>Albedo</b> of <code>{model}</code>: {cells} cells,"
        f" {int(np.sum(result.samples))} samples; largest standard error {_largest(stderr):.3g}"
    )
    details = _table_html(
        ["channel", "min", "max", "largest stderr"], _summary_rows(value, stderr, ["R", "G", "B"])
    )
    return _html(summary, albedo_png(result), details)


# ----------------------------------------------------------------------------- Energy


def energy_png(result: Energy) -> bytes | None:
    value, mu = np.asarray(result.value), np.asarray(result.mu)
    if value.ndim != 2 or value.shape != (mu.size, 3) or not np.all(np.isfinite(value)):
        return None
    fig = _figure(5.5, 3.4)
    if fig is None:
        return None
    ax = fig.subplots()
    _curve(
        ax,
        mu,
        _AXIS_LABELS["mu"],
        value,
        None,
        _channels(value, ["R", "G", "B"]),
        "directional albedo R",
    )
    ax.axhline(1.0, color="0.4", lw=0.8, ls="--")
    k = int(np.argmax(result.max))
    ax.plot(
        [result.mu_at_max],
        [result.max[k]],
        "o",
        color="black",
        ms=4,
        label=f"max {result.max[k]:.4g} at μ = {result.mu_at_max:.3g}",
    )
    ax.legend(fontsize=8, loc="best")
    verdict = "gains energy" if result.gains_energy else "conserves energy"
    head = result.model or "brdf-rs"
    title = f"{head}: {verdict}\nstandard error at the maximum {_largest(result.stderr):.2g}"
    fig.suptitle(title, fontsize=10)
    return _png(fig)


def energy_html(result: Energy) -> str:
    model = html.escape(str(result.model)) if result.model else "a model"
    k = int(np.argmax(result.max))
    verdict = "gains energy" if result.gains_energy else "conserves energy"
    summary = (
        f"<b>Energy</b> of <code>{model}</code>: largest albedo {result.max[k]:.6g} at"
        f" μ = {result.mu_at_max:.4g} ({verdict}); largest standard error"
        f" {_largest(result.stderr):.3g} (at the maximum)"
    )
    rows = [
        f"<tr><td>{name}</td><td>{result.max[i]:.6g}</td><td>{result.stderr[i]:.3g}</td></tr>"
        for i, name in enumerate("RGB")
    ]
    details = _table_html(["channel", "largest albedo", "stderr"], rows)
    return _html(summary, energy_png(result), details)
