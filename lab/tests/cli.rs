//! End-to-end tests of the `linesample-lab` binary, each in its own temp dir.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

const BIN: &str = env!("CARGO_BIN_EXE_linesample-lab");

/// A fresh, empty directory under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        let dir = std::env::temp_dir().join(format!(
            "linesample-lab-test-{tag}-{}-{}-{nanos}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    fn path(&self) -> &Path {
        &self.0
    }

    /// Every file below the directory (relative paths), sorted.
    fn files(&self) -> Vec<PathBuf> {
        fn walk(dir: &Path, root: &Path, out: &mut Vec<PathBuf>) {
            for e in fs::read_dir(dir).expect("read_dir").flatten() {
                let p = e.path();
                if p.is_dir() {
                    walk(&p, root, out);
                } else {
                    out.push(p.strip_prefix(root).unwrap().to_path_buf());
                }
            }
        }
        let mut v = Vec::new();
        walk(&self.0, &self.0, &mut v);
        v.sort();
        v
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

fn lab(dir: &TempDir, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir.path())
        .output()
        .expect("run linesample-lab")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Parses a point file and checks it has `n` lines of `d` numbers in `[0, 1)`.
fn check_points(path: &Path, n: usize, d: usize) -> Vec<Vec<f32>> {
    let text = fs::read_to_string(path).expect("read points");
    assert!(text.ends_with('\n'), "{}: no final newline", path.display());
    let pts: Vec<Vec<f32>> = text
        .lines()
        .map(|line| {
            assert!(!line.contains("  ") && !line.starts_with(' ') && !line.ends_with(' '));
            line.split(' ')
                .map(|t| {
                    t.parse::<f32>()
                        .unwrap_or_else(|_| panic!("bad number {t:?}"))
                })
                .collect()
        })
        .collect();
    assert_eq!(pts.len(), n, "{}: line count", path.display());
    for p in &pts {
        assert_eq!(p.len(), d, "{}: coordinates per line", path.display());
        assert!(
            p.iter().all(|x| (0.0..1.0).contains(x)),
            "{p:?} outside [0,1)"
        );
    }
    pts
}

fn circles(path: &Path) -> usize {
    let svg = fs::read_to_string(path).expect("read svg");
    assert!(svg.trim_start().starts_with("<?xml") && svg.trim_end().ends_with("</svg>"));
    svg.matches("<circle ").count()
}

#[test]
fn patterns_writes_points_and_svg() {
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
        ("halton", "3", 77, 3, &["--shift"][..]),
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
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let d: usize = dims.parse().unwrap();
        let txt = dir.path().join(format!("{prefix}.txt"));
        check_points(&txt, n, d);
        let svg = dir.path().join(format!("{prefix}.svg"));
        assert_eq!(circles(&svg), n * circles_per_point, "{args:?}");
        let title = fs::read_to_string(&svg).unwrap();
        assert!(title.contains(&format!("{sampler}, {d}D, N = {n}, seed 7")));
    }
    // No temporary files left behind.
    assert!(dir
        .files()
        .iter()
        .all(|f| !f.to_string_lossy().ends_with(".tmp")));
}

