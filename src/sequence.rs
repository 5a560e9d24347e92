//! Random-access sample sequences: point `k` of a pattern without generating
//! the others.
//!
//! A renderer asks for samples by index: "sample `s` of pixel `(x, y)`,
//! dimension `d`". [`Sequence<D>`] answers that for every pattern whose
//! generator is random access: [`Sequence::point`] returns point `index` and
//! [`Sequence::sample`] one coordinate of it, bit for bit the value that
//! [`Pattern::fill`](crate::pattern::Pattern::fill) /
//! [`Pattern::fill_range`](crate::pattern::Pattern::fill_range) writes for the
//! same pattern and seed, with no allocation. [`pixel_seed`] derives
//! independent seeds for neighbouring pixels and for the dimensions of one
//! pixel.
//!
//! # Implementations and cost per point
//!
//! Every implementation evaluates only the point asked for, with the scalar
//! generator of the pattern started at `index` (or, for [`Pmj02Pixel`], from
//! tables generated beforehand):
//!
//! | pattern | [`count`](Sequence::count) | [`dimensions`](Sequence::dimensions) | cost of one point |
//! |---|---|---|---|
//! | [`Sobol<D>`] | `2³²` (the whole sequence) | 1024 ([`SOBOL_DIMENSIONS`]) | `O(1)`: two hash scrambles and a 32-bit matrix product per coordinate |
//! | [`Halton<D>`] | `2³²` (the whole sequence) | 1024 ([`HALTON_DIMENSIONS`]) | `O(K_b)` per coordinate, `K_b ≤ 32` base-`b` digits (`K_b ≤ 3` from dimension 16 on) |
//! | [`Random<D>`] | `N` | `D` | `O(1)`: outputs `k·D + j` of the counter-based stream ([`crate::rng::Counter`]) |
//! | [`Jittered<D>`] | `N` | `D` | `O(1)`: counter outputs plus the cell of `k` (`D` divisions) |
//! | [`NRooks<D>`] | `N` | `D` | counter outputs plus one hash permutation per axis (`O(1)` expected, [`crate::hash::permute`]) |
//! | [`MultiJittered`] | `N` | 2 | counter outputs plus two hash permutations |
//! | [`CorrelatedMultiJittered`] | `N` | 2 | as [`MultiJittered`] (Kensler 2013 designed CMJ for random access) |
//! | [`Shifted<P>`] | as `P` | as `P` | as `P`, plus the shift |
//! | [`Pmj02Pixel`] (a pixel of [`Pmj02Tables`]) | `N` (a power of two) | `2³² − 2` (PMJ02), `2·sets` (PMJ02BN) | `O(1)`: hashes, a batch permutation (pairs ≥ 1), a scramble (PMJ02) or an isometry (PMJ02BN) and one load from the precomputed tables |
//!
//! None of them generates the points before `index`. [`Sobol`] and [`Halton`]
//! points do not depend on the pattern size `N` (a pattern is a prefix of the
//! sequence), so their sequence view is the whole `2³²`-point sequence whatever
//! `N` the pattern was built with; for the other patterns point `k` depends on
//! `N` (the strata, the permutations) and only `k < N` exists.
//!
//! Not random access, and so not a [`Sequence`]: [`PoissonDisk`] and
//! `PoissonDiskN` (dart throwing: point `k` depends on every earlier dart) and
//! `Ccvt` (a global optimisation of all points). Fill those once per pixel and
//! index the filled array instead.
//!
//! # Per-pixel seeds
//!
//! Giving every pixel its own scramble ([`pixel_seed`], a hash of the pixel
//! into the seed) decorrelates the error of neighbouring pixels; a
//! distinct `dim` per 2D sample dimension (lens, light, BSDF, …) makes the
//! dimensions of one pixel independent ("padding" of 2D patterns, Kollig &
//! Keller 2002). For a single high-dimensional point per pixel instead, use one
//! pixel seed and [`Sequence::sample`] with `dim` up to 1023 on [`Sobol`] or
//! [`Halton`].
//!
//! # Example: a renderer's sampler
//!
//! ```
//! use linesample::pattern::{Jittered, Pattern, Sobol};
//! use linesample::sequence::{pixel_seed, Sequence};
//! use linesample::{PatternError, Seed};
//!
//! /// Per-pixel sampler over any 2D sequence (or `&dyn Sequence<2>`).
//! struct PixelSampler<S> {
//!     seq: S,
//!     seed: Seed,
//! }
//!
//! impl<S: Sequence<2>> PixelSampler<S> {
//!     /// Sample `s` of pixel `(x, y)` in 2D dimension `dim`
//!     /// (0: position in the pixel, 1: lens, 2: light, …).
//!     fn get_2d(&self, x: u32, y: u32, dim: u32, s: u64) -> Result<[f32; 2], PatternError> {
//!         self.seq.point(s, pixel_seed(self.seed, x, y, dim))
//!     }
//! }
//!
//! let seed = Seed::new(7);
//! let sobol = PixelSampler { seq: Sobol::<2>::new(64)?, seed };
//! let [u, v] = sobol.get_2d(10, 20, 0, 5)?;
//! assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
//!
//! // Bit for bit the point that filling the pixel's whole pattern gives:
//! let mut pts = [[0.0f32; 2]; 64];
//! Sobol::<2>::new(64)?.fill(pixel_seed(seed, 10, 20, 0), &mut pts)?;
//! assert_eq!(pts[5], [u, v]);
//!
//! // Sobol' and Halton run past the pattern's N (the sequence has 2³² points) ...
//! assert!(sobol.get_2d(10, 20, 0, 1000).is_ok());
//! // ... and give 1024 dimensions of one point; past them, an error:
//! let z = sobol.seq.sample(5, 1023, pixel_seed(seed, 10, 20, 0))?;
//! assert!((0.0..1.0).contains(&z));
//! assert_eq!(
//!     sobol.seq.sample(5, 1024, seed),
//!     Err(PatternError::Dimension { dim: 1024, max: 1024 })
//! );
//!
//! // A stratified pattern has exactly N points; asking past them is an error.
//! let jit = PixelSampler { seq: Jittered::new([8, 8])?, seed };
//! assert!(jit.get_2d(10, 20, 0, 63).is_ok());
//! assert_eq!(
//!     jit.get_2d(10, 20, 0, 64),
//!     Err(PatternError::Range { first: 64, len: 1, n: 64 })
//! );
//!
//! // The trait is object safe: choose the sequence at run time.
//! let seqs: [&dyn Sequence<2>; 2] = [&sobol.seq, &jit.seq];
//! let by_ref = PixelSampler { seq: seqs[1], seed };
//! assert_eq!(by_ref.get_2d(3, 4, 1, 9)?, jit.get_2d(3, 4, 1, 9)?);
//! # Ok::<(), PatternError>(())
//! ```
//!
//! References: B. Burley, *Practical Hash-based Owen Scrambling*, JCGT 9(4),
//! 2020; A. Kensler, *Correlated Multi-Jittered Sampling*, Pixar Technical Memo
//! 13-01, 2013; T. Kollig, A. Keller, *Efficient Multidimensional Sampling*,
//! Computer Graphics Forum 21(3), 2002; J. K. Salmon et al., *Parallel Random
//! Numbers: As Easy as 1, 2, 3*, SC 2011.
//!
//! [`PoissonDisk`]: crate::pattern::PoissonDisk
//! [`Pmj02Pixel`]: crate::pattern::Pmj02Pixel
//! [`Pmj02Tables`]: crate::pattern::Pmj02Tables

