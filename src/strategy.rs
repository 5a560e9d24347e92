//! `proptest` strategies for the inputs that break renderers (feature
//! `proptest`): directions near and on the axes, rays grazing or tangent to a
//! sphere from either side, rays given through far-away points, segments
//! ending next to a boundary, deep Gaussian tails, far-away origins.
//!
//! Each case carries plain `f64` arrays, so it feeds this crate's
//! [`crate::world`] forms or a renderer's own geometry; the crate's own tests
//! use these strategies. In a renderer's property tests:
//!
//! ```
//! use linesample::strategy;
//! use linesample::world::{Ray, Sphere};
//! use proptest::prelude::*;
//!
//! proptest!(|(case in strategy::sphere_ray::<3>())| {
//!     let s = Sphere::new(case.centre, case.radius).unwrap();
//!     let ray = Ray::new(case.origin, case.dir).unwrap();
//!     // e.g. the renderer's intersector must agree with the closed form:
//!     let chord = s.chord(&ray);
//!     prop_assert!(chord >= 0.0 && chord <= 2.0 * case.radius * (1.0 + 1e-15));
//! });
//! ```
//!
//! Sizes are log-uniform over the whole accepted ranges
//! ([`crate::world::Sphere::RADIUS_MIN`] … `RADIUS_MAX`,
//! [`crate::world::Gaussian::SIGMA_MIN`] … `SIGMA_MAX`) unless a strategy says
//! otherwise.

use crate::world::{Gaussian, Sphere};
use proptest::prelude::*;

/// `10^U(lo, hi)`.
pub fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> + Clone {
    (lo..=hi).prop_map(|e| libm::pow(10.0, e))
}

/// A sign `±1`.
fn sign() -> impl Strategy<Value = f64> + Clone {
    any::<bool>().prop_map(|b| if b { 1.0 } else { -1.0 })
}

fn normalise<const D: usize>(v: [f64; D]) -> [f64; D] {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let s: [f64; D] = core::array::from_fn(|j| v[j] / m);
    let n = crate::num::scalar::sqrt(s.iter().map(|x| x * x).sum::<f64>());
    core::array::from_fn(|j| s[j] / n)
}

/// A generic direction (not normalised, components in `[−1, 1]`, not all
/// tiny).
pub fn generic_direction<const D: usize>() -> impl Strategy<Value = [f64; D]> + Clone {
    prop::array::uniform::<_, D>(-1.0f64..1.0).prop_filter("non-degenerate", |v| {
        v.iter().map(|x| x.abs()).sum::<f64>() > 1e-3
    })
}

/// A direction on an axis (`±e_j`) or within `10⁻³⁰⁰ … 10⁻⁴` of one (the other
/// components tiny, of either sign, or exactly zero): the inputs that break
/// slab tests and orthonormal frames.
pub fn near_axis_direction<const D: usize>() -> impl Strategy<Value = [f64; D]> + Clone {
    (
        0..D,
        sign(),
        prop::array::uniform::<_, D>((log_uniform(-300.0, -4.0), sign(), 0u8..4)),
    )
        .prop_map(|(axis, s, small)| {
            core::array::from_fn(|j| {
                if j == axis {
                    s
                } else {
                    let (m, sg, zero) = small[j];
                    if zero == 0 {
                        0.0
                    } else {
                        sg * m
                    }
                }
            })
        })
}

/// Any of the above, normalised to unit length.
pub fn direction<const D: usize>() -> impl Strategy<Value = [f64; D]> + Clone {
    prop_oneof![generic_direction::<D>(), near_axis_direction::<D>()].prop_map(normalise)
}

/// A centre near the origin (`|c_j| ≤ 10`) or far away (`|c_j|` up to
/// `10¹²`).
pub fn centre<const D: usize>() -> impl Strategy<Value = [f64; D]> + Clone {
    prop_oneof![
        prop::array::uniform::<_, D>(-10.0f64..10.0),
        prop::array::uniform::<_, D>((log_uniform(0.0, 12.0), sign()).prop_map(|(m, s)| m * s)),
    ]
}

