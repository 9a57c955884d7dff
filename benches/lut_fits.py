"""Analytic fits of GGX's tables as shader code: stated maximum error against the number
of coefficients, for polynomials and rational functions (brdf_rs.lut.fit).

    python benches/lut_fits.py                       # ue5 (DFG) and cycles (E) presets
    python benches/lut_fits.py --samples 16384 --presets ue5

For each preset's table (its layout and format; ``--samples`` per texel and per check
point, so that the Monte Carlo part of the error stays below the fits'), every channel is
fitted by minimax polynomials of total degree 2 to 10 and rational functions of total
degrees N/M. Each fit's error is measured against the texels and against fresh
integrals on a grid four times denser than the texels along each axis (at most 256, the
same grid for every fit, ``brdf_rs.lut.dense_check``); its stated maximum error is the
worst of those plus 3 standard errors of the integrals plus the largest difference
between the fit evaluated in float32 (as the emitted code does) and in float64. Prints a
table, writes benches/results/lut_fits.md, .json and a plot of the stated maximum error
against the coefficient count.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from _plot import pyplot
from brdf_rs import __version__, lut

RESULTS = Path(__file__).resolve().parent / "results"
POLYNOMIALS = [(d, 0) for d in range(2, 11)]
RATIONALS = [(2, 2), (3, 2), (3, 3), (4, 3), (4, 4), (5, 4), (5, 5), (6, 5), (6, 6), (8, 6)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--presets", nargs="+", default=["ue5", "cycles"])
    parser.add_argument("--samples", type=int, default=1 << 14)
    parser.add_argument("--out", type=Path, default=RESULTS / "lut_fits")
    args = parser.parse_args()
    rows = []
    for name in args.presets:
        spec = lut.preset(name, samples=args.samples)
        t0 = time.perf_counter()
        table = lut.build(spec)
        check = lut.dense_check(spec)
        built = time.perf_counter() - t0
        print(
            f"\n{name}: {spec.kind} of {spec.model}, {spec.columns.size} x {spec.rows.size},"
            f" {args.samples} samples; table and {check.value[..., 0].size} dense integrals"
            f" in {built:.1f} s (their stderr up to {check.stderr.max():.1e})"
        )
        print(
            f"{'fit':<9} {'terms':>5} {'channel':<7} {'texels':>9} {'dense':>9} {'f32':>9}"
            f" {'max error':>9} {'interior':>9} {'s':>6}"
        )
        for degree, den in POLYNOMIALS + RATIONALS:
            t = time.perf_counter()
            try:
                f = lut.fit(table, degree, den, dense=check)
            except ValueError as exc:
                print(f"{degree}/{den}: {exc}")
                continue
            seconds = time.perf_counter() - t
            for c, channel in enumerate(spec.channel_names):
                row = {
                    "preset": name,
                    "kind": spec.kind,
                    "fit": f"{degree}/{den}" if den else f"{degree}",
                    "degree": degree,
                    "denominator": den,
                    "terms": f.terms,
                    "channel": channel,
                    "worst_texels": f.worst_texels[c],
                    "worst_dense": f.worst_dense[c],
                    "dense_stderr": f.dense_stderr[c],
                    "float32_worst": f.float32_worst[c],
                    "max_error": f.max_error[c],
                    "max_error_interior": f.max_error_interior[c],
                    "seconds": seconds,
                }
                rows.append(row)
                print(
                    f"{row['fit']:<9} {f.terms:>5} {channel:<7} {row['worst_texels']:>9.2e}"
                    f" {row['worst_dense']:>9.2e} {row['float32_worst']:>9.2e}"
                    f" {row['max_error']:>9.2e} {row['max_error_interior']:>9.2e} {seconds:>6.1f}"
                )
    args.out.parent.mkdir(parents=True, exist_ok=True)
    meta = {"brdf_rs": __version__, "samples": args.samples, "presets": args.presets}
    args.out.with_suffix(".json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1))
    write_markdown(args.out.with_suffix(".md"), rows, meta)
    plot(args.out.with_suffix(".png"), rows)
    print(f"wrote {args.out}.md, .json, .png")


def write_markdown(path: Path, rows: list[dict], meta: dict) -> None:
    lines = [
        "# Analytic fits of GGX's tables: maximum error against coefficient count",
        "",
        f"`python benches/lut_fits.py --samples {meta['samples']} --presets"
        f" {' '.join(meta['presets'])}` (brdf-rs {meta['brdf_rs']}): each preset's table"
        " fitted per channel by minimax polynomials (fit N: total degree N) and rational"
        " functions (N/M: total degrees N over M) in the table's axis fractions; 'terms' is"
        " the coefficient count per channel. 'texels': worst error against the texels;"
        " 'max error': the largest of the worst errors against the texels, against fresh"
        " integrals between them and on a grid four times denser (at most 256 per axis),"
        " each + 3 stderr of its reference, + the float32 evaluation's largest difference"
        " from float64 (printed by the script): the maximum error the emitted code states"
        " over the whole range;"
        " 'interior' the same between the first and last texels of both axes (outside them"
        " the table itself clamps to its edge texels, and the fit extrapolates).",
    ]
    for preset in dict.fromkeys(r["preset"] for r in rows):
        sub = [r for r in rows if r["preset"] == preset]
        channels = list(dict.fromkeys(r["channel"] for r in sub))
        lines += ["", f"## {preset} ({sub[0]['kind']})", ""]
        head = "| fit | terms | " + " | ".join(
            f"{c} texels | {c} max error | {c} interior" for c in channels
        )
        lines += [head + " |", "|---|---:|" + "---:|" * (3 * len(channels))]
        for fit in dict.fromkeys(r["fit"] for r in sub):
            cells = {r["channel"]: r for r in sub if r["fit"] == fit}
            vals = " | ".join(
                f"{cells[c]['worst_texels']:.2e} | {cells[c]['max_error']:.2e} |"
                f" {cells[c]['max_error_interior']:.2e}"
                for c in channels
            )
            lines.append(f"| {fit} | {cells[channels[0]]['terms']} | {vals} |")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def plot(path: Path, rows: list[dict]) -> None:
    plt = pyplot()
    if plt is None:
        return
    presets = list(dict.fromkeys(r["preset"] for r in rows))
    fig, axes = plt.subplots(1, len(presets), figsize=(6 * len(presets), 4.5), squeeze=False)
    for ax, preset in zip(axes[0], presets, strict=True):
        sub = [r for r in rows if r["preset"] == preset]
        for channel in dict.fromkeys(r["channel"] for r in sub):
            for rational, style in ((False, "o-"), (True, "s--")):
                pts = [
                    r for r in sub if r["channel"] == channel and (r["denominator"] > 0) == rational
                ]
                if pts:
                    ax.semilogy(
                        [r["terms"] for r in pts],
                        [r["max_error_interior"] for r in pts],
                        style,
                        label=f"{channel}, {'rational' if rational else 'polynomial'}",
                    )
        ax.set_title(f"{preset} ({sub[0]['kind']} of ggx)")
        ax.set_xlabel("coefficients per channel")
        ax.set_ylabel("maximum error between the first and last texels")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
