//! Geometry shared by the integrands and estimators: validated directions,
//! clipping a line to the unit box and splitting a wrapped segment into
//! pieces, one per unit cell. (Arithmetic primitives live in [`crate::num`].)
//!
//! Conventions (the [crate's](crate#conventions), for every `f64` API): a
//! segment or line is the set `p + t·ω` for `t` in a parameter interval,
//! where `ω` is the stored [`Direction`] (unit length up to rounding).
//! Closed forms integrate over the parameter `t`, so they are exact for the
//! stored `f64` values.

use crate::error::ParamError;

/// A unit direction vector in `D` dimensions, normalised at construction.
///
/// `Direction::new` accepts any finite non-zero vector and divides it by its
/// length; the length is computed after scaling by the largest component, so
/// neither overflow nor underflow can occur. The stored vector has
/// `|‖ω‖ − 1| ≤ 2·D·2⁻⁵³`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Direction<const D: usize> {
    v: [f64; D],
}

impl<const D: usize> Direction<D> {
    /// Normalises `v` (an array, or `glam::DVec2`/`DVec3` with the `glam`
    /// feature).
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`direction`) for NaN or infinite components,
    /// [`ParamError::ZeroDirection`] for the zero vector.
    pub fn new(v: impl Into<[f64; D]>) -> Result<Self, ParamError> {
        let v: [f64; D] = v.into();
        if v.iter().any(|x| !x.is_finite()) {
            return Err(ParamError::NonFinite { name: "direction" });
        }
        let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if m == 0.0 {
            return Err(ParamError::ZeroDirection);
        }
        let mut s = [0.0; D];
        for j in 0..D {
            s[j] = v[j] / m;
        }
        let n = crate::num::scalar::sqrt(s.iter().map(|x| x * x).sum::<f64>());
        for x in &mut s {
            *x /= n;
        }
        Ok(Self { v: s })
    }

    /// A vector the caller knows to be finite and unit up to rounding
    /// (e.g. a reflection or refraction of unit vectors), taken as it is:
    /// no check and no renormalisation, so results keep their bits. Use
    /// [`Direction::new`] for anything else.
    #[inline]
    #[must_use]
    pub fn from_unit(v: [f64; D]) -> Self {
        Self { v }
    }

    /// The unit vector along `axis` (`e_axis`).
    ///
    /// # Errors
    /// [`ParamError::OutOfRange`] (`axis`) if `axis ≥ D`.
    pub fn axis(axis: usize) -> Result<Self, ParamError> {
        if axis >= D {
            return Err(ParamError::OutOfRange {
                name: "axis",
                value: axis as f64,
                min: 0.0,
                max: D as f64 - 1.0,
            });
        }
        let mut v = [0.0; D];
        v[axis] = 1.0;
        Ok(Self { v })
    }

    /// The components `ω`.
    #[inline]
    #[must_use]
    pub fn get(&self) -> [f64; D] {
        self.v
    }

    /// `Some(j)` if this is exactly the axis direction `±e_j`.
    #[must_use]
    pub fn as_axis(&self) -> Option<usize> {
        let mut found = None;
        for j in 0..D {
            if self.v[j] != 0.0 {
                if found.is_some() || self.v[j].abs() != 1.0 {
                    return None;
                }
                found = Some(j);
            }
        }
        found
    }

    /// An orthonormal basis `u_1 … u_{D−1}` of the plane `ω^⊥` (written into the
    /// first `D − 1` rows; the last row is `ω`). For axis directions it is the
    /// remaining axes in increasing order, so axis lines built from it agree with
    /// the torus convention exactly.
    #[must_use]
    pub fn frame(&self) -> [[f64; D]; D] {
        let mut rows = [[0.0; D]; D];
        rows[D - 1] = self.v;
        if let Some(a) = self.as_axis() {
            let mut r = 0;
            for j in 0..D {
                if j != a {
                    rows[r][j] = 1.0;
                    r += 1;
                }
            }
            return rows;
        }
        // Gram–Schmidt against the axes in order of increasing |ω_j| (the most
        // orthogonal axes first), twice for accuracy.
        let mut order: [usize; D] = core::array::from_fn(|j| j);
        order.sort_unstable_by(|&a, &b| self.v[a].abs().total_cmp(&self.v[b].abs()));
        for (r, &j) in order.iter().enumerate() {
            if r == D - 1 {
                break;
            }
            let mut u = [0.0; D];
            u[j] = 1.0;
            for _ in 0..2 {
                for k in 0..=r {
                    let basis = if k == 0 { self.v } else { rows[k - 1] };
                    let d = dot(&u, &basis);
                    for i in 0..D {
                        u[i] -= d * basis[i];
                    }
                }
            }
            let n = crate::num::scalar::sqrt(dot(&u, &u));
            for x in &mut u {
                *x /= n;
            }
            rows[r] = u;
        }
        rows
    }
}

