"""The constants of rust/src/math/fastmath.rs: where each one comes from, recomputed.

    python scripts/fastmath_coefficients.py            # print, and check against the file
    python scripts/fastmath_coefficients.py --sollya   # also re-solve the polynomials

**Split and rounded constants** (`SQRT3_F64`, `DP_H_F64`/`DP_L_F64`, `LN2_H32_F64`, ...):
each is a definition, recomputed here bit for bit with mpmath and compared with the file.
A "hi (N bits)" constant is the value truncated toward zero to N significant bits (so
that its product with another short operand is exact), and its "lo" partner is the rest,
rounded to nearest in the constant's format.

**Polynomial coefficients** (`Q64_*`, `Q32_*`, `P64_*`, `P32_*`): each set solves an
approximation problem stated below in `POLYNOMIALS` (a fixed leading part, free
coefficients in binary64 or binary32, an interval and an error measure) with Sollya's
`fpminimax`. The coefficients in the file came from such runs; which Sollya version and
exact options made them was not recorded, and `fpminimax` (a lattice search among
near-equal candidates) gives other low-order bits under other versions or intervals. So
this script does not claim to reproduce them bit for bit: it measures their error on the
stated problem with mpmath and prints it, and with `--sollya` (Debian's `sollya` package)
solves each problem anew and prints that solution and its error next to them. Either set
meets the accuracy fastmath.rs states; a new set goes into the file only together with a
rerun of the accuracy checks described there.

Exit status 1 if a constant in the file differs from its definition or a coefficient set
misses its error bound.
"""

from __future__ import annotations

import argparse
import re
import shutil
import struct
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import mpmath as mp

ROOT = Path(__file__).resolve().parents[1]
FASTMATH = ROOT / "rust" / "src" / "math" / "fastmath.rs"

mp.mp.prec = 300


def f64_bits(x: mp.mpf) -> int:
    return int(struct.unpack("<Q", struct.pack("<d", float(x)))[0])


def f32_bits(x: mp.mpf) -> int:
    # float(x) rounds to binary64 first; at 300 bits in, a double rounding to binary32
    # would need x within 2^-53 relative of a binary32 midpoint, which none of these is.
    return int(struct.unpack("<I", struct.pack("<f", float(x)))[0])


def truncate(x: mp.mpf, bits: int) -> mp.mpf:
    """``x`` truncated toward zero to ``bits`` significant bits."""
    exponent = int(mp.floor(mp.log(abs(x), 2)))
    scale = mp.mpf(2) ** (bits - 1 - exponent)
    return mp.sign(x) * mp.floor(abs(x) * scale) / scale


LOG2_15 = mp.log(mp.mpf(1.5), 2)
CP = 2 / (3 * mp.log(2))
LN2 = mp.log(2)


def constants() -> dict[str, tuple[str, int]]:
    """Every split or rounded constant: name -> (format, bits)."""
    out: dict[str, tuple[str, int]] = {}

    def rounded(name: str, x: mp.mpf, fmt: str) -> None:
        out[name] = (fmt, f64_bits(x) if fmt == "f64" else f32_bits(x))

    def split(hi: str, lo: str, x: mp.mpf, bits: int, fmt: str) -> None:
        h = truncate(x, bits)
        rounded(hi, h, fmt)
        rounded(lo, x - h, fmt)

    for fmt in ("f64", "f32"):
        suffix = fmt.upper()
        rounded(f"SQRT3_{suffix}", mp.sqrt(3), fmt)
        rounded(f"SQRT1P5_{suffix}", mp.sqrt(mp.mpf(1.5)), fmt)
        rounded(f"CP_{suffix}", CP, fmt)
        rounded(f"LN2_{suffix}", LN2, fmt)
        rounded(f"LOG2E_{suffix}", 1 / LN2, fmt)
    # f64: log2(1.5) in 21 bits (added to t1, which holds 21); 2/(3 ln 2) and ln 2 in 32
    # (times a 21-bit operand: exact); ln 2 in 42 for exp's Cody-Waite step (n < 2^11).
    split("DP_H_F64", "DP_L_F64", LOG2_15, 21, "f64")
    split("CP_H_F64", "CP_L_F64", CP, 32, "f64")
    split("LN2_H32_F64", "LN2_L32_F64", LN2, 32, "f64")
    split("LN2_H42_F64", "LN2_L42_F64", LN2, 42, "f64")
    # f32: 12-bit halves (times a 12-bit operand: exact); ln 2 in 16 for exp (n < 2^8).
    split("DP_H_F32", "DP_L_F32", LOG2_15, 12, "f32")
    split("CP_H_F32", "CP_L_F32", CP, 12, "f32")
    split("LN2_H12_F32", "LN2_L12_F32", LN2, 12, "f32")
    split("LN2_H16_F32", "LN2_L16_F32", LN2, 16, "f32")
    return out


