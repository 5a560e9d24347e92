//! `pixel-error`: how the per-pixel error of an image is distributed across
//! the screen. Every pixel integrates the same smooth 2D integrand with `spp`
//! samples from either a [`ZSobol`] sequence shared by the image (Ahmed &
//! Wonka 2020) or Owen-scrambled Sobol' points with an independent seed per
//! pixel ([`pixel_seed`]); the error image's periodogram is blue for the
//! first (little power at low frequency) and white for the second.
//!
//! All arithmetic is the kernel's: the integrand and its integral
//! ([`Gaussian`]), the samplers, the image periodogram and its rings
//! ([`linesample::spectrum`]) and the running means ([`RunningStats`]).

use std::path::{Path, PathBuf};

use linesample::integrand::{Gaussian, Integrand};
use linesample::pattern::{Sobol, ZSobol};
use linesample::sequence::pixel_seed;
use linesample::spectrum::{
    image_band_mean, image_periodogram, image_periodogram_scratch, image_ring_means,
    image_white_level,
};
use linesample::stats::RunningStats;
use linesample::Seed;
use serde::Serialize;

use crate::figures::image::{log_gray, png, Color};
use crate::figures::multi::{multi, Multi, Series};
use crate::io::FileGroup;
use crate::{LabError, Result};

/// The `pixel-error` output formats (its `--help`).
pub const FORMATS: &str = concat!(
    "\
Output formats:
  OUT/rings.csv  ring,frequencies,zsobol,zsobol_se,independent,independent_se: per
              ring r of the error image's periodogram (frequencies with
              round(|k|) = r, k in cycles per image), its mean power normalised
              by the image's mean power without DC (white noise = 1),
              averaged over the realizations, with its standard error across
              them.
  OUT/rings.svg  the two ring-mean curves on a log scale (white noise = 1).
  OUT/error-zsobol.png, OUT/error-independent.png  the error image of
              realization 0 (grey = 0; white and black = ± the larger of the two
              images' largest |error|), one image pixel per PNG pixel.
  OUT/spectrum-zsobol.png, OUT/spectrum-independent.png  the mean normalised
              periodogram, zero frequency at the centre, log grey from 10^-2
              (black) to 10^1 (white).

",
    crate::files_note!()
);

/// Parameters of one `pixel-error` run.
#[derive(Clone, Debug)]
pub struct PixelErrorConfig {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel (a power of two).
    pub spp: u32,
    /// Independent images (seeds `Seed::new(seed).realization(r)`).
    pub realizations: u32,
    /// Run seed.
    pub seed: u64,
    /// Output folder.
    pub out: PathBuf,
}

/// One row of `rings.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct RingRow {
    /// Ring index `r` (`round(|k|) = r`).
    pub ring: usize,
    /// Frequencies in the ring.
    pub frequencies: u64,
    /// ZSobol: mean normalised power.
    pub zsobol: f64,
    /// Its standard error across realizations.
    pub zsobol_se: f64,
    /// Independent per-pixel seeds: mean normalised power.
    pub independent: f64,
    /// Its standard error across realizations.
    pub independent_se: f64,
}

/// The low band the summary reports: rings `1..=LOW_BAND`.
pub const LOW_BAND: usize = 4;

/// What a run measured.
#[derive(Clone, Debug)]
pub struct PixelErrorResult {
    /// Per-ring means.
    pub rings: Vec<RingRow>,
    /// Mean normalised power over rings `1..=LOW_BAND`, ZSobol then
    /// independent seeds, each `(mean, standard error)` across realizations.
    pub low_band: [(f64, f64); 2],
    /// Frequencies in the low band.
    pub low_band_frequencies: u64,
    /// Written files.
    pub files: Vec<PathBuf>,
}

/// The integrand: a periodised Gaussian bump on the unit torus.
fn integrand() -> Result<Gaussian<2>> {
    Gaussian::new([0.3, 0.6], 0.2).map_err(|e| LabError::Usage(format!("integrand: {e}")))
}

