//! N-rooks (Latin hypercube) sampling.

use super::sealed::{Generate, Sink};
use super::{build, check_dims, check_n, drive32, put_flat, Aos, Strata, StrataX8, MAX_STRATA};
use crate::error::PatternError;
use crate::hash::{apply16, in_sixteen_bits, permute, PermuteX16, PermuteX8, Shape, KEY_WORDS};
use crate::num::lane::Wu32x8;
use crate::num::lane::{IntLane, Lane, U16x16Lane, U32x8Lane};
use crate::rng::{CounterX8, Seed};
use crate::simd::Isa;
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

/// The flat (point-major) path of [`NRooks`]: a chunk of `K` vectors (`K/D`
/// blocks of 8 points) holds consecutive stream outputs; lane `l` of vector
/// `w` holds axis `(8w + l) mod D` of point `⌊(8w + l)/D⌋` of the chunk, so
/// each vector permutes with per-lane axis keys and is stored whole. The
/// expression `$cells`, with `$k` the chunk's first point, gives its `K`
/// vectors of strata as `[I::F32; K]`; the points past the last whole chunk
/// go through the scalar path. A macro so that `$cells` compiles in place in
/// the dispatched AVX2 copy (see `pattern::drive8!`).
macro_rules! gen_flat {
    ($self:ident, $I:ty, $K:expr, $seed:expr, $first:expr, $flat:expr, |$k:ident| $cells:expr) => {{
        let (seed, first, flat): (Seed, u64, &mut [f32]) = ($seed, $first, $flat);
        let sx = [StrataX8::<<$I as Isa>::U32>::new([Strata::new($self.n); 8]); $K];
        let per_chunk = 8 * $K / D; // points
        let chunks = flat.len() / (8 * $K);
        let mut lanes = seed
            .counter(PURPOSE)
            .lanes_in::<<$I as Isa>::U32>(first * D as u64, 1);
        let mut it = lanes.chunk_iter::<{ $K }>(chunks);
        while let Some((b, bits)) = it.next() {
            let $k = first + (per_chunk * b) as u64;
            let cells: [<$I as Isa>::F32; $K] = $cells;
            put_flat(&sx, &cells, &bits, &mut flat[8 * $K * b..8 * $K * (b + 1)]);
        }
        let done = per_chunk * chunks;
        let (points, _) = flat.as_chunks_mut::<D>();
        $self.gen_scalar(seed, first + done as u64, &mut Aos(&mut points[done..]));
    }};
}

impl<const D: usize> NRooks<D> {
    /// [`gen_flat!`] in 32-bit lanes, four chains at a time
    /// ([`PermuteX8::apply4`]), in `wide`'s types at every level. Out of
    /// line: it gains nothing from the AVX2 copy, and inlined beside the
    /// narrow path it made that path's loop 30 % slower (v3, 2D, 65536).
    #[inline(never)]
    fn gen_flat32<const K: usize>(&self, seed: Seed, first: u64, flat: &mut [f32]) {
        let keys = Self::keys(seed);
        let perms: [PermuteX8; D] = core::array::from_fn(|v| {
            PermuteX8::new(
                self.n,
                u32x8::new(core::array::from_fn(|l| keys[(8 * v + l) % D])),
            )
        });
        let offs: [u32x8; K] = core::array::from_fn(|w| {
            u32x8::new(core::array::from_fn(|l| ((8 * w + l) / D) as u32))
        });
        gen_flat!(self, crate::simd::Wide, K, seed, first, flat, |k| {
            // Every lane is a point of the range, so below n.
            let k0 = u32x8::splat(k as u32);
            let mut cells = [f32x8::ZERO; K];
            for g in (0..K).step_by(4) {
                // Pads (w ≥ K) repeat vector g: valid input, result unused.
                let w = |i: usize| if g + i < K { g + i } else { g };
                let c = PermuteX8::apply4(
                    core::array::from_fn(|i| &perms[w(i) % D]),
                    core::array::from_fn(|i| k0 + offs[w(i)]),
                );
                for i in 0..4.min(K - g) {
                    cells[g + i] = f32x8::from_i32x8(bytemuck::cast(c[i]));
                }
            }
            cells
        });
    }

