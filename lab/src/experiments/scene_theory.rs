//! The spectral prediction of an AO pixel's variances: the pixel's
//! integrand spectra and the prediction `Var = (1/N) Σ ⟨N·P(j)⟩ |ĝ(j)|²`
//! are the scene crate's ([`linesample_scene::ao::theory`], whose docs
//! derive them); here the patterns' expected periodograms `⟨N·P(j)⟩` are
//! measured from the lab's samplers (NUFFT, tolerance 1e−9) on the same
//! grids.

use linesample::Seed;
use linesample_nufft::Plan;

use super::samples::{Buffers, SamplePattern};
use crate::scene::Primitive;
use crate::spec::ShiftMode;
use linesample_scene::ao::world::{EstimatorSpec, World};

pub use linesample_scene::ao::theory::{predict, PixelSpectra, K1, K2, M, M_LINE};

/// NUFFT tolerance of the patterns' periodograms.
const TOL: f64 = 1e-9;

/// The expected periodogram `⟨N·P(j)⟩` of the offsets of `world`'s `spec` with `n`
/// samples (toroidally shifted), over the realisations `realisations` of
/// `seed`: on the 2D half grid of half-width [`K2`] for points and segments,
/// on the 1D one of half-width [`K1`] for lines (their `u` offsets).
///
/// # Errors
/// A pattern or NUFFT error.
pub fn mean_periodogram(
    world: &World,
    spec: &EstimatorSpec,
    n: usize,
    realisations: std::ops::Range<u64>,
    seed: Seed,
) -> crate::Result<Vec<f64>> {
    let (_, offsets) = SamplePattern::of(world, Some(spec), n, Some(ShiftMode::Random))?;
    if spec.primitive == Primitive::Lines {
        mean_np::<1>(&offsets, K1, realisations, seed, |q| [f64::from(q[0])])
    } else {
        mean_np::<2>(&offsets, K2, realisations, seed, |q| {
            [f64::from(q[0]), f64::from(q[1])]
        })
    }
}

/// The mean of `|F(j)|²/N` on the half grid of half-width `k` over the
/// realisations, the offsets mapped to `D`-dimensional points by `point`.
fn mean_np<const D: usize>(
    offsets: &SamplePattern,
    k: usize,
    realisations: std::ops::Range<u64>,
    seed: Seed,
    point: impl Fn(&[f32; 2]) -> [f64; D],
) -> crate::Result<Vec<f64>> {
    let count = (realisations.end - realisations.start).max(1) as f64;
    let mut plan = Plan::<D>::new(k, TOL).map_err(|e| format!("NUFFT plan: {e}"))?;
    let len = plan.half_len();
    let (mut re, mut im, mut acc) = (vec![0.0; len], vec![0.0; len], vec![0.0; len]);
    let (mut uv, mut buf): (Vec<[f32; 2]>, _) = (Vec::new(), Buffers::default());
    let mut pts = Vec::new();
    for r in realisations {
        offsets.fill(seed.derive(&[r]), &mut uv, &mut buf)?;
        pts.clear();
        pts.extend(uv.iter().map(&point));
        plan.transform(&pts, &mut re, &mut im)
            .map_err(|e| format!("NUFFT: {e}"))?;
        let nf = pts.len() as f64;
        for i in 0..len {
            acc[i] += (re[i] * re[i] + im[i] * im[i]) / nf;
        }
    }
    Ok(acc.iter().map(|a| a / count).collect())
}
