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
