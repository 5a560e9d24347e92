//! Fuzzes every estimator (`PointEstimator`, `SegmentEstimator`, `LineEstimator`
//! with fixed, random and grouped directions), `run_realisations` and
//! `RunningStats::merge` with arbitrary parameters.
//!
//! Checks:
//! * rejected parameters are errors (never panics); a scratch buffer shorter than
//!   `scratch_len` is an error; a longer one gives the same bits;
//! * an estimate is finite, `≥ 0` and at most the largest possible summand
//!   (`max_value` for points and segments, `A·√D·max_value` for lines, `A ≤ D^{(D−1)/2}`
//!   the offset-rectangle area), and a function of the seed only (bit for bit);
//! * for the integrand `f ≡ 1` (a half-space containing the whole box), every
//!   point, segment and axis-line estimate is 1 to within `1e-12` — a summand that
//!   is off (a wrong normalisation, a piece dropped or counted twice at a cell
//!   face) shows here;
//! * `run_realisations` over `first .. first + count` equals the in-order merge of
//!   the same range cut into arbitrary parts, and `RunningStats` of arbitrary
//!   values pushed in one pass equals the merge of different parts of them, both
//!   within the rounding bound derived in `common/stats.rs`.
//!
//! Run: `cargo fuzz run --sanitizer none estimators`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::estimator::{
    run_realisations, Directions, Estimator, LineEstimator, PointEstimator, SegmentEstimator,
};
use linesample::geom::Direction;
use linesample::integrand::{Ball, Gaussian, HalfSpace, Integrand};
use linesample::pattern::{Halton, Jittered, NRooks, Pattern, Random, Sobol};
use linesample::Seed;

#[path = "common/stats.rs"]
mod stats;
use stats::{assert_merge_matches, one_pass_and_merged};

#[derive(Arbitrary, Debug)]
enum Kind {
    Point,
    Segment(f64),
    Line,
}

#[derive(Arbitrary, Debug)]
enum Dirs {
    Fixed([f64; 3]),
    Axis(u8),
    Random,
    Groups(Vec<[f64; 3]>),
}

#[derive(Arbitrary, Debug)]
struct Input {
    three_d: bool,
    kind: Kind,
    dirs: Dirs,
    pattern: u8,
    n: u8,
    integrand: u8,
    params: [f64; 4],
    seed: u64,
    homogenise: bool,
    first: u16,
    count: u8,
    cuts: Vec<u8>,
    values: Vec<f64>,
}

fn pattern<const K: usize>(sel: u8, n: u8) -> Option<Box<dyn Pattern<K>>> {
    let n = 1 + usize::from(n % 48);
    Some(match sel % 5 {
        0 => Box::new(Random::<K>::new(n).ok()?),
        1 => Box::new(Jittered::<K>::cube(1 + n % 6).ok()?),
        2 => Box::new(Sobol::<K>::new(n).ok()?),
        3 => Box::new(Halton::<K>::new(n).ok()?),
        _ => Box::new(NRooks::<K>::new(n).ok()?),
    })
}

fn integrand<const D: usize>(sel: u8, p: &[f64; 4]) -> Option<Box<dyn Integrand<D>>> {
    let c: [f64; D] = core::array::from_fn(|j| p[j]);
    Some(match sel % 4 {
        0 => Box::new(Ball::<D>::new(c, p[3]).ok()?),
        1 => Box::new(Gaussian::<D>::new(c, p[3]).ok()?),
        2 => Box::new(HalfSpace::<D>::new(Direction::new(c).ok()?, p[3]).ok()?),
        // f ≡ 1: the half-space x_0 ≥ −1 contains the whole box.
        _ => Box::new(one::<D>()),
    })
}

fn one<const D: usize>() -> HalfSpace<D> {
    HalfSpace::<D>::new(Direction::axis(0).unwrap(), -1.0).unwrap()
}

fn dir<const D: usize>(v: &[f64; 3]) -> Option<Direction<D>> {
    Direction::new(core::array::from_fn(|j| v[j])).ok()
}

