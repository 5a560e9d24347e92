//! `scene FILE` for a `volumetric-caustic` scene: photon points against
//! photon beams ([`linesample_scene::caustic`]) for the power a glass
//! ball focuses into a query ball `Q` of a homogeneous medium, in 2D
//! (flatland) or 3D. Nothing else is simulated.
//!
//! 1. **Fluence image** (not resumable: seconds), into `OUT/`: the beams of
//!    a jittered pattern of `[fluence] beams` emission samples, each
//!    integrated in closed form over every pixel it crosses (2D: the plane;
//!    3D: the slab `|z − z₀| < thickness/2`), as `fluence.png` (log scale,
//!    the glass and `Q` outlined) and `fluence.json` (frame, peak, total).
//! 2. **Study** (`KIND`, runner: resumable, shardable; cells: the reference,
//!    then estimator × sampler × `N`), into `OUT/study/`: `--realisations`
//!    independent estimates per row, their mean (with its z against the
//!    reference), variance and time; fitted slopes of variance vs `N` with
//!    95 % intervals, time to 1 % relative RMSE; `rows.csv`, `slopes.csv`,
//!    `convergence.svg`, `time-to-error.svg`, and `OUT/caustics.csv`
//!    (`dims,estimator,sampler,slope,slope_ci_low,slope_ci_high`).
//!
//! Patterns: points use `d`-dimensional samples `(u, s)` (emission angles,
//! then the free-flight variable), beams `(d − 1)`-dimensional `u`. Jittered
//! patterns of `N = 2^m` samples in `k` dimensions use the most balanced
//! power-of-two strata (`2^⌊m/k⌋` per axis, `2^⌈m/k⌉` on the last
//! `m mod k` axes: for points, the free-flight axis) and no shift (they
//! are unbiased as they are); Sobol′ gets a random toroidal shift per
//! realisation.
//!
//! Seeds ([`crate::streams`]): realisation `r` of row `e` (estimator ×
//! sampler, in the order of `rows.csv`) at `N` uses the stream
//! `(volumetric-caustic, dims, study, 0, e, N)` and then `r`; the
//! reference uses part `reference` and the fluence image part `fluence`,
//! with `e = N = 0`. No two rows share a stream, the 2D and 3D scenes draw
//! independent numbers, and a resumed or sharded run draws the same
//! numbers, whatever the thread count.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use linesample_scene::fluence::{splat_path2, splat_path3, Frame};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::experiments::samples::{Buffers, SamplePattern};
use crate::experiments::scene::rgb_png;
use crate::experiments::study;
use crate::experiments::{config_from, file_name, merge_to_files, run_to_files, OutputManifest};
use crate::figures::multi::{self, Multi};
use crate::fit::fit_sci;
use crate::io::{self, buffer, table, FileGroup};
use crate::runner::{RunInfo, RunOptions};
use crate::scene::CausticScene;
use crate::scene::{EffectKind, SceneSampler};
use crate::spec::MergeRequest;
use crate::spec::ShiftMode;
use crate::streams::{Part, Stream};

/// The study's runner kind.
pub const KIND: &str = "scene-caustic";

/// Realisations per parallel task.
const CHUNK: u64 = 16;

pub use linesample_scene::caustic::world::{CausticWorld as World, Estimator, Photons};

/// The scene file as read (so a resumed run refuses a changed file).
pub type CausticSource = crate::scene::SceneSource;

// ---------------------------------------------------------------- study

/// The study, every parameter resolved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyConfig {
    pub source: CausticSource,
    pub seed: u64,
    pub ns: Vec<usize>,
    pub realisations: u64,
    /// The rows: photon points or beams, each with its sampler.
    pub rows: Vec<Estimator>,
    /// Jittered beams per reference estimate.
    pub reference_beams: usize,
    pub reference_realisations: u64,
    /// `--shift` (`None`: Sobol′ shifted, the others not; [`SceneSampler::shifted`]).
    pub shift: Option<ShiftMode>,
}

