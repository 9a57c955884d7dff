"""A reusable χ² goodness-of-fit harness for direction samplers (a sampler against its pdf).

In the style of Mitsuba's ``chi2.py`` and pbrt's ``bsdfs_test.cpp``: draw N directions
from a sampler, histogram them on a (θ, φ) grid over the whole sphere, integrate the
claimed density over every cell to get the expected counts, pool the cells whose expected
count is below 5, and compare with Pearson's χ² statistic. Three things differ from the
fixed (cos θ, φ) grid of those tests, so that lobes as narrow as cos^10000 are resolved
and draws lost below the horizon are accounted for:

- **Lobe-aligned frame.** θ and φ are measured about a ``pole`` the caller chooses (the
  lobe's axis: the mirror direction for a Phong lobe, the normal for a cosine warp).
- **Adaptive θ bands, chosen without looking at the tested sample.** The θ band edges are
  quantiles of θ over an independent *pilot* sample (its own stream of random numbers),
  ``n_theta`` bands of equal pilot mass, followed by bands that double in θ up to π so the
  whole sphere is covered, plus an edge at π/2. Because the grid depends on the pilot
  only, the tested counts are exactly multinomial on a fixed partition and the usual χ²
  theory applies. φ is cut into ``n_phi`` equal bins over [0, 2π).
- **Mass outside the histogram.** Draws the sampler reports as invalid (e.g. below the
  surface, weight 0) are one more cell, with expected count ``N·(1 − ∫ pdf dω)`` where the
  integral runs over the whole sphere (the density of a mixture over the sphere of
  directions counts the lost mass by leaving it out).

Expected counts are ``N·∫_cell pdf dω`` in the same (θ, φ) parametrization,
``dω = sin θ dθ dφ``, by a tensor Gauss-Legendre rule per cell (all nodes of all cells in
one vectorized ``pdf`` call). If the caller gives the surface ``normal`` (the pdf is then
promised to vanish where ``d·normal ≤ 0``), the θ range of every φ node is clipped at the
horizon ``θ_h(φ)``, and the φ range is split where θ_h(φ) crosses the cell's θ edges, so
neither the density's jump at the horizon nor the kink it leaves ever sits inside a
Gauss-Legendre panel. The rule is adaptive: each piece is compared with the sum of its
four quarters and split again where they differ by more than a small fraction of the
Poisson noise of the cell's count (``qtol·sqrt(E)``), so quadrature error is negligible
against sampling noise.

The verdict combines three tests by Bonferroni (``p = min(1, 3·min(p₁, p₂, p₃))``):

1. Pearson's χ² over the histogram cells and the invalid cell. Cells with expected count
   < ``min_expected`` are pooled (smallest first) into one cell; if the pool stays below
   ``min_expected`` it is merged into the smallest regular cell. ``dof = cells − 1``.
   Cells with expected count < ``zero_expected`` (~0) are left to test 3.
2. The valid mass: the number of valid draws is Binomial(N, ∫ pdf dω); a two-sided exact
   binomial test (widened by the quadrature error). A global normalization error of
   1e-4 is a 10σ effect here but drowns among ~1600 χ² cells. A density that integrates
   to more than one fails outright.
3. Draws in cells the density calls (next to) impossible: the Poisson probability of at
   least that many there (Mitsuba fails such a test outright).

Multiple testing: :func:`sidak_alpha` gives the per-test level ``1 − (1 − α)^(1/K)`` for a
family of K tests with family-wise error rate α.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
from scipy import stats

__all__ = [
    "Chi2Result",
    "Frame",
    "adaptive_theta_edges",
    "chi2_test",
    "integrate_cells",
    "integrate_sphere",
    "sidak_alpha",
]

SampleFn = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
PdfFn = Callable[[np.ndarray], np.ndarray]

TWO_PI = 2.0 * math.pi


def sidak_alpha(alpha: float, k: int) -> float:
    """Per-test significance level for K independent tests at family-wise level ``alpha``."""
    if k < 1:
        raise ValueError(f"k: need at least one test; got {k}")
    return -math.expm1(math.log1p(-alpha) / k)


# ----------------------------------------------------------------------------- frames


@dataclasses.dataclass(frozen=True)
class Frame:
    """An orthonormal frame whose +z (``pole``) is the θ = 0 axis; φ is measured from x."""

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray

    @classmethod
    def around(cls, pole) -> Frame:
        z = np.asarray(pole, dtype=np.float64)
        z = z / np.linalg.norm(z)
        # Duff et al. 2017, "Building an orthonormal basis, revisited".
        sign = math.copysign(1.0, z[2])
        a = -1.0 / (sign + z[2])
        b = z[0] * z[1] * a
        x = np.array([1.0 + sign * z[0] * z[0] * a, sign * b, -sign * z[0]])
        y = np.array([b, sign + z[1] * z[1] * a, -z[1]])
        return cls(x, y, z)

    def to_world(self, theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
        st = np.sin(theta)
        return (
            (st * np.cos(phi))[..., None] * self.x
            + (st * np.sin(phi))[..., None] * self.y
            + np.cos(theta)[..., None] * self.z
        )

    def to_polar(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """θ in [0, π] (accurate near the pole) and φ in [0, 2π) of unit directions ``d``."""
        d = np.asarray(d, dtype=np.float64)
        # θ = 2 atan(|d − pole| / |d + pole|): accurate near the pole and near −pole.
        minus, plus = d - self.z, d + self.z
        theta = 2.0 * np.arctan2(
            np.sqrt(np.einsum("ij,ij->i", minus, minus)), np.sqrt(np.einsum("ij,ij->i", plus, plus))
        )
        phi = np.arctan2(d @ self.y, d @ self.x)
        phi[phi < 0.0] += TWO_PI
        phi[phi >= TWO_PI] = 0.0  # −tiny + 2π rounds to 2π
        return theta, phi

    def horizon(self, phi: np.ndarray, normal) -> np.ndarray:
        """θ_h(φ): the meridian at φ is above the plane ``d·normal = 0`` for θ < θ_h(φ).

        Needs ``pole·normal > 0``: on the meridian, ``d·normal = A cos θ + B(φ) sin θ``
        with ``A = pole·normal``, ``B = (cos φ x + sin φ y)·normal``, positive from θ = 0
        up to ``θ_h = π/2 + atan2(B, A)``.
        """
        n = np.asarray(normal, dtype=np.float64)
        n = n / np.linalg.norm(n)
        a = float(self.z @ n)
        if not a > 0.0:
            raise ValueError("the pole must lie strictly above the surface (pole·normal > 0)")
        b = np.cos(phi) * float(self.x @ n) + np.sin(phi) * float(self.y @ n)
        return 0.5 * math.pi + np.arctan2(b, a)


# ------------------------------------------------------------------------- quadrature


def _kinks(frame: Frame, normal, pieces: np.ndarray) -> np.ndarray:
    """φ where the horizon θ_h(φ) crosses a piece's θ0 or θ1 (there the clipped inner
    integral has a kink): shape ``(P, 4)``, φ1 where there is none inside (φ0, φ1)."""
    t0, t1, p0, p1 = pieces.T
    out = np.repeat(p1[:, None], 4, axis=1)
    if normal is None:
        return out
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    a, bx, by = float(frame.z @ n), float(frame.x @ n), float(frame.y @ n)
    r, psi = math.hypot(bx, by), math.atan2(by, bx)
    if r == 0.0:
        return out
    for k, edge in enumerate((t0, t1)):
        # θ_h(φ) = edge  ⇔  B(φ) = r cos(φ − ψ) = −a cot(edge).
        with np.errstate(divide="ignore", invalid="ignore"):
            c = -a * np.cos(edge) / np.sin(edge) / r
            half = np.arccos(np.where(np.abs(c) < 1.0, c, np.nan))
        for j, sign in enumerate((1.0, -1.0)):
            phi = p0 + np.mod(psi + sign * half - p0, TWO_PI)
            inside = np.isfinite(phi) & (phi > p0) & (phi < p1)
            out[:, 2 * k + j] = np.where(inside, phi, p1)
    return out


def _rule(
    pdf: PdfFn,
    frame: Frame,
    normal,
    pieces: np.ndarray,
    nodes: int,
) -> np.ndarray:
    """∫ pdf dω over each piece ``(θ0, θ1, φ0, φ1)`` by an ``nodes``² Gauss-Legendre rule.

    With ``normal``, θ is clipped at the horizon θ_h(φ) per φ node, and the φ range is
    split where θ_h crosses θ0 or θ1, so each panel's integrand is smooth."""
    if len(pieces) == 0:
        return np.zeros(0)
    x, w = np.polynomial.legendre.leggauss(nodes)
    t0, t1, p0, p1 = (pieces[:, k, None] for k in range(4))  # (P, 1)
    cuts = np.sort(_kinks(frame, normal, pieces), axis=1)
    bounds = np.concatenate([p0, cuts, p1], axis=1)  # (P, 6): 5 φ panels
    lo, hi = bounds[:, :-1, None], bounds[:, 1:, None]  # (P, 5, 1)
    phi = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x  # (P, 5, n)
    top = np.broadcast_to(t1[:, :, None], phi.shape)
    if normal is not None:
        top = np.minimum(top, frame.horizon(phi, normal))
    span = np.maximum(top - t0[:, :, None], 0.0)  # θ extent at each φ node
    u = 0.5 * (x + 1.0)
    theta = t0[:, :, None, None] + span[..., None] * u  # (P, 5, nφ, nθ)
    weight = (0.5 * (hi - lo) * w)[..., None] * (0.5 * span)[..., None] * w * np.sin(theta)
    live = weight > 0.0
    values = np.zeros(theta.shape)
    if live.any():
        phis = np.broadcast_to(phi[..., None], theta.shape)
        d = frame.to_world(theta[live], phis[live])
        values[live] = np.asarray(pdf(d), dtype=np.float64).reshape(-1)
    if not np.all(np.isfinite(values)):
        raise ValueError("pdf returned a non-finite value inside the integration domain")
    return np.sum(weight * values, axis=(1, 2, 3))


