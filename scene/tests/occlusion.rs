//! Ambient occlusion by spheres in closed form (`linesample_scene::occlusion`)
//! against brute force: the occluded angles against rays cast one by one with
//! `Sphere::hit`, and the visible cosine-weighted measure against adaptive
//! Gauss–Kronrod quadrature of `|sin θ| cos θ` over the visible pieces, whose
//! ends are found by bisection on the cast rays (so the reference shares
//! nothing with the closed form but `Sphere::hit`, tested on its own in
//! `tests/world_sphere.rs`). Scenes: the paper's AO scene of spheres with
//! shading points on every sphere, random spheres, and the grazing cases
//! (tangent to the half-plane, touching the horizon, cut by the tangent
//! plane, the shading point on its own sphere, the point inside a sphere).

#[path = "../../tests/common/mod.rs"]
mod common;

use common::ao_scene;
use common::{integrate, XorShift as Rng};
use linesample::world::{Ray, Sphere};
use linesample::ParamError;
use linesample_scene::occlusion::{cosine_weight, visible_weight};
use linesample_scene::occlusion_f32::AoPoint32;
use linesample_scene::HalfPlane;
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

// ---------------------------------------------------------------------------
// The f32 SIMD batches (`world::occlusion_f32::AoPoint32`) against their
// scalar twins (bit for bit) and against the f64 `HalfPlane::visible`
// (already checked against cast rays and quadrature above), within the error
// bound derived in the module docs, evaluated here from the f64 geometry.

/// `ε₃₂ = 2⁻²³`.
const E32: f64 = f32::EPSILON as f64;

fn dot(x: &[f64; 3], y: &[f64; 3]) -> f64 {
    x[0] * y[0] + x[1] * y[1] + x[2] * y[2]
}

fn cross(x: &[f64; 3], y: &[f64; 3]) -> [f64; 3] {
    [
        x[1] * y[2] - x[2] * y[1],
        x[2] * y[0] - x[0] * y[2],
        x[0] * y[1] - x[1] * y[0],
    ]
}

fn normalised(x: [f64; 3]) -> [f64; 3] {
    let l = dot(&x, &x).sqrt();
    x.map(|c| c / l)
}

fn axpy(p: [f64; 3], terms: &[(f64, [f64; 3])]) -> [f64; 3] {
    let mut out = p;
    for &(k, v) in terms {
        for j in 0..3 {
            out[j] += k * v[j];
        }
    }
    out
}

/// A shading frame and spheres for the f32 tests.
#[derive(Clone, Debug)]
struct Scene {
    p: [f64; 3],
    n: [f64; 3],
    t: [f64; 3],
    spheres: Vec<Sphere<3>>,
    max: f64,
    /// An azimuth (an f32 value) the grazing spheres were built for.
    phi0: f32,
}

impl Scene {
    fn half_plane(&self, phi: f32) -> HalfPlane {
        HalfPlane::at_azimuth(self.p, self.n, self.t, f64::from(phi)).unwrap()
    }

    fn prepared(&self) -> AoPoint32<8> {
        AoPoint32::new(self.p, self.n, self.t, &self.spheres, self.max).unwrap()
    }

