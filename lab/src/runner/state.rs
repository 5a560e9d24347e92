//! The state folder of a run, `<--out>.state/`: a manifest naming the
//! experiment and its configuration, and one file per finished cell with the
//! cell's accumulator state (enough to merge), written atomically.
//!
//! ```text
//! OUT.state/
//!   manifest.json      tool, version, state format, experiment, cell count,
//!                      shard, the command that made it, the configuration
//!   cells/000003.bin   cell 3: postcard encoding of `Stored<Cell>`
//!   lock               held (advisory lock) while a run uses the folder
//! ```
//!
//! Cells are binary (`postcard`, a compact serde format: `f64` as its eight
//! bytes, so accumulators round-trip exactly and a spectrum's grid of sums is
//! not inflated into decimal text); the manifest is JSON for people to read.
//! Cell files are renamed into place atomically but not forced to disk
//! (`fsync`): a killed process never leaves a partial cell, and a cell that an
//! operating-system crash or power loss damaged does not decode and is simply
//! computed again (cells are deterministic, so nothing changes).

use std::fs::{self, File};
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::Shard;
use crate::io::{self, FileGroup};
use crate::{LabError, Result};

/// Version of the state layout and of the cell encodings; a folder written
/// with another format is refused (start over with `--fresh`). 2: a `paper`
/// prediction cell stores the kernel's prediction and its standard error per
/// row, no longer the lab's own per-realisation moments.
pub const FORMAT: u32 = 2;

/// The manifest of a state folder.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Manifest<C> {
    /// `linesample-lab`.
    pub tool: String,
    /// The lab's version.
    pub version: String,
    /// [`FORMAT`].
    pub format: u32,
    /// The experiment (`convergence`, `spectrum`, `gallery`).
    pub experiment: String,
    /// Number of cells of the whole run (all shards).
    pub cells: usize,
    /// The shard this folder holds, if any.
    pub shard: Option<Shard>,
    /// The command line that created the folder (informative).
    pub command: String,
    /// The experiment's configuration: a rerun must match it.
    pub config: C,
}

impl<C> Manifest<C> {
    /// A manifest for this lab version.
    pub fn new(
        experiment: &str,
        cells: usize,
        shard: Option<Shard>,
        command: String,
        config: C,
    ) -> Self {
        Manifest {
            tool: "linesample-lab".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            format: FORMAT,
            experiment: experiment.into(),
            cells,
            shard,
            command,
            config,
        }
    }
}

/// One cell file.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Stored<C> {
    /// The cell's index (checked against the file name).
    pub index: u64,
    /// Wall time the cell took, in seconds.
    pub seconds: f64,
    /// The experiment's cell state.
    pub cell: C,
}

/// An open, locked state folder.
#[derive(Debug)]
pub struct StateDir {
    path: PathBuf,
    _lock: File,
}

/// The manifest's file name in a state folder.
const MANIFEST: &str = "manifest.json";

/// `STATE/cells/NNNNNN.bin`: cell `index` of the state folder `state`.
#[must_use]
pub fn cell_file(state: &Path, index: usize) -> PathBuf {
    state.join("cells").join(format!("{index:06}.bin"))
}

