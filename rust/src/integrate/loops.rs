//! The integrator's loops that do not depend on the model, compiled once per instruction
//! set rather than once per model: the warps' directions and densities for a block of
//! points, GGX's and Beckmann's closed-form lobe weights ([`ClosedFormLobe`]) and those
//! of their rough interfaces' two lobes ([`ClosedFormGlass`]).
//!
//! A cell's model-specific work is then one evaluation loop over the block
//! (`CellIntegrand::weights`). Before this split every model carried its own copy of
//! every warp (8 warps × 2 folds, 8 more for the azimuth average, both closed-form
//! lobes) inlined twice (random and Sobol) for each of the 3 instruction sets: 23 MB of
//! the extension's 30 MB and most of its 12-minute release build.
//!
//! The loops are the same arithmetic for every instruction set (no FMA contraction), so
//! results are bitwise identical whichever one runs.

use glam::DVec3;

use super::POINTS;
use super::sphere::ClosedFormGlass;
use crate::math::series::sin_cos_pi;
use crate::sampling::{Frame, Warp, reflect, reflected_pdf};

/// Sampled directions of one block of points.
pub(super) struct DirectionBlock {
    /// `wo` in the cell's world frame (`n = +z`, tangent `+x`).
    pub wo: [DVec3; POINTS],
    /// The density of `wo` in solid angle (0 where the warp's half vector faces away).
    pub pdf: [f64; POINTS],
    /// The per-point `wi` (the azimuth average only).
    pub wi: [DVec3; POINTS],
}

impl DirectionBlock {
    pub(super) fn new() -> Self {
        DirectionBlock {
            wo: [DVec3::ZERO; POINTS],
            pdf: [0.0; POINTS],
            wi: [DVec3::ZERO; POINTS],
        }
    }
}

/// The model-independent loops compiled for one instruction set.
///
/// # Safety
/// Every method runs instructions of the implementor's instruction set: call them only
/// once the CPU is known to support it (an [`Isa`](crate::simd::Isa) of it was chosen).
pub(super) trait Loops {
    /// Writes `wo` and its density for every point `(u0[j], u1[j])` of `warp` at the
    /// fixed `wi`, into `out.wo[..u0.len()]` and `out.pdf[..]`. `fold`: azimuths on the
    /// half circle. `mirror`: the mirror direction's frame (the Phong lobe's).
    ///
    /// # Safety
    /// See the trait.
    unsafe fn directions(
        warp: Warp,
        fold: bool,
        wi: DVec3,
        mirror: &Frame,
        u0: &[f64],
        u1: &[f64],
        out: &mut DirectionBlock,
    );

    /// As [`Loops::directions`] with `wi` drawn per point at azimuth `φ = (π/2)·u2[j]`
    /// (polar sine `sin`, cosine `mu`), also written to `out.wi`.
    ///
    /// # Safety
    /// See the trait.
    #[allow(clippy::too_many_arguments)]
    unsafe fn directions_averaged(
        warp: Warp,
        sin: f64,
        mu: f64,
        u0: &[f64],
        u1: &[f64],
        u2: &[f64],
        out: &mut DirectionBlock,
    );

    /// The closed-form weights of GGX's or Beckmann's lobe ([`ClosedFormLobe::weights`]).
    ///
    /// # Safety
    /// See the trait.
    unsafe fn closed_form<L: ClosedFormLobe>(
        lobe: &L,
        fold: bool,
        u0: &[f64],
        u1: &[f64],
        w: &mut [f64],
    );

    /// The closed-form weights of a rough interface, reflection and transmission
    /// ([`ClosedFormGlass::fill`]).
    ///
    /// # Safety
    /// See the trait.
    unsafe fn glass<G: ClosedFormGlass>(
        glass: &G,
        u0: &[f64],
        u1: &[f64],
        refl: &mut [f64],
        trans: &mut [f64],
    );
}

/// A lobe drawn from its visible normals whose weights are known in closed form (GGX's,
/// `integrate/ggx.rs`; Beckmann's, `integrate/beckmann.rs`).
pub(super) trait ClosedFormLobe {
    /// `mu_i > 0`: family-A lobes are 0 at grazing incidence.
    fn lit(&self) -> bool;
    /// The grey F0 (1 gives F = 1).
    fn f0(&self) -> f64;
    /// Whether `u0` is first substituted to smooth the rim singularity for QMC (with the
    /// Jacobian in the weight); plain Monte Carlo takes `u0` as the sampler's own number,
    /// because the Jacobian's spread would add variance that only QMC's smoothness repays.
    fn smooth(&self) -> bool;
    /// The weights of one (fold, Fresnel, substitution) case, a loop with a straight-line
    /// body.
    fn fill<const FOLD: bool, const F_ONE: bool, const SMOOTH: bool>(
        &self,
        u0: &[f64],
        u1: &[f64],
        w: &mut [f64],
    );

