//! `spectrum`: the mean periodogram `⟨N·P(ν)⟩` of a pattern (or of segments or
//! lines through it), or of point sets read from files, averaged over
//! realisations.
//!
//! Everything numeric is a kernel call: patterns from [`crate::sampler`],
//! amplitudes from `linesample::spectrum::Dft`, the mean from `Periodogram`,
//! per-ring standard errors from `RunningStats`. This module reads point
//! files, runs the realisations (in parallel, deterministically) and formats
//! the PNG, the CSV, the SVG plot and the summary.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use clap::{Args, ValueEnum};
use linesample::geom::Direction;
use linesample::primitive::Segment;
use linesample::spectrum::{self, line_offsets, AmplitudeView, Dft, Grid, Periodogram};
use linesample::stats::RunningStats;
use linesample::Seed;

use crate::plot::xml_escape;
use crate::sampler::{self, Sampler, Spec};
use crate::{output, png};
use linesample_lab::pointfile;
use linesample_nufft as nufft;

/// The CSV header.
pub const CSV_HEADER: &str = "radius,mean_np,std_error,count";

/// Default `--realizations`.
const DEFAULT_REALISATIONS: u64 = 16;
/// Default `--length`.
const DEFAULT_LENGTH: f64 = 0.1;
/// Caps of the default `--k` per grid dimension (1D, 2D, 3D).
const DEFAULT_K_CAP: [usize; 3] = [65_536, 1024, 64];
/// Largest grid (stored half-grid cells) the lab accepts: every thread holds
/// about 16 bytes per cell, and so does the accumulator.
const MAX_GRID_CELLS: usize = 1 << 25;
/// The PNG maps `log10 ⟨N·P⟩` from `LOG_MIN` (black) to `LOG_MAX` (white).
const LOG_MIN: f64 = -2.0;
const LOG_MAX: f64 = 1.0;
/// Small images are upscaled by an integer factor to at least this many pixels.
const MIN_IMAGE: usize = 256;
/// Upper bound on the per-chunk scratch of the direct method, in `f64`s.
const SCRATCH_VALUES: usize = 1 << 20;
/// Samples per chunk of the direct method (fewer if the scratch bound needs it).
const CHUNK_SAMPLES: usize = 128;

pub const FORMATS: &str = "\
Input format (--input FILE...): each file is one realisation, a plain text point
file as `patterns` writes it (and UTK and other sampling toolkits read and write):
one point per line, its D coordinates (1 <= D <= 3) separated by spaces or tabs.
D is the number of columns of the first data line; every other data line must
have the same count, and every file the same D. Blank lines and lines starting
with '#' are skipped. Numbers are decimal (e.g. 0.25, 2.5e-1); NaN and infinities
are rejected. If the first data line is a single integer and the next data line
has two or more columns, the first line is a point-count header (as UTK writes)
and is skipped with a note. Coordinates outside [0, 1) are wrapped onto the torus
(x - floor(x)) with a note on stderr. A file without points, a line with a different
column count, or a token that is not a finite number is an error naming the file
and the line.

Output formats:
  PREFIX.png          8-bit grayscale image of the mean <N*P(nu)> on the full frequency
                      grid [-k, k]^2: one pixel per frequency (each side upscaled by the
                      smallest integer that makes it at least 256 pixels), the DC
                      term nu = 0 in the centre, nu_x growing to the right, nu_y
                      upwards. Gray level round(255*(log10(v) + 2)/3) with log10(v)
                      clipped to [-2, 1]: black = 0.01 or less, white noise (1) = 170,
                      white = 10 or more; the DC value (N) is always white. 3D:
                      the central slice nu_z = 0. Lines: the (D-1)-dimensional
                      spectrum of the line offsets (3D lines along --axis A: the
                      two other axes in order). 1D spectra (1D points or segments,
                      2D lines) have no PNG.
  PREFIX-radial.csv   the header
                        radius,mean_np,std_error,count
                      and one row per ring r = 1..k: the ring holds the frequencies
                      with round(|nu|) = r; mean_np is the mean of <N*P> over them,
                      std_error the standard error of that ring mean across the R
                      realisations (from the R per-realisation ring means; inf when
                      R = 1), count the number of frequencies of the full grid in
                      the ring (e.g. 8 for ring 1 in 2D). Numbers use Rust's
                      shortest round-trip formatting (e.g. 9.8765e-1). The CSV holds
                      no timings and no thread count: it is byte-identical for any
                      --threads.
  PREFIX-radial.svg   the ring means against the radius (log y axis) with a +-1 SE
                      band and a dashed reference line at 1 (white noise).

Spectra: the amplitude of one realisation of N samples is F(nu) = sum_k w_k
exp(-2 pi i nu.x_k) with w_k = 1 for points and sinc(L nu.omega) for segments of
length L along omega centred at the points; N*P(nu) = |F(nu)|^2/N (1 for white
noise at nu != 0, N at nu = 0). Lines along axis A through the points have the
spectrum of their offsets (the points with coordinate A dropped) on the
hyperplane nu_A = 0 and 0 off it, so for lines the grid, the rings and the PNG are
(D-1)-dimensional.

The summary printed on stdout gives N, k, R, the time per realisation in
milliseconds (wall time of each realisation, pattern generation included, summed
over all realisations and divided by R, so it does not shrink with --threads), the
mean of <N*P> over all frequencies with rings ceil(k/2)..k (about 1 for most
patterns) and over rings 1..max(1, round(sqrt(N)/4)) (low for blue noise). All
files are written to FILE.tmp, synced and renamed, so a result file is either
complete or absent. Errors print `error: <message>` on stderr and exit with a
non-zero code.";

/// Sample primitives whose spectrum is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Primitive {
    /// The points themselves.
    Points,
    /// Segments of length --length along --direction centred at the points:
    /// the point spectrum times sinc^2(L nu.omega).
    Segments,
    /// Lines along axis --axis through the points: the (D-1)-dimensional
    /// spectrum of their offsets (the points with coordinate --axis dropped).
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

