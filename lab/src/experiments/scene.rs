//! `scene FILE`: a declarative scene's one effect (ambient occlusion here),
//! estimated with points, segments and lines, as images (`scene FILE`) or as
//! one pixel's convergence study (`scene FILE --pixel X,Y`).
//!
//! Both run through the [`crate::runner`] (resume, `--shard`, `merge`,
//! progress). Every estimate is the closed-form visibility of
//! [`linesample_scene::HalfPlane`] through [`linesample_scene::ao::sample`]: no ray is
//! traced except the camera ray that finds each pixel's shading point.
//!
//! **Images** (cells: blocks of rows). Per pixel: the reference (lines with
//! 1D-jittered azimuths, `--reference-realisations` independent sets of
//! `--reference-lines` lines: their mean, and its standard error from the
//! spread of the sets); every estimator of the image set (the scene's
//! primitives, segment lengths, with `--sampler` and `--pdf`) at each `N` of
//! a ladder (1, 2, 4, … up to `4·--n`; squares for jittered), realisation 0,
//! each timed; and the per-pixel variance of `--variance-realisations`
//! realisations at `N = --n`. The equal-time images are the ladder's images
//! whose measured time is closest (in ratio) to the lines' time at `--n`.
//!
//! **Pixel** (cells: the reference, then every estimator × sampler × `N`).
//! Each row runs `--realisations` independent realisations (fixed chunks of
//! 32 merged in order, so results do not depend on `--threads`) and records
//! mean, bias z-score, variance with its standard error, and time per
//! estimate; each estimator × sampler gets a fitted slope with its 95 %
//! interval beside the rate theory gives, and the time to a 1 % relative
//! RMSE read off the fit.
//!
//! Seeds ([`crate::streams`]): realisation `r` of row `e` (its index in
//! the study's or the images' list of estimators) at `N` at pixel
//! `i = y·W + x` uses the stream `(ambient-occlusion, 3, part, i, e, N)`
//! and then `r`, with part `study` or `image`; the references use
//! `reference` (`image-reference` for the images) with `e = N = 0`, and the
//! spectral prediction `spectrum` with `e` its job's index. No two rows,
//! pixels or parts share a stream, except that the images' f32 SIMD row
//! draws the numbers of its f64 twin (their difference is then the f32
//! rounding alone).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::experiments::images;
use crate::experiments::scene_theory;
use crate::experiments::study;
use crate::experiments::{config_from, file_name, merge_to_files, run_to_files, OutputManifest};
use crate::figures::image;
use crate::figures::multi::{self, Multi};
use crate::fit::fit_sci;
use crate::io::{self, FileGroup};
use crate::runner::{CellInfo, Ctx, Experiment, RunInfo};
use crate::scene::{self, CentrePdf, Primitive, Scene, SceneSampler};
use crate::spec::MergeRequest;
use crate::spec::ShiftMode;
use crate::streams::{Part, Stream};
pub use linesample_scene::ao::world::{EstimatorSpec, Pixel, World, SIMD_SPHERES};

/// The image experiment's name.
pub const KIND: &str = "scene";
/// The pixel study's name.
pub const PIXEL_KIND: &str = "scene-pixel";

/// Realisations per chunk of a pixel-study row.
const CHUNK: u64 = 32;

