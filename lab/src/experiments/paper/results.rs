//! The paper's results, computed from the finished cells: per-curve variance
//! rows, log-aware slope fits and verdicts, predictions against measurements,
//! cost rows, time-to-error, where lines overtake points, direction-group
//! ratios, and the timing tables. Everything the report shows and the CSVs
//! hold comes from here; nothing here writes files.

use linesample::stats::Ratio;
use serde::Serialize;

use super::plan::{Curve, Table};
use super::theory::Theory;
use super::timing::{NufftRow, SimdRow};
use super::{Cell, Paper};
use crate::experiments::convergence::{self, DirSpec, RowResult};
use crate::fit::{fit_loglog, Fit};
use crate::integrand::IntegrandKind;
use crate::spec::Primitive;
use crate::{LabError, Result};

/// Slope tolerance of the verdicts: a theory slope within the 95 % interval
/// widened by this much is "consistent". A log-log fit over one to three
/// decades of N cannot resolve an asymptotic exponent better than this: the
/// sub-leading terms of the variance (e.g. the next power of `1/N`, or a log
/// factor the theory does not state) shift a fitted slope by about 0.05–0.1
/// at these N.
pub const SLOPE_TOLERANCE: f64 = 0.1;

/// Family-wise false-alarm rate of the prediction comparison (Bonferroni over
/// the compared rows): a correct prediction flags any row of a run with at
/// most this probability (it is also the budget the lab's tests give it).
pub const PREDICTION_ALPHA: f64 = 5e-4;

/// Relative accuracy the prediction is held to where the standard errors can
/// resolve it.
pub const PREDICTION_REL: f64 = 0.05;

/// Two error-against-time exponents closer than this count as the same rate.
pub const SAME_RATE: f64 = 0.05;

/// Relative errors of the time-to-error table.
pub const TARGETS: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// One curve's measured rows.
#[derive(Clone, Debug, Serialize)]
pub struct CurveResult {
    /// The exact integral (0 for the randomised edge, whose rows hold errors).
    pub exact: f64,
    pub rows: Vec<RowResult>,
    /// Empirical mean squared error about the exact value per row:
    /// `Var·(R−1)/R + (mean − exact)²`.
    pub mse: Vec<f64>,
    /// The spectral prediction per row (value, standard error), if any.
    pub predicted: Vec<Option<(f64, f64)>>,
}

/// A slope fit with its 95 % interval.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SlopeFit {
    pub slope: f64,
    pub ci_low: f64,
    pub ci_high: f64,
    /// Intercept of `ln(Var/(ln N)^p) = a + s ln N`.
    pub intercept: f64,
    pub chi2_dof: f64,
    pub points: usize,
}

/// The verdict of a rate row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    Consistent,
    NotConsistent,
    PreAsymptotic,
    /// Fewer than two usable N.
    NotFitted,
    /// The fixed-edge pitfall: no homogenisation, no theory.
    Pitfall,
}

impl Verdict {
    /// The word in `rates.csv`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Consistent => "consistent",
            Verdict::NotConsistent => "not consistent",
            Verdict::PreAsymptotic => "pre-asymptotic",
            Verdict::NotFitted => "not fitted",
            Verdict::Pitfall => "pitfall (not homogenised)",
        }
    }
}

/// One row of a rate table.
#[derive(Clone, Debug, Serialize)]
pub struct RateRow {
    pub table: Table,
    pub curve: usize,
    /// `""`, or the segment regime `N < N*` / `N > N*`.
    pub regime: String,
    pub theory: Option<Theory>,
    pub n_min: usize,
    pub n_max: usize,
    pub fit: Option<SlopeFit>,
    /// Slope between the two largest N of the range, and its 95 % half-width.
    pub last_slope: Option<(f64, f64)>,
    pub verdict: Verdict,
}

