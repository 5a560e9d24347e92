//! One trait every effect implements: the world built from a scene, what a
//! query (a pixel's shading point, the caustic's query ball) needs, and one
//! estimate from a row's samples.
//!
//! In the spirit of pbrt-v4's integrators, where each integrator is only
//! its `Li()`, an effect here is only what is its own: what a query sees,
//! and the closed form it evaluates along each sample. Patterns, seeds,
//! statistics, images and files belong to whoever drives the effect (the
//! lab's image and study experiments are generic over this trait; a
//! renderer calls [`Effect::estimate`] in its own loop).
//!
//! Samples are points of `[0, 1)^K` ([`Effect::Sample`] is `[f32; K]`,
//! `K` the most coordinates any of the effect's estimators reads): an
//! estimator whose pattern has fewer dimensions ([`Effect::dims`]) reads
//! only its first coordinates. The caller draws them from a pattern of
//! [`Effect::sampler`] in [`Effect::dims`] dimensions, one realisation per
//! seed; the same seed then drives any randomness the estimator draws
//! beyond the pattern (direct light's random line orientations), so an
//! estimate is a pure function of `(query, estimator, samples, seed)`.
//!
//! Camera effects ([`CameraEffect`]) find their queries through the
//! scene's camera, one per pixel.

use crate::model::{Scene, SceneSampler};
use crate::Error;
use linesample::Seed;

/// An effect a scene asks for ([`crate::model::EffectParams`], or the
/// volumetric caustic's scene), evaluated in closed form along each
/// sample.
pub trait Effect: Sized + Sync {
    /// The scene file's `effect.kind`.
    const KIND: &'static str;
    /// The checked scene the world is built from.
    type Scene;
    /// One estimator of the effect (primitive, its parameters, sampler).
    type Estimator: Copy + PartialEq + core::fmt::Debug + Send + Sync;
    /// What one query's estimates need (a pixel's shading point, its frame
    /// and the shadows or spheres that matter there).
    type Query: Sync;
    /// One sample, a point of `[0, 1)^K` (`[f32; K]`).
    type Sample: Copy + Default + AsRef<[f32]> + AsMut<[f32]> + Send + Sync;
    /// Per-caller buffers.
    type Scratch: Send;

    /// The world of `scene` (a camera scene at its camera's resolution).
    ///
    /// # Errors
    /// [`Error::WrongEffect`] for a scene of another effect, and
    /// [`Error::Item`] or [`Error::Param`] for geometry the kernel refuses.
    fn from_scene(scene: Self::Scene) -> Result<Self, Error>;

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

    /// The dimension of `est`'s pattern in this world (at most the length
    /// of [`Effect::Sample`]).
    fn dims(&self, est: &Self::Estimator) -> usize;

    /// Whether `est`'s pattern (`None`: the reference's) is toroidally
    /// shifted per realisation when the caller asks `shift` (`None`: the
    /// effect's default).
    fn shifted(est: Option<&Self::Estimator>, shift: Option<bool>) -> bool;

    /// One estimate at `query` by `est` from the `samples` of realisation
    /// `seed` (the mean over its samples).
    ///
    /// # Errors
    /// The kernel's refusal, or an estimator that cannot be evaluated at
    /// this query (a fixed-capacity `f32` batch too small for it).
    fn estimate(
        &self,
        query: &Self::Query,
        est: &Self::Estimator,
        samples: &[Self::Sample],
        seed: Seed,
        scratch: &mut Self::Scratch,
    ) -> Result<f64, Error>;

    /// A per-query quantity of the effect a caller may keep beside its
    /// estimates (direct light: the fraction of the light hidden); `None`
    /// when it has none.
    ///
    /// # Errors
    /// The kernel's refusal.
    fn extra(&self, query: &Self::Query) -> Result<Option<f32>, Error> {
        let _ = query;
        Ok(None)
    }
}

/// An effect seen through the scene's camera: one query per pixel.
pub trait CameraEffect: Effect<Scene = Scene> {
    /// What the camera ray through the centre of pixel `(x, y)` finds, or
    /// `None` where the effect has nothing to estimate.
    fn pixel(&self, x: u32, y: u32) -> Option<Self::Query>;
}
