//! The image run every camera effect shares (ambient occlusion, direct
//! light): per pixel a reference, every estimator at every `N` of a
//! ladder (realisation 0, timed) and the per-pixel variance at the
//! equal-samples `N`; then one assembly (images, equal time, `images.csv`
//! rows, the sheet) whatever the effect.
//!
//! An effect says only what is its own ([`Effect`](linesample_scene::Effect)): its pixels, the
//! pattern of an estimator at `N`, one estimate (and the lab its name,
//! [`ImageWorld`]). Cells
//! are blocks of rows ([`row_blocks`]). Streams: the reference of pixel
//! `(x, y)` draws `(effect, dims, image-reference, y·W + x, 0, 0)`,
//! estimator `e` at `N` draws `(effect, dims, image, y·W + x, twin(e), N)`,
//! where `twin(e)` is the row of `e`'s `f64` twin (an `f32` SIMD row draws
//! the numbers of its twin, so their difference is the rounding alone).

use std::fmt::Write as _;
use std::time::Instant;

use linesample::stats::RunningStats;
use linesample_scene::CameraEffect;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::samples::{self, SamplePattern};
use crate::figures::image::{self, Color};
use crate::io::{buffer, table};
use crate::runner::{CellInfo, Ctx, Experiment};
use crate::scene::{EffectKind, SceneSource};
use crate::spec::ShiftMode;
use crate::streams::{stream_rows, Part, Realisations, Stream};

/// The lab's side of a camera effect: the experiment's name and the
/// effect's first stream component. Everything else (the world built from
/// the scene, its pixels, the estimators' patterns, one estimate, the
/// per-pixel quantity kept beside the images) is the effect's own
/// ([`Effect`](linesample_scene::Effect)).
pub trait ImageWorld: CameraEffect<Estimator: Serialize + DeserializeOwned> {
    /// The image experiment's name (its state folder's kind).
    const EXPERIMENT: &'static str;
    /// The effect, the first component of every stream.
    const EFFECT: EffectKind;
}

/// An image run, every parameter resolved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound = "E: Serialize + DeserializeOwned")]
pub struct ImagesConfig<E> {
    pub source: SceneSource,
    pub width: u32,
    pub height: u32,
    pub seed: u64,
    /// The equal-samples `N` (on the ladder).
    pub n: usize,
    /// The `N` of every rendered image (each estimator).
    pub ladder: Vec<usize>,
    pub estimators: Vec<E>,
    pub variance_realisations: u64,
    pub reference_lines: usize,
    pub reference_realisations: u64,
    pub rows_per_cell: u32,
    /// `--shift` (`None`: the effect's default).
    pub shift: Option<ShiftMode>,
}

/// The image experiment of an effect.
pub struct Images<W: ImageWorld> {
    config: ImagesConfig<W::Estimator>,
    world: W,
    twin: Vec<usize>,
    cells: Vec<CellInfo>,
}

impl<W: ImageWorld> Images<W> {
    /// The experiment of `config`.
    ///
    /// # Errors
    /// A scene that no longer parses, or geometry the kernel refuses.
    pub fn new(config: ImagesConfig<W::Estimator>) -> crate::Result<Self> {
        let mut scene = config.source.scene()?;
        (scene.camera.width, scene.camera.height) = (config.width, config.height);
        let world = W::from_scene(scene)?;
        let cells = row_blocks(config.width, config.height, config.rows_per_cell);
        let twin = stream_rows(&config.estimators, W::twin);
        Ok(Images {
            config,
            world,
            twin,
            cells,
        })
    }

    /// The world.
    pub fn world(&self) -> &W {
        &self.world
    }

    /// The sizes of the run.
    #[must_use]
    pub fn grid(&self) -> Grid<'_> {
        let c = &self.config;
        Grid {
            width: c.width,
            height: c.height,
            seed: c.seed,
            n: c.n,
            ladder: &c.ladder,
            variance_realisations: c.variance_realisations,
            reference_lines: c.reference_lines,
            reference_realisations: c.reference_realisations,
            rows_per_cell: c.rows_per_cell,
        }
    }
}

impl<W: ImageWorld> Experiment for Images<W> {
    type Config = ImagesConfig<W::Estimator>;
    type Cell = ImagesCell;
    const KIND: &'static str = W::EXPERIMENT;
    const UNIT: &'static str = "pixels";

    fn config(&self) -> &Self::Config {
        &self.config
    }

    fn cells(&self) -> &[CellInfo] {
        &self.cells
    }

    fn run_cell(&self, index: usize, ctx: &Ctx<'_>) -> crate::Result<ImagesCell> {
        run_cell(self, index, ctx)
    }
}

