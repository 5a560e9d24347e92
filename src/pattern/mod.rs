//! Finite point sets on the unit torus `[0, 1)^D`, `D = 1, 2, 3`.
//!
//! Every pattern implements [`Pattern<D>`]: it writes its `N` points (or any
//! contiguous range of them) into caller storage, as array-of-structs
//! `[[f32; D]]` or as a structure-of-arrays batch (`D` slices of `f32`), with no
//! allocation. The points are a pure function of the [`Seed`]: the SIMD path, the
//! scalar path ([`Pattern::fill_range_scalar`]), any split of the range into
//! batches, and any SIMD width give bit-identical results (tested lane by lane).
//!
//! Every coordinate lies in `[0, 1)`: never `1.0`, never NaN. Stratified patterns
//! guarantee exact stratum membership of the `f32` value: for a stratum
//! `[c/m, (c+1)/m)` the returned `x` satisfies `c ≤ x·m < c + 1` in exact arithmetic.
//!
//! [`Shifted`] adds a random toroidal shift (Cranley–Patterson rotation[^1]),
//! `x ↦ (x + s) mod 1` with `s` drawn from the seed: the homogenisation that makes a
//! pattern's statistics shift-invariant, which every spectral variance analysis
//! assumes (Pilleboue et al. 2015).
//!
//! | pattern | dims | `N` |
//! |---|---|---|
//! | [`Random`] | 1–3 | `≤ 2³²` |
//! | [`Jittered`] | 1–3 | `m₁·…·m_D` strata (each `m_i ≤ 2²⁴`, product `≤ 2³²`) |
//! | [`NRooks`] (Latin hypercube) | 1–3 | `≤ 2²⁴` |
//! | [`MultiJittered`] (Chiu, Shirley & Wang 1994) | 2 | `m·n ≤ 2²⁴` |
//! | [`CorrelatedMultiJittered`] (Kensler 2013) | 2 | `m·n ≤ 2²⁴` |
//! | [`Sobol`] (Owen-scrambled, Burley 2020) | 1–3 (sequence: 16 dims) | `≤ 2³²` |
//! | [`Halton`] (Owen-scrambled) | 1–3 (sequence: 16 dims) | `≤ 2³²` |
//! | [`PoissonDisk`] (Bridson 2007; maximal dart throwing with active boxes, Ebeida et al. 2011), toroidal | 1–3 | from the radius |
//! | `PoissonDiskN`: exactly `N` points, by default dart throwing stopped at `N` ([`PoissonN`]; `alloc` feature; each fill generates the whole set) | 1–3 | `≤` [`PoissonDisk::max_points`] |
//! | `Ccvt` (Balzer et al. 2009; `alloc` feature), toroidal | 2–3 | `≤ 2²⁴` (and `N·c ≤ 2³¹` for capacity `c`) |
//! | [`Pmj02`] (progressive multi-jittered (0,2), Christensen et al. 2018; Pharr 2019): every power-of-two prefix stratified in all elementary intervals (`Pattern` with the `alloc` feature; each fill generates the prefix) | 2 | `≤ 2²⁴` |
//! | [`Pmj02::blue_noise`] (PMJ02BN: best candidate, Christensen et al. 2018) | 2 | `≤ 2²⁴` |
//! | [`Pmj02Tables`]: `sets` PMJ02 or PMJ02BN realisations, read per pixel in `O(1)` ([`Pmj02Pixel`], a `Sequence<2>`: Owen-scrambled or moved by one of 32 isometries per pixel and pair, every power-of-two prefix a net) | 2 per pair | a power of two `≤ 2²⁴` |
//!
//! Point `k` of the random-access patterns (all of the above but Poisson disk,
//! CCVT and [`Pmj02`], whose generation is sequential) can also be computed on
//! its own, without the others: [`crate::sequence::Sequence`]. PMJ02 gets random
//! access from precomputed tables, per pixel ([`Pmj02Tables::pixel`]). With the `glam` feature, `PatternGlam` fills
//! slices of `glam::Vec2`, `Vec3` (cast in place) and `Vec3A`.
//!
//! [^1]: R. Cranley, T. N. L. Patterson, *Randomization of Number Theoretic Methods
//!   for Multiple Integration*, SIAM J. Numer. Anal. 13(6), 1976.

mod ccvt;
mod halton;
mod jittered;
pub mod multijitter;
mod nrooks;
mod pmj;
mod pmj_pixel;
mod poisson;
mod random;
mod sobol;
mod zsobol;

#[cfg(feature = "glam")]
mod glam;
#[cfg(feature = "glam")]
pub use self::glam::PatternGlam;

