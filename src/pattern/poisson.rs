//! Poisson-disk sampling on the unit torus: [`PoissonDisk`], and exactly `N`
//! of its points as a pattern ([`PoissonDiskN`], `alloc` feature).

use super::{check_dims, odometer_step, unit_f32, ONE_MINUS_EPSILON};
use crate::error::PatternError;
use crate::hash::permute;
use crate::num::{frac, to_unit_f32, torus_dist};
use crate::rng::{Pcg32, Seed};

/// Seed purpose of Bridson's algorithm (`"POISSON\0"`).
const BRIDSON_PURPOSE: u64 = 0x504F_4953_534F_4E00;
/// Seed purpose of maximal dart throwing.
const DART_PURPOSE: u64 = 0x504F_4953_534F_4E01;
/// Seed purpose of the random subset chosen by [`PoissonDisk::generate_n`].
const SUBSET_PURPOSE: u64 = 0x504F_4953_534F_4E02;

/// Largest supported number of background-grid cells in 2D and 3D, `2²⁶`.
pub const POISSON_MAX_CELLS: u64 = 1 << 26;

/// Largest supported number of background-grid cells in 1D, `2²²`, so that
/// `r > 2⁻²²`: four times the spacing `2⁻²⁴` of the `f32` coordinates near 1.
/// A candidate at distance `≥ r` from a point then stays more than `r − 2⁻²⁵`
/// away after rounding to `f32`; at smaller radii candidates round onto the
/// points they start from (found: Bridson at `r = 1.5·10⁻⁸` stopped after one
/// point).
pub const POISSON_MAX_CELLS_1D: u64 = 1 << 22;

/// Default number of candidates per active point in Bridson's algorithm (`k = 30`,
/// Bridson 2007).
pub const BRIDSON_DEFAULT_CANDIDATES: u32 = 30;

/// Largest number of annulus candidates per active point accepted by
/// [`PoissonDisk::with_candidates`].
pub const BRIDSON_MAX_CANDIDATES: u32 = 1024;

/// Subdivision depth of the maximality pass: a grid cell is split down to boxes of
/// width `2⁻⁶` of the cell.
const FILL_DEPTH: u32 = 6;

/// Relative margin of the rejection test: a candidate is rejected when
/// `d² < r²·(1 + CONFLICT_MARGIN)`.
const CONFLICT_MARGIN: f64 = 1e-12;

/// Grid word marking an empty cell: not the bits of any `f32` in `[0, 1)`.
const EMPTY: u32 = u32::MAX;

/// Which Poisson-disk generator [`PoissonDisk`] runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PoissonMethod {
    /// Bridson (2007): `O(N)`, dense, not maximal.
    #[default]
    Bridson,
    /// Dart throwing (Dippé & Wold 1985; Cook 1986) finished to a maximal set.
    MaximalDartThrowing,
}

/// Poisson-disk sampler on the unit torus `[0, 1)^D`, `D = 1, 2, 3`.
///
/// A Poisson-disk set with radius `r` is a point set in which every two points are
/// at toroidal distance at least `r`:
/// `d(p, q)² = Σ_j min(|p_j − q_j|, 1 − |p_j − q_j|)²`.
/// Two generators share one background grid:
///
/// * **Bridson's algorithm**[^1] ([`PoissonMethod::Bridson`], the default): `O(N)`.
///   An active list holds points that may still have free space around them; for a
///   random active point up to `k` candidates are drawn uniformly (by volume) in the
///   annulus `r ≤ |x − p| < 2r`; the first candidate at distance `≥ r` from every
///   point is accepted and made active, and if all `k` fail the active point is
///   retired. The result is dense but in general **not maximal**.
/// * **Maximal dart throwing**[^3][^4] ([`PoissonMethod::MaximalDartThrowing`]):
///   uniform candidates, each rejected if closer than `r` to an accepted point
///   (random sequential adsorption), followed by an exhaustive pass that makes the
///   set maximal (every location of the torus is covered by a disk; see
///   [`PoissonDisk::coverage_slack`] for the precise statement).
///
/// **Grid.** `g = ⌊√D / r⌋ + 1` cells per axis, so a cell has width `1/g < r/√D`
/// and diagonal `√D/g < r`: a cell holds at most one point, and a point covers its
/// whole cell. Because `g` is an integer, the grid wraps exactly on the torus. A
/// point within distance `< r` of `x` lies at most `m = ⌊r·g⌋ + 1` cells away per
/// axis, so a query visits `(2m + 1)^D` cells (`m = 2` unless `r` is large: 25 cells
/// in 2D, 125 in 3D), or every cell of an axis when `2m + 1 ≥ g`.
///
/// **Exactness.** Points are stored as `f32` in `[0, 1)` and every distance test is
/// made on those stored values, in `f64`, against `r²·(1 + 10⁻¹²)`: the margin
/// exceeds the `f64` rounding error of the test, so every accepted pair is at
/// distance `≥ r` exactly (in real arithmetic on the `f32` coordinates).
///
/// **Memory.** No allocation: the caller passes `scratch` (`u32` words, at least
/// [`PoissonDisk::scratch_len`]: the grid plus a work list) and `out` (at least
/// [`PoissonDisk::max_points`]). Allocating conveniences sit behind the `alloc`
/// feature.
///
/// **Determinism.** All random numbers come from `seed.pcg(purpose)`, one stream
/// per method; the result is a pure function of the seed and the parameters.
/// Every loop is bounded (see [`PoissonDisk::generate`]).
///
/// Build it from a radius ([`PoissonDisk::with_radius`]) or from a target point
/// count and a relative radius ([`PoissonDisk::for_n`], Lagae & Dutré 2008[^2]).
/// The number of points is an outcome of the run: [`PoissonDisk::generate`]
/// returns it.
///
/// Large radii are allowed: the toroidal distance never exceeds `√D/2`, so for
/// `r > √D/2` every run returns exactly one point.
///
/// [^1]: R. Bridson, *Fast Poisson Disk Sampling in Arbitrary Dimensions*,
///   SIGGRAPH 2007 sketches.
/// [^2]: A. Lagae, P. Dutré, *A Comparison of Methods for Generating Poisson Disk
///   Distributions*, Computer Graphics Forum 27(1), 2008.
/// [^3]: R. L. Cook, *Stochastic Sampling in Computer Graphics*, ACM TOG 5(1), 1986.
/// [^4]: M. A. Z. Dippé, E. H. Wold, *Antialiasing through Stochastic Sampling*,
///   SIGGRAPH 1985.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoissonDisk<const D: usize> {
    radius: f64,
    g: usize,
    cells: usize,
    reach: usize,
    max_points: usize,
    candidates: u32,
    method: PoissonMethod,
    target: Option<usize>,
}

