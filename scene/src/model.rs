//! The scene model every effect is built from: a camera, the geometry
//! (spheres, parallelograms, boxes, one rectangular light), the **one**
//! effect a scene asks for and the estimators it compares, every value
//! already checked (finite, in range, non-degenerate).
//!
//! A scene file reader (the lab's TOML reader is one) fills these types;
//! the effects ([`crate::effect::Effect`]) build their worlds from them and
//! use exactly the geometry their effect needs. The vocabulary
//! ([`Primitive`], [`SceneSampler`], [`crate::ao::CentrePdf`],
//! [`Orientation`]) derives `serde` (feature `serde`) and
//! `clap::ValueEnum` (feature `clap`) here, once.

use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use linesample::world::{Ray, Sphere};

use crate::ao::CentrePdf;
use crate::camera::Camera;
use crate::caustic::{Caustic, ConeEmitter, Fresnel, Glass, Medium};
use crate::vec3::{add, unit};
use crate::Error;

/// The sample primitive of an estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Primitive {
    /// Points.
    Points,
    /// Segments of a given length centred at the points.
    Segments,
    /// Whole lines through (or offset by) the points.
    Lines,
}

impl Primitive {
    /// The name on a command line and in scene files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Primitive::Points => "points",
            Primitive::Segments => "segments",
            Primitive::Lines => "lines",
        }
    }
}

/// The sample pattern of a scene's estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum SceneSampler {
    /// Independent uniform points.
    Random,
    /// Jittered (stratified).
    Jittered,
    /// Multi-jittered (Chiu, Shirley & Wang 1994).
    MultiJittered,
    /// Correlated multi-jittered (Kensler 2013).
    Cmj,
    /// Owen-scrambled Sobol′.
    Sobol,
}

impl SceneSampler {
    /// Whether this sampler's pattern gets a random toroidal shift per
    /// realisation when the caller asks `shift` (`None`: the default). By
    /// default only Sobol′ is shifted: the other patterns are random by
    /// construction, and a shift would move jittered strata off a light's
    /// edges, where a line function seen periodically jumps. Sobol′ without
    /// a shift stays randomised by its per-realisation Owen scramble. The
    /// direct-light and caustic scenes follow this rule.
    #[must_use]
    pub fn shifted(self, shift: Option<bool>) -> bool {
        shift.unwrap_or(self == SceneSampler::Sobol)
    }

    /// The name a scene file uses.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SceneSampler::Random => "random",
            SceneSampler::Jittered => "jittered",
            SceneSampler::MultiJittered => "multi-jittered",
            SceneSampler::Cmj => "cmj",
            SceneSampler::Sobol => "sobol",
        }
    }
}

/// A sphere of the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereDef {
    /// Centre.
    pub centre: [f64; 3],
    /// Radius, positive.
    pub radius: f64,
}

/// A parallelogram of the scene (a wall or a free-standing panel):
/// `corner + a·edge1 + b·edge2`, `a, b ∈ [0, 1]`, diffuse with an RGB
/// albedo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadDef {
    /// The corner.
    pub corner: [f64; 3],
    /// First edge.
    pub edge1: [f64; 3],
    /// Second edge (not parallel to the first).
    pub edge2: [f64; 3],
    /// Diffuse albedo, each channel in `[0, 1]`.
    pub albedo: [f64; 3],
}

/// A box standing on its base, rotated about the vertical `y` axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxDef {
    /// The centre of its base.
    pub base: [f64; 3],
    /// Width (x), height (y) and depth (z) before the rotation, positive.
    pub size: [f64; 3],
    /// Rotation about `+y`, degrees (counter-clockwise seen from above).
    pub rotation_deg: f64,
    /// Diffuse albedo, each channel in `[0, 1]`.
    pub albedo: [f64; 3],
}

impl BoxDef {
    /// The six faces as parallelograms `(corner, edge1, edge2)` with
    /// outward normals `edge1 × edge2`. The rotation by `ψ` about `+y` maps
    /// `(x, z)` to `(x cos ψ + z sin ψ, −x sin ψ + z cos ψ)`.
    #[must_use]
    pub fn faces(&self) -> [([f64; 3], [f64; 3], [f64; 3]); 6] {
        let psi = self.rotation_deg.to_radians();
        let (s, c) = (libm::sin(psi), libm::cos(psi));
        let ex = [c * self.size[0], 0.0, -s * self.size[0]];
        let ey = [0.0, self.size[1], 0.0];
        let ez = [s * self.size[2], 0.0, c * self.size[2]];
        let o = [
            self.base[0] - 0.5 * (ex[0] + ez[0]),
            self.base[1],
            self.base[2] - 0.5 * (ex[2] + ez[2]),
        ];
        let (ox, oy, oz) = (add(o, ex), add(o, ey), add(o, ez));
        [
            (o, ex, ez),  // bottom: ex × ez = −y
            (oy, ez, ex), // top: ez × ex = +y
            (o, ey, ex),  // the z-min side: ey × ex = −z
            (oz, ex, ey), // the z-max side: ex × ey = +z
            (o, ez, ey),  // the x-min side: ez × ey = −x
            (ox, ey, ez), // the x-max side: ey × ez = +x
        ]
    }
}

