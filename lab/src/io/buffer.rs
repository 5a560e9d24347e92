//! Fallible allocation of the lab's large buffers: a request the machine
//! cannot satisfy is an error naming the buffer and its size, never an abort.

use crate::{LabError, Result};

/// A vector of `len` copies of `value`, reserved with `try_reserve_exact`.
///
/// # Errors
/// [`LabError::Alloc`] (`"<what>: cannot allocate <bytes> bytes (<len> values)…"`)
/// when the allocation fails or its size overflows.
pub fn filled<T: Clone>(len: usize, value: T, what: &str) -> Result<Vec<T>> {
    let mut v = empty(len, what)?;
    v.resize(len, value);
    Ok(v)
}

/// An empty vector with room for `capacity` values, reserved fallibly.
///
/// # Errors
/// As [`filled`].
pub fn empty<T>(capacity: usize, what: &str) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(capacity).map_err(|_| LabError::Alloc {
        what: what.to_string(),
        bytes: (capacity as u128) * (std::mem::size_of::<T>() as u128),
        values: capacity,
    })?;
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_impossible_sizes() {
        let e = filled(usize::MAX / 4, 0.0f64, "points").unwrap_err();
        assert!(e.to_string().starts_with("points: cannot allocate"), "{e}");
        assert_eq!(filled(3, 1u8, "x").unwrap(), vec![1, 1, 1]);
    }
}
