//! PMJ02 and PMJ02BN: every elementary interval of every power-of-two prefix
//! holds exactly one point (exactly, as `f32`), the forced cells are the only
//! valid ones, range, determinism, prefix property, `fill_range` = slice of
//! `fill`, bad input, unbiasedness of PMJ02 and the blue-noise gain of PMJ02BN.

use linesample::pattern::{
    Pattern, Pmj02, PMJ02BN_DEFAULT_CANDIDATES, PMJ02BN_MAX_CANDIDATES, PMJ02_MAX_POINTS,
};
use linesample::{PatternError, Seed};
use proptest::prelude::*;

fn points(p: &Pmj02, seed: u64) -> Vec<[f32; 2]> {
    let mut out = vec![[0.0f32; 2]; p.n()];
    let mut scratch = vec![0u32; p.scratch_len()];
    p.generate(Seed::new(seed), &mut out, &mut scratch).unwrap();
    out
}

/// The exact 24-bit integer of a coordinate; fails unless it is a multiple of
/// `2⁻²⁴` in `[0, 1)`.
fn int24(v: f32) -> u32 {
    assert!((0.0..1.0).contains(&v), "coordinate {v} outside [0, 1)");
    let t = f64::from(v) * 16_777_216.0;
    assert_eq!(t, t.floor(), "coordinate {v} is not a multiple of 2^-24");
    t as u32
}

/// Index of the elementary interval of shape `a` (`2⁻ᵃ × 2⁻⁽ᵏ⁻ᵃ⁾`) holding `p`,
/// computed from the exact `f32` values (`⌊x·2ᵃ⌋`, `⌊y·2ᵏ⁻ᵃ⌋`).
fn interval(p: [f32; 2], k: u32, a: u32) -> usize {
    let xa = (f64::from(p[0]) * f64::from(1u32 << a)).floor() as usize;
    let yb = (f64::from(p[1]) * f64::from(1u32 << (k - a))).floor() as usize;
    (xa << (k - a)) | yb
}

