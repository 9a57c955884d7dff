"""Albedo tables on Dask (brdf_rs.dask): the same bits as the local build, whatever the
chunking or the workers, a worker killed mid-build, Zarr round trips.

The cluster is a ``dask.distributed.LocalCluster`` of two worker processes (one thread
each) on the loopback interface. Skipped when dask / distributed is not installed (the
``dask`` extra); the Zarr tests also need zarr.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time

import brdf_rs
import brdf_rs.dask
import numpy as np
import pytest

try:
    import dask
    import dask.array
    import distributed
except ImportError:  # the dask extra is not installed
    dask = distributed = None

try:
    import zarr
except ImportError:
    zarr = None

# Old dask warns when a test uses local threads while the module's client is active.
pytestmark = pytest.mark.filterwarnings("ignore:Running on a single-machine scheduler")

needs_dask = pytest.mark.skipif(distributed is None, reason="needs dask[array,distributed]")
needs_zarr = pytest.mark.skipif(distributed is None or zarr is None, reason="needs dask and zarr")

# Small tables, and the arguments of both the local and the Dask builds.
AXES_2D = {"mu": (np.arange(12) + 0.5) / 12, "p": np.geomspace(1, 1e3, 9)}
ARGS_2D = {"kd": 0.0, "ks": 1.0, "eta": 1.5, "samples": 1024, "seed": 7}
AXES_4D = {
    "mu": (np.arange(6) + 0.5) / 6,
    "p": np.geomspace(1, 1e3, 5),
    "eta": [1.3, 1.5, 2.0],
    "ks": [0.25, 1.0],
}
ARGS_4D = {"kd": [0.1, 0.05, 0.0], "samples": 512, "seed": 11}


def assert_same_bits(table, local):
    """Value, stderr and samples bit for bit; axes and metadata equal."""
    for what in ("value", "stderr", "samples"):
        got, want = getattr(table, what), getattr(local, what)
        assert got.shape == want.shape and got.dtype == want.dtype, what
        assert got.tobytes() == want.tobytes(), f"{what} differs"
    assert list(table.axes) == list(local.axes)
    for name in local.axes:
        assert table.axes[name].tobytes() == local.axes[name].tobytes()
    assert table.meta == local.meta


@pytest.fixture(scope="module")
def client():
    with (
        distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            host="127.0.0.1",
            env={"BRDF_RS_NUM_THREADS": "1"},
        ) as cluster,
        distributed.Client(cluster) as c,
    ):
        yield c


def test_import_brdf_rs_does_not_import_dask():
    code = (
        "import sys, brdf_rs, brdf_rs.dask\n"
        "bad = [m for m in ('dask', 'distributed', 'zarr') if m in sys.modules]\n"
        "assert not bad, bad\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


@needs_dask
@pytest.mark.parametrize(
    "chunks",
    [
        "auto",  # one block for a table this small
        1,  # one cell per task
        (5, 4),
        {"p": 2},  # mu whole, p in pairs
        ((1, 4, 7), (2, 7)),  # irregular blocks
    ],
)
def test_same_bits_as_the_local_build_for_any_chunking(client, chunks):
    local = brdf_rs.albedo_table("torrance_sparrow", AXES_2D, **ARGS_2D)
    lazy = brdf_rs.dask.albedo_table(
        "torrance_sparrow", AXES_2D, chunks=chunks, client=client, **ARGS_2D
    )
    assert isinstance(lazy, brdf_rs.dask.LazyTable)
    assert_same_bits(lazy.compute(), local)
    # The Dask arrays themselves (the graph path), computed on the cluster.
    value, samples = dask.compute(lazy.value, lazy.samples, scheduler=client)
    assert value.tobytes() == local.value.tobytes()
    assert samples.tobytes() == local.samples.tobytes()


@needs_dask
def test_adaptive_tol_and_the_local_threaded_scheduler(client):
    args = {"kd": 0.0, "ks": 1.0, "samples": 256, "tol": 3e-4, "seed": 2}
    local = brdf_rs.albedo_table("normalized_phong", AXES_2D, **args)
    assert local.samples.min() < local.samples.max()  # cells stopped at different counts
    on_cluster = brdf_rs.dask.albedo_table(
        "normalized_phong", AXES_2D, chunks=(4, 3), client=client, compute=True, **args
    )
    assert isinstance(on_cluster, brdf_rs.Table)
    assert_same_bits(on_cluster, local)
    lazy = brdf_rs.dask.albedo_table("normalized_phong", AXES_2D, chunks=(5, 5), **args)
    assert_same_bits(lazy.compute(scheduler="threads"), local)
    # A relative tolerance too, recorded in the metadata as locally.
    relative = {**args, "tol": None, "rtol": 0.02}
    local = brdf_rs.albedo_table("normalized_phong", AXES_2D, **relative)
    lazy = brdf_rs.dask.albedo_table("normalized_phong", AXES_2D, chunks=(5, 5), **relative)
    computed = lazy.compute(scheduler="threads")
    assert_same_bits(computed, local)
    assert computed.meta == local.meta and local.meta["rtol"] == 0.02


@needs_dask
def test_lazy_table_shapes_and_partial_computation():
    lazy = brdf_rs.dask.albedo_table("torrance_sparrow", AXES_2D, chunks=(4, 3), **ARGS_2D)
    assert lazy.shape == (12, 9) and lazy.chunks == ((4, 4, 4), (3, 3, 3))
    assert lazy.value.shape == (12, 9, 3) and lazy.value.dtype == np.float64
    assert lazy.stderr.chunks == ((4, 4, 4), (3, 3, 3), (3,))
    assert lazy.samples.shape == (12, 9) and lazy.samples.dtype == np.uint64
    assert lazy.value.npartitions == 9
    local = brdf_rs.albedo_table("torrance_sparrow", AXES_2D, **ARGS_2D)
    # One block alone, computed on its own, has the full table's bits.
    corner = lazy.value[8:, 6:].compute(scheduler="sync")
    assert corner.tobytes() == local.value[8:, 6:].tobytes()
    assert "blocks=9" in repr(lazy)


@needs_dask
def test_bad_requests_fail_before_any_task_runs():
    with pytest.raises(ValueError, match=r"^axes\['p'\]\[1\]: p = -2\.0 is out of range"):
        brdf_rs.dask.albedo_table("torrance_sparrow", {"mu": [0.5], "p": [1.0, -2.0]}, ks=1)
    with pytest.raises(ValueError, match="unknown model"):
        brdf_rs.dask.albedo_table("no_such_model", {"mu": [0.5]})
    with pytest.raises(ValueError, match="both as an axis and as a fixed value"):
        brdf_rs.dask.albedo_table("normalized_phong", {"mu": [0.5], "p": [1.0]}, p=2.0)
    with pytest.raises(ValueError, match="chunks: 'q' is not an axis"):
        brdf_rs.dask.albedo_table("normalized_phong", {"mu": [0.5]}, chunks={"q": 1})
    with pytest.raises(TypeError, match="progress: not available"):
        brdf_rs.dask.albedo_table("normalized_phong", {"mu": [0.5]}, progress=print)
    with pytest.raises(ValueError, match="tol: must be a positive number"):
        brdf_rs.dask.albedo_table("normalized_phong", {"mu": [0.5]}, tol=-1.0)
    with pytest.raises(ValueError, match="chunks: cannot split"):
        brdf_rs.dask.albedo_table("normalized_phong", {"mu": [0.5]}, chunks=0)


if distributed is not None:

    class DieOnce(distributed.WorkerPlugin):
        """Kills the worker process shortly after it starts its first block task, once
        per cluster: the flag file (created exclusively) records who died."""

        def __init__(self, flag: str, delay: float):
            self.flag = flag
            self.delay = delay

        def setup(self, worker):
            self.worker = worker

        def transition(self, key, start, finish, **kwargs):
            name = key[0] if isinstance(key, tuple) else key
            if finish != "executing" or not str(name).startswith("albedo-"):
                return
            try:
                fd = os.open(self.flag, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            except FileExistsError:
                return
            os.write(fd, f"{os.getpid()} {name} {self.worker.address}".encode())
            os.close(fd)
            threading.Timer(self.delay, os._exit, args=(1,)).start()


@needs_dask
@pytest.mark.parametrize("to_zarr", [False, pytest.param(True, marks=needs_zarr)])
def test_a_worker_killed_mid_build_loses_only_its_block(client, tmp_path, to_zarr):
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # workers can't import us
    axes = {"mu": (np.arange(8) + 0.5) / 8, "p": np.geomspace(1, 1e3, 8)}
    args = {"kd": 0.0, "ks": 1.0, "eta": 1.5, "samples": 1 << 19, "seed": 5}  # ~0.35 s a block
    local = brdf_rs.albedo_table("torrance_sparrow", axes, **args)
    flag = tmp_path / "killed"
    before = set(client.run(os.getpid).values())
    name = "brdf-rs-die-once"
    client.register_plugin(DieOnce(str(flag), delay=0.02), name=name)
    try:
        lazy = brdf_rs.dask.albedo_table(
            "torrance_sparrow", axes, chunks=(2, 4), client=client, **args
        )
        with distributed.get_task_stream(client) as stream:
            if to_zarr:
                store = tmp_path / "killed.zarr"
                lazy.to_zarr(store, retries=2)
                table = brdf_rs.dask.read_zarr(store)
            else:
                table = lazy.compute(retries=2)
    finally:
        client.unregister_worker_plugin(name)
    assert flag.exists(), "no worker was killed"
    pid, killed_key, killed_worker = flag.read_text().split()
    pid = int(pid)
    assert pid in before
    assert_same_bits(table, local)
    # Every block finished exactly once: the killed one's first try never finished, and
    # no block that had finished elsewhere (or earlier) was computed again.
    finished = {}
    for t in stream.data:
        if str(t["key"]).startswith("albedo-"):
            assert t["key"] not in finished, f"{t['key']} computed twice"
            finished[t["key"]] = t["worker"]
    assert len(finished) == 8
    assert finished[killed_key] != killed_worker  # it died mid-block; another finished it
    # The nanny starts a new worker. Starting a process that imports NumPy, Dask and the
    # extension can take long on a loaded machine (the suite runs in parallel processes),
    # so the wait is generous and a timeout says what the scheduler saw.
    wait_for_running_workers(client, 2, timeout=300)
    after = set(client.run(os.getpid).values())
    assert pid not in after and len(after) == 2


def wait_for_running_workers(client, n, timeout):
    """Waits until the scheduler lists ``n`` workers whose status is "running"."""
    deadline = time.monotonic() + timeout
    while True:
        workers = client.scheduler_info()["workers"]
        status = {w.get("name"): w.get("status") for w in workers.values()}
        if sum(s == "running" for s in status.values()) >= n:
            return
        if time.monotonic() > deadline:
            pytest.fail(
                f"{n} running workers expected after {timeout} s; the scheduler has {status}"
            )
        time.sleep(0.2)


@needs_zarr
def test_4d_table_streamed_to_zarr_and_read_back(client, tmp_path):
    local = brdf_rs.albedo_table("torrance_sparrow", AXES_4D, **ARGS_4D)
    assert local.value.shape == (6, 5, 3, 2, 3)
    lazy = brdf_rs.dask.albedo_table(
        "torrance_sparrow", AXES_4D, chunks={"mu": 2, "p": 3, "eta": 1}, client=client, **ARGS_4D
    )
    path = tmp_path / "ts.zarr"
    assert lazy.to_zarr(path) == path
    assert_same_bits(brdf_rs.dask.read_zarr(path), local)
    # The store: chunked like the blocks, metadata as attributes, complete.
    group = zarr.open_group(str(path), mode="r")
    assert group["value"].chunks == (2, 3, 1, 2, 3)
    assert group.attrs["model"] == "torrance_sparrow"
    assert group.attrs["axis_names"] == ["mu", "p", "eta", "ks"]
    assert group.attrs["brdf_rs_complete"] is True
    # Lazily, as Dask arrays over the store.
    back = brdf_rs.dask.read_zarr(path, lazy=True, client=client)
    assert isinstance(back.value, dask.array.Array)
    assert back.value.chunks == lazy.value.chunks
    assert_same_bits(back.compute(), local)
    # A Table from memory and a LazyTable without a plan (read back) write the same.
    brdf_rs.dask.write_zarr(local, tmp_path / "local.zarr", chunks=(3, 5, 3, 1))
    assert_same_bits(brdf_rs.dask.read_zarr(tmp_path / "local.zarr"), local)
    back.to_zarr(tmp_path / "again.zarr")
    assert_same_bits(brdf_rs.dask.read_zarr(tmp_path / "again.zarr"), local)
    # Existing stores are not overwritten unless asked; unfinished ones are refused.
    with pytest.raises(FileExistsError, match="already holds data; pass overwrite=True"):
        lazy.to_zarr(path)
    lazy.to_zarr(path, overwrite=True)
    group = zarr.open_group(str(path), mode="r+")
    group.attrs["brdf_rs_complete"] = False
    with pytest.raises(ValueError, match="incomplete"):
        brdf_rs.dask.read_zarr(path)


@needs_zarr
def test_zarr_with_the_threaded_scheduler_and_a_fixed_mu(tmp_path):
    axes = {"p": np.geomspace(1, 100, 7), "eta": [1.2, 1.5, 3.0]}
    args = {"mu": 0.4, "kd": 0.0, "ks": 1.0, "samples": 256}
    local = brdf_rs.albedo_table("torrance_sparrow", axes, **args)
    lazy = brdf_rs.dask.albedo_table("torrance_sparrow", axes, chunks=(3, 2), **args)
    with dask.config.set(scheduler="threads"):
        start = time.perf_counter()
        lazy.to_zarr(tmp_path / "t.zarr")
        assert time.perf_counter() - start < 30
    assert_same_bits(brdf_rs.dask.read_zarr(tmp_path / "t.zarr"), local)
