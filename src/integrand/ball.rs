//! Indicator of a disk (`D = 2`) or ball (`D = 3`): [`Ball`].
// `!(x > y)` is deliberate below: it also catches NaN (overflowing inputs).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{check_dim, check_finite, Complex, Integrand};
use crate::error::ParamError;
use crate::geom::{for_each_piece, Direction};
use crate::num::lane::{load8, store8, F32Lane, LANES};
use crate::num::{cis_turns, dot_turns, frac, sum_accurate, two_prod, two_sum, Dd};
use crate::primitive::{Rays32, Segment};
use core::f64::consts::PI;
use wide::f32x8;

/// Unit roundoff `u = 2⁻⁵³`.
const EPS: f64 = f64::EPSILON / 2.0;

/// `2⁻⁴⁰`: below `2⁻⁴⁰·a·r²` the double-double discriminant is recomputed
/// from the exact constant term (see `chord`).
const TWO_M40: f64 = 9.094947017729282e-13;

/// `2⁻⁹⁶` (the conditioning margin of the clipped chord, see `chord`).
const TWO_M96: f64 = f64::from_bits((1023 - 96) << 52);

/// `2π` as a double-double.
const TWO_PI: Dd = Dd {
    hi: core::f64::consts::TAU,
    lo: 2.4492935982947064e-16,
};

/// Indicator of a disk (`D = 2`) or ball (`D = 3`) of radius `r ≤ 1/2` on the
/// unit torus.
///
/// `F(x) = 1[|x − c| < r]` (open ball; the boundary has measure zero and no
/// integral depends on the convention). Because `r ≤ 1/2` the images `c + n`,
/// `n ∈ ℤ^D`, are disjoint, so the periodised `f = Σ_n F(· + n)` takes only the
/// values 0 and 1.
///
/// # Numerics
///
/// The segment integral is a chord length. For `q = p − c` and `a = |ω|²` the
/// line `p + tω` meets the sphere where `a t² + 2(q·ω) t + |q|² − r² = 0`, i.e.
/// `t± = (−b ± √Δ)/a` with `b = q·ω`, `Δ = b² − a(|q|² − r²)`, and the chord is
/// `2√Δ/a`. In `f64` the subtraction in `Δ` cancels catastrophically for tangent
/// and grazing lines (`Δ → 0` while `b²` and `a|q|²` stay of order `|q|²`), so
/// [`Ball::segment_free`] evaluates `Δ` in double-double ([`crate::num::dd`]):
///
/// 1. `q = p − c` exactly (`Dd::diff`);
/// 2. the origin is moved along the line to (nearly) the foot of the
///    perpendicular, `q' = q + τω` with `τ ≈ −b/a` a double (`Dd::prod` is exact
///    and the accurate double-double addition has a relative error `≤ 3u²` of
///    its result, `u = 2⁻⁵³`), so that `|q'| ≈ dist(c, line)`; the step is
///    repeated while the remaining offset along the line exceeds `2²⁶r` (a
///    point given far along the line);
/// 3. `Δ = b'² − a(|q'|² − r²)` in double-double, where now the only
///    cancellation is `|q'|²` against `r²`, harmless at `2⁻¹⁰⁴` precision;
/// 4. `√Δ` is rounded once more by a Newton step, and `t± = τ − b'/a ± √Δ/a`;
/// 5. an end `e ∈ {t0, t1}` within rounding distance of the chord is never
///    subtracted from a rounded root: the quadratic is re-based at it,
///    `a s² + 2b_e s + c_e = 0` for `s = t − e`, with `q_e = q + eω`,
///    `b_e = q_e·ω` in double-double and `c_e = |q_e|² − r²` summed exactly
///    from error-free products in four-fold precision
///    ([`crate::num::sum_accurate`]; it cancels to about `h·L` against `r²`),
///    and its roots taken from the cancellation-free pair
///    `s₁ = −(b_e + sign(b_e)√Δ)/a`, `s₂ = c_e/(a s₁)`, so a root next to the
///    end (`c_e → 0`) keeps its relative accuracy. The clipped length is then
///    one such quantity: `t1 − t0` (both ends inside), `t+ − t0` (exits inside),
///    `t1 − t−` (enters inside) or `2h` (whole chord), never a difference of
///    two rounded parameters.
///
/// The result is the exact chord of the given `f64` inputs up to a **relative**
/// error of a few ulp (about `3u + 2⁻¹⁰⁴/(1 − d/r)` for a line at distance `d`
/// from the centre, i.e. a few ulp down to `1 − d/r ≈ 10⁻³⁰`) when the segment
/// ends do not cut the chord. When they do, the relative error is at most
/// `8u + 2⁻¹⁰⁰·(r/h + r²/h²)` for half chord `h`, **whatever the clipped
/// length** `L`: `≤ 1e−13` for segments of any length that straddle, end at
/// or lie next to the boundary, unless the line is within `h < 10⁻⁸r` of
/// tangency (the `r/h` term is the double-double conditioning of `b_e`, the
/// `r²/h²` term that of a near-tangent whole chord `2h`). A segment whose ends
/// are inside by more than `2⁻¹⁰⁰r²/h` has length exactly `fl(t1 − t0)`.
/// (Tested against exact dyadic arithmetic over radii `10⁻¹⁰⁰ … 1/2`, lengths
/// down to `10⁻¹⁵·2r`, straddling, ending at, starting at, inside and grazing,
/// in 2D and 3D: measured `≤ 3.3e−16` relative in every case.) Any finite
/// `p` is accepted (the repeated re-basing reaches the foot from as far as
/// `10³⁰⁸`), and `r ≥ 10⁻¹⁰⁰` (enforced: [`Ball::RADIUS_MIN`]), so the squares
/// formed near the foot neither overflow nor underflow.
///
/// The `f32` batch path ([`Ball::segment_free_batch_f32`], one kernel generic
/// over the crate's `f32` lane type) uses the plain formula in `f32` with a
/// perpendicular decomposition (`d² = |q − (q·ω/a)ω|²`, `h² = (r² − d²)/a`):
/// see its docs for the error.
///
/// # Example
///
/// ```
/// use linesample::integrand::{Ball, Integrand};
/// use linesample::geom::Direction;
/// let disk = Ball::<2>::new([0.5, 0.5], 0.25)?;
/// let x = Direction::axis(0)?;
/// // A horizontal line through the centre: the chord is the diameter.
/// assert_eq!(disk.segment_free(&[0.0, 0.5], &x, f64::NEG_INFINITY, f64::INFINITY), 0.5);
/// assert!((disk.integral() - core::f64::consts::PI / 16.0).abs() < 1e-16);
/// # Ok::<(), linesample::ParamError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball<const D: usize> {
    /// Centre reduced modulo 1, in `[0, 1)^D`.
    centre: [f64; D],
    radius: f64,
    /// `r²` exactly.
    r2: Dd,
    /// The centre rounded to `f32` (free-space `f32` path).
    centre32: [f32; D],
    /// `fl32(r32 · r32)`.
    r2_32: f32,
}

