//! Special functions behind the closed forms, written for relative accuracy in
//! the far tails where the textbook formulas cancel or underflow.
//!
//! * [`erfcx`]: the scaled complementary error function `e^{x²}·erfc(x)`.
//! * [`gauss_mid`]: `∫_{−h}^{h} e^{−s²−2ms} ds` for short intervals, by a
//!   power series without cancellation.
//! * [`exp_neg_dd`]: `m·e^{−E}` for a double-double exponent `E`, accurate to a
//!   few ulp relative for every `E` (no loss when `E` is large, no premature
//!   underflow when `m` is large).
//!
//! Double-double arithmetic comes from [`crate::num::dd`].

use crate::num::lane::F64Lane;
use crate::num::{two_prod, Dd};

/// `1/√π`.
pub const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// `ln 2` as a double-double (`hi + lo`, Cody–Waite style split).
const LN2_HI: f64 = core::f64::consts::LN_2;
const LN2_LO: f64 = 2.319_046_813_846_299_6e-17;

/// `p` of the variable `t = 1/(1 + p·x)` of [`erfcx`] (exact in binary).
const ERFCX_P: f64 = 0.3125;

/// Coefficients (highest degree first) of the polynomial `P(s)`, `s = 2t − 1 ∈
/// [−1, 1]`, with `erfcx(x) = t·P(s)` for `x ≥ 0`: the degree-24 Chebyshev
/// least-squares fit of `erfcx(x(s))/t` computed for this crate with `mpmath`
/// at 50 digits (fit error `1.6e−18`; `Σ|c_k| = 1.0015`, so Horner's rule in
/// `s ∈ [−1, 1]` adds at most a few rounding errors).
#[rustfmt::skip]
const ERFCX_POLY: [f64; 25] = [
    -8.82379138295569e-11,
    -1.1981683851444789e-11,
    9.806313204314074e-10,
    -1.9664603872462902e-10,
    -6.170640973851849e-09,
    4.041778918241563e-09,
    3.149303644887779e-08,
    -3.773607877170247e-08,
    -1.573527134372838e-07,
    2.68552553651505e-07,
    8.79314016992216e-07,
    -1.6762261941519442e-06,
    -5.984024057941453e-06,
    8.805556772772885e-06,
    4.916243232390958e-05,
    -1.4775595603935782e-05,
    -0.0004234784084160173,
    -0.0007259921410823165,
    0.002146685323332872,
    0.015681802824258958,
    0.05042053773555177,
    0.11330552413365653,
    0.19851075757074127,
    0.2835914543692291,
    0.3374561936237686,
];

/// `erfcx(x)` for `x ≥ 0` (any lane type; `+∞ ↦ 0`), the polynomial form of
/// [`erfcx`]: `t = 1/(1 + px)`, `s = 2t − 1` for `t < 1/2`, else
/// `s = 1 − 2px·t` (so that a small `x` is not lost in `1 + px`), and
/// `t·P(s)` by four interleaved Horner chains in `s⁴` (a multiply and an add
/// per step, never fused, so the bits are the same in every build and no
/// build pays for a software `fma`); for `x ≥ 12` the asymptotic series
/// instead (computed only when a lane needs it, then selected lane by lane).
/// Relative error ≤ 8e−16 (measured 5.0e−16 against 40-digit `mpmath` values
/// at 24,000 log-spaced points in `10⁻⁹ ≤ x ≤ 10⁶`, worst at `x ≈ 3.96`; the
/// tests check it against an independent quadrature).
#[inline(always)]
pub(crate) fn erfcx_lane<L: F64Lane>(x: L) -> L {
    let px = L::splat(ERFCX_P) * x;
    let t = L::splat(1.0) / (L::splat(1.0) + px);
    let s_far = L::splat(2.0) * t - L::splat(1.0);
    let s_near = L::splat(1.0) - L::splat(2.0) * (px * t);
    let s = t.lt_select(L::splat(0.5), s_far, s_near);
    // P(s) = Σ c_k s^k as four interleaved chains in s⁴ (k ≡ 0, 1, 2, 3
    // mod 4), each by Horner's rule: a quarter of the latency of one
    // 25-step chain.
    let s2 = s * s;
    let s4 = s2 * s2;
    let chain = |r: usize| {
        // Coefficients of degree 24 − k with k ≡ r (mod 4), highest first.
        let mut acc = L::splat(0.0);
        let mut k = r;
        while k <= 24 {
            acc = acc * s4 + L::splat(ERFCX_POLY[k]);
            k += 4;
        }
        acc
    };
    // ERFCX_POLY[k] is the coefficient of s^{24−k}: chain r holds the degrees
    // 24 − r − 4i, i.e. ≡ (24 − r) mod 4.
    let c0 = chain(0); // degrees 24, 20, …, 0
    let c3 = chain(3); // degrees 21, 17, …, 1
    let c2 = chain(2); // degrees 22, 18, …, 2
    let c1 = chain(1); // degrees 23, 19, …, 3
    let even = c2 * s2 + c0;
    let odd = c1 * s2 + c3;
    let poly = t * (odd * s + even);
    let big = L::splat(12.0).le(x);
    if !L::any(big) {
        return poly;
    }
    // x ≥ 12: the asymptotic series (A&S 7.1.23)
    // erfcx(x) = (1/(x√π))·Σ_k (−1)^k (2k−1)!!/(2x²)^k through k = 12
    // (truncation < 10⁻¹⁸ at x = 12), where the polynomial at s ≈ −1
    // cancels by a factor 5.7 (its error there reaches 8.5e−16).
    let r = L::splat(1.0) / (L::splat(2.0) * x * x);
    let mut a = L::splat(ASYMPTOTIC[0]);
    for &c in &ASYMPTOTIC[1..] {
        a = a * r + L::splat(c);
    }
    let asym = (L::splat(FRAC_1_SQRT_PI) / x) * (a * r + L::splat(1.0));
    L::select(big, asym, poly)
}

