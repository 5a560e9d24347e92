//! `spectrum`: the mean periodogram `⟨N·P(ν)⟩` of a pattern (or of segments or
//! lines through it), or of point sets read from files, averaged over
//! realisations.
//!
//! Everything numeric is a kernel call (or the `linesample-nufft` crate):
//! patterns from [`crate::sampler`], exact amplitudes from
//! `linesample::spectrum::Dft`, NUFFT amplitudes into the kernel's
//! `Amplitudes`, both read through the one `AmplitudeView` (power, ring means);
//! the mean from `Periodogram`, per-ring standard errors from `RunningStats`.
//! A cell is a block of consecutive realisations; its state is the block's
//! periodogram sums and every realisation's ring means, merged in realisation
//! order.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::ValueEnum;
use linesample::geom::Direction;
use linesample::num::frac;
use linesample::pattern::{Pattern, Shifted};
use linesample::primitive::Segment;
use linesample::spectrum::{line_offsets, AmplitudeView, Amplitudes, Dft, Grid, Periodogram};
use linesample::stats::RunningStats;
use linesample::Seed;
use linesample_nufft as nufft;
use serde::{Deserialize, Serialize};

use crate::experiments::{config_from, file_name, merge_to_files, OutputManifest};
use crate::figures::{self, image};
use crate::integrand::join;
use crate::io::{self, buffer, table, FileGroup};
use crate::pointfile;
use crate::runner::{CellInfo, Ctx, Experiment, RunInfo};
use crate::sampler::{self, PatternSpec};
use crate::spec::MergeRequest;
use crate::spec::{Primitive, ShiftMode};
use crate::with_dims;
use crate::{LabError, Result};

/// The experiment's name.
pub const KIND: &str = "spectrum";

/// The radial CSV header.
pub const CSV_HEADER: &str = "radius,mean_np,std_error,count";

/// Default `--realizations`.
pub const DEFAULT_REALISATIONS: u64 = 16;
/// Default `--length`.
pub(crate) const DEFAULT_LENGTH: f64 = 0.1;
/// Default `--tol` of the NUFFT method.
pub const DEFAULT_TOL: f64 = 1e-9;
/// Caps of the default `--k` per grid dimension (1D, 2D, 3D).
const DEFAULT_K_CAP: [usize; 3] = [65_536, 1024, 64];
/// Largest grid (stored half-grid cells) the lab accepts: every cell in flight
/// holds about 32 bytes per grid cell.
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
/// At most this many cells (blocks of realisations).
const MAX_CELLS: u64 = 8;

/// The `spectrum` input and output formats (its `--help`).
pub const FORMATS: &str = concat!(
    "\
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
and the line. The manifest records each file's path, point count and CRC-32, so a
rerun after a file changed is refused instead of mixing the two.

Output formats:
  OUT/spectrum.png   8-bit grayscale image of the mean <N*P(nu)> on the full frequency
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
  OUT/spectrum-radial.csv
                      the header
                        radius,mean_np,std_error,count
                      and one row per ring r = 1..k: the ring holds the frequencies
                      with round(|nu|) = r; mean_np is the mean of <N*P> over them,
                      std_error the standard error of that ring mean across the R
                      realisations (from the R per-realisation ring means; inf when
                      R = 1), count the number of frequencies of the full grid in
                      the ring (e.g. 8 for ring 1 in 2D). Numbers use Rust's
                      shortest round-trip formatting (e.g. 9.8765e-1). The CSV holds
                      no timings and no thread count: it is byte-identical for any
                      --threads, and for a sharded run merged with `merge`.
  OUT/spectrum-radial.svg
                      the ring means against the radius (log y axis) with a +-1 SE
                      band and a dashed reference line at 1 (white noise).
  OUT/manifest.json   the manifest: command, configuration, version, timings.

Spectra: the amplitude of one realisation of N samples is F(nu) = sum_k w_k
exp(-2 pi i nu.x_k) with w_k = 1 for points and sinc(L nu.omega) for segments of
length L along omega centred at the points; N*P(nu) = |F(nu)|^2/N (1 for white
noise at nu != 0, N at nu = 0). Lines along axis A through the points have the
spectrum of their offsets (the points with coordinate A dropped) on the
hyperplane nu_A = 0 and 0 off it, so for lines the grid, the rings and the PNG are
(D-1)-dimensional. --shift random adds realisation r's toroidal shift (that of
`patterns --shift --realization r`) to the samples in f64 before the transform;
|F|^2 does not change under a shift, so spectra agree with --shift none up to
rounding.

