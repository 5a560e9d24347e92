//! Library half of the `linesample-lab` experiment runner.
//!
//! The lab binary (`src/main.rs`) drives experiments on top of the no_std
//! `linesample` kernel; numerical building blocks that need `std` and heavier
//! dependencies (FFT planners) live here so that benches, examples and the
//! binary can share them.
//!
//! - [`nufft`]: a single-threaded type-1 non-uniform FFT with real weights,
//!   evaluated on the half frequency grid used by the kernel's periodograms,
//!   F(ν) = Σ_k c_k · exp(−2πi ν·x_k), to a user tolerance (exponential of
//!   semicircle kernel, Barnett, Magland & af Klinteberg, SIAM J. Sci.
//!   Comput. 41(5), 2019).
//! - [`pointfile`]: the parser of the plain-text point files that
//!   `linesample-lab spectrum --input` reads (text in, points or an error
//!   naming the line and column out).

pub mod nufft;
pub mod pointfile;