pub use ccvt::CCVT_DEFAULT_CAPACITY;
#[cfg(feature = "alloc")]
pub use ccvt::{Ccvt, CcvtResult};
pub use halton::{radical_inverse, Halton, HALTON_BASES, HALTON_DIMENSIONS};
pub use jittered::Jittered;
pub use multijitter::{CorrelatedMultiJittered, MultiJittered};
pub use nrooks::NRooks;
pub use pmj::{Pmj02, PMJ02BN_DEFAULT_CANDIDATES, PMJ02BN_MAX_CANDIDATES, PMJ02_MAX_POINTS};
pub use pmj_pixel::{Pmj02Pixel, Pmj02Tables, PMJ02BN_TRANSFORMS, PMJ02_TABLES_MAX_SETS};
#[cfg(feature = "alloc")]
pub use poisson::PoissonDiskN;
pub use poisson::{
    poisson_max_radius, PoissonDisk, PoissonMethod, PoissonN, BRIDSON_DEFAULT_CANDIDATES,
    BRIDSON_MAX_CANDIDATES, POISSON_MAX_CELLS, POISSON_MAX_CELLS_1D,
};
pub use random::Random;
pub use sobol::{Sobol, SOBOL_DIMENSIONS};
pub use zsobol::{ZSobol, ZSobolPixel, ZSOBOL_MAX_INDEX_BITS};

use crate::error::PatternError;
use crate::num::lane::{F32Lane, Lane, U32x8Lane};
use crate::num::to_unit_f32;
use crate::rng::Seed;

pub use crate::num::torus::ONE_MINUS_EPSILON;

/// Largest dimension a [`Pattern`] supports.
pub const MAX_DIMS: usize = 3;

/// A finite point set of `N` points in `[0, 1)^D`, deterministic from a [`Seed`].
///
/// Implementations never allocate. All methods check their arguments and return
/// [`PatternError`] instead of panicking.
pub trait Pattern<const D: usize> {
    /// `N`, the number of points of one realisation.
    fn len(&self) -> usize;

    /// Always `false`: constructors reject `N = 0`.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Writes points `first .. first + out.len()` (SIMD path).
    ///
    /// # Errors
    /// [`PatternError::Range`] if the range runs past `N`.
    fn fill_range(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError>;

    /// Same points as [`Pattern::fill_range`], computed one point at a time by the
    /// scalar reference path.
    ///
    /// # Errors
    /// [`PatternError::Range`] if the range runs past `N`.
    fn fill_range_scalar(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError>;

    /// Structure-of-arrays batch: coordinate `j` of point `first + i` goes to
    /// `out[j][i]`. All `D` slices must have the same length.
    ///
    /// # Errors
    /// [`PatternError::OutputLength`] if the slices differ in length,
    /// [`PatternError::Range`] if the range runs past `N`.
    fn fill_range_soa(
        &self,
        seed: Seed,
        first: usize,
        out: [&mut [f32]; D],
    ) -> Result<(), PatternError>;

    /// Writes all `N` points.
    ///
    /// # Errors
    /// [`PatternError::OutputLength`] if `out.len() != N`.
    fn fill(&self, seed: Seed, out: &mut [[f32; D]]) -> Result<(), PatternError> {
        if out.len() != self.len() {
            return Err(PatternError::OutputLength {
                expected: self.len(),
                got: out.len(),
            });
        }
        self.fill_range(seed, 0, out)
    }

    /// This pattern with a random toroidal shift drawn from the seed.
    fn shifted(self) -> Shifted<Self>
    where
        Self: Sized,
    {
        Shifted { inner: self }
    }

    /// Allocating convenience: all `N` points in a new `Vec`.
    ///
    /// # Errors
    /// As [`Pattern::fill`].
    #[cfg(feature = "alloc")]
    fn to_vec(&self, seed: Seed) -> Result<alloc::vec::Vec<[f32; D]>, PatternError> {
        let mut v = alloc::vec![[0.0f32; D]; self.len()];
        self.fill(seed, &mut v)?;
        Ok(v)
    }
}

/// Checks `D` against the supported range, for constructors.
pub(crate) const fn check_dims<const D: usize>(min: usize, max: usize) -> Result<(), PatternError> {
    if D < min || D > max {
        Err(PatternError::Dims { dims: D, min, max })
    } else {
        Ok(())
    }
}

/// Checks a point count for constructors: `1 ≤ n ≤ max`.
pub(crate) const fn check_n(n: usize, max: u64) -> Result<u64, PatternError> {
    if n == 0 {
        Err(PatternError::ZeroPoints)
    } else if n as u64 > max {
        Err(PatternError::TooManyPoints { max })
    } else {
        Ok(n as u64)
    }
}

pub(crate) fn check_range(n: u64, first: usize, len: usize) -> Result<(), PatternError> {
    let end = (first as u64).checked_add(len as u64);
    match end {
        Some(e) if e <= n => Ok(()),
        _ => Err(PatternError::Range {
            first: first as u64,
            len: len as u64,
            n,
        }),
    }
}

pub(crate) mod sealed {
    use crate::num::lane::U32x8Lane;
    use crate::rng::Seed;

    /// Where generated points go: array-of-structs or structure-of-arrays.
    pub trait Sink<const D: usize> {
        /// Number of points the sink holds.
        fn len(&self) -> usize;
        /// Point `i`.
        fn put(&mut self, i: usize, p: [f32; D]);
        /// Points `i .. i + 8`, coordinate `j` of point `i + l` in lane `l` of
        /// `v[j]`, in the `f32` lanes of the level whose integer lanes are `U`.
        fn put8<U: U32x8Lane>(&mut self, i: usize, v: [U::F; D]);
        /// The output as one flat slice of `len()·D` coordinates, point-major
        /// (coordinate `j` of point `i` at `i·D + j`), if the sink has that layout.
        /// Generators whose values are a function of the flat index write it
        /// with contiguous vector stores and no transposition.
        fn flat(&mut self) -> Option<&mut [f32]> {
            None
        }
    }

    /// The generator behind a pattern: `count` points starting at `first` into `sink`.
    pub trait Generate<const D: usize> {
        fn n(&self) -> u64;
        /// The SIMD path in the lane types of the level `I` (generators not
        /// yet written over them use `wide`'s types whatever `I` is).
        fn gen_simd<I: crate::simd::Isa, S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S);
        fn gen_scalar<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S);
    }
}

