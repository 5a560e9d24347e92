//! Ambient occlusion by spheres in closed form, one half-plane at a time.
//!
//! At a shading point `p` with unit normal `n`, every direction of the upper
//! hemisphere is `d(φ, θ) = sin θ·a(φ) + cos θ·n` for an azimuth direction
//! `a(φ) ⊥ n`, `φ ∈ [0, π)`, and a signed polar angle `θ ∈ (−π/2, π/2)`
//! (negative `θ` leans towards `−a`; the crate's
//! [conventions](crate#conventions)). The solid-angle element is
//! `|sin θ| dθ dφ`, so cosine-weighted ambient occlusion normalised to 1 when
//! nothing occludes is
//!
//! ```text
//! AO = (1/π) ∫_0^π dφ ∫_{−π/2}^{π/2} V(φ, θ) |sin θ| cos θ dθ,
//! ```
//!
//! `V = 1` where the ray `p + s·d`, `0 < s ≤ s_max`, meets no sphere. For a
//! fixed `φ` the directions lie in the plane `Π` spanned by `a` and `n`, which
//! cuts a sphere `(c, R)` in a disc: with `q = c − p`, `h = q·(n × a)`,
//! the disc has radius `r = √((R − |h|)(R + |h|))` (none for `|h| ≥ R`) and
//! centre at distance `D = √((q·a)² + (q·n)²)` from `p`, in the direction
//! `θ_c = atan2(q·a, q·n)`. A ray at angle `α` from that direction meets the
//! disc's circle at distance `s` exactly when (law of cosines)
//! `r² = s² + D² − 2sD cos α`, so the ray at the circle point at distance
//! `s_max` has `cos α = κ = (s_max² + D² − r²)/(2 s_max D)`. Hence
//! ([`HalfPlane::occluded`]):
//!
//! * `p` outside the disc (`D > r`): the occluded directions are
//!   `|α| ≤ β = asin(r/D)` (`atan2(r, √(D² − r²))`), cut to `|α| ≤ acos κ`
//!   when the tangent point `√(D² − r²)` lies beyond `s_max`, and none when
//!   the nearest point `D − r` does;
//! * `p` inside (`D < r`, inside the sphere): the ray leaves the sphere at
//!   distance `D cos α + √(r² − D² sin² α)`, so the occluded directions are
//!   `|α| ≥ acos κ` (all when `s_max ≥ D + r`, none when `s_max ≤ r − D`);
//! * `p` on the sphere (`|q|² − R²` within `10⁻¹²·R²`, a shading point on its
//!   own sphere up to rounding): `β = π/2`, the half-plane below the tangent
//!   line, which meets `(−π/2, π/2)` in nothing.
//!
//! Each occluded set is an arc `θ_c ± w` (`θ_c + π ± w` inside) and meets
//! `[−π/2, π/2]` in at most two intervals (the arc may wrap past `±π`).
//! The visible part of a segment `[t0, t1]` is the complement of the merged
//! intervals, and its weight is the closed form
//! ([`cosine_weight`]) `∫_a^b |sin t| cos t dt`, which is
//! `sin(b − a)·sin(b + a)/2` on one side of 0 (no cancellation for short
//! pieces) and `(sin²a + sin²b)/2` across it.
//!
//! Errors: the interval ends come from `atan2`, `asin`/`acos` and square
//! roots of the offsets `q` (each a few ulp); with `q` rounded from
//! `c − p`, an end is off by at most about `4u·(|c| + |p|)/(D − r)`
//! radians plus a few ulp of `π` (the conditioning of a tangent direction:
//! large only for a point almost touching a sphere). The weights have a
//! relative error of a few ulp. Tested against brute-force ray casting with
//! [`linesample::world::Sphere::hit`] and adaptive quadrature (`scene/tests/occlusion.rs`).
//!
//! The `f32` SIMD batch of the line and wrapped-segment measures over many
//! azimuths at one shading point, with no transcendental per sphere and no
//! sorting, is [`super::occlusion_f32::AoPoint32`] (tested against this path).

use crate::vec3::cross;
use core::f64::consts::{FRAC_PI_2, PI};
use linesample::geom::dot;
use linesample::world::check_finite;
use linesample::world::Sphere;
use linesample::ParamError;

