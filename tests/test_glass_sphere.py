"""plot.render_glass_sphere: the path-traced picture of a transmitting model, checked
against what its geometry and the model's energy balance say it must show."""

from __future__ import annotations

import brdf_rs
import numpy as np
import pytest
from brdf_rs import plot

SIZE = 24


def backdrop(size: int, samples: int, seed: int) -> np.ndarray:
    """The image with no sphere at all: the camera rays' floor and sky, drawn from the
    same jitter stream as render_glass_sphere's."""
    rng = np.random.default_rng([seed, 0])
    total = np.zeros((size * size, 3))
    for _ in range(samples):
        o, d = plot._glass_camera(size, rng)
        total += plot._backdrop(o, d, False)
    return (total / samples).reshape(size, size, 3)


class Corner:
    """A stand-in for the camera's jitter generator: every pixel's ray through the same
    corner of the pixel."""

    def __init__(self, x: float, y: float) -> None:
        self.xy = (x, y)

    def random(self, shape: tuple[int, int]) -> np.ndarray:
        return np.broadcast_to(self.xy, shape)


def sphere_pixels(size: int) -> np.ndarray:
    """Pixels inside the sphere's outline: the rays through their four corners meet it
    (the outline is convex, so every ray through the pixel does)."""
    covered = np.ones(size * size, bool)
    for x in (0.0, 1.0):
        for y in (0.0, 1.0):
            o, d = plot._glass_camera(size, Corner(x, y))
            covered &= np.isfinite(plot._sphere_hit(o, d))
    return covered.reshape(size, size)


@pytest.mark.parametrize("model", ["ggx_dielectric", "beckmann_dielectric", "ggx_dielectric_ms"])
def test_without_an_interface_the_sphere_is_invisible(model):
    # eta = 1: no reflection, the light goes straight through (a delta of weight kt = 1):
    # every path crosses the sphere undeviated and the picture is the backdrop alone.
    image = plot.render_glass_sphere(
        model, size=SIZE, samples=2, seed=3, tonemap="none", eta=1.0, alpha=0.3
    )
    np.testing.assert_allclose(image, backdrop(SIZE, 2, 3), rtol=1e-5, atol=1e-6)
    assert sphere_pixels(SIZE).sum() > 50


def test_a_black_interface_is_a_black_disc():
    image = plot.render_glass_sphere(
        "ggx_dielectric", size=SIZE, samples=2, seed=1, tonemap="none", ks=0.0, kt=0.0
    )
    inside = sphere_pixels(SIZE)
    assert np.all(image[inside] == 0)
    expected = backdrop(SIZE, 2, 1)
    clear = np.zeros((SIZE, SIZE), bool)
    clear[:, :3] = True  # the left columns: far from the sphere
    np.testing.assert_allclose(image[clear], expected[clear], rtol=1e-6)


def test_white_furnace_shows_the_energy_single_scattering_loses():
    # In a uniform white environment an interface that keeps all the energy disappears:
    # the compensated model's sphere has radiance 1 within its furnace error and the
    # noise, the single-scattering one is visibly darker at alpha = 1.
    # Each pixel's mean over its paths is independent of the others': the spread of the
    # pixels gives the standard error of their mean.
    inside = sphere_pixels(SIZE)
    kwargs = dict(size=SIZE, samples=64, bounces=48, furnace=True, tonemap="none", alpha=1.0)
    compensated = plot.render_glass_sphere("ggx_dielectric_ms", **kwargs)
    disc = compensated[inside][:, 0]
    stderr = disc.std() / np.sqrt(disc.size)
    assert abs(disc.mean() - 1) < 0.01 + 4 * stderr, (disc.mean(), stderr)
    # Single scattering loses a quarter of the energy or more at each of the two or more
    # crossings at alpha = 1.
    single = plot.render_glass_sphere("ggx_dielectric", **kwargs)[inside]
    assert single.mean() < 0.6, single.mean()
    # The environment itself is 1 around the sphere (the top row misses it).
    assert np.all(compensated[0] == 1)


def test_same_seed_same_bits_and_the_seed_matters():
    a = plot.render_glass_sphere("ggx_dielectric", size=16, samples=2, seed=5)
    b = plot.render_glass_sphere("ggx_dielectric", size=16, samples=2, seed=5)
    c = plot.render_glass_sphere("ggx_dielectric", size=16, samples=2, seed=6)
    assert a.dtype == np.float32 and a.shape == (16, 16, 3)
    assert a.tobytes() == b.tobytes()
    assert a.tobytes() != c.tobytes()


def test_bad_arguments_are_refused_by_name():
    with pytest.raises(ValueError, match="does not transmit"):
        plot.render_glass_sphere("lambert")
    with pytest.raises(ValueError, match="model: unknown model"):
        plot.render_glass_sphere("glass")
    with pytest.raises(ValueError, match="eta: expected a scalar"):
        plot.render_glass_sphere("ggx_dielectric", eta=[1.5, 1.4])
    for name in ("size", "samples", "bounces"):
        with pytest.raises(ValueError, match=f"{name}: expected a positive integer"):
            plot.render_glass_sphere("ggx_dielectric", **{name: 0})
    with pytest.raises(ValueError, match="alpha"):
        plot.render_glass_sphere("ggx_dielectric", size=4, samples=1, alpha=-1.0)
    assert "render_glass_sphere" in plot.__all__
    assert brdf_rs.models()["ggx_dielectric"]["transmission"]