/// A predicted row against its measurement.
#[derive(Clone, Debug, Serialize)]
pub struct PredRow {
    pub curve: usize,
    pub row: usize,
    pub n: usize,
    pub predicted: f64,
    pub predicted_se: f64,
    pub measured: f64,
    pub measured_se: f64,
    /// `predicted/measured − 1`.
    pub rel: f64,
    /// `predicted/measured` and its delta-method SE (`stats::Ratio`; NaN
    /// where either SE is unknown or the measurement is 0).
    pub ratio: f64,
    pub ratio_se: f64,
    /// `(predicted − measured)/√(SE_p² + SE_m²)`.
    pub z: f64,
    /// `z_crit·√(SE_p² + SE_m²)/measured ≤ 5 %`: the row can resolve 5 %.
    pub resolves: bool,
    pub agrees: bool,
}

/// One row of `cost.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct CostRow {
    pub curve: usize,
    pub n: usize,
    pub rmse: f64,
    /// `rmse/|exact|`.
    pub rel_rmse: f64,
    /// Wall time of one estimate on one thread (pattern, evaluation, sum).
    pub seconds: f64,
    /// Closed-form evaluations per estimate (one per primitive).
    pub evaluations: u64,
}

/// Time to reach a relative error, from the power law fitted to a curve's
/// `(seconds, rel_rmse)` points.
#[derive(Clone, Debug, Serialize)]
pub struct TimeToError {
    pub curve: usize,
    /// `rel_rmse = e^a·t^b`.
    pub a: f64,
    pub b: f64,
    /// Seconds per estimate for each of [`TARGETS`], and whether it lies
    /// outside the measured errors (extrapolated).
    pub times: Vec<Option<(f64, bool)>>,
}

/// Points against lines at equal time.
#[derive(Clone, Debug, Serialize)]
pub struct Overtake {
    pub points: usize,
    pub lines: usize,
    /// Seconds per primitive of lines over points, at the largest common N.
    pub cost_ratio: f64,
    /// Time per estimate above which lines give the lower error (fitted
    /// power laws), if the lines' error falls faster.
    pub crossover_seconds: Option<f64>,
    /// One sentence.
    pub summary: String,
}

/// Direction groups against one direction at the same N.
#[derive(Clone, Debug, Serialize)]
pub struct DirRatio {
    pub curve: usize,
    pub n: usize,
    pub ratio: f64,
    pub ratio_se: f64,
}

/// Everything the report shows.
#[derive(Clone, Debug, Serialize)]
pub struct Results {
    pub curves: Vec<CurveResult>,
    pub rates: Vec<RateRow>,
    pub predictions: Vec<PredRow>,
    pub z_crit: f64,
    /// Inverse-variance weighted mean of `predicted/measured − 1` over every
    /// predicted row, and its standard error: a systematic error of the
    /// prediction shows here even where no single row resolves it.
    pub pooled_rel: (f64, f64),
    pub costs: Vec<CostRow>,
    pub time_to_error: Vec<TimeToError>,
    pub overtakes: Vec<Overtake>,
    pub dir_ratios: Vec<DirRatio>,
    /// The slope of the single-direction curve used for `K^(r−1)`.
    pub dir_rate: Option<f64>,
    pub simd: Vec<super::timing::SimdRow>,
    pub nufft: Vec<super::timing::NufftRow>,
}

/// Two-sided 97.5 % quantile of Student's t with `dof` degrees of freedom
/// (tabulated for 1–10; the normal 1.96 beyond 30; linear in `1/dof` between).
#[must_use]
pub fn t975(dof: usize) -> f64 {
    const T: [f64; 10] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
    ];
    match dof {
        0 => f64::INFINITY,
        1..=10 => T[dof - 1],
        _ if dof >= 30 => 1.96,
        _ => 1.96 + (2.228 - 1.96) * (1.0 / dof as f64 - 1.0 / 30.0) / (0.1 - 1.0 / 30.0),
    }
}

/// Upper-tail normal quantile `z` with `P(Z > z) = p`: the kernel's
/// [`linesample::stats::normal_upper_quantile`].
pub use linesample::stats::normal_upper_quantile as normal_quantile;

