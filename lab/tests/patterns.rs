//! `patterns`: the binary end to end, and `experiments::patterns` directly.

mod common;

use std::fs;
use std::path::PathBuf;

use common::*;
use linesample::Seed;
use linesample_lab::experiments::patterns;
use linesample_lab::sampler::{PatternSpec, Sampler};

#[test]
fn writes_points_and_svg() {
    let dir = TempDir::new("patterns");
    for (sampler, dims, n, circles_per_point, extra) in [
        ("cmj", "2", 256, 1, &[][..]),
        ("jittered", "3", 64, 3, &[][..]),
        (
            "random",
            "1",
            100,
            1,
            &["--shift", "--realization", "3"][..],
        ),
        ("multi-jittered", "2", 96, 1, &["--grid", "12x8"][..]),
        ("jittered", "2", 60, 1, &["--strata", "10,6"][..]),
        ("n-rooks", "3", 50, 3, &[][..]),
        ("sobol", "2", 128, 1, &[][..]),
        ("halton", "3", 77, 3, &["--shift", "random"][..]),
        ("pmj02", "2", 256, 1, &[][..]),
        ("pmj02bn", "2", 100, 1, &["--shift"][..]),
    ] {
        let prefix = format!("sub/dir/{sampler}-{dims}");
        let ns = n.to_string();
        let mut args = vec!["patterns", "--sampler", sampler, "--dims", dims];
        if !extra.contains(&"--grid") && !extra.contains(&"--strata") {
            args.extend(["-n", ns.as_str()]);
        }
        args.extend(["--seed", "7", "--out", prefix.as_str()]);
        args.extend(extra);
        let o = lab(&dir, &args);
        ok(&o, &format!("{args:?}"));
        let d: usize = dims.parse().unwrap();
        check_points(&dir.path().join(format!("{prefix}/points.txt")), n, d);
        let svg = dir.path().join(format!("{prefix}/points.svg"));
        assert_eq!(circles(&svg), n * circles_per_point, "{args:?}");
        let text = fs::read_to_string(&svg).unwrap();
        assert!(
            text.contains(&format!("{sampler}, {d}D, N = {n}, seed 7")),
            "{args:?}"
        );
        let shifted = extra.contains(&"--shift");
        assert!(text.contains(if shifted { "shift on" } else { "shift off" }));
    }
    no_tmp_files(&dir);
}

#[test]
fn deterministic_and_realizations_differ() {
    let dir = TempDir::new("determinism");
    let run = |out: &str, r: &str, shift: &[&str]| {
        let mut args = vec![
            "patterns",
            "--sampler",
            "random",
            "-n",
            "64",
            "--realization",
            r,
            "--out",
            out,
        ];
        args.extend(shift);
        ok(&lab(&dir, &args), out);
        fs::read_to_string(dir.path().join(format!("{out}/points.txt"))).unwrap()
    };
    assert_eq!(run("a", "0", &[]), run("b", "0", &[]));
    assert_ne!(run("a", "0", &[]), run("c", "1", &[]));
    assert_eq!(run("a", "0", &[]), run("d", "0", &["--shift", "none"]));
    assert_ne!(run("a", "0", &[]), run("e", "0", &["--shift"]));
}

#[test]
fn default_output_path() {
    let dir = TempDir::new("default-out");
    ok(
        &lab(&dir, &["patterns", "--sampler", "halton", "-n", "32"]),
        "halton",
    );
    check_points(
        &dir.path().join("out/patterns/halton-2d-32/points.txt"),
        32,
        2,
    );
    assert_eq!(
        circles(&dir.path().join("out/patterns/halton-2d-32/points.svg")),
        32
    );
    assert_eq!(
        dir.files(),
        [
            PathBuf::from("out/patterns/halton-2d-32/points.svg"),
            PathBuf::from("out/patterns/halton-2d-32/points.txt")
        ]
    );
}

