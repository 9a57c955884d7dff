//! End regions of a lobe's sampler numbers, where with Sobol points the weight runs off
//! along a logarithm or a normal quantile: which ends a lobe has ([`Ends`]), how a point
//! there is split into two ([`end_split`]), and the points that stand in for it
//! ([`Leaves`]). [`CellIntegrand::weights`] puts them together.
//!
//! [`CellIntegrand::weights`]: super::integrand::CellIntegrand::weights

use super::POINTS;
use crate::sampling::ONE_BELOW;

/// The end regions of a lobe's sampler numbers ([`Lobe::ends`]): `mask` bit `2d` for
/// `u_d → 0`, bit `2d + 1` for `u_d → 1`, each region `width` wide.
///
/// [`Lobe::ends`]: super::integrand::Lobe::ends
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Ends {
    pub(super) mask: u8,
    pub(super) width: f64,
}

impl Ends {
    pub(super) const NONE: Ends = Ends {
        mask: 0,
        width: 0.0,
    };
}

/// The ends of Ward's and Ashikhmin-Shirley's first number (`u0 → 1`), logarithmic all
/// the way: one Sobol stratum of replicates of 16 points (cells of 256 samples) wide.
/// Measured (`scripts/stderr_calibration.py --grid half_vector`): 1/32 leaves replicates
/// of 16 points skewed (Ward at normal incidence: mean z 0.1, 1.6% beyond 3 standard
/// errors).
pub(super) const LOG_ENDS: Ends = Ends {
    mask: 0b10,
    width: 1.0 / 16.0,
};

/// The ends of Beckmann's visible slopes, normal quantiles: both ends of the slope along
/// `wi`'s azimuth (`u0`) and, across it, the end of the folded quantile (`u1 → 0`), or
/// both of the full one. Measured as for [`LOG_ENDS`]: 1/64 leaves Beckmann at alpha 0.3
/// and normal incidence skewed (2.0% beyond 3 standard errors at 4096 samples, mean z
/// 0.16); 1/16 does not (0.4%, 0.02).
pub(super) const SLOPE_ENDS: Ends = Ends {
    mask: 0b0111,
    width: 1.0 / 16.0,
};

/// For a point `u` whose number `d` lies in an end region of `ends` ([`Lobe::ends`]):
/// that number at the two points that replace it, `φ(s)` and the region's edge, with
/// their coefficients `φ'(s)` and `1 − φ'(s)` ([`CellIntegrand::weights`]); `None`
/// elsewhere.
///
/// [`Lobe::ends`]: super::integrand::Lobe::ends
/// [`CellIntegrand::weights`]: super::integrand::CellIntegrand::weights
#[inline(always)]
pub(super) fn end_split(ends: Ends, u: [f64; 2], d: usize) -> Option<[(f64, f64); 2]> {
    let x = ends.width;
    let low = if ends.mask >> (2 * d) & 1 != 0 && u[d] < x {
        true
    } else if ends.mask >> (2 * d + 1) & 1 != 0 && u[d] > 1.0 - x {
        false
    } else {
        return None;
    };
    let s = if low { u[d] } else { 1.0 - u[d] };
    let t = s / x;
    let slope = t * (4.0 - 3.0 * t);
    let v = s * t * (2.0 - t);
    let (inner, edge) = if low {
        (v, x)
    } else {
        ((1.0 - v).min(ONE_BELOW), 1.0 - x)
    };
    Some([(inner, slope), (edge, 1.0 - slope)])
}

/// Points that stand in for the points of end regions ([`CellIntegrand::weights`]):
/// their numbers `(u0, u1, u2)`, the point each belongs to, its coefficient, and room
/// for its weight.
///
/// [`CellIntegrand::weights`]: super::integrand::CellIntegrand::weights
pub(super) struct Leaves {
    pub(super) len: usize,
    pub(super) u: [[f64; POINTS]; 3],
    pub(super) point: [usize; POINTS],
    pub(super) coef: [f64; POINTS],
    pub(super) w: [f64; POINTS],
}

impl Leaves {
    pub(super) fn new() -> Self {
        Leaves {
            len: 0,
            u: [[0.0; POINTS]; 3],
            point: [0; POINTS],
            coef: [0.0; POINTS],
            w: [0.0; POINTS],
        }
    }

    #[inline(always)]
    pub(super) fn push(&mut self, point: usize, u: [f64; 3], coef: f64) {
        let i = self.len;
        for (lane, x) in self.u.iter_mut().zip(u) {
            lane[i] = x;
        }
        self.point[i] = point;
        self.coef[i] = coef;
        self.len += 1;
    }
}
