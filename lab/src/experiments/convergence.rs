//! `convergence`: the variance of one estimator as the sample count `N` grows.
//!
//! Everything numeric is a kernel call: patterns from [`crate::sampler`],
//! integrands from `linesample::integrand`, estimates and statistics from
//! `linesample::estimator::run_realisations` and `RunningStats`. A cell is one
//! N; its realisations run in chunks of [`CHUNK`] whose statistics are merged
//! in chunk order.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use linesample::estimator::{
    run_realisations, Directions, Estimator, LineEstimator, PointEstimator, SegmentEstimator,
};
use linesample::geom::Direction;
use linesample::integrand::Integrand;
use linesample::stats::RunningStats;
use linesample::{EstimateError, PatternError, Seed};
use serde::{Deserialize, Serialize};

use crate::experiments::{config_from, file_name, merge_to_files, OutputManifest};
use crate::figures;
use crate::fit::{fit_loglog, Fit};
use crate::integrand::{join, to_array, IntegrandSpec};
use crate::io::{self, table, FileGroup};
use crate::runner::{CellInfo, Ctx, Experiment, RunInfo};
use crate::sampler::{self, DynPattern, PatternSpec, Sampler, DEFAULT_RELATIVE_RADIUS};
use crate::spec::MergeRequest;
use crate::spec::{Primitive, ShiftMode};
use crate::with_dims;
use crate::{LabError, Result};

/// The experiment's name.
pub const KIND: &str = "convergence";

/// Realisations per chunk. Fixed (independent of `--threads`), so the
/// statistics, merged chunk by chunk in chunk order, do not depend on the
/// thread count.
pub const CHUNK: u64 = 32;

/// Default `--n`.
pub const DEFAULT_NS: [usize; 5] = [16, 64, 256, 1024, 4096];
/// Reference slopes drawn in the plot.
const REFERENCE_SLOPES: [f64; 4] = [-1.0, -1.5, -2.0, -3.0];
/// Default `--length`.
pub(crate) const DEFAULT_LENGTH: f64 = 0.1;

/// The CSV header (the first line of `convergence.csv`).
pub const CSV_HEADER: &str =
    "n,realisations,mean,mean_se,exact,bias_z,variance,variance_se,var_times_n";

/// The `convergence` output formats (its `--help`).
pub const FORMATS: &str = concat!(
    "\
Output formats:
  OUT/convergence.csv  the header
                n,realisations,mean,mean_se,exact,bias_z,variance,variance_se,var_times_n
              and one row per N: the number of primitives N per realisation, R, the
              sample mean of the R estimates and its standard error, the exact
              integral, the bias z-score (mean - exact)/mean_se, the unbiased sample
              variance Var, its standard error SE(Var) (from the sample fourth
              central moment), and Var*N. Numbers use Rust's shortest round-trip
              formatting (e.g. 1.2345e-5). No timings and no thread count appear in
              the CSV, so it is byte-identical for every --threads, and for a
              sharded run merged with `linesample-lab merge`. Nothing precedes
              the header: what the file's readers should know besides its rows
              (the command that reproduces the run with every default filled
              in, the homogenisation (`homogenised: random toroidal shift per
              realisation`, or `not homogenised` with --shift none), the seeding
              rule, any rounding of N and the fitted slope) is in
              OUT/manifest.json under notes, key convergence.csv.
  OUT/convergence.svg  log-log plot of Var against N with +-1 SE(Var) error bars, the fitted
              power law, reference slopes -1, -1.5, -2 and -3 (dashed, through
              the smallest N), and a title naming the integrand, primitive,
              sampler and R.
  OUT/manifest.json  the manifest: command, configuration (parameters and
              seeds), lab version, threads, wall time, time per cell, and the
              notes on convergence.csv.

The printed table adds the time per realisation in microseconds: the wall time of
each chunk of realisations, summed over the row's chunks and divided by R (so it
does not shrink with --threads; a busy machine inflates it).

Runs: one cell per N, kept in OUT.state/ (resume, --fresh, --shard, merge,
progress: see `linesample-lab --help`).

",
    crate::files_note!()
);

