//! The experiments: each takes a typed configuration, runs through the
//! [`crate::runner`], and returns typed results; printing and files are
//! separate functions that read those results.

pub mod caustic;
pub mod convergence;
pub mod direct;
pub mod gallery;
pub mod images;
pub mod paper;
pub mod patterns;
pub mod pixel_error;
pub mod samples;
pub mod scene;
pub mod scene_theory;
pub mod spectrum;
pub mod study;

use std::path::Path;

use serde::Serialize;

use crate::runner::{self, Experiment, Outcome, RunInfo, RunOptions};
use crate::spec::MergeRequest;
use crate::{LabError, Result};

/// How an experiment turns its finished cells into files: `(experiment,
/// cells in order, run info, --out, quiet)`.
pub type Complete<'a, E> =
    dyn FnOnce(&E, Vec<<E as Experiment>::Cell>, &RunInfo, &Path, bool) -> crate::Result<()> + 'a;

/// Runs `exp` with its state next to `out`; when every cell is done, lets
/// `complete` write the outputs, and when a shard is done, says how to merge.
///
/// # Errors
/// Those of [`runner::run`] and of `complete`.
pub fn run_to_files<E: Experiment>(
    exp: &E,
    out: &Path,
    opts: &RunOptions,
    complete: Box<Complete<'_, E>>,
) -> crate::Result<()> {
    match runner::run(exp, out, opts)? {
        Outcome::Complete(cells, info) => complete(exp, cells, &info, out, opts.quiet),
        Outcome::Shard {
            shard, done, total, ..
        } => {
            if !opts.quiet {
                crate::out!(
                    "shard {shard}: {done} of {total} cells done in {}; when every shard is done, \
                     combine them with `linesample-lab merge --out OUT SHARD_OUT...`",
                    runner::state::state_path(out).display()
                );
            }
            Ok(())
        }
    }
}

/// `linesample-lab merge` for one experiment: gathers the shards' cells and
/// lets `complete` write the outputs to `--out`.
///
/// # Errors
/// Those of [`runner::merge`] and of `complete`.
pub fn merge_to_files<E: Experiment>(
    exp: &E,
    a: &MergeRequest,
    complete: Box<Complete<'_, E>>,
) -> crate::Result<()> {
    let (cells, info) = runner::merge(exp, &a.out, &a.shards)?;
    complete(exp, cells, &info, &a.out, a.quiet)
}

/// The record written next to every runner command's outputs.
#[derive(Debug, Serialize)]
pub struct OutputManifest<'a, C: Serialize> {
    /// `linesample-lab`.
    pub tool: &'static str,
    /// The lab's version.
    pub version: &'static str,
    /// The experiment.
    pub experiment: &'static str,
    /// This invocation's command line.
    pub command: String,
    /// A command that recomputes the same results from scratch.
    pub reproduce: String,
    /// The configuration (parameters and seeds).
    pub config: &'a C,
    /// Worker threads of this invocation.
    pub threads: usize,
    /// Wall time of this invocation, in seconds.
    pub wall_seconds: f64,
    /// Cells computed by this invocation and found done in the state folder.
    pub cells_computed: usize,
    pub cells_resumed: usize,
    /// Seconds each cell took when it was computed.
    pub cell_seconds: &'a [f64],
    /// The shard folders this output was merged from (empty unless merged).
    pub merged_from: Vec<String>,
    /// The output files, relative to the manifest's folder.
    pub files: Vec<String>,
    /// What the readers of each CSV should know besides its rows (the
    /// command, the rules behind a column), by file name. The CSVs
    /// themselves start with their header.
    pub notes: std::collections::BTreeMap<String, Vec<String>>,
}

impl<'a, C: Serialize> OutputManifest<'a, C> {
    /// A manifest for `experiment` from a finished run.
    pub fn new(
        experiment: &'static str,
        reproduce: String,
        config: &'a C,
        info: &'a RunInfo,
        files: Vec<String>,
    ) -> Self {
        OutputManifest {
            tool: "linesample-lab",
            version: env!("CARGO_PKG_VERSION"),
            experiment,
            command: runner::command_line(),
            reproduce,
            config,
            threads: info.threads,
            wall_seconds: info.wall.as_secs_f64(),
            cells_computed: info.computed,
            cells_resumed: info.resumed,
            cell_seconds: &info.cell_seconds,
            merged_from: info
                .merged_from
                .iter()
                .map(|p| p.display().to_string())
                .collect(),
            files,
            notes: std::collections::BTreeMap::new(),
        }
    }

    /// The same manifest with the notes of the CSVs staged in `group`.
    #[must_use]
    pub fn with_notes(mut self, group: &crate::io::FileGroup) -> Self {
        self.notes.clone_from(group.notes());
        self
    }
}

/// The file name of `path` (for manifests and indexes).
#[must_use]
pub fn file_name(path: &Path) -> String {
    path.file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

/// `linesample-lab merge`: reads the experiment from the first shard's
/// manifest and lets that experiment merge.
///
/// # Errors
/// As [`runner::merge`], or if the first shard has no readable manifest.
pub fn merge(a: &MergeRequest) -> Result<()> {
    let first = a
        .shards
        .first()
        .ok_or_else(|| LabError::Usage("merge: give the shard folders".into()))?;
    let manifest = runner::read_manifest_json(first)?;
    let kind = manifest
        .get("experiment")
        .and_then(|v| v.as_str())
        .unwrap_or_default()
        .to_string();
    let config = manifest.get("config").cloned().unwrap_or_default();
    match kind.as_str() {
        convergence::KIND => convergence::merge(a, config),
        spectrum::KIND => spectrum::merge(a, config),
        gallery::KIND => gallery::merge(a, config),
        paper::KIND => paper::merge(a, config),
        // Still on `String` errors (see `crate::error`).
        scene::KIND => Ok(scene::merge(a, config)?),
        scene::PIXEL_KIND => Ok(scene::merge_pixel(a, config)?),
        direct::KIND => Ok(direct::merge(a, config)?),
        direct::PIXEL_KIND => Ok(direct::merge_pixel(a, config)?),
        caustic::KIND => Ok(caustic::merge(a, config)?),
        other => Err(LabError::Message(format!(
            "{}: experiment '{other}' cannot be merged by this lab version",
            first.display()
        ))),
    }
}

/// Parses the stored configuration of a shard.
///
/// # Errors
/// If it does not describe this experiment.
pub fn config_from<C: serde::de::DeserializeOwned>(
    v: serde_json::Value,
    kind: &str,
) -> crate::Result<C> {
    serde_json::from_value(v).map_err(|e| {
        format!(
            "the shards' manifest does not hold a {kind} configuration this lab version reads: {e}"
        )
        .into()
    })
}
