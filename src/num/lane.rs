//! The one SIMD lane abstraction: every batch kernel in the crate (and in
//! `linesample-scene`, whose effects are written in it too) is written once, generic over [`Lane`], and instantiated for a scalar (the reference
//! path, always compiled and tested) and for a `wide` vector (the SIMD path):
//! `f32`/`f32x8` for the `f32` closed forms ([`F32Lane`]), `f64`/`f64x4` for the
//! periodogram kernels ([`F64Lane`]); with `std` in a build without AVX2 also
//! for `num::avx2`'s 256-bit types, which [`crate::simd::dispatch`] selects at
//! run time. The hash permutations' Feistel rounds
//! are generic over [`IntLane`] (`u32x8`, and `u16x16` for small domains);
//! their scalar reference is `hash::permute`.
//!
//! Both instantiations of a kernel execute the same IEEE operations in the same
//! order, so they agree **bit for bit** lane by lane, and in every build:
//!
//! * `+ − × ÷`, `sqrt` and `floor` are correctly rounded everywhere;
//! * `min`/`max` follow the x86 `minps`/`maxps` rule (`a < b ? a : b`) in both;
//! * there is **no fused multiply-add**: `wide`'s `mul_add` is fused only where
//!   FMA is enabled at compile time (so its bits change with the build), and a
//!   correctly rounded software `fma` costs about 35× a multiply and an add.
//!   Kernels write `a * b + c`; the exact products of the double-double
//!   arithmetic use `num::two_prod`, which is exact in every build.

use core::ops::{Add, BitAnd, BitOr, BitXor, BitXorAssign, Div, Mul, Neg, Shl, Shr, Sub};
use wide::{f32x8, f64x4, i32x8, u16x16, u32x8};

/// Width of the `f32` SIMD batch of the closed forms.
pub const LANES: usize = 8;

/// A lane type: a scalar or a `wide` vector of that scalar.
pub trait Lane:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The element type.
    type Scalar: Copy;
    /// Comparison mask.
    type Mask: Copy;
    /// Elements per value.
    const LANES: usize;
    /// Every lane `x`.
    fn splat(x: Self::Scalar) -> Self;
    /// The first `LANES` elements of `s`.
    fn load(s: &[Self::Scalar]) -> Self;
    /// Writes the lanes to the first `LANES` elements of `s`.
    fn store(self, s: &mut [Self::Scalar]);
    /// Correctly rounded square root.
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// `self < o ? self : o`.
    fn min(self, o: Self) -> Self;
    /// `self > o ? self : o`.
    fn max(self, o: Self) -> Self;
    /// Round towards `−∞`.
    fn floor(self) -> Self;
    /// `self < o`, lane by lane.
    fn lt(self, o: Self) -> Self::Mask;
    /// `self ≤ o`, lane by lane.
    fn le(self, o: Self) -> Self::Mask;
    /// `self > o`, lane by lane.
    fn gt(self, o: Self) -> Self::Mask;
    /// `m ? a : b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// Whether any lane of `m` is set (to skip work no lane needs; the
    /// selected results are the same either way).
    fn any(m: Self::Mask) -> bool;
    /// `a && b`, lane by lane.
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// `self < o ? a : b`, lane by lane.
    #[inline(always)]
    fn lt_select(self, o: Self, a: Self, b: Self) -> Self {
        Self::select(self.lt(o), a, b)
    }
}

/// `f32` lanes (`f32`, `f32x8`), with the exponent construction the `f32`
/// exponentials need.
pub trait F32Lane: Lane<Scalar = f32> {
    /// `2^n` for integral-valued `n ∈ [−126, 127]` (built from the exponent bits).
    fn pow2i(n: Self) -> Self;
}

/// `f64` lanes (`f64`, `f64x4`), with the exponent construction the `f64`
/// exponential needs.
pub trait F64Lane: Lane<Scalar = f64> {
    /// `2^n` for integral-valued `n ∈ [−1022, 1023]` (built from the exponent
    /// bits).
    fn pow2i(n: Self) -> Self;
}

