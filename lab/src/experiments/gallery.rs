//! `gallery` (the default command): every sampler in 2D and 3D, drawn, timed
//! and with its mean power spectrum. A cell is one pattern; cells run one
//! after another so that each pattern's fill is timed alone (its spectrum then
//! uses every thread).

use std::fmt::Write as _;
use std::path::Path;

use linesample::Seed;
use serde::{Deserialize, Serialize};

use crate::experiments::{
    config_from, file_name, merge_to_files, patterns, spectrum, OutputManifest,
};
use crate::io::{self, table, FileGroup};
use crate::runner::{CellInfo, Ctx, Experiment, RunInfo};
use crate::sampler::{PatternSpec, Sampler};
use crate::spec::MergeRequest;
use crate::spec::ShiftMode;
use crate::{LabError, Result};

/// The experiment's name.
pub const KIND: &str = "gallery";

/// Header of the gallery's `index.csv`.
pub const INDEX_HEADER: &str = "sampler,dims,n,seed,median_us,txt,svg,np_low,np_high,spectrum";

/// The `gallery` output formats (its `--help`).
pub const FORMATS: &str = concat!(
    "\
Output formats: the point files and plots as `patterns` writes them, the spectra
as `spectrum` writes them (see their --help), OUT_DIR/index.csv as described
above, and OUT_DIR/manifest.json (command, configuration, version, timings).

Runs: one cell per pattern, kept in OUT_DIR.state/ (resume, --fresh, --shard,
merge: see `linesample-lab --help`); a resumed gallery keeps the timings measured
when each cell was computed. All files are written as one group at the end.

",
    crate::files_note!()
);

/// One gallery entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Entry {
    pub sampler: Sampler,
    pub dims: usize,
    pub n: usize,
}

/// The gallery's patterns: every sampler in every dimension it supports out of
/// 2 and 3, with N = 1024 (jittered 3D: 1000).
#[must_use]
pub fn entries() -> Vec<Entry> {
    let mut v = Vec::new();
    for sampler in Sampler::ALL {
        for dims in [2, 3] {
            if sampler.dims().contains(&dims) {
                let n = if sampler == Sampler::Jittered && dims == 3 {
                    1000
                } else {
                    1024
                };
                v.push(Entry { sampler, dims, n });
            }
        }
    }
    v
}

/// A gallery, every parameter resolved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    pub entries: Vec<Entry>,
    pub seed: u64,
    pub runs: u32,
    pub spectrum_realizations: u64,
    pub shift: ShiftMode,
}

impl Config {
    fn spec(e: &Entry) -> PatternSpec {
        PatternSpec::simple(e.sampler, e.dims, e.n)
    }
}

/// One cell: a pattern's realisation 0 with its median fill time, and its
/// spectrum.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Cell {
    pub points: patterns::Points,
    pub spectrum: Option<spectrum::Summary>,
}

/// The experiment.
#[derive(Debug)]
pub struct Gallery {
    config: Config,
    cells: Vec<CellInfo>,
}

impl Gallery {
    /// The experiment of `config`.
    #[must_use]
    pub fn new(config: Config) -> Self {
        let cells = config
            .entries
            .iter()
            .map(|e| CellInfo {
                label: format!("{} {}D", e.sampler, e.dims),
                work: config.spectrum_realizations.max(1),
            })
            .collect();
        Gallery { config, cells }
    }
}

impl Experiment for Gallery {
    type Config = Config;
    type Cell = Cell;
    const KIND: &'static str = KIND;
    const UNIT: &'static str = "realisations";
    const PARALLEL_CELLS: bool = false;

    fn config(&self) -> &Config {
        &self.config
    }

    fn cells(&self) -> &[CellInfo] {
        &self.cells
    }

    fn run_cell(&self, index: usize, ctx: &Ctx<'_>) -> crate::Result<Cell> {
        let cfg = &self.config;
        let e = cfg.entries[index];
        let spec = Config::spec(&e);
        let ctx_err = |what: &'static str| {
            let (s, d) = (e.sampler, e.dims);
            move |err: LabError| format!("gallery, {s} {d}D{what}: {err}")
        };
        let pts = patterns::generate(
            &spec,
            cfg.shift == ShiftMode::Random,
            Seed::new(cfg.seed).realization(0),
            cfg.runs as usize,
        )
        .map_err(ctx_err(""))?;
        let spectrum = if cfg.spectrum_realizations > 0 {
            let scfg = spectrum::Config::for_pattern(
                &spec,
                pts.len(),
                cfg.spectrum_realizations,
                cfg.seed,
                cfg.shift,
            );
            let exp = spectrum::Spectrum::new(scfg, None).map_err(ctx_err(" spectrum"))?;
            let cells = ctx
                .map_ordered(exp.cells().len(), |c| exp.run_cell(c, ctx))
                .map_err(ctx_err(" spectrum"))?;
            Some(exp.summary(cells).map_err(ctx_err(" spectrum"))?)
        } else {
            ctx.advance(1);
            None
        };
        Ok(Cell {
            points: pts,
            spectrum,
        })
    }
}

