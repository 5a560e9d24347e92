//! The direct periodogram against independent references: a naive per-pair
//! double loop, closed-form expected spectra (white noise, jitter), the line
//! identity, and the accumulator algebra (chunking, SIMD vs scalar, merge).
#![allow(clippy::needless_range_loop)]

use linesample::geom::Direction;
use linesample::num::{frac_centered, sinc_dd};
use linesample::num::{two_prod, two_sum, Dd};
use linesample::pattern::{Jittered, Pattern, Random};
use linesample::primitive::Segment;
use linesample::spectrum::{
    jittered_expected, line_offsets, line_spectrum, Dft, Grid, Periodogram,
};
use linesample::stats::RunningStats;
use linesample::{Pcg32, Seed, SpectrumError};

fn uniform(rng: &mut Pcg32) -> f64 {
    let hi = u64::from(rng.next_u32()) << 21;
    let lo = u64::from(rng.next_u32()) >> 11;
    ((hi | lo) as f64) * (1.0 / (1u64 << 53) as f64)
}

fn random_points<const D: usize>(n: usize, seed: u64) -> Vec<[f64; D]> {
    let mut rng = Pcg32::new(seed, 11);
    (0..n)
        .map(|_| core::array::from_fn(|_| uniform(&mut rng)))
        .collect()
}

/// `ν·x mod 1` from exact per-axis products summed in double-double.
fn phase(j: &[i32], x: &[f64]) -> f64 {
    let mut acc = Dd::new(0.0);
    for (a, &ja) in j.iter().enumerate() {
        let (p, e) = two_prod(f64::from(ja), x[a]);
        let r = Dd { hi: p, lo: e };
        let f = frac_centered(r);
        let (s, e2) = two_sum(acc.hi, f);
        acc = Dd {
            hi: s,
            lo: acc.lo + e2,
        };
    }
    frac_centered(acc)
}

/// Naive `Σ_k w_k e^{−2πiν·x_k}`: one `sin`/`cos` per (sample, frequency).
fn naive(j: &[i32], xs: &[Vec<f64>], w: impl Fn(usize) -> f64) -> (f64, f64) {
    let (mut re, mut im) = (0.0, 0.0);
    for (k, x) in xs.iter().enumerate() {
        let t = core::f64::consts::TAU * phase(j, x);
        re += w(k) * t.cos();
        im -= w(k) * t.sin();
    }
    (re, im)
}

fn scratch_points<const D: usize>(g: Grid<D>, chunk: usize) -> Vec<f64> {
    vec![0.0; chunk * Dft::<D, Vec<f64>>::points_scratch_per_sample(g)]
}

fn scratch_segments<const D: usize>(g: Grid<D>, chunk: usize) -> Vec<f64> {
    vec![0.0; chunk * Dft::<D, Vec<f64>>::segments_scratch_per_sample(g)]
}

fn max_err_vs_naive<const D: usize>(pts: &[[f64; D]], k: usize) -> f64 {
    let g = Grid::<D>::new(k).unwrap();
    let mut dft = Dft::new_vec(g);
    dft.add_points(pts, &mut scratch_points(g, 37)).unwrap();
    let xs: Vec<Vec<f64>> = pts.iter().map(|p| p.to_vec()).collect();
    let mut worst: f64 = 0.0;
    for i in 0..g.len() {
        let j = g.freq(i);
        let (re, im) = naive(&j, &xs, |_| 1.0);
        let f = dft.amplitude_at(i);
        worst = worst.max((f.re - re).abs()).max((f.im - im).abs());
    }
    worst / pts.len() as f64
}

