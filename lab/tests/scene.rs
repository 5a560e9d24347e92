//! Scene files: the shipped AO scene reads back as the paper's scene, and
//! every kind of mistake gives one error naming the file, line and field.

use linesample_lab::scene::{self, CentrePdf, EffectParams, Primitive, SceneSampler};
use std::path::Path;

const GOOD: &str = r#"[camera]
from = [1.0, 1.0, 10.0]
at = [0.0, 0.0, -1.0]
up = [0.0, 1.0, 0.0]
fov = 40.0
resolution = [64, 48]

[[sphere]]
centre = [0.0, 1.0, 0.0]
radius = 1.0

[[sphere]]
centre = [0.0, -1000.0, 0.0]
radius = 1000.0

[effect]
kind = "ambient-occlusion"
max-distance = 500.0
"#;

/// The shipped AO scene.
fn ao_scene() -> scene::Scene {
    scene::load(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/ao-spheres.toml"
    )))
    .unwrap()
}

/// `GOOD` with line `line` (1-based) replaced by `new` (several lines allowed).
fn with_line(line: usize, new: &str) -> String {
    let mut v: Vec<&str> = GOOD.lines().collect();
    v[line - 1] = new;
    v.join("\n") + "\n"
}

/// Parses `text` as `bad.toml` and checks the error's line, field and the
/// words its message must contain; the displayed error starts with
/// `bad.toml:LINE:`.
fn fails(text: &str, line: usize, field: &str, words: &[&str]) {
    let e = scene::parse(Path::new("scenes/bad.toml"), text).expect_err("should fail");
    let shown = e.to_string();
    assert_eq!(e.line, line, "{shown}");
    assert_eq!(e.field, field, "{shown}");
    assert!(
        shown.starts_with(&format!("scenes/bad.toml:{line}:")),
        "{shown}"
    );
    for w in words {
        assert!(shown.contains(w), "'{w}' not in: {shown}");
    }
}

#[test]
fn the_shipped_ao_scene_is_the_papers() {
    let s = ao_scene();
    assert_eq!(s.camera.from, [1.0, 1.0, 10.0]);
    assert_eq!(s.camera.at, [0.0, 0.0, -1.0]);
    assert_eq!(s.camera.up, [0.0, 1.0, 0.0]);
    assert_eq!(s.camera.fov_deg, 40.0);
    assert_eq!((s.camera.width, s.camera.height), (512, 512));
    let spheres: Vec<([f64; 3], f64)> = s.spheres.iter().map(|d| (d.centre, d.radius)).collect();
    assert_eq!(
        spheres,
        vec![
            ([0.75, 0.125, 7.0], 0.125),
            ([1.25, 0.25, 6.0], 0.25),
            ([1.75, 0.6, 4.0], 0.5),
            ([1.0, 1.5, 0.0], 1.0),
            ([-1.5, 2.5, -2.0], 1.25),
            ([-4.5, 3.5, -2.5], 1.5),
            ([0.0, 0.75, 4.0], 0.75),
            ([0.0, -1000.0, 0.0], 1000.0),
        ]
    );
    assert_eq!(
        s.effect,
        EffectParams::AmbientOcclusion {
            max_distance: 500.0
        }
    );
    assert_eq!(
        s.estimators.primitives,
        vec![Primitive::Points, Primitive::Segments, Primitive::Lines]
    );
    assert_eq!(
        s.estimators.segment_lengths,
        vec![0.001, 0.1, 1.0, std::f64::consts::PI]
    );
    assert_eq!(
        s.estimators.pdfs,
        vec![CentrePdf::Uniform, CentrePdf::SolidAngle, CentrePdf::Cosine]
    );
    assert_eq!(s.estimators.samplers.len(), 5);
    assert_eq!(s.estimators.samplers[2], SceneSampler::MultiJittered);
    // The test scene parses too (estimators default).
    let t = scene::parse(Path::new("t.toml"), GOOD).unwrap();
    assert_eq!(t.spheres.len(), 2);
    assert_eq!(t.estimators, scene::Estimators::default());
}

