//! Model-level sampling over broadcast arrays (`brdf_rs.sample` / `brdf_rs.pdf`): the
//! batch front end of [`crate::sampling::bsdf`]'s mixture sampler, with the eval engine's
//! broadcasting, strided rows and input checks.

use crate::error::{BrdfError, format_shape, try_filled_vec};
use crate::eval::engine::read_row;
use crate::eval::params::ParamRows;
use crate::eval::rows::Rows;
use crate::eval::rows::own_index;
use crate::eval::{PARALLEL_TANGENT, vector_problem};
use crate::math::Real;
use crate::math::geometry::{tangent_frame, tangent_parallel};
use crate::models::{Directions, Family, Kernel, KernelVisitor, ModelKind, TangentUse};
use crate::parallel;
use crate::sampling::bsdf::Mixture;
use crate::sampling::{Frame, SamplerChoice};
use glam::DVec3;
use ndarray::ArrayViewD;
use rayon::prelude::*;

/// The inputs of a sampling call: `wi`, then `u` (sample) or `wo` (pdf), and `n`.
pub struct Inputs<'a> {
    pub wi: ArrayViewD<'a, f64>,
    /// `u` of shape `(..., 2)` for `sample`, `wo` of shape `(..., 3)` for `pdf`.
    pub second: ArrayViewD<'a, f64>,
    pub n: Option<ArrayViewD<'a, f64>>,
    pub tangent: Option<ArrayViewD<'a, f64>>,
    pub params: Vec<(&'a str, ArrayViewD<'a, f64>)>,
}

/// Results: the batch shape, and per element `wo` (3), `weight` (3), `pdf` (1).
#[derive(Debug, Default)]
pub struct Output {
    pub batch: Vec<usize>,
    pub wo: Vec<f64>,
    pub weight: Vec<f64>,
    pub pdf: Vec<f64>,
}

fn last_axis(name: &str, view: &ArrayViewD<'_, f64>, len: usize) -> Result<Vec<usize>, BrdfError> {
    let shape = view.shape();
    if shape.last() != Some(&len) {
        return Err(BrdfError::Shape(format!(
            "{name}: expected an array of shape (..., {len}); got shape {}",
            format_shape(shape)
        )));
    }
    Ok(shape[..shape.len() - 1].to_vec())
}

struct Run<'a, 'p> {
    inputs: Inputs<'a>,
    sampling: bool,
    sampler: SamplerChoice,
    poll: Poll<'p>,
}

/// Called between parts of a long call; returning false stops it with
/// [`BrdfError::Interrupted`] (Ctrl-C from Python).
pub type Poll<'p> = &'p mut dyn FnMut() -> bool;

/// Rows between two polls, in the input checks and in the sampling.
const POLL_ROWS: usize = 1 << 16;

impl KernelVisitor for Run<'_, '_> {
    type Output = Result<Output, BrdfError>;

