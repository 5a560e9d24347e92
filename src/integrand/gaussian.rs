//! The normalised isotropic Gaussian density, periodised on the unit torus.
//!
//! `F(x) = (2πσ²)^{−D/2} e^{−|x − c|²/2σ²}`, `∫_{ℝ^D} F = 1`,
//! `F̂(k) = e^{−2π²σ²|k|²} e^{−2πik·c}`.
//!
//! Along a ray `p + tω`, with `q = p − c`, `a = |ω|²`, `b = q·ω`, the foot
//! parameter `t_c = −b/a` and the squared distance of the line from the centre
//! `ρ² = |q|² − b²/a = |q × ω|²/a` (Lagrange's identity, no cancellation),
//!
//! ```text
//! ∫_{t0}^{t1} F = (2πσ²)^{−D/2} e^{−ρ²/2σ²} (σ√2/√a) G(u0, u1),
//! G(u0, u1) = ∫_{u0}^{u1} e^{−u²} du,   u = √a (t − t_c)/(σ√2).
//! ```
//!
//! See [`Gaussian::segment_free`](Integrand::segment_free) for how `G` and the
//! exponentials are evaluated without cancellation, and [`Gaussian`] for the
//! periodisation (real-space images for `σ ≤ 0.3`, Fourier/theta series above).

use super::{check_dim, check_finite, Complex, Integrand};
use crate::error::ParamError;
use crate::geom::{clip_to_unit_box, for_each_piece, Direction};
use crate::num::frac;
use crate::num::Dd;
use crate::num::{cis_turns, dot_turns, frac_centered, sinc_dd};
use crate::primitive::{Line, Rays32, Segment};
use crate::special::{exp_neg_dd, exp_neg_lane};
use crate::world::Gaussian as FreeGaussian;
use core::f64::consts::{PI, TAU};
use wide::f64x4;

const SIGMA_MIN: f64 = Gaussian::<2>::SIGMA_MIN;
const SIGMA_MAX: f64 = Gaussian::<2>::SIGMA_MAX;
const SIGMA_SWITCH: f64 = Gaussian::<2>::SIGMA_SWITCH;

/// Truncation threshold: terms below `e^{−TAIL}` relative to the leading term
/// are dropped (`e^{−45} ≈ 2.9e−20`).
const TAIL: f64 = 45.0;

/// Most candidate images a piece sorts by distance (`Gaussian::sorted_images`);
/// more (3D, σ near [`SIGMA_SWITCH`]) take the odometer order.
const MAX_SORTED: usize = 96;

/// Most image offsets per axis in `Gaussian::sorted_images`.
const AXIS: usize = 12;

/// `2⁻⁶⁰`: the relative size below which the remaining images are dropped.
const TWO_M60: f64 = 8.673_617_379_884_035e-19;

/// Images bounded below this share (`2⁻¹⁰`) of the sum so far are evaluated in
/// `f64` SIMD lanes (`world::Gaussian::segment_far4`), the rest in
/// double-double.
const FAR: f64 = 9.765_625e-4;

/// `π` as a double-double.
const PI_LO: f64 = 1.2246467991473532e-16;

/// The normalised isotropic Gaussian density `(2πσ²)^{−D/2} e^{−|x−c|²/2σ²}`
/// (`D` = 2 or 3), periodised on the unit torus.
///
/// * `σ ∈ [1e−6, 1e6]` ([`Gaussian::SIGMA_MIN`], [`Gaussian::SIGMA_MAX`]); the centre is stored
///   modulo 1.
/// * Periodisation: for `σ ≤` [`Gaussian::SIGMA_SWITCH`] (`0.3`) point values are
///   products of 1D real-space image sums and [`Integrand::piece_integral`]
///   sums the free-space closed form over the images whose Gaussian can
///   contribute more than `e^{−45}` relative to the nearest image anywhere on
///   the piece; above it, point values are products of 1D theta series
///   `Σ_k e^{−2π²σ²k²} cos(2πk(x − c))` and segment, piece and line integrals
///   use the Fourier series `Σ_k f̂_k e^{2πik·c_s} λ sinc(λ k·ω)` (cost
///   independent of the segment length; `O(1)` for `σ ≥ 1.6`, where only
///   `k = 0` survives).
/// * Every `f64` method is accurate to about `1e−15` relative (see each method);
///   tail values keep their relative accuracy down to the normal range.
#[derive(Clone, Copy, Debug)]
pub struct Gaussian<const D: usize> {
    centre: [f64; D],
    sigma: f64,
    /// `σ²` as an exact double-double, times 2.
    two_s2: Dd,
    /// `(2πσ²)^{−D/2}`.
    norm: f64,
    /// `2π²σ²` as a double-double.
    two_pi2_s2: Dd,
    max: f64,
    /// The free-space Gaussian at the reduced centre (segment integrals and
    /// the `f32` path).
    free: FreeGaussian<D>,
}

impl<const D: usize> Gaussian<D> {
    /// Smallest accepted `σ`.
    pub const SIGMA_MIN: f64 = 1e-6;
    /// Largest accepted `σ`.
    pub const SIGMA_MAX: f64 = 1e6;
    /// For `σ ≤ SIGMA_SWITCH` the periodisation is summed over real-space images,
    /// above it over Fourier modes (theta series).
    ///
    /// At `σ = 0.3` both are cheap and accurate: a 1D image sum needs `|n| ≤ 4`
    /// and the theta series `k ≤ 5`; along segments the real-space sum visits about
    /// `(4π/3)(9.5σ)³ ≈ 80` images per piece in 3D and the Fourier series about
    /// 270 modes per segment (independent of its length), whose relative rounding
    /// error is amplified by at most `max Σ|terms| / min f ≈ 8` there (it grows
    /// quickly below `σ ≈ 0.25`).
    pub const SIGMA_SWITCH: f64 = 0.3;

