//! Files: all-or-nothing groups ([`group`]), CSV tables ([`table`]), JSON
//! documents, and fallible buffers ([`buffer`]).

pub mod buffer;
pub mod group;
pub mod table;

pub use group::FileGroup;

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::{LabError, Result};

/// `PREFIX` + `suffix`, e.g. `out/conv` + `.csv`.
#[must_use]
pub fn suffixed(prefix: &Path, suffix: &str) -> PathBuf {
    let mut s = prefix.as_os_str().to_os_string();
    s.push(suffix);
    PathBuf::from(s)
}

/// Pretty-printed JSON with a final newline.
///
/// # Errors
/// [`LabError::Json`] if the value cannot be serialised (a bug in its type).
pub fn json<T: Serialize + ?Sized>(value: &T) -> Result<Vec<u8>> {
    let mut v = serde_json::to_vec_pretty(value)?;
    v.push(b'\n');
    Ok(v)
}

/// Checks that `dir` can be an output folder: it is a folder or does not
/// exist yet (every command's `--out` is a folder).
///
/// # Errors
/// [`LabError::Usage`]: `"<option> <dir>: expected an output folder, but it is
/// a file"`.
pub fn check_folder(option: &str, dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(LabError::Usage(format!(
            "{option} {}: expected an output folder, but it is a file",
            dir.display()
        )));
    }
    if dir.as_os_str().is_empty() {
        return Err(LabError::Usage(format!(
            "{option}: expected an output folder, got an empty path"
        )));
    }
    Ok(())
}
