//! Fuzzes `Ccvt` (capacity-constrained Voronoi point sets) with arbitrary
//! parameters, kept small (`N, c ≤ 16`, at most 30 iterations) so that one run
//! takes about a millisecond.
//!
//! Checks, recomputed here from the result (not from the kernel's helpers):
//! * rejected parameters are errors; `N` sites and `N·c` discrete points, all in
//!   `[0, 1)`; `assignment[k] < N` and every site owns exactly `c` points (counted
//!   from `assignment`), and `capacities()` says so;
//! * the discrete density: at most one point per cell of the `g^D` grid
//!   (`g = ⌈(N·c)^{1/D}⌉`), each within `δ/2` of its cell centre (in cell units);
//! * in a converged run every site is the toroidal centroid of its points
//!   (`|mean wrap(x − s)| ≤ 1e−9`, when all offsets are below 1/4, so that no offset
//!   crosses the wrap);
//! * `energy()` equals the mean squared toroidal distance to the owning site
//!   (relative `1e−9`), and the traced energy never increases by more than rounding;
//! * when `converged()`, no pair of sites can lower the energy by exchanging one
//!   point each: `max_x h_i(x) + max_y h_j(y) ≤ 1e−12` for all pairs (the stopping
//!   rule, checked over all pairs rather than the kernel's neighbour pairs);
//! * the result is a function of the seed (checked for `N·c ≤ 64`).
//!
//! Run: `cargo fuzz run --sanitizer none ccvt`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::pattern::{Ccvt, CcvtResult};
use linesample::Seed;

#[derive(Arbitrary, Debug)]
struct Input {
    three: bool,
    n: u64,
    capacity: u64,
    iterations: u64,
    jitter: f64,
    seed: u64,
}

fn wrap(d: f64) -> f64 {
    d - (d + 0.5).floor()
}

fn dist2<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    (0..D).map(|j| wrap(a[j] - b[j]).powi(2)).sum()
}

fn run<const D: usize>(inp: &Input) {
    // Constructors: any value is accepted or rejected without a panic.
    let _ = Ccvt::<D>::new(inp.n as usize);
    let n = 1 + (inp.n % 16) as usize;
    let c = 1 + (inp.capacity % 16) as usize;
    let Ok(base) = Ccvt::<D>::new(n) else {
        panic!("n = {n} rejected")
    };
    let _ = base.clone().capacity(inp.capacity as usize);
    let _ = base.clone().max_iterations(inp.iterations as usize);
    let cc = base.capacity(c).unwrap();
    let cc = cc
        .max_iterations(1 + (inp.iterations % 30) as usize)
        .unwrap();
    let cc = match cc.clone().jitter(inp.jitter) {
        Ok(j) => {
            assert!((0.0..=1.0).contains(&inp.jitter));
            j
        }
        Err(_) => {
            assert!(!(0.0..=1.0).contains(&inp.jitter));
            cc
        }
    };
    let delta = if (0.0..=1.0).contains(&inp.jitter) {
        inp.jitter
    } else {
        Ccvt::<D>::DEFAULT_JITTER
    };
    let seed = Seed::new(inp.seed);
    let mut trace = Vec::new();
    let r: CcvtResult<D> = cc.generate_with_trace(seed, &mut |t, e| trace.push((t, e)));
    let m = n * c;
    let sites = r.sites_f64();
    let pts = r.discrete_points();
    let asg = r.assignment();
    assert_eq!(r.sites().len(), n);
    assert_eq!(sites.len(), n);
    assert_eq!(pts.len(), m);
    assert_eq!(asg.len(), m);
    for s in r.sites() {
        assert!(s.iter().all(|x| (0.0..1.0).contains(x)), "site {s:?}");
    }
    for p in pts {
        assert!(p.iter().all(|x| (0.0..1.0).contains(x)), "point {p:?}");
    }
    let mut own = vec![0usize; n];
    for &a in asg {
        assert!((a as usize) < n);
        own[a as usize] += 1;
    }
    assert!(own.iter().all(|&k| k == c), "site loads {own:?} (c = {c})");
    assert_eq!(r.capacities(), own);
    // Discrete density: one point per cell, jittered by at most δ/2.
    let g = (1..).find(|&g: &usize| g.pow(D as u32) >= m).unwrap();
    let mut cells = std::collections::HashSet::new();
    for p in pts {
        let mut key = 0usize;
        for j in 0..D {
            let y = p[j] * g as f64;
            let cell = y.floor();
            let off = (y - cell - 0.5).abs();
            assert!(
                off <= delta / 2.0 + 1e-9,
                "point {p:?} off-centre {off} > δ/2 = {}",
                delta / 2.0
            );
            key = key * g + cell as usize;
        }
        assert!(cells.insert(key), "two discrete points in one cell");
    }
    // Centroids and energy.
    let mut energy = 0.0;
    for i in 0..n {
        let mut sum = [0.0f64; D];
        let mut far = 0.0f64;
        for (k, p) in pts.iter().enumerate() {
            if asg[k] as usize == i {
                for j in 0..D {
                    let e = wrap(p[j] - sites[i][j]);
                    sum[j] += e;
                    far = far.max(e.abs());
                }
                energy += dist2(p, &sites[i]);
            }
        }
        // Only for a converged run: a centroid step is taken in the frame of the
        // site before the step, so after an unfinished run a site whose points
        // straddled ±1/2 from its old position can be one point's worth (1/c) off
        // (seen at N = 13, c = 13 after 1 iteration).
        if far < 0.25 && r.converged() {
            for j in 0..D {
                let mean = sum[j] / c as f64;
                assert!(
                    mean.abs() <= 1e-9,
                    "site {i} is {mean:e} off its centroid on axis {j}"
                );
            }
        }
    }
    energy /= m as f64;
    assert!(
        (r.energy() - energy).abs() <= 1e-9 * energy.max(1e-300),
        "energy {} vs recomputed {energy}",
        r.energy()
    );
    for w in trace.windows(2) {
        assert!(
            w[1].1 <= w[0].1 * (1.0 + 1e-9) + 1e-15,
            "energy rose: {trace:?}"
        );
    }
    assert_eq!(trace.len(), r.iterations() + 1);
    if r.converged() {
        // Stable: no exchange between any pair lowers the energy.
        for i in 0..n {
            for j in i + 1..n {
                let mut hi = f64::NEG_INFINITY;
                let mut hj = f64::NEG_INFINITY;
                for (k, p) in pts.iter().enumerate() {
                    let a = asg[k] as usize;
                    if a == i {
                        hi = hi.max(dist2(p, &sites[i]) - dist2(p, &sites[j]));
                    } else if a == j {
                        hj = hj.max(dist2(p, &sites[j]) - dist2(p, &sites[i]));
                    }
                }
                assert!(
                    hi + hj <= 1e-12,
                    "sites {i}, {j}: an exchange saves {}",
                    hi + hj
                );
            }
        }
    }
    if m <= 64 {
        let again = cc.generate(seed);
        assert_eq!(again.sites_f64(), sites, "not a function of the seed");
    }
}

fuzz_target!(|inp: Input| {
    if inp.three {
        run::<3>(&inp);
    } else {
        run::<2>(&inp);
    }
});