    /// The normalised Gaussian of standard deviation `sigma` centred at
    /// `centre` (any finite point; stored modulo 1 with `num::frac`, which is
    /// exact for non-negative coordinates and rounds `1 − |x|`-type results for
    /// negative ones by at most `2⁻⁵⁴`).
    ///
    /// # Errors
    /// [`ParamError::Dimension`] unless `D ∈ {2, 3}`; [`ParamError::NonFinite`]
    /// (`centre`, `sigma`); [`ParamError::OutOfRange`] (`sigma`) unless
    /// `1e−6 ≤ σ ≤ 1e6`.
    pub fn new(centre: [f64; D], sigma: f64) -> Result<Self, ParamError> {
        check_dim::<D>()?;
        check_finite("centre", &centre)?;
        if !sigma.is_finite() {
            return Err(ParamError::NonFinite { name: "sigma" });
        }
        if !(SIGMA_MIN..=SIGMA_MAX).contains(&sigma) {
            return Err(ParamError::OutOfRange {
                name: "sigma",
                value: sigma,
                min: SIGMA_MIN,
                max: SIGMA_MAX,
            });
        }
        let mut c = [0.0; D];
        for j in 0..D {
            c[j] = frac(centre[j]);
        }
        let s2 = Dd::prod(sigma, sigma);
        let two_s2 = Dd {
            hi: 2.0 * s2.hi,
            lo: 2.0 * s2.lo,
        };
        let pi = Dd { hi: PI, lo: PI_LO };
        let pi2 = pi.mul(pi);
        let two_pi2_s2 = Dd {
            hi: 2.0 * pi2.hi,
            lo: 2.0 * pi2.lo,
        }
        .mul(s2);
        let free = FreeGaussian::normalised(c, sigma)?;
        let mut g = Self {
            centre: c,
            sigma,
            two_s2,
            norm: free.peak(),
            two_pi2_s2,
            max: 0.0,
            free,
        };
        g.max = g.value(&c);
        Ok(g)
    }

    /// The centre, reduced modulo 1 (in `[0, 1)^D`).
    #[must_use]
    pub fn centre(&self) -> [f64; D] {
        self.centre
    }

    /// The standard deviation `σ`.
    #[must_use]
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// The normalisation `(2πσ²)^{−D/2}` (the free-space peak value).
    #[must_use]
    pub fn peak(&self) -> f64 {
        self.norm
    }

    /// `x / (2σ²)` in double-double.
    #[inline]
    fn over_two_s2(&self, x: Dd) -> Dd {
        Dd::div(x, self.two_s2)
    }

    /// `x_j − c_j` reduced to about `[−1/2, 1/2]`, in double-double.
    #[inline]
    fn reduced_offset(&self, x: f64, j: usize) -> Dd {
        // Exact: `frac(x)` would round for negative `x`.
        let d = Dd::diff(x, self.centre[j]);
        d.sub(Dd::new(crate::num::scalar::round(d.hi)))
    }

    /// 1D real-space image sum relative to the nearest image:
    /// `Σ_n e^{−((y+n)² − y²)/2σ²}` for `|y| ≲ 1/2`.
    fn images_1d(&self, y: Dd) -> f64 {
        let inv = 1.0 / self.two_s2.hi;
        let mut s = 1.0;
        let mut n = 1.0f64;
        loop {
            // (y + n)² − y² = n (2y + n), with 2y + n formed in double-double.
            let ep = n
                * Dd::new(n)
                    .add(Dd {
                        hi: 2.0 * y.hi,
                        lo: 2.0 * y.lo,
                    })
                    .to_f64()
                * inv;
            let em = n
                * Dd::new(n)
                    .sub(Dd {
                        hi: 2.0 * y.hi,
                        lo: 2.0 * y.lo,
                    })
                    .to_f64()
                * inv;
            if ep.min(em) > TAIL {
                break;
            }
            s += libm::exp(-ep) + libm::exp(-em);
            n += 1.0;
        }
        s
    }

    /// 1D theta series `Σ_k e^{−2π²σ²k²} cos(2πky)`.
    fn theta_1d(&self, y: Dd) -> f64 {
        let q = self.two_pi2_s2.to_f64();
        let mut s = 1.0;
        let mut k = 1.0f64;
        while q * k * k <= TAIL {
            let ph = frac_centered(y.mul(Dd::new(k)));
            s += 2.0 * libm::exp(-q * k * k) * libm::cos(TAU * ph);
            k += 1.0;
        }
        s
    }

    /// Fourier series of the periodised integral over the segment centred at
    /// `c + delta` (delta in double-double), direction `w`, length `len`:
    /// `Σ_k e^{−2π²σ²|k|²} cos(2πk·delta) λ sinc(λ k·ω)`.
    fn fourier_segment(&self, delta: &[Dd; D], w: &[f64; D], len: f64) -> f64 {
        if !len.is_finite() {
            return f64::INFINITY;
        }
        if len == 0.0 {
            return 0.0;
        }
        let q = self.two_pi2_s2.to_f64();
        let kmax2 = TAIL / q;
        let kmax = crate::num::scalar::floor(crate::num::scalar::sqrt(kmax2)) as i64;
        let mut sum = 0.0;
        let mut k = [0i64; D];
        // Odometer over [−kmax, kmax]^D, keeping k in the positive half space
        // (first non-zero component > 0) and doubling (terms of ±k are
        // complex conjugates).
        for j in 0..D {
            k[j] = -kmax;
        }
        loop {
            let mut first = 0i64;
            for j in 0..D {
                if k[j] != 0 {
                    first = k[j];
                    break;
                }
            }
            if first > 0 {
                let mut k2 = 0.0;
                for j in 0..D {
                    k2 += (k[j] * k[j]) as f64;
                }
                if k2 <= kmax2 {
                    let mut ph = Dd::new(0.0);
                    let mut kw = Dd::new(0.0);
                    for j in 0..D {
                        let kj = k[j] as f64;
                        ph = ph.add(delta[j].mul(Dd::new(kj)));
                        kw = kw.add(Dd::prod(kj, w[j]));
                    }
                    let ph = frac_centered(ph);
                    let sc = sinc_dd(kw.mul(Dd::new(len)));
                    sum += 2.0 * libm::exp(-q * k2) * libm::cos(TAU * ph) * sc;
                }
            }
            // Advance.
            let mut j = 0;
            loop {
                if j == D {
                    return len * (1.0 + sum);
                }
                if k[j] < kmax {
                    k[j] += 1;
                    break;
                }
                k[j] = -kmax;
                j += 1;
            }
        }
    }