/// The `scene` output formats (its `--help`).
pub const FORMATS: &str = concat!(
    "\
Images (OUT/): reference.png (the reference, grey = AO in [0, 1], sky blue),
reference-se.png (its standard error, log grey 1e-5 black to 1e-2 white),
equal-samples-<est>.png (realisation 0 at N = --n), equal-time-<est>.png (the
ladder image closest in time to the lines at --n), variance-<est>.png (per-pixel
variance over --variance-realisations, log grey 1e-7 to 1e-1), sheet.png (all of
them: row 1 reference and equal samples, row 2 reference SE and equal time, row 3
variance; columns in the order of images.csv), images.csv (per estimator and N:
seconds, seconds per sample, mean squared error against the reference over the
pixels that hit the scene, mean variance; the equal-samples and equal-time rows
marked) and manifest.json.

Pixel (--pixel X,Y): OUT/pixel-X-Y.json with {\"reference\": {\"value\", \"se\",
\"method\"}, \"convergence\": [rows], \"slopes\": [fits]}, the same rows as
OUT/pixel-X-Y.csv, slopes as OUT/pixel-X-Y-slopes.csv, and the curves as
OUT/pixel-X-Y.svg (uniform centre density).

Direct light (OUT/): reference.png, <estimator>-n<N>.png (equal samples),
<estimator>-equal-time.png, <estimator>-variance.png (tone-mapped RGB; variance on
a log scale 8 decades below the mean E squared), orientation-map.png (red: lines
along edge 1 have the smaller variance, blue: edge 2; A and B marked), sheet.png,
images.csv (as above), pixels.json (A, B, and P1, P2 with the shadow edge's angle,
length and turn N*), orientation.csv (pixel,x,y,estimator,slope,slope_ci_low,
slope_ci_high; jittered), and OUT/pixels/: rows.csv (query,x,y,estimator,sampler,n,
realisations, mean, bias z, variance and its SE, seconds per estimate, error: the
same columns for every study), slopes.csv (fit, 95 % interval, slope of the last
two N, seconds to 1 % relative RMSE),
convergence-<pixel>.svg, time-to-error-<pixel>.svg, manifest.json.

Volumetric caustic (OUT/): fluence.png (sigma_s times the fluence, log scale over
four decades below the peak, black to white; the glass outlined grey and Q cyan;
3D: the slab of the file's thickness around z = fluence.centre[2]),
fluence.json (frame, beams, peak and where, power scattered inside the image,
seconds), caustics.csv (dims,estimator,sampler,slope,slope_ci_low,slope_ci_high:
variance vs N fitted over the three largest N, 95 % interval), and OUT/study/:
rows.csv (as for direct light, query Q), slopes.csv (the fit, the expected
rate and its log-factor end, the fit over every N, the slope of the last two N,
the largest |z|, N and seconds to 1 % relative RMSE), convergence.svg,
time-to-error.svg, manifest.json. The image is rendered again by a rerun (seconds);
the study resumes.

A study cell that fails (a kernel error or a non-finite estimate) is a row with
its error; the other rows complete and the command exits non-zero naming it.

Runs: cells kept in OUT.state/ (resume, --fresh, --shard, merge: see
`linesample-lab --help`). All files of a run are written as one group at the end.

",
    crate::files_note!()
);

/// A stream of the AO scene ([`crate::streams`]).
fn stream(part: Part) -> Stream {
    Stream::new(scene::EffectKind::AmbientOcclusion, 3, part)
}

pub use crate::scene::SceneSource;

// ---------------------------------------------------------------- images

/// The image run, every parameter resolved (`shift`: `None` or `random`
/// shift every pattern, `none` none).
pub type ImagesConfig = images::ImagesConfig<EstimatorSpec>;

/// One block of rows ([`images::ImagesCell`]).
pub type ImagesCell = images::ImagesCell;

/// The image experiment.
pub type Images = images::Images<World>;

impl images::ImageWorld for World {
    const EXPERIMENT: &'static str = KIND;
    const EFFECT: scene::EffectKind = scene::EffectKind::AmbientOcclusion;
}

/// The `N` ladder up to `max`: powers of two (squares for jittered, whose 2D
/// pattern needs `m²` points).
#[must_use]
pub fn ladder(sampler: SceneSampler, max: usize) -> Vec<usize> {
    if sampler == SceneSampler::Jittered {
        (1..).map(|k| k * k).take_while(|&n| n <= max).collect()
    } else {
        (0..)
            .map(|k| 1usize << k)
            .take_while(|&n| n <= max)
            .collect()
    }
}

fn ao_rgb(v: f32) -> [u8; 3] {
    if v.is_nan() {
        [96, 128, 176]
    } else {
        let g = (f64::from(v).clamp(0.0, 1.0) * 255.0).round() as u8;
        [g, g, g]
    }
}

fn log_rgb(v: f32, lo: f64, hi: f64) -> [u8; 3] {
    if v.is_nan() {
        [96, 128, 176]
    } else {
        let g = image::log_gray(f64::from(v).max(1e-300), lo, hi);
        [g, g, g]
    }
}

pub(crate) use images::rgb_png;

/// Writes the images, `images.csv` and `manifest.json` as one group, and
/// prints the table.
///
/// # Errors
/// An encoding or I/O error.
pub fn complete_images(
    exp: &Images,
    cells: Vec<ImagesCell>,
    info: &RunInfo,
    dir: &Path,
    quiet: bool,
) -> crate::Result<()> {
    let cfg = exp.config();
    let grid = exp.grid();
    let (w, h) = (cfg.width, cfg.height);
    let (ne, nl) = (cfg.estimators.len(), cfg.ladder.len());
    let all = images::assemble(cells, (w * h) as usize)?;
    let at_n = grid.at_n().unwrap_or(0);
    let lines = cfg
        .estimators
        .iter()
        .position(|e| e.primitive == Primitive::Lines);
    let target = all.seconds[lines.unwrap_or(0) * nl + at_n];
    let et = images::equal_time(&all.seconds, ne, nl, target);
    let pixels_hit = all.reference.iter().filter(|r| !r.is_nan()).count();
    let ao_img = |v: &[f32]| v.iter().map(|&x| ao_rgb(x)).collect::<Vec<_>>();
    let var_img = |v: &[f32]| {
        v.iter()
            .map(|&x| log_rgb(x, -7.0, -1.0))
            .collect::<Vec<_>>()
    };
    let se_img = |v: &[f32]| {
        v.iter()
            .map(|&x| log_rgb(x, -5.0, -2.0))
            .collect::<Vec<_>>()
    };
    let mut group = FileGroup::new();
    let add_png = |group: &mut FileGroup, name: String, px: &[[u8; 3]]| {
        group.add_bytes(dir.join(name), &rgb_png(w, h, px)?)
    };
    add_png(&mut group, "reference.png".into(), &ao_img(&all.reference))?;
    add_png(
        &mut group,
        "reference-se.png".into(),
        &se_img(&all.reference_se),
    )?;
    // The sheet: columns reference + estimators; rows equal samples, equal
    // time, variance.
    let mut columns = vec![vec![
        Some(ao_img(&all.reference)),
        Some(se_img(&all.reference_se)),
    ]];
    for (e, spec) in cfg.estimators.iter().enumerate() {
        let stem = spec.stem();
        let eq = ao_img(&all.images[e * nl + at_n]);
        let tm = ao_img(&all.images[e * nl + et[e]]);
        let var = var_img(&all.variance[e]);
        add_png(&mut group, format!("equal-samples-{stem}.png"), &eq)?;
        add_png(&mut group, format!("equal-time-{stem}.png"), &tm)?;
        add_png(&mut group, format!("variance-{stem}.png"), &var)?;
        columns.push(vec![Some(eq), Some(tm), Some(var)]);
    }
    let (sw, sh, sheet) = images::sheet(w, h, &columns);
    group.add_bytes(dir.join("sheet.png"), &rgb_png(sw, sh, &sheet)?)?;
    let labels: Vec<String> = cfg.estimators.iter().map(EstimatorSpec::label).collect();
    let (rows, text) = images::image_rows(&all, &grid, &labels, at_n, &et);
    let ref_var = images::reference_floor(&all);
    let comments = vec![
        format!(
            "scene {} at {w}x{h}; {pixels_hit} pixels hit the scene; estimators use sampler {} \
             and centre density {}",
            cfg.source.path,
            cfg.estimators[0].sampler.name(),
            cfg.estimators[0].pdf.name()
        ),
        format!(
            "reference: {} x {} jittered lines per pixel; mean squared SE {ref_var:.3e} \
             (the floor under every MSE)",
            cfg.reference_realisations, cfg.reference_lines
        ),
        "seconds: time of realisation 0 of each image (pattern fill and estimate) summed over \
         the cells, each cell on one thread"
            .into(),
    ];
    group.add_csv(dir.join("images.csv"), &comments, &rows)?;
    let mut files: Vec<String> = group.targets().map(file_name).collect();
    files.push("manifest.json".into());
    let manifest =
        OutputManifest::new(KIND, reproduce_images(cfg), cfg, info, files).with_notes(&group);
    group.add_bytes(dir.join("manifest.json"), &io::json(&manifest)?)?;
    group.commit()?;
    if !quiet {
        crate::out!("{}", text.trim_end());
        crate::out!(
            "reference: {} x {} jittered lines per pixel, mean squared SE {ref_var:.2e}",
            cfg.reference_realisations,
            cfg.reference_lines
        );
        crate::out!(
            "wrote {} (and the images beside it)",
            dir.join("images.csv").display()
        );
    }
    Ok(())
}

fn reproduce_images(cfg: &ImagesConfig) -> String {
    format!(
        "linesample-lab scene {} --resolution {}x{} --n {} --sampler {} --pdf {} \
         --variance-realisations {} --reference-lines {} --reference-realisations {} --seed {}{}",
        cfg.source.path,
        cfg.width,
        cfg.height,
        cfg.n,
        cfg.estimators[0].sampler.name(),
        cfg.estimators[0].pdf.name(),
        cfg.variance_realisations,
        cfg.reference_lines,
        cfg.reference_realisations,
        cfg.seed,
        if cfg.shift == Some(ShiftMode::None) {
            " --shift none"
        } else {
            ""
        }
    )
}

// ---------------------------------------------------------------- pixel

/// The pixel study, every parameter resolved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PixelConfig {
    pub source: SceneSource,
    pub width: u32,
    pub height: u32,
    pub pixel: (u32, u32),
    pub seed: u64,
    pub shift: ShiftMode,
    pub ns: Vec<usize>,
    pub realisations: u64,
    pub rows: Vec<EstimatorSpec>,
    pub reference_lines: usize,
    pub reference_realisations: u64,
    /// Realisations behind each expected periodogram of the spectral
    /// prediction (0: no prediction).
    pub spectrum_realisations: u64,
}

/// Largest `N` of a 2D pattern whose variance is predicted: the frequency
/// grid (half-width [`scene_theory::K2`]) must reach about `4√N`.
pub const PREDICT_MAX_2D: usize = 1024;
/// The `N` whose multi-jittered offset spectrum is drawn.
pub const MJ_SPECTRUM_N: usize = 256;

/// One cell of the pixel study: a measured cell ([`study::StudyCell`]) or,
/// for a prediction cell, the predicted variance of each row it serves and,
/// for the drawn multi-jittered spectrum, the mean periodogram.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PixelCell {
    pub measured: study::StudyCell,
    /// `(row, predicted variance)`.
    pub predictions: Vec<(usize, f64)>,
    /// `⟨N·P⟩` on the half grid (the drawn spectrum only).
    pub periodogram: Vec<f64>,
}