use crate::error::PatternError;
use crate::num::to_unit_f32;
use crate::pattern::sealed::{Generate, Sink};
use crate::pattern::{
    shift_component, CorrelatedMultiJittered, Halton, Jittered, MultiJittered, NRooks, Random,
    Shifted, Sobol, HALTON_DIMENSIONS, SOBOL_DIMENSIONS,
};
use crate::rng::{mix64, Seed, GOLDEN_64};

/// A point sequence with random access: point `index` (or one coordinate of
/// it) computed on its own, without generating the points before it.
///
/// Implemented by every random-access pattern (see the [module docs](self)
/// for the list and the cost per point) and by [`Shifted<P>`] for a
/// `P: Sequence<D>`. Results are bit-identical to
/// [`Pattern::fill_range`](crate::pattern::Pattern::fill_range) of the same
/// pattern and seed. Object safe; never allocates; never panics (bad indices
/// are errors).
///
/// The number of points is [`Sequence::count`], not `len`, so that a type
/// that is also a [`Pattern`](crate::pattern::Pattern) (whose `len` is the
/// `usize` pattern size, different for [`Sobol`] and [`Halton`]) has no
/// ambiguous method when both traits are in scope.
pub trait Sequence<const D: usize> {
    /// Number of points: the pattern's `N`, or `2³²` for [`Sobol`] and
    /// [`Halton`], whose points do not depend on `N`. Always at least 1.
    fn count(&self) -> u64;

