//! `paper`: the synthetic experiments of Singh, Miller & Jarosz (EGSR 2017) in
//! one command, with an HTML report.
//!
//! The plan ([`plan`]) lists convergence curves (each a
//! [`convergence::Config`]), spectral predictions and timing cases. They run
//! as the cells of one runner experiment, so `paper` resumes, shards and
//! merges like every command: a curve's N is one cell (computed by the
//! `convergence` experiment's own cell code, or, for the randomised straight
//! edge, by a row function that draws the edge per realisation), a
//! prediction is one cell (the mean periodogram of one sampler at one N and,
//! per predicted row, the statistics of the per-realisation predictions), and each timing case is one cell that runs
//! alone after every other cell ([`Experiment::exclusive`]). [`results`] turns
//! the cells into typed results and [`report`] writes them.

pub mod plan;
pub mod report;
pub mod results;
pub mod scenes;
pub mod theory;
pub mod timing;

use linesample::estimator::{Directions, Estimator, LineEstimator};
use linesample::geom::Direction;
use linesample::integrand::{HalfSpace, Integrand};
use linesample::num::sinc;
use linesample::spectrum::{Dft, Grid, Periodogram, PredictionStats};
use linesample::stats::RunningStats;
use linesample::Seed;
use serde::{Deserialize, Serialize};

use crate::experiments::convergence::{self, Convergence, DirSpec};
use crate::experiments::{config_from, merge_to_files};
use crate::integrand::{to_array, IntegrandKind, Params};
use crate::io::buffer;
use crate::runner::{CellInfo, Ctx, Experiment};
use crate::sampler::{self, PatternSpec};
use crate::spec::MergeRequest;
use crate::spec::Primitive;
use crate::{LabError, Result};

pub use plan::{Config, Curve, Mode};

/// The experiment's name.
pub const KIND: &str = "paper";

/// Default output folder.
pub const DEFAULT_OUT: &str = "out/paper";

/// Realisations per chunk of a prediction cell.
const PRED_CHUNK: u64 = 8;
/// Samples per chunk of the direct transform.
const DFT_CHUNK: usize = 128;
/// Seed purpose of the random edge offsets.
const EDGE_PURPOSE: u64 = 0xED6E;
/// Seed purpose of the prediction patterns.
const PRED_PURPOSE: u64 = 0x9E1D;

/// What a cell computes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Job {
    /// Row `row` of curve `curve` by the convergence experiment.
    Conv { curve: usize, row: usize },
    /// Row `row` of a randomised-edge curve.
    Edge { curve: usize, row: usize },
    /// Prediction `i`.
    Pred(usize),
    /// f32 SIMD vs f64 case `i`.
    Simd(usize),
    /// The NUFFT tolerance sweep.
    Nufft,
}

/// The prediction of one predicted row, as the kernel reports it
/// (`PredictionStats::prediction`, then `Prediction::with_white_outside`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RowPrediction {
    /// Realisations the prediction averages.
    pub realisations: u64,
    /// The predicted variance, with the tail outside the grid taken as white.
    pub predicted: f64,
    /// Its standard error over the realisations (`None` below 2).
    pub predicted_se: Option<f64>,
    /// `Σ p_f` outside the grid (taken as white), or 0.
    pub tail: f64,
}

/// A prediction cell.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PredCell {
    /// One per `Prediction::rows`, in order.
    pub rows: Vec<RowPrediction>,
    /// `Periodogram::parts` sums when the prediction feeds a figure (else empty).
    pub periodogram: Vec<f64>,
    pub realisations: u64,
}

/// One cell's stored state.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum Cell {
    /// Chunk statistics of a curve row (estimates, or errors for the edge).
    Conv(convergence::Cell),
    Pred(PredCell),
    Simd(timing::SimdRow),
    Nufft(Vec<timing::NufftRow>),
}

/// The experiment.
#[derive(Debug)]
pub struct Paper {
    config: Config,
    /// The convergence experiment of each curve (`None` for randomised edges).
    convs: Vec<Option<Convergence>>,
    jobs: Vec<Job>,
    cells: Vec<CellInfo>,
}