#[test]
fn unknown_key() {
    fails(
        &with_line(10, "radius = 1.0\ncolour = 3"),
        11,
        "colour",
        &["unknown field"],
    );
    fails(
        &with_line(5, "fov = 40.0\nzoom = 2.0"),
        6,
        "zoom",
        &["unknown field"],
    );
}

#[test]
fn unknown_table() {
    fails(
        &(GOOD.to_string() + "[fog]\ndensity = 1.0\n"),
        19,
        "fog",
        &["unknown field"],
    );
}

#[test]
fn missing_field() {
    let e = scene::parse(Path::new("scenes/bad.toml"), &with_line(10, "")).unwrap_err();
    assert_eq!(e.field, "radius", "{e}");
    assert!(e.to_string().contains("missing field"), "{e}");
    assert!((8..=10).contains(&e.line), "{e}");
    let e = scene::parse(Path::new("scenes/bad.toml"), &with_line(5, "")).unwrap_err();
    assert_eq!(e.field, "fov", "{e}");
    assert!((1..=6).contains(&e.line), "{e}");
}

#[test]
fn negative_or_zero_radius() {
    fails(
        &with_line(14, "radius = -1000.0"),
        14,
        "sphere[1].radius",
        &["must be positive", "-1000"],
    );
    fails(
        &with_line(10, "radius = 0.0"),
        10,
        "sphere[0].radius",
        &["must be positive"],
    );
}

#[test]
fn nan_and_infinite_numbers() {
    fails(
        &with_line(10, "radius = nan"),
        10,
        "sphere[0].radius",
        &["finite", "NaN"],
    );
    fails(
        &with_line(2, "from = [inf, 1.0, 10.0]"),
        2,
        "camera.from",
        &["component 0", "finite"],
    );
    fails(
        &with_line(13, "centre = [0.0, -nan, 0.0]"),
        13,
        "sphere[1].centre",
        &["component 1"],
    );
    fails(
        &with_line(18, "max-distance = inf"),
        18,
        "effect.max-distance",
        &["finite"],
    );
    fails(&with_line(5, "fov = -inf"), 5, "camera.fov", &["finite"]);
}

#[test]
fn wrong_type() {
    fails(&with_line(5, "fov = \"wide\""), 5, "fov", &["string"]);
    fails(
        &with_line(6, "resolution = [64.5, 48]"),
        6,
        "resolution",
        &[],
    );
    fails(&with_line(9, "centre = [0.0, 1.0]"), 9, "centre", &[]);
}

#[test]
fn syntax_error() {
    // The reader notices the unclosed array on the next line.
    fails(
        &with_line(9, "centre = [0.0, 1.0, 0.0"),
        10,
        "TOML syntax",
        &["missing comma"],
    );
}

#[test]
fn out_of_range_camera() {
    fails(&with_line(5, "fov = 180.0"), 5, "camera.fov", &["(0, 180)"]);
    fails(
        &with_line(6, "resolution = [0, 48]"),
        6,
        "camera.resolution",
        &["width"],
    );
    fails(
        &with_line(3, "at = [1.0, 1.0, 10.0]"),
        3,
        "camera.at",
        &["equals camera.from"],
    );
    fails(
        &with_line(4, "up = [-1.0, -1.0, -11.0]"),
        4,
        "camera.up",
        &["parallel"],
    );
}

#[test]
fn unknown_effect_and_names() {
    fails(
        &with_line(17, "kind = \"caustics\""),
        17,
        "effect.kind",
        &[
            "unknown effect 'caustics'",
            "ambient-occlusion, direct-light, volumetric-caustic",
        ],
    );
    fails(&with_line(18, ""), 16, "effect.max-distance", &["missing"]);
    let est = "\n[estimators]\nsamplers = [\"random\", \"halton\"]\n";
    fails(
        &(GOOD.to_string() + est),
        21,
        "estimators.samplers[1]",
        &["unknown name 'halton'", "sobol"],
    );
    let est = "\n[estimators]\npdfs = []\n";
    fails(&(GOOD.to_string() + est), 21, "estimators.pdfs", &["empty"]);
    let est = "\n[estimators]\nsegment-lengths = [0.1, 4.0]\n";
    fails(
        &(GOOD.to_string() + est),
        21,
        "estimators.segment-lengths[1]",
        &["(0, π]"],
    );
}

