//! The direct (exact) Fourier amplitudes of one realisation, accumulated in
//! chunks of samples. See the [module documentation](super) for the maths.

use super::{check_finite, zero_prefix, AmplitudeView, Coordinate, Grid, ONE_D_STRIDE, TILE};
use crate::error::SpectrumError;
use crate::geom::Direction;
use crate::num::lane::F64Lane;
use crate::num::{cis_turns, frac_centered, Complex, Dd};
use crate::primitive::Segment;
use core::f64::consts::TAU;

/// Tiles (of [`TILE`] columns) per column block: the column tables of one
/// block stay in L2 while every row runs over them.
const BLOCK_TILES: usize = 8;
/// Block length of the exact phase tables: `e^{−2πijx}` is the product of an
/// exactly reduced `e^{−2πi·16q·x}` and an exactly reduced `e^{−2πi·r·x}`.
const PHASE_BLOCK: usize = 16;

/// `e^{−2πi·j·x}` at one `j` as `(re, im)`, with `j·x` formed exactly
/// ([`Dd::prod`]) and reduced modulo 1 exactly ([`cis_turns`]).
#[inline]
fn exact_phase(j: usize, x: f64) -> (f64, f64) {
    let z = cis_turns(Dd::prod(j as f64, x));
    (z.re, z.im)
}

/// `x − round(x) ∈ [−1/2, 1/2]`: the coordinate modulo 1, exactly, for every
/// finite `x` (the same phases `e^{−2πijx}` for every integer `j`).
#[inline]
fn reduce(x: f64) -> f64 {
    frac_centered(Dd::new(x))
}

/// Blocked exact phase table of one coordinate: `e^{−2πijx}` is the product of
/// the exactly reduced `e^{−2πi·16q·x}` and `e^{−2πi·r·x}` (`j = 16q + r`), so
/// the error does not grow with `j`: absolute error ≤ 4 ulp of 1 for every `j`
/// and finite `x`, with one `sin`/`cos` pair per 16 frequencies.
struct PhaseTable {
    x: f64,
    small: [(f64, f64); PHASE_BLOCK],
}

impl PhaseTable {
    #[inline]
    fn new(x: f64, k: usize) -> Self {
        // x mod 1 as x − round(x) ∈ [−1/2, 1/2], which is exact for every
        // finite x (unlike x − ⌊x⌋, which rounds for x ∈ (−1, 0) and would
        // put an error of j·2⁻⁵⁴ into every phase), so j·x cannot overflow
        // for coordinates far outside [0, 1) and the phases are those of x.
        let x = reduce(x);
        let mut small = [(1.0, 0.0); PHASE_BLOCK];
        for (r, e) in small.iter_mut().enumerate().skip(1).take(k) {
            *e = exact_phase(r, x);
        }
        PhaseTable { x, small }
    }

    /// `put(j, re, im)` for `j ∈ [lo, min(lo + 15, hi)]`, `lo` a multiple of 16.
    #[inline]
    fn block(&self, lo: usize, hi: usize, mut put: impl FnMut(usize, f64, f64)) {
        let (br, bi) = if lo == 0 {
            (1.0, 0.0)
        } else {
            exact_phase(lo, self.x)
        };
        for (r, &(sr, si)) in self.small.iter().enumerate() {
            if lo + r > hi {
                break;
            }
            put(lo + r, br * sr - bi * si, br * si + bi * sr);
        }
    }
}

/// `e^{−2πi·j·x}` for `j = 0..=k`, passed to `put(j, re, im)` ([`PhaseTable`]).
#[inline]
pub(crate) fn phases(x: f64, k: usize, mut put: impl FnMut(usize, f64, f64)) {
    let t = PhaseTable::new(x, k);
    let mut lo = 0;
    while lo <= k {
        t.block(lo, k, &mut put);
        lo += PHASE_BLOCK;
    }
}