def integrate_cells(
    pdf: PdfFn,
    frame: Frame,
    theta_edges: np.ndarray,
    n_phi: int,
    *,
    normal=None,
    tolerance: Callable[[np.ndarray], np.ndarray],
    nodes: int = 4,
    max_levels: int = 10,
) -> tuple[np.ndarray, float]:
    """Integrates ``pdf`` over every cell of the (θ, φ) grid, adaptively.

    Each piece's ``nodes``² rule is compared with the sum of the same rule on its four
    quarters; a piece is accepted (with the finer value) when they differ by at most
    ``tolerance(finer value)``, else its quarters are refined in turn, up to
    ``max_levels`` splits. Returns the integrals, shape ``(len(theta_edges) − 1, n_phi)``,
    and the summed error estimate of the accepted pieces (a bound in practice: the
    accepted value is the finer one).
    """
    edges = np.asarray(theta_edges, dtype=np.float64)
    phi_edges = np.linspace(0.0, TWO_PI, n_phi + 1)
    nt = len(edges) - 1
    ti, pj = np.meshgrid(np.arange(nt), np.arange(n_phi), indexing="ij")
    pieces = np.stack(
        [edges[ti], edges[ti + 1], phi_edges[pj], phi_edges[pj + 1]], axis=-1
    ).reshape(-1, 4)
    owner = np.arange(nt * n_phi)
    coarse = _rule(pdf, frame, normal, pieces, nodes)
    total = np.zeros(nt * n_phi)
    error = 0.0
    for level in range(max_levels + 1):
        if len(pieces) == 0:
            break
        t0, t1, p0, p1 = pieces.T
        tm, pm = 0.5 * (t0 + t1), 0.5 * (p0 + p1)
        quarters = np.stack(
            [
                np.stack([t0, tm, p0, pm], -1),
                np.stack([tm, t1, p0, pm], -1),
                np.stack([t0, tm, pm, p1], -1),
                np.stack([tm, t1, pm, p1], -1),
            ],
            axis=1,
        )  # (P, 4, 4)
        sub = _rule(pdf, frame, normal, quarters.reshape(-1, 4), nodes).reshape(-1, 4)
        fine = sub.sum(axis=1)
        diff = np.abs(fine - coarse)
        done = diff <= tolerance(fine)
        if level == max_levels:
            done[:] = True
        np.add.at(total, owner[done], fine[done])
        error += float(diff[done].sum())
        keep = ~done
        pieces = quarters[keep].reshape(-1, 4)
        coarse = sub[keep].reshape(-1)
        owner = np.repeat(owner[keep], 4)
    return total.reshape(nt, n_phi), error