#[test]
fn no_sphere_and_unreadable_file() {
    let text: String = GOOD
        .lines()
        .take(6)
        .chain(GOOD.lines().skip(15))
        .collect::<Vec<_>>()
        .join("\n");
    let e = scene::parse(Path::new("scenes/bad.toml"), &text).unwrap_err();
    assert_eq!(e.field, "sphere", "{e}");
    assert!(e.to_string().contains("no [[sphere]]"), "{e}");
    let e = scene::load(Path::new("scenes/does-not-exist.toml")).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("scenes/does-not-exist.toml:0:0: (file): cannot read it"),
        "{e}"
    );
}

/// The paper's pixels through pbrt's camera conventions: (410, 305) sees the
/// ground near (−0.940, −0.008, 3.925) (image right is world −x for this
/// `LookAt`), (300, 290) a sphere; the image centre looks along `at − from`.
#[test]
fn camera_rays_follow_pbrt() {
    let s = ao_scene();
    let spheres = s.kernel_spheres().unwrap();
    let (o, d) = s.camera.ray(410.5, 305.5);
    let h = scene::Scene::first_hit(&spheres, o, d).unwrap();
    assert_eq!(h.sphere, 7, "{h:?}");
    for (got, want) in h.point.iter().zip([-0.940, -0.008, 3.925]) {
        assert!((got - want).abs() < 1e-3, "{:?}", h.point);
    }
    let (o, d) = s.camera.ray(300.5, 290.5);
    let h = scene::Scene::first_hit(&spheres, o, d).unwrap();
    assert_ne!(h.sphere, 7, "{h:?}");
    let (_, d) = s.camera.ray(256.0, 256.0);
    let v = [-1.0, -1.0, -11.0];
    let l = (1.0f64 + 1.0 + 121.0).sqrt();
    for j in 0..3 {
        assert!((d[j] - v[j] / l).abs() < 1e-15, "{d:?}");
    }
    // Pixel x grows towards up × dir (world −x here), pixel y downwards.
    let (_, a) = s.camera.ray(0.5, 256.0);
    let (_, b) = s.camera.ray(511.5, 256.0);
    assert!(a[0] > b[0], "{a:?} {b:?}");
    let (_, a) = s.camera.ray(256.0, 0.5);
    let (_, b) = s.camera.ray(256.0, 511.5);
    assert!(a[1] > b[1], "{a:?} {b:?}");
}

/// The line estimator with 4096 stratified azimuths against brute force:
/// cosine-distributed rays cast one by one at pixel (410, 305) (the fraction
/// that escapes is AO, standard error √(p(1−p)/n)), within 4 SE; and 1 for
/// a point nothing occludes.
#[test]
fn ao_by_lines_matches_cast_rays() {
    let s = ao_scene();
    let spheres = s.kernel_spheres().unwrap();
    let (o, d) = s.camera.ray(410.5, 305.5);
    let h = scene::Scene::first_hit(&spheres, o, d).unwrap();
    let phis: Vec<f64> = (0..4096)
        .map(|k| std::f64::consts::PI * (k as f64 + 0.5) / 4096.0)
        .collect();
    let lines = scene::ao_lines(&spheres, 500.0, h.point, h.normal, &phis).unwrap();
    // Brute force.
    let n = h.normal;
    let t = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let k = dot(t, n);
    let mut t1 = [t[0] - k * n[0], t[1] - k * n[1], t[2] - k * n[2]];
    let l = dot(t1, t1).sqrt();
    t1 = t1.map(|c| c / l);
    let t2 = [
        n[1] * t1[2] - n[2] * t1[1],
        n[2] * t1[0] - n[0] * t1[2],
        n[0] * t1[1] - n[1] * t1[0],
    ];
    let mut rng = linesample::Pcg32::new(0x1234_5678_9abc_def1, 1);
    let mut uni = move || f64::from(rng.next_u32()) / 4_294_967_296.0;
    let rays = 200_000;
    let mut free = 0usize;
    let eps = 1e-9 * (1.0 + dot(h.point, h.point).sqrt());
    for _ in 0..rays {
        let (u1, u2) = (uni(), uni());
        let r = u1.sqrt();
        let ph = 2.0 * std::f64::consts::PI * u2;
        let (x, y, z) = (r * ph.cos(), r * ph.sin(), (1.0 - u1).sqrt());
        let dir: [f64; 3] = std::array::from_fn(|j| x * t1[j] + y * t2[j] + z * n[j]);
        let ray = linesample::world::Ray::new(h.point, dir).unwrap();
        let blocked = spheres.iter().any(|s| match s.hit(&ray) {
            Some((a, b)) => (a > eps && a <= 500.0) || (b > eps && b <= 500.0),
            None => false,
        });
        free += usize::from(!blocked);
    }
    let p = free as f64 / rays as f64;
    let se = (p * (1.0 - p) / rays as f64).sqrt();
    println!("pixel (410, 305): AO by 4096 lines {lines:.6}, by {rays} cast rays {p:.6} ± {se:.6}");
    assert!((lines - p).abs() <= 4.0 * se, "{lines} vs {p} ± {se}");
    // Nothing above a point on top of the highest sphere.
    let top = [-4.5, 5.0, -2.5];
    let v = scene::ao_lines(&spheres, 500.0, top, [0.0, 1.0, 0.0], &phis[..64]).unwrap();
    assert!((v - 1.0).abs() < 1e-12, "{v}");
}

