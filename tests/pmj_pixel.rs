//! PMJ02 and PMJ02BN by pixel (`Pmj02Tables`, `Pmj02Pixel`): nets in every
//! power-of-two prefix of every pixel and pair, `sample` = `point` bit for
//! bit, errors, buffer lengths, the PMJ02BN pixels as isometric images of
//! distinct sets (nearest-neighbour distances kept exactly, the variant
//! frequencies), decorrelation and uniformity of the PMJ02 pixels with fixed
//! tables, determinism.

use linesample::pattern::{
    Pmj02, Pmj02Pixel, Pmj02Tables, PMJ02BN_TRANSFORMS, PMJ02_MAX_POINTS, PMJ02_TABLES_MAX_SETS,
};
use linesample::sequence::Sequence;
use linesample::stats::{chi2_upper_quantile, RunningStats};
use linesample::{PatternError, Seed};

const ONES: u32 = (1 << 24) - 1;
const TOP: u32 = 1 << 23;

fn pmj(bn: bool, n: usize) -> Pmj02 {
    if bn {
        Pmj02::blue_noise(n).unwrap()
    } else {
        Pmj02::new(n).unwrap()
    }
}

fn tables(bn: bool, n: usize, sets: u32, seed: u64) -> Pmj02Tables<Vec<[u32; 2]>> {
    Pmj02Tables::new(pmj(bn, n), sets, Seed::new(seed)).unwrap()
}

/// The exact 24-bit integer of a coordinate; fails unless it is a multiple of
/// `2⁻²⁴` in `[0, 1)`.
fn int24(v: f32) -> u32 {
    assert!((0.0..1.0).contains(&v), "coordinate {v} outside [0, 1)");
    let t = f64::from(v) * 16_777_216.0;
    assert_eq!(t, t.floor(), "coordinate {v} is not a multiple of 2^-24");
    t as u32
}

/// The first `n` points of pair `pair` of a pixel, as 24-bit integers.
fn pair_points(px: &Pmj02Pixel<'_>, pair: u32, n: usize, seed: Seed) -> Vec<[u32; 2]> {
    (0..n as u64)
        .map(|i| px.sample_2d(i, pair, seed).unwrap().map(int24))
        .collect()
}

/// The first violated elementary interval of a power-of-two prefix, if any.
fn check_nets(p: &[[u32; 2]]) -> Result<(), String> {
    let mut k = 0;
    while 1usize << k <= p.len() {
        let n = 1usize << k;
        for a in 0..=k {
            let mut seen = vec![false; n];
            for (i, q) in p[..n].iter().enumerate() {
                let c = (((q[0] >> (24 - a)) << (k - a)) | (q[1] >> (24 - (k - a)))) as usize;
                if std::mem::replace(&mut seen[c], true) {
                    return Err(format!("prefix 2^{k}, shape {a}: point {i} shares a cell"));
                }
            }
        }
        k += 1;
    }
    Ok(())
}

/// The 32 isometries, written independently of the crate: swap (bit 0), then
/// XOR `x` and `y` with `0`, `2²³`, `2²⁴ − 1` or both (bits 1–2, 3–4).
fn iso(p: [u32; 2], t: u32) -> [u32; 2] {
    let m = [0, TOP, ONES, ONES ^ TOP];
    let q = if t & 1 == 1 { [p[1], p[0]] } else { p };
    [
        q[0] ^ m[(t as usize >> 1) & 3],
        q[1] ^ m[(t as usize >> 3) & 3],
    ]
}

fn torus_d2(a: [u32; 2], b: [u32; 2]) -> u64 {
    (0..2)
        .map(|j| {
            let d = a[j].wrapping_sub(b[j]) & ONES;
            let d = u64::from(d.min((1 << 24) - d));
            d * d
        })
        .sum()
}

/// Squared toroidal nearest-neighbour distances of the points, sorted.
fn nn_d2(p: &[[u32; 2]]) -> Vec<u64> {
    let mut d: Vec<u64> = (0..p.len())
        .map(|i| {
            (0..p.len())
                .filter(|&j| j != i)
                .map(|j| torus_d2(p[i], p[j]))
                .min()
                .unwrap_or(0)
        })
        .collect();
    d.sort_unstable();
    d
}

/// Mean nearest-neighbour distance in units of `1/√n` (from sorted d²).
fn mean_nn(d2: &[u64]) -> f64 {
    let n = d2.len() as f64;
    d2.iter()
        .map(|&d| (d as f64).sqrt() / 16_777_216.0)
        .sum::<f64>()
        / n
        * n.sqrt()
}