    /// Whether an image at squared distance `d2` from the piece's box
    /// contributes less than a quarter ulp of the running sum `sum > 0` (its
    /// integral is at most `cap·e^{−d2/2σ²}`, with slack for the rounding of
    /// `d2` and of `exp`): adding it could not change `sum`, since
    /// `fl(s + x) = s` for `0 ≤ x < ulp(s)/2`, so skipping it is exact.
    #[inline]
    fn below_half_ulp(&self, d2: f64, cap: f64, sum: f64) -> bool {
        let ulp = f64::from_bits(sum.to_bits() + 1) - sum;
        self.image_bound(d2, cap) < 0.25 * ulp
    }

    /// An upper bound on the integral over a piece of an image at squared
    /// distance at least `d2` from it: `cap·e^{−d2/2σ²}` with slack for the
    /// rounding of `d2` and of `exp`.
    #[inline]
    /// The exponential is the lane one (`≤ 4u`, inside the `10⁻⁶` slack) with
    /// the exponent clamped at 700, which only raises the bound.
    fn image_bound(&self, d2: f64, cap: f64) -> f64 {
        let x = (d2 * (1.0 - 1e-9) / self.two_s2.hi).min(700.0);
        cap * exp_neg_lane::<f64>(x) * (1.0 + 1e-6)
    }

    /// `x_cut` such that an image with `key·(1 − 10⁻⁹)/2σ² > x_cut` has
    /// `n·image_bound(key) < 2⁻⁶⁰·sum` (by [`ln_upper`], an upper bound on
    /// the logarithm of `n·cap·(1 + 10⁻⁶)/(2⁻⁶⁰·sum)`).
    #[inline]
    fn log_cut(n: usize, cap: f64, sum: f64) -> f64 {
        ln_upper(n as f64 * cap * (1.0 + 1e-6) / (TWO_M60 * sum))
    }

    /// Periodised integral over the piece `c + q + tω`, `t ∈ [t0, t1]`, by
    /// real-space images; `q` (the piece origin minus the centre) is exact.
    fn piece_images(
        &self,
        q: &[Dd; D],
        w: &[f64; D],
        k: &crate::world::gaussian::LineConsts,
        t0: f64,
        t1: f64,
    ) -> f64 {
        if !(t1 - t0).is_finite() {
            return f64::INFINITY;
        }
        let mut lo = [0.0; D];
        let mut hi = [0.0; D];
        let mut dn2 = 0.0;
        for j in 0..D {
            let pj = self.centre[j] + q[j].to_f64();
            let xa = pj + t0 * w[j];
            let xb = pj + t1 * w[j];
            lo[j] = xa.min(xb) - 1e-12;
            hi[j] = xa.max(xb) + 1e-12;
            // Largest distance to the nearest image of c_j over [lo, hi].
            let ya = lo[j] - self.centre[j];
            let yb = hi[j] - self.centre[j];
            let dmax = if crate::num::scalar::floor(ya - 0.5) != crate::num::scalar::floor(yb - 0.5)
            {
                0.5
            } else {
                let da = (ya - crate::num::scalar::round(ya)).abs();
                let db = (yb - crate::num::scalar::round(yb)).abs();
                da.max(db)
            };
            dn2 += dmax * dmax;
        }
        // Images whose squared distance to the box exceeds R² can contribute at
        // most e^{−TAIL} relative to the nearest image, pointwise.
        let r2 = TAIL * self.two_s2.hi * (1.0 + 1e-9) + dn2;
        let r = crate::num::scalar::sqrt(r2);
        let mut mlo = [0i64; D];
        let mut mhi = [0i64; D];
        for j in 0..D {
            mlo[j] = crate::num::scalar::floor(lo[j] - self.centre[j] - r) as i64;
            mhi[j] = -crate::num::scalar::floor(-(hi[j] - self.centre[j] + r)) as i64;
        }
        let mut m = mlo;
        let mut sum = 0.0;
        // Any image's integral over the piece is at most its peak times
        // min(piece length, σ√(2π)/|ω|) times e^{−d²/2σ²}, d its distance to
        // the piece's box (|ω| = 1 up to 4u; the slack is in `image_bound`).
        let cap = self.norm * (t1 - t0).min(2.506_628_274_631_000_7 * self.sigma);
        let bx = ImageBox {
            lo,
            hi,
            r2,
            mlo,
            mhi,
            cap,
        };
        if let Some(v) = self.sorted_images(q, w, k, t0, t1, &bx) {
            return v;
        }
        loop {
            let mut d2 = 0.0;
            for j in 0..D {
                let cm = self.centre[j] + m[j] as f64;
                let d = (lo[j] - cm).max(cm - hi[j]).max(0.0);
                d2 += d * d;
            }
            if d2 <= r2 && !(sum > 0.0 && self.below_half_ulp(d2, cap, sum)) {
                sum += self.image_dd(q, &m.map(|x| x as f64), w, k, t0, t1);
            }
            let mut j = 0;
            loop {
                if j == D {
                    return sum;
                }
                if m[j] < mhi[j] {
                    m[j] += 1;
                    break;
                }
                m[j] = mlo[j];
                j += 1;
            }
        }
    }

