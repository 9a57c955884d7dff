//! Rendering: rays, nearest hits, then shading of every hit pixel under every light.
//!
//! Work is split in rows (in parallel), each row in segments of [`SEGMENT`] pixels. Per
//! segment: the objects the segment's rays can reach (a sphere outside the wedge or strip
//! they sweep is skipped; if nothing is left, the segment is background and not even its
//! rays are made), then camera rays and the ray tests (vectorized loops); if no ray hit,
//! nothing else runs. Otherwise hit points, normals and (only when a material needs
//! them) tangents are computed, and the hit pixels are grouped by material. Then, per
//! light: `wi`, falloff and `n·l` for every pixel (vectorized); pixels out of the light's
//! reach, and those with `n·l <= 0` for parts that are zero there, are culled — if none
//! is left the light costs nothing more for this segment; the survivors are packed into
//! a batch per material and each of the material's parts runs its kernel over the
//! batch (for a material under a sheen layer: the layer's lobe, then the base's parts on
//! the batch scaled by the layer's `1 − weight·E(n·v)`). A part that is one constant
//! colour for lights behind the surface (a toon dark band) gets `L·colour` added there
//! without a kernel.
//!
//! Every pixel's value is the same sum in the same order (parts in order, lights in
//! order) whatever the thread count: output is deterministic.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::camera::Camera;
use super::geometry::Object;
use super::lights::{Light, LightField};
use super::shading::{
    Accumulator, Batch, Component, MaterialDesc, Part, Role, SEGMENT, Unlit, material_parts,
};
use super::sheen::Scaling;
use crate::error::BrdfError;
use crate::models::ModelKind;
use crate::parallel;

/// A scene: camera, materials, objects (each naming a material by index), lights.
#[derive(Clone, Debug)]
pub struct Scene {
    pub camera: Camera,
    pub materials: Vec<MaterialDesc>,
    pub objects: Vec<Object>,
    pub lights: Vec<Light>,
    /// Radiance of pixels that hit nothing.
    pub background: [f32; 3],
}

impl Scene {
    /// Returns the radiance of pixels that hit nothing in the renderer's float32, or an
    /// error for a value beyond its range (it would become infinite).
    pub fn background_from(rgb: [f64; 3]) -> Result<[f32; 3], BrdfError> {
        if rgb.iter().any(|&x| !(x as f32).is_finite()) {
            return Err(BrdfError::InvalidArgument(format!(
                "background: expected an RGB triple within float32's range (|x| <= 3.4e38); \
                 got {rgb:?}"
            )));
        }
        Ok(rgb.map(|x| x as f32))
    }
}

/// Counts of the work one render did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Pixels rendered.
    pub pixels: u64,
    /// Ray-object tests (each segment's pixels × the objects its rays may reach).
    pub ray_tests: u64,
    /// Pixels whose ray hit an object.
    pub hits: u64,
    /// Lights that took part (black lights are dropped before rendering).
    pub lights: u64,
    /// Black lights dropped.
    pub lights_dropped: u64,
    /// Materials prepared (those some object uses).
    pub materials_prepared: u64,
    /// Hit pixel × light pairs (of segments where some material has a kernel to run).
    pub pairs: u64,
    /// Pairs beyond a point light's range (or at the light itself): never shaded.
    pub pairs_out_of_range: u64,
    /// Pairs with `n·l <= 0` (culled for every part that is zero there).
    pub pairs_backfacing: u64,
    /// Backfacing pairs shaded by a constant, without a kernel (toon dark bands).
    pub pairs_constant: u64,
    /// Kernel evaluations per prepared part.
    pub parts: Vec<PartStats>,
}

impl RenderStats {
    /// Returns the kernel evaluations of all parts.
    pub fn evaluations(&self) -> u64 {
        self.parts.iter().map(|p| p.evaluations).sum()
    }

    fn add(&mut self, other: &RenderStats) {
        self.pixels += other.pixels;
        self.ray_tests += other.ray_tests;
        self.hits += other.hits;
        self.pairs += other.pairs;
        self.pairs_out_of_range += other.pairs_out_of_range;
        self.pairs_backfacing += other.pairs_backfacing;
        self.pairs_constant += other.pairs_constant;
        for (a, b) in self.parts.iter_mut().zip(&other.parts) {
            a.evaluations += b.evaluations;
        }
    }
}

