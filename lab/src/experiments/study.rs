//! The convergence study every effect shares: at each query (a pixel's
//! shading point, or the caustic's query ball) a reference, then every
//! estimator row at every `N`, each cell the running statistics of its
//! realisations; then one analysis (bias, variance, fit, slope between the
//! two largest `N`, time to a 1 % error, verdict) whatever the effect.
//!
//! An effect says only what is its own ([`Effect`]: one estimate at a
//! query from a row's samples and a seed), and a configuration only how it
//! builds the world, the queries and the rows ([`StudySetup`]). The cell layout
//! ([`Layout`]), the streams ([`crate::streams`]), the measurement with its
//! failure rule ([`run_cell`]), the statistics ([`analyse`]), the verdict
//! ([`verdict`]) and the curves ([`convergence_series`], [`time_series`])
//! are written once, here.
//!
//! Cells: for query `q`, cell `q·(1 + E·M)` is its reference and cell
//! `q·(1 + E·M) + 1 + e·M + i` is row `e` at the `i`-th `N` (`E` rows, `M`
//! values of `N`). Streams: the reference of query `q` draws
//! `base_q` with part `reference`, row `e` at `N` draws `base_q` with part
//! `study`, estimator `e` and `N`; realisation `r` then derives `r`.

use linesample::stats::RunningStats;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::figures::multi::{Line, Series};
use crate::fit::{fit_loglog, n_to_target, Fit};
use crate::io::table;
use crate::runner::{CellInfo, Ctx, Experiment};
use crate::spec::ShiftMode;
use crate::streams::{Part, Realisations, Stream};
use linesample_scene::Effect;

use super::samples::{self, SamplePattern};

/// The study's side of a configuration: the effect it studies, and its
/// world, queries and rows ([`Queries`]) built from the configuration.
pub trait StudySetup: Serialize + DeserializeOwned + Clone + Sync {
    /// The effect studied.
    type Effect: Effect;
    /// Realisations per task: chunks are merged in order, so results do
    /// not depend on the thread count (nor, then, on this constant's
    /// relation to it).
    const CHUNK: u64;
    /// The experiment's name (its state folder's kind).
    const KIND: &'static str;

    /// The run's seed.
    fn seed(&self) -> u64;

    /// The world, its queries and the rows.
    ///
    /// # Errors
    /// A scene that no longer parses, a query the effect cannot estimate
    /// at, or a count a sampler cannot make.
    fn queries(&self) -> crate::Result<Queries<Self::Effect>>;
}

/// What every study of an effect measures: the effect's world, the queries
/// it is estimated at, the estimator rows, `--shift`, and the cells.
pub struct Queries<E: Effect> {
    /// The effect's world.
    pub world: E,
    /// What each query's estimates need, in the order of
    /// [`Layout::queries`].
    pub at: Vec<E::Query>,
    /// The estimator rows, in the order of [`Layout::rows`].
    pub rows: Vec<E::Estimator>,
    /// `--shift` (`None`: the effect's default).
    pub shift: Option<ShiftMode>,
    /// The cells.
    pub layout: Layout,
}

/// How many estimates a study takes: the values of `N`, realisations per
/// row and `N`, and the reference's `N` and realisations.
#[derive(Clone, Debug)]
pub struct Counts {
    /// The values of `N`, in row order.
    pub ns: Vec<usize>,
    /// Realisations per row and `N`.
    pub realisations: u64,
    /// The reference's `N`.
    pub reference_n: usize,
    /// The reference's realisations.
    pub reference_realisations: u64,
}

