//! The scene crate's one error type.

use core::fmt;

use linesample::ParamError;

/// Why a scene's world or an estimate could not be made. Every message
/// names what it is about.
///
/// With the `alloc` feature it converts into the kernel's one error,
/// [`linesample::Error`], as [`linesample::Error::Other`] (boxed, with the
/// same text; `downcast_ref::<linesample_scene::Error>()` recovers it), so
/// `?` mixes the scene's and the kernel's errors in a function returning
/// `Result<_, linesample::Error>`. It is `Send + Sync`.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// The kernel refused a parameter.
    Param(ParamError),
    /// The kernel refused item `index` of the scene's `what` (`sphere`,
    /// `quad`, `box`, `light`).
    Item {
        /// The scene's list (`sphere`, `quad`, …).
        what: &'static str,
        /// The item's index in it.
        index: usize,
        /// The kernel's reason.
        error: ParamError,
    },
    /// The scene asks for another effect than the one built from it.
    WrongEffect {
        /// The effect that was asked to build.
        expected: &'static str,
    },
    /// A fixed-capacity batch cannot hold what this query needs.
    Capacity {
        /// What is held (`occluding spheres`, `shadow polygons`).
        what: &'static str,
        /// The capacity.
        limit: usize,
        /// What the query needs.
        got: usize,
    },
    /// A large buffer could not be allocated (an error, never an abort).
    Alloc {
        /// Which buffer.
        what: &'static str,
        /// Its size in bytes.
        bytes: u128,
    },
    /// The NUFFT refused a plan or a transform (feature `theory`).
    #[cfg(feature = "theory")]
    Nufft(linesample_nufft::NufftError),
    /// This estimator cannot be evaluated this way.
    Unsupported {
        /// What was asked.
        what: &'static str,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::Param(ref e) => write!(f, "{e}"),
            Error::Item { what, index, error } => write!(f, "{what}[{index}]: {error}"),
            Error::WrongEffect { expected } => write!(f, "the scene's effect is not {expected}"),
            Error::Capacity { what, limit, got } => {
                write!(f, "{got} {what} exceed the batch's capacity of {limit}")
            }
            Error::Unsupported { what } => write!(f, "{what} is not supported"),
            Error::Alloc { what, bytes } => {
                write!(f, "{what}: cannot allocate {bytes} bytes; lower the size")
            }
            #[cfg(feature = "theory")]
            Error::Nufft(ref e) => write!(f, "NUFFT: {e}"),
        }
    }
}

impl core::error::Error for Error {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            Error::Param(e) | Error::Item { error: e, .. } => Some(e),
            #[cfg(feature = "theory")]
            Error::Nufft(e) => Some(e),
            _ => None,
        }
    }
}

impl From<ParamError> for Error {
    fn from(e: ParamError) -> Self {
        Error::Param(e)
    }
}

#[cfg(feature = "theory")]
impl From<linesample_nufft::NufftError> for Error {
    fn from(e: linesample_nufft::NufftError) -> Self {
        Error::Nufft(e)
    }
}

/// The scene's error as the kernel's [`linesample::Error::Other`] (boxed):
/// the kernel cannot name this crate's types (it is a dependency of this
/// crate), so the one error holds them as a boxed `core::error::Error`.
#[cfg(feature = "alloc")]
impl From<Error> for linesample::Error {
    fn from(e: Error) -> Self {
        linesample::Error::other(e)
    }
}
