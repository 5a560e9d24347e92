//! The direct-light world of a scene: what a camera ray sees (the light or
//! a surface point), the shadows every other occluder casts on the light
//! from that point, and one estimate of the irradiance integral
//! `E = ∫_light G V dA` by points on the light or by lines across it
//! ([`super::DirectLight`], Billen & Dutré 2016; Singh, Miller & Jarosz 2017
//! §7.2), with the line orientation strategies the scene files name.
//!
//! Every quad and box casts shadows. A box is convex, so only its faces
//! turned towards a point can shadow it (a ray entering a convex box
//! crosses one of them first) and it never shadows its own points; a
//! free-standing quad is two-sided. Walls are quads too: in a convex room
//! one never stands between a point and a light on the room's boundary, and
//! its shadow then misses the light ([`Shadow::misses`]) and is dropped.

use alloc::boxed::Box;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use libm::{cos, sin};
use linesample::{Pcg32, Seed};

use super::{DirectLight, Parallelogram, QuadLight, Shadow};
use crate::direct_light_f32::DirectLight32;
use crate::model::{EffectParams, Orientation, Scene, SceneSampler};
use crate::vec3::{cross, dot, sub, unit};
use crate::Error;

/// One estimator: points on the light, or lines with an orientation
/// strategy, and the pattern of its samples.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DlEstimator {
    /// `None`: points; `Some(o)`: lines oriented by `o`.
    pub lines: Option<Orientation>,
    /// The pattern of the samples.
    pub sampler: SceneSampler,
    /// Lines only: the `f32` SIMD batch
    /// ([`crate::direct_light_f32::DirectLight32`]) instead of the `f64`
    /// closed form.
    #[cfg_attr(feature = "serde", serde(default))]
    pub simd: bool,
}

impl DlEstimator {
    /// `points` or `lines-<orientation>` (the `orientation.csv` name).
    #[must_use]
    pub fn name(&self) -> String {
        match self.lines {
            None => "points".into(),
            Some(o) if self.simd => alloc::format!("lines-{}-f32", o.name()),
            Some(o) => alloc::format!("lines-{}", o.name()),
        }
    }

    /// The name with the sampler.
    #[must_use]
    pub fn label(&self) -> String {
        alloc::format!("{} {}", self.name(), self.sampler.name())
    }

    /// Whether the estimator draws 2D pattern points (points, and lines
    /// whose direction and offset come from one 2D pattern).
    #[must_use]
    pub fn two_d(&self) -> bool {
        matches!(self.lines, None | Some(Orientation::Stratified))
    }
}

/// A surface of the scene: a parallelogram with a unit normal and albedo,
/// and the occluder it belongs to (its index in [`DlWorld`]'s occluders).
#[derive(Clone, Copy, Debug)]
struct Surface {
    face: Parallelogram,
    normal: [f64; 3],
    albedo: [f64; 3],
    solid: usize,
}

/// An occluder: a box (convex: only its faces turned towards a point can
/// shadow it, and never a point on the box itself) or a free-standing quad
/// (two-sided: it shadows points on either side). Walls are quads: one
/// never stands between a point of a convex room and a light on its
/// boundary, and its shadow then misses the light ([`Shadow::misses`]).
#[derive(Clone, Debug)]
struct Occluder {
    /// The faces, each with its unit outward normal (`None`: two-sided).
    faces: Vec<(Parallelogram, Option<[f64; 3]>)>,
}

/// What a pixel sees.
#[derive(Debug)]
pub enum Seen {
    /// The light itself: its radiance.
    Light,
    /// A surface point and what it needs for every estimate.
    Surface(Box<DlPixel>),
}

/// A pixel's surface point.
#[derive(Debug)]
pub struct DlPixel {
    /// The point.
    pub x: [f64; 3],
    /// Its unit shading normal (facing the camera).
    pub n: [f64; 3],
    /// Its albedo.
    pub albedo: [f64; 3],
    /// The occluder faces' shadows on the light.
    pub shadows: Vec<Shadow>,
    /// The `f32` batch's prepared receiver (`None` with more than
    /// [`SIMD_SHADOWS`] shadows).
    pub dl32: Option<DirectLight32<SIMD_SHADOWS>>,
}

