//! `linesample-lab scene` end to end: the images and their table, resume,
//! independence of the thread count, the pixel study's JSON, and one clean
//! error for a bad scene file, a pixel outside the image and a pixel whose
//! camera ray misses the scene.

mod common;

use std::fs;
use std::path::PathBuf;

use common::*;

fn scene_file() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/ao-spheres.toml")
        .display()
        .to_string()
}

fn images(dir: &TempDir, out: &str, threads: &str) -> std::process::Output {
    let file = scene_file();
    lab(
        dir,
        &[
            "scene",
            &file,
            "--resolution",
            "20x16",
            "--n",
            "4",
            "--variance-realisations",
            "3",
            "--reference-lines",
            "16",
            "--reference-realisations",
            "4",
            "--threads",
            threads,
            "--out",
            out,
        ],
    )
}

#[test]
fn images_table_resume_and_threads() {
    let dir = TempDir::new("scene-images");
    let o = images(&dir, "a", "2");
    ok(&o, "scene images");
    let a = dir.path().join("a");
    for f in [
        "reference.png",
        "reference-se.png",
        "sheet.png",
        "images.csv",
        "manifest.json",
        "equal-samples-points.png",
        "equal-time-lines.png",
        "variance-segments-0.1.png",
        "variance-segments-pi.png",
    ] {
        assert!(a.join(f).is_file(), "{f} missing");
    }
    // The PNG header's width and height (big-endian, bytes 16..24).
    let png = fs::read(a.join("reference.png")).unwrap();
    let be = |i: usize| u32::from_be_bytes(png[i..i + 4].try_into().unwrap());
    assert_eq!((be(16), be(20)), (20, 16));
    // 7 estimators (points, 4 segment lengths, lines in f64 and in the f32
    // SIMD batch) x ladder 1, 2, 4, 8, 16.
    let (_, header, rows) = csv_table(&a.join("images.csv"));
    assert_eq!(
        header.join(","),
        "estimator,n,seconds,seconds_per_sample,mse,mean_variance,equal_samples,equal_time"
    );
    assert_eq!(rows.len(), 7 * 5);
    for est in 0..7 {
        let mine = &rows[est * 5..est * 5 + 5];
        assert_eq!(mine.iter().filter(|r| r[6] == "true").count(), 1);
        assert_eq!(mine.iter().filter(|r| r[7] == "true").count(), 1);
        let at4 = mine.iter().find(|r| r[1] == "4").unwrap();
        assert_eq!(at4[6], "true", "equal samples at --n 4");
        // Lines beat points by orders of magnitude in error at equal N.
        let mse: f64 = at4[4].parse().unwrap();
        assert!(mse.is_finite() && mse >= 0.0);
    }
    let mse_at = |name: &str| -> f64 {
        rows.iter()
            .find(|r| r[0].starts_with(name) && r[1] == "16")
            .unwrap()[4]
            .parse()
            .unwrap()
    };
    // The f32 batch's lines are the f64 lines to f32 rounding.
    let f32_lines: f64 = rows
        .iter()
        .find(|r| r[0].starts_with("lines f32") && r[1] == "16")
        .unwrap()[4]
        .parse()
        .unwrap();
    assert!((f32_lines - mse_at("lines multi")).abs() <= 1e-3 * mse_at("lines multi") + 1e-12);
    assert!(
        mse_at("lines") < 0.1 * mse_at("points"),
        "lines {} vs points {}",
        mse_at("lines"),
        mse_at("points")
    );
    // A rerun resumes every cell; another thread count gives the same images.
    let again = images(&dir, "a", "2");
    ok(&again, "resume");
    assert!(
        stdout(&again).contains("2 of 2 cell(s) already done, computing 0"),
        "{}",
        stdout(&again)
    );
    ok(&images(&dir, "b", "1"), "one thread");
    let b = dir.path().join("b");
    for f in [
        "reference.png",
        "equal-samples-points.png",
        "equal-samples-segments-1.png",
        "variance-lines.png",
    ] {
        assert_eq!(
            fs::read(a.join(f)).unwrap(),
            fs::read(b.join(f)).unwrap(),
            "{f} depends on the thread count"
        );
    }
    no_tmp_files(&dir);
}