The summary printed on stdout gives N, k, R, the time per realisation in
milliseconds (wall time of each realisation, pattern generation included, summed
over all realisations and divided by R, so it does not shrink with --threads), the
mean of <N*P> over all frequencies with rings ceil(k/2)..k (about 1 for most
patterns) and over rings 1..max(1, round(sqrt(N)/4)) (low for blue noise).

Runs: cells are blocks of ceil(R/8) realisations, kept in OUT.state/ (resume,
--fresh, --shard, merge: see `linesample-lab --help`).

",
    crate::files_note!()
);

/// How the amplitudes are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Exact direct sum over samples and frequencies (`linesample::spectrum::Dft`):
    /// about N*(cells of the half grid) complex multiply-adds per realisation.
    Direct,
    /// Type-1 non-uniform FFT (`linesample-nufft`: exponential-of-semicircle
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

/// One input file as the configuration records it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FileSpec {
    pub path: String,
    pub points: usize,
    /// CRC-32 of the file's bytes.
    pub crc32: u32,
}

/// Where the points come from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Source {
    Pattern(PatternSpec),
    Files(Vec<FileSpec>),
}

/// A spectrum experiment, every parameter resolved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    pub source: Source,
    /// Dimension of the points.
    pub dims: usize,
    pub primitive: Primitive,
    pub length: f64,
    pub direction: Vec<f64>,
    pub axis: usize,
    pub k: usize,
    pub realisations: u64,
    /// Points per realisation (the largest, for files).
    pub n: usize,
    /// For files: the smallest N (equal to `n` for patterns).
    pub n_min: usize,
    pub seed: u64,
    pub shift: ShiftMode,
    pub method: Method,
    /// NUFFT tolerance (0 for the direct method).
    pub tol: f64,
    /// The sampler, or the first input file's stem.
    pub label: String,
    pub detail: Option<String>,
    pub notes: Vec<String>,
}

