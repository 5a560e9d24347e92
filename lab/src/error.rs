//! The lab's one error type, [`LabError`], and its [`Result`] alias.
//!
//! Every message reads well on its own: the binary prints `error: {e}` and
//! nothing else, so a variant's message names the file, option or cell it is
//! about. Errors from the kernel, the scene parser and the file formats keep
//! their own types inside (see [`std::error::Error::source`]).
//!
//! The migration from `Result<_, String>` is gradual: [`LabError`] converts
//! from `String` and `&str` (into [`LabError::Message`]) and into `String`
//! (its message), so code that still returns `String` errors and code that
//! returns [`LabError`] call each other with `?`.

use std::path::PathBuf;

use crate::pointfile::PointFileError;
use crate::runner::stop;
use crate::scene::SceneError;

/// `Result` with [`LabError`] as its default error type.
pub type Result<T, E = LabError> = std::result::Result<T, E>;

/// Why a lab command failed.
#[derive(Debug, thiserror::Error)]
pub enum LabError {
    /// A file or folder operation failed: `cannot {action} {path}: {source}`,
    /// e.g. `cannot write out/a.csv: Permission denied (os error 13)`.
    #[error("cannot {action} {}: {source}", .path.display())]
    Io {
        /// What was being done, as a verb phrase (`write`, `read`,
        /// `create directory`, `list`, …).
        action: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A value could not be serialised as JSON (a bug in its type).
    #[error("internal error: JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// A row could not be serialised as CSV (a bug in its row type).
    #[error("internal error: CSV row: {0}")]
    Csv(#[from] csv::Error),
    /// The state folder's manifest does not parse.
    #[error("{}: not a manifest ({source}); use --fresh to start over", .path.display())]
    Manifest {
        /// `OUT.state/manifest.json`.
        path: PathBuf,
        /// The JSON error.
        source: serde_json::Error,
    },
    /// A point file given to `spectrum --input` was rejected:
    /// `FILE, line L…: …` (or `FILE: …` when no line is to blame).
    #[error("{file}{} {source}", if .source.line().is_some() { "," } else { ":" })]
    PointFile {
        /// The file, as given.
        file: String,
        /// What is wrong, and where.
        source: PointFileError,
    },
    /// A scene file's mistake (file, line, column, field).
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The kernel refused a pattern.
    #[error(transparent)]
    Pattern(#[from] linesample::PatternError),
    /// The kernel refused a parameter (a primitive, a direction, …).
    #[error(transparent)]
    Param(#[from] linesample::ParamError),
    /// The kernel's estimator failed.
    #[error(transparent)]
    Estimate(#[from] linesample::EstimateError),
    /// The kernel's spectrum code refused its input.
    #[error(transparent)]
    Spectrum(#[from] linesample::SpectrumError),
    /// The NUFFT refused its input.
    #[error(transparent)]
    SceneModel(#[from] linesample_scene::Error),
    #[error(transparent)]
    Nufft(#[from] linesample_nufft::NufftError),
    /// A buffer the machine cannot hold.
    #[error("{what}: cannot allocate {bytes} bytes ({values} values); lower the size")]
    Alloc {
        /// The buffer.
        what: String,
        /// The bytes asked for.
        bytes: u128,
        /// The values asked for.
        values: usize,
    },
    /// SIGINT or SIGTERM stopped the run ([`crate::runner::stop`]); every
    /// finished cell is stored and the same command resumes.
    #[error(
        "stopped by {}: {stored} of {cells} cell(s) are stored in {}; run the same command \
         again to resume",
        stop::signal_name(*.signal),
        .state.display()
    )]
    Stopped {
        /// The signal number.
        signal: i32,
        /// Cells in the state folder.
        stored: usize,
        /// Cells of this run (this shard's, when sharded).
        cells: usize,
        /// The state folder.
        state: PathBuf,
    },
    /// A bad option or combination of options, naming the option.
    #[error("{0}")]
    Usage(String),
    /// A broken invariant of the lab itself: `internal error: …`.
    #[error("internal error: {0}")]
    Internal(String),
    /// Any other failure, as a message.
    #[error("{0}")]
    Message(String),
}

impl LabError {
    /// The signal that stopped the run, for [`LabError::Stopped`].
    #[must_use]
    pub fn signal(&self) -> Option<i32> {
        match self {
            Self::Stopped { signal, .. } => Some(*signal),
            _ => None,
        }
    }

    /// A [`LabError::Io`] for `action` on `path`.
    pub fn io(action: &'static str, path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            action,
            path: path.into(),
            source,
        }
    }

    /// A closure making a [`LabError::Io`] for `action` on `path`, for
    /// `map_err`.
    pub fn io_at<'a>(
        action: &'static str,
        path: &'a std::path::Path,
    ) -> impl Fn(std::io::Error) -> Self + 'a {
        move |source| Self::io(action, path, source)
    }
}

impl From<String> for LabError {
    fn from(message: String) -> Self {
        Self::Message(message)
    }
}

impl From<&str> for LabError {
    fn from(message: &str) -> Self {
        Self::Message(message.to_string())
    }
}

impl From<LabError> for String {
    fn from(e: LabError) -> Self {
        e.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_read_on_their_own() {
        let e = LabError::io(
            "write",
            "out/a.csv",
            std::io::Error::from(std::io::ErrorKind::PermissionDenied),
        );
        assert_eq!(e.to_string(), "cannot write out/a.csv: permission denied");
        let e = LabError::PointFile {
            file: "a.txt".into(),
            source: PointFileError::Empty,
        };
        assert_eq!(
            e.to_string(),
            "a.txt: no points (the file is empty or only comments)"
        );
        let e = LabError::PointFile {
            file: "a.txt".into(),
            source: PointFileError::Dimension {
                line: 2,
                columns: 4,
            },
        };
        assert!(e.to_string().starts_with("a.txt, line 2: 4 columns"), "{e}");
        let e = LabError::Stopped {
            signal: 15,
            stored: 2,
            cells: 5,
            state: "res.state".into(),
        };
        assert_eq!(
            e.to_string(),
            "stopped by SIGTERM: 2 of 5 cell(s) are stored in res.state; run the same command \
             again to resume"
        );
        assert_eq!(e.signal(), Some(15));
        assert_eq!(
            LabError::Internal("x".into()).to_string(),
            "internal error: x"
        );
        let s: String = LabError::from("plain").into();
        assert_eq!(s, "plain");
    }
}