/// Row tables as `[j][k]` arrays of one chunk: `e^{−2πi j x_k}` for `j` in
/// `[lo, lo + len)` (negative `j` are the conjugates).
fn fill_row_table(
    re: &mut [f64],
    im: &mut [f64],
    p: usize,
    k: usize,
    lo: i64,
    slot: usize,
    x: f64,
) {
    let len = re.len() / p;
    phases(x, k, |j, c, s| {
        let jp = j as i64 - lo;
        if (0..len as i64).contains(&jp) {
            re[jp as usize * p + slot] = c;
            im[jp as usize * p + slot] = s;
        }
        let jn = -(j as i64) - lo;
        if j > 0 && (0..len as i64).contains(&jn) {
            re[jn as usize * p + slot] = c;
            im[jn as usize * p + slot] = -s;
        }
    });
}

/// The complex Fourier amplitudes `F(ν) = Σ_k w_k(ν)·e^{−2πiν·x_k}` of one
/// realisation on the half grid of a [`Grid`], accumulated over chunks.
///
/// * points: `w_k = 1` ([`Dft::add_points`]);
/// * segments of length `λ_k` along `ω_k` centred at `x_k`:
///   `w_k = sinc(λ_k ν·ω_k)`, `sinc(t) = sin(πt)/(πt)` ([`Dft::add_segments`],
///   [`Dft::add_segment_pattern`]), the Fourier coefficient of the unit-mass box
///   kernel along the segment (Singh et al. 2017; `docs/theory.md`, Segment
///   and line spectra).
///
/// Storage is the caller's buffer `B` (`&mut [f64]`, or `Vec<f64>` with the
/// `alloc` feature) of [`Dft::buffer_len`] values. Feeding a realisation in
/// chunks gives **bit-identical** amplitudes for any chunk size (each amplitude
/// is one multiply-and-add chain over the samples, in sample order), and the
/// SIMD and scalar paths agree bit for bit. The amplitudes, the power and the
/// ring means of the realisation are read through [`AmplitudeView`].
///
/// # Accuracy
/// Each phase is reduced modulo 1 exactly, so the error does not grow with the
/// frequency: `|F − F_exact| ≤ ~8ε·Σ_k|w_k|` for points at any `|ν| ≤ 2²⁰`
/// (`tests/spectrum.rs` bounds `max |F − F_ref|/N` against a reference sum at
/// `|ν|` up to 10⁴; the phase reduction is described in `docs/theory.md`,
/// Numerical methods).
#[derive(Clone, Debug)]
pub struct Dft<const D: usize, B> {
    grid: Grid<D>,
    buf: B,
    count: u64,
}

#[cfg(feature = "alloc")]
impl<const D: usize> Dft<D, alloc::vec::Vec<f64>> {
    /// A zeroed accumulator owning its buffer (**allocates**
    /// [`Dft::buffer_len`] values).
    #[must_use]
    pub fn new_vec(grid: Grid<D>) -> Self {
        Dft {
            grid,
            buf: alloc::vec![0.0; Self::buffer_len(grid)],
            count: 0,
        }
    }
}

impl<const D: usize, B> Dft<D, B> {
    /// The buffer length this grid needs: `2·rows·stride` (real and imaginary
    /// parts, rows padded to a multiple of the 8-column tile; a 1D grid of
    /// more than 64 frequencies is stored as `⌈(k+1)/64⌉` rows of 64).
    #[must_use]
    pub fn buffer_len(grid: Grid<D>) -> usize {
        2 * grid.storage_len()
    }

    /// Scratch values per sample needed by [`Dft::add_points`]: a chunk of `c`
    /// points needs `c ×` this many `f64`.
    #[must_use]
    pub fn points_scratch_per_sample(grid: Grid<D>) -> usize {
        2 * row_table_len(grid) + 2 * grid.stride() + 4
    }

    /// Scratch values per sample needed by the segment methods.
    #[must_use]
    pub fn segments_scratch_per_sample(grid: Grid<D>) -> usize {
        5 * row_table_len(grid) + 5 * grid.stride() + 8
    }

    /// The grid.
    #[must_use]
    pub fn grid(&self) -> Grid<D> {
        self.grid
    }

    /// Samples added since the last [`Dft::clear`].
    #[must_use]
    pub fn count(&self) -> u64 {
        self.count
    }
}

impl<const D: usize, B: AsRef<[f64]> + AsMut<[f64]>> Dft<D, B> {
    /// An accumulator over the caller's buffer, zeroed here.
    ///
    /// # Errors
    /// [`SpectrumError::Length`] if `buf` is shorter than [`Dft::buffer_len`].
    pub fn new(grid: Grid<D>, mut buf: B) -> Result<Self, SpectrumError> {
        zero_prefix(buf.as_mut(), Self::buffer_len(grid))?;
        Ok(Dft {
            grid,
            buf,
            count: 0,
        })
    }

