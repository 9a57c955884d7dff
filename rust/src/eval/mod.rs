//! The batch engine: evaluate a model over broadcast arrays of directions and parameters.
//!
//! [`plan`] checks everything (names, shapes, parameter ranges) and classifies each input
//! (constant / contiguous / strided); [`Plan::execute`] then runs the model in parallel
//! over blocks of rows, writing into a preallocated C-ordered output of shape
//! `batch + (3,)`. Inputs are read in place; nothing is copied except one block of rows
//! at a time into structure-of-arrays scratch, where the model's loop vectorizes.
//!
//! Results are bitwise identical for any thread count: every element is computed by the
//! same instructions whatever block or thread it falls in.

pub mod engine;
pub mod params;
pub mod rows;
pub mod sample;

use ndarray::{ArrayViewD, ArrayViewMutD};

use crate::error::{BrdfError, format_shape};
use crate::math::geometry::tangent_parallel;
use crate::math::{Real, Vector3};
use crate::models::{ModelKind, ModelSpec, TangentUse};
use params::{GivenParam, VaryingParam};
use rows::{Rows, broadcast_shapes, own_index};

/// The arrays of one evaluation: directions of shape `(..., 3)` and parameters by name.
pub struct EvalInputs<'a, F> {
    pub wi: ArrayViewD<'a, F>,
    pub wo: ArrayViewD<'a, F>,
    /// The surface normal; `None` means +z.
    pub n: Option<ArrayViewD<'a, F>>,
    pub tangent: Option<ArrayViewD<'a, F>>,
    pub params: Vec<(&'a str, ArrayViewD<'a, F>)>,
}

/// The accuracy tier of an evaluation (`precision=` in Python).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Precision {
    /// The library's accuracy goals (docs/numerics.md): powers to within an ulp.
    #[default]
    Accurate,
    /// Powers in plain floating point ([`crate::math::FastPow`]) and a short path for the
    /// normalization of ordinary vectors: relative error at most 1e-12 (`f64`) and 2e-6
    /// (`f32`) on well-conditioned inputs; the same handling of bad inputs.
    Fast,
}

impl Precision {
    /// The tier named `name` (`"accurate"` or `"fast"`).
    ///
    /// # Errors
    /// [`BrdfError::InvalidArgument`] naming the argument for any other name.
    pub fn from_name(name: &str) -> Result<Precision, BrdfError> {
        match name {
            "accurate" => Ok(Precision::Accurate),
            "fast" => Ok(Precision::Fast),
            _ => Err(BrdfError::InvalidArgument(format!(
                "precision: expected \"accurate\" or \"fast\"; got {name:?}"
            ))),
        }
    }
}

/// How to treat the inputs.
#[derive(Clone, Copy, Debug)]
pub struct EvalOptions {
    /// The caller promises unit-length directions: skip normalization.
    pub normalized: bool,
    /// Raise an error for NaN, infinite or zero-length input vectors (otherwise such rows
    /// give NaN).
    pub check: bool,
    /// Check parameter values against their ranges (off only when already checked).
    pub check_params: bool,
    /// The accuracy tier.
    pub precision: Precision,
}

impl Default for EvalOptions {
    fn default() -> Self {
        EvalOptions {
            normalized: false,
            check: true,
            check_params: true,
            precision: Precision::Accurate,
        }
    }
}

/// The problem of a tangent that [`tangent_parallel`] refuses.
pub const PARALLEL_TANGENT: &str = "parallel to the normal n (the sine of their angle is at most 64 machine epsilons of \
     the dtype), so it gives no direction in the tangent plane";

/// Returns what is wrong with an input vector, if anything: NaN, infinite or zero-length.
pub fn vector_problem<F: Real>(row: &[F; 3]) -> Option<&'static str> {
    if F::usable(F::V3::new(row[0], row[1], row[2])) {
        None
    } else if row.iter().any(|x| x.is_nan()) {
        Some("NaN")
    } else if row.iter().any(|x| !x.is_finite()) {
        Some("infinite")
    } else {
        Some("a zero-length vector")
    }
}

