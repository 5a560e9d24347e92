//! `linesample-lab convergence`: the command line to the experiment's typed configuration.

use crate::cli::*;
use crate::experiments::convergence::*;
use crate::experiments::run_to_files;
use crate::integrand::{
    IntegrandKind, IntegrandSpec, Params, DEFAULT_OFFSET, DEFAULT_RADIUS, DEFAULT_SIGMA,
};
use crate::io;
use crate::sampler::Sampler;
use crate::spec::{Primitive, ShiftMode};
use crate::{LabError, Result};
use std::path::PathBuf;

/// Resolves the command line into a configuration and the output prefix.
///
/// # Errors
/// [`LabError::Usage`] naming the offending option (checked in the order of
/// the helpers below: integrand, primitive, sampler, counts).
pub fn resolve(a: &ConvergenceArgs) -> Result<(Config, PathBuf)> {
    let dims = usize::from(a.dims);
    let integrand = resolve_integrand(&a.integrand, dims)?;
    let prim = a.primitive.primitive;
    let (length, dirs) = resolve_primitive(a, dims)?;
    let sampler = a.sampler;
    let pdims = pattern_dims(sampler, prim, dims)?;
    if a.realisations < 4 {
        return Err(LabError::Usage(format!(
            "--realisations {}: expected at least 4 (the standard error of the variance \
             needs 4 realisations)",
            a.realisations
        )));
    }
    if a.n.is_empty() {
        return Err(LabError::Usage(
            "--n: expected at least one sample count".into(),
        ));
    }
    let groups = match dirs {
        DirSpec::Groups(k) => k,
        _ => 1,
    };
    let (rows, notes) = resolve_rows(&a.n, sampler, pdims, groups)?;
    let config = Config {
        integrand,
        primitive: prim,
        sampler,
        relative_radius: a.poisson.relative_radius,
        bridson: a.poisson.bridson,
        length,
        dirs,
        rows,
        realisations: a.realisations,
        seed: a.run.seed,
        shift: a.run.shift_or(ShiftMode::Random),
        notes,
    };
    let out = a.out.clone().unwrap_or_else(|| config.default_out());
    io::check_folder("--out", &out)?;
    Ok((config, out))
}

/// `--integrand` and its parameters (`--radius`, `--sigma`, `--normal`,
/// `--offset`), each refused where it does not apply.
fn resolve_integrand(ia: &IntegrandArgs, dims: usize) -> Result<IntegrandSpec> {
    let kind = ia.integrand;
    let got_integrand = format!("--integrand {}", kind.name());
    if kind == IntegrandKind::Disk && dims != 2 {
        return Err(LabError::Usage(format!(
            "--dims {dims}: --integrand disk is 2D only; use --integrand ball for --dims 3"
        )));
    }
    let is_ball = matches!(kind, IntegrandKind::Disk | IntegrandKind::Ball);
    if ia.radius.is_some() && !is_ball {
        return Err(not_for(
            "--radius",
            "--integrand disk or ball",
            &got_integrand,
        ));
    }
    if ia.sigma.is_some() && kind != IntegrandKind::Gaussian {
        return Err(not_for("--sigma", "--integrand gaussian", &got_integrand));
    }
    if (ia.normal.is_some() || ia.offset.is_some()) && kind != IntegrandKind::Edge {
        let opt = if ia.normal.is_some() {
            "--normal"
        } else {
            "--offset"
        };
        return Err(not_for(opt, "--integrand edge", &got_integrand));
    }
    let params = match kind {
        IntegrandKind::Disk | IntegrandKind::Ball => Params::Ball {
            radius: ia.radius.unwrap_or(DEFAULT_RADIUS),
        },
        IntegrandKind::Gaussian => Params::Gaussian {
            sigma: ia.sigma.unwrap_or(DEFAULT_SIGMA),
        },
        IntegrandKind::Edge => {
            let normal = match &ia.normal {
                Some(v) if v.len() != dims => {
                    return Err(LabError::Usage(format!(
                        "--normal has {} component(s) but --dims is {dims}: give {dims} \
                         comma-separated numbers",
                        v.len()
                    )))
                }
                Some(v) => v.clone(),
                None if dims == 2 => vec![0.7, 1.0],
                None => vec![0.7, 1.0, 0.4],
            };
            Params::Edge {
                normal,
                offset: ia.offset.unwrap_or(DEFAULT_OFFSET),
            }
        }
    };
    Ok(IntegrandSpec { kind, dims, params })
}

