"""How efficiently the sheen and cloth lobes are sampled: uniform, cosine and the model's own.

The Charlie sheens peak where the half vector lies near the surface (grazing angles), so
``brdf_rs.sample`` and the integrator draw them uniformly over the hemisphere; Ashikhmin's
cloth is nearly flat near normal incidence and peaks at grazing ``wo`` near grazing
incidence, and draws from a mixture of cosine and uniform draws that moves with the
incidence. For each model, incidence and roughness this measures, over 2^18 random draws
per sampler (``sampler="uniform"``, ``"cosine"`` and ``"auto"``, the model's own; kd = 0,
ks = 1), the mean weight (the albedo) and the per-draw relative spread
``sd(weight)/mean(weight)``: the number of draws an estimate needs for a given relative
error is proportional to its square. Also the largest weight seen (cosine draws of
``charlie_sheen`` have weights ``f·π`` that grow like ``1/mu_o``). Prints a table, writes
``benches/results/sheen_sampling.md`` and a plot ``benches/results/sheen_sampling.png``
(relative spread against roughness).

Tables are integrated with Sobol points, where a warp's shape in the unit square matters
as well as its density: a second table compares, for a 16 x 8 table of each model
(mu at texel centres, alpha log-spaced from 0.01 to 1), the median standard error and
the RMS error against a 2^18-sample table of the model's own sampler, at 256 and 4096
samples per cell, for each sampler ("own" is the default, ``"auto"``: with Sobol points
the integrator draws the cloth uniformly, as this table measured).

    python benches/sheen_sampling.py
"""

from __future__ import annotations

import argparse
from pathlib import Path

import brdf_rs
import numpy as np
from _plot import pyplot

MODELS = ("charlie_sheen", "charlie_sheen_neubelt", "ashikhmin_cloth")
MUS = (1.0, 0.5, 0.1)
ALPHAS = (0.05, 0.2, 0.5, 1.0)
SAMPLERS = ("uniform", "cosine", "auto")
DRAWS = 1 << 18
OUT = Path(__file__).resolve().parent / "results"


def spread(model: str, mu: float, alpha: float, sampler: str) -> tuple[float, float, float]:
    """Mean weight, relative spread and largest weight of DRAWS draws."""
    rng = np.random.default_rng(1)
    wi = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    u = rng.random((DRAWS, 2))
    _, weight, _ = brdf_rs.sample(model, wi, u, sampler=sampler, kd=0.0, ks=1.0, alpha=alpha)
    w = weight[:, 0]
    mean = float(w.mean())
    return mean, float(w.std()) / mean, float(w.max())


def sobol_tables() -> str:
    """Median standard error and RMS error of Sobol tables, per sampler."""
    mu = (np.arange(16) + 0.5) / 16
    axes = {"mu": mu, "alpha": np.geomspace(0.01, 1.0, 8)}
    rows = [
        "| model | samples per cell | median stderr, uniform | cosine | own | "
        "RMS error, uniform | cosine | own |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for model in MODELS:
        ref = brdf_rs.albedo_table(model, axes, samples=1 << 18, kd=0.0, ks=1.0).value[..., 0]
        for samples in (256, 4096):
            se, rms = [], []
            for s in SAMPLERS:
                t = brdf_rs.albedo_table(model, axes, samples=samples, sampler=s, kd=0.0, ks=1.0)
                se.append(float(np.median(t.stderr[..., 0])))
                rms.append(float(np.sqrt(np.mean((t.value[..., 0] - ref) ** 2))))
            rows.append(
                f"| {model} | {samples} | " + " | ".join(f"{x:.3g}" for x in se + rms) + " |"
            )
    return "\n".join(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT / "sheen_sampling")
    args = parser.parse_args()
    rows = [
        "| model | mu | alpha | albedo | rel. spread, uniform | rel. spread, cosine | "
        "rel. spread, own | draws cosine needs per uniform draw | draws own needs per draw "
        "of the better of the two | largest weight, uniform | largest, cosine | largest, own |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    curves: dict[tuple[str, float, str], list[float]] = {}
    for model in MODELS:
        for mu in MUS:
            for alpha in ALPHAS:
                stats = {s: spread(model, mu, alpha, s) for s in SAMPLERS}
                (mean, su, mu_max), (_, sc, mc_max) = stats["uniform"], stats["cosine"]
                _, so, mo_max = stats["auto"]
                for s in SAMPLERS:
                    curves.setdefault((model, mu, s), []).append(stats[s][1])
                best = min(su, sc)
                own = f"{(so / best) ** 2:.2f}" if best > 1e-9 * so else "(the better is exact)"
                rows.append(
                    f"| {model} | {mu:g} | {alpha:g} | {mean:.4g} | {su:.3g} | {sc:.3g} | "
                    f"{so:.3g} | {(sc / su) ** 2:.2f} | {own} | {mu_max:.3g} | {mc_max:.3g} | "
                    f"{mo_max:.3g} |"
                )
    text = "\n".join(rows) + "\n\n" + sobol_tables()
    print(text)
    head = (
        "# Sampling the sheen and cloth lobes\n\n"
        f"`python benches/sheen_sampling.py`: {DRAWS} random draws per row and sampler "
        "(kd = 0, ks = 1), brdf-rs "
        f"{brdf_rs.__version__}. Relative spread = sd(weight)/mean(weight) per draw; "
        "the draws a sampler needs for a given relative error go as its square.\n\n"
    )
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.with_suffix(".md").write_text(head + text + "\n")
    plt = pyplot()
    if plt is None:
        return
    fig, axes = plt.subplots(1, len(MODELS), figsize=(12, 3.6), sharey=True)
    for ax, model in zip(axes, MODELS, strict=True):
        for mu in MUS:
            for s, style in zip(SAMPLERS, ("-", "--", ":"), strict=True):
                ax.plot(ALPHAS, curves[(model, mu, s)], style, marker="o", label=f"mu={mu:g} {s}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(model)
        ax.set_xlabel("alpha")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("sd(weight) / mean(weight) per draw")
    axes[-1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.tight_layout()
    fig.savefig(args.out.with_suffix(".png"), dpi=110)
    print(f"wrote {args.out.with_suffix('.md')} and .png")


if __name__ == "__main__":
    main()
