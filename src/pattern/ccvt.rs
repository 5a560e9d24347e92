//! Capacity-constrained Voronoi tessellation (CCVT) point sets on the unit torus.
//!
//! **Needs the `alloc` feature**: the algorithm keeps `N·c` discrete points in
//! memory (`c` = capacity per site), so [`Ccvt`] and [`CcvtResult`] exist only
//! with `alloc` (on by default through `std`).
//!
//! The algorithm, its stopping rule and its cost are documented on `Ccvt`.

#[cfg(feature = "alloc")]
pub use imp::{Ccvt, CcvtResult};

/// Default capacity `c` of a CCVT site: the number of discrete density points each
/// site owns (`Ccvt::DEFAULT_CAPACITY`). Defined without the `alloc` feature too,
/// so that the module always exports something.
pub const CCVT_DEFAULT_CAPACITY: usize = 64;

#[cfg(feature = "alloc")]
mod imp {
    use crate::error::PatternError;
    use crate::num::{frac, to_unit_f32, torus_delta};
    use crate::pattern::sealed::{Generate, Sink};
    use crate::pattern::{check_dims, check_n, odometer_step, unit_f64};
    use crate::rng::{Pcg32, Seed};
    use alloc::vec;
    use alloc::vec::Vec;

    /// Seed purpose of the discrete density (cell choice and jitter).
    const POINTS_PURPOSE: u64 = 0x4343_5654_5054_5300;
    /// Seed purpose of the initial sites.
    const SITES_PURPOSE: u64 = 0x4343_5654_5349_5445;

    /// Largest number of sites.
    const MAX_N: u64 = 1 << 24;
    /// Largest capacity per site.
    const MAX_CAPACITY: u64 = 1 << 16;
    /// Largest number of discrete points `N·c`.
    const MAX_POINTS: u64 = 1 << 31;

