//! `scene FILE` for a `direct-light` scene: direct illumination of diffuse
//! surfaces by one rectangular area light, estimated with point samples on
//! the light and with line samples across it (Billen & Dutré 2016), every
//! line integrated in closed form over its exactly visible pieces
//! ([`linesample_scene::direct_light`]). Nothing else is simulated: the
//! camera ray finds each pixel's surface point, and the only effect is the
//! light's direct irradiance there, `E = ∫ G V dA`, tinted by the surface's
//! albedo (`L = ρ/π · L_e · E`).
//!
//! Two runner experiments, one after the other, both resumable and
//! shardable:
//!
//! 1. **Images** (`KIND`, cells: blocks of rows), into `OUT/`: per pixel the
//!    reference (lines along the light's first edge, `--reference-lines`
//!    1D-jittered offsets, `--reference-realisations` independent sets),
//!    every estimator at each `N` of a ladder `1, 4, 16, …, 16·--n` (timed),
//!    and the per-pixel variance of `--variance-realisations` realisations
//!    at `N = --n`. Completion writes the tone-mapped reference, the
//!    equal-samples and equal-time images, the variance images, the map of
//!    which fixed orientation wins, `images.csv`, and `pixels.json` naming
//!    pixels A (the largest variance ratio in favour of orientation 1) and B
//!    (in favour of orientation 2).
//! 2. **Pixels** (`PIXEL_KIND`, cells: the reference, then every pixel ×
//!    estimator × `N`), into `OUT/pixels/`: the convergence of every
//!    estimator at A and B (or at `--pixel X,Y` alone) with `--realisations`
//!    independent realisations per row, fitted slopes with 95 % intervals,
//!    time to 1 % relative error, and `OUT/orientation.csv`.
//!
//! Seeds ([`crate::streams`]): realisation `r` of estimator `e` (its index
//! in the images' or the study's list) at `N` at pixel `i = y·W + x` uses
//! the stream `(direct-light, 3, part, i, e, N)` and then `r`, with part
//! `image` or `study`; the references use `image-reference` and
//! `reference` with `e = N = 0`. So no two rows or pixels share a stream
//! (but the images' f32 SIMD row draws its f64 twin's numbers, so that
//! their difference is the f32 rounding alone),
//! the studies at A and B repeat nothing the images drew, and a resumed or
//! sharded run draws the same numbers.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

pub use linesample_scene::direct_light::world::{
    estimators, image_estimators, orient_rng, DlEstimator, DlPixel, DlWorld, Seen, REFERENCE,
    SIMD_SHADOWS,
};
use serde::{Deserialize, Serialize};

use crate::experiments::images;
use crate::experiments::images::rgb_png;
use crate::experiments::study;
use crate::experiments::{config_from, file_name, merge_to_files, run_to_files, OutputManifest};
use crate::figures::multi::{self, Multi};
use crate::fit::fit_sci;
use crate::io::{self, table, FileGroup};
use crate::runner::{Experiment, RunInfo};
use crate::scene::SceneSource;
use crate::scene::{EffectKind, Orientation, Scene, SceneSampler};
use crate::spec::MergeRequest;
use crate::spec::ShiftMode;
use crate::streams::{Part, Stream};

/// The image experiment's name.
pub const KIND: &str = "scene-direct";
/// The pixel-study experiment's name.
pub const PIXEL_KIND: &str = "scene-direct-pixel";

/// Realisations per pixel-study chunk (merged in order: results do not
/// depend on the thread count).
const CHUNK: u64 = 32;

// ---------------------------------------------------------------- world

/// A stream of the direct-light scene ([`crate::streams`]).
fn stream(part: Part) -> Stream {
    Stream::new(EffectKind::DirectLight, 3, part)
}

// ---------------------------------------------------------------- images

/// The image run, every parameter resolved (`shift`: `--shift`; `None`:
/// Sobol′ shifted, the others not; the effect's [`linesample_scene::Effect::shifted`]).
pub type ImagesConfig = images::ImagesConfig<DlEstimator>;

/// One block of rows ([`images::ImagesCell`]; its `extra` is the fraction
/// of the light hidden by occluders, [`DlWorld::hidden_fraction`] with 64
/// lines).
pub type ImagesCell = images::ImagesCell;

/// The image experiment.
pub type Images = images::Images<DlWorld>;