impl<const D: usize> Ball<D> {
    /// Smallest accepted radius, `10⁻¹⁰⁰`: below about `10⁻¹⁵⁰` the squared
    /// quantities of the double-double chord underflow (found by fuzzing: a
    /// chord of a `10⁻¹⁵⁹` ball exceeded its diameter by `1.4e−7` relative).
    pub const RADIUS_MIN: f64 = 1e-100;

    /// The ball of radius `radius` centred at `centre` (taken modulo 1, exactly:
    /// the free-space function [`Integrand::value_free`] and the `f32` path use
    /// the reduced centre `frac(c) ∈ [0, 1)^D`).
    ///
    /// # Errors
    /// [`ParamError::Dimension`] unless `D ∈ {2, 3}`; [`ParamError::NonFinite`]
    /// (`centre`, `radius`); [`ParamError::OutOfRange`] (`radius`) unless
    /// [`Ball::RADIUS_MIN`] `≤ r ≤ 1/2`.
    pub fn new(centre: [f64; D], radius: f64) -> Result<Self, ParamError> {
        check_dim::<D>()?;
        check_finite("centre", &centre)?;
        if !radius.is_finite() {
            return Err(ParamError::NonFinite { name: "radius" });
        }
        if !(Self::RADIUS_MIN..=0.5).contains(&radius) {
            return Err(ParamError::OutOfRange {
                name: "radius",
                value: radius,
                min: Self::RADIUS_MIN,
                max: 0.5,
            });
        }
        let mut c = [0.0; D];
        let mut c32 = [0.0f32; D];
        for j in 0..D {
            c[j] = frac(centre[j]);
            c32[j] = c[j] as f32;
        }
        let r32 = radius as f32;
        Ok(Self {
            centre: c,
            radius,
            r2: Dd::prod(radius, radius),
            centre32: c32,
            r2_32: r32 * r32,
        })
    }

