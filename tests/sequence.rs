//! Random-access sequences (`linesample::sequence`): bit identity with the
//! fills, the 16-dimensional Sobol'/Halton samples, errors instead of panics,
//! and decorrelation of per-pixel seeds.

use linesample::num::to_unit_f32;
use linesample::pattern::{
    CorrelatedMultiJittered, Halton, Jittered, MultiJittered, NRooks, Pattern, Random, Shifted,
    Sobol, HALTON_DIMENSIONS, SOBOL_DIMENSIONS,
};
use linesample::sequence::{pixel_seed, Sequence};
use linesample::{PatternError, Seed};

const SEEDS: [Seed; 3] = [Seed(0), Seed(42), Seed(0xDEAD_BEEF_0BAD_F00D)];

fn bits<const D: usize>(p: [f32; D]) -> [u32; D] {
    p.map(f32::to_bits)
}

/// `point(k)` and `sample(k, j)` equal the fill, bit for bit, for every point,
/// and `point(n)` is the range error.
fn check_against_fill<const D: usize, P: Pattern<D> + Sequence<D>>(p: &P, what: &str) {
    let n = Pattern::len(p);
    let mut pts = vec![[0.0f32; D]; n];
    for seed in SEEDS {
        p.fill(seed, &mut pts).unwrap();
        for (k, &want) in pts.iter().enumerate() {
            let got = p.point(k as u64, seed).unwrap();
            assert_eq!(bits(got), bits(want), "{what} n {n} seed {seed:?} k {k}");
            for (j, w) in want.iter().enumerate() {
                let x = p.sample(k as u64, j as u32, seed).unwrap();
                assert_eq!(x.to_bits(), w.to_bits(), "{what} k {k} dim {j}");
            }
        }
        // Through a trait object as well.
        let dynamic: &dyn Sequence<D> = p;
        assert_eq!(bits(dynamic.point(0, seed).unwrap()), bits(pts[0]));
    }
    if Sequence::count(p) == n as u64 {
        for index in [n as u64, n as u64 + 7, u64::MAX] {
            assert_eq!(
                p.point(index, SEEDS[1]),
                Err(PatternError::Range {
                    first: index,
                    len: 1,
                    n: n as u64
                }),
                "{what} n {n}"
            );
        }
    }
}

/// Points at the end of a large pattern: `point(k)` equals `fill_range`
/// there (exercises the jump-ahead to a large index).
fn check_tail<const D: usize, P: Pattern<D> + Sequence<D>>(p: &P, what: &str) {
    let n = Pattern::len(p);
    let first = n - 13;
    let mut pts = [[0.0f32; D]; 13];
    for seed in SEEDS {
        p.fill_range(seed, first, &mut pts).unwrap();
        for (i, &want) in pts.iter().enumerate() {
            let k = (first + i) as u64;
            assert_eq!(bits(p.point(k, seed).unwrap()), bits(want), "{what} k {k}");
        }
    }
}

const SIZES: [usize; 7] = [1, 2, 7, 8, 13, 64, 100];

#[test]
fn random_points_equal_the_fill() {
    for n in SIZES {
        check_against_fill(&Random::<1>::new(n).unwrap(), "Random<1>");
        check_against_fill(&Random::<2>::new(n).unwrap(), "Random<2>");
        check_against_fill(&Random::<3>::new(n).unwrap(), "Random<3>");
    }
    check_tail(&Random::<3>::new(1 << 32).unwrap(), "Random<3> 2^32");
}

#[test]
fn jittered_points_equal_the_fill() {
    for m in SIZES {
        check_against_fill(&Jittered::new([m]).unwrap(), "Jittered<1>");
    }
    for s in [[1, 1], [3, 5], [8, 8], [7, 11], [1, 13]] {
        check_against_fill(&Jittered::new(s).unwrap(), "Jittered<2>");
    }
    for s in [[1, 1, 1], [2, 3, 5], [4, 4, 4], [5, 1, 3]] {
        check_against_fill(&Jittered::new(s).unwrap(), "Jittered<3>");
    }
    check_tail(
        &Jittered::new([65_536, 65_536]).unwrap(),
        "Jittered<2> 2^32",
    );
    check_tail(
        &Jittered::new([1 << 10, 3 << 10, 1000]).unwrap(),
        "Jittered<3>",
    );
}

