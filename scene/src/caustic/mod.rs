//! Volumetric caustics: light from a point source, focused by a glass ball
//! into a homogeneous medium, scored in a query ball `Q` by **photon points**
//! and **photon beams** (Jarosz, Nowrouzezahrai, Sadeghi & Jensen 2011; the
//! third application of Singh, Miller & Jarosz 2017).
//!
//! Only this effect is simulated: emission into a cone, exact refraction
//! through the ball (Snell's law; Fresnel reflection and internal
//! reflections when asked for), free flight in the medium outside the ball,
//! and the power scattered inside `Q`. The ball's interior is clear glass
//! (no medium); the medium fills the rest of space.
//!
//! # The path of a photon
//!
//! [`Caustic::trace`] turns an emission direction into a [`PhotonPath`]: a
//! few rays ([`Segment`]s) in the medium, each with its **medium offset**
//! `τ` (the medium distance travelled before its origin), its length `L`
//! (finite only for the first, which ends where it enters the ball) and its
//! weight `w` (the fraction of the photon's power it carries):
//!
//! 1. the emitted ray, `τ = 0`, weight 1, up to the ball (or to infinity if
//!    it misses the ball);
//! 2. with Fresnel: the ray reflected at the entry point, weight `R₁`;
//! 3. the refracted ray crosses the ball and leaves it with weight `T₁T₂`
//!    (Fresnel) or 1 (no Fresnel); with Fresnel its internally reflected
//!    part (`T₁R₂`) crosses the ball again and leaves with `T₁R₂T₂`, and so
//!    on for `k ≤ K` internal reflections (`K` given; the power left inside
//!    after the last one, `T₁R₂^{K+1}`, is dropped).
//!
//! All rays after the first start at `τ = L₁` (the glass has no medium).
//! Inside a ball, every internal chord meets the surface at the same angle
//! as the refracted ray, so `R₂ = R₁` (Fresnel reflectance is reciprocal)
//! and total internal reflection cannot happen for `n ≥ 1`; the weights sum
//! to `1 − T₁R₁^{K+1}` (tested).
//!
//! # The two estimators (per unit emitted power)
//!
//! With `σ_t = σ_s + σ_a`, the power scattered in `Q` is
//! `Φ_Q = Σ_k w_k σ_s ∫_{seg k} e^{−σ_t t} 1[x_k(t) ∈ Q] dt`
//! (`t` the medium distance).
//!
//! * **Photon points** ([`Caustic::point`]): one free-flight distance
//!   `t = −ln(1 − s)/σ_t` for `s ∈ [0, 1)` (density `σ_t e^{−σ_t t}`), and the
//!   score `(σ_s/σ_t) Σ_k w_k 1[τ_k ≤ t < τ_k + L_k] 1[x_k(t) ∈ Q]`: every
//!   branch of the path is a photon with the same `t` (splitting, not Russian
//!   roulette, so the sample dimension stays `d` and each branch is unbiased).
//! * **Photon beams** ([`Caustic::beam`]): the expectation over `s` in closed
//!   form. For each chord `[a, b]` of segment `k` inside `Q` (clipped to the
//!   segment), `(σ_s/σ_t) w_k e^{−σ_t(τ_k + a)} (1 − e^{−σ_t(b − a)})`. A beam
//!   is a line sample along the distance axis with a `(d − 1)`-dimensional
//!   offset (the emission angles).
//!
//! # Error bound of the beam closed form
//!
//! For the given segment rays, the chord `(a, b − a)` comes from
//! [`Sphere::hit`] and [`Sphere::segment`]: both relatively accurate to a few
//! ulp, down to grazing chords (`b − a` is never a difference of two rounded
//! ends, see [`linesample::world::sphere`]). `1 − e^{−x}` is `−expm1(−x)` (no
//! cancellation for short chords). The exponent `σ_t(τ + a)` carries an
//! absolute error of about `3u·σ_t(τ + a)`, so each term is relatively
//! accurate to about `(12 + 3σ_t(τ + a))·u` (`u = 2⁻⁵³`); the terms are
//! positive, so the sum keeps that bound. The tests check `≤ 1e−12` relative
//! against quadrature at 50 digits, including chords grazing `Q` to
//! `1 − d/r = 10⁻¹²`, chords cut by the ball, a light inside `Q`, and beams
//! that miss the ball.
//!
//! The directions themselves are rounded: a whole path agrees with an
//! exact trace to about `10⁻¹⁵/cos θᵢ` in direction and weight (`θᵢ` the
//! angle of incidence on the ball: its cosine `−n·d` is known only to
//! `≈ 10⁻¹⁶` absolute, from the rounded entry point). Every exit reuses the
//! entry's `cos θᵢ` and `R` (the ball's symmetry) instead of forming
//! `1 − n² sin²θ₂`, which would cancel near grazing. The beam value inherits
//! the direction error times its condition number, which is large only for
//! rays nearly tangent to `Q` or to the ball.