fn run<const D: usize, const K: usize>(inp: &Input) {
    let Some(f) = integrand::<D>(inp.integrand, &inp.params) else {
        return;
    };
    let group_dirs: Vec<Direction<D>> = match &inp.dirs {
        Dirs::Groups(g) => g.iter().take(4).filter_map(dir::<D>).collect(),
        _ => Vec::new(),
    };
    let dirs: Directions<'_, D> = match &inp.dirs {
        Dirs::Fixed(v) => match dir::<D>(v) {
            Some(d) => Directions::Fixed(d),
            None => return,
        },
        Dirs::Axis(a) => Directions::Fixed(Direction::axis(usize::from(*a) % D).unwrap()),
        Dirs::Random => Directions::Random,
        Dirs::Groups(_) => Directions::Groups(&group_dirs),
    };
    let axis_only = match &dirs {
        Directions::Fixed(d) => d.as_axis().is_some(),
        Directions::Groups(g) => g.iter().all(|d| d.as_axis().is_some()),
        Directions::Random => false,
    };
    let maxv = f.max_value();
    let pd = pattern::<D>(inp.pattern, inp.n);
    let pk = pattern::<K>(inp.pattern, inp.n);
    let (est, bound, constant_one): (Box<dyn Estimator<D> + '_>, f64, bool) = match inp.kind {
        Kind::Point => {
            let Some(p) = pd.as_deref() else {
                return;
            };
            (Box::new(PointEstimator::new(p).unwrap()), maxv, true)
        }
        Kind::Segment(len) => {
            let Some(p) = pd.as_deref() else {
                return;
            };
            // Lengths beyond 8 only cost time (linear in λ).
            if !(len.abs() <= 8.0) {
                assert!(SegmentEstimator::new(p, len, dirs).is_err() || len.abs() <= 1048576.0);
                return;
            }
            match SegmentEstimator::new(p, len, dirs) {
                Ok(e) => (Box::new(e), maxv, true),
                Err(_) => {
                    assert!(len < 0.0 || group_dirs.is_empty(), "length {len} rejected");
                    return;
                }
            }
        }
        Kind::Line => {
            let Some(p) = pk.as_deref() else {
                return;
            };
            let Ok(e) = LineEstimator::<D, K>::new(p, dirs) else {
                return;
            };
            let area = (D as f64).powf((D as f64 - 1.0) / 2.0);
            (Box::new(e), area * (D as f64).sqrt() * maxv, axis_only)
        }
    };
    let seed = Seed::new(inp.seed);
    let need = est.scratch_len();
    let mut scratch = vec![0.0f32; need];
    let v = est
        .estimate(f.as_ref(), seed, inp.homogenise, &mut scratch)
        .expect("scratch of scratch_len is accepted");
    assert!(v.is_finite() && v >= 0.0, "estimate {v}");
    assert!(
        v <= bound * (1.0 + 1e-9),
        "estimate {v} > largest summand {bound}"
    );
    let mut longer = vec![7.0f32; need + 5];
    let w = est
        .estimate(f.as_ref(), seed, inp.homogenise, &mut longer)
        .unwrap();
    assert_eq!(v.to_bits(), w.to_bits(), "estimate depends on the scratch");
    if need > 0 {
        let mut short = vec![0.0f32; need - 1];
        assert!(est
            .estimate(f.as_ref(), seed, inp.homogenise, &mut short)
            .is_err());
    }
    if constant_one {
        let o = one::<D>();
        let v1 = est
            .estimate(&o, seed, inp.homogenise, &mut scratch)
            .unwrap();
        assert!((v1 - 1.0).abs() <= 1e-12, "estimate of f = 1 is {v1}");
    }
    // run_realisations: one range vs the merge of its parts.
    let first = u64::from(inp.first);
    let count = u64::from(inp.count % 12);
    let all = run_realisations(
        est.as_ref(),
        f.as_ref(),
        seed,
        first,
        count,
        inp.homogenise,
        &mut scratch,
    )
    .unwrap();
    let xs: Vec<f64> = (first..first + count)
        .map(|r| {
            est.estimate(
                f.as_ref(),
                seed.realization(r),
                inp.homogenise,
                &mut scratch,
            )
            .unwrap()
        })
        .collect();
    let mut cuts: Vec<u64> = inp
        .cuts
        .iter()
        .take(6)
        .map(|&c| u64::from(c) % (count + 1))
        .collect();
    cuts.push(0);
    cuts.push(count);
    cuts.sort_unstable();
    let mut merged = linesample::stats::RunningStats::new();
    for w in cuts.windows(2) {
        let part = run_realisations(
            est.as_ref(),
            f.as_ref(),
            seed,
            first + w[0],
            w[1] - w[0],
            inp.homogenise,
            &mut scratch,
        )
        .unwrap();
        merged.merge(&part);
    }
    assert_merge_matches(&all, &merged, &xs);
}

fuzz_target!(|inp: Input| {
    // RunningStats of arbitrary values: one pass vs merged parts. Values are kept
    // below 1e60 so that fourth powers stay finite.
    let xs: Vec<f64> = inp
        .values
        .iter()
        .take(256)
        .copied()
        .filter(|x| x.is_finite() && x.abs() < 1e60)
        .collect();
    let (one, merged) = one_pass_and_merged(&xs, &inp.cuts);
    assert_merge_matches(&one, &merged, &xs);
    if inp.three_d {
        run::<3, 2>(&inp);
    } else {
        run::<2, 1>(&inp);
    }
});
