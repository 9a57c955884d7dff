"""Generates test vectors with mpmath references for fastmath's `pow_unit_*`.

Writes a little-endian binary file of rows of 8 f64: kind, x, one_minus_x, p, d, m_hi,
m_lo, e, where the reference value is (m_hi + m_lo) 2^e with m_hi in [1, 2) (or all zero
for a zero reference), computed at 50 digits from the exact inputs:

* x > sqrt(3)/2 (in the input's precision): (1 - one_minus_x)^p, one_minus_x exact, as
  the functions' contract says; otherwise x^p. Divided by d for the `over` kinds.
* kind 0: f64 pow_unit_f64, 1: f64 pow_unit_over_f64, 2: f32 pow_unit_f32,
  3: f32 pow_unit_over_f32 (f32 kinds hold f32 values widened to f64).

Input families (each kind): uniform and log-uniform x with |p log2 x| log-uniform up to
1100 (f32: 150); x = 1 - 2^-k with one_minus_x = 2^-k exact (k = 1..60, f32: 1..24);
one_minus_x = 1e-9 with p up to 1.5e12; one_minus_x log-uniform down to 1e-320 (f32:
1e-45) with p up to 1e300 (f32: 3e38); subnormal x; p log-uniform over the whole range
[1e-300, 1e300] with uniform x (mostly results 0 or 1); results in the subnormal range;
for the `over` kinds, d log-uniform and results up to the overflow threshold.

    python scripts/gen_pow_fixture.py OUT.bin N_PER_KIND [SEED]

rust/src/math/pow_fixture.bin (read by fastmath's tests) is `... 5000 1`.
"""

from __future__ import annotations

import random
import struct
import sys

import mpmath as mp
import numpy as np

mp.mp.dps = 50
SQRT3_HALF = float(mp.sqrt(3) / 2)


def f32(v: float) -> float:
    return float(np.float32(v))


def ref_parts(x, omc, p, d, is32):
    """(m_hi, m_lo, e) of the exact x^p / d."""
    if p == 0:
        v = mp.mpf(1)
    elif x == 0:
        return 0.0, 0.0, 0.0
    else:
        near = (f32(x) > f32(SQRT3_HALF)) if is32 else (x > SQRT3_HALF)
        if near:
            if omc == 0:
                v = mp.mpf(1)
            else:
                v = mp.exp(mp.mpf(p) * mp.log1p(-mp.mpf(omc)))
        else:
            v = mp.exp(mp.mpf(p) * mp.log(mp.mpf(x)))
    v = v / mp.mpf(d)
    if v == 0:
        return 0.0, 0.0, 0.0
    m, e = mp.frexp(v)  # v = m 2^e, m in [0.5, 1)
    m *= 2
    e -= 1
    hi = float(m)
    lo = float(m - mp.mpf(hi))
    return hi, lo, float(e)


