//! Planes along a ray: [`HalfSpace`] `n·x ≥ h` and [`Slab`] `h0 ≤ n·x ≤ h1`.
//!
//! Along `o + tω` the signed excess `g(t) = n·(o + tω) − h = g₀ + t·c` is
//! linear, `g₀ = n·o − h`, `c = n·ω`. The set where a half-space holds is a
//! half-line bounded by the crossing `t* = −g₀/c` (everything or nothing when
//! `c = 0`), a slab is the intersection of two such half-lines, and the
//! integral of the indicator over `[t0, t1]` is the length of the
//! intersection. `g₀` and `c` are formed from error-free products
//! (Dekker 1971) summed in double-double, the crossings are double-double
//! quotients, and the interval ends are kept in double-double until the one
//! final rounding of `hi − lo`: the length is a few ulp **relative** for the
//! given inputs, even for a ray almost parallel to the plane, a short segment
//! far from `t = 0`, or a segment ending next to the plane.

use super::{check_dim, check_finite, Ray};
use crate::error::ParamError;
use crate::geom::Direction;
use crate::num::lane::F32Lane;
use crate::num::Dd;
use crate::primitive::Rays32;
use wide::f32x8;

/// `n·x − h` in double-double (exact products, ≈ 2⁻¹⁰⁴-relative sums).
#[inline]
pub(crate) fn excess<const D: usize>(n: &[f64; D], h: f64, x: &[f64; D]) -> Dd {
    let mut g = Dd::new(-h);
    for j in 0..D {
        g = g.add(Dd::prod(n[j], x[j]));
    }
    g
}

/// `n·ω` in double-double.
#[inline]
pub(crate) fn slope<const D: usize>(n: &[f64; D], w: &[f64; D]) -> Dd {
    let mut c = Dd::new(0.0);
    for j in 0..D {
        c = c.add(Dd::prod(n[j], w[j]));
    }
    c
}

/// Narrows `[lo, hi]` to `{t : g + t·c ≥ 0}` (`g`, `c` in double-double);
/// returns `false` if the set is empty because `c = 0` and `g < 0`.
#[inline]
pub(crate) fn keep_side(g: Dd, c: Dd, lo: &mut Dd, hi: &mut Dd) -> bool {
    if c.hi == 0.0 {
        return g.hi >= 0.0;
    }
    let ts = Dd::div(g.neg(), c);
    if c.hi > 0.0 {
        if Dd::lt(*lo, ts) {
            *lo = ts;
        }
    } else if Dd::lt(ts, *hi) {
        *hi = ts;
    }
    true
}

/// The length `hi − lo` of a double-double interval, one rounding (the leading
/// parts where an end is infinite); 0 if empty.
#[inline]
pub(crate) fn length(lo: Dd, hi: Dd) -> f64 {
    let len = if lo.hi.is_finite() && hi.hi.is_finite() {
        hi.sub(lo).hi
    } else {
        hi.hi - lo.hi
    };
    len.max(0.0)
}

/// The half-space `{x : n·x ≥ h}` in `ℝ^D` (`D = 2, 3`), unit normal `n`
/// pointing into it.
///
/// ```
/// use linesample::world::{HalfSpace, Ray};
/// let floor = HalfSpace::new([0.0, 0.0, 1.0], 0.0)?; // z ≥ 0
/// let ray = Ray::new([0.0, 0.0, 2.0], [0.0, 0.6, -0.8])?;
/// assert_eq!(floor.crossing(&ray), Some(2.5));
/// assert_eq!(floor.segment(&ray, 0.0, 10.0), 2.5);
/// # Ok::<(), linesample::ParamError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSpace<const D: usize> {
    normal: Direction<D>,
    offset: f64,
    n32: [f32; D],
    h32: f32,
}

impl<const D: usize> HalfSpace<D> {
    /// `{x : n̂·x ≥ offset}` with `n̂ = normal/|normal|` (any finite non-zero
    /// vector).
    ///
    /// # Errors
    /// [`ParamError::Dimension`] unless `D ∈ {2, 3}`; [`ParamError::NonFinite`]
    /// (`direction`, `offset`); [`ParamError::ZeroDirection`].
    pub fn new(normal: impl Into<[f64; D]>, offset: f64) -> Result<Self, ParamError> {
        Self::from_direction(Direction::new(normal.into())?, offset)
    }

    /// [`HalfSpace::new`] with a validated unit normal.
    ///
    /// # Errors
    /// [`ParamError::Dimension`], [`ParamError::NonFinite`] (`offset`).
    pub fn from_direction(normal: Direction<D>, offset: f64) -> Result<Self, ParamError> {
        check_dim::<D>()?;
        check_finite("offset", &[offset])?;
        Ok(Self {
            normal,
            offset,
            n32: normal.get().map(|x| x as f32),
            h32: offset as f32,
        })
    }

    /// The unit normal.
    #[must_use]
    pub fn normal(&self) -> Direction<D> {
        self.normal
    }

