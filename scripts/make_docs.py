"""Generates docs/: one page per model, the conventions, an index and the benchmark page.

    python scripts/make_docs.py                                  # docs/ (committed)
    python scripts/make_docs.py --resolution small --out DIR     # quick check (the tests)

Every page comes from ``brdf_rs.models()`` (formula, source, parameters with kinds,
defaults and ranges) and every image from the library: a sphere rendered by
``brdf_rs.plot.render_sphere``, the lobe in the plane of incidence by
``brdf_rs.plot.polar_lobe`` and the directional albedo (family A) by
``brdf_rs.plot.albedo_curves``, computed when the script runs. Nothing here is written per
model except which parameters make a telling picture (``SHOWCASE``) and which parameter
the albedo curves vary (``CURVES``); a model added to the library gets a page from its
spec and defaults. The Markdown does not depend on the resolution, so the tests can
check the committed pages against a quick regeneration.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import brdf_rs
import numpy as np
from brdf_rs import plot

ROOT = Path(__file__).resolve().parents[1]

#: Image sizes and sample counts: "full" for the committed docs, "small" for tests.
RESOLUTIONS = {
    "full": {"sphere": 160, "dpi": 100, "overview": 96, "mu": 48, "samples": 4096, "paths": 256},
    "small": {"sphere": 24, "dpi": 24, "overview": 16, "mu": 6, "samples": 256, "paths": 4},
}

#: Scatterings a path through a transmitting model's sphere may take.
GLASS_BOUNCES = 12

#: Parameters beyond the defaults that make a telling sphere and lobe (a tinted diffuse
#: term under a specular lobe, the assignment's toon colours). Models not listed use
#: their defaults.
SHOWCASE: dict[str, dict[str, Any]] = {
    "phong": {"kd": [0.1, 0.04, 0.02], "ks": 0.5},
    "modified_phong": {"kd": [0.1, 0.04, 0.02], "ks": 0.5},
    "blinn_phong": {"kd": [0.1, 0.04, 0.02], "ks": 0.5},
    "modified_blinn_phong": {"kd": [0.1, 0.04, 0.02], "ks": 0.5},
    "normalized_phong": {"kd": [0.6, 0.25, 0.1], "ks": 0.3},
    "normalized_blinn_phong": {"kd": [0.6, 0.25, 0.1], "ks": 0.3},
    "blinn_phong_fresnel": {"kd": [0.3, 0.12, 0.05], "p": 200},
    "torrance_sparrow": {"kd": [0.3, 0.12, 0.05], "p": 200},
    "ggx": {"kd": [0.3, 0.12, 0.05], "ks": 0.04, "alpha": 0.15},
    "beckmann": {"kd": [0.3, 0.12, 0.05], "ks": 0.04, "alpha": 0.15},
    "ggx_ms": {"alpha": 0.8},
    # Gold-like per-channel eta and k.
    "ggx_conductor": {"eta": [0.14, 0.37, 1.44], "k": [3.98, 2.38, 1.60], "alpha": 0.15},
    "beckmann_conductor": {"eta": [0.14, 0.37, 1.44], "k": [3.98, 2.38, 1.60], "alpha": 0.15},
    # A copper-like tint (f82 below 1 in green and blue).
    "ggx_f82": {"f0": [0.95, 0.64, 0.54], "f82": [1.0, 0.8, 0.7], "alpha": 0.15},
    "beckmann_f82": {"f0": [0.95, 0.64, 0.54], "f82": [1.0, 0.8, 0.7], "alpha": 0.15},
    "ggx_gen_schlick": {"kd": [0.3, 0.12, 0.05], "alpha": 0.15},
    "beckmann_gen_schlick": {"kd": [0.3, 0.12, 0.05], "alpha": 0.15},
    "beckmann_ms": {"alpha": 0.8},
    "ward": {"kd": [0.6, 0.25, 0.1], "ks": 0.3, "alpha_x": 0.1, "alpha_y": 0.4},
    "ashikhmin_shirley": {"Rd": [0.6, 0.25, 0.1], "nu": 20, "nv": 400},
    "lambert_shading": {"kd": 0.8},
    "oren_nayar_shading": {"kd": 0.8},
    "toon_diffuse": {
        "thresholds": [0.15, 0.6],
        "colors": [[0.05, 0.08, 0.25], [0.2, 0.35, 0.75], [0.45, 0.65, 1.0]],
    },
    "phong_specular": {"ks": 0.5, "p": 40},
    "blinn_specular": {"ks": 0.5, "p": 160},
    "toon_specular": {"threshold": 0.93, "high": 0.9},
    "kajiya_kay": {"kd": [0.35, 0.22, 0.08], "ks": [0.5, 0.45, 0.35], "p": 60},
}

#: The parameter the albedo curves vary, first match in a model's parameters.
CURVES = {
    "p": [2.0, 10.0, 50.0, 200.0],
    "alpha": [0.05, 0.2, 0.5, 1.0],
    "sigma": [0.0, 0.3, 0.6, 1.2],
    "nu": [1.0, 10.0, 100.0, 1000.0],
    "alpha_x": [0.05, 0.1, 0.2, 0.4],
    "kd": [0.25, 0.5, 1.0],
}

#: Incidence angles of the polar plots (degrees).
LOBE_ANGLES = (30.0, 60.0)

#: A grey diffuse under family-B specular terms, so the sphere's shape shows.
SPECULAR_BASE = 0.15


def _show(value: Any) -> str:
    if value is None:
        return "required"
    if isinstance(value, float):
        return f"{value:g}"
    return json.dumps(value)


def _call(params: dict[str, Any]) -> str:
    return ", ".join(f"{k}={_show(v)}" for k, v in params.items())


def _cli_params(params: dict[str, Any]) -> str:
    def flat(v: Any) -> str:
        if isinstance(v, list):
            return ",".join(flat(x) for x in v)
        return f"{v:g}" if isinstance(v, float) else str(v)

    return "".join(f" -p {k}={flat(v)}" for k, v in params.items() if not _nested(v))


def _nested(v: Any) -> bool:
    return isinstance(v, list) and any(isinstance(x, list) for x in v)


def label(name: str, width: int = 14) -> str:
    """Breaks a long model name at the underscore nearest its middle (for captions)."""
    if len(name) <= width or "_" not in name:
        return name
    cuts = [k for k, c in enumerate(name) if c == "_"]
    k = min(cuts, key=lambda k: abs(k - len(name) / 2))
    return f"{name[: k + 1]}\n{name[k + 1 :]}"


def curve_of(spec: dict[str, Any]) -> tuple[str, list[float]] | None:
    """The (parameter, values) the albedo curves vary, or None (family B, and the
    transmitting models, whose albedo over the whole sphere the curves do not draw)."""
    if spec["family"] != "A" or spec["transmission"]:
        return None
    names = [p["name"] for p in spec["params"]]
    for name, values in CURVES.items():
        if name in names:
            return name, values
    return None


def family_line(spec: dict[str, Any]) -> str:
    if spec["transmission"]:
        return (
            "Family A, transmitting: a BSDF `f(wi, wo)` in 1/sr, **without** the cosine"
            " factor, defined on the whole sphere: reflection where both directions are on"
            " the same side of the surface, transmission where they are on opposite sides."
        )
    if spec["family"] == "A":
        return (
            "Family A: a BRDF `f(wi, wo)` in 1/sr, **without** the cosine factor; 0 unless"
            " both directions are above the surface."
        )
    return (
        "Family B: a scan-line shading term `s(l, v)` that **includes** the light's cosine;"
        " a light of colour `L` adds `L·s(l, v)`."
    )


def model_page(name: str, spec: dict[str, Any]) -> str:
    showcase = SHOWCASE.get(name, {})
    lines = [
        f"# `{name}`",
        "",
        f"{spec['summary'][0].upper()}{spec['summary'][1:]}.",
        "",
        family_line(spec),
        "",
        f"![{name} on a sphere](img/{name}_sphere.png)",
        f"![{name}: lobe in the plane of incidence](img/{name}_lobe.png)",
        "",
        "## Formula",
        "",
        "```text",
        spec["formula"],
        "```",
        "",
        f"Source: {spec['source']}. The definition, its degenerate cases and the"
        f" published sources: [the model reference](../models.md#{name}). The kernel:"
        f" [`rust/src/models/{name}.rs`](../../rust/src/models/{name}.rs).",
        "",
        "## Parameters",
        "",
        "| name | kind | default | range | meaning | per element |",
        "|---|---|---|---|---|---|",
    ]
    for p in spec["params"]:
        lines.append(
            f"| `{p['name']}` | {p['kind']} | {_show(p['default'])} | {p['range']} |"
            f" {p['doc']} | {'yes' if p['varies'] else 'no'} |"
        )
    tangent = (
        "required (`tangent=`)"
        if spec["tangent"]
        else ("optional (`tangent=`)" if spec.get("tangent_optional") else "not used")
    )
    base = (
        f" over a grey Lambert base (kd = {SPECULAR_BASE:g})"
        if spec["scene_slot"] == "specular"
        else ""
    )
    fibres = (
        ", tangents along the meridians" if spec["tangent"] or spec.get("tangent_optional") else ""
    )
    lines += [
        "",
        f"Tangent: {tangent}. Reciprocal (`f(wi, wo) = f(wo, wi)`): "
        f'{"yes" if spec["reciprocal"] else "no"}. "per element": the parameter may be an'
        " array over the batch (spatially varying).",
        "",
        "## Pictures",
        "",
        (
            f"**Sphere**: {_call(showcase) or 'the defaults'}, a solid sphere on a"
            " checkerboard under a sky, path traced with the model's own sampler"
            " (`brdf_rs.plot.render_glass_sphere`: paths that refract in and out, up to"
            f" {GLASS_BOUNCES} scatterings; the floor and sky are the only light, so no"
            " shadows or caustics), ACES tone map."
            if spec["transmission"]
            else f"**Sphere**: {_call(showcase) or 'the defaults'}{base}. Orthographic view,"
            " a white key light from the upper right and a 30% fill from the left"
            f" (intensity π for family A, 1 for family B), ACES tone map{fibres}."
        ),
        "",
        f"**Lobe**: the same parameters; `wo` sweeps the plane of incidence, the light"
        f" arrives from the left at θi = {', '.join(f'{a:g}°' for a in LOBE_ANGLES)} (dotted"
        " lines), the mirror direction is on the right. The radius is"
        f" {'`s` (no unit)' if spec['family'] == 'B' else '`f` in 1/sr'}: one curve per"
        " angle, of the value itself when the colour parameters are grey, else of its"
        " luminance 0.2126 R + 0.7152 G + 0.0722 B.",
        "",
    ]
    curve = curve_of(spec)
    if curve is not None:
        param, values = curve
        fixed = {
            p["name"]: p["default"]
            for p in spec["params"]
            if p["name"] != param and p["default"] is not None
        }
        lines += [
            f"![{name}: directional albedo](img/{name}_albedo.png)",
            "",
            f"**Directional albedo** `R(μ) = ∫ f(wi, wo)·cos θo dωo` against μ = cos θi, for"
            f" {param} = {', '.join(f'{v:g}' for v in values)} and the defaults"
            f" ({_call(fixed) or 'no others'}), computed by `brdf_rs.albedo_table` with ±2"
            " standard-error bands; the dotted line is R = 1 (energy conservation). The albedo"
            " axis is logarithmic when the curves span more than a factor of 30.",
            "",
        ]
    elif spec["transmission"]:
        lines += [
            "No albedo curve: the curves draw the albedo over the hemisphere above the"
            " surface, and this model's is over the whole sphere.",
            "",
        ]
    else:
        lines += [
            "No albedo curve: directional albedo is defined for family-A BRDFs; a shading"
            " term already includes the light's cosine.",
            "",
        ]
    args = [f'"{name}"', "wi", "wo"]
    if showcase:
        args.append(_call(showcase))
    if spec["tangent"]:
        args.append("tangent=t")
    lines += [
        "## Use it",
        "",
        "```python",
        "import brdf_rs",
        "",
        f"f = brdf_rs.eval({', '.join(args)})",
    ]
    if curve is not None:
        albedo_args = [f'"{name}"', "mu", *([_call(showcase)] if showcase else [])]
        lines.append(f"r = brdf_rs.albedo({', '.join(albedo_args)})")
    lines += ["```", ""]
    if not any(_nested(v) for v in showcase.values()):
        tangent_arg = " --tangent 1,0,0" if spec["tangent"] else ""
        cli = _cli_params(showcase)
        lines += [
            "```sh",
            f"brdf-rs eval {name} --wi 0,0.3,1 --wo 0.2,-0.3,1{cli}{tangent_arg}",
            f"brdf-rs plot-lobe {name} --theta-i 30 --theta-i 60{cli} -o lobe.png",
            "```",
            "",
        ]
    lines.append("[All models](../index.md#models) · [Conventions](../conventions.md)")
    return "\n".join(lines) + "\n"


CONVENTIONS = """# Conventions

