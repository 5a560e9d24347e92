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
//! * [`direct_light`] and [`direct_light_f32`]: direct light from a
//!   rectangular light onto a diffuse receiver along lines across the
//!   light (Billen & Dutré 2016), with the exact visibility of convex
//!   occluder faces projected onto the light's plane, in `f64` and as an
//!   `f32` SIMD batch;
//! * [`camera`]: the pinhole camera of the scene files (pbrt's
//!   conventions), whose ray per pixel finds the shading point;
//! * [`caustic`]: photon points and photon beams through a glass ball
//!   (Snell refraction, Fresnel splitting) into a homogeneous medium,
//!   scored in a query ball (volumetric caustics; Jarosz et al. 2011),
//!   and [`fluence`], their paths splatted into a fluence image;
//!
//! They build on the kernel's shapes ([`linesample::world`]: spheres,
//! rays, planes, Gaussians), its numeric core and its lane abstraction, so
//! every `f32` batch is bit for bit its scalar twin, lane by lane, in every
//! build. Like the kernel, the crate is `#![no_std]`, never allocates and
//! has no `unsafe` code. Each module states the error bound of its closed
//! forms; the derivations are in `docs/theory.md` of the repository.
//!
//! These modules were `linesample::world::{occlusion, occlusion_f32,
//! direct_light, direct_light_f32, caustic}` before 0.2; the kernel cannot
//! re-export them (this crate depends on it), so a renderer that used them
//! now depends on `linesample-scene` and changes the path's first segment.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
#![deny(missing_debug_implementations)]
#![allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    clippy::needless_range_loop
)]

#[cfg(feature = "std")]
extern crate std;

pub mod ao;
pub mod camera;
pub mod caustic;
pub mod direct_light;
pub mod direct_light_f32;
pub mod fluence;
pub mod occlusion;
pub mod occlusion_f32;

pub use occlusion::HalfPlane;
pub use occlusion_f32::AoPoint32;
