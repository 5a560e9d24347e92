//! The numeric core: the few primitives every closed form, pattern and
//! spectrum in the crate is built from, each written once with one contract.
//!
//! * [`dd`]: double-double arithmetic (error-free transformations, [`Dd`],
//!   and [`sum_accurate`] for sums that cancel).
//! * [`complex`]: [`Complex`] numbers for Fourier coefficients and amplitudes.
//! * [`phase`]: exact phase reduction and `e^{−2πiθ}`, [`sinc`].
//! * [`scalar`]: inlined `fma`, `sqrt`, `floor`, `round`, bit-identical to
//!   `libm`'s (which are never inlined without link-time optimisation).
//! * [`torus`]: wrapping onto the unit torus `[0, 1)` and toroidal differences.
//! * `lane` (crate-private): the one SIMD lane abstraction behind every `f32`
//!   and `f64` batch kernel (scalar reference path and `wide` vectors), and
//!   the integer lanes of the hash permutations.
//! * [`avx2`] (`std` on `x86_64`, in builds without AVX2): the 256-bit lane
//!   types of the run-time dispatched kernels ([`crate::simd`]).
//!
//! The error bounds stated here are tested against exact rational and exact
//! integer arithmetic (`tests/num.rs`), not against these functions
//! themselves. The derivations are in `docs/theory.md` (Numerical methods).

#[cfg(all(
    feature = "std",
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
#[allow(unsafe_code)]
pub mod avx2;
pub mod complex;
pub mod dd;
pub mod lane;
pub mod phase;
pub mod scalar;
pub mod torus;

pub use complex::Complex;
pub use dd::{sum_accurate, two_prod, two_sum, Dd};
pub use phase::{cis_turns, cos_sin_turns, dot_turns, frac_centered, sinc, sinc_dd};
pub use torus::{frac, to_unit_f32, torus_delta, torus_dist};
