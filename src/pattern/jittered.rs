//! Jittered (stratified) sampling.

use super::sealed::{Generate, Sink};
use super::{
    advance8, array, build, check_dims, drive8, f32_lanes, lanes_of, odometer_step, put_flat, Aos,
    Strata, StrataX8, MAX_STRATA,
};
use crate::error::PatternError;
use crate::num::lane::{F32Lane, Lane, U32x8Lane};
use crate::rng::{CounterLanes, Seed};
use crate::simd::Isa;

/// Jittered sampling: the unit cube is cut into `m₁×…×m_D` equal cells and each
/// cell gets one uniform point, `x_j = (c_j + u_j)/m_j`.
///
/// Point `k` lies in cell `c` with `k = c₁ + m₁·(c₂ + m₂·c₃)` (axis 1 fastest).
/// The jitter `u_j` of point `k` comes from output `k·D + j` of the counter-based
/// stream `seed.counter(JITTER)` ([`Counter`](crate::rng::Counter)). Exact cell membership of the `f32` coordinates is
/// guaranteed (see the [module docs](super)).
///
/// Variance for smooth integrands falls as `O(N^{-1-2/D})`, for integrands with a
/// C0 discontinuity as `O(N^{-1-1/D})` (Pilleboue et al. 2015).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Jittered<const D: usize> {
    strata: [u32; D],
    n: u64,
}

const PURPOSE: u64 = 0x4A49_5454;

impl<const D: usize> Jittered<D> {
    /// Jittered pattern with `strata[j]` cells along axis `j`; `N = ∏ strata[j]`.
    ///
    /// # Errors
    /// [`PatternError::Dims`] unless `1 ≤ D ≤ 3`; [`PatternError::ZeroStrata`] for a
    /// zero count; [`PatternError::TooManyPoints`] if a count exceeds 2²⁴ or the
    /// product exceeds 2³².
    pub fn new(strata: [usize; D]) -> Result<Self, PatternError> {
        check_dims::<D>(1, 3)?;
        let mut n: u64 = 1;
        for (axis, &m) in strata.iter().enumerate() {
            if m == 0 {
                return Err(PatternError::ZeroStrata { axis });
            }
            if m as u64 > MAX_STRATA {
                return Err(PatternError::TooManyPoints { max: MAX_STRATA });
            }
            n = n.saturating_mul(m as u64);
        }
        if n > 1 << 32 {
            return Err(PatternError::TooManyPoints { max: 1 << 32 });
        }
        Ok(Self {
            strata: strata.map(|m| m as u32),
            n,
        })
    }

    /// Jittered pattern of `n` points with the given per-axis counts, which must
    /// multiply to `n`.
    ///
    /// # Errors
    /// As [`Jittered::new`], plus [`PatternError::ZeroPoints`] for `n = 0` and
    /// [`PatternError::StrataMismatch`] if the product is not `n`.
    pub fn with_n(n: usize, strata: [usize; D]) -> Result<Self, PatternError> {
        if n == 0 {
            return Err(PatternError::ZeroPoints);
        }
        let j = Self::new(strata)?;
        if j.n != n as u64 {
            return Err(PatternError::StrataMismatch {
                product: j.n,
                n: n as u64,
            });
        }
        Ok(j)
    }

