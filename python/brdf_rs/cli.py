"""The ``brdf-rs`` command line.

argparse (the standard library) on purpose: the commands are plain subcommands with
typed options, and the core package then needs nothing beyond NumPy. Every command
prints a table for people or ``--json`` for machines; errors are one line on stderr
naming what was wrong (argparse's own errors too, with a pointer to ``--help`` instead
of the usage block). Exit codes: 0 success, 1 a failure (a file that cannot be written, a
missing optional dependency, a failed ``bench`` check), 2 a usage error (bad arguments,
unknown model, parameter out of range), 130 interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import difflib
import errno
import json
import math
import os
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

from . import _api, _images, _options, _spec
from ._brdf_rs import __version__

EXIT_USAGE = 2
EXIT_FAILURE = 1


class UsageError(Exception):
    """A bad command-line argument (exit code 2)."""


def _vector(text: str) -> list[float]:
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected x,y,z numbers, got {text!r}") from None
    if len(values) != 3:
        raise argparse.ArgumentTypeError(f"expected three comma-separated numbers, got {text!r}")
    return values


def _param(text: str) -> tuple[str, Any]:
    """Parses ``name=value``: a number, or comma-separated numbers (a colour or a list)."""
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected name=value, got {text!r}")
    name, _, value = text.partition("=")
    try:
        numbers = [float(x) for x in value.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{name}: expected numbers, got {value!r}") from None
    for x, given in zip(numbers, value.split(","), strict=True):
        if math.isinf(x) and "inf" not in given.lower():
            raise argparse.ArgumentTypeError(
                f"{name}: {given.strip()} is beyond float64's range (about 1.8e308)"
            )
    return name.strip(), numbers[0] if len(numbers) == 1 else numbers


def _named(pairs: list[tuple[str, Any]], option: str) -> dict[str, Any]:
    """The ``name=value`` pairs of a repeatable option as a dict; a name given twice is
    refused (taking one of the two silently would hide a typo)."""
    named: dict[str, Any] = {}
    for name, value in pairs:
        if name in named:
            raise UsageError(f"{option} {name}= is given twice; give each name once")
        named[name] = value
    return named


def _print_json(data: Any) -> None:
    json.dump(data, sys.stdout, indent=1, default=lambda x: np.asarray(x).tolist())
    sys.stdout.write("\n")


def cmd_models(args: argparse.Namespace) -> int:
    specs = _spec.specs()
    for name in args.names:
        if name not in specs:
            close = difflib.get_close_matches(name, specs, n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise UsageError(f"unknown model {name!r}; {hint}brdf-rs models lists them all")
    if args.names:
        specs = {name: specs[name] for name in dict.fromkeys(args.names)}
    if args.json:
        _print_json(specs)
        return 0
    for name, spec in specs.items():
        print(f"{name}  (family {spec['family']}: {spec['summary']})")
        print(f"    {spec['formula']}")
        print(f"    source: {spec['source']}")
        if spec["tangent"]:
            print("    needs tangent=")
        for p in spec["params"]:
            default = "required" if p["default"] is None else f"default {p['default']:g}"
            print(f"    {p['name']:11s} {p['kind']:12s} {default:14s} {p['range']:22s} {p['doc']}")
    return 0


def cmd_eval(args: argparse.Namespace) -> int:
    params = _named(args.param, "--param")
    value = _api.eval(args.model, args.wi, args.wo, args.n, tangent=args.tangent, **params)
    if args.json:
        _print_json({"model": args.model, "wi": args.wi, "wo": args.wo, "value": value})
    else:
        # One RGB line per value (a list-valued parameter gives several).
        for rgb in np.reshape(value, (-1, 3)):
            print(" ".join(f"{v:.17g}" for v in rgb))
    return 0


SEED_HELP = "random seed: the same seed gives the same bits"

#: The most values an axis of the command line may have.
MAX_AXIS = 1 << 20


def _axis(text: str) -> tuple[str, np.ndarray]:
    """Parses an axis: ``name=start:stop:count`` (linear, ends included),
    ``name=mid:start:stop:count`` (cell midpoints), ``name=log:start:stop:count`` or
    ``name=v1,v2,...``."""
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected name=spec, got {text!r}")
    name, _, spec = text.partition("=")
    name = name.strip()
    parts = spec.split(":")
    try:
        if len(parts) == 1:
            values = np.array([float(x) for x in spec.split(",")])
        else:
            kind = parts[0] if parts[0] in ("lin", "log", "mid") else "lin"
            nums = parts[1:] if parts[0] in ("lin", "log", "mid") else parts
            if len(nums) != 3:
                raise ValueError("need start:stop:count")
            start, stop = float(nums[0]), float(nums[1])
            try:
                count = int(nums[2])
            except ValueError:
                raise ValueError(f"count: expected an integer, got {nums[2]!r}") from None
            if not 1 <= count <= MAX_AXIS:
                raise ValueError(f"count must be from 1 to {MAX_AXIS}")
            if not (math.isfinite(start) and math.isfinite(stop)):
                raise ValueError("start and stop must be finite numbers")
            if kind == "log" and not (start > 0 and stop > 0):
                raise ValueError(
                    f"a log axis needs positive ends (start and stop > 0), got {start:g}"
                    f" and {stop:g}"
                )
            with np.errstate(all="raise"):  # e.g. stop - start beyond float64
                if kind == "log":
                    values = np.geomspace(start, stop, count)
                elif kind == "mid":
                    values = start + (stop - start) * (np.arange(count) + 0.5) / count
                else:
                    values = np.linspace(start, stop, count)
    except FloatingPointError as exc:
        raise argparse.ArgumentTypeError(
            f"axis {name}: the values overflow float64 ({exc}) (in {spec!r})"
        ) from None
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"axis {name}: {exc} (in {spec!r})") from None
    return name, values


def _azimuth_option(text: str) -> float | str:
    """Parses ``--phi``: degrees or ``average``."""
    if text.strip() == "average":
        return "average"
    try:
        degrees = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"phi: expected degrees or 'average'; got {text!r}"
        ) from None
    if not math.isfinite(degrees):
        raise argparse.ArgumentTypeError(f"phi: must be a finite number of degrees; got {text!r}")
    return degrees


#: ``brdf-rs table``'s incidence axis, and with no model named its tolerance (the model,
#: its other axes and its parameters are the spec's default table).
TABLE_MU_AXIS = "mu=mid:0:1:32"
DEFAULT_TABLE_TOL = 1e-4


def _default_table() -> tuple[str, list[str], list[str]]:
    """``brdf-rs table`` with no model: the model, its axes (``mu`` first) and parameters."""
    recipe = _spec.tool_defaults()["table"]
    return recipe["model"], [TABLE_MU_AXIS, *recipe["axes"]], list(recipe["params"])


def cmd_table(args: argparse.Namespace) -> int:
    from . import _albedo, _grid

    defaulted = args.model is None
    default_model, default_axes, default_params = _default_table()
    model = default_model if defaulted else args.model
    axes = _named(args.axis, "--axis") or dict(
        _axis(a) for a in default_axes[: None if defaulted else 1]
    )
    params = _named(args.param, "--param")
    if defaulted and not args.param:
        params = dict(_param(p) for p in default_params)
    if args.phi is not None:
        params["phi"] = args.phi if args.phi == "average" else np.radians(args.phi)
    if "phi" in axes:  # degrees on the command line, radians in the library
        axes["phi"] = np.radians(axes["phi"])
    tol = args.tol if args.tol is not None else (DEFAULT_TABLE_TOL if defaulted else None)
    # Everything is checked before any work (and before a progress bar is drawn).
    _grid.table_axes(model, axes, params)
    _options.check(
        {
            "samples": args.samples,
            "sampler": args.sampler,
            "sequence": args.sequence,
            "seed": args.seed,
            "tol": tol,
            "rtol": args.rtol,
            "max_samples": args.max_samples,
            "component": args.component,
        }
    )
    out = _table_output(args.output, f"albedo_{model}.npz", TABLE_FORMATS, args.plot)
    plot_path = _plot_path(args.plot)
    # Cells computed: a phi axis computes only its distinct folded azimuths.
    lengths = {k: len(v) for k, v in axes.items()}
    if "phi" in axes:
        lengths["phi"] = int(np.unique(_grid.azimuth_cells(model, axes["phi"])[1]).size)
    cells = int(np.prod(list(lengths.values())))
    bar = _progress_bar(cells, args.quiet)
    last = [0, 0]

    def progress(done: int, samples: int) -> None:
        if bar is not None:
            bar.update(done - last[0])
            bar.set_postfix_str(f"{(samples - last[1]) / 0.1 / 1e6:.0f} M samples/s")
        last[0], last[1] = done, samples

    start = time.perf_counter()
    try:
        table = _albedo.albedo_table(
            model,
            axes,
            samples=args.samples,
            sampler=args.sampler,
            sequence=args.sequence,
            seed=args.seed,
            tol=tol,
            rtol=args.rtol,
            max_samples=args.max_samples,
            progress=progress,
            component=args.component,
            **params,
        )
    finally:
        if bar is not None:
            bar.close()
    seconds = time.perf_counter() - start
    saved = _Saved(out, table.save)
    summary: dict[str, Any] = {
        "model": model,
        "axes": {k: [float(v[0]), float(v[-1]), len(v)] for k, v in table.axes.items()},
        "shape": list(table.value.shape),
        "params": params,
        "output": saved.output,
        "replaced": saved.replaced,
        "seconds": seconds,
        "samples": int(table.samples.sum()),
        "max_stderr": float(table.stderr.max()),
        "albedo_range": [float(table.value.min()), float(table.value.max())],
    }
    _draw(plot_path, summary, lambda plot, path: plot.table_heatmap(table, path=path))
    if args.json:
        _print_json(summary)
    else:
        shape = " x ".join(f"{k}[{len(v)}]" for k, v in table.axes.items())
        print(f"{model} albedo table {shape}: {saved.where}")
        print(
            f"  albedo in [{summary['albedo_range'][0]:.4g}, {summary['albedo_range'][1]:.4g}],"
            f" largest standard error {summary['max_stderr']:.2g},"
            f" {summary['samples']:,} samples in {seconds:.2f} s"
        )
        if plot_path is not None:
            print(f"  plot: {summary['plot']}")
    return 0


def _resolution(text: str) -> tuple[int, int]:
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected WIDTHxHEIGHT, e.g. 640x480, got {text!r}"
        ) from None
    from ._scene_schema import MAX_SIDE

    if not (1 <= w <= MAX_SIDE and 1 <= h <= MAX_SIDE):
        raise argparse.ArgumentTypeError(f"expected sizes from 1 to {MAX_SIDE}, got {text!r}")
    return w, h


def _example_names() -> list[str]:
    from .scene import example_scenes

    return list(example_scenes())


def cmd_render(args: argparse.Namespace) -> int:
    import time

    from . import scene as scenes

    scene = scenes.load_scene(args.scene)
    if args.resolution is not None:
        scene = scene.with_resolution(*args.resolution)
    flags = {"-o": args.output, "--exr": args.exr, "--npy": args.npy}
    outputs = [Path(p) for p in flags.values() if p is not None]
    if not outputs:
        raise UsageError("nothing to write: give -o image.png (or .exr, .npy), --exr or --npy")
    for flag, text in flags.items():
        if text is None:
            continue
        if Path(text).suffix.lower() not in (".png", ".exr", ".npy"):
            raise UsageError(f"{text}: unknown image format; use .png, .exr or .npy")
        _check_location(text, flag)
    start = time.perf_counter()
    linear, stats = scenes.render(scene, only=args.only, tonemap="none", exposure=0.0, stats=True)
    seconds = time.perf_counter() - start
    tonemap = args.tonemap or scene.output["tonemap"]
    exposure = scene.output["exposure"] if args.exposure is None else args.exposure
    display = scenes.tonemap(linear, tonemap, exposure)
    written = []
    for path in outputs:
        # PNG holds display values (tone-mapped, sRGB); EXR and NPY hold linear radiance.
        image = display if path.suffix.lower() == ".png" else linear
        written.append(str(scenes.save_image(path, image).resolve()))
    width, height = scene.resolution
    summary = {
        "scene": str(args.scene),
        "resolution": [width, height],
        "only": args.only,
        "tonemap": tonemap,
        "exposure": exposure,
        "seconds": seconds,
        "outputs": written,
        "stats": stats,
    }
    if args.json:
        _print_json(summary)
    elif not args.quiet:
        what = f" ({args.only} only)" if args.only else ""
        print(f"{args.scene}: {width}x{height}{what} in {seconds * 1e3:.1f} ms, tone map {tonemap}")
        print(
            f"  {stats['hits']:,} of {stats['pixels']:,} pixels hit; {stats['pairs']:,} pixel-light"
            f" pairs, {stats['pairs_backfacing']:,} facing away, {stats['pairs_out_of_range']:,}"
            f" out of range; {stats['evaluations']:,} kernel evaluations"
        )
        for name in written:
            print(f"  wrote {name}")
    return 0


def cmd_tables(args: argparse.Namespace) -> int:
    from . import scene as scenes

    scene = scenes.load_scene(args.scene)
    cache_dir = Path(args.cache_dir) if args.cache_dir else scenes.default_cache_dir()
    bar: Any = None
    current_material: str | None = None
    current_done = 0

    def progress(material: str, done: int, cells: int) -> None:
        nonlocal bar, current_material, current_done
        if current_material != material:
            if bar is not None:
                bar.close()
            bar = _progress_bar(cells, args.quiet or args.json)
            if bar is not None:
                bar.set_description(material)
            current_material, current_done = material, 0
        if bar is not None:
            bar.update(done - current_done)
        current_done = done

    try:
        results = scenes.scene_tables(
            scene,
            cache_dir=cache_dir,
            mu_count=args.mu_count,
            samples=args.samples,
            tol=args.tol,
            seed=args.seed,
            progress=progress,
        )
    finally:
        if bar is not None:
            bar.close()
    rows: list[dict[str, Any]] = [
        {
            "material": r.material,
            "model": r.model,
            "cached": r.cached,
            "path": str(r.path),
            "max_albedo": r.max_albedo,
            "mu_at_max": r.mu_at_max,
            "gains_energy": r.gains_energy,
            "seconds": r.seconds,
        }
        for r in results
    ]
    if args.json:
        _print_json({"scene": str(args.scene), "cache_dir": str(cache_dir), "tables": rows})
        return 0
    if not rows:
        print(f"{args.scene}: no family-A materials in use; no albedo tables needed")
        return 0
    built = sum(not r["cached"] for r in rows)
    print(f"{args.scene}: {len(rows)} albedo tables ({built} built, {len(rows) - built} cached)")
    print(f"  cache: {cache_dir.resolve()} (--cache-dir or $BRDF_RS_CACHE to move it)")
    for r in rows:
        status = "cached" if r["cached"] else f"built in {r['seconds']:.2f} s"
        albedo = ", ".join(f"{x:.4f}" for x in r["max_albedo"])
        verdict = "GAINS ENERGY" if r["gains_energy"] else "conserves energy"
        print(
            f"  {r['material']:18s} {r['model']:22s} max albedo [{albedo}]"
            f" at mu={r['mu_at_max']:.3f}"
            f"  {verdict}  ({status})"
        )
    return 0


# --------------------------------------------------------- dfg, energy, bench, plot-lobe

TABLE_FORMATS = (".npz", ".exr", ".png")
PLOT_FORMATS = (".png", ".svg", ".pdf")


def _output_path(text: str, formats: Sequence[str], what: str = "-o") -> Path:
    """Checks an output path before any work: known format, existing directory, not a
    directory itself (the file is written atomically when the work is done)."""
    path = Path(text)
    if path.suffix.lower() not in formats:
        raise UsageError(f"{what} {text}: unknown format; use {', '.join(formats)}")
    _check_location(text, what)
    return path


def _wrote(path: Path, existed: bool) -> str:
    """``wrote PATH``, saying so when an existing file was replaced."""
    return f"wrote {path.resolve()}" + (" (replaced the existing file)" if existed else "")


class _Saved:
    """A command's result written to ``out`` (when there is one): ``output`` the file
    written (absolute; None without ``out``), ``replaced`` whether it replaced a file,
    ``where`` the words saying so."""

    def __init__(self, out: Path | None, save: Callable[[Path], Path]) -> None:
        self.replaced = out is not None and out.exists()
        path = None if out is None else save(out)
        self.output = None if path is None else str(path.resolve())
        self.where = "not saved (no -o)" if path is None else _wrote(path, self.replaced)


def _draw(
    plot_path: Path | None, summary: dict[str, Any], draw: Callable[[Any, Path], Any]
) -> None:
    """Draws the result with ``draw(brdf_rs.plot, plot_path)`` when ``--plot`` asked for
    it, and records the figure's path in ``summary``."""
    if plot_path is None:
        return
    from . import plot

    draw(plot, plot_path)
    summary["plot"] = str(plot_path.resolve())


