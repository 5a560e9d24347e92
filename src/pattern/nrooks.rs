//! N-rooks (Latin hypercube) sampling.

use super::sealed::{Generate, Sink};
use super::{build, check_dims, check_n, drive32, Strata, MAX_STRATA};
use crate::error::PatternError;
use crate::hash::{permute, PermuteX8};
use crate::rng::{CounterX8, Seed};
use wide::{f32x8, u32x8};

/// N-rooks sampling (Latin hypercube, McKay, Beckman & Conover 1979; Shirley 1991):
/// every axis is cut into `N` strata and each stratum of each axis holds exactly one
/// point, `x_j(k) = (π_j(k) + u_j)/N` with independent random permutations `π_j`.
///
/// The permutations are hash-based bijections with random access
/// ([`crate::hash::permute`]), so any range of points is computed without
/// building a permutation table. `N ≤ 2²⁴`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NRooks<const D: usize> {
    n: u32,
}

const PURPOSE: u64 = 0x524F_4F4B;

impl<const D: usize> NRooks<D> {
    /// `n` points.
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`], [`PatternError::Dims`] unless `1 ≤ D ≤ 3`,
    /// [`PatternError::TooManyPoints`] for `n > 2²⁴`.
    pub fn new(n: usize) -> Result<Self, PatternError> {
        check_dims::<D>(1, 3)?;
        Ok(Self {
            n: check_n(n, MAX_STRATA)? as u32,
        })
    }

    fn keys(seed: Seed) -> [u32; D] {
        core::array::from_fn(|j| seed.stream(PURPOSE + 1 + j as u64) as u32)
    }
}

impl<const D: usize> Generate<D> for NRooks<D> {
    fn n(&self) -> u64 {
        u64::from(self.n)
    }

    fn gen_simd<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let key = seed.counter(PURPOSE);
        let d = D as u64;
        let mut lanes: [CounterX8; D] =
            core::array::from_fn(|j| key.lanes(first * d + j as u64, d));
        let perms = Self::keys(seed).map(|k| PermuteX8::new(self.n, u32x8::splat(k)));
        let axis = Strata::new(self.n);
        let n = self.n;
        // Lanes past the end (last partial group) are wrapped into [0, n) and discarded.
        let mut k = u32x8::new(core::array::from_fn(|l| {
            ((first + l as u64) % u64::from(n)) as u32
        }));
        let vn = u32x8::splat(n);
        let mut step = || {
            let cur = k;
            let mut next = k + u32x8::splat(8);
            loop {
                let over = next.simd_ge(vn);
                if !over.any() {
                    break;
                }
                next -= over & vn;
            }
            k = next;
            cur
        };
        drive32(sink, || {
            let ks: [u32x8; 4] = build(u32x8::ZERO, |_| step());
            let cells: [[u32x8; 4]; D] =
                build([u32x8::ZERO; 4], |j| PermuteX8::apply4([&perms[j]; 4], ks));
            build([f32x8::ZERO; D], |b| {
                build(f32x8::ZERO, |j| {
                    axis.point_x8(cells[j][b], lanes[j].next_u32x8())
                })
            })
        });
    }

    fn gen_scalar<S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        let key = seed.counter(PURPOSE);
        let keys = Self::keys(seed);
        let axis = Strata::new(self.n);
        for i in 0..sink.len() {
            let k = first + i as u64;
            let p = build(0.0, |j| {
                axis.point(
                    permute(k as u32, self.n, keys[j]),
                    key.at(k * D as u64 + j as u64),
                )
            });
            sink.put(i, p);
        }
    }
}