/// One cell's statistics ([`study::StudyCell`]).
pub type StudyCell = study::StudyCell;

/// The study experiment ([`study::Study`] of [`StudyConfig`]).
pub type Study = study::Study<StudyConfig>;

impl study::StudySetup for StudyConfig {
    type Effect = World;
    const CHUNK: u64 = CHUNK;
    const KIND: &'static str = KIND;

    fn seed(&self) -> u64 {
        self.seed
    }

    /// The scene's one query, its ball `Q`, and the rows.
    fn queries(&self) -> crate::Result<study::Queries<World>> {
        let scene = self.source.caustic()?;
        let world = World::new(&scene)?;
        let query = study::Query {
            label: String::new(),
            stream: Stream::new(EffectKind::VolumetricCaustic, scene.dims, Part::Study),
        };
        study::Queries::new(
            world,
            vec![(query, ())],
            self.rows.clone(),
            self.shift,
            study::Counts {
                ns: self.ns.clone(),
                realisations: self.realisations,
                reference_n: self.reference_beams,
                reference_realisations: self.reference_realisations,
            },
        )
    }
}

/// The expected slope of variance vs `N` for `est` with `sampler` in a
/// `dims`-dimensional scene, and why; `None` where no rate is claimed.
#[must_use]
pub fn expected(dims: usize, est: Photons, sampler: SceneSampler) -> Option<(f64, &'static str)> {
    match (sampler, est, dims) {
        (SceneSampler::Random, _, _) => Some((-1.0, "independent samples: N^-1")),
        (SceneSampler::Jittered, Photons::Points, 2) => Some((
            -1.5,
            "2D jitter across the edges of Q in (angle, distance): N^-(1+1/2)",
        )),
        (SceneSampler::Jittered, Photons::Points, _) => Some((
            -4.0 / 3.0,
            "3D jitter across the surface of Q in (angles, distance): N^-(1+1/3)",
        )),
        (SceneSampler::Jittered, Photons::Beams, 2) => Some((
            -3.0,
            "1D jitter of a continuous beam function with square-root edges at Q: N^-3 ln N",
        )),
        (SceneSampler::Jittered, Photons::Beams, _) => Some((
            -2.0,
            "2D jitter of a continuous beam function with square-root edges along curves: N^-2 ln N",
        )),
        _ => None,
    }
}

/// How many of the largest `N` the headline slope fits.
pub const TAIL: usize = 3;

/// The range of slopes to expect when fitting around `n`: [`expected`],
/// and for beams with jitter up to the logarithm's share. A ball `Q` cuts
/// the beam function with square-root edges (the chord `2√(r² − p²)` near
/// tangency), whose derivative `∝ 1/√x` makes the strata next to an edge
/// add `Σ_k 1/k ∝ ln N`: variance `N^−3 (A + c ln N)` (2D) or
/// `N^−2 (A + c ln N)` (3D), whose local slope lies between the rate and
/// the rate `+ 1/ln N` (all of it when the edge term dominates).
#[must_use]
pub fn effective(dims: usize, est: Photons, sampler: SceneSampler, n: f64) -> Option<(f64, f64)> {
    let (e, _) = expected(dims, est, sampler)?;
    Some(
        if est == Photons::Beams && sampler == SceneSampler::Jittered {
            (e, e + 1.0 / n.ln())
        } else {
            (e, e)
        },
    )
}

/// Slack added to a slope's 95 % interval before it is called consistent
/// with the expectation: the one slack of every study's verdict.
pub use crate::experiments::study::SLOPE_SLACK;

/// Whether the interval `[lo, hi]` (widened by [`SLOPE_SLACK`]) meets the
/// expected range `[a, b]`.
#[must_use]
pub fn consistent(lo: f64, hi: f64, a: f64, b: f64) -> bool {
    lo - SLOPE_SLACK <= b && hi + SLOPE_SLACK >= a
}