impl<E: Effect> Queries<E> {
    /// The study of `rows` at the queries `at` (each with its label and
    /// stream) of `world`, every pattern checked up front.
    ///
    /// # Errors
    /// No `N` or no row, or a count a row's (or the reference's) sampler
    /// cannot make.
    pub fn new(
        world: E,
        at: Vec<(Query, E::Query)>,
        rows: Vec<E::Estimator>,
        shift: Option<ShiftMode>,
        counts: Counts,
    ) -> crate::Result<Self> {
        if counts.ns.is_empty() || rows.is_empty() {
            return Err("the study needs at least one N and one estimator".into());
        }
        SamplePattern::of(&world, None, counts.reference_n, shift)
            .map_err(|e| format!("the reference: {e}"))?;
        for est in &rows {
            for &n in &counts.ns {
                SamplePattern::of(&world, Some(est), n, shift)?;
            }
        }
        let (queries, at) = at.into_iter().unzip();
        let layout = Layout {
            queries,
            rows: rows.iter().map(E::label).collect(),
            ns: counts.ns,
            realisations: counts.realisations,
            reference_n: counts.reference_n,
            reference_realisations: counts.reference_realisations,
        };
        Ok(Queries {
            world,
            at,
            rows,
            shift,
            layout,
        })
    }

    /// The pattern of row `row` at `n` (`None`: the reference's).
    ///
    /// # Errors
    /// A count the row's sampler cannot make.
    pub fn plan(&self, row: Option<usize>, n: usize) -> crate::Result<samples::Plan<E>> {
        SamplePattern::of(&self.world, row.map(|e| &self.rows[e]), n, self.shift)
    }
}

/// The convergence study of an effect: the [`Layout`]'s cells, each
/// measured by [`run_cell`]. It dereferences to its [`Queries`].
pub struct Study<C: StudySetup> {
    config: C,
    queries: Queries<C::Effect>,
    cells: Vec<CellInfo>,
}

impl<C: StudySetup> Study<C> {
    /// The study of `config`.
    ///
    /// # Errors
    /// As [`StudySetup::queries`].
    pub fn new(config: C) -> crate::Result<Self> {
        let queries = config.queries()?;
        let cells = queries.layout.cells();
        Ok(Study {
            config,
            queries,
            cells,
        })
    }

    /// The configuration.
    #[must_use]
    pub fn config(&self) -> &C {
        &self.config
    }

    /// The stream of cell `index`.
    #[must_use]
    pub fn stream(&self, index: usize) -> Stream {
        self.queries.layout.stream(index)
    }

    /// The streams of every cell, in cell order.
    #[must_use]
    pub fn streams(&self) -> Vec<Stream> {
        self.queries.layout.streams()
    }
}

impl<C: StudySetup> std::ops::Deref for Study<C> {
    type Target = Queries<C::Effect>;

    fn deref(&self) -> &Queries<C::Effect> {
        &self.queries
    }
}

impl<C: StudySetup> Experiment for Study<C> {
    type Config = C;
    type Cell = StudyCell;
    const KIND: &'static str = C::KIND;
    const UNIT: &'static str = "realisations";

    fn config(&self) -> &C {
        &self.config
    }

    fn cells(&self) -> &[CellInfo] {
        &self.cells
    }

    fn run_cell(&self, index: usize, ctx: &Ctx<'_>) -> crate::Result<StudyCell> {
        run_cell(&self.queries, C::CHUNK, index, self.config.seed(), ctx)
    }
}

/// One query of a study: its label and the stream its cells derive from
/// (the part is set per cell).
#[derive(Clone, Debug)]
pub struct Query {
    pub label: String,
    pub stream: Stream,
}

/// The cells of a study: queries × (the reference, then rows × `N`).
#[derive(Clone, Debug)]
pub struct Layout {
    pub queries: Vec<Query>,
    /// The rows' labels (`estimator sampler`).
    pub rows: Vec<String>,
    pub ns: Vec<usize>,
    pub realisations: u64,
    pub reference_n: usize,
    pub reference_realisations: u64,
}

/// What cell `index` of a [`Layout`] measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Slot {
    pub query: usize,
    /// `None`: the reference; `Some((e, i))`: row `e` at the `i`-th `N`.
    pub row: Option<(usize, usize)>,
}

impl Layout {
    /// Cells per query.
    #[must_use]
    pub fn per_query(&self) -> usize {
        1 + self.rows.len() * self.ns.len()
    }

