"""Albedo tables on Dask: 1 and 2 worker processes against the local build, and a
projection to 100 workers from the measured per-task cost and scheduler overhead.

The table: torrance_sparrow over mu x p x eta x ks (16 x 16 x 8 x 4 =
8192 cells, kd = 0, 16384 samples per cell, seed 1), built

- locally (``brdf_rs.albedo_table``) with 1 and 2 rayon threads, and
- on a Dask cluster on this machine (a ``dask scheduler`` process and ``dask worker``
  processes on the loopback interface, started here): 1 worker x 1 thread; 1 worker
  with 2 rayon threads; 1 worker x 2 Dask threads; 2 workers x 1 thread, each at two
  chunkings (16 blocks of 512 cells, 64 blocks of 128 cells), checking every result is
  bitwise the local table.

Then it measures the per-task overhead with no-op tasks submitted the way a build
submits its blocks (``Client.map`` + ``as_completed``): the scheduler's CPU time per
task (its own process), the workers' and the client's, and projects the wall time of
a build on 100 single-core workers (the method is written in the .md). Prints the
tables and writes benches/results/dask_scaling.{md,json}.

    python benches/dask_scaling.py              # ~5 minutes on 2 cores
    python benches/dask_scaling.py --quick      # a smaller table, 1 repetition
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"

import brdf_rs  # noqa: E402
import brdf_rs.dask  # noqa: E402

MODEL = "torrance_sparrow"
PROJECTED_WORKERS = 100


def table_spec(quick: bool) -> dict:
    n = 8 if quick else 16
    return {
        "axes": {
            "mu": (np.arange(n) + 0.5) / n,
            "p": np.geomspace(1.0, 1e4, n),
            "eta": np.linspace(1.2, 3.0, 8),
            "ks": np.array([0.25, 0.5, 0.75, 1.0]),
        },
        "args": {"kd": 0.0, "samples": 4096 if quick else 16384, "seed": 1},
    }


#: Blocks over (mu, p, eta, ks): 512 and 128 cells.
CHUNKINGS = {"coarse": (4, 4, 8, 4), "fine": (2, 2, 8, 4)}


# ------------------------------------------------------------------------------ clusters


def _cpu(pids: list[int]) -> float:
    """Total CPU seconds (user + system) of these processes so far."""
    import psutil

    total = 0.0
    for pid in pids:
        try:
            t = psutil.Process(pid).cpu_times()
        except psutil.NoSuchProcess:
            continue
        total += t.user + t.system
    return total


@contextlib.contextmanager
def cluster(workers: int, nthreads: int, rayon: int, scratch: Path):
    """A scheduler and ``workers`` worker processes on 127.0.0.1, started (and stopped)
    here, the workers' rayon pools set to ``rayon`` threads. Yields ``(client,
    scheduler pid, worker pids)``."""
    from dask.distributed import Client

    cli = str(Path(sys.executable).with_name("dask"))
    env = {**os.environ, "BRDF_RS_NUM_THREADS": str(rayon)}
    scheduler_file = scratch / f"scheduler-{os.getpid()}-{time.monotonic_ns()}.json"
    log = open(scratch / "cluster.log", "ab")
    local = ("--host", "127.0.0.1", "--no-dashboard")
    command = [cli, "scheduler", *local, "--port", "0", "--scheduler-file", str(scheduler_file)]
    procs = [subprocess.Popen(command, stdout=log, stderr=log, env=env)]
    client = None
    try:
        deadline = time.monotonic() + 60
        while not scheduler_file.exists():
            if time.monotonic() > deadline or procs[0].poll() is not None:
                raise RuntimeError(f"the scheduler did not start; see {scratch / 'cluster.log'}")
            time.sleep(0.1)
        for i in range(workers):
            command = [cli, "worker", *local, "--scheduler-file", str(scheduler_file)]
            command += ["--nthreads", str(nthreads), "--name", f"w{i}", "--memory-limit", "0"]
            procs.append(subprocess.Popen(command, stdout=log, stderr=log, env=env))
        client = Client(scheduler_file=str(scheduler_file), timeout="60s")
        client.wait_for_workers(workers, timeout=120)
        worker_pids = sorted(client.run(os.getpid).values())
        assert all(n == rayon for n in client.run(brdf_rs.num_threads).values())
        yield client, procs[0].pid, worker_pids
    finally:
        if client is not None:
            with contextlib.suppress(Exception):
                client.shutdown()
            client.close()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.terminate()
                try:
                    p.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
        log.close()
        scheduler_file.unlink(missing_ok=True)


def _noop(i: int) -> int:
    return i


def overhead_per_task(client, scheduler_pid: int, worker_pids: list[int], n: int) -> dict:
    """No-op tasks submitted and gathered the way a build does it: wall time and the
    CPU time of the scheduler, the workers and this client, per task."""
    from distributed import as_completed

    client.gather(client.map(_noop, range(50), key=[f"warm-{i}" for i in range(50)]))
    token = time.monotonic_ns()
    s0, w0, c0 = _cpu([scheduler_pid]), _cpu(worker_pids), time.process_time()
    start = time.perf_counter()
    futures = client.map(_noop, range(n), key=[f"noop-{token}-{i}" for i in range(n)])
    for future, _ in as_completed(futures, with_results=True):
        del future
    del futures
    wall = time.perf_counter() - start
    s1, w1, c1 = _cpu([scheduler_pid]), _cpu(worker_pids), time.process_time()
    # A one-task round trip: the fixed latency of a build (median of 10).
    trips = []
    for i in range(10):
        start = time.perf_counter()
        client.submit(_noop, -1, key=f"one-{token}-{i}").result()
        trips.append(time.perf_counter() - start)
    latency = float(np.median(trips))
    return {
        "tasks": n,
        "wall_per_task_ms": 1e3 * wall / n,
        "scheduler_cpu_per_task_ms": 1e3 * (s1 - s0) / n,
        "worker_cpu_per_task_ms": 1e3 * (w1 - w0) / n,
        "client_cpu_per_task_ms": 1e3 * (c1 - c0) / n,
        "round_trip_ms": 1e3 * latency,
    }


# ----------------------------------------------------------------------------- builds


def same_bits(a, b) -> bool:
    return all(
        getattr(a, k).tobytes() == getattr(b, k).tobytes() for k in ("value", "stderr", "samples")
    )


def time_local(spec: dict, threads: int, reps: int):
    """Median wall and CPU seconds of the local build on ``threads`` rayon threads."""
    before = brdf_rs.num_threads()
    brdf_rs.set_num_threads(threads)
    try:
        walls, cpus = [], []
        for _ in range(reps):
            cpu, start = time.process_time(), time.perf_counter()
            table = brdf_rs.albedo_table(MODEL, spec["axes"], **spec["args"])
            walls.append(time.perf_counter() - start)
            cpus.append(time.process_time() - cpu)
    finally:
        brdf_rs.set_num_threads(before)
    return float(np.median(walls)), float(np.median(cpus)), table


class CpuMeter:
    """CPU seconds spent by this client, the scheduler and the workers."""

    def __init__(self, scheduler_pid: int, worker_pids: list[int]):
        self.scheduler, self.workers = [scheduler_pid], worker_pids

    def read(self) -> np.ndarray:
        return np.array([time.process_time(), _cpu(self.scheduler), _cpu(self.workers)])


def time_dask(client, meter: CpuMeter, spec: dict, chunks, reps: int, local) -> dict:
    from distributed import get_task_stream

    lazy = brdf_rs.dask.albedo_table(
        MODEL, spec["axes"], chunks=chunks, client=client, **spec["args"]
    )
    blocks = math.prod(len(c) for c in lazy.chunks)
    walls, cpus, task_seconds, identical = [], [], [], True
    for _ in range(reps):
        with get_task_stream(client) as stream:
            cpu, start = meter.read(), time.perf_counter()
            table = lazy.compute()
            walls.append(time.perf_counter() - start)
            cpus.append(meter.read() - cpu)
        identical &= same_bits(table, local)
        for t in stream.data:
            if str(t["key"]).startswith("albedo-block-"):
                task_seconds += [
                    s["stop"] - s["start"] for s in t["startstops"] if s["action"] == "compute"
                ]
    cpu = np.median(np.array(cpus), axis=0)
    return {
        "blocks": blocks,
        "cells_per_block": int(np.prod([c[0] for c in lazy.chunks])),
        "wall_s": float(np.median(walls)),
        "cpu_s": float(cpu.sum()),
        "cpu_client_s": float(cpu[0]),
        "cpu_scheduler_s": float(cpu[1]),
        "cpu_workers_s": float(cpu[2]),
        "task_mean_s": float(np.mean(task_seconds)),
        "identical": bool(identical),
    }


def time_zarr(client, spec: dict, chunks, reps: int, scratch: Path, local) -> dict:
    import importlib

    client.run(importlib.import_module, "zarr")  # not timed: the workers' first import
    lazy = brdf_rs.dask.albedo_table(
        MODEL, spec["axes"], chunks=chunks, client=client, **spec["args"]
    )
    path = scratch / "bench.zarr"
    walls, identical = [], True
    for _ in range(reps):
        start = time.perf_counter()
        lazy.to_zarr(path, overwrite=True)
        walls.append(time.perf_counter() - start)
        identical &= same_bits(brdf_rs.dask.read_zarr(path), local)
    shutil.rmtree(path, ignore_errors=True)
    return {"wall_s": float(np.median(walls)), "identical": bool(identical)}


# ------------------------------------------------------------------------- projection


def project(n_blocks: int, t_block: float, w: int, over: dict, cores: int | None = None) -> float:
    """Wall time of ``n_blocks`` blocks of ``t_block`` seconds each (on one worker's
    cores) on ``w`` workers (see the .md): the slower of the workers' waves and the
    scheduler's (or client's) serial per-task work, plus one round trip; with
    ``cores`` (everything on one machine) also at least the total CPU over the cores."""
    o_w = over["worker_cpu_per_task_ms"] / 1e3
    serial = max(over["scheduler_cpu_per_task_ms"], over["client_cpu_per_task_ms"]) / 1e3
    waves = math.ceil(n_blocks / w) * (t_block + o_w)
    t = max(waves, n_blocks * serial)
    if cores is not None:
        cpu = (
            n_blocks * (t_block + o_w)
            + n_blocks * (over["scheduler_cpu_per_task_ms"] + over["client_cpu_per_task_ms"]) / 1e3
        )
        t = max(t, cpu / cores)
    return t + over["round_trip_ms"] / 1e3


# ------------------------------------------------------------------------------- main

CONFIGS = [
    # name, worker processes, Dask threads per worker, rayon threads per worker, cores
    ("1 worker x 1 thread", 1, 1, 1, 1),
    ("1 worker x 1 thread, rayon 2", 1, 1, 2, 2),
    ("1 worker x 2 threads", 1, 2, 1, 2),
    ("2 workers x 1 thread", 2, 1, 1, 2),
]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a smaller table, 1 repetition")
    parser.add_argument("--reps", type=int, default=None, help="repetitions (median; default 3)")
    parser.add_argument("--noop-tasks", type=int, default=2000)
    parser.add_argument("--no-write", action="store_true", help="do not write benches/results")
    args = parser.parse_args(argv)
    reps = args.reps or (1 if args.quick else 3)
    spec = table_spec(args.quick)
    chunks = CHUNKINGS
    shape = tuple(len(v) for v in spec["axes"].values())
    cells = math.prod(shape)
    load_before = os.getloadavg()
    print(
        f"{MODEL} {' x '.join(f'{k}[{len(v)}]' for k, v in spec['axes'].items())} = {cells} "
        f"cells, {spec['args']['samples']} samples per cell; {os.cpu_count()} CPUs (load "
        f"average {load_before[0]:.2f}), {reps} repetition(s)",
        flush=True,
    )
    local, local_cpu = {}, {}
    for threads in (1, 2):
        local[threads], local_cpu[threads], reference = time_local(spec, threads, reps)
        print(
            f"  local, {threads} rayon thread(s): {local[threads]:.3f} s "
            f"({local_cpu[threads]:.3f} s CPU)",
            flush=True,
        )
    per_cell = local_cpu[1] / cells  # CPU seconds per cell on one core

    rows, over, zarr_row = [], None, None
    scratch = Path(tempfile.mkdtemp(prefix="brdf_rs_dask_bench_"))
    try:
        for name, workers, nthreads, rayon, cores in CONFIGS:
            with cluster(workers, nthreads, rayon, scratch) as (client, sched_pid, worker_pids):
                meter = CpuMeter(sched_pid, worker_pids)
                # Warm up: the workers import brdf_rs and run one block.
                brdf_rs.dask.albedo_table(
                    MODEL, {"mu": [0.5]}, client=client, compute=True, kd=0, ks=1
                )
                for label, ch in chunks.items():
                    r = time_dask(client, meter, spec, ch, reps, reference)
                    extra_cpu = r["cpu_s"] - local_cpu[1]
                    r.update(
                        config=name,
                        workers=workers,
                        threads_per_worker=nthreads,
                        rayon_threads=rayon,
                        cores=cores,
                        chunking=label,
                        local_s=local[cores],
                        overhead=r["wall_s"] / local[cores] - 1.0,
                        local_cpu_s=local_cpu[1],
                        cpu_overhead=extra_cpu / local_cpu[1],
                        cpu_overhead_per_block_ms=1e3 * extra_cpu / r["blocks"],
                    )
                    rows.append(r)
                    print(
                        f"  {name:30s} {label:6s} {r['blocks']:3d} blocks: {r['wall_s']:.3f} s "
                        f"(local {local[cores]:.3f} s: {100 * r['overhead']:+.1f}%), CPU "
                        f"{r['cpu_s']:.3f} s ({100 * r['cpu_overhead']:+.1f}%), "
                        f"task {1e3 * r['task_mean_s']:.1f} ms, identical={r['identical']}",
                        flush=True,
                    )
                if workers == 2:
                    zarr_row = time_zarr(client, spec, chunks["coarse"], reps, scratch, reference)
                    zarr_row.update(
                        config=name,
                        chunking="coarse",
                        compute_s=next(
                            r["wall_s"]
                            for r in rows
                            if r["config"] == name and r["chunking"] == "coarse"
                        ),
                    )
                    print(
                        f"  {name:30s} coarse to_zarr: {zarr_row['wall_s']:.3f} s, "
                        f"identical={zarr_row['identical']}",
                        flush=True,
                    )
                    over = overhead_per_task(client, sched_pid, worker_pids, args.noop_tasks)
                    print(
                        "  no-op tasks: {wall_per_task_ms:.2f} ms wall per task; CPU per task: "
                        "scheduler {scheduler_cpu_per_task_ms:.2f} ms, workers "
                        "{worker_cpu_per_task_ms:.2f} ms, client {client_cpu_per_task_ms:.2f} "
                        "ms; round trip {round_trip_ms:.1f} ms".format(**over),
                        flush=True,
                    )
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    load_after = os.getloadavg()

    # Check the model against what was measured here (everything on one machine), then
    # project to 100 single-core workers (scheduler and client on their own cores).
    checks = []
    for r in rows:
        if r["rayon_threads"] != 1:
            continue
        slots = r["workers"] * r["threads_per_worker"]
        model = project(r["blocks"], r["task_mean_s"], slots, over, cores=os.cpu_count())
        checks.append(
            {
                "config": r["config"],
                "chunking": r["chunking"],
                "model_s": model,
                "measured_s": r["wall_s"],
            }
        )
    projections = []
    big_shape = (64, 64, 32, 16)
    serial_s = max(over["scheduler_cpu_per_task_ms"], over["client_cpu_per_task_ms"]) / 1e3
    for label, ch in chunks.items():
        block_cells = math.prod(ch)
        t_block = block_cells * per_cell
        for what, n_cells in (
            ("this table", cells),
            ("x".join(map(str, big_shape)), math.prod(big_shape)),
        ):
            n_blocks = math.ceil(n_cells / block_cells)
            t_local = n_cells * per_cell
            t = project(n_blocks, t_block, PROJECTED_WORKERS, over)
            waves = math.ceil(n_blocks / PROJECTED_WORKERS) * (
                t_block + over["worker_cpu_per_task_ms"] / 1e3
            )
            projections.append(
                {
                    "table": what,
                    "cells": n_cells,
                    "chunking": label,
                    "cells_per_block": block_cells,
                    "blocks": n_blocks,
                    "block_s": t_block,
                    "local_1_core_s": t_local,
                    "projected_s": t,
                    "speedup": t_local / t,
                    "efficiency": t_local / t / PROJECTED_WORKERS,
                    "bound": "scheduler" if n_blocks * serial_s > waves else "workers",
                }
            )

    result = {
        "machine": {
            "platform": platform.platform(),
            "python": platform.python_version(),
            "cpus": os.cpu_count(),
            "load_average_before": load_before,
            "load_average_after": load_after,
            "isa": brdf_rs.isa(),
            "brdf_rs": brdf_rs.__version__,
            "dask": _version("dask"),
            "distributed": _version("distributed"),
        },
        "table": {
            "model": MODEL,
            "shape": shape,
            "cells": cells,
            **spec["args"],
            "axes": {k: np.asarray(v).tolist() for k, v in spec["axes"].items()},
        },
        "reps": reps,
        "local_s": {str(k): v for k, v in local.items()},
        "local_cpu_s": {str(k): v for k, v in local_cpu.items()},
        "per_cell_1_core_ms": 1e3 * per_cell,
        "builds": rows,
        "zarr": zarr_row,
        "noop_overhead": over,
        "model_check": checks,
        "projection_workers": PROJECTED_WORKERS,
        "projections": projections,
    }
    md = markdown(result)
    print()
    print(md)
    if not args.no_write:
        RESULTS.mkdir(exist_ok=True)
        (RESULTS / "dask_scaling.json").write_text(json.dumps(result, indent=2) + "\n")
        (RESULTS / "dask_scaling.md").write_text(md)
        print(f"wrote {RESULTS / 'dask_scaling.md'} and .json")


def _version(module: str) -> str:
    try:
        return __import__(module).__version__
    except ImportError:
        return "not installed"


def markdown(r: dict) -> str:
    t, o, m = r["table"], r["noop_overhead"], r["machine"]
    lines = [
        "# Albedo tables on Dask: scaling",
        "",
        f"`python benches/dask_scaling.py` on {m['cpus']} CPUs ({m['platform']}, ISA "
        f"{m['isa']}), brdf-rs {m['brdf_rs']}, dask {m['dask']}, distributed "
        f"{m['distributed']}; median of {r['reps']} run(s). Load average (1 min) "
        f"{m['load_average_before'][0]:.2f} before, {m['load_average_after'][0]:.2f} after: "
        "other work shared the machine, so wall times are noisy; CPU times are steadier.",
        "",
        f"Table: `{t['model']}` over mu x p x eta x ks = {' x '.join(map(str, t['shape']))} = "
        f"{t['cells']} cells, kd = {t['kd']}, {t['samples']} samples per cell, seed "
        f"{t['seed']}. Local build (`brdf_rs.albedo_table`): {r['local_s']['1']:.3f} s on 1 "
        f"rayon thread, {r['local_s']['2']:.3f} s on 2; {r['local_cpu_s']['1']:.3f} CPU "
        f"seconds ({r['per_cell_1_core_ms']:.3f} ms per cell).",
        "",
        "Cluster: a `dask scheduler` and `dask worker` processes on 127.0.0.1, started by "
        "the script; the client, the scheduler and the workers share this machine's cores. "
        "Every Dask result was checked bit for bit against the local table.",
        "",
        "## Builds (in memory, `LazyTable.compute()`)",
        "",
        "Wall overhead: against the local build on the same number of cores. CPU: all "
        "processes (client, scheduler, workers), against the local build's CPU time; it "
        "includes the idle cost of the event loops (heartbeats, monitors) over the run, "
        "so it is not all per-block work.",
        "",
        "| cluster | cores | blocks | cells/block | wall s | local s | wall overhead "
        "| CPU s | CPU overhead | mean task s | identical |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|:-:|",
    ]
    for b in r["builds"]:
        lines.append(
            f"| {b['config']} | {b['cores']} | {b['blocks']} | {b['cells_per_block']} | "
            f"{b['wall_s']:.3f} | {b['local_s']:.3f} | {100 * b['overhead']:+.1f}% | "
            f"{b['cpu_s']:.3f} | {100 * b['cpu_overhead']:+.1f}% | "
            f"{b['task_mean_s']:.3f} | {'yes' if b['identical'] else '**NO**'} |"
        )
    if r["zarr"]:
        z = r["zarr"]
        lines += [
            "",
            f"Streamed to Zarr (`LazyTable.to_zarr`, {z['config']}, coarse blocks; each task "
            f"writes its block): {z['wall_s']:.3f} s against {z['compute_s']:.3f} s in memory; "
            f"read back identical: {'yes' if z['identical'] else '**NO**'}.",
        ]
    lines += [
        "",
        "## Per-task overhead (no-op tasks, 2 workers x 1 thread)",
        "",
        f"{o['tasks']} no-op tasks submitted and gathered the way a build submits its blocks "
        "(`Client.map`, then `as_completed` with results):",
        "",
        "| wall per task | scheduler CPU per task | worker CPU per task | client CPU per task "
        "| one-task round trip |",
        "|---:|---:|---:|---:|---:|",
        f"| {o['wall_per_task_ms']:.2f} ms | {o['scheduler_cpu_per_task_ms']:.2f} ms | "
        f"{o['worker_cpu_per_task_ms']:.2f} ms | {o['client_cpu_per_task_ms']:.2f} ms | "
        f"{o['round_trip_ms']:.1f} ms |",
        "",
        "## Projection to 100 workers (on paper)",
        "",
        "Method. A build is N blocks of t_b seconds each: t_b = cells per block x the "
        "per-cell cost on one core (the local build's CPU time per cell; the task stream's "
        "mean task duration agrees on an idle core). W single-core workers run the blocks "
        "in ceil(N / W) waves, each block also costing the worker o_w of per-task CPU. The "
        "scheduler is one event loop spending s CPU seconds on every task (assignment, "
        "completion, release) and the client c (submission, gathering each result); "
        "neither goes faster than one task per max(s, c) seconds, however many workers "
        "there are. So",
        "",
        "    T(W) = max( ceil(N / W) * (t_b + o_w),  N * max(s, c) ) + one round trip",
        "",
        "with s, c, o_w and the round trip from the no-op measurement above (CPU times, "
        "which contention on this machine inflates little). Speedup = N t_b / T(W), "
        "efficiency = speedup / W. The 100 workers are single-core processes "
        "(threads_per_worker = 1, BRDF_RS_NUM_THREADS = 1) on other machines, with the "
        "scheduler and the client on cores of their own. Not modelled: network bandwidth "
        "(a block's result is 56 bytes per cell, ~28 KB for 512 cells: negligible), uneven "
        "blocks (adaptive `tol` lengthens the last wave: keep N >> W), stragglers, and lost "
        "workers (each death costs the blocks it was running: about one t_b).",
        "",
        "Model check here: on one machine the total CPU N (t_b + o_w + s + c) / cores is a "
        "third lower bound; with t_b the measured mean task time and W the worker threads:",
        "",
        "| cluster | chunking | model s | measured s |",
        "|---|---|---:|---:|",
    ]
    for c in r["model_check"]:
        lines.append(
            f"| {c['config']} | {c['chunking']} | {c['model_s']:.3f} | {c['measured_s']:.3f} |"
        )
    lines += [
        "",
        f"Projection, W = {r['projection_workers']} single-core workers:",
        "",
        "| table | cells | cells/block | blocks N | t_b | local, 1 core | T(100) | speedup "
        "| efficiency | bound by |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for p in r["projections"]:
        lines.append(
            f"| {p['table']} | {p['cells']} | {p['cells_per_block']} | {p['blocks']} | "
            f"{p['block_s']:.3f} s | {p['local_1_core_s']:.1f} s | {p['projected_s']:.2f} s | "
            f"{p['speedup']:.1f}x | {100 * p['efficiency']:.0f}% | {p['bound']} |"
        )
    lines += [
        "",
        "Reading: a block must be long against W times the scheduler's per-task cost "
        "(t_b >> W max(s, c)), and there must be many blocks per worker (N >> W), or the "
        "scheduler or the last wave dominates; this benchmark's own table is far too small "
        "for 100 workers.",
        "",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