impl Paper {
    /// The experiment of `config`, every curve checked.
    ///
    /// # Errors
    /// The first invalid curve's message.
    pub fn new(config: Config) -> Result<Self> {
        let mut convs = Vec::new();
        let mut jobs = Vec::new();
        let mut cells = Vec::new();
        for (ci, c) in config.curves.iter().enumerate() {
            let randomised = c.edge.is_some_and(|e| e.randomised);
            convs.push(if randomised {
                None
            } else {
                Some(Convergence::new(c.run.clone()).map_err(|e| format!("{}: {e}", c.id))?)
            });
            for (ri, row) in c.run.rows.iter().enumerate() {
                jobs.push(if randomised {
                    Job::Edge { curve: ci, row: ri }
                } else {
                    Job::Conv { curve: ci, row: ri }
                });
                cells.push(CellInfo {
                    label: format!("{} N = {}", c.id, row.n),
                    work: c.run.realisations,
                });
            }
        }
        for (i, p) in config.predictions.iter().enumerate() {
            jobs.push(Job::Pred(i));
            cells.push(CellInfo {
                label: format!("spectrum {} {}D N = {}", p.sampler, p.pattern_dims, p.n),
                work: p.realisations,
            });
        }
        for (i, (spec, prim)) in config.timing.simd.iter().enumerate() {
            jobs.push(Job::Simd(i));
            cells.push(CellInfo {
                label: format!(
                    "timing f32 vs f64 {} {}D {}",
                    spec.kind.name(),
                    spec.dims,
                    prim.name()
                ),
                work: 0,
            });
        }
        jobs.push(Job::Nufft);
        cells.push(CellInfo {
            label: "timing NUFFT tolerance sweep".into(),
            work: 0,
        });
        Ok(Paper {
            config,
            convs,
            jobs,
            cells,
        })
    }

    /// The plan.
    #[must_use]
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The convergence experiment of curve `i` (`None` for randomised edges).
    #[must_use]
    pub fn convergence(&self, i: usize) -> Option<&Convergence> {
        self.convs.get(i).and_then(Option::as_ref)
    }

    /// The index of a job's cell in [`Experiment::cells`].
    #[cfg(test)]
    fn job_index(&self, job: Job) -> Option<usize> {
        self.jobs.iter().position(|&j| j == job)
    }
}

impl Experiment for Paper {
    type Config = Config;
    type Cell = Cell;
    const KIND: &'static str = KIND;
    const UNIT: &'static str = "realisations";

    fn config(&self) -> &Config {
        &self.config
    }

    fn cells(&self) -> &[CellInfo] {
        &self.cells
    }

    fn exclusive(&self, index: usize) -> bool {
        matches!(self.jobs.get(index), Some(Job::Simd(_) | Job::Nufft))
    }

    fn run_cell(&self, index: usize, ctx: &Ctx<'_>) -> crate::Result<Cell> {
        let cfg = &self.config;
        let label = &self.cells[index].label;
        self.job(index, cfg, ctx)
            .map_err(|e| format!("paper cell {index} ({label}): {e}").into())
    }
}

impl Paper {
    fn job(&self, index: usize, cfg: &Config, ctx: &Ctx<'_>) -> Result<Cell> {
        match self.jobs[index] {
            Job::Conv { curve, row } => {
                let conv = self.convs[curve]
                    .as_ref()
                    .ok_or_else(|| LabError::Internal("no convergence experiment".into()))?;
                // `run_cell` keeps the runner trait's `String` error.
                Ok(conv.run_cell(row, ctx).map(Cell::Conv)?)
            }
            Job::Edge { curve, row } => edge_row(&cfg.curves[curve], row, ctx).map(Cell::Conv),
            Job::Pred(i) => {
                let p = &cfg.predictions[i];
                match p.pattern_dims {
                    1 => predict::<1>(cfg, p, ctx),
                    2 => predict::<2>(cfg, p, ctx),
                    3 => predict::<3>(cfg, p, ctx),
                    d => Err(LabError::Internal(format!("a {d}-dimensional pattern"))),
                }
                .map(Cell::Pred)
            }
            Job::Simd(i) => {
                let (spec, prim) = &cfg.timing.simd[i];
                timing::simd_case(
                    spec,
                    *prim,
                    cfg.timing.simd_evaluations,
                    cfg.timing.repeats,
                    cfg.seed,
                )
                .map(Cell::Simd)
            }
            Job::Nufft => {
                let t = &cfg.timing;
                timing::nufft_sweep(
                    t.nufft_dims,
                    t.nufft_n,
                    t.nufft_k,
                    &t.nufft_tols,
                    t.repeats,
                    cfg.seed,
                )
                .map(Cell::Nufft)
            }
        }
    }
}

