//! Estimators: unbiasedness of every estimator with random and jittered patterns
//! (fixed seeds, 4 standard errors), and the convergence rates of the paper
//! (`paper-notes.md` §4.2), tested as weighted log-log slopes with their standard
//! errors (release-mode tests, `--ignored`, run by CI).

use linesample::estimator::{
    run_realisations, Directions, Estimator, LineEstimator, PointEstimator, SegmentEstimator,
};
use linesample::geom::Direction;
use linesample::integrand::{Ball, Gaussian, HalfSpace, Integrand};
use linesample::pattern::{Jittered, Pattern, Random};
use linesample::stats::RunningStats;
use linesample::Seed;

fn stats<const D: usize>(
    est: &dyn Estimator<D>,
    f: &dyn Integrand<D>,
    seed: u64,
    reps: u64,
) -> RunningStats {
    let mut scratch = vec![0.0f32; est.scratch_len()];
    run_realisations(est, f, Seed::new(seed), 0, reps, true, &mut scratch).unwrap()
}

/// Asserts `|mean − I| ≤ 4·SE` and returns the z-score.
fn assert_unbiased<const D: usize>(
    name: &str,
    est: &dyn Estimator<D>,
    f: &dyn Integrand<D>,
    seed: u64,
    reps: u64,
) -> f64 {
    let st = stats(est, f, seed, reps);
    let exact = f.integral();
    let se = st.mean_std_error();
    let z = (st.mean() - exact) / se;
    println!(
        "{name:<44} N = {:>4}: mean {:.6e}, exact {:.6e}, SE {:.2e}, z = {z:+.2}",
        est.count(),
        st.mean(),
        exact,
        se
    );
    assert!(se > 0.0 && se.is_finite(), "{name}: SE = {se}");
    assert!(z.abs() <= 4.0, "{name}: biased? z = {z}");
    z
}

fn dir<const D: usize>(v: [f64; D]) -> Direction<D> {
    Direction::new(v).unwrap()
}