/// The manifest of the state folder `state` as JSON, if there is one (read
/// without taking the folder's lock).
///
/// # Errors
/// If it exists but cannot be read or parsed.
pub fn read_manifest_at(state: &Path) -> Result<Option<Value>> {
    let p = state.join(MANIFEST);
    match fs::read(&p) {
        Ok(bytes) => serde_json::from_slice(&bytes)
            .map(Some)
            .map_err(|source| LabError::Manifest { path: p, source }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(LabError::io("read", p, e)),
    }
}

/// `OUT.state` next to `out` (a trailing `/` of `out` is ignored).
#[must_use]
pub fn state_path(out: &Path) -> PathBuf {
    let clean: PathBuf = out.components().collect();
    io::suffixed(&clean, ".state")
}

impl StateDir {
    /// Opens the state folder of `out`, creating it, and takes its lock;
    /// removes temporaries a killed run left behind.
    ///
    /// # Errors
    /// If the folder cannot be created or another run holds the lock.
    pub fn open(out: &Path) -> Result<Self> {
        let path = state_path(out);
        fs::create_dir_all(path.join("cells"))
            .map_err(LabError::io_at("create the state folder", &path))?;
        let lock_path = path.join("lock");
        let lock = File::options()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(LabError::io_at("open", &lock_path))?;
        match lock.try_lock() {
            Ok(()) => {}
            Err(fs::TryLockError::WouldBlock) => {
                return Err(LabError::Message(format!(
                    "another linesample-lab run is using {}; wait for it to finish or choose \
                     another --out",
                    path.display()
                )))
            }
            Err(fs::TryLockError::Error(e)) => return Err(LabError::io("lock", lock_path, e)),
        }
        let dir = StateDir { path, _lock: lock };
        for d in [dir.path.clone(), dir.path.join("cells")] {
            if let Ok(entries) = fs::read_dir(&d) {
                for e in entries.flatten() {
                    let name = e.file_name().to_string_lossy().into_owned();
                    if name.starts_with('.') && name.ends_with(".tmp") {
                        let _ = fs::remove_file(e.path());
                    }
                }
            }
        }
        Ok(dir)
    }

    /// The folder.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Removes the whole folder (best effort; used when a first run failed
    /// before storing any cell).
    pub fn remove(self) {
        let _ = fs::remove_dir_all(&self.path);
    }

    /// Removes the manifest and every cell (`--fresh`).
    ///
    /// # Errors
    /// If a file cannot be removed.
    pub fn clear(&self) -> Result<()> {
        let m = self.path.join(MANIFEST);
        if m.exists() {
            fs::remove_file(&m).map_err(LabError::io_at("remove", &m))?;
        }
        for i in self.cell_indices()? {
            let p = self.cell_path(i);
            fs::remove_file(&p).map_err(LabError::io_at("remove", &p))?;
        }
        Ok(())
    }

    /// The stored manifest as JSON, if there is one.
    ///
    /// # Errors
    /// If it exists but cannot be read or parsed.
    pub fn read_manifest(&self) -> Result<Option<Value>> {
        read_manifest_at(&self.path)
    }

    /// Writes the manifest atomically.
    ///
    /// # Errors
    /// On an I/O error.
    pub fn write_manifest<C: Serialize>(&self, m: &Manifest<C>) -> Result<()> {
        let mut g = FileGroup::new();
        g.add_bytes(self.path.join(MANIFEST), &io::json(m)?)?;
        g.commit()
    }

    /// `cells/NNNNNN.bin`.
    #[must_use]
    pub fn cell_path(&self, index: usize) -> PathBuf {
        cell_file(&self.path, index)
    }

    /// Indices of the cell files present, ascending.
    ///
    /// # Errors
    /// If the folder cannot be listed or holds a file that is not a cell.
    pub fn cell_indices(&self) -> Result<Vec<usize>> {
        let dir = self.path.join("cells");
        let entries = fs::read_dir(&dir).map_err(LabError::io_at("list", &dir))?;
        let mut v = Vec::new();
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') {
                continue;
            }
            let index = name
                .strip_suffix(".bin")
                .and_then(|s| s.parse::<usize>().ok())
                .ok_or_else(|| {
                    LabError::Message(format!(
                        "{}: not a cell file; remove it or use --fresh",
                        e.path().display()
                    ))
                })?;
            v.push(index);
        }
        v.sort_unstable();
        Ok(v)
    }

    /// Reads cell `index`.
    ///
    /// # Errors
    /// If the file cannot be read or decoded, or holds another cell.
    pub fn read_cell<C: DeserializeOwned>(&self, index: usize) -> Result<Stored<C>> {
        read_cell_file(&self.cell_path(index), index)
    }

    /// Writes cell `index` atomically.
    ///
    /// # Errors
    /// On an encoding or I/O error.
    pub fn write_cell<C: Serialize>(&self, stored: &Stored<C>) -> Result<()> {
        let index =
            usize::try_from(stored.index).map_err(|_| LabError::Internal("cell index".into()))?;
        let mut g = FileGroup::volatile();
        // Streamed: no second copy of a large accumulator in memory.
        g.add(self.cell_path(index), |w| {
            postcard::to_io(stored, w)
                .map(|_| ())
                .map_err(|e| std::io::Error::other(format!("encoding the cell: {e}")))
        })?;
        g.commit()
    }

    /// Copies a cell file from another state folder (merging shards), like
    /// [`StateDir::write_cell`] renamed into place but not forced to disk.
    ///
    /// # Errors
    /// On an I/O error.
    pub fn write_cell_bytes(&self, index: usize, bytes: &[u8]) -> Result<()> {
        let mut g = FileGroup::volatile();
        g.add_bytes(self.cell_path(index), bytes)?;
        g.commit()
    }
}