impl PixelCell {
    /// A measured cell that failed with `error`.
    #[must_use]
    pub fn failed(error: String) -> Self {
        PixelCell::measured(study::StudyCell::failed(error))
    }

    fn measured(measured: study::StudyCell) -> Self {
        PixelCell {
            measured,
            predictions: Vec::new(),
            periodogram: Vec::new(),
        }
    }
}

/// A prediction cell: one sampler's expected periodogram at one `N`, 2D
/// (points and segments) or 1D (lines).
#[derive(Clone, Copy, Debug, PartialEq)]
struct SpectrumJob {
    sampler: SceneSampler,
    lines: bool,
    n: usize,
}

/// The spectral model of the pixel: the integrand's spectra and each
/// predictable row's weights.
struct Theory {
    spectra: scene_theory::PixelSpectra,
    /// Per row: `(weights, tail)` for uniform-density rows, else `None`.
    weights: Vec<Option<(Vec<f64>, f64)>>,
}

/// The pixel study.
pub struct PixelStudy {
    config: PixelConfig,
    study: study::Queries<World>,
    cells: Vec<CellInfo>,
    jobs: Vec<SpectrumJob>,
    theory: Option<Theory>,
}

impl study::StudySetup for PixelConfig {
    type Effect = World;
    const CHUNK: u64 = CHUNK;
    const KIND: &'static str = PIXEL_KIND;

    fn seed(&self) -> u64 {
        self.seed
    }

    /// The pixel's shading point and the rows.
    fn queries(&self) -> crate::Result<study::Queries<World>> {
        let world = World::new(self.source.scene()?, self.width, self.height)?;
        let (x, y) = self.pixel;
        if x >= self.width || y >= self.height {
            return Err(format!(
                "--pixel {x},{y}: outside the {}x{} image",
                self.width, self.height
            )
            .into());
        }
        let px = world
            .pixel(x, y)
            .ok_or_else(|| format!("--pixel {x},{y}: the camera ray misses every sphere"))?;
        let query = study::Query {
            label: String::new(),
            stream: stream(Part::Study).pixel(x, y, self.width),
        };
        study::Queries::new(
            world,
            vec![(query, px)],
            self.rows.clone(),
            Some(self.shift),
            study::Counts {
                ns: self.ns.clone(),
                realisations: self.realisations,
                reference_n: self.reference_lines,
                reference_realisations: self.reference_realisations,
            },
        )
    }
}

impl PixelStudy {
    /// The study of `config`.
    ///
    /// # Errors
    /// A scene that no longer parses, a pixel outside the image or one whose
    /// camera ray misses the scene.
    pub fn new(config: PixelConfig) -> crate::Result<Self> {
        let study = study::StudySetup::queries(&config)?;
        let (world, px, layout) = (&study.world, &study.at[0], &study.layout);
        let mut cells = layout.cells();
        let mut jobs = Vec::new();
        let mut theory = None;
        if config.spectrum_realisations > 0 {
            let spectra = scene_theory::PixelSpectra::new(world, px)?;
            let mut lines_w = None;
            let weights = config
                .rows
                .iter()
                .map(|r| match r.primitive {
                    Primitive::Lines => {
                        Some(lines_w.get_or_insert_with(|| spectra.weights_1d()).clone())
                    }
                    _ if r.pdf == CentrePdf::Uniform => {
                        Some(spectra.weights_2d(r.primitive, r.length))
                    }
                    _ => None,
                })
                .collect();
            for r in &config.rows {
                if r.pdf != CentrePdf::Uniform && r.primitive != Primitive::Lines {
                    continue;
                }
                let lines = r.primitive == Primitive::Lines;
                for &n in &config.ns {
                    let job = SpectrumJob {
                        sampler: r.sampler,
                        lines,
                        n,
                    };
                    let fits = lines
                        || n <= PREDICT_MAX_2D
                        || (r.sampler == SceneSampler::MultiJittered && n == MJ_SPECTRUM_N);
                    if fits && !jobs.contains(&job) {
                        jobs.push(job);
                    }
                }
            }
            for j in &jobs {
                cells.push(CellInfo {
                    label: format!(
                        "spectrum {} {} N = {}",
                        j.sampler.name(),
                        if j.lines { "1D" } else { "2D" },
                        j.n
                    ),
                    work: config.spectrum_realisations,
                });
            }
            theory = Some(Theory { spectra, weights });
        }
        Ok(PixelStudy {
            config,
            study,
            cells,
            jobs,
            theory,
        })
    }