    /// The centre, reduced modulo 1 (in `[0, 1)^D`).
    #[inline]
    #[must_use]
    pub fn centre(&self) -> [f64; D] {
        self.centre
    }

    /// The radius `r`.
    #[inline]
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// `|q|² < r²`, decided in double-double (`q` exact).
    #[inline]
    fn inside(&self, q: &[Dd; D]) -> bool {
        let mut s = Dd::new(0.0);
        for x in q {
            s = s.add(x.mul(*x));
        }
        let d = s.sub(self.r2);
        d.hi < 0.0 || (d.hi == 0.0 && d.lo < 0.0)
    }

    /// The amplitude `F̂(k)·e^{2πik·c}` (real), see [`Integrand::fourier`].
    fn amplitude(&self, k: &[i32; D]) -> f64 {
        let r = self.radius;
        let ksq: u128 = k
            .iter()
            .map(|&x| {
                let a = u128::from(x.unsigned_abs());
                a * a
            })
            .sum();
        if ksq == 0 {
            return self.integral();
        }
        // ρ = |k| as a double-double: one rounding of |k|² (exact below 2⁵³),
        // then a Newton-corrected square root.
        let kk = ksq as f64;
        let s = libm::sqrt(kk);
        let (p, pe) = two_prod(s, s);
        let rho = {
            let (hi, lo) = two_sum(s, ((kk - p) - pe) / (2.0 * s));
            Dd { hi, lo }
        };
        // x = 2πρr in double-double.
        let xd = TWO_PI.mul(rho).mul(Dd::new(r));
        let (x, xl) = (xd.hi, xd.lo);
        let rho_f = rho.to_f64();
        if D == 2 {
            // F̂ = r·J1(x)/ρ. For large x a first-order correction carries the
            // low part of x: J1(x + δ) = J1(x) + δ·(J0(x) − J1(x)/x) + O(δ²).
            let j1 = libm::j1(x);
            let j = if x >= 2.0 {
                j1 + xl * (libm::j0(x) - j1 / x)
            } else {
                j1
            };
            r * j / rho_f
        } else if x < 2.0 {
            // (sin x − x cos x)/x³ = Σ_{n≥1} (−1)^{n+1}·2n·x^{2n−2}/(2n+1)!,
            // F̂ = 4πr³·that (no cancellation, no underflow of x³).
            let x2 = x * x;
            let mut term = 1.0 / 3.0; // n = 1
            let mut sum = term;
            let mut n = 1.0f64;
            for _ in 0..30 {
                // t_{n+1}/t_n = −x²/(2n(2n+3))
                term *= -x2 / ((2.0 * n) * (2.0 * n + 3.0));
                n += 1.0;
                let next = sum + term;
                if next == sum {
                    break;
                }
                sum = next;
            }
            4.0 * PI * r * r * r * sum
        } else {
            // g(x) = sin x − x cos x, g'(x) = x sin x; F̂ = g/(2π²ρ³).
            let (sn, cs) = libm::sincos(x);
            let g = (sn - x * cs) + xl * x * sn;
            let rho3 = rho.mul(rho).mul(rho).to_f64();
            g / (2.0 * PI * PI * rho3)
        }
    }

    /// [`Integrand::piece_integral`] with the offset `q0 = p − c` of the
    /// piece origin `p` from the centre given exactly (the origin itself is
    /// only used to select the images).
    fn piece_chords(
        &self,
        p: &[f64; D],
        q0: &[Dd; D],
        dir: &Direction<D>,
        t0: f64,
        t1: f64,
    ) -> f64 {
        if !(t1 > t0) {
            return 0.0;
        }
        let w = dir.get();
        let a = norm2(&w);
        let r = self.radius;
        // Bounding box of the piece, clamped to the unit cell (where the piece
        // lies by contract; also covers infinite parameters).
        let mut lo = [0.0; D];
        let mut hi = [1.0; D];
        for j in 0..D {
            let (u, v) = (p[j] + t0 * w[j], p[j] + t1 * w[j]);
            let (u, v) = if u <= v { (u, v) } else { (v, u) };
            if u.is_finite() && v.is_finite() {
                lo[j] = u.clamp(0.0, 1.0);
                hi[j] = v.clamp(0.0, 1.0);
            }
        }
        // Per-axis distance from c_j + n_j to [lo_j, hi_j], shrunk by a margin
        // that covers its rounding, so no reaching image is ever dropped.
        let mut dist2 = [[0.0f64; 3]; D];
        for j in 0..D {
            for (m, n) in [-1.0f64, 0.0, 1.0].into_iter().enumerate() {
                let x = self.centre[j] + n;
                let d = (lo[j] - x).max(x - hi[j]).max(0.0);
                let d = (d - 4e-16).max(0.0);
                dist2[j][m] = d * d;
            }
        }
        let r2 = r * r * (1.0 + 1e-12);
        let mut sum = 0.0;
        let total = if D == 2 { 9 } else { 27 };
        for idx in 0..total {
            let mut m = idx;
            let mut dd = 0.0;
            let mut q = *q0;
            for j in 0..D {
                let mj = m % 3;
                m /= 3;
                dd += dist2[j][mj];
                if mj != 1 {
                    // q = p − (c + n), n = mj − 1
                    q[j] = q[j].add(Dd::new(1.0 - mj as f64));
                }
            }
            if dd < r2 {
                sum += chord(&q, &w, a, self.r2, t0, t1);
            }
        }
        sum
    }