#[test]
fn nrooks_points_equal_the_fill() {
    for n in SIZES.into_iter().chain([17, 255]) {
        check_against_fill(&NRooks::<1>::new(n).unwrap(), "NRooks<1>");
        check_against_fill(&NRooks::<2>::new(n).unwrap(), "NRooks<2>");
        check_against_fill(&NRooks::<3>::new(n).unwrap(), "NRooks<3>");
    }
    check_tail(&NRooks::<3>::new(1 << 24).unwrap(), "NRooks<3> 2^24");
}

#[test]
fn multijittered_points_equal_the_fill() {
    for n in SIZES.into_iter().chain([12, 17, 30]) {
        check_against_fill(&MultiJittered::new(n).unwrap(), "MJ");
        check_against_fill(&CorrelatedMultiJittered::new(n).unwrap(), "CMJ");
    }
    for (c, r) in [(3, 5), (5, 3), (1, 9), (16, 20)] {
        check_against_fill(&MultiJittered::with_grid(c, r).unwrap(), "MJ grid");
        check_against_fill(
            &CorrelatedMultiJittered::with_grid(c, r).unwrap(),
            "CMJ grid",
        );
    }
    check_tail(&MultiJittered::with_grid(4096, 4096).unwrap(), "MJ 2^24");
    check_tail(
        &CorrelatedMultiJittered::with_grid(4096, 4096).unwrap(),
        "CMJ 2^24",
    );
}

#[test]
fn sobol_and_halton_points_equal_the_fill() {
    for n in SIZES {
        check_against_fill(&Sobol::<1>::new(n).unwrap(), "Sobol<1>");
        check_against_fill(&Sobol::<2>::new(n).unwrap(), "Sobol<2>");
        check_against_fill(&Sobol::<3>::new(n).unwrap(), "Sobol<3>");
        check_against_fill(&Halton::<1>::new(n).unwrap(), "Halton<1>");
        check_against_fill(&Halton::<2>::new(n).unwrap(), "Halton<2>");
        check_against_fill(&Halton::<3>::new(n).unwrap(), "Halton<3>");
    }
    check_tail(&Sobol::<3>::new(1 << 32).unwrap(), "Sobol<3> 2^32");
    check_tail(&Halton::<3>::new(1 << 32).unwrap(), "Halton<3> 2^32");
}

#[test]
fn sobol_and_halton_run_past_n() {
    // The sequence view has 2³² points whatever N: point k of a 10-point
    // pattern is point k of any pattern that contains it.
    let (small, big) = (Sobol::<2>::new(10).unwrap(), Sobol::<2>::new(1000).unwrap());
    let (hsmall, hbig) = (
        Halton::<3>::new(10).unwrap(),
        Halton::<3>::new(1000).unwrap(),
    );
    assert_eq!(Sequence::count(&small), 1 << 32);
    assert_eq!(Sequence::count(&hsmall), 1 << 32);
    let mut pts = vec![[0.0f32; 2]; 1000];
    let mut hpts = vec![[0.0f32; 3]; 1000];
    for seed in SEEDS {
        big.fill(seed, &mut pts).unwrap();
        hbig.fill(seed, &mut hpts).unwrap();
        for k in [10usize, 11, 63, 64, 500, 999] {
            assert_eq!(bits(small.point(k as u64, seed).unwrap()), bits(pts[k]));
            assert_eq!(bits(hsmall.point(k as u64, seed).unwrap()), bits(hpts[k]));
        }
    }
}