    fn spectrum_cell(&self, j: usize, ctx: &Ctx<'_>) -> crate::Result<PixelCell> {
        let job = self.jobs[j];
        let cfg = &self.config;
        let theory = self
            .theory
            .as_ref()
            .ok_or("internal error: a spectrum cell without a theory")?;
        let spec = EstimatorSpec {
            primitive: if job.lines {
                Primitive::Lines
            } else {
                Primitive::Points
            },
            length: 0.0,
            pdf: CentrePdf::Uniform,
            sampler: job.sampler,
            simd: false,
        };
        let seed = self.spectrum_stream(j).seed(cfg.seed);
        let chunks = cfg.spectrum_realisations.div_ceil(CHUNK) as usize;
        let parts = ctx.map_ordered(chunks, |c| {
            let r0 = c as u64 * CHUNK;
            let r1 = (r0 + CHUNK).min(cfg.spectrum_realisations);
            let np = scene_theory::mean_periodogram(&self.study.world, &spec, job.n, r0..r1, seed)?;
            ctx.advance(r1 - r0);
            Ok((np, (r1 - r0) as f64))
        })?;
        let mut np = vec![0.0; parts.first().map_or(0, |p| p.0.len())];
        for (p, w) in &parts {
            for (a, b) in np.iter_mut().zip(p) {
                *a += b * w;
            }
        }
        for a in &mut np {
            *a /= cfg.spectrum_realisations as f64;
        }
        let mut predictions = Vec::new();
        for (k, r) in cfg.rows.iter().enumerate() {
            let serves = r.sampler == job.sampler
                && (r.primitive == Primitive::Lines) == job.lines
                && (job.lines || job.n <= PREDICT_MAX_2D);
            if let (true, Some((w, tail))) = (serves, &theory.weights[k]) {
                predictions.push((k, scene_theory::predict(&np, w, *tail, job.n)));
            }
        }
        let drawn =
            !job.lines && job.sampler == SceneSampler::MultiJittered && job.n == MJ_SPECTRUM_N;
        Ok(PixelCell {
            measured: study::StudyCell {
                count: 0,
                moments: [0.0; 4],
                seconds: 0.0,
                error: None,
            },
            predictions,
            periodogram: if drawn { np } else { Vec::new() },
        })
    }

    /// The stream of measured cell `index` (the reference or a row).
    #[must_use]
    pub fn stream(&self, index: usize) -> Stream {
        self.study.layout.stream(index)
    }

    /// The stream of spectral prediction job `j`.
    fn spectrum_stream(&self, j: usize) -> Stream {
        let (x, y) = self.config.pixel;
        stream(Part::Spectrum)
            .pixel(x, y, self.config.width)
            .row(j, self.jobs[j].n)
    }

    /// The streams of the measured cells (the reference, then each row
    /// and `N`) and of the spectral predictions.
    #[must_use]
    pub fn streams(&self) -> Vec<Stream> {
        let mut v = self.study.layout.streams();
        v.extend((0..self.jobs.len()).map(|j| self.spectrum_stream(j)));
        v
    }
}

impl Experiment for PixelStudy {
    type Config = PixelConfig;
    type Cell = PixelCell;
    const KIND: &'static str = PIXEL_KIND;
    const UNIT: &'static str = "realisations";
    const PARALLEL_CELLS: bool = false;

    fn config(&self) -> &PixelConfig {
        &self.config
    }

    fn cells(&self) -> &[CellInfo] {
        &self.cells
    }

    fn run_cell(&self, index: usize, ctx: &Ctx<'_>) -> crate::Result<PixelCell> {
        let measured = self.study.layout.len();
        if index >= measured {
            return self.spectrum_cell(index - measured, ctx);
        }
        study::run_cell(&self.study, CHUNK, index, self.config.seed, ctx).map(PixelCell::measured)
    }
}

/// The convergence rate theory gives for the AO integrand at a pixel (the
/// rule of `docs/theory.md`, Convergence rates, and its AO section):
/// `(slope, log power, note)`; slope NaN where the variance is infinite.
///
/// The integrand `g(φ, θ)` is discontinuous across sphere silhouettes (curved
/// edges) and, on the torus the samples live on, across the seam `φ = 0`:
/// `g(φ + π, θ) = g(φ, −θ)` (the same half-plane, traversed the other way),
/// so `g` is not periodic in `φ` and the seam is a straight jump parallel to
/// the segments. Segments shorter than `π` do not pre-filter it, so they keep
/// the point rate of a straight edge, `N^−1.5` for jittered centres; the
/// pre-filtering of the silhouettes lowers only the constant. A whole line
/// (or a segment of length `π`) integrates `θ` out: `L(φ) = ∫ g dθ` is
/// periodic in `φ`, continuous, with square-root kinks where a half-plane
/// grazes a sphere, so `N` strata in `φ` give `N^−3 log N` and the `√N`
/// strata of 2D jitter `N^−2`. A centre density that vanishes where the
/// segment's mean does not (solid angle and cosine at `θ_c = 0`, cosine also at
/// `±π/2`) makes the second moment diverge like `∫ dθ/|θ|`: infinite variance
/// (its weight is about `ℓ²`, so it shows only for long segments).
#[must_use]
pub fn theory(spec: &EstimatorSpec) -> (f64, u32, String) {
    use std::f64::consts::PI;
    let one_d_strata = matches!(
        spec.sampler,
        SceneSampler::MultiJittered | SceneSampler::Cmj
    );
    let full = spec.primitive == Primitive::Lines
        || (spec.primitive == Primitive::Segments && spec.length >= PI - 1e-12);
    if spec.primitive == Primitive::Segments && spec.pdf != CentrePdf::Uniform {
        return (
            f64::NAN,
            0,
            format!(
                "{} centre density x segment: p(theta_c) = 0 at the normal where the segment \
                 mean is not: infinite variance (log-divergent; weight ~ l^2)",
                spec.pdf.name()
            ),
        );
    }
    if spec.sampler == SceneSampler::Random {
        return (-1.0, 0, "random: N^-1".into());
    }
    if full {
        let lines_1d = spec.primitive == Primitive::Lines || one_d_strata;
        return if lines_1d {
            (
                -3.0,
                1,
                "L(phi) periodic, C0 with square-root kinks; N strata in phi: N^-3 log N".into(),
            )
        } else if spec.sampler == SceneSampler::Jittered {
            (
                -2.0,
                0,
                "whole line as a segment, but 2D jitter has only sqrt(N) strata in phi: N^-2 \
                 (stalls)"
                    .into(),
            )
        } else {
            (
                -2.0,
                0,
                "whole line as a segment, 2D-stratified centres: N^-2".into(),
            )
        };
    }
    match spec.primitive {
        Primitive::Points => (
            -1.5,
            0,
            "2D discontinuous (silhouettes, seam): N^-1.5".into(),
        ),
        _ => (
            -1.5,
            0,
            "the seam phi = 0 is a jump parallel to the segments (g(phi+pi, theta) = \
             g(phi, -theta)), not pre-filtered: N^-1.5"
                .into(),
        ),
    }
}

