//! Fuzzes every sample pattern through the public `Pattern<D>` API.
//!
//! For arbitrary constructor parameters (huge ones included: a rejected parameter
//! is fine, a panic is not), seed, realization, shift flag and an in-range window
//! `first .. first + len`, it checks that
//!
//! * every coordinate is finite and in `[0, 1)`;
//! * `fill_range` (SIMD), `fill_range_scalar` and `fill_range_soa` agree bit for bit;
//! * for patterns small enough to fill completely (`N ≤ 2¹²`), the window equals the
//!   same points of a full `fill` (results do not depend on the batch split);
//! * out-of-range and wrongly sized requests return errors instead of panicking.
//!
//! Run: `cargo fuzz run --sanitizer none patterns` (from the repo root or fuzz/).

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::pattern::{
    CorrelatedMultiJittered, Halton, Jittered, MultiJittered, NRooks, Pattern, PoissonDisk,
    PoissonMethod, Random, Sobol,
};
use linesample::{PatternError, Seed};

/// Patterns with at most this many points are filled completely. (2¹⁴ halved the
/// executions per second for no extra coverage in a 60 s run.)
const FULL_CAP: u64 = 1 << 12;
/// Largest window filled from a bigger pattern.
const WINDOW_CAP: u64 = 1 << 10;

/// A count or size parameter: mostly small, sometimes anything at all.
#[derive(Arbitrary, Clone, Copy, Debug)]
enum Count {
    Small(u8),
    Medium(u16),
    Any(u64),
}

impl Count {
    fn get(self) -> usize {
        match self {
            Count::Small(v) => usize::from(v),
            Count::Medium(v) => usize::from(v),
            // Truncation on 32-bit hosts is fine: any value is a valid input.
            Count::Any(v) => v as usize,
        }
    }
}

/// Every sampler, dimension and constructor.
#[derive(Arbitrary, Debug)]
enum Sampler {
    Random1(Count),
    Random2(Count),
    Random3(Count),
    Jittered1([Count; 1]),
    Jittered2([Count; 2]),
    Jittered3([Count; 3]),
    JitteredWithN1(Count, [Count; 1]),
    JitteredWithN2(Count, [Count; 2]),
    JitteredWithN3(Count, [Count; 3]),
    JitteredCube1(Count),
    JitteredCube2(Count),
    JitteredCube3(Count),
    NRooks1(Count),
    NRooks2(Count),
    NRooks3(Count),
    MultiJittered(Count),
    MultiJitteredGrid(Count, Count),
    Cmj(Count),
    CmjGrid(Count, Count),
    Sobol1(Count),
    Sobol2(Count),
    Sobol3(Count),
    Halton1(Count),
    Halton2(Count),
    Halton3(Count),
    Poisson1(PoissonInput),
    Poisson2(PoissonInput),
    Poisson3(PoissonInput),
}

/// Poisson-disk parameters: a radius, or a target count with a relative radius.
#[derive(Arbitrary, Debug)]
struct PoissonInput {
    radius: f64,
    target: Option<(Count, f64)>,
    dart_throwing: bool,
    candidates: Option<u32>,
}

#[derive(Arbitrary, Debug)]
struct Input {
    sampler: Sampler,
    seed: u64,
    realization: Option<u64>,
    shift: bool,
    /// Window start, reduced into the valid range.
    first: u64,
    /// Window length, reduced to at most `N` (and `WINDOW_CAP` for big patterns).
    len: u64,
}