/// How the amplitudes are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Exact direct sum over samples and frequencies (`linesample::spectrum::Dft`):
    /// about N*(cells of the half grid) complex multiply-adds per realisation.
    Direct,
    /// Type-1 non-uniform FFT (`linesample_nufft`: exponential-of-semicircle
    /// spreading, FFT, deconvolution) with relative l2 error at most --tol on the
    /// amplitudes. Points and lines only (segment weights depend on the frequency).
    Nufft,
}

impl Method {
    fn name(self) -> &'static str {
        match self {
            Method::Direct => "direct",
            Method::Nufft => "nufft",
        }
    }
}

/// Default `--tol` of the NUFFT method.
const DEFAULT_TOL: f64 = 1e-9;

/// Options of `linesample-lab spectrum`.
#[derive(Debug, Args)]
pub struct SpectrumArgs {
    /// Sample pattern (required unless --input is given).
    #[arg(
        long,
        value_enum,
        required_unless_present = "input",
        conflicts_with = "input"
    )]
    sampler: Option<Sampler>,

    /// Dimension D of the points, 1 to 3 (multi-jittered and cmj: 2 only;
    /// lines: 2 or 3) [default: 2]. With --input, D is the files' column count.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=3), conflicts_with = "input")]
    dims: Option<u8>,

    /// Number of points N per realisation (default: 1024, or the product of
    /// --strata / --grid when those are given).
    #[arg(short = 'n', value_name = "N", conflicts_with = "input")]
    n: Option<usize>,

    /// Jittered only: strata per axis, one count per dimension, comma-separated
    /// (e.g. 32,32). Without it jittered uses a cubical grid (m^D = N).
    #[arg(
        long,
        value_name = "M1,M2,..",
        value_delimiter = ',',
        conflicts_with = "input"
    )]
    strata: Option<Vec<usize>>,

    /// Multi-jittered and cmj only: grid of COLS x ROWS cells (N = COLS*ROWS).
    #[arg(long, value_name = "COLSxROWS", value_parser = crate::parse_grid, conflicts_with = "input")]
    grid: Option<(usize, usize)>,

    /// Poisson disk only: minimum distance as a fraction of the densest-packing
    /// distance for N points, in (0, 1].
    #[arg(
        long,
        value_name = "R",
        default_value_t = 0.75,
        conflicts_with = "input"
    )]
    relative_radius: f64,

    /// Poisson disk only: use Bridson's algorithm instead of maximal dart
    /// throwing.
    #[arg(long, conflicts_with = "input")]
    bridson: bool,

    /// Seed of the run: realisation r uses the points of
    /// `patterns --seed SEED --realization r`.
    #[arg(long, default_value_t = 1, conflicts_with = "input")]
    seed: u64,

    /// Sample primitive.
    #[arg(long, value_enum, default_value_t = Primitive::Points)]
    primitive: Primitive,

    /// Segments only: segment length, from 0 (points) to 2^20 [default: 0.1].
    #[arg(long, value_name = "L", allow_hyphen_values = true)]
    length: Option<f64>,

    /// Segments only: direction of every segment, D comma-separated components
    /// (normalised) [default: the x axis, 1,0 in 2D].
    #[arg(
        long,
        value_name = "X,Y[,Z]",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    direction: Option<Vec<f64>>,

    /// Lines only: the axis of the lines, 0 to D-1 [default: 0, the x axis].
    #[arg(long, value_name = "A")]
    axis: Option<usize>,

    /// Half-width of the frequency grid [-k, k]^D' (D' = D, or D-1 for lines)
    /// [default: the largest k with 2k+1 <= 10*sqrt(N), at most 65536 in 1D,
    /// 1024 in 2D and 64 in 3D].
    #[arg(long = "k", value_name = "K")]
    k: Option<usize>,

    /// Number of independent realisations R [default: 16].
    #[arg(
        long,
        value_name = "R",
        visible_alias = "realisations",
        conflicts_with = "input"
    )]
    realizations: Option<u64>,

    /// Worker threads [default: the available parallelism]. The output files do
    /// not depend on it.
    #[arg(long, value_name = "T")]
    threads: Option<usize>,

    /// How the amplitudes are computed.
    #[arg(long, value_enum, default_value_t = Method::Direct)]
    method: Method,

    /// NUFFT only: requested relative l2 accuracy of the amplitudes, in
    /// [1e-14, 1e-1] (the accuracy/time knob: see `cargo run --release -p
    /// linesample-nufft --example nufft_bench`) [default: 1e-9].
    #[arg(long, value_name = "EPS")]
    tol: Option<f64>,

    /// Read the point sets from these files instead of a sampler, one
    /// realisation per file (format below).
    #[arg(long, value_name = "FILE", num_args = 1..)]
    input: Vec<PathBuf>,

    /// Output path prefix; writes PREFIX.png, PREFIX-radial.csv and
    /// PREFIX-radial.svg, creating parent directories (default:
    /// `out/spectrum/<sampler or first input's stem>-<D>d-<N>`, with
    /// `-segments` or `-lines` appended for those primitives).
    #[arg(long, value_name = "PREFIX")]
    out: Option<PathBuf>,
}

/// One point file: its points (wrapped into `[0, 1)`), flat.
#[derive(Clone, Debug)]
struct PointFile {
    path: PathBuf,
    coords: Vec<f64>,
}

#[derive(Clone, Debug)]
enum Source {
    Pattern(Spec),
    Files(Vec<PointFile>),
}

/// Everything resolved.
#[derive(Clone, Debug)]
struct Config {
    source: Source,
    /// Dimension of the points.
    dims: usize,
    primitive: Primitive,
    length: f64,
    direction: Vec<f64>,
    axis: usize,
    k: usize,
    realisations: u64,
    /// Points per realisation (the largest, for files).
    n: usize,
    /// For files: the smallest N (equal to `n` for patterns).
    n_min: usize,
    seed: u64,
    threads: usize,
    method: Method,
    /// NUFFT tolerance.
    tol: f64,
    out: PathBuf,
    /// `jittered`, or the first input file's stem.
    label: String,
    detail: Option<String>,
    notes: Vec<String>,
}