/// The half-plane through a shading point `p` spanned by its unit normal `n`
/// and a unit azimuth direction `a ⊥ n`: the directions
/// `d(θ) = sin θ·a + cos θ·n`, `θ ∈ (−π/2, π/2)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfPlane {
    p: [f64; 3],
    n: [f64; 3],
    a: [f64; 3],
    /// `n × a`, the plane's unit normal.
    b: [f64; 3],
}

/// The occluded part of `[−π/2, π/2]` in one half-plane by one sphere: at
/// most two intervals `[lo, hi]`, `lo < hi`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Occluded {
    pieces: [(f64, f64); 2],
    len: usize,
}

impl Occluded {
    /// The intervals (`0`, `1` or `2` of them), in increasing order.
    #[must_use]
    pub fn pieces(&self) -> &[(f64, f64)] {
        &self.pieces[..self.len]
    }

    fn push(&mut self, lo: f64, hi: f64) {
        let (lo, hi) = (lo.max(-FRAC_PI_2), hi.min(FRAC_PI_2));
        if lo < hi {
            self.pieces[self.len] = (lo, hi);
            self.len += 1;
        }
    }
}

fn unit(x: [f64; 3]) -> Option<[f64; 3]> {
    let l = linesample::num::scalar::sqrt(dot(&x, &x));
    (l > 0.0 && l.is_finite()).then(|| x.map(|c| c / l))
}

