//! A pinhole camera with pbrt's conventions: the ray of a raster point.

use crate::vec3::{cross, sub, unit};

/// A pinhole camera (pbrt-v3's `LookAt` and `perspective`): pixel `(0, 0)`
/// is the top left, and the ray of pixel `(i, j)` goes through its centre
/// `(i + 0.5, j + 0.5)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye.
    pub from: [f64; 3],
    /// The point looked at.
    pub at: [f64; 3],
    /// The up direction (not parallel to `at − from`).
    pub up: [f64; 3],
    /// Field of view, degrees, in `(0, 180)`, spanning the shorter image
    /// axis.
    pub fov_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Camera {
    /// The camera ray through raster point `(x, y)` (pixel `(i, j)` has its
    /// centre at `(i + 0.5, j + 0.5)`; `(0, 0)` is the top left corner):
    /// `(origin, unit direction)`. pbrt-v3's conventions: `LookAt` makes the
    /// camera frame `right = up × dir`, `up' = dir × right` (so the image's
    /// right is `up × dir`, e.g. world `−x` for a camera looking down `−z`),
    /// and the perspective screen window is `[−a, a] × [−1, 1]` for aspect
    /// `a = width/height ≥ 1` (`[−1, 1] × [−1/a, 1/a]` otherwise), scaled by
    /// `tan(fov/2)`: the field of view spans the shorter image axis.
    ///
    /// Every step is a correctly rounded `f64` operation except `tan`
    /// (`libm`, within 1 ulp), so the direction is within a few ulps of
    /// the exact one.
    #[must_use]
    pub fn ray(&self, x: f64, y: f64) -> ([f64; 3], [f64; 3]) {
        let dir = unit(sub(self.at, self.from));
        let right = unit(cross(unit(self.up), dir));
        let up = cross(dir, right);
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let aspect = w / h;
        let (sx, sy) = if aspect >= 1.0 {
            (aspect, 1.0)
        } else {
            (1.0, 1.0 / aspect)
        };
        let t = libm::tan(0.5 * self.fov_deg.to_radians());
        let cx = (-sx + 2.0 * sx * x / w) * t;
        let cy = (sy - 2.0 * sy * y / h) * t;
        let d = unit([
            cx * right[0] + cy * up[0] + dir[0],
            cx * right[1] + cy * up[1] + dir[1],
            cx * right[2] + cy * up[2] + dir[2],
        ]);
        (self.from, d)
    }
}
