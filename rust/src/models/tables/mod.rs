//! Tables the kernels interpolate, computed by brdf-rs itself (`scripts/gen_tables.py`)
//! and embedded in the binary.

pub mod beckmann_e;
pub mod ggx_e;

use crate::math::{Real, clamp};

/// A single-scattering energy table `E(mu, alpha)` with its average `E_avg(alpha)`, on
/// nodes uniform in mu (`j/32`) and log-uniform in alpha (`[1e-3, 1]`).
pub struct EnergyTable {
    pub e: &'static [[f64; 33]; 33],
    pub e_avg: &'static [f64; 33],
}

/// The GGX table (F = 1).
pub const GGX: EnergyTable = EnergyTable {
    e: &ggx_e::GGX_E,
    e_avg: &ggx_e::GGX_E_AVG,
};
/// The Beckmann table (F = 1).
pub const BECKMANN: EnergyTable = EnergyTable {
    e: &beckmann_e::BECKMANN_E,
    e_avg: &beckmann_e::BECKMANN_E_AVG,
};

/// A position between two nodes: the lower index and the weight of the upper one.
#[derive(Clone, Copy, Debug)]
pub struct Node<F> {
    pub index: usize,
    pub weight: F,
}

/// Returns the node interval of `x` on `[0, 32]` (clamped).
#[inline(always)]
fn node<F: Real>(x: F) -> Node<F> {
    let x = clamp(x, F::ZERO, F::from_f64(32.0));
    let lower = clamp(x, F::ZERO, F::from_f64(31.0));
    // Truncation of a value in [0, 31]: the integer part.
    let index = lower.to_f64() as usize;
    Node {
        index,
        weight: x - F::from_f64(index as f64),
    }
}

impl EnergyTable {
    /// Returns the alpha node of `alpha` (log-uniform; clamped to [1e-3, 1]).
    #[inline(always)]
    pub fn alpha_node<F: Real>(&self, alpha: F) -> Node<F> {
        // log(alpha / 1e-3) / log(1e3) · 32
        let scale = F::from_f64(32.0 / 1e3f64.ln());
        node((alpha * F::from_f64(1e3)).ln() * scale)
    }

    /// Returns the energy loss `1 − E(mu, alpha)` (bilinear in mu and log alpha). The
    /// nodes' losses are formed in f64 before any rounding to `F`: near alpha = 0, where
    /// E → 1, a float32 kernel keeps the loss to full relative precision instead of
    /// cancelling `1 − E` in float32.
    #[inline(always)]
    pub fn loss<F: Real>(&self, mu: F, a: Node<F>) -> F {
        let m = node(mu * F::from_f64(32.0));
        let row = |i: usize| {
            let lo = F::from_f64(1.0 - self.e[i][a.index]);
            let hi = F::from_f64(1.0 - self.e[i][(a.index + 1).min(32)]);
            lo + (hi - lo) * a.weight
        };
        let (lo, hi) = (row(m.index), row((m.index + 1).min(32)));
        lo + (hi - lo) * m.weight
    }

    /// Returns `1 − E_avg(alpha)`, the average loss.
    #[inline(always)]
    pub fn avg_loss<F: Real>(&self, a: Node<F>) -> F {
        let lo = F::from_f64(1.0 - self.e_avg[a.index]);
        let hi = F::from_f64(1.0 - self.e_avg[(a.index + 1).min(32)]);
        lo + (hi - lo) * a.weight
    }
}