/// How segments and lines are oriented (resolved).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DirSpec {
    None,
    Fixed(Vec<f64>),
    Random,
    Groups(usize),
}

/// One row: the requested N and what is actually run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    pub requested: usize,
    /// Primitives per pattern realisation (per group).
    pub per_group: usize,
    /// N = groups * per_group.
    pub n: usize,
}

/// A convergence experiment, every parameter resolved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    pub integrand: IntegrandSpec,
    pub primitive: Primitive,
    pub sampler: Sampler,
    /// Poisson disk: radius relative to the densest packing.
    pub relative_radius: f64,
    /// Poisson disk: Bridson instead of maximal dart throwing.
    pub bridson: bool,
    /// Segment length (segments only).
    pub length: f64,
    pub dirs: DirSpec,
    pub rows: Vec<Row>,
    pub realisations: u64,
    pub seed: u64,
    pub shift: ShiftMode,
    /// Notes about rounded N.
    pub notes: Vec<String>,
}

impl Config {
    /// Dimension D of the domain.
    #[must_use]
    pub fn dims(&self) -> usize {
        self.integrand.dims
    }

    /// Dimension of the pattern: D, or D − 1 for line offsets.
    #[must_use]
    pub fn pattern_dims(&self) -> usize {
        if self.primitive == Primitive::Lines {
            self.dims() - 1
        } else {
            self.dims()
        }
    }

    fn dirs_desc(&self) -> String {
        match &self.dirs {
            DirSpec::None => String::new(),
            DirSpec::Fixed(d) => format!("direction {}", join(d)),
            DirSpec::Random => "random directions".into(),
            DirSpec::Groups(k) => format!("{k} direction groups"),
        }
    }

    /// `disk 2D (centre …), points, jittered`.
    #[must_use]
    pub fn describe(&self) -> String {
        format!(
            "{} {}D ({}), {}{}, {}",
            self.integrand.kind.name(),
            self.dims(),
            self.integrand.describe(),
            self.primitive.name(),
            match self.primitive {
                Primitive::Points => String::new(),
                Primitive::Segments => format!(" (length {}, {})", self.length, self.dirs_desc()),
                Primitive::Lines => format!(" ({})", self.dirs_desc()),
            },
            self.sampler
        )
    }

    /// The command that recomputes the results (every default filled in;
    /// --threads and --out do not change them and are left out).
    #[must_use]
    pub fn command(&self) -> String {
        let mut c = format!("linesample-lab convergence {}", self.integrand.options());
        let _ = write!(
            c,
            " --primitive {} --sampler {}",
            self.primitive.name(),
            self.sampler
        );
        if self.relative_radius != DEFAULT_RELATIVE_RADIUS {
            let _ = write!(c, " --relative-radius {}", self.relative_radius);
        }
        if self.bridson {
            c.push_str(" --bridson");
        }
        if self.primitive == Primitive::Segments {
            let _ = write!(c, " --length {}", self.length);
        }
        match &self.dirs {
            DirSpec::None => {}
            DirSpec::Fixed(d) => {
                let _ = write!(c, " --direction {}", join(d));
            }
            DirSpec::Random => c.push_str(" --random-direction"),
            DirSpec::Groups(k) => {
                let _ = write!(c, " --groups {k}");
            }
        }
        let ns: Vec<String> = self.rows.iter().map(|r| r.n.to_string()).collect();
        let _ = write!(
            c,
            " --n {} --realisations {} --seed {}",
            ns.join(","),
            self.realisations,
            self.seed
        );
        if self.shift == ShiftMode::None {
            c.push_str(" --shift none");
        }
        c
    }

    fn pattern_spec(&self, row: &Row) -> PatternSpec {
        PatternSpec {
            relative_radius: self.relative_radius,
            bridson: self.bridson,
            ..PatternSpec::simple(self.sampler, self.pattern_dims(), row.per_group)
        }
    }

    /// The default output prefix.
    #[must_use]
    pub fn default_out(&self) -> PathBuf {
        PathBuf::from("out/convergence").join(format!(
            "{}-{}d-{}-{}",
            self.integrand.kind.name(),
            self.dims(),
            self.primitive.name(),
            self.sampler
        ))
    }
}

