//! The standard error of a spectral variance prediction, from the spread of
//! the per-realisation predictions ([`PredictionStats`]).
//!
//! The prediction `V̂ = (1/N) Σ_{ν≠0} ⟨N·P(ν)⟩·p_f(ν)` of
//! [`super::Periodogram::predict_variance`] is the mean over the `R`
//! realisations of `V_r = (1/N) Σ_{ν≠0} N·P_r(ν)·p_f(ν)`, the prediction of
//! realisation `r` alone. Realisations are independent, so the `V_r` are
//! i.i.d. and the standard error of their mean is the textbook
//! `SE(V̂) = s/√R` with `s² = Σ_r (V_r − V̂)²/(R − 1)`. The per-cell spread of
//! `N·P_r(ν)` does not give it: within a realisation the periodogram is
//! correlated across frequencies (strongly so for stratified and blue-noise
//! patterns), and that covariance is part of `Var(V_r)`. So the accumulator
//! evaluates `V_r` for each realisation, against integrand weights registered
//! up front, and keeps the power sums `Σ V_r`, `Σ V_r²`.

use super::amplitudes::{self, AmplitudeView};
use super::{check_len, Grid, Prediction};
use crate::error::{ParamError, SpectrumError};
use crate::num::{two_sum, Dd};

/// `2⁴⁸⁰`: the largest scaled per-realisation sum `t_r` accepted, so that
/// `t_r²`, `Σ t_r²` and `t̄·Σ t_r` stay finite for any `R < 2⁶³`.
const T_MAX: f64 = 3.121_748_550_315_992_2e144;

/// Per-realisation variance predictions of one integrand spectrum, and the
/// standard error of their mean.
///
/// Registered up front: the weights `w(ν) = m(ν)·p_f(ν)` of every stored
/// cell of the half grid ([`Grid::spectrum_weights`] fills them), where
/// `m(ν)` is [`Grid::multiplicity`] and `p_f` the even power spectrum of the
/// integrand (`|f̂|²` for points, the pre-filtered `|f̂|²·sinc²(λν·ω)` for
/// segments, the slice for lines; `docs/theory.md`, Spectral variance). The
/// weight of the DC cell is ignored. For each realisation [`Self::add`] forms
///
/// ```text
/// S_r = Σ_{ν≠0 in grid} w(ν)·|F_r(ν)|²/N_r        (so V_r = S_r/N)
/// ```
///
/// and [`Self::prediction`] reports, for `N` samples per estimate,
///
/// ```text
/// V̂ = S̄/N,   S̄ = (1/R) Σ_r S_r,
/// SE(V̂) = √( Σ_r (S_r − S̄)² / (R(R − 1)) ) / N,
/// ```
///
/// the sample mean of the `V_r` and its standard error `s/√R` (for i.i.d.
/// realisations `s²/R` is an unbiased estimate of `Var V̂`; e.g. Casella &
/// Berger, *Statistical Inference*, 2nd ed., §5.2). `V̂` is the estimator of
/// [`super::Periodogram::predict_variance`] with the same `p_f` over the same
/// realisations (equal to rounding, ~1e-15 relative), so the standard error
/// describes that prediction exactly. The part of the spectrum outside the
/// grid added as white noise ([`Prediction::with_white_tail`]) is a constant
/// and leaves the standard error unchanged.
///
/// **Arithmetic.** Each `S_r` is summed over the cells in cell order with a
/// compensated (TwoSum) sum, so it is a function of the realisation's
/// amplitudes only. The values are scaled by the power of two `2^{−e}` with
/// `2^{e−1} ≤ Σ w < 2^e` (exact; `e` clamped to `[−1000, 1000]`), which keeps
/// `t_r = 2^{−e}·S_r` of the order of the periodogram whatever the units of
/// `p_f`, and `Σ t_r`, `Σ t_r²` are kept as double-doubles with each square
/// formed exactly (TwoProd). Addition of double-doubles is accurate to `3u²`,
/// so [`Self::merge`] of any split of the realisations, in any order, gives
/// the sums of one accumulator fed everything to about `R·u²` relative,
/// below one rounding of the reported `f64`s: results do not depend on chunk
/// sizes, thread counts or merge order (bit for bit in the tests). The
/// sum of squared deviations is formed as `Σ t² − t̄·Σ t` in double-double,
/// which loses only `log₁₀(t̄²/s²)` of its ~32 digits.
///
/// Storage: the weights are the caller's (`W: AsRef<[f64]>`, e.g. `&[f64]`,
/// borrowed, or a `Vec<f64>` via [`Self::new_vec`] with `alloc`); the state
/// is a few numbers. Nothing allocates on [`Self::add`].
#[derive(Clone, Debug)]
pub struct PredictionStats<const D: usize, W> {
    grid: Grid<D>,
    weights: W,
    /// Index of the DC cell (its weight is skipped).
    dc: usize,
    /// `Σ_{ν≠0} w(ν)`, compensated.
    pf_in_grid: f64,
    /// `2^{−e}`.
    scale: f64,
    realisations: u64,
    /// `Σ t_r`.
    s1: Dd,
    /// `Σ t_r²`.
    s2: Dd,
}