#[test]
fn patterns_is_deterministic_and_realizations_differ() {
    let dir = TempDir::new("determinism");
    let run = |out: &str, r: &str| {
        let o = lab(
            &dir,
            &[
                "patterns",
                "--sampler",
                "random",
                "-n",
                "64",
                "--realization",
                r,
                "--out",
                out,
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        fs::read_to_string(dir.path().join(format!("{out}.txt"))).unwrap()
    };
    assert_eq!(run("a", "0"), run("b", "0"));
    assert_ne!(run("a", "0"), run("c", "1"));
}

#[test]
fn default_output_path() {
    let dir = TempDir::new("default-out");
    let o = lab(&dir, &["patterns", "--sampler", "halton", "-n", "32"]);
    assert!(o.status.success(), "{}", stderr(&o));
    check_points(&dir.path().join("out/patterns/halton-2d-32.txt"), 32, 2);
    assert_eq!(
        circles(&dir.path().join("out/patterns/halton-2d-32.svg")),
        32
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
    ] {
        let mut full = vec!["patterns"];
        full.extend(args);
        full.extend(["--out", "res/p"]);
        let o = lab(&dir, &full);
        let err = stderr(&o);
        assert!(!o.status.success(), "{full:?} succeeded");
        assert!(err.starts_with("error: "), "{full:?}: {err}");
        assert!(
            err.contains(names),
            "{full:?}: {err:?} should mention {names:?}"
        );
        assert!(dir.files().is_empty(), "{full:?} left {:?}", dir.files());
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
    // `blocker` is a file, so `blocker/p.txt` cannot be created.
    fs::write(dir.path().join("blocker"), "x").unwrap();
    let o = lab(
        &dir,
        &["patterns", "--sampler", "random", "--out", "blocker/p"],
    );
    assert!(!o.status.success());
    assert!(stderr(&o).starts_with("error: "), "{}", stderr(&o));
    assert_eq!(dir.files(), vec![PathBuf::from("blocker")]);
}

#[test]
fn gallery_writes_every_pattern_and_the_index() {
    let dir = TempDir::new("gallery");
    let o = lab(
        &dir,
        &[
            "gallery",
            "--out-dir",
            "g",
            "--runs",
            "1",
            "--spectrum-realizations",
            "2",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = fs::read_to_string(dir.path().join("g/index.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("sampler,dims,n,seed,median_us,txt,svg,np_low,np_high,spectrum")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 16, "{csv}");
    for r in &rows {
        assert_eq!(r.len(), 10, "{r:?}");
        let (d, n): (usize, usize) = (r[1].parse().unwrap(), r[2].parse().unwrap());
        assert_eq!(r[3], "1");
        assert!(r[4].parse::<f64>().unwrap() >= 0.0);
        check_points(&dir.path().join("g").join(r[5]), n, d);
        let per_point = if d == 3 { 3 } else { 1 };
        assert_eq!(circles(&dir.path().join("g").join(r[6])), n * per_point);
        // Spectra: every pattern is close to white at high frequencies; the
        // stratified and blue-noise ones are well below 1 at low frequencies.
        let (low, high): (f64, f64) = (r[7].parse().unwrap(), r[8].parse().unwrap());
        assert!((0.5..1.5).contains(&high), "{r:?}");
        if d == 2 && ["jittered", "poisson-disk", "ccvt", "cmj"].contains(&r[0]) {
            assert!(low < 0.6, "{r:?}");
        }
        let stem = dir.path().join("g").join(r[9]);
        assert!(stem.with_extension("png").is_file() || d == 1, "{r:?}");
        assert_eq!(
            spectrum_rows(&PathBuf::from(format!("{}-radial.csv", stem.display()))).len(),
            if d == 2 { 159 } else { 64 },
            "{r:?}"
        );
    }
    for (s, d) in [
        ("multi-jittered", "2"),
        ("cmj", "2"),
        ("jittered", "3"),
        ("poisson-disk", "3"),
        ("ccvt", "2"),
        ("ccvt", "3"),
    ] {
        assert!(
            rows.iter().any(|r| r[0] == s && r[1] == d),
            "{s} {d}D missing"
        );
    }
    assert!(!rows.iter().any(|r| r[0] == "cmj" && r[1] == "3"));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("median"), "{stdout}");
    assert_eq!(stdout.lines().filter(|l| l.contains(".svg")).count(), 16);
    no_tmp_files(&dir);
}

#[test]
fn no_subcommand_runs_the_gallery() {
    let dir = TempDir::new("default");
    let o = lab(&dir, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("out/patterns/index.csv").is_file());
    assert!(dir.path().join("out/patterns/cmj-2d-1024.txt").is_file());
    assert!(dir
        .path()
        .join("out/patterns/jittered-3d-1000.svg")
        .is_file());
}

#[test]
fn help_describes_the_formats() {
    let dir = TempDir::new("help");
    let o = lab(&dir, &["patterns", "--help"]);
    assert!(o.status.success());
    let h = String::from_utf8_lossy(&o.stdout);
    for s in [
        "--sampler",
        "multi-jittered",
        "n-rooks",
        "--strata",
        "--grid",
        "UTK",
        "<circle>",
    ] {
        assert!(h.contains(s), "help lacks {s}");
    }
}

#[test]
fn poisson_disk_and_ccvt_patterns() {
    let dir = TempDir::new("blue");
    let o = lab(
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
    );
    assert!(o.status.success(), "{}", stderr(&o));
    check_points(&dir.path().join("pd.txt"), 200, 2);
    let o = lab(
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
    );
    assert!(o.status.success(), "{}", stderr(&o));
    check_points(&dir.path().join("cv.txt"), 64, 3);
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
    assert!(!o.status.success());
    assert!(stderr(&o).contains("relative-radius"), "{}", stderr(&o));
    assert!(!dir.path().join("bad.txt").exists());
    // Options of other samplers are rejected.
    let o = lab(
        &dir,
        &["patterns", "--sampler", "random", "--bridson", "--out", "r"],
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--bridson"), "{}", stderr(&o));
}

/// The lines of a convergence CSV after the `#` comments: header, then rows.
fn csv_table(path: &Path) -> (Vec<String>, Vec<String>, Vec<Vec<String>>) {
    let text = fs::read_to_string(path).expect("read csv");
    assert!(text.ends_with('\n'));
    let comments: Vec<String> = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .map(str::to_owned)
        .collect();
    let mut rest = text.lines().skip(comments.len());
    let header: Vec<String> = rest
        .next()
        .expect("header")
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = rest
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    (comments, header, rows)
}

fn no_tmp_files(dir: &TempDir) {
    assert!(
        dir.files()
            .iter()
            .all(|f| !f.to_string_lossy().ends_with(".tmp")),
        "{:?}",
        dir.files()
    );
}

const CONVERGENCE_HEADER: &str =
    "n,realisations,mean,mean_se,exact,bias_z,variance,variance_se,var_times_n";

/// The bias check of a convergence row, from the row's own sample variance:
/// `SE = √(s²/R)` (recomputed here, and the CSV's `mean_se` and `bias_z` must
/// agree with it), then `|mean − exact| ≤ 5·SE` (tests/README.md: one z-check,
/// α = 5.7e-7; the smallest bias it detects for sure is 5·SE, printed relative
/// to the exact value).
fn check_bias(mean: f64, mean_se: f64, exact: f64, z: f64, var: f64, r: u64, what: &str) {
    let se = (var / r as f64).sqrt();
    assert!(
        (mean_se / se - 1.0).abs() <= 1e-9,
        "{what}: mean_se {mean_se:e} vs √(s²/R) = {se:e}"
    );
    let z_here = (mean - exact) / se;
    assert!(
        (z - z_here).abs() <= 1e-6 * z_here.abs().max(1.0),
        "{what}: bias_z {z} vs (mean − exact)/SE = {z_here}"
    );
    println!(
        "{what}: bias z = {z_here:+.2}; detects a relative bias of {:.1e}",
        5.0 * se / exact.abs()
    );
    assert!(
        z_here.abs() <= 5.0,
        "{what}: mean {mean} vs exact {exact}: |z| = {:.2} > 5 (SE {se:e})",
        z_here.abs()
    );
}

#[test]
fn convergence_writes_csv_and_svg() {
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
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("slope of log Var vs log N"), "{stdout}");
    assert!(
        stdout.contains("bias z") && stdout.contains("Var*N"),
        "{stdout}"
    );

    let (comments, header, rows) = csv_table(&dir.path().join("res/disk.csv"));
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
        assert_eq!(row[0], n);
        assert_eq!(row[1], "50");
        let v: Vec<f64> = row[2..].iter().map(|x| x.parse().unwrap()).collect();
        let (mean, mean_se, exact, z, var, var_se) = (v[0], v[1], v[2], v[3], v[4], v[5]);
        assert!(
            (exact - std::f64::consts::PI / 16.0).abs() < 1e-12,
            "{exact}"
        );
        assert!(var > 0.0 && var_se > 0.0 && var_se < var, "{row:?}");
        check_bias(mean, mean_se, exact, z, var, 50, &format!("N = {n}"));
    }

    let svg = fs::read_to_string(dir.path().join("res/disk.svg")).unwrap();
    assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("disk 2D, points, jittered, R = 50"), "title");
    // Two data points and the legend marker; four dashed reference lines and the
    // legend sample.
    assert_eq!(svg.matches("<circle ").count(), 3);
    assert_eq!(svg.matches("stroke-dasharray").count(), 5);
    no_tmp_files(&dir);
    assert_eq!(
        dir.files(),
        vec![PathBuf::from("res/disk.csv"), PathBuf::from("res/disk.svg")]
    );
}

#[test]
fn convergence_is_independent_of_the_thread_count() {
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
            let o = lab(&dir, &args);
            assert!(o.status.success(), "{args:?}: {}", stderr(&o));
            (
                fs::read(dir.path().join(format!("{out}.csv"))).unwrap(),
                fs::read(dir.path().join(format!("{out}.svg"))).unwrap(),
            )
        };
        let one = run("1");
        assert_eq!(one, run("2"), "{prim}: --threads 2 differs");
        assert_eq!(one, run("3"), "{prim}: --threads 3 differs");
    }
    no_tmp_files(&dir);
}

#[test]
fn convergence_rounds_jittered_counts_and_has_a_default_path() {
    let dir = TempDir::new("convergence-round");
    let o = lab(
        &dir,
        &["convergence", "--n", "10,60", "--realisations", "8"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("--n 60 -> N = 64"), "{stdout}");
    assert!(stdout.contains("--n 10 -> N = 9"), "{stdout}");
    let (comments, _, rows) = csv_table(
        &dir.path()
            .join("out/convergence/disk-2d-points-jittered.csv"),
    );
    assert!(comments.iter().any(|c| c.contains("--n 60 -> N = 64")));
    let ns: Vec<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(ns, ["9", "64"]);
    assert!(dir
        .path()
        .join("out/convergence/disk-2d-points-jittered.svg")
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
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, _, rows) = csv_table(&dir.path().join("b.csv"));
    let ns: Vec<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(ns, ["4", "100"]);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("note:"));
}

#[test]
fn convergence_bad_input_fails_cleanly() {
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
        (&["--n", "0"][..], "--n"),
        (&["--n", "16,17"][..], "--n"),
        (&["--n", "x"][..], "--n"),
        (&["--realisations", "2"][..], "--realisations"),
        (&["--threads", "0"][..], "--threads"),
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
        let o = lab(&dir, &full);
        let err = stderr(&o);
        assert!(!o.status.success(), "{full:?} succeeded");
        assert!(err.starts_with("error: "), "{full:?}: {err}");
        assert!(
            err.contains(names),
            "{full:?}: {err:?} should mention {names:?}"
        );
        assert!(dir.files().is_empty(), "{full:?} left {:?}", dir.files());
    }
}

#[test]
fn convergence_help_is_specific() {
    let dir = TempDir::new("convergence-help");
    let o = lab(&dir, &["convergence", "--help"]);
    assert!(o.status.success());
    let h = String::from_utf8_lossy(&o.stdout);
    for s in [
        "variance",
        "toroidal shift",
        "weighted least squares",
        "PREFIX.csv",
        "PREFIX.svg",
        "bias z-score",
        "--threads",
        "--groups",
        "m^d'",
        "bit-identical",
    ] {
        assert!(h.contains(s), "help lacks {s}");
    }
}

#[test]
fn convergence_runs_every_integrand_and_primitive() {
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
        let o = lab(&dir, &full);
        assert!(o.status.success(), "{full:?}: {}", stderr(&o));
        let (_, header, rows) = csv_table(&dir.path().join(format!("{out}.csv")));
        assert_eq!(header.join(","), CONVERGENCE_HEADER);
        assert_eq!(rows.len(), 2, "{full:?}");
        for r in &rows {
            let v: Vec<f64> = r[2..].iter().map(|x| x.parse().unwrap()).collect();
            check_bias(v[0], v[1], v[2], v[3], v[4], 40, &format!("{full:?}"));
        }
    }
    no_tmp_files(&dir);
}

