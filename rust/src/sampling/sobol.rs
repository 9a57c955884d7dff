//! Two-dimensional Owen-scrambled Sobol points, generated a block at a time in
//! branch-free integer code that vectorizes across points.
//!
//! The construction is Burley's (2020): Sobol integers scrambled by the hash-based
//! approximation of Owen scrambling, using `sobol_burley`'s own scramble and hash
//! (`sobol_burley::parts`), so the points are that crate's (un-shuffled) sequence.
//! The first two Sobol dimensions have closed-form generator matrices (the identity and
//! Pascal's triangle mod 2), computed here for all 32 index bits: a replicate can hold up
//! to 2^32 points, and every power-of-two prefix is a (0, m, 2)-net, which is what
//! adaptive doubling needs. (The crate's sampler shuffles indices and stops at 2^16.)

use sobol_burley::parts::{hash, owen_scramble_rev};

/// Returns the bit-reversed Sobol integers of dimensions 0 and 1 for `index`.
///
/// Dimension 0 reversed is the index itself; dimension 1 reversed is the index times
/// Pascal's matrix mod 2: bit `j` is the parity of the set index bits `k ⊇ j` (Lucas's
/// theorem), a superset-parity transform done in five shift/mask/xor steps.
#[inline(always)]
pub fn sobol2_rev(index: u32) -> (u32, u32) {
    let mut x = index;
    x ^= (x >> 1) & 0x5555_5555;
    x ^= (x >> 2) & 0x3333_3333;
    x ^= (x >> 4) & 0x0F0F_0F0F;
    x ^= (x >> 8) & 0x00FF_00FF;
    x ^= (x >> 16) & 0x0000_FFFF;
    (index, x)
}

/// The two scramble keys of a replicate keyed by `seed` (as `sobol_burley::sample` derives
/// them for dimensions 0 and 1).
#[inline]
pub fn scramble_keys(seed: u32) -> [u32; 2] {
    let s = seed.wrapping_mul(0x9c8f_2d3b);
    [hash(s ^ 0x912f_69ba), hash(s ^ 0x174f_18ab)]
}

/// The direction numbers of Sobol dimension 2 (Joe & Kuo's third: primitive polynomial
/// `x² + x + 1`, initial `m = 1, 3`), bit-reversed: entry `j` is XORed in when bit `j`
/// of the index is set, giving the reversed Sobol integer as [`sobol2_rev`] does.
const DIM2_REV: [u32; 32] = {
    let mut m = [0u64; 33];
    m[1] = 1;
    m[2] = 3;
    let mut k = 3;
    while k <= 32 {
        m[k] = (2 * m[k - 1]) ^ (4 * m[k - 2]) ^ m[k - 2];
        k += 1;
    }
    let mut out = [0u32; 32];
    let mut j = 0;
    while j < 32 {
        out[j] = ((m[j + 1] << (31 - j)) as u32).reverse_bits();
        j += 1;
    }
    out
};

/// `DIM2_REV[0] ^ … ^ DIM2_REV[t]`: going from index `i` to `i + 1` clears the trailing
/// ones of `i` and sets the next bit, `t = trailing_zeros(i + 1)`, so the Sobol integer
/// changes by this prefix XOR.
const DIM2_REV_PREFIX: [u32; 32] = {
    let mut out = [0u32; 32];
    let mut acc = 0u32;
    let mut j = 0;
    while j < 32 {
        acc ^= DIM2_REV[j];
        out[j] = acc;
        j += 1;
    }
    out
};

/// Returns the bit-reversed Sobol integer of dimension 2 for `index` (a branch-free XOR
/// of the direction numbers of the set index bits).
#[inline(always)]
pub fn sobol_dim2_rev(index: u32) -> u32 {
    let mut x = 0u32;
    for (j, d) in DIM2_REV.iter().enumerate() {
        x ^= d & 0u32.wrapping_sub((index >> j) & 1);
    }
    x
}