/// `r_max(N, d)`: the largest radius `N` points can have on the unit torus in the
/// densest packing (Lagae & Dutré 2008): `1/N` (d = 1), `√(2/(√3·N))` (hexagonal,
/// d = 2), `(√2/N)^{1/3}` (FCC, d = 3). Returns `NaN` for other `d`.
#[must_use]
pub fn poisson_max_radius(n: usize, dims: usize) -> f64 {
    let n = n as f64;
    match dims {
        1 => 1.0 / n,
        2 => crate::num::scalar::sqrt(2.0 / (crate::num::scalar::sqrt(3.0) * n)),
        3 => libm::cbrt(core::f64::consts::SQRT_2 / n),
        _ => f64::NAN,
    }
}

impl<const D: usize> PoissonDisk<D> {
    /// Sampler with minimum distance `radius`.
    ///
    /// # Errors
    /// [`PatternError::Dims`] unless `D ∈ 1..=3`; [`PatternError::Radius`] if
    /// `radius` is NaN, infinite or `≤ 0`; [`PatternError::GridTooLarge`] if the
    /// grid `g^D` (`g = ⌊√D/r⌋ + 1`) would exceed [`POISSON_MAX_CELLS`]
    /// ([`POISSON_MAX_CELLS_1D`] in 1D).
    pub fn with_radius(radius: f64) -> Result<Self, PatternError> {
        check_dims::<D>(1, 3)?;
        if !(radius.is_finite() && radius > 0.0) {
            return Err(PatternError::Radius);
        }
        let sd = crate::num::scalar::sqrt(D as f64);
        let gf = crate::num::scalar::floor(sd / radius) + 1.0;
        let cells_f = libm::pow(gf, D as f64);
        let max_cells = if D == 1 {
            POISSON_MAX_CELLS_1D
        } else {
            POISSON_MAX_CELLS
        };
        if cells_f > max_cells as f64 {
            let cells = if cells_f >= u64::MAX as f64 {
                u64::MAX
            } else {
                cells_f as u64
            };
            return Err(PatternError::GridTooLarge {
                cells,
                max: max_cells,
            });
        }
        let g = gf as usize;
        let cells = g.pow(D as u32);
        // Capped at g: beyond that the search covers every cell of an axis anyway.
        let reach = if radius * gf >= gf {
            g
        } else {
            crate::num::scalar::floor(radius * gf) as usize + 1
        };
        // Disks of radius r/2 around the points are disjoint, and for r ≤ 1 such a
        // disk embeds in the unit torus: N·V_D(r/2) ≤ 1.
        let packing = if radius <= 1.0 {
            let h = radius / 2.0;
            let vol = match D {
                1 => 2.0 * h,
                2 => core::f64::consts::PI * h * h,
                _ => 4.0 / 3.0 * core::f64::consts::PI * h * h * h,
            };
            let b = crate::num::scalar::floor(1.0 / vol) + 1.0;
            if b < cells as f64 {
                b as usize
            } else {
                cells
            }
        } else {
            cells
        };
        Ok(Self {
            radius,
            g,
            cells,
            reach,
            max_points: packing.clamp(1, cells),
            candidates: BRIDSON_DEFAULT_CANDIDATES,
            method: PoissonMethod::Bridson,
            target: None,
        })
    }