    /// [`gen_flat!`] for narrow domains (`16 < n ≤ 2¹⁶`), in the lanes of the
    /// level `I`: the permutations run in sixteen 16-bit lanes
    /// ([`crate::hash::apply16`]), `H = K/2` vectors interleaved. Same values.
    #[inline(always)]
    fn gen_flat16<I: Isa, const K: usize, const H: usize>(
        &self,
        seed: Seed,
        first: u64,
        flat: &mut [f32],
    ) {
        debug_assert_eq!(K, 2 * H);
        let keys = Self::keys(seed);
        let shape = Shape::new(self.n);
        // Vector c of sixteen lanes holds flat coordinates 16c + l: axis
        // (16c + l) mod D, which depends on c only through c mod D.
        let words: [[I::U16; KEY_WORDS]; D] = core::array::from_fn(|p| {
            let lane_keys =
                |o: usize| u32x8::new(core::array::from_fn(|l| keys[(16 * p + o + l) % D]));
            PermuteX16::new(self.n, lane_keys(0), lane_keys(8)).words_in::<I::U16>()
        });
        let offs: [I::U16; H] = core::array::from_fn(|c| {
            I::U16::from_array(core::array::from_fn(|l| ((16 * c + l) / D) as u16))
        });
        gen_flat!(self, I, K, seed, first, flat, |k| {
            // Point indices are below n ≤ 2¹⁶: they fit the lanes.
            let k0 = I::U16::splat(k as u32);
            let mut idx = offs;
            for x in &mut idx {
                *x = k0 + *x;
            }
            let out = apply16(&shape, idx, |c, w| words[c % D][w]);
            let mut cells = [I::F32::splat(0.0); K];
            for c in 0..H {
                let [lo, hi] = out[c].widen();
                cells[2 * c] = lo.to_f32();
                cells[2 * c + 1] = hi.to_f32();
            }
            cells
        });
    }
}

impl<const D: usize> Generate<D> for NRooks<D> {
    fn n(&self) -> u64 {
        u64::from(self.n)
    }

    #[inline(always)]
    fn gen_simd<I: Isa, S: Sink<D>>(&self, seed: Seed, first: u64, sink: &mut S) {
        // The narrow flat path runs in the lanes of the level `I`; the wide
        // flat path and the sink path below use `wide`'s types at every level.
        let key = seed.counter(PURPOSE);
        let d = D as u64;
        if let Some(flat) = sink.flat() {
            // 32-bit lanes: chunks of 4 vectors in 1D and 2D, of 12 in 3D (the
            // fastest of 3, 4, 6, 8 and 12 measured). 16-bit lanes (narrow
            // domains): 8 in 1D and 2D (four 16-lane chains; 8% faster than
            // 4 at 2D 65536), 12 in 3D.
            match (D, in_sixteen_bits(self.n)) {
                (1 | 2, true) => self.gen_flat16::<I, 8, 4>(seed, first, flat),
                (_, true) => self.gen_flat16::<I, 12, 6>(seed, first, flat),
                (1 | 2, false) => self.gen_flat32::<4>(seed, first, flat),
                _ => self.gen_flat32::<12>(seed, first, flat),
            }
            return;
        }
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
        drive32::<D, S, Wu32x8>(sink, || {
            let ks: [u32x8; 4] = build(u32x8::ZERO, |_| step());
            let cells: [[u32x8; 4]; D] =
                build([u32x8::ZERO; 4], |j| PermuteX8::apply4([&perms[j]; 4], ks));
            build([f32x8::ZERO; D], |b| {
                build(f32x8::ZERO, |j| {
                    axis.point_x8(Wu32x8(cells[j][b]), Wu32x8(lanes[j].next_u32x8()))
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
