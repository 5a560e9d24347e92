//! `linesample-lab paper --mode reduced` end to end: the files at their
//! fixed names with their columns, the numbers in them, resuming, and bad
//! input.
//!
//! False alarms (the seed is fixed, so each run is deterministic; these are
//! the probabilities over seeds that a correct lab fails; tests/README.md
//! keeps the suite-wide budget below 1e-3):
//! * two slopes within 5 SE of their theory (SE = 95 % half-width / 1.96):
//!   5.7e-7 each;
//! * five rows "consistent": they fail only beyond 1.96 SE + 0.1, which at the
//!   reduced run's slope SEs (at most 0.035) is beyond 4.8 SE: below 1.6e-6
//!   each;
//! * the prediction rows agree unless one exceeds the report's Bonferroni
//!   bound at family-wise α = 5e-4 (or misses 5 % where it resolves 5 %):
//!   at most 5e-4 for all rows together;
//! * the straight edge's exact per-N values within 5 SE (26 checks): 1.5e-5.
//!
//! Total below 5.3e-4.

mod common;

use std::fs;
use std::path::Path;

use common::{csv_table, fails_with, lab, ok, stdout, TempDir};

const RATES: [&str; 13] = [
    "table",
    "dims",
    "primitive",
    "sampler",
    "integrand",
    "theory_slope",
    "log_factor",
    "n_min",
    "n_max",
    "measured_slope",
    "slope_ci_low",
    "slope_ci_high",
    "verdict",
];
const PREDICTION: [&str; 12] = [
    "case",
    "dims",
    "primitive",
    "sampler",
    "integrand",
    "n",
    "predicted",
    "predicted_se",
    "measured",
    "measured_se",
    "ratio",
    "ratio_se",
];
const COST: [&str; 8] = [
    "integrand",
    "dims",
    "primitive",
    "sampler",
    "n",
    "rmse",
    "seconds_per_estimate",
    "evaluations_per_estimate",
];

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or_else(|_| panic!("not a number: {s:?}"))
}

/// The rates.csv row of a 2D rate-table curve.
fn rate<'a>(
    header: &[String],
    rows: &'a [Vec<String>],
    primitive: &str,
    sampler: &str,
    integrand: &str,
) -> &'a [String] {
    rows.iter()
        .find(|r| {
            r[col(header, "table")] == "rates"
                && r[col(header, "dims")] == "2"
                && r[col(header, "primitive")] == primitive
                && r[col(header, "sampler")] == sampler
                && r[col(header, "integrand")] == integrand
        })
        .unwrap_or_else(|| panic!("no rates row {primitive} {sampler} {integrand}"))
}

/// Asserts that a rates.csv row's measured slope is within 5 SE of `theory`.
fn assert_within_5_se(h: &[String], r: &[String], theory: f64) {
    // The 95 % interval, widened to 5 SE so that this check keeps the suite's
    // false-alarm budget.
    let (lo, hi) = (
        num(&r[col(h, "slope_ci_low")]),
        num(&r[col(h, "slope_ci_high")]),
    );
    let s = num(&r[col(h, "measured_slope")]);
    let se = (hi - lo) / 2.0 / 1.96;
    assert!(
        (s - theory).abs() <= 5.0 * se,
        "{theory} not within 5 SE of {s} (95 % interval [{lo}, {hi}]): {r:?}"
    );
}

/// The run wrote every file at its fixed name.
fn check_files_exist(out: &Path) {
    for f in [
        "index.html",
        "rates.csv",
        "prediction.csv",
        "cost.csv",
        "manifest.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
}

/// rates.csv: the columns, in order, then the slopes and verdicts.
fn check_rates(out: &Path) {
    let (_, h, rows) = csv_table(&out.join("rates.csv"));
    assert_eq!(&h[..RATES.len()], RATES);
    let random = rate(&h, &rows, "points", "random", "disk");
    assert_within_5_se(&h, random, -1.0);
    assert_eq!(random[col(&h, "verdict")], "consistent");
    let jit = rate(&h, &rows, "points", "jittered", "disk");
    assert_within_5_se(&h, jit, -1.5);
    assert_eq!(jit[col(&h, "theory_slope")], "-1.5e0");
    assert_eq!(jit[col(&h, "verdict")], "consistent");
    let lines = rate(&h, &rows, "lines", "jittered", "disk");
    assert!(
        num(&lines[col(&h, "slope_ci_high")]) < -2.5,
        "jittered lines not faster than -2.5: {lines:?}"
    );
    assert_eq!(lines[col(&h, "log_factor")], "log N");
    assert_eq!(lines[col(&h, "verdict")], "consistent", "{lines:?}");
    // The straight edge: crossing N^-3, parallel N^-2, the fixed edge flagged.
    let edge: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == "edge").collect();
    assert_eq!(edge.len(), 3, "{edge:?}");
    assert!(edge
        .iter()
        .any(|r| r[col(&h, "verdict")] == "pitfall (not homogenised)"));
    for r in &edge[..2] {
        assert_eq!(r[col(&h, "verdict")], "consistent", "{r:?}");
    }
}

