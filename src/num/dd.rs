//! Double-double arithmetic (Dekker 1971; Knuth, TAOCP vol. 2 §4.2.2; Joldes,
//! Muller & Popescu, ACM TOMS 44(2), 2017): a value is the unevaluated sum `hi + lo` of two doubles with
//! `|lo| ≤ ulp(hi)/2`, about 106 bits of significand. Used wherever a closed
//! form or a phase would otherwise cancel.
//!
//! Error bounds (relative to the exact result of the operation on the exact
//! inputs `hi + lo`, for results in the normal range; `u = 2⁻⁵³`):
//!
//! | operation | bound |
//! |---|---|
//! | [`two_sum`], [`two_prod`], [`Dd::diff`], [`Dd::prod`] | exact |
//! | [`Dd::add`], [`Dd::sub`] | `3u²` (accurate addition; Joldes, Muller & Popescu 2017) |
//! | [`Dd::mul`] | `7u²` |
//! | [`Dd::mul_f64`] | `3u²` |
//! | [`Dd::div`] | `4u²` |
//! | [`Dd::sqrt`] | `4u²` |
//! | [`sum_accurate`] of `n ≤ 64` doubles | `4u²`, whatever the cancellation (to `10³⁶`) |
//! | [`Dd::scale`] by `2^k` | exact |
//!
//! The bounds are checked in `tests/num.rs` against exact rationals.

/// `(s, e)` with `s = fl(a + b)` and `s + e = a + b` exactly (Knuth's TwoSum;
/// exact for all finite `a`, `b` whose sum does not overflow).
#[inline(always)]
#[must_use]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// `(p, e)` with `p = fl(a·b)` and `p + e = a·b` exactly (TwoProd; exact
/// unless `a·b` overflows or `e` underflows, i.e. for `|a·b| ≥ 2⁻⁹⁶⁹`).
///
/// The same bits in every build, by two exact algorithms:
///
/// * where the target has FMA at compile time (x86-64-v3, aarch64):
///   `e = fma(a, b, −p)`, one instruction;
/// * otherwise Dekker's product (Dekker 1971, with Veltkamp's splitting
///   `a = a_h + a_l` into 26-bit halves by `C = 2²⁷ + 1`): `e = ((a_h b_h − p) +
///   a_h b_l + a_l b_h) + a_l b_l`, 17 operations and no call. It is exact when
///   `|a|, |b| ≤ 2⁹⁹⁵` (the split does not overflow) and `2⁻⁹⁶⁰ ≤ |p| < ∞` (no
///   partial product underflows); outside that range, and for zeros, NaN and
///   infinities, the correctly rounded `libm::fma(a, b, −p)`, which is what
///   the instruction returns. Both give `e = a·b − p` whenever it is
///   representable, so the two builds agree bit for bit (`tests/num.rs`
///   compares them with `libm::fma` over edge cases and random inputs).
///
/// Why not `libm::fma` always: without the instruction it is a software
/// routine, about 35× slower than the product it corrects, and the exact
/// closed forms call this a few dozen times per chord.
#[inline(always)]
#[must_use]
pub fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    if crate::num::scalar::HARDWARE_FMA {
        (p, crate::num::scalar::fma(a, b, -p))
    } else {
        (p, dekker_err(a, b, p))
    }
}

/// `2⁹⁹⁵`: below this, Veltkamp's split `C·a` (`C = 2²⁷ + 1`) cannot overflow.
const SPLIT_MAX: f64 = 3.2e299; // < 2⁹⁹⁵ ≈ 3.33e299
/// `2⁻⁹⁶⁰`: above this, no partial product of Dekker's algorithm underflows.
const DEKKER_MIN: f64 = 1.1e-289; // > 2⁻⁹⁶⁰ ≈ 1.026e-289

/// `a·b − p` for `p = fl(a·b)`, exactly, by Dekker's product where it is
/// exact and the correctly rounded fused result elsewhere (see [`two_prod`]). Compiled in every build
/// so that the tests can compare it with the FMA on any machine.
#[doc(hidden)]
#[inline(always)]
#[must_use]
pub fn dekker_err(a: f64, b: f64, p: f64) -> f64 {
    let ap = p.abs();
    if (DEKKER_MIN..=f64::MAX).contains(&ap) && a.abs() <= SPLIT_MAX && b.abs() <= SPLIT_MAX {
        let (ah, al) = veltkamp(a);
        let (bh, bl) = veltkamp(b);
        ((ah * bh - p) + ah * bl + al * bh) + al * bl
    } else {
        err_outside_dekker(a, b, p)
    }
}

