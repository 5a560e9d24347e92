//! Spectral variance prediction against measured estimator variance.
//!
//! Predicted: `Var = (1/N) Σ_{ν≠0} ⟨N·P(ν)⟩·p_f(ν)` (Pilleboue et al. 2015;
//! Singh et al. 2017 §3) from the mean periodogram of independent pattern
//! realisations and the closed-form Fourier coefficients of the integrand:
//! points `p_f = |f̂|²`; segments the segment periodogram (sinc weights) times
//! `|f̂|²` (equivalently the pre-filtered `|f̂|²·sinc²(λν·ω)`); axis lines the
//! `(D−1)`-dim periodogram of the offsets times the slice `|f̂(ν_⊥, 0)|²`.
//! For points the part of `Σ p_f` outside the grid is added as white noise
//! (`⟨N·P⟩ = 1`), its size known exactly by Parseval: `Σ_{ν≠0}|f̂|² = ∫f² −
//! (∫f)²`.
//!
//! The prediction under test is the kernel's `Periodogram::predict_variance`
//! (with `Prediction::with_white_tail` for points); this file also sums the
//! per-realisation predictions itself and requires the two to agree to 1e-12.
//!
//! Measured: the sample variance of `M` homogenised estimates from the kernel's
//! estimators, with its standard error from the fourth moment. The prediction's
//! standard error is the kernel's (`PredictionStats`, fed the same
//! realisations), required to agree with the standard error of this file's
//! own per-realisation predictions to 1e-12. With the combined
//! `SE = √(SE_pred² + SE_meas²)` and `z = (pred − meas)/SE`, a case passes when
//!
//! * `|z| ≤ z_crit`, where `z_crit` is Bonferroni-corrected over all cases of
//!   the run: `z_crit = Φ⁻¹(1 − α/(2m))` with suite-wide `α = 1e-3` over the
//!   `m = 29` release cases (`z_crit ≈ 4.14`), and `z_crit = 5` for the two
//!   quick cases of the default suite (tests/README.md: α = 5.7e-7 per check);
//! * and `|pred/meas − 1| ≤ 5 %` in the cases whose resolution allows that
//!   claim, `z_crit·SE/meas ≤ 5 %` ("5 % resolved"); elsewhere only the `z`
//!   bound is claimed, and the table prints the resolution `z_crit·SE/meas`,
//!   the smallest relative error the case detects for sure.
//!
//! The false-alarm probability of a release run is at most `α = 1e-3` (union
//! bound over the 29 z-checks; the 5 % checks add nothing, since in a resolved
//! case `|z| ≤ z_crit` already implies `|pred − meas| ≤ 5 %·meas`).
//!
//! The full tables (release; three tests that run in parallel):
//! `cargo test --release --test spectral_variance -- --ignored --nocapture`.

use linesample::estimator::{
    run_realisations, Directions, Estimator, LineEstimator, PointEstimator, SegmentEstimator,
};
use linesample::geom::Direction;
use linesample::integrand::{Ball, Gaussian, Integrand};
use linesample::pattern::{
    Ccvt, Jittered, Pattern, PoissonDisk, PoissonDiskN, PoissonMethod, Random,
};
use linesample::primitive::Segment;
use linesample::spectrum::{AmplitudeView, Dft, Grid, Periodogram, PredictionStats};
use linesample::stats::normal_upper_quantile;
use linesample::stats::RunningStats;
use linesample::{Pcg32, Seed};

#[derive(Clone, Copy)]
enum Prim<const D: usize> {
    Points,
    /// Fixed direction and length.
    Segments(Direction<D>, f64),
    /// Uniformly random direction per segment, fixed length.
    RandomSegments(f64),
}

struct Row {
    name: String,
    predicted: f64,
    se_pred: f64,
    measured: f64,
    se_meas: f64,
}

impl Row {
    fn rel(&self) -> f64 {
        self.predicted / self.measured - 1.0
    }
    fn z(&self) -> f64 {
        (self.predicted - self.measured) / self.se_pred.hypot(self.se_meas)
    }
    /// `z_crit·SE/meas`: the smallest relative error this case detects for sure.
    fn resolution(&self, z_crit: f64) -> f64 {
        z_crit * self.se_pred.hypot(self.se_meas) / self.measured
    }
    /// Whether the case resolves the 5 % claim.
    fn resolves_5pc(&self, z_crit: f64) -> bool {
        self.resolution(z_crit) <= 0.05
    }
    fn ok(&self, z_crit: f64) -> bool {
        self.z().abs() <= z_crit && (!self.resolves_5pc(z_crit) || self.rel().abs() <= 0.05)
    }
}

