//! Run-time dispatch (`linesample::simd`): every dispatched hot path gives
//! the same bits at `Level::Compiled` and at `Level::Avx2Fma`.
//!
//! Meaningful in a build without AVX2 (CI's baseline SSE2 stage) on a CPU
//! with AVX2 and FMA; elsewhere it checks that asking for the AVX2 level is
//! an error, and that the compiled level is what runs. One `#[test]` only:
//! the level is process-wide, so the comparisons must not interleave with
//! another test that sets it.

use linesample::geom::Direction;
use linesample::integrand::{HalfSpace as HalfSpaceIntegrand, Integrand};
use linesample::pattern::{
    CorrelatedMultiJittered, Halton, Jittered, MultiJittered, NRooks, Pattern, Pmj02, Random, Sobol,
};
use linesample::primitive::{Rays32, Segment};
use linesample::simd::{self, Level};
use linesample::spectrum::{AmplitudeView, Dft, Grid};
use linesample::world::{Gaussian, HalfSpace, Slab, Sphere};
use linesample::{Pcg32, Seed};

/// Bits of everything the dispatched paths compute, in one list.
fn outputs() -> Vec<u64> {
    let mut bits = Vec::new();
    // Pattern fills (AoS and SoA), at an offset that is not a multiple of 8.
    let seed = Seed::new(2017);
    let pats: Vec<Box<dyn Pattern<2>>> = vec![
        Box::new(Random::<2>::new(1000).unwrap()),
        Box::new(Jittered::<2>::new([25, 40]).unwrap()),
        Box::new(NRooks::<2>::new(1000).unwrap()),
        Box::new(MultiJittered::new(1024).unwrap()),
        Box::new(CorrelatedMultiJittered::new(1024).unwrap()),
        Box::new(Sobol::<2>::new(1000).unwrap()),
        Box::new(Halton::<2>::new(1000).unwrap()),
        Box::new(Pmj02::new(1024).unwrap()),
        Box::new(Pmj02::blue_noise(256).unwrap()),
    ];
    for p in &pats {
        let mut out = vec![[0f32; 2]; p.len() - 3];
        p.fill_range(seed, 3, &mut out).unwrap();
        bits.extend(out.iter().flatten().map(|x| u64::from(x.to_bits())));
        let (mut xs, mut ys) = (vec![0f32; p.len()], vec![0f32; p.len()]);
        p.fill_range_soa(seed, 0, [&mut xs, &mut ys]).unwrap();
        bits.extend(xs.iter().chain(&ys).map(|x| u64::from(x.to_bits())));
    }
    let p3 = Sobol::<3>::new(999).unwrap().to_vec(seed).unwrap();
    bits.extend(p3.iter().flatten().map(|x| u64::from(x.to_bits())));
    // 3D N-rooks: the 16-bit permutation lanes in chunks of 12 vectors.
    let r3 = NRooks::<3>::new(2000).unwrap().to_vec(seed).unwrap();
    bits.extend(r3.iter().flatten().map(|x| u64::from(x.to_bits())));

    // Periodograms: points in 1D, 2D, 3D; segments; a segment pattern.
    let p1 = Random::<1>::new(301).unwrap().to_vec(seed).unwrap();
    let p2 = Random::<2>::new(301).unwrap().to_vec(seed).unwrap();
    fn amps<const D: usize>(d: &Dft<D, Vec<f64>>, bits: &mut Vec<u64>) {
        for i in 0..d.grid().len() {
            let a = d.amplitude_at(i);
            bits.extend([a.re.to_bits(), a.im.to_bits()]);
        }
    }
    /// The amplitudes of `pts` on the grid of half-width `k`, fed in chunks
    /// of `chunk` points (not a multiple of the lane width).
    fn point_amps<const D: usize>(pts: &[[f32; D]], k: usize, chunk: usize, bits: &mut Vec<u64>) {
        let g = Grid::<D>::new(k).unwrap();
        let mut d = Dft::new_vec(g);
        let per = Dft::<D, Vec<f64>>::points_scratch_per_sample(g);
        d.add_points(pts, &mut vec![0.0; chunk * per]).unwrap();
        amps(&d, bits);
    }
    point_amps(&p1, 200, 37, &mut bits);
    point_amps(&p2, 21, 64, &mut bits);
    point_amps(&p3, 5, 50, &mut bits);
    let g2 = Grid::<2>::new(21).unwrap();
    let segs: Vec<Segment<2>> = p2
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let v = [1.0, (i % 5) as f64 - 2.0];
            let c = [f64::from(p[0]), f64::from(p[1])];
            Segment::new(c, Direction::new(v).unwrap(), 0.02 * (i % 9) as f64).unwrap()
        })
        .collect();
    let mut s2 = Dft::new_vec(g2);
    s2.add_segments(
        &segs,
        &mut vec![0.0; 40 * Dft::<2, Vec<f64>>::segments_scratch_per_sample(g2)],
    )
    .unwrap();
    amps(&s2, &mut bits);
    let mut sp = Dft::new_vec(g2);
    let dir = Direction::new([0.6, 0.8]).unwrap();
    sp.add_segment_pattern(
        &p2,
        &dir,
        0.05,
        &mut vec![0.0; 40 * Dft::<2, Vec<f64>>::segments_scratch_per_sample(g2)],
    )
    .unwrap();
    amps(&sp, &mut bits);

    // f32 ray batches: random rays, with tangent, grazing, degenerate and
    // non-finite cases mixed in; a length that is not a multiple of 8.
    let n = 1003;
    let mut rng = Pcg32::new(9, 4);
    let mut u = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
    let mut o: [Vec<f32>; 3] = Default::default();
    let mut d: [Vec<f32>; 3] = Default::default();
    let (mut t0, mut t1) = (Vec::new(), Vec::new());
    for i in 0..n {
        for j in 0..3 {
            o[j].push(4.0 * u() - 2.0);
            d[j].push(2.0 * u() - 1.0);
        }
        let a = 3.0 * u() - 1.5;
        t0.push(a);
        t1.push(a + 3.0 * u());
        match i % 50 {
            // Tangent to the sphere of radius 0.5 at the origin.
            0 => {
                (o[0][i], o[1][i], o[2][i]) = (-2.0, 0.5, 0.0);
                (d[0][i], d[1][i], d[2][i]) = (1.0, 0.0, 0.0);
            }
            1 => (t0[i], t1[i]) = (f32::NEG_INFINITY, f32::INFINITY),
            2 => o[1][i] = f32::NAN,
            3 => (d[0][i], d[1][i], d[2][i]) = (0.0, 0.0, 1e-30),
            4 => (t0[i], t1[i]) = (1.0, 0.5),
            _ => {}
        }
    }
    let rays3 = Rays32 {
        origin: [&o[0], &o[1], &o[2]],
        dir: [&d[0], &d[1], &d[2]],
        t0: &t0,
        t1: &t1,
    };
    let rays2 = Rays32 {
        origin: [&o[0], &o[1]],
        dir: [&d[0], &d[1]],
        t0: &t0,
        t1: &t1,
    };
    let mut out = vec![0f32; n];
    let put = |out: &[f32], bits: &mut Vec<u64>| {
        bits.extend(out.iter().map(|x| u64::from(x.to_bits())));
    };
    Sphere::<3>::new([0.0, 0.0, 0.0], 0.5)
        .unwrap()
        .segment_batch_f32(&rays3, &mut out)
        .unwrap();
    put(&out, &mut bits);
    Sphere::<2>::new([0.1, -0.2], 0.7)
        .unwrap()
        .segment_batch_f32(&rays2, &mut out)
        .unwrap();
    put(&out, &mut bits);
    let g = Gaussian::<3>::normalised([0.2, 0.1, -0.3], 0.4).unwrap();
    g.segment_batch_f32(&rays3, &mut out).unwrap();
    put(&out, &mut bits);
    g.transmittance_batch_f32(&rays3, 2.5, &mut out).unwrap();
    put(&out, &mut bits);
    Gaussian::<2>::normalised([0.2, 0.1], 0.05)
        .unwrap()
        .segment_batch_f32(&rays2, &mut out)
        .unwrap();
    put(&out, &mut bits);
    HalfSpace::<3>::new([0.3, -1.0, 0.2], 0.25)
        .unwrap()
        .segment_batch_f32(&rays3, &mut out)
        .unwrap();
    put(&out, &mut bits);
    Slab::<2>::new([1.0, 1.0], -0.5, 0.75)
        .unwrap()
        .segment_batch_f32(&rays2, &mut out)
        .unwrap();
    put(&out, &mut bits);
    HalfSpaceIntegrand::<3>::new(Direction::new([0.2, 0.5, -1.0]).unwrap(), 0.3)
        .unwrap()
        .segment_free_batch_f32(&rays3, &mut out)
        .unwrap();
    put(&out, &mut bits);
    bits
}

