"""Regenerates the tables brdf-rs interpolates, computed by brdf-rs itself (its albedo
integrator).

- ``energy``: rust/src/models/tables/ggx_e.rs, beckmann_e.rs, nodes.rs, embedded in the binary:
  Kulla & Conty's E(mu, alpha) (directional albedo with F = 1) on 33 x 33 nodes
  (mu = j/32, the first node at 1e-4; alpha log-spaced in [1e-3, 1]), and
  E_avg(alpha) = 2 ∫ E(mu) mu dmu of the interpolated E itself (tanh-sinh between the
  nodes: the lobe's normalization). Each cell is integrated to
  a standard error of 1e-6 (randomized QMC, seed 0). ~1 minute on 2 cores.
- ``exact``: python/brdf_rs/exact_normalization.npz, shipped in the package (the factor
  is applied to the parameters in Python, before the kernel: see _normalization.py).
  Ward's albedo at normal incidence A(alpha_x, alpha_y) on 65 x 65 nodes log-spaced in
  [1e-2, 1e2] (symmetric: 2145 cells), as r = −log(A·s(alpha_x)·s(alpha_y)),
  s(a) = sqrt(1 + 3a²); each cell to a standard error of 5e-7 in A·s·s where the samplers
  allow it (the stderr is stored). It also checks Torrance-Sparrow's sup over mu of the
  F = 1 albedo (which is 1: no table needed) and prints what it found. ~10 minutes.
- ``dielectric``: rust/src/models/tables/ggx_dielectric_e.rs, embedded in the binary: the
  total albedo E (reflection + transmission, ks = kt = 1) of ``ggx_dielectric`` for light
  from either side of the interface, over (mu, alpha, |ln r|), r the relative index seen
  from the light's side: one table for r > 1 (entering the denser medium) and one for
  r < 1 (leaving it), 97 x 49 x 129 nodes each. ``ggx_dielectric_ms`` divides by it.
  Each cell to a standard error of 1e-4 (randomized QMC, seed 0). ~3 minutes on 2 cores.

    python scripts/gen_tables.py [energy] [exact] [dielectric]   # all by default
    python scripts/gen_tables.py exact-check          # measures the Ward interpolation error
"""

from __future__ import annotations

import datetime
import itertools
import json
import math
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import brdf_rs
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "rust" / "src" / "models" / "tables"
EXACT = ROOT / "python" / "brdf_rs" / "exact_normalization.npz"


def rust_array(values: np.ndarray) -> str:
    return "[" + ", ".join(f"{v!r}" for v in values.tolist()) + "]"


#: Nodes of the energy tables: NT uniform in x = (sqrt(t) + t)/2 over [0, 1], where
#: t = mu/(mu + alpha·sqrt(1 − mu²)) (the first node is integrated at t = T0 rather than
#: at grazing incidence); NA in log alpha over [1e-3, 1]. The square root refines the
#: grid near grazing incidence, where the loss of rough lobes grows like mu^0.85.
NT = 65
NA = 97
X_NODES = np.linspace(0.0, 1.0, NT)
T_NODES = ((np.sqrt(1 + 8 * X_NODES) - 1) / 2) ** 2
T_NODES[-1] = 1.0
T0 = 1e-6
ALPHA = np.geomspace(1e-3, 1.0, NA)
TOL = 1e-6


def x_of_t(t: np.ndarray) -> np.ndarray:
    """The table's node coordinate (as the kernel computes it)."""
    return 0.5 * (np.sqrt(t) + t)


