//! CCVT point sets (issue 3): exact equal capacities, centroidal sites, monotone
//! energy, determinism, input checking, and — the signature of a real CCVT — the
//! variance convergence rate of the point-sampling estimator (ignored by default;
//! run with `cargo test --release --test ccvt -- --ignored --nocapture`).

use linesample::pattern::{Ccvt, CcvtResult, Jittered, Pattern};
use linesample::{PatternError, Seed};

/// Toroidal offset wrapped into `[−1/2, 1/2)`.
fn wrap(d: f64) -> f64 {
    d - (d + 0.5).floor()
}

/// Largest `|site − centroid of its discrete points|` (toroidal), over all sites.
fn max_centroid_offset<const D: usize>(r: &CcvtResult<D>) -> f64 {
    let sites = r.sites_f64();
    let mut sum = vec![[0.0f64; D]; sites.len()];
    let mut count = vec![0usize; sites.len()];
    for (p, &a) in r.discrete_points().iter().zip(r.assignment()) {
        let a = a as usize;
        count[a] += 1;
        for j in 0..D {
            sum[a][j] += wrap(p[j] - sites[a][j]);
        }
    }
    let mut worst = 0.0f64;
    for (s, &c) in sum.iter().zip(&count) {
        let d2: f64 = s.iter().map(|v| (v / c as f64).powi(2)).sum();
        worst = worst.max(d2.sqrt());
    }
    worst
}

fn check_equal_and_centroidal<const D: usize>(n: usize, c: usize, seed: u64) {
    let r = Ccvt::<D>::new(n)
        .unwrap()
        .capacity(c)
        .unwrap()
        .generate(Seed::new(seed));
    assert!(
        r.converged(),
        "n = {n}: no stable state in {} iterations",
        r.iterations()
    );
    assert_eq!(r.sites().len(), n);
    assert_eq!(r.discrete_points().len(), n * c);
    // Equal capacity, exactly: every site owns c discrete points.
    assert!(
        r.capacities().iter().all(|&k| k == c),
        "{:?}",
        r.capacities()
    );
    // Centroidal: the site is the toroidal centroid of its points up to rounding,
    // tolerance 1e-9 of the site spacing N^{-1/D}.
    let spacing = (n as f64).powf(-1.0 / D as f64);
    let off = max_centroid_offset(&r);
    assert!(off < 1e-9 * spacing, "n = {n}: centroid offset {off:e}");
    // Energy near the optimum: at least the hexagonal (2D) / BCC-like (3D) bound
    // and at most 25 % above it (the value includes discretisation).
    let area = 1.0 / n as f64;
    let ideal = if D == 2 {
        5.0 / (18.0 * 3f64.sqrt()) * area
    } else {
        0.0785 * 3.0 * area.powf(2.0 / 3.0)
    };
    // A judgement, not a statistical bound (the energy is deterministic for
    // the seed): the lower edge 0.9 allows the discretisation (the energy is
    // a mean over M = n·c random discrete points, a few per cent off the
    // continuous integral in either direction at c = 50–64); the upper edge
    // 1.25 allows a capacity-constrained tessellation that is a local, not the
    // global, optimum (hexagonal / BCC-like cells are the ideal), while a broken
    // assignment or centroid step, which leaves sites far from their cells'
    // centroids, lands above it.
    assert!(
        r.energy() > 0.9 * ideal && r.energy() < 1.25 * ideal,
        "n = {n}: energy {:e} vs ideal {ideal:e}",
        r.energy()
    );
}

#[test]
fn equal_capacity_and_centroidal_2d() {
    check_equal_and_centroidal::<2>(64, 64, 1);
    check_equal_and_centroidal::<2>(256, 64, 2);
    check_equal_and_centroidal::<2>(100, 50, 3); // M = 5000, not a square
}

#[test]
fn equal_capacity_and_centroidal_3d() {
    check_equal_and_centroidal::<3>(64, 64, 4);
    check_equal_and_centroidal::<3>(100, 40, 5);
}

#[test]
fn low_jitter_and_bare_grid() {
    for delta in [0.0, 0.1] {
        let r = Ccvt::<2>::new(64)
            .unwrap()
            .jitter(delta)
            .unwrap()
            .generate(Seed::new(31));
        assert!(r.converged());
        assert!(r.capacities().iter().all(|&k| k == 64));
        assert!(max_centroid_offset(&r) < 1e-9);
        assert!(r.sites().iter().flatten().all(|&x| (0.0..1.0).contains(&x)));
    }
}