/// Running totals of every render and shade call: a cheap debug counter (one atomic
/// add per field per call), exposed to Python as `_brdf_rs.scene_counters()`.
pub struct Counters {
    renders: AtomicU64,
    pixels: AtomicU64,
    ray_tests: AtomicU64,
    hits: AtomicU64,
    pairs: AtomicU64,
    pairs_backfacing: AtomicU64,
    pairs_out_of_range: AtomicU64,
    evaluations: AtomicU64,
}

/// The process-wide counters.
pub static COUNTERS: Counters = Counters {
    renders: AtomicU64::new(0),
    pixels: AtomicU64::new(0),
    ray_tests: AtomicU64::new(0),
    hits: AtomicU64::new(0),
    pairs: AtomicU64::new(0),
    pairs_backfacing: AtomicU64::new(0),
    pairs_out_of_range: AtomicU64::new(0),
    evaluations: AtomicU64::new(0),
};

impl Counters {
    fn fields(&self) -> [(&'static str, &AtomicU64); 8] {
        [
            ("renders", &self.renders),
            ("pixels", &self.pixels),
            ("ray_tests", &self.ray_tests),
            ("hits", &self.hits),
            ("pairs", &self.pairs),
            ("pairs_backfacing", &self.pairs_backfacing),
            ("pairs_out_of_range", &self.pairs_out_of_range),
            ("evaluations", &self.evaluations),
        ]
    }

    fn record(&self, s: &RenderStats) {
        let values = [
            1,
            s.pixels,
            s.ray_tests,
            s.hits,
            s.pairs,
            s.pairs_backfacing,
            s.pairs_out_of_range,
            s.evaluations(),
        ];
        for ((_, counter), value) in self.fields().iter().zip(values) {
            counter.fetch_add(value, Ordering::Relaxed);
        }
    }

    /// Returns every counter by name, and zeroes them if `reset`.
    pub fn snapshot(&self, reset: bool) -> Vec<(&'static str, u64)> {
        self.fields()
            .iter()
            .map(|(name, c)| {
                let v = if reset {
                    c.swap(0, Ordering::Relaxed)
                } else {
                    c.load(Ordering::Relaxed)
                };
                (*name, v)
            })
            .collect()
    }
}

/// One prepared part's counts.
#[derive(Clone, Debug, PartialEq)]
pub struct PartStats {
    /// Index of the material in the scene.
    pub material: usize,
    pub role: Role,
    /// The kernel evaluated (a family-A model's diffuse term alone is `lambert`).
    pub model: ModelKind,
    pub evaluations: u64,
}

/// A material ready to shade: its parts, in order.
struct Prepared {
    parts: Vec<Part>,
    /// Index of the first part in the statistics.
    first_stat: usize,
    /// Family A: values are weighted by `n·l`.
    cosine_weighted: bool,
    /// Some part's kernel runs for lights behind the surface (its value varies there).
    any_varies: bool,
    /// Some part's kernel runs only for lights in front (zero or constant behind).
    any_front: bool,
    /// The sum of the parts' constant values for lights behind the surface, if any.
    unlit_constant: Option<[f32; 3]>,
    /// A sheen layer's scaling of the parts under it (its albedo table built once here).
    sheen: Option<Scaling>,
}

/// Prepares the materials in `used` (others stay `None`: never prepared).
fn prepare(
    materials: &[MaterialDesc],
    used: &[bool],
    component: Component,
    stats: &mut RenderStats,
) -> Result<Vec<Option<Prepared>>, BrdfError> {
    let mut out = Vec::with_capacity(materials.len());
    for (index, (desc, &is_used)) in materials.iter().zip(used).enumerate() {
        if !is_used {
            out.push(None);
            continue;
        }
        desc.check()?;
        let first_stat = stats.parts.len();
        let parts: Vec<Part> = material_parts(desc, component)?
            .iter()
            .map(Part::prepare)
            .collect();
        for p in &parts {
            stats.parts.push(PartStats {
                material: index,
                role: p.role,
                model: p.kind,
                evaluations: 0,
            });
        }
        stats.materials_prepared += 1;
        let mut constant: Option<[f32; 3]> = None;
        for p in &parts {
            if let Unlit::Constant(c) = p.unlit {
                let sum = constant.get_or_insert([0.0; 3]);
                for k in 0..3 {
                    sum[k] += c[k] as f32;
                }
            }
        }
        let sheen = match desc {
            MaterialDesc::Layered { sheen, .. } if parts.iter().any(|p| p.under_sheen) => {
                Some(Scaling::prepare(sheen)?)
            }
            _ => None,
        };
        out.push(Some(Prepared {
            cosine_weighted: matches!(desc, MaterialDesc::Brdf(_) | MaterialDesc::Layered { .. }),
            sheen,
            any_varies: parts.iter().any(|p| p.unlit == Unlit::Varies),
            any_front: parts.iter().any(|p| p.unlit != Unlit::Varies),
            unlit_constant: constant,
            first_stat,
            parts,
        }));
    }
    Ok(out)
}

/// Per-worker scratch: one segment's geometry, a light field, a batch, the accumulator.
struct Scratch {
    origin: [[f32; SEGMENT]; 3],
    dir: [[f32; SEGMENT]; 3],
    t: [f32; SEGMENT],
    id: [u32; SEGMENT],
    p: [[f32; SEGMENT]; 3],
    n: [[f32; SEGMENT]; 3],
    v: [[f32; SEGMENT]; 3],
    tangent: [[f32; SEGMENT]; 3],
    hit: [bool; SEGMENT],
    material: [u32; SEGMENT],
    /// Per pixel: the material's constant colour for lights behind the surface, if any.
    unlit_colour: [[f32; SEGMENT]; 3],
    has_constant: [bool; SEGMENT],
    /// Objects the segment's rays may hit, and whether each was hit.
    candidates: Vec<u32>,
    object_hit: Vec<bool>,
    /// Hit pixels sorted by material, and where each material's run starts.
    order: [u16; SEGMENT],
    starts: Vec<usize>,
    next: Vec<usize>,
    light: LightField,
    batch: Batch,
    acc: Accumulator,
    stats: RenderStats,
}

impl Scratch {
    fn new(stats: &RenderStats, materials: usize) -> Box<Scratch> {
        let mut stats = stats.clone();
        stats.pixels = 0;
        stats.ray_tests = 0;
        stats.hits = 0;
        for p in &mut stats.parts {
            p.evaluations = 0;
        }
        Box::new(Scratch {
            origin: [[0.0; SEGMENT]; 3],
            dir: [[0.0; SEGMENT]; 3],
            t: [0.0; SEGMENT],
            id: [0; SEGMENT],
            p: [[0.0; SEGMENT]; 3],
            n: [[0.0; SEGMENT]; 3],
            v: [[0.0; SEGMENT]; 3],
            tangent: [[1.0; SEGMENT]; 3],
            hit: [false; SEGMENT],
            material: [0; SEGMENT],
            unlit_colour: [[0.0; SEGMENT]; 3],
            has_constant: [false; SEGMENT],
            candidates: Vec::new(),
            object_hit: Vec::new(),
            order: [0; SEGMENT],
            starts: vec![0; materials + 1],
            next: vec![0; materials],
            light: LightField::new(),
            batch: Batch::new(),
            acc: [[0.0; SEGMENT]; 3],
            stats,
        })
    }

