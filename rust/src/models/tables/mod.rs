//! Tables the kernels interpolate, computed by brdf-rs itself (`scripts/gen_tables.py`)
//! and embedded in the binary.

pub mod beckmann_e;
pub mod ggx_e;
pub mod nodes;

use crate::math::{Real, clamp, max};

use nodes::{NA, NT};

/// A single-scattering energy table: the loss `L = 1 − E(mu, alpha)` with its average
/// `L_avg(alpha) = 2 ∫ L mu dmu`.
///
/// The incidence axis is `t = mu/(mu + alpha·sqrt(1 − mu²))` (Smith's `a = mu/(alpha
/// sinθ)` as `a/(1 + a)`): the loss of a smooth surface lives in a layer of width ~alpha
/// at grazing incidence, which a fixed `mu` grid cannot resolve at small alpha, while in
/// `t` it has the same shape at every alpha. The nodes are uniform in `x = (sqrt(t) +
/// t)/2`, which refines them towards `t = 0`, where the loss of rough lobes grows like
/// `mu^0.85` from 0 (`scripts/furnace_check.py` measures the result). The roughness axis is
/// log-uniform, blended by cubic (Catmull-Rom) weights over four node columns (linear
/// interpolation left several times the furnace error near Beckmann's alpha = 0.5 at
/// normal incidence, where the loss rises steeply). Each alpha column is read at its own node's
/// `t` (not at the query's alpha), so the interpolant is, for every alpha, a fixed blend
/// of node columns' functions of `mu`, and the stored averages (of those functions,
/// `scripts/gen_tables.py`) blend with the same weights: the lobe's albedo is exactly
/// `L(mu)·F_ms`. The losses are non-negative (clamped when generated) and so is every
/// interpolated value (clamped at 0 where the cubic would dip below).
pub struct EnergyTable {
    pub loss: &'static [[f64; NA]; NT],
    pub loss_avg: &'static [f64; NA],
}

/// The GGX table (F = 1).
pub static GGX: EnergyTable = EnergyTable {
    loss: &ggx_e::GGX_LOSS,
    loss_avg: &ggx_e::GGX_LOSS_AVG,
};
/// The Beckmann table (F = 1).
pub static BECKMANN: EnergyTable = EnergyTable {
    loss: &beckmann_e::BECKMANN_LOSS,
    loss_avg: &beckmann_e::BECKMANN_LOSS_AVG,
};

/// A position between two nodes: the lower index and the weight of the upper one.
#[derive(Clone, Copy, Debug)]
pub struct Node<F> {
    pub index: usize,
    pub weight: F,
}

/// Returns the node interval of `x` on `[0, last]` (clamped).
#[inline(always)]
fn node<F: Real>(x: F, last: usize) -> Node<F> {
    let x = clamp(x, F::ZERO, F::from_f64(last as f64));
    let lower = clamp(x, F::ZERO, F::from_f64((last - 1) as f64));
    // Truncation of a value in [0, last − 1]: the integer part.
    let index = lower.to_f64() as usize;
    Node {
        index,
        weight: x - F::from_f64(index as f64),
    }
}

/// A roughness between the table's nodes: four node columns and their cubic
/// (Catmull-Rom) weights in log alpha, which sum to 1 (at the ends of the range the
/// outer node is extrapolated linearly, and its column gets weight 0).
#[derive(Clone, Copy, Debug)]
pub struct AlphaNode<F> {
    pub columns: [usize; 4],
    /// The roughness of each column.
    pub alphas: [F; 4],
    pub weights: [F; 4],
}

