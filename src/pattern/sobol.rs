//! Owen-scrambled Sobol' points (Burley 2020): [`Sobol`] and its random-access
//! functions. The construction is documented on [`Sobol`].

use super::sealed::{Generate, Sink};
use super::{array, check_dims, check_n, drive8, unit_f32, unit_f32x8};
use crate::error::PatternError;
use crate::num::lane::{Lane, U32x8Lane, Wu32x8};
use crate::rng::{purpose_mix, Seed};
use crate::simd::Isa;
use wide::{u32x4, u32x8};

/// Number of Sobol' dimensions available to [`Sobol::sample`]: the van der Corput
/// sequence plus Joe & Kuo (2008) dimensions 2 to 1024.
pub const SOBOL_DIMENSIONS: u32 = 1024;

const NDIM: usize = SOBOL_DIMENSIONS as usize;

/// Dimensions with nibble tables ([`NIBBLES`], 8 KiB each): the pattern
/// dimensions and the first random-access ones. Higher dimensions use the
/// direct product over [`DIRECTIONS`] (the same values).
const NIBBLE_DIMS: usize = 16;

/// The first 1024 lines of Joe & Kuo's `new-joe-kuo-6.21201` (a header, then
/// `d s a m₁ … m_s` for dimensions 2 to 1024), verbatim; its licence is
/// `data/JOE-KUO-LICENSE.txt` beside it.
const JOE_KUO: &[u8] = include_bytes!("data/joe-kuo-6.21201-first1024.txt");

/// The next unsigned decimal in `t` at or after `*at`, skipping spaces and
/// stopping at the end of the line: `None` at a newline or the end of `t`.
const fn next_number(t: &[u8], at: &mut usize) -> Option<u32> {
    while *at < t.len() && t[*at] == b' ' {
        *at += 1;
    }
    if *at >= t.len() || t[*at] == b'\n' {
        return None;
    }
    let mut x = 0u32;
    while *at < t.len() && t[*at].is_ascii_digit() {
        x = x * 10 + (t[*at] - b'0') as u32;
        *at += 1;
    }
    Some(x)
}

/// `V[d][k]`: direction number of dimension `d` for index bit `k`, as a 32-bit
/// binary fraction (bit 31 = 1/2), from the table [`JOE_KUO`] (parsed at
/// compile time; a malformed table fails the build).
const fn direction_numbers() -> [[u32; 32]; NDIM] {
    let mut v = [[0u32; 32]; NDIM];
    let mut k = 0;
    while k < 32 {
        v[0][k] = 1 << (31 - k);
        k += 1;
    }
    let t = JOE_KUO;
    // Skip the header line.
    let mut at = 0;
    while t[at] != b'\n' {
        at += 1;
    }
    at += 1;
    let mut d = 1;
    while d < NDIM {
        let (Some(dd), Some(s), Some(a)) = (
            next_number(t, &mut at),
            next_number(t, &mut at),
            next_number(t, &mut at),
        ) else {
            panic!("Joe–Kuo table: a line lacks d, s or a");
        };
        assert!(
            dd as usize == d + 1,
            "Joe–Kuo table: dimensions out of order"
        );
        let s = s as usize;
        assert!(s >= 1 && s < 32, "Joe–Kuo table: degree out of range");
        // m[k] holds m_{k+1} < 2^{k+1}, so it fits 32 bits for k < 32.
        let mut m = [0u32; 32];
        let mut k = 0;
        while k < 32 {
            if k < s {
                let Some(mk) = next_number(t, &mut at) else {
                    panic!("Joe–Kuo table: fewer than s initial numbers");
                };
                assert!(mk % 2 == 1 && mk < 1 << (k + 1), "Joe–Kuo table: bad m_k");
                m[k] = mk;
            } else {
                let mut x = m[k - s] ^ (m[k - s] << s);
                let mut i = 1;
                while i < s {
                    if (a >> (s - 1 - i)) & 1 == 1 {
                        x ^= m[k - i] << i;
                    }
                    i += 1;
                }
                m[k] = x;
            }
            v[d][k] = m[k] << (31 - k);
            k += 1;
        }
        assert!(
            next_number(t, &mut at).is_none(),
            "Joe–Kuo table: more than s numbers"
        );
        at += 1;
        d += 1;
    }
    v
}

static DIRECTIONS: [[u32; 32]; NDIM] = direction_numbers();