use sealed::{Generate, Sink};

pub(crate) struct Aos<'a, const D: usize>(pub &'a mut [[f32; D]]);

impl<const D: usize> Sink<D> for Aos<'_, D> {
    #[inline(always)]
    fn len(&self) -> usize {
        self.0.len()
    }
    #[inline(always)]
    fn put(&mut self, i: usize, p: [f32; D]) {
        self.0[i] = p;
    }
    #[inline(always)]
    fn put8<U: U32x8Lane>(&mut self, i: usize, v: [U::F; D]) {
        if D == 2 {
            // Two interleaving unpacks (x₀ y₀ x₁ y₁ …), two contiguous stores.
            let (a, b) = U::interleave(U::from_f32_bits(v[0]), U::from_f32_bits(v[1]));
            let dst = self.0[i..i + 8].as_flattened_mut();
            a.to_f32_bits().store(&mut dst[..8]);
            b.to_f32_bits().store(&mut dst[8..]);
            return;
        }
        // Plain loops: a closure here could stay out of line in the AVX2
        // copy (see `drive8!`).
        let mut a = [[0.0; 8]; D];
        for j in 0..D {
            v[j].store(&mut a[j]);
        }
        let dst = &mut self.0[i..i + 8];
        for (l, p) in dst.iter_mut().enumerate() {
            for j in 0..D {
                p[j] = a[j][l];
            }
        }
    }
    #[inline(always)]
    fn flat(&mut self) -> Option<&mut [f32]> {
        Some(self.0.as_flattened_mut())
    }
}

pub(crate) struct Soa<'a, const D: usize>(pub [&'a mut [f32]; D]);

impl<const D: usize> Sink<D> for Soa<'_, D> {
    #[inline(always)]
    fn len(&self) -> usize {
        self.0[0].len()
    }
    #[inline(always)]
    fn put(&mut self, i: usize, p: [f32; D]) {
        for j in 0..D {
            self.0[j][i] = p[j];
        }
    }
    #[inline(always)]
    fn put8<U: U32x8Lane>(&mut self, i: usize, v: [U::F; D]) {
        for j in 0..D {
            v[j].store(&mut self.0[j][i..i + 8]);
        }
    }
}

/// Drives a generator of four blocks of 8 points at a time (so that independent
/// hash chains of the four can overlap in the CPU): full groups of 32 points go
/// out with `put8`; the last, partial group is generated whole and written point
/// by point. `block4` must therefore accept running past the end (its lanes past
/// `N` are discarded).
#[inline(always)]
pub(crate) fn drive32<const D: usize, S: Sink<D>, U: U32x8Lane>(
    sink: &mut S,
    mut block4: impl FnMut() -> [[U::F; D]; 4],
) {
    let n = sink.len();
    let mut i = 0;
    while i + 32 <= n {
        let v = block4();
        sink.put8::<U>(i, v[0]);
        sink.put8::<U>(i + 8, v[1]);
        sink.put8::<U>(i + 16, v[2]);
        sink.put8::<U>(i + 24, v[3]);
        i += 32;
    }
    if i < n {
        let v = block4();
        for (b, vb) in v.into_iter().enumerate() {
            let a: [[f32; 8]; D] = build([0.0; 8], |j| to_array8(vb[j]));
            for l in 0..8 {
                let k = i + 8 * b + l;
                if k < n {
                    sink.put(k, build(0.0, |j| a[j][l]));
                }
            }
        }
    }
}

/// Writes every point of `sink` in blocks of 8: the expression `$block`, the
/// next 8 points as `[U::F; D]` (coordinate `j` of point `i + l` in lane `l`),
/// is evaluated once per block; full blocks go out with `put8`, the last
/// partial block point by point ([`put_tail`]).
///
/// A macro rather than a function taking a closure: the run-time AVX2 copy
/// ([`crate::simd::dispatch`]) needs the block compiled inside its
/// `#[target_feature]` function, and stable Rust cannot mark a closure
/// `#[inline(always)]`. A closure left out of line is compiled for the
/// baseline, where every `core::arch` intrinsic in it is a call (the fills
/// ran 37–47× slower that way, seen in the disassembly).
macro_rules! drive8 {
    ($sink:expr, $U:ty, $block:expr) => {{
        let sink = $sink;
        let n = sink.len();
        let mut i = 0;
        while i < n {
            let v = $block;
            if i + 8 <= n {
                sink.put8::<$U>(i, v);
            } else {
                $crate::pattern::put_tail::<_, _, $U>(sink, i, v);
            }
            i += 8;
        }
    }};
}
pub(crate) use drive8;

