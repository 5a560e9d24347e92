//! Multi-jittered (Chiu, Shirley & Wang 1994) and correlated multi-jittered
//! (Kensler 2013) sampling in 2D.
//!
//! Both use an `m × n` grid of coarse cells (`m` columns, `n` rows, `N = m·n`).
//! Point `k` sits in coarse cell `(i, j) = (k mod m, ⌊k/m⌋)` and
//!
//! ```text
//! x = (i + (π_i(j) + u)/n)/m = (i·n + π_i(j) + u)/N
//! y = (j + (σ_j(i) + v)/m)/n = (j·m + σ_j(i) + v)/N
//! ```
//!
//! where `π_i` permutes `[0, n)` and `σ_j` permutes `[0, m)`. The fine `x` index
//! `i·n + π_i(j)` takes every value of `[0, N)` once, and so does the fine `y`
//! index: both 1D projections are stratified into `N` strata (N-rooks) while every
//! coarse cell holds one point (jittered). Multi-jittered sampling draws the
//! permutations independently per column and per row (the "shuffle" of Chiu et
//! al.); correlated multi-jittered sampling uses one `π` for all columns and one
//! `σ` for all rows, which lowers discrepancy further (Kensler 2013).
//!
//! References: K. Chiu, P. Shirley, C. Wang, *Multi-Jittered Sampling*, Graphics
//! Gems IV (1994); A. Kensler, *Correlated Multi-Jittered Sampling*, Pixar
//! Technical Memo 13-01 (2013).

use super::sealed::{Generate, Sink};
use super::{advance8, build, check_n, drive32, lanes_of, Strata, MAX_STRATA};
use crate::error::PatternError;
use crate::hash::{permute, PermuteX8};
use crate::rng::{CounterX8, Seed};
use wide::{f32x8, u32x8};

const PURPOSE: u64 = 0x4D4A_4954;

#[derive(Clone, Debug, PartialEq, Eq)]
struct Grid {
    cols: u32,
    rows: u32,
    correlated: bool,
}

impl Grid {
    fn with_grid(cols: usize, rows: usize, correlated: bool) -> Result<Self, PatternError> {
        if cols == 0 {
            return Err(PatternError::ZeroStrata { axis: 0 });
        }
        if rows == 0 {
            return Err(PatternError::ZeroStrata { axis: 1 });
        }
        let n = (cols as u64).saturating_mul(rows as u64);
        if n > MAX_STRATA {
            return Err(PatternError::TooManyPoints { max: MAX_STRATA });
        }
        Ok(Self {
            cols: cols as u32,
            rows: rows as u32,
            correlated,
        })
    }

    /// `cols` = the largest divisor of `n` not above `√n`, `rows = n / cols`.
    fn new(n: usize, correlated: bool) -> Result<Self, PatternError> {
        check_n(n, MAX_STRATA)?;
        let mut cols = crate::num::scalar::sqrt(n as f64) as usize;
        while cols * cols > n {
            cols -= 1;
        }
        while (cols + 1) * (cols + 1) <= n {
            cols += 1;
        }
        while !n.is_multiple_of(cols) {
            cols -= 1;
        }
        Self::with_grid(cols, n / cols, correlated)
    }

    fn n(&self) -> u64 {
        u64::from(self.cols) * u64::from(self.rows)
    }

    /// Keys `(x, y)`: per column `i` / row `j` for MJ, shared for CMJ.
    fn keys(&self, seed: Seed) -> (u32, u32, u32) {
        let kx = seed.stream(PURPOSE + 1) as u32;
        let ky = seed.stream(PURPOSE + 2) as u32;
        let step = if self.correlated { 0 } else { 0x9E37_79B9 };
        (kx, ky, step)
    }