def _table_output(
    text: str | None, default: str, formats: Sequence[str], plot: str | None
) -> Path | None:
    """The table file to write: ``-o``, else ``default`` unless only ``--plot`` was asked
    for (then no table file: the plot is what was requested). Checked before any work."""
    if text is None and plot is not None:
        return None
    return _output_path(text or default, formats)


def _check_location(text: str, what: str) -> None:
    """An output's folder exists (else a usage error) and the name is not taken by a
    directory (else the ``IsADirectoryError`` the write would raise, before the work)."""
    path = Path(text)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise UsageError(f"{what} {text}: directory {parent} does not exist")
    if path.is_dir():  # the error writing would give (exit 1), before the work
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), text)


def _plot_path(text: str | None) -> Path | None:
    """Checks ``--plot`` (and that matplotlib is there) before any work is done."""
    if text is None:
        return None
    path = _output_path(text, PLOT_FORMATS, "--plot")
    from . import _optional

    _optional.matplotlib()
    return path


def _values(text: str) -> np.ndarray:
    """An axis without a name: ``start:stop:count``, ``mid:...``, ``log:...`` or ``v1,v2``."""
    try:
        return _axis(f"values={text}")[1]
    except argparse.ArgumentTypeError as exc:
        raise argparse.ArgumentTypeError(str(exc).replace("axis values: ", "")) from None