/// The scalar instantiation of the comparisons and selections (`minps` rule).
macro_rules! scalar_lane {
    ($t:ty, $sqrt:path, $abs:path, $floor:path) => {
        impl Lane for $t {
            type Scalar = $t;
            type Mask = bool;
            const LANES: usize = 1;
            #[inline(always)]
            fn splat(x: $t) -> Self {
                x
            }
            #[inline(always)]
            fn load(s: &[$t]) -> Self {
                s[0]
            }
            #[inline(always)]
            fn store(self, s: &mut [$t]) {
                s[0] = self;
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $abs(self)
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                if self < o {
                    self
                } else {
                    o
                }
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                if self > o {
                    self
                } else {
                    o
                }
            }
            #[inline(always)]
            fn floor(self) -> Self {
                $floor(self)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> bool {
                self < o
            }
            #[inline(always)]
            fn le(self, o: Self) -> bool {
                self <= o
            }
            #[inline(always)]
            fn gt(self, o: Self) -> bool {
                self > o
            }
            #[inline(always)]
            fn select(m: bool, a: Self, b: Self) -> Self {
                if m {
                    a
                } else {
                    b
                }
            }
            #[inline(always)]
            fn any(m: bool) -> bool {
                m
            }
            #[inline(always)]
            fn and(a: bool, b: bool) -> bool {
                a && b
            }
        }
    };
}

scalar_lane!(f32, crate::num::scalar::sqrt32, libm::fabsf, libm::floorf);
scalar_lane!(f64, libm::sqrt, libm::fabs, libm::floor);

/// The vector instantiation (`wide`).
macro_rules! vector_lane {
    ($v:ty, $t:ty, $n:expr) => {
        impl Lane for $v {
            type Scalar = $t;
            type Mask = $v;
            const LANES: usize = $n;
            #[inline(always)]
            fn splat(x: $t) -> Self {
                <$v>::splat(x)
            }
            #[inline(always)]
            fn load(s: &[$t]) -> Self {
                let a: [$t; $n] = core::array::from_fn(|l| s[l]);
                <$v>::from(a)
            }
            #[inline(always)]
            fn store(self, s: &mut [$t]) {
                s[..$n].copy_from_slice(&self.to_array());
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$v>::sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$v>::abs(self)
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                self.fast_min(o)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                self.fast_max(o)
            }
            #[inline(always)]
            fn floor(self) -> Self {
                <$v>::floor(self)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> $v {
                self.simd_lt(o)
            }
            #[inline(always)]
            fn le(self, o: Self) -> $v {
                self.simd_le(o)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> $v {
                self.simd_gt(o)
            }
            #[inline(always)]
            fn select(m: $v, a: Self, b: Self) -> Self {
                wide::Select::select(m, a, b)
            }
            #[inline(always)]
            fn any(m: $v) -> bool {
                m.any()
            }
            #[inline(always)]
            fn and(a: $v, b: $v) -> $v {
                a & b
            }
        }
    };
}

vector_lane!(f32x8, f32, 8);
vector_lane!(f64x4, f64, 4);

impl F32Lane for f32 {
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        f32::from_bits((((n as i32) + 127) as u32) << 23)
    }
}

impl F32Lane for f32x8 {
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        let e: i32x8 = n.round_int() + i32x8::splat(127);
        bytemuck::cast(e << 23)
    }
}

impl F64Lane for f64 {
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        f64::from_bits((((n as i64) + 1023) as u64) << 52)
    }
}

impl F64Lane for f64x4 {
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        // Lane by lane through the integer bits (`wide` has no f64 → i64
        // conversion); the compiler keeps it in vector registers.
        let a: [f64; 4] = n.to_array();
        let b: [u64; 4] = core::array::from_fn(|l| (((a[l] as i64) + 1023) as u64) << 52);
        bytemuck::cast(b)
    }
}

/// Loads lanes `i..i+8` of a slice.
#[inline(always)]
pub fn load8(s: &[f32], i: usize) -> f32x8 {
    <f32x8 as Lane>::load(&s[i..i + LANES])
}

/// Stores a vector into lanes `i..i+8`.
#[inline(always)]
pub fn store8(s: &mut [f32], i: usize, v: f32x8) {
    v.store(&mut s[i..i + LANES]);
}

/// An unsigned integer lane type for the hash permutations
/// (`crate::hash`): eight 32-bit lanes, and sixteen 16-bit lanes for domains
/// of at most `2¹⁶` elements, whose round words and shifts are 16 bits
/// narrower. Wrapping arithmetic, unsigned comparisons.
pub trait IntLane:
    Copy
    + Add<Output = Self>
    + Mul<Output = Self>
    + Shr<u32, Output = Self>
    + Shl<u32, Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + BitXorAssign
{
    /// Bits the lanes lack against 32 (0 or 16).
    const NARROWER: u32;
    /// `v` in every lane (truncated to the lane width).
    fn splat(v: u32) -> Self;
    /// Lane-wise unsigned `self ≥ o`, as a mask.
    fn ge(self, o: Self) -> Self;
    /// Any lane of a mask set.
    fn any(self) -> bool;
    /// Lane-wise `mask ? t : f`.
    fn select(mask: Self, t: Self, f: Self) -> Self;
}

