//! Materials: which kernels a material needs, which it can skip, and the batch loop that
//! evaluates one kernel over the pixel-light pairs that survived culling.
//!
//! A material is one family-A BRDF (a light contributes `L·f(l, v)·(n·l)`), optionally
//! under a sheen layer ([`super::sheen`]), or a pair of family-B shading terms, diffuse
//! and specular (a light contributes `L·s(l, v)`), as docs/models.md defines them. Preparing a material turns it into *parts*, each one kernel
//! with its prepared constants ([`Kernel::prepare`] runs once per part, never per pixel):
//!
//! - a part whose colour parameters are all zero is dropped ([`is_zero_weight`]): a
//!   Phong material with `ks = 0` costs what Lambert costs;
//! - a family-A model whose specular colours are zero is evaluated as its diffuse term
//!   alone ([`family_a_diffuse`]: `lambert` with `kd` or `π·kd`), so it too costs what
//!   Lambert costs; the same split renders `--only diffuse` / `--only specular`;
//! - a sheen layer's lobe is a part of its own, and the base's parts are marked as under
//!   the layer: the renderer scales their batch by `1 − weight·E(n·v)` before they run;
//!   a layer with no coverage is dropped;
//! - each part knows what it is for lights behind the surface ([`unlit_behaviour`]):
//!   zero (such lights are culled before any kernel runs), a constant (a toon dark band:
//!   added without a kernel), or varying (the kernel runs).
//!
//! The rules are exhaustive matches over [`ModelKind`], so a new model must state them;
//! the tests check each rule against the kernels themselves.

use std::marker::PhantomData;

use glam::Vec3;

use crate::error::BrdfError;
use crate::eval::params::ParamRows;
use crate::models::spec::{DiffuseTerm, SceneUse};
use crate::models::toon_diffuse::MAX_THRESHOLDS;
use crate::models::{Directions, Family, Kernel, KernelVisitor, ModelKind};
use crate::simd::{Isa, isa};

use super::sheen::SheenLayer;

/// Pixels per segment: the unit of work the renderer shades at once (one row is cut into
/// segments). A batch of pixel-light pairs never holds more.
pub const SEGMENT: usize = 256;

/// Which components of the materials to render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Component {
    /// Everything.
    Both,
    /// Diffuse terms only; no specular kernel runs.
    Diffuse,
    /// Specular terms only; no diffuse kernel runs.
    Specular,
}

impl Component {
    /// Parses `"both"`, `"diffuse"` or `"specular"`.
    pub fn from_name(name: &str) -> Result<Component, BrdfError> {
        match name {
            "both" => Ok(Component::Both),
            "diffuse" => Ok(Component::Diffuse),
            "specular" => Ok(Component::Specular),
            _ => Err(BrdfError::InvalidArgument(format!(
                "only: expected \"diffuse\" or \"specular\"; got {name:?}"
            ))),
        }
    }
}

/// A model with checked parameters: the kernel's raw parameter slots.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    pub kind: ModelKind,
    pub slots: Vec<f64>,
}

impl Term {
    /// Checks `params` against the model's spec (names, ranges, list rules) and lays
    /// them out in slots. A scene's parameters are uniform: each must be a number, an
    /// RGB triple or (for toon lists) a list.
    pub fn new(
        kind: ModelKind,
        params: Vec<(&str, ndarray::ArrayViewD<'_, f64>)>,
    ) -> Result<Term, BrdfError> {
        let rows = ParamRows::new(kind.spec(), params, &[])?;
        if !rows.batch.is_empty() {
            return Err(BrdfError::Shape(format!(
                "{}: a material's parameters are single values (a number, or an RGB triple \
                 for a colour); got values that broadcast to shape {}",
                kind.name(),
                crate::error::format_shape(&rows.batch)
            )));
        }
        let mut slots = Vec::new();
        rows.slots(0, &mut slots);
        // The renderer's kernels run in float32: a finite value beyond its range would
        // become infinite there (unused list slots hold infinity on purpose).
        let too_big = |x: &f64| x.is_finite() && x.abs() > f64::from(f32::MAX);
        for p in kind.spec().params {
            let range = p.slot..p.slot + p.kind.slots();
            if let Some(&x) = slots.get(range).and_then(|s| s.iter().find(|x| too_big(x))) {
                return Err(BrdfError::InvalidArgument(format!(
                    "{} = {x:?} is out of range: the renderer computes in float32 (|x| <= 3.4e38)",
                    p.name
                )));
            }
        }
        Ok(Term { kind, slots })
    }

    /// Returns the slots of parameter `name` (empty if the model has none).
    pub fn param_slots(&self, name: &str) -> std::ops::Range<usize> {
        self.kind
            .spec()
            .param(name)
            .map_or(0..0, |p| p.slot..p.slot + p.kind.slots())
    }
}

/// A material as described in a scene.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialDesc {
    /// One family-A BRDF: a light contributes `L·f(l, v)·(n·l)`.
    Brdf(Term),
    /// Family-B shading terms: a light contributes `L·s(l, v)` for each term given.
    Shading {
        diffuse: Option<Term>,
        specular: Option<Term>,
    },
    /// A family-A BRDF under a sheen layer ([`super::sheen`]): `weight·f_sheen +
    /// (1 − weight·E_sheen(n·v))·f_base`.
    Layered { base: Term, sheen: SheenLayer },
}

