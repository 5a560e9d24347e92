//! The vocabulary the experiments share with the command line: typed
//! options that derive `clap::ValueEnum` and `serde` once, so that an
//! experiment's configuration never needs the CLI module.

use std::path::PathBuf;

use clap::ValueEnum;
use serde::{Deserialize, Serialize};

/// `--shift`: homogenisation by a random toroidal shift.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShiftMode {
    /// The pattern as generated.
    None,
    /// An independent uniform random toroidal shift per realisation.
    Random,
}

/// The sample primitive (`--primitive` of `spectrum` and `convergence`,
/// and an estimator's primitive in a scene file), the density of the sample
/// centres over the hemisphere, and the sample patterns of a scene's
/// estimators: the scene crate's vocabulary, with `serde` and
/// `clap::ValueEnum`.
pub use linesample_scene::ao::CentrePdf;
pub use linesample_scene::model::{Primitive, SceneSampler};

impl From<SceneSampler> for crate::sampler::Sampler {
    /// The lab's pattern for a scene sampler.
    fn from(s: SceneSampler) -> Self {
        use crate::sampler::Sampler;
        match s {
            SceneSampler::Random => Sampler::Random,
            SceneSampler::Jittered => Sampler::Jittered,
            SceneSampler::MultiJittered => Sampler::MultiJittered,
            SceneSampler::Cmj => Sampler::Cmj,
            SceneSampler::Sobol => Sampler::Sobol,
        }
    }
}

/// What `linesample-lab merge` asks of an experiment: gather the cells of
/// the shard runs whose `--out` were `shards` and write the outputs an
/// unsharded run would write into the folder `out`.
#[derive(Clone, Debug)]
pub struct MergeRequest {
    /// The merged run's output folder.
    pub out: PathBuf,
    /// The shard runs' output folders.
    pub shards: Vec<PathBuf>,
    /// No progress lines.
    pub quiet: bool,
}

/// How much to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[value(rename_all = "kebab-case")]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// Every table, sized for a few minutes on two cores (the default).
    Quick,
    /// Every table with more N and more realisations (publication quality).
    Full,
    /// Every table with few N, few realisations and fewer samplers (random
    /// and jittered in the rate table): an end-to-end check of every output
    /// for tests and CI, not for reading.
    Reduced,
}

impl Mode {
    /// The command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Mode::Quick => "quick",
            Mode::Full => "full",
            Mode::Reduced => "reduced",
        }
    }
}
