//! Tolerance sweep of the type-1 NUFFT (`linesample_nufft`) on the
//! issue's benchmark cases, with accuracy against an exact direct sum.
//!
//! ```text
//! cargo run --release -p linesample-nufft --example nufft_bench -- [--json] [--runs R]
//!     [--sigma auto|auto-k|2|1.25|both] [--case 2d-65536|2d-4096|3d-4096] [--tols 1e-6,1e-12]
//!     [--ref-dir DIR]
//! ```
//!
//! `--ref-dir DIR` also writes each case's direct-sum reference as raw
//! little-endian f64 files `DIR/<case>.re`, `DIR/<case>.im` (half grid, output
//! order), which `nufft/tools/finufft_bench.py --ref-dir DIR` uses to measure
//! FINUFFT's error on the same points.
//!
//! `--sigma auto` (default) is `Plan::new_for_points` (σ from the cost model
//! with the point count), `auto-k` is `Plan::new` (σ from ε alone).
//!
//! For every case and tolerance ε ∈ {1e-3, …, 1e-12} it prints σ, the kernel
//! width w, the fine-grid size n, the plan time, the median over `R ≥ 7` runs
//! of `Plan::transform`, its phase split (spread / FFT / deconvolve, from the
//! median run), and the relative l2 error ‖F − F_exact‖₂/‖F_exact‖₂ and max
//! |F − F_exact| / N against a separable direct DFT computed once per case.
//! Points are uniform in [0,1)^D from SplitMix64 with seed 42 (the same stream
//! `nufft/tools/finufft_bench.py` uses, so both time identical point sets).

use std::f64::consts::PI;
use std::time::Instant;

use linesample_nufft::{Plan, Upsampling};

/// The shared SplitMix64 points (seed 42; the Python FINUFFT script uses the
/// same stream).
fn points<const D: usize>(n: usize) -> Vec<[f64; D]> {
    linesample_nufft::testdata::points::<D>(42, n)
}

/// Exact e^{−2πi j x} for j ∈ [−K, K] (index j + K), reducing j·x mod 1 first.
fn phase_table(x: f64, k: usize, re: &mut [f64], im: &mut [f64]) {
    for (i, (r, m)) in re.iter_mut().zip(im.iter_mut()).enumerate() {
        let j = i as f64 - k as f64;
        let t = j * x;
        let a = -2.0 * PI * (t - t.round());
        *r = a.cos();
        *m = a.sin();
    }
}

/// Separable direct DFT on the half grid: O(N K^D).
fn direct<const D: usize>(pts: &[[f64; D]], k: usize) -> (Vec<f64>, Vec<f64>) {
    let m = 2 * k + 1;
    let len = (k + 1) * m.pow(D as u32 - 1);
    let (mut fr, mut fi) = (vec![0.0; len], vec![0.0; len]);
    let mut tr = vec![vec![0.0; m]; D];
    let mut ti = vec![vec![0.0; m]; D];
    let (mut ar, mut ai) = (vec![0.0; m], vec![0.0; m]);
    for p in pts {
        for d in 0..D {
            phase_table(p[d], k, &mut tr[d], &mut ti[d]);
        }
        // axis 0 only j0 ∈ [0, K]: entries k..=2k of the table.
        for j0 in 0..=k {
            let (r0, i0) = (tr[0][k + j0], ti[0][k + j0]);
            if D == 1 {
                fr[j0] += r0;
                fi[j0] += i0;
                continue;
            }
            for j1 in 0..m {
                let (r1, i1) = (tr[1][j1], ti[1][j1]);
                let (r01, i01) = (r0 * r1 - i0 * i1, r0 * i1 + i0 * r1);
                if D == 2 {
                    fr[j0 * m + j1] += r01;
                    fi[j0 * m + j1] += i01;
                    continue;
                }
                for j2 in 0..m {
                    ar[j2] = r01 * tr[2][j2] - i01 * ti[2][j2];
                    ai[j2] = r01 * ti[2][j2] + i01 * tr[2][j2];
                }
                let off = (j0 * m + j1) * m;
                for j2 in 0..m {
                    fr[off + j2] += ar[j2];
                    fi[off + j2] += ai[j2];
                }
            }
        }
    }
    (fr, fi)
}