impl MaterialDesc {
    /// Checks that the models belong where they are: a BRDF of family A, shading terms of
    /// family B.
    pub fn check(&self) -> Result<(), BrdfError> {
        let family_of = |t: &Term, want: Family, role: &str| {
            if t.kind.spec().family == want {
                Ok(())
            } else {
                Err(BrdfError::InvalidArgument(format!(
                    "{role}: {} is a family-{} model; expected family {}",
                    t.kind.name(),
                    t.kind.spec().family.letter(),
                    want.letter()
                )))
            }
        };
        // Scenes shade reflection only (lights and viewer on n's side of the surface).
        let reflects = |t: &Term| {
            if t.kind.spec().transmission {
                Err(BrdfError::InvalidArgument(format!(
                    "model: {} transmits (a BSDF); scenes render reflecting models only",
                    t.kind.name()
                )))
            } else {
                Ok(())
            }
        };
        match self {
            MaterialDesc::Brdf(t) => {
                family_of(t, Family::A, "model")?;
                reflects(t)
            }
            MaterialDesc::Layered { base, sheen } => {
                family_of(base, Family::A, "model")?;
                reflects(base)?;
                SheenLayer::new(sheen.term.clone(), sheen.weight).map(|_| ())
            }
            MaterialDesc::Shading { diffuse, specular } => {
                if let Some(t) = diffuse {
                    family_of(t, Family::B, "diffuse")?;
                }
                if let Some(t) = specular {
                    family_of(t, Family::B, "specular")?;
                }
                Ok(())
            }
        }
    }

    /// Returns whether any kernel of the material reads a tangent.
    pub fn needs_tangent(&self) -> bool {
        self.any_term(|t| t.kind.spec().tangent != crate::models::TangentUse::None)
    }

    /// Returns whether a term requires a tangent (`kajiya_kay`); the anisotropic models
    /// take +x, projected onto the tangent plane, when none is given (as in `eval`).
    pub fn requires_tangent(&self) -> bool {
        self.any_term(|t| t.kind.spec().tangent == crate::models::TangentUse::Required)
    }

    fn any_term(&self, uses: impl Fn(&Term) -> bool) -> bool {
        match self {
            MaterialDesc::Brdf(t) => uses(t),
            MaterialDesc::Layered { base, sheen } => uses(base) || uses(&sheen.term),
            MaterialDesc::Shading { diffuse, specular } => {
                diffuse.as_ref().is_some_and(&uses) || specular.as_ref().is_some_and(&uses)
            }
        }
    }
}

/// What a part computes, for statistics and `--only`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A whole family-A BRDF.
    Brdf,
    /// A diffuse term (family B), or a family-A model's diffuse term alone.
    Diffuse,
    /// A specular term (family B), or a family-A model without its diffuse term.
    Specular,
    /// A sheen layer's lobe (weighted by its coverage).
    Sheen,
}

impl Role {
    /// Returns `"brdf"`, `"diffuse"` or `"specular"`.
    pub fn name(self) -> &'static str {
        match self {
            Role::Brdf => "brdf",
            Role::Diffuse => "diffuse",
            Role::Specular => "specular",
            Role::Sheen => "sheen",
        }
    }
}

/// The colour parameters that weight every term of a model (its spec's `weights`).
pub fn weight_params(kind: ModelKind) -> Option<&'static [&'static str]> {
    kind.spec().weights
}

/// Returns whether a term is zero everywhere because its weight colours are all zero.
pub fn is_zero_weight(term: &Term) -> bool {
    let Some(names) = weight_params(term.kind) else {
        return false;
    };
    names
        .iter()
        .all(|name| term.slots[term.param_slots(name)].iter().all(|&x| x == 0.0))
}