/// A sphere and a ray against it, named by kind.
#[derive(Clone, Copy, Debug)]
pub struct SphereRay<const D: usize> {
    /// Sphere centre.
    pub centre: [f64; D],
    /// Sphere radius.
    pub radius: f64,
    /// Ray origin.
    pub origin: [f64; D],
    /// Unit ray direction.
    pub dir: [f64; D],
    /// The distance of the line from the centre, in radii (as intended; the
    /// rounded inputs differ from it by rounding).
    pub distance: f64,
    /// What kind of case this is (`"inside"`, `"grazing"`, `"tangent"`,
    /// `"miss"`).
    pub kind: &'static str,
}

/// Point on the line at parameter `-s` from the foot `f`: `f − s·ω`.
fn back<const D: usize>(f: &[f64; D], w: &[f64; D], s: f64) -> [f64; D] {
    core::array::from_fn(|j| f[j] - s * w[j])
}

/// A unit vector perpendicular to the unit `w` (Gram–Schmidt against the axis
/// least aligned with `w`, then against a second random direction in 3D).
fn perpendicular<const D: usize>(w: &[f64; D], v: &[f64; D]) -> [f64; D] {
    let d: f64 = (0..D).map(|j| v[j] * w[j]).sum();
    let p: [f64; D] = core::array::from_fn(|j| v[j] - d * w[j]);
    let n = crate::num::scalar::sqrt(p.iter().map(|x| x * x).sum::<f64>());
    if n > 1e-6 {
        return core::array::from_fn(|j| p[j] / n);
    }
    let mut k = 0;
    for j in 1..D {
        if w[j].abs() < w[k].abs() {
            k = j;
        }
    }
    let mut e = [0.0; D];
    e[k] = 1.0;
    perpendicular(w, &e)
}

/// A sphere (radius log-uniform over `10⁻¹⁰⁰ … 10¹⁰⁰`, centre from
/// [`centre`]) and a ray whose line passes at distance `d·r` from the centre:
/// well inside (`d < 0.9`), grazing from inside (`d = 1 − 10^{−k}`, `k` up to
/// 15), tangent from either side (`d = 1 ± 10^{−k}`, `k` up to 16) or missing;
/// the origin at a parameter `s·r` before the foot of the perpendicular with
/// `|s|` from 0 (at the foot) to `10³⁰` (a ray given through a far-away point),
/// or on the surface. Directions from [`direction`].
pub fn sphere_ray<const D: usize>() -> impl Strategy<Value = SphereRay<D>> + Clone {
    (
        centre::<D>(),
        log_uniform(-100.0, 100.0),
        direction::<D>(),
        generic_direction::<D>(),
        prop_oneof![
            (0.0f64..0.9).prop_map(|d| (d, "inside")),
            (1.0f64..15.0).prop_map(|k| (1.0 - libm::pow(10.0, -k), "grazing")),
            ((1.0f64..16.0), sign()).prop_map(|(k, s)| (1.0 + s * libm::pow(10.0, -k), "tangent")),
            (1.0f64..3.0).prop_map(|d| (d, "miss")),
        ],
        prop_oneof![
            (-3.0f64..3.0),
            (log_uniform(0.0, 30.0), sign()).prop_map(|(m, s)| m * s),
        ],
    )
        .prop_map(|(c, r, w, v, (d, kind), s)| {
            let r = r.clamp(Sphere::<D>::RADIUS_MIN, Sphere::<D>::RADIUS_MAX);
            let u = perpendicular(&w, &v);
            let foot: [f64; D] = core::array::from_fn(|j| c[j] + d * r * u[j]);
            SphereRay {
                centre: c,
                radius: r,
                origin: back(&foot, &w, s * r),
                dir: w,
                distance: d,
                kind,
            }
        })
}

