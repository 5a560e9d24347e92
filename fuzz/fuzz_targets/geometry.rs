//! Fuzzes `Direction::new`, `Line::new`, `Line::axis`, `Segment::new` and
//! `geom::clip_to_unit_box` with arbitrary `f64` input.
//!
//! Oracles:
//! * `Direction::new` accepts exactly the finite non-zero vectors and returns a unit
//!   vector (`| |ω|² − 1 | ≤ 8u`) parallel to the input (cross terms
//!   `≤ 8u·|v|²`, computed on the input scaled by its largest entry);
//! * `Line::new(p, ω)` rejects exactly the non-finite points; the stored point lies
//!   on the given line (its offset from `p` orthogonal to `ω` is within
//!   `4u·(|p| + |τ| + 1)`) and near the foot of the box centre
//!   (`|(c − q)·ω| ≤ 4u·(|p| + 1)` with `c = (½, …, ½)`);
//! * `clip_to_unit_box(q, ω)`: `t0 < t1`; both ends lie on the box boundary (every
//!   coordinate in `[−η, 1 + η]`, one within `η` of 0 or 1, `η = 8u·(|q| + |t|)`);
//!   the midpoint lies in the box; the chord is at most `√D`; and a line whose
//!   point is well inside the box (`q ∈ [0.01, 0.99]^D`) is never reported as
//!   missing it; a line that clips to `None` has no sampled point strictly inside;
//! * `Line::axis` reduces offsets modulo 1 and has chord exactly 1.
//!
//! Run: `cargo fuzz run --sanitizer none geometry`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::geom::{clip_to_unit_box, Direction};
use linesample::primitive::{Line, Segment};

const U: f64 = f64::EPSILON / 2.0;

#[derive(Arbitrary, Debug)]
struct Input {
    three: bool,
    p: [f64; 3],
    w: [f64; 3],
    len: f64,
    axis: u8,
    probe: [u16; 4],
}

fn norm<const D: usize>(v: &[f64; D]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn run<const D: usize>(inp: &Input) {
    let p: [f64; D] = core::array::from_fn(|j| inp.p[j]);
    let v: [f64; D] = core::array::from_fn(|j| inp.w[j]);
    let ok_dir = v.iter().all(|x| x.is_finite()) && v.iter().any(|&x| x != 0.0);
    let dir = match Direction::new(v) {
        Ok(d) => {
            assert!(ok_dir, "{v:?} accepted");
            d
        }
        Err(_) => {
            assert!(!ok_dir, "{v:?} rejected");
            return;
        }
    };
    let w = dir.get();
    let n2: f64 = w.iter().map(|x| x * x).sum();
    assert!((n2 - 1.0).abs() <= 8.0 * U, "|ω|² = {n2}");
    let big = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let vs: [f64; D] = core::array::from_fn(|j| v[j] / big);
    for a in 0..D {
        for b in a + 1..D {
            let cross = vs[a] * w[b] - vs[b] * w[a];
            assert!(
                cross.abs() <= 8.0 * U * norm(&vs),
                "ω {w:?} not parallel to {v:?}"
            );
        }
    }
    let s = Segment::new(p, dir, inp.len);
    let seg_ok = p.iter().all(|x| x.is_finite()) && inp.len.is_finite() && inp.len >= 0.0;
    if s.is_ok() {
        assert!(seg_ok);
    }
    let line = match Line::new(p, dir) {
        Ok(l) => {
            assert!(p.iter().all(|x| x.is_finite()));
            l
        }
        Err(_) => {
            assert!(p.iter().any(|x| !x.is_finite()));
            return;
        }
    };
    let q = line.point();
    let pn = norm(&p);
    let d: [f64; D] = core::array::from_fn(|j| q[j] - p[j]);
    let tau: f64 = (0..D).map(|j| d[j] * w[j]).sum();
    let perp: [f64; D] = core::array::from_fn(|j| d[j] - tau * w[j]);
    let tol = 4.0 * U * (pn + tau.abs() + 1.0) * (D as f64);
    assert!(
        norm(&perp) <= tol,
        "stored point {q:?} off the line through {p:?} by {:e}",
        norm(&perp)
    );
    let foot: f64 = (0..D).map(|j| (0.5 - q[j]) * w[j]).sum();
    assert!(
        foot.abs() <= tol,
        "stored point {q:?} is {foot:e} from the foot"
    );
    let clip = clip_to_unit_box(&q, &dir);
    let inside = q.iter().all(|&x| (0.01..=0.99).contains(&x));
    match clip {
        None => {
            assert!(!inside, "line through {q:?} (inside) reported as missing");
            for &k in &inp.probe {
                let t = (f64::from(k) / 65535.0 - 0.5) * 2.0 * (D as f64).sqrt();
                let x: [f64; D] = core::array::from_fn(|j| q[j] + t * w[j]);
                assert!(
                    !x.iter().all(|&c| (1e-9..=1.0 - 1e-9).contains(&c)),
                    "missed line has {x:?} strictly inside"
                );
            }
        }
        Some((t0, t1)) => {
            assert!(t0 < t1);
            // Found by this target (tests/fuzz_regressions.rs,
            // `line_far_along_its_direction_keeps_its_chord`): a point given far
            // along the line once left the stored point ulp(τ) from the box.
            assert!(
                t1 - t0 <= (D as f64).sqrt() * (1.0 + 8.0 * U),
                "chord {} > √D",
                t1 - t0
            );
            let qn = norm(&q);
            for t in [t0, t1] {
                let x: [f64; D] = core::array::from_fn(|j| q[j] + t * w[j]);
                let eta = 8.0 * U * (qn + t.abs() + 1.0);
                assert!(
                    x.iter().all(|&c| c >= -eta && c <= 1.0 + eta),
                    "end {x:?} outside"
                );
                assert!(
                    x.iter().any(|&c| c.abs() <= eta || (c - 1.0).abs() <= eta),
                    "end {x:?} not on the boundary"
                );
            }
            let tm = 0.5 * (t0 + t1);
            let m: [f64; D] = core::array::from_fn(|j| q[j] + tm * w[j]);
            let eta = 8.0 * U * (qn + tm.abs() + 1.0);
            assert!(
                m.iter().all(|&c| c >= -eta && c <= 1.0 + eta),
                "midpoint {m:?} outside"
            );
        }
    }
    // Axis lines: offsets reduced modulo 1, chord exactly 1.
    let axis = usize::from(inp.axis) % D;
    let off: Vec<f64> = (0..D - 1).map(|j| inp.p[j]).collect();
    if let Ok(l) = Line::<D>::axis(axis, &off) {
        let q = l.point();
        let mut k = 0;
        for j in 0..D {
            if j != axis {
                assert!((0.0..1.0).contains(&q[j]), "axis line offset {q:?}");
                k += 1;
            }
        }
        assert_eq!(k, D - 1);
        let (t0, t1) = clip_to_unit_box(&q, &l.dir()).expect("an axis line crosses the box");
        assert_eq!(t1 - t0, 1.0);
    } else {
        assert!(off.iter().any(|x| !x.is_finite()));
    }
}

fuzz_target!(|inp: Input| {
    if inp.three {
        run::<3>(&inp);
    } else {
        run::<2>(&inp);
    }
});
