//! Periodograms of point, segment and line samples, and the spectral variance
//! prediction of Pilleboue et al. (2015) and Singh, Miller & Jarosz (2017).
//!
//! # Definitions
//!
//! For one realisation of `N` samples on the unit torus `[0,1)^D`, at an
//! integer frequency `ν`,
//!
//! * amplitude `F(ν) = Σ_k w_k(ν)·e^{−2πiν·x_k}` ([`Dft`]), with `w_k = 1` for
//!   points and `w_k = sinc(λ_k ν·ω_k)` for segments of length `λ_k` along
//!   `ω_k` centred at `x_k` (the segment sampling function is the point one
//!   convolved with a unit-mass box along `ω`; `sinc(t) = sin(πt)/(πt)`);
//! * periodogram `P(ν) = |F(ν)/N|²`. A [`Periodogram`] accumulates `N·P(ν)`
//!   over realisations (it is 1 for white noise at `ν ≠ 0`) and reports the
//!   mean `⟨N·P(ν)⟩`;
//! * variance of the estimator `I_N = (1/N) Σ_k ⟨f, sample_k⟩` with a random
//!   toroidal shift (homogenisation):
//!   `Var(I_N) = Σ_{ν≠0} ⟨P(ν)⟩·|f̂(ν)|² = (1/N) Σ_{ν≠0} ⟨N·P(ν)⟩·|f̂(ν)|²`
//!   (Pilleboue et al. 2015, torus form; `docs/theory.md`, Spectral variance),
//!   where `f̂` is the Fourier coefficient of the integrand
//!   ([`crate::integrand::Integrand::fourier`]). For segments with a common
//!   `λ, ω` this is the point spectrum of the centres times the pre-filtered
//!   integrand spectrum `|f̂|²·sinc²(λν·ω)` (Singh et al. 2017; `docs/theory.md`,
//!   Segment and line spectra).
//! * Lines along axis `a` integrate out coordinate `a`: their estimator is
//!   point sampling of the projection `g(x_⊥) = ∫ f dx_a` by the `(D−1)`-dim
//!   offsets, whose coefficients are the slice `ĝ(ν_⊥) = f̂(ν_⊥, ν_a = 0)`
//!   (Fourier slice theorem). So the line spectrum lives on the hyperplane
//!   `ν_a = 0` and equals the `(D−1)`-dim periodogram of the offsets
//!   ([`line_offsets`], [`line_spectrum`]). A segment of length 1 along the
//!   axis has exactly this spectrum (`sinc(j) = 0` at non-zero integers).
//!
//! # Grid and storage
//!
//! The frequencies are the integer grid `[−k, k]^D`. Samples are real, so
//! `F(−ν) = conj F(ν)` and only the **half grid** `j_0 ∈ [0, k]` (other axes
//! `[−k, k]`) is stored, last axis fastest ([`Grid`]). Memory is the grid,
//! independent of `N` and of the number of realisations: feed realisations,
//! and chunks of one large realisation, one at a time.
//!
//! # The direct path
//!
//! `F` is computed exactly (no binning). The phases are separable:
//! `e^{−2πiν·x} = Π_a e^{−2πi j_a x_a}`, so per chunk of samples the kernel
//! builds per-axis phase tables (one `sin`/`cos` pair per 16 frequencies per
//! axis, each `j·x` reduced modulo 1 **exactly** before multiplying by `2π`, so
//! high frequencies stay accurate), and the accumulation is a complex
//! matrix product `F[row, col] += Σ_k g_k(row)·c_k(col)` (rows: all axes but
//! the last; columns: the last axis), blocked for cache and registers and
//! vectorised over columns with `f64x4` multiply-adds (unfused, so the same
//! bits and nearly the same speed in a build without FMA). A long 1D grid
//! is split the same way, `j = 64a + b` (row phasor `e^{−2πi·a·64x}`, column
//! phasor `e^{−2πi·b·x}`). Cost: about `N·|grid|` complex multiply-adds.
//!
//! # One view of the amplitudes
//!
//! [`AmplitudeView`] is what every consumer reads: the grid, the sample count
//! `N` and the half-grid amplitudes, from which the per-cell power `|F|²/N`,
//! the ring means of one realisation ([`AmplitudeView::radial_power`]) and
//! [`Periodogram::add`] are computed by one piece of code. It is implemented
//! by [`Dft`] (the direct path) and by [`Amplitudes`], a plain buffer in grid
//! layout that an external transform (a NUFFT) fills, so both paths give the
//! same numbers from the same amplitudes, bit for bit.
//!
//! # The standard error of a prediction
//!
//! A prediction is a mean over realisations, so it has a standard error:
//! `SE = s/√R`, `s` the standard deviation of the per-realisation predictions
//! `V_r = (1/N) Σ_{ν≠0} N·P_r(ν)·p_f(ν)` (not of the per-cell periodograms,
//! which are correlated across frequencies). [`PredictionStats`] forms `V_r`
//! for each realisation against integrand weights registered up front
//! ([`Grid::spectrum_weights`]) and reports the prediction with its standard
//! error ([`Prediction::std_error`]); it merges exactly, like the periodogram.
//!
//! # Persisting accumulators
//!
//! [`Periodogram::parts`] and [`Periodogram::from_parts`] (and
//! [`crate::stats::RunningStats::parts`] / `from_parts`) export and import
//! the exact accumulator state as plain numbers, so a caller can store it
//! (the kernel has no serialisation dependency), resume a run, or merge shards
//! computed on other machines: an imported accumulator is the exported one,
//! bit for bit, so it adds and merges exactly as the original would.