/// `(−1)^k (2k − 1)!!` for `k = 12, 11, …, 1` (exact in `f64`).
const ASYMPTOTIC: [f64; 12] = [
    316_234_143_225.0,
    -13_749_310_575.0,
    654_729_075.0,
    -34_459_425.0,
    2_027_025.0,
    -135_135.0,
    10_395.0,
    -945.0,
    105.0,
    -15.0,
    3.0,
    -1.0,
];

/// `e^{−x}` for `0 ≤ x ≤ 708` (any lane type): `2^{−n}·e^{r}` with
/// `n = ⌊x·log₂e + ½⌋`, `r = n·ln2 − x` (Cody–Waite: `n·LN2_HI` is exact, so
/// `|r| ≤ 0.347` carries an absolute error below `2u`), `e^r` by its
/// degree-13 Taylor polynomial (truncation `< 4·10⁻¹⁸`), as even and odd
/// Horner chains in `r²` (unfused, so the bits are the same in every build).
/// Relative error
/// ≤ `4u` (`u = 2⁻⁵³`) for results in the normal range (tested against
/// `libm::exp`); the caller keeps `x` in range.
#[inline(always)]
pub(crate) fn exp_neg_lane<L: F64Lane>(x: L) -> L {
    // ln 2 split so that n·LN2_HI is exact for |n| < 2²¹ (fdlibm's split).
    const LN2_HI: f64 = 6.931_471_803_691_238_2e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
    let n = (x * L::splat(core::f64::consts::LOG2_E) + L::splat(0.5)).floor();
    let r = (n * L::splat(LN2_HI) - x) + n * L::splat(LN2_LO);
    // Σ_{k≤13} r^k/k! as even and odd chains in r².
    let r2 = r * r;
    let mut ev = L::splat(INV_FACT[12]);
    let mut od = L::splat(INV_FACT[13]);
    for k in (0..6).rev() {
        ev = ev * r2 + L::splat(INV_FACT[2 * k]);
        od = od * r2 + L::splat(INV_FACT[2 * k + 1]);
    }
    (od * r + ev) * L::pow2i(-n)
}

/// `1/k!` for `k ≤ 13`, each the correctly rounded quotient of `1` by the
/// exact `k!` (computed at compile time).
const INV_FACT: [f64; 14] = {
    let mut out = [1.0; 14];
    let mut fact = 1.0;
    let mut k = 1;
    while k < 14 {
        fact *= k as f64;
        out[k] = 1.0 / fact;
        k += 1;
    }
    out
};