def default_theta_edges(count: int = 48, smallest: float = 1e-4) -> np.ndarray:
    """Edges 0, then geometric from ``smallest`` to π, and π/2 (where a lobe about the
    pole is clipped): resolves any lobe about the pole of width ≳ 1e-3."""
    edges = np.concatenate([[0.0], np.geomspace(smallest, math.pi, count), [0.5 * math.pi]])
    return np.unique(edges)


def integrate_sphere(
    pdf: PdfFn,
    pole=(0.0, 0.0, 1.0),
    *,
    normal=None,
    theta_edges: np.ndarray | None = None,
    n_phi: int = 16,
    atol: float = 1e-11,
    rtol: float = 1e-10,
) -> tuple[float, float]:
    """``∫ pdf dω`` over the whole sphere in the frame about ``pole``, and an error estimate.

    The default θ edges are geometric from 1e-4 to π (fine enough for cos^p lobes up to
    p ≈ 1e6 about the pole); per-piece tolerance ``atol + rtol·|piece|``.
    """
    frame = Frame.around(pole)
    edges = default_theta_edges() if theta_edges is None else theta_edges
    q, err = integrate_cells(
        pdf,
        frame,
        edges,
        n_phi,
        normal=normal,
        tolerance=lambda v: atol + rtol * np.abs(v),
        nodes=5,
        max_levels=14,
    )
    return float(q.sum()), err