/// The scene's rectangular area light: corner, orthogonal edges, emitting
/// towards `edge1 × edge2`, with an RGB radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightDef {
    /// The corner.
    pub corner: [f64; 3],
    /// First edge ("orientation 1" lines run along it).
    pub edge1: [f64; 3],
    /// Second edge, orthogonal to the first.
    pub edge2: [f64; 3],
    /// Emitted radiance, RGB, non-negative.
    pub radiance: [f64; 3],
}

/// How the lines of a direct-light line estimator are oriented on the
/// light (Billen & Dutré 2016; Singh, Miller & Jarosz 2017 §7.2).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Orientation {
    /// Along the light's first edge (offsets along the second).
    Edge1,
    /// Along the light's second edge.
    Edge2,
    /// At a fixed angle from the first edge, degrees.
    Angle(f64),
    /// One uniformly random direction per estimate (per shading point).
    RandomPerPoint,
    /// An independent random direction per line.
    RandomPerLine,
    /// Directions and offsets from one 2D pattern: `(φ/π, offset)`.
    Stratified,
}

impl Orientation {
    /// The name a scene file uses (`edge1`, `angle-30`, …).
    #[must_use]
    pub fn name(self) -> String {
        match self {
            Orientation::Edge1 => "edge1".into(),
            Orientation::Edge2 => "edge2".into(),
            Orientation::Angle(a) => alloc::format!("angle-{a}"),
            Orientation::RandomPerPoint => "random-per-point".into(),
            Orientation::RandomPerLine => "random-per-line".into(),
            Orientation::Stratified => "stratified".into(),
        }
    }

    /// Parses a name (`angle-<degrees>` with a finite angle).
    #[must_use]
    pub fn parse(name: &str) -> Option<Orientation> {
        match name {
            "edge1" => Some(Orientation::Edge1),
            "edge2" => Some(Orientation::Edge2),
            "random-per-point" => Some(Orientation::RandomPerPoint),
            "random-per-line" => Some(Orientation::RandomPerLine),
            "stratified" => Some(Orientation::Stratified),
            _ => {
                let a: f64 = name.strip_prefix("angle-")?.parse().ok()?;
                a.is_finite().then_some(Orientation::Angle(a))
            }
        }
    }
}

/// The one effect a camera scene estimates, with its parameters (the
/// volumetric caustic has no camera; its scene is
/// [`CausticScene`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EffectParams {
    /// Cosine-weighted ambient occlusion, normalised to 1 when nothing
    /// occludes, counting hits up to `max_distance`.
    AmbientOcclusion {
        /// Largest distance at which a sphere occludes.
        max_distance: f64,
    },
    /// Direct light from the scene's one rectangular light onto diffuse
    /// surfaces: no indirect bounces, no specular, no medium.
    DirectLight,
}

/// The estimators a scene compares.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimators {
    /// Primitives.
    pub primitives: Vec<Primitive>,
    /// Segment lengths in `θ`, in `(0, π]` (`π` is the whole line).
    pub segment_lengths: Vec<f64>,
    /// Centre densities.
    pub pdfs: Vec<CentrePdf>,
    /// Samplers.
    pub samplers: Vec<SceneSampler>,
    /// Line orientations (direct light).
    pub orientations: Vec<Orientation>,
}

impl Default for Estimators {
    fn default() -> Self {
        Self {
            primitives: vec![Primitive::Points, Primitive::Segments, Primitive::Lines],
            segment_lengths: vec![0.001, 0.1, 1.0, core::f64::consts::PI],
            pdfs: vec![CentrePdf::Uniform, CentrePdf::SolidAngle, CentrePdf::Cosine],
            samplers: vec![
                SceneSampler::Random,
                SceneSampler::Jittered,
                SceneSampler::MultiJittered,
                SceneSampler::Cmj,
                SceneSampler::Sobol,
            ],
            orientations: vec![
                Orientation::Edge1,
                Orientation::Edge2,
                Orientation::RandomPerPoint,
                Orientation::RandomPerLine,
                Orientation::Stratified,
            ],
        }
    }
}

/// A checked camera scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    /// The spheres (at least one for ambient occlusion).
    pub spheres: Vec<SphereDef>,
    /// Walls and other parallelograms.
    pub quads: Vec<QuadDef>,
    /// Boxes.
    pub boxes: Vec<BoxDef>,
    /// The area light (direct light needs it).
    pub light: Option<LightDef>,
    /// The effect to estimate.
    pub effect: EffectParams,
    /// The estimators to compare.
    pub estimators: Estimators,
}

/// Where a camera ray meets the scene's spheres first: the shading point,
/// its unit outward normal and the sphere's index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The point.
    pub point: [f64; 3],
    /// The unit outward normal.
    pub normal: [f64; 3],
    /// Index of the sphere in [`Scene::spheres`].
    pub sphere: usize,
}