/// A row of `OUT/caustics.csv`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CausticsRow {
    pub dims: usize,
    pub estimator: String,
    pub sampler: String,
    pub slope: f64,
    pub slope_ci_low: f64,
    pub slope_ci_high: f64,
}

/// A row of `OUT/study/slopes.csv`: the fit and what follows from it.
#[derive(Serialize)]
struct SlopeRow {
    dims: usize,
    estimator: &'static str,
    sampler: &'static str,
    #[serde(serialize_with = "table::sci")]
    slope: f64,
    #[serde(serialize_with = "table::sci")]
    slope_ci_low: f64,
    #[serde(serialize_with = "table::sci")]
    slope_ci_high: f64,
    /// The asymptotic rate.
    #[serde(serialize_with = "table::sci")]
    expected: f64,
    /// The other end of the expected range: the rate with its logarithm
    /// at the fitted range's middle `N` ([`effective`]).
    #[serde(serialize_with = "table::sci")]
    expected_with_log: f64,
    /// Fit over every `N`.
    #[serde(serialize_with = "table::sci")]
    slope_all: f64,
    /// Slope between the two largest `N`.
    #[serde(serialize_with = "table::sci")]
    last_slope: f64,
    /// Largest `|bias_z|` over the row's `N`.
    #[serde(serialize_with = "table::sci")]
    max_abs_bias_z: f64,
    /// `N` for a 1 % relative RMSE, read off the fit.
    #[serde(serialize_with = "table::sci")]
    n_to_1pct: f64,
    /// Seconds to a 1 % relative RMSE (one thread).
    #[serde(serialize_with = "table::sci")]
    seconds_to_1pct: f64,
}

