//! `linesample-lab scene` on a direct-light scene (the Cornell box): the
//! files and `orientation.csv`, resume, independence of the thread count,
//! clean errors for bad scene files and pixels; and (release, `--ignored`) every
//! estimator unbiased against the reference at A, B and random pixels.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use common::*;
use linesample::stats::RunningStats;
use linesample::Seed;
use linesample_lab::experiments::direct::{self, DlEstimator, DlWorld, Seen, REFERENCE};
use linesample_lab::experiments::samples::{Buffers, SamplePattern};
use linesample_lab::experiments::scene::SceneSource;
use linesample_lab::scene::{self, Orientation, SceneSampler};

fn scene_file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml")
}

fn run(dir: &TempDir, out: &str, threads: &str) -> std::process::Output {
    let file = scene_file().display().to_string();
    lab(
        dir,
        &[
            "scene",
            &file,
            "--resolution",
            "24x24",
            "--n",
            "4",
            "--sampler",
            "jittered",
            "--variance-realisations",
            "3",
            "--reference-lines",
            "16",
            "--reference-realisations",
            "2",
            "--pixel-n",
            "4,16,64",
            "--realisations",
            "8",
            "--threads",
            threads,
            "--out",
            out,
        ],
    )
}

#[test]
fn images_pixels_orientation_resume_and_threads() {
    let dir = TempDir::new("direct-images");
    let o = run(&dir, "a", "2");
    ok(&o, "direct-light scene");
    let a = dir.path().join("a");
    for f in [
        "reference.png",
        "sheet.png",
        "orientation-map.png",
        "images.csv",
        "pixels.json",
        "manifest.json",
        "orientation.csv",
        "points-jittered-n4.png",
        "lines-edge1-jittered-equal-time.png",
        "lines-edge2-jittered-variance.png",
        "pixels/slopes.csv",
        "pixels/rows.csv",
        "pixels/convergence-A.svg",
        "pixels/convergence-B.svg",
        "pixels/time-to-error-A.svg",
    ] {
        assert!(a.join(f).is_file(), "missing {f}");
    }
    let csv = fs::read_to_string(a.join("orientation.csv")).unwrap();
    let body: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(
        body[0],
        "pixel,x,y,estimator,slope,slope_ci_low,slope_ci_high"
    );
    for want in ["A,", "B,"] {
        for est in ["points", "lines-edge1", "lines-edge2"] {
            assert!(
                body.iter()
                    .any(|l| l.starts_with(want) && l.split(',').nth(3) == Some(est)),
                "orientation.csv lacks {want}{est}:\n{csv}"
            );
        }
    }
    // Every slope is a number.
    for l in &body[1..] {
        let s: f64 = l.split(',').nth(4).unwrap().parse().unwrap();
        assert!(s.is_finite(), "{l}");
    }
    // Resume: nothing is recomputed.
    let again = run(&dir, "a", "2");
    ok(&again, "resumed run");
    assert!(
        stdout(&again).contains("already done, computing 0"),
        "{}",
        stdout(&again)
    );
    // One thread draws the same numbers: the estimate images and the rows
    // (times aside) are identical.
    ok(&run(&dir, "b", "1"), "one thread");
    let b = dir.path().join("b");
    for f in [
        "reference.png",
        "points-jittered-n4.png",
        "lines-edge2-jittered-n4.png",
        "pixels.json",
    ] {
        assert_eq!(
            fs::read(a.join(f)).unwrap(),
            fs::read(b.join(f)).unwrap(),
            "{f} differs between 2 and 1 threads"
        );
    }
    let strip = |p: &Path| -> Vec<String> {
        fs::read_to_string(p)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| l.split(',').take(11).collect::<Vec<_>>().join(","))
            .collect()
    };
    assert_eq!(
        strip(&a.join("pixels/rows.csv")),
        strip(&b.join("pixels/rows.csv"))
    );
}