    /// The `f32` chord kernel shared by the scalar twin and the SIMD batch.
    #[inline(always)]
    fn chord_lanes<L: F32Lane>(&self, o: [L; D], d: [L; D], t0: L, t1: L) -> L {
        let zero = L::splat(0.0);
        let mut q = [zero; D];
        for j in 0..D {
            q[j] = o[j] - L::splat(self.centre32[j]);
        }
        let mut a = d[0] * d[0];
        let mut b = q[0] * d[0];
        for j in 1..D {
            a = a + d[j] * d[j];
            b = b + q[j] * d[j];
        }
        let inv_a = L::splat(1.0) / a;
        let tm = -(b * inv_a);
        // Squared distance from the centre to the line, from the perpendicular
        // component (no cancellation of |q|² against (q·ω)²/a).
        let mut p2 = zero;
        for j in 0..D {
            let e = q[j] + tm * d[j];
            p2 = p2 + e * e;
        }
        let h2 = (L::splat(self.r2_32) - p2) * inv_a;
        let h = h2.max(zero).sqrt();
        let lo = t0.max(tm - h);
        let hi = t1.min(tm + h);
        (hi - lo).max(zero)
    }
}

/// Chord of the free-space ball `|y| < r` (`r² = r2`) with the line
/// `q + tω`, `t ∈ [t0, t1]`; `q` exact in double-double, `a = |ω|²`. See the
/// module docs for the algorithm and its error.
#[inline]
fn chord<const D: usize>(q: &[Dd; D], w: &[f64; D], a: Dd, r2: Dd, t0: f64, t1: f64) -> f64 {
    // Re-base at (nearly) the foot of the perpendicular: q' = q + τω, each
    // shift τ a double and exact as a product (Dd::prod). The rounding of τ
    // leaves q' about (D + 2)u|q| from the foot along ω; the double-double q'
    // holds that offset accurately, so a further pass shrinks it to about u
    // times itself. Passes continue while the offset exceeds r, so
    // |q'| ≲ dist + r afterwards (found by fuzzing: a whole line through
    // (2.4e35, 2.4e35) gave a chord of 2048 for r = 0.13, one through
    // (−7.3e211, …) 1.9e50); an ordinary ray (offset ≈ u|q| ≪ r) takes one
    // pass. Each pass shrinks the offset by about 2⁻⁵⁰, so 25 reach r from any
    // finite point (|p − c| ≤ 10³⁰⁸, r ≥ 10⁻¹⁰⁰).
    let rf = libm::sqrt(r2.hi);
    let sa = libm::sqrt(a.hi);
    let mut qp = *q;
    let mut tau = Dd::ZERO;
    // Σ|q_j| of the point the last shift was computed from (its rounding
    // sets the rejection slack below), and of the given point.
    let mut qn = 0.0;
    let mut q0n = 0.0;
    for pass in 0..25 {
        let mut bp = 0.0;
        let mut qpn = 0.0;
        for j in 0..D {
            bp += qp[j].hi * w[j];
            qpn += qp[j].hi.abs();
        }
        let t = -bp / a.hi;
        if pass == 0 {
            q0n = qpn;
        } else if !(t.abs() * sa > rf) {
            break;
        }
        for j in 0..D {
            qp[j] = qp[j].add(Dd::prod(t, w[j]));
        }
        tau = tau.add(Dd::new(t));
        qn = qpn;
    }
    let tau = tau.to_f64();
    let mut d2 = 0.0;
    let mut qpn = 0.0;
    for j in 0..D {
        d2 += qp[j].hi * qp[j].hi;
        qpn += qp[j].hi.abs();
    }
    // Quick, safe rejection: d2 is within a few ulp of the exact |q'|², and
    // |q'|² = dist² + a(τ − τ*)² with |τ − τ*| ≤ (D + 2)u|q| (τ* the exact
    // foot), which matters when r ≲ u|q| (a tiny ball seen from afar, whose
    // chords were once all rejected). Also rejects NaN from overflowing inputs.
    let slack = 8.0 * EPS * qn;
    if !(d2 <= r2.hi * (1.0 + 1e-12) + slack * slack) {
        return 0.0;
    }
    let mut b = Dd::new(0.0);
    let mut qq = Dd::new(0.0);
    for j in 0..D {
        b = b.add(qp[j].mul(Dd::new(w[j])));
        qq = qq.add(qp[j].mul(qp[j]));
    }
    let mut delta = b.mul(b).sub(a.mul(qq.sub(r2)));
    if !(delta.hi > TWO_M40 * a.hi * r2.hi) {
        // Near tangency (or a miss) the double-double Δ has lost ≥ 40 of its
        // bits to |q'|² − r²: recompute it from the exact constant term at the
        // base point τ (Δ = b_e² − a·c_e does not depend on the base point;
        // fuzz finding: a line 1e-42 inside the tangent of r = 4.8e-4 got
        // h = 3e-127 for 3.2e-23 and then a chord of 1.5e63).
        // The exact sum is only as good as its condition number: use it when
        // q itself is near the foot (|q| ≲ 4(|q'| + r)); from a far point the
        // expansion of |q + τω|² cancels by |q|²/r² and the double-double Δ
        // of the re-based q' is the better one (fuzz finding: a line through
        // (2.4e35, 2.4e35, 2.4e35) got Δ = 2²³ from the expansion).
        if q0n <= 4.0 * (qpn + rf) {
            let (be, ce) = rebased_bc(q, w, r2, tau);
            delta = be.mul(be).sub(a.mul(ce));
        }
    }
    if !(delta.hi > 0.0) {
        return 0.0;
    }
    let af = a.to_f64();
    let sd = delta.sqrt().hi;
    let h = sd / af;
    let tm = tau - b.to_f64() / af;
    let (lo, hi) = (tm - h, tm + h);
    // A bound on |lo − t−| and |hi − t+| (t± the exact roots): the roundings of
    // τ, b/a, t_m and t_m ± h, and the conditioning of h (its absolute error is
    // ≈ 2⁻¹⁰⁴·r²/h, from Δ's). An end farther than `m` from both roots is on a
    // known side of each, so only an end within `m` needs the re-based roots.
    let m = 8.0 * EPS * (tau.abs() + tm.abs() + h) + TWO_M96 * (r2.hi / h);
    if t0 + m < lo && hi + m < t1 {
        // Clearly unclipped; still never longer than the segment itself (when
        // `tm ± h` round onto a zero-length segment far out on the line, found
        // by fuzzing).
        return (2.0 * h).min(t1 - t0);
    }
    // A NaN end is unbounded on its side.
    let t0 = if t0.is_nan() { f64::NEG_INFINITY } else { t0 };
    let t1 = if t1.is_nan() { f64::INFINITY } else { t1 };
    if !(t0 <= t1) || t1 + m < lo || hi + m < t0 {
        return 0.0;
    }
    // The clipped length, each case one accurately computed quantity (no
    // rounded root minus an end). With s± = t± − t0 and u± = t± − t1, the
    // roots of the quadratic re-based at each end (`rebased_roots`; an end
    // farther than `m` from the chord has known signs), and T = fl(t1 − t0):
    //   s− ≤ 0 ≤ u+ (both ends inside):  T,
    //   s− ≤ 0, u+ < 0 (exits inside):    min(T, s+),
    //   s− > 0 (enters inside):           min(T, −u−, 2h)   (−u− = T − s−).
    // The signs of s−, u+ are those of the re-based constant terms c_e, whose
    // double-double error is ≈ 2⁻¹⁰²|q_e|², so an end inside the boundary by
    // more than ≈ 2⁻¹⁰⁰r²/h (far below 1 ulp of e unless e ≈ 0) keeps T.
    let len = t1 - t0;
    let (sm, sp) = if lo <= t0 + m {
        rebased_roots(q, w, r2, af, sd, t0)
    } else {
        (f64::INFINITY, f64::INFINITY)
    };
    let (um, up) = if t1 <= hi + m {
        rebased_roots(q, w, r2, af, sd, t1)
    } else {
        (f64::NEG_INFINITY, f64::NEG_INFINITY)
    };
    if sm <= 0.0 {
        if !(sp > 0.0) {
            return 0.0;
        }
        if up >= 0.0 {
            return len;
        }
        return len.min(sp);
    }
    len.min(-um).min(2.0 * h).max(0.0)
}

