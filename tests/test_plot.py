"""brdf_rs.plot: figures saved as valid PNGs of the expected size, drawing the library's
own numbers (the plotted data is compared with eval / albedo_table), and a clear error
when matplotlib is missing."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import brdf_rs
import numpy as np
import pytest

pytest.importorskip("matplotlib")
PIL = pytest.importorskip("PIL.Image")

from brdf_rs import plot  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def png_size(path: Path) -> tuple[int, int]:
    with PIL.open(path) as image:
        assert image.format == "PNG"
        image.load()
        return image.size


def test_polar_lobe_draws_eval_in_the_plane_of_incidence(tmp_path):
    out = tmp_path / "lobe.png"
    fig = plot.polar_lobe("ggx", [30, 60], alpha=0.3, kd=0.1, resolution=181, path=out, dpi=80)
    assert png_size(out) == (round(plot.LOBE_SIZE[0] * 80), round(plot.LOBE_SIZE[1] * 80))
    ax = fig.axes[0]
    curves = [line for line in ax.lines if line.get_label().startswith("θi")]
    assert [c.get_label() for c in curves] == ["θi = 30°", "θi = 60°"]
    theta_o = curves[1].get_xdata()
    assert theta_o.size == 181 and np.all(np.abs(theta_o) < np.pi / 2)
    t = np.radians(60)
    wo = np.stack([np.sin(theta_o), 0 * theta_o, np.cos(theta_o)], axis=-1)
    want = brdf_rs.eval("ggx", [-np.sin(t), 0, np.cos(t)], wo, alpha=0.3, kd=0.1)[:, 0]
    np.testing.assert_array_equal(curves[1].get_ydata(), want)
    # The mirror direction is on the right: the reflected radiance f·cos θo peaks near
    # θo = +θi (f itself peaks at grazing θo for a rough microfacet lobe).
    assert 50 < np.degrees(theta_o[np.argmax(want * np.cos(theta_o))]) < 70


def test_polar_lobe_colours_channels_that_differ_and_takes_a_tangent(tmp_path):
    fig = plot.polar_lobe("kajiya_kay", 45, kd=[0.5, 0.2, 0.1], cosine=True, channel="rgb")
    labels = [line.get_label() for line in fig.axes[0].lines]
    assert [label for label in labels if label.startswith("θi")] == [
        "θi = 45°, R",
        "θi = 45°, G",
        "θi = 45°, B",
    ]


def test_polar_lobe_draws_one_line_per_angle_and_labels_its_axes():
    # A coloured lobe is one curve, its luminance; the radial axis says what and in what
    # unit; the legend sits outside the half disc.
    kd = [0.3, 0.12, 0.05]
    fig = plot.polar_lobe("ggx", [30, 60], kd=kd, ks=0.04, alpha=0.15, resolution=91)
    ax = fig.axes[0]
    curves = [line for line in ax.lines if line.get_label().startswith("θi")]
    assert [c.get_label() for c in curves] == ["θi = 30°", "θi = 60°"]
    theta_o = curves[0].get_xdata()
    wo = np.stack([np.sin(theta_o), 0 * theta_o, np.cos(theta_o)], axis=-1)
    t = np.radians(30)
    rgb = brdf_rs.eval("ggx", [-np.sin(t), 0, np.cos(t)], wo, kd=kd, ks=0.04, alpha=0.15)
    np.testing.assert_allclose(curves[0].get_ydata(), rgb @ [0.2126, 0.7152, 0.0722], rtol=1e-15)
    texts = [t.get_text() for t in ax.texts]
    assert "f, luminance of RGB (1/sr)" in texts
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == [
        "θi = 30°",
        "θi = 60°",
        "light direction",
    ]
    fig.canvas.draw()
    box = legend.get_window_extent()
    disc = ax.get_tightbbox()
    assert box.x0 > disc.x1 - 1  # beside the half disc, not over it
    # A grey lobe is one curve of its value; family B has no unit; channel= picks one.
    fig = plot.polar_lobe("blinn_specular", 45, channel=1, ks=[0.2, 0.5, 0.9])
    assert "s, G (no unit)" in [t.get_text() for t in fig.axes[0].texts]
    with pytest.raises(ValueError, match="channel: expected 0, 1, 2"):
        plot.polar_lobe("ggx", channel="r")


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"theta_i": 95}, "theta_i: expected angles in degrees from 0 to 90"),
        ({"theta_i": []}, "theta_i: expected angles"),
        ({"resolution": 2}, "resolution: expected an integer of at least 3"),
        ({"alpha": -1}, "alpha = -1.0 is out of range"),
    ],
)
def test_polar_lobe_bad_input(kwargs, message):
    with pytest.raises(ValueError, match=message):
        plot.polar_lobe("ggx", **kwargs)


def test_albedo_curves_plot_the_albedo_table_with_bands(tmp_path):
    out = tmp_path / "albedo.png"
    mu = np.linspace(0.1, 1, 5)
    fig = plot.albedo_curves("normalized_phong", "p", [2, 50], mu=mu, kd=0, ks=1, path=out)
    assert png_size(out) == (round(plot.CURVES_SIZE[0] * 100), round(plot.CURVES_SIZE[1] * 100))
    assert fig.axes[0].get_yscale() == "linear"  # 0.6 to 1: no decades
    table = brdf_rs.albedo_table("normalized_phong", {"p": [2, 50], "mu": mu}, kd=0, ks=1)
    lines = [line for line in fig.axes[0].lines if line.get_label().startswith("p =")]
    assert [line.get_label() for line in lines] == ["p = 2", "p = 50"]
    for k, line in enumerate(lines):
        np.testing.assert_array_equal(line.get_xdata(), mu)
        np.testing.assert_array_equal(line.get_ydata(), table.value[k, :, 0])
    with pytest.raises(ValueError, match="param: mu is the curve's x axis"):
        plot.albedo_curves("ggx", "mu", [0.5])


def test_albedo_curves_spanning_decades_get_a_log_axis():
    # Un-normalized Phong: R(0.02) near 20 for p = 2, about 0.03 for p = 200.
    fig = plot.albedo_curves("phong", "p", [2, 200], mu=[0.02, 0.5, 1], samples=256)
    ax = fig.axes[0]
    assert ax.get_yscale() == "log" and ax.get_ylabel().endswith(", log")
    assert ax.get_legend() is not None and ax.get_legend().get_bbox_to_anchor().x0 > 0


def test_table_heatmap_panels_and_sizes(tmp_path):
    mu = (np.arange(6) + 0.5) / 6
    albedo = brdf_rs.albedo_table(
        "torrance_sparrow", {"mu": mu, "p": np.geomspace(1, 1e3, 5)}, kd=0, samples=256
    )
    fig = plot.table_heatmap(albedo, path=tmp_path / "a.png", dpi=50)
    assert png_size(tmp_path / "a.png") == (round(4.8 * 50), round(3.8 * 50))
    panel = [ax for ax in fig.axes if ax.get_title()]
    assert len(panel) == 1 and panel[0].get_yscale() == "log"  # p is geometric
    mesh = panel[0].collections[0]
    np.testing.assert_array_equal(
        np.asarray(mesh.get_array()).ravel(), albedo.value[:, :, 0].T.ravel()
    )

    dfg = brdf_rs.dfg_table("ggx", mu, [0.2, 0.5, 0.9], samples=256)
    fig = plot.table_heatmap(dfg, path=tmp_path / "d.png", dpi=50)
    assert png_size(tmp_path / "d.png") == (round(9.6 * 50), round(3.8 * 50))
    bars = [ax.get_ylabel() for ax in fig.axes if not ax.get_title()]
    assert bars == ["scale A", "bias B"]  # the colour bars say what they show
    assert [ax.get_title() for ax in fig.axes if ax.get_title()] == ["ggx scale A", "ggx bias B"]

    one_d = brdf_rs.albedo_table("lambert", {"mu": mu}, kd=[0.2, 0.5, 0.8], samples=64)
    fig = plot.table_heatmap(one_d, channel=2)
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_ydata(), one_d.value[:, 2])

    three_d = brdf_rs.albedo_table("ggx", {"mu": [0.5], "alpha": [0.5], "kd": [0.1]}, samples=64)
    with pytest.raises(ValueError, match="this one has 3 axes"):
        plot.table_heatmap(three_d)
    with pytest.raises(ValueError, match="give channel= to draw one"):
        plot.table_heatmap(dfg, ax=fig.axes[0])
    with pytest.raises(TypeError, match=r"expected a brdf_rs\.Table"):
        plot.table_heatmap(albedo.value)


def test_energy_compensation_figure(tmp_path):
    result = brdf_rs.energy_compensation_table("ggx", [0.25, 0.75], [0.2, 0.6], tol=1e-3)
    fig = plot.energy_compensation(result, path=tmp_path / "e.png", dpi=50)
    assert png_size(tmp_path / "e.png") == (round(10.0 * 50), round(3.8 * 50))
    curve = next(line for line in fig.axes[1].lines if line.get_label() == "E_avg(α)")
    np.testing.assert_array_equal(curve.get_ydata(), result.e_avg)
    assert fig.axes[0].get_xlabel() == "μ = cos θi"


def test_energy_compensation_figure_of_a_view_albedo_says_mu_is_the_views():
    """A lobe whose E is the albedo seen from the view (not reciprocal) labels μ as the
    view's cosine."""
    views = [m for m, s in brdf_rs.models().items() if s["view_albedo_closed_form"]]
    assert views
    result = brdf_rs.energy_compensation_table(views[0], [0.25, 0.75], [0.2, 0.6])
    fig = plot.energy_compensation(result, dpi=50)
    assert fig.axes[0].get_xlabel() == "μ = cos θo (view)"


