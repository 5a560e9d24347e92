//! Indicator of a disk (`D = 2`) or ball (`D = 3`): [`Ball`].
// `!(x > y)` is deliberate below: it also catches NaN (overflowing inputs).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{check_dim, check_finite, Complex, Integrand};
use crate::error::ParamError;
use crate::geom::{for_each_piece, Direction};
use crate::num::{cis_turns, dot_turns, frac, two_prod, two_sum, Dd};
use crate::primitive::{Rays32, Segment};
use crate::world::sphere::{self, Sphere};
use core::f64::consts::PI;

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
/// Every chord is a [`crate::world::Sphere`] chord (the one closed form of the
/// shape; its module docs give the double-double algorithm and its error):
/// [`Ball::segment_free`] is [`crate::world::Sphere::segment`] of the ball at
/// the reduced centre, and the periodised integrals sum those chords over the
/// images of the ball that reach the piece. The result is the exact chord of
/// the given `f64` inputs up to a **relative** error of a few ulp when the
/// segment ends do not cut the chord, and at most `8u + 2⁻¹⁰⁰·(r/h + r²/h²)`
/// (half chord `h`) when they do, whatever the clipped length. (Tested against
/// exact dyadic arithmetic over radii `10⁻¹⁰⁰ … 1/2`, lengths down to
/// `10⁻¹⁵·2r`, straddling, ending at, starting at, inside and grazing, in 2D
/// and 3D: measured `≤ 3.8e−16` relative in every case.)
///
/// The `f32` batch path ([`Ball::segment_free_batch_f32`]) is
/// [`crate::world::Sphere::segment_batch_f32`]: see its docs for the error.
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
    /// The free-space ball at the reduced centre.
    sphere: Sphere<D>,
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
        let c = centre.map(frac);
        Ok(Self {
            centre: c,
            radius,
            sphere: Sphere::new(c, radius)?,
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
        let d = s.sub(self.sphere.r2());
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
        let s = crate::num::scalar::sqrt(kk);
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

    /// Whether the segment `c0 + tω`, `|t| ≤ half`, is provably farther than
    /// `r` from every image of the ball (then every piece's chord is exactly
    /// 0 and the segment integral is `+0.0`, so returning it early changes no
    /// bit; most short segments of a small ball take this exit).
    ///
    /// With `x = fl(c0 − c)` and `y = x − round(x)` (exact; `|y_j| ≤ 1/2`),
    /// `y` is the offset from the nearest image of the centre up to
    /// `e ≤ 2u·Σ|x_j|` (the rounding of `x`). Every other image is at least
    /// `1/2 − e` from the midpoint along some axis, so farther than `r` from
    /// the segment when `half + r + e < 1/2` (with a `10⁻⁹` margin). For the
    /// nearest image the squared distance to the segment is
    /// `|y|² − b²/a + a·max(|b|/a − half, 0)²` (`b = y·ω`, `a = |ω|²`; the
    /// perpendicular part plus the overshoot along the line), computed in
    /// `f64` with an absolute error below `10⁻¹⁵` (`|y|² ≤ 3/4`); it must
    /// exceed `r²` by `10⁻¹³ + 4e` (the error of `y` moves the distance by
    /// `e`, its square by `≤ 2.4e + e²`). The margin is far above what the
    /// double-double chords need to return exactly 0.
    #[inline]
    fn misses_every_image(&self, c0: &[f64; D], w: &[f64; D], half: f64) -> bool {
        let r = self.radius;
        let mut y = [0.0; D];
        let mut e = 0.0;
        for j in 0..D {
            let x = c0[j] - self.centre[j];
            y[j] = x - crate::num::scalar::round(x);
            e += x.abs();
        }
        let e = f64::EPSILON * e;
        if !(half + r + e < 0.5 - 1e-9) {
            return false;
        }
        let (mut yy, mut b, mut a) = (0.0, 0.0, 0.0);
        for j in 0..D {
            yy += y[j] * y[j];
            b += y[j] * w[j];
            a += w[j] * w[j];
        }
        let over = (b.abs() / a - half).max(0.0);
        let d2 = yy - b * b / a + a * over * over;
        d2 > r * r * (1.0 + 1e-12) + 1e-13 + 4.0 * e
    }

    /// [`Integrand::piece_integral`] with the offset `q0 = p − c` of the
    /// piece origin `p` from the centre given exactly (the origin itself is
    /// only used to select the images).
    fn piece_chords(
        &self,
        p: &[f64; D],
        q0: &[Dd; D],
        dir: &Direction<D>,
        a: Dd,
        t0: f64,
        t1: f64,
    ) -> f64 {
        if !(t1 > t0) {
            return 0.0;
        }
        let w = dir.get();
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
        // Per axis, the image offsets that can reach the piece on their own
        // (at most 2 of the 3, since r ≤ 1/2), and q's component for each.
        let mut cand = [[0usize; 3]; D];
        let mut ncand = [0usize; D];
        for j in 0..D {
            for mj in 0..3 {
                if dist2[j][mj] < r2 {
                    cand[j][ncand[j]] = mj;
                    ncand[j] += 1;
                }
            }
        }
        // The images in the order idx = m_0 + 3 m_1 + 9 m_2 (so the sum is
        // formed in the same order as over all 3^D images), each whose
        // distance to the piece's box is below r.
        let mut sum = 0.0;
        let mut k = [0usize; D];
        if ncand.contains(&0) {
            return 0.0;
        }
        loop {
            let mut dd = 0.0;
            for j in 0..D {
                dd += dist2[j][cand[j][k[j]]];
            }
            if dd < r2 {
                // q = p − (c + n), n = mj − 1, formed only for the images
                // that reach the piece.
                let q: [Dd; D] = core::array::from_fn(|j| {
                    let mj = cand[j][k[j]];
                    if mj == 1 {
                        q0[j]
                    } else {
                        q0[j].add(Dd::new(1.0 - mj as f64))
                    }
                });
                sum += sphere::chord(&q, &w, a, self.sphere.r2(), t0, t1);
            }
            // Odometer, axis 0 fastest.
            let mut j = 0;
            loop {
                if j == D {
                    return sum;
                }
                k[j] += 1;
                if k[j] < ncand[j] {
                    break;
                }
                k[j] = 0;
                j += 1;
            }
        }
    }
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
        let q: [Dd; D] = core::array::from_fn(|j| Dd::diff(p[j], self.centre[j]));
        self.sphere.segment_offset(&q, &dir.get(), t0, t1)
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
        self.sphere.segment_f32(o, d, t0, t1)
    }

    fn segment_free_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        self.sphere.segment_batch_f32(rays, out)
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
        self.piece_chords(p, &q0, dir, sphere::norm2(&dir.get()), t0, t1)
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
        let dir = seg.dir();
        if self.misses_every_image(&c0, &dir.get(), half) {
            return 0.0;
        }
        let mut c = [0.0; D];
        let mut cq = [Dd::new(0.0); D];
        for j in 0..D {
            c[j] = frac(c0[j]);
            // c0 − c is an integer up to the rounding of `frac` (≤ 2⁻⁵⁴, or
            // a result rounded to 1 returned as 0).
            cq[j] = Dd::diff(c0[j], self.centre[j])
                .sub(Dd::new(crate::num::scalar::round(c0[j] - c[j])));
        }
        // |ω|² once per segment (the same value every piece would compute).
        let a2 = sphere::norm2(&dir.get());
        let mut sum = 0.0;
        for_each_piece(&c, &dir, -half, half, |p, a, b| {
            let mut q0 = cq;
            for j in 0..D {
                q0[j] = cq[j].sub(Dd::new(crate::num::scalar::round(c[j] - p[j])));
            }
            sum += self.piece_chords(p, &q0, &dir, a2, a, b);
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
