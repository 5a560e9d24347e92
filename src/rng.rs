//! Random numbers: the PCG32 generator, its SIMD lanes, seeds and hashing.
//!
//! # PCG32
//!
//! [`Pcg32`] is PCG-XSH-RR 64/32 (O'Neill 2014[^1]): a 64-bit linear congruential
//! generator `s ← a·s + c (mod 2⁶⁴)` with `a = 6364136223846793005` and an odd
//! stream increment `c`, and the output permutation
//! `out(s) = rotr32(((s ⊕ (s ≫ 18)) ≫ 27) mod 2³², s ≫ 59)`.
//! It implements the `rand_core` 0.10 traits ([`rand_core::TryRng`] with
//! `Error = Infallible`, hence [`rand_core::Rng`], and [`rand_core::SeedableRng`]).
//!
//! # Lanes
//!
//! An LCG can jump `n` steps in `O(log n)` (Brown 1994[^2]): `s_{t+n} = A_n·s_t + C_n`
//! with `A_n = aⁿ` and `C_n = c·(aⁿ−1)/(a−1)`, both computed by square-and-multiply
//! without division. [`Pcg32x8`] keeps eight states `s_{t}, s_{t+δ}, …, s_{t+7δ}` in
//! SIMD lanes and steps all of them by `8δ` at once, so lane `l` of block `b` holds
//! exactly output number `t + (8b + l)·δ` of the scalar generator. The values a
//! pattern gets therefore do not depend on the SIMD width, on the batch it was
//! generated in, or on whether the scalar or the SIMD path ran.
//!
//! # Counter-based generator
//!
//! The patterns draw their random coordinates from [`Counter`], a counter-based
//! generator (Salmon et al. 2011[^3]): output `t` of a stream is a hash of the
//! stream key and `t`, with no state between outputs. Random access is free,
//! `8` lanes need only 32-bit lane multiplies (three per output), and the value
//! of coordinate `j` of point `k` is the same whichever path, batch or width
//! computed it. See [`Counter`] for the construction.
//!
//! [^1]: M. E. O'Neill, *PCG: A Family of Simple Fast Space-Efficient Statistically
//!   Good Algorithms for Random Number Generation*, HMC-CS-2014-0905 (2014).
//! [^2]: F. B. Brown, *Random Number Generation with Arbitrary Strides*,
//!   Trans. Am. Nucl. Soc. 71 (1994).
//! [^3]: J. K. Salmon, M. A. Moraes, R. O. Dror, D. E. Shaw, *Parallel Random
//!   Numbers: As Easy as 1, 2, 3*, SC 2011.

use crate::num::lane::{U32x8Lane, Wu32x8};
use core::convert::Infallible;
use wide::u32x8;

use crate::error::SeedError;

/// The PCG32 LCG multiplier `a`.
pub const PCG_MULT: u64 = 6_364_136_223_846_793_005;

/// PCG-XSH-RR 64/32 output permutation of a state.
#[inline(always)]
#[must_use]
pub const fn pcg_output(state: u64) -> u32 {
    let xorshifted = (((state >> 18) ^ state) >> 27) as u32;
    let rot = (state >> 59) as u32;
    xorshifted.rotate_right(rot)
}

/// The affine map `(A_n, C_n)` that advances an LCG with multiplier
/// [`PCG_MULT`] and increment `inc` by `n` steps: `s_{t+n} = A_n·s_t + C_n (mod 2⁶⁴)`.
///
/// Square-and-multiply over the affine maps (Brown 1994), `O(log n)`.
#[inline]
#[must_use]
pub const fn lcg_jump(mut n: u64, inc: u64) -> (u64, u64) {
    let (mut acc_mult, mut acc_plus) = (1u64, 0u64);
    let (mut cur_mult, mut cur_plus) = (PCG_MULT, inc);
    while n > 0 {
        if n & 1 == 1 {
            acc_mult = acc_mult.wrapping_mul(cur_mult);
            acc_plus = acc_plus.wrapping_mul(cur_mult).wrapping_add(cur_plus);
        }
        cur_plus = cur_mult.wrapping_add(1).wrapping_mul(cur_plus);
        cur_mult = cur_mult.wrapping_mul(cur_mult);
        n >>= 1;
    }
    (acc_mult, acc_plus)
}