    /// Groups the hit pixels by material (a counting sort into `order`).
    #[inline(always)]
    fn group_by_material(&mut self, len: usize) {
        let m = self.starts.len() - 1;
        self.starts.fill(0);
        for j in 0..len {
            if self.hit[j] {
                self.starts[self.material[j] as usize + 1] += 1;
            }
        }
        for k in 0..m {
            self.starts[k + 1] += self.starts[k];
        }
        self.next.copy_from_slice(&self.starts[..m]);
        for j in 0..len {
            if self.hit[j] {
                let k = self.material[j] as usize;
                self.order[self.next[k]] = j as u16;
                self.next[k] += 1;
            }
        }
    }

    /// Shades the hit pixels of the segment (`len` pixels; geometry filled in) into
    /// `acc`: the part of the work shared by `render` and `shade`.
    #[inline(always)]
    fn shade_segment(&mut self, len: usize, materials: &[Option<Prepared>], lights: &[Light]) {
        for c in 0..3 {
            self.acc[c].fill(0.0);
        }
        self.group_by_material(len);
        let hits = self.hit[..len].iter().filter(|&&h| h).count() as u64;
        // The pixels from the first hit to the last: per-light work covers only them.
        let first = self.hit[..len].iter().position(|&h| h).unwrap_or(0);
        let last = self.hit[..len]
            .iter()
            .rposition(|&h| h)
            .map_or(0, |j| j + 1);
        // What the materials present here need: any kernel at all, kernels for lights
        // behind the surface, constants for lights behind the surface (per pixel).
        let (mut any_parts, mut any_varies, mut any_constant) = (false, false, false);
        for (k, m) in materials.iter().enumerate() {
            if let Some(m) = m {
                if self.starts[k] < self.starts[k + 1] {
                    any_parts |= !m.parts.is_empty();
                    any_varies |= m.any_varies;
                    any_constant |= m.unlit_constant.is_some();
                }
            }
        }
        if !any_parts {
            return;
        }
        if any_constant {
            for j in first..last {
                let colour = match &materials[self.material[j] as usize] {
                    Some(m) if self.hit[j] => m.unlit_constant,
                    _ => None,
                };
                self.has_constant[j] = colour.is_some();
                let colour = colour.unwrap_or([0.0; 3]);
                for c in 0..3 {
                    self.unlit_colour[c][j] = colour[c];
                }
            }
        }
        for light in lights {
            let (in_range, lit) =
                self.light
                    .compute(light, &self.p, &self.n, &self.hit, first..last);
            let (in_range, lit) = (in_range as u64, lit as u64);
            self.stats.pairs += hits;
            self.stats.pairs_out_of_range += hits - in_range;
            self.stats.pairs_backfacing += in_range - lit;
            let intensity = light.intensity();
            if any_constant && in_range > lit {
                self.add_unlit_constants(intensity, first..last);
            }
            // Nothing else this light reaches can show it: no kernel runs.
            let front = lit > 0;
            let behind = any_varies && in_range > lit;
            if !front && !behind {
                continue;
            }
            for (k, material) in materials.iter().enumerate() {
                let Some(material) = material else { continue };
                let (start, end) = (self.starts[k], self.starts[k + 1]);
                if start == end {
                    continue;
                }
                for front_only in [true, false] {
                    let wanted = if front_only {
                        front && material.any_front
                    } else {
                        material.any_varies && in_range > 0
                    };
                    if !wanted {
                        continue;
                    }
                    self.fill_batch(start, end, front_only, material.cosine_weighted, intensity);
                    if self.batch.len == 0 {
                        continue;
                    }
                    let mut scaled = false;
                    for (i, part) in material.parts.iter().enumerate() {
                        if (part.unlit != Unlit::Varies) == front_only {
                            if part.under_sheen && !scaled {
                                if let Some(sheen) = &material.sheen {
                                    scale_under_sheen(&mut self.batch, sheen);
                                }
                                scaled = true;
                            }
                            part.shade(&self.batch, &mut self.acc);
                            self.stats.parts[material.first_stat + i].evaluations +=
                                self.batch.len as u64;
                        }
                    }
                }
            }
        }
    }