impl EnergyTable {
    /// Returns the alpha node of `alpha` (log-uniform; clamped to [1e-3, 1]).
    #[inline(always)]
    pub fn alpha_node<F: Real>(&self, alpha: F) -> AlphaNode<F> {
        // log(alpha / 1e-3) / log(1e3) · (NA − 1)
        let scale = F::from_f64((NA - 1) as f64 / 1e3f64.ln());
        let a = node((alpha * F::from_f64(1e3)).ln() * scale, NA - 1);
        let j = a.index;
        let w = a.weight;
        let (w2, w3) = (w * w, w * w * w);
        let half = F::from_f64(0.5);
        let (two, three, four, five) = (
            F::from_f64(2.0),
            F::from_f64(3.0),
            F::from_f64(4.0),
            F::from_f64(5.0),
        );
        let mut weights = [
            half * (two * w2 - w3 - w),
            half * (three * w3 - five * w2 + two),
            half * (four * w2 - three * w3 + w),
            half * (w3 - w2),
        ];
        // At the ends of the range the missing outer node is the linear extrapolation of
        // the two inner ones (L₋₁ = 2L₀ − L₁), folded into their weights.
        if j == 0 {
            let c = weights[0];
            weights = [F::ZERO, weights[1] + two * c, weights[2] - c, weights[3]];
        }
        if j + 2 > NA - 1 {
            let c = weights[3];
            weights = [weights[0], weights[1] - c, weights[2] + two * c, F::ZERO];
        }
        let columns = [j.saturating_sub(1), j, j + 1, (j + 2).min(NA - 1)];
        AlphaNode {
            columns,
            alphas: columns.map(|c| F::from_f64(nodes::ALPHA[c])),
            weights,
        }
    }

    /// Returns the loss of node column `j` at the node coordinate of its own `t`, given
    /// `sqrt(t)` (linear in the node coordinate between the incidence nodes).
    /// Branch-free, with indices clamped where the compiler can see it (no bounds checks
    /// in the row loop).
    #[inline(always)]
    fn column<F: Real>(&self, j: usize, t: F, sqrt_t: F) -> F {
        // The node coordinate x = (sqrt(t) + t)/2, uniform over the nodes.
        let x = (sqrt_t + t) * F::from_f64(0.5 * (NT - 1) as f64);
        let m = node(x, NT - 1);
        let (i, j) = (m.index.min(NT - 2), j.min(NA - 1));
        let lo = F::from_f64(self.loss[i][j]);
        let hi = F::from_f64(self.loss[i + 1][j]);
        lo + (hi - lo) * m.weight
    }

    /// Returns the energy loss `1 − E(mu, alpha)`: each of the four alpha node columns
    /// read at its own `t = mu/(mu + alpha_k·sinθ)`, blended with the cubic weights.
    /// Never negative: the blend is clamped at 0 (where it would dip below, the loss is
    /// within the table's noise of 0). Below the surface (and for NaN) it is read at
    /// `mu = 0`.
    ///
    /// In `f64` the four `t` and their square roots cost one division and three square
    /// roots in all (the divider is the bottleneck of this loop): the denominators `D_k = mu +
    /// alpha_k·sinθ` lie in `[1e-3, 2]` (`alpha_k >= 1e-3`, and `mu`, `sinθ` are never
    /// both 0), so their product cannot overflow or underflow and one reciprocal of it
    /// gives every `1/D_k`; `sqrt(t_k) = sqrt(mu)·D_k^(−1/2)`, with `D_1^(−1/2)` a
    /// square root and the others from it (neighbouring columns: `D_k/D_1` within 16%)
    /// by a second-order seed and three Newton steps for `1/sqrt`, to within an ulp or
    /// two. In `f32`, where divisions are cheap and the extra roundings would show (the
    /// node coordinate near `t = 1` magnifies the relative error of `1 − t`), each `t` is
    /// divided out directly.
    #[inline(always)]
    pub fn loss<F: Real>(&self, mu: F, a: AlphaNode<F>) -> F {
        let mu = if mu > F::ZERO { mu } else { F::ZERO };
        let sin = max((F::ONE - mu) * (F::ONE + mu), F::ZERO).sqrt();
        if std::mem::size_of::<F>() < 8 {
            let mut sum = F::ZERO;
            for k in 0..4 {
                let t = mu / (mu + a.alphas[k] * sin);
                sum = sum + self.column(a.columns[k], t, t.sqrt()) * a.weights[k];
            }
            return max(sum, F::ZERO);
        }
        let d = a.alphas.map(|alpha| mu + alpha * sin);
        let (p01, p23) = (d[0] * d[1], d[2] * d[3]);
        let inv = F::ONE / (p01 * p23);
        let recip = [
            inv * d[1] * p23,
            inv * d[0] * p23,
            inv * p01 * d[3],
            inv * p01 * d[2],
        ];
        let root_mu = mu.sqrt();
        let r1 = recip[1].sqrt();
        let (half, three_halves) = (F::HALF, F::from_f64(1.5));
        let three_eighths = F::from_f64(0.375);
        let mut sum = F::ZERO;
        for k in 0..4 {
            // (1 + e)^(−1/2) ≈ 1 − e/2 + 3e²/8 with e = (D_k − D_1)/D_1, then Newton.
            let e = (a.alphas[k] - a.alphas[1]) * sin * recip[1];
            let mut y = r1 * (F::ONE - half * e + three_eighths * e * e);
            for _ in 0..3 {
                y = y * (three_halves - half * d[k] * y * y);
            }
            let y = if k == 1 { r1 } else { y };
            let t = mu * recip[k];
            sum = sum + self.column(a.columns[k], t, root_mu * y) * a.weights[k];
        }
        max(sum, F::ZERO)
    }