/// Every power-of-two prefix of every tested pixel and pair is a (0,k,2)-net,
/// exactly as f32, for both variants (pair 0 in table order, pairs ≥ 1
/// permuted within batches, far pixels, the last pair of PMJ02).
#[test]
fn every_prefix_of_every_pixel_and_pair_is_a_net() {
    let seed = Seed::new(11);
    for bn in [false, true] {
        let t = tables(bn, 1024, 4, 3);
        let pairs: &[u32] = if bn {
            &[0, 1, 2, 3]
        } else {
            &[0, 1, 2, 3, 4, 9, u32::MAX / 2 - 1]
        };
        for (x, y) in [(0, 0), (1, 0), (0, 1), (12_345, 678), (u32::MAX, u32::MAX)] {
            let px = t.pixel(x, y);
            for &p in pairs {
                let pts = pair_points(&px, p, 1024, seed);
                if let Err(e) = check_nets(&pts) {
                    panic!("bn {bn} pixel ({x}, {y}) pair {p}: {e}");
                }
            }
        }
    }
}

/// `sample`, `sample_2d`, `point`, `sample_4d`, `sample_8d` agree bit for
/// bit, and the dimension count is as documented.
#[test]
fn sample_equals_point_bit_for_bit() {
    for bn in [false, true] {
        let t = tables(bn, 256, 8, 4);
        assert_eq!(t.dimensions(), if bn { 16 } else { u32::MAX - 1 });
        for (x, y) in [(3, 4), (900, 2)] {
            let px = t.pixel(x, y);
            assert_eq!(px.position(), (x, y));
            assert_eq!(px.count(), 256);
            assert_eq!(px.dimensions(), t.dimensions());
            for seed in [Seed::new(0), Seed::new(99)] {
                for i in [0u64, 1, 2, 3, 17, 128, 255] {
                    let p = px.point(i, seed).unwrap();
                    assert_eq!(
                        p.map(f32::to_bits),
                        px.sample_2d(i, 0, seed).unwrap().map(f32::to_bits)
                    );
                    for pair in 0..8 {
                        let q = px.sample_2d(i, pair, seed).unwrap();
                        for c in 0..2 {
                            let s = px.sample(i, 2 * pair + c, seed).unwrap();
                            assert_eq!(s.to_bits(), q[c as usize].to_bits(), "i {i} pair {pair}");
                        }
                    }
                    let four = px.sample_4d(i, 6, seed).unwrap();
                    let eight = px.sample_8d(i, 8, seed).unwrap();
                    for (l, v) in four.iter().enumerate() {
                        let s = px.sample(i, 6 + l as u32, seed).unwrap();
                        assert_eq!(v.to_bits(), s.to_bits());
                    }
                    for (l, v) in eight.iter().enumerate() {
                        let s = px.sample(i, 8 + l as u32, seed).unwrap();
                        assert_eq!(v.to_bits(), s.to_bits());
                    }
                }
            }
        }
    }
    // The last pair of PMJ02 exists and is complete.
    let t = tables(false, 64, 1, 4);
    let px = t.pixel(1, 1);
    let last = px.sample_2d(5, u32::MAX / 2 - 1, Seed::new(1)).unwrap();
    assert_eq!(
        last[1].to_bits(),
        px.sample(5, u32::MAX - 2, Seed::new(1)).unwrap().to_bits()
    );
}

/// Bad indices and dimensions are errors (index first), never panics.
#[test]
fn access_errors() {
    let seed = Seed::new(1);
    for bn in [false, true] {
        let t = tables(bn, 64, 3, 5);
        let px = t.pixel(7, 7);
        let dims = px.dimensions();
        let range = PatternError::Range {
            first: 64,
            len: 1,
            n: 64,
        };
        assert_eq!(px.point(64, seed), Err(range));
        assert_eq!(px.sample(64, 0, seed), Err(range));
        assert_eq!(
            px.sample(u64::MAX, dims, seed),
            Err(PatternError::Range {
                first: u64::MAX,
                len: 1,
                n: 64
            })
        );
        assert_eq!(px.sample_2d(64, 0, seed), Err(range));
        assert_eq!(
            px.sample(63, dims, seed),
            Err(PatternError::Dimension {
                dim: dims,
                max: dims
            })
        );
        assert_eq!(
            px.sample(63, u32::MAX, seed),
            Err(PatternError::Dimension {
                dim: u32::MAX,
                max: dims
            })
        );
        assert!(px.sample(63, dims - 1, seed).is_ok());
        assert_eq!(
            px.sample_2d(0, dims / 2, seed),
            Err(PatternError::Dimension {
                dim: dims,
                max: dims
            })
        );
        assert!(px.sample_2d(0, dims / 2 - 1, seed).is_ok());
        assert_eq!(
            px.sample_4d(0, dims - 2, seed),
            Err(PatternError::Dimension {
                dim: dims,
                max: dims
            })
        );
    }
    assert_eq!(tables(true, 64, 3, 5).dimensions(), 6);
}

