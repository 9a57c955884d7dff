"""The cloth channel of the split-sum table: ``dfg_table(..., sheen=MODEL)``.

The third channel holds the directional albedo of a sheen model with unit colour and no
diffuse term, at the table's own ``alpha`` (Filament's cloth DG term). It must be that
albedo bit for bit, agree with an independent quadrature, leave the split-sum channels
untouched, and go through the files, the plots and the command line.
"""

from __future__ import annotations

import json
import subprocess
import sys

import brdf_rs
import numpy as np
import pytest

SHEEN = "charlie_sheen_neubelt"
MU = [0.05, 0.3, 0.7, 1.0]
ALPHA = [0.05, 0.25, 0.6, 1.0]


@pytest.fixture(scope="module")
def tables():
    on = brdf_rs.dfg_table("ggx", MU, ALPHA, samples=1024, seed=7, sheen=SHEEN)
    off = brdf_rs.dfg_table("ggx", MU, ALPHA, samples=1024, seed=7)
    return on, off


def test_cloth_channel_is_the_sheen_albedo_table_bit_for_bit(tables):
    on, _ = tables
    ref = brdf_rs.albedo_table(SHEEN, {"mu": MU, "alpha": ALPHA}, kd=0, ks=1, samples=1024, seed=7)
    np.testing.assert_array_equal(on.value[..., 2], ref.value[..., 0])
    np.testing.assert_array_equal(on.stderr[..., 2], ref.stderr[..., 0])
    assert on.meta["sheen"] == SHEEN
    assert "channel 2 = cloth DG" in on.meta["quantity"]
    assert "alpha = the alpha axis value" in on.meta["quantity"]


def test_the_switch_off_leaves_the_split_sum_table_as_it_was(tables):
    on, off = tables
    assert np.all(off.value[..., 2] == 0) and np.all(off.stderr[..., 2] == 0)
    assert "sheen" not in off.meta and "cloth" not in off.meta["quantity"]
    np.testing.assert_array_equal(on.value[..., :2], off.value[..., :2])
    np.testing.assert_array_equal(on.stderr[..., :2], off.stderr[..., :2])
    explicit = brdf_rs.dfg_table("ggx", MU, ALPHA, samples=1024, seed=7, sheen=None)
    np.testing.assert_array_equal(explicit.value, off.value)
    np.testing.assert_array_equal(explicit.samples, off.samples)
    assert explicit.meta == off.meta
    # Both tables drew the split-sum cells; the cloth channel adds its own.
    assert np.all(on.samples > off.samples)


def _sheen_albedo(model: str, mu_i: float, alpha: float, n: int) -> float:
    """The directional albedo (kd = 0, ks = 1) ``∫ f·mu_o dωo`` of a sheen model by a
    product Gauss-Legendre rule in (mu_o, φ), from the published formulas, not brdf_rs:
    ``charlie_sheen`` (Estevez & Kulla's D and their fitted Smith Λ),
    ``charlie_sheen_neubelt`` (that D with Neubelt & Pettineo's V) or ``ashikhmin_cloth``
    (Ashikhmin's D with that V)."""
    x, w = np.polynomial.legendre.leggauss(n)
    mu_o, w_mu = 0.5 * (x + 1), 0.5 * w
    phi, w_phi = 0.5 * np.pi * (x + 1), 0.5 * np.pi * w  # φ in [0, π], doubled below
    m, p = np.meshgrid(mu_o, phi, indexing="ij")
    s_i, s_o = np.sqrt(1 - mu_i**2), np.sqrt(1 - m**2)
    h = np.stack([s_i + s_o * np.cos(p), s_o * np.sin(p), mu_i + m])
    cos_h2 = h[2] ** 2 / np.sum(h**2, axis=0)
    sin_h2 = np.clip(1 - cos_h2, 1e-300, None)
    visibility = 1 / (4 * (mu_i + m - mu_i * m))
    if model == "charlie_sheen_neubelt":
        lobe = (2 + 1 / alpha) * sin_h2 ** (0.5 / alpha) / (2 * np.pi) * visibility
    elif model == "charlie_sheen":
        t = (1 - alpha) ** 2
        at_1 = np.array([21.5473, 3.82987, 0.19823, -1.97760, -4.32054])
        at_0 = np.array([25.3245, 3.32435, 0.16801, -1.27393, -4.85967])
        a, b, c, d, e = (1 - t) * at_1 + t * at_0

        def fit(x):
            return a / (1 + b * x**c) + d * x + e

        def lam(mu):
            return np.where(
                mu < 0.5,
                np.exp(fit(np.minimum(mu, 0.5))),
                np.exp(2 * fit(0.5) - fit(1 - np.maximum(mu, 0.5))),
            )

        dist = (2 + 1 / alpha) * sin_h2 ** (0.5 / alpha) / (2 * np.pi)
        lobe = dist / (4 * mu_i * m * (1 + lam(mu_i) + lam(m)))
    else:
        x2 = cos_h2 / (alpha**2 * sin_h2)
        dist = (1 + 4 * np.exp(-np.minimum(x2, 700)) / sin_h2**2) / (np.pi * (1 + 4 * alpha**2))
        lobe = dist * visibility
    return float(2 * np.einsum("i,j,ij->", w_mu, w_phi, lobe * m))


