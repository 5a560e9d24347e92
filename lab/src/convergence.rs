//! `convergence`: the variance of one estimator as the sample count `N` grows.
//!
//! Everything numeric is a kernel call: patterns from [`crate::sampler`],
//! integrands from `linesample::integrand`, estimates and statistics from
//! `linesample::estimator::run_realisations` and `RunningStats`. This module
//! orchestrates the runs (in parallel, deterministically), fits the slope, and
//! formats the table, the CSV and the plot.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use clap::{Args, ValueEnum};
use linesample::estimator::{
    run_realisations, Directions, Estimator, LineEstimator, PointEstimator, SegmentEstimator,
};
use linesample::geom::Direction;
use linesample::integrand::{Ball, Gaussian, HalfSpace, Integrand};
use linesample::pattern::Pattern;
use linesample::stats::RunningStats;
use linesample::Seed;

use crate::output;
use crate::plot;
use crate::sampler::{self, AnyPattern, Sampler, Spec};

/// Realisations per work unit. Fixed (independent of `--threads`), so the
/// statistics, merged chunk by chunk in chunk order, do not depend on the thread
/// count.
pub const CHUNK: u64 = 32;

/// Default `--n`.
const DEFAULT_NS: [usize; 5] = [16, 64, 256, 1024, 4096];
/// Reference slopes drawn in the plot.
const REFERENCE_SLOPES: [f64; 4] = [-1.0, -1.5, -2.0, -3.0];
/// Centre coordinate of the disk, ball and Gaussian (in every dimension).
const CENTRE: f64 = 0.5;
const DEFAULT_RADIUS: f64 = 0.25;
const DEFAULT_SIGMA: f64 = 0.1;
const DEFAULT_OFFSET: f64 = 0.6;
const DEFAULT_LENGTH: f64 = 0.1;

/// The CSV header (the first line that does not start with `#`).
pub const CSV_HEADER: &str =
    "n,realisations,mean,mean_se,exact,bias_z,variance,variance_se,var_times_n";

pub const FORMATS: &str = "\
Output formats:
  PREFIX.csv  comment lines starting with '#' (the command that reproduces the run
              with every default filled in, `# homogenised: random toroidal shift per
              realisation`, the seeding rule, any rounding of N, the fitted slope),
              then the header
                n,realisations,mean,mean_se,exact,bias_z,variance,variance_se,var_times_n
              and one row per N: the number of primitives N per realisation, R, the
              sample mean of the R estimates and its standard error, the exact
              integral, the bias z-score (mean - exact)/mean_se, the unbiased sample
              variance Var, its standard error SE(Var) (from the sample fourth
              central moment), and Var*N. Numbers use Rust's shortest round-trip
              formatting (e.g. 1.2345e-5). No timings and no thread count appear in
              the CSV, so it is byte-identical for every --threads.
  PREFIX.svg  log-log plot of Var against N with +-1 SE(Var) error bars, the fitted
              power law (solid), reference slopes -1, -1.5, -2 and -3 (thin dashed,
              through the smallest N), decade tick labels, and a title naming the
              integrand, primitive, sampler and R.

The printed table adds the time per realisation in microseconds: the wall time of
each chunk of realisations, summed over the row's chunks and divided by R (so it
does not shrink with --threads; a busy machine inflates it). Both files are written to FILE.tmp, synced and
renamed, so a result file is either complete or absent. Errors print
`error: <message>` on stderr and exit with a non-zero code.";

/// The integrands `convergence` can measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IntegrandKind {
    /// Indicator of the disk of radius --radius centred at (0.5, 0.5); 2D only.
    Disk,
    /// Indicator of the ball of radius --radius centred at (0.5, ..); a 2D ball
    /// is the disk.
    Ball,
    /// Normalised isotropic Gaussian density with standard deviation --sigma
    /// centred at (0.5, ..), periodised on the torus (integral 1).
    Gaussian,
    /// Straight edge: the indicator of {x in [0,1)^D : n.x >= h} for the unit
    /// normal n along --normal and the offset h = --offset.
    Edge,
}

impl IntegrandKind {
    fn name(self) -> &'static str {
        match self {
            IntegrandKind::Disk => "disk",
            IntegrandKind::Ball => "ball",
            IntegrandKind::Gaussian => "gaussian",
            IntegrandKind::Edge => "edge",
        }
    }
}

/// Sample primitives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Primitive {
    /// Points from a D-dimensional pattern: (1/N) sum f(x_k).
    Points,
    /// Segments of length --length centred at the points of a D-dimensional
    /// pattern, wrapped on the torus: (1/N) sum (1/length) int f along segment k.
    Segments,
    /// Lines whose offsets come from a (D-1)-dimensional pattern on the plane
    /// orthogonal to the direction: A (1/N) sum int f along line k (A = 1 for
    /// axis directions; other directions are clipped to the unit box).
    Lines,
}

