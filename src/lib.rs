//! # linesample
//!
//! A `no_std`, allocation-free numeric kernel for Monte Carlo integration with
//! point, segment and line samples, after Singh, Miller & Jarosz, *Variance and
//! Convergence Analysis of Monte Carlo Line and Segment Sampling* (EGSR 2017,
//! doi:10.1111/cgf.13226).
//!
//! This release provides
//!
//! * SIMD-batched, seed-deterministic sample patterns ([`pattern`], including
//!   toroidal Poisson disk and CCVT blue noise) and the random numbers behind
//!   them ([`rng`], [`hash`]);
//! * integrands with closed-form point, segment and line integrals and Fourier
//!   coefficients ([`integrand`]: ball/disk, Gaussian, half-space), each with an
//!   `f64` path accurate to a few ulp in the hard cases (tangent lines, far
//!   Gaussian tails, tiny segments) and an `f32` SIMD batch path over
//!   [`primitive::Rays32`];
//! * point, segment and line estimators over any pattern ([`estimator`]) and
//!   mergeable running statistics ([`stats`]);
//! * exact streaming periodograms of points, segments and lines, radial
//!   averages and the spectral variance prediction
//!   `Var = (1/N) Σ_{ν≠0} ⟨N·P(ν)⟩·|f̂(ν)|²` ([`spectrum`]).
//! * world-space closed forms a renderer calls along its rays ([`world`]:
//!   sphere entry/exit and clipped chords, Gaussian segment integrals,
//!   transmittance and opacity, half-spaces and slabs; exact `f64` and 8-lane
//!   `f32` batches), which the torus integrands periodise. The rendering
//!   problems built on them (ambient occlusion by spheres, direct light from
//!   a rectangular light along lines, and photon points and beams through a
//!   glass ball into a medium: volumetric caustics) are not in this crate
//!   but in the repository's `linesample-scene` crate
//!   (`linesample_scene::{occlusion, direct_light, caustic}`);
//! * random access into sample patterns ([`sequence::Sequence`]) and
//!   per-pixel seeds ([`sequence::pixel_seed`]).
//!
//! ## Quick start
//!
//! ```
//! use linesample::pattern::Pattern;
//! use linesample::Seed;
//!
//! use linesample::pattern::Jittered;
//! let cmj = Jittered::new([32, 32])?;                    // 32 × 32 strata
//! let mut pts = [[0.0f32; 2]; 1024];
//! cmj.fill(Seed::new(7), &mut pts)?;                     // no allocation
//! assert!(pts.iter().all(|p| p.iter().all(|&x| (0.0..1.0).contains(&x))));
//!
//! // Homogenised (randomly shifted on the torus), as variance analysis needs:
//! cmj.clone().shifted().fill(Seed::new(7).realization(3), &mut pts)?;
//! # Ok::<(), linesample::PatternError>(())
//! ```
//!
//! ## Conventions
//!
//! One set for the whole crate, the `f64` and the `f32` APIs alike, and for
//! the crates built on it; a method's docs state only its own case and
//! point here.
//!
//! * **Domain**: the unit torus `[0, 1)^D`. Pattern coordinates are `f32`
//!   and always in `[0, 1)`; every sum and statistic elsewhere in the crate
//!   is `f64`.
//! * **Units**: none is implied. Positions, radii, `σ`, segment lengths and
//!   ray parameters are in the caller's length unit, and an integral along
//!   a ray is in that unit times the integrand's (a chord is a length, a
//!   Gaussian's line integral a density times a length; the extinction
//!   `σ_t` is per unit density per unit length). Angles are radians.
//!   Frequencies `ν` are integer cycles per period of the unit torus,
//!   `f̂(ν) = ∫ f(x) e^{−2πi ν·x} dx`.
//! * **Directions and the ray parameter**: every closed form along a line
//!   integrates over the parameter `t` of `o + t·d` for the direction `d`
//!   it is given, so anything it returns in `t` (an entry or exit
//!   parameter, a chord, a clipped length, `∫ F dt`) is in units of `|d|`.
//!   - The `f64` API takes directions as validated values:
//!     [`geom::Direction`] (held by [`world::Ray`], [`primitive::Segment`]
//!     and [`primitive::Line`]) divides any finite non-zero vector by its
//!     length when it is built, and plane normals are normalised the same
//!     way. So `|d| = 1` up to rounding and `t` is **arc length**.
//!   - The `f32` API (the scalar twins `*_f32` and the batches `*_batch_f32`
//!     over [`primitive::Rays32`]) uses `d` **as given**, any finite non-zero
//!     vector, and never normalises it: that would cost a square root and a
//!     division per ray and change the result of every direction already
//!     rounded to `f32`. Pass unit vectors for arc length (the `f32` result
//!     then matches the `f64` one for the same ray within the bound each
//!     method states), or a ray whose `t` is yours (a renderer's
//!     object-space ray, transformed without renormalising).
//! * **Angles**: radians, any finite value (reduced where needed), e.g.
//!   the normal `(cos θ, sin θ)` of [`integrand::HalfSpace::from_angle`].
//!   The effects built on this crate name their own angles, in the same way
//!   in their `f64` and `f32` APIs: `linesample-scene`'s crate docs state
//!   the ambient-occlusion parameterisation (azimuth `φ ∈ [0, π)` naming a
//!   half-plane through the normal, signed polar angle `θ ∈ (−π/2, π/2)`
//!   in it) and the direct-light line directions `(cos φ, sin φ)`.
//! * **Determinism**: a [`Seed`] (plus a realisation index,
//!   [`Seed::realization`]) fixes every value. Results do not depend on SIMD
//!   width, batch size, thread count, or on whether the SIMD or the scalar
//!   path ran.
//! * **Errors**: constructors and fills return `Result` with an error that
//!   names the parameter; nothing in the public API panics on bad input.
//!   Each module's error type converts into the one [`Error`] (also without
//!   `std`), so `?` works across modules in a function returning
//!   `Result<_, linesample::Error>`.
//!
//! ## SIMD and build flags
//!
//! SIMD comes from [`wide`], which selects its instructions **at compile
//! time**: a dependent crate built with default flags gets baseline `x86_64`
//! (SSE2, no FMA). Three things keep that build fast and identical:
//!
//! * No hot path uses a fused multiply-add (a software `fma` without the
//!   instruction costs about 35× a multiply and an add); the exact products
//!   of the double-double closed forms ([`num::two_prod`]) use Dekker's
//!   product there, which is exact, so it returns the FMA's bits.
//! * With `std` on `x86_64`, the periodogram accumulation ([`spectrum::Dft`])
//!   and the `f32` ray batches ([`world`], [`integrand`]) also run a copy
//!   compiled with AVX2 + FMA when the CPU has them, chosen at run time
//!   ([`simd`]; `LINESAMPLE_SIMD=compiled` turns it off), as do the random,
//!   jittered, Sobol′, Halton and N-rooks fills. The multi-jittered fills
//!   run their copy too, which still uses 128-bit halves.
//! * Every kernel executes the same IEEE operations in either copy, so the
//!   results are bit-identical in every build and at every level.
//!
//! `RUSTFLAGS="-C target-cpu=x86-64-v3"` compiles AVX2 + FMA everywhere (no
//! dispatch needed); the README gives the measured speed of the three builds.
//!
//! ## Features
//!
//! * `std` (default): implies `alloc`; adds run-time AVX2 dispatch ([`simd`]).
//! * `alloc`: allocating conveniences such as [`pattern::Pattern::to_vec`].
//! * `glam` (off by default): patterns fill `glam::Vec2`/`Vec3` slices in
//!   place and `Vec3A` through a stack buffer (`pattern::PatternGlam`); rays
//!   and shapes take `DVec2`/`DVec3`, the `f32` twins `Vec2`/`Vec3`/`Vec3A`.
//!   Off by default because the core API is plain arrays and a renderer on
//!   another glam major version would otherwise build two copies.
//! * `proptest`: `strategy`, proptest strategies for the inputs that break
//!   renderers (grazing and tangent rays, far origins, deep Gaussian tails,
//!   near-axis directions), for your own property tests.
//!
//! Without default features the crate is `#![no_std]` with no allocator.
#![no_std]
// The one `unsafe` is the call into the AVX2 copy of a hot path after the
// CPU check (`simd::dispatch`); everything else is safe code.
#![deny(unsafe_code)]
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

pub mod error;
pub mod estimator;
pub mod geom;
pub mod hash;
pub mod integrand;
pub mod num;
pub mod pattern;
pub mod primitive;
pub mod rng;
pub mod sequence;
#[allow(unsafe_code)]
pub mod simd;
pub mod special;
pub mod spectrum;
pub mod stats;
#[cfg(feature = "proptest")]
pub mod strategy;
pub mod world;

pub use error::{Error, EstimateError, ParamError, PatternError, SeedError, SpectrumError};
pub use rng::{Pcg32, Seed};

/// The `glam` version this crate's interop is written against (feature `glam`).
#[cfg(feature = "glam")]
pub use glam;

/// The README's code examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