#[test]
fn direct_matches_naive_double_loop() {
    // Low and moderate frequencies in 2D and 3D, including hard coordinates.
    let mut pts: Vec<[f64; 2]> = random_points(61, 1);
    pts.extend([
        [0.0, 0.0],
        [1.0 - f64::EPSILON / 2.0, 0.5],
        [0.25, 0.75],
        [-3.2, 1e3 + 0.1],
    ]);
    let e2 = max_err_vs_naive(&pts, 40);
    let e3 = max_err_vs_naive(&random_points::<3>(23, 2), 9);
    // 1D up to |ν| = 10⁴, and 2D with |ν_a| up to 10⁴ on a thin grid slice.
    let e1 = max_err_vs_naive(&random_points::<1>(40, 3), 10_000);
    println!("max |F − F_naive|/N: 2D {e2:.2e}, 3D {e3:.2e}, 1D to 10⁴ {e1:.2e}");
    assert!(e2 < 1e-15 && e3 < 1e-15, "{e2} {e3}");
    assert!(e1 < 1e-14, "{e1}");
}

#[test]
fn high_frequencies_in_2d_stay_exact() {
    // k = 700 puts |ν| up to ~990; check the periodogram P = |F/N|² at the
    // top corner cells and along the axes.
    let pts: Vec<[f64; 2]> = random_points(17, 4);
    let g = Grid::<2>::new(700).unwrap();
    let mut dft = Dft::new_vec(g);
    dft.add_points(&pts, &mut scratch_points(g, 5)).unwrap();
    let xs: Vec<Vec<f64>> = pts.iter().map(|p| p.to_vec()).collect();
    let n = pts.len() as f64;
    let mut worst: f64 = 0.0;
    for j in [
        [700, 700],
        [700, -700],
        [1, -699],
        [0, 700],
        [613, 1],
        [700, 0],
    ] {
        let (re, im) = naive(&j, &xs, |_| 1.0);
        let f = dft.amplitude(j).unwrap();
        let p_ref = (re * re + im * im) / (n * n);
        worst = worst.max((f.norm_sqr() / (n * n) - p_ref).abs());
    }
    assert!(worst < 1e-14, "{worst}");
}

#[test]
fn simd_scalar_and_chunking_agree_bit_for_bit() {
    fn check<const D: usize>(k: usize, n: usize) {
        let pts: Vec<[f64; D]> = random_points(n, 5 + D as u64);
        let g = Grid::<D>::new(k).unwrap();
        let mut a = Dft::new_vec(g);
        a.add_points(&pts, &mut scratch_points(g, n)).unwrap();
        let mut b = Dft::new_vec(g);
        b.add_points_scalar(&pts, &mut scratch_points(g, 3))
            .unwrap();
        let mut c = Dft::new_vec(g);
        for part in pts.chunks(7) {
            c.add_points(part, &mut scratch_points(g, 1)).unwrap();
        }
        for i in 0..g.len() {
            let (x, y, z) = (a.amplitude_at(i), b.amplitude_at(i), c.amplitude_at(i));
            assert_eq!(
                (x.re.to_bits(), x.im.to_bits()),
                (y.re.to_bits(), y.im.to_bits())
            );
            assert_eq!(
                (x.re.to_bits(), x.im.to_bits()),
                (z.re.to_bits(), z.im.to_bits())
            );
        }
        // Segments too, with per-sample directions and lengths.
        let segs: Vec<Segment<D>> = pts
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mut v = [0.0; D];
                for (a, x) in v.iter_mut().enumerate() {
                    *x = ((i * 7 + a * 3) % 5) as f64 - 1.9;
                }
                Segment::new(*p, Direction::new(v).unwrap(), 0.01 + (i % 9) as f64 * 0.13).unwrap()
            })
            .collect();
        let mut s1 = Dft::new_vec(g);
        s1.add_segments(&segs, &mut scratch_segments(g, 4)).unwrap();
        let mut s2 = Dft::new_vec(g);
        s2.add_segments_scalar(&segs, &mut scratch_segments(g, n))
            .unwrap();
        for i in 0..g.len() {
            let (x, y) = (s1.amplitude_at(i), s2.amplitude_at(i));
            assert_eq!(
                (x.re.to_bits(), x.im.to_bits()),
                (y.re.to_bits(), y.im.to_bits())
            );
        }
    }
    check::<1>(21, 50);
    // 1D grids of more than 64 frequencies are stored as rows of 64 (k + 1 =
    // 65, 128 and 301: one extra cell, full rows, a partial last row).
    check::<1>(64, 23);
    check::<1>(127, 19);
    check::<1>(300, 50);
    check::<2>(13, 41);
    check::<3>(5, 29);
}

