"""Shared test helpers: random inputs drawn from the spec table, a condition estimate,
a small scene and a CLI runner.

The condition estimate says how much a model's exact value moves when its inputs move by
a relative ``delta``: the ratio of relative output change to relative input change,
measured with the pure-Python reference under random component-wise perturbations of
the directions and the parameters. Comparisons then allow an error proportional to it:
a well-conditioned value must match to 1e-12, an ill-conditioned one (a 1/mu_i blow-up,
a toon threshold, an exponent of 1e6 far from the peak) only as well as its inputs
determine it.
"""

from __future__ import annotations

import importlib.util
import math
import os
import signal
import subprocess
import sys
from pathlib import Path

import brdf_rs
import numpy as np
import pytest
from brdf_rs import reference
from hypothesis import settings

# The interrupt tests send this process a Ctrl-C (``_thread.interrupt_main``), which does
# nothing where SIGINT is ignored: a shell starts background jobs that way (``cmd &``,
# ``nohup``), and Python then installs no handler. Install the terminal's
# (KeyboardInterrupt), so those tests check the extension whatever started the run.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

# Property tests are derandomized by default so a run (CI's included) is reproducible:
# the same examples every time. HYPOTHESIS_PROFILE=explore draws new random examples
# (run it locally to hunt for failures; a failure it finds becomes a fixed test).
settings.register_profile("default", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))

SPECS = brdf_rs.models()
MODEL_NAMES = list(SPECS)
FAMILY_A = [m for m in MODEL_NAMES if SPECS[m]["family"] == "A"]
FAMILY_B = [m for m in MODEL_NAMES if SPECS[m]["family"] == "B"]
#: Family-A models defined on the whole sphere (BSDFs that transmit: the rough
#: dielectrics), not 0 below the surface; tests/test_dielectric.py covers what is theirs.
TRANSMISSION = [m for m in MODEL_NAMES if SPECS[m].get("transmission")]
#: Models with a pure-Python reference (the multiple-scattering lobes interpolate tables
#: computed by brdf-rs itself; they are tested by the white furnace instead).
REFERENCE_MODELS = [m for m in MODEL_NAMES if not m.endswith("_ms")]


def takes_tangent(model: str) -> bool:
    """Whether the model reads a tangent (required or optional)."""
    return bool(SPECS[model]["tangent"] or SPECS[model].get("tangent_optional"))


def required_extras(model: str) -> dict:
    """Fixed values for a model's required arguments (toon lists, threshold, tangent)."""
    if model == "toon_diffuse":
        return {"thresholds": [-0.2, 0.4], "colors": [[0.1, 0, 0], [0.5, 0.5, 0], [1, 1, 1]]}
    if model == "toon_specular":
        return {"threshold": 0.9}
    if model == "kajiya_kay":
        return {"tangent": [1.0, 0.0, 0.0]}
    return {}


def fresnel(c: float, r: float) -> float:
    """The unpolarized reflectance for the cosine ``c`` on the incident side and the
    relative index ``r`` (far side / incident side), from Snell's law and the amplitude
    ratios ``r_s``, ``r_p`` (the textbook form, not docs/models.md's)."""
    sin2_t = (1.0 - c * c) / (r * r)
    if sin2_t >= 1.0:
        return 1.0
    c_t = math.sqrt(1.0 - sin2_t)
    r_s = (c - r * c_t) / (c + r * c_t)
    r_p = (r * c - c_t) / (r * c + c_t)
    return 0.5 * (r_s * r_s + r_p * r_p)


def random_directions(rng: np.random.Generator, n: int, *, unnormalized: bool = True):
    """Random directions over the whole sphere, some with random lengths."""
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    if unnormalized:
        scale = 10.0 ** rng.uniform(-3, 3, size=(n, 1))
        v *= np.where(rng.random((n, 1)) < 0.5, 1.0, scale)
    return v


def upper_directions(rng: np.random.Generator, n: int):
    """Random unit directions in the upper hemisphere (+z)."""
    v = random_directions(rng, n, unnormalized=False)
    v[:, 2] = np.abs(v[:, 2])
    return v


def random_value(rng: np.random.Generator, model: str, spec: dict, size=None):
    """A random valid value of one parameter (arrays of ``size`` rows for varying ones)."""
    name, kind = spec["name"], spec["kind"]
    if kind == "colour":
        hi = 1.0 if spec["max"] <= 1.0 else 1.5
        shape = (3,) if size is None else (size, 3)
        # A conductor's eta (a colour whose range starts above 0) keeps to its range.
        return rng.uniform(max(0.0, spec["min"]), hi, size=shape)
    if kind == "scalar":
        if name == "p":
            p = 10.0 ** rng.uniform(-1, 3, size=size)
            return np.where(rng.random(size=size) < 0.05, 0.0, p)
        if name == "eta":
            return 10.0 ** rng.uniform(-0.7, 0.7, size=size)
        if name in ("alpha", "alpha_x", "alpha_y"):
            return 10.0 ** rng.uniform(-2, 0, size=size)
        if name in ("nu", "nv"):
            return 10.0 ** rng.uniform(0, 4, size=size)
        if name == "exponent":  # the generalized Schlick term's power
            return 10.0 ** rng.uniform(-1, 1.5, size=size)
        return rng.uniform(spec["min"], spec["max"], size=size)
    raise AssertionError(f"no varying generator for {model}.{name}")


