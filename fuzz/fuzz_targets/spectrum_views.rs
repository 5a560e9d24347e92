//! Fuzzes the derived views of a periodogram on grids beyond `k = 12`
//! (1D up to `k = 300`, 2D up to 32, 3D up to 13): `radial_average`, `slice`,
//! `predict_variance`, `radial_variance`, `Grid::radial_mean_of`, and the line
//! spectrum (`line_offsets` + `line_spectrum`), for points and segments.
//!
//! Oracles (recomputed here over the full grid `[−k, k]^D` from `Periodogram::mean`):
//! * amplitudes equal the naive sum `Σ_k e^{−2πi ν·x_k}` (segments:
//!   `× sinc(λ ν·ω)`), phases formed here in `f64`, for coordinates in `[−4, 4]`,
//!   within `N·(2π·u·Σ_a |ν_a|(|x_a| + λ) + 1e−14)`;
//! * `radial_average` = the mean of `⟨N·P(ν)⟩` over the full-grid frequencies with
//!   `round(|ν|) = r` (relative `1e−12`), `count` = their number (exactly);
//! * `slice(dir)` = `⟨N·P(t·dir)⟩` for `t = 0, 1, …` while in the grid;
//! * `predict_variance(n, p_f)` = `(1/n) Σ_{ν≠0} ⟨N·P(ν)⟩ p_f(ν)` and
//!   `pf_in_grid = Σ_{ν≠0} p_f(ν)` (relative `1e−12`), for an even `p_f` from the
//!   input; for a `p_f` constant on rings (zero past ring `k`), `radial_variance` of
//!   the ring means equals it (relative `1e−12`);
//! * 2D points: the 1D spectrum of the axis-line offsets equals the 2D spectrum on
//!   the line `ν_axis = 0` (a line integrates out its axis) and is 0 off it.
//!
//! Run: `cargo fuzz run --sanitizer none spectrum_views`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::geom::Direction;
use linesample::num::sinc;
use linesample::primitive::Segment;
use linesample::spectrum::{
    line_offsets, line_spectrum, radial_variance, AmplitudeView, Dft, Grid, Periodogram,
};

#[derive(Arbitrary, Debug)]
struct Input {
    dims: u8,
    k: u16,
    segments: Option<(f64, [f64; 3])>,
    coords: Vec<f64>,
    slice: [i8; 3],
    pf: [f64; 4],
    n: u16,
    axis: u8,
}

const U: f64 = f64::EPSILON / 2.0;

fn full_grid<const D: usize>(k: i32) -> Vec<[i32; D]> {
    let mut out = vec![[0i32; D]];
    for a in 0..D {
        let mut next = Vec::new();
        for j in &out {
            for v in -k..=k {
                let mut j = *j;
                j[a] = v;
                next.push(j);
            }
        }
        out = next;
    }
    out
}

fn ring<const D: usize>(j: &[i32; D]) -> f64 {
    j.iter()
        .map(|&x| f64::from(x) * f64::from(x))
        .sum::<f64>()
        .sqrt()
        .round()
}

fn close(a: f64, b: f64, scale: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-12 * scale.abs().max(a.abs()).max(1e-300),
        "{what}: {a:e} vs {b:e}"
    );
}

