"""An albedo table's grid: its axes and fixed values checked, laid out for the integrator.

:func:`brdf_rs.albedo_table`, ``brdf_rs.dask.albedo_table`` and the command line's
``table`` share these steps, so the same request is checked with the same messages and
gives the same cells (ids, folded azimuths) and the same metadata in all of them:

- :func:`table_axes` checks a table's inputs before any work;
- :func:`azimuth_cells` maps a ``phi`` axis onto the azimuths actually computed;
- :func:`grid_inputs` shapes coordinates and fixed values for :func:`brdf_rs.albedo`;
- :func:`table_meta` writes the table's metadata;
- :func:`axis_values` checks the 1-D axes of the split-sum and energy tables.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from . import _arrays, _options, _spec
from . import _brdf_rs as _core
from ._brdf_rs import __version__

__all__ = [
    "TABLE_OPTIONS",
    "axis_values",
    "azimuth_cells",
    "grid_inputs",
    "table_axes",
    "table_meta",
]


def _anisotropic(model: str) -> bool:
    """Whether a family-A model's albedo depends on the azimuth of ``wi`` (it reads a
    tangent: Ward, Ashikhmin-Shirley)."""
    spec = _spec.specs().get(model)
    return bool(
        spec is not None
        and spec["family"] == "A"
        and (spec["tangent"] or spec.get("tangent_optional", False))
    )


def _reduced_azimuth(phi: np.ndarray) -> np.ndarray:
    """``φ`` folded onto ``[0, π/2]`` by ``R(φ) = R(−φ) = R(π − φ)``."""
    r = np.mod(np.abs(phi), np.pi)
    return np.asarray(np.where(r > np.pi / 2, np.pi - r, r), dtype=np.float64)


def azimuth_cells(model: str, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For a ``phi`` axis: the azimuth each entry is computed at and the axis index whose
    cell (id) computes it. Anisotropic models: ``φ`` folded onto ``[0, π/2]``, entries
    with equal folded values sharing the first one's cell; isotropic ones: one cell.
    Shared with ``brdf_rs.dask`` so both builds give the same bits."""
    _options.azimuth(phi)  # finite
    if _anisotropic(model):
        reduced = _reduced_azimuth(phi)
        _, first, inverse = np.unique(reduced, return_index=True, return_inverse=True)
        return reduced, first[inverse.reshape(-1)]
    return np.full_like(phi, phi[0]), np.zeros(phi.size, dtype=np.intp)


#: Keywords of :func:`brdf_rs.albedo` that :func:`brdf_rs.albedo_table` passes on with the
#: fixed values.
TABLE_OPTIONS = ("normalization", "fold_azimuth")


def table_axes(
    model: str, axes: Mapping[str, Any], fixed: Mapping[str, Any]
) -> tuple[tuple[str, ...], dict[str, np.ndarray], frozenset[str]]:
    """Checks a table's inputs before any work: the model, the axes' names and values,
    the fixed values. Returns the axes' names (in order), their 1-D float64 coordinates
    and the names of the colour axes (which hold greys)."""
    _arrays.model_name(model)
    specs = _spec.specs()
    if model not in specs:
        _core.check_params(model, {})  # the core's message: known models, a suggestion
    if specs[model]["family"] != "A":
        raise ValueError(
            f"{model}: a family-{specs[model]['family']} shading term has no albedo; an albedo"
            " table needs a family-A model (brdf_rs.models() lists them)"
        )
    if not isinstance(axes, Mapping):
        raise TypeError(
            "axes: expected a mapping {name: coordinates}, e.g. {'mu': np.linspace(0, 1, 64)};"
            f" got {type(axes).__name__}"
        )
    if not axes:
        raise ValueError("axes: give at least one axis, e.g. {'mu': np.linspace(0, 1, 64)}")
    param_specs = {p["name"]: p for p in specs[model]["params"]}
    known = ("mu", "phi", *param_specs)
    for name in axes:
        if name not in known:
            raise ValueError(
                f"axes[{name!r}]: unknown axis; {model} tabulates over {', '.join(known)}"
            )
    for name in fixed:
        if name not in known and name not in TABLE_OPTIONS:
            raise TypeError(
                f"{name}: unknown keyword; {model} takes the parameters"
                f" {', '.join(param_specs)}, mu, phi and {', '.join(TABLE_OPTIONS)}"
            )
        if name in axes:
            raise ValueError(f"{name}: given both as an axis and as a fixed value")
    if "mu" not in axes and "mu" not in fixed:
        raise ValueError("axes: needs a 'mu' axis (or a fixed mu=...)")
    _check_fixed(model, param_specs, fixed)
    names = tuple(axes)
    coords = {}
    for name in names:
        label = f"axes[{name!r}]"
        a = np.asarray(_arrays.parameters({label: axes[name]}, np.float64)[label])
        if a.ndim != 1 or a.size == 0:
            raise ValueError(
                f"{label}: expected a non-empty 1-D list of values; got shape {a.shape}"
            )
        _check_axis_values(model, label, name, a, fixed)
        coords[name] = a
    kinds = {n: p["kind"] for n, p in param_specs.items()}
    return names, coords, frozenset(n for n in names if kinds.get(n) == "colour")


