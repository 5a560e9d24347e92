//! Turning command-line choices into kernel patterns, and running them.
//!
//! Nothing here computes sample positions: every number comes from a
//! `linesample::pattern` constructor and `Pattern::fill`.

use std::fmt;
use std::time::{Duration, Instant};

use clap::ValueEnum;
use linesample::pattern::{
    Ccvt, CorrelatedMultiJittered, Halton, Jittered, MultiJittered, NRooks, Pattern, PoissonDisk,
    PoissonMethod, Random, Sobol,
};
use linesample::{PatternError, Seed};

/// The sample patterns the lab can write.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
#[value(rename_all = "kebab-case")]
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
    /// Toroidal Poisson disk, 1D to 3D: N points from a maximal (or Bridson) set
    /// with radius --relative-radius times the densest-packing radius for N.
    PoissonDisk,
    /// Capacity-constrained Voronoi tessellation (Balzer et al. 2009), 2D and 3D.
    Ccvt,
}

impl Sampler {
    /// Every sampler, in the order of the gallery.
    pub const ALL: [Sampler; 9] = [
        Sampler::Random,
        Sampler::Jittered,
        Sampler::NRooks,
        Sampler::MultiJittered,
        Sampler::Cmj,
        Sampler::Sobol,
        Sampler::Halton,
        Sampler::PoissonDisk,
        Sampler::Ccvt,
    ];

    /// The command-line name (as `--sampler` accepts it).
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Random => "random",
            Sampler::Jittered => "jittered",
            Sampler::NRooks => "n-rooks",
            Sampler::MultiJittered => "multi-jittered",
            Sampler::Cmj => "cmj",
            Sampler::Sobol => "sobol",
            Sampler::Halton => "halton",
            Sampler::PoissonDisk => "poisson-disk",
            Sampler::Ccvt => "ccvt",
        }
    }

    /// Dimensions this sampler supports.
    pub fn dims(self) -> &'static [usize] {
        match self {
            Sampler::MultiJittered | Sampler::Cmj => &[2],
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

/// What to build: the sampler and its parameters as given on the command line.
#[derive(Clone, Debug)]
pub struct Spec {
    pub sampler: Sampler,
    pub dims: usize,
    /// `-n`; `None` means "from --strata / --grid, else 1024".
    pub n: Option<usize>,
    pub strata: Option<Vec<usize>>,
    pub grid: Option<(usize, usize)>,
    pub shift: bool,
    /// Poisson disk: radius relative to the densest packing for N.
    pub relative_radius: f64,
    /// Poisson disk: maximal dart throwing (`true`) or Bridson.
    pub dart_throwing: bool,
}

/// `N` when neither `-n`, `--strata` nor `--grid` says otherwise.
pub const DEFAULT_N: usize = 1024;

/// A built pattern of any supported dimension.
pub enum AnyPattern {
    D1(Box<dyn Pattern<1>>),
    D2(Box<dyn Pattern<2>>),
    D3(Box<dyn Pattern<3>>),
}

/// A built pattern plus what the plot title should say about it.
pub struct Built {
    pub pattern: AnyPattern,
    /// Extra parameters worth showing, e.g. `strata 32x32`.
    pub detail: Option<String>,
}

/// Points in row-major order (`dims` coordinates per point).
pub struct Points {
    pub dims: usize,
    pub coords: Vec<f32>,
}

impl Points {
    pub fn len(&self) -> usize {
        self.coords.len() / self.dims
    }

    pub fn iter(&self) -> std::slice::ChunksExact<'_, f32> {
        self.coords.chunks_exact(self.dims)
    }
}

impl AnyPattern {
    pub fn len(&self) -> usize {
        match self {
            AnyPattern::D1(p) => p.len(),
            AnyPattern::D2(p) => p.len(),
            AnyPattern::D3(p) => p.len(),
        }
    }

    /// Fills all points `runs` times (at least once) and returns the points with
    /// the median wall time of one `fill`.
    pub fn generate(&self, seed: Seed, runs: usize) -> Result<(Points, Duration), String> {
        match self {
            AnyPattern::D1(p) => run(p.as_ref(), seed, runs),
            AnyPattern::D2(p) => run(p.as_ref(), seed, runs),
            AnyPattern::D3(p) => run(p.as_ref(), seed, runs),
        }
    }
}