#: |s| bound of the log's reduction: s = f/(2c + f) with c + f in [1, sqrt(3/2)] (c = 1)
#: or (sqrt(3/2), sqrt(3)] (c = 1.5).
S_MAX = (mp.sqrt(mp.mpf(1.5)) - 1) / (mp.sqrt(mp.mpf(1.5)) + 1)
#: |z| bound of exp's reduced argument (ln 2 / 2 and the low part's margin).
Z_MAX = mp.mpf("0.3487")


@dataclass(frozen=True)
class Polynomial:
    """Free coefficients c_k of ``fixed + sum_k c_k x^(first + step·k)`` approximating
    ``target`` on ``[-bound, bound]`` under ``error`` ("relative" or "absolute")."""

    prefix: str
    fmt: str  # "f64" or "f32"
    degree: int  # number of free coefficients - 1
    first: int
    step: int
    target: str  # Sollya syntax, in x
    fixed: str  # Sollya syntax, in x
    bound: mp.mpf
    error: str
    #: the error the committed coefficients must stay within
    limit: float
    what: str

    def monomials(self) -> list[int]:
        return [self.first + self.step * k for k in range(self.degree + 1)]

    def target_mp(self, x: mp.mpf) -> mp.mpf:
        return 3 * mp.atanh(x) if self.target.startswith("3*atanh") else mp.exp(x)

    def fixed_mp(self, x: mp.mpf) -> mp.mpf:
        return 3 * x + x**3 if self.fixed == "3*x + x^3" else 1 + x + x**2 / 2

    def max_error(self, coeffs: list[mp.mpf], points: int = 4000) -> mp.mpf:
        worst = mp.mpf(0)
        for i in range(1, points + 1):
            for x in (self.bound * i / points, -self.bound * i / points):
                approx = self.fixed_mp(x) + sum(
                    c * x**m for c, m in zip(coeffs, self.monomials(), strict=True)
                )
                exact = self.target_mp(x)
                err = abs(approx - exact)
                if self.error == "relative":
                    err /= abs(exact)
                worst = max(worst, err)
        return worst

    def sollya(self) -> str:
        fmt = "D" if self.fmt == "f64" else "SG"
        monomials = ",".join(map(str, self.monomials()))
        formats = ",".join([fmt] * (self.degree + 1))
        bound = "(sqrt(1.5)-1)/(sqrt(1.5)+1)" if self.bound == S_MAX else mp.nstr(self.bound, 10)
        return (
            f"p = fpminimax({self.target}, [|{monomials}|], [|{formats}|],"
            f" [-({bound}); {bound}], {self.error}, floating, {self.fixed});\n"
            + "".join(
                f'print("{self.prefix}_{k}", coeff(p, {m}));\n'
                for k, m in enumerate(self.monomials())
            )
        )