/// The study's completion: `study/rows.csv`, `study/slopes.csv`, plots, and
/// `caustics.csv` one folder up.
///
/// # Errors
/// An output error.
pub fn complete_study(
    exp: &Study,
    cells: Vec<StudyCell>,
    info: &RunInfo,
    dir: &Path,
    quiet: bool,
) -> crate::Result<()> {
    let cfg = exp.config();
    let dims = exp.world.dimension();
    let (reference, stats) = study::analyse(&exp.layout, &cells, 0)?;
    let (rv, rse) = (reference.value, reference.se);
    let mut text = format!(
        "{dims}D caustic: reference Φ_Q = {rv:.8e} ± {rse:.1e} ({} x {} jittered beams)\n",
        cfg.reference_realisations, cfg.reference_beams
    );
    let mut rows = Vec::new();
    let mut slopes = Vec::new();
    let mut caustics = Vec::new();
    let mut series = Vec::new();
    let mut time_series = Vec::new();
    let mut failed = Vec::new();
    let nn = cfg.ns.len();
    for (e, row) in cfg.rows.iter().enumerate() {
        let (est, sampler) = (row.photons, row.sampler);
        let rs = &stats[e * nn..(e + 1) * nn];
        for r in rs {
            rows.push(study::RowRecord::new(
                "Q",
                None,
                est.name(),
                sampler.name(),
                r,
            ));
            failed.extend(r.error.clone());
        }
        // The headline fit: the largest TAIL values of N, where the strata
        // are finer than the features of Q's preimage (the smaller N show
        // the pre-asymptotic approach; `slope_all` fits every N).
        let fit = study::fit_row(rs, Some(TAIL), rv, false);
        let (slope, lo, hi) = fit.interval();
        let tail = &rs[nn.saturating_sub(TAIL)..];
        let n_mid = (tail.iter().map(|r| (r.n as f64).ln()).sum::<f64>() / tail.len() as f64).exp();
        let exp_slope = expected(dims, est, sampler).map_or(f64::NAN, |x| x.0);
        let (exp_lo, exp_hi) = effective(dims, est, sampler, n_mid).unwrap_or((f64::NAN, f64::NAN));
        let exp_text = if exp_lo == exp_hi {
            format!("{exp_lo:+.2}")
        } else {
            format!("{exp_lo:+.2} … {exp_hi:+.2}")
        };
        let label = format!("{} {}", est.name(), sampler.name());
        let _ = writeln!(
            text,
            "  {label:<18} slope {slope:+.2} [{lo:+.2}, {hi:+.2}] (expected {exp_text})  \
             all N {:+.2}  max |z| {:.2}  1 %: N ≈ {}, {} s",
            fit.slope_all,
            fit.max_abs_z,
            fit_sci(fit.n_to_1pct, 3),
            fit_sci(fit.seconds_to_1pct, 2),
        );
        slopes.push(SlopeRow {
            dims,
            estimator: est.name(),
            sampler: sampler.name(),
            slope,
            slope_ci_low: lo,
            slope_ci_high: hi,
            expected: exp_slope,
            expected_with_log: exp_hi,
            slope_all: fit.slope_all,
            last_slope: fit.last_slope,
            max_abs_bias_z: fit.max_abs_z,
            n_to_1pct: fit.n_to_1pct,
            seconds_to_1pct: fit.seconds_to_1pct,
        });
        caustics.push(CausticsRow {
            dims,
            estimator: est.name().into(),
            sampler: sampler.name().into(),
            slope,
            slope_ci_low: lo,
            slope_ci_high: hi,
        });
        time_series.push(study::time_series(label.clone(), rs, rv));
        series.push(study::convergence_series(label, rs, &fit));
    }
    let mut group = FileGroup::new();
    let title = format!("{dims}D volumetric caustic: variance vs N");
    let svg = multi::multi(&Multi {
        title: &title,
        subtitle: "photon points vs photon beams; solid: fitted power law",
        x_label: "N (photons per estimate)",
        y_label: "variance of the in-scattered power",
        series: &series,
        log_x: true,
    })?;
    group.add_bytes(dir.join("convergence.svg"), svg.as_bytes())?;
    let title = format!("{dims}D volumetric caustic: error vs time");
    let svg = multi::multi(&Multi {
        title: &title,
        subtitle: "relative RMSE of one estimate against its time (one thread)",
        x_label: "seconds per estimate",
        y_label: "relative RMSE",
        series: &time_series,
        log_x: true,
    })?;
    group.add_bytes(dir.join("time-to-error.svg"), svg.as_bytes())?;
    let comments = vec![format!(
        "scene {}; {} realisations per row; reference {rv:.10e} ± {rse:.2e}; \
         bias_z = (mean − reference)/combined SE",
        cfg.source.path, cfg.realisations
    )];
    group.add_csv(dir.join("rows.csv"), &comments, &rows)?;
    group.add_csv(dir.join("slopes.csv"), &comments, &slopes)?;
    let parent = dir.parent().unwrap_or(dir);
    group.add_csv(
        parent.join("caustics.csv"),
        &[format!(
            "slopes of variance vs N with 95 % intervals, fitted over the {TAIL} largest N \
                 (study/slopes.csv also fits every N)"
        )],
        &caustics,
    )?;
    let mut files: Vec<String> = group.targets().map(file_name).collect();
    files.push("manifest.json".into());
    let manifest = OutputManifest::new(KIND, reproduce(cfg), cfg, info, files).with_notes(&group);
    group.add_bytes(dir.join("manifest.json"), &io::json(&manifest)?)?;
    group.commit()?;
    if !quiet {
        crate::out!("{}", text.trim_end());
        crate::out!("wrote {}", parent.join("caustics.csv").display());
    }
    study::no_failures("study", &failed, &dir.join("rows.csv"))
}

fn reproduce(cfg: &StudyConfig) -> String {
    format!(
        "linesample-lab scene {} --pixel-n {} --realisations {} --reference-lines {} \
         --reference-realisations {} --seed {}",
        cfg.source.path,
        study::list(&cfg.ns),
        cfg.realisations,
        cfg.reference_beams,
        cfg.reference_realisations,
        cfg.seed
    )
}

// ---------------------------------------------------------------- image