    /// Adds `L·falloff·colour` at the pixels of `span` the light reaches from behind
    /// (`n·l <= 0`), `colour` being each pixel's material constant there (0 for others):
    /// terms constant behind the surface need no kernel. A straight loop: it vectorizes.
    #[inline(always)]
    fn add_unlit_constants(&mut self, intensity: [f32; 3], span: std::ops::Range<usize>) {
        let light = &self.light;
        let span = span.start.min(SEGMENT)..span.end.min(SEGMENT);
        let mut count = 0u32;
        for j in span {
            let behind = self.hit[j] & light.in_range(j) & !(light.cos_l[j] > 0.0);
            let f = if behind { light.falloff(j) } else { 0.0 };
            for c in 0..3 {
                self.acc[c][j] += intensity[c] * self.unlit_colour[c][j] * f;
            }
            count += (behind & self.has_constant[j]) as u32;
        }
        self.stats.pairs_constant += count as u64;
    }

    /// Packs the pixels `order[start..end]` that the light reaches (and, if
    /// `front_only`, lights from the front) into the batch.
    #[inline(always)]
    fn fill_batch(
        &mut self,
        start: usize,
        end: usize,
        front_only: bool,
        cosine_weighted: bool,
        intensity: [f32; 3],
    ) {
        let light = &self.light;
        let b = &mut self.batch;
        let mut k = 0;
        for &j in &self.order[start..end] {
            let j = j as usize;
            let keep = light.in_range(j) & (!front_only | (light.cos_l[j] > 0.0));
            b.pixel[k] = j as u16;
            k += keep as usize;
        }
        b.len = k;
        for k in 0..b.len {
            let j = b.pixel[k] as usize;
            let scale = if cosine_weighted {
                light.falloff(j) * light.cos_l[j]
            } else {
                light.falloff(j)
            };
            let wi = light.wi(j);
            for c in 0..3 {
                b.wi[c][k] = wi[c];
                b.wo[c][k] = self.v[c][j];
                b.n[c][k] = self.n[c][j];
                b.t[c][k] = self.tangent[c][j];
                b.weight[c][k] = intensity[c] * scale;
            }
        }
    }
}

/// Multiplies each pair's weight by a sheen layer's `1 − weight·E(n·v)`: the batch then
/// shades the parts under the layer.
#[inline(always)]
fn scale_under_sheen(b: &mut Batch, sheen: &Scaling) {
    for k in 0..b.len.min(SEGMENT) {
        let mu_o = b.n[0][k] * b.wo[0][k] + b.n[1][k] * b.wo[1][k] + b.n[2][k] * b.wo[2][k];
        let f = sheen.factor(mu_o);
        for c in 0..3 {
            b.weight[c][k] *= f;
        }
    }
}

/// The scene's objects and prepared materials, for the row loop.
struct Frame<'a> {
    camera: &'a Camera,
    objects: &'a [Object],
    /// Per object: its material index, and whether that material needs tangents.
    object_material: Vec<u32>,
    object_tangent: Vec<bool>,
    materials: Vec<Option<Prepared>>,
    lights: Vec<Light>,
    background: [f32; 3],
}

