//! AVX2 lane types for the run-time dispatched copies of the batch kernels
//! ([`crate::simd`]): [`F32x8`] and [`F64x4`], 256-bit vectors over
//! `core::arch`, implementing the same [`Lane`], [`F32Lane`] and [`F64Lane`]
//! traits as `wide`'s `f32x8` and `f64x4`, with the same IEEE operations
//! (so the same bits, lane by lane; `tests` below and `tests/simd.rs`).
//!
//! Why not `wide`: `wide` chooses its instructions when it is compiled, so in
//! a baseline build its `f32x8` is two SSE2 halves even inside a function
//! compiled with AVX2 enabled. These types are used only inside such
//! functions (after the CPU check of [`crate::simd::dispatch`]); every method
//! is `#[inline(always)]` so that the intrinsics inline into them.
//!
//! Semantics, the same as the `wide` instantiation's: `min`/`max` are
//! `vminps`/`vmaxps` (`a < b ? a : b`, and `b` if either is NaN), `floor` is
//! `vroundps` towards `−∞` (exact), `sqrt` is the correctly rounded `vsqrtps`,
//! comparisons are ordered and quiet (false for NaN), `select` takes the
//! whole lane from the mask's sign bit (masks are all-ones or all-zeros).

use super::lane::{F32Lane, F64Lane, IntLane, Lane, U16x16Lane, U32x8Lane};
use core::arch::x86_64::{
    __m256, __m256d, __m256i, _mm256_add_epi16, _mm256_add_epi32, _mm256_add_epi64, _mm256_add_pd,
    _mm256_add_ps, _mm256_and_pd, _mm256_and_ps, _mm256_and_si256, _mm256_andnot_pd,
    _mm256_andnot_ps, _mm256_blendv_epi8, _mm256_blendv_pd, _mm256_blendv_ps, _mm256_castps_si256,
    _mm256_castsi256_pd, _mm256_castsi256_ps, _mm256_castsi256_si128, _mm256_cmp_pd, _mm256_cmp_ps,
    _mm256_cmpeq_epi16, _mm256_cmpeq_epi32, _mm256_cmpgt_epi32, _mm256_cvtepi32_epi64,
    _mm256_cvtepi32_ps, _mm256_cvtepu16_epi32, _mm256_cvtpd_epi32, _mm256_cvtps_epi32,
    _mm256_div_pd, _mm256_div_ps, _mm256_extracti128_si256, _mm256_loadu_pd, _mm256_loadu_ps,
    _mm256_loadu_si256, _mm256_max_epu16, _mm256_max_pd, _mm256_max_ps, _mm256_min_pd,
    _mm256_min_ps, _mm256_movemask_epi8, _mm256_movemask_pd, _mm256_movemask_ps, _mm256_mul_pd,
    _mm256_mul_ps, _mm256_mullo_epi16, _mm256_mullo_epi32, _mm256_or_si256,
    _mm256_permute2x128_si256, _mm256_round_pd, _mm256_round_ps, _mm256_set1_epi16,
    _mm256_set1_epi32, _mm256_set1_epi64x, _mm256_set1_pd, _mm256_set1_ps, _mm256_sll_epi16,
    _mm256_sll_epi32, _mm256_slli_epi32, _mm256_slli_epi64, _mm256_sqrt_pd, _mm256_sqrt_ps,
    _mm256_srl_epi16, _mm256_srl_epi32, _mm256_storeu_pd, _mm256_storeu_ps, _mm256_storeu_si256,
    _mm256_sub_epi16, _mm256_sub_epi32, _mm256_sub_pd, _mm256_sub_ps, _mm256_unpackhi_epi32,
    _mm256_unpacklo_epi32, _mm256_xor_pd, _mm256_xor_ps, _mm256_xor_si256, _mm_cvtsi32_si128,
    _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _MM_FROUND_NO_EXC, _MM_FROUND_TO_NEG_INF,
};
use core::ops::{Add, BitAnd, BitOr, BitXor, BitXorAssign, Div, Mul, Neg, Shl, Shr, Sub};

/// Eight `f32` lanes in one AVX register.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F32x8(__m256);

/// Four `f64` lanes in one AVX register.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F64x4(__m256d);

macro_rules! binop {
    ($t:ident, $tr:ident, $m:ident, $f:ident) => {
        impl $tr for $t {
            type Output = $t;
            #[inline(always)]
            fn $m(self, o: $t) -> $t {
                // SAFETY: these types exist only in AVX2 code paths, entered
                // after the CPU check (`simd::dispatch`).
                $t(unsafe { $f(self.0, o.0) })
            }
        }
    };
}