/// curves.csv: the straight edge's exact variance at every N, within 5 SE.
fn check_edge_curves(out: &Path) {
    // Exact checks per N (1D jitter, one stratum straddles the edge): a fixed
    // edge at h has Var·N² = q(1 − q), q = frac(h·N); an edge uniform per
    // realisation averages it to 1/6. Within 5 SE at every N.
    let (_, ch, crows) = csv_table(&out.join("curves.csv"));
    let golden = (5f64.sqrt() - 1.0) / 2.0;
    let mut seen = [0, 0];
    for r in &crows {
        let n = num(&r[col(&ch, "n")]);
        let (v, se) = (
            num(&r[col(&ch, "variance")]),
            num(&r[col(&ch, "variance_se")]),
        );
        let want = match r[col(&ch, "curve")].as_str() {
            "edge-2d-lines-parallel-jittered" => {
                seen[0] += 1;
                1.0 / 6.0
            }
            "edge-2d-lines-parallel-fixed-jittered" => {
                seen[1] += 1;
                let q = (golden * n).fract();
                q * (1.0 - q)
            }
            _ => continue,
        };
        assert!(
            (v * n * n - want).abs() <= 5.0 * se * n * n,
            "N = {n}: Var·N² = {} ± {}, expected {want}",
            v * n * n,
            se * n * n
        );
    }
    assert!(seen[0] >= 8 && seen[1] >= 8, "{seen:?}");
}

/// prediction.csv: every predicted row agrees, for both primitives and both integrands.
fn check_prediction(out: &Path) {
    let (comments, h, rows) = csv_table(&out.join("prediction.csv"));
    assert_eq!(&h[..PREDICTION.len()], PREDICTION);
    assert!(comments[0].contains("Bonferroni"), "{comments:?}");
    assert!(rows.len() >= 20, "only {} predicted rows", rows.len());
    for r in &rows {
        let rel = num(&r[col(&h, "rel_diff")]);
        assert_eq!(r[col(&h, "agrees")], "true", "{r:?}");
        if r[col(&h, "resolves_5pc")] == "true" {
            assert!(rel.abs() <= 0.05, "{r:?}");
        }
        assert!(num(&r[col(&h, "predicted")]) > 0.0);
        // The ratio and its delta-method SE, √(SE_p² + ratio²·SE_m²)/measured
        // (a structural check of the columns; the formula is tested in the kernel).
        let (p, sp, m, sm) = (
            num(&r[col(&h, "predicted")]),
            num(&r[col(&h, "predicted_se")]),
            num(&r[col(&h, "measured")]),
            num(&r[col(&h, "measured_se")]),
        );
        let (q, sq) = (num(&r[col(&h, "ratio")]), num(&r[col(&h, "ratio_se")]));
        assert!((q - p / m).abs() <= 1e-12 * q.abs(), "{r:?}");
        assert!((q - 1.0 - rel).abs() <= 1e-12, "{r:?}");
        let want = sp.hypot(q * sm) / m;
        assert!(sp > 0.0 && (sq / want - 1.0).abs() <= 1e-12, "{r:?}");
    }
    // Both primitives and both integrands are predicted.
    for (p, i) in [
        ("points", "disk"),
        ("lines", "disk"),
        ("points", "gaussian"),
    ] {
        assert!(
            rows.iter()
                .any(|r| r[col(&h, "primitive")] == p && r[col(&h, "integrand")] == i),
            "no prediction for {p} {i}"
        );
    }
}