    /// Zeroes the amplitudes and the count (start of a new realisation).
    pub fn clear(&mut self) {
        let n = Self::buffer_len(self.grid);
        self.buf.as_mut()[..n].fill(0.0);
        self.count = 0;
    }

    /// Adds points `x_k` (any finite coordinates; only `x mod 1` matters):
    /// `F(ν) += Σ_k e^{−2πiν·x_k}`.
    ///
    /// `scratch` holds the per-chunk phase tables; its length sets the chunk
    /// size `c = scratch.len() / points_scratch_per_sample(grid)` (at least 1;
    /// 64–256 is fastest). The result does not depend on `c`. Runs the SIMD
    /// path (`f64x4` multiply-adds, unfused).
    ///
    /// # Errors
    /// [`SpectrumError::NonFinite`] (naming `points` and the index) if a
    /// coordinate is NaN or ±∞, [`SpectrumError::Length`] if `scratch` is too
    /// short for one point. Nothing is added on error.
    pub fn add_points<T: Coordinate>(
        &mut self,
        points: &[[T; D]],
        scratch: &mut [f64],
    ) -> Result<(), SpectrumError> {
        crate::simd::dispatch(AddPoints {
            dft: self,
            points,
            scratch,
        })
    }

    /// [`Dft::add_points`] on the scalar reference path (bit-identical).
    ///
    /// # Errors
    /// As [`Dft::add_points`].
    pub fn add_points_scalar<T: Coordinate>(
        &mut self,
        points: &[[T; D]],
        scratch: &mut [f64],
    ) -> Result<(), SpectrumError> {
        self.add_points_lane::<f64, T>(points, scratch)
    }

    // `#[inline(always)]` down to the lane operations: the AVX2 copy
    // (`simd::dispatch`) must compile all of it with AVX2 enabled.
    #[inline(always)]
    fn add_points_lane<L: F64Lane, T: Coordinate>(
        &mut self,
        points: &[[T; D]],
        scratch: &mut [f64],
    ) -> Result<(), SpectrumError> {
        Grid::<D>::check_dim()?;
        check_finite("points", points.iter().map(|p| p.map(Coordinate::to_f64)))?;
        let g = self.grid;
        let per = Self::points_scratch_per_sample(g);
        let chunk = scratch.len() / per;
        if chunk == 0 {
            return Err(SpectrumError::Length {
                name: "scratch",
                expected: per,
                got: scratch.len(),
            });
        }
        for pts in points.chunks(chunk) {
            self.points_chunk::<L, T>(pts, &mut scratch[..per * pts.len()]);
        }
        self.count += points.len() as u64;
        Ok(())
    }