/// `--primitive`'s segment length and directions (`--length`,
/// `--direction`, `--random-direction`, `--groups`), each refused where it
/// does not apply.
fn resolve_primitive(a: &ConvergenceArgs, dims: usize) -> Result<(f64, DirSpec)> {
    let pa = &a.primitive;
    let prim = pa.primitive;
    let got_prim = format!("--primitive {}", prim.name());
    if pa.length.is_some() && prim != Primitive::Segments {
        return Err(not_for("--length", "--primitive segments", &got_prim));
    }
    let length = pa.length.unwrap_or(DEFAULT_LENGTH);
    let oriented = "--primitive segments or lines";
    let dirs = if prim == Primitive::Points {
        if pa.direction.is_some() {
            return Err(not_for("--direction", oriented, &got_prim));
        }
        if a.random_direction {
            return Err(not_for("--random-direction", oriented, &got_prim));
        }
        if a.groups.is_some() {
            return Err(not_for("--groups", oriented, &got_prim));
        }
        DirSpec::None
    } else if a.random_direction {
        DirSpec::Random
    } else if let Some(k) = a.groups {
        if k == 0 {
            return Err(LabError::Usage(
                "--groups 0: expected at least 1 direction group".into(),
            ));
        }
        DirSpec::Groups(k)
    } else {
        match &pa.direction {
            Some(v) if v.len() != dims => {
                return Err(LabError::Usage(format!(
                    "--direction has {} component(s) but --dims is {dims}: give {dims} \
                     comma-separated numbers",
                    v.len()
                )))
            }
            Some(v) => DirSpec::Fixed(v.clone()),
            None => {
                let mut v = vec![0.0; dims];
                v[dims - 1] = 1.0;
                DirSpec::Fixed(v)
            }
        }
    };
    Ok((length, dirs))
}

/// The dimension of the sampler's patterns (`dims − 1` for line offsets),
/// refused unless the sampler supports it.
fn pattern_dims(sampler: Sampler, prim: Primitive, dims: usize) -> Result<usize> {
    let pdims = if prim == Primitive::Lines {
        dims - 1
    } else {
        dims
    };
    if !sampler.dims().contains(&pdims) {
        let ds: Vec<String> = sampler.dims().iter().map(ToString::to_string).collect();
        return Err(LabError::Usage(if prim == Primitive::Lines {
            format!(
                "--sampler {sampler} cannot place line offsets for --dims {dims}: lines need a \
                 {pdims}D pattern and {sampler} supports only {}D",
                ds.join("D, ")
            )
        } else {
            format!(
                "--dims {dims}: --sampler {sampler} supports only --dims {}",
                ds.join(", ")
            )
        }));
    }
    Ok(pdims)
}

/// One row per `--n`, rounded to what the sampler and `--groups` need (a
/// note says so), refusing counts that round to the same `N`.
fn resolve_rows(
    requested_ns: &[usize],
    sampler: Sampler,
    pdims: usize,
    groups: usize,
) -> Result<(Vec<Row>, Vec<String>)> {
    let mut notes = Vec::new();
    let mut rows: Vec<Row> = Vec::new();
    for &requested in requested_ns {
        let (per_group, note) = rounded_n(requested, sampler, pdims, groups)?;
        notes.extend(note);
        let n = per_group * groups;
        if let Some(prev) = rows.iter().find(|r| r.n == n) {
            return Err(LabError::Usage(format!(
                "--n: {} and {requested} both give N = {n}{}; give distinct sample counts",
                prev.requested,
                if sampler == Sampler::Jittered {
                    " after rounding to a jittered grid"
                } else {
                    " after rounding"
                }
            )));
        }
        rows.push(Row {
            requested,
            per_group,
            n,
        });
    }
    Ok((rows, notes))
}

/// `--n requested` as primitives per group (a multiple of `--groups`, and
/// `m^pdims` for the jittered sampler), with the note that says why it
/// changed, if it did.
fn rounded_n(
    requested: usize,
    sampler: Sampler,
    pdims: usize,
    groups: usize,
) -> Result<(usize, Option<String>)> {
    if requested == 0 {
        return Err(LabError::Usage("--n 0: every N must be at least 1".into()));
    }
    if requested < groups {
        return Err(LabError::Usage(format!(
            "--n {requested}: fewer samples than --groups {groups} (every group needs at \
             least one primitive)"
        )));
    }
    let mut per_group = ((requested as f64) / groups as f64).round().max(1.0) as usize;
    let mut why = Vec::new();
    if groups > 1 && per_group * groups != requested {
        why.push(format!("a multiple of --groups {groups}"));
    }
    let mut note = None;
    if sampler == Sampler::Jittered && pdims > 1 {
        let m = nearest_power(per_group as f64, pdims);
        let p = m.pow(u32::try_from(pdims).unwrap_or(1));
        if p != per_group {
            why.push(format!("m^{pdims} points per pattern"));
        }
        per_group = p;
        if !why.is_empty() {
            let strata = vec![m.to_string(); pdims].join("x");
            let n = per_group * groups;
            note = Some(format!(
                "--n {requested} -> N = {n}: --sampler jittered needs {} ({strata} strata{})",
                why.join(" and "),
                if groups > 1 {
                    format!(" per group, {groups} groups")
                } else {
                    String::new()
                }
            ));
        }
    } else if !why.is_empty() {
        note = Some(format!(
            "--n {requested} -> N = {}: N must be {}",
            per_group * groups,
            why.join(" and ")
        ));
    }
    Ok((per_group, note))
}

/// `linesample-lab convergence`.
///
/// # Errors
/// A message naming the offending option, file or cell.
pub fn main(a: &ConvergenceArgs) -> Result<()> {
    let (config, out) = resolve(a)?;
    let exp = Convergence::new(config)?;
    let opts = a.run.options();
    run_to_files(
        &exp,
        &out,
        &opts,
        Box::new(|e, c, i, o, q| {
            complete(e, &c, i, o, q)?;
            Ok(())
        }),
    )
}
