//! The albedo of a transmitting model (the rough dielectrics) over the whole sphere:
//! `A(mu) = ∫_{S²} f(wi, wo)·|n·wo| dωo`, as its reflected part (`wo` above), its
//! transmitted part (`wo` below) or both ([`Component`]).
//!
//! Each point `u` draws one half vector `h` from the distribution's visible normals seen
//! from `wi` ([`DielectricSampler::warp`]), and both of its directions are scored (a split
//! estimator, with no random choice between them): the reflection `wo_r` of `wi` about
//! `h`, with weight `f(wi, wo_r)·|n·wo_r| / (D_wi(h)/(4|wo_r·h|))` where `wo_r` is above,
//! and the refraction `wo_t` through `h`, with weight
//! `f(wi, wo_t)·|n·wo_t| / (D_wi(h)·eta²|wo_t·h|/((wi·h) + eta(wo_t·h))²)` where `wo_t`
//! is below. These are `ks·F·G2/G1(wi)` and `kt·(1 − F)·G2/G1(wi)`, each at most its
//! colour, so the estimator is bounded. `f` is the model's own kernel, at grey unit
//! colours (the colours multiply the two parts).
//!
//! The error bar is the one of the hemisphere integrator: the per-point spread for random
//! points, the spread of the replicates' means for Sobol points, in rounds that double
//! until `tol` is met. At `eta = 1` the albedo is exact: the reflection is 0 and the
//! transmission `kt` (the straight-through delta).

use std::sync::atomic::Ordering;

use glam::DVec3;

use super::options::{AlbedoOptions, CellResult, Component, Progress};
use super::sums::mean_and_stderr;
use crate::models::{Directions, Kernel};
use crate::sampling::dielectric::DielectricSampler;
use crate::sampling::reflect;
use crate::sampling::streams::{Sequence, Stream};

/// The grey weights `(reflection, transmission)` of one point `u` at `wi` (`n = +z`).
fn weights<K: Kernel>(
    sampler: &DielectricSampler,
    prepared: &K::Prepared<f64>,
    wi: DVec3,
    u: [f64; 2],
) -> (f64, f64) {
    let s = sampler.warp.sample(wi, u);
    let pdf_h = s.pdf;
    if !(pdf_h > 0.0) {
        return (0.0, 0.0);
    }
    let h = s.dir.normalize();
    let c = wi.dot(h);
    if !(c > 0.0) {
        return (0.0, 0.0);
    }
    let eval = |wo: DVec3| {
        K::eval::<f64>(
            prepared,
            &Directions {
                wi,
                wo,
                n: DVec3::Z,
                t: DVec3::X,
            },
        )[0]
    };
    let wo_r = reflect(wi, h).normalize();
    let r = if wo_r.z > 0.0 {
        let pdf = pdf_h / (4.0 * wo_r.dot(h).abs());
        eval(wo_r) * wo_r.z / pdf
    } else {
        0.0
    };
    let eta = sampler.eta;
    let sin2_t = (1.0 - c * c).max(0.0) / (eta * eta);
    let t = if sin2_t < 1.0 {
        let cos_t = (1.0 - sin2_t).sqrt();
        let wo_t = (-wi / eta + h * (c / eta - cos_t)).normalize();
        if wo_t.z < 0.0 {
            let co = wo_t.dot(h);
            let denom = c + eta * co;
            let pdf = pdf_h * eta * eta * co.abs() / (denom * denom);
            eval(wo_t) * -wo_t.z / pdf
        } else {
            0.0
        }
    } else {
        0.0
    };
    let ok = |x: f64| if x.is_finite() { x } else { 0.0 };
    (ok(r), ok(t))
}