binop!(F32x8, Add, add, _mm256_add_ps);
binop!(F32x8, Sub, sub, _mm256_sub_ps);
binop!(F32x8, Mul, mul, _mm256_mul_ps);
binop!(F32x8, Div, div, _mm256_div_ps);
binop!(F64x4, Add, add, _mm256_add_pd);
binop!(F64x4, Sub, sub, _mm256_sub_pd);
binop!(F64x4, Mul, mul, _mm256_mul_pd);
binop!(F64x4, Div, div, _mm256_div_pd);

impl Neg for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn neg(self) -> F32x8 {
        // SAFETY: AVX2 code paths only (see `binop!`).
        F32x8(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
    }
}

impl Neg for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn neg(self) -> F64x4 {
        // SAFETY: AVX2 code paths only (see `binop!`).
        F64x4(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
    }
}

macro_rules! avx_lane {
    ($t:ident, $s:ty, $n:expr, $set1:ident, $loadu:ident, $storeu:ident, $sqrt:ident,
     $andnot:ident, $min:ident, $max:ident, $round:ident, $cmp:ident, $blendv:ident,
     $movemask:ident, $and:ident) => {
        impl Lane for $t {
            type Scalar = $s;
            type Mask = $t;
            const LANES: usize = $n;
            #[inline(always)]
            fn splat(x: $s) -> Self {
                // SAFETY (every method): AVX2 code paths only (see `binop!`).
                $t(unsafe { $set1(x) })
            }
            #[inline(always)]
            fn load(s: &[$s]) -> Self {
                let s = &s[..$n];
                // SAFETY: `s` has `$n` elements (checked above); unaligned load.
                $t(unsafe { $loadu(s.as_ptr()) })
            }
            #[inline(always)]
            fn store(self, s: &mut [$s]) {
                let s = &mut s[..$n];
                // SAFETY: `s` has `$n` elements (checked above); unaligned store.
                unsafe { $storeu(s.as_mut_ptr(), self.0) }
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $t(unsafe { $sqrt(self.0) })
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $t(unsafe { $andnot($set1(-0.0), self.0) })
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                $t(unsafe { $min(self.0, o.0) })
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                $t(unsafe { $max(self.0, o.0) })
            }
            #[inline(always)]
            fn floor(self) -> Self {
                $t(unsafe { $round::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(self.0) })
            }
            #[inline(always)]
            fn lt(self, o: Self) -> Self {
                $t(unsafe { $cmp::<_CMP_LT_OQ>(self.0, o.0) })
            }
            #[inline(always)]
            fn le(self, o: Self) -> Self {
                $t(unsafe { $cmp::<_CMP_LE_OQ>(self.0, o.0) })
            }
            #[inline(always)]
            fn gt(self, o: Self) -> Self {
                $t(unsafe { $cmp::<_CMP_GT_OQ>(self.0, o.0) })
            }
            #[inline(always)]
            fn select(m: Self, a: Self, b: Self) -> Self {
                $t(unsafe { $blendv(b.0, a.0, m.0) })
            }
            #[inline(always)]
            fn any(m: Self) -> bool {
                unsafe { $movemask(m.0) != 0 }
            }
            #[inline(always)]
            fn and(a: Self, b: Self) -> Self {
                $t(unsafe { $and(a.0, b.0) })
            }
        }
    };
}

avx_lane!(
    F32x8,
    f32,
    8,
    _mm256_set1_ps,
    _mm256_loadu_ps,
    _mm256_storeu_ps,
    _mm256_sqrt_ps,
    _mm256_andnot_ps,
    _mm256_min_ps,
    _mm256_max_ps,
    _mm256_round_ps,
    _mm256_cmp_ps,
    _mm256_blendv_ps,
    _mm256_movemask_ps,
    _mm256_and_ps
);
avx_lane!(
    F64x4,
    f64,
    4,
    _mm256_set1_pd,
    _mm256_loadu_pd,
    _mm256_storeu_pd,
    _mm256_sqrt_pd,
    _mm256_andnot_pd,
    _mm256_min_pd,
    _mm256_max_pd,
    _mm256_round_pd,
    _mm256_cmp_pd,
    _mm256_blendv_pd,
    _mm256_movemask_pd,
    _mm256_and_pd
);

impl F32Lane for F32x8 {
    /// `2^n` from the exponent bits: `(n + 127) << 23`, `n` converted with
    /// `vcvtps2dq` (exact for the integral `n` the contract allows).
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        // SAFETY: AVX2 code paths only (see `binop!`).
        unsafe {
            let e = _mm256_add_epi32(_mm256_cvtps_epi32(n.0), _mm256_set1_epi32(127));
            F32x8(_mm256_castsi256_ps(_mm256_slli_epi32::<23>(e)))
        }
    }
}