/// Constructor inputs are checked with the parameter named, the buffer
/// lengths are exactly the stated ones, and nothing is written on an error.
#[test]
fn constructor_errors_and_buffer_lengths() {
    let seed = Seed::new(2);
    let p = Pmj02::new(256).unwrap();
    let len = Pmj02Tables::table_len(p, 3).unwrap();
    assert_eq!(len, 768);
    assert_eq!(Pmj02Tables::scratch_len(p), p.scratch_len());
    assert_eq!(
        Pmj02Tables::table_len(Pmj02::new(100).unwrap(), 3),
        Err(PatternError::PowerOfTwo {
            name: "n",
            value: 100
        })
    );
    for sets in [0, PMJ02_TABLES_MAX_SETS + 1] {
        assert_eq!(
            Pmj02Tables::table_len(p, sets),
            Err(PatternError::Parameter {
                name: "sets",
                value: u64::from(sets),
                min: 1,
                max: u64::from(PMJ02_TABLES_MAX_SETS)
            })
        );
    }
    assert!(Pmj02Tables::table_len(p, PMJ02_TABLES_MAX_SETS).is_ok());
    for bn in [false, true] {
        let p = pmj(bn, 256);
        let need = Pmj02Tables::scratch_len(p);
        // Exactly the stated lengths work.
        let mut table = vec![[0u32; 2]; len];
        let mut scratch = vec![0u32; need];
        let t = Pmj02Tables::generate(p, 3, seed, &mut table, &mut scratch).unwrap();
        assert_eq!(
            (t.points(), t.sets(), t.is_blue_noise(), t.bytes()),
            (256, 3, bn, len * 8)
        );
        for bad in [len - 1, len + 1, 0] {
            let mut table = vec![[7u32; 2]; bad];
            assert_eq!(
                Pmj02Tables::generate(p, 3, seed, &mut table, &mut scratch).unwrap_err(),
                PatternError::Parameter {
                    name: "table",
                    value: bad as u64,
                    min: len as u64,
                    max: len as u64
                }
            );
            assert!(table.iter().all(|q| *q == [7, 7]));
        }
        let mut table = vec![[7u32; 2]; len];
        let mut short = vec![0u32; need - 1];
        assert_eq!(
            Pmj02Tables::generate(p, 3, seed, &mut table, &mut short).unwrap_err(),
            PatternError::Scratch {
                expected: need,
                got: need - 1
            }
        );
        assert!(table.iter().all(|q| *q == [7, 7]));
        let mut table = vec![[7u32; 2]; len];
        assert!(matches!(
            Pmj02Tables::generate(p, 0, seed, &mut table, &mut scratch),
            Err(PatternError::Parameter { name: "sets", .. })
        ));
        assert!(matches!(
            Pmj02Tables::new(pmj(bn, 96), 1, seed),
            Err(PatternError::PowerOfTwo {
                name: "n",
                value: 96
            })
        ));
    }
    // One point per set works (every pixel gets its set's point, transformed).
    let one = Pmj02Tables::new(Pmj02::new(1).unwrap(), 2, seed).unwrap();
    assert_eq!(one.pixel(4, 5).count(), 1);
    assert!(one.pixel(4, 5).point(0, seed).is_ok());
}