    /// Sampler for about `n` points: `r = relative_radius · r_max(n, D)` with the
    /// densest-packing radius ([`poisson_max_radius`])
    ///
    /// * `D = 1`: `r_max = 1/N`;
    /// * `D = 2`: `r_max = √(2/(√3·N))` (hexagonal packing);
    /// * `D = 3`: `r_max = (√2/N)^{1/3}` (face-centred cubic packing),
    ///
    /// the relative radius of Lagae & Dutré (2008), who recommend about `0.75`.
    /// How many points a run produces depends on the method: at `0.75` in 2D,
    /// maximal dart throwing gives about `1.07·N` (measured `1.06–1.08·N` at
    /// `N = 1024`), Bridson about `0.95·N` (measured `0.94–0.98·N`), so Bridson
    /// usually falls short of `N` there. Use
    /// [`PoissonDisk::generate_n`] to get exactly `n` (or a
    /// [`PatternError::Shortfall`]).
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`] if `n = 0`; [`PatternError::RelativeRadius`] if
    /// `relative_radius` is NaN or outside `(0, 1]`; as [`PoissonDisk::with_radius`].
    pub fn for_n(n: usize, relative_radius: f64) -> Result<Self, PatternError> {
        check_dims::<D>(1, 3)?;
        if n == 0 {
            return Err(PatternError::ZeroPoints);
        }
        if !(relative_radius > 0.0 && relative_radius <= 1.0) {
            return Err(PatternError::RelativeRadius);
        }
        let mut s = Self::with_radius(relative_radius * poisson_max_radius(n, D))?;
        s.target = Some(n);
        Ok(s)
    }

    /// The same sampler running `method`.
    #[must_use]
    pub fn with_method(mut self, method: PoissonMethod) -> Self {
        self.method = method;
        self
    }

    /// The same sampler with `k = candidates` annulus candidates per active point
    /// (Bridson only; default [`BRIDSON_DEFAULT_CANDIDATES`]).
    ///
    /// # Errors
    /// [`PatternError::Candidates`] unless `1 ≤ candidates ≤`
    /// [`BRIDSON_MAX_CANDIDATES`] (which bounds the work per active point).
    pub fn with_candidates(mut self, candidates: u32) -> Result<Self, PatternError> {
        if candidates == 0 || candidates > BRIDSON_MAX_CANDIDATES {
            return Err(PatternError::Candidates {
                max: BRIDSON_MAX_CANDIDATES,
            });
        }
        self.candidates = candidates;
        Ok(self)
    }

    /// The minimum distance `r`.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The `n` given to [`PoissonDisk::for_n`], if any.
    #[must_use]
    pub fn target(&self) -> Option<usize> {
        self.target
    }

    /// The generator this sampler runs.
    #[must_use]
    pub fn method(&self) -> PoissonMethod {
        self.method
    }

    /// `g = ⌊√D/r⌋ + 1`, grid cells per axis.
    #[must_use]
    pub fn grid_resolution(&self) -> usize {
        self.g
    }

    /// An upper bound on the number of points of any run, and the length `out`
    /// needs: `min(g^D, ⌊1/V_D(r/2)⌋ + 1)` (one point per cell; and disjoint disks
    /// of radius `r/2`, volume `V_D(r/2)`, on the unit torus when `r ≤ 1`).
    #[must_use]
    pub fn max_points(&self) -> usize {
        self.max_points
    }

    /// Length of the `scratch` buffer ([`u32`] words): `D·g^D` for the grid (each
    /// cell holds the `f32` bits of its point, if any) plus a work list of
    /// [`PoissonDisk::max_points`] entries (Bridson's active list).
    #[must_use]
    pub fn scratch_len(&self) -> usize {
        D * self.cells + self.max_points
    }

    /// Maximality slack `ε` of [`PoissonMethod::MaximalDartThrowing`]: every
    /// location `x` of the torus is within toroidal distance `< r + ε` of a point
    /// of the set, with `ε = √D·(w + 2⁻²³)` and `w = 1/(g·2⁶)` the smallest box of
    /// the maximality pass (so `ε < r/64 + √D·2⁻²³`).
    ///
    /// Proof sketch: a location in an occupied cell is within the cell diagonal
    /// `√D/g < r` of the cell's point. Each empty cell is split recursively into
    /// boxes; a box is dropped only when one disk contains it entirely, and
    /// otherwise a candidate drawn in it (moved by at most one `f32` ulp) is
    /// accepted if it conflicts with no point, which ends the cell. At the deepest
    /// level a rejected candidate `c` lies within `r` of a point `q`, so every `x`
    /// of its box satisfies `d(x, q) < r + √D·(w + 2⁻²⁴)`. Points added later only
    /// add coverage.
    ///
    /// The bound needs an `f32` inside every grid cell, which holds while the cell
    /// width `1/g` exceeds the `f32` spacing `2⁻²⁴` near 1, i.e. always except
    /// `D = 1` with `r < 2⁻²⁴` (about `6·10⁻⁸`).
    #[must_use]
    pub fn coverage_slack(&self) -> f64 {
        let w = 1.0 / (self.g as f64 * f64::from(1u32 << FILL_DEPTH));
        crate::num::scalar::sqrt(D as f64) * (w + 1.0 / 8_388_608.0)
    }

    /// Runs the generator: writes the points to `out[..count]` and returns `count`.
    ///
    /// [`PoissonMethod::Bridson`]: starts from one uniform point; every pick of an
    /// active point either adds a point or retires one, so there are at most
    /// `2·max_points` picks of at most `k` candidates each. [`PoissonMethod::MaximalDartThrowing`]:
    /// `4·g^D` uniform darts, then one pass over the empty cells in a random
    /// order, each split into at most `Σ_{l≤6} 2^{lD}` boxes. Both end.
    ///
    /// `scratch` is overwritten; its contents on entry do not matter.
    ///
    /// # Errors
    /// [`PatternError::Scratch`] if `scratch.len() < scratch_len()`,
    /// [`PatternError::OutputLength`] if `out.len() < max_points()`.
    pub fn generate(
        &self,
        seed: Seed,
        scratch: &mut [u32],
        out: &mut [[f32; D]],
    ) -> Result<usize, PatternError> {
        self.generate_impl(seed, scratch, out, true)
    }

    /// [`PoissonDisk::generate`]; `fast = false` forces the generic neighbour scan
    /// (for the test that both scans give the same points).
    fn generate_impl(
        &self,
        seed: Seed,
        scratch: &mut [u32],
        out: &mut [[f32; D]],
        fast: bool,
    ) -> Result<usize, PatternError> {
        if scratch.len() < self.scratch_len() {
            return Err(PatternError::Scratch {
                expected: self.scratch_len(),
                got: scratch.len(),
            });
        }
        if out.len() < self.max_points {
            return Err(PatternError::OutputLength {
                expected: self.max_points,
                got: out.len(),
            });
        }
        let (grid, list) = scratch.split_at_mut(D * self.cells);
        grid.fill(EMPTY);
        let r2_hi = self.radius * self.radius * (1.0 + CONFLICT_MARGIN);
        let (near, mut near_len) = near_offsets::<D>(self.g, self.reach, r2_hi);
        if !fast {
            near_len = 0;
        }
        let mut st = State {
            p: self,
            grid,
            pts: out,
            n: 0,
            r2_hi,
            r2_lo: self.radius * self.radius * (1.0 - CONFLICT_MARGIN),
            gf: self.g as f64,
            near,
            near_len,
        };
        match self.method {
            PoissonMethod::Bridson => st.bridson(seed.pcg(BRIDSON_PURPOSE), list),
            PoissonMethod::MaximalDartThrowing => st.darts(seed.pcg(DART_PURPOSE)),
        }
        Ok(st.n)
    }

    /// Exactly `n` points in `out[..n]`: a run of [`PoissonDisk::generate`]
    /// followed by a uniformly random subset of size `n` of its points (a subset of
    /// a Poisson-disk set is one; the subset is random so that it stays spatially
    /// homogeneous, which the first `n` of a Bridson run are not).
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`] if `n = 0`; [`PatternError::Shortfall`] if the
    /// run produced fewer than `n` points (`out[..got]` then holds all of them);
    /// as [`PoissonDisk::generate`].
    pub fn generate_n(
        &self,
        n: usize,
        seed: Seed,
        scratch: &mut [u32],
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        if n == 0 {
            return Err(PatternError::ZeroPoints);
        }
        let got = self.generate(seed, scratch, out)?;
        if got < n {
            return Err(PatternError::Shortfall {
                got: got as u64,
                wanted: n as u64,
            });
        }
        // Partial Fisher–Yates: out[..n] becomes a uniform random n-subset.
        let mut rng = seed.pcg(SUBSET_PURPOSE);
        for i in 0..n {
            let j = i + below(&mut rng, (got - i) as u32) as usize;
            out.swap(i, j);
        }
        Ok(())
    }

    /// Allocating convenience: [`PoissonDisk::generate`] into a new `Vec` of the
    /// generated points.
    ///
    /// # Errors
    /// As [`PoissonDisk::generate`] (never, with the buffers it allocates).
    #[cfg(feature = "alloc")]
    pub fn generate_vec(&self, seed: Seed) -> Result<alloc::vec::Vec<[f32; D]>, PatternError> {
        let mut scratch = alloc::vec![0u32; self.scratch_len()];
        let mut out = alloc::vec![[0.0f32; D]; self.max_points];
        let n = self.generate(seed, &mut scratch, &mut out)?;
        out.truncate(n);
        Ok(out)
    }

    /// Allocating convenience: [`PoissonDisk::generate_n`] into a new `Vec` of `n`
    /// points.
    ///
    /// # Errors
    /// As [`PoissonDisk::generate_n`].
    #[cfg(feature = "alloc")]
    pub fn generate_n_vec(
        &self,
        n: usize,
        seed: Seed,
    ) -> Result<alloc::vec::Vec<[f32; D]>, PatternError> {
        let mut scratch = alloc::vec![0u32; self.scratch_len()];
        let mut out = alloc::vec![[0.0f32; D]; self.max_points.max(n)];
        self.generate_n(n, seed, &mut scratch, &mut out)?;
        out.truncate(n);
        Ok(out)
    }
}