/// Integrates one cell of a transmitting model at incidence `mu` (the model's sampler
/// `sampler`, its raw parameter `slots`, whose colours `ks` and `kt` weigh the two parts).
pub(super) fn integrate_cell<K: Kernel>(
    sampler: DielectricSampler,
    mu: f64,
    slots: &[f64],
    cell: u64,
    options: &AlbedoOptions,
    progress: &Progress,
) -> CellResult {
    let spec = K::spec();
    let colour = |name: &str| -> [f64; 3] {
        spec.param(name).map_or([0.0; 3], |p| {
            [slots[p.slot], slots[p.slot + 1], slots[p.slot + 2]]
        })
    };
    let (reflection, transmission) = match options.component {
        Component::Total => (true, true),
        Component::Reflection => (true, false),
        Component::Transmission => (false, true),
    };
    let ks = if reflection { colour("ks") } else { [0.0; 3] };
    let kt = if transmission { colour("kt") } else { [0.0; 3] };
    if sampler.eta == 1.0 || !(mu > 0.0) || ks.iter().chain(&kt).all(|&c| c == 0.0) {
        // No interface: the delta straight through (exact); grazing incidence: 0.
        let value = if sampler.eta == 1.0 && mu > 0.0 {
            kt
        } else {
            [0.0; 3]
        };
        return CellResult {
            value,
            stderr: [0.0; 3],
            samples: 0,
        };
    }
    // Grey unit colours: the kernel's value is one part, the colours weigh them.
    let mut grey = slots.to_vec();
    for name in ["ks", "kt"] {
        if let Some(p) = spec.param(name) {
            grey[p.slot..p.slot + 3].fill(1.0);
        }
    }
    let prepared = K::prepare::<f64, [f64]>(&grey);
    let mu = mu.min(1.0);
    let wi = DVec3::new(((1.0 - mu) * (1.0 + mu)).sqrt(), 0.0, mu);
    let point = |u: [f64; 2]| -> [f64; 3] {
        let (r, t) = weights::<K>(&sampler, &prepared, wi, u);
        std::array::from_fn(|c| {
            let a = if ks[c] == 0.0 { 0.0 } else { ks[c] * r };
            let b = if kt[c] == 0.0 { 0.0 } else { kt[c] * t };
            a + b
        })
    };
    let random = options.sequence == Sequence::Random;
    let streams_count = if random {
        1
    } else {
        u64::from(options.replicates)
    };
    let cap = if options.tol.is_some() {
        options.max_samples
    } else {
        u64::MAX
    };
    let first = options.samples.min(cap);
    let mut per_stream = if random {
        first.max(2)
    } else {
        first.div_ceil(streams_count).next_power_of_two()
    };
    let mut streams: Vec<Stream> = (0..streams_count)
        .map(|r| Stream::new(options.sequence, options.seed, cell, r))
        .collect();
    // Per stream: the sums of the values and (random) of their squares.
    let mut sums = vec![([0.0; 3], [0.0; 3]); streams.len()];
    let mut done = 0u64;
    loop {
        let count = per_stream - done;
        for (stream, (sum, squares)) in streams.iter_mut().zip(sums.iter_mut()) {
            for _ in 0..count {
                let x = point(stream.next_point());
                for c in 0..3 {
                    sum[c] += x[c];
                    squares[c] += x[c] * x[c];
                }
            }
        }
        progress
            .samples_done
            .fetch_add(count * streams_count, Ordering::Relaxed);
        done = per_stream;
        let total = per_stream * streams_count;
        let n = per_stream as f64;
        let (mean, se) = if random {
            let (sum, squares) = sums[0];
            let mean: [f64; 3] = std::array::from_fn(|c| sum[c] / n);
            let se = std::array::from_fn(|c| {
                let var = ((squares[c] - sum[c] * mean[c]) / (n - 1.0)).max(0.0);
                (var / n).sqrt()
            });
            (mean, se)
        } else {
            let means: Vec<[f64; 3]> = sums
                .iter()
                .map(|(s, _)| std::array::from_fn(|c| s[c] / n))
                .collect();
            mean_and_stderr(&means)
        };
        let finished = match options.tol {
            None => true,
            Some(tol) => {
                let capped = if random {
                    total >= options.max_samples
                } else {
                    total * 2 > options.max_samples
                };
                se.iter().all(|&s| s <= tol) || capped
            }
        };
        if finished || progress.cancel.load(Ordering::Relaxed) {
            let stderr = std::array::from_fn(|c| se[c].max(mean[c].abs() * f64::EPSILON));
            return CellResult {
                value: mean,
                stderr,
                samples: total,
            };
        }
        per_stream = if random {
            (per_stream * 2).min(options.max_samples)
        } else {
            per_stream * 2
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::ggx_dielectric::GgxDielectric;

    fn slots(eta: f64, alpha: f64) -> Vec<f64> {
        use crate::models::dielectric::{ALPHA, ETA, KS, KT};
        let mut s = vec![0.0; 8];
        KS.write(&mut s, [1.0; 3]);
        KT.write(&mut s, [1.0; 3]);
        ETA.write(&mut s, eta);
        ALPHA.write(&mut s, alpha);
        s
    }

    fn albedo(eta: f64, alpha: f64, mu: f64, component: Component) -> CellResult {
        let s = slots(eta, alpha);
        let sampler = GgxDielectric::transmission_sampler(&s).unwrap();
        let options = AlbedoOptions {
            samples: 1 << 14,
            component,
            ..AlbedoOptions::default()
        };
        integrate_cell::<GgxDielectric>(sampler, mu, &s, 7, &options, &Progress::default())
    }

    /// Near-smooth interfaces: R → F(mu), T → 1 − F(mu).
    #[test]
    fn small_roughness_gives_the_smooth_interface() {
        let mu: f64 = 0.7;
        let eta: f64 = 1.5;
        let g = (eta * eta - 1.0 + mu * mu).sqrt();
        let a = (g - mu) / (g + mu);
        let b = (mu * (g + mu) - 1.0) / (mu * (g - mu) + 1.0);
        let fresnel = 0.5 * a * a * (1.0 + b * b);
        let r = albedo(eta, 1e-3, mu, Component::Reflection);
        let t = albedo(eta, 1e-3, mu, Component::Transmission);
        let total = albedo(eta, 1e-3, mu, Component::Total);
        assert!((r.value[0] - fresnel).abs() < 1e-3, "{r:?} vs {fresnel}");
        assert!((t.value[0] - (1.0 - fresnel)).abs() < 1e-3, "{t:?}");
        assert!((total.value[0] - 1.0).abs() < 1e-3, "{total:?}");
        assert!((total.value[0] - r.value[0] - t.value[0]).abs() < 1e-12);
    }

    #[test]
    fn eta_one_is_exact() {
        let t = albedo(1.0, 0.5, 0.4, Component::Transmission);
        assert_eq!((t.value, t.stderr, t.samples), ([1.0; 3], [0.0; 3], 0));
        let r = albedo(1.0, 0.5, 0.4, Component::Reflection);
        assert_eq!(r.value, [0.0; 3]);
    }
}
