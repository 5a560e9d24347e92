//! The AO scene's model: its estimators (primitive, segment length,
//! centre density, sampler), the sample offsets each draws, and the world a
//! camera sees (the shading point of a pixel, its frame and the spheres).
//! The experiments ([`super::scene`], [`super::scene_theory`]) build on it.

use crate::sampler::{self, DynPattern, PatternSpec};
use crate::scene::{CentrePdf, Effect, Primitive, Scene, SceneSampler};
use linesample::world::Sphere;
use linesample::Seed;
use linesample_scene::ao::{self, AoEstimator, Frame, Sample};
use linesample_scene::occlusion_f32::AoPoint32;
use serde::{Deserialize, Serialize};

/// One estimator of a scene: primitive, segment length (segments), centre
/// density (points and segments) and sampler.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EstimatorSpec {
    pub primitive: Primitive,
    /// Segment length in `θ` (segments; 0 otherwise).
    pub length: f64,
    pub pdf: CentrePdf,
    pub sampler: SceneSampler,
    /// Lines only: the kernel's `f32` SIMD batch
    /// ([`linesample_scene::occlusion_f32::AoPoint32::line_batch_f32`])
    /// instead of the `f64` closed form.
    #[serde(default)]
    pub simd: bool,
}

impl EstimatorSpec {
    /// The kernel-side estimator.
    #[must_use]
    pub fn ao(&self) -> AoEstimator {
        AoEstimator {
            sample: match self.primitive {
                Primitive::Points => Sample::Point,
                Primitive::Segments => Sample::Segment {
                    length: self.length,
                },
                Primitive::Lines => Sample::Line,
            },
            pdf: self.pdf,
        }
    }

    /// `points`, `segments-0.1`, `lines` (without sampler and density).
    #[must_use]
    pub fn stem(&self) -> String {
        match self.primitive {
            Primitive::Segments if (self.length - std::f64::consts::PI).abs() < 1e-12 => {
                "segments-pi".into()
            }
            Primitive::Segments => format!("segments-{}", self.length),
            Primitive::Lines if self.simd => "lines-f32".into(),
            p => p.name().into(),
        }
    }

    /// `segments-0.1 uniform jittered` (lines have no density).
    #[must_use]
    pub fn label(&self) -> String {
        match self.primitive {
            Primitive::Lines if self.simd => format!("lines f32-simd {}", self.sampler.name()),
            Primitive::Lines => format!("lines {}", self.sampler.name()),
            _ => format!(
                "{} {} {}",
                self.stem(),
                self.pdf.name(),
                self.sampler.name()
            ),
        }
    }
}

/// The sample offsets of an estimator: `N` points of `[0, 1)²` for points and
/// segments (`u` → azimuth, `v` → centre angle); `N` azimuth offsets for lines,
/// from the sampler's 1D pattern (random, jittered, Sobol′), or the `u`
/// coordinates of its 2D pattern (multi-jittered and CMJ, whose `u`
/// projection is stratified into `N` strata: a 1D jittered pattern).
pub struct Offsets {
    two: Option<DynPattern<2>>,
    one: Option<DynPattern<1>>,
    n: usize,
}

impl Offsets {
    /// The offsets of `spec` with `n` samples, toroidally shifted per
    /// realisation when `shift`.
    ///
    /// # Errors
    /// A sample count the sampler does not support.
    pub fn new(spec: &EstimatorSpec, n: usize, shift: bool) -> crate::Result<Self> {
        let s = spec.sampler.pattern();
        let one_d = spec.primitive == Primitive::Lines
            && !matches!(
                spec.sampler,
                SceneSampler::MultiJittered | SceneSampler::Cmj
            );
        let err = |e: String| format!("{} with N = {n}: {e}", spec.label());
        if one_d {
            let b = sampler::build::<1>(&PatternSpec::simple(s, 1, n), shift).map_err(err)?;
            Ok(Offsets {
                two: None,
                one: Some(b.pattern),
                n,
            })
        } else {
            let b = sampler::build::<2>(&PatternSpec::simple(s, 2, n), shift).map_err(err)?;
            Ok(Offsets {
                two: Some(b.pattern),
                one: None,
                n,
            })
        }
    }

    /// Writes realisation `seed`'s offsets to `out` (length `N`).
    ///
    /// # Errors
    /// The pattern's error.
    pub fn fill(&self, seed: Seed, out: &mut Vec<[f32; 2]>) -> crate::Result<()> {
        out.resize(self.n, [0.5, 0.5]);
        if let Some(p) = &self.two {
            p.fill(seed, out)
                .map_err(|e| crate::LabError::Message(e.to_string()))
        } else if let Some(p) = &self.one {
            let mut one = vec![[0.0f32; 1]; self.n];
            p.fill(seed, &mut one)
                .map_err(|e| crate::LabError::Message(e.to_string()))?;
            for (o, u) in out.iter_mut().zip(&one) {
                *o = [u[0], 0.5];
            }
            Ok(())
        } else {
            Err("internal error: offsets without a pattern".into())
        }
    }
}

