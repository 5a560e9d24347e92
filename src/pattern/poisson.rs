//! Poisson-disk sampling on the unit torus: [`PoissonDisk`], and exactly `N`
//! of its points as a pattern ([`PoissonDiskN`], `alloc` feature).

use super::{check_dims, odometer_step, unit_f32, ONE_MINUS_EPSILON};
use crate::error::PatternError;
use crate::num::{frac, to_unit_f32, torus_dist};
use crate::rng::{Pcg32, Seed};

/// Seed purpose of Bridson's algorithm (`"POISSON\0"`).
const BRIDSON_PURPOSE: u64 = 0x504F_4953_534F_4E00;
/// Seed purpose of maximal dart throwing.
const DART_PURPOSE: u64 = 0x504F_4953_534F_4E01;
/// Stream of the boxes darts are thrown into (separate from the dart
/// positions, so that a batch of boxes can be drawn ahead).
const PICK_PURPOSE: u64 = 0x504F_4953_534F_4E03;
/// Boxes drawn ahead per batch in active-box dart throwing.
const BATCH: usize = 32;
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

/// Bits per axis of a packed sub-box corner (levels up to [`FILL_DEPTH`] `≤ 10`).
const SUB_BITS: u32 = 10;
/// Mask of one axis of a packed sub-box corner.
const SUB_MASK: u32 = (1 << SUB_BITS) - 1;
/// Darts per active box and level before refining: `DART_NUM / DART_DEN`
/// (measured: `1` is as fast as `1/2` or `1/4` in 2D and 3D at `N ≈ 65536`).
const DART_NUM: u64 = 1;
/// Denominator of the dart budget per box (see [`DART_NUM`]).
const DART_DEN: u64 = 1;
/// Rounds of `State::clean` at one level before the bounded fallback.
const MAX_ROUNDS: u32 = 16;

/// Relative margin of the rejection test: a candidate is rejected when
/// `d² < r²·(1 + CONFLICT_MARGIN)`.
const CONFLICT_MARGIN: f64 = 1e-12;

/// Grid word marking an empty cell: not the bits of any `f32` in `[0, 1)`.
const EMPTY: u32 = u32::MAX;

/// Cell word of a removed (tombstoned) active box: not a packed cell (`g <
/// 2^{32/D} − 1`).
const DEAD: u32 = u32::MAX;

/// Level of the coverage masks: each grid cell keeps one bit per sub-box of
/// width `1/(g·2^MASK_LEVEL)`, `4^D ≤ 64` bits.
const MASK_LEVEL: u32 = 2;

/// Which Poisson-disk generator [`PoissonDisk`] runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PoissonMethod {
    /// Bridson (2007): `O(N)`, dense, not maximal.
    #[default]
    Bridson,
    /// Maximal Poisson-disk sampling: dart throwing (Dippé & Wold 1985; Cook
    /// 1986) run until the torus is covered, with darts drawn only in
    /// still-active boxes of the grid (Ebeida et al. 2011, 2012), so the
    /// accepted points are exactly those of plain dart throwing.
    MaximalDartThrowing,
}

