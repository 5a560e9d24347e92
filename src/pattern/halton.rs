//! Owen-scrambled Halton points: [`Halton`], its random-access functions and
//! [`radical_inverse`]. The construction is documented on [`Halton`].

use super::sealed::{Generate, Sink};
use super::{check_dims, check_n, drive8, stratum_f32, ONE_MINUS_EPSILON};
use crate::error::PatternError;
use crate::rng::{mix32, mix32x8, Seed};
use wide::{f32x8, u32x8};

/// The first 16 primes: the base of each Halton dimension.
pub const HALTON_BASES: [u32; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

/// Number of Halton dimensions available to [`Halton::sample`].
pub const HALTON_DIMENSIONS: u32 = 16;

const NDIM: usize = HALTON_DIMENSIONS as usize;

/// The radical inverse `φ_b(i) = Σ_k a_k b^{−(k+1)}` of `index = Σ_k a_k b^k` in base
/// `base` (van der Corput 1935, Halton 1960): the base-`b` digits of the index
/// mirrored about the radix point. Unscrambled; the value is in `[0, 1)`.
///
/// The mirrored digits form an integer `N < b^n` (`n` = number of digits of the
/// index) and the result is `N / b^n` with one correctly rounded `f64` division, so
/// it is the correctly rounded value whenever `b^n ≤ 2⁵³`, which holds for every
/// index when `base < 2²¹` (all of [`HALTON_BASES`]); e.g. `φ₂(6) = 0.375`,
/// `φ₃(5) = 7/9`. For larger bases the result is within a few ulps and is clamped
/// below 1.
///
/// Any `base ≥ 2` is accepted, prime or not (a composite base gives its digit
/// reversal as well, which is not a Halton coordinate). For `base < 2`, where no
/// digit expansion exists, the result is `0.0`. Never panics.
#[must_use]
pub fn radical_inverse(base: u32, index: u32) -> f64 {
    if base < 2 {
        return 0.0;
    }
    let b = u64::from(base);
    let (mut q, mut n, mut pow) = (u64::from(index), 0u64, 1u64);
    // n < pow ≤ b·index < 2⁶⁴ throughout: no overflow.
    while q > 0 {
        n = n * b + q % b;
        pow *= b;
        q /= b;
    }
    (n as f64 / pow as f64).min(1.0 - f64::EPSILON / 2.0)
}

/// Unsigned division by an invariant `d ≥ 1` for every 32-bit dividend:
/// `⌊n/d⌋ = (t + ((n − t) ≫ s₁)) ≫ s₂` with `t = ⌊m·n/2³²⌋`
/// (Granlund & Montgomery 1994, Fig. 4.1).
#[derive(Clone, Copy, Debug)]
struct Divisor {
    m: u32,
    s1: u32,
    s2: u32,
}

impl Divisor {
    const fn new(d: u32) -> Self {
        // l = ⌈log₂ d⌉, m = ⌊2³²·(2^l − d)/d⌋ + 1 < 2³².
        let l = if d <= 1 {
            0
        } else {
            32 - (d - 1).leading_zeros()
        };
        let d64 = d as u64;
        let m = (((1u64 << 32) * ((1u64 << l) - d64)) / d64 + 1) as u32;
        Self {
            m,
            s1: if l < 1 { l } else { 1 },
            s2: l.saturating_sub(1),
        }
    }

    #[inline(always)]
    const fn div(self, n: u32) -> u32 {
        let t = ((self.m as u64 * n as u64) >> 32) as u32;
        (t + ((n - t) >> self.s1)) >> self.s2
    }

    #[inline(always)]
    fn div_x8(self, n: u32x8) -> u32x8 {
        let t = n.mul_keep_high(u32x8::splat(self.m));
        (t + ((n - t) >> self.s1)) >> self.s2
    }
}

/// Per-base constants of the digit loop and the `f32` conversion.
#[derive(Clone, Copy, Debug)]
struct Base {
    b: u32,
    /// `J_b`: leading digits that form the cell, `b^J ≤ 2²⁴ < b^{J+1}`.
    cell_digits: u32,
    /// `K_b`: all digits, the first `K` with `b^K ≥ 2³²`.
    digits: u32,
    /// `b^J` (≤ 2²⁴).
    cells: u32,
    /// `2³² / b^{K−J}`: scale of the tail digits to a 32-bit offset.
    tail_scale: f64,
    /// `b^k mod 2³²` for `k < K` (exact: `b^{K−1} < 2³²`).
    pow: [u32; 32],
    div: Divisor,
}

impl Base {
    const fn new(b: u32) -> Self {
        let b64 = b as u64;
        let mut cell_digits = 0;
        let mut cells = 1u64;
        while cells * b64 <= 1 << 24 {
            cells *= b64;
            cell_digits += 1;
        }
        let mut digits = 0;
        let mut p = 1u64;
        let mut pow = [0u32; 32];
        while p < 1 << 32 {
            pow[digits as usize] = p as u32;
            p *= b64;
            digits += 1;
        }
        let mut tail = 1u64;
        let mut k = cell_digits;
        while k < digits {
            tail *= b64;
            k += 1;
        }
        Self {
            b,
            cell_digits,
            digits,
            cells: cells as u32,
            tail_scale: 4_294_967_296.0 / tail as f64,
            pow,
            div: Divisor::new(b),
        }
    }

    /// The coordinate from the cell digits `cell` and the tail digits `tail`.
    #[inline(always)]
    fn coordinate(&self, cell: u32, tail: u32) -> f32 {
        let bits = (f64::from(tail) * self.tail_scale) as u32;
        let m = f64::from(self.cells);
        stratum_f32(cell, bits, m, 1.0 / m).min(ONE_MINUS_EPSILON)
    }
}

const fn bases() -> [Base; NDIM] {
    let mut out = [Base::new(2); NDIM];
    let mut d = 0;
    while d < NDIM {
        out[d] = Base::new(HALTON_BASES[d]);
        d += 1;
    }
    out
}

static BASES: [Base; NDIM] = bases();

/// Seed purpose of the digit permutations of dimension `d` (plus `d`).
const PURPOSE: u64 = 0x4841_4C54_0000_0000;

/// `κ_{σ,d}`.
#[inline(always)]
const fn dim_key(seed: Seed, dim: u32) -> u32 {
    let s = seed.stream(PURPOSE + dim as u64);
    (s ^ (s >> 32)) as u32
}

/// `κ_{σ,d,k}`.
#[inline(always)]
const fn digit_key(dim_key: u32, k: u32) -> u32 {
    mix32(dim_key.wrapping_add(k.wrapping_mul(0x9E37_79B9)))
}

/// Random affine permutation of the digits `[0, b)` of a prime base `b`:
/// `π(a) = (α·a + β) mod b` with `α = 1 + ⌊h₁(b−1)/2³²⌋ ∈ [1, b)` and
/// `β = ⌊h₂·b/2³²⌋ ∈ [0, b)` from two hashes of `key`. For prime `b` this is a
/// bijection; `π(a)` is uniform on `[0, b)` for every `a`, and for `a ≠ a'` the pair
/// `(π(a), π(a'))` is uniform over the `b(b−1)` ordered pairs of distinct digits
/// (up to hash bias below `b/2³²`).
#[inline(always)]
const fn affine_digit(a: u32, b: u32, key: u32) -> u32 {
    let (alpha, beta) = affine_coefficients(b, key);
    (alpha * a + beta) % b
}

#[inline(always)]
const fn affine_coefficients(b: u32, key: u32) -> (u32, u32) {
    let h1 = mix32(key);
    let h2 = mix32(key ^ 0x5851_F42D);
    let alpha = 1 + ((h1 as u64 * (b - 1) as u64) >> 32) as u32;
    let beta = ((h2 as u64 * b as u64) >> 32) as u32;
    (alpha, beta)
}

/// Lane-wise [`affine_digit`] (the `mod b` by the exact invariant divisor).
#[inline(always)]
fn affine_digit_x8(a: u32x8, b: u32, div: Divisor, key: u32x8) -> u32x8 {
    let alpha = u32x8::ONE + mix32x8(key).mul_keep_high(u32x8::splat(b - 1));
    let beta = mix32x8(key ^ u32x8::splat(0x5851_F42D)).mul_keep_high(u32x8::splat(b));
    let x = alpha * a + beta;
    x - div.div_x8(x) * u32x8::splat(b)
}

/// The digit loop: `(cell, tail)` of the scrambled radical inverse of `index`;
/// `perm(a_k, k, i mod b^k)` is the digit permutation.
#[inline(always)]
fn digits(index: u32, base: &Base, mut perm: impl FnMut(u32, u32, u32) -> u32) -> (u32, u32) {
    let b = base.b;
    let (mut q, mut prefix, mut cell, mut tail) = (index, 0u32, 0u32, 0u32);
    for k in 0..base.digits {
        let qn = base.div.div(q);
        let a = q - qn * b;
        let d = perm(a, k, prefix);
        if k < base.cell_digits {
            cell = cell * b + d;
        } else {
            tail = tail * b + d;
        }
        prefix = prefix.wrapping_add(a.wrapping_mul(base.pow[k as usize]));
        q = qn;
    }
    (cell, tail)
}

#[inline(always)]
fn sample_keyed(index: u32, base: &Base, dim_key: u32) -> f32 {
    let (cell, tail) = digits(index, base, |a, k, prefix| {
        affine_digit(a, base.b, prefix ^ digit_key(dim_key, k))
    });
    base.coordinate(cell, tail)
}

/// Owen-scrambled Halton points: point `k` is
/// `(Halton::sample(k, 0, σ), …, Halton::sample(k, D−1, σ))`, bases `2, 3, 5`.
///
/// The first `b^k` points are stratified in every coordinate of base `b` (one per
/// interval of length `b^{−k}`), and the first `2^p·3^q` points in the first two
/// coordinates (one per box of size `2^{−p} × 3^{−q}`). Points do not depend on
/// `N`. The random-access functions ([`Halton::sample`], [`Halton::try_sample`],
/// [`Halton::sample_unscrambled`]) are defined on `Halton<1>`, so that
/// `Halton::sample(i, d, seed)` needs no type argument.
///
/// # The sequence
///
/// Dimension `d` of the Halton sequence is the radical inverse of the index in the
/// prime base `b = HALTON_BASES[d]`: for `i = Σ_k a_k b^k` (digits `a_k ∈ [0, b)`),
///
/// `φ_b(i) = Σ_k a_k b^{−(k+1)}`,
///
/// the digits of `i` mirrored about the radix point ([`radical_inverse`]). The first
/// `b^k` indices give one point in every interval `[c/b^k, (c+1)/b^k)`, and in two
/// dimensions with bases `2, 3` the first `2^p·3^q` points give one point in every
/// box `[u/2^p, (u+1)/2^p) × [v/3^q, (v+1)/3^q)`.
///
/// # Randomisation
///
/// Owen scrambling in base `b` (Owen 1995[^1]; for Halton, Owen 2017[^2]): digit `k`
/// of `φ_b(i)` (`k = 0` the most significant) is replaced by `π_{k, i mod b^k}(a_k)`,
/// where `π` is a random permutation of `[0, b)` that depends on the seed, the
/// dimension, the digit position `k` and the digits before it (`i mod b^k`). The
/// permutations are random affine maps `a ↦ (α·a + β) mod b` (nested random linear
/// scrambling, Matoušek 1998[^4]): each digit value is mapped uniformly and each pair
/// of distinct digits to a uniform pair of distinct digits, which is all that the
/// mean and variance of Owen-scrambled points depend on (Owen 1997[^5]), at the cost
/// of one hash per digit. The map is `affine_digit(a_k, b, key)` with
/// `key = (i mod b^k) ⊕ κ_{σ,d,k}`, `κ_{σ,d,k} = mix32(κ_{σ,d} + k·⌊2³²/φ⌋)` and
/// `κ_{σ,d}` drawn from the seed. The scramble keeps going past the digits of the
/// index (those digits are 0 but are still permuted, which fills the low digits
/// randomly) up to digit `K_b`, the first with `b^{−K_b} ≤ 2⁻³²`. A nested
/// permutation of digits keeps every stratification property above.
///
/// # Conversion to `f32`
///
/// The scrambled digits are accumulated in integers: the leading `J_b` digits
/// (`b^{J_b} ≤ 2²⁴ < b^{J_b+1}`) give a cell `c < b^{J_b}`, the remaining
/// `K_b − J_b` digits an offset `u ∈ [0, 1)` in that cell, and the coordinate is
/// `(c + u)/b^{J_b}` rounded to the nearest `f32` and then moved by one ulp if the
/// rounding left the cell. The `f32` therefore lies in the exact stratum
/// `[c'/b^k, (c'+1)/b^k)` of the scrambled digits for every `k ≤ J_b`, and is never
/// 1.0. The SIMD path runs the digit loop in `u32x8` lanes (division by `b` by a
/// multiply-high with a precomputed magic number, Granlund & Montgomery 1994[^3]) and the final `f32` rounding lane by lane, with
/// the same integer and `f64` operations as the scalar path, so both give the same
/// bits.
///
/// [^1]: A. B. Owen, *Randomly permuted (t,m,s)-nets and (t,s)-sequences*, Monte Carlo
///   and Quasi-Monte Carlo Methods in Scientific Computing, 1995.
/// [^2]: A. B. Owen, *A randomized Halton algorithm in R*, arXiv:1706.02808, 2017.
/// [^3]: T. Granlund, P. L. Montgomery, *Division by invariant integers using
///   multiplication*, PLDI 1994.
/// [^4]: J. Matoušek, *On the L2-discrepancy for anchored boxes*, J. Complexity
///   14(4), 1998.
/// [^5]: A. B. Owen, *Monte Carlo variance of scrambled net quadrature*, SIAM J.
///   Numer. Anal. 34(5), 1997.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Halton<const D: usize> {
    n: u64,
}