/// The log-aware fit of rows `(N, Var, SE)`: weighted least squares of
/// `ln(Var/(ln N)^p)` against `ln N` with weights `(Var/SE)²` (the inverse
/// variance of `ln Var`), so the fitted slope estimates the power of `N`
/// with the theory's log factor `(log N)^p` divided out. The 95 % interval is
/// `±1.96·SE(slope)` when the residuals are as small as the weights say
/// (`χ²/dof ≤ 1`), and `±t(dof)·SE·√(χ²/dof)` when they scatter more (the
/// curve is not a pure power law over the range).
#[must_use]
pub fn slope_fit(rows: &[(f64, f64, f64)], log_power: u32) -> Option<SlopeFit> {
    let data: Vec<(f64, f64, f64)> = rows
        .iter()
        .map(|&(n, v, se)| {
            let l = n.ln().powi(log_power as i32);
            (n, v / l, se / l)
        })
        .collect();
    let f: Fit = fit_loglog(&data)?;
    let dof = f.points.saturating_sub(2);
    let hw = if dof == 0 || f.chi2_dof <= 1.0 || !f.chi2_dof.is_finite() {
        1.96 * f.slope_se
    } else {
        t975(dof) * f.slope_se * f.chi2_dof.sqrt()
    };
    Some(SlopeFit {
        slope: f.slope,
        ci_low: f.slope - hw,
        ci_high: f.slope + hw,
        intercept: f.intercept,
        chi2_dof: f.chi2_dof,
        points: f.points,
    })
}

/// The local slope between two rows and its 95 % half-width (delta method).
fn two_point(a: (f64, f64, f64), b: (f64, f64, f64), log_power: u32) -> Option<(f64, f64)> {
    let (n0, v0, s0) = a;
    let (n1, v1, s1) = b;
    if v0 <= 0.0 || v1 <= 0.0 || n1 <= n0 {
        return None;
    }
    let lp = f64::from(log_power);
    let dx = (n1 / n0).ln();
    let s = ((v1 / v0).ln() - lp * (n1.ln().ln() - n0.ln().ln())) / dx;
    let hw = 1.96 * ((s0 / v0).powi(2) + (s1 / v1).powi(2)).sqrt() / dx;
    Some((s, hw))
}

/// The verdict rule: **consistent** if the theory slope lies in the 95 %
/// interval widened by [`SLOPE_TOLERANCE`]; otherwise **pre-asymptotic** if
/// the slope between the two largest N (with its own 95 % interval, widened
/// the same way) is consistent with it — the curve is still bending towards
/// its rate; otherwise **not consistent**.
#[must_use]
pub fn verdict(theory: f64, fit: Option<&SlopeFit>, last: Option<(f64, f64)>) -> Verdict {
    let Some(f) = fit else {
        return Verdict::NotFitted;
    };
    if theory >= f.ci_low - SLOPE_TOLERANCE && theory <= f.ci_high + SLOPE_TOLERANCE {
        return Verdict::Consistent;
    }
    match last {
        Some((s, hw)) if (s - theory).abs() <= hw + SLOPE_TOLERANCE => Verdict::PreAsymptotic,
        _ => Verdict::NotConsistent,
    }
}

/// The N range a rate row fits: the upper two thirds of the N values (the
/// smallest third is the most pre-asymptotic), at least three N when there
/// are three or more.
#[must_use]
pub fn fit_range(n: usize) -> std::ops::Range<usize> {
    let drop = (n / 3).min(n.saturating_sub(3));
    drop..n
}

fn rate_row(
    table: Table,
    ci: usize,
    regime: &str,
    theory: Option<Theory>,
    pts: &[(f64, f64, f64)],
) -> Option<RateRow> {
    if pts.is_empty() {
        return None;
    }
    let p = theory.map_or(0, |t| t.log_power);
    let fit = slope_fit(pts, p);
    let last = (pts.len() >= 2)
        .then(|| two_point(pts[pts.len() - 2], pts[pts.len() - 1], p))
        .flatten();
    let verdict = match theory {
        None => Verdict::Pitfall,
        Some(t) => verdict(t.slope, fit.as_ref(), last),
    };
    Some(RateRow {
        table,
        curve: ci,
        regime: regime.to_string(),
        theory,
        n_min: pts[0].0 as usize,
        n_max: pts[pts.len() - 1].0 as usize,
        fit,
        last_slope: last,
        verdict,
    })
}