# ------------------------------------------------------------------------------- grid


def adaptive_theta_edges(theta: np.ndarray, n_theta: int) -> np.ndarray:
    """θ band edges: 0, the pilot's θ quantiles at k/n_theta, then doubling up to π, and
    π/2."""
    theta = np.asarray(theta, dtype=np.float64)
    theta = theta[np.isfinite(theta)]
    if len(theta) < 10 * n_theta:
        # Too few pilot draws to place bands: the uniform-in-cos θ grid of Mitsuba.
        return np.arccos(np.linspace(1.0, -1.0, n_theta + 1))
    q = np.quantile(theta, np.arange(1, n_theta) / n_theta)
    edges = [0.0]
    for e in q:
        if e > edges[-1] * (1.0 + 1e-9) and e < math.pi:
            edges.append(float(e))
    while edges[-1] < math.pi:
        # The tail: bands doubling in θ; close to π, stop rather than leave a sliver.
        nxt = max(2.0 * edges[-1], 1e-6)
        edges.append(math.pi if nxt > 0.9 * math.pi else nxt)
    # π/2 is always an edge: a lobe about the pole is clipped there (cos^p of a negative
    # cosine is 0), and a kink on a band edge costs the quadrature nothing.
    return np.unique(np.append(edges, 0.5 * math.pi))


# ----------------------------------------------------------------------------- result


@dataclasses.dataclass
class Chi2Result:
    """The outcome of :func:`chi2_test`; ``str(result)`` is a readable summary."""

    statistic: float
    dof: int
    p_value: float
    p_chi2: float
    p_mass: float
    p_zero: float
    alpha: float
    n_samples: int
    n_cells: int
    n_pooled: int
    invalid_observed: int
    invalid_expected: float
    integral: float
    quadrature_error: float
    impossible: int
    observed: np.ndarray = dataclasses.field(repr=False)
    expected: np.ndarray = dataclasses.field(repr=False)
    theta_edges: np.ndarray = dataclasses.field(repr=False)
    label: str = ""

    @property
    def passed(self) -> bool:
        return self.p_value >= self.alpha

    def worst_cells(self, k: int = 5) -> list[tuple[int, int, float, float]]:
        """The k histogram cells with the largest χ² contributions: (iθ, iφ, O, E)."""
        o, e = self.observed, self.expected
        with np.errstate(divide="ignore", invalid="ignore"):
            c = np.where(e > 0, (o - e) ** 2 / np.where(e > 0, e, 1.0), np.where(o > 0, np.inf, 0))
        flat = np.argsort(c, axis=None)[::-1][:k]
        out = []
        for f in flat:
            i, j = np.unravel_index(f, c.shape)
            out.append((int(i), int(j), float(o[i, j]), float(e[i, j])))
        return out

    def summary(self) -> str:
        verdict = "PASS" if self.passed else "FAIL"
        lines = [
            f"χ² test {self.label}: {verdict}, p = {self.p_value:.3g} (α = {self.alpha:.3g})",
            f"  Pearson χ² = {self.statistic:.2f}, dof = {self.dof}, p = {self.p_chi2:.3g};"
            f" valid mass p = {self.p_mass:.3g}; empty-cell p = {self.p_zero:.3g}",
            f"  N = {self.n_samples}, cells = {self.n_cells} (θ bands {len(self.theta_edges) - 1}),"
            f" {self.n_pooled} pooled (E < 5)",
            f"  ∫ pdf dω = {self.integral:.8f} (quadrature error ≲ {self.quadrature_error:.1e});"
            f" invalid draws: observed {self.invalid_observed},"
            f" expected {self.invalid_expected:.1f}",
        ]
        if self.impossible:
            lines.append(f"  {self.impossible} draws fell in cells of expected count ~0")
        lines.append("  largest contributions (θ range, φ bin, observed, expected):")
        e = self.theta_edges
        for i, j, o, x in self.worst_cells():
            lines.append(
                f"    θ ∈ [{e[i]:.4g}, {e[i + 1]:.4g}], φ bin {j}: O = {o:.0f}, E = {x:.1f}"
            )
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