    /// Capacity-constrained Voronoi tessellation point set of `N` points on the
    /// torus `[0, 1)^D`, `D ∈ {2, 3}` (Balzer, Schlömer & Deussen 2009).
    ///
    /// Needs the `alloc` feature. Implements [`Pattern<D>`](crate::pattern::Pattern)
    /// for use with estimators and [`Shifted`](crate::pattern::Shifted); each fill
    /// runs a full optimisation.
    ///
    /// # The point set
    ///
    /// Balzer, Schlömer & Deussen[^1] define a CCVT of `N` sites `s_i` on a domain with
    /// density `ρ` as a partition into regions `V_i` of equal capacity
    /// `∫_{V_i} ρ = 1/N` whose sites are the centroids of their regions, reached by
    /// minimising the energy `E = Σ_i ∫_{V_i} ρ(x)·|x − s_i|² dx` under the capacity
    /// constraint. The density is represented by `M = N·c` discrete points `x_k`, each of
    /// mass `1/M`, and every site owns exactly `c` of them. Here `ρ` is uniform on the
    /// torus `[0, 1)^D` (`D = 2, 3`) and `|·|` is the toroidal distance (each coordinate
    /// difference wrapped into `[−1/2, 1/2)`).
    ///
    /// The resulting points are blue-noise: Pilleboue et al.[^2] list the variance of
    /// the point-sampling estimator for CCVT as `O(N^{−1−3/d})` for smooth integrands
    /// and `O(N^{−1−1/d})` for integrands with a discontinuity, against
    /// `O(N^{−1−2/d})` / `O(N^{−1−1/d})` for jittered sampling.
    ///
    /// # Algorithm
    ///
    /// 1. **Discrete density.** A grid of `g^D ≥ M` cells, `g = ⌈M^{1/D}⌉`; `M` distinct
    ///    cells are drawn uniformly without replacement (all of them when `M = g^D`)
    ///    and each gets one point, jittered inside the cell: coordinate
    ///    `(c_j + ½ + δ·(u − ½))/g`, `u` uniform, `δ` = [`Ccvt::jitter`] (default 0.1,
    ///    see *Discretisation noise*). The capacity measure is thus a stratified
    ///    sample of the uniform density.
    /// 2. **Initial state.** `N` uniform random sites, ordered along the Morton
    ///    (Z-order) curve. Every discrete point is given to its nearest random site
    ///    (ring search in a grid of the sites); the points, sorted by (Morton rank
    ///    of that site, Morton order of the point's cell), are cut into `N` runs of
    ///    `c` consecutive points, run `i` going to site `i`, and each site moves to
    ///    the centroid of its run. Every site thus starts with exactly `c` points
    ///    in a compact, irregular region (pieces of a random Voronoi diagram), which
    ///    makes the first iterations cheap without imposing a lattice.
    /// 3. **Iteration** (Balzer's Algorithm 1, restricted to neighbouring pairs):
    ///    * *Swap phase.* For each candidate pair of sites `(i, j)`, with the sites
    ///      held fixed, every point `x` of `i` gets `h_i(x) = |x − s_i|² − |x − s_j|²`
    ///      (the energy saved by moving it to `j`), every point `y` of `j` gets
    ///      `h_j(y) = |y − s_j|² − |y − s_i|²`. Both lists are sorted in decreasing
    ///      order and the `k`-th entries are exchanged while `h_i + h_j > 0`; each
    ///      exchange lowers `E` by `h_i + h_j` and keeps both capacities at `c`
    ///      (1-for-1). Greedy pairing of the sorted lists is the optimal exchange for
    ///      that pair.
    ///    * *Centroid phase.* Every site whose points changed moves to the toroidal
    ///      centroid of its points: `s ← wrap₀₁(s + (1/c)·Σ wrap(x − s))`, with
    ///      `wrap` into `[−1/2, 1/2)` per axis and `wrap₀₁` into `[0, 1)`. For fixed
    ///      offsets `e = wrap(x − s)` the mean minimises `Σ|e − m|²`, and the toroidal
    ///      distance to the new site is at most `|e − m|`, so `E` never increases.
    ///    * *Stop* when an iteration makes no exchange (the point set is stable: no
    ///      pair of sites can lower `E` by any exchange) and every site is the
    ///      centroid of its points seen from itself (a centroid step is taken in the
    ///      frame of the site's old position; if its points straddled that
    ///      position's antipode, the step is repeated from the new position and
    ///      the iteration goes on), or after `max_iterations`.
    /// 4. **Neighbour pairs.** Let `r_i = max |x − s_i|` over the points of site `i`.
    ///    If `|s_i − s_j| ≥ r_i + r_j`, the triangle inequality gives
    ///    `|x − s_j| ≥ |x − s_i|` and `|y − s_i| ≥ |y − s_j|` for all `x` of `i`, `y`
    ///    of `j`, so no exchange can help: only pairs with overlapping bounding
    ///    balls are examined. They are found with a uniform grid of
    ///    `⌊N^{1/D}⌋^D` cells in which every site is entered into the cells its
    ///    bounding box covers. A pair is skipped, too, if neither site changed since
    ///    the pair was last examined (its answer cannot have changed); both skips are
    ///    exact, so the stopping rule is the same as for the all-pairs algorithm.
    ///
    /// The energy reported by [`Ccvt::generate_with_trace`] is the mean squared
    /// toroidal distance `E = (1/M)·Σ_k |x_k − s(x_k)|²`.
    ///
    /// # Discretisation noise
    ///
    /// The sites inherit the fluctuations of the discrete density: the estimator
    /// of a smooth integrand cannot do better than the `M`-point jittered estimate
    /// behind it, whose variance falls as `(N·c)^{−1−2/D}`. With full jitter
    /// (`δ = 1`) and `c = 64` this floor is reached around `N ≈ 10³–10⁴` in 2D (the
    /// local variance slope for a Gaussian dropped from ≈ −2.7 to ≈ −2.2 between
    /// `N = 1024` and `4096`); with the default `δ = 0.1` it stayed at ≈ −3.0. A
    /// smaller jitter (`δ = 0` is the bare grid; realisations then differ only
    /// through the initial sites and the random shift) or a larger `c` lowers the
    /// floor. When `M` is not a perfect
    /// `D`-th power, the `g^D − M` empty cells are placed at random and add a
    /// white-noise term; prefer `N·c` equal to a perfect power (e.g. `N` a power of
    /// 4 in 2D with `c = 64`) when measuring convergence rates.
    ///
    /// # Quality settings
    ///
    /// The spacing of the sites grows with the capacity `c` (see
    /// [`Ccvt::high_quality`] for the measurements): [`Ccvt::fast_quality`]
    /// (the default, `c = 64`), [`Ccvt::standard_quality`] (`c = 256`, warm
    /// start) and [`Ccvt::high_quality`] (`c = 1024`, warm start) give
    /// `δ_min ≈ 0.63 / 0.69 / 0.74` and `δ_avg ≈ 0.818 / 0.845 / 0.866` at
    /// `N = 1024` (normalised by the hexagonal spacing `√(2/(√3·N))`) for
    /// ≈ 1× / 8× / 70× the time.
    ///
    /// # Cost
    ///
    /// One realisation is one full CCVT run: memory `O(N·c)`, time
    /// `O(iterations · N · c · log c · neighbours)` in the worst case; in practice the
    /// later iterations only revisit the few sites that still change. Runs
    /// stabilise after 20–40 iterations; one core (release build) needs ≈ 0.06 s
    /// for `N = 1024`, 0.12 s for `N = 2048` and 0.25 s for `N = 4096` in 2D. Used as a
    /// [`Pattern`](crate::pattern::Pattern), **every** `fill`/`fill_range` call runs the whole
    /// optimisation (and allocates), then copies the requested points.
    ///
    /// [^1]: M. Balzer, T. Schlömer, O. Deussen, *Capacity-Constrained Point
    ///   Distributions: A Variant of Lloyd's Method*, ACM Trans. Graph. 28(3) (SIGGRAPH
    ///   2009), article 86.
    /// [^2]: A. Pilleboue, G. Singh, D. Coeurjolly, M. Kazhdan, V. Ostromoukhov,
    ///   *Variance Analysis for Monte Carlo Integration*, ACM Trans. Graph. 34(4)
    ///   (SIGGRAPH 2015).
    ///
    /// # Example
    ///
    /// ```
    /// use linesample::pattern::Ccvt;
    /// use linesample::Seed;
    /// let r = Ccvt::<2>::new(64)?.capacity(64)?.generate(Seed::new(1));
    /// assert_eq!(r.sites().len(), 64);
    /// assert!(r.capacities().iter().all(|&c| c == 64));
    /// # Ok::<(), linesample::PatternError>(())
    /// ```
    #[derive(Clone, Debug, PartialEq)]
    pub struct Ccvt<const D: usize> {
        n: usize,
        capacity: usize,
        max_iterations: usize,
        jitter: f64,
        warm_start: bool,
    }

