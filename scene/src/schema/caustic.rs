//! Volumetric-caustic scene files (`scenes/caustic-2d.toml`,
//! `scenes/caustic-3d.toml`): a point light emitting into a cone above a
//! glass ball in a homogeneous medium, and the query ball `Q` whose
//! in-scattered power photon points and photon beams estimate. Nothing else
//! is simulated: no camera, no surfaces, no other bounces.
//!
//! ```toml
//! [effect]
//! kind = "volumetric-caustic"
//! dims = 2                      # 2 (flatland) or 3; every vector has dims entries
//!
//! [light]                       # a point light emitting into a cone
//! position = [0.0, 2.0]
//! axis = [0.0, -1.0]
//! cone = 18.0                   # half-angle, degrees, in (0, 180]
//!
//! [glass]
//! centre = [0.0, 0.0]
//! radius = 0.5
//! ior = 1.5                     # relative to the medium, in [1, 10]
//! fresnel = true                # false: every photon refracts in and out
//! internal-reflections = 2      # with fresnel: reflections inside followed (≤ 8)
//!
//! [medium]                      # fills space outside the glass
//! sigma-s = 0.5
//! sigma-a = 0.1
//!
//! [query]                       # the ball Q scored
//! centre = [0.05, -1.0]
//! radius = 0.2
//!
//! [fluence]                     # the beam-rendered fluence image
//! centre = [0.0, -0.5]          # 3D: [x, y, z]; the slice is z = centre[2]
//! size = [3.0, 3.0]             # width and height in scene units
//! resolution = [512, 512]
//! beams = 262144
//! thickness = 0.02              # 3D only: the slab |z − centre[2]| < thickness/2
//!
//! [estimators]                  # optional; the default
//! samplers = ["random", "jittered"]
//! ```
//!
//! Every mistake is one error naming the file, line, column and field: TOML
//! syntax, an unknown or missing key, a vector of the wrong length, NaN or
//! infinity anywhere, a non-positive radius, size or resolution, a zero
//! axis, a cone out of range, an index below 1, negative coefficients, a
//! light inside the glass, too many internal reflections, fewer than 1024
//! fluence beams, a missing `thickness` in 3D (or one given in 2D), and a
//! sampler that cannot make the estimators' patterns.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;

use crate::caustic::MAX_INTERNAL_REFLECTIONS;
use serde::Deserialize;
use toml::Spanned;

use super::{Ctx, EffectKind, SceneError, SceneSampler};

/// The `[effect] kind` of a volumetric-caustic scene.
pub const KIND_NAME: &str = "volumetric-caustic";