/// Sphere capacity of the `f32` line batch's prepared shading point.
pub const SIMD_SPHERES: usize = 32;

/// The shading geometry of one pixel.
pub struct Pixel {
    /// The shading point and its frame.
    pub frame: Frame,
    /// The `f32` batch's prepared point (`None` with more than
    /// [`SIMD_SPHERES`] spheres that can occlude it).
    ao32: Option<AoPoint32<SIMD_SPHERES>>,
}

/// What every estimate needs: the scene's spheres and its effect.
pub struct World {
    spheres: Vec<Sphere<3>>,
    max_distance: f64,
    scene: Scene,
}

impl World {
    /// The world of a checked scene, rendered at `width × height`.
    ///
    /// # Errors
    /// A sphere the kernel refuses.
    pub fn new(mut scene: Scene, width: u32, height: u32) -> crate::Result<Self> {
        scene.camera.width = width;
        scene.camera.height = height;
        let spheres = scene.kernel_spheres()?;
        let Effect::AmbientOcclusion { max_distance } = scene.effect else {
            return Err("not an ambient-occlusion scene".into());
        };
        Ok(World {
            spheres,
            max_distance,
            scene,
        })
    }

    /// The shading point of pixel `(x, y)` (camera ray through its centre),
    /// or `None` where the ray leaves the scene.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Option<Pixel> {
        let (o, d) = self
            .scene
            .camera
            .ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
        let hit = Scene::first_hit(&self.spheres, o, d)?;
        let frame = Frame::new(hit.point, hit.normal);
        let ao32 = AoPoint32::new(
            frame.point,
            frame.normal,
            frame.tangent,
            &self.spheres,
            self.max_distance,
        )
        .ok();
        Some(Pixel { frame, ao32 })
    }

    /// The estimate of `spec` from the offsets `uv`: the mean of its
    /// samples ([`ao::sample`]), or for `f32` SIMD lines the mean of
    /// `line_batch_f32` over `φ = πu` (summed in `f64`).
    ///
    /// # Errors
    /// A degenerate shading frame, or `f32` lines at a point with more than
    /// [`SIMD_SPHERES`] occluding spheres.
    pub fn estimate(
        &self,
        px: &Pixel,
        spec: &EstimatorSpec,
        uv: &[[f32; 2]],
        scratch: &mut [(f64, f64)],
    ) -> crate::Result<f64> {
        if spec.simd && spec.primitive == Primitive::Lines {
            let ao32 = px.ao32.as_ref().ok_or_else(|| {
                format!("f32 lines: more than {SIMD_SPHERES} spheres can occlude this point")
            })?;
            let (mut phis, mut out) = ([0.0f32; 64], [0.0f32; 64]);
            let mut sum = 0.0;
            for chunk in uv.chunks(64) {
                let k = chunk.len();
                for (f, p) in phis.iter_mut().zip(chunk) {
                    *f = std::f32::consts::PI * p[0];
                }
                ao32.line_batch_f32(&phis[..k], &mut out[..k])
                    .map_err(|e| crate::LabError::Message(e.to_string()))?;
                sum += out[..k].iter().map(|&x| f64::from(x)).sum::<f64>();
            }
            return Ok(sum / uv.len() as f64);
        }
        let est = spec.ao();
        let mut sum = 0.0;
        for p in uv {
            sum += ao::sample(
                &self.spheres,
                self.max_distance,
                &px.frame,
                &est,
                f64::from(p[0]),
                f64::from(p[1]),
                scratch,
            )
            .map_err(|e| format!("shading frame or scratch: {e}"))?;
        }
        Ok(sum / uv.len() as f64)
    }

    /// One sample's estimate at `(u, v)` ([`ao::sample`]).
    ///
    /// # Errors
    /// A degenerate shading frame.
    pub fn sample(
        &self,
        px: &Pixel,
        est: &AoEstimator,
        u: f64,
        v: f64,
        scratch: &mut [(f64, f64)],
    ) -> crate::Result<f64> {
        ao::sample(
            &self.spheres,
            self.max_distance,
            &px.frame,
            est,
            u,
            v,
            scratch,
        )
        .map_err(|e| format!("shading frame or scratch: {e}").into())
    }

    /// Number of spheres (scratch holds twice as many intervals).
    #[must_use]
    pub fn sphere_count(&self) -> usize {
        self.spheres.len()
    }

    pub(crate) fn scratch(&self) -> Vec<(f64, f64)> {
        vec![(0.0, 0.0); 2 * self.spheres.len()]
    }
}
