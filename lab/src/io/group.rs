//! All-or-nothing output: a group of files appears whole or not at all.
//!
//! [`FileGroup::add`] streams each file into a uniquely named temporary file
//! (`.<name>.XXXXXX.tmp`, created exclusively by `tempfile`) in the target's
//! own directory, flushed and synced. [`FileGroup::commit`] then
//!
//! 1. keeps a hard link (or, where the file system has none, a copy) of every
//!    target that already exists, under another unique temporary name;
//! 2. renames the temporaries over their targets, one by one (a rename within a
//!    directory is atomic, so each target is always either its old or its new
//!    complete version);
//! 3. if any rename fails, puts every already replaced target back from its
//!    backup (or removes it if it did not exist before), so the group's files
//!    are byte-for-byte what they were, and reports the error;
//! 4. on success removes the backups and syncs the directories (best effort).
//!
//! Dropping a group that was not committed removes its temporaries. A killed
//! process can leave a `.…tmp` file behind, never a partial result file; the
//! unique names mean two concurrent runs never write into each other's
//! temporaries, and no user file is ever used as a scratch name.

use std::collections::BTreeMap;
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::{NamedTempFile, TempPath};

use crate::{LabError, Result};

/// A group of files written together (see the module docs).
#[derive(Debug)]
pub struct FileGroup {
    staged: Vec<(PathBuf, NamedTempFile)>,
    durable: bool,
    notes: BTreeMap<String, Vec<String>>,
}

impl Default for FileGroup {
    fn default() -> Self {
        FileGroup {
            staged: Vec::new(),
            durable: true,
            notes: BTreeMap::new(),
        }
    }
}

/// The directory a file lives in (`.` for a bare file name).
#[must_use]
pub fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// `.<file name>.`: the prefix of this target's temporaries and backups.
fn temp_prefix(target: &Path) -> String {
    let name = target
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    format!(".{name}.")
}

impl FileGroup {
    /// An empty group.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// A group whose files are not forced to disk (no `fsync`): the renames
    /// are still atomic, so a killed process never leaves a partial file, but
    /// after a power loss or an operating-system crash a file may be missing
    /// or empty. For recomputable data such as the runner's cell files, whose
    /// readers treat an undecodable file as not written.
    #[must_use]
    pub fn volatile() -> Self {
        FileGroup {
            staged: Vec::new(),
            durable: false,
            notes: BTreeMap::new(),
        }
    }

    /// Number of staged files.
    #[must_use]
    pub fn len(&self) -> usize {
        self.staged.len()
    }

