//! The instruction set the hot loops run with, chosen once at run time.
//!
//! The batch engine ([`crate::eval`]), the integrator ([`crate::integrate`]) and the
//! renderer ([`crate::scene`]) compile their loops once per instruction set, each copy in
//! a function marked `#[target_feature(enable = ...)]`, and call the copy [`isa`] picks.
//! Calling such a function on a CPU without those features is undefined behaviour, so an
//! [`Isa`] above the baseline can only be made here: its variant carries a [`Checked`]
//! token, whose field is private, and this module makes one only after the CPU reported
//! every feature of that variant's list ([`AVX2_FEATURES`], [`AVX512_FEATURES`]). Holding
//! `Isa::Avx2(_)` or `Isa::Avx512(_)` is thus the proof the `unsafe` call at a dispatch
//! site needs.
//!
//! Every `#[target_feature(enable = ...)]` in the crate names exactly one of these two
//! lists (an attribute cannot name a constant; a test checks the sources).

use std::sync::OnceLock;

/// The features of the AVX2 loops (x86-64-v3): what [`Isa::Avx2`] guarantees.
pub const AVX2_FEATURES: &str = "avx2,fma,bmi1,bmi2,lzcnt,popcnt";
/// The features of the AVX-512 loops (x86-64-v4): what [`Isa::Avx512`] guarantees.
pub const AVX512_FEATURES: &str =
    "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt";

/// Proof that this CPU has the features of the [`Isa`] variant that carries it. Only
/// this module makes one (the field is private), after checking them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Checked(());

/// The instruction sets the hot loops are compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Isa {
    /// Whatever the target's baseline is (SSE2 on x86-64).
    Baseline,
    /// x86-64-v3: AVX2 + FMA ([`AVX2_FEATURES`]).
    Avx2(Checked),
    /// x86-64-v4: AVX-512 (F, DQ, VL, BW) + FMA ([`AVX512_FEATURES`]).
    Avx512(Checked),
}

impl Isa {
    /// Returns the name used by `BRDF_RS_ISA` and the benchmarks.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Baseline => "baseline",
            Isa::Avx2(_) => "avx2",
            Isa::Avx512(_) => "avx512",
        }
    }
}

/// Returns the best instruction set this CPU supports.
pub fn detected() -> Isa {
    #[cfg(target_arch = "x86_64")]
    {
        // Each check lists the features of its constant, one by one.
        let avx2 = is_x86_feature_detected!("avx2")
            && is_x86_feature_detected!("fma")
            && is_x86_feature_detected!("bmi1")
            && is_x86_feature_detected!("bmi2")
            && is_x86_feature_detected!("lzcnt")
            && is_x86_feature_detected!("popcnt");
        let avx512 = avx2
            && is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512dq")
            && is_x86_feature_detected!("avx512vl")
            && is_x86_feature_detected!("avx512bw");
        if avx512 {
            return Isa::Avx512(Checked(()));
        }
        if avx2 {
            return Isa::Avx2(Checked(()));
        }
    }
    Isa::Baseline
}

/// Returns the instruction set in use: the detected one, lowered by the environment
/// variable `BRDF_RS_ISA` (`baseline`, `avx2`, `avx512`) if set; never raised above
/// what the CPU supports.
pub fn isa() -> Isa {
    static ISA: OnceLock<Isa> = OnceLock::new();
    *ISA.get_or_init(|| {
        let best = detected();
        let wanted = match std::env::var("BRDF_RS_ISA").as_deref() {
            Ok("baseline") => 0,
            Ok("avx2") => 1,
            _ => 2,
        };
        lowered(best, wanted)
    })
}

/// `best`, or the instruction set of rank `wanted` below it (whose features are a subset
/// of `best`'s, so `best`'s check covers it).
fn lowered(best: Isa, wanted: u8) -> Isa {
    match (best, wanted) {
        (_, 0) | (Isa::Baseline, _) => Isa::Baseline,
        (Isa::Avx512(checked), 1) => Isa::Avx2(checked),
        _ => best,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rank(isa: Isa) -> u8 {
        match isa {
            Isa::Baseline => 0,
            Isa::Avx2(_) => 1,
            Isa::Avx512(_) => 2,
        }
    }

    #[test]
    fn lowering_never_raises() {
        let all = [
            Isa::Baseline,
            Isa::Avx2(Checked(())),
            Isa::Avx512(Checked(())),
        ];
        for best in all {
            for wanted in 0..=2 {
                let got = lowered(best, wanted);
                assert_eq!(rank(got), rank(best).min(wanted));
            }
        }
        assert!(rank(isa()) <= rank(detected()));
    }

    /// Every `target_feature` list in the crate is one of the two [`detected`] checks.
    #[test]
    fn target_features_are_the_checked_lists() {
        let sources = [
            include_str!("eval/engine.rs"),
            include_str!("integrate/cell.rs"),
            include_str!("integrate/loops.rs"),
            include_str!("scene/render.rs"),
            include_str!("scene/shading.rs"),
        ];
        let marker = concat!("#[target_feature(enable = ", "\"");
        let mut seen = 0;
        for src in sources {
            for (at, _) in src.match_indices(marker) {
                let rest = &src[at + marker.len()..];
                let list = &rest[..rest.find('"').unwrap()];
                assert!(list == AVX2_FEATURES || list == AVX512_FEATURES, "{list}");
                seen += 1;
            }
        }
        assert!(seen >= 10, "{seen}");
    }
}
