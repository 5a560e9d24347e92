//! `linesample-lab`: the experiment runner for the `linesample` kernel.
//!
//! It only orchestrates kernel calls and writes files; every sample position
//! comes from `linesample::pattern`.

mod convergence;
mod output;
mod plot;
mod png;
mod render;
mod sampler;
mod spectrum;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Parser, Subcommand};
use linesample::Seed;

use crate::sampler::{Sampler, Spec};

const FORMATS: &str = "\
Output formats:
  PREFIX.txt  one point per line, its D coordinates separated by single spaces,
              each the shortest decimal that round-trips the f32 (e.g. 0.25 0.7312012);
              every coordinate is in [0, 1). This is the point-file format the
              UTK toolkit reads.
  PREFIX.svg  scatter plot of the unit square (frame, tick labels, one <circle> per
              point) under a title naming sampler, dimension, N, seed, realization
              and shift. 1D: the points on the segment [0, 1]. 3D: the projections
              xy, xz and yz side by side (3N circles).

Every file is written to FILE.tmp in the same directory, synced, then renamed, so a
result file is either complete or absent. Errors print `error: <message>` on stderr
and exit with a non-zero code.";

/// Experiment runner for the linesample kernel: writes sample patterns as point
/// files and SVG plots, and measures how estimator variance converges with N.
///
/// Without a subcommand it runs `gallery` with its defaults.
#[derive(Debug, Parser)]
#[command(name = "linesample-lab", version, after_long_help = FORMATS)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Write one pattern as PREFIX.txt (points) and PREFIX.svg (plot).
    #[command(after_long_help = FORMATS)]
    Patterns(PatternsArgs),
    /// Write every sampler in 2D and 3D with its spectrum and an index (the
    /// default command).
    ///
    /// Samplers random, jittered, n-rooks, sobol, halton, poisson-disk (maximal
    /// dart throwing, relative radius 0.75) and ccvt in 2D and 3D, and
    /// multi-jittered and cmj in 2D (they are 2D only), all with N = 1024 points
    /// except jittered 3D, which uses N = 1000 = 10x10x10 strata. For each one it
    /// writes `OUT_DIR/<sampler>-<dims>d-<N>.txt` and `.svg` (realisation 0), and
    /// the mean periodogram of --spectrum-realizations realisations as
    /// `OUT_DIR/<sampler>-<dims>d-<N>-spectrum.png`, `-spectrum-radial.csv` and
    /// `-spectrum-radial.svg` (as `spectrum --method nufft --tol 1e-9` on the
    /// default grid; the 3D image is the slice nu_z = 0). It prints a table
    /// (sampler, dims, N, median time of --runs calls to Pattern::fill in
    /// microseconds, which excludes formatting and file output; the mean <N*P>
    /// over the low rings 1..round(sqrt(N)/4) and the high rings ceil(k/2)..k;
    /// files) and writes the same rows to OUT_DIR/index.csv (file names relative
    /// to OUT_DIR; spectrum = the spectrum files' prefix) under the header
    /// sampler,dims,n,seed,median_us,txt,svg,np_low,np_high,spectrum.
    #[command(after_long_help = FORMATS)]
    Gallery(GalleryArgs),
    /// Measure how the variance of one estimator falls as N grows; write
    /// PREFIX.csv (table) and PREFIX.svg (log-log plot).
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
    /// Homogenisation: every realisation adds its own uniform random toroidal
    /// shift (drawn from the realisation seed) to the pattern, so every estimator
    /// is unbiased and Var is the variance of the homogenised (stationary) sampling
    /// process.
    ///
    /// Parallelism: realisations run on --threads threads in fixed chunks of 32,
    /// and the chunk statistics are merged in chunk order, so the results and the
    /// CSV are bit-identical for any --threads.
    #[command(after_long_help = convergence::FORMATS)]
    Convergence(convergence::ConvergenceArgs),
    /// Measure the mean periodogram <N*P(nu)> of a pattern, of segments or lines
    /// through it, or of point sets read from files; write PREFIX.png (log-scale
    /// image), PREFIX-radial.csv and PREFIX-radial.svg (radial average).
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
    /// Parallelism: realisations run on --threads threads and are added to the
    /// accumulators in realisation order, so every output file is byte-identical
    /// for any --threads.
    #[command(after_long_help = spectrum::FORMATS)]
    Spectrum(spectrum::SpectrumArgs),
}

#[derive(Debug, Args)]
struct PatternsArgs {
    /// Sample pattern.
    #[arg(long, value_enum)]
    sampler: Sampler,

    /// Dimension of the points, 1 to 3 (multi-jittered and cmj: 2 only).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(1..=3))]
    dims: u8,

    /// Number of points N (default: 1024, or the product of --strata / --grid
    /// when those are given).
    #[arg(short = 'n', value_name = "N")]
    n: Option<usize>,

    /// Seed of the run.
    #[arg(long, default_value_t = 1)]
    seed: u64,

    /// Realization index R: the points use Seed::new(SEED).realization(R).
    #[arg(long, value_name = "R", default_value_t = 0)]
    realization: u64,