#[test]
fn pixel_study_writes_its_json() {
    let dir = TempDir::new("scene-pixel");
    let file = scene_file();
    let o = lab(
        &dir,
        &[
            "scene",
            &file,
            "--pixel",
            "410,305",
            "--pixel-n",
            "4,16",
            "--realisations",
            "8",
            "--samplers",
            "multi-jittered",
            "--reference-lines",
            "256",
            "--reference-realisations",
            "8",
            "--spectrum-realisations",
            "0",
            "--out",
            "p",
            "--quiet",
        ],
    );
    ok(&o, "pixel study");
    let p = dir.path().join("p");
    let v: serde_json::Value =
        serde_json::from_slice(&fs::read(p.join("pixel-410-305.json")).unwrap()).unwrap();
    let value = v["reference"]["value"].as_f64().unwrap();
    let se = v["reference"]["se"].as_f64().unwrap();
    // The AO of this pixel from 2^16 stratified lines is 0.714721.
    assert!(
        (value - 0.714_721).abs() < 5.0 * se + 1e-5,
        "{value} ± {se}"
    );
    assert!(se > 0.0 && se < 1e-3);
    // 16 rows (3 point densities, 3 x 4 segments, lines) x 2 N.
    let rows = v["convergence"].as_array().unwrap();
    assert_eq!(rows.len(), 16 * 2);
    for r in rows {
        assert!(r["variance"].as_f64().unwrap() >= 0.0);
        assert_eq!(r["realisations"].as_u64(), Some(8));
    }
    assert_eq!(v["slopes"].as_array().unwrap().len(), 16);
    for f in [
        "pixel-410-305.csv",
        "pixel-410-305-slopes.csv",
        "pixel-410-305.svg",
    ] {
        assert!(p.join(f).is_file(), "{f} missing");
    }
}

#[test]
fn bad_input_is_one_clean_error() {
    let dir = TempDir::new("scene-errors");
    let bad = dir.path().join("bad.toml");
    let text = fs::read_to_string(scene_file()).unwrap();
    fs::write(&bad, text.replace("radius = 0.5", "radius = -0.5")).unwrap();
    let o = lab(&dir, &["scene", "bad.toml", "--resolution", "8x8"]);
    fails_with(&o, "bad.toml:", "negative radius");
    assert!(
        stderr(&o).contains(".radius: must be positive"),
        "{}",
        stderr(&o)
    );
    assert_eq!(stderr(&o).lines().count(), 1, "{}", stderr(&o));
    let file = scene_file();
    fails_with(
        &lab(&dir, &["scene", &file, "--pixel", "600,10"]),
        "outside the 512x512 image",
        "pixel outside",
    );
    // The top row looks over the ground into the sky.
    fails_with(
        &lab(&dir, &["scene", &file, "--pixel", "5,0"]),
        "misses every sphere",
        "sky pixel",
    );
    fails_with(
        &lab(&dir, &["scene", &file, "--n", "12"]),
        "--n 12",
        "N off the ladder",
    );
    assert!(dir.files().iter().all(|f| f.ends_with("bad.toml")));
}

/// The spectral prediction of the pixel study against its measurement at
/// pixel (410, 305): every uniform-density estimator (points, segments of
/// each length, lines) x jittered and multi-jittered x N = 16, 64, 256, 400
/// realisations each. Each predicted/measured variance ratio must satisfy
/// `|ln ratio| ≤ 4·SE(Var)/Var + 0.1` (the measurement's standard error,
/// delta method, plus 10 % for the model: the integrand sampled on a
/// 1024² grid and 64 pattern realisations per spectrum). 36 checks; the
/// measurement term alone gives each a false-alarm probability of about
/// 6e−5 (4 SE, normal), 0.2 % for the suite. Release only (the integrand
/// grid is 1M closed-form visibilities): run by CI's statistical step.
#[test]
#[ignore = "release-mode statistics: cargo test --release -p linesample-lab --test scene_cmd -- --ignored"]
fn spectral_prediction_matches_the_pixel() {
    let dir = TempDir::new("scene-predict");
    let file = scene_file();
    let o = lab(
        &dir,
        &[
            "scene",
            &file,
            "--pixel",
            "410,305",
            "--pixel-n",
            "16,64,256",
            "--realisations",
            "400",
            "--samplers",
            "jittered,multi-jittered",
            "--out",
            "p",
        ],
    );
    ok(&o, "pixel study");
    println!("{}", stdout(&o));
    let v: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.path().join("p/pixel-410-305.json")).unwrap())
            .unwrap();
    let mut checks = 0;
    let mut worst = 0.0f64;
    for r in v["convergence"].as_array().unwrap() {
        let Some(pred) = r["predicted_variance"].as_f64() else {
            continue;
        };
        let (var, se) = (
            r["variance"].as_f64().unwrap(),
            r["variance_se"].as_f64().unwrap(),
        );
        let z = (pred / var).ln().abs() / (4.0 * se / var + 0.1);
        worst = worst.max(z);
        assert!(
            z <= 1.0,
            "{} N = {}: predicted {pred:.3e}, measured {var:.3e} ± {se:.1e}",
            r["estimator"],
            r["n"]
        );
        checks += 1;
    }
    println!("{checks} checks, worst |ln ratio| at {worst:.2} of its tolerance");
    assert_eq!(checks, 36);
}