/// `a · b`.
#[inline(always)]
#[must_use]
pub fn dot<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    let mut s = 0.0;
    for j in 0..D {
        s += a[j] * b[j];
    }
    s
}

/// The parameter interval `[t0, t1]` of `p + t·ω` inside the closed box
/// `[0, 1]^D`, or `None` if the line misses the box (or only touches it in a
/// single point). Slab method (Kay & Kajiya 1986); an axis with `ω_j = 0` keeps
/// the line iff `p_j ∈ [0, 1]`.
#[must_use]
pub fn clip_to_unit_box<const D: usize>(p: &[f64; D], dir: &Direction<D>) -> Option<(f64, f64)> {
    let w = dir.get();
    let mut t0 = f64::NEG_INFINITY;
    let mut t1 = f64::INFINITY;
    for j in 0..D {
        if w[j] == 0.0 {
            if !(0.0..=1.0).contains(&p[j]) {
                return None;
            }
        } else {
            let a = (0.0 - p[j]) / w[j];
            let b = (1.0 - p[j]) / w[j];
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            t0 = t0.max(lo);
            t1 = t1.min(hi);
        }
    }
    (t1 > t0).then_some((t0, t1))
}

/// Longest segment accepted anywhere in the crate, in units of the period.
/// A wrapped segment is split into about `λ·Σ|ω_j| + D` pieces, so the cost of a
/// torus segment integral grows linearly with `λ`; this cap bounds it.
pub const MAX_SEGMENT_LENGTH: f64 = 1_048_576.0;