    /// The number of measured cells.
    #[must_use]
    pub fn len(&self) -> usize {
        self.queries.len() * self.per_query()
    }

    /// Whether the layout has no cell.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// What cell `index` measures.
    #[must_use]
    pub fn slot(&self, index: usize) -> Slot {
        let (q, k) = (index / self.per_query(), index % self.per_query());
        Slot {
            query: q,
            row: (k > 0).then(|| ((k - 1) / self.ns.len(), (k - 1) % self.ns.len())),
        }
    }

    /// The index of query `q`'s cell for row `e` at the `i`-th `N`.
    #[must_use]
    pub fn index(&self, q: usize, e: usize, i: usize) -> usize {
        q * self.per_query() + 1 + e * self.ns.len() + i
    }

    /// The stream of cell `index`.
    #[must_use]
    pub fn stream(&self, index: usize) -> Stream {
        let s = self.slot(index);
        let base = self.queries[s.query].stream;
        match s.row {
            None => Stream {
                part: Part::Reference,
                ..base
            },
            Some((e, i)) => Stream {
                part: Part::Study,
                ..base
            }
            .row(e, self.ns[i]),
        }
    }

    /// The streams of every cell, in cell order.
    #[must_use]
    pub fn streams(&self) -> Vec<Stream> {
        (0..self.len()).map(|i| self.stream(i)).collect()
    }

    /// The runner's cells, labelled `query reference` and `query row N=n`.
    #[must_use]
    pub fn cells(&self) -> Vec<CellInfo> {
        (0..self.len())
            .map(|i| {
                let s = self.slot(i);
                let q = &self.queries[s.query].label;
                let sep = if q.is_empty() { "" } else { " " };
                match s.row {
                    None => CellInfo {
                        label: format!("{q}{sep}reference"),
                        work: self.reference_realisations,
                    },
                    Some((e, i)) => CellInfo {
                        label: format!("{q}{sep}{} N={}", self.rows[e], self.ns[i]),
                        work: self.realisations,
                    },
                }
            })
            .collect()
    }
}

/// One measured cell: running statistics (count and the four moment sums
/// of [`RunningStats::parts`]) and seconds per estimate, or why it has none.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StudyCell {
    pub count: u64,
    pub moments: [f64; 4],
    /// Seconds per estimate (one thread).
    pub seconds: f64,
    /// Why a row's cell has no statistics (an error of the kernel or a
    /// non-finite estimate, naming the estimator, `N` and realisation):
    /// the study completes every other row and reports this one as failed.
    pub error: Option<String>,
}

impl StudyCell {
    /// A cell that failed with `error`.
    #[must_use]
    pub fn failed(error: String) -> Self {
        StudyCell {
            count: 0,
            moments: [0.0; 4],
            seconds: 0.0,
            error: Some(error),
        }
    }

    /// The cell's statistics.
    ///
    /// # Errors
    /// A failed cell, or moments that do not decode.
    pub fn stats(&self) -> crate::Result<RunningStats> {
        if let Some(e) = &self.error {
            return Err(e.clone().into());
        }
        RunningStats::from_parts(self.count, self.moments)
            .map_err(|e| format!("a stored cell: {e}").into())
    }
}

