//! The runner end to end: shards in separate processes merged into the
//! single-process result, a killed run resumed to the uninterrupted result,
//! refused configuration changes, locks, all-or-nothing output groups, and the
//! progress bar on a terminal only.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::*;

fn spawn(dir: &TempDir, args: &[&str]) -> Child {
    Command::new(BIN)
        .args(args)
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn linesample-lab")
}

fn cells(dir: &TempDir, state: &str) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir.path().join(state).join("cells"))
        .map(|r| {
            r.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| !n.starts_with('.'))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

const SWEEP: &[&str] = &[
    "convergence",
    "--integrand",
    "gaussian",
    "--primitive",
    "segments",
    "--sampler",
    "random",
    "--n",
    "12,20,33,47,64,90",
    "--realisations",
    "150",
    "--seed",
    "11",
];

#[test]
fn two_shard_processes_merge_to_the_single_run() {
    let dir = TempDir::new("shards");
    fn with<'a>(extra: &[&'a str]) -> Vec<&'a str> {
        let mut a = SWEEP.to_vec();
        a.extend(extra);
        a.push("--quiet");
        a
    }
    ok(&lab(&dir, &with(&["--out", "single"])), "single");
    let (a, b) = (
        with(&["--shard", "1/2", "--out", "s1"]),
        with(&["--shard", "2/2", "--out", "s2"]),
    );
    let (c1, c2) = (spawn(&dir, &a), spawn(&dir, &b));
    for c in [c1, c2] {
        let o = c.wait_with_output().unwrap();
        ok(&o, "shard");
    }
    // Shards hold disjoint cells and write no outputs.
    assert_eq!(
        cells(&dir, "s1.state"),
        ["000000.bin", "000002.bin", "000004.bin"]
    );
    assert_eq!(
        cells(&dir, "s2.state"),
        ["000001.bin", "000003.bin", "000005.bin"]
    );
    assert!(!dir.path().join("s1/convergence.csv").exists());
    let o = lab(&dir, &["merge", "--out", "merged", "s1", "s2"]);
    ok(&o, "merge");
    for ext in ["csv", "svg"] {
        assert_eq!(
            fs::read_to_string(dir.path().join(format!("single/convergence.{ext}"))).unwrap(),
            fs::read_to_string(dir.path().join(format!("merged/convergence.{ext}"))).unwrap(),
            "merged.{ext} differs from the single run"
        );
    }
    let m: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.path().join("merged/manifest.json")).unwrap())
            .unwrap();
    assert_eq!(m["merged_from"], serde_json::json!(["s1", "s2"]));
    // The merged state is complete: the unsharded command finds every cell.
    let o = lab(&dir, &with(&["--out", "merged"])[..SWEEP.len() + 2]);
    ok(&o, "rerun on the merged state");
    assert!(
        stdout(&o).contains("6 of 6 cell(s) already done, computing 0"),
        "{}",
        stdout(&o)
    );

    // Merge errors: a missing shard, a shard twice, a different run.
    fails_with(
        &lab(&dir, &["merge", "--out", "m2", "s1"]),
        "missing: 2/2",
        "missing shard",
    );
    fails_with(
        &lab(&dir, &["merge", "--out", "m2", "s1", "s1"]),
        "given twice",
        "twice",
    );
    let mut other = with(&["--shard", "2/2", "--out", "s2x"]);
    let at = other.iter().position(|a| *a == "150").unwrap();
    other[at] = "160";
    ok(&lab(&dir, &other), "other shard");
    fails_with(
        &lab(&dir, &["merge", "--out", "m2", "s1", "s2x"]),
        "realisations: stored 160, now 150",
        "different run",
    );
    fails_with(
        &lab(&dir, &["merge", "--out", "m2", "single"]),
        "not a sharded run",
        "unsharded",
    );
    fs::remove_file(dir.path().join("s2.state/cells/000003.bin")).unwrap();
    fails_with(
        &lab(&dir, &["merge", "--out", "m2", "s1", "s2"]),
        "has not finished cell 3",
        "unfinished shard",
    );
    assert!(!dir.path().join("m2/convergence.csv").exists());
}

