//! The ambient-occlusion world of a scene: the shading point a camera ray
//! finds on the spheres, its frame, and one estimate of
//! `AO = (1/π) ∫_0^π dφ ∫_{−π/2}^{π/2} V(φ, θ) |sin θ| cos θ dθ` from a
//! row's sample offsets (points, segments or lines in the half-plane
//! parameterisation, [`super::sample`]; lines also through the `f32` SIMD
//! batch, [`crate::occlusion_f32::AoPoint32`]).

use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use linesample::world::Sphere;

use super::{AoEstimator, CentrePdf, Frame, Sample};
use crate::ao;
use crate::model::{EffectParams, Primitive, Scene, SceneSampler};
use crate::occlusion_f32::AoPoint32;
use crate::{Error, HalfPlane};

/// One estimator of a scene: primitive, segment length (segments), centre
/// density (points and segments) and sampler.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EstimatorSpec {
    /// Points, segments or lines.
    pub primitive: Primitive,
    /// Segment length in `θ` (segments; 0 otherwise).
    pub length: f64,
    /// Density of the sample centres (points and segments).
    pub pdf: CentrePdf,
    /// The pattern of the samples.
    pub sampler: SceneSampler,
    /// Lines only: the `f32` SIMD batch
    /// ([`crate::occlusion_f32::AoPoint32::line_batch_f32`]) instead of
    /// the `f64` closed form.
    #[cfg_attr(feature = "serde", serde(default))]
    pub simd: bool,
}

impl EstimatorSpec {
    /// The estimator at a shading point ([`super::sample`]).
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
            Primitive::Segments if (self.length - core::f64::consts::PI).abs() < 1e-12 => {
                "segments-pi".into()
            }
            Primitive::Segments => alloc::format!("segments-{}", self.length),
            Primitive::Lines if self.simd => "lines-f32".into(),
            p => p.name().into(),
        }
    }

    /// `segments-0.1 uniform jittered` (lines have no density).
    #[must_use]
    pub fn label(&self) -> String {
        match self.primitive {
            Primitive::Lines if self.simd => {
                alloc::format!("lines f32-simd {}", self.sampler.name())
            }
            Primitive::Lines => alloc::format!("lines {}", self.sampler.name()),
            _ => alloc::format!(
                "{} {} {}",
                self.stem(),
                self.pdf.name(),
                self.sampler.name()
            ),
        }
    }
}

/// Sphere capacity of the `f32` line batch's prepared shading point.
pub const SIMD_SPHERES: usize = 32;

/// The shading geometry of one pixel.
#[derive(Debug)]
pub struct Pixel {
    /// The shading point and its frame.
    pub frame: Frame,
    /// The `f32` batch's prepared point (`None` with more than
    /// [`SIMD_SPHERES`] spheres that can occlude it).
    ao32: Option<AoPoint32<SIMD_SPHERES>>,
}

/// What every estimate needs: the scene's spheres and its effect.
#[derive(Debug)]
pub struct World {
    spheres: Vec<Sphere<3>>,
    max_distance: f64,
    scene: Scene,
}

