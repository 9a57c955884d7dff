"""Energy tables of the rough dielectrics (``brdf_rs.energy_compensation_table`` with an
``eta`` axis): ``E(mu, alpha, eta)`` the total albedo (reflection + transmission) of the
white interface for light from the side ``eta`` says (below 1: from the denser side),
``E_avg(alpha, eta) = 2 ∫ E mu dmu``.

Checked against values the table does not compute itself: the white furnace at small
roughness (nothing is absorbed and the shadowing takes almost nothing: E ≈ 1 on both
sides), direct ``brdf_rs.albedo`` calls with other cell ids and the uniform sampler
(independent streams and a different estimator, within the combined standard errors),
a cubature of the reference kernel over the half vector (no Rust involved), and ``E_avg``
against a composite Simpson rule over a fine column of ``E`` cells.
"""

from __future__ import annotations

import brdf_rs
import numpy as np
import pytest
from brdf_rs import _spec
from test_dielectric import converged_half_vector_albedo

#: The single-scattering interfaces, whose tables measure a loss (``ggx_dielectric_ms``,
#: which restores it, has its table tested in tests/test_dielectric_ms.py).
DIELECTRICS = ("ggx_dielectric", "beckmann_dielectric")
ETAS = np.array([1 / 1.5, 0.9, 1.33, 2.4])


def test_the_transmitting_models_are_the_dielectrics():
    transmitting = {n for n, s in _spec.specs().items() if s["transmission"]}
    assert transmitting == {*DIELECTRICS, "ggx_dielectric_ms"}


@pytest.mark.parametrize("model", DIELECTRICS)
def test_shapes_and_white_furnace_at_small_roughness(model):
    """alpha = 1e-3: E = F + (1 − F) = 1 up to the shadowing of so smooth a surface
    (≲ 1e-5 per the reference's cubature, test_dielectric), from both sides, including
    beyond the critical angle; E_avg likewise. eta = 1 is the exact delta: 1."""
    mu = np.array([0.1, 0.4, 0.7, 1.0])
    alpha = np.array([1e-3, 0.3])
    eta = np.concatenate([ETAS, [1.0]])
    ec = brdf_rs.energy_compensation_table(model, mu, alpha, eta=eta, tol=1e-4)
    assert ec.e.shape == ec.stderr.shape == (4, 2, 5)
    assert ec.e_avg.shape == ec.e_avg_stderr.shape == (2, 5)
    np.testing.assert_array_equal(ec.eta, eta)
    assert np.all(ec.stderr <= 1e-4) and np.all(ec.e_avg_stderr <= 1e-4)
    smooth = ec.e[:, 0, :]
    assert np.all(np.abs(smooth - 1) <= 5 * ec.stderr[:, 0, :] + 2e-5), smooth
    assert np.all(np.abs(ec.e_avg[0] - 1) <= 5 * ec.e_avg_stderr[0] + 2e-5), ec.e_avg
    # No interface: the straight-through delta, exactly 1 with no error, at any roughness.
    np.testing.assert_array_equal(ec.e[..., -1], 1.0)
    np.testing.assert_array_equal(ec.stderr[..., -1], 0.0)
    # Rough: energy lost to the shadowing, more at grazing incidence, never gained.
    rough, se = ec.e[:, 1, :-1], ec.stderr[:, 1, :-1]
    assert np.all(rough[:-1] < 1 - 5 * se[:-1]) and np.all(rough <= 1 + 5 * se), rough
    assert np.all(rough[0] < rough[-1]), rough


@pytest.mark.parametrize("model", DIELECTRICS)
def test_cells_match_direct_albedo_with_other_streams(model):
    """Each cell against brdf_rs.albedo(component="total") at the same (mu, alpha, eta)
    with other cell ids, and against the uniform sampler: within 5 combined sigmas."""
    mu = np.array([0.15, 0.6, 0.95])
    alpha = np.array([0.2, 0.8])
    ec = brdf_rs.energy_compensation_table(model, mu, alpha, eta=ETAS, tol=2e-4)
    m, a, e = np.meshgrid(mu, alpha, ETAS, indexing="ij")
    ids = np.arange(m.size, dtype=np.uint64).reshape(m.shape) + np.uint64(10**6)
    for sampler, kw in (("importance", {"cell_ids": ids, "tol": 2e-4}), ("uniform", {})):
        direct = brdf_rs.albedo(
            model,
            m,
            alpha=a,
            eta=e,
            ks=1,
            kt=1,
            component="total",
            sampler=sampler,
            samples=1 << 14,
            **kw,
        )
        se = np.hypot(ec.stderr, direct.stderr[..., 0])
        diff = np.abs(ec.e - direct.value[..., 0])
        assert np.all(diff <= 5 * se + 1e-12), (sampler, diff.max(), se.max())
        assert np.all(se > 0)