/// Nibble tables of the bit-reversed generator matrices, indexed by the bits of the
/// *reversed* index `t = reverse(i)`: `NIBBLES[d][p][n] = ⊕_{b: n_b = 1}
/// reverse(V[d][31 − 4p − b])`, so that `reverse(x_d(i)) = ⊕_p NIBBLES[d][p][(t ≫ 4p) & 15]`.
const fn nibble_tables() -> [[[u32; 16]; 8]; NIBBLE_DIMS] {
    let dirs = direction_numbers();
    let mut t = [[[0u32; 16]; 8]; NIBBLE_DIMS];
    let mut d = 0;
    while d < NIBBLE_DIMS {
        let mut p = 0;
        while p < 8 {
            let mut n = 0;
            while n < 16 {
                let mut x = 0u32;
                let mut b = 0;
                while b < 4 {
                    if (n >> b) & 1 == 1 {
                        x ^= dirs[d][31 - 4 * p - b].reverse_bits();
                    }
                    b += 1;
                }
                t[d][p][n] = x;
                n += 1;
            }
            p += 1;
        }
        d += 1;
    }
    t
}

static NIBBLES: [[[u32; 16]; 8]; NIBBLE_DIMS] = nibble_tables();

/// Row length of [`PAIRS`]: the 1024 dimensions plus 16 unused words. Rows
/// 4 KiB apart would map the loads of one batch to one L1 cache set (8
/// ways): measured, that made a batch slower than a single-coordinate
/// `sample` per lane. The padding spreads them over distinct sets.
const ROW: usize = NDIM + 16;

/// The bit-reversed direction numbers by pairs of index bits, transposed for
/// the batch random access: `PAIRS[c][v][d] = ⊕_{b ∈ {0,1}: v_b = 1}
/// reverse(V[d][31 − 2c − b])`, so that for a reversed index `t`
/// (bit reversal commutes with XOR)
///
/// `reverse(x_d(reverse(t))) = ⊕_{c=0}^{15} PAIRS[c][(t ≫ 2c) & 3][d]`,
///
/// 16 lookups instead of 32 masked ones, and the numbers of consecutive
/// dimensions for one lookup are one vector load (260 KiB).
const fn direction_pairs() -> [[[u32; ROW]; 4]; 16] {
    let dirs = direction_numbers();
    let mut t = [[[0u32; ROW]; 4]; 16];
    let mut c = 0;
    while c < 16 {
        let mut d = 0;
        while d < NDIM {
            let lo = dirs[d][31 - 2 * c].reverse_bits();
            let hi = dirs[d][30 - 2 * c].reverse_bits();
            t[c][1][d] = lo;
            t[c][2][d] = hi;
            t[c][3][d] = lo ^ hi;
            d += 1;
        }
        c += 1;
    }
    t
}

static PAIRS: [[[u32; ROW]; 4]; 16] = direction_pairs();

/// The seed-free half of every value key, `purpose_mix(VALUE_PURPOSE + d)`,
/// split into its low (`[0][d]`) and high (`[1][d]`) 32-bit words (8 KiB):
/// `value_key(σ, d)` is one `mix64` of `σ ⊕` it, in
/// scalar code or, for the batches, in `u32` lanes.
const fn value_mix_halves() -> [[u32; NDIM]; 2] {
    let mut h = [[0u32; NDIM]; 2];
    let mut d = 0;
    while d < NDIM {
        let m = purpose_mix(VALUE_PURPOSE + d as u64);
        h[0][d] = m as u32;
        h[1][d] = (m >> 32) as u32;
        d += 1;
    }
    h
}

static VALUE_MIX_HALVES: [[u32; NDIM]; 2] = value_mix_halves();

/// Unscrambled value `x_d(i)` as a 32-bit binary fraction (see
/// [`Sobol::sobol_u32`]); `dim < SOBOL_DIMENSIONS` (checked by the callers).
#[inline(always)]
fn sobol_u32(index: u32, dim: u32) -> u32 {
    let v = &DIRECTIONS[dim as usize];
    let mut x = 0;
    for (k, vk) in v.iter().enumerate() {
        // Branch-free: all ones where bit k of the index is set.
        x ^= vk & 0u32.wrapping_sub((index >> k) & 1);
    }
    x
}

/// Panics unless `dim < SOBOL_DIMENSIONS`, in every build.
#[inline(always)]
#[track_caller]
fn assert_dim(dim: u32) {
    super::assert_sequence_dim("Sobol", dim, SOBOL_DIMENSIONS);
}

/// `reverse(x_d(reverse(t)))` from the nibble tables (`t` is a reversed index).
#[inline(always)]
fn matvec_rev(t: u32, dim: usize) -> u32 {
    let tab = &NIBBLES[dim];
    let mut x = 0;
    for (p, row) in tab.iter().enumerate() {
        x ^= row[((t >> (4 * p)) & 15) as usize];
    }
    x
}

/// Key of one Owen scramble: an additive key and an odd multiplier.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct OwenKey {
    add: u32,
    mul: u32,
}