/// The rate rows of one curve in one table (segments: one row per regime
/// around `N* = λ^(−d)` with at least two N).
fn curve_rates(table: Table, ci: usize, c: &Curve, r: &CurveResult) -> Vec<RateRow> {
    let all: Vec<(f64, f64, f64)> = r
        .rows
        .iter()
        .map(|x| (x.row.n as f64, x.variance, x.variance_se))
        .collect();
    if let Some(nstar) = c.crossover() {
        if c.run.integrand.kind != IntegrandKind::Gaussian {
            let below: Vec<_> = all.iter().copied().filter(|p| p.0 < nstar).collect();
            let above: Vec<_> = all.iter().copied().filter(|p| p.0 >= nstar).collect();
            let mut out = Vec::new();
            if below.len() >= 2 {
                out.extend(rate_row(
                    table,
                    ci,
                    "N < N*",
                    Some(c.point_theory()),
                    &below,
                ));
            }
            if above.len() >= 2 {
                out.extend(rate_row(table, ci, "N > N*", c.theory(), &above));
            }
            if out.is_empty() {
                out.extend(rate_row(table, ci, "", c.theory(), &all));
            }
            return out;
        }
    }
    let range = fit_range(all.len());
    rate_row(table, ci, "", c.theory(), &all[range])
        .into_iter()
        .collect()
}

/// A cell's convergence chunks, or an error naming it.
fn conv_cell(cells: &[Cell], i: usize) -> Result<&convergence::Cell> {
    match cells.get(i) {
        Some(Cell::Conv(c)) => Ok(c),
        _ => Err(LabError::Internal(format!("cell {i} is not a curve row"))),
    }
}

/// The rows of a randomised-edge curve (errors, so the exact value is 0).
fn edge_rows(c: &Curve, cells: &[&convergence::Cell]) -> Result<Vec<RowResult>> {
    c.run
        .rows
        .iter()
        .zip(cells)
        .map(|(row, cell)| {
            convergence::row_result(row, cell, 0.0, c.run.realisations)
                .map_err(|e| LabError::Message(format!("{}: {e}", c.id)))
        })
        .collect()
}

impl Paper {
    /// The results of the finished cells.
    ///
    /// # Errors
    /// If a stored cell is invalid.
    pub fn results(&self, cells: &[Cell]) -> Result<Results> {
        let cfg = self.config();
        if cells.len() != self.jobs.len() {
            return Err(LabError::Internal(format!(
                "{} cells for {} jobs",
                cells.len(),
                self.jobs.len()
            )));
        }
        let (mut curves, mut cursor) = self.curve_results(cells)?;
        let raw = self.read_predictions(cells, cursor, &mut curves)?;
        cursor += cfg.predictions.len();
        let z_crit = normal_quantile(PREDICTION_ALPHA / (2.0 * raw.len().max(1) as f64));
        let predictions = prediction_rows(raw, &curves, z_crit);
        let pooled_rel = pooled(&predictions);
        let (simd, nufft) = timing_cells(&cells[cursor..])?;
        let rates = rate_rows(cfg.curves.as_slice(), &curves);
        let costs = costs(cfg.curves.as_slice(), &curves);
        let time_to_error = time_to_error(cfg.curves.as_slice(), &costs);
        let overtakes = overtakes(cfg.curves.as_slice(), &costs, &time_to_error);
        let (dir_ratios, dir_rate) = dir_ratios(cfg.curves.as_slice(), &curves, &rates);
        Ok(Results {
            curves,
            rates,
            predictions,
            z_crit,
            pooled_rel,
            costs,
            time_to_error,
            overtakes,
            dir_ratios,
            dir_rate,
            simd,
            nufft,
        })
    }