macro_rules! int_lane {
    ($t:ty, $narrower:expr, $scalar:ty) => {
        impl IntLane for $t {
            const NARROWER: u32 = $narrower;
            #[inline(always)]
            fn splat(v: u32) -> Self {
                <$t>::splat(v as $scalar)
            }
            #[inline(always)]
            fn ge(self, o: Self) -> Self {
                self.simd_ge(o)
            }
            #[inline(always)]
            fn any(self) -> bool {
                <$t>::any(self)
            }
            #[inline(always)]
            fn select(mask: Self, t: Self, f: Self) -> Self {
                mask.select(t, f)
            }
        }
    };
}
int_lane!(u32x8, 0, u32);
int_lane!(u16x16, 16, u16);

/// Sixteen `u16` lanes for the narrow-domain permutations
/// ([`crate::hash`]'s 16-bit Feistel rounds), at one instruction-set level:
/// `wide`'s `u16x16` at the compiled level (SSE2 has a native 16-bit
/// multiply), [`crate::num::avx2::U16x16`] in the run-time AVX2 copy
/// ([`crate::simd::Isa::U16`]). Arithmetic wraps modulo `2¹⁶`.
pub trait U16x16Lane: IntLane + Sub<Output = Self> {
    /// The level's `u32` lanes.
    type U32: U32x8Lane;
    /// Lanes from sixteen values.
    fn from_array(a: [u16; 16]) -> Self;
    /// Lanes 0–7 and 8–15, zero-extended to 32 bits.
    fn widen(self) -> [Self::U32; 2];
}

impl U16x16Lane for u16x16 {
    type U32 = Wu32x8;
    #[inline(always)]
    fn from_array(a: [u16; 16]) -> Self {
        u16x16::new(a)
    }
    #[inline(always)]
    fn widen(self) -> [Wu32x8; 2] {
        let h: [wide::u16x8; 2] = bytemuck::cast(self);
        [Wu32x8(u32x8::from(h[0])), Wu32x8(u32x8::from(h[1]))]
    }
}

/// Eight `u32` lanes for the pattern generators' integer hot paths (the
/// counter-based generator, the hashes, the Sobol′ products, the strata
/// tests), at one instruction-set level: [`Wu32x8`] at the compiled level,
/// [`crate::num::avx2::U32x8`] in the run-time AVX2 copy
/// ([`crate::simd::Isa::U32`]).
///
/// Arithmetic wraps modulo `2³²`; shifts take counts below 32; comparisons
/// return masks whose lanes are all ones or all zeros; [`U32x8Lane::any`] and
/// [`U32x8Lane::select`] take such masks. Every operation is exact integer
/// arithmetic, so both implementations give the same bits lane by lane
/// (`tests/simd.rs`, and the test in [`crate::num::avx2`]).
pub trait U32x8Lane:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + BitXor<Output = Self>
    + Shr<u32, Output = Self>
    + Shl<u32, Output = Self>
{
    /// The `f32` lanes of the same level.
    type F: F32Lane;
    /// `v` in every lane.
    fn splat(v: u32) -> Self;
    /// Lane `l` is `a[l]`.
    fn from_array(a: [u32; 8]) -> Self;
    /// The lanes.
    fn to_array(self) -> [u32; 8];
    /// Unsigned `self < o`.
    fn lt(self, o: Self) -> Self;
    /// Unsigned `self ≥ o`.
    fn ge(self, o: Self) -> Self;
    /// `self ≠ o`.
    fn ne(self, o: Self) -> Self;
    /// Signed (`i32`) `self > o`.
    fn gt_i32(self, o: Self) -> Self;
    /// Signed (`i32`) `self < o`.
    fn lt_i32(self, o: Self) -> Self;
    /// Whether any lane of the mask `self` is set.
    fn any(self) -> bool;
    /// `m ? t : f`, lane by lane.
    fn select(m: Self, t: Self, f: Self) -> Self;
    /// The lanes read as `i32` and converted to `f32` (round to nearest,
    /// exact below `2²⁴` in magnitude).
    fn to_f32(self) -> Self::F;
    /// The lanes' bits as `f32` lanes.
    fn to_f32_bits(self) -> Self::F;
    /// The bits of `f32` lanes (also of their comparison masks).
    fn from_f32_bits(f: Self::F) -> Self;
    /// The bits of an `f32` comparison mask.
    fn from_f32_mask(m: <Self::F as Lane>::Mask) -> Self;
    /// `(x₀ y₀ x₁ y₁ x₂ y₂ x₃ y₃, x₄ y₄ … x₇ y₇)`: two points-major vectors
    /// of 2D points from the two coordinate vectors.
    fn interleave(x: Self, y: Self) -> (Self, Self);
}