#[test]
fn spectrum_shards_merge_to_the_single_run() {
    let dir = TempDir::new("spectrum-shards");
    let base = [
        "spectrum",
        "--sampler",
        "poisson-disk",
        "-n",
        "128",
        "--k",
        "10",
        "--realizations",
        "19",
        "--quiet",
    ];
    let run = |extra: &[&str]| {
        let mut a = base.to_vec();
        a.extend(extra);
        ok(&lab(&dir, &a), &format!("{a:?}"));
    };
    run(&["--out", "single"]);
    for i in 1..=3 {
        run(&["--shard", &format!("{i}/3"), "--out", &format!("s{i}")]);
    }
    ok(
        &lab(&dir, &["merge", "--out", "merged", "s3", "s1", "s2"]),
        "merge",
    );
    for suffix in ["-radial.csv", ".png", "-radial.svg"] {
        assert_eq!(
            fs::read(dir.path().join(format!("single/spectrum{suffix}"))).unwrap(),
            fs::read(dir.path().join(format!("merged/spectrum{suffix}"))).unwrap(),
            "{suffix}"
        );
    }
}

/// Runs a long convergence sweep (20 cells, one thread), stops it with
/// `signal` once at least one cell is stored, reruns it, and compares with an
/// uninterrupted run.
fn interrupted_run_resumes(signal: &str) {
    let dir = TempDir::new(&format!("kill-{signal}"));
    let ns: Vec<String> = (0..20).map(|i| (3000 + 7 * i).to_string()).collect();
    let ns = ns.join(",");
    let args = |out: &str| -> Vec<String> {
        [
            "convergence",
            "--sampler",
            "random",
            "--n",
            &ns,
            "--realisations",
            "160",
            "--threads",
            "1",
            "--out",
            out,
        ]
        .iter()
        .map(ToString::to_string)
        .collect()
    };
    let argv = args("run");
    let argv: Vec<&str> = argv.iter().map(String::as_str).collect();
    let mut child = spawn(&dir, &argv);
    let start = Instant::now();
    while cells(&dir, "run.state").is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no cell after 120 s"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before the first check"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    // A second run on the same folder is refused while the first holds it.
    let o = lab(&dir, &argv);
    fails_with(&o, "another linesample-lab run is using", "concurrent run");
    if signal == "KILL" {
        child.kill().unwrap();
    } else {
        let st = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
    }
    let status = child.wait().unwrap();
    assert!(
        !status.success(),
        "the run finished before the signal: {status:?}"
    );
    if signal != "KILL" {
        // A handled signal: one clear line, and the shell's exit code for
        // a process stopped by it.
        use std::os::unix::process::ExitStatusExt;
        let code = if signal == "TERM" { 143 } else { 130 };
        assert_eq!(status.code(), Some(code), "{status:?}");
        assert_eq!(
            status.signal(),
            None,
            "killed instead of stopping: {status:?}"
        );
        let mut err = String::new();
        std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
        let name = format!("stopped by SIG{signal}: ");
        assert!(
            err.contains(&name) && err.contains("run the same command again to resume"),
            "{err}"
        );
    }
    let done = cells(&dir, "run.state").len();
    assert!((1..20).contains(&done), "{done} cells at the signal");
    assert!(
        !dir.path().join("run/convergence.csv").exists(),
        "no output from a stopped run"
    );

    let o = lab(&dir, &argv);
    ok(&o, "resume");
    let want = format!("{done} of 20 cell(s) already done, computing {}", 20 - done);
    assert!(stdout(&o).contains(&want), "{}", stdout(&o));
    assert_eq!(
        cells(&dir, "run.state").len(),
        20,
        "no cell lost or duplicated"
    );
    let m: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.path().join("run/manifest.json")).unwrap()).unwrap();
    assert_eq!(
        (m["cells_resumed"].as_u64(), m["cells_computed"].as_u64()),
        (Some(done as u64), Some(20 - done as u64))
    );

    let full = args("full");
    let full: Vec<&str> = full.iter().map(String::as_str).collect();
    ok(&lab(&dir, &full), "uninterrupted");
    assert_eq!(
        fs::read_to_string(dir.path().join("run/convergence.csv")).unwrap(),
        fs::read_to_string(dir.path().join("full/convergence.csv")).unwrap(),
        "the resumed run differs from the uninterrupted one"
    );
    no_tmp_files(&dir);
}

#[test]
fn killed_run_resumes_to_the_uninterrupted_result() {
    interrupted_run_resumes("KILL");
}

/// SIGTERM (what Slurm, `timeout` and systemd send) stops the run cleanly.
#[test]
fn terminated_run_resumes_to_the_uninterrupted_result() {
    interrupted_run_resumes("TERM");
}

/// SIGINT stops it the same way, even when the test runs as a background
/// job of a non-interactive shell (which starts its children with SIGINT
/// ignored: the lab installs its own handler).
#[test]
fn interrupted_run_resumes_to_the_uninterrupted_result() {
    interrupted_run_resumes("INT");
}