    /// The image sum of [`Self::piece_images`] over the candidate images
    /// (those within `r` of the piece's box, offsets `mlo..=mhi`), nearest
    /// first, stopped when the rest provably cannot reach `2⁻⁶⁰` of the sum;
    /// `None` when there are more than `MAX_SORTED` candidates or `AXIS`
    /// offsets per axis (the caller then walks them in odometer order).
    ///
    /// Each candidate gets a lower bound `δ²` on its squared distance from
    /// the piece itself (not its box): the perpendicular part
    /// `ρ² = |y|² − (y·ω)²/a` (`y` the image's offset in `f64`) and the
    /// overshoot `τ` of the foot beyond `[t0, t1]`, each reduced by a margin
    /// far above their rounding (`10⁻¹²` relative plus `10⁻¹⁴(|y|² + |q|² + 1)`
    /// absolute for `ρ²`, `10⁻¹²(1 + |t_f| + |t0| + |t1|)` for `τ`). Along
    /// the piece the integrand is at most `e^{−(ρ² + aτ²)/2σ²}` times the
    /// 1D Gaussian beyond the foot, so the image's integral is at most
    /// `cap·e^{−δ²/2σ²}` (`cap = peak·min(length, σ√(2π))`, with the slack of
    /// [`Self::below_half_ulp`]). In order of `δ²` (a stable sort), once the
    /// sum is positive and `(remaining count)·cap·e^{−δ²_next/2σ²} <
    /// 2⁻⁶⁰·sum`, the remaining images are dropped: a relative truncation
    /// below `9e−19`, on top of the `e^{−45}` image cutoff. Summing nearest
    /// first is also the accurate order. Only a prefix of that order is
    /// sorted: the nearest candidate is evaluated first, and the candidates
    /// that rule would drop even against its value alone are never sorted.
    /// For an oblique piece this evaluates only the images near the line,
    /// where the box test keeps every image near the box. Once an image is
    /// bounded below `2⁻¹⁰` of the running sum, it and the rest are
    /// evaluated four at a time in `f64` SIMD lanes
    /// ([`crate::world::Gaussian::segment_fast`]'s kernel, with its relative
    /// error bound `R`; bit for bit the scalar kernel's values) and each
    /// value `v` is kept when `min(bound, 1.002|v|)·R < 2⁻⁶⁰·sum` (the exact
    /// value is at most `|v|/(1 − R)`, `R < 10⁻³`), else evaluated in
    /// double-double; the sum's total error from both shortcuts stays below
    /// `n·2⁻⁶⁰` of it.
    fn sorted_images(
        &self,
        q: &[Dd; D],
        w: &[f64; D],
        k: &crate::world::gaussian::LineConsts,
        t0: f64,
        t1: f64,
        bx: &ImageBox<D>,
    ) -> Option<f64> {
        let ImageBox {
            lo,
            hi,
            r2,
            mlo,
            mhi,
            ..
        } = bx;
        let r2 = *r2;
        // Per axis, the image offsets whose distance to the box alone is
        // within r (at most AXIS of them), with their squared distances.
        let mut axd = [[0.0f64; AXIS]; D];
        let mut axm = [[0i16; AXIS]; D];
        let mut axn = [0usize; D];
        for j in 0..D {
            if mhi[j] - mlo[j] >= AXIS as i64 || mlo[j] < -1000 || mhi[j] > 1000 {
                return None;
            }
            for mj in mlo[j]..=mhi[j] {
                let cm = self.centre[j] + mj as f64;
                let d = (lo[j] - cm).max(cm - hi[j]).max(0.0);
                if d * d <= r2 {
                    axd[j][axn[j]] = d * d;
                    axm[j][axn[j]] = mj as i16;
                    axn[j] += 1;
                }
            }
            if axn[j] == 0 {
                return Some(0.0);
            }
        }
        let mut cells = 1usize;
        for j in 0..D {
            cells *= axn[j];
        }
        if cells > 2 * MAX_SORTED {
            // More candidates than fit, almost surely (a ball fills about half
            // of its bounding box in 3D): the odometer order instead.
            return None;
        }
        let mut key = [0.0f64; MAX_SORTED];
        let mut img = [[0i16; D]; MAX_SORTED];
        let mut n = 0usize;
        let mut a = 0.0;
        for j in 0..D {
            a += w[j] * w[j];
        }
        // 1/a rounded (a = |ω|² ≈ 1): a relative error of u in ρ² and t_f,
        // far inside the margins below.
        let inv_a = 1.0 / a;
        let fin = |x: f64| if x.is_finite() { x.abs() } else { 0.0 };
        let slack = 1e-12 * (1.0 + fin(t0) + fin(t1));
        let mut qq = 0.0;
        for j in 0..D {
            qq += q[j].hi * q[j].hi;
        }
        // The walk over the cells in odometer order (axis 0 fastest), pruned
        // by the outer axes' partial distance: the sums are of non-negative
        // terms and rounding is monotone, so fl(fl(a0 + a1) + a2) ≥ fl(a1 + a2)
        // ≥ a2 and a pruned cell would also fail the full test.
        let (n2, n1) = if D == 3 {
            (axn[2], axn[1])
        } else {
            (1, axn[1])
        };
        for i2 in 0..n2 {
            let a2 = if D == 3 { axd[2][i2] } else { 0.0 };
            if a2 > r2 {
                continue;
            }
            for i1 in 0..n1 {
                let a12 = axd[1][i1] + a2;
                if a12 > r2 {
                    continue;
                }
                for i0 in 0..axn[0] {
                    // The same sum, in the same order, as the unpruned walk.
                    let d2 = if D == 3 {
                        (axd[0][i0] + axd[1][i1]) + a2
                    } else {
                        axd[0][i0] + axd[1][i1]
                    };
                    if d2 > r2 {
                        continue;
                    }
                    if n == MAX_SORTED {
                        return None;
                    }
                    let mut yy = 0.0;
                    let mut b = 0.0;
                    let mut m = [0i16; D];
                    for j in 0..D {
                        let ij = [i0, i1, i2][j];
                        m[j] = axm[j][ij];
                        let y = q[j].hi - f64::from(m[j]);
                        yy += y * y;
                        b += y * w[j];
                    }
                    // The margin covers the roundings (≤ 6u·|y|²) and the
                    // offset's error (|δy| ≤ 2u|q|, moving ρ² by
                    // ≤ 2ρ|δy| ≤ 2u(|y|² + |q|²)).
                    let rho2 = (yy - b * b * inv_a) * (1.0 - 1e-12) - 1e-14 * (yy + qq + 1.0);
                    let tf = -b * inv_a;
                    let tau = (t0 - tf).max(tf - t1) - (slack + 1e-12 * tf.abs());
                    let tau = tau.max(0.0);
                    let dist2 = rho2.max(0.0) + a * tau * tau * (1.0 - 1e-12);
                    key[n] = dist2;
                    img[n] = m;
                    n += 1;
                }
            }
        }
        if n == 0 {
            return Some(0.0);
        }
        // The nearest candidate (the first in walk order among equal keys,
        // where a stable sort would put it) is evaluated first, and its value
        // decides which others can matter: one whose key exceeds the cut
        // below has n·bound < 2⁻⁶⁰·sum₁ ≤ 2⁻⁶⁰·sum (the sum only grows), so
        // the nearest-first rule below would stop at or before it. Only the
        // candidates within the cut are sorted, which is the prefix of the
        // full stable sort: the same images in the same order as sorting all
        // of them, without the quadratic insertion over every candidate.
        let mut first = 0;
        for c in 1..n {
            if key[c] < key[first] {
                first = c;
            }
        }
        let inv2s2 = 1.0 / self.two_s2.hi;
        let sum1 = self.image_dd(q, &img[first].map(f64::from), w, k, t0, t1);
        // The cut in log space, raised by 10⁻⁹ so that a candidate beyond it
        // fails the exact test with the lane exponential's rounding too.
        let x_cut = if sum1 > 0.0 && sum1.is_finite() {
            Self::log_cut(n, bx.cap, sum1) + 1e-9
        } else {
            f64::INFINITY
        };
        let mut kept = 0;
        for c in 0..n {
            let (kc, mc) = (key[c], img[c]);
            if kc * (1.0 - 1e-9) * inv2s2 > x_cut {
                continue;
            }
            // Stable insertion into the sorted prefix (ties keep the walk
            // order; `core` has no allocation-free stable sort, and the
            // prefix holds a few images).
            let mut i = kept;
            while i > 0 && key[i - 1] > kc {
                key[i] = key[i - 1];
                img[i] = img[i - 1];
                i -= 1;
            }
            key[i] = kc;
            img[i] = mc;
            kept += 1;
        }
        let mut sum = sum1;
        let mut i = 1;
        // Near images, nearest first, in double-double.
        while i < kept {
            if sum > 0.0 {
                let bound = self.image_bound(key[i], bx.cap);
                if (n - i) as f64 * bound < TWO_M60 * sum {
                    return Some(sum);
                }
                if bound < FAR * sum {
                    break;
                }
            }
            sum += self.image_dd(q, &img[i].map(f64::from), w, k, t0, t1);
            i += 1;
        }
        if i == kept {
            return Some(sum);
        }
        // Far images: every remaining image is bounded below FAR·sum (keys
        // ascend, the sum only grows). Four at a time in f64 SIMD lanes (the
        // last group padded with the last image), in order: an image whose
        // bound times n is below 2⁻⁶⁰ of the sum so far ends the sum (so do
        // all after it: their bounds are smaller); one whose error, at most
        // bound·R, is below 2⁻⁶⁰ of the sum is kept, else it is evaluated in
        // double-double. Comparing with the sum before the far images (which
        // only grow it) cuts no earlier than the sequential rule.
        let sum0 = sum;
        let far = self.free.far_consts(w, k, t0, t1);
        // The groups stop at `end`, a first cut found in log space (no
        // exponential per image): n·cap·(1 + 10⁻⁶)·e^{−key(1−10⁻⁹)/2σ²} <
        // 2⁻⁶⁰·sum0 ⇐ key(1−10⁻⁹)/2σ² > x_stop for any x_stop ≥ the log of
        // n·cap·(1 + 10⁻⁶)/(2⁻⁶⁰·sum0), so `end` is never before the exact
        // rule's cut (the lanes apply the exact rule).
        let x_stop = Self::log_cut(n, bx.cap, sum0);
        let mut end = i;
        while end < kept && key[end] * (1.0 - 1e-9) * inv2s2 <= x_stop {
            end += 1;
        }
        while i < end {
            let idx: [usize; 4] = core::array::from_fn(|l| (i + l).min(end - 1));
            let mut y = [[0.0; D]; 4];
            let mut dy = [0.0f64; 4];
            for l in 0..4 {
                for j in 0..D {
                    y[l][j] = q[j].hi - f64::from(img[idx[l]][j]);
                    // |y − (q − m)| ≤ |q.lo| + u|y| ≤ u(|q.hi| + |y|).
                    dy[l] = dy[l].max(0.51 * f64::EPSILON * (q[j].hi.abs() + y[l][j].abs()));
                }
            }
            let (v, rel) = FreeGaussian::segment_far4(&far, &y, &dy);
            // The image bounds in the same lanes (the exponent clamped at 700,
            // which only raises a bound; the lane exponential's 4u error is
            // inside the 10⁻⁶ slack).
            let x = f64x4::from(core::array::from_fn::<f64, 4, _>(|l| {
                (key[idx[l]] * (1.0 - 1e-9) * inv2s2).min(700.0)
            }));
            let bound = (exp_neg_lane(x) * f64x4::splat(bx.cap * (1.0 + 1e-6))).to_array();
            for l in 0..4.min(end - i) {
                if n as f64 * bound[l] < TWO_M60 * sum0 {
                    return Some(sum);
                }
                // |exact| ≤ min(bound, |v|/(1 − R)) with R < 10⁻³ where
                // usable (R = ∞ otherwise, which never passes).
                if bound[l].min(1.002 * v[l].abs()) * rel[l] < TWO_M60 * sum0 {
                    sum += v[l];
                } else {
                    sum += self.image_dd(q, &img[idx[l]].map(f64::from), w, k, t0, t1);
                }
            }
            i += 4;
        }
        Some(sum)
    }