// `!(x > y)` is deliberate below: it also catches NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use linesample::geom::{dot, Direction};
use linesample::num::scalar::sqrt;
use linesample::world::{check_dim, check_finite, check_range};
use linesample::world::{Ray, Sphere};
use linesample::ParamError;

#[cfg(feature = "alloc")]
pub mod world;

/// The largest number of internal reflections [`Caustic::new`] accepts.
pub const MAX_INTERNAL_REFLECTIONS: u32 = 8;

/// The most segments a [`PhotonPath`] holds: the emitted ray, the ray
/// reflected at the entry, and one exit per internal reflection plus one.
pub const MAX_SEGMENTS: usize = 3 + MAX_INTERNAL_REFLECTIONS as usize;

/// A homogeneous medium: scattering and absorption coefficients `σ_s, σ_a`
/// (per unit length), extinction `σ_t = σ_s + σ_a`, albedo `σ_s/σ_t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    sigma_s: f64,
    sigma_a: f64,
    sigma_t: f64,
}

impl Medium {
    /// The medium with `σ_s, σ_a ∈ [0, 10¹⁰⁰]` and `σ_t = σ_s + σ_a ≥ 10⁻¹⁰⁰`.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] or [`ParamError::OutOfRange`] naming
    /// `sigma_s`, `sigma_a` or `sigma_t`.
    pub fn new(sigma_s: f64, sigma_a: f64) -> Result<Self, ParamError> {
        let sigma_s = check_range("sigma_s", sigma_s, 0.0, 1e100)?;
        let sigma_a = check_range("sigma_a", sigma_a, 0.0, 1e100)?;
        let sigma_t = check_range("sigma_t", sigma_s + sigma_a, 1e-100, 2e100)?;
        Ok(Self {
            sigma_s,
            sigma_a,
            sigma_t,
        })
    }

    /// `σ_s`.
    #[must_use]
    pub fn sigma_s(&self) -> f64 {
        self.sigma_s
    }

    /// `σ_a`.
    #[must_use]
    pub fn sigma_a(&self) -> f64 {
        self.sigma_a
    }

    /// `σ_t = σ_s + σ_a`.
    #[must_use]
    pub fn sigma_t(&self) -> f64 {
        self.sigma_t
    }

    /// The free-flight distance `t = −ln(1 − s)/σ_t` of a uniform `s ∈ [0, 1)`
    /// (inverse of the CDF `1 − e^{−σ_t t}`; `ln(1 − s)` as `log1p(−s)`).
    #[must_use]
    pub fn free_flight(&self, s: f64) -> f64 {
        -libm::log1p(-s) / self.sigma_t
    }
}

/// A point light emitting uniformly into a cone: uniform in angle in 2D,
/// uniform in solid angle in 3D.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeEmitter<const D: usize> {
    position: [f64; D],
    axis: [f64; D],
    /// 3D: two unit vectors completing `axis` to an orthonormal basis.
    e1: [f64; D],
    e2: [f64; D],
    half_angle: f64,
    /// `1 − cos α = 2 sin²(α/2)` (no cancellation for narrow cones).
    one_minus_cos: f64,
}

