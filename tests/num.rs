//! The numeric core (`linesample::num`) against exact arithmetic.
//!
//! Every double is a dyadic rational `m·2^e`, and so is every sum and product
//! of doubles: the reference here is exact big-integer arithmetic on
//! `(mantissa, exponent)` pairs ([`Exact`]), written in this file and sharing
//! nothing with the kernel. Quotients and square roots are checked through the
//! exact identities `q·y − x = x·δ` and `r² − x = x·(2δ + δ²)`, which stay in
//! dyadic arithmetic. Phase reduction is checked against `j·m mod 2^k`
//! computed in `i128` on the mantissa of `x` (`|j| ≤ 10⁶`).
//!
//! Bounds asserted (`u = 2⁻⁵³`, relative to the exact result for the exact
//! double-double inputs): add/sub `3u²`, mul `7u²`, `mul_f64` `3u²`, div
//! `4u²`, recip `8u²`, sqrt `4u²`; `frac_centered` within `2⁻⁵⁴` absolute; `cis_turns`
//! and `sinc` within 2 ulp of 1 of the exact-phase reference.

use linesample::num::{
    cis_turns, frac, frac_centered, sinc, sum_accurate, to_unit_f32, torus_delta, torus_dist,
    two_prod, two_sum, Dd,
};
use num_bigint::BigInt;
use proptest::prelude::*;
use std::cmp::Ordering;

/// An exact dyadic rational `n·2^e`.
#[derive(Clone, Debug)]
struct Exact {
    n: BigInt,
    e: i64,
}

impl Exact {
    /// The exact value of a finite double.
    fn of(x: f64) -> Self {
        assert!(x.is_finite());
        let bits = x.to_bits();
        let sign = if bits >> 63 == 1 { -1 } else { 1 };
        let be = ((bits >> 52) & 0x7ff) as i64;
        let frac = bits & ((1u64 << 52) - 1);
        let (m, e) = if be == 0 {
            (frac, -1074)
        } else {
            (frac | (1u64 << 52), be - 1075)
        };
        Self {
            n: BigInt::from(m) * sign,
            e,
        }
    }
    fn of_dd(x: Dd) -> Self {
        Self::of(x.hi).add(&Self::of(x.lo))
    }
    fn aligned(&self, o: &Self) -> (BigInt, BigInt, i64) {
        let e = self.e.min(o.e);
        (
            self.n.clone() << (self.e - e) as usize,
            o.n.clone() << (o.e - e) as usize,
            e,
        )
    }
    fn add(&self, o: &Self) -> Self {
        let (a, b, e) = self.aligned(o);
        Self { n: a + b, e }
    }
    fn sub(&self, o: &Self) -> Self {
        let (a, b, e) = self.aligned(o);
        Self { n: a - b, e }
    }
    fn mul(&self, o: &Self) -> Self {
        Self {
            n: &self.n * &o.n,
            e: self.e + o.e,
        }
    }
    fn abs(&self) -> Self {
        Self {
            n: if self.n < BigInt::from(0) {
                -self.n.clone()
            } else {
                self.n.clone()
            },
            e: self.e,
        }
    }
    fn cmp(&self, o: &Self) -> Ordering {
        let (a, b, _) = self.aligned(o);
        a.cmp(&b)
    }
    fn is_zero(&self) -> bool {
        self.n == BigInt::from(0)
    }
    /// `|self| ≤ k·2^p·|o|`.
    fn within(&self, o: &Self, k: u64, p: i64) -> bool {
        let rhs = Self {
            n: o.abs().n * BigInt::from(k),
            e: o.e + p,
        };
        self.abs().cmp(&rhs) != Ordering::Greater
    }
}

const U2: i64 = -106; // u² = 2⁻¹⁰⁶

/// A double with a random sign, a mantissa of random bits and an exponent in
/// `[lo, hi]`: covers every binade evenly, unlike uniform floats.
fn double(lo: i32, hi: i32) -> impl Strategy<Value = f64> {
    (any::<bool>(), 0u64..(1 << 52), lo..=hi).prop_map(|(neg, m, e)| {
        let x = libm::ldexp(1.0 + m as f64 / (1u64 << 52) as f64, e);
        if neg {
            -x
        } else {
            x
        }
    })
}