fn run<const D: usize>(inp: &Input) {
    let k = 1 + usize::from(inp.k) % [300, 32, 13][D - 1];
    let grid = Grid::<D>::new(k).unwrap();
    let pts: Vec<[f64; D]> = inp
        .coords
        .chunks_exact(D)
        .take([32, 12, 6][D - 1])
        .map(|c| core::array::from_fn(|a| c[a]))
        .filter(|p: &[f64; D]| p.iter().all(|x| x.is_finite()))
        .collect();
    if pts.is_empty() {
        return;
    }
    let mut dft = Dft::new_vec(grid);
    let seg = match inp.segments {
        Some((len, w)) => {
            let Ok(dir) = Direction::<D>::new(core::array::from_fn(|a| w[a])) else {
                return;
            };
            let len = len.abs() % 4.0;
            let Some(segs) = pts
                .iter()
                .map(|p| Segment::new(*p, dir, len).ok())
                .collect::<Option<Vec<_>>>()
            else {
                return;
            };
            let mut s = vec![0.0; Dft::<D, Vec<f64>>::segments_scratch_per_sample(grid) * 4];
            dft.add_segments(&segs, &mut s).unwrap();
            Some((segs[0].length(), dir.get()))
        }
        None => {
            let mut s = vec![0.0; Dft::<D, Vec<f64>>::points_scratch_per_sample(grid) * 4];
            dft.add_points(&pts, &mut s).unwrap();
            None
        }
    };
    let n = pts.len() as f64;
    let kk = k as i32;
    let full = full_grid::<D>(kk);
    // Naive amplitudes on a sample of frequencies.
    if pts.iter().all(|p| p.iter().all(|x| x.abs() <= 4.0)) {
        let lam = seg.map_or(0.0, |s| s.0);
        for j in full.iter().step_by(1 + full.len() / 64) {
            let Some(c) = dft.amplitude(*j) else { continue };
            let (mut re, mut im) = (0.0, 0.0);
            for p in &pts {
                let ph: f64 = (0..D).map(|a| f64::from(j[a]) * p[a]).sum();
                let (s, co) = (2.0 * core::f64::consts::PI * ph).sin_cos();
                let wgt = match seg {
                    Some((l, w)) => sinc(l * (0..D).map(|a| f64::from(j[a]) * w[a]).sum::<f64>()),
                    None => 1.0,
                };
                re += wgt * co;
                im -= wgt * s;
            }
            let nu: f64 = (0..D).map(|a| f64::from(j[a].abs()) * (4.0 + lam)).sum();
            let tol = n * (2.0 * core::f64::consts::PI * U * nu * 8.0 + 1e-14);
            assert!(
                (c.re - re).abs() <= tol && (c.im - im).abs() <= tol,
                "F{j:?} = {c:?}, naive ({re}, {im}), tol {tol:e}"
            );
        }
    }
    let mut per = Periodogram::new_vec(grid);
    per.add(&dft).unwrap();
    let mean = |j: [i32; D]| per.mean(j).expect("frequency in the grid");
    // Radial average.
    let mut rm = vec![0.0; k + 1];
    let mut rc = vec![0u64; k + 1];
    per.radial_average(&mut rm, &mut rc).unwrap();
    let mut sum = vec![0.0; k + 1];
    let mut cnt = vec![0u64; k + 1];
    for j in &full {
        let r = ring(j) as usize;
        if r <= k {
            sum[r] += mean(*j);
            cnt[r] += 1;
        }
    }
    assert_eq!(rc, cnt, "ring counts");
    for r in 0..=k {
        let want = sum[r] / cnt[r] as f64;
        close(rm[r], want, n, &format!("ring {r}"));
    }
    // Slice.
    let dir: [i32; D] = core::array::from_fn(|a| i32::from(inp.slice[a] % 5));
    let mut out = vec![f64::NAN; 2 * k + 2];
    match per.slice(dir, &mut out) {
        Err(_) => assert!(dir.iter().all(|&x| x == 0)),
        Ok(m) => {
            let steps = (0..)
                .take_while(|t| dir.iter().all(|&d| (d * t).abs() <= kk))
                .count();
            assert_eq!(m, steps.min(out.len()), "slice length");
            for t in 0..m {
                let j = dir.map(|d| d * t as i32);
                assert_eq!(out[t].to_bits(), mean(j).to_bits(), "slice at {j:?}");
            }
        }
    }
    // Prediction with an even p_f.
    let c = inp
        .pf
        .map(|x| if x.is_finite() { x.abs() % 1e6 } else { 1.0 });
    let pf = |j: [i32; D]| {
        let r2: f64 = j.iter().map(|&x| f64::from(x) * f64::from(x)).sum();
        let ax: f64 = j.iter().map(|&x| f64::from(x.abs())).sum();
        c[0] / (1.0 + r2) + c[1] * (-ax / (1.0 + c[2])).exp()
    };
    let samples = 1 + u64::from(inp.n);
    let pred = per.predict_variance(samples, pf);
    let (mut s, mut f) = (0.0, 0.0);
    for j in &full {
        if j.iter().any(|&x| x != 0) {
            s += mean(*j) * pf(*j);
            f += pf(*j);
        }
    }
    close(
        pred.grid,
        s / samples as f64,
        s / samples as f64,
        "predict_variance",
    );
    close(pred.pf_in_grid, f, f, "pf_in_grid");
    // Ring-constant p_f: the radial form is exact.
    let radial = |j: [i32; D]| {
        let r = ring(&j);
        if r as usize > k {
            0.0
        } else {
            c[3] / (1.0 + r)
        }
    };
    let pr = per.predict_variance(samples, radial);
    let mut im = vec![0.0; k + 1];
    grid.radial_mean_of(radial, &mut im, &mut rc).unwrap();
    let rv = radial_variance(samples, &rm, &im, &rc).unwrap();
    close(rv, pr.grid, pr.grid, "radial_variance vs predict_variance");
    // Line spectrum in 2D.
    if D == 2 && seg.is_none() {
        let axis = usize::from(inp.axis % 2);
        let p2: Vec<[f64; 2]> = pts.iter().map(|p| [p[0], p[1 % D]]).collect();
        let mut offs = vec![[0.0f64; 1]; p2.len()];
        line_offsets::<2, 1, f64>(&p2, axis, &mut offs).unwrap();
        let g1 = Grid::<1>::new(k).unwrap();
        let mut d1 = Dft::new_vec(g1);
        let mut s1 = vec![0.0; Dft::<1, Vec<f64>>::points_scratch_per_sample(g1) * 4];
        d1.add_points(&offs, &mut s1).unwrap();
        let mut p1 = Periodogram::new_vec(g1);
        p1.add(&d1).unwrap();
        for v in -kk..=kk {
            let mut j = [0i32; 2];
            j[1 - axis] = v;
            let ls = line_spectrum::<2, 1, _>(&p1, axis, j).unwrap();
            let want = mean(core::array::from_fn(|a| j[a]));
            close(ls, want, n, &format!("line spectrum at {j:?}"));
            j[axis] = 1;
            assert_eq!(line_spectrum::<2, 1, _>(&p1, axis, j), Some(0.0));
        }
    }
}

fuzz_target!(|inp: Input| match inp.dims % 3 {
    0 => run::<1>(&inp),
    1 => run::<2>(&inp),
    _ => run::<3>(&inp),
});
