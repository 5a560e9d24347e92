//! The command line: one `clap` definition per subcommand, built from shared
//! option groups (`#[command(flatten)]`) so that every option that means the
//! same thing in two commands is defined once.

use std::path::PathBuf;

use clap::{ArgGroup, Args, Parser, Subcommand};

use crate::commands;
use crate::experiments::paper::{self, Mode};
use crate::experiments::{convergence, gallery, patterns, pixel_error, scene, spectrum};
use crate::integrand::IntegrandKind;
use crate::runner::{RunOptions, Shard, MAX_THREADS};
use crate::sampler::{Sampler, DEFAULT_RELATIVE_RADIUS};
use crate::scene::{CentrePdf, SceneSampler};
use crate::{LabError, Result};

/// The note on how every command writes files (a literal, so the commands'
/// `--help` texts can `concat!` it).
#[macro_export]
macro_rules! files_note {
    () => {
        "Files: every command's --out is a folder (its state is kept in OUT.state/ beside
it). Every group of files (e.g. OUT/convergence.csv + .svg + OUT/manifest.json) is
written to uniquely
named temporary files next to the targets and renamed into place only when all
are complete; on any failure the temporaries are removed and existing files are
left byte-for-byte unchanged. Errors print one line `error: <message>` on stderr
and exit with a non-zero code."
    };
}

/// The top-level `--help` notes: runs (cells, state, shards, progress) and
/// files.
pub const TOP_HELP: &str = concat!(
    "\
Runs: the work is a list of cells (see the command's description). Every finished
cell is written atomically to the state folder OUT.state/ next to the output (OUT
is --out or --out-dir) with its accumulator state; rerunning the same command
resumes, computing only the missing cells (--fresh starts over), so Ctrl-C or a
kill loses at most the cells in flight. A different configuration in the same
state folder is refused. --shard I/N computes only the cells c with c mod N = I-1
and writes only its state; `linesample-lab merge --out OUT SHARD_OUT...` combines
the N shards into exactly the files one unsharded run with --out OUT writes.
Results never depend on --threads. A progress bar (cells, work done, rate, ETA) is
drawn on stderr when it is a terminal, unless --quiet. OUT.json (gallery:
OUT_DIR/manifest.json) records the command, the configuration, the seeds, the
version, the thread count and the timings.

",
    crate::files_note!()
);

