"""scripts/make_docs.py: runs at low resolution into a temporary directory; every page's
images exist and are valid PNGs, its links resolve, its examples run, and the committed
docs/ say what a fresh run says (the Markdown does not depend on the resolution)."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import brdf_rs
import numpy as np
import pytest
from brdf_rs import plot
from brdf_rs.cli import main as cli_main

pytest.importorskip("matplotlib")
PIL = pytest.importorskip("PIL.Image")

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "make_docs.py"
SMALL = {
    "sphere": 24,
    "lobe": (int(plot.LOBE_SIZE[0] * 24), int(plot.LOBE_SIZE[1] * 24)),
    "albedo": (int(plot.CURVES_SIZE[0] * 24), int(plot.CURVES_SIZE[1] * 24)),
}


@pytest.fixture(scope="module")
def docs(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("docs")
    result = subprocess.run(
        [sys.executable, str(SCRIPT), "--resolution", "small", "--out", str(out)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    return out


def png_size(path: Path) -> tuple[int, int]:
    with PIL.open(path) as image:
        assert image.format == "PNG"
        image.load()
        return image.size


def links(markdown: str) -> list[str]:
    return re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", markdown)


def test_one_page_per_model_with_its_spec(docs):
    specs = brdf_rs.models()
    assert sorted(p.stem for p in (docs / "models").glob("*.md")) == sorted(specs)
    for name, spec in specs.items():
        page = (docs / "models" / f"{name}.md").read_text(encoding="utf-8")
        assert page.startswith(f"# `{name}`\n")
        assert spec["formula"] in page and spec["source"] in page
        for p in spec["params"]:
            default = "required" if p["default"] is None else f"{p['default']:g}"
            assert f"| `{p['name']}` | {p['kind']} | {default} | {p['range']} |" in page


def test_images_are_pngs_of_the_requested_size(docs):
    img = docs / "models" / "img"
    for name, spec in brdf_rs.models().items():
        # A sphere for every model (a traced glass sphere for the transmitting ones); no
        # hemisphere albedo curve for those.
        assert png_size(img / f"{name}_sphere.png") == (SMALL["sphere"],) * 2
        assert png_size(img / f"{name}_lobe.png") == SMALL["lobe"]
        albedo = img / f"{name}_albedo.png"
        assert albedo.exists() == (spec["family"] == "A" and not spec["transmission"])
        if albedo.exists():
            assert png_size(albedo) == SMALL["albedo"]
    for family in ("a", "b"):
        assert png_size(img / f"overview_{family}.png")[0] > 0


def test_committed_overviews_show_every_model_of_their_family():
    """docs/models/img/overview_*.png: one panel (1.25 in at 100 dpi, 8 to a row) per
    model the scenes render; a run of the script limited to some models keeps them."""
    specs = brdf_rs.models().values()
    for family in ("A", "B"):
        count = sum(s["family"] == family and not s["transmission"] for s in specs)
        width, height = png_size(
            ROOT / "docs" / "models" / "img" / f"overview_{family.lower()}.png"
        )
        assert width == 125 * min(count, 8), (family, width, count)
        assert height == 150 * -(-count // 8), (family, height, count)


def test_a_run_for_some_models_keeps_the_overviews(tmp_path):
    img = tmp_path / "models" / "img"
    img.mkdir(parents=True)
    kept = b"not an image: the run must leave it alone"
    (img / "overview_a.png").write_bytes(kept)
    args = ["--resolution", "small", "--out", str(tmp_path), "--models", "lambert"]
    result = subprocess.run(
        [sys.executable, str(SCRIPT), *args],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert (img / "overview_a.png").read_bytes() == kept
    assert (img / "lambert_sphere.png").exists()


def test_sphere_images_show_the_model(docs):
    # Rendered, not drawn: the lit side of every sphere is brighter than the corner, and
    # the white Lambert sphere matches a direct render at that size.
    img = docs / "models" / "img"
    for name, spec in brdf_rs.models().items():
        if spec["transmission"]:
            continue
        with PIL.open(img / f"{name}_sphere.png") as image:
            pixels = np.asarray(image.convert("RGB"), dtype=float)
        assert pixels[0, 0].max() == 0, name
        assert pixels.max() > 40, name
    with PIL.open(img / "lambert_sphere.png") as image:
        pixels = np.asarray(image.convert("RGB"))
    direct = plot.render_sphere("lambert", size=SMALL["sphere"])
    encoded = brdf_rs._brdf_rs.encode_srgb8(np.ascontiguousarray(direct))
    np.testing.assert_array_equal(pixels, encoded)


def test_every_link_resolves(docs):
    for page in docs.rglob("*.md"):
        for target in links(page.read_text(encoding="utf-8")):
            if target.startswith("http"):
                continue
            resolved = page.parent / target
            if not resolved.exists():  # links out of docs/ point into the repository
                resolved = ROOT / "docs" / page.parent.relative_to(docs) / target
            assert resolved.exists(), f"{page.name}: {target}"


def test_the_examples_on_every_page_run(docs, tmp_path):
    rng = np.random.default_rng(1)
    scope = {
        "brdf_rs": brdf_rs,
        "wi": rng.normal(size=(8, 3)),
        "wo": rng.normal(size=(8, 3)),
        "mu": np.linspace(0.1, 1, 4),
        "t": [1.0, 0.0, 0.0],
    }
    for page in sorted((docs / "models").glob("*.md")):
        text = page.read_text(encoding="utf-8")
        for block in re.findall(r"```python\n(.*?)```", text, re.S):
            exec(compile(block, str(page), "exec"), dict(scope))
        for block in re.findall(r"```sh\n(.*?)```", text, re.S):
            for line in block.strip().splitlines():
                args = shlex.split(line)[1:]
                if args[0] == "plot-lobe":
                    args[args.index("-o") + 1] = str(tmp_path / "lobe.png")
                assert cli_main(args) == 0, line


@pytest.mark.parametrize("page", ["normalization.md", "dask.md"])
def test_the_examples_in_the_guides_run_and_print_what_they_show(page, capsys):
    if page == "dask.md":
        pytest.importorskip("dask.array")
    text = (ROOT / "docs" / page).read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks
    for block in blocks:
        exec(compile(block, page, "exec"), {})
        # Every line the code prints is shown in the block as a "# <line>" comment.
        shown = {line[2:] for line in block.splitlines() if line.startswith("# ")}
        for line in capsys.readouterr().out.splitlines():
            assert line in shown, f"{page} prints {line!r} but does not show it"


def test_the_committed_docs_match_a_fresh_run(docs):
    committed = ROOT / "docs"
    for page in ["index.md", "conventions.md", *(f"models/{m}.md" for m in brdf_rs.models())]:
        assert (committed / page).read_text(encoding="utf-8") == (docs / page).read_text(
            encoding="utf-8"
        ), f"docs/{page} is stale: run python scripts/make_docs.py"
    for name, spec in brdf_rs.models().items():
        reflects = not spec["transmission"]
        kinds: tuple[str, ...] = ("lobe", "sphere")
        kinds += ("albedo",) if spec["family"] == "A" and reflects else ()
        for kind in kinds:
            assert (committed / "models" / "img" / f"{name}_{kind}.png").exists()


def test_committed_docs_stay_small():
    size = sum(f.stat().st_size for f in (ROOT / "docs").rglob("*") if f.is_file())
    assert size < 5e6