/// Reads and decodes a cell file, checking it holds cell `index`.
///
/// # Errors
/// If the file cannot be read or decoded, or holds another cell.
pub fn read_cell_file<C: DeserializeOwned>(path: &Path, index: usize) -> Result<Stored<C>> {
    let bytes = read_file(path)?;
    decode_cell(&bytes, path, index)
}

/// A file's bytes in a fallibly allocated buffer.
///
/// # Errors
/// If the file cannot be read or its buffer cannot be allocated.
pub fn read_file(path: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    let err = LabError::io_at("read", path);
    let mut f = File::open(path).map_err(&err)?;
    let len = f.metadata().map_err(&err)?.len();
    let len = usize::try_from(len)
        .map_err(|_| LabError::Message(format!("{}: too large", path.display())))?;
    let mut bytes = io::buffer::empty(len, &path.display().to_string())?;
    f.read_to_end(&mut bytes).map_err(&err)?;
    Ok(bytes)
}

/// Decodes cell bytes read from `path`.
///
/// # Errors
/// If they do not decode or hold another cell.
pub fn decode_cell<C: DeserializeOwned>(
    bytes: &[u8],
    path: &Path,
    index: usize,
) -> Result<Stored<C>> {
    let stored: Stored<C> = postcard::from_bytes(bytes).map_err(|e| {
        LabError::Message(format!("{}: cannot decode the cell ({e})", path.display()))
    })?;
    if stored.index != index as u64 {
        return Err(LabError::Message(format!(
            "{}: holds cell {} instead of {index}",
            path.display(),
            stored.index
        )));
    }
    Ok(stored)
}

/// Checks a stored manifest against the one this run would write.
///
/// # Errors
/// A message saying what differs (experiment, version, format, shard, cell
/// count, or which configuration fields), naming the folder and `--fresh`.
pub fn check_manifest<C: Serialize>(stored: &Value, now: &Manifest<C>, dir: &Path) -> Result<()> {
    let refuse = |what: String| {
        Err(LabError::Message(format!(
            "{} holds a run with {what}; use --fresh to discard it, or choose another --out",
            dir.display()
        )))
    };
    let field = |k: &str| stored.get(k).cloned().unwrap_or(Value::Null);
    if field("format") != now.format {
        return refuse(format!(
            "state format {} (this lab writes {})",
            field("format"),
            now.format
        ));
    }
    if field("experiment") != now.experiment {
        return refuse(format!(
            "experiment {} (this command is {})",
            field("experiment"),
            now.experiment
        ));
    }
    if field("version") != now.version {
        return refuse(format!(
            "lab version {} (this is {})",
            field("version"),
            now.version
        ));
    }
    let shard = serde_json::to_value(now.shard)?;
    if field("shard") != shard {
        let show = |v: &Value| match (v.get("index"), v.get("count")) {
            (Some(i), Some(n)) => format!("--shard {i}/{n}"),
            _ => "no --shard".to_string(),
        };
        return refuse(format!(
            "{} (this run has {})",
            show(&field("shard")),
            show(&shard)
        ));
    }
    let config = serde_json::to_value(&now.config)?;
    let old = field("config");
    if old != config {
        let diffs = differences(&old, &config);
        return refuse(format!("a different configuration ({})", diffs.join("; ")));
    }
    if field("cells") != now.cells {
        return refuse(format!(
            "{} cells (this run has {})",
            field("cells"),
            now.cells
        ));
    }
    Ok(())
}

