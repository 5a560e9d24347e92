//! One trait every camera effect implements: the world built from a scene,
//! the shading point of a pixel, and one estimate from a row's samples.
//!
//! In the spirit of pbrt-v4's integrators, where each integrator is only
//! its `Li()`, an effect here is only what is its own: what a pixel sees,
//! and the closed form it evaluates along each sample. Patterns, seeds,
//! statistics, images and files belong to whoever drives the effect (the
//! lab's image and pixel-study experiments are generic over this trait; a
//! renderer calls [`Effect::estimate`] in its own loop).
//!
//! Samples are points of `[0, 1)²`: an estimator whose pattern is 1D
//! ([`Effect::dims`] = 1) reads only their first coordinate. The caller
//! draws them from a pattern of [`Effect::sampler`] in [`Effect::dims`]
//! dimensions, one realisation per seed; the same seed then drives any
//! randomness the estimator draws beyond the pattern (direct light's random
//! line orientations), so an estimate is a pure function of
//! `(pixel, estimator, samples, seed)`.

use crate::model::{Scene, SceneSampler};
use crate::Error;
use linesample::Seed;

/// An effect a camera scene asks for ([`crate::model::EffectParams`]),
/// evaluated in closed form along each sample.
pub trait Effect: Sized + Sync {
    /// The scene file's `effect.kind`.
    const KIND: &'static str;
    /// One estimator of the effect (primitive, its parameters, sampler).
    type Estimator: Copy + PartialEq + core::fmt::Debug + Send + Sync;
    /// What a pixel's estimates need (the shading point, its frame, the
    /// shadows or spheres that matter there).
    type Pixel;
    /// Per-caller buffers.
    type Scratch;

    /// The world of `scene` seen at `width × height` pixels.
    ///
    /// # Errors
    /// [`Error::WrongEffect`] for a scene of another effect, and
    /// [`Error::Item`] for geometry the kernel refuses.
    fn from_scene(scene: Scene, width: u32, height: u32) -> Result<Self, Error>;

    /// What the camera ray through the centre of pixel `(x, y)` finds, or
    /// `None` where the effect has nothing to estimate.
    fn pixel(&self, x: u32, y: u32) -> Option<Self::Pixel>;

    /// Fresh buffers for [`Effect::estimate`].
    fn scratch(&self) -> Self::Scratch;

    /// The effect's reference estimator (the one whose mean at large `N`
    /// is the reference value).
    fn reference() -> Self::Estimator;

    /// The estimator whose samples `est` draws: itself, or for an `f32`
    /// SIMD estimator its `f64` twin (so their difference is the rounding
    /// alone).
    fn twin(est: Self::Estimator) -> Self::Estimator;

    /// `est`'s name in tables and errors (`segments-0.1 uniform jittered`).
    fn label(est: &Self::Estimator) -> alloc::string::String;

    /// The sampler of `est`'s pattern.
    fn sampler(est: &Self::Estimator) -> SceneSampler;

    /// The dimension (1 or 2) of `est`'s pattern.
    fn dims(est: &Self::Estimator) -> usize;

    /// Whether `est`'s pattern (`None`: the reference's) is toroidally
    /// shifted per realisation when the caller asks `shift` (`None`: the
    /// effect's default).
    fn shifted(est: Option<&Self::Estimator>, shift: Option<bool>) -> bool;

    /// One estimate at `px` by `est` from the `samples` of realisation
    /// `seed` (the mean over its samples).
    ///
    /// # Errors
    /// The kernel's refusal, or an estimator that cannot be evaluated at
    /// this pixel (a fixed-capacity `f32` batch too small for it).
    fn estimate(
        &self,
        px: &Self::Pixel,
        est: &Self::Estimator,
        samples: &[[f32; 2]],
        seed: Seed,
        scratch: &mut Self::Scratch,
    ) -> Result<f64, Error>;

    /// A per-pixel quantity of the effect a caller may keep beside its
    /// estimates (direct light: the fraction of the light hidden); `None`
    /// when it has none.
    ///
    /// # Errors
    /// The kernel's refusal.
    fn extra(&self, px: &Self::Pixel) -> Result<Option<f32>, Error> {
        let _ = px;
        Ok(None)
    }
}