const SPECTRUM_HEADER: &str = "radius,mean_np,std_error,count";

/// Width and height from the IHDR chunk, after checking the signature.
fn png_size(path: &Path) -> (u32, u32) {
    let b = fs::read(path).expect("read png");
    assert_eq!(
        &b[..8],
        b"\x89PNG\r\n\x1a\n",
        "{}: signature",
        path.display()
    );
    assert_eq!(
        &b[8..16],
        b"\0\0\0\x0dIHDR",
        "{}: IHDR first",
        path.display()
    );
    let be = |i: usize| u32::from_be_bytes(b[i..i + 4].try_into().unwrap());
    assert!(
        b.ends_with(b"IEND\xae\x42\x60\x82"),
        "{}: IEND",
        path.display()
    );
    (be(16), be(20))
}

/// Full-grid frequency counts of the rings `round(|ν|) = r`, `r = 0..=k`, in
/// `d` dimensions (exact integer rule: `r² − r < |ν|² ≤ r² + r`).
fn ring_counts(k: i64, d: u32) -> Vec<u64> {
    let mut c = vec![0u64; k as usize + 1];
    let w = 2 * k + 1;
    for i in 0..w.pow(d) {
        let mut m = 0;
        let mut rest = i;
        for _ in 0..d {
            let j = rest % w - k;
            rest /= w;
            m += j * j;
        }
        let r = (0..=k).find(|&r| m <= r * r + r);
        if let Some(r) = r {
            c[r as usize] += 1;
        }
    }
    c
}