    #[inline(always)]
    fn points_chunk<L: F64Lane, T: Coordinate>(&mut self, pts: &[[T; D]], scratch: &mut [f64]) {
        let g = self.grid;
        let k = g.half_width();
        let p = pts.len();
        let stride = g.stride();
        let w = 2 * k + 1;
        let (row0, rest) = scratch.split_at_mut(2 * row0_len(g) * p);
        let (row1, rest) = rest.split_at_mut(if D == 3 { 2 * w * p } else { 0 });
        let (cols, gbuf) = rest.split_at_mut(2 * stride * p);
        let (r0re, r0im) = row0.split_at_mut(row0.len() / 2);
        let (r1re, r1im) = row1.split_at_mut(row1.len() / 2);
        let (col_lo, kc, ncols) = col_range(g);
        let ntiles = stride / TILE;
        cols.fill(0.0);
        for (slot, x) in pts.iter().enumerate() {
            if D == 1 {
                // Rows of the 1D storage: e^{−2πi·(64a)·x} = e^{−2πi·a·64·(x mod 1)}.
                let xr = (ONE_D_STRIDE as f64) * reduce(x[0].to_f64());
                fill_row_table(r0re, r0im, p, g.storage_rows() - 1, 0, slot, xr);
            } else {
                fill_row_table(r0re, r0im, p, k, 0, slot, x[0].to_f64());
            }
            if D == 3 {
                fill_row_table(r1re, r1im, p, k, -(k as i64), slot, x[1].to_f64());
            }
            let xc = x[D - 1].to_f64();
            phases(xc, kc, |j, c, s| {
                let mut put = |col: i64, s: f64| {
                    if (0..ncols).contains(&col) {
                        let (t, lane) = (col as usize / TILE, col as usize % TILE);
                        let base = (t * p + slot) * 2 * TILE;
                        cols[base + lane] = c;
                        cols[base + TILE + lane] = s;
                    }
                };
                put(j as i64 - col_lo, s);
                if j > 0 {
                    put(-(j as i64) - col_lo, -s);
                }
            });
        }
        let half = g.storage_len();
        let (f_re, f_im) = self.buf.as_mut()[..2 * half].split_at_mut(half);
        let gbuf = &mut gbuf[..4 * p];
        let rows = g.storage_rows();
        let mut t0 = 0;
        while t0 < ntiles {
            let t1 = (t0 + BLOCK_TILES).min(ntiles);
            let mut r = 0;
            while r < rows {
                let nr = if r + 1 < rows { 2 } else { 1 };
                for (i, gk) in gbuf.chunks_exact_mut(4).enumerate() {
                    for q in 0..nr {
                        let (gr, gi) = row_coefficient::<D>(r + q, i, p, k, r0re, r0im, r1re, r1im);
                        gk[2 * q] = gr;
                        gk[2 * q + 1] = gi;
                    }
                }
                for t in t0..t1 {
                    let tile = &cols[t * p * 2 * TILE..(t + 1) * p * 2 * TILE];
                    let c0 = t * TILE;
                    if nr == 2 {
                        tile_points::<L, 2>(f_re, f_im, r * stride + c0, stride, gbuf, tile);
                    } else {
                        tile_points::<L, 1>(f_re, f_im, r * stride + c0, stride, gbuf, tile);
                    }
                }
                r += nr;
            }
            t0 = t1;
        }
    }

    /// Adds segments (each with its own centre, direction and length):
    /// `F(ν) += Σ_k e^{−2πiν·c_k}·sinc(λ_k ν·ω_k)`. A zero-length segment is a
    /// point.
    ///
    /// The weight is `sin(X)/X` with `X = πλν·ω`, `sin X` taken from exactly
    /// reduced per-axis phasors `e^{iπλ j_a ω_a}` (so it is exactly 0 where
    /// `λν·ω` is a non-zero integer and the per-axis products are exact, e.g.
    /// a unit-length axis segment) and a Taylor series for `|X| < 1/2`. Extra
    /// error over the point path: `≤ 4ε·Σ_a|π λ j_a ω_a| / max(|X|, 1/2)`
    /// relative to the weight.
    ///
    /// `scratch`: as [`Dft::add_points`] with
    /// [`Dft::segments_scratch_per_sample`].
    ///
    /// # Errors
    /// As [`Dft::add_points`] (a centre is NaN or ±∞, or scratch too short).
    pub fn add_segments(
        &mut self,
        segments: &[Segment<D>],
        scratch: &mut [f64],
    ) -> Result<(), SpectrumError> {
        crate::simd::dispatch(AddSegments {
            dft: self,
            n: segments.len(),
            seg: segment_parts(segments),
            scratch,
        })
    }

    /// Segments of one direction and length centred at the points of a
    /// pattern (the [`crate::estimator::SegmentEstimator`] with fixed
    /// direction): as [`Dft::add_segments`].
    ///
    /// # Errors
    /// As [`Dft::add_segments`], and [`SpectrumError::Param`] if `length` is
    /// NaN, negative or above [`crate::geom::MAX_SEGMENT_LENGTH`].
    pub fn add_segment_pattern<T: Coordinate>(
        &mut self,
        centres: &[[T; D]],
        dir: &Direction<D>,
        length: f64,
        scratch: &mut [f64],
    ) -> Result<(), SpectrumError> {
        let length = crate::primitive::check_length(length)?;
        let dir = *dir;
        crate::simd::dispatch(AddSegments {
            dft: self,
            n: centres.len(),
            seg: move |i: usize| (centres[i].map(Coordinate::to_f64), dir, length),
            scratch,
        })
    }