/// `fluence.json`.
#[derive(Serialize)]
struct FluenceSummary<'a> {
    scene: &'a str,
    dims: usize,
    beams: u64,
    width: usize,
    height: usize,
    /// Scene coordinates of the image's lower-left corner and pixel size.
    x0: f64,
    y0: f64,
    pixel: [f64; 2],
    /// 3D: the slab.
    slab: Option<[f64; 2]>,
    /// Power scattered per unit volume (area in 2D) per unit emitted power,
    /// `σ_s·φ`: the brightest pixel and where it is.
    peak: f64,
    peak_at: [f64; 2],
    /// Power scattered inside the image (per unit emitted power).
    total_in_image: f64,
    seconds: f64,
}

/// A perceptual dark-to-bright colour ramp (black, purple, orange, yellow,
/// white), `v ∈ [0, 1]`.
fn ramp(v: f64) -> [u8; 3] {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [0.0, 0.0, 0.02]),
        (0.3, [0.33, 0.06, 0.43]),
        (0.6, [0.87, 0.32, 0.18]),
        (0.85, [0.99, 0.75, 0.15]),
        (1.0, [1.0, 1.0, 0.9]),
    ];
    let v = v.clamp(0.0, 1.0);
    let mut k = 0;
    while k + 2 < STOPS.len() && v > STOPS[k + 1].0 {
        k += 1;
    }
    let (a, ca) = STOPS[k];
    let (b, cb) = STOPS[k + 1];
    let t = ((v - a) / (b - a)).clamp(0.0, 1.0);
    std::array::from_fn(|j| ((ca[j] + t * (cb[j] - ca[j])) * 255.0).round() as u8)
}

/// The fluence image in colour: a log scale over four decades below the
/// peak, with outlines of the glass (grey) and Q (cyan) where the image
/// plane cuts them.
fn fluence_rgb(scene: &CausticScene, f: &Frame, grid: &[f64], peak: f64) -> Vec<[u8; 3]> {
    let fl = &scene.fluence;
    let (w, h) = (f.w, f.h);
    // Log scale over four decades below the peak.
    let lo = peak * 1e-4;
    let mut px: Vec<[u8; 3]> = grid
        .iter()
        .map(|&g| {
            if g <= lo || peak <= 0.0 {
                ramp(0.0)
            } else {
                ramp((g / lo).log10() / 4.0)
            }
        })
        .collect();
    // Outlines: the glass (grey) and Q (cyan), where the image plane cuts them.
    let slice_r = |c: &[f64; 3], r: f64| -> f64 {
        if scene.dims == 3 {
            let dz = c[2] - fl.centre[2];
            (r * r - dz * dz).max(0.0).sqrt()
        } else {
            r
        }
    };
    let outlines = [
        (
            scene.glass_centre,
            slice_r(&scene.glass_centre, scene.glass_radius),
            [150u8, 150, 150],
        ),
        (
            scene.query_centre,
            slice_r(&scene.query_centre, scene.query_radius),
            [60, 220, 255],
        ),
    ];
    for row in 0..h {
        for col in 0..w {
            let xc = f.x0 + (col as f64 + 0.5) * f.px;
            let yc = f.y0 + ((h - 1 - row) as f64 + 0.5) * f.py;
            for (c, r, colour) in &outlines {
                if *r > 0.0 {
                    let d = ((xc - c[0]).powi(2) + (yc - c[1]).powi(2)).sqrt();
                    if (d - r).abs() < 0.6 * f.px.max(f.py) {
                        px[row * w + col] = *colour;
                    }
                }
            }
        }
    }
    px
}