impl Primitive {
    fn name(self) -> &'static str {
        match self {
            Primitive::Points => "points",
            Primitive::Segments => "segments",
            Primitive::Lines => "lines",
        }
    }
}

/// Options of `linesample-lab convergence`.
#[derive(Debug, Args)]
pub struct ConvergenceArgs {
    /// Integrand whose integral over the unit torus is estimated.
    #[arg(long, value_enum, default_value_t = IntegrandKind::Disk)]
    integrand: IntegrandKind,

    /// Dimension D of the domain, 2 or 3.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
    dims: u8,

    /// Disk and ball: radius, in [1e-100, 1/2] [default: 0.25].
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    radius: Option<f64>,

    /// Gaussian: standard deviation (the kernel accepts 1e-6 to 1e6) [default:
    /// 0.1].
    #[arg(long, value_name = "SIGMA", allow_hyphen_values = true)]
    sigma: Option<f64>,

    /// Edge: normal of the edge, D comma-separated components (normalised to unit
    /// length) [default: 0.7,1 in 2D, 0.7,1,0.4 in 3D].
    #[arg(
        long,
        value_name = "X,Y[,Z]",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    normal: Option<Vec<f64>>,

    /// Edge: offset h of the edge n.x >= h along the unit normal [default: 0.6].
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    offset: Option<f64>,

    /// Sample primitive.
    #[arg(long, value_enum, default_value_t = Primitive::Points)]
    primitive: Primitive,

    /// Pattern of the points, the segment centres, or the line offsets (lines use
    /// a (D-1)-dimensional pattern). Poisson disk uses maximal dart throwing at
    /// 0.75 times the densest-packing radius for N; no pattern is pre-shifted
    /// (the estimator homogenises).
    #[arg(long, value_enum, default_value_t = Sampler::Jittered)]
    sampler: Sampler,

    /// Segments only: segment length, from 0 (the point estimator) to 2^20;
    /// segments wrap on the torus, so lengths above 1 are allowed [default: 0.1].
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    length: Option<f64>,

    /// Segments and lines: one fixed direction for every primitive, D
    /// comma-separated components (normalised) [default: the last axis, 0,1 in 2D
    /// and 0,0,1 in 3D].
    #[arg(
        long,
        value_name = "X,Y[,Z]",
        value_delimiter = ',',
        allow_hyphen_values = true,
        conflicts_with_all = ["random_direction", "groups"]
    )]
    direction: Option<Vec<f64>>,

    /// Segments and lines: an independent uniformly random direction per
    /// primitive.
    #[arg(long, conflicts_with = "groups")]
    random_direction: bool,

    /// Segments and lines: K direction groups, each with its own independent
    /// realisation of the pattern holding N/K primitives; the estimate is the
    /// mean of the group estimates. 2D: the angles k*pi/K from the x axis,
    /// k = 0..K-1. 3D: a Fibonacci spiral on the upper hemisphere starting at the
    /// z axis, z_k = 1 - k/K, azimuth k*pi*(3 - sqrt 5).
    #[arg(long, value_name = "K")]
    groups: Option<usize>,

    /// Sample counts N (primitives per realisation, all groups together),
    /// comma-separated. Jittered needs m^d' points per pattern (d' = D, or D-1
    /// for lines): each N is rounded to the nearest such count, and a note says
    /// so. With --groups K each N is rounded to a multiple of K.
    #[arg(
        short = 'n',
        long = "n",
        value_name = "N1,N2,..",
        value_delimiter = ',',
        default_values_t = DEFAULT_NS
    )]
    n: Vec<usize>,

    /// Number of independent realisations R per N (at least 4).
    #[arg(
        long,
        value_name = "R",
        visible_alias = "realizations",
        default_value_t = 1000
    )]
    realisations: u64,

    /// Seed of the run. Row N uses the run seed
    /// Seed::new(Seed::new(SEED).stream(N)) and realisation r its
    /// .realization(r), so rows are independent of each other.
    #[arg(long, default_value_t = 1)]
    seed: u64,

    /// Worker threads [default: the available parallelism]. The results do not
    /// depend on it.
    #[arg(long, value_name = "T")]
    threads: Option<usize>,

    /// Output path prefix; writes PREFIX.csv and PREFIX.svg, creating parent
    /// directories (default:
    /// `out/convergence/<integrand>-<dims>d-<primitive>-<sampler>`).
    #[arg(long, value_name = "PREFIX")]
    out: Option<PathBuf>,
}

/// The integrand with every parameter resolved.
#[derive(Clone, Debug)]
enum IntegrandSpec {
    Ball { radius: f64 },
    Gaussian { sigma: f64 },
    Edge { normal: Vec<f64>, offset: f64 },
}