def cases(kind: int, n: int, rng: random.Random):
    is32 = kind >= 2
    over = kind in (1, 3)
    ymax = 150.0 if is32 else 1100.0
    pmax = 3e38 if is32 else 1e300
    omc_min_exp = -45 if is32 else -320
    kmax = 24 if is32 else 60
    cvt = f32 if is32 else (lambda v: v)
    out = []

    def add(x, omc, p, d=1.0):
        x, omc, p, d = cvt(x), cvt(omc), cvt(p), cvt(d)
        if not (0 <= x <= 1) or p < 0 or d <= 0 or p == float("inf") or d == float("inf"):
            return
        out.append((x, omc, p, d))

    def rand_d():
        if not over:
            return 1.0
        lo, hi = (-45, 38) if is32 else (-320, 300)
        return 10.0 ** rng.uniform(lo, hi)

    def log2(v):
        return float(mp.log(mp.mpf(v), 2))

    def log2_1m(omc):  # log2(1 - omc), exact omc
        return float(mp.log1p(-mp.mpf(omc)) / mp.log(2))

    fam = 0
    while len(out) < n:
        fam = (fam + 1) % 9
        if fam == 0:  # uniform x, |y| log-uniform
            x = cvt(rng.random())
            if x == 0:
                continue
            y = 10.0 ** rng.uniform(-6, np.log10(ymax))
            add(x, 1 - x, y / max(-log2(x), 1e-300), rand_d())
        elif fam == 1:  # log-uniform x
            x = 10.0 ** rng.uniform(-40 if is32 else -300, 0)
            x = cvt(x)
            if x == 0 or x >= 1:
                continue
            y = 10.0 ** rng.uniform(-6, np.log10(ymax))
            add(x, 1 - x, y / -log2(x), rand_d())
        elif fam == 2:  # x = 1 - 2^-k, omc exact
            k = rng.randint(1, kmax)
            omc = 2.0**-k
            y = 10.0 ** rng.uniform(-6, np.log10(ymax))
            add(1 - omc, omc, y / -log2_1m(omc), rand_d())
        elif fam == 3:  # omc = 1e-9, p up to 1.5e12
            omc = cvt(1e-9)
            add(1 - omc, omc, 10.0 ** rng.uniform(0, np.log10(1.5e12)), rand_d())
        elif fam == 4:  # omc log-uniform down to subnormal, p up to pmax
            omc = cvt(10.0 ** rng.uniform(omc_min_exp, -1))
            if omc == 0:
                continue
            if rng.random() < 0.5:
                p = 10.0 ** rng.uniform(0, np.log10(pmax))
            else:
                y = 10.0 ** rng.uniform(-6, np.log10(ymax))
                p = min(pmax, y / -log2_1m(omc))
            add(1 - omc, omc, p, rand_d())
        elif fam == 5:  # subnormal x
            if is32:
                x = float(np.frombuffer(struct.pack("<I", rng.randint(1, (1 << 23) - 1)), np.float32)[0])
            else:
                x = struct.unpack("<d", struct.pack("<Q", rng.randint(1, (1 << 52) - 1)))[0]
            y = 10.0 ** rng.uniform(-6, np.log10(ymax))
            add(x, 1 - x, y / -log2(x), rand_d())
        elif fam == 6:  # p over the whole range, uniform x
            x = cvt(rng.random())
            add(x, 1 - x, 10.0 ** rng.uniform(-40 if is32 else -300, np.log10(pmax)), rand_d())
        elif fam == 7:  # results in the subnormal range
            x = cvt(rng.uniform(0.001, 0.999999))
            lo, hi = (126, 150) if is32 else (1022, 1075)
            y = rng.uniform(lo, hi)
            d = 1.0
            if over:  # x^p / d in the subnormal range with d not 1
                d = 2.0 ** rng.uniform(-20, 20)
                y = y - log2(d)
            add(x, 1 - x, y / -log2(x), d)
        else:  # over: results near overflow; pow: x near 1 with moderate p
            x = cvt(rng.uniform(0.2, 0.999))
            if over:
                top = 128 if is32 else 1024
                y = rng.uniform(0.001, 30)
                # x^p / d = 2^(top - delta), delta in (-0.01, 2)
                delta = rng.uniform(-0.01, 2)
                log2d = -y - (top - delta)
                d = 2.0**log2d
                if d == 0:
                    continue
                add(x, 1 - x, y / -log2(x), d)
            else:
                omc = cvt(rng.uniform(0, 0.13))
                add(1 - omc, omc, 10.0 ** rng.uniform(-3, 6), 1.0)
    return out[:n]


def main() -> None:
    path, n = sys.argv[1], int(sys.argv[2])
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    rng = random.Random(seed)
    rows = []
    for kind in range(4):
        for x, omc, p, d in cases(kind, n, rng):
            rows.append((float(kind), x, omc, p, d, *ref_parts(x, omc, p, d, kind >= 2)))
    with open(path, "wb") as f:
        for r in rows:
            f.write(struct.pack("<8d", *r))
    print(f"wrote {len(rows)} rows to {path}")


if __name__ == "__main__":
    main()