    /// Returns `1 − E_avg(alpha)`, the average loss: the stored averages blended with the
    /// same weights as the columns, so that it is the average of [`Self::loss`].
    #[inline(always)]
    pub fn avg_loss<F: Real>(&self, a: AlphaNode<F>) -> F {
        let mut sum = F::ZERO;
        for (&j, &w) in a.columns.iter().zip(&a.weights) {
            sum = sum + F::from_f64(self.loss_avg[j]) * w;
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loss as first written: each column's `t` divided out and square-rooted on its
    /// own (four divisions and five square roots per call).
    fn loss_direct<F: Real>(table: &EnergyTable, mu: F, a: AlphaNode<F>) -> F {
        let mu = max(mu, F::ZERO);
        let sin = max((F::ONE - mu) * (F::ONE + mu), F::ZERO).sqrt();
        let mut sum = F::ZERO;
        for k in 0..4 {
            let t = mu / (mu + a.alphas[k] * sin);
            sum = sum + table.column(a.columns[k], t, t.sqrt()) * a.weights[k];
        }
        max(sum, F::ZERO)
    }

    #[test]
    fn shared_reciprocals_match_the_direct_loss() {
        for (table, name) in [(&GGX, "ggx"), (&BECKMANN, "beckmann")] {
            for ia in 0..=400 {
                let alpha = 1e-3 * 1e3f64.powf(ia as f64 / 400.0);
                let a = table.alpha_node(alpha);
                let a32 = table.alpha_node(alpha as f32);
                for im in 0..=400 {
                    // Dense near grazing, where the loss varies fastest.
                    let mu = (im as f64 / 400.0).powi(3);
                    let direct = loss_direct(table, mu, a);
                    let fast = table.loss(mu, a);
                    // Relative to the blend's terms: the cubic weights alternate in sign, so
                    // a small loss is a difference of larger terms, each rounded alike.
                    let terms: f64 = (0..4)
                        .map(|k| {
                            let t = mu / (mu + a.alphas[k] * ((1.0 - mu) * (1.0 + mu)).sqrt());
                            (table.column(a.columns[k], t, t.sqrt()) * a.weights[k]).abs()
                        })
                        .sum();
                    // (A loss far below its neighbouring node values is a small fraction
                    // of a steep step: an ulp of the node coordinate moves it by ~1e-21.)
                    assert!(
                        (fast - direct).abs() <= 1e-12 * terms + 1e-18,
                        "{name} alpha {alpha} mu {mu}: {fast} vs {direct}"
                    );
                    let fast32 = f64::from(table.loss(mu as f32, a32));
                    let direct32 = f64::from(loss_direct(table, mu as f32, a32));
                    // Float32 divides each `t` out: the direct version, bit for bit.
                    assert_eq!(fast32, direct32, "{name} f32 alpha {alpha} mu {mu}");
                }
            }
        }
    }
}