/// PCG-XSH-RR 64/32 generator (O'Neill 2014), with jump-ahead.
///
/// Not `Copy` on purpose (an accidental copy repeats values), and no `Default`:
/// construct it with [`Pcg32::new`] or [`rand_core::SeedableRng`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// Generator with initial state `init_state` on stream `stream`
    /// (`2⁶³` distinct streams; the increment is `2·stream + 1`).
    ///
    /// Seeding follows the PCG reference: `s = 0`, step, `s += init_state`, step.
    #[must_use]
    pub const fn new(init_state: u64, stream: u64) -> Self {
        let inc = (stream << 1) | 1;
        let mut s = inc; // 0·a + inc
        s = s.wrapping_add(init_state);
        s = s.wrapping_mul(PCG_MULT).wrapping_add(inc);
        Self { state: s, inc }
    }

    /// The current LCG state (the state the next output is computed from).
    #[inline]
    #[must_use]
    pub const fn state(&self) -> u64 {
        self.state
    }

    /// The odd LCG increment of this stream.
    #[inline]
    #[must_use]
    pub const fn increment(&self) -> u64 {
        self.inc
    }

    /// Next 32-bit output.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
        pcg_output(old)
    }

    /// Skips `delta` outputs in `O(log delta)`.
    #[inline]
    pub fn advance(&mut self, delta: u64) {
        let (m, p) = lcg_jump(delta, self.inc);
        self.state = m.wrapping_mul(self.state).wrapping_add(p);
    }

    /// The generator `delta` outputs ahead of this one.
    #[inline]
    #[must_use]
    pub fn advanced(&self, delta: u64) -> Self {
        let mut g = self.clone();
        g.advance(delta);
        g
    }
}

impl rand_core::TryRng for Pcg32 {
    type Error = Infallible;

    #[inline]
    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        Ok(Pcg32::next_u32(self))
    }

    #[inline]
    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        let lo = u64::from(Pcg32::next_u32(self));
        let hi = u64::from(Pcg32::next_u32(self));
        Ok(lo | (hi << 32))
    }

    #[inline]
    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
        rand_core::utils::fill_bytes_via_next_word(dst, || {
            Ok::<u32, Infallible>(Pcg32::next_u32(self))
        })
    }
}

impl rand_core::SeedableRng for Pcg32 {
    /// 16 little-endian bytes: the initial state, then the stream.
    type Seed = [u8; 16];

    fn from_seed(seed: [u8; 16]) -> Self {
        let mut a = [0u8; 8];
        let mut b = [0u8; 8];
        a.copy_from_slice(&seed[..8]);
        b.copy_from_slice(&seed[8..]);
        Pcg32::new(u64::from_le_bytes(a), u64::from_le_bytes(b))
    }
}

/// Eight PCG32 states in SIMD lanes, each stepping `8·stride` outputs per call.
///
/// Lane `l` of the `b`-th call to [`Pcg32x8::next_u32x8`] returns output number
/// `first + (8b + l)·stride` of the scalar [`Pcg32`] it was built from.
/// States are kept as split 32-bit halves so that the 64-bit multiply needs only
/// 32-bit lane multiplies (no 64-bit lane multiply exists on AVX2).
#[derive(Clone, Debug)]
pub struct Pcg32x8 {
    lo: u32x8,
    hi: u32x8,
    m_lo: u32x8,
    m_hi: u32x8,
    p_lo: u32x8,
    p_hi: u32x8,
}

impl Pcg32x8 {
    /// Lanes reading outputs `first, first + stride, …` of `base`.
    #[must_use]
    pub fn new(base: &Pcg32, first: u64, stride: u64) -> Self {
        let start = base.advanced(first);
        let (sm, sp) = lcg_jump(stride, base.inc);
        let mut lo = [0u32; 8];
        let mut hi = [0u32; 8];
        let mut s = start.state;
        for l in 0..8 {
            lo[l] = s as u32;
            hi[l] = (s >> 32) as u32;
            s = sm.wrapping_mul(s).wrapping_add(sp);
        }
        let (m, p) = lcg_jump(stride.wrapping_mul(8), base.inc);
        Self {
            lo: u32x8::new(lo),
            hi: u32x8::new(hi),
            m_lo: u32x8::splat(m as u32),
            m_hi: u32x8::splat((m >> 32) as u32),
            p_lo: u32x8::splat(p as u32),
            p_hi: u32x8::splat((p >> 32) as u32),
        }
    }

