//! Owen-scrambled Halton points: [`Halton`], its random-access functions and
//! [`radical_inverse`]. The construction is documented on [`Halton`].

use super::sealed::{Generate, Sink};
use super::{array, check_dims, check_n, drive8};
use crate::error::PatternError;
use crate::num::lane::{Lane, U32x8Lane};
use crate::rng::{mix32, mix32_lanes, Seed};
use wide::{f32x8, f64x4, u32x8, u64x4};

/// Number of Halton dimensions available to [`Halton::sample`].
pub const HALTON_DIMENSIONS: u32 = 1024;

/// The first 1024 primes (2, 3, 5, …, 8161): the base of each Halton dimension,
/// computed at compile time by trial division.
pub const HALTON_BASES: [u32; HALTON_DIMENSIONS as usize] = first_primes();

const fn first_primes() -> [u32; HALTON_DIMENSIONS as usize] {
    let mut out = [0u32; HALTON_DIMENSIONS as usize];
    let (mut n, mut c) = (0, 2u32);
    while n < out.len() {
        let mut k = 0;
        let mut prime = true;
        // Trial division by the primes found so far, up to √c.
        while k < n && out[k] * out[k] <= c {
            if c % out[k] == 0 {
                prime = false;
                break;
            }
            k += 1;
        }
        if prime {
            out[n] = c;
            n += 1;
        }
        c += 1;
    }
    out
}

/// Dimensions whose per-base constants are tabulated ([`BASES`]); higher
/// dimensions build theirs per call ([`Base::new`], `O(K_b)` with `K_b ≤ 3` for
/// their bases above 1625).
const NDIM: usize = 16;

/// The largest base whose digit permutation is affine (the first 16 bases);
/// larger bases use a hashed uniform permutation (see [`affine_digit`]).
const AFFINE_MAX_BASE: u32 = 53;

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
    /// `b^{K−J}` as an `f64` (exact): weight of the cell in the full digit integer.
    tail_pow: f64,
    /// `fl(1/b^K)`.
    inv_total: f64,
    /// `b^k mod 2³²` for `k < K` (exact: `b^{K−1} < 2³²`).
    pow: [u32; 32],
    /// `⌈2²⁰/b⌉`: `⌊x/b⌋ = ⌊x·small/2²⁰⌋` for `x < b²` (see [`small_mod`]).
    small: u32,
    div: Divisor,
}

impl Base {
    const fn new(b: u32) -> Self {
        // `b < 2¹⁶`: every product below stays within its integer type.
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
            tail_pow: tail as f64,
            inv_total: 1.0 / (cells as f64 * tail as f64),
            pow,
            small: (1u32 << 20).div_ceil(b),
            div: Divisor::new(b),
        }
    }

    /// The coordinate from the cell digits `cell` and the tail digits `tail`: see
    /// "Conversion to `f32`" in the [`Halton`] docs. [`Base::coordinate_x8`] is the
    /// same sequence of `f64` operations lane by lane.
    #[inline(always)]
    fn coordinate(&self, cell: u32, tail: u32) -> f32 {
        let c = f64::from(cell);
        let x = (c * self.tail_pow + f64::from(tail)) * self.inv_total;
        let p = x * VELTKAMP;
        let hi = p - (p - x);
        let t = hi * f64::from(self.cells);
        let bits = (hi as f32).to_bits();
        let bits = if t >= c + 1.0 {
            bits - 1
        } else if t < c {
            bits + 1
        } else {
            bits
        };
        f32::from_bits(bits)
    }

    /// Lane-wise [`Base::coordinate`]: the even and odd lanes go through `f64x4`
    /// (`u32 → f64` by the exponent-bias trick, `f64 → f32` by moving the exponent
    /// and mantissa bits of the already 24-bit `hi`).
    #[inline(always)]
    fn coordinate_x8(&self, cell: u32x8, tail: u32x8) -> f32x8 {
        let (ce, co) = split_f64(cell);
        let (te, to) = split_f64(tail);
        let e = self.coordinate_x4(ce, te);
        let o = self.coordinate_x4(co, to);
        bytemuck::cast(e | (o << 32))
    }

    /// `f32` bits (in the low half of each `u64`) of [`Base::coordinate`].
    #[inline(always)]
    fn coordinate_x4(&self, c: f64x4, tail: f64x4) -> u64x4 {
        let x = (c * f64x4::splat(self.tail_pow) + tail) * f64x4::splat(self.inv_total);
        let p = x * f64x4::splat(VELTKAMP);
        let hi = p - (p - x);
        let t = hi * f64x4::splat(f64::from(self.cells));
        let up: u64x4 = bytemuck::cast(t.simd_ge(c + f64x4::ONE));
        let down: u64x4 = bytemuck::cast(t.simd_lt(c));
        let hb: u64x4 = bytemuck::cast(hi);
        let zero = hb.simd_eq(u64x4::ZERO);
        // f64 → f32 bits of a 24-bit normal value: exponent bias 1023 → 127.
        let bits = ((hb >> 29) - u64x4::splat(896 << 23)) & !zero;
        // `up`/`down` are all ones (−1) where set.
        (bits + up - down) & u64x4::splat(0xFFFF_FFFF)
    }
}

/// `2²⁹ + 1`: Veltkamp's splitting constant that rounds an `f64` to its leading
/// 24 significant bits, `hi = p − (p − x)` with `p = x·(2²⁹ + 1)` (Dekker 1971).
const VELTKAMP: f64 = 536_870_913.0;