/// Checks that every prefix of `2ᵏ ≤ pts.len()` points has exactly one point in
/// every elementary interval of area `2⁻ᵏ` (all shapes `a = 0 … k`). Returns a
/// description of the first violation.
fn check_elementary(pts: &[[f32; 2]]) -> Result<(), String> {
    for p in pts {
        int24(p[0]);
        int24(p[1]);
    }
    let mut k = 0u32;
    while (1usize << k) <= pts.len() {
        let n = 1usize << k;
        let mut seen = vec![false; n];
        for a in 0..=k {
            seen.iter_mut().for_each(|s| *s = false);
            for (i, &p) in pts[..n].iter().enumerate() {
                let c = interval(p, k, a);
                if seen[c] {
                    return Err(format!(
                        "prefix 2^{k}: shape a = {a}: point {i} shares interval {c}"
                    ));
                }
                seen[c] = true;
            }
        }
        k += 1;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Both variants, random seeds: all prefixes up to 4096 points.
    #[test]
    fn every_power_of_two_prefix_is_a_net(seed: u64) {
        for p in [Pmj02::new(4096).unwrap(), Pmj02::blue_noise(4096).unwrap()] {
            let pts = points(&p, seed);
            prop_assert_eq!(pts.len(), 4096);
            if let Err(e) = check_elementary(&pts) {
                return Err(TestCaseError::fail(format!("bn {}: {e}", p.is_blue_noise())));
            }
        }
    }

    /// Any `n` is the first `n` points of a longer sequence (same seed), and
    /// its power-of-two prefixes are nets.
    #[test]
    fn any_n_is_a_prefix(n in 1usize..1500, seed: u64, bn: bool) {
        let (short, long) = if bn {
            (Pmj02::blue_noise(n).unwrap(), Pmj02::blue_noise(2048).unwrap())
        } else {
            (Pmj02::new(n).unwrap(), Pmj02::new(2048).unwrap())
        };
        let a = points(&short, seed);
        let b = points(&long, seed);
        prop_assert!(a.iter().zip(&b).all(|(p, q)| p[0].to_bits() == q[0].to_bits()
            && p[1].to_bits() == q[1].to_bits()));
        if let Err(e) = check_elementary(&a) {
            return Err(TestCaseError::fail(e));
        }
    }

    /// `fill_range` of a sub-range (AoS, scalar, SoA) equals the slice of the
    /// full fill.
    #[test]
    fn fill_range_is_a_slice_of_fill(first in 0usize..700, len in 0usize..400, seed: u64, bn: bool) {
        let n = 1000;
        let p = if bn { Pmj02::blue_noise(n).unwrap() } else { Pmj02::new(n).unwrap() };
        let len = len.min(n - first);
        let full = p.to_vec(Seed::new(seed)).unwrap();
        prop_assert_eq!(&full, &points(&p, seed));
        let mut part = vec![[0.0f32; 2]; len];
        p.fill_range(Seed::new(seed), first, &mut part).unwrap();
        prop_assert_eq!(&part[..], &full[first..first + len]);
        let mut scalar = vec![[0.0f32; 2]; len];
        p.fill_range_scalar(Seed::new(seed), first, &mut scalar).unwrap();
        prop_assert_eq!(&scalar[..], &full[first..first + len]);
        let (mut xs, mut ys) = (vec![0.0f32; len], vec![0.0f32; len]);
        p.fill_range_soa(Seed::new(seed), first, [&mut xs, &mut ys]).unwrap();
        for i in 0..len {
            prop_assert_eq!(xs[i].to_bits(), full[first + i][0].to_bits());
            prop_assert_eq!(ys[i].to_bits(), full[first + i][1].to_bits());
        }
    }
}

#[test]
fn nets_at_65536() {
    for p in [
        Pmj02::new(65536).unwrap(),
        Pmj02::blue_noise(65536).unwrap(),
    ] {
        let pts = points(&p, 0xDEAD_BEEF);
        check_elementary(&pts).unwrap();
    }
}

/// The stratification check itself catches a broken set: moving one point of a
/// valid sequence into its neighbour's `2⁻¹²` column must be reported.
#[test]
fn the_checker_catches_a_misplaced_point() {
    let mut pts = points(&Pmj02::new(4096).unwrap(), 3);
    check_elementary(&pts).unwrap();
    pts[4095][0] = pts[4094][0];
    assert!(check_elementary(&pts).is_err());
}

/// The positions are the only valid ones: for each batch `2^{k−1} → 2ᵏ`
/// (`k ≤ 8`), the cells of side `2⁻ᵏ` that lie in no elementary interval of
/// level `k` occupied by an old point are found by brute force over all
/// `2ᵏ × 2ᵏ` cells; there are exactly `2^{k−1}` of them and the new points fill
/// them, one each (the completion theorem of the module docs).
#[test]
fn new_points_fill_exactly_the_valid_cells() {
    for bn in [false, true] {
        for seed in 0..4u64 {
            let p = if bn {
                Pmj02::blue_noise(256).unwrap()
            } else {
                Pmj02::new(256).unwrap()
            };
            let pts = points(&p, seed);
            for k in 1..=8u32 {
                let old = 1usize << (k - 1);
                let side = 1usize << k;
                let mut occupied = vec![vec![false; side]; (k + 1) as usize];
                for &q in &pts[..old] {
                    for a in 0..=k {
                        occupied[a as usize][interval(q, k, a)] = true;
                    }
                }
                let mut valid = Vec::new();
                for cx in 0..side {
                    for cy in 0..side {
                        let centre = [
                            ((cx as f64 + 0.5) / side as f64) as f32,
                            ((cy as f64 + 0.5) / side as f64) as f32,
                        ];
                        if (0..=k).all(|a| !occupied[a as usize][interval(centre, k, a)]) {
                            valid.push((cx, cy));
                        }
                    }
                }
                assert_eq!(valid.len(), old, "bn {bn} seed {seed} k {k}");
                let mut got: Vec<(usize, usize)> = pts[old..2 * old]
                    .iter()
                    .map(|q| {
                        (
                            (f64::from(q[0]) * side as f64) as usize,
                            (f64::from(q[1]) * side as f64) as usize,
                        )
                    })
                    .collect();
                got.sort_unstable();
                assert_eq!(got, valid, "bn {bn} seed {seed} k {k}");
            }
        }
    }
}

#[test]
fn deterministic_and_seed_dependent() {
    for p in [Pmj02::new(777).unwrap(), Pmj02::blue_noise(777).unwrap()] {
        let a = points(&p, 11);
        assert_eq!(a, points(&p, 11));
        // scratch contents on entry do not matter
        let mut out = vec![[0.0f32; 2]; p.n()];
        let mut scratch = vec![u32::MAX; p.scratch_len() + 5];
        p.generate(Seed::new(11), &mut out, &mut scratch).unwrap();
        assert_eq!(a, out);
        for s in [12u64, 11 ^ (1 << 40)] {
            let b = points(&p, s);
            let same = a.iter().zip(&b).filter(|(x, y)| x == y).count();
            assert!(same <= 1, "seeds 11 and {s}: {same} equal points");
        }
    }
    // the variants differ
    assert_ne!(
        points(&Pmj02::new(64).unwrap(), 5),
        points(&Pmj02::blue_noise(64).unwrap(), 5)
    );
}

#[test]
fn bad_input() {
    assert_eq!(Pmj02::new(0), Err(PatternError::ZeroPoints));
    assert_eq!(Pmj02::blue_noise(0), Err(PatternError::ZeroPoints));
    let max = PMJ02_MAX_POINTS as usize;
    assert_eq!(
        Pmj02::new(max + 1),
        Err(PatternError::TooManyPoints {
            max: PMJ02_MAX_POINTS
        })
    );
    assert!(Pmj02::new(max).is_ok());
    let p = Pmj02::new(100).unwrap();
    for k in [0, PMJ02BN_MAX_CANDIDATES + 1] {
        match p.with_candidates(k) {
            Err(PatternError::Parameter { name, .. }) => assert_eq!(name, "candidates"),
            other => panic!("candidates {k}: {other:?}"),
        }
    }
    assert_eq!(
        p.with_candidates(PMJ02BN_MAX_CANDIDATES)
            .unwrap()
            .candidates(),
        PMJ02BN_MAX_CANDIDATES
    );
    assert_eq!(
        Pmj02::blue_noise(5).unwrap().candidates(),
        PMJ02BN_DEFAULT_CANDIDATES
    );
    let mut out = vec![[0.0f32; 2]; 99];
    let mut scratch = vec![0u32; p.scratch_len()];
    assert_eq!(
        p.generate(Seed::new(1), &mut out, &mut scratch),
        Err(PatternError::OutputLength {
            expected: 100,
            got: 99
        })
    );
    let mut out = vec![[0.0f32; 2]; 100];
    let mut short = vec![0u32; p.scratch_len() - 1];
    assert_eq!(
        p.generate(Seed::new(1), &mut out, &mut short),
        Err(PatternError::Scratch {
            expected: p.scratch_len(),
            got: p.scratch_len() - 1
        })
    );
    let mut o = vec![[0.0f32; 2]; 10];
    assert!(matches!(
        p.fill_range(Seed::new(1), 95, &mut o),
        Err(PatternError::Range { .. })
    ));
    assert!(matches!(
        p.fill(Seed::new(1), &mut o),
        Err(PatternError::OutputLength { .. })
    ));
    // n = 1: one uniform point, no scratch
    let one = Pmj02::new(1).unwrap();
    assert_eq!(one.scratch_len(), 0);
    let pts = points(&one, 9);
    assert!(pts[0].iter().all(|v| (0.0..1.0).contains(v)));
}

/// Nearest-neighbour toroidal distance of every point of a set (brute force).
fn nn_dists(pts: &[[f32; 2]]) -> Vec<f64> {
    let mut best = vec![f64::INFINITY; pts.len()];
    for i in 0..pts.len() {
        for j in 0..i {
            let mut d2 = 0.0;
            for (u, v) in pts[i].iter().zip(&pts[j]) {
                let d = (f64::from(*u) - f64::from(*v)).abs();
                let d = d.min(1.0 - d);
                d2 += d * d;
            }
            best[i] = best[i].min(d2);
            best[j] = best[j].min(d2);
        }
    }
    best.into_iter().map(f64::sqrt).collect()
}

/// PMJ02BN spreads its points further than PMJ02, at `N = 1024` over 256 seeds
/// per variant, distances in units of `1/√N`.
///
/// Measured by this test (seeds 0..256): mean nearest-neighbour distance PMJ02
/// 0.6528, PMJ02BN (10 candidates) 0.6632, `z = 7.15`; mean minimum distance
/// PMJ02 0.125, PMJ02BN 0.139. Earlier release runs over 64 seeds with `k`
/// candidates gave mean NN 0.649 (`k = 0`, plain), 0.666 (10), 0.668 (30),
/// 0.671 (100), per-set sd ≈ 0.015, and minimum distances with per-set sd ≈ 0.04.
/// The gain is small because the (0,2) constraints fix every point of a `2ᵏ`
/// prefix to a cell of side `2⁻ᵏ` (module docs). The minimum distance is too
/// noisy to show it with a few seeds (its per-set spread is three times the
/// gain), so the assertion uses the mean nearest-neighbour distance: pass iff
/// `z = (m_bn − m_pmj)/SE ≥ 3`, `SE` from the sample variances. With the
/// measured effect a correct implementation fails with probability
/// `Φ(3 − 7.15) ≈ 2·10⁻⁵`; a best-candidate step that did nothing passes with
/// probability `1.3·10⁻³`. Deterministic (fixed seeds).
#[test]
fn blue_noise_spreads_points() {
    let n = 1024;
    let seeds = 256u64;
    let scale = (n as f64).sqrt();
    let stats = |p: &Pmj02| -> (f64, f64, f64) {
        let (mut m, mut m2, mut min) = (0.0, 0.0, 0.0);
        for s in 0..seeds {
            let d = nn_dists(&points(p, s));
            let mean = d.iter().sum::<f64>() / n as f64 * scale;
            m += mean;
            m2 += mean * mean;
            min += d.iter().copied().fold(f64::INFINITY, f64::min) * scale;
        }
        let k = seeds as f64;
        let mean = m / k;
        let var = (m2 / k - mean * mean) * k / (k - 1.0);
        (mean, var / k, min / k)
    };
    let (plain, v_plain, min_plain) = stats(&Pmj02::new(n).unwrap());
    let (bn, v_bn, min_bn) = stats(&Pmj02::blue_noise(n).unwrap());
    let z = (bn - plain) / (v_plain + v_bn).sqrt();
    eprintln!(
        "N = {n}, ·√N: mean NN pmj02 {plain:.4}, pmj02bn {bn:.4} (z = {z:.2}); \
         mean min distance pmj02 {min_plain:.4}, pmj02bn {min_bn:.4}"
    );
    assert!(z >= 3.0, "pmj02bn {bn} vs pmj02 {plain}: z = {z}");
}

/// Every point of PMJ02 is uniform on the square (the construction's law is
/// invariant under Owen scrambling): over 4000 seeds, the mean of each
/// coordinate of points 1, 2, 3, 6, 100 and 1023 of a 1024-point sequence is
/// ½ within 5 standard errors (`SE = 1/√(12·4000)`; 12 checks, false alarm
/// `12 × 5.7·10⁻⁷`). A bias of `5·SE ≈ 0.023` would be flagged half the time.
#[test]
fn pmj02_points_are_unbiased() {
    let p = Pmj02::new(1024).unwrap();
    let idx = [1usize, 2, 3, 6, 100, 1023];
    let reps = 4000;
    let mut sum = [[0.0f64; 2]; 6];
    for s in 0..reps {
        let pts = points(&p, 1_000_000 + s as u64);
        for (k, &i) in idx.iter().enumerate() {
            for (acc, v) in sum[k].iter_mut().zip(pts[i]) {
                *acc += f64::from(v);
            }
        }
    }
    let se = (1.0 / 12.0 / reps as f64).sqrt();
    for (k, &i) in idx.iter().enumerate() {
        for (c, total) in sum[k].iter().enumerate() {
            let z = (total / reps as f64 - 0.5) / se;
            assert!(z.abs() <= 5.0, "point {i} coordinate {c}: z = {z}");
        }
    }
}