impl images::ImageWorld for DlWorld {
    const EXPERIMENT: &'static str = KIND;
    const EFFECT: EffectKind = EffectKind::DirectLight;
}

/// The `N` ladder `1, 4, 16, …` up to `max` (squares and powers of two:
/// every sampler supports them).
#[must_use]
pub fn ladder(max: usize) -> Vec<usize> {
    (0..)
        .map(|k| 1usize << (2 * k))
        .take_while(|&n| n <= max)
        .collect()
}

/// Pixels A and B: where the first fixed orientation's variance is smallest
/// relative to the second's, and the reverse.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Chosen {
    /// `(x, y)` of A (orientation 1 wins).
    pub a: (u32, u32),
    /// `var(edge2)/var(edge1)` at A.
    pub ratio_a: f64,
    /// `(x, y)` of B (orientation 2 wins).
    pub b: (u32, u32),
    /// `var(edge2)/var(edge1)` at B.
    pub ratio_b: f64,
    /// The penumbra pixel with a shadow edge closest to parallel to the
    /// light's first edge ([`DlWorld::edge_alignment`]), when that edge is
    /// within [`PARALLEL_MAX_DEG`]: lines along edge 1 see a near-jump.
    pub parallel1: Option<Parallel>,
    /// The same for the second edge.
    pub parallel2: Option<Parallel>,
}

/// Largest angle between a shadow edge and a light edge for which the
/// pixel is studied as a parallel-edge case (P1, P2).
pub const PARALLEL_MAX_DEG: f64 = 2.0;

/// A pixel whose shadow has an edge nearly parallel to a light edge.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parallel {
    /// `(x, y)`.
    pub pixel: (u32, u32),
    /// The angle between the shadow edge and the light edge, degrees.
    pub angle_deg: f64,
    /// The length of the shadow edge on the light.
    pub length: f64,
    /// `N* = W/(ℓ sin α)`: with `N` jittered lines parallel to the light
    /// edge (offset range `W`), the edge is a ramp narrower than a stratum
    /// (a jump: `N⁻²`) for `N ≪ N*`, and a resolved kink (`N⁻³`) for
    /// `N ≫ N*`.
    pub turn_n: f64,
}

impl Chosen {
    /// The pixels to study: A, B, then P1 and P2 when found.
    #[must_use]
    pub fn study_pixels(&self) -> Vec<(String, u32, u32)> {
        let mut v = vec![
            ("A".to_string(), self.a.0, self.a.1),
            ("B".to_string(), self.b.0, self.b.1),
        ];
        for (name, p) in [("P1", self.parallel1), ("P2", self.parallel2)] {
            if let Some(p) = p {
                v.push((name.to_string(), p.pixel.0, p.pixel.1));
            }
        }
        v
    }
}

/// Finds A and B from the two fixed orientations' variance images: among
/// the penumbra pixels (occluders hide between 5 % and 95 % of the light:
/// the shadow edges whose orientation the question is about) where both
/// variances are positive and the larger one is at least `10⁻²` of the
/// image's 99th percentile of the larger one, the largest and smallest
/// ratio.
#[must_use]
pub fn choose(v1: &[f32], v2: &[f32], hidden: &[f32], width: u32) -> Option<Chosen> {
    let mut big: Vec<f32> = v1
        .iter()
        .zip(v2)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| a.max(*b))
        .collect();
    if big.is_empty() {
        return None;
    }
    big.sort_by(f32::total_cmp);
    let p99 = big[(big.len() - 1) * 99 / 100];
    let floor = 1e-2 * p99;
    let mut best_a: Option<(f64, usize)> = None;
    let mut best_b: Option<(f64, usize)> = None;
    for (i, (&a, &b)) in v1.iter().zip(v2).enumerate() {
        let penumbra = hidden[i] > 0.05 && hidden[i] < 0.95;
        if !(penumbra && a > 0.0 && b > 0.0 && a.max(b) >= floor) {
            continue;
        }
        let r = f64::from(b) / f64::from(a);
        if best_a.is_none_or(|(x, _)| r > x) {
            best_a = Some((r, i));
        }
        if best_b.is_none_or(|(x, _)| r < x) {
            best_b = Some((r, i));
        }
    }
    let (ra, ia) = best_a?;
    let (rb, ib) = best_b?;
    let at = |i: usize| ((i % width as usize) as u32, (i / width as usize) as u32);
    Some(Chosen {
        a: at(ia),
        ratio_a: ra,
        b: at(ib),
        ratio_b: rb,
        parallel1: None,
        parallel2: None,
    })
}

