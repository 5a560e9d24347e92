//! Error types. Each variant names the parameter it is about.
//!
//! Every fallible function returns the error type of its module
//! ([`PatternError`], [`SeedError`], [`ParamError`], [`EstimateError`],
//! [`SpectrumError`]); each of them converts into the one [`Error`], so a
//! caller that mixes modules writes `Result<_, linesample::Error>` and `?`.
//! All of them implement [`core::fmt::Display`] and [`core::error::Error`]
//! (which is `std::error::Error`), also without `std`.

#[cfg(feature = "alloc")]
use alloc::boxed::Box;
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
    /// The parameter `name` has the value `value`, outside `min..=max`.
    Parameter {
        /// Name of the parameter (as in the API, e.g. `"capacity"`).
        name: &'static str,
        /// Value given.
        value: u64,
        /// Smallest accepted value.
        min: u64,
        /// Largest accepted value.
        max: u64,
    },
    /// `dim` is not below the number of dimensions of the sequence (`max`).
    Dimension {
        /// Requested dimension index.
        dim: u32,
        /// Number of dimensions.
        max: u32,
    },
    /// The parameter `name` has the value `value`, which is not a power of two.
    PowerOfTwo {
        /// Name of the parameter (as in the API, e.g. `"spp"`).
        name: &'static str,
        /// Value given.
        value: u64,
    },
    /// `radius` is NaN, infinite, or not `> 0`.
    Radius,
    /// `radius` is so small that the background grid would need `cells` cells
    /// (at most `max` are supported).
    GridTooLarge {
        /// Cells the grid would need (saturating).
        cells: u64,
        /// The largest supported number of cells.
        max: u64,
    },
    /// `relative_radius` is NaN or outside `(0, 1]`.
    RelativeRadius,
    /// `jitter` is NaN or outside `[0, 1]`.
    Jitter,
    /// `candidates` (Bridson's `k`) is 0 or above `max`.
    Candidates {
        /// Largest accepted count.
        max: u32,
    },
    /// `scratch` is shorter than needed.
    Scratch {
        /// Length needed.
        expected: usize,
        /// Length given.
        got: usize,
    },
    /// Fewer points fit than were asked for.
    Shortfall {
        /// Points generated.
        got: u64,
        /// Points requested.
        wanted: u64,
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
            PatternError::Parameter {
                name,
                value,
                min,
                max,
            } => write!(
                f,
                "{name} = {value} is out of range (expected {min}..={max})"
            ),
            PatternError::Dimension { dim, max } => {
                write!(
                    f,
                    "dim = {dim} is out of range (the sequence has {max} dimensions)"
                )
            }
            PatternError::PowerOfTwo { name, value } => {
                write!(f, "{name} = {value} must be a power of two")
            }
            PatternError::Radius => write!(f, "radius must be finite and > 0"),
            PatternError::GridTooLarge { cells, max } => write!(
                f,
                "radius is too small: the background grid would need {cells} cells (at most {max})"
            ),
            PatternError::Jitter => write!(f, "jitter must be in [0, 1] (and not NaN)"),
            PatternError::RelativeRadius => {
                write!(f, "relative_radius must be in (0, 1]")
            }
            PatternError::Candidates { max } => {
                write!(f, "candidates must be in 1..={max}")
            }
            PatternError::Scratch { expected, got } => {
                write!(f, "scratch: length {got}, need at least {expected}")
            }
            PatternError::Shortfall { got, wanted } => write!(
                f,
                "n: only {got} points fit at this radius, {wanted} were requested"
            ),
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

/// Invalid parameter of an integrand, a primitive (direction, segment, line) or an
/// estimator. Every message names the parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum ParamError {
    /// `name` is NaN or infinite.
    NonFinite {
        /// Parameter name.
        name: &'static str,
    },
    /// `name = value` is outside `[min, max]`.
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// Smallest accepted value.
        min: f64,
        /// Largest accepted value.
        max: f64,
    },
    /// A direction vector is zero (or all its components underflow when normalised).
    ZeroDirection,
    /// The dimension `D` is not supported by this type.
    Dimension {
        /// The requested dimension.
        dim: usize,
    },
    /// A slice argument `name` has the wrong length.
    Length {
        /// Parameter name.
        name: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
    /// A count `name` is zero or does not divide evenly.
    Count {
        /// Parameter name.
        name: &'static str,
        /// The rejected value.
        value: usize,
    },
    /// `name` asks for something this build or this machine does not have.
    Unavailable {
        /// Parameter name.
        name: &'static str,
        /// What is missing.
        reason: &'static str,
    },
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ParamError::NonFinite { name } => write!(f, "{name} must be finite (got NaN or ±∞)"),
            ParamError::OutOfRange {
                name,
                value,
                min,
                max,
            } => write!(
                f,
                "{name} = {value} is out of range (expected {min}..={max})"
            ),
            ParamError::ZeroDirection => {
                write!(f, "direction must be a non-zero finite vector")
            }
            ParamError::Dimension { dim } => {
                write!(f, "dimension D = {dim} is not supported (expected 2 or 3)")
            }
            ParamError::Length {
                name,
                expected,
                got,
            } => write!(f, "{name}: length {got}, expected {expected}"),
            ParamError::Count { name, value } => {
                write!(f, "{name} = {value} is not a valid count")
            }
            ParamError::Unavailable { name, reason } => write!(f, "{name}: {reason}"),
        }
    }
}