@pytest.mark.parametrize(("mu", "alpha"), [(0.3, 0.25), (0.7, 0.6), (1.0, 1.0), (0.3, 1.0)])
def test_cloth_channel_matches_an_independent_quadrature(mu, alpha):
    exact = _sheen_albedo(SHEEN, mu, alpha, 200)
    # converged far below the tolerance (alpha = 1 has a square-root kink at wo = n)
    assert abs(exact - _sheen_albedo(SHEEN, mu, alpha, 100)) < 1e-6
    table = brdf_rs.dfg_table("ggx", [mu], [alpha], tol=2e-4, sheen=SHEEN)
    got, se = table.value[0, 0, 2], table.stderr[0, 0, 2]
    assert 0 < se <= 2e-4
    assert abs(got - exact) <= 5 * se, (got, exact, se)


@pytest.mark.parametrize(
    ("model", "mu", "alpha"),
    [("charlie_sheen", 0.3, 0.5), ("charlie_sheen", 0.8, 1.0), ("ashikhmin_cloth", 0.5, 0.5)],
)
def test_other_sheen_albedos_match_an_independent_quadrature(model, mu, alpha):
    exact = _sheen_albedo(model, mu, alpha, 200)
    assert abs(exact - _sheen_albedo(model, mu, alpha, 100)) < 1e-6
    r = brdf_rs.albedo(model, mu, alpha=alpha, kd=0, ks=1, tol=2e-4)
    got, se = float(r.value[0]), float(r.stderr[0])
    assert 0 < se <= 2e-4
    assert abs(got - exact) <= 5 * se, (got, exact, se)


def test_sheen_energy_tables_refuse_the_microfacet_completion():
    e = brdf_rs.energy_compensation_table("charlie_sheen", [0.5, 1.0], [0.5], samples=256)
    assert e.e.shape == (2, 1) and np.all(e.e > 0)
    with pytest.raises(ValueError, match=r"^multiple_scattering: .* charlie_sheen has none"):
        e.multiple_scattering(0, 1, 0)


def test_filament_rows_are_squared_perceptual_roughness():
    # Filament's rows sit at perceptual roughness rho and evaluate alpha = rho**2: a table
    # on the alpha axis rho**2 holds, at each rho, the cloth albedo at alpha = rho**2.
    rho = np.array([0.5, 0.9])
    table = brdf_rs.dfg_table("beckmann", [0.5], rho**2, samples=256, sheen=SHEEN)
    ref = brdf_rs.albedo(SHEEN, [[0.5]], alpha=[rho**2], kd=0, ks=1, samples=256)
    np.testing.assert_array_equal(table.value[..., 2], ref.value[..., 0])
    np.testing.assert_array_equal(table.axes["alpha"], rho**2)


def test_other_sheen_models_fill_the_channel_too():
    for sheen in ("charlie_sheen", "ashikhmin_cloth"):
        t = brdf_rs.dfg_table("ggx", [0.5], [0.5], samples=256, sheen=sheen)
        ref = brdf_rs.albedo(sheen, 0.5, alpha=0.5, kd=0, ks=1, samples=256)
        assert t.value[0, 0, 2] == ref.value[0] and t.meta["sheen"] == sheen