/// Experiment runner for the linesample kernel: writes sample patterns as point
/// files and SVG plots, measures their power spectra, and measures how
/// estimator variance converges with N.
///
/// Without a subcommand it runs `gallery` with its defaults.
#[derive(Debug, Parser)]
#[command(name = "linesample-lab", version, after_long_help = TOP_HELP)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Reproduce the convergence analysis of Singh, Miller & Jarosz (EGSR
    /// 2017) on this machine and write an HTML report (OUT/index.html).
    ///
    /// Runs, as the cells of one resumable run: (1) rate tables for points
    /// and unidirectional lines (samplers random, jittered, poisson-disk, ccvt,
    /// multi-jittered, sobol x gaussian (best case) and disk/ball (worst
    /// case) x 2D, 3D), each measured slope with its 95 % interval against the
    /// theoretical rate; (2) points, segments (lengths 0.001 to 1) and lines in
    /// 3D (the segment cross-over); (3) lines in K = 1, 2, 3 direction groups
    /// and in random directions; (4) Poisson-disk line offsets; (5) lines
    /// crossing and parallel to a straight edge with a randomised edge
    /// position, and the fixed-edge pitfall; (6) expected power spectra of
    /// every sampler and of the integrands; (7) what accuracy costs in time:
    /// RMSE against time per estimate, the time to reach a relative error,
    /// f32 SIMD against f64 closed forms, and the NUFFT tolerance sweep.
    /// Every homogenised curve has the spectral variance prediction beside
    /// the measurement where the pattern's periodogram is measured (see the
    /// report). Seeds: curve row N uses the rule of `convergence` (run seed
    /// Seed::new(Seed::new(SEED).stream(N)), realisation r its
    /// .realization(r)); predictions draw independent pattern realisations;
    /// the straight edge draws its offset from each realisation's seed.
    /// --mode quick (the default) takes about 3 minutes on two cores; --full
    /// is publication quality (about 45 minutes on two cores, or sharded with
    /// --shard and merge); --mode reduced is a small end-to-end check.
    #[command(after_long_help = paper::report::FORMATS)]
    Paper(PaperArgs),
    /// Write one pattern as OUT/points.txt (points) and OUT/points.svg (plot).
    #[command(after_long_help = patterns::FORMATS)]
    Patterns(PatternsArgs),
    /// Write every sampler in 2D and 3D with its spectrum and an index (the
    /// default command).
    ///
    /// Samplers random, jittered, n-rooks, sobol, halton, poisson-disk
    /// (sequential dart throwing stopped at N, relative radius 0.75),
    /// poisson-disk-thinned (N points drawn from a maximal set of the same
    /// radius, beside it for comparison) and ccvt in 2D and 3D, and
    /// multi-jittered, cmj, pmj02 and pmj02bn in 2D (they are 2D only), all
    /// with N = 1024 points except jittered 3D, which uses N = 1000 = 10x10x10
    /// strata. For each one it
    /// writes `OUT_DIR/<sampler>-<dims>d-<N>.txt` and `.svg` (realisation 0), and
    /// the mean periodogram of --spectrum-realizations realisations as
    /// `OUT_DIR/<sampler>-<dims>d-<N>-spectrum.png`, `-spectrum-radial.csv` and
    /// `-spectrum-radial.svg` (as `spectrum --method nufft --tol 1e-9` on the
    /// default grid; the 3D image is the slice nu_z = 0). It prints a table
    /// (sampler, dims, N, median time of --runs calls to Pattern::fill in
    /// microseconds, which excludes formatting and file output; the mean <N*P>
    /// over the low rings 1..round(sqrt(N)/4) and the high rings ceil(k/2)..k;
    /// files) and writes the same rows to OUT_DIR/index.csv (file names relative
    /// to OUT_DIR; spectrum = the spectrum files' common stem) under the header
    /// sampler,dims,n,seed,median_us,txt,svg,np_low,np_high,spectrum.
    ///
    /// Cells: one per pattern, run one after another so that the timings are
    /// not disturbed (each pattern's spectrum uses every thread).
    #[command(after_long_help = gallery::FORMATS)]
    Gallery(GalleryArgs),
    /// Measure how the variance of one estimator falls as N grows; write
    /// OUT/convergence.csv (table), OUT/convergence.svg (log-log plot) and
    /// OUT/manifest.json (manifest).
    ///
    /// For each N in --n it runs R (--realisations) independent realisations of
    /// one estimator of the integral of --integrand over the unit torus [0,1)^D:
    /// the point, segment or line estimator (--primitive) with the pattern of
    /// --sampler. For each N it reports the mean of the R estimates, the exact
    /// integral (closed form), the bias z-score (mean - exact)/SE(mean), the
    /// unbiased sample variance Var of the estimates, its standard error SE(Var)
    /// (from the fourth central moment), Var*N and the time per realisation, then
    /// fits the slope of log Var against log N over all N by weighted least
    /// squares (weights (Var/SE(Var))^2, the inverse variance of log Var) and
    /// prints it with its standard error.
    ///
    /// Homogenisation (--shift): by default every realisation adds its own
    /// uniform random toroidal shift (drawn from the realisation seed) to the
    /// pattern, so every estimator is unbiased and Var is the variance of the
    /// homogenised (stationary) sampling process; --shift none uses the patterns
    /// as generated (strata aligned to the domain), as tools and papers that do
    /// not homogenise do.
    ///
    /// Cells: one per N. Inside a cell the realisations run in fixed chunks of
    /// 32 on the worker threads, and the chunk statistics are merged in chunk
    /// order, so the results and the CSV are bit-identical for any --threads.
    #[command(after_long_help = convergence::FORMATS)]
    Convergence(ConvergenceArgs),
    /// Measure the mean periodogram <N*P(nu)> of a pattern, of segments or lines
    /// through it, or of point sets read from files; write OUT/spectrum.png
    /// (log-scale image), OUT/spectrum-radial.csv and OUT/spectrum-radial.svg
    /// (radial average) and OUT/manifest.json (manifest).
    ///
    /// For each of R realisations (--realizations; realisation r of a sampler
    /// uses the points of `patterns --seed SEED --realization r`; with --input
    /// each file is one realisation) it computes the Fourier amplitudes F(nu)
    /// of the samples at every integer frequency of the grid [-k, k]^D, exactly
    /// (--method direct, the default) or by a type-1 non-uniform FFT to relative
    /// accuracy --tol (--method nufft, points and lines; about 20x faster for
    /// N = 4096 on the 639x639 grid), and accumulates N*P(nu) = |F(nu)|^2/N, which is 1 for
    /// white noise. It writes the mean over the realisations as an image, its
    /// radial average over rings of unit width with the standard error of each
    /// ring mean across the realisations, and prints a summary.
    ///
    /// Cells: blocks of ceil(R/8) consecutive realisations (at most 8 cells);
    /// blocks run in parallel and are merged in realisation order, so every
    /// output file is byte-identical for any --threads.
    #[command(after_long_help = spectrum::FORMATS)]
    Spectrum(SpectrumArgs),
    /// Measure how the per-pixel error of an image is spread across the
    /// screen: blue noise with ZSobol (one Owen-scrambled Sobol' sequence over
    /// all pixels in Morton order, Ahmed & Wonka 2020), white noise with an
    /// independent Sobol' seed per pixel.
    ///
    /// Every pixel integrates the same smooth 2D integrand (a periodised
    /// Gaussian, centre (0.3, 0.6), sigma 0.2) with --spp samples; the error
    /// image's periodogram is normalised by its mean power without DC (white
    /// noise = 1) and averaged over rings round(|k|) = r and over
    /// --realizations independent images (seeds Seed::new(SEED).realization(r)).
    /// Prints the mean over rings 1..=4 for both samplers with its standard
    /// error. Takes about a second at the defaults.
    #[command(after_long_help = pixel_error::FORMATS)]
    PixelError(PixelErrorArgs),
    /// Combine the state of the shards of a sharded run (`--shard I/N`) into
    /// the files one unsharded run with --out OUT would write.
    ///
    /// Each SHARD is the --out (or --out-dir) the shard was run with; every
    /// shard must have finished, and all must come from the same command (apart
    /// from --shard and --threads). The cells are copied into OUT.state, so the
    /// unsharded command with --out OUT afterwards finds every cell done.
    ///
    /// Slurm job array (one shard per task):
    ///   sbatch --array=0-7 --wrap 'linesample-lab convergence ... --quiet
    ///     --shard $((SLURM_ARRAY_TASK_ID+1))/$SLURM_ARRAY_TASK_COUNT
    ///     --out runs/s$SLURM_ARRAY_TASK_ID'
    ///   linesample-lab merge --out runs/all runs/s0 runs/s1 ... runs/s7
    ///
    /// GNU parallel (8 shards on the machines of --sshloginfile, or locally):
    ///   parallel linesample-lab convergence ... --quiet --shard {}/8 --out runs/s{} ::: $(seq 8)
    ///   linesample-lab merge --out runs/all runs/s{1..8}
    #[command(after_long_help = crate::files_note!())]
    Merge(MergeArgs),
    /// Estimate a scene file's one effect (ambient occlusion, direct light
    /// from an area light, or a volumetric caustic) with points, segments,
    /// lines or beams: images, and convergence studies.
    ///
    /// FILE is a TOML scene (scenes/ao-spheres.toml, the paper's AO scene;
    /// scenes/cornell-box.toml, direct light in the Cornell box;
    /// scenes/caustic-2d.toml and caustic-3d.toml, volumetric caustics): camera,
    /// geometry, the effect and the estimators to compare; a mistake in it is
    /// one error naming the file, line, column and field. Only the effect is
    /// simulated: a camera ray per pixel finds the shading point, and every
    /// estimate is a closed form (no ray tracing, no bounces): for AO the
    /// visibility of the spheres in half-planes through the normal; for
    /// direct light the occluders' faces projected onto the light's plane
    /// and the diffuse geometry term integrated along each line.
    ///
    /// AO images (default): per pixel the reference (lines, 16 x 64 jittered
    /// azimuths unless --reference-realisations/--reference-lines say
    /// otherwise; its SE from the spread), every primitive of the scene (each
    /// segment length; lines also through the kernel's f32 SIMD batch) with
    /// --sampler (default multi-jittered) and --pdf at N = 1, 2, 4, ..., 4*--n
    /// (squares for jittered), timed, and the per-pixel variance at --n. The
    /// equal-time images are those whose time is closest to the lines' at
    /// --n. Cells: blocks of 8 rows. Every realisation has its own random
    /// toroidal shift (--shift none to turn it off).
    ///
    /// AO --pixel X,Y (pbrt's convention: (0,0) is the top left pixel, the ray
    /// goes through the pixel centre): the reference (64 x 4096 jittered lines
    /// unless overridden) and, for every estimator of the scene (primitive,
    /// segment length, centre density, sampler; --samplers to restrict), the
    /// variance of --realisations estimates at each N of --pixel-n, the fitted
    /// slope with its 95 % interval beside the rate theory gives, and the time
    /// to a 1 % relative error. Cells: the reference, then each row and N.
    ///
    /// Direct light: images of points on the light and lines across it with
    /// each orientation of the scene (edge1, edge2, angle-DEG (DEG degrees from edge1),
    /// random-per-point, random-per-line, stratified), with --sampler
    /// (default jittered) at N = 1, 4, 16, ..., 16*--n (--n a power of 4),
    /// the reference (4 x 256 jittered lines along edge 1 unless overridden),
    /// variance images at --n and the map of which fixed orientation wins;
    /// then pixels A and B (the largest variance ratio between the two fixed
    /// orientations, each way, among penumbra pixels) and P1, P2 (a shadow
    /// edge closest to parallel to each light edge, when within 2 degrees) get a convergence study
    /// (--pixel-n, --realisations, --samplers: default random and jittered)
    /// into OUT/pixels/, and OUT/orientation.csv gets their slopes. --pixel
    /// X,Y studies that one pixel instead. By default only Sobol' points get
    /// a random toroidal shift per realisation; the other patterns are used
    /// unshifted (a shift would misalign jittered strata with the light's
    /// edges); --shift random shifts every pattern, --shift none none.
    ///
    /// Volumetric caustic (no camera: light, glass ball, medium, query ball
    /// Q): the fluence image rendered with the file's fluence.beams
    /// (--resolution overrides its size) into OUT/fluence.png, then photon
    /// points against photon beams with each of the file's samplers
    /// (--samplers to restrict) at each N of --pixel-n (jittered: powers of
    /// two), --realisations estimates each, against a reference of
    /// --reference-realisations x --reference-lines jittered beams (default
    /// 64 x 65536), into OUT/study/; OUT/caustics.csv gets the slopes, fitted
    /// over the three largest N. Shifts as for direct light: Sobol' only by
    /// default, --shift random or none to choose.
    ///
    /// Seeds: see the scene experiments' docs; results do not depend on
    /// --threads.
    #[command(after_long_help = scene::FORMATS)]
    Scene(SceneArgs),
}