impl core::error::Error for ParamError {}

/// Why an estimate could not be computed.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum EstimateError {
    /// The pattern rejected the request.
    Pattern(PatternError),
    /// An estimator or primitive parameter is invalid.
    Param(ParamError),
}

impl fmt::Display for EstimateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EstimateError::Pattern(e) => write!(f, "pattern: {e}"),
            EstimateError::Param(e) => e.fmt(f),
        }
    }
}

impl core::error::Error for EstimateError {}

impl From<PatternError> for EstimateError {
    fn from(e: PatternError) -> Self {
        EstimateError::Pattern(e)
    }
}

impl From<ParamError> for EstimateError {
    fn from(e: ParamError) -> Self {
        EstimateError::Param(e)
    }
}

/// Why a spectrum (periodogram) call was rejected. Nothing is accumulated
/// when a call returns an error.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum SpectrumError {
    /// The grid half-width `k` is 0, above `max`, or makes the grid larger than
    /// `max_cells` cells.
    HalfWidth {
        /// The rejected half-width.
        k: usize,
        /// Largest accepted half-width.
        max: usize,
        /// Largest accepted number of stored cells.
        max_cells: usize,
    },
    /// The dimension `D` is not supported (expected 1, 2 or 3).
    Dimension {
        /// The requested dimension.
        dim: usize,
    },
    /// A slice argument `name` has the wrong length.
    Length {
        /// Parameter name.
        name: &'static str,
        /// Length needed (the minimum, for scratch buffers).
        expected: usize,
        /// Length given.
        got: usize,
    },
    /// Element `index` of `name` is NaN or infinite.
    NonFinite {
        /// Parameter name.
        name: &'static str,
        /// Index of the first bad element.
        index: usize,
    },
    /// Two objects built on different grids were combined.
    GridMismatch {
        /// Half-width of the receiver.
        left: usize,
        /// Half-width of the argument.
        right: usize,
    },
    /// A realisation with no samples was added (its periodogram `|F|²/N` is undefined).
    Empty,
    /// Two prediction accumulators with different integrand `weights` were
    /// merged; `index` is the first cell where they differ.
    WeightsMismatch {
        /// The first differing cell.
        index: usize,
    },
    /// The parameter `name` is invalid (see the inner error).
    Param(ParamError),
}

impl fmt::Display for SpectrumError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            SpectrumError::HalfWidth { k, max, max_cells } => write!(
                f,
                "k = {k} is out of range (expected 1..={max}, and at most {max_cells} grid cells)"
            ),
            SpectrumError::Dimension { dim } => {
                write!(
                    f,
                    "dimension D = {dim} is not supported (expected 1, 2 or 3)"
                )
            }
            SpectrumError::Length {
                name,
                expected,
                got,
            } => write!(f, "{name}: length {got}, expected {expected}"),
            SpectrumError::NonFinite { name, index } => {
                write!(f, "{name}[{index}] is NaN or infinite")
            }
            SpectrumError::GridMismatch { left, right } => write!(
                f,
                "grids differ: half-width {left} cannot be combined with half-width {right}"
            ),
            SpectrumError::Empty => write!(f, "a realisation must have at least one sample"),
            SpectrumError::WeightsMismatch { index } => write!(
                f,
                "weights differ at cell {index}: predictions of different integrand spectra \
                 cannot be merged"
            ),
            SpectrumError::Param(e) => e.fmt(f),
        }
    }
}