def _fit_degrees(text: str) -> tuple[int, int]:
    """``--fit N`` or ``N/M``: the numerator's and the denominator's total degrees."""
    parts = text.split("/")
    try:
        if len(parts) > 2:
            raise ValueError
        values = [int(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected N or N/M (integers), got {text!r}") from None
    return values[0], values[1] if len(values) == 2 else 0


class _PassProgress:
    """One progress bar over consecutive albedo runs (``sizes`` cells each) that report
    ``progress(cells_done, samples_done)`` from 0 again at the start of every run. A run
    may go on past its size (an energy table's ``E_avg`` rounds, which carry their counts
    on from round to round): the bar then runs past its total."""

    def __init__(self, sizes: Sequence[int], quiet: bool) -> None:
        self.sizes = list(sizes)
        self.bar = _progress_bar(sum(self.sizes), quiet)
        self.run = 0
        self.offset = 0
        self.last = 0

    def __call__(self, done: int, samples: int) -> None:
        more = self.run + 1 < len(self.sizes)
        # A run that reported its end, then a count the next run could report.
        finished_run = (
            more
            and self.last == self.sizes[self.run]
            and self.last != done <= self.sizes[self.run + 1]
        )
        if (done < self.last or finished_run) and more:
            self.offset += self.sizes[self.run]
            self.run += 1
        self.last = done
        if self.bar is not None:
            self.bar.update(max(0, self.offset + done - self.bar.n))

    def close(self, completed: bool) -> None:
        if self.bar is not None:
            if completed:
                self.bar.update(self.bar.total - self.bar.n)
            self.bar.close()


def cmd_dfg(args: argparse.Namespace) -> int:
    from . import _albedo

    model = args.model
    dfg = _spec.with_dfg()
    if model not in dfg:
        raise UsageError(f"unknown model {model!r}; a split-sum table takes {', '.join(dfg)}")
    mu = args.mu
    roughness = _values(dfg[model]["axis"]) if args.roughness is None else args.roughness
    out = _table_output(args.output, f"dfg_{model}.npz", TABLE_FORMATS, args.plot)
    plot_path = _plot_path(args.plot)
    cells = mu.size * roughness.size
    passes = 2 if args.sheen is None else 3
    progress = _PassProgress([cells] * passes, args.quiet or args.json)
    options: dict[str, Any] = {
        k: v for k, v in (("tol", args.tol), ("rtol", args.rtol)) if v is not None
    }
    if args.sheen is not None:
        options["sheen"] = args.sheen
    start = time.perf_counter()
    completed = False
    try:
        table = _albedo.dfg_table(
            model, mu, roughness, samples=args.samples, seed=args.seed, progress=progress, **options
        )
        completed = True
    finally:
        progress.close(completed)
    seconds = time.perf_counter() - start
    saved = _Saved(out, table.save)
    rough = list(table.axes)[1]
    summary: dict[str, Any] = {
        "model": model,
        "axes": {k: [float(v[0]), float(v[-1]), len(v)] for k, v in table.axes.items()},
        "shape": [mu.size, roughness.size],
        "channels": ["scale A", "bias B", "zero" if args.sheen is None else "cloth"],
        "output": saved.output,
        "replaced": saved.replaced,
        "seconds": seconds,
        "samples": int(table.samples.sum()),
        "max_stderr": float(table.stderr[..., :2].max()),
        "scale_range": [float(table.value[..., 0].min()), float(table.value[..., 0].max())],
        "bias_range": [float(table.value[..., 1].min()), float(table.value[..., 1].max())],
    }
    if args.sheen is not None:
        summary["sheen"] = args.sheen
        summary["max_stderr"] = float(table.stderr.max())
        summary["cloth_range"] = [
            float(table.value[..., 2].min()),
            float(table.value[..., 2].max()),
        ]
    _draw(plot_path, summary, lambda plot, path: plot.table_heatmap(table, path=path))
    if args.json:
        _print_json(summary)
        return 0
    print(f"{model} split-sum table mu[{mu.size}] x {rough}[{roughness.size}]: {saved.where}")
    print(
        f"  scale A in [{summary['scale_range'][0]:.4g}, {summary['scale_range'][1]:.4g}],"
        f" bias B in [{summary['bias_range'][0]:.4g}, {summary['bias_range'][1]:.4g}],"
        + (
            ""
            if args.sheen is None
            else f" cloth ({args.sheen}) in [{summary['cloth_range'][0]:.4g},"
            f" {summary['cloth_range'][1]:.4g}],"
        )
        + f" largest standard error {summary['max_stderr']:.2g}, {seconds:.2f} s"
    )
    if plot_path is not None:
        print(f"  plot: {summary['plot']}")
    return 0


def save_energy(result: Any, path: Path) -> Path:
    """Writes an :class:`~brdf_rs.EnergyCompensation` as ``.npz`` (arrays and metadata)."""
    from . import _atomic

    quantity = (
        "energy table: e[mu, alpha] = E(mu, alpha), the lobe's albedo seen from"
        " the view (over the light) at kd = 0, ks = 1 (F = 1), e_avg[alpha] = 2 * integral of"
        " E(mu) mu dmu"
    )
    axes: dict[str, np.ndarray] = {}
    if result.eta is not None:
        quantity = (
            "energy table: e[mu, alpha, eta] = E(mu, alpha, eta), the total albedo (reflection"
            " + transmission) of the white interface (ks = kt = 1) for light from above at"
            " n.wi = mu (eta < 1: from the denser side), e_avg[alpha, eta] = 2 * integral of"
            " E(mu) mu dmu"
        )
        axes["eta"] = result.eta
    meta = {
        "model": result.model,
        "quantity": quantity,
        "estimator": result.estimator,
        "brdf_rs": __version__,
    }
    _atomic.save_npz(
        path,
        mu=result.mu,
        alpha=result.alpha,
        **axes,
        e=result.e,
        stderr=result.stderr,
        e_avg=result.e_avg,
        e_avg_stderr=result.e_avg_stderr,
        meta=np.array(json.dumps(meta)),
    )
    return path


def cmd_energy(args: argparse.Namespace) -> int:
    from . import _albedo

    transmitting = _spec.transmitting()
    if args.model not in _spec.with_energy_table() + transmitting:
        known = ", ".join(_spec.with_energy_table())
        raise UsageError(
            f"unknown model {args.model!r}; energy compensation takes {known}, and with"
            f" --eta {', '.join(transmitting)}"
        )
    mu, alpha, eta = args.mu, args.alpha, args.eta
    if args.model in transmitting and eta is None:
        raise UsageError(f"--eta: {args.model}'s table is E(mu, alpha, eta); give the eta axis")
    if args.model not in transmitting and eta is not None:
        raise UsageError(f"--eta: only {', '.join(transmitting)} have an eta axis")
    if eta is not None and args.plot is not None:
        raise UsageError("--plot: the plot draws E(mu, alpha) tables, not ones over eta")
    out = _table_output(args.output, f"energy_{args.model}.npz", (".npz",), args.plot)
    plot_path = _plot_path(args.plot)
    n_eta = 1 if eta is None else eta.size
    # Two runs: the E grid, then E_avg's adaptive rule (30 cells per column in its first
    # round, more where it halves panels: the bar runs on past its total then).
    progress = _PassProgress(
        [mu.size * alpha.size * n_eta, 30 * alpha.size * n_eta], args.quiet or args.json
    )
    extra: dict[str, Any] = {} if eta is None else {"eta": eta}
    if args.rtol is not None:
        extra["rtol"] = args.rtol
    start = time.perf_counter()
    completed = False
    try:
        result = _albedo.energy_compensation_table(
            args.model,
            mu,
            alpha,
            samples=args.samples,
            tol=args.tol,
            seed=args.seed,
            progress=progress,
            **extra,
        )
        completed = True
    finally:
        progress.close(completed)
    seconds = time.perf_counter() - start
    saved = _Saved(out, lambda path: save_energy(result, path))
    axes = {
        "mu": [float(mu[0]), float(mu[-1]), mu.size],
        "alpha": [float(alpha[0]), float(alpha[-1]), alpha.size],
    }
    if eta is not None:
        axes["eta"] = [float(eta[0]), float(eta[-1]), eta.size]
    summary: dict[str, Any] = {
        "model": args.model,
        "axes": axes,
        "shape": list(result.e.shape),
        "output": saved.output,
        "replaced": saved.replaced,
        "seconds": seconds,
        "max_stderr": float(result.stderr.max()),
        "e_range": [float(result.e.min()), float(result.e.max())],
        "alpha": alpha,
        "e_avg": result.e_avg,
        "e_avg_stderr": result.e_avg_stderr,
    }
    _draw(plot_path, summary, lambda plot, path: plot.energy_compensation(result, path=path))
    if args.json:
        _print_json(summary)
        return 0
    grid = f"mu[{mu.size}], alpha[{alpha.size}]" + ("" if eta is None else f", eta[{eta.size}]")
    print(f"{args.model} energy compensation E({grid}) and E_avg: {saved.where}, {seconds:.2f} s")
    print(
        f"  E in [{summary['e_range'][0]:.4g}, {summary['e_range'][1]:.4g}],"
        f" largest standard error {summary['max_stderr']:.2g}"
    )
    step = max(1, alpha.size // 8)
    rows = [*range(0, alpha.size, step)][:8] + ([alpha.size - 1] if alpha.size > 1 else [])
    if eta is None:
        print("  alpha      E_avg      1 - E_avg (lost by single scattering)")
        for j in rows:
            print(f"  {alpha[j]:<9.4g}  {result.e_avg[j]:.5f}    {1 - result.e_avg[j]:.5f}")
    else:
        columns = sorted({*range(0, eta.size, max(1, eta.size // 6))} | {eta.size - 1})
        print("  E_avg (total albedo, cosine-weighted): alpha down, eta across")
        print("  alpha    " + "".join(f"{eta[k]:>10.4g}" for k in columns))
        for j in rows:
            print(f"  {alpha[j]:<9.4g}" + "".join(f"{result.e_avg[j, k]:>10.5f}" for k in columns))
    if plot_path is not None:
        print(f"  plot: {summary['plot']}")
    return 0


def _lut_spec(args: argparse.Namespace) -> Any:
    """The ``lut`` command's :class:`~brdf_rs.lut.LutSpec`: a preset with the options
    given replacing its fields, or an explicit description (checked before any work)."""
    import dataclasses

    from . import lut

    changes: dict[str, Any] = {}
    for key in ("kind", "model", "format", "samples", "seed", "name", "sheen"):
        if getattr(args, key) is not None:
            changes[key] = getattr(args, key)
    for key in ("columns", "rows", "layers"):
        if getattr(args, key) is not None:
            changes[key] = lut.parse_axis(getattr(args, key), f"--{key}")
    if args.channels is not None:
        changes["channels"] = tuple(c.strip() for c in args.channels.split(",") if c.strip())
    elif "kind" in changes or "format" in changes:
        changes["channels"] = None
    if args.preset is not None:
        if args.preset not in lut.PRESETS:
            raise UsageError(f"--preset: unknown {args.preset!r}; use {', '.join(lut.PRESETS)}")
        return dataclasses.replace(lut.PRESETS[args.preset].spec, **changes)
    missing = [f"--{k}" for k in ("kind", "model", "columns", "rows") if k not in changes]
    if missing:
        raise UsageError(
            f"give --preset ({', '.join(lut.PRESETS)}) or describe the table: missing"
            f" {', '.join(missing)}"
        )
    if "model" not in changes:
        raise UsageError("--model: give the model (brdf-rs models lists them) or a --preset")
    return lut.LutSpec(**changes)


def cmd_lut(args: argparse.Namespace) -> int:
    from . import _lutfiles, lut

    if args.list:
        rows = {
            name: {
                "summary": p.summary,
                "source": p.source,
                "command": p.spec.command(f"{name}{p.container}"),
            }
            for name, p in lut.PRESETS.items()
        }
        if args.json:
            _print_json(rows)
        else:
            for name, row in rows.items():
                print(f"{name}: {row['summary']}\n  source: {row['source']}")
        return 0
    if args.verify is not None:
        path = Path(args.verify)
        if not path.is_file():
            raise UsageError(f"--verify {args.verify}: no such file")
        result = lut.verify(path)
        checked: dict[str, Any] = {
            "file": str(path.resolve()),
            "ok": result.ok,
            "hash_ok": result.hash_ok,
            "max_difference": result.max_difference,
            "tolerance": result.tolerance,
            "versions": list(result.versions),
        }
        if args.json:
            _print_json(checked)
        else:
            verdict = "matches" if result.ok and result.hash_ok else "DOES NOT match"
            print(f"{path}: {verdict} its rebuilt table")
            print(f"  largest difference {result.max_difference}, tolerance {result.tolerance}")
            if result.versions[0] != result.versions[1]:
                print(
                    f"  written by brdf-rs {result.versions[0]}, rebuilt by"
                    f" {result.versions[1]}: compared within the statistical tolerance"
                )
            if not result.hash_ok:
                print(
                    "  the recorded content hash is not the recorded recipe's, or the recipe"
                    " is not the rebuild's"
                )
        return 0 if result.ok and result.hash_ok else EXIT_FAILURE
    spec = _lut_spec(args)
    default = "lut.ktx2"
    if args.preset is not None:
        default = f"{args.preset}{lut.PRESETS[args.preset].container}"
    out = Path(args.output or default)
    try:
        count = math.prod(spec.shape) * len(spec.channel_names)
        _lutfiles.check(spec.format, out, None if args.fit is not None else count)
    except ValueError as exc:
        raise UsageError(str(exc).replace("path:", f"-o {out}:", 1)) from None
    for option, given in (("--fit", args.fit), ("--max-error", args.max_error)):
        if given is not None and spec.layers is not None:
            raise UsageError(
                f"{option}: takes 2-D tables; this one has a layers axis"
                f" ({spec.layers.quantity}): build it at a chosen size"
            )
    if args.fit is not None:
        if out.suffix.lower() not in (".h", ".glsl", ".hlsl", ".wgsl"):
            raise UsageError(f"-o {out}: a --fit is source code: .h, .glsl, .hlsl or .wgsl")
        degree, denominator = args.fit
        if not (1 <= degree <= 12 and 0 <= denominator <= 12):
            raise UsageError(
                f"--fit: expected N from 1 to 12 and M from 0 to 12, got {degree}/{denominator}"
            )
        if args.max_error is not None:
            raise UsageError("--fit and --max-error: give one or the other")
    _check_location(str(out), "-o")
    if args.interp_limit < 2:
        raise UsageError(f"--interp-limit: expected at least 2, got {args.interp_limit}")
    if args.max_error is not None and not (math.isfinite(args.max_error) and args.max_error > 0):
        raise UsageError(f"--max-error: expected a positive number, got {args.max_error}")
    start = time.perf_counter()
    if args.max_error is not None:
        choice = lut.meet_error(spec, args.max_error, interp_limit=args.interp_limit)
        if choice.lut is None:
            best = min(choice.tried, key=lambda t: t[2])
            print(
                f"brdf-rs lut: no resolution up to {choice.tried[-1][0]} and format meets"
                f" --max-error {args.max_error:g}: the best is {best[2]:.3g} ({best[0]} x"
                f" {best[0]} {best[1]}); raise --samples, change the axes (e.g. sqrt_mu,"
                " ends) or accept a larger error",
                file=sys.stderr,
            )
            return EXIT_FAILURE
        table = choice.lut
        spec = table.spec
    else:
        progress = _PassProgress(lut.passes(spec, args.interp_limit), args.quiet or args.json)
        completed = False
        try:
            table = lut.build(spec, interp_limit=args.interp_limit, progress=progress)
            completed = True
        finally:
            progress.close(completed)
    seconds = time.perf_counter() - start
    if args.fit is not None:
        fitted = lut.fit(table, *args.fit)
        saved = _Saved(out, fitted.save)
        fit_summary = {
            "output": saved.output,
            "degree": fitted.degree,
            "denominator": fitted.denominator,
            "terms": fitted.terms,
            "table_content_hash": table.content_hash,
            "worst_texels": fitted.worst_texels,
            "rms_texels": fitted.rms_texels,
            "worst_between": fitted.worst_between,
            "between_stderr": fitted.between_stderr,
            "worst_dense": fitted.worst_dense,
            "dense_stderr": fitted.dense_stderr,
            "dense_points": fitted.dense_points,
            "float32_worst": fitted.float32_worst,
            "max_error": fitted.max_error,
            "seconds": time.perf_counter() - start,
        }
        if args.json:
            _print_json(fit_summary)
        else:
            print(f"{fitted.form} fit of the {spec.kind} table of {spec.model}: {saved.where}")
            for k, c in enumerate(spec.channel_names):
                print(
                    f"  {c}: maximum error {fitted.max_error[k]:.2g} (worst"
                    f" {fitted.worst_dense[k]:.2g} against {fitted.dense_points} integrals on"
                    f" a dense grid, {fitted.worst_texels[k]:.2g} against the texels)"
                )
        return 0
    saved = _Saved(out, table.save)
    summary: dict[str, Any] = {
        "output": saved.output,
        "replaced": saved.replaced,
        "seconds": seconds,
        "content_hash": table.content_hash,
        "command": spec.command(out.name),
        "width": spec.columns.size,
        "height": spec.rows.size,
        **({"depth": spec.layers.size} if spec.layers is not None else {}),
        "format": spec.format,
        "channels": list(spec.channel_names),
        "budget": table.budget.to_json(),
    }
    if args.json:
        _print_json(summary)
        return 0
    b = table.budget
    size = " x ".join(str(n) for n in spec.shape[::-1])
    print(f"{spec.kind} LUT of {spec.model}, {size} {spec.format}: {saved.where}, {seconds:.2f} s")
    print("  channel  MC stderr  quant worst  quant RMS  interp worst  total (3 sigma per point)")
    for k, c in enumerate(b.channels):
        print(
            f"  {c:<7}  {b.mc_max_stderr[k]:<9.2g}  {b.quant_worst[k]:<11.2g}"
            f"  {b.quant_rms[k]:<9.2g}  {b.interp_worst[k]:<12.2g}  {b.total[k]:.2g}"
        )
    print(f"  hash {table.content_hash}")
    return 0


def cmd_bench(args: argparse.Namespace) -> int:
    from . import _bench

    if args.threads is not None:
        _api.set_num_threads(args.threads)
    result = _bench.run(
        args.models or None,
        n=args.n,
        repeat=args.repeat,
        table_size=args.table_size,
        tol=args.tol,
    )
    passed = bool(result["albedo_table"]["check_passed"])
    if args.json:
        _print_json(result)
        return 0 if passed else EXIT_FAILURE
    m = result["machine"]
    print(
        f"brdf-rs {m['brdf_rs']} on {m['cpu']} ({m['cpus']} CPUs), {m['threads']} threads,"
        f" {m['isa']} kernels"
    )
    print(f"\neval: {args.n:,} direction pairs, best of {args.repeat}, written with out=")
    print(f"  {'model':22s} {'float64':>14s} {'float32':>14s}")
    rows: dict[str, dict[str, float]] = {}
    for row in result["eval"]:
        rows.setdefault(row["model"], {})[row["dtype"]] = row["mevals_per_s"]
    for model, speeds in rows.items():
        cells = [f"{speeds[d]:9.1f} M/s" for d in ("float64", "float32")]
        print(f"  {model:22s} {cells[0]:>14s} {cells[1]:>14s}")
    t = result["albedo_table"]
    print(
        f"\nalbedo table: {t['model']} {t['shape'][0]}x{t['shape'][1]} (mu x p), kd=0, ks=1,"
        f" tol {t['tol']:g}"
    )
    print(
        f"  {t['seconds']:.3f} s, {t['samples']:,} samples ({t['msamples_per_s']:.1f} M/s),"
        f" largest standard error {t['max_stderr']:.2g}"
    )
    verdict = "passed" if passed else "FAILED"
    print(
        f"  check: exact albedo 1 at mu = 1; largest |R - 1| = {t['max_error_at_mu_1']:.2g}"
        f" ({t['max_error_in_stderr_at_mu_1']:.1f} standard errors):"
        f" {verdict} (limit {t['check_limit_in_stderr']:g} standard errors)"
    )
    return 0 if passed else EXIT_FAILURE


def cmd_plot_lobe(args: argparse.Namespace) -> int:
    from . import _optional, plot

    path = _output_path(args.output, PLOT_FORMATS)
    _optional.matplotlib()
    theta = args.theta_i or [45.0]
    plot.polar_lobe(
        args.model,
        theta,
        cosine=args.cosine,
        tangent=args.tangent,
        path=path,
        **_named(args.param, "--param"),
    )
    summary = {"model": args.model, "theta_i": theta, "plot": str(path.resolve())}
    if args.json:
        _print_json(summary)
    else:
        angles = ", ".join(f"{t:g}" for t in theta)
        print(f"{args.model} lobe at theta_i = {angles} deg: wrote {summary['plot']}")
    return 0


def cmd_stress(args: argparse.Namespace) -> int:
    from . import _stress

    models = [m for group in args.models for m in group.split(",") if m] if args.models else None
    bar = _progress_bar_models(args.quiet or args.json)

    def progress(model: str, dtype: str, done: int, total: int) -> None:
        if bar is not None:
            bar.total = total
            bar.set_postfix_str(f"{model} ({dtype})")
            bar.update(1)

    try:
        report = _stress.stress(
            models,
            dtype=args.dtype,
            cases=args.cases,
            seed=args.seed,
            progress=progress,
            precision=args.precision,
        )
    finally:
        if bar is not None:
            bar.close()
    if args.json:
        _print_json(report.to_dict())
    else:
        print(report.table())
    return 0 if report.ok else EXIT_FAILURE


class _LazyBar:
    """A tqdm progress bar drawn only once the work reports progress: an error found
    before any work is done (a bad argument, a missing dependency) prints no bar."""

    def __init__(self, total: int, unit: str) -> None:
        self._options: dict[str, Any] = {"total": total, "unit": unit}
        self._bar: Any = None

    def _drawn(self) -> Any:
        if self._bar is None:
            from tqdm import tqdm

            self._bar = tqdm(file=sys.stderr, dynamic_ncols=True, **self._options)
        return self._bar

    @property
    def n(self) -> int:
        return 0 if self._bar is None else int(self._bar.n)

    @property
    def total(self) -> int:
        return int(self._options["total"] if self._bar is None else self._bar.total)

    @total.setter
    def total(self, value: int) -> None:
        if self._bar is None:
            self._options["total"] = value
        else:
            self._bar.total = value

    def set_description(self, text: str) -> None:
        if self._bar is None:
            self._options["desc"] = text
        else:
            self._bar.set_description(text)

    def set_postfix_str(self, text: str) -> None:
        self._drawn().set_postfix_str(text)

    def update(self, n: int) -> None:
        self._drawn().update(n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()


def _tqdm_available() -> bool:
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return False
    return True


def _progress_bar_models(quiet: bool) -> Any:
    if quiet or not _tqdm_available():
        return None
    return _LazyBar(0, "model")


def _progress_bar(total: int, quiet: bool) -> Any:
    if quiet or not _tqdm_available():
        return None
    return _LazyBar(total, "cell")


class _HelpFormatter(argparse.HelpFormatter):
    """Adds ``(default: X)`` to an option's help when it has a default worth stating
    (not None, False or an empty list) and the help does not state it already."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ""
        default = action.default
        if (
            action.option_strings
            and "default" not in text
            and not any(default is x for x in (None, False, argparse.SUPPRESS))
            and default != []
        ):
            text += " (default: %(default)s)"
        return text


class _Parser(argparse.ArgumentParser):
    """argparse, with usage errors as one line and a pointer to ``--help`` (argparse's
    own prints the whole usage block first); exit code 2 as before."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", _HelpFormatter)
        super().__init__(*args, **kwargs)

    def add_subparsers(self, **kwargs: Any) -> Any:
        sub = super().add_subparsers(**kwargs)
        add = sub.add_parser

        def add_parser(name: str, **options: Any) -> Any:
            # The one-line help doubles as the description `brdf-rs NAME --help` shows.
            options.setdefault("description", options.get("help"))
            return add(name, **options)

        sub.add_parser = add_parser  # type: ignore[method-assign]
        return sub

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_USAGE, f"{self.prog}: {message} (see {self.prog} --help)\n")


# ------------------------------------------------------------------------- the parser
#
# One builder: build_parser() registers each command with its own _add_* function; the
# options several commands share are defined once, by the helpers below (their help
# texts are the commands' too).

TOL_PER_CELL_HELP = "stop each cell at this standard error (default: none, --samples per cell)"
SCENE_HELP = "a scene file (TOML), or an example scene that ships with brdf-rs: "


def _add_model(p: Any, help: str = "a model name (brdf-rs models lists them)") -> None:
    p.add_argument("model", help=help)


def _add_params(p: Any, help: str = "name=value (repeat)") -> None:
    """``--param name=value``, repeated."""
    p.add_argument("--param", "-p", type=_param, action="append", default=[], help=help)


def _add_tangent(p: Any) -> None:
    p.add_argument("--tangent", type=_vector, default=None, help="tangent x,y,z")


def _add_incidences(p: Any) -> None:
    """``--mu``: the incidences of a split-sum or energy table."""
    p.add_argument(
        "--mu", type=_values, default="mid:0:1:32", help="incidences (default mid:0:1:32)"
    )


def _add_integrator(
    p: Any,
    *,
    samples: int,
    samples_help: str,
    tol: float | None = None,
    tol_help: str = TOL_PER_CELL_HELP,
    sampling: bool = False,
    relative: bool = False,
) -> None:
    """``--samples``, ``--tol``, (with ``relative``: ``--rtol``; with ``sampling``:
    ``--max-samples``, ``--sampler``, ``--sequence``) and ``--seed``: the integrator's
    options."""
    p.add_argument("--samples", type=int, default=samples, help=samples_help)
    p.add_argument("--tol", type=float, default=tol, help=tol_help)
    if relative:
        p.add_argument(
            "--rtol",
            type=float,
            default=None,
            help="stop each cell once its standard error is at most this times its value"
            " (with --tol: at most tol + rtol·|value|; default: none)",
        )
    if sampling:
        p.add_argument(
            "--max-samples",
            type=int,
            default=None,
            help="cap per cell with --tol (default: the larger of --samples and 2^24)",
        )
        p.add_argument(
            "--sampler",
            default="auto",
            choices=list(_options.SAMPLERS),
            help="how directions are drawn (auto: the model's importance sampling)",
        )
        p.add_argument(
            "--sequence",
            default="sobol",
            choices=list(_options.SEQUENCES),
            help="scrambled Sobol points or independent random numbers",
        )
    _add_seed(p)


def _add_seed(p: Any) -> None:
    p.add_argument("--seed", type=int, default=0, help=SEED_HELP)


def _add_table_files(p: Any, output_help: str, plot_help: str) -> None:
    """``-o`` (the table file) and ``--plot`` (a figure of it)."""
    p.add_argument("-o", "--output", default=None, help=output_help)
    p.add_argument("--plot", default=None, help=plot_help)


def _add_reporting(
    p: Any,
    *,
    quiet_help: str | None = "no progress bar",
    json_help: str = "machine-readable summary",
) -> None:
    """``--quiet`` (unless ``quiet_help`` is None) and ``--json``."""
    if quiet_help is not None:
        p.add_argument("--quiet", "-q", action="store_true", help=quiet_help)
    p.add_argument("--json", action="store_true", help=json_help)


def _add_scene(p: Any) -> None:
    p.add_argument("scene", help=SCENE_HELP + ", ".join(_example_names()))


def _add_models_command(sub: Any) -> None:
    p = sub.add_parser(
        "models",
        help="list the models (or the named ones): family, formula, source, parameters",
    )
    p.add_argument(
        "names",
        nargs="*",
        metavar="NAME",
        help="only these models (default: every model)",
    )
    _add_reporting(p, quiet_help=None, json_help="machine-readable output")
    p.set_defaults(run=cmd_models)


def _add_eval_command(sub: Any) -> None:
    p = sub.add_parser("eval", help="evaluate one model for one pair of directions")
    _add_model(p)
    p.add_argument("--wi", type=_vector, required=True, help="toward the light: x,y,z")
    p.add_argument("--wo", type=_vector, required=True, help="toward the viewer: x,y,z")
    p.add_argument("--n", type=_vector, default=None, help="surface normal (default 0,0,1)")
    _add_tangent(p)
    _add_params(p)
    _add_reporting(p, quiet_help=None, json_help="machine-readable output")
    p.set_defaults(run=cmd_eval)


def _add_table_command(sub: Any) -> None:
    model, default_axes, _ = _default_table()
    axes = [_axis(a) for a in default_axes]
    names = [name for name, _ in axes]
    shape = "x".join(str(len(values)) for _, values in axes)
    tol = np.format_float_scientific(DEFAULT_TABLE_TOL, trim="-", exp_digits=1)
    p = sub.add_parser(
        "table",
        help="build an albedo table (the main job)",
        description="Tabulate the directional albedo R(mu) over axes of mu and parameters. "
        f"With no arguments: a {shape} {model} table over {' and '.join(names)}, tol {tol};"
        f" with a model and no --axis: {len(axes[0][1])} incidences mu.",
    )
    p.add_argument(
        "model",
        nargs="?",
        default=None,
        help=f"a family-A model (default: the {shape} {model} table described above)",
    )
    p.add_argument(
        "--axis",
        type=_axis,
        action="append",
        default=[],
        help="name=start:stop:count | name=mid:start:stop:count | name=log:start:stop:count"
        " | name=v1,v2,... (repeat; mu, phi and parameters)",
    )
    p.add_argument(
        "--phi",
        type=_azimuth_option,
        default=None,
        help="the azimuth of wi in degrees from the tangent, counterclockwise about n "
        "(default 0), or 'average' for the azimuth average; only "
        f"{' and '.join(n for n, s in _spec.specs().items() if s['tangent_optional'])} "
        "depend on it (an axis: --axis phi=..., also in degrees; "
        "the saved table's phi axis is in radians, as brdf_rs.albedo_table takes it)",
    )
    _add_params(p, help="fixed name=value")
    p.add_argument(
        "--component",
        default="total",
        help="for a model that transmits: total, reflection (wo above the surface) or"
        " transmission (wo below), integrated over the whole sphere (default: total)",
    )
    _add_integrator(
        p,
        samples=4096,
        samples_help="samples per cell (first round with --tol)",
        tol_help="stop each cell at this standard error (default: 1e-4 for the default"
        " table, else none: --samples per cell)",
        sampling=True,
        relative=True,
    )
    _add_table_files(
        p, "table.npz | table.exr | table.png", "also draw the table (needs matplotlib): out.png"
    )
    _add_reporting(p)
    p.set_defaults(run=cmd_table)


def _add_render_command(sub: Any) -> None:
    p = sub.add_parser(
        "render",
        help="render a scene file (TOML) to PNG, EXR or NPY",
        description="Render a scene: PNG gets the tone-mapped, sRGB-encoded image; EXR and "
        "NPY get linear radiance (float32).",
    )
    _add_scene(p)
    p.add_argument("-o", "--output", default=None, help="image.png | image.exr | image.npy")
    p.add_argument("--exr", default=None, help="also write linear radiance as .exr")
    p.add_argument("--npy", default=None, help="also write linear radiance as .npy")
    p.add_argument(
        "--tonemap",
        default=None,
        choices=_images.TONEMAPS,
        help="override the scene's [output] tonemap",
    )
    p.add_argument("--exposure", type=float, default=None, help="stops (override the scene's)")
    p.add_argument(
        "--only",
        default=None,
        choices=["diffuse", "specular"],
        help="render one component without computing the other",
    )
    p.add_argument("--resolution", type=_resolution, default=None, help="WIDTHxHEIGHT override")
    _add_reporting(
        p, quiet_help="print nothing", json_help="machine-readable summary and statistics"
    )
    p.set_defaults(run=cmd_render)


def _add_tables_command(sub: Any) -> None:
    p = sub.add_parser(
        "tables",
        help="build (or find cached) the albedo tables a scene's materials need",
        description="For every family-A material a scene uses: its directional albedo "
        "R(mu), cached on disk under a hash of the model, parameters, sampler settings and "
        "library version; a second run skips every table already built.",
    )
    _add_scene(p)
    p.add_argument(
        "--cache-dir", default=None, help="default: $BRDF_RS_CACHE or ~/.cache/brdf-rs/tables"
    )
    p.add_argument("--mu-count", type=int, default=32, help="incidences (cell midpoints of [0, 1])")
    _add_integrator(p, samples=4096, samples_help="samples per cell (first round with --tol)")
    _add_reporting(p)
    p.set_defaults(run=cmd_tables)


def _add_dfg_command(sub: Any) -> None:
    by_param: dict[str, list[str]] = {}
    for name, axis in _spec.with_dfg().items():
        by_param.setdefault(axis["param"], []).append(name)
    roughness = ", ".join(f"{param} for {' and '.join(names)}" for param, names in by_param.items())
    p = sub.add_parser(
        "dfg",
        help="build a split-sum (DFG) table: scale A and bias B with R_spec = F0*A + B",
        description="Tabulate the split-sum terms of a Schlick-Fresnel model over mu and "
        f"roughness ({roughness}). Channel 0 of the "
        "table is the scale A, channel 1 the bias B, channel 2 the cloth term with --sheen"
        " (else 0).",
    )
    default = _spec.tool_defaults()["dfg"]
    p.add_argument(
        "model",
        nargs="?",
        default=default,
        help=f"{', '.join(_spec.with_dfg())} (default {default})",
    )
    _add_incidences(p)
    p.add_argument(
        "--roughness",
        type=_values,
        default=None,
        help="roughness axis spec (default mid:0:1:32 for alpha, log:1:10000:32 for p)",
    )
    # Bare --sheen: the lobe of Filament's cloth channel, as its engine preset says.
    from .lut import PRESETS

    filament_cloth = PRESETS["filament_cloth"].spec.sheen
    p.add_argument(
        "--sheen",
        nargs="?",
        const=filament_cloth,
        default=None,
        metavar="MODEL",
        help="fill channel 2 with a cloth term: the directional albedo of the sheen MODEL with"
        f" kd = 0, ks = 1 at alpha = the table's alpha (bare --sheen: {filament_cloth},"
        " Filament's cloth DG channel; pass --roughness as squared perceptual roughness to"
        " match its rows); alpha tables only",
    )
    _add_integrator(p, samples=1 << 14, samples_help="samples per cell", relative=True)
    _add_table_files(
        p,
        "dfg.npz | dfg.exr | dfg.png",
        "also draw A and B, and the cloth term with --sheen (needs matplotlib): out.png",
    )
    _add_reporting(p)
    p.set_defaults(run=cmd_dfg)


def _add_energy_command(sub: Any) -> None:
    p = sub.add_parser(
        "energy",
        help="build an energy compensation table: E(mu, alpha) and E_avg(alpha)",
        description="The single-scattering albedo E(mu, alpha) of a microfacet model with "
        "F = 1 and its cosine-weighted average E_avg(alpha); 1 - E_avg is the energy a "
        "multiple-scattering lobe (Kulla and Conty's; the _ms models) restores. For a sheen "
        "model, the albedo a layer takes out of the light (the base under it keeps 1 - E). "
        "E is the albedo seen from the view; where the model gives it in closed form (a lobe "
        "that is not reciprocal) nothing is sampled: E is exact and E_avg's error bar bounds "
        "a quadrature's error.",
    )
    _add_model(p, help=" or ".join(_spec.with_energy_table() + _spec.transmitting()))
    _add_incidences(p)
    p.add_argument(
        "--alpha", type=_values, default="mid:0:1:32", help="roughness (default mid:0:1:32)"
    )
    p.add_argument(
        "--eta",
        type=_values,
        default=None,
        help="relative index axis, required for the transmitting models (and only for them):"
        " E(mu, alpha, eta) is then the total albedo (reflection + transmission) of the white"
        " interface for light from above, eta < 1 from the denser side",
    )
    _add_integrator(
        p,
        samples=1 << 12,
        samples_help="samples per cell (first round)",
        tol=1e-5,
        tol_help="standard error per cell",
        relative=True,
    )
    _add_table_files(p, "energy.npz", "also draw E and E_avg (needs matplotlib): out.png")
    _add_reporting(p)
    p.set_defaults(run=cmd_energy)


def _add_lut_command(sub: Any) -> None:
    from . import lut

    p = sub.add_parser(
        "lut",
        help="bake an engine-ready LUT (split-sum DFG, Kulla-Conty E and E_avg) with its"
        " error budget",
        description="Bake a lookup table in an engine's layout, by preset or by explicit"
        " description, into EXR, KTX2, DDS, 16-bit PNG or C/GLSL/HLSL/WGSL source (by the"
        " suffix of -o). Every file records its recipe, content hash, rebuild command and"
        " error budget; --verify FILE rebuilds it and compares.",
    )
    p.add_argument("--preset", default=None, help=f"one of {', '.join(lut.PRESETS)}")
    p.add_argument("--kind", default=None, help=f"what the table holds: {', '.join(lut.KINDS)}")
    p.add_argument("--model", default=None, help="the model (default: the preset's)")
    axis_help = (
        "QUANTITY:PLACEMENT:SIZE[:LO:HI[:FLOOR[:CEILING]]], QUANTITY one of "
        + ", ".join(lut.QUANTITIES)
        + "; PLACEMENT centres or ends"
    )
    p.add_argument("--columns", default=None, help="the texture's x axis: " + axis_help)
    p.add_argument("--rows", default=None, help="the texture's y axis (row 0 first): " + axis_help)
    p.add_argument(
        "--layers",
        default=None,
        help="a 3-D table's depth axis (slice 0 first), the index of refraction of a"
        " transmitting model's energy table (eta, eta_z or eta_z_inside): " + axis_help,
    )
    p.add_argument("--format", default=None, help=f"pixel format: {', '.join(lut.FORMATS)}")
    p.add_argument("--channels", default=None, help="channels kept, comma-separated (e.g. E)")
    p.add_argument(
        "--sheen",
        default=None,
        metavar="MODEL",
        help="the sheen model of a DFG table's cloth channel (e.g. the filament_cloth preset's)",
    )
    p.add_argument("--samples", type=int, default=None, help="samples per texel")
    p.add_argument("--seed", type=int, default=None, help=SEED_HELP)
    p.add_argument("--name", default=None, help="identifier in source code outputs")
    p.add_argument(
        "--interp-limit",
        type=int,
        default=64,
        help="points per axis checked between texels for the interpolation error",
    )
    p.add_argument(
        "--max-error",
        type=float,
        default=None,
        help="pick the smallest square resolution and format whose error budget total is at"
        " most this (exit 1 when none up to 512 is)",
    )
    p.add_argument(
        "--fit",
        type=_fit_degrees,
        default=None,
        metavar="N[/M]",
        help="write a minimax fit as source code instead of the table: a polynomial of total"
        " degree N, or N/M a rational function of total degrees N over M",
    )
    p.add_argument("-o", "--output", default=None, help="out.exr | .ktx2 | .dds | .png | .h | ...")
    p.add_argument("--verify", default=None, metavar="FILE", help="rebuild FILE and compare")
    p.add_argument("--list", action="store_true", help="list the presets and their sources")
    _add_reporting(p)
    p.set_defaults(run=cmd_lut)


def _add_bench_command(sub: Any) -> None:
    p = sub.add_parser(
        "bench",
        help="a short benchmark: eval throughput and an albedo table, on this machine",
        description="Measures million evaluations per second of a few models (float64 and "
        f"float32) and builds a small {_spec.tool_defaults()['albedo_check']['model']} albedo"
        " table to a tolerance, checking "
        "it against its exact value at mu = 1. A few seconds; benches/ in the repository has "
        "the full benchmarks.",
    )
    p.add_argument("--models", nargs="+", default=None, help="models to time (default: 5 kinds)")
    p.add_argument("--n", type=int, default=1_000_000, help="direction pairs per call")
    p.add_argument("--repeat", type=int, default=3, help="timed calls (the best is kept)")
    p.add_argument("--table-size", type=int, default=16, help="the albedo table is SIZE x SIZE")
    p.add_argument("--tol", type=float, default=1e-4, help="the albedo table's standard error")
    p.add_argument("--threads", type=int, default=None, help="worker threads (default: all)")
    _add_reporting(p, quiet_help=None, json_help="machine-readable results")
    p.set_defaults(run=cmd_bench)


def _add_plot_lobe_command(sub: Any) -> None:
    p = sub.add_parser(
        "plot-lobe",
        help="polar plot of a model's lobe in the plane of incidence (needs matplotlib)",
        description="Draws f(wi, wo) for wo in the plane of incidence, light arriving from "
        "the left at each --theta-i (degrees), like Disney's BRDF Explorer.",
    )
    _add_model(p)
    p.add_argument(
        "--theta-i", type=float, action="append", default=[], help="degrees (repeat; default 45)"
    )
    _add_params(p)
    _add_tangent(p)
    p.add_argument("--cosine", action="store_true", help="multiply by cos(theta_o)")
    p.add_argument("-o", "--output", required=True, help="lobe.png | .svg | .pdf")
    _add_reporting(p, quiet_help=None)
    p.set_defaults(run=cmd_plot_lobe)


def _add_stress_command(sub: Any) -> None:
    p = sub.add_parser(
        "stress",
        help="numerical stress test: every model against a 50-digit reference",
        description="Run the models over an adversarial input set (grazing angles down to "
        "5e-324, wi = -wo, huge and tiny vectors, exponents up to 1e8, ...) and compare "
        "with an mpmath evaluation from the exact inputs: NaN and infinity counts, errors "
        "in ulps and relative, split by condition number. Exit code 0 when every goal is "
        "met, 1 when not. Needs mpmath (pip install 'brdf-rs[stress]').",
    )
    p.add_argument(
        "--models",
        nargs="+",
        default=None,
        metavar="MODEL",
        help="models to run (space or comma separated; default: all)",
    )
    p.add_argument(
        "--dtype",
        default="float64",
        choices=["float64", "float32", "both"],
        help="the kernels' float width",
    )
    p.add_argument(
        "--cases",
        default="quick",
        choices=["quick", "all"],
        help="quick: ~10 cases per model (seconds); all: ~400 (minutes)",
    )
    p.add_argument(
        "--precision",
        default="accurate",
        choices=list(_api.PRECISIONS),
        help="the tier of brdf_rs.eval to run, whose goals are checked (fast: relative "
        "error at most 1e-12 in float64, 2e-6 in float32, on well-conditioned cases)",
    )
    _add_seed(p)
    _add_reporting(p, json_help="the whole report as JSON")
    p.set_defaults(run=cmd_stress)


def build_parser() -> argparse.ArgumentParser:
    """The ``brdf-rs`` parser: every command, in the order ``--help`` lists them."""
    parser = _Parser(
        prog="brdf-rs",
        description="Evaluate, integrate and tabulate reflectance models (BRDFs).",
        epilog="brdf-rs COMMAND --help describes a command. Exit codes: 0 success, 1 failure,"
        " 2 usage error, 130 interrupted.",
    )
    parser.add_argument("--version", action="version", version=f"brdf-rs {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for add in (
        _add_models_command,
        _add_eval_command,
        _add_table_command,
        _add_render_command,
        _add_tables_command,
        _add_dfg_command,
        _add_energy_command,
        _add_lut_command,
        _add_bench_command,
        _add_plot_lobe_command,
        _add_stress_command,
    ):
        add(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    with warnings.catch_warnings():
        # A NumPy warning (an overflow, an invalid value) means a number the checks let
        # through: it becomes the command's one-line error, never a warning and a result.
        warnings.simplefilter("error", RuntimeWarning)
        args = parser.parse_args(argv)
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    try:
        return int(args.run(args))
    except RuntimeWarning as exc:
        print(f"brdf-rs {args.command}: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except UsageError as exc:
        print(f"brdf-rs {args.command}: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (TypeError, ValueError) as exc:
        print(f"brdf-rs {args.command}: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # `brdf-rs models | head`: the reader left; say nothing
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_FAILURE
    except (OSError, ImportError, RuntimeError, MemoryError) as exc:
        print(f"brdf-rs {args.command}: {exc}", file=sys.stderr)
        return EXIT_FAILURE
    except KeyboardInterrupt:
        print(f"brdf-rs {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