    /// Every curve's rows and MSE (predictions not yet filled in), from the
    /// cells in curve order; and the index of the first cell after them.
    fn curve_results(&self, cells: &[Cell]) -> Result<(Vec<CurveResult>, usize)> {
        let cfg = self.config();
        let mut curves = Vec::new();
        let mut cursor = 0;
        for (ci, c) in cfg.curves.iter().enumerate() {
            let mine: Vec<&convergence::Cell> = (0..c.run.rows.len())
                .map(|r| conv_cell(cells, cursor + r))
                .collect::<Result<_, _>>()?;
            cursor += c.run.rows.len();
            let (exact, rows) = match self.convergence(ci) {
                Some(conv) => {
                    let owned: Vec<convergence::Cell> = mine.into_iter().cloned().collect();
                    let res = conv.results(&owned)?;
                    (res.exact, res.rows)
                }
                None => (0.0, edge_rows(c, &mine)?),
            };
            let rr = c.run.realisations as f64;
            let mse = rows
                .iter()
                .map(|x| x.variance * (rr - 1.0) / rr + (x.mean - exact).powi(2))
                .collect();
            let predicted = vec![None; rows.len()];
            curves.push(CurveResult {
                exact,
                rows,
                mse,
                predicted,
            });
        }
        Ok((curves, cursor))
    }

    /// Fills in the curves' predicted variances from the prediction cells
    /// (from `cursor` on) and returns them as `(curve, row, predicted, SE)`.
    fn read_predictions(
        &self,
        cells: &[Cell],
        cursor: usize,
        curves: &mut [CurveResult],
    ) -> Result<Vec<(usize, usize, f64, f64)>> {
        let cfg = self.config();
        let mut raw = Vec::new();
        for (pi, p) in cfg.predictions.iter().enumerate() {
            let Some(Cell::Pred(pc)) = cells.get(cursor + pi) else {
                return Err(LabError::Internal(format!(
                    "cell {} is not a prediction",
                    cursor + pi
                )));
            };
            if pc.rows.len() != p.rows.len() {
                return Err(LabError::Message(format!(
                    "stored prediction {pi} has {} rows, expected {}",
                    pc.rows.len(),
                    p.rows.len()
                )));
            }
            for (&(c, r), rp) in p.rows.iter().zip(&pc.rows) {
                // An unknown SE (fewer than 2 realisations) is infinite: the
                // row cannot disagree and resolves nothing.
                let se = rp.predicted_se.unwrap_or(f64::INFINITY);
                curves[c].predicted[r] = Some((rp.predicted, se));
                raw.push((c, r, rp.predicted, se));
            }
        }
        Ok(raw)
    }
}

/// Each prediction against its measured variance: the z-score with the
/// Bonferroni critical value `z_crit`, and whether it agrees.
fn prediction_rows(
    raw: Vec<(usize, usize, f64, f64)>,
    curves: &[CurveResult],
    z_crit: f64,
) -> Vec<PredRow> {
    raw.into_iter()
        .map(|(c, r, p, pse)| {
            let m = &curves[c].rows[r];
            let se = pse.hypot(m.variance_se);
            let z = if se > 0.0 { (p - m.variance) / se } else { 0.0 };
            let rel = p / m.variance - 1.0;
            let resolves = z_crit * se / m.variance <= PREDICTION_REL;
            let (ratio, ratio_se) = Ratio::new(p, pse, m.variance, m.variance_se)
                .map_or((f64::NAN, f64::NAN), |q| (q.value, q.std_error));
            PredRow {
                curve: c,
                row: r,
                n: m.row.n,
                predicted: p,
                predicted_se: pse,
                measured: m.variance,
                measured_se: m.variance_se,
                rel,
                ratio,
                ratio_se,
                z,
                resolves,
                agrees: z.abs() <= z_crit && (!resolves || rel.abs() <= PREDICTION_REL),
            }
        })
        .collect::<Vec<PredRow>>()
}

/// The timing cells, which come last: the SIMD rows and the NUFFT sweep.
fn timing_cells(cells: &[Cell]) -> Result<(Vec<SimdRow>, Vec<NufftRow>)> {
    let mut simd = Vec::new();
    let mut nufft = Vec::new();
    for cell in cells {
        match cell {
            Cell::Simd(s) => simd.push(s.clone()),
            Cell::Nufft(v) => nufft.extend(v.iter().cloned()),
            _ => return Err(LabError::Internal("a timing cell out of place".into())),
        }
    }
    Ok((simd, nufft))
}

