//! Planes along a ray: [`HalfSpace`] `n·x ≥ h` and [`Slab`] `h0 ≤ n·x ≤ h1`.
//!
//! Along `o + tω` the signed excess `g(t) = n·(o + tω) − h = g₀ + t·c` is
//! linear, `g₀ = n·o − h`, `c = n·ω`. The set where a half-space holds is a
//! half-line bounded by the crossing `t* = −g₀/c` (everything or nothing when
//! `c = 0`), a slab the intersection of two such half-lines, and the integral
//! of the indicator over `[t0, t1]` is the length of the intersection.
//!
//! Which of the three cases applies is decided by the **exact signs** of the
//! excess at the two segment ends (`g(e)` summed exactly from error-free
//! products, Dekker 1971, in four-fold precision), never by comparing rounded
//! crossing parameters, which overflow for rays nearly parallel to a plane.
//! The length is then one accurately computed quantity: `t1 − t0` (both ends
//! kept), an end's distance to the plane that cuts it, `|g(e)|/|c|`, or the
//! distance between the slab's planes, `|h1 − h0|/|c|`. So it is a few ulp
//! **relative** for the given inputs, even for a ray almost parallel to the
//! plane, a segment ending `10⁻³⁰` from it, or a thin slab `10⁹` along the
//! ray; plus an absolute error of a few `2⁻¹⁰⁷⁴/|c|` when products of the
//! coordinates underflow (inputs below about `10⁻²⁹⁰`).

use super::{check_dim, check_finite, Ray};
use crate::error::ParamError;
use crate::geom::Direction;
use crate::num::lane::F32Lane;
use crate::num::{sum_accurate, two_prod, Dd};
use crate::primitive::Rays32;

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

/// `−g/c`, the crossing of `g + t·c = 0`, in double-double; `±∞` (with the
/// leading part's sign, low part 0) when the quotient overflows (a ray nearly
/// parallel to the plane: found by the world tests, where `∞ − ∞` had made a
/// kept half-line empty).
#[inline]
pub(crate) fn crossing(g: Dd, c: Dd) -> Dd {
    let q = -g.hi / c.hi;
    if q.is_finite() {
        Dd::div(g.neg(), c)
    } else {
        Dd::new(q)
    }
}

/// The excess `n·(o + eω) − h` at a finite parameter `e`, summed exactly
/// (four-fold precision, [`sum_accurate`]) from error-free products: `n_j o_j`
/// and `n_j·(e ω_j)` with `e ω_j = p + p'` exactly, so 6 products of doubles
/// per coordinate. It cancels to the end's distance from the plane times
/// `|n·ω|`, which no double-double sum from `o` resolves for an end next to
/// the plane (found by the world tests: `4.4e−32` came out as `1.5e−31`).
fn excess_at<const D: usize>(n: &[f64; D], h: f64, o: &[f64; D], w: &[f64; D], e: f64) -> Dd {
    let mut t = [0.0f64; 19];
    let mut k = 0;
    for j in 0..D {
        let (a, ae) = two_prod(n[j], o[j]);
        let (p, pe) = two_prod(e, w[j]);
        let (b, be) = two_prod(n[j], p);
        let (c, ce) = two_prod(n[j], pe);
        t[k..k + 6].copy_from_slice(&[a, ae, b, be, c, ce]);
        k += 6;
    }
    t[k] = -h;
    sum_accurate(&mut t[..k + 1])
}

/// One plane constraint `sign·(n·x − h) ≥ 0`.
#[derive(Clone, Copy)]
struct Plane {
    h: f64,
    sign: f64,
}