/// Measures cell `index` of `layout` for `effect` with run seed `run`.
/// Every estimate must be finite. A row's cell that fails is returned as
/// [`StudyCell::failed`], naming the row, `N` and the error (the other
/// rows go on), unless the run is being stopped; a failed reference is an
/// error (nothing can be compared without it).
///
/// # Errors
/// The reference's error, or a stop.
pub fn run_cell<E: Effect>(
    study: &Queries<E>,
    chunk: u64,
    index: usize,
    run: u64,
    ctx: &Ctx<'_>,
) -> crate::Result<StudyCell> {
    let layout = &study.layout;
    let slot = layout.slot(index);
    let (row, n, total) = match slot.row {
        None => (None, layout.reference_n, layout.reference_realisations),
        Some((e, i)) => (Some(e), layout.ns[i], layout.realisations),
    };
    let seed = Realisations::of(&layout.stream(index), run);
    let query = &study.at[slot.query];
    let measured = study.plan(row, n).and_then(|plan| {
        ctx.realisations(
            total,
            chunk,
            || Ok(samples::scratch(&study.world)),
            |scratch, r| {
                let v = samples::estimate(&study.world, query, &plan, seed.at(r), scratch)?;
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(format!("realisation {r}: the estimate is {v}").into())
                }
            },
        )
    });
    match (measured, row) {
        (Ok((rs, seconds)), _) => {
            let (count, moments) = rs.parts();
            Ok(StudyCell {
                count,
                moments,
                seconds,
                error: None,
            })
        }
        (Err(e), Some(r)) if crate::runner::stop::requested().is_none() => Ok(StudyCell::failed(
            format!("{} at N = {n}: {e}", layout.rows[r]),
        )),
        (Err(e), _) => Err(e),
    }
}

/// A reference estimate and its standard error.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Reference {
    pub value: f64,
    pub se: f64,
}

/// One row at one `N`.
#[derive(Clone, Debug)]
pub struct RowStat {
    pub n: usize,
    pub realisations: u64,
    pub mean: f64,
    /// `(mean − reference)/√(SE² + SE_ref²)`.
    pub bias_z: f64,
    pub variance: f64,
    pub variance_se: f64,
    pub seconds: f64,
    /// Why the cell has no statistics (`None` when it has).
    pub error: Option<String>,
}

/// The rate theory gives for a row: the slope of variance against `N`
/// (NaN: infinite variance, no rate), the power of a `log N` factor, and
/// why.
#[derive(Clone, Debug, PartialEq)]
pub struct Theory {
    pub slope: f64,
    pub log_power: u32,
    pub note: String,
}

/// The fit of one row and what follows from it.
#[derive(Clone, Copy, Debug)]
pub struct RowFit {
    /// The weighted log-log fit over the fitted range (`None`: fewer than
    /// two usable points, or a failed cell).
    pub fit: Option<Fit>,
    /// The first `N` of the fitted range.
    pub n_from: usize,
    /// The fit over every `N` (as `fit` when the range is every `N`).
    pub slope_all: f64,
    /// `ln(V₂/V₁)/ln(N₂/N₁)` over the two largest `N`, and its standard
    /// error `√((SE₁/V₁)² + (SE₂/V₂)²)/ln(N₂/N₁)` (delta method).
    pub last_slope: f64,
    pub last_slope_se: f64,
    /// The largest `|bias_z|` over the row's `N`.
    pub max_abs_z: f64,
    /// `N` and seconds per estimate to a relative RMSE of 1 %, read off the
    /// fit (NaN when it does not converge, or the variance is infinite).
    pub n_to_1pct: f64,
    pub seconds_to_1pct: f64,
}

impl RowFit {
    /// `(slope, low, high)` of the fit's 95 % interval (NaN without a fit).
    #[must_use]
    pub fn interval(&self) -> (f64, f64, f64) {
        self.fit.map_or((f64::NAN, f64::NAN, f64::NAN), |f| {
            (
                f.slope,
                f.slope - 1.96 * f.slope_se,
                f.slope + 1.96 * f.slope_se,
            )
        })
    }
}