    /// Writes the weight of every point `(u0[j], u1[j])` into `w`; `fold`: azimuths on
    /// the half `h.y >= 0` (the integrand is even in `h.y`).
    #[inline(always)]
    fn weights(&self, fold: bool, u0: &[f64], u1: &[f64], w: &mut [f64]) {
        if !self.lit() {
            w.fill(0.0);
            return;
        }
        match (fold, self.f0() == 1.0, self.smooth()) {
            (true, true, true) => self.fill::<true, true, true>(u0, u1, w),
            (true, false, true) => self.fill::<true, false, true>(u0, u1, w),
            (false, true, true) => self.fill::<false, true, true>(u0, u1, w),
            (false, false, true) => self.fill::<false, false, true>(u0, u1, w),
            (true, true, false) => self.fill::<true, true, false>(u0, u1, w),
            (true, false, false) => self.fill::<true, false, false>(u0, u1, w),
            (false, true, false) => self.fill::<false, true, false>(u0, u1, w),
            (false, false, false) => self.fill::<false, false, false>(u0, u1, w),
        }
    }
}

/// Calls `$each!(variant, place)` for `warp`: the variant rebuilt from its fields, so
/// that each arm's loop is compiled for one warp, and the frame its samples are local to
/// (`normal`, `mirror` or `half`). The one table of which warp samples in which frame.
macro_rules! per_warp {
    ($warp:expr, $each:ident) => {
        match $warp {
            Warp::UniformHemisphere => $each!(Warp::UniformHemisphere, normal),
            Warp::CosineHemisphere => $each!(Warp::CosineHemisphere, normal),
            Warp::CosineUniform { cosine } => $each!(Warp::CosineUniform { cosine }, normal),
            Warp::PhongLobe { p } => $each!(Warp::PhongLobe { p }, mirror),
            Warp::BlinnHalf { p } => $each!(Warp::BlinnHalf { p }, half),
            Warp::BlinnStratum { p, v_lo, width } => {
                $each!(Warp::BlinnStratum { p, v_lo, width }, half)
            }
            Warp::PhongStratum { p, v_lo, width } => {
                $each!(Warp::PhongStratum { p, v_lo, width }, mirror)
            }
            Warp::GgxVisible { alpha } => $each!(Warp::GgxVisible { alpha }, half),
            Warp::BeckmannHalf { alpha_x, alpha_y } => {
                $each!(Warp::BeckmannHalf { alpha_x, alpha_y }, half)
            }
            Warp::BeckmannVisible { alpha } => $each!(Warp::BeckmannVisible { alpha }, half),
            Warp::AnisotropicPhongHalf { nu, nv } => {
                $each!(Warp::AnisotropicPhongHalf { nu, nv }, half)
            }
        }
    };
}

/// One loop per warp and fold, so each loop body is straight-line code. Local frames:
/// the normal's is the world frame; the Phong lobe's is the mirror direction's; half
/// vectors are reflected about.
#[inline(always)]
fn directions(
    warp: Warp,
    fold: bool,
    wi: DVec3,
    mirror: &Frame,
    u0: &[f64],
    u1: &[f64],
    out: &mut DirectionBlock,
) {
    let n = u0.len();
    let (wo, pdf) = (&mut out.wo[..n], &mut out.pdf[..n]);
    macro_rules! lobe_loop {
        ($warp:expr, $fold:literal, $place:ident) => {{
            let warp = $warp;
            for j in 0..n {
                let u = [u0[j], u1[j]];
                let s = if $fold { warp.sample_folded(wi, u) } else { warp.sample(wi, u) };
                (wo[j], pdf[j]) = lobe_loop!(@$place, s);
            }
        }};
        (@normal, $s:ident) => {
            ($s.dir, $s.pdf)
        };
        (@mirror, $s:ident) => {
            (mirror.to_world($s.dir), $s.pdf)
        };
        (@half, $s:ident) => {{
            let wo = reflect(wi, $s.dir);
            (wo, reflected_pdf($s.pdf, wo.dot($s.dir)))
        }};
    }
    macro_rules! both_folds {
        ($warp:expr, $place:ident) => {
            if fold {
                lobe_loop!($warp, true, $place)
            } else {
                lobe_loop!($warp, false, $place)
            }
        };
    }
    per_warp!(warp, both_folds)
}