impl OwenKey {
    #[inline(always)]
    pub(super) const fn from_stream(s: u64) -> Self {
        Self {
            add: s as u32,
            mul: (s >> 32) as u32 | 1,
        }
    }
}

// Even multipliers of the Laine–Karras (2011) permutation, as listed by Burley (2020).
const LK1: u32 = 0x6C50_B47C;
const LK2: u32 = 0xB82F_1E52;
const LK3: u32 = 0xC7AF_E638;
const LK4: u32 = 0x8D22_F6E6;

/// Hash-based nested uniform scramble of a bit-reversed word (Laine & Karras 2011,
/// Burley 2020): each step changes bit `j` only as a function of bits `0..j`, so
/// bit `j` of the result is bit `j` of `r` XOR a function of the bits below `j`.
#[inline(always)]
pub(super) const fn owen_rev(mut r: u32, k: OwenKey) -> u32 {
    r = r.wrapping_add(k.add);
    r ^= r.wrapping_mul(LK1);
    r ^= r.wrapping_mul(LK2);
    r = r.wrapping_mul(k.mul);
    r ^= r.wrapping_mul(LK3);
    r ^= r.wrapping_mul(LK4);
    r
}

/// Lane-wise [`owen_rev`] and lane-wise `u32::reverse_bits` (five swap steps)
/// for one `wide` vector type.
macro_rules! lane_ops {
    ($v:ty, $owen:ident, $reverse:ident) => {
        /// Lane-wise [`owen_rev`].
        #[inline(always)]
        fn $owen(mut r: $v, add: $v, mul: $v) -> $v {
            r += add;
            r ^= r * <$v>::splat(LK1);
            r ^= r * <$v>::splat(LK2);
            r *= mul;
            r ^= r * <$v>::splat(LK3);
            r ^= r * <$v>::splat(LK4);
            r
        }

        /// Lane-wise `u32::reverse_bits` (five swap steps).
        #[inline(always)]
        fn $reverse(mut x: $v) -> $v {
            x = (x >> 16) | (x << 16);
            let m = <$v>::splat(0x00FF_00FF);
            x = ((x >> 8) & m) | ((x & m) << 8);
            let m = <$v>::splat(0x0F0F_0F0F);
            x = ((x >> 4) & m) | ((x & m) << 4);
            let m = <$v>::splat(0x3333_3333);
            x = ((x >> 2) & m) | ((x & m) << 2);
            let m = <$v>::splat(0x5555_5555);
            x = ((x >> 1) & m) | ((x & m) << 1);
            x
        }
    };
}

/// [`owen_rev_lanes`] in `wide`'s lanes (the batch random access).
#[inline(always)]
fn owen_rev_x8(r: u32x8, add: u32x8, mul: u32x8) -> u32x8 {
    owen_rev_lanes(Wu32x8(r), Wu32x8(add), Wu32x8(mul)).0
}

/// [`reverse_lanes`] in `wide`'s lanes.
#[inline(always)]
fn reverse_x8(x: u32x8) -> u32x8 {
    reverse_lanes(Wu32x8(x)).0
}

/// Lane-wise [`owen_rev`] in the integer lanes of any level (the fills'
/// dispatched copies).
#[inline(always)]
fn owen_rev_lanes<U: U32x8Lane>(mut r: U, add: U, mul: U) -> U {
    r = r + add;
    r = r ^ (r * U::splat(LK1));
    r = r ^ (r * U::splat(LK2));
    r = r * mul;
    r = r ^ (r * U::splat(LK3));
    r ^ (r * U::splat(LK4))
}

/// Lane-wise `u32::reverse_bits` (five swap steps) in the lanes of any level.
#[inline(always)]
fn reverse_lanes<U: U32x8Lane>(mut x: U) -> U {
    x = (x >> 16) | (x << 16);
    let m = U::splat(0x00FF_00FF);
    x = ((x >> 8) & m) | ((x & m) << 8);
    let m = U::splat(0x0F0F_0F0F);
    x = ((x >> 4) & m) | ((x & m) << 4);
    let m = U::splat(0x3333_3333);
    x = ((x >> 2) & m) | ((x & m) << 2);
    let m = U::splat(0x5555_5555);
    ((x >> 1) & m) | ((x & m) << 1)
}
lane_ops!(u32x4, owen_rev_x4, reverse_x4);

/// Seed purpose of the index scramble.
const INDEX_PURPOSE: u64 = 0x534F_424C_0000_0000;
/// Seed purpose of the value scramble of dimension `d` (plus `d`).
const VALUE_PURPOSE: u64 = 0x534F_424C_0001_0000;