#[inline(always)]
fn render_row_impl(frame: &Frame<'_>, y: usize, row: &mut [f32], s: &mut Scratch) {
    let width = frame.camera.width;
    for x0 in (0..width).step_by(SEGMENT) {
        let len = SEGMENT.min(width - x0);
        let bounds = frame.camera.segment_bounds(y, x0, len);
        s.candidates.clear();
        for (i, object) in frame.objects.iter().enumerate() {
            if object.may_hit(&bounds) {
                s.candidates.push(i as u32);
            }
        }
        s.stats.pixels += len as u64;
        let out = &mut row[3 * x0..3 * (x0 + len)];
        if s.candidates.is_empty() {
            // No ray of the segment can hit anything: background, without even rays.
            for px in out.chunks_exact_mut(3) {
                px.copy_from_slice(&frame.background);
            }
            continue;
        }
        frame.camera.rays(y, x0, &mut s.origin, &mut s.dir);
        s.t.fill(f32::INFINITY);
        s.id.fill(u32::MAX);
        for &i in &s.candidates {
            frame.objects[i as usize].intersect(i, &s.origin, &s.dir, &mut s.t, &mut s.id);
        }
        s.stats.ray_tests += (len * s.candidates.len()) as u64;
        let mut hits = 0;
        s.object_hit.clear();
        s.object_hit.resize(frame.objects.len(), false);
        for j in 0..SEGMENT {
            s.hit[j] = j < len && s.id[j] != u32::MAX;
            hits += s.hit[j] as usize;
            if s.hit[j] {
                s.object_hit[s.id[j] as usize] = true;
            }
        }
        s.stats.hits += hits as u64;
        if hits == 0 {
            for px in out.chunks_exact_mut(3) {
                px.copy_from_slice(&frame.background);
            }
            continue;
        }
        for c in 0..3 {
            for j in 0..SEGMENT {
                s.p[c][j] = s.origin[c][j] + s.t[j] * s.dir[c][j];
                s.v[c][j] = -s.dir[c][j];
            }
        }
        for &i in &s.candidates {
            let i = i as usize;
            if !s.object_hit[i] {
                continue;
            }
            let object = &frame.objects[i];
            object.normals(i as u32, &s.id, &s.p, &s.dir, &mut s.n);
            if frame.object_tangent[i] {
                object.tangents(i as u32, &s.id, &s.n, &mut s.tangent);
            }
        }
        for j in 0..len {
            s.material[j] = if s.hit[j] {
                frame.object_material[s.id[j] as usize]
            } else {
                0
            };
        }
        s.shade_segment(len, &frame.materials, &frame.lights);
        for (j, px) in out.chunks_exact_mut(3).enumerate() {
            for c in 0..3 {
                px[c] = if s.hit[j] {
                    s.acc[c][j]
                } else {
                    frame.background[c]
                };
            }
        }
    }
}