    /// [`Dft::add_segments`] on the scalar reference path (bit-identical).
    ///
    /// # Errors
    /// As [`Dft::add_segments`].
    pub fn add_segments_scalar(
        &mut self,
        segments: &[Segment<D>],
        scratch: &mut [f64],
    ) -> Result<(), SpectrumError> {
        self.segments_lane::<f64>(segments.len(), segment_parts(segments), scratch)
    }

    #[inline(always)]
    fn segments_lane<L: F64Lane>(
        &mut self,
        n: usize,
        seg: impl Fn(usize) -> ([f64; D], Direction<D>, f64),
        scratch: &mut [f64],
    ) -> Result<(), SpectrumError> {
        Grid::<D>::check_dim()?;
        check_finite("centres", (0..n).map(|i| seg(i).0))?;
        let per = Self::segments_scratch_per_sample(self.grid);
        let chunk = scratch.len() / per;
        if chunk == 0 {
            return Err(SpectrumError::Length {
                name: "scratch",
                expected: per,
                got: scratch.len(),
            });
        }
        let mut first = 0;
        while first < n {
            let p = chunk.min(n - first);
            self.segments_chunk::<L>(first, p, &seg, &mut scratch[..per * p]);
            first += p;
        }
        self.count += n as u64;
        Ok(())
    }

    #[inline(always)]
    fn segments_chunk<L: F64Lane>(
        &mut self,
        first: usize,
        p: usize,
        seg: &impl Fn(usize) -> ([f64; D], Direction<D>, f64),
        scratch: &mut [f64],
    ) {
        let g = self.grid;
        let k = g.half_width();
        let stride = g.stride();
        let w = 2 * k + 1;
        let (row0, rest) = scratch.split_at_mut(5 * row0_len(g) * p);
        let (row1, rest) = rest.split_at_mut(if D == 3 { 5 * w * p } else { 0 });
        let (cols, gbuf) = rest.split_at_mut(5 * stride * p);
        let (col_lo, kc, ncols) = col_range(g);
        let ntiles = stride / TILE;
        cols.fill(0.0);
        for slot in 0..p {
            let (c, dir, len) = seg(first + slot);
            let y: [f64; D] = core::array::from_fn(|a| 0.5 * len * dir.get()[a]);
            if D == 1 {
                // Row a stands for j = 64a: the factors at 64·(c mod 1), 64·y
                // (exact scalings by a power of two).
                let s = ONE_D_STRIDE as f64;
                let rows = g.storage_rows() - 1;
                fill_seg_rows(row0, p, rows, 0, slot, s * reduce(c[0]), s * y[0]);
            } else {
                fill_seg_rows(row0, p, k, 0, slot, c[0], y[0]);
            }
            if D == 3 {
                fill_seg_rows(row1, p, k, -(k as i64), slot, c[1], y[1]);
            }
            let mut put = |col: i64, v: [f64; 5]| {
                if (0..ncols).contains(&col) {
                    let (t, lane) = (col as usize / TILE, col as usize % TILE);
                    let base = (t * p + slot) * 5 * TILE;
                    for (q, x) in v.iter().enumerate() {
                        cols[base + q * TILE + lane] = *x;
                    }
                }
            };
            seg_axis(c[D - 1], y[D - 1], kc, |j, v, vn| {
                put(j as i64 - col_lo, v);
                if j > 0 {
                    put(-(j as i64) - col_lo, vn);
                }
            });
        }
        let half = g.storage_len();
        let (f_re, f_im) = self.buf.as_mut()[..2 * half].split_at_mut(half);
        let gbuf = &mut gbuf[..8 * p];
        let rows = g.storage_rows();
        let mut t0 = 0;
        while t0 < ntiles {
            let t1 = (t0 + BLOCK_TILES).min(ntiles);
            for r in 0..rows {
                for (i, gk) in gbuf.chunks_exact_mut(8).enumerate() {
                    let v = seg_row_coefficient::<D>(r, i, p, k, row0, row1);
                    gk[..5].copy_from_slice(&v);
                }
                for t in t0..t1 {
                    let tile = &cols[t * p * 5 * TILE..(t + 1) * p * 5 * TILE];
                    tile_segments::<L>(f_re, f_im, r * stride + t * TILE, gbuf, tile);
                }
            }
            t0 = t1;
        }
    }
}