/// A stored table gives the same pixels; its shape and range are checked.
#[test]
fn from_table_round_trip_and_errors() {
    let t = tables(true, 128, 2, 8);
    let stored: Vec<[u32; 2]> = t.table().to_vec();
    let back = Pmj02Tables::from_table(&stored[..], 128, 2, true).unwrap();
    let seed = Seed::new(5);
    for i in 0..128 {
        for d in 0..4 {
            assert_eq!(
                t.pixel(9, 1).sample(i, d, seed).unwrap().to_bits(),
                back.pixel(9, 1).sample(i, d, seed).unwrap().to_bits()
            );
        }
    }
    assert_eq!(back.into_inner().as_ptr(), stored.as_ptr());
    assert_eq!(
        Pmj02Tables::from_table(&stored[..], 128, 3, true).unwrap_err(),
        PatternError::Parameter {
            name: "table",
            value: 256,
            min: 384,
            max: 384
        }
    );
    assert_eq!(
        Pmj02Tables::from_table(&stored[..], 0, 2, true).unwrap_err(),
        PatternError::ZeroPoints
    );
    assert_eq!(
        Pmj02Tables::from_table(&stored[..], PMJ02_MAX_POINTS as usize * 2, 2, true).unwrap_err(),
        PatternError::TooManyPoints {
            max: PMJ02_MAX_POINTS
        }
    );
    assert_eq!(
        Pmj02Tables::from_table(&stored[..], 96, 2, true).unwrap_err(),
        PatternError::PowerOfTwo {
            name: "n",
            value: 96
        }
    );
    let mut bad = stored.clone();
    bad[77][1] = 1 << 24;
    assert_eq!(
        Pmj02Tables::from_table(bad, 128, 2, false).unwrap_err(),
        PatternError::Parameter {
            name: "table",
            value: 1 << 24,
            min: 0,
            max: u64::from(ONES)
        }
    );
}

/// The variant `(set, isometry)` of a PMJ02BN pixel's pair, found from point
/// 0 (index 0 is never permuted); `None` if no variant maps to it.
fn variant(t: &Pmj02Tables<Vec<[u32; 2]>>, p0: [u32; 2]) -> Option<(u32, u32)> {
    let n = t.points() as usize;
    let mut found = None;
    for s in 0..t.sets() {
        for tr in 0..PMJ02BN_TRANSFORMS {
            if iso(t.table()[s as usize * n], tr) == p0 {
                assert!(found.is_none(), "point 0 matches two variants");
                found = Some((s, tr));
            }
        }
    }
    found
}

/// Every PMJ02BN pixel pair is the isometric image of one table set, its
/// power-of-two prefixes the images of the set's prefixes, so its
/// nearest-neighbour distances are the set's exactly; the pairs of one
/// pixel use distinct sets.
#[test]
fn blue_noise_pixels_are_isometric_images_of_distinct_sets() {
    let sets = 4;
    let t = tables(true, 1024, sets, 6);
    let seed = Seed::new(21);
    let n = 1024;
    for (x, y) in [(0, 0), (5, 9), (40_000, 3)] {
        let px = t.pixel(x, y);
        let mut used = Vec::new();
        for pair in 0..sets {
            let pts = pair_points(&px, pair, n, seed);
            let (s, tr) = variant(&t, pts[0]).expect("pair point 0 is a table point 0 moved");
            used.push(s);
            let src = &t.table()[s as usize * n..(s as usize + 1) * n];
            for k in [1, 4, 7, 10] {
                let m = 1usize << k;
                let mut a: Vec<[u32; 2]> = pts[..m].to_vec();
                let mut b: Vec<[u32; 2]> = src[..m].iter().map(|&q| iso(q, tr)).collect();
                a.sort_unstable();
                b.sort_unstable();
                assert_eq!(
                    a, b,
                    "pixel ({x}, {y}) pair {pair}: prefix 2^{k} is not T(set prefix)"
                );
                let (da, db) = (nn_d2(&pts[..m]), nn_d2(&src[..m]));
                assert_eq!(da, db, "prefix 2^{k}: nearest-neighbour distances differ");
                assert_eq!(mean_nn(&da), mean_nn(&db));
            }
            if pair == 0 {
                // Pair 0 keeps the table order exactly.
                assert!(pts.iter().zip(src).all(|(&a, &b)| a == iso(b, tr)));
            }
        }
        used.sort_unstable();
        used.dedup();
        assert_eq!(
            used.len(),
            sets as usize,
            "pixel ({x}, {y}): two pairs share a set"
        );
    }
}