/// Every table or field the scene's effect does not use is an error naming
/// it (not silently ignored): AO takes no quad, box, light or line
/// orientations; direct light no sphere, max-distance, primitives, pdfs or
/// segment lengths. One parser entry reads every effect.
#[test]
fn fields_the_effect_does_not_use_are_errors() {
    let ao = |extra: &str| format!("{GOOD}{extra}");
    let quad = "[[quad]]\ncorner = [0.0, 0.0, 0.0]\nedge1 = [1.0, 0.0, 0.0]\n\
                edge2 = [0.0, 1.0, 0.0]\nalbedo = [0.5, 0.5, 0.5]\n";
    fails(
        &ao(quad),
        19,
        "quad",
        &["ambient-occlusion does not use it"],
    );
    let light = "[light]\ncorner = [0.0, 2.0, 0.0]\nedge1 = [1.0, 0.0, 0.0]\n\
                 edge2 = [0.0, 0.0, 1.0]\nradiance = [1.0, 1.0, 1.0]\n";
    fails(
        &ao(light),
        19,
        "light",
        &["ambient-occlusion does not use it"],
    );
    fails(
        &ao("[estimators]\norientations = [\"edge1\"]\n"),
        20,
        "estimators.orientations",
        &["ambient-occlusion does not use it"],
    );
    let dl_file = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/cornell-box.toml");
    let dl = std::fs::read_to_string(dl_file).unwrap();
    let last = dl.lines().count();
    for (field, line) in [
        ("estimators.primitives", "primitives = [\"points\"]"),
        ("estimators.pdfs", "pdfs = [\"cosine\"]"),
        ("estimators.segment-lengths", "segment-lengths = [0.1]"),
    ] {
        fails(
            &format!("{dl}{line}\n"),
            last + 1,
            field,
            &["direct-light does not use it"],
        );
    }
    let with_md = dl.replace(
        "kind = \"direct-light\"",
        "kind = \"direct-light\"\nmax-distance = 5.0",
    );
    let e = scene::parse(Path::new("x.toml"), &with_md).unwrap_err();
    assert_eq!(e.field, "effect.max-distance", "{e}");
    // One entry for every effect.
    let caustic = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/caustic-2d.toml");
    let text = std::fs::read_to_string(caustic).unwrap();
    assert!(matches!(
        scene::parse_any(Path::new(caustic), &text).unwrap(),
        scene::SceneFile::Caustic(c) if c.dims == 2
    ));
    assert!(matches!(
        scene::parse_any(Path::new(dl_file), &dl).unwrap(),
        scene::SceneFile::Camera(s) if s.effect == EffectParams::DirectLight
    ));
    let e =
        scene::parse_any(Path::new("c.toml"), &format!("{text}[camera]\nfov = 1.0\n")).unwrap_err();
    assert!(e.to_string().contains("camera"), "{e}");
}