/// What a term is for lights behind the surface (`n·l <= 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unlit {
    /// Zero: such lights are culled before any kernel runs.
    Zero,
    /// The same colour for every such light and view: added as `L·colour`, no kernel.
    Constant([f64; 3]),
    /// Depends on the directions: the kernel runs.
    Varies,
}

/// Returns what a term is for lights behind the surface. Every family-A model that does
/// not transmit is zero there (zero unless `mu_i > 0`), and so is every family-B term but `toon_diffuse`,
/// whose bands count thresholds against the signed `n·l` (docs/models.md): when no threshold
/// lies in `(−1, 0]` every `n·l` in `[−1, 0]` falls in the same band, whose colour (read
/// from the kernel itself at `n·l = −1`) is the term's constant value there.
pub fn unlit_behaviour(term: &Term) -> Unlit {
    use ModelKind::*;
    match term.kind {
        ToonDiffuse => {
            let thresholds = &term.slots[term.param_slots("thresholds")];
            debug_assert_eq!(thresholds.len(), MAX_THRESHOLDS);
            let band = |cos_l: f64| thresholds.iter().filter(|&&t| t <= cos_l).count();
            if band(-1.0) != band(0.0) {
                return Unlit::Varies;
            }
            let behind = Directions::<f64> {
                wi: glam::DVec3::NEG_Z,
                wo: glam::DVec3::Z,
                n: glam::DVec3::Z,
                t: glam::DVec3::X,
            };
            match eval_f64(term, &behind) {
                [0.0, 0.0, 0.0] => Unlit::Zero,
                colour => Unlit::Constant(colour),
            }
        }
        // A transmitting model (which `MaterialDesc::check` keeps out of scenes) is not
        // zero behind the surface.
        _ if term.kind.spec().transmission => Unlit::Varies,
        _ => Unlit::Zero,
    }
}

/// Returns the term's value for one set of directions, in `f64`.
pub fn eval_f64(term: &Term, d: &Directions<f64>) -> [f64; 3] {
    struct Eval<'a>(&'a [f64], &'a Directions<f64>);
    impl KernelVisitor for Eval<'_> {
        type Output = [f64; 3];
        fn visit<K: Kernel>(self) -> [f64; 3] {
            K::eval(&K::prepare::<f64, [f64]>(self.0), self.1)
        }
    }
    term.kind.visit(Eval(&term.slots, d))
}

/// Returns how a family-A model's diffuse term is evaluated alone (`None` for family B).
/// A family-A model with a `kd` is `diffuse(kd) + rest(other parameters)`
/// (docs/models.md); the tests check `f(kd, ...) − f(0, ...) = lambert(scale·kd)` for
/// each. The multiple-scattering lobes have no diffuse term, and Ashikhmin-Shirley's is
/// coupled to its specular reflectance.
pub fn family_a_diffuse(kind: ModelKind) -> Option<DiffuseTerm> {
    match kind.spec().scene {
        SceneUse::Brdf(diffuse) => Some(diffuse),
        _ => None,
    }
}

/// One kernel a material needs, before preparation.
#[derive(Clone, Debug, PartialEq)]
pub struct PartDesc {
    pub term: Term,
    pub role: Role,
    /// A base term under a sheen layer: its value is scaled by `1 − weight·E(n·v)`.
    pub under_sheen: bool,
}