/// How segments and lines are oriented (resolved).
#[derive(Clone, Debug)]
enum DirSpec {
    None,
    Fixed(Vec<f64>),
    Random,
    Groups(usize),
}

/// One row of the experiment: the requested N and what is actually run.
#[derive(Clone, Copy, Debug)]
struct Row {
    requested: usize,
    /// Primitives per pattern realisation (per group).
    per_group: usize,
    /// N = groups * per_group.
    n: usize,
}

#[derive(Clone, Debug)]
struct Config {
    kind: IntegrandKind,
    dims: usize,
    integrand: IntegrandSpec,
    primitive: Primitive,
    sampler: Sampler,
    length: f64,
    dirs: DirSpec,
    rows: Vec<Row>,
    realisations: u64,
    seed: u64,
    threads: usize,
    out: PathBuf,
    notes: Vec<String>,
}

impl Config {
    /// Dimension of the pattern: D, or D − 1 for line offsets.
    fn pattern_dims(&self) -> usize {
        if self.primitive == Primitive::Lines {
            self.dims - 1
        } else {
            self.dims
        }
    }

    fn integrand_desc(&self) -> String {
        let c = vec![format!("{CENTRE}"); self.dims].join(",");
        match &self.integrand {
            IntegrandSpec::Ball { radius } => format!("centre {c}, radius {radius}"),
            IntegrandSpec::Gaussian { sigma } => format!("centre {c}, sigma {sigma}"),
            IntegrandSpec::Edge { normal, offset } => {
                format!("normal {}, offset {offset}", join(normal))
            }
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

    /// The command that reproduces the results (every default filled in;
    /// --threads and --out do not change them and are left out).
    fn command(&self) -> String {
        let mut c = format!(
            "linesample-lab convergence --integrand {} --dims {}",
            self.kind.name(),
            self.dims
        );
        match &self.integrand {
            IntegrandSpec::Ball { radius } => {
                let _ = write!(c, " --radius {radius}");
            }
            IntegrandSpec::Gaussian { sigma } => {
                let _ = write!(c, " --sigma {sigma}");
            }
            IntegrandSpec::Edge { normal, offset } => {
                let _ = write!(c, " --normal {} --offset {offset}", join(normal));
            }
        }
        let _ = write!(
            c,
            " --primitive {} --sampler {}",
            self.primitive.name(),
            self.sampler
        );
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
        c
    }
}

fn join(v: &[f64]) -> String {
    v.iter().map(f64::to_string).collect::<Vec<_>>().join(",")
}

/// The `m` minimising `|m^d − x|` (`m ≥ 1`).
fn nearest_power(x: f64, d: usize) -> usize {
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

fn not_for(option: &str, what: &str, got: &str) -> String {
    format!("{option} applies only to {what} (got {got})")
}

fn resolve(a: &ConvergenceArgs) -> Result<Config, String> {
    let dims = usize::from(a.dims);
    let kind = a.integrand;
    let got_integrand = format!("--integrand {}", kind.name());
    if kind == IntegrandKind::Disk && dims != 2 {
        return Err(format!(
            "--dims {dims}: --integrand disk is 2D only; use --integrand ball for --dims 3"
        ));
    }
    let is_ball = matches!(kind, IntegrandKind::Disk | IntegrandKind::Ball);
    if a.radius.is_some() && !is_ball {
        return Err(not_for(
            "--radius",
            "--integrand disk or ball",
            &got_integrand,
        ));
    }
    if a.sigma.is_some() && kind != IntegrandKind::Gaussian {
        return Err(not_for("--sigma", "--integrand gaussian", &got_integrand));
    }
    if (a.normal.is_some() || a.offset.is_some()) && kind != IntegrandKind::Edge {
        let opt = if a.normal.is_some() {
            "--normal"
        } else {
            "--offset"
        };
        return Err(not_for(opt, "--integrand edge", &got_integrand));
    }
    let integrand = match kind {
        IntegrandKind::Disk | IntegrandKind::Ball => IntegrandSpec::Ball {
            radius: a.radius.unwrap_or(DEFAULT_RADIUS),
        },
        IntegrandKind::Gaussian => IntegrandSpec::Gaussian {
            sigma: a.sigma.unwrap_or(DEFAULT_SIGMA),
        },
        IntegrandKind::Edge => {
            let normal = match &a.normal {
                Some(v) if v.len() != dims => {
                    return Err(format!(
                        "--normal has {} component(s) but --dims is {dims}: give {dims} \
                         comma-separated numbers",
                        v.len()
                    ))
                }
                Some(v) => v.clone(),
                None if dims == 2 => vec![0.7, 1.0],
                None => vec![0.7, 1.0, 0.4],
            };
            IntegrandSpec::Edge {
                normal,
                offset: a.offset.unwrap_or(DEFAULT_OFFSET),
            }
        }
    };

    let prim = a.primitive;
    let got_prim = format!("--primitive {}", prim.name());
    if a.length.is_some() && prim != Primitive::Segments {
        return Err(not_for("--length", "--primitive segments", &got_prim));
    }
    let length = a.length.unwrap_or(DEFAULT_LENGTH);
    let oriented = "--primitive segments or lines";
    let dirs = if prim == Primitive::Points {
        if a.direction.is_some() {
            return Err(not_for("--direction", oriented, &got_prim));
        }
        if a.random_direction {
            return Err(not_for("--random-direction", oriented, &got_prim));
        }
        if a.groups.is_some() {
            return Err(not_for("--groups", oriented, &got_prim));
        }
        DirSpec::None
    } else if a.random_direction {
        DirSpec::Random
    } else if let Some(k) = a.groups {
        if k == 0 {
            return Err("--groups 0: expected at least 1 direction group".into());
        }
        DirSpec::Groups(k)
    } else {
        match &a.direction {
            Some(v) if v.len() != dims => {
                return Err(format!(
                    "--direction has {} component(s) but --dims is {dims}: give {dims} \
                     comma-separated numbers",
                    v.len()
                ))
            }
            Some(v) => DirSpec::Fixed(v.clone()),
            None => {
                let mut v = vec![0.0; dims];
                v[dims - 1] = 1.0;
                DirSpec::Fixed(v)
            }
        }
    };

    let sampler = a.sampler;
    let pdims = if prim == Primitive::Lines {
        dims - 1
    } else {
        dims
    };
    if !sampler.dims().contains(&pdims) {
        let ds: Vec<String> = sampler.dims().iter().map(ToString::to_string).collect();
        return Err(if prim == Primitive::Lines {
            format!(
                "--sampler {sampler} cannot place line offsets for --dims {dims}: lines need a \
                 {pdims}D pattern and {sampler} supports only {}D",
                ds.join("D, ")
            )
        } else {
            format!(
                "--dims {dims}: --sampler {sampler} supports only --dims {}",
                ds.join(", ")
            )
        });
    }

    if a.realisations < 4 {
        return Err(format!(
            "--realisations {}: expected at least 4 (the standard error of the variance \
             needs 4 realisations)",
            a.realisations
        ));
    }
    let threads = match a.threads {
        Some(0) => return Err("--threads 0: expected at least 1".into()),
        Some(t) => t,
        None => std::thread::available_parallelism().map_or(1, usize::from),
    };

    if a.n.is_empty() {
        return Err("--n: expected at least one sample count".into());
    }
    let groups = match dirs {
        DirSpec::Groups(k) => k,
        _ => 1,
    };
    let mut notes = Vec::new();
    let mut rows: Vec<Row> = Vec::new();
    for &requested in &a.n {
        if requested == 0 {
            return Err("--n 0: every N must be at least 1".into());
        }
        if requested < groups {
            return Err(format!(
                "--n {requested}: fewer samples than --groups {groups} (every group needs at \
                 least one primitive)"
            ));
        }
        let mut per_group = ((requested as f64) / groups as f64).round().max(1.0) as usize;
        let mut why = Vec::new();
        if groups > 1 && per_group * groups != requested {
            why.push(format!("a multiple of --groups {groups}"));
        }
        if sampler == Sampler::Jittered && pdims > 1 {
            let m = nearest_power(per_group as f64, pdims);
            let p = m.pow(u32::try_from(pdims).unwrap_or(1));
            if p != per_group {
                why.push(format!("m^{pdims} points per pattern"));
            }
            per_group = p;
            if !why.is_empty() {
                let strata = vec![m.to_string(); pdims].join("x");
                let n = per_group * groups;
                notes.push(format!(
                    "--n {requested} -> N = {n}: --sampler jittered needs {} ({strata} strata{})",
                    why.join(" and "),
                    if groups > 1 {
                        format!(" per group, {groups} groups")
                    } else {
                        String::new()
                    }
                ));
            }
        } else if !why.is_empty() {
            notes.push(format!(
                "--n {requested} -> N = {}: N must be {}",
                per_group * groups,
                why.join(" and ")
            ));
        }
        let n = per_group * groups;
        if let Some(prev) = rows.iter().find(|r| r.n == n) {
            return Err(format!(
                "--n: {} and {requested} both give N = {n}{}; give distinct sample counts",
                prev.requested,
                if sampler == Sampler::Jittered {
                    " after rounding to a jittered grid"
                } else {
                    " after rounding"
                }
            ));
        }
        rows.push(Row {
            requested,
            per_group,
            n,
        });
    }

    let out = match &a.out {
        Some(p) => p.clone(),
        None => PathBuf::from("out/convergence").join(format!(
            "{}-{dims}d-{}-{sampler}",
            kind.name(),
            prim.name()
        )),
    };
    if out.file_name().is_none() {
        return Err(format!(
            "--out {}: expected a file prefix such as out/conv, not a directory",
            out.display()
        ));
    }
    Ok(Config {
        kind,
        dims,
        integrand,
        primitive: prim,
        sampler,
        length,
        dirs,
        rows,
        realisations: a.realisations,
        seed: a.seed,
        threads,
        out,
        notes,
    })
}

/// The `D`-dimensional pattern inside an [`AnyPattern`].
trait PatternOf<const D: usize> {
    fn get(p: &AnyPattern) -> Option<&dyn Pattern<D>>;
}

struct Dim;

impl PatternOf<1> for Dim {
    fn get(p: &AnyPattern) -> Option<&dyn Pattern<1>> {
        match p {
            AnyPattern::D1(p) => Some(p.as_ref()),
            _ => None,
        }
    }
}

impl PatternOf<2> for Dim {
    fn get(p: &AnyPattern) -> Option<&dyn Pattern<2>> {
        match p {
            AnyPattern::D2(p) => Some(p.as_ref()),
            _ => None,
        }
    }
}

impl PatternOf<3> for Dim {
    fn get(p: &AnyPattern) -> Option<&dyn Pattern<3>> {
        match p {
            AnyPattern::D3(p) => Some(p.as_ref()),
            _ => None,
        }
    }
}

fn to_array<const D: usize>(v: &[f64]) -> [f64; D] {
    let mut a = [0.0; D];
    a.copy_from_slice(v);
    a
}

fn make_integrand<const D: usize>(cfg: &Config) -> Result<Box<dyn Integrand<D>>, String> {
    let centre = [CENTRE; D];
    let kind = cfg.kind.name();
    Ok(match &cfg.integrand {
        IntegrandSpec::Ball { radius } => Box::new(
            Ball::<D>::new(centre, *radius)
                .map_err(|e| format!("--radius {radius} (--integrand {kind}): {e}"))?,
        ),
        IntegrandSpec::Gaussian { sigma } => Box::new(
            Gaussian::<D>::new(centre, *sigma)
                .map_err(|e| format!("--sigma {sigma} (--integrand gaussian): {e}"))?,
        ),
        IntegrandSpec::Edge { normal, offset } => {
            let n = Direction::<D>::new(to_array(normal))
                .map_err(|e| format!("--normal {}: {e}", join(normal)))?;
            Box::new(HalfSpace::<D>::new(n, *offset).map_err(|e| {
                format!(
                    "--normal {} --offset {offset} (--integrand edge): {e}",
                    join(normal)
                )
            })?)
        }
    })
}

/// The fixed direction, or the `K` group directions (documented at `--groups`).
fn directions<const D: usize>(cfg: &Config) -> Result<Vec<Direction<D>>, String> {
    match &cfg.dirs {
        DirSpec::None | DirSpec::Random => Ok(Vec::new()),
        DirSpec::Fixed(v) => Ok(vec![Direction::<D>::new(to_array(v))
            .map_err(|e| format!("--direction {}: {e}", join(v)))?]),
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
                Direction::<D>::new(w).map_err(|e| format!("--groups {k}: {e}"))
            })
            .collect(),
    }
}

fn spec(cfg: &Config, row: &Row) -> Spec {
    Spec {
        sampler: cfg.sampler,
        dims: cfg.pattern_dims(),
        n: Some(row.per_group),
        strata: None,
        grid: None,
        shift: false,
        relative_radius: 0.75,
        dart_throwing: true,
    }
}

fn build_pattern(cfg: &Config, row: &Row) -> Result<sampler::Built, String> {
    let built = sampler::build(&spec(cfg, row)).map_err(|e| format!("--n {}: {e}", row.n))?;
    if built.pattern.len() != row.per_group {
        return Err(format!(
            "--n {}: --sampler {} built {} points instead of {}",
            row.n,
            cfg.sampler,
            built.pattern.len(),
            row.per_group
        ));
    }
    Ok(built)
}

fn make_estimator<'a, const D: usize, const K: usize>(
    cfg: &Config,
    pattern: &'a AnyPattern,
    dirs: &'a [Direction<D>],
) -> Result<Box<dyn Estimator<D> + 'a>, String>
where
    Dim: PatternOf<D> + PatternOf<K>,
{
    let wrong = || "internal error: pattern of the wrong dimension".to_string();
    let directions = match &cfg.dirs {
        DirSpec::Random => Directions::Random,
        DirSpec::Groups(_) => Directions::Groups(dirs),
        DirSpec::None | DirSpec::Fixed(_) => match dirs.first() {
            Some(d) => Directions::Fixed(*d),
            None => Directions::Random, // unused by points
        },
    };
    let err = |e: linesample::ParamError| format!("--primitive {}: {e}", cfg.primitive.name());
    Ok(match cfg.primitive {
        Primitive::Points => {
            let p = <Dim as PatternOf<D>>::get(pattern).ok_or_else(wrong)?;
            Box::new(PointEstimator::new(p).map_err(err)?)
        }
        Primitive::Segments => {
            let p = <Dim as PatternOf<D>>::get(pattern).ok_or_else(wrong)?;
            Box::new(
                SegmentEstimator::new(p, cfg.length, directions)
                    .map_err(|e| format!("--length {}: {e}", cfg.length))?,
            )
        }
        Primitive::Lines => {
            let p = <Dim as PatternOf<K>>::get(pattern).ok_or_else(wrong)?;
            Box::new(LineEstimator::<D, K>::new(p, directions).map_err(err)?)
        }
    })
}

