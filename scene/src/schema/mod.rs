//! Declarative scene files: the geometry, the camera and the **one** effect
//! a scene asks to estimate, with the estimators to compare.
//!
//! A scene is a TOML file (`scenes/ao-spheres.toml` is the paper's ambient
//! occlusion scene):
//!
//! ```toml
//! [camera]
//! from = [1.0, 1.0, 10.0]   # eye
//! at = [0.0, 0.0, -1.0]     # the point looked at
//! up = [0.0, 1.0, 0.0]
//! fov = 40.0                # vertical, degrees
//! resolution = [512, 512]   # width, height
//!
//! [[sphere]]
//! centre = [0.0, -1000.0, 0.0]
//! radius = 1000.0
//!
//! [effect]
//! kind = "ambient-occlusion"
//! max-distance = 500.0
//!
//! [estimators]              # optional; these are the defaults
//! primitives = ["points", "segments", "lines"]
//! segment-lengths = [0.001, 0.1, 1.0, 3.141592653589793]
//! pdfs = ["uniform", "solid-angle", "cosine"]
//! samplers = ["random", "jittered", "multi-jittered", "cmj", "sobol"]
//! ```
//!
//! A `direct-light` scene (`scenes/cornell-box.toml`) has quads (walls, or
//! free-standing panels: every quad and box casts shadows), boxes and one
//! rectangular light instead of spheres:
//!
//! ```toml
//! [light]                       # emits towards edge1 × edge2
//! corner = [-0.24, 1.98, -0.22]
//! edge1 = [0.47, 0.0, 0.0]      # orthogonal edges
//! edge2 = [0.0, 0.0, 0.38]
//! radiance = [17.0, 12.0, 4.0]
//!
//! [[quad]]                      # corner + a·edge1 + b·edge2, a, b ∈ [0, 1]
//! corner = [-1.0, 0.0, -1.0]
//! edge1 = [0.0, 0.0, 2.0]
//! edge2 = [2.0, 0.0, 0.0]
//! albedo = [0.73, 0.73, 0.73]
//!
//! [[box]]                       # standing on its base, rotated about +y
//! base = [-0.33, 0.0, 0.30]     # centre of the base
//! size = [0.6, 0.6, 0.6]        # width, height, depth
//! rotation = 17.0               # degrees
//! albedo = [0.73, 0.73, 0.73]
//!
//! [effect]
//! kind = "direct-light"
//!
//! [estimators]                  # optional; these are the defaults
//! samplers = ["random", "jittered", "multi-jittered", "cmj", "sobol"]
//! orientations = ["edge1", "edge2", "random-per-point", "random-per-line", "stratified"]
//! ```
//!
//! (`angle-<degrees>` is a further orientation: lines at that angle from
//! `edge1`.)
//!
//! Every mistake is an error naming the file, the line and column, and the
//! field: a TOML syntax error, an unknown key, a missing field, a value of
//! the wrong type, NaN or an infinite number anywhere, a radius, field of
//! view, resolution, distance, segment length, albedo, radiance or box size
//! out of range, a degenerate camera (`from = at`, `up` along the view), a
//! degenerate quad or light (parallel or non-orthogonal edges), an unknown
//! effect, primitive, pdf, sampler or orientation name, an empty list, no
//! sphere (ambient occlusion) or no light (direct light), and every table
//! or field the effect does not use (a quad, box, light or orientation in
//! an AO scene; a sphere, max-distance, primitive, pdf or segment length
//! in a direct-light scene).
//!
//! One entry reads every effect: [`parse_any`] reads `[effect] kind` first
//! ([`effect_kind`]) and then that effect's schema: [`parse`] for the
//! camera effects, [`caustic::parse`] for the volumetric caustic (no
//! camera). They share one error type and one source context, so every
//! error has the same form.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::fmt;
use core::ops::Range;

use serde::Deserialize;
use toml::Spanned;

pub mod caustic;

use crate::model::CausticScene;

