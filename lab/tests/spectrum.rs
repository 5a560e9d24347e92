//! `spectrum`: the binary end to end, and the experiment directly.

mod common;

use std::fs;
use std::path::PathBuf;

use clap::Parser;
use common::*;
use linesample_lab::cli::{Cli, Command};
use linesample_lab::experiments::spectrum::{self, Spectrum};
use linesample_lab::runner::{self, Experiment};

#[test]
fn of_random_points() {
    let dir = TempDir::new("spectrum");
    let o = lab(
        &dir,
        &[
            "spectrum",
            "--sampler",
            "random",
            "-n",
            "64",
            "--k",
            "8",
            "--realizations",
            "8",
            "--out",
            "res/white",
        ],
    );
    ok(&o, "spectrum");
    let out = stdout(&o);
    assert!(out.contains("N = 64, k = 8"), "{out}");
    assert!(out.contains("ms/real."), "{out}");
    let rows = spectrum_rows(&dir.path().join("res/white/spectrum-radial.csv"));
    assert_eq!(rows.len(), 8);
    let counts = ring_counts(8, 2);
    assert_eq!(counts[1], 8); // |ν|² ∈ {1, 2}
    for (i, &(r, mean, se, count)) in rows.iter().enumerate() {
        assert_eq!(r, i + 1);
        assert_eq!(count, counts[r], "ring {r}");
        assert!(se > 0.0 && se.is_finite(), "ring {r}: se {se}");
        if r >= 4 {
            // White noise: <N·P> = 1 at every ν ≠ 0.
            assert!((mean - 1.0).abs() < 5.0 * se, "ring {r}: {mean} ± {se}");
        }
    }
    // 17 frequencies per side, upscaled 16x to at least 256 pixels; the DC
    // pixel block in the centre is white.
    let (w, h, px) = png_gray(&dir.path().join("res/white/spectrum.png"));
    assert_eq!((w, h), (17 * 16, 17 * 16));
    assert_eq!(px[(8 * 16 + 3) * 272 + 8 * 16 + 3], 255);
    let svg = fs::read_to_string(dir.path().join("res/white/spectrum-radial.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("random 2D points, N = 64, R = 8"), "title");
    no_tmp_files(&dir);
    assert_eq!(
        dir.files(),
        [
            "res/white/manifest.json",
            "res/white/spectrum-radial.csv",
            "res/white/spectrum-radial.svg",
            "res/white/spectrum.png"
        ]
        .map(PathBuf::from)
    );
}

#[test]
fn independent_of_the_thread_count() {
    let dir = TempDir::new("spectrum-threads");
    let run = |threads: &str| {
        let out = format!("t{threads}");
        ok(
            &lab(
                &dir,
                &[
                    "spectrum",
                    "--sampler",
                    "jittered",
                    "-n",
                    "64",
                    "--k",
                    "12",
                    "--realisations",
                    "21",
                    "--seed",
                    "3",
                    "--threads",
                    threads,
                    "--out",
                    &out,
                ],
            ),
            threads,
        );
        (
            fs::read(dir.path().join(format!("{out}/spectrum-radial.csv"))).unwrap(),
            fs::read(dir.path().join(format!("{out}/spectrum.png"))).unwrap(),
            fs::read(dir.path().join(format!("{out}/spectrum-radial.svg"))).unwrap(),
        )
    };
    let one = run("1");
    assert_eq!(one, run("3"), "--threads 3 differs from --threads 1");
    no_tmp_files(&dir);
}

#[test]
fn reads_point_files() {
    let dir = TempDir::new("spectrum-input");
    let mut state = 12345u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut plain = String::from("# made elsewhere\n\n");
    let mut utk = String::from("40\n");
    for i in 0..40 {
        let (x, y) = (next(), next());
        // One coordinate outside [0, 1): wrapped with a note.
        let x = if i == 5 { x + 1.0 } else { x };
        plain.push_str(&format!("{x} {y}\n"));
        utk.push_str(&format!("{}\t{}\n", next(), next()));
    }
    fs::write(dir.path().join("a.txt"), &plain).unwrap();
    fs::write(dir.path().join("b.pts"), &utk).unwrap();
    let o = lab(
        &dir,
        &[
            "spectrum", "--input", "a.txt", "b.pts", "--k", "6", "--out", "files",
        ],
    );
    ok(&o, "files");
    let err = stderr(&o);
    assert!(
        err.contains("b.pts, line 1: skipped the header line '40'"),
        "{err}"
    );
    assert!(err.contains("a.txt: wrapped 1 coordinate"), "{err}");
    assert!(
        stdout(&o).contains("R = 2 realisation(s)"),
        "{}",
        stdout(&o)
    );
    assert_eq!(
        spectrum_rows(&dir.path().join("files/spectrum-radial.csv")).len(),
        6
    );
    assert_eq!(
        png_size(&dir.path().join("files/spectrum.png")),
        (13 * 20, 13 * 20)
    );

    // A changed input file is a changed configuration: refused, not mixed.
    fs::write(dir.path().join("b.pts"), utk.replacen("\t", " ", 1)).unwrap();
    let o = lab(
        &dir,
        &[
            "spectrum", "--input", "a.txt", "b.pts", "--k", "6", "--out", "files",
        ],
    );
    fails_with(&o, "crc32", "changed input file");

    // A single 3D file with the default output path.
    fs::write(
        dir.path().join("c.txt"),
        "0.1 0.2 0.3\n0.5 0.5 0.5\n0.9 0.1 0.7\n",
    )
    .unwrap();
    ok(
        &lab(&dir, &["spectrum", "--input", "c.txt", "--k", "2"]),
        "3D file",
    );
    assert!(dir
        .path()
        .join("out/spectrum/c-3d-3/spectrum-radial.csv")
        .is_file());

    // Malformed: a bad number at line 3; nothing is written.
    let bad = TempDir::new("spectrum-bad-input");
    fs::write(bad.path().join("bad.txt"), "0.1 0.2\n0.3 0.4\n0.5 x\n").unwrap();
    let o = lab(&bad, &["spectrum", "--input", "bad.txt", "--out", "r"]);
    fails_with(&o, "bad.txt, line 3", "bad number");
    assert_eq!(bad.all_files(), vec![PathBuf::from("bad.txt")]);
    for (name, text, want) in [
        ("cols.txt", "0.1 0.2\n0.3\n", "line 2: 1 columns"),
        (
            "nan.txt",
            "0.1 0.2\nNaN 0.4\n",
            "line 2, column 1: 'NaN' is not a finite",
        ),
        ("empty.txt", "# nothing\n\n", "no points"),
    ] {
        fs::write(bad.path().join(name), text).unwrap();
        let o = lab(&bad, &["spectrum", "--input", name, "--out", "r"]);
        fails_with(&o, want, name);
        assert!(stderr(&o).contains(name), "{name}: {}", stderr(&o));
    }
    fails_with(
        &lab(&bad, &["spectrum", "--input", "missing.txt", "--out", "r"]),
        "missing.txt",
        "missing",
    );
    assert!(bad
        .all_files()
        .iter()
        .all(|f| f.extension().is_some_and(|e| e == "txt")));
}

#[test]
fn of_segments_and_lines() {
    let dir = TempDir::new("spectrum-prims");
    for (args, out, png) in [
        (
            &[
                "--primitive",
                "segments",
                "--length",
                "0.3",
                "--direction",
                "1,1",
            ][..],
            "seg",
            Some(272),
        ),
        (&["--primitive", "lines"][..], "lines2", None),
        (
            &["--primitive", "lines", "--dims", "3", "--axis", "2"][..],
            "lines3",
            Some(272),
        ),
        (&["--dims", "3", "--k", "4"][..], "pts3", Some(261)),
        (&["--dims", "1", "--k", "20"][..], "pts1", None),
    ] {
        let mut a = vec![
            "spectrum",
            "--sampler",
            "random",
            "-n",
            "27",
            "--realizations",
            "3",
        ];
        if !args.contains(&"--k") {
            a.extend(["--k", "8"]);
        }
        a.extend(args);
        a.extend(["--out", out]);
        let o = lab(&dir, &a);
        ok(&o, &format!("{a:?}"));
        let rows = spectrum_rows(&dir.path().join(format!("{out}/spectrum-radial.csv")));
        assert!(!rows.is_empty() && rows.iter().all(|r| r.1 > 0.0), "{out}");
        let png_path = dir.path().join(format!("{out}/spectrum.png"));
        match png {
            Some(side) => assert_eq!(png_size(&png_path), (side, side), "{out}"),
            None => {
                assert!(!png_path.exists(), "{out}");
                assert!(stdout(&o).contains("no PNG"), "{}", stdout(&o));
            }
        }
    }
    let rows = spectrum_rows(&dir.path().join("pts3/spectrum-radial.csv"));
    let c3 = ring_counts(4, 3);
    assert!(rows.iter().all(|r| r.3 == c3[r.0]), "{rows:?}");
    assert_eq!(rows[0].3, 18); // |ν|² ∈ {1, 2}: 6 + 12
    let rows = spectrum_rows(&dir.path().join("lines2/spectrum-radial.csv"));
    assert!(rows.iter().all(|r| r.3 == 2), "{rows:?}");
    no_tmp_files(&dir);

    // Options that do not apply, and impossible ones.
    for (args, want) in [
        (
            &["--length", "0.2"][..],
            "--length applies only to --primitive segments",
        ),
        (
            &["--axis", "1"][..],
            "--axis applies only to --primitive lines",
        ),
        (&["--primitive", "lines", "--axis", "2"][..], "--axis 2"),
        (
            &["--primitive", "lines", "--dims", "1"][..],
            "dimension 2 or 3",
        ),
        (
            &["--primitive", "segments", "--direction", "1,0,0"][..],
            "--direction has 3 component(s)",
        ),
        (&["--k", "0"][..], "--k 0"),
        (&["--threads", "0"][..], "--threads"),
    ] {
        let mut a = vec![
            "spectrum",
            "--sampler",
            "random",
            "-n",
            "16",
            "--out",
            "never",
        ];
        a.extend(args);
        fails_with(&lab(&dir, &a), want, &format!("{a:?}"));
    }
    assert!(!dir
        .all_files()
        .iter()
        .any(|f| f.to_string_lossy().contains("never")));
}

#[test]
fn help_documents_the_formats() {
    let dir = TempDir::new("spectrum-help");
    let o = lab(&dir, &["spectrum", "--help"]);
    ok(&o, "help");
    let help = stdout(&o);
    for want in [
        "radius,mean_np,std_error,count",
        "--realizations",
        "realisations",
        "--input",
        "--method",
        "direct",
        "point-count header",
        "--shift",
        "OUT.state",
        "OUT/spectrum-radial.csv",
    ] {
        assert!(help.contains(want), "{want}: {help}");
    }
}

/// One ring of `spectrum-radial.csv`: radius, mean `N·P`, its SE, cell count.
type Ring = (usize, f64, f64, u64);

/// The rings of a direct run, then a NUFFT run at `tol`, of the jittered `dims`D `prim`.
fn direct_and_nufft_rings(dir: &TempDir, dims: &str, prim: &str, tol: &str) -> Vec<Vec<Ring>> {
    let mut rows = Vec::new();
    for method in ["direct", "nufft"] {
        let out = format!("res/{dims}{prim}-{method}");
        let mut args = vec![
            "spectrum",
            "--sampler",
            "jittered",
            "--dims",
            dims,
            "-n",
            "64",
            "--k",
            "9",
            "--realizations",
            "3",
            "--primitive",
            prim,
            "--method",
            method,
            "--out",
            &out,
        ];
        if method == "nufft" {
            args.extend(["--tol", tol]);
        }
        let o = lab(dir, &args);
        ok(&o, &format!("{args:?}"));
        assert!(stdout(&o).contains(&format!("method {method}")));
        rows.push(spectrum_rows(
            &dir.path().join(format!("{out}/spectrum-radial.csv")),
        ));
    }
    rows
}

/// `A`, the mean `‖F‖²` over the whole grid, from a direct run on a grid holding every ring.
fn total_power(dir: &TempDir, dims: &str, prim: &str) -> f64 {
    // The DC term N² plus every ring that meets [−9, 9]^d (up to ρ = round(√d·9)).
    let d_eff: usize = if prim == "lines" {
        dims.parse::<usize>().unwrap() - 1
    } else {
        dims.parse().unwrap()
    };
    let k_all = ((d_eff as f64).sqrt() * 9.0 + 0.5).ceil() as usize;
    let out = format!("res/{dims}{prim}-direct-all");
    let k_all_s = k_all.to_string();
    ok(
        &lab(
            dir,
            &[
                "spectrum",
                "--sampler",
                "jittered",
                "--dims",
                dims,
                "-n",
                "64",
                "--k",
                &k_all_s,
                "--realizations",
                "3",
                "--primitive",
                prim,
                "--method",
                "direct",
                "--out",
                &out,
            ],
        ),
        "direct-all",
    );
    let all = spectrum_rows(&dir.path().join(format!("{out}/spectrum-radial.csv")));
    let n = 64.0;
    n * n + n * all.iter().map(|r| r.3 as f64 * r.1).sum::<f64>()
}

/// Asserts every NUFFT ring mean within its bound of the direct run's.
fn check_ring_means(dims: &str, prim: &str, tol: f64, rows: &[Vec<Ring>], a_total: f64) {
    let n = 64.0;
    let eps = 2f64.sqrt() * tol;
    let mut worst: f64 = 0.0;
    for (a, b) in rows[0].iter().zip(&rows[1]) {
        assert_eq!((a.0, a.3), (b.0, b.3));
        let c = a.3 as f64;
        let bound = eps * (2.0 * (a_total * n * c * a.1).sqrt() + eps * a_total) / (n * c);
        worst = worst.max((a.1 - b.1).abs() / bound);
        assert!(
            (a.1 - b.1).abs() <= bound,
            "{dims}D {prim}, ring {}: direct {} vs nufft {} (bound {bound:e})",
            a.0,
            a.1,
            b.1
        );
    }
    println!("{dims}D {prim}, tol {tol:e}: max |Δ ring mean| / bound = {worst:.2e}");
}

/// `--tol` belongs to nufft, nufft does not do segments, and `--tol 0` is refused.
fn check_nufft_option_errors(dir: &TempDir) {
    fails_with(
        &lab(
            dir,
            &[
                "spectrum",
                "--sampler",
                "random",
                "--tol",
                "1e-6",
                "--out",
                "res/x",
            ],
        ),
        "--tol applies to --method nufft",
        "tol",
    );
    fails_with(
        &lab(
            dir,
            &[
                "spectrum",
                "--sampler",
                "random",
                "--method",
                "nufft",
                "--primitive",
                "segments",
                "--out",
                "res/x",
            ],
        ),
        "segment",
        "nufft segments",
    );
    fails_with(
        &lab(
            dir,
            &[
                "spectrum",
                "--sampler",
                "random",
                "--method",
                "nufft",
                "--tol",
                "0",
                "--out",
                "res/x",
            ],
        ),
        "--tol 0",
        "tol 0",
    );
}

/// NUFFT ring means match direct ones within the bound its tolerance implies, in 1D–3D.
#[test]
fn nufft_matches_direct_to_its_tolerance() {
    let dir = TempDir::new("spectrum-nufft");
    for (dims, prim, tol) in [
        ("2", "points", "1e-12"),
        ("3", "lines", "1e-10"),
        ("1", "points", "1e-6"),
    ] {
        let rows = direct_and_nufft_rings(&dir, dims, prim, tol);
        let tol: f64 = tol.parse().unwrap();
        // The NUFFT's contract: relative l2 error ‖F̃ − F‖₂ ≤ ε‖F‖₂ per
        // realisation over its half grid, so ≤ √2·ε over the full grid
        // (conjugate symmetry). For a ring ρ of c cells, per realisation,
        //   |Σ_ρ (|F̃|² − |F|²)| ≤ ‖F̃ − F‖_ρ (‖F̃‖_ρ + ‖F‖_ρ)
        //                       ≤ ε'‖F‖ (2‖F‖_ρ + ε'‖F‖),   ε' = √2·ε,
        // and averaged over the R realisations (Cauchy–Schwarz)
        //   |m̃_ρ − m_ρ| ≤ ε' (2√(A·N c m_ρ) + ε' A)/(N c),
        // with m_ρ the direct ring mean of |F|²/N (so mean ‖F‖_ρ² = N c m_ρ)
        // and A ≥ mean ‖F‖² over the whole grid: the DC term N² plus every ring
        // that meets the grid [−k, k]^d, up to ρ = round(√d·k), taken from a
        // direct run on a grid that holds those rings.
        let a_total = total_power(&dir, dims, prim);
        check_ring_means(dims, prim, tol, &rows, a_total);
    }
    // --tol belongs to nufft; nufft does not do segments.
    check_nufft_option_errors(&dir);
    no_tmp_files(&dir);
}

fn config(args: &[&str]) -> (spectrum::Config, Option<Vec<Vec<f64>>>) {
    let mut full = vec!["linesample-lab", "spectrum"];
    full.extend(args);
    match Cli::try_parse_from(full).unwrap().command {
        Some(Command::Spectrum(a)) => {
            let r = linesample_lab::commands::spectrum::resolve(&a).unwrap();
            (r.config, r.files)
        }
        other => panic!("{other:?}"),
    }
}

/// The compute functions directly: the summary is the kernel's periodogram
/// of the same points, the shift does not change the spectrum beyond
/// rounding, and blocks of realisations merge to the same ring statistics.
#[test]
fn summary_is_the_kernels_periodogram() {
    use linesample::pattern::{Jittered, Pattern};
    use linesample::spectrum::{AmplitudeView, Dft, Grid, Periodogram};
    use linesample::Seed;
    let (cfg, _) = config(&[
        "--sampler",
        "jittered",
        "-n",
        "64",
        "--k",
        "6",
        "--realizations",
        "11",
        "--seed",
        "9",
    ]);
    assert_eq!(cfg.block(), 2);
    let exp = Spectrum::new(cfg.clone(), None).unwrap();
    assert_eq!(exp.cells().len(), 6);
    let s = exp
        .summary(runner::compute(&exp, Some(2)).unwrap())
        .unwrap();
    // The same periodogram straight from the kernel.
    let grid = Grid::<2>::new(6).unwrap();
    let mut total = Periodogram::new_vec(grid);
    let pat = Jittered::<2>::cube(64).unwrap();
    let mut ring_stats = vec![linesample::stats::RunningStats::new(); 7];
    for r in 0..11 {
        let mut pts = [[0f32; 2]; 64];
        pat.fill(Seed::new(9).realization(r), &mut pts).unwrap();
        let pts: Vec<[f64; 2]> = pts.iter().map(|p| p.map(f64::from)).collect();
        let mut dft = Dft::new_vec(grid);
        let mut scratch = vec![0.0; 64 * Dft::<2, Vec<f64>>::points_scratch_per_sample(grid)];
        dft.add_points(&pts, &mut scratch).unwrap();
        total.add(&dft).unwrap();
        let (mut m, mut c) = (vec![0.0; 7], vec![0u64; 7]);
        dft.radial_power(&mut m, &mut c).unwrap();
        for (st, v) in ring_stats.iter_mut().zip(m) {
            st.push(v);
        }
    }
    let (mut mean, mut count) = (vec![0.0; 7], vec![0u64; 7]);
    total.radial_average(&mut mean, &mut count).unwrap();
    assert_eq!(s.mean, mean);
    assert_eq!(s.count, count);
    let se: Vec<f64> = ring_stats.iter().map(|st| st.mean_std_error()).collect();
    assert_eq!(s.se, se);
    let img = s.image.as_ref().unwrap();
    assert_eq!(img.side, 13);
    assert_eq!(
        img.values[0],
        total.mean([-6, 6]).unwrap(),
        "top-left pixel is (−k, k)"
    );

    // A random shift per realisation leaves |F|² unchanged up to rounding.
    let (shifted, _) = config(&[
        "--sampler",
        "jittered",
        "-n",
        "64",
        "--k",
        "6",
        "--realizations",
        "11",
        "--seed",
        "9",
        "--shift",
        "random",
    ]);
    let exp = Spectrum::new(shifted, None).unwrap();
    let t = exp
        .summary(runner::compute(&exp, Some(1)).unwrap())
        .unwrap();
    for (a, b) in s.mean.iter().zip(&t.mean) {
        assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{a} vs {b}");
    }
    assert_ne!(s.mean, t.mean, "the shift is applied (rounding differs)");
}

/// `--out` is a folder, as for every command: an existing folder takes the
/// files (it was refused as "not a file prefix"), a file is refused.
#[test]
fn out_is_a_folder() {
    let dir = TempDir::new("spectrum-out-folder");
    fs::create_dir(dir.path().join("here")).unwrap();
    let args = |out: &'static str| {
        vec![
            "spectrum",
            "--sampler",
            "random",
            "-n",
            "16",
            "--realizations",
            "2",
            "--out",
            out,
        ]
    };
    ok(&lab(&dir, &args("here")), "an existing folder");
    let (_, header, rows) = csv_table(&dir.path().join("here/spectrum-radial.csv"));
    assert_eq!(header.join(","), "radius,mean_np,std_error,count");
    assert!(!rows.is_empty());
    assert!(dir.path().join("here/manifest.json").is_file());
    fs::write(dir.path().join("afile"), "x").unwrap();
    fails_with(
        &lab(&dir, &args("afile")),
        "--out afile: expected an output folder, but it is a file",
        "a file",
    );
}
