"""Smoke test of an installed brdf-rs wheel, run by .ci/run in a fresh virtual environment.

    python scripts/wheel_smoke.py        # with the environment's python, not the repo's

Checks that the package imported is the installed one (not the source tree), that the
compiled core evaluates and integrates with known exact answers, that the typing files
and both licence texts ship, that the console script works (rendering an example scene
that ships in the wheel), and that the optional extras stay optional: without pypng,
writing PNG gives its one-line error naming the ``png`` extra (with pypng, a PNG render
and a table's PNG preview that reads back), and without matplotlib plotting names the
``plot`` extra. Exits non-zero on the first failure.
"""

from __future__ import annotations

import importlib.metadata
import json
import math
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

import brdf_rs
import numpy as np

package = Path(brdf_rs.__file__).resolve().parent
site = Path(sysconfig.get_paths()["purelib"]).resolve()
assert package.parent == site, f"imported {package}, not the installed wheel in {site}"
assert (package / "py.typed").exists() and (package / "_brdf_rs.pyi").exists()
assert list(package.glob("_brdf_rs*.so")) or list(package.glob("_brdf_rs*.pyd"))
# The licence texts (pyproject's license-files) in the wheel's metadata.
shipped = {Path(str(f)).name for f in importlib.metadata.files("brdf-rs") or []}
assert {"LICENSE-MIT", "LICENSE-APACHE"} <= shipped, sorted(shipped)

# eval: Lambert is kd/π, in float64 and float32.
f = brdf_rs.eval("lambert", [0.3, 0.2, 1.0], [-0.1, 0.4, 1.0], kd=1.0)
assert f.dtype == np.float64 and np.allclose(f, 1 / math.pi, rtol=1e-15), f
f32 = brdf_rs.eval("lambert", np.float32([[0, 0, 1]]), np.float32([[0, 0, 1]]), kd=1.0)
assert f32.dtype == np.float32 and np.allclose(f32, 1 / math.pi, rtol=1e-6), f32

# A tiny albedo table: normalized_phong (kd = 0, ks = 1) has albedo exactly 1 at mu = 1.
table = brdf_rs.albedo_table(
    "normalized_phong", {"mu": [0.5, 1.0], "p": [10.0, 100.0]}, kd=0, ks=1, tol=1e-4
)
assert table.value.shape == (2, 2, 3)
error = np.abs(table.value[1, :, 0] - 1.0)
assert np.all(error <= 6 * table.stderr[1, :, 0] + 1e-12), (error, table.stderr[1])

# The Ward exact-normalization table ships as package data: at normal incidence the
# exactly normalized lobe's albedo is 1 (alpha 0.2: the integrator's error is ~1e-6).
assert (package / "exact_normalization.npz").exists()
ward = brdf_rs.albedo("ward", 1.0, kd=0, ks=1, alpha_x=0.2, alpha_y=0.2, normalization="exact")
assert abs(ward.value[0] - 1) < 6 * ward.stderr[0] + 1e-4, ward

# The console script, as a user runs it.
script = Path(sys.executable).parent / "brdf-rs"
models = json.loads(
    subprocess.run([script, "models", "--json"], capture_output=True, text=True, check=True).stdout
)
assert set(models) == set(brdf_rs.models()) and "torrance_sparrow" in models
with tempfile.TemporaryDirectory() as tmp:
    out = Path(tmp) / "t.npz"
    result = subprocess.run(
        [
            script,
            "table",
            "lambert",
            "--axis",
            "mu=0.5,1",
            "-p",
            "kd=0.5",
            "-q",
            "--json",
            "-o",
            str(out),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    summary = json.loads(result.stdout)
    assert summary["shape"] == [2, 3] and out.exists()
    bad = subprocess.run(
        [script, "eval", "nope", "--wi", "0,0,1", "--wo", "0,0,1"], capture_output=True, text=True
    )
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1, bad.stderr

    # The example scenes ship in the wheel: render one by name (.npy needs no extra).
    assert set(brdf_rs.example_scenes()) >= {"gallery", "hdr", "rtr_fig_7_38"}
    render = [script, "render", "hdr", "--resolution", "64x36", "-q", "-o"]
    subprocess.run([*render, str(Path(tmp) / "hdr.npy")], check=True)
    assert np.load(Path(tmp) / "hdr.npy").shape == (36, 64, 3)
    # PNG (rendered images and table previews) needs the png extra (pypng). With it: a
    # PNG render, and a table's 16-bit preview whose values read back; without it (CI
    # installs the wheel alone): the one-line error naming the extra, and no file.
    image = Path(tmp) / "hdr.png"
    try:
        import png  # noqa: F401
    except ImportError:
        result = subprocess.run([*render, str(image)], capture_output=True, text=True)
        assert result.returncode == 1 and not image.exists(), result
        assert result.stderr == (
            "brdf-rs render: saving a PNG needs pypng: pip install 'brdf-rs[png]'\n"
        ), result.stderr
        try:
            table.save(Path(tmp) / "t.png")
        except ImportError as exc:
            assert "pip install 'brdf-rs[png]'" in str(exc), exc
        else:
            raise AssertionError("Table.save('t.png') without pypng did not raise ImportError")
    else:
        subprocess.run([*render, str(image)], check=True)
        assert image.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
        preview = brdf_rs.TablePreview.load(table.save(Path(tmp) / "t.png"))
        assert np.all(np.abs(preview.value - table.value) <= preview.step / 2 + 1e-12)

# Optional extras stay optional: without matplotlib, plotting says what to install.
try:
    import matplotlib  # noqa: F401
except ImportError:
    from brdf_rs import plot

    try:
        plot.polar_lobe("lambert")
    except ImportError as exc:
        assert "pip install 'brdf-rs[plot]'" in str(exc), exc
    else:
        raise AssertionError("polar_lobe without matplotlib did not raise ImportError")

print(f"wheel smoke test passed: brdf-rs {brdf_rs.__version__} from {package}, isa {brdf_rs.isa()}")