impl World {
    /// The world of a checked scene, rendered at `width × height`.
    ///
    /// # Errors
    /// [`Error::Item`] for a sphere the kernel refuses,
    /// [`Error::WrongEffect`] for a scene of another effect.
    pub fn new(mut scene: Scene, width: u32, height: u32) -> Result<Self, Error> {
        scene.camera.width = width;
        scene.camera.height = height;
        let spheres = scene.kernel_spheres()?;
        let EffectParams::AmbientOcclusion { max_distance } = scene.effect else {
            return Err(Error::WrongEffect {
                expected: "ambient occlusion",
            });
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
    ) -> Result<f64, Error> {
        if spec.simd && spec.primitive == Primitive::Lines {
            let ao32 = px.ao32.as_ref().ok_or(Error::Capacity {
                what: "spheres that can occlude the point",
                limit: SIMD_SPHERES,
                got: self.spheres.len(),
            })?;
            let (mut phis, mut out) = ([0.0f32; 64], [0.0f32; 64]);
            let mut sum = 0.0;
            for chunk in uv.chunks(64) {
                let k = chunk.len();
                for (f, p) in phis.iter_mut().zip(chunk) {
                    *f = core::f32::consts::PI * p[0];
                }
                ao32.line_batch_f32(&phis[..k], &mut out[..k])?;
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
            )?;
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
    ) -> Result<f64, Error> {
        Ok(ao::sample(
            &self.spheres,
            self.max_distance,
            &px.frame,
            est,
            u,
            v,
            scratch,
        )?)
    }

    /// Number of spheres (scratch holds twice as many intervals).
    #[must_use]
    pub fn sphere_count(&self) -> usize {
        self.spheres.len()
    }

    /// Fresh scratch for [`World::estimate`] and [`World::sample`].
    #[must_use]
    pub fn scratch(&self) -> Vec<(f64, f64)> {
        vec![(0.0, 0.0); 2 * self.spheres.len()]
    }
}

/// Ambient occlusion at a shading point by the line estimator: the mean over
/// the azimuths `phis` (each in `[0, π)`) of the whole half-plane's visible
/// cosine weight ([`crate::HalfPlane::visible`]), i.e.
/// `(1/N)Σ_k ∫_{−π/2}^{π/2} V(φ_k, θ)|sin θ| cos θ dθ`, an unbiased estimate
/// of `AO = (1/π)∫_0^π dφ ∫ V|sin θ| cos θ dθ` for uniform `φ_k`.
///
/// # Errors
/// A degenerate normal ([`Error::Param`]).
pub fn ao_lines(
    spheres: &[Sphere<3>],
    max_distance: f64,
    point: [f64; 3],
    normal: [f64; 3],
    phis: &[f64],
) -> Result<f64, Error> {
    let t = Frame::new(point, normal).tangent;
    let mut scratch = vec![(0.0, 0.0); 2 * spheres.len()];
    let mut sum = 0.0;
    for &phi in phis {
        let hp = HalfPlane::at_azimuth(point, normal, t, phi)?;
        let half = core::f64::consts::FRAC_PI_2;
        sum += hp.visible(spheres, max_distance, -half, half, &mut scratch)?;
    }
    Ok(sum / phis.len() as f64)
}

/// The AO reference estimator: lines with 1D-jittered azimuths.
pub const REFERENCE: EstimatorSpec = EstimatorSpec {
    primitive: Primitive::Lines,
    length: 0.0,
    pdf: CentrePdf::Uniform,
    sampler: SceneSampler::Jittered,
    simd: false,
};

impl crate::Effect for World {
    const KIND: &'static str = "ambient-occlusion";
    type Scene = Scene;
    type Estimator = EstimatorSpec;
    type Query = Pixel;
    /// `(u, v)`: the azimuth `φ = πu` and the centre angle (lines read `u`).
    type Sample = [f32; 2];
    type Scratch = Vec<(f64, f64)>;

    fn from_scene(scene: Scene) -> Result<Self, Error> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        World::new(scene, w, h)
    }

    fn scratch(&self) -> Vec<(f64, f64)> {
        World::scratch(self)
    }

    fn reference() -> EstimatorSpec {
        REFERENCE
    }

    fn twin(est: EstimatorSpec) -> EstimatorSpec {
        EstimatorSpec { simd: false, ..est }
    }

    fn label(est: &EstimatorSpec) -> String {
        est.label()
    }

    fn sampler(est: &EstimatorSpec) -> SceneSampler {
        est.sampler
    }

    /// Lines need one coordinate (the azimuth); points and segments two
    /// (azimuth and centre angle).
    fn dims(&self, est: &EstimatorSpec) -> usize {
        if est.primitive == Primitive::Lines {
            1
        } else {
            2
        }
    }

    /// Every pattern, the reference's too, is shifted unless the caller
    /// says not to. (The line function `L(φ)` has period `π`, so a shift of
    /// the azimuths costs lines nothing; for points and segments the shift
    /// puts a seam at `φ = 0`.)
    fn shifted(_est: Option<&EstimatorSpec>, shift: Option<bool>) -> bool {
        shift.unwrap_or(true)
    }

    fn estimate(
        &self,
        px: &Pixel,
        est: &EstimatorSpec,
        samples: &[[f32; 2]],
        _seed: linesample::Seed,
        scratch: &mut Vec<(f64, f64)>,
    ) -> Result<f64, Error> {
        World::estimate(self, px, est, samples, scratch)
    }
}

impl crate::CameraEffect for World {
    fn pixel(&self, x: u32, y: u32) -> Option<Pixel> {
        World::pixel(self, x, y)
    }
}
