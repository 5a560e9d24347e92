//! Volumetric caustics (`world::caustic`): photon points against photon
//! beams in the lab's two scenes (`scenes/caustic-2d.toml`,
//! `scenes/caustic-3d.toml`): a point light at `(0, 2[, 0])` emitting down
//! into a cone of half-angle 18°, a glass ball of radius 0.5 and index 1.5
//! at the origin (Fresnel, 2 internal reflections), a medium `σ_s = 0.5`,
//! `σ_a = 0.1`, and the scored ball `Q` of radius 0.2 at
//! `(0.05, −1.0[, 0.03])`, across the caustic.
//!
//! Group `caustic`, with jittered primary samples (fixed-seed
//! `linesample::Pcg32`):
//!
//! * `<dims>/beams`: 4096 `Caustic::beam_sample(u)` summed per iteration
//!   (2D: `u₀` jittered in 4096 strata; 3D: `(u₀, u₁)` in 64 × 64);
//!   criterion's `thrpt` is beams per second (trace + closed form);
//! * `<dims>/points`: 4096 `Caustic::point_sample(u, s)` summed (2D:
//!   `(u₀, s)` in 64 × 64 strata; 3D: `(u₀, u₁, s)` in 16 × 16 × 16);
//!   `thrpt` is points per second (trace + one free flight);
//! * `<dims>/<estimator>-to-1pct`: one whole estimate (sample generation
//!   included) at the smallest `N` (doubling from 16, strata as equal as
//!   possible per axis) whose RMSE over 256 independent jittered
//!   realisations is at most 1 % of the reference mean (`2²⁰` jittered
//!   beams). The search runs in the set-up and prints `N` to stderr (an `N`
//!   is abandoned as soon as its partial sum of squared errors exceeds the
//!   1 % budget: the same decision as all 256, sooner).
//!
//! Run: `cargo bench --bench caustic` (about two minutes, most of it the
//! set-up's search for `N`).

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode, Throughput};
use linesample::world::Sphere;
use linesample::Pcg32;
use linesample_scene::caustic::{Caustic, ConeEmitter, Fresnel, Glass, Medium};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Samples per iteration of the throughput benches.
const BATCH: usize = 4096;
/// Independent realisations per RMSE.
const REALISATIONS: usize = 256;
/// Beams of the reference mean.
const REFERENCE_BEAMS: usize = 1 << 20;

/// The lab's scene in `D` dimensions (`scenes/caustic-<D>d.toml`).
fn scene<const D: usize>() -> Caustic<D> {
    let at = |v: [f64; 3]| -> [f64; D] { core::array::from_fn(|j| v[j]) };
    Caustic::new(
        ConeEmitter::new(
            at([0.0, 2.0, 0.0]),
            at([0.0, -1.0, 0.0]),
            18f64.to_radians(),
        )
        .unwrap(),
        Glass::new([0.0; D], 0.5, 1.5).unwrap(),
        Medium::new(0.5, 0.1).unwrap(),
        Sphere::new(at([0.05, -1.0, 0.03]), 0.2).unwrap(),
        Fresnel::On {
            internal_reflections: 2,
        },
    )
    .unwrap()
}

/// Uniform double in `[0, 1)` (53 random bits).
fn uniform(rng: &mut Pcg32) -> f64 {
    let hi = u64::from(rng.next_u32());
    let lo = u64::from(rng.next_u32());
    ((hi << 21) | (lo >> 11)) as f64 * (1.0 / 9_007_199_254_740_992.0)
}

/// Per-axis strata for `n = 2^m` points over `k` axes, as equal as possible.
fn strata(n: usize, k: usize) -> Vec<usize> {
    assert!(n.is_power_of_two());
    let m = n.trailing_zeros() as usize;
    (0..k)
        .map(|a| 1 << (m / k + usize::from(a < m % k)))
        .collect()
}