#[test]
fn a_changed_configuration_is_refused_and_fresh_starts_over() {
    let dir = TempDir::new("changed");
    let run = |r: &str, extra: &[&str]| {
        let mut a = vec![
            "convergence",
            "--n",
            "16,64",
            "--realisations",
            r,
            "--out",
            "c",
        ];
        a.extend(extra);
        lab(&dir, &a)
    };
    ok(&run("40", &[]), "first");
    let before: Vec<(PathBuf, Vec<u8>)> = dir
        .all_files()
        .into_iter()
        .filter(|f| !f.ends_with("lock"))
        .map(|f| {
            let b = fs::read(dir.path().join(&f)).unwrap();
            (f, b)
        })
        .collect();
    let o = run("50", &[]);
    fails_with(&o, "realisations: stored 40, now 50", "changed R");
    assert!(stderr(&o).contains("--fresh"), "{}", stderr(&o));
    let o = run("40", &["--shift", "none"]);
    fails_with(
        &o,
        "shift: stored \"random\", now \"none\"",
        "changed shift",
    );
    let o = run("40", &["--shard", "1/2"]);
    fails_with(&o, "--shard 1/2", "changed shard");
    for (f, b) in &before {
        assert_eq!(
            &fs::read(dir.path().join(f)).unwrap(),
            b,
            "{} changed",
            f.display()
        );
    }
    let o = run("50", &["--fresh"]);
    ok(&o, "fresh");
    let (_, _, rows) = csv_table(&dir.path().join("c/convergence.csv"));
    assert!(rows.iter().all(|r| r[1] == "50"));
}

#[test]
fn a_group_that_fails_after_its_first_file_leaves_the_old_files() {
    let dir = TempDir::new("group");
    fs::create_dir_all(dir.path().join("res/c/convergence.svg/keep")).unwrap();
    fs::write(dir.path().join("res/c/convergence.csv"), "old table\n").unwrap();
    let o = lab(
        &dir,
        &[
            "convergence",
            "--n",
            "16",
            "--realisations",
            "8",
            "--out",
            "res/c",
        ],
    );
    fails_with(&o, "res/c/convergence.svg", "svg path is a directory");
    assert_eq!(
        fs::read_to_string(dir.path().join("res/c/convergence.csv")).unwrap(),
        "old table\n"
    );
    assert!(!dir.path().join("res/c/manifest.json").exists());
    no_tmp_files(&dir);
}

#[test]
fn an_unwritable_folder_is_an_error_and_touches_nothing() {
    let dir = TempDir::new("unwritable-run");
    fs::write(dir.path().join("blocker"), "x").unwrap();
    let o = lab(
        &dir,
        &[
            "convergence",
            "--n",
            "16",
            "--realisations",
            "8",
            "--out",
            "blocker/c",
        ],
    );
    fails_with(&o, "blocker", "parent is a file");
    assert_eq!(dir.all_files(), [PathBuf::from("blocker")]);
    // A read-only folder (effective only without root's override).
    let ro = dir.path().join("ro");
    fs::create_dir_all(ro.join("c")).unwrap();
    fs::write(ro.join("c/convergence.csv"), "old\n").unwrap();
    use std::os::unix::fs::PermissionsExt;
    fs::set_permissions(ro.join("c"), fs::Permissions::from_mode(0o555)).unwrap();
    fs::set_permissions(&ro, fs::Permissions::from_mode(0o555)).unwrap();
    if fs::write(ro.join("probe"), "x").is_ok() {
        let _ = fs::remove_file(ro.join("probe"));
        println!("running as root: the read-only folder case is not effective here");
    } else {
        let o = lab(
            &dir,
            &[
                "convergence",
                "--n",
                "16",
                "--realisations",
                "8",
                "--out",
                "ro/c",
            ],
        );
        fails_with(&o, "ro/c", "read-only folder");
        assert_eq!(
            fs::read_to_string(ro.join("c/convergence.csv")).unwrap(),
            "old\n"
        );
    }
    fs::set_permissions(&ro, fs::Permissions::from_mode(0o755)).unwrap();
    fs::set_permissions(ro.join("c"), fs::Permissions::from_mode(0o755)).unwrap();
}

#[test]
fn a_failed_first_run_leaves_no_state() {
    let dir = TempDir::new("failed-first");
    // Bridson at the densest radius cannot place N points: the first cell fails.
    let o = lab(
        &dir,
        &[
            "convergence",
            "--sampler",
            "poisson-disk",
            "--bridson",
            "--relative-radius",
            "1",
            "--n",
            "64",
            "--realisations",
            "8",
            "--out",
            "c",
        ],
    );
    fails_with(&o, "relative-radius", "shortfall");
    assert!(dir.all_files().is_empty(), "{:?}", dir.all_files());
}