/// Options of `linesample-lab scene`.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// The scene file (TOML).
    #[arg(value_name = "FILE")]
    pub file: PathBuf,

    /// Output folder (default: out/scene/FILE_STEM, the scene file name without its extension).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Study one pixel instead of rendering images.
    #[arg(long, value_name = "X,Y", value_parser = parse_pixel)]
    pub pixel: Option<(u32, u32)>,

    /// Render at WxH instead of the scene's resolution (the camera's field of
    /// view is kept; pixel coordinates refer to this resolution).
    #[arg(long, value_name = "WxH", value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,

    /// Images: samples per pixel of the equal-samples images and of the
    /// variance images (a power of two; a square for jittered).
    #[arg(long, value_name = "N", default_value_t = 16)]
    pub n: usize,

    /// Images: the sampler of every estimator [default: multi-jittered for
    /// ambient occlusion, jittered for direct light].
    #[arg(long, value_enum)]
    pub sampler: Option<SceneSampler>,

    /// Images: the centre density of points and segments.
    #[arg(long, value_enum, default_value_t = CentrePdf::Uniform)]
    pub pdf: CentrePdf,

    /// Images: realisations behind each pixel's variance (at least 2).
    #[arg(long, value_name = "R", default_value_t = 8, value_parser = clap::value_parser!(u64).range(2..))]
    pub variance_realisations: u64,

    /// Lines per reference estimate [default: 64 for images, 4096 for --pixel].
    #[arg(long, value_name = "M")]
    pub reference_lines: Option<usize>,

    /// Independent reference estimates (their spread gives the reference's
    /// SE) [default: 16 for images, 64 for --pixel].
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(2..))]
    pub reference_realisations: Option<u64>,

    /// --pixel: sample counts N, comma-separated.
    #[arg(long, value_name = "N1,N2,..", value_delimiter = ',', default_values_t = [16usize, 64, 256, 1024, 4096])]
    pub pixel_n: Vec<usize>,

    /// --pixel: realisations per N (at least 4).
    #[arg(long, value_name = "R", visible_alias = "realizations", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(4..))]
    pub realisations: u64,

    /// --pixel: pattern realisations behind each expected periodogram of the
    /// spectral variance prediction (0: no prediction, no integrand images).
    #[arg(long, value_name = "R", default_value_t = 64)]
    pub spectrum_realisations: u64,

    /// --pixel: only these samplers (comma-separated) of the scene's.
    #[arg(long, value_enum, value_delimiter = ',')]
    pub samplers: Option<Vec<SceneSampler>>,

    #[command(flatten)]
    pub run: RunArgs,
}