    fn gen_simd<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
        if self.correlated {
            self.gen_correlated(seed, first, sink);
            return;
        }
        let key = seed.counter(PURPOSE);
        let mut lanes: [CounterX8; 2] =
            core::array::from_fn(|j| key.lanes(first * 2 + j as u64, 2));
        let (kx, ky, step) = self.keys(seed);
        let (m, n) = (self.cols, self.rows);
        let axis = Strata::new(m * n);
        let radix = [u32x8::splat(m), u32x8::splat(n)];
        let mut cell = lanes_of(|l| {
            let k = first + l as u64;
            [
                (k % u64::from(m)) as u32,
                ((k / u64::from(m)) % u64::from(n)) as u32,
            ]
        });
        let (vm, vn, vstep) = (u32x8::splat(m), u32x8::splat(n), u32x8::splat(step));
        // Correlated: one key per axis for every lane, so the round keys are
        // computed once; otherwise per column / row, per block.
        let fixed = (
            PermuteX8::new(n, u32x8::splat(kx)),
            PermuteX8::new(m, u32x8::splat(ky)),
        );
        let correlated = self.correlated;
        drive32(sink, || {
            let cells: [[u32x8; 2]; 4] = build([u32x8::ZERO; 2], |_| {
                let c = cell;
                advance8(&mut cell, &radix);
                c
            });
            let rows: [u32x8; 4] = build(u32x8::ZERO, |b| cells[b][1]);
            let cols: [u32x8; 4] = build(u32x8::ZERO, |b| cells[b][0]);
            let (px, py) = if correlated {
                (
                    PermuteX8::apply4([&fixed.0; 4], rows),
                    PermuteX8::apply4([&fixed.1; 4], cols),
                )
            } else {
                // One key per column (row) and lane: the round keys differ per
                // vector, and four sets of them would not fit in registers, so
                // each vector is permuted on its own.
                (
                    build(u32x8::ZERO, |b| {
                        PermuteX8::new(n, u32x8::splat(kx) + cols[b] * vstep).apply(rows[b])
                    }),
                    build(u32x8::ZERO, |b| {
                        PermuteX8::new(m, u32x8::splat(ky) + rows[b] * vstep).apply(cols[b])
                    }),
                )
            };
            build([f32x8::ZERO; 2], |b| {
                let [i, j] = cells[b];
                [
                    axis.point_x8(i * vn + px[b], lanes[0].next_u32x8()),
                    axis.point_x8(j * vm + py[b], lanes[1].next_u32x8()),
                ]
            })
        });
    }

    /// Correlated multi-jitter: `x` of point `(i, j)` uses `π_x(j)` (one value
    /// per row) and `y` uses `π_y(i)` (one per column), so both permutations
    /// are tabulated for tiles of [`TILE`] rows and columns and every point is
    /// a table read plus its jitter; values as [`Grid::gen_scalar`].
    fn gen_correlated<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let len = sink.len() as u64;
        if len == 0 {
            return;
        }
        let key = seed.counter(PURPOSE);
        let (kx, ky, _) = self.keys(seed);
        let (m, n) = (u64::from(self.cols), u64::from(self.rows));
        let axis = Strata::new(self.cols * self.rows);
        let by_row = PermuteX8::new(self.rows, u32x8::splat(kx));
        let by_col = PermuteX8::new(self.cols, u32x8::splat(ky));
        let end = first + len;
        let (j0, j1) = (first / m, (end - 1) / m + 1);
        let (mut tx, mut ty) = ([0u32; TILE], [0u32; TILE]);
        let vn = u32x8::splat(self.rows);
        let lane = u32x8::new(core::array::from_fn(|l| l as u32));
        let mut r0 = j0;
        while r0 < j1 {
            let rc = ((j1 - r0) as usize).min(TILE);
            tabulate(&by_row, self.rows, r0, rc, &mut tx);
            let mut c0 = 0;
            while c0 < m {
                let cc = ((m - c0) as usize).min(TILE);
                // Columns [c0, c0 + cc) of rows [r0, r0 + rc) that lie in the range.
                let col_lo = |j: u64| first.saturating_sub(j * m).max(c0);
                let col_hi = |j: u64| (end - j * m).min(c0 + cc as u64);
                if (r0..r0 + rc as u64).all(|j| col_lo(j) >= col_hi(j)) {
                    c0 += cc as u64;
                    continue;
                }
                tabulate(&by_col, self.cols, c0, cc, &mut ty);
                for j in r0..r0 + rc as u64 {
                    let (lo, hi) = (col_lo(j), col_hi(j));
                    if lo >= hi {
                        continue;
                    }
                    let px = tx[(j - r0) as usize];
                    let k0 = j * m + lo;
                    let count = (hi - lo) as usize;
                    let t0 = (lo - c0) as usize;
                    let mut bx = key.lanes(2 * k0, 2);
                    let mut by = key.lanes(2 * k0 + 1, 2);
                    let (vpx, vrow) = (u32x8::splat(px), u32x8::splat((j * m) as u32));
                    let mut vi = u32x8::splat(lo as u32) + lane;
                    for b in 0..count / 8 {
                        let t = t0 + 8 * b;
                        let py = u32x8::new(core::array::from_fn(|l| ty[t + l]));
                        let x = axis.point_x8(vi * vn + vpx, bx.next_u32x8());
                        let y = axis.point_x8(vrow + py, by.next_u32x8());
                        sink.put8((k0 - first) as usize + 8 * b, [x, y]);
                        vi += u32x8::splat(8);
                    }
                    for t in 8 * (count / 8)..count {
                        let (k, i) = (k0 + t as u64, lo + t as u64);
                        let x = axis.point((i * n) as u32 + px, key.at(2 * k));
                        let y = axis.point((j * m) as u32 + ty[t0 + t], key.at(2 * k + 1));
                        sink.put((k - first) as usize, [x, y]);
                    }
                }
                c0 += cc as u64;
            }
            r0 += rc as u64;
        }
    }

    fn gen_scalar<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let key = seed.counter(PURPOSE);
        let (kx, ky, step) = self.keys(seed);
        let (m, n) = (self.cols, self.rows);
        let axis = Strata::new(m * n);
        for t in 0..sink.len() {
            let k = first + t as u64;
            let i = (k % u64::from(m)) as u32;
            let j = (k / u64::from(m)) as u32;
            let px = permute(j, n, kx.wrapping_add(i.wrapping_mul(step)));
            let py = permute(i, m, ky.wrapping_add(j.wrapping_mul(step)));
            let x = axis.point(i * n + px, key.at(2 * k));
            let y = axis.point(j * m + py, key.at(2 * k + 1));
            sink.put(t, [x, y]);
        }
    }
}