/// The directions with `wi` drawn per point, `φ = (π/2)·u2` (the quarter `[0, π/2)`
/// carries the whole average: see the module docs of `integrate`). `wi` and the mirror
/// frame change per point; one loop per warp.
#[inline(always)]
fn directions_averaged(
    warp: Warp,
    sin: f64,
    mu: f64,
    u0: &[f64],
    u1: &[f64],
    u2: &[f64],
    out: &mut DirectionBlock,
) {
    let n = u0.len();
    let (wis, wo, pdf) = (&mut out.wi[..n], &mut out.wo[..n], &mut out.pdf[..n]);
    macro_rules! average_loop {
        ($warp:expr, $place:ident) => {{
            let warp = $warp;
            for j in 0..n {
                let (sin_phi, cos_phi) = sin_cos_pi(0.5 * u2[j]);
                let wi = DVec3::new(sin * cos_phi, sin * sin_phi, mu);
                let s = warp.sample(wi, [u0[j], u1[j]]);
                wis[j] = wi;
                (wo[j], pdf[j]) = average_loop!(@$place, s, wi, sin_phi, cos_phi);
            }
        }};
        (@normal, $s:ident, $wi:ident, $sp:ident, $cp:ident) => {
            ($s.dir, $s.pdf)
        };
        (@mirror, $s:ident, $wi:ident, $sp:ident, $cp:ident) => {{
            let frame = Frame::with_y(DVec3::new(-$wi.x, -$wi.y, mu), DVec3::new(-$sp, $cp, 0.0));
            (frame.to_world($s.dir), $s.pdf)
        }};
        (@half, $s:ident, $wi:ident, $sp:ident, $cp:ident) => {{
            let wo = reflect($wi, $s.dir);
            (wo, reflected_pdf($s.pdf, wo.dot($s.dir)))
        }};
    }
    per_warp!(warp, average_loop)
}

/// One method of [`Loops`]: it calls `$body` through an out-of-line function compiled
/// with the attributes given (the instruction set's `target_feature`, or none).
macro_rules! forward {
    ($(#[$attr:meta])* fn $name:ident $(<$l:ident: $bound:path>)?($($arg:ident: $ty:ty),*) $body:block) => {
        unsafe fn $name$(<$l: $bound>)?($($arg: $ty),*) {
            $(#[$attr])*
            #[inline(never)]
            unsafe fn run$(<$l: $bound>)?($($arg: $ty),*) $body
            // SAFETY: `run` enables the instruction set this `Loops` implementor stands
            // for (its `target_feature` list, none for the baseline); the trait's
            // contract, which this method's callers accept, is that the CPU runs it.
            unsafe { run($($arg),*) }
        }
    };
}

/// Implements [`Loops`] for the marker `$isa`, each method out of line with `$attr`.
macro_rules! isa_loops {
    ($(#[$doc:meta])* $isa:ident $(, #[$attr:meta])?) => {
        $(#[$doc])*
        pub(super) struct $isa;

        impl Loops for $isa {
            forward!($(#[$attr])? fn directions(
                warp: Warp,
                fold: bool,
                wi: DVec3,
                mirror: &Frame,
                u0: &[f64],
                u1: &[f64],
                out: &mut DirectionBlock
            ) {
                directions(warp, fold, wi, mirror, u0, u1, out)
            });

            forward!($(#[$attr])? fn directions_averaged(
                warp: Warp,
                sin: f64,
                mu: f64,
                u0: &[f64],
                u1: &[f64],
                u2: &[f64],
                out: &mut DirectionBlock
            ) {
                directions_averaged(warp, sin, mu, u0, u1, u2, out)
            });

            forward!($(#[$attr])? fn closed_form<L: ClosedFormLobe>(
                lobe: &L,
                fold: bool,
                u0: &[f64],
                u1: &[f64],
                w: &mut [f64]
            ) {
                lobe.weights(fold, u0, u1, w)
            });

            forward!($(#[$attr])? fn glass<G: ClosedFormGlass>(
                glass: &G,
                u0: &[f64],
                u1: &[f64],
                refl: &mut [f64],
                trans: &mut [f64]
            ) {
                glass.fill(u0, u1, refl, trans)
            });
        }
    };
}

isa_loops!(
    /// The target's baseline (SSE2 on x86-64).
    Baseline
);
#[cfg(target_arch = "x86_64")]
isa_loops!(
    /// x86-64-v3: AVX2 + FMA.
    Avx2,
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
);
#[cfg(target_arch = "x86_64")]
isa_loops!(
    /// x86-64-v4: AVX-512 (F, DQ, VL, BW) + FMA.
    Avx512,
    #[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
);
