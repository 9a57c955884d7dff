//! The cells of an albedo request: `mu` and parameters broadcast together (NumPy rules),
//! checked against the model's spec exactly as `eval` checks them.

use ndarray::ArrayViewD;

use super::Cells;
use crate::error::{BrdfError, format_shape};
use crate::eval::engine::read_row;
use crate::eval::params::{self, BatchParam, GivenParam};
use crate::eval::rows::{Rows, broadcast_shapes};
use crate::models::ModelKind;

/// Broadcast cells: uniform slots plus the rows of every varying parameter and of `mu`.
pub struct CellGrid<'a> {
    pub batch: Vec<usize>,
    mu: Rows<'a, f64>,
    uniform: Vec<f64>,
    varying: Vec<(usize, usize, Rows<'a, f64>)>,
    ids: Option<&'a [u64]>,
}

impl<'a> CellGrid<'a> {
    /// Checks `mu` (in [0, 1]) and the parameters, and broadcasts them. `ids`, if given,
    /// are the cells' global ids (C order over the batch), keying their sample streams;
    /// otherwise a cell's id is its flat index.
    pub fn new(
        kind: ModelKind,
        mu: ArrayViewD<'a, f64>,
        given: Vec<(&'a str, ArrayViewD<'a, f64>)>,
        ids: Option<&'a [u64]>,
    ) -> Result<CellGrid<'a>, BrdfError> {
        let spec = kind.spec();
        if let Some(pos) = mu.iter().position(|&m| !(0.0..=1.0).contains(&m)) {
            let index = params::unravel(pos, mu.shape());
            return Err(BrdfError::OutOfRange {
                name: "mu".into(),
                value: mu[ndarray::IxDyn(&index)],
                index,
                valid: "in [0, 1] (the cosine of the incidence angle)".into(),
            });
        }
        let matched = params::match_names(spec, given.iter().map(|(name, _)| *name))?;
        let given: Vec<GivenParam<'a, f64>> = matched
            .into_iter()
            .zip(given)
            .map(|(spec, (_, view))| GivenParam { spec, view })
            .collect();
        let resolved = params::resolve(spec, given, true)?;
        let mut named = vec![("mu", mu.shape().to_vec())];
        for p in &resolved.batch {
            named.push((p.spec.name, p.own_batch.clone()));
        }
        let batch = broadcast_shapes(&named)?;
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
        let mut uniform = resolved.uniform;
        let mut varying = Vec::new();
        for BatchParam {
            spec: p,
            view,
            has_component_axis,
            ..
        } in resolved.batch
        {
            let comps = p.kind.slots();
            let rows = Rows::new(view, has_component_axis, comps, &batch);
            match rows.constant() {
                Some(row) => uniform[p.slot..p.slot + comps].copy_from_slice(&row[..comps]),
                None => varying.push((p.slot, comps, rows)),
            }
        }
        Ok(CellGrid {
            batch,
            mu,
            uniform,
            varying,
            ids,
        })
    }
}

impl Cells for CellGrid<'_> {
    fn count(&self) -> usize {
        self.batch.iter().product()
    }

    fn cell(&self, i: usize, slots: &mut Vec<f64>) -> (f64, u64) {
        slots.clear();
        slots.extend_from_slice(&self.uniform);
        let mut row = [0.0; 3];
        for (slot, comps, rows) in &self.varying {
            read_row(rows, *comps, &self.batch, i, &mut row);
            slots[*slot..*slot + *comps].copy_from_slice(&row[..*comps]);
        }
        read_row(&self.mu, 1, &self.batch, i, &mut row);
        let id = self.ids.map_or(i as u64, |ids| ids[i]);
        (row[0], id)
    }
}
