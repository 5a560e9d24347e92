//! The sampler registry: command-line choices turned into kernel patterns.
//!
//! Nothing here computes sample positions: every number comes from a
//! `linesample::pattern` constructor and `Pattern::fill`. [`build`] is generic
//! over the dimension, so the const-generic dispatch happens once per
//! experiment ([`crate::with_dims`]).

use std::any::Any;
use std::fmt;
use std::time::{Duration, Instant};

use clap::ValueEnum;
use linesample::pattern::{
    Ccvt, CorrelatedMultiJittered, Halton, Jittered, MultiJittered, NRooks, Pattern, Pmj02,
    PoissonDisk, PoissonDiskN, PoissonMethod, PoissonN, Random, Sobol,
};
use linesample::{PatternError, Seed};
use serde::{Deserialize, Serialize};

use crate::io::buffer;
use crate::{LabError, Result};

/// The sample patterns the lab can use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[value(rename_all = "kebab-case")]
#[serde(rename_all = "kebab-case")]
pub enum Sampler {
    /// Independent uniform points (white noise), 1D to 3D.
    Random,
    /// Jittered (stratified) grid, one point per cell, 1D to 3D.
    Jittered,
    /// N-rooks (Latin hypercube), 1D to 3D.
    NRooks,
    /// Multi-jittered (Chiu, Shirley & Wang 1994), 2D only.
    MultiJittered,
    /// Correlated multi-jittered (Kensler 2013), 2D only.
    Cmj,
    /// Owen-scrambled Sobol', 1D to 3D.
    Sobol,
    /// Owen-scrambled Halton, 1D to 3D.
    Halton,
    /// Progressive multi-jittered (0,2) sequence (Christensen, Kensler &
    /// Kilpatrick 2018), 2D only: every power-of-two prefix is stratified in all
    /// elementary intervals.
    Pmj02,
    /// PMJ02 with best-candidate blue-noise choices (PMJ02BN, Christensen et al.
    /// 2018), 2D only.
    #[value(name = "pmj02bn")]
    #[serde(rename = "pmj02bn")]
    Pmj02Bn,
    /// Toroidal Poisson disk, 1D to 3D: sequential dart throwing stopped at
    /// exactly N points (random sequential adsorption), radius --relative-radius
    /// times the densest-packing radius for N; with --bridson, N points drawn
    /// at random from a Bridson set.
    PoissonDisk,
    /// Toroidal Poisson disk thinned to N: a random N-point subset of a maximal
    /// dart-throwing set (or, with --bridson, of a Bridson set) of the same
    /// radius; thinning adds white noise at low frequencies.
    PoissonDiskThinned,
    /// Capacity-constrained Voronoi tessellation (Balzer et al. 2009), 2D and 3D.
    Ccvt,
}

impl Sampler {
    /// Every sampler, in the order of the gallery.
    pub const ALL: [Sampler; 12] = [
        Sampler::Random,
        Sampler::Jittered,
        Sampler::NRooks,
        Sampler::MultiJittered,
        Sampler::Cmj,
        Sampler::Sobol,
        Sampler::Halton,
        Sampler::Pmj02,
        Sampler::Pmj02Bn,
        Sampler::PoissonDisk,
        Sampler::PoissonDiskThinned,
        Sampler::Ccvt,
    ];

    /// The command-line name (as `--sampler` accepts it).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Random => "random",
            Sampler::Jittered => "jittered",
            Sampler::NRooks => "n-rooks",
            Sampler::MultiJittered => "multi-jittered",
            Sampler::Cmj => "cmj",
            Sampler::Sobol => "sobol",
            Sampler::Halton => "halton",
            Sampler::Pmj02 => "pmj02",
            Sampler::Pmj02Bn => "pmj02bn",
            Sampler::PoissonDisk => "poisson-disk",
            Sampler::PoissonDiskThinned => "poisson-disk-thinned",
            Sampler::Ccvt => "ccvt",
        }
    }

    /// Poisson disk, sequential or thinned (the samplers with a radius).
    #[must_use]
    pub fn is_poisson(self) -> bool {
        matches!(self, Sampler::PoissonDisk | Sampler::PoissonDiskThinned)
    }

    /// Dimensions this sampler supports.
    #[must_use]
    pub fn dims(self) -> &'static [usize] {
        match self {
            Sampler::MultiJittered | Sampler::Cmj | Sampler::Pmj02 | Sampler::Pmj02Bn => &[2],
            Sampler::Ccvt => &[2, 3],
            _ => &[1, 2, 3],
        }
    }
}