/// Shadow capacity of the `f32` batch's prepared receiver.
pub const SIMD_SHADOWS: usize = 16;

/// The direct-light world of a scene: the light, every surface a camera
/// ray can hit, and the occluders whose shadows a surface point projects
/// onto the light.
#[derive(Debug)]
pub struct DlWorld {
    scene: Scene,
    light: QuadLight,
    surfaces: Vec<Surface>,
    /// The quads, then the boxes, as occluders.
    occluders: Vec<Occluder>,
}

impl DlWorld {
    /// The world of a checked `direct-light` scene at `width × height`.
    ///
    /// # Errors
    /// [`Error::WrongEffect`] for another effect or a scene without a
    /// light; [`Error::Item`] for geometry the kernel refuses.
    pub fn new(mut scene: Scene, width: u32, height: u32) -> Result<Self, Error> {
        let wrong = Error::WrongEffect {
            expected: "direct light (with a light)",
        };
        if scene.effect != EffectParams::DirectLight {
            return Err(wrong);
        }
        scene.camera.width = width;
        scene.camera.height = height;
        let l = scene.light.ok_or(wrong)?;
        let item = |what, index| move |error| Error::Item { what, index, error };
        let light = QuadLight::new(l.corner, l.edge1, l.edge2).map_err(item("light", 0))?;
        let mut surfaces = Vec::new();
        let mut occluders = Vec::new();
        for (i, q) in scene.quads.iter().enumerate() {
            let face = Parallelogram::new(q.corner, q.edge1, q.edge2).map_err(item("quad", i))?;
            surfaces.push(Surface {
                face,
                normal: unit(face.normal()),
                albedo: q.albedo,
                solid: occluders.len(),
            });
            occluders.push(Occluder {
                faces: vec![(face, None)],
            });
        }
        for (i, b) in scene.boxes.iter().enumerate() {
            let mut faces = Vec::new();
            for (c, e1, e2) in b.faces() {
                let face = Parallelogram::new(c, e1, e2).map_err(item("box", i))?;
                let normal = unit(face.normal());
                surfaces.push(Surface {
                    face,
                    normal,
                    albedo: b.albedo,
                    solid: occluders.len(),
                });
                faces.push((face, Some(normal)));
            }
            occluders.push(Occluder { faces });
        }
        Ok(DlWorld {
            scene,
            light,
            surfaces,
            occluders,
        })
    }

    /// The light.
    #[must_use]
    pub fn light(&self) -> &QuadLight {
        &self.light
    }

    /// The light's radiance.
    #[must_use]
    pub fn radiance(&self) -> [f64; 3] {
        self.scene.light.map_or([0.0; 3], |l| l.radiance)
    }

    /// What the camera ray through the centre of pixel `(x, y)` sees, or
    /// `None` (nothing).
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Option<Seen> {
        let (o, d) = self
            .scene
            .camera
            .ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
        self.trace(o, d)
    }