    /// The f64 reference line value at `phi`.
    fn line64(&self, phi: f32) -> f64 {
        let mut scratch = [(0.0, 0.0); 16];
        self.half_plane(phi)
            .visible(&self.spheres, self.max, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
            .unwrap()
    }

    /// The error bound of the module docs of `occlusion_f32` at `phi`.
    fn bound(&self, phi: f32) -> f64 {
        let hp = self.half_plane(phi);
        let (a, n) = (hp.azimuth(), hp.normal());
        let b = cross(&n, &a);
        let e = E32;
        let mut total = 0.0;
        let mut intervals = 0.0;
        for sph in &self.spheres {
            let c = sph.centre();
            let big_r = sph.radius();
            let q = [c[0] - self.p[0], c[1] - self.p[1], c[2] - self.p[2]];
            let l = dot(&q, &q).sqrt();
            let out2 = (l - big_r) * (l + big_r);
            let (qa, qb, qn) = (dot(&q, &a), dot(&q, &b), dot(&q, &n));
            if l - big_r >= self.max || qn + big_r <= 1e-12 * big_r {
                continue; // dropped (occludes at most 1e−12, the floor below)
            }
            let h = qb.abs();
            let d = qa.hypot(qn);
            let r = (big_r - h).max(0.0).sqrt() * (big_r + h).sqrt();
            let dq = 3.0 * e * l;
            let dd = 1.5 * dq + 2.0 * e * d;
            let dr2 = 3.0 * h.min(d) * dq + 2.0 * e * (big_r * big_r + d * d);
            let dr = if r > 0.0 {
                (dr2 / (2.0 * r)).min(dr2.sqrt())
            } else {
                dr2.sqrt()
            } + e * r;
            let on = out2.abs() <= 1e-12 * big_r * big_r;
            let inside = !on && out2 < 0.0;
            let cut = !on && out2 > 0.0 && out2.sqrt() > self.max;
            let d_c = 2.0 * (dq + dd) / d + 4.0 * e;
            let d_beta = (dd + dr) / d + 4.0 * e;
            let d_kappa = || {
                let s = self.max.min(2.0 * (l + big_r));
                let kap = (s * s + out2) / (2.0 * s * d);
                let dk = kap.abs() * (dd / d + 3.0 * e);
                let du = 2.0 * kap.abs() * dk + 2.0 * e;
                let sw = (1.0 - kap * kap).max(0.0).sqrt();
                let dsw = if sw > 0.0 {
                    (du / (2.0 * sw)).min(du.sqrt())
                } else {
                    du.sqrt()
                };
                dk + dsw + 2.0 * e
            };
            let d_w = if on {
                0.0
            } else if inside {
                d_kappa()
            } else if cut {
                d_beta + d_kappa()
            } else {
                d_beta
            };
            let ds = d_c + d_w + 2.0 * e;
            let ends = if inside { 4.0 } else { 2.0 };
            intervals += ends / 2.0;
            total += ends * ds.min(2.0);
        }
        total + 3.0 * e * (intervals + 2.0) + 1e-11
    }
}

/// A random frame and one to eight spheres mixing the cases: near and far,
/// tangent to the half-plane at `phi0` (`h = R(1 − 10⁻ᵏ)`), touching the
/// horizon, cut by the tangent plane, the shading point on a sphere (its own,
/// along the normal or not), inside a sphere, a ground-sized sphere under the
/// point; `max_dist` from `∞` down to short.
fn random_scene(rng: &mut Rng) -> Scene {
    let p: [f64; 3] = std::array::from_fn(|_| 20.0 * rng.uniform() - 10.0);
    let n = rng.unit_vector();
    let t = loop {
        let t = rng.unit_vector();
        if cross(&t, &n).iter().map(|x| x * x).sum::<f64>() > 0.01 {
            break t;
        }
    };
    let hp = HalfPlane::new(p, n, t).unwrap();
    let (n, t0) = (hp.normal(), hp.azimuth());
    let u0 = cross(&n, &t0);
    let phi0 = (PI * rng.uniform()) as f32;
    let (sp, cp) = f64::from(phi0).sin_cos();
    let a0 = axpy([0.0; 3], &[(cp, t0), (sp, u0)]);
    let b0 = cross(&n, &a0);
    let horizontal = |rng: &mut Rng| {
        let w = 2.0 * PI * rng.uniform();
        axpy([0.0; 3], &[(w.cos(), t0), (w.sin(), u0)])
    };
    let count = 1 + (8.0 * rng.uniform()) as usize;
    let mut spheres = Vec::new();
    for _ in 0..count {
        let big_r = 0.05 + 2.0 * rng.uniform();
        let kind = (11.0 * rng.uniform()) as usize;
        let (c, big_r) = match kind {
            0 | 1 => {
                let dist = 0.5 + 15.0 * rng.uniform();
                (axpy(p, &[(dist, rng.unit_vector())]), big_r)
            }
            2 | 3 => {
                // Tangent to the half-plane at phi0 (just inside or outside).
                let k = 1.0 + 11.0 * rng.uniform();
                let rho = 1.0 + if kind == 2 { -1.0 } else { 1.0 } * 10f64.powf(-k);
                let x = 6.0 * rng.uniform() - 3.0;
                let y = 3.0 * rng.uniform();
                (axpy(p, &[(x, a0), (y, n), (rho * big_r, b0)]), big_r)
            }
            4 => {
                // Touching the horizon.
                let dist = big_r + 0.1 + 5.0 * rng.uniform();
                (axpy(p, &[(dist, horizontal(rng)), (big_r, n)]), big_r)
            }
            5 => {
                // Cut by the tangent plane.
                let dist = big_r + 0.1 + 5.0 * rng.uniform();
                let y = (2.0 * rng.uniform() - 1.0) * big_r;
                (axpy(p, &[(dist, horizontal(rng)), (y, n)]), big_r)
            }
            6 => {
                // The shading point on a sphere, any orientation.
                (axpy(p, &[(-big_r, rng.unit_vector())]), big_r)
            }
            7 => {
                // The shading point on its own sphere, facing out.
                (axpy(p, &[(-big_r, n)]), big_r)
            }
            8 => {
                // Containing the shading point.
                let big_r = 0.5 + 3.0 * rng.uniform();
                let off = 0.95 * big_r * rng.uniform();
                (axpy(p, &[(off, rng.unit_vector())]), big_r)
            }
            9 => {
                // A ground-sized sphere just under, on or over the point.
                let m = normalised(axpy(n, &[(0.3 * rng.uniform(), rng.unit_vector())]));
                let big_r = 1000.0 * (0.5 + rng.uniform());
                let lift = [0.0, 1e-9, 0.01, 0.3][(4.0 * rng.uniform()) as usize];
                (axpy(p, &[(-(big_r + lift), m)]), big_r)
            }
            _ => {
                // Near the max distance's reach.
                let dist = 1.0 + 2.0 * rng.uniform();
                (axpy(p, &[(dist, rng.unit_vector())]), 0.3 * big_r)
            }
        };
        spheres.push(Sphere::new(c, big_r).unwrap());
    }
    // Exact duplicates (the same sphere twice in a scene) give intervals with
    // equal ends, which the union must not count twice.
    if count >= 2 && rng.uniform() < 0.25 {
        let k = (rng.uniform() * (count - 1) as f64) as usize;
        spheres[count - 1] = spheres[k];
    }
    let max = [f64::INFINITY, 1000.0, 5.0, 2.0, 1.3, 0.7, 0.2][(7.0 * rng.uniform()) as usize];
    Scene {
        p,
        n,
        t,
        spheres,
        max,
        phi0,
    }
}

/// Azimuths for a scene: the grazing one, random ones in `[0, π)`, a few
/// outside it, and exact multiples of `π/2`.
fn azimuths(rng: &mut Rng, scene: &Scene, count: usize) -> Vec<f32> {
    let mut phis = vec![
        scene.phi0,
        0.0,
        -0.0,
        std::f32::consts::FRAC_PI_2,
        std::f32::consts::PI,
    ];
    for k in 0..count {
        phis.push(if k % 8 == 7 {
            (40.0 * rng.uniform() - 20.0) as f32
        } else {
            (PI * rng.uniform()) as f32
        });
    }
    phis
}

#[test]
fn f32_batch_is_its_scalar_twin_bit_for_bit() {
    let mut rng = Rng(0xb17f_0b17_5eed);
    let mut lanes = 0usize;
    for case in 0..300 {
        let scene = random_scene(&mut rng);
        let ao = scene.prepared();
        // Lengths that leave every remainder 0..7 after the 8-lane blocks.
        let count = [0, 1, 7, 8, 9, 15, 16, 17, 60, 203][case % 10];
        let mut phis = azimuths(&mut rng, &scene, count);
        phis.truncate(count.max(1) - usize::from(count == 0));
        let mut out = vec![f32::NAN; phis.len()];
        ao.line_batch_f32(&phis, &mut out).unwrap();
        for (k, (&phi, &v)) in phis.iter().zip(&out).enumerate() {
            let s = ao.line_f32(phi);
            assert_eq!(
                v.to_bits(),
                s.to_bits(),
                "case {case} lane {k}: φ {phi}: {v} {s}"
            );
            assert!((0.0..=1.0).contains(&v), "case {case}: {v}");
        }
        let theta0s: Vec<f32> = phis
            .iter()
            .map(|_| (12.0 * rng.uniform() - 6.0) as f32)
            .collect();
        let len = [0.0, 1e-3, 0.5, 1.0, 2.5, 3.1415925, std::f32::consts::PI][case % 7];
        ao.segment_batch_f32(&phis, &theta0s, len, &mut out)
            .unwrap();
        for k in 0..phis.len() {
            let s = ao.segment_f32(phis[k], theta0s[k], len);
            assert_eq!(
                out[k].to_bits(),
                s.to_bits(),
                "segment case {case} lane {k}: φ {} θ0 {} len {len}",
                phis[k],
                theta0s[k]
            );
        }
        lanes += phis.len();
    }
    println!("f32 AO batch: {lanes} lines and segments bit-identical to the scalar twin");
}

#[test]
fn f32_lines_match_f64_within_the_bound_on_random_scenes() {
    let mut rng = Rng(0x0cc1_0de5_f32f_64aa);
    let (mut worst, mut worst_ratio, mut checked) = (0.0f64, 0.0f64, 0usize);
    let (mut worst_tame, mut tame) = (0.0f64, 0usize);
    let mut worst_case = String::new();
    let mut partly = 0usize;
    for case in 0..1500 {
        let scene = random_scene(&mut rng);
        let ao = scene.prepared();
        for phi in azimuths(&mut rng, &scene, 24) {
            let got = f64::from(ao.line_f32(phi));
            let want = scene.line64(phi);
            let bound = scene.bound(phi);
            let err = (got - want).abs();
            assert!(
                err <= bound,
                "case {case} φ {phi}: f32 {got} f64 {want} (err {err:e} > bound {bound:e})\n{scene:?}"
            );
            if err > worst {
                worst = err;
                worst_case = format!("case {case} φ {phi} (bound {bound:.1e})");
            }
            worst_ratio = worst_ratio.max(err / bound);
            if bound <= 1e-4 {
                worst_tame = worst_tame.max(err);
                tame += 1;
            }
            partly += usize::from(want > 1e-3 && want < 1.0 - 1e-3);
            checked += 1;
        }
    }
    println!(
        "f32 AO lines, random scenes: {checked} lines ({partly} partly occluded), worst |f32 − f64| = \
         {worst:.2e} at {worst_case}, worst error/bound = {worst_ratio:.3}; {tame} lines away \
         from grazing (bound ≤ 1e−4): worst {worst_tame:.2e}"
    );
    assert!(partly > checked / 4, "{partly} of {checked}");
}

#[test]
fn f32_lines_match_f64_in_the_ao_scene() {
    let spheres = ao_scene::spheres();
    let mut rng = Rng(0xa05_ce2e);
    let (mut worst_ground, mut worst_spheres, mut worst_ratio) = (0.0f64, 0.0f64, 0.0f64);
    for case in 0..400 {
        let (p, n) = if case % 2 == 0 {
            // A ground point in the camera's view, on the ground sphere.
            let (x, z) = (10.0 * rng.uniform() - 5.0, 15.0 * rng.uniform() - 5.0);
            let m = normalised([x, 1000.0, z]);
            ([1000.0 * m[0], 1000.0 * m[1] - 1000.0, 1000.0 * m[2]], m)
        } else {
            point_on(&mut rng, &spheres[case / 2 % 7])
        };
        let scene = Scene {
            p,
            n,
            t: rng.unit_vector(),
            spheres: spheres.clone(),
            max: [500.0, 3.0, f64::INFINITY, 0.5][case / 2 % 4],
            phi0: 0.0,
        };
        let ao = scene.prepared();
        let phis: Vec<f32> = (0..64)
            .map(|k| (PI * (k as f64 + rng.uniform()) / 64.0) as f32)
            .collect();
        let mut out = vec![0.0; phis.len()];
        ao.line_batch_f32(&phis, &mut out).unwrap();
        for (&phi, &v) in phis.iter().zip(&out) {
            let want = scene.line64(phi);
            let err = (f64::from(v) - want).abs();
            let bound = scene.bound(phi);
            assert!(
                err <= bound,
                "case {case} φ {phi}: f32 {v} f64 {want} (err {err:e} > {bound:e})"
            );
            worst_ratio = worst_ratio.max(err / bound);
            if case % 2 == 0 {
                worst_ground = worst_ground.max(err);
            } else {
                worst_spheres = worst_spheres.max(err);
            }
        }
    }
    println!(
        "f32 AO lines, paper scene: worst |f32 − f64| = {worst_ground:.2e} on the ground, \
         {worst_spheres:.2e} on the spheres; worst error/bound = {worst_ratio:.3}"
    );
    assert!(worst_ground <= 1e-5 && worst_spheres <= 1e-4);
}

#[test]
fn f32_segments_match_f64_wrapped_segments() {
    let mut rng = Rng(0x5e9_3e27);
    let (mut worst, mut worst_ratio) = (0.0f64, 0.0f64);
    let mut scratch = [(0.0, 0.0); 16];
    for case in 0..600 {
        let scene = random_scene(&mut rng);
        let ao = scene.prepared();
        let len = [
            0.0f32,
            1e-3,
            0.3,
            1.0,
            2.0,
            3.0,
            3.1415925,
            std::f32::consts::PI,
        ][case % 8];
        let phis = azimuths(&mut rng, &scene, 12);
        let theta0s: Vec<f32> = phis
            .iter()
            .map(|_| (20.0 * rng.uniform() - 10.0) as f32)
            .collect();
        let mut out = vec![0.0; phis.len()];
        ao.segment_batch_f32(&phis, &theta0s, len, &mut out)
            .unwrap();
        for k in 0..phis.len() {
            let want = scene
                .half_plane(phis[k])
                .visible_wrapped(
                    &scene.spheres,
                    scene.max,
                    f64::from(theta0s[k]),
                    f64::from(len).min(PI),
                    &mut scratch,
                )
                .unwrap();
            let err = (f64::from(out[k]) - want).abs();
            let bound = scene.bound(phis[k]) + 4.0 * 6.0 * E32;
            assert!(
                err <= bound,
                "case {case}: φ {} θ0 {} len {len}: f32 {} f64 {want} (err {err:e} > {bound:e})",
                phis[k],
                theta0s[k],
                out[k]
            );
            worst = worst.max(err);
            worst_ratio = worst_ratio.max(err / bound);
        }
    }
    println!("f32 AO wrapped segments: worst |f32 − f64| = {worst:.2e}, worst error/bound = {worst_ratio:.3}");
}

/// A ground-sized sphere (`R = 1000`) under a shading point at small
/// heights, seen by normals tilted off the horizontal (a point on the side of
/// a small sphere): the planes that cut the big sphere in a small disc
/// (`h ≈ R`, `D ≪ h`), where `r²` must come from `D² − (|q|² − R²)`; and
/// `max_dist` just reaching a large sphere nearby (`κ → 1`).
#[test]
fn f32_lines_grazing_large_spheres() {
    let mut rng = Rng(0x9_a2e1_a29e);
    let ground = Sphere::new([0.0, -1000.0, 0.0], 1000.0).unwrap();
    let mut worst = 0.0f64;
    for case in 0..200 {
        let lift = [2.0, 1.0, 0.1, 0.01][case % 4];
        let tilt = 0.3 * (2.0 * rng.uniform() - 1.0);
        let az = 2.0 * PI * rng.uniform();
        let n = [tilt.cos() * az.cos(), tilt.sin(), tilt.cos() * az.sin()];
        let scene = Scene {
            p: [0.0, lift, 0.0],
            n,
            t: [0.0, 1.0, 0.0],
            spheres: vec![ground],
            max: [f64::INFINITY, 30.0][case / 4 % 2],
            phi0: 0.0,
        };
        let ao = scene.prepared();
        for k in 0..64 {
            let phi = (PI * (k as f64 + rng.uniform()) / 64.0) as f32;
            let err = (f64::from(ao.line_f32(phi)) - scene.line64(phi)).abs();
            assert!(err <= scene.bound(phi), "case {case} φ {phi}: {err:e}");
            worst = worst.max(err);
        }
    }
    println!(
        "f32 AO lines over a ground-sized sphere, tilted normals: worst |f32 − f64| = {worst:.2e}"
    );
    assert!(worst <= 1e-6, "{worst:e}");
    let big = Sphere::new([0.0, 0.3, 10.1], 10.0).unwrap();
    let near = (0.3f64.hypot(10.1)) - 10.0;
    let mut worst_reach = 0.0f64;
    for k in [1.0, 1e-2, 1e-4, 1e-6, 1e-8] {
        let scene = Scene {
            p: [0.0; 3],
            n: [0.0, 1.0, 0.0],
            t: [1.0, 0.0, 0.0],
            spheres: vec![big],
            max: near * (1.0 + k),
            phi0: 0.0,
        };
        let ao = scene.prepared();
        for i in 0..500 {
            let phi = (PI * (i as f64 + 0.5) / 500.0) as f32;
            let err = (f64::from(ao.line_f32(phi)) - scene.line64(phi)).abs();
            assert!(err <= scene.bound(phi), "reach 1 + {k:e}, φ {phi}: {err:e}");
            worst_reach = worst_reach.max(err);
        }
    }
    println!("f32 AO lines with max_dist just reaching a large sphere: worst |f32 − f64| = {worst_reach:.2e}");
}

/// Several spheres giving intervals with equal ends (exact duplicates, an
/// interval touching another): each gap counted once, as in the f64 path.
#[test]
fn f32_duplicate_spheres_count_each_gap_once() {
    let s = |c: [f64; 3], r: f64| Sphere::new(c, r).unwrap();
    let (p, n, t) = ([0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]);
    let a = s([1.0, 1.0, 0.2], 0.4);
    let b = s([-0.5, 2.0, -0.3], 0.7);
    let inside = s([0.1, 0.2, 0.0], 1.0);
    let scenes: [(&[Sphere<3>], f64); 5] = [
        (&[a, a], 100.0),
        (&[a, b, a, b, a], 100.0),
        (&[b, a, b], 1.5),
        (&[inside, a, inside], 1.1),
        (&[inside, inside, b], 1.1),
    ];
    let mut worst = 0.0f64;
    for (k, &(spheres, max)) in scenes.iter().enumerate() {
        let scene = Scene {
            p,
            n,
            t,
            spheres: spheres.to_vec(),
            max,
            phi0: 0.0,
        };
        let single = {
            let mut u = spheres.to_vec();
            u.sort_by(|x, y| x.centre()[0].total_cmp(&y.centre()[0]));
            u.dedup();
            AoPoint32::<8>::new(p, n, t, &u, max).unwrap()
        };
        let ao = scene.prepared();
        for i in 0..200 {
            let phi = (PI * (i as f64 + 0.5) / 200.0) as f32;
            let got = ao.line_f32(phi);
            let want = scene.line64(phi);
            let err = (f64::from(got) - want).abs();
            worst = worst.max(err);
            assert!(err <= scene.bound(phi), "scene {k} φ {phi}: {got} {want}");
            // The same as with each sphere once.
            let once = single.line_f32(phi);
            assert!(
                (got - once).abs() <= 1e-6,
                "scene {k} φ {phi}: {got} {once}"
            );
        }
    }
    println!("f32 AO lines with duplicate spheres: worst |f32 − f64| = {worst:.2e}");
}

/// The ground point of the bench (pixel (410, 305)): the ground sphere is
/// dropped (below the tangent plane) and the f32 AO estimate from 4096
/// stratified lines agrees with the f64 one.
#[test]
fn f32_ao_estimate_at_the_bench_point() {
    let spheres = ao_scene::spheres();
    let p0 = [-0.940_f64, -0.008, 3.925];
    let d = normalised([p0[0], p0[1] + 1000.0, p0[2]]);
    let p = [1000.0 * d[0], 1000.0 * d[1] - 1000.0, 1000.0 * d[2]];
    let ao = AoPoint32::<8>::new(p, d, [1.0, 0.0, 0.0], &spheres, 500.0).unwrap();
    assert_eq!(ao.occluders(), 7);
    let n = 4096;
    let phis: Vec<f32> = (0..n)
        .map(|k| (PI * (k as f64 + 0.5) / n as f64) as f32)
        .collect();
    let mut out = vec![0.0; n];
    ao.line_batch_f32(&phis, &mut out).unwrap();
    let mut scratch = [(0.0, 0.0); 16];
    let (mut sum32, mut sum64) = (0.0f64, 0.0f64);
    for (&phi, &v) in phis.iter().zip(&out) {
        let hp = HalfPlane::at_azimuth(p, d, [1.0, 0.0, 0.0], f64::from(phi)).unwrap();
        sum64 += hp
            .visible(&spheres, 500.0, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
            .unwrap();
        sum32 += f64::from(v);
    }
    let (a32, a64) = (sum32 / n as f64, sum64 / n as f64);
    println!("AO at the bench point: f32 {a32:.7}, f64 {a64:.7}");
    assert!((a32 - a64).abs() <= 1e-6, "{a32} {a64}");
    assert!((a64 - 0.7148).abs() < 5e-4, "{a64}");
}

#[test]
fn f32_bad_input_names_the_parameter() {
    let spheres = ao_scene::spheres();
    let (p, n, t) = ([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]);
    let nan = f64::NAN;
    let e = AoPoint32::<8>::new([nan, 0.0, 0.0], n, t, &spheres, 1.0).unwrap_err();
    assert_eq!(e, ParamError::NonFinite { name: "point" });
    let e = AoPoint32::<8>::new(p, [0.0, nan, 0.0], t, &spheres, 1.0).unwrap_err();
    assert_eq!(e, ParamError::NonFinite { name: "normal" });
    let e = AoPoint32::<8>::new(p, n, [f64::INFINITY, 0.0, 0.0], &spheres, 1.0).unwrap_err();
    assert_eq!(e, ParamError::NonFinite { name: "tangent" });
    let e = AoPoint32::<8>::new(p, n, [0.0, 2.0, 0.0], &spheres, 1.0).unwrap_err();
    assert_eq!(e, ParamError::ZeroDirection);
    // Capacity: seven spheres of the scene can occlude (the ground is under
    // the tangent plane at the origin... the origin is on it).
    let e = AoPoint32::<3>::new(p, n, t, &spheres, 1000.0).unwrap_err();
    assert_eq!(
        e,
        ParamError::Length {
            name: "spheres",
            expected: 3,
            got: 7
        }
    );
    let ao = AoPoint32::<8>::new(p, n, t, &spheres, 1000.0).unwrap();
    let mut out = [0.0f32; 3];
    assert_eq!(
        ao.line_batch_f32(&[0.1, 0.2], &mut out).unwrap_err(),
        ParamError::Length {
            name: "out",
            expected: 2,
            got: 3
        }
    );
    let mut phis = [0.5f32; 11];
    let mut out = [7.0f32; 11];
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        phis[9] = bad;
        assert_eq!(
            ao.line_batch_f32(&phis, &mut out).unwrap_err(),
            ParamError::NonFinite { name: "phis" }
        );
        assert!(out.iter().all(|&x| x == 7.0), "written before the check");
        assert!(ao.line_f32(bad).is_nan());
        assert!(ao.segment_f32(bad, 0.0, 1.0).is_nan());
        assert!(ao.segment_f32(0.5, bad, 1.0).is_nan());
    }
    phis[9] = 0.5;
    let theta0s = [0.0f32; 11];
    assert_eq!(
        ao.segment_batch_f32(&phis, &theta0s[..10], 1.0, &mut out)
            .unwrap_err(),
        ParamError::Length {
            name: "theta0s",
            expected: 11,
            got: 10
        }
    );
    assert_eq!(
        ao.segment_batch_f32(&phis, &theta0s, 1.0, &mut out[..4])
            .unwrap_err(),
        ParamError::Length {
            name: "out",
            expected: 11,
            got: 4
        }
    );
    let mut bad_t = theta0s;
    bad_t[3] = f32::NAN;
    assert_eq!(
        ao.segment_batch_f32(&phis, &bad_t, 1.0, &mut out)
            .unwrap_err(),
        ParamError::NonFinite { name: "theta0s" }
    );
    assert_eq!(
        ao.segment_batch_f32(&phis, &theta0s, f32::NAN, &mut out)
            .unwrap_err(),
        ParamError::NonFinite { name: "len" }
    );
    for len in [-0.1f32, 3.2] {
        assert_eq!(
            ao.segment_batch_f32(&phis, &theta0s, len, &mut out)
                .unwrap_err(),
            ParamError::OutOfRange {
                name: "len",
                value: f64::from(len),
                min: 0.0,
                max: f64::from(std::f32::consts::PI)
            }
        );
        assert!(ao.segment_f32(0.5, 0.0, len).is_nan());
    }
    // A non-positive or NaN max distance occludes nothing.
    for m in [0.0, -1.0, nan] {
        let ao = AoPoint32::<0>::new(p, n, t, &spheres, m).unwrap();
        assert_eq!(ao.occluders(), 0);
        assert_eq!(ao.line_f32(0.3), 1.0);
        let v = f64::from(ao.segment_f32(0.3, 0.0, 1.0));
        assert!((v - cosine_weight(0.0, 1.0)).abs() <= 4.0 * E32, "{v}");
    }
}

/// `rotated` from the base half-plane of a frame is `at_azimuth` of that
/// frame up to rounding (directions within 1e−15), and the visible
/// measures of the two agree to 1e−13 in the AO scene.
#[test]
fn rotated_half_planes_are_at_azimuth() {
    let spheres = ao_scene::spheres();
    let mut rng = Rng(0x0707_1e1e_2b2b_3c3c);
    let mut scratch = vec![(0.0, 0.0); 2 * spheres.len()];
    let mut worst = 0.0f64;
    for case in 0..200 {
        let on = &spheres[case % spheres.len()];
        let (p, n) = point_on(&mut rng, on);
        let t = rng.unit_vector();
        let base = HalfPlane::new(p, n, t).unwrap();
        let phi = PI * rng.uniform();
        let r = base.rotated(phi);
        let a = HalfPlane::at_azimuth(p, n, t, phi).unwrap();
        for j in 0..3 {
            assert!(
                (r.azimuth()[j] - a.azimuth()[j]).abs() < 1e-15,
                "case {case}"
            );
            assert!((r.normal()[j] - a.normal()[j]).abs() < 1e-15, "case {case}");
        }
        let vr = r
            .visible(&spheres, 500.0, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
            .unwrap();
        let va = a
            .visible(&spheres, 500.0, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
            .unwrap();
        worst = worst.max((vr - va).abs());
    }
    println!("rotated vs at_azimuth: worst visible difference {worst:.1e}");
    assert!(worst < 1e-13, "{worst}");
}

/// `sees` (the ray's own quadratic) against rays cast with `Sphere::hit`
/// from points outside, inside and near random spheres, with maximum
/// distances that cut the spheres: every direction farther than 1e−9 from
/// an occluded interval's end must agree, and both outcomes occur from
/// inside a sphere.
#[test]
fn point_visibility_matches_cast_rays_inside_and_out() {
    let mut rng = Rng(0x1a2b_3c4d_5e6f_7081);
    let (mut checked, mut inside_hits, mut inside_misses) = (0usize, 0usize, 0usize);
    for case in 0..400 {
        let c = [
            4.0 * rng.uniform() - 2.0,
            4.0 * rng.uniform() - 2.0,
            4.0 * rng.uniform() - 2.0,
        ];
        let r = 0.2 + 1.5 * rng.uniform();
        let s = Sphere::new(c, r).unwrap();
        let p = [
            3.0 * rng.uniform() - 1.5,
            3.0 * rng.uniform() - 1.5,
            3.0 * rng.uniform() - 1.5,
        ];
        let q = [c[0] - p[0], c[1] - p[1], c[2] - p[2]];
        let inside = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] < r * r;
        let hp = HalfPlane::new(p, rng.unit_vector(), rng.unit_vector()).unwrap();
        let max = [0.3, 1.0, 2.5, 500.0][case % 4];
        let occ = hp.occluded(&s, max);
        for i in 0..=200 {
            let t = -FRAC_PI_2 + PI * (i as f64 + 0.5) / 201.0;
            if occ
                .pieces()
                .iter()
                .any(|&(a, b)| (t - a).abs() < 1e-9 || (t - b).abs() < 1e-9)
            {
                continue;
            }
            let hit = cast(p, hp.direction(t), std::slice::from_ref(&s), max);
            let sees = hp.sees(std::slice::from_ref(&s), max, t);
            assert_eq!(sees, !hit, "case {case} θ {t} inside {inside} max {max}");
            checked += 1;
            if inside {
                if hit {
                    inside_hits += 1;
                } else {
                    inside_misses += 1;
                }
            }
        }
    }
    println!("{checked} directions; from inside: {inside_hits} blocked, {inside_misses} free");
    assert!(inside_hits > 100 && inside_misses > 100);
}
