//! Ambient-occlusion estimators at one shading point: points, segments and
//! lines in the half-plane parameterisation, for each centre density.
//!
//! With the azimuth `φ ∈ [0, π)` naming the half-plane through the normal
//! and the signed polar angle `θ ∈ (−π/2, π/2)` a direction in it (the
//! crate's [conventions](crate#conventions)), every direction of the
//! hemisphere is named once and `dω = |sin θ| dθ dφ`, so
//!
//! ```text
//! AO = (1/π) ∫_0^π dφ ∫ V(φ, θ) |sin θ| cos θ dθ = ∫∫ g,   g = V|sin θ|cos θ/π.
//! ```
//!
//! A sample `(u, v) ∈ [0, 1)²` gives `φ = πu` and a centre `θ_c` from `v`
//! by the inverse CDF of the chosen centre density `p_θ` (the joint density
//! is `p = p_θ/π`):
//!
//! * uniform: `θ = π(v − ½)`, `p_θ = 1/π`;
//! * solid angle: `s = 2v − 1`, `|θ| = acos(1 − |s|)` with the sign of `s`,
//!   `p_θ = |sin θ|/2` (`p = |sin θ|/2π`, uniform over the hemisphere's `2π`);
//! * cosine: `|θ| = asin √|s|`, `p_θ = |sin θ| cos θ` (`∫ = 1`).
//!
//! The point estimate is `g(φ, θ)/p`; a segment of length `ℓ` in `θ`
//! centred at `θ_c` (wrapping with period `π`, so `ℓ = π` is the whole line)
//! gives `[(1/ℓ) ∫_{θ_c−ℓ/2}^{θ_c+ℓ/2} g dt]/p(φ, θ_c)`, unbiased because
//! every `t` is covered by the centres within `ℓ/2` of it, of total measure
//! `ℓ`; a line uses `u` only and gives `∫ g dθ · π = ∫ V|sin θ|cos θ dθ`.
//! The visible measures are the closed forms of [`crate::occlusion`]
//! ([`HalfPlane::visible_wrapped`]).
//!
//! The solid-angle and cosine densities with a segment divide by
//! `p_θ(θ_c)`, which is 0 at the normal while the segment's mean is not: the
//! estimate has infinite (log-divergent) variance, visible for long segments
//! (the pitfall the scene report shows).

use core::f64::consts::{FRAC_PI_2, PI};
use linesample::world::Sphere;
use linesample::ParamError;

use crate::HalfPlane;

#[cfg(feature = "theory")]
pub mod theory;
#[cfg(feature = "alloc")]
pub mod world;

/// The density of the sample centres over the hemisphere, `p_θ` above.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum CentrePdf {
    /// Uniform in `(φ, θ)`.
    Uniform,
    /// Uniform in solid angle.
    SolidAngle,
    /// Cosine-weighted.
    Cosine,
}

impl CentrePdf {
    /// The name a scene file uses.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            CentrePdf::Uniform => "uniform",
            CentrePdf::SolidAngle => "solid-angle",
            CentrePdf::Cosine => "cosine",
        }
    }
}

/// What one sample is: a point `(φ, θ_c)`, a segment of length `ℓ` in `θ`
/// centred at `θ_c`, or the whole line (half-plane) at `φ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sample {
    /// A point.
    Point,
    /// A segment of length `length` in `(0, π]` (`π`: the whole line,
    /// wrapped).
    Segment {
        /// `ℓ`.
        length: f64,
    },
    /// The whole line: `u` only.
    Line,
}

/// One AO estimator: its sample and the density of the sample centres
/// (points and segments; a line has none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AoEstimator {
    /// Point, segment or line.
    pub sample: Sample,
    /// Density of the sample centres.
    pub pdf: CentrePdf,
}

/// The shading point: the point, its unit normal, and a tangent from which
/// azimuths are measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// The shading point.
    pub point: [f64; 3],
    /// Its unit normal.
    pub normal: [f64; 3],
    /// A direction not parallel to the normal (`φ = 0` is its projection).
    pub tangent: [f64; 3],
    /// The half-plane at `φ = 0` ([`HalfPlane::new`]), from which every
    /// azimuth's is [`HalfPlane::rotated`]; `None` for a degenerate normal.
    pub base: Option<HalfPlane>,
}

