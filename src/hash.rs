//! Hash-based random permutations with random access.
//!
//! `permute(i, n, key)` is a bijection of `[0, n)` chosen by `key`, evaluated in
//! `O(1)` expected time and no memory:
//!
//! 1. a keyed bijection `P` of `[0, 2ᵇ)`, `b = ⌈log₂ n⌉`: a generalised Feistel
//!    network on the split `x = (hi, lo)` (`⌈b/2⌉` and `⌊b/2⌋` bits) whose rounds
//!    alternate `hi ⊕= F_r(lo)` and `lo ⊕= F_r(hi)` (twelve rounds for `b ≤ 5`,
//!    eight up to `b = 12`, six above; Luby & Rackoff 1988[^1]); each round is
//!    invertible whatever `F_r` is;
//! 2. *cycle walking* (Black & Rogaway 2002[^2]): `P` is re-applied until the value
//!    falls in `[0, n)`, which restricts the bijection to `[0, n)`; since
//!    `n > 2ᵇ⁻¹`, fewer than two steps are needed on average;
//! 3. a keyed rotation `x ↦ (x + c) mod n` with `c` uniform in `[0, n)`, so that for
//!    every `i` the value `permute(i, n, key)` is uniform over `[0, n)` when the key
//!    is random: patterns built from these permutations stay unbiased.
//!
//! # Round function
//!
//! Round `r` writes `F_r(x) = ((a_r·x + b_r) mod 2³²) >> (32 − l)` into an
//! `l`-bit half, with `a_r`, `b_r` two words of the key expansion. For inputs
//! of `u` bits this *multiply-add-shift* family is strongly universal
//! (pairwise independent) whenever `32 ≥ u + l − 1` (Dietzfelbinger 1996[^4];
//! Thorup 2015[^5]), which holds for every half here (`u, l ≤ 16`): for
//! `x ≠ x'` and uniform `a_r`, `b_r`, the pair `(F_r(x), F_r(x'))` is exactly
//! uniform. (The test `multiply_add_shift_is_strongly_universal` checks the
//! statement exhaustively on small word sizes, and that it fails one bit
//! below the bound.) For domains of at most `2¹⁶` elements the round words
//! keep only their top 16 bits (`Shape::word_mask`), so a round is exact
//! 16-bit arithmetic, `((a'·x + b') mod 2¹⁶) >> (16 − l)`, strongly universal
//! since `16 ≥ u + l − 1` for halves of at most eight bits, and the pattern
//! generators run it in sixteen 16-bit lanes (`apply16`).
//!
//! Why that is enough for sampling: two trajectories through the network query
//! each round function at no more than two points, so if the round words were
//! independent and uniform, the joint law of `(P(i), P(j))` over keys would
//! be *exactly* that of the same network with truly random round functions
//! (for a power-of-two domain; cycle walking re-uses a round function on more
//! points). The variance of any estimator built from these permutations, and
//! the expected periodogram of any pattern, are sums over pairs of points, so
//! they would be those of the ideal network. Our round words are hashes of
//! one 32-bit key, as before, so this is the model, and the tests measure the
//! pair law of the real function against it, cycle-walking sizes included.
//! The price is higher-order structure, which no variance formula sees (a
//! study of single realisations, `examples/permutation_realizations.rs`,
//! finds N-rooks, MJ and CMJ periodograms indistinguishable from those
//! built on exact Fisher–Yates shuffles); the gain is one multiply, one add
//! and one shift per round, against two multiplies and six other operations
//! for a full 32-bit mixer (the round function of earlier versions).
//!
//! Domains of at most [`SMALL_DOMAIN`] elements, where a Feistel network reaches
//! too few permutations, use an exact Fisher–Yates shuffle on the stack instead.
//!
//! The same idea drives Kensler's correlated multi-jittered sampling[^3]; the
//! rounds and constants here are our own.
//!
//! [^1]: M. Luby, C. Rackoff, *How to Construct Pseudorandom Permutations from
//!   Pseudorandom Functions*, SIAM J. Comput. 17(2), 1988.
//! [^2]: J. Black, P. Rogaway, *Ciphers with Arbitrary Finite Domains*, CT-RSA 2002.
//! [^3]: A. Kensler, *Correlated Multi-Jittered Sampling*, Pixar Technical Memo 13-01 (2013).
//! [^4]: M. Dietzfelbinger, *Universal hashing and k-wise independent random
//!   variables via integer arithmetic without primes*, STACS 1996, LNCS 1046.
//! [^5]: M. Thorup, *High Speed Hashing for Integers and Strings*, arXiv:1504.06804
//!   (2015), section on multiply-add-shift.

use crate::num::lane::{IntLane, U16x16Lane};
use crate::rng::{mix32, mix32x8};
use wide::{u16x16, u16x8, u32x8};

