//! The integrand registry: command-line choices turned into kernel integrands
//! on the unit torus.

use crate::{LabError, Result};
use clap::ValueEnum;
use linesample::geom::Direction;
use linesample::integrand::{Ball, Gaussian, HalfSpace, Integrand};
use serde::{Deserialize, Serialize};

/// Centre coordinate of the disk, ball and Gaussian (in every dimension).
pub const CENTRE: f64 = 0.5;
/// Default `--radius`.
pub const DEFAULT_RADIUS: f64 = 0.25;
/// Default `--sigma`.
pub const DEFAULT_SIGMA: f64 = 0.1;
/// Default `--offset`.
pub const DEFAULT_OFFSET: f64 = 0.6;

/// The integrands the lab can measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegrandKind {
    /// Indicator of the disk of radius --radius centred at (0.5, 0.5); 2D only.
    Disk,
    /// Indicator of the ball of radius --radius centred at (0.5, ..); a 2D ball
    /// is the disk.
    Ball,
    /// Normalised isotropic Gaussian density with standard deviation --sigma
    /// centred at (0.5, ..), periodised on the torus (integral 1).
    Gaussian,
    /// Straight edge: the indicator of {x in [0,1)^D : n.x >= h} for the unit
    /// normal n along --normal and the offset h = --offset.
    Edge,
}

impl IntegrandKind {
    /// The command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            IntegrandKind::Disk => "disk",
            IntegrandKind::Ball => "ball",
            IntegrandKind::Gaussian => "gaussian",
            IntegrandKind::Edge => "edge",
        }
    }
}

/// An integrand with every parameter resolved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IntegrandSpec {
    pub kind: IntegrandKind,
    pub dims: usize,
    pub params: Params,
}

/// The parameters of an [`IntegrandSpec`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Params {
    Ball { radius: f64 },
    Gaussian { sigma: f64 },
    Edge { normal: Vec<f64>, offset: f64 },
}

/// `a,b,c` with Rust's shortest round-trip formatting.
#[must_use]
pub fn join(v: &[f64]) -> String {
    v.iter().map(f64::to_string).collect::<Vec<_>>().join(",")
}

/// `v` as an array (`v.len() = D`, checked by the caller).
#[must_use]
pub fn to_array<const D: usize>(v: &[f64]) -> [f64; D] {
    let mut a = [0.0; D];
    a.copy_from_slice(&v[..D]);
    a
}

impl IntegrandSpec {
    /// E.g. `centre 0.5,0.5, radius 0.25`.
    #[must_use]
    pub fn describe(&self) -> String {
        let c = vec![format!("{CENTRE}"); self.dims].join(",");
        match &self.params {
            Params::Ball { radius } => format!("centre {c}, radius {radius}"),
            Params::Gaussian { sigma } => format!("centre {c}, sigma {sigma}"),
            Params::Edge { normal, offset } => format!("normal {}, offset {offset}", join(normal)),
        }
    }

    /// The options that select it, e.g. `--integrand disk --dims 2 --radius 0.25`.
    #[must_use]
    pub fn options(&self) -> String {
        let head = format!("--integrand {} --dims {}", self.kind.name(), self.dims);
        match &self.params {
            Params::Ball { radius } => format!("{head} --radius {radius}"),
            Params::Gaussian { sigma } => format!("{head} --sigma {sigma}"),
            Params::Edge { normal, offset } => {
                format!("{head} --normal {} --offset {offset}", join(normal))
            }
        }
    }

    /// The kernel integrand (`D = dims`).
    ///
    /// # Errors
    /// The kernel's parameter error, prefixed with the option that caused it.
    pub fn build<const D: usize>(&self) -> Result<Box<dyn Integrand<D> + Send + Sync>> {
        let centre = [CENTRE; D];
        let kind = self.kind.name();
        Ok(match &self.params {
            Params::Ball { radius } => Box::new(Ball::<D>::new(centre, *radius).map_err(|e| {
                LabError::Usage(format!("--radius {radius} (--integrand {kind}): {e}"))
            })?),
            Params::Gaussian { sigma } => {
                Box::new(Gaussian::<D>::new(centre, *sigma).map_err(|e| {
                    LabError::Usage(format!("--sigma {sigma} (--integrand gaussian): {e}"))
                })?)
            }
            Params::Edge { normal, offset } => {
                let n = Direction::<D>::new(to_array(normal))
                    .map_err(|e| LabError::Usage(format!("--normal {}: {e}", join(normal))))?;
                Box::new(HalfSpace::<D>::new(n, *offset).map_err(|e| {
                    format!(
                        "--normal {} --offset {offset} (--integrand edge): {e}",
                        join(normal)
                    )
                })?)
            }
        })
    }
}