#[inline(always)]
const fn index_key(seed: Seed) -> OwenKey {
    OwenKey::from_stream(seed.stream(INDEX_PURPOSE))
}

/// `OwenKey::from_stream(seed.stream(VALUE_PURPOSE + dim))`, from the table of
/// the purposes' halves; `dim < SOBOL_DIMENSIONS`.
#[inline(always)]
fn value_key(seed: Seed, dim: u32) -> OwenKey {
    let d = dim as usize;
    let m = u64::from(VALUE_MIX_HALVES[0][d]) | u64::from(VALUE_MIX_HALVES[1][d]) << 32;
    OwenKey::from_stream(seed.stream_premixed(m))
}

/// Dimensions `dim … dim + L − 1` of one sample in lanes (`L` = 4 or 8,
/// `dim + L ≤ SOBOL_DIMENSIONS`): the index scramble once, then per
/// pair of index bits one vector load from [`PAIRS`], the value scrambles in
/// lanes. Lane `l` equals `sample_keyed(index, dim + l, …)` bit for
/// bit: the same XOR of the same direction numbers (in another order, which
/// XOR does not see), the same scramble and conversion.
macro_rules! sample_lanes {
    ($name:ident, $v:ty, $l:expr, $owen:ident, $reverse:ident) => {
        #[inline(always)]
        fn $name(index: u32, dim: usize, seed: Seed) -> [f32; $l] {
            let t = shuffled_rev(index, index_key(seed));
            let mut x = <$v>::splat(0);
            for (c, rows) in PAIRS.iter().enumerate() {
                let row = &rows[((t >> (2 * c)) & 3) as usize];
                let v: [u32; $l] = core::array::from_fn(|l| row[dim + l]);
                x ^= <$v>::new(v);
            }
            // value_key(σ, dim + l) = mix64(σ ⊕ VALUE_MIX_HALVES[·][dim + l]) in lanes of
            // (low, high) halves.
            let half = |h: usize| <$v>::new(core::array::from_fn(|l| VALUE_MIX_HALVES[h][dim + l]));
            let (lo, hi) = mix64_halves(
                half(0) ^ <$v>::splat(seed.0 as u32),
                half(1) ^ <$v>::splat((seed.0 >> 32) as u32),
            );
            let mul = hi | <$v>::splat(1);
            $reverse($owen(x, lo, mul)).to_array().map(unit_f32)
        }
    };
}

/// [`mix64`](crate::rng::mix64) of `x = hi·2³² + lo` in `u32` lanes:
/// `x ⊕= x ≫ 33` is `lo ⊕= hi ≫ 1`; `x ·= C` (mod 2⁶⁴) is
/// `lo' = lo·C_lo`, `hi' = ⌊lo·C_lo / 2³²⌋ + lo·C_hi + hi·C_lo` (mod 2³²).
macro_rules! mix64_lanes {
    ($($v:ty),*) => {$(
        impl MixHalves for $v {
            #[inline(always)]
            fn mix64_halves(mut lo: Self, mut hi: Self) -> (Self, Self) {
                #[inline(always)]
                fn mul(lo: $v, hi: $v, c: u64) -> ($v, $v) {
                    let (cl, ch) = (<$v>::splat(c as u32), <$v>::splat((c >> 32) as u32));
                    (lo * cl, lo.mul_keep_high(cl) + lo * ch + hi * cl)
                }
                lo ^= hi >> 1;
                (lo, hi) = mul(lo, hi, crate::rng::MIX64_C1);
                lo ^= hi >> 1;
                (lo, hi) = mul(lo, hi, crate::rng::MIX64_C2);
                lo ^= hi >> 1;
                (lo, hi)
            }
        }
    )*};
}

/// Lane-wise `mix64` on split 64-bit words.
trait MixHalves: Sized {
    fn mix64_halves(lo: Self, hi: Self) -> (Self, Self);
}

mix64_lanes!(u32x4, u32x8);

#[inline(always)]
fn mix64_halves<V: MixHalves>(lo: V, hi: V) -> (V, V) {
    V::mix64_halves(lo, hi)
}

sample_lanes!(sample_lanes4, u32x4, 4, owen_rev_x4, reverse_x4);
sample_lanes!(sample_lanes8, u32x8, 8, owen_rev_x8, reverse_x8);

/// The reversed shuffled index `t = scramble(reverse(i))`.
#[inline(always)]
const fn shuffled_rev(index: u32, k: OwenKey) -> u32 {
    owen_rev(index.reverse_bits(), k)
}