/// A convergence row of the pixel study.
#[derive(Clone, Debug, Serialize)]
pub struct PixelRow {
    pub estimator: String,
    pub primitive: Primitive,
    pub length: f64,
    pub pdf: CentrePdf,
    pub sampler: SceneSampler,
    pub n: usize,
    pub realisations: u64,
    pub mean: f64,
    pub bias_z: f64,
    pub variance: f64,
    pub variance_se: f64,
    pub seconds_per_estimate: f64,
    /// The spectral prediction (uniform density; 2D patterns up to
    /// [`PREDICT_MAX_2D`]), NaN where none.
    pub predicted_variance: f64,
    /// Why the cell has no statistics (empty when it has).
    pub error: String,
}

/// A fitted slope of the pixel study.
#[derive(Clone, Debug, Serialize)]
pub struct SlopeRow {
    pub estimator: String,
    pub primitive: Primitive,
    pub length: f64,
    pub pdf: CentrePdf,
    pub sampler: SceneSampler,
    pub n_min: usize,
    pub n_max: usize,
    pub slope: f64,
    pub ci95_low: f64,
    pub ci95_high: f64,
    pub theory: f64,
    pub theory_log_power: u32,
    pub theory_note: String,
    /// Seconds per estimate to reach a relative RMSE of 1 %, from the fit
    /// and the measured cost per sample at the largest `N`.
    pub seconds_to_1pct: f64,
    /// The fit's `χ²` per degree of freedom (large: the rows do not follow
    /// one power law, e.g. a heavy-tailed estimator or a rate change).
    pub fit_chi2_dof: f64,
    /// The slope between the two largest `N`, `ln(V₂/V₁)/ln(N₂/N₁)`, and its
    /// standard error `√((SE₁/V₁)² + (SE₂/V₂)²)/ln(N₂/N₁)` (delta method).
    pub last_slope: f64,
    pub last_slope_se: f64,
    /// [`verdict`] of the row: `consistent`, `log factor`,
    /// `pre-asymptotic`, `not consistent`, `infinite variance` (the theory
    /// predicts no rate), `no fit` (fewer than two usable points) or
    /// `failed` (a cell has no statistics).
    pub verdict: String,
    /// The failed cells' errors (empty when none failed).
    pub error: String,
}

pub use crate::experiments::study::{verdict, SLOPE_SLACK};

/// The pixel study's JSON document.
#[derive(Serialize)]
struct PixelDoc<'a> {
    pixel: (u32, u32),
    shading_point: [f64; 3],
    normal: [f64; 3],
    reference: Reference,
    convergence: &'a [PixelRow],
    slopes: &'a [SlopeRow],
}

#[derive(Serialize)]
struct Reference {
    value: f64,
    se: f64,
    method: String,
}

