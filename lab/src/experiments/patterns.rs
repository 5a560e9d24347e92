//! `patterns`: one realisation of one pattern, as a point file and a plot.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use linesample::Seed;
use serde::{Deserialize, Serialize};

use crate::figures;
use crate::io::{self, FileGroup};
use crate::sampler::{self, PatternSpec, Sampler};
use crate::{LabError, Result};

/// The `patterns` output formats (its `--help`).
pub const FORMATS: &str = concat!(
    "\
Output formats:
  OUT/points.txt  one point per line, its D coordinates separated by single spaces,
              each the shortest decimal that round-trips the f32 (e.g. 0.25 0.7312012);
              every coordinate is in [0, 1). This is the point-file format the
              UTK toolkit reads.
  OUT/points.svg  scatter plot of the unit square (axes with tick labels, one <circle>
              per point) under a title naming sampler, dimension, N, seed,
              realization and shift. 1D: the points on the segment [0, 1]. 3D: the
              projections xy, xz and yz side by side (3N circles). At most 65536
              points are drawn per panel (the title says so); the .txt has all.

",
    crate::files_note!()
);

/// One generated pattern realisation (also the gallery's stored cell).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Points {
    /// Coordinates per point.
    pub dims: usize,
    /// Row-major coordinates.
    pub coords: Vec<f32>,
    /// Median wall time of one fill.
    pub median: Duration,
    /// What the plot title says about the parameters.
    pub detail: Option<String>,
}

impl Points {
    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.coords.len() / self.dims.max(1)
    }

    /// `true` without points.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }
}

fn generate_dims<const D: usize>(
    spec: &PatternSpec,
    shift: bool,
    seed: Seed,
    runs: usize,
) -> Result<Points> {
    let built = sampler::build::<D>(spec, shift)?;
    let (pts, median) = sampler::generate(built.pattern.as_ref(), seed, runs)?;
    Ok(Points {
        dims: D,
        coords: pts.into_flattened(),
        median,
        detail: built.detail,
    })
}

/// Generates realisation `seed` of the pattern `spec` (with the toroidal shift
/// of `Pattern::shifted` when `shift`), filling it `runs` times for the median
/// time.
///
/// # Errors
/// A message naming the offending parameter, or a failed allocation.
pub fn generate(spec: &PatternSpec, shift: bool, seed: Seed, runs: usize) -> Result<Points> {
    match spec.dims {
        1 => generate_dims::<1>(spec, shift, seed, runs),
        2 => generate_dims::<2>(spec, shift, seed, runs),
        3 => generate_dims::<3>(spec, shift, seed, runs),
        d => Err(LabError::Usage(format!("--dims {d}: expected 1, 2 or 3"))),
    }
}

/// Streams the point file: one point per line, shortest round-trip `f32`s.
///
/// # Errors
/// Those of the writer.
pub fn write_txt(points: &Points, w: &mut dyn Write) -> std::io::Result<()> {
    for p in points.coords.chunks_exact(points.dims) {
        for (j, x) in p.iter().enumerate() {
            if j > 0 {
                w.write_all(b" ")?;
            }
            write!(w, "{x}")?;
        }
        w.write_all(b"\n")?;
    }
    Ok(())
}

/// The plot title: `sampler, dD, N = n, seed s, realization r, shift on|off[, detail]`.
#[must_use]
pub fn title(
    sampler: Sampler,
    points: &Points,
    seed: u64,
    realization: u64,
    shift: bool,
) -> String {
    format!(
        "{sampler}, {}D, N = {}, seed {seed}, realization {realization}, shift {}{}",
        points.dims,
        points.len(),
        if shift { "on" } else { "off" },
        points
            .detail
            .as_ref()
            .map(|d| format!(", {d}"))
            .unwrap_or_default()
    )
}

/// Stages `PREFIX.txt` and `PREFIX.svg` of `points` in `group`.
///
/// # Errors
/// A drawing or I/O error.
pub fn stage(
    group: &mut FileGroup,
    prefix: &Path,
    points: &Points,
    title: &str,
) -> Result<(PathBuf, PathBuf)> {
    let (txt, svg) = (io::suffixed(prefix, ".txt"), io::suffixed(prefix, ".svg"));
    group.add(&txt, |w| write_txt(points, w))?;
    let plot = figures::scatter(&points.coords, points.dims, title)?;
    group.add_bytes(&svg, plot.as_bytes())?;
    Ok((txt, svg))
}

/// `<sampler>-<dims>d-<n>`.
#[must_use]
pub fn default_stem(sampler: Sampler, dims: usize, n: usize) -> String {
    format!("{sampler}-{dims}d-{n}")
}