/// The sizes of an image run.
#[derive(Clone, Copy, Debug)]
pub struct Grid<'a> {
    pub width: u32,
    pub height: u32,
    pub seed: u64,
    /// The equal-samples `N` (on the ladder).
    pub n: usize,
    pub ladder: &'a [usize],
    pub variance_realisations: u64,
    pub reference_lines: usize,
    pub reference_realisations: u64,
    pub rows_per_cell: u32,
}

impl Grid<'_> {
    /// The ladder index of the equal-samples `N`.
    ///
    /// # Errors
    /// `n` is not on the ladder.
    pub fn at_n(&self) -> crate::Result<usize> {
        self.ladder
            .iter()
            .position(|&n| n == self.n)
            .ok_or_else(|| "internal error: --n is not on the ladder".into())
    }
}

/// One block of rows (or, assembled, the whole image).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct ImagesCell {
    /// Reference mean per pixel (NaN: not estimated).
    pub reference: Vec<f32>,
    /// Its standard error.
    pub reference_se: Vec<f32>,
    /// [`Effect::extra`](linesample_scene::Effect::extra) per pixel (empty when the effect has none).
    pub extra: Vec<f32>,
    /// `images[e·L + l]`: estimator `e` at ladder `N_l`, per pixel.
    pub images: Vec<Vec<f32>>,
    /// Per-pixel variance of each estimator at `N = n`.
    pub variance: Vec<Vec<f32>>,
    /// Seconds spent on `images[e·L + l]`.
    pub seconds: Vec<f64>,
}

/// The cells of an image run: blocks of `rows` rows (at least 1) of a
/// `width × height` image, the last one possibly shorter.
#[must_use]
pub fn row_blocks(width: u32, height: u32, rows: u32) -> Vec<CellInfo> {
    let rows = rows.max(1);
    (0..height.div_ceil(rows))
        .map(|c| {
            let y0 = c * rows;
            let y1 = (y0 + rows).min(height);
            CellInfo {
                label: format!("rows {y0}..{y1}"),
                work: u64::from((y1 - y0) * width),
            }
        })
        .collect()
}

fn nan_images(k: usize, count: usize, what: &str) -> crate::Result<Vec<Vec<f32>>> {
    (0..k)
        .map(|_| buffer::filled(count, f32::NAN, what))
        .collect()
}

/// Computes cell `index` (a block of rows) of `exp`'s images.
///
/// # Errors
/// A pattern or kernel error.
fn run_cell<W: ImageWorld>(
    exp: &Images<W>,
    index: usize,
    ctx: &Ctx<'_>,
) -> crate::Result<ImagesCell> {
    let (cfg, world, grid) = (&exp.config, &exp.world, exp.grid());
    let rows = grid.rows_per_cell.max(1);
    let y0 = index as u32 * rows;
    let y1 = (y0 + rows).min(grid.height);
    let count = ((y1 - y0) * grid.width) as usize;
    let (ne, nl) = (cfg.estimators.len(), grid.ladder.len());
    let reference = SamplePattern::of(world, None, grid.reference_lines, cfg.shift)?;
    let mut plans = Vec::with_capacity(ne * nl);
    for e in &cfg.estimators {
        for &n in grid.ladder {
            plans.push(SamplePattern::of(world, Some(e), n, cfg.shift)?);
        }
    }
    let at_n = grid.at_n()?;
    let mut cell = ImagesCell {
        reference: buffer::filled(count, f32::NAN, "the reference image")?,
        reference_se: buffer::filled(count, f32::NAN, "the reference SE image")?,
        extra: Vec::new(),
        images: nan_images(ne * nl, count, "an image")?,
        variance: nan_images(ne, count, "a variance image")?,
        seconds: vec![0.0; ne * nl],
    };
    let mut scratch = samples::scratch(world);
    for y in y0..y1 {
        for x in 0..grid.width {
            let p = ((y - y0) * grid.width + x) as usize;
            let Some(px) = world.pixel(x, y) else {
                continue;
            };
            let base = Stream::new(W::EFFECT, 3, Part::Image).pixel(x, y, grid.width);
            let mut rs = RunningStats::new();
            let seeds = Realisations::of(
                &Stream {
                    part: Part::ImageReference,
                    ..base
                },
                grid.seed,
            );
            for r in 0..grid.reference_realisations {
                rs.push(samples::estimate(
                    world,
                    &px,
                    &reference,
                    seeds.at(r),
                    &mut scratch,
                )?);
            }
            cell.reference[p] = rs.mean() as f32;
            cell.reference_se[p] = rs.mean_std_error() as f32;
            if let Some(v) = world.extra(&px)? {
                if cell.extra.is_empty() {
                    cell.extra = buffer::filled(count, f32::NAN, "a per-pixel image")?;
                }
                cell.extra[p] = v;
            }
            for e in 0..ne {
                for (l, &n) in grid.ladder.iter().enumerate() {
                    let k = e * nl + l;
                    let seeds = Realisations::of(&base.row(exp.twin[e], n), grid.seed);
                    let t = Instant::now();
                    let v = samples::estimate(world, &px, &plans[k], seeds.at(0), &mut scratch)?;
                    cell.seconds[k] += t.elapsed().as_secs_f64();
                    cell.images[k][p] = v as f32;
                    if l == at_n {
                        let mut vs = RunningStats::new();
                        vs.push(v);
                        for r in 1..grid.variance_realisations {
                            vs.push(samples::estimate(
                                world,
                                &px,
                                &plans[k],
                                seeds.at(r),
                                &mut scratch,
                            )?);
                        }
                        cell.variance[e][p] = vs.variance() as f32;
                    }
                }
            }
        }
        ctx.advance(u64::from(grid.width));
    }
    Ok(cell)
}

