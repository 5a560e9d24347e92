//! The direct periodogram against independent references: an exact per-pair
//! double loop (phases in integer arithmetic, `e^{−2πit}` in this file's own
//! double-double), closed-form expected spectra (white noise, jitter), the line
//! identity, and the accumulator algebra (chunking, SIMD vs scalar, merge).
#![allow(clippy::needless_range_loop)]

use linesample::geom::Direction;
use linesample::pattern::{Jittered, Pattern, Random};
use linesample::primitive::Segment;
use linesample::spectrum::{
    jittered_expected, line_offsets, line_spectrum, AmplitudeView, Amplitudes, Dft, Grid,
    Periodogram,
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

/// The exact reference: every phase `ν·x mod 1` is formed in exact integer
/// arithmetic on the `f64` mantissas (`i128`), and `e^{−2πit}` is evaluated in
/// this file's own double-double arithmetic (about 2⁻¹⁰⁴ relative), so nothing
/// here shares code or rounding with the kernel's phase tables.
mod exact {
    /// An unevaluated sum `hi + lo`, `|lo| ≤ ulp(hi)/2`.
    #[derive(Clone, Copy, Debug)]
    pub struct D2(pub f64, pub f64);

    fn quick_two_sum(a: f64, b: f64) -> D2 {
        let s = a + b;
        D2(s, b - (s - a))
    }
    fn two_sum(a: f64, b: f64) -> D2 {
        let s = a + b;
        let bb = s - a;
        D2(s, (a - (s - bb)) + (b - bb))
    }
    impl D2 {
        pub fn add(self, o: D2) -> D2 {
            let s = two_sum(self.0, o.0);
            let t = two_sum(self.1, o.1);
            let u = quick_two_sum(s.0, s.1 + t.0);
            quick_two_sum(u.0, u.1 + t.1)
        }
        pub fn neg(self) -> D2 {
            D2(-self.0, -self.1)
        }
        pub fn mul(self, o: D2) -> D2 {
            let p = self.0 * o.0;
            let e = self.0.mul_add(o.0, -p);
            quick_two_sum(p, e + (self.0 * o.1 + self.1 * o.0))
        }
        /// Division by a small integer (exact quotient to ~2⁻¹⁰⁴).
        pub fn div(self, d: f64) -> D2 {
            let q1 = self.0 / d;
            let r = self.add(D2(-q1 * d, -q1.mul_add(d, -(q1 * d))));
            let q2 = r.0 / d;
            let r = r.add(D2(-q2 * d, -q2.mul_add(d, -(q2 * d))));
            quick_two_sum(q1, q2).add(D2(r.0 / d, 0.0))
        }
        pub fn to_f64(self) -> f64 {
            self.0 + self.1
        }
    }

    /// `π/2` to 107 bits (the `f64` nearest π/2 and the remainder, which is
    /// `cos(fl(π/2))` to first order).
    const HALF_PI: D2 = D2(core::f64::consts::FRAC_PI_2, 6.123_233_995_736_766e-17);

    /// `x = m·2^e` with an integer `m` (exact for every finite `x`).
    fn parts(x: f64) -> (i128, i32) {
        assert!(x.is_finite());
        if x == 0.0 {
            return (0, 0);
        }
        let b = x.to_bits();
        let exp = ((b >> 52) & 0x7ff) as i32;
        let frac = (b & ((1 << 52) - 1)) as i128;
        let (m, e) = if exp == 0 {
            (frac, -1074)
        } else {
            (frac | (1 << 52), exp - 1075)
        };
        (if x < 0.0 { -m } else { m }, e)
    }

    /// `Σ_a j_a·x_a mod 1` as `(num, s)`, the value `num/2^s ∈ [−1/2, 1/2)`,
    /// computed exactly (denominators up to 2¹²⁰: coordinates with at most 120
    /// fractional bits, which covers every `|x| ≥ 2⁻⁶⁷`).
    pub fn phase(j: &[i32], x: &[f64]) -> (i128, u32) {
        let terms: Vec<(i128, u32)> = j
            .iter()
            .zip(x)
            .filter_map(|(&ja, &xa)| {
                let (m, e) = parts(xa);
                if e >= 0 {
                    return None; // j·m·2^e is an integer
                }
                let s = (-e) as u32;
                assert!(s <= 120, "coordinate {xa:e} has too many fractional bits");
                Some(((i128::from(ja) * m).rem_euclid(1i128 << s), s))
            })
            .collect();
        let s = terms.iter().map(|t| t.1).max().unwrap_or(0);
        let one = 1i128 << s;
        let mut num = 0i128;
        for (n, sa) in terms {
            num = (num + (n << (s - sa))).rem_euclid(one);
        }
        if 2 * num >= one {
            num -= one;
        }
        (num, s)
    }

    /// `num/2^s` as a double-double (exact for `|num| < 2¹⁰⁶`).
    fn ratio(num: i128, s: u32) -> D2 {
        let scale = 2f64.powi(-(s as i32));
        let hi = num as f64;
        let rest = num - hi as i128;
        D2(hi * scale, rest as f64 * scale)
    }

    /// `(sin θ, cos θ)` for `|θ| ≤ π/4` by Taylor series in double-double
    /// (the 19th term is below 2⁻¹²⁰).
    fn sin_cos(t: D2) -> (D2, D2) {
        let t2 = t.mul(t);
        let (mut s, mut c) = (t, D2(1.0, 0.0));
        let (mut ts, mut tc) = (t, D2(1.0, 0.0));
        for k in 1..20 {
            let k = f64::from(k);
            ts = ts.mul(t2).div(2.0 * k * (2.0 * k + 1.0)).neg();
            tc = tc.mul(t2).div((2.0 * k - 1.0) * (2.0 * k)).neg();
            s = s.add(ts);
            c = c.add(tc);
        }
        (s, c)
    }

    /// `(cos 2πt, sin 2πt)` for `t = num/2^s ∈ [−1/2, 1/2)`: the quadrant `q`
    /// (`4t = q + w`, `|w| ≤ 1/2`) is removed in integers, `θ = w·π/2`.
    pub fn cos_sin_turns(num: i128, s: u32) -> (D2, D2) {
        // 4t = 4·num/2^s; with s ≥ 2 the quadrant split is exact in integers.
        let (num, s) = if s < 2 { (num << (2 - s), 2) } else { (num, s) };
        let quarter = 1i128 << (s - 2);
        let q = (num + quarter / 2).div_euclid(quarter); // round(4t), ties up
        let w = num - q * quarter; // 4t − q = w/2^{s−2}
        let (sn, cs) = sin_cos(ratio(w, s - 2).mul(HALF_PI));
        match q.rem_euclid(4) {
            0 => (cs, sn),
            1 => (sn.neg(), cs),
            2 => (cs.neg(), sn.neg()),
            _ => (sn, cs.neg()),
        }
    }

    /// `sin(πX)/(πX)` for `X = 2·Σ_a j_a·y_a` (exact rational from the `f64`
    /// inputs), 1 at `X = 0`.
    pub fn sinc_2jy(j: &[i32], y: &[f64]) -> f64 {
        // sin(πX) = sin(2π·(Σ j_a y_a mod 1)).
        let (num, s) = phase(j, y);
        let (_, sn) = cos_sin_turns(num, s);
        // X itself (not reduced) in double-double: Σ 2 j_a y_a, each product
        // exact in two parts.
        let mut x = D2(0.0, 0.0);
        for (&ja, &ya) in j.iter().zip(y) {
            let p = 2.0 * f64::from(ja) * ya;
            let e = (2.0 * f64::from(ja)).mul_add(ya, -p);
            x = x.add(D2(p, e));
        }
        if x.0 == 0.0 {
            return 1.0;
        }
        let pix = x.mul(D2(core::f64::consts::PI, 1.224_646_799_147_353_2e-16));
        // sn / pix in double-double (one Newton step on the f64 quotient).
        let q = sn.0 / pix.0;
        let r = sn.add(pix.mul(D2(-q, 0.0)));
        q + r.0 / pix.0
    }

    /// `Σ_k w_k e^{−2πiν·x_k}` summed in double-double, rounded once.
    pub fn amplitude(j: &[i32], xs: &[Vec<f64>], w: impl Fn(usize) -> f64) -> (f64, f64) {
        let (mut re, mut im) = (D2(0.0, 0.0), D2(0.0, 0.0));
        for (k, x) in xs.iter().enumerate() {
            let (num, s) = phase(j, x);
            let (c, sn) = cos_sin_turns(num, s);
            let wk = D2(w(k), 0.0);
            re = re.add(c.mul(wk));
            im = im.add(sn.mul(wk).neg());
        }
        (re.to_f64(), im.to_f64())
    }
}

/// The exact reference amplitude (see [`exact`]).
fn exact_amplitude(j: &[i32], xs: &[Vec<f64>], w: impl Fn(usize) -> f64) -> (f64, f64) {
    exact::amplitude(j, xs, w)
}

#[test]
fn exact_reference_checks_itself() {
    use exact::*;
    // Known values: t = 1/8 → cos = sin = √½; t = −1/4 → (0, −1); t = 1/3·(1 − 2⁻⁵⁴)
    // against the f64 libm value (agreement to a few ulp only).
    let r = 0.5f64.sqrt();
    let (c, s) = cos_sin_turns(1, 3);
    assert!((c.to_f64() - r).abs() <= 1.2e-16 && (s.to_f64() - r).abs() <= 1.2e-16);
    let (c, s) = cos_sin_turns(-1, 2);
    assert_eq!((c.to_f64(), s.to_f64()), (0.0, -1.0));
    let mut rng = Pcg32::new(1, 1);
    for _ in 0..2000 {
        let x = uniform(&mut rng) - 0.5;
        let (num, s) = phase(&[1], &[x]);
        let (c, sn) = cos_sin_turns(num, s);
        // cos² + sin² = 1 to double-double accuracy.
        let one = c.mul(c).add(sn.mul(sn)).add(D2(-1.0, 0.0)).to_f64();
        assert!(one.abs() < 1e-30, "{one:e}");
        let th = core::f64::consts::TAU * x;
        assert!((c.to_f64() - th.cos()).abs() < 4e-16 && (sn.to_f64() - th.sin()).abs() < 4e-16);
    }
    // The phase is exact: j·x mod 1 for x = (2⁵³ − 1)/2⁵³ and j = 3 is −3/2⁵³.
    assert_eq!(phase(&[3], &[1.0 - f64::EPSILON / 2.0]), (-3, 53));
    // 7·(3/4) − 2·(49/16) = −7/8 ≡ 1/8 = 2⁵⁰/2⁵³ (mantissas are not reduced).
    assert_eq!(phase(&[7, -2], &[0.75, 3.0625]), (1 << 50, 53));
}

fn scratch_points<const D: usize>(g: Grid<D>, chunk: usize) -> Vec<f64> {
    vec![0.0; chunk * Dft::<D, Vec<f64>>::points_scratch_per_sample(g)]
}

fn scratch_segments<const D: usize>(g: Grid<D>, chunk: usize) -> Vec<f64> {
    vec![0.0; chunk * Dft::<D, Vec<f64>>::segments_scratch_per_sample(g)]
}

fn max_err_vs_exact<const D: usize>(pts: &[[f64; D]], k: usize) -> f64 {
    let g = Grid::<D>::new(k).unwrap();
    let mut dft = Dft::new_vec(g);
    dft.add_points(pts, &mut scratch_points(g, 37)).unwrap();
    let xs: Vec<Vec<f64>> = pts.iter().map(|p| p.to_vec()).collect();
    let mut worst: f64 = 0.0;
    for i in 0..g.len() {
        let j = g.freq(i);
        let (re, im) = exact_amplitude(&j, &xs, |_| 1.0);
        let f = dft.amplitude_at(i);
        worst = worst.max((f.re - re).abs()).max((f.im - im).abs());
    }
    worst / pts.len() as f64
}

/// The README's promise for points: `|F − F_exact| ≤ 4e-16·N` (each of the real
/// and imaginary parts) at any frequency up to `|ν| = 10⁴`. It is a fixed
/// deterministic computation, so the bound is asserted as stated (no
/// statistical margin); the kernel's own `Dft` docs allow `~8ε·Σ|w_k|`
/// (1.8e-15·N), the README is the stricter claim.
const README_POINT_BOUND: f64 = 4e-16;

#[test]
fn direct_matches_exact_reference() {
    // Low and moderate frequencies in 2D and 3D, including hard coordinates.
    let mut pts: Vec<[f64; 2]> = random_points(61, 1);
    pts.extend([
        [0.0, 0.0],
        [1.0 - f64::EPSILON / 2.0, 0.5],
        [0.25, 0.75],
        [-3.2, 1e3 + 0.1],
    ]);
    let e2 = max_err_vs_exact(&pts, 40);
    let e3 = max_err_vs_exact(&random_points::<3>(23, 2), 9);
    // 1D up to |ν| = 10⁴ (every frequency).
    let e1 = max_err_vs_exact(&random_points::<1>(40, 3), 10_000);
    println!("max |F − F_exact|/N: 2D {e2:.2e}, 3D {e3:.2e}, 1D to 10⁴ {e1:.2e} (bound {README_POINT_BOUND:e})");
    for e in [e2, e3, e1] {
        assert!(e <= README_POINT_BOUND, "max |F − F_exact|/N = {e:e}");
    }
}

#[test]
fn negative_coordinates_are_reduced_exactly() {
    // x ∈ (−0.3, 0] with bits below 2⁻⁵³: x + 1 is not representable.
    let neg: Vec<[f64; 1]> = random_points::<1>(40, 3)
        .iter()
        .map(|p| [-0.3 * p[0]])
        .collect();
    let e = max_err_vs_exact(&neg, 10_000);
    println!("negative coordinates, 1D to 10⁴: max |F − F_exact|/N = {e:.2e}");
    assert!(e <= README_POINT_BOUND, "max |F − F_exact|/N = {e:e}");
}

#[test]
fn high_frequencies_stay_exact() {
    // 2D: k = 700 puts |ν| up to ~990 (corner cells and axis ends); 1D: a grid
    // of k = 2²⁰ (the largest |ν| the Dft docs cover), 400 random frequencies
    // and the top ones.
    fn worst<const D: usize>(pts: &[[f64; D]], g: Grid<D>, cells: &[[i32; D]]) -> f64 {
        let mut dft = Dft::new_vec(g);
        dft.add_points(pts, &mut scratch_points(g, 5)).unwrap();
        let xs: Vec<Vec<f64>> = pts.iter().map(|p| p.to_vec()).collect();
        let mut worst: f64 = 0.0;
        for j in cells {
            let (re, im) = exact_amplitude(j, &xs, |_| 1.0);
            let f = dft.amplitude(*j).unwrap();
            worst = worst.max((f.re - re).abs()).max((f.im - im).abs());
        }
        worst / pts.len() as f64
    }
    let e2 = worst(
        &random_points::<2>(17, 4),
        Grid::<2>::new(700).unwrap(),
        &[
            [700, 700],
            [700, -700],
            [1, -699],
            [0, 700],
            [613, 1],
            [700, 0],
        ],
    );
    let k = 1usize << 20;
    let mut rng = Pcg32::new(6, 6);
    let mut cells: Vec<[i32; 1]> = vec![[k as i32], [k as i32 - 1], [1 << 19], [999_999]];
    cells.extend((0..400).map(|_| [(rng.next_u32() % (k as u32 + 1)) as i32]));
    let e1 = worst(
        &random_points::<1>(9, 7),
        Grid::<1>::new(k).unwrap(),
        &cells,
    );
    println!("max |F − F_exact|/N: 2D to |ν| ≈ 990 {e2:.2e}, 1D to 2²⁰ {e1:.2e}");
    assert!(e2 <= README_POINT_BOUND, "2D: {e2:e}");
    // Beyond the README's |ν| = 10⁴ the Dft docs' bound ~8ε applies.
    assert!(e1 <= 8.0 * f64::EPSILON, "1D to 2²⁰: {e1:e}");
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
fn segments_match_exact_weighted_sum() {
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
            let (re, im) = exact_amplitude(&j, &xs, |s| {
                let seg = &segs[s];
                let y: Vec<f64> = (0..D)
                    .map(|a| 0.5 * seg.length() * seg.dir().get()[a])
                    .collect();
                exact::sinc_2jy(&j, &y)
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
        "segments: max |F − F_exact|/N = {:.2e} (1D k = 60), {:.2e} (1D k = 700), {:.2e} (2D), {:.2e} (3D)",
        e[0], e[1], e[2], e[3]
    );
    // The Dft docs' bound for weighted sums, `~8ε·Σ|w_k|`, with Σ|w_k| ≤ N
    // (|sinc| ≤ 1); the README states no separate segment figure.
    for x in e {
        assert!(x <= 8.0 * f64::EPSILON, "max |F − F_exact|/N = {x:e}");
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
        // |z| ≤ 5 per ring (tests/README.md: α = 5.7e-7 per check; 60 + 12 + 5
        // rings = 77 checks). Smallest detectable ring bias: 5·SE ≈ 5/√R of the
        // white-noise level 1 (0.25, 0.29, 0.35 in 1D, 2D, 3D; less on outer
        // rings, which average many cells).
        println!("random {d}D: max |ring mean − 1|/SE = {worst:.2} (limit 5)");
        assert!(worst <= 5.0, "{d}D: {worst}");
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
        // A low-frequency cell where the spectrum is tiny: there F is a sum of
        // N independent bounded terms, close to complex normal, so N·P is close
        // to exponential with SD = mean and the mean of R realisations has
        // SE ≈ e/√R; |z| ≤ 5 (a relative effect of 5/√R = 0.25 in 2D, 0.29 in 3D).
        let mut j = [0i32; D];
        j[D - 1] = 1;
        let (m, e) = (per.mean(j).unwrap(), jittered_expected(strata, j));
        let z = (m - e) / (e / (reals as f64).sqrt());
        assert!(z.abs() <= 5.0, "cell {j:?}: {m} vs {e}, z = {z:.2}");
        worst
    }
    let w2 = check::<2>([8, 8], 24, 400);
    let w3 = check::<3>([4, 4, 4], 8, 300);
    // |z| ≤ 5 per ring: 24 + 8 ring checks and 2 cell checks (34 in all).
    println!("jittered: max ring |z| 2D {w2:.2}, 3D {w3:.2} (limit 5)");
    assert!(w2 <= 5.0 && w3 <= 5.0, "{w2} {w3}");
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
    let mut amps = Amplitudes::new_vec(p.grid());
    amps.set_count(4);
    amps.parts_mut().0[2] = f64::NAN;
    assert!(matches!(
        p.add(&amps),
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
    // ν = (1, 1)·1 has N·P = 2 up to the rounding of the two phasors.
    assert!((2.0 - 1e-14..=2.0).contains(&out[1]), "{}", out[1]);
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
fn issue_case_n4096_on_the_639_grid_matches_the_exact_reference() {
    // The benchmark case (N = 4096 uniform points, k = 319): every corner and
    // axis end plus 300 random cells against the exact reference.
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
        let (re, im) = exact_amplitude(&j, &xs, |_| 1.0);
        let f = dft.amplitude(j).unwrap();
        worst_f = worst_f.max((f.re - re).abs().max((f.im - im).abs()) / n);
        worst_p = worst_p.max(((f.norm_sqr() - (re * re + im * im)) / (n * n)).abs());
    }
    println!(
        "N = 4096, k = 319: max |F − F_exact|/N = {worst_f:.1e}, max |P − P_exact| = {worst_p:.1e}"
    );
    // The README's bound on F, and the bound on P = |F|²/N² it implies:
    // |P − P_exact| ≤ (2|F|·δ + δ²)/N² with |F| ≤ N, δ = √2·4e-16·N (complex).
    let delta = 2f64.sqrt() * README_POINT_BOUND;
    assert!(
        worst_f <= README_POINT_BOUND,
        "max |F − F_exact|/N = {worst_f:e}"
    );
    assert!(
        worst_p <= 2.0 * delta + delta * delta,
        "max |P − P_exact| = {worst_p:e}"
    );
}

/// Copies the amplitudes of `dft` into an [`Amplitudes`] (grid layout), as an
/// external transform would write them.
fn copy_amplitudes<const D: usize>(dft: &Dft<D, Vec<f64>>) -> Amplitudes<D, Vec<f64>> {
    let g = dft.grid();
    let mut a = Amplitudes::new_vec(g);
    let (re, im) = a.parts_mut();
    for i in 0..g.len() {
        let c = dft.amplitude_at(i);
        re[i] = c.re;
        im[i] = c.im;
    }
    a.set_count(dft.count());
    a
}

/// The two producers of the one view give the same bits: amplitudes copied out
/// of a `Dft` into `Amplitudes` add to the same periodogram means, the same
/// per-realisation power and ring means, and the same full-grid amplitudes as
/// the `Dft` itself. The values are also checked against the formulas written
/// out here: power `(re² + im²)·(1/N)`, ring sums of multiplicity × power in
/// cell order divided by the ring count, and the order the lab's NUFFT path
/// used, `(mult·(re² + im²))·(1/N)` (multiplicity 1 or 2: scaling by a power of
/// two commutes with rounding, so both orders give the same bits for results
/// in the normal range).
#[test]
fn amplitudes_view_matches_the_dft_bit_for_bit() {
    fn check<const D: usize>(k: usize, n: usize, reals: u64) {
        let g = Grid::<D>::new(k).unwrap();
        let mut dft = Dft::new_vec(g);
        let mut via_dft = Periodogram::new_vec(g);
        let mut via_amps = Periodogram::new_vec(g);
        let mut scratch = scratch_points(g, 32);
        let (mut m1, mut m2) = (vec![0.0; k + 1], vec![0.0; k + 1]);
        let (mut c1, mut c2) = (vec![0u64; k + 1], vec![0u64; k + 1]);
        let (mut p1, mut p2) = (vec![0.0; g.len()], vec![0.0; g.len()]);
        for r in 0..reals {
            let pts: Vec<[f64; D]> = random_points(n + r as usize, 100 + r);
            dft.clear();
            dft.add_points(&pts, &mut scratch).unwrap();
            let amps = copy_amplitudes(&dft);
            assert_eq!(AmplitudeView::count(&amps), dft.count());
            via_dft.add(&dft).unwrap();
            // Through a trait object, too.
            let view: &dyn AmplitudeView<D> = &amps;
            via_amps.add(view).unwrap();
            dft.radial_power(&mut m1, &mut c1).unwrap();
            amps.radial_power(&mut m2, &mut c2).unwrap();
            dft.power(&mut p1).unwrap();
            amps.power(&mut p2).unwrap();
            assert_eq!(c1, c2);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&m1), bits(&m2), "{D}D k = {k}: ring means");
            assert_eq!(bits(&p1), bits(&p2), "{D}D k = {k}: power");
            // The formulas, written out.
            let (re, im) = amps.parts();
            let inv = 1.0 / amps.count() as f64;
            let mut rings = vec![0.0; k + 1];
            let mut lab_rings = vec![0.0; k + 1];
            for i in 0..g.len() {
                let power = (re[i] * re[i] + im[i] * im[i]) * inv;
                assert_eq!(p1[i].to_bits(), power.to_bits(), "cell {i}");
                if let Some(ring) = g.ring(i) {
                    let mult = f64::from(g.multiplicity(i));
                    rings[ring] += mult * power;
                    lab_rings[ring] += mult * (re[i] * re[i] + im[i] * im[i]) * inv;
                }
            }
            for ring in 0..=k {
                rings[ring] /= c1[ring] as f64;
                lab_rings[ring] /= c1[ring] as f64;
            }
            assert_eq!(bits(&m1), bits(&rings), "{D}D k = {k}: ring formula");
            assert_eq!(bits(&m1), bits(&lab_rings), "{D}D k = {k}: lab order");
            for i in (0..g.len()).step_by(7) {
                let j = g.freq(i);
                let neg = j.map(|x| -x);
                assert_eq!(dft.amplitude(j), amps.amplitude(j));
                assert_eq!(dft.amplitude(neg), amps.amplitude(neg));
            }
        }
        assert_eq!(via_dft.realisations(), reals);
        for i in 0..g.len() {
            assert_eq!(
                via_dft.mean_at(i).to_bits(),
                via_amps.mean_at(i).to_bits(),
                "{D}D k = {k}, cell {i}"
            );
        }
        let (mut a1, mut a2) = (vec![0.0; k + 1], vec![0.0; k + 1]);
        via_dft.radial_average(&mut a1, &mut c1).unwrap();
        via_amps.radial_average(&mut a2, &mut c2).unwrap();
        assert_eq!(
            a1.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            a2.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
    }
    // 1D both storage layouts (one padded row; rows of 64), 2D, 3D.
    check::<1>(20, 30, 3);
    check::<1>(150, 40, 3);
    check::<2>(9, 50, 4);
    check::<3>(4, 20, 3);
}

#[test]
fn amplitudes_reject_bad_buffers_and_empty_realisations() {
    let g = Grid::<2>::new(3).unwrap();
    let need = Amplitudes::<2, Vec<f64>>::buffer_len(g);
    assert_eq!(need, 2 * g.len());
    let err = Amplitudes::new(g, vec![1.0; need - 1]).unwrap_err();
    assert_eq!(
        err,
        SpectrumError::Length {
            name: "buf",
            expected: need,
            got: need - 1
        }
    );
    assert!(err.to_string().starts_with("buf: "), "{err}");
    // A caller buffer is zeroed; a longer one is fine.
    let mut buf = vec![1.0; need + 3];
    let mut a = Amplitudes::new(g, &mut buf[..]).unwrap();
    assert!(a.parts().0.iter().chain(a.parts().1).all(|&v| v == 0.0));
    assert_eq!(a.count(), 0);
    let mut p = Periodogram::new_vec(g);
    // Count 0 is an empty realisation, for every consumer.
    assert_eq!(p.add(&a), Err(SpectrumError::Empty));
    let (mut mean, mut count) = (vec![0.0; 4], vec![0u64; 4]);
    assert_eq!(
        a.radial_power(&mut mean, &mut count),
        Err(SpectrumError::Empty)
    );
    assert_eq!(a.power(&mut vec![0.0; g.len()]), Err(SpectrumError::Empty));
    a.parts_mut().0[0] = 2.0;
    a.set_count(2);
    let err = a.radial_power(&mut [0.0; 3], &mut count).unwrap_err();
    assert!(matches!(err, SpectrumError::Length { name: "mean", .. }));
    let err = a.power(&mut [0.0; 2]).unwrap_err();
    assert!(matches!(err, SpectrumError::Length { name: "out", .. }));
    // Non-finite amplitudes name the first bad cell; nothing is added.
    a.parts_mut().1[5] = f64::INFINITY;
    a.parts_mut().0[7] = f64::NAN;
    assert_eq!(
        p.add(&a),
        Err(SpectrumError::NonFinite {
            name: "amplitudes",
            index: 5
        })
    );
    assert_eq!(p.realisations(), 0);
    let mut means = vec![1.0; g.len()];
    p.means(&mut means).unwrap();
    assert!(means.iter().all(|&v| v == 0.0));
    // Another grid is a mismatch; after clear() the view is empty again.
    let other = Amplitudes::new_vec(Grid::<2>::new(4).unwrap());
    assert!(matches!(
        p.add(&other),
        Err(SpectrumError::GridMismatch { left: 3, right: 4 })
    ));
    a.clear();
    assert_eq!(a.count(), 0);
    assert!(a.parts().0.iter().chain(a.parts().1).all(|&v| v == 0.0));
    // DC amplitude N of N points: N·P(0) = N.
    a.parts_mut().0[g.index([0, 0]).unwrap().0] = 3.0;
    a.set_count(3);
    p.add(&a).unwrap();
    assert_eq!(p.mean([0, 0]), Some(3.0));
    assert_eq!(p.realisations(), 1);
}
