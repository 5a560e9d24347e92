//! Ambient occlusion by spheres in closed form (`linesample::world::occlusion`)
//! against brute force: the occluded angles against rays cast one by one with
//! `Sphere::hit`, and the visible cosine-weighted measure against adaptive
//! Gauss–Kronrod quadrature of `|sin θ| cos θ` over the visible pieces, whose
//! ends are found by bisection on the cast rays (so the reference shares
//! nothing with the closed form but `Sphere::hit`, tested on its own in
//! `tests/world_sphere.rs`). Scenes: the paper's AO scene of spheres with
//! shading points on every sphere, random spheres, and the grazing cases
//! (tangent to the half-plane, touching the horizon, cut by the tangent
//! plane, the shading point on its own sphere, the point inside a sphere).

mod common;

use common::ao_scene;
use common::{integrate, XorShift as Rng};
use linesample::world::occlusion::{cosine_weight, visible_weight};
use linesample::world::{HalfPlane, Ray, Sphere};
use linesample::ParamError;
use std::f64::consts::{FRAC_PI_2, PI};

/// Whether the ray `p + s·d`, `ε < s ≤ max`, meets a sphere's surface, by
/// `Sphere::hit`. The usual ray-tracing `ε = 10⁻⁹(1 + |p|)` keeps a point on
/// a sphere (rounded) from hitting that sphere at `s ≈ 0`.
fn cast(p: [f64; 3], d: [f64; 3], spheres: &[Sphere<3>], max: f64) -> bool {
    let ray = Ray::new(p, d).unwrap();
    let eps = 1e-9 * (1.0 + (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt());
    spheres.iter().any(|s| match s.hit(&ray) {
        Some((t0, t1)) => (t0 > eps && t0 <= max) || (t1 > eps && t1 <= max),
        None => false,
    })
}

/// The reference: visible cosine-weighted measure of `[t0, t1]` by casting,
/// bisection of every visibility switch on a grid of `grid` steps (to
/// `1e−14`), and Gauss–Kronrod quadrature over the visible pieces.
fn reference(hp: &HalfPlane, spheres: &[Sphere<3>], max: f64, t0: f64, t1: f64) -> f64 {
    let vis = |t: f64| !cast(hp.point(), hp.direction(t), spheres, max);
    let grid = 4000;
    let mut ends = vec![t0];
    let mut prev = vis(t0);
    let mut last = t0;
    for i in 1..=grid {
        let t = t0 + (t1 - t0) * i as f64 / grid as f64;
        let v = vis(t);
        if v != prev {
            let (mut a, mut b) = (last, t);
            while b - a > 1e-14 {
                let m = 0.5 * (a + b);
                if vis(m) == prev {
                    a = m;
                } else {
                    b = m;
                }
            }
            ends.push(0.5 * (a + b));
            prev = v;
        }
        last = t;
    }
    ends.push(t1);
    let mut visible = vis(t0);
    let mut sum = 0.0;
    for w in ends.windows(2) {
        if visible && w[1] > w[0] {
            // Split at the kink of |sin t| (adaptive quadrature converges
            // slowly across it).
            let f = |t: f64| t.sin().abs() * t.cos();
            if w[0] < 0.0 && w[1] > 0.0 {
                sum += integrate(f, w[0], 0.0, 1e-15) + integrate(f, 0.0, w[1], 1e-15);
            } else {
                sum += integrate(f, w[0], w[1], 1e-15);
            }
        }
        visible = !visible;
    }
    sum
}

/// A shading point on sphere `k` of the scene, facing away from its centre,
/// at a random spot of its upper half (where the camera sees it).
fn point_on(rng: &mut Rng, s: &Sphere<3>) -> ([f64; 3], [f64; 3]) {
    loop {
        let n = rng.unit_vector();
        if n[1] > -0.2 {
            let c = s.centre();
            let r = s.radius();
            return ([c[0] + r * n[0], c[1] + r * n[1], c[2] + r * n[2]], n);
        }
    }
}

#[test]
fn occluded_angles_match_cast_rays() {
    let spheres = ao_scene::spheres();
    let mut rng = Rng(0x5eed_1234_abcd_ef01);
    let (mut checked, mut occluded) = (0usize, 0usize);
    for case in 0..300 {
        let on = &spheres[case % spheres.len()];
        let (p, n) = point_on(&mut rng, on);
        let hp = HalfPlane::at_azimuth(p, n, rng.unit_vector(), PI * rng.uniform()).unwrap();
        let max = [500.0, 2.0, 0.5][case % 3];
        for s in &spheres {
            let occ = hp.occluded(s, max);
            for i in 0..=400 {
                let t = -FRAC_PI_2 + PI * i as f64 / 400.0;
                let near_end = occ
                    .pieces()
                    .iter()
                    .any(|&(a, b)| (t - a).abs() < 1e-9 || (t - b).abs() < 1e-9);
                if near_end || t.abs() > FRAC_PI_2 - 1e-9 {
                    continue;
                }
                let inside = occ.pieces().iter().any(|&(a, b)| a < t && t < b);
                let hit = cast(p, hp.direction(t), std::slice::from_ref(s), max);
                assert_eq!(inside, hit, "case {case} θ {t} sphere {s:?} max {max}");
                let sees = hp.sees(std::slice::from_ref(s), max, t);
                assert_eq!(sees, !hit, "sees: case {case} θ {t} sphere {s:?} max {max}");
                checked += 1;
                occluded += usize::from(hit);
            }
        }
    }
    println!("occluded angles: {checked} directions cast, {occluded} occluded");
    assert!(occluded > checked / 200, "{occluded} of {checked}");
}

#[test]
fn visible_weight_matches_quadrature_in_the_ao_scene() {
    let spheres = ao_scene::spheres();
    let mut rng = Rng(0x0dd_ba11_cafe_f00d);
    let mut scratch = vec![(0.0, 0.0); 2 * spheres.len()];
    let mut worst = 0.0f64;
    let mut partial = 0;
    for case in 0..120 {
        let on = &spheres[case % spheres.len()];
        let (p, n) = point_on(&mut rng, on);
        let hp = HalfPlane::at_azimuth(p, n, rng.unit_vector(), PI * rng.uniform()).unwrap();
        let max = [500.0, 3.0][case % 2];
        // Whole lines and random segments of several lengths.
        let len = [PI, 1.0, 0.1, 1e-3][case % 4];
        let t0 = if len == PI {
            -FRAC_PI_2
        } else {
            -FRAC_PI_2 + (PI - len) * rng.uniform()
        };
        let t1 = t0 + len;
        let got = hp.visible(&spheres, max, t0, t1, &mut scratch).unwrap();
        let want = reference(&hp, &spheres, max, t0, t1);
        let total = cosine_weight(t0, t1);
        let err = (got - want).abs() / total.max(1e-300);
        worst = worst.max(err);
        partial += usize::from(want > 1e-3 * total && want < (1.0 - 1e-3) * total);
        assert!(
            err <= 1e-11,
            "case {case}: got {got:e} want {want:e} (of {total:e}) [{t0}, {t1}] max {max}"
        );
    }
    println!("AO scene: worst |visible − reference| = {worst:.2e} of the segment's weight; {partial} of 120 partly occluded");
    assert!(partial >= 20, "{partial}");
}

#[test]
fn grazing_cases() {
    let max = 500.0;
    let mut scratch = vec![(0.0, 0.0); 8];
    let p = [0.0, 0.0, 0.0];
    let n = [0.0, 1.0, 0.0];
    let hp = HalfPlane::new(p, n, [1.0, 0.0, 0.0]).unwrap();
    let check = |spheres: &[Sphere<3>], what: &str, scratch: &mut [(f64, f64)]| {
        let got = hp
            .visible(spheres, max, -FRAC_PI_2, FRAC_PI_2, scratch)
            .unwrap();
        let want = reference(&hp, spheres, max, -FRAC_PI_2, FRAC_PI_2);
        assert!((got - want).abs() <= 1e-11, "{what}: got {got} want {want}");
        got
    };
    // Tangent to the half-plane (h = R(1 − 10⁻¹²)) and just missing it.
    let r = 0.5;
    let s = Sphere::new([1.0, 1.0, r * (1.0 - 1e-12)], r).unwrap();
    let v = check(&[s], "tangent to the plane", &mut scratch);
    assert!(v < 1.0 && v > 1.0 - 1e-5, "{v}");
    let s = Sphere::new([1.0, 1.0, r * (1.0 + 1e-12)], r).unwrap();
    assert_eq!(hp.occluded(&s, max).pieces().len(), 0);
    // Touching the horizon: the centre at height r above the tangent plane.
    let s = Sphere::new([3.0, r, 0.0], r).unwrap();
    check(&[s], "touching the horizon", &mut scratch);
    // Cut by the tangent plane (centre below it) and straddling the normal.
    let s = Sphere::new([2.0, -0.2, 0.0], r).unwrap();
    check(&[s], "cut by the tangent plane", &mut scratch);
    let s = Sphere::new([0.0, 3.0, 0.0], r).unwrap();
    check(&[s], "straddling the normal", &mut scratch);
    // The shading point on its own sphere: nothing occluded in the hemisphere.
    let own = Sphere::new([0.0, -1000.0, 0.0], 1000.0).unwrap();
    let v = hp
        .visible(&[own], max, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
        .unwrap();
    assert!((v - 1.0).abs() <= 1e-15, "own sphere: {v}");
    // A point on a small sphere, rounding included, for many normals.
    let mut rng = Rng(77);
    for _ in 0..200 {
        let small = Sphere::new([0.3, 0.7, -0.2], 0.37).unwrap();
        let (q, m) = point_on(&mut rng, &small);
        let h = HalfPlane::at_azimuth(q, m, rng.unit_vector(), PI * rng.uniform()).unwrap();
        let v = h
            .visible(&[small], max, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
            .unwrap();
        assert!((v - 1.0).abs() <= 1e-9, "own small sphere: {v}");
    }
    // Inside a sphere: everything occluded, or only the far arc when the
    // exit lies beyond max_dist.
    for c in [[0.0, 0.5, 0.0], [1.5, -0.5, 0.0], [-1.2, -1.0, 0.3]] {
        let big = Sphere::new(c, 2.0).unwrap();
        let v = hp
            .visible(&[big], max, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
            .unwrap();
        assert_eq!(v, 0.0, "inside the sphere at {c:?}");
    }
    let big = Sphere::new([0.0, 0.5, 0.0], 2.0).unwrap();
    check(&[big], "inside, short max_dist", &mut scratch);
    let got = hp
        .visible(&[big], 2.2, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
        .unwrap();
    let want = reference(&hp, &[big], 2.2, -FRAC_PI_2, FRAC_PI_2);
    assert!(
        (got - want).abs() <= 1e-11 && got > 0.0,
        "inside: {got} {want}"
    );
    // max_dist cuts the arc (nearest point inside, tangent point beyond).
    let s = Sphere::new([0.0, 5.0, 0.0], 1.0).unwrap();
    for m in [4.2, 4.5, 4.89, 5.0, 6.0] {
        let got = hp
            .visible(&[s], m, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
            .unwrap();
        let want = reference(&hp, &[s], m, -FRAC_PI_2, FRAC_PI_2);
        assert!((got - want).abs() <= 1e-11, "max {m}: {got} {want}");
    }
}

#[test]
fn cosine_weight_is_the_integral() {
    let mut worst = 0.0f64;
    let mut rng = Rng(3);
    for i in 0..2000 {
        let w = [1e-12, 1e-6, 1e-3, 0.3, 2.0][i % 5];
        let a = -FRAC_PI_2 + (PI - w) * rng.uniform();
        let b = a + w;
        let got = cosine_weight(a, b);
        // The kink at 0 split off for the quadrature.
        let f = |t: f64| t.sin().abs() * t.cos();
        let want = if a < 0.0 && b > 0.0 {
            integrate(f, a, 0.0, 1e-16) + integrate(f, 0.0, b, 1e-16)
        } else {
            integrate(f, a, b, 1e-16)
        };
        if want > 1e-290 {
            let e = ((got - want) / want).abs();
            worst = worst.max(e);
            assert!(e <= 1e-13, "[{a}, {b}]: {got:e} {want:e}");
        }
    }
    assert_eq!(cosine_weight(-FRAC_PI_2, FRAC_PI_2), 1.0);
    assert_eq!(cosine_weight(0.3, 0.3), 0.0);
    assert_eq!(cosine_weight(0.5, 0.1), 0.0);
    println!("cosine_weight: worst relative error {worst:.2e}");
    // visible_weight: unsorted, overlapping intervals.
    let mut occ = [(0.5, 0.9), (-0.2, 0.1), (0.0, 0.6)];
    let v = visible_weight(&mut occ, -FRAC_PI_2, FRAC_PI_2);
    let want = cosine_weight(-FRAC_PI_2, -0.2) + cosine_weight(0.9, FRAC_PI_2);
    assert!((v - want).abs() <= 1e-16, "{v} {want}");
}

/// Segments that wrap with period π: the sum of the two pieces, the whole
/// half-plane for `len = π` from any start, and equal to the plain form when
/// they do not wrap.
#[test]
fn wrapped_segments() {
    let spheres = ao_scene::spheres();
    let mut rng = Rng(99);
    let mut scratch = vec![(0.0, 0.0); 2 * spheres.len()];
    for _ in 0..200 {
        let (p, n) = point_on(&mut rng, &spheres[7]);
        let hp = HalfPlane::at_azimuth(p, n, rng.unit_vector(), PI * rng.uniform()).unwrap();
        let whole = hp
            .visible(&spheres, 500.0, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
            .unwrap();
        let t0 = 10.0 * rng.uniform() - 5.0;
        let v = hp
            .visible_wrapped(&spheres, 500.0, t0, PI, &mut scratch)
            .unwrap();
        assert_eq!(v, whole);
        let len = 2.0 * rng.uniform() + 0.5;
        let a = t0 - PI * (t0 / PI).round();
        let got = hp
            .visible_wrapped(&spheres, 500.0, t0, len, &mut scratch)
            .unwrap();
        let want = if a + len > FRAC_PI_2 {
            reference(&hp, &spheres, 500.0, a, FRAC_PI_2)
                + reference(&hp, &spheres, 500.0, -FRAC_PI_2, a + len - PI)
        } else {
            reference(&hp, &spheres, 500.0, a, a + len)
        };
        assert!((got - want).abs() <= 1e-11, "{t0} {len}: {got} {want}");
    }
    let hp = HalfPlane::new([0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
    assert_eq!(
        hp.visible_wrapped(&spheres, 1.0, 0.0, 4.0, &mut scratch)
            .unwrap_err(),
        ParamError::OutOfRange {
            name: "len",
            value: 4.0,
            min: 0.0,
            max: PI
        }
    );
}

#[test]
fn bad_input_names_the_parameter() {
    let nan = f64::NAN;
    let e = HalfPlane::new([nan, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]).unwrap_err();
    assert_eq!(e, ParamError::NonFinite { name: "point" });
    let e = HalfPlane::new([0.0; 3], [0.0, nan, 0.0], [1.0, 0.0, 0.0]).unwrap_err();
    assert_eq!(e, ParamError::NonFinite { name: "normal" });
    let e = HalfPlane::new([0.0; 3], [0.0, 1.0, 0.0], [1.0, f64::INFINITY, 0.0]).unwrap_err();
    assert_eq!(e, ParamError::NonFinite { name: "azimuth" });
    let e = HalfPlane::new([0.0; 3], [0.0; 3], [1.0, 0.0, 0.0]).unwrap_err();
    assert_eq!(e, ParamError::ZeroDirection);
    let e = HalfPlane::new([0.0; 3], [0.0, 1.0, 0.0], [0.0, 2.0, 0.0]).unwrap_err();
    assert_eq!(e, ParamError::ZeroDirection);
    let e = HalfPlane::at_azimuth([0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], nan).unwrap_err();
    assert_eq!(e, ParamError::NonFinite { name: "phi" });
    let hp = HalfPlane::new([0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
    let s = [Sphere::new([0.0, 3.0, 0.0], 1.0).unwrap(); 2];
    let mut short = [(0.0, 0.0); 3];
    let e = hp.visible(&s, 10.0, -1.0, 1.0, &mut short).unwrap_err();
    assert_eq!(
        e,
        ParamError::Length {
            name: "scratch",
            expected: 4,
            got: 3
        }
    );
    let mut ok = [(0.0, 0.0); 4];
    assert_eq!(
        hp.visible(&s, 10.0, nan, 1.0, &mut ok).unwrap_err(),
        ParamError::NonFinite { name: "t0" }
    );
    // A non-positive or NaN max distance occludes nothing.
    for m in [0.0, -1.0, nan] {
        assert_eq!(
            hp.visible(&s, m, -FRAC_PI_2, FRAC_PI_2, &mut ok).unwrap(),
            1.0
        );
    }
}