impl<const D: usize> Halton<D> {
    /// The first `n` points of the scrambled sequence.
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`] for `n = 0`, [`PatternError::Dims`] unless
    /// `1 ≤ D ≤ 3`, [`PatternError::TooManyPoints`] for `n > 2³²`.
    pub fn new(n: usize) -> Result<Self, PatternError> {
        check_dims::<D>(1, 3)?;
        Ok(Self {
            n: check_n(n, 1 << 32)?,
        })
    }
}

impl Halton<1> {
    /// Sample `index` of dimension `dim` of the Owen-scrambled Halton sequence for
    /// `seed`: the scrambled radical inverse in base `HALTON_BASES[dim]` (see the
    /// [`Halton`] docs), as an `f32` in `[0, 1)` (never 1.0, never NaN). Every
    /// `index` in `0..2³²` is valid.
    ///
    /// `dim` must be below [`HALTON_DIMENSIONS`] (debug builds assert); in release
    /// builds dimension `dim % HALTON_DIMENSIONS` is used. [`Halton::try_sample`]
    /// checks instead.
    #[inline]
    #[must_use]
    pub fn sample(index: u32, dim: u32, seed: Seed) -> f32 {
        debug_assert!(
            dim < HALTON_DIMENSIONS,
            "Halton::sample: dim = {dim} must be below {HALTON_DIMENSIONS}"
        );
        let dim = dim % HALTON_DIMENSIONS;
        sample_keyed(index, &BASES[dim as usize], dim_key(seed, dim))
    }

    /// [`Halton::sample`] with a checked dimension.
    ///
    /// # Errors
    /// [`PatternError::Dimension`] if `dim ≥ HALTON_DIMENSIONS`.
    pub fn try_sample(index: u32, dim: u32, seed: Seed) -> Result<f32, PatternError> {
        if dim >= HALTON_DIMENSIONS {
            return Err(PatternError::Dimension {
                dim,
                max: HALTON_DIMENSIONS,
            });
        }
        Ok(Self::sample(index, dim, seed))
    }

    /// The unscrambled radical inverse `φ_b(index)`, `b = HALTON_BASES[dim]`, as an
    /// `f32` in `[0, 1)`, converted like the scrambled samples (exact stratum of
    /// the leading digits, never 1.0); within one `f32` ulp of
    /// [`radical_inverse`]. `dim` is taken modulo [`HALTON_DIMENSIONS`].
    #[must_use]
    pub fn sample_unscrambled(index: u32, dim: u32) -> f32 {
        let base = &BASES[(dim % HALTON_DIMENSIONS) as usize];
        let (cell, tail) = digits(index, base, |a, _, _| a);
        base.coordinate(cell, tail)
    }
}

impl<const D: usize> Generate<D> for Halton<D> {
    fn n(&self) -> u64 {
        self.n
    }

    fn gen_simd<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let keys: [[u32; 32]; D] = core::array::from_fn(|j| {
            let dk = dim_key(seed, j as u32);
            core::array::from_fn(|k| digit_key(dk, k as u32))
        });
        let mut idx = u32x8::splat(first as u32) + u32x8::new([0, 1, 2, 3, 4, 5, 6, 7]);
        drive8(sink, || {
            let out = core::array::from_fn(|j| {
                let base = &BASES[j];
                let vb = u32x8::splat(base.b);
                let (mut q, mut prefix) = (idx, u32x8::ZERO);
                let (mut cell, mut tail) = (u32x8::ZERO, u32x8::ZERO);
                for k in 0..base.digits {
                    let qn = base.div.div_x8(q);
                    let a = q - qn * vb;
                    let d = affine_digit_x8(
                        a,
                        base.b,
                        base.div,
                        prefix ^ u32x8::splat(keys[j][k as usize]),
                    );
                    if k < base.cell_digits {
                        cell = cell * vb + d;
                    } else {
                        tail = tail * vb + d;
                    }
                    prefix += a * u32x8::splat(base.pow[k as usize]);
                    q = qn;
                }
                let (c, t) = (cell.to_array(), tail.to_array());
                f32x8::new(core::array::from_fn(|l| base.coordinate(c[l], t[l])))
            });
            idx += u32x8::splat(8);
            out
        });
    }

    fn gen_scalar<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let dk: [u32; D] = core::array::from_fn(|j| dim_key(seed, j as u32));
        for i in 0..sink.len() {
            let index = (first + i as u64) as u32;
            let p = core::array::from_fn(|j| sample_keyed(index, &BASES[j], dk[j]));
            sink.put(i, p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn divisor_is_exact() {
        let mut x = 1u32;
        for d in [1u32, 2, 3, 5, 7, 10, 11, 13, 47, 53, 641, 65_537, u32::MAX] {
            let div = Divisor::new(d);
            for n in [
                0u32,
                1,
                2,
                d - 1,
                d,
                d.wrapping_add(1),
                u32::MAX,
                u32::MAX - 1,
            ] {
                assert_eq!(div.div(n), n / d, "{n} / {d}");
            }
            for _ in 0..2000 {
                x = mix32(x.wrapping_add(0x9E37_79B9));
                assert_eq!(div.div(x), x / d, "{x} / {d}");
            }
            let v: [u32; 8] = core::array::from_fn(|l| mix32(l as u32 ^ d));
            let q = div.div_x8(u32x8::new(v)).to_array();
            for l in 0..8 {
                assert_eq!(q[l], v[l] / d);
            }
        }
    }

    #[test]
    fn base_constants() {
        for base in &BASES {
            let b = u64::from(base.b);
            let cells = u64::from(base.cells);
            assert_eq!(cells, b.pow(base.cell_digits));
            assert!(cells <= 1 << 24 && cells * b > 1 << 24);
            assert!(b.pow(base.digits) >= 1 << 32 && b.pow(base.digits - 1) < 1 << 32);
            for k in 0..base.digits {
                assert_eq!(u64::from(base.pow[k as usize]), b.pow(k));
            }
            let tail = b.pow(base.digits - base.cell_digits);
            assert_eq!(base.tail_scale, 4_294_967_296.0 / tail as f64);
            // The largest tail maps below 2³².
            assert!(((tail - 1) as f64 * base.tail_scale) < 4_294_967_296.0);
        }
        assert_eq!(BASES[0].cell_digits, 24);
        assert_eq!(BASES[0].digits, 32);
        assert_eq!(BASES[1].cell_digits, 15);
        assert_eq!(BASES[1].digits, 21);
    }

    #[test]
    fn unscrambled_digits_reproduce_the_radical_inverse() {
        for (d, base) in BASES.iter().enumerate() {
            for i in [0u32, 1, 2, 3, 7, 100, 12_345, 1 << 31, u32::MAX] {
                let x = Halton::sample_unscrambled(i, d as u32);
                let r = radical_inverse(base.b, i);
                assert!((0.0..1.0).contains(&x));
                assert!(
                    (f64::from(x) - r).abs() <= 1.0 / 16_777_216.0,
                    "d {d} i {i}"
                );
            }
        }
    }

    #[test]
    fn affine_digits_are_pairwise_uniform() {
        // Over keys, (π(0), π(1)) is uniform over the b(b−1) ordered pairs of
        // distinct digits: chi-square below its 99.99% quantile.
        for b in [2u32, 3, 5, 7, 13, 53] {
            let mut h = [0u32; 53 * 53];
            let n = 60_000u32;
            for key in 0..n {
                let key = key.wrapping_mul(0x2545_F491);
                let (x, y) = (affine_digit(0, b, key), affine_digit(1, b, key));
                assert_ne!(x, y);
                h[(x * b + y) as usize] += 1;
            }
            let e = f64::from(n) / f64::from(b * (b - 1));
            let chi: f64 = (0..b * b)
                .filter(|c| c / b != c % b)
                .map(|c| (f64::from(h[c as usize]) - e).powi(2) / e)
                .sum();
            let df = f64::from((b * (b - 1)).max(2) - 1);
            let q = df
                * (1.0 - 2.0 / (9.0 * df) + 3.72 * crate::num::scalar::sqrt(2.0 / (9.0 * df)))
                    .powi(3);
            assert!(chi < q + 1e-9 || b == 2, "b {b}: chi2 {chi} ≥ {q}");
            if b == 2 {
                assert!((f64::from(h[1]) - e).abs() < 4.0 * e.sqrt());
            }
        }
    }

    #[test]
    fn scramble_permutes_each_digit() {
        // With a nested permutation, indices that differ only in digit k differ
        // in scrambled digit k and agree in digits 0..k.
        let base = &BASES[1];
        let dk = dim_key(Seed(5), 1);
        let scr = |i| digits(i, base, |a, k, p| affine_digit(a, 3, p ^ digit_key(dk, k)));
        for i in [0u32, 1, 5, 17, 100] {
            for k in 0..5u32 {
                let step = 3u32.pow(k);
                let a = (i / step) % 3;
                let j = i - a * step + ((a + 1) % 3) * step;
                let (ci, _) = scr(i);
                let (cj, _) = scr(j);
                let shift = 3u32.pow(base.cell_digits - 1 - k);
                assert_eq!(ci / shift / 3, cj / shift / 3, "prefix differs");
                assert_ne!(ci / shift % 3, cj / shift % 3, "digit {k} equal");
            }
        }
    }
}