def test_lut_texels_draws_the_decoded_texels_at_their_sample_positions(tmp_path):
    """Each panel holds one channel's decoded texels (row 0 at the bottom), its cells
    centred on the axis' sample positions; a 3-D table shows its first, middle and last
    slices, titled with the slice's index of refraction."""
    from brdf_rs import lut

    axis = lut.parse_axis
    spec = lut.preset(
        "ue5", samples=64, columns=axis("mu:centres:8"), rows=axis("perceptual:ends:5:0:1:0.01")
    )
    table = lut.build(spec)
    fig = plot.lut_texels(table, path=tmp_path / "u.png", dpi=50)
    assert png_size(tmp_path / "u.png")[1] == round(3.4 * 50)
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title() for ax in panels] == list(spec.channel_names)
    for c, ax in enumerate(panels):
        mesh = ax.collections[0]
        np.testing.assert_array_equal(
            np.asarray(mesh.get_array()).reshape(5, 8), table.decoded[:, :, c]
        )
        # Texel centres along n·v: edges at k/8; range ends along r: edges half a step out.
        x0, x1 = ax.get_xlim()
        assert (x0, x1) == pytest.approx((0.0, 1.0))
        assert ax.get_ylim() == pytest.approx((-0.125, 1.125))
    assert panels[0].get_xlabel() == "n·v"

    glass = lut.build(
        lut.preset(
            "cycles_glass",
            samples=16,
            columns=axis("perceptual:ends:4:0:1:0.01"),
            rows=axis("mu:ends:3:0:1:0.01"),
            layers=axis("eta:ends:5:1.1:2"),
        )
    )
    fig = plot.lut_texels(glass, dpi=40)
    titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
    assert titles == [
        f"{c} at η = {eta}" for eta in ("1.1", "1.55", "2") for c in glass.spec.channel_names
    ]
    last = [ax for ax in fig.axes if ax.get_title()][-1]
    np.testing.assert_array_equal(
        np.asarray(last.collections[0].get_array()).reshape(3, 4), glass.decoded[4, :, :, -1]
    )
    with pytest.raises(TypeError, match=r"expected a brdf_rs\.lut\.Lut"):
        plot.lut_texels(table.image)