/// `X,Y` → pixel coordinates.
///
/// # Errors
/// [`LabError::Usage`] showing the expected form.
pub fn parse_pixel(s: &str) -> Result<(u32, u32)> {
    let bad = || {
        LabError::Usage(format!(
            "expected X,Y with two non-negative integers, e.g. 410,305 (got '{s}')"
        ))
    };
    let (x, y) = s.split_once(',').ok_or_else(bad)?;
    Ok((
        x.trim().parse().map_err(|_| bad())?,
        y.trim().parse().map_err(|_| bad())?,
    ))
}

/// `WxH` → a resolution of 1 to 65536 pixels a side.
///
/// # Errors
/// [`LabError::Usage`] showing the expected form.
pub fn parse_resolution(s: &str) -> Result<(u32, u32)> {
    let (w, h) = parse_grid(s)?;
    let ok = |v: usize| (1..=65536).contains(&v);
    if !ok(w) || !ok(h) {
        return Err(LabError::Usage(format!(
            "expected 1 to 65536 pixels a side (got '{s}')"
        )));
    }
    Ok((w as u32, h as u32))
}

pub use crate::spec::ShiftMode;

/// `--shift [MODE]`, shared by `patterns` and the runner commands.
#[derive(Clone, Debug, Args)]
pub struct ShiftArgs {
    /// Homogenisation: `random` (also `--shift` alone) adds an independent
    /// uniform random toroidal shift (Cranley-Patterson rotation), drawn from
    /// the realisation's seed, to every realisation; `none` uses the pattern as
    /// generated. [default: random for convergence and ambient-occlusion
    /// scenes; none for patterns, gallery and spectrum (a shift does not change
    /// a power spectrum |F|^2, so spectra agree either way up to rounding);
    /// Sobol' only for direct-light and caustic scenes]
    #[arg(
        long,
        value_enum,
        value_name = "MODE",
        num_args = 0..=1,
        default_missing_value = "random"
    )]
    pub shift: Option<ShiftMode>,
}