    /// Number of dimensions [`Sequence::sample`] accepts: `D`, or 1024
    /// ([`SOBOL_DIMENSIONS`], [`HALTON_DIMENSIONS`]) for [`Sobol`] and
    /// [`Halton`]. The default is `D`.
    fn dimensions(&self) -> u32 {
        D as u32
    }

    /// Point `index`, equal bit for bit to element `index` of a fill of all
    /// points with `seed`.
    ///
    /// # Errors
    /// [`PatternError::Range`] `{ first: index, len: 1, n: self.count() }` if
    /// `index ≥ self.count()`.
    fn point(&self, index: u64, seed: Seed) -> Result<[f32; D], PatternError>;

    /// Coordinate `dim` of point `index`: `point(index, seed)?[dim]` for
    /// `dim < D`. [`Sobol`] and [`Halton`] accept every `dim` below 1024 (their
    /// sequence dimensions, independent of `D`) and return their
    /// [`Sobol::sample`] / [`Halton::sample`].
    ///
    /// The default computes the whole point and accepts `dim < D`; an
    /// implementation that raises [`Sequence::dimensions`] above `D` must
    /// override this method too.
    ///
    /// # Errors
    /// [`PatternError::Range`] as for [`Sequence::point`], then
    /// [`PatternError::Dimension`] `{ dim, max: self.dimensions() }` if
    /// `dim ≥ self.dimensions()`.
    fn sample(&self, index: u64, dim: u32, seed: Seed) -> Result<f32, PatternError> {
        let p = self.point(index, seed)?;
        p.get(dim as usize)
            .copied()
            .ok_or(PatternError::Dimension { dim, max: D as u32 })
    }

    /// Coordinates `dim … dim + 3` of point `index` at once:
    /// `[sample(index, dim + l, seed)?; l = 0..4]`, bit for bit. [`Sobol`]
    /// computes the four in SIMD lanes ([`Sobol::sample_4d`]: one index
    /// scramble, one vector load per pair of index bits); the default calls
    /// [`Sequence::sample`] four times.
    ///
    /// # Errors
    /// As [`Sequence::sample`] for the first coordinate that has one: a bad
    /// `index` first, then [`PatternError::Dimension`] naming the first
    /// dimension `≥ self.dimensions()`.
    fn sample_4d(&self, index: u64, dim: u32, seed: Seed) -> Result<[f32; 4], PatternError> {
        lanes_by_sample(self, index, dim, seed)
    }

    /// Coordinates `dim … dim + 7` of point `index` at once:
    /// [`Sequence::sample_4d`] with eight lanes ([`Sobol::sample_8d`] for
    /// [`Sobol`]).
    ///
    /// # Errors
    /// As [`Sequence::sample_4d`].
    fn sample_8d(&self, index: u64, dim: u32, seed: Seed) -> Result<[f32; 8], PatternError> {
        lanes_by_sample(self, index, dim, seed)
    }
}