    /// The offset `h`.
    #[must_use]
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// `n·x ≥ h`, decided in double-double (exact unless `n·x − h` is within
    /// `2⁻¹⁰⁴` relative of its terms).
    #[must_use]
    pub fn contains(&self, x: &[f64; D]) -> bool {
        excess(&self.normal.get(), self.offset, x).hi >= 0.0
    }

    /// The parameter `t* = −(n·o − h)/(n·ω)` where the ray crosses the plane
    /// (relative error ≤ 2 ulp), or `None` if the ray is parallel to it.
    #[must_use]
    pub fn crossing(&self, ray: &Ray<D>) -> Option<f64> {
        let n = self.normal.get();
        let c = slope(&n, &ray.dir().get());
        if c.hi == 0.0 {
            return None;
        }
        Some(Dd::div(excess(&n, self.offset, &ray.origin()).neg(), c).to_f64())
    }

    /// `∫_{t0}^{t1} 1[n·(o + tω) ≥ h] dt`: the length of `[t0, t1]` on the kept
    /// side (either end may be infinite; the result is then `∞` or finite).
    /// Relative error a few ulp (the interval ends are double-double, see the
    /// [module docs](self)); `t0 > t1` gives 0, a NaN end gives an unspecified
    /// value (no panic).
    #[must_use]
    pub fn segment(&self, ray: &Ray<D>, t0: f64, t1: f64) -> f64 {
        let n = self.normal.get();
        let (mut lo, mut hi) = (Dd::new(t0), Dd::new(t1));
        let g = excess(&n, self.offset, &ray.origin());
        if !keep_side(g, slope(&n, &ray.dir().get()), &mut lo, &mut hi) {
            return 0.0;
        }
        length(lo, hi)
    }

    /// `f32` twin of [`HalfSpace::segment_batch_f32`] along `o + t·d`:
    /// `g = n₃₂·o − h₃₂`, `c = n₃₂·d`, `t* = −g/c`, length of `[t0, t1]` on the
    /// kept side. Error against the `f64` path at the same (`f32`) inputs, with
    /// `u = 2⁻²⁴`: the crossing has absolute error
    /// `≲ 6u·(Σ|n_j o_j| + |h| + |t*|·Σ|n_j d_j|)/|n·d|` plus the rounding of
    /// the normal and offset to `f32` (`≤ u(Σ|o_j| + |h|)/|n·d|`), and the
    /// length additionally `≤ 2u(|t0| + |t1|)`. A ray (nearly) parallel to
    /// the plane is ill-conditioned: it may be kept or dropped whole.
    #[must_use]
    pub fn segment_f32(
        &self,
        o: impl Into<[f32; D]>,
        d: impl Into<[f32; D]>,
        t0: f32,
        t1: f32,
    ) -> f32 {
        half_kernel::<f32, D>(&self.n32, self.h32, o.into(), d.into(), t0, t1)
    }

    /// SIMD batch (8 lanes) of [`HalfSpace::segment_f32`], bit-identical to the
    /// scalar twin lane by lane.
    ///
    /// # Errors
    /// [`ParamError::Length`] if the slices differ in length.
    pub fn segment_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        let (n, h) = (&self.n32, self.h32);
        super::gaussian::batch(
            rays,
            out,
            |o, d, t0, t1| half_kernel::<f32x8, D>(n, h, o, d, t0, t1),
            |o, d, t0, t1| half_kernel::<f32, D>(n, h, o, d, t0, t1),
        )
    }
}

/// The slab `{x : h0 ≤ n·x ≤ h1}` between two parallel planes.
///
/// ```
/// use linesample::world::{Ray, Slab};
/// let layer = Slab::new([0.0, 1.0], 1.0, 3.0)?; // 1 ≤ y ≤ 3
/// let ray = Ray::new([0.0, 0.0], [1.0, 1.0])?;
/// let len = layer.segment(&ray, 0.0, f64::INFINITY);
/// assert!((len - 2.0 * 2f64.sqrt()).abs() < 1e-15);
/// # Ok::<(), linesample::ParamError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab<const D: usize> {
    normal: Direction<D>,
    h0: f64,
    h1: f64,
    n32: [f32; D],
    h32: [f32; 2],
}

impl<const D: usize> Slab<D> {
    /// `{x : h0 ≤ n̂·x ≤ h1}`, `n̂ = normal/|normal|`.
    ///
    /// # Errors
    /// [`ParamError::Dimension`]; [`ParamError::NonFinite`] (`direction`,
    /// `h0`, `h1`); [`ParamError::ZeroDirection`]; [`ParamError::OutOfRange`]
    /// (`h1`) if `h1 < h0`.
    pub fn new(normal: impl Into<[f64; D]>, h0: f64, h1: f64) -> Result<Self, ParamError> {
        check_dim::<D>()?;
        let normal = Direction::new(normal.into())?;
        check_finite("h0", &[h0])?;
        check_finite("h1", &[h1])?;
        if h1 < h0 {
            return Err(ParamError::OutOfRange {
                name: "h1",
                value: h1,
                min: h0,
                max: f64::INFINITY,
            });
        }
        Ok(Self {
            normal,
            h0,
            h1,
            n32: normal.get().map(|x| x as f32),
            h32: [h0 as f32, h1 as f32],
        })
    }