/// Suite-wide false-alarm probability of the release tables.
const SUITE_ALPHA: f64 = 1e-3;
/// Cases in the three release tables together (8 + 9 + 12; each table checks
/// its own count, so adding a case forces this and `z_crit` to follow).
const RELEASE_CASES: usize = 29;
/// `|z|` limit of the quick default-suite cases (tests/README.md).
const QUICK_Z: f64 = 5.0;

/// The Bonferroni `z_crit` of the release tables.
fn release_z_crit() -> f64 {
    normal_upper_quantile(SUITE_ALPHA / (2.0 * RELEASE_CASES as f64))
}

fn scratch(len: usize) -> Vec<f32> {
    vec![0.0; len]
}

/// Per-realisation predictions `V_r = Σ_{ν≠0} w(ν)·|F_r(ν)|²/N² ` over
/// `reals` realisations, where `w` already includes the grid multiplicity,
/// summed here; the mean periodogram; and the kernel's standard error of the
/// prediction from the same realisations.
fn predict<const D: usize>(
    g: Grid<D>,
    weights: &[f64],
    tail: f64,
    reals: u64,
    mut fill: impl FnMut(u64, &mut Dft<D, Vec<f64>>),
) -> (RunningStats, Periodogram<D, Vec<f64>>, f64) {
    let mut dft = Dft::new_vec(g);
    let mut per = Periodogram::new_vec(g);
    let mut acc = PredictionStats::new(g, weights).unwrap();
    let mut power = vec![0.0; g.len()];
    let mut st = RunningStats::default();
    let mut n = 0;
    for r in 0..reals {
        dft.clear();
        fill(r, &mut dft);
        per.add(&dft).unwrap();
        acc.add(&dft).unwrap();
        dft.power(&mut power).unwrap();
        n = dft.count();
        let v: f64 = power.iter().zip(weights).map(|(p, w)| p * w).sum::<f64>() / n as f64;
        st.push(v + tail / n as f64);
    }
    let se = acc.prediction(n).unwrap().std_error.unwrap();
    (st, per, se)
}

/// The kernel's prediction from the mean periodogram and its standard error,
/// checked against this file's own per-realisation sums (the mean of the
/// `V_r` and its standard error), and the row.
fn row(name: &str, api: f64, api_se: f64, own: &RunningStats, meas: &RunningStats) -> Row {
    // Both are the same sum over the same realisations in a different order
    // (mean of sums vs sum of means, plain vs compensated): rounding only.
    assert!(
        (api / own.mean() - 1.0).abs() <= 1e-12,
        "{name}: predict_variance {api:e} vs the direct sum {:e}",
        own.mean()
    );
    // Exact power sums against Welford's update: rounding only.
    assert!(
        (api_se / own.mean_std_error() - 1.0).abs() <= 1e-12,
        "{name}: PredictionStats SE {api_se:e} vs the direct {:e}",
        own.mean_std_error()
    );
    Row {
        name: name.to_string(),
        predicted: api,
        se_pred: api_se,
        measured: meas.variance(),
        se_meas: meas.variance_std_error(),
    }
}

/// `w(ν) = multiplicity·p_f(ν)` on the half grid, 0 at DC, and `Σ w`.
fn weights<const D: usize>(g: Grid<D>, mut pf: impl FnMut([i32; D]) -> f64) -> (Vec<f64>, f64) {
    let mut w = vec![0.0; g.len()];
    let mut sum = 0.0;
    for (i, x) in w.iter_mut().enumerate() {
        let j = g.freq(i);
        if j.iter().any(|&a| a != 0) {
            *x = f64::from(g.multiplicity(i)) * pf(j);
            sum += *x;
        }
    }
    (w, sum)
}

const PTS_SCRATCH: usize = 64;