    /// The free-space integral over the piece of the image `c + m` (integer
    /// offsets `m`), in double-double ([`crate::world::Gaussian`]'s exact
    /// form).
    #[inline]
    fn image_dd(
        &self,
        q: &[Dd; D],
        m: &[f64; D],
        w: &[f64; D],
        k: &crate::world::gaussian::LineConsts,
        t0: f64,
        t1: f64,
    ) -> f64 {
        let mut qm = *q;
        for j in 0..D {
            qm[j] = q[j].sub(Dd::new(m[j]));
        }
        self.free.segment_with(&qm, w, k, t0, t1)
    }

    /// `(p + t_m ω) − c` in double-double, `t_m` the midpoint of `[t0, t1]`.
    fn mid_delta(&self, p: &[f64; D], w: &[f64; D], t0: f64, t1: f64) -> [Dd; D] {
        let s = Dd::new(t0).add(Dd::new(t1));
        let tm = Dd {
            hi: 0.5 * s.hi,
            lo: 0.5 * s.lo,
        };
        let mut d = [Dd::new(0.0); D];
        for j in 0..D {
            d[j] = Dd::diff(p[j], self.centre[j]).add(tm.mul(Dd::new(w[j])));
        }
        d
    }
}

/// An upper bound on `ln x` for `x > 0` from the binary exponent alone:
/// `x < 2^{e+1}` with `e = ⌊log₂ x⌋`, so `ln x < (e + 1)·ln 2` (over by at most
/// `ln 2`; `+∞` for `x = +∞` or NaN, and `(−1022)·ln 2` for subnormal `x`,
/// which is still an upper bound there).
#[inline]
fn ln_upper(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::INFINITY;
    }
    let e = ((x.to_bits() >> 52) & 0x7ff) as i64 - 1023;
    // (e + 1)·ln 2 rounded up by a relative 10⁻¹⁵ (it is never 0 for e ≠ −1).
    let v = (e + 1) as f64 * core::f64::consts::LN_2;
    v + 1e-15 * v.abs()
}

