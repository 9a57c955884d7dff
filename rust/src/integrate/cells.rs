//! The cells of an albedo request: `mu`, the azimuth `phi` and the parameters broadcast
//! together (NumPy rules), checked against the model's spec exactly as `eval` checks them.

use ndarray::ArrayViewD;

use super::Cells;
use crate::error::{BrdfError, format_shape};
use crate::eval::engine::read_row;
use crate::eval::params::{self, ParamRows};
use crate::eval::rows::Rows;
use crate::models::ModelKind;

/// Broadcast cells: the parameters' rows and the rows of `mu` and `phi`.
pub struct CellGrid<'a> {
    pub batch: Vec<usize>,
    mu: Rows<'a, f64>,
    phi: Option<Rows<'a, f64>>,
    params: ParamRows<'a, f64>,
    ids: Option<&'a [u64]>,
}

impl<'a> CellGrid<'a> {
    /// Checks `mu` (in [0, 1]), the azimuths `phi` (finite, radians from the tangent;
    /// absent: 0) and the parameters, and broadcasts them. `ids`, if given, are the cells'
    /// global ids (C order over the batch), keying their sample streams; otherwise a
    /// cell's id is its flat index.
    pub fn new(
        kind: ModelKind,
        mu: ArrayViewD<'a, f64>,
        phi: Option<ArrayViewD<'a, f64>>,
        given: Vec<(&'a str, ArrayViewD<'a, f64>)>,
        ids: Option<&'a [u64]>,
    ) -> Result<CellGrid<'a>, BrdfError> {
        all_valid(
            &mu,
            "mu",
            |m| (0.0..=1.0).contains(&m),
            "in [0, 1] (the cosine of the incidence angle)",
        )?;
        let mut others = vec![("mu", mu.shape().to_vec())];
        if let Some(phi) = &phi {
            all_valid(
                phi,
                "phi",
                f64::is_finite,
                "finite (the azimuth of wi in radians, from the tangent)",
            )?;
            others.push(("phi", phi.shape().to_vec()));
        }
        let params = ParamRows::new(kind.spec(), given, &others)?;
        let batch = params.batch.clone();
        let cells: usize = batch.iter().product();
        if let Some(ids) = ids {
            if ids.len() != cells {
                return Err(BrdfError::Shape(format!(
                    "cell_ids: expected {cells} ids for batch shape {}; got {}",
                    format_shape(&batch),
                    ids.len()
                )));
            }
        }
        let mu = Rows::new(mu, false, 1, &batch);
        let phi = phi.map(|phi| Rows::new(phi, false, 1, &batch));
        Ok(CellGrid {
            batch,
            mu,
            phi,
            params,
            ids,
        })
    }
}

/// `Ok` where every element of `values` is `ok`; else the out-of-range error of the first
/// that is not, for the argument `name` that must be `valid`.
fn all_valid(
    values: &ArrayViewD<'_, f64>,
    name: &str,
    ok: impl Fn(f64) -> bool,
    valid: &str,
) -> Result<(), BrdfError> {
    match params::first_bad(values, |x| !ok(x)) {
        None => Ok(()),
        Some(index) => Err(BrdfError::OutOfRange {
            name: name.into(),
            value: values[ndarray::IxDyn(&index)],
            index,
            valid: valid.into(),
        }),
    }
}

impl Cells for CellGrid<'_> {
    fn count(&self) -> usize {
        self.batch.iter().product()
    }

    fn cell(&self, i: usize, slots: &mut Vec<f64>) -> (f64, f64, u64) {
        self.params.slots(i, slots);
        let mut row = [0.0; 3];
        read_row(&self.mu, 1, &self.batch, i, &mut row);
        let mu = row[0];
        let phi = match &self.phi {
            Some(phi) => {
                read_row(phi, 1, &self.batch, i, &mut row);
                row[0]
            }
            None => 0.0,
        };
        let id = self.ids.map_or(i as u64, |ids| ids[i]);
        (mu, phi, id)
    }
}