fn run<const D: usize>(
    p: &dyn Pattern<D>,
    seed: Seed,
    runs: usize,
) -> Result<(Points, Duration), String> {
    let n = p.len();
    let mut buf: Vec<[f32; D]> = Vec::new();
    buf.try_reserve_exact(n).map_err(|_| {
        format!(
            "n = {n}: cannot allocate memory for {n} points of {D} coordinates \
             ({} bytes)",
            (n as u128) * (D as u128) * 4
        )
    })?;
    buf.resize(n, [0.0; D]);
    let mut times = Vec::with_capacity(runs.max(1));
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        p.fill(seed, std::hint::black_box(&mut buf))
            .map_err(|e| match e {
                PatternError::Shortfall { .. } => format!(
                    "fill failed: {e}; lower --relative-radius or use maximal dart \
                     throwing (drop --bridson)"
                ),
                _ => format!("fill failed: {e}"),
            })?;
        times.push(t.elapsed());
    }
    times.sort_unstable();
    let median = times[times.len() / 2];
    let mut coords = Vec::new();
    coords
        .try_reserve_exact(n * D)
        .map_err(|_| format!("n = {n}: cannot allocate memory for the coordinates"))?;
    coords.extend(buf.iter().flatten());
    Ok((Points { dims: D, coords }, median))
}

fn boxed<const D: usize, P: Pattern<D> + 'static>(p: P, shift: bool) -> Box<dyn Pattern<D>> {
    if shift {
        Box::new(p.shifted())
    } else {
        Box::new(p)
    }
}

/// Prefixes a kernel error with what was being built.
fn kernel(spec: &Spec, n: usize) -> impl Fn(PatternError) -> String + '_ {
    move |e| {
        format!(
            "invalid parameters for --sampler {} --dims {} -n {n}: {e}",
            spec.sampler, spec.dims
        )
    }
}