    fn visit<K: Kernel>(self) -> Result<Output, BrdfError> {
        let Run {
            inputs,
            sampling,
            sampler,
            poll,
        } = self;
        let second_len = if sampling { 2 } else { 3 };
        let second_name = if sampling { "u" } else { "wo" };
        let mut named = vec![
            ("wi", last_axis("wi", &inputs.wi, 3)?),
            (
                second_name,
                last_axis(second_name, &inputs.second, second_len)?,
            ),
        ];
        if let Some(n) = &inputs.n {
            named.push(("n", last_axis("n", n, 3)?));
        }
        if let Some(t) = &inputs.tangent {
            if K::SPEC.tangent == TangentUse::None {
                return Err(BrdfError::UnknownParameter {
                    model: K::SPEC.name,
                    name: "tangent".into(),
                    suggestion: None,
                    known: K::SPEC.param_names(),
                });
            }
            named.push(("tangent", last_axis("tangent", t, 3)?));
        }
        let params = ParamRows::<f64>::new(K::SPEC, inputs.params, &named)?;
        let batch = params.batch.clone();
        let count = params.count();
        let wi = Rows::new(inputs.wi, true, 3, &batch);
        let second = Rows::new(inputs.second, true, second_len, &batch);
        let n = inputs.n.map(|v| Rows::new(v, true, 3, &batch));
        let tangent = inputs.tangent.map(|v| Rows::new(v, true, 3, &batch));
        let sources = [Some(&wi), Some(&second), n.as_ref(), tangent.as_ref()];
        // The outputs first: a batch too large to hold fails at once, before the checks
        // read every row.
        let mut out = Output {
            batch: batch.clone(),
            wo: try_filled_vec(if sampling { 3 * count } else { 0 }, "sampled directions")?,
            weight: try_filled_vec(3 * count, "sample weights")?,
            pdf: try_filled_vec(count, "pdf values")?,
        };
        check_inputs::<K>(&named, &batch, sources, sampling, &mut *poll)?;
        let batch = &out.batch.clone();
        let element = |i: usize, wo_out: &mut [f64], weight_out: &mut [f64], pdf_out: &mut f64| {
            let mut slots = Vec::new();
            params.slots(i, &mut slots);
            let mut row = [0.0; 3];
            read_row(&wi, 3, batch, i, &mut row);
            let (wi_v, ok_i) = f64::normalize(DVec3::from_array(row));
            let mut row2 = [0.0; 3];
            read_row(&second, second_len, batch, i, &mut row2);
            let n_v = match &n {
                Some(rows) => {
                    let mut r = [0.0; 3];
                    read_row(rows, 3, batch, i, &mut r);
                    f64::normalize(DVec3::from_array(r))
                }
                None => (DVec3::Z, true),
            };
            let t_v = match &tangent {
                Some(rows) => {
                    let mut r = [0.0; 3];
                    read_row(rows, 3, batch, i, &mut r);
                    DVec3::from_array(r)
                }
                None => DVec3::X,
            };
            let (x, _) = tangent_frame::<f64>(n_v.0, t_v);
            let frame = Frame {
                x,
                y: n_v.0.cross(x),
                z: n_v.0,
            };
            if let Some(dielectric) = K::transmission_sampler(&slots) {
                // The whole sphere: the generic weight with |n·wo|, 0 for an invalid
                // draw; at eta = 1 the straight-through delta, weight kt.
                let ok_u = sampling && row2[0].is_finite() && row2[1].is_finite();
                let (wo, pdf, valid, ok) = if sampling {
                    let u = [
                        row2[0].clamp(0.0, crate::sampling::ONE_BELOW),
                        row2[1].clamp(0.0, crate::sampling::ONE_BELOW),
                    ];
                    let (wo, pdf, valid) = dielectric.sample(wi_v, &frame, u);
                    (wo, pdf, valid, ok_i && n_v.1 && ok_u)
                } else {
                    let (wo, ok_o) = f64::normalize(DVec3::from_array(row2));
                    let pdf = dielectric.pdf(wi_v, wo, &frame);
                    (wo, pdf, pdf > 0.0, ok_i && ok_o && n_v.1)
                };
                let prepared = K::prepare::<f64, [f64]>(&slots);
                let d = Directions::<f64> {
                    wi: wi_v,
                    wo,
                    n: n_v.0,
                    t: t_v,
                };
                let f = K::eval::<f64>(&prepared, &d);
                let mu_o = wo.dot(n_v.0).abs();
                let delta = pdf == f64::INFINITY;
                let kt = K::SPEC.param("kt").map(|p| p.slot);
                for c in 0..3 {
                    weight_out[c] = if !ok {
                        f64::NAN
                    } else if delta {
                        kt.map_or(0.0, |slot| slots[slot + c])
                    } else if valid && pdf > 0.0 {
                        f[c] * mu_o / pdf
                    } else {
                        0.0
                    };
                }
                if sampling {
                    wo_out.copy_from_slice(&(if ok { wo } else { DVec3::NAN }).to_array());
                }
                *pdf_out = if ok { pdf } else { f64::NAN };
                return;
            }
            let terms = K::sampling_terms(&slots, wi_v.dot(n_v.0)).unwrap_or_default();
            let mixture = Mixture::new(&terms, sampler);
            let (wo, pdf, ok) = if sampling {
                let u = [
                    row2[0].clamp(0.0, crate::sampling::ONE_BELOW),
                    row2[1].clamp(0.0, crate::sampling::ONE_BELOW),
                ];
                let (wo, pdf) = mixture.sample(wi_v, &frame, u);
                (
                    wo,
                    pdf,
                    ok_i && n_v.1 && row2[0].is_finite() && row2[1].is_finite(),
                )
            } else {
                let (wo, ok_o) = f64::normalize(DVec3::from_array(row2));
                (wo, mixture.pdf(wi_v, wo, &frame), ok_i && ok_o && n_v.1)
            };
            let prepared = K::prepare::<f64, [f64]>(&slots);
            let d = Directions::<f64> {
                wi: wi_v,
                wo,
                n: n_v.0,
                t: t_v,
            };
            let f = K::eval::<f64>(&prepared, &d);
            let mu_o = wo.dot(n_v.0);
            for c in 0..3 {
                let w = f[c] * mu_o / pdf;
                weight_out[c] = if !ok {
                    f64::NAN
                } else if pdf > 0.0 && mu_o > 0.0 {
                    w
                } else {
                    0.0
                };
            }
            if sampling {
                wo_out.copy_from_slice(&(if ok { wo } else { DVec3::NAN }).to_array());
            }
            *pdf_out = if ok { pdf } else { f64::NAN };
        };
        let chunk = 4096;
        for part in 0..count.div_ceil(POLL_ROWS) {
            if part > 0 && !poll() {
                return Err(BrdfError::Interrupted);
            }
            let rows = part * POLL_ROWS..count.min((part + 1) * POLL_ROWS);
            let (weight, pdf) = (
                &mut out.weight[3 * rows.start..3 * rows.end],
                &mut out.pdf[rows.clone()],
            );
            let first = rows.start;
            // The sampled directions' chunks, or none (a pdf query writes no directions).
            let chunks = pdf.len().div_ceil(chunk);
            let wo: Vec<Option<&mut [f64]>> = if sampling {
                out.wo[3 * rows.start..3 * rows.end]
                    .chunks_mut(3 * chunk)
                    .map(Some)
                    .collect()
            } else {
                (0..chunks).map(|_| None).collect()
            };
            parallel::install(|| {
                weight
                    .par_chunks_mut(3 * chunk)
                    .zip(pdf.par_chunks_mut(chunk))
                    .zip(wo)
                    .enumerate()
                    .for_each(|(c, ((weight, pdf), mut wo))| {
                        let mut unused = [0.0; 3];
                        for j in 0..pdf.len() {
                            let wo_out = match wo.as_deref_mut() {
                                Some(wo) => &mut wo[3 * j..3 * j + 3],
                                None => &mut unused[..],
                            };
                            element(
                                first + c * chunk + j,
                                wo_out,
                                &mut weight[3 * j..3 * j + 3],
                                &mut pdf[j],
                            );
                        }
                    })
            });
        }
        Ok(out)
    }
}