/// A scene file's mistake: where it is and what is wrong. Converts into
/// [`linesample::Error`] (as [`linesample::Error::Other`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The scene file, as the caller named it.
    pub file: String,
    /// 1-based line (0 when the file could not be read).
    pub line: usize,
    /// 1-based column (0 when the file could not be read).
    pub column: usize,
    /// The field, as a path (`sphere[3].radius`, `camera.fov`), or the key
    /// the TOML reader stopped at.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}: {}",
            self.file, self.line, self.column, self.field, self.message
        )
    }
}

impl core::error::Error for SceneError {}

/// A scene file's mistake as the kernel's [`linesample::Error::Other`]
/// (boxed, with the same text), as [`crate::Error`] converts.
impl From<SceneError> for linesample::Error {
    fn from(e: SceneError) -> Self {
        linesample::Error::other(e)
    }
}

use crate::ao::CentrePdf;
use crate::camera::Camera;
use crate::model::{
    BoxDef, EffectParams, Estimators, LightDef, Orientation, Primitive, QuadDef, Scene,
    SceneSampler, SphereDef,
};
use crate::vec3::{cross, dot, norm2, sub};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    camera: Spanned<RawCamera>,
    #[serde(default)]
    sphere: Vec<Spanned<RawSphere>>,
    #[serde(default)]
    quad: Vec<Spanned<RawQuad>>,
    #[serde(default, rename = "box")]
    boxes: Vec<Spanned<RawBox>>,
    light: Option<Spanned<RawLight>>,
    effect: Spanned<RawEffect>,
    estimators: Option<Spanned<RawEstimators>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    from: Spanned<[f64; 3]>,
    at: Spanned<[f64; 3]>,
    up: Spanned<[f64; 3]>,
    fov: Spanned<f64>,
    resolution: Spanned<[i64; 2]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSphere {
    centre: Spanned<[f64; 3]>,
    radius: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawQuad {
    corner: Spanned<[f64; 3]>,
    edge1: Spanned<[f64; 3]>,
    edge2: Spanned<[f64; 3]>,
    albedo: Spanned<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBox {
    base: Spanned<[f64; 3]>,
    size: Spanned<[f64; 3]>,
    rotation: Spanned<f64>,
    albedo: Spanned<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLight {
    corner: Spanned<[f64; 3]>,
    edge1: Spanned<[f64; 3]>,
    edge2: Spanned<[f64; 3]>,
    radiance: Spanned<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct RawEffect {
    kind: Spanned<String>,
    max_distance: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct RawEstimators {
    primitives: Option<Spanned<Vec<Spanned<String>>>>,
    segment_lengths: Option<Spanned<Vec<Spanned<f64>>>>,
    pdfs: Option<Spanned<Vec<Spanned<String>>>>,
    samplers: Option<Spanned<Vec<Spanned<String>>>>,
    orientations: Option<Spanned<Vec<Spanned<String>>>>,
}

/// The effect a scene file asks for: its `[effect] kind`, the one field
/// every scene file has and the one that decides how the rest is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EffectKind {
    /// `ambient-occlusion`.
    AmbientOcclusion,
    /// `direct-light`.
    DirectLight,
    /// `volumetric-caustic` (read by [`caustic::parse`]).
    VolumetricCaustic,
}

impl EffectKind {
    /// Every effect, in the order error messages list them.
    pub const ALL: [EffectKind; 3] = [
        EffectKind::AmbientOcclusion,
        EffectKind::DirectLight,
        EffectKind::VolumetricCaustic,
    ];

    /// The name in scene files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            EffectKind::AmbientOcclusion => "ambient-occlusion",
            EffectKind::DirectLight => "direct-light",
            EffectKind::VolumetricCaustic => "volumetric-caustic",
        }
    }

    /// `ambient-occlusion, direct-light, volumetric-caustic`.
    #[must_use]
    pub fn known() -> String {
        Self::ALL.map(Self::name).join(", ")
    }
}

#[derive(Deserialize)]
struct KindHead {
    effect: Option<Spanned<KindEffect>>,
}

#[derive(Deserialize)]
struct KindEffect {
    kind: Option<Spanned<toml::Value>>,
}

/// Reads `[effect] kind` alone, before any other field is looked at, so that
/// a misspelt kind is reported as such (not as the first field the wrong
/// reader does not know).
///
/// # Errors
/// A TOML syntax error, no `[effect]` table or no `kind`, a kind that is
/// not a string, or an unknown kind (the message lists the known ones).
pub fn effect_kind(file: &str, text: &str) -> Result<EffectKind, SceneError> {
    let ctx = Ctx { file, text };
    if let Err(e) = text.parse::<toml::Table>() {
        let mut err = ctx.toml_error(&e);
        err.field = "TOML syntax".into();
        return Err(err);
    }
    let head: KindHead = toml::from_str(text).map_err(|e| ctx.toml_error(&e))?;
    let known = EffectKind::known();
    let Some(effect) = head.effect else {
        return Err(ctx.at(
            0..0,
            "effect",
            format!("missing: the scene needs an [effect] table with a kind (one of {known})"),
        ));
    };
    let Some(kind) = &effect.get_ref().kind else {
        return Err(ctx.at(
            effect.span(),
            "effect.kind",
            format!("missing (one of {known})"),
        ));
    };
    let Some(name) = kind.get_ref().as_str() else {
        return Err(ctx.at(
            kind.span(),
            "effect.kind",
            format!("must be a string, one of {known}"),
        ));
    };
    EffectKind::ALL
        .into_iter()
        .find(|k| k.name() == name)
        .ok_or_else(|| {
            ctx.at(
                kind.span(),
                "effect.kind",
                format!("unknown effect '{name}' (known: {known})"),
            )
        })
}

/// A checked scene file of any effect.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneFile {
    /// Ambient occlusion or direct light, seen through a camera.
    Camera(Scene),
    /// A volumetric caustic (no camera: a query ball).
    Caustic(CausticScene),
}

/// Checks the text of a scene file of any effect: `[effect] kind` first
/// ([`effect_kind`]), then that effect's schema ([`parse`] or
/// [`caustic::parse`]); every table or field the effect does not use is
/// an error naming it.
///
/// # Errors
/// A [`SceneError`] naming the file, line, column and field.
pub fn parse_any(file: &str, text: &str) -> Result<SceneFile, SceneError> {
    Ok(match effect_kind(file, text)? {
        EffectKind::VolumetricCaustic => SceneFile::Caustic(caustic::parse(file, text)?),
        _ => SceneFile::Camera(parse(file, text)?),
    })
}

/// Checks the text of a camera scene file (ambient occlusion or direct
/// light; `path` names it in errors).
///
/// # Errors
/// A [`SceneError`] naming the file, line, column and field.
pub fn parse(file: &str, text: &str) -> Result<Scene, SceneError> {
    let ctx = Ctx { file, text };
    // Syntax and the effect's kind first (their errors name no other
    // field), then the structure.
    let kind = effect_kind(file, text)?;
    if kind == EffectKind::VolumetricCaustic {
        return Err(ctx.at(
            0..0,
            "effect.kind",
            "a volumetric-caustic scene has no camera: read it with scene::caustic::parse".into(),
        ));
    }
    let raw: RawScene = toml::from_str(text).map_err(|e| ctx.toml_error(&e))?;
    unused(&ctx, kind, &raw)?;
    let camera = parse_camera(&ctx, &raw.camera)?;
    let spheres = parse_spheres(&ctx, &raw.sphere)?;
    let quads = parse_quads(&ctx, &raw.quad)?;
    let boxes = parse_boxes(&ctx, &raw.boxes)?;
    let light = raw
        .light
        .as_ref()
        .map(|l| parse_light(&ctx, l))
        .transpose()?;
    let effect = parse_effect(&ctx, kind, &raw)?;
    let estimators = match &raw.estimators {
        Some(est) => parse_estimators(&ctx, est.get_ref())?,
        None => Estimators::default(),
    };
    Ok(Scene {
        camera,
        spheres,
        quads,
        boxes,
        light,
        effect,
        estimators,
    })
}

/// The tables and fields `kind` does not use: each is an error naming it
/// (ambient occlusion is spheres alone; direct light is quads, boxes and a
/// light, with orientations and samplers to compare).
fn unused(ctx: &Ctx<'_>, kind: EffectKind, raw: &RawScene) -> Result<(), SceneError> {
    let name = kind.name();
    let not = |span: Range<usize>, field: &str, why: &str| {
        Err(ctx.at(span, field, format!("{name} does not use it ({why})")))
    };
    let est = raw.estimators.as_ref().map(Spanned::get_ref);
    match kind {
        EffectKind::AmbientOcclusion => {
            if let Some(q) = raw.quad.first() {
                return not(q.span(), "quad", "its occluders are [[sphere]]s");
            }
            if let Some(b) = raw.boxes.first() {
                return not(b.span(), "box", "its occluders are [[sphere]]s");
            }
            if let Some(l) = &raw.light {
                return not(l.span(), "light", "the sky is the light: it needs none");
            }
            if let Some(o) = est.and_then(|e| e.orientations.as_ref()) {
                return not(
                    o.span(),
                    "estimators.orientations",
                    "lines turn about the normal",
                );
            }
        }
        EffectKind::DirectLight => {
            if let Some(s) = raw.sphere.first() {
                return not(
                    s.span(),
                    "sphere",
                    "direct-light scenes are made of [[quad]]s and [[box]]es (spheres are not \
                     supported as occluders)",
                );
            }
            if let Some(md) = &raw.effect.get_ref().max_distance {
                return not(md.span(), "effect.max-distance", "nothing is cut off");
            }
            for (field, v) in [
                (
                    "estimators.primitives",
                    est.and_then(|e| e.primitives.as_ref().map(Spanned::span)),
                ),
                (
                    "estimators.pdfs",
                    est.and_then(|e| e.pdfs.as_ref().map(Spanned::span)),
                ),
                (
                    "estimators.segment-lengths",
                    est.and_then(|e| e.segment_lengths.as_ref().map(Spanned::span)),
                ),
            ] {
                if let Some(span) = v {
                    return not(
                        span,
                        field,
                        "points on the light and lines across it are compared",
                    );
                }
            }
        }
        EffectKind::VolumetricCaustic => {}
    }
    Ok(())
}

fn parse_camera(ctx: &Ctx<'_>, raw: &Spanned<RawCamera>) -> Result<Camera, SceneError> {
    let c = raw.get_ref();
    let from = ctx.finite3("camera.from", &c.from)?;
    let at = ctx.finite3("camera.at", &c.at)?;
    let up = ctx.finite3("camera.up", &c.up)?;
    let fov = ctx.finite("camera.fov", &c.fov)?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(ctx.at(
            c.fov.span(),
            "camera.fov",
            format!("must be in (0, 180) degrees, got {fov}"),
        ));
    }
    let view = sub(at, from);
    if norm2(view) == 0.0 {
        return Err(ctx.at(
            c.at.span(),
            "camera.at",
            "equals camera.from: no view direction".into(),
        ));
    }
    let side = cross(view, up);
    if norm2(side) <= 1e-24 * norm2(view) * norm2(up) {
        return Err(ctx.at(
            c.up.span(),
            "camera.up",
            "is zero or parallel to the view direction".into(),
        ));
    }
    let [w, h] = *c.resolution.get_ref();
    for (v, name) in [(w, "width"), (h, "height")] {
        if !(1..=65_536).contains(&v) {
            return Err(ctx.at(
                c.resolution.span(),
                "camera.resolution",
                format!("{name} must be in 1..=65536, got {v}"),
            ));
        }
    }
    Ok(Camera {
        from,
        at,
        up,
        fov_deg: fov,
        width: w as u32,
        height: h as u32,
    })
}