impl core::error::Error for SpectrumError {}

impl From<ParamError> for SpectrumError {
    fn from(e: ParamError) -> Self {
        SpectrumError::Param(e)
    }
}

/// Any error of this crate: one variant per module error type, each of which
/// converts into it (`From`), so `?` works in a function returning
/// `Result<_, linesample::Error>` whichever module failed. Available without
/// `std` and without an allocator.
///
/// [`Display`](fmt::Display) is the inner error's text, unchanged, and
/// [`source`](core::error::Error::source) is the inner error itself (match
/// on the variant to get it by value).
///
/// With the `alloc` feature, [`Error::Other`] holds any other error, boxed:
/// the crates built on this one convert their errors into it
/// (`linesample_nufft::NufftError`, `linesample_scene::Error` and
/// `linesample_scene::schema::SceneError`), and so can a caller's own.
///
/// ```
/// use linesample::pattern::{Jittered, Pattern};
/// use linesample::world::{Ray, Sphere};
/// use linesample::{Error, ParamError, Seed};
///
/// /// The chord of a sphere along a ray through the first point of a pattern.
/// fn chord_through_first_point(radius: f64) -> Result<f64, Error> {
///     let mut pts = [[0.0f32; 2]; 16];
///     Jittered::new([4, 4])?.fill(Seed::new(7), &mut pts)?; // PatternError
///     let [x, y] = pts[0].map(f64::from);
///     let ray = Ray::new([x, y, -2.0], [0.0, 0.0, 1.0])?; // ParamError
///     Ok(Sphere::new([0.5, 0.5, 0.0], radius)?.chord(&ray))
/// }
///
/// assert!(chord_through_first_point(1.0)? > 0.0);
/// let e = chord_through_first_point(-1.0).unwrap_err();
/// assert!(matches!(e, Error::Param(ParamError::OutOfRange { name: "radius", .. })));
/// assert!(e.to_string().starts_with("radius = -1"));
/// # Ok::<(), Error>(())
/// ```
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// A pattern could not be built or filled.
    Pattern(PatternError),
    /// A seed could not be drawn.
    Seed(SeedError),
    /// A parameter of an integrand, primitive, shape or estimator is invalid.
    Param(ParamError),
    /// An estimate could not be computed.
    Estimate(EstimateError),
    /// A spectrum (periodogram) call was rejected.
    Spectrum(SpectrumError),
    /// An error of another crate (feature `alloc`): the crates built on this
    /// one convert theirs into this variant, whose inner error can be
    /// recovered with `downcast_ref`.
    #[cfg(feature = "alloc")]
    Other(Box<dyn core::error::Error + Send + Sync + 'static>),
}

impl Error {
    /// Wraps any other error in [`Error::Other`] (feature `alloc`).
    #[cfg(feature = "alloc")]
    #[must_use]
    pub fn other(e: impl core::error::Error + Send + Sync + 'static) -> Self {
        Error::Other(Box::new(e))
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Pattern(e) => e.fmt(f),
            Error::Seed(e) => e.fmt(f),
            Error::Param(e) => e.fmt(f),
            Error::Estimate(e) => e.fmt(f),
            Error::Spectrum(e) => e.fmt(f),
            #[cfg(feature = "alloc")]
            Error::Other(e) => e.fmt(f),
        }
    }
}

impl core::error::Error for Error {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        Some(match self {
            Error::Pattern(e) => e,
            Error::Seed(e) => e,
            Error::Param(e) => e,
            Error::Estimate(e) => e,
            Error::Spectrum(e) => e,
            #[cfg(feature = "alloc")]
            Error::Other(e) => &**e,
        })
    }
}

impl From<PatternError> for Error {
    fn from(e: PatternError) -> Self {
        Error::Pattern(e)
    }
}

impl From<SeedError> for Error {
    fn from(e: SeedError) -> Self {
        Error::Seed(e)
    }
}

impl From<ParamError> for Error {
    fn from(e: ParamError) -> Self {
        Error::Param(e)
    }
}

impl From<EstimateError> for Error {
    fn from(e: EstimateError) -> Self {
        Error::Estimate(e)
    }
}

impl From<SpectrumError> for Error {
    fn from(e: SpectrumError) -> Self {
        Error::Spectrum(e)
    }
}