/// The direction arguments, in the order errors report them.
pub const VECTOR_NAMES: [&str; 4] = ["wi", "wo", "n", "tangent"];

/// A checked evaluation, ready to run.
pub struct Plan<'a, F: Real> {
    pub kind: ModelKind,
    /// The broadcast batch shape; the output is `batch + (3,)`.
    pub batch: Vec<usize>,
    pub rows: usize,
    /// `wi`, `wo`, `n`, `tangent` as rows of 3.
    pub vectors: [Rows<'a, F>; 4],
    /// The given direction arrays (for error messages), in `VECTOR_NAMES` order.
    originals: [Option<ArrayViewD<'a, F>>; 4],
    pub uniform: Vec<F>,
    pub varying: Vec<VaryingParam<'a, F>>,
    pub options: EvalOptions,
}

fn check_vector_shape<F>(name: &str, view: &ArrayViewD<'_, F>) -> Result<Vec<usize>, BrdfError> {
    let shape = view.shape();
    match shape.last() {
        Some(3) => Ok(shape[..shape.len() - 1].to_vec()),
        _ => Err(BrdfError::Shape(format!(
            "{name}: expected an array of shape (..., 3) (x, y, z components); got shape {}",
            format_shape(shape)
        ))),
    }
}

/// Checks an evaluation request and prepares it.
pub fn plan<'a, F: Real>(
    kind: ModelKind,
    inputs: EvalInputs<'a, F>,
    options: EvalOptions,
) -> Result<Plan<'a, F>, BrdfError> {
    let spec: &'static ModelSpec = kind.spec();
    let given = given_params(spec, inputs.params)?;
    let originals = [Some(inputs.wi), Some(inputs.wo), inputs.n, inputs.tangent];
    let named_shapes = checked_vectors(spec, &originals)?;
    let params::ParamRows {
        batch,
        uniform,
        varying,
    } = params::resolve(spec, given, options.check_params)?.broadcast(named_shapes)?;
    Ok(Plan::with_vectors(
        kind, batch, originals, uniform, varying, options,
    ))
}

/// [`plan`] for parameters resolved beforehand by [`uniform_params`] (`brdf_rs.Model`):
/// only the direction arrays are checked. An error from resolving the parameters (a
/// float32 rounding of a value beyond float32's range) is returned where [`plan`] would
/// have found it: after the directions' shapes.
pub fn plan_uniform<'a, F: Real>(
    kind: ModelKind,
    uniform: Result<&[F], &BrdfError>,
    vectors: [Option<ArrayViewD<'a, F>>; 4],
    options: EvalOptions,
) -> Result<Plan<'a, F>, BrdfError> {
    let named_shapes = checked_vectors(kind.spec(), &vectors)?;
    let uniform = uniform.map_err(BrdfError::clone)?.to_vec();
    let batch = broadcast_shapes(&named_shapes)?;
    Ok(Plan::with_vectors(
        kind,
        batch,
        vectors,
        uniform,
        Vec::new(),
        options,
    ))
}