/// Options of every runner command (`gallery`, `spectrum`, `convergence`).
#[derive(Clone, Debug, Args)]
pub struct RunArgs {
    /// Seed of the run (how realisations derive their seeds is in the
    /// command's description).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,

    #[command(flatten)]
    pub shift: ShiftArgs,

    /// Worker threads, 1 to 1024 [default: the available parallelism]. The
    /// results do not depend on it.
    #[arg(long, value_name = "T", value_parser = clap::value_parser!(u64).range(1..=MAX_THREADS as u64))]
    pub threads: Option<u64>,

    /// No progress bar and no progress lines.
    #[arg(long)]
    pub quiet: bool,

    /// Discard the cells in the state folder OUT.state and start over.
    #[arg(long)]
    pub fresh: bool,

    /// Compute only shard I of N (cells c with c mod N = I-1) and write only
    /// the state; combine the shards with `linesample-lab merge`.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
}

impl RunArgs {
    /// The runner options.
    #[must_use]
    pub fn options(&self) -> RunOptions {
        RunOptions {
            threads: self.threads.map(|t| t as usize),
            quiet: self.quiet,
            fresh: self.fresh,
            shard: self.shard,
        }
    }

    /// `--shift`, or `default` when not given.
    #[must_use]
    pub fn shift_or(&self, default: ShiftMode) -> ShiftMode {
        self.shift.shift.unwrap_or(default)
    }
}

/// Poisson-disk options.
#[derive(Clone, Debug, Args)]
pub struct PoissonArgs {
    /// Poisson disk only: minimum distance as a fraction of the densest-packing
    /// distance for N points (Lagae & Dutre 2008), in (0, 1]. Dart throwing
    /// jams (no room for another point) near 0.7476 in 1D (Renyi's parking
    /// constant), 0.777 in 2D and 0.80 in 3D, so N points need a radius below
    /// those (0.7 or less in 1D).
    #[arg(long, value_name = "R", default_value_t = DEFAULT_RELATIVE_RADIUS)]
    pub relative_radius: f64,

    /// Poisson disk only: N points drawn at random from a Bridson set instead
    /// of sequential dart throwing stopped at N (poisson-disk) or of a maximal
    /// set (poisson-disk-thinned). Bridson is fast but not maximal, and at
    /// --relative-radius 0.75 usually fits fewer than N points, which is an
    /// error.
    #[arg(long)]
    pub bridson: bool,
}

/// One pattern of N points.
#[derive(Clone, Debug, Args)]
pub struct PatternArgs {
    /// Sample pattern.
    #[arg(long, value_enum)]
    pub sampler: Option<Sampler>,

    /// Number of points N (default: 1024, or the product of --strata / --grid
    /// when those are given).
    #[arg(short = 'n', value_name = "N")]
    pub n: Option<usize>,

    /// Jittered only: strata per axis, one count per dimension, comma-separated
    /// (e.g. 32,32). Without it jittered uses a cubical grid (m^D = N), which
    /// needs N to be a perfect square (2D) or cube (3D).
    #[arg(long, value_name = "M1,M2,..", value_delimiter = ',')]
    pub strata: Option<Vec<usize>>,

    /// Multi-jittered and cmj only: grid of COLS x ROWS cells (N = COLS*ROWS),
    /// e.g. 64x16. Without it the kernel picks the most square grid with
    /// COLS*ROWS = N (COLS = the largest divisor of N not above its square root).
    #[arg(long, value_name = "COLSxROWS", value_parser = parse_grid)]
    pub grid: Option<(usize, usize)>,

    #[command(flatten)]
    pub poisson: PoissonArgs,
}

pub use crate::spec::Primitive;

/// `--primitive`, `--length`, `--direction`.
#[derive(Clone, Debug, Args)]
pub struct PrimitiveArgs {
    /// Sample primitive. convergence: points (1/N) sum f(x_k); segments
    /// (1/N) sum (1/L) int f along segment k; lines A (1/N) sum int f along
    /// line k, offsets from a (D-1)-dimensional pattern on the plane orthogonal
    /// to the direction (A = 1 for axis directions; other directions are clipped
    /// to the unit box). spectrum: points; segments (the point spectrum times
    /// sinc^2(L nu.omega)); lines along --axis (the (D-1)-dimensional spectrum of
    /// their offsets).
    #[arg(long, value_enum, default_value_t = Primitive::Points)]
    pub primitive: Primitive,