impl HalfPlane {
    /// The half-plane at `point` with normal `normal` (normalised here) and
    /// azimuth direction `azimuth` (its component along the normal removed,
    /// then normalised).
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`point`, `normal`, `azimuth`);
    /// [`ParamError::ZeroDirection`] if `normal` is zero or `azimuth` is
    /// parallel to it.
    pub fn new(
        point: impl Into<[f64; 3]>,
        normal: impl Into<[f64; 3]>,
        azimuth: impl Into<[f64; 3]>,
    ) -> Result<Self, ParamError> {
        let (p, n, a) = (point.into(), normal.into(), azimuth.into());
        check_finite("point", &p)?;
        check_finite("normal", &n)?;
        check_finite("azimuth", &a)?;
        let n = unit(n).ok_or(ParamError::ZeroDirection)?;
        // a without its component along n, normalised; twice, so that the
        // rounding of the first pass leaves no normal component.
        let reject = |a: [f64; 3]| {
            let an = dot(&a, &n);
            unit([a[0] - an * n[0], a[1] - an * n[1], a[2] - an * n[2]])
                .ok_or(ParamError::ZeroDirection)
        };
        let a = reject(reject(a)?)?;
        Ok(Self {
            p,
            n,
            a,
            b: cross(n, a),
        })
    }

    /// The half-plane at azimuth `phi` of the frame `(t, n × t, n)` at
    /// `point`: `a(φ) = cos φ·t + sin φ·(n × t)`, with `t` the given tangent
    /// (its normal component removed); any finite `φ`, radians
    /// ([conventions](crate#conventions)).
    ///
    /// # Errors
    /// As [`HalfPlane::new`], and [`ParamError::NonFinite`] (`phi`).
    pub fn at_azimuth(
        point: impl Into<[f64; 3]>,
        normal: impl Into<[f64; 3]>,
        tangent: impl Into<[f64; 3]>,
        phi: f64,
    ) -> Result<Self, ParamError> {
        if !phi.is_finite() {
            return Err(ParamError::NonFinite { name: "phi" });
        }
        let base = Self::new(point, normal, tangent)?;
        let t2 = base.b;
        let (s, c) = (libm::sin(phi), libm::cos(phi));
        let a = core::array::from_fn::<f64, 3, _>(|j| c * base.a[j] + s * t2[j]);
        Self::new(base.p, base.n, a)
    }

    /// The shading point.
    #[must_use]
    pub fn point(&self) -> [f64; 3] {
        self.p
    }

    /// The unit normal `n`.
    #[must_use]
    pub fn normal(&self) -> [f64; 3] {
        self.n
    }

    /// The unit azimuth direction `a`.
    #[must_use]
    pub fn azimuth(&self) -> [f64; 3] {
        self.a
    }

    /// The unit direction `sin θ·a + cos θ·n` (signed `θ`, radians:
    /// [conventions](crate#conventions)).
    #[must_use]
    pub fn direction(&self, theta: f64) -> [f64; 3] {
        let (s, c) = (libm::sin(theta), libm::cos(theta));
        core::array::from_fn(|j| s * self.a[j] + c * self.n[j])
    }

    /// The angles `θ ∈ [−π/2, π/2]` whose rays `p + s·d(θ)`, `0 < s ≤
    /// max_dist`, meet `sphere` (see the [module docs](self) for the
    /// derivation and the error bound). `max_dist` may be `+∞`; a `max_dist`
    /// that is not positive, or NaN, occludes nothing.
    #[must_use]
    pub fn occluded(&self, sphere: &Sphere<3>, max_dist: f64) -> Occluded {
        let mut out = Occluded::default();
        if max_dist.is_nan() || max_dist <= 0.0 {
            return out;
        }
        let c = sphere.centre();
        let big_r = sphere.radius();
        let q = [c[0] - self.p[0], c[1] - self.p[1], c[2] - self.p[2]];
        let h = dot(&q, &self.b).abs();
        if h >= big_r {
            return out;
        }
        let r2 = (big_r - h) * (big_r + h);
        let (qa, qn) = (dot(&q, &self.a), dot(&q, &self.n));
        let d2 = qa * qa + qn * qn;
        let d = linesample::num::scalar::sqrt(d2);
        let r = linesample::num::scalar::sqrt(r2);
        let theta_c = libm::atan2(qa, qn);
        // |q|² − R² = D² − r², from |q| and R (no cancellation of squares).
        let ql = linesample::num::scalar::sqrt(dot(&q, &q));
        let out2 = (ql - big_r) * (ql + big_r);
        // cos α of the circle point at distance s = max_dist:
        // (s² + D² − r²)/(2sD), with D² − r² = |q|² − R² = out2.
        let kap = if max_dist.is_finite() {
            (max_dist * max_dist + out2) / (2.0 * max_dist * d)
        } else {
            f64::INFINITY
        };
        let on_surface = out2.abs() <= 1e-12 * big_r * big_r;
        let (centre, half) = if on_surface || out2 > 0.0 {
            // Outside (or on the sphere): |α| ≤ β, cut by max_dist.
            if d - r >= max_dist {
                return out;
            }
            // The distance to the tangent points, √(D² − r²), and the half
            // angle β = atan2(r, that) of the whole disc.
            let (tangent, beta) = if on_surface {
                (0.0, FRAC_PI_2)
            } else {
                let t = linesample::num::scalar::sqrt(out2);
                (t, libm::atan2(r, t))
            };
            let w = if tangent <= max_dist {
                beta
            } else {
                libm::acos(kap.clamp(-1.0, 1.0)).min(beta)
            };
            (theta_c, w)
        } else {
            // Inside: |α| ≥ acos κ, an arc around the opposite direction.
            if max_dist >= d + r {
                (theta_c, PI)
            } else if max_dist <= r - d {
                return out;
            } else {
                let a0 = libm::acos(kap.clamp(-1.0, 1.0));
                let opp = if theta_c > 0.0 {
                    theta_c - PI
                } else {
                    theta_c + PI
                };
                (opp, PI - a0)
            }
        };
        if half >= PI {
            // The whole circle (no seam from the shifted copies below).
            out.push(-FRAC_PI_2, FRAC_PI_2);
            return out;
        }
        // The arc [centre − half, centre + half] (centre ∈ [−π, π], half < π)
        // and its copies shifted by ±2π, each cut to [−π/2, π/2]. The copies
        // are disjoint (width 2·half < 2π) and pushed left to right, so the
        // pieces come out in increasing order.
        for k in [-1.0, 0.0, 1.0] {
            let shift = 2.0 * PI * k;
            out.push(centre - half + shift, centre + half + shift);
        }
        out
    }

    /// `V(θ)`: whether the ray `p + s·d(θ)`, `0 < s ≤ max_dist`, escapes
    /// every sphere of `spheres`: a point sample's visibility, by the ray's
    /// own quadratic (no angles, no interval). For `q = c − p`, `b = q·d` and
    /// `c₂ = |q|² − R²` (formed as `(|q| − R)(|q| + R)`), the ray meets the
    /// sphere's surface at `s = b ∓ √(b² − c₂)`: from outside (`c₂ > 0`) it
    /// is blocked iff `b > 0`, `b² > c₂` (a tangent ray passes) and the near
    /// root `c₂/(b + √(b² − c₂))` (no cancellation) is at most `max_dist`;
    /// from inside (`c₂ < 0`) iff the exit `b + √(b² − c₂)` is at most
    /// `max_dist`. A point on a sphere (`|c₂| ≤ 10⁻¹²R²`, as in
    /// [`HalfPlane::occluded`]) is not blocked by it (its hemisphere lies
    /// above the tangent plane). This is the same set as "`θ` in no occluded
    /// interval of [`HalfPlane::occluded`]" up to directions within rounding
    /// of an interval's end (tested). A `max_dist` that is not positive, or
    /// NaN, blocks nothing. Nothing is allocated.
    #[must_use]
    pub fn sees(&self, spheres: &[Sphere<3>], max_dist: f64, theta: f64) -> bool {
        if max_dist.is_nan() || max_dist <= 0.0 {
            return true;
        }
        let d = self.direction(theta);
        spheres.iter().all(|sp| {
            let c = sp.centre();
            let big_r = sp.radius();
            let q = [c[0] - self.p[0], c[1] - self.p[1], c[2] - self.p[2]];
            let ql = linesample::num::scalar::sqrt(dot(&q, &q));
            let c2 = (ql - big_r) * (ql + big_r);
            if c2.abs() <= 1e-12 * big_r * big_r {
                return true;
            }
            let b = dot(&q, &d);
            let disc = b * b - c2;
            if disc <= 0.0 {
                return true;
            }
            let root = linesample::num::scalar::sqrt(disc);
            let hit_at = if c2 > 0.0 {
                if b <= 0.0 {
                    return true;
                }
                c2 / (b + root)
            } else {
                b + root
            };
            hit_at > max_dist
        })
    }

    /// The half-plane at azimuth `phi` measured from this one, in the frame
    /// `(a, b = n × a)`: `a' = cos φ·a + sin φ·b`, `b' = n × a' = cos φ·b −
    /// sin φ·a`, with no normalisation (the new vectors are unit and
    /// orthogonal to a few ulp). From the half-plane of
    /// [`HalfPlane::new`]`(p, n, t)` this is [`HalfPlane::at_azimuth`]`(p, n,
    /// t, φ)` up to rounding, at a fraction of its cost: a renderer builds
    /// the base once per shading point. A non-finite `phi` gives NaN
    /// directions (whose visible measures are then NaN).
    #[must_use]
    pub fn rotated(&self, phi: f64) -> Self {
        let (s, c) = (libm::sin(phi), libm::cos(phi));
        let a = core::array::from_fn(|j| c * self.a[j] + s * self.b[j]);
        let b = core::array::from_fn(|j| c * self.b[j] - s * self.a[j]);
        Self {
            p: self.p,
            n: self.n,
            a,
            b,
        }
    }

    /// The cosine-weighted visible measure `∫_{t0}^{t1} V(θ)|sin θ| cos θ dθ`
    /// of `[t0, t1] ⊆ [−π/2, π/2]` (signed polar angles,
    /// [conventions](crate#conventions); clamped to it, `t0 ≥ t1` gives 0) among
    /// `spheres`, with `scratch` for the occluded intervals (at least
    /// `2·spheres.len()` long; nothing is allocated).
    ///
    /// # Errors
    /// [`ParamError::Length`] (`scratch`) if `scratch` is too short;
    /// [`ParamError::NonFinite`] (`t0`, `t1`) for NaN ends.
    pub fn visible(
        &self,
        spheres: &[Sphere<3>],
        max_dist: f64,
        t0: f64,
        t1: f64,
        scratch: &mut [(f64, f64)],
    ) -> Result<f64, ParamError> {
        if t0.is_nan() {
            return Err(ParamError::NonFinite { name: "t0" });
        }
        if t1.is_nan() {
            return Err(ParamError::NonFinite { name: "t1" });
        }
        if scratch.len() < 2 * spheres.len() {
            return Err(ParamError::Length {
                name: "scratch",
                expected: 2 * spheres.len(),
                got: scratch.len(),
            });
        }
        let mut m = 0;
        for s in spheres {
            for &(lo, hi) in self.occluded(s, max_dist).pieces() {
                if hi > t0 && lo < t1 {
                    scratch[m] = (lo, hi);
                    m += 1;
                }
            }
        }
        Ok(visible_weight(&mut scratch[..m], t0, t1))
    }

    /// [`HalfPlane::visible`] over a segment of the angle `θ` that wraps with
    /// period `π`: `[θ0, θ0 + len]` with `θ0` reduced to `[−π/2, π/2)` and the
    /// part beyond `π/2` continued from `−π/2` (`len = π` is the whole
    /// half-plane, whatever `θ0`). `0 ≤ len ≤ π`.
    ///
    /// # Errors
    /// As [`HalfPlane::visible`]; [`ParamError::NonFinite`] (`theta0`, `len`)
    /// and [`ParamError::OutOfRange`] (`len`) outside `[0, π]`.
    pub fn visible_wrapped(
        &self,
        spheres: &[Sphere<3>],
        max_dist: f64,
        theta0: f64,
        len: f64,
        scratch: &mut [(f64, f64)],
    ) -> Result<f64, ParamError> {
        if !theta0.is_finite() {
            return Err(ParamError::NonFinite { name: "theta0" });
        }
        if !len.is_finite() {
            return Err(ParamError::NonFinite { name: "len" });
        }
        if !(0.0..=PI).contains(&len) {
            return Err(ParamError::OutOfRange {
                name: "len",
                value: len,
                min: 0.0,
                max: PI,
            });
        }
        if len >= PI {
            return self.visible(spheres, max_dist, -FRAC_PI_2, FRAC_PI_2, scratch);
        }
        // θ0 − π·round(θ0/π) ∈ [−π/2, π/2] (one rounding).
        let mut a = theta0 - PI * linesample::num::scalar::round(theta0 / PI);
        if a >= FRAC_PI_2 {
            a -= PI;
        }
        let b = a + len;
        if b <= FRAC_PI_2 {
            return self.visible(spheres, max_dist, a, b, scratch);
        }
        Ok(self.visible(spheres, max_dist, a, FRAC_PI_2, scratch)?
            + self.visible(spheres, max_dist, -FRAC_PI_2, b - PI, scratch)?)
    }
}