def random_lists(rng: np.random.Generator, model: str) -> dict:
    """Random valid values for list parameters and required scalars of toon models."""
    if model == "toon_diffuse":
        k = int(rng.integers(1, 4))
        return {
            "thresholds": np.sort(rng.uniform(-1, 1, size=k)),
            "colors": rng.uniform(0, 1, size=(k + 1, 3)),
        }
    return {}


def random_params(rng: np.random.Generator, model: str, size=None) -> dict:
    """Random values of every parameter of ``model`` (per-row arrays when ``size``)."""
    out = random_lists(rng, model)
    for spec in SPECS[model]["params"]:
        if spec["name"] in out:
            continue
        out[spec["name"]] = random_value(rng, model, spec, size)
    return out


def row_params(model: str, params: dict, i: int) -> dict:
    """The parameters of row ``i`` as plain Python values, for the reference."""
    out = {}
    kinds = {p["name"]: p["kind"] for p in SPECS[model]["params"]}
    for k, v in params.items():
        a = np.asarray(v, dtype=np.float64)
        per_row = (kinds[k] == "colour" and a.ndim == 2) or (kinds[k] == "scalar" and a.ndim == 1)
        out[k] = a[i].tolist() if per_row else a.tolist()
    return out


def reference_rgb(model, wi, wo, n=(0.0, 0.0, 1.0), tangent=None, **params):
    return np.array(reference.eval(model, list(wi), list(wo), list(n), tangent, **params))


def condition(model, wi, wo, n, tangent, params, rng, value, delta=1e-7, trials=3):
    """Estimated relative condition number of the reference value at these inputs.

    Directions are nudged normwise (by ``delta·|v|`` in a random direction: what the
    roundings inside any algorithm amount to), parameters relatively.
    """
    worst = 0.0

    def jitter(v):
        g = rng.normal(size=3)
        g *= delta * math.hypot(*v) / np.linalg.norm(g)
        return [float(x + d) for x, d in zip(v, g, strict=True)]

    for _ in range(trials):
        p2 = {}
        for k, v in params.items():
            if k in ("thresholds", "colors"):
                p2[k] = v
            elif isinstance(v, list):
                p2[k] = jitter(v)
            else:
                p2[k] = v * (1.0 + delta * rng.uniform(-1, 1))
        t2 = None if tangent is None else jitter(tangent)
        try:
            moved = reference_rgb(model, jitter(wi), jitter(wo), jitter(n), t2, **p2)
        except (ValueError, OverflowError):
            return math.inf
        with np.errstate(invalid="ignore", divide="ignore"):
            # Relative to the value itself down to the smallest normal (a floor of 1e-300
            # made the condition of a value of 1e-303 a thousand times too small).
            scale = np.maximum(np.abs(value), np.finfo(np.float64).tiny)
            change = np.abs(moved - value) / scale / delta
        change = np.where(np.isfinite(value) & np.isfinite(moved), change, 0.0)
        change = np.where(np.isinf(value) != np.isinf(moved), math.inf, change)
        worst = max(worst, float(np.max(change)))
    # A relative jump of 1% or more under a 1e-7 nudge is a discontinuity (a toon band
    # edge, the horizon): the value is not determined by the inputs' precision at all.
    return math.inf if worst * delta >= 1e-2 else worst


@pytest.fixture
def rng():
    return np.random.default_rng(20261121)


# ------------------------------------------------------------------ scenes and the CLI

#: One unit sphere carrying material ``m``.
SPHERE = '[[objects]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = "m"\n'


def tiny_scene(material: str, objects: str = SPHERE, lights: str = "") -> str:
    """A TOML scene: an 8×8 orthographic camera, one material ``m`` (its TOML body
    lines), ``objects`` and ``lights`` (TOML tables)."""
    return (
        '[camera]\ntype = "orthographic"\nposition = [0, 0, 5]\nheight = 3\n'
        f"resolution = [8, 8]\n\n[materials.m]\n{material}\n\n{objects}\n{lights}"
    )


def run_cli(*args: str, cwd: Path | None = None, code: int = 0) -> subprocess.CompletedProcess:
    """Runs ``python -m brdf_rs ARGS`` (2 threads) and checks its exit code."""
    env = {**os.environ, "BRDF_RS_NUM_THREADS": "2"}
    result = subprocess.run(
        [sys.executable, "-m", "brdf_rs", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        check=False,
    )
    assert result.returncode == code, (result.returncode, result.stdout, result.stderr)
    return result


def calibration_script():
    """scripts/stderr_calibration.py as a module."""
    return script("stderr_calibration")


def script(name: str):
    """scripts/<name>.py as a module (loaded once)."""
    module = sys.modules.get(name)
    if module is None:
        path = Path(__file__).resolve().parent.parent / "scripts" / f"{name}.py"
        spec = importlib.util.spec_from_file_location(name, path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module  # dataclasses look their module up there
        spec.loader.exec_module(module)
    return module