impl Config {
    /// Dimension of the frequency grid: D, or D − 1 for lines.
    #[must_use]
    pub fn grid_dims(&self) -> usize {
        if self.primitive == Primitive::Lines {
            self.dims - 1
        } else {
            self.dims
        }
    }

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
            Source::Files(files) if files.len() == 1 => format!("file {}", files[0].path),
            Source::Files(files) => format!(
                "{} files ({} .. {})",
                files.len(),
                files[0].path,
                files[files.len() - 1].path
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

    /// Realisations per cell: `⌈R/8⌉`.
    #[must_use]
    pub fn block(&self) -> u64 {
        self.realisations.div_ceil(MAX_CELLS).max(1)
    }

    /// The spectrum of `R` realisations of a pattern's points on the default
    /// grid by the NUFFT at tolerance 1e-9 (the gallery's spectra).
    #[must_use]
    pub fn for_pattern(
        spec: &PatternSpec,
        n: usize,
        realisations: u64,
        seed: u64,
        shift: ShiftMode,
    ) -> Self {
        Config {
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
            shift,
            method: Method::Nufft,
            tol: DEFAULT_TOL,
            label: spec.sampler.name().to_string(),
            detail: None,
            notes: Vec::new(),
        }
    }
}

pub(crate) fn not_for(option: &str, what: &str, got: Primitive) -> LabError {
    LabError::Usage(format!(
        "{option} applies only to {what} (got --primitive {})",
        got.name()
    ))
}

/// The largest `k` with `2k + 1 ≤ 10·√N`, capped per grid dimension.
#[must_use]
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

/// One point file read: its dimension, flat coordinates wrapped into `[0, 1)`,
/// and its CRC-32; notes about headers and wrapping go to `notes`.
pub(crate) fn read_points(path: &Path, notes: &mut Vec<String>) -> Result<(usize, Vec<f64>, u32)> {
    let name = path.display();
    let bytes = std::fs::read(path).map_err(LabError::io_at("read --input", path))?;
    let crc = crc32fast::hash(&bytes);
    let text = String::from_utf8(bytes).map_err(|e| {
        format!(
            "{name}: not UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        )
    })?;
    let set = pointfile::parse_points(&text).map_err(|source| LabError::PointFile {
        file: name.to_string(),
        source,
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
    Ok((set.dims, set.coords, crc))
}

pub(crate) fn pattern_n<const D: usize, const E: usize>(
    spec: &PatternSpec,
) -> Result<(usize, Option<String>)> {
    let b = sampler::build::<D>(spec, false)?;
    Ok((b.pattern.len(), b.detail))
}

/// A resolved command line.
#[derive(Clone, Debug)]
pub struct Resolved {
    pub config: Config,
    /// The points of the `--input` files (flat, per file), if any.
    pub files: Option<Vec<Vec<f64>>>,
    /// The output prefix.
    pub out: PathBuf,
}

/// One cell: a block of consecutive realisations.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Cell {
    /// `Periodogram::parts` of the block.
    pub sums: Vec<f64>,
    /// Realisations in the block.
    pub realisations: u64,
    /// Per realisation, its ring means (rings `0..=k`).
    pub rings: Vec<Vec<f64>>,
    /// Wall time of the block's realisations, in seconds.
    pub seconds: f64,
}

/// The experiment.
#[derive(Debug)]
pub struct Spectrum {
    config: Config,
    cells: Vec<CellInfo>,
    /// The points of the input files (not needed to merge finished cells).
    files: Option<Vec<Vec<f64>>>,
}

fn check_grid<const D: usize, const E: usize>(cfg: &Config) -> Result<()> {
    let grid = Grid::<E>::new(cfg.k).map_err(|e| LabError::Usage(format!("--k {}: {e}", cfg.k)))?;
    if grid.len() > MAX_GRID_CELLS {
        return Err(LabError::Usage(format!(
            "--k {}: the {E}D grid has {} stored cells (above the lab's limit of {MAX_GRID_CELLS}, \
             about 32 bytes each per block in flight); lower --k",
            cfg.k,
            grid.len()
        )));
    }
    if cfg.primitive == Primitive::Segments {
        let d = Direction::<D>::new(crate::integrand::to_array(&cfg.direction))
            .map_err(|e| LabError::Usage(format!("--direction {}: {e}", join(&cfg.direction))))?;
        Segment::<D>::new([0.5; D], d, cfg.length)
            .map_err(|e| LabError::Usage(format!("--length {}: {e}", cfg.length)))?;
    }
    Ok(())
}

impl Spectrum {
    /// The experiment of `config`; `files` holds the points of `--input` files
    /// (`None` for a sampler, or when only merging finished cells).
    ///
    /// # Errors
    /// An invalid grid, direction or length.
    pub fn new(config: Config, files: Option<Vec<Vec<f64>>>) -> Result<Self> {
        with_dims!(config.dims, config.grid_dims(), check_grid(&config))?;
        let b = config.block();
        let cells = (0..config.realisations.div_ceil(b))
            .map(|c| {
                let first = c * b;
                let last = (first + b).min(config.realisations);
                CellInfo {
                    label: format!("realisations {first}..{last}"),
                    work: last - first,
                }
            })
            .collect();
        Ok(Spectrum {
            config,
            cells,
            files,
        })
    }

    /// The configuration.
    #[must_use]
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The points of realisation `r` in `f64`, shifted if asked.
    fn points<const D: usize>(
        &self,
        pattern: Option<&dyn Pattern<D>>,
        r: u64,
    ) -> Result<Vec<[f64; D]>> {
        let cfg = &self.config;
        let mut pts: Vec<[f64; D]> = match (&cfg.source, pattern) {
            (Source::Pattern(_), Some(p)) => {
                let (pts, _) = sampler::generate(p, Seed::new(cfg.seed).realization(r), 1)?;
                let mut v = buffer::empty(pts.len(), "points")?;
                v.extend(pts.iter().map(|q| q.map(f64::from)));
                v
            }
            (Source::Files(_), _) => {
                let flat = usize::try_from(r)
                    .ok()
                    .and_then(|i| self.files.as_ref()?.get(i))
                    .ok_or_else(|| LabError::Internal("the input files are not loaded".into()))?;
                let mut v = buffer::empty(flat.len() / D, "points")?;
                v.extend(flat.chunks_exact(D).map(|c| {
                    let mut p = [0.0; D];
                    p.copy_from_slice(c);
                    p
                }));
                v
            }
            (Source::Pattern(_), None) => return Err(LabError::Internal("no pattern".into())),
        };
        if cfg.shift == ShiftMode::Random {
            let s = Shifted::<()>::shift::<D>(Seed::new(cfg.seed).realization(r));
            for p in &mut pts {
                for (x, d) in p.iter_mut().zip(s) {
                    *x = frac(*x + d);
                }
            }
        }
        Ok(pts)
    }

    fn what(&self, r: u64) -> String {
        match &self.config.source {
            Source::Files(files) => files
                .get(r as usize)
                .map_or_else(|| format!("realisation {r}"), |f| f.path.clone()),
            Source::Pattern(_) => format!("realisation {r}"),
        }
    }
}

/// The `E`-dim sample coordinates of one realisation: the points, or the line
/// offsets (points with the line axis dropped).
fn sample_coords<const D: usize, const E: usize>(
    cfg: &Config,
    pts: &[[f64; D]],
    buf: &mut Vec<[f64; E]>,
) -> Result<()> {
    buf.clear();
    buf.try_reserve(pts.len())
        .map_err(|_| format!("{} samples: cannot allocate", pts.len()))?;
    buf.resize(pts.len(), [0.0; E]);
    match cfg.primitive {
        Primitive::Lines => line_offsets::<D, E, f64>(pts, cfg.axis, buf)
            .map_err(|e| LabError::Usage(format!("--primitive lines: {e}"))),
        _ => {
            for (o, p) in buf.iter_mut().zip(pts) {
                o.copy_from_slice(&p[..E]);
            }
            Ok(())
        }
    }
}

/// The amplitude engine of one cell.
enum Engine<const E: usize> {
    Direct {
        dft: Dft<E, Vec<f64>>,
        scratch: Vec<f64>,
        dir: Option<Direction<E>>,
    },
    Nufft {
        plan: Box<nufft::Plan<E>>,
        amps: Amplitudes<E, Vec<f64>>,
    },
}

impl<const E: usize> Engine<E> {
    fn new(cfg: &Config, grid: Grid<E>) -> Result<Self> {
        Ok(match cfg.method {
            Method::Direct => {
                let per = if cfg.primitive == Primitive::Segments {
                    Dft::<E, Vec<f64>>::segments_scratch_per_sample(grid)
                } else {
                    Dft::<E, Vec<f64>>::points_scratch_per_sample(grid)
                };
                let chunk = (SCRATCH_VALUES / per).clamp(1, CHUNK_SAMPLES);
                let buf = buffer::filled(
                    Dft::<E, Vec<f64>>::buffer_len(grid),
                    0.0,
                    "the amplitude grid",
                )?;
                let dir = if cfg.primitive == Primitive::Segments {
                    Some(
                        Direction::<E>::new(crate::integrand::to_array(&cfg.direction)).map_err(
                            |e| {
                                LabError::Usage(format!(
                                    "--direction {}: {e}",
                                    join(&cfg.direction)
                                ))
                            },
                        )?,
                    )
                } else {
                    None
                };
                Engine::Direct {
                    dft: Dft::new(grid, buf)?,
                    scratch: buffer::filled(chunk * per, 0.0, "the phase tables")?,
                    dir,
                }
            }
            Method::Nufft => {
                let plan = nufft::Plan::<E>::new_for_points(cfg.k, cfg.tol, cfg.n)
                    .map_err(|e| LabError::Usage(format!("--method nufft: {e}")))?;
                let buf = buffer::filled(
                    Amplitudes::<E, Vec<f64>>::buffer_len(grid),
                    0.0,
                    "the amplitude grid",
                )?;
                Engine::Nufft {
                    plan: Box::new(plan),
                    amps: Amplitudes::new(grid, buf)?,
                }
            }
        })
    }

    /// The amplitudes of one realisation's samples.
    fn transform(&mut self, cfg: &Config, samples: &[[f64; E]]) -> Result<&dyn AmplitudeView<E>> {
        let what =
            |e: linesample::SpectrumError| format!("--primitive {}: {e}", cfg.primitive.name());
        match self {
            Engine::Direct { dft, scratch, dir } => {
                dft.clear();
                match dir {
                    Some(d) => dft
                        .add_segment_pattern(samples, d, cfg.length, scratch)
                        .map_err(what)?,
                    None => dft.add_points(samples, scratch).map_err(what)?,
                }
                Ok(dft)
            }
            Engine::Nufft { plan, amps } => {
                plan.transform_into(samples, amps)
                    .map_err(|e| LabError::Usage(format!("--method nufft: {e}")))?;
                Ok(amps)
            }
        }
    }
}

fn run_block<const D: usize, const E: usize>(
    exp: &Spectrum,
    index: usize,
    ctx: &Ctx<'_>,
) -> Result<Cell> {
    let cfg = &exp.config;
    let t = Instant::now();
    let b = cfg.block();
    let first = index as u64 * b;
    let last = (first + b).min(cfg.realisations);
    let grid = Grid::<E>::new(cfg.k).map_err(|e| LabError::Usage(format!("--k {}: {e}", cfg.k)))?;
    let built = match &cfg.source {
        Source::Pattern(spec) => Some(sampler::build::<D>(spec, false)?),
        Source::Files(_) => None,
    };
    let mut engine = Engine::<E>::new(cfg, grid)?;
    let buf = buffer::filled(
        Periodogram::<E, Vec<f64>>::buffer_len(grid),
        0.0,
        "the periodogram",
    )?;
    let mut total = Periodogram::new(grid, buf)?;
    let mut count = vec![0u64; cfg.k + 1];
    let mut rings = Vec::with_capacity((last - first) as usize);
    let mut samples: Vec<[f64; E]> = Vec::new();
    for r in first..last {
        let step = exp
            .points::<D>(
                built
                    .as_ref()
                    .map(|b| b.pattern.as_ref() as &dyn Pattern<D>),
                r,
            )
            .and_then(|pts| {
                sample_coords::<D, E>(cfg, &pts, &mut samples)?;
                if samples.is_empty() {
                    return Err(LabError::Message("no points".into()));
                }
                let view = engine.transform(cfg, &samples)?;
                total.add(view)?;
                let mut ring = vec![0.0; cfg.k + 1];
                view.radial_power(&mut ring, &mut count)?;
                Ok(ring)
            })
            .map_err(|e| format!("{}: {e}", exp.what(r)))?;
        rings.push(step);
        ctx.advance(1);
    }
    // The periodogram's own buffer becomes the cell (no copy).
    let (sums, n) = total.into_parts();
    Ok(Cell {
        sums,
        realisations: n,
        rings,
        seconds: t.elapsed().as_secs_f64(),
    })
}

impl Experiment for Spectrum {
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
        Ok(with_dims!(
            self.config.dims,
            self.config.grid_dims(),
            run_block(self, index, ctx)
        )?)
    }
}

/// The mean spectrum as an image: `side × side` values `⟨N·P⟩`, row 0 at
/// `ν_1 = k`, column 0 at `ν_0 = −k` (3D: the slice `ν_2 = 0`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Image {
    pub side: usize,
    pub values: Vec<f64>,
}

/// What a spectrum run measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Half-width of the grid.
    pub k: usize,
    /// Dimension of the grid.
    pub grid_dims: usize,
    /// Rings `0..=k`: mean of `⟨N·P⟩`, standard error, frequency count.
    pub mean: Vec<f64>,
    pub se: Vec<f64>,
    pub count: Vec<u64>,
    /// The image (2D and 3D grids).
    pub image: Option<Image>,
    /// Mean `⟨N·P⟩` over rings `⌈k/2⌉..k`.
    pub high: f64,
    /// Mean `⟨N·P⟩` over rings `1..round(√N/4)`.
    pub low: f64,
    /// Wall time per realisation, in milliseconds.
    pub ms: f64,
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

/// The bands of the summary: `(⌈k/2⌉, round(√N/4))` clamped to the grid.
fn bands(k: usize, n: usize) -> (usize, usize) {
    let hi_lo = k.div_ceil(2).max(1);
    let low_hi = ((n as f64).sqrt() / 4.0).round().max(1.0) as usize;
    (hi_lo, low_hi.min(k))
}

fn summarise<const D: usize, const E: usize>(cfg: &Config, cells: Vec<Cell>) -> Result<Summary> {
    let grid = Grid::<E>::new(cfg.k).map_err(|e| LabError::Usage(format!("--k {}: {e}", cfg.k)))?;
    let bad = |e: linesample::SpectrumError| format!("a stored block of realisations: {e}");
    let mut total: Option<Periodogram<E, Vec<f64>>> = None;
    let mut rings = vec![RunningStats::new(); cfg.k + 1];
    let mut seconds = 0.0;
    for c in cells {
        for ring in &c.rings {
            if ring.len() != cfg.k + 1 {
                return Err(LabError::Message(
                    "a stored block of realisations has rings of the wrong length".into(),
                ));
            }
            for (s, &v) in rings.iter_mut().zip(ring) {
                s.push(v);
            }
        }
        seconds += c.seconds;
        let p = Periodogram::from_parts(grid, c.sums, c.realisations).map_err(bad)?;
        match &mut total {
            None => total = Some(p),
            Some(t) => t.merge(&p).map_err(bad)?,
        }
    }
    let total = total.ok_or_else(|| LabError::Internal("no realisations".into()))?;
    if total.realisations() != cfg.realisations {
        return Err(LabError::Internal("missing realisations".into()));
    }
    let mut mean = vec![0.0; cfg.k + 1];
    let mut count = vec![0u64; cfg.k + 1];
    total.radial_average(&mut mean, &mut count)?;
    let se = rings.iter().map(RunningStats::mean_std_error).collect();
    let image = if E >= 2 {
        let k = cfg.k as i32;
        let side = 2 * cfg.k + 1;
        let mut values = buffer::empty(side * side, "the spectrum image")?;
        for row in 0..side as i32 {
            for col in 0..side as i32 {
                let mut j = [0i32; E];
                j[0] = col - k;
                j[1] = k - row;
                values.push(total.mean(j).unwrap_or(0.0));
            }
        }
        Some(Image { side, values })
    } else {
        None
    };
    let (hi_lo, low_hi) = bands(cfg.k, cfg.n);
    Ok(Summary {
        k: cfg.k,
        grid_dims: E,
        high: band_mean(&mean, &count, hi_lo, cfg.k),
        low: band_mean(&mean, &count, 1, low_hi),
        mean,
        se,
        count,
        image,
        ms: seconds * 1e3 / cfg.realisations as f64,
    })
}

impl Spectrum {
    /// The summary of the cells (in order): periodograms merged in block
    /// order, ring statistics pushed in realisation order.
    ///
    /// # Errors
    /// If a stored cell is invalid.
    pub fn summary(&self, cells: Vec<Cell>) -> Result<Summary> {
        with_dims!(
            self.config.dims,
            self.config.grid_dims(),
            summarise(&self.config, cells)
        )
    }
}

/// A radial CSV row (field names are the header).
#[derive(Serialize)]
struct CsvRow {
    radius: usize,
    #[serde(serialize_with = "table::sci")]
    mean_np: f64,
    #[serde(serialize_with = "table::sci")]
    std_error: f64,
    count: u64,
}

/// The grey image of the summary: side in pixels and the pixels (`None` for
/// a 1D grid).
#[must_use]
pub fn image_pixels(s: &Summary) -> Option<(usize, Vec<u8>)> {
    let img = s.image.as_ref()?;
    let scale = MIN_IMAGE.div_ceil(img.side).max(1);
    let centre = img.side / 2;
    let px = image::upscaled(img.side, scale, |row, col| {
        if row == centre && col == centre {
            255
        } else {
            image::log_gray(img.values[row * img.side + col], LOG_MIN, LOG_MAX)
        }
    });
    Some((img.side * scale, px))
}

/// Stages `PREFIX.png` (2D/3D grids), `PREFIX-radial.csv` and
/// `PREFIX-radial.svg` of `s`; returns their paths.
///
/// # Errors
/// A drawing or I/O error.
pub fn stage(
    group: &mut FileGroup,
    prefix: &Path,
    s: &Summary,
    title: &str,
    subtitle: &str,
) -> Result<Vec<PathBuf>> {
    let mut paths = Vec::new();
    let rings_ok = [s.mean.len(), s.se.len(), s.count.len()]
        .iter()
        .all(|&l| l == s.k + 1);
    let image_ok = s
        .image
        .as_ref()
        .is_none_or(|i| i.values.len() == i.side * i.side);
    if !rings_ok || !image_ok {
        return Err(LabError::Message(
            "a stored spectrum summary has arrays of the wrong length; use --fresh".into(),
        ));
    }
    if let Some((w, px)) = image_pixels(s) {
        let png_path = io::suffixed(prefix, ".png");
        let side = u32::try_from(w).map_err(|_| "internal error: image too large")?;
        group.add_bytes(&png_path, &image::png(side, side, image::Color::Gray, &px)?)?;
        paths.push(png_path);
    }
    let rows: Vec<CsvRow> = (1..=s.k)
        .map(|r| CsvRow {
            radius: r,
            mean_np: s.mean[r],
            std_error: s.se[r],
            count: s.count[r],
        })
        .collect();
    let csv_path = io::suffixed(prefix, "-radial.csv");
    group.add_bytes(&csv_path, &table::csv(&rows)?)?;
    paths.push(csv_path);
    let svg = figures::radial(&figures::Radial {
        title,
        subtitle,
        mean: &s.mean,
        se: &s.se,
        k: s.k,
    })?;
    let svg_path = io::suffixed(prefix, "-radial.svg");
    group.add_bytes(&svg_path, svg.as_bytes())?;
    paths.push(svg_path);
    Ok(paths)
}

/// The plot title and subtitle of a spectrum.
#[must_use]
pub fn titles(cfg: &Config) -> (String, String) {
    (
        format!(
            "{} {}D {}, N = {}, R = {}",
            cfg.label,
            cfg.dims,
            cfg.primitive.name(),
            cfg.n_desc(),
            cfg.realisations
        ),
        format!(
            "{}; {}; shift {}; radial average of <N·P> over rings of unit width, k = {}",
            cfg.source_desc(),
            cfg.primitive_desc(),
            match cfg.shift {
                ShiftMode::None => "none",
                ShiftMode::Random => "random",
            },
            cfg.k
        ),
    )
}

/// The printed summary.
#[must_use]
pub fn report(cfg: &Config, s: &Summary, threads: usize) -> String {
    let k = cfg.k;
    let side = 2 * k + 1;
    let e = cfg.grid_dims();
    let grid_desc = vec![side.to_string(); e].join("x");
    let mut out = String::new();
    let _ = writeln!(
        out,
        "spectrum: {} {}D, {}; N = {}, k = {k} ({e}D grid {grid_desc}), R = {} realisation(s){}, \
         method {}, {threads} thread(s){}",
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
        match cfg.shift {
            ShiftMode::None => "",
            ShiftMode::Random => ", random toroidal shift per realisation",
        }
    );
    let (hi_lo, low_hi) = bands(k, cfg.n);
    let high_h = format!("<N*P> rings {hi_lo}..{k}");
    let low_h = format!("<N*P> rings 1..{low_hi}");
    let (w1, w2) = (high_h.len().max(10), low_h.len().max(10));
    let _ = writeln!(
        out,
        "{:>10} {:>6} {:>6} {:>12} {high_h:>w1$} {low_h:>w2$}",
        "N", "k", "R", "ms/real."
    );
    let _ = writeln!(
        out,
        "{:>10} {:>6} {:>6} {:>12.2} {:>w1$.4} {:>w2$.4}",
        cfg.n_desc(),
        k,
        cfg.realisations,
        s.ms,
        s.high,
        s.low
    );
    out
}

/// Writes `OUT/spectrum.png` (2D/3D), `OUT/spectrum-radial.csv`,
/// `OUT/spectrum-radial.svg` and `OUT/manifest.json` as one group and
/// prints the summary (unless `quiet`).
///
/// # Errors
/// A stored-cell, drawing or I/O error.
pub fn complete(
    exp: &Spectrum,
    cells: Vec<Cell>,
    info: &RunInfo,
    out: &Path,
    quiet: bool,
) -> Result<Summary> {
    let cfg = &exp.config;
    let s = exp.summary(cells)?;
    let (title, subtitle) = titles(cfg);
    let mut group = FileGroup::new();
    let paths = stage(&mut group, &out.join("spectrum"), &s, &title, &subtitle)?;
    let json_path = out.join("manifest.json");
    let files = paths.iter().map(|p| file_name(p)).collect();
    let manifest = OutputManifest::new(KIND, reproduce(cfg), cfg, info, files).with_notes(&group);
    group.add_bytes(&json_path, &io::json(&manifest)?)?;
    group.commit()?;
    for note in &cfg.notes {
        crate::err!("note: {note}");
    }
    if !quiet {
        crate::out!("{}", report(cfg, &s, info.threads).trim_end());
        crate::out!("total wall time {:.2} s", info.wall.as_secs_f64());
        let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        crate::out!(
            "wrote {} and {}{}",
            names.join(", "),
            json_path.display(),
            if s.image.is_none() {
                " (no PNG: the spectrum is 1D)"
            } else {
                ""
            }
        );
    }
    Ok(s)
}

/// A command that recomputes the spectrum (sampler runs only; files are
/// listed as given).
fn reproduce(cfg: &Config) -> String {
    let mut c = String::from("linesample-lab spectrum");
    match &cfg.source {
        Source::Pattern(p) => {
            let _ = write!(c, " --sampler {} --dims {} -n {}", p.sampler, p.dims, cfg.n);
            if let Some(s) = &p.strata {
                let s: Vec<String> = s.iter().map(ToString::to_string).collect();
                let _ = write!(c, " --strata {}", s.join(","));
            }
            if let Some((a, b)) = p.grid {
                let _ = write!(c, " --grid {a}x{b}");
            }
            if p.sampler.is_poisson() {
                let _ = write!(c, " --relative-radius {}", p.relative_radius);
                if p.bridson {
                    c.push_str(" --bridson");
                }
            }
            let _ = write!(
                c,
                " --seed {} --realizations {}",
                cfg.seed, cfg.realisations
            );
        }
        Source::Files(files) => {
            c.push_str(" --input");
            for f in files {
                let _ = write!(c, " {}", f.path);
            }
        }
    }
    let _ = write!(c, " --primitive {}", cfg.primitive.name());
    match cfg.primitive {
        Primitive::Segments => {
            let _ = write!(
                c,
                " --length {} --direction {}",
                cfg.length,
                join(&cfg.direction)
            );
        }
        Primitive::Lines => {
            let _ = write!(c, " --axis {}", cfg.axis);
        }
        Primitive::Points => {}
    }
    let _ = write!(c, " --k {} --method {}", cfg.k, cfg.method.name());
    if cfg.method == Method::Nufft {
        let _ = write!(c, " --tol {:e}", cfg.tol);
    }
    if cfg.shift == ShiftMode::Random {
        c.push_str(" --shift random");
    }
    c
}

/// `linesample-lab merge` for spectrum shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge(a: &MergeRequest, config: serde_json::Value) -> Result<()> {
    let exp = Spectrum::new(config_from(config, KIND)?, None)?;
    merge_to_files(
        &exp,
        a,
        Box::new(|e, c, i, o, q| {
            complete(e, c, i, o, q)?;
            Ok(())
        }),
    )
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
    fn bands_and_means() {
        assert_eq!(bands(159, 1024), (80, 8));
        assert_eq!(bands(4, 4096), (2, 4));
        let mean = [9.0, 1.0, 3.0];
        let count = [1, 2, 6];
        assert_eq!(band_mean(&mean, &count, 1, 2), (2.0 + 18.0) / 8.0);
    }
}
