//! Reading broadcast, strided inputs as rows of 1 or 3 floats, without copying them.
//!
//! An input array is classified once per batch: one row for the whole batch
//! ([`Rows::Constant`]), a C-contiguous slice covering the batch ([`Rows::Contiguous`],
//! the fast path), or anything else ([`Rows::Strided`]: broadcast axes, negative strides,
//! Fortran order), read element by element with safe indexing.

use ndarray::{ArrayViewD, IxDyn};

use crate::error::{BrdfError, format_shape};
use crate::math::Real;

/// Rows of `comps` (1 or 3) floats over a batch, read from an input array in place.
#[derive(Clone, Debug)]
pub enum Rows<'a, F> {
    /// The same row for every batch element (only `comps` entries are meaningful).
    Constant([F; 3]),
    /// Row `r` is `slice[comps*r .. comps*(r+1)]`.
    Contiguous(&'a [F]),
    /// General layout; see [`StridedRows`].
    Strided(StridedRows<'a, F>),
}

/// An array whose batch axes broadcast (right-aligned) against the batch shape.
#[derive(Clone, Debug)]
pub struct StridedRows<'a, F> {
    view: ArrayViewD<'a, F>,
    /// For each batch axis, the axis of `view` it reads (or `None` when broadcast).
    axis_of: Vec<Option<usize>>,
    /// Whether `view` has a trailing component axis.
    has_component_axis: bool,
}

/// Splits the batch part and component count off a shape: `(batch, comps)`.
pub type RowShape = (Vec<usize>, usize);

impl<'a, F: Real> Rows<'a, F> {
    /// Classifies `view`, whose leading axes (all but the trailing component axis when
    /// `has_component_axis`) broadcast against `batch`; `comps` is 1 or 3. A trailing
    /// axis of length 1 is repeated to 3 components (a grey colour).
    pub fn new(
        view: ArrayViewD<'a, F>,
        has_component_axis: bool,
        comps: usize,
        batch: &[usize],
    ) -> Rows<'a, F> {
        let shape = view.shape().to_vec();
        let nb = shape.len() - usize::from(has_component_axis);
        let own_batch = &shape[..nb];
        let offset = batch.len() - nb;
        let rows: usize = batch.iter().product();
        let own_comps = if has_component_axis { shape[nb] } else { 1 };
        let is_constant = own_batch
            .iter()
            .zip(&view.strides()[..nb])
            .all(|(&len, &stride)| len == 1 || stride == 0);
        if rows == 0 || is_constant {
            let mut row = [F::ZERO; 3];
            if rows > 0 {
                let mut idx = vec![0usize; shape.len()];
                for (c, value) in row.iter_mut().enumerate().take(comps) {
                    if has_component_axis {
                        idx[nb] = if own_comps == 1 { 0 } else { c };
                    }
                    *value = view[IxDyn(&idx)];
                }
            }
            return Rows::Constant(row);
        }
        if own_batch == batch && own_comps == comps && view.is_standard_layout() {
            if let Some(slice) = view.to_slice() {
                return Rows::Contiguous(slice);
            }
        }
        let axis_of = (0..batch.len())
            .map(|k| {
                if k < offset || own_batch[k - offset] == 1 {
                    None
                } else {
                    Some(k - offset)
                }
            })
            .collect();
        Rows::Strided(StridedRows {
            view,
            axis_of,
            has_component_axis,
        })
    }

    /// Returns the constant row, if the rows do not vary.
    pub fn constant(&self) -> Option<[F; 3]> {
        match self {
            Rows::Constant(row) => Some(*row),
            _ => None,
        }
    }
}

