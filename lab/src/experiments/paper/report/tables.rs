//! The machine-readable tables: `rates.csv`, `prediction.csv`, `cost.csv` and
//! the per-curve rows behind every convergence figure.

use serde::Serialize;

use super::{fmt_opt, integrand_name};
use crate::experiments::paper::plan::Config;
use crate::experiments::paper::results::{Results, PREDICTION_ALPHA, PREDICTION_REL};
use crate::experiments::paper::theory::format_exponent;
use crate::io::table;
use crate::Result;

/// A CSV table (header first) and the notes its run's manifest keeps about
/// it.
pub(super) struct Table {
    pub(super) notes: Vec<String>,
    pub(super) bytes: Vec<u8>,
}

#[derive(Serialize)]
pub(super) struct RateCsv<'a> {
    table: &'a str,
    dims: usize,
    primitive: &'a str,
    sampler: &'a str,
    integrand: &'a str,
    theory_slope: String,
    log_factor: String,
    n_min: usize,
    n_max: usize,
    measured_slope: String,
    slope_ci_low: String,
    slope_ci_high: String,
    verdict: &'a str,
    regime: &'a str,
    beta: String,
    alpha: String,
    pattern_dims: usize,
    last_slope: String,
    curve: &'a str,
}

pub(super) fn rates_csv(cfg: &Config, res: &Results) -> Result<Table> {
    let rows: Vec<RateCsv<'_>> = res
        .rates
        .iter()
        .map(|r| {
            let c = &cfg.curves[r.curve];
            let t = r.theory;
            RateCsv {
                table: r.table.name(),
                dims: c.run.dims(),
                primitive: c.run.primitive.name(),
                sampler: c.run.sampler.name(),
                integrand: integrand_name(c),
                theory_slope: fmt_opt(t.map(|t| t.slope)),
                log_factor: t.map_or_else(String::new, |t| t.log_factor()),
                n_min: r.n_min,
                n_max: r.n_max,
                measured_slope: fmt_opt(r.fit.map(|f| f.slope)),
                slope_ci_low: fmt_opt(r.fit.map(|f| f.ci_low)),
                slope_ci_high: fmt_opt(r.fit.map(|f| f.ci_high)),
                verdict: r.verdict.name(),
                regime: &r.regime,
                beta: t.map_or_else(String::new, |t| format_exponent(t.beta)),
                alpha: t.map_or_else(String::new, |t| format_exponent(t.alpha)),
                pattern_dims: c.run.pattern_dims(),
                last_slope: fmt_opt(r.last_slope.map(|l| l.0)),
                curve: &c.id,
            }
        })
        .collect();
    Ok(Table {
        notes: vec![format!(
            "rate tables of linesample-lab paper (--mode {}); fit, range and verdict rules in index.html",
            cfg.mode.name()
        )],
        bytes: table::csv(&rows)?,
    })
}

#[derive(Serialize)]
pub(super) struct PredCsv<'a> {
    case: &'a str,
    dims: usize,
    primitive: &'a str,
    sampler: &'a str,
    integrand: &'a str,
    n: usize,
    #[serde(serialize_with = "table::sci")]
    predicted: f64,
    #[serde(serialize_with = "table::sci")]
    predicted_se: f64,
    #[serde(serialize_with = "table::sci")]
    measured: f64,
    #[serde(serialize_with = "table::sci")]
    measured_se: f64,
    #[serde(serialize_with = "table::sci")]
    ratio: f64,
    #[serde(serialize_with = "table::sci")]
    ratio_se: f64,
    #[serde(serialize_with = "table::sci")]
    rel_diff: f64,
    #[serde(serialize_with = "table::sci")]
    z: f64,
    resolves_5pc: bool,
    agrees: bool,
}