/// [`Dft::add_points`] as one dispatched call ([`crate::simd::dispatch`]).
struct AddPoints<'a, const D: usize, B, T> {
    dft: &'a mut Dft<D, B>,
    points: &'a [[T; D]],
    scratch: &'a mut [f64],
}

impl<const D: usize, B: AsRef<[f64]> + AsMut<[f64]>, T: Coordinate> crate::simd::Kernel
    for AddPoints<'_, D, B, T>
{
    type Output = Result<(), SpectrumError>;
    #[inline(always)]
    fn run<I: crate::simd::Isa>(self) -> Self::Output {
        self.dft
            .add_points_lane::<I::F64, T>(self.points, self.scratch)
    }
}

/// [`Dft::add_segments`] and [`Dft::add_segment_pattern`] as one dispatched
/// call: segment `i` is `seg(i)` (centre, direction, length).
struct AddSegments<'a, const D: usize, B, F> {
    dft: &'a mut Dft<D, B>,
    n: usize,
    seg: F,
    scratch: &'a mut [f64],
}

impl<const D: usize, B, F> crate::simd::Kernel for AddSegments<'_, D, B, F>
where
    B: AsRef<[f64]> + AsMut<[f64]>,
    F: Fn(usize) -> ([f64; D], Direction<D>, f64),
{
    type Output = Result<(), SpectrumError>;
    #[inline(always)]
    fn run<I: crate::simd::Isa>(self) -> Self::Output {
        self.dft
            .segments_lane::<I::F64>(self.n, self.seg, self.scratch)
    }
}

impl<const D: usize, B: AsRef<[f64]>> AmplitudeView<D> for Dft<D, B> {
    fn grid(&self) -> Grid<D> {
        self.grid
    }

    fn count(&self) -> u64 {
        self.count
    }

    /// # Panics
    /// If `index ≥ grid.len()`.
    fn amplitude_at(&self, index: usize) -> Complex {
        assert!(index < self.grid.len(), "index out of range");
        let cols = self.grid.cols();
        let (row, col) = (index / cols, index % cols);
        let off = row * self.grid.stride() + col;
        let half = self.grid.storage_len();
        let b = self.buf.as_ref();
        Complex {
            re: b[off],
            im: b[half + off],
        }
    }

    /// One run per grid row (the rows of the internal storage are padded to
    /// the tile width; a long 1D grid is one contiguous run).
    fn for_each_run(&self, f: &mut dyn FnMut(usize, &[f64], &[f64])) {
        let g = self.grid;
        let (cols, stride) = (g.cols(), g.stride());
        let half = g.storage_len();
        let (re, im) = self.buf.as_ref()[..2 * half].split_at(half);
        for row in 0..g.rows() {
            let o = row * stride;
            f(row * cols, &re[o..o + cols], &im[o..o + cols]);
        }
    }
}

/// Row-table entries per sample and row axis 0: `k + 1`, or the storage rows
/// in 1D.
fn row0_len<const D: usize>(g: Grid<D>) -> usize {
    if D == 1 {
        g.storage_rows()
    } else {
        g.half_width() + 1
    }
}

/// Row-table entries per sample over all row axes.
fn row_table_len<const D: usize>(g: Grid<D>) -> usize {
    let w = 2 * g.half_width() + 1;
    row0_len(g) + if D == 3 { w } else { 0 }
}

/// The column axis: `(lowest frequency, largest |j| tabulated, columns)`:
/// `(−k, k, 2k+1)`; in 1D `(0, min(k, stride − 1), min(k + 1, stride))`.
fn col_range<const D: usize>(g: Grid<D>) -> (i64, usize, i64) {
    let k = g.half_width();
    if D == 1 {
        let s = g.stride();
        (0, k.min(s - 1), (k + 1).min(s) as i64)
    } else {
        (-(k as i64), k, g.cols() as i64)
    }
}

/// Centre, direction and length of segment `i`.
fn segment_parts<const D: usize>(
    segments: &[Segment<D>],
) -> impl Fn(usize) -> ([f64; D], Direction<D>, f64) + '_ {
    |i| {
        let s = &segments[i];
        (s.centre(), s.dir(), s.length())
    }
}