    /// Jittered only: strata per axis, one count per dimension, comma-separated
    /// (e.g. 32,32). Without it jittered uses a cubical grid (m^D = N), which
    /// needs N to be a perfect square (2D) or cube (3D).
    #[arg(long, value_name = "M1,M2,..", value_delimiter = ',')]
    strata: Option<Vec<usize>>,

    /// Multi-jittered and cmj only: grid of COLS x ROWS cells (N = COLS*ROWS),
    /// e.g. 64x16. Without it the kernel picks the most square grid with
    /// COLS*ROWS = N (COLS = the largest divisor of N not above its square root).
    #[arg(long, value_name = "COLSxROWS", value_parser = parse_grid)]
    grid: Option<(usize, usize)>,

    /// Apply the random toroidal shift (Cranley-Patterson rotation) drawn from the
    /// seed.
    #[arg(long)]
    shift: bool,

    /// Poisson disk only: minimum distance as a fraction of the densest-packing
    /// distance for N points (Lagae & Dutre 2008), in (0, 1].
    #[arg(long, value_name = "R", default_value_t = 0.75)]
    relative_radius: f64,

    /// Poisson disk only: use Bridson's algorithm instead of maximal dart throwing
    /// (Bridson is faster but not maximal, and at --relative-radius 0.75 usually
    /// fits fewer than N points, which is an error).
    #[arg(long)]
    bridson: bool,

    /// Output path prefix; writes PREFIX.txt and PREFIX.svg, creating parent
    /// directories (default: `out/patterns/<sampler>-<dims>d-<N>`).
    #[arg(long, value_name = "PREFIX")]
    out: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct GalleryArgs {
    /// Directory for the pattern files and index.csv.
    #[arg(long, value_name = "DIR", default_value = "out/patterns")]
    out_dir: PathBuf,

    /// Seed of every pattern.
    #[arg(long, default_value_t = 1)]
    seed: u64,

    /// Timed fills per pattern; the table reports the median.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    runs: u32,

    /// Realisations R averaged into each pattern's spectrum (0: no spectra).
    #[arg(
        long,
        value_name = "R",
        default_value_t = 16,
        visible_alias = "spectrum-realisations"
    )]
    spectrum_realizations: u64,

    /// Worker threads for the spectra [default: the available parallelism].
    /// The files do not depend on it.
    #[arg(long, value_name = "T")]
    threads: Option<usize>,
}

impl Default for GalleryArgs {
    fn default() -> Self {
        Self {
            out_dir: PathBuf::from("out/patterns"),
            seed: 1,
            runs: 5,
            spectrum_realizations: 16,
            threads: None,
        }
    }
}

fn parse_grid(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("expected COLSxROWS with two positive integers, e.g. 32x32 (got '{s}')");
    let (c, r) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let c = c.trim().parse().map_err(|_| bad())?;
    let r = r.trim().parse().map_err(|_| bad())?;
    Ok((c, r))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Patterns(a)) => patterns(&a),
        Some(Command::Gallery(a)) => gallery(&a),
        Some(Command::Convergence(a)) => convergence::run(&a),
        Some(Command::Spectrum(a)) => spectrum::run(&a),
        None => gallery(&GalleryArgs::default()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::FAILURE
        }
    }
}

/// One pattern generated and rendered, ready to be written.
struct Rendered {
    n: usize,
    median: Duration,
    txt: Vec<u8>,
    svg: Vec<u8>,
}

struct Run<'a> {
    spec: &'a Spec,
    seed: u64,
    realization: u64,
    runs: usize,
}

fn render(run: &Run<'_>) -> Result<Rendered, String> {
    let built = sampler::build(run.spec)?;
    let seed = Seed::new(run.seed).realization(run.realization);
    let (points, median) = built.pattern.generate(seed, run.runs)?;
    let title = format!(
        "{}, {}D, N = {}, seed {}, realization {}, shift {}{}",
        run.spec.sampler,
        run.spec.dims,
        points.len(),
        run.seed,
        run.realization,
        if run.spec.shift { "on" } else { "off" },
        built.detail.map(|d| format!(", {d}")).unwrap_or_default()
    );
    Ok(Rendered {
        n: points.len(),
        median,
        txt: render::txt(&points).into_bytes(),
        svg: render::svg(&points, &title).into_bytes(),
    })
}