/// All `32·sets` PMJ02BN variants occur, about equally often, and two
/// neighbouring pixels share their pair-0 variant with probability
/// `1/(32·sets)`, as documented.
#[test]
fn blue_noise_variants_are_uniform_and_collide_as_stated() {
    let sets = 4u32;
    let t = tables(true, 16, sets, 7);
    let seed = Seed::new(3);
    let v = (32 * sets) as usize;
    let (w, h) = (96u32, 64u32);
    let mut counts = vec![0u32; v];
    let mut grid = vec![(0u32, 0u32); (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let p0 = t.pixel(x, y).point(0, seed).unwrap().map(int24);
            let var = variant(&t, p0).unwrap();
            counts[(var.0 * 32 + var.1) as usize] += 1;
            grid[(y * w + x) as usize] = var;
        }
    }
    // chi^2 over the variants, against its standard error.
    let e = f64::from(w * h) / v as f64;
    let chi2: f64 = counts.iter().map(|&c| (f64::from(c) - e).powi(2) / e).sum();
    let dof = (v - 1) as f64;
    assert!(counts.iter().all(|&c| c > 0), "a variant never occurs");
    assert!(
        chi2 < chi2_upper_quantile(dof, 1e-6),
        "chi2 {chi2} for {dof} dof"
    );
    // Horizontal and vertical neighbours with the same variant.
    let mut pairs = 0u32;
    let mut same = 0u32;
    for y in 0..h {
        for x in 0..w {
            let a = grid[(y * w + x) as usize];
            if x + 1 < w {
                pairs += 1;
                same += u32::from(grid[(y * w + x + 1) as usize] == a);
            }
            if y + 1 < h {
                pairs += 1;
                same += u32::from(grid[((y + 1) * w + x) as usize] == a);
            }
        }
    }
    let p = 1.0 / v as f64;
    let mean = f64::from(pairs) * p;
    let sd = (f64::from(pairs) * p * (1.0 - p)).sqrt();
    assert!(
        (f64::from(same) - mean).abs() < 5.0 * sd,
        "{same} of {pairs} neighbour pairs share a variant, expected {mean:.1} ± {sd:.1}"
    );
}

/// Mean and variance over pixels of per-pixel estimates.
/// The running statistics of `v`.
fn stats(v: &[f64]) -> RunningStats {
    let mut s = RunningStats::new();
    v.iter().for_each(|&x| s.push(x));
    s
}

/// Mean and unbiased variance of `v`.
fn mean_var(v: &[f64]) -> (f64, f64) {
    let s = stats(v);
    (s.mean(), s.variance())
}

/// Standard error of the sample variance of `v`.
fn var_std_error(v: &[f64]) -> f64 {
    stats(v).variance_std_error()
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let (ma, va) = mean_var(a);
    let (mb, vb) = mean_var(b);
    let c = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - ma) * (y - mb))
        .sum::<f64>()
        / (a.len() as f64 - 1.0);
    c / (va * vb).sqrt()
}