@pytest.mark.parametrize(
    ("model", "roughness", "sheen", "error", "pattern"),
    [
        ("ggx", [0.5], 3, TypeError, r"^sheen: expected a model name"),
        ("ggx", [0.5], "velvet", ValueError, r"^sheen: unknown model 'velvet'"),
        ("ggx", [0.5], "lambert", ValueError, r"^sheen: lambert cannot fill the cloth channel"),
        (
            "blinn_phong_fresnel",
            [10.0],
            SHEEN,
            ValueError,
            r"^sheen: charlie_sheen_neubelt cannot fill .* a blinn_phong_fresnel table: .* p$",
        ),
        (
            "ggx",
            [0.5, 1e-4],
            SHEEN,
            ValueError,
            r"^roughness\[1\]: alpha = 0.0001 is out of range for sheen='charlie_sheen_neubelt'",
        ),
    ],
)
def test_bad_sheen_errors_name_the_argument(model, roughness, sheen, error, pattern):
    with pytest.raises(error, match=pattern):
        brdf_rs.dfg_table(model, [0.5], roughness, samples=64, sheen=sheen)


def test_files_keep_the_cloth_channel_and_its_name(tables, tmp_path):
    on, _ = tables
    back = brdf_rs.Table.load(on.save(tmp_path / "d.npz"))
    np.testing.assert_array_equal(back.value, on.value)
    np.testing.assert_array_equal(back.stderr, on.stderr)
    assert back.meta["sheen"] == SHEEN
    preview = brdf_rs.TablePreview.load(on.save(tmp_path / "d.png"))
    assert preview.meta["sheen"] == SHEEN


def test_plot_and_display_show_the_cloth_channel(tables, tmp_path):
    pytest.importorskip("matplotlib")
    from brdf_rs import _display, plot

    on, off = tables
    fig = plot.table_heatmap(on, path=tmp_path / "d.png", dpi=40)
    titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
    assert titles == ["ggx scale A", "ggx bias B", f"ggx cloth ({SHEEN})"]
    fig = plot.table_heatmap(off, dpi=40)
    assert [ax.get_title() for ax in fig.axes if ax.get_title()] == ["ggx scale A", "ggx bias B"]
    assert _display.channel_names(on.meta)[2] == f"cloth ({SHEEN})"
    assert _display.channel_names(off.meta)[2] == "unused (0)"
    assert on._repr_png_() is not None


def _run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "brdf_rs", *args], capture_output=True, text=True, check=False
    )


def test_cli_sheen_writes_the_same_table(tmp_path):
    out = tmp_path / "d.npz"
    args = ["dfg", "ggx", "--mu", "0.3,0.9", "--roughness", "0.2,0.7", "--samples", "512"]
    result = _run(*args, "--sheen", "-o", str(out), "--json", "-q")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    table = brdf_rs.Table.load(out)
    lib = brdf_rs.dfg_table("ggx", [0.3, 0.9], [0.2, 0.7], samples=512, sheen=SHEEN)
    np.testing.assert_array_equal(table.value, lib.value)
    assert summary["channels"] == ["scale A", "bias B", "cloth"]
    assert summary["sheen"] == SHEEN
    assert summary["cloth_range"] == [
        float(lib.value[..., 2].min()),
        float(lib.value[..., 2].max()),
    ]
    assert summary["max_stderr"] == float(lib.stderr.max())

    named = _run(*args, "--sheen", "ashikhmin_cloth", "-o", str(tmp_path / "a.npz"), "-q")
    assert named.returncode == 0, named.stderr
    assert "cloth (ashikhmin_cloth) in [" in named.stdout
    assert brdf_rs.Table.load(tmp_path / "a.npz").meta["sheen"] == "ashikhmin_cloth"

    plain = _run(*args, "-o", str(tmp_path / "p.npz"), "--json", "-q")
    assert json.loads(plain.stdout)["channels"] == ["scale A", "bias B", "zero"]
    assert "sheen" not in brdf_rs.Table.load(tmp_path / "p.npz").meta


def test_cli_sheen_help_and_errors(tmp_path):
    help_text = _run("dfg", "--help").stdout
    assert "--sheen [MODEL]" in help_text and SHEEN in help_text
    bad = _run(
        "dfg", "blinn_phong_fresnel", "--mu", "0.5", "--sheen", "-q", "-o", str(tmp_path / "b.npz")
    )
    assert bad.returncode == 2
    assert bad.stderr.strip().splitlines() == [
        "brdf-rs dfg: sheen: charlie_sheen_neubelt cannot fill the cloth channel of a"
        " blinn_phong_fresnel table: it needs a family-A model with a colour ks and the"
        " table's roughness p"
    ]
    assert list(tmp_path.iterdir()) == []