/// Largest number of Feistel rounds, used for domains of 17 to 32 elements.
const MAX_ROUNDS: usize = 12;

/// Words a key expands to: `a_r` (word `2r`) and `b_r` (word `2r + 1`) for
/// each round, then the rotation word.
pub(crate) const KEY_WORDS: usize = 2 * MAX_ROUNDS + 1;

/// Index of the rotation word in a key expansion.
pub(crate) const ROTATION: usize = 2 * MAX_ROUNDS;

/// Feistel rounds for a `b`-bit domain: eight up to `b = 12` (halves of at
/// most six bits), six above, twelve for 17 to 32 elements. Four rounds of a
/// random round function give a pseudo-random permutation only
/// asymptotically (Luby & Rackoff 1988); with these halves they do not: for
/// two indices that differ only in the top bit, `(0, n/2)` say, the pair
/// `(permute(0), permute(n/2))` over keys departs from uniform (measured with
/// a full 32-bit mixer as round function, which the pair law of the
/// multiply-add-shift rounds equals: 64 × 64 bins, 2·10⁶ keys, z = 248 at
/// `n = 2¹³`, 18 at `2¹⁶`, 4.3 at `2¹⁸`). Six rounds showed no departure
/// from `2¹³` to `2²⁴` (|z| ≤ 3.3 over 96 such tests), and
/// `large_domain_pairs_are_uniform_over_keys` fails with four. Below `2¹³` six
/// are not enough (z = 6.1 at `n = 64`), eight are down to 33 elements; at 17
/// to 32 (halves of two and three bits) eight fail the same test (z = 13 at
/// `n = 17`, 44 at `n = 32`, pair `(1, 17)`) and twelve pass
/// (`pairs_are_uniform_over_keys` fails with eight).
#[inline(always)]
const fn rounds(bits: u32) -> usize {
    if bits > 12 {
        6
    } else if bits > 5 {
        8
    } else {
        MAX_ROUNDS
    }
}

/// Domains up to this size use an exact Fisher–Yates shuffle instead of the
/// Feistel network (tiny Feistel networks reach only some permutations).
pub const SMALL_DOMAIN: u32 = 16;

/// Element `i` of a uniformly random permutation of `[0, n)`, `n ≤ 16`, by a
/// Fisher–Yates shuffle of a stack array driven by keyed hashes (Durstenfeld 1964);
/// each swap index is `⌊h·(j+1)/2³²⌋`, uniform up to a bias below `2⁻²⁷`.
#[inline]
fn permute_small(i: u32, n: u32, key: u32) -> u32 {
    u32::from(small_table(n, key)[i as usize])
}

/// The whole permutation of [`permute_small`].
#[inline]
fn small_table(n: u32, key: u32) -> [u8; SMALL_DOMAIN as usize] {
    let mut a = [0u8; SMALL_DOMAIN as usize];
    for (j, x) in a.iter_mut().enumerate() {
        *x = j as u8;
    }
    let mut j = n - 1;
    while j > 0 {
        let h = round_key(key, 64 + j);
        let k = ((u64::from(h) * u64::from(j + 1)) >> 32) as usize;
        a.swap(j as usize, k);
        j -= 1;
    }
    a
}

/// The `b`-bit mask `2ᵇ − 1` with `b = ⌈log₂ n⌉` (0 for `n ≤ 1`).
#[inline(always)]
#[must_use]
pub const fn domain_mask(n: u32) -> u32 {
    if n <= 1 {
        0
    } else {
        u32::MAX >> (n - 1).leading_zeros()
    }
}

/// The split of a domain `[0, n)`, `n > 16`, into Feistel halves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Shape {
    n: u32,
    /// `2ᵇ − 1`.
    mask: u32,
    /// Bits of the low half, `⌊b/2⌋`.
    lo_bits: u32,
    /// `32 −` bits of the high half: the shift of a round that writes it.
    hi_shift: u32,
    /// `32 − lo_bits`.
    lo_shift: u32,
    /// Feistel rounds (even).
    rounds: usize,
}

impl Shape {
    /// The shape of `[0, n)`; only meaningful for `n > SMALL_DOMAIN`.
    #[inline(always)]
    pub(crate) const fn new(n: u32) -> Self {
        let mask = domain_mask(n);
        let bits = mask.count_ones();
        let lo_bits = bits / 2;
        Shape {
            n,
            mask,
            lo_bits,
            hi_shift: 32 - (bits - lo_bits),
            lo_shift: 32 - lo_bits,
            rounds: rounds(bits),
        }
    }

    /// Key words this shape reads: `2·rounds` round words (the rotation word
    /// is always read).
    #[inline(always)]
    pub(crate) const fn round_words(&self) -> usize {
        2 * self.rounds
    }