/// The roots `(s−, s+)`, `s = t − e`, of the chord's quadratic re-based at the
/// finite end `e`: `a s² + 2 b_e s + c_e = 0` with `q_e = q + eω` (exact
/// products, ≈ 2⁻¹⁰⁴-relative sums), `b_e = q_e·ω`, `c_e = |q_e|² − r²` in
/// double-double and `√Δ = sd` (`Δ = b_e² − a c_e` is independent of `e`; the
/// caller's is computed where it does not cancel). The root of larger
/// magnitude is `−(b_e + sign(b_e)√Δ)/a` (no cancellation), the other `c_e`
/// over that numerator (the product of the roots is `c_e/a`), so a root near
/// the end (`c_e → 0`) keeps its relative accuracy.
#[inline]
fn rebased_roots<const D: usize>(
    q: &[Dd; D],
    w: &[f64; D],
    r2: Dd,
    af: f64,
    sd: f64,
    e: f64,
) -> (f64, f64) {
    let (b, c) = rebased_bc(q, w, r2, e);
    let (b, c) = (b.to_f64(), c.to_f64());
    if b >= 0.0 {
        let k = -(b + sd);
        (k / af, c / k)
    } else {
        let k = sd - b;
        (c / k, k / af)
    }
}

/// `b_e = q_e·ω` (double-double) and `c_e = |q_e|² − r²` for `q_e = q + eω`.
///
/// `c_e` cancels to about `h·L` against `r²` for an end near the boundary (`L`
/// its distance to the root, `h` the half chord), and to `r² − d²` at the foot
/// of a near-tangent line, which a double-double sum would resolve only to
/// `2⁻¹⁰⁶r²`: it is formed exactly as a sum of error-free products (`q_j = hi +
/// lo` and `e·ω_j = p + p'` exactly, so `(q + eω)_j²` is 10 products of
/// doubles) summed in four-fold precision ([`sum_accurate`]).
#[inline]
fn rebased_bc<const D: usize>(q: &[Dd; D], w: &[f64; D], r2: Dd, e: f64) -> (Dd, Dd) {
    let mut b = Dd::new(0.0);
    let mut t = [0.0f64; 62];
    let mut n = 0;
    for j in 0..D {
        let qe = q[j].add(Dd::prod(e, w[j]));
        b = b.add(qe.mul(Dd::new(w[j])));
        let (ph, pl) = two_prod(e, w[j]);
        let parts = [q[j].hi, q[j].lo, ph, pl];
        for i in 0..4 {
            for k in i..4 {
                let (x, y) = two_prod(parts[i], parts[k]);
                let f = if i == k { 1.0 } else { 2.0 };
                t[n] = f * x;
                t[n + 1] = f * y;
                n += 2;
            }
        }
    }
    t[n] = -r2.hi;
    t[n + 1] = -r2.lo;
    n += 2;
    (b, sum_accurate(&mut t[..n]))
}