fn progress_output(dir: &Path) -> Option<String> {
    let cmd = format!("{BIN} convergence --n 1000,2000,3000 --sampler random --realisations 3000 --threads 1 --out p");
    let o = Command::new("script")
        .args(["-qec", &cmd, "/dev/null"])
        .current_dir(dir)
        .output()
        .ok()?;
    Some(String::from_utf8_lossy(&o.stdout).into_owned())
}

#[test]
fn progress_is_drawn_on_a_terminal_only() {
    let dir = TempDir::new("progress");
    // Not a terminal (this test's pipes, like CI logs): nothing on stderr.
    let o = lab(
        &dir,
        &[
            "convergence",
            "--n",
            "16,64",
            "--realisations",
            "64",
            "--out",
            "q",
        ],
    );
    ok(&o, "piped");
    assert!(stderr(&o).is_empty(), "{:?}", stderr(&o));
    // On a pseudo-terminal (util-linux `script`): the bar with its counts.
    match progress_output(dir.path()) {
        Some(tty) => {
            assert!(tty.contains("realisations, cells"), "{tty:?}");
            assert!(tty.contains("/9000") || tty.contains("/9,000"), "{tty:?}");
            let quiet = Command::new("script")
                .args([
                    "-qec",
                    &format!("{BIN} convergence --n 16 --realisations 8 --quiet --out pq"),
                    "/dev/null",
                ])
                .current_dir(dir.path())
                .output()
                .unwrap();
            assert!(
                String::from_utf8_lossy(&quiet.stdout).trim().is_empty(),
                "--quiet prints nothing"
            );
        }
        None => println!("`script` is not installed: the terminal case is not checked here"),
    }
}

#[test]
fn a_damaged_cell_is_computed_again() {
    let dir = TempDir::new("damaged");
    let args = [
        "convergence",
        "--n",
        "16,64,100",
        "--realisations",
        "40",
        "--out",
        "c",
    ];
    ok(&lab(&dir, &args), "first");
    let csv = fs::read(dir.path().join("c/convergence.csv")).unwrap();
    // An empty file (what a power loss can leave) and a truncated one.
    fs::write(dir.path().join("c.state/cells/000001.bin"), b"").unwrap();
    let b = fs::read(dir.path().join("c.state/cells/000002.bin")).unwrap();
    fs::write(
        dir.path().join("c.state/cells/000002.bin"),
        &b[..b.len() / 2],
    )
    .unwrap();
    let o = lab(&dir, &args);
    ok(&o, "rerun");
    assert!(
        stderr(&o).contains("000001.bin: cannot decode the cell"),
        "{}",
        stderr(&o)
    );
    assert!(
        stdout(&o).contains("1 of 3 cell(s) already done, computing 2"),
        "{}",
        stdout(&o)
    );
    assert_eq!(fs::read(dir.path().join("c/convergence.csv")).unwrap(), csv);
    // Rewritten whole (its stored timings differ, its statistics do not: the
    // CSV above is byte-identical).
    assert_eq!(
        fs::read(dir.path().join("c.state/cells/000002.bin"))
            .unwrap()
            .len(),
        b.len()
    );
}

#[test]
fn a_reader_that_stops_early_does_not_break_the_run() {
    // The rerun prints its "resuming" line, `head` exits, and the run goes on
    // computing the missing cell and printing its table into a closed pipe.
    let dir = TempDir::new("pipe");
    let run = format!("{BIN} convergence --sampler random --n 16,4096 --realisations 4000 --out c");
    ok(
        &Command::new("sh")
            .args(["-c", &run])
            .current_dir(dir.path())
            .output()
            .unwrap(),
        "first",
    );
    fs::remove_file(dir.path().join("c.state/cells/000001.bin")).unwrap();
    fs::remove_file(dir.path().join("c/convergence.csv")).unwrap();
    let cmd = format!("set -o pipefail; {run} | head -n 1 > /dev/null");
    let o = Command::new("bash")
        .args(["-c", &cmd])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("c/convergence.csv").is_file());
}

#[test]
fn the_top_level_help_explains_runs() {
    let dir = TempDir::new("help-top");
    let o = lab(&dir, &["--help"]);
    ok(&o, "help");
    let h = stdout(&o);
    for want in [
        "OUT.state/",
        "--fresh",
        "--shard I/N",
        "linesample-lab merge",
        "--threads",
        "--quiet",
        "byte-for-byte",
    ] {
        assert!(h.contains(want), "{want}: {h}");
    }
}