    /// The unit normal.
    #[must_use]
    pub fn normal(&self) -> Direction<D> {
        self.normal
    }

    /// The offsets `(h0, h1)`.
    #[must_use]
    pub fn offsets(&self) -> (f64, f64) {
        (self.h0, self.h1)
    }

    /// `h0 ≤ n·x ≤ h1`, decided in double-double.
    #[must_use]
    pub fn contains(&self, x: &[f64; D]) -> bool {
        let n = self.normal.get();
        excess(&n, self.h0, x).hi >= 0.0 && excess(&n, self.h1, x).hi <= 0.0
    }

    /// `∫_{t0}^{t1} 1[h0 ≤ n·(o + tω) ≤ h1] dt`, relative error a few ulp
    /// (both crossings are double-double quotients; see the
    /// [module docs](self)); `t0 > t1` gives 0.
    #[must_use]
    pub fn segment(&self, ray: &Ray<D>, t0: f64, t1: f64) -> f64 {
        let n = self.normal.get();
        let o = ray.origin();
        let c = slope(&n, &ray.dir().get());
        let (mut lo, mut hi) = (Dd::new(t0), Dd::new(t1));
        // g0 + tc ≥ 0 and −(g1 + tc) ≥ 0.
        if !keep_side(excess(&n, self.h0, &o), c, &mut lo, &mut hi)
            || !keep_side(excess(&n, self.h1, &o).neg(), c.neg(), &mut lo, &mut hi)
        {
            return 0.0;
        }
        length(lo, hi)
    }

    /// `f32` twin of [`Slab::segment_batch_f32`]: the [`HalfSpace::segment_f32`]
    /// computation for both planes (same error per crossing).
    #[must_use]
    pub fn segment_f32(
        &self,
        o: impl Into<[f32; D]>,
        d: impl Into<[f32; D]>,
        t0: f32,
        t1: f32,
    ) -> f32 {
        slab_kernel::<f32, D>(&self.n32, self.h32, o.into(), d.into(), t0, t1)
    }

    /// SIMD batch (8 lanes) of [`Slab::segment_f32`], bit-identical to the
    /// scalar twin lane by lane.
    ///
    /// # Errors
    /// [`ParamError::Length`] if the slices differ in length.
    pub fn segment_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        let (n, h) = (&self.n32, self.h32);
        super::gaussian::batch(
            rays,
            out,
            |o, d, t0, t1| slab_kernel::<f32x8, D>(n, h, o, d, t0, t1),
            |o, d, t0, t1| slab_kernel::<f32, D>(n, h, o, d, t0, t1),
        )
    }
}

/// `(g, c)` of `n·(o + t d) − h = g + t c` in `f32`.
#[inline(always)]
fn lin<L: F32Lane, const D: usize>(n: &[f32; D], o: &[L; D], d: &[L; D]) -> (L, L) {
    let mut g = L::splat(n[0]) * o[0];
    let mut c = L::splat(n[0]) * d[0];
    for j in 1..D {
        g = g + L::splat(n[j]) * o[j];
        c = c + L::splat(n[j]) * d[j];
    }
    (g, c)
}

/// Narrows `[lo, hi]` to `g + t c ≥ 0` (all lanes; `c = 0` keeps everything
/// or nothing by the sign of `g`).
#[inline(always)]
fn keep32<L: F32Lane>(g: L, c: L, lo: L, hi: L) -> (L, L) {
    let zero = L::splat(0.0);
    let inf = L::splat(f32::INFINITY);
    let ts = -g / c;
    let cpos = L::gt(c, zero);
    let cneg = L::lt(c, zero);
    let par = L::select(L::lt(g, zero), inf, lo);
    let lo = L::select(cpos, lo.max(ts), L::select(cneg, lo, par));
    let hi = L::select(cneg, hi.min(ts), hi);
    (lo, hi)
}

#[inline(always)]
fn half_kernel<L: F32Lane, const D: usize>(
    n: &[f32; D],
    h: f32,
    o: [L; D],
    d: [L; D],
    t0: L,
    t1: L,
) -> L {
    let (g, c) = lin(n, &o, &d);
    let (lo, hi) = keep32(g - L::splat(h), c, t0, t1);
    (hi - lo).max(L::splat(0.0))
}

#[inline(always)]
fn slab_kernel<L: F32Lane, const D: usize>(
    n: &[f32; D],
    h: [f32; 2],
    o: [L; D],
    d: [L; D],
    t0: L,
    t1: L,
) -> L {
    let (g, c) = lin(n, &o, &d);
    let (lo, hi) = keep32(g - L::splat(h[0]), c, t0, t1);
    let (lo, hi) = keep32(L::splat(h[1]) - g, L::splat(0.0) - c, lo, hi);
    (hi - lo).max(L::splat(0.0))
}