/// The `m` minimising `|m^d − x|` (`m ≥ 1`).
pub(crate) fn nearest_power(x: f64, d: usize) -> usize {
    let exp = i32::try_from(d).unwrap_or(i32::MAX);
    let m = x.max(1.0).powf(1.0 / d as f64).floor().max(1.0) as usize;
    let pow = |m: usize| (m as f64).powi(exp);
    let mut best = m;
    for c in [m.saturating_sub(1).max(1), m, m + 1] {
        if (pow(c) - x).abs() < (pow(best) - x).abs() {
            best = c;
        }
    }
    best
}

pub(crate) fn not_for(option: &str, what: &str, got: &str) -> LabError {
    LabError::Usage(format!("{option} applies only to {what} (got {got})"))
}

/// The fixed direction, or the `K` group directions (documented at `--groups`).
fn directions<const D: usize>(cfg: &Config) -> Result<Vec<Direction<D>>> {
    match &cfg.dirs {
        DirSpec::None | DirSpec::Random => Ok(Vec::new()),
        DirSpec::Fixed(v) => Ok(vec![Direction::<D>::new(to_array(v))
            .map_err(|e| LabError::Usage(format!("--direction {}: {e}", join(v))))?]),
        DirSpec::Groups(k) => (0..*k)
            .map(|i| {
                let (i, k) = (i as f64, *k as f64);
                let mut w = [0.0; D];
                if D == 2 {
                    let a = i * std::f64::consts::PI / k;
                    w[0] = a.cos();
                    w[1] = a.sin();
                } else {
                    let z = 1.0 - i / k;
                    let r = (1.0 - z * z).max(0.0).sqrt();
                    let phi = i * std::f64::consts::PI * (3.0 - 5f64.sqrt());
                    w[0] = r * phi.cos();
                    w[1] = r * phi.sin();
                    w[2] = z;
                }
                Direction::<D>::new(w).map_err(|e| LabError::Usage(format!("--groups {k}: {e}")))
            })
            .collect(),
    }
}

/// Everything the chunks of a row share: the integrand, the directions and the
/// pattern (`D`-dimensional for points and segments, `K = D − 1` for lines).
struct Setup<const D: usize, const K: usize> {
    f: Box<dyn Integrand<D> + Send + Sync>,
    dirs: Vec<Direction<D>>,
    full: Option<DynPattern<D>>,
    offsets: Option<DynPattern<K>>,
}

impl<const D: usize, const K: usize> Setup<D, K> {
    fn new(cfg: &Config, row: &Row) -> Result<Self> {
        let spec = cfg.pattern_spec(row);
        let what = |e: String| LabError::Usage(format!("--n {}: {e}", row.n));
        let (full, offsets, len) = if cfg.primitive == Primitive::Lines {
            let p = sampler::build::<K>(&spec, false).map_err(what)?.pattern;
            let len = p.len();
            (None, Some(p), len)
        } else {
            let p = sampler::build::<D>(&spec, false).map_err(what)?.pattern;
            let len = p.len();
            (Some(p), None, len)
        };
        if len != row.per_group {
            return Err(LabError::Usage(format!(
                "--n {}: --sampler {} built {len} points instead of {}",
                row.n, cfg.sampler, row.per_group
            )));
        }
        Ok(Setup {
            f: cfg.integrand.build::<D>()?,
            dirs: directions::<D>(cfg)?,
            full,
            offsets,
        })
    }

