//! World-space closed forms: what a renderer calls along its rays.
//!
//! Every shape here lives in free space `ℝ^D` (`D = 2, 3`), with any centre and
//! a size over a huge range, and integrates along a [`Ray`] `o + t·ω` (unit
//! `ω`, so `t` is arc length) over a parameter interval `[t0, t1]` that may be
//! infinite; the `f32` twins and batches integrate along `o + t·d` with `d`
//! as given (`t` in units of `|d|`, arc length for a unit `d`), as the
//! [crate's conventions](crate#conventions) state for the whole crate:
//!
//! * [`Sphere`]: entry and exit parameters, chord length, the chord clipped to
//!   `[t0, t1]` (the integral of the indicator along a segment);
//! * [`Gaussian`]: the line and segment integral of an isotropic Gaussian
//!   (normalised or with a given peak), its optical depth and transmittance
//!   `exp(−σ_t ∫ρ)` and opacity `1 − exp(−σ_t ∫ρ)`;
//! * [`HalfSpace`] and [`Slab`]: the length of `[t0, t1]` on the kept side of a
//!   plane, or between two parallel planes;
//!
//! The effects built on these shapes (ambient occlusion by spheres, direct
//! light from a rectangular light, volumetric caustics) are the
//! `linesample-scene` crate's (they were `world::{occlusion, occlusion_f32,
//! direct_light, direct_light_f32, caustic}` before 0.2).
//!
//! Each has an exact `f64` path (double-double where cancellation would
//! otherwise lose digits; every method states its error bound) and an `f32`
//! SIMD batch over a structure-of-arrays [`Rays32`] batch whose lanes are bit
//! for bit the `f32` scalar twin, with a stated bound against the `f64` path.
//! The torus integrands of [`crate::integrand`] are periodisations of these
//! forms: [`crate::integrand::Ball`] sums [`Sphere`] chords over the images of
//! the ball, [`crate::integrand::Gaussian`] sums [`Gaussian`] segment
//! integrals, [`crate::integrand::HalfSpace`] intersects [`HalfSpace`] with
//! the unit box's [`Slab`]s. So each shape has one closed form.
//!
//! ```
//! use linesample::world::{Gaussian, Ray, Sphere};
//! let ray = Ray::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?;
//! let s = Sphere::new([0.0, 0.5, 0.0], 1.0)?;
//! let (t_in, t_out) = s.hit(&ray).unwrap();            // 10 ∓ √(1 − 0.5²)
//! assert!((t_in - (10.0 - 0.75f64.sqrt())).abs() <= 1e-15 * t_in);
//! assert!((s.chord(&ray) - 2.0 * 0.75f64.sqrt()).abs() <= 1e-15);
//! // A Gaussian puff of density peak 2 and σ = 0.3, extinction σ_t = 1.5:
//! let g = Gaussian::with_peak([0.0, 0.0, 0.0], 0.3, 2.0)?;
//! let tr = g.transmittance(&ray, 0.0, f64::INFINITY, 1.5);
//! let depth = 1.5 * 2.0 * 0.3 * (2.0 * core::f64::consts::PI).sqrt();
//! assert!((tr - (-depth).exp()).abs() < 1e-15);
//! # Ok::<(), linesample::ParamError>(())
//! ```
//!
//! ## Types
//!
//! `f64` inputs are `impl Into<[f64; D]>` (arrays, or `glam::DVec2`/`DVec3`
//! with the `glam` feature); the scalar `f32` twins take `impl Into<[f32; D]>`
//! (arrays, `glam::Vec2`/`Vec3`/`Vec3A`), which compiles to a plain move. The
//! batches take structure-of-arrays slices ([`Rays32`]): a renderer keeps
//! its ray packets that way for SIMD anyway.
//!
//! The derivations are in `docs/theory.md` (World-space closed forms).

pub mod gaussian;
pub mod plane;
pub mod sphere;

pub use gaussian::Gaussian;
pub use plane::{HalfSpace, Slab};
pub use sphere::Sphere;

pub use crate::geom::Direction;
pub use crate::primitive::Rays32;

use crate::error::ParamError;

/// A ray `o + t·ω` in `ℝ^D` with a finite origin and a unit direction
/// ([`Direction`], normalised at construction), so the parameter `t` is arc
/// length: the `f64` side of the [crate's conventions](crate#conventions)
/// (the `f32` methods take [`Rays32`] or `o`, `d` as given instead).
/// Constructors take anything that converts into `[f64; D]`: arrays, or
/// `glam::DVec2`/`DVec3` (feature `glam`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<const D: usize> {
    origin: [f64; D],
    dir: Direction<D>,
}