    /// Segments only: segment length L, from 0 (points) to 2^20; segments wrap
    /// on the torus, so lengths above 1 are allowed [default: 0.1].
    #[arg(long, value_name = "L", allow_hyphen_values = true)]
    pub length: Option<f64>,

    /// One fixed direction for every segment (and, in convergence, every line),
    /// D comma-separated components (normalised) [default: convergence, the last
    /// axis (0,1 in 2D, 0,0,1 in 3D); spectrum, the x axis (1,0 in 2D)].
    #[arg(
        long,
        value_name = "X,Y[,Z]",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub direction: Option<Vec<f64>>,
}

/// Options of `linesample-lab patterns`.
/// `linesample-lab pixel-error`.
#[derive(Debug, Args)]
pub struct PixelErrorArgs {
    /// Image width in pixels (1 to 65536).
    #[arg(long, default_value_t = 128)]
    pub width: u32,

    /// Image height in pixels (1 to 65536).
    #[arg(long, default_value_t = 128)]
    pub height: u32,

    /// Samples per pixel: a power of two, with 2*ceil(log2(max(W, H))) +
    /// log2(SPP) <= 32.
    #[arg(long, default_value_t = 4)]
    pub spp: u32,

    /// Independent images averaged.
    #[arg(long, value_name = "R", default_value_t = 16)]
    pub realizations: u32,

    /// Seed of the run.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,

    /// Output folder (default: out/pixel-error).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

#[derive(Debug, Args)]
#[command(mut_arg("sampler", |a| a.required(true)))]
pub struct PatternsArgs {
    #[command(flatten)]
    pub pattern: PatternArgs,

    /// Dimension of the points, 1 to 3 (multi-jittered, cmj, pmj02 and pmj02bn: 2 only;
    /// ccvt: 2 or 3).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(1..=3))]
    pub dims: u8,

    /// Seed of the run.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,

    /// Realization index R: the points use Seed::new(SEED).realization(R).
    #[arg(long, value_name = "R", default_value_t = 0)]
    pub realization: u64,

    #[command(flatten)]
    pub shift: ShiftArgs,

    /// Output folder; writes OUT/points.txt and OUT/points.svg, creating it
    /// (default: `out/patterns/<sampler>-<dims>d-<N>`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Options of `linesample-lab gallery`.
#[derive(Clone, Debug, Args)]
pub struct GalleryArgs {
    /// Output folder for the pattern files and index.csv (`--out-dir` is
    /// an alias); its state is kept in OUT.state/.
    #[arg(
        long = "out",
        visible_alias = "out-dir",
        value_name = "DIR",
        default_value = "out/patterns"
    )]
    pub out_dir: PathBuf,

    /// Timed fills per pattern; the table reports the median.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub runs: u32,

    /// Realisations R averaged into each pattern's spectrum (0: no spectra).
    #[arg(
        long,
        value_name = "R",
        default_value_t = 16,
        visible_alias = "spectrum-realisations"
    )]
    pub spectrum_realizations: u64,

    #[command(flatten)]
    pub run: RunArgs,
}

/// Options of `linesample-lab spectrum`.
#[derive(Debug, Args)]
#[command(
    mut_arg("sampler", |a| a.required_unless_present("input")),
    group(
        ArgGroup::new("generated")
            .multiple(true)
            .args(["sampler", "dims", "n", "strata", "grid", "relative_radius", "bridson", "seed", "realizations"])
            .conflicts_with("input")
    )
)]
pub struct SpectrumArgs {
    #[command(flatten)]
    pub pattern: PatternArgs,

    /// Dimension D of the points, 1 to 3 (multi-jittered, cmj, pmj02 and
    /// pmj02bn: 2 only; ccvt: 2 or 3;
    /// lines: 2 or 3) [default: 2]. With --input, D is the files' column count.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=3))]
    pub dims: Option<u8>,

    #[command(flatten)]
    pub primitive: PrimitiveArgs,

    /// Lines only: the axis of the lines, 0 to D-1 [default: 0, the x axis].
    #[arg(long, value_name = "A")]
    pub axis: Option<usize>,

    /// Half-width of the frequency grid [-k, k]^D' (D' = D, or D-1 for lines)
    /// [default: the largest k with 2k+1 <= 10*sqrt(N), at most 65536 in 1D,
    /// 1024 in 2D and 64 in 3D].
    #[arg(long = "k", value_name = "K")]
    pub k: Option<usize>,

    /// Number of independent realisations R [default: 16].
    #[arg(long, value_name = "R", visible_alias = "realisations")]
    pub realizations: Option<u64>,

    /// How the amplitudes are computed.
    #[arg(long, value_enum, default_value_t = spectrum::Method::Direct)]
    pub method: spectrum::Method,