/// The scaled complementary error function `erfcx(x) = e^{x²}·erfc(x)`.
///
/// * `0 ≤ x < 12`: `t·P(s)` with `t = 1/(1 + x/3.2)` and a degree-24
///   polynomial `P` in `s = 2t − 1` fitted for this crate (see `erfcx_lane`):
///   one division and 25 multiply-adds, no exponential, and the same form in
///   the `f64` SIMD lanes. `erfcx(x)/t` is smooth on `t ∈ [0, 1]` (it tends to
///   `p/√π` as `x → ∞`, the leading term of the asymptotic series
///   `1/(x√π)`, A&S 7.1.23), which is why one polynomial covers the range.
/// * `x ≥ 12`: the asymptotic series `(1/(x√π))·Σ_{k≤12} (−1)^k
///   (2k−1)!!/(2x²)^k` (truncation `< 10⁻¹⁸`), where the polynomial's
///   alternating sum near `s = −1` would cancel.
/// * `x < 0`: `2e^{x²} − erfcx(−x)` (no cancellation: `erfcx(−x) ≤ 1 ≤ e^{x²}`);
///   overflows to `+∞` for `x < −26.6`.
///
/// Relative error ≤ 8e−16 (≈ 4 ulp) for `x ≥ 0` (measured 5.0e−16 against
/// 40-digit `mpmath` values; the tests check it against an independent quadrature of
/// `(2/√π)∫_0^∞ e^{−t²−2xt} dt` and tabulated `mpmath` values).
#[must_use]
pub fn erfcx(x: f64) -> f64 {
    if x.is_nan() {
        return x;
    }
    if x < 0.0 {
        if x < -26.7 {
            return f64::INFINITY;
        }
        let (h, l) = two_prod(x, x);
        return 2.0 * libm::exp(h) * (1.0 + l) - erfcx(-x);
    }
    erfcx_lane::<f64>(x)
}

/// `∫_{−h}^{h} e^{−s² − 2ms} ds` for `h ≥ 0` with `|m|·h ≤ 1/4` and `h ≤ 1/2`
/// (the caller guarantees this; it is the short-interval case of
/// `∫ e^{−u²} du = e^{−m²}·gauss_mid(m, h)` around the midpoint `m`).
///
/// Power series of the integrand: `e^{−s²−2ms} = Σ c_k s^k` with
/// `c_0 = 1`, `c_1 = −2m`, `(k+1)c_{k+1} = −2m c_k − 2c_{k−1}` (from
/// `f' = (−2m − 2s)f`), integrated term by term (odd terms vanish), with the
/// scaled coefficients `d_k = c_k h^k` so that neither overflows:
/// `2h·Σ_{k even} d_k/(k+1)`. Under the stated bounds `|d_k| ≤ (3/4)^k/⌊k/2⌋!`,
/// the partial sums never cancel by more than a factor 1.3, and the result has
/// a relative error of a few ulp. Continuous in `h → 0` (`≈ 2h`).
#[must_use]
pub fn gauss_mid(m: f64, h: f64) -> f64 {
    let mh2 = -2.0 * m * h;
    let h2 = -2.0 * h * h;
    let mut dkm1 = 1.0; // d_0
    let mut dk = mh2; // d_1
    let mut sum = 1.0;
    let mut k = 1usize;
    while k < 80 {
        let dn = (mh2 * dk + h2 * dkm1) / (k as f64 + 1.0); // d_{k+1}
        k += 1;
        if k.is_multiple_of(2) {
            sum += dn / (k as f64 + 1.0);
        }
        dkm1 = dk;
        dk = dn;
        if dk.abs() + dkm1.abs() <= 1e-18 * sum.abs() {
            break;
        }
    }
    2.0 * h * sum
}