/// The pattern of `sampler` with `n` points in `dims` dimensions, with the
/// plan's Poisson-disk radius ([`plan::poisson_radius`]).
fn pattern_spec(sampler: crate::sampler::Sampler, dims: usize, n: usize) -> PatternSpec {
    let mut s = PatternSpec::simple(sampler, dims, n);
    if sampler.is_poisson() {
        s.relative_radius = plan::poisson_radius(dims);
    }
    s
}

/// A uniform number in `[0, 1)` from 53 bits of `x`.
fn unit(x: u64) -> f64 {
    (x >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The edge offset of realisation `r` of a randomised-edge curve.
#[must_use]
pub fn edge_offset(curve: &Curve, seed: Seed, r: u64) -> f64 {
    match curve.edge {
        Some(e) if e.randomised => {
            e.lo + (e.hi - e.lo) * unit(seed.realization(r).stream(EDGE_PURPOSE))
        }
        Some(e) => e.lo,
        None => f64::NAN,
    }
}

/// Row `row` of a randomised straight-edge curve (2D lines): realisation `r`
/// draws the edge offset `h_r` ([`edge_offset`]), builds the half-space
/// `1[n·x ≥ h_r]` and records the error `I_N − ∫f` of the line estimator with
/// the pattern as generated (no shift: the strata stay aligned with the
/// domain, whose boundary is then not a discontinuity the estimator sees).
/// Seeds and chunks are those of `convergence` ([`convergence::row_seed`],
/// [`convergence::run_chunks`]).
fn edge_row(curve: &Curve, row: usize, ctx: &Ctx<'_>) -> Result<convergence::Cell> {
    let cfg = &curve.run;
    let row = cfg.rows[row];
    let Params::Edge { normal, .. } = &cfg.integrand.params else {
        return Err(LabError::Internal("an edge curve without an edge".into()));
    };
    let normal = Direction::<2>::new(to_array(normal)).map_err(|e| format!("edge normal: {e}"))?;
    let DirSpec::Fixed(d) = &cfg.dirs else {
        return Err(LabError::Internal(
            "an edge curve without a line direction".into(),
        ));
    };
    let dir = Direction::<2>::new(to_array(d)).map_err(|e| format!("line direction: {e}"))?;
    let spec = pattern_spec(cfg.sampler, 1, row.per_group);
    let pattern = sampler::build::<1>(&spec, false)?.pattern;
    let seed = convergence::row_seed(cfg.seed, row.n);
    convergence::run_chunks(ctx, cfg.realisations, |first, count| {
        let est = LineEstimator::<2, 1>::new(&*pattern, Directions::Fixed(dir))
            .map_err(|e| format!("{}: {e}", curve.id))?;
        let mut scratch = buffer::filled(est.scratch_len(), 0.0f32, "estimator scratch")?;
        let mut st = RunningStats::new();
        for r in first..first + count {
            let h = edge_offset(curve, seed, r);
            let f = HalfSpace::<2>::new(normal, h).map_err(|e| format!("edge offset {h}: {e}"))?;
            let v = est
                .estimate(&f, seed.realization(r), false, &mut scratch)
                .map_err(|e| format!("{} N = {}, realisation {r}: {e}", curve.id, row.n))?;
            st.push(v - f.integral());
        }
        Ok(st)
    })
}

/// The weights `w(ν) = multiplicity·p_f(ν)` of one predicted row on the
/// `K`-dimensional half grid (0 at DC), and the tail `Σ p_f` outside it:
/// `p_f = |f̂|²` (points), `|f̂|²·sinc²(λ ν·ω)` (segments along an axis), or
/// the slice `|f̂(ν_⊥, ν_a = 0)|²` (lines along axis `a`; Fourier slice
/// theorem). The tail is exact by Parseval for indicators sampled by points
/// (`∫f² − (∫f)² = I − I²`), else the sum over the shell
/// `k < |ν|_∞ ≤ 4k` (the rest is neglected; it is below 1e-3 of the grid
/// part for every case of the plan).
fn weights<const D: usize, const K: usize>(
    curve: &Curve,
    grid: Grid<K>,
) -> Result<(Vec<f64>, f64)> {
    let r = &curve.run;
    let f = r.integrand.build::<D>()?;
    let axis = match &r.dirs {
        DirSpec::Fixed(v) => v.iter().position(|&x| x != 0.0).unwrap_or(D - 1),
        _ => D - 1,
    };
    let embed = |j: [i32; K]| -> [i32; D] {
        let mut full = [0i32; D];
        if D == K {
            full[..K].copy_from_slice(&j);
        } else {
            let mut b = 0;
            for (a, x) in full.iter_mut().enumerate() {
                if a != axis {
                    *x = j[b];
                    b += 1;
                }
            }
        }
        full
    };
    let length = r.length;
    let segments = r.primitive == Primitive::Segments;
    let pf = |j: [i32; K]| -> f64 {
        let full = embed(j);
        let p = f.fourier(&full).norm_sqr();
        if segments {
            let s = sinc(length * f64::from(full[axis]));
            p * s * s
        } else {
            p
        }
    };
    let mut w = buffer::filled(grid.len(), 0.0f64, "prediction weights")?;
    let in_grid = grid
        .spectrum_weights(pf, &mut w)
        .map_err(|e| format!("prediction weights: {e}"))?;
    let indicator = matches!(r.integrand.kind, IntegrandKind::Disk | IntegrandKind::Ball);
    let tail = if indicator && r.primitive == Primitive::Points {
        let i = f.integral();
        (i - i * i - in_grid).max(0.0)
    } else {
        let k = i32::try_from(grid.half_width()).map_err(|_| "grid too large")?;
        let big = Grid::<K>::new(4 * grid.half_width()).map_err(|e| format!("tail grid: {e}"))?;
        let mut t = 0.0;
        for i in 0..big.len() {
            let j = big.freq(i);
            if j.iter().any(|&a| a.abs() > k) {
                t += f64::from(big.multiplicity(i)) * pf(j);
            }
        }
        t
    };
    Ok((w, tail))
}

fn weights_for<const K: usize>(curve: &Curve, grid: Grid<K>) -> Result<(Vec<f64>, f64)> {
    match (curve.run.dims(), K) {
        (2, 2) => weights::<2, K>(curve, grid),
        (3, 3) => weights::<3, K>(curve, grid),
        (2, 1) => weights::<2, K>(curve, grid),
        (3, 2) => weights::<3, K>(curve, grid),
        (d, k) => Err(LabError::Internal(format!(
            "a {d}D curve predicted from a {k}D pattern"
        ))),
    }
}

/// A prediction cell: realisations of the pattern (independent of the
/// measured ones), their exact amplitudes, the mean periodogram and, per
/// predicted row, the kernel's prediction with its standard error
/// (`PredictionStats`, merged in chunk order).
fn predict<const K: usize>(cfg: &Config, p: &plan::Prediction, ctx: &Ctx<'_>) -> Result<PredCell> {
    let grid = Grid::<K>::new(p.k).map_err(|e| format!("prediction grid k = {}: {e}", p.k))?;
    let pattern = sampler::build::<K>(&pattern_spec(p.sampler, K, p.n), false)?.pattern;
    let ws: Vec<(Vec<f64>, f64)> = p
        .rows
        .iter()
        .map(|&(c, _)| weights_for::<K>(&cfg.curves[c], grid))
        .collect::<Result<_, _>>()?;
    let seed = Seed::new(Seed::new(cfg.seed ^ PRED_PURPOSE).stream(p.n as u64));
    let chunks = usize::try_from(p.realisations.div_ceil(PRED_CHUNK))
        .map_err(|_| "too many realisations".to_string())?;
    let parts = ctx.map_ordered(chunks, |c| {
        let mut dft = Dft::new_vec(grid);
        let mut per = Periodogram::new_vec(grid);
        let mut stats = ws
            .iter()
            .map(|(w, _)| PredictionStats::new(grid, &w[..]))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| format!("prediction weights: {e}"))?;
        let mut pts = buffer::filled(p.n, [0.0f32; K], "pattern points")?;
        let per_sample = Dft::<K, Vec<f64>>::points_scratch_per_sample(grid);
        let mut scratch = buffer::filled(DFT_CHUNK * per_sample, 0.0f64, "transform scratch")?;
        let first = c as u64 * PRED_CHUNK;
        let count = PRED_CHUNK.min(p.realisations - first);
        for r in first..first + count {
            pattern
                .fill(seed.realization(r), &mut pts)
                .map_err(|e| format!("{} {K}D N = {}: {e}", p.sampler, p.n))?;
            dft.clear();
            dft.add_points(&pts, &mut scratch)
                .map_err(|e| format!("transform: {e}"))?;
            per.add(&dft).map_err(|e| format!("periodogram: {e}"))?;
            for st in &mut stats {
                st.add(&dft).map_err(|e| format!("prediction: {e}"))?;
            }
        }
        ctx.advance(count);
        Ok((per, stats))
    })?;
    let mut total = Periodogram::new_vec(grid);
    let mut stats = ws
        .iter()
        .map(|(w, _)| PredictionStats::new(grid, &w[..]))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| format!("prediction weights: {e}"))?;
    for (per, st) in &parts {
        total
            .merge(per)
            .map_err(|e| format!("periodogram merge: {e}"))?;
        for (a, b) in stats.iter_mut().zip(st) {
            a.merge(b).map_err(|e| format!("prediction merge: {e}"))?;
        }
    }
    let (sums, realisations) = total.parts();
    let mut rows = Vec::with_capacity(stats.len());
    for (st, (_, tail)) in stats.iter().zip(&ws) {
        let pred = st
            .prediction(p.n as u64)
            .map_err(|e| format!("prediction: {e}"))?;
        rows.push(RowPrediction {
            realisations: pred.realisations,
            predicted: pred.with_white_outside(*tail),
            predicted_se: pred.std_error,
            tail: *tail,
        });
    }
    Ok(PredCell {
        rows,
        periodogram: if p.figure { sums.to_vec() } else { Vec::new() },
        realisations,
    })
}