/// `2^{−e}` with `2^{e−1} ≤ sum < 2^e` (`e` clamped to `[−1000, 1000]`), or 1
/// for a zero sum.
fn scale_for(sum: f64) -> f64 {
    if sum == 0.0 {
        return 1.0;
    }
    let (_, e) = libm::frexp(sum);
    libm::scalbn(1.0, -e.clamp(-1000, 1000))
}

/// Checks the weights (length, finite, non-negative) and returns the DC index,
/// `Σ_{ν≠0} w` and the scale.
fn check_weights<const D: usize>(
    grid: Grid<D>,
    w: &[f64],
) -> Result<(usize, f64, f64), SpectrumError> {
    check_len("weights", w.len(), grid.len())?;
    if let Some(index) = w.iter().position(|v| !v.is_finite()) {
        return Err(SpectrumError::NonFinite {
            name: "weights",
            index,
        });
    }
    if let Some(&value) = w.iter().find(|&&v| v < 0.0) {
        return Err(ParamError::OutOfRange {
            name: "weights",
            value,
            min: 0.0,
            max: f64::MAX,
        }
        .into());
    }
    let dc = grid.index([0; D]).map_or(0, |(i, _)| i);
    let (mut s, mut e) = (0.0, 0.0);
    for (i, &x) in w.iter().enumerate() {
        if i != dc {
            let (a, b) = two_sum(s, x);
            s = a;
            e += b;
        }
    }
    let sum = s + e;
    if !sum.is_finite() {
        return Err(ParamError::OutOfRange {
            name: "weights",
            value: sum,
            min: 0.0,
            max: f64::MAX,
        }
        .into());
    }
    Ok((dc, sum, scale_for(sum)))
}

#[cfg(feature = "alloc")]
impl<const D: usize> PredictionStats<D, alloc::vec::Vec<f64>> {
    /// An empty accumulator owning its weights `w(ν) = m(ν)·p_f(ν)`, filled
    /// from the even power spectrum `p_f` by [`Grid::spectrum_weights`]
    /// (**allocates** `grid.len()` values).
    ///
    /// # Errors
    /// As [`Grid::spectrum_weights`] (naming `p_f`).
    pub fn new_vec(grid: Grid<D>, p_f: impl FnMut([i32; D]) -> f64) -> Result<Self, SpectrumError> {
        let mut w = alloc::vec![0.0; grid.len()];
        grid.spectrum_weights(p_f, &mut w)?;
        Self::new(grid, w)
    }
}

impl<const D: usize, W: AsRef<[f64]>> PredictionStats<D, W> {
    /// An empty accumulator for the integrand weights `weights` (length
    /// `grid.len()`, cell order of [`Grid::freq`], `w(ν) = m(ν)·p_f(ν)` as
    /// [`Grid::spectrum_weights`] writes them; the DC weight is ignored).
    ///
    /// # Errors
    /// [`SpectrumError::Length`] (naming `weights`) if the length is not
    /// `grid.len()`; [`SpectrumError::NonFinite`] (naming `weights` and the
    /// first bad cell) for NaN or ±∞; [`SpectrumError::Param`] with
    /// [`ParamError::OutOfRange`] naming `weights` if a weight is negative (a
    /// power spectrum is not) or their sum overflows.
    pub fn new(grid: Grid<D>, weights: W) -> Result<Self, SpectrumError> {
        let (dc, pf_in_grid, scale) = check_weights(grid, weights.as_ref())?;
        Ok(PredictionStats {
            grid,
            weights,
            dc,
            pf_in_grid,
            scale,
            realisations: 0,
            s1: Dd::ZERO,
            s2: Dd::ZERO,
        })
    }

    /// The grid.
    #[must_use]
    pub fn grid(&self) -> Grid<D> {
        self.grid
    }

    /// The registered weights `w(ν) = m(ν)·p_f(ν)`.
    #[must_use]
    pub fn weights(&self) -> &[f64] {
        self.weights.as_ref()
    }

    /// `Σ_{ν≠0 in grid} w(ν) = Σ_{ν≠0 in grid} p_f(ν)` over the full grid (as
    /// [`Prediction::pf_in_grid`]).
    #[must_use]
    pub fn pf_in_grid(&self) -> f64 {
        self.pf_in_grid
    }