impl<F: Real> StridedRows<'_, F> {
    /// Calls `store(j, component, value)` for rows `start .. start + len` of the batch
    /// `batch`, `comps` components each (a length-1 component axis is repeated).
    ///
    /// An odometer over the batch axes keeps the element offset incrementally (one add
    /// per row, a carry at the end of an axis), so a broadcast or strided input costs
    /// about what a contiguous one does, not a dynamic index per element.
    pub fn for_each(
        &self,
        batch: &[usize],
        start: usize,
        len: usize,
        comps: usize,
        mut store: impl FnMut(usize, usize, F),
    ) {
        let ndim = self.view.ndim();
        let strides = self.view.strides();
        let own_comps = if self.has_component_axis {
            self.view.shape()[ndim - 1]
        } else {
            1
        };
        assert!(comps <= 3 && (own_comps == 1 || own_comps >= comps));
        // Element strides: per batch axis (0 where broadcast), and between components.
        let step: Vec<isize> = self
            .axis_of
            .iter()
            .map(|axis| axis.map_or(0, |a| strides[a]))
            .collect();
        let comp_step = if self.has_component_axis && own_comps > 1 {
            strides[ndim - 1]
        } else {
            0
        };
        // Multi-index of `start` in the batch, and its offset.
        let mut m = vec![0usize; batch.len()];
        let mut rest = start;
        for k in (0..batch.len()).rev() {
            m[k] = rest % batch[k];
            rest /= batch[k];
        }
        let mut offset: isize = m.iter().zip(&step).map(|(&i, &s)| i as isize * s).sum();
        let base = self.view.as_ptr();
        let Some(last) = batch.len().checked_sub(1) else {
            return;
        };
        for j in 0..len {
            for c in 0..comps {
                // SAFETY: every read axis has the batch axis's length (`Rows::new` maps an
                // axis only where the lengths agree), `m[k] < batch[k]`, and `c` is below
                // the component axis's length (or its stride is 0): the offset is that of
                // an element of the view.
                let value = unsafe { *base.offset(offset + c as isize * comp_step) };
                store(j, c, value);
            }
            // Next row: the last axis moves; a full axis carries into the one before.
            let mut k = last;
            loop {
                m[k] += 1;
                offset += step[k];
                if m[k] < batch[k] || k == 0 {
                    break;
                }
                offset -= m[k] as isize * step[k];
                m[k] = 0;
                k -= 1;
            }
        }
    }
}

/// Broadcasts shapes by NumPy's rules; on failure, says which two named shapes conflict.
pub fn broadcast_shapes(named: &[(&str, Vec<usize>)]) -> Result<Vec<usize>, BrdfError> {
    let ndim = named.iter().map(|(_, s)| s.len()).max().unwrap_or(0);
    let mut out = vec![1usize; ndim];
    // Which argument set each output axis (for the error message).
    let mut set_by: Vec<Option<usize>> = vec![None; ndim];
    for (i, (_, shape)) in named.iter().enumerate() {
        let offset = ndim - shape.len();
        for (k, &len) in shape.iter().enumerate() {
            let o = &mut out[offset + k];
            if len == *o || len == 1 {
                continue;
            }
            if *o == 1 {
                *o = len;
                set_by[offset + k] = Some(i);
                continue;
            }
            let j = set_by[offset + k].unwrap_or(0);
            let (a, sa) = &named[j];
            let (b, sb) = &named[i];
            return Err(BrdfError::Shape(format!(
                "shapes do not broadcast: {a} has batch shape {} and {b} has batch shape {}",
                format_shape(sa),
                format_shape(sb)
            )));
        }
    }
    // Every batch row becomes 3 floats of output: refuse batches no array can hold
    // (the product would overflow, or pass isize::MAX bytes as NumPy's own limit).
    let rows = out.iter().try_fold(1usize, |a, &b| a.checked_mul(b));
    if rows.is_none_or(|r| r > isize::MAX as usize / 24) {
        let names: Vec<&str> = named.iter().map(|(n, _)| *n).collect();
        return Err(BrdfError::Shape(format!(
            "the broadcast batch shape {} of {} is too large for any array",
            format_shape(&out),
            names.join(", ")
        )));
    }
    Ok(out)
}