/// `mult · e^{−E}` for a double-double `E = e.hi + e.lo ≥ 0` (or any `E`; the
/// result overflows to `∞` for very negative `E`).
///
/// `e^{−E} = e^{−hi}·(1 − lo)` (`|lo| ≤ ulp(hi)/2`, so the neglected `lo²/2` is
/// below `2⁻¹⁰⁰`): the relative error is that of libm `exp` (< 1 ulp) plus one
/// rounding, independent of the size of `E`. For `E > 600` the exponent is
/// first reduced by `n·ln 2` (in double-double) and the product rescaled by
/// `2^{−n}` at the end, so a large `mult` does not let an intermediate
/// `e^{−E}` underflow: the result keeps full relative accuracy down to the
/// normal range (`≈ 2.2e−308`) and degrades gracefully into subnormals.
#[must_use]
pub fn exp_neg_dd(e: Dd, mult: f64) -> f64 {
    if e.hi.is_nan() || mult.is_nan() {
        return f64::NAN;
    }
    if e.hi == f64::INFINITY {
        return 0.0;
    }
    if e.hi <= 600.0 {
        return mult * (libm::exp(-e.hi) * (1.0 - e.lo));
    }
    // E' = E − n·ln2 ≈ 500.
    let n = crate::num::scalar::floor((e.hi - 500.0) * core::f64::consts::LOG2_E);
    if n > 4000.0 {
        return 0.0;
    }
    let nl = Dd::prod(n, LN2_HI).add(Dd::prod(n, LN2_LO));
    let r = e.sub(nl);
    let v = mult * (libm::exp(-r.hi) * (1.0 - r.lo));
    libm::scalbn(v, -(n as i32))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erfcx_basics() {
        assert_eq!(erfcx(0.0), 1.0);
        assert_eq!(erfcx(f64::INFINITY), 0.0);
        assert!(erfcx(f64::NAN).is_nan());
        // Asymptotics: erfcx(x) ≈ 1/(x√π)·(1 − 1/(2x²) + 3/(4x⁴)).
        for x in [1e3, 1e4, 1e7] {
            let x2 = x * x;
            let a =
                FRAC_1_SQRT_PI / x * (1.0 - 0.5 / x2 + 0.75 / (x2 * x2) - 1.875 / (x2 * x2 * x2));
            assert!(((erfcx(x) - a) / a).abs() < 4e-16, "{x}");
        }
        // Continuity at the switches: s = 2t − 1 from either form at
        // t = 1/2 (x = 3.2), and the asymptotic series from x = 12.
        for s in [3.2, 12.0] {
            let lo = erfcx(s * (1.0 - 1e-15));
            let hi = erfcx(s);
            assert!(((lo - hi) / hi).abs() < 1e-14, "{s}: {lo} {hi}");
        }
    }

    /// The lane exponential against `libm::exp` (≤ 1 ulp): within `4u + 1`
    /// ulp over `[0, 708]`, and `f64x4` lanes equal the scalar bit for bit
    /// (also for `erfcx_lane`).
    #[test]
    fn lane_exp_and_erfcx() {
        use wide::f64x4;
        let mut worst = 0.0f64;
        for i in 0..40_000 {
            let x = 708.0 * (i as f64 / 40_000.0).powi(3) + 1e-3 * (i % 7) as f64;
            let e = exp_neg_lane::<f64>(x);
            let r = libm::exp(-x);
            worst = worst.max(((e - r) / r).abs());
            let xs = [x, 0.5 * x, x / 3.0, 1e-9 * x];
            let v = exp_neg_lane(f64x4::from(xs)).to_array();
            let c = erfcx_lane(f64x4::from(xs)).to_array();
            for l in 0..4 {
                assert_eq!(v[l].to_bits(), exp_neg_lane::<f64>(xs[l]).to_bits());
                assert_eq!(c[l].to_bits(), erfcx_lane::<f64>(xs[l]).to_bits());
            }
        }
        assert!(worst <= 5.0 * f64::EPSILON / 2.0, "{worst:e}");
        assert_eq!(exp_neg_lane::<f64>(0.0), 1.0);
    }

    #[test]
    fn gauss_mid_small() {
        assert_eq!(gauss_mid(0.3, 0.0), 0.0);
        let h = 1e-9;
        assert!((gauss_mid(0.1, h) / (2.0 * h) - 1.0).abs() < 1e-15);
        // m = 0: ∫_{-h}^{h} e^{-s²} = √π erf(h).
        let h = 0.45;
        let v = gauss_mid(0.0, h);
        let r = libm::erf(h) / FRAC_1_SQRT_PI;
        assert!(((v - r) / r).abs() < 1e-15, "{v} {r}");
    }

    #[test]
    fn exp_neg_dd_large() {
        // e^{-700} · e^{300} = e^{-400}.
        let v = exp_neg_dd(Dd::new(700.0), libm::exp(300.0));
        let r = libm::exp(-400.0);
        assert!(((v - r) / r).abs() < 1e-14, "{v} {r}");
        assert_eq!(exp_neg_dd(Dd::new(f64::INFINITY), 1.0), 0.0);
    }
}