impl<const D: usize> ConeEmitter<D> {
    /// A point light at `position` emitting into the cone of half-angle
    /// `half_angle ∈ [10⁻¹², π]` (radians) around `axis` (any non-zero vector).
    ///
    /// # Errors
    /// [`ParamError::Dimension`] unless `D ∈ {2, 3}`; [`ParamError::NonFinite`]
    /// (`position`, `axis`), [`ParamError::ZeroDirection`] (`axis`),
    /// [`ParamError::OutOfRange`] (`half_angle`).
    pub fn new(
        position: impl Into<[f64; D]>,
        axis: impl Into<[f64; D]>,
        half_angle: f64,
    ) -> Result<Self, ParamError> {
        check_dim::<D>()?;
        let position = position.into();
        check_finite("position", &position)?;
        let axis = axis.into();
        check_finite("axis", &axis)?;
        let axis = Direction::new(axis)?.get();
        let half_angle = check_range("half_angle", half_angle, 1e-12, core::f64::consts::PI)?;
        let (mut e1, mut e2) = ([0.0; D], [0.0; D]);
        if D == 2 {
            e1[0] = -axis[1];
            e1[1] = axis[0];
        } else {
            // Duff et al. 2017, "Building an orthonormal basis, revisited".
            let (x, y, z) = (axis[0], axis[1], axis[2]);
            let sign = 1.0f64.copysign(z);
            let a = -1.0 / (sign + z);
            let b = x * y * a;
            e1[0] = 1.0 + sign * x * x * a;
            e1[1] = sign * b;
            e1[2] = -sign * x;
            e2[0] = b;
            e2[1] = sign + y * y * a;
            e2[2] = -y;
        }
        let sh = libm::sin(0.5 * half_angle);
        Ok(Self {
            position,
            axis,
            e1,
            e2,
            half_angle,
            one_minus_cos: 2.0 * sh * sh,
        })
    }

    /// The light's position.
    #[must_use]
    pub fn position(&self) -> [f64; D] {
        self.position
    }

    /// The unit cone axis.
    #[must_use]
    pub fn axis(&self) -> [f64; D] {
        self.axis
    }

    /// The half-angle `α` (radians).
    #[must_use]
    pub fn half_angle(&self) -> f64 {
        self.half_angle
    }

    /// The measure of the cone: `2α` (radians, 2D) or `2π(1 − cos α)`
    /// (steradians, 3D). An isotropic source of intensity `I` puts
    /// `I` times this into the cone.
    #[must_use]
    pub fn measure(&self) -> f64 {
        if D == 2 {
            2.0 * self.half_angle
        } else {
            2.0 * core::f64::consts::PI * self.one_minus_cos
        }
    }

    /// The unit emission direction of the primary sample `u ∈ [0, 1)²`:
    /// 2D, `θ = α(2u₀ − 1)` from the axis (`u₁` unused); 3D,
    /// `cos θ = 1 − u₀(1 − cos α)`, `φ = 2πu₁` (uniform in solid angle).
    #[must_use]
    pub fn direction(&self, u: [f64; 2]) -> [f64; D] {
        let mut d = [0.0; D];
        if D == 2 {
            let th = self.half_angle * (2.0 * u[0] - 1.0);
            let (s, c) = (libm::sin(th), libm::cos(th));
            for j in 0..D {
                d[j] = c * self.axis[j] + s * self.e1[j];
            }
        } else {
            let v = u[0] * self.one_minus_cos;
            let cos_t = 1.0 - v;
            let sin_t = sqrt((v * (2.0 - v)).max(0.0));
            let phi = 2.0 * core::f64::consts::PI * u[1];
            let (sp, cp) = (libm::sin(phi), libm::cos(phi));
            for j in 0..D {
                d[j] = cos_t * self.axis[j] + sin_t * (cp * self.e1[j] + sp * self.e2[j]);
            }
        }
        d
    }
}

/// A glass ball (`D = 3`) or disk (`D = 2`) of refractive index `n` relative
/// to the medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Glass<const D: usize> {
    ball: Sphere<D>,
    ior: f64,
}

impl<const D: usize> Glass<D> {
    /// The ball of `centre` and `radius` with index `ior ∈ [1, 10]`.
    ///
    /// # Errors
    /// The [`Sphere::new`] errors (`centre`, `radius`), and
    /// [`ParamError::OutOfRange`] (`ior`).
    pub fn new(centre: impl Into<[f64; D]>, radius: f64, ior: f64) -> Result<Self, ParamError> {
        let ball = Sphere::new(centre, radius)?;
        let ior = check_range("ior", ior, 1.0, 10.0)?;
        Ok(Self { ball, ior })
    }

    /// The ball.
    #[must_use]
    pub fn ball(&self) -> &Sphere<D> {
        &self.ball
    }

    /// The refractive index.
    #[must_use]
    pub fn ior(&self) -> f64 {
        self.ior
    }
}