    /// The outcome of one CCVT run: the sites (the point set), the discrete density
    /// points and their assignment to sites, and convergence information.
    #[derive(Clone, Debug)]
    pub struct CcvtResult<const D: usize> {
        sites: Vec<[f32; D]>,
        sites_f64: Vec<[f64; D]>,
        points: Vec<[f64; D]>,
        assignment: Vec<u32>,
        iterations: usize,
        converged: bool,
        energy: f64,
    }

    impl<const D: usize> CcvtResult<D> {
        /// The `N` sites as `f32`, every coordinate in `[0, 1)`.
        #[must_use]
        pub fn sites(&self) -> &[[f32; D]] {
            &self.sites
        }

        /// The sites, consumed into a `Vec`.
        #[must_use]
        pub fn into_sites(self) -> Vec<[f32; D]> {
            self.sites
        }

        /// The sites in the `f64` precision of the optimisation, in `[0, 1)`.
        #[must_use]
        pub fn sites_f64(&self) -> &[[f64; D]] {
            &self.sites_f64
        }

        /// The `M = N·c` discrete points representing the uniform density.
        #[must_use]
        pub fn discrete_points(&self) -> &[[f64; D]] {
            &self.points
        }

        /// `assignment()[k]` is the site owning discrete point `k`.
        #[must_use]
        pub fn assignment(&self) -> &[u32] {
            &self.assignment
        }

        /// Number of discrete points owned by each site, counted from
        /// [`CcvtResult::assignment`] (all equal to the capacity `c`).
        #[must_use]
        pub fn capacities(&self) -> Vec<usize> {
            let mut c = vec![0usize; self.sites.len()];
            for &a in &self.assignment {
                c[a as usize] += 1;
            }
            c
        }

        /// Iterations run (swap phase + centroid phase each).
        #[must_use]
        pub fn iterations(&self) -> usize {
            self.iterations
        }

        /// `true` if the last iteration made no exchange (a stable CCVT), `false`
        /// if the run stopped at the iteration limit.
        #[must_use]
        pub fn converged(&self) -> bool {
            self.converged
        }

        /// Final energy `(1/M)·Σ_k |x_k − s(x_k)|²` (toroidal distance).
        #[must_use]
        pub fn energy(&self) -> f64 {
            self.energy
        }
    }

    impl<const D: usize> Ccvt<D> {
        /// Default capacity `c` (discrete points per site): 64. With `c = 64` a site
        /// region is resolved by 64 points (8×8 in 2D, 4×4×4 in 3D), which is
        /// enough for the region shapes to settle while one realisation of
        /// `N = 4096` stays well under a second. Larger `c` gives better-spaced
        /// sites at a higher cost: raise it with [`Ccvt::capacity`] or pick
        /// [`Ccvt::standard_quality`] / [`Ccvt::high_quality`].
        pub const DEFAULT_CAPACITY: usize = super::CCVT_DEFAULT_CAPACITY;

        /// Default jitter `δ` of the discrete density points: 0.1 (see
        /// *Discretisation noise* in the [`Ccvt`] docs).
        pub const DEFAULT_JITTER: f64 = 0.1;

        /// Default iteration limit: 1000 (runs normally stabilise far earlier).
        pub const DEFAULT_MAX_ITERATIONS: usize = 1000;

        /// CCVT point set of `n` sites with the default capacity and iteration
        /// limit.
        ///
        /// # Errors
        /// [`PatternError::Dims`] unless `D ∈ {2, 3}`; [`PatternError::ZeroPoints`]
        /// for `n = 0`; [`PatternError::TooManyPoints`] for `n > 2²⁴` or
        /// `n·c > 2³¹`.
        pub fn new(n: usize) -> Result<Self, PatternError> {
            check_dims::<D>(2, 3)?;
            check_n(n, MAX_N)?;
            let c = Self::DEFAULT_CAPACITY;
            if (n as u64) * (c as u64) > MAX_POINTS {
                return Err(PatternError::TooManyPoints {
                    max: MAX_POINTS / c as u64,
                });
            }
            Ok(Self {
                n,
                capacity: c,
                max_iterations: Self::DEFAULT_MAX_ITERATIONS,
                jitter: Self::DEFAULT_JITTER,
                warm_start: false,
            })
        }

        /// The same point set with capacity `c` discrete points per site.
        ///
        /// # Errors
        /// [`PatternError::Parameter`] named `"capacity"` unless
        /// `1 ≤ c ≤ min(2¹⁶, 2³¹/N)`.
        pub fn capacity(self, c: usize) -> Result<Self, PatternError> {
            let max = MAX_CAPACITY.min(MAX_POINTS / self.n as u64);
            if c == 0 || c as u64 > max {
                return Err(PatternError::Parameter {
                    name: "capacity",
                    value: c as u64,
                    min: 1,
                    max,
                });
            }
            Ok(Self {
                capacity: c,
                ..self
            })
        }

        /// The same point set with at most `k` iterations.
        ///
        /// # Errors
        /// [`PatternError::Parameter`] named `"max_iterations"` unless
        /// `1 ≤ k ≤ 2³²`.
        pub fn max_iterations(self, k: usize) -> Result<Self, PatternError> {
            let max = 1u64 << 32;
            if k == 0 || k as u64 > max {
                return Err(PatternError::Parameter {
                    name: "max_iterations",
                    value: k as u64,
                    min: 1,
                    max,
                });
            }
            Ok(Self {
                max_iterations: k,
                ..self
            })
        }