/// The compiled level's [`U32x8Lane`]: `wide`'s `u32x8`, with a multiply that
/// stays in vector registers on baseline SSE2.
///
/// Why a wrapper: SSE2 has no 32-bit lane multiply (`pmulld` is SSE4.1), and
/// `wide` then multiplies through a scalar array, four times slower than its
/// other operations. This type multiplies with two `pmuludq` (even and odd
/// lanes' 64-bit products) and keeps the low halves, which is the same
/// wrapping product. Everything else is `wide`'s.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(transparent)]
pub struct Wu32x8(pub u32x8);

macro_rules! wu32_op {
    ($tr:ident, $m:ident) => {
        impl $tr for Wu32x8 {
            type Output = Wu32x8;
            #[inline(always)]
            fn $m(self, o: Wu32x8) -> Wu32x8 {
                Wu32x8($tr::$m(self.0, o.0))
            }
        }
    };
}
wu32_op!(Add, add);
wu32_op!(Sub, sub);
wu32_op!(BitAnd, bitand);
wu32_op!(BitOr, bitor);
wu32_op!(BitXor, bitxor);

impl Shr<u32> for Wu32x8 {
    type Output = Wu32x8;
    #[inline(always)]
    fn shr(self, n: u32) -> Wu32x8 {
        Wu32x8(self.0 >> n)
    }
}

impl Shl<u32> for Wu32x8 {
    type Output = Wu32x8;
    #[inline(always)]
    fn shl(self, n: u32) -> Wu32x8 {
        Wu32x8(self.0 << n)
    }
}

impl Mul for Wu32x8 {
    type Output = Wu32x8;
    #[inline(always)]
    fn mul(self, o: Wu32x8) -> Wu32x8 {
        #[cfg(all(target_arch = "x86_64", not(target_feature = "sse4.1")))]
        {
            use safe_arch::{
                m128i, mul_widen_u32_odd_m128i, shr_imm_u64_m128i, shuffle_ai_f32_all_m128i,
                unpack_low_i32_m128i,
            };
            /// The wrapping product of four lanes: `pmuludq` of the even
            /// lanes and of the odd ones (shifted down), low halves kept.
            #[inline(always)]
            fn mul4(a: m128i, b: m128i) -> m128i {
                let even = mul_widen_u32_odd_m128i(a, b);
                let odd =
                    mul_widen_u32_odd_m128i(shr_imm_u64_m128i::<32>(a), shr_imm_u64_m128i::<32>(b));
                unpack_low_i32_m128i(
                    shuffle_ai_f32_all_m128i::<0b10_00_10_00>(even),
                    shuffle_ai_f32_all_m128i::<0b10_00_10_00>(odd),
                )
            }
            let a: [m128i; 2] = bytemuck::cast(self.0);
            let b: [m128i; 2] = bytemuck::cast(o.0);
            Wu32x8(bytemuck::cast([mul4(a[0], b[0]), mul4(a[1], b[1])]))
        }
        #[cfg(not(all(target_arch = "x86_64", not(target_feature = "sse4.1"))))]
        {
            Wu32x8(self.0 * o.0)
        }
    }
}

