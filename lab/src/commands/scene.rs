//! `linesample-lab scene`: the command line to the experiment's typed configuration.

use crate::cli::*;
use crate::experiments::run_to_files;
use crate::experiments::scene::*;
use crate::scene::{EffectParams, SceneFile, SceneSampler};
use crate::spec::ShiftMode;
use crate::{LabError, Result};
use std::path::PathBuf;

/// `linesample-lab scene`.
///
/// # Errors
/// A scene file error (file, line, field), a bad option, or a run error.
pub fn main(a: &SceneArgs) -> Result<()> {
    let text = std::fs::read_to_string(&a.file)
        .map_err(|e| LabError::Message(format!("{}: cannot read it: {e}", a.file.display())))?;
    let source = SceneSource {
        path: a.file.display().to_string(),
        text,
    };
    let scene = match source.any()? {
        SceneFile::Caustic(scene) => {
            return crate::commands::scene_caustic::main(a, source, &scene)
        }
        SceneFile::Camera(scene) => scene,
    };
    if scene.effect == EffectParams::DirectLight {
        let out = a
            .out
            .clone()
            .unwrap_or_else(|| crate::experiments::direct::default_out(&a.file));
        return crate::commands::scene_direct::main(a, source, &scene, &out);
    }
    let (width, height) = match a.resolution {
        Some(r) => r,
        None => (scene.camera.width, scene.camera.height),
    };
    let stem = a
        .file
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/scene").join(stem));
    let opts = a.run.options();
    let shift = a.run.shift_or(ShiftMode::Random);
    let image_shift = a.run.shift.shift;
    if let Some((x, y)) = a.pixel {
        let mut rows = all_rows(&scene);
        if let Some(samplers) = &a.samplers {
            rows.retain(|r| samplers.contains(&r.sampler));
        }
        if rows.is_empty() {
            return Err(LabError::Usage(
                "--samplers: none of the scene's samplers is left".into(),
            ));
        }
        let config = PixelConfig {
            source: source.clone(),
            width,
            height,
            pixel: (x, y),
            seed: a.run.seed,
            shift,
            ns: a.pixel_n.clone(),
            realisations: a.realisations,
            rows,
            reference_lines: a.reference_lines.unwrap_or(4096),
            reference_realisations: a.reference_realisations.unwrap_or(64),
            spectrum_realisations: a.spectrum_realisations,
        };
        let exp = PixelStudy::new(config)?;
        return run_to_files(&exp, &out, &opts, Box::new(complete_pixel));
    }
    let sampler = a.sampler.unwrap_or(SceneSampler::MultiJittered);
    let max = 4 * a.n;
    let lad = ladder(sampler, max);
    if !lad.contains(&a.n) {
        return Err(LabError::Usage(format!(
            "--n {}: {} needs {} (a ladder value)",
            a.n,
            sampler.name(),
            if sampler == SceneSampler::Jittered {
                "a square"
            } else {
                "a power of two"
            }
        )));
    }
    let estimators = image_estimators(&scene, a.pdf, sampler);
    let config = ImagesConfig {
        source: source.clone(),
        width,
        height,
        seed: a.run.seed,
        shift: image_shift,
        n: a.n,
        ladder: lad,
        estimators,
        variance_realisations: a.variance_realisations,
        reference_lines: a.reference_lines.unwrap_or(64),
        reference_realisations: a.reference_realisations.unwrap_or(16),
        rows_per_cell: 8,
    };
    let exp = Images::new(config)?;
    run_to_files(&exp, &out, &opts, Box::new(complete_images))
}