/// Tone map: exposure, `x/(1 + x)`-free simple clamp, sRGB gamma.
fn srgb(v: f64) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let g = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (g * 255.0 + 0.5) as u8
}

fn log_rgb(v: f32, lo: f64, hi: f64) -> [u8; 3] {
    if !v.is_finite() || v <= 0.0 {
        return [0, 0, 0];
    }
    let t = ((f64::from(v).log10() - lo) / (hi - lo)).clamp(0.0, 1.0);
    // Dark blue → yellow.
    [
        (255.0 * t) as u8,
        (255.0 * t.sqrt()) as u8,
        (255.0 * (1.0 - t) * 0.6) as u8,
    ]
}

/// Per-pixel colour data of the image: `Some(tint)` for surfaces, the
/// light's radiance for the light, `None` for nothing.
fn tints(world: &DlWorld, w: u32, h: u32) -> Vec<Option<([f64; 3], bool)>> {
    let mut v = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            v.push(match world.pixel(x, y) {
                None => None,
                Some(Seen::Light) => Some((world.radiance(), true)),
                Some(Seen::Surface(px)) => Some((world.tint(&px), false)),
            });
        }
    }
    v
}

/// The tone map of the images: per pixel the surface's tint times `E`,
/// exposed so that the reference's 99th percentile luminance maps to 1,
/// sRGB-encoded; the light white, nothing black.
struct Tone {
    tint: Vec<Option<([f64; 3], bool)>>,
    exposure: f64,
}

impl Tone {
    fn new(world: &DlWorld, w: u32, h: u32, reference: &[f32]) -> Self {
        let tint = tints(world, w, h);
        let lum = |t: [f64; 3], e: f64| (0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2]) * e;
        let mut lums: Vec<f64> = tint
            .iter()
            .zip(reference)
            .filter_map(|(t, &r)| match t {
                Some((t, false)) if r.is_finite() => Some(lum(*t, f64::from(r))),
                _ => None,
            })
            .collect();
        lums.sort_by(f64::total_cmp);
        let exposure = lums
            .get(lums.len().saturating_sub(1) * 99 / 100)
            .copied()
            .filter(|&l| l > 0.0)
            .map_or(1.0, |l| 1.0 / l);
        Tone { tint, exposure }
    }

    fn rgb(&self, e_img: &[f32]) -> Vec<[u8; 3]> {
        self.tint
            .iter()
            .zip(e_img)
            .map(|(t, &e)| match t {
                None => [0, 0, 0],
                Some((_, true)) => [255, 255, 255],
                Some((t, false)) => {
                    let e = if e.is_finite() { f64::from(e) } else { 0.0 };
                    core::array::from_fn(|k| srgb(t[k] * e * self.exposure))
                }
            })
            .collect()
    }
}

/// P1 and P2: the penumbra pixels whose shadow edge is closest to parallel
/// to each light edge, when within [`PARALLEL_MAX_DEG`].
fn parallels(world: &DlWorld, hidden: &[f32], w: u32, h: u32) -> [Option<Parallel>; 2] {
    type Best = Option<((u32, u32), (f64, f64))>;
    let mut best: [Best; 2] = [None, None];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if !(hidden[i] > 0.05 && hidden[i] < 0.95) {
                continue;
            }
            let Some(Seen::Surface(px)) = world.pixel(x, y) else {
                continue;
            };
            let al = world.edge_alignment(&px);
            for k in 0..2 {
                if best[k].is_none_or(|(_, a)| al[k].0 < a.0) {
                    best[k] = Some(((x, y), al[k]));
                }
            }
        }
    }
    let [l1, l2] = world.light().lengths();
    // Lines along edge 1 have offsets across edge 2, and vice versa.
    let widths = [l2, l1];
    core::array::from_fn(|k| {
        best[k].and_then(|(pixel, (a, len))| {
            (a.to_degrees() <= PARALLEL_MAX_DEG).then(|| Parallel {
                pixel,
                angle_deg: a.to_degrees(),
                length: len,
                turn_n: widths[k] / (len * a.sin()),
            })
        })
    })
}

