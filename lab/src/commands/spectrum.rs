//! `linesample-lab spectrum`: the command line to the experiment's typed configuration.

use crate::cli::*;
use crate::experiments::run_to_files;
use crate::experiments::spectrum::*;
use crate::io;
use crate::sampler::PatternSpec;
use crate::spec::{Primitive, ShiftMode};
use crate::with_dims;
use crate::{LabError, Result};
use std::path::PathBuf;

/// Resolves the command line: the configuration, the loaded input files (if
/// any) and the output prefix.
///
/// # Errors
/// A message naming the offending option or file.
pub fn resolve(a: &SpectrumArgs) -> Result<Resolved> {
    let mut notes = Vec::new();
    let pa = &a.primitive;
    let prim = pa.primitive;
    let tol = match (a.method, a.tol) {
        (Method::Direct, Some(_)) => {
            return Err(LabError::Usage(
                "--tol applies to --method nufft only (the direct method is exact)".into(),
            ))
        }
        (Method::Direct, None) => 0.0,
        (Method::Nufft, t) => {
            let t = t.unwrap_or(DEFAULT_TOL);
            if !(1e-14..=1e-1).contains(&t) {
                return Err(LabError::Usage(format!(
                    "--tol {t}: expected a number in [1e-14, 1e-1]"
                )));
            }
            if prim == Primitive::Segments {
                return Err(LabError::Usage("--method nufft supports --primitive points and lines; \
                            segment weights sinc(L nu.omega) depend on the frequency: use --method direct".into()));
            }
            t
        }
    };
    let (source, dims, n, n_min, label, detail, realisations, data) = if a.input.is_empty() {
        let p = &a.pattern;
        let sampler = p.sampler.ok_or("give --sampler or --input (see --help)")?;
        let dims = usize::from(a.dims.unwrap_or(2));
        let spec = PatternSpec {
            sampler,
            dims,
            n: p.n,
            strata: p.strata.clone(),
            grid: p.grid,
            relative_radius: p.poisson.relative_radius,
            bridson: p.poisson.bridson,
        };
        let (n, detail) = with_dims!(dims, dims, pattern_n(&spec))?;
        let r = a.realizations.unwrap_or(DEFAULT_REALISATIONS);
        if r == 0 {
            return Err(LabError::Usage(
                "--realizations 0: expected at least 1".into(),
            ));
        }
        (
            Source::Pattern(spec),
            dims,
            n,
            n,
            sampler.name().to_string(),
            detail,
            r,
            None,
        )
    } else {
        let mut files = Vec::with_capacity(a.input.len());
        let mut data = Vec::with_capacity(a.input.len());
        let mut dims = 0;
        for path in &a.input {
            let (d, coords, crc32) = read_points(path, &mut notes)?;
            if files.is_empty() {
                dims = d;
            } else if d != dims {
                return Err(LabError::Message(format!(
                    "{}: {d} coordinates per point, but {} has {dims}; every --input file must \
                     have the same dimension",
                    path.display(),
                    a.input[0].display()
                )));
            }
            files.push(FileSpec {
                path: path.display().to_string(),
                points: coords.len() / d,
                crc32,
            });
            data.push(coords);
        }
        let (n_min, n) = files.iter().fold((usize::MAX, 0), |(lo, hi), f| {
            (lo.min(f.points), hi.max(f.points))
        });
        if n_min != n {
            notes.push(format!(
                "the --input files have {n_min} to {n} points; the default --k and the default \
                 --out use N = {n}"
            ));
        }
        let stem = a.input[0]
            .file_stem()
            .map_or_else(|| "input".into(), |s| s.to_string_lossy().into_owned());
        let r = files.len() as u64;
        (
            Source::Files(files),
            dims,
            n,
            n_min,
            stem,
            None,
            r,
            Some(data),
        )
    };

    if pa.length.is_some() && prim != Primitive::Segments {
        return Err(not_for("--length", "--primitive segments", prim));
    }
    if pa.direction.is_some() && prim != Primitive::Segments {
        return Err(not_for("--direction", "--primitive segments", prim));
    }
    if a.axis.is_some() && prim != Primitive::Lines {
        return Err(not_for("--axis", "--primitive lines", prim));
    }
    let length = pa.length.unwrap_or(DEFAULT_LENGTH);
    let direction = match &pa.direction {
        Some(v) if v.len() != dims => {
            return Err(LabError::Usage(format!(
                "--direction has {} component(s) but the points have {dims} dimension(s): give \
                 {dims} comma-separated numbers",
                v.len()
            )))
        }
        Some(v) => v.clone(),
        None => {
            let mut v = vec![0.0; dims];
            v[0] = 1.0;
            v
        }
    };
    let axis = a.axis.unwrap_or(0);
    if prim == Primitive::Lines {
        if dims < 2 {
            return Err(LabError::Usage(format!(
                "--primitive lines needs points of dimension 2 or 3 (lines along --axis through \
                 the points); got {dims}"
            )));
        }
        if axis >= dims {
            return Err(LabError::Usage(format!(
                "--axis {axis}: expected 0 to {} for {dims}D points",
                dims - 1
            )));
        }
    }
    let grid_dims = if prim == Primitive::Lines {
        dims - 1
    } else {
        dims
    };
    let k = a.k.unwrap_or_else(|| default_k(n, grid_dims));
    let config = Config {
        source,
        dims,
        primitive: prim,
        length,
        direction,
        axis,
        k,
        realisations,
        n,
        n_min,
        seed: a.run.seed,
        shift: a.run.shift_or(ShiftMode::None),
        method: a.method,
        tol,
        label,
        detail,
        notes,
    };
    let out = match &a.out {
        Some(p) => p.clone(),
        None => {
            let suffix = match prim {
                Primitive::Points => "",
                Primitive::Segments => "-segments",
                Primitive::Lines => "-lines",
            };
            PathBuf::from("out/spectrum").join(format!("{}-{dims}d-{n}{suffix}", config.label))
        }
    };
    io::check_folder("--out", &out)?;
    Ok(Resolved {
        config,
        files: data,
        out,
    })
}

/// `linesample-lab spectrum`.
///
/// # Errors
/// A message naming the offending option, file or realisation.
pub fn main(a: &SpectrumArgs) -> Result<()> {
    let Resolved { config, files, out } = resolve(a)?;
    let exp = Spectrum::new(config, files)?;
    let opts = a.run.options();
    Ok(run_to_files(
        &exp,
        &out,
        &opts,
        Box::new(|e, c, i, o, q| {
            complete(e, c, i, o, q)?;
            Ok(())
        }),
    )?)
}