/// Maps a flat batch row to the index of the same element in an argument's own batch
/// axes (broadcast axes give 0).
pub fn own_index(row: usize, batch: &[usize], own_batch: &[usize]) -> Vec<usize> {
    let mut m = vec![0usize; batch.len()];
    let mut rest = row;
    for k in (0..batch.len()).rev() {
        m[k] = rest % batch[k];
        rest /= batch[k];
    }
    let offset = batch.len() - own_batch.len();
    own_batch
        .iter()
        .enumerate()
        .map(|(k, &len)| if len == 1 { 0 } else { m[offset + k] })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::{Array, ArrayD, IxDyn};

    fn arr(shape: &[usize]) -> ArrayD<f64> {
        let n: usize = shape.iter().product();
        Array::from_iter((0..n).map(|x| x as f64))
            .into_shape_with_order(IxDyn(shape))
            .unwrap()
    }

    fn read_all(rows: &Rows<f64>, batch: &[usize], comps: usize) -> Vec<f64> {
        let n: usize = batch.iter().product();
        let mut out = vec![0.0; n * comps];
        match rows {
            Rows::Constant(r) => {
                for j in 0..n {
                    out[j * comps..(j + 1) * comps].copy_from_slice(&r[..comps]);
                }
            }
            Rows::Contiguous(s) => out.copy_from_slice(&s[..n * comps]),
            Rows::Strided(s) => s.for_each(batch, 0, n, comps, |j, c, v| out[j * comps + c] = v),
        }
        out
    }

    #[test]
    fn classifies_layouts() {
        let a = arr(&[4, 3]);
        assert!(matches!(
            Rows::new(a.view(), true, 3, &[4]),
            Rows::Contiguous(_)
        ));
        assert!(matches!(
            Rows::new(a.view(), true, 3, &[2, 4]),
            Rows::Strided(_)
        ));
        let one = arr(&[3]);
        assert_eq!(
            Rows::new(one.view(), true, 3, &[7]).constant(),
            Some([0.0, 1.0, 2.0])
        );
        let t = a.t().as_standard_layout().to_owned();
        let tv = t.t();
        assert!(matches!(
            Rows::new(tv.into_dyn(), true, 3, &[4]),
            Rows::Strided(_)
        ));
    }

    #[test]
    fn strided_rows_follow_broadcasting() {
        // (2, 1, 3) against batch (2, 3): each row of the first axis repeats.
        let a = arr(&[2, 1, 3]);
        let rows = Rows::new(a.view(), true, 3, &[2, 3]);
        let got = read_all(&rows, &[2, 3], 3);
        let want: Vec<f64> = [
            0., 1., 2., 0., 1., 2., 0., 1., 2., 3., 4., 5., 3., 4., 5., 3., 4., 5.,
        ]
        .to_vec();
        assert_eq!(got, want);
        // Fortran-ordered (4, 3) reads like the C-ordered one.
        let c = arr(&[4, 3]);
        let f = c.t().as_standard_layout().to_owned();
        let fv = f.t();
        let rows = Rows::new(fv.into_dyn(), true, 3, &[4]);
        assert_eq!(
            read_all(&rows, &[4], 3),
            c.iter().copied().collect::<Vec<_>>()
        );
        // A grey colour axis of length 1 repeats to three components.
        let g = arr(&[2, 1]);
        let rows = Rows::new(g.view(), true, 3, &[2]);
        assert_eq!(read_all(&rows, &[2], 3), vec![0., 0., 0., 1., 1., 1.]);
    }

    /// The odometer reads what indexing element by element reads, for broadcast,
    /// reversed and transposed views, from any starting row and for any length.
    #[test]
    fn strided_rows_match_indexing_from_any_start() {
        let base = arr(&[3, 1, 4, 3]);
        let reversed = base.slice(ndarray::s![..;-1, .., ..;-1, ..]).into_dyn();
        let transposed = arr(&[4, 5, 3]).permuted_axes(IxDyn(&[1, 0, 2]));
        let grey = arr(&[3, 1, 4, 1]);
        let batch = [2usize, 3, 5, 4];
        let views = [
            (base.view(), 3),
            (reversed.view(), 3),
            (transposed.view(), 3),
            (grey.view(), 3),
        ];
        for (view, comps) in views {
            let rows = Rows::new(view.clone(), true, comps, &batch);
            let Rows::Strided(strided) = &rows else {
                panic!("expected strided rows");
            };
            let n: usize = batch.iter().product();
            let nd = view.ndim();
            let nb = nd - 1;
            let own = &view.shape()[..nb];
            for start in [0usize, 1, 7, 19, 20, 57, n - 1] {
                for len in [1usize, 3, 20, n - start] {
                    let len = len.min(n - start);
                    let mut got = vec![0.0; len * comps];
                    strided.for_each(&batch, start, len, comps, |j, c, v| got[j * comps + c] = v);
                    for j in 0..len {
                        let idx = own_index(start + j, &batch, own);
                        for c in 0..comps {
                            let mut full = idx.clone();
                            full.push(if view.shape()[nb] == 1 { 0 } else { c });
                            assert_eq!(
                                got[j * comps + c],
                                view[IxDyn(&full)],
                                "start {start} row {j}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn broadcast_errors_name_both_arguments() {
        let err = broadcast_shapes(&[("wi", vec![5]), ("wo", vec![4])]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "shapes do not broadcast: wi has batch shape (5,) and wo has batch shape (4,)"
        );
        let ok = broadcast_shapes(&[("wi", vec![5, 1]), ("wo", vec![4]), ("n", vec![])]);
        assert_eq!(ok.unwrap(), vec![5, 4]);
    }

    #[test]
    fn own_index_drops_broadcast_axes() {
        assert_eq!(own_index(7, &[3, 4], &[1, 4]), vec![0, 3]);
        assert_eq!(own_index(7, &[3, 4], &[4]), vec![3]);
        assert_eq!(own_index(7, &[3, 4], &[3, 1]), vec![1, 0]);
    }
}
