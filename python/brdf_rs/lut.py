"""Engine-ready lookup tables: split-sum DFG and Kulla-Conty E / E_avg, laid out as engines
ship them, with an error budget and a provenance record in every file.

A LUT is described by a :class:`LutSpec`: what it holds (``kind``: ``"dfg"``, the
split-sum scale A and bias B; ``"dfg_multiscatter"``, Filament's ``∫V·Fc`` = B and ``∫V``
= A + B; ``"energy"``, Kulla and Conty's E(mu) and E_avg; ``"gen_schlick"``, generalized
Schlick's F0/F90 blend), the model, two :class:`Axis` (the texture's columns and rows:
which quantity, its range, how many texels and whether they sit at texel centres or at
the ends of the range), a third for a 3-D table (``layers``: the index of refraction of a
rough dielectric's energy table, or generalized Schlick's exponent) and the pixel
format. The presets (:data:`PRESETS`) reproduce engines' conventions; docs/luts.md says
where each comes from.

:func:`build` integrates the table with the library's own DFG and energy builders
(:func:`brdf_rs.dfg_table`, :func:`brdf_rs.energy_compensation_table`) and computes its
error budget (:class:`Budget`): the Monte Carlo standard errors, the exact error the
pixel format's quantization introduces, and the error of bilinear interpolation measured
against the integral itself at points between the texels. :meth:`Lut.save` writes EXR,
KTX2, DDS, 16-bit PNG or source code (C/C++, GLSL, HLSL, WGSL); :func:`verify` rebuilds
a file's table from the recipe it records and compares.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import shlex
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _arrays, _spec
from ._brdf_rs import __version__

if TYPE_CHECKING:  # pragma: no cover
    from ._lutfit import DenseCheck, Fit

__all__ = [
    "CONTAINERS",
    "FORMATS",
    "KINDS",
    "PLACEMENTS",
    "PRESETS",
    "QUANTITIES",
    "Axis",
    "Budget",
    "Lut",
    "LutSpec",
    "build",
    "dense_check",
    "fit",
    "meet_error",
    "parse_axis",
    "passes",
    "preset",
    "read",
    "recipe_hash",
    "trilinear",
    "verify",
]

#: The axis quantities: the incidence cosine ``mu`` or its square root, the model's
#: roughness parameter (``alpha`` for the microfacet models; ``brdf_rs.models()`` names
#: it under ``dfg``) or its square root, the perceptual roughness ``r`` (``alpha = r²``).
QUANTITIES = {
    "mu": "mu = cos(theta_v), the texel coordinate is mu",
    "sqrt_mu": "the texel coordinate is sqrt(mu), mu = cos(theta_v)",
    "alpha": "the model's roughness parameter itself",
    "perceptual": "perceptual roughness r, the model's roughness parameter = r^2",
    "eta": "the relative index of refraction eta itself (a dielectric table's third axis)",
    "eta_z": "z = sqrt(|eta - 1|/(eta + 1)) = F0^(1/4), eta = (1 + z^2)/(1 - z^2) >= 1: light"
    " from the less dense side",
    "eta_z_inside": "z = sqrt(|eta - 1|/(eta + 1)) = F0^(1/4), eta = (1 - z^2)/(1 + z^2) <= 1:"
    " light from the denser side (a table at 1/eta)",
    "exponent": "generalized Schlick's exponent itself (a gen_schlick table's third axis)",
    "exponent_z": "z = 1/(1 + exponent/5), exponent = 5 (1 - z)/z: Cycles' coordinate, z = 0.5"
    " at Schlick's exponent 5",
}
_MU_QUANTITIES = ("mu", "sqrt_mu")
_ETA_QUANTITIES = ("eta", "eta_z", "eta_z_inside")
_EXPONENT_QUANTITIES = ("exponent", "exponent_z")
#: The quantities whose range is [0, 1] at most.
_UNIT_QUANTITIES = (*_MU_QUANTITIES, "eta_z", "eta_z_inside", "exponent_z")

#: Where a texel's sample sits: ``centres``: texel k of n at ``(k + 0.5)/n`` of the range
#: (what a GPU's bilinear filter assumes); ``ends``: at ``k/(n − 1)`` (first and last
#: texels on the range's ends).
PLACEMENTS = ("centres", "ends")

#: What a table holds, and its channels.
KINDS: dict[str, tuple[str, ...]] = {
    "dfg": ("A", "B", "cloth"),
    "dfg_multiscatter": ("B", "A+B", "cloth"),
    "energy": ("E", "E_avg"),
    "gen_schlick": ("s", "E"),
}
#: The kinds whose 3-D tables have more channels than :data:`KINDS` says: a
#: transmitting model's energy table has E and E_avg at the layer's index, and at its
#: inverse (the same interface lit from the other side).
KINDS_3D: dict[str, tuple[str, ...]] = {"energy": ("E", "E_avg", "E_inv", "E_inv_avg")}
_CHANNEL_TEXT = {
    "A": "split-sum scale A: R_spec = F0*A + B (Schlick F0, F90 = 1)",
    "B": "split-sum bias B = integral of V*Fc, Fc = (1 - v.h)^5",
    "A+B": "A + B = integral of V (the directional albedo with F = 1)",
    "E": "E(mu, roughness): directional albedo with F = 1 (single scattering)",
    "E_avg": "E_avg(roughness) = 2 * integral of E(mu) mu dmu (constant along the mu axis)",
    "s": "the blend of generalized Schlick's F0 and F90 in the albedo: E(F0, F90) ="
    " E * (F0 + (F90 - F0) * s), s = E(F0 = 0, F90 = 1)/E(F0 = F90 = 1), at the layer's"
    " exponent (0 where E is 0)",
    "cloth": "the sheen model's directional albedo with unit colour (integral of D*V*(n.l))"
    " at the table's roughness parameter value, or the sheen model's smallest where the"
    " table's is below it",
}


#: What a 3-D (transmitting model's) energy table's channels hold.
_CHANNEL_TEXT_3D = {
    "E": "E(mu, roughness, eta): the total albedo (reflection + transmission) of the white"
    " rough dielectric (ks = kt = 1, nothing absorbed) for light arriving at n.v = mu from"
    " the side the index eta says (eta > 1: from the less dense side); 1 - E is what single"
    " scattering misses",
    "E_avg": "E_avg(roughness, eta) = 2 * integral of E(mu) mu dmu (constant along the mu axis)",
    "E_inv": "E at 1/eta: the same interface lit from the other side (eta > 1 on the"
    " layers axis: light leaving the denser medium)",
    "E_inv_avg": "E_avg at 1/eta (constant along the mu axis)",
}


def _channel_text(spec: LutSpec, channel: str) -> str:
    """What ``channel`` of a table described by ``spec`` holds."""
    if spec.layer_role == "eta":
        return _CHANNEL_TEXT_3D[channel]
    return _CHANNEL_TEXT[channel]


#: An axis for each kind of third axis, as the errors suggest it.
_LAYER_EXAMPLES = {
    "eta": "eta_z:ends:16:0:1:0.0001:0.99",
    "exponent": "exponent_z:ends:16:0:1:0.0001:0.99",
}


def _gen_schlick_models() -> list[str]:
    """The models a ``gen_schlick`` table takes: generalized Schlick's ``f0``, ``f90`` and
    ``exponent`` on a microfacet lobe of roughness ``alpha``."""
    need = {"f0", "f90", "exponent", "alpha"}
    return [
        name
        for name, s in _spec.specs().items()
        if need <= {p["name"] for p in s["params"]} and s["family"] == "A"
    ]


@dataclasses.dataclass(frozen=True)
class PixelFormat:
    """A texel format: its channels, bits, encoding and the container codes for it."""

    name: str
    channels: int
    bits: int
    encoding: str  # "sfloat" or "unorm"
    vk: int  # VkFormat (KTX2)
    dxgi: int  # DXGI_FORMAT (DDS)

    @property
    def dtype(self) -> np.dtype[Any]:
        if self.encoding == "unorm":
            return np.dtype("<u2")
        return np.dtype("<f2") if self.bits == 16 else np.dtype("<f4")


#: The pixel formats, by their Vulkan names (VkFormat and DXGI_FORMAT codes from the
#: Vulkan and DXGI headers).
FORMATS: dict[str, PixelFormat] = {
    f.name: f
    for f in (
        PixelFormat("R16_UNORM", 1, 16, "unorm", 70, 56),
        PixelFormat("R16_SFLOAT", 1, 16, "sfloat", 76, 54),
        PixelFormat("R32_SFLOAT", 1, 32, "sfloat", 100, 41),
        PixelFormat("R16G16_UNORM", 2, 16, "unorm", 77, 35),
        PixelFormat("R16G16_SFLOAT", 2, 16, "sfloat", 83, 34),
        PixelFormat("R32G32_SFLOAT", 2, 32, "sfloat", 103, 16),
        # DXGI has no three-channel 16-bit format (0: none).
        PixelFormat("R16G16B16_SFLOAT", 3, 16, "sfloat", 90, 0),
        PixelFormat("R32G32B32_SFLOAT", 3, 32, "sfloat", 106, 6),
    )
}

#: File suffixes and what they hold.
CONTAINERS = {
    ".exr": "OpenEXR, half or float channels R, G, B in the table's channel order (the"
    " brdf-rs:channels attribute says which is which)",
    ".ktx2": "KTX 2.0 texture (one level, no supercompression)",
    ".dds": "DirectDraw Surface with the DX10 header",
    ".png": "16-bit PNG, value = offset + scale * pixel / 65535 per channel",
    ".h": "C/C++ header: the array and a bilinear lookup function (trilinear for a 3-D table)",
    ".glsl": "GLSL: the array and a bilinear (3-D: trilinear) lookup function",
    ".hlsl": "HLSL: the array and a bilinear (3-D: trilinear) lookup function",
    ".wgsl": "WGSL: the array and a bilinear (3-D: trilinear) lookup function",
}


# ------------------------------------------------------------------------------- axes


@dataclasses.dataclass(frozen=True)
class Axis:
    """One axis of a LUT: ``size`` texels over ``[lo, hi]`` of ``quantity`` (see
    :data:`QUANTITIES`), placed at texel ``centres`` or at the range's ``ends``
    (:data:`PLACEMENTS`). The integral at a texel is evaluated at ``max(q, floor)`` (a
    floor keeps e.g. roughness 0 out of a model's range, as Cycles clamps to 1e-4), and
    at ``min(q, ceiling)`` when a ``ceiling`` is given (Cycles evaluates its index axis
    at ``z <= 0.99``: ``z = 1`` is an infinite index). A mu axis with texels at the
    ``ends`` from ``lo = 0`` needs a floor: its first texel would be at mu = 0, where the
    albedo is 0 by convention."""

    quantity: str
    size: int
    placement: str = "centres"
    lo: float = 0.0
    hi: float = 1.0
    floor: float = 0.0
    ceiling: float | None = None

    def __post_init__(self) -> None:
        # Whole numbers are taken as floats: the recipe, its hash and the code's literals
        # are then the same for 0 and 0.0.
        fields = ("lo", "hi", "floor") + (() if self.ceiling is None else ("ceiling",))
        for field in fields:
            value = getattr(self, field)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
                raise ValueError(f"axis {field}: expected a number, got {value!r}")
            number = float(value)
            if not math.isfinite(number):
                raise ValueError(f"axis {field}: expected a finite number, got {value!r}")
            object.__setattr__(self, field, number)
        if self.quantity not in QUANTITIES:
            raise ValueError(
                f"axis quantity: unknown {self.quantity!r}; use {', '.join(QUANTITIES)}"
            )
        if self.placement not in PLACEMENTS:
            raise ValueError(
                f"axis placement: unknown {self.placement!r}; use {', '.join(PLACEMENTS)}"
            )
        if isinstance(self.size, bool) or not isinstance(self.size, int) or self.size < 2:
            raise ValueError(f"axis size: expected an integer >= 2, got {self.size!r}")
        if self.size > 4096:
            raise ValueError(f"axis size: {self.size} texels is more than 4096")
        if not (math.isfinite(self.lo) and math.isfinite(self.hi) and 0 <= self.lo < self.hi):
            raise ValueError(f"axis range: expected 0 <= lo < hi, got [{self.lo}, {self.hi}]")
        if self.quantity in _UNIT_QUANTITIES and self.hi > 1:
            raise ValueError(f"axis range: {self.quantity} is at most 1, got hi = {self.hi}")
        if not (math.isfinite(self.floor) and 0 <= self.floor < self.hi):
            raise ValueError(f"axis floor: expected 0 <= floor < hi, got {self.floor}")
        if self.ceiling is not None and not self.floor < self.ceiling <= self.hi:
            raise ValueError(
                f"axis ceiling: expected floor < ceiling <= hi, got {self.ceiling} (floor"
                f" {self.floor}, hi {self.hi})"
            )
        if self.role == "mu" and self.placement == "ends" and max(self.lo, self.floor) == 0:
            # The albedo at exactly mu = 0 is 0 by convention, not its limit: a whole first
            # row of zeros that the lookup would interpolate towards.
            raise ValueError(
                f"axis floor: {self.quantity} with texels at the range ends and lo = 0 puts"
                " the first texel at mu = 0, where the albedo is 0 by convention; give a"
                " floor (1e-4 for mu, 0.01 for sqrt_mu: mu = 1e-4, where engines clamp n.v),"
                f" e.g. {self.quantity}:ends:{self.size}:0:{self.hi!r}:"
                + ("0.0001" if self.quantity == "mu" else "0.01")
            )

    @property
    def role(self) -> str:
        """``"mu"``, ``"roughness"``, ``"eta"`` or ``"exponent"``."""
        if self.quantity in _MU_QUANTITIES:
            return "mu"
        if self.quantity in _ETA_QUANTITIES:
            return "eta"
        return "exponent" if self.quantity in _EXPONENT_QUANTITIES else "roughness"

    def fractions(self) -> np.ndarray:
        """Where the texels sit, as fractions of ``[lo, hi]``."""
        k = np.arange(self.size, dtype=np.float64)
        if self.placement == "centres":
            return (k + 0.5) / self.size
        return k / (self.size - 1)

    def positions(self) -> np.ndarray:
        """The axis quantity at each texel."""
        return self.lo + (self.hi - self.lo) * self.fractions()

    def physical(self, q: np.ndarray) -> np.ndarray:
        """``mu``, the model's roughness parameter, ``eta`` or generalized Schlick's
        exponent at quantity values ``q`` (floored, and capped at the ceiling when there is
        one; ``eta_z = 1`` is an infinite index, ``exponent_z = 0`` an infinite
        exponent)."""
        q = np.maximum(np.asarray(q, dtype=np.float64), self.floor)
        if self.ceiling is not None:
            q = np.minimum(q, self.ceiling)
        if self.quantity in ("sqrt_mu", "perceptual"):
            return np.asarray(q * q)
        if self.quantity in ("eta_z", "eta_z_inside"):
            z2 = q * q
            with np.errstate(divide="ignore"):
                eta = np.asarray((1 + z2) / (1 - z2))
            return np.asarray(1 / eta) if self.quantity == "eta_z_inside" else eta
        if self.quantity == "exponent_z":
            with np.errstate(divide="ignore"):
                return np.asarray(5 * (1 - q) / q)
        return q

    def quantity_of(self, x: Any) -> np.ndarray:
        """The axis quantity of a physical value (``mu``, the roughness parameter, ``eta``
        or the exponent)."""
        a = np.asarray(x, dtype=np.float64)
        if self.quantity in ("sqrt_mu", "perceptual"):
            return np.asarray(np.sqrt(np.maximum(a, 0)))
        if self.quantity in ("eta_z", "eta_z_inside"):
            return np.asarray(np.sqrt(np.abs(a - 1) / (a + 1)))
        if self.quantity == "exponent_z":
            return np.asarray(1 / (1 + a / 5))
        return a

    def texel(self, q: Any) -> np.ndarray:
        """The continuous texel coordinate of quantity ``q`` (0 = first texel's sample),
        clamped to ``[0, size − 1]``: what a bilinear filter interpolates between."""
        t = (np.asarray(q, dtype=np.float64) - self.lo) / (self.hi - self.lo)
        x = t * self.size - 0.5 if self.placement == "centres" else t * (self.size - 1)
        return np.clip(x, 0.0, self.size - 1.0)

    def spec(self) -> str:
        """The command line's text for this axis:
        ``QUANTITY:PLACEMENT:SIZE[:LO:HI[:FLOOR[:CEILING]]]``."""
        text = f"{self.quantity}:{self.placement}:{self.size}"
        if (self.lo, self.hi, self.floor, self.ceiling) != (0.0, 1.0, 0.0, None):
            text += f":{self.lo!r}:{self.hi!r}"
            if self.floor or self.ceiling is not None:
                text += f":{self.floor!r}"
            if self.ceiling is not None:
                text += f":{self.ceiling!r}"
        return text

    def describe(self, param: str) -> str:
        """One line saying exactly what the axis is."""
        what = {
            "mu": "mu = cos(theta_v)",
            "sqrt_mu": "sqrt(mu), mu = cos(theta_v)",
            "alpha": f"{param} (the model's roughness parameter)",
            "perceptual": f"perceptual roughness r with {param} = r^2",
            "eta": "eta, the relative index of refraction (below / above)",
            "eta_z": "z = sqrt(|eta - 1|/(eta + 1)) with eta = (1 + z^2)/(1 - z^2) >= 1 (light"
            " from the less dense side)",
            "eta_z_inside": "z = sqrt(|eta - 1|/(eta + 1)) with eta = (1 - z^2)/(1 + z^2) <= 1"
            " (light from the denser side)",
            "exponent": "generalized Schlick's exponent",
            "exponent_z": "z = 1/(1 + exponent/5) with exponent = 5 (1 - z)/z",
        }[self.quantity]
        where = (
            f"texel k at q = lo + (hi - lo) * (k + 0.5) / {self.size} (texel centres)"
            if self.placement == "centres"
            else f"texel k at q = lo + (hi - lo) * k / {self.size - 1} (range ends on the"
            " first and last texels)"
        )
        floor = f", evaluated at max(q, {self.floor!r})" if self.floor else ""
        if self.ceiling is not None:
            floor += f" and at most {self.ceiling!r}"
        return f"q = {what} over [{self.lo!r}, {self.hi!r}], {self.size} texels, {where}{floor}"

    def to_json(self) -> dict[str, Any]:
        # Without a ceiling the record is the one axes have always had (recipes, and so
        # content hashes, of existing tables are unchanged).
        record = dataclasses.asdict(self)
        if self.ceiling is None:
            del record["ceiling"]
        return record


#: :attr:`Budget.confidence` for a table computed without sampling.
_CLOSED_FORM_CONFIDENCE = (
    "an estimate per point checked: the texels come from a closed form and a quadrature"
    " with an error bound (mc_max_stderr holds the largest bound, counted 3 times in"
    " total), nothing is sampled; the interpolation error is measured at the points"
    " checked, not bounded over the whole table"
)


def parse_axis(text: str, what: str = "axis") -> Axis:
    """An :class:`Axis` from ``QUANTITY:PLACEMENT:SIZE[:LO:HI[:FLOOR[:CEILING]]]``, e.g.
    ``mu:centres:128``, ``perceptual:ends:32:0:1:1e-4`` or ``eta_z:ends:16:0:1:1e-4:0.99``."""
    parts = str(text).split(":")
    if not 3 <= len(parts) <= 7 or len(parts) == 4:
        raise ValueError(
            f"{what}: expected QUANTITY:PLACEMENT:SIZE[:LO:HI[:FLOOR[:CEILING]]], e.g."
            f" mu:centres:128; got {text!r}"
        )
    try:
        size = int(parts[2])
        numbers = [float(p) for p in parts[3:]]
    except ValueError:
        raise ValueError(
            f"{what}: SIZE must be an integer and LO, HI, FLOOR, CEILING numbers; got {text!r}"
        ) from None
    lo, hi, floor = (numbers + [0.0, 1.0, 0.0][len(numbers) :])[:3] if numbers else (0.0, 1.0, 0.0)
    ceiling = numbers[3] if len(numbers) == 4 else None
    try:
        return Axis(parts[0], size, parts[1], lo, hi, floor, ceiling)
    except ValueError as exc:
        raise ValueError(f"{what}: {exc}") from None


# ------------------------------------------------------------------------------- specs


@dataclasses.dataclass(frozen=True)
class LutSpec:
    """Everything that determines a LUT: what it holds, the model, the two axes (the
    texture's ``columns``, its width, and ``rows``, its height: row 0 is the first row
    stored), the pixel format, the channels kept (default: all of the kind's; a
    one-channel format keeps the first unless told) and the estimator's settings.

    A transmitting model's energy table (the rough dielectrics) is a 3-D texture: its
    ``layers`` axis (the depth, slice 0 first) is the index of refraction (``eta``,
    ``eta_z`` or ``eta_z_inside``). So is a ``gen_schlick`` table, over generalized
    Schlick's exponent (``exponent`` or ``exponent_z``). The other tables have no
    ``layers``."""

    kind: str
    model: str
    columns: Axis
    rows: Axis
    format: str = "R16G16_SFLOAT"
    channels: tuple[str, ...] | None = None
    samples: int = 1024
    seed: int = 0
    name: str = "brdf_lut"
    sheen: str | None = None
    layers: Axis | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind: unknown {self.kind!r}; use {', '.join(KINDS)}")
        if self.format not in FORMATS:
            raise ValueError(f"format: unknown {self.format!r}; use {', '.join(FORMATS)}")
        transmitting = _spec.transmitting()
        if self.kind == "energy":
            known: Sequence[str] = _spec.with_energy_table() + transmitting
        elif self.kind == "gen_schlick":
            known = _gen_schlick_models()
        else:
            known = list(_spec.with_dfg())
        if self.model not in known:
            raise ValueError(
                f"model: {self.model!r} has no {self.kind} table; use {', '.join(known)}"
            )
        if {self.columns.role, self.rows.role} != {"mu", "roughness"}:
            raise ValueError(
                "axes: one axis must be mu (mu or sqrt_mu) and the other roughness (alpha or"
                f" perceptual); got {self.columns.quantity} and {self.rows.quantity}"
            )
        if self.layers is not None and not isinstance(self.layers, Axis):
            raise ValueError(f"layers: expected an Axis or None, got {self.layers!r}")
        role = self.layer_role
        if role is not None and self.layers is None:
            example = _LAYER_EXAMPLES[role]
            raise ValueError(
                f"layers: the {self.kind} table of {self.model} is a 3-D texture over {role};"
                f" give its axis (layers=parse_axis({example!r}), --layers {example})"
            )
        if role is None and self.layers is not None:
            raise ValueError(
                "layers: only a transmitting model's energy table"
                f" ({', '.join(transmitting)}) and a gen_schlick table have a third axis;"
                f" a {self.kind} table of {self.model} is 2-D"
            )
        if self.layers is not None and self.layers.role != role:
            quantities = _ETA_QUANTITIES if role == "eta" else _EXPONENT_QUANTITIES
            raise ValueError(
                f"layers: this table's third axis is {role} ({', '.join(quantities)}); got"
                f" {self.layers.quantity}"
            )
        fmt = FORMATS[self.format]
        chosen = self.channel_names
        unknown = [c for c in chosen if c not in self.kind_channels]
        if unknown or not chosen or len(set(chosen)) != len(chosen):
            raise ValueError(
                f"channels: {', '.join(chosen) or 'none'} for a {self.kind} table; choose"
                f" distinct ones of {', '.join(self.kind_channels)}"
            )
        if ("cloth" in chosen) != (self.sheen is not None):
            raise ValueError(
                "sheen: the cloth channel needs a sheen model (sheen=..., --sheen) and a sheen"
                " model needs the cloth channel"
                + (f"; the channels are {', '.join(chosen)}" if self.sheen is not None else "")
            )
        if self.sheen is not None:
            if not isinstance(self.sheen, str):
                raise ValueError(f"sheen: expected a model name, got {self.sheen!r}")
            _sheen(self)
        if len(chosen) != fmt.channels:
            raise ValueError(
                f"format: {self.format} holds {fmt.channels} channel(s) but the table has"
                f" {len(chosen)} ({', '.join(chosen)}); pick a {len(chosen)}-channel format"
                " or choose channels"
            )
        if isinstance(self.samples, bool) or not isinstance(self.samples, int):
            raise ValueError(f"samples: expected an integer, got {self.samples!r}")
        if not 1 <= self.samples <= 1 << 24:
            raise ValueError(f"samples: expected 1 to 2^24 per texel, got {self.samples}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"seed: expected a non-negative integer, got {self.seed!r}")
        if not (isinstance(self.name, str) and self.name.isidentifier() and self.name.isascii()):
            raise ValueError(f"name: expected a C identifier, got {self.name!r}")
        for label, axis in self._axes():
            if axis.role == "mu":
                continue
            param = self.param if axis.role == "roughness" else axis.role
            ends = axis.physical(axis.positions()[[0, -1]])
            for which, value, fix in (
                ("first", float(ends[0]), "raise lo or give a floor"),
                ("last", float(ends[1]), "lower hi or give a ceiling"),
            ):
                if not _spec.admits(self.model, param, value):
                    raise ValueError(
                        f"{label}: {param} = {value!r} at the {which} texel is out of"
                        f" range for {self.model}; {fix}"
                    )

    @property
    def layer_role(self) -> str | None:
        """What the third axis holds (``"eta"``, ``"exponent"``), None for a 2-D table."""
        if self.kind == "gen_schlick":
            return "exponent"
        if self.kind == "energy" and self.model in _spec.transmitting():
            return "eta"
        return None

    def _axes(self) -> list[tuple[str, Axis]]:
        """The axes by their field names, ``layers`` last when there is one."""
        axes = [("columns", self.columns), ("rows", self.rows)]
        return axes + ([("layers", self.layers)] if self.layers is not None else [])

    @property
    def channel_names(self) -> tuple[str, ...]:
        if self.channels is not None:
            return tuple(self.channels)
        return self.kind_channels[: FORMATS[self.format].channels]

    @property
    def kind_channels(self) -> tuple[str, ...]:
        """Every channel the table's kind has (:data:`KINDS`; :data:`KINDS_3D` for a 3-D
        table of a kind listed there)."""
        if self.layers is None:
            return KINDS[self.kind]
        return KINDS_3D.get(self.kind, KINDS[self.kind])

    @property
    def param(self) -> str:
        """The model's roughness parameter."""
        if self.kind in ("energy", "gen_schlick"):
            return "alpha"
        return _spec.with_dfg()[self.model]["param"]

    @property
    def mu_axis(self) -> Axis:
        return self.columns if self.columns.role == "mu" else self.rows

    @property
    def roughness_axis(self) -> Axis:
        return self.columns if self.columns.role == "roughness" else self.rows

    @property
    def shape(self) -> tuple[int, ...]:
        """The texture's shape without channels: ``(rows, columns)``, or ``(layers, rows,
        columns)`` for a 3-D table."""
        plane = (self.rows.size, self.columns.size)
        return plane if self.layers is None else (self.layers.size, *plane)

    def recipe(self) -> dict[str, Any]:
        """What made the table: hashed for its provenance."""
        return {
            "kind": self.kind,
            "model": self.model,
            "roughness_parameter": self.param,
            "columns": self.columns.to_json(),
            "rows": self.rows.to_json(),
            "format": self.format,
            "channels": list(self.channel_names),
            "samples": self.samples,
            "seed": self.seed,
            "name": self.name,
            "sheen": self.sheen,
            "estimator": _estimator(self.kind, self.model),
            "brdf_rs": __version__,
        } | ({} if self.layers is None else {"layers": self.layers.to_json()})

    def content_hash(self) -> str:
        return recipe_hash(self.recipe())

    def command(self, output: str = "OUT") -> str:
        """The command line that rebuilds this table into ``output``."""
        args = [
            "brdf-rs",
            "lut",
            "--kind",
            self.kind,
            "--model",
            self.model,
            "--columns",
            self.columns.spec(),
            "--rows",
            self.rows.spec(),
            "--format",
            self.format,
            "--channels",
            ",".join(self.channel_names),
            "--samples",
            str(self.samples),
            "--seed",
            str(self.seed),
            "--name",
            self.name,
            *(["--sheen", self.sheen] if self.sheen is not None else []),
            *(["--layers", self.layers.spec()] if self.layers is not None else []),
            "-o",
            output,
        ]
        return " ".join(shlex.quote(a) for a in args)

    @classmethod
    def from_recipe(cls, recipe: Mapping[str, Any]) -> LutSpec:
        return cls(
            kind=recipe["kind"],
            model=recipe["model"],
            columns=Axis(**recipe["columns"]),
            rows=Axis(**recipe["rows"]),
            format=recipe["format"],
            channels=tuple(recipe["channels"]),
            samples=int(recipe["samples"]),
            seed=int(recipe["seed"]),
            name=recipe["name"],
            sheen=recipe.get("sheen"),
            layers=Axis(**recipe["layers"]) if recipe.get("layers") is not None else None,
        )


def recipe_hash(recipe: Mapping[str, Any]) -> str:
    """The SHA-256 of a recipe (:meth:`LutSpec.recipe`, or one a file records) as
    canonical JSON: a file's ``content_hash``."""
    text = json.dumps(recipe, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


_ESTIMATOR = {
    "dfg": "brdf_rs.dfg_table: randomized QMC (Owen-scrambled Sobol), kd = 0, ks = 0 and 1",
    "dfg_multiscatter": "brdf_rs.dfg_table: randomized QMC (Owen-scrambled Sobol), kd = 0,"
    " ks = 0 and 1",
    "energy": "brdf_rs.energy_compensation_table: randomized QMC (Owen-scrambled Sobol),"
    " E_avg by adaptive Gauss-Kronrod (7/15 points) in sqrt(mu)",
    "gen_schlick": "brdf_rs.albedo_table: randomized QMC (Owen-scrambled Sobol) of the albedo"
    " at F0 = 0, F90 = 1 and at F0 = F90 = 1 on the same cells, s their ratio (its stderr"
    " propagated as if independent: an upper estimate)",
}


def _closed_form(kind: str, model: str) -> bool:
    """Whether the table samples nothing: the energy table of a model whose albedo seen
    from the view is in closed form."""
    spec = _spec.specs().get(model)
    return kind == "energy" and spec is not None and bool(spec["view_albedo_closed_form"])


def _estimator(kind: str, model: str) -> str:
    """How a table's values are computed: :data:`_ESTIMATOR`, except for a table that
    samples nothing (:func:`_closed_form`)."""
    if _closed_form(kind, model):
        return (
            "brdf_rs.energy_compensation_table: E the closed form of the albedo seen from the"
            " view, E_avg by adaptive Gauss-Legendre in mu with an error bound"
        )
    if kind == "energy" and model in _spec.transmitting():
        return (
            "brdf_rs.energy_compensation_table: randomized QMC (Owen-scrambled Sobol) of the"
            " total albedo (reflection + transmission) of the white interface, E_avg by"
            " adaptive Gauss-Kronrod (7/15 points) in sqrt(mu)"
        )
    return _ESTIMATOR[kind]


@dataclasses.dataclass(frozen=True)
class Preset:
    """An engine's convention: the spec it builds by default and where it comes from."""

    spec: LutSpec
    container: str
    summary: str
    source: str


#: The perceptual roughness floor of the Cycles preset: the square root of 1e-7, the
#: smallest alpha ggx takes (Cycles clamps r to 1e-4, alpha 1e-8; E differs by less than
#: the Monte Carlo error there).
_CYCLES_ROUGHNESS_FLOOR = 3.1623e-4

#: The perceptual roughness floor of the UE5 preset: Unreal's table builder takes
#: ``max(Roughness, 0.01)`` before squaring (GGX_MIN_ROUGHNESS of its path tracer's GGX).
_UE5_ROUGHNESS_FLOOR = 0.01


def _presets() -> dict[str, Preset]:
    r32_centres = Axis("perceptual", 32, "centres")
    # Unreal's energy tables (specular and glass): NoV and Roughness at texel centres of
    # 32; its builder floors r at 0.01 (alpha 1e-4): no texel of 32 is below.
    ue5_mu = Axis("mu", 32, "centres")
    ue5_r = Axis("perceptual", 32, "centres", floor=_UE5_ROUGHNESS_FLOOR)
    return {
        "filament": Preset(
            LutSpec(
                "dfg_multiscatter",
                "ggx",
                Axis("mu", 128, "centres"),
                Axis("perceptual", 128, "centres"),
                "R16G16_SFLOAT",
                name="filament_dfg",
            ),
            ".ktx2",
            "Filament's DFG: 128 x 128 RG16F, x = n.v, y = perceptual roughness, R = B"
            " (integral of V*Fc), G = A + B (integral of V)",
            "Filament libs/ibl/src/CubemapIBL.cpp (CubemapIBL::DFG, DFV_Multiscatter),"
            " filament/src/details/DFG.h (DFG_LUT_SIZE 128; the engine's texture is RGB16F,"
            " blue the cloth term) and the shaders' textureLod(iblDFG, vec2(NoV,"
            " perceptualRoughness))",
        ),
        "filament_cloth": Preset(
            LutSpec(
                "dfg_multiscatter",
                "ggx",
                Axis("mu", 128, "centres"),
                Axis("perceptual", 128, "centres"),
                "R16G16B16_SFLOAT",
                name="filament_dfg_cloth",
                sheen="charlie_sheen_neubelt",
            ),
            ".ktx2",
            "Filament's engine DFG texture: 128 x 128 RGB16F, the filament preset's R and G"
            " plus B = the cloth term (Charlie distribution, Neubelt's visibility) at alpha ="
            " r^2",
            "Filament filament/src/details/DFG.cpp (RGB16F, DFG_LUT_SIZE x DFG_LUT_SIZE x 3)"
            " and libs/ibl/src/CubemapIBL.cpp (CubemapIBL::DFG with cloth: DFV_Charlie_Uniform"
            " at linear_roughness = coord^2)",
        ),
        "ue5": Preset(
            LutSpec(
                "dfg_multiscatter",
                "ggx",
                ue5_mu,
                ue5_r,
                "R16G16_UNORM",
                channels=("A+B", "B"),
                name="ue5_ggx_spec_energy",
            ),
            ".dds",
            "Unreal Engine 5's GGX specular energy table (View.ShadingEnergyGGXSpecTexture):"
            " 32 x 32 R16G16 UNORM, x = n.v, y = perceptual roughness (alpha = r^2), both at"
            " texel centres, R = integral of V (E with F = 1, = A + B), G = integral of V*Fc"
            " (B); E(F0, F90) = F0*R + (F90 - F0)*G",
            "Unreal Engine Shaders/Private/ShadingEnergyConservationTable.usf"
            " (BuildEnergyTableCS: NoV = (x + 0.5)/N, Roughness = (y + 0.5)/N, alpha ="
            " max(Roughness, 0.01)^2, channels (E, E*(1 - VoH)^5)),"
            " ShadingEnergyConservation.ush (GGXEnergyLookup samples float2(NoV, Roughness)"
            " bilinearly, clamped) and Renderer/Private/ShadingEnergyConservation.cpp (32 x 32,"
            " PF_G16R16 UNORM; PF_G32R32F when generated at run time)",
        ),
        "ue5_glass": Preset(
            LutSpec(
                "energy",
                "ggx_dielectric",
                ue5_mu,
                ue5_r,
                "R16G16_UNORM",
                channels=("E", "E_inv"),
                samples=1 << 14,  # the engine builder's NumSamples
                name="ue5_ggx_glass_energy",
                layers=Axis("eta", 32, "centres", 1.0, 3.0),
            ),
            ".dds",
            "Unreal Engine 5's GGX glass energy table (View.ShadingEnergyGGXGlassTexture):"
            " 32 x 32 x 32 R16G16 UNORM, x = n.v, y = perceptual roughness (alpha = r^2), z ="
            " (eta - 1)/2 for eta in [1, 3], all at texel centres; R = the total albedo"
            " (reflection + refraction) of the white rough glass for light entering the"
            " denser side (eta), G = for light leaving it (1/eta)",
            "Unreal Engine Shaders/Private/ShadingEnergyConservationTable.usf"
            " (BuildEnergyTableCS, BUILD_ENERGY_TABLE 1: Index = (id + 0.5)/N, NoV = Index.x,"
            " Roughness = Index.y, EtaIn = 1 + 2 Index.z, EtaOut = 1/EtaIn, weights"
            " GGXEvalReflection / GGXEvalRefraction = G2/G1 after choosing by Fresnel, x"
            " outside -> in, y inside -> out, written to OutputTexture3D[id]),"
            " PathTracing/Material/PathTracingGlossy.ush (GetGGXBasis: alpha = max(Roughness,"
            " 0.01)^2; a refraction to the light's side scores 0) and"
            " Renderer/Private/ShadingEnergyConservation.cpp (a 32^3 texture of the 2-D"
            " table's format, PF_G16R16)",
        ),
        "cycles": Preset(
            LutSpec(
                "energy",
                "ggx",
                # Cycles floors r at 1e-4 (alpha 1e-8); ggx takes alpha >= 1e-7.
                Axis("perceptual", 32, "ends", floor=_CYCLES_ROUGHNESS_FLOOR),
                Axis("mu", 32, "ends", floor=1e-4),
                "R32G32_SFLOAT",
                samples=4096,
                name="cycles_ggx_E",
            ),
            ".h",
            "Blender Cycles' ggx_E: 32 x 32 floats, x = r = i/31 (alpha = r^2), y = mu ="
            " j/31, mu clamped to >= 1e-4, r to >= 3.1623e-4 (Cycles: 1e-4); E_avg(r) in the"
            " second channel",
            "Blender intern/cycles/app/cycles_precompute.cpp (precompute_terms ggx_E and"
            " ggx_Eavg, data[y * nx + x]) and kernel/util/lookup_table.h (x = saturate(x) *"
            " (size - 1): samples at the ends)",
        ),
        "cycles_glass": Preset(
            _cycles_16("energy", "ggx_dielectric", "eta_z", "cycles_ggx_glass_E"),
            ".h",
            "Blender Cycles' ggx_glass_E and ggx_glass_Eavg: 16 x 16 x 16 floats, x = r ="
            " i/15 (alpha = r^2), y = mu = j/15, slices z = k/15 with eta = (1 + z^2)/(1 -"
            " z^2) (z = F0^(1/4)); r clamped to >= 3.1623e-4 (Cycles: 1e-4), mu to >= 1e-4,"
            " z to [1e-4, 0.99]; E = the total albedo (reflection + transmission) of the"
            " white rough glass for light from the less dense side; E_avg(r, z) in the"
            " second channel",
            "Blender intern/cycles/app/cycles_precompute.cpp (precompute_terms ggx_glass_E and"
            " ggx_glass_Eavg: rough = x/(nx - 1), mu = y/(ny - 1), z = z/(nz - 1) clamped to"
            " [1e-4, 0.99], ior = ior_from_F0(z^4), data[y * nx + x] per slice z) and"
            " kernel/closure/bsdf_microfacet.h (microfacet_ggx_preserve_energy:"
            " lookup_table_read_3D(kg, rough, mu, z, ...), rough = sqrt(alpha), z ="
            " sqrt(|ior - 1|/(ior + 1)), the _inv_ tables at 1/ior when ior < 1)",
        ),
        "cycles_glass_inv": Preset(
            _cycles_16("energy", "ggx_dielectric", "eta_z_inside", "cycles_ggx_glass_inv_E"),
            ".h",
            "Blender Cycles' ggx_glass_inv_E and ggx_glass_inv_Eavg: the cycles_glass"
            " layout for light from the denser side, eta = (1 - z^2)/(1 + z^2) (Cycles reads"
            " it at z of 1/ior when ior < 1). The values are the single-scattering model's:"
            " Cycles' own are higher near grazing incidence, as its sampler keeps a"
            " refraction back to the light's side (docs/luts.md)",
            "Blender intern/cycles/app/cycles_precompute.cpp (precompute_terms"
            " ggx_glass_inv_E and ggx_glass_inv_Eavg: precompute_ggx_glass_E at 1/ior) and"
            " kernel/closure/bsdf_microfacet.h (microfacet_ggx_preserve_energy)",
        ),
        "cycles_gen_schlick": Preset(
            _cycles_16("gen_schlick", "ggx_gen_schlick", "exponent_z", "cycles_ggx_gen_schlick_s"),
            ".h",
            "Blender Cycles' ggx_gen_schlick_s: 16 x 16 x 16 floats, x = r = i/15 (alpha ="
            " r^2), y = mu = j/15, slices z = k/15 with exponent = 5 (1 - z)/z; r clamped to"
            " >= 3.1623e-4 (Cycles: 1e-4), mu to >= 1e-4, z to [1e-4, 0.99]; s the blend of"
            " generalized Schlick's F0 and F90 in the albedo, E(F0, F90) = E * mix(F0, F90, s)",
            "Blender intern/cycles/app/cycles_precompute.cpp (precompute_ggx_gen_schlick_s:"
            " f0 = (0, 1, 0), f90 = (1, 1, 0), s = eval.x / eval.y, saturated; the term"
            " ggx_gen_schlick_s at exponent = 5 (1 - z)/z, 1 << 20 samples) and"
            " kernel/closure/bsdf_microfacet.h (bsdf_microfacet_estimate_albedo:"
            " lookup_table_read_3D(kg, rough, cos_NI, z, ...) with z = 1/(0.2 exponent + 1),"
            " reflectance = mix(f0, f90, s))",
        ),
        "gltf": Preset(
            LutSpec(
                "dfg",
                "ggx",
                Axis("mu", 1024, "centres"),
                Axis("perceptual", 1024, "centres"),
                "R16G16_SFLOAT",
                samples=256,
                name="gltf_ggx_lut",
            ),
            ".ktx2",
            "glTF Sample Viewer's GGX LUT: 1024 x 1024, x = n.v, y = perceptual roughness,"
            " R = scale A, G = bias B (specularColor * brdf.x + brdf.y)",
            "glTF-Sample-Viewer ibl_sampler.js (lutResolution = 1024), ibl_filtering.frag"
            " LUT() (A += (1 - Fc) * V_pdf, B += Fc * V_pdf, V with roughness^4 = alpha^2)"
            " and ibl.glsl (texture(u_GGXLUT, vec2(NdotV, perceptualRoughness))); its"
            " texture format is a render target's, not confirmed as RG16F",
        ),
        "enterprise": Preset(
            LutSpec(
                "energy",
                "ggx",
                Axis("mu", 32, "centres"),
                r32_centres,
                "R16G16_SFLOAT",
                samples=4096,
                name="enterprise_pbr_E",
            ),
            ".exr",
            "Enterprise PBR's Kulla-Conty compensation inputs E(mu, alpha) and E_avg:"
            " 32 x 32 over mu and perceptual roughness",
            "Dassault Systemes Enterprise PBR Shading Model specification (versions 2019x to"
            " 2025x): the pages read describe the BSDF, with roughness the user parameter"
            " (alpha = r^2), but give no table layout. Its published E_avg at the last"
            " roughness, 0.42276, is GGX's at r = 31.5/32 (the last texel centre of 32:"
            " 0.42293) and not at r = 1 (0.40913), which places the roughness axis at"
            " texel centres; the mu axis, the resolution along it and the format are this"
            " preset's choice",
        ),
    }


def _cycles_16(kind: str, model: str, layer: str, name: str) -> LutSpec:
    """A Cycles 16^3 table over (r, mu, z), all at the ends, the third axis' quantity
    ``layer`` clamped as Cycles' generator clamps z, to [1e-4, 0.99]; floats, every
    channel of the kind but the dielectric's other side."""
    return LutSpec(
        kind,
        model,
        Axis("perceptual", 16, "ends", floor=_CYCLES_ROUGHNESS_FLOOR),
        Axis("mu", 16, "ends", floor=1e-4),
        "R32G32_SFLOAT" if kind == "energy" else "R32_SFLOAT",
        samples=4096,
        name=name,
        layers=Axis(layer, 16, "ends", floor=1e-4, ceiling=0.99),
    )


def preset(name: str, **changes: Any) -> LutSpec:
    """The :class:`LutSpec` of a preset, with fields replaced by ``changes`` (e.g.
    ``samples=64``)."""
    if name not in PRESETS:
        raise ValueError(f"preset: unknown {name!r}; use {', '.join(PRESETS)}")
    return dataclasses.replace(PRESETS[name].spec, **changes)


# ------------------------------------------------------------------------------ values


def _integrate(
    spec: LutSpec,
    mu_q: np.ndarray,
    rough_q: np.ndarray,
    seed: int,
    progress: Any = None,
    layer_q: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The kind's channels and standard errors at quantity values ``mu_q`` x ``rough_q``
    (x ``layer_q`` for a 3-D table), shape ``(len(mu_q), len(rough_q)[, len(layer_q)],
    channels)`` (every channel of the kind)."""
    from . import _albedo

    mu = spec.mu_axis.physical(mu_q)
    rough = spec.roughness_axis.physical(rough_q)
    extra: dict[str, Any] = {} if progress is None else {"progress": progress}
    if spec.kind == "gen_schlick":
        assert layer_q is not None and spec.layers is not None
        exponent = spec.layers.physical(layer_q)
        return _gen_schlick_blend(spec, mu, rough, exponent, seed, extra)
    if spec.layers is not None:
        assert layer_q is not None
        eta = spec.layers.physical(layer_q)
        values, errors = [], []
        for side, index in zip(_side_needs(spec), (eta, 1 / eta), strict=True):
            e, e_se, avg, avg_se = (np.zeros(index.shape) for _ in range(4))
            if side is None:  # no channel of this side is kept
                pass
            elif side == "E":  # E alone: no E_avg run
                e, e_se = _albedo.transmitting_e(
                    spec.model, mu, rough, index, samples=spec.samples, seed=seed, **extra
                )
            else:
                ec = _albedo.energy_compensation_table(
                    spec.model,
                    mu,
                    rough,
                    eta=index,
                    samples=spec.samples,
                    tol=None,
                    seed=seed,
                    **extra,
                )
                e, e_se = ec.e, ec.stderr
                avg = np.broadcast_to(ec.e_avg, e.shape)
                avg_se = np.broadcast_to(ec.e_avg_stderr, e.shape)
            shape = (mu.size, rough.size, eta.size)
            values += [np.broadcast_to(e, shape), np.broadcast_to(avg, shape)]
            errors += [np.broadcast_to(e_se, shape), np.broadcast_to(avg_se, shape)]
        return np.stack(values, axis=-1), np.stack(errors, axis=-1)
    if spec.kind == "energy":
        en = _albedo.energy_compensation_table(
            spec.model, mu, rough, samples=spec.samples, tol=None, seed=seed, **extra
        )
        value = np.stack([en.e, np.broadcast_to(en.e_avg, en.e.shape)], axis=-1)
        stderr = np.stack([en.stderr, np.broadcast_to(en.e_avg_stderr, en.e.shape)], axis=-1)
        return value, stderr
    t = _albedo.dfg_table(spec.model, mu, rough, samples=spec.samples, seed=seed, **extra)
    a, b = t.value[..., 0], t.value[..., 1]
    se_a, se_b = t.stderr[..., 0], t.stderr[..., 1]
    cloth, se_cloth = np.zeros_like(a), np.zeros_like(a)
    if spec.sheen is not None:
        # The cloth channel is the sheen model's albedo at the same parameter value, held
        # at the sheen model's smallest value below it (its cells are dfg_table's).
        weights, low = _sheen(spec)
        axes = {"mu": mu, spec.param: np.maximum(rough, low)}
        c = _albedo.albedo_table(
            spec.sheen, axes, samples=spec.samples, seed=seed, **weights, **extra
        )
        cloth, se_cloth = c.value[..., 0], c.stderr[..., 0]
    if spec.kind == "dfg":
        return np.stack([a, b, cloth], -1), np.stack([se_a, se_b, se_cloth], -1)
    # A + B is the F0 = 1 integral: its stderr is the one dfg_table folded into A's.
    se_one = np.sqrt(np.maximum(se_a**2 - se_b**2, 0.0))
    return np.stack([b, a + b, cloth], -1), np.stack([se_b, se_one, se_cloth], -1)


def _sheen(spec: LutSpec) -> tuple[dict[str, Any], float]:
    """The cloth channel's weights (the sheen model's ``ks`` = 1, its other weights 0) and
    the smallest value of the roughness parameter the sheen model takes."""
    from . import _albedo

    assert spec.sheen is not None
    specs = _spec.specs()
    if spec.sheen not in specs:
        raise ValueError(f"sheen: unknown model {spec.sheen!r} (brdf_rs.models() lists them)")
    param = next((p for p in specs[spec.sheen]["params"] if p["name"] == spec.param), None)
    if param is None:
        raise ValueError(
            f"sheen: {spec.sheen} has no {spec.param}, the table's roughness parameter"
        )
    low = float(param["min"])
    if param["min_open"]:
        low = float(np.nextafter(low, np.inf))
    weights = _albedo._sheen_weights(spec.sheen, spec.model, spec.param, np.array([low]))
    return weights, low


def _gen_schlick_blend(
    spec: LutSpec,
    mu: np.ndarray,
    rough: np.ndarray,
    exponent: np.ndarray,
    seed: int,
    extra: dict[str, Any],
) -> tuple[np.ndarray, np.ndarray]:
    """A ``gen_schlick`` table's channels (s, E) over ``(mu, alpha, exponent)``: the
    albedos with ``F0 = 0, F90 = 1`` and with ``F = 1`` (``F0 = F90 = 1``), integrated at
    the same cells, and their ratio. Its standard error is propagated to first order as
    if the two were independent: they share their samples, which makes the ratio's error
    smaller, so this is an upper estimate."""
    from . import _albedo

    axes = {"mu": mu, spec.param: rough, "exponent": exponent}
    common = {"samples": spec.samples, "seed": seed, "tol": None, "kd": 0.0, **extra}
    blend = _albedo.albedo_table(spec.model, axes, f0=0.0, f90=1.0, **common)
    one = _albedo.albedo_table(spec.model, axes, f0=1.0, f90=1.0, **common)
    x, se_x = blend.value[..., 0], blend.stderr[..., 0]
    e, se_e = one.value[..., 0], one.stderr[..., 0]
    positive = e > 0
    safe = np.where(positive, e, 1.0)
    s = np.where(positive, x / safe, 0.0)
    se_s = np.where(positive, np.hypot(se_x, s * se_e) / safe, 0.0)
    return np.stack([s, e], axis=-1), np.stack([se_s, se_e], axis=-1)


def _side_needs(spec: LutSpec) -> list[str | None]:
    """For a dielectric's 3-D table: what each side (at ``eta``, then at ``1/eta``) must
    compute for the channels kept: ``"E"`` alone, ``"E+avg"`` or None."""
    chosen = set(spec.channel_names)
    return [
        "E+avg" if avg in chosen else ("E" if e in chosen else None)
        for e, avg in (("E", "E_avg"), ("E_inv", "E_inv_avg"))
    ]


def _to_image(spec: LutSpec, a: np.ndarray) -> np.ndarray:
    """``(mu, roughness[, eta], channels)`` to the image's ``([layers,] rows, columns,
    channels)``, kept channels only."""
    if spec.layers is not None:
        a = np.moveaxis(a, 2, 0)  # (eta, mu, roughness, channels)
        if spec.rows.role != "mu":
            a = np.swapaxes(a, 1, 2)
    elif spec.rows.role != "mu":
        a = np.swapaxes(a, 0, 1)
    keep = [spec.kind_channels.index(c) for c in spec.channel_names]
    return np.ascontiguousarray(a[..., keep])


def quantize(values: np.ndarray, fmt: str) -> tuple[np.ndarray, np.ndarray]:
    """The stored texels of ``values`` in format ``fmt`` and what they decode to
    (float64): UNORM is ``round(clip(v, 0, 1) * 65535)``, SFLOAT the nearest half or
    float."""
    if fmt not in FORMATS:
        raise ValueError(f"format: unknown {fmt!r}; use {', '.join(FORMATS)}")
    f = FORMATS[fmt]
    v = np.asarray(_arrays.as_numeric("values", values), dtype=np.float64)
    _finite("values", v)
    if f.encoding == "unorm":
        stored = np.round(np.clip(v, 0.0, 1.0) * 65535.0).astype(f.dtype)
        return stored, stored.astype(np.float64) / 65535.0
    with np.errstate(over="ignore"):
        stored = v.astype(f.dtype)
    return stored, stored.astype(np.float64)


def _finite(name: str, values: np.ndarray) -> None:
    """Refuses a NaN or infinite value, naming its index."""
    bad = _arrays.first_bad(np.isfinite(values))
    if bad is not None:
        where = f"{bad}" if bad else ""
        raise ValueError(f"{name}{where} = {values[tuple(bad)]}: must be finite")


def bilinear(image: np.ndarray, columns: Axis, rows: Axis, col_q: Any, row_q: Any) -> np.ndarray:
    """Bilinear lookup of ``image`` (rows, columns, channels) at axis quantities, with the
    axes' texel mapping and clamping to the edge texels (a GPU's clamp-to-edge)."""
    img = np.asarray(_arrays.as_numeric("image", image), dtype=np.float64)
    if img.ndim != 3 or img.shape[:2] != (rows.size, columns.size):
        raise ValueError(
            f"image: expected shape ({rows.size}, {columns.size}, channels) for these axes,"
            f" got {img.shape}"
        )
    col = np.asarray(_arrays.as_numeric("col_q", col_q), dtype=np.float64)
    row = np.asarray(_arrays.as_numeric("row_q", row_q), dtype=np.float64)
    _finite("col_q", col)
    _finite("row_q", row)
    x = columns.texel(col)
    y = rows.texel(row)
    x, y = np.broadcast_arrays(x, y)
    x0 = np.minimum(np.floor(x).astype(np.intp), columns.size - 2)
    y0 = np.minimum(np.floor(y).astype(np.intp), rows.size - 2)
    fx = (x - x0)[..., None]
    fy = (y - y0)[..., None]
    top = img[y0, x0] * (1 - fx) + img[y0, x0 + 1] * fx
    bottom = img[y0 + 1, x0] * (1 - fx) + img[y0 + 1, x0 + 1] * fx
    return np.asarray(top * (1 - fy) + bottom * fy)


def trilinear(
    volume: np.ndarray,
    columns: Axis,
    rows: Axis,
    layers: Axis,
    col_q: Any,
    row_q: Any,
    layer_q: Any,
) -> np.ndarray:
    """Trilinear lookup of ``volume`` (layers, rows, columns, channels) at axis
    quantities: :func:`bilinear` in the two slices around ``layer_q``, blended along the
    layers with the same texel mapping and clamping (a GPU's 3-D texture filter)."""
    vol = np.asarray(_arrays.as_numeric("volume", volume), dtype=np.float64)
    if vol.ndim != 4 or vol.shape[0] != layers.size:
        raise ValueError(
            f"volume: expected shape ({layers.size}, {rows.size}, {columns.size}, channels)"
            f" for these axes, got {vol.shape}"
        )
    layer = np.asarray(_arrays.as_numeric("layer_q", layer_q), dtype=np.float64)
    _finite("layer_q", layer)
    col, row, layer = np.broadcast_arrays(
        np.asarray(_arrays.as_numeric("col_q", col_q), dtype=np.float64),
        np.asarray(_arrays.as_numeric("row_q", row_q), dtype=np.float64),
        layer,
    )
    z = layers.texel(layer)
    z0 = np.minimum(np.floor(z).astype(np.intp), layers.size - 2)
    fz = (z - z0)[..., None]
    out = np.empty((*z.shape, vol.shape[-1]))
    for k in np.unique(z0):
        at = z0 == k
        near = bilinear(vol[k], columns, rows, col[at], row[at])
        far = bilinear(vol[k + 1], columns, rows, col[at], row[at])
        out[at] = near * (1 - fz[at]) + far * fz[at]
    return out


# ------------------------------------------------------------------------------ budget


@dataclasses.dataclass(frozen=True)
class Budget:
    """A LUT's error budget, per channel (lists in the channels' order).

    ``mc_max_stderr``: the largest Monte Carlo standard error of a texel (one sigma;
    about 99.7 % of texels are within 3 of them of the exact integral when the errors are
    normal). For a table computed without sampling (an energy table whose E is in closed
    form, :meth:`LutSpec.recipe`'s ``estimator``) it is the largest error bound of a
    texel instead, and ``confidence`` says so. ``quant_worst`` / ``quant_rms``: the
    exact largest and RMS difference between the stored (quantized, decoded) texels and
    the float64 integrals.
    ``interp_worst``: the largest difference between the bilinear (3-D: trilinear)
    lookup of the float64 table and a fresh Monte Carlo integral (an independent seed)
    at ``interp_points`` points between the texels (midpoints between neighbouring
    texels, and the range ends); it holds the texels' and the reference's Monte Carlo
    noise as well as the interpolation error. The reference's standard error is up to
    ``interp_ref_stderr``.
    ``interp_worst_at`` says where (``[mu, roughness parameter]``, and the third axis'
    value for a 3-D table), ``interp_worst_interior`` is the worst over the points
    between the first and last texels of every axis (leaving out the margins a
    texel-centre table clamps, where the lookup holds the edge texel's value).

    ``total`` = quant_worst + interp_worst + 3 * interp_ref_stderr + 3 * mc_max_stderr:
    an estimate, at 3 sigma per point, of how far the file's lookup is from the exact
    function at the points checked and near them. It is not a guarantee over the whole
    table: the interpolation error is measured at finitely many points, and at 3 sigma
    per point about 0.3 % of points may exceed it by chance when the errors are normal.
    """

    channels: list[str]
    mc_max_stderr: list[float]
    quant_worst: list[float]
    quant_rms: list[float]
    interp_worst: list[float]
    interp_ref_stderr: list[float]
    interp_points: int
    interp_worst_at: list[list[float]]
    interp_worst_interior: list[float]
    total: list[float]
    confidence: str = (
        "an estimate per point checked, at 3 sigma of the texels' and the reference"
        " integrals' Monte Carlo standard errors (about 99.7 % per point), not a bound"
        " over the whole table"
    )

    def to_json(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


def _check_points(axis: Axis, limit: int) -> np.ndarray:
    """Axis quantities between the texels: midpoints of neighbouring samples, plus the
    range's ends (for centres: the clamped margins). At most about ``limit``."""
    p = axis.positions()
    if axis.placement == "centres":
        p = np.concatenate([[axis.lo], p, [axis.hi]])
    mids = 0.5 * (p[:-1] + p[1:])
    if mids.size > limit:
        idx = np.unique(np.round(np.linspace(0, mids.size - 1, limit)).astype(np.intp))
        mids = mids[idx]
    pts = np.concatenate([mids, [axis.lo, axis.hi]]) if axis.placement == "centres" else mids
    return np.unique(np.maximum(pts, axis.floor))


#: The smallest mu the interpolation error is checked at (engines clamp n.v to it).
_GRAZING_MU = 1e-4


def _check_grid(spec: LutSpec, interp_limit: int) -> tuple[np.ndarray, np.ndarray]:
    """The mu and roughness quantities the interpolation error is checked at. ``mu = 0``
    exactly is 0 by convention (no light above the horizon): its end is checked at 1e-4,
    the limit engines clamp n.v to. A roughness the model refuses (alpha = 0) is not
    checked."""
    return _checkable(
        spec,
        _check_points(spec.mu_axis, interp_limit),
        _check_points(spec.roughness_axis, interp_limit),
    )


def _checkable(
    spec: LutSpec, mu_pts: np.ndarray, r_pts: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Axis quantities to check a table (or a fit of it) at, as :func:`_check_grid` takes
    them: ``mu`` from 1e-4 up (sorted, once each), roughness values the model refuses
    left out."""
    # Clamped in physical units: on a sqrt_mu axis mu = 1e-4 is the quantity 0.01.
    grazing = float(spec.mu_axis.quantity_of(_GRAZING_MU))
    mu_pts = np.unique(np.maximum(mu_pts, grazing))
    phys = spec.roughness_axis.physical(r_pts)
    r_pts = r_pts[[_spec.admits(spec.model, spec.param, float(x)) for x in phys]]
    return mu_pts, r_pts


def _worst_inside(
    spec: LutSpec,
    mq: np.ndarray,
    rq: np.ndarray,
    err: np.ndarray,
    eq: np.ndarray | None = None,
) -> np.ndarray:
    """The largest of ``err`` (points x channels, the points at axis quantities ``mq`` x
    ``rq`` [x ``eq``]) between the first and last texels of every axis, where the table
    interpolates rather than clamps; 0 where no point is."""
    m, r = spec.mu_axis.positions(), spec.roughness_axis.positions()
    inside = (mq >= m[0]) & (mq <= m[-1]) & (rq >= r[0]) & (rq <= r[-1])
    if spec.layers is not None and eq is not None:
        e = spec.layers.positions()
        inside &= (eq >= e[0]) & (eq <= e[-1])
    inside = inside.reshape(-1)
    return err[inside].max(axis=0) if inside.any() else np.zeros(err.shape[-1])


def _layer_check_points(spec: LutSpec, interp_limit: int) -> np.ndarray | None:
    """A 3-D table's layer quantities (eta, the exponent) the interpolation error is
    checked at (values the model refuses left out); None for a 2-D table."""
    if spec.layers is None:
        return None
    pts = _check_points(spec.layers, interp_limit)
    phys = spec.layers.physical(pts)
    return pts[[_spec.admits(spec.model, spec.layers.role, float(x)) for x in phys]]


def passes(spec: LutSpec, interp_limit: int = 64) -> list[int]:
    """The cells of each integration run :func:`build` makes, in order (what a progress
    callback counts: ``progress(cells_done, samples_done)`` restarts at 0 with each). An
    energy table's ``E_avg`` run counts its first round, 30 cells per roughness (and
    index, for a 3-D table): where it halves panels it counts on past that."""
    mu_pts, r_pts = _check_grid(spec, interp_limit)
    layer_pts = _layer_check_points(spec, interp_limit)
    runs = []
    if spec.kind == "gen_schlick":
        assert layer_pts is not None
        # E(F0 = 0, F90 = 1), then E(F0 = F90 = 1), on the grid and between the texels
        for cells in (
            spec.mu_axis.size * spec.roughness_axis.size * spec.shape[0],
            mu_pts.size * r_pts.size * layer_pts.size,
        ):
            runs += [cells, cells]
        return runs
    if spec.layers is not None:
        assert layer_pts is not None
        for m, r, e in (
            (spec.mu_axis.size, spec.roughness_axis.size, spec.layers.size),
            (mu_pts.size, r_pts.size, layer_pts.size),
        ):
            # each side kept: E on the grid, then (with an E_avg channel) E_avg's first round
            for need in _side_needs(spec):
                if need is not None:
                    runs += [m * r * e] + ([30 * r * e] if need == "E+avg" else [])
        return runs
    for m, r in ((spec.mu_axis.size, spec.roughness_axis.size), (mu_pts.size, r_pts.size)):
        # dfg: F0 = 1, F0 = 0, then the cloth channel's sheen model when there is one;
        # energy: E on the grid, then E_avg's adaptive rule, 30 cells per roughness in
        # its first round (more where it halves panels).
        if spec.kind == "energy":
            runs += [m * r, 30 * r]
        else:
            runs += [m * r] * (3 if spec.sheen is not None else 2)
    return runs


def _budget(
    spec: LutSpec,
    image: np.ndarray,
    stderr: np.ndarray,
    decoded: np.ndarray,
    interp_limit: int,
    progress: Any = None,
) -> tuple[Budget, Checks]:
    diff = decoded - image
    flat = diff.reshape(-1, diff.shape[-1])
    mu_pts, r_pts = _check_grid(spec, interp_limit)
    layer_pts = _layer_check_points(spec, interp_limit)
    ref, ref_se = _integrate(spec, mu_pts, r_pts, spec.seed + 1, progress, layer_pts)
    keep = [spec.kind_channels.index(c) for c in spec.channel_names]
    ref, ref_se = ref[..., keep], ref_se[..., keep]
    grids = np.meshgrid(mu_pts, r_pts, *([] if layer_pts is None else [layer_pts]), indexing="ij")
    mq, rq = grids[0], grids[1]
    eq = grids[2] if layer_pts is not None else None
    looked = _lookup_q(spec, image, mq, rq, eq)
    ierr = np.abs(looked - ref).reshape(-1, ref.shape[-1])
    axes = [spec.mu_axis, spec.roughness_axis] + ([spec.layers] if spec.layers else [])
    interior = _worst_inside(spec, mq, rq, ierr, eq)
    worst = ierr.argmax(axis=0)
    where = [
        [float(a.physical(g.reshape(-1)[k])) for a, g in zip(axes, grids, strict=True)]
        for k in worst
    ]
    mc = stderr.reshape(-1, stderr.shape[-1]).max(axis=0)
    qw = np.abs(flat).max(axis=0)
    iw = ierr.max(axis=0)
    rse = ref_se.reshape(-1, ref_se.shape[-1]).max(axis=0)
    budget = Budget(
        channels=list(spec.channel_names),
        mc_max_stderr=mc.tolist(),
        quant_worst=qw.tolist(),
        quant_rms=np.sqrt(np.mean(flat**2, axis=0)).tolist(),
        interp_worst=iw.tolist(),
        interp_ref_stderr=rse.tolist(),
        interp_points=int(mq.size),
        interp_worst_at=where,
        interp_worst_interior=interior.tolist(),
        total=_total(qw, iw, rse, mc).tolist(),
    )
    if _closed_form(spec.kind, spec.model):
        budget = dataclasses.replace(budget, confidence=_CLOSED_FORM_CONFIDENCE)
    return budget, Checks(mq, rq, ref, ref_se, eq)


def _lookup_q(spec: LutSpec, image: np.ndarray, mq: Any, rq: Any, eq: Any = None) -> np.ndarray:
    """The filtered lookup of ``image`` at axis quantities (mu, roughness[, layer])."""
    cols, rows = (mq, rq) if spec.columns.role == "mu" else (rq, mq)
    if spec.layers is None:
        return bilinear(image, spec.columns, spec.rows, cols, rows)
    return trilinear(image, spec.columns, spec.rows, spec.layers, cols, rows, eq)


@dataclasses.dataclass(frozen=True)
class Checks:
    """The integrals the interpolation error was measured against: at axis quantities
    ``mu_q`` x ``roughness_q`` (2-D, mu first; x ``layer_q`` for a 3-D table), ``value``
    and ``stderr`` (kept channels last), integrated with an independent seed."""

    mu_q: np.ndarray
    roughness_q: np.ndarray
    value: np.ndarray
    stderr: np.ndarray
    layer_q: np.ndarray | None = None


# --------------------------------------------------------------------------------- Lut


@dataclasses.dataclass(frozen=True)
class Lut:
    """A built LUT: ``image`` the float64 integrals (rows, columns, channels; a 3-D
    table's: layers, rows, columns, channels),
    ``stderr`` their standard errors, ``stored`` the texels in the spec's format and
    ``decoded`` what they decode to; ``budget`` its error budget."""

    spec: LutSpec
    image: np.ndarray
    stderr: np.ndarray
    stored: np.ndarray
    decoded: np.ndarray
    budget: Budget
    checks: Checks | None = dataclasses.field(default=None, repr=False, compare=False)

    @property
    def content_hash(self) -> str:
        return self.spec.content_hash()

    def lookup(self, mu: Any, roughness: Any, layer: Any = None) -> np.ndarray:
        """Bilinear lookup of the stored table at incidence cosines ``mu`` and values of
        the model's roughness parameter (``alpha``), as a GPU's filter reads it; a 3-D
        table's is trilinear and takes the layers axis' value too, ``layer`` (the relative
        index eta, or generalized Schlick's exponent)."""
        role = self.spec.layer_role
        if (layer is None) != (role is None):
            raise ValueError(
                f"layer: a 3-D table (layers over {role}) needs its {role}; a 2-D table takes none"
                if layer is None
                else "layer: this table is 2-D (no layers axis); leave layer out"
            )
        for label, value in (("mu", mu), ("roughness", roughness), ("layer", layer)):
            if value is not None:
                _check_finite(label, value)
        m = self.spec.mu_axis.quantity_of(mu)
        r = self.spec.roughness_axis.quantity_of(roughness)
        e = None if self.spec.layers is None else self.spec.layers.quantity_of(layer)
        return _lookup_q(self.spec, self.decoded, m, r, e)

    def meta(self, output: str = "OUT") -> dict[str, Any]:
        """The metadata every file carries."""
        s = self.spec
        return {
            "brdf_rs_lut": 1,
            "content_hash": self.content_hash,
            "command": s.command(output),
            "recipe": s.recipe(),
            "width": s.columns.size,
            "height": s.rows.size,
            "layout": "row-major, row 0 first (the top of an image; texture coordinate"
            " v = 0 in GL, Vulkan and D3D when uploaded as stored), channels interleaved",
            "columns": s.columns.describe(s.param),
            "rows": s.rows.describe(s.param),
            "channels": {c: _channel_text(s, c) for c in s.channel_names},
            "budget": self.budget.to_json(),
        } | (
            {}
            if s.layers is None
            else {
                "depth": s.layers.size,
                "layers": s.layers.describe(s.param),
                "layout": "slices (layers) outermost, slice 0 first (texture coordinate"
                " w = 0), each slice row-major, row 0 first, channels interleaved:"
                " DATA[((layer * HEIGHT + row) * WIDTH + column) * CHANNELS + channel]; in"
                " an .exr or .png the slices are stacked top to bottom, slice 0 on top",
            }
        )

    def save(self, path: str | Path) -> Path:
        """Writes the LUT by the suffix of ``path`` (:data:`CONTAINERS`), atomically."""
        from . import _lutfiles

        return _lutfiles.save(self, Path(path))


def _check_finite(label: str, value: Any) -> None:
    """Raises ``ValueError`` naming ``label`` and the first non-finite element."""
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{label}: expected numbers, got {value!r}") from None
    bad = ~np.isfinite(a)
    if bad.any():
        if a.ndim == 0:
            raise ValueError(f"{label}: expected a finite number, got {float(a)!r}")
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        at = index[0] if len(index) == 1 else index
        raise ValueError(f"{label}: expected finite numbers, got {float(a[index])!r} at index {at}")


def build(
    spec: LutSpec, *, interp_limit: int = 64, progress: Callable[[int, int], None] | None = None
) -> Lut:
    """Integrates the table ``spec`` describes and measures its error budget.

    ``interp_limit`` caps the points checked along each axis for the interpolation error
    (midpoints between texels, spread over the axis when there are more)."""
    if not isinstance(spec, LutSpec):
        raise TypeError(f"spec: expected a LutSpec, got {type(spec).__name__}")
    if isinstance(interp_limit, bool) or not isinstance(interp_limit, int) or interp_limit < 2:
        raise ValueError(f"interp_limit: expected an integer >= 2, got {interp_limit!r}")
    layer_q = None if spec.layers is None else spec.layers.positions()
    value, se = _integrate(
        spec,
        spec.mu_axis.positions(),
        spec.roughness_axis.positions(),
        spec.seed,
        progress,
        layer_q,
    )
    image, stderr = _to_image(spec, value), _to_image(spec, se)
    stored, decoded = quantize(image, spec.format)
    budget, checks = _budget(spec, image, stderr, decoded, interp_limit, progress)
    return Lut(spec, image, stderr, stored, decoded, budget, checks)


@dataclasses.dataclass(frozen=True)
class ErrorChoice:
    """:func:`meet_error`'s answer: ``lut`` the cheapest table meeting the error (None
    when none does), and every candidate tried: ``(size, format, worst total)``."""

    lut: Lut | None
    tried: list[tuple[int, str, float]]
    max_error: float


def meet_error(
    spec: LutSpec,
    max_error: float,
    *,
    sizes: Sequence[int] = (16, 32, 64, 128, 256, 512),
    interp_limit: int = 64,
) -> ErrorChoice:
    """The smallest square resolution (both axes ``size`` texels, their quantities,
    placements and ranges kept) and, at it, the smallest pixel format of the spec's
    channel count whose budget total (quantization + interpolation + 3 standard errors of
    the reference and of the texels, worst channel) is at most ``max_error``. Sizes are
    tried in order; the Monte Carlo part is the spec's ``samples``' (raise them when it
    alone exceeds the error)."""
    if not (isinstance(max_error, (int, float)) and math.isfinite(max_error) and max_error > 0):
        raise ValueError(f"max_error: expected a positive number, got {max_error!r}")
    _two_d("meet_error", spec)
    sizes = [int(n) for n in sizes]
    if not sizes or any(n < 2 for n in sizes):
        raise ValueError(f"sizes: expected sizes of at least 2 texels, got {sizes}")
    nc = len(spec.channel_names)
    formats = sorted(
        (f for f in FORMATS.values() if f.channels == nc), key=lambda f: (f.bits, f.encoding)
    )
    tried: list[tuple[int, str, float]] = []
    for n in sizes:
        trial = dataclasses.replace(
            spec,
            columns=dataclasses.replace(spec.columns, size=n),
            rows=dataclasses.replace(spec.rows, size=n),
            format=formats[-1].name,
        )
        table = build(trial, interp_limit=interp_limit)
        for f in formats:
            # The trial's integrals in this format: the budget measured once, with the same
            # check points, so the answer's total is the one compared here.
            candidate = _requantize(table, f.name)
            total = float(max(candidate.budget.total))
            tried.append((n, f.name, total))
            if total <= max_error:
                return ErrorChoice(candidate, tried, max_error)
    return ErrorChoice(None, tried, max_error)


def _requantize(table: Lut, fmt: str) -> Lut:
    """``table``'s integrals stored in pixel format ``fmt`` (same channel count): the
    quantization part of the budget remeasured, the rest kept."""
    spec = dataclasses.replace(table.spec, format=fmt)
    stored, decoded = quantize(table.image, fmt)
    flat = (decoded - table.image).reshape(-1, table.image.shape[-1])
    qw = np.abs(flat).max(axis=0)
    b = table.budget
    budget = dataclasses.replace(
        b,
        quant_worst=qw.tolist(),
        quant_rms=np.sqrt(np.mean(flat**2, axis=0)).tolist(),
        total=_total(
            qw,
            np.asarray(b.interp_worst),
            np.asarray(b.interp_ref_stderr),
            np.asarray(b.mc_max_stderr),
        ).tolist(),
    )
    return Lut(spec, table.image, table.stderr, stored, decoded, budget, table.checks)


def _total(
    quant: np.ndarray, interp: np.ndarray, ref_stderr: np.ndarray, mc: np.ndarray
) -> np.ndarray:
    """The budget's total per channel (see :class:`Budget`): the interpolation error
    measured against a reference known to ``ref_stderr``, so 3 of those are added."""
    return np.asarray(quant + interp + 3 * ref_stderr + 3 * mc)


def fit(
    table: Lut, degree: int = 6, denominator: int = 0, *, dense: bool | DenseCheck = True
) -> Fit:
    """A minimax fit of ``table``'s channels in its two axis fractions: a polynomial of
    total ``degree``, or with ``denominator`` > 0 a rational function of total degrees
    ``degree`` over ``denominator``. Its error is measured against the texels, against the
    integrals between them and (``dense``) against fresh integrals on a grid four times
    denser than the texels, which with the float32 evaluation's rounding gives its
    ``max_error`` (a ``Fit``: call it, or ``.save("fit.glsl")`` for shader code; see
    docs/luts.md). ``dense`` may be a :func:`dense_check` of the table's spec, computed
    once for several fits; ``False`` skips that check (then ``max_error`` rests on the
    points between the texels only)."""
    from . import _lutfit

    if not isinstance(table, Lut):
        raise TypeError(f"table: expected a Lut (lut.build's), got {type(table).__name__}")
    _two_d("fit", table.spec)
    return _lutfit.fit(table, degree, denominator, dense)


def _two_d(what: str, spec: LutSpec) -> None:
    """Refuses a 3-D table where only 2-D ones are handled."""
    if spec.layers is not None:
        raise ValueError(
            f"{what}: handles 2-D tables; this one has a layers axis ({spec.layers.quantity})."
            " Build it at a chosen size with build()"
        )


def dense_check(spec: LutSpec) -> DenseCheck:
    """Fresh integrals on the grid :func:`fit` measures a fit's maximum error on (four
    times the texels along each axis, at most 256, ends included), for reuse."""
    from . import _lutfit

    _two_d("dense_check", spec)
    return _lutfit.dense_check(spec)


def read(path: str | Path) -> tuple[np.ndarray, dict[str, Any]]:
    """The decoded texels (float64, rows x columns x channels) and metadata of a file
    :meth:`Lut.save` wrote."""
    from . import _lutfiles

    return _lutfiles.read(Path(path))


@dataclasses.dataclass(frozen=True)
class Verification:
    """:func:`verify`'s answer: whether the file's texels are within ``tolerance`` (per
    channel) of the rebuilt table's, the largest difference, and whether the recorded
    content hash is the recorded recipe's and that recipe is the rebuild's (every field
    but the library version). ``versions``: the file's library version and this one's."""

    ok: bool
    hash_ok: bool
    max_difference: list[float]
    tolerance: list[float]
    versions: tuple[str, str] = ("", "")


def verify(path: str | Path, *, interp_limit: int = 8) -> Verification:
    """Rebuilds the table a file records (its recipe) and compares. The recorded content
    hash must be the SHA-256 of the recorded recipe, and the recipe must be the rebuilt
    spec's in every field but the library version. Built by this version of the library,
    the rebuild has the same bits: every texel must then match exactly (to the decimal
    literals' rounding in source code, to half a step in a PNG). Built by another
    version, each texel must be within the quantization error plus 6 Monte Carlo
    standard errors of the rebuilt one, plus the same literal rounding or PNG step."""
    values, meta = read(path)
    recipe = meta["recipe"]
    spec = LutSpec.from_recipe(recipe)
    rebuilt = spec.recipe()
    same_fields = {k: v for k, v in recipe.items() if k != "brdf_rs"} == {
        k: v for k, v in rebuilt.items() if k != "brdf_rs"
    }
    hash_ok = recipe_hash(recipe) == meta.get("content_hash") and same_fields
    versions = (str(recipe.get("brdf_rs")), __version__)
    lut = build(spec, interp_limit=interp_limit)
    if values.shape != lut.decoded.shape:
        return Verification(False, hash_ok, [math.inf], [0.0], versions)
    diff = np.abs(values - lut.decoded).reshape(-1, values.shape[-1]).max(axis=0)
    nc = values.shape[-1]
    # What the container adds to the format's decoded texels.
    if "png" in meta:
        container = np.asarray(meta["png"]["step"], dtype=np.float64) / 2
    elif Path(path).suffix.lower() in (".h", ".glsl", ".hlsl", ".wgsl"):
        container = np.full(nc, 1e-9)
    else:
        container = np.zeros(nc)
    tol = container + (1e-12 if container.any() else 0.0)
    if versions[0] != versions[1]:
        quant = np.asarray(lut.budget.quant_worst)
        tol = tol + quant + 6 * np.asarray(lut.budget.mc_max_stderr) + 1e-12
    return Verification(bool(np.all(diff <= tol)), hash_ok, diff.tolist(), tol.tolist(), versions)


#: The presets by name (see docs/luts.md).
PRESETS: dict[str, Preset] = _presets()