/// Whether Fresnel reflection is modelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fresnel {
    /// Every photon refracts into the ball and out of it (weight 1): the
    /// classic "refraction only" caustic.
    Off,
    /// Unpolarised Fresnel reflectance ([`fresnel_reflectance`]) at each
    /// interface: the ray reflected at the entry is followed, and up to
    /// `internal_reflections` internal reflections (each leaving a ray).
    On {
        /// `K ≤` [`MAX_INTERNAL_REFLECTIONS`].
        internal_reflections: u32,
    },
}

/// One ray of a photon's path in the medium: `ray.at(t − start)` for medium
/// distances `t ∈ [start, start + length)`, carrying `weight` of the
/// photon's power.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment<const D: usize> {
    /// Origin and unit direction.
    pub ray: Ray<D>,
    /// Medium distance travelled before the origin (`τ`).
    pub start: f64,
    /// Length (`+∞` for a ray that leaves for good).
    pub length: f64,
    /// Fraction of the photon's power.
    pub weight: f64,
}

/// A photon's path: at most [`MAX_SEGMENTS`] segments, no allocation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhotonPath<const D: usize> {
    segs: [Segment<D>; MAX_SEGMENTS],
    len: usize,
}

impl<const D: usize> PhotonPath<D> {
    /// A path of the given segments (to score a path built elsewhere, e.g.
    /// by a renderer's own tracer).
    ///
    /// # Errors
    /// [`ParamError::Length`] (`segments`) for none or more than
    /// [`MAX_SEGMENTS`]; [`ParamError::NonFinite`] or
    /// [`ParamError::OutOfRange`] for a negative or NaN `start`, `length` or
    /// `weight`.
    pub fn new(segments: &[Segment<D>]) -> Result<Self, ParamError> {
        if segments.is_empty() || segments.len() > MAX_SEGMENTS {
            return Err(ParamError::Length {
                name: "segments",
                expected: MAX_SEGMENTS,
                got: segments.len(),
            });
        }
        for g in segments {
            check_range("start", g.start, 0.0, f64::MAX)?;
            if !(g.length >= 0.0) {
                return Err(ParamError::OutOfRange {
                    name: "length",
                    value: g.length,
                    min: 0.0,
                    max: f64::INFINITY,
                });
            }
            check_range("weight", g.weight, 0.0, f64::MAX)?;
        }
        let mut segs = [segments[0]; MAX_SEGMENTS];
        segs[..segments.len()].copy_from_slice(segments);
        Ok(Self {
            segs,
            len: segments.len(),
        })
    }

    /// The segments, the emitted ray first.
    #[must_use]
    pub fn segments(&self) -> &[Segment<D>] {
        &self.segs[..self.len]
    }

    /// Whether the emitted ray hit the glass.
    #[must_use]
    pub fn hit_glass(&self) -> bool {
        self.len > 1
    }

    /// The sum of the weights of the rays leaving for good (all but a first
    /// one that ends at the glass): 1 without Fresnel, `1 − T₁R^{K+1}` with.
    #[must_use]
    pub fn escaping_weight(&self) -> f64 {
        let s = self.segments();
        if s.len() == 1 {
            s[0].weight
        } else {
            s[1..].iter().map(|g| g.weight).sum()
        }
    }

    fn push(&mut self, s: Segment<D>) {
        if self.len < MAX_SEGMENTS {
            self.segs[self.len] = s;
            self.len += 1;
        }
    }
}

#[inline]
fn normalise<const D: usize>(v: [f64; D]) -> [f64; D] {
    let inv = 1.0 / sqrt(dot(&v, &v));
    core::array::from_fn(|j| v[j] * inv)
}

/// Snell's law in vector form: the unit refracted direction of the unit
/// incident direction `d` at a surface with unit normal `n` on the incident
/// side (`n·d < 0`), `eta = n₁/n₂`:
/// `t = η d + (η cos θᵢ − cos θₜ) n` with `cos θᵢ = −n·d`,
/// `cos θₜ = √(1 − η²(1 − cos²θᵢ))` (Glassner 1989; Pharr, Jakob & Humphreys,
/// *PBRT* 4th ed. §9.3). `None` under total internal reflection.
/// `1 − cos²θᵢ` is formed as `(1 − c)(1 + c)`; the result is renormalised.
#[must_use]
pub fn refract<const D: usize>(d: &[f64; D], n: &[f64; D], eta: f64) -> Option<[f64; D]> {
    let ci = -dot(n, d);
    let sin2_i = ((1.0 - ci) * (1.0 + ci)).max(0.0);
    let sin2_t = eta * eta * sin2_i;
    if sin2_t > 1.0 {
        return None;
    }
    Some(refracted(d, n, eta, ci, sqrt(1.0 - sin2_t)))
}