    /// Eight outputs (one per lane), then every lane steps `8·stride` outputs.
    #[inline(always)]
    pub fn next_u32x8(&mut self) -> u32x8 {
        let (lo, hi) = (self.lo, self.hi);
        // out(s): t = s ^ (s >> 18); x = (t >> 27) mod 2^32; rot = s >> 59.
        let t_lo = lo ^ ((lo >> 18) | (hi << 14));
        let t_hi = hi ^ (hi >> 18);
        let x = (t_lo >> 27) | (t_hi << 5);
        let rot = hi >> 27;
        let neg = (u32x8::ZERO - rot) & u32x8::splat(31);
        let out = (x >> rot) | (x << neg);
        // s <- m*s + p (mod 2^64) from 32-bit halves.
        let prod_lo = lo * self.m_lo;
        let prod_hi = lo.mul_keep_high(self.m_lo) + lo * self.m_hi + hi * self.m_lo;
        let new_lo = prod_lo + self.p_lo;
        let carry = new_lo.simd_lt(self.p_lo); // all ones where the low half wrapped
        self.lo = new_lo;
        self.hi = prod_hi + self.p_hi - carry;
        out
    }
}

/// A counter-based random stream: output `t` is a pure function of the key and `t`.
///
/// The key is a 64-bit offset `o` and two 32-bit words `a`, `m`. Output `t` is
///
/// ```text
/// c = o + t (mod 2⁶⁴),   c = c_hi·2³² + c_lo
/// A = mix32(c_hi ⊕ a),   M = γ(mix32(c_hi ⊕ m))
/// out(t) = mix32(((c_lo ⊕ A)·M) mod 2³²)
/// ```
///
/// with [`mix32`] the MurmurHash3 finaliser (Appleby 2011) and `γ` the odd
/// "gamma" rule of SplitMix (Steele, Lea & Flood 2014[^1]): `M | 1`, and if
/// fewer than 16 of its adjacent bit pairs differ, `M ⊕ 0xAAAAAAAA`. For a
/// fixed `c_hi` the map `c_lo ↦ out` is a bijection of `u32`, and `c_lo·M`
/// walks the 32-bit ring with the random odd stride `M` as a SplitMix32 Weyl
/// sequence does, so `mix32` sees well-spread inputs.
///
/// **Streams do not overlap.** Two keys give shifted copies of one another only
/// when their offsets differ by less than the number of outputs used *and*
/// their `(a, m)` agree: a random 64-bit offset makes a shift of `L` outputs
/// between two streams a `2L/2⁶⁴` event, and even then the words `a, m` differ.
/// (A plain 32-bit counter plus key would overlap for one pair in `2¹⁴` among
/// streams of `2¹⁸` outputs, far too often for thousands of realisations.)
///
/// **Cost.** Three 32-bit multiplies per output; `A` and `M` change only when
/// `c_hi` does, once per `2³²` outputs, so [`CounterX8`] keeps them in
/// registers. Statistical quality: `tools/dieharder.sh` feeds the raw stream to
/// the `dieharder` battery (results in `CHANGELOG.md`).
///
/// [^1]: G. L. Steele, D. Lea, C. H. Flood, *Fast Splittable Pseudorandom Number
///   Generators*, OOPSLA 2014.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Counter {
    offset: u64,
    a: u32,
    m: u32,
}

/// SplitMix's gamma fix-up: odd, and at least 16 bit transitions.
#[inline]
const fn gamma(m: u32) -> u32 {
    let m = m | 1;
    if (m ^ (m >> 1)).count_ones() < 16 {
        m ^ 0xAAAA_AAAA
    } else {
        m
    }
}

impl Counter {
    /// The stream with offset `offset` and words `a`, `m`.
    #[must_use]
    pub const fn from_key(offset: u64, a: u32, m: u32) -> Self {
        Counter { offset, a, m }
    }

    /// The per-`c_hi` words `(A, M)`.
    #[inline(always)]
    const fn words(&self, hi: u32) -> (u32, u32) {
        (mix32(hi ^ self.a), gamma(mix32(hi ^ self.m)))
    }

    /// Output `t`.
    #[inline]
    #[must_use]
    pub const fn at(&self, t: u64) -> u32 {
        let c = self.offset.wrapping_add(t);
        let (a, m) = self.words((c >> 32) as u32);
        mix32(((c as u32) ^ a).wrapping_mul(m))
    }

    /// Eight lanes reading outputs `first, first + stride, …`; each call to
    /// [`CounterX8::next_u32x8`] then moves every lane on by `8·stride`.
    #[must_use]
    pub fn lanes(&self, first: u64, stride: u64) -> CounterX8 {
        CounterX8(self.lanes_in(first, stride))
    }