/// The images a piece may reach: its bounding box `[lo, hi]`, the squared
/// cutoff distance `r2` from it, the image offsets `mlo..=mhi` per axis, and
/// `cap` (see `Gaussian::image_bound`).
struct ImageBox<const D: usize> {
    lo: [f64; D],
    hi: [f64; D],
    r2: f64,
    mlo: [i64; D],
    mhi: [i64; D],
    cap: f64,
}

impl<const D: usize> Integrand<D> for Gaussian<D> {
    /// `(2πσ²)^{−D/2} e^{−|x−c|²/2σ²}` with the squared distance in
    /// double-double: relative error ≤ 4 ulp (to the normal range).
    fn value_free(&self, x: &[f64; D]) -> f64 {
        let mut d2 = Dd::new(0.0);
        for j in 0..D {
            let d = Dd::diff(x[j], self.centre[j]);
            d2 = d2.add(d.mul(d));
        }
        exp_neg_dd(self.over_two_s2(d2), self.norm)
    }

    /// `∫_{t0}^{t1} F(p + tω) dt`, any `t0 ≤ t1` (either may be infinite;
    /// `t0 > t1` gives the negated integral, NaN propagates).
    ///
    /// Evaluation (all with `q = p − c`, `a`, `b`, `t_c = −b/a` and
    /// `ρ² = |q × ω|²/a` in double-double, so the endpoint offsets `t − t_c` are
    /// exact to `2⁻¹⁰⁰`; hence there is **no** conditioning loss near tangency or
    /// where the ends clip the support):
    /// * straddling (`u0 < 0 < u1`): `G = (√π/2)(erf(u1) + erf(−u0))`, times
    ///   `e^{−ρ²/2σ²}`;
    /// * same sign, mirrored to `0 ≤ v0 < v1 ≤ ∞`, if `v1² − v0² ≥ 1`:
    ///   `G = (√π/2) e^{−v0²}[erfcx(v0) − e^{−(v1²−v0²)} erfcx(v1)]`
    ///   ([`crate::special::erfcx`]; cancellation ≤ 1.6×), and the exponentials
    ///   `e^{−ρ²/2σ²} e^{−v0²}` are merged into one
    ///   `e^{−|q + t_near ω|²/2σ²}` whose argument is a double-double;
    /// * same sign with `v1² − v0² < 1` (short, including `λ → 0`): around the
    ///   midpoint `m`, `G = e^{−m²}·∫_{−h}^{h} e^{−s²−2ms} ds`
    ///   ([`crate::special::gauss_mid`], a cancellation-free series), again
    ///   with one merged exponential; continuous as `λ → 0` (`≈ λ·F(midpoint)`).
    ///
    /// Error bound: relative error ≤ `1e−14` (≈ 45 ulp; measured ≤ 2e−15)
    /// for all inputs whose result is at least `2.2e−308`; the bound does not
    /// grow with the exponent (values of `1e−300` are as accurate as values of
    /// `1`). Below the normal range the result degrades gracefully into
    /// subnormals and 0.
    fn segment_free(&self, p: &[f64; D], dir: &Direction<D>, t0: f64, t1: f64) -> f64 {
        let q: [Dd; D] = core::array::from_fn(|j| Dd::diff(p[j], self.centre[j]));
        self.free.segment_signed(&q, &dir.get(), t0, t1)
    }

