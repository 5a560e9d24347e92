//! One view of the half-grid amplitudes of a realisation ([`AmplitudeView`]),
//! whoever computed them: the exact direct sum ([`super::Dft`]) or an external
//! transform such as a NUFFT writing into [`Amplitudes`]. The per-cell power
//! `|F|²/N` and the ring means of one realisation are computed here, once, for
//! every producer.

use super::{check_len, radial_into, zero_prefix, Grid};
use crate::error::SpectrumError;
use crate::num::Complex;

/// The Fourier amplitudes `F(ν) = Σ_k w_k(ν)·e^{−2πiν·x_k}` of one realisation
/// of `N` samples on the half grid of a [`Grid`] (see the
/// [module documentation](super)), however they were computed.
///
/// Implementors give the grid, the sample count `N` ([`AmplitudeView::count`])
/// and the amplitude of each stored cell ([`AmplitudeView::amplitude_at`], in
/// the cell order of [`Grid::freq`]); the periodogram of the realisation,
/// `N·P(ν) = |F(ν)|²/N`, its ring means and [`super::Periodogram::add`] are
/// derived from those here, so every producer gets the same numbers from the
/// same amplitudes, bit for bit. The power of a cell is evaluated as
/// `(re·re + im·im)·(1/N)` (two roundings of the squares, one of their sum,
/// one of the product; no fused multiply-add).
///
/// Implemented by [`super::Dft`] (the exact direct sum) and [`Amplitudes`]
/// (amplitudes written by an external transform, e.g. a type-1 NUFFT).
pub trait AmplitudeView<const D: usize> {
    /// The grid.
    fn grid(&self) -> Grid<D>;

    /// `N`, the number of samples of the realisation (the normalisation of
    /// `N·P = |F|²/N`).
    fn count(&self) -> u64;

    /// `F(j)` at a half-grid index of the grid (cell order of [`Grid::freq`]).
    ///
    /// # Panics
    /// Implementations may panic if `index ≥ grid.len()`.
    fn amplitude_at(&self, index: usize) -> Complex;

    /// Calls `f(first, re, im)` on runs of consecutive half-grid cells: cell
    /// `first + t` has amplitude `re[t] + i·im[t]`. The runs cover every cell
    /// `0..grid.len()` once, in increasing order, with `re.len() == im.len()`.
    ///
    /// The default calls [`AmplitudeView::amplitude_at`] one cell at a time;
    /// producers that store whole rows contiguously override it to hand out
    /// rows (or the whole array), which only changes the speed: every value
    /// derived from the view is computed from these runs by the same code.
    // A `dyn` callback keeps the trait object safe (`&dyn AmplitudeView<D>`).
    #[allow(clippy::type_complexity)]
    fn for_each_run(&self, f: &mut dyn FnMut(usize, &[f64], &[f64])) {
        for i in 0..self.grid().len() {
            let c = self.amplitude_at(i);
            f(i, &[c.re], &[c.im]);
        }
    }

    /// `F(j)` at any frequency of the full grid (`|j_a| ≤ k`), using
    /// `F(−j) = conj F(j)` for real weights; `None` outside the grid.
    fn amplitude(&self, j: [i32; D]) -> Option<Complex> {
        let (idx, conj) = self.grid().index(j)?;
        let c = self.amplitude_at(idx);
        Some(if conj {
            Complex {
                re: c.re,
                im: -c.im,
            }
        } else {
            c
        })
    }

    /// `|F(j)|²/N` for every half-grid cell, into `out` (grid layout), where
    /// `N` is [`AmplitudeView::count`]: the periodogram `N·P(ν)` of this
    /// realisation.
    ///
    /// # Errors
    /// [`SpectrumError::Length`] if `out.len() != grid.len()`;
    /// [`SpectrumError::Empty`] if `N = 0`.
    fn power(&self, out: &mut [f64]) -> Result<(), SpectrumError> {
        check_len("out", out.len(), self.grid().len())?;
        if self.count() == 0 {
            return Err(SpectrumError::Empty);
        }
        for_each_power(self, |i, v| out[i] = v);
        Ok(())
    }