#[test]
fn capacities_exact_when_stopped_early() {
    let r = Ccvt::<2>::new(128)
        .unwrap()
        .max_iterations(2)
        .unwrap()
        .generate(Seed::new(9));
    assert_eq!(r.iterations(), 2);
    assert!(!r.converged());
    assert!(r.capacities().iter().all(|&k| k == 64));
    // The sites are centroids of their points after every iteration.
    assert!(max_centroid_offset(&r) < 1e-9);
}

#[test]
fn energy_non_increasing() {
    for (n, seed) in [(64usize, 11u64), (256, 12)] {
        let mut trace = Vec::new();
        let r = Ccvt::<2>::new(n)
            .unwrap()
            .generate_with_trace(Seed::new(seed), &mut |t, e| trace.push((t, e)));
        assert_eq!(trace.len(), r.iterations() + 1);
        for (k, w) in trace.windows(2).enumerate() {
            assert_eq!(w[1].0, k + 1);
            assert!(
                w[1].1 <= w[0].1 * (1.0 + 1e-12),
                "n = {n}: energy rose at iteration {}: {} -> {}",
                k + 1,
                w[0].1,
                w[1].1
            );
        }
        assert_eq!(trace.last().unwrap().1, r.energy());
        assert!(trace[0].1 > r.energy());
    }
    let mut trace = Vec::new();
    Ccvt::<3>::new(64)
        .unwrap()
        .generate_with_trace(Seed::new(13), &mut |_, e| trace.push(e));
    assert!(trace.windows(2).all(|w| w[1] <= w[0] * (1.0 + 1e-12)));
}

#[test]
fn range_determinism_seeds_and_pattern() {
    let p = Ccvt::<2>::new(96).unwrap();
    let a = p.generate(Seed::new(21));
    let b = p.generate(Seed::new(21));
    let c = p.generate(Seed::new(22));
    assert_eq!(a.sites(), b.sites());
    assert_eq!(a.assignment(), b.assignment());
    assert_ne!(a.sites(), c.sites());
    for s in a.sites().iter().chain(c.sites()) {
        assert!(s.iter().all(|&x| (0.0..1.0).contains(&x)), "{s:?}");
    }
    for s in a.discrete_points() {
        assert!(s.iter().all(|&x| (0.0..1.0).contains(&x)), "{s:?}");
    }
    // As a Pattern: fill = generate, ranges agree, shifted stays in [0, 1).
    assert_eq!(p.len(), 96);
    let mut out = vec![[0.0f32; 2]; 96];
    p.fill(Seed::new(21), &mut out).unwrap();
    assert_eq!(&out[..], a.sites());
    let mut part = vec![[0.0f32; 2]; 10];
    p.fill_range(Seed::new(21), 80, &mut part).unwrap();
    assert_eq!(&part[..], &a.sites()[80..90]);
    assert!(p.fill_range(Seed::new(21), 90, &mut part).is_err());
    let sh = p.clone().shifted();
    sh.fill(Seed::new(21), &mut out).unwrap();
    assert!(out.iter().flatten().all(|&x| (0.0..1.0).contains(&x)));

    let p3 = Ccvt::<3>::new(32).unwrap();
    let r3 = p3.generate(Seed::new(5));
    assert!(r3.converged());
    assert_eq!(r3.sites(), p3.generate(Seed::new(5)).sites());
    assert!(r3
        .sites()
        .iter()
        .flatten()
        .all(|&x| (0.0..1.0).contains(&x)));
}

