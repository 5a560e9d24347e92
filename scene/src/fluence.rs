//! Photon paths splatted into a fluence image: the power each segment
//! scatters inside each pixel it crosses, in closed form along the segment
//! (no allocation: the caller owns the grid).

use crate::caustic::PhotonPath;

/// The fluence image's pixel grid (the plane, or the slab's `x, y`):
/// `w × h` pixels of `px × py` from `(x0, y0)`, row 0 at the top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// The left edge.
    pub x0: f64,
    /// The bottom edge.
    pub y0: f64,
    /// Pixel width.
    pub px: f64,
    /// Pixel height.
    pub py: f64,
    /// Pixels across.
    pub w: usize,
    /// Pixels down.
    pub h: usize,
}

impl Frame {
    /// The frame of a `w × h` image of `size` centred on `centre`.
    #[must_use]
    pub fn new(centre: [f64; 2], size: [f64; 2], w: usize, h: usize) -> Self {
        Frame {
            x0: centre[0] - 0.5 * size[0],
            y0: centre[1] - 0.5 * size[1],
            px: size[0] / w as f64,
            py: size[1] / h as f64,
            w,
            h,
        }
    }
}

/// Adds the scattered power of the ray `o + t·d`, `t ∈ [t0, t1]` (medium
/// offset `tau`, weight `w`), to every pixel it crosses: per pixel interval
/// `[ta, tb]`, `w e^{−σ_t(τ + ta)}(1 − e^{−σ_t(tb − ta)})` (Amanatides & Woo
/// 1987 grid traversal). Only the `x, y` components of `o` and `d` are used.
// `!(hi > lo)` also catches NaN.
#[allow(clippy::too_many_arguments, clippy::neg_cmp_op_on_partial_ord)]
fn splat(
    grid: &mut [f64],
    f: &Frame,
    o: [f64; 2],
    d: [f64; 2],
    t0: f64,
    t1: f64,
    tau: f64,
    w: f64,
    st: f64,
) {
    // Clip to the frame (slab method).
    let (mut lo, mut hi) = (t0, t1);
    let bounds = [
        (f.x0, f.x0 + f.px * f.w as f64),
        (f.y0, f.y0 + f.py * f.h as f64),
    ];
    for j in 0..2 {
        let (a, b) = bounds[j];
        if d[j] == 0.0 {
            if !(o[j] >= a && o[j] < b) {
                return;
            }
        } else {
            let (ta, tb) = ((a - o[j]) / d[j], (b - o[j]) / d[j]);
            lo = lo.max(ta.min(tb));
            hi = hi.min(ta.max(tb));
        }
    }
    if !(hi > lo) {
        return;
    }
    let cell = |j: usize, t: f64| -> i64 {
        let (origin, size, n) = if j == 0 {
            (f.x0, f.px, f.w)
        } else {
            (f.y0, f.py, f.h)
        };
        (libm::floor((o[j] + t * d[j] - origin) / size) as i64).clamp(0, n as i64 - 1)
    };
    // On a grid line the floor may name the cell behind: its interval is
    // empty and the traversal steps on.
    let mut idx = [cell(0, lo), cell(1, lo)];
    let sizes = [f.px, f.py];
    let origins = [f.x0, f.y0];
    let mut t_max = [f64::INFINITY; 2];
    let mut t_delta = [f64::INFINITY; 2];
    let mut step = [0i64; 2];
    for j in 0..2 {
        if d[j] > 0.0 {
            step[j] = 1;
            t_max[j] = (origins[j] + (idx[j] + 1) as f64 * sizes[j] - o[j]) / d[j];
            t_delta[j] = sizes[j] / d[j];
        } else if d[j] < 0.0 {
            step[j] = -1;
            t_max[j] = (origins[j] + idx[j] as f64 * sizes[j] - o[j]) / d[j];
            t_delta[j] = -sizes[j] / d[j];
        }
    }
    let mut t = lo;
    loop {
        let tn = t_max[0].min(t_max[1]).min(hi);
        if tn > t {
            let row = f.h - 1 - idx[1] as usize;
            grid[row * f.w + idx[0] as usize] +=
                w * libm::exp(-st * (tau + t)) * -libm::expm1(-st * (tn - t));
            t = tn;
        }
        if t >= hi {
            return;
        }
        let j = usize::from(t_max[1] < t_max[0]);
        idx[j] += step[j];
        if idx[j] < 0 || idx[j] >= if j == 0 { f.w } else { f.h } as i64 {
            return;
        }
        t_max[j] += t_delta[j];
    }
}