fn parse_spheres(ctx: &Ctx<'_>, raw: &[Spanned<RawSphere>]) -> Result<Vec<SphereDef>, SceneError> {
    let mut spheres = Vec::with_capacity(raw.len());
    for (i, s) in raw.iter().enumerate() {
        let s = s.get_ref();
        let centre = ctx.finite3(&format!("sphere[{i}].centre"), &s.centre)?;
        let radius = ctx.finite(&format!("sphere[{i}].radius"), &s.radius)?;
        if radius <= 0.0 {
            return Err(ctx.at(
                s.radius.span(),
                &format!("sphere[{i}].radius"),
                format!("must be positive, got {radius}"),
            ));
        }
        spheres.push(SphereDef { centre, radius });
    }
    Ok(spheres)
}

fn parse_quads(ctx: &Ctx<'_>, raw: &[Spanned<RawQuad>]) -> Result<Vec<QuadDef>, SceneError> {
    let mut quads = Vec::with_capacity(raw.len());
    for (i, q) in raw.iter().enumerate() {
        let q = q.get_ref();
        let corner = ctx.finite3(&format!("quad[{i}].corner"), &q.corner)?;
        let edge1 = ctx.finite3(&format!("quad[{i}].edge1"), &q.edge1)?;
        let edge2 = ctx.finite3(&format!("quad[{i}].edge2"), &q.edge2)?;
        if norm2(cross(edge1, edge2)) <= 1e-24 * norm2(edge1) * norm2(edge2)
            || norm2(cross(edge1, edge2)) == 0.0
        {
            return Err(ctx.at(
                q.edge2.span(),
                &format!("quad[{i}].edge2"),
                "is zero or parallel to edge1".into(),
            ));
        }
        let albedo = ctx.albedo(&format!("quad[{i}].albedo"), &q.albedo)?;
        quads.push(QuadDef {
            corner,
            edge1,
            edge2,
            albedo,
        });
    }
    Ok(quads)
}

