//! Fuzzes the random-access functions of the low-discrepancy sequences:
//! `Sobol::sample` / `try_sample` / `sample_unscrambled` / `sobol_u32`,
//! `Halton::sample` / `try_sample` / `sample_unscrambled` and `radical_inverse`,
//! at any index in `0..2³²`, any dimension and seed.
//!
//! Oracles (independent of the kernel's code paths):
//! * random access equals `fill_range` of the `D`-dimensional pattern of `2³²`
//!   points, coordinate `d` = dimension `d`, at a window anywhere in the index range
//!   (windows that cross an 8-point SIMD block boundary included);
//! * `try_sample` rejects exactly the dimensions `≥ SOBOL_DIMENSIONS`
//!   (`HALTON_DIMENSIONS`) and otherwise equals `sample`;
//! * unscrambled Sobol' dimension 0 is the bit reversal of the index (van der
//!   Corput), and `sample_unscrambled` is its top 24 bits;
//! * `radical_inverse(b, i)` equals the digit reversal of `i` in base `b` computed
//!   here in exact integer arithmetic, correctly rounded (`b^n ≤ 2⁵³`);
//! * nets: an aligned block of `2^m` scrambled Sobol' indices (`m ≤ 10`) has exactly
//!   one point in each interval `[c/2^m, (c+1)/2^m)` of every dimension, and
//!   dimensions 0 and 1 form a `(0, m, 2)`-net (one point in every elementary box
//!   `2^{−a} × 2^{−(m−a)}`); an aligned block of `b^m` scrambled Halton indices has
//!   one point in each interval `[c/b^m, (c+1)/b^m)`.
//!
//! Run: `cargo fuzz run --sanitizer none lowdisc`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::pattern::{
    radical_inverse, Halton, Pattern, Sobol, HALTON_BASES, HALTON_DIMENSIONS, SOBOL_DIMENSIONS,
};
use linesample::Seed;

#[derive(Arbitrary, Debug)]
struct Input {
    seed: u64,
    index: u32,
    dim: u32,
    base: u32,
    len: u8,
    m: u8,
    block: u32,
    three: bool,
}

/// Digit reversal of `i` in base `b`: `(N, b^n)` exactly (`N < b^n`).
fn reversal(b: u64, mut i: u64) -> (u128, u128) {
    let (mut n, mut pow) = (0u128, 1u128);
    while i > 0 {
        n = n * u128::from(b) + u128::from(i % b);
        pow *= u128::from(b);
        i /= b;
    }
    (n, pow)
}

fn window<const D: usize>(inp: &Input, seed: Seed) {
    let len = usize::from(inp.len % 40);
    let first = (inp.index as usize).min((1usize << 32) - len);
    let sob = Sobol::<D>::new(1 << 32).unwrap();
    let mut buf = vec![[0.0f32; D]; len];
    sob.fill_range(seed, first, &mut buf).unwrap();
    for (k, p) in buf.iter().enumerate() {
        for d in 0..D {
            let s = Sobol::sample((first + k) as u32, d as u32, seed);
            assert_eq!(
                p[d].to_bits(),
                s.to_bits(),
                "Sobol point {} dim {d}",
                first + k
            );
        }
    }
    let hal = Halton::<D>::new(1 << 32).unwrap();
    hal.fill_range(seed, first, &mut buf).unwrap();
    for (k, p) in buf.iter().enumerate() {
        for d in 0..D {
            let s = Halton::sample((first + k) as u32, d as u32, seed);
            assert_eq!(
                p[d].to_bits(),
                s.to_bits(),
                "Halton point {} dim {d}",
                first + k
            );
        }
    }
}

