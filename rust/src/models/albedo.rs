//! How a family-A model's directional albedo decomposes, for the integrator.
//!
//! Colours enter every model linearly (and Schlick's F is affine in F0), so the RGB albedo
//! `R(mu) = ∫ f(wi, wo)·mu_o dωo` is a short sum `Σ colour_k · I_k` of *scalar*
//! integrals: a model lists its terms ([`Term`]) and the integrator computes each `I_k`
//! once, not once per channel. An `I_k` is either known exactly (a Lambert lobe
//! integrates to 1, the Summary's bare `kd` to π) or the integral of the same model
//! evaluated with grey "basis" parameters, drawn with the importance sampler the model
//! names. Terms whose colour is zero are never integrated.

use super::lobes::{KD, KS, P};
use super::slots::{ColourSlot, MAX_VARYING_SLOTS};

/// Parameter slots of a basis evaluation (family-A models have at most this many).
pub type Slots = [f64; MAX_VARYING_SLOTS];

/// The sampler matched to a lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Importance {
    /// Cosine-weighted about the normal (diffuse lobes).
    Cosine,
    /// Uniform over the hemisphere (lobes that peak at grazing angles, such as sheen,
    /// whose weight `f·mu_o·2π` stays bounded where cosine sampling's `f·π` does not).
    Uniform,
    /// A one-sample mixture of the two: cosine-weighted with probability `cosine`, else
    /// uniform; the density is the mixture's, `cosine·mu/π + (1 − cosine)/(2π)`, so the
    /// weight never exceeds `1/(1 − cosine)` times the uniform one or `1/cosine` times
    /// the cosine one (lobes that are flat at some incidences and peak at grazing
    /// angles at others, such as Ashikhmin's cloth).
    CosineUniform { cosine: f64 },
    /// The Phong lobe `cos^p α_r` about the mirror direction.
    PhongLobe { p: f64 },
    /// Half vectors from the Blinn NDF `∝ cos^p θh` (pdf_h `= D·cos θh`).
    BlinnHalf { p: f64 },
    /// Half vectors from the GGX distribution of visible normals (Heitz 2018).
    GgxVisible { alpha: f64 },
    /// Half vectors from the isotropic Beckmann distribution of visible normals
    /// (Heitz & d'Eon 2014).
    BeckmannVisible { alpha: f64 },
    /// Half vectors from the (anisotropic) Beckmann / Ward NDF times `cos θh`
    /// (Walter 2005): `tan²θh = −ln u / (cos²φ/αx² + sin²φ/αy²)`.
    BeckmannHalf { alpha_x: f64, alpha_y: f64 },
    /// Half vectors from Ashikhmin & Shirley's anisotropic Phong distribution (2000).
    AnisotropicPhongHalf { nu: f64, nv: f64 },
}