    /// [`Counter::lanes`] in the lane type `U` of one instruction-set level
    /// (the pattern fills' dispatched copies).
    #[must_use]
    pub(crate) fn lanes_in<U: U32x8Lane>(&self, first: u64, stride: u64) -> CounterLanes<U> {
        let mut x = CounterLanes {
            lo: U::splat(0),
            hi: U::splat(0),
            wa: U::splat(0),
            wm: U::splat(0),
            step_lo: U::splat(0),
            step_hi: 0,
            key: *self,
        };
        x.place(first, stride);
        x.refresh();
        x
    }
}

/// Eight lanes of a [`Counter`] stream (see [`Counter::lanes`]); lane `l` of
/// call `b` returns output `first + (8b + l)·stride`, bit-identical to
/// [`Counter::at`].
#[derive(Clone, Debug)]
pub struct CounterX8(CounterLanes<Wu32x8>);

impl CounterX8 {
    /// Calls `f(b, out)` for `b = 0 … count − 1`, where `out` holds the next
    /// `K` results of [`CounterX8::next_u32x8`] in order; the lanes end where
    /// `K·count` calls would leave them.
    ///
    /// This is the fast way to read a long stream: between carries out of the
    /// low counter words (one per `2³²` outputs) the lanes live in registers
    /// and each vector costs the hash alone, with no carry test.
    #[inline(always)]
    pub fn chunks<const K: usize>(&mut self, count: usize, mut f: impl FnMut(usize, [u32x8; K])) {
        self.0
            .chunks(count, |b, v: [Wu32x8; K]| f(b, v.map(|x| x.0)));
    }

    /// Moves the lanes to read outputs `first, first + stride, …` again (as
    /// [`Counter::lanes`] with the same key); the per-block words are only
    /// recomputed when a lane's high counter word changed, so this is cheap
    /// enough to call per short run.
    #[inline]
    pub fn seek(&mut self, first: u64, stride: u64) {
        self.0.seek(first, stride);
    }

    /// Eight outputs, one per lane, then every lane moves on by `8·stride`.
    #[inline(always)]
    pub fn next_u32x8(&mut self) -> u32x8 {
        self.0.next().0
    }
}

/// [`CounterX8`] in the lane type `U` of one instruction-set level.
#[derive(Clone, Debug)]
pub(crate) struct CounterLanes<U> {
    lo: U,
    hi: U,
    wa: U,
    wm: U,
    step_lo: U,
    step_hi: u32,
    key: Counter,
}

impl<U: U32x8Lane> CounterLanes<U> {
    /// Recomputes the per-lane words after `c_hi` changed (rare).
    #[cold]
    fn refresh(&mut self) {
        let hi = self.hi.to_array();
        if hi.iter().all(|&h| h == hi[0]) {
            // The usual case (every lane in one 2³²-block): two hashes, not 16.
            let (a, m) = self.key.words(hi[0]);
            self.wa = U::splat(a);
            self.wm = U::splat(m);
            return;
        }
        let w = hi.map(|h| self.key.words(h));
        self.wa = U::from_array(w.map(|p| p.0));
        self.wm = U::from_array(w.map(|p| p.1));
    }

    /// [`CounterX8::chunks`].
    #[inline(always)]
    pub(crate) fn chunks<const K: usize>(
        &mut self,
        count: usize,
        mut f: impl FnMut(usize, [U; K]),
    ) {
        let mut it = self.chunk_iter::<K>(count);
        while let Some((b, v)) = it.next() {
            f(b, v);
        }
    }