/// [`dekker_err`] outside the range where Dekker's product is exact: `+0` for
/// a zero factor (`a·b − p` is then `(±0) + (∓0) = +0`, what the fused
/// operation returns), else the correctly rounded `libm::fma(a, b, −p)`.
///
/// Out of line and cold, so that a build without FMA has exactly one caller of
/// the software routine, reached only for zeros, NaN, infinities, factors
/// above `2⁹⁹⁵` and products below `2⁻⁹⁶⁰` (`tools/outside_crate.sh` checks
/// a dependent crate's binary for any other caller).
#[cold]
#[inline(never)]
fn err_outside_dekker(a: f64, b: f64, p: f64) -> f64 {
    if (a == 0.0 && b.is_finite()) || (b == 0.0 && a.is_finite()) {
        0.0
    } else {
        libm::fma(a, b, -p)
    }
}

/// Veltkamp's split: `a = h + l` with `h` of at most 26 significant bits and
/// `l` of at most 26 (exact for `|a| ≤ 2⁹⁹⁵`).
#[inline(always)]
fn veltkamp(a: f64) -> (f64, f64) {
    const C: f64 = 134_217_729.0; // 2²⁷ + 1
    let t = C * a;
    let h = t - (t - a);
    (h, a - h)
}

/// A double-double number `hi + lo` with `|lo| ≤ ulp(hi)/2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dd {
    /// Leading part.
    pub hi: f64,
    /// Trailing part.
    pub lo: f64,
}

// Named methods rather than operator traits: each one documents its accuracy,
// and `a.add(b)` reads as the double-double operation it is.
#[allow(clippy::should_implement_trait)]
impl Dd {
    /// Zero.
    pub const ZERO: Self = Self { hi: 0.0, lo: 0.0 };

    /// The exact value `x`.
    #[inline(always)]
    #[must_use]
    pub fn new(x: f64) -> Self {
        Self { hi: x, lo: 0.0 }
    }

    /// Exact `a + b` of two doubles.
    #[inline(always)]
    #[must_use]
    pub fn sum(a: f64, b: f64) -> Self {
        let (hi, lo) = two_sum(a, b);
        Self { hi, lo }
    }

    /// Exact `a − b` of two doubles.
    #[inline(always)]
    #[must_use]
    pub fn diff(a: f64, b: f64) -> Self {
        let (hi, lo) = two_sum(a, -b);
        Self { hi, lo }
    }

    /// Exact `a · b` of two doubles.
    #[inline(always)]
    #[must_use]
    pub fn prod(a: f64, b: f64) -> Self {
        let (hi, lo) = two_prod(a, b);
        Self { hi, lo }
    }

    /// `self + o`, the accurate double-double addition (relative error
    /// ≤ `3u²`; not the "sloppy" one-TwoSum variant, which loses everything
    /// under cancellation).
    #[inline(always)]
    #[must_use]
    pub fn add(self, o: Self) -> Self {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let e = e + t;
        let (s, e) = two_sum(s, e);
        let e = e + f;
        let (hi, lo) = two_sum(s, e);
        Self { hi, lo }
    }