/// An `index.csv` row.
#[derive(Serialize)]
struct IndexRow {
    sampler: &'static str,
    dims: usize,
    n: usize,
    seed: u64,
    #[serde(serialize_with = "table::fixed1")]
    median_us: f64,
    txt: String,
    svg: String,
    #[serde(serialize_with = "table::opt_fixed4")]
    np_low: Option<f64>,
    #[serde(serialize_with = "table::opt_fixed4")]
    np_high: Option<f64>,
    spectrum: String,
}

fn stem(e: &Entry, n: usize) -> String {
    patterns::default_stem(e.sampler, e.dims, n)
}

/// Writes every pattern's files, its spectrum files, `index.csv` and
/// `manifest.json` into `dir` as one group, and prints the table (unless
/// `quiet`).
///
/// # Errors
/// A drawing or I/O error.
pub fn complete(
    exp: &Gallery,
    cells: &[Cell],
    info: &RunInfo,
    dir: &Path,
    quiet: bool,
) -> Result<()> {
    let cfg = &exp.config;
    let shifted = cfg.shift == ShiftMode::Random;
    let mut group = FileGroup::new();
    let mut rows = Vec::with_capacity(cells.len());
    let mut table_text = String::new();
    let _ = writeln!(
        table_text,
        "{:<15} {:>4} {:>6} {:>12} {:>9} {:>9}  files",
        "sampler", "dims", "N", "median µs", "NP low", "NP high"
    );
    let mut spectrum_ms = 0.0;
    for (e, c) in cfg.entries.iter().zip(cells) {
        let points = &c.points;
        let n = points.len();
        let stem = stem(e, n);
        let title = patterns::title(e.sampler, points, cfg.seed, 0, shifted);
        let (txt, svg) = patterns::stage(&mut group, &dir.join(&stem), points, &title)?;
        let us = points.median.as_secs_f64() * 1e6;
        let spec_stem = format!("{stem}-spectrum");
        if let Some(s) = &c.spectrum {
            let scfg = spectrum::Config::for_pattern(
                &Config::spec(e),
                n,
                cfg.spectrum_realizations,
                cfg.seed,
                cfg.shift,
            );
            let (t, sub) = spectrum::titles(&scfg);
            spectrum::stage(&mut group, &dir.join(&spec_stem), s, &t, &sub)?;
            spectrum_ms += s.ms * cfg.spectrum_realizations as f64;
        }
        let (low, high) = match &c.spectrum {
            Some(s) => (Some(s.low), Some(s.high)),
            None => (None, None),
        };
        let fmt = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:.4}"));
        let _ = writeln!(
            table_text,
            "{:<15} {:>4} {:>6} {:>12.1} {:>9} {:>9}  {} {}{}",
            e.sampler.name(),
            e.dims,
            n,
            us,
            fmt(low),
            fmt(high),
            txt.display(),
            svg.display(),
            if c.spectrum.is_some() {
                format!(" {}.png", dir.join(&spec_stem).display())
            } else {
                String::new()
            }
        );
        rows.push(IndexRow {
            sampler: e.sampler.name(),
            dims: e.dims,
            n,
            seed: cfg.seed,
            median_us: us,
            txt: file_name(&txt),
            svg: file_name(&svg),
            np_low: low,
            np_high: high,
            spectrum: if c.spectrum.is_some() {
                spec_stem
            } else {
                String::new()
            },
        });
    }
    let index = dir.join("index.csv");
    group.add_bytes(&index, &table::csv(&rows)?)?;
    let mut files: Vec<String> = group.targets().map(file_name).collect();
    files.push("manifest.json".into());
    let manifest = OutputManifest::new(KIND, reproduce(cfg), cfg, info, files).with_notes(&group);
    group.add_bytes(dir.join("manifest.json"), &io::json(&manifest)?)?;
    group.commit()?;
    if !quiet {
        crate::out!("{}", table_text.trim_end());
        if cfg.spectrum_realizations > 0 {
            crate::out!(
                "spectra: {} realisations each, {:.2} s of pattern generation and NUFFT in all",
                cfg.spectrum_realizations,
                spectrum_ms / 1e3
            );
        }
        crate::out!("wrote {}", index.display());
    }
    Ok(())
}

fn reproduce(cfg: &Config) -> String {
    format!(
        "linesample-lab gallery --seed {} --runs {} --spectrum-realizations {}{}",
        cfg.seed,
        cfg.runs,
        cfg.spectrum_realizations,
        if cfg.shift == ShiftMode::Random {
            " --shift random"
        } else {
            ""
        }
    )
}

/// `linesample-lab merge` for gallery shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge(a: &MergeRequest, config: serde_json::Value) -> Result<()> {
    let exp = Gallery::new(config_from(config, KIND)?);
    merge_to_files(&exp, a, Box::new(|e, c, i, o, q| complete(e, &c, i, o, q)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covers_every_sampler() {
        let e = entries();
        assert_eq!(e.len(), 20);
        for s in Sampler::ALL {
            assert!(e.iter().any(|t| t.sampler == s && t.dims == 2));
        }
        assert!(e
            .iter()
            .any(|t| t.sampler == Sampler::Jittered && t.dims == 3 && t.n == 1000));
    }
}