    /// `true` when nothing is staged.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.staged.is_empty()
    }

    /// The targets staged so far, in order.
    pub fn targets(&self) -> impl Iterator<Item = &Path> {
        self.staged.iter().map(|(p, _)| p.as_path())
    }

    /// Stages `target`: creates its directory if needed and lets `write` fill a
    /// new temporary file next to it (buffered; flushed and synced here).
    ///
    /// # Errors
    /// [`LabError::Io`] naming `target` (or its directory) and the I/O error;
    /// the temporary file is removed.
    pub fn add(
        &mut self,
        target: impl Into<PathBuf>,
        write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<()> {
        let target = target.into();
        if target.file_name().is_none() {
            return Err(LabError::io(
                "write",
                &target,
                io::Error::new(io::ErrorKind::InvalidInput, "not a file name"),
            ));
        }
        let dir = parent_dir(&target);
        fs::create_dir_all(dir).map_err(LabError::io_at("create directory", dir))?;
        let ctx = |e: io::Error| LabError::io("write", &target, e);
        let prefix = temp_prefix(&target);
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).suffix(".tmp");
        // Result files get the usual 0o666 & !umask, not tempfile's 0o600.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(fs::Permissions::from_mode(0o666));
        }
        let mut tmp = builder.tempfile_in(dir).map_err(&ctx)?;
        {
            let mut w = BufWriter::new(tmp.as_file_mut());
            write(&mut w).map_err(&ctx)?;
            w.flush().map_err(&ctx)?;
        }
        if self.durable {
            tmp.as_file().sync_all().map_err(&ctx)?;
        }
        self.staged.push((target, tmp));
        Ok(())
    }

    /// Stages `target` with the given contents.
    ///
    /// # Errors
    /// As [`FileGroup::add`].
    pub fn add_bytes(&mut self, target: impl Into<PathBuf>, bytes: &[u8]) -> Result<()> {
        self.add(target, |w| w.write_all(bytes))
    }

    /// Stages the CSV table `rows` at `target` (header first,
    /// [`crate::io::table::csv`]) and keeps `notes`, what its readers should
    /// know besides the rows, for the run's manifest ([`FileGroup::notes`]).
    ///
    /// # Errors
    /// As [`FileGroup::add`], or a row that cannot be serialised.
    pub fn add_csv<R: serde::Serialize>(
        &mut self,
        target: impl Into<PathBuf>,
        notes: &[String],
        rows: &[R],
    ) -> Result<()> {
        let target = target.into();
        let bytes = crate::io::table::csv(rows)?;
        self.add_bytes(&target, &bytes)?;
        let name = target
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        self.note(&name, notes);
        Ok(())
    }

    /// Keeps `notes` about the staged file `name` for the manifest (what
    /// [`FileGroup::add_csv`] does for the tables it stages).
    pub fn note(&mut self, name: &str, notes: &[String]) {
        if !notes.is_empty() {
            self.notes.insert(name.to_string(), notes.to_vec());
        }
    }

    /// The notes of the CSVs staged with [`FileGroup::add_csv`], by file
    /// name: what the manifest records about them.
    #[must_use]
    pub fn notes(&self) -> &BTreeMap<String, Vec<String>> {
        &self.notes
    }

    /// Renames every staged file into place, all or nothing (module docs).
    ///
    /// # Errors
    /// [`LabError::Io`] naming the file that could not be written (a
    /// [`LabError::Message`] that also names the targets that could not be
    /// restored, if any); every target is then as it was before the call.
    pub fn commit(self) -> Result<()> {
        let targets: Vec<PathBuf> = self.staged.iter().map(|(t, _)| t.clone()).collect();
        let mut backups: Vec<Option<TempPath>> = Vec::with_capacity(targets.len());
        for t in &targets {
            backups.push(backup(t)?);
        }
        let mut placed = 0;
        let mut failure = None;
        for (target, tmp) in self.staged {
            if failure.is_some() {
                continue; // dropping `tmp` removes it
            }
            match tmp.persist(&target) {
                Ok(_) => placed += 1,
                Err(e) => failure = Some((target, e.error)),
            }
        }
        let Some((target, err)) = failure else {
            for dir in unique_dirs(&targets).into_iter().filter(|_| self.durable) {
                if let Ok(d) = File::open(dir) {
                    let _ = d.sync_all();
                }
            }
            return Ok(());
        };
        let mut unrestored = String::new();
        for (t, b) in targets.iter().zip(&backups).take(placed).rev() {
            let undone = match b {
                Some(b) => fs::rename(b, t),
                None => fs::remove_file(t),
            };
            if let Err(e) = undone {
                unrestored.push_str(&format!("; and {} could not be restored: {e}", t.display()));
            }
        }
        let err = LabError::io("write", target, err);
        if unrestored.is_empty() {
            Err(err)
        } else {
            Err(LabError::Message(format!("{err}{unrestored}")))
        }
    }
}

fn unique_dirs(targets: &[PathBuf]) -> Vec<&Path> {
    let mut dirs: Vec<&Path> = Vec::new();
    for t in targets {
        let d = parent_dir(t);
        if !dirs.contains(&d) {
            dirs.push(d);
        }
    }
    dirs
}