/// Rows and columns per permutation table of correlated multi-jitter (two
/// stack tables of 1 KiB).
const TILE: usize = 256;

/// `t[v] = π(start + v)` for `v < count` (`count ≤ TILE`), 32 at a time. The
/// padding reads `π(n − 1)`: an index outside the domain could start a
/// cycle-walk that never returns to it.
fn tabulate(p: &PermuteX8, n: u32, start: u64, count: usize, t: &mut [u32; TILE]) {
    let groups = count.div_ceil(32);
    for g in 0..groups {
        let idx: [u32x8; 4] = core::array::from_fn(|v| {
            u32x8::new(core::array::from_fn(|l| {
                (start + (32 * g + 8 * v + l) as u64).min(u64::from(n) - 1) as u32
            }))
        });
        let out = PermuteX8::apply4([p; 4], idx);
        for (v, o) in out.iter().enumerate() {
            let at = 32 * g + 8 * v;
            if at < TILE {
                t[at..at + 8].copy_from_slice(&o.to_array());
            }
        }
    }
}

macro_rules! grid_pattern {
    ($(#[$doc:meta])* $name:ident, $correlated:expr) => {
        $(#[$doc])*
        #[derive(Clone, Debug, PartialEq, Eq)]
        pub struct $name {
            grid: Grid,
        }

        impl $name {
            /// `n` points on the most square grid with `cols · rows = n`
            /// (`cols` = the largest divisor of `n` not above `√n`; a prime `n` gives
            /// a `1 × n` grid, which is still stratified in both projections).
            ///
            /// # Errors
            /// [`PatternError::ZeroPoints`] for `n = 0`,
            /// [`PatternError::TooManyPoints`] for `n > 2²⁴`.
            pub fn new(n: usize) -> Result<Self, PatternError> {
                Ok(Self { grid: Grid::new(n, $correlated)? })
            }

            /// `cols × rows` coarse cells, `N = cols · rows`.
            ///
            /// # Errors
            /// [`PatternError::ZeroStrata`] for a zero count (axis 0 = `cols`,
            /// axis 1 = `rows`), [`PatternError::TooManyPoints`] for `N > 2²⁴`.
            pub fn with_grid(cols: usize, rows: usize) -> Result<Self, PatternError> {
                Ok(Self { grid: Grid::with_grid(cols, rows, $correlated)? })
            }

            /// `(cols, rows)`.
            #[must_use]
            pub fn grid(&self) -> (usize, usize) {
                (self.grid.cols as usize, self.grid.rows as usize)
            }
        }

        impl Generate<2> for $name {
            fn n(&self) -> u64 {
                self.grid.n()
            }
            fn gen_simd<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
                self.grid.gen_simd(seed, first, sink)
            }
            fn gen_scalar<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
                self.grid.gen_scalar(seed, first, sink)
            }
        }
    };
}

grid_pattern!(
    /// Multi-jittered sampling (Chiu, Shirley & Wang 1994): jittered in the
    /// `cols × rows` grid and N-rooks in both projections, with independent
    /// shuffles per column and per row. See the [module docs](self).
    MultiJittered,
    false
);

grid_pattern!(
    /// Correlated multi-jittered sampling (Kensler 2013): as [`MultiJittered`] but
    /// one shuffle shared by all columns and one by all rows.
    /// See the [module docs](self).
    CorrelatedMultiJittered,
    true
);
