//! `linesample-lab scene` for volumetric-caustic scenes: the command line to the experiment's typed configuration.

use crate::cli::*;
use crate::experiments::caustic::*;
use crate::scene::CausticScene;
use crate::{LabError, Result};

/// `linesample-lab scene FILE` for the volumetric-caustic scene `scene`
/// read from `source`.
///
/// # Errors
/// A scene error, a bad option or a run error.
pub fn main(a: &SceneArgs, source: CausticSource, scene: &CausticScene) -> Result<()> {
    if a.pixel.is_some() {
        return Err(LabError::Usage(
            "--pixel: a volumetric-caustic scene has no pixels (it studies Q)".into(),
        ));
    }
    let out = a.out.clone().unwrap_or_else(|| default_out(&a.file));
    let opts = a.run.options();
    let samplers = a.samplers.clone().unwrap_or_else(|| scene.samplers.clone());
    run_all(
        source,
        a.resolution,
        None,
        a.run.seed,
        a.pixel_n.clone(),
        a.realisations,
        study_rows(&samplers),
        a.reference_lines.unwrap_or(1 << 16),
        a.reference_realisations.unwrap_or(64),
        a.run.shift.shift,
        &out,
        &opts,
    )
}
