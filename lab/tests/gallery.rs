//! `gallery` and the default job.

mod common;

use std::fs;
use std::path::PathBuf;

use common::*;

#[test]
fn writes_every_pattern_and_the_index() {
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
    ok(&o, "gallery");
    let csv = fs::read_to_string(dir.path().join("g/index.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("sampler,dims,n,seed,median_us,txt,svg,np_low,np_high,spectrum")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 20, "{csv}");
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
        if d == 2
            && [
                "jittered",
                "poisson-disk",
                "ccvt",
                "cmj",
                "pmj02",
                "pmj02bn",
            ]
            .contains(&r[0])
        {
            assert!(low < 0.6, "{r:?}");
        }
        let stem = dir.path().join("g").join(r[9]);
        assert!(
            PathBuf::from(format!("{}.png", stem.display())).is_file(),
            "{r:?}"
        );
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
        ("poisson-disk-thinned", "2"),
        ("pmj02", "2"),
        ("pmj02bn", "2"),
        ("ccvt", "2"),
        ("ccvt", "3"),
    ] {
        assert!(
            rows.iter().any(|r| r[0] == s && r[1] == d),
            "{s} {d}D missing"
        );
    }
    assert!(!rows.iter().any(|r| r[0] == "cmj" && r[1] == "3"));
    assert!(!rows.iter().any(|r| r[0] == "pmj02" && r[1] == "3"));
    let out = stdout(&o);
    assert!(out.contains("median"), "{out}");
    assert_eq!(out.lines().filter(|l| l.contains(".svg")).count(), 20);
    // 20 × (txt, svg, png, radial csv, radial svg) + index + manifest.
    assert_eq!(dir.files().len(), 20 * 5 + 2, "{:?}", dir.files());
    let manifest: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.path().join("g/manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["experiment"], "gallery");
    assert_eq!(manifest["config"]["spectrum_realizations"], 2);
    assert_eq!(manifest["config"]["shift"], "none");
    assert_eq!(manifest["cell_seconds"].as_array().unwrap().len(), 20);
    no_tmp_files(&dir);

    // A rerun resumes: nothing is recomputed (the timings are the stored
    // ones), and the index is rewritten byte for byte.
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
    ok(&o, "rerun");
    assert!(
        stdout(&o).contains("20 of 20 cell(s) already done, computing 0"),
        "{}",
        stdout(&o)
    );
    assert_eq!(
        fs::read_to_string(dir.path().join("g/index.csv")).unwrap(),
        csv
    );
}

#[test]
fn no_subcommand_runs_the_gallery() {
    let dir = TempDir::new("default");
    ok(&lab(&dir, &[]), "default job");
    assert!(dir.path().join("out/patterns/index.csv").is_file());
    assert!(dir.path().join("out/patterns/cmj-2d-1024.txt").is_file());
    assert!(dir
        .path()
        .join("out/patterns/jittered-3d-1000.svg")
        .is_file());
    assert!(dir
        .path()
        .join("out/patterns.state/manifest.json")
        .is_file());
}

#[test]
fn without_spectra() {
    let dir = TempDir::new("gallery-nospec");
    ok(
        &lab(
            &dir,
            &[
                "gallery",
                "--out-dir",
                "g",
                "--runs",
                "1",
                "--spectrum-realizations",
                "0",
                "--shift",
                "random",
            ],
        ),
        "no spectra",
    );
    let csv = fs::read_to_string(dir.path().join("g/index.csv")).unwrap();
    for l in csv.lines().skip(1) {
        assert!(l.ends_with(",,,"), "{l}");
    }
    assert_eq!(dir.files().len(), 20 * 2 + 2);
    let svg = fs::read_to_string(dir.path().join("g/sobol-2d-1024.svg")).unwrap();
    assert!(svg.contains("shift on"));
}