impl fmt::Display for Sampler {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// `N` when neither `-n`, `--strata` nor `--grid` says otherwise.
pub const DEFAULT_N: usize = 1024;
/// Default Poisson-disk radius relative to the densest packing.
pub const DEFAULT_RELATIVE_RADIUS: f64 = 0.75;

/// A pattern as the command line describes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PatternSpec {
    pub sampler: Sampler,
    /// Dimension of the points.
    pub dims: usize,
    /// `-n`; `None` means "from --strata / --grid, else 1024".
    pub n: Option<usize>,
    pub strata: Option<Vec<usize>>,
    pub grid: Option<(usize, usize)>,
    /// Poisson disk: radius relative to the densest packing for N.
    pub relative_radius: f64,
    /// Poisson disk: N points of a Bridson set (thinned) instead of
    /// sequential dart throwing (or of a maximal set, for the thinned sampler).
    pub bridson: bool,
}

impl PatternSpec {
    /// `sampler` in `dims` dimensions with `n` points and default options.
    #[must_use]
    pub fn simple(sampler: Sampler, dims: usize, n: usize) -> Self {
        PatternSpec {
            sampler,
            dims,
            n: Some(n),
            strata: None,
            grid: None,
            relative_radius: DEFAULT_RELATIVE_RADIUS,
            bridson: false,
        }
    }
}

/// A pattern shared by the worker threads.
pub type DynPattern<const D: usize> = Box<dyn Pattern<D> + Send + Sync>;

/// A built pattern plus what a plot title should say about it.
pub struct Built<const D: usize> {
    pub pattern: DynPattern<D>,
    /// Extra parameters worth showing, e.g. `strata 32x32`.
    pub detail: Option<String>,
}

fn boxed<const D: usize, P: Pattern<D> + Send + Sync + 'static>(
    p: P,
    shift: bool,
) -> DynPattern<D> {
    if shift {
        Box::new(p.shifted())
    } else {
        Box::new(p)
    }
}

/// A 2D pattern as a `D`-dimensional one; `None` unless `D = 2`.
fn as_dims<const D: usize>(p: DynPattern<2>) -> Option<DynPattern<D>> {
    let any: Box<dyn Any> = Box::new(p);
    any.downcast::<DynPattern<D>>().ok().map(|b| *b)
}

/// A pattern without parameters worth a title.
fn plain<const D: usize>(
    p: Result<DynPattern<D>, PatternError>,
    err: &impl Fn(PatternError) -> String,
) -> Result<Built<D>, String> {
    Ok(Built {
        pattern: p.map_err(err)?,
        detail: None,
    })
}

/// Prefixes a kernel error with what was being built.
fn kernel(spec: &PatternSpec, n: usize) -> impl Fn(PatternError) -> String + '_ {
    move |e| {
        format!(
            "invalid parameters for --sampler {} --dims {} -n {n}: {e}",
            spec.sampler, spec.dims
        )
    }
}

