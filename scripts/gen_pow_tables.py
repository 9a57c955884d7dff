"""Generates rust/src/math/pow_tables.rs: the tables and polynomial coefficients of the
table-driven x^p in rust/src/math/fastmath.rs (included there with `include!`).

The scheme is the one of ARM optimized-routines' `pow` (no-FMA variant), regenerated here
with mpmath at 60 digits:

* Logarithm, N = 128 entries. x = 2^k z with z in [OFF, 2 OFF), OFF = 0x3fe6955500000000
  (about 0.7051); the entry index is bits 45..51 of bits(x) - OFF, so the entries cover
  equal steps of the mantissa (2^-8 below 1, 2^-7 above). For entry i with interval centre
  m: invc = round(N/m)/N if m < 1 else round(2N/m)/(2N) (at most 9 significant bits, so
  z_hi * invc - 1 is exact for a 21-bit z_hi), c = 1/invc; the entry whose interval holds
  1.0 gets c = 1 exactly (no cancellation near x = 1). logc = log(c) rounded to a multiple
  of 2^-42, so that k * ln2_hi + logc is exact for |k| < 2^11 (ln2_hi has 42 bits);
  logctail = log(c) - logc rounded to a double.
  log1p(r) = r - r^2/2 + r^3 Q(r), Q of degree 5, minimax for relative error of log1p on
  |r| <= the largest |z/c - 1| over all entries (printed), by Lawson's iteration on a dense
  grid; the coefficients are emitted pre-scaled as in the evaluation
  (A1 + A2 r + ar2 (A3 + A4 r + ar2 (A5 + A6 r)), ar2 = -r^2/2).
* Exponential, N = 128 entries: 2^(i/128) = s_i (1 + tail_i), s_i the rounded double.
  e^r = 1 + r + r^2 (C2 + C3 r + C4 r^2 + C5 r^3), minimax for relative error on
  |r| <= ln2/256 + 2^-14 (the low part of y widens the nominal range a little).
  ln2/128 is split into a 34-bit high part (kd * hi is exact for |kd| < 2^19) and a low part.

Every value is printed as a bit-exact `f64::from_bits(0x...)` literal with its decimal value
in a comment. Run from the repository root:

    python scripts/gen_pow_tables.py            # rewrites rust/src/math/pow_tables.rs
"""

from __future__ import annotations

import struct
from pathlib import Path

import mpmath as mp

mp.mp.dps = 60

N = 128
OFF = 0x3FE6955500000000


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def from_bits(b: int) -> float:
    return struct.unpack("<d", struct.pack("<Q", b))[0]


def lit(x: float) -> str:
    return f"f64::from_bits(0x{bits(x):016x})"


def lawson(f, basis, weight, a, b, npts=1200, iters=40):
    """Near-minimax fit of f by sum c_j basis_j on [a, b], minimizing max |weight (f - fit)|
    (Lawson's iteratively reweighted least squares on Chebyshev-like points)."""
    xs = [a + (b - a) * (1 - mp.cos(mp.pi * (i + 0.5) / npts)) / 2 for i in range(npts)]
    fx = [f(x) for x in xs]
    wx = [weight(x) for x in xs]
    bx = [[g(x) for g in basis] for x in xs]
    m = len(basis)
    lw = [mp.mpf(1) / npts] * npts
    coeffs = None
    for _ in range(iters):
        ata = mp.matrix(m, m)
        atb = mp.matrix(m, 1)
        for i in range(npts):
            w = lw[i] * wx[i] ** 2
            row = bx[i]
            for j in range(m):
                atb[j] += w * row[j] * fx[i]
                for k in range(j, m):
                    ata[j, k] += w * row[j] * row[k]
        for j in range(m):
            for k in range(j):
                ata[j, k] = ata[k, j]
        coeffs = mp.lu_solve(ata, atb)
        errs = [
            abs(wx[i] * (fx[i] - sum(coeffs[j] * bx[i][j] for j in range(m)))) for i in range(npts)
        ]
        tot = sum(lw[i] * errs[i] for i in range(npts))
        lw = [lw[i] * errs[i] / tot for i in range(npts)]
    return [coeffs[j] for j in range(m)]


def max_rel_err(exact, approx, a, b, npts=4001):
    worst = mp.mpf(0)
    for i in range(npts):
        x = mp.mpf(a) + (mp.mpf(b) - mp.mpf(a)) * i / (npts - 1)
        if x == 0:
            continue
        e = exact(x)
        worst = max(worst, abs((approx(x) - e) / e))
    return worst


def log_table():
    invc, logc, logctail = [], [], []
    rmax = mp.mpf(0)
    one_idx = ((bits(1.0) - OFF) >> 45) % N
    for i in range(N):
        lo = from_bits(OFF + (i << 45))
        hi = from_bits(OFF + ((i + 1) << 45))
        centre = (mp.mpf(lo) + mp.mpf(hi)) / 2
        if i == one_idx:
            ic = 1.0
        elif centre < 1:
            ic = float(mp.nint(N / centre) / N)
        else:
            ic = float(mp.nint(2 * N / centre) / (2 * N))
        c = 1 / mp.mpf(ic)
        lc = mp.log(c)
        lch = float(mp.nint(lc * 2**42) / 2**42)
        lct = float(lc - lch)
        invc.append(ic)
        logc.append(lch)
        logctail.append(lct)
        for z in (lo, hi):
            rmax = max(rmax, abs(mp.mpf(z) * mp.mpf(ic) - 1))
    return invc, logc, logctail, rmax, one_idx