mod amplitudes;
mod dft;
mod image;
mod prediction;

pub use amplitudes::{AmplitudeView, Amplitudes};
pub use dft::Dft;
pub use image::{
    image_band_mean, image_periodogram, image_periodogram_scratch, image_ring_means,
    image_white_level,
};
pub use prediction::PredictionStats;

use crate::error::{ParamError, SpectrumError};
use crate::num::{sinc, two_sum};

/// Columns per register tile; rows are padded to a multiple of it.
pub(crate) const TILE: usize = 8;
/// Storage row length of long 1D grids (a power of two, so `ONE_D_STRIDE·x`
/// is exact; 8 tiles, one column block of the kernel).
pub(crate) const ONE_D_STRIDE: usize = 64;

/// Largest grid half-width `k`.
pub const MAX_HALF_WIDTH: usize = 1 << 20;
/// Largest number of stored (half-grid) cells.
pub const MAX_CELLS: usize = 1 << 31;

/// A sample coordinate type (`f32`, as patterns produce, or `f64`).
pub trait Coordinate: Copy + sealed::Sealed {
    /// The value as `f64` (exact).
    fn to_f64(self) -> f64;
}

impl Coordinate for f32 {
    #[inline(always)]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
}

impl Coordinate for f64 {
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// Rejects the first non-finite coordinate.
pub(crate) fn check_finite<const D: usize>(
    name: &'static str,
    xs: impl Iterator<Item = [f64; D]>,
) -> Result<(), SpectrumError> {
    for (index, x) in xs.enumerate() {
        if !x.iter().all(|c| c.is_finite()) {
            return Err(SpectrumError::NonFinite { name, index });
        }
    }
    Ok(())
}

/// The half frequency grid of half-width `k` in `D = 1, 2, 3` dimensions.
///
/// Stored cells: `j_0 ∈ [0, k]` and `j_a ∈ [−k, k]` for `a ≥ 1`, in row-major
/// order with the last axis fastest. The plane `j_0 = 0` is stored whole (both
/// `ν` and `−ν`); every cell with `j_0 > 0` also stands for its mirror `−ν`
/// ([`Grid::multiplicity`]). Lengths: `k+1`, `(k+1)(2k+1)`, `(k+1)(2k+1)²`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid<const D: usize> {
    k: usize,
}

impl<const D: usize> Grid<D> {
    pub(crate) fn check_dim() -> Result<(), SpectrumError> {
        if (1..=3).contains(&D) {
            Ok(())
        } else {
            Err(SpectrumError::Dimension { dim: D })
        }
    }

    /// The grid `[−k, k]^D`.
    ///
    /// # Errors
    /// [`SpectrumError::HalfWidth`] unless `1 ≤ k ≤ MAX_HALF_WIDTH` and the half
    /// grid has at most [`MAX_CELLS`] cells; [`SpectrumError::Dimension`]
    /// unless `D ∈ {1, 2, 3}`.
    pub fn new(k: usize) -> Result<Self, SpectrumError> {
        Self::check_dim()?;
        let err = SpectrumError::HalfWidth {
            k,
            max: MAX_HALF_WIDTH,
            max_cells: MAX_CELLS,
        };
        if k == 0 || k > MAX_HALF_WIDTH {
            return Err(err);
        }
        let w = 2 * k + 1;
        let mut cells = k + 1;
        for _ in 1..D {
            cells = cells.checked_mul(w).ok_or(err)?;
        }
        if cells > MAX_CELLS {
            return Err(err);
        }
        Ok(Grid { k })
    }

    /// The half-width `k`.
    #[must_use]
    pub fn half_width(&self) -> usize {
        self.k
    }

    /// Columns (last axis): `2k+1`, or `k+1` in 1D.
    #[must_use]
    pub fn cols(&self) -> usize {
        if D == 1 {
            self.k + 1
        } else {
            2 * self.k + 1
        }
    }

