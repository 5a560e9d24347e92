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
use super::{check_n, Strata, MAX_STRATA};
use crate::error::PatternError;
use crate::hash::{
    apply16, apply_with, in_sixteen_bits, key_word_x8, narrow_words_x8, permute, rotation_x8,
    widen, PermuteX8, Shape, KEY_WORDS, ROTATION, SMALL_DOMAIN,
};
use crate::num::lane::Wu32x8;
use crate::rng::{Counter, Seed};
use wide::{u16x16, u32x8};

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

    #[inline(always)]
    fn gen_simd<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
        if !self.correlated && in_sixteen_bits(self.rows) && in_sixteen_bits(self.cols) {
            self.gen_mj16(seed, first, sink);
        } else {
            self.gen_tiled(seed, first, sink);
        }
    }

    /// Multi-jitter with both permutation domains narrow (`16 < m, n ≤ 2¹⁶`):
    /// the permutations run in sixteen 16-bit lanes
    /// ([`crate::hash::apply16`]). The key words (top halves; the rotation
    /// as `d = n − c`) of `π_x`, one key per column, are tabulated per tile
    /// of [`MJ_TILE`] columns, and those of `π_y`, one per row, per tile of
    /// [`TILE`] rows, eight keys at a time. Values as [`Grid::gen_scalar`].
    fn gen_mj16<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let len = sink.len() as u64;
        if len == 0 {
            return;
        }
        let key = seed.counter(PURPOSE);
        let (kx, ky, step) = self.keys(seed);
        let m = u64::from(self.cols);
        let axis = Strata::new(self.cols * self.rows);
        let (row_shape, col_shape) = (Shape::new(self.rows), Shape::new(self.cols));
        let end = first + len;
        // Padded by 8·GROUP lanes: a group starts at an in-range block (at
        // most column MJ_TILE − 8 of the tile); its last vector of sixteen
        // starts 8·GROUP − 16 further and reads 16, ending before
        // MJ_TILE + 8·GROUP.
        let mut xw = [[0u16; MJ_TILE + 8 * GROUP]; KEY_WORDS];
        let mut yw = [[0u16; TILE]; KEY_WORDS];
        let lane = u32x8::new(core::array::from_fn(|l| l as u32));
        let lane16 = u16x16::new(core::array::from_fn(|l| l as u16));
        let (vn, vstep) = (u32x8::splat(self.rows), u32x8::splat(step));
        let ymax = u16x16::splat((self.cols - 1) as u16);
        let (mut bx0, mut by0) = (key.lanes(2 * first, 2), key.lanes(2 * first + 1, 2));
        let (mut r0, mut c0) = (0, 0);
        walk_tiles(m, first, end, MJ_TILE, |tile| match tile {
            Tile::Rows { start, count } => {
                r0 = start;
                for t in (0..count).step_by(8) {
                    let rows = u32x8::splat(start as u32 + t as u32) + lane;
                    tabulate16(&col_shape, u32x8::splat(ky) + rows * vstep, &mut yw, t);
                }
            }
            Tile::Cols { start, count } => {
                c0 = start;
                for t in (0..count).step_by(8) {
                    let cols = u32x8::splat(start as u32 + t as u32) + lane;
                    tabulate16(&row_shape, u32x8::splat(kx) + cols * vstep, &mut xw, t);
                }
            }
            Tile::Run { j, lo, hi } => {
                let k0 = j * m + lo;
                let count = (hi - lo) as usize;
                let t0 = (lo - c0) as usize;
                let jj = (j - r0) as usize;
                bx0.seek(2 * k0, 2);
                by0.seek(2 * k0 + 1, 2);
                let (mut bx, mut by) = (bx0.clone(), by0.clone());
                let vrow = u32x8::splat((j * m) as u32);
                let vj = u16x16::splat(j as u16);
                let blocks = count / 8;
                let mut b = 0;
                while b < blocks {
                    let g = (blocks - b).min(GROUP);
                    let i0 = lo as u32 + 8 * b as u32;
                    // π_x: the row index in every lane, column keys from the
                    // table; lanes past the range read padding.
                    let px = apply16(&row_shape, [vj; GROUP / 2], |c, w| {
                        let at = t0 + 8 * b + 16 * c;
                        match xw[w][at..].first_chunk::<16>() {
                            Some(a) => u16x16::new(*a),
                            None => u16x16::ZERO,
                        }
                    });
                    // π_y: this row's key; columns past the row's end clamped
                    // into [0, m) (their values are not used).
                    let iy: [u16x16; GROUP / 2] = core::array::from_fn(|c| {
                        (u16x16::splat((i0 + 16 * c as u32) as u16) + lane16).min(ymax)
                    });
                    let py = apply16(&col_shape, iy, |_, w| u16x16::splat(yw[w][jj]));
                    let (px, py) = (px.map(widen), py.map(widen));
                    for v in 0..g {
                        let vi = u32x8::splat(i0 + 8 * v as u32) + lane;
                        let x = axis
                            .point_x8(Wu32x8(vi * vn + px[v / 2][v % 2]), Wu32x8(bx.next_u32x8()));
                        let y =
                            axis.point_x8(Wu32x8(vrow + py[v / 2][v % 2]), Wu32x8(by.next_u32x8()));
                        sink.put8::<Wu32x8>((k0 - first) as usize + 8 * (b + v), [x, y]);
                    }
                    b += g;
                }
                self.put_tail(sink, (key, (kx, ky, step), &axis), first, k0, count);
            }
        });
    }

    /// Both variants, tile by tile. Point `(i, j)` (column `i`, row `j`) has
    /// `x` from `π_x(j)` with key `k_x + i·s` and `y` from `π_y(i)` with key
    /// `k_y + j·s`, where `s = 0` for correlated multi-jitter. Rows run over
    /// tiles of columns:
    /// * correlated: both permutations are tabulated per tile of [`TILE`]
    ///   rows and columns, so a point costs two table reads and its jitter;
    /// * multi-jittered: the `y` keys are one per row, expanded once per row
    ///   run; the `x` keys are one per column, and their expansions (round
    ///   keys and rotation, [`crate::hash::key_words`]) are tabulated per tile
    ///   of [`MJ_TILE`] columns and reused by every row.
    ///
    /// Values as [`Grid::gen_scalar`].
    fn gen_tiled<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let len = sink.len() as u64;
        if len == 0 {
            return;
        }
        let key = seed.counter(PURPOSE);
        let (kx, ky, step) = self.keys(seed);
        let correlated = self.correlated;
        let m = u64::from(self.cols);
        let axis = Strata::new(self.cols * self.rows);
        let by_row = PermuteX8::new(self.rows, u32x8::splat(kx));
        let by_col = PermuteX8::new(self.cols, u32x8::splat(ky));
        // π_y of the current row (multi-jitter), re-keyed in place.
        let mut own = by_col;
        let end = first + len;
        let (mut tx, mut ty) = ([0u32; TILE], [0u32; TILE]);
        let mut words = [[0u32; MJ_TILE]; KEY_WORDS];
        let row_shape = Shape::new(self.rows);
        let col_tile = if correlated { TILE } else { MJ_TILE };
        let (vn, vstep, vkx) = (
            u32x8::splat(self.rows),
            u32x8::splat(step),
            u32x8::splat(kx),
        );
        let lane = u32x8::new(core::array::from_fn(|l| l as u32));
        let (mut bx0, mut by0) = (key.lanes(2 * first, 2), key.lanes(2 * first + 1, 2));
        let (mut r0, mut c0) = (0, 0);
        walk_tiles(m, first, end, col_tile, |tile| match tile {
            Tile::Rows { start, count } => {
                r0 = start;
                if correlated {
                    tabulate(&by_row, self.rows, start, count, &mut tx);
                }
            }
            Tile::Cols { start, count } => {
                c0 = start;
                if correlated {
                    tabulate(&by_col, self.cols, start, count, &mut ty);
                } else if self.rows > SMALL_DOMAIN {
                    // Eight columns at a time; columns past `count` (up to
                    // MJ_TILE) get keys too and are never read in range.
                    for t in (0..count).step_by(8) {
                        let col = u32x8::splat(start as u32 + t as u32) + lane;
                        let keys = vkx + col * vstep;
                        for w in 0..row_shape.round_words() {
                            let word = key_word_x8(keys, w, &row_shape).to_array();
                            words[w][t..t + 8].copy_from_slice(&word);
                        }
                        let c = rotation_x8(keys, self.rows).to_array();
                        words[ROTATION][t..t + 8].copy_from_slice(&c);
                    }
                }
            }
            Tile::Run { j, lo, hi } => {
                let k0 = j * m + lo;
                let count = (hi - lo) as usize;
                let t0 = (lo - c0) as usize;
                // Local copies (kept in registers), moved without rehashing.
                bx0.seek(2 * k0, 2);
                by0.seek(2 * k0 + 1, 2);
                let (mut bx, mut by) = (bx0.clone(), by0.clone());
                let vrow = u32x8::splat((j * m) as u32);
                let vj = u32x8::splat(j as u32);
                // π_y with this row's key (k_y itself for CMJ: by_col).
                let row_perm = if correlated {
                    &by_col
                } else {
                    let key = ky.wrapping_add((j as u32).wrapping_mul(step));
                    own.set_key(u32x8::splat(key));
                    &own
                };
                let mut vi = u32x8::splat(lo as u32) + lane;
                // Groups of four blocks: four independent permutation chains
                // in flight (PermuteX8::apply4).
                let blocks = count / 8;
                let mut b = 0;
                while b < blocks {
                    let g = (blocks - b).min(4);
                    let vis: [u32x8; 4] = core::array::from_fn(|v| vi + u32x8::splat(8 * v as u32));
                    let (px, py): ([u32x8; 4], [u32x8; 4]) = if correlated {
                        (
                            [u32x8::splat(tx[(j - r0) as usize]); 4],
                            core::array::from_fn(|v| {
                                let t = (t0 + 8 * (b + v)).min(TILE - 8);
                                u32x8::new(core::array::from_fn(|l| ty[t + l]))
                            }),
                        )
                    } else {
                        // π_x: per-lane column keys from the table.
                        let col_word = |v: usize, w: usize| {
                            let t = (t0 + 8 * (b + v)).min(MJ_TILE - 8);
                            match words[w][t..].first_chunk::<8>() {
                                Some(a) => u32x8::new(*a),
                                None => u32x8::ZERO,
                            }
                        };
                        // π_x's input is the row index, valid in every lane,
                        // so all four vectors run even when fewer are in range.
                        let px: [u32x8; 4] = if self.rows > SMALL_DOMAIN {
                            apply_with(&row_shape, [vj; 4], col_word)
                        } else {
                            core::array::from_fn(|v| {
                                PermuteX8::new(self.rows, vkx + vis[v] * vstep).apply(vj)
                            })
                        };
                        // Only the g blocks in range for π_y: lanes past the
                        // row's end are outside [0, m), where a cycle walk need
                        // not end.
                        let py = if g == 4 {
                            PermuteX8::apply4([row_perm; 4], vis)
                        } else {
                            let mut py = [u32x8::ZERO; 4];
                            for v in 0..g {
                                py[v] = row_perm.apply(vis[v]);
                            }
                            py
                        };
                        (px, py)
                    };
                    for v in 0..g {
                        let x = axis.point_x8(Wu32x8(vis[v] * vn + px[v]), Wu32x8(bx.next_u32x8()));
                        let y = axis.point_x8(Wu32x8(vrow + py[v]), Wu32x8(by.next_u32x8()));
                        sink.put8::<Wu32x8>((k0 - first) as usize + 8 * (b + v), [x, y]);
                    }
                    b += g;
                    vi += u32x8::splat(8 * g as u32);
                }
                self.put_tail(sink, (key, (kx, ky, step), &axis), first, k0, count);
            }
        });
    }

    /// The points of a row run past its last whole block of eight, `k0` its
    /// first point and `count` its length, by scalar code.
    #[inline]
    fn put_tail<S: Sink<2>>(
        &self,
        sink: &mut S,
        (key, keys, axis): (Counter, (u32, u32, u32), &Strata),
        first: u64,
        k0: u64,
        count: usize,
    ) {
        for t in 8 * (count / 8)..count {
            let k = k0 + t as u64;
            sink.put((k - first) as usize, self.point(key, keys, axis, k));
        }
    }

    /// Point `k` (column `i = k mod m`, row `j = ⌊k/m⌋`) by scalar code.
    #[inline]
    fn point(
        &self,
        key: Counter,
        (kx, ky, step): (u32, u32, u32),
        axis: &Strata,
        k: u64,
    ) -> [f32; 2] {
        let (m, n) = (self.cols, self.rows);
        let i = (k % u64::from(m)) as u32;
        let j = (k / u64::from(m)) as u32;
        let px = permute(j, n, kx.wrapping_add(i.wrapping_mul(step)));
        let py = permute(i, m, ky.wrapping_add(j.wrapping_mul(step)));
        [
            axis.point(i * n + px, key.at(2 * k)),
            axis.point(j * m + py, key.at(2 * k + 1)),
        ]
    }

    fn gen_scalar<S: Sink<2>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let key = seed.counter(PURPOSE);
        let keys = self.keys(seed);
        let axis = Strata::new(self.cols * self.rows);
        for t in 0..sink.len() {
            sink.put(t, self.point(key, keys, &axis, first + t as u64));
        }
    }
}

