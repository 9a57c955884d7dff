"""The public evaluation API: ``eval``, ``Model``, ``models``, thread control."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from . import _arrays, _normalization, _spec
from . import _brdf_rs as _core

__all__ = ["Model", "eval", "isa", "models", "num_threads", "set_num_threads"]

#: The accuracy tiers of ``precision=`` (docs/numerics.md).
PRECISIONS = ("accurate", "fast")


def eval(
    model: str,
    wi: Any,
    wo: Any,
    n: Any = None,
    *,
    tangent: Any = None,
    normalized: bool = False,
    check: bool = True,
    out: np.ndarray | None = None,
    normalization: str = "approximate",
    precision: str = "accurate",
    **params: Any,
) -> np.ndarray:
    """Evaluates ``model`` for every pair of directions.

    Directions point away from the surface: ``wi`` toward the light, ``wo`` toward the
    viewer; ``n`` is the surface normal (default +z). Family-A models return the BRDF
    ``f(wi, wo)`` in 1/sr **without** the cosine factor (0 unless both directions are
    above the surface); family-B models return the shading term ``s(l, v)``, which
    **includes** the light's cosine. ``brdf_rs.models()`` lists every model.

    Args:
        model: a model name, e.g. ``"torrance_sparrow"``.
        wi, wo, n, tangent: array-likes of shape ``(..., 3)`` broadcasting against each
            other (NumPy rules); any memory layout. Not necessarily unit length unless
            ``normalized=True``.
        normalized: promise that the inputs are unit vectors (skips normalization).
        check: raise ``ValueError`` naming the argument and first bad index for NaN,
            infinite or zero-length vectors, and for a tangent of ``ward`` or
            ``ashikhmin_shirley`` parallel to the normal (the sine of their angle at most
            64 machine epsilons of the dtype); with ``check=False`` such rows give NaN.
        out: optional C-contiguous array of the result's shape and dtype to write into.
        normalization: ``"exact"`` scales the lobe so its directional albedo (kd = 0,
            ks = 1, Fresnel factor 1) peaks at exactly 1: ``normalized_blinn_phong``
            (a closed form instead of RTR's ``(p+8)/(8π)``), ``torrance_sparrow`` (its
            supremum over incidences is already 1 for every p: the factor is 1) and
            ``ward`` (whose albedo is unbounded at grazing incidence: exactly 1 at
            normal incidence, from a table the library computed). Details and
            accuracy: ``brdf_rs._normalization``.
        precision: ``"accurate"`` (the default: the goals of docs/numerics.md, within a
            few ulps) or ``"fast"``: powers ``x^p`` in plain floating point, the
            microfacet lobes without their length corrections and, in float64 on
            AVX-512, normalizations without square roots or divisions; relative error at most
            1e-12 in float64 and 2e-6 in float32 on well-conditioned inputs
            (docs/numerics.md); the same results for bad inputs (NaN rows or errors).
            Models whose ``models()`` entry has ``fast_tier`` false give the same bits
            in both, and so do those without ``powers`` in float32 (which carries no
            length corrections).
        **params: the model's parameters (docs/models.md names). Scalars, RGB triples for
            colours, or arrays broadcasting against the batch (colours with a trailing
            axis of 3) for spatially varying parameters.

    Returns:
        An array of shape ``broadcast(...) + (3,)`` (RGB): float32 if every direction
        input is float32 (computed by float32 kernels), float64 otherwise.
    """
    if precision != "accurate" and precision != "fast":
        _arrays.choice("precision", precision, PRECISIONS)
    if check.__class__ is not bool or normalized.__class__ is not bool:
        # Reachable from untyped callers, whatever the annotations say.
        _arrays.flags(check=check, normalized=normalized)  # type: ignore[unreachable]
    if isinstance(normalization, str) and normalization == "approximate":
        # The common call (float arrays or 3-lists, numbers and colours) read in Rust;
        # None where an argument needs the conversions below (same results, same errors).
        result = _core.eval_fast(
            model, wi, wo, n, tangent, params, normalized, check, out, precision
        )
        if result is not None:
            return result
    return _eval_general(
        model, wi, wo, n, tangent, normalized, check, out, normalization, params, precision
    )


def _grey_colours(model: str, params: dict[str, Any]) -> dict[str, Any]:
    """A colour list may mix greys and RGB triples (``[[0.1, 0.2, 0.3], 0.5]``), as in a
    scene file: each grey becomes its triple, so the list is an array."""
    out = dict(params)
    for name in _spec.colour_lists(model):
        value = out.get(name)
        if isinstance(value, (list, tuple)) and any(
            isinstance(c, (list, tuple, np.ndarray)) for c in value
        ):
            out[name] = [
                [c, c, c] if not isinstance(c, (list, tuple, np.ndarray)) else c for c in value
            ]
    return out


def _eval_general(
    model: str,
    wi: Any,
    wo: Any,
    n: Any,
    tangent: Any,
    normalized: bool,
    check: bool,
    out: np.ndarray | None,
    normalization: str,
    params: dict[str, Any],
    precision: str = "accurate",
) -> np.ndarray:
    """:func:`eval` for any arguments: converted here, then evaluated in Rust."""
    _arrays.model_name(model, params)
    dtype, v = _arrays.directions(wi=wi, wo=wo, n=n, tangent=tangent)
    _check_out(out, dtype)
    params = _grey_colours(model, params)
    numeric = _arrays.numeric(params)
    p = _arrays.parameters(_normalization.apply(model, numeric, normalization), dtype)
    wi_, wo_ = _arrays.given(v, "wi"), _arrays.given(v, "wo")
    kernel = _core.eval_f32 if dtype == np.float32 else _core.eval_f64
    return kernel(model, wi_, wo_, v["n"], v["tangent"], p, normalized, check, True, out, precision)


def _check_out(out: object, dtype: type[np.floating]) -> None:
    """``out`` must be an array of the result's dtype (shape and layout: checked in Rust)."""
    if out is None:
        return
    if not isinstance(out, np.ndarray):
        raise TypeError(f"out: expected a NumPy array, got {type(out).__name__}")
    if out.dtype != dtype:
        raise TypeError(
            f"out: expected dtype {np.dtype(dtype).name} in native byte order (the result's:"
            f" float32 only when every direction is float32), got {out.dtype}"
        )
    if out.ndim > _arrays.MAX_NDIM:
        raise ValueError(
            f"out: an array of {out.ndim} dimensions; at most {_arrays.MAX_NDIM} are supported"
        )