    fn estimator(&self, cfg: &Config) -> Result<Box<dyn Estimator<D> + '_>> {
        let directions = match &cfg.dirs {
            DirSpec::Random => Directions::Random,
            DirSpec::Groups(_) => Directions::Groups(&self.dirs),
            DirSpec::None | DirSpec::Fixed(_) => match self.dirs.first() {
                Some(d) => Directions::Fixed(*d),
                None => Directions::Random, // unused by points
            },
        };
        let err = |e: linesample::ParamError| {
            LabError::Usage(format!("--primitive {}: {e}", cfg.primitive.name()))
        };
        let missing = || LabError::Internal("no pattern".into());
        Ok(match cfg.primitive {
            Primitive::Points => {
                let p = self.full.as_deref().ok_or_else(missing)?;
                Box::new(PointEstimator::new(p).map_err(err)?)
            }
            Primitive::Segments => {
                let p = self.full.as_deref().ok_or_else(missing)?;
                Box::new(
                    SegmentEstimator::new(p, cfg.length, directions)
                        .map_err(|e| LabError::Usage(format!("--length {}: {e}", cfg.length)))?,
                )
            }
            Primitive::Lines => {
                let p = self.offsets.as_deref().ok_or_else(missing)?;
                Box::new(LineEstimator::<D, K>::new(p, directions).map_err(err)?)
            }
        })
    }
}

/// The statistics of one chunk, as stored.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct ChunkStats {
    /// `RunningStats::parts`.
    pub n: u64,
    pub moments: [f64; 4],
    /// Wall time of the chunk on its thread, in seconds.
    pub seconds: f64,
}

/// One cell: the chunk statistics of one N, in chunk order.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Cell {
    pub chunks: Vec<ChunkStats>,
}

/// The experiment.
#[derive(Debug)]
pub struct Convergence {
    config: Config,
    cells: Vec<CellInfo>,
}

fn validate<const D: usize, const K: usize>(cfg: &Config) -> Result<()> {
    for row in &cfg.rows {
        let setup = Setup::<D, K>::new(cfg, row)?;
        setup.estimator(cfg)?;
    }
    Ok(())
}

impl Convergence {
    /// The experiment of `config`, with every row's pattern and estimator
    /// checked before any work.
    ///
    /// # Errors
    /// The first invalid row's message.
    pub fn new(config: Config) -> Result<Self> {
        with_dims!(domain config.dims(), validate(&config))?;
        let cells = config
            .rows
            .iter()
            .map(|r| CellInfo {
                label: format!("N = {}", r.n),
                work: config.realisations,
            })
            .collect();
        Ok(Convergence { config, cells })
    }
}

fn run_row<const D: usize, const K: usize>(
    exp: &Convergence,
    row: &Row,
    ctx: &Ctx<'_>,
) -> Result<Cell> {
    let cfg = &exp.config;
    let seed = row_seed(cfg.seed, row.n);
    // Pattern, integrand and directions once per row; each chunk borrows them
    // for its own estimator and scratch.
    let setup = Setup::<D, K>::new(cfg, row)?;
    run_chunks(ctx, cfg.realisations, |first, count| {
        let est = setup.estimator(cfg)?;
        let mut scratch = io::buffer::filled(est.scratch_len(), 0.0f32, "estimator scratch")?;
        run_realisations(
            &*est,
            &*setup.f,
            seed,
            first,
            count,
            cfg.shift == ShiftMode::Random,
            &mut scratch,
        )
        .map_err(|e| {
            let hint = match e {
                EstimateError::Pattern(PatternError::Shortfall { .. }) => {
                    "; lower --relative-radius (or drop --bridson)"
                }
                _ => "",
            };
            LabError::Message(format!(
                "N = {}, realisations {first}..{}: {e}{hint}",
                row.n,
                first + count
            ))
        })
    })
}

/// The run seed of the row with N primitives:
/// `Seed::new(Seed::new(seed).stream(N))` (realisation `r` uses its
/// `.realization(r)`).
#[must_use]
pub fn row_seed(seed: u64, n: usize) -> Seed {
    Seed::new(Seed::new(seed).stream(n as u64))
}

/// One row's cell: `realisations` split into chunks of [`CHUNK`], each run
/// by `chunk(first, count)` on the pool (with its wall time) and returned in
/// chunk order, so the merged statistics do not depend on the thread count.
///
/// # Errors
/// The first error of `chunk`, or a realisation count too large to split.
pub fn run_chunks(
    ctx: &Ctx<'_>,
    realisations: u64,
    chunk: impl Fn(u64, u64) -> Result<RunningStats> + Sync + Send,
) -> Result<Cell> {
    let n_chunks = usize::try_from(realisations.div_ceil(CHUNK))
        .map_err(|_| LabError::Usage(format!("--realisations {realisations}: too many")))?;
    let chunks = ctx.map_ordered(n_chunks, |c| {
        let t = Instant::now();
        let first = c as u64 * CHUNK;
        let count = CHUNK.min(realisations - first);
        let st = chunk(first, count)?;
        ctx.advance(count);
        let (n, moments) = st.parts();
        Ok(ChunkStats {
            n,
            moments,
            seconds: t.elapsed().as_secs_f64(),
        })
    })?;
    Ok(Cell { chunks })
}