    /// Rows (all axes but the last): `(k+1)(2k+1)^{D−2}`, or 1 in 1D.
    #[must_use]
    pub fn rows(&self) -> usize {
        if D == 1 {
            1
        } else {
            (self.k + 1) * (2 * self.k + 1).pow(D as u32 - 2)
        }
    }

    /// Number of stored cells, `rows·cols`.
    #[must_use]
    pub fn len(&self) -> usize {
        self.rows() * self.cols()
    }

    /// Always false (a grid has at least the DC cell).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Row length of the internal (padded) amplitude storage. A 1D grid with
    /// more than [`ONE_D_STRIDE`] frequencies is stored as rows of
    /// `ONE_D_STRIDE` columns, frequency `j = a·ONE_D_STRIDE + b` at row `a`,
    /// column `b` (so the storage offset is still `j`), which turns the 1D
    /// sum into the same blocked matrix product as in 2D.
    pub(crate) fn stride(&self) -> usize {
        if D == 1 && self.k + 1 > ONE_D_STRIDE {
            ONE_D_STRIDE
        } else {
            self.cols().div_ceil(TILE) * TILE
        }
    }

    /// Rows of the internal amplitude storage: [`Grid::rows`], or
    /// `⌈(k+1)/stride⌉` in 1D.
    pub(crate) fn storage_rows(&self) -> usize {
        if D == 1 {
            (self.k + 1).div_ceil(self.stride())
        } else {
            self.rows()
        }
    }

    /// Values of one (real or imaginary) half of the internal storage.
    pub(crate) fn storage_len(&self) -> usize {
        self.storage_rows() * self.stride()
    }

    /// The frequency of stored cell `index`.
    ///
    /// # Panics
    /// If `index ≥ len()`.
    #[must_use]
    pub fn freq(&self, index: usize) -> [i32; D] {
        assert!(index < self.len(), "index out of range");
        let k = self.k as i64;
        let w = 2 * self.k + 1;
        let (row, col) = (index / self.cols(), index % self.cols());
        let mut j = [0i32; D];
        match D {
            1 => j[0] = col as i32,
            2 => {
                j[0] = row as i32;
                j[1] = (col as i64 - k) as i32;
            }
            _ => {
                j[0] = (row / w) as i32;
                j[1] = ((row % w) as i64 - k) as i32;
                j[2] = (col as i64 - k) as i32;
            }
        }
        j
    }

    /// The stored cell holding `j` (any frequency with `|j_a| ≤ k`) and whether
    /// the stored value is that of `−j` (conjugate the amplitude); `None`
    /// outside the grid.
    #[must_use]
    pub fn index(&self, j: [i32; D]) -> Option<(usize, bool)> {
        let k = self.k as i64;
        if j.iter().any(|&x| i64::from(x).abs() > k) {
            return None;
        }
        let conj = j[0] < 0;
        let j: [i64; D] = core::array::from_fn(|a| {
            if conj {
                -i64::from(j[a])
            } else {
                i64::from(j[a])
            }
        });
        let w = 2 * k + 1;
        let idx = match D {
            1 => j[0],
            2 => j[0] * w + j[1] + k,
            _ => (j[0] * w + j[1] + k) * w + j[2] + k,
        };
        Some((idx as usize, conj))
    }

    /// How many full-grid frequencies stored cell `index` stands for: 2 if
    /// `j_0 > 0` (itself and `−ν`), 1 on the plane `j_0 = 0`.
    #[must_use]
    pub fn multiplicity(&self, index: usize) -> u32 {
        if index >= self.rows().div_ceil(self.k + 1) * self.cols() || (D == 1 && index > 0) {
            2
        } else {
            1
        }
    }

    /// Ring of stored cell `index`: `round(|ν|)` (rings of unit width, ring `r`
    /// holds `r − ½ ≤ |ν| < r + ½`, decided in exact integer arithmetic);
    /// rings above `k` are incomplete and reported as `None`.
    #[must_use]
    pub fn ring(&self, index: usize) -> Option<usize> {
        let j = self.freq(index);
        let m: u64 = j
            .iter()
            .map(|&x| (i64::from(x) * i64::from(x)) as u64)
            .sum();
        let r = ring_of(m);
        (r <= self.k as u64).then_some(r as usize)
    }

    /// Number of full-grid frequencies in each ring `0..=k` (`counts.len()`
    /// must be `k + 1`).
    ///
    /// # Errors
    /// [`SpectrumError::Length`] if `counts.len() != k + 1`.
    pub fn ring_counts(&self, counts: &mut [u64]) -> Result<(), SpectrumError> {
        check_len("counts", counts.len(), self.k + 1)?;
        counts.fill(0);
        for i in 0..self.len() {
            if let Some(r) = self.ring(i) {
                counts[r] += u64::from(self.multiplicity(i));
            }
        }
        Ok(())
    }
}

