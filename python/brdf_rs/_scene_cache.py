"""The albedo tables a scene's materials need, built once and cached on disk."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import logging
import os
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from . import _arrays, _options, _spec
from ._brdf_rs import __version__
from ._scene_schema import Scene, as_scene
from ._table import Table, TableFileError

__all__ = ["TableResult", "default_cache_dir", "scene_tables"]

log = logging.getLogger("brdf_rs")


@dataclasses.dataclass(frozen=True)
class TableResult:
    """One material's albedo table: where it is, whether it was built or found in the
    cache, and what it says (the largest albedo over mu, RGB, and whether it exceeds 1
    by more than 3 standard errors)."""

    material: str
    model: str
    path: Path
    cached: bool
    max_albedo: list[float]
    mu_at_max: float
    gains_energy: bool
    seconds: float


def default_cache_dir() -> Path:
    """``$BRDF_RS_CACHE``, else ``$XDG_CACHE_HOME/brdf-rs/tables``, else
    ``~/.cache/brdf-rs/tables``."""
    if os.environ.get("BRDF_RS_CACHE"):
        return Path(os.environ["BRDF_RS_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "brdf-rs" / "tables"


def _canonical_params(model: str, params: Mapping[str, Any]) -> dict[str, Any]:
    """Every parameter, defaults filled in, colours as RGB triples: equal materials hash
    equal however they were spelled."""
    out = {}
    for p in _spec.specs()[model]["params"]:
        value = params.get(p["name"], p["default"])
        if p["kind"] == "colour":
            value = [float(x) for x in np.broadcast_to(np.asarray(value, dtype=float), (3,))]
        elif p["kind"] == "scalar":
            value = float(value)
        else:
            value = np.asarray(value, dtype=float).tolist()
        out[p["name"]] = value
    return out


def _cached_table(path: Path, key: Mapping[str, Any]) -> Table | None:
    """The table cached at ``path`` if it is whole and is the one ``key`` asks for, else
    None (the caller builds it again); a file that fails is logged as a warning."""
    try:
        table = Table.load(path)
    except (OSError, TableFileError) as exc:
        log.warning("albedo table cache: %s; building it again", exc)
        return None
    # The name holds a prefix of the key's hash: check the whole key and the grid too.
    want = json.loads(json.dumps(key))
    if (
        table.meta.get("cache_key") != want
        or list(table.axes) != ["mu"]
        or not np.array_equal(table.axes["mu"], np.asarray(key["mu"], dtype=np.float64))
    ):
        log.warning(
            "albedo table cache: %s holds another table than its name says; building it again",
            path,
        )
        return None
    return table


def scene_tables(
    scene: Scene | str | os.PathLike[str] | Mapping[str, Any],
    *,
    cache_dir: str | os.PathLike[str] | None = None,
    mu_count: int = 32,
    samples: int = 4096,
    tol: float | None = None,
    seed: int = 0,
    progress: Callable[[str, int, int], None] | None = None,
) -> list[TableResult]:
    """Builds the albedo tables a scene's materials need for energy checks.

    For every family-A material some object uses, the directional albedo ``R(mu)`` over
    ``mu_count`` cell midpoints of [0, 1] (:func:`brdf_rs.albedo_table`). Each table is
    cached in ``cache_dir`` (default :func:`default_cache_dir`) under a hash of the model,
    its parameters (defaults filled in), the sampler settings and the library version; a
    table already there is read, not rebuilt, once it has been checked: a cached file that
    is damaged, cut short or holds another table is built again (with a warning on the
    ``brdf_rs`` logger), never used. Tables are written atomically, so processes sharing
    a cache never see a half-written one. Family-B shading terms are not BRDFs and
    have no albedo: they are skipped. A material's sheen layer is not included: the table
    is its model's (the layered albedo at view cosine ``mu`` is ``weight·E_sheen(mu)·ks +
    (1 − weight·E_sheen(mu))·R(mu)``, docs/scenes.md).

    ``progress(material, cells_done, cells)`` is called while a table is built.
    """
    from ._albedo import albedo_table

    scene = as_scene(scene)
    mu_count = _arrays.integer("mu_count", mu_count, 1, 1 << 20)
    checked = _options.check({"samples": samples, "seed": seed, "tol": tol})
    samples, seed, tol = checked["samples"], checked["seed"], checked["tol"]
    directory = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    directory.mkdir(parents=True, exist_ok=True)
    mu = (np.arange(mu_count) + 0.5) / mu_count
    results = []
    for name in scene.used_materials():
        material = scene.materials[name]
        if "brdf" not in material:
            continue
        model = material["brdf"]["model"]
        params = _canonical_params(model, material["brdf"]["params"])
        key = {
            "model": model,
            "params": params,
            "mu": mu.tolist(),
            "samples": samples,
            "sampler": "auto",
            "sequence": "sobol",
            "seed": seed,
            "tol": tol,
            "replicates": _options.DEFAULT_REPLICATES,
            "brdf_rs": __version__,
        }
        digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()
        path = directory / f"{model}-{digest[:24]}.npz"
        start = time.perf_counter()
        table = _cached_table(path, key) if path.exists() else None
        cached = table is not None
        if table is None:
            callback = None
            if progress is not None:

                def callback(done: int, _samples: int, _name: str = name) -> None:
                    progress(_name, done, mu_count)

            table = albedo_table(
                model,
                {"mu": mu},
                samples=samples,
                tol=tol,
                seed=seed,
                progress=callback,
                **params,
            )
            table.meta["cache_key"] = key
            table.save(path)
        peak_channel = table.value.max(axis=0)
        k = int(np.argmax(table.value.max(axis=1)))
        gains = bool(np.any(table.value - 3 * table.stderr > 1.0))
        results.append(
            TableResult(
                material=name,
                model=model,
                path=path,
                cached=cached,
                max_albedo=[float(x) for x in peak_channel],
                mu_at_max=float(mu[k]),
                gains_energy=gains,
                seconds=time.perf_counter() - start,
            )
        )
    return results
