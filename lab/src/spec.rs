//! The vocabulary the experiments share with the command line: typed
//! options that derive `clap::ValueEnum` and `serde` once, so that an
//! experiment's configuration never needs the CLI module.

use clap::ValueEnum;
use serde::{Deserialize, Serialize};

use crate::scene::SceneSampler;

/// `--shift`: homogenisation by a random toroidal shift.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShiftMode {
    /// The pattern as generated.
    None,
    /// An independent uniform random toroidal shift per realisation.
    Random,
}

/// Whether the direct-light and caustic scenes shift `sampler`'s pattern
/// per realisation under `shift` (`None`: no `--shift` given). By default
/// only the deterministic Sobol′ points are shifted (the others are
/// random by construction, and a shift would move jittered strata off the
/// light's edges, where a line function seen periodically jumps);
/// `--shift random` shifts every pattern, `--shift none` none.
///
/// # Errors
/// `--shift none` with Sobol′, whose unshifted realisations are all the
/// same point set (a variance of 0 that measures nothing).
pub fn scene_shift(sampler: SceneSampler, shift: Option<ShiftMode>) -> Result<bool, String> {
    match shift {
        None => Ok(sampler == SceneSampler::Sobol),
        Some(ShiftMode::Random) => Ok(true),
        Some(ShiftMode::None) if sampler == SceneSampler::Sobol => Err(
            "--shift none with the sobol sampler: unshifted, every realisation is the same \
             point set; drop --shift none or choose other --samplers"
                .into(),
        ),
        Some(ShiftMode::None) => Ok(false),
    }
}