/// The cells (blocks of rows, in order) as one image of `total` pixels.
///
/// # Errors
/// An allocation failure.
pub fn assemble(cells: Vec<ImagesCell>, total: usize) -> crate::Result<ImagesCell> {
    let mut all = ImagesCell {
        reference: buffer::empty(total, "the reference image")?,
        reference_se: buffer::empty(total, "the reference SE image")?,
        ..ImagesCell::default()
    };
    let has_extra = cells.iter().any(|c| !c.extra.is_empty());
    if has_extra {
        all.extra = buffer::empty(total, "a per-pixel image")?;
    }
    for c in cells {
        if all.images.is_empty() {
            all.images = nan_images(c.images.len(), 0, "an image")?;
            all.variance = nan_images(c.variance.len(), 0, "a variance image")?;
            all.seconds = vec![0.0; c.seconds.len()];
            for v in all.images.iter_mut().chain(all.variance.iter_mut()) {
                v.try_reserve_exact(total)
                    .map_err(|_| format!("out of memory for an image of {total} pixels"))?;
            }
        }
        let n = c.reference.len();
        all.reference.extend_from_slice(&c.reference);
        all.reference_se.extend_from_slice(&c.reference_se);
        if has_extra {
            if c.extra.is_empty() {
                all.extra.extend(std::iter::repeat_n(f32::NAN, n));
            } else {
                all.extra.extend_from_slice(&c.extra);
            }
        }
        for (a, b) in all.images.iter_mut().zip(&c.images) {
            a.extend_from_slice(b);
        }
        for (a, b) in all.variance.iter_mut().zip(&c.variance) {
            a.extend_from_slice(b);
        }
        for (a, b) in all.seconds.iter_mut().zip(&c.seconds) {
            *a += b;
        }
    }
    Ok(all)
}

/// The equal-time ladder index per estimator: the image whose time is
/// closest in ratio to `target` seconds.
#[must_use]
pub fn equal_time(seconds: &[f64], ne: usize, nl: usize, target: f64) -> Vec<usize> {
    (0..ne)
        .map(|e| {
            (0..nl)
                .min_by(|&a, &b| {
                    let d = |l: usize| (seconds[e * nl + l] / target).ln().abs();
                    d(a).total_cmp(&d(b))
                })
                .unwrap_or(0)
        })
        .collect()
}

/// Mean squared difference from the reference over the estimated pixels.
#[must_use]
pub fn mse(img: &[f32], reference: &[f32]) -> f64 {
    let (mut s, mut c) = (0.0, 0usize);
    for (a, r) in img.iter().zip(reference) {
        if !r.is_nan() {
            let d = f64::from(*a) - f64::from(*r);
            s += d * d;
            c += 1;
        }
    }
    s / c.max(1) as f64
}

/// The mean of the finite values.
#[must_use]
pub fn mean_finite(v: &[f32]) -> f64 {
    let (mut s, mut c) = (0.0, 0usize);
    for x in v.iter().filter(|x| x.is_finite()) {
        s += f64::from(*x);
        c += 1;
    }
    s / c.max(1) as f64
}

/// The mean squared standard error of the reference over the estimated
/// pixels: the floor under every MSE.
#[must_use]
pub fn reference_floor(all: &ImagesCell) -> f64 {
    let hit = all.reference.iter().filter(|r| r.is_finite()).count();
    all.reference_se
        .iter()
        .filter(|s| s.is_finite())
        .map(|&s| f64::from(s) * f64::from(s))
        .sum::<f64>()
        / hit.max(1) as f64
}