/// A normalised double-double `hi + lo` with `|lo| ≤ ulp(hi)/2`.
fn dd(lo: i32, hi: i32) -> impl Strategy<Value = Dd> {
    (double(lo, hi), double(-60, -53)).prop_map(|(h, l)| {
        let (hi, lo) = two_sum(h, h * l);
        Dd { hi, lo }
    })
}

/// Pairs whose leading parts nearly cancel (the hard case of add/sub and of
/// the comparisons): `y = −x·(1 + tiny)` or `y = −x` plus a perturbation.
fn cancelling() -> impl Strategy<Value = (Dd, Dd)> {
    (dd(-40, 40), double(-110, -50), any::<bool>()).prop_map(|(x, t, same_hi)| {
        let y = if same_hi {
            Dd {
                hi: -x.hi,
                lo: -x.lo + x.hi * t * 1e-3,
            }
        } else {
            let (hi, lo) = two_sum(-x.hi, -x.hi * t);
            Dd { hi, lo }
        };
        (x, y)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn error_free_transformations_are_exact(a in double(-400, 400), b in double(-400, 400)) {
        let (s, e) = two_sum(a, b);
        prop_assert!(Exact::of(s).add(&Exact::of(e)).sub(&Exact::of(a).add(&Exact::of(b))).is_zero());
        let (p, e) = two_prod(a, b);
        prop_assert!(Exact::of(p).add(&Exact::of(e)).sub(&Exact::of(a).mul(&Exact::of(b))).is_zero());
        prop_assert!(Exact::of_dd(Dd::diff(a, b)).sub(&Exact::of(a).sub(&Exact::of(b))).is_zero());
        prop_assert!(Exact::of_dd(Dd::sum(a, b)).sub(&Exact::of(a).add(&Exact::of(b))).is_zero());
        prop_assert!(Exact::of_dd(Dd::prod(a, b)).sub(&Exact::of(a).mul(&Exact::of(b))).is_zero());
    }

    #[test]
    fn add_sub_within_3u2(x in dd(-300, 300), y in dd(-300, 300)) {
        for (z, exact) in [
            (x.add(y), Exact::of_dd(x).add(&Exact::of_dd(y))),
            (x.sub(y), Exact::of_dd(x).sub(&Exact::of_dd(y))),
        ] {
            let err = Exact::of_dd(z).sub(&exact);
            prop_assert!(err.within(&exact, 3, U2), "{x:?} {y:?} -> {z:?}");
        }
    }

    #[test]
    fn add_under_cancellation_within_3u2((x, y) in cancelling()) {
        let z = x.add(y);
        let exact = Exact::of_dd(x).add(&Exact::of_dd(y));
        let err = Exact::of_dd(z).sub(&exact);
        prop_assert!(err.within(&exact, 3, U2), "{x:?} {y:?} -> {z:?}");
        // The comparisons are exact, whatever the cancellation.
        let zero = Exact::of(0.0);
        prop_assert_eq!(x.lt(y.neg()), exact.cmp(&zero) == Ordering::Less);
        prop_assert_eq!(x.le(y.neg()), exact.cmp(&zero) != Ordering::Greater);
    }

    #[test]
    fn mul_within_7u2(x in dd(-300, 300), y in dd(-300, 300), s in double(-300, 300)) {
        let exact = Exact::of_dd(x).mul(&Exact::of_dd(y));
        let err = Exact::of_dd(x.mul(y)).sub(&exact);
        prop_assert!(err.within(&exact, 7, U2), "{x:?} {y:?}");
        let exact = Exact::of_dd(x).mul(&Exact::of(s));
        let err = Exact::of_dd(x.mul_f64(s)).sub(&exact);
        prop_assert!(err.within(&exact, 3, U2), "{x:?} {s}");
        // Scaling by a power of two is exact.
        let k = (s.abs().log2() as i32).clamp(-300, 300);
        let p = libm::ldexp(1.0, k);
        let err = Exact::of_dd(x.scale(p)).sub(&Exact::of_dd(x).mul(&Exact::of(p)));
        prop_assert!(err.is_zero());
    }

    #[test]
    fn div_within_4u2(x in dd(-300, 300), y in dd(-300, 300)) {
        // q = (x/y)(1 + δ) ⟺ q·y − x = x·δ, all dyadic.
        let q = x.div(y);
        let resid = Exact::of_dd(q).mul(&Exact::of_dd(y)).sub(&Exact::of_dd(x));
        prop_assert!(resid.within(&Exact::of_dd(x), 4, U2), "{x:?} / {y:?} = {q:?}");
    }

    #[test]
    fn recip_within_8u2(y in dd(-300, 300)) {
        // q = (1/y)(1 + δ) ⟺ q·y − 1 = δ, all dyadic.
        let q = y.recip();
        let one = Exact::of(1.0);
        let resid = Exact::of_dd(q).mul(&Exact::of_dd(y)).sub(&one);
        prop_assert!(resid.within(&one, 8, U2), "1 / {y:?} = {q:?}");
    }

    #[test]
    fn sqrt_within_4u2(x in dd(-600, 600)) {
        let x = Dd { hi: x.hi.abs(), lo: if x.hi < 0.0 { -x.lo } else { x.lo } };
        // r = √x(1 + δ) ⟺ r² − x = x(2δ + δ²): |δ| ≤ 4u² ⟸ |r² − x| ≤ 8u²·x.
        let r = x.sqrt();
        let ex = Exact::of_dd(x);
        let er = Exact::of_dd(r);
        let resid = er.mul(&er).sub(&ex);
        prop_assert!(resid.within(&ex, 8, U2), "√{x:?} = {r:?}");
    }

    /// Sums of up to 62 doubles that cancel to 10⁻³⁶ of their magnitude (the
    /// constant term of a re-based quadratic): relative error ≤ 4u².
    #[test]
    fn accurate_sum_survives_cancellation(xs in proptest::collection::vec(double(-40, 40), 1..31), tiny in double(-120, -60)) {
        let mut t: Vec<f64> = Vec::new();
        for &x in &xs {
            t.push(x);
            t.push(-x);
        }
        t.push(tiny);
        // Interleave so that the cancelling pairs are far apart.
        let n = t.len();
        let mut u: Vec<f64> = (0..n).map(|i| t[(i * 7) % n]).collect();
        if n.is_multiple_of(7) {
            u = t.clone();
        }
        let exact = u.iter().fold(Exact::of(0.0), |acc, &x| acc.add(&Exact::of(x)));
        let got = sum_accurate(&mut u.clone());
        let err = Exact::of_dd(got).sub(&exact);
        prop_assert!(err.within(&exact, 4, U2), "{got:?} vs tiny {tiny:e}");
    }

    #[test]
    fn comparisons_are_exact(x in dd(-50, 50), y in dd(-50, 50)) {
        let o = Exact::of_dd(x).cmp(&Exact::of_dd(y));
        prop_assert_eq!(x.lt(y), o == Ordering::Less);
        prop_assert_eq!(x.le(y), o != Ordering::Greater);
        prop_assert!(x.le(x) && !x.lt(x));
    }

    /// `frac_centered(j·x)` against `j·m mod 2^k` in `i128` (`x = m·2^−k`).
    #[test]
    fn phase_reduction_matches_integer_arithmetic(
        j in -1_000_000i64..=1_000_000,
        x in double(-60, 3),
    ) {
        let got = frac_centered(Dd::prod(j as f64, x));
        let want = exact_frac_centered(j, x);
        prop_assert!(phase_gap(got, want) <= libm::ldexp(1.0, -53), "j = {j}, x = {x}: {got} vs {want}");
        // e^{−2πiθ} from the exact phase (rounded once): the same within 2 ulp of 1
        // plus the reference's own rounding of 2π·want.
        let z = cis_turns(Dd::prod(j as f64, x));
        let a = -core::f64::consts::TAU * want;
        let tol = 2.0 * f64::EPSILON + 8.0 * libm::ldexp(1.0, -54);
        prop_assert!((z.re - libm::cos(a)).abs() <= tol && (z.im - libm::sin(a)).abs() <= tol,
            "j = {j}, x = {x}: {z:?} vs ({}, {})", libm::cos(a), libm::sin(a));
    }

    /// `sinc(t)` for large `t` against the period removed in integer arithmetic.
    #[test]
    fn sinc_matches_exact_reduction(t in double(-30, 23)) {
        // sin(πt) = sin(π·r), r = t − 2·round(t/2) ∈ [−1, 1], exact.
        let r = 2.0 * exact_frac_centered(1, 0.5 * t);
        let want = libm::sin(core::f64::consts::PI * r) / (core::f64::consts::PI * t);
        prop_assert!((sinc(t) - want).abs() <= 2.0 * f64::EPSILON + 4.0 * libm::ldexp(1.0, -53) / t.abs().max(1.0),
            "t = {t}: {} vs {want}", sinc(t));
    }

    #[test]
    fn torus_wrapping_is_exact_where_promised(x in double(-60, 60), a in 0.0f64..1.0, b in 0.0f64..1.0) {
        // frac(x) = x − ⌊x⌋ exactly for x ≥ 0; within 2⁻⁵⁴ (then 0 if it rounds to 1) for x < 0.
        let f = frac(x);
        prop_assert!((0.0..1.0).contains(&f));
        let ex = Exact::of(x);
        let fl = Exact { n: floor_exact(&ex), e: 0 };
        let exact = ex.sub(&fl);
        let err = Exact::of(f).sub(&exact);
        if x >= 0.0 {
            prop_assert!(err.is_zero(), "frac({x}) = {f}");
        } else {
            let one = Exact::of(1.0);
            prop_assert!(err.within(&one, 1, -54) || (f == 0.0 && exact.sub(&one).within(&one, 1, -54)), "frac({x}) = {f}");
        }
        let g = to_unit_f32(x);
        prop_assert!((0.0..1.0).contains(&g));
        let d = (f64::from(g) - f).abs();
        prop_assert!(d <= libm::ldexp(1.0, -24) || (g == 0.0 && 1.0 - f <= libm::ldexp(1.0, -24)));
        // torus_delta: the representative in [−1/2, 1/2), exact.
        let dlt = torus_delta(a - b);
        prop_assert!((-0.5..0.5).contains(&dlt));
        let k = Exact::of(dlt).sub(&Exact::of(a - b));
        prop_assert!(k.is_zero() || k.abs().cmp(&Exact::of(1.0)) == Ordering::Equal);
        let dist = torus_dist(a, b);
        prop_assert!((dist - dlt.abs()).abs() == 0.0 && dist <= 0.5);
    }
}

/// `|a − b|` modulo 1 (the phases `1/2` and `−1/2` are the same). Both the
/// kernel's value and the reference are the exact phase rounded once (≤ 2⁻⁵⁴
/// each), so they differ by at most 2⁻⁵³.
fn phase_gap(a: f64, b: f64) -> f64 {
    let d = a - b;
    (d - libm::round(d)).abs()
}

/// `⌊v⌋` of an exact dyadic value, as an integer.
fn floor_exact(v: &Exact) -> BigInt {
    if v.e >= 0 {
        v.n.clone() << v.e as usize
    } else {
        // Arithmetic shift right floors (num-bigint rounds towards −∞ for >>).
        v.n.clone() >> (-v.e) as usize
    }
}

/// `j·x − round(j·x)` in `[−1/2, 1/2]` from exact integer arithmetic on the
/// mantissa of `x = m·2^e` (`|j·m| < 2^73` fits `i128`), rounded once.
fn exact_frac_centered(j: i64, x: f64) -> f64 {
    let ex = Exact::of(x);
    let m: i128 = i128::try_from(&ex.n).unwrap();
    let e = ex.e;
    let p = i128::from(j) * m;
    if e >= 0 {
        return 0.0;
    }
    let k = (-e) as u32;
    if k >= 126 {
        // |j·x| < 2^(73−126): no integer part at all.
        return (p as f64) * libm::ldexp(1.0, e as i32);
    }
    let modulus = 1i128 << k;
    let mut r = p.rem_euclid(modulus); // j·m mod 2^k ∈ [0, 2^k)
    if 2 * r > modulus {
        r -= modulus; // centred: (−2^(k−1), 2^(k−1)]
    }
    // r·2^e, |r| ≤ 2^(k−1): one rounding in the conversion of r (exact when
    // |r| < 2^53) and an exact scaling.
    libm::ldexp(r as f64, e as i32)
}

#[test]
fn phase_reduction_hard_cases() {
    // Exact halves, quarters and the largest j with x just below 1.
    for &(j, x) in &[
        (1_000_000i64, 0.5),
        (999_999, 0.25),
        (-1_000_000, 1.0 - f64::EPSILON / 2.0),
        (3, 1.0 / 3.0),
        (1_000_000, 0.1),
        (777_777, 1e-17),
        (1, -0.75),
    ] {
        let got = frac_centered(Dd::prod(j as f64, x));
        let want = exact_frac_centered(j, x);
        assert!(
            phase_gap(got, want) <= libm::ldexp(1.0, -53),
            "{j} {x}: {got} {want}"
        );
    }
    // A plain f64 product loses the phase entirely at this size: the test can
    // tell the difference (the reduction is what is being tested).
    let (j, x) = (1_000_000.0f64, 0.1f64);
    let naive = j * x - libm::round(j * x);
    let exact = exact_frac_centered(1_000_000, 0.1);
    assert!((naive - exact).abs() > 1e-12, "{naive} {exact}");
}

/// Edge cases for the inlined scalar primitives: zeros of both signs, halves,
/// the neighbours of integers and halves, the `2⁵²` boundary, subnormals,
/// huge values, infinities.
fn scalar_edge_cases() -> Vec<f64> {
    let mut v = vec![
        0.0,
        -0.0,
        0.5,
        -0.5,
        1.5,
        -1.5,
        2.5,
        -2.5,
        0.49999999999999994,
        -0.49999999999999994,
        4503599627370496.0,
        4503599627370495.5,
        -4503599627370495.5,
        9007199254740991.0,
        f64::MIN_POSITIVE,
        -f64::MIN_POSITIVE,
        5e-324,
        -5e-324,
        f64::MAX,
        f64::MIN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e300,
        -1e300,
    ];
    for k in -70i32..=70 {
        let x = 2f64.powi(k);
        for y in [x, x.next_up(), x.next_down(), x + 0.5, x - 0.5] {
            v.push(y);
            v.push(-y);
        }
    }
    v
}

/// `scalar::{fma, sqrt, floor, round}` are `libm`'s bit for bit (they are
/// inlined replacements; a difference would change pinned values).
#[test]
fn inlined_scalar_primitives_equal_libm_bit_for_bit() {
    use linesample::num::scalar;
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    let edges = scalar_edge_cases();
    let mut rng = linesample::Pcg32::new(5, 9);
    let mut rand = || {
        // Random bit patterns (every exponent) and random values near 1.
        let bits = (u64::from(rng.next_u32()) << 32) | u64::from(rng.next_u32());
        f64::from_bits(bits)
    };
    let mut xs = edges.clone();
    for _ in 0..200_000 {
        xs.push(rand());
    }
    let mut n = 0usize;
    for &x in &xs {
        assert!(same(scalar::floor(x), libm::floor(x)), "floor({x:e})");
        assert!(same(scalar::round(x), libm::round(x)), "round({x:e})");
        assert!(same(scalar::sqrt(x), libm::sqrt(x)), "sqrt({x:e})");
        n += 3;
    }
    // fma: edge triples (including exact cancellation, the case two_prod relies
    // on) and random triples, with c = −a·b rounded so the result is the error.
    for &a in edges.iter().step_by(3) {
        for &b in edges.iter().step_by(7) {
            for c in [0.0, -0.0, 1.0, -(a * b), a, -b] {
                assert!(
                    same(scalar::fma(a, b, c), libm::fma(a, b, c)),
                    "fma({a:e}, {b:e}, {c:e})"
                );
                n += 1;
            }
        }
    }
    for _ in 0..200_000 {
        let (a, b) = (rand(), rand());
        for c in [rand(), -(a * b)] {
            assert!(
                same(scalar::fma(a, b, c), libm::fma(a, b, c)),
                "fma({a:e}, {b:e}, {c:e})"
            );
            n += 1;
        }
        let (a, b) = (1.0 + rand().fract(), rand().fract());
        let c = -(a * b);
        assert!(
            same(scalar::fma(a, b, c), libm::fma(a, b, c)),
            "fma({a:e}, {b:e}, {c:e})"
        );
        n += 1;
    }
    println!("{n} comparisons, all bit-identical");
}

/// `two_prod`'s error term without FMA (Dekker's product with Veltkamp's
/// split, `num::dd::dekker_err`) equals the correctly rounded
/// `libm::fma(a, b, −p)` bit for bit, so a build without FMA gives the same
/// double-double results as one with it: edge cases, values at the guard
/// boundaries (`|a|, |b|` near `2⁹⁹⁵`, `|a·b|` near `2⁻⁹⁶⁰` and below, where
/// the partial products would underflow), random bit patterns of every
/// exponent and random significands near 1.
#[test]
fn dekker_product_equals_the_fused_error_bit_for_bit() {
    use linesample::num::dd::dekker_err;
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    let mut rng = linesample::Pcg32::new(11, 3);
    let mut bits = || (u64::from(rng.next_u32()) << 32) | u64::from(rng.next_u32());
    let mut pairs: Vec<(f64, f64)> = Vec::new();
    let edges = scalar_edge_cases();
    for &a in &edges {
        for &b in edges.iter().step_by(5) {
            pairs.push((a, b));
        }
    }
    let p995 = 2f64.powi(995);
    let m960 = 2f64.powi(-960);
    for _ in 0..20_000 {
        let f = 1.0 + f64::from_bits(bits()).fract().abs();
        let g = 1.0 + f64::from_bits(bits()).fract().abs();
        for (sa, sb) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0)] {
            pairs.push((sa * p995 * f, sb * g));
            pairs.push((sa * p995 / f, sb * p995 / g));
            pairs.push((sa * f * 2f64.powi(-480), sb * g * 2f64.powi(-481)));
            pairs.push((sa * m960.sqrt() * f, sb * m960.sqrt() / g));
            pairs.push((sa * f * 1e-300, sb * g * 1e-20));
        }
    }
    for _ in 0..300_000 {
        pairs.push((f64::from_bits(bits()), f64::from_bits(bits())));
        let a = 1.0 + f64::from_bits(bits()).fract().abs();
        let b = f64::from_bits(bits()).fract();
        pairs.push((a, b));
    }
    let mut dekker = 0usize;
    for &(a, b) in &pairs {
        let p = a * b;
        let want = libm::fma(a, b, -p);
        let got = dekker_err(a, b, p);
        assert!(same(got, want), "a = {a:e}, b = {b:e}: {got:e} vs {want:e}");
        let (tp, te) = two_prod(a, b);
        assert!(same(tp, p) && same(te, want), "two_prod({a:e}, {b:e})");
        if p.abs() >= 1.1e-289 && p.is_finite() && a.abs() <= 3.2e299 && b.abs() <= 3.2e299 {
            dekker += 1;
        }
    }
    // Most pairs exercise the split itself, not the fallback.
    assert!(dekker * 2 > pairs.len(), "{dekker} of {}", pairs.len());
    println!(
        "{} pairs ({dekker} through Dekker's product), all bit-identical",
        pairs.len()
    );
}