#[allow(clippy::too_many_arguments)]
fn case<const D: usize>(
    name: &str,
    pattern: &dyn Pattern<D>,
    f: &dyn Integrand<D>,
    prim: Prim<D>,
    k: usize,
    parseval_total: Option<f64>,
    meas: u64,
    reals: u64,
) -> Row {
    let g = Grid::<D>::new(k).unwrap();
    let (w, in_grid) = weights(g, |j| f.fourier(&j).norm_sqr());
    let tail = parseval_total.map_or(0.0, |t| (t - in_grid).max(0.0));
    let n = pattern.len();
    let mut pts = vec![[0.0f32; D]; n];
    let per_p = Dft::<D, Vec<f64>>::points_scratch_per_sample(g);
    let per_s = Dft::<D, Vec<f64>>::segments_scratch_per_sample(g);
    let mut sc = vec![0.0; PTS_SCRATCH * per_p.max(per_s)];
    let pseed = Seed::new(0x5EC7);
    let mut rng = Pcg32::new(77, 3);
    let (pred, per, se) = predict(g, &w, tail, reals, |r, dft| {
        pattern.fill(pseed.realization(r), &mut pts).unwrap();
        match prim {
            Prim::Points => dft.add_points(&pts, &mut sc).unwrap(),
            Prim::Segments(dir, len) => dft.add_segment_pattern(&pts, &dir, len, &mut sc).unwrap(),
            Prim::RandomSegments(len) => {
                let segs: Vec<Segment<D>> = pts
                    .iter()
                    .map(|p| {
                        let dir = random_direction::<D>(&mut rng);
                        Segment::new(p.map(f64::from), dir, len).unwrap()
                    })
                    .collect();
                dft.add_segments(&segs, &mut sc).unwrap();
            }
        }
    });
    let est: Box<dyn Estimator<D>> = match prim {
        Prim::Points => Box::new(PointEstimator::new(pattern).unwrap()),
        Prim::Segments(dir, len) => {
            Box::new(SegmentEstimator::new(pattern, len, Directions::Fixed(dir)).unwrap())
        }
        Prim::RandomSegments(len) => {
            Box::new(SegmentEstimator::new(pattern, len, Directions::Random).unwrap())
        }
    };
    let mut s = scratch(est.scratch_len());
    let m = run_realisations(est.as_ref(), f, Seed::new(0xE57), 0, meas, true, &mut s).unwrap();
    let p = per.predict_variance(n as u64, |j| f.fourier(&j).norm_sqr());
    let api = parseval_total.map_or(p.grid, |t| p.with_white_tail(t));
    row(name, api, se, &pred, &m)
}

/// Axis lines in `D` dims with `K = D − 1`-dim offsets.
#[allow(clippy::too_many_arguments)]
fn line_case<const D: usize, const K: usize>(
    name: &str,
    offsets: &dyn Pattern<K>,
    f: &dyn Integrand<D>,
    axis: usize,
    k: usize,
    meas: u64,
    reals: u64,
) -> Row {
    let g = Grid::<K>::new(k).unwrap();
    let embed = |j: [i32; K]| {
        let mut full = [0i32; D];
        let mut b = 0;
        for (a, x) in full.iter_mut().enumerate() {
            if a != axis {
                *x = j[b];
                b += 1;
            }
        }
        full
    };
    let (w, _) = weights(g, |j| f.fourier(&embed(j)).norm_sqr());
    let n = offsets.len();
    let mut pts = vec![[0.0f32; K]; n];
    let mut sc = vec![0.0; PTS_SCRATCH * Dft::<K, Vec<f64>>::points_scratch_per_sample(g)];
    let pseed = Seed::new(0x11E5);
    let (pred, per, se) = predict(g, &w, 0.0, reals, |r, dft| {
        offsets.fill(pseed.realization(r), &mut pts).unwrap();
        dft.add_points(&pts, &mut sc).unwrap();
    });
    let est =
        LineEstimator::<D, K>::new(offsets, Directions::Fixed(Direction::axis(axis).unwrap()))
            .unwrap();
    let mut s = scratch(est.scratch_len());
    let m = run_realisations(&est, f, Seed::new(0xE58), 0, meas, true, &mut s).unwrap();
    let api = per
        .predict_variance(n as u64, |j| f.fourier(&embed(j)).norm_sqr())
        .grid;
    row(name, api, se, &pred, &m)
}

fn random_direction<const D: usize>(rng: &mut Pcg32) -> Direction<D> {
    let u = |rng: &mut Pcg32| f64::from(rng.next_u32()) / 4294967296.0;
    let mut v = [0.0; D];
    if D == 2 {
        let t = core::f64::consts::TAU * u(rng);
        v[0] = t.cos();
        v[1] = t.sin();
    } else {
        let z = 2.0 * u(rng) - 1.0;
        let t = core::f64::consts::TAU * u(rng);
        let s = (1.0 - z * z).sqrt();
        v[0] = s * t.cos();
        v[1] = s * t.sin();
        v[2] = z;
    }
    Direction::new(v).unwrap()
}