/// `|ω|²` in double-double.
#[inline]
fn norm2<const D: usize>(w: &[f64; D]) -> Dd {
    let mut a = Dd::new(0.0);
    for &x in w {
        a = a.add(Dd::prod(x, x));
    }
    a
}

impl<const D: usize> Integrand<D> for Ball<D> {
    /// `1[|x − c| < r]` with the reduced centre `c ∈ [0, 1)^D` (decided exactly,
    /// in double-double).
    fn value_free(&self, x: &[f64; D]) -> f64 {
        let mut q = [Dd::new(0.0); D];
        for j in 0..D {
            q[j] = Dd::diff(x[j], self.centre[j]);
        }
        if self.inside(&q) {
            1.0
        } else {
            0.0
        }
    }

    /// The chord `max(0, min(t1, t+) − max(t0, t−))`, in double-double: relative
    /// error of a few ulp for an unclipped chord (including tangent and grazing
    /// lines), and relative error `≤ 8u + 2⁻¹⁰⁰·(r/h + r²/h²)` (`h` the half
    /// chord) when the ends clip it, whatever the clipped length, i.e. a few
    /// ulp for short segments at the boundary too. See [`Ball`] (numerics).
    ///
    /// Bad input (no panic): `t0 > t1` gives 0; a NaN or infinite `p`, or a
    /// line so far away that the squares overflow, gives 0; a NaN end is
    /// treated as unbounded on its side.
    fn segment_free(&self, p: &[f64; D], dir: &Direction<D>, t0: f64, t1: f64) -> f64 {
        let w = dir.get();
        let mut q = [Dd::new(0.0); D];
        for j in 0..D {
            q[j] = Dd::diff(p[j], self.centre[j]);
        }
        chord(&q, &w, norm2(&w), self.r2, t0, t1)
    }