/// Writes `pixel-X-Y.json`, `.csv`, `-slopes.csv`, `.svg` and the manifest
/// as one group, and prints the tables.
///
/// # Errors
/// An encoding or I/O error.
pub fn complete_pixel(
    exp: &PixelStudy,
    cells: Vec<PixelCell>,
    info: &RunInfo,
    dir: &Path,
    quiet: bool,
) -> crate::Result<()> {
    let cfg = &exp.config;
    let measured: Vec<study::StudyCell> = cells[..exp.study.layout.len()]
        .iter()
        .map(|c| c.measured.clone())
        .collect();
    let (ref_stats, stats) = study::analyse(&exp.study.layout, &measured, 0)?;
    let reference = Reference {
        value: ref_stats.value,
        se: ref_stats.se,
        method: format!(
            "{} realisations of {} lines with 1D-jittered azimuths (closed-form visibility)",
            cfg.reference_realisations, cfg.reference_lines
        ),
    };
    let (predicted, mj_spectrum) = predictions(exp, &cells);
    let nn = cfg.ns.len();
    let rows: Vec<PixelRow> = stats
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let spec = cfg.rows[i / nn];
            PixelRow {
                estimator: spec.label(),
                primitive: spec.primitive,
                length: spec.length,
                pdf: spec.pdf,
                sampler: spec.sampler,
                n: r.n,
                realisations: r.realisations,
                mean: r.mean,
                bias_z: r.bias_z,
                variance: r.variance,
                variance_se: r.variance_se,
                seconds_per_estimate: r.seconds,
                predicted_variance: predicted[i],
                error: r.error.clone().unwrap_or_default(),
            }
        })
        .collect();
    let mut var_max = Vec::new();
    let n_max = cfg.ns.iter().copied().max().unwrap_or(1);
    let mut slopes = Vec::new();
    let mut series = Vec::new();
    for (k, spec) in cfg.rows.iter().enumerate() {
        let rs = &stats[k * nn..(k + 1) * nn];
        let (th, lp, note) = theory(spec);
        let theory = study::Theory {
            slope: th,
            log_power: lp,
            note,
        };
        let fit = study::fit_row(rs, None, reference.value, th.is_nan());
        let (slope, lo, hi) = fit.interval();
        let errors: Vec<&str> = rs.iter().filter_map(|r| r.error.as_deref()).collect();
        slopes.push(SlopeRow {
            estimator: spec.label(),
            primitive: spec.primitive,
            length: spec.length,
            pdf: spec.pdf,
            sampler: spec.sampler,
            n_min: cfg.ns.iter().copied().min().unwrap_or(0),
            n_max,
            slope,
            ci95_low: lo,
            ci95_high: hi,
            theory: th,
            theory_log_power: lp,
            verdict: study::row_verdict(rs, &fit, &theory).into(),
            theory_note: theory.note,
            seconds_to_1pct: fit.seconds_to_1pct,
            fit_chi2_dof: fit.fit.map_or(f64::NAN, |f| f.chi2_dof),
            last_slope: fit.last_slope,
            last_slope_se: fit.last_slope_se,
            error: errors.join("; "),
        });
        var_max.push(rs[nn - 1].variance);
        if fit.fit.is_some()
            && (spec.pdf == CentrePdf::Uniform || spec.primitive == Primitive::Lines)
        {
            let mut s = study::convergence_series(spec.label(), rs, &fit);
            s.predicted = rows[k * nn..(k + 1) * nn]
                .iter()
                .filter(|r| r.predicted_variance.is_finite())
                .map(|r| (r.n as f64, r.predicted_variance))
                .collect();
            series.push(s);
        }
    }
    let (x, y) = cfg.pixel;
    let stem = format!("pixel-{x}-{y}");
    let doc = PixelDoc {
        pixel: cfg.pixel,
        shading_point: exp.study.at[0].frame.point,
        normal: exp.study.at[0].frame.normal,
        reference,
        convergence: &rows,
        slopes: &slopes,
    };
    let mut group = FileGroup::new();
    group.add_bytes(dir.join(format!("{stem}.json")), &io::json(&doc)?)?;
    let comments = vec![format!(
        "pixel ({x}, {y}) of {}; reference {:.6} +- {:.1e} ({})",
        cfg.source.path, doc.reference.value, doc.reference.se, doc.reference.method
    )];
    group.add_csv(dir.join(format!("{stem}.csv")), &comments, &rows)?;
    group.add_csv(dir.join(format!("{stem}-slopes.csv")), &comments, &slopes)?;
    let title = format!("AO at pixel ({x}, {y}): variance against N");
    let svg = multi::multi(&Multi {
        title: &title,
        subtitle: "uniform centre density; solid: fitted power law; hollow: spectral prediction",
        x_label: "N (samples per estimate)",
        y_label: "variance",
        series: &series,
        log_x: true,
    })?;
    group.add_bytes(dir.join(format!("{stem}.svg")), svg.as_bytes())?;
    if let Some(t) = &exp.theory {
        stage_theory_images(&mut group, dir, &stem, cfg, t, mj_spectrum)?;
    }
    let mut files: Vec<String> = group.targets().map(file_name).collect();
    files.push(format!("{stem}-manifest.json"));
    let manifest =
        OutputManifest::new(PIXEL_KIND, reproduce_pixel(cfg), cfg, info, files).with_notes(&group);
    group.add_bytes(
        dir.join(format!("{stem}-manifest.json")),
        &io::json(&manifest)?,
    )?;
    group.commit()?;
    if !quiet {
        print_pixel(cfg, &doc, &var_max);
        crate::out!("wrote {}", dir.join(format!("{stem}.json")).display());
    }
    let failed: Vec<String> = stats.iter().filter_map(|r| r.error.clone()).collect();
    study::no_failures("pixel study", &failed, &dir.join(format!("{stem}.json")))
}

/// Prints the pixel study's tables: the slopes with their verdicts, and
/// the spectral predictions beside the measurements.
fn print_pixel(cfg: &PixelConfig, doc: &PixelDoc<'_>, var_max: &[f64]) {
    let (x, y) = cfg.pixel;
    let (slopes, rows) = (doc.slopes, doc.convergence);
    crate::out!(
        "pixel ({x}, {y}): AO reference {:.6} ± {:.1e} ({})",
        doc.reference.value,
        doc.reference.se,
        doc.reference.method
    );
    crate::out!(
        "{:<42} {:>7} {:>18} {:>9}  {:<17}  {:>11} {:>14}  {}",
        "estimator",
        "slope",
        "95 % interval",
        "theory",
        "verdict",
        "Var(N_max)",
        "s to 1 %",
        "note"
    );
    for (s, &var_max) in slopes.iter().zip(var_max) {
        crate::out!(
            "{:<42} {:>7.2} [{:>7.2}, {:>7.2}] {:>9}  {:<17}  {:>11.3e} {:>14}  {}",
            s.estimator,
            s.slope,
            s.ci95_low,
            s.ci95_high,
            if s.theory.is_nan() {
                "-".to_string()
            } else {
                format!(
                    "{:.2}{}",
                    s.theory,
                    if s.theory_log_power > 0 { "+log" } else { "" }
                )
            },
            s.verdict,
            var_max,
            if s.verdict == "infinite variance" {
                "-".into()
            } else {
                fit_sci(s.seconds_to_1pct, 2)
            },
            if s.error.is_empty() {
                &s.theory_note
            } else {
                &s.error
            }
        );
    }
    let preds: Vec<&PixelRow> = rows
        .iter()
        .filter(|r| r.predicted_variance.is_finite())
        .collect();
    if !preds.is_empty() {
        crate::out!(
            "spectral prediction (uniform density; {} pattern realisations per spectrum):",
            cfg.spectrum_realisations
        );
        crate::out!(
            "{:<42} {:>5} {:>11} {:>10} {:>11} {:>7}",
            "estimator",
            "N",
            "measured",
            "SE",
            "predicted",
            "ratio"
        );
        for r in preds {
            crate::out!(
                "{:<42} {:>5} {:>11.3e} {:>10.2e} {:>11.3e} {:>7.3}",
                r.estimator,
                r.n,
                r.variance,
                r.variance_se,
                r.predicted_variance,
                r.predicted_variance / r.variance
            );
        }
    }
}