class Model:
    """A model with fixed parameters, checked once, for many evaluations.

    The parameters are also laid out for the kernels once (unless one varies over the
    batch), so a call with a few directions costs little more than the Python call
    itself: the way to evaluate in a loop (per object, per light, in an optimizer).

    >>> m = Model("torrance_sparrow", ks=0.8, p=50, eta=1.5)
    >>> m.eval([0, 0, 1], [0, 0, 1]).shape
    (3,)
    """

    __slots__ = ("_fast", "_given", "_params", "name", "normalization", "precision")

    def __init__(
        self,
        name: str,
        *,
        normalization: str = "approximate",
        precision: str = "accurate",
        **params: Any,
    ) -> None:
        """``normalization`` and ``precision`` as in :func:`brdf_rs.eval` (``"exact"``
        rescales ``ks`` once, here; every evaluation uses the ``precision`` tier);
        ``params`` the model's parameters."""
        _arrays.model_name(name, params)
        self.precision = _arrays.choice("precision", precision, PRECISIONS)
        given = _arrays.parameters(params, np.float64)
        _core.check_params(name, given)
        applied = _normalization.apply(name, given, normalization)
        p64 = given if applied is given else _arrays.parameters(applied, np.float64)
        if p64 is not given:
            _core.check_params(name, p64)
        self.name = name
        self.normalization = normalization
        self._given = given
        self._params = {np.float64: p64}
        # The parameters laid out for the kernels once, both dtypes (None when one has
        # batch axes: those broadcast with the directions in the general path).
        self._fast = _core.prepare_model(name, p64)

    def __reduce__(self) -> tuple[Any, ...]:
        # Rebuilt from what it was made of (the prepared core object does not pickle).
        return (_restore, (self.name, self.normalization, self._given, self.precision))

    @property
    def params(self) -> dict[str, np.ndarray]:
        """The parameters given (defaults are not listed; ``ks`` as given, before an exact
        normalization's factor)."""
        return dict(self._given)

    def _params_for(self, dtype: type[np.floating]) -> dict[str, np.ndarray]:
        if dtype not in self._params:
            with np.errstate(over="ignore"):
                self._params[dtype] = {
                    k: v.astype(dtype) for k, v in self._params[np.float64].items()
                }
        return self._params[dtype]

    def eval(
        self,
        wi: Any,
        wo: Any,
        n: Any = None,
        *,
        tangent: Any = None,
        normalized: bool = False,
        check: bool = True,
        out: np.ndarray | None = None,
    ) -> np.ndarray:
        """Evaluates the model; arguments as :func:`brdf_rs.eval`."""
        if check.__class__ is not bool or normalized.__class__ is not bool:
            # Reachable from untyped callers, whatever the annotations say.
            _arrays.flags(check=check, normalized=normalized)  # type: ignore[unreachable]
        if self._fast is not None:
            # The common call read in Rust with the parameters laid out at __init__; None
            # where an argument needs the conversions below (same results, same errors).
            result = self._fast.eval(wi, wo, n, tangent, normalized, check, out, self.precision)
            if result is not None:
                return result
        return self._eval_general(wi, wo, n, tangent, normalized, check, out)

    def _eval_general(
        self,
        wi: Any,
        wo: Any,
        n: Any,
        tangent: Any,
        normalized: bool,
        check: bool,
        out: np.ndarray | None,
    ) -> np.ndarray:
        """:meth:`eval` for any arguments: converted here, then evaluated in Rust."""
        dtype, v = _arrays.directions(wi=wi, wo=wo, n=n, tangent=tangent)
        _check_out(out, dtype)
        kernel = _core.eval_f32 if dtype == np.float32 else _core.eval_f64
        # Values were range-checked in __init__ (a float32 cast can only overflow to
        # inf for values beyond float32's range: check those again).
        recheck = dtype == np.float32
        return kernel(
            self.name,
            _arrays.given(v, "wi"),
            _arrays.given(v, "wo"),
            v["n"],
            v["tangent"],
            self._params_for(dtype),
            normalized,
            check,
            recheck,
            out,
            self.precision,
        )

    __call__ = eval

    def __repr__(self) -> str:
        args = "".join(f", {k}={v.tolist()!r}" for k, v in self._given.items())
        if self.normalization != "approximate":
            args += f", normalization={self.normalization!r}"
        if self.precision != "accurate":
            args += f", precision={self.precision!r}"
        return f"Model({self.name!r}{args})"