    /// `f32` chord: `q = o − c₃₂`, `a = |d|²`, `t_m = −(q·d)·(1/a)`,
    /// `h² = (r₃₂² − |q + t_m d|²)·(1/a)`, result `max(0, min(t1, t_m + h) −
    /// max(t0, t_m − h))` (one division, one square root, no FMA; `d ≠ 0`).
    ///
    /// Error against the exact chord of the `f32` inputs, for `|d| = 1` and
    /// `L = |o − c₃₂|`: the distance `d⊥` from the centre to the line is
    /// computed to a few `ε₃₂·L` absolute (`ε₃₂ = 2⁻²³`), so `h²` (`h` = half
    /// chord) is off by about `δ = ε₃₂·(L·r + r²)` and the chord by about
    /// `min(δ/h, 2√δ)`: absolute, in units of `r`, `≈ ε₃₂·L/r` well inside the
    /// ball (`h ≳ r`), growing to `≈ 2√(ε₃₂·L/r)` at tangency (the square-root
    /// singularity of the chord at `d⊥ = r`); clipping adds
    /// `≈ ε₃₂·(|t0| + |t1| + |t±|)`. The tests measure at most `2.2×` that model;
    /// e.g. for `L ≤ 1`: `≤ 1e-6·r` (`r = 0.1`) and `≤ 1e-4·r` (`r = 10⁻³`)
    /// for `d⊥ ≤ r/2`, `≤ 2e-3·r` (`r = 0.1`) and `≤ 2e-2·r` (`r = 10⁻³`)
    /// within `10⁻⁶r` of tangency. The model assumes `r²` is a normal `f32`:
    /// for `r ≲ 1e−19` it underflows and `δ` gains about `4·2⁻¹⁴⁹` (found by
    /// the `integrand_ball` fuzz target). The centre is the reduced centre
    /// rounded to `f32`. Bad input (no panic): `t0 > t1` gives 0, a NaN or infinite
    /// origin gives 0, a NaN end is treated as unbounded; `d` must be non-zero
    /// (the result for `d = 0` is unspecified).
    fn segment_free_f32(&self, o: [f32; D], d: [f32; D], t0: f32, t1: f32) -> f32 {
        self.chord_lanes::<f32>(o, d, t0, t1)
    }