/// Builds the `D`-dimensional pattern `spec` describes (`spec.dims` must be
/// `D`), with the random toroidal shift of [`Pattern::shifted`] if `shift`.
///
/// # Errors
/// A message naming the offending parameter: an unsupported `--dims`, an option
/// that does not apply to the sampler, or the kernel's own [`PatternError`].
/// (Still a `String`: the scene experiments map it as one.)
pub fn build<const D: usize>(spec: &PatternSpec, shift: bool) -> Result<Built<D>, String> {
    let s = spec.sampler;
    if spec.dims != D {
        return Err(format!(
            "internal error: a {}D spec built as {D}D",
            spec.dims
        ));
    }
    if !s.dims().contains(&D) {
        return Err(if s.dims().len() == 1 {
            format!(
                "--dims {D}: --sampler {s} supports only --dims {}",
                s.dims()[0]
            )
        } else if s.dims().len() == 2 {
            format!("--dims {D}: --sampler {s} supports only --dims 2 and 3")
        } else {
            format!("--dims {D}: expected 1, 2 or 3")
        });
    }
    if spec.strata.is_some() && s != Sampler::Jittered {
        return Err(format!(
            "--strata applies only to --sampler jittered (got --sampler {s})"
        ));
    }
    if !s.is_poisson() && (spec.relative_radius != DEFAULT_RELATIVE_RADIUS || spec.bridson) {
        return Err(format!(
            "--relative-radius and --bridson apply only to --sampler poisson-disk or \
             poisson-disk-thinned (got --sampler {s})"
        ));
    }
    if spec.grid.is_some() && !matches!(s, Sampler::MultiJittered | Sampler::Cmj) {
        return Err(format!(
            "--grid applies only to --sampler multi-jittered or cmj (got --sampler {s})"
        ));
    }
    let n = spec.n.unwrap_or(DEFAULT_N);
    let err = kernel(spec, n);
    let built = match s {
        Sampler::Random => plain(Random::<D>::new(n).map(|p| boxed(p, shift)), &err)?,
        Sampler::NRooks => plain(NRooks::<D>::new(n).map(|p| boxed(p, shift)), &err)?,
        Sampler::Sobol => plain(Sobol::<D>::new(n).map(|p| boxed(p, shift)), &err)?,
        Sampler::Halton => plain(Halton::<D>::new(n).map(|p| boxed(p, shift)), &err)?,
        Sampler::Pmj02 | Sampler::Pmj02Bn => {
            let p = if s == Sampler::Pmj02 {
                Pmj02::new(n)
            } else {
                Pmj02::blue_noise(n)
            }
            .map_err(&err)?;
            Built {
                pattern: as_dims::<D>(boxed(p, shift))
                    .ok_or_else(|| format!("--dims {D}: --sampler {s} supports only --dims 2"))?,
                detail: None,
            }
        }
        Sampler::Ccvt => Built {
            pattern: boxed(Ccvt::<D>::new(n).map_err(err)?, shift),
            detail: Some("capacity 64".into()),
        },
        Sampler::PoissonDisk | Sampler::PoissonDiskThinned => {
            let method = if spec.bridson {
                PoissonMethod::Bridson
            } else {
                PoissonMethod::MaximalDartThrowing
            };
            let thinned = spec.bridson || s == Sampler::PoissonDiskThinned;
            let n_mode = if thinned {
                PoissonN::ThinnedRun
            } else {
                PoissonN::SequentialDartThrowing
            };
            let perr = |e: PatternError| {
                format!(
                    "invalid parameters for --sampler {s} -n {n} --relative-radius {}: {e}",
                    spec.relative_radius
                )
            };
            let disk = PoissonDisk::<D>::for_n(n, spec.relative_radius)
                .map_err(perr)?
                .with_method(method)
                .with_n_mode(n_mode);
            let detail = format!(
                "r = {:.4} ({} x packing), {}",
                disk.radius(),
                spec.relative_radius,
                match (thinned, spec.bridson) {
                    (false, _) => "dart throwing stopped at N",
                    (true, false) => "maximal dart throwing thinned to N",
                    (true, true) => "Bridson thinned to N",
                }
            );
            Built {
                pattern: boxed(PoissonDiskN::new(disk, n).map_err(perr)?, shift),
                detail: Some(detail),
            }
        }
        Sampler::Jittered => {
            let j = jittered::<D>(spec)?;
            let detail = strata_detail(&j.strata());
            Built {
                pattern: boxed(j, shift),
                detail: Some(detail),
            }
        }
        Sampler::MultiJittered | Sampler::Cmj => {
            let grid_err = |(c, r): (usize, usize)| {
                move |e: PatternError| {
                    format!("invalid parameters for --sampler {s} --grid {c}x{r}: {e}")
                }
            };
            let (p, grid): (DynPattern<2>, (usize, usize)) = if s == Sampler::MultiJittered {
                let p = match spec.grid {
                    None => MultiJittered::new(n).map_err(kernel(spec, n))?,
                    Some(g) => MultiJittered::with_grid(g.0, g.1).map_err(grid_err(g))?,
                };
                let g = p.grid();
                (boxed(p, shift), g)
            } else {
                let p = match spec.grid {
                    None => CorrelatedMultiJittered::new(n).map_err(kernel(spec, n))?,
                    Some(g) => CorrelatedMultiJittered::with_grid(g.0, g.1).map_err(grid_err(g))?,
                };
                let g = p.grid();
                (boxed(p, shift), g)
            };
            Built {
                pattern: as_dims::<D>(p)
                    .ok_or_else(|| format!("--dims {D}: --sampler {s} supports only --dims 2"))?,
                detail: Some(format!("grid {}x{}", grid.0, grid.1)),
            }
        }
    };
    if let (Some(n), Some((c, r))) = (spec.n, spec.grid) {
        // The kernel checks --strata against -n itself; --grid has no n to check.
        if built.pattern.len() != n {
            return Err(format!(
                "-n {n} does not match --grid {c}x{r}, which has {} points; omit -n \
                 or make it COLS*ROWS",
                built.pattern.len()
            ));
        }
    }
    Ok(built)
}

