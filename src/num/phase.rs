//! Exact phase reduction, `e^{−2πiθ}` and `sinc`.
//!
//! A phase `θ = ν·x` is needed modulo 1 only, but for `|θ| ≫ 1` a rounded `θ`
//! has already lost its fractional bits. Every phase in the crate is therefore
//! formed as a double-double (the product `ν·x` of two doubles is exact as a
//! [`Dd`], [`crate::num::two_prod`]), reduced modulo 1 **exactly** by
//! [`frac_centered`] (the integer part is removed from `hi`, where the
//! subtraction is exact, before `lo` is added), and only then turned into an
//! angle. The error of `e^{−2πiθ}` is then a few ulp of 1 whatever `|θ|` is
//! (tested at `|ν| ≤ 10⁶` against exact integer arithmetic on the mantissa).

use super::complex::Complex;
use super::dd::Dd;
use core::f64::consts::{PI, TAU};

/// `x − round(x)` for a double-double `x`, as a double in `[−1/2, 1/2]`.
///
/// `r = hi − round(hi)` is exact (Sterbenz: both are within a factor 2 or `r`
/// is exactly representable), `s = r + lo` rounds once, and a final
/// `s − round(s)` is exact. So the result is the exact fractional phase
/// rounded once: absolute error ≤ `2⁻⁵⁴` (half an ulp of `1/2`). NaN for
/// non-finite `x`.
#[inline]
#[must_use]
pub fn frac_centered(x: Dd) -> f64 {
    if !x.hi.is_finite() {
        return f64::NAN;
    }
    let r = x.hi - crate::num::scalar::round(x.hi); // exact
    let s = r + x.lo;
    s - crate::num::scalar::round(s)
}

/// `(cos 2πt, sin 2πt)` for `t ∈ [−1/2, 1/2]`: exact at multiples of `1/4`
/// (the quadrant `q = round(4t)` is removed exactly, so `libm::sin`/`cos` only
/// see an argument in `[−π/4, π/4]`); absolute error ≤ 1.5 ulp of 1 elsewhere.
#[inline]
#[must_use]
pub fn cos_sin_turns(t: f64) -> (f64, f64) {
    let u = 4.0 * t; // exact
    let q = crate::num::scalar::round(u);
    let w = u - q; // exact, |w| ≤ 1/2
    let th = w * (TAU / 4.0);
    let (s, c) = (libm::sin(th), libm::cos(th));
    match (q as i64).rem_euclid(4) {
        0 => (c, s),
        1 => (-s, c),
        2 => (-c, -s),
        _ => (s, -c),
    }
}

/// `e^{−2πiθ}` for a double-double phase `θ`, reduced modulo 1 exactly first
/// ([`frac_centered`], then [`cos_sin_turns`]): absolute error ≤ 2 ulp of 1 in
/// each component for every finite `θ`; NaN components for non-finite `θ`.
#[inline]
#[must_use]
pub fn cis_turns(theta: Dd) -> Complex {
    let (c, s) = cos_sin_turns(frac_centered(theta));
    Complex { re: c, im: -s }
}

/// The phase `θ = Σ_j k_j·x_j` of `e^{−2πik·x}` modulo 1, as a double-double
/// in about `[−D/2, D/2]`: each product `k_j x_j` is formed exactly
/// ([`crate::num::two_prod`]), its integer part removed from the leading term
/// (exact), and the pieces summed in double-double, so no fractional bit is
/// lost however large `|k|` or `|x|` are. Pass it to [`cis_turns`].
#[inline]
#[must_use]
pub fn dot_turns<const D: usize>(k: &[i32; D], x: &[f64; D]) -> Dd {
    let mut acc = Dd::ZERO;
    for j in 0..D {
        let (p, e) = super::dd::two_prod(f64::from(k[j]), x[j]);
        acc = acc
            .add(Dd::new(p - crate::num::scalar::round(p)))
            .add(Dd::new(e));
    }
    acc
}

/// `sinc(t) = sin(πt)/(πt)` (1 at 0) for a double `t`: absolute error ≤ 2 ulp
/// of 1 for any `|t|` ([`sinc_dd`] of the exact `t`).
#[inline]
#[must_use]
pub fn sinc(t: f64) -> f64 {
    sinc_dd(Dd::new(t))
}

/// `sin(πx)/(πx)` for a double-double `x`: absolute error ≤ 2 ulp of 1 even for
/// `|x| ~ 10⁷`, since the period 2 is removed from `x` exactly
/// (`x − 2·round(x/2)` via [`frac_centered`] of `x/2`, a power-of-two scaling).
/// For `|x| < 10⁻⁸` the two-term Taylor series `1 − (πx)²/6` (next term below
/// `2⁻⁵⁸`); 0 for infinite `x`.
#[must_use]
pub fn sinc_dd(x: Dd) -> f64 {
    let xf = x.to_f64();
    let ax = xf.abs();
    if ax < 1.0 {
        if ax < 1e-8 {
            let px = PI * xf;
            return 1.0 - px * px / 6.0;
        }
        let px = PI * xf;
        return libm::sin(px) / px;
    }
    if !xf.is_finite() {
        return 0.0;
    }
    let r = 2.0 * frac_centered(x.scale(0.5));
    libm::sin(PI * r) / (PI * xf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarters_are_exact() {
        let (c, s) = cos_sin_turns(0.5);
        assert_eq!((c, s.abs()), (-1.0, 0.0));
        assert_eq!(cos_sin_turns(-0.25), (0.0, -1.0));
        assert_eq!(cos_sin_turns(0.0), (1.0, 0.0));
        assert_eq!(cis_turns(Dd::new(1e300)), Complex::new(1.0, -0.0));
        assert!(cis_turns(Dd::new(f64::NAN)).re.is_nan());
    }

    #[test]
    fn sinc_zeros_and_values() {
        assert!(sinc_dd(Dd::new(3.0)).abs() < 1e-16);
        assert!((sinc(0.5) - 2.0 / PI).abs() < 1e-16);
        assert_eq!(sinc(0.0), 1.0);
        assert_eq!(sinc(f64::INFINITY), 0.0);
    }
}