fuzz_target!(|input: Input| {
    let c = |a: [Count; 1]| a.map(Count::get);
    let c2 = |a: [Count; 2]| a.map(Count::get);
    let c3 = |a: [Count; 3]| a.map(Count::get);
    match input.sampler {
        Sampler::Random1(n) => run(Random::<1>::new(n.get()), &input),
        Sampler::Random2(n) => run(Random::<2>::new(n.get()), &input),
        Sampler::Random3(n) => run(Random::<3>::new(n.get()), &input),
        Sampler::Jittered1(s) => run(Jittered::<1>::new(c(s)), &input),
        Sampler::Jittered2(s) => run(Jittered::<2>::new(c2(s)), &input),
        Sampler::Jittered3(s) => run(Jittered::<3>::new(c3(s)), &input),
        Sampler::JitteredWithN1(n, s) => run(Jittered::<1>::with_n(n.get(), c(s)), &input),
        Sampler::JitteredWithN2(n, s) => run(Jittered::<2>::with_n(n.get(), c2(s)), &input),
        Sampler::JitteredWithN3(n, s) => run(Jittered::<3>::with_n(n.get(), c3(s)), &input),
        Sampler::JitteredCube1(n) => run(Jittered::<1>::cube(n.get()), &input),
        Sampler::JitteredCube2(n) => run(Jittered::<2>::cube(n.get()), &input),
        Sampler::JitteredCube3(n) => run(Jittered::<3>::cube(n.get()), &input),
        Sampler::NRooks1(n) => run(NRooks::<1>::new(n.get()), &input),
        Sampler::NRooks2(n) => run(NRooks::<2>::new(n.get()), &input),
        Sampler::NRooks3(n) => run(NRooks::<3>::new(n.get()), &input),
        Sampler::MultiJittered(n) => run(MultiJittered::new(n.get()), &input),
        Sampler::MultiJitteredGrid(cols, rows) => {
            run(MultiJittered::with_grid(cols.get(), rows.get()), &input)
        }
        Sampler::Cmj(n) => run(CorrelatedMultiJittered::new(n.get()), &input),
        Sampler::CmjGrid(cols, rows) => run(
            CorrelatedMultiJittered::with_grid(cols.get(), rows.get()),
            &input,
        ),
        Sampler::Sobol1(n) => run(Sobol::<1>::new(n.get()), &input),
        Sampler::Sobol2(n) => run(Sobol::<2>::new(n.get()), &input),
        Sampler::Sobol3(n) => run(Sobol::<3>::new(n.get()), &input),
        Sampler::Halton1(n) => run(Halton::<1>::new(n.get()), &input),
        Sampler::Halton2(n) => run(Halton::<2>::new(n.get()), &input),
        Sampler::Halton3(n) => run(Halton::<3>::new(n.get()), &input),
        Sampler::Poisson1(ref p) => poisson::<1>(p, input.seed),
        Sampler::Poisson2(ref p) => poisson::<2>(p, input.seed),
        Sampler::Poisson3(ref p) => poisson::<3>(p, input.seed),
    }
});

/// Poisson disk: any parameters are accepted or rejected without a panic; small
/// accepted sets are generated and checked (range, count bound, minimum toroidal
/// distance ≥ r between stored points).
fn poisson<const D: usize>(input: &PoissonInput, seed: u64) {
    let built = match input.target {
        Some((n, rel)) => PoissonDisk::<D>::for_n(n.get(), rel),
        None => PoissonDisk::<D>::with_radius(input.radius),
    };
    let Ok(mut disk) = built else { return };
    if input.dart_throwing {
        disk = disk.with_method(PoissonMethod::MaximalDartThrowing);
    }
    if let Some(k) = input.candidates {
        match disk.clone().with_candidates(k) {
            Ok(d) => disk = d,
            Err(_) => assert!(k == 0 || k > 1024, "k = {k} rejected"),
        }
    }
    let r = disk.radius();
    assert!(r.is_finite() && r > 0.0);
    if disk.max_points() > 2000 || disk.scratch_len() > 1 << 20 {
        return;
    }
    let mut scratch = vec![0u32; disk.scratch_len()];
    let mut out = vec![[0.0f32; D]; disk.max_points()];
    let count = disk
        .generate(Seed::new(seed), &mut scratch, &mut out)
        .expect("buffers of the advertised sizes are accepted");
    assert!(count >= 1 && count <= disk.max_points());
    let pts = &out[..count];
    for q in pts {
        assert!(q.iter().all(|&x| (0.0..1.0).contains(&x)), "{q:?}");
    }
    for (i, a) in pts.iter().enumerate() {
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
                "points {a:?} {b:?} closer than r = {r}"
            );
        }
    }
    let small = vec![0u32; disk.scratch_len().saturating_sub(1)];
    let mut small = small;
    assert!(disk
        .generate(Seed::new(seed), &mut small, &mut out)
        .is_err());
}