/// The rows of every table, table by table in report order.
fn rate_rows(cfg_curves: &[Curve], curves: &[CurveResult]) -> Vec<RateRow> {
    let mut rates = Vec::new();
    for table in [
        Table::Rates,
        Table::Segments,
        Table::Directions,
        Table::Offsets,
        Table::Edge,
    ] {
        for (ci, c) in cfg_curves.iter().enumerate() {
            if c.tables.contains(&table) {
                rates.extend(curve_rates(table, ci, c, &curves[ci]));
            }
        }
    }
    rates
}

/// Inverse-variance weighted mean of the relative differences
/// (`w = (measured/SE)²`, SE the combined standard error) and its SE.
fn pooled(rows: &[PredRow]) -> (f64, f64) {
    let (mut sw, mut swr) = (0.0, 0.0);
    for p in rows {
        let se = p.predicted_se.hypot(p.measured_se) / p.measured;
        if se > 0.0 && se.is_finite() && p.rel.is_finite() {
            let w = 1.0 / (se * se);
            sw += w;
            swr += w * p.rel;
        }
    }
    if sw > 0.0 {
        (swr / sw, 1.0 / sw.sqrt())
    } else {
        (f64::NAN, f64::NAN)
    }
}

/// Cost rows of every curve but the straight edge (whose errors are about
/// a different integral per realisation).
fn costs(curves: &[Curve], res: &[CurveResult]) -> Vec<CostRow> {
    let mut out = Vec::new();
    for (ci, (c, r)) in curves.iter().zip(res).enumerate() {
        if c.edge.is_some() {
            continue;
        }
        for (row, mse) in r.rows.iter().zip(&r.mse) {
            let rmse = mse.sqrt();
            out.push(CostRow {
                curve: ci,
                n: row.row.n,
                rmse,
                rel_rmse: rmse / r.exact.abs(),
                seconds: row.us_per_realisation * 1e-6,
                evaluations: row.row.n as u64,
            });
        }
    }
    out
}

/// Ordinary least squares `y = a + b x`.
fn ols(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = pts.len() as f64;
    if pts.len() < 2 {
        return None;
    }
    let xm = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let ym = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - xm).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - xm) * (p.1 - ym)).sum();
    (sxx > 0.0).then(|| (ym - sxy / sxx * xm, sxy / sxx))
}

fn time_to_error(curves: &[Curve], costs: &[CostRow]) -> Vec<TimeToError> {
    let mut out = Vec::new();
    for ci in 0..curves.len() {
        let pts: Vec<(f64, f64)> = costs
            .iter()
            .filter(|c| c.curve == ci && c.seconds > 0.0 && c.rel_rmse > 0.0)
            .map(|c| (c.seconds.ln(), c.rel_rmse.ln()))
            .collect();
        let Some((a, b)) = ols(&pts) else {
            continue;
        };
        let (lo, hi) = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                (l.min(p.1), h.max(p.1))
            });
        let times = TARGETS
            .iter()
            .map(|&e| {
                (b < 0.0).then(|| {
                    let le = e.ln();
                    (((le - a) / b).exp(), le < lo || le > hi)
                })
            })
            .collect();
        out.push(TimeToError {
            curve: ci,
            a,
            b,
            times,
        });
    }
    out
}