/// `[e(0), …, e(D − 1)]` with the index bound to `$j`, written out where it
/// is used, its length `D` taken from the expected type (for the hot bodies
/// of the dispatched fills: a closure, as in [`build`], may stay out of line;
/// see [`drive8!`]).
macro_rules! array {
    ($init:expr, |$j:ident| $e:expr) => {{
        let mut a = [$init; _];
        for $j in 0..a.len() {
            a[$j] = $e;
        }
        a
    }};
}
pub(crate) use array;

/// The last, partial block of [`drive8!`]: the first `sink.len() − i` of the
/// 8 points in `v`, point by point (once per fill, out of line).
#[cold]
#[inline(never)]
pub(crate) fn put_tail<const D: usize, S: Sink<D>, U: U32x8Lane>(
    sink: &mut S,
    i: usize,
    v: [U::F; D],
) {
    let a: [[f32; 8]; D] = build([0.0; 8], |j| to_array8(v[j]));
    for l in 0..sink.len() - i {
        sink.put(i + l, build(0.0, |j| a[j][l]));
    }
}

/// The eight lanes of an `f32` lane vector.
#[inline(always)]
pub(crate) fn to_array8<F: crate::num::lane::F32Lane>(v: F) -> [f32; 8] {
    let mut a = [0.0; 8];
    v.store(&mut a);
    a
}

/// A pattern fill as one dispatched call ([`crate::simd::dispatch`]).
struct Fill<'a, const D: usize, G, S> {
    gen: &'a G,
    seed: Seed,
    first: u64,
    sink: &'a mut S,
}

impl<const D: usize, G: Generate<D>, S: Sink<D>> crate::simd::Kernel for Fill<'_, D, G, S> {
    type Output = ();
    #[inline(always)]
    fn run<I: crate::simd::Isa>(self) {
        self.gen.gen_simd::<I, S>(self.seed, self.first, self.sink);
    }
}

impl<const D: usize, G: Generate<D>> Pattern<D> for G {
    fn len(&self) -> usize {
        self.n() as usize
    }

    fn fill_range(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        check_range(self.n(), first, out.len())?;
        crate::simd::dispatch(Fill {
            gen: self,
            seed,
            first: first as u64,
            sink: &mut Aos(out),
        });
        Ok(())
    }

    fn fill_range_scalar(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        check_range(self.n(), first, out.len())?;
        self.gen_scalar(seed, first as u64, &mut Aos(out));
        Ok(())
    }

    fn fill_range_soa(
        &self,
        seed: Seed,
        first: usize,
        out: [&mut [f32]; D],
    ) -> Result<(), PatternError> {
        let len = soa_len(&out)?;
        check_range(self.n(), first, len)?;
        crate::simd::dispatch(Fill {
            gen: self,
            seed,
            first: first as u64,
            sink: &mut Soa(out),
        });
        Ok(())
    }
}

pub(crate) fn soa_len<const D: usize>(out: &[&mut [f32]; D]) -> Result<usize, PatternError> {
    let len = out.first().map_or(0, |s| s.len());
    for s in out.iter() {
        if s.len() != len {
            return Err(PatternError::OutputLength {
                expected: len,
                got: s.len(),
            });
        }
    }
    Ok(len)
}

/// A pattern with a random toroidal shift (Cranley–Patterson rotation):
/// `x_j ↦ (x_j + s_j) mod 1`, with `s ∈ [0,1)^D` uniform and drawn from the seed.
///
/// The sum is formed in `f64`, wrapped and rounded to `f32` by
/// [`crate::num::to_unit_f32`], so the result stays in `[0, 1)`.
#[derive(Clone, Debug)]
pub struct Shifted<P> {
    inner: P,
}

/// Seed purpose of the toroidal shift.
const SHIFT_PURPOSE: u64 = 0x5348_4946_5400_0000;

impl<P> Shifted<P> {
    /// The shift vector used for `seed`.
    #[must_use]
    pub fn shift<const D: usize>(seed: Seed) -> [f64; D] {
        core::array::from_fn(|j| shift_component(seed, j as u32))
    }

    /// The unshifted pattern.
    pub fn inner(&self) -> &P {
        &self.inner
    }
}

impl<const D: usize, P: Pattern<D>> Pattern<D> for Shifted<P> {
    fn len(&self) -> usize {
        self.inner.len()
    }

    fn fill_range(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        self.inner.fill_range(seed, first, out)?;
        let s = Self::shift::<D>(seed);
        for p in out.iter_mut() {
            for j in 0..D {
                p[j] = to_unit_f32(f64::from(p[j]) + s[j]);
            }
        }
        Ok(())
    }

