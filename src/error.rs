//! Error types. Each variant names the parameter it is about.

use core::fmt;

/// Why a pattern could not be built or filled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PatternError {
    /// `n` (the number of points) is 0.
    ZeroPoints,
    /// `n` is larger than the pattern supports (`max`).
    TooManyPoints {
        /// The largest supported `n`.
        max: u64,
    },
    /// The stratum counts per axis do not multiply to `n`.
    StrataMismatch {
        /// Product of the per-axis counts (saturating).
        product: u64,
        /// The requested number of points.
        n: u64,
    },
    /// A per-axis stratum count is 0.
    ZeroStrata {
        /// The axis with zero strata.
        axis: usize,
    },
    /// The dimension `dims` is not supported by this pattern (supported: `min..=max`).
    Dims {
        /// Requested dimension.
        dims: usize,
        /// Smallest supported.
        min: usize,
        /// Largest supported.
        max: usize,
    },
    /// `out` (or one of the structure-of-arrays slices) does not have the length
    /// the call needs.
    OutputLength {
        /// Length needed.
        expected: usize,
        /// Length given.
        got: usize,
    },
    /// `first + out.len()` runs past the end of the pattern (`n` points).
    Range {
        /// First index requested.
        first: u64,
        /// Number of points requested.
        len: u64,
        /// Points in the pattern.
        n: u64,
    },
    /// `dim` is not below the number of dimensions of the sequence (`max`).
    Dimension {
        /// Requested dimension index.
        dim: u32,
        /// Number of dimensions.
        max: u32,
    },
}

impl fmt::Display for PatternError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            PatternError::ZeroPoints => write!(f, "n must be at least 1 (got n = 0)"),
            PatternError::TooManyPoints { max } => {
                write!(f, "n is too large for this pattern (at most {max})")
            }
            PatternError::StrataMismatch { product, n } => write!(
                f,
                "strata: the per-axis counts multiply to {product}, but n = {n}"
            ),
            PatternError::ZeroStrata { axis } => {
                write!(f, "strata: the count on axis {axis} is 0")
            }
            PatternError::Dims { dims, min, max } => {
                write!(f, "dims = {dims} is not supported (expected {min}..={max})")
            }
            PatternError::OutputLength { expected, got } => {
                write!(f, "out: length {got}, expected {expected}")
            }
            PatternError::Range { first, len, n } => write!(
                f,
                "first + out.len() = {first} + {len} exceeds the pattern size n = {n}"
            ),
            PatternError::Dimension { dim, max } => {
                write!(
                    f,
                    "dim = {dim} is out of range (the sequence has {max} dimensions)"
                )
            }
        }
    }
}

impl core::error::Error for PatternError {}

/// Why a seed could not be drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SeedError {
    /// The seed source (`rng`) returned an error.
    Source,
}

impl fmt::Display for SeedError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SeedError::Source => write!(f, "rng: the seed source failed to produce a value"),
        }
    }
}

impl core::error::Error for SeedError {}