/// Returns the kernels a material needs to render `component`, zero-weight terms left out;
/// an error for a diffuse term that is not a kernel of its own (`ashikhmin_shirley`).
///
/// A sheen layer's lobe comes first (with the specular terms: `--only specular` renders
/// it, `--only diffuse` does not), then the base's parts, marked as under the layer. A
/// layer without coverage (`weight = 0`) leaves the base's parts as they are.
pub fn material_parts(
    material: &MaterialDesc,
    component: Component,
) -> Result<Vec<PartDesc>, BrdfError> {
    let mut parts = Vec::new();
    let mut push = |term: Term, role: Role| {
        if !is_zero_weight(&term) {
            parts.push(PartDesc {
                term,
                role,
                under_sheen: false,
            });
        }
    };
    match material {
        MaterialDesc::Layered { base, sheen } => return layered_parts(base, sheen, component),
        MaterialDesc::Shading { diffuse, specular } => {
            if component != Component::Specular {
                if let Some(t) = diffuse {
                    push(t.clone(), Role::Diffuse);
                }
            }
            if component != Component::Diffuse {
                if let Some(t) = specular {
                    push(t.clone(), Role::Specular);
                }
            }
        }
        MaterialDesc::Brdf(term) => match family_a_diffuse(term.kind) {
            Some(DiffuseTerm::Whole) | None => {
                if component != Component::Specular {
                    push(term.clone(), Role::Brdf);
                }
            }
            Some(DiffuseTerm::Absent) => {
                if component != Component::Diffuse {
                    push(term.clone(), Role::Specular);
                }
            }
            Some(DiffuseTerm::Coupled) => match component {
                Component::Specular => {
                    let mut rest = term.clone();
                    let rd = rest.param_slots("Rd");
                    rest.slots[rd].fill(0.0);
                    push(rest, Role::Specular);
                }
                Component::Both => push(term.clone(), Role::Brdf),
                Component::Diffuse => {
                    return Err(BrdfError::InvalidArgument(format!(
                        "only: {}'s diffuse term depends on the specular parameters and \
                         cannot be rendered alone; render only='specular' or both",
                        term.kind.name()
                    )));
                }
            },
            Some(DiffuseTerm::Lambert(scale)) => {
                let kd = term.param_slots("kd");
                let diffuse = Term {
                    kind: ModelKind::Lambert,
                    slots: term.slots[kd.clone()].iter().map(|c| c * scale).collect(),
                };
                let mut rest = term.clone();
                rest.slots[kd].fill(0.0);
                let rest_is_zero = is_zero_weight(&rest);
                match component {
                    Component::Both if rest_is_zero => push(diffuse, Role::Diffuse),
                    Component::Both => push(term.clone(), Role::Brdf),
                    Component::Diffuse => push(diffuse, Role::Diffuse),
                    Component::Specular => push(rest, Role::Specular),
                }
            }
        },
    }
    Ok(parts)
}

/// The parts of a family-A model under a sheen layer (see [`material_parts`]).
fn layered_parts(
    base: &Term,
    sheen: &SheenLayer,
    component: Component,
) -> Result<Vec<PartDesc>, BrdfError> {
    let base_parts = material_parts(&MaterialDesc::Brdf(base.clone()), component)?;
    if sheen.is_absent() {
        return Ok(base_parts);
    }
    let mut parts = Vec::new();
    let lobe = sheen.weighted_term();
    if component != Component::Diffuse && !is_zero_weight(&lobe) {
        parts.push(PartDesc {
            term: lobe,
            role: Role::Sheen,
            under_sheen: false,
        });
    }
    parts.extend(base_parts.into_iter().map(|p| PartDesc {
        under_sheen: true,
        ..p
    }));
    Ok(parts)
}

/// Pixel-light pairs to shade with one kernel, structure of arrays: the directions (unit
/// vectors), the weight each value is multiplied by (light colour × falloff, × `n·l` for
/// family A) and the segment pixel each pair adds into.
pub struct Batch {
    pub len: usize,
    pub wi: [[f32; SEGMENT]; 3],
    pub wo: [[f32; SEGMENT]; 3],
    pub n: [[f32; SEGMENT]; 3],
    pub t: [[f32; SEGMENT]; 3],
    pub weight: [[f32; SEGMENT]; 3],
    pub pixel: [u16; SEGMENT],
}

impl Batch {
    /// Returns an empty batch.
    pub fn new() -> Batch {
        Batch {
            len: 0,
            wi: [[0.0; SEGMENT]; 3],
            wo: [[0.0; SEGMENT]; 3],
            n: [[0.0; SEGMENT]; 3],
            t: [[1.0; SEGMENT]; 3],
            weight: [[0.0; SEGMENT]; 3],
            pixel: [0; SEGMENT],
        }
    }
}

impl Default for Batch {
    fn default() -> Self {
        Batch::new()
    }
}

/// Radiance accumulated per segment pixel, RGB structure of arrays.
pub type Accumulator = [[f32; SEGMENT]; 3];

/// A prepared kernel, its type erased: adds `weight·value` of every pair of a batch into
/// the accumulator.
trait BatchKernel: Send + Sync {
    fn shade(&self, batch: &Batch, acc: &mut Accumulator);
}