/// `[seq.sample(index, dim + l, seed)?; l = 0..L]`, the first error returned
/// (the default batch).
#[inline]
fn lanes_by_sample<const D: usize, const L: usize, S: Sequence<D> + ?Sized>(
    seq: &S,
    index: u64,
    dim: u32,
    seed: Seed,
) -> Result<[f32; L], PatternError> {
    let mut out = [0.0f32; L];
    for (l, o) in out.iter_mut().enumerate() {
        let d = dim.checked_add(l as u32).ok_or(PatternError::Dimension {
            dim: u32::MAX,
            max: seq.dimensions(),
        })?;
        *o = seq.sample(index, d, seed)?;
    }
    Ok(out)
}

/// `Ok` iff dimensions `dim … dim + lanes − 1` all exist (`< max`); else the
/// error naming the first that does not.
#[inline]
fn check_dims(dim: u32, lanes: u32, max: u32) -> Result<(), PatternError> {
    match dim.checked_add(lanes - 1) {
        Some(last) if last < max => Ok(()),
        _ => Err(PatternError::Dimension {
            dim: dim.max(max),
            max,
        }),
    }
}

impl<const D: usize, S: Sequence<D> + ?Sized> Sequence<D> for &S {
    fn count(&self) -> u64 {
        (**self).count()
    }
    fn dimensions(&self) -> u32 {
        (**self).dimensions()
    }
    fn point(&self, index: u64, seed: Seed) -> Result<[f32; D], PatternError> {
        (**self).point(index, seed)
    }
    fn sample(&self, index: u64, dim: u32, seed: Seed) -> Result<f32, PatternError> {
        (**self).sample(index, dim, seed)
    }
    fn sample_4d(&self, index: u64, dim: u32, seed: Seed) -> Result<[f32; 4], PatternError> {
        (**self).sample_4d(index, dim, seed)
    }
    fn sample_8d(&self, index: u64, dim: u32, seed: Seed) -> Result<[f32; 8], PatternError> {
        (**self).sample_8d(index, dim, seed)
    }
}

/// `Ok` iff `index < n`, else the [`PatternError::Range`] of a one-point fill.
#[inline]
fn check_index(index: u64, n: u64) -> Result<(), PatternError> {
    if index < n {
        Ok(())
    } else {
        Err(PatternError::Range {
            first: index,
            len: 1,
            n,
        })
    }
}

/// `Ok` iff `dim < max`.
#[inline]
fn check_dim(dim: u32, max: u32) -> Result<(), PatternError> {
    if dim < max {
        Ok(())
    } else {
        Err(PatternError::Dimension { dim, max })
    }
}

/// A sink of exactly one point.
struct One<const D: usize>([f32; D]);

impl<const D: usize> Sink<D> for One<D> {
    #[inline(always)]
    fn len(&self) -> usize {
        1
    }
    #[inline(always)]
    fn put(&mut self, i: usize, p: [f32; D]) {
        if i == 0 {
            self.0 = p;
        }
    }
    #[inline(always)]
    fn put8<U: crate::num::lane::U32x8Lane>(&mut self, i: usize, v: [U::F; D]) {
        // Never called for a one-point sink (a full block needs 8 points);
        // kept total: lane 0 is point `i`.
        if i == 0 {
            self.0 = core::array::from_fn(|j| crate::pattern::to_array8(v[j])[0]);
        }
    }
}

/// Point `index` of a generator by its scalar path started at `index`: the
/// cost of one point, never of the `index` before it.
#[inline]
fn generated<const D: usize, G: Generate<D>>(
    g: &G,
    len: u64,
    index: u64,
    seed: Seed,
) -> Result<[f32; D], PatternError> {
    check_index(index, len)?;
    let mut one = One([0.0; D]);
    g.gen_scalar(seed, index, &mut one);
    Ok(one.0)
}