/// Which fixed orientation wins, per pixel: red where edge 1's variance is
/// smaller, blue where edge 2's is, brightness the log ratio (full at
/// 100×); A and B marked with white crosses.
fn orientation_map(
    v1: &[f32],
    v2: &[f32],
    chosen: Option<&Chosen>,
    w: u32,
    h: u32,
) -> Vec<[u8; 3]> {
    let mut map: Vec<[u8; 3]> = v1
        .iter()
        .zip(v2)
        .map(|(&v1, &v2)| {
            if !(v1 > 0.0 && v2 > 0.0) {
                return [0, 0, 0];
            }
            let r = (f64::from(v2) / f64::from(v1)).log10() / 2.0;
            let t = (r.abs().clamp(0.0, 1.0) * 255.0) as u8;
            if r > 0.0 {
                [t, t / 6, 0]
            } else {
                [0, t / 3, t]
            }
        })
        .collect();
    if let Some(c) = chosen {
        for (px, py) in [c.a, c.b] {
            for d in -4i32..=4 {
                for (x, y) in [(px as i32 + d, py as i32), (px as i32, py as i32 + d)] {
                    if x >= 0 && y >= 0 && (x as u32) < w && (y as u32) < h {
                        map[(y as u32 * w + x as u32) as usize] = [255, 255, 255];
                    }
                }
            }
        }
    }
    map
}

/// Prints A, B, P1 and P2.
fn print_chosen(c: &Chosen) {
    crate::out!(
        "pixel A {:?}: var(edge2)/var(edge1) = {:.3}; pixel B {:?}: {:.3}",
        c.a,
        c.ratio_a,
        c.b,
        c.ratio_b
    );
    for (name, p) in [("P1", c.parallel1), ("P2", c.parallel2)] {
        match p {
            Some(p) => crate::out!(
                "pixel {name} {:?}: a shadow edge {:.3}° from the light's edge {} \
                 (a jump for N below about {:.0})",
                p.pixel,
                p.angle_deg,
                &name[1..],
                p.turn_n
            ),
            None => crate::out!(
                "no penumbra pixel has a shadow edge within {PARALLEL_MAX_DEG}° of the \
                 light's edge {}",
                &name[1..]
            ),
        }
    }
}