POLYNOMIALS = [
    Polynomial(
        "Q64",
        "f64",
        5,
        5,
        2,
        "3*atanh(x)",
        "3*x + x^3",
        S_MAX,
        "relative",
        1e-21,
        "log: ln(1 + f/c) = 2 atanh(s) = (2/3) s (3 + s² + s⁴ Q(s²)), |s| <= 0.10102",
    ),
    Polynomial(
        "Q32",
        "f32",
        1,
        5,
        2,
        "3*atanh(x)",
        "3*x + x^3",
        S_MAX,
        "relative",
        1e-10,
        "log (f32): the same with Q of degree 1 in s²",
    ),
    Polynomial(
        "P64",
        "f64",
        8,
        3,
        1,
        "exp(x)",
        "1 + x + x^2/2",
        Z_MAX,
        "absolute",
        1e-17,
        "exp: e^z = 1 + z + z²/2 + z³ P(z), |z| <= 0.3487",
    ),
    Polynomial(
        "P32",
        "f32",
        3,
        3,
        1,
        "exp(x)",
        "1 + x + x^2/2",
        Z_MAX,
        "absolute",
        1e-8,
        "exp (f32): the same with P of degree 3",
    ),
]


def read_file() -> dict[str, tuple[str, int]]:
    """The file's bit-pattern constants: name -> (format, bits)."""
    text = FASTMATH.read_text(encoding="utf-8")
    pattern = r"const (\w+): (f64|f32) = (?:f64|f32)::from_bits\((0x[0-9a-fA-F_]+)\);"
    return {
        name: (fmt, int(bits.replace("_", ""), 16)) for name, fmt, bits in re.findall(pattern, text)
    }


def value(fmt: str, bits: int) -> mp.mpf:
    if fmt == "f64":
        return mp.mpf(struct.unpack("<d", struct.pack("<Q", bits))[0])
    return mp.mpf(struct.unpack("<f", struct.pack("<I", bits))[0])


def run_sollya(poly: Polynomial) -> list[mp.mpf] | None:
    script = "prec = 300;\nverbosity = 0;\ndisplay = hexadecimal;\n" + poly.sollya() + "quit;\n"
    result = subprocess.run(
        ["sollya", "--warnonstderr"], input=script, capture_output=True, text=True, check=True
    )
    found = dict(re.findall(r"^(\w+_\d+) (\S+)$", result.stdout, re.M))
    if len(found) != poly.degree + 1:
        return None
    return [mp.mpf(float.fromhex(found[f"{poly.prefix}_{k}"])) for k in range(poly.degree + 1)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--sollya", action="store_true", help="also solve each polynomial problem with Sollya"
    )
    args = parser.parse_args()
    if args.sollya and shutil.which("sollya") is None:
        parser.error("--sollya: no sollya on PATH (Debian: apt-get install sollya)")
    in_file = read_file()
    failed = False

    print("Split and rounded constants (definition -> bits; = matches fastmath.rs):")
    for name, (fmt, bits) in constants().items():
        width = 16 if fmt == "f64" else 8
        if name not in in_file:
            mark = "(not in the file)"
        elif in_file[name] == (fmt, bits):
            mark = "="
        else:
            mark = f"DIFFERS: the file has 0x{in_file[name][1]:0{width}x}"
            failed = True
        print(f"  {name:<12} {fmt}::from_bits(0x{bits:0{width}x})  {mark}")

    for poly in POLYNOMIALS:
        names = [f"{poly.prefix}_{k}" for k in range(poly.degree + 1)]
        print(f"\n{poly.prefix}: {poly.what}; {poly.error} error on the interval.")
        print(f"  Sollya: {poly.sollya().splitlines()[0]}")
        if not all(n in in_file for n in names):
            print("  (not in the file)")
            continue
        committed = [value(*in_file[n]) for n in names]
        err = poly.max_error(committed)
        ok = err <= poly.limit
        failed |= not ok
        verdict = "within" if ok else "MISSES"
        print(f"  fastmath.rs: max error {mp.nstr(err, 4)} ({verdict} {poly.limit:g})")
        if args.sollya:
            fresh = run_sollya(poly)
            if fresh is None:
                print("  Sollya gave no solution")
                continue
            print(f"  Sollya now: max error {mp.nstr(poly.max_error(fresh), 4)}")
            for name, old, new in zip(names, committed, fresh, strict=True):
                same = "=" if old == new else f"(file: {float(old).hex()})"
                print(f"    {name} = {float(new).hex()}  {same}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