/// `(radius, mean, se, count)` rows of a spectrum CSV, checking the header.
fn spectrum_rows(path: &Path) -> Vec<(usize, f64, f64, u64)> {
    let (comments, header, rows) = csv_table(path);
    assert!(comments.is_empty(), "{comments:?}");
    assert_eq!(header.join(","), SPECTRUM_HEADER);
    rows.iter()
        .map(|r| {
            assert_eq!(r.len(), 4, "{r:?}");
            (
                r[0].parse().unwrap(),
                r[1].parse().unwrap(),
                r[2].parse().unwrap(),
                r[3].parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn spectrum_of_random_points() {
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
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("N = 64, k = 8"), "{stdout}");
    assert!(stdout.contains("ms/real."), "{stdout}");
    let rows = spectrum_rows(&dir.path().join("res/white-radial.csv"));
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
    // 17 frequencies per side, upscaled 16x to at least 256 pixels.
    assert_eq!(
        png_size(&dir.path().join("res/white.png")),
        (17 * 16, 17 * 16)
    );
    let svg = fs::read_to_string(dir.path().join("res/white-radial.svg")).unwrap();
    assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("random 2D points, N = 64, R = 8"), "title");
    no_tmp_files(&dir);
    assert_eq!(
        dir.files(),
        vec![
            PathBuf::from("res/white-radial.csv"),
            PathBuf::from("res/white-radial.svg"),
            PathBuf::from("res/white.png")
        ]
    );
}

#[test]
fn spectrum_is_independent_of_the_thread_count() {
    let dir = TempDir::new("spectrum-threads");
    let run = |threads: &str| {
        let out = format!("t{threads}");
        let o = lab(
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
                "7",
                "--seed",
                "3",
                "--threads",
                threads,
                "--out",
                &out,
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        (
            fs::read(dir.path().join(format!("{out}-radial.csv"))).unwrap(),
            fs::read(dir.path().join(format!("{out}.png"))).unwrap(),
            fs::read(dir.path().join(format!("{out}-radial.svg"))).unwrap(),
        )
    };
    let one = run("1");
    assert_eq!(one, run("3"), "--threads 3 differs from --threads 1");
    no_tmp_files(&dir);
}

#[test]
fn spectrum_reads_point_files() {
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
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("b.pts, line 1: skipped the header line '40'"),
        "{err}"
    );
    assert!(err.contains("a.txt: wrapped 1 coordinate"), "{err}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("R = 2 realisation(s)"), "{stdout}");
    let rows = spectrum_rows(&dir.path().join("files-radial.csv"));
    assert_eq!(rows.len(), 6);
    assert_eq!(png_size(&dir.path().join("files.png")), (13 * 20, 13 * 20));

    // A single 3D file with the default output path.
    fs::write(
        dir.path().join("c.txt"),
        "0.1 0.2 0.3\n0.5 0.5 0.5\n0.9 0.1 0.7\n",
    )
    .unwrap();
    let o = lab(&dir, &["spectrum", "--input", "c.txt", "--k", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("out/spectrum/c-3d-3-radial.csv").is_file());

    // Malformed: a bad number at line 3; nothing is written.
    let bad = TempDir::new("spectrum-bad-input");
    fs::write(bad.path().join("bad.txt"), "0.1 0.2\n0.3 0.4\n0.5 x\n").unwrap();
    let o = lab(&bad, &["spectrum", "--input", "bad.txt", "--out", "r"]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.starts_with("error: ") && err.contains("bad.txt, line 3"),
        "{err}"
    );
    assert_eq!(bad.files(), vec![PathBuf::from("bad.txt")]);
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
        assert!(!o.status.success(), "{name}");
        let err = stderr(&o);
        assert!(err.contains(name) && err.contains(want), "{name}: {err}");
    }
    let o = lab(&bad, &["spectrum", "--input", "missing.txt", "--out", "r"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("missing.txt"), "{}", stderr(&o));
    assert!(bad
        .files()
        .iter()
        .all(|f| f.extension().is_some_and(|e| e == "txt")));
    no_tmp_files(&bad);
}

#[test]
fn spectrum_of_segments_and_lines() {
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
            Some(272), // 2k+1 = 17 frequencies, upscaled 16x
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
        assert!(o.status.success(), "{a:?}: {}", stderr(&o));
        let rows = spectrum_rows(&dir.path().join(format!("{out}-radial.csv")));
        assert!(!rows.is_empty() && rows.iter().all(|r| r.1 > 0.0), "{out}");
        let png_path = dir.path().join(format!("{out}.png"));
        match png {
            Some(side) => assert_eq!(png_size(&png_path), (side, side), "{out}"),
            None => {
                assert!(!png_path.exists(), "{out}");
                let stdout = String::from_utf8_lossy(&o.stdout);
                assert!(stdout.contains("no PNG"), "{stdout}");
            }
        }
    }
    // Ring counts of the 3D grid and the 1D grid.
    let rows = spectrum_rows(&dir.path().join("pts3-radial.csv"));
    let c3 = ring_counts(4, 3);
    assert!(rows.iter().all(|r| r.3 == c3[r.0]), "{rows:?}");
    assert_eq!(rows[0].3, 18); // |ν|² ∈ {1, 2}: 6 + 12
    let rows = spectrum_rows(&dir.path().join("lines2-radial.csv"));
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
        (&["--threads", "0"][..], "--threads 0"),
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
        let o = lab(&dir, &a);
        assert!(!o.status.success(), "{a:?}");
        assert!(stderr(&o).contains(want), "{a:?}: {}", stderr(&o));
    }
    assert!(!dir
        .files()
        .iter()
        .any(|f| f.to_string_lossy().contains("never")));
}

#[test]
fn spectrum_help_documents_the_formats() {
    let dir = TempDir::new("spectrum-help");
    let o = lab(&dir, &["spectrum", "--help"]);
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    for want in [
        "radius,mean_np,std_error,count",
        "--realizations",
        "realisations",
        "--input",
        "--method",
        "direct",
        "point-count header",
    ] {
        assert!(help.contains(want), "{want}: {help}");
    }
}

#[test]
fn spectrum_nufft_matches_direct_to_its_tolerance() {
    let dir = TempDir::new("spectrum-nufft");
    for (dims, prim, tol) in [
        ("2", "points", "1e-12"),
        ("3", "lines", "1e-10"),
        ("1", "points", "1e-6"),
    ] {
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
            let o = lab(&dir, &args);
            assert!(o.status.success(), "{}", stderr(&o));
            assert!(String::from_utf8_lossy(&o.stdout).contains(&format!("method {method}")));
            rows.push(spectrum_rows(&dir.path().join(format!("{out}-radial.csv"))));
        }
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
        let d_eff: usize = if prim == "lines" {
            dims.parse::<usize>().unwrap() - 1
        } else {
            dims.parse().unwrap()
        };
        let k_all = ((d_eff as f64).sqrt() * 9.0 + 0.5).ceil() as usize;
        let out = format!("res/{dims}{prim}-direct-all");
        let k_all_s = k_all.to_string();
        let o = lab(
            &dir,
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
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let all = spectrum_rows(&dir.path().join(format!("{out}-radial.csv")));
        let n = 64.0;
        let a_total = n * n + n * all.iter().map(|r| r.3 as f64 * r.1).sum::<f64>();
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
    // --tol belongs to nufft; nufft does not do segments.
    let o = lab(
        &dir,
        &[
            "spectrum",
            "--sampler",
            "random",
            "--tol",
            "1e-6",
            "--out",
            "res/x",
        ],
    );
    assert!(!o.status.success() && stderr(&o).contains("--tol applies to --method nufft"));
    let o = lab(
        &dir,
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
    );
    assert!(
        !o.status.success() && stderr(&o).contains("segment"),
        "{}",
        stderr(&o)
    );
    let o = lab(
        &dir,
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
    );
    assert!(
        !o.status.success() && stderr(&o).contains("--tol 0"),
        "{}",
        stderr(&o)
    );
    no_tmp_files(&dir);
}