/// `round(√m)` for an integer `m`, exactly: the `r` with `r² − r < m ≤ r² + r`.
fn ring_of(m: u64) -> u64 {
    // A first guess (the cast truncates √m + ½); the loops make it exact.
    let mut r = (crate::num::scalar::sqrt(m as f64) + 0.5) as u64;
    while r > 0 && m <= r * r - r {
        r -= 1;
    }
    while m > r * r + r {
        r += 1;
    }
    r
}

/// Zeroes `buf[..need]`, or reports that `buf` is too short.
pub(crate) fn zero_prefix(buf: &mut [f64], need: usize) -> Result<(), SpectrumError> {
    if buf.len() < need {
        return Err(SpectrumError::Length {
            name: "buf",
            expected: need,
            got: buf.len(),
        });
    }
    buf[..need].fill(0.0);
    Ok(())
}

fn check_len(name: &'static str, got: usize, expected: usize) -> Result<(), SpectrumError> {
    if got == expected {
        Ok(())
    } else {
        Err(SpectrumError::Length {
            name,
            expected,
            got,
        })
    }
}

/// The mean periodogram `⟨N·P(ν)⟩` over realisations, on a half grid.
///
/// Each realisation adds `|F(ν)|²/N` per cell. The sums are kept as
/// unevaluated double-double pairs (TwoSum), so [`Periodogram::merge`] is
/// exact to a relative `~R²ε²` (≈ 1e-24 for `R = 10⁴` realisations), far below
/// one rounding of the reported `f64` mean: an accumulator merged from parts
/// (parallel or resumed runs) reports the same means as one fed everything,
/// bit for bit (tested).
///
/// Storage is the caller's buffer `B` of [`Periodogram::buffer_len`] values
/// (`Vec<f64>` via [`Periodogram::new_vec`] with `alloc`).
#[derive(Clone, Debug)]
pub struct Periodogram<const D: usize, B> {
    grid: Grid<D>,
    buf: B,
    realisations: u64,
}

#[cfg(feature = "alloc")]
impl<const D: usize> Periodogram<D, alloc::vec::Vec<f64>> {
    /// An empty accumulator owning its buffer (**allocates**).
    #[must_use]
    pub fn new_vec(grid: Grid<D>) -> Self {
        Periodogram {
            grid,
            buf: alloc::vec![0.0; Self::buffer_len(grid)],
            realisations: 0,
        }
    }
}

impl<const D: usize, B> Periodogram<D, B> {
    /// `2·grid.len()` (sum and compensation per cell).
    #[must_use]
    pub fn buffer_len(grid: Grid<D>) -> usize {
        2 * grid.len()
    }

    /// The grid.
    #[must_use]
    pub fn grid(&self) -> Grid<D> {
        self.grid
    }

    /// Realisations accumulated.
    #[must_use]
    pub fn realisations(&self) -> u64 {
        self.realisations
    }
}

impl<const D: usize, B: AsRef<[f64]>> Periodogram<D, B> {
    /// The accumulator state, to persist it (resume a run, merge shards
    /// computed elsewhere): the first [`Periodogram::buffer_len`] values of
    /// the buffer (the per-cell sums in grid layout, then their
    /// compensations) and the number of realisations.
    /// [`Periodogram::from_parts`] rebuilds the same accumulator, bit for bit.
    #[must_use]
    pub fn parts(&self) -> (&[f64], u64) {
        (
            &self.buf.as_ref()[..Self::buffer_len(self.grid)],
            self.realisations,
        )
    }

    /// The caller's buffer back, with the realisation count: the state of
    /// [`Periodogram::parts`] without a copy (its first
    /// [`Periodogram::buffer_len`] values; [`Periodogram::from_parts`] takes
    /// it back).
    #[must_use]
    pub fn into_parts(self) -> (B, u64) {
        (self.buf, self.realisations)
    }

    /// An accumulator holding exported state ([`Periodogram::parts`]): `buf`
    /// starts with the [`Periodogram::buffer_len`] values, which are kept
    /// as they are (not zeroed), and `realisations` is the realisation count.
    ///
    /// # Errors
    /// [`SpectrumError::Length`] (naming `buf`) if `buf` is shorter than
    /// [`Periodogram::buffer_len`]; [`SpectrumError::NonFinite`] (naming
    /// `buf` and the index) if one of those values is NaN or ±∞;
    /// [`SpectrumError::Param`] with [`ParamError::OutOfRange`] naming `buf`
    /// if a per-cell sum (the first `grid.len()` values) is negative (every
    /// added value is `|F|²/N ≥ 0`), and with [`ParamError::Count`] naming
    /// `realisations` if it is 0 while a value is non-zero.
    pub fn from_parts(grid: Grid<D>, buf: B, realisations: u64) -> Result<Self, SpectrumError> {
        let need = Self::buffer_len(grid);
        let b = buf.as_ref();
        if b.len() < need {
            return Err(SpectrumError::Length {
                name: "buf",
                expected: need,
                got: b.len(),
            });
        }
        let b = &b[..need];
        if let Some(index) = b.iter().position(|v| !v.is_finite()) {
            return Err(SpectrumError::NonFinite { name: "buf", index });
        }
        if let Some(&value) = b[..grid.len()].iter().find(|&&v| v < 0.0) {
            return Err(ParamError::OutOfRange {
                name: "buf",
                value,
                min: 0.0,
                max: f64::MAX,
            }
            .into());
        }
        if realisations == 0 && b.iter().any(|&v| v != 0.0) {
            return Err(ParamError::Count {
                name: "realisations",
                value: 0,
            }
            .into());
        }
        Ok(Periodogram {
            grid,
            buf,
            realisations,
        })
    }
}