/// The two samplers of the comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    ZSobol,
    Independent,
}

/// One error image: `estimate(x, y) − ∫f`, row-major.
fn error_image(
    cfg: &PixelErrorConfig,
    z: &ZSobol,
    f: &Gaussian<2>,
    kind: Kind,
    seed: Seed,
) -> Result<Vec<f64>> {
    let truth = f.integral();
    let (w, h) = (cfg.width, cfg.height);
    let mut err = Vec::with_capacity(w as usize * h as usize);
    for y in 0..h {
        for x in 0..w {
            let mut s = RunningStats::default();
            let ps = pixel_seed(seed, x, y, 0);
            for i in 0..cfg.spp {
                let p = match kind {
                    Kind::ZSobol => z.sample_2d(x, y, i, 0, seed)?,
                    Kind::Independent => [Sobol::sample(i, 0, ps), Sobol::sample(i, 1, ps)],
                };
                s.push(f.value(&[f64::from(p[0]), f64::from(p[1])]));
            }
            err.push(s.mean() - truth);
        }
    }
    Ok(err)
}

/// Runs the comparison and writes its files (one group: all or none).
///
/// # Errors
/// A bad parameter (named), or an I/O error.
pub fn run(cfg: &PixelErrorConfig) -> Result<PixelErrorResult> {
    if cfg.realizations == 0 {
        return Err(LabError::Usage("--realizations must be at least 1".into()));
    }
    let z = ZSobol::new(cfg.width, cfg.height, cfg.spp)
        .map_err(|e| LabError::Usage(format!("--width/--height/--spp: {e}")))?;
    if cfg.width.min(cfg.height) < 2 * LOW_BAND as u32 {
        return Err(LabError::Usage(format!(
            "--width/--height: at least {} pixels each, so that the image has rings 1..={LOW_BAND} \
             (got {} x {})",
            2 * LOW_BAND,
            cfg.width,
            cfg.height
        )));
    }
    let f = integrand()?;
    let (w, h) = (cfg.width as usize, cfg.height as usize);
    let rings = w.min(h) / 2 + 1;
    let mut scratch = vec![0.0; image_periodogram_scratch(w, h)];
    let mut power = vec![0.0; w * h];
    let mut ring_mean = vec![0.0; rings];
    let mut count = vec![0u64; rings];
    let kinds = [Kind::ZSobol, Kind::Independent];
    let mut stats = [
        vec![RunningStats::default(); rings],
        vec![RunningStats::default(); rings],
    ];
    let mut spectra = [
        vec![RunningStats::default(); w * h],
        vec![RunningStats::default(); w * h],
    ];
    let mut first: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    let mut band = [RunningStats::default(); 2];
    let mut band_n = 0;
    for r in 0..cfg.realizations {
        let seed = Seed::new(cfg.seed).realization(u64::from(r));
        for (k, &kind) in kinds.iter().enumerate() {
            let err = error_image(cfg, &z, &f, kind, seed)?;
            image_periodogram(&err, w, h, &mut scratch, &mut power)?;
            let white = image_white_level(&power)?;
            for p in power.iter_mut() {
                *p /= white;
            }
            image_ring_means(&power, w, h, &mut ring_mean, &mut count)?;
            let (b, n) = image_band_mean(&power, w, h, 1, LOW_BAND)?;
            band[k].push(b);
            band_n = n;
            for (s, &m) in stats[k].iter_mut().zip(&ring_mean) {
                s.push(m);
            }
            for (s, &p) in spectra[k].iter_mut().zip(&power) {
                s.push(p);
            }
            if r == 0 {
                first[k] = err;
            }
        }
    }
    let se = |s: &RunningStats| {
        if s.count() > 1 {
            s.mean_std_error()
        } else {
            f64::NAN
        }
    };
    let rows: Vec<RingRow> = (0..rings)
        .map(|r| RingRow {
            ring: r,
            frequencies: count[r],
            zsobol: stats[0][r].mean(),
            zsobol_se: se(&stats[0][r]),
            independent: stats[1][r].mean(),
            independent_se: se(&stats[1][r]),
        })
        .collect();
    let files = write(cfg, &rows, &first, &spectra)?;
    Ok(PixelErrorResult {
        rings: rows,
        low_band: band.map(|s| (s.mean(), se(&s))),
        low_band_frequencies: band_n,
        files,
    })
}

