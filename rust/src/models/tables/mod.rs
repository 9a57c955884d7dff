//! Tables the kernels interpolate, computed by brdf-rs itself (`scripts/gen_tables.py`)
//! and embedded in the binary.

pub mod beckmann_e;
pub mod ggx_dielectric_e;
pub mod ggx_e;
pub mod nodes;

use super::sheen::Dd;
use crate::math::fastmath::log_dd_f64;
use crate::math::{Real, clamp, max, min};

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

/// The four nodes about `x`'s interval on `[0, last]` and their cubic (Catmull-Rom)
/// weights, which sum to 1. At the ends of the range the missing outer node is the linear
/// extrapolation of the two inner ones (`L₋₁ = 2L₀ − L₁`), folded into their weights (the
/// outer index is clamped and gets weight 0).
#[inline(always)]
fn cubic<F: Real>(x: Node<F>, last: usize) -> ([usize; 4], [F; 4]) {
    let j = x.index;
    let w = x.weight;
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
    if j == 0 {
        let c = weights[0];
        weights = [F::ZERO, weights[1] + two * c, weights[2] - c, weights[3]];
    }
    if j + 2 > last {
        let c = weights[3];
        weights = [weights[0], weights[1] - c, weights[2] + two * c, F::ZERO];
    }
    let nodes = [j.saturating_sub(1), j, j + 1, (j + 2).min(last)];
    (nodes, weights)
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
        let (columns, weights) = cubic(
            node((alpha * F::from_f64(1e3)).ln() * scale, NA - 1),
            NA - 1,
        );
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
        self.loss_sine(mu, sin, a)
    }

    /// [`Self::loss`] given also `sinθ`, as a model computes it from the directions
    /// (`|n × w|`): from `mu = n·w` alone, a `w` along `n` an ulp off unit length reads as
    /// `sinθ = √(2ε)` (1.5e-8), which moved the loss by 10^-9 relative.
    #[inline(always)]
    pub fn loss_sine<F: Real>(&self, mu: F, sin: F, a: AlphaNode<F>) -> F {
        let mu = if mu > F::ZERO { mu } else { F::ZERO };
        let sin = min(sin, F::ONE);
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

/// The dielectric table's incidence coordinate
/// `x = (q^(1/4)/2 + (sqrt(t) + t)/4)·(NT − 1)`, `t = mu/(mu + alpha·sin)`,
/// `q = mu/(mu + w·sin)` with `w = y/(alpha + y)`, for the cosine `mu` and sine `sin` of
/// the incidence (both in [0, 1]) and `y = |ln r|`. Formed in double width: `x` reaches
/// 96, and its rounding in `f64` alone, times the table's slope, shows in `E`.
/// Branch-free: a loop of it over a block's rows vectorizes.
#[inline(always)]
fn incidence_coordinate(mu: f64, sin: f64, alpha: f64, y: Dd<f64>) -> Dd<f64> {
    use ggx_dielectric_e::NT;
    let mu_dd = Dd::new(mu, 0.0);
    let t = mu_dd.over(mu_dd.plus(Dd::two_prod(sin, alpha)));
    // q = mu·(alpha + y)/(mu·(alpha + y) + y·sin); 0 at mu = 0 (y > 0).
    let scaled = mu_dd.times(y.plus(Dd::new(alpha, 0.0)));
    let below = scaled.plus(y.times(Dd::new(sin, 0.0)));
    let q = if below.value() > 0.0 {
        scaled.over(below)
    } else {
        Dd::new(0.0, 0.0)
    };
    // (NT − 1)/2 = 48 and (NT − 1)/4 = 24: exact scalings.
    let layer_part = q.sqrt().sqrt().times(Dd::new(0.5 * (NT - 1) as f64, 0.0));
    let power_part = t.sqrt().plus(t).times(Dd::new(0.25 * (NT - 1) as f64, 0.0));
    layer_part.plus(power_part)
}

/// The cosine and sine a lookup reads for light at `mu_i` with sine `sin_i`: `|mu_i|`,
/// both at most 1; NaN reads as grazing incidence.
#[inline(always)]
fn incidence_angles(mu_i: f64, sin_i: f64) -> (f64, f64) {
    if mu_i.is_nan() || sin_i.is_nan() {
        (0.0, 1.0)
    } else {
        (mu_i.abs().min(1.0), sin_i.min(1.0))
    }
}

/// `ln(1 + z)` in double width for `z ≥ 0`.
#[inline(always)]
fn ln_1p(z: Dd<f64>) -> Dd<f64> {
    let (z_hi, z_lo) = z.parts();
    let (w_hi, w_lo) = Dd::two_sum(1.0, z_hi).plus(Dd::new(z_lo, 0.0)).parts();
    let (l_hi, l_lo) = log_dd_f64(w_hi);
    // ln(w_hi + w_lo) = ln(w_hi) + w_lo/w_hi to the width (|w_lo/w_hi| < 2^-52).
    Dd::new(l_hi, 0.0).plus(Dd::new(l_lo + w_lo / w_hi, 0.0))
}

/// The node interval of a coordinate `x` in double width on `[0, last]` (clamped): the
/// weight from `x`'s two parts, to an ulp of the weight.
#[inline(always)]
fn dd_node(x: Dd<f64>, last: usize) -> Node<f64> {
    let (hi, lo) = x.parts();
    let top = (last - 1) as f64;
    let index = if hi.is_nan() {
        0.0
    } else {
        hi.floor().clamp(0.0, top)
    };
    let weight = ((hi - index) + lo).clamp(0.0, 1.0);
    Node {
        index: index as usize,
        weight,
    }
}

/// `ln 1000` in double width.
const LN_1000: Dd<f64> = Dd::new(6.907_755_278_982_137, 2.369_515_526_854_504e-16);
/// `Y = ln 1e7`, the largest `|ln r|` of the dielectric table, in double width.
const LN_1E7: Dd<f64> = Dd::new(16.118_095_650_958_32, -6.313_509_366_674_493e-16);
/// `ln(1 + Y·2^50)`, the dielectric table's index scale, in double width.
const LN_1P_Y: Dd<f64> = Dd::new(37.437_301_622_300_54, -3.297_947_851_815_396_8e-15);

/// `ggx_dielectric`'s total albedo `E = R + T` of the white interface (`ks = kt = 1`,
/// nothing absorbed) for light arriving at cosine `mu` from either side, as a table over
/// `(mu, alpha, r)`, `r` the relative index seen from the light's side (`eta` from
/// above, `1/eta` from below): [`ggx_dielectric_e`], computed by brdf-rs itself
/// (`scripts/gen_tables.py dielectric`), one table for `r > 1` and one for `r < 1`.
///
/// The axes, on which `E` is read linearly in the first and by cubic (Catmull-Rom)
/// weights in the other two:
/// - index `v = ln(1 + y·2^50)/(2 ln(1 + Y·2^50)) + y/(2Y)`, `y = |ln r|`, `Y = ln 1e7`:
///   logarithmic in `|r − 1|` from the last ulps before 1, uniform in `ln r` towards
///   `r = 1e7` (the transmission falls as `1/r`);
/// - roughness `log alpha` over `[1e-3, 1]`;
/// - incidence `x = q^(1/4)/2 + (sqrt(t) + t)/4`, `t = mu/(mu + alpha·sin)` with `sin`
///   the sine of the incidence and `q = mu/(mu + w·sin)`, `w = y/(alpha + y)`. `t` as
///   the conductors' [`EnergyTable`] (the shadowing loss lives within `mu` of about
///   `alpha` of grazing); `q` for the layer an index near 1 opens, `mu` below about
///   `y/alpha`, in which `E` falls to 0 (light from the denser side is turned back
///   across the surface) or rises to 1 (from the rarer side, reflected whole): in `q`
///   the layer holds still as `y → 0`, so `E` is smooth along the index at a fixed `x`.
///
/// How far the interpolant is from `E` is measured by `scripts/dielectric_furnace.py`
/// (docs/models.md, `ggx_dielectric_ms`).
///
/// `r = 1` exactly has no interface (the light goes straight through, `E = 1`); the
/// table's `y = 0` nodes hold `r = 1 ± 2^-52`, which differs: the rough interface's
/// shadowing takes its share however close to 1 `r` is.
pub struct DielectricEnergy {
    /// `E` as little-endian `f32`, indexed `[side][i][j][k]` (side 0: `r > 1`).
    bytes: &'static [u8],
}

/// `ggx_dielectric`'s table.
pub static GGX_DIELECTRIC: DielectricEnergy = DielectricEnergy {
    bytes: ggx_dielectric_e::E,
};

/// A cubic blend of four nodes' values: the second node plus the weighted differences
/// from it (the weights sum to 1), so that the weights' rounding multiplies the small
/// differences between neighbouring nodes, not the value. [`DielectricEnergy::energy`]
/// blends along the index axis, then roughness, then (linearly) incidence.
#[inline(always)]
fn blend(v: [f64; 4], w: &[f64; 4]) -> f64 {
    v[1] + (w[0] * (v[0] - v[1]) + w[2] * (v[2] - v[1]) + w[3] * (v[3] - v[1]))
}

/// A roughness and index on a [`DielectricEnergy`] table, prepared once per parameter
/// set.
#[derive(Clone, Copy, Debug)]
pub struct DielectricNode {
    alpha: f64,
    /// `y = |ln eta|` (clamped to `ln 1e7`), in double width.
    y: Dd<f64>,
    /// The roughness and index nodes and their cubic weights.
    a: ([usize; 4], [f64; 4]),
    u: ([usize; 4], [f64; 4]),
    /// Whether light from above enters the denser medium (`eta > 1`).
    above_enters: bool,
    /// `eta != 1`.
    interface: bool,
}

impl DielectricEnergy {
    /// The table's shape: sides, incidence, roughness and index nodes.
    pub const SHAPE: [usize; 4] = [
        2,
        ggx_dielectric_e::NT,
        ggx_dielectric_e::NA,
        ggx_dielectric_e::NS,
    ];

    /// Returns the stored `E` at `[side][i][j][k]`.
    #[inline(always)]
    fn stored(&self, side: usize, i: usize, j: usize, k: usize) -> f32 {
        use ggx_dielectric_e::{NA, NS, NT};
        let at = 4 * (((side * NT + i) * NA + j) * NS + k);
        let b = &self.bytes[at..at + 4];
        f32::from_le_bytes([b[0], b[1], b[2], b[3]])
    }

    /// Returns every stored `E` in the table's order (`[side][i][j][k]`).
    pub fn values(&self) -> Vec<f32> {
        let [sides, nt, na, ns] = Self::SHAPE;
        let mut out = Vec::with_capacity(sides * nt * na * ns);
        for side in 0..sides {
            for i in 0..nt {
                for j in 0..na {
                    out.extend((0..ns).map(|k| self.stored(side, i, j, k)));
                }
            }
        }
        out
    }

    /// Returns the node of roughness `alpha` (clamped to `[1e-3, 1]`) and relative index
    /// `eta` (below over above).
    pub fn node(&self, alpha: f64, eta: f64) -> DielectricNode {
        use ggx_dielectric_e::{NA, NS};
        let alpha = alpha.clamp(1e-3, 1.0);
        // Both coordinates in double width, as the incidence's: (ln α − ln 1e-3)·(NA −
        // 1)/ln 1e3, from ln α (accurate where α is large and E depends on it most), and
        // v·(NS − 1) from y = |ln eta|, the same number for r = eta and r = 1/eta.
        let span = Dd::new((NA - 1) as f64, 0.0).over(LN_1000);
        let a = dd_node(Dd::new(alpha.ln(), 0.0).plus(LN_1000).times(span), NA - 1);
        // eta is in [1e-7, 1e7] (validated), normal and positive; NaN reads as no index.
        let (hi, lo) = if eta.is_finite() && eta > 0.0 {
            log_dd_f64(eta)
        } else {
            (0.0, 0.0)
        };
        let y = Dd::new(hi, lo);
        let y = if hi < 0.0 { y.negated() } else { y };
        let y = if y.value() > LN_1E7.value() {
            LN_1E7
        } else {
            y
        };
        // (NS − 1)/2 = 64: exact.
        let half = Dd::new(0.5 * (NS - 1) as f64, 0.0);
        let log_part = ln_1p(y.times(Dd::new(2f64.powi(50), 0.0))).times(half.over(LN_1P_Y));
        let linear_part = y.times(half.over(LN_1E7));
        let u = dd_node(log_part.plus(linear_part), NS - 1);
        let (a, u) = (cubic(a, NA - 1), cubic(u, NS - 1));
        DielectricNode {
            alpha,
            y,
            a,
            u,
            above_enters: eta > 1.0,
            interface: eta != 1.0,
        }
    }

    /// Returns `E` for light at `mu_i = n·wi` (its sign says the side; `|mu_i|` is the
    /// cosine) with `sin_i = |n × wi|`, 1 without an interface. The sine is taken as
    /// given, not as `sqrt(1 − mu²)`: near normal incidence that form turns an ulp of
    /// `mu` into 1e-8 of the sine. NaN reads as grazing incidence.
    pub fn energy(&self, p: &DielectricNode, mu_i: f64, sin_i: f64) -> f64 {
        let (hi, lo) = self.incidence(p, mu_i, sin_i);
        self.energy_from(p, mu_i, Dd::new(hi, lo), |side, i| self.row(p, side, i))
    }

    /// The incidence coordinate at which [`DielectricEnergy::energy`] reads `E` for light
    /// at `mu_i` with sine `sin_i`, in double width `(hi, lo)`: the costly part of a
    /// lookup, branch-free, so that a loop of it over many rows vectorizes; then
    /// [`DielectricEnergy::energy_at`].
    #[inline(always)]
    pub fn incidence(&self, p: &DielectricNode, mu_i: f64, sin_i: f64) -> (f64, f64) {
        let (mu, sin) = incidence_angles(mu_i, sin_i);
        incidence_coordinate(mu, sin, p.alpha, p.y).parts()
    }

    /// [`DielectricEnergy::energy`] at the incidence coordinate `x`
    /// ([`DielectricEnergy::incidence`] of the same `mu_i`) read from `column`, the node's
    /// rows blended once ([`DielectricEnergy::column`]): the same bits, without the 32
    /// loads and 10 blends per call.
    #[inline(always)]
    pub fn energy_at(&self, column: &[f64], p: &DielectricNode, mu_i: f64, x: (f64, f64)) -> f64 {
        self.energy_from(p, mu_i, Dd::new(x.0, x.1), |side, i| {
            let at = 3 * (side * ggx_dielectric_e::NT + i);
            (column[at], column[at + 1], column[at + 2])
        })
    }

    /// Every row of the node blended ([`DielectricEnergy::row`]), for
    /// [`DielectricEnergy::energy_at`]: `(E, least, most)` of side `s` and incidence node
    /// `i` at `3·(s·NT + i)`.
    pub fn column(&self, p: &DielectricNode) -> Vec<f64> {
        use ggx_dielectric_e::NT;
        let mut out = Vec::with_capacity(3 * 2 * NT);
        for side in 0..2 {
            for i in 0..NT {
                let (e, least, most) = self.row(p, side, i);
                out.extend([e, least, most]);
            }
        }
        out
    }

    /// The table's incidence row `i` of `side` at the node: blended along the index, then
    /// the roughness, with the least and most of the 16 values it blends.
    #[inline(always)]
    fn row(&self, p: &DielectricNode, side: usize, i: usize) -> (f64, f64, f64) {
        let (mut least, mut most) = (f64::INFINITY, 0.0f64);
        let mut along_a = [0.0; 4];
        for (blended, &j) in along_a.iter_mut().zip(&p.a.0) {
            let mut v = [0.0; 4];
            for (e, &k) in v.iter_mut().zip(&p.u.0) {
                *e = f64::from(self.stored(side, i, j, k));
                // Plain comparisons: the stored values are finite (no NaN rule).
                least = if *e < least { *e } else { least };
                most = if *e > most { *e } else { most };
            }
            *blended = blend(v, &p.u.1);
        }
        (blend(along_a, &p.a.1), least, most)
    }

    /// `E` at the incidence coordinate `x` from the node's rows as `row(side, i)` gives
    /// them ([`DielectricEnergy::row`]), for light at `mu_i` (its sign says the side).
    #[inline(always)]
    fn energy_from(
        &self,
        p: &DielectricNode,
        mu_i: f64,
        x: Dd<f64>,
        row: impl Fn(usize, usize) -> (f64, f64, f64),
    ) -> f64 {
        if !p.interface {
            return 1.0;
        }
        let side = usize::from((mu_i > 0.0) != p.above_enters);
        let x = dd_node(x, ggx_dielectric_e::NT - 1);
        let (lo, least_lo, most_lo) = row(side, x.index);
        let (hi, least_hi, most_hi) = row(side, x.index + 1);
        let least = if least_hi < least_lo {
            least_hi
        } else {
            least_lo
        };
        let most = if most_hi > most_lo { most_hi } else { most_lo };
        let sum = lo + x.weight * (hi - lo);
        // The cubic can overshoot where E bends sharply: held within the values it
        // blends (all positive, at most 1).
        sum.clamp(least, most)
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

    #[test]
    fn dielectric_energy_reads_its_nodes_and_sides() {
        use ggx_dielectric_e::{NA, NS, NT};
        let stored = |side: usize, i: usize, j: usize, k: usize| {
            let at = 4 * (((side * NT + i) * NA + j) * NS + k);
            let b = &ggx_dielectric_e::E[at..at + 4];
            f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        };
        // The axes' coordinates in plain f64, inverted by bisection.
        let top = 1e7f64.ln();
        let scale = 2f64.powi(50);
        let v_of_y = |y: f64| 0.5 * (y * scale).ln_1p() / (top * scale).ln_1p() + 0.5 * y / top;
        let invert = |f: &dyn Fn(f64) -> f64, target: f64, hi: f64| {
            let (mut lo, mut hi) = (0.0, hi);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if f(mid) < target {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        };
        // Index nodes where the index's rounding to a float moves y by under 1e-8 of it.
        for (i, j, k) in [
            (1, 0, 40),
            (20, 7, 45),
            (40, 12, 50),
            (96, 48, 70),
            (33, 3, 127),
            (60, 30, 60),
            (10, 45, 100),
        ] {
            let alpha = 1e-3 * 1e3f64.powf(j as f64 / (NA - 1) as f64);
            let r = invert(&v_of_y, k as f64 / (NS - 1) as f64, top).exp();
            let y = r.ln();
            let x_of_mu = |mu: f64| {
                let sin = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
                let t = mu / (mu + alpha * sin);
                let q = mu * (alpha + y) / (mu * (alpha + y) + y * sin);
                0.5 * q.sqrt().sqrt() + 0.25 * (t.sqrt() + t)
            };
            let mu = invert(&x_of_mu, i as f64 / (NT - 1) as f64, 1.0);
            for (side, eta, sign) in [
                (0, r, 1.0),
                (1, 1.0 / r, 1.0),
                (0, 1.0 / r, -1.0),
                (1, r, -1.0),
            ] {
                let sin = ((1.0 - mu) * (1.0 + mu)).sqrt();
                let e = GGX_DIELECTRIC.energy(&GGX_DIELECTRIC.node(alpha, eta), sign * mu, sin);
                let want = stored(side, i, j, k);
                assert!(
                    (e - want).abs() <= 1e-9,
                    "{i} {j} {k} side {side}: {e} vs {want}"
                );
            }
        }
        // No interface: E = 1 from both sides.
        let none = GGX_DIELECTRIC.node(0.5, 1.0);
        assert_eq!(GGX_DIELECTRIC.energy(&none, 0.3, 0.9), 1.0);
        assert_eq!(GGX_DIELECTRIC.energy(&none, -0.3, 0.9), 1.0);
    }

    #[test]
    fn dielectric_energy_from_the_blended_column_is_the_table_s_bit_for_bit() {
        use rand_core::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
        let mut uniform = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        // Nodes across the table, eta = 1 and both sides of it included.
        let mut nodes = vec![
            (1e-3, 1.5),
            (0.3, 1.33),
            (1.0, 0.4),
            (0.05, 1.0),
            (0.7, 1e7),
        ];
        for _ in 0..20 {
            let alpha = 1e-3 * 1e3f64.powf(uniform());
            nodes.push((alpha, 10f64.powf(14.0 * uniform() - 7.0)));
        }
        for (alpha, eta) in nodes {
            let p = GGX_DIELECTRIC.node(alpha, eta);
            let column = GGX_DIELECTRIC.column(&p);
            let check = |mu: f64, sin: f64| {
                let want = GGX_DIELECTRIC.energy(&p, mu, sin);
                let x = GGX_DIELECTRIC.incidence(&p, mu, sin);
                let got = GGX_DIELECTRIC.energy_at(&column, &p, mu, x);
                assert_eq!(
                    got.to_bits(),
                    want.to_bits(),
                    "alpha {alpha} eta {eta} mu {mu}"
                );
            };
            for _ in 0..500 {
                let mu = 2.0 * uniform() - 1.0;
                check(mu, (1.0 - mu * mu).sqrt());
            }
            for (mu, sin) in [
                (0.0, 1.0),
                (-0.0, 1.0),
                (1.0, 0.0),
                (-1.0, 0.0),
                (f64::NAN, 0.5),
                (0.5, f64::NAN),
                (1e-300, 1.0),
            ] {
                check(mu, sin);
            }
        }
    }

    #[test]
    fn dielectric_energy_stays_within_the_values_it_blends() {
        for ia in 0..=60 {
            let alpha = 1e-3 * 1e3f64.powf(f64::from(ia) / 60.0);
            for ie in 0..=60 {
                let eta = 10f64.powf(-7.0 + 14.0 * f64::from(ie) / 60.0);
                let p = GGX_DIELECTRIC.node(alpha, eta);
                for im in -100..=100 {
                    let mu = (f64::from(im) / 100.0).powi(3);
                    let e = GGX_DIELECTRIC.energy(&p, mu, (1.0 - mu * mu).sqrt());
                    assert!(e > 0.0 && e <= 1.0, "alpha {alpha} eta {eta} mu {mu}: {e}");
                }
            }
        }
    }
}
