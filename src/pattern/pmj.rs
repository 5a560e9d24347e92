//! Progressive multi-jittered (0,2) sequences, PMJ02 and PMJ02BN: [`Pmj02`]
//! (the algorithm, its proof and the references are in its documentation).

use crate::error::PatternError;
use crate::rng::{Pcg32, Seed};

/// Largest number of points of a [`Pmj02`] sequence, `2²⁴`: coordinates are
/// 24-bit fixed point (`f32`-exact), so a prefix of `2^K` points with `K ≤ 24` is
/// stratified down to intervals of width `2⁻ᴷ`.
pub const PMJ02_MAX_POINTS: u64 = 1 << 24;

/// Default number of best-candidate trials per admissible cell of
/// [`Pmj02::blue_noise`]: `10`, as UTK's PMJ02 sampler. The spreading gain
/// grows little beyond it while the cost grows linearly: mean nearest-neighbour
/// distance at `N = 1024` (64 seeds, units `1/√N`) 0.649 for PMJ02, 0.653 / 0.661
/// / 0.666 / 0.668 / 0.671 for `k` = 1 / 3 / 10 / 30 / 100 (per-set sd ≈ 0.015).
pub const PMJ02BN_DEFAULT_CANDIDATES: u32 = 10;

/// Largest accepted candidate count of [`Pmj02::with_candidates`].
pub const PMJ02BN_MAX_CANDIDATES: u32 = 256;

/// Seed purpose of the sequence (`"PMJ02\0\0\0"`).
const PURPOSE: u64 = 0x504D_4A30_3200_0000;

/// Bits of the fixed-point coordinates.
const BITS: u32 = 24;

/// Scale from a 24-bit integer to `[0, 1)`.
const TO_UNIT: f32 = 1.0 / 16_777_216.0;

/// Candidate cells per point in the blue-noise variant (two sub-quadrants).
const MAX_CELLS: usize = 2;