/// An `images.csv` row.
#[derive(Clone, Debug, Serialize)]
pub struct ImageRow {
    pub estimator: String,
    pub n: usize,
    #[serde(serialize_with = "table::sci")]
    pub seconds: f64,
    #[serde(serialize_with = "table::sci")]
    pub seconds_per_sample: f64,
    #[serde(serialize_with = "table::sci")]
    pub mse: f64,
    #[serde(serialize_with = "table::sci")]
    pub mean_variance: f64,
    pub equal_samples: bool,
    pub equal_time: bool,
}

/// The rows of `images.csv` (estimator `e` at every ladder `N`, labelled
/// `labels[e]`) and the printed table of the equal-samples and equal-time
/// rows; `et` from [`equal_time`].
#[must_use]
pub fn image_rows(
    all: &ImagesCell,
    grid: &Grid<'_>,
    labels: &[String],
    at_n: usize,
    et: &[usize],
) -> (Vec<ImageRow>, String) {
    let nl = grid.ladder.len();
    let hit = all.reference.iter().filter(|r| !r.is_nan()).count();
    let width = labels.iter().map(String::len).max().unwrap_or(0).max(9) + 2;
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{:<width$} {:>5} {:>10} {:>12} {:>11} {:>11}  shown",
        "estimator", "N", "seconds", "s/sample", "MSE", "mean Var"
    );
    let mut rows = Vec::new();
    for (e, label) in labels.iter().enumerate() {
        for (l, &n) in grid.ladder.iter().enumerate() {
            let k = e * nl + l;
            let row = ImageRow {
                estimator: label.clone(),
                n,
                seconds: all.seconds[k],
                seconds_per_sample: all.seconds[k] / (n * hit).max(1) as f64,
                mse: mse(&all.images[k], &all.reference),
                mean_variance: if l == at_n {
                    mean_finite(&all.variance[e])
                } else {
                    f64::NAN
                },
                equal_samples: l == at_n,
                equal_time: l == et[e],
            };
            if row.equal_samples || row.equal_time {
                let _ = writeln!(
                    text,
                    "{:<width$} {:>5} {:>10.3e} {:>12.3e} {:>11.3e} {:>11}  {}",
                    row.estimator,
                    n,
                    row.seconds,
                    row.seconds_per_sample,
                    row.mse,
                    if row.mean_variance.is_nan() {
                        String::new()
                    } else {
                        format!("{:.3e}", row.mean_variance)
                    },
                    match (row.equal_samples, row.equal_time) {
                        (true, true) => "equal samples, equal time",
                        (true, false) => "equal samples",
                        _ => "equal time",
                    }
                );
            }
            rows.push(row);
        }
    }
    (rows, text)
}

/// A contact sheet of `w × h` images: `columns[c][r]` at column `c`, row
/// `r`, 4 white pixels apart (a missing image leaves its place white).
#[must_use]
pub fn sheet(w: u32, h: u32, columns: &[Vec<Option<Vec<[u8; 3]>>>]) -> (u32, u32, Vec<[u8; 3]>) {
    let gap = 4u32;
    let cols = columns.len() as u32;
    let nrows = columns.iter().map(Vec::len).max().unwrap_or(0) as u32;
    let sw = cols * w + cols.saturating_sub(1) * gap;
    let sh = nrows * h + nrows.saturating_sub(1) * gap;
    let mut out = vec![[255u8; 3]; (sw * sh) as usize];
    for (c, column) in columns.iter().enumerate() {
        for (r, px) in column.iter().enumerate() {
            let Some(px) = px else { continue };
            for y in 0..h {
                let dst = ((r as u32 * (h + gap) + y) * sw + c as u32 * (w + gap)) as usize;
                let src = (y * w) as usize;
                out[dst..dst + w as usize].copy_from_slice(&px[src..src + w as usize]);
            }
        }
    }
    (sw, sh, out)
}

/// An RGB PNG of `w × h` pixels.
///
/// # Errors
/// An encoding error.
pub fn rgb_png(w: u32, h: u32, px: &[[u8; 3]]) -> crate::Result<Vec<u8>> {
    let flat: Vec<u8> = px.iter().flatten().copied().collect();
    Ok(image::png(w, h, Color::Rgb, &flat)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sheet puts each image at its column and row, gaps white.
    #[test]
    fn sheet_places_images() {
        let a = vec![[1u8, 1, 1]; 4];
        let b = vec![[2u8, 2, 2]; 4];
        let (sw, sh, px) = sheet(2, 2, &[vec![Some(a), None], vec![Some(b.clone()), Some(b)]]);
        assert_eq!((sw, sh), (8, 8));
        assert_eq!(px[0], [1, 1, 1]);
        assert_eq!(px[2], [255, 255, 255]);
        assert_eq!(px[6], [2, 2, 2]);
        assert_eq!(px[(6 * 8) as usize], [255, 255, 255]);
        assert_eq!(px[(6 * 8 + 6) as usize], [2, 2, 2]);
    }
}