impl Scene {
    /// The scene's spheres as kernel spheres.
    ///
    /// # Errors
    /// [`Error::Item`] for a radius outside the kernel's `[1e−100, 1e100]`.
    pub fn kernel_spheres(&self) -> Result<Vec<Sphere<3>>, Error> {
        self.spheres
            .iter()
            .enumerate()
            .map(|(index, s)| {
                Sphere::new(s.centre, s.radius).map_err(|error| Error::Item {
                    what: "sphere",
                    index,
                    error,
                })
            })
            .collect()
    }

    /// The first of `spheres` the ray `origin + t·dir`, `t > 0`, meets
    /// ([`Sphere::hit`]: the nearer root with `t > 0`), or `None` (also for
    /// a zero or non-finite direction).
    #[must_use]
    pub fn first_hit(spheres: &[Sphere<3>], origin: [f64; 3], dir: [f64; 3]) -> Option<Hit> {
        let ray = Ray::new(origin, dir).ok()?;
        let mut best: Option<(f64, usize)> = None;
        for (i, s) in spheres.iter().enumerate() {
            if let Some((t0, t1)) = s.hit(&ray) {
                let t = if t0 > 0.0 { t0 } else { t1 };
                if t > 0.0 && best.is_none_or(|(b, _)| t < b) {
                    best = Some((t, i));
                }
            }
        }
        let (t, i) = best?;
        let point = ray.at(t);
        let c = spheres[i].centre();
        let r = spheres[i].radius();
        let normal = unit([
            (point[0] - c[0]) / r,
            (point[1] - c[1]) / r,
            (point[2] - c[2]) / r,
        ]);
        Some(Hit {
            point,
            normal,
            sphere: i,
        })
    }
}

/// A checked volumetric-caustic scene: a point light emitting into a cone,
/// a glass ball in a homogeneous medium, the query ball scored and the
/// fluence image's frame. Vectors are padded to 3 components; `dims` says
/// how many count.
#[derive(Clone, Debug, PartialEq)]
pub struct CausticScene {
    /// 2 (flatland) or 3.
    pub dims: usize,
    /// The light's position.
    pub light: [f64; 3],
    /// The cone's axis (non-zero).
    pub axis: [f64; 3],
    /// The cone's half-angle, degrees, in `(0, 180]`.
    pub cone_deg: f64,
    /// The glass ball's centre.
    pub glass_centre: [f64; 3],
    /// The glass ball's radius, positive.
    pub glass_radius: f64,
    /// The glass's index of refraction relative to the medium, in `[1, 10]`.
    pub ior: f64,
    /// Fresnel splitting (`false`: every photon refracts in and out).
    pub fresnel: bool,
    /// With Fresnel splitting, the reflections inside the glass followed.
    pub internal_reflections: u32,
    /// The medium's scattering coefficient.
    pub sigma_s: f64,
    /// The medium's absorption coefficient.
    pub sigma_a: f64,
    /// The query ball's centre.
    pub query_centre: [f64; 3],
    /// The query ball's radius, positive.
    pub query_radius: f64,
    /// The fluence image.
    pub fluence: FluenceDef,
    /// The samplers compared.
    pub samplers: Vec<SceneSampler>,
}

/// The frame of a volumetric-caustic scene's fluence image.
#[derive(Clone, Debug, PartialEq)]
pub struct FluenceDef {
    /// The image's centre (3D: the slice is `z = centre[2]`).
    pub centre: [f64; 3],
    /// Width and height in scene units.
    pub size: [f64; 2],
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Photon beams traced.
    pub beams: u64,
    /// 3D: the thickness of the slab `|z − centre[2]| < thickness/2`.
    pub thickness: Option<f64>,
}

impl CausticScene {
    /// The effect's closed-form scene ([`Caustic`]) in `D` dimensions
    /// (`D` must be [`CausticScene::dims`]).
    ///
    /// # Errors
    /// A parameter the kernel rejects, or [`linesample::ParamError::Dimension`]
    /// when `D ≠ dims`.
    pub fn kernel<const D: usize>(&self) -> Result<Caustic<D>, Error> {
        if D != self.dims {
            return Err(Error::Param(linesample::ParamError::Dimension { dim: D }));
        }
        let v = |a: &[f64; 3]| -> [f64; D] { core::array::from_fn(|j| a[j]) };
        let light =
            ConeEmitter::<D>::new(v(&self.light), v(&self.axis), self.cone_deg.to_radians())?;
        let glass = Glass::<D>::new(v(&self.glass_centre), self.glass_radius, self.ior)?;
        let medium = Medium::new(self.sigma_s, self.sigma_a)?;
        let query = Sphere::<D>::new(v(&self.query_centre), self.query_radius)?;
        let fresnel = if self.fresnel {
            Fresnel::On {
                internal_reflections: self.internal_reflections,
            }
        } else {
            Fresnel::Off
        };
        Ok(Caustic::new(light, glass, medium, query, fresnel)?)
    }
}