use crate::model::{CausticScene, FluenceDef};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    effect: Spanned<RawEffect>,
    light: Spanned<RawLight>,
    glass: Spanned<RawGlass>,
    medium: Spanned<RawMedium>,
    query: Spanned<RawQuery>,
    fluence: Spanned<RawFluence>,
    estimators: Option<Spanned<RawEstimators>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEffect {
    /// Checked first, by [`crate::scene::effect_kind`].
    #[serde(rename = "kind")]
    _kind: serde::de::IgnoredAny,
    dims: Spanned<i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLight {
    position: Spanned<Vec<f64>>,
    axis: Spanned<Vec<f64>>,
    cone: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct RawGlass {
    centre: Spanned<Vec<f64>>,
    radius: Spanned<f64>,
    ior: Spanned<f64>,
    fresnel: Spanned<bool>,
    internal_reflections: Option<Spanned<i64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct RawMedium {
    sigma_s: Spanned<f64>,
    sigma_a: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawQuery {
    centre: Spanned<Vec<f64>>,
    radius: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFluence {
    centre: Spanned<Vec<f64>>,
    size: Spanned<[f64; 2]>,
    resolution: Spanned<[i64; 2]>,
    beams: Spanned<i64>,
    thickness: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEstimators {
    samplers: Option<Spanned<Vec<Spanned<String>>>>,
}

fn vector(
    ctx: &Ctx<'_>,
    field: &str,
    v: &Spanned<Vec<f64>>,
    dims: usize,
) -> Result<[f64; 3], SceneError> {
    let x = v.get_ref();
    if x.len() != dims {
        return Err(ctx.at(
            v.span(),
            field,
            format!(
                "must have {dims} components (dims = {dims}), got {}",
                x.len()
            ),
        ));
    }
    if let Some(j) = x.iter().position(|c| !c.is_finite()) {
        return Err(ctx.at(
            v.span(),
            field,
            format!("component {j} must be a finite number, got {}", x[j]),
        ));
    }
    let mut out = [0.0; 3];
    out[..dims].copy_from_slice(x);
    Ok(out)
}

fn positive(ctx: &Ctx<'_>, field: &str, v: &Spanned<f64>) -> Result<f64, SceneError> {
    let x = ctx.finite(field, v)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(ctx.at(v.span(), field, format!("must be positive, got {x}")))
    }
}

/// The glass: centre, radius, index of refraction, Fresnel and internal
/// reflections.
fn parse_glass(
    ctx: &Ctx<'_>,
    g: &RawGlass,
    dims: usize,
) -> Result<([f64; 3], f64, f64, bool, u32), SceneError> {
    let glass_centre = vector(ctx, "glass.centre", &g.centre, dims)?;
    let glass_radius = positive(ctx, "glass.radius", &g.radius)?;
    let ior = ctx.finite("glass.ior", &g.ior)?;
    if !(1.0..=10.0).contains(&ior) {
        return Err(ctx.at(
            g.ior.span(),
            "glass.ior",
            format!("must be in [1, 10] (relative to the medium), got {ior}"),
        ));
    }
    let fresnel = *g.fresnel.get_ref();
    let internal_reflections = match &g.internal_reflections {
        None => 0,
        Some(k) => {
            if !fresnel {
                return Err(ctx.at(
                    k.span(),
                    "glass.internal-reflections",
                    "needs fresnel = true (without Fresnel nothing reflects)".into(),
                ));
            }
            let v = *k.get_ref();
            if !(0..=i64::from(MAX_INTERNAL_REFLECTIONS)).contains(&v) {
                return Err(ctx.at(
                    k.span(),
                    "glass.internal-reflections",
                    format!("must be in 0..={MAX_INTERNAL_REFLECTIONS}, got {v}"),
                ));
            }
            v as u32
        }
    };
    Ok((
        glass_centre,
        glass_radius,
        ior,
        fresnel,
        internal_reflections,
    ))
}

/// The medium's scattering and absorption coefficients.
fn parse_medium(ctx: &Ctx<'_>, m: &RawMedium) -> Result<(f64, f64), SceneError> {
    let sigma_s = ctx.finite("medium.sigma-s", &m.sigma_s)?;
    let sigma_a = ctx.finite("medium.sigma-a", &m.sigma_a)?;
    for (x, f, sp) in [
        (sigma_s, "medium.sigma-s", m.sigma_s.span()),
        (sigma_a, "medium.sigma-a", m.sigma_a.span()),
    ] {
        if !(0.0..=1e6).contains(&x) {
            return Err(ctx.at(sp, f, format!("must be in [0, 1e6], got {x}")));
        }
    }
    if sigma_s <= 0.0 {
        return Err(ctx.at(
            m.sigma_s.span(),
            "medium.sigma-s",
            "must be positive: a medium that scatters nothing has no caustic".into(),
        ));
    }
    Ok((sigma_s, sigma_a))
}

/// The fluence image's frame.
fn parse_fluence(
    ctx: &Ctx<'_>,
    raw: &Spanned<RawFluence>,
    dims: usize,
) -> Result<FluenceDef, SceneError> {
    let f = raw.get_ref();
    let centre = vector(ctx, "fluence.centre", &f.centre, dims)?;
    let size = *f.size.get_ref();
    if size.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(ctx.at(
            f.size.span(),
            "fluence.size",
            format!("both sides must be positive, got {size:?}"),
        ));
    }
    let [w, h] = *f.resolution.get_ref();
    for (v, name) in [(w, "width"), (h, "height")] {
        if !(1..=8192).contains(&v) {
            return Err(ctx.at(
                f.resolution.span(),
                "fluence.resolution",
                format!("{name} must be in 1..=8192, got {v}"),
            ));
        }
    }
    let beams = *f.beams.get_ref();
    if !(1024..=1 << 32).contains(&beams) {
        return Err(ctx.at(
            f.beams.span(),
            "fluence.beams",
            format!("must be in 1024..=2^32, got {beams}"),
        ));
    }
    let thickness = match (&f.thickness, dims) {
        (None, 2) => None,
        (Some(t), 2) => {
            return Err(ctx.at(
                t.span(),
                "fluence.thickness",
                "is for 3D scenes (the 2D image is the whole plane)".into(),
            ))
        }
        (None, _) => {
            return Err(ctx.at(
                raw.span(),
                "fluence.thickness",
                "missing (a 3D fluence image is a slab of this thickness)".into(),
            ))
        }
        (Some(t), _) => Some(positive(ctx, "fluence.thickness", t)?),
    };
    Ok(FluenceDef {
        centre,
        size,
        width: w as u32,
        height: h as u32,
        beams: beams as u64,
        thickness,
    })
}

/// Checks the text of a caustic scene file (`path` names it in errors).
///
/// # Errors
/// A [`SceneError`] naming the file, line, column and field.
pub fn parse(file: &str, text: &str) -> Result<CausticScene, SceneError> {
    let ctx = Ctx { file, text };
    let kind = super::effect_kind(file, text)?;
    if kind != EffectKind::VolumetricCaustic {
        return Err(ctx.at(
            0..0,
            "effect.kind",
            format!("expected '{KIND_NAME}', got '{}'", kind.name()),
        ));
    }
    let raw: Raw = toml::from_str(text).map_err(|e| ctx.toml_error(&e))?;
    let e = raw.effect.get_ref();
    let dims = match *e.dims.get_ref() {
        2 => 2,
        3 => 3,
        d => {
            return Err(ctx.at(
                e.dims.span(),
                "effect.dims",
                format!("must be 2 or 3, got {d}"),
            ))
        }
    };
    let l = raw.light.get_ref();
    let light = vector(&ctx, "light.position", &l.position, dims)?;
    let axis = vector(&ctx, "light.axis", &l.axis, dims)?;
    if axis.iter().all(|&c| c == 0.0) {
        return Err(ctx.at(l.axis.span(), "light.axis", "is the zero vector".into()));
    }
    let cone_deg = ctx.finite("light.cone", &l.cone)?;
    if !(cone_deg > 1e-9 && cone_deg <= 180.0) {
        return Err(ctx.at(
            l.cone.span(),
            "light.cone",
            format!("the half-angle must be in (0, 180] degrees, got {cone_deg}"),
        ));
    }
    let g = raw.glass.get_ref();
    let (glass_centre, glass_radius, ior, fresnel, internal_reflections) =
        parse_glass(&ctx, g, dims)?;
    let d2: f64 = (0..dims)
        .map(|j| {
            let d = light[j] - glass_centre[j];
            d * d
        })
        .sum();
    if libm::sqrt(d2) <= glass_radius {
        return Err(ctx.at(
            l.position.span(),
            "light.position",
            "is inside the glass (the light must be in the medium)".into(),
        ));
    }
    let (sigma_s, sigma_a) = parse_medium(&ctx, raw.medium.get_ref())?;
    let q = raw.query.get_ref();
    let query_centre = vector(&ctx, "query.centre", &q.centre, dims)?;
    let query_radius = positive(&ctx, "query.radius", &q.radius)?;
    let fluence = parse_fluence(&ctx, &raw.fluence, dims)?;
    let samplers = match raw
        .estimators
        .as_ref()
        .and_then(|e| e.get_ref().samplers.as_ref())
    {
        None => vec![SceneSampler::Random, SceneSampler::Jittered],
        Some(list) => {
            let known = [
                ("random", SceneSampler::Random),
                ("jittered", SceneSampler::Jittered),
                ("sobol", SceneSampler::Sobol),
            ];
            ctx.names("estimators.samplers", list, &known)?
        }
    };
    let scene = CausticScene {
        dims,
        light,
        axis,
        cone_deg,
        glass_centre,
        glass_radius,
        ior,
        fresnel,
        internal_reflections,
        sigma_s,
        sigma_a,
        query_centre,
        query_radius,
        fluence,
        samplers,
    };
    // The kernel's own checks (ranges it enforces beyond the above).
    let kernel = if dims == 2 {
        scene.kernel::<2>().map(|_| ())
    } else {
        scene.kernel::<3>().map(|_| ())
    };
    kernel.map_err(|e| ctx.at(raw.glass.span(), "(scene)", e.to_string()))?;
    Ok(scene)
}