impl Experiment for Convergence {
    type Config = Config;
    type Cell = Cell;
    const KIND: &'static str = KIND;
    const UNIT: &'static str = "realisations";

    fn config(&self) -> &Config {
        &self.config
    }

    fn cells(&self) -> &[CellInfo] {
        &self.cells
    }

    fn run_cell(&self, index: usize, ctx: &Ctx<'_>) -> crate::Result<Cell> {
        let row = self.config.rows[index];
        Ok(with_dims!(domain self.config.dims(), run_row(self, &row, ctx))?)
    }
}

/// One finished row.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RowResult {
    pub row: Row,
    pub mean: f64,
    pub mean_se: f64,
    pub variance: f64,
    pub variance_se: f64,
    pub bias_z: f64,
    /// Summed chunk wall time divided by R, in microseconds.
    pub us_per_realisation: f64,
}

/// The results of a convergence experiment.
#[derive(Clone, Debug, Serialize)]
pub struct Results {
    pub exact: f64,
    pub rows: Vec<RowResult>,
    pub fit: Option<Fit>,
}

/// `(mean − exact)/se`, with `0` for an exact mean and `±∞` for a biased
/// zero-variance mean.
fn bias_z(mean: f64, exact: f64, se: f64) -> f64 {
    let d = mean - exact;
    if d == 0.0 {
        0.0
    } else if se > 0.0 {
        d / se
    } else {
        d.signum() * f64::INFINITY
    }
}

impl Convergence {
    /// The configuration.
    #[must_use]
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The results from the cells (in row order): chunk statistics merged in
    /// chunk order, the exact integral, and the weighted log-log fit.
    ///
    /// # Errors
    /// If a stored chunk is invalid or the integrand cannot be built.
    pub fn results(&self, cells: &[Cell]) -> Result<Results> {
        let cfg = &self.config;
        let exact = with_dims!(domain cfg.dims(), exact_integral(cfg))?;
        let rows = cfg
            .rows
            .iter()
            .zip(cells)
            .map(|(row, cell)| row_result(row, cell, exact, cfg.realisations))
            .collect::<Result<Vec<_>, _>>()?;
        let data: Vec<(f64, f64, f64)> = rows
            .iter()
            .map(|r| (r.row.n as f64, r.variance, r.variance_se))
            .collect();
        Ok(Results {
            exact,
            rows,
            fit: fit_loglog(&data),
        })
    }
}

/// One row's result: its chunk statistics merged in chunk order, the bias
/// z-score against `exact`, and the summed chunk time per realisation.
///
/// # Errors
/// If a stored chunk is invalid.
pub fn row_result(row: &Row, cell: &Cell, exact: f64, realisations: u64) -> Result<RowResult> {
    let mut st = RunningStats::new();
    let mut busy = 0.0;
    for c in &cell.chunks {
        let part = RunningStats::from_parts(c.n, c.moments)
            .map_err(|e| format!("N = {}: stored chunk statistics: {e}", row.n))?;
        st.merge(&part);
        busy += c.seconds;
    }
    Ok(RowResult {
        row: *row,
        mean: st.mean(),
        mean_se: st.mean_std_error(),
        variance: st.variance(),
        variance_se: st.variance_std_error(),
        bias_z: bias_z(st.mean(), exact, st.mean_std_error()),
        us_per_realisation: busy * 1e6 / realisations as f64,
    })
}

fn exact_integral<const D: usize, const E: usize>(cfg: &Config) -> Result<f64> {
    Ok(cfg.integrand.build::<D>()?.integral())
}