#[test]
fn segments_match_naive_weighted_sum() {
    fn check<const D: usize>(k: usize, n: usize) -> f64 {
        let pts: Vec<[f64; D]> = random_points(n, 30 + D as u64);
        let mut rng = Pcg32::new(99, 1);
        let segs: Vec<Segment<D>> = pts
            .iter()
            .map(|p| {
                let v: [f64; D] = core::array::from_fn(|_| uniform(&mut rng) - 0.5);
                let len = [0.0, 1e-9, 0.03, 0.4, 1.0, 2.7][(rng.next_u32() % 6) as usize];
                Segment::new(*p, Direction::new(v).unwrap(), len).unwrap()
            })
            .collect();
        let g = Grid::<D>::new(k).unwrap();
        let mut dft = Dft::new_vec(g);
        dft.add_segments(&segs, &mut scratch_segments(g, 16))
            .unwrap();
        let xs: Vec<Vec<f64>> = segs.iter().map(|s| s.centre().to_vec()).collect();
        let mut worst: f64 = 0.0;
        for i in 0..g.len() {
            let j = g.freq(i);
            // The kernel's definition: y_a = fl(λω_a/2), weight sinc(2 Σ j_a y_a).
            let (re, im) = naive(&j, &xs, |s| {
                let seg = &segs[s];
                let mut t = Dd::new(0.0);
                for a in 0..D {
                    let y = 0.5 * seg.length() * seg.dir().get()[a];
                    let (p, e) = two_prod(2.0 * f64::from(j[a]), y);
                    t = t.add(Dd { hi: p, lo: e });
                }
                sinc_dd(t)
            });
            let f = dft.amplitude_at(i);
            worst = worst.max((f.re - re).abs()).max((f.im - im).abs());
        }
        worst / n as f64
    }
    // 1D at k = 60 (one storage row) and k = 700 (rows of 64 frequencies).
    let e = [
        check::<1>(60, 30),
        check::<1>(700, 30),
        check::<2>(17, 30),
        check::<3>(5, 20),
    ];
    println!(
        "segments: max |F − F_naive|/N = {:.2e} (1D k = 60), {:.2e} (1D k = 700), {:.2e} (2D), {:.2e} (3D)",
        e[0], e[1], e[2], e[3]
    );
    for x in e {
        assert!(x < 1e-14, "{x}");
    }
}