    /// NUFFT only: requested relative l2 accuracy of the amplitudes, in
    /// [1e-14, 1e-1] (the accuracy/time knob: see `cargo run --release -p
    /// linesample-nufft --example nufft_bench`) [default: 1e-9].
    #[arg(long, value_name = "EPS")]
    pub tol: Option<f64>,

    /// Read the point sets from these files instead of a sampler, one
    /// realisation per file (format below).
    #[arg(long, value_name = "FILE", num_args = 1..)]
    pub input: Vec<PathBuf>,

    /// Output folder; writes OUT/spectrum.png, OUT/spectrum-radial.csv,
    /// OUT/spectrum-radial.svg and OUT/manifest.json, creating it (default:
    /// `out/spectrum/<sampler or first input's stem>-<D>d-<N>`, with
    /// `-segments` or `-lines` appended for those primitives); its state is
    /// kept in OUT.state/.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    #[command(flatten)]
    pub run: RunArgs,
}

/// `--integrand` and its parameters.
#[derive(Clone, Debug, Args)]
pub struct IntegrandArgs {
    /// Integrand whose integral over the unit torus is estimated.
    #[arg(long, value_enum, default_value_t = IntegrandKind::Disk)]
    pub integrand: IntegrandKind,

    /// Disk and ball: radius, in [1e-100, 1/2] [default: 0.25].
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub radius: Option<f64>,

    /// Gaussian: standard deviation (the kernel accepts 1e-6 to 1e6) [default:
    /// 0.1].
    #[arg(long, value_name = "SIGMA", allow_hyphen_values = true)]
    pub sigma: Option<f64>,

    /// Edge: normal of the edge, D comma-separated components (normalised to unit
    /// length) [default: 0.7,1 in 2D, 0.7,1,0.4 in 3D].
    #[arg(
        long,
        value_name = "X,Y[,Z]",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub normal: Option<Vec<f64>>,

    /// Edge: offset h of the edge n.x >= h along the unit normal [default: 0.6].
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub offset: Option<f64>,
}

/// Options of `linesample-lab paper` (`--shift` is hidden: the paper
/// homogenises every curve itself and refuses the option).
#[derive(Debug, Args)]
#[command(mut_arg("shift", |a| a.hide(true)))]
pub struct PaperArgs {
    /// Output folder [default: out/paper]; its state is kept in OUT.state/.
    #[arg(long, value_name = "OUT")]
    pub out: Option<PathBuf>,

    /// Publication quality: more N and more realisations (same as --mode full).
    #[arg(long)]
    pub full: bool,

    /// quick (default), full, or reduced (a small end-to-end check of every
    /// output; its verdicts use fewer realisations).
    #[arg(long, value_enum, value_name = "MODE")]
    pub mode: Option<Mode>,

    #[command(flatten)]
    pub run: RunArgs,
}

/// Options of `linesample-lab convergence`.
#[derive(Debug, Args)]
#[command(
    mut_arg("direction", |a| a.conflicts_with_all(["random_direction", "groups"])),
)]
pub struct ConvergenceArgs {
    #[command(flatten)]
    pub integrand: IntegrandArgs,

    /// Dimension D of the domain, 2 or 3.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub dims: u8,

    #[command(flatten)]
    pub primitive: PrimitiveArgs,

    /// Segments and lines: an independent uniformly random direction per
    /// primitive.
    #[arg(long, conflicts_with = "groups")]
    pub random_direction: bool,

    /// Segments and lines: K direction groups, each with its own independent
    /// realisation of the pattern holding N/K primitives; the estimate is the
    /// mean of the group estimates. 2D: the angles k*pi/K from the x axis,
    /// k = 0..K-1. 3D: a Fibonacci spiral on the upper hemisphere starting at the
    /// z axis, z_k = 1 - k/K, azimuth k*pi*(3 - sqrt 5).
    #[arg(long, value_name = "K")]
    pub groups: Option<usize>,

    /// Pattern of the points, the segment centres, or the line offsets (lines use
    /// a (D-1)-dimensional pattern). Poisson disk uses --relative-radius times the
    /// densest-packing radius for N.
    #[arg(long, value_enum, default_value_t = Sampler::Jittered)]
    pub sampler: Sampler,

    #[command(flatten)]
    pub poisson: PoissonArgs,

    /// Sample counts N (primitives per realisation, all groups together),
    /// comma-separated. Jittered needs m^d' points per pattern (d' = D, or D-1
    /// for lines): each N is rounded to the nearest such count, and a note says
    /// so. With --groups K each N is rounded to a multiple of K.
    #[arg(
        short = 'n',
        long = "n",
        value_name = "N1,N2,..",
        value_delimiter = ',',
        default_values_t = convergence::DEFAULT_NS
    )]
    pub n: Vec<usize>,

    /// Number of independent realisations R per N (at least 4).
    #[arg(
        long,
        value_name = "R",
        visible_alias = "realizations",
        default_value_t = 1000
    )]
    pub realisations: u64,

    /// Output folder; writes OUT/convergence.csv, OUT/convergence.svg and
    /// OUT/manifest.json, creating it (default:
    /// `out/convergence/<integrand>-<dims>d-<primitive>-<sampler>`); its
    /// state is kept in OUT.state/.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    #[command(flatten)]
    pub run: RunArgs,
}

