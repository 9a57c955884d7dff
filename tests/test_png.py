"""PNG files through pypng (the png extra): what the package writes read back by an
independent decoder (Pillow) and by pypng itself, text chunks included; the error
without pypng names the extra; the 16-bit table preview's scale chunk read back to recover
the table's values; example scenes rendered by name."""

from __future__ import annotations

import io
import json
import sys

import brdf_rs
import numpy as np
import pytest
from brdf_rs import _png
from brdf_rs.cli import main as cli_main

png = pytest.importorskip("png")  # pypng: the png extra
PIL = pytest.importorskip("PIL.Image")  # an independent decoder


def _pypng_pixels(data: bytes) -> np.ndarray:
    width, height, rows, info = png.Reader(bytes=data).asDirect()
    return np.array([list(r) for r in rows]).reshape(height, width, info["planes"])


@pytest.mark.parametrize(
    ("dtype", "shape"),
    [(np.uint8, (37, 53, 3)), (np.uint16, (20, 31, 3)), (np.uint8, (9, 7)), (np.uint16, (5, 6, 4))],
)
def test_encode_round_trips_with_text_and_pillow_agrees(dtype, shape):
    rng = np.random.default_rng(7)
    pixels = rng.integers(0, np.iinfo(dtype).max + 1, size=shape, dtype=dtype)
    data = _png.encode(pixels, {"key": "value", "brdf-rs:scale": '{"min": 0.0}'})
    back, text = _png.decode(data)
    expected = pixels.reshape(shape[0], shape[1], -1)
    np.testing.assert_array_equal(back, expected)
    assert back.dtype == dtype
    assert text == {"key": "value", "brdf-rs:scale": '{"min": 0.0}'}
    kinds = [kind for kind, _ in png.Reader(bytes=data).chunks()]
    assert kinds.index(b"tEXt") < kinds.index(b"IDAT")  # text before the image data
    if dtype == np.uint8 and len(shape) == 3:  # Pillow reads 8-bit RGB as it is
        with PIL.open(io.BytesIO(data)) as decoded:
            np.testing.assert_array_equal(np.asarray(decoded), pixels)
            assert decoded.text["key"] == "value"


def test_decode_refuses_damaged_files(tmp_path):
    data = bytearray(_png.encode(np.zeros((4, 4, 3), dtype=np.uint8)))
    data[40] ^= 0xFF  # inside IHDR's body or CRC
    with pytest.raises(ValueError, match="damaged PNG file"):
        _png.decode(bytes(data))
    with pytest.raises(ValueError, match="not a PNG file"):
        _png.decode(b"GIF89a")
    path = tmp_path / "cut.png"
    path.write_bytes(_png.encode(np.zeros((4, 4, 3), dtype=np.uint8))[:-20])
    with pytest.raises(ValueError, match=rf"^{path}: damaged PNG file"):
        _png.read(path)


def test_without_pypng_the_error_names_the_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "png", None)  # import png then raises ImportError
    image = np.zeros((2, 2, 3), dtype=np.float32)
    with pytest.raises(
        ImportError, match=r"^saving a PNG needs pypng: pip install 'brdf-rs\[png\]'$"
    ):
        brdf_rs.save_image(tmp_path / "a.png", image)
    with pytest.raises(ImportError, match=r"pip install 'brdf-rs\[png\]'"):
        brdf_rs.encode_png(image)
    with pytest.raises(ImportError, match=r"pip install 'brdf-rs\[png\]'"):
        _table(np.ones((2, 3, 3))).save(tmp_path / "t.png")
    (tmp_path / "x.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    with pytest.raises(
        ImportError, match=r"^reading a PNG needs pypng: pip install 'brdf-rs\[png\]'$"
    ):
        brdf_rs.TablePreview.load(tmp_path / "x.png")
    assert list(tmp_path.iterdir()) == [tmp_path / "x.png"]


def test_save_image_png_is_encode_png_and_pillow_reads_it(tmp_path):
    image = np.random.default_rng(1).random((12, 17, 3)).astype(np.float32)
    path = brdf_rs.save_image(tmp_path / "a.png", image)
    data = brdf_rs.encode_png(image)
    assert path.read_bytes() == data
    srgb = brdf_rs._brdf_rs.encode_srgb8(image)
    with PIL.open(io.BytesIO(data)) as decoded:
        np.testing.assert_array_equal(np.asarray(decoded), srgb)
    with pytest.raises(ValueError, match=r"^image: expected shape \(height, width, 3\)"):
        brdf_rs.encode_png(np.zeros((4, 4)))


# ---------------------------------------------------------------- table previews