def main() -> None:
    invc, logc, logctail, rmax, one_idx = log_table()
    R = float(rmax) * 1.001

    # log1p(r) = r - r^2/2 + r^3 Q(r): fit Q with weight r^2 / log1p(r) ~ r (relative error).
    def q_exact(r):
        if abs(r) < mp.mpf(10) ** -15:
            return mp.mpf(1) / 3 - r / 4 + r * r / 5
        return (mp.log1p(r) - r + r * r / 2) / r**3

    def rel_weight_log(r):
        return r**3 / mp.log1p(r) if r != 0 else mp.mpf(0)

    q = lawson(q_exact, [lambda r, j=j: r**j for j in range(6)], rel_weight_log, -R, R)
    qd = [float(c) for c in q]
    log_err = max_rel_err(
        mp.log1p,
        lambda r: r - r * r / 2 + r**3 * sum(mp.mpf(qd[j]) * r**j for j in range(6)),
        -R,
        R,
    )
    scale = [-2, -2, 4, 4, -8, -8]
    a = [qd[j] * scale[j] for j in range(6)]

    # exp
    ln2 = mp.log(2)
    RE = float(ln2 / 256) + 2.0**-14

    def e_exact(r):
        if abs(r) < mp.mpf(10) ** -15:
            return mp.mpf(1) / 2 + r / 6 + r * r / 24
        return (mp.exp(r) - 1 - r) / r**2

    def rel_weight_exp(r):
        return r**2 / mp.exp(r)

    c = lawson(e_exact, [lambda r, j=j: r**j for j in range(4)], rel_weight_exp, -RE, RE)
    cd = [float(v) for v in c]
    exp_err = max_rel_err(
        mp.exp, lambda r: 1 + r + r * r * sum(mp.mpf(cd[j]) * r**j for j in range(4)), -RE, RE
    )
    exp_s, exp_tail = [], []
    for i in range(N):
        v = mp.mpf(2) ** (mp.mpf(i) / N)
        s = float(v)
        exp_s.append(s)
        exp_tail.append(float(v / mp.mpf(s) - 1))

    ln2n = ln2 / N
    # 34 significant bits: kd * hi exact for |kd| < 2^19
    e2 = int(mp.floor(mp.log(ln2n, 2)))
    ulp = mp.mpf(2) ** (e2 - 33)
    ln2n_hi = float(mp.nint(ln2n / ulp) * ulp)
    ln2n_lo = float(ln2n - mp.mpf(ln2n_hi))
    ln2_hi = from_bits(0x3FE62E42FEFA3800)  # 42 bits
    ln2_lo = float(ln2 - mp.mpf(ln2_hi))

    out = []
    w = out.append
    w("// Generated by scripts/gen_pow_tables.py: do not edit by hand.")
    w("// Tables and coefficients of the table-driven pow in fastmath.rs (see its docs).")
    w("")
    w("/// Index of the logarithm entry whose interval holds 1.0 (c = 1 exactly).")
    w("#[allow(dead_code)]")
    w(f"const LOG_ONE_INDEX: usize = {one_idx};")
    w(f"/// Largest |z/c - 1| over the logarithm entries: {float(rmax)!r}.")
    w("#[allow(dead_code)]")
    w(f"const LOG_R_MAX: f64 = {float(rmax)!r};")
    w(f"const LN2_HI: f64 = {lit(ln2_hi)}; // {ln2_hi!r} ln 2, 42 bits")
    w(f"const LN2_LO: f64 = {lit(ln2_lo)}; // {ln2_lo!r}")
    w(f"const INV_LN2_N: f64 = {lit(float(N / ln2))}; // {float(N / ln2)!r} 128/ln 2")
    w(f"const LN2_N_HI: f64 = {lit(ln2n_hi)}; // {ln2n_hi!r} ln2/128, 34 bits")
    w(f"const LN2_N_LO: f64 = {lit(ln2n_lo)}; // {ln2n_lo!r}")
    w("/// log1p(r) - r + r^2/2 = ar3 (A1 + A2 r + ar2 (A3 + A4 r + ar2 (A5 + A6 r))),")
    w(f"/// ar2 = -r^2/2, ar3 = -r^3/2; max relative error of log1p {float(log_err):.3e}")
    w(f"/// (2^{float(mp.log(log_err, 2)):.1f}) on |r| <= {R!r}.")
    w("const LOG_A: [f64; 6] = [")
    for v in a:
        w(f"    {lit(v)}, // {v!r}")
    w("];")
    w("/// e^r = 1 + r + r^2 (C2 + C3 r + C4 r^2 + C5 r^3); max relative error")
    w(f"/// {float(exp_err):.3e} (2^{float(mp.log(exp_err, 2)):.1f}) on |r| <= {RE!r}.")
    w("const EXP_C: [f64; 4] = [")
    for v in cd:
        w(f"    {lit(v)}, // {v!r}")
    w("];")

    def table(name, doc, vals):
        w(f"/// {doc}")
        w(f"static {name}: [f64; {N}] = [")
        for v in vals:
            w(f"    {lit(v)}, // {v!r}")
        w("];")

    table("LOG_INVC", "1/c per logarithm entry (at most 9 significant bits).", invc)
    table("LOG_LOGC", "log(c) rounded to a multiple of 2^-42.", logc)
    table("LOG_LOGCTAIL", "log(c) - logc.", logctail)
    table("EXP_S", "2^(i/128) rounded to a double.", exp_s)
    table("EXP_TAIL", "2^(i/128) / s_i - 1.", exp_tail)

    path = Path(__file__).resolve().parent.parent / "rust" / "src" / "math" / "pow_tables.rs"
    path.write_text("\n".join(out) + "\n")
    print(
        f"wrote {path.name}: r_max {float(rmax)!r}, log rel err 2^{float(mp.log(log_err, 2)):.1f}, "
        f"exp 2^{float(mp.log(exp_err, 2)):.1f}"
    )


if __name__ == "__main__":
    main()