/// Splats every segment of `path` (2D) into `grid` (`w·h`, row-major,
/// row 0 at the top), `st` the medium's extinction σ_t.
pub fn splat_path2(grid: &mut [f64], f: &Frame, path: &PhotonPath<2>, st: f64) {
    for s in path.segments() {
        let (o, d) = (s.ray.origin(), s.ray.dir().get());
        splat(grid, f, o, d, 0.0, s.length, s.start, s.weight, st);
    }
}

/// Splats every segment of `path` clipped to the slab `|z − z0| < half`
/// (3D) into `grid`, as [`splat_path2`].
pub fn splat_path3(grid: &mut [f64], f: &Frame, path: &PhotonPath<3>, st: f64, z0: f64, half: f64) {
    for s in path.segments() {
        let (o, d) = (s.ray.origin(), s.ray.dir().get());
        let (mut lo, mut hi) = (0.0f64, s.length);
        if d[2] == 0.0 {
            if libm::fabs(o[2] - z0) >= half {
                continue;
            }
        } else {
            let ta = (z0 - half - o[2]) / d[2];
            let tb = (z0 + half - o[2]) / d[2];
            lo = lo.max(ta.min(tb));
            hi = hi.min(ta.max(tb));
        }
        if hi > lo {
            splat(
                grid,
                f,
                [o[0], o[1]],
                [d[0], d[1]],
                lo,
                hi,
                s.start,
                s.weight,
                st,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::caustic::Segment;
    use linesample::world::Ray;

    fn path2(o: [f64; 2], d: [f64; 2], start: f64, length: f64, weight: f64) -> PhotonPath<2> {
        let ray = Ray::new(o, d).unwrap();
        PhotonPath::new(&[Segment {
            ray,
            start,
            length,
            weight,
        }])
        .unwrap()
    }

    /// A segment inside the frame deposits exactly `w e^{−σ τ}(1 − e^{−σ L})`
    /// over the pixels it crosses (the per-pixel pieces telescope), into the
    /// pixels its points lie in; one outside deposits nothing.
    #[test]
    fn splatting_conserves_the_scattered_power() {
        let f = Frame::new([0.0, 0.0], [2.0, 2.0], 16, 8);
        let mut grid = [0.0f64; 16 * 8];
        let (st, tau, len, w) = (0.7, 0.3, 1.2, 0.25);
        let d = [0.6, 0.8];
        splat_path2(&mut grid, &f, &path2([-0.5, -0.6], d, tau, len, w), st);
        let want = w * libm::exp(-st * tau) * -libm::expm1(-st * len);
        let got: f64 = grid.iter().sum();
        assert!((got - want).abs() <= 1e-15 * want, "{got} vs {want}");
        // The pixel of the segment's midpoint has power, a far corner none.
        let mid = [-0.5 + 0.6 * 0.6, -0.6 + 0.8 * 0.6];
        let col = ((mid[0] - f.x0) / f.px) as usize;
        let row = f.h - 1 - ((mid[1] - f.y0) / f.py) as usize;
        assert!(grid[row * f.w + col] > 0.0);
        assert_eq!(grid[0], 0.0);
        let mut empty = [0.0f64; 16 * 8];
        splat_path2(&mut empty, &f, &path2([5.0, 5.0], d, 0.0, 1.0, 1.0), st);
        assert!(empty.iter().all(|&v| v == 0.0));
    }
}
