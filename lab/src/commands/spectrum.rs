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
/// [`LabError::Usage`] naming the offending option, or the error of an
/// `--input` file (checked in the order of the helpers below: `--tol`, the
/// points, the primitive's geometry, `--out`).
pub fn resolve(a: &SpectrumArgs) -> Result<Resolved> {
    let mut notes = Vec::new();
    let prim = a.primitive.primitive;
    let tol = resolve_tol(a, prim)?;
    let points = if a.input.is_empty() {
        pattern_points(a)?
    } else {
        file_points(a, &mut notes)?
    };
    let dims = points.dims;
    let (length, direction, axis) = resolve_geometry(a, prim, dims)?;
    let grid_dims = if prim == Primitive::Lines {
        dims - 1
    } else {
        dims
    };
    let k = a.k.unwrap_or_else(|| default_k(points.n, grid_dims));
    let config = Config {
        source: points.source,
        dims,
        primitive: prim,
        length,
        direction,
        axis,
        k,
        realisations: points.realisations,
        n: points.n,
        n_min: points.n_min,
        seed: a.run.seed,
        shift: a.run.shift_or(ShiftMode::None),
        method: a.method,
        tol,
        label: points.label,
        detail: points.detail,
        notes,
    };
    let out = match &a.out {
        Some(p) => p.clone(),
        None => default_out(&config),
    };
    io::check_folder("--out", &out)?;
    Ok(Resolved {
        config,
        files: points.data,
        out,
    })
}

/// Where the points come from, as resolved: what [`Config`] records about
/// them and, for `--input`, their coordinates.
struct ResolvedPoints {
    source: Source,
    dims: usize,
    n: usize,
    n_min: usize,
    label: String,
    detail: Option<String>,
    realisations: u64,
    data: Option<Vec<Vec<f64>>>,
}

/// `--tol`: only for `--method nufft` (default [`DEFAULT_TOL`]), which
/// supports points and lines; 0 for the exact direct method.
fn resolve_tol(a: &SpectrumArgs, prim: Primitive) -> Result<f64> {
    match (a.method, a.tol) {
        (Method::Direct, Some(_)) => Err(LabError::Usage(
            "--tol applies to --method nufft only (the direct method is exact)".into(),
        )),
        (Method::Direct, None) => Ok(0.0),
        (Method::Nufft, t) => {
            let t = t.unwrap_or(DEFAULT_TOL);
            if !(1e-14..=1e-1).contains(&t) {
                return Err(LabError::Usage(format!(
                    "--tol {t}: expected a number in [1e-14, 1e-1]"
                )));
            }
            if prim == Primitive::Segments {
                return Err(LabError::Usage(
                    "--method nufft supports --primitive points and lines; segment weights \
                     sinc(L nu.omega) depend on the frequency: use --method direct"
                        .into(),
                ));
            }
            Ok(t)
        }
    }
}

/// The points of `--sampler` (and its pattern options), `--realizations`
/// realisations of them.
fn pattern_points(a: &SpectrumArgs) -> Result<ResolvedPoints> {
    let p = &a.pattern;
    let sampler = p
        .sampler
        .ok_or_else(|| LabError::Usage("give --sampler or --input (see --help)".into()))?;
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
    let realisations = a.realizations.unwrap_or(DEFAULT_REALISATIONS);
    if realisations == 0 {
        return Err(LabError::Usage(
            "--realizations 0: expected at least 1".into(),
        ));
    }
    Ok(ResolvedPoints {
        source: Source::Pattern(spec),
        dims,
        n,
        n_min: n,
        label: sampler.name().to_string(),
        detail,
        realisations,
        data: None,
    })
}

/// The points of the `--input` files, one realisation per file (all of one
/// dimension); notes about headers, wrapping and unequal sizes go to `notes`.
fn file_points(a: &SpectrumArgs, notes: &mut Vec<String>) -> Result<ResolvedPoints> {
    let mut files = Vec::with_capacity(a.input.len());
    let mut data = Vec::with_capacity(a.input.len());
    let mut dims = 0;
    for path in &a.input {
        let (d, coords, crc32) = read_points(path, notes)?;
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
    let label = a.input[0]
        .file_stem()
        .map_or_else(|| "input".into(), |s| s.to_string_lossy().into_owned());
    let realisations = files.len() as u64;
    Ok(ResolvedPoints {
        source: Source::Files(files),
        dims,
        n,
        n_min,
        label,
        detail: None,
        realisations,
        data: Some(data),
    })
}

/// The primitive's geometry: the segment `--length` and `--direction`, and
/// the lines' `--axis`, each refused where it does not apply.
fn resolve_geometry(
    a: &SpectrumArgs,
    prim: Primitive,
    dims: usize,
) -> Result<(f64, Vec<f64>, usize)> {
    let pa = &a.primitive;
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
    Ok((length, direction, axis))
}

/// `out/spectrum/LABEL-Dd-N[-segments|-lines]`.
fn default_out(config: &Config) -> PathBuf {
    let suffix = match config.primitive {
        Primitive::Points => "",
        Primitive::Segments => "-segments",
        Primitive::Lines => "-lines",
    };
    PathBuf::from("out/spectrum").join(format!(
        "{}-{}d-{}{suffix}",
        config.label, config.dims, config.n
    ))
}

/// `linesample-lab spectrum`.
///
/// # Errors
/// A message naming the offending option, file or realisation.
pub fn main(a: &SpectrumArgs) -> Result<()> {
    let Resolved { config, files, out } = resolve(a)?;
    let exp = Spectrum::new(config, files)?;
    let opts = a.run.options();
    run_to_files(
        &exp,
        &out,
        &opts,
        Box::new(|e, c, i, o, q| {
            complete(e, c, i, o, q)?;
            Ok(())
        }),
    )
}