    /// This realisation's radial average of `|F|²/N` (rings as in
    /// [`super::Periodogram::radial_average`]: `mean[r]` is the sum over the
    /// stored cells of ring `r` of multiplicity × power, in cell order, divided
    /// by the number `count[r]` of full-grid frequencies in the ring). Feed
    /// these to [`crate::stats::RunningStats`] per ring for standard errors
    /// across realisations. `mean` and `count` must have length `k + 1`.
    ///
    /// # Errors
    /// [`SpectrumError::Length`] (naming `mean` or `counts`);
    /// [`SpectrumError::Empty`] if `N = 0`.
    fn radial_power(&self, mean: &mut [f64], count: &mut [u64]) -> Result<(), SpectrumError> {
        let g = self.grid();
        check_len("mean", mean.len(), g.half_width() + 1)?;
        if self.count() == 0 {
            return Err(SpectrumError::Empty);
        }
        check_len("counts", count.len(), g.half_width() + 1)?;
        radial_into(g, mean, count, |add| for_each_power(self, add));
        Ok(())
    }
}

/// Calls `f(index, |F|²/N)` for every half-grid cell of `a` in index order:
/// the one place the power of a cell is evaluated, as `(re·re + im·im)·(1/N)`.
/// Runs reaching past the grid are cut (a faulty view cannot index out of
/// bounds downstream).
pub(crate) fn for_each_power<const D: usize, A: AmplitudeView<D> + ?Sized>(
    a: &A,
    mut f: impl FnMut(usize, f64),
) {
    let len = a.grid().len();
    let inv = 1.0 / a.count() as f64;
    a.for_each_run(&mut |first, re, im| {
        let m = re.len().min(im.len()).min(len.saturating_sub(first));
        for t in 0..m {
            let (x, y) = (re[t], im[t]);
            f(first + t, (x * x + y * y) * inv);
        }
    });
}

/// The checks every accumulator makes before adding a realisation (the
/// periodogram and [`super::PredictionStats`]): the same grid, at least one
/// sample, every amplitude finite.
pub(crate) fn check_realisation<const D: usize, A: AmplitudeView<D> + ?Sized>(
    grid: Grid<D>,
    a: &A,
) -> Result<(), SpectrumError> {
    if a.grid() != grid {
        return Err(SpectrumError::GridMismatch {
            left: grid.half_width(),
            right: a.grid().half_width(),
        });
    }
    if a.count() == 0 {
        return Err(SpectrumError::Empty);
    }
    match first_non_finite(a) {
        Some(index) => Err(SpectrumError::NonFinite {
            name: "amplitudes",
            index,
        }),
        None => Ok(()),
    }
}

/// The lowest half-grid index whose amplitude is NaN or ±∞, if any.
pub(crate) fn first_non_finite<const D: usize, A: AmplitudeView<D> + ?Sized>(
    a: &A,
) -> Option<usize> {
    let len = a.grid().len();
    let mut bad = None;
    a.for_each_run(&mut |first, re, im| {
        if bad.is_some() {
            return;
        }
        let m = re.len().min(im.len()).min(len.saturating_sub(first));
        if let Some(t) = re[..m]
            .iter()
            .zip(&im[..m])
            .position(|(x, y)| !(x.is_finite() && y.is_finite()))
        {
            bad = Some(first + t);
        }
    });
    bad
}

