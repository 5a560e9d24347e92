//! `linesample-lab patterns`: the command line to the experiment's typed configuration.

use crate::cli::*;
use crate::experiments::patterns::*;
use crate::io::{self, FileGroup};
use crate::sampler::PatternSpec;
use crate::spec::ShiftMode;
use crate::{LabError, Result};
use linesample::Seed;
use std::path::Path;

/// `linesample-lab patterns`.
///
/// # Errors
/// A message naming the offending parameter or file.
pub fn main(a: &PatternsArgs) -> Result<()> {
    let p = &a.pattern;
    let sampler = p
        .sampler
        .ok_or_else(|| LabError::Usage("--sampler is required".into()))?;
    let spec = PatternSpec {
        sampler,
        dims: usize::from(a.dims),
        n: p.n,
        strata: p.strata.clone(),
        grid: p.grid,
        relative_radius: p.poisson.relative_radius,
        bridson: p.poisson.bridson,
    };
    let shift = a.shift.shift == Some(ShiftMode::Random);
    if let Some(out) = &a.out {
        io::check_folder("--out", out)?;
    }
    let points = generate(
        &spec,
        shift,
        Seed::new(a.seed).realization(a.realization),
        1,
    )?;
    let dir = match &a.out {
        Some(p) => p.clone(),
        None => Path::new("out/patterns").join(default_stem(sampler, spec.dims, points.len())),
    };
    let prefix = dir.join("points");
    let mut group = FileGroup::new();
    let t = title(sampler, &points, a.seed, a.realization, shift);
    let (txt, svg) = stage(&mut group, &prefix, &points, &t)?;
    group.commit()?;
    crate::out!(
        "wrote {} and {} ({} points)",
        txt.display(),
        svg.display(),
        points.len()
    );
    Ok(())
}