    fn fill_range_scalar(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        self.inner.fill_range_scalar(seed, first, out)?;
        let s = Self::shift::<D>(seed);
        for p in out.iter_mut() {
            for j in 0..D {
                p[j] = to_unit_f32(f64::from(p[j]) + s[j]);
            }
        }
        Ok(())
    }

    fn fill_range_soa(
        &self,
        seed: Seed,
        first: usize,
        mut out: [&mut [f32]; D],
    ) -> Result<(), PatternError> {
        let s = Self::shift::<D>(seed);
        {
            let reb: [&mut [f32]; D] = out.each_mut().map(|x| &mut **x);
            self.inner.fill_range_soa(seed, first, reb)?;
        }
        for j in 0..D {
            for x in out[j].iter_mut() {
                *x = to_unit_f32(f64::from(*x) + s[j]);
            }
        }
        Ok(())
    }
}

/// Component `j` of the toroidal shift of [`Shifted`] for `seed`:
/// `s_j = unit_f64(seed.stream(SHIFT_PURPOSE + j))`, so `Shifted::shift::<D>(seed)[j]`
/// for every `D > j`. Defined for every `j`, which extends the shift to the
/// sequence dimensions beyond `D` ([`crate::sequence::Sequence::sample`]).
#[inline]
#[must_use]
pub(crate) fn shift_component(seed: Seed, j: u32) -> f64 {
    unit_f64(seed.stream(SHIFT_PURPOSE + u64::from(j)))
}

/// Top 24 bits of `bits` as an `f32` in `[0, 1 − 2⁻²⁴]` (exact).
#[inline(always)]
#[must_use]
pub(crate) fn unit_f32(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Lane-wise [`unit_f32`].
#[inline(always)]
pub(crate) fn unit_f32x8<U: U32x8Lane>(bits: U) -> U::F {
    (bits >> 8).to_f32() * <U::F as Lane>::splat(1.0 / 16_777_216.0)
}

/// Top 53 bits of `bits` as an `f64` in `[0, 1)`.
#[inline(always)]
#[must_use]
pub(crate) fn unit_f64(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
}

/// One axis cut into `m` strata: maps `(cell, random bits)` to an `f32` inside the
/// stratum `[cell/m, (cell+1)/m)`, exactly.
///
/// The value is `v = (c + U·2⁻²⁴)·fl(1/m)` in `f32`, with `U = bits ≫ 8`. Its
/// three roundings move `v` by at most `3.01·2⁻²⁴·v`, i.e. about three ulps,
/// from `(c + u)/m`, so when `4m ≤ U ≤ 2²⁴ − 4m` the point is provably inside
/// its stratum and `v` is returned. When `m = 2ᵏ < 2²²` the window is wider,
/// `U ≤ 2²⁴ − 2m`: `1/m` and the product are exact, so the only rounding is
/// `s = fl(c + U·2⁻²⁴) ∈ [c, c + 1]`, and `s` reaches `c + 1` only if
/// `1 − U·2⁻²⁴ ≤ ½ulp(c + 1) ≤ 2⁻²⁴·m`. Otherwise (probability `8m/2²⁴`, `2m/2²⁴`
/// for powers of two, or always when `m ≥ 2²¹` is not one)
/// membership is tested exactly and `v` moved by one ulp at a
/// time (at most four) until it is inside: `v·m = p + e` exactly by Dekker's
/// product with Veltkamp splits (Dekker 1971; no fused multiply-add, so every
/// build gives the same bits), and `(p − c) + e` has the sign of `v·m − c`
/// (`p − c` is exact: `c` is an integer near `p`). Both tests and the moves run
/// in `f32` lanes; the scalar path does the same operations, so the two agree
/// bit for bit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Strata {
    m: f32,
    m_hi: f32,
    m_lo: f32,
    inv32: f32,
    lo: i32,
    hi: i32,
}

/// Veltkamp's splitting constant for `f32`, `2¹² + 1`: `a = hi + lo` with both
/// halves of at most 12 significant bits.
const SPLIT_F32: f32 = 4097.0;

impl Strata {
    /// `m` strata, `1 ≤ m ≤ 2²⁴`.
    pub(crate) fn new(m: u32) -> Self {
        let d = 4 * u64::from(m);
        let (lo, hi) = if m.is_power_of_two() && m < 1 << 22 {
            // 1/m is exact and so is the product: only c + u can round, and only
            // up to c + 1, which needs 2²⁴ − U ≤ m.
            (0, (1 << 24) - 2 * m as i32)
        } else if d >= 1 << 23 {
            (i32::MAX, i32::MIN)
        } else {
            (d as i32, (1 << 24) - d as i32)
        };
        let mf = m as f32; // exact: m ≤ 2²⁴
        let t = mf * SPLIT_F32;
        let m_hi = t - (t - mf);
        Self {
            m: mf,
            m_hi,
            m_lo: mf - m_hi,
            inv32: 1.0 / mf,
            lo,
            hi,
        }
    }