/// Refuses, naming the argument and its first bad index (rows in order, then the
/// arguments in order): a `wi`, `wo`, `n` or `tangent` that is NaN, infinite or of zero
/// length, a `u` outside `[0, 1)` (NaN and infinities included), and a tangent
/// parallel to `n` for the models that project it onto the tangent plane.
fn check_inputs<K: Kernel>(
    named: &[(&str, Vec<usize>)],
    batch: &[usize],
    rows: [Option<&Rows<'_, f64>>; 4],
    sampling: bool,
    poll: &mut dyn FnMut() -> bool,
) -> Result<(), BrdfError> {
    let count: usize = batch.iter().product();
    let projected = K::SPEC.tangent == TangentUse::Optional;
    let own = |name: &str| {
        named
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, s)| s.as_slice())
            .unwrap_or(&[])
    };
    let names = ["wi", if sampling { "u" } else { "wo" }, "n", "tangent"];
    let mut r = [[0.0; 3]; 4];
    for i in 0..count {
        if i > 0 && i % POLL_ROWS == 0 && !poll() {
            return Err(BrdfError::Interrupted);
        }
        for (k, source) in rows.iter().enumerate() {
            let Some(source) = source else { continue };
            let comps = if k == 1 && sampling { 2 } else { 3 };
            read_row(source, comps, batch, i, &mut r[k]);
            let problem = if k == 1 && sampling {
                let u = &r[1][..2];
                if u.iter().any(|x| x.is_nan()) {
                    Some("NaN")
                } else if u.iter().any(|x| !x.is_finite()) {
                    Some("infinite")
                } else if u.iter().any(|x| !(0.0..1.0).contains(x)) {
                    Some("outside [0, 1)")
                } else {
                    None
                }
            } else {
                vector_problem(&r[k])
            };
            let problem = problem.or_else(|| {
                let n = if rows[2].is_some() {
                    r[2]
                } else {
                    [0.0, 0.0, 1.0]
                };
                let parallel = k == 3
                    && projected
                    && tangent_parallel::<f64>(
                        f64::normalize(DVec3::from_array(n)).0,
                        f64::normalize(DVec3::from_array(r[3])).0,
                    );
                parallel.then_some(PARALLEL_TANGENT)
            });
            if let Some(problem) = problem {
                return Err(BrdfError::BadVector {
                    argument: names[k],
                    index: own_index(i, batch, own(names[k])),
                    problem,
                });
            }
        }
    }
    Ok(())
}

/// Draws one `wo` per element (`u` of shape `(..., 2)` in `[0, 1)²`); returns `wo`,
/// the RGB weight `f·cos θo / pdf` (0 for an invalid draw) and the mixture `pdf`.
pub fn sample(
    kind: ModelKind,
    inputs: Inputs<'_>,
    sampler: SamplerChoice,
    poll: Poll<'_>,
) -> Result<Output, BrdfError> {
    family_a(kind, sampler)?;
    kind.visit(Run {
        inputs,
        sampling: true,
        sampler,
        poll,
    })
}

/// Returns the sampler's density of `wo` per element (and `f·cos/pdf` as `weight`).
pub fn pdf(
    kind: ModelKind,
    inputs: Inputs<'_>,
    sampler: SamplerChoice,
    poll: Poll<'_>,
) -> Result<Output, BrdfError> {
    family_a(kind, sampler)?;
    kind.visit(Run {
        inputs,
        sampling: false,
        sampler,
        poll,
    })
}

fn family_a(kind: ModelKind, sampler: SamplerChoice) -> Result<(), BrdfError> {
    // The hemisphere samplers cannot reach the transmitted half of the sphere.
    if kind.spec().transmission
        && !matches!(sampler, SamplerChoice::Auto | SamplerChoice::Importance)
    {
        return Err(BrdfError::InvalidArgument(format!(
            "sampler: {} transmits, and only its own sampler (\"auto\" or \"importance\") \
             covers the whole sphere",
            kind.name()
        )));
    }
    if kind.spec().family == Family::A {
        Ok(())
    } else {
        Err(BrdfError::InvalidArgument(format!(
            "{}: sampling is defined for family-A BRDFs; {} is a family-B shading term",
            kind.name(),
            kind.name()
        )))
    }
}
