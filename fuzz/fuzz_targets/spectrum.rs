//! Fuzzes the direct periodogram (`linesample::spectrum`) through its public API.
//!
//! For arbitrary coordinates (any `f64`: huge, tiny, negative, NaN, ±∞), grid
//! half-widths, segment directions and lengths, and scratch sizes, it checks that
//!
//! * non-finite input and short buffers are rejected with errors, and leave the
//!   accumulator unchanged;
//! * the SIMD and the scalar path agree bit for bit, and the result does not
//!   depend on the chunk size (scratch length) or on feeding the samples in
//!   two calls;
//! * every amplitude is finite and `|F(ν)| ≤ Σ_k |w_k| ≤ N` (plus rounding);
//! * a periodogram of the realisation has `N·P(0) = N` and merges exactly.
//!
//! Run: `cargo fuzz run --sanitizer none spectrum`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::geom::Direction;
use linesample::primitive::Segment;
use linesample::spectrum::{AmplitudeView, Dft, Grid, Periodogram};

#[derive(Arbitrary, Debug)]
struct Input {
    dims: u8,
    k: u8,
    chunk_a: u8,
    chunk_b: u8,
    split: u8,
    segments: bool,
    length: f64,
    dir: [f64; 3],
    coords: Vec<f64>,
}

fn run<const D: usize>(inp: &Input) {
    // Small grids, and in 1D also k = 60..=139, across the switch to rows of
    // 64 frequencies at k = 64.
    let k = if D == 1 && inp.k >= 128 {
        60 + usize::from(inp.k % 80)
    } else {
        1 + usize::from(inp.k % 12)
    };
    let grid = Grid::<D>::new(k).expect("k in 1..=139 is valid");
    let pts: Vec<[f64; D]> = inp
        .coords
        .chunks_exact(D)
        .take(48)
        .map(|c| core::array::from_fn(|a| c[a]))
        .collect();
    let finite = pts.iter().all(|p| p.iter().all(|x| x.is_finite()));
    let per = if inp.segments {
        Dft::<D, Vec<f64>>::segments_scratch_per_sample(grid)
    } else {
        Dft::<D, Vec<f64>>::points_scratch_per_sample(grid)
    };
    let seg_dir = Direction::<D>::new(core::array::from_fn(|a| inp.dir[a])).ok();
    let segs: Option<Vec<Segment<D>>> = if inp.segments {
        let dir = match seg_dir {
            Some(d) => d,
            None => return,
        };
        if !finite {
            return; // Segment::new itself rejects non-finite centres.
        }
        pts.iter()
            .map(|p| Segment::new(*p, dir, inp.length).ok())
            .collect()
    } else {
        None
    };
    if inp.segments && segs.is_none() {
        return;
    }
    let feed = |dft: &mut Dft<D, Vec<f64>>,
                part: &[[f64; D]],
                first: usize,
                chunk: usize,
                scalar: bool| {
        let mut scratch = vec![0.0; chunk * per];
        match &segs {
            Some(s) => {
                let s = &s[first..first + part.len()];
                if scalar {
                    dft.add_segments_scalar(s, &mut scratch)
                } else {
                    dft.add_segments(s, &mut scratch)
                }
            }
            None => {
                if scalar {
                    dft.add_points_scalar(part, &mut scratch)
                } else {
                    dft.add_points(part, &mut scratch)
                }
            }
        }
    };
    let (ca, cb) = (
        1 + usize::from(inp.chunk_a % 64),
        1 + usize::from(inp.chunk_b % 7),
    );
    let mut a = Dft::new_vec(grid);
    let res = feed(&mut a, &pts, 0, ca, false);
    if !finite {
        assert!(res.is_err(), "non-finite coordinates must be rejected");
        assert_eq!(a.count(), 0);
        for i in 0..grid.len() {
            let c = a.amplitude_at(i);
            assert!(
                c.re == 0.0 && c.im == 0.0,
                "rejected input left amplitudes behind"
            );
        }
        return;
    }
    res.expect("finite input is accepted");
    // Short scratch is an error, not a panic.
    if !pts.is_empty() {
        let mut tiny = vec![0.0; Dft::<D, Vec<f64>>::points_scratch_per_sample(grid) - 1];
        assert!(a.clone().add_points(&pts[..1], &mut tiny).is_err());
    }
    let mut b = Dft::new_vec(grid);
    let split = usize::from(inp.split) % (pts.len() + 1);
    feed(&mut b, &pts[..split], 0, cb, true).unwrap();
    feed(&mut b, &pts[split..], split, ca, true).unwrap();
    let n = pts.len() as f64;
    for i in 0..grid.len() {
        let (x, y) = (a.amplitude_at(i), b.amplitude_at(i));
        assert_eq!(
            (x.re.to_bits(), x.im.to_bits()),
            (y.re.to_bits(), y.im.to_bits()),
            "SIMD/scalar or chunking mismatch at {:?}",
            grid.freq(i)
        );
        assert!(x.re.is_finite() && x.im.is_finite());
        assert!(
            x.abs() <= n * (1.0 + 1e-12) + 1e-12,
            "|F| = {} > N = {n}",
            x.abs()
        );
    }
    if pts.is_empty() {
        return;
    }
    let mut p = Periodogram::new_vec(grid);
    p.add(&a).unwrap();
    let dc = p.mean([0; D]).unwrap();
    assert!((dc - n).abs() <= 1e-12 * n, "DC {dc} != N {n}");
    let mut q = Periodogram::new_vec(grid);
    q.merge(&p).unwrap();
    q.merge(&p).unwrap();
    p.add(&b).unwrap();
    for i in 0..grid.len() {
        assert_eq!(p.mean_at(i).to_bits(), q.mean_at(i).to_bits());
    }
}

fuzz_target!(|inp: Input| {
    match inp.dims % 3 {
        0 => run::<1>(&inp),
        1 => run::<2>(&inp),
        _ => run::<3>(&inp),
    }
});