/// The scramble key of dimension 2 of a replicate keyed by `seed` (independent of the
/// keys of dimensions 0 and 1).
#[inline]
pub fn scramble_key_dim2(seed: u32) -> u32 {
    let s = seed.wrapping_mul(0x9c8f_2d3b);
    hash(s ^ 0x5bd1_e995)
}

/// Returns point `index` of the scrambled sequence with keys `keys`, in `[0, 1)²`.
#[inline(always)]
pub fn point(index: u32, keys: [u32; 2]) -> [f64; 2] {
    let (d0, d1) = sobol2_rev(index);
    let x = owen_scramble_rev(d0, keys[0]).reverse_bits();
    let y = owen_scramble_rev(d1, keys[1]).reverse_bits();
    const SCALE: f64 = 1.0 / 4_294_967_296.0;
    [f64::from(x) * SCALE, f64::from(y) * SCALE]
}

/// Fills `u0`, `u1` with points `first ..` of the sequence (as many as `u0` holds).
#[inline(always)]
pub fn fill(first: u32, keys: [u32; 2], u0: &mut [f64], u1: &mut [f64]) {
    for (j, (a, b)) in u0.iter_mut().zip(u1.iter_mut()).enumerate() {
        let [x, y] = point(first.wrapping_add(j as u32), keys);
        *a = x;
        *b = y;
    }
}

/// Fills `u0`, `u1`, `u2` with the three-dimensional points `first ..` (dimensions 0
/// and 1 exactly as [`fill`]; dimension 2 scrambled with `key2`).
#[inline(always)]
pub fn fill3(
    first: u32,
    keys: [u32; 2],
    key2: u32,
    u0: &mut [f64],
    u1: &mut [f64],
    u2: &mut [f64],
) {
    fill(first, keys, u0, u1);
    const SCALE: f64 = 1.0 / 4_294_967_296.0;
    // The first integer in full, then one XOR per point (see DIM2_REV_PREFIX).
    let mut d2 = sobol_dim2_rev(first);
    for (j, c) in u2.iter_mut().enumerate() {
        if j > 0 {
            let index = first.wrapping_add(j as u32);
            d2 ^= DIM2_REV_PREFIX[index.trailing_zeros() as usize & 31];
        }
        *c = f64::from(owen_scramble_rev(d2, key2).reverse_bits()) * SCALE;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sobol_burley::parts::sobol_rev;

    #[test]
    fn generator_matrices_match_sobol_burley() {
        // sobol_burley stores 16 direction numbers: compare on 16-bit indices.
        for i in 0..(1u32 << 16) {
            let (d0, d1) = sobol2_rev(i);
            let rev = i.reverse_bits();
            assert_eq!(d0, sobol_rev(rev, 0), "dim 0, index {i}");
            assert_eq!(d1, sobol_rev(rev, 1), "dim 1, index {i}");
            assert_eq!(sobol_dim2_rev(i), sobol_rev(rev, 2), "dim 2, index {i}");
            // The incremental update of fill3 gives the same integers.
            if i > 0 {
                let step = DIM2_REV_PREFIX[i.trailing_zeros() as usize];
                assert_eq!(sobol_dim2_rev(i - 1) ^ step, sobol_dim2_rev(i), "index {i}");
            }
        }
    }

    #[test]
    fn every_power_of_two_prefix_is_a_net() {
        let keys = scramble_keys(12345);
        for m in [4u32, 8, 10] {
            let n = 1usize << m;
            // Every elementary interval of area 2^-m (2^a × 2^(m−a) boxes) holds one point.
            for a in 0..=m {
                let mut seen = vec![false; n];
                for i in 0..n as u32 {
                    let [x, y] = point(i, keys);
                    let cx = (x * f64::from(1u32 << a)) as usize;
                    let cy = (y * f64::from(1u32 << (m - a))) as usize;
                    let cell = cx * (1 << (m - a)) + cy;
                    assert!(!seen[cell], "m={m} a={a}: two points in one box");
                    seen[cell] = true;
                }
            }
        }
    }
}