def test_convergence_from_the_benchmark_json_and_from_a_dict(tmp_path):
    bench = ROOT / "benches" / "results" / "albedo_convergence.json"
    fig = plot.convergence(bench, targets=(1e-3, 1e-4), path=tmp_path / "c.png", dpi=50)
    tables = json.loads(bench.read_text())["results"]
    assert png_size(tmp_path / "c.png") == (round(5.5 * len(tables) * 50), round(4.8 * 50))
    points = [{"seconds": 0.1, "rms": 1e-2}, {"seconds": 0.4, "rms": 5e-3}]
    fig = plot.convergence({"mine": points})
    line = fig.axes[0].lines[0]
    assert line.get_label() == "mine" and list(line.get_ydata()) == [1e-2, 5e-3]
    with pytest.raises(ValueError, match="each point needs 'seconds' and 'rms'"):
        plot.convergence({"mine": [{"time": 1}]})
    with pytest.raises(ValueError, match="results: expected"):
        plot.convergence({})


def test_spheres_side_by_side(tmp_path):
    images = [plot.render_sphere("lambert", size=24), np.zeros((24, 24, 3), np.uint8)]
    plot.spheres(images, ["lambert", "black"], path=tmp_path / "s.png", dpi=50, panel_inches=1)
    assert png_size(tmp_path / "s.png") == (100, round(1.25 * 50))
    with pytest.raises(ValueError, match="labels: expected 2 labels, got 1"):
        plot.spheres(images, ["one"])
    with pytest.raises(ValueError, match=r"images\[0\]: expected an \(H, W, 3\) image"):
        plot.spheres([np.zeros((4, 4))])