/// One failed cell does not discard the study: the other rows are fitted
/// and written, the failed row says why (estimator, N, realisation) in the
/// CSV, the JSON and its verdict, and the study returns one error naming
/// it. The infinite-variance rows say so in their verdict.
#[test]
fn a_failed_cell_is_reported_in_its_row_and_the_others_complete() {
    use linesample_lab::experiments::scene::{
        all_rows, complete_pixel, PixelCell, PixelConfig, PixelStudy, SceneSource,
    };
    let path = scene_file();
    let text = fs::read_to_string(&path).unwrap();
    let sc = linesample_lab::scene::parse(std::path::Path::new(&path), &text).unwrap();
    let rows = all_rows(&sc);
    let cfg = PixelConfig {
        source: SceneSource { path, text },
        width: 512,
        height: 512,
        pixel: (410, 305),
        seed: 1,
        shift: linesample_lab::cli::ShiftMode::Random,
        ns: vec![4, 16],
        realisations: 8,
        rows: rows[..17].to_vec(),
        reference_lines: 64,
        reference_realisations: 4,
        spectrum_realisations: 0,
    };
    let study = PixelStudy::new(cfg).unwrap();
    let mut cells = linesample_lab::runner::compute(&study, Some(2)).unwrap();
    // Row 2 (the cosine point density) at N = 16 fails.
    let bad = 1 + 2 * 2 + 1;
    cells[bad] = PixelCell::failed(
        "points cosine random at N = 16: realisation 5: the estimate is inf".into(),
    );
    let dir = TempDir::new("scene-failed-cell");
    let info = linesample_lab::runner::RunInfo {
        threads: 2,
        wall: std::time::Duration::ZERO,
        computed: cells.len(),
        resumed: 0,
        cell_seconds: vec![0.0; cells.len()],
        merged_from: Vec::new(),
    };
    let err = complete_pixel(&study, cells, &info, dir.path(), true)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("1 cell(s) of the pixel study failed")
            && err.contains("points cosine random at N = 16: realisation 5"),
        "{err}"
    );
    let v: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.path().join("pixel-410-305.json")).unwrap()).unwrap();
    let slopes = v["slopes"].as_array().unwrap();
    assert_eq!(slopes.len(), 17, "every row has its slope row");
    for (k, s) in slopes.iter().enumerate() {
        let verdict = s["verdict"].as_str().unwrap();
        if k == 2 {
            assert_eq!(verdict, "failed");
            assert!(s["error"].as_str().unwrap().contains("realisation 5"));
        } else {
            assert!(s["slope"].as_f64().is_some(), "row {k} was fitted: {s}");
            assert_eq!(s["error"], "");
            let infinite = s["estimator"].as_str().unwrap().starts_with("segments")
                && !s["estimator"].as_str().unwrap().contains("uniform");
            assert_eq!(verdict == "infinite variance", infinite, "row {k}: {s}");
        }
    }
    let csv = fs::read_to_string(dir.path().join("pixel-410-305.csv")).unwrap();
    let failed: Vec<&str> = csv
        .lines()
        .filter(|l| l.contains("realisation 5"))
        .collect();
    assert_eq!(failed.len(), 1, "{csv}");
}