    /// `−self` (exact).
    #[inline(always)]
    #[must_use]
    pub fn neg(self) -> Self {
        Self {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    /// `self − o` (as [`Dd::add`]).
    #[inline(always)]
    #[must_use]
    pub fn sub(self, o: Self) -> Self {
        self.add(o.neg())
    }

    /// `self · o` (relative error ≤ `7u²`; the `lo·lo` term, below `u²`
    /// relative, is dropped).
    #[inline(always)]
    #[must_use]
    pub fn mul(self, o: Self) -> Self {
        let (p, e) = two_prod(self.hi, o.hi);
        let e = e + (self.hi * o.lo + self.lo * o.hi);
        let (hi, lo) = two_sum(p, e);
        Self { hi, lo }
    }

    /// `self · x` for a double `x` (relative error ≤ `3u²`).
    #[inline(always)]
    #[must_use]
    pub fn mul_f64(self, x: f64) -> Self {
        let (p, e) = two_prod(self.hi, x);
        let e = e + self.lo * x;
        let (hi, lo) = two_sum(p, e);
        Self { hi, lo }
    }

    /// `self · s` part by part: exact when `s` is a power of two (and nothing
    /// over- or underflows); for other `s` use [`Dd::mul_f64`].
    #[inline(always)]
    #[must_use]
    pub fn scale(self, s: f64) -> Self {
        Self {
            hi: self.hi * s,
            lo: self.lo * s,
        }
    }

    /// `self / o` by long division with exact remainders: three quotient
    /// digits `q₁ + q₂ + q₃`, each remainder `r − o·q` formed in double-double
    /// (relative error ≤ `4u²`). A non-finite leading quotient (division by
    /// zero, overflow, NaN) is returned as it is.
    #[must_use]
    pub fn div(self, o: Self) -> Self {
        let q1 = self.hi / o.hi;
        if !q1.is_finite() {
            return Self::new(q1);
        }
        let r = self.sub(o.mul(Self::new(q1)));
        let q2 = r.hi / o.hi;
        let r = r.sub(o.mul(Self::new(q2)));
        let q3 = r.hi / o.hi;
        let (s, e) = two_sum(q1, q2);
        let (hi, lo) = two_sum(s, e + q3);
        Self { hi, lo }
    }

    /// `1/self` by one Newton step from `q₁ = fl(1/hi)`: the remainder
    /// `1 − hi·q₁` is exact (an exact product), `r = (1 − hi·q₁) − lo·q₁`, and
    /// `q₁ + q₁·r` as a double-double. Since `y(q₁ + q₁r) = 1 − (1 − yq₁)²`
    /// up to the roundings of `r` and `q₁r`, the relative error is
    /// `≤ (2u)² + 4u² = 8u²` — a few times cheaper than [`Dd::div`] by
    /// `Dd::new(1.0)`. A non-finite `q₁` (division by zero, overflow, NaN) is
    /// returned as it is.
    #[inline]
    #[must_use]
    pub fn recip(self) -> Self {
        let q1 = 1.0 / self.hi;
        if !q1.is_finite() {
            return Self::new(q1);
        }
        // 1 − hi·q₁ is representable (q₁ is the rounded reciprocal), and
        // 1 − p is exact (p ∈ [½, 2], Sterbenz), so this is its exact value.
        let (p, pe) = two_prod(self.hi, q1);
        let e = (1.0 - p) - pe;
        let r = e - self.lo * q1;
        let (hi, lo) = two_sum(q1, q1 * r);
        Self { hi, lo }
    }

    /// `√self` for `self ≥ 0`: `s = √hi` and one Newton correction
    /// `(self − s²)/(2s)` with `s²` formed exactly (relative error ≤ `4u²`).
    /// `√0 = 0`; a negative or NaN argument gives NaN.
    #[must_use]
    pub fn sqrt(self) -> Self {
        if self.hi <= 0.0 || !self.hi.is_finite() {
            return Self::new(crate::num::scalar::sqrt(self.hi));
        }
        let s = crate::num::scalar::sqrt(self.hi);
        let (p, pe) = two_prod(s, s);
        let c = (((self.hi - p) - pe) + self.lo) / (2.0 * s);
        let (hi, lo) = two_sum(s, c);
        Self { hi, lo }
    }

    /// `self < o`, exactly for finite values (the sign of the double-double
    /// difference); for infinite operands the leading parts are compared.
    #[inline]
    #[must_use]
    pub fn lt(self, o: Self) -> bool {
        if self.hi.is_finite() && o.hi.is_finite() {
            self.sub(o).hi < 0.0
        } else {
            self.hi < o.hi
        }
    }

    /// `self ≤ o` (as [`Dd::lt`]).
    #[inline]
    #[must_use]
    pub fn le(self, o: Self) -> bool {
        if self.hi.is_finite() && o.hi.is_finite() {
            self.sub(o).hi <= 0.0
        } else {
            self.hi <= o.hi
        }
    }

    /// The nearest double (`hi + lo` rounded once; `hi` itself when the pair
    /// is normalised).
    #[inline(always)]
    #[must_use]
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
}

/// `Σ t_i` of many doubles to double-double accuracy whatever the
/// cancellation: Ogita, Rump & Oishi's `SumK` (*Accurate sum and dot product*,
/// SIAM J. Sci. Comput. 26(6), 2005) with `K = 4`: three error-free `VecSum`
/// passes (each replaces the terms by an exactly equal set whose last entry is
/// the rounded running sum), then the last entry plus the plain sum of the
/// rest. The result is as if computed in four-fold precision and rounded: its
/// error is `≤ 2u²|S| + γ_{n−1}⁴·Σ|t_i|` (`γ_m = mu/(1 − mu)`), so for `n ≤ 64`
/// terms it is `u²`-relative even when `Σ|t_i|/|S|` reaches `10³⁶`. The terms
/// are overwritten.
#[must_use]
pub fn sum_accurate(t: &mut [f64]) -> Dd {
    let n = t.len();
    if n == 0 {
        return Dd::ZERO;
    }
    for _ in 0..3 {
        for i in 1..n {
            let (s, e) = two_sum(t[i], t[i - 1]);
            t[i] = s;
            t[i - 1] = e;
        }
    }
    let mut rest = 0.0;
    for &x in &t[..n - 1] {
        rest += x;
    }
    Dd::sum(t[n - 1], rest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_are_exact() {
        let a = 1.0 + f64::EPSILON;
        let p = Dd::prod(a, a);
        assert_eq!(p.hi, 1.0 + 2.0 * f64::EPSILON);
        assert_eq!(p.lo, f64::EPSILON * f64::EPSILON);
        assert_eq!(Dd::diff(1.0, 1e-20).lo, -1e-20);
    }

    #[test]
    fn sqrt_edges() {
        assert_eq!(Dd::new(0.0).sqrt(), Dd::ZERO);
        assert!(Dd::new(-1.0).sqrt().hi.is_nan());
        assert_eq!(Dd::new(4.0).sqrt(), Dd::new(2.0));
        assert_eq!(Dd::new(f64::INFINITY).sqrt().hi, f64::INFINITY);
    }
}