#[test]
fn bad_scene_files_give_one_clean_error() {
    let dir = TempDir::new("direct-bad");
    let text = fs::read_to_string(scene_file()).unwrap();
    let cases: [(&str, &str, &str); 6] = [
        (
            "edge2 = [0.0, 0.0, 0.38]",
            "edge2 = [0.1, 0.0, 0.38]",
            "light.edge2",
        ),
        (
            "\"stratified\"]",
            "\"diagonal\"]",
            "estimators.orientations[4]",
        ),
        (
            "albedo = [0.63, 0.065, 0.05]",
            "albedo = [1.63, 0.065, 0.05]",
            "quad[3].albedo",
        ),
        (
            "size = [0.6, 0.6, 0.6]",
            "size = [0.6, -0.6, 0.6]",
            "box[0].size",
        ),
        (
            "kind = \"direct-light\"",
            "kind = \"direct-light\"\nmax-distance = 3.0",
            "effect.max-distance",
        ),
        (
            "radiance = [17.0, 12.0, 4.0]",
            "radiance = [17.0, nan, 4.0]",
            "light.radiance",
        ),
    ];
    for (from, to, field) in cases {
        assert!(text.contains(from), "{from}");
        let path = dir.path().join("bad.toml");
        fs::write(&path, text.replacen(from, to, 1)).unwrap();
        let o = lab(&dir, &["scene", path.to_str().unwrap(), "--out", "x"]);
        fails_with(&o, field, field);
    }
    // No light at all.
    let start = text.find("[light]").unwrap();
    let end = text[start..].find("[[quad]]").unwrap() + start;
    let path = dir.path().join("nolight.toml");
    fs::write(&path, format!("{}{}", &text[..start], &text[end..])).unwrap();
    let o = lab(&dir, &["scene", path.to_str().unwrap(), "--out", "x"]);
    fails_with(&o, "needs a [light]", "no light");
    // A pixel that sees the light itself, and one outside the image.
    let file = scene_file().display().to_string();
    let o = lab(
        &dir,
        &[
            "scene",
            &file,
            "--resolution",
            "32x32",
            "--pixel",
            "16,2",
            "--out",
            "p",
        ],
    );
    fails_with(&o, "sees the light itself", "pixel on the light");
    let o = lab(
        &dir,
        &[
            "scene",
            &file,
            "--resolution",
            "32x32",
            "--pixel",
            "40,3",
            "--out",
            "p",
        ],
    );
    fails_with(&o, "outside", "pixel outside");
}

