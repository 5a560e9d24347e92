//! Wrapping onto the unit torus `[0, 1)` (one period per axis), in `f64`, and
//! rounding a wrapped value to an `f32` coordinate that is never `1.0`.
//!
//! | function | input | output |
//! |---|---|---|
//! | [`frac`] | any finite `x` | `x mod 1 ∈ [0, 1)` |
//! | [`to_unit_f32`] | any finite `y` | `y mod 1` rounded to `f32`, in `[0, 1)` |
//! | [`torus_delta`] | a difference `d ∈ (−1, 1)` | the representative in `[−1/2, 1/2)` |
//! | [`torus_dist`] | `a, b ∈ [0, 1)` | `min(|a − b|, 1 − |a − b|)`, exactly |

/// The largest `f32` below 1: every `f32` coordinate in the crate is at most
/// this (`1 − 2⁻²⁴`).
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// `x mod 1 = x − ⌊x⌋ ∈ [0, 1)`.
///
/// Exact for `x ≥ 0` (the fractional part of a non-negative double is a
/// double). For negative non-integral `x` the subtraction rounds (error
/// ≤ `2⁻⁵⁴`), and a result that would round to `1` (e.g. `x = −1e−20`) is
/// returned as `0`. The common ranges `[−1, 2)` take a branch instead of
/// `floor` (the same value: `x + 1` and `x − 1` are the subtractions `floor`
/// would lead to). Closed forms that need the exact offset form `x − c`
/// themselves. NaN and infinities give NaN.
#[inline(always)]
#[must_use]
pub fn frac(x: f64) -> f64 {
    let f = if (0.0..1.0).contains(&x) {
        x + 0.0 // −0 becomes +0, as `x − ⌊x⌋` gives
    } else if (-1.0..0.0).contains(&x) {
        x + 1.0
    } else if (1.0..2.0).contains(&x) {
        x - 1.0
    } else {
        x - crate::num::scalar::floor(x)
    };
    if f >= 1.0 {
        0.0
    } else {
        f
    }
}

/// `y mod 1` ([`frac`]) rounded to the nearest `f32` and clamped to
/// [`ONE_MINUS_EPSILON`], so that a value just below 1 cannot round up to
/// `1.0`: the result is in `[0, 1)` for every finite `y` (within `2⁻²⁴` of the
/// exact `y mod 1` on the torus).
#[inline(always)]
#[must_use]
pub fn to_unit_f32(y: f64) -> f32 {
    (frac(y) as f32).min(ONE_MINUS_EPSILON)
}

/// A coordinate difference `d ∈ (−1, 1)` wrapped to its representative in
/// `[−1/2, 1/2)` (the shortest signed step on the torus). Exact: `d ∓ 1` is
/// an exact subtraction for `|d| ≥ 1/2` (Sterbenz).
#[inline(always)]
#[must_use]
pub fn torus_delta(d: f64) -> f64 {
    if d >= 0.5 {
        d - 1.0
    } else if d < -0.5 {
        d + 1.0
    } else {
        d
    }
}

/// The toroidal distance `min(|a − b|, 1 − |a − b|)` along one axis between
/// coordinates `a, b ∈ [0, 1)`; exact when `a − b` is (e.g. both are `f32`
/// values, or `f64` values within a factor 2 of each other), since `1 − d`
/// is exact for `d ∈ [1/2, 1]`.
#[inline(always)]
#[must_use]
pub fn torus_dist(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    if d > 0.5 {
        1.0 - d
    } else {
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frac_matches_floor_form() {
        for x in [
            -2.5, -1.0, -0.75, -1e-20, -0.0, 0.0, 0.25, 1.0, 1.5, 2.0, 7.25, 1e17, -1e17,
        ] {
            let f = x - crate::num::scalar::floor(x);
            let want = if f >= 1.0 { 0.0 } else { f };
            assert_eq!(frac(x).to_bits(), want.to_bits(), "{x}");
        }
        assert!(frac(f64::NAN).is_nan());
        assert_eq!(to_unit_f32(-1e-20), 0.0);
        assert_eq!(to_unit_f32(1.0 - 1e-17), 0.0);
        assert!(to_unit_f32(1.0 - 1e-9) < 1.0);
        assert_eq!(torus_delta(0.5), -0.5);
        assert_eq!(torus_delta(-0.75), 0.25);
        assert_eq!(torus_dist(0.9, 0.1), 1.0 - (0.9f64 - 0.1).abs());
    }
}