# ------------------------------------------------------------------------------- test


def _pooled_chi2(obs: np.ndarray, exp: np.ndarray, min_expected: float):
    """Pearson's χ² with cells of expected count < min_expected pooled (smallest first)."""
    order = np.argsort(exp, kind="stable")
    obs, exp = obs[order], exp[order]
    small = exp < min_expected
    pool_o, pool_e = float(obs[small].sum()), float(exp[small].sum())
    n_pooled = int(small.sum())
    obs, exp = obs[~small], exp[~small]
    if n_pooled and pool_e < min_expected and len(exp):
        # Not enough mass in the pool on its own: merge it into the smallest cell.
        pool_o += float(obs[0])
        pool_e += float(exp[0])
        obs, exp = obs[1:], exp[1:]
    stat = float(np.sum((obs - exp) ** 2 / exp))
    cells = len(exp)
    if pool_e > 0:
        stat += (pool_o - pool_e) ** 2 / pool_e
        cells += 1
    return stat, cells - 1, n_pooled


def chi2_test(
    sample: SampleFn,
    pdf: PdfFn,
    *,
    pole=(0.0, 0.0, 1.0),
    normal=None,
    n_samples: int = 1_000_000,
    n_theta: int = 40,
    n_phi: int = 40,
    n_pilot: int = 50_000,
    seed: int = 0,
    alpha: float = 0.01,
    min_expected: float = 5.0,
    qtol: float = 1e-3,
    zero_expected: float = 1e-3,
    theta_edges: np.ndarray | None = None,
    extra_edges=(),
    label: str = "",
) -> Chi2Result:
    """Tests that ``sample`` draws directions with density ``pdf`` (module docstring:
    Pearson's χ², the valid-mass test and the empty-cell test, combined by Bonferroni).

    Args:
        sample: ``u`` of shape ``(M, 2)`` (uniform in [0, 1)) → ``(dirs (M, 3), valid (M,))``;
            invalid draws (``valid`` False) are the mass the density leaves out.
        pdf: directions ``(M, 3)`` → density in 1/sr ``(M,)`` over the sphere.
        pole: the θ = 0 axis of the histogram (the lobe's axis).
        normal: if given, ``pdf`` is promised to be 0 where ``d·normal ≤ 0`` (and valid
            draws are above that plane); cell integrals are clipped at the horizon.
        n_theta, n_phi: θ bands of equal pilot mass (plus tail bands) × φ bins.
        n_pilot: draws of the independent pilot sample that places the θ bands
            (0, or ``theta_edges`` given, for a fixed grid).
        seed: seeds the generator of the pilot and tested ``u`` (deterministic).
        alpha: the test's significance level (see :func:`sidak_alpha`).
        qtol: quadrature tolerance per cell, as a fraction of the cell's Poisson noise.
        zero_expected: cells with a smaller expected count are tested together by the
            Poisson probability of the draws they hold, not by χ².
        extra_edges: θ values added to the band edges: where the density jumps (a jump
            inside a band can hide from every node of the cell quadrature, which then
            calls a thin sliver of real mass impossible).
    """
    rng = np.random.default_rng(seed)
    frame = Frame.around(pole)
    if theta_edges is None:
        if n_pilot > 0:
            d, ok = sample(rng.random((n_pilot, 2)))
            ok = np.asarray(ok, dtype=bool)
            theta_edges = adaptive_theta_edges(frame.to_polar(np.asarray(d)[ok])[0], n_theta)
        else:
            theta_edges = np.arccos(np.linspace(1.0, -1.0, n_theta + 1))
    theta_edges = np.asarray(theta_edges, dtype=np.float64)
    extra = np.asarray(extra_edges, dtype=np.float64).ravel()
    extra = extra[(extra > theta_edges[0]) & (extra < theta_edges[-1])]
    if len(extra):
        theta_edges = np.unique(np.append(theta_edges, extra))
    nt = len(theta_edges) - 1

    # The tested sample.
    d, ok = sample(rng.random((n_samples, 2)))
    ok = np.asarray(ok, dtype=bool)
    d = np.asarray(d, dtype=np.float64)[ok]
    if not np.all(np.isfinite(d)):
        raise ValueError("sample returned a non-finite direction it calls valid")
    theta, phi = frame.to_polar(d)
    it = np.clip(np.searchsorted(theta_edges, theta, side="right") - 1, 0, nt - 1)
    ip = np.minimum((phi * (n_phi / TWO_PI)).astype(np.int64), n_phi - 1)
    observed = np.bincount(it * n_phi + ip, minlength=nt * n_phi).reshape(nt, n_phi)
    observed = observed.astype(np.float64)
    invalid_observed = int(n_samples - ok.sum())

    # Expected counts.
    n = float(n_samples)
    q, qerr = integrate_cells(
        pdf,
        frame,
        theta_edges,
        n_phi,
        normal=normal,
        tolerance=lambda v: qtol * np.sqrt(np.maximum(np.abs(v), 1.0 / n) / n),
    )
    integral = float(q.sum())
    expected = n * q
    lost = 1.0 - integral
    invalid_expected = n * max(lost, 0.0)

    # (1) Pearson's χ² over the histogram cells and the invalid cell. Cells the density
    # calls (next to) impossible are left out of it and judged by (3).
    obs = np.concatenate([observed.ravel(), [invalid_observed]])
    exp = np.concatenate([expected.ravel(), [invalid_expected]])
    zero = exp < zero_expected
    stat, dof, n_pooled = _pooled_chi2(obs[~zero], exp[~zero], min_expected)
    if dof < 1:
        raise ValueError("χ² test: fewer than two cells with enough expected mass")
    p_chi2 = float(stats.chi2.sf(stat, dof))
    # (2) The valid mass: the count of valid draws is Binomial(N, ∫ pdf dω). Two-sided,
    # made conservative by the quadrature error; a density whose integral exceeds one is
    # no density of any sampler.
    valid = n_samples - invalid_observed
    slack = qerr + 1e-10  # the quadrature's error estimate and its rounding (~1e-12)
    if integral > 1.0 + slack:
        p_mass = 0.0
    else:
        hi, lo = min(1.0, integral + slack), max(0.0, min(1.0, integral - slack))
        p_mass = min(
            1.0,
            2.0 * float(stats.binom.sf(valid - 1, n_samples, hi)),
            2.0 * float(stats.binom.cdf(valid, n_samples, lo)),
        )
    # (3) Draws in histogram cells of expected count < zero_expected: Poisson probability
    # of at least that many in all of them together.
    zero_cells = zero[:-1]
    impossible = int(obs[:-1][zero_cells].sum())
    e_zero = float(exp[:-1][zero_cells].sum()) + n * qerr
    p_zero = float(stats.poisson.sf(impossible - 1, e_zero)) if impossible else 1.0
    # Bonferroni over the three: the test rejects at α when any rejects at α/3.
    p_value = min(1.0, 3.0 * min(p_chi2, p_mass, p_zero))
    return Chi2Result(
        statistic=stat,
        dof=dof,
        p_value=p_value,
        p_chi2=p_chi2,
        p_mass=p_mass,
        p_zero=p_zero,
        alpha=alpha,
        n_samples=n_samples,
        n_cells=int((~zero).sum()),
        n_pooled=n_pooled,
        invalid_observed=invalid_observed,
        invalid_expected=float(invalid_expected),
        integral=integral,
        quadrature_error=qerr,
        impossible=impossible,
        observed=observed,
        expected=expected,
        theta_edges=theta_edges,
        label=label,
    )