/// The images' completion: PNGs, `images.csv`, `pixels.json`; returns A
/// and B.
///
/// # Errors
/// An output error.
pub fn complete_images(
    exp: &Images,
    cells: Vec<ImagesCell>,
    info: &RunInfo,
    dir: &Path,
    quiet: bool,
) -> crate::Result<Option<Chosen>> {
    let cfg = exp.config();
    let grid = exp.grid();
    let (w, h) = (cfg.width, cfg.height);
    let (ne, nl) = (cfg.estimators.len(), cfg.ladder.len());
    let all = images::assemble(cells, (w * h) as usize)?;
    let hidden = &all.extra;
    let tone = Tone::new(exp.world(), w, h, &all.reference);
    let at_n = grid.at_n().unwrap_or(0);
    // Variance images share one log scale (the reference's squared mean
    // level down 8 decades).
    let mean_ref = {
        let f: Vec<f64> = all
            .reference
            .iter()
            .filter(|x| x.is_finite() && **x > 0.0)
            .map(|&x| f64::from(x))
            .collect();
        f.iter().sum::<f64>() / f.len().max(1) as f64
    };
    let vhi = (mean_ref * mean_ref).log10();
    let var_rgb =
        |v: &[f32]| -> Vec<[u8; 3]> { v.iter().map(|&v| log_rgb(v, vhi - 8.0, vhi)).collect() };
    // Equal time: each estimator's ladder image whose time is closest (in
    // ratio) to the first line estimator's time at N = n.
    let target_e = cfg
        .estimators
        .iter()
        .position(|e| e.lines.is_some())
        .unwrap_or(0);
    let et = images::equal_time(&all.seconds, ne, nl, all.seconds[target_e * nl + at_n]);
    let labels: Vec<String> = cfg.estimators.iter().map(DlEstimator::label).collect();
    let (rows, text) = images::image_rows(&all, &grid, &labels, at_n, &et);
    let mut group = FileGroup::new();
    let add_png = |group: &mut FileGroup, name: String, px: &[[u8; 3]]| {
        group.add_bytes(dir.join(name), &rgb_png(w, h, px)?)
    };
    let ref_rgb = tone.rgb(&all.reference);
    add_png(&mut group, "reference.png".into(), &ref_rgb)?;
    // The sheet: reference + every estimator; rows: equal samples, equal
    // time, variance.
    let mut columns = vec![vec![Some(ref_rgb)]];
    for (e, label) in labels.iter().enumerate() {
        let stem = label.replace(' ', "-");
        let eq = tone.rgb(&all.images[e * nl + at_n]);
        let tm = tone.rgb(&all.images[e * nl + et[e]]);
        let var = var_rgb(&all.variance[e]);
        add_png(&mut group, format!("{stem}-n{}.png", cfg.ladder[at_n]), &eq)?;
        add_png(&mut group, format!("{stem}-equal-time.png"), &tm)?;
        add_png(&mut group, format!("{stem}-variance.png"), &var)?;
        columns.push(vec![Some(eq), Some(tm), Some(var)]);
    }
    let (sw, sh, sheet) = images::sheet(w, h, &columns);
    group.add_bytes(dir.join("sheet.png"), &rgb_png(sw, sh, &sheet)?)?;
    let fixed = |o: Orientation| cfg.estimators.iter().position(|e| e.lines == Some(o));
    let (e1, e2) = (fixed(Orientation::Edge1), fixed(Orientation::Edge2));
    let mut chosen = None;
    if let (Some(a), Some(b)) = (e1, e2) {
        chosen = choose(&all.variance[a], &all.variance[b], hidden, w);
        if let Some(c) = chosen.as_mut() {
            [c.parallel1, c.parallel2] = parallels(exp.world(), hidden, w, h);
        }
        let map = orientation_map(&all.variance[a], &all.variance[b], chosen.as_ref(), w, h);
        add_png(&mut group, "orientation-map.png".into(), &map)?;
    }
    let hit = all.reference.iter().filter(|r| r.is_finite()).count();
    let ref_var = images::reference_floor(&all);
    let comments = vec![
        format!(
            "scene {} at {w}x{h}; {hit} pixels see a surface; direct light E = ∫ G V dA per pixel",
            cfg.source.path,
        ),
        format!(
            "reference: {} x {} lines along edge 1 with jittered offsets; mean squared SE \
             {ref_var:.3e} (the floor under every MSE)",
            cfg.reference_realisations, cfg.reference_lines
        ),
        "seconds: time of realisation 0 of each image (pattern fill and estimate), summed over \
         the cells"
            .into(),
    ];
    group.add_csv(dir.join("images.csv"), &comments, &rows)?;
    group.add_bytes(dir.join("pixels.json"), &io::json(&chosen)?)?;
    let mut files: Vec<String> = group.targets().map(file_name).collect();
    files.push("manifest.json".into());
    let manifest =
        OutputManifest::new(KIND, reproduce_images(cfg), cfg, info, files).with_notes(&group);
    group.add_bytes(dir.join("manifest.json"), &io::json(&manifest)?)?;
    group.commit()?;
    if !quiet {
        crate::out!("{}", text.trim_end());
        if let Some(c) = &chosen {
            print_chosen(c);
        }
        crate::out!(
            "wrote {} (and the images beside it)",
            dir.join("images.csv").display()
        );
    }
    Ok(chosen)
}

fn reproduce_images(cfg: &ImagesConfig) -> String {
    format!(
        "linesample-lab scene {} --resolution {}x{} --n {} --sampler {} \
         --variance-realisations {} --reference-lines {} --reference-realisations {} --seed {}",
        cfg.source.path,
        cfg.width,
        cfg.height,
        cfg.n,
        cfg.estimators
            .first()
            .map_or("jittered", |e| e.sampler.name()),
        cfg.variance_realisations,
        cfg.reference_lines,
        cfg.reference_realisations,
        cfg.seed
    )
}

// ---------------------------------------------------------------- pixels

/// The pixel studies, every parameter resolved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PixelConfig {
    pub source: SceneSource,
    pub width: u32,
    pub height: u32,
    /// `(label, x, y)`: `A`, `B`, or `P` for `--pixel`.
    pub pixels: Vec<(String, u32, u32)>,
    pub seed: u64,
    pub ns: Vec<usize>,
    pub realisations: u64,
    pub estimators: Vec<DlEstimator>,
    pub reference_lines: usize,
    pub reference_realisations: u64,
    /// `--shift` (`None`: Sobol′ shifted, the others not; the effect's [`linesample_scene::Effect::shifted`]).
    pub shift: Option<ShiftMode>,
}

