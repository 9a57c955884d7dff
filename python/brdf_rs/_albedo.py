"""Directional albedo, albedo tables, split-sum (DFG) tables and energy checks.

The directional albedo of a family-A BRDF is ``R(mu) = ∫ f(wi, wo)·cos θo dωo`` with
``cos θi = mu`` (docs/models.md, "Directional albedo"). The Rust core computes it by
randomized quasi-Monte Carlo or Monte Carlo with the lobe's own importance sampler,
exact terms added in closed form, and an honest standard error per cell.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from . import _arrays, _display, _grid, _normalization, _options, _spec
from . import _brdf_rs as _core
from ._brdf_rs import __version__
from ._options import DEFAULT_REPLICATES
from ._table import Table, TableFileError, TablePreview

__all__ = [
    "Albedo",
    "Energy",
    "EnergyCompensation",
    "Table",
    "TableFileError",
    "TablePreview",
    "albedo",
    "albedo_table",
    "dfg_table",
    "energy",
    "energy_compensation_table",
]

log = logging.getLogger("brdf_rs")


@dataclasses.dataclass(frozen=True)
class Albedo:
    """Directional albedo estimates: ``value`` and ``stderr`` (shape ``cells + (3,)``,
    RGB) and ``samples`` drawn per cell (0 where the value is exact); :func:`albedo`
    also records the ``model`` and the cells' incidences ``mu`` (shape ``cells``).

    In Jupyter it shows itself as a curve over ``mu`` (a heat map for 2-D cells) with
    the largest standard error, or as a summary table without matplotlib.
    """

    value: np.ndarray
    stderr: np.ndarray
    samples: np.ndarray
    model: str | None = None
    mu: np.ndarray | None = None

    def _repr_png_(self) -> bytes | None:
        return _display.albedo_png(self)

    def _repr_html_(self) -> str:
        return _display.albedo_html(self)


def albedo(
    model: str,
    mu: Any,
    *,
    phi: Any = 0.0,
    samples: int = 4096,
    sampler: str = "auto",
    sequence: str = "sobol",
    seed: int = 0,
    tol: float | None = None,
    rtol: float | None = None,
    max_samples: int | None = None,
    replicates: int = DEFAULT_REPLICATES,
    progress: Callable[[int, int], None] | None = None,
    cell_ids: np.ndarray | None = None,
    fold_azimuth: bool = True,
    normalization: str = "approximate",
    component: str = "total",
    **params: Any,
) -> Albedo:
    """Directional albedo ``R(mu) = ∫ f(wi, wo)·cos θo dωo`` of a family-A model.

    Incidence: ``wi = (sin θ cos φ, sin θ sin φ, mu)`` in the local frame with the normal
    ``n = +z`` and the tangent ``+x``: ``φ`` is the angle between the projection of ``wi``
    on the tangent plane and the tangent, counterclockwise about ``n``.

    Args:
        model: a family-A model name.
        mu: cosines of the incidence angle, in [0, 1]; any shape, broadcast with the
            parameters (NumPy rules) into cells.
        phi: the azimuth ``φ`` of ``wi`` in radians (any finite values, an array
            broadcasting like ``mu``), or ``"average"`` for the azimuth average
            ``(1/2π) ∫ R(mu, φ) dφ``. Only the anisotropic models (``ward``,
            ``ashikhmin_shirley``: those with a tangent) depend on it; for the others
            ``phi`` changes no bit and ``"average"`` costs nothing extra. For the
            anisotropic ones, the average draws ``φ`` per sample as a third
            (quasi-)random dimension of the same randomized estimator, on ``[0, π/2)``
            because ``R(φ) = R(−φ) = R(π − φ)`` (the models are even under both
            reflections of the tangent frame; tested, not assumed): the φ quadrature
            error is then inside the replicates' spread, so ``stderr`` covers it without
            a separate bound (a fixed φ rule would need a bound on its error, which
            depends on how sharp the lobe is). The time is about that of one fixed-φ
            cell; the standard error is larger (R varies with φ): for a 32×32 Ward
            table a median of 2.3e-4 against 7e-5 at φ = 0 with 4096 samples
            (``benches/results/azimuth_table.md``); ``tol`` buys it down.
        samples: samples per cell (rounded up to ``replicates`` × a power of two for
            ``sobol``); with ``tol``, the first round.
        sampler: ``"auto"`` / ``"importance"`` (each lobe's own sampler), ``"cosine"``
            or ``"uniform"``.
        sequence: ``"sobol"`` (Owen-scrambled Sobol, randomized QMC with ``replicates``
            independent scrambles for the error bar) or ``"random"`` (PCG-64).
        seed: the streams are keyed by (seed, cell): same seed, same bits.
        tol: stop each cell once every channel's standard error is at most ``tol``
            (doubling its samples, up to ``max_samples``, default max(samples, 2^24)).
        rtol: stop each cell once every channel's standard error is at most ``rtol``
            times the channel's absolute value (with ``tol`` too: at most ``tol + rtol·
            |value|``, NumPy's ``allclose`` rule), so that small albedos get as many
            digits as large ones; a cell whose value is tiny but not 0 runs to
            ``max_samples``.
        progress: called as ``progress(cells_done, samples_done)`` about every 0.1 s.
        cell_ids: ids keying each cell's stream (default: the flat cell index):
            non-negative integers below 2**64, as integers or integral floats.
        fold_azimuth: draw azimuths on [0, π) only, using the integrand's symmetry about
            the plane of incidence (default), where it holds: isotropic models at any
            ``phi``, anisotropic ones at ``sin φ = 0``; ``False`` covers the full circle.
        normalization: ``"exact"`` for the exactly normalized lobe (see ``eval``).
        component: the part of the albedo of a model that transmits (``transmission`` in
            :func:`brdf_rs.models`), integrated over the whole sphere of ``wo``:
            ``"total"`` (default), ``"reflection"`` (``wo`` above the surface) or
            ``"transmission"`` (``wo`` below; refused for the models that do not
            transmit, whose albedo is the reflection).
        **params: the model's parameters (docs/models.md names), scalars or arrays
            broadcasting against ``mu``.

    Returns:
        :class:`Albedo` with ``value``/``stderr`` of shape ``broadcast(mu, params)+(3,)``.
    """
    _arrays.model_name(model, params)
    _arrays.flags(fold_azimuth=fold_azimuth)
    if progress is not None and not callable(progress):
        raise TypeError(
            "progress: expected a function called as progress(cells_done, samples_done),"
            f" or None; got {type(progress).__name__}"
        )
    phi_array, average = _options.azimuth(phi)
    mu_array = np.asarray(_arrays.parameters({"mu": mu}, np.float64)["mu"])
    numeric = _arrays.numeric(params)
    p = _arrays.parameters(_normalization.apply(model, numeric, normalization), np.float64)
    options = {"samples": samples, "sampler": sampler, "sequence": sequence, "seed": seed}
    options.update(replicates=replicates, tol=tol, rtol=rtol, max_samples=max_samples)
    options["component"] = component
    # Checked before cell_ids (the core converts them again, by the same code).
    options = _options.check(options)
    ids = _options.cell_ids(cell_ids)
    value, stderr, drawn = _core.albedo(
        model,
        mu_array,
        p,
        options,
        ids,
        progress,
        bool(fold_azimuth),
        phi_array,
        average,
    )
    cells = np.shape(value)[:-1]
    return Albedo(value, stderr, drawn, model, np.broadcast_to(mu_array, cells))


# ------------------------------------------------------------------------------- tables


def albedo_table(
    model: str,
    axes: Mapping[str, Sequence[float] | np.ndarray],
    *,
    samples: int = 4096,
    sampler: str = "auto",
    sequence: str = "sobol",
    seed: int = 0,
    tol: float | None = None,
    rtol: float | None = None,
    max_samples: int | None = None,
    replicates: int = DEFAULT_REPLICATES,
    progress: Callable[[int, int], None] | None = None,
    component: str = "total",
    **fixed: Any,
) -> Table:
    """Tabulates the directional albedo over a grid of ``axes``.

    Args:
        model: a family-A model.
        axes: ordered ``{name: coordinates}``; names are ``mu``, ``phi`` (the azimuth of
            ``wi`` in radians from the tangent, counterclockwise about ``n``: see
            :func:`albedo`) and the model's parameters (a colour axis holds grey values).
            The table's shape is the axes' lengths (in order) + (3,).
        component: the part of a transmitting model's albedo (see :func:`albedo`).
        **fixed: parameters held fixed over the table (``phi=`` a number, default 0, or
            ``"average"`` for the azimuth average), and the options of :func:`albedo`.

    A ``phi`` axis costs one cell per distinct ``|φ| mod π`` folded onto ``[0, π/2]``
    (``R(φ) = R(−φ) = R(π − φ)``) for the anisotropic models, and one cell in all for
    the isotropic ones (which do not depend on ``phi``); the other cells copy those.
    """
    names, coords, colour = _grid.table_axes(model, axes, fixed)
    computed = dict(coords)
    inverse = ids = None
    if "phi" in coords:
        at, first = _grid.azimuth_cells(model, coords["phi"])
        keep = np.unique(first)
        computed["phi"] = at[keep]
        inverse = np.searchsorted(keep, first)
        index = [keep if n == "phi" else np.arange(coords[n].size) for n in names]
        flat = np.ravel_multi_index(
            np.meshgrid(*index, indexing="ij", sparse=True), [coords[n].size for n in names]
        )
        ids = np.ascontiguousarray(np.broadcast_to(flat, [i.size for i in index]), dtype=np.uint64)
    mu, grid, rest = _grid.grid_inputs(names, colour, [computed[n] for n in names], fixed)
    result = albedo(
        model,
        mu,
        samples=samples,
        sampler=sampler,
        sequence=sequence,
        seed=seed,
        tol=tol,
        rtol=rtol,
        max_samples=max_samples,
        replicates=replicates,
        progress=progress,
        cell_ids=ids,
        component=component,
        **grid,
        **rest,
    )
    full = tuple(len(computed[n]) for n in names)
    value = np.broadcast_to(result.value, (*full, 3)).copy()
    stderr = np.broadcast_to(result.stderr, (*full, 3)).copy()
    drawn = np.broadcast_to(result.samples, full).copy()
    if inverse is not None:
        k = names.index("phi")
        value, stderr, drawn = (np.take(a, inverse, axis=k) for a in (value, stderr, drawn))
    options = {
        "samples": samples,
        "sampler": sampler,
        "sequence": sequence,
        "seed": seed,
        "tol": tol,
        "rtol": rtol,
        "max_samples": max_samples,
        "replicates": replicates,
        "component": component,
    }
    meta = _grid.table_meta(model, names, rest, options)
    return Table(value, stderr, drawn, coords, meta)


# ------------------------------------------------------------------------- DFG, energy


def _not_given(function: str, options: dict[str, Any], fixed: dict[str, str]) -> None:
    """Refuses, naming it, an argument the table sets itself (``fixed``: its name and
    why), which ``**options`` would otherwise pass on twice or let override."""
    for name, why in fixed.items():
        if name in options:
            raise TypeError(f"{name}: {function} sets it ({why}); do not pass it")


def dfg_table(
    model: str,
    mu: Sequence[float] | np.ndarray,
    roughness: Sequence[float] | np.ndarray,
    *,
    samples: int = 1 << 14,
    seed: int = 0,
    sheen: str | None = None,
    **options: Any,
) -> Table:
    """The split-sum table: ``scale`` A and ``bias`` B with ``R_spec = F0·A + B``.

    For a Schlick-Fresnel model (``F = F0 + (1 − F0)(1 − cos β)^5``) the specular albedo
    is affine in F0: ``A = I(F0 = 1) − I(F0 = 0)``, ``B = I(F0 = 0)``. Both integrals use
    the same points (same cell ids), so their errors are correlated and largely cancel in
    ``A``; the reported stderr of ``A`` is the conservative ``sqrt(se1² + se0²)``.
    ``roughness`` is the model's roughness parameter (``p`` for blinn_phong_fresnel).

    ``sheen`` names a sheen model (``"charlie_sheen_neubelt"`` for Filament's cloth
    channel; any family-A model with ``ks`` and the table's roughness parameter is
    accepted) whose directional albedo with no diffuse term and unit colour (``ks = 1``,
    every other weight 0) fills the third channel, the cloth term ``DG`` of the
    prefiltered-environment assumption: ``∫ D·V·(n·l) dωl`` at ``n·v = mu``. It is
    evaluated at the same value of the same parameter as the split-sum channels: a ggx or
    beckmann table's ``alpha`` axis value is the sheen model's ``alpha`` (Filament indexes
    its table by the perceptual roughness ρ and evaluates both terms at α = ρ²; pass
    ``roughness = ρ**2`` to get its rows). Its cells use the same seed and cell ids as
    ``brdf_rs.albedo_table(sheen, {"mu": mu, "alpha": roughness}, kd=0, ks=1)``, so the
    two agree bit for bit. Without ``sheen`` (the default) the third channel is 0.

    Returns a :class:`Table` with axes ``mu``, roughness; ``value[..., 0]`` = A,
    ``value[..., 1]`` = B, ``value[..., 2]`` = the sheen channel (else 0); ``meta["sheen"]``
    names the sheen model when there is one.
    """
    _arrays.model_name(model)
    dfg = _spec.with_dfg()
    if model not in dfg:
        known = ", ".join(dfg)
        raise ValueError(f"{model}: a split-sum table needs a Schlick-Fresnel model: {known}")
    rough = dfg[model]["param"]
    _not_given(
        "dfg_table",
        options,
        {
            "kd": "kd = 0: the tables hold the specular lobe",
            "ks": "ks = 0 and 1: A and B come from both",
            rough: "the roughness axis",
            "cell_ids": "one id per cell of the grid",
        },
    )
    mu = _grid.axis_values(model, "mu", "mu", mu)
    r = _grid.axis_values(model, "roughness", rough, roughness)
    weights = None if sheen is None else _sheen_weights(sheen, model, rough, r)
    ids = np.arange(mu.size * r.size, dtype=np.uint64).reshape(mu.size, r.size)
    mus = mu[:, None]
    roughness_axis: dict[str, Any] = {rough: r[None, :]}
    one = albedo(
        model,
        mus,
        cell_ids=ids,
        samples=samples,
        seed=seed,
        kd=0.0,
        ks=1.0,
        **roughness_axis,
        **options,
    )
    zero = albedo(
        model,
        mus,
        cell_ids=ids,
        samples=samples,
        seed=seed,
        kd=0.0,
        ks=0.0,
        **roughness_axis,
        **options,
    )
    value = np.zeros((mu.size, r.size, 3))
    stderr = np.zeros_like(value)
    value[..., 0] = one.value[..., 0] - zero.value[..., 0]
    value[..., 1] = zero.value[..., 0]
    stderr[..., 0] = np.hypot(one.stderr[..., 0], zero.stderr[..., 0])
    stderr[..., 1] = zero.stderr[..., 0]
    drawn = one.samples + zero.samples
    quantity = "split-sum DFG: channel 0 = scale A, channel 1 = bias B, R_spec = F0*A + B"
    if sheen is not None and weights is not None:
        cloth = albedo(
            sheen,
            mus,
            cell_ids=ids,
            samples=samples,
            seed=seed,
            **weights,
            **roughness_axis,
            **options,
        )
        value[..., 2] = cloth.value[..., 0]
        stderr[..., 2] = cloth.stderr[..., 0]
        drawn = drawn + cloth.samples
        fixed = ", ".join(f"{k} = {v:g}" for k, v in weights.items())
        quantity += (
            f"; channel 2 = cloth DG: directional albedo of {sheen} with {fixed},"
            f" {rough} = the {rough} axis value"
        )
    meta = {
        "model": model,
        "axis_names": ["mu", rough],
        "quantity": quantity,
        "samples": samples,
        "seed": seed,
        "brdf_rs": __version__,
        **({} if sheen is None else {"sheen": sheen}),
        **{k: v for k, v in options.items() if isinstance(v, (int, float, str))},
    }
    return Table(value, stderr, drawn, {"mu": mu, rough: r}, meta)


def _sheen_weights(sheen: Any, model: str, rough: str, r: np.ndarray) -> dict[str, Any]:
    """Checks ``dfg_table``'s ``sheen`` (a family-A model taking ``ks`` and the table's
    roughness parameter ``rough``, valid at every value ``r`` of the axis) and returns its
    weights for the cloth channel: ``ks = 1``, the others 0."""
    specs = _spec.specs()
    if not isinstance(sheen, str):
        raise TypeError(
            "sheen: expected a model name (a string; brdf_rs.models() lists them) or None,"
            f" got {type(sheen).__name__} {_arrays.show(sheen)}"
        )
    if sheen not in specs:
        raise ValueError(f"sheen: unknown model {sheen!r} (brdf_rs.models() lists them)")
    spec = specs[sheen]
    params = [p["name"] for p in spec["params"]]
    if spec["family"] != "A" or "ks" not in params or rough not in params:
        raise ValueError(
            f"sheen: {sheen} cannot fill the cloth channel of a {model} table: it needs a"
            f" family-A model with a colour ks and the table's roughness {rough}"
        )
    weights: dict[str, Any] = {w: 0.0 for w in spec["weights"] or () if w != "ks"}
    weights["ks"] = 1.0
    for i, x in enumerate(r):
        if not _spec.admits(sheen, rough, float(x)):
            raise ValueError(
                f"roughness[{i}]: {rough} = {x} is out of range for sheen={sheen!r}"
                f" ({next(p['range'] for p in spec['params'] if p['name'] == rough)})"
            )
    return weights


@dataclasses.dataclass(frozen=True)
class Energy:
    """The largest directional albedo of a parameter set, and where it occurs.

    ``max`` and ``stderr`` are RGB at ``mu_at_max`` (the incidence of the largest
    channel's maximum); ``gains_energy`` is true when some channel exceeds 1 by more than
    3 standard errors; ``mu`` / ``value`` hold the whole curve that was searched, and
    ``model`` the model's name. In Jupyter it shows itself as that curve, its maximum
    marked, with the verdict and the standard error there.
    """

    max: np.ndarray
    stderr: np.ndarray
    mu_at_max: float
    gains_energy: bool
    mu: np.ndarray
    value: np.ndarray
    model: str | None = None

    def _repr_png_(self) -> bytes | None:
        return _display.energy_png(self)

    def _repr_html_(self) -> str:
        return _display.energy_html(self)


def energy(model: str, *, samples: int = 1 << 16, seed: int = 0, **params: Any) -> Energy:
    """Finds the maximum directional albedo over mu (the Summary's eq. 4 energy check).

    A grid of 65 incidences (including mu = 1 and a grazing 0.005) is integrated; the
    best cell's neighbourhood (from the coarse node below it to the one above) is then
    refined on a finer grid of 17 incidences, of which those not already on the coarse
    grid are integrated: ``mu`` is strictly increasing, one value per node.
    """
    _arrays.model_name(model, params)
    # The refinement uses seed + 1.
    seed = _arrays.integer("seed", seed, 0, _arrays.U64_MAX - 1)
    mu = np.concatenate([[0.005], np.arange(1, 65) / 64.0])
    coarse = albedo(model, mu, samples=samples, seed=seed, **params)
    best = int(np.argmax(coarse.value.max(axis=-1)))
    lo, hi = mu[max(best - 1, 0)], mu[min(best + 1, mu.size - 1)]
    fine_mu = np.linspace(lo, hi, 17)
    fine_mu = fine_mu[~np.isin(fine_mu, mu)]
    fine = albedo(model, fine_mu, samples=samples, seed=seed + 1, **params)
    all_mu = np.concatenate([mu, fine_mu])
    all_value = np.concatenate([coarse.value, fine.value])
    all_err = np.concatenate([coarse.stderr, fine.stderr])
    order = np.argsort(all_mu, kind="stable")
    all_mu, all_value, all_err = all_mu[order], all_value[order], all_err[order]
    k = int(np.argmax(all_value.max(axis=-1)))
    gains = bool(np.any(all_value[k] - 3 * all_err[k] > 1.0))
    return Energy(all_value[k], all_err[k], float(all_mu[k]), gains, all_mu, all_value, model)


# ----------------------------------------------------------------- energy compensation


@dataclasses.dataclass(frozen=True)
class EnergyCompensation:
    """Energy tables ``E(mu, alpha)`` and ``E_avg(alpha)`` at kd = 0, ks = 1: Kulla & Conty's
    (2017) single-scattering tables of a microfacet model (F = 1), or a sheen model's
    albedo-scaling table (a base layered under sheen keeps ``1 − E_sheen``).

    ``e[i, j]`` is the lobe's albedo seen from the view ``E(mu_i, alpha_j) = ∫ f(wi, wo)
    mu_i dωi`` at ``n·wo = mu`` (for a reciprocal lobe the directional albedo), ``e_avg[j]``
    the cosine-weighted average ``E_avg(alpha) = 2 ∫ E(mu) mu dmu``, ``stderr`` and
    ``e_avg_stderr`` their error bars; ``estimator`` says how they were computed (see
    :func:`energy_compensation_table`). The missing energy
    is restored by the lobe ``f_ms = (1 − E(mu_i))(1 − E(mu_o)) / (π (1 − E_avg))``, scaled
    for a Schlick F0 by ``F_avg² E_avg / (1 − F_avg (1 − E_avg))``, ``F_avg = F0 + (1 − F0)/21``
    (see :meth:`multiple_scattering`; microfacet models with a Schlick F0 only: a sheen
    lobe has no Fresnel term, and its ``E`` may exceed 1).

    A transmitting model's table (the rough dielectrics) has an ``eta`` axis as well:
    ``e[i, j, k] = E(mu_i, alpha_j, eta_k)``, the total albedo (reflection +
    transmission) of the white interface for light from above at ``eta_k`` (below 1: from
    the denser side), ``e_avg[j, k]``, and the standard errors shaped alike; it has no
    :meth:`multiple_scattering` lobe.
    """

    model: str
    mu: np.ndarray
    alpha: np.ndarray
    e: np.ndarray
    e_avg: np.ndarray
    stderr: np.ndarray
    e_avg_stderr: np.ndarray
    estimator: str = (
        "randomized QMC (Owen-scrambled Sobol) of the directional albedo, E_avg by"
        " adaptive Gauss-Kronrod (7/15 points) in sqrt(mu)"
    )
    #: The ``eta`` axis of a transmitting model's table (``e[i, j, k]`` at ``eta[k]``,
    #: ``e_avg[j, k]``), None for the others.
    eta: np.ndarray | None = None

    def multiple_scattering(
        self, mu_i: Any, mu_o: Any, alpha_index: Any, f0: Any = 1.0
    ) -> np.ndarray:
        """``f_ms`` for incidences on the table's mu grid (indices into ``mu``), RGB F0.

        Raises:
            ValueError: for a model without Schlick's F0 (the sheen models), and for a
                transmitting model's table (whose ``E`` is the total albedo of the white
                interface over ``eta``, not the reflection Kulla and Conty's lobe adds to).
        """
        if self.eta is not None or _spec.specs()[self.model]["transmission"]:
            raise ValueError(
                f"multiple_scattering: Kulla and Conty's lobe completes the reflection of a"
                f" microfacet lobe with a Schlick F0; {self.model}'s table holds the total"
                f" albedo (reflection + transmission) of a white rough dielectric over eta,"
                f" for which this lobe is not defined"
            )
        if _spec.specs()[self.model]["dfg"] is None:
            raise ValueError(
                f"multiple_scattering: Kulla and Conty's lobe completes a microfacet lobe with "
                f"a Schlick F0; {self.model} has none (its E table scales a base layered "
                f"under it by 1 - E)"
            )
        e_i = self.e[mu_i, alpha_index]
        e_o = self.e[mu_o, alpha_index]
        e_avg = self.e_avg[alpha_index]
        f_ms = (1 - e_i) * (1 - e_o) / (np.pi * (1 - e_avg))
        f_avg = np.asarray(f0, dtype=np.float64) + (1 - np.asarray(f0, dtype=np.float64)) / 21
        scale = f_avg**2 * e_avg / (1 - f_avg * (1 - e_avg))
        return np.asarray(np.multiply.outer(f_ms, scale), dtype=np.float64)


def energy_compensation_table(
    model: str,
    mu: Sequence[float] | np.ndarray,
    alpha: Sequence[float] | np.ndarray,
    *,
    eta: Sequence[float] | np.ndarray | None = None,
    samples: int = 1 << 12,
    tol: float | None = 1e-5,
    seed: int = 0,
    **options: Any,
) -> EnergyCompensation:
    """Builds E(mu, alpha) and E_avg(alpha) at kd = 0, ks = 1 for the models whose spec has
    ``energy_table`` (the microfacet models with F = 1, and the sheen models).

    ``E`` is the albedo seen from the view, ``∫ f(wi, wo)·mu_i dωi`` over the light at
    ``n·wo = mu``: the albedo a layer takes out of the light, and the one Kulla and Conty's
    lobe completes. How it is computed depends on the model (its :func:`brdf_rs.models`
    entry):

    - A reciprocal lobe: ``E`` is its directional albedo, integrated by
      :func:`brdf_rs.albedo` (randomized QMC with ``samples``, ``tol``, ``seed`` and the
      other ``options``; standard errors), ``E_avg`` by an adaptive Gauss-Kronrod rule in
      ``sqrt(mu)`` over cells of their own (:func:`_adaptive_average`): its panels are
      halved until the rule's error estimate is within the noise, so ``e_avg_stderr``,
      the Monte Carlo standard error, covers the whole error at any ``tol``
      (``scripts/energy_quadrature_check.py``; docs/models.md).
    - A kernel with ``view_albedo_closed_form`` (a lobe that is not reciprocal, whose
      albedo over ``wo`` that :func:`brdf_rs.albedo` integrates is not ``E``): ``E`` is the
      closed form, exact (``stderr`` 0; ``E(0) = 0``, as ``f`` is 0 there). ``E_avg`` is an
      adaptive Gauss-Legendre quadrature of it in ``mu`` (:func:`_closed_form_average`),
      and ``e_avg_stderr`` a bound on that quadrature's error, not a standard error. The
      integrator's options are checked and otherwise not used (nothing is sampled).
    - A transmitting model (``transmission``: the rough dielectrics) takes an ``eta`` axis
      too (required; the other models refuse it): ``e[i, j, k] = E(mu_i, alpha_j, eta_k)``
      is the total albedo (reflection + transmission, :func:`brdf_rs.albedo` with
      ``component="total"``) of the white interface (``ks = kt = 1``, nothing absorbed)
      for light arriving from above at ``n·wi = mu`` with ``eta`` as given: ``eta > 1``
      from the less dense side, ``eta < 1`` from the denser side (total internal
      reflection included; ``eta = 1``, no interface, is the straight-through delta: 1,
      exact). ``e_avg[j, k] = 2 ∫ E mu dmu`` by the same adaptive rule over cells of
      its own. ``1 − E`` is the energy the single
      scattering misses. Cells are keyed by their flat index (E_avg's after E's), so a
      table is bitwise reproducible for a seed, and each has its standard error.
    """
    _arrays.model_name(model)
    compensated = _spec.with_energy_table()
    transmitting = _spec.transmitting()
    if model in transmitting:
        if eta is None:
            raise TypeError(
                f"eta: energy_compensation_table needs an eta axis for {model}, whose"
                f" table is E(mu, alpha, eta); pass eta=[...] (relative indices below/above)"
            )
        return _transmitting_table(model, mu, alpha, eta, samples, tol, seed, options)
    if model not in compensated:
        raise ValueError(
            f"{model}: energy compensation tables exist for {', '.join(compensated)}, and"
            f" over (mu, alpha, eta) for {', '.join(transmitting)}"
        )
    if eta is not None:
        raise TypeError(
            f"eta: energy_compensation_table takes an eta axis only for the transmitting"
            f" models ({', '.join(transmitting)}); {model} has no eta"
        )
    _not_given(
        "energy_compensation_table",
        options,
        {
            "kd": "kd = 0: E is the lobe's albedo",
            "ks": "ks = 1: E is the albedo at unit colour",
            "cell_ids": "one id per cell of the grid",
        },
    )
    mu = _grid.axis_values(model, "mu", "mu", mu)
    alpha = _grid.axis_values(model, "alpha", "alpha", alpha)
    if _spec.specs()[model]["view_albedo_closed_form"]:
        return _closed_form_table(model, mu, alpha, samples, tol, seed, options)
    common = {"samples": samples, "tol": tol, "seed": seed, "kd": 0.0, "ks": 1.0, **options}
    grid = albedo(model, mu[:, None], alpha=alpha[None, :], **common)
    e_avg, e_avg_se = _adaptive_average(model, {"alpha": alpha}, mu.size * alpha.size, common)
    return EnergyCompensation(
        model, mu, alpha, grid.value[..., 0], e_avg, grid.stderr[..., 0], e_avg_se
    )


def _gauss_kronrod_15() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The 7/15-point Gauss-Kronrod pair on ``[-1, 1]``: the 15 Kronrod nodes, their
    Kronrod weights, and the 7-point Gauss weights placed on the Gauss nodes among them
    (every other node from the ends; 0 on the others). QUADPACK's ``qk15`` constants
    (Piessens et al. 1983); ``tests/test_energy_average.py`` checks them (the Gauss half
    against NumPy's rule, the Kronrod rule exact to degree 22)."""
    half_x = [
        0.991455371120812639206854697526329,
        0.949107912342758524526189684047851,
        0.864864423359769072789712788640926,
        0.741531185599394439863864773280788,
        0.586087235467691130294144845693013,
        0.405845151377397166906606412076961,
        0.207784955007898467600689403773245,
    ]
    half_wk = [
        0.022935322010529224963732008058970,
        0.063092092629978553290700663189204,
        0.104790010322250183839876322541518,
        0.140653259715525918745189590510238,
        0.169004726639267902826583426598550,
        0.190350578064785409913256402421014,
        0.204432940075298892414161999234649,
    ]
    half_wg = [0.0, 0.129484966168869693270611432679082, 0.0, 0.279705391489276667901467771423780]
    half_wg += [0.0, 0.381830050505118944950369775488975, 0.0]
    x = np.array([*(-v for v in half_x), 0.0, *half_x[::-1]])
    wk = np.array([*half_wk, 0.209482141084727828012999174891714, *half_wk[::-1]])
    wg = np.array([*half_wg, 0.417959183673469387755102040816327, *half_wg[::-1]])
    return x, wk, wg


#: :func:`_gauss_kronrod_15`, once.
_GK15 = _gauss_kronrod_15()
#: A panel of E_avg is kept once |K − G| is within this many of its noise's standard
#: deviations.
_GK_NOISE = 2.0
#: E_avg's panels are halved down to width 2^-_GK_DEPTH at most, ...
_GK_DEPTH = 24
#: ... so a column's node ids (one per node of each panel, panels numbered below
#: 2^(_GK_DEPTH + 1)) fit in this many.
_GK_COLUMN_IDS = _GK15[0].size << (_GK_DEPTH + 1)


def _adaptive_average(
    model: str, axes: dict[str, np.ndarray], first_id: int, common: dict[str, Any]
) -> tuple[np.ndarray, np.ndarray]:
    """``E_avg = 2 ∫_0^1 E(mu) mu dmu`` over the grid of ``axes`` (the table's axes after
    ``mu``, in order) by :func:`_kronrod_average` on ``E`` cells of their own (``albedo``
    with ``common``), and its error bar. A ``progress`` callback in ``common`` sees the
    rounds as one run: counts carry on from round to round."""
    shape = tuple(a.size for a in axes.values())
    flat = [a.ravel() for a in np.meshgrid(*axes.values(), indexing="ij")]
    progress = common.get("progress")
    carried, seen = [0, 0], [0, 0]
    if progress is not None:

        def carry_on(done: int, samples: int) -> None:
            seen[:] = [done, samples]
            progress(carried[0] + done, carried[1] + samples)

        common = {**common, "progress": carry_on}

    def cells(mu: np.ndarray, ids: np.ndarray, col: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        params: dict[str, Any] = {
            name: np.repeat(a[col], mu.shape[1]).reshape(mu.shape)
            for name, a in zip(axes, flat, strict=True)
        }
        got = albedo(model, mu, cell_ids=ids, **params, **common)
        carried[0] += mu.size
        carried[1] += seen[1]
        seen[:] = [0, 0]
        return got.value[..., 0], got.stderr[..., 0]

    value, error = _kronrod_average(cells, math.prod(shape), first_id)
    return value.reshape(shape), error.reshape(shape)


def _kronrod_average(
    cells: Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]],
    columns: int,
    first_id: int,
) -> tuple[np.ndarray, np.ndarray]:
    """``E_avg = 2 ∫_0^1 E(mu) mu dmu`` of ``columns`` functions ``E`` by adaptive
    Gauss-Kronrod, and its error bar. ``cells(mu, ids, col)`` estimates ``E`` of column
    ``col[p]`` at ``mu[p, :]`` (a panel's nodes) on cells keyed by ``ids``, and
    returns the estimates and their standard errors, shaped like ``mu``.

    The rule runs in ``t = sqrt(mu)`` (``E_avg = ∫_0^1 4 t³ E(t²) dt``), which flattens the
    fall of ``E`` at grazing incidence. Each column of the grid starts with two panels of
    ``t``, ``[0, 1/2]`` and ``[1/2, 1]``; each panel gets the 15-point Kronrod rule and the
    7-point Gauss rule on the Gauss nodes among its 15 (:data:`_GK15`), one ``E`` cell per
    node. ``K − G`` is the Gauss rule's error to first order, and the Kronrod rule's, far
    smaller, is below it; the Monte Carlo noise of ``K − G``, ``sigma_d``, follows from the
    cells' standard errors. A panel is kept, with its Kronrod value, once ``|K − G| <=
    _GK_NOISE · sigma_d`` (twice: the rule's error no longer shows through the noise);
    otherwise it is
    halved, down to width ``2^-24``, where it is kept as it is and its ``|K − G|`` is added
    to the error bar. So ``E`` with a bend (near the critical angle of a dielectric seen
    from the denser side) or a steep fall (a smooth lobe at grazing incidence) gets narrow
    panels there, and a smooth ``E`` two panels: 30 cells.

    The error bar is the Monte Carlo standard error of the kept Kronrod values, plus the
    ``|K − G|`` of any panel kept at the narrowest width. A node's cell id depends only
    on its column's index, its panel's place in the halving of
    ``[0, 1]`` and its node, counted from ``first_id`` on (after the table's ``E``
    cells): each column's ``E_avg`` is bitwise reproducible for a seed, whatever the rest
    of the grid.
    """
    x15, wk15, wg15 = _GK15
    # Panel ``k`` of the halving (``[0, 1]`` is 1, its halves ``2k`` and ``2k + 1``).
    col = np.repeat(np.arange(columns), 2)
    heap = np.tile(np.array([2, 3], dtype=np.int64), columns)
    value = np.zeros(columns)
    variance = np.zeros(columns)
    forced = np.zeros(columns)
    while col.size:
        depth = np.floor(np.log2(heap)).astype(np.int64)
        width = np.ldexp(1.0, -depth)
        lo = (heap - (1 << depth)) * width
        h = width / 2
        t = (lo + h)[:, None] + h[:, None] * x15
        mu = t * t
        ids = (
            np.uint64(first_id)
            + col.astype(np.uint64)[:, None] * np.uint64(_GK_COLUMN_IDS)
            + (heap.astype(np.uint64) * np.uint64(x15.size))[:, None]
            + np.arange(x15.size, dtype=np.uint64)
        )
        e, se = cells(mu, ids, col)
        jacobian = 4 * mu * t  # 2 mu dmu = 4 t^3 dt
        f = jacobian * e
        s2 = (jacobian * se) ** 2
        k = h * (f @ wk15)
        diff = np.abs(k - h * (f @ wg15))
        sigma_d = h * np.sqrt(s2 @ (wk15 - wg15) ** 2)
        settled = diff <= _GK_NOISE * sigma_d + 16 * np.finfo(float).eps * np.abs(k)
        kept = settled | (heap >= 1 << _GK_DEPTH)
        np.add.at(value, col[kept], k[kept])
        np.add.at(variance, col[kept], (h * h)[kept] * (s2[kept] @ wk15**2))
        np.add.at(forced, col[kept & ~settled], diff[kept & ~settled])
        col = np.repeat(col[~kept], 2)
        heap = ((2 * heap[~kept])[:, None] + np.array([0, 1])).ravel()
    return value, np.sqrt(variance) + forced


def _transmitting_table(
    model: str,
    mu: Any,
    alpha: Any,
    eta: Any,
    samples: int,
    tol: float | None,
    seed: int,
    options: dict[str, Any],
) -> EnergyCompensation:
    """:func:`energy_compensation_table` for a transmitting model: the total albedo of the
    white interface over ``(mu, alpha, eta)``."""
    _not_given(
        "energy_compensation_table",
        options,
        {
            "ks": "ks = 1: E is the albedo of the white interface",
            "kt": "kt = 1: E is the albedo of the white interface",
            "component": "component = total: E is reflection + transmission",
            "cell_ids": "one id per cell of the grid",
        },
    )
    mu = _grid.axis_values(model, "mu", "mu", mu)
    alpha = _grid.axis_values(model, "alpha", "alpha", alpha)
    eta = _grid.axis_values(model, "eta", "eta", eta)
    grid, common = _transmitting_e(model, mu, alpha, eta, samples, tol, seed, options)
    cells = mu.size * alpha.size * eta.size
    e_avg, e_avg_se = _adaptive_average(model, {"alpha": alpha, "eta": eta}, cells, common)
    estimator = (
        "randomized QMC (Owen-scrambled Sobol) of the total albedo (reflection +"
        " transmission) of the white interface, E_avg by adaptive Gauss-Kronrod (7/15"
        " points) in sqrt(mu)"
    )
    return EnergyCompensation(
        model,
        mu,
        alpha,
        grid.value[..., 0],
        e_avg,
        grid.stderr[..., 0],
        e_avg_se,
        estimator,
        eta,
    )


def _transmitting_e(
    model: str,
    mu: np.ndarray,
    alpha: np.ndarray,
    eta: np.ndarray,
    samples: int,
    tol: float | None,
    seed: int,
    options: dict[str, Any],
) -> tuple[Albedo, dict[str, Any]]:
    """``E(mu, alpha, eta)`` of a transmitting model's energy table alone (checked axes),
    as :func:`energy_compensation_table` computes it (cells keyed by their flat index),
    and the integrator's arguments its ``E_avg`` run takes."""
    common = {"samples": samples, "tol": tol, "seed": seed, "ks": 1.0, "kt": 1.0, **options}
    common["component"] = "total"
    shape = (mu.size, alpha.size, eta.size)
    ids = np.arange(math.prod(shape), dtype=np.uint64).reshape(shape)
    grid = albedo(
        model,
        mu[:, None, None],
        alpha=alpha[None, :, None],
        eta=eta[None, None, :],
        cell_ids=ids,
        **common,
    )
    return grid, common


def transmitting_e(
    model: str,
    mu: Any,
    alpha: Any,
    eta: Any,
    *,
    samples: int,
    seed: int,
    progress: Any = None,
) -> tuple[np.ndarray, np.ndarray]:
    """``E`` of :func:`energy_compensation_table`'s transmitting table and its standard
    errors (``tol=None``), the same bits, without the ``E_avg`` run: for a LUT that keeps
    no ``E_avg`` channel."""
    mu = _grid.axis_values(model, "mu", "mu", mu)
    alpha = _grid.axis_values(model, "alpha", "alpha", alpha)
    eta = _grid.axis_values(model, "eta", "eta", eta)
    extra = {} if progress is None else {"progress": progress}
    grid, _ = _transmitting_e(model, mu, alpha, eta, samples, None, seed, extra)
    return grid.value[..., 0], grid.stderr[..., 0]


#: The integrator's options :func:`energy_compensation_table` checks but does not use
#: for a closed form (with ``samples``, ``tol`` and ``seed``).
_SAMPLING_OPTIONS = ("sampler", "sequence", "replicates", "rtol", "max_samples", "component")

#: The closed form's E_avg: panels are halved until ``|G20 − G10|`` is at most this much
#: per unit of ``mu`` (so at most this much in all), ...
_AVERAGE_TOL = 1e-14
#: ... or the panel is this narrow (then its estimate is kept as it is, in the bound).
_MIN_PANEL = 2.0**-40


def _closed_form_table(
    model: str,
    mu: np.ndarray,
    alpha: np.ndarray,
    samples: int,
    tol: float | None,
    seed: int,
    options: dict[str, Any],
) -> EnergyCompensation:
    """:func:`energy_compensation_table` for a kernel with the view albedo in closed form."""
    progress = options.pop("progress", None)
    if progress is not None and not callable(progress):
        raise TypeError(
            "progress: expected a function called as progress(cells_done, samples_done),"
            f" or None; got {type(progress).__name__}"
        )
    given = {k: options.pop(k) for k in _SAMPLING_OPTIONS if k in options}
    _options.check({"samples": samples, "tol": tol, "seed": seed, **given})
    if options:
        raise TypeError(
            f"{next(iter(options))}: energy_compensation_table takes no such option for"
            f" {model}, whose E is in closed form"
        )
    m, a = np.broadcast_arrays(mu[:, None], alpha[None, :])
    e = _core.view_albedo(model, np.ascontiguousarray(m), np.ascontiguousarray(a))
    averages = [_closed_form_average(model, float(x)) for x in alpha]
    e_avg = np.array([v for v, _ in averages])
    bound = np.array([b for _, b in averages])
    estimator = (
        "closed form of the albedo seen from the view (exact, stderr 0); E_avg by adaptive"
        " Gauss-Legendre in mu, e_avg_stderr a bound on its error (sum of |G20 - G10| over"
        " the panels, plus rounding)"
    )
    return EnergyCompensation(model, mu, alpha, e, e_avg, np.zeros_like(e), bound, estimator)


def _closed_form_average(model: str, alpha: float) -> tuple[float, float]:
    """``E_avg = 2 ∫_0^1 E(mu) mu dmu`` of the closed form ``E`` at one ``alpha``, and a
    bound on the error.

    Adaptive Gauss-Legendre: each panel of ``[0, 1]`` (16 to start) gets the 10- and
    20-point rules; a panel where they differ by more than :data:`_AVERAGE_TOL` times its
    width is halved, otherwise its 20-point value is kept (the kept values are summed
    exactly rounded). The bound is the sum of ``|G20 − G10|`` over the kept panels, plus
    32 ulp of each panel's value for rounding (``E`` is evaluated to about an ulp; each
    panel's value is a 20-term sum of positive products). ``|G20 − G10|`` is the 10-point
    rule's error to first order, and on a panel where ``E`` is smooth the 20-point rule's
    error is far below it (Gauss rules converge geometrically for analytic integrands):
    so the kept value is within the bound. Where ``E`` is not smooth (a closed form held
    at 0 has a kink) the halving closes in on the kink until the panel's share is
    negligible; the tests check the bound against an independent reference
    (``scripts/zeltner_energy_check.py``).
    """
    x10, w10 = np.polynomial.legendre.leggauss(10)
    x20, w20 = np.polynomial.legendre.leggauss(20)
    lo = np.arange(16) / 16.0
    hi = lo + 1 / 16.0
    values: list[np.ndarray] = []
    bounds: list[np.ndarray] = []
    while lo.size:
        c, h = (lo + hi)[:, None] / 2, (hi - lo)[:, None] / 2
        points = np.concatenate([c + h * x10, c + h * x20], axis=1)
        e = _core.view_albedo(model, points, np.full_like(points, alpha))
        integrand = 2 * points * e
        g10 = h[:, 0] * (integrand[:, :10] @ w10)
        g20 = h[:, 0] * (integrand[:, 10:] @ w20)
        estimate = np.abs(g20 - g10)
        width = hi - lo
        kept = (estimate <= _AVERAGE_TOL * width) | (width <= _MIN_PANEL)
        values.append(g20[kept])
        bounds.append(estimate[kept] + 32 * np.finfo(float).eps * np.abs(g20[kept]))
        mid = (lo + hi)[~kept] / 2
        lo, hi = np.concatenate([lo[~kept], mid]), np.concatenate([mid, hi[~kept]])
    # Summed exactly rounded: the panels add no rounding of their own.
    value = math.fsum(np.concatenate(values).tolist())
    return value, math.fsum(np.concatenate(bounds).tolist())