#[test]
fn sobol_and_halton_samples_equal_the_inherent_functions() {
    let s2 = Sobol::<2>::new(5).unwrap();
    let h1 = Halton::<1>::new(5).unwrap();
    assert_eq!(Sequence::<2>::dimensions(&s2), SOBOL_DIMENSIONS);
    assert_eq!(Sequence::<1>::dimensions(&h1), HALTON_DIMENSIONS);
    let indices = [
        0u32,
        1,
        2,
        7,
        8,
        63,
        1000,
        0x8000_0000,
        u32::MAX - 1,
        u32::MAX,
    ];
    for seed in SEEDS {
        for &k in &indices {
            for dim in 0..16 {
                let want = Sobol::<1>::sample(k, dim, seed);
                let got = s2.sample(u64::from(k), dim, seed).unwrap();
                assert_eq!(got.to_bits(), want.to_bits(), "Sobol k {k} dim {dim}");
                let want = Halton::<1>::sample(k, dim, seed);
                let got = h1.sample(u64::from(k), dim, seed).unwrap();
                assert_eq!(got.to_bits(), want.to_bits(), "Halton k {k} dim {dim}");
            }
        }
    }
}

/// The shifted sequence equals the shifted fill, and `sample` the coordinate.
fn check_shifted<const D: usize, P: Pattern<D> + Sequence<D> + Clone>(p: &P, what: &str) {
    let sh: Shifted<P> = p.clone().shifted();
    check_against_fill(&sh, what);
    // Shifting really happened: the shifted point is the inner point plus s.
    for seed in SEEDS {
        let s = Shifted::<P>::shift::<D>(seed);
        let inner = p.point(0, seed).unwrap();
        let want: [f32; D] = core::array::from_fn(|j| to_unit_f32(f64::from(inner[j]) + s[j]));
        assert_eq!(bits(sh.point(0, seed).unwrap()), bits(want), "{what}");
    }
}

#[test]
fn shifted_points_equal_the_shifted_fill() {
    for n in [1, 13, 64] {
        check_shifted(&Random::<1>::new(n).unwrap(), "Shifted<Random<1>>");
        check_shifted(&Sobol::<2>::new(n).unwrap(), "Shifted<Sobol<2>>");
        check_shifted(&Halton::<3>::new(n).unwrap(), "Shifted<Halton<3>>");
        check_shifted(&NRooks::<2>::new(n).unwrap(), "Shifted<NRooks<2>>");
        check_shifted(&CorrelatedMultiJittered::new(n).unwrap(), "Shifted<CMJ>");
        check_shifted(&MultiJittered::new(n).unwrap(), "Shifted<MJ>");
    }
    check_shifted(&Jittered::new([2, 3, 5]).unwrap(), "Shifted<Jittered<3>>");
    check_shifted(&Jittered::new([8, 8]).unwrap(), "Shifted<Jittered<2>>");
}