    /// Realisations accumulated, `R`.
    #[must_use]
    pub fn realisations(&self) -> u64 {
        self.realisations
    }

    /// Adds one finished realisation and returns its sum
    /// `S_r = Σ_{ν≠0 in grid} w(ν)·|F_r(ν)|²/N_r` (its own prediction is
    /// `V_r = S_r/N`), with `|F|²/N_r` evaluated as [`AmplitudeView`]
    /// documents (the same per-cell values [`super::Periodogram::add`]
    /// accumulates). No allocation.
    ///
    /// # Errors
    /// [`SpectrumError::GridMismatch`]; [`SpectrumError::Empty`] if the
    /// realisation has no samples; [`SpectrumError::NonFinite`] (naming
    /// `amplitudes` and the first bad cell) if an amplitude is NaN or ±∞;
    /// [`SpectrumError::Param`] with [`ParamError::OutOfRange`] naming
    /// `amplitudes` if `S_r` is so large that its square would overflow
    /// (`2^{−e}·S_r ≥ 2⁴⁸⁰`, i.e. `|F|²/N` near `10¹⁴⁴`). Nothing is added on
    /// error.
    pub fn add<A: AmplitudeView<D> + ?Sized>(&mut self, amps: &A) -> Result<f64, SpectrumError> {
        amplitudes::check_realisation(self.grid, amps)?;
        let w = self.weights.as_ref();
        let (dc, scale) = (self.dc, self.scale);
        let (mut s, mut e) = (0.0, 0.0);
        amplitudes::for_each_power(amps, |i, p| {
            if i != dc {
                let (a, b) = two_sum(s, (w[i] * scale) * p);
                s = a;
                e += b;
            }
        });
        let t = s + e;
        // `t ≥ 0` (weights and powers are); NaN or ∞ from overflowing squares
        // fail the range test too.
        if !(0.0..T_MAX).contains(&t) {
            return Err(ParamError::OutOfRange {
                name: "amplitudes",
                value: t / scale,
                min: 0.0,
                max: T_MAX / scale,
            }
            .into());
        }
        self.s1 = self.s1.add(Dd::new(t));
        self.s2 = self.s2.add(Dd::prod(t, t));
        self.realisations += 1;
        Ok(t / scale)
    }

    /// Adds another accumulator's realisations (exact up to `~R·u²`, so the
    /// result does not depend on how the realisations were split).
    ///
    /// # Errors
    /// [`SpectrumError::GridMismatch`]; [`SpectrumError::WeightsMismatch`]
    /// (naming the first differing cell) unless both have the same weights,
    /// bit for bit.
    pub fn merge<W2: AsRef<[f64]>>(
        &mut self,
        other: &PredictionStats<D, W2>,
    ) -> Result<(), SpectrumError> {
        if other.grid != self.grid {
            return Err(SpectrumError::GridMismatch {
                left: self.grid.half_width(),
                right: other.grid.half_width(),
            });
        }
        let (a, b) = (self.weights.as_ref(), other.weights.as_ref());
        if let Some(index) = a
            .iter()
            .zip(b)
            .position(|(x, y)| x.to_bits() != y.to_bits())
        {
            return Err(SpectrumError::WeightsMismatch { index });
        }
        self.s1 = self.s1.add(other.s1);
        self.s2 = self.s2.add(other.s2);
        self.realisations += other.realisations;
        Ok(())
    }

    /// The prediction for `n` samples per estimate and its standard error:
    /// `grid = S̄/n` (0 before any realisation) and
    /// `std_error = √(Σ_r (S_r − S̄)²/(R(R − 1)))/n` (`None` for `R < 2`),
    /// with `pf_in_grid` and `realisations` set (see the type's
    /// documentation for the formula and its source). Always finite.
    ///
    /// # Errors
    /// [`SpectrumError::Param`] with [`ParamError::Count`] naming `n` if it
    /// is 0.
    pub fn prediction(&self, n: u64) -> Result<Prediction, SpectrumError> {
        if n == 0 {
            return Err(ParamError::Count {
                name: "n",
                value: 0,
            }
            .into());
        }
        let nf = n as f64;
        let r = self.realisations;
        let rf = r as f64;
        let (grid, std_error) = if r == 0 {
            (0.0, None)
        } else {
            let mean = self.s1.div(Dd::new(rf));
            let se = (r >= 2).then(|| {
                // Σ (t − t̄)² = Σ t² − t̄·Σ t, in double-double.
                let ss = self.s2.sub(mean.mul(self.s1)).to_f64().max(0.0);
                crate::num::scalar::sqrt(ss / (rf - 1.0) / rf) / self.scale / nf
            });
            (mean.to_f64() / self.scale / nf, se)
        };
        Ok(Prediction {
            grid,
            std_error,
            pf_in_grid: self.pf_in_grid,
            n,
            realisations: r,
        })
    }

