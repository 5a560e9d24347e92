//! The samples a camera effect's estimator draws: its sampler's pattern of
//! `N` points in the dimension the estimator needs
//! ([`linesample_scene::Effect::dims`]), shifted per realisation as the
//! effect says ([`linesample_scene::Effect::shifted`]), written as points
//! of `[0, 1)²` (a 1D pattern fills the first coordinate, the second is ½).
//!
//! Multi-jittered and CMJ patterns exist only in 2D: a 1D estimator then
//! reads the `u` coordinates of the 2D pattern, whose projection is
//! stratified into `N` strata (a 1D jittered pattern).

use linesample::Seed;
use linesample_scene::model::SceneSampler;
use linesample_scene::Effect;

use crate::sampler::{self, DynPattern, PatternSpec, Sampler};
use crate::spec::ShiftMode;

/// A sampler's pattern of `N` points in one or two dimensions.
pub struct SamplePattern {
    pattern: Dims,
    n: usize,
}

/// The pattern in its dimension.
enum Dims {
    One(DynPattern<1>),
    Two(DynPattern<2>),
}

impl SamplePattern {
    /// The pattern of `sampler` with `n` points in `dims` (1 or 2)
    /// dimensions, toroidally shifted per realisation when `shift`; `label`
    /// names the estimator in an error.
    ///
    /// # Errors
    /// A sample count the sampler does not support.
    pub fn new(
        sampler: SceneSampler,
        dims: usize,
        n: usize,
        shift: bool,
        label: &str,
    ) -> crate::Result<Self> {
        let s = Sampler::from(sampler);
        let err = |e: String| format!("{label} with N = {n}: {e}");
        let only_2d = matches!(sampler, SceneSampler::MultiJittered | SceneSampler::Cmj);
        let pattern = if dims == 1 && !only_2d {
            Dims::One(
                sampler::build::<1>(&PatternSpec::simple(s, 1, n), shift)
                    .map_err(err)?
                    .pattern,
            )
        } else {
            Dims::Two(
                sampler::build::<2>(&PatternSpec::simple(s, 2, n), shift)
                    .map_err(err)?
                    .pattern,
            )
        };
        Ok(SamplePattern { pattern, n })
    }

    /// The pattern of effect `E`'s estimator `est` (`None`: the effect's
    /// reference) with `n` points under `--shift` `shift` (`None`: the
    /// effect's default), with the estimator it is for.
    ///
    /// # Errors
    /// A sample count the sampler does not support.
    pub fn of<E: Effect>(
        est: Option<&E::Estimator>,
        n: usize,
        shift: Option<ShiftMode>,
    ) -> crate::Result<(E::Estimator, Self)> {
        let shifted = E::shifted(est, shift.map(|s| s == ShiftMode::Random));
        let e = est.copied().unwrap_or_else(E::reference);
        let p = Self::new(E::sampler(&e), E::dims(&e), n, shifted, &E::label(&e))?;
        Ok((e, p))
    }

    /// Realisation `seed` into `out` (length `N`; `one` is a buffer for 1D
    /// patterns).
    ///
    /// # Errors
    /// The pattern's error.
    pub fn fill(
        &self,
        seed: Seed,
        out: &mut Vec<[f32; 2]>,
        one: &mut Vec<[f32; 1]>,
    ) -> crate::Result<()> {
        out.resize(self.n, [0.5, 0.5]);
        match &self.pattern {
            Dims::Two(p) => p.fill(seed, out)?,
            Dims::One(p) => {
                one.resize(self.n, [0.0]);
                p.fill(seed, one)?;
                for (o, u) in out.iter_mut().zip(one.iter()) {
                    *o = [u[0], 0.5];
                }
            }
        }
        Ok(())
    }
}

/// An estimator with its pattern at one `N`.
pub type Plan<E> = (<E as Effect>::Estimator, SamplePattern);

/// The buffers of [`estimate`]: the effect's, and the samples.
pub type Scratch<E> = (<E as Effect>::Scratch, Vec<[f32; 2]>, Vec<[f32; 1]>);

/// Fresh [`Scratch`] for `world`.
pub fn scratch<E: Effect>(world: &E) -> Scratch<E> {
    (world.scratch(), Vec::new(), Vec::new())
}

/// One estimate at `px` with `plan` from realisation `seed`: fill the
/// pattern, then [`Effect::estimate`].
///
/// # Errors
/// The pattern's or the effect's error.
pub fn estimate<E: Effect>(
    world: &E,
    px: &E::Pixel,
    (est, pattern): &Plan<E>,
    seed: Seed,
    (scratch, uv, one): &mut Scratch<E>,
) -> crate::Result<f64> {
    pattern.fill(seed, uv, one)?;
    Ok(world.estimate(px, est, uv, seed, scratch)?)
}
