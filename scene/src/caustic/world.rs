//! The volumetric-caustic world of a scene: the kernel's [`Caustic`] in
//! the scene's dimension, and the mean of photon points or photon beams
//! over a pattern's samples (points sample the emission angles and the
//! free-flight distance, `D` coordinates; beams sample the emission angles
//! and integrate along the beam in closed form, `D − 1`).

use super::Caustic;
use crate::model::CausticScene;
use crate::Error;

/// Photon points or photon beams.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Estimator {
    /// Sample the emission angles and the free-flight distance.
    Points,
    /// Sample the emission angles; integrate along the beam in closed form.
    Beams,
}

impl Estimator {
    /// The name in the output files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Estimator::Points => "points",
            Estimator::Beams => "beams",
        }
    }

    /// The dimension of its samples in a `dims`-dimensional scene.
    #[must_use]
    pub fn sample_dims(self, dims: usize) -> usize {
        match self {
            Estimator::Points => dims,
            Estimator::Beams => dims - 1,
        }
    }
}

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

    /// The mean of `est` over the samples `x` (each padded to 3 components:
    /// `u` first, then `s` for points).
    #[must_use]
    pub fn estimate(&self, est: Estimator, x: &[[f64; 3]]) -> f64 {
        let mut sum = 0.0;
        match (self, est) {
            (CausticWorld::Two(c), Estimator::Beams) => {
                for p in x {
                    sum += c.beam_sample([p[0], 0.0]);
                }
            }
            (CausticWorld::Two(c), Estimator::Points) => {
                for p in x {
                    sum += c.point_sample([p[0], 0.0], p[1]);
                }
            }
            (CausticWorld::Three(c), Estimator::Beams) => {
                for p in x {
                    sum += c.beam_sample([p[0], p[1]]);
                }
            }
            (CausticWorld::Three(c), Estimator::Points) => {
                for p in x {
                    sum += c.point_sample([p[0], p[1]], p[2]);
                }
            }
        }
        sum / x.len().max(1) as f64
    }
}