fn parse_boxes(ctx: &Ctx<'_>, raw: &[Spanned<RawBox>]) -> Result<Vec<BoxDef>, SceneError> {
    let mut boxes = Vec::with_capacity(raw.len());
    for (i, b) in raw.iter().enumerate() {
        let b = b.get_ref();
        let base = ctx.finite3(&format!("box[{i}].base"), &b.base)?;
        let size = ctx.finite3(&format!("box[{i}].size"), &b.size)?;
        if size.iter().any(|&x| x <= 0.0) {
            return Err(ctx.at(
                b.size.span(),
                &format!("box[{i}].size"),
                format!("every side must be positive, got {size:?}"),
            ));
        }
        let rotation_deg = ctx.finite(&format!("box[{i}].rotation"), &b.rotation)?;
        let albedo = ctx.albedo(&format!("box[{i}].albedo"), &b.albedo)?;
        boxes.push(BoxDef {
            base,
            size,
            rotation_deg,
            albedo,
        });
    }
    Ok(boxes)
}

fn parse_light(ctx: &Ctx<'_>, raw: &Spanned<RawLight>) -> Result<LightDef, SceneError> {
    let l = raw.get_ref();
    let corner = ctx.finite3("light.corner", &l.corner)?;
    let edge1 = ctx.finite3("light.edge1", &l.edge1)?;
    let edge2 = ctx.finite3("light.edge2", &l.edge2)?;
    let (n1, n2) = (libm::sqrt(norm2(edge1)), libm::sqrt(norm2(edge2)));
    if n1 == 0.0 || n2 == 0.0 {
        return Err(ctx.at(
            l.edge1.span(),
            "light.edge1",
            "the light's edges must be non-zero".into(),
        ));
    }
    let cosine = dot(edge1, edge2) / (n1 * n2);
    if cosine.abs() > 1e-9 {
        return Err(ctx.at(
            l.edge2.span(),
            "light.edge2",
            format!("must be orthogonal to light.edge1 (cosine {cosine:.3e})"),
        ));
    }
    let radiance = ctx.finite3("light.radiance", &l.radiance)?;
    if radiance.iter().any(|&x| x < 0.0) {
        return Err(ctx.at(
            l.radiance.span(),
            "light.radiance",
            format!("must be non-negative, got {radiance:?}"),
        ));
    }
    Ok(LightDef {
        corner,
        edge1,
        edge2,
        radiance,
    })
}