    /// A domain of at most `2¹⁶` elements (halves of at most eight bits).
    /// Its round words keep only their top 16 bits ([`Shape::word_mask`]),
    /// so each round is exact 16-bit arithmetic and runs in sixteen 16-bit
    /// lanes ([`apply16`]).
    #[inline(always)]
    pub(crate) const fn narrow(&self) -> bool {
        self.mask <= 0xFFFF
    }

    /// The mask applied to round words (not the rotation word): the top 16
    /// bits for narrow domains, where `((a·x + b) mod 2³²) >> (32 − l)` with
    /// the low halves of `a`, `b` zero is `((a'·x + b') mod 2¹⁶) >> (16 − l)`
    /// with `a' = a >> 16`, `b' = b >> 16`: still strongly universal, since
    /// `16 ≥ u + l − 1` for halves of at most eight bits.
    #[inline(always)]
    pub(crate) const fn word_mask(&self) -> u32 {
        if self.narrow() {
            0xFFFF_0000
        } else {
            u32::MAX
        }
    }
}

/// The words of `key` that a domain of `shape` reads (`round_key(key, w)`,
/// round words masked by [`Shape::word_mask`]), zero elsewhere.
#[inline]
#[must_use]
pub(crate) fn key_words(key: u32, shape: &Shape) -> [u32; KEY_WORDS] {
    let used = shape.round_words();
    core::array::from_fn(|w| {
        if w < used {
            round_key(key, w as u32) & shape.word_mask()
        } else if w == ROTATION {
            round_key(key, w as u32)
        } else {
            0
        }
    })
}

/// Round word `w < 2·rounds` of the key expansions of eight lane keys for
/// a domain of shape `s` ([`key_words`]).
#[inline(always)]
#[must_use]
pub(crate) fn key_word_x8(key: u32x8, w: usize, s: &Shape) -> u32x8 {
    raw_word_x8(key, w) & u32x8::splat(s.word_mask())
}

/// Word `w` of the key expansions of eight lane keys, unmasked.
#[inline(always)]
fn raw_word_x8(key: u32x8, w: usize) -> u32x8 {
    mix32x8(key ^ u32x8::splat(round_const(w as u32)))
}

/// The rotations `c = ⌊w·n/2³²⌋ ∈ [0, n)` of eight lane keys, `w` their
/// rotation word: what the vector paths keep at [`ROTATION`] in place of `w`.
#[inline(always)]
#[must_use]
pub(crate) fn rotation_x8(key: u32x8, n: u32) -> u32x8 {
    raw_word_x8(key, ROTATION).mul_keep_high(u32x8::splat(n))
}

/// The constant that separates word `r` of a key expansion from the others.
#[inline(always)]
const fn round_const(r: u32) -> u32 {
    r.wrapping_mul(0x9E37_79B9).wrapping_add(0x7F4A_7C15)
}

/// Word `r` of a key expansion.
#[inline(always)]
const fn round_key(key: u32, r: u32) -> u32 {
    mix32(key ^ round_const(r))
}

/// The multiply-add-shift round function `((a·x + b) mod 2³²) >> shift`.
#[inline(always)]
const fn round_fn(x: u32, a: u32, b: u32, shift: u32) -> u32 {
    a.wrapping_mul(x).wrapping_add(b) >> shift
}

/// The keyed bijection `P` of `[0, 2ᵇ)` (lo = low `lo_bits` bits).
#[inline(always)]
const fn feistel(x: u32, keys: &[u32; KEY_WORDS], s: &Shape) -> u32 {
    let mut hi = x >> s.lo_bits;
    let mut lo = x & ((1 << s.lo_bits) - 1);
    let mut r = 0;
    while r < s.rounds {
        hi ^= round_fn(lo, keys[2 * r], keys[2 * r + 1], s.hi_shift);
        lo ^= round_fn(hi, keys[2 * r + 2], keys[2 * r + 3], s.lo_shift);
        r += 2;
    }
    (hi << s.lo_bits) | lo
}

/// Element `i` of the random permutation of `[0, n)` selected by `key`.
///
/// `i` must be below `n`; in release builds an `i ≥ n` is reduced modulo `n`
/// first (debug builds assert): cycle-walking from outside `[0, n)` could
/// otherwise run forever. For `n ≤ 1` the result is 0.
#[inline]
#[must_use]
pub fn permute(i: u32, n: u32, key: u32) -> u32 {
    debug_assert!(i < n.max(1), "permute: i = {i} must be below n = {n}");
    if n <= 1 {
        return 0;
    }
    let i = if i < n { i } else { i % n };
    if n <= SMALL_DOMAIN {
        return permute_small(i, n, key);
    }
    let s = Shape::new(n);
    let keys = key_words(key, &s);
    let mut x = i;
    loop {
        x = feistel(x, &keys, &s);
        if x < n {
            break;
        }
    }
    let c = ((u64::from(keys[ROTATION]) * u64::from(n)) >> 32) as u32;
    let y = x + c;
    if y >= n {
        y - n
    } else {
        y
    }
}

