//! Sample streams, keyed by (seed, cell, replicate) so results never depend on how cells
//! are split between threads, chunks or machines.
//!
//! - Randomized quasi-Monte Carlo: Owen-scrambled Sobol points ([`super::sobol`]:
//!   Burley 2020, `sobol_burley`'s scramble), one independent scramble per replicate, up
//!   to 2^32 points each.
//! - Monte Carlo: PCG-64 (MCG variant, `rand_pcg`) seeded per (seed, cell, replicate).

use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

use super::sobol;

/// The most points one Sobol replicate can hold.
pub const SOBOL_MAX_POINTS: u64 = 1 << 32;

/// How sample points are generated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sequence {
    /// Independent uniform points.
    Random,
    /// Owen-scrambled Sobol points.
    Sobol,
}

impl Sequence {
    /// Every sequence, in the order the interfaces list them.
    pub const ALL: [Sequence; 2] = [Sequence::Sobol, Sequence::Random];
    /// Their names, in the same order.
    pub const NAMES: [&'static str; 2] = ["sobol", "random"];

    /// Parses `"random"` or `"sobol"`.
    pub fn from_name(name: &str) -> Option<Sequence> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Returns the name.
    pub fn name(self) -> &'static str {
        match self {
            Sequence::Sobol => Self::NAMES[0],
            Sequence::Random => Self::NAMES[1],
        }
    }
}

/// Mixes three 64-bit keys into one well-spread 64-bit value (SplitMix64 finalizer).
pub fn mix(seed: u64, cell: u64, replicate: u64) -> u64 {
    let mut z = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(cell.wrapping_mul(0xBF58_476D_1CE4_E5B9))
        .wrapping_add(replicate.wrapping_mul(0x94D0_49BB_1331_11EB))
        .wrapping_add(0x2545_F491_4F6C_DD1D);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The points of one replicate of one cell.
pub enum Stream {
    Sobol {
        keys: [u32; 2],
        key2: u32,
        next: u64,
    },
    Random(Box<Pcg64Mcg>),
}

impl Stream {
    /// Returns the stream of replicate `replicate` of cell `cell` under `seed`.
    pub fn new(sequence: Sequence, seed: u64, cell: u64, replicate: u64) -> Stream {
        let key = mix(seed, cell, replicate);
        match sequence {
            Sequence::Sobol => Stream::Sobol {
                keys: sobol::scramble_keys((key ^ (key >> 32)) as u32),
                key2: sobol::scramble_key_dim2((key ^ (key >> 32)) as u32),
                next: 0,
            },
            Sequence::Random => Stream::Random(Box::new(Pcg64Mcg::seed_from_u64(key))),
        }
    }

    /// Returns the next point in `[0, 1)²`.
    #[inline]
    pub fn next_point(&mut self) -> [f64; 2] {
        let (mut a, mut b) = ([0.0], [0.0]);
        self.fill(&mut a, &mut b);
        [a[0], b[0]]
    }

    /// Fills `u0`, `u1` with the next points (as many as `u0` holds).
    ///
    /// # Panics
    /// When a Sobol replicate would pass 2^32 points (the integrator never asks).
    #[inline(always)]
    pub fn fill(&mut self, u0: &mut [f64], u1: &mut [f64]) {
        match self {
            Stream::Sobol { keys, next, .. } => {
                assert!(
                    *next + u0.len() as u64 <= SOBOL_MAX_POINTS,
                    "Sobol replicate exhausted"
                );
                sobol::fill(*next as u32, *keys, u0, u1);
                *next += u0.len() as u64;
            }
            Stream::Random(rng) => {
                for (a, b) in u0.iter_mut().zip(u1.iter_mut()) {
                    *a = unit(rng.next_u64());
                    *b = unit(rng.next_u64());
                }
            }
        }
    }
}

impl Stream {
    /// Fills `u0`, `u1`, `u2` with the next three-dimensional points (as many as `u0`
    /// holds): for Sobol, `u0` and `u1` are exactly what [`Stream::fill`] gives and `u2`
    /// is Sobol dimension 2 under its own scramble; random streams draw three numbers per
    /// point.
    ///
    /// # Panics
    /// When a Sobol replicate would pass 2^32 points (the integrator never asks).
    #[inline(always)]
    pub fn fill3(&mut self, u0: &mut [f64], u1: &mut [f64], u2: &mut [f64]) {
        match self {
            Stream::Sobol { keys, key2, next } => {
                assert!(
                    *next + u0.len() as u64 <= SOBOL_MAX_POINTS,
                    "Sobol replicate exhausted"
                );
                sobol::fill3(*next as u32, *keys, *key2, u0, u1, u2);
                *next += u0.len() as u64;
            }
            Stream::Random(rng) => {
                for ((a, b), c) in u0.iter_mut().zip(u1.iter_mut()).zip(u2.iter_mut()) {
                    *a = unit(rng.next_u64());
                    *b = unit(rng.next_u64());
                    *c = unit(rng.next_u64());
                }
            }
        }
    }
}

/// Maps 64 random bits to a float in `[0, 1)` with 53 random bits.
#[inline]
fn unit(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        for seq in [Sequence::Sobol, Sequence::Random] {
            let a: Vec<_> = {
                let mut s = Stream::new(seq, 7, 3, 0);
                (0..8).map(|_| s.next_point()).collect()
            };
            let b: Vec<_> = {
                let mut s = Stream::new(seq, 7, 3, 0);
                (0..8).map(|_| s.next_point()).collect()
            };
            let c: Vec<_> = {
                let mut s = Stream::new(seq, 7, 4, 0);
                (0..8).map(|_| s.next_point()).collect()
            };
            assert_eq!(a, b);
            assert_ne!(a, c);
            assert!(a.iter().flatten().all(|&x| (0.0..1.0).contains(&x)));
        }
    }

    #[test]
    fn sobol_points_stratify_power_of_two_prefixes() {
        // The first 2^k points of a replicate put one point in each of 2^k x-strata.
        let mut s = Stream::new(Sequence::Sobol, 1, 2, 3);
        let pts: Vec<_> = (0..256).map(|_| s.next_point()).collect();
        let mut seen = [false; 256];
        for p in &pts {
            seen[(p[0] * 256.0) as usize] = true;
        }
        assert!(seen.iter().all(|&x| x));
    }
}