/// Per-axis segment factors at `j ≥ 0` and `−j`: `[u_re, u_im, v_re, v_im, X]`
/// with `u = e^{−2πijc}`, `v = e^{+2πijy}` (`y = λω_a/2`) and `X = 2πjy`.
#[inline]
fn seg_axis(c: f64, y: f64, k: usize, mut put: impl FnMut(usize, [f64; 5], [f64; 5])) {
    let (tu, tv) = (PhaseTable::new(c, k), PhaseTable::new(-y, k));
    let mut u = [(0.0, 0.0); PHASE_BLOCK];
    let mut lo = 0;
    while lo <= k {
        tu.block(lo, k, |j, re, im| u[j - lo] = (re, im));
        tv.block(lo, k, |j, vr, vi| {
            let (ur, ui) = u[j - lo];
            let x = TAU * (j as f64 * y);
            put(j, [ur, ui, vr, vi, x], [ur, -ui, vr, -vi, -x]);
        });
        lo += PHASE_BLOCK;
    }
}

/// Row tables for segments: five `[j][k]` arrays (u_re, u_im, v_re, v_im, X).
fn fill_seg_rows(t: &mut [f64], p: usize, k: usize, lo: i64, slot: usize, c: f64, y: f64) {
    let len = t.len() / (5 * p);
    seg_axis(c, y, k, |j, v, vn| {
        let both = [(j as i64, v), (-(j as i64), vn)];
        for &(jj, vals) in &both[..if j > 0 { 2 } else { 1 }] {
            let r = jj - lo;
            if (0..len as i64).contains(&r) {
                for (q, x) in vals.iter().enumerate() {
                    t[(q * len + r as usize) * p + slot] = *x;
                }
            }
        }
    });
}

/// `g_k(row)`: the product of the row-axis phasors of point `i` (in 1D the
/// phasor of `j = 64·row`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn row_coefficient<const D: usize>(
    row: usize,
    i: usize,
    p: usize,
    k: usize,
    r0re: &[f64],
    r0im: &[f64],
    r1re: &[f64],
    r1im: &[f64],
) -> (f64, f64) {
    match D {
        1 | 2 => (r0re[row * p + i], r0im[row * p + i]),
        _ => {
            let w = 2 * k + 1;
            let (j0, j1) = (row / w, row % w);
            let (ar, ai) = (r0re[j0 * p + i], r0im[j0 * p + i]);
            let (br, bi) = (r1re[j1 * p + i], r1im[j1 * p + i]);
            (ar * br - ai * bi, ar * bi + ai * br)
        }
    }
}

/// Row factors of segment `i`: `[u_re, u_im, v_re, v_im, X]` (products of the
/// row axes; in 1D the factors of `j = 64·row`).
#[inline(always)]
fn seg_row_coefficient<const D: usize>(
    row: usize,
    i: usize,
    p: usize,
    k: usize,
    row0: &[f64],
    row1: &[f64],
) -> [f64; 5] {
    let at = |t: &[f64], j: usize| {
        let len = t.len() / (5 * p);
        core::array::from_fn::<f64, 5, _>(|q| t[(q * len + j) * p + i])
    };
    match D {
        1 | 2 => at(row0, row),
        _ => {
            let w = 2 * k + 1;
            let a = at(row0, row / w);
            let b = at(row1, row % w);
            [
                a[0] * b[0] - a[1] * b[1],
                a[0] * b[1] + a[1] * b[0],
                a[2] * b[2] - a[3] * b[3],
                a[2] * b[3] + a[3] * b[2],
                a[4] + b[4],
            ]
        }
    }
}