/// One cell: a reference or a row's statistics ([`study::StudyCell`]).
pub type PixelCell = study::StudyCell;

/// The pixel-study experiment ([`study::Study`] of [`PixelConfig`]).
pub type PixelStudy = study::Study<PixelConfig>;

impl study::StudySetup for PixelConfig {
    type Effect = DlWorld;
    const CHUNK: u64 = CHUNK;
    const KIND: &'static str = PIXEL_KIND;

    fn seed(&self) -> u64 {
        self.seed
    }

    /// The shading points of the studied pixels, and the rows.
    ///
    /// # Errors
    /// A pixel outside the image or one that sees no surface.
    fn queries(&self) -> crate::Result<study::Queries<DlWorld>> {
        let world = DlWorld::new(self.source.scene()?, self.width, self.height)?;
        let mut at = Vec::new();
        for (label, x, y) in &self.pixels {
            if *x >= self.width || *y >= self.height {
                return Err(format!(
                    "pixel {label} ({x}, {y}) is outside the {}x{} image",
                    self.width, self.height
                )
                .into());
            }
            let px = match world.pixel(*x, *y) {
                Some(Seen::Surface(px)) => *px,
                Some(Seen::Light) => {
                    return Err(format!(
                        "pixel {label} ({x}, {y}) sees the light itself: nothing to estimate"
                    )
                    .into())
                }
                None => return Err(format!("pixel {label} ({x}, {y}) sees no surface").into()),
            };
            let query = study::Query {
                label: label.clone(),
                stream: stream(Part::Study).pixel(*x, *y, self.width),
            };
            at.push((query, px));
        }
        study::Queries::new(
            world,
            at,
            self.estimators.clone(),
            self.shift,
            study::Counts {
                ns: self.ns.clone(),
                realisations: self.realisations,
                reference_n: self.reference_lines,
                reference_realisations: self.reference_realisations,
            },
        )
    }
}

/// A row of `OUT/orientation.csv`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct OrientationRow {
    pub pixel: String,
    pub x: u32,
    pub y: u32,
    pub estimator: String,
    pub slope: f64,
    pub slope_ci_low: f64,
    pub slope_ci_high: f64,
}

/// A row of `OUT/pixels/slopes.csv`: the fit and what follows from it.
#[derive(Serialize)]
struct SlopeRow {
    pixel: String,
    estimator: String,
    sampler: String,
    #[serde(serialize_with = "table::sci")]
    slope: f64,
    #[serde(serialize_with = "table::sci")]
    slope_ci_low: f64,
    #[serde(serialize_with = "table::sci")]
    slope_ci_high: f64,
    /// Slope between the two largest `N`.
    #[serde(serialize_with = "table::sci")]
    last_slope: f64,
    /// Seconds to a 1 % relative RMSE, read off the fit.
    #[serde(serialize_with = "table::sci")]
    seconds_to_1pct: f64,
}