/// Statistics of one row, merged in chunk order.
struct RowResult {
    stats: RunningStats,
    /// Summed thread time of all chunks.
    busy: Duration,
}

struct Job<'a, const D: usize> {
    cfg: &'a Config,
    row: Row,
    f: &'a dyn Integrand<D>,
    dirs: &'a [Direction<D>],
    seed: Seed,
    chunks: usize,
    next: AtomicUsize,
    stop: AtomicBool,
}

type ChunkResult = (usize, RunningStats, Duration);

/// One thread: its own pattern, estimator and scratch; takes chunks until none
/// are left.
fn worker<const D: usize, const K: usize>(job: &Job<'_, D>) -> Result<Vec<ChunkResult>, String>
where
    Dim: PatternOf<D> + PatternOf<K>,
{
    let built = build_pattern(job.cfg, &job.row)?;
    let est = make_estimator::<D, K>(job.cfg, &built.pattern, job.dirs)?;
    let mut scratch = vec![0.0f32; est.scratch_len()];
    let r = job.cfg.realisations;
    let mut out = Vec::new();
    while !job.stop.load(Ordering::Relaxed) {
        let c = job.next.fetch_add(1, Ordering::Relaxed);
        if c >= job.chunks {
            break;
        }
        let first = c as u64 * CHUNK;
        let count = CHUNK.min(r - first);
        let t = Instant::now();
        match run_realisations(&*est, job.f, job.seed, first, count, true, &mut scratch) {
            Ok(st) => out.push((c, st, t.elapsed())),
            Err(e) => {
                job.stop.store(true, Ordering::Relaxed);
                return Err(format!(
                    "N = {}, realisations {first}..{}: {e}",
                    job.row.n,
                    first + count
                ));
            }
        }
    }
    Ok(out)
}

fn run_row<const D: usize, const K: usize>(
    cfg: &Config,
    row: Row,
    f: &dyn Integrand<D>,
    dirs: &[Direction<D>],
) -> Result<RowResult, String>
where
    Dim: PatternOf<D> + PatternOf<K>,
{
    let chunks = usize::try_from(cfg.realisations.div_ceil(CHUNK))
        .map_err(|_| format!("--realisations {}: too many", cfg.realisations))?;
    let job = Job {
        cfg,
        row,
        f,
        dirs,
        seed: Seed::new(Seed::new(cfg.seed).stream(row.n as u64)),
        chunks,
        next: AtomicUsize::new(0),
        stop: AtomicBool::new(false),
    };
    let threads = cfg.threads.min(chunks).max(1);
    let results: Vec<Result<Vec<ChunkResult>, String>> = if threads == 1 {
        vec![worker::<D, K>(&job)]
    } else {
        std::thread::scope(|s| {
            let handles: Vec<_> = (0..threads)
                .map(|_| s.spawn(|| worker::<D, K>(&job)))
                .collect();
            handles
                .into_iter()
                .map(|h| match h.join() {
                    Ok(r) => r,
                    Err(p) => std::panic::resume_unwind(p),
                })
                .collect()
        })
    };
    let mut all: Vec<ChunkResult> = Vec::with_capacity(chunks);
    for r in results {
        all.extend(r?);
    }
    all.sort_by_key(|c| c.0);
    if all.len() != chunks || all.iter().enumerate().any(|(i, c)| c.0 != i) {
        return Err(format!("internal error: N = {}: missing chunks", row.n));
    }
    let mut stats = RunningStats::new();
    let mut busy = Duration::ZERO;
    for (_, st, t) in &all {
        stats.merge(st);
        busy += *t;
    }
    Ok(RowResult { stats, busy })
}

/// Weighted least-squares fit of `ln Var = a + b ln N`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    pub slope: f64,
    pub slope_se: f64,
    /// `a` (natural logarithms).
    pub intercept: f64,
    /// `χ²/(m − 2)` for `m` points (NaN for `m = 2`).
    pub chi2_dof: f64,
    pub points: usize,
}