#[test]
fn shifted_sobol_samples_extend_the_shift_to_all_dimensions() {
    let sh = Sobol::<2>::new(8).unwrap().shifted();
    assert_eq!(Sequence::<2>::dimensions(&sh), SOBOL_DIMENSIONS);
    for seed in SEEDS {
        let s = Shifted::<Sobol<2>>::shift::<16>(seed);
        for k in [0u32, 5, 12345] {
            for dim in 0..16 {
                let want =
                    to_unit_f32(f64::from(Sobol::<1>::sample(k, dim, seed)) + s[dim as usize]);
                let got = sh.sample(u64::from(k), dim, seed).unwrap();
                assert_eq!(got.to_bits(), want.to_bits(), "k {k} dim {dim}");
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Errors, never panics

#[test]
fn out_of_range_index_and_dim_are_errors() {
    let seed = Seed(3);
    let range = |first: u64, n: u64| Some(PatternError::Range { first, len: 1, n });
    let dimension = |dim: u32, max: u32| Some(PatternError::Dimension { dim, max });

    let j = Jittered::new([3, 5]).unwrap();
    assert_eq!(j.point(15, seed).err(), range(15, 15));
    assert_eq!(j.point(u64::MAX, seed).err(), range(u64::MAX, 15));
    assert_eq!(j.sample(15, 0, seed).err(), range(15, 15));
    assert_eq!(j.sample(14, 2, seed).err(), dimension(2, 2));
    assert_eq!(j.sample(0, u32::MAX, seed).err(), dimension(u32::MAX, 2));

    let r = Random::<3>::new(4).unwrap();
    assert_eq!(r.sample(3, 3, seed).err(), dimension(3, 3));
    assert_eq!(r.point(4, seed).err(), range(4, 4));
    let cmj = CorrelatedMultiJittered::new(6).unwrap();
    assert_eq!(cmj.point(6, seed).err(), range(6, 6));
    assert_eq!(cmj.sample(0, 2, seed).err(), dimension(2, 2));
    let nr = NRooks::<1>::new(1).unwrap();
    assert_eq!(nr.sample(0, 1, seed).err(), dimension(1, 1));
    assert_eq!(nr.point(1, seed).err(), range(1, 1));

    let full = 1u64 << 32;
    let s = Sobol::<3>::new(4).unwrap();
    assert!(s.point(full - 1, seed).is_ok());
    assert_eq!(s.point(full, seed).err(), range(full, full));
    assert_eq!(s.point(u64::MAX, seed).err(), range(u64::MAX, full));
    assert_eq!(s.sample(full, 0, seed).err(), range(full, full));
    assert!(s.sample(0, 1023, seed).is_ok());
    assert_eq!(s.sample(0, 1024, seed).err(), dimension(1024, 1024));
    assert_eq!(s.sample(0, u32::MAX, seed).err(), dimension(u32::MAX, 1024));
    let h = Halton::<2>::new(4).unwrap();
    assert_eq!(h.point(full, seed).err(), range(full, full));
    assert_eq!(h.sample(0, 1024, seed).err(), dimension(1024, 1024));
    assert!(h.sample(full - 1, 1023, seed).is_ok());

    let sh = Sobol::<2>::new(4).unwrap().shifted();
    assert_eq!(sh.point(full, seed).err(), range(full, full));
    assert_eq!(sh.sample(1, 1024, seed).err(), dimension(1024, 1024));
    let shj = j.clone().shifted();
    assert_eq!(shj.point(15, seed).err(), range(15, 15));
    assert_eq!(shj.sample(0, 2, seed).err(), dimension(2, 2));
}

// ---------------------------------------------------------------------------
// Per-pixel decorrelation
//
// Statistical checks (tests/README.md rule, |z| ≤ 5, fixed seeds): Pearson's r
// of coordinate j of point k between two pixels (or two `dim`s, or two
// coordinates of one pixel), pooled over all pixels and all k, against 0.
//
// The standard error is clustered by pixel (pair): the N points of one pixel
// are not independent draws (they are stratified, a net, or share one shift),
// so Σ_k (a_k − ā)(b_k − b̄) need not have the variance of N independent
// products, and SE = 1/√n can be too small. For the shifted jittered sets all
// 64 points of a pixel move with one shift: points of nearby cells covary
// strongly, the same k' for every pixel, and the clustered SE is 3.5 times
// 1/√n (printed; r = 0.022 there would fail a 5/√n bound). For Sobol' the
// index scramble re-randomises which points covary in every pixel and the
// ratio is about 1.2. With S_p = Σ_k (a_k − ā)(b_k − b̄) the sum over cluster
// p, r = Σ_p S_p / √(S_aa·S_bb) and SE = √(Σ_p S_p²) / √(S_aa·S_bb); different
// clusters are independent under the null (different pixel seeds; overlapping
// neighbour pairs share one pixel but their products are uncorrelated).
// 18 checks in this file.

const W: u32 = 32;
const H: u32 = 32;
const BASE: Seed = Seed(0x5EED_0F91_7E15);

/// Pearson's r over all pairs of all clusters, its cluster-robust standard
/// error, and the naive `1/√n`.
fn clustered_pearson(clusters: &[Vec<(f64, f64)>]) -> (f64, f64, f64) {
    let n = clusters.iter().map(Vec::len).sum::<usize>() as f64;
    let (mut ma, mut mb) = (0.0, 0.0);
    for &(a, b) in clusters.iter().flatten() {
        ma += a / n;
        mb += b / n;
    }
    let (mut sab, mut saa, mut sbb, mut s2) = (0.0, 0.0, 0.0, 0.0);
    for c in clusters {
        let mut sp = 0.0;
        for &(a, b) in c {
            let (da, db) = (a - ma, b - mb);
            sp += da * db;
            saa += da * da;
            sbb += db * db;
        }
        sab += sp;
        s2 += sp * sp;
    }
    let norm = (saa * sbb).sqrt();
    (sab / norm, s2.sqrt() / norm, 1.0 / n.sqrt())
}

fn assert_uncorrelated(clusters: &[Vec<(f64, f64)>], what: &str) {
    let (r, se, naive) = clustered_pearson(clusters);
    let n: usize = clusters.iter().map(Vec::len).sum();
    println!(
        "{what}: r = {r:+.5}, z = {:+.2}, SE = {se:.5} (naive 1/√n = {naive:.5}, n = {n}, {} clusters)",
        r / se,
        clusters.len()
    );
    assert!(r.abs() <= 5.0 * se, "{what}: r = {r} > 5 SE = {}", 5.0 * se);
}

/// All points of every pixel in the `W × H` grid for pixel seeds
/// `seed_of(x, y)`: pixel `(x, y)` at `pts[y·W + x]`.
fn pixel_points<P: Sequence<2>>(
    seq: &P,
    n: u64,
    seed_of: impl Fn(u32, u32) -> Seed,
) -> Vec<Vec<[f32; 2]>> {
    let mut out = Vec::with_capacity((W * H) as usize);
    for y in 0..H {
        for x in 0..W {
            let s = seed_of(x, y);
            out.push((0..n).map(|k| seq.point(k, s).unwrap()).collect());
        }
    }
    out
}

/// One cluster per pixel `(x, y)` that has a neighbour `(x + dx, y + dy)`:
/// the pairs `(f(a_k[j]), f(b_k[j]))` over k.
fn neighbour_pairs(
    pts: &[Vec<[f32; 2]>],
    (dx, dy): (u32, u32),
    j: usize,
    f: fn(f32) -> f64,
) -> Vec<Vec<(f64, f64)>> {
    let mut clusters = Vec::new();
    for y in 0..H - dy {
        for x in 0..W - dx {
            let a = &pts[(y * W + x) as usize];
            let b = &pts[((y + dy) * W + x + dx) as usize];
            clusters.push(a.iter().zip(b).map(|(p, q)| (f(p[j]), f(q[j]))).collect());
        }
    }
    clusters
}

fn value(x: f32) -> f64 {
    f64::from(x)
}

/// Position inside an 8-stratum axis: `frac(8x)` (exact in `f32`).
fn in_stratum(x: f32) -> f64 {
    let t = f64::from(x) * 8.0;
    t - t.floor()
}

/// Horizontal and vertical neighbours (coordinates 0 and 1), two `dim`
/// arguments of one pixel, and coordinates 0 and 1 of one pixel: all
/// uncorrelated. Six checks.
fn check_decorrelation<P: Sequence<2>>(seq: &P, n: u64, f: fn(f32) -> f64, what: &str) {
    let d0 = pixel_points(seq, n, |x, y| pixel_seed(BASE, x, y, 0));
    let d1 = pixel_points(seq, n, |x, y| pixel_seed(BASE, x, y, 1));
    for j in 0..2 {
        let h = neighbour_pairs(&d0, (1, 0), j, f);
        assert_uncorrelated(
            &h,
            &format!("{what}: pixel (x, y) vs (x+1, y), coordinate {j}"),
        );
        let v = neighbour_pairs(&d0, (0, 1), j, f);
        assert_uncorrelated(
            &v,
            &format!("{what}: pixel (x, y) vs (x, y+1), coordinate {j}"),
        );
    }
    let dims: Vec<Vec<(f64, f64)>> = d0
        .iter()
        .zip(&d1)
        .map(|(a, b)| a.iter().zip(b).map(|(p, q)| (f(p[0]), f(q[0]))).collect())
        .collect();
    assert_uncorrelated(
        &dims,
        &format!("{what}: pixel_seed dim 0 vs dim 1, coordinate 0"),
    );
    let within: Vec<Vec<(f64, f64)>> = d0
        .iter()
        .map(|a| a.iter().map(|p| (f(p[0]), f(p[1]))).collect())
        .collect();
    assert_uncorrelated(
        &within,
        &format!("{what}: coordinates 0 and 1 of one pixel"),
    );
}

#[test]
fn neighbouring_pixels_are_uncorrelated_sobol() {
    // Owen-scrambled Sobol' N = 64 per pixel: each point is uniform, and the
    // scrambles of different pixels are independent.
    check_decorrelation(&Sobol::<2>::new(64).unwrap(), 64, value, "Sobol N=64");
}

#[test]
fn neighbouring_pixels_are_uncorrelated_jittered() {
    // Jittered 8×8: point k lies in the same cell in every pixel, so the raw
    // coordinates of neighbours are correlated by construction (r ≈ 63/64,
    // whatever the seeds). The random part is the position inside the cell,
    // frac(8x): that must be independent between pixels.
    let jit = Jittered::new([8, 8]).unwrap();
    check_decorrelation(&jit, 64, in_stratum, "Jittered 8x8, in-cell");
    // With the toroidal shift the raw coordinates are independent too.
    check_decorrelation(&jit.shifted(), 64, value, "Shifted Jittered 8x8");
}

#[test]
fn the_decorrelation_check_detects_shared_seeds() {
    // Power of the statistic: if pixel_seed ignored x, pixels (x, y) and
    // (x+1, y) would share their seed and their points: r = 1, z ≈ √992.
    let seq = Sobol::<2>::new(64).unwrap();
    let same = pixel_points(&seq, 64, |_, y| pixel_seed(BASE, 0, y, 0));
    let (r, se, _) = clustered_pearson(&neighbour_pairs(&same, (1, 0), 0, value));
    assert!(r > 0.999 && r > 20.0 * se, "r = {r}, SE = {se}");
    // The same for the in-cell jitter of Jittered.
    let jit = Jittered::new([8, 8]).unwrap();
    let same = pixel_points(&jit, 64, |_, y| pixel_seed(BASE, 0, y, 0));
    let (r, se, _) = clustered_pearson(&neighbour_pairs(&same, (1, 0), 1, in_stratum));
    assert!(r > 0.999 && r > 20.0 * se, "r = {r}, SE = {se}");
}

/// `sample_4d`/`sample_8d` equal `L` calls of `sample`, bit for bit, through
/// the trait and (for Sobol') the inherent SIMD functions, at every alignment
/// of `dim` and up to the last dimensions.
fn check_batches<const D: usize, S: Sequence<D> + ?Sized>(seq: &S, indices: &[u64], what: &str) {
    let top = seq.dimensions();
    let mut dims: Vec<u32> = (0..top.min(19)).collect();
    dims.extend([
        top.saturating_sub(9),
        top.saturating_sub(8),
        top.saturating_sub(4),
    ]);
    for seed in SEEDS {
        for &i in indices {
            for &d in &dims {
                let one = |l: u32| seq.sample(i, d + l, seed).map(f32::to_bits);
                let want4: Result<Vec<u32>, _> = (0..4).map(one).collect();
                let got4 = seq
                    .sample_4d(i, d, seed)
                    .map(|v| v.map(f32::to_bits).to_vec());
                assert_eq!(got4, want4, "{what}: sample_4d index {i} dim {d}");
                let want8: Result<Vec<u32>, _> = (0..8).map(one).collect();
                let got8 = seq
                    .sample_8d(i, d, seed)
                    .map(|v| v.map(f32::to_bits).to_vec());
                assert_eq!(got8, want8, "{what}: sample_8d index {i} dim {d}");
            }
        }
    }
}

#[test]
fn batch_random_access_equals_single_samples() {
    let mut idx: Vec<u64> = vec![0, 1, 2, 7, 8, 255, 0xDEAD_BEEF, u32::MAX as u64];
    let mut x = 0x1234_5678u32;
    for _ in 0..24 {
        x = x.wrapping_mul(0x9E37_79B9).wrapping_add(0x7F4A_7C15);
        idx.push(u64::from(x));
    }
    check_batches(&Sobol::<2>::new(64).unwrap(), &idx, "sobol");
    check_batches(&Halton::<2>::new(64).unwrap(), &idx, "halton");
    check_batches(
        &Sobol::<2>::new(64).unwrap().shifted(),
        &idx,
        "shifted sobol",
    );
    let small: Vec<u64> = vec![0, 1, 17, 63];
    check_batches(&Jittered::new([8, 8]).unwrap(), &small, "jittered");
    check_batches(&Random::<3>::new(64).unwrap(), &small, "random");
    let dynamic: &dyn Sequence<2> = &Sobol::<2>::new(8).unwrap();
    check_batches(dynamic, &idx[..4], "dyn sobol");
    // The inherent functions are the SIMD lanes the trait returns.
    for seed in SEEDS {
        for &i in &idx {
            for d in (0..=SOBOL_DIMENSIONS - 8).step_by(37).chain([1015, 1016]) {
                let want: [u32; 8] =
                    core::array::from_fn(|l| Sobol::sample(i as u32, d + l as u32, seed).to_bits());
                assert_eq!(Sobol::sample_8d(i as u32, d, seed).map(f32::to_bits), want);
                assert_eq!(
                    Sobol::sample_4d(i as u32, d + 4, seed).map(f32::to_bits),
                    want[4..]
                );
            }
        }
    }
}

#[test]
fn batch_random_access_errors_name_the_first_missing_dimension() {
    let sobol = Sobol::<2>::new(64).unwrap();
    let top = SOBOL_DIMENSIONS;
    assert!(sobol.sample_8d(5, top - 8, SEEDS[0]).is_ok());
    for (dim, first) in [(top - 7, top), (top, top), (u32::MAX - 3, u32::MAX - 3)] {
        let e = Err(PatternError::Dimension {
            dim: first,
            max: top,
        });
        assert_eq!(sobol.sample_8d(5, dim, SEEDS[0]), e, "dim {dim}");
    }
    assert_eq!(
        sobol.sample_4d(5, top - 3, SEEDS[0]),
        Err(PatternError::Dimension { dim: top, max: top })
    );
    assert_eq!(
        sobol.sample_4d(1 << 32, 0, SEEDS[0]),
        Err(PatternError::Range {
            first: 1 << 32,
            len: 1,
            n: 1 << 32
        })
    );
    let jit = Jittered::new([8, 8]).unwrap();
    assert_eq!(
        jit.sample_4d(3, 0, SEEDS[0]),
        Err(PatternError::Dimension { dim: 2, max: 2 })
    );
    assert_eq!(
        Halton::<2>::new(4)
            .unwrap()
            .sample_8d(0, HALTON_DIMENSIONS - 2, SEEDS[0]),
        Err(PatternError::Dimension {
            dim: HALTON_DIMENSIONS,
            max: HALTON_DIMENSIONS
        })
    );
}

#[test]
#[should_panic(expected = "must be below 1024")]
fn sobol_sample_8d_past_the_last_dimension_panics() {
    let _ = Sobol::sample_8d(0, SOBOL_DIMENSIONS - 7, SEEDS[0]);
}
