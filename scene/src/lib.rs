//! `linesample-scene`: the effects of linesample's scenes, each evaluated
//! in closed form along the samples a scene asks for. Nothing else is
//! simulated: a scene names its geometry and one effect.
//!
//! * [`ao`]: the AO estimators at a shading point (points, segments and
//!   lines in the half-plane parameterisation, for each centre density);
//! * [`occlusion`] ([`HalfPlane`]) and [`occlusion_f32`] ([`AoPoint32`]):
//!   ambient occlusion by spheres, one half-plane through the shading
//!   point's normal at a time (the angles a sphere occludes, and the
//!   cosine-weighted visible measure of an angle interval), in `f64` and
//!   as an `f32` SIMD batch of lines and segments;
//! * [`direct_light`] ([`QuadLight`], [`Parallelogram`], [`Shadow`],
//!   [`DirectLight`]) and [`direct_light_f32`] ([`DirectLight32`]): direct
//!   light from a rectangular light onto a diffuse receiver along lines
//!   across the light (Billen & Dutré 2016), with the exact visibility of
//!   convex occluder faces projected onto the light's plane, in `f64` and
//!   as an `f32` SIMD batch;
//! * [`camera`]: the pinhole camera of the scene files (pbrt's
//!   conventions), whose ray per pixel finds the shading point;
//! * [`caustic`]: photon points and photon beams through a glass ball
//!   (Snell refraction, Fresnel splitting) into a homogeneous medium,
//!   scored in a query ball (volumetric caustics; Jarosz et al. 2011),
//!   and [`fluence`], their paths splatted into a fluence image;
//!
//! With the `alloc` feature, the scene layer over them:
//!
//! * `model`: the checked scene a scene file describes (camera, spheres,
//!   quads, boxes, one light, the one effect and the estimators to
//!   compare; the volumetric caustic's own scene), with the vocabulary
//!   (`Primitive`, `SceneSampler`, `Orientation`) deriving `serde` and
//!   `clap::ValueEnum` behind the features of those names;
//! * `Effect`: one trait every effect implements (the world built from its
//!   scene, one estimate at a query from a row's samples and seed, the
//!   reference estimator and each estimator's sampler, dimension and shift
//!   rule), like a pbrt-v4 integrator's `Li()`; `ao::world::World`,
//!   `direct_light::world::DlWorld` and `caustic::world::CausticWorld`
//!   implement it, and `CameraEffect` adds the query a camera pixel sees
//!   for the two camera effects;
//! * `schema` (feature `toml`, no std needed): the scene file reader into
//!   the model, one entry for every effect, errors naming the file, line,
//!   column and field, every field an effect does not use an error;
//! * `ao::theory` (feature `theory`: std and the NUFFT): the Fourier
//!   coefficients of an AO pixel's integrand and the variance they predict
//!   for a pattern's expected periodogram.
//!
//! They build on the kernel's shapes ([`linesample::world`]: spheres,
//! rays, planes, Gaussians), its numeric core and its lane abstraction, so
//! every `f32` batch is bit for bit its scalar twin, lane by lane, in every
//! build. Like the kernel, the crate is `#![no_std]` and has no `unsafe`
//! code; the closed forms never allocate (the scene layer, behind `alloc`,
//! holds the scene's lists and a pixel's shadows in `Vec`s, built once per
//! world and per pixel). Each module states the error bound of its closed
//! forms; the derivations are in `docs/theory.md` of the repository.
//!
//! These modules were `linesample::world::{occlusion, occlusion_f32,
//! direct_light, direct_light_f32, caustic}` before 0.2; the kernel cannot
//! re-export them (this crate depends on it), so a renderer that used them
//! now depends on `linesample-scene` and changes the path's first segment.
//!
//! ## Conventions
//!
//! The kernel's, stated once in [its crate docs](linesample#conventions):
//! no implied unit of length, angles in radians, `f64` directions
//! normalised when they are built (the parameter along them is arc length),
//! `f32` directions used as given. The effects add their own angles, named
//! the same way in their `f64` and `f32` APIs:
//!
//! * **Ambient occlusion** ([`occlusion`], [`occlusion_f32`], [`ao`]): at a
//!   shading point `p` with unit normal `n` and a tangent `t` (normalised,
//!   its normal component removed), the **azimuth** `φ` names the
//!   half-plane through `n` spanned by `a(φ) = cos φ·t + sin φ·(n × t)`,
//!   and the **signed polar angle** `θ` the direction
//!   `d(φ, θ) = sin θ·a(φ) + cos θ·n` in it (negative `θ` leans towards
//!   `−a`). With `φ ∈ [0, π)` and `θ ∈ (−π/2, π/2)` every direction of the
//!   upper hemisphere is named once, and `dω = |sin θ| dθ dφ`; the
//!   estimators draw `φ = πu`. Any finite `φ` is accepted (`φ + π` is the
//!   same half-plane with `θ` negated). An interval of `θ`
//!   ([`HalfPlane::visible`]) is clamped to `[−π/2, π/2]`; a segment of `θ`
//!   ([`HalfPlane::visible_wrapped`], [`AoPoint32::segment_f32`]) wraps with
//!   period `π`, `0 ≤ len ≤ π`. The `f32` batches take `φ` and `θ0` as `f32`
//!   radians (their reduction is accurate to `2⁻²³` for `|φ|, |θ0| ≤ 6000`).
//! * **Direct light** ([`direct_light`], [`direct_light_f32`]): a line
//!   across the light has the direction `d = (cos φ, sin φ)` in light
//!   coordinates (along the unit edges `ê₁`, `ê₂`, in the scene's length
//!   unit) and the offset `o` (the line `p·d⊥ = o`, `d⊥ = (−sin φ, cos φ)`),
//!   and its parameter is arc length. As in the kernel, the `f64`
//!   [`QuadLight::chord`] normalises `(cos φ, sin φ)`, and the `f32`
//!   [`DirectLight32`] uses it as given and refuses it unless it is unit
//!   within `10⁻⁵`.
//! * **Caustics** ([`caustic`]): photon rays are the kernel's
//!   [`linesample::world::Ray`] (unit directions, arc length, which the
//!   medium distance `τ` is too).
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
#![deny(missing_debug_implementations)]
#![allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    clippy::needless_range_loop
)]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod ao;
pub mod camera;
pub mod caustic;
pub mod direct_light;
pub mod direct_light_f32;
#[cfg(feature = "alloc")]
pub mod effect;
mod error;
pub mod fluence;
#[cfg(feature = "alloc")]
pub mod model;
pub mod occlusion;
pub mod occlusion_f32;
#[cfg(feature = "toml")]
pub mod schema;
mod vec3;

pub use direct_light::{DirectLight, Parallelogram, QuadLight, Shadow};
pub use direct_light_f32::DirectLight32;
#[cfg(feature = "alloc")]
pub use effect::{CameraEffect, Effect};
pub use error::Error;
pub use occlusion::HalfPlane;
pub use occlusion_f32::AoPoint32;