fn fit_line(fit: Option<&Fit>) -> String {
    match fit {
        Some(f) => format!(
            "slope of log Var vs log N (weighted least squares over {} N, weights (Var/SE(Var))^2): \
             {:.4} ± {:.4} (chi2/dof {})",
            f.points,
            f.slope,
            f.slope_se,
            if f.chi2_dof.is_nan() {
                "n/a".to_string()
            } else {
                format!("{:.2}", f.chi2_dof)
            }
        ),
        None => "slope of log Var vs log N: not fitted (needs two N with positive variance \
                 and finite SE)"
            .to_string(),
    }
}

/// A CSV row (field names are the header).
#[derive(Serialize)]
struct CsvRow {
    n: usize,
    realisations: u64,
    #[serde(serialize_with = "table::sci")]
    mean: f64,
    #[serde(serialize_with = "table::sci")]
    mean_se: f64,
    #[serde(serialize_with = "table::sci")]
    exact: f64,
    #[serde(serialize_with = "table::sci")]
    bias_z: f64,
    #[serde(serialize_with = "table::sci")]
    variance: f64,
    #[serde(serialize_with = "table::sci")]
    variance_se: f64,
    #[serde(serialize_with = "table::sci")]
    var_times_n: f64,
}

/// What the manifest says about `convergence.csv` (format in [`FORMATS`]):
/// the command, the homogenisation, the seeding rule, notes, the fit.
#[must_use]
pub fn csv_notes(cfg: &Config, res: &Results) -> Vec<String> {
    let mut comments = vec![cfg.command()];
    comments.push(match cfg.shift {
        ShiftMode::Random => "homogenised: random toroidal shift per realisation".into(),
        ShiftMode::None => {
            "not homogenised (--shift none): the patterns as generated, strata aligned to the domain"
                .into()
        }
    });
    comments.push(format!(
        "seeding: row N uses run seed Seed::new(Seed::new({}).stream(N)), realisation r \
         its .realization(r); realisations run in chunks of {CHUNK} merged in order",
        cfg.seed
    ));
    comments.extend(cfg.notes.iter().map(|n| format!("note: {n}")));
    comments.push(fit_line(res.fit.as_ref()));
    comments
}

/// The rows of `convergence.csv` (format in [`FORMATS`]).
#[must_use]
fn csv_rows(cfg: &Config, res: &Results) -> Vec<CsvRow> {
    res.rows
        .iter()
        .map(|r| CsvRow {
            n: r.row.n,
            realisations: cfg.realisations,
            mean: r.mean,
            mean_se: r.mean_se,
            exact: res.exact,
            bias_z: r.bias_z,
            variance: r.variance,
            variance_se: r.variance_se,
            var_times_n: r.variance * r.row.n as f64,
        })
        .collect()
}

/// The log-log plot of `res`.
///
/// # Errors
/// Only on an internal drawing error.
pub fn svg(cfg: &Config, res: &Results) -> Result<String> {
    let title = format!(
        "{} {}D, {}, {}, R = {}",
        cfg.integrand.kind.name(),
        cfg.dims(),
        cfg.primitive.name(),
        cfg.sampler,
        cfg.realisations
    );
    let homog = match cfg.shift {
        ShiftMode::Random => "homogenised",
        ShiftMode::None => "not homogenised",
    };
    let subtitle = match &res.fit {
        Some(f) => format!(
            "{}; {homog}; slope {:.3} ± {:.3}",
            cfg.describe(),
            f.slope,
            f.slope_se
        ),
        None => format!("{}; {homog}", cfg.describe()),
    };
    let points: Vec<figures::Point> = res
        .rows
        .iter()
        .map(|r| figures::Point {
            x: r.row.n as f64,
            y: r.variance,
            err: r.variance_se,
        })
        .collect();
    figures::loglog(&figures::LogLog {
        title: &title,
        subtitle: &subtitle,
        x_label: "N (primitives per realisation)",
        y_label: "variance of the estimate",
        points: &points,
        fit: res.fit.map(|f| figures::PowerLaw {
            slope: f.slope,
            intercept: f.intercept,
            label: format!("fit: slope {:.3} ± {:.3}", f.slope, f.slope_se),
        }),
        reference_slopes: &REFERENCE_SLOPES,
    })
}