    /// [`CounterLanes::chunks`] as an iterator, for bodies that must compile
    /// inside the caller (the run-time AVX2 copy; see `pattern::drive8!`):
    /// `next` is always inlined, its carry path is out of line.
    #[inline(always)]
    pub(crate) fn chunk_iter<const K: usize>(&mut self, count: usize) -> Chunks<'_, U, K> {
        let run = (self.carry_free() / K).min(count);
        Chunks {
            lo: self.lo,
            wa: self.wa,
            wm: self.wm,
            step: self.step_lo,
            step_k: self.step_lo * U::splat(K as u32),
            run,
            b: 0,
            count,
            lanes: self,
        }
    }

    /// [`CounterX8::seek`].
    #[inline]
    pub(crate) fn seek(&mut self, first: u64, stride: u64) {
        if self.place(first, stride) {
            self.refresh();
        }
    }

    /// Sets the counters and step for `first, first + stride, …` without the
    /// per-block words; returns whether a lane's high word changed.
    #[inline]
    fn place(&mut self, first: u64, stride: u64) -> bool {
        let c0 = self.key.offset.wrapping_add(first);
        let c: [u64; 8] = core::array::from_fn(|l| c0.wrapping_add(stride.wrapping_mul(l as u64)));
        let step = stride.wrapping_mul(8);
        let hi = U::from_array(c.map(|v| (v >> 32) as u32));
        self.lo = U::from_array(c.map(|v| v as u32));
        self.step_lo = U::splat(step as u32);
        self.step_hi = (step >> 32) as u32;
        let moved = hi.ne(self.hi).any();
        self.hi = hi;
        moved
    }

    /// How many steps every lane can take before a low word wraps.
    fn carry_free(&self) -> usize {
        if self.step_hi != 0 {
            return 0;
        }
        let step = self.step_lo.to_array()[0];
        if step == 0 {
            return usize::MAX;
        }
        let room = self
            .lo
            .to_array()
            .into_iter()
            .map(|lo| u32::MAX - lo)
            .min()
            .unwrap_or(0);
        (room / step) as usize
    }

    /// [`CounterX8::next_u32x8`].
    #[inline(always)]
    pub(crate) fn next(&mut self) -> U {
        let out = mix32_lanes((self.lo ^ self.wa) * self.wm);
        let lo = self.lo + self.step_lo;
        let carry = lo.lt(self.step_lo); // all ones where the low half wrapped
        self.lo = lo;
        if self.step_hi != 0 || carry.any() {
            self.hi = self.hi + U::splat(self.step_hi) - carry;
            self.refresh();
        }
        out
    }
}

/// The iterator of [`CounterLanes::chunk_iter`]: item `b` is `(b, out)`,
/// `out` the next `K` results of [`CounterLanes::next`] in order. Between
/// carries out of the low counter words (one per `2³²` outputs) each item
/// costs the hash alone; dropping it leaves the lanes where the items taken
/// would.
pub(crate) struct Chunks<'a, U: U32x8Lane, const K: usize> {
    lanes: &'a mut CounterLanes<U>,
    lo: U,
    wa: U,
    wm: U,
    step: U,
    step_k: U,
    /// Items left before a low word could wrap (or `count` is reached).
    run: usize,
    b: usize,
    count: usize,
}

impl<U: U32x8Lane, const K: usize> Chunks<'_, U, K> {
    /// The next item, `None` after `count`.
    #[inline(always)]
    #[allow(clippy::should_implement_trait)] // `Iterator::next` need not inline
    pub(crate) fn next(&mut self) -> Option<(usize, [U; K])> {
        let b = self.b;
        if self.run == 0 {
            // By value, so that `self` does not escape and stays in registers.
            let (out, lo, wa, wm, run) = carry_step::<U, K>(self.lanes, self.lo, b, self.count)?;
            (self.lo, self.wa, self.wm, self.run, self.b) = (lo, wa, wm, run, b + 1);
            return Some((b, out));
        }
        self.run -= 1;
        let mut x = self.lo;
        let mut out = [x; K];
        for o in &mut out {
            *o = mix32_lanes((x ^ self.wa) * self.wm);
            x = x + self.step;
        }
        self.lo = self.lo + self.step_k;
        self.b = b + 1;
        Some((b, out))
    }
}

/// Item `b` of [`Chunks`] through [`CounterLanes::next`], which carries into
/// the high words, with the lanes' low words at `lo`; then the lanes' new
/// `(lo, wa, wm)` and the next carry-free run. Rare: at the start and once
/// per `2³²` outputs.
#[cold]
#[inline(never)]
#[allow(clippy::type_complexity)]
fn carry_step<U: U32x8Lane, const K: usize>(
    lanes: &mut CounterLanes<U>,
    lo: U,
    b: usize,
    count: usize,
) -> Option<([U; K], U, U, U, usize)> {
    if b >= count {
        return None;
    }
    lanes.lo = lo;
    let mut out = [lo; K];
    for o in &mut out {
        *o = lanes.next();
    }
    let run = (lanes.carry_free() / K).min(count - b - 1);
    Some((out, lanes.lo, lanes.wa, lanes.wm, run))
}