fn parse_effect(
    ctx: &Ctx<'_>,
    kind: EffectKind,
    raw: &RawScene,
) -> Result<EffectParams, SceneError> {
    let e = raw.effect.get_ref();
    match kind {
        EffectKind::AmbientOcclusion => {
            let Some(md) = &e.max_distance else {
                return Err(ctx.at(
                    raw.effect.span(),
                    "effect.max-distance",
                    "missing (ambient-occlusion needs it)".into(),
                ));
            };
            let d = ctx.finite("effect.max-distance", md)?;
            if d <= 0.0 {
                return Err(ctx.at(
                    md.span(),
                    "effect.max-distance",
                    format!("must be positive, got {d}"),
                ));
            }
            if raw.sphere.is_empty() {
                return Err(ctx.at(0..0, "sphere", "the scene has no [[sphere]]".into()));
            }
            Ok(EffectParams::AmbientOcclusion { max_distance: d })
        }
        EffectKind::DirectLight => {
            if raw.light.is_none() {
                return Err(ctx.at(
                    raw.effect.span(),
                    "light",
                    "direct-light needs a [light]".into(),
                ));
            }
            Ok(EffectParams::DirectLight)
        }
        EffectKind::VolumetricCaustic => Err(ctx.at(
            e.kind.span(),
            "effect.kind",
            "a volumetric-caustic scene has no camera".into(),
        )),
    }
}