/// A progressive multi-jittered (0,2) sequence of `N` points in `[0, 1)²`
/// (Christensen, Kensler & Kilpatrick 2018[^1]), plain ([`Pmj02::new`]) or with
/// best-candidate blue noise ([`Pmj02::blue_noise`], "PMJ02BN").
///
/// Every power-of-two prefix of `2^K` points (`K ≤ 24`) has exactly one point in
/// every elementary interval `2⁻ᵃ × 2⁻⁽ᴷ⁻ᵃ⁾`, `a = 0 … K`, exactly as `f32`
/// values (coordinates are multiples of `2⁻²⁴`). A pattern of `n` points is the
/// first `n` points of the sequence: for one seed, `Pmj02::new(n)` is a prefix of
/// `Pmj02::new(n')` for `n ≤ n'`.
///
/// Generation is sequential (point `i` depends on the points before it),
/// `O(n log n)` time, allocation-free with caller scratch
/// ([`Pmj02::generate`], [`Pmj02::scratch_len`]). The [`super::Pattern`]
/// implementation (`alloc` feature) allocates, and **a fill of any range
/// `first .. first + len` generates the whole prefix of `first + len` points**:
/// fill all points at once where possible. For random access per pixel and
/// sample index, generate tables once: [`super::Pmj02Tables`].
///
/// # The sequence
///
/// Write a coordinate as a 24-bit integer `X = x·2²⁴` and `X_a` for its top `a`
/// bits. The `2^K` points of a prefix are *stratified in every elementary
/// interval* of area `2⁻ᴷ` when, for every shape `a = 0 … K`, the map
/// `p ↦ (X_a(p), Y_{K−a}(p))` is a bijection onto `{0,1}ᴷ`: every interval
/// `2⁻ᵃ × 2⁻⁽ᴷ⁻ᵃ⁾` holds exactly one point (a `(0, K, 2)`-net in base 2). PMJ02
/// asks this of every power-of-two prefix `K = 0, 1, 2, …`.
///
/// Points are generated in batches: the `N = 2^{K−1}` points of a net extended by
/// `N` new ones to a net of level `K`. Christensen et al. place new point `N + i`
/// in a sub-quadrant chosen from point `i`:
/// * `K = 2m + 1` (from `4ᵐ` points): the sub-quadrant diagonally opposite point
///   `i` inside its square `2⁻ᵐ` cell;
/// * `K = 2m + 2` (from `2·4ᵐ` points, two per `2⁻ᵐ` cell on a diagonal): for
///   `i < 4ᵐ` the sub-quadrant horizontally or vertically next to point `i`, and
///   for point `N + 4ᵐ + i` the last empty sub-quadrant of that cell.
///
/// # Choosing the position (Pharr's problem, solved by forced digits)
///
/// Pharr 2019[^2] builds, per new point, the set of positions that lie in no
/// occupied elementary interval instead of Christensen's rejection loop. For
/// base-2 `(0,2)` nets that set is very small, and it can be written down digit
/// by digit. Every interval of level `K` is one of two children of an interval of
/// level `K − 1`, split either in `y` (shape `a`, parent `(X_a, Y_{K−1−a})`) or in
/// `x` (shape `a + 1`, same parent). The parent holds exactly one old point, so
/// exactly one child is free: the new point must take the *other* value of the
/// digit the old point has there. With the sub-quadrant fixing the top
/// `c = ⌈K/2⌉` digits of both coordinates, this forces
/// * `y_b = ¬y_b(p)` for `b = c+1 … K`, with `p` the old point of the parent of
///   shape `a = K − b` at `(X_a, Y_{b−1})` (all `a < c`, so `X_a` is known), and
/// * `x_b = ¬x_b(p)` for `b = c+1 … K`, with `p` the old point of the parent of
///   shape `b − 1` at `(X_{b−1}, Y_{K−b})` (`K − b < c`, so `Y_{K−b}` is known),
///
/// so each new point costs `2(K − c)` bit look-ups in per-shape tables of the
/// old points' digits, `O(K)` per point and `O(N log N)` in all (no rejection, no
/// candidate lists). The valid region inside the sub-quadrant is a single cell of
/// side `2⁻ᴷ`: the remaining `24 − K` bits of each coordinate are free (uniform
/// jitter).
///
/// That the forced cells of all new points never collide is a theorem, proved
/// by induction on `K`: *a `(0, K−1, 2)`-net `P` in base 2 has exactly one
/// completion to a `(0, K, 2)`-net at the resolution `2⁻ᴷ` per axis.* For
/// `K = 1` the new point takes the other half in both axes. For `K > 1`, the
/// halves `x < ½` and `x ≥ ½` of `P`, stretched by 2 in `x`, are
/// `(0, K−2, 2)`-nets, so by induction each has a unique completion (which fixes
/// the new points' digits `x₁ … x_K`, `y₁ … y_{K−1}`), and the shape `a = 0`
/// forces `y_K`: each strip `Y_{K−1}` holds one old point and one new point, and
/// they must differ in `y_K`. The sub-quadrants of the construction are exactly
/// the free intervals of shape `c` (`K` even) or lie in free intervals of shapes
/// `c−1` and `c` (`K` odd), one per new point, so every new point lands on its
/// cell of that completion. New points therefore never need to be entered into
/// the tables during a batch.
///
/// # PMJ02BN: best candidate
///
/// [`Pmj02::blue_noise`] draws `k` candidates (default
/// [`PMJ02BN_DEFAULT_CANDIDATES`]) in each admissible cell — the free jitter
/// digits, and for the first half of an even-`K` batch both admissible
/// sub-quadrants — and keeps the one farthest (toroidal distance) from the points
/// already placed, found with a background grid of one point per cell at most
/// (Mitchell's best-candidate rule, as Christensen et al.). The theorem above
/// leaves less freedom than the sub-quadrant suggests: at a power-of-two prefix
/// `2^K` the positions are fixed to `2⁻ᴷ` by the earlier points' digits, so the
/// blue-noise gain comes from choosing the low digits of earlier points, which
/// become the high digits of later ones, and from the order within a batch. The
/// gain is modest: at `N = 1024` (256 seeds, `tests/pmj.rs`) the mean
/// nearest-neighbour distance grows from `0.653/√N` to `0.663/√N` and the mean
/// minimum distance from `0.125/√N` to `0.139/√N`; the stratification is the
/// same. Cost: the `k` candidates are compared with the points of the grid cells
/// around their sub-quadrant, about 7× the time of PMJ02 at `k = 10`.
///
/// # Randomisation
///
/// The construction is random from the seed (first point uniform, the
/// horizontal/vertical choices fair coins, the jitter uniform). Every choice is
/// equivariant under flipping any digit subtree of either coordinate (a nested
/// uniform, "Owen", scramble maps free intervals to free intervals and
/// sub-quadrant choices to sub-quadrant choices), so the law of a PMJ02 sequence
/// is invariant under Owen scrambling: scrambling a realisation again would not
/// change its distribution, and every point is uniform on `[0, 1)²` (unbiased
/// estimates). No extra scramble is applied. PMJ02BN is not scramble-invariant
/// (distances are not), and a scramble would undo its blue noise; a toroidal
/// shift ([`super::Shifted`]) keeps its distances but moves the points off the
/// dyadic elementary intervals, so neither is applied by default either.
///
/// [^1]: P. Christensen, A. Kensler, C. Kilpatrick, *Progressive Multi-Jittered
///   Sample Sequences*, Computer Graphics Forum 37(4) (EGSR), 2018.
/// [^2]: M. Pharr, *Efficient Generation of Points that Satisfy Two-Dimensional
///   Elementary Intervals*, JCGT 8(1), 2019.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pmj02 {
    n: usize,
    /// Best-candidate trials per admissible cell; 0 for plain PMJ02.
    candidates: u32,
}