    /// `(v·m < c, v·m ≥ c + 1)`, exactly.
    #[inline(always)]
    fn outside(&self, v: f32, c: f32) -> (bool, bool) {
        let p = v * self.m;
        let t = v * SPLIT_F32;
        let vh = t - (t - v);
        let vl = v - vh;
        let e = ((vh * self.m_hi - p) + vh * self.m_lo + vl * self.m_hi) + vl * self.m_lo;
        ((p - c) + e < 0.0, (p - (c + 1.0)) + e >= 0.0)
    }

    /// The coordinate of a point of stratum `cell` with jitter `bits`.
    #[inline(always)]
    pub(crate) fn point(&self, cell: u32, bits: u32) -> f32 {
        let u = (bits >> 8) as i32;
        let c = cell as f32;
        let mut v = (c + u as f32 * (1.0 / 16_777_216.0)) * self.inv32;
        if u >= self.lo && u <= self.hi {
            return v;
        }
        loop {
            match self.outside(v, c) {
                (true, _) => v = f32::from_bits(v.to_bits() + 1),
                (_, true) => v = f32::from_bits(v.to_bits() - 1),
                _ => return v,
            }
        }
    }

    /// Lane-wise [`Strata::point`].
    #[inline(always)]
    pub(crate) fn point_x8<U: U32x8Lane>(&self, cell: U, bits: U) -> U::F {
        StrataX8::<U>::new([*self; 8]).point_x8(cell.to_f32(), bits)
    }
}

/// [`Strata`] with its own axis in every lane: lane `l` of
/// [`StrataX8::point_x8`] is [`Strata::point`] of `lanes[l]`, bit for bit. A
/// point-major flat buffer (`x₀ y₀ x₁ y₁ …`) mixes axes within one vector.
/// In the lanes of the level whose integer lanes are `U`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StrataX8<U: U32x8Lane> {
    m: U::F,
    m_hi: U::F,
    m_lo: U::F,
    inv32: U::F,
    /// `Strata::lo` and `Strata::hi`, as `i32` bits.
    lo: U,
    hi: U,
    /// Every lane's `lo` is 0 (`U ≥ 0` always holds).
    one_sided: bool,
}

/// `f32` lanes from eight values.
#[inline(always)]
pub(crate) fn f32_lanes<F: F32Lane>(a: [f32; 8]) -> F {
    <F as Lane>::load(&a)
}

impl<U: U32x8Lane> StrataX8<U> {
    #[inline(always)]
    pub(crate) fn new(lanes: [Strata; 8]) -> Self {
        Self {
            m: f32_lanes(lanes.map(|s| s.m)),
            m_hi: f32_lanes(lanes.map(|s| s.m_hi)),
            m_lo: f32_lanes(lanes.map(|s| s.m_lo)),
            inv32: f32_lanes(lanes.map(|s| s.inv32)),
            lo: U::from_array(lanes.map(|s| s.lo as u32)),
            hi: U::from_array(lanes.map(|s| s.hi as u32)),
            one_sided: lanes.iter().all(|s| s.lo == 0),
        }
    }

    /// Lane-wise [`Strata::point`], the cell given as an (exact) `f32`.
    #[inline(always)]
    pub(crate) fn point_x8(&self, c: U::F, bits: U) -> U::F {
        let (v, slow) = self.fast_x8(c, bits);
        if !slow.any() {
            return v;
        }
        self.fix_x8(v, c)
    }

    /// The fast value of [`StrataX8::point_x8`] and the mask of lanes that
    /// need [`StrataX8::fix_x8`] (for callers that test several vectors at once).
    #[inline(always)]
    pub(crate) fn fast_x8(&self, c: U::F, bits: U) -> (U::F, U) {
        let u = bits >> 8;
        let uf = u.to_f32() * <U::F as Lane>::splat(1.0 / 16_777_216.0);
        let v = (c + uf) * self.inv32;
        // Power-of-two strata have lo = 0 in every lane: one compare.
        let slow = if self.one_sided {
            u.gt_i32(self.hi)
        } else {
            u.lt_i32(self.lo) | u.gt_i32(self.hi)
        };
        (v, slow)
    }

    /// The exact test and the one-ulp moves of [`Strata::point`], in lanes (a
    /// lane that is inside stays put, so the fast lanes are unchanged).
    ///
    /// Always inlined, though it runs for few vectors: out of line, the AVX2
    /// copy would compile it for the baseline, with every intrinsic a call,
    /// and with many strata (`m = 2¹⁶`: a vector of 64 lanes needs it 40 % of
    /// the time) that made N-rooks 7× slower.
    #[inline(always)]
    pub(crate) fn fix_x8(&self, mut v: U::F, c: U::F) -> U::F {
        let one = U::splat(1);
        let zero = <U::F as Lane>::splat(0.0);
        loop {
            let p = v * self.m;
            let t = v * <U::F as Lane>::splat(SPLIT_F32);
            let vh = t - (t - v);
            let vl = v - vh;
            let e = ((vh * self.m_hi - p) + vh * self.m_lo + vl * self.m_hi) + vl * self.m_lo;
            let below = U::from_f32_mask(((p - c) + e).lt(zero));
            let above = U::from_f32_mask(zero.le((p - (c + <U::F as Lane>::splat(1.0))) + e));
            if !(below | above).any() {
                return v;
            }
            // below/above are all-ones masks: +1 ulp where below, −1 where above.
            let bits = U::from_f32_bits(v);
            v = (bits + (below & one) - (above & one)).to_f32_bits();
        }
    }
}

