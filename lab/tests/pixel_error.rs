//! `linesample-lab pixel-error`: its files, the blue-against-white result it
//! reports, and clean errors for bad parameters.

mod common;

use common::*;

#[test]
fn writes_the_files_and_reports_blue_against_white() {
    let dir = TempDir::new("pixel-error");
    let o = lab(
        &dir,
        &[
            "pixel-error",
            "--width",
            "32",
            "--height",
            "32",
            "--realizations",
            "8",
            "--out",
            "pe",
        ],
    );
    ok(&o, "pixel-error");
    let out = stdout(&o);
    assert!(out.contains("ZSobol"), "{out}");
    let p = dir.path().join("pe");
    for f in [
        "rings.csv",
        "rings.svg",
        "error-zsobol.png",
        "error-independent.png",
        "spectrum-zsobol.png",
        "spectrum-independent.png",
    ] {
        assert!(p.join(f).is_file(), "{f} missing");
    }
    assert_eq!(png_size(&p.join("error-zsobol.png")), (32, 32));
    let (_, header, rows) = csv_table(&p.join("rings.csv"));
    assert_eq!(
        header,
        [
            "ring",
            "frequencies",
            "zsobol",
            "zsobol_se",
            "independent",
            "independent_se"
        ]
    );
    assert_eq!(rows.len(), 17);
    // Rings 1..=4 (8–32 frequencies each, in ± pairs): for white noise a
    // ring mean over 8 images averages at least 32 independent unit
    // exponentials, Gamma(32)/32, so P(< 0.3) < 10⁻⁷ per ring; the ZSobol
    // ring means measured 0.003–0.03, ten times below the 0.35 rule.
    for row in &rows[1..=4] {
        let z: f64 = row[2].parse().unwrap();
        let i: f64 = row[4].parse().unwrap();
        assert!(z < 0.35, "ZSobol ring {}: {z}", row[0]);
        assert!(i > 0.3, "independent ring {}: {i}", row[0]);
    }
    no_tmp_files(&dir);
}

#[test]
fn bad_parameters_are_one_clear_error() {
    let dir = TempDir::new("pixel-error-bad");
    let o = lab(&dir, &["pixel-error", "--spp", "3", "--out", "x"]);
    fails_with(&o, "spp = 3 must be a power of two", "spp 3");
    let o = lab(&dir, &["pixel-error", "--width", "0", "--out", "x"]);
    fails_with(&o, "width = 0", "width 0");
    let o = lab(&dir, &["pixel-error", "--width", "4", "--out", "x"]);
    fails_with(&o, "at least 8 pixels", "width 4");
    let o = lab(&dir, &["pixel-error", "--realizations", "0", "--out", "x"]);
    fails_with(&o, "--realizations", "realizations 0");
    assert!(!dir.path().join("x").join("rings.csv").exists());
}