    /// What the ray `o + t d` sees first.
    #[must_use]
    pub fn trace(&self, o: [f64; 3], d: [f64; 3]) -> Option<Seen> {
        let mut best: Option<(f64, usize)> = None;
        for (i, s) in self.surfaces.iter().enumerate() {
            if let Some(t) = hit(&s.face, o, d) {
                if best.is_none_or(|(b, _)| t < b) {
                    best = Some((t, i));
                }
            }
        }
        let [u, v] = self.light.axes();
        let [l1, l2] = self.light.lengths();
        let light_face = Parallelogram::new(
            self.light.corner(),
            [u[0] * l1, u[1] * l1, u[2] * l1],
            [v[0] * l2, v[1] * l2, v[2] * l2],
        )
        .ok()?;
        if let Some(t) = hit(&light_face, o, d) {
            if best.is_none_or(|(b, _)| t < b) && dot(d, self.light.normal()) < 0.0 {
                return Some(Seen::Light);
            }
        }
        let (t, i) = best?;
        let s = &self.surfaces[i];
        let x = [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
        let n = if dot(s.normal, d) > 0.0 {
            [-s.normal[0], -s.normal[1], -s.normal[2]]
        } else {
            s.normal
        };
        Some(Seen::Surface(Box::new(self.surface_point(
            x,
            n,
            s.albedo,
            Some(s.solid),
        ))))
    }

    /// The shading data of surface point `x` with normal `n` on occluder
    /// `solid` (which cannot shadow it: a box is convex, and a quad does not
    /// shadow its own points). The others cast shadows: every quad, and the
    /// faces of each box that face `x` (a ray entering a convex box crosses
    /// one of them first). Shadows that miss the light are dropped.
    #[must_use]
    pub fn surface_point(
        &self,
        x: [f64; 3],
        n: [f64; 3],
        albedo: [f64; 3],
        solid: Option<usize>,
    ) -> DlPixel {
        let mut shadows = Vec::new();
        for (b, occ) in self.occluders.iter().enumerate() {
            if Some(b) == solid {
                continue;
            }
            for (f, nrm) in &occ.faces {
                if nrm.is_some_and(|m| dot(sub(x, f.corner()), m) <= 0.0) {
                    continue;
                }
                if let Some(s) = Shadow::project(&self.light, x, f) {
                    if !s.misses(&self.light) {
                        shadows.push(s);
                    }
                }
            }
        }
        let dl32 = DirectLight32::new(&self.light, x, n, &shadows).ok();
        DlPixel {
            x,
            n,
            albedo,
            shadows,
            dl32,
        }
    }

    /// One estimate of `E = ∫ G V dA` at `px` from the pattern values
    /// `vals` (`[u, v]` for 2D estimators, `[o, ·]` for the others), with
    /// `rng` for random orientations.
    ///
    /// # Errors
    /// A receiver the kernel refuses.
    pub fn estimate(
        &self,
        px: &DlPixel,
        est: &DlEstimator,
        vals: &[[f32; 2]],
        rng: &mut Pcg32,
        scratch: &mut Vec<(f64, f64)>,
    ) -> Result<f64, Error> {
        let dl = DirectLight::new(&self.light, px.x, px.n, &px.shadows)?;
        scratch.resize(dl.scratch_len(), (0.0, 0.0));
        let n = vals.len() as f64;
        let [l1, l2] = self.light.lengths();
        let line = |phi: f64, o01: f64, scratch: &mut Vec<(f64, f64)>| -> Result<f64, Error> {
            let (s, c) = (sin(phi), cos(phi));
            let (lo, hi) = self.light.offset_range(c, s);
            let w = hi - lo;
            Ok(match self.light.chord(c, s, lo + w * o01) {
                Some(ch) => w * dl.line(&ch, scratch)?,
                None => 0.0,
            })
        };
        let mut sum = 0.0;
        if est.simd {
            let Some(o) = est.lines else {
                return Err(Error::Unsupported {
                    what: "points through the f32 batch",
                });
            };
            let dl32 = px.dl32.as_ref().ok_or(Error::Capacity {
                what: "shadows",
                limit: SIMD_SHADOWS,
                got: px.shadows.len(),
            })?;
            let phi = match o {
                Orientation::Edge1 => 0.0,
                Orientation::Edge2 => core::f64::consts::FRAC_PI_2,
                Orientation::Angle(a) => a.to_radians(),
                _ => {
                    return Err(Error::Unsupported {
                        what: "random orientations through the f32 batch",
                    })
                }
            };
            let (sn, cs) = (sin(phi), cos(phi));
            let (lo, hi) = self.light.offset_range(cs, sn);
            let w = hi - lo;
            let (c32, s32) = ([cs as f32; 64], [sn as f32; 64]);
            let (mut offs, mut out) = ([0.0f32; 64], [0.0f32; 64]);
            for chunk in vals.chunks(64) {
                let k = chunk.len();
                for (o, p) in offs.iter_mut().zip(chunk) {
                    *o = (lo + w * f64::from(p[0])) as f32;
                }
                dl32.line_batch_f32(&c32[..k], &s32[..k], &offs[..k], &mut out[..k])?;
                sum += out[..k].iter().map(|&v| f64::from(v)).sum::<f64>();
            }
            return Ok(w * sum / n);
        }
        match est.lines {
            None => {
                for p in vals {
                    sum += dl.point(f64::from(p[0]) * l1, f64::from(p[1]) * l2);
                }
                sum *= self.light.area();
            }
            Some(Orientation::Stratified) => {
                for p in vals {
                    sum += line(
                        core::f64::consts::PI * f64::from(p[0]),
                        f64::from(p[1]),
                        scratch,
                    )?;
                }
            }
            Some(Orientation::RandomPerLine) => {
                for p in vals {
                    let phi = core::f64::consts::PI * unit_f64(rng.next_u32());
                    sum += line(phi, f64::from(p[0]), scratch)?;
                }
            }
            Some(o) => {
                let phi = match o {
                    Orientation::Edge1 => 0.0,
                    Orientation::Edge2 => core::f64::consts::FRAC_PI_2,
                    Orientation::Angle(a) => a.to_radians(),
                    _ => core::f64::consts::PI * unit_f64(rng.next_u32()),
                };
                for p in vals {
                    sum += line(phi, f64::from(p[0]), scratch)?;
                }
            }
        }
        Ok(sum / n)
    }

    /// The fraction of the light's area hidden from `px` (occluders only,
    /// not the tangent-plane clamp), from the exactly shadowed lengths of
    /// `lines` lines along the first edge at the midpoints of equal strata of
    /// offsets: a midpoint rule, exact up to `O(lines⁻²)`.
    ///
    /// # Errors
    /// A receiver the kernel refuses.
    pub fn hidden_fraction(&self, px: &DlPixel, lines: usize) -> Result<f64, Error> {
        let dl = DirectLight::new(&self.light, px.x, px.n, &px.shadows)?;
        let mut scratch = vec![(0.0, 0.0); dl.scratch_len()];
        let [l1, l2] = self.light.lengths();
        let mut hidden = 0.0;
        for k in 0..lines {
            let o = l2 * (k as f64 + 0.5) / lines as f64;
            let Some(ch) = self.light.chord(1.0, 0.0, o) else {
                continue;
            };
            let m = dl.shadowed(&ch, &mut scratch)?;
            let mut end = f64::NEG_INFINITY;
            for &(lo, hi) in &scratch[..m] {
                let lo = lo.max(end);
                if hi > lo {
                    hidden += hi - lo;
                }
                end = end.max(hi);
            }
        }
        Ok(hidden / (lines as f64 * l1))
    }

    /// How close a shadow edge on the light comes to each fixed orientation:
    /// the smallest angle (radians) between the light's first (second) edge
    /// and a shadow boundary segment that crosses at least a fifth of the
    /// light (the shorter side) and is not hidden under another shadow at
    /// its midpoint, with that segment's length; `(π/2, 0)` without such an
    /// edge. Lines parallel to a shadow edge see it as a jump of the line
    /// function; lines crossing it see a kink.
    #[must_use]
    pub fn edge_alignment(&self, px: &DlPixel) -> [(f64, f64); 2] {
        let mut best = [(core::f64::consts::FRAC_PI_2, 0.0); 2];
        let [l1, l2] = self.light.lengths();
        let min_len = 0.2 * l1.min(l2);
        for (si, sh) in px.shadows.iter().enumerate() {
            let planes = sh.planes();
            for (pi, p) in planes.iter().enumerate() {
                let norm = libm::hypot(p[0], p[1]);
                if norm == 0.0 {
                    continue;
                }
                let d = [-p[1] / norm, p[0] / norm];
                let p0 = [-p[2] * p[0] / (norm * norm), -p[2] * p[1] / (norm * norm)];
                let o = -p0[0] * d[1] + p0[1] * d[0];
                let Some(ch) = self.light.chord(d[0], d[1], o) else {
                    continue;
                };
                let (mut lo, mut hi) = (ch.t0, ch.t1);
                for (qi, q) in planes.iter().enumerate() {
                    if qi == pi {
                        continue;
                    }
                    let k = q[0] * d[0] + q[1] * d[1];
                    let m = q[0] * ch.p0[0] + q[1] * ch.p0[1] + q[2];
                    if k > 0.0 {
                        lo = lo.max(-m / k);
                    } else if k < 0.0 {
                        hi = hi.min(-m / k);
                    } else if m < 0.0 {
                        hi = lo;
                    }
                }
                if hi - lo < min_len {
                    continue;
                }
                let mid = ch.at(0.5 * (lo + hi));
                let covered = px
                    .shadows
                    .iter()
                    .enumerate()
                    .any(|(j, o)| j != si && o.contains(mid[0], mid[1]));
                if covered {
                    continue;
                }
                let phi = rem_pi(libm::atan2(d[1], d[0]));
                let a1 = phi.min(core::f64::consts::PI - phi);
                let a2 = (core::f64::consts::FRAC_PI_2 - phi).abs();
                if a1 < best[0].0 {
                    best[0] = (a1, hi - lo);
                }
                if a2 < best[1].0 {
                    best[1] = (a2, hi - lo);
                }
            }
        }
        best
    }

    /// The radiance factor `ρ/π · L_e` of a surface point (RGB).
    #[must_use]
    pub fn tint(&self, px: &DlPixel) -> [f64; 3] {
        let le = self.radiance();
        core::array::from_fn(|k| px.albedo[k] / core::f64::consts::PI * le[k])
    }
}

/// Ray–parallelogram hit parameter `t > 10⁻⁹`, or `None`.
fn hit(f: &Parallelogram, o: [f64; 3], d: [f64; 3]) -> Option<f64> {
    let [e1, e2] = f.edges();
    let n = f.normal();
    let den = dot(n, d);
    if den == 0.0 {
        return None;
    }
    let t = dot(n, sub(f.corner(), o)) / den;
    if t.partial_cmp(&1e-9) != Some(core::cmp::Ordering::Greater) {
        return None;
    }
    let p = sub(
        [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]],
        f.corner(),
    );
    // Dual basis: a = (p × e2)·n / |n|², b = (e1 × p)·n / |n|².
    let nn = dot(n, n);
    let a = dot(cross(p, e2), n) / nn;
    let b = dot(cross(e1, p), n) / nn;
    ((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b)).then_some(t)
}