/// Renders the fluence image into `out` (`fluence.png`, `fluence.json`).
///
/// # Errors
/// A pattern, allocation or output error.
pub fn run_image(
    source: &CausticSource,
    resolution: Option<(u32, u32)>,
    beams: Option<u64>,
    seed: u64,
    out: &Path,
    quiet: bool,
) -> crate::Result<()> {
    let scene = source.caustic()?;
    let world = World::new(&scene)?;
    let fl = &scene.fluence;
    let (w, h) = resolution.unwrap_or((fl.width, fl.height));
    let (w, h) = (w as usize, h as usize);
    let f = Frame::new([fl.centre[0], fl.centre[1]], fl.size, w, h);
    let m = usize::try_from(beams.unwrap_or(fl.beams))
        .map_err(|_| "fluence.beams: too many for this machine")?;
    let k = scene.dims - 1;
    let m = if k == 2 {
        // A power of two for balanced strata.
        m.next_power_of_two()
    } else {
        m
    };
    let t = Instant::now();
    let pattern = SamplePattern::new(SceneSampler::Jittered, k, m, false, "fluence beams")?;
    let mut x: Vec<[f32; 3]> = Vec::new();
    let image_seed = Stream::new(EffectKind::VolumetricCaustic, scene.dims, Part::Fluence);
    pattern.fill(image_seed.seed(seed), &mut x, &mut Buffers::default())?;
    let st = scene.sigma_s + scene.sigma_a;
    let albedo = scene.sigma_s / st;
    const PARTS: usize = 16;
    let per = m.div_ceil(PARTS);
    let parts: Vec<crate::Result<Vec<f64>>> = x
        .par_chunks(per)
        .map(|chunk| {
            let mut grid = buffer::filled(w * h, 0.0f64, "fluence image")?;
            match &world {
                World::Two(c) => {
                    for p in chunk {
                        splat_path2(&mut grid, &f, &c.path([f64::from(p[0]), 0.0]), st);
                    }
                }
                World::Three(c) => {
                    let half = 0.5 * fl.thickness.unwrap_or(0.0);
                    for p in chunk {
                        let u = [f64::from(p[0]), f64::from(p[1])];
                        splat_path3(&mut grid, &f, &c.path(u), st, fl.centre[2], half);
                    }
                }
            }
            Ok(grid)
        })
        .collect();
    let mut grid = buffer::filled(w * h, 0.0f64, "fluence image")?;
    for p in parts {
        for (g, v) in grid.iter_mut().zip(p?) {
            *g += v;
        }
    }
    let cell = f.px * f.py * fl.thickness.unwrap_or(1.0);
    let scale = albedo / (m as f64 * cell);
    let mut total = 0.0;
    let (mut peak, mut at) = (0.0f64, 0usize);
    for (i, g) in grid.iter_mut().enumerate() {
        total += *g * albedo / m as f64;
        *g *= scale;
        if *g > peak {
            peak = *g;
            at = i;
        }
    }
    let seconds = t.elapsed().as_secs_f64();
    let px = fluence_rgb(&scene, &f, &grid, peak);
    let (prow, pcol) = (at / w, at % w);
    let summary = FluenceSummary {
        scene: &source.path,
        dims: scene.dims,
        beams: m as u64,
        width: w,
        height: h,
        x0: f.x0,
        y0: f.y0,
        pixel: [f.px, f.py],
        slab: fl
            .thickness
            .map(|t| [fl.centre[2] - 0.5 * t, fl.centre[2] + 0.5 * t]),
        peak,
        peak_at: [
            f.x0 + (pcol as f64 + 0.5) * f.px,
            f.y0 + ((h - 1 - prow) as f64 + 0.5) * f.py,
        ],
        total_in_image: total,
        seconds,
    };
    let mut group = FileGroup::new();
    group.add_bytes(out.join("fluence.png"), &rgb_png(w as u32, h as u32, &px)?)?;
    group.add_bytes(out.join("fluence.json"), &io::json(&summary)?)?;
    group.commit()?;
    if !quiet {
        crate::out!(
            "fluence image: {m} beams, {w}x{h}, peak σ_s·φ = {peak:.3e} at ({:.3}, {:.3}), \
             {seconds:.2} s; wrote {}",
            summary.peak_at[0],
            summary.peak_at[1],
            out.join("fluence.png").display()
        );
    }
    Ok(())
}