impl Config {
    fn primitive_desc(&self) -> String {
        match self.primitive {
            Primitive::Points => "points".into(),
            Primitive::Segments => format!(
                "segments (length {}, direction {})",
                self.length,
                join(&self.direction)
            ),
            Primitive::Lines => format!("lines along axis {}", self.axis),
        }
    }

    fn source_desc(&self) -> String {
        match &self.source {
            Source::Pattern(spec) => format!(
                "{}{}",
                spec.sampler,
                self.detail
                    .as_ref()
                    .map(|d| format!(" ({d})"))
                    .unwrap_or_default()
            ),
            Source::Files(files) if files.len() == 1 => {
                format!("file {}", files[0].path.display())
            }
            Source::Files(files) => format!(
                "{} files ({} .. {})",
                files.len(),
                files[0].path.display(),
                files[files.len() - 1].path.display()
            ),
        }
    }

    fn n_desc(&self) -> String {
        if self.n_min == self.n {
            format!("{}", self.n)
        } else {
            format!("{}..{}", self.n_min, self.n)
        }
    }
}

fn join(v: &[f64]) -> String {
    v.iter().map(f64::to_string).collect::<Vec<_>>().join(",")
}

fn not_for(option: &str, what: &str, got: Primitive) -> String {
    format!(
        "{option} applies only to {what} (got --primitive {})",
        got.name()
    )
}

/// The largest `k` with `2k + 1 ≤ 10·√N`, capped per grid dimension.
pub fn default_k(n: usize, grid_dims: usize) -> usize {
    let limit = 10.0 * (n as f64).sqrt();
    let mut k = ((limit - 1.0) / 2.0).floor().max(1.0) as usize;
    // Guard the floating-point floor in both directions.
    while k > 1 && (2 * k + 1) as f64 > limit {
        k -= 1;
    }
    while ((2 * k + 3) as f64) <= limit {
        k += 1;
    }
    k.min(DEFAULT_K_CAP[grid_dims.clamp(1, 3) - 1])
}

/// Reads one point file (format in [`FORMATS`], parsed by
/// [`pointfile::parse_points`]); returns its dimension, flat coordinates
/// wrapped into `[0, 1)`, and notes.
fn read_points(path: &Path, notes: &mut Vec<String>) -> Result<(usize, Vec<f64>), String> {
    let name = path.display();
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read --input {name}: {e}"))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        format!(
            "{name}: not UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        )
    })?;
    let set = pointfile::parse_points(&text).map_err(|e| match e.line() {
        Some(_) => format!("{name}, {e}"),
        None => format!("{name}: {e}"),
    })?;
    if let Some(h) = set.header {
        notes.push(format!(
            "{name}, line {}: skipped the header line '{}' (a point count, as UTK writes){}",
            h.line,
            h.count,
            if h.count as usize == h.points {
                String::new()
            } else {
                format!("; the file has {} points", h.points)
            }
        ));
    }
    if set.wrapped > 0 {
        notes.push(format!(
            "{name}: wrapped {} coordinate(s) outside [0, 1) onto the torus (x - floor(x))",
            set.wrapped
        ));
    }
    Ok((set.dims, set.coords))
}

fn resolve(a: &SpectrumArgs) -> Result<Config, String> {
    let mut notes = Vec::new();
    let prim = a.primitive;
    let tol = match (a.method, a.tol) {
        (Method::Direct, Some(_)) => {
            return Err("--tol applies to --method nufft only (the direct method is exact)".into())
        }
        (Method::Direct, None) => 0.0,
        (Method::Nufft, t) => {
            let t = t.unwrap_or(DEFAULT_TOL);
            if !(1e-14..=1e-1).contains(&t) {
                return Err(format!("--tol {t}: expected a number in [1e-14, 1e-1]"));
            }
            if prim == Primitive::Segments {
                return Err("--method nufft supports --primitive points and lines; \
                            segment weights sinc(L nu.omega) depend on the frequency: use --method direct"
                    .into());
            }
            t
        }
    };
    let (source, dims, n, n_min, label, detail, realisations) = if a.input.is_empty() {
        let sampler = a.sampler.ok_or("give --sampler or --input (see --help)")?;
        let dims = usize::from(a.dims.unwrap_or(2));
        let spec = Spec {
            sampler,
            dims,
            n: a.n,
            strata: a.strata.clone(),
            grid: a.grid,
            shift: false,
            relative_radius: a.relative_radius,
            dart_throwing: !a.bridson,
        };
        let built = sampler::build(&spec)?;
        let n = built.pattern.len();
        if n == 0 {
            return Err("-n 0: expected at least one point".into());
        }
        let r = a.realizations.unwrap_or(DEFAULT_REALISATIONS);
        if r == 0 {
            return Err("--realizations 0: expected at least 1".into());
        }
        (
            Source::Pattern(spec),
            dims,
            n,
            n,
            sampler.name().to_string(),
            built.detail,
            r,
        )
    } else {
        let mut files = Vec::with_capacity(a.input.len());
        let mut dims = 0;
        for path in &a.input {
            let (d, coords) = read_points(path, &mut notes)?;
            if files.is_empty() {
                dims = d;
            } else if d != dims {
                return Err(format!(
                    "{}: {d} coordinates per point, but {} has {dims}; every --input file must \
                     have the same dimension",
                    path.display(),
                    a.input[0].display()
                ));
            }
            files.push(PointFile {
                path: path.clone(),
                coords,
            });
        }
        let counts = files.iter().map(|f| f.coords.len() / dims);
        let (n_min, n) = counts.fold((usize::MAX, 0), |(lo, hi), c| (lo.min(c), hi.max(c)));
        if n_min != n {
            notes.push(format!(
                "the --input files have {n_min} to {n} points; the default --k and the default \
                 --out use N = {n}"
            ));
        }
        let stem = a.input[0]
            .file_stem()
            .map_or_else(|| "input".into(), |s| s.to_string_lossy().into_owned());
        let r = files.len() as u64;
        (Source::Files(files), dims, n, n_min, stem, None, r)
    };

    if a.length.is_some() && prim != Primitive::Segments {
        return Err(not_for("--length", "--primitive segments", prim));
    }
    if a.direction.is_some() && prim != Primitive::Segments {
        return Err(not_for("--direction", "--primitive segments", prim));
    }
    if a.axis.is_some() && prim != Primitive::Lines {
        return Err(not_for("--axis", "--primitive lines", prim));
    }
    let length = a.length.unwrap_or(DEFAULT_LENGTH);
    let direction = match &a.direction {
        Some(v) if v.len() != dims => {
            return Err(format!(
                "--direction has {} component(s) but the points have {dims} dimension(s): give \
                 {dims} comma-separated numbers",
                v.len()
            ))
        }
        Some(v) => v.clone(),
        None => {
            let mut v = vec![0.0; dims];
            v[0] = 1.0;
            v
        }
    };
    let axis = a.axis.unwrap_or(0);
    if prim == Primitive::Lines {
        if dims < 2 {
            return Err(format!(
                "--primitive lines needs points of dimension 2 or 3 (lines along --axis through \
                 the points); got {dims}"
            ));
        }
        if axis >= dims {
            return Err(format!(
                "--axis {axis}: expected 0 to {} for {dims}D points",
                dims - 1
            ));
        }
    }
    let grid_dims = if prim == Primitive::Lines {
        dims - 1
    } else {
        dims
    };
    let k = a.k.unwrap_or_else(|| default_k(n, grid_dims));
    let threads = match a.threads {
        Some(0) => return Err("--threads 0: expected at least 1".into()),
        Some(t) => t,
        None => std::thread::available_parallelism().map_or(1, usize::from),
    };
    let threads = usize::try_from(realisations).map_or(threads, |r| threads.min(r).max(1));
    let out = match &a.out {
        Some(p) => p.clone(),
        None => {
            let suffix = match prim {
                Primitive::Points => "",
                Primitive::Segments => "-segments",
                Primitive::Lines => "-lines",
            };
            PathBuf::from("out/spectrum").join(format!("{label}-{dims}d-{n}{suffix}"))
        }
    };
    if out.file_name().is_none() {
        return Err(format!(
            "--out {}: expected a file prefix such as out/spec, not a directory",
            out.display()
        ));
    }
    Ok(Config {
        source,
        dims,
        primitive: prim,
        length,
        direction,
        axis,
        k,
        realisations,
        n,
        n_min,
        seed: a.seed,
        threads,
        method: a.method,
        tol,
        out,
        label,
        detail,
        notes,
    })
}