/// The spectral predictions of the measured rows (row-major, NaN where
/// none) and the drawn multi-jittered spectrum, from the prediction cells.
fn predictions<'a>(exp: &PixelStudy, cells: &'a [PixelCell]) -> (Vec<f64>, Option<&'a Vec<f64>>) {
    let cfg = &exp.config;
    let measured = exp.study.layout.len();
    let mut predicted = vec![f64::NAN; measured - 1];
    let mut mj_spectrum = None;
    for (j, c) in cells.iter().enumerate().skip(measured) {
        let job = exp.jobs[j - measured];
        for &(k, v) in &c.predictions {
            if let Some(i) = cfg.ns.iter().position(|&n| n == job.n) {
                predicted[k * cfg.ns.len() + i] = v;
            }
        }
        if !c.periodogram.is_empty() {
            mj_spectrum = Some(&c.periodogram);
        }
    }
    (predicted, mj_spectrum)
}

/// `log10` of a positive value as a grey level in `[lo, hi]` decades, as RGB.
fn log_px(v: f64, lo: f64, hi: f64) -> [u8; 3] {
    let g = image::log_gray(v, lo, hi);
    [g, g, g]
}

/// A half-grid spectrum of half-width `k` drawn on the full grid `[−k, k]²`
/// (`j_u` across, `j_v` up), each cell `scale × scale` pixels.
fn spectrum_png(half: &[f64], k: usize, scale: usize, lo: f64, hi: f64) -> crate::Result<Vec<u8>> {
    let grid = linesample::spectrum::Grid::<2>::new(k)
        .map_err(|e| crate::LabError::Message(e.to_string()))?;
    let side = 2 * k + 1;
    let mut px = vec![[0u8; 3]; side * side * scale * scale];
    let ki = k as i32;
    for row in 0..side {
        for col in 0..side {
            let j = [col as i32 - ki, ki - row as i32];
            let v = grid.index(j).map_or(f64::NAN, |(i, _)| half[i]);
            let c = log_px(v, lo, hi);
            for dy in 0..scale {
                let start = (row * scale + dy) * side * scale + col * scale;
                px[start..start + scale].fill(c);
            }
        }
    }
    let w = (side * scale) as u32;
    rgb_png(w, w, &px)
}

/// The pixel's integrand `f(u, v)` (and a filtered version) as an image:
/// `u` (azimuth) across, `θ = +π/2` at the top; 2 × 2 grid cells per pixel,
/// grey from 0 to the image's maximum.
fn integrand_png(f: &[f64]) -> crate::Result<Vec<u8>> {
    use scene_theory::M;
    let side = M / 2;
    let max = f.iter().copied().fold(0.0f64, f64::max).max(1e-300);
    let mut px = Vec::with_capacity(side * side);
    for row in 0..side {
        for col in 0..side {
            let b = M - 2 - 2 * row;
            let a = 2 * col;
            let v = (f[a * M + b] + f[(a + 1) * M + b] + f[a * M + b + 1] + f[(a + 1) * M + b + 1])
                / 4.0;
            let g = (v / max * 255.0).round().clamp(0.0, 255.0) as u8;
            px.push([g, g, g]);
        }
    }
    rgb_png(side as u32, side as u32, &px)
}

/// The theory images of a pixel study: the integrand over `(u, v)` and its
/// pre-filtered versions (each segment length, lines), their power spectra
/// `|ĝ(j)|²`, and the multi-jittered offsets' `⟨N·P⟩`.
fn stage_theory_images(
    group: &mut FileGroup,
    dir: &Path,
    stem: &str,
    cfg: &PixelConfig,
    t: &Theory,
    mj: Option<&Vec<f64>>,
) -> crate::Result<()> {
    let sp = &t.spectra;
    group.add_bytes(
        dir.join(format!("{stem}-integrand.png")),
        &integrand_png(&sp.f)?,
    )?;
    let mut lengths: Vec<f64> = Vec::new();
    for r in &cfg.rows {
        if r.primitive == Primitive::Segments && !lengths.contains(&r.length) {
            lengths.push(r.length);
        }
    }
    let k = scene_theory::K2;
    let grid = linesample::spectrum::Grid::<2>::new(k)
        .map_err(|e| crate::LabError::Message(e.to_string()))?;
    // |ĝ(j)|² without the half grid's multiplicity.
    let power = |w: Vec<f64>| -> Vec<f64> {
        w.iter()
            .enumerate()
            .map(|(i, x)| x / f64::from(grid.multiplicity(i)))
            .collect()
    };
    let w = power(sp.weights_2d(Primitive::Points, 0.0).0);
    group.add_bytes(
        dir.join(format!("{stem}-integrand-spectrum.png")),
        &spectrum_png(&w, k, 2, -12.0, -2.0)?,
    )?;
    for &l in &lengths {
        let spec = EstimatorSpec {
            primitive: Primitive::Segments,
            length: l,
            pdf: CentrePdf::Uniform,
            sampler: SceneSampler::Random,
            simd: false,
        };
        group.add_bytes(
            dir.join(format!("{stem}-{}.png", spec.stem())),
            &integrand_png(&sp.filtered(l))?,
        )?;
        let w = power(sp.weights_2d(Primitive::Segments, l).0);
        group.add_bytes(
            dir.join(format!("{stem}-{}-spectrum.png", spec.stem())),
            &spectrum_png(&w, k, 2, -12.0, -2.0)?,
        )?;
    }
    if let Some(np) = mj {
        group.add_bytes(
            dir.join(format!("{stem}-mj-offsets-spectrum.png")),
            &spectrum_png(np, k, 2, -2.0, 0.5)?,
        )?;
    }
    Ok(())
}

fn reproduce_pixel(cfg: &PixelConfig) -> String {
    format!(
        "linesample-lab scene {} --pixel {},{} --resolution {}x{} --pixel-n {} --realisations {} \
         --reference-lines {} --reference-realisations {} --seed {}",
        cfg.source.path,
        cfg.pixel.0,
        cfg.pixel.1,
        cfg.width,
        cfg.height,
        study::list(&cfg.ns),
        cfg.realisations,
        cfg.reference_lines,
        cfg.reference_realisations,
        cfg.seed
    )
}

// ---------------------------------------------------------------- entry