/// The reference of query `q` and the statistics of each row at each `N`
/// (row-major: row `e` at the `i`-th `N` is `e·M + i`).
///
/// # Errors
/// A reference cell that failed or does not decode.
pub fn analyse(
    layout: &Layout,
    cells: &[StudyCell],
    q: usize,
) -> crate::Result<(Reference, Vec<RowStat>)> {
    let r = cells[q * layout.per_query()].stats()?;
    let reference = Reference {
        value: r.mean(),
        se: r.mean_std_error(),
    };
    let mut rows = Vec::with_capacity(layout.rows.len() * layout.ns.len());
    for e in 0..layout.rows.len() {
        for (i, &n) in layout.ns.iter().enumerate() {
            let c = &cells[layout.index(q, e, i)];
            rows.push(match c.stats() {
                Ok(s) => {
                    let se = s.mean_std_error();
                    RowStat {
                        n,
                        realisations: s.count(),
                        mean: s.mean(),
                        bias_z: (s.mean() - reference.value) / se.hypot(reference.se),
                        variance: s.variance(),
                        variance_se: s.variance_std_error(),
                        seconds: c.seconds,
                        error: None,
                    }
                }
                Err(why) => RowStat {
                    n,
                    realisations: 0,
                    mean: f64::NAN,
                    bias_z: f64::NAN,
                    variance: f64::NAN,
                    variance_se: f64::NAN,
                    seconds: f64::NAN,
                    error: Some(
                        c.error
                            .clone()
                            .unwrap_or_else(|| format!("{} at N = {n}: {why}", layout.rows[e])),
                    ),
                },
            });
        }
    }
    Ok((reference, rows))
}

/// A row of a study's `rows.csv`: one estimator at one `N` at one query.
#[derive(Clone, Debug, Serialize)]
pub struct RowRecord {
    /// The query's label (`A`, `B`, `P1`, `P2`, `P` for `--pixel`, `Q`
    /// for the caustic's query ball).
    pub query: String,
    /// The pixel (empty for a query that is not a pixel).
    pub x: Option<u32>,
    pub y: Option<u32>,
    pub estimator: String,
    pub sampler: String,
    pub n: usize,
    pub realisations: u64,
    #[serde(serialize_with = "table::sci")]
    pub mean: f64,
    #[serde(serialize_with = "table::sci")]
    pub bias_z: f64,
    #[serde(serialize_with = "table::sci")]
    pub variance: f64,
    #[serde(serialize_with = "table::sci")]
    pub variance_se: f64,
    #[serde(serialize_with = "table::sci")]
    pub seconds_per_estimate: f64,
    /// Why the cell has no statistics (empty when it has).
    pub error: String,
}

impl RowRecord {
    /// The record of `r` for `estimator` with `sampler` at `query`
    /// (`pixel`: its coordinates, if it is one).
    #[must_use]
    pub fn new(
        query: &str,
        pixel: Option<(u32, u32)>,
        estimator: &str,
        sampler: &str,
        r: &RowStat,
    ) -> Self {
        RowRecord {
            query: query.into(),
            x: pixel.map(|p| p.0),
            y: pixel.map(|p| p.1),
            estimator: estimator.into(),
            sampler: sampler.into(),
            n: r.n,
            realisations: r.realisations,
            mean: r.mean,
            bias_z: r.bias_z,
            variance: r.variance,
            variance_se: r.variance_se,
            seconds_per_estimate: r.seconds,
            error: r.error.clone().unwrap_or_default(),
        }
    }
}

/// `N1,N2,…` (a command line's list).
#[must_use]
pub fn list(ns: &[usize]) -> String {
    ns.iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(",")
}

/// `(N, variance, SE)` of a row.
#[must_use]
pub fn points(rows: &[RowStat]) -> Vec<(f64, f64, f64)> {
    rows.iter()
        .map(|r| (r.n as f64, r.variance, r.variance_se))
        .collect()
}