#[test]
fn bad_input_is_an_error() {
    assert_eq!(Ccvt::<2>::new(0).unwrap_err(), PatternError::ZeroPoints);
    assert!(matches!(
        Ccvt::<1>::new(8).unwrap_err(),
        PatternError::Dims {
            dims: 1,
            min: 2,
            max: 3
        }
    ));
    assert!(matches!(
        Ccvt::<4>::new(8).unwrap_err(),
        PatternError::Dims { dims: 4, .. }
    ));
    assert!(matches!(
        Ccvt::<2>::new(1 << 25).unwrap_err(),
        PatternError::TooManyPoints { .. }
    ));
    let e = Ccvt::<2>::new(8).unwrap().capacity(0).unwrap_err();
    assert!(matches!(
        e,
        PatternError::Parameter {
            name: "capacity",
            value: 0,
            ..
        }
    ));
    assert!(e.to_string().contains("capacity"), "{e}");
    let e = Ccvt::<2>::new(8).unwrap().capacity(1 << 20).unwrap_err();
    assert!(matches!(
        e,
        PatternError::Parameter {
            name: "capacity",
            ..
        }
    ));
    let e = Ccvt::<2>::new(1 << 20)
        .unwrap()
        .capacity(1 << 12)
        .unwrap_err();
    assert!(matches!(
        e,
        PatternError::Parameter {
            name: "capacity",
            ..
        }
    ));
    let e = Ccvt::<3>::new(8).unwrap().max_iterations(0).unwrap_err();
    assert!(matches!(
        e,
        PatternError::Parameter {
            name: "max_iterations",
            ..
        }
    ));
    assert!(e.to_string().contains("max_iterations"), "{e}");
    for bad in [-0.1, 1.5, f64::NAN] {
        let e = Ccvt::<2>::new(8).unwrap().jitter(bad).unwrap_err();
        assert_eq!(e, PatternError::Jitter);
        assert!(e.to_string().contains("jitter"), "{e}");
    }
    // Smallest valid inputs work.
    let r = Ccvt::<2>::new(1)
        .unwrap()
        .capacity(1)
        .unwrap()
        .generate(Seed::new(0));
    assert_eq!(r.capacities(), vec![1]);
}

// ---------------------------------------------------------------------------
// Spatial quality: normalised minimum and mean nearest-neighbour distances.

/// `(δ_min, δ_avg)`: the smallest and the mean toroidal nearest-neighbour
/// distance of a 2D point set, in units of the hexagonal packing distance
/// `d_hex = √(2/(√3·N))` (Schlömer, Heck & Deussen 2011). Brute force.
fn deltas(p: &[[f64; 2]]) -> (f64, f64) {
    let n = p.len();
    let mut dmin2 = f64::INFINITY;
    let mut sum = 0.0;
    for (i, a) in p.iter().enumerate() {
        let mut best = f64::INFINITY;
        for (j, b) in p.iter().enumerate() {
            if i != j {
                let dx = wrap(a[0] - b[0]);
                let dy = wrap(a[1] - b[1]);
                best = best.min(dx * dx + dy * dy);
            }
        }
        dmin2 = dmin2.min(best);
        sum += best.sqrt();
    }
    let dhex = (2.0 / (3f64.sqrt() * n as f64)).sqrt();
    (dmin2.sqrt() / dhex, sum / n as f64 / dhex)
}

/// Checks a quality setting at N = 1024 over seeds 0 and 1: both runs are
/// stable CCVTs with exact capacities and centroidal sites, every set has
/// `δ_min ≥ min_floor`, and the mean `δ_avg` over the two seeds is at least
/// `avg_floor`.
fn check_quality(p: &Ccvt<2>, c: usize, min_floor: f64, avg_floor: f64) {
    let mut avg = 0.0;
    for seed in 0..2u64 {
        let r = p.generate(Seed::new(seed));
        assert!(r.converged(), "seed {seed}: not stable");
        assert!(r.capacities().iter().all(|&k| k == c));
        assert!(max_centroid_offset(&r) < 1e-9);
        let (dmin, davg) = deltas(r.sites_f64());
        println!("c = {c}, seed {seed}: δ_min = {dmin:.4}, δ_avg = {davg:.4}");
        assert!(
            dmin >= min_floor,
            "seed {seed}: δ_min = {dmin:.4} < {min_floor}"
        );
        avg += davg / 2.0;
    }
    assert!(avg >= avg_floor, "mean δ_avg = {avg:.4} < {avg_floor}");
}

// Thresholds. Measured at N = 1024 (release build, `cargo run --release
// --example ccvt_quality -- --sweep`, 4–8 seeds): fast δ_min 0.636 ± 0.008,
// δ_avg 0.818 ± 0.001; standard 0.692 ± 0.004 / 0.845 ± 0.001; high
// 0.739 ± 0.006 / 0.866 ± 0.001 (mean ± s.e.; seed-to-seed s.d. of δ_avg ≈
// 0.003, of δ_min ≈ 0.012–0.02). The values are deterministic for the fixed
// seeds; the floors sit ≥ 3 seed-to-seed s.d. below the means (a new build or
// platform that perturbs the run would fail with probability ≲ 1e-3 per
// check), and each δ_avg floor lies above the mean of the next lower setting
// by ≥ 5 s.d. of a two-seed mean, so a setting that silently falls back to a
// lower capacity (or runs without swaps: δ_avg ≈ 0.5–0.7) fails.

