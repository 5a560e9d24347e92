//! `linesample-lab`: the experiment runner for the `linesample` kernel. The
//! binary only parses the command line and prints one error line; everything
//! else is the `linesample_lab` library.

use std::process::ExitCode;

use clap::Parser;
use linesample_lab::cli::{dispatch, Cli};
use linesample_lab::runner::stop;

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = stop::install() {
        linesample_lab::err!("error: {e}");
        return ExitCode::FAILURE;
    }
    match dispatch(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            linesample_lab::err!("error: {e}");
            // A run stopped by a signal exits as the shell reports a process
            // killed by it (128 + the signal number). An error that wraps a
            // stop in a message (a group of runs such as `paper`) is still
            // a stop: the flag the handler set decides too.
            match e.signal().or_else(stop::requested) {
                Some(sig) => ExitCode::from(u8::try_from(128 + sig).unwrap_or(1)),
                None => ExitCode::FAILURE,
            }
        }
    }
}