#[test]
fn unit_axis_segment_is_exactly_the_line_spectrum() {
    fn check<const D: usize, const K: usize>(k: usize) -> f64 {
        let mut worst: f64 = 0.0;
        let centres: Vec<[f32; D]> = Random::<D>::new(97).unwrap().to_vec(Seed::new(3)).unwrap();
        let g = Grid::<D>::new(k).unwrap();
        for axis in 0..D {
            let mut seg = Dft::new_vec(g);
            seg.add_segment_pattern(
                &centres,
                &Direction::axis(axis).unwrap(),
                1.0,
                &mut scratch_segments(g, 10),
            )
            .unwrap();
            let mut p_seg = Periodogram::new_vec(g);
            p_seg.add(&seg).unwrap();
            let mut offs = vec![[0.0f32; K]; centres.len()];
            line_offsets(&centres, axis, &mut offs).unwrap();
            let gk = Grid::<K>::new(k).unwrap();
            let mut line = Dft::new_vec(gk);
            line.add_points(&offs, &mut scratch_points(gk, 10)).unwrap();
            let mut p_line = Periodogram::new_vec(gk);
            p_line.add(&line).unwrap();
            for i in 0..g.len() {
                let j = g.freq(i);
                let want = line_spectrum::<D, K, _>(&p_line, axis, j).unwrap();
                let got = p_seg.mean_at(i);
                if j[axis] != 0 {
                    // sinc(j_axis) is exactly 0 off the hyperplane.
                    assert_eq!(got, 0.0, "axis {axis} j {j:?}");
                } else if D == 2 {
                    // Same phase tables and the same fused chain: bit for bit.
                    assert_eq!(got.to_bits(), want.to_bits(), "axis {axis} j {j:?}");
                } else {
                    // In 3D the row phasor is a rounded product of two axes,
                    // grouped differently from the 2D offsets' accumulation.
                    worst = worst.max((got - want).abs() / want.max(1.0));
                }
            }
        }
        worst
    }
    assert_eq!(check::<2, 1>(11), 0.0);
    let w3 = check::<3, 2>(4);
    println!("3D unit axis segments vs lines: max relative difference {w3:.1e}");
    assert!(w3 < 1e-14, "{w3}");
}

#[test]
fn merge_equals_one_accumulator_fed_everything() {
    let g = Grid::<2>::new(9).unwrap();
    let pat = Random::<2>::new(50).unwrap();
    let mut all = Periodogram::new_vec(g);
    let mut parts = [
        Periodogram::new_vec(g),
        Periodogram::new_vec(g),
        Periodogram::new_vec(g),
    ];
    let mut dft = Dft::new_vec(g);
    let mut scratch = scratch_points(g, 16);
    for r in 0..23u64 {
        let pts = pat.to_vec(Seed::new(8).realization(r)).unwrap();
        dft.clear();
        // Each realisation fed in two chunks.
        dft.add_points(&pts[..20], &mut scratch).unwrap();
        dft.add_points(&pts[20..], &mut scratch).unwrap();
        all.add(&dft).unwrap();
        parts[(r % 3) as usize].add(&dft).unwrap();
    }
    let mut merged = Periodogram::new_vec(g);
    for p in &parts {
        merged.merge(p).unwrap();
    }
    assert_eq!(merged.realisations(), all.realisations());
    for i in 0..g.len() {
        assert_eq!(
            merged.mean_at(i).to_bits(),
            all.mean_at(i).to_bits(),
            "cell {i}"
        );
    }
}

/// Per-ring means of `N·P` with standard errors from independent realisations.
fn ring_stats<const D: usize>(
    g: Grid<D>,
    realisations: u64,
    mut fill: impl FnMut(u64, &mut Dft<D, Vec<f64>>),
) -> (Vec<RunningStats>, Periodogram<D, Vec<f64>>) {
    let k = g.half_width();
    let mut stats = vec![RunningStats::default(); k + 1];
    let mut per = Periodogram::new_vec(g);
    let mut dft = Dft::new_vec(g);
    let (mut mean, mut count) = (vec![0.0; k + 1], vec![0u64; k + 1]);
    for r in 0..realisations {
        dft.clear();
        fill(r, &mut dft);
        dft.radial_power(&mut mean, &mut count).unwrap();
        for (s, &m) in stats.iter_mut().zip(&mean) {
            s.push(m);
        }
        per.add(&dft).unwrap();
    }
    (stats, per)
}