/// The fit of one row's statistics (`rows`: its `N` in order) over its
/// `tail` largest `N` (`None`: every `N`). A row with a failed cell is not
/// fitted (its slope would mix `N`). `infinite`: the theory claims
/// infinite variance (no time to 1 % is read off).
#[must_use]
pub fn fit_row(rows: &[RowStat], tail: Option<usize>, reference: f64, infinite: bool) -> RowFit {
    let pts = points(rows);
    let m = pts.len();
    let from = tail.map_or(0, |t| m.saturating_sub(t));
    let failed = rows.iter().any(|r| r.error.is_some());
    let fit = if failed {
        None
    } else {
        fit_loglog(&pts[from..])
    };
    let slope_all = if from == 0 {
        fit.map_or(f64::NAN, |f| f.slope)
    } else if failed {
        f64::NAN
    } else {
        fit_loglog(&pts).map_or(f64::NAN, |f| f.slope)
    };
    let (last_slope, last_slope_se) = match rows {
        [.., a, b] => {
            let l = (b.n as f64 / a.n as f64).ln();
            (
                (b.variance / a.variance).ln() / l,
                ((a.variance_se / a.variance).powi(2) + (b.variance_se / b.variance).powi(2))
                    .sqrt()
                    / l,
            )
        }
        _ => (f64::NAN, f64::NAN),
    };
    // Var(N) = e^a N^b = (0.01 ref)^2  =>  N = ((0.01 ref)^2 e^-a)^(1/b);
    // NaN for a fit that does not converge, and for an estimator of
    // infinite variance (no rate to extrapolate).
    let n_to_1pct = if infinite {
        f64::NAN
    } else {
        n_to_target(fit.as_ref(), (0.01 * reference).powi(2))
    };
    let per_sample = rows.last().map_or(f64::NAN, |r| r.seconds / r.n as f64);
    RowFit {
        fit,
        n_from: rows.get(from).map_or(0, |r| r.n),
        slope_all,
        last_slope,
        last_slope_se,
        max_abs_z: rows.iter().map(|r| r.bias_z.abs()).fold(0.0, f64::max),
        n_to_1pct,
        seconds_to_1pct: n_to_1pct * per_sample,
    }
}

/// The verdict on a row's fit against its theory: `failed` (a cell has no
/// statistics), `infinite variance` (the theory predicts no rate), `no
/// fit` (fewer than two usable points), else [`verdict`].
#[must_use]
pub fn row_verdict(rows: &[RowStat], fit: &RowFit, theory: &Theory) -> &'static str {
    if rows.iter().any(|r| r.error.is_some()) {
        "failed"
    } else if theory.slope.is_nan() {
        "infinite variance"
    } else if fit.fit.is_none() {
        "no fit"
    } else {
        verdict(
            theory.slope,
            theory.log_power > 0,
            fit.interval(),
            (fit.last_slope, fit.last_slope_se),
        )
    }
}

/// Slack added to each side of a slope's 95 % interval by [`verdict`].
pub const SLOPE_SLACK: f64 = 0.15;

/// The verdict on a fitted slope against the theory's rate `theory` (NaN:
/// infinite variance, no rate), with `log` when the theory has a `log N`
/// factor: `consistent` if the theory lies in the 95 % interval
/// `[lo, hi]` widened by [`SLOPE_SLACK`]; `log factor` if the slope is
/// shallower than a theory with a `log N` factor by less than 0.5;
/// `pre-asymptotic` if the slope between the two largest `N` is consistent
/// by the same widened rule; else `not consistent`.
#[must_use]
pub fn verdict(
    theory: f64,
    log: bool,
    (slope, lo, hi): (f64, f64, f64),
    (last, last_se): (f64, f64),
) -> &'static str {
    if theory.is_nan() {
        "infinite variance"
    } else if theory >= lo - SLOPE_SLACK && theory <= hi + SLOPE_SLACK {
        "consistent"
    } else if log && slope > theory && slope < theory + 0.5 {
        "log factor"
    } else if (last - theory).abs() <= 1.96 * last_se + SLOPE_SLACK {
        "pre-asymptotic"
    } else {
        "not consistent"
    }
}

/// A row's variance against `N` with its fitted line over the fitted range.
#[must_use]
pub fn convergence_series(label: String, rows: &[RowStat], fit: &RowFit) -> Series {
    let pts = points(rows);
    let x1 = pts.last().map_or(1.0, |p| p.0);
    Series {
        label,
        fit: fit.fit.map(|f| Line {
            a: f.intercept,
            slope: f.slope,
            log_power: 0,
            x0: fit.n_from as f64,
            x1,
        }),
        points: pts,
        ..Series::default()
    }
}