/// Every estimator × {random, jittered} at A, B and five random surface
/// pixels of a 64² image: the mean of R = 20000 estimates with N = 16 within
/// 4.5 combined standard errors of the reference (64 × 4096 lines along
/// edge 1). 7 pixels × 12 rows = 84 checks; at 4.5 SE a normal mean
/// exceeds the bound with probability 6.8·10⁻⁶, so the suite's false-alarm
/// rate is 84 × 6.8·10⁻⁶ ≈ 0.06 %.
#[test]
#[ignore = "release statistics: cargo test --release -p linesample-lab --test direct_cmd -- --ignored"]
fn every_estimator_is_unbiased() {
    let path = scene_file();
    let text = fs::read_to_string(&path).unwrap();
    let sc = scene::parse(&path, &text).unwrap();
    let source = SceneSource {
        path: path.display().to_string(),
        text,
    };
    let (w, h) = (64u32, 64u32);
    let world = DlWorld::new(sc.clone(), w, h).unwrap();
    // A and B from a small image run.
    let dir = TempDir::new("direct-bias");
    let out = dir.path().join("img");
    let opts = linesample_lab::runner::RunOptions {
        quiet: true,
        ..linesample_lab::runner::RunOptions::default()
    };
    let chosen = direct::run_images(
        source,
        w,
        h,
        7,
        16,
        direct::estimators(&sc, SceneSampler::Jittered),
        8,
        64,
        2,
        None,
        &out,
        &opts,
    )
    .unwrap()
    .expect("a penumbra in the Cornell box");
    let mut pixels = vec![chosen.a, chosen.b];
    let mut rng = Seed::new(99).pcg(1);
    // Random pixels that get some light (the ceiling and the faces turned
    // away from the light get none: every estimator is exactly 0 there).
    while pixels.len() < 7 {
        let (x, y) = (rng.next_u32() % w, rng.next_u32() % h);
        if let Some(Seen::Surface(px)) = world.pixel(x, y) {
            let lit = (0..64).any(|k| {
                let l = world.light().lengths();
                let a = l[0] * (f64::from(k % 8) + 0.5) / 8.0;
                let b = l[1] * (f64::from(k / 8) + 0.5) / 8.0;
                linesample_scene::direct_light::DirectLight::new(
                    world.light(),
                    px.x,
                    px.n,
                    &px.shadows,
                )
                .unwrap()
                .point(a, b)
                    > 0.0
            });
            if lit {
                pixels.push((x, y));
            }
        }
    }
    let ests = direct::study_estimators(&sc, &[SceneSampler::Random, SceneSampler::Jittered]);
    assert_eq!(ests.len(), 12);
    let (mut vals, mut one, mut scratch) = (Vec::new(), Buffers::default(), Vec::new());
    let mut worst: f64 = 0.0;
    let mut biggest_se: f64 = 0.0;
    for (pi, &(x, y)) in pixels.iter().enumerate() {
        let Some(Seen::Surface(px)) = world.pixel(x, y) else {
            panic!("pixel ({x}, {y}) sees no surface");
        };
        let estimate = |est: &DlEstimator,
                        pat: &SamplePattern,
                        seed: Seed,
                        vals: &mut Vec<[f32; 2]>,
                        one: &mut Buffers,
                        scratch: &mut Vec<(f64, f64)>| {
            pat.fill(seed, vals, one).unwrap();
            let mut r = seed.pcg(0x0c1e_47a7);
            world.estimate(&px, est, vals, &mut r, scratch).unwrap()
        };
        let (_, rp) = SamplePattern::of(&world, None, 4096, None).unwrap();
        let mut rs = RunningStats::new();
        for r in 0..64 {
            rs.push(estimate(
                &REFERENCE,
                &rp,
                Seed::new(5).realization(1000 * pi as u64 + r),
                &mut vals,
                &mut one,
                &mut scratch,
            ));
        }
        let (rv, rse) = (rs.mean(), rs.mean_std_error());
        for (e, est) in ests.iter().enumerate() {
            let (_, pat) = SamplePattern::of(&world, Some(est), 16, None).unwrap();
            let mut s = RunningStats::new();
            for r in 0..20_000 {
                s.push(estimate(
                    est,
                    &pat,
                    Seed::new(11).realization(100_000 * pi as u64 + 1000 * e as u64 + r),
                    &mut vals,
                    &mut one,
                    &mut scratch,
                ));
            }
            let se = s.mean_std_error().hypot(rse);
            let z = (s.mean() - rv) / se;
            worst = worst.max(z.abs());
            biggest_se = biggest_se.max(se / rv.abs().max(1e-300));
            assert!(
                z.abs() <= 4.5,
                "pixel ({x}, {y}) {}: mean {} vs reference {rv} ± {rse}: z = {z:.2}",
                est.label(),
                s.mean()
            );
        }
        // The f32 SIMD lines agree with the f64 lines on the same offsets.
        let f64e = ests[7];
        assert_eq!(f64e.name(), "lines-edge1");
        let f32e = DlEstimator { simd: true, ..f64e };
        let (_, pat) = SamplePattern::of(&world, Some(&f64e), 16, None).unwrap();
        for r in 0..50 {
            let seed = Seed::new(13).realization(r);
            let a = estimate(&f64e, &pat, seed, &mut vals, &mut one, &mut scratch);
            let b = estimate(&f32e, &pat, seed, &mut vals, &mut one, &mut scratch);
            assert!(
                (a - b).abs() <= 1e-5 * a.abs().max(1e-3 * rv.abs()),
                "pixel ({x}, {y}): f64 lines {a} vs f32 {b}"
            );
        }
        // The orientations must not all be the same estimator in disguise.
        assert!(ests
            .iter()
            .any(|e| e.lines == Some(Orientation::Stratified)));
    }
    eprintln!(
        "84 checks: worst |z| = {worst:.2}; smallest detectable relative bias (4.5 × the \
         largest relative SE) = {:.2e}",
        4.5 * biggest_se
    );
}

/// Box faces have outward normals `edge1 × edge2` (the lab projects only the
/// faces turned towards a receiver), for any rotation.
#[test]
fn box_faces_point_outwards() {
    for rot in [0.0, 17.0, -17.0, 90.0, 133.0] {
        let b = scene::BoxDef {
            base: [0.3, 0.1, -0.2],
            size: [0.6, 1.2, 0.4],
            rotation_deg: rot,
            albedo: [0.5; 3],
        };
        let centre = [0.3, 0.1 + 0.6, -0.2];
        for (c, e1, e2) in b.faces() {
            let mid: Vec<f64> = (0..3).map(|k| c[k] + 0.5 * (e1[k] + e2[k])).collect();
            let n = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            let out: f64 = (0..3).map(|k| (mid[k] - centre[k]) * n[k]).sum();
            assert!(
                out > 0.0,
                "rotation {rot}: face at {mid:?} has normal {n:?}"
            );
        }
    }
}