#[test]
fn white_noise_has_unit_expected_spectrum() {
    for d in [1usize, 2, 3] {
        let worst = match d {
            1 => white::<1>(60, 64, 400),
            2 => white::<2>(12, 64, 300),
            _ => white::<3>(5, 64, 200),
        };
        println!("random {d}D: max |ring mean − 1|/SE = {worst:.2}");
        assert!(worst < 4.0, "{d}D: {worst}");
    }
    fn white<const D: usize>(k: usize, n: usize, reals: u64) -> f64 {
        let g = Grid::<D>::new(k).unwrap();
        let pat = Random::<D>::new(n).unwrap();
        let mut scratch = scratch_points(g, 64);
        let (stats, per) = ring_stats(g, reals, |r, dft| {
            let pts = pat.to_vec(Seed::new(21).realization(r)).unwrap();
            dft.add_points(&pts, &mut scratch).unwrap();
        });
        // Every cell mean is an average of `reals` draws of mean 1; the grand
        // mean over all ν ≠ 0 as well.
        let mut worst: f64 = 0.0;
        for s in &stats[1..] {
            worst = worst.max((s.mean() - 1.0).abs() / s.mean_std_error());
        }
        assert_eq!(per.mean([0; D]).unwrap(), n as f64);
        worst
    }
}

#[test]
fn jittered_matches_closed_form_expected_spectrum() {
    // 2D: 8×8 strata, 3D: 4×4×4, rings compared with the ring average of
    // 1 − Π sinc²(ν_a/n_a) over the same cells.
    fn check<const D: usize>(strata: [usize; D], k: usize, reals: u64) -> f64 {
        let g = Grid::<D>::new(k).unwrap();
        let pat = Jittered::new(strata).unwrap();
        let mut scratch = scratch_points(g, 64);
        let (stats, per) = ring_stats(g, reals, |r, dft| {
            let pts = pat.to_vec(Seed::new(5).realization(r)).unwrap();
            dft.add_points(&pts, &mut scratch).unwrap();
        });
        let mut expect = vec![0.0; k + 1];
        let mut count = vec![0u64; k + 1];
        g.ring_counts(&mut count).unwrap();
        for i in 0..g.len() {
            if let Some(r) = g.ring(i) {
                let j = g.freq(i);
                if r > 0 {
                    expect[r] += f64::from(g.multiplicity(i)) * jittered_expected(strata, j);
                }
            }
        }
        let mut worst: f64 = 0.0;
        for r in 1..=k {
            let e = expect[r] / count[r] as f64;
            let z = (stats[r].mean() - e) / stats[r].mean_std_error();
            worst = worst.max(z.abs());
        }
        // A low-frequency cell where the spectrum is tiny: relative check.
        let mut j = [0i32; D];
        j[D - 1] = 1;
        let (m, e) = (per.mean(j).unwrap(), jittered_expected(strata, j));
        assert!((m - e).abs() < 0.25 * e, "cell {j:?}: {m} vs {e}");
        worst
    }
    let w2 = check::<2>([8, 8], 24, 400);
    let w3 = check::<3>([4, 4, 4], 8, 300);
    println!("jittered: max ring |z| 2D {w2:.2}, 3D {w3:.2}");
    assert!(w2 < 4.0 && w3 < 4.0);
}