/// Builds the pattern `spec` describes.
///
/// # Errors
/// A message naming the offending parameter: an unsupported `--dims`, an option
/// that does not apply to the sampler, or the kernel's own [`PatternError`].
pub fn build(spec: &Spec) -> Result<Built, String> {
    let s = spec.sampler;
    if !s.dims().contains(&spec.dims) {
        return Err(if s.dims().len() == 1 {
            format!(
                "--dims {}: --sampler {s} supports only --dims {}",
                spec.dims,
                s.dims()[0]
            )
        } else {
            format!("--dims {}: expected 1, 2 or 3", spec.dims)
        });
    }
    if spec.strata.is_some() && s != Sampler::Jittered {
        return Err(format!(
            "--strata applies only to --sampler jittered (got --sampler {s})"
        ));
    }
    if s != Sampler::PoissonDisk && (spec.relative_radius != 0.75 || !spec.dart_throwing) {
        return Err(format!(
            "--relative-radius and --bridson apply only to --sampler poisson-disk (got --sampler {s})"
        ));
    }
    if spec.grid.is_some() && !matches!(s, Sampler::MultiJittered | Sampler::Cmj) {
        return Err(format!(
            "--grid applies only to --sampler multi-jittered or cmj (got --sampler {s})"
        ));
    }
    let built = match spec.dims {
        1 => {
            let (p, detail) = build_common::<1>(spec)?;
            Built {
                pattern: AnyPattern::D1(p),
                detail,
            }
        }
        2 => {
            let (p, detail) = build_2d(spec)?;
            Built {
                pattern: AnyPattern::D2(p),
                detail,
            }
        }
        3 => {
            let (p, detail) = build_common::<3>(spec)?;
            Built {
                pattern: AnyPattern::D3(p),
                detail,
            }
        }
        d => return Err(format!("--dims {d}: expected 1, 2 or 3")),
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

type Boxed<const D: usize> = (Box<dyn Pattern<D>>, Option<String>);

/// The samplers available in every dimension (`D` = 1 and 3; 2D goes through
/// [`build_2d`]).
fn build_common<const D: usize>(spec: &Spec) -> Result<Boxed<D>, String>
where
    Random<D>: Pattern<D>,
    NRooks<D>: Pattern<D>,
    Sobol<D>: Pattern<D>,
    Halton<D>: Pattern<D>,
{
    let n = spec.n.unwrap_or(DEFAULT_N);
    let err = kernel(spec, n);
    let shift = spec.shift;
    Ok(match spec.sampler {
        Sampler::Random => (boxed(Random::<D>::new(n).map_err(err)?, shift), None),
        Sampler::NRooks => (boxed(NRooks::<D>::new(n).map_err(err)?, shift), None),
        Sampler::Sobol => (boxed(Sobol::<D>::new(n).map_err(err)?, shift), None),
        Sampler::Halton => (boxed(Halton::<D>::new(n).map_err(err)?, shift), None),
        Sampler::PoissonDisk => {
            let method = if spec.dart_throwing {
                PoissonMethod::MaximalDartThrowing
            } else {
                PoissonMethod::Bridson
            };
            let disk = PoissonDisk::<D>::for_n(n, spec.relative_radius)
                .map_err(|e| {
                    format!(
                        "invalid parameters for --sampler poisson-disk -n {n} \
                         --relative-radius {}: {e}",
                        spec.relative_radius
                    )
                })?
                .with_method(method);
            let detail = format!(
                "r = {:.4} ({} x packing), {}",
                disk.radius(),
                spec.relative_radius,
                if spec.dart_throwing {
                    "maximal dart throwing"
                } else {
                    "Bridson"
                }
            );
            (boxed(PoissonN { disk, n }, shift), Some(detail))
        }
        Sampler::Ccvt => (
            boxed(Ccvt::<D>::new(n).map_err(err)?, shift),
            Some("capacity 64".into()),
        ),
        Sampler::Jittered => {
            let j = jittered::<D>(spec)?;
            let detail = strata_detail(&j.strata());
            (boxed(j, shift), Some(detail))
        }
        Sampler::MultiJittered | Sampler::Cmj => {
            return Err(format!(
                "--dims {D}: --sampler {} supports only --dims 2",
                spec.sampler
            ))
        }
    })
}

/// N points of a Poisson-disk set as a [`Pattern`]: each fill generates the whole
/// set for the seed (allocating, as the lab may) and keeps a random subset of N
/// (`PoissonDisk::generate_n_vec`); fewer than N fitting is an error that says so.
struct PoissonN<const D: usize> {
    disk: PoissonDisk<D>,
    n: usize,
}

impl<const D: usize> PoissonN<D> {
    fn points(&self, seed: Seed, first: usize, len: usize) -> Result<Vec<[f32; D]>, PatternError> {
        if first.checked_add(len).is_none_or(|e| e > self.n) {
            return Err(PatternError::Range {
                first: first as u64,
                len: len as u64,
                n: self.n as u64,
            });
        }
        let all = self.disk.generate_n_vec(self.n, seed)?;
        Ok(all[first..first + len].to_vec())
    }
}

impl<const D: usize> Pattern<D> for PoissonN<D> {
    fn len(&self) -> usize {
        self.n
    }

    fn fill_range(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        out.copy_from_slice(&self.points(seed, first, out.len())?);
        Ok(())
    }

    fn fill_range_scalar(
        &self,
        seed: Seed,
        first: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        self.fill_range(seed, first, out)
    }

    fn fill_range_soa(
        &self,
        seed: Seed,
        first: usize,
        out: [&mut [f32]; D],
    ) -> Result<(), PatternError> {
        let len = out[0].len();
        if out.iter().any(|s| s.len() != len) {
            return Err(PatternError::OutputLength {
                expected: len,
                got: out
                    .iter()
                    .map(|s| s.len())
                    .find(|&l| l != len)
                    .unwrap_or(len),
            });
        }
        let pts = self.points(seed, first, len)?;
        for (j, col) in out.into_iter().enumerate() {
            for (x, p) in col.iter_mut().zip(&pts) {
                *x = p[j];
            }
        }
        Ok(())
    }
}

fn build_2d(spec: &Spec) -> Result<Boxed<2>, String> {
    let n = spec.n.unwrap_or(DEFAULT_N);
    let shift = spec.shift;
    let grid_detail = |(c, r): (usize, usize)| Some(format!("grid {c}x{r}"));
    match (spec.sampler, spec.grid) {
        (Sampler::MultiJittered, grid) => {
            let p = match grid {
                None => MultiJittered::new(n).map_err(kernel(spec, n))?,
                Some((c, r)) => MultiJittered::with_grid(c, r).map_err(grid_err(spec, c, r))?,
            };
            let detail = grid_detail(p.grid());
            Ok((boxed(p, shift), detail))
        }
        (Sampler::Cmj, grid) => {
            let p = match grid {
                None => CorrelatedMultiJittered::new(n).map_err(kernel(spec, n))?,
                Some((c, r)) => {
                    CorrelatedMultiJittered::with_grid(c, r).map_err(grid_err(spec, c, r))?
                }
            };
            let detail = grid_detail(p.grid());
            Ok((boxed(p, shift), detail))
        }
        _ => build_common::<2>(spec),
    }
}

fn grid_err(spec: &Spec, c: usize, r: usize) -> impl Fn(PatternError) -> String + '_ {
    move |e| {
        format!(
            "invalid parameters for --sampler {} --grid {c}x{r}: {e}",
            spec.sampler
        )
    }
}

fn strata_detail(strata: &[usize]) -> String {
    let s: Vec<String> = strata.iter().map(ToString::to_string).collect();
    format!("strata {}", s.join("x"))
}

fn jittered<const D: usize>(spec: &Spec) -> Result<Jittered<D>, String> {
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
                         --strata ({} comma-separated counts whose product is n)",
                        D
                    )
                }
                other => kernel(spec, n)(other),
            })
        }
    }
}