/// The pixel studies' completion: `pixels/rows.csv`, `pixels/slopes.csv`,
/// plots, and `orientation.csv` one folder up (in `OUT`).
///
/// # Errors
/// An output error.
pub fn complete_pixels(
    exp: &PixelStudy,
    cells: Vec<PixelCell>,
    info: &RunInfo,
    dir: &Path,
    quiet: bool,
) -> crate::Result<()> {
    let cfg = exp.config();
    let layout = &exp.layout;
    let mut group = FileGroup::new();
    let mut rows = Vec::new();
    let mut slopes = Vec::new();
    let mut orientation = Vec::new();
    let mut text = String::new();
    let mut failed = Vec::new();
    let nn = cfg.ns.len();
    for (p, (label, x, y)) in cfg.pixels.iter().enumerate() {
        let (reference, stats) = study::analyse(layout, &cells, p)?;
        let rv = reference.value;
        let _ = writeln!(
            text,
            "pixel {label} ({x}, {y}): reference E = {rv:.6e} ± {:.1e} ({} x {} lines)",
            reference.se, cfg.reference_realisations, cfg.reference_lines
        );
        let mut series = Vec::new();
        let mut time_series = Vec::new();
        for (e, est) in cfg.estimators.iter().enumerate() {
            let rs = &stats[e * nn..(e + 1) * nn];
            for r in rs {
                let (e, s) = (est.name(), est.sampler.name());
                rows.push(study::RowRecord::new(label, Some((*x, *y)), &e, s, r));
                failed.extend(r.error.clone());
            }
            let fit = study::fit_row(rs, None, rv, false);
            let (slope, lo, hi) = fit.interval();
            let _ = writeln!(
                text,
                "  {:<30} slope {slope:+.2} [{lo:+.2}, {hi:+.2}]  last two N {:+.2}  \
                 time to 1 %: {} s",
                est.label(),
                fit.last_slope,
                fit_sci(fit.seconds_to_1pct, 2)
            );
            slopes.push(SlopeRow {
                pixel: label.clone(),
                estimator: est.name(),
                sampler: est.sampler.name().into(),
                slope,
                slope_ci_low: lo,
                slope_ci_high: hi,
                last_slope: fit.last_slope,
                seconds_to_1pct: fit.seconds_to_1pct,
            });
            if est.sampler == SceneSampler::Jittered {
                orientation.push(OrientationRow {
                    pixel: label.clone(),
                    x: *x,
                    y: *y,
                    estimator: est.name(),
                    slope,
                    slope_ci_low: lo,
                    slope_ci_high: hi,
                });
            }
            series.push(study::convergence_series(est.label(), rs, &fit));
            time_series.push(study::time_series(est.label(), rs, rv));
        }
        let title = format!("Direct light, pixel {label} ({x}, {y}): variance vs N");
        let svg = multi::multi(&Multi {
            title: &title,
            subtitle: "points on the light vs lines across it; solid: fitted power law",
            x_label: "N (samples per estimate)",
            y_label: "variance of E",
            series: &series,
            log_x: true,
        })?;
        group.add_bytes(dir.join(format!("convergence-{label}.svg")), svg.as_bytes())?;
        let title = format!("Direct light, pixel {label} ({x}, {y}): error vs time");
        let svg = multi::multi(&Multi {
            title: &title,
            subtitle: "relative RMSE of one estimate against its time (one thread)",
            x_label: "seconds per estimate",
            y_label: "relative RMSE",
            series: &time_series,
            log_x: true,
        })?;
        group.add_bytes(
            dir.join(format!("time-to-error-{label}.svg")),
            svg.as_bytes(),
        )?;
    }
    let comments = vec![format!(
        "scene {}; {} realisations per row; bias_z = (mean − reference)/combined SE",
        cfg.source.path, cfg.realisations
    )];
    group.add_csv(dir.join("rows.csv"), &comments, &rows)?;
    group.add_csv(dir.join("slopes.csv"), &comments, &slopes)?;
    let parent = dir.parent().unwrap_or(dir);
    group.add_csv(
        parent.join("orientation.csv"),
        &["slopes of variance vs N with 95 % intervals, jittered patterns".to_string()],
        &orientation,
    )?;
    let mut files: Vec<String> = group.targets().map(file_name).collect();
    files.push("manifest.json".into());
    let manifest =
        OutputManifest::new(PIXEL_KIND, reproduce_pixels(cfg), cfg, info, files).with_notes(&group);
    group.add_bytes(dir.join("manifest.json"), &io::json(&manifest)?)?;
    group.commit()?;
    if !quiet {
        crate::out!("{}", text.trim_end());
        crate::out!("wrote {}", parent.join("orientation.csv").display());
    }
    study::no_failures("pixel studies", &failed, &dir.join("rows.csv"))
}

fn reproduce_pixels(cfg: &PixelConfig) -> String {
    let px: Vec<String> = cfg
        .pixels
        .iter()
        .map(|(l, x, y)| format!("{l}=({x},{y})"))
        .collect();
    format!(
        "linesample-lab scene {} --resolution {}x{} --pixel-n {} --realisations {} --seed {}  \
         (pixels {})",
        cfg.source.path,
        cfg.width,
        cfg.height,
        study::list(&cfg.ns),
        cfg.realisations,
        cfg.seed,
        px.join(" ")
    )
}

// ---------------------------------------------------------------- entry

/// The pixel-study estimators: each of `samplers` × (points, lines with
/// each orientation).
#[must_use]
pub fn study_estimators(scene: &Scene, samplers: &[SceneSampler]) -> Vec<DlEstimator> {
    samplers
        .iter()
        .flat_map(|&s| estimators(scene, s))
        .collect()
}