/// Checks a constructed pattern (rejected parameters end the input), plain or shifted.
fn run<const D: usize, P: Pattern<D>>(built: Result<P, PatternError>, input: &Input) {
    let Some(p) = built.ok() else { return };
    if input.shift {
        check(&p.shifted(), input);
    } else {
        check(&p, input);
    }
}

fn check<const D: usize, P: Pattern<D>>(p: &P, input: &Input) {
    let n = p.len() as u64;
    assert!(n > 0 && !p.is_empty(), "constructors reject N = 0");
    let seed = match input.realization {
        Some(r) => Seed::new(input.seed).realization(r),
        None => Seed::new(input.seed),
    };
    let cap = if n <= FULL_CAP { n } else { WINDOW_CAP };
    let len = input.len % (cap + 1);
    // Any first in 0..=n - len (all of u64 when that range is all of u64).
    let first = match (n - len).checked_add(1) {
        Some(m) => input.first % m,
        None => input.first,
    };
    let (first, len) = (first as usize, len as usize);

    // SIMD path.
    let mut simd = vec![[0.0f32; D]; len];
    p.fill_range(seed, first, &mut simd)
        .unwrap_or_else(|e| panic!("fill_range({first}, {len}) of N = {n}: {e}"));
    for (i, q) in simd.iter().enumerate() {
        for &x in q {
            assert!(
                x.is_finite() && (0.0..1.0).contains(&x),
                "point {}: {q:?} outside [0, 1)",
                first + i
            );
        }
    }

    // Scalar reference path.
    let mut scalar = vec![[1.0f32; D]; len];
    p.fill_range_scalar(seed, first, &mut scalar).unwrap();
    for i in 0..len {
        assert_eq!(
            bits(&simd[i]),
            bits(&scalar[i]),
            "point {}: SIMD {:?} != scalar {:?}",
            first + i,
            simd[i],
            scalar[i]
        );
    }

    // Structure of arrays.
    let mut soa: [Vec<f32>; D] = core::array::from_fn(|_| vec![2.0f32; len]);
    p.fill_range_soa(seed, first, soa.each_mut().map(|v| v.as_mut_slice()))
        .unwrap();
    for i in 0..len {
        for j in 0..D {
            assert_eq!(
                simd[i][j].to_bits(),
                soa[j][i].to_bits(),
                "point {}, coordinate {j}: AoS {} != SoA {}",
                first + i,
                simd[i][j],
                soa[j][i]
            );
        }
    }

    // The window is the same as those points of a full fill.
    if n <= FULL_CAP {
        let all = p.to_vec(seed).unwrap();
        assert_eq!(all.len() as u64, n);
        for i in 0..len {
            assert_eq!(
                bits(&all[first + i]),
                bits(&simd[i]),
                "point {}: window differs from the full fill",
                first + i
            );
        }
        // A full fill into the wrong length is an error.
        let mut wrong = vec![[0.0f32; D]; n as usize + 1];
        assert!(matches!(
            p.fill(seed, &mut wrong),
            Err(PatternError::OutputLength { .. })
        ));
    }

    // Past the end: an error, never a panic.
    let mut one = [[0.0f32; D]; 1];
    assert!(matches!(
        p.fill_range(seed, n as usize, &mut one),
        Err(PatternError::Range { .. })
    ));
    assert!(matches!(
        p.fill_range_scalar(seed, usize::MAX, &mut one),
        Err(PatternError::Range { .. })
    ));
    if D >= 2 && len > 0 {
        // SoA slices of different lengths.
        let mut a = vec![0.0f32; len];
        let mut b = vec![0.0f32; len - 1];
        let mut slices: [&mut [f32]; D] = core::array::from_fn(|_| &mut [][..]);
        slices[0] = &mut a;
        slices[1] = &mut b;
        assert!(p.fill_range_soa(seed, first, slices).is_err());
    }
}

fn bits<const D: usize>(p: &[f32; D]) -> [u32; D] {
    p.map(f32::to_bits)
}