#[test]
fn quality_fast_default() {
    let p = Ccvt::<2>::new(1024).unwrap();
    assert_eq!(p, Ccvt::<2>::new(1024).unwrap().fast_quality().unwrap());
    check_quality(&p, 64, 0.58, 0.810);
}

#[test]
fn quality_standard() {
    let p = Ccvt::<2>::new(1024).unwrap().standard_quality().unwrap();
    assert_eq!(p.capacity_per_site(), 256);
    check_quality(&p, 256, 0.64, 0.835);
}

/// ≈ 13 s in the test profile (two sets at c = 1024).
#[test]
fn quality_high() {
    let p = Ccvt::<2>::new(1024).unwrap().high_quality().unwrap();
    assert_eq!(p.capacity_per_site(), 1024);
    check_quality(&p, 1024, 0.69, 0.857);
}

#[test]
fn warm_start_gives_a_stable_ccvt() {
    // Coarse-to-fine runs (c = 256 after c = 64) are still exact CCVTs, and
    // deterministic; the discrete density of the final stage is the one of
    // the cold run, so only the sites differ.
    let cold = Ccvt::<2>::new(128).unwrap().capacity(256).unwrap();
    let warm = cold.clone().warm_start(true);
    let a = warm.generate(Seed::new(3));
    assert!(a.converged());
    assert!(a.capacities().iter().all(|&k| k == 256));
    assert!(max_centroid_offset(&a) < 1e-9);
    assert_eq!(a.sites(), warm.generate(Seed::new(3)).sites());
    let b = cold.generate(Seed::new(3));
    assert_eq!(a.discrete_points(), b.discrete_points());
    assert_ne!(a.sites(), b.sites());
    // Below c = 256 there is no coarser stage: warm start changes nothing.
    let small = Ccvt::<2>::new(128).unwrap();
    assert_eq!(
        small.generate(Seed::new(4)).sites(),
        small
            .clone()
            .warm_start(true)
            .generate(Seed::new(4))
            .sites()
    );
    // 3D too.
    let r3 = Ccvt::<3>::new(64)
        .unwrap()
        .standard_quality()
        .unwrap()
        .generate(Seed::new(5));
    assert!(r3.converged());
    assert!(r3.capacities().iter().all(|&k| k == 256));
}

#[test]
fn quality_settings_reject_too_many_points() {
    // N·c ≤ 2³¹: N = 2²² allows c ≤ 512, so high (1024) is an error.
    let p = Ccvt::<2>::new(1 << 22).unwrap();
    assert!(p.clone().standard_quality().is_ok());
    assert!(matches!(
        p.high_quality().unwrap_err(),
        PatternError::Parameter {
            name: "capacity",
            ..
        }
    ));
}

// ---------------------------------------------------------------------------
// Convergence signature.

const SIGMA: f64 = 0.1;

/// Gaussian of width σ centred at (1/2, 1/2), periodised over the 3×3 images.
fn gaussian(p: [f32; 2]) -> f64 {
    let mut s = 0.0;
    for a in -1..=1 {
        for b in -1..=1 {
            let dx = f64::from(p[0]) + f64::from(a) - 0.5;
            let dy = f64::from(p[1]) + f64::from(b) - 0.5;
            s += (-(dx * dx + dy * dy) / (2.0 * SIGMA * SIGMA)).exp();
        }
    }
    s
}

/// Indicator of the disk of radius 1/4 centred at (1/2, 1/2).
fn disk(p: [f32; 2]) -> f64 {
    let dx = f64::from(p[0]) - 0.5;
    let dy = f64::from(p[1]) - 0.5;
    f64::from(u8::from(dx * dx + dy * dy < 0.0625))
}