@pytest.mark.parametrize("model", DIELECTRICS)
@pytest.mark.parametrize("eta", [1.5, 1 / 1.5])
def test_cells_match_a_cubature_of_the_reference(model, eta):
    """E against the half-vector cubature of the Python reference (independent of the
    Rust kernels and integrator): E = R + T of the white interface."""
    alpha = 0.5
    ec = brdf_rs.energy_compensation_table(model, [0.35], [alpha], eta=[eta], tol=1e-4)
    (r, t), err = converged_half_vector_albedo(model, 0.35, eta=eta, alpha=alpha, ks=1.0, kt=1.0)
    assert abs(ec.e[0, 0, 0] - (r + t)) <= 5 * ec.stderr[0, 0, 0] + 2 * err + 1e-9


@pytest.mark.parametrize("model", DIELECTRICS)
def test_e_avg_matches_a_separate_quadrature_of_e(model):
    """E_avg (adaptive Gauss-Kronrod on cells of its own) against composite Simpson on
    129 E cells of the table (other nodes, other streams): within 5 sigmas plus Simpson's
    error, taken as its difference from the 65-node rule on the same cells."""
    mu = np.linspace(0.0, 1.0, 129)
    alpha = np.array([0.1, 0.6])
    eta = np.array([1 / 1.5, 1.5])
    ec = brdf_rs.energy_compensation_table(model, mu, alpha, eta=eta, tol=3e-4)

    def simpson(step: int) -> tuple[np.ndarray, np.ndarray]:
        x = mu[::step]
        h = x[1] - x[0]
        w = np.full(x.size, 2.0)
        w[1::2] = 4.0
        w[0] = w[-1] = 1.0
        w *= h / 3
        f = 2 * x[:, None, None] * ec.e[::step]
        s = 2 * x[:, None, None] * ec.stderr[::step]
        return np.einsum("i,ijk->jk", w, f), np.sqrt(np.einsum("i,ijk->jk", w**2, s**2))

    fine, fine_se = simpson(1)
    coarse, _ = simpson(2)
    rule = np.abs(fine - coarse)
    se = np.hypot(fine_se, ec.e_avg_stderr)
    assert np.all(np.abs(ec.e_avg - fine) <= 5 * se + rule + 1e-9), (ec.e_avg, fine, se, rule)
    # Energy is lost at alpha = 0.6 on both sides, none created.
    assert np.all(ec.e_avg[1] < 1 - 5 * ec.e_avg_stderr[1]) and np.all(ec.e_avg > 0)


def test_bitwise_reproducible_and_seeded():
    model = DIELECTRICS[0]
    args = (model, [0.3, 0.9], [0.25, 0.7])
    kw = {"eta": [0.75, 1.45], "samples": 256, "tol": None}
    a = brdf_rs.energy_compensation_table(*args, seed=3, **kw)
    b = brdf_rs.energy_compensation_table(*args, seed=3, **kw)
    c = brdf_rs.energy_compensation_table(*args, seed=4, **kw)
    for name in ("e", "stderr", "e_avg", "e_avg_stderr"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name
    assert not np.array_equal(a.e, c.e)
    # A cell does not depend on the rest of the grid: the same (mu, alpha, eta) at the
    # same flat index gives the same bits (cells are keyed by their index).
    kw["eta"] = [0.75]
    one = brdf_rs.energy_compensation_table(model, [0.3], [0.25], seed=3, **kw)
    assert one.e[0, 0, 0] == a.e[0, 0, 0]


def test_eta_errors():
    model = DIELECTRICS[0]
    with pytest.raises(TypeError, match=r"^eta: energy_compensation_table needs an eta axis"):
        brdf_rs.energy_compensation_table(model, [0.5], [0.5])
    with pytest.raises(TypeError, match=r"^eta: energy_compensation_table takes an eta axis only"):
        brdf_rs.energy_compensation_table("ggx", [0.5], [0.5], eta=[1.5])
    with pytest.raises(ValueError, match=r"^eta\[1\]"):
        brdf_rs.energy_compensation_table(model, [0.5], [0.5], eta=[1.5, -1.0])
    with pytest.raises(ValueError, match=r"^eta: expected a non-empty 1-D"):
        brdf_rs.energy_compensation_table(model, [0.5], [0.5], eta=[])
    for name, value in (("ks", 0.5), ("kt", 0.5), ("component", "reflection")):
        with pytest.raises(TypeError, match=rf"^{name}: energy_compensation_table sets it"):
            brdf_rs.energy_compensation_table(model, [0.5], [0.5], eta=[1.5], **{name: value})
    with pytest.raises(ValueError, match=r"ggx_dielectric"):
        brdf_rs.energy_compensation_table("ward", [0.5], [0.5])


def test_multiple_scattering_refuses_a_dielectric_table():
    ec = brdf_rs.energy_compensation_table(
        DIELECTRICS[0], [0.5], [0.5], eta=[1.5], samples=64, tol=None
    )
    with pytest.raises(ValueError, match=r"^multiple_scattering: .*total albedo"):
        ec.multiple_scattering(0, 0, 0, 0.04)
    pytest.importorskip("matplotlib")
    from brdf_rs import plot

    with pytest.raises(ValueError, match=r"^result: the plot draws E\(mu, alpha\) tables"):
        plot.energy_compensation(ec)
