//! From radiance to display values: exposure, a tone map, and sRGB encoding.
//!
//! `exposure` is in stops: radiance is multiplied by `2^exposure` first. The tone maps:
//!
//! - `clamp`: `min(max(x, 0), 1)` per channel (the LDR output of the shading assignment);
//! - `reinhard`: `x / (1 + x)` per channel (Reinhard et al. 2002, the simple operator);
//! - `aces`: Narkowicz's 2015 fit of the ACES filmic curve,
//!   `x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)`, clamped to [0, 1] (no hidden
//!   exposure factor: use `exposure`);
//! - `none`: radiance as is (only the exposure applied).
//!
//! NaN becomes 0 in every tone map but `none`.

use rayon::prelude::*;

use crate::error::BrdfError;
use crate::parallel;

/// A tone map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToneMap {
    None,
    Clamp,
    Reinhard,
    Aces,
}

impl ToneMap {
    /// The tone maps' names, in the order messages and docs list them (the first is a
    /// scene's default).
    pub const NAMES: [&'static str; 4] = ["clamp", "reinhard", "aces", "none"];

    /// Parses `"none"`, `"clamp"`, `"reinhard"` or `"aces"`.
    pub fn from_name(name: &str) -> Result<ToneMap, BrdfError> {
        match name {
            "none" => Ok(ToneMap::None),
            "clamp" => Ok(ToneMap::Clamp),
            "reinhard" => Ok(ToneMap::Reinhard),
            "aces" => Ok(ToneMap::Aces),
            _ => Err(BrdfError::InvalidArgument(format!(
                "tonemap: expected \"clamp\", \"reinhard\", \"aces\" or \"none\"; got {name:?}"
            ))),
        }
    }

    /// Returns the display value of one radiance channel (after exposure).
    #[inline(always)]
    pub fn map(self, x: f32) -> f32 {
        // `max(x, 0)` written so that NaN gives 0.
        let pos = if x > 0.0 { x } else { 0.0 };
        match self {
            ToneMap::None => x,
            ToneMap::Clamp => pos.min(1.0),
            ToneMap::Reinhard => {
                if pos < f32::INFINITY {
                    pos / (1.0 + pos)
                } else {
                    1.0
                }
            }
            ToneMap::Aces => {
                let y = (pos * (2.51 * pos + 0.03)) / (pos * (2.43 * pos + 0.59) + 0.14);
                if pos < f32::INFINITY { y.min(1.0) } else { 1.0 }
            }
        }
    }
}

const CHUNK: usize = 1 << 16;

/// Exposures beyond this many stops change no result: `x·2^±400` is beyond `f32`'s range
/// (2^-149 to 2^128) for every nonzero `f32` `x`, as it is at any larger magnitude.
const EXPOSURE_LIMIT: f64 = 400.0;

/// Applies `2^exposure` and the tone map to every value, in place.
///
/// Any finite `exposure` is valid: each value is scaled in `f64` (where `2^exposure`,
/// limited to ±[`EXPOSURE_LIMIT`] stops, is finite and nonzero), then rounded to `f32`.
/// So the result is the rounding of `x·2^exposure`: 0 stays 0 (never `0·inf`), a value too
/// large for `f32` becomes ±inf (1 after a tone map), one too small 0.
pub fn apply(values: &mut [f32], tonemap: ToneMap, exposure: f64) -> Result<(), BrdfError> {
    if !exposure.is_finite() {
        return Err(BrdfError::InvalidArgument(format!(
            "exposure: expected a finite number of stops; got {exposure}"
        )));
    }
    let scale = exposure.clamp(-EXPOSURE_LIMIT, EXPOSURE_LIMIT).exp2();
    let work = |chunk: &mut [f32]| {
        for x in chunk {
            *x = tonemap.map((f64::from(*x) * scale) as f32);
        }
    };
    if values.len() <= CHUNK || parallel::num_threads() == 1 {
        work(values);
    } else {
        parallel::install(|| values.par_chunks_mut(CHUNK).for_each(work));
    }
    Ok(())
}

/// Returns the sRGB encoding (IEC 61966-2-1) of a display value in [0, 1] (clamped).
#[inline]
pub fn srgb_encode(x: f32) -> f32 {
    let x = if x > 0.0 { x.min(1.0) } else { 0.0 };
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Encodes display values (linear, [0, 1]) as 8-bit sRGB, rounding to nearest.
pub fn encode_srgb8(values: &[f32], out: &mut [u8]) {
    let work = |(src, dst): (&[f32], &mut [u8])| {
        for (x, y) in src.iter().zip(dst) {
            *y = (srgb_encode(*x) * 255.0 + 0.5) as u8;
        }
    };
    if values.len() <= CHUNK || parallel::num_threads() == 1 {
        work((values, out));
    } else {
        parallel::install(|| {
            values
                .par_chunks(CHUNK)
                .zip(out.par_chunks_mut(CHUNK))
                .for_each(work)
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_and_no_other() {
        for name in ToneMap::NAMES {
            assert!(ToneMap::from_name(name).is_ok(), "{name}");
        }
        assert!(ToneMap::from_name("Clamp").is_err());
    }

    #[test]
    fn tone_maps_are_monotone_and_bounded() {
        for tm in [ToneMap::Clamp, ToneMap::Reinhard, ToneMap::Aces] {
            let mut last = -1.0;
            for k in 0..2000 {
                let x = k as f32 * 0.01;
                let y = tm.map(x);
                assert!((0.0..=1.0).contains(&y), "{tm:?} {x} {y}");
                assert!(y >= last, "{tm:?} {x}");
                last = y;
            }
            assert_eq!(tm.map(f32::NAN), 0.0);
            assert_eq!(tm.map(f32::INFINITY), 1.0);
            assert_eq!(tm.map(-3.0), 0.0);
        }
        // Any finite exposure: 0 stays 0, overflow saturates, never NaN.
        for exposure in [129.0, 1e300, -1e300, 400.5, -149.5] {
            for tm in [
                ToneMap::None,
                ToneMap::Clamp,
                ToneMap::Reinhard,
                ToneMap::Aces,
            ] {
                let mut v = [0.0, -0.0, 1.0, 1e-45, f32::MAX];
                apply(&mut v, tm, exposure).unwrap();
                assert!(v.iter().all(|x| !x.is_nan()), "{tm:?} {exposure} {v:?}");
                assert_eq!(v[0], 0.0);
            }
        }
        assert_eq!(ToneMap::Reinhard.map(1.0), 0.5);
        assert!((ToneMap::Aces.map(1.0) - 2.54 / 3.16).abs() < 1e-6);
    }

    #[test]
    fn srgb_matches_the_standard() {
        let mut out = [0u8; 5];
        encode_srgb8(&[0.0, 1.0, 0.5, 0.0031308, 0.2159], &mut out);
        // 0.2159 encodes to 0.5014 (128 after rounding).
        assert_eq!(out, [0, 255, 188, 10, 128]);
    }
}