/// One scalar integral of a decomposition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integral {
    /// Known exactly (at the incidence the terms were asked for).
    Exact(f64),
    /// `∫ f(wi, wo; basis)·mu_o dωo` with the model evaluated at the grey `basis`
    /// parameters, sampled with `importance`.
    Lobe {
        basis: Slots,
        importance: Importance,
    },
    /// GGX's specular lobe `D·G2·F/(4·mu_i·mu_o)` (height-correlated Smith `G2`) with
    /// Schlick's `F` for the grey F0 `f0` (1: F = 1; 0: F = `(1 − cos_b)^5`), the lobe
    /// of the `ggx` model at `basis`. Drawn from the visible normals (`Importance::
    /// GgxVisible`), its weight `f·mu_o/pdf = F·G2/G1(wi)` is known in closed form, and
    /// the integrator computes it so; `basis` serves the uniform and cosine samplers.
    GgxVisible { alpha: f64, f0: f64, basis: Slots },
    /// Beckmann's specular lobe, likewise (`integrate/beckmann.rs`): the lobe of the
    /// `beckmann` model at `basis`, drawn from its visible normals (`Importance::
    /// BeckmannVisible`) with the closed-form weight `F·G2/G1(wi)`; `basis` serves the
    /// uniform and cosine samplers.
    BeckmannVisible { alpha: f64, f0: f64, basis: Slots },
    /// One stratum of a power-cosine lobe drawn from its own density (`lobe`: Blinn half
    /// vectors, `Importance::BlinnHalf { p }`, or the Phong lobe about the mirror
    /// direction, `Importance::PhongLobe { p }`): `∫ f(wi, wo; basis)·mu_o dωo` over the
    /// directions whose lobe cosine (`cos θh`, or `cos α` about the mirror direction) is in
    /// `[c_lo, c_hi]`, drawn from the lobe's density restricted to them, with an optional
    /// control variate ([`crate::models::strata`]). The stratum with `whole` (the bulk,
    /// `c_hi = 1`) stands for the whole lobe where strata do not apply (a uniform or
    /// cosine sampler, or the cosine fallback); the others, which follow it in the list of
    /// terms, are then dropped. Sobol points draw the stratum with the exponent `p_sobol`
    /// in place of `p` (a flatter one for a Blinn tail, see `strata`); the weights are
    /// `f·mu_o/pdf` of the density drawn from.
    Stratum {
        lobe: StratumLobe,
        basis: Slots,
        p: f64,
        p_sobol: f64,
        c_lo: f64,
        c_hi: f64,
        whole: bool,
        control: Option<Control>,
        /// The lobe cosine below which `wo` leaves the surface for some azimuths (the
        /// weight is 0 there), where that begins strictly inside the stratum: a Blinn
        /// tail whose first part has every `wo` above the surface (Torrance-Sparrow's,
        /// away from the normal). With few Sobol points per replicate that region of
        /// zeros is rare in its bins, and the error bar counts a pseudo-point at 0 there
        /// (`integrate`'s `skewed_stderr`). `None` where the region is empty or the whole
        /// stratum (the Blinn-Phong and Phong tails begin at the horizon's edge).
        zeros_below: Option<f64>,
    },
}

/// The lobe density an [`Integral::Stratum`] restricts: `v = cos^(p + offset)` of the
/// lobe's angle is uniform under it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StratumLobe {
    /// Blinn half vectors: `pdf_h = (p+2)/(2π)·cos^(p+1) θh`, `v = cos^(p+2) θh`.
    Blinn,
    /// The Phong lobe about the mirror direction: `pdf = (p+1)/(2π)·cos^p α`,
    /// `v = cos^(p+1) α`.
    Phong,
}

impl StratumLobe {
    /// The power of the lobe's cosine that is uniform under its density, less `p`.
    pub fn offset(self) -> f64 {
        match self {
            StratumLobe::Blinn => 2.0,
            StratumLobe::Phong => 1.0,
        }
    }

    /// The importance of the whole lobe of exponent `p`: its own density, but for the
    /// Phong lobe at `p = 0`, where `cos_ar^0 = 1` over the whole hemisphere above the
    /// surface (also beyond 90° from the mirror direction, which the Phong lobe's density
    /// does not reach), the cosine.
    pub fn importance(self, p: f64) -> Importance {
        match self {
            StratumLobe::Blinn => Importance::BlinnHalf { p },
            StratumLobe::Phong if p == 0.0 => Importance::Cosine,
            StratumLobe::Phong => Importance::PhongLobe { p },
        }
    }
}

/// A control variate of a [`Integral::Stratum`]: the integrator subtracts
/// `beta·(C − mean)`, times the stratum's probability under the Blinn sampler, from each
/// point's weight, where `C = r0 + (1 − r0)·(1 − wi·h)^5` (Schlick's `F` for the
/// normal-incidence reflectance `r0`, or its excess alone where `r0` is 0) of the
/// point's half vector `h`, times `(wi·h)/cos θh` if `over_cos` and `mu_o = n·wo` if
/// `mu_o`; `mean` is `E[C]` over the
/// stratum under the lobe's Blinn density (where Sobol points draw the stratum with
/// another exponent, `C` is weighted by the ratio of the densities).
///
/// Where the control makes the weights (nearly) constant, the estimate is as certain as
/// the closed form and the weights' rounding: `rounding` bounds both (per unit `beta`),
/// and the error bar is never below `beta·rounding` (scaled like the weights).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Control {
    pub beta: f64,
    pub mean: f64,
    pub r0: f64,
    pub over_cos: bool,
    pub mu_o: bool,
    pub rounding: f64,
}

/// `colour · integral`, per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Term {
    pub colour: [f64; 3],
    pub integral: Integral,
}