#[test]
fn bad_input_is_rejected_without_side_effects() {
    let g = Grid::<2>::new(4).unwrap();
    let mut dft = Dft::new_vec(g);
    let mut scratch = scratch_points(g, 4);
    dft.add_points(&[[0.1, 0.2]], &mut scratch).unwrap();
    let before: Vec<_> = (0..g.len()).map(|i| dft.amplitude_at(i)).collect();
    let err = dft
        .add_points(&[[0.1, 0.2], [f64::NAN, 0.0]], &mut scratch)
        .unwrap_err();
    assert_eq!(
        err,
        SpectrumError::NonFinite {
            name: "points",
            index: 1
        }
    );
    assert!(err.to_string().contains("points[1]"));
    let err = dft
        .add_points(&[[0.1f32, f32::INFINITY]], &mut scratch)
        .unwrap_err();
    assert!(matches!(err, SpectrumError::NonFinite { .. }));
    let err = dft.add_points(&[[0.1, 0.2]], &mut [0.0; 3]).unwrap_err();
    assert!(matches!(
        err,
        SpectrumError::Length {
            name: "scratch",
            ..
        }
    ));
    assert_eq!(dft.count(), 1);
    for (i, b) in before.iter().enumerate() {
        assert_eq!(*b, dft.amplitude_at(i));
    }
    let err = dft
        .add_segment_pattern(
            &[[0.1, 0.2]],
            &Direction::axis(0).unwrap(),
            f64::NAN,
            &mut scratch_segments(g, 1),
        )
        .unwrap_err();
    assert!(err.to_string().contains("length"), "{err}");
    let mut p = Periodogram::new_vec(Grid::<2>::new(5).unwrap());
    assert!(matches!(
        p.add(&dft),
        Err(SpectrumError::GridMismatch { left: 5, right: 4 })
    ));
    let empty = Dft::new_vec(Grid::<2>::new(5).unwrap());
    assert_eq!(p.add(&empty), Err(SpectrumError::Empty));
    assert!(p.add_amplitudes(&[0.0; 3], &[0.0; 3], 1).is_err());
    let n = p.grid().len();
    let mut re = vec![0.0; n];
    re[2] = f64::NAN;
    assert!(matches!(
        p.add_amplitudes(&re, &vec![0.0; n], 4),
        Err(SpectrumError::NonFinite {
            name: "amplitudes",
            index: 2
        })
    ));
    assert_eq!(p.realisations(), 0);
    assert!(Dft::new(g, vec![0.0; 3]).is_err());
}

#[test]
fn caller_buffers_work_without_alloc_conveniences() {
    let g = Grid::<2>::new(6).unwrap();
    let mut buf = vec![0.0; Dft::<2, &mut [f64]>::buffer_len(g)];
    let mut pbuf = vec![0.0; Periodogram::<2, &mut [f64]>::buffer_len(g)];
    let mut dft = Dft::new(g, &mut buf[..]).unwrap();
    let mut per = Periodogram::new(g, &mut pbuf[..]).unwrap();
    let mut scratch = scratch_points(g, 8);
    dft.add_points(&[[0.25f32, 0.5], [0.75, 0.0]], &mut scratch)
        .unwrap();
    per.add(&dft).unwrap();
    // Two points at distance (1/2, 1/2): N·P = |1 + e^{−iπ(j0+j1)}|²/2.
    for i in 0..g.len() {
        let j = g.freq(i);
        let want = if (j[0] + j[1]).rem_euclid(2) == 0 {
            2.0
        } else {
            0.0
        };
        assert!((per.mean_at(i) - want).abs() < 1e-14, "{j:?}");
    }
    let mut out = vec![0.0; 7];
    assert_eq!(per.slice([1, 1], &mut out).unwrap(), 7);
    assert_eq!(out[1], 2.0_f64.min(out[1].max(2.0 - 1e-14)));
}

#[test]
fn coordinates_far_outside_the_torus_are_reduced_exactly() {
    // Found by the spectrum fuzz target: j·x overflowed for x ~ 1e308.
    let g = Grid::<2>::new(7).unwrap();
    let mut a = Dft::new_vec(g);
    let mut b = Dft::new_vec(g);
    let mut s = scratch_points(g, 4);
    a.add_points(&[[1e308, -3.75], [2.0f64.powi(60) + 4096.0, 0.125]], &mut s)
        .unwrap();
    b.add_points(&[[0.0, 0.25], [0.0, 0.125]], &mut s).unwrap();
    for i in 0..g.len() {
        assert_eq!(a.amplitude_at(i), b.amplitude_at(i), "{:?}", g.freq(i));
    }
}

mod properties {
    use super::*;
    use proptest::prelude::*;