impl<const D: usize, B: AsRef<[f64]> + AsMut<[f64]>> Periodogram<D, B> {
    /// An empty accumulator over the caller's buffer (zeroed here).
    ///
    /// # Errors
    /// [`SpectrumError::Length`] if `buf` is shorter than
    /// [`Periodogram::buffer_len`].
    pub fn new(grid: Grid<D>, mut buf: B) -> Result<Self, SpectrumError> {
        zero_prefix(buf.as_mut(), Self::buffer_len(grid))?;
        Ok(Periodogram {
            grid,
            buf,
            realisations: 0,
        })
    }

    #[inline(always)]
    fn accumulate(&mut self, i: usize, v: f64) {
        let n = self.grid.len();
        let b = self.buf.as_mut();
        let (s, e) = two_sum(b[i], v);
        b[i] = s;
        b[n + i] += e;
    }

    /// Adds one finished realisation: `|F(ν)|²/N` per cell, from any view of
    /// its amplitudes ([`Dft`], [`Amplitudes`] filled by an external transform,
    /// …), evaluated as [`AmplitudeView`] documents.
    ///
    /// # Errors
    /// [`SpectrumError::GridMismatch`]; [`SpectrumError::Empty`] if the
    /// realisation has no samples; [`SpectrumError::NonFinite`] (naming
    /// `amplitudes` and the first bad cell) if an amplitude is NaN or ±∞.
    /// Nothing is added on error.
    pub fn add<A: AmplitudeView<D> + ?Sized>(&mut self, amps: &A) -> Result<(), SpectrumError> {
        amplitudes::check_realisation(self.grid, amps)?;
        amplitudes::for_each_power(amps, |i, v| self.accumulate(i, v));
        self.realisations += 1;
        Ok(())
    }

    /// Adds another accumulator's realisations (exact up to `~R²ε²`).
    ///
    /// # Errors
    /// [`SpectrumError::GridMismatch`].
    pub fn merge<B2: AsRef<[f64]>>(
        &mut self,
        other: &Periodogram<D, B2>,
    ) -> Result<(), SpectrumError> {
        self.check_grid(other.grid)?;
        let n = self.grid.len();
        let o = other.buf.as_ref();
        let b = self.buf.as_mut();
        for i in 0..n {
            let (s, e) = two_sum(b[i], o[i]);
            b[i] = s;
            b[n + i] += e + o[n + i];
        }
        self.realisations += other.realisations;
        Ok(())
    }

    fn check_grid(&self, g: Grid<D>) -> Result<(), SpectrumError> {
        if g == self.grid {
            Ok(())
        } else {
            Err(SpectrumError::GridMismatch {
                left: self.grid.k,
                right: g.k,
            })
        }
    }

    /// `⟨N·P⟩` at stored cell `index` (0 before any realisation).
    ///
    /// # Panics
    /// If `index ≥ grid.len()`.
    #[must_use]
    pub fn mean_at(&self, index: usize) -> f64 {
        let n = self.grid.len();
        assert!(index < n, "index out of range");
        if self.realisations == 0 {
            return 0.0;
        }
        let b = self.buf.as_ref();
        (b[index] + b[n + index]) / self.realisations as f64
    }

    /// `⟨N·P(j)⟩` at any frequency `|j_a| ≤ k` (the periodogram is even);
    /// `None` outside the grid.
    #[must_use]
    pub fn mean(&self, j: [i32; D]) -> Option<f64> {
        self.grid.index(j).map(|(i, _)| self.mean_at(i))
    }