/// The estimator configurations of the unbiasedness suite in `D` dimensions.
struct Suite<'a, const D: usize> {
    /// (length, direction) of the fixed-direction segments.
    fixed_segment: (f64, Direction<D>),
    /// Length of the random-direction segments.
    random_segment: f64,
    /// Direction groups (segments of length 0.2, and lines).
    groups: &'a [Direction<D>],
    /// (label, direction) of the axis lines and of the oblique box lines.
    axis_line: (&'a str, Direction<D>),
    oblique_line: (&'a str, Direction<D>),
    reps: u64,
}

/// Every estimator × every pattern × every integrand is unbiased (4 SE).
/// `pats` are `D`-dimensional (points, segment centres), `offsets` are
/// `K = D − 1`-dimensional (line offsets).
fn unbiased_suite<const D: usize, const K: usize>(
    fs: &[(&str, &dyn Integrand<D>)],
    pats: &[(&str, &dyn Pattern<D>)],
    offsets: &[(&str, &dyn Pattern<K>)],
    suite: &Suite<'_, D>,
    mut seed: u64,
) {
    let reps = suite.reps;
    for &(fname, f) in fs {
        for &(pname, p) in pats {
            seed += 1;
            let (len, w) = suite.fixed_segment;
            let cases: [(String, Box<dyn Estimator<D>>); 4] = [
                (
                    "points".to_string(),
                    Box::new(PointEstimator::new(p).unwrap()),
                ),
                (
                    format!("segments λ={len} fixed"),
                    Box::new(SegmentEstimator::new(p, len, Directions::Fixed(w)).unwrap()),
                ),
                (
                    format!("segments λ={} random dir", suite.random_segment),
                    Box::new(
                        SegmentEstimator::new(p, suite.random_segment, Directions::Random).unwrap(),
                    ),
                ),
                (
                    format!("segments {} groups", suite.groups.len()),
                    Box::new(
                        SegmentEstimator::new(p, 0.2, Directions::Groups(suite.groups)).unwrap(),
                    ),
                ),
            ];
            for (what, e) in &cases {
                assert_unbiased(
                    &format!("{fname} {what} {pname}"),
                    e.as_ref(),
                    f,
                    seed,
                    reps,
                );
            }
        }
        for &(pname, p) in offsets {
            seed += 1;
            let cases: [(String, Box<dyn Estimator<D>>); 4] = [
                (
                    format!("lines {}", suite.axis_line.0),
                    Box::new(LineEstimator::new(p, Directions::Fixed(suite.axis_line.1)).unwrap()),
                ),
                (
                    format!("lines {} (box)", suite.oblique_line.0),
                    Box::new(
                        LineEstimator::new(p, Directions::Fixed(suite.oblique_line.1)).unwrap(),
                    ),
                ),
                (
                    "lines random dir".to_string(),
                    Box::new(LineEstimator::new(p, Directions::Random).unwrap()),
                ),
                (
                    format!("lines {} groups", suite.groups.len()),
                    Box::new(LineEstimator::new(p, Directions::Groups(suite.groups)).unwrap()),
                ),
            ];
            for (what, e) in &cases {
                assert_unbiased(
                    &format!("{fname} {what} {pname}"),
                    e.as_ref(),
                    f,
                    seed,
                    reps,
                );
            }
        }
    }
}

#[test]
fn every_estimator_is_unbiased_2d() {
    let disk = Ball::<2>::new([0.5, 0.5], 0.25).unwrap();
    let gauss = Gaussian::<2>::new([0.3, 0.8], 0.1).unwrap();
    let edge = HalfSpace::<2>::new(dir([0.7, 1.0]), 0.6).unwrap();
    let random2 = Random::<2>::new(64).unwrap();
    let jitter2 = Jittered::new([8, 8]).unwrap();
    let random1 = Random::<1>::new(16).unwrap();
    let jitter1 = Jittered::new([16]).unwrap();
    let groups = [dir([1.0, 0.0]), dir([0.0, 1.0]), dir([1.0, 1.0])];
    let suite = Suite {
        fixed_segment: (0.3, dir([0.6, 0.8])),
        random_segment: 1.7,
        groups: &groups,
        axis_line: ("∥x", Direction::axis(0).unwrap()),
        oblique_line: ("slope 0.7", dir([1.0, 0.7])),
        reps: 400,
    };
    unbiased_suite(
        &[("disk", &disk), ("gauss", &gauss), ("edge", &edge)],
        &[("random", &random2), ("jittered", &jitter2)],
        &[("random", &random1), ("jittered", &jitter1)],
        &suite,
        100,
    );
}

#[test]
fn every_estimator_is_unbiased_3d() {
    let ball = Ball::<3>::new([0.5, 0.5, 0.5], 0.25).unwrap();
    let gauss = Gaussian::<3>::new([0.1, 0.5, 0.9], 0.15).unwrap();
    let edge = HalfSpace::<3>::new(dir([0.3, -0.5, 1.0]), 0.2).unwrap();
    let random3 = Random::<3>::new(64).unwrap();
    let jitter3 = Jittered::new([4, 4, 4]).unwrap();
    let random2 = Random::<2>::new(16).unwrap();
    let jitter2 = Jittered::new([4, 4]).unwrap();
    let groups = [
        dir([0.0, 0.0, 1.0]),
        dir([1.0, 0.0, 0.0]),
        dir([1.0, 1.0, 1.0]),
    ];
    let suite = Suite {
        fixed_segment: (0.4, dir([0.2, 0.3, 0.9])),
        random_segment: 0.25,
        groups: &groups,
        axis_line: ("∥z", Direction::axis(2).unwrap()),
        oblique_line: ("oblique", dir([0.3, -0.4, 1.0])),
        reps: 300,
    };
    unbiased_suite(
        &[("ball", &ball), ("gauss", &gauss), ("edge", &edge)],
        &[("random", &random3), ("jittered", &jitter3)],
        &[("random", &random2), ("jittered", &jitter2)],
        &suite,
        200,
    );
}

#[test]
fn estimators_are_deterministic_and_check_arguments() {
    let disk = Ball::<2>::new([0.5, 0.5], 0.25).unwrap();
    let p = Jittered::new([4, 4]).unwrap();
    let e = SegmentEstimator::new(&p, 0.1, Directions::Random).unwrap();
    let mut s = vec![0.0f32; e.scratch_len()];
    let a = e.estimate(&disk, Seed::new(3), true, &mut s).unwrap();
    let b = e.estimate(&disk, Seed::new(3), true, &mut s).unwrap();
    assert_eq!(a.to_bits(), b.to_bits());
    let c = e.estimate(&disk, Seed::new(4), true, &mut s).unwrap();
    assert_ne!(a, c);
    // Parallel halves merged in order = one run (up to rounding).
    let all = run_realisations(&e, &disk, Seed::new(9), 0, 100, true, &mut s).unwrap();
    let mut h = run_realisations(&e, &disk, Seed::new(9), 0, 37, true, &mut s).unwrap();
    h.merge(&run_realisations(&e, &disk, Seed::new(9), 37, 63, true, &mut s).unwrap());
    assert_eq!(h.count(), 100);
    assert!((h.mean() - all.mean()).abs() <= 1e-15);
    assert!((h.variance() - all.variance()).abs() <= 1e-12 * all.variance());
    // Errors name the parameter.
    let mut short = vec![0.0f32; 3];
    let err = e
        .estimate(&disk, Seed::new(3), true, &mut short)
        .unwrap_err();
    assert!(err.to_string().contains("scratch"), "{err}");
    for bad in [f64::NAN, -1.0, f64::INFINITY, 2e6] {
        let err = SegmentEstimator::new(&p, bad, Directions::Random).unwrap_err();
        assert!(err.to_string().contains("length"), "{err}");
    }
    let err = SegmentEstimator::new(&p, 0.1, Directions::Groups(&[])).unwrap_err();
    assert!(err.to_string().contains("directions"), "{err}");
    let p3 = Jittered::new([2, 2, 2]).unwrap();
    assert!(LineEstimator::<2, 3>::new(&p3, Directions::Random).is_err());
}

// ---------------------------------------------------------------------------
// Convergence rates (release; `cargo test --release --test estimators -- --ignored`).

/// Weighted least-squares fit of `y = a + b·x`, weights `1/σ²`: returns
/// `(b, SE(b))`.
fn wls(x: &[f64], y: &[f64], sigma: &[f64]) -> (f64, f64) {
    let w: Vec<f64> = sigma.iter().map(|s| 1.0 / (s * s)).collect();
    let sw: f64 = w.iter().sum();
    let sx: f64 = w.iter().zip(x).map(|(w, x)| w * x).sum();
    let sy: f64 = w.iter().zip(y).map(|(w, y)| w * y).sum();
    let sxx: f64 = w.iter().zip(x).map(|(w, x)| w * x * x).sum();
    let sxy: f64 = w.iter().zip(x).zip(y).map(|((w, x), y)| w * x * y).sum();
    let det = sw * sxx - sx * sx;
    ((sw * sxy - sx * sy) / det, (sw / det).sqrt())
}

struct Curve {
    n: Vec<f64>,
    var: Vec<f64>,
    se: Vec<f64>,
}

fn curve<const D: usize>(
    f: &dyn Integrand<D>,
    ests: &[(usize, Box<dyn Estimator<D> + '_>)],
    seed: u64,
    reps: u64,
) -> Curve {
    let mut c = Curve {
        n: vec![],
        var: vec![],
        se: vec![],
    };
    for (n, e) in ests {
        let st = stats(e.as_ref(), f, seed + *n as u64, reps);
        c.n.push(*n as f64);
        c.var.push(st.variance());
        c.se.push(st.variance_std_error());
    }
    c
}

/// Fits `log(Var/(log N)^l)` against `log N` over the upper two thirds of the
/// `log N` range (the rates are asymptotic; `paper-notes.md` §5.1 fits the same
/// way): the slope estimates the rate.
fn slope(c: &Curve, label: &str, log_power: f64) -> (f64, f64) {
    let lo = c.n[0].ln();
    let hi = c.n[c.n.len() - 1].ln();
    let cut = lo + (hi - lo) / 3.0 - 1e-9;
    let keep: Vec<usize> = (0..c.n.len()).filter(|&i| c.n[i].ln() >= cut).collect();
    let x: Vec<f64> = keep.iter().map(|&i| c.n[i].ln()).collect();
    let y: Vec<f64> = keep
        .iter()
        .map(|&i| c.var[i].ln() - log_power * c.n[i].ln().ln())
        .collect();
    let s: Vec<f64> = keep.iter().map(|&i| c.se[i] / c.var[i]).collect();
    let (b, se) = wls(&x, &y, &s);
    println!("{label}");
    for i in 0..c.n.len() {
        println!(
            "  N = {:>5}  Var = {:.4e} ± {:.1e}",
            c.n[i], c.var[i], c.se[i]
        );
    }
    println!(
        "  slope of log(Var/(log N)^{log_power}) over N ≥ {} = {b:.3} ± {se:.3}",
        c.n[keep[0]]
    );
    (b, se)
}

fn check(label: &str, (b, se): (f64, f64), theory: f64) {
    let z = (b - theory) / se;
    println!("  {label}: {b:.3} ± {se:.3}, theory {theory:.3}, z = {z:+.2}");
    assert!(
        z.abs() <= 3.0,
        "{label}: slope {b} ± {se} vs theory {theory}"
    );
}

const REPS: u64 = 1000;

#[test]
#[ignore = "release-mode statistical test (CI runs it)"]
fn convergence_disk_2d_points() {
    let disk = Ball::<2>::new([0.5, 0.5], 0.25).unwrap();
    let ms = [8usize, 12, 16, 24, 32, 48, 64];
    let jit: Vec<Jittered<2>> = ms.iter().map(|&m| Jittered::new([m, m]).unwrap()).collect();
    let ests: Vec<(usize, Box<dyn Estimator<2>>)> = jit
        .iter()
        .map(|p| {
            (
                p.len(),
                Box::new(PointEstimator::new(p).unwrap()) as Box<dyn Estimator<2>>,
            )
        })
        .collect();
    let c = curve(&disk, &ests, 11, REPS);
    check(
        "disk 2D jittered points",
        slope(&c, "disk 2D jittered points", 0.0),
        -1.5,
    );
    let rnd: Vec<Random<2>> = ms.iter().map(|&m| Random::new(m * m).unwrap()).collect();
    let ests: Vec<(usize, Box<dyn Estimator<2>>)> = rnd
        .iter()
        .map(|p| {
            (
                p.len(),
                Box::new(PointEstimator::new(p).unwrap()) as Box<dyn Estimator<2>>,
            )
        })
        .collect();
    let c = curve(&disk, &ests, 12, REPS);
    check(
        "disk 2D random points",
        slope(&c, "disk 2D random points", 0.0),
        -1.0,
    );
}

#[test]
#[ignore = "release-mode statistical test (CI runs it)"]
fn convergence_sphere_3d_points() {
    let ball = Ball::<3>::new([0.5, 0.5, 0.5], 0.25).unwrap();
    let ms = [4usize, 5, 6, 8, 10, 12, 16];
    let jit: Vec<Jittered<3>> = ms
        .iter()
        .map(|&m| Jittered::new([m, m, m]).unwrap())
        .collect();
    let ests: Vec<(usize, Box<dyn Estimator<3>>)> = jit
        .iter()
        .map(|p| {
            (
                p.len(),
                Box::new(PointEstimator::new(p).unwrap()) as Box<dyn Estimator<3>>,
            )
        })
        .collect();
    let c = curve(&ball, &ests, 21, REPS);
    check(
        "sphere 3D jittered points",
        slope(&c, "sphere 3D jittered points", 0.0),
        -4.0 / 3.0,
    );
}

#[test]
#[ignore = "release-mode statistical test (CI runs it)"]
fn convergence_3d_lines() {
    let ball = Ball::<3>::new([0.5, 0.5, 0.5], 0.25).unwrap();
    let gauss = Gaussian::<3>::new([0.5, 0.5, 0.5], 0.1).unwrap();
    let z = Direction::axis(2).unwrap();
    let ms = [4usize, 6, 8, 12, 16, 24, 32, 48, 64];
    let jit: Vec<Jittered<2>> = ms.iter().map(|&m| Jittered::new([m, m]).unwrap()).collect();
    let ests: Vec<(usize, Box<dyn Estimator<3>>)> = jit
        .iter()
        .map(|p| {
            (
                p.len(),
                Box::new(LineEstimator::new(p, Directions::Fixed(z)).unwrap())
                    as Box<dyn Estimator<3>>,
            )
        })
        .collect();
    // Sphere: Var ~ N^-2 log N (paper-notes §4.1): N²·Var/log N is flat.
    let c = curve(&ball, &ests, 31, REPS);
    let (b, se) = slope(&c, "sphere 3D jittered lines ∥z", 1.0);
    check("sphere 3D jittered lines, Var/log N", (b, se), -2.0);
    // Gaussian: Var ~ N^-2, no log.
    let c = curve(&gauss, &ests, 32, REPS);
    check(
        "gaussian 3D jittered lines",
        slope(&c, "gaussian σ = 0.1, 3D jittered lines ∥z", 0.0),
        -2.0,
    );
    let rnd: Vec<Random<2>> = ms.iter().map(|&m| Random::new(m * m).unwrap()).collect();
    let ests: Vec<(usize, Box<dyn Estimator<3>>)> = rnd
        .iter()
        .map(|p| {
            (
                p.len(),
                Box::new(LineEstimator::new(p, Directions::Fixed(z)).unwrap())
                    as Box<dyn Estimator<3>>,
            )
        })
        .collect();
    let c = curve(&ball, &ests, 33, REPS);
    check(
        "sphere 3D random lines",
        slope(&c, "sphere 3D random lines ∥z", 0.0),
        -1.0,
    );
}

/// Found by the fuzzers: a subnormal length used to halve inexactly (so the
/// mean exceeded the maximum); `Segment::new` now stores it as 0, a point.
#[test]
fn subnormal_segment_lengths_are_points() {
    use linesample::primitive::Segment;
    let disk = Ball::<2>::new([2.6e-270, 1.9e-288], 1e-100).unwrap();
    let gauss = Gaussian::<2>::new([8.3e-141, 2.6e-260], 0.0365).unwrap();
    let edge = HalfSpace::<2>::new(dir([1.0, -0.3]), 0.2).unwrap();
    let fs: [&dyn Integrand<2>; 3] = [&disk, &gauss, &edge];
    let c = [3.3e-274, 7.7e-121];
    for f in fs {
        for len in [1.26e-321, 2.99e-319, 4e-310, 0.0] {
            let s = Segment::new(c, dir([-1.9e260, 9.1e-97]), len).unwrap();
            assert_eq!(s.length(), if len < f64::MIN_POSITIVE { 0.0 } else { len });
            let m = f.segment_mean(&s);
            assert_eq!(m, f.value(&c), "{f:?} λ = {len:e}");
            assert!(m <= f.max_value());
        }
    }
}