/// Plain PMJ02 with one fixed table: across pixels (one image seed) the
/// estimates of an integrand that couples pairs 0 and 1 are unbiased with
/// the variance of independent pairs (index-aligned pairs would give 75× it),
/// neighbouring pixels and the pairs of one pixel are uncorrelated, and the
/// coordinates of one sample index are uniform across pixels.
#[test]
fn plain_pixels_and_pairs_are_decorrelated_and_uniform() {
    let n = 256usize;
    let t = tables(false, n, 4, 9);
    let seed = Seed::new(17);
    let (w, h) = (33u32, 16u32);
    let bins = 16usize;
    let mut bilinear = Vec::new(); // 12 (u0 - 1/2)(u2 - 1/2): mean 0, variance 1
    let mut quadrant = Vec::new(); // 1[u0 < 1/2] 1[u2 < 1/2]: mean 1/4, variance 3/16
    let mut tri0 = vec![0.0; (w * h) as usize]; // 1[u0 + u1 < 1], pair 0
    let mut tri1 = vec![0.0; (w * h) as usize]; // the same of pair 1
    let mut hist = vec![[0u32; 16]; 4]; // dimensions 0..4 of sample 5
    for y in 0..h {
        for x in 0..w {
            let px = t.pixel(x, y);
            let (mut b, mut q, mut r0, mut r1) = (0.0, 0.0, 0.0, 0.0);
            for i in 0..n as u64 {
                let [u0, u1] = px.sample_2d(i, 0, seed).unwrap().map(f64::from);
                let [u2, u3] = px.sample_2d(i, 1, seed).unwrap().map(f64::from);
                b += 12.0 * (u0 - 0.5) * (u2 - 0.5);
                q += f64::from(u8::from(u0 < 0.5 && u2 < 0.5));
                r0 += f64::from(u8::from(u0 + u1 < 1.0));
                r1 += f64::from(u8::from(u2 + u3 < 1.0));
            }
            let k = (y * w + x) as usize;
            bilinear.push(b / n as f64);
            quadrant.push(q / n as f64);
            tri0[k] = r0 / n as f64;
            tri1[k] = r1 / n as f64;
            for (d, hd) in hist.iter_mut().enumerate() {
                let u = px.sample(5, d as u32, seed).unwrap();
                hd[(u * bins as f32) as usize] += 1;
            }
        }
    }
    let p = bilinear.len() as f64;
    let nf = n as f64;
    let (m, v) = mean_var(&bilinear);
    assert!(
        m.abs() < 5.0 * (v / p).sqrt(),
        "bilinear: mean {m}, sd {}",
        (v / p).sqrt()
    );
    // var·n: 1 for a random pairing of the two pairs' points (index-aligned
    // pairs give 73), within 5 standard errors of the sample variance.
    let se = var_std_error(&bilinear);
    assert!(
        (v * nf - 1.0).abs() < 5.0 * se * nf,
        "bilinear: var·n = {} ± {}",
        v * nf,
        se * nf
    );
    let (m, v) = mean_var(&quadrant);
    assert!(
        (m - 0.25).abs() < 5.0 * (v / p).sqrt(),
        "quadrant: mean {m}"
    );
    // Below independent random points' 3/16 (the stratification gain) by
    // more than 5 standard errors (one-sided; index-aligned pairs give 8).
    let se = var_std_error(&quadrant);
    assert!(
        v * nf < 3.0 / 16.0 - 5.0 * se * nf,
        "quadrant: var·n = {} ± {} (independent points 0.1875)",
        v * nf,
        se * nf
    );
    // Neighbours (x, y), (x + 1, y) and the two pairs of one pixel.
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w - 1 {
            a.push(tri0[(y * w + x) as usize]);
            b.push(tri0[(y * w + x + 1) as usize]);
        }
    }
    // Under independence r·√n is nearly standard normal: |z| ≤ 5.
    let tol = 5.0 / (a.len() as f64).sqrt();
    let r = correlation(&a, &b);
    assert!(r.abs() < tol, "neighbour correlation {r} (tolerance {tol})");
    let r = correlation(&tri0, &tri1);
    assert!(r.abs() < 5.0 / p.sqrt(), "pair 0 / pair 1 correlation {r}");
    // Coordinates of one sample index across pixels: uniform.
    let e = p / bins as f64;
    let dof = (bins - 1) as f64;
    for (d, hd) in hist.iter().enumerate() {
        let chi2: f64 = hd.iter().map(|&c| (f64::from(c) - e).powi(2) / e).sum();
        assert!(
            chi2 < chi2_upper_quantile(dof, 1e-6),
            "dim {d}: chi2 {chi2}"
        );
    }
}

/// Same seeds, same bits; another image seed or table seed, other bits.
#[test]
fn determinism() {
    for bn in [false, true] {
        let a = tables(bn, 256, 2, 12);
        let b = tables(bn, 256, 2, 12);
        assert_eq!(a, b);
        let c = tables(bn, 256, 2, 13);
        assert_ne!(a.table(), c.table());
        // generate into a caller buffer = new.
        let p = pmj(bn, 256);
        let mut table = vec![[0u32; 2]; Pmj02Tables::table_len(p, 2).unwrap()];
        let mut scratch = vec![u32::MAX; Pmj02Tables::scratch_len(p)];
        Pmj02Tables::generate(p, 2, Seed::new(12), &mut table, &mut scratch).unwrap();
        assert_eq!(&table[..], a.table());
        let s = Seed::new(4);
        let get = |t: &Pmj02Tables<Vec<[u32; 2]>>, seed: Seed| -> Vec<u32> {
            (0..256)
                .flat_map(|i| (0..4).map(move |d| (i, d)))
                .map(|(i, d)| t.pixel(2, 3).sample(i, d, seed).unwrap().to_bits())
                .collect()
        };
        assert_eq!(get(&a, s), get(&b, s));
        assert_ne!(get(&a, s), get(&a, Seed::new(5)));
        assert_ne!(get(&a, s), get(&c, s));
        // The sets are different realisations.
        assert_ne!(a.table()[..256], a.table()[256..]);
    }
}