/// Stores one flat chunk of `K` vectors, lane-wise [`Strata::point`] of
/// `cells[v]` and `bits[v]` with the constants `sx[v]`, into `out` (`8K`
/// values). The exact fix runs only when a lane needs it
/// (lanes already inside their cell are left as they are).
#[inline(always)]
pub(crate) fn put_flat<U: U32x8Lane, const K: usize>(
    sx: &[StrataX8<U>; K],
    cells: &[U::F; K],
    bits: &[U; K],
    out: &mut [f32],
) {
    let mut slow = U::splat(0);
    for v in 0..K {
        let (x, sv) = sx[v].fast_x8(cells[v], bits[v]);
        x.store(&mut out[8 * v..8 * v + 8]);
        slow = slow | sv;
    }
    if slow.any() {
        fix_flat(sx, cells, out);
    }
}

/// The fix of [`put_flat`], inlined for the reason given at
/// [`StrataX8::fix_x8`].
#[inline(always)]
fn fix_flat<U: U32x8Lane, const K: usize>(
    sx: &[StrataX8<U>; K],
    cells: &[U::F; K],
    out: &mut [f32],
) {
    for (v, o) in out.chunks_exact_mut(8).enumerate() {
        let x = <U::F as Lane>::load(o);
        sx[v].fix_x8(x, cells[v]).store(o);
    }
}

/// Adds 8 to per-lane mixed-radix counters `cell` (digit `j` in `[0, m_j)`, digit 0
/// fastest), carrying between digits; the top digit wraps.
#[inline(always)]
pub(crate) fn advance8<U: U32x8Lane, const D: usize>(cell: &mut [U; D], m: &[U; D]) {
    let mut carry = U::splat(8);
    let zero = U::splat(0);
    for j in 0..D {
        let mut c = cell[j] + carry;
        carry = zero;
        loop {
            let over = c.ge(m[j]);
            if !over.any() {
                break;
            }
            c = c - (over & m[j]);
            carry = carry - over; // `over` is all ones (−1) where a digit wrapped
        }
        cell[j] = c;
        if !carry.ne(zero).any() {
            break;
        }
    }
}

/// Advances the mixed-radix counter `digits` by one (digit 0 fastest, digit `j` in
/// `[0, radix[j])`). Returns `false`, with every digit back at 0, when it wraps
/// past its last value.
#[inline(always)]
pub(crate) fn odometer_step<T, const D: usize>(digits: &mut [T; D], radix: &[T; D]) -> bool
where
    T: Copy + PartialOrd + core::ops::AddAssign + From<u8>,
{
    for j in 0..D {
        digits[j] += T::from(1);
        if digits[j] < radix[j] {
            return true;
        }
        digits[j] = T::from(0);
    }
    false
}

/// `[f(0), …, f(D−1)]`, always inlined (unlike `core::array::from_fn`, whose
/// closure call is not always inlined in hot loops).
#[inline(always)]
pub(crate) fn build<T: Copy, const D: usize>(init: T, mut f: impl FnMut(usize) -> T) -> [T; D] {
    let mut a = [init; D];
    for (j, x) in a.iter_mut().enumerate() {
        *x = f(j);
    }
    a
}

/// Transposes 8 per-point arrays into `D` lane vectors.
#[inline(always)]
pub(crate) fn lanes_of<U: U32x8Lane, const D: usize>(f: impl Fn(usize) -> [u32; D]) -> [U; D] {
    let pts: [[u32; D]; 8] = core::array::from_fn(f);
    core::array::from_fn(|j| U::from_array(core::array::from_fn(|l| pts[l][j])))
}

/// Largest per-axis stratum count [`Strata`] handles exactly (`f32` strata of
/// one ulp near 1).
pub(crate) const MAX_STRATA: u64 = 1 << 24;