/// Entry point of the subcommand.
pub fn run(a: &SpectrumArgs) -> Result<(), String> {
    let cfg = resolve(a)?;
    match (cfg.dims, cfg.primitive == Primitive::Lines) {
        (1, false) => run_dims::<1, 1>(&cfg, false),
        (2, false) => run_dims::<2, 2>(&cfg, false),
        (3, false) => run_dims::<3, 3>(&cfg, false),
        (2, true) => run_dims::<2, 1>(&cfg, false),
        (3, true) => run_dims::<3, 2>(&cfg, false),
        (d, _) => Err(format!("internal error: dimension {d}")),
    }
    .map(|_| ())
}

/// What the workers share. Realisations are claimed in order from `next` and
/// handed to `merge`, which adds them in realisation order, so the results do
/// not depend on the thread count or on timing.
struct Job<'a, const E: usize> {
    cfg: &'a Config,
    grid: Grid<E>,
    dir: Option<Direction<E>>,
    next: AtomicU64,
    stop: AtomicBool,
    merge: Mutex<Merge<E>>,
}

/// The ordered accumulator.
struct Merge<const E: usize> {
    /// The next realisation to add.
    next: u64,
    /// Finished realisations waiting for their predecessors: amplitudes and
    /// ring means.
    pending: BTreeMap<u64, (Amplitudes<E>, Vec<f64>)>,
    /// Amplitude buffers to reuse.
    spare: Vec<Dft<E, Vec<f64>>>,
    total: Periodogram<E, Vec<f64>>,
    /// Per ring, the per-realisation ring means.
    rings: Vec<RunningStats>,
    busy: Duration,
}

/// One realisation's amplitudes: the kernel's exact accumulator, or the
/// NUFFT's half-grid arrays.
enum Amplitudes<const E: usize> {
    Direct(Dft<E, Vec<f64>>),
    Nufft(spectrum::Amplitudes<E, Vec<f64>>),
}

impl<const E: usize> Merge<E> {
    fn drain(&mut self) -> Result<(), String> {
        while let Some((amps, ring)) = self.pending.remove(&self.next) {
            let added = match &amps {
                Amplitudes::Direct(dft) => self.total.add(dft),
                Amplitudes::Nufft(amps) => self.total.add(amps),
            };
            added.map_err(|e| format!("realisation {}: {e}", self.next))?;
            for (s, &v) in self.rings.iter_mut().zip(&ring) {
                s.push(v);
            }
            self.next += 1;
            if let Amplitudes::Direct(dft) = amps {
                self.spare.push(dft);
            }
        }
        Ok(())
    }
}

fn lock<T>(m: &Mutex<T>) -> Result<std::sync::MutexGuard<'_, T>, String> {
    m.lock()
        .map_err(|_| "internal error: a worker thread panicked".to_string())
}

/// The points of realisation `r`.
fn realisation_points<const D: usize>(
    cfg: &Config,
    pattern: Option<&sampler::Built>,
    r: u64,
) -> Result<Vec<[f64; D]>, String> {
    let to_points = |flat: &mut dyn Iterator<Item = f64>, n: usize| {
        let mut v = Vec::with_capacity(n);
        let mut p = [0.0; D];
        for (i, x) in flat.enumerate() {
            p[i % D] = x;
            if i % D == D - 1 {
                v.push(p);
            }
        }
        v
    };
    match (&cfg.source, pattern) {
        (Source::Pattern(_), Some(built)) => {
            let seed = Seed::new(cfg.seed).realization(r);
            let (pts, _) = built.pattern.generate(seed, 1)?;
            if pts.dims != D {
                return Err("internal error: pattern of the wrong dimension".into());
            }
            let n = pts.len();
            Ok(to_points(&mut pts.coords.iter().map(|&x| f64::from(x)), n))
        }
        (Source::Files(files), _) => {
            let f = usize::try_from(r)
                .ok()
                .and_then(|i| files.get(i))
                .ok_or("internal error: realisation without a file")?;
            Ok(to_points(&mut f.coords.iter().copied(), f.coords.len() / D))
        }
        (Source::Pattern(_), None) => Err("internal error: no pattern".into()),
    }
}