impl Frame {
    /// The frame at `point` with `normal`, the tangent chosen from the axis
    /// least aligned with it.
    #[must_use]
    pub fn new(point: [f64; 3], normal: [f64; 3]) -> Self {
        let tangent = if libm::fabs(normal[0]) < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        Self {
            point,
            normal,
            tangent,
            base: HalfPlane::new(point, normal, tangent).ok(),
        }
    }
}

/// `(θ, p_θ(θ))` for the centre coordinate `v ∈ [0, 1)` under `pdf`.
#[must_use]
pub fn centre_theta(pdf: CentrePdf, v: f64) -> (f64, f64) {
    match pdf {
        CentrePdf::Uniform => (PI * (v - 0.5), 1.0 / PI),
        CentrePdf::SolidAngle => {
            let s = 2.0 * v - 1.0;
            let a = libm::acos((1.0 - libm::fabs(s)).clamp(-1.0, 1.0));
            let t = libm::copysign(a, s);
            (t, 0.5 * libm::fabs(libm::sin(t)))
        }
        CentrePdf::Cosine => {
            let s = 2.0 * v - 1.0;
            let a = libm::asin(libm::sqrt(libm::fabs(s)).min(1.0));
            let t = libm::copysign(a, s);
            (t, libm::fabs(libm::sin(t)) * libm::cos(t))
        }
    }
}

/// The estimate of one sample `(u, v)`: see the module documentation.
/// `scratch` holds at least `2·spheres.len()` intervals.
///
/// Where the centre density is 0 (the solid-angle and cosine densities at
/// `θ_c = 0`, the cosine density at `θ_c = ±π/2`: `v` exactly `½`, `0` or
/// `1`) both a point and a segment give 0. That set has measure zero, so
/// the estimator's expectation is unchanged, and no pattern value can make
/// an estimate non-finite (a segment divided by the vanishing density gave
/// `+∞`, which discarded a whole pixel study). Near those points the
/// segment estimate stays finite but unbounded (at most about `10⁴` for
/// `f32` offsets, whose distance from `½` is at least `2⁻²⁵`): the
/// solid-angle and cosine × segment estimators have infinite variance
/// because of that neighbourhood, and the studies report them as such.
///
/// # Errors
/// [`ParamError::ZeroDirection`] for a degenerate frame (a zero or
/// non-finite normal), and the kernel's error for a too-short `scratch`.
pub fn sample(
    spheres: &[Sphere<3>],
    max_distance: f64,
    frame: &Frame,
    est: &AoEstimator,
    u: f64,
    v: f64,
    scratch: &mut [(f64, f64)],
) -> Result<f64, ParamError> {
    let hp = frame.base.ok_or(ParamError::ZeroDirection)?.rotated(PI * u);
    let vis = |t0: f64, len: f64, s: &mut [(f64, f64)]| {
        hp.visible_wrapped(spheres, max_distance, t0, len, s)
    };
    match est.sample {
        Sample::Line => vis(-FRAC_PI_2, PI, scratch),
        Sample::Point => {
            let (t, pt) = centre_theta(est.pdf, v);
            if pt <= 0.0 {
                // The density vanishes only where g does (θ = 0 for the
                // solid-angle and cosine densities, ±π/2 for the cosine one).
                return Ok(0.0);
            }
            let g = libm::fabs(libm::sin(t)) * libm::cos(t) / PI;
            let visible = hp.sees(spheres, max_distance, t);
            Ok(if visible { g / (pt / PI) } else { 0.0 })
        }
        Sample::Segment { length: len } => {
            let (t, pt) = centre_theta(est.pdf, v);
            if pt <= 0.0 {
                // A measure-zero set of centres: see the function's docs.
                return Ok(0.0);
            }
            let m = vis(t - 0.5 * len, len, scratch)? / (PI * len);
            if m == 0.0 {
                return Ok(0.0);
            }
            Ok(m / (pt / PI))
        }
    }
}