fn strata_detail(strata: &[usize]) -> String {
    let s: Vec<String> = strata.iter().map(ToString::to_string).collect();
    format!("strata {}", s.join("x"))
}

fn jittered<const D: usize>(spec: &PatternSpec) -> Result<Jittered<D>, String> {
    match &spec.strata {
        Some(strata) => {
            let arr: [usize; D] = strata.as_slice().try_into().map_err(|_| {
                format!(
                    "--strata has {} count(s) but --dims is {D}: give one count per axis, \
                     e.g. --strata {}",
                    strata.len(),
                    vec!["16"; D].join(",")
                )
            })?;
            let r = match spec.n {
                Some(n) => Jittered::<D>::with_n(n, arr),
                None => Jittered::<D>::new(arr),
            };
            r.map_err(|e| {
                format!(
                    "invalid parameters for --sampler jittered --dims {D} --strata {}: {e}",
                    strata
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join(",")
                )
            })
        }
        None => {
            let n = spec.n.unwrap_or(DEFAULT_N);
            Jittered::<D>::cube(n).map_err(|e| match e {
                PatternError::StrataMismatch { .. } => {
                    let power = if D == 2 { "square" } else { "cube" };
                    format!(
                        "-n {n} is not a perfect {power}, so --sampler jittered --dims {D} \
                         has no default grid ({e}); pass the per-axis strata counts with \
                         --strata ({D} comma-separated counts whose product is n)"
                    )
                }
                other => kernel(spec, n)(other),
            })
        }
    }
}

/// Fills all points of `pattern` for `seed` into a new, fallibly allocated
/// buffer, `runs` times (at least once), and returns the points and the median
/// wall time of one fill.
///
/// # Errors
/// If the buffer cannot be allocated or the fill fails (a Poisson-disk
/// shortfall says what to change).
pub fn generate<const D: usize>(
    pattern: &dyn Pattern<D>,
    seed: Seed,
    runs: usize,
) -> Result<(Vec<[f32; D]>, Duration)> {
    let n = pattern.len();
    let mut buf = buffer::filled(n, [0.0f32; D], &format!("{n} points of {D} coordinates"))?;
    let mut times = Vec::with_capacity(runs.max(1));
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        pattern
            .fill(seed, std::hint::black_box(&mut buf))
            .map_err(|e| match e {
                PatternError::Shortfall { .. } => LabError::Message(format!(
                    "fill failed: {e}; lower --relative-radius (dart throwing jams at \
                     about 0.74 in 1D, 0.77 in 2D, 0.80 in 3D) or drop --bridson"
                )),
                _ => LabError::Message(format!("fill failed: {e}")),
            })?;
        times.push(t.elapsed());
    }
    times.sort_unstable();
    Ok((buf, times[times.len() / 2]))
}