def test_render_sphere_is_lit_as_documented():
    # A white Lambert sphere, linear output: at the centre (n = +z) the key light gives
    # n·l = 1.2/|(1, 1, 1.2)| and the 30% fill light 0.5/|(1, 0.3, 0.5)|; intensity π
    # times kd/π. The corners see the background.
    image = plot.render_sphere("lambert", size=33, tonemap="none", kd=1.0)
    assert image.shape == (33, 33, 3) and image.dtype == np.float32
    want = 1.2 / np.sqrt(3.44) + 0.3 * 0.5 / np.sqrt(1.34)
    np.testing.assert_allclose(image[16, 16], want, rtol=1e-6)
    assert np.all(image[0, 0] == 0)
    # The same in family B (lambert_shading includes the cosine; intensity 1), except on
    # the silhouette, where n·v = 0: family A is 0 there (wo not above the surface).
    shading = plot.render_sphere("lambert_shading", size=33, tonemap="none", kd=1.0)
    x = -1.1 + 2.2 * (np.arange(33) + 0.5) / 33
    inside = x[None, :] ** 2 + x[:, None] ** 2 < 0.95
    np.testing.assert_allclose(shading[inside], image[inside], rtol=1e-5, atol=1e-7)
    specular = plot.render_sphere("phong_specular", size=33, tonemap="none", base=0.2)
    assert specular[16, 16, 0] > 0.2 * want  # the grey base is under the highlight term


def test_no_matplotlib_until_a_plot_and_then_no_pyplot():
    code = """
import sys
import brdf_rs.plot
assert "matplotlib" not in sys.modules
brdf_rs.plot.polar_lobe("lambert")
assert "matplotlib" in sys.modules and "matplotlib.pyplot" not in sys.modules
"""
    subprocess.run([sys.executable, "-c", code], check=True)


def test_missing_matplotlib_is_a_clear_import_error():
    code = """
import sys
sys.modules["matplotlib"] = None
import brdf_rs.plot
try:
    brdf_rs.plot.polar_lobe("lambert")
except ImportError as exc:
    print(exc)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == (
        "brdf_rs.plot needs matplotlib: pip install 'brdf-rs[plot]' (or matplotlib>=3.7)"
    )