    /// All cell means in grid layout.
    ///
    /// # Errors
    /// [`SpectrumError::Length`] if `out.len() != grid.len()`.
    pub fn means(&self, out: &mut [f64]) -> Result<(), SpectrumError> {
        check_len("out", out.len(), self.grid.len())?;
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.mean_at(i);
        }
        Ok(())
    }

    /// Radial average over rings of unit width (`round(|ν|) = r`, `r = 0..=k`;
    /// ring 0 is the DC term, `⟨N·P(0)⟩ = N`): `mean[r]` is the mean of
    /// `⟨N·P⟩` over the full-grid frequencies of the ring, `count[r]` their
    /// number. Both slices must have length `k + 1`.
    ///
    /// # Errors
    /// [`SpectrumError::Length`].
    pub fn radial_average(&self, mean: &mut [f64], count: &mut [u64]) -> Result<(), SpectrumError> {
        check_len("mean", mean.len(), self.grid.k + 1)?;
        check_len("counts", count.len(), self.grid.k + 1)?;
        radial_into(self.grid, mean, count, |add| {
            for i in 0..self.grid.len() {
                add(i, self.mean_at(i));
            }
        });
        Ok(())
    }

    /// The directional slice `out[t] = ⟨N·P(t·dir)⟩` for `t = 0, 1, …` while
    /// `t·dir` is in the grid; returns how many values were written.
    ///
    /// # Errors
    /// [`SpectrumError::Param`] if `dir` is zero.
    pub fn slice(&self, dir: [i32; D], out: &mut [f64]) -> Result<usize, SpectrumError> {
        if dir.iter().all(|&d| d == 0) {
            return Err(crate::ParamError::ZeroDirection.into());
        }
        let mut n = 0;
        for (t, o) in out.iter_mut().enumerate() {
            let j: Option<[i32; D]> = (|| {
                let mut j = [0i32; D];
                for a in 0..D {
                    j[a] = dir[a].checked_mul(i32::try_from(t).ok()?)?;
                }
                Some(j)
            })();
            match j.and_then(|j| self.mean(j)) {
                Some(v) => *o = v,
                None => break,
            }
            n += 1;
        }
        Ok(n)
    }

    /// The predicted variance `(1/N) Σ_{ν≠0, ν ∈ grid} ⟨N·P(ν)⟩·p_f(ν)` of an
    /// estimator with `n` samples whose pattern has this mean periodogram, for
    /// an even integrand power spectrum `p_f(ν) = p_f(−ν)` such as `|f̂(ν)|²`
    /// or the pre-filtered `|f̂(ν)|²·sinc²(λν·ω)` of segments (Pilleboue et al.
    /// 2015; Singh et al. 2017; `docs/theory.md`, Spectral variance and Segment
    /// and line spectra). See [`Prediction`] for the part of the
    /// spectrum outside the grid. The mean periodogram does not keep the
    /// per-realisation spread, so [`Prediction::std_error`] is `None` here;
    /// [`PredictionStats`], fed the same realisations, gives the same
    /// prediction with its standard error.
    #[must_use]
    pub fn predict_variance(&self, n: u64, mut p_f: impl FnMut([i32; D]) -> f64) -> Prediction {
        let (mut s, mut se) = (0.0, 0.0);
        let (mut f, mut fe) = (0.0, 0.0);
        for i in 0..self.grid.len() {
            let j = self.grid.freq(i);
            if j.iter().all(|&x| x == 0) {
                continue;
            }
            let m = f64::from(self.grid.multiplicity(i));
            let pf = m * p_f(j);
            let (a, e) = two_sum(s, self.mean_at(i) * pf);
            s = a;
            se += e;
            let (a, e) = two_sum(f, pf);
            f = a;
            fe += e;
        }
        Prediction {
            grid: (s + se) / n as f64,
            std_error: None,
            pf_in_grid: f + fe,
            n,
            realisations: self.realisations,
        }
    }
}

/// A variance prediction from a periodogram truncated to its grid, with its
/// standard error when the per-realisation spread is known.
///
/// Made by [`Periodogram::predict_variance`] (no standard error) and
/// [`PredictionStats::prediction`] (with it); more fields may be added.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Prediction {
    /// `V̂ = (1/N) Σ_{ν≠0 in grid} ⟨N·P⟩·p_f`, the mean over the realisations
    /// of `V_r = (1/N) Σ_{ν≠0 in grid} N·P_r·p_f`.
    pub grid: f64,
    /// The standard error of [`Prediction::grid`] over the realisations,
    /// `SE = √(Σ_r (V_r − V̂)²/(R(R − 1)))` (the sample standard deviation of
    /// the `V_r` over `√R`; see [`PredictionStats`]). It is also the standard
    /// error of [`Prediction::with_white_tail`] and
    /// [`Prediction::with_white_outside`], which add a constant. `None` from
    /// [`Periodogram::predict_variance`] (a mean periodogram does not keep the
    /// spread) and for fewer than 2 realisations.
    pub std_error: Option<f64>,
    /// `Σ_{ν≠0 in grid} p_f` (to size the truncated tail).
    pub pf_in_grid: f64,
    /// Samples per realisation.
    pub n: u64,
    /// Realisations `R` the prediction averages.
    pub realisations: u64,
}