/// Lane-wise [`permute`] with a common `n` and per-lane keys; equal to the scalar
/// function lane by lane.
#[inline]
#[must_use]
pub fn permute_x8(i: u32x8, n: u32, key: u32x8) -> u32x8 {
    PermuteX8::new(n, key).apply(i)
}

/// Eight permutations of `[0, n)` (one key per lane) with their key words and
/// rotation computed once: [`PermuteX8::apply`] is [`permute_x8`] without the
/// key hashes, and [`PermuteX8::apply4`] evaluates four independent vectors in
/// lock step.
///
/// The Feistel rounds form a dependency chain (a multiply, an add, a shift and
/// an exclusive or per round); interleaving four independent chains lets the
/// CPU overlap them, which is what makes N-rooks and (correlated)
/// multi-jittered generation throughput-bound rather than latency-bound. The
/// values are those of [`permute`], lane by lane.
#[derive(Clone, Copy, Debug)]
pub struct PermuteX8 {
    key: u32x8,
    shape: Shape,
    words: [u32x8; KEY_WORDS],
}

impl PermuteX8 {
    /// Permutations of `[0, n)` with lane keys `key`.
    #[inline(always)]
    #[must_use]
    pub fn new(n: u32, key: u32x8) -> Self {
        let mut p = PermuteX8 {
            key,
            shape: Shape::new(n),
            words: [u32x8::ZERO; KEY_WORDS],
        };
        p.set_key(key);
        p
    }

    /// The same domain with lane keys `key`, in place (no copy of the key
    /// words, for callers that change keys often).
    #[inline(always)]
    pub(crate) fn set_key(&mut self, key: u32x8) {
        self.key = key;
        if self.shape.n > SMALL_DOMAIN {
            let used = self.shape.round_words();
            for (w, word) in self.words.iter_mut().enumerate().take(used) {
                *word = key_word_x8(key, w, &self.shape);
            }
            self.words[ROTATION] = rotation_x8(key, self.shape.n);
        }
    }

    /// Exact Fisher–Yates tables for `n ≤ 16` (see [`permute`]).
    #[cold]
    fn small(&self, i: u32x8) -> u32x8 {
        let n = self.shape.n;
        let (ia, ka) = (i.to_array(), self.key.to_array());
        if ka.iter().all(|&k| k == ka[0]) {
            // One key for all lanes (e.g. correlated multi-jitter): one table.
            let t = small_table(n, ka[0]);
            return u32x8::new(core::array::from_fn(|l| u32::from(t[(ia[l] % n) as usize])));
        }
        u32x8::new(core::array::from_fn(|l| permute_small(ia[l] % n, n, ka[l])))
    }

    /// `permute(i_l, n, key_l)` in lane `l`. Every lane must be below `n`: the
    /// vector path does not reduce, and a cycle walk that starts outside
    /// `[0, n)` may never end.
    #[inline(always)]
    #[must_use]
    pub fn apply(&self, i: u32x8) -> u32x8 {
        let n = self.shape.n;
        if n <= 1 {
            return u32x8::ZERO;
        }
        if n <= SMALL_DOMAIN {
            return self.small(i);
        }
        apply_with(&self.shape, [i], |_, w| self.words[w])[0]
    }

    /// Four vectors through four permutation sets sharing `n`: element `v` is
    /// `perms[v].apply(i[v])`. The first Feistel pass of all four runs
    /// interleaved, round by round.
    ///
    /// # Panics
    /// Debug builds assert that all four share `n`.
    #[inline(always)]
    #[must_use]
    pub fn apply4(perms: [&PermuteX8; 4], i: [u32x8; 4]) -> [u32x8; 4] {
        let s = perms[0].shape;
        debug_assert!(perms.iter().all(|p| p.shape == s));
        if s.n <= SMALL_DOMAIN {
            return core::array::from_fn(|v| perms[v].apply(i[v]));
        }
        apply_with(&s, i, |v, w| perms[v].words[w])
    }
}