/// Splits the wrapped segment `c + t·ω`, `t ∈ [t_lo, t_hi]`, into pieces that
/// each lie in one unit cell `m + [0, 1]^D`, and calls
/// `piece(c − m, t_a, t_b)` for each: on the piece, `c − m + t·ω ∈ [0, 1]^D`
/// (up to rounding of a few ulp at the cell faces).
///
/// Amanatides & Woo (1987) cell traversal; the crossing parameters are recomputed
/// from `c` and `m` at every step (no accumulated drift). Pieces are visited in
/// increasing `t`, their number is at most `⌈(t_hi − t_lo)·Σ|ω_j|⌉ + D + 1`.
/// The origin `c − m` is rounded to the nearest double (error ≤ ulp(|m| + 1)/2
/// per coordinate); integrands that need more (a Gaussian with tiny σ) rebuild
/// it exactly.
/// The caller guarantees finite `c`, `t_lo ≤ t_hi` and `t_hi − t_lo ≤`
/// [`MAX_SEGMENT_LENGTH`].
pub fn for_each_piece<const D: usize>(
    c: &[f64; D],
    dir: &Direction<D>,
    t_lo: f64,
    t_hi: f64,
    mut piece: impl FnMut(&[f64; D], f64, f64),
) {
    let w = dir.get();
    let mut t = t_lo;
    // Cell of the point just after `t`: use the direction to break ties on faces.
    let mut m = [0.0f64; D];
    for j in 0..D {
        let x = c[j] + t * w[j];
        let mut f = crate::num::scalar::floor(x);
        if x == f && w[j] < 0.0 {
            f -= 1.0;
        }
        m[j] = f;
    }
    let mut origin = [0.0; D];
    let bound = ((t_hi - t_lo) * w.iter().map(|x| x.abs()).sum::<f64>()) as usize + D + 2;
    // Each axis's crossing parameter, computed once per step and reused by
    // the stepping test below (the same quotient, so the same decisions).
    let mut tf = [f64::INFINITY; D];
    for _ in 0..bound.min(usize::MAX - 1) + 1 {
        let mut t_next = t_hi;
        for j in 0..D {
            if w[j] != 0.0 {
                let face = if w[j] > 0.0 { m[j] + 1.0 } else { m[j] };
                tf[j] = (face - c[j]) / w[j];
                if tf[j] < t_next {
                    t_next = tf[j];
                }
            }
        }
        let t_next = t_next.max(t);
        for j in 0..D {
            origin[j] = c[j] - m[j];
        }
        if t_next > t {
            piece(&origin, t, t_next);
        }
        if t_next >= t_hi {
            return;
        }
        // Step every axis whose face is crossed at t_next.
        for j in 0..D {
            if w[j] != 0.0 && tf[j] <= t_next {
                m[j] += if w[j] > 0.0 { 1.0 } else { -1.0 };
            }
        }
        t = t_next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direction_normalises_and_rejects() {
        let d = Direction::new([3.0, 4.0]).unwrap();
        assert!((d.get()[0] - 0.6).abs() < 1e-16 && (d.get()[1] - 0.8).abs() < 1e-16);
        let tiny = Direction::new([1e-310, 0.0]).unwrap();
        assert_eq!(tiny.get(), [1.0, 0.0]);
        let huge = Direction::new([1e308, 1e308]).unwrap();
        assert!((huge.get()[0] - core::f64::consts::FRAC_1_SQRT_2).abs() < 3e-16);
        assert_eq!(Direction::new([0.0, 0.0]), Err(ParamError::ZeroDirection));
        assert!(Direction::new([f64::NAN, 1.0]).is_err());
        assert!(Direction::new([f64::INFINITY, 1.0]).is_err());
        assert_eq!(Direction::<3>::axis(2).unwrap().as_axis(), Some(2));
        assert_eq!(Direction::new([0.0, -2.0, 0.0]).unwrap().as_axis(), Some(1));
        assert!(Direction::<2>::axis(2).is_err());
    }

    #[test]
    fn frame_is_orthonormal() {
        for v in [
            [1.0, 2.0, 3.0],
            [0.0, 0.0, 1.0],
            [1e-9, 1.0, -1e-12],
            [-1.0, 1.0, 0.0],
        ] {
            let d = Direction::new(v).unwrap();
            let f = d.frame();
            for a in 0..3 {
                for b in 0..3 {
                    let e = if a == b { 1.0 } else { 0.0 };
                    assert!((dot(&f[a], &f[b]) - e).abs() < 1e-15, "{v:?} {a} {b}");
                }
            }
        }
    }

    #[test]
    fn pieces_cover_the_segment_in_cells() {
        let c = [0.3, 0.7, 0.1];
        let d = Direction::new([0.4, -1.3, 0.7]).unwrap();
        let mut total = 0.0;
        let mut last = -2.5;
        let mut n = 0;
        for_each_piece(&c, &d, -2.5, 3.0, |o, a, b| {
            assert!((a - last).abs() < 1e-12);
            last = b;
            total += b - a;
            n += 1;
            for t in [a, 0.5 * (a + b), b] {
                for j in 0..3 {
                    let x = o[j] + t * d.get()[j];
                    assert!((-1e-12..=1.0 + 1e-12).contains(&x), "{x}");
                }
            }
        });
        assert!((total - 5.5).abs() < 1e-12);
        assert!((5..=(5.5 * 2.4) as usize + 6).contains(&n), "{n}");
    }

    #[test]
    fn clip_box() {
        let d = Direction::new([1.0, 1.0]).unwrap();
        let (a, b) = clip_to_unit_box(&[0.0, 0.0], &d).unwrap();
        assert!((b - a - core::f64::consts::SQRT_2).abs() < 1e-15);
        assert!(clip_to_unit_box(&[2.0, 0.0], &Direction::axis(1).unwrap()).is_none());
        let (a, b) = clip_to_unit_box(&[0.25, 0.5], &Direction::axis(1).unwrap()).unwrap();
        assert_eq!((a, b), (-0.5, 0.5));
    }
}