/// Jittered samples: one uniform point in each cell of the grid `strata`
/// (unused axes 0).
fn jittered(rng: &mut Pcg32, strata: &[usize], out: &mut Vec<[f64; 3]>) {
    out.clear();
    let n: usize = strata.iter().product();
    for i in 0..n {
        let mut idx = i;
        let mut p = [0.0; 3];
        for (a, &m) in strata.iter().enumerate() {
            p[a] = ((idx % m) as f64 + uniform(rng)) / m as f64;
            idx /= m;
        }
        out.push(p);
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Estimator {
    Beams,
    Points,
}

impl Estimator {
    fn name(self) -> &'static str {
        match self {
            Estimator::Beams => "beams",
            Estimator::Points => "points",
        }
    }
    /// Sample dimension: the emission angles (`D − 1`), plus the free
    /// flight for points.
    fn axes<const D: usize>(self) -> usize {
        match self {
            Estimator::Beams => D - 1,
            Estimator::Points => D,
        }
    }
}

/// The score of one primary sample `p` (`u₀[, u₁][, s]`).
#[inline]
fn score<const D: usize>(sc: &Caustic<D>, est: Estimator, p: &[f64; 3]) -> f64 {
    let u = [p[0], if D == 3 { p[1] } else { 0.0 }];
    match est {
        Estimator::Beams => sc.beam_sample(u),
        Estimator::Points => sc.point_sample(u, p[D - 1]),
    }
}

/// One jittered estimate of `Φ_Q` with `n` samples.
fn estimate<const D: usize>(
    sc: &Caustic<D>,
    est: Estimator,
    n: usize,
    rng: &mut Pcg32,
    buf: &mut Vec<[f64; 3]>,
) -> f64 {
    jittered(rng, &strata(n, est.axes::<D>()), buf);
    buf.iter().map(|p| score(sc, est, p)).sum::<f64>() / n as f64
}

/// The smallest `N = 16·2ᵏ` whose RMSE over [`REALISATIONS`] independent
/// realisations is at most 1 % of `reference`, and that RMSE (relative).
/// A smaller `N` is abandoned as soon as its partial sum of squared errors
/// exceeds the whole budget (`REALISATIONS·(0.01·reference)²`): the sum only
/// grows, so the decision is the one the full 256 would give.
fn n_to_1pct<const D: usize>(sc: &Caustic<D>, est: Estimator, reference: f64) -> (usize, f64) {
    let mut rng = Pcg32::new(
        0x1c_0ffe,
        2 * D as u64 + u64::from(est == Estimator::Points),
    );
    let mut buf = Vec::new();
    let budget = REALISATIONS as f64 * (0.01 * reference).powi(2);
    let mut n = 16;
    loop {
        let mut se = 0.0;
        for _ in 0..REALISATIONS {
            se += (estimate(sc, est, n, &mut rng, &mut buf) - reference).powi(2);
            if se > budget && n < 1 << 22 {
                break;
            }
        }
        if se <= budget || n >= 1 << 22 {
            return (n, (se / REALISATIONS as f64).sqrt() / reference);
        }
        n *= 2;
    }
}

fn dims<const D: usize>(g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>) {
    let sc = scene::<D>();
    let t = Instant::now();
    let mut rng = Pcg32::new(2011, D as u64);
    let mut buf = Vec::new();
    let reference = estimate(&sc, Estimator::Beams, REFERENCE_BEAMS, &mut rng, &mut buf);
    eprintln!(
        "caustic {D}d: reference Φ_Q = {reference:.6e} per unit emitted power \
         (2^20 jittered beams, {:.1} s)",
        t.elapsed().as_secs_f64()
    );
    let mut to_1pct = Vec::new();
    for est in [Estimator::Beams, Estimator::Points] {
        let t = Instant::now();
        let (n, rel) = n_to_1pct(&sc, est, reference);
        eprintln!(
            "caustic {D}d {}: N to 1 % relative RMSE = {n} (strata {:?}, RMSE {:.3} % over \
             {REALISATIONS} realisations; search {:.1} s)",
            est.name(),
            strata(n, est.axes::<D>()),
            100.0 * rel,
            t.elapsed().as_secs_f64()
        );
        to_1pct.push((est, n));
    }

    // Throughput: fixed jittered batches.
    g.sampling_mode(SamplingMode::Auto);
    g.throughput(Throughput::Elements(BATCH as u64));
    for est in [Estimator::Beams, Estimator::Points] {
        let mut samples = Vec::new();
        let cells = match (D, est) {
            (2, Estimator::Beams) => vec![BATCH],
            (3, Estimator::Beams) | (2, Estimator::Points) => vec![64, 64],
            _ => vec![16, 16, 16],
        };
        jittered(&mut rng, &cells, &mut samples);
        g.bench_function(format!("{D}d/{}", est.name()), |b| {
            b.iter(|| {
                samples
                    .iter()
                    .map(|p| score(&sc, est, black_box(p)))
                    .sum::<f64>()
            })
        });
    }
    // One whole estimate at the N that reaches 1 %.
    g.sampling_mode(SamplingMode::Flat);
    for (est, n) in to_1pct {
        g.throughput(Throughput::Elements(n as u64));
        let mut rng = Pcg32::new(7, 3);
        g.bench_function(format!("{D}d/{}-to-1pct", est.name()), |b| {
            b.iter(|| estimate(&sc, est, black_box(n), &mut rng, &mut buf))
        });
    }
}

fn caustic(c: &mut Criterion) {
    let mut g = c.benchmark_group("caustic");
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(2));
    g.sample_size(10);
    dims::<2>(&mut g);
    dims::<3>(&mut g);
    g.finish();
}

criterion_group!(benches, caustic);
criterion_main!(benches);