    fn segment_free_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        let n = rays.check(out.len())?;
        let mut i = 0;
        while i + LANES <= n {
            let o: [f32x8; D] = core::array::from_fn(|j| load8(rays.origin[j], i));
            let d: [f32x8; D] = core::array::from_fn(|j| load8(rays.dir[j], i));
            let v = self.chord_lanes(o, d, load8(rays.t0, i), load8(rays.t1, i));
            store8(out, i, v);
            i += LANES;
        }
        for i in i..n {
            let o = core::array::from_fn(|j| rays.origin[j][i]);
            let d = core::array::from_fn(|j| rays.dir[j][i]);
            out[i] = self.chord_lanes::<f32>(o, d, rays.t0[i], rays.t1[i]);
        }
        Ok(())
    }

    /// `1` if the minimal-image distance from `x` to the centre is `< r`
    /// (decided exactly in double-double), else `0`.
    fn value(&self, x: &[f64; D]) -> f64 {
        if x.iter().any(|v| !v.is_finite()) {
            return 0.0;
        }
        let mut q = [Dd::new(0.0); D];
        for j in 0..D {
            // y ∈ (−1, 1); the nearest image shifts it into [−1/2, 1/2].
            let y = Dd::diff(frac(x[j]), self.centre[j]);
            q[j] = if y.hi > 0.5 {
                y.add(Dd::new(-1.0))
            } else if y.hi < -0.5 {
                y.add(Dd::new(1.0))
            } else {
                y
            };
        }
        if self.inside(&q) {
            1.0
        } else {
            0.0
        }
    }

    /// `πr²` (2D) or `4πr³/3` (3D).
    fn integral(&self) -> f64 {
        let r = self.radius;
        if D == 2 {
            PI * r * r
        } else {
            4.0 / 3.0 * PI * r * r * r
        }
    }

    /// Sum of the chords of the images `c + n`, `n ∈ {−1, 0, 1}^D`, whose
    /// distance to the piece's bounding box is below `r` (`c ∈ [0, 1)^D` and
    /// `r ≤ 1/2`, so no other image reaches the unit cell). `q = p − c − n` is
    /// formed in double-double, so each chord has the error of
    /// [`Ball::segment_free`].
    fn piece_integral(&self, p: &[f64; D], dir: &Direction<D>, t0: f64, t1: f64) -> f64 {
        let mut q0 = [Dd::new(0.0); D];
        for j in 0..D {
            q0[j] = Dd::diff(p[j], self.centre[j]);
        }
        self.piece_chords(p, &q0, dir, t0, t1)
    }

    /// The wrapped segment integral: the sum of the piece integrals over the
    /// cells crossed, as the provided method, but with each piece's offset
    /// from the centre, `c_s − c − k − m` (segment centre `c_s`, `k` the
    /// integer it is reduced by, `m` the piece's cell), formed exactly in
    /// double-double instead of from the piece origin `frac(c_s) − m` that
    /// [`crate::geom::for_each_piece`] rounds. The chords are clipped at the
    /// pieces' ends, so a rounded origin would shift a clip at the boundary by
    /// up to `2⁻⁵⁴`, a large relative error for a short segment. Each piece
    /// then has the error of [`Ball::segment_free`] (see [`Ball`], numerics).
    fn segment_integral(&self, seg: &Segment<D>) -> f64 {
        let half = 0.5 * seg.length();
        if half == 0.0 {
            return 0.0;
        }
        let c0 = seg.centre();
        let mut c = [0.0; D];
        let mut cq = [Dd::new(0.0); D];
        for j in 0..D {
            c[j] = frac(c0[j]);
            // c0 − c is an integer up to the rounding of `frac` (≤ 2⁻⁵⁴, or
            // a result rounded to 1 returned as 0).
            cq[j] = Dd::diff(c0[j], self.centre[j]).sub(Dd::new(libm::round(c0[j] - c[j])));
        }
        let dir = seg.dir();
        let mut sum = 0.0;
        for_each_piece(&c, &dir, -half, half, |p, a, b| {
            let mut q0 = cq;
            for j in 0..D {
                q0[j] = cq[j].sub(Dd::new(libm::round(c[j] - p[j])));
            }
            sum += self.piece_chords(p, &q0, &dir, a, b);
        });
        sum
    }

    /// `1`.
    fn max_value(&self) -> f64 {
        1.0
    }

    /// `F̂(k) = A(|k|)·e^{−2πi k·c}` with, for `ρ = |k|`, `x = 2πρr`:
    /// disk `A = r·J1(x)/ρ` (`πr²` at `k = 0`), ball
    /// `A = (sin x − x cos x)/(2π²ρ³)` (a power series of `(sin x − x cos x)/x³`
    /// for `x < 2`; `4πr³/3` at `k = 0`).
    ///
    /// High frequencies: the phase `k·c mod 1` is reduced exactly (`k_j c_j` by
    /// `two_prod`, minus its nearest integer, summed in double-double) and the
    /// angle `2π·frac` carries its low part, so the phase factor is accurate to
    /// about 1 ulp for every `k`. `x` is formed in double-double
    /// (`ρ` with a Newton correction, `2π` as a double-double) and its low part
    /// enters through the derivative (`J1' = J0 − J1/x`, `g' = x sin x`), so the
    /// argument error does not grow with `|k|`.
    ///
    /// Accuracy: few ulp relative wherever the amplitude is not near a zero of
    /// `J1(x)` (disk) or of `tan x = x` (ball). `libm::j1` (the FreeBSD/musl
    /// algorithm) is only **absolutely** accurate near its zeros (about
    /// `ε·√(2/(πx))`), so there the disk coefficient has an absolute error of
    /// about `ε·r·√(2/(πx))/ρ`; the ball's has an absolute error of about
    /// `ε·x/(2π²ρ³)` there.
    fn fourier(&self, k: &[i32; D]) -> Complex {
        let amp = self.amplitude(k);
        // e^{−2πik·c} with k·c reduced modulo 1 exactly (crate::num::phase).
        cis_turns(dot_turns(k, &self.centre)).scale(amp)
    }
}