    /// `f32` twin of the batch: `∫_{t0}^{t1} F(o + t·d) dt` (the parameter is
    /// that of the given, not necessarily unit, `d`).
    ///
    /// `K/√a · e^{−ρ²/2σ²} · (erf(u1) − erf(u0))` with `ρ²` from the cross
    /// product, this crate's `f32` `exp` (`2^n`·polynomial) and `erf` (the
    /// Abramowitz–Stegun 7.1.25–28 form with coefficients fitted for this
    /// crate, absolute error ≤ 3e−7 in `f32`).
    ///
    /// Error bound against the exact integral (asserted in the tests): with
    /// the line's peak `P = (2πσ²)^{−D/2} e^{−ρ²/2σ²} σ√(2π)/|d|`,
    /// `E = ρ²/2σ²` and `κ = |d|(|q| + |t0| + |t1|)/σ` (finite ends only;
    /// `q = o − c`), `|err| ≤ P·(1e−6 + expm1(B))` with
    /// `B = 1e−6·E + 2e−7·κ·(1 + √(2E))`: `B` bounds the error of the `f32`
    /// exponent `−E`, which the factor `e^{−E}` turns into a relative error of
    /// at most `e^B − 1` (`≈ B` while `B` is small, the form this bound had
    /// before the `integrand_gaussian` fuzz target found a 2D ray with
    /// `σ = 3e−5` and `κ ≈ 4e9` whose exponent was off by 3.5, a factor 33 that
    /// the linear form did not cover). An absolute bound relative to the peak
    /// that grows only with the `f32` conditioning of the inputs (a tail
    /// segment whose exact value is far below `P·1e−6` may come out as 0). The `f32` exponential flushes to 0
    /// below `e^{−87}`: a ray whose factor `e^{−E}` is below that gives 0, an
    /// absolute error of up to `1.7e−38·P·e^{E}` (`P·e^{E}` the prefactor
    /// without the exponential: for narrow Gaussians up to `≈ 1e−26`; found
    /// by the `integrand_gaussian` fuzz target, a 2D ray with `σ = 3e−5` and
    /// `E ≈ 90` whose exact value is `8.7e−36`).
    ///
    /// Release behaviour: never panics; infinite `t0`/`t1` are supported;
    /// `t0 > t1` gives the negated integral; NaN inputs or `d = 0` give an
    /// unspecified value (NaN or finite).
    fn segment_free_f32(&self, o: [f32; D], d: [f32; D], t0: f32, t1: f32) -> f32 {
        self.free.segment_f32(o, d, t0, t1)
    }