/// A sphere, a ray and a segment `[t0, t1]` with one end next to where the
/// line crosses the sphere: at the (rounded) crossing or `±1…4` ulp from it,
/// or inside/outside by `10^{−k}` of the radius, `k` up to 15; the other end
/// at a length `10^{−U(0, 15)}·2r` (down to `10⁻¹⁵` of the diameter) on
/// either side. The crossing is computed in `f64` from the intended geometry
/// (foot parameter and half chord), so it is within rounding of the exact
/// root: exactly the inputs that make `t − t±` cancel.
pub fn boundary_segment<const D: usize>() -> impl Strategy<Value = (SphereRay<D>, f64, f64)> + Clone
{
    (
        sphere_ray::<D>().prop_filter("crosses", |c| c.distance < 1.0),
        any::<bool>(),
        prop_oneof![
            (-4i32..=4).prop_map(|k| (k, 0.0)),
            ((1.0f64..15.0), sign()).prop_map(|(k, s)| (0, s * libm::pow(10.0, -k))),
        ],
        log_uniform(-15.0, 0.0),
        any::<bool>(),
    )
        .prop_map(|(case, exit, (ulps, frac), len, forward)| {
            let r = case.radius;
            let q: [f64; D] = core::array::from_fn(|j| case.origin[j] - case.centre[j]);
            let b: f64 = (0..D).map(|j| q[j] * case.dir[j]).sum();
            let h = r * crate::num::scalar::sqrt((1.0 - case.distance) * (1.0 + case.distance));
            let root = if exit { -b + h } else { -b - h };
            let mut e = root + frac * r;
            for _ in 0..ulps.unsigned_abs() {
                e = if ulps > 0 { next_up(e) } else { next_down(e) };
            }
            let l = len * 2.0 * r;
            let (t0, t1) = if forward { (e, e + l) } else { (e - l, e) };
            (case, t0, t1)
        })
}

fn next_up(x: f64) -> f64 {
    if x == 0.0 {
        f64::from_bits(1)
    } else if x > 0.0 {
        f64::from_bits(x.to_bits() + 1)
    } else {
        f64::from_bits(x.to_bits() - 1)
    }
}

fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// A Gaussian and a segment along a ray.
#[derive(Clone, Copy, Debug)]
pub struct GaussianSegment<const D: usize> {
    /// Centre.
    pub centre: [f64; D],
    /// Standard deviation.
    pub sigma: f64,
    /// Ray origin.
    pub origin: [f64; D],
    /// Unit direction.
    pub dir: [f64; D],
    /// Start parameter (may be `−∞`).
    pub t0: f64,
    /// End parameter (may be `∞`).
    pub t1: f64,
    /// The intended exponent `E = d²/2σ²` of the segment's nearest point
    /// (`e^{−E}` down to `10⁻³⁰⁰`).
    pub exponent: f64,
}

/// A Gaussian (σ log-uniform over `10⁻⁶ … 10⁶`, centre from [`centre`]) and a
/// segment whose nearest point is at exponent `E = d²/2σ²` from 0 to 690
/// (values down to `e^{−690} ≈ 10⁻³⁰⁰` of the peak): lines and half-lines,
/// segments straddling the foot, short segments (down to `10⁻⁹σ`) and long
/// ones, running radially away from or across the centre. The origin is
/// placed `s·σ` before the foot with `|s|` up to `10⁶`.
pub fn gaussian_segment<const D: usize>() -> impl Strategy<Value = GaussianSegment<D>> + Clone {
    (
        centre::<D>(),
        log_uniform(-6.0, 6.0),
        direction::<D>(),
        generic_direction::<D>(),
        prop_oneof![0.0f64..4.0, 4.0f64..690.0],
        prop_oneof![
            (-3.0f64..3.0),
            (log_uniform(0.0, 6.0), sign()).prop_map(|(m, s)| m * s)
        ],
        0u8..4,
        log_uniform(-9.0, 2.0),
        -3.0f64..3.0,
    )
        .prop_map(|(c, sigma, w, v, e, s, shape, len, a)| {
            let sigma = sigma.clamp(Gaussian::<D>::SIGMA_MIN, Gaussian::<D>::SIGMA_MAX);
            let u = perpendicular(&w, &v);
            let d = sigma * crate::num::scalar::sqrt(2.0 * e);
            let foot: [f64; D] = core::array::from_fn(|j| c[j] + d * u[j]);
            let origin = back(&foot, &w, s * sigma);
            // Parameters relative to the foot (at t = s·σ).
            let tf = s * sigma;
            let l = len * sigma;
            let (t0, t1) = match shape {
                0 => (f64::NEG_INFINITY, f64::INFINITY),
                1 => (tf + a * sigma, f64::INFINITY),
                2 => (tf + a * sigma, tf + a * sigma + l),
                _ => (tf - 0.5 * l, tf + 0.5 * l),
            };
            GaussianSegment {
                centre: c,
                sigma,
                origin,
                dir: w,
                t0,
                t1,
                exponent: e,
            }
        })
}
