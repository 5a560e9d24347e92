//! Files: all-or-nothing groups ([`group`]), CSV tables ([`table`]), JSON
//! documents, and fallible buffers ([`buffer`]).

pub mod buffer;
pub mod group;
pub mod table;

pub use group::FileGroup;

use std::path::{Path, PathBuf};

use serde::Serialize;

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
/// A message if the value cannot be serialised (a bug in its type).
pub fn json<T: Serialize + ?Sized>(value: &T) -> Result<Vec<u8>, String> {
    let mut v =
        serde_json::to_vec_pretty(value).map_err(|e| format!("internal error: JSON: {e}"))?;
    v.push(b'\n');
    Ok(v)
}

/// Checks that `prefix` names a file prefix (not a directory such as `out/`).
///
/// # Errors
/// `"<option> <prefix>: expected a file prefix such as <example>, not a directory"`.
pub fn check_prefix(option: &str, prefix: &Path, example: &str) -> Result<(), String> {
    let s = prefix.as_os_str().to_string_lossy();
    if prefix.file_name().is_none() || s.ends_with('/') || prefix.is_dir() {
        return Err(format!(
            "{option} {}: expected a file prefix such as {example}, not a directory",
            prefix.display()
        ));
    }
    Ok(())
}