/// Every estimator row of a scene: its primitives × segment lengths ×
/// densities × samplers (lines once per sampler: they have no density).
#[must_use]
pub fn all_rows(scene: &Scene) -> Vec<EstimatorSpec> {
    let est = &scene.estimators;
    let mut rows = Vec::new();
    for &sampler in &est.samplers {
        for &primitive in &est.primitives {
            match primitive {
                Primitive::Lines => rows.push(EstimatorSpec {
                    primitive,
                    length: 0.0,
                    pdf: CentrePdf::Uniform,
                    sampler,
                    simd: false,
                }),
                Primitive::Points => {
                    for &pdf in &est.pdfs {
                        rows.push(EstimatorSpec {
                            primitive,
                            length: 0.0,
                            pdf,
                            sampler,
                            simd: false,
                        });
                    }
                }
                Primitive::Segments => {
                    for &pdf in &est.pdfs {
                        for &length in &est.segment_lengths {
                            rows.push(EstimatorSpec {
                                primitive,
                                length,
                                pdf,
                                sampler,
                                simd: false,
                            });
                        }
                    }
                }
            }
        }
    }
    rows
}

/// The estimators of the images: the scene's primitives (segments once per
/// length) with `pdf` and `sampler`, and the lines once more through the
/// kernel's `f32` SIMD batch (what accuracy costs in time).
pub(crate) fn image_estimators(
    scene: &Scene,
    pdf: CentrePdf,
    sampler: SceneSampler,
) -> Vec<EstimatorSpec> {
    let mut estimators = Vec::new();
    for &primitive in &scene.estimators.primitives {
        let e = EstimatorSpec {
            primitive,
            length: 0.0,
            pdf,
            sampler,
            simd: false,
        };
        match primitive {
            Primitive::Segments => {
                for &length in &scene.estimators.segment_lengths {
                    estimators.push(EstimatorSpec { length, ..e });
                }
            }
            Primitive::Lines => {
                estimators.push(e);
                estimators.push(EstimatorSpec { simd: true, ..e });
            }
            Primitive::Points => estimators.push(e),
        }
    }
    estimators
}

/// `linesample-lab merge` for scene image shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge(a: &MergeRequest, config: serde_json::Value) -> crate::Result<()> {
    let exp = Images::new(config_from(config, KIND)?)?;
    merge_to_files(&exp, a, Box::new(complete_images))
}

/// `linesample-lab merge` for pixel-study shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge_pixel(a: &MergeRequest, config: serde_json::Value) -> crate::Result<()> {
    let exp = PixelStudy::new(config_from(config, PIXEL_KIND)?)?;
    merge_to_files(&exp, a, Box::new(complete_pixel))
}

// ---------------------------------------------------------------- paper

/// The paper's AO scene, built into the binary (so the report does not
/// depend on the working directory).
pub const AO_SCENE: &str = include_str!("../../../scenes/ao-spheres.toml");
/// The name the built-in scene is reported under.
pub const AO_SCENE_NAME: &str = "scenes/ao-spheres.toml";
/// The pixels the paper's report studies (the authors' pixels).
pub const PAPER_PIXELS: [(u32, u32); 2] = [(410, 305), (300, 290)];

/// The AO scene runs of the `paper` report for `mode`: images at a
/// mode-sized resolution and the two paper pixels' studies, into
/// `dir` (each with its own state folder beside it: resume works as for
/// every runner command). Returns the image resolution.
///
/// Sizes: reduced 48² images, pixels with N = 16, 64 (R = 40, spectra of 8
/// realisations); quick 256² images, N = 16 … 1024 (R = 400, spectra 32);
/// full 512², N = 16 … 4096 (R = 1000, spectra 64). Images: N = 16,
/// multi-jittered, uniform centre density.
///
/// # Errors
/// A run error.
pub fn paper_runs(
    mode: crate::spec::Mode,
    seed: u64,
    dir: &Path,
    opts: &crate::runner::RunOptions,
) -> crate::Result<u32> {
    use crate::spec::Mode;
    let source = SceneSource {
        path: AO_SCENE_NAME.into(),
        text: AO_SCENE.into(),
    };
    let scene = source.scene()?;
    let (res, ns, r, spec_r): (u32, Vec<usize>, u64, u64) = match mode {
        Mode::Reduced => (48, vec![16, 64], 40, 8),
        Mode::Quick => (256, vec![16, 64, 256, 1024], 400, 32),
        Mode::Full => (512, vec![16, 64, 256, 1024, 4096], 1000, 64),
    };
    let n = 16;
    let estimators = image_estimators(&scene, CentrePdf::Uniform, SceneSampler::MultiJittered);
    let images = Images::new(ImagesConfig {
        source: source.clone(),
        width: res,
        height: res,
        seed,
        shift: Some(ShiftMode::Random),
        n,
        ladder: ladder(SceneSampler::MultiJittered, 4 * n),
        estimators,
        variance_realisations: 8,
        reference_lines: 64,
        reference_realisations: 16,
        rows_per_cell: 8,
    })?;
    let quiet = crate::runner::RunOptions {
        quiet: true,
        ..opts.clone()
    };
    if !opts.quiet {
        crate::out!("AO scene: images at {res}x{res} and pixels {PAPER_PIXELS:?}");
    }
    run_to_files(
        &images,
        &dir.join("images"),
        &quiet,
        Box::new(complete_images),
    )?;
    let rows: Vec<EstimatorSpec> = all_rows(&scene)
        .into_iter()
        .filter(|r| {
            matches!(
                r.sampler,
                SceneSampler::Jittered | SceneSampler::MultiJittered
            ) || (r.pdf == CentrePdf::Uniform
                && matches!(r.primitive, Primitive::Points | Primitive::Lines))
        })
        .collect();
    for (x, y) in PAPER_PIXELS {
        let study = PixelStudy::new(PixelConfig {
            source: source.clone(),
            width: scene.camera.width,
            height: scene.camera.height,
            pixel: (x, y),
            seed,
            shift: ShiftMode::Random,
            ns: ns.clone(),
            realisations: r,
            rows: rows.clone(),
            reference_lines: 4096,
            reference_realisations: 64,
            spectrum_realisations: spec_r,
        })?;
        run_to_files(
            &study,
            &dir.join(format!("pixel-{x}-{y}")),
            &quiet,
            Box::new(complete_pixel),
        )?;
    }
    Ok(res)
}
