"""The model spec table, read once from the extension: every per-model fact Python needs
(parameters, family, scene slot, split-sum roughness axis, energy tables, exact
normalization) comes from here, and so do the models the tools pick when the user names
none (:func:`tool_defaults`), so no Python module names a model to know what it is."""

from __future__ import annotations

from functools import cache
from typing import Literal, TypedDict

from . import _brdf_rs as _core


class ParamSpec(TypedDict):
    """One parameter of a model."""

    name: str
    #: ``"scalar"``, ``"colour"``, ``"scalar list"`` or ``"colour list"``.
    kind: str
    #: None: the parameter is required.
    default: float | None
    min: float
    max: float
    min_open: bool
    max_open: bool
    #: The valid range as text.
    range: str
    doc: str
    #: Whether it may be an array over the batch.
    varies: bool
    #: The most values a list parameter takes (None for scalars and colours).
    max_len: int | None
    #: For a colour list: the list parameter it has exactly one more entry than (else
    #: None).
    one_more_than: str | None


class DfgAxis(TypedDict):
    """The roughness axis of a model's split-sum (DFG) table."""

    #: The parameter that plays roughness.
    param: str
    #: The CLI's default axis (``"mid:lo:hi:n"``, ``"log:lo:hi:n"``).
    axis: str


class ExactNormalization(TypedDict):
    """A model's ``normalization="exact"`` (``brdf_rs._normalization``)."""

    #: How the factor is computed: ``"one"`` (the lobe as written), ``"blinn_closed_form"``
    #: or ``"table"`` (interpolated in the shipped table named by ``table``).
    factor: Literal["one", "blinn_closed_form", "table"]
    #: The shape parameters the factor is a function of, in the order it takes them.
    params: list[str]
    #: The colour parameter the factor multiplies.
    scales: str
    #: The table's name, for ``factor == "table"`` (else None).
    table: str | None


class ModelSpec(TypedDict):
    """One model's spec, as ``brdf_rs.models()`` returns it."""

    name: str
    #: ``"A"``: a BRDF without the cosine; ``"B"``: a shading term with the light cosine.
    family: Literal["A", "B"]
    summary: str
    formula: str
    source: str
    reciprocal: bool
    #: Whether ``tangent=`` is required, and whether it is optional.
    tangent: bool
    tangent_optional: bool
    #: The parameters whose all being zero makes the model zero everywhere (None: no
    #: such set, e.g. where ``ks`` is Schlick's F0).
    weights: list[str] | None
    #: Where a scene material takes it: ``"brdf"`` (family A), or for family-B terms
    #: ``"diffuse"``, ``"specular"`` or ``"both"``.
    scene_slot: Literal["brdf", "diffuse", "specular", "both"]
    #: How a family-A model's diffuse term renders alone: ``"whole"`` (the model is
    #: diffuse), ``"lambert"``, ``"absent"`` or ``"coupled"`` (not one kernel); None for
    #: family B.
    diffuse: Literal["whole", "lambert", "absent", "coupled"] | None
    #: The split-sum table's roughness axis, for models with Schlick's F0 (else None).
    dfg: DfgAxis | None
    #: Whether it has energy-compensation tables.
    energy_table: bool
    #: Whether the kernel gives the lobe's albedo seen from the view (``kd = 0``,
    #: ``ks = 1``: ``∫ f(wi, wo)·mu_i dωi`` over the light) in closed form: its energy
    #: table and sheen layer take it rather than integrate.
    view_albedo_closed_form: bool
    #: Whether it transmits: defined on the whole sphere of ``wi`` and ``wo`` (a BSDF),
    #: not zero unless both directions are above the surface; scenes refuse it.
    transmission: bool
    sheen_layer: bool
    #: Whether its kernel raises something to a power.
    powers: bool
    #: Whether ``precision="fast"`` computes it differently (only in float64): it has
    #: powers, or length corrections the fast tier leaves out (the microfacet lobes).
    fast_tier: bool
    #: Its ``normalization="exact"``, or None where it has none.
    exact: ExactNormalization | None
    params: list[ParamSpec]


class TableDefault(TypedDict):
    """``brdf-rs table``'s recipe when no model is named."""

    model: str
    #: The axes beyond ``mu``, as ``name=spec``.
    axes: list[str]
    #: The parameters, as ``name=value``.
    params: list[str]


class AlbedoCheck(TypedDict):
    """The benchmark's self-checking albedo table: ``model`` with ``kd = 0``, ``ks = 1``
    (its albedo at normal incidence is exactly 1) over ``param`` from ``lo`` to ``hi``,
    logarithmically."""

    model: str
    param: str
    lo: float
    hi: float


class ToolDefaults(TypedDict):
    """The models the tools pick when the user names none."""

    table: TableDefault
    #: ``brdf-rs dfg``'s model.
    dfg: str
    #: The diffuse shading term a sphere preview puts under a specular-only term.
    plain_diffuse: str
    #: ``brdf-rs bench``'s models: one per family of kernels.
    bench: list[str]
    albedo_check: AlbedoCheck


@cache
def specs() -> dict[str, ModelSpec]:
    """Every model's spec by name, in a stable order: read once from the extension and
    shared by every module (do not mutate; :func:`brdf_rs.models` hands out copies)."""
    return {m["name"]: m for m in _core.models()}


@cache
def tool_defaults() -> ToolDefaults:
    """The models the tools pick when the user names none (do not mutate)."""
    return _core.tool_defaults()


def admits(model: str, param: str, value: float) -> bool:
    """Whether ``value`` passes the range check ``eval`` makes on ``model``'s ``param``
    (closed bounds also admit their float32 roundings): for callers that word their own
    errors."""
    return _core.param_admits(model, param, value)


def with_dfg() -> dict[str, DfgAxis]:
    """The models with a split-sum table, and its roughness axis."""
    return {name: s["dfg"] for name, s in specs().items() if s["dfg"] is not None}


def with_energy_table() -> tuple[str, ...]:
    """The models with energy tables (E and E_avg at kd = 0, ks = 1)."""
    return tuple(name for name, s in specs().items() if s["energy_table"])


def transmitting() -> tuple[str, ...]:
    """The transmitting models (defined on the whole sphere; energy tables over ``eta``)."""
    return tuple(name for name, s in specs().items() if s["transmission"])


def with_exact() -> dict[str, ExactNormalization]:
    """The models with ``normalization="exact"``, and how it is computed."""
    return {name: s["exact"] for name, s in specs().items() if s["exact"] is not None}


@cache
def sheen_layers() -> tuple[str, ...]:
    """The models a scene material's sheen layer takes (``sheen = {model = ...}``)."""
    return tuple(name for name, s in specs().items() if s["sheen_layer"])


def in_slot(slot: str) -> tuple[str, ...]:
    """The family-B terms a material's ``slot`` (``"diffuse"``, ``"specular"``) takes."""
    return tuple(name for name, s in specs().items() if s["scene_slot"] in (slot, "both"))


def colour_lists(model: str) -> tuple[str, ...]:
    """The model's colour-list parameters (none for an unknown model: the core names it)."""
    spec = specs().get(model)
    if spec is None:
        return ()
    return tuple(p["name"] for p in spec["params"] if p["kind"] == "colour list")