impl Prediction {
    /// The prediction with the spectrum outside the grid taken as white
    /// (`⟨N·P⟩ = 1` there, as for every pattern far above its Nyquist-like
    /// frequency): `grid + (total − pf_in_grid)/N`, where
    /// `total = Σ_{ν≠0} p_f(ν)` over all frequencies — for points
    /// `∫f² − (∫f)²` by Parseval. Its standard error is
    /// [`Prediction::std_error`].
    #[must_use]
    pub fn with_white_tail(&self, total: f64) -> f64 {
        self.with_white_outside(total - self.pf_in_grid)
    }

    /// The prediction with a known part of the spectrum outside the grid
    /// taken as white: `grid + outside/N`, where
    /// `outside = Σ_{ν∉grid} p_f(ν)` (negative values count as 0). Its
    /// standard error is [`Prediction::std_error`].
    #[must_use]
    pub fn with_white_outside(&self, outside: f64) -> f64 {
        self.grid + outside.max(0.0) / self.n as f64
    }
}

/// The radial form of the variance (Pilleboue et al. 2015; `docs/theory.md`,
/// Spectral variance), `Var = (μ(S^{D−1})/N) ∫ ρ^{D−1} P̆_S(ρ) P̆_f(ρ) dρ`, on the lattice:
/// `(1/N) Σ_{r≥1} count_r · P̆_S(r) · P̆_f(r)`, where `P̆_S` are ring means of
/// `⟨N·P⟩` ([`Periodogram::radial_average`]), `P̆_f` ring means of the
/// integrand power spectrum ([`Grid::radial_mean_of`]) and `count_r` the
/// frequencies per ring (`≈ μ(S^{D−1}) r^{D−1}`). It equals
/// [`Periodogram::predict_variance`] when either spectrum is constant on each
/// ring, and approximates it for isotropic ones; the difference is the
/// within-ring covariance of the two spectra.
///
/// # Errors
/// [`SpectrumError::Length`] unless the three slices have the same length.
pub fn radial_variance(
    n: u64,
    sampling: &[f64],
    integrand: &[f64],
    count: &[u64],
) -> Result<f64, SpectrumError> {
    check_len("integrand", integrand.len(), sampling.len())?;
    check_len("count", count.len(), sampling.len())?;
    let mut s = 0.0;
    for r in 1..sampling.len() {
        s += count[r] as f64 * sampling[r] * integrand[r];
    }
    Ok(s / n as f64)
}

impl<const D: usize> Grid<D> {
    /// Ring means (rings `0..=k`, as [`Periodogram::radial_average`]) of a
    /// function of the frequency, e.g. the integrand power spectrum
    /// `|f̂(ν)|²` (averaged over `ν` and `−ν`). Both slices must have length
    /// `k + 1`.
    ///
    /// # Errors
    /// [`SpectrumError::Length`].
    pub fn radial_mean_of(
        &self,
        mut f: impl FnMut([i32; D]) -> f64,
        mean: &mut [f64],
        count: &mut [u64],
    ) -> Result<(), SpectrumError> {
        check_len("mean", mean.len(), self.k + 1)?;
        self.ring_counts(count)?;
        mean.fill(0.0);
        for i in 0..self.len() {
            if let Some(r) = self.ring(i) {
                let j = self.freq(i);
                let v = if self.multiplicity(i) == 2 {
                    f(j) + f(j.map(|x| -x))
                } else {
                    f(j)
                };
                mean[r] += v;
            }
        }
        for (m, &c) in mean.iter_mut().zip(count.iter()) {
            if c > 0 {
                *m /= c as f64;
            }
        }
        Ok(())
    }
}

/// Ring means of a per-cell quantity (shared by periodograms and single
/// realisations): `values` passes `(index, value)` for every cell in index
/// order; `mean[r]` is the sum of multiplicity × value over the cells of ring
/// `r`, divided by `count[r]`, the number of full-grid frequencies of the ring
/// (as [`Grid::ring_counts`]), counted in the same pass so that every cell's
/// ring is classified once.
fn radial_into<const D: usize>(
    grid: Grid<D>,
    mean: &mut [f64],
    count: &mut [u64],
    values: impl FnOnce(&mut dyn FnMut(usize, f64)),
) {
    mean.fill(0.0);
    count.fill(0);
    values(&mut |i, v| {
        if let Some(r) = grid.ring(i) {
            let m = grid.multiplicity(i);
            mean[r] += f64::from(m) * v;
            count[r] += u64::from(m);
        }
    });
    for (m, &c) in mean.iter_mut().zip(count.iter()) {
        if c > 0 {
            *m /= c as f64;
        }
    }
}