#[inline(always)]
fn sample_keyed(index: u32, dim: usize, ki: OwenKey, kv: OwenKey) -> f32 {
    let t = shuffled_rev(index, ki);
    let x_rev = if dim < NIBBLE_DIMS {
        matvec_rev(t, dim)
    } else {
        sobol_u32(t.reverse_bits(), dim as u32).reverse_bits()
    };
    let y = owen_rev(x_rev, kv);
    unit_f32(y.reverse_bits())
}

/// Dimension `dim < 16` of the Sobol' point with index `index` itself (no
/// index shuffle), Owen-scrambled with the key drawn from the 64-bit `stream`
/// (its low half additive, its high half the odd multiplier): the ZSobol
/// value, whose index is already a hierarchical permutation.
#[inline]
pub(crate) fn sample_unshuffled(index: u32, dim: usize, stream: u64) -> f32 {
    let y = owen_rev(
        matvec_rev(index.reverse_bits(), dim),
        OwenKey::from_stream(stream),
    );
    unit_f32(y.reverse_bits())
}

/// Owen-scrambled Sobol' points (Burley 2020): point `k` is
/// `(Sobol::sample(k, 0, σ), …, Sobol::sample(k, D−1, σ))`, dimensions `0..D` of the
/// sequence.
///
/// For `N = 2^m` the points form a `(0, m, 2)`-net in dimensions 0 and 1 (one point
/// in every elementary interval of area `2^{-m}`) and every coordinate is a
/// `(0, m, 1)`-net. Points do not depend on `N`: a pattern is a prefix of every
/// larger one. The random-access functions ([`Sobol::sample`], [`Sobol::try_sample`],
/// [`Sobol::sobol_u32`], [`Sobol::sample_unscrambled`]) are defined on `Sobol<1>`, so
/// that `Sobol::sample(i, d, seed)` needs no type argument.
///
/// # The sequence
///
/// The Sobol' sequence[^1] in base 2: coordinate `d` of point `i` is
/// `x_d(i) = ⊕_k i_k·v_{d,k}`, the XOR of the *direction numbers* `v_{d,k}` (32-bit
/// binary fractions) over the set bits `i_k` of the index. Dimension 0 is the van der
/// Corput sequence (`v_{0,k} = 2^{-(k+1)}`, the bit reversal of `i`). Dimensions
/// `1..1024` use the Joe & Kuo parameters[^2] of their file `new-joe-kuo-6.21201`
/// (their dimensions 2 to 1024, the file's first 1024 lines, kept verbatim in
/// the crate with its licence): a primitive polynomial of degree `s` with inner
/// coefficients `a = a₁…a_{s−1}` (binary) and initial odd integers `m₁…m_s`,
/// `m_k < 2^k`, extended by the recurrence
///
/// `m_k = 2a₁m_{k−1} ⊕ 2²a₂m_{k−2} ⊕ … ⊕ 2^{s−1}a_{s−1}m_{k−s+1} ⊕ 2^s m_{k−s} ⊕ m_{k−s}`,
///
/// and `v_{d,k} = m_{k+1}/2^{k+1}`. The 32-bit tables are computed by `const fn` at
/// compile time from the table text (128 KiB of direction numbers; the first 16
/// dimensions also get 8 KiB nibble tables for the fills). Every block of `2^m`
/// consecutive indices starting at a multiple of `2^m` is a `(t, m, s)`-net; dimensions 0 and 1 together are a `(0, m, 2)`-net and
/// every single dimension is a `(0, m, 1)`-net.
///
/// # Randomisation
///
/// Following Burley[^3], sample `i` of dimension `d` for seed `σ` is
///
/// 1. `i' = scramble(i; κ_σ)`: the index, read as a 32-digit binary fraction
///    (bit 31 first), goes through a nested uniform (Owen[^4]) scramble keyed by the
///    seed. It maps every aligned block of `2^m` indices onto an aligned block of
///    `2^m` indices, so the first `2^m` points are still a net;
/// 2. `x = x_d(i')`, the unscrambled Sobol' value of the shuffled index;
/// 3. `y = scramble(x; κ_{σ,d})`, an Owen scramble of the value, keyed by seed and
///    dimension;
/// 4. the top 24 bits of `y` become an `f32`, `⌊y/2⁸⌋·2⁻²⁴ ∈ [0, 1 − 2⁻²⁴]`.
///
/// The scramble is the hash-based one of Laine & Karras[^5] as refined by Burley: on
/// the *bit-reversed* word `r`, the operations `r += k`, `r ⊕= r·c` (`c` even) and
/// `r ·= k'` (`k'` odd), all mod 2³², change bit `j` of `r` only as a function of
/// bits `0..j` below it. After reversal this is exactly a nested uniform scramble:
/// digit `k` of the binary fraction is flipped or not depending on the digits
/// before it, which preserves every net property. With the four even Laine–Karras
/// constants and a seed-dependent odd multiplier, the scramble of `r` is
///
/// `r ← r + k_a; r ⊕= r·0x6C50B47C; r ⊕= r·0xB82F1E52; r ← r·k_m;`
/// `r ⊕= r·0xC7AFE638; r ⊕= r·0x8D22F6E6`,
///
/// where `(k_a, k_m | 1)` are the two halves of a 64-bit key from [`Seed::stream`]
/// (one purpose for the index, one per dimension for the value).
///
/// # Batches
///
/// Because the index scramble is triangular, the eight indices `8q … 8q+7` share
/// bits `3..32` of their shuffled index. The SIMD path therefore evaluates the
/// generator-matrix product of those shared bits once per block (from nibble
/// tables) and only the three low bits per lane, then runs the value scramble in
/// `u32x8` lanes. It gives the same bits as [`Sobol::sample`], lane by lane.
///
/// [^1]: I. M. Sobol', *On the distribution of points in a cube and the approximate
///   evaluation of integrals*, USSR Comput. Math. Math. Phys. 7(4), 1967.
/// [^2]: S. Joe, F. Y. Kuo, *Constructing Sobol sequences with better two-dimensional
///   projections*, SIAM J. Sci. Comput. 30(5), 2008.
/// [^3]: B. Burley, *Practical Hash-based Owen Scrambling*, JCGT 9(4), 2020.
/// [^4]: A. B. Owen, *Randomly permuted (t,m,s)-nets and (t,s)-sequences*, Monte Carlo
///   and Quasi-Monte Carlo Methods in Scientific Computing, 1995.
/// [^5]: S. Laine, T. Karras, *Stratified sampling for stochastic transparency*,
///   Computer Graphics Forum 30(4), 2011.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sobol<const D: usize> {
    n: u64,
}

