//! Sampling a whole family-A model: a mixture of its lobes' importance samplers.
//!
//! The lobes come from the model's albedo decomposition ([`crate::models::albedo`]):
//! diffuse terms are drawn cosine-weighted, Phong lobes about the mirror direction,
//! Blinn / Torrance-Sparrow lobes through half vectors. A lobe is picked with probability
//! proportional to its weight (its largest colour channel times its albedo where that is
//! known exactly, else 1), and the density of the sample is the mixture's,
//! `pdf = Σ_k p_k · pdf_k(wo)` (the one-sample balance heuristic), so `f·cos/pdf` stays
//! bounded wherever any lobe covers the integrand.

use glam::DVec3;

use super::{Frame, SamplerChoice, Warp, one_minus_dot, reflect, reflected_pdf};
use crate::models::albedo::{Importance, Integral, Term};

/// Returns the warp that draws a lobe with importance `importance`.
pub fn warp_of(importance: Importance) -> Warp {
    match importance {
        Importance::Cosine => Warp::CosineHemisphere,
        Importance::Uniform => Warp::UniformHemisphere,
        Importance::CosineUniform { cosine } => Warp::CosineUniform { cosine },
        Importance::PhongLobe { p } => Warp::PhongLobe { p },
        Importance::BlinnHalf { p } => Warp::BlinnHalf { p },
        Importance::GgxVisible { alpha } => Warp::GgxVisible { alpha },
        Importance::BeckmannHalf { alpha_x, alpha_y } => Warp::BeckmannHalf { alpha_x, alpha_y },
        Importance::BeckmannVisible { alpha } => Warp::BeckmannVisible { alpha },
        Importance::AnisotropicPhongHalf { nu, nv } => Warp::AnisotropicPhongHalf { nu, nv },
    }
}

/// One mixture component: a warp and its selection probability.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Component {
    pub warp: Warp,
    pub probability: f64,
}

/// The mixture of a parameter set's lobes (or a single uniform / cosine warp).
#[derive(Clone, Debug, PartialEq)]
pub struct Mixture {
    pub components: Vec<Component>,
}

impl Mixture {
    /// Builds the sampler for a model's terms.
    pub fn new(terms: &[Term], sampler: SamplerChoice) -> Mixture {
        let single = |warp| Mixture {
            components: vec![Component {
                warp,
                probability: 1.0,
            }],
        };
        match sampler {
            SamplerChoice::Uniform => return single(Warp::UniformHemisphere),
            SamplerChoice::Cosine => return single(Warp::CosineHemisphere),
            SamplerChoice::Auto | SamplerChoice::Importance => {}
        }
        let mut comps: Vec<Component> = Vec::new();
        for term in terms {
            let strength = term.colour.iter().fold(0.0_f64, |a, &c| a.max(c.abs()));
            let (warp, weight) = match term.integral {
                Integral::Exact(v) => (Warp::CosineHemisphere, strength * v),
                Integral::Lobe { importance, .. } => (warp_of(importance), strength),
                Integral::GgxVisible { alpha, .. } => (Warp::GgxVisible { alpha }, strength),
                Integral::BeckmannVisible { alpha, .. } => {
                    (Warp::BeckmannVisible { alpha }, strength)
                }
                // A sampler draws whole lobes: the whole lobe for the stratum that stands
                // for it, nothing for the others.
                Integral::Stratum {
                    lobe,
                    p,
                    whole: true,
                    ..
                } => (warp_of(lobe.importance(p)), strength),
                Integral::Stratum { whole: false, .. } => continue,
            };
            if !(weight > 0.0) {
                continue;
            }
            match comps.iter_mut().find(|c| c.warp == warp) {
                Some(c) => c.probability += weight,
                None => comps.push(Component {
                    warp,
                    probability: weight,
                }),
            }
        }
        let total: f64 = comps.iter().map(|c| c.probability).sum();
        if !(total > 0.0) {
            // A black material: any valid sampler will do.
            return single(Warp::CosineHemisphere);
        }
        for c in &mut comps {
            c.probability /= total;
        }
        Mixture { components: comps }
    }

    /// Draws `wo` for `wi` (unit, any side) in the shading frame `frame` (z = the normal,
    /// x = the tangent) from `u` in `[0, 1)²`. Returns `(wo, pdf)`; `pdf` is the
    /// mixture's density of `wo` (0 when the draw is invalid, e.g. below the surface).
    pub fn sample(&self, wi: DVec3, frame: &Frame, u: [f64; 2]) -> (DVec3, f64) {
        let n = frame.z;
        // Pick a component with u0, then stretch u0 back onto [0, 1).
        let mut u0 = u[0];
        let mut chosen = self.components.len() - 1;
        for (k, c) in self.components.iter().enumerate() {
            if u0 < c.probability || k + 1 == self.components.len() {
                chosen = k;
                u0 = (u0 / c.probability).min(crate::sampling::ONE_BELOW);
                break;
            }
            u0 -= c.probability;
        }
        let warp = self.components[chosen].warp;
        let wi_local = frame.to_local(wi);
        let s = warp.sample(wi_local, [u0, u[1]]);
        let wo = if warp.half_vector() {
            reflect(wi, frame.to_world(s.dir))
        } else if let Warp::PhongLobe { .. } = warp {
            let mu_i = wi.dot(n);
            Frame::around((n * (2.0 * mu_i) - wi).normalize()).to_world(s.dir)
        } else {
            frame.to_world(s.dir)
        };
        let wo = wo.normalize();
        (wo, self.pdf(wi, wo, frame))
    }

    /// Returns the mixture's density of `wo` given `wi` in the shading frame `frame`.
    pub fn pdf(&self, wi: DVec3, wo: DVec3, frame: &Frame) -> f64 {
        let n = frame.z;
        let mu_o = wo.dot(n);
        if !(mu_o > 0.0) || !(wi.dot(n) > 0.0) {
            return 0.0;
        }
        let mut total = 0.0;
        for c in &self.components {
            let density = if c.warp.half_vector() {
                let s = wi + wo;
                if s.length_squared() == 0.0 {
                    0.0
                } else {
                    let h = s.normalize();
                    let d = frame.to_local(h);
                    let pdf_h = c
                        .warp
                        .pdf_local(frame.to_local(wi), d, d.z, one_minus_dot(h, n));
                    reflected_pdf(pdf_h, wo.dot(h))
                }
            } else if let Warp::PhongLobe { .. } = c.warp {
                let r = (n * (2.0 * wi.dot(n)) - wi).normalize();
                c.warp.pdf(r.dot(wo), one_minus_dot(r, wo))
            } else {
                c.warp.pdf(mu_o, one_minus_dot(n, wo))
            };
            total += c.probability * density;
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mixture_probabilities_follow_lobe_strength() {
        use crate::models::torrance_sparrow::{ETA, KD, KS, P};
        let mut slots = [0.0; 8];
        KD.write(&mut slots, [0.2; 3]);
        KS.write(&mut slots, [0.6, 0.0, 0.0]);
        P.write(&mut slots, 10.0);
        ETA.write(&mut slots, 1.5);
        let terms = crate::models::albedo::diffuse_and_lobe(
            &slots,
            KD,
            KS,
            1.0,
            Importance::BlinnHalf { p: 10.0 },
        );
        let m = Mixture::new(&terms, SamplerChoice::Auto);
        assert_eq!(m.components.len(), 2);
        assert!((m.components[0].probability - 0.25).abs() < 1e-15);
        assert!((m.components[1].probability - 0.75).abs() < 1e-15);
    }
}