        /// The same point set with the discrete density points jittered over the
        /// fraction `δ ∈ [0, 1]` of their grid cell: point `(c + ½ + δ·(u − ½))/g`
        /// per axis, `u` uniform. `δ = 1` is full jittered sampling (default 0.1);
        /// `δ = 0` is the regular grid of cell centres (randomness then comes only
        /// from the initial sites). A smaller `δ` lowers the noise the discrete
        /// density passes on to the sites (see *Discretisation noise* above).
        ///
        /// # Errors
        /// [`PatternError::Jitter`] unless `0 ≤ δ ≤ 1` (NaN included).
        pub fn jitter(self, delta: f64) -> Result<Self, PatternError> {
            if !(0.0..=1.0).contains(&delta) {
                return Err(PatternError::Jitter);
            }
            Ok(Self {
                jitter: delta,
                ..self
            })
        }

        /// Capacity of [`Ccvt::standard_quality`]: 256.
        pub const STANDARD_CAPACITY: usize = 256;

        /// Capacity of [`Ccvt::high_quality`]: 1024.
        pub const HIGH_CAPACITY: usize = 1024;

        /// The fast setting, which is the default: capacity `c = 64`
        /// ([`Ccvt::DEFAULT_CAPACITY`]), random initial sites, no warm start.
        ///
        /// Measured (2D, `N = 1024`, 8 seeds, one core, release build,
        /// `cargo run --release --example ccvt_quality`): normalised minimum
        /// distance `δ_min ≈ 0.63` and mean nearest-neighbour distance
        /// `δ_avg ≈ 0.818` (both in units of the hexagonal packing distance
        /// `d_hex = √(2/(√3·N))`), ≈ 0.06 s per set; `N = 4096`: same
        /// `δ`, ≈ 0.45 s.
        ///
        /// # Errors
        /// As [`Ccvt::capacity`].
        pub fn fast_quality(self) -> Result<Self, PatternError> {
            Ok(self.capacity(Self::DEFAULT_CAPACITY)?.warm_start(false))
        }

        /// The standard setting: capacity `c = 256` ([`Ccvt::STANDARD_CAPACITY`])
        /// computed coarse to fine ([`Ccvt::warm_start`]). Measured as for
        /// [`Ccvt::fast_quality`] (`N = 1024`): `δ_min ≈ 0.70`, `δ_avg ≈ 0.844`,
        /// ≈ 0.5 s per set (≈ 8× the fast setting).
        ///
        /// # Errors
        /// As [`Ccvt::capacity`] (`N·256 ≤ 2³¹`).
        pub fn standard_quality(self) -> Result<Self, PatternError> {
            Ok(self.capacity(Self::STANDARD_CAPACITY)?.warm_start(true))
        }

        /// The high setting: capacity `c = 1024` ([`Ccvt::HIGH_CAPACITY`])
        /// computed coarse to fine ([`Ccvt::warm_start`]:
        /// converged CCVTs at `c = 64` and `256` seed the final run).
        /// Measured as for [`Ccvt::fast_quality`] (`N = 1024`):
        /// `δ_min ≈ 0.74`, `δ_avg ≈ 0.866`, ≈ 4 s per set (≈ 70× the fast
        /// setting; `N = 4096` ≈ 4× that).
        ///
        /// The capacity is what limits `δ`: measured at `N = 1024` (release,
        /// 4–8 seeds; `c = 4096` one seed) `δ_min / δ_avg` rise from
        /// 0.63 / 0.818 (`c = 64`) to 0.69 / 0.84 (256), 0.73–0.74 / 0.862–0.866
        /// (1024) and 0.78 / 0.886 (4096, ≈ 50× the cost of 1024), while the
        /// jitter of the discrete points (`δ ∈ {0, 0.1, 1}`) changes them by
        /// less than their seed-to-seed scatter, and stopping before the
        /// stable state loses quality (`c = 1024`, 30 / 60 iterations: `δ_avg`
        /// 0.842 / 0.852). The warm start adds ≈ +0.005 to `δ_avg` and saves
        /// ≈ 25 % of the time at `c = 1024`. For comparison, farthest-point
        /// optimisation reaches `δ_min = 0.925`, `δ_avg = 0.932` at `N = 1024`
        /// (Schlömer, Heck & Deussen, HPG 2011, Fig. 1).
        ///
        /// # Errors
        /// As [`Ccvt::capacity`] (`N·1024 ≤ 2³¹`).
        pub fn high_quality(self) -> Result<Self, PatternError> {
            Ok(self.capacity(Self::HIGH_CAPACITY)?.warm_start(true))
        }

        /// The same point set computed coarse to fine (`on = true`): before the
        /// run at capacity `c`, CCVTs at capacities `c/4ᵏ ≥ 64` (coarsest
        /// first, each on its own discrete density) are converged, and each
        /// one's sites are the initial sites of the next, instead of `N`
        /// uniform random sites. Most of the work of reaching a stable state
        /// is then done with few points per site; the final run starts close
        /// to its stable state. Off by default; [`Ccvt::high_quality`]
        /// turns it on. Has no effect for `c < 256`.
        #[must_use]
        pub fn warm_start(self, on: bool) -> Self {
            Self {
                warm_start: on,
                ..self
            }
        }

        /// Number of sites `N`.
        #[must_use]
        pub fn n(&self) -> usize {
            self.n
        }

