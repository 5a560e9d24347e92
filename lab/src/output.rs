//! Atomic file output: a result file either appears complete or not at all.

use std::fs::{self, File};
use std::io::Write;
use std::path::{Path, PathBuf};

/// `<file>.tmp`, in the same directory as `file`.
pub fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

/// Writes every `(path, contents)` pair atomically, as one group.
///
/// Creates missing parent directories, writes each file to `<file>.tmp` in the
/// same directory, flushes and syncs it, and only when all temporary files are
/// complete renames them into place. On any error the temporary files are removed
/// and no result file of the group has been replaced by a partial one.
///
/// # Errors
/// A message naming the file and the I/O error.
pub fn write_atomic(files: &[(PathBuf, Vec<u8>)]) -> Result<(), String> {
    let mut written: Vec<PathBuf> = Vec::with_capacity(files.len());
    let cleanup = |tmps: &[PathBuf]| {
        for t in tmps {
            let _ = fs::remove_file(t);
        }
    };
    for (path, contents) in files {
        let tmp = tmp_path(path);
        if let Err(e) = write_synced(path, &tmp, contents) {
            // The failed tmp file may exist too.
            written.push(tmp);
            cleanup(&written);
            return Err(e);
        }
        written.push(tmp);
    }
    for (i, (path, _)) in files.iter().enumerate() {
        if let Err(e) = fs::rename(&written[i], path) {
            cleanup(&written[i..]);
            return Err(format!("cannot write {}: {e}", path.display()));
        }
    }
    // Make the renames durable (best effort: not every platform can sync a directory).
    for (path, _) in files {
        if let Some(dir) = parent(path) {
            if let Ok(d) = File::open(dir) {
                let _ = d.sync_all();
            }
        }
    }
    Ok(())
}

fn parent(path: &Path) -> Option<&Path> {
    match path.parent() {
        Some(p) if p.as_os_str().is_empty() => Some(Path::new(".")),
        other => other,
    }
}

fn write_synced(path: &Path, tmp: &Path, contents: &[u8]) -> Result<(), String> {
    let ctx = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
    if let Some(dir) = parent(path) {
        fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create directory {}: {e}", dir.display()))?;
    }
    let mut f = File::create(tmp).map_err(ctx)?;
    f.write_all(contents).map_err(ctx)?;
    f.flush().map_err(ctx)?;
    f.sync_all().map_err(ctx)?;
    Ok(())
}
