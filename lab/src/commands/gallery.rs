//! `linesample-lab gallery`: the command line to the experiment's typed configuration.

use crate::cli::*;
use crate::experiments::gallery::*;
use crate::experiments::run_to_files;
use crate::spec::ShiftMode;
use crate::Result;
use std::path::PathBuf;

/// The arguments of the default job (`linesample-lab` without a subcommand).
#[must_use]
pub fn default_args() -> GalleryArgs {
    GalleryArgs {
        out_dir: PathBuf::from("out/patterns"),
        runs: 5,
        spectrum_realizations: 16,
        run: RunArgs {
            seed: 1,
            shift: ShiftArgs { shift: None },
            threads: None,
            quiet: false,
            fresh: false,
            shard: None,
        },
    }
}

/// `linesample-lab gallery`.
///
/// # Errors
/// A message naming the pattern and what failed.
pub fn main(a: &GalleryArgs) -> Result<()> {
    let config = Config {
        entries: entries(),
        seed: a.run.seed,
        runs: a.runs,
        spectrum_realizations: a.spectrum_realizations,
        shift: a.run.shift_or(ShiftMode::None),
    };
    let exp = Gallery::new(config);
    let opts = a.run.options();
    run_to_files(
        &exp,
        &a.out_dir,
        &opts,
        Box::new(|e, c, i, o, q| complete(e, &c, i, o, q)),
    )
}