These hold everywhere in brdf-rs: `eval`, `sample`, `pdf`, the albedo integrators, the
scenes and the command line. [The model reference](models.md) defines every model in
these terms.

## Directions

- Directions point **away** from the surface: `wi` toward the light, `wo` toward the
  viewer. `n` is the surface normal, +z unless given.
- `mu_i = n·wi` and `mu_o = n·wo` are the cosines of θi and θo; the half vector is
  `h = (wi + wo)/|wi + wo|`.
- Inputs need not be unit length: they are normalized robustly (from about 1e-300 to
  1e300) unless `normalized=True` promises that they already are.
- Models with an anisotropic lobe (`ward`, `ashikhmin_shirley`) take an optional
  `tangent=`, projected onto the tangent plane; `kajiya_kay` requires its fibre tangent,
  used as given. A tangent given to an anisotropic model must not be parallel to the
  normal: one whose angle to `n` has a sine of at most 64 machine epsilons of the dtype
  (1.4e-14 for float64, 7.6e-6 for float32; the renderer's float32 for scenes and
  `shade`) is refused, since its projection is rounding error pointing anywhere.

## Units and what `f` includes

- **Family A** models return the BRDF `f(wi, wo)` in 1/sr, **without** the cosine factor,
  and 0 unless both directions are above the surface (the rough dielectrics excepted:
  [below](#the-whole-sphere-rough-dielectrics)). A light of radiance-scale `L` reflects
  `L·f(wi, wo)·cos θi`.
- **Family B** models return the scan-line shading term `s(l, v)` of the shading
  assignment, which **includes** the light's cosine (`l = wi`, `v = wo`).
- Directional albedo: `R(μ) = ∫ f(wi, wo)·cos θo dωo` over the hemisphere, μ = cos θi
  (family A only; the whole sphere for the rough dielectrics). A table's `stderr` is the
  standard error of each cell; how far it can be trusted, and its one known limit, is in
  [error_bars.md](error_bars.md).
- Angles on the command line and in `brdf_rs.plot` are in degrees; everything else takes
  cosines or vectors, except the azimuth `phi` of `brdf_rs.albedo` and
  `brdf_rs.albedo_table`: radians, measured from the tangent counterclockwise about `n`,
  `wi = (sin θi cos φ, sin θi sin φ, μ)` (only the anisotropic models depend on it).

## The whole sphere: rough dielectrics

`ggx_dielectric` and `beckmann_dielectric` are BSDFs: they reflect and transmit, and
`brdf_rs.models()[name]["transmission"]` is true for them (false for every other
model). What changes for them:

- `f` still excludes the cosine, and `wi`, `wo` still point away from the surface; but
  `f` is defined on the **whole sphere** of both: `wi` and `wo` on the same side
  (either side) is a reflection, on opposite sides a transmission. It is 0 only where
  `mu_i = 0` or `mu_o = 0`, or where no microfacet explains the pair.
- `eta` is the relative index `eta_below/eta_above`, "below" being the side opposite
  `n`; the medium a direction lies in has index 1 above and `eta` below. `eta < 1`
  means the denser medium is on `n`'s side.
- **Radiance transport.** `f` carries radiance from `wi` to the viewer at `wo`: a
  transmitted value includes the factor `eta_o²` (the index of `wo`'s medium), as
  radiance entering a denser medium is concentrated. So `f` is reciprocal in the form
  `f(wi, wo)/eta_o² = f(wo, wi)/eta_i²`, not `f(wi, wo) = f(wo, wi)` (reflections, with
  `eta_i = eta_o`, are symmetric).
- **Albedo.** `brdf_rs.albedo` and `brdf_rs.albedo_table` integrate
  `∫ f(wi, wo)·|cos θo| dωo` over the whole sphere of `wo`, with `wi` fixed above the
  surface at cosine `mu` (light from inside a glass body: `eta < 1`). With the `eta_o²`
  factor this is the fraction of the incident energy scattered: at most 1 for
  `ks = kt = 1`. `component=` chooses the part: `"total"` (the default), `"reflection"`
  (`wo` above) or `"transmission"` (`wo` below). `"transmission"` for a model that does
  not transmit, or any other value, is refused with a message naming `component`.
- **eta = 1** is valid and means no interface: nothing is reflected and the light goes
  straight through, a delta at `wo = −wi`. `eval` gives 0 for every pair (the delta is
  not a function value); `albedo` gives reflection 0 and transmission `kt`, exactly;
  `sample` draws `wo = −wi` with weight `kt` and reports its density as `inf`, while
  `pdf()` reports 0 for every direction.
- **Scenes** shade reflection only (lights and viewer on `n`'s side): a scene refuses a
  transmitting model by name. `brdf_rs.plot.render_glass_sphere` path-traces one as a
  solid sphere (light refracted in and out, with the `eta²` factors of the radiance it
  carries), on a checkerboard or in a white furnace.

## Colours

Every result is RGB: a trailing axis of 3. Colour parameters (`kd`, `ks`, `Rd`, `Rs`,
`colors`) take a scalar (grey) or an RGB triple; Schlick's `F0` is `ks` per channel.
`torrance_sparrow`'s `eta` is a scalar (its Fresnel term is grey).

## Arrays and dtypes

- `wi`, `wo`, `n`, `tangent` and every parameter broadcast together by NumPy's rules; any
  memory layout is read in place. Parameters may be arrays over the batch (spatially
  varying materials), colours with a trailing axis of 3.
- float64 in → float64 out; **float32** in (every direction array float32, in either byte
  order) → float32 out from float32 kernels; anything else (ints, lists, mixed widths) →
  float64. `sample`, `pdf` and the albedo functions compute in float64 whatever the input;
  `render`, `shade` and `tonemap` return float32.
- `out=` writes into a preallocated C-contiguous array of the result's shape and dtype.
- float32 lobes below 2^-100 ≈ 7.9e-31 are flushed to 0.
- A parameter's closed bound is accepted as given and as float32 rounds it, in both
  dtypes: `sigma=np.pi/2` with float32 directions is float32(π/2), just above π/2, and
  valid.

## Errors, threads, reproducibility

- Bad input raises `ValueError` / `TypeError` in one line naming the argument (and, for
  arrays, the first bad index); nothing reachable from Python panics. The command line
  prints that line and exits with 2 (usage) or 1 (failure).
- Work runs in Rust threads without the GIL: `BRDF_RS_NUM_THREADS`, else the CPU count;
  `brdf_rs.set_num_threads(n)` at run time.
- Long calls answer Ctrl-C: `eval` (between parts of 262,144 rows), `render` (between
  bands of about 262,144 pixels) and the albedo builds check for signals at most every
  20–100 ms and raise `KeyboardInterrupt` (`eval` with `out=` leaves it partly written).
- The same inputs and seed give the same bits for any thread count and any chunking of a
  table.
- The library never prints: it logs to the `brdf_rs` logger (`logging`).
"""


def index_page(specs: dict[str, dict[str, Any]], has_benchmarks: bool) -> str:
    lines = [
        "# brdf-rs documentation",
        "",
        "Evaluate reflectance models on NumPy arrays, integrate them over the hemisphere and"
        " bake albedo tables, with the work done in Rust. Start with the"
        " [README](../README.md) (install, a five-minute tour), then:",
        "",
        "- [Model reference](models.md): every model's formula, parameters, degenerate cases"
        " and published source.",
        "- [Conventions](conventions.md): directions, units, what `f` includes, RGB, dtypes.",
        "- [Example scenes](scenes.md): scan-line rendering with the models as materials.",
        "- [Error bars](error_bars.md): what an albedo's `stderr` means, how it is measured,"
        " and its known limit.",
        '- [Exact normalization](normalization.md): `normalization="exact"`, per model,'
        " and how accurate it is.",
        "- [Albedo tables on Dask](dask.md): one table built by many processes or machines,"
        " with the same bits.",
        "- [Engine LUTs](luts.md): split-sum DFG and Kulla-Conty tables in engines' layouts"
        " (`brdf_rs.lut`, `brdf-rs lut`): presets, axes, formats, error budgets.",
        "- [Numerics](numerics.md): the stress test of every model against a 50-digit"
        " reference, and what it measured.",
    ]
    if has_benchmarks:
        lines.append("- [Benchmarks](benchmarks.md): throughput, convergence, rendering, Dask.")
    lines += [
        "",
        "## Models",
        "",
        "![family A models on spheres](models/img/overview_a.png)",
        "",
        "| model | family | what it is |",
        "|---|---|---|",
    ]
    for name, spec in specs.items():
        lines.append(f"| [`{name}`](models/{name}.md) | {spec['family']} | {spec['summary']} |")
    lines += [
        "",
        "![family B terms on spheres](models/img/overview_b.png)",
        "",
        "Family A: BRDFs in 1/sr without the cosine; family B: shading terms that include",
        "the light's cosine (see [Conventions](conventions.md)). The pages and images are",
        "generated by `python scripts/make_docs.py` from `brdf_rs.models()` and the library's",
        "own renderer and integrators.",
        "",
    ]
    return "\n".join(lines)


#: Result pages that are not for users: comparisons of development builds of the library
#: (their labels name code that no release contains). They stay in benches/results/.
NOT_FOR_USERS = ("ab_builds",)

#: Titles of result pages whose first line is not a heading, or whose heading is shared
#: with other pages (the calibration runs).
TITLES = {
    "eval_layouts": "brdf_rs.eval by input memory layout",
    "furnace": "White furnace of the multiple-scattering lobes (ggx_ms, beckmann_ms)",
    "install_time": "From-source install time",
    "stderr_calibration": "Standard errors of brdf_rs.albedo: the named cases",
    "stderr_calibration_deep": (
        "Standard errors of brdf_rs.albedo: Torrance-Sparrow at 2^20 samples"
    ),
    "stderr_calibration_grid_half_vector": (
        "Standard errors of brdf_rs.albedo: Ward, Ashikhmin-Shirley and Beckmann over "
        "incidence and roughness"
    ),
    "stderr_calibration_grid_power_cosine": (
        "Standard errors of brdf_rs.albedo: the Phong and Blinn-Phong families over "
        "incidence and exponent"
    ),
    "stderr_calibration_grid_torrance_sparrow": (
        "Standard errors of brdf_rs.albedo: Torrance-Sparrow over eta, incidence and exponent"
    ),
}


#: What each figure shows, for a reader (the figure's own title names the model).
CAPTIONS = {
    "albedo_convergence": "RMS error of the whole table against wall time, log-log, one line"
    " per sampling method: lower and further left is better.",
    "dielectric_table": "RMS error of the table against wall time, one point per"
    " tolerance, log-log; the dotted lines mark RMS 1e-4 and 10 s.",
    "eval_layouts": "Million evaluations per second for each way of passing the directions:"
    " contiguous, reversed rows, Fortran order, an outer product of broadcast arrays.",
    "eval_throughput": "Million evaluations per second of every model (log scale), NumPy"
    " implementations of the same formulas (where one exists) against brdf-rs on one and two"
    " threads.",
    "render": "The frame that was timed: the gallery scene (examples/scenes/gallery.toml).",
}


def benchmarks_page(results: Path) -> str | None:
    """Collects benches/results/*.md: each one's title and description, its figure."""
    pages = [p for p in sorted(results.glob("*.md")) if not p.stem.startswith(NOT_FOR_USERS)]
    if not pages:
        return None
    rel = Path("..") / results.relative_to(ROOT)  # docs/ is beside benches/
    lines = [
        "# Benchmarks",
        "",
        "Written by the scripts in `benches/` (each page says how it was run and on what"
        " machine); `brdf-rs bench` runs a short version on yours.",
        "",
    ]
    for page in pages:
        text = page.read_text(encoding="utf-8").splitlines()
        if text and text[0].startswith("#"):
            title, text = text[0].lstrip("# ").strip(), text[1:]
        else:
            title = page.stem
        title = TITLES.get(page.stem, title)
        intro = []
        for line in text:
            if line.startswith(("|", "#")):
                break
            intro.append(line)
        lines += [f"## {title}", "", "\n".join(intro).strip(), ""]
        lines.append(f"Full tables: [`{page.name}`]({(rel / page.name).as_posix()}).")
        figure = page.with_suffix(".png")
        if figure.exists():
            lines += ["", f"![{title}]({(rel / figure.name).as_posix()})"]
            caption = CAPTIONS.get(page.stem) or CAPTIONS.get(page.stem.rsplit("_", 1)[0])
            if caption:
                lines += ["", f"*{caption}*"]
        lines.append("")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--resolution", choices=sorted(RESOLUTIONS), default="full")
    parser.add_argument("--out", type=Path, default=ROOT / "docs", help="default: docs/")
    parser.add_argument("--models", nargs="+", default=None, help="only these (default all)")
    args = parser.parse_args()
    res = RESOLUTIONS[args.resolution]
    specs = brdf_rs.models()
    names = args.models or list(specs)
    for name in names:
        if name not in specs:
            parser.error(f"--models: unknown model {name!r}")
    pages, img = args.out / "models", args.out / "models" / "img"
    img.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    overview: dict[str, list[tuple[np.ndarray, str]]] = {"A": [], "B": []}
    for name in names:
        spec = specs[name]
        params = SHOWCASE.get(name, {})
        base = {"base": SPECULAR_BASE} if spec["scene_slot"] == "specular" else {}
        if spec["transmission"]:  # scenes shade reflection only: traced here
            glass = plot.render_glass_sphere(
                name, size=res["sphere"], samples=res["paths"], bounces=GLASS_BOUNCES, **params
            )
            brdf_rs.save_image(img / f"{name}_sphere.png", glass)
        else:
            sphere = plot.render_sphere(name, size=res["sphere"], **base, **params)
            brdf_rs.save_image(img / f"{name}_sphere.png", sphere)
            small = plot.render_sphere(name, size=res["overview"], **base, **params)
            overview[spec["family"]].append((small, label(name)))
        plot.polar_lobe(name, LOBE_ANGLES, path=img / f"{name}_lobe.png", dpi=res["dpi"], **params)
        curve = curve_of(spec)
        if curve is not None:
            param, values = curve
            plot.albedo_curves(
                name,
                param,
                values,
                mu=np.linspace(0.02, 1.0, res["mu"]),
                samples=res["samples"],
                path=img / f"{name}_albedo.png",
                dpi=res["dpi"],
            )
        (pages / f"{name}.md").write_text(model_page(name, spec), encoding="utf-8")
        print(f"{pages / name}.md  ({time.perf_counter() - start:.1f} s)")
    # The overviews show every model of a family: a run limited to some models keeps
    # the committed ones.
    for family, items in overview.items():
        if items and args.models is None:
            images, labels = zip(*items, strict=True)
            plot.spheres(
                images,
                labels,
                ncols=8,
                path=img / f"overview_{family.lower()}.png",
                dpi=res["dpi"],
                panel_inches=1.25,
            )
    if args.models is None:
        bench = benchmarks_page(ROOT / "benches" / "results")
        if bench is not None:
            (args.out / "benchmarks.md").write_text(bench, encoding="utf-8")
        (args.out / "index.md").write_text(index_page(specs, bench is not None), encoding="utf-8")
        (args.out / "conventions.md").write_text(CONVENTIONS, encoding="utf-8")
    size = sum(f.stat().st_size for f in args.out.rglob("*") if f.is_file())
    print(f"{args.out}: {size / 1e6:.2f} MB in {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