/// The `E`-dim sample coordinates of one realisation: the points, or the line
/// offsets (points with the line axis dropped).
fn sample_coords<const D: usize, const E: usize>(
    cfg: &Config,
    pts: &[[f64; D]],
    buf: &mut Vec<[f64; E]>,
) -> Result<(), String> {
    buf.clear();
    buf.resize(pts.len(), [0.0; E]);
    match cfg.primitive {
        Primitive::Lines => line_offsets::<D, E, f64>(pts, cfg.axis, buf)
            .map_err(|e| format!("--primitive lines: {e}")),
        _ => {
            for (o, p) in buf.iter_mut().zip(pts) {
                o.copy_from_slice(&p[..E]);
            }
            Ok(())
        }
    }
}

/// Adds one realisation's samples to `dft` (cleared first).
fn add_samples<const D: usize, const E: usize>(
    job: &Job<'_, E>,
    pts: &[[f64; D]],
    dft: &mut Dft<E, Vec<f64>>,
    buf: &mut Vec<[f64; E]>,
    scratch: &mut [f64],
) -> Result<(), String> {
    let cfg = job.cfg;
    dft.clear();
    buf.clear();
    buf.resize(pts.len(), [0.0; E]);
    let what = |e: linesample::SpectrumError| format!("--primitive {}: {e}", cfg.primitive.name());
    match cfg.primitive {
        Primitive::Points | Primitive::Segments => {
            if D != E {
                return Err("internal error: grid of the wrong dimension".into());
            }
            for (o, p) in buf.iter_mut().zip(pts) {
                o.copy_from_slice(&p[..E]);
            }
            match (cfg.primitive, &job.dir) {
                (Primitive::Segments, Some(dir)) => dft
                    .add_segment_pattern(buf, dir, cfg.length, scratch)
                    .map_err(what),
                _ => dft.add_points(buf, scratch).map_err(what),
            }
        }
        Primitive::Lines => {
            line_offsets::<D, E, f64>(pts, cfg.axis, buf).map_err(what)?;
            dft.add_points(buf, scratch).map_err(what)
        }
    }
}

/// One thread: its own pattern, amplitudes and scratch; takes realisations
/// until none are left.
fn worker<const D: usize, const E: usize>(job: &Job<'_, E>) -> Result<(), String> {
    let cfg = job.cfg;
    let built = match &cfg.source {
        Source::Pattern(spec) => Some(sampler::build(spec)?),
        Source::Files(_) => None,
    };
    let per = if cfg.primitive == Primitive::Segments {
        Dft::<E, Vec<f64>>::segments_scratch_per_sample(job.grid)
    } else {
        Dft::<E, Vec<f64>>::points_scratch_per_sample(job.grid)
    };
    let chunk = (SCRATCH_VALUES / per).clamp(1, CHUNK_SAMPLES);
    let mut scratch = vec![0.0; chunk * per];
    let mut dft = Dft::<E, Vec<f64>>::new_vec(job.grid);
    let mut buf: Vec<[f64; E]> = Vec::new();
    let mut count = vec![0u64; cfg.k + 1];
    job.grid
        .ring_counts(&mut count)
        .map_err(|e| e.to_string())?;
    let mut plan = match cfg.method {
        Method::Direct => None,
        Method::Nufft => Some(
            nufft::Plan::<E>::new_for_points(cfg.k, cfg.tol, cfg.n)
                .map_err(|e| format!("--method nufft: {e}"))?,
        ),
    };
    while !job.stop.load(Ordering::Relaxed) {
        let r = job.next.fetch_add(1, Ordering::Relaxed);
        if r >= cfg.realisations {
            break;
        }
        let t = Instant::now();
        let mut ring = vec![0.0; cfg.k + 1];
        let step =
            realisation_points::<D>(cfg, built.as_ref(), r).and_then(|pts| match &mut plan {
                None => {
                    add_samples::<D, E>(job, &pts, &mut dft, &mut buf, &mut scratch)?;
                    dft.radial_power(&mut ring, &mut count)
                        .map_err(|e| e.to_string())?;
                    Ok(None)
                }
                Some(plan) => {
                    sample_coords::<D, E>(cfg, &pts, &mut buf)?;
                    let mut amps = spectrum::Amplitudes::new_vec(job.grid);
                    plan.transform_into(&buf, &mut amps)
                        .map_err(|e| format!("--method nufft: {e}"))?;
                    if amps.count() == 0 {
                        return Err("no points".into());
                    }
                    amps.radial_power(&mut ring, &mut count)
                        .map_err(|e| e.to_string())?;
                    Ok(Some(Amplitudes::Nufft(amps)))
                }
            });
        if let Err(e) = &step {
            job.stop.store(true, Ordering::Relaxed);
            return Err(match &cfg.source {
                Source::Files(files) => format!("{}: {e}", files[r as usize].path.display()),
                Source::Pattern(_) => format!("realisation {r}: {e}"),
            });
        }
        let busy = t.elapsed();
        let mut m = lock(&job.merge)?;
        m.busy += busy;
        let amps = match step {
            Ok(Some(amps)) => amps,
            _ => {
                let next = m.spare.pop().unwrap_or_else(|| Dft::new_vec(job.grid));
                Amplitudes::Direct(std::mem::replace(&mut dft, next))
            }
        };
        m.pending.insert(r, (amps, ring));
        if let Err(e) = m.drain() {
            job.stop.store(true, Ordering::Relaxed);
            return Err(e);
        }
    }
    Ok(())
}

/// The results of all realisations.
struct Results<const E: usize> {
    total: Periodogram<E, Vec<f64>>,
    /// Rings `0..=k`: mean of `⟨N·P⟩`, standard error, count.
    mean: Vec<f64>,
    se: Vec<f64>,
    count: Vec<u64>,
    busy: Duration,
}

