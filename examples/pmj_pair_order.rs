//! Why `Pmj02Pixel` permutes the batches of its pairs `p ≥ 1`: two independent
//! PMJ02 sequences used as dimension pairs 0 and 1 of one pixel, in table
//! order, against the same sequences with the second one's batches
//! `[2ᵇ, 2ᵇ⁺¹)` permuted.
//!
//! The PMJ02 construction copies the high digits of point `i` to point
//! `N + i`, so the top `x` digit of point `i` is a function of `i mod 4`,
//! with one pattern for every sequence up to two coins. Index-aligned
//! sequences then share that pattern, and the estimate of an integrand that
//! couples `u₀` (pair 0) with `u₂` (pair 1) does not converge. The example
//! prints `N·Var` of the estimates of `12(u₀ − ½)(u₂ − ½)` (independent
//! uniform points: 1) and `1[u₀ < ½]·1[u₂ < ½]` (independent uniform
//! points: 3/16) over pairs of independent sequences, for
//!
//! * `aligned`: point `i` of both sequences;
//! * `nested`: the batches of the second sequence through an ideal nested
//!   (Owen) scramble of the index bits, every flip a fresh hash;
//! * `permute`: the batches of the second sequence through
//!   `linesample::hash::permute`, as `Pmj02Pixel` does;
//! * `random`: independent uniform points.
//!
//! Run: `cargo run --release --example pmj_pair_order` (a few seconds).

use linesample::hash::permute;
use linesample::pattern::Pmj02;
use linesample::rng::mix64;
use linesample::Seed;

const REPS: u64 = 2000;

fn sequence(p: &Pmj02, seed: u64) -> Vec<[f64; 2]> {
    let mut out = vec![[0.0f32; 2]; p.n()];
    let mut scratch = vec![0u32; p.scratch_len()];
    p.generate(Seed::new(seed), &mut out, &mut scratch).unwrap();
    out.iter().map(|q| q.map(f64::from)).collect()
}

/// `i` with its batch `[2ᵇ, 2ᵇ⁺¹)` permuted: `nested` flips bit `j` of the
/// batch-local index by a hash of the bits above it, else `hash::permute`.
fn batch_permuted(i: usize, key: u64, nested: bool) -> usize {
    if i < 2 {
        return i;
    }
    let b = usize::BITS - 1 - i.leading_zeros();
    let base = 1usize << b;
    let l = i - base;
    let kb = mix64(key ^ u64::from(b).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    if !nested {
        return base + permute(l as u32, base as u32, (kb >> 32) as u32) as usize;
    }
    let mut out = 0;
    for j in (0..b).rev() {
        let above = (l >> (j + 1)) as u64;
        let flip = (mix64(kb ^ mix64((above << 6) | u64::from(j))) >> 63) as usize;
        out |= (((l >> j) & 1) ^ flip) << j;
    }
    base + out
}

fn main() {
    println!("N·Var of the estimates over {REPS} pairs of independent PMJ02 sequences");
    println!(
        "{:>6} {:>9} {:>12} {:>12}",
        "N", "order", "bilinear", "quadrant"
    );
    for n in [256usize, 1024] {
        let p = Pmj02::new(n).unwrap();
        for order in ["aligned", "nested", "permute", "random"] {
            let (mut s, mut s2) = ([0.0f64; 2], [0.0f64; 2]);
            for r in 0..REPS {
                let a = sequence(&p, 2 * r + 1000);
                let b = sequence(&p, 2 * r + 1001);
                let mut est = [0.0; 2];
                for i in 0..n {
                    let (u0, u2) = match order {
                        "aligned" => (a[i][0], b[i][0]),
                        "nested" => (a[i][0], b[batch_permuted(i, r, true)][0]),
                        "permute" => (a[i][0], b[batch_permuted(i, r, false)][0]),
                        _ => {
                            let h = mix64(r * 1_000_003 + i as u64);
                            let unit = |x: u64| (x >> 11) as f64 / (1u64 << 53) as f64;
                            (unit(h), unit(mix64(h)))
                        }
                    };
                    est[0] += 12.0 * (u0 - 0.5) * (u2 - 0.5);
                    est[1] += f64::from(u8::from(u0 < 0.5 && u2 < 0.5));
                }
                for k in 0..2 {
                    let e = est[k] / n as f64;
                    s[k] += e;
                    s2[k] += e * e;
                }
            }
            let var = |k: usize| {
                let m = s[k] / REPS as f64;
                (s2[k] / REPS as f64 - m * m) * n as f64
            };
            println!("{n:>6} {order:>9} {:>12.3} {:>12.3}", var(0), var(1));
        }
    }
}