    fn pts2() -> impl Strategy<Value = Vec<[f64; 2]>> {
        prop::collection::vec(prop::array::uniform2(-2.0f64..3.0), 1..40)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// |F|² is invariant under a toroidal shift (F only gains the phase
        /// e^{−2πiν·s}) and under reordering the samples, up to rounding.
        #[test]
        fn periodogram_is_shift_and_order_invariant(
            pts in pts2(),
            s in prop::array::uniform2(-1.0f64..1.0),
            k in 1usize..12,
            chunk in 1usize..9,
        ) {
            let g = Grid::<2>::new(k).unwrap();
            let n = pts.len() as f64;
            let mut sc = scratch_points(g, chunk);
            let power = |p: &[[f64; 2]], sc: &mut Vec<f64>| {
                let mut d = Dft::new_vec(g);
                d.add_points(p, sc).unwrap();
                let mut out = vec![0.0; g.len()];
                d.power(&mut out).unwrap();
                out
            };
            let base = power(&pts, &mut sc);
            let shifted: Vec<[f64; 2]> = pts.iter().map(|p| [p[0] + s[0], p[1] + s[1]]).collect();
            let mut reversed = pts.clone();
            reversed.reverse();
            for other in [power(&shifted, &mut sc), power(&reversed, &mut sc)] {
                for (a, b) in base.iter().zip(&other) {
                    prop_assert!((a - b).abs() <= 1e-13 * n, "{a} vs {b}");
                }
            }
            // DC is N exactly; N·P ≤ N everywhere.
            prop_assert_eq!(base[g.index([0, 0]).unwrap().0], n);
            prop_assert!(base.iter().all(|&v| v <= n * (1.0 + 1e-12)));
        }

        /// A segment of length 0 is a point; SIMD and scalar segment paths agree.
        #[test]
        fn zero_length_segments_are_points(
            pts in pts2(),
            d in prop::array::uniform2(-1.0f64..1.0),
            k in 1usize..10,
        ) {
            prop_assume!(d[0].abs() + d[1].abs() > 1e-6);
            let g = Grid::<2>::new(k).unwrap();
            let dir = Direction::new(d).unwrap();
            let mut a = Dft::new_vec(g);
            a.add_points(&pts, &mut scratch_points(g, 7)).unwrap();
            let mut b = Dft::new_vec(g);
            b.add_segment_pattern(&pts, &dir, 0.0, &mut scratch_segments(g, 5)).unwrap();
            for i in 0..g.len() {
                prop_assert_eq!(a.amplitude_at(i), b.amplitude_at(i));
            }
        }
    }
}

#[test]
fn issue_case_n4096_on_the_639_grid_matches_the_naive_loop() {
    // The benchmark case (N = 4096 uniform points, k = 319): every corner and
    // axis end plus 300 random cells against the naive double loop.
    let pts: Vec<[f64; 2]> = random_points(4096, 77);
    let g = Grid::<2>::new(319).unwrap();
    let mut dft = Dft::new_vec(g);
    dft.add_points(&pts, &mut scratch_points(g, 128)).unwrap();
    let xs: Vec<Vec<f64>> = pts.iter().map(|p| p.to_vec()).collect();
    let mut rng = Pcg32::new(5, 5);
    let mut cells: Vec<[i32; 2]> =
        vec![[319, 319], [319, -319], [0, 319], [319, 0], [1, 0], [0, 1]];
    cells.extend((0..300).map(|_| {
        [
            (rng.next_u32() % 320) as i32,
            (rng.next_u32() % 639) as i32 - 319,
        ]
    }));
    let n = pts.len() as f64;
    let (mut worst_f, mut worst_p): (f64, f64) = (0.0, 0.0);
    for j in cells {
        let (re, im) = naive(&j, &xs, |_| 1.0);
        let f = dft.amplitude(j).unwrap();
        worst_f = worst_f.max((f.re - re).abs().max((f.im - im).abs()) / n);
        worst_p = worst_p.max(((f.norm_sqr() - (re * re + im * im)) / (n * n)).abs());
    }
    println!(
        "N = 4096, k = 319: max |F − F_naive|/N = {worst_f:.1e}, max |P − P_naive| = {worst_p:.1e}"
    );
    assert!(worst_f <= 1e-12 && worst_p <= 1e-12, "{worst_f} {worst_p}");
}