/// [`refract`] with both cosines known: `η d + (η cos θᵢ − cos θₜ) n`,
/// renormalised.
fn refracted<const D: usize>(d: &[f64; D], n: &[f64; D], eta: f64, ci: f64, ct: f64) -> [f64; D] {
    let k = eta * ci - ct;
    normalise(core::array::from_fn(|j| eta * d[j] + k * n[j]))
}

/// Mirror reflection of the unit direction `d` about the unit normal `n`:
/// `d − 2(n·d) n`.
#[must_use]
pub fn reflect<const D: usize>(d: &[f64; D], n: &[f64; D]) -> [f64; D] {
    let k = 2.0 * dot(n, d);
    normalise(core::array::from_fn(|j| d[j] - k * n[j]))
}

/// Unpolarised Fresnel reflectance of a smooth dielectric interface for
/// light arriving at `cos θᵢ = cos_i ∈ [0, 1]` from index `n₁` onto `n₂`,
/// `eta = n₁/n₂`: `R = (r_s² + r_p²)/2` with
/// `r_s = (η cos θᵢ − cos θₜ)/(η cos θᵢ + cos θₜ)`,
/// `r_p = (cos θᵢ − η cos θₜ)/(cos θᵢ + η cos θₜ)` (Fresnel's equations divided
/// by `n₂`; Born & Wolf §1.5.2), and 1 under total internal reflection.
/// (In flatland the same unpolarised average is used.)
#[must_use]
pub fn fresnel_reflectance(cos_i: f64, eta: f64) -> f64 {
    let ci = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - ci) * (1.0 + ci);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let ct = sqrt(1.0 - sin2_t);
    let rs = (eta * ci - ct) / (eta * ci + ct);
    let rp = (ci - eta * ct) / (ci + eta * ct);
    0.5 * (rs * rs + rp * rp)
}

/// A volumetric-caustic scene: a cone light, a glass ball, a medium and a
/// query ball `Q`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Caustic<const D: usize> {
    light: ConeEmitter<D>,
    glass: Glass<D>,
    medium: Medium,
    query: Sphere<D>,
    fresnel: Fresnel,
}

impl<const D: usize> Caustic<D> {
    /// The scene. The light must be outside the glass (strictly).
    ///
    /// # Errors
    /// [`ParamError::OutOfRange`] naming `position` (the light inside or on
    /// the glass) or `internal_reflections` (more than
    /// [`MAX_INTERNAL_REFLECTIONS`]).
    pub fn new(
        light: ConeEmitter<D>,
        glass: Glass<D>,
        medium: Medium,
        query: Sphere<D>,
        fresnel: Fresnel,
    ) -> Result<Self, ParamError> {
        let p = light.position();
        let c = glass.ball.centre();
        let q: [f64; D] = core::array::from_fn(|j| p[j] - c[j]);
        let dist = sqrt(dot(&q, &q));
        if dist <= glass.ball.radius() * (1.0 + 1e-12) {
            return Err(ParamError::OutOfRange {
                name: "position",
                value: dist,
                min: glass.ball.radius(),
                max: f64::INFINITY,
            });
        }
        if let Fresnel::On {
            internal_reflections,
        } = fresnel
        {
            if internal_reflections > MAX_INTERNAL_REFLECTIONS {
                return Err(ParamError::OutOfRange {
                    name: "internal_reflections",
                    value: f64::from(internal_reflections),
                    min: 0.0,
                    max: f64::from(MAX_INTERNAL_REFLECTIONS),
                });
            }
        }
        Ok(Self {
            light,
            glass,
            medium,
            query,
            fresnel,
        })
    }

    /// The light.
    #[must_use]
    pub fn light(&self) -> &ConeEmitter<D> {
        &self.light
    }

    /// The glass.
    #[must_use]
    pub fn glass(&self) -> &Glass<D> {
        &self.glass
    }

    /// The medium.
    #[must_use]
    pub fn medium(&self) -> &Medium {
        &self.medium
    }