#[test]
fn bad_input_fails_cleanly() {
    let dir = TempDir::new("bad");
    for (args, names) in [
        (
            &["--sampler", "random", "-n", "0"][..],
            "n must be at least 1",
        ),
        (&["--sampler", "random", "--dims", "4"][..], "--dims"),
        (&["--sampler", "cmj", "--dims", "3"][..], "--dims 3"),
        (
            &["--sampler", "multi-jittered", "--dims", "1"][..],
            "--dims 1",
        ),
        (&["--sampler", "ccvt", "--dims", "1"][..], "--dims 1"),
        (
            &["--sampler", "jittered", "-n", "1000", "--dims", "2"][..],
            "--strata",
        ),
        (
            &["--sampler", "jittered", "--strata", "4,4", "--dims", "3"][..],
            "--strata",
        ),
        (
            &["--sampler", "jittered", "--strata", "4,4", "-n", "15"][..],
            "strata",
        ),
        (&["--sampler", "random", "--strata", "4,4"][..], "--strata"),
        (&["--sampler", "sobol", "--grid", "4x4"][..], "--grid"),
        (
            &["--sampler", "cmj", "--grid", "4x4", "-n", "15"][..],
            "-n 15",
        ),
        (&["--sampler", "cmj", "--grid", "4by4"][..], "--grid"),
        (&["--sampler", "nope"][..], "--sampler"),
        (&["-n", "4"][..], "--sampler"),
        (
            &["--sampler", "random", "--shift", "sideways"][..],
            "--shift",
        ),
    ] {
        let mut full = vec!["patterns"];
        full.extend(args);
        full.extend(["--out", "res/p"]);
        fails_with(&lab(&dir, &full), names, &format!("{full:?}"));
        assert!(
            dir.all_files().is_empty(),
            "{full:?} left {:?}",
            dir.all_files()
        );
    }
    // The jittered message explains why and what to do.
    let o = lab(
        &dir,
        &[
            "patterns",
            "--sampler",
            "jittered",
            "-n",
            "1000",
            "--dims",
            "2",
        ],
    );
    assert!(
        stderr(&o).contains("not a perfect square"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn unwritable_output_fails_without_partial_files() {
    let dir = TempDir::new("unwritable");
    // `blocker` is a file, so `blocker/p/points.txt` cannot be created.
    fs::write(dir.path().join("blocker"), "x").unwrap();
    let o = lab(
        &dir,
        &["patterns", "--sampler", "random", "--out", "blocker/p"],
    );
    fails_with(&o, "blocker", "file as a directory");
    assert_eq!(dir.all_files(), vec![PathBuf::from("blocker")]);
}

#[test]
fn help_describes_the_formats() {
    let dir = TempDir::new("help");
    let o = lab(&dir, &["patterns", "--help"]);
    ok(&o, "help");
    let h = stdout(&o);
    for s in [
        "--sampler",
        "multi-jittered",
        "n-rooks",
        "--strata",
        "--grid",
        "UTK",
        "<circle>",
        "--shift",
    ] {
        assert!(h.contains(s), "help lacks {s}");
    }
}

#[test]
fn poisson_disk_and_ccvt_patterns() {
    let dir = TempDir::new("blue");
    ok(
        &lab(
            &dir,
            &[
                "patterns",
                "--sampler",
                "poisson-disk",
                "-n",
                "200",
                "--out",
                "pd",
            ],
        ),
        "pd",
    );
    check_points(&dir.path().join("pd/points.txt"), 200, 2);
    ok(
        &lab(
            &dir,
            &[
                "patterns",
                "--sampler",
                "ccvt",
                "--dims",
                "3",
                "-n",
                "64",
                "--out",
                "cv",
            ],
        ),
        "ccvt",
    );
    check_points(&dir.path().join("cv/points.txt"), 64, 3);
    // Bridson at the densest relative radius cannot fit N points: a clear error.
    let o = lab(
        &dir,
        &[
            "patterns",
            "--sampler",
            "poisson-disk",
            "-n",
            "200",
            "--relative-radius",
            "1",
            "--bridson",
            "--out",
            "bad",
        ],
    );
    fails_with(&o, "relative-radius", "bridson shortfall");
    assert!(!dir.path().join("bad").exists());
    // Options of other samplers are rejected.
    let o = lab(
        &dir,
        &["patterns", "--sampler", "random", "--bridson", "--out", "r"],
    );
    fails_with(&o, "--bridson", "bridson for random");
}

/// The compute function directly: the points are the kernel's, with and
/// without the shift, and every dimension the sampler supports.
#[test]
fn generate_gives_the_kernel_points() {
    use linesample::pattern::{Pattern, Sobol};
    let spec = PatternSpec::simple(Sampler::Sobol, 2, 64);
    let seed = Seed::new(3).realization(2);
    let p = patterns::generate(&spec, false, seed, 3).unwrap();
    assert_eq!((p.dims, p.len()), (2, 64));
    let mut want = [[0f32; 2]; 64];
    Sobol::<2>::new(64).unwrap().fill(seed, &mut want).unwrap();
    assert_eq!(p.coords, want.as_flattened());
    let mut shifted = [[0f32; 2]; 64];
    Sobol::<2>::new(64)
        .unwrap()
        .shifted()
        .fill(seed, &mut shifted)
        .unwrap();
    assert_eq!(
        patterns::generate(&spec, true, seed, 1).unwrap().coords,
        shifted.as_flattened()
    );
    for d in 1..=3 {
        // Dart throwing in 1D jams at Rényi's parking constant 0.7476 of the
        // packing: 0.75 (the default) fits 30 points only about half the time.
        let mut spec = PatternSpec::simple(Sampler::PoissonDisk, d, 30);
        if d == 1 {
            spec.relative_radius = 0.5;
        }
        let q = patterns::generate(&spec, false, seed, 1).unwrap();
        assert_eq!((q.dims, q.len()), (d, 30));
    }
    let e =
        patterns::generate(&PatternSpec::simple(Sampler::Cmj, 3, 16), false, seed, 1).unwrap_err();
    assert!(e.to_string().contains("--dims 3"), "{e}");
}

/// `patterns -n 40000000` under a 256 MiB address-space limit: the point
/// buffer (320 MB) cannot be allocated, which is an error, not an abort.
#[test]
fn huge_n_under_a_memory_limit_is_an_error() {
    let dir = TempDir::new("memory");
    let cmd =
        format!("ulimit -v 262144 && exec {BIN} patterns --sampler random -n 40000000 --out big");
    let o = std::process::Command::new("sh")
        .arg("-c")
        .arg(&cmd)
        .current_dir(dir.path())
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_eq!(
        o.status.code(),
        Some(1),
        "exit status {:?}: {err}",
        o.status
    );
    assert!(
        err.starts_with("error: ") && err.contains("cannot allocate"),
        "{err}"
    );
    assert!(dir.all_files().is_empty(), "{:?}", dir.all_files());
}