fn overtakes(curves: &[Curve], costs: &[CostRow], tte: &[TimeToError]) -> Vec<Overtake> {
    let mut out = Vec::new();
    for (pi, p) in curves.iter().enumerate() {
        if p.run.primitive != Primitive::Points || !p.tables.contains(&Table::Rates) {
            continue;
        }
        let Some(li) = curves.iter().position(|l| {
            l.run.primitive == Primitive::Lines
                && l.tables.contains(&Table::Rates)
                && l.run.sampler == p.run.sampler
                && l.run.integrand == p.run.integrand
        }) else {
            continue;
        };
        let (Some(tp), Some(tl)) = (
            tte.iter().find(|t| t.curve == pi),
            tte.iter().find(|t| t.curve == li),
        ) else {
            continue;
        };
        // Largest common N: seconds per primitive.
        let common = costs
            .iter()
            .filter(|c| c.curve == pi)
            .filter_map(|c| {
                costs
                    .iter()
                    .find(|d| d.curve == li && d.n == c.n)
                    .map(|d| (c.n, c.seconds, d.seconds))
            })
            .max_by_key(|x| x.0);
        let cost_ratio = common.map_or(f64::NAN, |(_, sp, sl)| sl / sp);
        let (lo, hi) = common_time_range(costs, pi, li);
        let (crossover, summary) = overtake_verdict(tp, tl, lo, hi, cost_ratio);
        out.push(Overtake {
            points: pi,
            lines: li,
            cost_ratio,
            crossover_seconds: crossover,
            summary,
        });
    }
    out
}

/// The time span (seconds per estimate) that the costs of curves `pi` and
/// `li` both cover.
fn common_time_range(costs: &[CostRow], pi: usize, li: usize) -> (f64, f64) {
    let range = |ci: usize| {
        costs
            .iter()
            .filter(|c| c.curve == ci)
            .fold((f64::INFINITY, 0.0f64), |(l, h), c| {
                (l.min(c.seconds), h.max(c.seconds))
            })
    };
    let (a, b) = range(pi);
    let (c, d) = range(li);
    (a.max(c), b.min(d))
}

/// Where the fitted error-against-time law of lines (`tl`) overtakes that of
/// points (`tp`), given the common measured times `lo..hi` and the cost
/// ratio of a line to a point: the crossover time (if lines overtake within
/// reach) and the verdict in words.
fn overtake_verdict(
    tp: &TimeToError,
    tl: &TimeToError,
    lo: f64,
    hi: f64,
    cost_ratio: f64,
) -> (Option<f64>, String) {
    // Fitted error of lines over points at time t.
    let ratio_at = |t: f64| ((tl.a - tp.a) + (tl.b - tp.b) * t.ln()).exp();
    // Where the fitted power laws cross (if their exponents differ).
    let cross = (tl.b != tp.b)
        .then(|| ((tl.a - tp.a) / (tp.b - tl.b)).exp())
        .filter(|t| t.is_finite() && *t > 0.0);
    let mid = (lo * hi).sqrt();
    if (tl.b - tp.b).abs() < SAME_RATE {
        (
            None,
            format!(
                "same rate in time (b = {:.2} vs {:.2}); at equal time lines give {:.2}x the \
                 error of points",
                tl.b,
                tp.b,
                ratio_at(mid)
            ),
        )
    } else if tl.b < tp.b {
        let t = cross.unwrap_or(f64::NAN);
        let text = if t <= lo {
            format!(
                "lines give the lower error at every common time measured ({} to {} per \
                 estimate), {} {:.1}x a point",
                secs(lo),
                secs(hi),
                if cost_ratio >= 1.0 {
                    "though a line costs"
                } else {
                    "and a line costs only"
                },
                cost_ratio
            )
        } else if t <= hi {
            format!(
                "lines overtake points at {} per estimate (a line costs {:.1}x a point)",
                secs(t),
                cost_ratio
            )
        } else if t <= 1e3 * hi {
            format!(
                "lines would overtake points at about {} per estimate (extrapolated beyond \
                 the measured {})",
                secs(t),
                secs(hi)
            )
        } else {
            format!(
                "lines fall slightly faster (b = {:.2} vs {:.2}) but would overtake points only \
                 far beyond the measured times; at {} they give {:.2}x the error of points",
                tl.b,
                tp.b,
                secs(hi),
                ratio_at(hi)
            )
        };
        (Some(t).filter(|t| t.is_finite()), text)
    } else {
        let text = match cross {
            Some(t) if t > lo => format!(
                "lines give the lower error up to {} per estimate; beyond it points do (their \
                 error falls faster with time: b = {:.2} vs {:.2})",
                secs(t.min(hi)),
                tp.b,
                tl.b
            ),
            _ => format!(
                "lines do not overtake points: their error falls more slowly with time \
                 (b = {:.2} vs {:.2})",
                tl.b, tp.b
            ),
        };
        (None, text)
    }
}