    /// The query ball `Q`.
    #[must_use]
    pub fn query(&self) -> &Sphere<D> {
        &self.query
    }

    /// The Fresnel model.
    #[must_use]
    pub fn fresnel(&self) -> Fresnel {
        self.fresnel
    }

    /// The path of the photon emitted along the unit direction `dir` (see the
    /// [module docs](self)).
    #[must_use]
    pub fn trace(&self, dir: [f64; D]) -> PhotonPath<D> {
        let origin = self.light.position();
        let ray0 = Ray::from_parts(origin, Direction::from_unit(dir));
        let mut path = PhotonPath {
            segs: [Segment {
                ray: ray0,
                start: 0.0,
                length: f64::INFINITY,
                weight: 1.0,
            }; MAX_SEGMENTS],
            len: 1,
        };
        let ball = &self.glass.ball;
        let Some((t_in, _)) = ball.hit(&ray0) else {
            return path;
        };
        if !(t_in > 0.0) {
            // Behind the light (the light is outside the ball).
            return path;
        }
        let c = ball.centre();
        let inv_r = 1.0 / ball.radius();
        // The unit normal at a computed surface point, or `None` when the
        // point is not on the sphere to within a factor √2 of the radius: the
        // scene's scale hides the ball from `f64` (a light 10³² away from a
        // ball of radius 10⁻⁸ puts the "hit" point 10¹⁶ radii off it), and the
        // photon cannot be traced through it. On resolvable scenes
        // `|p − c|/r` is 1 to within the rounding of `p`.
        let normal = |p: &[f64; D]| {
            let v: [f64; D] = core::array::from_fn(|j| (p[j] - c[j]) * inv_r);
            let s = dot(&v, &v);
            if (0.5..=2.0).contains(&s) {
                Some(normalise(v))
            } else {
                None
            }
        };
        let mut p = ray0.at(t_in);
        let Some(n1) = normal(&p) else {
            // Unresolvable: the photon passes the ball untouched.
            return path;
        };
        path.segs[0].length = t_in;
        let cos1 = -dot(&n1, &dir);
        let eta_in = 1.0 / self.glass.ior;
        let (k_max, r1) = match self.fresnel {
            Fresnel::Off => (0, 0.0),
            Fresnel::On {
                internal_reflections,
            } => (internal_reflections, fresnel_reflectance(cos1, eta_in)),
        };
        if r1 > 0.0 {
            path.push(Segment {
                ray: Ray::from_parts(p, Direction::from_unit(reflect(&dir, &n1))),
                start: t_in,
                length: f64::INFINITY,
                weight: r1,
            });
        }
        // n ≥ 1: no total internal reflection on the way in.
        let Some(mut d) = refract(&dir, &n1, eta_in) else {
            return path;
        };
        let mut w = 1.0 - r1;
        for k in 0..=k_max {
            // Chord through the ball from a point on its surface: the far root.
            let inside = Ray::from_parts(p, Direction::from_unit(d));
            let t_out = match ball.hit(&inside) {
                Some((_, t)) if t > 0.0 => t,
                // Rounding put p just outside, on the far side of a tangent: stop.
                _ => break,
            };
            p = inside.at(t_out);
            let Some(n2) = normal(&p) else {
                // Unresolvable exit point (see `normal`): stop, as above.
                break;
            };
            let inward: [f64; D] = core::array::from_fn(|j| -n2[j]);
            let cos2 = dot(&n2, &d);
            // The ball's symmetry: the ray leaves at the angle it entered
            // (cos θₒ = cos θᵢ, no cancellation in 1 − n² sin²θ₂ near
            // grazing), and R₂ = R₁ (reciprocity).
            let out = refracted(&d, &inward, self.glass.ior, cos2, cos1);
            path.push(Segment {
                ray: Ray::from_parts(p, Direction::from_unit(out)),
                start: t_in,
                length: f64::INFINITY,
                weight: w * (1.0 - r1),
            });
            w *= r1;
            if k == k_max || !(w > 0.0) {
                break;
            }
            d = reflect(&d, &n2);
        }
        path
    }

    /// The path of the photon of primary sample `u` (see
    /// [`ConeEmitter::direction`]).
    #[must_use]
    pub fn path(&self, u: [f64; 2]) -> PhotonPath<D> {
        self.trace(self.light.direction(u))
    }