fn report(rows: &[Row], z_crit: f64, rule: &str) {
    println!("rule: {rule}");
    println!(
        "pass iff |z| ≤ {z_crit:.3}, and |pred/meas − 1| ≤ 5 % where {z_crit:.3}·SE/meas ≤ 5 % (\"5 % resolved\")"
    );
    println!("| case | predicted Var | ± SE | measured Var | ± SE | pred/meas − 1 | z | resolution | 5 % resolved |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        println!(
            "| {} | {:.4e} | {:.1e} | {:.4e} | {:.1e} | {:+.2} % | {:+.2} | {:.1} % | {} |{}",
            r.name,
            r.predicted,
            r.se_pred,
            r.measured,
            r.se_meas,
            100.0 * r.rel(),
            r.z(),
            100.0 * r.resolution(z_crit),
            if r.resolves_5pc(z_crit) { "yes" } else { "no" },
            if r.ok(z_crit) { "" } else { " FAIL" }
        );
    }
    let bad: Vec<&str> = rows
        .iter()
        .filter(|r| !r.ok(z_crit))
        .map(|r| r.name.as_str())
        .collect();
    assert!(
        bad.is_empty(),
        "prediction and measurement disagree: {bad:?}"
    );
}

fn report_release(rows: &[Row], expected_cases: usize) {
    assert_eq!(rows.len(), expected_cases, "update RELEASE_CASES");
    let z = release_z_crit();
    report(
        rows,
        z,
        &format!(
            "Bonferroni over the {RELEASE_CASES} release cases at suite α = {SUITE_ALPHA:e}: z_crit = Φ⁻¹(1 − α/(2·{RELEASE_CASES})) = {z:.3}"
        ),
    );
}

/// A quick debug-build check on two cases (the full table is the ignored test).
#[test]
fn prediction_matches_measurement_quick() {
    let disk = Ball::<2>::new([0.41, 0.53], 0.27).unwrap();
    let rows = vec![
        case(
            "2D disk, random points",
            &Random::<2>::new(64).unwrap(),
            &disk,
            Prim::Points,
            24,
            Some(disk.integral() - disk.integral().powi(2)),
            4000,
            1500,
        ),
        case(
            "2D disk, jittered points",
            &Jittered::new([8, 8]).unwrap(),
            &disk,
            Prim::Points,
            24,
            Some(disk.integral() - disk.integral().powi(2)),
            4000,
            1500,
        ),
    ];
    report(
        &rows,
        QUICK_Z,
        "default suite: |z| ≤ 5 per case (α = 5.7e-7 each, tests/README.md)",
    );
}

const IGNORE: &str =
    "release: cargo test --release --test spectral_variance -- --ignored --nocapture";

fn disk() -> Ball<2> {
    Ball::<2>::new([0.41, 0.53], 0.27).unwrap()
}
fn gauss2() -> Gaussian<2> {
    Gaussian::<2>::new([0.37, 0.61], 0.06).unwrap()
}
fn ball() -> Ball<3> {
    Ball::<3>::new([0.45, 0.52, 0.58], 0.3).unwrap()
}
fn gauss3() -> Gaussian<3> {
    Gaussian::<3>::new([0.4, 0.55, 0.6], 0.07).unwrap()
}
fn parseval<const D: usize>(f: &dyn Integrand<D>) -> Option<f64> {
    // An indicator: ∫f² = ∫f.
    Some(f.integral() - f.integral().powi(2))
}

const N2: usize = 256;
const K2: usize = 64;
const K3: usize = 16;
/// Measured realisations and periodogram realisations for the cheap patterns.
const M: u64 = 10_000;
const R: u64 = 1500;

fn timed(rows: &mut Vec<Row>, f: impl FnOnce() -> Row) {
    let t = std::time::Instant::now();
    let r = f();
    eprintln!("{}: {:.1?}", r.name, t.elapsed());
    rows.push(r);
}