impl<U: U32x8Lane, const K: usize> Drop for Chunks<'_, U, K> {
    #[inline(always)]
    fn drop(&mut self) {
        self.lanes.lo = self.lo;
    }
}

/// A 64-bit seed. A seed plus a realisation index fully determines a run.
///
/// Every random choice a pattern makes is a pure function of the seed (through
/// [`Seed::stream`]), never of thread count, SIMD width or batch size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Seed(pub u64);

impl Seed {
    /// Seed from an integer.
    #[inline]
    #[must_use]
    pub const fn new(value: u64) -> Self {
        Seed(value)
    }

    /// Seed drawn from any `rand_core` 0.10 generator; a failing source is an error.
    ///
    /// # Errors
    /// [`SeedError::Source`] if the generator reports an error.
    pub fn try_from_rng<R: rand_core::TryRng + ?Sized>(rng: &mut R) -> Result<Self, SeedError> {
        rng.try_next_u64().map(Seed).map_err(|_| SeedError::Source)
    }

    /// The seed of realisation `r` of a run seeded with `self`
    /// (`mix64(seed ⊕ mix64(r + φ))`, a bijection in `seed` for each `r`).
    #[inline]
    #[must_use]
    pub const fn realization(self, r: u64) -> Seed {
        Seed(mix64(
            self.0 ^ mix64(r.wrapping_add(GOLDEN_64).wrapping_mul(3)),
        ))
    }

    /// An independent 64-bit key for one purpose (a stream, a dimension, a shift).
    #[inline]
    #[must_use]
    pub const fn stream(self, purpose: u64) -> u64 {
        self.stream_premixed(purpose_mix(purpose))
    }

    /// [`Seed::stream`] from its purpose's half, `purpose_mix(purpose)`,
    /// computed beforehand: callers that derive many keys of fixed purposes
    /// (the Sobol' value scrambles) keep a table of them.
    #[inline(always)]
    pub(crate) const fn stream_premixed(self, premixed: u64) -> u64 {
        mix64(self.0 ^ premixed)
    }

    /// The seed of one item named by a path of purposes, e.g. `(effect,
    /// part, pixel, estimator, N, realisation)`: each step is
    /// `s ← Seed(s.stream(pᵢ))`, so `derive(&[a, b]) ==
    /// derive(&[a]).derive(&[b])`.
    ///
    /// **Distinct paths of one length give distinct seeds**, for every
    /// starting seed: a step is a bijection of the purpose for a fixed
    /// state (`p·φ + c` with odd `φ`, [`mix64`], `⊕ s` and [`mix64`] are
    /// each bijections of `u64`) and a bijection of the state for a fixed
    /// purpose, so the first component where two paths differ gives
    /// different states, and every later step keeps them apart. A caller
    /// that names every stream by a fixed-length tuple therefore cannot
    /// give two rows the same stream (as `1000·e + N` did for `N ≥ 1000`).
    #[inline]
    #[must_use]
    pub const fn derive(self, path: &[u64]) -> Seed {
        let mut s = self;
        let mut i = 0;
        while i < path.len() {
            s = Seed(s.stream(path[i]));
            i += 1;
        }
        s
    }

    /// The [`Counter`] stream for one purpose: offset `stream(purpose)`, words
    /// from `stream(purpose ⊕ 2⁶³)`.
    #[inline]
    #[must_use]
    pub const fn counter(self, purpose: u64) -> Counter {
        let w = self.stream(purpose ^ 0x8000_0000_0000_0000);
        Counter::from_key(self.stream(purpose), w as u32, (w >> 32) as u32)
    }

    /// A [`Pcg32`] for one purpose, its state and stream both derived from the seed.
    #[inline]
    #[must_use]
    pub const fn pcg(self, purpose: u64) -> Pcg32 {
        Pcg32::new(
            self.stream(purpose),
            self.stream(purpose ^ 0x8000_0000_0000_0000),
        )
    }
}

/// `⌊2⁶⁴/φ⌋`, the Weyl increment.
pub(crate) const GOLDEN_64: u64 = 0x9E37_79B9_7F4A_7C15;

/// The half of [`Seed::stream`] that depends only on the purpose:
/// `mix64(purpose·φ₆₄ + 0x632BE59BD9B4E019)`.
#[inline(always)]
pub(crate) const fn purpose_mix(purpose: u64) -> u64 {
    mix64(
        purpose
            .wrapping_mul(GOLDEN_64)
            .wrapping_add(0x632B_E59B_D9B4_E019),
    )
}