/// A free-standing quad casts a shadow: a 1 × 1 panel just under the light
/// hides all of it from the floor below (only boxes' faces were projected
/// onto the light, so the floor stayed fully lit), from either side of the
/// panel, while the walls (quads too) still cast none inside the room.
#[test]
fn a_free_standing_quad_casts_a_shadow() {
    let path = scene_file();
    let text = fs::read_to_string(&path).unwrap();
    let floor_point = [-0.1, 0.0, -0.03];
    let hidden = |extra: &str| {
        let sc = scene::parse(&path, &format!("{text}\n{extra}")).unwrap();
        let world = DlWorld::new(sc, 64, 64).unwrap();
        // The floor is quad 0, occluder 0.
        let px = world.surface_point(floor_point, [0.0, 1.0, 0.0], [0.73; 3], Some(0));
        let h = world.hidden_fraction(&px, 64).unwrap();
        let mut v = vec![[0.0f32; 2]; 64];
        for (k, p) in v.iter_mut().enumerate() {
            *p = [(k % 8) as f32 / 8.0 + 0.06, (k / 8) as f32 / 8.0 + 0.06];
        }
        let points = DlEstimator {
            lines: None,
            sampler: SceneSampler::Random,
            simd: false,
        };
        let e = world
            .estimate(&px, &points, &v, &mut Seed::new(1).pcg(2), &mut Vec::new())
            .unwrap();
        (h, e, px.shadows.len())
    };
    let (h0, e0, s0) = hidden("");
    assert!(
        h0 < 0.5 && e0 > 0.0,
        "without the panel: hidden {h0}, E {e0}"
    );
    for (corner, e1, e2) in [
        ("[-0.5, 1.9, -0.5]", "[1.0, 0.0, 0.0]", "[0.0, 0.0, 1.0]"),
        ("[-0.5, 1.9, -0.5]", "[0.0, 0.0, 1.0]", "[1.0, 0.0, 0.0]"),
    ] {
        let panel = format!(
            "[[quad]]\ncorner = {corner}\nedge1 = {e1}\nedge2 = {e2}\nalbedo = [0.5, 0.5, 0.5]\n"
        );
        let (h, e, s) = hidden(&panel);
        assert!(
            h > 1.0 - 1e-12 && e == 0.0,
            "with the panel (edges {e1} {e2}): hidden {h}, E {e}"
        );
        assert_eq!(s, s0 + 1, "the panel's shadow and no wall's");
    }
}

/// `--shift` is honoured (it was silently ignored): `--shift random` moves
/// the jittered rows, `--shift none` leaves Sobol′ unshifted but still
/// random (Owen-scrambled), and the configuration records the choice.
#[test]
fn shift_is_honoured() {
    let dir = TempDir::new("direct-shift");
    let file = scene_file().display().to_string();
    let study = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "scene",
            &file,
            "--resolution",
            "64x64",
            "--pixel",
            "32,40",
            "--pixel-n",
            "4,16",
            "--realisations",
            "8",
            "--reference-lines",
            "64",
            "--reference-realisations",
            "4",
            "--samplers",
            "jittered",
            "--out",
            out,
            "--quiet",
        ];
        args.extend_from_slice(extra);
        lab(&dir, &args)
    };
    ok(&study("plain", &[]), "default shift");
    ok(&study("shifted", &["--shift", "random"]), "--shift random");
    let rows = |out: &str| -> Vec<String> {
        fs::read_to_string(dir.path().join(out).join("pixels/rows.csv"))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| l.split(',').take(9).collect::<Vec<_>>().join(","))
            .collect()
    };
    let (a, b) = (rows("plain"), rows("shifted"));
    assert_eq!(a.len(), b.len());
    let moved = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert!(
        moved >= a.len() - 2,
        "only {moved} of {} rows moved",
        a.len()
    );
    let config = |out: &str| -> serde_json::Value {
        let m: serde_json::Value = serde_json::from_slice(
            &fs::read(dir.path().join(out).join("pixels.state/manifest.json")).unwrap(),
        )
        .unwrap();
        m["config"]["shift"].clone()
    };
    assert_eq!(config("plain"), serde_json::Value::Null);
    assert_eq!(config("shifted"), "random");
    // Unshifted Sobol' is still randomised by its Owen scramble: its rows
    // have a variance.
    ok(
        &study("none", &["--shift", "none", "--samplers", "sobol"]),
        "--shift none with sobol",
    );
    assert_eq!(config("none"), "none");
    // By default Sobol' is shifted: the unshifted rows differ.
    ok(
        &study("sobol", &["--samplers", "sobol"]),
        "default shift, sobol",
    );
    // (The study's base arguments add the jittered rows, unshifted in both.)
    let sobol = |out: &str| -> Vec<String> {
        rows(out)
            .into_iter()
            .filter(|r| r.contains(",sobol,"))
            .collect()
    };
    let (a, b) = (sobol("sobol"), sobol("none"));
    assert_eq!(a.len(), 12);
    let moved = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert_eq!(
        moved,
        a.len(),
        "only {moved} of {} sobol rows moved",
        a.len()
    );
    let (_, header, rows) = csv_table(&dir.path().join("none/pixels/rows.csv"));
    let var = header.iter().position(|h| h == "variance").unwrap();
    for r in &rows {
        assert!(r[var].parse::<f64>().unwrap() > 0.0, "{r:?}");
    }
}