impl<const D: usize> Sobol<D> {
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

impl Sobol<1> {
    /// Sample `index` of dimension `dim` of the Owen-scrambled Sobol' sequence
    /// for `seed`, in `[0, 1 − 2⁻²⁴]` (never 1.0, never NaN):
    /// `⌊scramble_{σ,d}(x_d(scramble_σ(i))) / 2⁸⌋ · 2⁻²⁴` (Burley 2020; see the
    /// [`Sobol`] docs). Every `index` in `0..2³²` is valid.
    ///
    /// # Panics
    /// If `dim ≥ SOBOL_DIMENSIONS` (1024), in debug and release builds alike:
    /// there is no dimension to repeat silently. [`Sobol::try_sample`] returns
    /// an error instead.
    #[inline]
    #[must_use]
    #[track_caller]
    pub fn sample(index: u32, dim: u32, seed: Seed) -> f32 {
        assert_dim(dim);
        sample_keyed(index, dim as usize, index_key(seed), value_key(seed, dim))
    }

    /// [`Sobol::sample`] with a checked dimension.
    ///
    /// # Errors
    /// [`PatternError::Dimension`] if `dim ≥ SOBOL_DIMENSIONS`.
    pub fn try_sample(index: u32, dim: u32, seed: Seed) -> Result<f32, PatternError> {
        if dim >= SOBOL_DIMENSIONS {
            return Err(PatternError::Dimension {
                dim,
                max: SOBOL_DIMENSIONS,
            });
        }
        Ok(Self::sample(index, dim, seed))
    }

    /// Unscrambled Sobol' value `x_d(i)` of index `index` in dimension `dim` as a
    /// 32-bit binary fraction: `⊕_k i_k·v_{d,k}`, the XOR of the direction numbers
    /// over the set bits of the index (Sobol' 1967; Joe & Kuo 2008 direction
    /// numbers). The point is `sobol_u32(i, d)·2⁻³² ∈ [0, 1)`.
    ///
    /// Points are in direct index order (not Gray-code order): index 0 is 0 in
    /// every dimension, index 1 is 1/2.
    ///
    /// # Panics
    /// If `dim ≥ SOBOL_DIMENSIONS`, in every build.
    #[must_use]
    #[track_caller]
    pub fn sobol_u32(index: u32, dim: u32) -> u32 {
        assert_dim(dim);
        sobol_u32(index, dim)
    }

    /// The unscrambled Sobol' value [`Sobol::sobol_u32`] as an `f32`: its top 24 bits,
    /// `⌊x_d(i)/2⁸⌋·2⁻²⁴ ∈ [0, 1)`.
    ///
    /// # Panics
    /// If `dim ≥ SOBOL_DIMENSIONS`, in every build.
    #[must_use]
    #[track_caller]
    pub fn sample_unscrambled(index: u32, dim: u32) -> f32 {
        assert_dim(dim);
        unit_f32(sobol_u32(index, dim))
    }

