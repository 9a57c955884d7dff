"""The error budget of every engine LUT preset at its own resolution, format and sample
count (brdf_rs.lut), and of each preset's table in the other pixel formats.

    python benches/lut_budgets.py              # every preset (the glTF one, 1024 x 1024,
                                                # takes about two minutes)
    python benches/lut_budgets.py filament ue5  # only these

For each preset it prints, per channel: the largest Monte Carlo standard error of a
texel, the exact worst and RMS quantization error of the preset's format and of the
other formats of the same channel count (quantize, decode, compare with the float64
integrals), the worst bilinear (3-D: trilinear) interpolation error against the integral at
points between the texels (at most 64 per axis: midpoints between neighbouring texels
and the range ends; the reference integrals' own standard error alongside), and the
total (quantization + interpolation + 3 standard errors of the reference and 3 of the
texels: a per-point estimate at 3 sigma, not a bound over the whole table). Writes
benches/results/lut_budgets.md; docs/luts.md quotes it. With matplotlib installed it
also draws each preset's decoded texels (``brdf_rs.plot.lut_texels``) into
docs/luts/PRESET.png, the pictures docs/luts.md shows (``--pictures DIR`` elsewhere,
``--pictures ''`` for none).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from _plot import pyplot
from brdf_rs import __version__, lut

FIT_DEGREE = 6
OUT = Path(__file__).resolve().parent / "results" / "lut_budgets.md"
PICTURES = Path(__file__).resolve().parent.parent / "docs" / "luts"


def small(path: Path) -> None:
    """Rewrites a picture with a palette of 128 colours (a third of the bytes, for the
    docs' size budget), when Pillow is installed."""
    try:
        from PIL import Image
    except ImportError:
        return
    with Image.open(path) as image:
        quantized = image.convert("RGB").quantize(colors=128)
    quantized.save(path, optimize=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("presets", nargs="*", default=list(lut.PRESETS))
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--pictures", default=str(PICTURES))
    args = parser.parse_args()
    plt = pyplot() if args.pictures else None
    lines = [
        "# Engine LUT error budgets",
        "",
        f"`python benches/lut_budgets.py` (brdf-rs {__version__}): each preset at its own"
        " resolution, format and samples per texel. Errors are absolute, per channel;"
        " total = quantization worst + interpolation worst + 3 x the reference integrals'"
        " largest standard error + 3 x the texels' largest standard error, an estimate at"
        " 3 sigma per point checked, not a bound over the whole table. The interpolation"
        " worst is measured against Monte Carlo integrals: it holds both sides' noise.",
        "",
    ]
    for name in args.presets:
        spec = lut.preset(name)
        start = time.perf_counter()
        table = lut.build(spec)
        seconds = time.perf_counter() - start
        b = table.budget
        if plt is not None:
            from brdf_rs import plot

            picture = Path(args.pictures) / f"{name}.png"
            picture.parent.mkdir(parents=True, exist_ok=True)
            plot.lut_texels(table, path=picture, dpi=80)
            small(picture)
            print(f"wrote {picture}")
        size = " x ".join(str(n) for n in spec.shape[::-1])
        at = f"mu, {spec.param}" + (f", {spec.layers.role}" if spec.layers is not None else "")
        lines += [
            f"## {name}",
            "",
            f"{spec.kind} of {spec.model}, {size} {spec.format}, {spec.samples} samples per"
            f" texel, built and checked in {seconds:.1f} s; interpolation checked at"
            f" {b.interp_points} points.",
            "",
            f"| channel | MC stderr (max) | quant worst | quant RMS | interp worst (at {at})"
            " | interp worst between first and last texels | reference stderr (max) | total |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for k, c in enumerate(b.channels):
            where = ", ".join(f"{v:.3g}" for v in b.interp_worst_at[k])
            lines.append(
                f"| {c} | {b.mc_max_stderr[k]:.2e} | {b.quant_worst[k]:.2e}"
                f" | {b.quant_rms[k]:.2e} | {b.interp_worst[k]:.2e} (at {where})"
                f" | {b.interp_worst_interior[k]:.2e} | {b.interp_ref_stderr[k]:.2e}"
                f" | {b.total[k]:.2e} |"
            )
        lines += ["", "Quantization worst in the other formats:", ""]
        nc = len(b.channels)
        for fmt in lut.FORMATS.values():
            if fmt.channels != nc:
                continue
            _, decoded = lut.quantize(table.image, fmt.name)
            err = np.abs(decoded - table.image).reshape(-1, nc).max(axis=0)
            lines.append(f"- {fmt.name}: " + ", ".join(f"{v:.2e}" for v in err))
        if spec.layers is not None:  # fits take 2-D tables
            lines.append("")
            print("\n".join(lines[-(12 + nc) :]), flush=True)
            continue
        fitted = lut.fit(table, FIT_DEGREE)
        lines += [
            "",
            f"Degree-{FIT_DEGREE} minimax polynomial fit (`--fit {FIT_DEGREE}`), worst against"
            " the texels / against the integrals between them / its maximum error over the"
            " whole range (texels, between them and a denser grid, 3 stderr and float32"
            " rounding included):",
            "",
        ]
        for k, c in enumerate(b.channels):
            lines.append(
                f"- {c}: {fitted.worst_texels[k]:.2e} / {fitted.worst_between[k]:.2e} /"
                f" {fitted.max_error[k]:.2e}"
            )
        lines.append("")
        print("\n".join(lines[-(17 + 2 * nc) :]), flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