fn parse_estimators(ctx: &Ctx<'_>, est: &RawEstimators) -> Result<Estimators, SceneError> {
    let mut estimators = Estimators::default();
    if let Some(p) = &est.primitives {
        estimators.primitives = ctx.names(
            "estimators.primitives",
            p,
            &[
                ("points", Primitive::Points),
                ("segments", Primitive::Segments),
                ("lines", Primitive::Lines),
            ],
        )?;
    }
    if let Some(p) = &est.pdfs {
        estimators.pdfs = ctx.names(
            "estimators.pdfs",
            p,
            &[
                ("uniform", CentrePdf::Uniform),
                ("solid-angle", CentrePdf::SolidAngle),
                ("cosine", CentrePdf::Cosine),
            ],
        )?;
    }
    if let Some(p) = &est.samplers {
        estimators.samplers = ctx.names(
            "estimators.samplers",
            p,
            &[
                ("random", SceneSampler::Random),
                ("jittered", SceneSampler::Jittered),
                ("multi-jittered", SceneSampler::MultiJittered),
                ("cmj", SceneSampler::Cmj),
                ("sobol", SceneSampler::Sobol),
            ],
        )?;
    }
    if let Some(o) = &est.orientations {
        estimators.orientations = parse_orientations(ctx, o)?;
    }
    if let Some(l) = &est.segment_lengths {
        if l.get_ref().is_empty() {
            return Err(ctx.at(l.span(), "estimators.segment-lengths", "is empty".into()));
        }
        let mut v = Vec::new();
        for (i, x) in l.get_ref().iter().enumerate() {
            let name = format!("estimators.segment-lengths[{i}]");
            let len = ctx.finite(&name, x)?;
            // π as written to 16 digits (3.141592653589793) is the line.
            if !(len > 0.0 && len <= core::f64::consts::PI) {
                return Err(ctx.at(x.span(), &name, format!("must be in (0, π], got {len}")));
            }
            v.push(len);
        }
        estimators.segment_lengths = v;
    }
    Ok(estimators)
}

fn parse_orientations(
    ctx: &Ctx<'_>,
    o: &Spanned<Vec<Spanned<String>>>,
) -> Result<Vec<Orientation>, SceneError> {
    if o.get_ref().is_empty() {
        return Err(ctx.at(o.span(), "estimators.orientations", "is empty".into()));
    }
    let mut v = Vec::new();
    for (i, n) in o.get_ref().iter().enumerate() {
        let Some(or) = Orientation::parse(n.get_ref()) else {
            return Err(ctx.at(
                n.span(),
                &format!("estimators.orientations[{i}]"),
                format!(
                    "unknown orientation '{}' (known: edge1, edge2, angle-<degrees>, \
                     random-per-point, random-per-line, stratified)",
                    n.get_ref()
                ),
            ));
        };
        v.push(or);
    }
    Ok(v)
}