    fn segment_free_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        self.free.segment_batch_f32(rays, out)
    }

    /// The periodised value, a product of 1D periodised Gaussians.
    /// `σ ≤ 0.3`: `(2πσ²)^{−D/2} e^{−Σ y_j²/2σ²} Π_j Σ_n e^{−n(2y_j+n)/2σ²}`
    /// with `y_j = x_j − c_j` reduced to `[−1/2, 1/2]` and the leading exponent
    /// in double-double (terms below `e^{−45}` of the nearest image dropped):
    /// relative error ≤ 1e−14 for every value in the normal range. `σ > 0.3`:
    /// `Π_j Σ_k e^{−2π²σ²k²} cos(2πk y_j)` (values ≥ 0.31, relative error
    /// ≤ 1e−15).
    fn value(&self, x: &[f64; D]) -> f64 {
        let mut y = [Dd::new(0.0); D];
        for j in 0..D {
            if !x[j].is_finite() {
                return f64::NAN;
            }
            y[j] = self.reduced_offset(x[j], j);
        }
        if self.sigma > SIGMA_SWITCH {
            let mut v = 1.0;
            for j in 0..D {
                v *= self.theta_1d(y[j]);
            }
            return v;
        }
        let mut e = Dd::new(0.0);
        let mut prod = 1.0;
        for j in 0..D {
            e = e.add(y[j].mul(y[j]));
            prod *= self.images_1d(y[j]);
        }
        exp_neg_dd(self.over_two_s2(e), self.norm * prod)
    }

    /// Exactly 1 (the density is normalised).
    fn integral(&self) -> f64 {
        1.0
    }

    /// `σ ≤ 0.3`: the sum of [`Integrand::segment_free`] over the images `c + m`
    /// whose squared distance to the piece's bounding box is within
    /// `90σ² + Σ_j (max nearest-image distance)²`: every dropped image is below
    /// `e^{−45}` of the nearest image at each point of the piece, so the
    /// relative error is that of `segment_free` plus `≤ 1e−18`. `σ > 0.3`: the
    /// Fourier series of the segment (see [`Integrand::segment_integral`]).
    /// An infinite piece returns `+∞`.
    fn piece_integral(&self, p: &[f64; D], dir: &Direction<D>, t0: f64, t1: f64) -> f64 {
        if t0.is_nan() || t1.is_nan() {
            return f64::NAN;
        }
        if t0 >= t1 {
            return if t0 == t1 {
                0.0
            } else {
                -self.piece_integral(p, dir, t1, t0)
            };
        }
        let w = dir.get();
        if self.sigma > SIGMA_SWITCH {
            if !(t1 - t0).is_finite() {
                return f64::INFINITY;
            }
            let delta = self.mid_delta(p, &w, t0, t1);
            return self.fourier_segment(&delta, &w, t1 - t0);
        }
        let mut q = [Dd::new(0.0); D];
        for j in 0..D {
            q[j] = Dd::diff(p[j], self.centre[j]);
        }
        self.piece_images(&q, &w, &self.free.line_consts(&w), t0, t1)
    }

    /// The periodised value at the centre (`max f`).
    fn max_value(&self) -> f64 {
        self.max
    }

    /// `e^{−2π²σ²|k|²} e^{−2πik·c}`: the exponent is a double-double (so the
    /// modulus has a relative error ≤ 2 ulp even where it is `1e−300`) and the
    /// phase `k·c mod 1` is reduced exactly (`k_j c_j` by `two_prod`), so the
    /// coefficient is accurate to ≤ 4 ulp of its modulus at any frequency.
    fn fourier(&self, k: &[i32; D]) -> Complex {
        let mut k2 = Dd::new(0.0);
        for j in 0..D {
            let kj = f64::from(k[j]);
            k2 = k2.add(Dd::prod(kj, kj));
        }
        let modulus = exp_neg_dd(self.two_pi2_s2.mul(k2), 1.0);
        if modulus == 0.0 {
            return Complex { re: 0.0, im: 0.0 };
        }
        // e^{−2πik·c} with k·c reduced modulo 1 exactly (crate::num::phase).
        cis_turns(dot_turns(k, &self.centre)).scale(modulus)
    }

    /// The wrapped segment integral. `σ > 0.3`: the Fourier series
    /// `λ Σ_k e^{−2π²σ²|k|²} cos(2πk·(c_s − c)) sinc(λ k·ω)` over
    /// `2π²σ²|k|² ≤ 45` (phases and `λ k·ω` in double-double), whose cost does
    /// not depend on `λ`; relative error ≤ 1e−14. `σ ≤ 0.3`: the sum of
    /// [`Integrand::piece_integral`] over the cells crossed (as the provided
    /// method).
    fn segment_integral(&self, seg: &Segment<D>) -> f64 {
        let len = seg.length();
        if len == 0.0 {
            return 0.0;
        }
        let c0 = seg.centre();
        let mut c = [0.0; D];
        for j in 0..D {
            c[j] = frac(c0[j]);
        }
        let dir = seg.dir();
        // `c_s − c` exactly (`frac` rounds negative coordinates, so the reduced
        // centre is only used to walk the cells).
        let mut cq = [Dd::new(0.0); D];
        for j in 0..D {
            cq[j] = Dd::diff(c0[j], self.centre[j]).sub(Dd::new(crate::num::scalar::floor(c0[j])));
        }
        if self.sigma > SIGMA_SWITCH {
            return self.fourier_segment(&cq, &dir.get(), len);
        }
        // As the provided method, but with each piece's origin `c − m` (which
        // `for_each_piece` rounds) rebuilt exactly as a double-double.
        let w = dir.get();
        // The direction's constants once per segment, not once per piece.
        let k = self.free.line_consts(&w);
        let half = 0.5 * len;
        let mut sum = 0.0;
        for_each_piece(&c, &dir, -half, half, |p, a, b| {
            let mut q = cq;
            for j in 0..D {
                q[j] = cq[j].sub(Dd::new(crate::num::scalar::round(c[j] - p[j])));
            }
            if a < b {
                sum += self.piece_images(&q, &w, &k, a, b);
            }
        });
        sum
    }

    /// The integral over the chord of the unit box: for `σ > 0.3` the chord is
    /// a segment of the periodised function and the Fourier series is used;
    /// otherwise the real-space image sum over the chord (one piece, with the
    /// offset `p − c` exact).
    fn line_integral(&self, line: &Line<D>) -> f64 {
        let dir = line.dir();
        let p = line.point();
        let Some((t0, t1)) = clip_to_unit_box(&p, &dir) else {
            return 0.0;
        };
        let w = dir.get();
        if self.sigma > SIGMA_SWITCH {
            let delta = self.mid_delta(&p, &w, t0, t1);
            return self.fourier_segment(&delta, &w, t1 - t0);
        }
        // One piece, with the exact offset p − c (no re-basing needed: the
        // closed form works with t − t_c in double-double).
        let mut q = [Dd::new(0.0); D];
        for j in 0..D {
            q[j] = Dd::diff(p[j], self.centre[j]);
        }
        self.piece_images(&q, &w, &self.free.line_consts(&w), t0, t1)
    }
}

#[cfg(test)]
mod tests {
    use super::ln_upper;

    /// `ln_upper` is an upper bound on `ln x` within `ln 2` of it, for
    /// normal, subnormal, tiny and huge `x` (it decides where the far-image
    /// groups may stop, so an underestimate would drop images).
    #[test]
    fn ln_upper_bounds_ln() {
        let mut x = 5e-324f64;
        while x.is_finite() {
            for f in [1.0, 1.000_000_1, 1.5, 1.999_999_9] {
                let y = x * f;
                if y.is_finite() && y > 0.0 {
                    let (u, l) = (ln_upper(y), libm::log(y));
                    assert!(u >= l, "{y:e}: {u} < {l}");
                    if y >= f64::MIN_POSITIVE {
                        assert!(u <= l + core::f64::consts::LN_2 + 1e-12, "{y:e}: {u} {l}");
                    }
                }
            }
            x *= 2.0;
        }
        assert_eq!(ln_upper(f64::INFINITY), f64::INFINITY);
    }
}
