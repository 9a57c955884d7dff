//! Where a model's parameters sit in its raw parameter vector, written once per model.
//!
//! A model file declares its layout with [`param_slots!`](crate::param_slots): one typed
//! constant per parameter, in spec order, each starting where the previous one ends. Its
//! [`ModelSpec`](super::ModelSpec) entries take their `slot` from these constants and its
//! kernel reads its values through them (`KD.read(p)`, `ALPHA.read(slots)`), so no slot
//! number is written by hand. The constant's type says how many slots the parameter takes
//! and what a read returns; the tests check each layout against its spec.

use super::ParamSource;
use crate::math::Real;

/// Most parameter slots a per-element (varying) parameter set may use: the batch engine's
/// scratch holds this many, and a family-A model's albedo basis has at most this many.
pub const MAX_VARYING_SLOTS: usize = 12;

/// A scalar parameter's slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScalarSlot(usize);

/// A colour parameter's three consecutive slots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColourSlot(usize);

/// A list of `N` scalars (a toon ramp's thresholds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScalarListSlot<const N: usize>(usize);

/// A list of `N` colours (a toon ramp's band colours).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColourListSlot<const N: usize>(usize);

macro_rules! slot_type {
    ($ty:ident $(<$n:ident>)?, $width:expr) => {
        impl<$(const $n: usize)?> $ty$(<$n>)? {
            /// How many float slots the parameter takes.
            pub const WIDTH: usize = $width;

            /// The parameter starting at slot `first` (layouts come from
            /// [`param_slots!`](crate::param_slots)).
            pub const fn new(first: usize) -> Self {
                Self(first)
            }

            /// Returns the parameter's first slot.
            pub const fn first(self) -> usize {
                self.0
            }

            /// Returns the slot after the parameter's last one.
            pub const fn end(self) -> usize {
                self.0 + Self::WIDTH
            }
        }
    };
}

slot_type!(ScalarSlot, 1);
slot_type!(ColourSlot, 3);
slot_type!(ScalarListSlot<N>, N);
slot_type!(ColourListSlot<N>, 3 * N);

impl ScalarSlot {
    /// Returns the parameter's value in `p`.
    #[inline(always)]
    pub fn read<F: Real, P: ParamSource<F> + ?Sized>(self, p: &P) -> F {
        p.scalar(self.0)
    }
}

impl ColourSlot {
    /// Returns the parameter's colour in `p`.
    #[inline(always)]
    pub fn read<F: Real, P: ParamSource<F> + ?Sized>(self, p: &P) -> [F; 3] {
        p.colour(self.0)
    }
}

impl ScalarSlot {
    /// Writes the parameter's value into a raw parameter vector.
    pub fn write(self, slots: &mut [f64], x: f64) {
        slots[self.0] = x;
    }
}

impl ColourSlot {
    /// Writes the parameter's colour into a raw parameter vector.
    pub fn write(self, slots: &mut [f64], c: [f64; 3]) {
        slots[self.0..self.end()].copy_from_slice(&c);
    }
}

impl<const N: usize> ScalarListSlot<N> {
    /// Returns the list's values in `p` (unused entries are `+inf`).
    #[inline(always)]
    pub fn read<F: Real, P: ParamSource<F> + ?Sized>(self, p: &P) -> [F; N] {
        std::array::from_fn(|k| p.scalar(self.0 + k))
    }
}

impl<const N: usize> ColourListSlot<N> {
    /// Returns the list's colours in `p`.
    #[inline(always)]
    pub fn read<F: Real, P: ParamSource<F> + ?Sized>(self, p: &P) -> [[F; 3]; N] {
        std::array::from_fn(|k| p.colour(self.0 + 3 * k))
    }
}

/// One entry of a layout as [`param_slots!`](crate::param_slots) declared it: the
/// constant's name, its first slot and its width, for checking a layout against its spec.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SlotDecl {
    pub name: &'static str,
    pub first: usize,
    pub width: usize,
}

/// Declares a model's parameter layout in spec order: `NAME: Type` makes `pub const NAME`
/// of that slot type, starting where the previous parameter ends (the first at slot 0),
/// and `pub const SLOTS` lists them all for the tests. A constant is named after its
/// parameter (`KD` for `kd`, `RD` for `Rd`).
#[macro_export]
macro_rules! param_slots {
    ($($name:ident: $ty:ty),+ $(,)?) => {
        $crate::param_slots!(@at 0; $($name: $ty,)+);
        /// The layout as declared, for checking it against the spec.
        pub const SLOTS: &[$crate::models::slots::SlotDecl] = &[$(
            $crate::models::slots::SlotDecl {
                name: stringify!($name),
                first: $name.first(),
                width: <$ty>::WIDTH,
            }
        ),+];
    };
    (@at $at:expr;) => {};
    (@at $at:expr; $name:ident: $ty:ty, $($rest:tt)*) => {
        #[doc = concat!("The `", stringify!($name), "` parameter's slots.")]
        pub const $name: $ty = <$ty>::new($at);
        $crate::param_slots!(@at $name.end(); $($rest)*);
    };
}
