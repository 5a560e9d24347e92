//! The `linesample-lab` experiment runner, as a library: the binary
//! (`src/main.rs`) only parses the command line and prints errors.
//!
//! Data flows one way: command line ([`cli`], [`commands`]) → typed
//! configuration →
//! [`runner`] (cells on a thread pool, resumable state, shards, progress) →
//! typed results ([`experiments`]) → files ([`io`], [`figures`]). Nothing
//! below [`experiments`] knows about files; every number comes from the
//! `linesample` kernel or the `linesample-nufft` crate.
//!
//! - [`cli`]: the subcommands and the option groups they share.
//! - [`commands`]: each command's arguments to its experiment's typed
//!   configuration; the only module besides [`cli`] that reads `clap`
//!   argument types (the experiments never import the CLI).
//! - [`sampler`], [`integrand`]: registries turning options into kernel
//!   patterns and integrands; [`with_dims!`] is the one const-generic
//!   dimension dispatch.
//! - [`runner`]: the one runner (parallel, resumable, shardable, with
//!   progress).
//! - [`experiments`]: `patterns`, `gallery`, `spectrum`, `convergence`,
//!   `paper`, the scene experiments (`scene`, `direct`, `caustic`, over the
//!   one image run `images` and the one convergence study `study` they
//!   share, and the AO model) and `merge`.
//! - [`scene`]: scene files of every effect (one entry, `parse_any`).
//! - [`io`]: all-or-nothing file groups, CSV tables, JSON, fallible buffers.
//! - [`figures`]: plots (`plotters`, SVG) and PNG images.
//! - [`fit`]: weighted log-log fits.
//! - [`error`]: [`LabError`], the one error type, and its [`Result`] alias
//!   (which also converts from and into `String`, for code not yet migrated).
//! - [`spec`]: the vocabulary experiments share with the command line.
//! - [`streams`]: the one seed scheme of the scene experiments (a typed
//!   tuple of purposes per stream).
//! - [`pointfile`]: the parser of the plain-text point files that
//!   `linesample-lab spectrum --input` reads (text in, points or an error
//!   naming the line and column out).

pub mod cli;
pub mod commands;
mod dims;
pub mod error;
pub mod experiments;
pub mod figures;
pub mod fit;
pub mod integrand;
pub mod io;
pub mod pointfile;
pub mod runner;
pub mod sampler;
pub mod scene;
pub mod spec;
pub mod streams;
pub mod term;

pub use error::{LabError, Result};