        /// Capacity `c` per site.
        #[must_use]
        pub fn capacity_per_site(&self) -> usize {
            self.capacity
        }

        /// Runs the optimisation for `seed`.
        ///
        /// Deterministic: the result is a pure function of the parameters and the
        /// seed.
        #[must_use]
        pub fn generate(&self, seed: Seed) -> CcvtResult<D> {
            self.generate_with_trace(seed, &mut |_, _| {})
        }

        /// As [`Ccvt::generate`], calling `trace(t, E_t)` with the energy
        /// `E_t = (1/M)·Σ_k |x_k − s(x_k)|²` of the initial state (`t = 0`) and after
        /// every iteration `t ≥ 1`. `E_t` is non-increasing in `t` (up to rounding).
        /// With [`Ccvt::warm_start`], the coarser stages are not traced: `t`
        /// and [`CcvtResult::iterations`] count the iterations of the final
        /// run at capacity `c`, and `max_iterations` limits that run only.
        pub fn generate_with_trace(
            &self,
            seed: Seed,
            trace: &mut dyn FnMut(usize, f64),
        ) -> CcvtResult<D> {
            // Coarse-to-fine warm start (see `Ccvt::high_quality`): converged
            // CCVTs at capacities c/16, c/4 (each ≥ WARM_MIN_CAPACITY) seed the
            // final run; their discrete densities use their own seed purposes.
            let mut start: Option<Vec<[f64; D]>> = None;
            if self.warm_start {
                let mut stages = Vec::new();
                let mut cc = self.capacity / 4;
                while cc >= WARM_MIN_CAPACITY {
                    stages.push(cc);
                    cc /= 4;
                }
                for (k, &cc) in stages.iter().rev().enumerate() {
                    let mut st = State::<D>::new(
                        self.n,
                        cc,
                        self.jitter,
                        seed,
                        POINTS_PURPOSE ^ (k as u64 + 1),
                        start.as_deref(),
                    );
                    run(&mut st, Self::DEFAULT_MAX_ITERATIONS, &mut |_, _| {});
                    start = Some(st.sites);
                }
            }
            let mut st = State::<D>::new(
                self.n,
                self.capacity,
                self.jitter,
                seed,
                POINTS_PURPOSE,
                start.as_deref(),
            );
            let (iterations, converged) = run(&mut st, self.max_iterations, trace);
            st.finish(iterations, converged)
        }
    }

    /// Smallest capacity of a warm-start stage.
    const WARM_MIN_CAPACITY: usize = 64;

    /// Iterates swap and centroid phases on `st` until stable or
    /// `max_iterations`; reports `(t, E_t)` to `trace`; returns the iterations
    /// run and whether the state is stable.
    fn run<const D: usize>(
        st: &mut State<D>,
        max_iterations: usize,
        trace: &mut dyn FnMut(usize, f64),
    ) -> (usize, bool) {
        let m = (st.n * st.c) as f64;
        trace(0, st.total_energy() / m);
        let mut iterations = 0;
        while iterations < max_iterations {
            iterations += 1;
            let swaps = st.swap_phase();
            st.centroid_phase();
            trace(iterations, st.total_energy() / m);
            // A stable assignment is converged once every site is also the
            // centroid of its points seen from itself (see
            // `recentre_straddling`); otherwise iterate on.
            if swaps == 0 && st.recentre_straddling() == 0 {
                return (iterations, true);
            }
        }
        (iterations, false)
    }

    impl<const D: usize> Generate<D> for Ccvt<D> {
        fn n(&self) -> u64 {
            self.n as u64
        }

        #[inline(always)]
        fn gen_simd<I: crate::simd::Isa, S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
            let r = self.generate(seed);
            let first = first as usize;
            for i in 0..sink.len() {
                sink.put(i, r.sites[first + i]);
            }
        }