/// One tile of `R` rows × [`TILE`] columns: for each sample `k` in order,
/// `F += g_k·c_k` as the chain `re = re + g_r·c_r; re = re − g_i·c_i;
/// im = im + g_r·c_i; im = im + g_i·c_r` (each product and sum rounded, never
/// fused: the same bits in every build, and no software `fma` where the
/// target lacks the instruction).
#[inline(always)]
fn tile_points<L: F64Lane, const R: usize>(
    f_re: &mut [f64],
    f_im: &mut [f64],
    off: usize,
    stride: usize,
    gbuf: &[f64],
    tile: &[f64],
) {
    let nv = TILE / L::LANES;
    let mut ar = [[L::splat(0.0); TILE]; R];
    let mut ai = [[L::splat(0.0); TILE]; R];
    for q in 0..R {
        for v in 0..nv {
            let o = off + q * stride + v * L::LANES;
            ar[q][v] = L::load(&f_re[o..]);
            ai[q][v] = L::load(&f_im[o..]);
        }
    }
    for (gk, ck) in gbuf.chunks_exact(4).zip(tile.chunks_exact(2 * TILE)) {
        for v in 0..nv {
            let cr = L::load(&ck[v * L::LANES..]);
            let ci = L::load(&ck[TILE + v * L::LANES..]);
            for q in 0..R {
                let gr = L::splat(gk[2 * q]);
                let gi = L::splat(gk[2 * q + 1]);
                let mut re = ar[q][v];
                re = re + gr * cr;
                re = re - gi * ci;
                ar[q][v] = re;
                let mut im = ai[q][v];
                im = im + gr * ci;
                im = im + gi * cr;
                ai[q][v] = im;
            }
        }
    }
    for q in 0..R {
        for v in 0..nv {
            let o = off + q * stride + v * L::LANES;
            ar[q][v].store(&mut f_re[o..]);
            ai[q][v].store(&mut f_im[o..]);
        }
    }
}

/// Taylor coefficients of `sin(X)/X` in `z = X²` (enough for `|X| < 1/2` to
/// below `ε/4`).
const SINC_SERIES: [f64; 9] = [
    1.0,
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5040.0,
    1.0 / 362880.0,
    -1.0 / 39916800.0,
    1.0 / 6227020800.0,
    -1.0 / 1307674368000.0,
    1.0 / 355687428096000.0,
];

/// One row × [`TILE`] columns of segment samples: `sin X = Im(v_row·v_col)`,
/// `X = X_row + X_col`, weight `w = sin X / X` (series below `|X| = 1/2`), then
/// `F += (w·u_row)·u_col` as the chain of [`tile_points`].
#[inline(always)]
fn tile_segments<L: F64Lane>(
    f_re: &mut [f64],
    f_im: &mut [f64],
    off: usize,
    gbuf: &[f64],
    tile: &[f64],
) {
    let nv = TILE / L::LANES;
    let mut ar = [L::splat(0.0); TILE];
    let mut ai = [L::splat(0.0); TILE];
    for v in 0..nv {
        ar[v] = L::load(&f_re[off + v * L::LANES..]);
        ai[v] = L::load(&f_im[off + v * L::LANES..]);
    }
    let half = L::splat(0.5);
    for (gk, ck) in gbuf.chunks_exact(8).zip(tile.chunks_exact(5 * TILE)) {
        let (ur, ui) = (L::splat(gk[0]), L::splat(gk[1]));
        let (vr, vi) = (L::splat(gk[2]), L::splat(gk[3]));
        let xr = L::splat(gk[4]);
        for v in 0..nv {
            let o = v * L::LANES;
            let cur = L::load(&ck[o..]);
            let cui = L::load(&ck[TILE + o..]);
            let cvr = L::load(&ck[2 * TILE + o..]);
            let cvi = L::load(&ck[3 * TILE + o..]);
            let cx = L::load(&ck[4 * TILE + o..]);
            let sin_x = vr * cvi + vi * cvr;
            let x = xr + cx;
            let z = x * x;
            let mut series = L::splat(SINC_SERIES[8]);
            for c in SINC_SERIES[..8].iter().rev() {
                series = series * z + L::splat(*c);
            }
            let weight = x.abs().lt_select(half, series, sin_x / x);
            // F += (w·u_row)·u_col as the chain of the point path, so a
            // weight of exactly 1 reproduces the point amplitudes bit for bit.
            let (gr, gi) = (ur * weight, ui * weight);
            let mut re = ar[v] + gr * cur;
            re = re - gi * cui;
            ar[v] = re;
            let mut im = ai[v] + gr * cui;
            im = im + gi * cur;
            ai[v] = im;
        }
    }
    for v in 0..nv {
        ar[v].store(&mut f_re[off + v * L::LANES..]);
        ai[v].store(&mut f_im[off + v * L::LANES..]);
    }
}