/// The offsets of axis-`axis` lines through `points`: each point with
/// coordinate `axis` removed (`K = D − 1`). Their `K`-dim periodogram is the
/// line spectrum ([`line_spectrum`]).
///
/// # Errors
/// [`SpectrumError::Length`] if `out.len() != points.len()`;
/// [`SpectrumError::Dimension`] unless `K + 1 = D` and `axis < D`.
pub fn line_offsets<const D: usize, const K: usize, T: Coordinate>(
    points: &[[T; D]],
    axis: usize,
    out: &mut [[T; K]],
) -> Result<(), SpectrumError> {
    if K + 1 != D || axis >= D {
        return Err(SpectrumError::Dimension { dim: D });
    }
    check_len("out", out.len(), points.len())?;
    for (o, p) in out.iter_mut().zip(points) {
        let mut b = 0;
        for (a, &x) in p.iter().enumerate() {
            if a != axis {
                o[b] = x;
                b += 1;
            }
        }
    }
    Ok(())
}

/// The `D`-dim line spectrum at `j` from the `(D−1)`-dim periodogram of the
/// offsets of lines along `axis`: `⟨N·P_offsets(j_⊥)⟩` on the hyperplane
/// `j_axis = 0` and 0 off it (a line integrates out its own axis: the Fourier
/// slice theorem). `None` outside the grid.
#[must_use]
pub fn line_spectrum<const D: usize, const K: usize, B: AsRef<[f64]> + AsMut<[f64]>>(
    offsets: &Periodogram<K, B>,
    axis: usize,
    j: [i32; D],
) -> Option<f64> {
    if K + 1 != D || axis >= D {
        return None;
    }
    let k = offsets.grid().half_width() as i64;
    if j.iter().any(|&x| i64::from(x).abs() > k) {
        return None;
    }
    if j[axis] != 0 {
        return Some(0.0);
    }
    let mut jp = [0i32; K];
    let mut b = 0;
    for (a, &x) in j.iter().enumerate() {
        if a != axis {
            jp[b] = x;
            b += 1;
        }
    }
    offsets.mean(jp)
}

/// Expected `⟨N·P(ν)⟩` of jittered sampling with `n_a` strata per axis at an
/// integer `ν ≠ 0`: `1 − Π_a sinc²(ν_a/n_a)`.
///
/// Derivation: with `x = (i + u)/n`, `E|F|² = N + |Σ_k E e_k|² − Σ_k |E e_k|²`;
/// `E e_k = e^{−2πiν·i/n} Π_a e^{−iπν_a/n_a} sinc(ν_a/n_a)`, whose lattice sum
/// vanishes unless every `ν_a` is a multiple of `n_a`, where the sinc product
/// vanishes (some `ν_a/n_a` is a non-zero integer). So `E|F|²/N = 1 − Π sinc²`.
#[must_use]
pub fn jittered_expected<const D: usize>(strata: [usize; D], j: [i32; D]) -> f64 {
    let mut p = 1.0;
    for a in 0..D {
        let s = sinc(f64::from(j[a]) / strata[a] as f64);
        p *= s * s;
    }
    1.0 - p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_of_is_exact_rounding() {
        for m in 0..100_000u64 {
            let r = crate::num::scalar::round(crate::num::scalar::sqrt(m as f64)) as u64;
            // round(√m) and the integer rule agree except exactly at m = r² ± r,
            // which cannot be a half (√m = r ± ½ needs m = r² ± r + ¼).
            assert_eq!(ring_of(m), r, "m = {m}");
        }
    }

    #[test]
    fn grid_index_roundtrip_and_multiplicity() {
        fn check<const D: usize>(k: usize) {
            let g = Grid::<D>::new(k).unwrap();
            let mut total = 0u64;
            for i in 0..g.len() {
                let j = g.freq(i);
                assert_eq!(g.index(j), Some((i, false)));
                let neg = j.map(|x| -x);
                let (ni, conj) = g.index(neg).unwrap();
                if j[0] > 0 {
                    assert!(conj);
                    assert_eq!(ni, i);
                    assert_eq!(g.multiplicity(i), 2);
                } else {
                    assert_eq!(g.multiplicity(i), 1);
                }
                total += u64::from(g.multiplicity(i));
            }
            // The stored cells stand for the whole grid [−k, k]^D, where the
            // plane j_0 = 0 is stored whole (both ν and −ν).
            assert_eq!(total, ((2 * k + 1) as u64).pow(D as u32));
        }
        check::<1>(5);
        check::<2>(4);
        check::<3>(3);
    }

    #[test]
    fn bad_grids_are_rejected() {
        assert!(matches!(
            Grid::<2>::new(0),
            Err(SpectrumError::HalfWidth { .. })
        ));
        assert!(matches!(
            Grid::<3>::new(1 << 12),
            Err(SpectrumError::HalfWidth { .. })
        ));
        assert!(matches!(
            Grid::<4>::new(3),
            Err(SpectrumError::Dimension { dim: 4 })
        ));
        assert!(Grid::<1>::new(MAX_HALF_WIDTH).is_ok());
    }
}
