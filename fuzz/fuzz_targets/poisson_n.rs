//! Fuzzes `PoissonDisk::generate_n` (and `generate`, `for_n`, `with_radius`) with
//! arbitrary parameters, counts and buffer sizes.
//!
//! Checks, for both ways of getting exactly `n` points ([`PoissonN`]): never a
//! panic; `n = 0` and short buffers are errors. The reference run is the
//! maximal dart-throwing run for the same seed (sequential dart throwing
//! stopped at `n`, the default: `out[..n]` must be its first `n` points, in
//! order) or the run of the sampler's own method (thinned: `out[..n]` must be
//! a subset of it, as a multiset, bit for bit). The points are in `[0, 1)`,
//! pairwise at toroidal distance `≥ r` (the stored `f32` points,
//! `d² ≥ r²(1 − 1e−9)`, as the `patterns` target checks for `generate`);
//! when the reference run has fewer than `n` points the error is
//! `Shortfall { got, wanted: n }` with `got` its count and `out[..got]` its
//! points. Sizes are kept to at most 128 points.
//!
//! Run: `cargo fuzz run --sanitizer none poisson_n`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::pattern::{PoissonDisk, PoissonMethod, PoissonN};
use linesample::{PatternError, Seed};

#[derive(Arbitrary, Debug)]
struct Input {
    dims: u8,
    target: Option<(u16, f64)>,
    radius: f64,
    dart: bool,
    thinned: bool,
    n: u16,
    extra: u8,
    seed: u64,
}

fn run<const D: usize>(inp: &Input) {
    let built = match inp.target {
        Some((n, rel)) => PoissonDisk::<D>::for_n(usize::from(n), rel),
        None => PoissonDisk::<D>::with_radius(inp.radius),
    };
    let Ok(mut disk) = built else { return };
    if inp.dart {
        disk = disk.with_method(PoissonMethod::MaximalDartThrowing);
    }
    if inp.thinned {
        disk = disk.with_n_mode(PoissonN::ThinnedRun);
    }
    if disk.max_points() > 128 || disk.scratch_len() > 1 << 12 {
        return;
    }
    let seed = Seed::new(inp.seed);
    let r = disk.radius();
    let n = usize::from(inp.n) % (disk.max_points() + 8);
    let mut scratch = vec![0u32; disk.scratch_len()];
    let cap = disk.max_points().max(n) + usize::from(inp.extra % 4);
    let mut out = vec![[0.0f32; D]; cap];
    let res = disk.generate_n(n, seed, &mut scratch, &mut out);
    let mut all = vec![[0.0f32; D]; disk.max_points()];
    let reference = if inp.thinned {
        disk
    } else {
        disk.with_method(PoissonMethod::MaximalDartThrowing)
    };
    let got = reference.generate(seed, &mut scratch, &mut all).unwrap();
    let all = &all[..got];
    let key = |p: &[f32; D]| p.map(f32::to_bits);
    let mut pool: Vec<[u32; D]> = all.iter().map(key).collect();
    pool.sort_unstable();
    match res {
        Err(PatternError::ZeroPoints) => assert_eq!(n, 0),
        Err(PatternError::Shortfall { got: g, wanted }) => {
            assert_eq!(wanted, n as u64);
            assert_eq!(g, got as u64);
            assert!(got < n);
            for (a, b) in out[..got].iter().zip(all) {
                assert_eq!(key(a), key(b));
            }
        }
        Err(e) => panic!("generate_n({n}) with buffers of {cap}: {e}"),
        Ok(()) => {
            assert!(n >= 1 && n <= got);
            if !inp.thinned {
                // The first n points of the maximal run, in acceptance order.
                for (a, b) in out[..n].iter().zip(all) {
                    assert_eq!(key(a), key(b));
                }
            }
            let mut sub: Vec<[u32; D]> = out[..n].iter().map(key).collect();
            sub.sort_unstable();
            // Multiset inclusion in the full run.
            let mut j = 0;
            for s in &sub {
                while j < pool.len() && pool[j] < *s {
                    j += 1;
                }
                assert!(j < pool.len() && pool[j] == *s, "point {s:?} not generated");
                j += 1;
            }
            let pts = &out[..n];
            for (i, a) in pts.iter().enumerate() {
                assert!(a.iter().all(|&x| (0.0..1.0).contains(&x)), "{a:?}");
                for b in &pts[i + 1..] {
                    let d2: f64 = (0..D)
                        .map(|j| {
                            let t = (f64::from(a[j]) - f64::from(b[j])).abs();
                            let t = t.min(1.0 - t);
                            t * t
                        })
                        .sum();
                    assert!(
                        d2 >= r * r * (1.0 - 1e-9),
                        "{a:?} and {b:?} closer than r = {r}"
                    );
                }
            }
        }
    }
    if n >= 1 && disk.scratch_len() > 0 {
        let mut small = vec![0u32; disk.scratch_len() - 1];
        assert!(disk.generate_n(n, seed, &mut small, &mut out).is_err());
    }
}

fuzz_target!(|inp: Input| match inp.dims % 3 {
    0 => run::<1>(&inp),
    1 => run::<2>(&inp),
    _ => run::<3>(&inp),
});