/// The Feistel rounds of `C` interleaved vectors (the keyed bijection `P`
/// of `[0, 2ᵇ)`), vector `v` with word `w` of its lane keys from `word(v, w)`.
#[inline(always)]
fn feistel_lanes<L: IntLane, const C: usize>(
    s: &Shape,
    x: &mut [L; C],
    word: &impl Fn(usize, usize) -> L,
) {
    let lo_mask = L::splat((1 << s.lo_bits) - 1);
    let (hi_shift, lo_shift) = (s.hi_shift - L::NARROWER, s.lo_shift - L::NARROWER);
    // Plain loops over fixed-size arrays (not `array::from_fn`, whose
    // closures the compiler does not always inline here).
    let (mut hi, mut lo) = (*x, *x);
    for v in 0..C {
        hi[v] = x[v] >> s.lo_bits;
        lo[v] = x[v] & lo_mask;
    }
    for r in (0..s.rounds).step_by(2) {
        for v in 0..C {
            hi[v] ^= (word(v, 2 * r) * lo[v] + word(v, 2 * r + 1)) >> hi_shift;
        }
        for v in 0..C {
            lo[v] ^= (word(v, 2 * r + 2) * hi[v] + word(v, 2 * r + 3)) >> lo_shift;
        }
    }
    for v in 0..C {
        x[v] = (hi[v] << s.lo_bits) | lo[v];
    }
}

/// Cycle walking (Black & Rogaway 2002): `P` re-applied to the lanes of `x`
/// still outside `[0, n)`, with the lane key words `word(w)`. A power-of-two
/// domain (`n = mask + 1`) never walks.
#[inline(always)]
fn walk<L: IntLane>(s: &Shape, mut x: L, word: impl Fn(usize) -> L) -> L {
    if s.n > s.mask {
        return x;
    }
    let vn = L::splat(s.n);
    let mut pending = x.ge(vn);
    while pending.any() {
        let mut y = [x];
        feistel_lanes(s, &mut y, &|_, w| word(w));
        x = L::select(pending, y[0], x);
        pending = pending & x.ge(vn);
    }
    x
}

/// `C` vectors through permutations of a domain of shape `s` (`n > 16`),
/// element `v` with the lane key words `word(v, w)` (and at [`ROTATION`] the
/// rotation of [`rotation_x8`], not its raw word): the Feistel rounds of
/// the `C` run interleaved, then each walks into `[0, n)` and is rotated.
/// Every lane must be below `n`. For callers that keep key words in their
/// own tables (multi-jitter's per-column keys); values as [`permute`] with
/// those keys.
#[inline(always)]
pub(crate) fn apply_with<const C: usize>(
    s: &Shape,
    i: [u32x8; C],
    word: impl Fn(usize, usize) -> u32x8,
) -> [u32x8; C] {
    let mask = u32x8::splat(s.mask);
    let mut x = i.map(|v| v & mask);
    feistel_lanes(s, &mut x, &word);
    let vn = u32x8::splat(s.n);
    for v in 0..C {
        let y = walk(s, x[v], |w| word(v, w)) + word(v, ROTATION);
        x[v] = y - (y.simd_ge(vn) & vn);
    }
    x
}

/// The key words of sixteen permutations of a narrow domain
/// (`16 < n ≤ 2¹⁶`, [`Shape::narrow`]), one key per 16-bit lane, as
/// [`apply16`] reads them ([`PermuteX16::words_in`]): twice the lanes of
/// [`PermuteX8`] per instruction, and a native multiply in SSE2 builds.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PermuteX16 {
    words: [u16x16; KEY_WORDS],
}

impl PermuteX16 {
    /// Lanes 0–7 with the keys of `lo`, lanes 8–15 with those of `hi`.
    ///
    /// # Panics
    /// Debug builds assert that the domain is narrow and above 16 elements.
    #[inline]
    #[must_use]
    pub(crate) fn new(n: u32, lo: u32x8, hi: u32x8) -> Self {
        let shape = Shape::new(n);
        let (a, b) = (narrow_words_x8(lo, &shape), narrow_words_x8(hi, &shape));
        let words = core::array::from_fn(|w| {
            u16x16::new(core::array::from_fn(|l| {
                if l < 8 {
                    a[w][l]
                } else {
                    b[w][l - 8]
                }
            }))
        });
        PermuteX16 { words }
    }

    /// Every key word in the lanes `L` of one instruction-set level.
    #[inline(always)]
    pub(crate) fn words_in<L: U16x16Lane>(&self) -> [L; KEY_WORDS] {
        let mut out = [L::splat(0); KEY_WORDS];
        for (o, w) in out.iter_mut().zip(&self.words) {
            *o = L::from_array(w.to_array());
        }
        out
    }
}

/// Whether permutations of `[0, n)` run in 16-bit lanes ([`apply16`]):
/// `16 < n ≤ 2¹⁶` ([`Shape::narrow`], above the Fisher–Yates tables).
#[inline(always)]
#[must_use]
pub(crate) const fn in_sixteen_bits(n: u32) -> bool {
    n > SMALL_DOMAIN && n <= 1 << 16
}