    /// The accumulator state, to persist it (resume a run, merge shards
    /// computed elsewhere): `(R, [Σt.hi, Σt.lo, Σt².hi, Σt².lo])`, the
    /// double-double sums of the scaled `t_r = 2^{−e}·S_r` (the scale is
    /// fixed by the weights). [`Self::from_parts`] with the same weights
    /// rebuilds the same accumulator, bit for bit.
    #[must_use]
    pub fn parts(&self) -> (u64, [f64; 4]) {
        (
            self.realisations,
            [self.s1.hi, self.s1.lo, self.s2.hi, self.s2.lo],
        )
    }

    /// An accumulator holding exported state ([`Self::parts`]) for the same
    /// weights, kept as they are.
    ///
    /// # Errors
    /// As [`Self::new`] for the weights; [`SpectrumError::NonFinite`]
    /// (naming `sums` and the index) for NaN or ±∞;
    /// [`SpectrumError::Param`] with [`ParamError::OutOfRange`] naming `sums`
    /// if a sum is negative or larger than `R` accepted values can make
    /// (`Σt ≤ R·2⁴⁸⁰`, `Σt² ≤ R·2⁹⁶⁰`), and with [`ParamError::Count`] naming
    /// `realisations` if it is 0 while a sum is non-zero.
    pub fn from_parts(
        grid: Grid<D>,
        weights: W,
        realisations: u64,
        sums: [f64; 4],
    ) -> Result<Self, SpectrumError> {
        let mut acc = Self::new(grid, weights)?;
        if let Some(index) = sums.iter().position(|v| !v.is_finite()) {
            return Err(SpectrumError::NonFinite {
                name: "sums",
                index,
            });
        }
        if realisations == 0 && sums.iter().any(|&v| v != 0.0) {
            return Err(ParamError::Count {
                name: "realisations",
                value: 0,
            }
            .into());
        }
        let rf = realisations as f64;
        let (s1, s2) = (sums[0] + sums[1], sums[2] + sums[3]);
        for (value, max) in [(s1, rf * T_MAX), (s2, rf * T_MAX * T_MAX)] {
            if !(0.0..=max).contains(&value) {
                return Err(ParamError::OutOfRange {
                    name: "sums",
                    value,
                    min: 0.0,
                    max,
                }
                .into());
            }
        }
        acc.realisations = realisations;
        acc.s1 = Dd {
            hi: sums[0],
            lo: sums[1],
        };
        acc.s2 = Dd {
            hi: sums[2],
            lo: sums[3],
        };
        Ok(acc)
    }
}

impl<const D: usize> Grid<D> {
    /// Fills `out` (length `len()`, cell order of [`Grid::freq`]) with the
    /// prediction weights `w(ν) = m(ν)·p_f(ν)` of an even power spectrum
    /// `p_f(ν) = p_f(−ν)` (`m` = [`Grid::multiplicity`]: a cell with `j_0 > 0`
    /// stands for `ν` and `−ν`), 0 at DC, and returns
    /// `Σ_{ν≠0 in grid} p_f(ν) = Σ w` (compensated). These are the weights of
    /// [`PredictionStats`]; with them the prediction of
    /// [`super::Periodogram::predict_variance`] is `(1/N) Σ ⟨N·P⟩·w`.
    ///
    /// # Errors
    /// [`SpectrumError::Length`] (naming `out`); [`SpectrumError::NonFinite`]
    /// (naming `p_f` and the cell) if `p_f` returns NaN or ±∞;
    /// [`SpectrumError::Param`] with [`ParamError::OutOfRange`] naming `p_f`
    /// if it returns a negative value. `out` is unspecified on error.
    pub fn spectrum_weights(
        &self,
        mut p_f: impl FnMut([i32; D]) -> f64,
        out: &mut [f64],
    ) -> Result<f64, SpectrumError> {
        check_len("out", out.len(), self.len())?;
        let (mut s, mut e) = (0.0, 0.0);
        for (i, o) in out.iter_mut().enumerate() {
            let j = self.freq(i);
            if j.iter().all(|&x| x == 0) {
                *o = 0.0;
                continue;
            }
            let v = p_f(j);
            if !v.is_finite() {
                return Err(SpectrumError::NonFinite {
                    name: "p_f",
                    index: i,
                });
            }
            if v < 0.0 {
                return Err(ParamError::OutOfRange {
                    name: "p_f",
                    value: v,
                    min: 0.0,
                    max: f64::MAX,
                }
                .into());
            }
            *o = f64::from(self.multiplicity(i)) * v;
            let (a, b) = two_sum(s, *o);
            s = a;
            e += b;
        }
        Ok(s + e)
    }
}