def mu_of_t(t: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """Inverse of t = mu/(mu + alpha·sqrt(1 − mu²)): mu = t·alpha/sqrt((1 − t)² + t²alpha²)."""
    return t * alpha / np.sqrt((1 - t) ** 2 + (t * alpha) ** 2)


def t_of_mu(mu: np.ndarray, alpha: float) -> np.ndarray:
    """The table's incidence coordinate (as the kernel computes it)."""
    s = np.sqrt((1 - mu) * (1 + mu))
    return mu / (mu + alpha * s)


def interpolated_loss(loss_column: np.ndarray, t: np.ndarray) -> np.ndarray:
    """One alpha column's loss at t, linear in x between the nodes (as the kernel does)."""
    return np.interp(x_of_t(t), X_NODES, loss_column)


def _tanh_sinh(level: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """Tanh-sinh nodes and weights on [-1, 1] (step 2^-level): exact to rounding for
    integrands analytic inside the interval, whatever their endpoint singularities."""
    h = 2.0**-level
    k = np.arange(-6 * 2**level, 6 * 2**level + 1) * h
    u = 0.5 * np.pi * np.sinh(k)
    x = np.tanh(u)
    w = 0.5 * np.pi * h * np.cosh(k) / np.cosh(u) ** 2
    keep = (np.abs(x) < 1) & (w > 1e-300)
    return x[keep], w[keep]


def average_loss(loss_column: np.ndarray, alpha: float) -> float:
    """2 ∫ L(t(mu)) mu dmu of the interpolant itself: the normalization that makes the
    lobe's albedo exactly (1 − E(mu))·F_ms for the function the kernel evaluates.

    Piece by piece between the nodes' incidences, by tanh-sinh quadrature: inside a piece
    the interpolant is analytic in mu; at the ends it has the square-root singularities
    of t(mu) at mu = 1 and of x(t) at t = 0."""
    xq, wq = _tanh_sinh()
    edges = mu_of_t(T_NODES, alpha)
    total = 0.0
    for a, b in itertools.pairwise(edges):
        mu = 0.5 * (a + b) + 0.5 * (b - a) * xq
        total += (
            0.5 * (b - a) * np.sum(wq * interpolated_loss(loss_column, t_of_mu(mu, alpha)) * mu)
        )
    return 2.0 * total


def table(model: str) -> str:
    t = T_NODES.copy()
    t[0] = T0
    mu = mu_of_t(t[:, None], ALPHA[None, :])
    r = brdf_rs.albedo(model, mu, kd=0.0, ks=1.0, alpha=ALPHA[None, :], samples=1 << 12, tol=TOL)
    # The loss 1 − E, clamped to [0, 1] (a single-scattering albedo with F = 1 never
    # exceeds 1: an estimate above 1 is noise).
    loss = np.clip(1.0 - r.value[..., 0], 0.0, 1.0)
    avg = np.array([average_loss(loss[:, j], a) for j, a in enumerate(ALPHA)])
    rows = ",\n    ".join(rust_array(row) for row in loss)
    worst = float(r.stderr.max())
    name = model.upper()
    return f"""//! Generated by scripts/gen_tables.py on {datetime.date.today()} with brdf-rs
//! {brdf_rs.__version__}: do not edit. {model} with F = 1; largest standard error {worst:.1e}.

use super::nodes::{{NA, NT}};

/// `LOSS[i][j]` = 1 − E at `T[i]`, `ALPHA[j]` (E the directional albedo, clamped to [0, 1]).
pub static {name}_LOSS: [[f64; NA]; NT] = [
    {rows}
];
/// `LOSS_AVG[j]` = 2 ∫ L(mu) mu dmu at `ALPHA[j]` of the interpolated loss itself.
pub static {name}_LOSS_AVG: [f64; NA] = {rust_array(avg)};
"""


def nodes() -> str:
    return f"""//! Generated by scripts/gen_tables.py on {datetime.date.today()} with brdf-rs
//! {brdf_rs.__version__}: do not edit. The nodes of the energy tables.

/// Incidence nodes.
pub const NT: usize = {NT};
/// Roughness nodes.
pub const NA: usize = {NA};
/// Incidence nodes `t = mu/(mu + alpha·sqrt(1 − mu²))`, uniform in `x = (sqrt(t) + t)/2`
/// over [0, 1] (the first is integrated at t = {T0:g}).
pub const T: [f64; NT] = {rust_array(T_NODES)};
/// Roughness nodes, log-spaced in [1e-3, 1].
pub const ALPHA: [f64; NA] = {rust_array(ALPHA)};
"""


def energy_tables() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "nodes.rs").write_text(nodes())
    for model in ("ggx", "beckmann"):
        path = OUT / f"{model}_e.rs"
        path.write_text(table(model))
        print(f"wrote {path}")
    # Keep `cargo fmt --check` (CI) happy.
    subprocess.run(["cargo", "fmt"], cwd=OUT.parents[3], check=True)


# ----------------------------------------------------------------- exact normalization

#: Ward's roughness nodes: 16 per decade in [1e-2, 1e2].
WARD_ALPHA = np.geomspace(1e-2, 1e2, 65)
WARD_TOL = 5e-7
WARD_MAX_SAMPLES = 1 << 24


def ward_scale(alpha_x: np.ndarray, alpha_y: np.ndarray) -> np.ndarray:
    """s(αx)·s(αy), s(a) = sqrt(1 + 3a²): 1/A to within 3.1% for every αx, αy (A ≈ 1 −
    1.5(αx² + αy²) for small α, 1/(3 αx αy) for large ones, ≈ 1/(1.71 αx) for large αx,
    small αy). Integrating ks = s·s makes every cell's value ≈ 1, so an absolute
    tolerance is a relative one."""
    return np.sqrt((1 + 3 * alpha_x**2) * (1 + 3 * alpha_y**2))


def ward_integrate(
    alpha_x: np.ndarray, alpha_y: np.ndarray, seed: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ward's albedo at normal incidence times ward_scale, its stderr and the sampler
    used (0: importance, 1: uniform) per cell. Ward's own importance sampler (Walter's
    Gaussian NDF sampling) is the good one for narrow lobes, uniform hemisphere sampling
    for wide ones (where importance sampling sends almost every sample below the horizon
    and its stderr, from a handful of hits, is not to be trusted); where neither clearly
    wins both run and the smaller stderr is kept."""
    scale = ward_scale(alpha_x, alpha_y)
    narrow = np.maximum(alpha_x, alpha_y) <= 0.3
    wide = np.minimum(alpha_x, alpha_y) >= 0.3
    value = np.full(alpha_x.size, np.nan)
    stderr = np.full(alpha_x.size, np.inf)
    used = np.zeros(alpha_x.size, dtype=np.int8)
    for code, sampler, cells in ((0, "importance", ~wide), (1, "uniform", ~narrow)):
        k = np.flatnonzero(cells)
        t0 = time.perf_counter()
        r = brdf_rs.albedo(
            "ward",
            1.0,
            kd=0.0,
            ks=scale[k, None],
            alpha_x=alpha_x[k],
            alpha_y=alpha_y[k],
            samples=1 << 16,
            tol=WARD_TOL,
            max_samples=WARD_MAX_SAMPLES,
            sampler=sampler,
            seed=seed + code,
        )
        v, e = r.value[:, 0], r.stderr[:, 0]
        better = e < stderr[k]
        value[k[better]] = v[better]
        stderr[k[better]] = e[better]
        used[k[better]] = code
        print(
            f"ward {sampler}: {k.size} cells in {time.perf_counter() - t0:.0f} s, "
            f"largest stderr {e.max():.1e}",
            flush=True,
        )
    return value, stderr, used


def ward_table() -> dict[str, np.ndarray]:
    """Ward's albedo at normal incidence over the symmetric (αx, αy) grid (seed 0)."""
    n = WARD_ALPHA.size
    i, j = np.triu_indices(n)
    value, stderr, sampler_used = ward_integrate(WARD_ALPHA[i], WARD_ALPHA[j], seed=0)
    full = np.empty((n, n))
    full_se = np.empty((n, n))
    used = np.empty((n, n), dtype=np.int8)
    for a, b in ((i, j), (j, i)):
        full[a, b] = -np.log(value)
        full_se[a, b] = stderr / value
        used[a, b] = sampler_used
    print(
        f"ward: r in [{full.min():.4e}, {full.max():.4e}]; stderr of r: largest "
        f"{full_se.max():.1e}, median {np.median(full_se):.1e}",
        flush=True,
    )
    return {
        "ward_alpha": WARD_ALPHA,
        "ward_r": full,
        "ward_r_stderr": full_se,
        "ward_sampler": used,
    }


#: Torrance-Sparrow check: p nodes and incidences.
TS_P = np.concatenate([[0.0], np.geomspace(0.1, 1e5, 13)])
TS_MU = np.concatenate([[1e-6, 1e-4, 1e-3, 1e-2], np.linspace(0.05, 1.0, 20)])


def torrance_sparrow_check() -> None:
    """Prints sup over mu of the F = 1 Torrance-Sparrow albedo (R0 = 1: eta = 1e20 rounds
    R0 to exactly 1) per p: it is 1 (the V-cavity G conserves projected area), reached as
    mu → 0, so the exact factor is 1. Fails if any cell exceeds 1 by more than 5 stderr."""
    r = brdf_rs.albedo(
        "torrance_sparrow",
        TS_MU[:, None],
        kd=0.0,
        ks=1.0,
        eta=1e20,
        p=TS_P[None, :],
        samples=1 << 16,
        tol=1e-6,
        max_samples=1 << 22,
    )
    v, e = r.value[..., 0], r.stderr[..., 0]
    # Cells the estimator gets exactly (every replicate equal: stderr 0) count as z = 0.
    z = np.divide(v - 1, e, out=np.zeros_like(v), where=e > 0)
    for k, p in enumerate(TS_P):
        m = int(np.argmax(v[:, k]))
        print(
            f"torrance_sparrow p={p:<9.4g} max over mu {v[m, k]:.7f} ± {e[m, k]:.1e} at mu="
            f"{TS_MU[m]:g}; A(mu=1) = {v[-1, k]:.6f}; largest (A − 1)/stderr "
            f"{np.max(z[:, k]):.1f}",
            flush=True,
        )
    if np.any(v > 1 + 5 * e + 1e-12):
        raise SystemExit("torrance_sparrow: an albedo exceeds 1 by more than 5 stderr")


def exact_tables() -> None:
    torrance_sparrow_check()
    ward = ward_table()
    meta = {
        "generator": "scripts/gen_tables.py exact",
        "date": str(datetime.date.today()),
        "brdf_rs": brdf_rs.__version__,
        "ward": "r = -log(A(mu=1)·s(ax)·s(ay)), s(a) = sqrt(1 + 3a^2); A the directional "
        "albedo of ward with kd = 0, ks = 1 at normal incidence",
        "ward_tol": WARD_TOL,
        "ward_max_samples": WARD_MAX_SAMPLES,
        "sequence": "sobol",
    }
    tmp = EXACT.with_name(EXACT.name + ".partial.npz")
    np.savez_compressed(tmp, meta=np.array(json.dumps(meta)), **ward)
    tmp.replace(EXACT)
    print(f"wrote {EXACT}")


def ward_albedo_quadrature(alpha_x: float, alpha_y: float) -> float:
    """Ward's albedo at normal incidence by 1-D quadrature: tests/quadrature.py's, the
    function the tests check the factor with."""
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    from quadrature import ward_albedo_at_normal_incidence

    return ward_albedo_at_normal_incidence(alpha_x, alpha_y)


def exact_check() -> None:
    """Measures the interpolated Ward factor at the table's cell midpoints (in log α)
    against 1-D quadrature (all midpoints) and fresh integrations (every third one, a
    new seed), and beyond the table against quadrature."""
    import warnings

    from brdf_rs import _normalization

    mid = np.sqrt(WARD_ALPHA[:-1] * WARD_ALPHA[1:])
    k, m = np.triu_indices(mid.size)
    ax, ay = mid[k], mid[m]
    c = _normalization.factor("ward", {"alpha_x": ax, "alpha_y": ay})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        quad = np.array([ward_albedo_quadrature(x, y) for x, y in zip(ax, ay, strict=True)])
    rel = np.abs(c * quad - 1)
    worst = int(np.argmax(rel))
    print(
        f"ward midpoints vs quadrature ({rel.size}): largest |c·A − 1| {rel.max():.2e} at "
        f"({ax[worst]:.4g}, {ay[worst]:.4g}); median {np.median(rel):.1e}; 99th percentile "
        f"{np.quantile(rel, 0.99):.1e}"
    )
    pick = (k % 3 == 0) & (m % 3 == 0)
    sub_x, sub_y = ax[pick], ay[pick]
    fresh, fresh_se, _ = ward_integrate(sub_x, sub_y, seed=100)
    scale = ward_scale(sub_x, sub_y)
    fresh_value, fresh_se = fresh / scale, fresh_se / scale
    dev = c[pick] * fresh_value - 1
    z = dev / (c[pick] * fresh_se)
    print(
        f"ward midpoints vs fresh integrations ({dev.size}): largest |c·A − 1| "
        f"{np.abs(dev).max():.2e}; median {np.median(np.abs(dev)):.1e}; largest stderr "
        f"of c·A {np.max(c[pick] * fresh_se):.1e}; |z| > 4 in {(np.abs(z) > 4).sum()} cells"
    )
    beyond = [(1e-7, 1e-7), (1e-3, 0.5), (1e-7, 1e7), (5e2, 5e2), (1e7, 1e7), (0.3, 1e4)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for x, y in beyond:
            cb = float(_normalization.factor("ward", {"alpha_x": x, "alpha_y": y}))
            print(
                f"ward beyond the table ({x:g}, {y:g}): c = {cb:.6g}, "
                f"|c·A − 1| = {abs(cb * ward_albedo_quadrature(x, y) - 1):.1e}"
            )
    print(f"ward factor at the midpoints: c in [{c.min():.6g}, {c.max():.6g}]")


# ----------------------------------------------------------------- dielectric energy

#: Nodes of the dielectric energy table. Index: y = |ln r| (the same for r and 1/r)
#: uniform in v = ln(1 + y·2^50)/(2 ln(1 + Y_MAX·2^50)) + y/(2 Y_MAX), Y_MAX = ln 1e7:
#: logarithmic in |r − 1| from the last ulps before 1, uniform in ln r towards r = 1e7
#: (where the transmission falls as 1/r); v = 0 is integrated at r = 1 ± 2^-52, the
#: closest index to 1 a float holds. Roughness log-uniform in [1e-3, 1]. Incidence: the
#: nodes sit at x = q^(1/4)/2 + (sqrt(t) + t)/4, which depends on all three:
#: - t = mu/(mu + alpha·sin) as the conductors' tables (the shadowing loss lives within
#:   mu of about alpha of grazing);
#: - q = mu/(mu + w·sin), w = y/(alpha + y): an index near 1 opens a layer of grazing
#:   incidence, mu below about y/alpha, in which E falls towards 0 (light from the
#:   denser side is turned back across the surface) or rises to 1 (from the rarer side,
#:   reflected whole). In q the layer holds still as y → 0, so that E is smooth along
#:   the index axis at a fixed x.
DT_NT = 97
DT_NA = 49
DT_NS = 129
DT_Y_SCALE = 2.0**50
DT_Y_MAX = math.log(1e7)
DT_TOL = 1e-4


def dt_x(mu: np.ndarray, alpha: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The incidence coordinate in [0, 1] (as the kernel computes it)."""
    sin = np.sqrt(np.maximum((1 - mu) * (1 + mu), 0.0))
    t = mu / (mu + alpha * sin)
    q = mu * (alpha + y) / (mu * (alpha + y) + y * sin)
    return 0.5 * np.sqrt(np.sqrt(q)) + 0.25 * (np.sqrt(t) + t)


def dt_v_of_y(y: np.ndarray) -> np.ndarray:
    """The index coordinate in [0, 1] of y = |ln r|."""
    scale = math.log1p(DT_Y_MAX * DT_Y_SCALE)
    return 0.5 * np.log1p(y * DT_Y_SCALE) / scale + 0.5 * y / DT_Y_MAX


def _invert(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray, top: float) -> np.ndarray:
    """The increasing function f's inverse at x, by bisection on [0, top]."""
    lo, hi = np.zeros_like(x), np.full_like(x, top)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        below = f(mid) < x
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return 0.5 * (lo + hi)


DT_ALPHA = np.geomspace(1e-3, 1.0, DT_NA)
DT_Y = _invert(dt_v_of_y, np.linspace(0.0, 1.0, DT_NS), DT_Y_MAX)
DT_Y[0] = 2.0**-52
DT_Y[-1] = DT_Y_MAX


def dielectric_mu() -> np.ndarray:
    """The incidence cosine of every node, shaped (NT, NA, NS): x's inverse in mu for
    each roughness and index (the first node at mu = 1e-300, the last at 1)."""
    x = np.broadcast_to(np.linspace(0.0, 1.0, DT_NT)[:, None, None], (DT_NT, DT_NA, DT_NS))
    alpha, y = DT_ALPHA[None, :, None], DT_Y[None, None, :]
    mu = _invert(lambda m: dt_x(m, alpha, y), x, 1.0)
    mu[0] = 1e-300
    mu[-1] = 1.0
    return mu


def dielectric_index(y: np.ndarray) -> np.ndarray:
    """The relative index r > 1 of each y node (r = e^y, at most 1e7; e^(2^-52) rounds
    to 1 + 2^-52)."""
    return np.minimum(np.exp(y), 1e7)


def dielectric_e(enter: bool, first_cell: int) -> tuple[np.ndarray, float, float]:
    """E[i, j, k] at the (x_i, ALPHA[j], Y[k]) node for light entering (r > 1) or leaving
    (r < 1) the denser medium, its largest stderr and the seconds it took."""
    mu = dielectric_mu()
    r = dielectric_index(DT_Y)
    eta = (r if enter else 1.0 / r)[None, None, :]
    ids = first_cell + np.arange(DT_NT * DT_NA * DT_NS).reshape(DT_NT, DT_NA, DT_NS)
    start = time.perf_counter()
    res = brdf_rs.albedo(
        "ggx_dielectric",
        mu,
        ks=1.0,
        kt=1.0,
        alpha=DT_ALPHA[None, :, None],
        eta=eta,
        samples=1 << 10,
        tol=DT_TOL,
        cell_ids=ids,
    )
    seconds = time.perf_counter() - start
    # The white interface absorbs nothing: an estimate above 1 is noise. Below the cells'
    # standard error (deep in the layer of grazing incidence from the denser side, where E
    # falls towards 0) the estimate cannot tell E from 0: the table holds DT_TOL there,
    # which caps the compensation 1/E at 1/DT_TOL.
    e = np.clip(res.value[..., 0], DT_TOL, 1.0)
    return e, float(res.stderr.max()), seconds


def dielectric_table() -> None:
    enter, se_enter, sec_enter = dielectric_e(True, 0)
    print(f"entering: largest stderr {se_enter:.1e}, {sec_enter:.0f} s", flush=True)
    leave, se_leave, sec_leave = dielectric_e(False, DT_NT * DT_NA * DT_NS)
    print(f"leaving: largest stderr {se_leave:.1e}, {sec_leave:.0f} s", flush=True)
    worst = max(se_enter, se_leave)
    data = np.stack([enter, leave]).astype("<f4")
    (OUT / "ggx_dielectric_e.bin").write_bytes(data.tobytes())
    text = f"""//! Generated by scripts/gen_tables.py on {datetime.date.today()} with brdf-rs
//! {brdf_rs.__version__}: do not edit. ggx_dielectric's total albedo E (ks = kt = 1);
//! largest standard error {worst:.1e}.

/// Incidence nodes, uniform in `x = q^(1/4)/2 + (sqrt(t) + t)/4` over [0, 1], with
/// `t = mu/(mu + alpha·sin)` and `q = mu/(mu + w·sin)`, `w = y/(alpha + y)`.
pub const NT: usize = {DT_NT};
/// Roughness nodes, log-uniform in [1e-3, 1].
pub const NA: usize = {DT_NA};
/// Index nodes, uniform in `v = ln(1 + y·2^50)/(2 ln(1 + Y·2^50)) + y/(2Y)` over [0, 1],
/// `y = |ln r|`, `Y = ln 1e7`, `r` the relative index seen from the light's side.
pub const NS: usize = {DT_NS};

/// `E` as little-endian `f32`, indexed `[side][i][j][k]`: side 0 for light from the
/// rarer medium (`r > 1`), 1 from the denser one (`r < 1`); the `i`-th incidence, `j`-th
/// roughness and `k`-th index node.
pub static E: &[u8; 4 * 2 * NT * NA * NS] = include_bytes!("ggx_dielectric_e.bin");
"""
    path = OUT / "ggx_dielectric_e.rs"
    path.write_text(text)
    print(f"wrote {path} and its .bin")


def main() -> None:
    which = sys.argv[1:] or ["energy", "exact", "dielectric"]
    known = ("energy", "exact", "exact-check", "dielectric")
    for name in which:
        if name not in known:
            raise SystemExit(f"unknown table {name!r}: expected one of {', '.join(known)}")
    if "energy" in which:
        energy_tables()
    if "exact" in which:
        exact_tables()
    if "exact-check" in which:
        exact_check()
    if "dielectric" in which:
        dielectric_table()


if __name__ == "__main__":
    main()
