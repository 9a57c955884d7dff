"""Albedo tables on Dask: one table, built by many processes or machines.

:func:`albedo_table` splits the parameter grid of :func:`brdf_rs.albedo_table` into
blocks (``chunks``); each block becomes one Dask task that calls the Rust integrator
(:func:`brdf_rs.albedo`, which releases the GIL and runs on the worker's rayon pool) with
``cell_ids`` = the block's global flat cell indices (``np.ravel_multi_index`` over the
full grid). A cell's sample streams are keyed by (seed, cell id) only, so the table has
**the same bits** as the single-process ``brdf_rs.albedo_table`` with the same seed,
whatever the chunking, the number of workers, the threads per worker, retries or
workers lost mid-build. Adaptive ``tol`` stops each cell on its own, exactly as locally.

What you get back (``compute=False``, the default) is a :class:`LazyTable`: three Dask
arrays that share one task per block, ``value`` and ``stderr`` (axes lengths + (3,),
RGB, float64) and ``samples`` (axes lengths, uint64), with the table's ``axes`` and
``meta``. Compute them together (:meth:`LazyTable.compute`, returning the same
:class:`brdf_rs.Table` as the local build) or stream them to a Zarr store
(:meth:`LazyTable.to_zarr`): each task then writes its block straight into the store
and returns only a count, so no process ever holds more than a few blocks of a table
that does not fit in memory. :func:`read_zarr` reads a store back as a ``Table`` or,
``lazy=True``, as a ``LazyTable`` over the store.

    from dask.distributed import Client
    import brdf_rs.dask

    client = Client("tcp://scheduler:8786")          # or LocalCluster(...), or no client
    lazy = brdf_rs.dask.albedo_table(
        "torrance_sparrow",
        {"mu": mu, "p": p, "eta": eta, "ks": ks},
        chunks={"mu": 16, "p": 16},                    # blocks of the grid = tasks
        client=client, kd=0.0, tol=1e-5,
    )
    lazy.to_zarr("s3://bucket/ts_albedo.zarr", retries=3)   # stream to a store, or
    table = lazy.compute()                             # the brdf_rs.Table, in memory

Workers: a task runs the Rust integrator on the worker's rayon pool (by default every
CPU it sees, or ``BRDF_RS_NUM_THREADS``), so one Dask thread per worker process
(``threads_per_worker=1``) with the pool sized to the worker's cores is the natural
layout; ``client.run(brdf_rs.set_num_threads, n)`` resizes the pools of running
workers. Failures: a worker that dies mid-build loses only the blocks it was computing
or holding; the scheduler recomputes them elsewhere (a task is given up after
``distributed.scheduler.allowed-failures`` worker deaths, default 3), and ``retries=``
on ``compute`` / ``to_zarr`` retries tasks that raised. Recomputed blocks have the
same bits. Progress: use Dask's own (``dask.diagnostics.ProgressBar`` locally,
``distributed.progress`` or the dashboard on a cluster); the ``progress`` callback of
the local build is not available.

Needs the ``dask`` extra (``pip install 'brdf-rs[dask]'``: dask[array,distributed] and
zarr). ``import brdf_rs`` never imports Dask, and neither does importing this module:
Dask and Zarr are imported when first used.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _albedo, _grid, _options
from ._table import Table

if TYPE_CHECKING:
    import dask.array

__all__ = ["LazyTable", "albedo_table", "read_zarr", "write_zarr"]

#: The options of :func:`brdf_rs.albedo_table` that are not model parameters.
_OPTION_NAMES = (
    "samples",
    "sampler",
    "sequence",
    "seed",
    "tol",
    "rtol",
    "max_samples",
    "replicates",
)
#: Default blocks aim at about this many samples each (≈ 0.2–1 s of one core) ...
TARGET_SAMPLES_PER_CHUNK = 1 << 24
#: ... with between this many ...
MIN_CELLS_PER_CHUNK = 16
#: ... and this many cells.
MAX_CELLS_PER_CHUNK = 1 << 16
#: Zarr group attributes besides the table's ``meta``.
_FORMAT_KEY = "brdf_rs_format"
_COMPLETE_KEY = "brdf_rs_complete"
_FORMAT = "brdf_rs.Table/1"
_ARRAYS = ("value", "stderr", "samples")


def _import_dask() -> Any:
    try:
        import dask
        import dask.array
    except ImportError:
        raise ImportError(
            "brdf_rs.dask needs Dask: pip install 'brdf-rs[dask]' (dask[array,distributed], zarr)"
        ) from None
    return dask


def _import_zarr() -> Any:
    try:
        import zarr
    except ImportError:
        raise ImportError(
            "writing and reading Zarr tables needs zarr: pip install 'brdf-rs[dask]'"
        ) from None
    return zarr


# ------------------------------------------------------------------------ block tasks


@dataclasses.dataclass(frozen=True, eq=False)
class _Block:
    """Everything one task needs to integrate one block of the grid (kept small: only
    the block's own coordinates travel with it)."""

    model: str
    names: tuple[str, ...]
    colour: frozenset[str]
    coords: tuple[np.ndarray, ...]  # the block's coordinates, one 1-D array per axis
    start: tuple[int, ...]  # the block's first index along each axis of the full grid
    grid_shape: tuple[int, ...]  # the full grid's shape
    fixed: dict[str, Any]
    options: dict[str, Any]
    # A phi axis: the full-grid axis index whose cell id each of the block's azimuths
    # uses (its coordinates are already the azimuths computed; see _grid.azimuth_cells).
    phi_index: np.ndarray | None = None

    @property
    def block_shape(self) -> tuple[int, ...]:
        return tuple(c.size for c in self.coords)

    def region(self) -> tuple[slice, ...]:
        return tuple(slice(s, s + n) for s, n in zip(self.start, self.block_shape, strict=True))


def _compute_block(block: _Block) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Integrates one block; returns its ``(value, stderr, samples)``."""
    shape = block.block_shape
    mu, grid, fixed = _grid.grid_inputs(block.names, block.colour, block.coords, block.fixed)
    ranges = [np.arange(s, s + n) for s, n in zip(block.start, shape, strict=True)]
    if block.phi_index is not None:
        ranges[block.names.index("phi")] = block.phi_index
    index = np.meshgrid(*ranges, indexing="ij", sparse=True)
    ids = np.ravel_multi_index(index, block.grid_shape).astype(np.uint64)
    ids = np.ascontiguousarray(np.broadcast_to(ids, shape))
    r = _albedo.albedo(block.model, mu, cell_ids=ids, **block.options, **grid, **fixed)
    if r.value.shape != (*shape, 3):
        raise ValueError(
            f"the fixed parameters add cell dimensions: block {shape} gave {r.value.shape[:-1]}"
        )
    return r.value, r.stderr, r.samples


def _store_block(block: _Block, *, targets: tuple[Any, ...]) -> int:
    """Integrates one block and writes it into the Zarr arrays ``targets``
    (value, stderr, samples); returns the samples drawn (all the scheduler keeps)."""
    value, stderr, samples = _compute_block(block)
    region = block.region()
    rgb = (*region, slice(None))  # the block's cells, every channel
    targets[0][rgb] = value
    targets[1][rgb] = stderr
    targets[2][region] = samples
    return int(samples.sum(dtype=np.uint64))


def _total(counts: list[int]) -> int:
    return int(sum(counts))


# ------------------------------------------------------------------------- the plan


@dataclasses.dataclass(frozen=True)
class _Plan:
    """A table to build: the grid, its chunking and the integrator's inputs."""

    model: str
    names: tuple[str, ...]
    colour: frozenset[str]
    coords: dict[str, np.ndarray]
    fixed: dict[str, Any]
    options: dict[str, Any]
    chunks: tuple[tuple[int, ...], ...]
    token: str

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(self.coords[n].size for n in self.names)

    def blocks(self) -> Iterator[tuple[tuple[int, ...], _Block]]:
        """Yields ``(block index, _Block)`` for every block, in C order."""
        offsets = [np.concatenate([[0], np.cumsum(c)]).astype(int) for c in self.chunks]
        shape = self.shape
        computed = dict(self.coords)
        first = None
        if "phi" in computed:  # the local build's azimuth cells, for the same bits
            computed["phi"], first = _grid.azimuth_cells(self.model, computed["phi"])
        for index in itertools.product(*(range(len(c)) for c in self.chunks)):
            start = tuple(int(offsets[k][i]) for k, i in enumerate(index))
            stop = tuple(int(offsets[k][i + 1]) for k, i in enumerate(index))
            coords = tuple(
                computed[n][a:b] for n, a, b in zip(self.names, start, stop, strict=True)
            )
            phi_index = None
            if first is not None:
                k = self.names.index("phi")
                phi_index = first[start[k] : stop[k]]
            yield (
                index,
                _Block(
                    self.model,
                    self.names,
                    self.colour,
                    coords,
                    start,
                    shape,
                    self.fixed,
                    self.options,
                    phi_index,
                ),
            )


def _normalize_chunks(
    chunks: Any, names: Sequence[str], shape: tuple[int, ...], samples: int
) -> tuple[tuple[int, ...], ...]:
    from dask.array.core import normalize_chunks

    if isinstance(chunks, str) and chunks == "auto":
        cells = min(
            max(TARGET_SAMPLES_PER_CHUNK // samples, MIN_CELLS_PER_CHUNK), MAX_CELLS_PER_CHUNK
        )
        return _int_chunks(normalize_chunks("auto", shape, limit=cells * 8, dtype=np.float64))
    if isinstance(chunks, list):
        chunks = tuple(chunks)
    if isinstance(chunks, Mapping):
        by_position = {}
        for key, c in chunks.items():
            if isinstance(key, str):
                if key not in names:
                    raise ValueError(f"chunks: {key!r} is not an axis; the axes are {list(names)}")
                key = names.index(key)
            by_position[int(key)] = c
        chunks = tuple(by_position.get(k, -1) for k in range(len(names)))
    try:
        out = normalize_chunks(chunks, shape, dtype=np.float64)
    except (ValueError, TypeError, ArithmeticError) as exc:
        raise ValueError(f"chunks: cannot split the axes {shape} into {chunks!r} ({exc})") from None
    if any(n <= 0 for c in out for n in c):
        raise ValueError(f"chunks: blocks must be non-empty; got {out}")
    return _int_chunks(out)


def _int_chunks(chunks: Any) -> tuple[tuple[int, ...], ...]:
    return tuple(tuple(int(n) for n in c) for c in chunks)


def _probe(
    model: str,
    names: Sequence[str],
    colour: frozenset[str],
    coords: Mapping[str, np.ndarray],
    fixed: Mapping[str, Any],
    options: Mapping[str, Any],
) -> None:
    """Checks the options, the model, every axis value and the fixed parameters now,
    cheaply (the options on no cells; each axis once, the others at their first value,
    1 sample per cell), so a bad value fails here and not in the last task of a long
    build."""
    # The options together (max_samples against samples, Sobol points per replicate), as
    # the core checks them: on no cells, so no work.
    mu, grid, rest = _grid.grid_inputs(names, colour, [coords[n][:0] for n in names], fixed)
    _albedo.albedo(model, mu, **options, **grid, **rest)
    quick = {**options, "samples": 1, "tol": None, "rtol": None, "max_samples": None}
    for k in range(len(names)):
        line = [coords[n] if j == k else coords[n][:1] for j, n in enumerate(names)]
        mu, grid, rest = _grid.grid_inputs(names, colour, line, fixed)
        r = _albedo.albedo(model, mu, **quick, **grid, **rest)
        expected = tuple(a.size for a in line)
        if r.value.shape != (*expected, 3):
            raise ValueError(
                "fixed parameters must not add table dimensions: cells of shape "
                f"{r.value.shape[:-1]} where the axes give {expected}"
            )


def _make_plan(model: str, axes: Mapping[str, Any], chunks: Any, options: dict[str, Any]) -> _Plan:
    for bad, why in (
        ("progress", "use Dask's progress (dask.diagnostics.ProgressBar, distributed.progress)"),
        ("cell_ids", "the cells' ids are their flat indices in the full grid"),
    ):
        if bad in options:
            raise TypeError(f"{bad}: not available for Dask builds ({why})")
    opts = {k: options.pop(k) for k in _OPTION_NAMES if k in options}
    opts = {**_options.check({}), **opts}  # every option: the defaults, then the given
    checked = _options.check(opts)  # the local build's checks and messages
    fixed = options
    names, coords, colour = _grid.table_axes(model, axes, fixed)
    _probe(model, names, colour, coords, fixed, opts)
    shape = tuple(coords[n].size for n in names)
    normalized = _normalize_chunks(chunks, names, shape, checked["samples"])
    from dask.base import tokenize

    token = tokenize(model, names, coords, fixed, opts, normalized)
    return _Plan(model, names, colour, coords, fixed, opts, normalized, token)


def _meta(plan: _Plan) -> dict[str, Any]:
    """The ``meta`` of the local ``brdf_rs.albedo_table`` for the same request."""
    fixed = {k: v for k, v in plan.fixed.items() if not (k == "mu" and "mu" not in plan.names)}
    return _grid.table_meta(plan.model, plan.names, fixed, plan.options)


def _arrays_of(plan: _Plan) -> tuple[Any, Any, Any]:
    """The three Dask arrays of a plan: one task per block, and one selection per array."""
    import operator

    import dask.array as da
    from dask.highlevelgraph import HighLevelGraph

    blocks = f"albedo-block-{plan.token}"
    layer = {(blocks, *index): (_compute_block, block) for index, block in plan.blocks()}
    out = []
    for position, what in enumerate(_ARRAYS):
        name = f"albedo-{what}-{plan.token}"
        rgb = what != "samples"
        select = {
            ((name, *key[1:], 0) if rgb else (name, *key[1:])): (operator.getitem, key, position)
            for key in layer
        }
        graph = HighLevelGraph({blocks: layer, name: select}, {blocks: set(), name: {blocks}})
        chunks = (*plan.chunks, (3,)) if rgb else plan.chunks
        dtype = np.float64 if rgb else np.uint64
        meta = np.empty((0,) * len(chunks), dtype=dtype)
        out.append(da.Array(graph, name, chunks, dtype=dtype, meta=meta))
    value, stderr, samples = out
    return value, stderr, samples


# ------------------------------------------------------------------------- LazyTable


@dataclasses.dataclass(frozen=True, eq=False)
class LazyTable:
    """An albedo table as Dask arrays, not computed yet.

    ``value`` and ``stderr`` have shape ``axes lengths + (3,)`` (RGB), ``samples`` the
    axes' lengths; the three share one task per block, so compute them together
    (:meth:`compute`, :meth:`persist`, :meth:`to_zarr`) to integrate each block once.
    ``axes`` and ``meta`` are those of the ``brdf_rs.Table`` it computes to. ``client``
    (a ``distributed.Client``) runs the computations; ``None`` uses Dask's default
    scheduler (the active distributed client if there is one, else local threads).
    """

    value: dask.array.Array
    stderr: dask.array.Array
    samples: dask.array.Array
    axes: dict[str, np.ndarray]
    meta: dict[str, Any]
    client: Any = None
    _plan: _Plan | None = dataclasses.field(default=None, repr=False)

    @property
    def shape(self) -> tuple[int, ...]:
        """The table's grid shape (the axes' lengths)."""
        return tuple(self.samples.shape)

    @property
    def chunks(self) -> tuple[tuple[int, ...], ...]:
        """The blocks along each axis (one task per block)."""
        return _int_chunks(self.samples.chunks)

    def _kwargs(self, kwargs: dict[str, Any]) -> dict[str, Any]:
        if self.client is not None and "scheduler" not in kwargs:
            kwargs = {**kwargs, "scheduler": self.client}
        return kwargs

    def _distributed(self, kwargs: dict[str, Any]) -> Any:
        """The ``distributed.Client`` these ``kwargs`` would compute on, if any (and if
        this table's blocks can be submitted one by one)."""
        if self._plan is None:
            return None
        from dask.base import get_scheduler

        get = get_scheduler(scheduler=self._kwargs(kwargs).get("scheduler"))
        client = getattr(get, "__self__", None)
        return client if type(client).__name__ == "Client" else None

    def compute(self, **kwargs: Any) -> Table:
        """Computes the table and returns it in memory as a :class:`brdf_rs.Table`
        (bitwise the local build's).

        On a distributed client the blocks are submitted one by one and gathered into
        the result as each finishes, so a worker that dies loses only the blocks it
        was computing, and no worker ever holds the whole table; ``kwargs`` may then
        be ``retries``, ``priority``, ``workers``, ``resources``,
        ``allow_other_workers`` (as for ``Client.map``). Otherwise ``kwargs`` go to
        ``dask.compute`` (e.g. ``scheduler="threads"``).
        """
        dask = _import_dask()
        axes = {k: v.copy() for k, v in self.axes.items()}
        client = self._distributed(kwargs)
        plan = self._plan
        if client is None or plan is None:
            value, stderr, samples = dask.compute(
                self.value, self.stderr, self.samples, **self._kwargs(kwargs)
            )
            return Table(value, stderr, samples, axes, _copy_meta(self.meta))
        shape = self.shape
        value = np.full((*shape, 3), np.nan)
        stderr = np.full((*shape, 3), np.nan)
        samples = np.zeros(shape, dtype=np.uint64)
        for block, (v, e, n) in _run_blocks(client, plan, "block", _compute_block, kwargs):
            region = block.region()
            value[region] = v
            stderr[region] = e
            samples[region] = n
        return Table(value, stderr, samples, axes, _copy_meta(self.meta))

    def persist(self, **kwargs: Any) -> LazyTable:
        """Computes the blocks and keeps them where they are (in the workers' memory on
        a cluster); returns a ``LazyTable`` over the results."""
        dask = _import_dask()
        value, stderr, samples = dask.persist(
            self.value, self.stderr, self.samples, **self._kwargs(kwargs)
        )
        return dataclasses.replace(self, value=value, stderr=stderr, samples=samples, _plan=None)

    def to_zarr(self, path: Any, *, overwrite: bool = False, **kwargs: Any) -> Any:
        """Streams the table into a Zarr store at ``path`` (see :func:`write_zarr`)."""
        return write_zarr(self, path, overwrite=overwrite, **kwargs)

    def __repr__(self) -> str:
        axes = ", ".join(f"{k}[{len(v)}]" for k, v in self.axes.items())
        blocks = math.prod(len(c) for c in self.chunks)
        return f"LazyTable({self.meta.get('model')!r}, axes={axes}, blocks={blocks})"


#: ``Client.map`` options a block-by-block build passes on.
_MAP_OPTIONS = ("retries", "priority", "workers", "resources", "allow_other_workers")


def _run_blocks(
    client: Any,
    plan: _Plan,
    what: str,
    func: Callable[[_Block], Any],
    kwargs: dict[str, Any],
) -> Iterator[tuple[_Block, Any]]:
    """Submits ``func(block)`` for every block of ``plan`` and yields ``(block, result)``
    as each finishes, dropping the result from the cluster at once: a worker that dies
    then loses only the blocks it was running."""
    from distributed import as_completed

    unknown = set(kwargs) - {*_MAP_OPTIONS, "scheduler"}
    if unknown:
        raise TypeError(
            f"{sorted(unknown)}: not options of a distributed build; use {list(_MAP_OPTIONS)}"
        )
    options = {k: v for k, v in kwargs.items() if k in _MAP_OPTIONS}
    pairs = list(plan.blocks())
    blocks = [block for _, block in pairs]
    keys = [f"albedo-{what}-{plan.token}-" + "-".join(map(str, i)) for i, _ in pairs]
    futures = client.map(func, blocks, key=keys, pure=True, **options)
    pending = {f.key: (f, b) for f, b in zip(futures, blocks, strict=True)}
    done = as_completed(futures, with_results=True)
    del futures
    try:
        for future, result in done:
            _, block = pending.pop(future.key)
            del future  # the last reference: the scheduler forgets the block's result
            yield block, result
    finally:
        if pending:
            client.cancel([f for f, _ in pending.values()])


def _copy_meta(meta: Mapping[str, Any]) -> dict[str, Any]:
    import copy

    return copy.deepcopy(dict(meta))


def albedo_table(
    model: str,
    axes: Mapping[str, Sequence[float] | np.ndarray],
    *,
    chunks: Any = "auto",
    client: Any = None,
    compute: bool = False,
    **options: Any,
) -> LazyTable | Table:
    """:func:`brdf_rs.albedo_table` as a Dask computation: blocks of the grid are tasks.

    Args:
        model, axes, **options: as for :func:`brdf_rs.albedo_table` (the integrator's
            options ``samples``, ``sampler``, ``sequence``, ``seed``, ``tol``,
            ``max_samples``, ``replicates``, and the fixed parameters); the table has
            the same bits as the local build with the same arguments.
        chunks: the blocks, one task each. ``"auto"`` aims at about 2^24 samples per
            block (16 to 65536 cells); an int (the same block length on every axis), a
            tuple per axis, or a dict by axis name or position (missing axes whole);
            ``-1`` means a whole axis. Aim for blocks of ≥ 0.1 s each, and several per
            worker. The local build's limit of 2^44 samples per request applies per
            block here.
        client: the ``distributed.Client`` to run on (``None``: Dask's default).
        compute: return the computed :class:`brdf_rs.Table` instead of a
            :class:`LazyTable`.

    Returns:
        A :class:`LazyTable` (``value``, ``stderr``, ``samples`` Dask arrays, ``axes``,
        ``meta``), or with ``compute=True`` the ``Table``.

    Raises:
        ValueError, TypeError: bad model, axes, parameters or options, found before any
            task runs (each axis value is checked once, cheaply).
    """
    _import_dask()
    plan = _make_plan(model, axes, chunks, dict(options))
    value, stderr, samples = _arrays_of(plan)
    axes_out = {n: plan.coords[n].copy() for n in plan.names}
    lazy = LazyTable(value, stderr, samples, axes_out, _meta(plan), client, plan)
    return lazy.compute() if compute else lazy


# ------------------------------------------------------------------------------ Zarr


def _zarr_chunks(chunks: tuple[tuple[int, ...], ...]) -> tuple[int, ...]:
    """Regular Zarr chunks that every block covers whole: per axis the largest length
    dividing every block boundary (the blocks' own length when they are regular)."""
    return tuple(math.gcd(*c[:-1]) if len(c) > 1 else c[0] for c in chunks)


def _create(
    group: Any,
    name: str,
    *,
    shape: Sequence[int],
    chunks: Sequence[int],
    dtype: Any,
    fill_value: Any,
    dims: Sequence[str],
) -> Any:
    """Creates an array in a Zarr v3 (``create_array``) or v2 (``create_dataset``) group."""
    if hasattr(group, "create_array"):
        try:
            return group.create_array(
                name,
                shape=shape,
                chunks=chunks,
                dtype=dtype,
                fill_value=fill_value,
                dimension_names=dims,
            )
        except TypeError:  # zarr 2 releases with create_array but no dimension names
            pass
    array = group.create_dataset(
        name, shape=shape, chunks=chunks, dtype=dtype, fill_value=fill_value
    )
    array.attrs["_ARRAY_DIMENSIONS"] = list(dims)  # the xarray convention for zarr 2
    return array


def _open_group(path: Any, mode: str) -> Any:
    zarr = _import_zarr()
    if isinstance(path, Path):
        path = str(path)
    return zarr.open_group(path, mode=mode)


def _json_meta(meta: Mapping[str, Any]) -> dict[str, Any]:
    import json

    copy: dict[str, Any] = json.loads(json.dumps(dict(meta)))
    return copy


def _prepare_store(
    table: Table | LazyTable, path: Any, overwrite: bool, chunks: Sequence[int]
) -> tuple[Any, tuple[Any, ...]]:
    try:
        group = _open_group(path, "w" if overwrite else "w-")
    except (FileExistsError, ValueError) as exc:
        # zarr 3 raises FileExistsError, zarr 2 ContainsGroupError / ContainsArrayError.
        if not (isinstance(exc, FileExistsError) or type(exc).__name__.startswith("Contains")):
            raise
        raise FileExistsError(
            f"{path}: already holds data; pass overwrite=True to replace it"
        ) from None
    names = list(table.axes)
    meta = _json_meta(table.meta)
    clash = {_FORMAT_KEY, _COMPLETE_KEY} & set(meta)
    if clash:
        raise ValueError(f"table.meta: {sorted(clash)} are reserved Zarr attributes")
    group.attrs.update({**meta, _FORMAT_KEY: _FORMAT, _COMPLETE_KEY: False})
    for name in names:
        coords = np.asarray(table.axes[name])
        a = _create(
            group,
            name,
            shape=coords.shape,
            chunks=coords.shape,
            dtype=coords.dtype,
            fill_value=0,
            dims=[name],
        )
        a[...] = coords
    shape = tuple(len(table.axes[n]) for n in names)
    targets = []
    for what in _ARRAYS:
        rgb = what != "samples"
        targets.append(
            _create(
                group,
                what,
                shape=(*shape, 3) if rgb else shape,
                chunks=(*chunks, 3) if rgb else chunks,
                dtype=np.float64 if rgb else np.uint64,
                fill_value=np.nan if rgb else 0,
                dims=[*names, "channel"] if rgb else names,
            )
        )
    return group, tuple(targets)


def write_zarr(
    table: Table | LazyTable,
    path: Any,
    *,
    overwrite: bool = False,
    chunks: Sequence[int] | None = None,
    **kwargs: Any,
) -> Any:
    """Writes a table to a Zarr store (a directory path, or any URL or store zarr opens).

    Layout: arrays ``value``, ``stderr`` (axes + (3,), float64), ``samples`` (uint64),
    one 1-D coordinate array per axis (named after it; dimension names set, so
    ``xarray.open_zarr`` reads it too), and the table's ``meta`` as the group's
    attributes, with ``brdf_rs_complete`` set true only once every block is written.

    A :class:`LazyTable` is streamed: each task computes its block and writes it into
    the store itself, so the table never has to fit in one process; Zarr chunks follow
    the blocks. On a cluster ``path`` must be reachable from every worker (a shared
    file system or an object store URL). ``kwargs`` go to ``dask.compute`` (e.g.
    ``retries=3``). A :class:`brdf_rs.Table` is written from memory (``chunks``:
    Zarr chunks over the axes, default whole).

    Returns:
        ``path``.

    Raises:
        FileExistsError: ``path`` holds data and ``overwrite`` is false.
    """
    if isinstance(table, LazyTable):
        zarr_chunks = _zarr_chunks(table.chunks) if chunks is None else tuple(chunks)
        group, targets = _prepare_store(table, path, overwrite, zarr_chunks)
        _stream(table, targets, zarr_chunks, kwargs)
    elif isinstance(table, Table):
        shape = table.samples.shape
        zarr_chunks = shape if chunks is None else tuple(chunks)
        group, targets = _prepare_store(table, path, overwrite, zarr_chunks)
        for target, data in zip(targets, (table.value, table.stderr, table.samples), strict=True):
            target[...] = data
    else:
        raise TypeError(f"table: expected a brdf_rs.Table or LazyTable; got {type(table)}")
    group.attrs[_COMPLETE_KEY] = True
    return path


def _stream(
    table: LazyTable,
    targets: tuple[Any, ...],
    zarr_chunks: tuple[int, ...],
    kwargs: dict[str, Any],
) -> None:
    dask = _import_dask()
    kwargs = table._kwargs(kwargs)
    plan = table._plan
    aligned = all(
        all(b % z == 0 for b in c[:-1]) for c, z in zip(table.chunks, zarr_chunks, strict=True)
    )
    if plan is not None and aligned:
        import functools

        store = functools.partial(_store_block, targets=targets)
        client = table._distributed(kwargs)
        if client is not None:
            for _ in _run_blocks(client, plan, "store", store, kwargs):
                pass
            return
        # One task per block: integrate, write, return a count.
        from dask.delayed import Delayed
        from dask.highlevelgraph import HighLevelGraph

        name = f"albedo-store-{plan.token}"
        layer = {(name, *i): (store, block) for i, block in plan.blocks()}
        total = f"albedo-stored-{plan.token}"
        graph = HighLevelGraph(
            {name: layer, total: {total: (_total, list(layer))}}, {name: set(), total: {name}}
        )
        dask.compute(Delayed(total, graph), **kwargs)
        return
    import dask.array as da

    sources = []
    for array in (table.value, table.stderr, table.samples):
        want = zarr_chunks if array.ndim == len(zarr_chunks) else (*zarr_chunks, 3)
        ok = all(all(b % z == 0 for b in c[:-1]) for c, z in zip(array.chunks, want, strict=True))
        sources.append(array if ok else array.rechunk(want))
    da.store(sources, list(targets), lock=False, compute=True, **kwargs)


def read_zarr(path: Any, *, lazy: bool = False, client: Any = None) -> Table | LazyTable:
    """Reads a table written by :func:`write_zarr` / :meth:`LazyTable.to_zarr`.

    Returns a :class:`brdf_rs.Table` (in memory), or with ``lazy=True`` a
    :class:`LazyTable` whose arrays read the store block by block (its Zarr chunks).

    Raises:
        ValueError: the store is not a brdf-rs table, or its build did not finish.
    """
    group = _open_group(path, "r")
    attrs = dict(group.attrs)
    if attrs.get(_FORMAT_KEY) != _FORMAT:
        raise ValueError(f"{path}: not a brdf-rs table store (no {_FORMAT_KEY!r} attribute)")
    if not attrs.get(_COMPLETE_KEY):
        raise ValueError(f"{path}: the table is incomplete (its build was interrupted)")
    meta = {k: v for k, v in attrs.items() if k not in (_FORMAT_KEY, _COMPLETE_KEY)}
    axes = {name: np.asarray(group[name][...]) for name in meta["axis_names"]}
    if lazy:
        _import_dask()
        import dask.array as da

        value, stderr, samples = (
            da.from_array(group[what], chunks=group[what].chunks) for what in _ARRAYS
        )
        return LazyTable(value, stderr, samples, axes, meta, client)
    value, stderr, samples = (np.asarray(group[what][...]) for what in _ARRAYS)
    return Table(value, stderr, samples, axes, meta)