/// The length of `[t0, t1]` where every constraint holds (one for a
/// half-space; two for a slab, `n·x ≥ h0` and `n·x ≤ h1`).
///
/// Decided by the exact signs of the excesses at the two ends ([`excess_at`];
/// at an infinite end, the sign of `n·ω` times that end's sign, or of
/// `n·o − h` when `n·ω = 0`), never by comparing rounded crossing parameters,
/// which can overflow for a ray nearly parallel to a plane (found by the world
/// tests: `∞ − ∞` made a kept half-line empty). The length is then one
/// accurately computed quantity: `fl(t1 − t0)` when both ends are kept, an
/// end's distance to the plane it is cut by, `|excess at the end|/|n·ω|`
/// (relative error a few ulp however close the end is to the plane), or the
/// distance between the two planes `|h1 − h0|/|n·ω|` when the segment crosses
/// the whole slab (however far along the ray). NaN ends give an unspecified
/// value (no panic).
fn clipped_length<const D: usize>(
    n: &[f64; D],
    planes: &[Plane],
    ray: &Ray<D>,
    t0: f64,
    t1: f64,
) -> f64 {
    // Also rejects NaN ends.
    if t0
        .partial_cmp(&t1)
        .is_none_or(|o| o == core::cmp::Ordering::Greater)
    {
        return 0.0;
    }
    let o = ray.origin();
    let w = ray.dir().get();
    let c = slope(n, &w);
    // The first violated constraint at an end (None: the end is kept).
    let violated = |e: f64| -> Option<usize> {
        for (i, p) in planes.iter().enumerate() {
            let g = if e.is_finite() {
                excess_at(n, p.h, &o, &w, e).hi
            } else if c.hi != 0.0 {
                c.hi * e
            } else {
                excess(n, p.h, &o).hi
            };
            if p.sign * g < 0.0 {
                return Some(i);
            }
        }
        None
    };
    let abs_c = if c.hi < 0.0 { c.neg() } else { c };
    // |excess of plane i at the end e| / |n·ω| (∞ for an infinite end).
    let dist = |i: usize, e: f64| -> f64 {
        if !e.is_finite() {
            return f64::INFINITY;
        }
        let g = excess_at(n, planes[i].h, &o, &w, e);
        let g = if g.hi < 0.0 { g.neg() } else { g };
        Dd::div(g, abs_c).to_f64()
    };
    let len = match (violated(t0), violated(t1)) {
        (None, None) => t1 - t0,
        (Some(i), None) => dist(i, t1),
        (None, Some(i)) => dist(i, t0),
        (Some(i), Some(k)) if i != k => {
            // Below one plane at t0 and beyond the other at t1: the whole
            // slab is crossed.
            let gap = Dd::diff(planes[k].h, planes[i].h);
            let gap = if gap.hi < 0.0 { gap.neg() } else { gap };
            Dd::div(gap, abs_c).to_f64()
        }
        (Some(_), Some(_)) => 0.0,
    };
    len.max(0.0)
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
    /// (arc length along the ray's unit `ω`, [conventions](crate#conventions);
    /// the excess summed exactly, relative error ≤ 2 ulp; `±∞` if it
    /// overflows), or `None` if the ray is parallel to it.
    #[must_use]
    pub fn crossing(&self, ray: &Ray<D>) -> Option<f64> {
        let n = self.normal.get();
        let c = slope(&n, &ray.dir().get());
        if c.hi == 0.0 {
            return None;
        }
        let g = excess_at(&n, self.offset, &ray.origin(), &ray.dir().get(), 0.0);
        Some(crossing(g, c).to_f64())
    }

    /// `∫_{t0}^{t1} 1[n·(o + tω) ≥ h] dt`: the length of `[t0, t1]` on the kept
    /// side (arc length, [conventions](crate#conventions); either end may be
    /// infinite, the result is then `∞` or finite).
    /// Relative error a few ulp (measured ≤ 2.3e−16, see the
    /// [module docs](self) for the method and the underflow term); `t0 > t1`
    /// gives 0, a NaN end gives 0 (no panic).
    #[must_use]
    pub fn segment(&self, ray: &Ray<D>, t0: f64, t1: f64) -> f64 {
        let planes = [Plane {
            h: self.offset,
            sign: 1.0,
        }];
        clipped_length(&self.normal.get(), &planes, ray, t0, t1)
    }

    /// `f32` twin of [`HalfSpace::segment_batch_f32`] along `o + t·d` (`d` as
    /// given, not normalised: `t` and the length in units of `|d|`,
    /// [conventions](crate#conventions)): `g = n₃₂·o − h₃₂`, `c = n₃₂·d`,
    /// `t* = −g/c`, length of `[t0, t1]` on the kept side. Error against the
    /// `f64` path at the same (`f32`) inputs, with `u = 2⁻²⁴`: the crossing
    /// has absolute error
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

    /// SIMD batch (8 lanes) of [`HalfSpace::segment_f32`] (directions as given,
    /// as the scalar twin), bit-identical to the scalar twin lane by lane.
    ///
    /// # Errors
    /// [`ParamError::Length`] if the slices differ in length.
    pub fn segment_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        super::ray_batch(&HalfK32(self.n32, self.h32), rays, out)
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

    /// `∫_{t0}^{t1} 1[h0 ≤ n·(o + tω) ≤ h1] dt` (arc length,
    /// [conventions](crate#conventions)), relative error a few ulp (see the
    /// [module docs](self)); `t0 > t1` gives 0.
    #[must_use]
    pub fn segment(&self, ray: &Ray<D>, t0: f64, t1: f64) -> f64 {
        // n·x − h0 ≥ 0 and −(n·x − h1) ≥ 0.
        let planes = [
            Plane {
                h: self.h0,
                sign: 1.0,
            },
            Plane {
                h: self.h1,
                sign: -1.0,
            },
        ];
        clipped_length(&self.normal.get(), &planes, ray, t0, t1)
    }

    /// `f32` twin of [`Slab::segment_batch_f32`]: the [`HalfSpace::segment_f32`]
    /// computation for both planes (same error per crossing; `d` as given,
    /// `t` in units of `|d|`, [conventions](crate#conventions)).
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

    /// SIMD batch (8 lanes) of [`Slab::segment_f32`] (directions as given, as
    /// the scalar twin), bit-identical to the scalar twin lane by lane.
    ///
    /// # Errors
    /// [`ParamError::Length`] if the slices differ in length.
    pub fn segment_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        super::ray_batch(&SlabK32(self.n32, self.h32), rays, out)
    }
}

/// The half-space's `f32` segment length as a [`super::RayKernel32`].
struct HalfK32<const D: usize>([f32; D], f32);

impl<const D: usize> super::RayKernel32<D> for HalfK32<D> {
    #[inline(always)]
    fn eval<L: F32Lane>(&self, o: [L; D], d: [L; D], t0: L, t1: L) -> L {
        half_kernel::<L, D>(&self.0, self.1, o, d, t0, t1)
    }
}

/// The slab's `f32` segment length as a [`super::RayKernel32`].
struct SlabK32<const D: usize>([f32; D], [f32; 2]);

impl<const D: usize> super::RayKernel32<D> for SlabK32<D> {
    #[inline(always)]
    fn eval<L: F32Lane>(&self, o: [L; D], d: [L; D], t0: L, t1: L) -> L {
        slab_kernel::<L, D>(&self.0, self.1, o, d, t0, t1)
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