/// The key words of eight lane keys for a narrow domain of shape `s`, as
/// [`apply16`] reads them, lane by lane: the top 16 bits of each round word
/// ([`Shape::word_mask`]) and at [`ROTATION`] `d = (n − c) mod 2¹⁶` for the
/// rotation `c` ([`rotation_x8`]); zero elsewhere.
///
/// # Panics
/// Debug builds assert that the domain is narrow and above 16 elements.
#[inline]
#[must_use]
pub(crate) fn narrow_words_x8(key: u32x8, s: &Shape) -> [[u16; 8]; KEY_WORDS] {
    debug_assert!(in_sixteen_bits(s.n));
    let narrow = |v: u32x8| (v >> 16u32).to_array().map(|x| x as u16);
    let mut words = [[0u16; 8]; KEY_WORDS];
    for (w, word) in words.iter_mut().enumerate().take(s.round_words()) {
        *word = narrow(raw_word_x8(key, w));
    }
    words[ROTATION] = narrow((u32x8::splat(s.n) - rotation_x8(key, s.n)) << 16u32);
    words
}

/// The two halves of a vector of sixteen 16-bit lanes, zero-extended.
#[inline(always)]
#[must_use]
pub(crate) fn widen(x: u16x16) -> [u32x8; 2] {
    let h: [u16x8; 2] = bytemuck::cast(x);
    [u32x8::from(h[0]), u32x8::from(h[1])]
}

