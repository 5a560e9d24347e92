//! The renderer-side kernel of the `render` example: camera rays through a
//! pixel row, jittered by a random-access [`Sequence`] per pixel, optical depth
//! of a scene of homogeneous spheres and Gaussian puffs by the `f32` SIMD
//! closed forms, and per-channel transmittance `T = e^{−τ}`.
//!
//! No allocation and no `std`: every buffer is a caller slice, so this file
//! also compiles into the `no_std` check crate (`tools/nostd-check`).

use linesample::primitive::Rays32;
use linesample::sequence::{pixel_seed, Sequence};
use linesample::world::{Direction, Gaussian, Sphere};
use linesample::{ParamError, Seed};

/// A pinhole camera: ray `k` of pixel `(x, y)` (pbrt's convention, `(0, 0)` at
/// the top left) leaves `eye` along `forward + (2u/W − 1)·right +
/// (1 − 2v/H)·up`, `(u, v)` the jittered position in the pixel.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    /// Eye position.
    pub eye: [f32; 3],
    /// Unit view direction.
    pub forward: [f32; 3],
    /// Right vector, scaled by `tan(fov/2)·aspect`.
    pub right: [f32; 3],
    /// Up vector, scaled by `tan(fov/2)`.
    pub up: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Camera {
    /// A camera at `eye` looking at `target` with vertical field of view
    /// `fov_deg` degrees.
    ///
    /// # Errors
    /// [`ParamError`] if `eye = target` or `up` is parallel to the view.
    pub fn look_at(
        eye: [f64; 3],
        target: [f64; 3],
        up: [f64; 3],
        fov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, ParamError> {
        let f = Direction::new([target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]])?.get();
        let r = Direction::new(cross(f, up))?.get();
        let u = cross(r, f);
        let th = libm::tan(0.5 * fov_deg.to_radians());
        let aspect = f64::from(width) / f64::from(height);
        Ok(Self {
            eye: eye.map(|x| x as f32),
            forward: f.map(|x| x as f32),
            right: r.map(|x| (x * th * aspect) as f32),
            up: u.map(|x| (x * th) as f32),
            width,
            height,
        })
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A homogeneous sphere of coloured absorbing medium: extinction `sigma` per
/// unit length in each RGB channel.
#[derive(Clone, Copy, Debug)]
pub struct Ball {
    /// The shape.
    pub sphere: Sphere<3>,
    /// Extinction per channel.
    pub sigma: [f32; 3],
}

/// A Gaussian puff of medium: density `A·e^{−|x−c|²/2σ²}` times an extinction
/// per channel.
#[derive(Clone, Copy, Debug)]
pub struct Puff {
    /// The density.
    pub density: Gaussian<3>,
    /// Extinction per unit density, per channel.
    pub sigma: [f32; 3],
}

/// What the renderer integrates: absorbing media in front of a background.
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    /// Homogeneous spheres.
    pub balls: &'a [Ball],
    /// Gaussian puffs.
    pub puffs: &'a [Puff],
}

/// Caller-owned structure-of-arrays buffers for one row: `width·spp` rays.
#[derive(Debug)]
pub struct RowScratch<'a> {
    /// Ray origins, per coordinate.
    pub origin: [&'a mut [f32]; 3],
    /// Ray directions, per coordinate.
    pub dir: [&'a mut [f32]; 3],
    /// `t0 = 0` per ray.
    pub t0: &'a mut [f32],
    /// `t1 = ∞` per ray.
    pub t1: &'a mut [f32],
    /// One shape's integral per ray.
    pub value: &'a mut [f32],
    /// Optical depth per ray, per channel.
    pub tau: [&'a mut [f32]; 3],
}

/// The scratch length of a row: `width · spp` `f32`s per buffer (12 buffers).
#[must_use]
pub fn row_scratch_len(width: u32, spp: u32) -> usize {
    width as usize * spp as usize
}

/// Where a pixel's camera rays go: point `k < spp` of `seq`, seeded per pixel
/// by [`pixel_seed`]`(seed, x, y, 0)`.
#[derive(Clone, Copy, Debug)]
pub struct PixelSampler<'a, S> {
    /// The random-access sequence (e.g. Owen-scrambled Sobol').
    pub seq: &'a S,
    /// The image seed.
    pub seed: Seed,
    /// Samples per pixel.
    pub spp: u32,
}

/// Renders row `y`: the mean transmittance of each pixel over `spp` camera rays
/// (the pixel positions drawn by `sampler`), written as RGB into `out` (length `width`).
///
/// # Errors
/// [`ParamError::Length`] if a buffer has the wrong length; a pattern error
/// from the sequence (e.g. `spp` above its length) is reported as
/// [`ParamError::OutOfRange`] (`spp`).
pub fn render_row<S: Sequence<2>>(
    scene: &Scene<'_>,
    cam: &Camera,
    sampler: &PixelSampler<'_, S>,
    y: u32,
    scratch: &mut RowScratch<'_>,
    out: &mut [[f32; 3]],
) -> Result<(), ParamError> {
    let PixelSampler { seq, seed, spp } = *sampler;
    let n = row_scratch_len(cam.width, spp);
    if out.len() != cam.width as usize {
        return Err(ParamError::Length {
            name: "out",
            expected: cam.width as usize,
            got: out.len(),
        });
    }
    if scratch.t0.len() != n {
        return Err(ParamError::Length {
            name: "scratch",
            expected: n,
            got: scratch.t0.len(),
        });
    }
    // Camera rays: the sample point of ray k in pixel (x, y) by random access.
    let (w, h) = (cam.width as f32, cam.height as f32);
    for x in 0..cam.width {
        let pseed = pixel_seed(seed, x, y, 0);
        for k in 0..spp {
            let [u, v] = seq
                .point(u64::from(k), pseed)
                .map_err(|_| ParamError::OutOfRange {
                    name: "spp",
                    value: f64::from(spp),
                    min: 1.0,
                    max: seq.count() as f64,
                })?;
            let px = 2.0 * (x as f32 + u) / w - 1.0;
            let py = 1.0 - 2.0 * (y as f32 + v) / h;
            let i = (x * spp + k) as usize;
            let d: [f32; 3] =
                core::array::from_fn(|j| cam.forward[j] + px * cam.right[j] + py * cam.up[j]);
            // Unit directions, so t is arc length and the integrals are per
            // unit length.
            let inv = 1.0 / libm::sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (j, dj) in d.iter().enumerate() {
                scratch.origin[j][i] = cam.eye[j];
                scratch.dir[j][i] = dj * inv;
            }
            scratch.t0[i] = 0.0;
            scratch.t1[i] = f32::INFINITY;
        }
    }
    for c in 0..3 {
        scratch.tau[c].fill(0.0);
    }
    let RowScratch {
        origin,
        dir,
        t0,
        t1,
        value,
        tau,
    } = scratch;
    let rays = Rays32 {
        origin: [&origin[0][..], &origin[1][..], &origin[2][..]],
        dir: [&dir[0][..], &dir[1][..], &dir[2][..]],
        t0,
        t1,
    };
    // Optical depth: each shape's closed form over the whole row (8 lanes).
    for b in scene.balls {
        b.sphere.segment_batch_f32(&rays, value)?;
        accumulate(tau, value, b.sigma);
    }
    for p in scene.puffs {
        p.density.segment_batch_f32(&rays, value)?;
        accumulate(tau, value, p.sigma);
    }
    for (i, px) in out.iter_mut().enumerate() {
        let mut acc = [0.0f32; 3];
        for k in 0..spp as usize {
            let r = i * spp as usize + k;
            for c in 0..3 {
                acc[c] += libm::expf(-tau[c][r]);
            }
        }
        *px = acc.map(|a| a / spp as f32);
    }
    Ok(())
}

fn accumulate(tau: &mut [&mut [f32]; 3], value: &[f32], sigma: [f32; 3]) {
    for c in 0..3 {
        for (t, v) in tau[c].iter_mut().zip(value) {
            *t += sigma[c] * v;
        }
    }
}