    /// Dimensions `dim, dim + 1, dim + 2, dim + 3` of sample `index` at once,
    /// in SIMD lanes: `[Sobol::sample(index, dim + l, seed); l = 0..4]`, bit
    /// for bit. The index scramble is computed once for the four lanes, the
    /// generator-matrix product reads one vector of the four dimensions'
    /// direction numbers per pair of index bits, and the value scrambles run lane by
    /// lane (see the [`Sobol`] docs for the construction). `dim` need not be
    /// a multiple of 4.
    ///
    /// [`Sequence::sample_4d`](crate::sequence::Sequence::sample_4d) is the
    /// checked form (an error instead of a panic).
    ///
    /// # Panics
    /// If `dim + 4 > SOBOL_DIMENSIONS`, in every build.
    #[inline]
    #[must_use]
    #[track_caller]
    pub fn sample_4d(index: u32, dim: u32, seed: Seed) -> [f32; 4] {
        assert_dim(dim.saturating_add(3));
        sample_lanes4(index, dim as usize, seed)
    }

    /// Dimensions `dim … dim + 7` of sample `index` at once, in SIMD lanes:
    /// [`Sobol::sample_4d`] with eight lanes (one 256-bit vector with AVX2).
    ///
    /// # Panics
    /// If `dim + 8 > SOBOL_DIMENSIONS`, in every build.
    #[inline]
    #[must_use]
    #[track_caller]
    pub fn sample_8d(index: u32, dim: u32, seed: Seed) -> [f32; 8] {
        assert_dim(dim.saturating_add(7));
        sample_lanes8(index, dim as usize, seed)
    }
}

/// Per-block data of an aligned group of eight indices `g … g+7`: the reversed
/// shuffled index of `g` (its bits `0..29` are shared by the group) and the
/// matrix products of those shared bits.
struct Group<const D: usize> {
    rev: u32,
    hi: [u32; D],
}

impl<const D: usize> Group<D> {
    #[inline(always)]
    fn new(g: u64, ki: OwenKey) -> Self {
        let t = shuffled_rev(g as u32, ki) & 0x1FFF_FFFF;
        Self {
            rev: (g as u32).reverse_bits(),
            hi: core::array::from_fn(|j| matvec_rev(t, j)),
        }
    }
}

impl<const D: usize> Generate<D> for Sobol<D> {
    fn n(&self) -> u64 {
        self.n
    }

    #[inline(always)]
    fn gen_simd<I: Isa, S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let ki = index_key(seed);
        let kv: [OwenKey; D] = core::array::from_fn(|j| value_key(seed, j as u32));
        let v = I::U32::splat;
        let (ki_add, ki_mul) = (v(ki.add), v(ki.mul));
        let kv_add: [I::U32; D] = kv.map(|k| v(k.add));
        let kv_mul: [I::U32; D] = kv.map(|k| v(k.mul));
        // Columns of index bits 0, 1, 2 (reversed bits 31, 30, 29 of t).
        let col: [[I::U32; 3]; D] =
            core::array::from_fn(|j| core::array::from_fn(|b| v(NIBBLES[j][7][8 >> b])));
        // Lane l holds index first + 8·block + l = group + ((off + l) & 7), where the
        // group is `base` for off + l < 8 and `base + 8` otherwise.
        let off = (first & 7) as u32;
        let mut base = first - u64::from(off);
        let low_rev = I::U32::from_array(core::array::from_fn(|l| {
            ((off + l as u32) & 7).reverse_bits()
        }));
        let second = I::U32::from_array(core::array::from_fn(|l| {
            if off + l as u32 >= 8 {
                u32::MAX
            } else {
                0
            }
        }));
        let mut cur = Group::<D>::new(base, ki);
        let (zero, one) = (v(0), v(1));
        drive8!(sink, I::U32, {
            let next = Group::<D>::new(base.wrapping_add(8), ki);
            let r = I::U32::select(second, v(next.rev), v(cur.rev)) | low_rev;
            let t = owen_rev_lanes(r, ki_add, ki_mul);
            let m0 = zero - (t >> 31);
            let m1 = zero - ((t >> 30) & one);
            let m2 = zero - ((t >> 29) & one);
            let out: [I::F32; D] = array!(I::F32::splat(0.0), |j| {
                let hi = I::U32::select(second, v(next.hi[j]), v(cur.hi[j]));
                let x = hi ^ (m0 & col[j][0]) ^ (m1 & col[j][1]) ^ (m2 & col[j][2]);
                let y = owen_rev_lanes(x, kv_add[j], kv_mul[j]);
                unit_f32x8(reverse_lanes(y))
            });
            cur = next;
            base = base.wrapping_add(8);
            out
        });
    }

