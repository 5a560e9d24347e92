//! The commands: each turns its parsed arguments ([`crate::cli`]) into the
//! typed configuration of an experiment ([`crate::experiments`]) and runs
//! it. This is the only layer that reads `clap` types; the experiments
//! never import the CLI.

pub mod convergence;
pub mod gallery;
pub mod paper;
pub mod patterns;
pub mod pixel_error;
pub mod scene;
pub mod scene_caustic;
pub mod scene_direct;
pub mod spectrum;
