//! Uniform random points.

use super::sealed::{Generate, Sink};
use super::{array, build, check_dims, check_n, drive8, unit_f32, unit_f32x8, Aos};
use crate::error::PatternError;
use crate::num::lane::Lane;
use crate::rng::{CounterLanes, Seed};
use crate::simd::Isa;

/// `N` independent uniform points in `[0,1)^D` (white noise).
///
/// Coordinate `j` of point `k` is `⌊o_t / 2⁸⌋·2⁻²⁴` where `o_t` is output
/// `t = k·D + j` of the counter-based stream [`Counter`](crate::rng::Counter)
/// `seed.counter(RANDOM)`. The SIMD path reads the same outputs through
/// [`CounterX8`](crate::rng::CounterX8) lanes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Random<const D: usize> {
    n: u64,
}

/// Seed purpose of [`Random`].
const PURPOSE: u64 = 0x5241_4E44;

impl<const D: usize> Random<D> {
    /// `n` uniform points.
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

impl<const D: usize> Generate<D> for Random<D> {
    fn n(&self) -> u64 {
        self.n
    }

    #[inline(always)]
    fn gen_simd<I: Isa, S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let key = seed.counter(PURPOSE);
        let d = D as u64;
        if let Some(flat) = sink.flat() {
            // Flat index i is stream output first·D + i: eight consecutive
            // outputs per vector, stored whole; the last point or few by the
            // scalar path (a point split by the last vector is written twice,
            // with the same value).
            let vectors = flat.len() / 8;
            let mut lanes = key.lanes_in::<I::U32>(first * d, 1);
            let mut it = lanes.chunk_iter::<1>(vectors);
            while let Some((b, [bits])) = it.next() {
                unit_f32x8(bits).store(&mut flat[8 * b..8 * b + 8]);
            }
            let done = 8 * vectors / D;
            let (points, _) = flat.as_chunks_mut::<D>();
            self.gen_scalar(seed, first + done as u64, &mut Aos(&mut points[done..]));
            return;
        }
        let mut lanes: [CounterLanes<I::U32>; D] =
            core::array::from_fn(|j| key.lanes_in(first.wrapping_mul(d) + j as u64, d));
        drive8!(
            sink,
            I::U32,
            array!(I::F32::splat(0.0), |j| unit_f32x8(lanes[j].next()))
        );
    }

    fn gen_scalar<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let key = seed.counter(PURPOSE);
        let d = D as u64;
        for i in 0..sink.len() {
            let t = (first + i as u64) * d;
            let p = build(0.0, |j| unit_f32(key.at(t + j as u64)));
            sink.put(i, p);
        }
    }
}