/// Half-grid amplitudes of one realisation in grid layout, written by a
/// producer outside the kernel (e.g. a type-1 NUFFT), with the realisation's
/// sample count `N`.
///
/// Storage is the caller's buffer `B` of [`Amplitudes::buffer_len`] values
/// (`Vec<f64>` via [`Amplitudes::new_vec`] with `alloc`): the real parts of
/// the `grid.len()` cells (order of [`Grid::freq`]) in the first `grid.len()`
/// values, the imaginary parts in the next `grid.len()`. Producers write them
/// through [`Amplitudes::parts_mut`] and set `N` with
/// [`Amplitudes::set_count`]; consumers read them through [`AmplitudeView`]
/// (e.g. [`super::Periodogram::add`], [`AmplitudeView::radial_power`]), with
/// the same values as for a [`super::Dft`] holding the same amplitudes.
#[derive(Clone, Debug)]
pub struct Amplitudes<const D: usize, B> {
    grid: Grid<D>,
    buf: B,
    count: u64,
}

#[cfg(feature = "alloc")]
impl<const D: usize> Amplitudes<D, alloc::vec::Vec<f64>> {
    /// Zeroed amplitudes (count 0) owning their buffer (**allocates**
    /// [`Amplitudes::buffer_len`] values).
    #[must_use]
    pub fn new_vec(grid: Grid<D>) -> Self {
        Amplitudes {
            grid,
            buf: alloc::vec![0.0; Self::buffer_len(grid)],
            count: 0,
        }
    }
}

impl<const D: usize, B> Amplitudes<D, B> {
    /// `2·grid.len()` (real parts, then imaginary parts).
    #[must_use]
    pub fn buffer_len(grid: Grid<D>) -> usize {
        2 * grid.len()
    }

    /// The grid.
    #[must_use]
    pub fn grid(&self) -> Grid<D> {
        self.grid
    }

    /// `N`, the number of samples of the realisation (0 until set).
    #[must_use]
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Sets `N`, the number of samples the amplitudes were computed from.
    pub fn set_count(&mut self, n: u64) {
        self.count = n;
    }
}

impl<const D: usize, B: AsRef<[f64]>> Amplitudes<D, B> {
    /// The real and imaginary parts, each `grid.len()` long (grid layout).
    #[must_use]
    pub fn parts(&self) -> (&[f64], &[f64]) {
        let n = self.grid.len();
        self.buf.as_ref()[..2 * n].split_at(n)
    }
}

impl<const D: usize, B: AsRef<[f64]> + AsMut<[f64]>> Amplitudes<D, B> {
    /// Zeroed amplitudes (count 0) over the caller's buffer.
    ///
    /// # Errors
    /// [`SpectrumError::Length`] (naming `buf`) if `buf` is shorter than
    /// [`Amplitudes::buffer_len`].
    pub fn new(grid: Grid<D>, mut buf: B) -> Result<Self, SpectrumError> {
        zero_prefix(buf.as_mut(), Self::buffer_len(grid))?;
        Ok(Amplitudes {
            grid,
            buf,
            count: 0,
        })
    }

    /// Zeroes the amplitudes and the count.
    pub fn clear(&mut self) {
        let n = Self::buffer_len(self.grid);
        self.buf.as_mut()[..n].fill(0.0);
        self.count = 0;
    }

    /// The real and imaginary parts for a producer to write, each
    /// `grid.len()` long (grid layout).
    pub fn parts_mut(&mut self) -> (&mut [f64], &mut [f64]) {
        let n = self.grid.len();
        self.buf.as_mut()[..2 * n].split_at_mut(n)
    }
}

impl<const D: usize, B: AsRef<[f64]>> AmplitudeView<D> for Amplitudes<D, B> {
    fn grid(&self) -> Grid<D> {
        self.grid
    }

    fn count(&self) -> u64 {
        self.count
    }

    /// # Panics
    /// If `index ≥ grid.len()`.
    fn amplitude_at(&self, index: usize) -> Complex {
        let (re, im) = self.parts();
        assert!(index < re.len(), "index out of range");
        Complex {
            re: re[index],
            im: im[index],
        }
    }

    fn for_each_run(&self, f: &mut dyn FnMut(usize, &[f64], &[f64])) {
        let (re, im) = self.parts();
        f(0, re, im);
    }
}