    fn gen_scalar<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let ki = index_key(seed);
        let kv: [OwenKey; D] = core::array::from_fn(|j| value_key(seed, j as u32));
        for i in 0..sink.len() {
            let index = (first + i as u64) as u32;
            let p = core::array::from_fn(|j| sample_keyed(index, j, ki, kv[j]));
            sink.put(i, p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn van_der_corput_and_first_points() {
        for i in [0u32, 1, 2, 3, 6, 0xDEAD_BEEF, u32::MAX] {
            assert_eq!(sobol_u32(i, 0), i.reverse_bits());
        }
        // Point 1 is 1/2 in every dimension (m₁ = 1 everywhere).
        for d in 0..SOBOL_DIMENSIONS {
            assert_eq!(sobol_u32(1, d), 1 << 31);
        }
    }

    #[test]
    fn direction_numbers_are_upper_triangular() {
        // Column k has its lowest set bit at position 31 − k (m_k odd), which makes
        // every generator matrix invertible.
        for d in 0..NDIM {
            for k in 0..32 {
                assert_eq!(
                    DIRECTIONS[d][k].trailing_zeros() as usize,
                    31 - k,
                    "d {d} k {k}"
                );
            }
        }
    }

    #[test]
    fn nibble_tables_match_the_direct_product() {
        let mut x = 0x1234_5678u32;
        for _ in 0..2000 {
            x = crate::rng::mix32(x.wrapping_add(0x9E37_79B9));
            for d in 0..NIBBLE_DIMS {
                let want = sobol_u32(x, d as u32).reverse_bits();
                assert_eq!(matvec_rev(x.reverse_bits(), d), want);
            }
        }
    }

    fn keys() -> [OwenKey; 4] {
        [
            OwenKey { add: 0, mul: 1 },
            OwenKey::from_stream(Seed(1).stream(INDEX_PURPOSE)),
            OwenKey::from_stream(Seed(2).stream(VALUE_PURPOSE)),
            OwenKey {
                add: u32::MAX,
                mul: u32::MAX,
            },
        ]
    }

    #[test]
    fn owen_scramble_is_triangular() {
        // Flipping input bit k never changes output bits below k, and always flips
        // output bit k.
        let mut x = 7u32;
        for key in keys() {
            for _ in 0..500 {
                x = crate::rng::mix32(x ^ 0x5555_AAAA);
                let y = owen_rev(x, key);
                for k in 0..32 {
                    let z = owen_rev(x ^ (1 << k), key);
                    let below = (1u64 << k) as u32 - 1;
                    assert_eq!((y ^ z) & below, 0, "bit {k} leaked downwards");
                    assert_eq!((y ^ z) >> k & 1, 1, "bit {k} not flipped");
                }
            }
        }
    }

    #[test]
    fn owen_scramble_is_a_bijection_on_low_bits() {
        // Triangularity makes it a bijection of every residue class mod 2^b.
        for key in keys() {
            for bits in [1u32, 4, 12] {
                let n = 1usize << bits;
                let mut seen = [false; 4096];
                for x in 0..n as u32 {
                    let y = owen_rev(x, key) as usize & (n - 1);
                    assert!(!seen[y]);
                    seen[y] = true;
                }
            }
        }
    }

    #[test]
    fn simd_helpers_match_scalar() {
        let xs: [u32; 8] = [
            0,
            1,
            u32::MAX,
            0x8000_0000,
            0xDEAD_BEEF,
            12345,
            0x0F0F_1234,
            77,
        ];
        let v = u32x8::new(xs);
        for key in keys() {
            let a = owen_rev_x8(v, u32x8::splat(key.add), u32x8::splat(key.mul)).to_array();
            for l in 0..8 {
                assert_eq!(a[l], owen_rev(xs[l], key));
            }
        }
        let r = reverse_x8(v).to_array();
        for l in 0..8 {
            assert_eq!(r[l], xs[l].reverse_bits());
        }
    }

    #[test]
    fn group_shares_the_high_bits() {
        let ki = index_key(Seed(99));
        for g in [0u64, 8, 1 << 20, (1 << 32) - 8] {
            let grp = Group::<3>::new(g, ki);
            for l in 0..8u32 {
                let t = shuffled_rev(g as u32 + l, ki);
                assert_eq!(t & 0x1FFF_FFFF, shuffled_rev(g as u32, ki) & 0x1FFF_FFFF);
                for d in 0..3 {
                    let lo = matvec_rev(t & 0xE000_0000, d);
                    assert_eq!(grp.hi[d] ^ lo, matvec_rev(t, d));
                }
            }
        }
    }
}
