//! `linesample-lab`: the experiment runner for the `linesample` kernel. The
//! binary only parses the command line and prints one error line; everything
//! else is the `linesample_lab` library.

use std::process::ExitCode;

use clap::Parser;
use linesample_lab::cli::{dispatch, Cli};

fn main() -> ExitCode {
    match dispatch(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            linesample_lab::err!("error: {msg}");
            ExitCode::FAILURE
        }
    }
}