/// `1.2 µs`, `3.4 ms`, `5.6 s`.
#[must_use]
pub fn secs(t: f64) -> String {
    if t < 1e-3 {
        format!("{:.3} µs", t * 1e6)
    } else if t < 1.0 {
        format!("{:.3} ms", t * 1e3)
    } else {
        format!("{t:.3} s")
    }
}

fn dir_ratios(
    curves: &[Curve],
    res: &[CurveResult],
    rates: &[RateRow],
) -> (Vec<DirRatio>, Option<f64>) {
    let in_table = |c: &Curve| c.tables.contains(&Table::Directions);
    let Some(one) = curves
        .iter()
        .position(|c| in_table(c) && matches!(c.run.dirs, DirSpec::Groups(1)))
    else {
        return (Vec::new(), None);
    };
    let rate = rates
        .iter()
        .find(|r| r.curve == one && r.table == Table::Directions)
        .and_then(|r| r.fit.map(|f| f.slope));
    let mut out = Vec::new();
    for (ci, c) in curves.iter().enumerate() {
        if !in_table(c) || ci == one {
            continue;
        }
        for (a, b) in res[ci].rows.iter().zip(&res[one].rows) {
            if a.row.n != b.row.n || b.variance <= 0.0 {
                continue;
            }
            let ratio = a.variance / b.variance;
            let se = ratio
                * ((a.variance_se / a.variance).powi(2) + (b.variance_se / b.variance).powi(2))
                    .sqrt();
            out.push(DirRatio {
                curve: ci,
                n: a.row.n,
                ratio,
                ratio_se: se,
            });
        }
    }
    (out, rate)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_fit_divides_out_the_log_factor() {
        // Var = 0.1·N^-3·ln N exactly, 2 % errors.
        let rows: Vec<(f64, f64, f64)> = [16.0f64, 64.0, 256.0, 1024.0]
            .iter()
            .map(|&n| {
                let v = 0.1 * n.powf(-3.0) * n.ln();
                (n, v, 0.02 * v)
            })
            .collect();
        let f = slope_fit(&rows, 1).unwrap();
        assert!((f.slope + 3.0).abs() < 1e-9, "{f:?}");
        // Without dividing out ln N the plain fit is shallower.
        let g = slope_fit(&rows, 0).unwrap();
        assert!(g.slope > -2.9, "{g:?}");
        // An exact power law: chi2 = 0, interval ±1.96 SE.
        assert!((f.ci_high - f.slope - (f.slope - f.ci_low)).abs() < 1e-12);
    }

    #[test]
    fn verdict_rule() {
        let fit = |s: f64, hw: f64| SlopeFit {
            slope: s,
            ci_low: s - hw,
            ci_high: s + hw,
            intercept: 0.0,
            chi2_dof: 1.0,
            points: 4,
        };
        assert_eq!(
            verdict(-1.5, Some(&fit(-1.45, 0.03)), None),
            Verdict::Consistent
        );
        assert_eq!(
            verdict(-1.5, Some(&fit(-1.3, 0.03)), None),
            Verdict::NotConsistent
        );
        assert_eq!(
            verdict(-2.0, Some(&fit(-1.7, 0.03)), Some((-1.95, 0.05))),
            Verdict::PreAsymptotic
        );
        assert_eq!(verdict(-2.0, None, None), Verdict::NotFitted);
    }

    #[test]
    fn quantiles() {
        assert!((normal_quantile(0.025) - 1.959964).abs() < 1e-5);
        assert!((t975(1) - 12.706).abs() < 1e-9);
        assert!((t975(30) - 1.96).abs() < 1e-12);
        assert!(t975(15) > 1.96 && t975(15) < 2.228);
    }

    #[test]
    fn two_point_slope() {
        let (s, hw) = two_point((16.0, 1.0 / 256.0, 0.0), (64.0, 1.0 / 4096.0, 0.0), 0).unwrap();
        assert!((s + 2.0).abs() < 1e-12 && hw == 0.0);
    }
}