impl MergeArgs {
    /// The experiments' form of the request.
    #[must_use]
    pub fn request(&self) -> crate::spec::MergeRequest {
        crate::spec::MergeRequest {
            out: self.out.clone(),
            shards: self.shards.clone(),
            quiet: self.quiet,
        }
    }
}

/// Options of `linesample-lab merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Where the merged outputs go: the --out folder an unsharded run would
    /// have used.
    #[arg(long, value_name = "OUT")]
    pub out: PathBuf,

    /// The --out of every shard run.
    #[arg(value_name = "SHARD", required = true, num_args = 1..)]
    pub shards: Vec<PathBuf>,

    /// No progress lines.
    #[arg(long)]
    pub quiet: bool,
}

/// `COLSxROWS` → `(COLS, ROWS)`.
///
/// # Errors
/// [`LabError::Usage`] showing the expected form.
pub fn parse_grid(s: &str) -> Result<(usize, usize)> {
    let bad = || {
        LabError::Usage(format!(
            "expected COLSxROWS with two positive integers, e.g. 32x32 (got '{s}')"
        ))
    };
    let (c, r) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let c = c.trim().parse().map_err(|_| bad())?;
    let r = r.trim().parse().map_err(|_| bad())?;
    Ok((c, r))
}

/// Runs the parsed command line.
///
/// # Errors
/// The command's error ([`LabError::Stopped`] when a signal stopped it).
pub fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Some(Command::Paper(a)) => commands::paper::main(&a),
        Some(Command::Patterns(a)) => commands::patterns::main(&a),
        Some(Command::Gallery(a)) => commands::gallery::main(&a),
        Some(Command::Spectrum(a)) => commands::spectrum::main(&a),
        Some(Command::Convergence(a)) => commands::convergence::main(&a),
        Some(Command::Merge(a)) => crate::experiments::merge(&a.request()),
        Some(Command::Scene(a)) => commands::scene::main(&a),
        Some(Command::PixelError(a)) => commands::pixel_error::main(&a),
        None => commands::gallery::main(&commands::gallery::default_args()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn grid_parsing() {
        assert_eq!(parse_grid("32x16").unwrap(), (32, 16));
        assert_eq!(parse_grid("4X4").unwrap(), (4, 4));
        assert!(parse_grid("32").is_err());
        assert!(parse_grid("ax2").is_err());
    }

    #[test]
    fn shared_options_parse_everywhere() {
        let c = Cli::try_parse_from([
            "lab",
            "patterns",
            "--sampler",
            "random",
            "--shift",
            "--realization",
            "3",
        ])
        .unwrap();
        match c.command {
            Some(Command::Patterns(a)) => {
                assert_eq!(a.shift.shift, Some(ShiftMode::Random));
                assert_eq!(a.realization, 3);
            }
            other => panic!("{other:?}"),
        }
        assert!(
            Cli::try_parse_from(["lab", "patterns"]).is_err(),
            "--sampler is required"
        );
        assert!(
            Cli::try_parse_from(["lab", "spectrum"]).is_err(),
            "--sampler or --input"
        );
        assert!(
            Cli::try_parse_from(["lab", "spectrum", "--input", "a", "--sampler", "random"])
                .is_err()
        );
        assert!(Cli::try_parse_from(["lab", "spectrum", "--input", "a", "--seed", "3"]).is_err());
        assert!(Cli::try_parse_from(["lab", "spectrum", "--input", "a"]).is_ok());
        let c = Cli::try_parse_from([
            "lab",
            "convergence",
            "--shift",
            "none",
            "--shard",
            "2/3",
            "--threads",
            "2",
        ])
        .unwrap();
        match c.command {
            Some(Command::Convergence(a)) => {
                let o = a.run.options();
                assert_eq!(o.shard, Some(Shard { index: 2, count: 3 }));
                assert_eq!(o.threads, Some(2));
                assert_eq!(a.run.shift_or(ShiftMode::Random), ShiftMode::None);
            }
            other => panic!("{other:?}"),
        }
        assert!(Cli::try_parse_from(["lab", "convergence", "--threads", "0"]).is_err());
        assert!(Cli::try_parse_from(["lab", "convergence", "--threads", "1025"]).is_err());
        assert!(
            Cli::try_parse_from(["lab", "convergence", "--direction", "1,0", "--groups", "2"])
                .is_err()
        );
        assert!(Cli::try_parse_from(["lab", "gallery", "--shard", "3/2"]).is_err());
    }
}