/// The batch loop: the kernel over every pair (a straight loop over structure-of-arrays
/// that vectorizes across pairs), then the weighted values added into their pixels.
#[inline(always)]
fn shade_batch<K: Kernel>(prepared: &K::Prepared<f32>, b: &Batch, acc: &mut Accumulator) {
    let len = b.len.min(SEGMENT);
    let mut rgb = [[0.0f32; SEGMENT]; 3];
    for j in 0..len {
        let d = Directions::<f32> {
            wi: Vec3::new(b.wi[0][j], b.wi[1][j], b.wi[2][j]),
            wo: Vec3::new(b.wo[0][j], b.wo[1][j], b.wo[2][j]),
            n: Vec3::new(b.n[0][j], b.n[1][j], b.n[2][j]),
            t: Vec3::new(b.t[0][j], b.t[1][j], b.t[2][j]),
        };
        let s = K::eval(prepared, &d);
        for c in 0..3 {
            rgb[c][j] = s[c] * b.weight[c][j];
        }
    }
    for j in 0..len {
        let p = b.pixel[j] as usize % SEGMENT;
        for c in 0..3 {
            acc[c][p] += rgb[c][j];
        }
    }
}

type BatchFn<K> = unsafe fn(&<K as Kernel>::Prepared<f32>, &Batch, &mut Accumulator);

fn batch_baseline<K: Kernel>(p: &K::Prepared<f32>, b: &Batch, acc: &mut Accumulator) {
    shade_batch::<K>(p, b, acc)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn batch_avx2<K: Kernel>(p: &K::Prepared<f32>, b: &Batch, acc: &mut Accumulator) {
    shade_batch::<K>(p, b, acc)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn batch_avx512<K: Kernel>(p: &K::Prepared<f32>, b: &Batch, acc: &mut Accumulator) {
    shade_batch::<K>(p, b, acc)
}

struct Typed<K: Kernel> {
    prepared: K::Prepared<f32>,
    run: BatchFn<K>,
    _kernel: PhantomData<fn() -> K>,
}

impl<K: Kernel> BatchKernel for Typed<K> {
    fn shade(&self, batch: &Batch, acc: &mut Accumulator) {
        // SAFETY: `run` is the loop `Prepare::visit` picked for its `Isa`: `batch_avx512`
        // or `batch_avx2` only for an `Isa::Avx512` / `Isa::Avx2` token, which `simd`
        // makes after finding their features on this CPU; else the baseline loop.
        unsafe { (self.run)(&self.prepared, batch, acc) }
    }
}

/// Prepares a kernel from raw slots (once per material part) and picks its batch loop.
struct Prepare<'a> {
    slots: &'a [f32],
    isa: Isa,
}

impl KernelVisitor for Prepare<'_> {
    type Output = Box<dyn BatchKernel>;

    fn visit<K: Kernel>(self) -> Box<dyn BatchKernel> {
        let run: BatchFn<K> = match self.isa {
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512(_) => batch_avx512::<K>,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2(_) => batch_avx2::<K>,
            _ => batch_baseline::<K>,
        };
        Box::new(Typed::<K> {
            prepared: K::prepare::<f32, [f32]>(self.slots),
            run,
            _kernel: PhantomData,
        })
    }
}

/// A material part ready to shade.
pub struct Part {
    pub kind: ModelKind,
    pub role: Role,
    /// Family A: each value is multiplied by `n·l`.
    pub cosine_weighted: bool,
    /// What the part is for lights behind the surface.
    pub unlit: Unlit,
    /// A base term under a sheen layer (its batch is scaled first).
    pub under_sheen: bool,
    kernel: Box<dyn BatchKernel>,
}

impl Part {
    /// Prepares a part: the kernel's constants are derived here, once.
    pub fn prepare(desc: &PartDesc) -> Part {
        let slots: Vec<f32> = desc.term.slots.iter().map(|&x| x as f32).collect();
        let kernel = desc.term.kind.visit(Prepare {
            slots: &slots,
            isa: isa(),
        });
        Part {
            kind: desc.term.kind,
            role: desc.role,
            cosine_weighted: desc.term.kind.spec().family == Family::A,
            unlit: unlit_behaviour(&desc.term),
            under_sheen: desc.under_sheen,
            kernel,
        }
    }