/// `C` vectors of sixteen 16-bit lanes through permutations of a narrow
/// domain of shape `s` (`16 < n ≤ 2¹⁶`), vector `v` with the lane key words
/// `word(v, w)`: the top 16 bits of round word `w` (as `u16`), and at
/// [`ROTATION`] `d = (n − c) mod 2¹⁶` for the rotation `c`
/// ([`narrow_words_x8`]). Every lane must be below `n`. The Feistel rounds of
/// the `C` vectors run interleaved; each round is
/// `h ⊕= ((a'·x + b') mod 2¹⁶) >> (16 − l)`, equal to the 32-bit round of
/// [`permute`] on the masked words ([`Shape::word_mask`]). The rotation
/// `x + c mod n` is `x − d` when `x ≥ d`, else `x + c`, which never leaves
/// 16 bits (`n = 2¹⁶` included).
#[inline(always)]
pub(crate) fn apply16<L: U16x16Lane, const C: usize>(
    s: &Shape,
    i: [L; C],
    word: impl Fn(usize, usize) -> L,
) -> [L; C] {
    debug_assert!(in_sixteen_bits(s.n));
    let mut x = i;
    feistel_lanes(s, &mut x, &word);
    let vn = L::splat(s.n); // truncated: 0 for n = 2¹⁶, as the rotation wants
    for v in 0..C {
        x[v] = walk(s, x[v], |w| word(v, w));
        let d = word(v, ROTATION);
        let c = vn - d;
        x[v] = L::select(x[v].ge(d), x[v] - d, x[v] + c);
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::chi2_limit;

    #[test]
    fn multiply_add_shift_is_strongly_universal() {
        // The round function on W-bit words, through `round_fn` itself: with
        // a, b scaled by 2^(32−W), ((a·x + b) mod 2^W) >> (W − l) is
        // round_fn(x, a·2^(32−W), b·2^(32−W), 32 − l). Over all a, b < 2^W
        // and every pair x < x' < 2^u, each output pair must occur exactly
        // 2^(2W − 2l) times when W ≥ u + l − 1, and not when W = u + l − 2.
        let pair_counts_exact = |w: u32, u: u32, l: u32| {
            let scale = 32 - w;
            for x in 0..1u32 << u {
                for x2 in x + 1..1u32 << u {
                    let mut h = [0u32; 1 << 10];
                    for a in 0..1u32 << w {
                        for b in 0..1u32 << w {
                            let f = |x: u32| round_fn(x, a << scale, b << scale, 32 - l);
                            h[((f(x) << l) | f(x2)) as usize] += 1;
                        }
                    }
                    if h[..1 << (2 * l)].iter().any(|&c| c != 1 << (2 * w - 2 * l)) {
                        return false;
                    }
                }
            }
            true
        };
        for (w, u, l) in [(7, 4, 4), (6, 3, 4), (6, 4, 3), (8, 5, 4), (5, 3, 3)] {
            assert!(pair_counts_exact(w, u, l), "W {w}, u {u}, l {l}");
        }
        for (w, u, l) in [(6, 4, 4), (4, 3, 3), (7, 5, 4)] {
            assert!(
                !pair_counts_exact(w, u, l),
                "W {w}, u {u}, l {l} below the bound"
            );
        }
    }

    #[test]
    fn is_a_bijection() {
        for n in [1u32, 2, 3, 5, 7, 8, 9, 31, 64, 100, 1000, 4097] {
            for key in [0u32, 1, 0xDEAD_BEEF] {
                let mut seen = [false; 4097];
                for i in 0..n {
                    let p = permute(i, n, key) as usize;
                    assert!(p < n as usize);
                    assert!(!seen[p], "n {n} key {key}: {p} twice");
                    seen[p] = true;
                }
            }
        }
    }

    #[test]
    fn each_element_is_uniform_over_keys() {
        // For a fixed i, permute(i, n, key) over 60000 keys: chi-square against the
        // uniform distribution below its 1 − 10⁻⁶ quantile (df = n − 1; bound from
        // the Wilson–Hilferty approximation, z = 4.753; tests/README.md).
        for n in [2u32, 3, 5, 6, 7, 11, 53, 100] {
            for i in [0, 1, n - 1] {
                let mut h = [0u32; 100];
                let k = 60_000u32;
                for key in 0..k {
                    h[permute(i, n, key.wrapping_mul(0x2545_F491)) as usize] += 1;
                }
                let e = f64::from(k) / f64::from(n);
                let chi: f64 = h[..n as usize]
                    .iter()
                    .map(|&c| (f64::from(c) - e).powi(2) / e)
                    .sum();
                let df = f64::from(n - 1);
                let q = chi2_limit(df);
                assert!(chi < q, "n {n} i {i}: chi2 {chi} ≥ {q}");
            }
        }
    }

    #[test]
    fn pairs_are_uniform_over_keys() {
        // (permute(i), permute(j)) over the keys is uniform over the n(n−1)
        // ordered pairs of distinct values: chi-square below its 1 − 10⁻⁶
        // quantile (z = 4.753). (0, 1) over 40000 keys; pairs that differ only in the top
        // bit over 2·10⁶ keys, where eight rounds fail at 17 to 32 elements
        // (z = 13 at n = 17, 44 at n = 32; twelve rounds pass).
        let mut cases = [3u32, 5, 7, 11, 17, 31, 33, 53]
            .map(|n| (n, 0, 1, 40_000u32))
            .to_vec();
        for n in [17u32, 32] {
            cases.push((n, 0, n / 2, 2_000_000));
            cases.push((n, 1, 1 + n / 2, 2_000_000));
        }
        for (n, i, j, k) in cases {
            let mut h = [0u32; 53 * 53];
            let cells = (n * n) as usize;
            for key in 0..k {
                let key = key.wrapping_mul(0x2545_F491);
                h[(permute(i, n, key) * n + permute(j, n, key)) as usize] += 1;
            }
            let e = f64::from(k) / f64::from(n * (n - 1));
            let mut chi = 0.0;
            for (c, &v) in h[..cells].iter().enumerate() {
                if c as u32 / n == c as u32 % n {
                    assert_eq!(v, 0, "n {n}: a permutation repeated a value");
                } else {
                    chi += (f64::from(v) - e).powi(2) / e;
                }
            }
            let df = f64::from(n * (n - 1) - 1);
            let q = chi2_limit(df);
            assert!(chi < q, "n {n} ({i}, {j}): chi2 {chi} ≥ {q}");
        }
    }

    #[test]
    fn large_domain_pairs_are_uniform_over_keys() {
        // The six-round regime (b > 12): for fixed i ≠ j, the pair
        // (permute(i), permute(j)) over 100000 keys, binned 16 × 16, against
        // the uniform distribution on distinct pairs (each bin holds a share
        // (n/16)² minus its diagonal of the n(n−1) pairs): chi-square below
        // its 1 − 10⁻⁶ quantile (df = 255; Wilson–Hilferty, z = 4.753).
        // Pairs that differ only in the top bit, (0, n/2) and (n/4, 3n/4),
        // are where four rounds fail (z ≈ 15 at n = 2¹³ with these keys).
        for n in [1u32 << 13, 1 << 16, 100_000, (1 << 24) - 5] {
            let pairs = [
                (0u32, 1u32),
                (5, 6),
                (1000, 1001),
                (7, n - 1),
                (0, n / 2),
                (n / 4, 3 * n / 4),
            ];
            for (i, j) in pairs {
                let keys = 100_000u32;
                let mut h = [0u32; 256];
                for key in 0..keys {
                    let key = key.wrapping_mul(0x2545_F491) ^ 0x9E37_79B9;
                    let (a, b) = (permute(i, n, key), permute(j, n, key));
                    assert_ne!(a, b);
                    let bin = |v: u32| ((u64::from(v) * 16) / u64::from(n)) as usize;
                    h[bin(a) * 16 + bin(b)] += 1;
                }
                // Bin sizes: value bin k holds w_k = ⌈(k+1)n/16⌉ − ⌈kn/16⌉ values.
                let w: [f64; 16] = core::array::from_fn(|k| {
                    let lo = (k as u64 * u64::from(n)).div_ceil(16);
                    let hi = ((k as u64 + 1) * u64::from(n)).div_ceil(16);
                    (hi - lo) as f64
                });
                let pairs = f64::from(n) * (f64::from(n) - 1.0);
                let mut chi = 0.0;
                for (c, &v) in h.iter().enumerate() {
                    let (x, y) = (c / 16, c % 16);
                    let cells = w[x] * w[y] - if x == y { w[x] } else { 0.0 };
                    let e = f64::from(keys) * cells / pairs;
                    chi += (f64::from(v) - e).powi(2) / e;
                }
                let df = 255.0f64;
                let q = chi2_limit(df);
                assert!(chi < q, "n {n} ({i}, {j}): chi2 {chi} ≥ {q}");
            }
        }
    }

    #[test]
    fn interleaved_matches_scalar() {
        for n in [1u32, 2, 3, 16, 17, 255, 256, 257, 100_000, 1 << 24] {
            let perms: [PermuteX8; 4] = core::array::from_fn(|v| {
                PermuteX8::new(
                    n,
                    u32x8::new(core::array::from_fn(|l| (v * 8 + l) as u32 * 977 + n)),
                )
            });
            let idx: [u32x8; 4] = core::array::from_fn(|v| {
                u32x8::new(core::array::from_fn(|l| {
                    ((v * 8 + l) as u32 * 31 + 5) % n.max(1)
                }))
            });
            let out = PermuteX8::apply4([&perms[0], &perms[1], &perms[2], &perms[3]], idx);
            for v in 0..4 {
                let (o, ia) = (out[v].to_array(), idx[v].to_array());
                for l in 0..8 {
                    let key = (v * 8 + l) as u32 * 977 + n;
                    assert_eq!(o[l], permute(ia[l], n, key), "n {n} v {v} l {l}");
                }
            }
        }
    }

    #[test]
    fn sixteen_bit_lanes_match_scalar() {
        // apply16 with PermuteX16's words (narrow domains in 16-bit lanes)
        // against permute, lane by lane, for one, two and four interleaved
        // vectors; indices cover the domain's ends (lanes at or above n are
        // clamped to n − 1, as callers do with padding lanes).
        for n in [
            17u32, 31, 32, 33, 100, 255, 256, 257, 1000, 4095, 4096, 4097, 40_000, 65_535, 65_536,
        ] {
            for seed in [0u32, 0x9E37_79B9, 0xFFFF_FFFF] {
                let key = |l: u32| seed ^ l.wrapping_mul(0x2545_F491) ^ n;
                let lo = u32x8::new(core::array::from_fn(|l| key(l as u32)));
                let hi = u32x8::new(core::array::from_fn(|l| key(l as u32 + 8)));
                let p = PermuteX16::new(n, lo, hi);
                let s = Shape::new(n);
                let top = u16x16::splat((n - 1) as u16);
                let clamp = |v: u16x16| v.min(top);
                let pw = p.words_in::<u16x16>();
                let word = |_: usize, w: usize| pw[w];
                for base in [0u32, n / 3, n.saturating_sub(40)] {
                    let idx = |v: u32, l: u32| (base + 16 * v + l).min(n + 5);
                    let x: [u16x16; 4] = core::array::from_fn(|v| {
                        u16x16::new(core::array::from_fn(|l| {
                            idx(v as u32, l as u32).min(0xFFFF) as u16
                        }))
                    });
                    let want = |v: u32, l: u32| permute(idx(v, l).min(n - 1), n, key(l));
                    let one = apply16(&s, [clamp(x[0])], word);
                    let two = apply16(&s, [clamp(x[0]), clamp(x[1])], word);
                    let four = apply16(&s, x.map(clamp), word);
                    for l in 0..16u32 {
                        let at = |y: u16x16| u32::from(y.to_array()[l as usize]);
                        assert_eq!(at(one[0]), want(0, l), "n {n} lane {l}");
                        assert_eq!(at(two[1]), want(1, l), "n {n} lane {l}");
                        for v in 0..4 {
                            assert_eq!(at(four[v]), want(v as u32, l), "n {n} v {v} lane {l}");
                        }
                    }
                    let wide = widen(four[3]);
                    for l in 0..16 {
                        assert_eq!(wide[l / 8].to_array()[l % 8], want(3, l as u32));
                    }
                }
            }
        }
    }

    #[test]
    fn simd_matches_scalar() {
        for n in [1u32, 2, 3, 17, 255, 256, 257, 100_000] {
            for base in (0..n.min(64)).step_by(8) {
                let idx: [u32; 8] = core::array::from_fn(|l| (base + l as u32) % n);
                let keys: [u32; 8] = core::array::from_fn(|l| 77 * l as u32 + n);
                let v = permute_x8(u32x8::new(idx), n, u32x8::new(keys)).to_array();
                for l in 0..8 {
                    assert_eq!(v[l], permute(idx[l], n, keys[l]));
                }
            }
        }
    }
}