/// Blocks of eight points per group of the 16-bit multi-jitter path (its
/// permutations run `GROUP/2` chains of sixteen lanes).
const GROUP: usize = 8;

/// One step of [`walk_tiles`].
enum Tile {
    /// A tile of `count` rows from row `start` begins.
    Rows { start: u64, count: usize },
    /// `count` columns from column `start` of the current rows hold points
    /// of the range.
    Cols { start: u64, count: usize },
    /// Row `j`'s points in the current tile: columns `[lo, hi)`.
    Run { j: u64, lo: u64, hi: u64 },
}

/// Walks the points `[first, end)` of a grid of `m` columns (point `k` in
/// column `k mod m`, row `⌊k/m⌋`) by tiles of [`TILE`] rows and `col_tile`
/// columns, column tiles within row tiles, skipping tiles without points of
/// the range; within a tile, rows in order.
fn walk_tiles(m: u64, first: u64, end: u64, col_tile: usize, mut f: impl FnMut(Tile)) {
    let (j0, j1) = (first / m, (end - 1) / m + 1);
    let mut r0 = j0;
    while r0 < j1 {
        let rc = ((j1 - r0) as usize).min(TILE);
        f(Tile::Rows {
            start: r0,
            count: rc,
        });
        let mut c0 = 0;
        while c0 < m {
            let cc = ((m - c0) as usize).min(col_tile);
            let col_lo = |j: u64| first.saturating_sub(j * m).max(c0);
            let col_hi = |j: u64| (end - j * m).min(c0 + cc as u64);
            if (r0..r0 + rc as u64).any(|j| col_lo(j) < col_hi(j)) {
                f(Tile::Cols {
                    start: c0,
                    count: cc,
                });
                for j in r0..r0 + rc as u64 {
                    let (lo, hi) = (col_lo(j), col_hi(j));
                    if lo < hi {
                        f(Tile::Run { j, lo, hi });
                    }
                }
            }
            c0 += cc as u64;
        }
        r0 += rc as u64;
    }
}

/// Rows and columns per permutation table of correlated multi-jitter (two
/// stack tables of 1 KiB).
const TILE: usize = 256;

/// Columns per key-word table of multi-jitter (`KEY_WORDS·64` words, 6.4 KiB).
const MJ_TILE: usize = 64;

/// Key words of eight permutations of a narrow domain `s` (lane keys
/// `keys`, [`crate::hash::narrow_words_x8`]) into columns `t..t + 8` of
/// `table`.
fn tabulate16<const W: usize>(s: &Shape, keys: u32x8, table: &mut [[u16; W]; KEY_WORDS], t: usize) {
    let words = narrow_words_x8(keys, s);
    for w in (0..s.round_words()).chain([ROTATION]) {
        table[w][t..t + 8].copy_from_slice(&words[w]);
    }
}

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
            #[inline(always)]
            fn gen_simd<I: crate::simd::Isa, S: Sink<2>>(
                &self,
                seed: Seed,
                first: u64,
                sink: &mut S,
            ) {
                // Written over `wide`'s types: every level runs this.
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