#[test]
fn every_dispatched_path_gives_the_same_bits_at_every_level() {
    let initial = simd::level();
    simd::set_level(Level::Compiled).unwrap();
    assert_eq!(simd::level(), Level::Compiled);
    let compiled = outputs();
    let available = simd::RUNTIME_DISPATCH && simd::avx2_fma_available();
    match simd::set_level(Level::Avx2Fma) {
        Ok(()) => {
            assert!(available);
            assert_eq!(simd::level(), Level::Avx2Fma);
            let avx2 = outputs();
            assert_eq!(compiled.len(), avx2.len());
            let moved = compiled.iter().zip(&avx2).filter(|(a, b)| a != b).count();
            assert_eq!(
                moved,
                0,
                "{moved} of {} values differ between the levels",
                avx2.len()
            );
            println!("{} values, bit-identical at both levels", avx2.len());
        }
        Err(e) => {
            assert!(!available);
            assert!(e.to_string().starts_with("level: "), "{e}");
            println!("no run-time AVX2 level here ({e}): compiled level only");
        }
    }
    // The default level is the best available (nothing sets LINESAMPLE_SIMD
    // in the test run), and a second call gives the same.
    assert_eq!(
        initial == Level::Avx2Fma,
        available && std::env::var_os("LINESAMPLE_SIMD").is_none()
    );
    simd::set_level(initial).unwrap();
    assert_eq!(simd::level(), initial);
}

