//! The volumetric-caustic world of a scene: the closed forms' [`Caustic`] in
//! the scene's dimension, and the mean of photon points or photon beams
//! over a pattern's samples (points sample the emission angles and the
//! free-flight distance, `D` coordinates; beams sample the emission angles
//! and integrate along the beam in closed form, `D − 1`).
//!
//! As an [`Effect`](crate::Effect) the caustic has one query, the scene's
//! query ball `Q` (so [`Effect::Query`](crate::Effect::Query) is `()`), and
//! samples of up to 3 coordinates: the emission angles first, then, for
//! points, the free-flight variable.

use alloc::format;
use alloc::string::String;

use super::Caustic;
use crate::model::{CausticScene, SceneSampler};
use crate::Error;
use linesample::Seed;

/// Photon points or photon beams.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Photons {
    /// Sample the emission angles and the free-flight distance.
    Points,
    /// Sample the emission angles; integrate along the beam in closed form.
    Beams,
}

impl Photons {
    /// The name in the output files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Photons::Points => "points",
            Photons::Beams => "beams",
        }
    }

    /// The dimension of its samples in a `dims`-dimensional scene.
    #[must_use]
    pub fn sample_dims(self, dims: usize) -> usize {
        match self {
            Photons::Points => dims,
            Photons::Beams => dims - 1,
        }
    }
}

/// One estimator of the caustic: photon points or beams, and the sampler
/// of their primary samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Estimator {
    /// Points or beams.
    pub photons: Photons,
    /// The pattern of their primary samples.
    pub sampler: SceneSampler,
}

impl Estimator {
    /// The name in tables (`beams jittered`).
    #[must_use]
    pub fn label(&self) -> String {
        format!("{} {}", self.photons.name(), self.sampler.name())
    }
}

/// The reference estimator: jittered beams, never shifted.
pub const REFERENCE: Estimator = Estimator {
    photons: Photons::Beams,
    sampler: SceneSampler::Jittered,
};

/// The caustic scene in its dimension.
#[derive(Clone, Copy, Debug)]
pub enum CausticWorld {
    /// Flatland.
    Two(Caustic<2>),
    /// Three dimensions.
    Three(Caustic<3>),
}

impl CausticWorld {
    /// The scene's kernel form.
    ///
    /// # Errors
    /// A parameter the kernel rejects.
    pub fn new(scene: &CausticScene) -> Result<Self, Error> {
        Ok(if scene.dims == 2 {
            CausticWorld::Two(scene.kernel::<2>()?)
        } else {
            CausticWorld::Three(scene.kernel::<3>()?)
        })
    }

    /// The scene's dimension: 2 (flatland) or 3 (the dimension of an
    /// estimator's samples is [`Effect::dims`](crate::Effect::dims)).
    #[must_use]
    pub fn dimension(&self) -> usize {
        match self {
            CausticWorld::Two(_) => 2,
            CausticWorld::Three(_) => 3,
        }
    }

    /// The mean of `photons` over the samples `x` (emission angles first,
    /// then `s` for points; unused coordinates ignored), summed in `f64`;
    /// 0 for no samples.
    #[must_use]
    pub fn mean(&self, photons: Photons, x: &[[f32; 3]]) -> f64 {
        let f = |p: &[f32; 3], j: usize| f64::from(p[j]);
        let mut sum = 0.0;
        match (self, photons) {
            (CausticWorld::Two(c), Photons::Beams) => {
                for p in x {
                    sum += c.beam_sample([f(p, 0), 0.0]);
                }
            }
            (CausticWorld::Two(c), Photons::Points) => {
                for p in x {
                    sum += c.point_sample([f(p, 0), 0.0], f(p, 1));
                }
            }
            (CausticWorld::Three(c), Photons::Beams) => {
                for p in x {
                    sum += c.beam_sample([f(p, 0), f(p, 1)]);
                }
            }
            (CausticWorld::Three(c), Photons::Points) => {
                for p in x {
                    sum += c.point_sample([f(p, 0), f(p, 1)], f(p, 2));
                }
            }
        }
        sum / x.len().max(1) as f64
    }
}

impl crate::Effect for CausticWorld {
    const KIND: &'static str = "volumetric-caustic";
    type Scene = CausticScene;
    type Estimator = Estimator;
    /// The scene's one query, its ball `Q`.
    type Query = ();
    /// The emission angles (`D − 1` coordinates), then for points the
    /// free-flight variable `s`.
    type Sample = [f32; 3];
    type Scratch = ();

    fn from_scene(scene: CausticScene) -> Result<Self, Error> {
        CausticWorld::new(&scene)
    }

    fn scratch(&self) {}

    fn reference() -> Estimator {
        REFERENCE
    }

    fn twin(est: Estimator) -> Estimator {
        est
    }

    fn label(est: &Estimator) -> String {
        est.label()
    }

    fn sampler(est: &Estimator) -> SceneSampler {
        est.sampler
    }

    /// Points: `D` (angles and distance); beams: `D − 1`.
    fn dims(&self, est: &Estimator) -> usize {
        est.photons.sample_dims(self.dimension())
    }

    /// As [`SceneSampler::shifted`] (by default Sobol′ only: jittered
    /// patterns are unbiased as they are); the reference never.
    fn shifted(est: Option<&Estimator>, shift: Option<bool>) -> bool {
        est.is_some_and(|e| e.sampler.shifted(shift))
    }

    fn estimate(
        &self,
        _query: &(),
        est: &Estimator,
        samples: &[[f32; 3]],
        _seed: Seed,
        _scratch: &mut (),
    ) -> Result<f64, Error> {
        Ok(self.mean(est.photons, samples))
    }
}