/// `∫_a^b |sin t| cos t dt` for `−π/2 ≤ a ≤ b ≤ π/2` (ends clamped to that
/// range; `a ≥ b` gives 0): `sign·sin(b − a)·sin(b + a)/2` when both ends are
/// on one side of 0 (no cancellation, also for a short interval) and
/// `(sin²a + sin²b)/2` across it. Relative error of a few ulp.
#[must_use]
pub fn cosine_weight(a: f64, b: f64) -> f64 {
    let (a, b) = (a.max(-FRAC_PI_2), b.min(FRAC_PI_2));
    if a.is_nan() || b.is_nan() || a >= b {
        return 0.0;
    }
    if a >= 0.0 {
        0.5 * libm::sin(b - a) * libm::sin(b + a)
    } else if b <= 0.0 {
        -0.5 * libm::sin(b - a) * libm::sin(b + a)
    } else {
        let (sa, sb) = (libm::sin(a), libm::sin(b));
        0.5 * (sa * sa + sb * sb)
    }
}

/// The cosine weight ([`cosine_weight`]) of the part of `[t0, t1]` outside
/// the union of `occluded` (any order, overlapping allowed; sorted in place),
/// summed over the visible gaps directly (no subtraction from the total, so a
/// mostly occluded segment keeps its relative accuracy).
pub fn visible_weight(occluded: &mut [(f64, f64)], t0: f64, t1: f64) -> f64 {
    occluded.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
    let mut sum = 0.0;
    let mut at = t0;
    for &(lo, hi) in occluded.iter() {
        if lo > at {
            sum += cosine_weight(at, lo.min(t1));
        }
        at = at.max(hi);
        if at >= t1 {
            return sum;
        }
    }
    sum + cosine_weight(at, t1)
}