/// Runs the images; `Some(A and B)` when complete and found.
///
/// # Errors
/// A run error.
#[allow(clippy::too_many_arguments)]
pub fn run_images(
    source: SceneSource,
    width: u32,
    height: u32,
    seed: u64,
    n: usize,
    estimators: Vec<DlEstimator>,
    variance_realisations: u64,
    reference_lines: usize,
    reference_realisations: u64,
    shift: Option<ShiftMode>,
    out: &Path,
    opts: &crate::runner::RunOptions,
) -> crate::Result<Option<Chosen>> {
    let config = ImagesConfig {
        source,
        width,
        height,
        seed,
        n,
        ladder: ladder(16 * n),
        estimators,
        variance_realisations,
        reference_lines,
        reference_realisations,
        rows_per_cell: 8,
        shift,
    };
    let exp = Images::new(config)?;
    let mut chosen = None;
    let slot = &mut chosen;
    run_to_files(
        &exp,
        out,
        opts,
        Box::new(move |e, c, i, d, q| {
            *slot = complete_images(e, c, i, d, q)?;
            Ok(())
        }),
    )?;
    Ok(chosen)
}

/// `linesample-lab merge` for direct-light image shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge(a: &MergeRequest, config: serde_json::Value) -> crate::Result<()> {
    let exp = Images::new(config_from(config, KIND)?)?;
    merge_to_files(
        &exp,
        a,
        Box::new(|e, c, i, d, q| complete_images(e, c, i, d, q).map(|_| ())),
    )
}

/// `linesample-lab merge` for direct-light pixel-study shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge_pixel(a: &MergeRequest, config: serde_json::Value) -> crate::Result<()> {
    let exp = PixelStudy::new(config_from(config, PIXEL_KIND)?)?;
    merge_to_files(&exp, a, Box::new(complete_pixels))
}

/// Where `scene FILE` writes by default.
#[must_use]
pub fn default_out(file: &Path) -> PathBuf {
    let stem = file
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from("out/scene").join(stem)
}

// ---------------------------------------------------------------- paper

/// The Cornell box scene, built into the binary (the report does not depend
/// on the working directory).
pub const CORNELL_SCENE: &str = include_str!("../../../scenes/cornell-box.toml");
/// The name the built-in scene is reported under.
pub const CORNELL_SCENE_NAME: &str = "scenes/cornell-box.toml";

/// The direct-light runs of the `paper` report for `mode`, into `dir`:
/// images (jittered, N = 16) and the studies at A, B and the
/// parallel-edge pixels (jittered and random). Sizes: reduced 48² images,
/// N = 16, 64, 256 with R = 40; quick 192², N = 16 … 1024, R = 300; full
/// 512², N = 16 … 4096, R = 1000.
///
/// # Errors
/// A run error.
pub fn paper_runs(
    mode: crate::spec::Mode,
    seed: u64,
    dir: &Path,
    opts: &crate::runner::RunOptions,
) -> crate::Result<()> {
    use crate::spec::Mode;
    let source = SceneSource {
        path: CORNELL_SCENE_NAME.into(),
        text: CORNELL_SCENE.into(),
    };
    let scene = source.scene()?;
    let (res, ns, r): (u32, Vec<usize>, u64) = match mode {
        Mode::Reduced => (48, vec![16, 64, 256], 40),
        Mode::Quick => (192, vec![16, 64, 256, 1024], 300),
        Mode::Full => (512, vec![16, 64, 256, 1024, 4096], 1000),
    };
    let quiet = crate::runner::RunOptions {
        quiet: true,
        ..opts.clone()
    };
    if !opts.quiet {
        crate::out!("Cornell box direct light: images at {res}x{res}, pixels A and B");
    }
    let chosen = run_images(
        source.clone(),
        res,
        res,
        seed,
        16,
        image_estimators(&scene, SceneSampler::Jittered),
        8,
        256,
        4,
        None,
        dir,
        &quiet,
    )?;
    let Some(chosen) = chosen else {
        return Ok(());
    };
    let pixels = chosen.study_pixels();
    let exp = PixelStudy::new(PixelConfig {
        source,
        width: res,
        height: res,
        pixels,
        seed,
        ns,
        realisations: r,
        estimators: study_estimators(&scene, &[SceneSampler::Random, SceneSampler::Jittered]),
        reference_lines: 4096,
        reference_realisations: 64,
        shift: None,
    })?;
    run_to_files(&exp, &dir.join("pixels"), &quiet, Box::new(complete_pixels))
}
