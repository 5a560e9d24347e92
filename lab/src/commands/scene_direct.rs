//! `linesample-lab scene` for direct-light scenes: the command line to the experiment's typed configuration.

use crate::cli::*;
use crate::experiments::direct::*;
use crate::experiments::run_to_files;
use crate::scene::SceneSource;
use crate::scene::{Scene, SceneSampler};
use crate::{LabError, Result};
use std::path::Path;

/// `linesample-lab scene FILE` for a direct-light scene.
///
/// # Errors
/// A bad option or a run error.
pub fn main(a: &SceneArgs, source: SceneSource, scene: &Scene, out: &Path) -> Result<()> {
    let (width, height) = a
        .resolution
        .unwrap_or((scene.camera.width, scene.camera.height));
    let opts = a.run.options();
    let samplers = a
        .samplers
        .clone()
        .unwrap_or_else(|| vec![SceneSampler::Random, SceneSampler::Jittered]);
    let pixel_config = |pixels: Vec<(String, u32, u32)>| PixelConfig {
        source: source.clone(),
        width,
        height,
        pixels,
        seed: a.run.seed,
        ns: a.pixel_n.clone(),
        realisations: a.realisations,
        estimators: study_estimators(scene, &samplers),
        reference_lines: a.reference_lines.unwrap_or(4096),
        reference_realisations: a.reference_realisations.unwrap_or(64),
        shift: a.run.shift.shift,
    };
    if let Some((x, y)) = a.pixel {
        let exp = PixelStudy::new(pixel_config(vec![("P".into(), x, y)]))?;
        return run_to_files(&exp, &out.join("pixels"), &opts, Box::new(complete_pixels));
    }
    if !a.n.is_power_of_two() || !a.n.trailing_zeros().is_multiple_of(2) {
        return Err(LabError::Usage(format!(
            "--n {}: direct-light images need a power of 4 (1, 4, 16, 64, …: a square and a \
             power of two, which every sampler supports)",
            a.n
        )));
    }
    let chosen = run_images(
        source.clone(),
        width,
        height,
        a.run.seed,
        a.n,
        image_estimators(scene, a.sampler.unwrap_or(SceneSampler::Jittered)),
        a.variance_realisations,
        a.reference_lines.unwrap_or(256),
        a.reference_realisations.unwrap_or(4),
        a.run.shift.shift,
        out,
        &opts,
    )?;
    let Some(chosen) = chosen else {
        return Ok(());
    };
    let exp = PixelStudy::new(pixel_config(chosen.study_pixels()))?;
    run_to_files(&exp, &out.join("pixels"), &opts, Box::new(complete_pixels))
}