/// The first multiplier of [`mix64`].
pub(crate) const MIX64_C1: u64 = 0xFF51_AFD7_ED55_8CCD;
/// The second multiplier of [`mix64`].
pub(crate) const MIX64_C2: u64 = 0xC4CE_B9FE_1A85_EC53;

/// 64-bit finaliser (MurmurHash3 `fmix64`, Appleby 2011): a bijection on `u64`
/// with full avalanche.
#[inline]
#[must_use]
pub const fn mix64(mut x: u64) -> u64 {
    x ^= x >> 33;
    x = x.wrapping_mul(MIX64_C1);
    x ^= x >> 33;
    x = x.wrapping_mul(MIX64_C2);
    x ^= x >> 33;
    x
}

/// 32-bit finaliser (MurmurHash3 `fmix32`, Appleby 2011): a bijection on `u32`.
#[inline]
#[must_use]
pub const fn mix32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x85EB_CA6B);
    x ^= x >> 13;
    x = x.wrapping_mul(0xC2B2_AE35);
    x ^= x >> 16;
    x
}

/// Lane-wise [`mix32`].
#[inline(always)]
#[must_use]
pub fn mix32x8(x: u32x8) -> u32x8 {
    mix32_lanes(Wu32x8(x)).0
}

/// [`mix32`] in the lanes of any level.
#[inline(always)]
#[must_use]
pub(crate) fn mix32_lanes<U: U32x8Lane>(mut x: U) -> U {
    x = x ^ (x >> 16);
    x = x * U::splat(0x85EB_CA6B);
    x = x ^ (x >> 13);
    x = x * U::splat(0xC2B2_AE35);
    x ^ (x >> 16)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `derive` chains, and distinct paths of one length never collide:
    /// every path `(a, b, c)` over a grid of 64 × 64 × 64 values, near-equal
    /// and far apart, under two seeds (2^19 seeds, all distinct; a random
    /// map would collide with probability 2^-26). A path that swaps two
    /// components differs too.
    #[test]
    #[cfg(feature = "alloc")]
    fn derived_seeds_chain_and_do_not_collide() {
        let s = Seed::new(0x5eed);
        assert_eq!(s.derive(&[3, 7]), s.derive(&[3]).derive(&[7]));
        assert_eq!(s.derive(&[]), s);
        assert_ne!(s.derive(&[3, 7]), s.derive(&[7, 3]));
        let vals: [u64; 64] = core::array::from_fn(|i| match i {
            0..=31 => i as u64,
            32..=47 => 1000 + (i as u64 - 32),
            48..=55 => u64::MAX - (i as u64 - 48),
            _ => 1u64 << (i - 56 + 40),
        });
        let mut all = alloc::vec::Vec::with_capacity(2 * 64 * 64 * 64);
        for seed in [Seed::new(0), Seed::new(u64::MAX)] {
            for &a in &vals {
                for &b in &vals {
                    for &c in &vals {
                        all.push(seed.derive(&[a, b, c]).0);
                    }
                }
            }
        }
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), 2 * 64 * 64 * 64);
    }

    #[test]
    fn pcg32_reference_vector() {
        // pcg32_srandom_r(42, 54) from the PCG reference implementation's demo
        // prints 0xa15c02b7 0x7b47f409 0xba1d3330 0x83d2f293 0xbfa4784b 0xcbed606e.
        let mut g = Pcg32::new(42, 54);
        let want = [
            0xa15c02b7u32,
            0x7b47f409,
            0xba1d3330,
            0x83d2f293,
            0xbfa4784b,
            0xcbed606e,
        ];
        for w in want {
            assert_eq!(g.next_u32(), w);
        }
    }

    #[test]
    fn advance_matches_stepping() {
        let g = Pcg32::new(7, 11);
        let mut a = g.clone();
        for _ in 0..1000 {
            a.next_u32();
        }
        assert_eq!(a, g.advanced(1000));
        // a full period returns to the start
        assert_eq!(g.advanced(0).state(), g.state());
        let mut b = g.clone();
        b.advance(u64::MAX);
        b.advance(1);
        assert_eq!(b, g);
    }

    #[test]
    fn counter_lanes_match_scalar() {
        // Offsets just below a 2^32 boundary exercise the carry into c_hi (and
        // the refresh of A, M); stride 2^32 + 3 makes every step carry.
        for &(offset, first, stride) in &[
            (0u64, 0u64, 1u64),
            (12_345, 7, 3),
            ((1 << 32) - 13, 0, 1),
            ((3 << 32) - 40, 5, 3),
            (u64::MAX - 30, 0, 2),
            (99, 0, (1 << 32) + 3),
        ] {
            let key = Counter::from_key(offset, 0x1234_5678, 0x9ABC_DEF0);
            let mut lanes = key.lanes(first, stride);
            for b in 0..16u64 {
                let out = lanes.next_u32x8().to_array();
                for (l, &v) in out.iter().enumerate() {
                    let t = first.wrapping_add((8 * b + l as u64).wrapping_mul(stride));
                    assert_eq!(v, key.at(t), "offset {offset} stride {stride} b {b} l {l}");
                }
            }
        }
    }

    #[test]
    fn chunks_and_seek_match_scalar_across_carries() {
        // Offsets just below a 2³² boundary, so that reads cross a carry out
        // of the low counter word (chunks' slow step) at varying positions.
        for (o, stride) in [
            ((1u64 << 32) - 37, 1u64),
            ((5u64 << 32) - 100, 2),
            ((1u64 << 33) - 7, 3),
        ] {
            let key = Counter::from_key(o, 0x1234_5678, 0x9ABC_DEF1);
            for first in [0u64, 5, 13] {
                let check = |got: &[u32x8], from: u64, what: &str| {
                    for (v, g) in got.iter().enumerate() {
                        for (l, &x) in g.to_array().iter().enumerate() {
                            let t = from + (8 * v + l) as u64 * stride;
                            assert_eq!(
                                x,
                                key.at(t),
                                "{what} o {o} first {first} vector {v} lane {l}"
                            );
                        }
                    }
                };
                let mut lanes = key.lanes(first, stride);
                let mut got = [u32x8::ZERO; 21];
                lanes.chunks::<3>(7, |b, out| got[3 * b..3 * b + 3].copy_from_slice(&out));
                check(&got, first, "chunks");
                // The lanes continue where 21 next_u32x8 calls would leave them.
                check(
                    &[lanes.next_u32x8()],
                    first + 21 * 8 * stride,
                    "after chunks",
                );
                // Seeking back and forth reads the same outputs again.
                lanes.seek(first, stride);
                let again: [u32x8; 21] = core::array::from_fn(|_| lanes.next_u32x8());
                check(&again, first, "seek");
                lanes.seek(first + (1 << 40), stride);
                lanes.seek(first, stride);
                check(&[lanes.next_u32x8()], first, "seek far and back");
            }
        }
    }

    #[test]
    fn counter_is_a_bijection_per_block_and_keys_differ() {
        // For fixed c_hi, c_lo -> out is a bijection: no repeat in 2^16 outputs
        // (a random function would repeat with probability 1 - e^{-1/2}).
        let key = Seed::new(5).counter(1);
        let mut v: [u32; 1 << 16] = core::array::from_fn(|t| key.at(t as u64));
        v.sort_unstable();
        assert!(v.windows(2).all(|w| w[0] != w[1]));
        // Different purposes and seeds give different streams.
        assert_ne!(Seed::new(5).counter(2).at(0), key.at(0));
        assert_ne!(Seed::new(6).counter(1).at(0), key.at(0));
        // gamma: odd, and at least 16 transitions.
        for m in [0u32, 1, 0xFFFF_FFFF, 0x0000_FFFF, 0x1234_5678] {
            let g = gamma(m);
            assert_eq!(g & 1, 1);
            assert!((g ^ (g >> 1)).count_ones() >= 15, "{m:#x} -> {g:#x}");
        }
    }

    #[test]
    fn lanes_match_scalar() {
        let g = Pcg32::new(123, 456);
        for &(first, stride) in &[(0u64, 1u64), (5, 1), (3, 2), (1000, 3), (u64::MAX - 20, 7)] {
            let mut lanes = Pcg32x8::new(&g, first, stride);
            let mut s = g.advanced(first);
            let mut scalar = [0u32; 64 * 7];
            for v in scalar.iter_mut() {
                *v = s.next_u32();
            }
            for b in 0..8 {
                let out = lanes.next_u32x8().to_array();
                for (l, &v) in out.iter().enumerate() {
                    let t = ((8 * b + l) as u64 * stride) as usize;
                    assert_eq!(
                        v, scalar[t],
                        "first {first} stride {stride} block {b} lane {l}"
                    );
                }
            }
        }
    }
}