/// `key: stored A, now B` for every top-level field that differs.
fn differences(old: &Value, new: &Value) -> Vec<String> {
    let (Some(o), Some(n)) = (old.as_object(), new.as_object()) else {
        return vec![format!("stored {old}, now {new}")];
    };
    let mut keys: Vec<&String> = o.keys().chain(n.keys()).collect();
    keys.sort();
    keys.dedup();
    keys.into_iter()
        .filter(|k| o.get(*k) != n.get(*k))
        .map(|k| {
            // Long values (a whole scene file) are cut: the key says what changed.
            let show = |v: Option<&Value>| {
                let s = v.map_or_else(|| "absent".to_string(), Value::to_string);
                match s.char_indices().nth(80) {
                    Some((i, _)) => format!("{}…", &s[..i]),
                    None => s,
                }
            };
            format!("{k}: stored {}, now {}", show(o.get(k)), show(n.get(k)))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize, Deserialize, PartialEq, Debug, Clone)]
    struct Cfg {
        n: Vec<usize>,
        r: u64,
    }

    #[test]
    fn manifest_check_names_the_difference() {
        let d = tempfile::tempdir().unwrap();
        let m = Manifest::new(
            "convergence",
            3,
            None,
            "cmd".into(),
            Cfg {
                n: vec![16, 64],
                r: 100,
            },
        );
        let stored = serde_json::to_value(&m).unwrap();
        assert!(check_manifest(&stored, &m, d.path()).is_ok());
        let other = Manifest::new(
            "convergence",
            3,
            None,
            "cmd".into(),
            Cfg {
                n: vec![16, 64],
                r: 200,
            },
        );
        let e = check_manifest(&stored, &other, d.path())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("r: stored 100, now 200") && e.contains("--fresh"),
            "{e}"
        );
        let sharded = Manifest::new(
            "convergence",
            3,
            Some(Shard { index: 1, count: 2 }),
            "cmd".into(),
            m.config.clone(),
        );
        let e = check_manifest(&stored, &sharded, d.path())
            .unwrap_err()
            .to_string();
        assert!(e.contains("no --shard") && e.contains("--shard 1/2"), "{e}");
        let spec = Manifest::new("spectrum", 3, None, "cmd".into(), m.config.clone());
        assert!(check_manifest(&stored, &spec, d.path())
            .unwrap_err()
            .to_string()
            .contains("experiment"));
    }

    #[test]
    fn cells_round_trip_and_the_lock_is_exclusive() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("run");
        let s = StateDir::open(&out).unwrap();
        assert_eq!(s.path(), d.path().join("run.state"));
        let e = StateDir::open(&out).unwrap_err().to_string();
        assert!(e.contains("another linesample-lab run"), "{e}");
        s.write_cell(&Stored {
            index: 7,
            seconds: 0.5,
            cell: vec![1.0f64, -0.0, 1e-300],
        })
        .unwrap();
        assert_eq!(s.cell_indices().unwrap(), vec![7]);
        let back: Stored<Vec<f64>> = s.read_cell(7).unwrap();
        assert_eq!(back.cell[2].to_bits(), 1e-300f64.to_bits());
        assert!(back.cell[1].is_sign_negative());
        // A cell file under another name is refused.
        fs::copy(s.cell_path(7), s.cell_path(8)).unwrap();
        assert!(s
            .read_cell::<Vec<f64>>(8)
            .unwrap_err()
            .to_string()
            .contains("holds cell 7"));
        fs::write(s.cell_path(9), b"\xff").unwrap();
        assert!(s
            .read_cell::<Vec<f64>>(9)
            .unwrap_err()
            .to_string()
            .contains("cannot decode"));
        s.clear().unwrap();
        assert!(s.cell_indices().unwrap().is_empty());
        drop(s);
        assert!(StateDir::open(&out).is_ok(), "the lock is released on drop");
        assert_eq!(state_path(Path::new("a/b/")), PathBuf::from("a/b.state"));
    }
}