pub(crate) struct Ctx<'a> {
    pub(crate) file: &'a str,
    pub(crate) text: &'a str,
}

impl Ctx<'_> {
    /// 1-based line and column of a byte offset.
    fn line_col(&self, at: usize) -> (usize, usize) {
        let at = at.min(self.text.len());
        let before = &self.text[..at];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, col)
    }

    pub(crate) fn at(&self, span: Range<usize>, field: &str, message: String) -> SceneError {
        let (line, column) = if span.is_empty() && span.start == 0 {
            (1, 1)
        } else {
            self.line_col(span.start)
        };
        SceneError {
            file: self.file.into(),
            line,
            column,
            field: field.to_string(),
            message,
        }
    }

    /// A TOML reader error: the field is the one its message names in
    /// backticks (unknown or missing fields), else the key on the line it
    /// points at.
    pub(crate) fn toml_error(&self, e: &toml::de::Error) -> SceneError {
        let span = e.span().unwrap_or(0..0);
        let msg = e.message().trim().to_string();
        let named = msg
            .split('`')
            .nth(1)
            .filter(|_| msg.contains("field"))
            .map(ToString::to_string);
        let field = named.unwrap_or_else(|| {
            let start = self.text[..span.start.min(self.text.len())]
                .rfind('\n')
                .map_or(0, |i| i + 1);
            let line = self.text[start..].lines().next().unwrap_or("").trim();
            match line.split_once('=') {
                Some((k, _)) => k.trim().to_string(),
                None => line.to_string(),
            }
        });
        let mut err = self.at(span, &field, msg);
        if err.line == 1 && err.column == 1 && e.span().is_none() {
            err.line = 0;
            err.column = 0;
        }
        err
    }

    pub(crate) fn finite(&self, field: &str, v: &Spanned<f64>) -> Result<f64, SceneError> {
        let x = *v.get_ref();
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.at(v.span(), field, format!("must be a finite number, got {x}")))
        }
    }

    fn finite3(&self, field: &str, v: &Spanned<[f64; 3]>) -> Result<[f64; 3], SceneError> {
        let x = *v.get_ref();
        if let Some(j) = x.iter().position(|c| !c.is_finite()) {
            return Err(self.at(
                v.span(),
                field,
                format!("component {j} must be a finite number, got {}", x[j]),
            ));
        }
        Ok(x)
    }

    fn albedo(&self, field: &str, v: &Spanned<[f64; 3]>) -> Result<[f64; 3], SceneError> {
        let x = self.finite3(field, v)?;
        if x.iter().any(|c| !(0.0..=1.0).contains(c)) {
            return Err(self.at(
                v.span(),
                field,
                format!("every channel must be in [0, 1], got {x:?}"),
            ));
        }
        Ok(x)
    }

    pub(crate) fn names<T: Copy>(
        &self,
        field: &str,
        list: &Spanned<Vec<Spanned<String>>>,
        known: &[(&str, T)],
    ) -> Result<Vec<T>, SceneError> {
        if list.get_ref().is_empty() {
            return Err(self.at(list.span(), field, "is empty".into()));
        }
        let mut out = Vec::new();
        for (i, n) in list.get_ref().iter().enumerate() {
            let Some(&(_, v)) = known.iter().find(|(k, _)| k == n.get_ref()) else {
                let names: Vec<&str> = known.iter().map(|(k, _)| *k).collect();
                return Err(self.at(
                    n.span(),
                    &format!("{field}[{i}]"),
                    format!(
                        "unknown name '{}' (known: {})",
                        n.get_ref(),
                        names.join(", ")
                    ),
                ));
            };
            out.push(v);
        }
        Ok(out)
    }
}