/// Panics unless `dim < max`, in every build: the random-access sequences
/// ([`Sobol`], [`Halton`]) never repeat a dimension silently; their
/// `try_sample` returns an error instead.
#[inline(always)]
#[track_caller]
pub(crate) fn assert_sequence_dim(name: &str, dim: u32, max: u32) {
    assert!(
        dim < max,
        "{name}: dim = {dim} must be below {max} ({name}::try_sample returns an error instead)"
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::lane::Wu32x8;

    #[test]
    fn stratum_membership_at_the_edges() {
        for m in [
            1u32,
            2,
            3,
            7,
            10,
            1000,
            65_536,
            99_991,
            1 << 24,
            (1 << 24) - 3,
        ] {
            let (mf, strata) = (f64::from(m), Strata::new(m));
            for cell in [0, 1, m / 2, m.saturating_sub(2), m - 1] {
                if cell >= m {
                    continue;
                }
                for bits in [
                    0u32,
                    1,
                    2,
                    0x7FFF_FFFF,
                    0xFFFF_FFFE,
                    0xFFFF_FFFF,
                    0x8000_0000,
                ] {
                    let v = strata.point(cell, bits);
                    let t = f64::from(v) * mf;
                    assert!((0.0..1.0).contains(&v));
                    assert!(
                        t >= f64::from(cell) && t < f64::from(cell) + 1.0,
                        "m {m} cell {cell} bits {bits:#x}: {v}"
                    );
                }
            }
        }
    }

    #[test]
    fn strata_exact_path_over_random_cells() {
        // Random (m, cell, bits) across the whole range of m, with the SIMD lanes
        // against the scalar path and both against an exact f64 membership test
        // (v·m is exact in f64: 24 × 24 bits).
        let mut x = 0x1234_5678u32;
        let mut next = || {
            x = crate::rng::mix32(x.wrapping_add(0x9E37_79B9));
            x
        };
        for _ in 0..4000 {
            let m = match next() % 4 {
                0 => 1 + next() % 64,
                1 => 1 + next() % (1 << 16),
                2 => (1 << 20) + next() % (1 << 20),
                _ => (1 << 24) - next() % 1024,
            };
            let s = Strata::new(m);
            let cells: [u32; 8] = core::array::from_fn(|_| next() % m);
            let bits: [u32; 8] = core::array::from_fn(|_| next());
            let v8 = s
                .point_x8(
                    Wu32x8(wide::u32x8::new(cells)),
                    Wu32x8(wide::u32x8::new(bits)),
                )
                .to_array();
            for l in 0..8 {
                let v = s.point(cells[l], bits[l]);
                assert_eq!(v8[l].to_bits(), v.to_bits(), "m {m} lane {l}");
                let t = f64::from(v) * f64::from(m);
                assert!(
                    t >= f64::from(cells[l]) && t < f64::from(cells[l]) + 1.0 && v < 1.0,
                    "m {m} cell {} bits {:#x}: {v}",
                    cells[l],
                    bits[l]
                );
            }
        }
    }

    #[test]
    fn strata_fast_path_is_exact_and_lanes_agree() {
        for m in [
            1u32,
            2,
            3,
            7,
            64,
            1000,
            65_536,
            99_991,
            1 << 20,
            (1 << 21) - 1,
            1 << 21,
            1 << 22,
            1 << 24,
        ] {
            let s = Strata::new(m);
            let lo = (4 * m).min(1 << 23);
            // The power-of-two window ends at 2²⁴ − 2m.
            let hi2 = (1u32 << 24).saturating_sub(2 * m).max(1);
            let bits = [0u32, 1, 0xFFFF_FFFF, 0x8000_0000, 0x7FFF_FFFF];
            let edges = [
                lo.saturating_sub(1),
                lo,
                (1 << 24) - lo,
                ((1 << 24) - lo + 1).min((1 << 24) - 1),
                hi2,
                (hi2 + 1).min((1 << 24) - 1),
                hi2 - 1,
            ];
            let mut all: [u32; 19] = [0; 19];
            all[..5].copy_from_slice(&bits);
            for (k, e) in edges.iter().enumerate() {
                all[5 + 2 * k] = e << 8;
                all[6 + 2 * k] = (e << 8) | 0xFF;
            }
            for cell in [0, 1, m / 2, m.saturating_sub(2), m - 1] {
                if cell >= m {
                    continue;
                }
                for &b in &all {
                    let v = s.point(cell, b);
                    let t = f64::from(v) * f64::from(m);
                    assert!((0.0..1.0).contains(&v));
                    assert!(
                        t >= f64::from(cell) && t < f64::from(cell) + 1.0,
                        "m {m} cell {cell} bits {b:#x}: {v}"
                    );
                }
                for chunk in all.chunks(8) {
                    let mut b8 = [0u32; 8];
                    b8[..chunk.len()].copy_from_slice(chunk);
                    let v8 = s
                        .point_x8(
                            Wu32x8(wide::u32x8::splat(cell)),
                            Wu32x8(wide::u32x8::new(b8)),
                        )
                        .to_array();
                    for l in 0..8 {
                        assert_eq!(v8[l].to_bits(), s.point(cell, b8[l]).to_bits());
                    }
                }
            }
        }
    }

    #[test]
    fn unit_conversions_stay_below_one() {
        assert_eq!(unit_f32(u32::MAX), ONE_MINUS_EPSILON);
        assert!(unit_f64(u64::MAX) < 1.0);
        assert!(to_unit_f32(f64::from(ONE_MINUS_EPSILON) + (1.0 - 1e-17)) < 1.0);
        assert!(to_unit_f32(f64::from(ONE_MINUS_EPSILON)) < 1.0);
        assert!(to_unit_f32(0.5 + (0.5 - 1e-12)) < 1.0);
    }
}