/// Even and odd lanes of `v` as exact `f64`s: `(bits | 2⁵²) − 2⁵²` (the bits of
/// `2⁵² + v` are those of `2⁵²` with `v` in the low mantissa).
#[inline(always)]
fn split_f64(v: u32x8) -> (f64x4, f64x4) {
    let w: u64x4 = bytemuck::cast(v);
    let magic = u64x4::splat(0x4330_0000_0000_0000);
    let two52 = f64x4::splat(4_503_599_627_370_496.0);
    let e: f64x4 = bytemuck::cast((w & u64x4::splat(0xFFFF_FFFF)) | magic);
    let o: f64x4 = bytemuck::cast((w >> 32) | magic);
    (e - two52, o - two52)
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

/// The constants of dimension `dim < HALTON_DIMENSIONS`: tabulated below
/// [`NDIM`], built per call above.
#[inline(always)]
fn base_of(dim: u32) -> Base {
    match BASES.get(dim as usize) {
        Some(b) => *b,
        None => Base::new(HALTON_BASES[dim as usize]),
    }
}

/// Panics unless `dim < HALTON_DIMENSIONS`, in every build.
#[inline(always)]
#[track_caller]
fn assert_dim(dim: u32) {
    super::assert_sequence_dim("Halton", dim, HALTON_DIMENSIONS);
}

/// Base constants as an associated constant, for kernels monomorphised per base.
struct BaseOf<const B: u32>;

impl<const B: u32> BaseOf<B> {
    const BASE: Base = Base::new(B);
}

/// Seed purpose of the digit permutations of dimension `d` (plus `d`).
const PURPOSE: u64 = 0x4841_4C54_0000_0000;

/// Multiplier of the per-digit hash [`digit_hash`] (odd, so the map is a bijection).
const DIGIT_MUL: u32 = 0x7FEB_352D;

/// The keys of one dimension: `κ_{σ,d}` and, per digit position `k`, the
/// xorshifted digit key `μ_k = κ_{σ,d,k} ⊕ (κ_{σ,d,k} ≫ 16)`.
#[derive(Clone, Copy, Debug)]
struct DimKeys {
    dim: u32,
    digit: [u32; 32],
}

impl DimKeys {
    fn new(seed: Seed, dim: u32) -> Self {
        let (dim, lambda) = dim_key(seed, dim);
        Self {
            dim,
            digit: core::array::from_fn(|k| digit_mu(lambda, k as u32)),
        }
    }
}

/// `(κ_{σ,d}, λ_{σ,d})`: the low and high halves of the seed stream of dimension
/// `d`. `κ` keys the prefix hash, `λ` the digit keys; two independent keys, so
/// that no `G(p)` equals a digit key by construction (with one key,
/// `G(0) = mix32(κ) = κ_{σ,d,0}` would cancel and fix digit 0 of every point).
#[inline(always)]
const fn dim_key(seed: Seed, dim: u32) -> (u32, u32) {
    let s = seed.stream(PURPOSE + dim as u64);
    (s as u32, (s >> 32) as u32)
}

/// `κ_{σ,d,k} = mix32(λ_{σ,d} + k·⌊2³²/φ⌋)`.
#[inline(always)]
const fn digit_key(lambda: u32, k: u32) -> u32 {
    mix32(lambda.wrapping_add(k.wrapping_mul(0x9E37_79B9)))
}

/// First level of the digit hash: `G(p) = mix32(p ⊕ κ_{σ,d})`, returned
/// xorshifted (`G ⊕ (G ≫ 16)`), the form [`digit_hash`] consumes.
#[inline(always)]
const fn prefix_hash(prefix: u32, dim_key: u32) -> u32 {
    let g = mix32(prefix ^ dim_key);
    g ^ (g >> 16)
}

/// Second level: `h = ((G ⊕ κ_k) ⊕ ((G ⊕ κ_k) ≫ 16))·M mod 2³²`, from the
/// xorshifted `y = G ⊕ (G ≫ 16)` and `μ_k = κ_k ⊕ (κ_k ≫ 16)` (the xorshift is
/// linear over XOR, so `y ⊕ μ_k` is the xorshift of `G ⊕ κ_k`).
#[inline(always)]
const fn digit_hash(y: u32, mu: u32) -> u32 {
    (y ^ mu).wrapping_mul(DIGIT_MUL)
}

/// `x mod b` for `x < b²`, `b ≤ 53`: `⌊x/b⌋ = ⌊x·⌈2²⁰/b⌉/2²⁰⌋` (the error
/// `x·(⌈2²⁰/b⌉ − 2²⁰/b)/2²⁰ < b²/2²⁰` is below the gap `1/b` to the next integer
/// because `b³ < 2²⁰`).
#[inline(always)]
const fn small_mod(x: u32, b: u32, small: u32) -> u32 {
    x - ((x * small) >> 20) * b
}

/// The affine digit permutation `π(a) = (α·a + β) mod b` of hash `h`, with
/// `t = ⌊h/2⁸⌋`, `α = 1 + ⌊t(b−1)/2²⁴⌋ ∈ [1, b)`, `r = t(b−1) mod 2²⁴` and
/// `β = ⌊r·b/2²⁴⌋ ∈ [0, b)`: one hash gives both, `α` from the integer part and
/// `β` from the fractional part of `t(b−1)/2²⁴`.
///
/// For bases above 53 (dimensions 16 and up) the permutation is instead the
/// pseudo-random permutation of `[0, b)` keyed by `h` ([`crate::hash::permute`],
/// a cycle-walking Feistel network): Owen's nested *uniform* scramble. An
/// affine map there leaves the linear structure `(α₁i + β₁) mod b₁`,
/// `(α₂i + β₂) mod b₂` between the first digits of neighbouring dimensions,
/// whose bases are close; at `N = 4096` it correlated dimensions 56 and 57
/// (bases 269 and 271) at `r = 0.084`, 5.4 standard errors (measured).
#[inline(always)]
fn affine_digit(a: u32, b: u32, small: u32, h: u32) -> u32 {
    if b > AFFINE_MAX_BASE {
        return crate::hash::permute(a, b, h);
    }
    let x = (h >> 8) * (b - 1);
    let alpha = 1 + (x >> 24);
    let beta = ((x & 0xFF_FFFF) * b) >> 24;
    small_mod(alpha * a + beta, b, small)
}

/// Lane-wise [`affine_digit`], in the lanes `U` of one instruction-set level.
#[inline(always)]
fn affine_digit_x8<U: U32x8Lane, const B: u32>(a: U, h: U) -> U {
    if B == 2 {
        return a ^ (h >> 31);
    }
    let x = (h >> 8) * U::splat(B - 1);
    let alpha = U::splat(1) + (x >> 24);
    let beta = ((x & U::splat(0xFF_FFFF)) * U::splat(B)) >> 24;
    let y = alpha * a + beta;
    y - ((y * U::splat(BaseOf::<B>::BASE.small)) >> 20) * U::splat(B)
}

/// `π(0) = β` of [`affine_digit`] (the digit of an index past its last digit).
#[inline(always)]
fn beta_x8<U: U32x8Lane, const B: u32>(h: U) -> U {
    if B == 2 {
        return h >> 31;
    }
    let x = (h >> 8) * U::splat(B - 1);
    ((x & U::splat(0xFF_FFFF)) * U::splat(B)) >> 24
}

/// The plain digit loop: `(cell, tail)` of the radical inverse of `index` with
/// digit `k` replaced by `perm(a_k, k, i mod b^k)`.
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

/// The scrambled digit `π_{k, prefix}(a)`; `mu(k)` = `μ_k` of the dimension.
#[inline(always)]
fn scrambled_digit(a: u32, prefix: u32, base: &Base, dim: u32, mu: u32) -> u32 {
    affine_digit(
        a,
        base.b,
        base.small,
        digit_hash(prefix_hash(prefix, dim), mu),
    )
}

/// `μ_k = κ_{σ,d,k} ⊕ (κ_{σ,d,k} ≫ 16)` from `λ_{σ,d}`.
#[inline(always)]
const fn digit_mu(lambda: u32, k: u32) -> u32 {
    let kk = digit_key(lambda, k);
    kk ^ (kk >> 16)
}

/// `(cell, tail)` of the scrambled radical inverse: [`digits`] with
/// [`scrambled_digit`], except that once the index has no digits left (the prefix
/// is the index itself from there on) `G(index)` is computed once.
#[inline(always)]
fn scrambled_digits(index: u32, base: &Base, dim: u32, mu: impl Fn(u32) -> u32) -> (u32, u32) {
    let b = base.b;
    let (mut q, mut prefix) = (index, 0u32);
    // Digits of the index: `k < nd`.
    let nd = digit_count(index, base);
    let (mut cell, mut tail) = (0u32, 0u32);
    fold_scalar(b, base.cell_digits, 0, nd, &mut cell, &mut tail, |k| {
        let qn = base.div.div(q);
        let a = q - qn * b;
        let d = scrambled_digit(a, prefix, base, dim, mu(k));
        prefix = prefix.wrapping_add(a.wrapping_mul(base.pow[k as usize]));
        q = qn;
        d
    });
    let y = prefix_hash(index, dim);
    fold_scalar(
        b,
        base.cell_digits,
        nd,
        base.digits,
        &mut cell,
        &mut tail,
        |k| affine_digit(0, b, base.small, digit_hash(y, mu(k))),
    );
    (cell, tail)
}

/// Scalar [`fold_digits`]: `digit(k)` for `k ∈ [lo, hi)` into `cell` (`k < j`)
/// and `tail` (`k ≥ j`) in base `b`, one loop per accumulator.
#[inline(always)]
fn fold_scalar(
    b: u32,
    j: u32,
    lo: u32,
    hi: u32,
    cell: &mut u32,
    tail: &mut u32,
    mut digit: impl FnMut(u32) -> u32,
) {
    let mut c = *cell;
    for k in lo..hi.min(j) {
        c = c * b + digit(k);
    }
    *cell = c;
    let mut t = *tail;
    for k in lo.max(j)..hi {
        t = t * b + digit(k);
    }
    *tail = t;
}

#[inline(always)]
fn sample_keyed(index: u32, base: &Base, dim: u32, mu: impl Fn(u32) -> u32) -> f32 {
    let (cell, tail) = scrambled_digits(index, base, dim, mu);
    base.coordinate(cell, tail)
}

/// Capacity of [`Lead::t`]: `b^{K₀} + 7 ≤ LEAD_CAP`.
const LEAD_CAP: usize = 640;

/// The leading `K₀` scrambled digits of every residue `r < M = b^{K₀}`, for the
/// SIMD path: digits `k < K₀` of index `i` and their prefixes `i mod b^k` depend
/// only on `i mod M`, so `t[r] = Σ_{k<K₀} π_{k, r mod b^k}(a_k(r))·b^{K₀−1−k}` is
/// the digit accumulator after `K₀` digits. `t[M + j] = t[j]` for `j < 7`, so that
/// 8 consecutive indices read 8 consecutive entries. A cache: the values are those
/// of the digit loop, built per fill from `Σ_{k<K₀} b^k` hashes.
struct Lead {
    k0: u32,
    div: Divisor,
    m: u32,
    t: [u32; LEAD_CAP],
}

impl Lead {
    /// The table for base `base` with the largest `K₀` such that
    /// `b^{K₀} ≤ max(8, min(n/16, LEAD_CAP − 8))` (at least 8 entries, at most a
    /// sixteenth of the points).
    fn new(base: &Base, keys: &DimKeys, n: usize) -> Self {
        let b = base.b;
        let cap = (n / 16).clamp(8, LEAD_CAP - 8) as u32;
        let mut k0 = 0;
        while base.pow[k0 as usize + 1] <= cap || base.pow[k0 as usize] < 8 {
            k0 += 1;
        }
        let m = base.pow[k0 as usize];
        let mut t = [0u32; LEAD_CAP];
        for k in 0..k0 {
            let pk = base.pow[k as usize];
            let mu = keys.digit[k as usize];
            for r in 0..pk {
                let h = digit_hash(prefix_hash(r, keys.dim), mu);
                let v = t[r as usize];
                for a in (0..b).rev() {
                    t[(r + a * pk) as usize] = v * b + affine_digit(a, b, base.small, h);
                }
            }
        }
        for j in 0..7 {
            t[(m + j) as usize] = t[j as usize];
        }
        Self {
            k0,
            div: Divisor::new(m),
            m,
            t,
        }
    }
}

/// One coordinate of the 8 consecutive indices `s0 + l` in base `B`, `nd` = number
/// of base-`B` digits of the largest of them. Digits `k < K₀` come from the
/// [`Lead`] table; the full digit step runs for `K₀ ≤ k < nd` (for a lane whose
/// index has ended it computes the same `h(i, k)` as the deep step); the deep step
/// (`a_k = 0`, prefix = index, shared `G(index)`) after.
///
/// Digits and prefixes for `k ≥ K₀`: in base 2 by shifts and masks; otherwise from
/// the digits `A_k` and residues `R_k = s0 mod b^k` of `s0` (scalar) and the carry
/// `c = [R_k + l ≥ b^k]` (one at most, as `b^k ≥ 8`): prefix `R_k + l − c·b^k`,
/// digit `(A_k + c) mod b`.
#[inline(always)]
fn coord_x8<U: U32x8Lane, const B: u32>(s0: u32, nd: u32, keys: &DimKeys, lead: &Lead) -> U::F {
    let base = &BaseOf::<B>::BASE;
    let vb = U::splat(B);
    let kd = U::splat(keys.dim);
    let lanes = U::from_array([0, 1, 2, 3, 4, 5, 6, 7]);
    let idx = U::splat(s0) + lanes;
    let q0 = lead.div.div(s0);
    let r0 = s0 - q0 * lead.m;
    let t: [u32; 8] = lead.t[r0 as usize..r0 as usize + 8].try_into().unwrap();
    let (mut cell, mut tail) = (U::from_array(t), U::splat(0));
    let nd = nd.min(base.digits);
    let k0 = lead.k0;
    let dm = U::splat(DIGIT_MUL);
    if B == 2 {
        fold_digits!(B, U, k0, nd, cell, tail, |k| {
            let prefix = idx & U::splat((1u32 << k) - 1);
            let a = (idx >> k) & U::splat(1);
            let g = mix32_lanes(prefix ^ kd);
            let h = ((g ^ (g >> 16)) ^ U::splat(keys.digit[k as usize])) * dm;
            affine_digit_x8::<U, B>(a, h)
        });
    } else {
        let (mut q, mut r) = (q0, r0);
        fold_digits!(B, U, k0, nd, cell, tail, |k| {
            let qn = q / B;
            let ak = q - qn * B;
            let pk = base.pow[k as usize];
            let x = U::splat(r) + lanes;
            let vp = U::splat(pk);
            let c = x.ge(vp);
            let prefix = x - (c & vp);
            let a = U::splat(ak) - c;
            let a = a & a.ne(vb);
            let g = mix32_lanes(prefix ^ kd);
            let h = ((g ^ (g >> 16)) ^ U::splat(keys.digit[k as usize])) * dm;
            r = r.wrapping_add(ak.wrapping_mul(pk));
            q = qn;
            affine_digit_x8::<U, B>(a, h)
        });
    }
    let g = mix32_lanes(idx ^ kd);
    let y = g ^ (g >> 16);
    fold_digits!(B, U, nd.max(k0), base.digits, cell, tail, |k| {
        beta_x8::<U, B>((y ^ U::splat(keys.digit[k as usize])) * dm)
    });
    // The conversion in `wide`'s `f64x4` at every level (once per coordinate,
    // against ~20 hashed digits).
    let v = base.coordinate_x8(u32x8::new(cell.to_array()), u32x8::new(tail.to_array()));
    <U::F as Lane>::load(&v.to_array())
}

/// Folds `digit(k)` for `k ∈ [lo, hi)` into the base-`B` accumulators `cell`
/// (for `k < J_B`) and `tail` (after), lanes `U`. Two loops rather than one
/// with a per-digit choice, so that each accumulator stays in a register (a
/// per-digit choice compiled to a store and reload of whichever one was
/// chosen, a latency chain through memory on every digit). A macro, so that
/// the digit expression compiles in place in the dispatched AVX2 copy (see
/// `pattern::drive8!`); the expression is written out in both loops and runs
/// once per `k`, in order.
macro_rules! fold_digits {
    ($B:expr, $U:ty, $lo:expr, $hi:expr, $cell:ident, $tail:ident, |$k:ident| $digit:expr) => {{
        let j = BaseOf::<$B>::BASE.cell_digits;
        let vb = <$U>::splat($B);
        let (lo, hi): (u32, u32) = ($lo, $hi);
        for $k in lo..hi.min(j) {
            $cell = $cell * vb + $digit;
        }
        for $k in lo.max(j)..hi {
            $tail = $tail * vb + $digit;
        }
    }};
}
use fold_digits;

/// Number of base-`b` digits of `i` (0 for `i = 0`).
#[inline(always)]
fn digit_count(i: u32, base: &Base) -> u32 {
    let mut n = 0;
    while n < base.digits && base.pow[n as usize] <= i {
        n += 1;
    }
    n
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
/// dimension, the digit position `k` and the digits before it (`p = i mod b^k`).
/// The scramble keeps going past the digits of the index (those digits are 0 but
/// are still permuted, which fills the low digits randomly) up to digit `K_b`, the
/// first with `b^{−K_b} ≤ 2⁻³²`. A nested permutation of digits keeps every
/// stratification property above.
///
/// **Permutations.** `π_{k,p}(a) = (α·a + β) mod b`, a random affine map (nested
/// random linear scrambling, Matoušek 1998[^4]): for prime `b` each digit value is
/// mapped uniformly and each pair of distinct digits to a uniform pair of distinct
/// digits, which is all that the mean and variance of Owen-scrambled points depend
/// on (Owen 1997[^5]). Both coefficients come from one 32-bit hash `h`: with
/// `t = ⌊h/2⁸⌋`, `α = 1 + ⌊t(b−1)/2²⁴⌋ ∈ [1, b)` is the integer part and
/// `β = ⌊r·b/2²⁴⌋`, `r = t(b−1) mod 2²⁴`, the scaled fractional part of
/// `t(b−1)/2²⁴`; for uniform `h`, `(α, β)` is uniform on `[1, b) × [0, b)` up to a
/// bias below `b²/2²⁴` (below `1.5·10⁻⁶` for `b ≤ 5`, `1.7·10⁻⁴` for the last
/// sequence base `b = 53`). In base 2, `α = 1` and the
/// map is `a ⊕ (top bit of h)`. (Taking both coefficients from one hash is ours.)
///
/// **Hash.** `h(p, k) = C(G(p) ⊕ κ_{σ,d,k})` with the two levels
///
/// * `G(p) = mix32(p ⊕ κ_{σ,d})` (MurmurHash3's finaliser, Appleby 2011[^6]), per
///   prefix, and
/// * `C(x) = (x ⊕ (x ≫ 16))·M mod 2³²`, `M = 0x7FEB352D` (a multiplier from
///   Wellons' hash search[^7]), per digit,
///
/// `κ_{σ,d}` and `λ_{σ,d}` the two halves of a 64-bit seed stream of dimension `d`
/// and `κ_{σ,d,k} = mix32(λ_{σ,d} + k·⌊2³²/φ⌋)` (with a single key,
/// `κ_{σ,d,0} = mix32(κ_{σ,d}) = G(0)` would cancel).
/// The coefficients use the high bits of the product, which depend on every bit
/// of `G(p) ⊕ κ_{σ,d,k}`. The same `h` is used for every digit; the split only
/// makes the digits past the end of the index cheap: there `a_k = 0` and the
/// prefix is `i` itself, so all of them share one `G(i)` and cost one multiply
/// each (the two-level split is ours). This matters for correctness as much as for
/// speed: `i` and `i + b^k` share the prefix at position `k` whether or not `i`
/// ends before it, and must see the same `π_{k,i}`.
///
/// # Conversion to `f32`
///
/// The scrambled digits are accumulated in integers: the leading `J_b` digits
/// (`b^{J_b} ≤ 2²⁴ < b^{J_b+1}`) give a cell `c < m = b^{J_b}` and the remaining
/// `K_b − J_b` digits an integer `T < b^{K_b−J_b}`, so that the scrambled value is
/// `V/b^{K_b}` with `V = c·b^{K_b−J_b} + T` (exact in `f64`). Then, in `f64`:
/// `x = V·fl(b^{−K_b})`, rounded to 24 significant bits by Veltkamp's split
/// (`p = x·(2²⁹+1)`, `x̂ = p − (p − x)`, Dekker 1971[^8]), which is an `f32`;
/// `x̂·m` is exact in `f64`, and if `x̂·m ≥ c + 1` (or `< c`) the `f32` is moved
/// down (up) by one ulp. The `f32` therefore lies in the exact stratum
/// `[c'/b^k, (c'+1)/b^k)` of the scrambled digits for every `k ≤ J_b`, and is never
/// 1.0.
///
/// # Paths
///
/// The scalar path and [`Halton::sample`] run the digit loop per index (division
/// by `b` by a multiply-high with a precomputed magic number, Granlund & Montgomery
/// 1994[^3]) and switch to the shared-`G(i)` loop once the index has no digits left.
/// The SIMD path runs 8 consecutive indices in `u32x8` lanes and computes the same
/// digits by other means, all exact:
///
/// * the leading `K₀` scrambled digits (`b^{K₀}` between 8 and 632, at most
///   `N/16`, chosen per fill) depend only on `i mod b^{K₀}`; they are tabulated once
///   per fill and read as 8 consecutive table entries;
/// * digits `K₀ ≤ k < n` (`n` = digit count of the largest of the 8 indices) take
///   the full step: in base 2 prefix and digit are a mask and a shift; in bases 3
///   and 5 they follow from the digits and residues of the first index of the 8
///   (scalar) and a carry of at most one (`b^k ≥ 8`); a lane whose index has
///   ended gets `a_k = 0` and prefix `i`, the same `h(i, k)` as below;
/// * digits `k ≥ max(n, K₀)` take the shared-`G(i)` step.
///
/// The conversion runs in `f64x4` with the same operations. All three give the
/// same bits.
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
/// [^6]: A. Appleby, *MurmurHash3*, 2011.
/// [^7]: C. Wellons, *Prospecting for hash functions*, 2018 (`lowbias32`).
/// [^8]: T. J. Dekker, *A floating-point technique for extending the available
///   precision*, Numer. Math. 18, 1971.
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
    /// # Panics
    /// If `dim ≥ HALTON_DIMENSIONS` (1024), in debug and release builds alike.
    /// [`Halton::try_sample`] returns an error instead.
    #[inline]
    #[must_use]
    #[track_caller]
    pub fn sample(index: u32, dim: u32, seed: Seed) -> f32 {
        assert_dim(dim);
        let (dk, lambda) = dim_key(seed, dim);
        sample_keyed(index, &base_of(dim), dk, |k| digit_mu(lambda, k))
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
    /// [`radical_inverse`].
    ///
    /// # Panics
    /// If `dim ≥ HALTON_DIMENSIONS`, in every build.
    #[must_use]
    #[track_caller]
    pub fn sample_unscrambled(index: u32, dim: u32) -> f32 {
        assert_dim(dim);
        let base = &base_of(dim);
        let (cell, tail) = digits(index, base, |a, _, _| a);
        base.coordinate(cell, tail)
    }
}

impl<const D: usize> Generate<D> for Halton<D> {
    fn n(&self) -> u64 {
        self.n
    }

    #[inline(always)]
    fn gen_simd<I: crate::simd::Isa, S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let keys: [DimKeys; D] = core::array::from_fn(|j| DimKeys::new(seed, j as u32));
        let n = sink.len();
        let leads: [Lead; D] = core::array::from_fn(|j| Lead::new(&BASES[j], &keys[j], n));
        let mut start = first;
        drive8!(sink, I::U32, {
            // Lanes past 2³² − 1 are past `N` and discarded.
            let last = (start + 7).min(u64::from(u32::MAX)) as u32;
            let s0 = start as u32;
            let out: [I::F32; D] = array!(I::F32::splat(0.0), |j| match j {
                0 => coord_x8::<I::U32, 2>(s0, 32 - last.leading_zeros(), &keys[0], &leads[0]),
                1 => coord_x8::<I::U32, 3>(
                    s0,
                    digit_count(last, &BaseOf::<3>::BASE),
                    &keys[1],
                    &leads[1],
                ),
                _ => coord_x8::<I::U32, 5>(
                    s0,
                    digit_count(last, &BaseOf::<5>::BASE),
                    &keys[2],
                    &leads[2],
                ),
            });
            start += 8;
            out
        });
    }

    fn gen_scalar<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let keys: [DimKeys; D] = core::array::from_fn(|j| DimKeys::new(seed, j as u32));
        for i in 0..sink.len() {
            let index = (first + i as u64) as u32;
            let p = core::array::from_fn(|j| {
                let kj = &keys[j];
                sample_keyed(index, &BASES[j], kj.dim, |k| kj.digit[k as usize])
            });
            sink.put(i, p);
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::pattern::Pattern;
    use crate::stats::chi2_limit;
    use std::{vec, vec::Vec};

    fn chi2(h: &[u32], e: f64) -> f64 {
        h.iter().map(|&c| (f64::from(c) - e).powi(2) / e).sum()
    }

    /// The definition, digit by digit, with no early exit: `h(p, k)` for every `k`.
    fn reference(index: u32, dim: u32, seed: Seed) -> f32 {
        let base = &base_of(dim);
        let (dk, lambda) = dim_key(seed, dim);
        let (c, t) = digits(index, base, |a, k, p| {
            let g = mix32(p ^ dk);
            let x = g ^ digit_key(lambda, k);
            let h = (x ^ (x >> 16)).wrapping_mul(DIGIT_MUL);
            if base.b > AFFINE_MAX_BASE {
                return crate::hash::permute(a, base.b, h);
            }
            let tt = (h >> 8) * (base.b - 1);
            let alpha = 1 + (tt >> 24);
            let beta = ((tt & 0xFF_FFFF) * base.b) >> 24;
            (alpha * a + beta) % base.b
        });
        base.coordinate(c, t)
    }

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
        }
    }

    #[test]
    fn small_mod_is_exact() {
        for base in &BASES {
            for x in 0..base.b * base.b {
                assert_eq!(
                    small_mod(x, base.b, base.small),
                    x % base.b,
                    "{x} mod {}",
                    base.b
                );
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
            assert_eq!(base.tail_pow, tail as f64);
            // t(b−1) and r·b fit in 32 bits.
            assert!((1u64 << 24) * (b - 1) <= 1 << 32 && (1u64 << 24) * b <= 1 << 32);
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
    fn coordinate_x8_matches_scalar_and_is_in_its_stratum() {
        let mut x = 7u32;
        for base in &BASES {
            let tmax = base.tail_pow as u32 - 1;
            let mut cases = vec![(0, 0), (0, 1), (0, tmax), (1, 0), (base.cells - 1, tmax)];
            cases.extend([
                (base.cells - 1, 0),
                (base.cells / 2, tmax),
                (base.cells / 3, 0),
            ]);
            for _ in 0..4000 {
                x = mix32(x.wrapping_add(0x9E37_79B9));
                let y = mix32(x ^ 0x55);
                cases.push((x % base.cells, y % (tmax + 1)));
            }
            for ch in cases.chunks(8) {
                let c: [u32; 8] = core::array::from_fn(|l| ch[l % ch.len()].0);
                let t: [u32; 8] = core::array::from_fn(|l| ch[l % ch.len()].1);
                let v = base.coordinate_x8(u32x8::new(c), u32x8::new(t)).to_array();
                for l in 0..8 {
                    let s = base.coordinate(c[l], t[l]);
                    assert_eq!(
                        v[l].to_bits(),
                        s.to_bits(),
                        "b {} c {} t {}",
                        base.b,
                        c[l],
                        t[l]
                    );
                    assert!((0.0..1.0).contains(&s));
                    let cm = f64::from(s) * f64::from(base.cells);
                    assert!(cm >= f64::from(c[l]) && cm < f64::from(c[l]) + 1.0);
                    let exact =
                        (f64::from(c[l]) * base.tail_pow + f64::from(t[l])) * base.inv_total;
                    assert!((f64::from(s) - exact).abs() <= exact * 1.2e-7 + 1e-300);
                }
            }
        }
    }

    #[test]
    fn affine_digits_are_pairwise_uniform() {
        // Over hashes, (π(0), π(1)) is uniform over the b(b−1) ordered pairs of
        // distinct digits and (π(1), π(b−1)) likewise: chi-square below its 1 − 10⁻⁶
        // quantile (false alarm ≤ 10⁻⁶ per check).
        for base in BASES.iter().take(8) {
            let b = base.b;
            for (u, w) in [(0, 1), (1, b - 1)] {
                if u == w {
                    continue;
                }
                let mut h = [0u32; 53 * 53];
                let n = 400 * b * (b - 1);
                for key in 0..n {
                    let hh = mix32(key.wrapping_mul(0x2545_F491));
                    let (x, y) = (
                        affine_digit(u, b, base.small, hh),
                        affine_digit(w, b, base.small, hh),
                    );
                    assert_ne!(x, y);
                    h[(x * b + y) as usize] += 1;
                }
                let e = f64::from(n) / f64::from(b * (b - 1));
                let cells: Vec<u32> = (0..b * b)
                    .filter(|c| c / b != c % b)
                    .map(|c| h[c as usize])
                    .collect();
                let chi = chi2(&cells, e);
                let df = f64::from((b * (b - 1)).max(2) - 1);
                if b == 2 {
                    assert!(
                        (f64::from(h[1]) - e).abs() < 3.9 * e.sqrt(),
                        "b 2: {}",
                        h[1]
                    );
                } else {
                    assert!(chi < chi2_limit(df), "b {b}: chi2 {chi}");
                }
            }
        }
    }

    #[test]
    fn early_exit_matches_the_full_digit_loop() {
        // The shared-G(i) loop for digits past the index must compute the same
        // h(p, k) as the full step (else i and i + b^k would see different π).
        let seed = Seed(11);
        let mut x = 3u32;
        for dim in 0..HALTON_DIMENSIONS {
            for i in (0..300u32).chain([u32::MAX, u32::MAX - 1, 1 << 31]) {
                assert_eq!(
                    Halton::sample(i, dim, seed).to_bits(),
                    reference(i, dim, seed).to_bits()
                );
            }
            for _ in 0..300 {
                x = mix32(x.wrapping_add(0x9E37_79B9));
                let i = x >> (x % 32);
                assert_eq!(
                    Halton::sample(i, dim, seed).to_bits(),
                    reference(i, dim, seed).to_bits()
                );
            }
        }
    }

    fn check_paths(first: u64, len: usize, seed: Seed) {
        let h = Halton::<3>::new(1 << 32).unwrap();
        let mut a = vec![[0.0f32; 3]; len];
        let mut b = vec![[0.0f32; 3]; len];
        h.fill_range(seed, first as usize, &mut a).unwrap();
        h.fill_range_scalar(seed, first as usize, &mut b).unwrap();
        for l in 0..len {
            for d in 0..3 {
                let i = (first + l as u64) as u32;
                let s = Halton::sample(i, d as u32, seed);
                assert_eq!(a[l][d].to_bits(), s.to_bits(), "simd i {i} d {d}");
                assert_eq!(b[l][d].to_bits(), s.to_bits(), "scalar i {i} d {d}");
            }
        }
    }

    #[test]
    fn simd_scalar_and_sample_agree_across_digit_boundaries() {
        for (s, b) in [2u64, 3, 5].into_iter().enumerate() {
            let mut p = b;
            while p < 1 << 32 {
                for off in [1u64, 5, 8, 13] {
                    if p >= off {
                        check_paths(p - off, 21 + off as usize, Seed(s as u64 + 3));
                    }
                }
                p *= b;
            }
        }
        check_paths(0, 77, Seed(9));
        // Long fills use the largest leading-digit tables (K₀ = 9, 5, 4); start
        // them off a table period and across b^k boundaries.
        check_paths(0, 12_000, Seed(12));
        check_paths(3u64.pow(9) - 5_001, 12_000, Seed(13));
        check_paths(5u64.pow(13) - 6_007, 12_000, Seed(14));
        check_paths((1 << 31) - 6_001, 12_000, Seed(15));
        check_paths((1 << 32) - 12_000, 12_000, Seed(16));
        check_paths((1 << 32) - 1_003, 1_003, Seed(17));
        check_paths((1 << 32) - 40, 40, Seed(9));
        check_paths((1 << 32) - 37, 37, Seed(10));
        check_paths((1 << 32) - 5, 5, Seed(10));
    }

    /// Digit `k` (0 = leading) of `x` in base `b`, valid for `k < J_b` (exact stratum).
    fn digit_of(x: f32, b: u32, k: u32) -> u32 {
        ((f64::from(x) * f64::from(b).powi(k as i32 + 1)) as u64 % u64::from(b)) as u32
    }

    #[test]
    fn prefixes_are_stratified() {
        for seed in 0..6u64 {
            let seed = Seed(seed * 7919 + 1);
            // 1D in bases 2, 3, 5, n = b^k, k ≤ 6; offsets b^k·j for a few j.
            for (d, b) in [2u32, 3, 5].into_iter().enumerate() {
                for k in 1..=6u32 {
                    let n = b.pow(k);
                    for j in [0u32, 1, 7] {
                        let mut seen = vec![false; n as usize];
                        for i in j * n..(j + 1) * n {
                            let c = (f64::from(Halton::sample(i, d as u32, seed)) * f64::from(n))
                                as usize;
                            assert!(!seen[c], "b {b} k {k} j {j}: cell {c} twice");
                            seen[c] = true;
                        }
                    }
                }
            }
            // 2D boxes 2^p × 3^q from the SIMD fill.
            for p in 0..=6u32 {
                for q in 0..=4u32 {
                    let n = (1usize << p) * 3usize.pow(q);
                    let mut pts = vec![[0.0f32; 2]; n];
                    Halton::<2>::new(n).unwrap().fill(seed, &mut pts).unwrap();
                    let mut seen = vec![false; n];
                    for pt in &pts {
                        let u = (f64::from(pt[0]) * f64::from(1u32 << p)) as usize;
                        let v = (f64::from(pt[1]) * f64::from(3u32.pow(q))) as usize;
                        let c = u * 3usize.pow(q) + v;
                        assert!(!seen[c], "box {p} {q}");
                        seen[c] = true;
                    }
                }
            }
        }
    }

    #[test]
    fn digits_are_uniform_and_nested_independent() {
        // Over 4000 seeds: (1) digit k of point i is uniform on [0, b); (2) for two
        // prefixes p ≠ p' at the same position k, (π_{k,p}(0), π_{k,p'}(0)) is
        // uniform on [0, b)² (independent permutations). Chi-square below the
        // 1 − 10⁻⁶ quantile (df = 1: 23.9, where Wilson–Hilferty is poor);
        // 3 bases × 5 digit positions × 2 checks = 30 checks, false alarm
        // ≤ 3·10⁻⁵ in all (the seeds are fixed, so the test is deterministic).
        let seeds = 4000u64;
        for (d, b) in [2u32, 3, 5].into_iter().enumerate() {
            for k in [0u32, 1, 2, 4, 9] {
                if b.pow(k) > 40_000 {
                    continue;
                }
                let bk = b.pow(k);
                // index i = p < b^k has digit k = 0 and prefix p; j = p' likewise.
                // Two distinct prefixes at position k (none for k = 0).
                let p = bk - 1;
                let q = if bk / 2 != p { bk / 2 } else { 0 };
                let mut h1 = vec![0u32; b as usize];
                let mut h2 = vec![0u32; (b * b) as usize];
                for s in 0..seeds {
                    let seed = Seed(s.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 17);
                    let x = digit_of(Halton::sample(p + 5 * bk * b, d as u32, seed), b, k);
                    h1[x as usize] += 1;
                    if k > 0 && p != q {
                        let y = digit_of(Halton::sample(p, d as u32, seed), b, k);
                        let z = digit_of(Halton::sample(q, d as u32, seed), b, k);
                        h2[(y * b + z) as usize] += 1;
                    }
                }
                let e1 = seeds as f64 / f64::from(b);
                let df1 = f64::from(b - 1).max(1.0);
                assert!(
                    chi2(&h1, e1) < chi2_limit(df1).max(23.9),
                    "b {b} k {k} uniform: {h1:?}"
                );
                if k > 0 && p != q {
                    let e2 = seeds as f64 / f64::from(b * b);
                    let df2 = f64::from(b * b - 1);
                    assert!(chi2(&h2, e2) < chi2_limit(df2), "b {b} k {k} pairs: {h2:?}");
                }
            }
        }
    }

    #[test]
    fn scramble_permutes_each_digit() {
        // With a nested permutation, indices that differ only in digit k differ
        // in scrambled digit k and agree in digits 0..k.
        let base = &BASES[1];
        let (dk, lambda) = dim_key(Seed(5), 1);
        let scr = |i| scrambled_digits(i, base, dk, |k| digit_mu(lambda, k));
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