// ---------------------------------------------------------------- entry

/// Where `scene FILE` writes by default.
#[must_use]
pub fn default_out(file: &Path) -> PathBuf {
    crate::experiments::direct::default_out(file)
}

/// The study rows of a scene: its samplers × (points, beams).
#[must_use]
pub fn study_rows(samplers: &[SceneSampler]) -> Vec<Estimator> {
    samplers
        .iter()
        .flat_map(|&sampler| {
            [Photons::Points, Photons::Beams].map(|photons| Estimator { photons, sampler })
        })
        .collect()
}

/// The image (unless sharded), then the study.
///
/// # Errors
/// A run error.
#[allow(clippy::too_many_arguments)]
pub fn run_all(
    source: CausticSource,
    resolution: Option<(u32, u32)>,
    beams: Option<u64>,
    seed: u64,
    ns: Vec<usize>,
    realisations: u64,
    rows: Vec<Estimator>,
    reference_beams: usize,
    reference_realisations: u64,
    shift: Option<ShiftMode>,
    out: &Path,
    opts: &RunOptions,
) -> crate::Result<()> {
    if opts.shard.is_none() {
        std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
        run_image(&source, resolution, beams, seed, out, opts.quiet)?;
    }
    let exp = Study::new(StudyConfig {
        source,
        seed,
        ns,
        realisations,
        rows,
        reference_beams,
        reference_realisations,
        shift,
    })?;
    run_to_files(&exp, &out.join("study"), opts, Box::new(complete_study))
}

/// `linesample-lab merge` for caustic-study shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge(a: &MergeRequest, config: serde_json::Value) -> crate::Result<()> {
    let exp = Study::new(config_from(config, KIND)?)?;
    merge_to_files(&exp, a, Box::new(complete_study))
}

// ---------------------------------------------------------------- paper

/// The 2D scene, built into the binary.
pub const SCENE_2D: &str = include_str!("../../../scenes/caustic-2d.toml");
/// The 3D scene, built into the binary.
pub const SCENE_3D: &str = include_str!("../../../scenes/caustic-3d.toml");

/// The caustic runs of the `paper` report for `mode`, into `dir/2d` and
/// `dir/3d`: the fluence images and the studies (random and jittered).
/// Sizes: reduced 128² images from 2¹⁴ beams, N = 16, 64, 256 with R = 40;
/// quick 256², 2¹⁸ beams, N = 16 … 4096, R = 300; full 512², 2²⁰ beams,
/// N = 16 … 16384, R = 1000.
///
/// # Errors
/// A run error.
pub fn paper_runs(
    mode: crate::spec::Mode,
    seed: u64,
    dir: &Path,
    opts: &RunOptions,
) -> crate::Result<()> {
    use crate::spec::Mode;
    let (res, beams, ns, r): (u32, u64, Vec<usize>, u64) = match mode {
        Mode::Reduced => (128, 1 << 14, vec![16, 64, 256], 40),
        Mode::Quick => (256, 1 << 18, vec![16, 64, 256, 1024, 4096], 300),
        Mode::Full => (512, 1 << 20, vec![16, 64, 256, 1024, 4096, 16384], 1000),
    };
    let quiet = RunOptions {
        quiet: true,
        ..opts.clone()
    };
    for (name, text) in [("2d", SCENE_2D), ("3d", SCENE_3D)] {
        if !opts.quiet {
            crate::out!("volumetric caustic {name}: fluence image {res}x{res}, points vs beams");
        }
        let source = CausticSource {
            path: format!("scenes/caustic-{name}.toml"),
            text: text.into(),
        };
        run_all(
            source,
            Some((res, res)),
            Some(beams),
            seed,
            ns.clone(),
            r,
            study_rows(&[SceneSampler::Random, SceneSampler::Jittered]),
            1 << 16,
            64,
            None,
            &dir.join(name),
            &quiet,
        )?;
    }
    Ok(())
}