def _check_fixed(model: str, param_specs: Mapping[str, Any], fixed: Mapping[str, Any]) -> None:
    """Values held fixed over a table are single values: a number (a colour: or an RGB
    triple; a list parameter: its list); ``mu`` a cosine in [0, 1]."""
    for name, value in fixed.items():
        if name in TABLE_OPTIONS or (name == "phi" and isinstance(value, str)):
            continue
        a = _arrays.as_numeric(name, value)
        kind = "scalar" if name in ("mu", "phi") else param_specs[name]["kind"]
        single = a.ndim == 0 or (kind == "colour" and a.shape == (3,)) or "list" in kind
        if not single:
            what = "a number or an RGB triple" if kind == "colour" else "a number"
            raise ValueError(
                f"{name}: a value held fixed over the table is one value ({what}); got shape"
                f" {a.shape}. To tabulate over it, give it as an axis: axes={{..., {name!r}:"
                " [...]}"
            )
        if name == "mu" and not 0 <= float(a) <= 1:
            raise ValueError(f"mu = {float(a)} is out of range: must be in [0, 1]")
    params = {k: v for k, v in fixed.items() if k not in ("mu", "phi", *TABLE_OPTIONS)}
    _core.check_params(model, _arrays.parameters(params, np.float64))


def _check_axis_values(
    model: str, label: str, name: str, a: np.ndarray, fixed: Mapping[str, Any]
) -> None:
    """Checks an axis's values one by one, so an error names the axis's own index."""
    if name == "phi":
        bad = ~np.isfinite(a)
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(f"{label}[{i}] = {a[i]} is not finite (radians)")
        return
    if name == "mu":
        bad = ~((a >= 0) & (a <= 1))
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(
                f"{label}[{i}] = {a[i]} is out of range: must be in [0, 1] (the cosine of the"
                " incidence angle)"
            )
        return
    params = {k: v for k, v in fixed.items() if k not in ("mu", "phi", *TABLE_OPTIONS)}
    base = _arrays.parameters(params, np.float64)
    try:
        _core.check_params(model, {**base, name: a[:, None] if a.ndim == 1 else a})
    except ValueError:
        for i, x in enumerate(a):
            try:
                _core.check_params(model, {**base, name: np.asarray(x)})
            except ValueError as exc:
                raise ValueError(f"{label}[{i}]: {exc}") from None
        raise


def axis_values(model: str, label: str, name: str, values: Any) -> np.ndarray:
    """A 1-D axis of :func:`brdf_rs.dfg_table` or :func:`brdf_rs.energy_compensation_table`, checked
    value by value (``name``: the parameter it holds, or ``mu``)."""
    a = np.asarray(_arrays.parameters({label: values}, np.float64)[label])
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{label}: expected a non-empty 1-D list of values; got shape {a.shape}")
    _check_axis_values(model, label, name, a, {})
    return a


def grid_inputs(
    names: Sequence[str],
    colour: frozenset[str],
    coords: Sequence[np.ndarray],
    fixed: Mapping[str, Any],
) -> tuple[np.ndarray, dict[str, Any], dict[str, Any]]:
    """``mu``, the axis parameters and the fixed ones (``mu`` removed), shaped for
    :func:`brdf_rs.albedo`: one grid dimension per table axis; a colour axis holds greys."""
    grid: dict[str, Any] = {}
    for k, name in enumerate(names):
        shape = [1] * len(names)
        shape[k] = -1
        a = coords[k].reshape(shape)
        if name in colour:
            a = a[..., None]
        grid[name] = a
    fixed = dict(fixed)
    # phi (an axis, or fixed) goes to albedo's own ``phi=`` keyword with the parameters.
    mu = grid.pop("mu") if "mu" in grid else np.asarray(fixed.pop("mu"), dtype=np.float64)
    mu = np.broadcast_to(mu, [coords[k].size if n == "mu" else 1 for k, n in enumerate(names)])
    return mu, grid, fixed


def table_meta(
    model: str, names: Sequence[str], fixed: Mapping[str, Any], options: Mapping[str, Any]
) -> dict[str, Any]:
    """A table's metadata: the model, axes, fixed parameters (``mu`` excluded) and the
    integrator's options."""
    return {
        "model": model,
        "axis_names": list(names),
        "fixed": {k: np.asarray(v).tolist() for k, v in fixed.items()},
        **{
            k: options[k]
            for k in ("samples", "sampler", "sequence", "seed", "tol", "max_samples", "replicates")
        },
        # A relative tolerance (recorded when one was given).
        **({"rtol": options["rtol"]} if options.get("rtol") is not None else {}),
        "brdf_rs": __version__,
        "quantity": "directional albedo R(mu): integral of f(wi, wo) cos(theta_o) d(omega_o)",
        # The part of a transmitting model's albedo (recorded when it is not the total).
        **(
            {"component": options["component"]}
            if options.get("component", "total") != "total"
            else {}
        ),
    }