def _restore(
    name: str,
    normalization: str,
    params: dict[str, np.ndarray],
    precision: str = "accurate",
) -> Model:
    """Unpickles a :class:`Model` (pickles from before ``precision`` have 3 arguments)."""
    return Model(name, normalization=normalization, precision=precision, **params)


def models() -> dict[str, _spec.ModelSpec]:
    """Returns every model's spec, by name, in a stable order (a copy: yours to change).

    Each entry has ``family`` ("A": BRDF without cosine, "B": shading term with the
    light cosine), ``summary``, ``formula``, ``source``, ``reciprocal``, ``tangent``
    (whether ``tangent=`` is required), ``tangent_optional``, ``weights`` (the
    parameters whose all being zero makes the model zero), ``scene_slot`` (where a scene
    material takes it), ``diffuse`` (how a family-A model's diffuse term renders alone),
    ``dfg`` (the roughness axis of its split-sum table, or None), ``energy_table``,
    ``view_albedo_closed_form`` (whether the lobe's albedo seen from the view, over the
    light, is known in closed form: energy tables use it),
    ``transmission`` (whether it transmits: defined on the whole sphere, not zero below
    the surface),
    ``sheen_layer`` (whether a scene material may stack it over a base as a sheen layer),
    ``powers`` (whether it raises something to a power), ``fast_tier`` (whether
    ``precision="fast"`` changes it: powers, or microfacet length corrections in float64;
    in float64 on AVX-512 the fast tier also normalizes such a model's directions its own
    way),
    ``exact`` (its ``normalization="exact"``: how the factor is
    computed, the parameters it takes and the colour it scales; None where it has none) and
    ``params``: a list of dicts with ``name``, ``kind`` (scalar, colour, scalar list,
    colour list), ``default`` (None: required), ``range`` (as text, plus
    ``min``/``max``/``min_open``/``max_open``), ``doc``, ``varies`` (whether it may be
    an array over the batch), ``max_len`` and ``one_more_than`` (for a colour list, the
    list it has one more entry than). The types are ``brdf_rs._spec.ModelSpec``.
    """
    return copy.deepcopy(_spec.specs())


def set_num_threads(n: int) -> None:
    """Sets the number of worker threads (default: ``BRDF_RS_NUM_THREADS``, else CPUs).

    ``n`` is an integer from 1 to 65535 (the thread pool's limit)."""
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)):
        raise TypeError(f"n: expected an integer thread count, got {type(n).__name__} {n!r}")
    _core.set_num_threads(_arrays.integer("n", n, 1, _core.max_num_threads()))


def num_threads() -> int:
    """Returns the number of worker threads."""
    return _core.num_threads()


def isa() -> str:
    """Returns the instruction set the kernels use here: avx512, avx2 or baseline."""
    return _core.isa()