/// A row's relative RMSE against seconds per estimate, joined.
#[must_use]
pub fn time_series(label: String, rows: &[RowStat], reference: f64) -> Series {
    Series {
        label,
        points: rows
            .iter()
            .map(|r| {
                let s = r.variance.sqrt();
                (
                    r.seconds,
                    s / reference,
                    0.5 * r.variance_se / s / reference,
                )
            })
            .collect(),
        joined: true,
        ..Series::default()
    }
}

/// `Ok` when no cell failed, else one error counting the failed cells of
/// `what` (`pixel study`, …), naming each, and saying where the other rows
/// are (`file`).
///
/// # Errors
/// As described.
pub fn no_failures(what: &str, failed: &[String], file: &std::path::Path) -> crate::Result<()> {
    if failed.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} cell(s) of the {what} failed (the other rows are in {}): {}",
            failed.len(),
            file.display(),
            failed.join("; ")
        )
        .into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::EffectKind;

    fn layout() -> Layout {
        let q = |label: &str, x| Query {
            label: label.into(),
            stream: Stream::new(EffectKind::DirectLight, 3, Part::Study).pixel(x, 0, 10),
        };
        Layout {
            queries: vec![q("A", 1), q("B", 2)],
            rows: vec!["points".into(), "lines".into(), "beams".into()],
            ns: vec![4, 16],
            realisations: 10,
            reference_n: 64,
            reference_realisations: 3,
        }
    }

    /// Every cell has one slot, the slots index back to their cells, and
    /// no two cells share a stream.
    #[test]
    fn slots_and_streams_are_one_to_one() {
        let l = layout();
        assert_eq!(l.len(), 2 * 7);
        for i in 0..l.len() {
            let s = l.slot(i);
            if let Some((e, k)) = s.row {
                assert_eq!(l.index(s.query, e, k), i);
            } else {
                assert_eq!(i % l.per_query(), 0);
            }
        }
        let mut seeds: Vec<_> = l.streams().iter().map(|s| s.seed(7)).collect();
        seeds.sort_by_key(|s| format!("{s:?}"));
        seeds.dedup();
        assert_eq!(seeds.len(), l.len());
        assert_eq!(l.cells()[8].label, "B points N=4");
        assert_eq!(l.cells()[7].work, 3);
    }

    /// A row with a failed cell is not fitted and reads `failed`; the
    /// last slope's SE follows the delta method.
    #[test]
    fn failed_rows_and_last_slope() {
        let row = |n: usize, v: f64, err: Option<&str>| RowStat {
            n,
            realisations: 100,
            mean: 1.0,
            bias_z: 0.5,
            variance: v,
            variance_se: 0.1 * v,
            seconds: 1e-6 * n as f64,
            error: err.map(Into::into),
        };
        let rows = [row(16, 1e-2, None), row(64, 1e-2 / 8.0, None)];
        let f = fit_row(&rows, None, 1.0, false);
        assert!((f.last_slope + 1.5).abs() < 1e-12);
        let want = (2.0f64 * 0.01).sqrt() / 4.0f64.ln();
        assert!((f.last_slope_se - want).abs() < 1e-12);
        let th = Theory {
            slope: -1.5,
            log_power: 0,
            note: String::new(),
        };
        assert_eq!(row_verdict(&rows, &f, &th), "consistent");
        let bad = [row(16, 1e-2, None), row(64, f64::NAN, Some("boom"))];
        let f = fit_row(&bad, None, 1.0, false);
        assert!(f.fit.is_none());
        assert_eq!(row_verdict(&bad, &f, &th), "failed");
        let inf = Theory {
            slope: f64::NAN,
            ..th
        };
        assert!(fit_row(&rows, None, 1.0, true).seconds_to_1pct.is_nan());
        assert_eq!(row_verdict(&rows, &f, &inf), "infinite variance");
    }
}