/// The printed table.
#[must_use]
pub fn report(cfg: &Config, res: &Results, threads: usize) -> String {
    let mut s = String::new();
    for note in &cfg.notes {
        let _ = writeln!(s, "note: {note}");
    }
    let _ = writeln!(
        s,
        "convergence: {}; R = {} realisations per N, seed {}, {threads} thread(s), {}",
        cfg.describe(),
        cfg.realisations,
        cfg.seed,
        match cfg.shift {
            ShiftMode::Random => "homogenised (random toroidal shift per realisation)",
            ShiftMode::None => "not homogenised (--shift none)",
        }
    );
    let _ = writeln!(s, "exact integral {}", res.exact);
    let _ = writeln!(
        s,
        "{:>8} {:>14} {:>14} {:>8} {:>12} {:>10} {:>12} {:>12}",
        "N", "mean", "exact", "bias z", "variance", "SE(var)", "Var*N", "µs/real."
    );
    for r in &res.rows {
        let _ = writeln!(
            s,
            "{:>8} {:>14.10} {:>14.10} {:>+8.2} {:>12.4e} {:>10.2e} {:>12.4e} {:>12.1}",
            r.row.n,
            r.mean,
            res.exact,
            r.bias_z,
            r.variance,
            r.variance_se,
            r.variance * r.row.n as f64,
            r.us_per_realisation
        );
    }
    let _ = writeln!(s, "{}", fit_line(res.fit.as_ref()));
    s
}

/// Writes `OUT/convergence.csv`, `OUT/convergence.svg` and
/// `OUT/manifest.json` as one group and prints the table (unless `quiet`).
///
/// # Errors
/// A drawing or I/O error.
pub fn complete(
    exp: &Convergence,
    cells: &[Cell],
    info: &RunInfo,
    out: &Path,
    quiet: bool,
) -> Result<Results> {
    let cfg = &exp.config;
    let res = exp.results(cells)?;
    let (csv_path, svg_path, json_path) = (
        out.join("convergence.csv"),
        out.join("convergence.svg"),
        out.join("manifest.json"),
    );
    let mut group = FileGroup::new();
    group.add_csv(&csv_path, &csv_notes(cfg, &res), &csv_rows(cfg, &res))?;
    group.add_bytes(&svg_path, svg(cfg, &res)?.as_bytes())?;
    let files = [&csv_path, &svg_path].map(|p| file_name(p)).to_vec();
    let manifest = OutputManifest::new(KIND, cfg.command(), cfg, info, files).with_notes(&group);
    group.add_bytes(&json_path, &io::json(&manifest)?)?;
    group.commit()?;
    if !quiet {
        crate::out!("{}", report(cfg, &res, info.threads).trim_end());
        crate::out!("total wall time {:.2} s", info.wall.as_secs_f64());
        crate::out!(
            "wrote {}, {} and {}",
            csv_path.display(),
            svg_path.display(),
            json_path.display()
        );
    }
    Ok(res)
}

/// `linesample-lab merge` for convergence shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge(a: &MergeRequest, config: serde_json::Value) -> Result<()> {
    let exp = Convergence::new(config_from(config, KIND)?)?;
    merge_to_files(
        &exp,
        a,
        Box::new(|e, c, i, o, q| {
            complete(e, &c, i, o, q)?;
            Ok(())
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_powers() {
        assert_eq!(nearest_power(16.0, 2), 4);
        assert_eq!(nearest_power(1000.0, 2), 32);
        assert_eq!(nearest_power(4096.0, 3), 16);
        assert_eq!(nearest_power(1000.0, 3), 10);
        assert_eq!(nearest_power(17.0, 2), 4);
        assert_eq!(nearest_power(1.0, 3), 1);
        assert_eq!(nearest_power(5.0, 1), 5);
    }

    #[test]
    fn z_scores() {
        assert_eq!(bias_z(1.0, 1.0, 0.0), 0.0);
        assert_eq!(bias_z(1.5, 1.0, 0.25), 2.0);
        assert_eq!(bias_z(0.5, 1.0, 0.0), f64::NEG_INFINITY);
    }
}