pub(super) fn prediction_csv(cfg: &Config, res: &Results) -> Result<Table> {
    let rows: Vec<PredCsv<'_>> = res
        .predictions
        .iter()
        .map(|p| {
            let c = &cfg.curves[p.curve];
            PredCsv {
                case: &c.id,
                dims: c.run.dims(),
                primitive: c.run.primitive.name(),
                sampler: c.run.sampler.name(),
                integrand: integrand_name(c),
                n: p.n,
                predicted: p.predicted,
                predicted_se: p.predicted_se,
                measured: p.measured,
                measured_se: p.measured_se,
                ratio: p.ratio,
                ratio_se: p.ratio_se,
                rel_diff: p.rel,
                z: p.z,
                resolves_5pc: p.resolves,
                agrees: p.agrees,
            }
        })
        .collect();
    Ok(Table {
        notes: vec![format!(
            "agrees: |z| <= {:.3} (Bonferroni, family-wise alpha {PREDICTION_ALPHA} over {} rows) \
             and |rel_diff| <= {PREDICTION_REL} where resolves_5pc",
            res.z_crit,
            res.predictions.len()
        )],
        bytes: table::csv(&rows)?,
    })
}

#[derive(Serialize)]
pub(super) struct CostCsv<'a> {
    integrand: &'a str,
    dims: usize,
    primitive: &'a str,
    sampler: &'a str,
    n: usize,
    #[serde(serialize_with = "table::sci")]
    rmse: f64,
    #[serde(serialize_with = "table::sci")]
    seconds_per_estimate: f64,
    evaluations_per_estimate: u64,
    #[serde(serialize_with = "table::sci")]
    relative_rmse: f64,
    curve: &'a str,
}

pub(super) fn cost_csv(cfg: &Config, res: &Results) -> Result<Table> {
    let rows: Vec<CostCsv<'_>> = res
        .costs
        .iter()
        .map(|r| {
            let c = &cfg.curves[r.curve];
            CostCsv {
                integrand: integrand_name(c),
                dims: c.run.dims(),
                primitive: c.run.primitive.name(),
                sampler: c.run.sampler.name(),
                n: r.n,
                rmse: r.rmse,
                seconds_per_estimate: r.seconds,
                evaluations_per_estimate: r.evaluations,
                relative_rmse: r.rel_rmse,
                curve: &c.id,
            }
        })
        .collect();
    Ok(Table {
        notes: vec![
            "seconds_per_estimate: summed wall time of the realisations on their worker \
                     threads / R (pattern generation, closed-form evaluations and the sum), \
                     measured with every worker busy"
                .to_string(),
        ],
        bytes: table::csv(&rows)?,
    })
}

#[derive(Serialize)]
pub(super) struct CurveCsv<'a> {
    curve: &'a str,
    n: usize,
    realisations: u64,
    #[serde(serialize_with = "table::sci")]
    mean: f64,
    #[serde(serialize_with = "table::sci")]
    exact: f64,
    #[serde(serialize_with = "table::sci")]
    variance: f64,
    #[serde(serialize_with = "table::sci")]
    variance_se: f64,
    predicted: String,
    predicted_se: String,
}

pub(super) fn curves_csv(cfg: &Config, res: &Results, which: &[usize]) -> Result<Table> {
    let mut rows = Vec::new();
    for &ci in which {
        let c = &cfg.curves[ci];
        let r = &res.curves[ci];
        for (row, p) in r.rows.iter().zip(&r.predicted) {
            rows.push(CurveCsv {
                curve: &c.id,
                n: row.row.n,
                realisations: c.run.realisations,
                mean: row.mean,
                exact: r.exact,
                variance: row.variance,
                variance_se: row.variance_se,
                predicted: fmt_opt(p.map(|x| x.0)),
                predicted_se: fmt_opt(p.map(|x| x.1)),
            });
        }
    }
    Ok(Table {
        notes: vec![
            "variance of the R estimates per N (edge curves: of the errors estimate - exact for \
           that realisation's edge); predicted: spectral prediction where measured"
                .to_string(),
        ],
        bytes: table::csv(&rows)?,
    })
}