impl F64Lane for F64x4 {
    /// `2^n` from the exponent bits: `(n + 1023) << 52`, `n` converted to 32
    /// bits (`vcvtpd2dq`, exact for the integral `n ∈ [−1022, 1023]` the
    /// contract allows) and widened to 64.
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        // SAFETY: AVX2 code paths only (see `binop!`).
        unsafe {
            let i = _mm256_cvtepi32_epi64(_mm256_cvtpd_epi32(n.0));
            let e = _mm256_add_epi64(i, _mm256_set1_epi64x(1023));
            F64x4(_mm256_castsi256_pd(_mm256_slli_epi64::<52>(e)))
        }
    }
}

/// Eight `u32` lanes in one AVX2 register: [`U32x8Lane`] for the pattern
/// generators' run-time AVX2 copy (`vpmulld` for the wrapping multiply,
/// unsigned comparisons as signed ones of the lanes with their top bit
/// flipped).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct U32x8(__m256i);

macro_rules! ibinop {
    ($t:ident, $tr:ident, $m:ident, $f:ident) => {
        impl $tr for $t {
            type Output = $t;
            #[inline(always)]
            fn $m(self, o: $t) -> $t {
                // SAFETY: AVX2 code paths only (see `binop!`).
                $t(unsafe { $f(self.0, o.0) })
            }
        }
    };
}

/// Shifts of every lane by one count (`vpsrl*`/`vpsll*` with the count in
/// an `xmm` register).
macro_rules! ishift {
    ($t:ident, $srl:ident, $sll:ident) => {
        impl Shr<u32> for $t {
            type Output = $t;
            #[inline(always)]
            fn shr(self, n: u32) -> $t {
                // SAFETY: AVX2 code paths only (see `binop!`).
                $t(unsafe { $srl(self.0, _mm_cvtsi32_si128(n as i32)) })
            }
        }

        impl Shl<u32> for $t {
            type Output = $t;
            #[inline(always)]
            fn shl(self, n: u32) -> $t {
                // SAFETY: AVX2 code paths only (see `binop!`).
                $t(unsafe { $sll(self.0, _mm_cvtsi32_si128(n as i32)) })
            }
        }
    };
}

ibinop!(U32x8, Add, add, _mm256_add_epi32);
ibinop!(U32x8, Sub, sub, _mm256_sub_epi32);
ibinop!(U32x8, Mul, mul, _mm256_mullo_epi32);
ibinop!(U32x8, BitAnd, bitand, _mm256_and_si256);
ibinop!(U32x8, BitOr, bitor, _mm256_or_si256);
ibinop!(U32x8, BitXor, bitxor, _mm256_xor_si256);
ishift!(U32x8, _mm256_srl_epi32, _mm256_sll_epi32);

impl U32x8 {
    /// The lanes with their top bit flipped, so that signed comparisons of
    /// them order the unsigned values.
    #[inline(always)]
    fn biased(self) -> __m256i {
        // SAFETY: AVX2 code paths only (see `binop!`).
        unsafe { _mm256_xor_si256(self.0, _mm256_set1_epi32(i32::MIN)) }
    }

    /// All-ones lanes.
    #[inline(always)]
    fn ones() -> __m256i {
        // SAFETY: AVX2 code paths only (see `binop!`).
        unsafe { _mm256_set1_epi32(-1) }
    }
}