    /// The most cubical grid for `n` points (`m^D = n`); `n` must be a perfect
    /// `D`-th power.
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`] for `n = 0`; [`PatternError::StrataMismatch`] if
    /// `n` is not a perfect `D`-th power.
    pub fn cube(n: usize) -> Result<Self, PatternError> {
        check_dims::<D>(1, 3)?;
        if n == 0 {
            return Err(PatternError::ZeroPoints);
        }
        let m = crate::num::scalar::round(libm::pow(n as f64, 1.0 / D as f64)) as usize;
        Self::with_n(n, [m.max(1); D])
    }

    /// Cells per axis.
    #[must_use]
    pub fn strata(&self) -> [usize; D] {
        self.strata.map(|m| m as usize)
    }

    /// The flat (point-major) fast path: blocks of 8 points, which share every
    /// cell digit but the first when `m₁` and `first` are multiples of 8, are
    /// `D` vectors of consecutive stream outputs; vector `v`, lane `l` holds
    /// axis `(8v + l) mod D` of point `⌊(8v + l)/D⌋` of the block.
    #[inline(always)]
    fn gen_flat<I: Isa>(&self, seed: Seed, first: u64, flat: &mut [f32]) {
        let key = seed.counter(PURPOSE);
        let axis = |v: usize, l: usize| (8 * v + l) % D;
        let axes: [Strata; D] = self.strata.map(Strata::new);
        let sx: [StrataX8<I::U32>; D] =
            core::array::from_fn(|v| StrataX8::new(core::array::from_fn(|l| axes[axis(v, l)])));
        let step: [I::F32; D] = core::array::from_fn(|v| {
            f32_lanes(core::array::from_fn(|l| {
                if axis(v, l) == 0 {
                    8.0
                } else {
                    0.0
                }
            }))
        });
        let m0 = self.strata[0];
        let mut cell = self.cell_of(first);
        let mut cf = Self::cell_lanes::<I::F32>(&cell);
        let mut row_left = (m0 - cell[0]) / 8;
        let blocks = flat.len() / (8 * D);
        let mut lanes = key.lanes_in::<I::U32>(first * D as u64, 1);
        let mut it = lanes.chunk_iter::<D>(blocks);
        while let Some((b, bits)) = it.next() {
            put_flat(&sx, &cf, &bits, &mut flat[8 * D * b..8 * D * (b + 1)]);
            row_left -= 1;
            if row_left == 0 {
                self.next_row(&mut cell, &mut cf);
                row_left = m0 / 8;
            } else {
                for v in 0..D {
                    cf[v] = cf[v] + step[v];
                }
            }
        }
        let done = 8 * blocks;
        let (points, _) = flat.as_chunks_mut::<D>();
        self.gen_scalar(seed, first + done as u64, &mut Aos(&mut points[done..]));
    }

    /// The cells of a flat block's lanes (see [`Jittered::gen_flat`]) whose
    /// first point is in `cell`, exact in `f32` (every count is ≤ 2²⁴).
    fn cell_lanes<F: F32Lane>(cell: &[u32; D]) -> [F; D] {
        core::array::from_fn(|v| {
            f32_lanes(core::array::from_fn(|l| {
                let (a, q) = ((8 * v + l) % D, ((8 * v + l) / D) as u32);
                (cell[a] + if a == 0 { q } else { 0 }) as f32
            }))
        })
    }

    /// Moves a flat block from the end of a row to the start of the next one.
    /// Rare (once per `m₁/8` blocks) and out of line, so that the per-block
    /// code stays small enough to inline.
    #[cold]
    #[inline(never)]
    fn next_row<F: F32Lane>(&self, cell: &mut [u32; D], cf: &mut [F; D]) {
        cell[0] = self.strata[0] - 8;
        for _ in 0..8 {
            odometer_step(cell, &self.strata);
        }
        *cf = Self::cell_lanes(cell);
    }

    fn cell_of(&self, mut k: u64) -> [u32; D] {
        core::array::from_fn(|j| {
            let m = u64::from(self.strata[j]);
            let c = k % m;
            k /= m;
            c as u32
        })
    }
}

impl<const D: usize> Generate<D> for Jittered<D> {
    fn n(&self) -> u64 {
        self.n
    }

    #[inline(always)]
    fn gen_simd<I: Isa, S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let key = seed.counter(PURPOSE);
        let d = D as u64;
        if let Some(flat) = sink.flat() {
            if self.strata[0].is_multiple_of(8) && first.is_multiple_of(8) {
                self.gen_flat::<I>(seed, first, flat);
                return;
            }
        }
        let mut lanes: [CounterLanes<I::U32>; D] =
            core::array::from_fn(|j| key.lanes_in(first * d + j as u64, d));
        let sx: [StrataX8<I::U32>; D] =
            core::array::from_fn(|j| StrataX8::new([Strata::new(self.strata[j]); 8]));
        let vm: [I::U32; D] = self.strata.map(I::U32::splat);
        // Per-lane cell counters for points first + l, advanced by 8 per block.
        let mut cell: [I::U32; D] = lanes_of(|l| self.cell_of(first + l as u64));
        drive8!(sink, I::U32, {
            let out: [I::F32; D] = array!(I::F32::splat(0.0), |j| sx[j]
                .point_x8(cell[j].to_f32(), lanes[j].next()));
            advance8(&mut cell, &vm);
            out
        });
    }

    fn gen_scalar<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let key = seed.counter(PURPOSE);
        let axes: [Strata; D] = self.strata.map(Strata::new);
        let mut cell = self.cell_of(first);
        for i in 0..sink.len() {
            let t = (first + i as u64) * D as u64;
            let p = build(0.0, |j| axes[j].point(cell[j], key.at(t + j as u64)));
            sink.put(i, p);
            odometer_step(&mut cell, &self.strata);
        }
    }
}