/// A `u32` as a uniform number in `[0, 1)`.
fn unit_f64(u: u32) -> f64 {
    f64::from(u) * (1.0 / 4_294_967_296.0)
}

/// The reference estimator: lines along the light's first edge, 1D-jittered.
pub const REFERENCE: DlEstimator = DlEstimator {
    lines: Some(Orientation::Edge1),
    sampler: SceneSampler::Jittered,
    simd: false,
};

/// A realisation's random-orientation generator (its own purpose of the
/// realisation's seed, so orientations never reuse the pattern's stream).
#[must_use]
pub fn orient_rng(seed: Seed) -> linesample::Pcg32 {
    seed.pcg(0x0c1e_47a7)
}

/// The estimators of the images: [`estimators`], and the first fixed
/// orientation's lines once more through the `f32` SIMD batch
/// ([`crate::DirectLight32`]: what accuracy costs in time).
#[must_use]
pub fn image_estimators(scene: &Scene, sampler: SceneSampler) -> Vec<DlEstimator> {
    let mut v = estimators(scene, sampler);
    if let Some(e) = v.iter().find(|e| {
        matches!(
            e.lines,
            Some(Orientation::Edge1 | Orientation::Edge2 | Orientation::Angle(_))
        )
    }) {
        let f32 = DlEstimator { simd: true, ..*e };
        v.push(f32);
    }
    v
}