/// Exactly `n` points of a Poisson-disk set as a [`super::Pattern`]: for a
/// seed, the `n` points of [`PoissonDisk::generate_n_vec`] (a run of the disk
/// sampler followed by a uniformly random subset of `n` of its points), bit for
/// bit. Fewer than `n` points fitting in a run is an error
/// ([`PatternError::Shortfall`]) that says so. With the `alloc` feature.
///
/// **Every fill generates the whole set and allocates** (the disk sampler's
/// grid, its output and the subset): a Poisson-disk set is produced by one
/// sequential run whose every point depends on the points before it, and the
/// random subset is drawn from all of them, so point `i` cannot be computed on
/// its own (no random access) and a fill of any range costs a full run. Use it
/// where a `Pattern` is needed (estimators, spectra over realisations), not on
/// a hot path that fills small ranges; fill all `n` points at once.
#[cfg(feature = "alloc")]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoissonDiskN<const D: usize> {
    disk: PoissonDisk<D>,
    n: usize,
}

#[cfg(feature = "alloc")]
impl<const D: usize> PoissonDiskN<D> {
    /// `n` points of the Poisson-disk sets of `disk`.
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`] if `n = 0`; [`PatternError::TooManyPoints`]
    /// if `n` exceeds [`PoissonDisk::max_points`] (no run can give that many).
    pub fn new(disk: PoissonDisk<D>, n: usize) -> Result<Self, PatternError> {
        super::check_n(n, disk.max_points() as u64)?;
        Ok(PoissonDiskN { disk, n })
    }

    /// The disk sampler.
    #[must_use]
    pub fn disk(&self) -> &PoissonDisk<D> {
        &self.disk
    }

    /// `N`, the number of points.
    #[must_use]
    pub fn n(&self) -> usize {
        self.n
    }

    /// Points `first .. first + len` of the set for `seed` (generates all of it).
    fn points(
        &self,
        seed: Seed,
        first: usize,
        len: usize,
    ) -> Result<alloc::vec::Vec<[f32; D]>, PatternError> {
        super::check_range(self.n as u64, first, len)?;
        let mut all = self.disk.generate_n_vec(self.n, seed)?;
        all.truncate(first + len);
        all.drain(..first);
        Ok(all)
    }
}

#[cfg(feature = "alloc")]
impl<const D: usize> super::Pattern<D> for PoissonDiskN<D> {
    fn len(&self) -> usize {
        self.n
    }

    /// Generates the whole set (allocates) and copies the range.
    fn fill_range(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        out.copy_from_slice(&self.points(seed, first, out.len())?);
        Ok(())
    }

    /// As [`super::Pattern::fill_range`] (the run has no separate scalar path).
    fn fill_range_scalar(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        self.fill_range(seed, first, out)
    }

    /// Generates the whole set (allocates) and scatters the range.
    fn fill_range_soa(
        &self,
        seed: Seed,
        first: usize,
        out: [&mut [f32]; D],
    ) -> Result<(), PatternError> {
        let len = super::soa_len(&out)?;
        let pts = self.points(seed, first, len)?;
        for (j, col) in out.into_iter().enumerate() {
            for (x, p) in col.iter_mut().zip(&pts) {
                *x = p[j];
            }
        }
        Ok(())
    }
}

/// Uniform integer in `[0, n)` (`n ≥ 1`), Lemire's multiply-shift (bias `< n/2³²`).
#[inline(always)]
fn below(rng: &mut Pcg32, n: u32) -> u32 {
    ((u64::from(rng.next_u32()) * u64::from(n)) >> 32) as u32
}

/// Uniform `f64` in `[0, 1)` with 32 random bits.
#[inline(always)]
fn unit_f64_32(rng: &mut Pcg32) -> f64 {
    f64::from(rng.next_u32()) * (1.0 / 4_294_967_296.0)
}

/// The neighbour cells of the common case `reach = 2`, `g ≥ 6`: offsets
/// `o ∈ {−2 … 2}^D` (stored as `o + 2`) whose cells can hold a point within `r`
/// (per-axis gap `max(|o_j| − 1, 0)/g`; with `g ≥ 6` the toroidal gap is the same),
/// nearest first so that a rejected candidate is usually rejected early. The order
/// changes only the speed: the test is a pure "any point within `r`".
/// Returns length 0 for other cases (the generic odometer is used then).
fn near_offsets<const D: usize>(g: usize, reach: usize, r2: f64) -> ([[u8; 3]; 125], usize) {
    let mut list = [[0u8; 3]; 125];
    let mut key = [0u32; 125];
    let mut len = 0;
    if reach != 2 || g < 6 {
        return (list, 0);
    }
    let w = 1.0 / g as f64;
    let total = 5usize.pow(D as u32);
    for t in 0..total {
        let mut rest = t;
        let mut o = [2u8; 3];
        let (mut gap2, mut l1) = (0.0f64, 0u32);
        for oj in o.iter_mut().take(D) {
            *oj = (rest % 5) as u8;
            rest /= 5;
            let a = (i32::from(*oj) - 2).unsigned_abs();
            let gap = f64::from(a.saturating_sub(1)) * w;
            gap2 += gap * gap;
            l1 += a * a;
        }
        if gap2 >= r2 {
            continue;
        }
        // insertion sort by (|o|², t)
        let k = l1;
        let mut i = len;
        while i > 0 && key[i - 1] > k {
            list[i] = list[i - 1];
            key[i] = key[i - 1];
            i -= 1;
        }
        list[i] = o;
        key[i] = k;
        len += 1;
    }
    (list, len)
}

/// Working state of one run.
struct State<'a, const D: usize> {
    p: &'a PoissonDisk<D>,
    /// Cell `i` → the `f32` bits of its point in words `D·i .. D·i + D`
    /// ([`EMPTY`] in word `D·i`: no point). Storing the coordinates (not an index)
    /// saves one dependent random memory access per visited cell.
    grid: &'a mut [u32],
    pts: &'a mut [[f32; D]],
    n: usize,
    /// Rejection threshold `r²(1 + 10⁻¹²)`.
    r2_hi: f64,
    /// Containment threshold `r²(1 − 10⁻¹²)`.
    r2_lo: f64,
    gf: f64,
    /// Neighbour offsets, nearest first ([`near_offsets`]); `near_len = 0`: odometer.
    near: [[u8; 3]; 125],
    near_len: usize,
}

impl<const D: usize> State<'_, D> {
    /// Cell of a stored coordinate (`x·g` is exact in `f64`).
    #[inline(always)]
    fn cell(&self, x: &[f32; D]) -> [usize; D] {
        core::array::from_fn(|j| ((f64::from(x[j]) * self.gf) as usize).min(self.p.g - 1))
    }

    /// The point stored in cell `idx`, if any.
    #[inline(always)]
    fn at(&self, idx: usize) -> Option<[f32; D]> {
        let w = &self.grid[D * idx..D * idx + D];
        if w[0] == EMPTY {
            None
        } else {
            Some(core::array::from_fn(|j| f32::from_bits(w[j])))
        }
    }

    #[inline(always)]
    fn index(&self, c: &[usize; D]) -> usize {
        let g = self.p.g;
        let mut i = 0;
        for j in (0..D).rev() {
            i = i * g + c[j];
        }
        i
    }

    /// Calls `f` on every point within `reach` cells of cell `c` (each cell once);
    /// stops and returns `true` as soon as `f` does.
    #[inline(always)]
    fn any_near(&self, c: &[usize; D], mut f: impl FnMut(&[f32; D]) -> bool) -> bool {
        let g = self.p.g;
        if self.near_len > 0 {
            // wrapped cell coordinates c_j − 2 … c_j + 2, times the axis stride
            let mut axis = [[0usize; 5]; D];
            let mut stride = 1;
            for j in 0..D {
                for (t, a) in axis[j].iter_mut().enumerate() {
                    // c_j + t − 2 ∈ [−2, g + 1]: one wrap either way.
                    let mut k = c[j] + t + g - 2;
                    if k >= g {
                        k -= g;
                    }
                    if k >= g {
                        k -= g;
                    }
                    *a = k * stride;
                }
                stride *= g;
            }
            for o in &self.near[..self.near_len] {
                let mut idx = 0;
                for j in 0..D {
                    idx += axis[j][o[j] as usize];
                }
                if let Some(q) = self.at(idx) {
                    if f(&q) {
                        return true;
                    }
                }
            }
            return false;
        }
        let span = (2 * self.p.reach + 1).min(g);
        let start: [usize; D] = core::array::from_fn(|j| {
            if span == g {
                0
            } else {
                (c[j] + g - self.p.reach) % g
            }
        });
        let mut t = [0usize; D];
        loop {
            let mut idx = 0;
            for j in (0..D).rev() {
                let mut k = start[j] + t[j];
                if k >= g {
                    k -= g;
                }
                idx = idx * g + k;
            }
            if let Some(q) = self.at(idx) {
                if f(&q) {
                    return true;
                }
            }
            if !odometer_step(&mut t, &[span; D]) {
                return false;
            }
        }
    }

    /// `true` if `x` (in cell `c`) may not be added: its cell is taken or a point
    /// lies within distance `r` (with margin).
    #[inline(always)]
    fn conflicts(&self, x: &[f32; D], c: &[usize; D]) -> bool {
        if self.grid[D * self.index(c)] != EMPTY {
            return true;
        }
        let r2 = self.r2_hi;
        let xf: [f64; D] = core::array::from_fn(|j| f64::from(x[j]));
        self.any_near(c, |q| {
            let mut s = 0.0;
            for j in 0..D {
                let d = torus_dist(xf[j], f64::from(q[j]));
                s += d * d;
            }
            s < r2
        })
    }

    #[inline(always)]
    fn add(&mut self, x: [f32; D], c: &[usize; D]) -> usize {
        let i = self.n;
        self.pts[i] = x;
        let ci = self.index(c);
        for j in 0..D {
            self.grid[D * ci + j] = x[j].to_bits();
        }
        self.n += 1;
        i
    }

    /// Tries to add `x`; returns whether it was added. Never exceeds `max_points`
    /// (which the packing bound guarantees anyway).
    #[inline(always)]
    fn try_add(&mut self, x: [f32; D]) -> Option<usize> {
        let c = self.cell(&x);
        if self.n < self.p.max_points && !self.conflicts(&x, &c) {
            Some(self.add(x, &c))
        } else {
            None
        }
    }

    fn uniform(rng: &mut Pcg32) -> [f32; D] {
        core::array::from_fn(|_| unit_f32(rng.next_u32()))
    }

    /// A point uniform (by volume) in the annulus `r ≤ |y − p| < 2r`, wrapped.
    #[inline(always)]
    fn annulus(&self, rng: &mut Pcg32, p: &[f32; D]) -> [f32; D] {
        let r = self.p.radius;
        if D > 1 {
            // Rejection from the cube [−2r, 2r]^D: uniform in the annulus, accepted
            // with probability 3π/16 ≈ 0.59 (2D), 7π/48 ≈ 0.46 (3D). At most 32
            // tries (all fail with probability < 10⁻¹⁰), then the inverse-CDF path.
            let (r2, r2x4) = (r * r, 4.0 * r * r);
            for _ in 0..32 {
                let v: [f64; D] = core::array::from_fn(|_| r * (4.0 * unit_f64_32(rng) - 2.0));
                let s: f64 = v.iter().map(|x| x * x).sum();
                if s >= r2 && s < r2x4 {
                    return core::array::from_fn(|j| to_unit_f32(f64::from(p[j]) + v[j]));
                }
            }
        }
        let u = unit_f64_32(rng);
        let mut off = [0.0f64; D];
        match D {
            1 => {
                let rho = r * (1.0 + u);
                off[0] = if rng.next_u32() & 1 == 0 { rho } else { -rho };
            }
            2 => {
                // P(|y − p| < ρ) = (ρ² − r²)/(3r²)
                let rho = r * crate::num::scalar::sqrt(1.0 + 3.0 * u);
                let (s, c) = libm::sincos(core::f64::consts::TAU * unit_f64_32(rng));
                off[0] = rho * c;
                off[1] = rho * s;
            }
            _ => {
                // P(|y − p| < ρ) = (ρ³ − r³)/(7r³); direction uniform on the sphere
                // (Archimedes: z uniform in [−1, 1]).
                let rho = r * libm::cbrt(1.0 + 7.0 * u);
                let z = 1.0 - 2.0 * unit_f64_32(rng);
                let h = crate::num::scalar::sqrt((1.0 - z * z).max(0.0));
                let (s, c) = libm::sincos(core::f64::consts::TAU * unit_f64_32(rng));
                off[0] = rho * h * c;
                off[1] = rho * h * s;
                off[2] = rho * z;
            }
        }
        core::array::from_fn(|j| to_unit_f32(f64::from(p[j]) + off[j]))
    }

    /// Bridson (2007) on the torus; `active` holds indices of active points.
    fn bridson(&mut self, mut rng: Pcg32, active: &mut [u32]) {
        let first = Self::uniform(&mut rng);
        let Some(i0) = self.try_add(first) else {
            return;
        };
        active[0] = i0 as u32;
        let mut len = 1usize;
        let k = self.p.candidates;
        // The set cannot grow past max_points (e.g. one point when r > √D/2).
        while len > 0 && self.n < self.p.max_points {
            let a = below(&mut rng, len as u32) as usize;
            let p = self.pts[active[a] as usize];
            let mut found = false;
            for _ in 0..k {
                let y = self.annulus(&mut rng, &p);
                if let Some(i) = self.try_add(y) {
                    active[len] = i as u32;
                    len += 1;
                    found = true;
                    break;
                }
            }
            if !found {
                len -= 1;
                active[a] = active[len];
            }
        }
    }

    /// Dart throwing, then the maximality pass.
    fn darts(&mut self, mut rng: Pcg32) {
        let cells = self.p.cells;
        for _ in 0..4 * cells {
            let x = Self::uniform(&mut rng);
            self.try_add(x);
        }
        // Empty cells in a random order (a keyed bijection of [0, cells)).
        let key = rng.next_u32();
        for i in 0..cells {
            let ci = permute(i as u32, cells as u32, key) as usize;
            if self.grid[D * ci] == EMPTY {
                self.fill_cell(&mut rng, ci);
            }
        }
    }

    /// Finds an uncovered location in the empty cell `ci` and adds a point there,
    /// or proves (up to [`PoissonDisk::coverage_slack`]) that there is none.
    fn fill_cell(&mut self, rng: &mut Pcg32, ci: usize) {
        let g = self.p.g;
        let mut c = [0usize; D];
        let mut rest = ci;
        for cj in c.iter_mut() {
            *cj = rest % g;
            rest /= g;
        }
        // Depth-first stack of boxes: (integer corner at its level, level).
        const STACK: usize = 8 * (FILL_DEPTH as usize + 1);
        let mut stack = [([0u32; D], 0u32); STACK];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let (b, level) = stack[top];
            let w = 1.0 / (self.gf * f64::from(1u32 << level));
            let lo: [f64; D] =
                core::array::from_fn(|j| c[j] as f64 / self.gf + f64::from(b[j]) * w);
            if self.box_covered(&c, &lo, w) {
                continue;
            }
            let x = self.candidate_in(rng, &c, &lo, w);
            if let Some(x) = x {
                if !self.conflicts(&x, &c) && self.n < self.p.max_points {
                    self.add(x, &c);
                    return;
                }
            }
            if level < FILL_DEPTH {
                for child in 0..(1u32 << D) {
                    let nb: [u32; D] = core::array::from_fn(|j| 2 * b[j] + ((child >> j) & 1));
                    stack[top] = (nb, level + 1);
                    top += 1;
                }
            }
        }
    }

    /// `true` if one disk contains the box `[lo, lo + w]^D` entirely.
    fn box_covered(&self, c: &[usize; D], lo: &[f64; D], w: f64) -> bool {
        let r2 = self.r2_lo;
        self.any_near(c, |q| {
            let mut s = 0.0;
            for j in 0..D {
                let qj = f64::from(q[j]);
                // Farthest toroidal distance from qj to [lo, lo + w]: 1/2 if the
                // antipode of qj lies in the interval, else the farther end.
                let mut anti = qj + 0.5;
                if anti >= 1.0 {
                    anti -= 1.0;
                }
                let d = if (anti >= lo[j] && anti <= lo[j] + w)
                    || (anti + 1.0 >= lo[j] && anti + 1.0 <= lo[j] + w)
                {
                    0.5
                } else {
                    torus_dist(qj, lo[j]).max(torus_dist(qj, frac(lo[j] + w)))
                };
                s += d * d;
                if s >= r2 {
                    return false;
                }
            }
            true
        })
    }

    /// A uniform candidate in the box, rounded to `f32` and moved by at most one ulp
    /// back into cell `c`; `None` if no `f32` of the cell is that close.
    fn candidate_in(
        &self,
        rng: &mut Pcg32,
        c: &[usize; D],
        lo: &[f64; D],
        w: f64,
    ) -> Option<[f32; D]> {
        let mut x = [0.0f32; D];
        for j in 0..D {
            let mut v = ((lo[j] + w * unit_f64_32(rng)) as f32).min(ONE_MINUS_EPSILON);
            let cell = |v: f32| crate::num::scalar::floor(f64::from(v) * self.gf);
            let cj = c[j] as f64;
            if cell(v) > cj {
                v = f32::from_bits(v.to_bits() - 1);
            } else if cell(v) < cj {
                v = f32::from_bits(v.to_bits() + 1);
            }
            if cell(v) != cj {
                return None;
            }
            x[j] = v;
        }
        Some(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sorted neighbour list (fast path) and the generic odometer scan decide
    /// the same predicate, so they give the same points.
    fn same<const D: usize>(r: f64, method: PoissonMethod) {
        let p = PoissonDisk::<D>::with_radius(r)
            .unwrap()
            .with_method(method);
        let mut scratch = [0u32; 1 << 16];
        let mut a = [[0.0f32; D]; 4096];
        let mut b = [[0.0f32; D]; 4096];
        for seed in 0..3 {
            let na = p
                .generate_impl(Seed::new(seed), &mut scratch, &mut a, true)
                .unwrap();
            let nb = p
                .generate_impl(Seed::new(seed), &mut scratch, &mut b, false)
                .unwrap();
            assert_eq!(na, nb);
            assert_eq!(a[..na], b[..nb]);
        }
    }

    #[test]
    fn fast_neighbour_scan_matches_generic() {
        for m in [PoissonMethod::Bridson, PoissonMethod::MaximalDartThrowing] {
            same::<1>(0.01, m);
            same::<2>(0.04, m);
            same::<3>(0.12, m);
        }
        let (_, len) = near_offsets::<2>(100, 2, 1e-4);
        assert!(len > 0);
    }
}