    /// The **beam** estimate of a path: `(σ_s/σ_t) Σ_k w_k e^{−σ_t(τ_k + a_k)}
    /// (1 − e^{−σ_t(b_k − a_k)})` over the chords `[a_k, b_k]` of its segments
    /// inside `Q` (see the [module docs](self) for the error bound).
    #[must_use]
    pub fn beam(&self, path: &PhotonPath<D>) -> f64 {
        let st = self.medium.sigma_t;
        let mut sum = 0.0;
        for s in path.segments() {
            let Some((tm, tp)) = self.query.hit(&s.ray) else {
                continue;
            };
            let lo = tm.max(0.0);
            if !(tp.min(s.length) > lo) {
                continue;
            }
            let width = self.query.segment(&s.ray, 0.0, s.length);
            if !(width > 0.0) {
                continue;
            }
            sum += s.weight * libm::exp(-st * (s.start + lo)) * -libm::expm1(-st * width);
        }
        sum * (self.medium.sigma_s / st)
    }

    /// The **point** estimate of a path with free-flight sample `s ∈ [0, 1)`:
    /// `t = −ln(1 − s)/σ_t`, score `(σ_s/σ_t) Σ_k w_k 1[τ_k ≤ t < τ_k + L_k]
    /// 1[x_k(t) ∈ Q]`. Its expectation over `s` is [`Caustic::beam`].
    #[must_use]
    pub fn point(&self, path: &PhotonPath<D>, s: f64) -> f64 {
        let t = self.medium.free_flight(s);
        let mut sum = 0.0;
        for g in path.segments() {
            if t >= g.start && t - g.start < g.length && self.query.contains(&g.ray.at(t - g.start))
            {
                sum += g.weight;
            }
        }
        sum * (self.medium.sigma_s / self.medium.sigma_t)
    }

    /// [`Caustic::beam`] of the photon of primary sample `u`.
    #[must_use]
    pub fn beam_sample(&self, u: [f64; 2]) -> f64 {
        self.beam(&self.path(u))
    }

    /// [`Caustic::point`] of the photon of primary sample `(u, s)`.
    #[must_use]
    pub fn point_sample(&self, u: [f64; 2], s: f64) -> f64 {
        self.point(&self.path(u), s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene2(fresnel: Fresnel) -> Caustic<2> {
        Caustic::new(
            ConeEmitter::new([0.0, 2.0], [0.0, -1.0], 0.3).unwrap(),
            Glass::new([0.0, 0.0], 0.5, 1.5).unwrap(),
            Medium::new(0.5, 0.1).unwrap(),
            Sphere::new([0.05, -1.0], 0.1).unwrap(),
            fresnel,
        )
        .unwrap()
    }

    #[test]
    fn fresnel_is_reciprocal_and_weights_add_up() {
        let k = 3;
        let c = scene2(Fresnel::On {
            internal_reflections: k,
        });
        for i in 0..100 {
            let u = [(f64::from(i) + 0.5) / 100.0, 0.0];
            let p = c.path(u);
            if !p.hit_glass() {
                assert_eq!(p.escaping_weight(), 1.0);
                continue;
            }
            let r1 = p.segments()[1].weight;
            let t1 = 1.0 - r1;
            let want = 1.0 - t1 * r1.powi(k as i32 + 1);
            assert!((p.escaping_weight() - want).abs() < 1e-14, "{i}");
        }
    }

    #[test]
    fn rejects_bad_input() {
        assert!(Medium::new(f64::NAN, 0.0).is_err());
        assert!(Medium::new(0.0, 0.0).is_err());
        assert!(ConeEmitter::<2>::new([0.0, 0.0], [0.0, 0.0], 0.1).is_err());
        assert!(ConeEmitter::<2>::new([0.0, 0.0], [0.0, 1.0], 0.0).is_err());
        assert!(Glass::<2>::new([0.0, 0.0], 1.0, 0.9).is_err());
        let inside = Caustic::new(
            ConeEmitter::new([0.0, 0.2], [0.0, -1.0], 0.3).unwrap(),
            Glass::new([0.0, 0.0], 0.5, 1.5).unwrap(),
            Medium::new(0.5, 0.1).unwrap(),
            Sphere::new([0.05, -1.0], 0.1).unwrap(),
            Fresnel::Off,
        );
        assert!(matches!(
            inside,
            Err(ParamError::OutOfRange {
                name: "position",
                ..
            })
        ));
    }
}