impl U32x8Lane for U32x8 {
    type F = F32x8;
    #[inline(always)]
    fn splat(v: u32) -> Self {
        // SAFETY (every method): AVX2 code paths only (see `binop!`).
        U32x8(unsafe { _mm256_set1_epi32(v as i32) })
    }
    #[inline(always)]
    fn from_array(a: [u32; 8]) -> Self {
        // SAFETY: `a` is 32 bytes; unaligned load.
        U32x8(unsafe { _mm256_loadu_si256(a.as_ptr().cast()) })
    }
    #[inline(always)]
    fn to_array(self) -> [u32; 8] {
        let mut a = [0u32; 8];
        // SAFETY: `a` is 32 bytes; unaligned store.
        unsafe { _mm256_storeu_si256(a.as_mut_ptr().cast(), self.0) };
        a
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self {
        U32x8(unsafe { _mm256_cmpgt_epi32(o.biased(), self.biased()) })
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Self {
        U32x8(unsafe {
            _mm256_xor_si256(_mm256_cmpgt_epi32(o.biased(), self.biased()), Self::ones())
        })
    }
    #[inline(always)]
    fn ne(self, o: Self) -> Self {
        U32x8(unsafe { _mm256_xor_si256(_mm256_cmpeq_epi32(self.0, o.0), Self::ones()) })
    }
    #[inline(always)]
    fn gt_i32(self, o: Self) -> Self {
        U32x8(unsafe { _mm256_cmpgt_epi32(self.0, o.0) })
    }
    #[inline(always)]
    fn lt_i32(self, o: Self) -> Self {
        U32x8(unsafe { _mm256_cmpgt_epi32(o.0, self.0) })
    }
    #[inline(always)]
    fn any(self) -> bool {
        unsafe { _mm256_movemask_epi8(self.0) != 0 }
    }
    #[inline(always)]
    fn select(m: Self, t: Self, f: Self) -> Self {
        U32x8(unsafe { _mm256_blendv_epi8(f.0, t.0, m.0) })
    }
    #[inline(always)]
    fn to_f32(self) -> F32x8 {
        F32x8(unsafe { _mm256_cvtepi32_ps(self.0) })
    }
    #[inline(always)]
    fn to_f32_bits(self) -> F32x8 {
        F32x8(unsafe { _mm256_castsi256_ps(self.0) })
    }
    #[inline(always)]
    fn from_f32_bits(f: F32x8) -> Self {
        U32x8(unsafe { _mm256_castps_si256(f.0) })
    }
    #[inline(always)]
    fn from_f32_mask(m: F32x8) -> Self {
        U32x8(unsafe { _mm256_castps_si256(m.0) })
    }
    #[inline(always)]
    fn interleave(x: Self, y: Self) -> (Self, Self) {
        // In-lane unpacks give x₀y₀x₁y₁|x₄y₄x₅y₅ and x₂y₂x₃y₃|x₆y₆x₇y₇; the
        // two 128-bit permutes put the halves in order.
        unsafe {
            let lo = _mm256_unpacklo_epi32(x.0, y.0);
            let hi = _mm256_unpackhi_epi32(x.0, y.0);
            (
                U32x8(_mm256_permute2x128_si256::<0x20>(lo, hi)),
                U32x8(_mm256_permute2x128_si256::<0x31>(lo, hi)),
            )
        }
    }
}

/// Sixteen `u16` lanes in one AVX2 register: [`U16x16Lane`] for the
/// narrow-domain permutations in the run-time AVX2 copy (`vpmullw`; the
/// unsigned `≥` as `max(a, b) = a`).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct U16x16(__m256i);

ibinop!(U16x16, Add, add, _mm256_add_epi16);
ibinop!(U16x16, Sub, sub, _mm256_sub_epi16);
ibinop!(U16x16, Mul, mul, _mm256_mullo_epi16);
ibinop!(U16x16, BitAnd, bitand, _mm256_and_si256);
ibinop!(U16x16, BitOr, bitor, _mm256_or_si256);
ishift!(U16x16, _mm256_srl_epi16, _mm256_sll_epi16);

impl BitXorAssign for U16x16 {
    #[inline(always)]
    fn bitxor_assign(&mut self, o: U16x16) {
        // SAFETY: AVX2 code paths only (see `binop!`).
        self.0 = unsafe { _mm256_xor_si256(self.0, o.0) };
    }
}

impl IntLane for U16x16 {
    const NARROWER: u32 = 16;
    #[inline(always)]
    fn splat(v: u32) -> Self {
        // SAFETY (every method): AVX2 code paths only (see `binop!`).
        U16x16(unsafe { _mm256_set1_epi16(v as u16 as i16) })
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Self {
        U16x16(unsafe { _mm256_cmpeq_epi16(_mm256_max_epu16(self.0, o.0), self.0) })
    }
    #[inline(always)]
    fn any(self) -> bool {
        unsafe { _mm256_movemask_epi8(self.0) != 0 }
    }
    #[inline(always)]
    fn select(m: Self, t: Self, f: Self) -> Self {
        U16x16(unsafe { _mm256_blendv_epi8(f.0, t.0, m.0) })
    }
}

impl U16x16Lane for U16x16 {
    type U32 = U32x8;
    #[inline(always)]
    fn from_array(a: [u16; 16]) -> Self {
        // SAFETY: `a` is 32 bytes; unaligned load.
        U16x16(unsafe { _mm256_loadu_si256(a.as_ptr().cast()) })
    }
    #[inline(always)]
    fn widen(self) -> [U32x8; 2] {
        unsafe {
            [
                U32x8(_mm256_cvtepu16_epi32(_mm256_castsi256_si128(self.0))),
                U32x8(_mm256_cvtepu16_epi32(_mm256_extracti128_si256::<1>(self.0))),
            ]
        }
    }
}