/// Sample variance of the estimator of each integrand in `fs` over the same `r`
/// shifted realisations (one fill serves every integrand: the CCVT generation
/// is the cost), and the standard error of its logarithm (delta method with
/// the sample kurtosis).
fn variances<P: Pattern<2> + Sync, const F: usize>(
    p: &P,
    r: usize,
    fs: [fn([f32; 2]) -> f64; F],
) -> [(f64, f64); F] {
    let n = p.len();
    let threads = std::thread::available_parallelism().map_or(1, |t| t.get());
    let mut est = vec![[0.0f64; F]; r];
    std::thread::scope(|s| {
        for (t, chunk) in est.chunks_mut(r.div_ceil(threads)).enumerate() {
            let base = t * r.div_ceil(threads);
            s.spawn(move || {
                let mut pts = vec![[0.0f32; 2]; n];
                for (k, e) in chunk.iter_mut().enumerate() {
                    let seed = Seed::new(0xCC57).realization((base + k) as u64);
                    p.fill(seed, &mut pts).unwrap();
                    for (ej, f) in e.iter_mut().zip(fs) {
                        *ej = pts.iter().map(|&x| f(x)).sum::<f64>() / n as f64;
                    }
                }
            });
        }
    });
    let rf = r as f64;
    core::array::from_fn(|j| {
        let mean = est.iter().map(|e| e[j]).sum::<f64>() / rf;
        let m2 = est.iter().map(|e| (e[j] - mean).powi(2)).sum::<f64>() / rf;
        let m4 = est.iter().map(|e| (e[j] - mean).powi(4)).sum::<f64>() / rf;
        let kurt = m4 / (m2 * m2);
        let var = m2 * rf / (rf - 1.0);
        let se_log = ((kurt - (rf - 3.0) / (rf - 1.0)) / rf).max(0.0).sqrt();
        (var, se_log)
    })
}

/// Weighted least-squares slope of `ln v` against `ln n` and its standard error.
fn slope(ns: &[usize], vs: &[(f64, f64)]) -> (f64, f64) {
    let x: Vec<f64> = ns.iter().map(|&n| (n as f64).ln()).collect();
    let w: Vec<f64> = vs.iter().map(|v| 1.0 / (v.1 * v.1)).collect();
    let y: Vec<f64> = vs.iter().map(|v| v.0.ln()).collect();
    let sw: f64 = w.iter().sum();
    let xm = x.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>() / sw;
    let ym = y.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>() / sw;
    let sxx: f64 = x.iter().zip(&w).map(|(a, b)| b * (a - xm).powi(2)).sum();
    let sxy: f64 = (0..x.len()).map(|i| w[i] * (x[i] - xm) * (y[i] - ym)).sum();
    (sxy / sxx, (1.0 / sxx).sqrt())
}

/// Variances of the Gaussian and disk estimators for CCVT with discrete-point
/// jitter `delta` and for jittered sampling; prints the table and the fitted
/// slopes; returns `[(gaussian), (disk)]` as (CCVT slope, SE, jittered slope, SE,
/// last local CCVT slope, its SE).
fn rates(delta: f64, ns: &[usize], r: usize) -> Vec<(f64, f64, f64, f64, f64, f64)> {
    let names = ["gaussian", "disk"];
    let fs = [gaussian as fn([f32; 2]) -> f64, disk];
    // vc[j][k], vj[j][k]: integrand j, size ns[k].
    let mut vc = [Vec::new(), Vec::new()];
    let mut vj = [Vec::new(), Vec::new()];
    for &n in ns {
        let m = (n as f64).sqrt() as usize;
        let ccvt = Ccvt::<2>::new(n).unwrap().jitter(delta).unwrap();
        let c = variances(&ccvt.shifted(), r, fs);
        let j = variances(&Jittered::<2>::new([m, m]).unwrap().shifted(), r, fs);
        for (f, name) in names.iter().enumerate() {
            println!(
                "δ = {delta}: {name:8} N = {n:5}: var CCVT {:.3e} (±{:.0} %), jittered {:.3e} (±{:.0} %)",
                c[f].0,
                100.0 * c[f].1,
                j[f].0,
                100.0 * j[f].1
            );
            vc[f].push(c[f]);
            vj[f].push(j[f]);
        }
    }
    let mut table = Vec::new();
    for (f, name) in names.iter().enumerate() {
        let (vc, vj) = (&vc[f], &vj[f]);
        let (sc, ec) = slope(ns, vc);
        let (sj, ej) = slope(ns, vj);
        println!("δ = {delta}: {name:8} slope CCVT {sc:.3} ± {ec:.3}, jittered {sj:.3} ± {ej:.3}");
        let mut last = (0.0, 0.0);
        for k in 0..ns.len() - 1 {
            let (lc, lec) = slope(&ns[k..k + 2], &vc[k..k + 2]);
            let (lj, lej) = slope(&ns[k..k + 2], &vj[k..k + 2]);
            println!(
                "δ = {delta}: {name:8}   N {:4} -> {:4}: CCVT {lc:.3} ± {lec:.3}, jittered {lj:.3} ± {lej:.3}",
                ns[k],
                ns[k + 1]
            );
            last = (lc, lec);
        }
        table.push((sc, ec, sj, ej, last.0, last.1));
    }
    table
}