/// A hard link (or copy) of `target` under a unique temporary name in its
/// directory, if `target` is an existing regular file.
fn backup(target: &Path) -> Result<Option<TempPath>> {
    match fs::symlink_metadata(target) {
        Ok(m) if m.is_file() => {}
        _ => return Ok(None),
    }
    let prefix = temp_prefix(target);
    tempfile::Builder::new()
        .prefix(&prefix)
        .suffix(".bak.tmp")
        .make_in(parent_dir(target), |p| {
            fs::hard_link(target, p).or_else(|e| {
                if e.kind() == io::ErrorKind::AlreadyExists {
                    Err(e)
                } else {
                    fs::copy(target, p).map(|_| ())
                }
            })
        })
        .map(|f| Some(f.into_temp_path()))
        .map_err(|e| {
            LabError::Message(format!(
                "cannot write {}: cannot keep a backup of it: {e}",
                target.display()
            ))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn writes_a_group() {
        let d = tempfile::tempdir().unwrap();
        let mut g = FileGroup::new();
        g.add_bytes(d.path().join("a.txt"), b"a").unwrap();
        g.add_bytes(d.path().join("sub/b.txt"), b"b").unwrap();
        assert_eq!(g.len(), 2);
        g.commit().unwrap();
        assert_eq!(fs::read(d.path().join("a.txt")).unwrap(), b"a");
        assert_eq!(fs::read(d.path().join("sub/b.txt")).unwrap(), b"b");
        assert_eq!(listing(d.path()), ["a.txt", "sub"]);
    }

    #[cfg(unix)]
    #[test]
    fn results_get_the_usual_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let d = tempfile::tempdir().unwrap();
        let mut g = FileGroup::new();
        g.add_bytes(d.path().join("a"), b"a").unwrap();
        g.commit().unwrap();
        File::create(d.path().join("plain")).unwrap();
        let mode = |n: &str| fs::metadata(d.path().join(n)).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode("a"), mode("plain"), "as File::create (0o666 & !umask)");
    }

    #[test]
    fn failure_after_the_first_rename_restores_the_group() {
        let d = tempfile::tempdir().unwrap();
        let (a, b) = (d.path().join("a.txt"), d.path().join("b.svg"));
        fs::write(&a, b"old a").unwrap();
        // `b.svg` is a non-empty directory: renaming a file onto it fails
        // after `a.txt` has been replaced.
        fs::create_dir(&b).unwrap();
        fs::write(b.join("keep"), b"x").unwrap();
        let ino = |p: &Path| {
            use std::os::unix::fs::MetadataExt;
            fs::metadata(p).unwrap().ino()
        };
        let before = ino(&a);
        let mut g = FileGroup::new();
        g.add_bytes(&a, b"new a").unwrap();
        g.add_bytes(&b, b"new b").unwrap();
        let err = g.commit().unwrap_err().to_string();
        assert!(
            err.starts_with("cannot write ") && err.contains("b.svg"),
            "{err}"
        );
        assert_eq!(fs::read(&a).unwrap(), b"old a");
        assert_eq!(ino(&a), before, "the old file itself is back");
        assert_eq!(listing(d.path()), ["a.txt", "b.svg"], "no temporaries left");
    }

    #[test]
    fn a_new_file_is_removed_again_on_failure() {
        let d = tempfile::tempdir().unwrap();
        let b = d.path().join("b");
        fs::create_dir(&b).unwrap();
        fs::write(b.join("x"), b"x").unwrap();
        let mut g = FileGroup::new();
        g.add_bytes(d.path().join("a"), b"a").unwrap();
        g.add_bytes(&b, b"b").unwrap();
        assert!(g.commit().is_err());
        assert_eq!(listing(d.path()), ["b"]);
    }

    #[test]
    fn dropping_an_uncommitted_group_leaves_nothing() {
        let d = tempfile::tempdir().unwrap();
        let mut g = FileGroup::new();
        g.add_bytes(d.path().join("a"), b"a").unwrap();
        drop(g);
        assert!(listing(d.path()).is_empty());
    }

    #[test]
    fn a_failing_writer_stages_nothing() {
        let d = tempfile::tempdir().unwrap();
        let mut g = FileGroup::new();
        let e = g
            .add(d.path().join("a"), |_| Err(io::Error::other("boom")))
            .unwrap_err()
            .to_string();
        assert!(e.contains("boom") && e.contains("a"), "{e}");
        assert!(g.is_empty());
        assert!(listing(d.path()).is_empty());
    }
}