struct Opts {
    json: bool,
    runs: usize,
    sigma: String,
    cases: Vec<String>,
    tols: Vec<f64>,
    ref_dir: Option<String>,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn run_case<const D: usize>(name: &str, n_pts: usize, k: usize, o: &Opts) {
    let pts = points::<D>(n_pts);
    let t = Instant::now();
    let (er, ei) = direct::<D>(&pts, k);
    let direct_s = t.elapsed().as_secs_f64();
    if let Some(dir) = &o.ref_dir {
        for (ext, v) in [("re", &er), ("im", &ei)] {
            let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
            std::fs::write(format!("{dir}/{name}.{ext}"), bytes).expect("write reference");
        }
    }
    if !o.json {
        println!(
            "\n== {name}: D={D} N={n_pts} K={k} ({} modes), direct sum {direct_s:.2} s",
            er.len()
        );
        println!(
            "{:>7} {:>5} {:>3} {:>5} {:>8} {:>9} {:>8} {:>8} {:>8} {:>10} {:>10}",
            "tol",
            "sigma",
            "w",
            "n",
            "plan_ms",
            "median_ms",
            "spr_ms",
            "fft_ms",
            "dec_ms",
            "rel_l2",
            "maxabs/N"
        );
    }
    let norm: f64 = er.iter().chain(&ei).map(|v| v * v).sum::<f64>().sqrt();
    for &tol in &o.tols {
        let sigmas: Vec<Option<Upsampling>> = match o.sigma.as_str() {
            "2" => vec![Some(Upsampling::Two)],
            "1.25" => vec![Some(Upsampling::FiveQuarters)],
            "both" => vec![Some(Upsampling::FiveQuarters), Some(Upsampling::Two)],
            _ => vec![None],
        };
        for s in sigmas {
            let t = Instant::now();
            let mut plan = match s {
                Some(s) => Plan::<D>::with_upsampling(k, tol, s),
                None if o.sigma == "auto-k" => Plan::<D>::new(k, tol),
                None => Plan::<D>::new_for_points(k, tol, n_pts),
            }
            .expect("valid plan");
            let plan_ms = t.elapsed().as_secs_f64() * 1e3;
            let (mut re, mut im) = (vec![0.0; plan.half_len()], vec![0.0; plan.half_len()]);
            plan.transform(&pts, &mut re, &mut im)
                .expect("finite points"); // warm-up
            let mut times = Vec::new();
            let mut phases = Vec::new();
            for _ in 0..o.runs {
                let t = Instant::now();
                plan.transform(&pts, &mut re, &mut im)
                    .expect("finite points");
                times.push(t.elapsed().as_secs_f64() * 1e3);
                phases.push(plan.phase_times());
            }
            let med = median(times.clone());
            let mi = times.iter().position(|&x| x == med).unwrap_or(0);
            let ph = phases[mi];
            let (mut num, mut mx) = (0.0f64, 0.0f64);
            for i in 0..re.len() {
                let d = (re[i] - er[i]).powi(2) + (im[i] - ei[i]).powi(2);
                num += d;
                mx = mx.max(d.sqrt());
            }
            let rel = num.sqrt() / norm;
            let sig = plan.upsampling().factor();
            if o.json {
                println!(
                    "{{\"case\":\"{name}\",\"d\":{D},\"n_pts\":{n_pts},\"k\":{k},\"tol\":{tol:e},\"sigma\":{sig},\"w\":{},\"n\":{},\"plan_ms\":{plan_ms:.4},\"median_ms\":{med:.4},\"spread_ms\":{:.4},\"fft_ms\":{:.4},\"deconv_ms\":{:.4},\"rel_l2\":{rel:e},\"maxabs_over_n\":{:e}}}",
                    plan.kernel_width(),
                    plan.fine_size(),
                    ph.spread * 1e3,
                    ph.fft * 1e3,
                    ph.deconvolve * 1e3,
                    mx / n_pts as f64
                );
            } else {
                println!(
                    "{tol:>7.0e} {sig:>5} {:>3} {:>5} {plan_ms:>8.2} {med:>9.3} {:>8.3} {:>8.3} {:>8.3} {rel:>10.2e} {:>10.2e}",
                    plan.kernel_width(),
                    plan.fine_size(),
                    ph.spread * 1e3,
                    ph.fft * 1e3,
                    ph.deconvolve * 1e3,
                    mx / n_pts as f64
                );
            }
        }
    }
}

fn main() {
    let mut o = Opts {
        json: false,
        runs: 9,
        sigma: "auto".into(),
        cases: vec!["2d-65536".into(), "2d-4096".into(), "3d-4096".into()],
        tols: (3..=12).map(|e| 10f64.powi(-e)).collect(),
        ref_dir: None,
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let val = || args.get(i + 1).cloned().expect("option needs a value");
        match args[i].as_str() {
            "--json" => o.json = true,
            "--runs" => {
                o.runs = val().parse::<usize>().expect("--runs N").max(1);
                i += 1;
            }
            "--sigma" => {
                o.sigma = val();
                i += 1;
            }
            "--ref-dir" => {
                o.ref_dir = Some(val());
                i += 1;
            }
            "--case" => {
                o.cases = val().split(',').map(String::from).collect();
                i += 1;
            }
            "--tols" => {
                o.tols = val()
                    .split(',')
                    .map(|t| t.parse().expect("--tols a,b,c"))
                    .collect();
                i += 1;
            }
            other => panic!("unknown argument {other}"),
        }
        i += 1;
    }
    for c in o.cases.clone() {
        match c.as_str() {
            "2d-65536" => run_case::<2>(&c, 65536, 128, &o),
            "2d-4096" => run_case::<2>(&c, 4096, 319, &o),
            "3d-4096" => run_case::<3>(&c, 4096, 32, &o),
            other => panic!("unknown case {other}"),
        }
    }
}