#[test]
#[ignore = "release (see IGNORE)"]
fn table_2d_points() {
    let _ = IGNORE;
    let (disk, g2) = (disk(), gauss2());
    let random2 = Random::<2>::new(N2).unwrap();
    let jit2 = Jittered::new([16, 16]).unwrap();
    let pd2 = PoissonDiskN::new(
        PoissonDisk::<2>::for_n(N2, 0.75)
            .unwrap()
            .with_method(PoissonMethod::MaximalDartThrowing),
        N2,
    )
    .unwrap();
    let ccvt2 = Ccvt::<2>::new(N2).unwrap();
    let mut rows = Vec::new();
    for (pname, p, meas, reals) in [
        ("random", &random2 as &dyn Pattern<2>, M, R),
        ("jittered", &jit2, M, R),
        ("Poisson disk", &pd2, 4000, 400),
        ("CCVT", &ccvt2, 1500, 150),
    ] {
        timed(&mut rows, || {
            case(
                &format!("2D disk, {pname} points"),
                p,
                &disk,
                Prim::Points,
                K2,
                parseval(&disk),
                meas,
                reals,
            )
        });
        timed(&mut rows, || {
            case(
                &format!("2D Gaussian, {pname} points"),
                p,
                &g2,
                Prim::Points,
                K2,
                None,
                meas,
                reals,
            )
        });
    }
    report_release(&rows, 8);
}

#[test]
#[ignore = "release (see IGNORE)"]
fn table_2d_segments_and_lines() {
    let (disk, g2) = (disk(), gauss2());
    let random2 = Random::<2>::new(N2).unwrap();
    let jit2 = Jittered::new([16, 16]).unwrap();
    let random1 = Random::<1>::new(N2).unwrap();
    let jit1 = Jittered::new([N2]).unwrap();
    let oblique2 = Direction::new([1.0, 0.45]).unwrap();
    let mut rows = Vec::new();
    for (pname, p) in [("random", &random2 as &dyn Pattern<2>), ("jittered", &jit2)] {
        timed(&mut rows, || {
            case(
                &format!("2D disk, {pname} segments λ=0.1 fixed dir"),
                p,
                &disk,
                Prim::Segments(oblique2, 0.1),
                K2,
                None,
                M,
                R,
            )
        });
        timed(&mut rows, || {
            case(
                &format!("2D Gaussian, {pname} segments λ=0.1 fixed dir"),
                p,
                &g2,
                Prim::Segments(oblique2, 0.1),
                K2,
                None,
                M,
                R,
            )
        });
    }
    timed(&mut rows, || {
        case(
            "2D disk, jittered segments λ=0.05 random dir",
            &jit2,
            &disk,
            Prim::RandomSegments(0.05),
            K2,
            None,
            M,
            R,
        )
    });
    for (pname, p) in [("random", &random1 as &dyn Pattern<1>), ("jittered", &jit1)] {
        timed(&mut rows, || {
            line_case::<2, 1>(
                &format!("2D disk, {pname} x-lines"),
                p,
                &disk,
                0,
                2048,
                M,
                R,
            )
        });
        timed(&mut rows, || {
            line_case::<2, 1>(
                &format!("2D Gaussian, {pname} y-lines"),
                p,
                &g2,
                1,
                2048,
                M,
                R,
            )
        });
    }
    report_release(&rows, 9);
}

#[test]
#[ignore = "release (see IGNORE)"]
fn table_3d() {
    let (ball, g3) = (ball(), gauss3());
    let random3 = Random::<3>::new(512).unwrap();
    let jit3 = Jittered::new([8, 8, 8]).unwrap();
    let pd3 = PoissonDiskN::new(
        PoissonDisk::<3>::for_n(512, 0.75)
            .unwrap()
            .with_method(PoissonMethod::MaximalDartThrowing),
        512,
    )
    .unwrap();
    let random2 = Random::<2>::new(N2).unwrap();
    let jit2 = Jittered::new([16, 16]).unwrap();
    let oblique3 = Direction::new([0.3, 1.0, -0.6]).unwrap();
    let r3 = 600;
    let mut rows = Vec::new();
    for (pname, p, meas, reals) in [
        ("random", &random3 as &dyn Pattern<3>, M, r3),
        ("jittered", &jit3, M, r3),
        ("Poisson disk", &pd3, 2000, 200),
    ] {
        timed(&mut rows, || {
            case(
                &format!("3D ball, {pname} points"),
                p,
                &ball,
                Prim::Points,
                K3,
                parseval(&ball),
                meas,
                reals,
            )
        });
        timed(&mut rows, || {
            case(
                &format!("3D Gaussian, {pname} points"),
                p,
                &g3,
                Prim::Points,
                K3,
                None,
                meas,
                reals,
            )
        });
    }
    timed(&mut rows, || {
        case(
            "3D ball, jittered segments λ=0.2 fixed dir",
            &jit3,
            &ball,
            Prim::Segments(oblique3, 0.2),
            K3,
            None,
            M,
            r3,
        )
    });
    timed(&mut rows, || {
        case(
            "3D Gaussian, random segments λ=0.2 fixed dir",
            &random3,
            &g3,
            Prim::Segments(oblique3, 0.2),
            K3,
            None,
            M,
            r3,
        )
    });
    for (pname, p) in [("random", &random2 as &dyn Pattern<2>), ("jittered", &jit2)] {
        timed(&mut rows, || {
            line_case::<3, 2>(&format!("3D ball, {pname} z-lines"), p, &ball, 2, 48, M, r3)
        });
        timed(&mut rows, || {
            line_case::<3, 2>(
                &format!("3D Gaussian, {pname} x-lines"),
                p,
                &g3,
                0,
                48,
                M,
                r3,
            )
        });
    }
    report_release(&rows, 12);
}