/// How [`PoissonDisk::generate_n`] (and [`PoissonDiskN`]) produce exactly `N`
/// points.
///
/// References: B. Widom, *Random Sequential Addition of Hard Spheres to a
/// Volume*, J. Chem. Phys. 44 (1966); J. Feder, *Random Sequential Adsorption*,
/// J. Theor. Biol. 87 (1980); A. Lagae, P. Dutré, *A Comparison of Methods for
/// Generating Poisson Disk Distributions*, Computer Graphics Forum 27(1), 2008;
/// M. S. Ebeida et al., *Efficient Maximal Poisson-Disk Sampling*, SIGGRAPH 2011.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PoissonN {
    /// Sequential dart throwing (random sequential adsorption; Widom 1966,
    /// Feder 1980; Lagae & Dutré 2008) **stopped at exactly `N` accepted
    /// points**: each accepted point is uniform over the region not yet covered
    /// by the disks of radius `r` around the earlier ones. The darts are drawn
    /// only in still-active boxes of the background grid (Ebeida et al. 2011),
    /// which keeps this exact and fast near saturation. The points are in
    /// acceptance order, so a prefix of the set is itself the process stopped
    /// earlier, and the set is the first `N` points of the
    /// [`PoissonMethod::MaximalDartThrowing`] run for the same seed and radius
    /// (whatever [`PoissonDisk::method`] is). If the process saturates (becomes
    /// maximal) before `N` points, the result is [`PatternError::Shortfall`].
    #[default]
    SequentialDartThrowing,
    /// A uniformly random `N`-subset of a whole run of [`PoissonDisk::method`]
    /// (a maximal set, or Bridson's): "thinning". A subset of a Poisson-disk set
    /// is one, but thinning a maximal set leaves holes, so its low-frequency
    /// spectrum is higher than that of sequential dart throwing stopped at `N`.
    ThinnedRun,
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
/// * **Maximal dart throwing**[^3][^4][^5] ([`PoissonMethod::MaximalDartThrowing`]):
///   random sequential adsorption (each dart uniform on the torus, rejected if
///   closer than `r` to an accepted point) run until no uncovered location is
///   left: a maximal set (see [`PoissonDisk::coverage_slack`] for the precise
///   statement). As in Ebeida et al. (2011, 2012), darts are thrown only into
///   *active boxes*: at level `l` the active boxes are cubes of width
///   `1/(g·2^l)` inside empty grid cells, all of one size, and a dart picks a
///   box uniformly and then a location uniformly in it. The active boxes contain
///   every uncovered location, so an accepted dart is uniform over the uncovered
///   region: the accepted points, in order, are distributed exactly as plain
///   dart throwing's. A box is removed when its cell receives a point or
///   when it is known to be covered, and after one dart per active box the
///   level is refined: every box is split into `2^D` children and the
///   children known to be covered are dropped. At the last level
///   ([`PoissonDisk::coverage_slack`]) a box that receives a rejected dart is
///   removed, which ends the run. *Coverage masks*: every cell keeps one bit
///   per sub-box of width `1/(4g)` (`4^D ≤ 64` bits), set when one disk
///   contains that sub-box; each accepted point sets the bits of the cells
///   around it (per axis the farthest distance to each sub-interval, then a
///   sum of squares per sub-box, with the margin of the exactness rule). A box
///   of level `≤ 2` is known to be covered when all the level-2 sub-boxes it
///   contains are marked (their union contains it), a box of level `> 2` when
///   the level-2 box containing it is marked or one disk contains it. The
///   masks are read when a box is drawn (a covered box is removed without a
///   dart) and at refinement, which at levels `0 → 1 → 2` then needs no
///   neighbour search. Removed boxes are tombstoned, so the list stays in
///   cell order and refinement walks the grid in memory order (the points
///   around a cell are gathered once for all its boxes). None of this changes
///   which darts are accepted: only boxes without an uncovered location are
///   removed.
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
/// [^5]: M. S. Ebeida, A. A. Davidson, A. Patney, P. M. Knupp, S. A. Mitchell,
///   J. D. Owens, *Efficient Maximal Poisson-Disk Sampling*, ACM TOG 30(4)
///   (SIGGRAPH 2011); M. S. Ebeida, S. A. Mitchell, A. Patney, A. A. Davidson,
///   J. D. Owens, *A Simple Algorithm for Maximal Poisson-Disk Sampling in High
///   Dimensions*, Computer Graphics Forum 31(2) (Eurographics 2012).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoissonDisk<const D: usize> {
    radius: f64,
    g: usize,
    cells: usize,
    reach: usize,
    max_points: usize,
    candidates: u32,
    method: PoissonMethod,
    n_mode: PoissonN,
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
            n_mode: PoissonN::SequentialDartThrowing,
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
    /// [`PoissonDisk::generate_n`] (sequential dart throwing stopped at `n` by
    /// default, [`PoissonN`]) to get exactly `n` (or a
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

    /// The same sampler producing `N`-point sets ([`PoissonDisk::generate_n`])
    /// by `mode` (default [`PoissonN::SequentialDartThrowing`]).
    #[must_use]
    pub fn with_n_mode(mut self, mode: PoissonN) -> Self {
        self.n_mode = mode;
        self
    }

    /// How [`PoissonDisk::generate_n`] makes exactly `N` points.
    #[must_use]
    pub fn n_mode(&self) -> PoissonN {
        self.n_mode
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
    /// cell holds the `f32` bits of its point, if any), `2·g^D` for the coverage
    /// masks of dart throwing (`4^D ≤ 64` bits per cell), plus a work list of
    /// `max(max_points, 2·2^D·g^D)` words: Bridson's active list, or the
    /// active-box list of dart throwing (two words per box, capacity `2^D·g^D`
    /// boxes so that the first refinement always fits). In all
    /// `(D + 2 + 2^{D+1})·g^D` words, e.g. `12·g^D` in 2D.
    #[must_use]
    pub fn scratch_len(&self) -> usize {
        (D + 2) * self.cells + self.max_points.max(2 * self.list_cap())
    }

    /// Capacity of the active-box list, in boxes: `2^D·g^D`, so that the
    /// first refinement (at most `g^D` boxes of `2^D` children) always fits.
    fn list_cap(&self) -> usize {
        self.cells << D
    }

    /// Maximality slack `ε` of [`PoissonMethod::MaximalDartThrowing`]: every
    /// location `x` of the torus is within toroidal distance `< r + ε` of a point
    /// of the set, with `ε = √D·(w + 2⁻²³)` and `w = 1/(g·2⁶)` the smallest box of
    /// the maximality pass (so `ε < r/64 + √D·2⁻²³`).
    ///
    /// Proof sketch: a location in an occupied cell is within the cell diagonal
    /// `√D/g < r` of the cell's point. An active box of an empty cell is removed
    /// only (a) when its cell receives a point, (b) when one disk contains it
    /// entirely, or the coverage masks show that disks contain each level-2
    /// sub-box of it (or the level-2 box that contains it) entirely, or (c) at the deepest level, `w = 1/(g·2⁶)`,
    /// when a candidate drawn in it (moved by at most one `f32` ulp) is rejected:
    /// then the candidate `c` lies within `r` of a point `q`, so every `x` of the
    /// box satisfies `d(x, q) < r + √D·(w + 2⁻²⁴)`. The run ends only when no box
    /// is left. Points added later only add coverage. (If the active list would
    /// overflow its capacity at a refinement 16 times in a row, the remaining
    /// cells are finished one by one by the same depth-first subdivision, with
    /// the same three removal rules; not observed at the tested radii.)
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
    /// `2·max_points` picks of at most `k` candidates each.
    /// [`PoissonMethod::MaximalDartThrowing`]: at levels `0 … 5` one dart per
    /// active box (times at most 16 rounds per level), at level 6 every dart
    /// removes a box, and the bounded fallback visits each remaining cell once.
    /// Both end.
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
        self.generate_impl(seed, scratch, out, true, None)
    }

    /// [`PoissonDisk::generate`]; `fast = false` forces the generic neighbour scan
    /// (for the test that both scans give the same points); `stop = Some(n)` runs
    /// active-box dart throwing stopped at `n` points, whatever the method.
    fn generate_impl(
        &self,
        seed: Seed,
        scratch: &mut [u32],
        out: &mut [[f32; D]],
        fast: bool,
        stop: Option<usize>,
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
        let (grid, rest) = scratch.split_at_mut(D * self.cells);
        let (mask, list) = rest.split_at_mut(2 * self.cells);
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
            mask,
            use_mask: false,
        };
        // The list capacity is fixed (not the caller's length): the refinement
        // schedule, hence the points, must not depend on the scratch size.
        let cap = self.list_cap();
        let list = &mut list[..(2 * cap).max(self.max_points)];
        match (self.method, stop) {
            (_, Some(n)) => st.active_darts(seed, &mut list[..2 * cap], n),
            (PoissonMethod::Bridson, None) => {
                st.bridson(&mut seed.pcg(BRIDSON_PURPOSE), list, self.candidates);
            }
            (PoissonMethod::MaximalDartThrowing, None) => {
                st.active_darts(seed, &mut list[..2 * cap], usize::MAX);
            }
        }
        Ok(st.n)
    }

    /// Exactly `n` points in `out[..n]`, by [`PoissonDisk::n_mode`]:
    ///
    /// * [`PoissonN::SequentialDartThrowing`] (default): dart throwing (random
    ///   sequential adsorption, with the active boxes of
    ///   [`PoissonMethod::MaximalDartThrowing`]) stopped at the `n`-th accepted
    ///   point, in acceptance order: the first `n` points of the
    ///   [`PoissonMethod::MaximalDartThrowing`] run for this seed and radius,
    ///   whatever [`PoissonDisk::method`] says. Literature: Widom (1966), Feder
    ///   (1980) for the process; Lagae & Dutré (2008) for its use as the
    ///   reference Poisson-disk pattern.
    /// * [`PoissonN::ThinnedRun`]: a run of [`PoissonDisk::generate`] followed
    ///   by a uniformly random subset of size `n` of its points (a subset of a
    ///   Poisson-disk set is one; the subset is random so that it stays
    ///   spatially homogeneous, which the first `n` of a Bridson run are not).
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`] if `n = 0`; [`PatternError::Shortfall`] if
    /// fewer than `n` points fit (dart throwing saturated, or the run produced
    /// fewer; `out[..got]` then holds all of them); as [`PoissonDisk::generate`].
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
        let stop = match self.n_mode {
            PoissonN::SequentialDartThrowing => Some(n),
            PoissonN::ThinnedRun => None,
        };
        let got = self.generate_impl(seed, scratch, out, true, stop)?;
        if got < n {
            return Err(PatternError::Shortfall {
                got: got as u64,
                wanted: n as u64,
            });
        }
        if stop.is_some() {
            return Ok(());
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
/// seed, the `n` points of [`PoissonDisk::generate_n_vec`], bit for bit. By
/// default ([`PoissonN::SequentialDartThrowing`]) that is sequential dart
/// throwing stopped at `n` accepted points, in acceptance order (a prefix is
/// the process stopped earlier); [`PoissonN::ThinnedRun`] (set on the disk
/// sampler with [`PoissonDisk::with_n_mode`]) gives a random `n`-subset of a
/// whole run instead. Fewer than `n` points fitting is an error
/// ([`PatternError::Shortfall`]) that says so. With the `alloc` feature.
///
/// **Every fill generates the whole set and allocates** (the disk sampler's
/// grid and its output): a Poisson-disk set is produced by one sequential run
/// whose every point depends on the points before it, so point `i` cannot be
/// computed on its own (no random access) and a fill of any range costs a
/// full run. Use it
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

/// Farthest toroidal distance from `q` to the interval `[lo, lo + w]`
/// (`lo, q ∈ [0, 1)`): `1/2` if the antipode of `q` lies in it, else the
/// farther end.
#[inline(always)]
fn far_axis(q: f64, lo: f64, w: f64) -> f64 {
    let mut anti = q + 0.5;
    if anti >= 1.0 {
        anti -= 1.0;
    }
    if (anti >= lo && anti <= lo + w) || (anti + 1.0 >= lo && anti + 1.0 <= lo + w) {
        0.5
    } else {
        torus_dist(q, lo).max(torus_dist(q, frac(lo + w)))
    }
}

/// All `4^D` bits of a coverage mask ([`MASK_LEVEL`]).
#[inline(always)]
const fn mask_full<const D: usize>() -> u64 {
    if 2 * D >= 6 {
        u64::MAX
    } else {
        (1u64 << (1 << (2 * D))) - 1
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
    /// Coverage masks, two words per cell ([`State::mask_of`]); kept up to
    /// date by [`State::add`] while `use_mask` (active-box dart throwing).
    mask: &'a mut [u32],
    use_mask: bool,
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
        if self.use_mask {
            self.scatter(&x);
        }
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
    fn bridson(&mut self, rng: &mut Pcg32, active: &mut [u32], k: u32) {
        let first = Self::uniform(rng);
        let Some(i0) = self.try_add(first) else {
            return;
        };
        active[0] = i0 as u32;
        let mut len = 1usize;
        // The set cannot grow past max_points (e.g. one point when r > √D/2).
        while len > 0 && self.n < self.p.max_points {
            let a = below(rng, len as u32) as usize;
            let p = self.pts[active[a] as usize];
            let mut found = false;
            for _ in 0..k {
                let y = self.annulus(rng, &p);
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

    /// Cell coordinates packed in one word, `32/D` bits per axis (`g ≤ 2²²`,
    /// `8192`, `406` in 1, 2, 3D fits).
    #[inline(always)]
    fn unpack(word: u32) -> [usize; D] {
        let bits = 32 / D as u32;
        let mask = if D == 1 { u32::MAX } else { (1u32 << bits) - 1 };
        core::array::from_fn(|j| ((word >> (bits * j as u32)) & mask) as usize)
    }

    /// Inverse of [`State::unpack`].
    #[inline(always)]
    fn pack(c: &[usize; D]) -> u32 {
        let bits = 32 / D as u32;
        let mut w = 0u32;
        for j in 0..D {
            w |= (c[j] as u32) << (bits * j as u32);
        }
        w
    }

    /// Lower corner of sub-box `sub` (packed, [`SUB_BITS`] per axis) of width `w`
    /// in cell `c`.
    #[inline(always)]
    fn box_lo(&self, c: &[usize; D], sub: u32, w: f64) -> [f64; D] {
        core::array::from_fn(|j| {
            c[j] as f64 / self.gf + f64::from((sub >> (SUB_BITS * j as u32)) & SUB_MASK) * w
        })
    }

    /// Reads the list entries of the boxes `picks` and, for live ones, their
    /// cells' first grid word and coverage mask, so that the reads of a batch
    /// of darts overlap (the values are discarded; `black_box` keeps the reads).
    #[inline(always)]
    fn touch(&self, list: &[u32], picks: &[u32; BATCH]) {
        let mut acc = 0u32;
        for &k in picks {
            let cw = list[2 * k as usize];
            if cw != DEAD {
                let c = Self::unpack(cw);
                let ci = self.index(&c);
                let w = self.grid[D * ci];
                acc ^= w;
                if self.use_mask {
                    acc ^= self.mask[2 * ci];
                }
            }
        }
        core::hint::black_box(acc);
    }

    /// Active-box dart throwing (Ebeida et al. 2011, 2012), stopped after `stop`
    /// accepted points or when no active box is left (maximal).
    ///
    /// `list` holds the active boxes, two words each (cell index, packed
    /// sub-box corner), all of width `w = 1/(g·2^level)`. A dart picks a box
    /// uniformly and a location uniformly in it, so darts are uniform over the
    /// union of the active boxes, which contains the whole uncovered region: the
    /// accepted darts are those of plain dart throwing over the torus (a dart
    /// drawn in a tombstone is rejected, so the live boxes are drawn uniformly
    /// too). Boxes of occupied cells and boxes the coverage masks show covered
    /// are removed when drawn; after `DART_NUM/DART_DEN` darts per active box
    /// the level is refined (children known to be covered are dropped). At the
    /// last level a box that received a rejected dart is removed (the slack of
    /// [`PoissonDisk::coverage_slack`]).
    ///
    /// Boxes come from their own stream (`PICK_PURPOSE`), locations from the
    /// dart stream. Below the last level the number of boxes `a` is fixed, so
    /// the boxes of `BATCH` darts are drawn at once and their memory read
    /// ahead ([`State::touch`]); each dart still sees the state the darts
    /// before it left, so the process is the same one, dart by dart.
    fn active_darts(&mut self, seed: Seed, list: &mut [u32], stop: usize) {
        let rng = &mut seed.pcg(DART_PURPOSE);
        let pick = &mut seed.pcg(PICK_PURPOSE);
        let cells = self.p.cells;
        let cap = list.len() / 2;
        let stop = stop.min(self.p.max_points);
        self.mask.fill(0);
        // The scatter loops hold at most 7 cells per axis, which always holds
        // (`State::scatter`); the check only keeps the arrays in bounds.
        self.use_mask = (2 * self.p.reach + 1).min(self.p.g) <= 7;
        // Level 0: every cell (the torus is empty).
        let mut c = [0usize; D];
        for i in 0..cells {
            list[2 * i] = Self::pack(&c);
            list[2 * i + 1] = 0;
            odometer_step(&mut c, &[self.p.g; D]);
        }
        let mut a = cells;
        let mut level = 0u32;
        let mut rounds = 0u32;
        while a > 0 && self.n < stop {
            let w = 1.0 / (self.gf * f64::from(1u32 << level));
            let last = level == FILL_DEPTH;
            let budget = if last {
                u64::MAX
            } else {
                (a as u64 * DART_NUM).div_ceil(DART_DEN)
            };
            // Removed boxes become tombstones (`DEAD`) instead of being swapped
            // out, so the list keeps its cell order (refinement and cleaning then
            // walk the grid in memory order); a dart drawn in a tombstone is
            // rejected. `dead` counts them. The list enters a level without
            // tombstones (refinement and cleaning drop them), and the last level
            // swap-removes instead.
            let mut dead = 0usize;
            let mut thrown = 0u64;
            // Boxes are drawn BATCH at a time from their own stream (`a` is
            // fixed below the last level), and the batch's list entries, cell
            // words and masks are read before its first dart runs: the reads of
            // one dart no longer wait for those of the one before. Each dart
            // then reads them again (from cache), after the darts before it.
            let mut picks = [0u32; BATCH];
            let mut next = BATCH;
            while dead < a && thrown < budget && self.n < stop {
                thrown += 1;
                let k = if last {
                    below(pick, a as u32) as usize
                } else {
                    if next == BATCH {
                        for p in &mut picks {
                            *p = below(pick, a as u32);
                        }
                        self.touch(list, &picks);
                        next = 0;
                    }
                    let k = picks[next];
                    next += 1;
                    k as usize
                };
                // Drawn for this level's `a` (a stale batch would not be).
                debug_assert!(k < a, "box {k} of {a}");
                let cw = list[2 * k];
                if cw == DEAD {
                    continue;
                }
                let c = Self::unpack(cw);
                let ci = self.index(&c);
                let mut drop = true;
                if self.grid[D * ci] == EMPTY && !self.mask_covers(ci, level, list[2 * k + 1]) {
                    let lo = self.box_lo(&c, list[2 * k + 1], w);
                    let x = self.candidate_in(rng, &c, &lo, w);
                    match x {
                        Some(x) if !self.conflicts(&x, &c) => {
                            self.add(x, &c);
                        }
                        _ => drop = last,
                    }
                }
                if drop && last {
                    // Order no longer matters: swap-remove, so every dart of
                    // the last level removes a box or adds a point.
                    a -= 1;
                    list.copy_within(2 * a..2 * a + 2, 2 * k);
                } else if drop {
                    list[2 * k] = DEAD;
                    dead += 1;
                }
            }
            if dead == a || self.n >= stop || last {
                if dead == a {
                    a = 0;
                }
                continue;
            }
            if (a << D) <= cap {
                a = self.refine(list, a, level, cap);
                level += 1;
                rounds = 0;
            } else {
                a = self.clean(list, a, level);
                rounds += 1;
                if rounds >= MAX_ROUNDS {
                    // Fallback (bounded): complete the remaining cells one by one.
                    for k in 0..a {
                        let ci = self.index(&Self::unpack(list[2 * k]));
                        if self.n < stop && self.grid[D * ci] == EMPTY {
                            self.fill_cell(rng, ci);
                        }
                    }
                    return;
                }
            }
        }
    }

    /// The points within `reach` cells of cell `c`, as `f64`.
    #[inline(always)]
    fn gather(&self, c: &[usize; D], near: &mut [[f64; D]; 125]) -> usize {
        let mut len = 0;
        self.any_near(c, |q| {
            if len < 125 {
                near[len] = core::array::from_fn(|j| f64::from(q[j]));
                len += 1;
            }
            false
        });
        len
    }

    /// Splits every active box (`list[..2a]`, tombstones skipped) into its
    /// `2^D` children and keeps those of empty cells that are not known to be
    /// covered: by the coverage masks ([`State::mask_covers`]) and, below the
    /// mask level, by one disk ([`State::covers`]). Needs `2^D·a ≤ cap`: the
    /// boxes are moved to the end of the list and read from there while the
    /// children are written from the start (the writes never pass the reads).
    /// Returns the new number of active boxes.
    fn refine(&mut self, list: &mut [u32], a: usize, level: u32, cap: usize) -> usize {
        let base = cap - a;
        list.copy_within(0..2 * a, 2 * base);
        let wc = 1.0 / (self.gf * f64::from(2u32 << level));
        let deep = !self.use_mask || level + 1 > MASK_LEVEL;
        let mut out = 0usize;
        // The list is in cell order: the points around a cell are gathered
        // once for all its boxes.
        let mut all = [[0.0f64; D]; 125];
        let (mut all_len, mut all_ci) = (0usize, usize::MAX);
        let mut near = [[0.0f64; D]; 125];
        for i in 0..a {
            let cw = list[2 * (base + i)];
            if cw == DEAD {
                continue;
            }
            let sub = list[2 * (base + i) + 1];
            let c = Self::unpack(cw);
            let ci = self.index(&c);
            if self.grid[D * ci] != EMPTY {
                continue;
            }
            let mut len = 0;
            if deep {
                if ci != all_ci {
                    all_len = self.gather(&c, &mut all);
                    all_ci = ci;
                }
                // Every child has the parent's centre as a corner, so a disk
                // that contains a child contains the centre: keep only those.
                let lo_p = self.box_lo(&c, sub, 2.0 * wc);
                for q in &all[..all_len] {
                    let mut d2 = 0.0;
                    for j in 0..D {
                        let d = torus_dist(q[j], lo_p[j] + wc);
                        d2 += d * d;
                    }
                    if d2 < self.r2_lo {
                        near[len] = *q;
                        len += 1;
                    }
                }
            }
            for child in 0..(1u32 << D) {
                let mut s = 0u32;
                for j in 0..D {
                    let b = (sub >> (SUB_BITS * j as u32)) & SUB_MASK;
                    s |= (2 * b + ((child >> j) & 1)) << (SUB_BITS * j as u32);
                }
                if self.mask_covers(ci, level + 1, s) {
                    continue;
                }
                if deep {
                    let lo = self.box_lo(&c, s, wc);
                    if near[..len].iter().any(|q| self.covers(q, &lo, wc)) {
                        continue;
                    }
                }
                list[2 * out] = cw;
                list[2 * out + 1] = s;
                out += 1;
            }
        }
        out
    }

    /// Removes the tombstones, the boxes of occupied cells and the boxes known
    /// to be covered (as in [`State::refine`]).
    fn clean(&mut self, list: &mut [u32], a: usize, level: u32) -> usize {
        let w = 1.0 / (self.gf * f64::from(1u32 << level));
        let deep = !self.use_mask || level > MASK_LEVEL;
        let mut out = 0usize;
        for i in 0..a {
            let cw = list[2 * i];
            if cw == DEAD {
                continue;
            }
            let sub = list[2 * i + 1];
            let c = Self::unpack(cw);
            let ci = self.index(&c);
            if self.grid[D * ci] != EMPTY || self.mask_covers(ci, level, sub) {
                continue;
            }
            if deep && self.box_covered(&c, &self.box_lo(&c, sub, w), w) {
                continue;
            }
            list[2 * out] = cw;
            list[2 * out + 1] = sub;
            out += 1;
        }
        out
    }

    /// The coverage mask of cell `ci`: bit `Σ_j i_j·4^j` is set when one disk
    /// is known to contain the sub-box `i ∈ {0..3}^D` of width `1/(4g)`
    /// (level [`MASK_LEVEL`]).
    #[inline(always)]
    fn mask_of(&self, ci: usize) -> u64 {
        u64::from(self.mask[2 * ci]) | (u64::from(self.mask[2 * ci + 1]) << 32)
    }

    /// `true` if the masks show that the box `sub` of level `level` in cell
    /// `ci` is covered: every level-2 sub-box it contains (levels 0, 1), or the
    /// level-2 sub-box that contains it (levels ≥ 2), is contained in one disk.
    /// Always `false` when the masks are off.
    #[inline(always)]
    fn mask_covers(&self, ci: usize, level: u32, sub: u32) -> bool {
        if !self.use_mask {
            return false;
        }
        let m = self.mask_of(ci);
        if level >= MASK_LEVEL {
            let mut bit = 0u32;
            for j in (0..D).rev() {
                let b = ((sub >> (SUB_BITS * j as u32)) & SUB_MASK) >> (level - MASK_LEVEL);
                bit = 4 * bit + b;
            }
            return (m >> bit) & 1 == 1;
        }
        let full = mask_full::<D>();
        if level == 0 {
            return m == full;
        }
        // level 1: the 2^D level-2 sub-boxes 2b + {0, 1} per axis.
        let mut region = 0u64;
        for t in 0..(1u32 << D) {
            let mut bit = 0u32;
            for j in (0..D).rev() {
                let b = (sub >> (SUB_BITS * j as u32)) & SUB_MASK;
                bit = 4 * bit + 2 * b + ((t >> j) & 1);
            }
            region |= 1 << bit;
        }
        m & region == region
    }

    /// Marks in the coverage masks every level-2 sub-box ([`State::mask_of`])
    /// of the cells within `reach` of `x` that the disk of `x` contains.
    /// Per axis the farthest toroidal distance from `x` to each of the four
    /// sub-intervals of each cell is computed once; a sub-box is contained iff
    /// the sum of the squares is below `r²(1 − 10⁻¹²)` (as [`State::covers`]).
    /// A cell is skipped when the sum of the per-axis minima reaches `r²` and
    /// filled when the sum of the maxima stays below it. At most 7 cells per
    /// axis: for `r < 1`, `r·g ≤ √D + r < 3` so `reach ≤ 3`; for `r ≥ 1`,
    /// `g ≤ 2`.
    fn scatter(&mut self, x: &[f32; D]) {
        let g = self.p.g;
        let span = (2 * self.p.reach + 1).min(g);
        let c = self.cell(x);
        let w4 = 1.0 / (self.gf * 4.0);
        let r2 = self.r2_lo;
        // far[j][t][i]: squared farthest distance along axis j to
        // sub-interval i of the cell at step t; lo/hi: min/max over i.
        let mut far = [[[0.0f64; 4]; 7]; D];
        let mut fmin = [[0.0f64; 7]; D];
        let mut fmax = [[0.0f64; 7]; D];
        let mut cellj = [[0usize; 7]; D];
        for j in 0..D {
            let qj = f64::from(x[j]);
            let start = if span == g {
                0
            } else {
                c[j] + g - self.p.reach
            };
            for t in 0..span {
                let k = (start + t) % g;
                cellj[j][t] = k;
                let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
                for i in 0..4 {
                    let a = k as f64 / self.gf + i as f64 * w4;
                    let d = far_axis(qj, a, w4);
                    let d2 = d * d;
                    far[j][t][i] = d2;
                    lo = lo.min(d2);
                    hi = hi.max(d2);
                }
                fmin[j][t] = lo;
                fmax[j][t] = hi;
            }
        }
        let full = mask_full::<D>();
        let mut t = [0usize; D];
        loop {
            let (mut smin, mut smax) = (0.0, 0.0);
            for j in 0..D {
                smin += fmin[j][t[j]];
                smax += fmax[j][t[j]];
            }
            if smin < r2 {
                let mut idx = 0;
                for j in (0..D).rev() {
                    idx = idx * g + cellj[j][t[j]];
                }
                let mut m = self.mask_of(idx);
                if smax < r2 {
                    m = full;
                } else if m != full {
                    // Axes padded to three: a missing axis has one interval
                    // at distance 0. Nested loops skip a slab as soon as its
                    // partial sum plus the other axes' minima reaches r².
                    let mut f = [[0.0f64; 4]; 3];
                    let mut n = [1usize; 3];
                    let mut mn = [0.0f64; 3];
                    for j in 0..D {
                        f[j] = far[j][t[j]];
                        n[j] = 4;
                        mn[j] = fmin[j][t[j]];
                    }
                    for i2 in 0..n[2] {
                        let s2 = f[2][i2];
                        if s2 + mn[1] + mn[0] >= r2 {
                            continue;
                        }
                        for i1 in 0..n[1] {
                            let s1 = s2 + f[1][i1];
                            if s1 + mn[0] >= r2 {
                                continue;
                            }
                            for i0 in 0..n[0] {
                                if s1 + f[0][i0] < r2 {
                                    m |= 1 << (i0 + 4 * i1 + 16 * i2);
                                }
                            }
                        }
                    }
                }
                self.mask[2 * idx] = m as u32;
                self.mask[2 * idx + 1] = (m >> 32) as u32;
            }
            if !odometer_step(&mut t, &[span; D]) {
                return;
            }
        }
    }

    /// `true` if the disk of `q` contains the box `[lo, lo + w]^D` entirely
    /// (its farthest point is closer than `r`, with margin).
    #[inline(always)]
    fn covers(&self, q: &[f64; D], lo: &[f64; D], w: f64) -> bool {
        let r2 = self.r2_lo;
        let mut s = 0.0;
        for j in 0..D {
            let d = far_axis(q[j], lo[j], w);
            s += d * d;
            if s >= r2 {
                return false;
            }
        }
        true
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
        self.any_near(c, |q| {
            let qf: [f64; D] = core::array::from_fn(|j| f64::from(q[j]));
            self.covers(&qf, lo, w)
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

    /// Every random stream of the module has its own purpose: two equal
    /// purposes would give two uses the same numbers (box picks equal to the
    /// thinned subset's draws, say).
    #[test]
    fn stream_purposes_are_distinct() {
        let p = [BRIDSON_PURPOSE, DART_PURPOSE, PICK_PURPOSE, SUBSET_PURPOSE];
        for i in 0..p.len() {
            for j in 0..i {
                assert_ne!(p[i], p[j], "purposes {i} and {j}");
            }
        }
    }

    /// The sorted neighbour list (fast path) and the generic odometer scan decide
    /// the same predicate, so they give the same points.
    fn same<const D: usize>(r: f64, method: PoissonMethod) {
        let p = PoissonDisk::<D>::with_radius(r)
            .unwrap()
            .with_method(method);
        let mut scratch = [0u32; 1 << 17];
        let mut a = [[0.0f32; D]; 4096];
        let mut b = [[0.0f32; D]; 4096];
        for seed in 0..3 {
            let na = p
                .generate_impl(Seed::new(seed), &mut scratch, &mut a, true, None)
                .unwrap();
            let nb = p
                .generate_impl(Seed::new(seed), &mut scratch, &mut b, false, None)
                .unwrap();
            assert_eq!(na, nb);
            assert_eq!(a[..na], b[..nb]);
        }
    }

    /// After a dart-throwing run the coverage masks (scratch words after the
    /// grid) mark a level-2 sub-box only if one disk contains it (brute force
    /// over all points, farthest point of the box, no margin), and mark every
    /// sub-box that a disk contains with room to spare (`d² < r²(1 − 10⁻⁹)`).
    fn masks<const D: usize>(r: f64) {
        let p = PoissonDisk::<D>::with_radius(r)
            .unwrap()
            .with_method(PoissonMethod::MaximalDartThrowing);
        let mut scratch = [0u32; 1 << 17];
        let mut out = [[0.0f32; D]; 4096];
        let n = p.generate(Seed::new(5), &mut scratch, &mut out).unwrap();
        let (g, cells) = (p.g, p.cells);
        let w4 = 1.0 / (4.0 * g as f64);
        let r2 = r * r;
        let mut marked = 0;
        for ci in 0..cells {
            let m = u64::from(scratch[D * cells + 2 * ci])
                | (u64::from(scratch[D * cells + 2 * ci + 1]) << 32);
            let mut rest = ci;
            let c: [usize; D] = core::array::from_fn(|_| {
                let v = rest % g;
                rest /= g;
                v
            });
            for bit in 0..(1usize << (2 * D)) {
                let lo: [f64; D] = core::array::from_fn(|j| {
                    c[j] as f64 / g as f64 + ((bit >> (2 * j)) & 3) as f64 * w4
                });
                // Largest squared distance from a point to the box, minimised
                // over the points.
                let best = out[..n]
                    .iter()
                    .map(|q| {
                        (0..D)
                            .map(|j| {
                                let d = far_axis(f64::from(q[j]), lo[j], w4);
                                d * d
                            })
                            .sum::<f64>()
                    })
                    .fold(f64::INFINITY, f64::min);
                let set = (m >> bit) & 1 == 1;
                assert!(
                    !set || best < r2,
                    "D={D} cell {ci} bit {bit}: {best} ≥ {r2}"
                );
                assert!(
                    set || best >= r2 * (1.0 - 1e-9),
                    "D={D} cell {ci} bit {bit} missed"
                );
                marked += usize::from(set);
            }
        }
        assert!(marked > 0);
    }

    #[test]
    fn coverage_masks_mark_exactly_the_contained_sub_boxes() {
        masks::<1>(0.01);
        masks::<2>(0.05);
        masks::<3>(0.15);
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
