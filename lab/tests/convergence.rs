//! `convergence`: the binary end to end, and the experiment's compute
//! functions directly.

mod common;

use std::fs;
use std::path::PathBuf;

use clap::Parser;
use common::*;
use linesample::estimator::{run_realisations, PointEstimator};
use linesample::integrand::{Ball, Integrand};
use linesample::pattern::Jittered;
use linesample::Seed;
use linesample_lab::cli::{Cli, Command};
use linesample_lab::experiments::convergence::{self, Convergence};
use linesample_lab::runner;

fn config(args: &[&str]) -> convergence::Config {
    let mut full = vec!["linesample-lab", "convergence"];
    full.extend(args);
    match Cli::try_parse_from(full).unwrap().command {
        Some(Command::Convergence(a)) => {
            linesample_lab::commands::convergence::resolve(&a)
                .unwrap()
                .0
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn writes_csv_svg_and_manifest() {
    let dir = TempDir::new("convergence");
    let o = lab(
        &dir,
        &[
            "convergence",
            "--integrand",
            "disk",
            "--dims",
            "2",
            "--primitive",
            "points",
            "--sampler",
            "jittered",
            "--n",
            "16,64",
            "--realisations",
            "50",
            "--out",
            "res/disk",
        ],
    );
    ok(&o, "convergence");
    let out = stdout(&o);
    assert!(out.contains("slope of log Var vs log N"), "{out}");
    assert!(out.contains("bias z") && out.contains("Var*N"), "{out}");

    let (comments, header, rows) = csv_table(&dir.path().join("res/disk/convergence.csv"));
    assert_eq!(header.join(","), CONVERGENCE_HEADER);
    assert!(comments
        .iter()
        .any(|c| c == "# homogenised: random toroidal shift per realisation"));
    assert!(
        comments.iter().any(|c| c.starts_with(
            "# linesample-lab convergence --integrand disk --dims 2 --radius 0.25 \
             --primitive points --sampler jittered --n 16,64 --realisations 50 --seed 1"
        )),
        "{comments:?}"
    );
    assert_eq!(rows.len(), 2, "{rows:?}");
    for (row, n) in rows.iter().zip(["16", "64"]) {
        assert_eq!(row.len(), 9, "{row:?}");
        assert_eq!((row[0].as_str(), row[1].as_str()), (n, "50"));
        let v: Vec<f64> = row[2..].iter().map(|x| x.parse().unwrap()).collect();
        let (mean, mean_se, exact, z, var, var_se) = (v[0], v[1], v[2], v[3], v[4], v[5]);
        assert!(
            (exact - std::f64::consts::PI / 16.0).abs() < 1e-12,
            "{exact}"
        );
        assert!(var > 0.0 && var_se > 0.0 && var_se < var, "{row:?}");
        check_bias(mean, mean_se, exact, z, var, 50, &format!("N = {n}"));
    }

    let svg = fs::read_to_string(dir.path().join("res/disk/convergence.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("disk 2D, points, jittered, R = 50"), "title");
    // Two data points (error-bar markers) and the legend marker; the fit and
    // the four reference slopes are in the legend.
    assert_eq!(svg.matches("<circle").count(), 3);
    for label in [
        "slope -1",
        "slope -1.5",
        "slope -2",
        "slope -3",
        "fit: slope",
    ] {
        assert!(svg.contains(label), "{label}");
    }
    let manifest: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.path().join("res/disk/manifest.json")).unwrap())
            .unwrap();
    assert_eq!(manifest["experiment"], "convergence");
    assert_eq!(manifest["config"]["realisations"], 50);
    assert_eq!(manifest["config"]["seed"], 1);
    assert_eq!(manifest["config"]["shift"], "random");
    assert!(manifest["reproduce"]
        .as_str()
        .unwrap()
        .starts_with("linesample-lab convergence"));
    assert_eq!(manifest["cells_computed"], 2);
    no_tmp_files(&dir);
    assert_eq!(
        dir.files(),
        [
            "res/disk/convergence.csv",
            "res/disk/convergence.svg",
            "res/disk/manifest.json"
        ]
        .map(PathBuf::from)
    );
    let state = dir.all_files();
    assert!(
        state.contains(&PathBuf::from("res/disk.state/cells/000000.bin")),
        "{state:?}"
    );
    assert!(
        state.contains(&PathBuf::from("res/disk.state/cells/000001.bin")),
        "{state:?}"
    );
}

#[test]
fn independent_of_the_thread_count() {
    let dir = TempDir::new("convergence-threads");
    for (prim, extra) in [
        ("points", &[][..]),
        ("lines", &["--sampler", "random"][..]),
        ("segments", &["--groups", "2", "--length", "0.3"][..]),
    ] {
        let run = |threads: &str| {
            let out = format!("{prim}-t{threads}");
            let mut args = vec![
                "convergence",
                "--primitive",
                prim,
                "--n",
                "16,36",
                "--realisations",
                "100",
                "--seed",
                "5",
                "--threads",
                threads,
                "--out",
                out.as_str(),
            ];
            args.extend(extra);
            ok(&lab(&dir, &args), &format!("{args:?}"));
            (
                fs::read(dir.path().join(format!("{out}/convergence.csv"))).unwrap(),
                fs::read(dir.path().join(format!("{out}/convergence.svg"))).unwrap(),
            )
        };
        let one = run("1");
        assert_eq!(one, run("2"), "{prim}: --threads 2 differs");
        assert_eq!(one, run("3"), "{prim}: --threads 3 differs");
    }
    no_tmp_files(&dir);
}

#[test]
fn rounds_jittered_counts_and_has_a_default_path() {
    let dir = TempDir::new("convergence-round");
    let o = lab(
        &dir,
        &["convergence", "--n", "10,60", "--realisations", "8"],
    );
    ok(&o, "default path");
    let out = stdout(&o);
    assert!(out.contains("--n 60 -> N = 64"), "{out}");
    assert!(out.contains("--n 10 -> N = 9"), "{out}");
    let (comments, _, rows) = csv_table(
        &dir.path()
            .join("out/convergence/disk-2d-points-jittered/convergence.csv"),
    );
    assert!(comments.iter().any(|c| c.contains("--n 60 -> N = 64")));
    let ns: Vec<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(ns, ["9", "64"]);
    assert!(dir
        .path()
        .join("out/convergence/disk-2d-points-jittered/convergence.svg")
        .is_file());
    // Lines in 3D use a 2D offset pattern: 100 is already a square.
    let o = lab(
        &dir,
        &[
            "convergence",
            "--integrand",
            "ball",
            "--dims",
            "3",
            "--primitive",
            "lines",
            "--n",
            "4,100",
            "--realisations",
            "8",
            "--out",
            "b",
        ],
    );
    ok(&o, "3D lines");
    let (_, _, rows) = csv_table(&dir.path().join("b/convergence.csv"));
    let ns: Vec<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(ns, ["4", "100"]);
    assert!(!stdout(&o).contains("note:"));
}

#[test]
fn bad_input_fails_cleanly() {
    let dir = TempDir::new("convergence-bad");
    for (args, names) in [
        (&["--length", "0.1"][..], "--length"),
        (&["--integrand", "disk", "--dims", "3"][..], "--dims 3"),
        (&["--dims", "4"][..], "--dims"),
        (&["--radius", "0.7"][..], "--radius"),
        (&["--radius", "nan"][..], "--radius"),
        (
            &["--integrand", "gaussian", "--radius", "0.1"][..],
            "--radius",
        ),
        (&["--integrand", "gaussian", "--sigma", "-1"][..], "--sigma"),
        (&["--integrand", "edge", "--normal", "0,0"][..], "--normal"),
        (
            &["--integrand", "edge", "--normal", "1,0,0"][..],
            "--normal",
        ),
        (&["--integrand", "edge", "--offset", "inf"][..], "--offset"),
        (&["--integrand", "ball", "--offset", "0.5"][..], "--offset"),
        (&["--integrand", "nope"][..], "--integrand"),
        (
            &["--primitive", "lines", "--sampler", "cmj"][..],
            "--sampler cmj",
        ),
        (
            &[
                "--sampler",
                "multi-jittered",
                "--dims",
                "3",
                "--integrand",
                "ball",
            ][..],
            "--dims 3",
        ),
        (&["--primitive", "points", "--groups", "2"][..], "--groups"),
        (
            &["--primitive", "points", "--random-direction"][..],
            "--random-direction",
        ),
        (&["--primitive", "lines", "--groups", "0"][..], "--groups"),
        (
            &["--primitive", "lines", "--direction", "0,0"][..],
            "--direction",
        ),
        (
            &["--primitive", "lines", "--direction", "1,0,0"][..],
            "--direction",
        ),
        (
            &[
                "--primitive",
                "lines",
                "--direction",
                "1,0",
                "--random-direction",
            ][..],
            "--direction",
        ),
        (
            &["--primitive", "segments", "--length", "-1"][..],
            "--length",
        ),
        (
            &["--primitive", "segments", "--groups", "4", "--n", "2"][..],
            "--groups 4",
        ),
        (
            &["--sampler", "random", "--relative-radius", "0.5"][..],
            "--relative-radius",
        ),
        (&["--n", "0"][..], "--n"),
        (&["--n", "16,17"][..], "--n"),
        (&["--n", "x"][..], "--n"),
        (&["--realisations", "2"][..], "--realisations"),
        (&["--threads", "0"][..], "--threads"),
        (&["--threads", "5000"][..], "--threads"),
        (&["--shard", "0/2"][..], "--shard"),
        (&["--shard", "3/2"][..], "--shard"),
        (&["--shift", "maybe"][..], "--shift"),
    ] {
        let mut full = vec!["convergence"];
        full.extend(args);
        if !args.contains(&"--realisations") {
            full.extend(["--realisations", "8"]);
        }
        if !args.contains(&"--n") {
            full.extend(["--n", "4,16"]);
        }
        full.extend(["--out", "res/c"]);
        fails_with(&lab(&dir, &full), names, &format!("{full:?}"));
        assert!(
            dir.all_files().is_empty(),
            "{full:?} left {:?}",
            dir.all_files()
        );
    }
}

#[test]
fn help_is_specific() {
    let dir = TempDir::new("convergence-help");
    let o = lab(&dir, &["convergence", "--help"]);
    ok(&o, "help");
    let h = stdout(&o);
    for s in [
        "variance",
        "toroidal shift",
        "weighted least squares",
        "OUT/convergence.csv",
        "OUT/convergence.svg",
        "OUT/manifest.json",
        "bias z-score",
        "--threads",
        "--groups",
        "m^d'",
        "bit-identical",
        "--shard",
        "--fresh",
        "--quiet",
        "--shift",
        "OUT.state",
    ] {
        assert!(h.contains(s), "help lacks {s}");
    }
}

#[test]
fn runs_every_integrand_and_primitive() {
    let dir = TempDir::new("convergence-all");
    for (i, args) in [
        &[
            "--integrand",
            "gaussian",
            "--dims",
            "3",
            "--primitive",
            "segments",
        ][..],
        &[
            "--integrand",
            "edge",
            "--primitive",
            "lines",
            "--direction",
            "1,2",
        ][..],
        &[
            "--integrand",
            "edge",
            "--dims",
            "3",
            "--primitive",
            "points",
            "--sampler",
            "sobol",
        ][..],
        &[
            "--integrand",
            "ball",
            "--dims",
            "3",
            "--primitive",
            "lines",
            "--groups",
            "3",
        ][..],
        &[
            "--integrand",
            "disk",
            "--primitive",
            "segments",
            "--random-direction",
            "--sampler",
            "cmj",
        ][..],
        &[
            "--integrand",
            "disk",
            "--primitive",
            "points",
            "--sampler",
            "jittered",
            "--shift",
            "none",
        ][..],
    ]
    .into_iter()
    .enumerate()
    {
        let out = format!("r{i}");
        let mut full = vec![
            "convergence",
            "--n",
            "8,27",
            "--realisations",
            "40",
            "--out",
            &out,
        ];
        full.extend(args);
        ok(&lab(&dir, &full), &format!("{full:?}"));
        let (comments, header, rows) =
            csv_table(&dir.path().join(format!("{out}/convergence.csv")));
        assert_eq!(header.join(","), CONVERGENCE_HEADER);
        assert_eq!(rows.len(), 2, "{full:?}");
        if args.contains(&"none") {
            assert!(
                comments.iter().any(|c| c.starts_with("# not homogenised")),
                "{comments:?}"
            );
            assert!(comments[0].ends_with("--shift none"), "{comments:?}");
        }
        for r in &rows {
            let v: Vec<f64> = r[2..].iter().map(|x| x.parse().unwrap()).collect();
            check_bias(v[0], v[1], v[2], v[3], v[4], 40, &format!("{full:?}"));
        }
    }
    no_tmp_files(&dir);
}

/// The compute functions directly: the experiment's row statistics are the
/// kernel's `run_realisations` over the same seeds, merged chunk by chunk,
/// and `--shift none` runs the estimator without homogenisation.
#[test]
fn results_are_the_kernels_statistics() {
    for shift in ["random", "none"] {
        let cfg = config(&[
            "--n",
            "16,64",
            "--realisations",
            "70",
            "--seed",
            "4",
            "--shift",
            shift,
        ]);
        let exp = Convergence::new(cfg).unwrap();
        let cells = runner::compute(&exp, Some(2)).unwrap();
        assert_eq!(cells[0].chunks.len(), 3, "70 realisations in chunks of 32");
        let res = exp.results(&cells).unwrap();
        let f = Ball::<2>::new([0.5; 2], 0.25).unwrap();
        assert_eq!(res.exact, f.integral());
        for (row, n) in res.rows.iter().zip([16usize, 64]) {
            let pat = Jittered::<2>::cube(n).unwrap();
            let est = PointEstimator::new(&pat).unwrap();
            let seed = Seed::new(Seed::new(4).stream(n as u64));
            let mut scratch = vec![0f32; 2 * n];
            let mut want = linesample::stats::RunningStats::new();
            for (first, count) in [(0, 32), (32, 32), (64, 6)] {
                want.merge(
                    &run_realisations(
                        &est,
                        &f,
                        seed,
                        first,
                        count,
                        shift == "random",
                        &mut scratch,
                    )
                    .unwrap(),
                );
            }
            assert_eq!(row.mean.to_bits(), want.mean().to_bits(), "{shift} N = {n}");
            assert_eq!(row.variance.to_bits(), want.variance().to_bits());
            assert_eq!(
                row.variance_se.to_bits(),
                want.variance_std_error().to_bits()
            );
        }
        let fit = res.fit.unwrap();
        assert!(
            fit.slope < -1.0,
            "jittered disk points converge faster than N^-1: {fit:?}"
        );
    }
}