/// `Sequence<D>` for finite random-access patterns: `N` points, `D` dimensions.
macro_rules! finite_sequence {
    ($(impl[$($gen:tt)*] Sequence<$d:tt> for $ty:ty;)*) => {$(
        impl<$($gen)*> Sequence<$d> for $ty {
            fn count(&self) -> u64 {
                Generate::<$d>::n(self)
            }
            fn point(&self, index: u64, seed: Seed) -> Result<[f32; $d], PatternError> {
                generated(self, Generate::<$d>::n(self), index, seed)
            }
        }
    )*};
}

finite_sequence! {
    impl[const D: usize] Sequence<D> for Random<D>;
    impl[const D: usize] Sequence<D> for Jittered<D>;
    impl[const D: usize] Sequence<D> for NRooks<D>;
    impl[] Sequence<2> for MultiJittered;
    impl[] Sequence<2> for CorrelatedMultiJittered;
}

/// Points in the Sobol' and Halton sequences: every `u32` index.
const FULL: u64 = 1 << 32;

/// `Sequence<D>` for the low-discrepancy sequences, with `sample` from their
/// inherent 1024-dimensional random access.
macro_rules! full_sequence {
    ($($ty:ident, $dims:expr $(, batch: $b4:ident, $b8:ident)?;)*) => {$(
        impl<const D: usize> Sequence<D> for $ty<D> {
            fn count(&self) -> u64 {
                FULL
            }
            fn dimensions(&self) -> u32 {
                $dims
            }
            fn point(&self, index: u64, seed: Seed) -> Result<[f32; D], PatternError> {
                generated(self, FULL, index, seed)
            }
            fn sample(&self, index: u64, dim: u32, seed: Seed) -> Result<f32, PatternError> {
                check_index(index, FULL)?;
                check_dim(dim, $dims)?;
                // index < 2³² and dim < 1024 were checked: no truncation, no panic.
                Ok($ty::<1>::sample(index as u32, dim, seed))
            }
            $(
            fn sample_4d(&self, index: u64, dim: u32, seed: Seed) -> Result<[f32; 4], PatternError> {
                check_index(index, FULL)?;
                check_dims(dim, 4, $dims)?;
                Ok($ty::<1>::$b4(index as u32, dim, seed))
            }
            fn sample_8d(&self, index: u64, dim: u32, seed: Seed) -> Result<[f32; 8], PatternError> {
                check_index(index, FULL)?;
                check_dims(dim, 8, $dims)?;
                Ok($ty::<1>::$b8(index as u32, dim, seed))
            }
            )?
        }
    )*};
}

full_sequence! {
    Sobol, SOBOL_DIMENSIONS, batch: sample_4d, sample_8d;
    Halton, HALTON_DIMENSIONS;
}

/// The shifted sequence: coordinate `j` is `to_unit_f32(x_j + s_j)` with the
/// shift `s_j` of [`Shifted::shift`], exactly as [`Shifted`]'s fills compute it
/// (the sum in `f64`, wrapped and rounded by [`to_unit_f32`]).
///
/// For the sequence dimensions `j ≥ D` of [`Sobol`] and [`Halton`],
/// [`Sequence::sample`] continues the shift with the same formula,
/// `s_j = Shifted::shift::<J>(seed)[j]` for any `J > j`.
impl<const D: usize, P: Sequence<D>> Sequence<D> for Shifted<P> {
    fn count(&self) -> u64 {
        self.inner().count()
    }
    fn dimensions(&self) -> u32 {
        self.inner().dimensions()
    }
    fn point(&self, index: u64, seed: Seed) -> Result<[f32; D], PatternError> {
        let p = self.inner().point(index, seed)?;
        let s = Self::shift::<D>(seed);
        Ok(core::array::from_fn(|j| {
            to_unit_f32(f64::from(p[j]) + s[j])
        }))
    }
    fn sample(&self, index: u64, dim: u32, seed: Seed) -> Result<f32, PatternError> {
        let x = self.inner().sample(index, dim, seed)?;
        Ok(to_unit_f32(f64::from(x) + shift_component(seed, dim)))
    }
    fn sample_4d(&self, index: u64, dim: u32, seed: Seed) -> Result<[f32; 4], PatternError> {
        let x = self.inner().sample_4d(index, dim, seed)?;
        Ok(shift_lanes(x, dim, seed))
    }
    fn sample_8d(&self, index: u64, dim: u32, seed: Seed) -> Result<[f32; 8], PatternError> {
        let x = self.inner().sample_8d(index, dim, seed)?;
        Ok(shift_lanes(x, dim, seed))
    }
}