impl<const D: usize> Ray<D> {
    /// The ray from `origin` along `dir` (any finite non-zero vector; it is
    /// normalised).
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`origin`, `direction`),
    /// [`ParamError::ZeroDirection`].
    pub fn new(origin: impl Into<[f64; D]>, dir: impl Into<[f64; D]>) -> Result<Self, ParamError> {
        Self::from_direction(origin, Direction::new(dir.into())?)
    }

    /// The ray from `origin` along an already validated direction.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`origin`).
    pub fn from_direction(
        origin: impl Into<[f64; D]>,
        dir: Direction<D>,
    ) -> Result<Self, ParamError> {
        let origin = origin.into();
        if origin.iter().any(|x| !x.is_finite()) {
            return Err(ParamError::NonFinite { name: "origin" });
        }
        Ok(Self { origin, dir })
    }

    /// The ray from `origin` along `dir`, taken as they are (no check): for
    /// callers that build rays from rays (a reflected or refracted photon,
    /// whose origin is a point of a finite path). Use [`Ray::new`] or
    /// [`Ray::from_direction`] for anything else.
    #[inline]
    #[must_use]
    pub fn from_parts(origin: [f64; D], dir: Direction<D>) -> Self {
        Self { origin, dir }
    }

    /// The ray from `from` through `to` (`to ≠ from`); `t = |to − from|` at `to`
    /// up to the rounding of the difference.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`origin`, `direction`: also when `to − from`
    /// overflows), [`ParamError::ZeroDirection`] for `to = from`.
    pub fn through(from: impl Into<[f64; D]>, to: impl Into<[f64; D]>) -> Result<Self, ParamError> {
        let (from, to) = (from.into(), to.into());
        if to.iter().any(|x| !x.is_finite()) {
            return Err(ParamError::NonFinite { name: "to" });
        }
        let d: [f64; D] = core::array::from_fn(|j| to[j] - from[j]);
        Self::new(from, d)
    }

    /// The origin `o`.
    #[inline]
    #[must_use]
    pub fn origin(&self) -> [f64; D] {
        self.origin
    }

    /// The unit direction `ω`.
    #[inline]
    #[must_use]
    pub fn dir(&self) -> Direction<D> {
        self.dir
    }

    /// The point `o + t·ω` (rounded).
    #[inline]
    #[must_use]
    pub fn at(&self, t: f64) -> [f64; D] {
        let w = self.dir.get();
        core::array::from_fn(|j| self.origin[j] + t * w[j])
    }
}

/// Checks `D ∈ {2, 3}`: the parameter checks every world-space constructor
/// applies (here and in crates built on these shapes, such as
/// `linesample-scene`), so that their errors name the parameter alike.
///
/// # Errors
/// [`ParamError::Dimension`].
pub fn check_dim<const D: usize>() -> Result<(), ParamError> {
    if D == 2 || D == 3 {
        Ok(())
    } else {
        Err(ParamError::Dimension { dim: D })
    }
}

/// Checks that every component of `v` is finite.
///
/// # Errors
/// [`ParamError::NonFinite`] naming `name`.
pub fn check_finite<const D: usize>(name: &'static str, v: &[f64; D]) -> Result<(), ParamError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(ParamError::NonFinite { name })
    }
}

/// Checks that `x` is finite and in `[min, max]`, and returns it.
///
/// # Errors
/// [`ParamError::NonFinite`] or [`ParamError::OutOfRange`] naming `name`.
pub fn check_range(name: &'static str, x: f64, min: f64, max: f64) -> Result<f64, ParamError> {
    if !x.is_finite() {
        return Err(ParamError::NonFinite { name });
    }
    if !(min..=max).contains(&x) {
        return Err(ParamError::OutOfRange {
            name,
            value: x,
            min,
            max,
        });
    }
    Ok(x)
}

/// An `f32` closed form along rays `o + t·d`, `t ∈ [t0, t1]`, written once
/// over lane types: the scalar twin (`L = f32`) and the 8-lane batches of
/// [`ray_batch`] (`wide`'s `f32x8`, or AVX2's at run time).
pub(crate) trait RayKernel32<const D: usize> {
    /// The value for each lane's ray.
    fn eval<L: crate::num::lane::F32Lane>(&self, o: [L; D], d: [L; D], t0: L, t1: L) -> L;
}

/// Runs `k` over a ray batch: 8-lane blocks at the [`crate::simd::level`],
/// the tail through the scalar twin (the same bits either way).
///
/// # Errors
/// [`ParamError::Length`] if the slices differ in length.
pub(crate) fn ray_batch<const D: usize, K: RayKernel32<D>>(
    k: &K,
    rays: &Rays32<'_, D>,
    out: &mut [f32],
) -> Result<(), ParamError> {
    let n = rays.check(out.len())?;
    crate::simd::dispatch(RayBatch {
        k,
        rays,
        out: &mut out[..n],
    });
    Ok(())
}

/// [`ray_batch`] as one dispatched call.
struct RayBatch<'a, 'r, const D: usize, K> {
    k: &'a K,
    rays: &'a Rays32<'r, D>,
    out: &'a mut [f32],
}

impl<const D: usize, K: RayKernel32<D>> crate::simd::Kernel for RayBatch<'_, '_, D, K> {
    type Output = ();
    #[inline(always)]
    fn run<I: crate::simd::Isa>(self) {
        use crate::num::lane::Lane;
        let (rays, out) = (self.rays, self.out);
        let n = out.len();
        let w = <I::F32 as Lane>::LANES;
        let mut i = 0;
        while i + w <= n {
            let o: [I::F32; D] = core::array::from_fn(|j| Lane::load(&rays.origin[j][i..]));
            let d: [I::F32; D] = core::array::from_fn(|j| Lane::load(&rays.dir[j][i..]));
            let t0 = Lane::load(&rays.t0[i..]);
            let t1 = Lane::load(&rays.t1[i..]);
            self.k.eval::<I::F32>(o, d, t0, t1).store(&mut out[i..]);
            i += w;
        }
        for i in i..n {
            let o = core::array::from_fn(|j| rays.origin[j][i]);
            let d = core::array::from_fn(|j| rays.dir[j][i]);
            out[i] = self.k.eval::<f32>(o, d, rays.t0[i], rays.t1[i]);
        }
    }
}