/// The convergence signature of CCVT: for the smooth Gaussian the variance falls
/// faster than for jittered sampling (theory: N^{-2.5} against N^{-2}); for the
/// disk both fall as N^{-1.5}. R = 200 shifted realisations per point, N = 16 … 4096.
#[test]
#[ignore = "slow (~2 min): run with cargo test --release --test ccvt -- --ignored --nocapture"]
fn convergence_rate_ccvt_vs_jittered() {
    let ns = [16usize, 64, 256, 1024, 4096];
    let r = 200;
    for delta in [1.0, 0.1] {
        let t = rates(delta, &ns, r);
        let (sc, ec, sj, ej, last, elast) = t[0];
        // Release-only checks (5 per δ, 10 in all). Tolerances: `k·SE` parts are
        // statistical (the slope SEs come from the delta-method SEs of the
        // log-variances); the fixed parts are judgements about the pre-asymptotic
        // range N = 16 … 4096, where a fitted rate is not yet its limit: the
        // jittered Gaussian slope reaches −2 only asymptotically (±0.3 around
        // it), and the disk slopes follow −1.5 with an oscillation from how the
        // boundary meets the strata (±0.15 plus 3 SE). The "steeper than"
        // checks use 3 combined SEs (one-sided α = 1.3e-3 each); a slope
        // difference of ≥ 3 SE + the noise (≈ 5 SE) is detected for sure.
        let margin = 3.0 * (ec * ec + ej * ej).sqrt();
        assert!(
            sc < sj - margin,
            "δ = {delta}, Gaussian: CCVT slope {sc:.3} ± {ec:.3} not steeper than jittered {sj:.3} ± {ej:.3}"
        );
        assert!((sj + 2.0).abs() < 0.3, "jittered Gaussian slope {sj:.3}");
        // Disk: both ≈ −1.5.
        let (dc, dec, dj, dej, _, _) = t[1];
        assert!(
            (dc + 1.5).abs() < 0.15 + 3.0 * dec,
            "CCVT disk slope {dc:.3}"
        );
        assert!(
            (dj + 1.5).abs() < 0.15 + 3.0 * dej,
            "jittered disk slope {dj:.3}"
        );
        if delta < 1.0 {
            // With a quiet discrete density the rate holds up to N = 4096.
            assert!(
                last < sj - 3.0 * (elast * elast + ej * ej).sqrt(),
                "δ = {delta}: last local Gaussian slope {last:.3} ± {elast:.3}"
            );
        }
    }
}

#[test]
#[ignore = "timing report: cargo test --release --test ccvt timing -- --ignored --nocapture"]
fn timing() {
    for n in [1024usize, 2048, 4096] {
        for seed in 0..3u64 {
            let t0 = std::time::Instant::now();
            let mut last = t0;
            let mut steps = Vec::new();
            let r = Ccvt::<2>::new(n)
                .unwrap()
                .generate_with_trace(Seed::new(seed), &mut |_, _| {
                    let now = std::time::Instant::now();
                    steps.push((now - last).as_secs_f64() * 1e3);
                    last = now;
                });
            println!(
                "N = {n}, seed {seed}: {:.3} s, {} iterations, converged {}; ms per step: {:.1?}",
                t0.elapsed().as_secs_f64(),
                r.iterations(),
                r.converged(),
                &steps[..steps.len().min(8)]
            );
        }
    }
    for n in [1000usize, 4096] {
        let t0 = std::time::Instant::now();
        let r = Ccvt::<3>::new(n).unwrap().generate(Seed::new(0));
        println!(
            "3D N = {n}: {:.3} s, {} iterations, converged {}",
            t0.elapsed().as_secs_f64(),
            r.iterations(),
            r.converged()
        );
    }
}
