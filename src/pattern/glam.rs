//! glam interop (feature `glam`): patterns fill `glam` vector slices.

use super::Pattern;
use crate::error::PatternError;
use crate::rng::Seed;
use ::glam::{Vec2, Vec3, Vec3A};

// `Vec2` and `Vec3` are `#[repr(C)]` structs of 2 and 3 `f32`s: the same size as
// `[f32; D]` and at least its alignment, so `bytemuck::cast_slice_mut` never
// fails (it only panics on a size or alignment mismatch). Checked at compile
// time, in case a glam feature ever changes the layout.
const _: () = {
    use core::mem::{align_of, size_of};
    assert!(size_of::<Vec2>() == size_of::<[f32; 2]>());
    assert!(align_of::<Vec2>() >= align_of::<[f32; 2]>());
    assert!(size_of::<Vec3>() == size_of::<[f32; 3]>());
    assert!(align_of::<Vec3>() >= align_of::<[f32; 3]>());
};

/// Points per chunk of the [`Vec3A`] fill (a stack buffer of `64 × 12` bytes).
const VEC3A_CHUNK: usize = 64;

/// Fills slices of [`glam`](::glam) vectors: `&mut [Vec2]` from a
/// [`Pattern<2>`], `&mut [Vec3]` and `&mut [Vec3A]` from a [`Pattern<3>`]
/// (feature `glam`).
///
/// Implemented for every pattern (and `dyn Pattern<D>`); the element type of
/// the slice selects the impl. The values are bit for bit those of
/// [`Pattern::fill`] / [`Pattern::fill_range`] into `[[f32; D]]`, and the
/// errors are theirs. Nothing allocates:
///
/// * `Vec2` and `Vec3` have the layout of `[f32; 2]` and `[f32; 3]`
///   (`#[repr(C)]`), so the slice is cast in place with
///   [`bytemuck::cast_slice_mut`] and filled directly: no copy.
/// * `Vec3A` is 16 bytes (SIMD-aligned, a padding lane), not the layout of
///   `[f32; 3]`: it is filled through a stack buffer of 64 points, one
///   [`Pattern::fill_range`] call per 64 points. For patterns whose every
///   `fill_range` generates the whole set (`PoissonDiskN`, `Ccvt`) that repeats
///   the generation `⌈len/64⌉` times: fill a `[Vec3]` or `[[f32; 3]]` once and
///   convert instead.
///
/// ```
/// use glam::{Vec2, Vec3, Vec3A};
/// use linesample::pattern::{Jittered, Pattern, PatternGlam, Sobol};
/// use linesample::Seed;
///
/// let mut uv = [Vec2::ZERO; 64];
/// Jittered::new([8, 8])?.fill_glam(Seed::new(1), &mut uv)?;
///
/// let sobol = Sobol::<3>::new(100)?;
/// let mut p = vec![Vec3::ZERO; 100];
/// sobol.fill_glam(Seed::new(2), &mut p)?;
/// let mut pa = vec![Vec3A::ZERO; 100];
/// sobol.fill_glam(Seed::new(2), &mut pa)?;
/// assert!(p.iter().zip(&pa).all(|(a, b)| *a == Vec3::from(*b)));
///
/// // A range: points 90..100.
/// sobol.fill_range_glam(Seed::new(2), 90, &mut pa[..10])?;
/// assert_eq!(Vec3::from(pa[0]), p[90]);
/// # Ok::<(), linesample::PatternError>(())
/// ```
///
/// For one point of a [`Sequence`](crate::sequence::Sequence), convert the
/// array: `seq.point(k, seed).map(Vec2::from)`.
pub trait PatternGlam<V> {
    /// Writes all `N` points into `out` (as [`Pattern::fill`]).
    ///
    /// # Errors
    /// [`PatternError::OutputLength`] if `out.len() != N`.
    fn fill_glam(&self, seed: Seed, out: &mut [V]) -> Result<(), PatternError>;

    /// Writes points `first .. first + out.len()` into `out` (as
    /// [`Pattern::fill_range`]).
    ///
    /// # Errors
    /// [`PatternError::Range`] if the range runs past `N`; nothing is written
    /// then.
    fn fill_range_glam(&self, seed: Seed, first: usize, out: &mut [V]) -> Result<(), PatternError>;
}

impl<P: Pattern<2> + ?Sized> PatternGlam<Vec2> for P {
    fn fill_glam(&self, seed: Seed, out: &mut [Vec2]) -> Result<(), PatternError> {
        self.fill(seed, bytemuck::cast_slice_mut(out))
    }

    fn fill_range_glam(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [Vec2],
    ) -> Result<(), PatternError> {
        self.fill_range(seed, first, bytemuck::cast_slice_mut(out))
    }
}

impl<P: Pattern<3> + ?Sized> PatternGlam<Vec3> for P {
    fn fill_glam(&self, seed: Seed, out: &mut [Vec3]) -> Result<(), PatternError> {
        self.fill(seed, bytemuck::cast_slice_mut(out))
    }

    fn fill_range_glam(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [Vec3],
    ) -> Result<(), PatternError> {
        self.fill_range(seed, first, bytemuck::cast_slice_mut(out))
    }
}

impl<P: Pattern<3> + ?Sized> PatternGlam<Vec3A> for P {
    fn fill_glam(&self, seed: Seed, out: &mut [Vec3A]) -> Result<(), PatternError> {
        if out.len() != self.len() {
            return Err(PatternError::OutputLength {
                expected: self.len(),
                got: out.len(),
            });
        }
        self.fill_range_glam(seed, 0, out)
    }

    fn fill_range_glam(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [Vec3A],
    ) -> Result<(), PatternError> {
        // Check the whole range first, so that an error names the request and
        // leaves `out` untouched, as the other fills do.
        let n = self.len() as u64;
        match (first as u64).checked_add(out.len() as u64) {
            Some(end) if end <= n => {}
            _ => {
                return Err(PatternError::Range {
                    first: first as u64,
                    len: out.len() as u64,
                    n,
                })
            }
        }
        let mut buf = [[0.0f32; 3]; VEC3A_CHUNK];
        for (c, chunk) in out.chunks_mut(VEC3A_CHUNK).enumerate() {
            let pts = &mut buf[..chunk.len()];
            self.fill_range(seed, first + c * VEC3A_CHUNK, pts)?;
            for (v, p) in chunk.iter_mut().zip(pts.iter()) {
                *v = Vec3A::from_array(*p);
            }
        }
        Ok(())
    }
}