def _table(value: np.ndarray) -> brdf_rs.Table:
    rows, cols = value.shape[:2]
    axes = {"mu": np.linspace(0.1, 1, rows), "p": np.geomspace(1, 1e3, cols)}
    meta = {"model": "normalized_phong", "axis_names": ["mu", "p"], "quantity": "test"}
    samples = np.zeros((rows, cols), dtype=np.int64)
    return brdf_rs.Table(value, np.full_like(value, 1e-3), samples, axes, meta)


@pytest.mark.parametrize("low", [0.0, -0.25], ids=["non-negative", "negative"])
def test_table_png_records_its_scale_and_the_values_come_back(tmp_path, low):
    rng = np.random.default_rng(11)
    value = low + rng.random((5, 7, 3)) * 1.7
    table = _table(value)
    path = table.save(tmp_path / "t.png")

    # With an independent reader: the pixels and the text chunks, as the docstring says.
    reader = png.Reader(filename=str(path))
    text = {}
    for kind, body in reader.chunks():
        if kind == b"tEXt":
            key, _, val = body.partition(b"\0")
            text[key.decode("latin-1")] = val.decode("latin-1")
    scale = json.loads(text["brdf-rs:scale"])
    assert scale["min"] == min(0.0, value.min()) and scale["max"] == value.max()
    axes = json.loads(text["brdf-rs:axes"])
    assert axes["rows"]["name"] == "mu" and axes["columns"]["name"] == "p"
    np.testing.assert_array_equal(axes["columns"]["values"], table.axes["p"])
    assert json.loads(text["brdf-rs:meta"])["model"] == "normalized_phong"
    pixels = _pypng_pixels(path.read_bytes())
    assert pixels.max() == 65535
    recovered = scale["min"] + (scale["max"] - scale["min"]) * pixels / 65535
    step = (scale["max"] - scale["min"]) / 65535
    assert np.max(np.abs(recovered - value)) <= step / 2 * (1 + 1e-9)

    preview = brdf_rs.TablePreview.load(path)
    assert preview.step == step and preview.meta["model"] == "normalized_phong"
    np.testing.assert_array_equal(preview.value, recovered)
    assert list(preview.axes) == ["mu", "p"]
    np.testing.assert_array_equal(preview.axes["mu"], table.axes["mu"])


def test_table_preview_of_a_real_table(tmp_path):
    table = brdf_rs.albedo_table(
        "normalized_phong", {"mu": [0.2, 0.6, 1.0], "p": [5.0, 50.0]}, kd=0, ks=1, samples=64
    )
    preview = brdf_rs.TablePreview.load(table.save(tmp_path / "t.png"))
    assert preview.step == pytest.approx(table.value.max() / 65535)
    assert np.max(np.abs(preview.value - table.value)) <= preview.step / 2 * (1 + 1e-9)


def test_table_preview_load_names_the_file_and_the_problem(tmp_path):
    image = brdf_rs.save_image(tmp_path / "image.png", np.zeros((2, 2, 3)))
    with pytest.raises(
        brdf_rs.TableFileError, match=rf"^{image}: not a table preview: no 'brdf-rs:scale'"
    ):
        brdf_rs.TablePreview.load(image)
    other = tmp_path / "t.npz"
    other.write_bytes(b"PK\x03\x04 not a png")
    with pytest.raises(brdf_rs.TableFileError, match=rf"^{other}: not a table preview: not a PNG"):
        brdf_rs.TablePreview.load(other)


# --------------------------------------------------------------- example scenes


def test_example_scenes_ship_in_the_package_and_render_by_name(tmp_path, monkeypatch):
    examples = brdf_rs.example_scenes()
    assert set(examples) == {"gallery", "hdr", "rtr_fig_7_38", "sheen"}
    package = __import__("pathlib").Path(brdf_rs.__file__).parent
    assert all(p.parent == package / "example_scenes" for p in examples.values())
    monkeypatch.chdir(tmp_path)  # no file of that name here: the name means the example
    assert brdf_rs.load_scene("hdr").camera == brdf_rs.load_scene(examples["hdr"]).camera
    assert cli_main(["render", "gallery", "--resolution", "32x16", "-q", "-o", "g.png"]) == 0
    pixels, _ = _png.read(tmp_path / "g.png")
    assert pixels.shape == (16, 32, 3) and pixels.max() > 0
    # A file in the way wins over the example of the same name.
    (tmp_path / "hdr").write_text("not toml [")
    with pytest.raises(brdf_rs.SceneError, match=r"^hdr: not valid TOML"):
        brdf_rs.load_scene("hdr")


def test_a_misspelt_example_name_lists_the_examples():
    with pytest.raises(
        brdf_rs.SceneError,
        match=r"^galery: cannot read the scene: .*\(nor an example scene: gallery, hdr,"
        r" rtr_fig_7_38, sheen\); did you mean 'gallery'\?$",
    ):
        brdf_rs.load_scene("galery")