/// Returns a copy of `slots` with the given colours set to grey values:
/// `basis(slots, &[(KD, 0.0), (KS, 1.0)])` is "kd = 0, ks = 1".
pub fn basis(slots: &[f64], colours: &[(ColourSlot, f64)]) -> Slots {
    let mut out = [0.0; MAX_VARYING_SLOTS];
    out[..slots.len()].copy_from_slice(slots);
    for &(colour, value) in colours {
        colour.write(&mut out, [value; 3]);
    }
    out
}

/// Returns `[s·c for c in colour]`.
pub fn scaled(colour: [f64; 3], s: f64) -> [f64; 3] {
    colour.map(|c| c * s)
}

/// The diffuse colour `kd` with a known albedo, and the whole power-cosine lobe (`lobe`,
/// exponent `p`) with the specular colour `ks`, drawn from its own density
/// ([`StratumLobe::importance`]): what a sampler draws. The slots are the power-lobe
/// models' ([`super::lobes`]).
pub fn diffuse_and_whole_power_lobe(
    slots: &[f64],
    diffuse_albedo: f64,
    lobe: StratumLobe,
) -> Vec<Term> {
    let importance = lobe.importance(P.read(slots));
    diffuse_and_lobe(slots, KD, KS, diffuse_albedo, importance)
}

/// The diffuse colour `kd` with a known albedo, and a power-cosine lobe `A·cos^p`
/// (`lobe`: of `θh` for Blinn half vectors, of `α` about the mirror direction for Phong;
/// `A = lobe_scale` for a unit colour) with the specular colour `ks`, in the power-lobe
/// models' slots ([`super::lobes`]).
/// At `p = 0` the lobe is `A` over the whole hemisphere above the surface (`cos^0 = 1`,
/// for Phong also beyond 90° from the mirror direction), whose albedo is `A·π`;
/// elsewhere in strata with its bulk exact where those apply
/// ([`super::strata::blinn_terms`], [`super::strata::phong_terms`]), else drawn whole
/// from its density.
pub fn diffuse_and_power_lobe(
    slots: &[f64],
    diffuse_albedo: f64,
    lobe_scale: f64,
    mu: f64,
    lobe: StratumLobe,
) -> Vec<Term> {
    let p = P.read(slots);
    let mut terms = diffuse_and_whole_power_lobe(slots, diffuse_albedo, lobe);
    if p == 0.0 {
        terms[1].integral = Integral::Exact(lobe_scale * std::f64::consts::PI);
        return terms;
    }
    let (colour, basis) = (KS.read(slots), basis(slots, &[(KD, 0.0), (KS, 1.0)]));
    let strata = match lobe {
        StratumLobe::Blinn => super::strata::blinn_terms(colour, basis, mu, p, lobe_scale),
        StratumLobe::Phong => super::strata::phong_terms(colour, basis, mu, p, lobe_scale),
    };
    if let Some(strata) = strata {
        terms.truncate(1);
        terms.extend(strata);
    }
    terms
}

/// A diffuse term and a specular lobe whose Fresnel term is Schlick's, affine in the
/// colour `f0`: the lobe at grey F0 = 1 with the colour `f0`, and at F0 = 0 (its excess
/// `(1 − cos)^5` alone) with `1 − f0`; `lobe(v)` is the lobe's integral at grey F0 `v`.
pub fn diffuse_and_schlick_lobe(
    diffuse: Term,
    f0: [f64; 3],
    lobe: impl Fn(f64) -> Integral,
) -> Vec<Term> {
    vec![
        diffuse,
        Term {
            colour: f0,
            integral: lobe(1.0),
        },
        Term {
            colour: f0.map(|c| 1.0 - c),
            integral: lobe(0.0),
        },
    ]
}

/// The usual pair: a diffuse colour `kd` with a known albedo, and a specular colour `ks`
/// whose lobe is integrated with `importance`.
pub fn diffuse_and_lobe(
    slots: &[f64],
    kd: ColourSlot,
    ks: ColourSlot,
    diffuse_albedo: f64,
    importance: Importance,
) -> Vec<Term> {
    vec![
        Term {
            colour: kd.read(slots),
            integral: Integral::Exact(diffuse_albedo),
        },
        Term {
            colour: ks.read(slots),
            integral: Integral::Lobe {
                basis: basis(slots, &[(kd, 0.0), (ks, 1.0)]),
                importance,
            },
        },
    ]
}