/// `linesample-lab merge` for paper shards.
///
/// # Errors
/// As [`crate::runner::merge`].
pub fn merge(a: &MergeRequest, config: serde_json::Value) -> Result<()> {
    let exp = Paper::new(config_from(config, KIND)?)?;
    merge_to_files(
        &exp,
        a,
        Box::new(|e, c, i, o, q| {
            report::complete(e, &c, i, o, q, &scenes::sections())?;
            Ok(())
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plans_are_valid_and_distinct() {
        for mode in [Mode::Reduced, Mode::Quick, Mode::Full] {
            let cfg = plan::plan(mode, 1);
            let ids: std::collections::BTreeSet<&str> =
                cfg.curves.iter().map(|c| c.id.as_str()).collect();
            assert_eq!(ids.len(), cfg.curves.len(), "{mode:?}: duplicate curve ids");
            let exp = Paper::new(cfg).unwrap();
            assert!(exp.cells().len() > 10);
            for (i, c) in exp.config.curves.iter().enumerate() {
                assert!(
                    exp.job_index(Job::Conv { curve: i, row: 0 }).is_some()
                        || exp.job_index(Job::Edge { curve: i, row: 0 }).is_some(),
                    "{}",
                    c.id
                );
            }
        }
    }

    #[test]
    fn edge_offsets_cover_their_range() {
        let cfg = plan::plan(Mode::Reduced, 1);
        let c = cfg
            .curves
            .iter()
            .find(|c| c.edge.is_some_and(|e| e.randomised))
            .unwrap();
        let e = c.edge.unwrap();
        let s = Seed::new(3);
        let hs: Vec<f64> = (0..2000).map(|r| edge_offset(c, s, r)).collect();
        assert!(hs.iter().all(|&h| h >= e.lo && h < e.hi));
        let mean = hs.iter().sum::<f64>() / hs.len() as f64;
        // Uniform: mean (lo + hi)/2 within 4 SE.
        let se = (e.hi - e.lo) / (12.0f64 * hs.len() as f64).sqrt();
        assert!((mean - 0.5 * (e.lo + e.hi)).abs() < 4.0 * se, "{mean}");
    }
}