    /// Adds `weight·value` of every pair of `batch` into `acc`.
    pub fn shade(&self, batch: &Batch, acc: &mut Accumulator) {
        self.kernel.shade(batch, acc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A deterministic stream of numbers in [0, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn unit(&mut self) -> DVec3 {
            loop {
                let v = DVec3::new(
                    2.0 * self.next() - 1.0,
                    2.0 * self.next() - 1.0,
                    2.0 * self.next() - 1.0,
                );
                let l = v.length();
                if l > 0.1 && l < 1.0 {
                    return v / l;
                }
            }
        }
    }

    fn term(kind: ModelKind, given: &[(&str, Vec<f64>)]) -> Term {
        let arrays: Vec<(&str, ndarray::ArrayD<f64>)> = given
            .iter()
            .map(|(k, v)| {
                let a = if v.len() == 1 {
                    ndarray::ArrayD::from_elem(ndarray::IxDyn(&[]), v[0])
                } else {
                    ndarray::ArrayD::from_shape_vec(ndarray::IxDyn(&[v.len()]), v.clone()).unwrap()
                };
                (*k, a)
            })
            .collect();
        let views = arrays.iter().map(|(k, a)| (*k, a.view())).collect();
        Term::new(kind, views).unwrap()
    }

    fn toon_required(kind: ModelKind) -> Vec<(&'static str, Vec<f64>)> {
        match kind {
            ModelKind::ToonDiffuse => vec![
                ("thresholds", vec![-0.3, 0.5]),
                ("colors", vec![0.2, 0.5, 0.9]),
            ],
            ModelKind::ToonSpecular => vec![("threshold", vec![0.8])],
            _ => vec![],
        }
    }

    fn eval64(t: &Term, d: &Directions<f64>) -> [f64; 3] {
        eval_f64(t, d)
    }

    fn directions(rng: &mut Lcg) -> Directions<f64> {
        let n = rng.unit();
        Directions {
            wi: rng.unit(),
            wo: rng.unit(),
            n,
            t: rng.unit(),
        }
    }

    #[test]
    fn zero_weight_terms_are_zero_everywhere() {
        let mut rng = Lcg(7);
        for &kind in ModelKind::ALL {
            let mut given = toon_required(kind);
            let Some(names) = weight_params(kind) else {
                // Schlick F0 (blinn_phong_fresnel, ggx, beckmann, the multiple-scattering
                // lobes, ashikhmin_shirley) and the conductor Fresnel term: black colours
                // (those that may be 0: not a conductor's eta) still reflect at grazing
                // angles.
                let black: Vec<(&str, Vec<f64>)> = kind
                    .spec()
                    .params
                    .iter()
                    .filter(|p| p.kind == crate::models::ParamKind::Colour && p.range.admits(0.0))
                    .map(|p| (p.name, vec![0.0]))
                    .collect();
                let t = term(kind, &black);
                assert!(!is_zero_weight(&t));
                let d = Directions {
                    wi: DVec3::new(0.9, 0.0, 0.1).normalize(),
                    wo: DVec3::new(-0.9, 0.0, 0.1).normalize(),
                    n: DVec3::Z,
                    t: DVec3::X,
                };
                assert!(eval64(&t, &d)[0] > 0.0);
                continue;
            };
            for name in names {
                given.retain(|(k, _)| k != name);
                let zeros = if *name == "colors" {
                    vec![0.0; 3]
                } else {
                    vec![0.0]
                };
                given.push((name, zeros));
            }
            let t = term(kind, &given);
            assert!(is_zero_weight(&t), "{}", kind.name());
            for _ in 0..2000 {
                let d = directions(&mut rng);
                assert_eq!(eval64(&t, &d), [0.0; 3], "{}", kind.name());
            }
        }
    }

    /// Directions with the light behind the surface (`n·l <= 0`).
    fn behind(rng: &mut Lcg) -> Directions<f64> {
        let mut d = directions(rng);
        if d.n.dot(d.wi) > 0.0 {
            d.wi = d.wi - d.n * (2.0 * d.n.dot(d.wi));
        }
        d
    }

    #[test]
    fn unlit_behaviour_matches_the_kernels() {
        let mut rng = Lcg(11);
        for &kind in ModelKind::ALL {
            if kind == ModelKind::ToonDiffuse {
                continue;
            }
            let t = term(kind, &toon_required(kind));
            if kind.spec().transmission {
                assert_eq!(unlit_behaviour(&t), Unlit::Varies, "{}", kind.name());
                continue;
            }
            assert_eq!(unlit_behaviour(&t), Unlit::Zero, "{}", kind.name());
            for _ in 0..2000 {
                assert_eq!(eval64(&t, &behind(&mut rng)), [0.0; 3], "{}", kind.name());
            }
        }
        // Toon diffuse: constant when no threshold lies in (-1, 0], whatever the colours.
        for _ in 0..50 {
            let k = 1 + (rng.next() * 4.0) as usize;
            let mut thresholds: Vec<f64> = (0..k).map(|_| 1e-6 + rng.next()).collect();
            thresholds.sort_by(f64::total_cmp);
            let colours: Vec<f64> = (0..3 * (k + 1)).map(|_| rng.next()).collect();
            let mut t = term(
                ModelKind::ToonDiffuse,
                &[("thresholds", thresholds), ("colors", vec![0.0; k + 1])],
            );
            let c = t.param_slots("colors").start;
            t.slots[c..c + colours.len()].copy_from_slice(&colours);
            let Unlit::Constant(value) = unlit_behaviour(&t) else {
                panic!("{:?}", unlit_behaviour(&t));
            };
            assert_eq!(value, [colours[0], colours[1], colours[2]]);
            for _ in 0..200 {
                assert_eq!(eval64(&t, &behind(&mut rng)), value);
            }
        }
        // Black dark bands are zero; a threshold in (-1, 0] makes the value vary.
        let dark = term(
            ModelKind::ToonDiffuse,
            &[
                ("thresholds", vec![0.1, 0.6]),
                ("colors", vec![0.0, 0.5, 1.0]),
            ],
        );
        assert_eq!(unlit_behaviour(&dark), Unlit::Zero);
        for thresholds in [vec![-0.5, 0.6], vec![0.0, 0.6]] {
            let t = term(
                ModelKind::ToonDiffuse,
                &[("thresholds", thresholds), ("colors", vec![0.0, 0.5, 1.0])],
            );
            assert_eq!(unlit_behaviour(&t), Unlit::Varies);
        }
        // Thresholds at or below -1 are passed by every n·l: the band is constant again.
        let low = term(
            ModelKind::ToonDiffuse,
            &[
                ("thresholds", vec![-1.0, 0.5]),
                ("colors", vec![0.0, 0.25, 1.0]),
            ],
        );
        assert_eq!(unlit_behaviour(&low), Unlit::Constant([0.25; 3]));
    }

    #[test]
    fn family_a_diffuse_terms_are_exact() {
        let mut rng = Lcg(3);
        for &kind in ModelKind::ALL {
            let Some(DiffuseTerm::Lambert(scale)) = family_a_diffuse(kind) else {
                continue;
            };
            let mut given = vec![("kd", vec![0.3, 0.6, 0.9])];
            if kind.spec().param("ks").is_some() {
                given.push(("ks", vec![0.4, 0.2, 0.7]));
            }
            if kind.spec().params.iter().any(|p| p.name == "p") {
                given.push(("p", vec![20.0]));
            }
            let full = term(kind, &given);
            let mut rest = full.clone();
            let kd = rest.param_slots("kd");
            rest.slots[kd].fill(0.0);
            let lambert = term(
                ModelKind::Lambert,
                &[("kd", vec![0.3 * scale, 0.6 * scale, 0.9 * scale])],
            );
            for _ in 0..2000 {
                let d = directions(&mut rng);
                let (a, b, c) = (eval64(&full, &d), eval64(&rest, &d), eval64(&lambert, &d));
                for ch in 0..3 {
                    let want = b[ch] + c[ch];
                    assert!(
                        (a[ch] - want).abs() <= 1e-12 * want.abs().max(1.0),
                        "{}: {a:?} vs {b:?} + {c:?}",
                        kind.name()
                    );
                }
            }
        }
    }

    #[test]
    fn parts_skip_what_is_not_needed() {
        let lambert_d = term(ModelKind::LambertShading, &[("kd", vec![0.5])]);
        let phong_s0 = term(ModelKind::PhongSpecular, &[("ks", vec![0.0])]);
        let m = MaterialDesc::Shading {
            diffuse: Some(lambert_d.clone()),
            specular: Some(phong_s0),
        };
        let parts = material_parts(&m, Component::Both).unwrap();
        assert_eq!(parts.len(), 1);
        assert_eq!(parts[0].term, lambert_d);

        let phong_a = term(ModelKind::Phong, &[("kd", vec![0.5]), ("ks", vec![0.0])]);
        let parts = material_parts(&MaterialDesc::Brdf(phong_a.clone()), Component::Both).unwrap();
        assert_eq!(parts.len(), 1);
        assert_eq!(parts[0].term.kind, ModelKind::Lambert);
        assert!(
            (parts[0].term.slots[crate::models::lambert::KD.first()] - 0.5 * std::f64::consts::PI)
                .abs()
                < 1e-15
        );
        assert!(
            material_parts(&MaterialDesc::Brdf(phong_a), Component::Specular)
                .unwrap()
                .is_empty()
        );

        let ts = term(
            ModelKind::TorranceSparrow,
            &[("kd", vec![0.2]), ("ks", vec![0.8])],
        );
        let m = MaterialDesc::Brdf(ts);
        assert_eq!(
            material_parts(&m, Component::Both).unwrap()[0].role,
            Role::Brdf
        );
        assert_eq!(
            material_parts(&m, Component::Diffuse).unwrap()[0].term.kind,
            ModelKind::Lambert
        );
        let spec = &material_parts(&m, Component::Specular).unwrap()[0];
        assert_eq!(spec.term.kind, ModelKind::TorranceSparrow);
        assert_eq!(&spec.term.slots[spec.term.param_slots("kd")], &[0.0; 3]);
    }

    #[test]
    fn a_sheen_layer_goes_first_and_its_base_under_it() {
        let base = term(ModelKind::Ggx, &[("kd", vec![0.4]), ("alpha", vec![0.3])]);
        let lobe = term(
            ModelKind::CharlieSheen,
            &[("ks", vec![0.8, 0.4, 0.4]), ("alpha", vec![0.3])],
        );
        let layered = |weight: f64| MaterialDesc::Layered {
            base: base.clone(),
            sheen: SheenLayer::new(lobe.clone(), weight).unwrap(),
        };
        for component in [Component::Both, Component::Diffuse, Component::Specular] {
            let plain = material_parts(&MaterialDesc::Brdf(base.clone()), component).unwrap();
            // No coverage: exactly the base's parts.
            assert_eq!(material_parts(&layered(0.0), component).unwrap(), plain);
            let parts = material_parts(&layered(0.5), component).unwrap();
            let (sheen, under): (Vec<_>, Vec<_>) = parts.iter().partition(|p| !p.under_sheen);
            assert_eq!(under.len(), plain.len());
            for (u, p) in under.iter().zip(&plain) {
                assert_eq!((&u.term, u.role), (&p.term, p.role));
            }
            if component == Component::Diffuse {
                assert!(sheen.is_empty());
            } else {
                assert_eq!(parts[0].role, Role::Sheen);
                assert_eq!(sheen.len(), 1);
                let ks = lobe.param_slots("ks");
                assert_eq!(sheen[0].term.slots[ks], [0.4, 0.2, 0.2]);
            }
        }
        // A black layer still covers the base: no lobe, the base under it.
        let black = term(ModelKind::CharlieSheen, &[("ks", vec![0.0])]);
        let m = MaterialDesc::Layered {
            base: base.clone(),
            sheen: SheenLayer::new(black, 1.0).unwrap(),
        };
        let parts = material_parts(&m, Component::Both).unwrap();
        assert!(parts.iter().all(|p| p.under_sheen) && !parts.is_empty());
        // What a layer refuses, and a family-B base.
        let with_kd = term(ModelKind::CharlieSheen, &[("kd", vec![0.1])]);
        for (t, w, want) in [
            (lobe.clone(), 1.5, "sheen.weight"),
            (lobe.clone(), f64::NAN, "sheen.weight"),
            (with_kd, 1.0, "sheen.kd"),
            (base.clone(), 1.0, "sheen.model"),
        ] {
            let err = SheenLayer::new(t, w).unwrap_err().to_string();
            assert!(err.contains(want), "{err}");
        }
        let shading = MaterialDesc::Layered {
            base: term(ModelKind::LambertShading, &[("kd", vec![0.5])]),
            sheen: SheenLayer::new(lobe, 1.0).unwrap(),
        };
        assert!(shading.check().is_err());
    }

    #[test]
    fn parts_of_the_newer_models() {
        let ms = term(ModelKind::GgxMs, &[("ks", vec![0.5])]);
        let m = MaterialDesc::Brdf(ms.clone());
        assert!(material_parts(&m, Component::Diffuse).unwrap().is_empty());
        for component in [Component::Both, Component::Specular] {
            let parts = material_parts(&m, component).unwrap();
            assert_eq!(
                parts,
                vec![PartDesc {
                    term: ms.clone(),
                    role: Role::Specular,
                    under_sheen: false,
                }]
            );
        }
        let a_s = term(
            ModelKind::AshikhminShirley,
            &[("Rd", vec![0.5]), ("Rs", vec![0.1])],
        );
        let m = MaterialDesc::Brdf(a_s.clone());
        assert_eq!(
            material_parts(&m, Component::Both).unwrap()[0].role,
            Role::Brdf
        );
        let spec = material_parts(&m, Component::Specular).unwrap();
        assert_eq!(spec.len(), 1);
        let rd = a_s.param_slots("Rd");
        assert_eq!(spec[0].term.slots[rd.clone()], [0.0; 3]);
        assert_eq!(spec[0].term.slots[rd.end..], a_s.slots[rd.end..]);
        let refused = material_parts(&m, Component::Diffuse)
            .unwrap_err()
            .to_string();
        assert!(
            refused.contains("ashikhmin_shirley's diffuse term"),
            "{refused}"
        );
    }
}