/// Grey bytes of an error image: 128 at zero, ± `scale` at 255/0.
fn error_gray(err: &[f64], scale: f64) -> Vec<u8> {
    err.iter()
        .map(|e| (127.5 + 127.5 * (e / scale).clamp(-1.0, 1.0)).round() as u8)
        .collect()
}

/// Grey bytes of a mean periodogram with zero frequency moved to the centre.
fn spectrum_gray(spec: &[RunningStats], w: usize, h: usize) -> Vec<u8> {
    let mut px = vec![0u8; w * h];
    for ky in 0..h {
        for kx in 0..w {
            let (row, col) = ((ky + h / 2) % h, (kx + w / 2) % w);
            px[row * w + col] = log_gray(spec[ky * w + kx].mean(), -2.0, 1.0);
        }
    }
    px
}

fn write(
    cfg: &PixelErrorConfig,
    rows: &[RingRow],
    first: &[Vec<f64>; 2],
    spectra: &[Vec<RunningStats>; 2],
) -> Result<Vec<PathBuf>> {
    let (w, h) = (cfg.width, cfg.height);
    let out = &cfg.out;
    let mut group = FileGroup::new();
    let mut files = Vec::new();
    let mut add = |group: &mut FileGroup, name: &str, bytes: &[u8]| -> Result<()> {
        let p = out.join(name);
        group.add_bytes(&p, bytes)?;
        files.push(p);
        Ok(())
    };
    let csv = crate::io::table::csv(rows)?;
    add(&mut group, "rings.csv", &csv)?;
    let curve = |pick: fn(&RingRow) -> (f64, f64), label: &str, color: usize| Series {
        label: label.into(),
        points: rows
            .iter()
            .skip(1)
            .map(|r| {
                let (m, s) = pick(r);
                (r.ring as f64, m, s)
            })
            .collect(),
        joined: true,
        color: Some(color),
        ..Series::default()
    };
    let series = [
        curve(
            |r| (r.zsobol, r.zsobol_se),
            "ZSobol (one sequence, Morton order)",
            0,
        ),
        curve(
            |r| (r.independent, r.independent_se),
            "Sobol', independent seed per pixel",
            1,
        ),
    ];
    let subtitle = format!(
        "{w} x {h} pixels, {} spp, {} realization(s), seed {}; white noise = 1",
        cfg.spp, cfg.realizations, cfg.seed
    );
    let svg = multi(&Multi {
        title: "Per-pixel error spectrum: ring means of the normalised periodogram",
        subtitle: &subtitle,
        x_label: "ring r = round(|k|), cycles per image",
        y_label: "mean power / mean power without DC",
        series: &series,
        log_x: false,
    })?;
    add(&mut group, "rings.svg", svg.as_bytes())?;
    let scale = first
        .iter()
        .flat_map(|e| e.iter())
        .fold(0.0f64, |m, e| m.max(e.abs()))
        .max(f64::MIN_POSITIVE);
    for (k, name) in ["zsobol", "independent"].iter().enumerate() {
        let img =
            png(w, h, Color::Gray, &error_gray(&first[k], scale)).map_err(LabError::Internal)?;
        add(&mut group, &format!("error-{name}.png"), &img)?;
        let spec = spectrum_gray(&spectra[k], w as usize, h as usize);
        let img = png(w, h, Color::Gray, &spec).map_err(LabError::Internal)?;
        add(&mut group, &format!("spectrum-{name}.png"), &img)?;
    }
    group.commit()?;
    Ok(files)
}

/// The default output folder.
#[must_use]
pub fn default_out() -> &'static Path {
    Path::new("out/pixel-error")
}