/// The estimators of a scene (points, then lines with each orientation), all
/// with `sampler`.
#[must_use]
pub fn estimators(scene: &Scene, sampler: SceneSampler) -> Vec<DlEstimator> {
    let mut v = vec![DlEstimator {
        lines: None,
        sampler,
        simd: false,
    }];
    for &o in &scene.estimators.orientations {
        v.push(DlEstimator {
            lines: Some(o),
            sampler,
            simd: false,
        });
    }
    v
}

/// `x` reduced to `[0, π)` (`x mod π`, as `f64::rem_euclid`, which `core`
/// lacks).
fn rem_pi(x: f64) -> f64 {
    let r = x % core::f64::consts::PI;
    if r < 0.0 {
        r + core::f64::consts::PI
    } else {
        r
    }
}

impl crate::Effect for DlWorld {
    const KIND: &'static str = "direct-light";
    type Scene = Scene;
    type Estimator = DlEstimator;
    type Query = DlPixel;
    /// A point on the light (`u` along the first edge, `v` the second), or
    /// a stratified line's `(direction φ = πu, offset v)`; lines of a given
    /// or random orientation read their offset from `u` alone.
    type Sample = [f32; 2];
    type Scratch = Vec<(f64, f64)>;

    fn from_scene(scene: Scene) -> Result<Self, Error> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        DlWorld::new(scene, w, h)
    }

    fn scratch(&self) -> Vec<(f64, f64)> {
        Vec::new()
    }

    fn reference() -> DlEstimator {
        REFERENCE
    }

    fn twin(est: DlEstimator) -> DlEstimator {
        DlEstimator { simd: false, ..est }
    }

    fn label(est: &DlEstimator) -> String {
        est.label()
    }

    fn sampler(est: &DlEstimator) -> SceneSampler {
        est.sampler
    }

    /// Points on the light and stratified lines (direction and offset from
    /// one pattern) need two coordinates; lines of a given orientation one
    /// (the offset).
    fn dims(&self, est: &DlEstimator) -> usize {
        if est.two_d() {
            2
        } else {
            1
        }
    }

    /// As [`SceneSampler::shifted`]: by default only Sobol′ (a shift would
    /// move a jittered pattern's strata off the light's edges, where the
    /// line function of lines along an edge, seen periodically, jumps: the
    /// two opposite edges carry different line integrals, capping jittered
    /// lines at `N⁻²`). The reference (jittered lines along an edge) is
    /// never shifted.
    fn shifted(est: Option<&DlEstimator>, shift: Option<bool>) -> bool {
        est.is_some_and(|e| e.sampler.shifted(shift))
    }

    fn estimate(
        &self,
        px: &DlPixel,
        est: &DlEstimator,
        samples: &[[f32; 2]],
        seed: Seed,
        scratch: &mut Vec<(f64, f64)>,
    ) -> Result<f64, Error> {
        let mut rng = orient_rng(seed);
        DlWorld::estimate(self, px, est, samples, &mut rng, scratch)
    }

    /// The fraction of the light hidden by occluders
    /// ([`DlWorld::hidden_fraction`] with 64 lines).
    fn extra(&self, px: &DlPixel) -> Result<Option<f32>, Error> {
        Ok(Some(self.hidden_fraction(px, 64)? as f32))
    }
}

impl crate::CameraEffect for DlWorld {
    /// Surface points only: a pixel that sees the light or nothing has no
    /// irradiance to estimate.
    fn pixel(&self, x: u32, y: u32) -> Option<DlPixel> {
        match DlWorld::pixel(self, x, y) {
            Some(Seen::Surface(px)) => Some(*px),
            _ => None,
        }
    }
}
