"""How Table, Albedo and Energy show themselves in Jupyter: ``_repr_png_`` gives PNG bytes
of a figure (matplotlib), ``_repr_html_`` names the model and the largest standard error,
and without matplotlib the HTML falls back to a summary table (and no PNG)."""

from __future__ import annotations

import base64
import re
import sys

import brdf_rs
import numpy as np
import pytest
from brdf_rs import _png

pytest.importorskip("matplotlib")


def _objects():
    mu = np.linspace(0.1, 1, 6)
    table2 = brdf_rs.albedo_table(
        "torrance_sparrow", {"mu": mu, "p": np.geomspace(1, 1e4, 5)}, kd=0, ks=1, samples=64
    )
    table1 = brdf_rs.albedo_table(
        "normalized_phong", {"mu": mu}, kd=[0.5, 0.2, 0.1], ks=0.5, p=20, samples=64
    )
    dfg = brdf_rs.dfg_table("ggx", mu=mu, roughness=[0.1, 0.5, 1.0], samples=64)
    albedo = brdf_rs.albedo("ggx", mu, alpha=0.3, samples=64)
    energy = brdf_rs.energy("normalized_blinn_phong", kd=0, ks=1, p=2, samples=256)
    return {
        "table2": (table2, "torrance_sparrow", float(table2.stderr.max())),
        "table1": (table1, "normalized_phong", float(table1.stderr.max())),
        "dfg": (dfg, "ggx", float(dfg.stderr.max())),
        "albedo": (albedo, "ggx", float(albedo.stderr.max())),
        "energy": (energy, "normalized_blinn_phong", float(energy.stderr.max())),
    }


@pytest.fixture(scope="module")
def objects():
    return _objects()


NAMES = ["table2", "table1", "dfg", "albedo", "energy"]


@pytest.mark.parametrize("name", NAMES)
def test_repr_png_is_a_png_figure(objects, name):
    obj, _, _ = objects[name]
    data = obj._repr_png_()
    assert data.startswith(_png.SIGNATURE)
    pixels, text = _png.decode(data)
    assert pixels.shape[0] > 200 and pixels.shape[1] > 300  # a figure, not a thumbnail
    assert "matplotlib" in text.get("Software", "")
    assert len(np.unique(pixels.reshape(-1, pixels.shape[2]), axis=0)) > 20  # not blank


@pytest.mark.parametrize("name", NAMES)
def test_repr_html_names_the_model_and_the_largest_stderr(objects, name):
    obj, model, largest = objects[name]
    page = obj._repr_html_()
    assert f"<code>{model}</code>" in page
    assert f"largest standard error {largest:.3g}" in page
    embedded = re.search(r'src="data:image/png;base64,([^"]+)"', page)
    assert embedded is not None
    assert base64.b64decode(embedded.group(1)) == obj._repr_png_()


def test_the_figures_label_their_axes(objects):
    """The heat map's axes carry the axis names, its colour bar the quantity; the
    curve's x axis is the cosine of incidence."""
    from brdf_rs import _display
    from matplotlib.figure import Figure

    drawn = []
    real = Figure.savefig
    try:
        Figure.savefig = lambda self, *a, **k: (drawn.append(self), real(self, *a, **k))[1]
        _display.table_png(objects["table2"][0])
        _display.energy_png(objects["energy"][0])
    finally:
        Figure.savefig = real
    heat, curve = drawn
    labels = {(ax.get_xlabel(), ax.get_ylabel()) for ax in heat.axes}
    assert ("p", "μ = cos θi") in labels
    assert ("", "directional albedo R(mu)") in labels  # the colour bar
    assert heat.axes[0].get_xscale() == "log"  # p spans four decades
    assert "torrance_sparrow: largest standard error" in heat.texts[0].get_text()
    assert curve.axes[0].get_xlabel() == "μ = cos θi"
    assert curve.axes[0].get_xscale() == "linear"


@pytest.mark.parametrize("name", NAMES)
def test_without_matplotlib_html_falls_back_to_a_table(objects, monkeypatch, name):
    obj, model, largest = objects[name]
    for module in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.setitem(sys.modules, module, None)
    with pytest.raises(ImportError):
        import matplotlib.figure  # noqa: F401
    assert obj._repr_png_() is None  # Jupyter then shows the HTML
    page = obj._repr_html_()
    assert "<img" not in page and "<table>" in page
    assert f"<code>{model}</code>" in page
    assert f"largest standard error {largest:.3g}" in page


def test_a_table_of_three_axes_has_html_but_no_figure():
    value = np.zeros((2, 3, 4, 3))
    axes = {"mu": np.array([0.5, 1.0]), "p": np.arange(3.0), "ks": np.arange(4.0)}
    meta = {"model": "normalized_phong", "axis_names": list(axes)}
    table = brdf_rs.Table(value, value + 0.5, np.zeros(value.shape[:-1], int), axes, meta)
    assert table._repr_png_() is None
    page = table._repr_html_()
    assert "mu[2] × p[3] × ks[4]" in page and "largest standard error 0.5" in page


def test_albedo_records_its_model_and_incidences():
    mu = np.array([0.2, 0.7])
    r = brdf_rs.albedo("ggx", mu[:, None], alpha=[0.1, 0.2, 0.3], samples=16)
    assert r.model == "ggx"
    np.testing.assert_array_equal(r.mu, np.broadcast_to(mu[:, None], (2, 3)))
    assert brdf_rs.energy("lambert", samples=16).model == "lambert"