fuzz_target!(|inp: Input| {
    let seed = Seed::new(inp.seed);
    let i = inp.index;
    // try_sample: rejects exactly the out-of-range dimensions.
    match Sobol::try_sample(i, inp.dim, seed) {
        Ok(v) => {
            assert!(inp.dim < SOBOL_DIMENSIONS);
            assert_eq!(v.to_bits(), Sobol::sample(i, inp.dim, seed).to_bits());
            assert!((0.0..1.0).contains(&v));
        }
        Err(_) => assert!(inp.dim >= SOBOL_DIMENSIONS),
    }
    match Halton::try_sample(i, inp.dim, seed) {
        Ok(v) => {
            assert!(inp.dim < HALTON_DIMENSIONS);
            assert_eq!(v.to_bits(), Halton::sample(i, inp.dim, seed).to_bits());
            assert!((0.0..1.0).contains(&v));
        }
        Err(_) => assert!(inp.dim >= HALTON_DIMENSIONS),
    }
    // Unscrambled Sobol' dimension 0 = van der Corput = bit reversal.
    assert_eq!(Sobol::sobol_u32(i, 0), i.reverse_bits());
    let top = (i.reverse_bits() >> 8) as f32 / (1u32 << 24) as f32;
    assert_eq!(Sobol::sample_unscrambled(i, 0).to_bits(), top.to_bits());
    // Radical inverse against exact digit reversal.
    let b = 2 + inp.base % 1000;
    let (n, pow) = reversal(u64::from(b), u64::from(i));
    let ri = radical_inverse(b, i);
    assert!((0.0..1.0).contains(&ri), "radical_inverse({b}, {i}) = {ri}");
    if pow <= 1u128 << 53 {
        assert_eq!(ri, n as f64 / pow as f64, "radical_inverse({b}, {i})");
    } else {
        let exact = n as f64 / pow as f64; // two roundings: within 2 ulp
        assert!((ri - exact).abs() <= 4.0 * f64::EPSILON * exact.max(f64::MIN_POSITIVE));
    }
    let d = inp.dim % HALTON_DIMENSIONS;
    let (hn, hp) = reversal(u64::from(HALTON_BASES[d as usize]), u64::from(i));
    let hu = Halton::sample_unscrambled(i, d);
    let exact = hn as f64 / hp as f64;
    // The f32 is in the cell of its first J digits: within one f32 ulp of 1 of
    // the exact value, never 1.
    assert!((0.0..1.0).contains(&hu) && (f64::from(hu) - exact).abs() <= 1.2e-7);

    // Random access = fill_range.
    if inp.three {
        window::<3>(&inp, seed);
    } else {
        window::<2>(&inp, seed);
    }

    // Sobol' nets on an aligned block of 2^m indices.
    let m = u32::from(inp.m % 11);
    let size = 1u64 << m;
    let start = (u64::from(inp.block) % ((1u64 << 32) / size)) * size;
    let dim = inp.dim % SOBOL_DIMENSIONS;
    let mut hit = vec![false; size as usize];
    let pts: Vec<(f32, f32)> = (start..start + size)
        .map(|k| {
            (
                Sobol::sample(k as u32, dim, seed),
                Sobol::sample(k as u32, (dim + 1) % SOBOL_DIMENSIONS, seed),
            )
        })
        .collect();
    for &(x, _) in &pts {
        let c = (f64::from(x) * size as f64) as usize;
        assert!(
            !hit[c],
            "Sobol dim {dim}, block {start}+2^{m}: two points in cell {c}"
        );
        hit[c] = true;
    }
    let x0: Vec<(f32, f32)> = (start..start + size)
        .map(|k| {
            (
                Sobol::sample(k as u32, 0, seed),
                Sobol::sample(k as u32, 1, seed),
            )
        })
        .collect();
    for a in 0..=m {
        let (nx, ny) = (1u64 << a, 1u64 << (m - a));
        let mut cell = vec![false; size as usize];
        for &(x, y) in &x0 {
            let cx = (f64::from(x) * nx as f64) as u64;
            let cy = (f64::from(y) * ny as f64) as u64;
            let c = (cx * ny + cy) as usize;
            assert!(
                !cell[c],
                "Sobol dims 0,1 block {start}+2^{m}: box {a} not a (0,m,2)-net"
            );
            cell[c] = true;
        }
    }
    // Halton strata on an aligned block of b^m indices (b^m ≤ 2^10).
    let hb = u64::from(HALTON_BASES[d as usize]);
    let mut bm = 1u64;
    while bm * hb <= size.max(1) {
        bm *= hb;
    }
    let hstart = (u64::from(inp.block) % ((1u64 << 32) / bm)) * bm;
    let mut hit = vec![false; bm as usize];
    for k in hstart..hstart + bm {
        let x = Halton::sample(k as u32, d, seed);
        let c = (f64::from(x) * bm as f64) as usize;
        assert!(
            !hit[c],
            "Halton dim {d}, block {hstart}+{bm}: two points in cell {c}"
        );
        hit[c] = true;
    }
});