impl Pmj02 {
    /// PMJ02 with `n` points.
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`] if `n = 0`, [`PatternError::TooManyPoints`]
    /// if `n >` [`PMJ02_MAX_POINTS`].
    pub fn new(n: usize) -> Result<Self, PatternError> {
        super::check_n(n, PMJ02_MAX_POINTS)?;
        Ok(Self { n, candidates: 0 })
    }

    /// PMJ02BN with `n` points: PMJ02 whose free digits and sub-quadrant order
    /// are chosen by best candidate ([`PMJ02BN_DEFAULT_CANDIDATES`] trials per
    /// admissible cell), see [`Pmj02`].
    ///
    /// # Errors
    /// As [`Pmj02::new`].
    pub fn blue_noise(n: usize) -> Result<Self, PatternError> {
        super::check_n(n, PMJ02_MAX_POINTS)?;
        Ok(Self {
            n,
            candidates: PMJ02BN_DEFAULT_CANDIDATES,
        })
    }

    /// The blue-noise variant with `k` best-candidate trials per admissible cell
    /// (also turns a plain PMJ02 into PMJ02BN).
    ///
    /// # Errors
    /// [`PatternError::Parameter`] (`"candidates"`) unless
    /// `1 ≤ k ≤` [`PMJ02BN_MAX_CANDIDATES`].
    pub fn with_candidates(self, k: u32) -> Result<Self, PatternError> {
        if k == 0 || k > PMJ02BN_MAX_CANDIDATES {
            return Err(PatternError::Parameter {
                name: "candidates",
                value: u64::from(k),
                min: 1,
                max: u64::from(PMJ02BN_MAX_CANDIDATES),
            });
        }
        Ok(Self {
            n: self.n,
            candidates: k,
        })
    }

    /// `N`, the number of points.
    #[must_use]
    pub fn n(&self) -> usize {
        self.n
    }

    /// Whether this is the blue-noise variant (PMJ02BN).
    #[must_use]
    pub fn is_blue_noise(&self) -> bool {
        self.candidates > 0
    }

    /// Best-candidate trials per admissible cell (0 for plain PMJ02).
    #[must_use]
    pub fn candidates(&self) -> u32 {
        self.candidates
    }

    /// Length of the `scratch` buffer of [`Pmj02::generate`] ([`u32`] words), for
    /// `K = ⌈log₂ N⌉`: the digit tables of the last batch, `2⌊K/2⌋` bit sets of
    /// `2^{K−1}` bits; for PMJ02BN also the background grid, `2^{2⌈K/2⌉}` cells.
    /// About `K·N/64` words for PMJ02 (`N` a power of two) and `N` to `2N` more
    /// for PMJ02BN.
    #[must_use]
    pub fn scratch_len(&self) -> usize {
        scratch_len_for(self.n, self.candidates > 0)
    }

    /// Writes the `N` points into `out`. `scratch` is overwritten; its contents
    /// on entry do not matter. No allocation.
    ///
    /// # Errors
    /// [`PatternError::OutputLength`] if `out.len() != N`,
    /// [`PatternError::Scratch`] if `scratch.len() <` [`Pmj02::scratch_len`].
    pub fn generate(
        &self,
        seed: Seed,
        out: &mut [[f32; 2]],
        scratch: &mut [u32],
    ) -> Result<(), PatternError> {
        if out.len() != self.n {
            return Err(PatternError::OutputLength {
                expected: self.n,
                got: out.len(),
            });
        }
        if scratch.len() < self.scratch_len() {
            return Err(PatternError::Scratch {
                expected: self.scratch_len(),
                got: scratch.len(),
            });
        }
        run(seed, self.candidates, out, scratch);
        Ok(())
    }

    /// The first `count ≤ N` points (allocates the scratch and the prefix).
    #[cfg(feature = "alloc")]
    fn prefix(&self, seed: Seed, count: usize) -> alloc::vec::Vec<[f32; 2]> {
        let mut out = alloc::vec![[0.0f32; 2]; count];
        let mut scratch = alloc::vec![0u32; scratch_len_for(count, self.candidates > 0)];
        run(seed, self.candidates, &mut out, &mut scratch);
        out
    }
}

#[cfg(feature = "alloc")]
impl super::Pattern<2> for Pmj02 {
    fn len(&self) -> usize {
        self.n
    }

    /// Generates the prefix `0 .. first + out.len()` (allocates) and copies the
    /// range.
    fn fill_range(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; 2]],
    ) -> Result<(), PatternError> {
        super::check_range(self.n as u64, first, out.len())?;
        if out.is_empty() {
            return Ok(());
        }
        let all = self.prefix(seed, first + out.len());
        out.copy_from_slice(&all[first..]);
        Ok(())
    }

    /// As [`super::Pattern::fill_range`] (the generator has no separate scalar
    /// path).
    fn fill_range_scalar(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; 2]],
    ) -> Result<(), PatternError> {
        self.fill_range(seed, first, out)
    }

    /// Generates the prefix `0 .. first + len` (allocates) and scatters the
    /// range.
    fn fill_range_soa(
        &self,
        seed: Seed,
        first: usize,
        out: [&mut [f32]; 2],
    ) -> Result<(), PatternError> {
        let len = super::soa_len(&out)?;
        super::check_range(self.n as u64, first, len)?;
        if len == 0 {
            return Ok(());
        }
        let all = self.prefix(seed, first + len);
        for (j, col) in out.into_iter().enumerate() {
            for (x, p) in col.iter_mut().zip(&all[first..]) {
                *x = p[j];
            }
        }
        Ok(())
    }
}

/// `K = ⌈log₂ count⌉`, the level of the last batch (0 for `count ≤ 1`).
fn levels(count: usize) -> u32 {
    if count <= 1 {
        0
    } else {
        usize::BITS - (count - 1).leading_zeros()
    }
}

/// Words of one digit table of level `k ≥ 1` (`2^{k−1}` bits).
fn table_words(k: u32) -> usize {
    (1usize << (k - 1)).div_ceil(32)
}

/// Words of all digit tables of level `k`: `2⌊k/2⌋` tables.
fn tables_len(k: u32) -> usize {
    2 * (k / 2) as usize * table_words(k)
}

/// Cells of the background grid of level `k`: `2^{⌈k/2⌉}` per axis.
fn grid_len(k: u32) -> usize {
    1usize << (2 * k.div_ceil(2))
}

fn scratch_len_for(count: usize, blue_noise: bool) -> usize {
    let k = levels(count);
    if k == 0 {
        return 0;
    }
    tables_len(k) + if blue_noise { grid_len(k) } else { 0 }
}

/// The 24-bit integer of a coordinate written by [`to_f32`] (exact).
#[inline(always)]
fn to_int(v: f32) -> u32 {
    (v * 16_777_216.0) as u32
}

/// A 24-bit integer as an `f32` in `[0, 1)` (exact).
#[inline(always)]
fn to_f32(v: u32) -> f32 {
    v as f32 * TO_UNIT
}

/// Bit `idx` of the bit set starting at word `base` of `t`.
#[inline(always)]
fn get_bit(t: &[u32], base: usize, idx: u32) -> u32 {
    (t[base + (idx >> 5) as usize] >> (idx & 31)) & 1
}

/// The digit tables of level `k` from the old points (the first `2^{k−1}` of
/// `pts`). Table `a < ⌊k/2⌋` holds, at the parent `(X_a, Y_{k−1−a})` of shape
/// `a` and level `k − 1`, the digit `y_{k−a}` of its old point; table
/// `⌊k/2⌋ + a − c` (`c = ⌈k/2⌉ ≤ a < k`) the digit `x_{a+1}`.
fn build_tables(k: u32, old: &[[f32; 2]], tables: &mut [u32]) {
    let h = k / 2;
    let c = k - h;
    let w = table_words(k);
    let tables = &mut tables[..tables_len(k)];
    tables.fill(0);
    for p in old {
        let xk = to_int(p[0]) >> (BITS - k);
        let yk = to_int(p[1]) >> (BITS - k);
        for a in 0..h {
            let idx = ((xk >> (k - a)) << (k - 1 - a)) | (yk >> (a + 1));
            let bit = (yk >> a) & 1;
            tables[a as usize * w + (idx >> 5) as usize] |= bit << (idx & 31);
        }
        for a in c..k {
            let idx = ((xk >> (k - a)) << (k - 1 - a)) | (yk >> (a + 1));
            let bit = (xk >> (k - 1 - a)) & 1;
            tables[(h + a - c) as usize * w + (idx >> 5) as usize] |= bit << (idx & 31);
        }
    }
}

/// The forced digits, for `L` independent points at once (their look-up chains
/// interleave): from the sub-quadrants `(xc, yc)` (top `c = ⌈k/2⌉` digits) to
/// the cells `(X_k, Y_k)` of side `2⁻ᵏ` (see [`Pmj02`]).
#[inline(always)]
fn descend<const L: usize>(
    k: u32,
    xc: [u32; L],
    yc: [u32; L],
    tables: &[u32],
) -> ([u32; L], [u32; L]) {
    let h = k / 2;
    let c = k - h;
    let w = table_words(k);
    let mut y = yc;
    let mut x = xc;
    for b in c + 1..=k {
        let a = k - b;
        for l in 0..L {
            let idx = ((xc[l] >> (c - a)) << (b - 1)) | y[l];
            let bit = get_bit(tables, a as usize * w, idx);
            y[l] = (y[l] << 1) | (bit ^ 1);
        }
        let a = b - 1;
        for l in 0..L {
            let idx = (x[l] << (k - b)) | (yc[l] >> (c - (k - b)));
            let bit = get_bit(tables, (h + a - c) as usize * w, idx);
            x[l] = (x[l] << 1) | (bit ^ 1);
        }
    }
    (x, y)
}

/// The admissible sub-quadrants (top `c = ⌈k/2⌉` digits of both coordinates) of
/// new point `j` of the batch of level `k` (`old = 2^{k−1}`), and how many there
/// are: one, or two for the first half of an even-`k` batch (horizontal and
/// vertical neighbour of point `j − old`). Reads points before `j` only.
#[inline(always)]
fn sub_quadrants(
    k: u32,
    old: usize,
    j: usize,
    out: &[[f32; 2]],
) -> ([(u32, u32); MAX_CELLS], usize) {
    let c = k.div_ceil(2);
    let top = |p: [f32; 2]| (to_int(p[0]) >> (BITS - c), to_int(p[1]) >> (BITS - c));
    let i = j - old;
    // At even k, points i and i + quarter share a 2^-(c-1) cell.
    let quarter = old / 2;
    let mut cells = [(0u32, 0u32); MAX_CELLS];
    if k % 2 == 1 {
        let (xp, yp) = top(out[i]);
        cells[0] = (xp ^ 1, yp ^ 1);
        (cells, 1)
    } else if i < quarter {
        let (xp, yp) = top(out[i]);
        cells[0] = (xp ^ 1, yp);
        cells[1] = (xp, yp ^ 1);
        (cells, 2)
    } else {
        let (xp, yp) = top(out[i - quarter]);
        let (xr, _) = top(out[old + i - quarter]);
        cells[0] = if xr != xp { (xp, yp ^ 1) } else { (xp ^ 1, yp) };
        (cells, 1)
    }
}

/// Plain PMJ02 point `j`: its sub-quadrant (a coin for two) and jitter, drawn
/// in this order from `rng`; the cell is left to [`descend`].
#[inline(always)]
fn plain_draws(
    k: u32,
    old: usize,
    j: usize,
    out: &[[f32; 2]],
    rng: &mut Pcg32,
) -> (u32, u32, u32, u32) {
    let (cells, ncells) = sub_quadrants(k, old, j, out);
    let cell = if ncells == 2 {
        cells[(rng.next_u32() >> 31) as usize]
    } else {
        cells[0]
    };
    let jx = jitter(rng, k);
    let jy = jitter(rng, k);
    (cell.0, cell.1, jx, jy)
}

/// Points interleaved by [`descend`] in plain PMJ02.
const LANES: usize = 4;

/// `24 − k` uniform jitter digits below a level-`k` cell.
#[inline(always)]
fn jitter(rng: &mut Pcg32, k: u32) -> u32 {
    let r = rng.next_u32() >> 8;
    if k >= BITS {
        0
    } else {
        r & ((1u32 << (BITS - k)) - 1)
    }
}

/// Toroidal distance² between two fixed-point points (units `2⁻²⁴`).
#[inline(always)]
fn torus_d2(a: [u32; 2], b: [u32; 2]) -> u64 {
    let mut s = 0u64;
    for j in 0..2 {
        let d = a[j].wrapping_sub(b[j]) & 0x00FF_FFFF;
        let d = u64::from(d.min((1 << BITS) - d));
        s += d * d;
    }
    s
}

/// Background grid of the blue-noise variant: `2^g × 2^g` cells, each holding
/// `index + 1` of its point (at most one) or 0.
struct Grid<'a> {
    cells: &'a mut [u32],
    g: u32,
}

impl Grid<'_> {
    #[inline(always)]
    fn cell(&self, p: [u32; 2]) -> (u32, u32) {
        (p[0] >> (BITS - self.g), p[1] >> (BITS - self.g))
    }

    #[inline(always)]
    fn insert(&mut self, p: [u32; 2], index: usize) {
        let (cx, cy) = self.cell(p);
        let i = ((cx << self.g) | cy) as usize;
        debug_assert_eq!(self.cells[i], 0, "two points in one grid cell");
        self.cells[i] = index as u32 + 1;
    }

    /// Updates `best[i]` to the squared distance from `cands[i]` to the nearest
    /// point of the grid (all candidates lie in the grid cell `(cx, cy)`): rings
    /// of cells around it, until every candidate's nearest point is closer than
    /// the next ring can be (`r·w` after ring `r`).
    fn nearest(
        &self,
        pts: &[[f32; 2]],
        (cx, cy): (u32, u32),
        cands: &[[u32; 2]],
        best: &mut [u64],
    ) {
        let side = 1i64 << self.g;
        let mask = (1u32 << self.g) - 1;
        let w = 1u64 << (BITS - self.g);
        let visit = |dx: i64, dy: i64, best: &mut [u64]| {
            let x = (i64::from(cx) + dx) as u32 & mask;
            let y = (i64::from(cy) + dy) as u32 & mask;
            let e = self.cells[((x << self.g) | y) as usize];
            if e != 0 {
                let p = pts[(e - 1) as usize];
                let q = [to_int(p[0]), to_int(p[1])];
                for (b, c) in best.iter_mut().zip(cands) {
                    *b = (*b).min(torus_d2(*c, q));
                }
            }
        };
        let mut r: i64 = 0;
        loop {
            if 2 * r + 1 >= side {
                for dx in 0..side {
                    for dy in 0..side {
                        visit(dx, dy, best);
                    }
                }
                return;
            }
            if r == 0 {
                visit(0, 0, best);
            } else {
                for d in -r..=r {
                    visit(d, -r, best);
                    visit(d, r, best);
                }
                for d in 1 - r..r {
                    visit(-r, d, best);
                    visit(r, d, best);
                }
            }
            let reach = r as u64 * w;
            if best.iter().all(|&b| b <= reach * reach) {
                return;
            }
            r += 1;
        }
    }
}

/// Generates `out.len()` points of the sequence (the first ones: any prefix of
/// the output is the output for a shorter length). `scratch` must hold
/// [`scratch_len_for`] words.
fn run(seed: Seed, candidates: u32, out: &mut [[f32; 2]], scratch: &mut [u32]) {
    let count = out.len();
    if count == 0 {
        return;
    }
    let mut rng = seed.pcg(PURPOSE);
    let x0 = rng.next_u32() >> 8;
    let y0 = rng.next_u32() >> 8;
    out[0] = [to_f32(x0), to_f32(y0)];
    let bn = candidates > 0;
    let kmax = levels(count);
    let mut cand = [[0u32; 2]; PMJ02BN_MAX_CANDIDATES as usize * MAX_CELLS];
    let mut best = [0u64; PMJ02BN_MAX_CANDIDATES as usize * MAX_CELLS];
    for k in 1..=kmax {
        let old = 1usize << (k - 1);
        let end = (2 * old).min(count);
        let (tables, rest) = scratch.split_at_mut(tables_len(k));
        build_tables(k, &out[..old], tables);
        let mut grid = Grid {
            cells: &mut rest[..if bn { grid_len(k) } else { 0 }],
            g: k.div_ceil(2),
        };
        if bn {
            grid.cells.fill(0);
            for (i, p) in out[..old].iter().enumerate() {
                grid.insert([to_int(p[0]), to_int(p[1])], i);
            }
        }
        let shift = BITS - k;
        if !bn {
            // Groups of LANES points whose sub-quadrants read only earlier
            // groups: within one half of an even batch (the second half reads the
            // first), anywhere in an odd one. Same draws, same order, as one by one.
            let half = if k % 2 == 0 { old + old / 2 } else { end };
            let mut j = old;
            while j < end {
                let stop = if j < half { half.min(end) } else { end };
                if j + LANES <= stop {
                    let (mut xc, mut yc, mut jx, mut jy) =
                        ([0u32; LANES], [0; LANES], [0; LANES], [0; LANES]);
                    for l in 0..LANES {
                        (xc[l], yc[l], jx[l], jy[l]) = plain_draws(k, old, j + l, out, &mut rng);
                    }
                    let (x, y) = descend(k, xc, yc, tables);
                    for l in 0..LANES {
                        out[j + l] = [
                            to_f32((x[l] << shift) | jx[l]),
                            to_f32((y[l] << shift) | jy[l]),
                        ];
                    }
                    j += LANES;
                } else {
                    let (xc, yc, jx, jy) = plain_draws(k, old, j, out, &mut rng);
                    let (x, y) = descend(k, [xc], [yc], tables);
                    out[j] = [to_f32((x[0] << shift) | jx), to_f32((y[0] << shift) | jy)];
                    j += 1;
                }
            }
            continue;
        }
        for j in old..end {
            let (cells, ncells) = sub_quadrants(k, old, j, out);
            let kc = candidates as usize;
            let mut m = 0;
            for &(xc, yc) in &cells[..ncells] {
                let (x, y) = descend(k, [xc], [yc], tables);
                for _ in 0..kc {
                    cand[m] = [
                        (x[0] << shift) | jitter(&mut rng, k),
                        (y[0] << shift) | jitter(&mut rng, k),
                    ];
                    m += 1;
                }
            }
            best[..m].fill(u64::MAX);
            for q in 0..ncells {
                let a = q * kc;
                grid.nearest(
                    out,
                    grid.cell(cand[a]),
                    &cand[a..a + kc],
                    &mut best[a..a + kc],
                );
            }
            let mut arg = 0;
            for t in 1..m {
                if best[t] > best[arg] {
                    arg = t;
                }
            }
            let p = cand[arg];
            out[j] = [to_f32(p[0]), to_f32(p[1])];
            grid.insert(p, j);
        }
    }
}
