//! `linesample-lab paper`: the command line to the experiment's typed configuration.

use crate::cli::*;
use crate::experiments::paper::*;
use crate::experiments::run_to_files;
use crate::{LabError, Result};

/// Resolves the command line.
///
/// # Errors
/// [`LabError::Usage`] naming the offending option.
pub fn resolve(a: &PaperArgs) -> Result<(Config, std::path::PathBuf)> {
    if a.run.shift.shift.is_some() {
        return Err(LabError::Usage(
            "--shift: paper homogenises every curve itself (random toroidal shift per \
                    realisation; randomised edge position for the straight edge); it takes no \
                    --shift"
                .into(),
        ));
    }
    let mode = if a.full {
        if a.mode.is_some_and(|m| m != Mode::Full) {
            return Err(LabError::Usage(
                "--full and --mode: give one of them".into(),
            ));
        }
        Mode::Full
    } else {
        a.mode.unwrap_or(Mode::Quick)
    };
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| std::path::PathBuf::from(DEFAULT_OUT));
    if out.file_name().is_none() || out.is_file() {
        return Err(LabError::Usage(format!(
            "--out {}: expected a folder such as {DEFAULT_OUT}",
            out.display()
        )));
    }
    Ok((plan::plan(mode, a.run.seed), out))
}

/// `linesample-lab paper`.
///
/// # Errors
/// A message naming the offending option, file or cell.
pub fn main(a: &PaperArgs) -> Result<()> {
    let (config, out) = resolve(a)?;
    let opts = a.run.options();
    if opts.shard.is_none() {
        // The scene parts' runs (each resumable on its own); a sharded
        // paper run leaves them out (the report says how to add them).
        for part in &crate::experiments::paper::scenes::PARTS {
            (part.run)(config.mode, config.seed, &out.join(part.dir), &opts)?;
        }
    }
    let exp = Paper::new(config)?;
    run_to_files(
        &exp,
        &out,
        &opts,
        Box::new(|e, c, i, o, q| {
            report::complete(e, &c, i, o, q, &scenes::sections())?;
            Ok(())
        }),
    )
}