/// Checks the parameters of a model and returns their slots, if every parameter is one
/// value with no batch axes (a number, an RGB triple, a list): `Ok(None)` when one has
/// batch axes (its shape takes part in broadcasting).
pub fn uniform_params<F: Real>(
    kind: ModelKind,
    params: Vec<(&str, ArrayViewD<'_, F>)>,
) -> Result<Option<Vec<F>>, BrdfError> {
    let spec = kind.spec();
    let resolved = params::resolve(spec, given_params(spec, params)?, true)?;
    let mut uniform = resolved.uniform;
    for p in resolved.batch {
        if !p.own_batch.is_empty() {
            return Ok(None);
        }
        let comps = p.spec.kind.slots();
        let rows = Rows::new(p.view, p.has_component_axis, comps, &[]);
        let row = rows.constant().expect("no batch axes: one row");
        uniform[p.spec.slot..p.spec.slot + comps].copy_from_slice(&row[..comps]);
    }
    Ok(Some(uniform))
}

/// Checks the tangent against the model's use of one and each direction's shape
/// `(..., 3)`; returns the batch shape of each given direction, named.
fn checked_vectors<F>(
    spec: &'static ModelSpec,
    vectors: &[Option<ArrayViewD<'_, F>>; 4],
) -> Result<Vec<(&'static str, Vec<usize>)>, BrdfError> {
    match (spec.tangent, &vectors[3]) {
        (TangentUse::Required, None) => {
            return Err(BrdfError::MissingParameter {
                model: spec.name,
                name: "tangent",
            });
        }
        (TangentUse::None, Some(_)) => {
            return Err(BrdfError::UnknownParameter {
                model: spec.name,
                name: "tangent".to_string(),
                suggestion: None,
                known: spec.param_names(),
            });
        }
        _ => {}
    }
    let mut named_shapes: Vec<(&'static str, Vec<usize>)> = Vec::with_capacity(4);
    for (name, view) in VECTOR_NAMES.iter().zip(vectors) {
        if let Some(v) = view {
            named_shapes.push((name, check_vector_shape(name, v)?));
        }
    }
    Ok(named_shapes)
}

impl<'a, F: Real> Plan<'a, F> {
    /// Assembles a plan from checked parts: the direction arrays are classified against
    /// the batch shape here.
    fn with_vectors(
        kind: ModelKind,
        batch: Vec<usize>,
        originals: [Option<ArrayViewD<'a, F>>; 4],
        uniform: Vec<F>,
        varying: Vec<VaryingParam<'a, F>>,
        options: EvalOptions,
    ) -> Plan<'a, F> {
        let rows: usize = batch.iter().product();
        let default_rows = [
            Rows::Constant([F::ZERO; 3]),
            Rows::Constant([F::ZERO; 3]),
            Rows::Constant([F::ZERO, F::ZERO, F::ONE]),
            Rows::Constant([F::ONE, F::ZERO, F::ZERO]),
        ];
        let vectors = std::array::from_fn(|i| match &originals[i] {
            Some(view) => Rows::new(view.clone(), true, 3, &batch),
            None => default_rows[i].clone(),
        });
        Plan {
            kind,
            batch,
            rows,
            vectors,
            originals,
            uniform,
            varying,
            options,
        }
    }
}

impl<F: Real> Plan<'_, F> {
    /// Returns the output shape, `batch + (3,)`.
    pub fn output_shape(&self) -> Vec<usize> {
        let mut shape = self.batch.clone();
        shape.push(3);
        shape
    }

    /// Runs the plan into `out` (shape `batch + (3,)`, C order).
    ///
    /// # Errors
    /// An error naming the first bad input vector (NaN, infinite or zero-length) when
    /// `check` is on; `out` then holds NaN in the bad rows and results elsewhere.
    pub fn execute(&self, out: ArrayViewMutD<'_, F>) -> Result<(), BrdfError> {
        self.execute_polled(out, &mut || true)
    }

    /// [`Plan::execute`], calling `poll` between parts of a large batch (see
    /// [`engine::run_polled`]): when it returns false the work stops with
    /// [`BrdfError::Interrupted`], `out` partly written.
    pub fn execute_polled(
        &self,
        out: ArrayViewMutD<'_, F>,
        poll: &mut dyn FnMut() -> bool,
    ) -> Result<(), BrdfError> {
        if out.shape() != self.output_shape().as_slice() {
            return Err(BrdfError::Shape(format!(
                "out: expected shape {}; got {}",
                format_shape(&self.output_shape()),
                format_shape(out.shape())
            )));
        }
        let Some(out) = out.into_slice() else {
            return Err(BrdfError::InvalidArgument(
                "out: must be C-contiguous (a fresh numpy.empty array is)".into(),
            ));
        };
        let any_bad = engine::run_polled(self, out, poll).ok_or(BrdfError::Interrupted)?;
        if any_bad && self.options.check {
            return Err(self.first_bad_vector());
        }
        Ok(())
    }

    /// Whether a given tangent must not be parallel to the normal: the models that
    /// project it onto the tangent plane (those taking it optionally: `ward`,
    /// `ashikhmin_shirley`) have no frame there; `kajiya_kay` uses its fibre as given.
    pub fn checks_tangent_direction(&self) -> bool {
        self.originals[3].is_some() && self.kind.spec().tangent == TangentUse::Optional
    }

    /// Finds the first bad input vector, in row order then argument order.
    fn first_bad_vector(&self) -> BrdfError {
        let mut row_buf = [F::ZERO; 3];
        let check_tangent = self.checks_tangent_direction();
        // Normalized as the loop did, which decided the row was bad.
        let division_free = engine::normalizes_division_free(self);
        for row in 0..self.rows {
            for (i, original) in self.originals.iter().enumerate() {
                let Some(view) = original else { continue };
                engine::read_row(&self.vectors[i], 3, &self.batch, row, &mut row_buf);
                let v = F::V3::new(row_buf[0], row_buf[1], row_buf[2]);
                let parallel = i == 3 && check_tangent && F::usable(v) && {
                    let mut n = [F::ZERO; 3];
                    engine::read_row(&self.vectors[2], 3, &self.batch, row, &mut n);
                    let n = F::V3::new(n[0], n[1], n[2]);
                    let (unit_n, _) = engine::unit::<F>(n, division_free);
                    let (unit_t, _) = engine::unit::<F>(v, division_free);
                    let (n, t) = if self.options.normalized {
                        (n, v)
                    } else {
                        (unit_n, unit_t)
                    };
                    tangent_parallel::<F>(n, t)
                };
                if F::usable(v) && !parallel {
                    continue;
                }
                let problem = if parallel {
                    PARALLEL_TANGENT
                } else if row_buf.iter().any(|x| x.is_nan()) {
                    "NaN"
                } else if row_buf.iter().any(|x| !x.is_finite()) {
                    "infinite"
                } else {
                    "a zero-length vector"
                };
                let shape = view.shape();
                let index = own_index(row, &self.batch, &shape[..shape.len() - 1]);
                return BrdfError::BadVector {
                    argument: VECTOR_NAMES[i],
                    index,
                    problem,
                };
            }
        }
        BrdfError::InvalidArgument("a bad input vector was seen but not found again".into())
    }
}

/// Plans and runs an evaluation into a new array.
pub fn eval_to_vec<F: Real>(
    kind: ModelKind,
    inputs: EvalInputs<'_, F>,
    options: EvalOptions,
) -> Result<(Vec<usize>, Vec<F>), BrdfError> {
    let plan = plan(kind, inputs, options)?;
    let shape = plan.output_shape();
    let mut out = crate::error::try_filled_vec::<F>(plan.rows * 3, "output")?;
    let view = ArrayViewMutD::from_shape(ndarray::IxDyn(&shape), &mut out)
        .map_err(|e| BrdfError::Shape(e.to_string()))?;
    plan.execute(view)?;
    Ok((shape, out))
}

/// Checks parameter names, list rules and values for a model without evaluating it
/// (shapes against a batch are checked at evaluation).
pub fn check_params<F: Real>(
    kind: ModelKind,
    params: Vec<(&str, ArrayViewD<'_, F>)>,
) -> Result<(), BrdfError> {
    let spec = kind.spec();
    params::resolve(spec, given_params(spec, params)?, true).map(|_| ())
}

/// Pairs each named parameter array with its spec (unknown or misspelt names are an
/// error naming them), in the order given.
fn given_params<'a, F>(
    spec: &'static ModelSpec,
    params: Vec<(&str, ArrayViewD<'a, F>)>,
) -> Result<Vec<GivenParam<'a, F>>, BrdfError> {
    let matched = params::match_names(spec, params.iter().map(|(name, _)| *name))?;
    Ok(matched
        .into_iter()
        .zip(params)
        .map(|(spec, (_, view))| GivenParam { spec, view })
        .collect())
}