/// The radial form `(1/N) Σ_r count_r P̆_S(r) P̆_f(r)` against the lattice sum
/// `(1/N) Σ_ν ⟨N·P⟩ |f̂|²` from the same periodogram: equal when the sampling
/// spectrum is constant on rings, close for isotropic blue noise.
#[test]
fn radial_form_matches_the_lattice_sum() {
    use linesample::spectrum::radial_variance;
    let disk = Ball::<2>::new([0.41, 0.53], 0.27).unwrap();
    let k = 24;
    let g = Grid::<2>::new(k).unwrap();
    let pf = |j: [i32; 2]| disk.fourier(&j).norm_sqr();
    let (mut f_mean, mut count) = (vec![0.0; k + 1], vec![0u64; k + 1]);
    g.radial_mean_of(pf, &mut f_mean, &mut count).unwrap();
    // Ring-constant sampling spectrum: identical up to rounding.
    let s_ring: Vec<f64> = (0..=k).map(|r| 1.0 - (-(r as f64) / 5.0).exp()).collect();
    let lattice: f64 = (0..g.len())
        .filter(|&i| g.freq(i) != [0, 0])
        .filter_map(|i| {
            g.ring(i)
                .map(|r| f64::from(g.multiplicity(i)) * s_ring[r] * pf(g.freq(i)))
        })
        .sum::<f64>()
        / 64.0;
    let radial = radial_variance(64, &s_ring, &f_mean, &count).unwrap();
    assert!(
        (radial / lattice - 1.0).abs() < 1e-13,
        "{radial} vs {lattice}"
    );
    // Poisson-disk points (isotropic): the within-ring covariance is small.
    let pd = PoissonDiskN::new(
        PoissonDisk::<2>::for_n(64, 0.65)
            .unwrap()
            .with_method(PoissonMethod::MaximalDartThrowing),
        64,
    )
    .unwrap();
    let mut per = Periodogram::new_vec(g);
    let mut dft = Dft::new_vec(g);
    let mut sc = vec![0.0; 64 * Dft::<2, Vec<f64>>::points_scratch_per_sample(g)];
    let mut pts = vec![[0.0f32; 2]; 64];
    for r in 0..200 {
        pd.fill(Seed::new(4).realization(r), &mut pts).unwrap();
        dft.clear();
        dft.add_points(&pts, &mut sc).unwrap();
        per.add(&dft).unwrap();
    }
    let mut s_mean = vec![0.0; k + 1];
    per.radial_average(&mut s_mean, &mut count).unwrap();
    let radial = radial_variance(64, &s_mean, &f_mean, &count).unwrap();
    // Rings are complete only up to k: compare with the lattice sum over the
    // same frequencies (|ν| rounding to ≤ k).
    let lattice: f64 = (0..g.len())
        .filter(|&i| g.freq(i) != [0, 0] && g.ring(i).is_some())
        .map(|i| f64::from(g.multiplicity(i)) * per.mean_at(i) * pf(g.freq(i)))
        .sum::<f64>()
        / 64.0;
    println!("Poisson disk, disk integrand: radial form {radial:.5e}, lattice {lattice:.5e}");
    // A judgement, not a statistical bound: the two sums differ by the
    // within-ring covariance of the two spectra, which is not zero for a finite
    // set of realisations (and for the disk's anisotropic |f̂|² off-centre);
    // 3 % is the size the radial form is documented to be usable at.
    assert!(
        (radial / lattice - 1.0).abs() < 0.03,
        "{radial} vs {lattice}"
    );
}