/// Lane `l` of `x` shifted as dimension `dim + l` (the inner batch succeeded,
/// so `dim + l` does not overflow).
#[inline]
fn shift_lanes<const L: usize>(x: [f32; L], dim: u32, seed: Seed) -> [f32; L] {
    core::array::from_fn(|l| to_unit_f32(f64::from(x[l]) + shift_component(seed, dim + l as u32)))
}

/// Seed purpose of [`pixel_seed`].
const PIXEL_PURPOSE: u64 = 0x5049_5845_4C00_0000;

/// The seed of pixel `(x, y)` and sample dimension `dim` in a run seeded with
/// `seed`: an independent scramble per pixel and per dimension.
///
/// With `mix64` the MurmurHash3 64-bit finaliser ([`mix64`], full avalanche)
/// and `φ₆₄ = ⌊2⁶⁴/φ⌋ = 0x9E3779B97F4A7C15`,
///
/// `h = mix64((x + 2³²·y) ⊕ P)`, `k = mix64(h + (dim + 1)·φ₆₄)`,
/// `pixel_seed = Seed(mix64(seed ⊕ k))` (all mod `2⁶⁴`, `P` a fixed constant).
///
/// `h` is a bijection of the pixel `(x, y)`, `k` is injective in `dim` for a
/// fixed pixel, and the result is a bijection of `seed` for every
/// `(x, y, dim)`; two different `(x, y, dim)` get the same key only by a hash
/// coincidence (probability about `2⁻⁶⁴` per pair). Neighbouring pixels, which
/// differ in one low bit of `x` or `y`, therefore get unrelated seeds, and so
/// unrelated scrambles, jitters and permutations. `tests/sequence.rs` checks that the
/// points of neighbouring pixels and of neighbouring `dim` are uncorrelated.
///
/// Compose with [`Seed::realization`] for independent runs:
/// `pixel_seed(seed.realization(r), x, y, dim)`.
#[inline]
#[must_use]
pub const fn pixel_seed(seed: Seed, x: u32, y: u32, dim: u32) -> Seed {
    let h = mix64((x as u64 | (y as u64) << 32) ^ PIXEL_PURPOSE);
    let k = mix64(h.wrapping_add((dim as u64 + 1).wrapping_mul(GOLDEN_64)));
    Seed(mix64(seed.0 ^ k))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wide::f32x8;

    #[test]
    fn one_point_sink_takes_lane_zero() {
        let mut one = One::<2>([0.0; 2]);
        let v = [f32x8::new([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]); 2];
        one.put8::<crate::num::lane::Wu32x8>(0, v);
        assert_eq!(one.0, [1.0, 1.0]);
        one.put8::<crate::num::lane::Wu32x8>(8, [f32x8::ZERO; 2]);
        one.put(3, [9.0, 9.0]);
        assert_eq!(one.0, [1.0, 1.0]);
    }

    #[test]
    fn pixel_seed_is_a_bijection_of_the_seed_and_separates_pixels() {
        let a = pixel_seed(Seed(1), 0, 0, 0);
        assert_ne!(a, pixel_seed(Seed(2), 0, 0, 0));
        assert_ne!(a, pixel_seed(Seed(1), 1, 0, 0));
        assert_ne!(a, pixel_seed(Seed(1), 0, 1, 0));
        assert_ne!(a, pixel_seed(Seed(1), 0, 0, 1));
        // (x, y) is not symmetric.
        assert_ne!(pixel_seed(Seed(1), 1, 2, 0), pixel_seed(Seed(1), 2, 1, 0));
    }
}