type RowFn = unsafe fn(&Frame<'_>, usize, &mut [f32], &mut Scratch);

fn row_baseline(frame: &Frame<'_>, y: usize, row: &mut [f32], s: &mut Scratch) {
    render_row_impl(frame, y, row, s)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn row_avx2(frame: &Frame<'_>, y: usize, row: &mut [f32], s: &mut Scratch) {
    render_row_impl(frame, y, row, s)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn row_avx512(frame: &Frame<'_>, y: usize, row: &mut [f32], s: &mut Scratch) {
    render_row_impl(frame, y, row, s)
}

fn row_fn() -> RowFn {
    use crate::simd::{Isa, isa};
    match isa() {
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512(_) => row_avx512,
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2(_) => row_avx2,
        _ => row_baseline,
    }
}

/// Returns `len` zeros, or an error (not an abort) if the memory is not there. Like
/// `vec![0.0; len]` the memory comes zeroed from the allocator (fresh pages cost nothing
/// until the workers write them).
fn zeroed(len: usize, what: &str) -> Result<Vec<f32>, BrdfError> {
    let too_big = || {
        BrdfError::InvalidArgument(format!(
            "{what}: cannot allocate {:.1} GB",
            len as f64 * std::mem::size_of::<f32>() as f64 / 1e9
        ))
    };
    if len == 0 {
        return Ok(Vec::new());
    }
    let layout = std::alloc::Layout::array::<f32>(len).map_err(|_| too_big())?;
    // SAFETY: `layout` has a nonzero size: `len > 0` (checked above) `f32`s.
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f32>();
    if ptr.is_null() {
        return Err(too_big());
    }
    // SAFETY: `ptr` was allocated by the global allocator with the layout of `len`
    // `f32`s (the layout a `Vec<f32>` of capacity `len` uses) and is zeroed, and zero
    // bits are the float 0.0.
    Ok(unsafe { Vec::from_raw_parts(ptr, len, len) })
}

/// Drops black lights, counting them.
fn live_lights(lights: &[Light], stats: &mut RenderStats) -> Vec<Light> {
    let live: Vec<Light> = lights.iter().filter(|l| !l.is_black()).copied().collect();
    stats.lights = live.len() as u64;
    stats.lights_dropped = (lights.len() - live.len()) as u64;
    live
}

/// Renders `component` of the scene: linear radiance, `height × width × 3` floats in
/// row-major order (row 0 at the top), and the counts of the work done.
///
/// # Errors
/// An object naming a material the scene does not have, or a material whose models are
/// of the wrong family.
pub fn render(scene: &Scene, component: Component) -> Result<(Vec<f32>, RenderStats), BrdfError> {
    render_polled(scene, component, &mut || true)
}

/// Pixels rendered between two calls of the `poll` of [`render_polled`] (whole rows: at
/// least one).
pub const POLL_PIXELS: usize = 1 << 18;

/// [`render`], calling `poll` between bands of about [`POLL_PIXELS`] pixels (whole rows)
/// and stopping with [`BrdfError::Interrupted`] when it returns false. Every pixel is
/// computed as by [`render`], bit for bit.
///
/// # Errors
/// As [`render`]; [`BrdfError::Interrupted`].
pub fn render_polled(
    scene: &Scene,
    component: Component,
    poll: &mut dyn FnMut() -> bool,
) -> Result<(Vec<f32>, RenderStats), BrdfError> {
    let mut stats = RenderStats::default();
    let mut used = vec![false; scene.materials.len()];
    for (i, o) in scene.objects.iter().enumerate() {
        if o.material >= scene.materials.len() {
            return Err(BrdfError::InvalidArgument(format!(
                "objects[{i}]: material index {} is out of range ({} materials)",
                o.material,
                scene.materials.len()
            )));
        }
        used[o.material] = true;
    }
    let materials = prepare(&scene.materials, &used, component, &mut stats)?;
    let lights = live_lights(&scene.lights, &mut stats);
    let frame = Frame {
        camera: &scene.camera,
        objects: &scene.objects,
        object_material: scene.objects.iter().map(|o| o.material as u32).collect(),
        object_tangent: scene
            .objects
            .iter()
            .map(|o| scene.materials[o.material].needs_tangent())
            .collect(),
        materials,
        lights,
        background: scene.background,
    };
    let (width, height) = (scene.camera.width, scene.camera.height);
    let mut image = zeroed(width * height * 3, "image")?;
    let row_fn = row_fn();
    let n_materials = scene.materials.len();
    let template = stats.clone();
    let run = |rows: &mut [f32], first: usize, s: &mut Scratch| {
        for (k, row) in rows.chunks_exact_mut(3 * width).enumerate() {
            // SAFETY: `row_fn()` returned `row_avx512` or `row_avx2` only for an
            // `Isa::Avx512` / `Isa::Avx2` token, made by `simd` after it found their
            // `target_feature`s on this CPU; else the baseline `row_baseline`.
            unsafe { row_fn(&frame, first + k, row, s) };
        }
    };
    let band_rows = (POLL_PIXELS / width.max(1)).max(1);
    let mut totals = Vec::new();
    for (b, band) in image.chunks_mut(3 * width * band_rows).enumerate() {
        if b > 0 && !poll() {
            return Err(BrdfError::Interrupted);
        }
        let first = b * band_rows;
        if parallel::num_threads() == 1 || height == 1 {
            let mut s = Scratch::new(&template, n_materials);
            run(band, first, &mut s);
            totals.push(s.stats);
        } else {
            totals.extend(parallel::install(|| {
                band.par_chunks_mut(3 * width)
                    .enumerate()
                    .fold(
                        || Scratch::new(&template, n_materials),
                        |mut s, (y, row)| {
                            run(row, first + y, &mut s);
                            s
                        },
                    )
                    .map(|s| s.stats)
                    .collect::<Vec<_>>()
            }));
        }
    }
    for t in &totals {
        stats.add(t);
    }
    COUNTERS.record(&stats);
    Ok((image, stats))
}

/// What `shade` works on.
struct ShadeJob<'a> {
    g: &'a GBuffer<'a>,
    materials: &'a [Option<Prepared>],
    lights: &'a [Light],
}

/// Shades G-buffer pixels `first ..` into `chunk`, segment by segment.
#[inline(always)]
fn shade_chunk_impl(job: &ShadeJob<'_>, first: usize, chunk: &mut [f32], s: &mut Scratch) {
    let g = job.g;
    for (k, seg) in chunk.chunks_mut(3 * SEGMENT).enumerate() {
        let base = first + k * SEGMENT;
        let n = seg.len() / 3;
        for j in 0..SEGMENT {
            let i = 3 * (base + j.min(n - 1));
            for c in 0..3 {
                s.n[c][j] = g.n[i + c];
                s.v[c][j] = g.v[i + c];
                s.p[c][j] = g.positions.map_or(0.0, |p| p[i + c]);
                // Without tangents: +x, as `eval` takes for the anisotropic models.
                let x_axis = if c == 0 { 1.0 } else { 0.0 };
                s.tangent[c][j] = g.tangents.map_or(x_axis, |t| t[i + c]);
            }
            s.hit[j] = j < n;
            s.material[j] = 0;
        }
        s.stats.pixels += n as u64;
        s.stats.hits += n as u64;
        s.shade_segment(n, job.materials, job.lights);
        for (j, px) in seg.chunks_exact_mut(3).enumerate() {
            for c in 0..3 {
                px[c] = s.acc[c][j];
            }
        }
    }
}

type ShadeFn = unsafe fn(&ShadeJob<'_>, usize, &mut [f32], &mut Scratch);

fn shade_baseline(job: &ShadeJob<'_>, first: usize, chunk: &mut [f32], s: &mut Scratch) {
    shade_chunk_impl(job, first, chunk, s)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn shade_avx2(job: &ShadeJob<'_>, first: usize, chunk: &mut [f32], s: &mut Scratch) {
    shade_chunk_impl(job, first, chunk, s)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn shade_avx512(job: &ShadeJob<'_>, first: usize, chunk: &mut [f32], s: &mut Scratch) {
    shade_chunk_impl(job, first, chunk, s)
}

fn shade_fn() -> ShadeFn {
    use crate::simd::{Isa, isa};
    match isa() {
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512(_) => shade_avx512,
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2(_) => shade_avx2,
        _ => shade_baseline,
    }
}

/// A G-buffer: per-pixel unit normals, unit view directions (toward the viewer),
/// optional positions (for point lights) and unit tangents (for models that need one),
/// each `count × 3` floats.
pub struct GBuffer<'a> {
    pub n: &'a [f32],
    pub v: &'a [f32],
    pub positions: Option<&'a [f32]>,
    pub tangents: Option<&'a [f32]>,
}

/// Shades one material under `lights` at every G-buffer pixel: linear radiance,
/// `count × 3` floats, and the counts of the work done. Inputs are read as given (the
/// caller normalizes them).
///
/// # Errors
/// Lengths that differ or are not multiples of 3; a point light without positions; a
/// material that needs tangents without them.
pub fn shade(
    material: &MaterialDesc,
    lights: &[Light],
    g: &GBuffer<'_>,
    component: Component,
) -> Result<(Vec<f32>, RenderStats), BrdfError> {
    let len = g.n.len();
    let bad = |msg: &str| Err(BrdfError::Shape(msg.to_string()));
    if len % 3 != 0 || g.v.len() != len {
        return bad("n, v: expected arrays of the same shape (..., 3)");
    }
    if g.positions.is_some_and(|p| p.len() != len) || g.tangents.is_some_and(|t| t.len() != len) {
        return bad("positions, tangent: expected the shape of n");
    }
    if g.positions.is_none() && lights.iter().any(Light::needs_positions) {
        return Err(BrdfError::InvalidArgument(
            "positions: point lights need the surface positions".into(),
        ));
    }
    if g.tangents.is_none() && material.requires_tangent() {
        // The argument of `shade` (`brdf_rs.shade(..., tangent=...)`), not a material
        // parameter.
        return Err(BrdfError::MissingParameter {
            model: "shade",
            name: "tangent",
        });
    }
    let mut stats = RenderStats::default();
    let materials = prepare(
        std::slice::from_ref(material),
        &[true],
        component,
        &mut stats,
    )?;
    let lights = live_lights(lights, &mut stats);
    let count = len / 3;
    let mut out = zeroed(len, "output")?;
    let template = stats.clone();
    const TASK: usize = 16 * SEGMENT;
    let job = ShadeJob {
        g,
        materials: &materials,
        lights: &lights,
    };
    let chunk_fn = shade_fn();
    let run = |first: usize, chunk: &mut [f32], s: &mut Scratch| {
        // SAFETY: `shade_fn()` returned `shade_avx512` or `shade_avx2` only for an
        // `Isa::Avx512` / `Isa::Avx2` token, made by `simd` after it found their
        // `target_feature`s on this CPU; else the baseline `shade_baseline`.
        unsafe { chunk_fn(&job, first, chunk, s) }
    };
    let totals = if parallel::num_threads() == 1 || count <= TASK {
        let mut s = Scratch::new(&template, 1);
        run(0, &mut out, &mut s);
        vec![s.stats]
    } else {
        parallel::install(|| {
            out.par_chunks_mut(3 * TASK)
                .enumerate()
                .fold(
                    || Scratch::new(&template, 1),
                    |mut s, (i, chunk)| {
                        run(i * TASK, chunk, &mut s);
                        s
                    },
                )
                .map(|s| s.stats)
                .collect::<Vec<_>>()
        })
    };
    for t in &totals {
        stats.add(t);
    }
    COUNTERS.record(&stats);
    Ok((out, stats))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn impossible_allocations_are_errors() {
        let err = zeroed(usize::MAX / 2, "image").unwrap_err();
        assert!(
            err.to_string().starts_with("image: cannot allocate"),
            "{err}"
        );
        assert_eq!(zeroed(5, "image").unwrap(), vec![0.0; 5]);
        assert!(zeroed(0, "image").unwrap().is_empty());
    }
}