/// cost.csv: one row per N of every non-edge curve; evaluations = N.
fn check_cost(out: &Path) {
    let (_, h, rows) = csv_table(&out.join("cost.csv"));
    assert_eq!(&h[..COST.len()], COST);
    assert!(rows.len() >= 8 * 4, "{} cost rows", rows.len());
    for r in &rows {
        assert_eq!(r[col(&h, "n")], r[col(&h, "evaluations_per_estimate")]);
        assert!(num(&r[col(&h, "seconds_per_estimate")]) > 0.0);
        assert!(num(&r[col(&h, "rmse")]) > 0.0);
    }
}

/// index.html links only existing local files; manifest.json names the experiment and mode.
fn check_report(out: &Path) {
    let html = fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        html.contains("random toroidal shift"),
        "homogenisation not stated"
    );
    let mut links = 0;
    for part in html
        .split("src=\"")
        .skip(1)
        .chain(html.split("href=\"").skip(1))
    {
        let target = &part[..part.find('"').unwrap()];
        if target.starts_with('#') {
            continue;
        }
        assert!(!target.contains("://"), "external link {target}");
        assert!(out.join(target).is_file(), "{target} linked but missing");
        links += 1;
    }
    assert!(links > 15, "{links} links");
    let manifest: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["experiment"], "paper");
    assert_eq!(manifest["config"]["mode"], "reduced");
}

/// A rerun into `p` resumes every cell and writes the same tables.
fn check_rerun_resumes(dir: &TempDir, out: &Path) {
    let before = fs::read(out.join("rates.csv")).unwrap();
    let o = lab(dir, &["paper", "--mode", "reduced", "--out", "p"]);
    ok(&o, "rerun");
    assert!(
        stdout(&o).contains("already done, computing 0"),
        "{}",
        stdout(&o)
    );
    assert_eq!(fs::read(out.join("rates.csv")).unwrap(), before);
}

/// One reduced paper run, then every check on its outputs and a resumed rerun.
#[test]
fn reduced_paper_end_to_end() {
    let dir = TempDir::new("paper");
    let o = lab(
        &dir,
        &["paper", "--mode", "reduced", "--out", "p", "--quiet"],
    );
    ok(&o, "paper --mode reduced");
    let out = dir.path().join("p");
    check_files_exist(&out);
    check_rates(&out);
    check_edge_curves(&out);
    check_prediction(&out);
    check_cost(&out);
    check_report(&out);
    check_rerun_resumes(&dir, &out);
}

#[test]
fn bad_input_is_one_line_and_writes_nothing() {
    let dir = TempDir::new("paper-bad");
    let o = lab(&dir, &["paper", "--mode", "slow"]);
    assert!(!o.status.success());
    let o = lab(&dir, &["paper", "--shift", "none", "--out", "p"]);
    fails_with(&o, "--shift", "--shift none");
    let o = lab(
        &dir,
        &["paper", "--full", "--mode", "reduced", "--out", "p"],
    );
    fails_with(&o, "--full and --mode", "--full --mode reduced");
    fs::write(dir.path().join("f"), b"x").unwrap();
    let o = lab(&dir, &["paper", "--mode", "reduced", "--out", "f"]);
    fails_with(&o, "--out f", "--out a file");
    // A parent that is a file: the run cannot create its state folder.
    let o = lab(
        &dir,
        &["paper", "--mode", "reduced", "--out", "f/p", "--quiet"],
    );
    fails_with(&o, "f/p", "--out under a file");
    assert_eq!(dir.files(), vec![std::path::PathBuf::from("f")]);
}

#[test]
fn sharded_paper_merges_to_the_same_tables() {
    let dir = TempDir::new("paper-shards");
    let args = ["paper", "--mode", "reduced", "--quiet"];
    let one = lab(&dir, &[&args[..], &["--out", "one"]].concat());
    ok(&one, "unsharded");
    for i in 1..=2 {
        let shard = format!("{i}/2");
        let out = format!("s{i}");
        let o = lab(
            &dir,
            &[&args[..], &["--shard", &shard, "--out", &out]].concat(),
        );
        ok(&o, &shard);
        // A shard writes only its state, no report.
        assert!(!dir.path().join(&out).join("index.html").exists());
    }
    let o = lab(&dir, &["merge", "--out", "merged", "s1", "s2", "--quiet"]);
    ok(&o, "merge");
    // Tables without timings are identical, byte for byte.
    for f in ["rates.csv", "prediction.csv", "curves.csv"] {
        assert_eq!(
            fs::read(dir.path().join("one").join(f)).unwrap(),
            fs::read(dir.path().join("merged").join(f)).unwrap(),
            "{f}"
        );
    }
    assert!(dir.path().join("merged/index.html").is_file());
}