impl U32x8Lane for Wu32x8 {
    type F = f32x8;
    #[inline(always)]
    fn splat(v: u32) -> Self {
        Wu32x8(u32x8::splat(v))
    }
    #[inline(always)]
    fn from_array(a: [u32; 8]) -> Self {
        Wu32x8(u32x8::new(a))
    }
    #[inline(always)]
    fn to_array(self) -> [u32; 8] {
        self.0.to_array()
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self {
        Wu32x8(self.0.simd_lt(o.0))
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Self {
        Wu32x8(self.0.simd_ge(o.0))
    }
    #[inline(always)]
    fn ne(self, o: Self) -> Self {
        Wu32x8(self.0.simd_ne(o.0))
    }
    #[inline(always)]
    fn gt_i32(self, o: Self) -> Self {
        let (a, b): (i32x8, i32x8) = (bytemuck::cast(self.0), bytemuck::cast(o.0));
        Wu32x8(bytemuck::cast(a.simd_gt(b)))
    }
    #[inline(always)]
    fn lt_i32(self, o: Self) -> Self {
        let (a, b): (i32x8, i32x8) = (bytemuck::cast(self.0), bytemuck::cast(o.0));
        Wu32x8(bytemuck::cast(a.simd_lt(b)))
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.any()
    }
    #[inline(always)]
    fn select(m: Self, t: Self, f: Self) -> Self {
        Wu32x8(m.0.select(t.0, f.0))
    }
    #[inline(always)]
    fn to_f32(self) -> f32x8 {
        f32x8::from_i32x8(bytemuck::cast(self.0))
    }
    #[inline(always)]
    fn to_f32_bits(self) -> f32x8 {
        bytemuck::cast(self.0)
    }
    #[inline(always)]
    fn from_f32_bits(f: f32x8) -> Self {
        Wu32x8(bytemuck::cast(f))
    }
    #[inline(always)]
    fn from_f32_mask(m: f32x8) -> Self {
        Wu32x8(bytemuck::cast(m))
    }
    #[inline(always)]
    fn interleave(x: Self, y: Self) -> (Self, Self) {
        (Wu32x8(x.0.unpack_lo(y.0)), Wu32x8(x.0.unpack_hi(y.0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every operation of both vector instantiations against the scalar one,
    /// lane by lane, bit for bit (signed zeros, tiny and huge values).
    #[test]
    fn scalar_and_simd_lanes_agree() {
        let a = [-3.5f32, -0.0, 0.0, 1.25, 7.0, -1e-30, 3e30, 0.5];
        let b = [2.0f32, 0.0, -0.0, 1.25, -7.0, 1e-30, 2.0, 0.75];
        let c = [0.1f32, -1.0, 3.0, 1e-7, 2.5, 1e30, -3e30, 1.0 / 3.0];
        let (va, vb, vc) = (f32x8::from(a), f32x8::from(b), f32x8::from(c));
        let mn = Lane::min(va, vb).to_array();
        let mx = Lane::max(va, vb).to_array();
        let fl = Lane::floor(va).to_array();
        let ma = (va * vb + vc).to_array();
        let sq = Lane::sqrt(Lane::abs(va)).to_array();
        let sel = <f32x8 as Lane>::select(va.lt(vb), va, vb).to_array();
        for l in 0..8 {
            assert_eq!(mn[l].to_bits(), Lane::min(a[l], b[l]).to_bits(), "min {l}");
            assert_eq!(mx[l].to_bits(), Lane::max(a[l], b[l]).to_bits(), "max {l}");
            assert_eq!(fl[l].to_bits(), Lane::floor(a[l]).to_bits(), "floor {l}");
            let f = a[l] * b[l] + c[l];
            assert_eq!(ma[l].to_bits(), f.to_bits(), "mul-add {l}");
            assert_eq!(
                sq[l].to_bits(),
                libm::sqrtf(a[l].abs()).to_bits(),
                "sqrt {l}"
            );
            let s = <f32 as Lane>::select(a[l] < b[l], a[l], b[l]);
            assert_eq!(sel[l].to_bits(), s.to_bits(), "select {l}");
        }
        let n = [-126.0f32, -1.0, 0.0, 1.0, 5.0, 64.0, 127.0, -30.0];
        let p = F32Lane::pow2i(f32x8::from(n)).to_array();
        for l in 0..8 {
            assert_eq!(p[l], libm::exp2f(n[l]));
            assert_eq!(p[l].to_bits(), <f32 as F32Lane>::pow2i(n[l]).to_bits());
        }
        let x = [1.0 + f64::EPSILON, -0.0, 1e300, -2.5];
        let y = [1.0 - f64::EPSILON, 0.0, 1e10, 4.0];
        let z = [-1.0, -0.0, -1e308, 0.1];
        let (vx, vy, vz) = (
            <f64x4 as Lane>::load(&x),
            <f64x4 as Lane>::load(&y),
            <f64x4 as Lane>::load(&z),
        );
        let mut out = [0.0f64; 4];
        (vx * vy + vz).store(&mut out);
        let sel = vx.lt_select(vy, vx, vz).to_array();
        for l in 0..4 {
            assert_eq!(
                out[l].to_bits(),
                (x[l] * y[l] + z[l]).to_bits(),
                "mul-add {l}"
            );
            let s = <f64 as Lane>::lt_select(x[l], y[l], x[l], z[l]);
            assert_eq!(sel[l].to_bits(), s.to_bits(), "lt_select {l}");
        }
        // Unfused in every build: the −ε² of the exact product is rounded away.
        assert_eq!(out[0], 0.0);
    }
}
