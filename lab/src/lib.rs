//! Library half of the `linesample-lab` experiment runner.
//!
//! The lab binary (`src/main.rs`) drives experiments on top of the no_std
//! `linesample` kernel (and the `linesample-nufft` crate for the fast
//! spectra); what the binary shares with the fuzz targets lives here.
//!
//! - [`pointfile`]: the parser of the plain-text point files that
//!   `linesample-lab spectrum --input` reads (text in, points or an error
//!   naming the line and column out).

pub mod pointfile;