/// Fits `ln y = a + b ln x` by weighted least squares with weights
/// `w = (y/err)²`, the inverse variance of `ln y` by the delta method. Points
/// with `y ≤ 0`, a non-finite or non-positive `err`, or `x ≤ 0` are left out.
/// `slope_se = 1/√(Σ w (ln x − x̄)²)` uses the weights as known variances (it is
/// not rescaled by `χ²`). `None` with fewer than two usable points or a single
/// distinct `x`.
pub fn fit_loglog(data: &[(f64, f64, f64)]) -> Option<Fit> {
    let pts: Vec<(f64, f64, f64)> = data
        .iter()
        .filter(|(x, y, e)| *x > 0.0 && *y > 0.0 && e.is_finite() && *e > 0.0 && y.is_finite())
        .map(|&(x, y, e)| (x.ln(), y.ln(), (y / e) * (y / e)))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let sw: f64 = pts.iter().map(|p| p.2).sum();
    let xm = pts.iter().map(|p| p.2 * p.0).sum::<f64>() / sw;
    let ym = pts.iter().map(|p| p.2 * p.1).sum::<f64>() / sw;
    let sxx: f64 = pts.iter().map(|p| p.2 * (p.0 - xm) * (p.0 - xm)).sum();
    let sxy: f64 = pts.iter().map(|p| p.2 * (p.0 - xm) * (p.1 - ym)).sum();
    if sxx <= 0.0 || !sxx.is_finite() {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = ym - slope * xm;
    let chi2: f64 = pts
        .iter()
        .map(|p| {
            let r = p.1 - intercept - slope * p.0;
            p.2 * r * r
        })
        .sum();
    let dof = pts.len() - 2;
    Some(Fit {
        slope,
        slope_se: 1.0 / sxx.sqrt(),
        intercept,
        chi2_dof: if dof > 0 { chi2 / dof as f64 } else { f64::NAN },
        points: pts.len(),
    })
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

/// One finished row.
struct Done {
    row: Row,
    mean: f64,
    mean_se: f64,
    var: f64,
    var_se: f64,
    z: f64,
    us_per_realisation: f64,
}

/// Entry point of the subcommand.
pub fn run(a: &ConvergenceArgs) -> Result<(), String> {
    let cfg = resolve(a)?;
    match cfg.dims {
        2 => run_dims::<2, 1>(&cfg),
        3 => run_dims::<3, 2>(&cfg),
        d => Err(format!("--dims {d}: expected 2 or 3")),
    }
}

fn run_dims<const D: usize, const K: usize>(cfg: &Config) -> Result<(), String>
where
    Dim: PatternOf<D> + PatternOf<K>,
{
    let f = make_integrand::<D>(cfg)?;
    let dirs = directions::<D>(cfg)?;
    // Validate every row's pattern and estimator before spending time on any.
    for row in &cfg.rows {
        let built = build_pattern(cfg, row)?;
        make_estimator::<D, K>(cfg, &built.pattern, &dirs)?;
    }
    let exact = f.integral();

    let what = format!(
        "{} {}D ({}), {}{}, {}",
        cfg.kind.name(),
        cfg.dims,
        cfg.integrand_desc(),
        cfg.primitive.name(),
        match cfg.primitive {
            Primitive::Points => String::new(),
            Primitive::Segments => format!(" (length {}, {})", cfg.length, cfg.dirs_desc()),
            Primitive::Lines => format!(" ({})", cfg.dirs_desc()),
        },
        cfg.sampler
    );
    for note in &cfg.notes {
        println!("note: {note}");
    }
    println!(
        "convergence: {what}; R = {} realisations per N, seed {}, {} thread(s), homogenised \
         (random toroidal shift per realisation)",
        cfg.realisations, cfg.seed, cfg.threads
    );
    println!("exact integral {exact}");
    println!(
        "{:>8} {:>14} {:>14} {:>8} {:>12} {:>10} {:>12} {:>12}",
        "N", "mean", "exact", "bias z", "variance", "SE(var)", "Var*N", "µs/real."
    );
    let wall = Instant::now();
    let mut done = Vec::with_capacity(cfg.rows.len());
    for &row in &cfg.rows {
        let res = run_row::<D, K>(cfg, row, &*f, &dirs)?;
        let st = &res.stats;
        let d = Done {
            row,
            mean: st.mean(),
            mean_se: st.mean_std_error(),
            var: st.variance(),
            var_se: st.variance_std_error(),
            z: bias_z(st.mean(), exact, st.mean_std_error()),
            us_per_realisation: res.busy.as_secs_f64() * 1e6 / cfg.realisations as f64,
        };
        println!(
            "{:>8} {:>14.10} {:>14.10} {:>+8.2} {:>12.4e} {:>10.2e} {:>12.4e} {:>12.1}",
            row.n,
            d.mean,
            exact,
            d.z,
            d.var,
            d.var_se,
            d.var * row.n as f64,
            d.us_per_realisation
        );
        done.push(d);
    }
    let data: Vec<(f64, f64, f64)> = done
        .iter()
        .map(|d| (d.row.n as f64, d.var, d.var_se))
        .collect();
    let fit = fit_loglog(&data);
    let fit_line = match &fit {
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
    };
    println!("{fit_line}");
    println!("total wall time {:.2} s", wall.elapsed().as_secs_f64());

    let csv = csv(cfg, &done, exact, &fit_line);
    let title = format!(
        "{} {}D, {}, {}, R = {}",
        cfg.kind.name(),
        cfg.dims,
        cfg.primitive.name(),
        cfg.sampler,
        cfg.realisations
    );
    let subtitle = match &fit {
        Some(f) => format!("{what}; slope {:.3} ± {:.3}", f.slope, f.slope_se),
        None => what.clone(),
    };
    let points: Vec<plot::Point> = done
        .iter()
        .map(|d| plot::Point {
            x: d.row.n as f64,
            y: d.var,
            err: d.var_se,
        })
        .collect();
    let svg = plot::svg(&plot::LogLog {
        title: &title,
        subtitle: &subtitle,
        x_label: "N (primitives per realisation)",
        y_label: "variance of the estimate",
        points: &points,
        fit: fit.map(|f| plot::PowerLaw {
            slope: f.slope,
            intercept: f.intercept,
            label: format!("fit: slope {:.3} ± {:.3}", f.slope, f.slope_se),
        }),
        reference_slopes: &REFERENCE_SLOPES,
    });
    let (csv_path, svg_path) = (
        crate::with_ext(&cfg.out, "csv"),
        crate::with_ext(&cfg.out, "svg"),
    );
    output::write_atomic(&[
        (csv_path.clone(), csv.into_bytes()),
        (svg_path.clone(), svg.into_bytes()),
    ])?;
    println!("wrote {} and {}", csv_path.display(), svg_path.display());
    Ok(())
}

fn csv(cfg: &Config, done: &[Done], exact: f64, fit_line: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# {}", cfg.command());
    s.push_str("# homogenised: random toroidal shift per realisation\n");
    let _ = writeln!(
        s,
        "# seeding: row N uses run seed Seed::new(Seed::new({}).stream(N)), realisation r \
         its .realization(r); realisations run in chunks of {CHUNK} merged in order",
        cfg.seed
    );
    for note in &cfg.notes {
        let _ = writeln!(s, "# note: {note}");
    }
    let _ = writeln!(s, "# {fit_line}");
    s.push_str(CSV_HEADER);
    s.push('\n');
    for d in done {
        let _ = writeln!(
            s,
            "{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            d.row.n,
            cfg.realisations,
            d.mean,
            d.mean_se,
            exact,
            d.z,
            d.var,
            d.var_se,
            d.var * d.row.n as f64
        );
    }
    s
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
    fn fit_recovers_a_power_law() {
        let data: Vec<(f64, f64, f64)> = [16.0, 64.0, 256.0, 1024.0]
            .iter()
            .map(|&n: &f64| (n, 3.0 * n.powf(-1.5), 0.1 * 3.0 * n.powf(-1.5)))
            .collect();
        let f = fit_loglog(&data).unwrap();
        assert!((f.slope + 1.5).abs() < 1e-12, "{f:?}");
        assert!((f.intercept - 3f64.ln()).abs() < 1e-12);
        assert!(f.chi2_dof < 1e-20);
        // σ(ln y) = 0.1 for all points: SE = 0.1/√Σ(ln x − x̄)².
        let xs: Vec<f64> = data.iter().map(|d| d.0.ln()).collect();
        let m = xs.iter().sum::<f64>() / 4.0;
        let sxx: f64 = xs.iter().map(|x| (x - m) * (x - m)).sum();
        assert!((f.slope_se - 0.1 / sxx.sqrt()).abs() < 1e-12);
        // Unusable points are skipped.
        assert!(fit_loglog(&[(16.0, 1.0, 0.1), (64.0, 0.0, 0.1)]).is_none());
        assert_eq!(
            fit_loglog(&[
                (16.0, 1.0, 0.1),
                (64.0, 0.5, 0.1),
                (256.0, 0.2, f64::INFINITY)
            ])
            .unwrap()
            .points,
            2
        );
    }

    #[test]
    fn z_scores() {
        assert_eq!(bias_z(1.0, 1.0, 0.0), 0.0);
        assert_eq!(bias_z(1.5, 1.0, 0.25), 2.0);
        assert_eq!(bias_z(0.5, 1.0, 0.0), f64::NEG_INFINITY);
    }
}