/// The AVX2 lane types against the scalar lanes, operation by operation and
/// lane by lane (signed zeros, NaN, tiny and huge values), where they exist.
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
#[test]
fn avx2_lanes_equal_scalar_lanes() {
    use linesample::num::avx2::{F32x8, F64x4};
    use linesample::num::lane::{F32Lane, F64Lane, Lane};
    if !simd::avx2_fma_available() {
        println!("no AVX2 on this CPU: skipped");
        return;
    }
    let a = [-3.5f32, -0.0, 0.0, 1.25, f32::NAN, -1e-30, 3e30, 0.5];
    let b = [2.0f32, 0.0, -0.0, 1.25, 1.0, f32::NAN, 2.0, -0.75];
    let same32 = |x: f32, y: f32| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan());
    let (va, vb) = (F32x8::load(&a), F32x8::load(&b));
    let mut r = [0f32; 8];
    type Op32 = (&'static str, F32x8, fn(f32, f32) -> f32);
    let ops: [Op32; 11] = [
        ("add", va + vb, |x, y| x + y),
        ("sub", va - vb, |x, y| x - y),
        ("mul", va * vb, |x, y| x * y),
        ("div", va / vb, |x, y| x / y),
        ("neg", -va, |x, _| -x),
        ("min", va.min(vb), |x, y| Lane::min(x, y)),
        ("max", va.max(vb), |x, y| Lane::max(x, y)),
        ("floor", va.floor(), |x, _| Lane::floor(x)),
        ("abs", va.abs(), |x, _| Lane::abs(x)),
        ("sqrt", va.abs().sqrt(), |x, _| Lane::sqrt(Lane::abs(x))),
        ("select", F32x8::select(va.lt(vb), va, vb), |x, y| {
            Lane::lt_select(x, y, x, y)
        }),
    ];
    for (name, v, f) in ops {
        v.store(&mut r);
        for l in 0..8 {
            assert!(
                same32(r[l], f(a[l], b[l])),
                "{name} lane {l}: {} vs {}",
                r[l],
                f(a[l], b[l])
            );
        }
    }
    let le = F32x8::select(va.le(vb), F32x8::splat(1.0), F32x8::splat(0.0));
    let gt = F32x8::select(va.gt(vb), F32x8::splat(1.0), F32x8::splat(0.0));
    let both = F32x8::select(
        F32x8::and(va.le(vb), vb.gt(va)),
        F32x8::splat(1.0),
        F32x8::splat(0.0),
    );
    for (v, f) in [
        (le, (|x: f32, y: f32| x <= y) as fn(f32, f32) -> bool),
        (gt, |x, y| x > y),
        (both, |x, y| x <= y && y > x),
    ] {
        v.store(&mut r);
        for l in 0..8 {
            assert_eq!(r[l] == 1.0, f(a[l], b[l]), "comparison lane {l}");
        }
    }
    assert!(F32x8::any(va.lt(vb)) && !F32x8::any(va.lt(F32x8::splat(f32::NEG_INFINITY))));
    let n = [-126.0f32, -1.0, 0.0, 1.0, 5.0, 64.0, 127.0, -30.0];
    F32Lane::pow2i(F32x8::load(&n)).store(&mut r);
    for l in 0..8 {
        assert_eq!(r[l].to_bits(), <f32 as F32Lane>::pow2i(n[l]).to_bits());
    }
    let x = [1.0 + f64::EPSILON, -0.0, f64::NAN, -2.5];
    let y = [1.0 - f64::EPSILON, 0.0, 1e10, f64::NAN];
    let same64 = |p: f64, q: f64| p.to_bits() == q.to_bits() || (p.is_nan() && q.is_nan());
    let (vx, vy) = (F64x4::load(&x), F64x4::load(&y));
    let mut s = [0f64; 4];
    type Op64 = (&'static str, F64x4, fn(f64, f64) -> f64);
    let ops: [Op64; 11] = [
        ("add", vx + vy, |p, q| p + q),
        ("sub", vx - vy, |p, q| p - q),
        ("mul", vx * vy, |p, q| p * q),
        ("div", vx / vy, |p, q| p / q),
        ("neg", -vx, |p, _| -p),
        ("min", vx.min(vy), |p, q| Lane::min(p, q)),
        ("max", vx.max(vy), |p, q| Lane::max(p, q)),
        ("floor", (vx * F64x4::splat(-3.7)).floor(), |p, _| {
            Lane::floor(p * -3.7)
        }),
        ("abs", vx.abs(), |p, _| Lane::abs(p)),
        ("sqrt", vx.abs().sqrt(), |p, _| Lane::sqrt(Lane::abs(p))),
        ("select", F64x4::select(vx.lt(vy), vx, vy), |p, q| {
            Lane::lt_select(p, q, p, q)
        }),
    ];
    for (name, v, f) in ops {
        v.store(&mut s);
        for l in 0..4 {
            assert!(
                same64(s[l], f(x[l], y[l])),
                "{name} lane {l}: {} vs {}",
                s[l],
                f(x[l], y[l])
            );
        }
    }
    let m = [-1022.0, -1.0, 0.0, 1023.0];
    F64Lane::pow2i(F64x4::load(&m)).store(&mut s);
    for l in 0..4 {
        assert_eq!(s[l].to_bits(), <f64 as F64Lane>::pow2i(m[l]).to_bits());
    }
}

/// Every operation of the AVX2 integer lanes and of the compiled level's
/// (`Wu32x8`, whose multiply is hand-written for SSE2) against scalar `u32`
/// arithmetic, lane by lane: wrapping products, shifts, unsigned and signed
/// comparisons on both sides of `2³¹`, selections, conversions, interleaving.
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
#[test]
fn integer_lanes_equal_scalar_u32() {
    use linesample::num::avx2::U32x8;
    use linesample::num::lane::{Lane, U32x8Lane, Wu32x8};
    let a = [
        0u32,
        1,
        0x7FFF_FFFF,
        0x8000_0000,
        u32::MAX,
        0xDEAD_BEEF,
        12345,
        1 << 24,
    ];
    let b = [
        u32::MAX,
        1,
        0x8000_0000,
        0x7FFF_FFFF,
        3,
        0x9E37_79B9,
        12345,
        7,
    ];
    fn check<U: U32x8Lane>(a: [u32; 8], b: [u32; 8], level: &str) {
        let (va, vb) = (U::from_array(a), U::from_array(b));
        type Op = (&'static str, fn(u32, u32) -> u32);
        let ops: [Op; 14] = [
            ("add", |x, y| x.wrapping_add(y)),
            ("sub", |x, y| x.wrapping_sub(y)),
            ("mul", |x, y| x.wrapping_mul(y)),
            ("and", |x, y| x & y),
            ("or", |x, y| x | y),
            ("xor", |x, y| x ^ y),
            ("shr 13", |x, _| x >> 13),
            ("shl 7", |x, _| x << 7),
            ("lt", |x, y| if x < y { u32::MAX } else { 0 }),
            ("ge", |x, y| if x >= y { u32::MAX } else { 0 }),
            ("ne", |x, y| if x != y { u32::MAX } else { 0 }),
            (
                "gt_i32",
                |x, y| if (x as i32) > (y as i32) { u32::MAX } else { 0 },
            ),
            (
                "lt_i32",
                |x, y| if (x as i32) < (y as i32) { u32::MAX } else { 0 },
            ),
            ("select", |x, y| if x < y { x } else { y }),
        ];
        let got: [U; 14] = [
            va + vb,
            va - vb,
            va * vb,
            va & vb,
            va | vb,
            va ^ vb,
            va >> 13,
            va << 7,
            va.lt(vb),
            va.ge(vb),
            va.ne(vb),
            va.gt_i32(vb),
            va.lt_i32(vb),
            U::select(va.lt(vb), va, vb),
        ];
        for ((name, f), v) in ops.iter().zip(got) {
            let r = v.to_array();
            for l in 0..8 {
                assert_eq!(r[l], f(a[l], b[l]), "{level} {name} lane {l}");
            }
        }
        assert!(va.lt(vb).any() && !va.lt(U::splat(0)).any(), "{level} any");
        let mut f = [0f32; 8];
        (va >> 8).to_f32().store(&mut f);
        for l in 0..8 {
            assert_eq!(f[l], (a[l] >> 8) as f32, "{level} to_f32 lane {l}");
        }
        let bits = U::from_f32_bits(va.to_f32_bits()).to_array();
        assert_eq!(bits, a, "{level} bit casts");
        let (lo, hi) = U::interleave(va, vb);
        let (lo, hi) = (lo.to_array(), hi.to_array());
        for l in 0..4 {
            assert_eq!(
                [lo[2 * l], lo[2 * l + 1]],
                [a[l], b[l]],
                "{level} interleave lo"
            );
            assert_eq!(
                [hi[2 * l], hi[2 * l + 1]],
                [a[l + 4], b[l + 4]],
                "{level} interleave hi"
            );
        }
    }
    check::<Wu32x8>(a, b, "compiled");
    if simd::avx2_fma_available() {
        check::<U32x8>(a, b, "avx2");
    } else {
        println!("no AVX2 on this CPU: AVX2 integer lanes skipped");
    }
}

/// The 16-bit lanes of the narrow-domain permutations, AVX2 and compiled
/// level (`wide`'s `u16x16`), against scalar `u16` arithmetic lane by lane:
/// wrapping products, shifts, the unsigned `≥` on both sides of `2¹⁵`,
/// selections and the zero-extension to 32 bits.
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
#[test]
fn integer_lanes_equal_scalar_u16() {
    use linesample::num::avx2::U16x16;
    use linesample::num::lane::{IntLane, U16x16Lane, U32x8Lane};
    let a: [u16; 16] = [
        0, 1, 0x7FFF, 0x8000, 0xFFFF, 0xBEEF, 12345, 256, 3, 0x8001, 0x7FFE, 40000, 2, 9, 0xFFFE,
        1000,
    ];
    let b: [u16; 16] = [
        0xFFFF, 1, 0x8000, 0x7FFF, 3, 0x79B9, 12345, 7, 3, 0x7FFF, 0x8000, 39999, 0, 0xFFFF, 5,
        65535,
    ];
    fn check<L: U16x16Lane>(a: [u16; 16], b: [u16; 16], level: &str) {
        let (va, vb) = (L::from_array(a), L::from_array(b));
        let lanes = |v: L| -> [u32; 16] {
            let [lo, hi] = v.widen();
            let (lo, hi) = (lo.to_array(), hi.to_array());
            core::array::from_fn(|l| if l < 8 { lo[l] } else { hi[l - 8] })
        };
        type Op = (&'static str, fn(u16, u16) -> u16);
        let ops: [Op; 10] = [
            ("add", |x, y| x.wrapping_add(y)),
            ("sub", |x, y| x.wrapping_sub(y)),
            ("mul", |x, y| x.wrapping_mul(y)),
            ("and", |x, y| x & y),
            ("or", |x, y| x | y),
            ("xor", |x, y| x ^ y),
            ("shr 5", |x, _| x >> 5),
            ("shl 3", |x, _| x << 3),
            ("ge", |x, y| if x >= y { u16::MAX } else { 0 }),
            ("select", |x, y| if x >= y { x } else { y }),
        ];
        let mut x = va;
        x ^= vb;
        let got: [L; 10] = [
            va + vb,
            va - vb,
            va * vb,
            va & vb,
            va | vb,
            x,
            va >> 5,
            va << 3,
            va.ge(vb),
            L::select(va.ge(vb), va, vb),
        ];
        for ((name, f), v) in ops.iter().zip(got) {
            let r = lanes(v);
            for l in 0..16 {
                assert_eq!(r[l], u32::from(f(a[l], b[l])), "{level} {name} lane {l}");
            }
        }
        assert_eq!(lanes(L::splat(0x1_2345)), [0x2345; 16], "{level} splat");
        assert!(
            va.ge(vb).any() && !L::splat(0).ge(L::splat(1)).any(),
            "{level} any"
        );
    }
    check::<wide::u16x16>(a, b, "compiled");
    if simd::avx2_fma_available() {
        check::<U16x16>(a, b, "avx2");
    } else {
        println!("no AVX2 on this CPU: AVX2 16-bit lanes skipped");
    }
}