pub(crate) fn with_ext(prefix: &Path, ext: &str) -> PathBuf {
    let mut s = prefix.as_os_str().to_os_string();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

fn default_stem(sampler: Sampler, dims: usize, n: usize) -> String {
    format!("{sampler}-{dims}d-{n}")
}

fn patterns(a: &PatternsArgs) -> Result<(), String> {
    let spec = Spec {
        sampler: a.sampler,
        dims: usize::from(a.dims),
        n: a.n,
        strata: a.strata.clone(),
        grid: a.grid,
        shift: a.shift,
        relative_radius: a.relative_radius,
        dart_throwing: !a.bridson,
    };
    let r = render(&Run {
        spec: &spec,
        seed: a.seed,
        realization: a.realization,
        runs: 1,
    })?;
    let prefix = match &a.out {
        Some(p) => p.clone(),
        None => Path::new("out/patterns").join(default_stem(a.sampler, spec.dims, r.n)),
    };
    if prefix.file_name().is_none() {
        return Err(format!(
            "--out {}: expected a file prefix such as out/pts, not a directory",
            prefix.display()
        ));
    }
    let (txt, svg) = (with_ext(&prefix, "txt"), with_ext(&prefix, "svg"));
    output::write_atomic(&[(txt.clone(), r.txt), (svg.clone(), r.svg)])?;
    println!(
        "wrote {} and {} ({} points)",
        txt.display(),
        svg.display(),
        r.n
    );
    Ok(())
}

/// Header of the gallery's `index.csv`.
const GALLERY_HEADER: &str = "sampler,dims,n,seed,median_us,txt,svg,np_low,np_high,spectrum";

/// The gallery's patterns: every sampler in every dimension it supports out of
/// 2 and 3, with its N.
fn gallery_entries() -> Vec<(Sampler, usize, usize)> {
    let mut v = Vec::new();
    for s in Sampler::ALL {
        for d in [2, 3] {
            if s.dims().contains(&d) {
                let n = if s == Sampler::Jittered && d == 3 {
                    1000
                } else {
                    1024
                };
                v.push((s, d, n));
            }
        }
    }
    v
}

fn gallery(a: &GalleryArgs) -> Result<(), String> {
    let mut csv = String::from(GALLERY_HEADER);
    csv.push('\n');
    let threads = a
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let spectra = a.spectrum_realizations > 0;
    let mut spectrum_ms = 0.0;
    println!(
        "{:<15} {:>4} {:>6} {:>12} {:>9} {:>9}  files",
        "sampler", "dims", "N", "median µs", "NP low", "NP high"
    );
    for (sampler, dims, n) in gallery_entries() {
        let spec = Spec {
            sampler,
            dims,
            n: Some(n),
            strata: None,
            grid: None,
            shift: false,
            relative_radius: 0.75,
            dart_throwing: true,
        };
        let r = render(&Run {
            spec: &spec,
            seed: a.seed,
            realization: 0,
            runs: a.runs as usize,
        })
        .map_err(|e| format!("gallery, {sampler} {dims}D: {e}"))?;
        let stem = default_stem(sampler, dims, r.n);
        let (txt_name, svg_name) = (format!("{stem}.txt"), format!("{stem}.svg"));
        let (txt, svg) = (a.out_dir.join(&txt_name), a.out_dir.join(&svg_name));
        output::write_atomic(&[(txt.clone(), r.txt), (svg.clone(), r.svg)])?;
        let us = r.median.as_secs_f64() * 1e6;
        let (low, high, spec_name) = if spectra {
            let stem = format!("{stem}-spectrum");
            let s = spectrum::pattern_spectrum(
                &spec,
                a.seed,
                a.spectrum_realizations,
                threads,
                a.out_dir.join(&stem),
            )
            .map_err(|e| format!("gallery, {sampler} {dims}D spectrum: {e}"))?;
            spectrum_ms += s.ms * a.spectrum_realizations as f64;
            (format!("{:.4}", s.low), format!("{:.4}", s.high), stem)
        } else {
            (String::new(), String::new(), String::new())
        };
        println!(
            "{:<15} {:>4} {:>6} {:>12.1} {:>9} {:>9}  {} {}{}",
            sampler.name(),
            dims,
            r.n,
            us,
            low,
            high,
            txt.display(),
            svg.display(),
            if spectra {
                format!(" {}.png", a.out_dir.join(&spec_name).display())
            } else {
                String::new()
            }
        );
        csv.push_str(&format!(
            "{},{dims},{},{},{us:.1},{txt_name},{svg_name},{low},{high},{spec_name}\n",
            sampler.name(),
            r.n,
            a.seed
        ));
    }
    if spectra {
        println!(
            "spectra: {} realisations each, {:.2} s of pattern generation and NUFFT in all",
            a.spectrum_realizations,
            spectrum_ms / 1e3
        );
    }
    let index = a.out_dir.join("index.csv");
    output::write_atomic(&[(index.clone(), csv.into_bytes())])?;
    println!("wrote {}", index.display());
    Ok(())
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
        assert_eq!(parse_grid("32x16"), Ok((32, 16)));
        assert_eq!(parse_grid("4X4"), Ok((4, 4)));
        assert!(parse_grid("32").is_err());
        assert!(parse_grid("ax2").is_err());
    }

    #[test]
    fn gallery_covers_every_sampler() {
        let e = gallery_entries();
        assert_eq!(e.len(), 16);
        for s in Sampler::ALL {
            assert!(e.iter().any(|&(t, d, _)| t == s && d == 2));
        }
    }

    #[test]
    fn tmp_path_is_a_sibling() {
        assert_eq!(
            output::tmp_path(Path::new("a/b/c.txt")),
            PathBuf::from("a/b/c.txt.tmp")
        );
    }
}