        fn gen_scalar<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
            self.gen_simd::<crate::simd::Wide, S>(seed, first, sink);
        }
    }

    /// Squared toroidal distance.
    #[inline(always)]
    fn dist2<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
        let mut s = 0.0;
        for j in 0..D {
            let d = torus_delta(a[j] - b[j]);
            s += d * d;
        }
        s
    }

    /// Bit-interleaved (Morton) key of integer cell coordinates.
    fn morton<const D: usize>(c: [u32; D]) -> u64 {
        let bits = 64 / D;
        let mut key = 0u64;
        for b in 0..bits.min(32) {
            for (j, &cj) in c.iter().enumerate() {
                key |= u64::from((cj >> b) & 1) << (b * D + j);
            }
        }
        key
    }

    /// Cell `c` of a `g`-grid as the integer coordinates of its centre on the
    /// `2¹⁶` grid, so that points and sites share one Morton curve.
    fn quantise<const D: usize>(c: [u32; D], g: u64) -> [u32; D] {
        c.map(|x| ((f64::from(x) + 0.5) / g as f64 * 65536.0) as u32)
    }

    /// Uniform `f64` in `[0, 1)` from two outputs of `rng`.
    fn unit(rng: &mut Pcg32) -> f64 {
        let lo = u64::from(rng.next_u32());
        let hi = u64::from(rng.next_u32());
        unit_f64(lo | (hi << 32))
    }

    /// Uniform integer in `[0, bound)` (multiply-shift on 64 random bits; bias
    /// below `bound/2⁶⁴`).
    fn below(rng: &mut Pcg32, bound: u64) -> u64 {
        let lo = u64::from(rng.next_u32());
        let hi = u64::from(rng.next_u32());
        ((u128::from(lo | (hi << 32)) * u128::from(bound)) >> 64) as u64
    }

    /// `M` jittered points in distinct cells of a `g^D` grid, in Morton order.
    fn discrete_points<const D: usize>(m: usize, jitter: f64, rng: &mut Pcg32) -> Vec<[f64; D]> {
        let mut g = crate::num::scalar::floor(libm::pow(m as f64, 1.0 / D as f64)).max(1.0) as u64;
        while g.pow(D as u32) < m as u64 {
            g += 1;
        }
        while g > 1 && (g - 1).pow(D as u32) >= m as u64 {
            g -= 1;
        }
        let total = g.pow(D as u32);
        let mut cells: Vec<u64> = (0..total).collect();
        if total > m as u64 {
            // Partial Fisher–Yates: the first m entries are a uniform m-subset.
            for k in 0..m {
                let r = k + below(rng, total - k as u64) as usize;
                cells.swap(k, r);
            }
            cells.truncate(m);
        }
        let coords = |cell: u64| -> [u32; D] {
            let mut c = [0u32; D];
            let mut rest = cell;
            for cj in c.iter_mut() {
                *cj = (rest % g) as u32;
                rest /= g;
            }
            c
        };
        let mut keyed: Vec<(u64, u64)> = cells
            .iter()
            .map(|&c| (morton(quantise::<D>(coords(c), g)), c))
            .collect();
        keyed.sort_unstable();
        let inv = 1.0 / g as f64;
        let below_one = 1.0 - f64::EPSILON / 2.0;
        keyed
            .iter()
            .map(|&(_, cell)| {
                let c = coords(cell);
                let mut p = [0.0f64; D];
                for j in 0..D {
                    let u = 0.5 + jitter * (unit(rng) - 0.5);
                    p[j] = ((f64::from(c[j]) + u) * inv).min(below_one);
                }
                p
            })
            .collect()
    }

    /// Working state of one run. Site `i` owns the slots `i·c .. (i+1)·c` of
    /// `slab`/`ids` (exactly `c` each, by construction).
    struct State<const D: usize> {
        n: usize,
        c: usize,
        sites: Vec<[f64; D]>,
        slab: Vec<[f64; D]>,
        ids: Vec<u32>,
        radius: Vec<f64>,
        energy: Vec<f64>,
        changed_prev: Vec<bool>,
        changed_cur: Vec<bool>,
        // neighbour grid
        g: usize,
        cell_start: Vec<u32>,
        cell_sites: Vec<u32>,
        stamp: Vec<u32>,
        scratch_cells: Vec<usize>,
        hi: Vec<(f64, u32)>,
        hj: Vec<(f64, u32)>,
    }

    impl<const D: usize> State<D> {
        /// Initial state with `c` points per site: the discrete density drawn
        /// from `seed.pcg(points_purpose)`, the sites either `N` uniform random
        /// points (`start = None`) or the given sites (`Some`, e.g. a coarser
        /// CCVT), in both cases re-ordered along the Morton curve.
        fn new(
            n: usize,
            c: usize,
            jitter: f64,
            seed: Seed,
            points_purpose: u64,
            start: Option<&[[f64; D]]>,
        ) -> Self {
            let mut prng = seed.pcg(points_purpose);
            let slab = discrete_points::<D>(n * c, jitter, &mut prng);
            let mut srng = seed.pcg(SITES_PURPOSE);
            let mut keyed: Vec<(u64, [f64; D])> = (0..n)
                .map(|i| {
                    let p = match start {
                        Some(s) => s[i],
                        None => {
                            let mut p = [0.0f64; D];
                            for x in p.iter_mut() {
                                *x = unit(&mut srng);
                            }
                            p
                        }
                    };
                    let q = p.map(|x| (x * 65536.0) as u32);
                    (morton(q), p)
                })
                .collect();
            keyed.sort_unstable_by_key(|a| a.0);
            let sites: Vec<[f64; D]> = keyed.into_iter().map(|(_, p)| p).collect();
            let g = crate::num::scalar::floor(libm::pow(n as f64, 1.0 / D as f64) + 1e-9).max(1.0)
                as usize;
            let mut st = Self {
                n,
                c,
                sites,
                ids: (0..(n * c) as u32).collect(),
                slab,
                radius: vec![0.0; n],
                energy: vec![0.0; n],
                changed_prev: vec![true; n],
                changed_cur: vec![false; n],
                g,
                cell_start: vec![0; g.pow(D as u32) + 1],
                cell_sites: Vec::new(),
                stamp: vec![u32::MAX; n],
                scratch_cells: Vec::new(),
                hi: Vec::with_capacity(c),
                hj: Vec::with_capacity(c),
            };
            // Initial partition: every discrete point goes to its nearest random
            // site; the points, ordered by (Morton rank of that site, Morton order
            // of the point), are cut into runs of `c`; each site moves to the
            // centroid of its run.
            let owner = st.nearest_sites();
            let mut order: Vec<u64> = owner
                .iter()
                .enumerate()
                .map(|(k, &o)| (u64::from(o) << 32) | k as u64)
                .collect();
            order.sort_unstable();
            let slab: Vec<[f64; D]> = order
                .iter()
                .map(|&key| st.slab[(key & 0xFFFF_FFFF) as usize])
                .collect();
            st.ids = order.iter().map(|&key| key as u32).collect();
            st.slab = slab;
            st.changed_cur.iter_mut().for_each(|x| *x = true);
            st.centroid_phase();
            st
        }

        /// Index of the nearest site of every discrete point (ties to the lower
        /// index), by a ring search in the site grid.
        fn nearest_sites(&mut self) -> Vec<u32> {
            self.radius.iter_mut().for_each(|r| *r = 0.0);
            self.build_grid();
            let g = self.g as i64;
            let h = 1.0 / g as f64;
            let mut owner = Vec::with_capacity(self.slab.len());
            for p in &self.slab {
                let pc: [i64; D] = core::array::from_fn(|j| ((p[j] * g as f64) as i64).min(g - 1));
                let mut best = f64::INFINITY;
                let mut bi = 0u32;
                let mut r = 0i64;
                loop {
                    let w = 2 * r + 1;
                    let mut idx = [0i64; D];
                    'cells: loop {
                        if idx.iter().any(|&o| (o - r).abs() == r) || r == 0 {
                            let mut cell = 0usize;
                            for j in (0..D).rev() {
                                cell = cell * self.g + (pc[j] + idx[j] - r).rem_euclid(g) as usize;
                            }
                            let (a, b) = (
                                self.cell_start[cell] as usize,
                                self.cell_start[cell + 1] as usize,
                            );
                            for &site in &self.cell_sites[a..b] {
                                let d = dist2(p, &self.sites[site as usize]);
                                if d < best || (d == best && site < bi) {
                                    best = d;
                                    bi = site;
                                }
                            }
                        }
                        if !odometer_step(&mut idx, &[w; D]) {
                            break 'cells;
                        }
                    }
                    if w >= g || (best.is_finite() && best <= (r as f64 * h) * (r as f64 * h)) {
                        break;
                    }
                    r += 1;
                }
                owner.push(bi);
            }
            owner
        }

        fn total_energy(&self) -> f64 {
            self.energy.iter().sum()
        }

        /// Recomputes the bounding radius and energy of site `i`.
        fn measure(&mut self, i: usize) {
            let s = self.sites[i];
            let mut r2 = 0.0f64;
            let mut e = 0.0;
            for x in &self.slab[i * self.c..(i + 1) * self.c] {
                let d = dist2(x, &s);
                r2 = r2.max(d);
                e += d;
            }
            self.radius[i] = crate::num::scalar::sqrt(r2);
            self.energy[i] = e;
        }

        /// Grid cells covered by the bounding box of site `i` into `scratch_cells`.
        fn cover(&mut self, i: usize) {
            let g = self.g as i64;
            let s = self.sites[i];
            let r = self.radius[i];
            let mut lo = [0i64; D];
            let mut len = [0i64; D];
            for j in 0..D {
                let a = crate::num::scalar::floor((s[j] - r) * g as f64) as i64;
                let b = crate::num::scalar::floor((s[j] + r) * g as f64) as i64;
                if b - a + 1 >= g {
                    lo[j] = 0;
                    len[j] = g;
                } else {
                    lo[j] = a;
                    len[j] = b - a + 1;
                }
            }
            self.scratch_cells.clear();
            let mut idx = [0i64; D];
            loop {
                let mut cell = 0usize;
                for j in (0..D).rev() {
                    cell = cell * self.g + (lo[j] + idx[j]).rem_euclid(g) as usize;
                }
                self.scratch_cells.push(cell);
                if !odometer_step(&mut idx, &len) {
                    return;
                }
            }
        }

        /// Enters every site into the grid cells its bounding box covers (CSR).
        fn build_grid(&mut self) {
            let ncell = self.cell_start.len() - 1;
            self.cell_start.iter_mut().for_each(|x| *x = 0);
            for i in 0..self.n {
                self.cover(i);
                for k in 0..self.scratch_cells.len() {
                    self.cell_start[self.scratch_cells[k] + 1] += 1;
                }
            }
            for k in 0..ncell {
                self.cell_start[k + 1] += self.cell_start[k];
            }
            self.cell_sites.clear();
            self.cell_sites.resize(self.cell_start[ncell] as usize, 0);
            let mut fill: Vec<u32> = self.cell_start[..ncell].to_vec();
            for i in 0..self.n {
                self.cover(i);
                for k in 0..self.scratch_cells.len() {
                    let cell = self.scratch_cells[k];
                    self.cell_sites[fill[cell] as usize] = i as u32;
                    fill[cell] += 1;
                }
            }
        }

        /// One swap phase over all candidate pairs; returns the number of exchanges.
        fn swap_phase(&mut self) -> usize {
            self.build_grid();
            self.changed_cur.iter_mut().for_each(|x| *x = false);
            self.stamp.iter_mut().for_each(|x| *x = u32::MAX);
            let mut swaps = 0;
            let mut cells = Vec::new();
            for i in 0..self.n {
                self.cover(i);
                core::mem::swap(&mut cells, &mut self.scratch_cells);
                for &cell in &cells {
                    let (a, b) = (
                        self.cell_start[cell] as usize,
                        self.cell_start[cell + 1] as usize,
                    );
                    for t in a..b {
                        let j = self.cell_sites[t] as usize;
                        if j <= i || self.stamp[j] == i as u32 {
                            continue;
                        }
                        self.stamp[j] = i as u32;
                        if !(self.changed_prev[i]
                            || self.changed_prev[j]
                            || self.changed_cur[i]
                            || self.changed_cur[j])
                        {
                            continue;
                        }
                        let rr = self.radius[i] + self.radius[j];
                        if dist2(&self.sites[i], &self.sites[j]) >= rr * rr {
                            continue;
                        }
                        let k = self.swap_pair(i, j);
                        if k > 0 {
                            swaps += k;
                            self.changed_cur[i] = true;
                            self.changed_cur[j] = true;
                        }
                    }
                }
                core::mem::swap(&mut cells, &mut self.scratch_cells);
            }
            swaps
        }

        /// Balzer's exchange between sites `i` and `j` with fixed sites; returns
        /// the number of points exchanged.
        fn swap_pair(&mut self, i: usize, j: usize) -> usize {
            let c = self.c;
            let (si, sj) = (self.sites[i], self.sites[j]);
            let mut max_i = f64::NEG_INFINITY;
            let mut max_j = f64::NEG_INFINITY;
            let mut hi_all = core::mem::take(&mut self.hi);
            let mut hj_all = core::mem::take(&mut self.hj);
            hi_all.clear();
            hj_all.clear();
            for t in 0..c {
                let x = &self.slab[i * c + t];
                let h = dist2(x, &si) - dist2(x, &sj);
                max_i = max_i.max(h);
                hi_all.push((h, t as u32));
            }
            for t in 0..c {
                let y = &self.slab[j * c + t];
                let h = dist2(y, &sj) - dist2(y, &si);
                max_j = max_j.max(h);
                hj_all.push((h, t as u32));
            }
            let mut k = 0;
            if max_i + max_j > 0.0 {
                hi_all.retain(|e| e.0 + max_j > 0.0);
                hj_all.retain(|e| e.0 + max_i > 0.0);
                hi_all.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
                hj_all.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
                while k < hi_all.len() && k < hj_all.len() && hi_all[k].0 + hj_all[k].0 > 0.0 {
                    let a = i * c + hi_all[k].1 as usize;
                    let b = j * c + hj_all[k].1 as usize;
                    self.slab.swap(a, b);
                    self.ids.swap(a, b);
                    k += 1;
                }
            }
            self.hi = hi_all;
            self.hj = hj_all;
            k
        }

        /// Re-centres every site that is not the toroidal centroid of its
        /// points in its own frame, and returns how many moved.
        ///
        /// A centroid step takes the mean offset `wrap(x − s)` seen from the
        /// site's position before the step. When a site's points straddle the
        /// antipode of that position, an offset wraps differently seen from
        /// the new position, and the new site is one point's worth (`1/c` per
        /// such point) off its centroid. Here each site's offsets are summed
        /// from where it is; a sum of `1/4` or more on an axis (exact
        /// centroids give rounding noise, a changed wrap gives ±1) repeats the
        /// step from there until no offset changes its wrap. A moved site is
        /// marked changed, so the next swap phase re-examines its pairs. Each
        /// step lowers the energy (the mean minimises the squared offsets, and
        /// a toroidal distance is at most its offset). Sites already at their
        /// centroids are not touched, so runs where this never happens keep
        /// their values bit for bit.
        fn recentre_straddling(&mut self) -> usize {
            const PASSES: usize = 8;
            let c = self.c;
            let inv = 1.0 / c as f64;
            let mut moved = 0;
            for i in 0..self.n {
                let mut s = self.sites[i];
                let mut changed = false;
                for _ in 0..PASSES {
                    let mut sum = [0.0f64; D];
                    for x in &self.slab[i * c..(i + 1) * c] {
                        for j in 0..D {
                            sum[j] += torus_delta(x[j] - s[j]);
                        }
                    }
                    if sum.iter().all(|v| v.abs() < 0.25) {
                        break;
                    }
                    for j in 0..D {
                        s[j] = frac(s[j] + sum[j] * inv);
                    }
                    changed = true;
                }
                if changed {
                    self.sites[i] = s;
                    self.measure(i);
                    self.changed_prev[i] = true;
                    moved += 1;
                }
            }
            moved
        }

        /// Moves every changed site to the toroidal centroid of its points.
        fn centroid_phase(&mut self) {
            let c = self.c;
            for i in 0..self.n {
                if !self.changed_cur[i] {
                    continue;
                }
                let s = self.sites[i];
                let mut sum = [0.0f64; D];
                for x in &self.slab[i * c..(i + 1) * c] {
                    for j in 0..D {
                        sum[j] += torus_delta(x[j] - s[j]);
                    }
                }
                let inv = 1.0 / c as f64;
                let mut ns = s;
                for j in 0..D {
                    ns[j] = frac(s[j] + sum[j] * inv);
                }
                self.sites[i] = ns;
                self.measure(i);
            }
            core::mem::swap(&mut self.changed_prev, &mut self.changed_cur);
        }

        fn finish(self, iterations: usize, converged: bool) -> CcvtResult<D> {
            let energy = self.total_energy() / (self.n * self.c) as f64;
            let mut points = vec![[0.0f64; D]; self.n * self.c];
            let mut assignment = vec![0u32; self.n * self.c];
            for (slot, (&id, p)) in self.ids.iter().zip(&self.slab).enumerate() {
                points[id as usize] = *p;
                assignment[id as usize] = (slot / self.c) as u32;
            }
            let sites = self.sites.iter().map(|s| s.map(to_unit_f32)).collect();
            CcvtResult {
                sites,
                sites_f64: self.sites,
                points,
                assignment,
                iterations,
                converged,
                energy,
            }
        }
    }
}