fn compute<const D: usize, const E: usize>(cfg: &Config) -> Result<Results<E>, String> {
    let grid = Grid::<E>::new(cfg.k).map_err(|e| format!("--k {}: {e}", cfg.k))?;
    if grid.len() > MAX_GRID_CELLS {
        return Err(format!(
            "--k {}: the {E}D grid has {} stored cells (above the lab's limit of {MAX_GRID_CELLS}, \
             about 16 bytes each per thread); lower --k",
            cfg.k,
            grid.len()
        ));
    }
    let dir = if cfg.primitive == Primitive::Segments {
        let mut v = [0.0; E];
        v.copy_from_slice(&cfg.direction[..E]);
        let d = Direction::<E>::new(v)
            .map_err(|e| format!("--direction {}: {e}", join(&cfg.direction)))?;
        Segment::<E>::new([0.5; E], d, cfg.length)
            .map_err(|e| format!("--length {}: {e}", cfg.length))?;
        Some(d)
    } else {
        None
    };
    let job = Job {
        cfg,
        grid,
        dir,
        next: AtomicU64::new(0),
        stop: AtomicBool::new(false),
        merge: Mutex::new(Merge {
            next: 0,
            pending: BTreeMap::new(),
            spare: Vec::new(),
            total: Periodogram::new_vec(grid),
            rings: vec![RunningStats::new(); cfg.k + 1],
            busy: Duration::ZERO,
        }),
    };
    let results: Vec<Result<(), String>> = if cfg.threads <= 1 {
        vec![worker::<D, E>(&job)]
    } else {
        std::thread::scope(|s| {
            let handles: Vec<_> = (0..cfg.threads)
                .map(|_| s.spawn(|| worker::<D, E>(&job)))
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
    for r in results {
        r?;
    }
    let m = job
        .merge
        .into_inner()
        .map_err(|_| "internal error: a worker thread panicked".to_string())?;
    if m.next != cfg.realisations || !m.pending.is_empty() {
        return Err("internal error: missing realisations".into());
    }
    let mut mean = vec![0.0; cfg.k + 1];
    let mut count = vec![0u64; cfg.k + 1];
    m.total
        .radial_average(&mut mean, &mut count)
        .map_err(|e| e.to_string())?;
    let se = m.rings.iter().map(RunningStats::mean_std_error).collect();
    Ok(Results {
        total: m.total,
        mean,
        se,
        count,
        busy: m.busy,
    })
}

/// Mean of `⟨N·P⟩` over all frequencies of rings `lo..=hi`.
fn band_mean(mean: &[f64], count: &[u64], lo: usize, hi: usize) -> f64 {
    let (mut s, mut c) = (0.0, 0u64);
    for r in lo..=hi.min(mean.len() - 1) {
        s += mean[r] * count[r] as f64;
        c += count[r];
    }
    if c == 0 {
        f64::NAN
    } else {
        s / c as f64
    }
}

/// What a run measured, for callers that make their own tables (the gallery).
#[derive(Clone, Debug)]
pub struct Summary {
    /// Mean `⟨N·P⟩` over rings `⌈k/2⌉..k`.
    pub high: f64,
    /// Mean `⟨N·P⟩` over rings `1..round(√N/4)`.
    pub low: f64,
    /// Milliseconds per realisation.
    pub ms: f64,
}

/// The spectrum of `R` realisations of a sampler's points on the default grid
/// (NUFFT, tolerance 1e-9), written to `out` (`PREFIX.png`,
/// `PREFIX-radial.csv`, `PREFIX-radial.svg`) without printing: the gallery's
/// spectra.
pub fn pattern_spectrum(
    spec: &Spec,
    seed: u64,
    realisations: u64,
    threads: usize,
    out: PathBuf,
) -> Result<Summary, String> {
    let n = sampler::build(spec)?.pattern.len();
    let cfg = Config {
        source: Source::Pattern(spec.clone()),
        dims: spec.dims,
        primitive: Primitive::Points,
        length: 0.0,
        direction: Vec::new(),
        axis: 0,
        k: default_k(n, spec.dims),
        realisations,
        n,
        n_min: n,
        seed,
        threads: threads.max(1),
        method: Method::Nufft,
        tol: DEFAULT_TOL,
        out,
        label: spec.sampler.name().to_string(),
        detail: None,
        notes: Vec::new(),
    };
    match cfg.dims {
        1 => run_dims::<1, 1>(&cfg, true),
        2 => run_dims::<2, 2>(&cfg, true),
        3 => run_dims::<3, 3>(&cfg, true),
        d => Err(format!("internal error: dimension {d}")),
    }
}

fn run_dims<const D: usize, const E: usize>(cfg: &Config, quiet: bool) -> Result<Summary, String> {
    let say = |line: &str| {
        if !quiet {
            println!("{line}");
        }
    };
    for note in &cfg.notes {
        eprintln!("note: {note}");
    }
    let wall = Instant::now();
    let res = compute::<D, E>(cfg)?;
    let wall = wall.elapsed();
    let k = cfg.k;
    let side = 2 * k + 1;
    let grid_desc = vec![side.to_string(); E].join("x");
    say(&format!(
        "spectrum: {} {}D, {}; N = {}, k = {k} ({E}D grid {grid_desc}), R = {} realisation(s){}, \
         method {}, {} thread(s)",
        cfg.source_desc(),
        cfg.dims,
        cfg.primitive_desc(),
        cfg.n_desc(),
        cfg.realisations,
        match cfg.source {
            Source::Pattern(_) => format!(", seed {}", cfg.seed),
            Source::Files(_) => String::new(),
        },
        match cfg.method {
            Method::Direct => cfg.method.name().to_string(),
            Method::Nufft => format!("nufft (tol {:e})", cfg.tol),
        },
        cfg.threads
    ));
    let (hi_lo, low_hi) = (
        k.div_ceil(2).max(1),
        ((cfg.n as f64).sqrt() / 4.0).round().max(1.0) as usize,
    );
    let low_hi = low_hi.min(k);
    let high = band_mean(&res.mean, &res.count, hi_lo, k);
    let low = band_mean(&res.mean, &res.count, 1, low_hi);
    let ms = res.busy.as_secs_f64() * 1e3 / cfg.realisations as f64;
    let high_h = format!("<N*P> rings {hi_lo}..{k}");
    let low_h = format!("<N*P> rings 1..{low_hi}");
    say(&format!(
        "{:>10} {:>6} {:>6} {:>12} {:>w1$} {:>w2$}",
        "N",
        "k",
        "R",
        "ms/real.",
        high_h,
        low_h,
        w1 = high_h.len().max(10),
        w2 = low_h.len().max(10)
    ));
    say(&format!(
        "{:>10} {:>6} {:>6} {:>12.2} {:>w1$.4} {:>w2$.4}",
        cfg.n_desc(),
        k,
        cfg.realisations,
        ms,
        high,
        low,
        w1 = high_h.len().max(10),
        w2 = low_h.len().max(10)
    ));
    say(&format!("total wall time {:.2} s", wall.as_secs_f64()));

    let mut csv = String::with_capacity(64 * (k + 1));
    csv.push_str(CSV_HEADER);
    csv.push('\n');
    for r in 1..=k {
        let _ = writeln!(
            csv,
            "{r},{:e},{:e},{}",
            res.mean[r], res.se[r], res.count[r]
        );
    }
    let title = format!(
        "{} {}D {}, N = {}, R = {}",
        cfg.label,
        cfg.dims,
        cfg.primitive.name(),
        cfg.n_desc(),
        cfg.realisations
    );
    let subtitle = format!(
        "{}; {}; radial average of <N·P> over rings of unit width, k = {k}",
        cfg.source_desc(),
        cfg.primitive_desc()
    );
    let svg = radial_svg(&title, &subtitle, &res.mean, &res.se, k);
    let csv_path = suffixed(&cfg.out, "-radial.csv");
    let svg_path = suffixed(&cfg.out, "-radial.svg");
    let mut files = vec![
        (csv_path.clone(), csv.into_bytes()),
        (svg_path.clone(), svg.into_bytes()),
    ];
    let png_path = crate::with_ext(&cfg.out, "png");
    if E >= 2 {
        let (w, px) = image(&res.total, k);
        files.insert(0, (png_path.clone(), png::grayscale(w, w, &px)));
    }
    output::write_atomic(&files)?;
    if E >= 2 {
        say(&format!(
            "wrote {}, {} and {}",
            png_path.display(),
            csv_path.display(),
            svg_path.display()
        ));
    } else {
        say(&format!(
            "wrote {} and {} (no PNG: the spectrum is 1D)",
            csv_path.display(),
            svg_path.display()
        ));
    }
    Ok(Summary { high, low, ms })
}

/// `PREFIX` + `suffix` (e.g. `-radial.csv`).
fn suffixed(prefix: &Path, suffix: &str) -> PathBuf {
    let mut s = prefix.as_os_str().to_os_string();
    s.push(suffix);
    PathBuf::from(s)
}

/// Gray level of `⟨N·P⟩ = v` (see [`FORMATS`]).
fn gray(v: f64) -> u8 {
    if v.is_nan() || v <= 0.0 {
        return 0;
    }
    let l = v.log10().clamp(LOG_MIN, LOG_MAX);
    ((l - LOG_MIN) / (LOG_MAX - LOG_MIN) * 255.0).round() as u8
}

/// The `[−k, k]²` image (`E = 2`) or its `ν_2 = 0` slice (`E = 3`): side in
/// pixels and the pixels, `ν_1 = k` in the top row.
fn image<const E: usize>(p: &Periodogram<E, Vec<f64>>, k: usize) -> (usize, Vec<u8>) {
    let side = 2 * k + 1;
    let scale = MIN_IMAGE.div_ceil(side).max(1);
    let w = side * scale;
    let mut px = vec![0u8; w * w];
    let ki = k as i32;
    for row in 0..side {
        let y = ki - row as i32;
        for col in 0..side {
            let x = col as i32 - ki;
            let mut j = [0i32; E];
            j[0] = x;
            j[1] = y;
            let g = if x == 0 && y == 0 {
                255
            } else {
                gray(p.mean(j).unwrap_or(0.0))
            };
            for dy in 0..scale {
                let start = (row * scale + dy) * w + col * scale;
                px[start..start + scale].fill(g);
            }
        }
    }
    (w, px)
}

/// A "nice" tick step (1, 2 or 5 times a power of ten) giving at most about
/// `max_ticks` intervals over `span`.
fn tick_step(span: f64, max_ticks: f64) -> f64 {
    let raw = (span / max_ticks).max(1.0);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

/// The radial average plot: ring means (rings `1..=k`) with a ±1 SE band on a
/// log y axis, and the white-noise reference at 1.
fn radial_svg(title: &str, subtitle: &str, mean: &[f64], se: &[f64], k: usize) -> String {
    const W: f64 = 760.0;
    const H: f64 = 500.0;
    const LEFT: f64 = 80.0;
    const RIGHT: f64 = 190.0;
    const TOP: f64 = 70.0;
    const BOTTOM: f64 = 60.0;
    let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
    let rings: Vec<usize> = (1..=k).collect();
    let mut lo = 0.0f64; // log10 of the white-noise line
    let mut hi = 0.0f64;
    for &r in &rings {
        for v in [mean[r], mean[r] + se[r], mean[r] - se[r]] {
            if v > 0.0 && v.is_finite() {
                lo = lo.min(v.log10());
                hi = hi.max(v.log10());
            }
        }
    }
    let (y1, y0) = (
        hi.ceil().max(1.0),
        lo.floor().max(hi.ceil() - 8.0).min(-1.0),
    );
    let x1 = k.max(1) as f64;
    let sx = |r: f64| LEFT + r / x1 * pw;
    let sy = |v: f64| {
        let l = if v > 0.0 { v.log10().max(y0) } else { y0 };
        TOP + ph - (l - y0) / (y1 - y0) * ph
    };

    let mut s = String::with_capacity(4096 + 40 * k);
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#fff"/>"##);
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="26" text-anchor="middle" font-size="16">{}</text>"#,
        W / 2.0,
        xml_escape(title)
    );
    let _ = writeln!(
        s,
        r##"<text x="{:.1}" y="48" text-anchor="middle" fill="#444" font-size="11">{}</text>"##,
        W / 2.0,
        xml_escape(subtitle)
    );
    let _ = writeln!(
        s,
        r#"<defs><clipPath id="area"><rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}"/></clipPath></defs>"#
    );
    // Vertical grid and radius ticks.
    let step = tick_step(x1, 8.0);
    let mut t = 0.0;
    while t <= x1 + 1e-9 {
        let x = sx(t);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{t}</text>"##,
            TOP + ph,
            TOP + ph + 20.0
        );
        t += step;
    }
    // Decades.
    let mut d = y0;
    while d <= y1 + 0.5 {
        let y = sy(10f64.powf(d));
        let label = format!("{d}").replace('-', "\u{2212}");
        let _ = writeln!(
            s,
            r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">10<tspan dy="-6" font-size="10">{label}</tspan></text>"##,
            LEFT + pw,
            LEFT - 8.0,
            y + 4.0
        );
        d += 1.0;
    }
    let _ = writeln!(
        s,
        r##"<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="#000"/>"##
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">radius |ν| (ring r: round(|ν|) = r)</text>"#,
        LEFT + pw / 2.0,
        H - 14.0
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(22 {:.1}) rotate(-90)" text-anchor="middle">ring mean of ⟨N·P(ν)⟩</text>"#,
        TOP + ph / 2.0
    );
    // ±1 SE band.
    let finite: Vec<usize> = rings
        .iter()
        .copied()
        .filter(|&r| se[r].is_finite() && mean[r].is_finite())
        .collect();
    if !finite.is_empty() {
        let mut pts = String::new();
        for &r in &finite {
            let _ = write!(pts, "{:.1},{:.1} ", sx(r as f64), sy(mean[r] + se[r]));
        }
        for &r in finite.iter().rev() {
            let _ = write!(pts, "{:.1},{:.1} ", sx(r as f64), sy(mean[r] - se[r]));
        }
        let _ = writeln!(
            s,
            r##"<polygon points="{}" fill="#9db7e0" fill-opacity="0.6" stroke="none" clip-path="url(#area)"/>"##,
            pts.trim_end()
        );
    }
    // White-noise reference.
    let _ = writeln!(
        s,
        r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#c0392b" stroke-width="1.2" stroke-dasharray="6 4"/>"##,
        LEFT + pw,
        y = sy(1.0)
    );
    // Ring means: one polyline per run of positive values.
    let mut runs: Vec<Vec<usize>> = vec![Vec::new()];
    for &r in &rings {
        if mean[r] > 0.0 && mean[r].is_finite() {
            if let Some(v) = runs.last_mut() {
                v.push(r);
            }
        } else if runs.last().is_some_and(|v| !v.is_empty()) {
            runs.push(Vec::new());
        }
    }
    for run in runs.iter().filter(|v| !v.is_empty()) {
        let pts: Vec<String> = run
            .iter()
            .map(|&r| format!("{:.1},{:.1}", sx(r as f64), sy(mean[r])))
            .collect();
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#1f4e99" stroke-width="1.5" clip-path="url(#area)"/>"##,
            pts.join(" ")
        );
    }
    // Legend.
    let lx = LEFT + pw + 16.0;
    let ly = TOP + 10.0;
    let _ = writeln!(
        s,
        r##"<line x1="{lx:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#1f4e99" stroke-width="1.5"/><text x="{:.1}" y="{ly:.1}">ring mean</text>"##,
        ly - 4.0,
        lx + 20.0,
        ly - 4.0,
        lx + 26.0
    );
    let _ = writeln!(
        s,
        r##"<rect x="{lx:.1}" y="{:.1}" width="20" height="10" fill="#9db7e0" fill-opacity="0.6"/><text x="{:.1}" y="{:.1}">± 1 SE</text>"##,
        ly + 13.0,
        lx + 26.0,
        ly + 22.0
    );
    let _ = writeln!(
        s,
        r##"<line x1="{lx:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#c0392b" stroke-width="1.2" stroke-dasharray="6 4"/><text x="{:.1}" y="{:.1}">white noise (1)</text>"##,
        ly + 40.0,
        lx + 20.0,
        ly + 40.0,
        lx + 26.0,
        ly + 44.0
    );
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_half_width() {
        // 2k+1 ≤ 10·√N: N = 4096 → 639 → k = 319.
        assert_eq!(default_k(4096, 2), 319);
        assert_eq!(default_k(1024, 2), 159);
        assert_eq!(default_k(100, 2), 49); // 2·49+1 = 99 ≤ 100
        assert_eq!(default_k(1, 2), 4);
        assert_eq!(default_k(4096, 3), 64);
        assert_eq!(default_k(1 << 24, 2), 1024);
    }

    #[test]
    fn gray_levels() {
        assert_eq!(gray(0.0), 0);
        assert_eq!(gray(0.01), 0);
        assert_eq!(gray(1.0), 170);
        assert_eq!(gray(10.0), 255);
        assert_eq!(gray(1e9), 255);
        assert_eq!(gray(f64::NAN), 0);
    }

    #[test]
    fn ticks() {
        assert_eq!(tick_step(319.0, 8.0), 50.0);
        assert_eq!(tick_step(8.0, 8.0), 1.0);
        assert_eq!(tick_step(64.0, 8.0), 10.0);
    }

    #[test]
    fn plot_is_well_formed() {
        let mean = [1.0, 0.0, 0.5, 1.2, 1.0];
        let se = [0.0, 0.1, 0.1, f64::INFINITY, 0.05];
        let s = radial_svg("a < b", "s", &mean, &se, 4);
        assert!(s.starts_with("<?xml") && s.ends_with("</svg>\n"));
        assert!(s.contains("a &lt; b"));
        // Ring 1 is 0 (not drawable): the line starts at ring 2.
        assert_eq!(s.matches("<polyline ").count(), 1);
    }
}
