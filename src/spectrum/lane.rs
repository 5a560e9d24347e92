//! One `f64` lane abstraction for the periodogram kernels: each kernel is
//! written once, generic over [`F64Lane`], and instantiated for the scalar `f64`
//! (the reference path, always compiled) and for `wide::f64x4` (the SIMD path).
//!
//! Both run the same IEEE operations in the same order. The multiply-add is
//! always **fused** (one rounding): `wide`'s `mul_add` where the target has FMA,
//! and the correctly rounded `libm::fma` lane by lane otherwise, so the two
//! paths agree bit for bit in every build (SSE2 and AVX2 + FMA).

use core::ops::{Add, Div, Mul, Neg, Sub};
use wide::f64x4;

/// An `f64` lane type: `f64` itself or `f64x4`.
pub(crate) trait F64Lane:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Lanes per value.
    const LANES: usize;
    fn splat(x: f64) -> Self;
    /// The first `LANES` elements of `s`.
    fn load(s: &[f64]) -> Self;
    /// Writes the lanes to the first `LANES` elements of `s`.
    fn store(self, s: &mut [f64]);
    /// `a·b + c` with one rounding.
    fn fma(a: Self, b: Self, c: Self) -> Self;
    fn abs(self) -> Self;
    /// `self < o ? a : b`, lane by lane.
    fn lt_select(self, o: Self, a: Self, b: Self) -> Self;
}

impl F64Lane for f64 {
    const LANES: usize = 1;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn load(s: &[f64]) -> Self {
        s[0]
    }
    #[inline(always)]
    fn store(self, s: &mut [f64]) {
        s[0] = self;
    }
    #[inline(always)]
    fn fma(a: Self, b: Self, c: Self) -> Self {
        libm::fma(a, b, c)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        libm::fabs(self)
    }
    #[inline(always)]
    fn lt_select(self, o: Self, a: Self, b: Self) -> Self {
        if self < o {
            a
        } else {
            b
        }
    }
}

impl F64Lane for f64x4 {
    const LANES: usize = 4;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        f64x4::splat(x)
    }
    #[inline(always)]
    fn load(s: &[f64]) -> Self {
        f64x4::from([s[0], s[1], s[2], s[3]])
    }
    #[inline(always)]
    fn store(self, s: &mut [f64]) {
        s[..4].copy_from_slice(&self.to_array());
    }
    #[inline(always)]
    fn fma(a: Self, b: Self, c: Self) -> Self {
        #[cfg(all(target_feature = "avx", target_feature = "fma"))]
        {
            a.mul_add(b, c)
        }
        #[cfg(not(all(target_feature = "avx", target_feature = "fma")))]
        {
            let (a, b, c) = (a.to_array(), b.to_array(), c.to_array());
            f64x4::from([
                libm::fma(a[0], b[0], c[0]),
                libm::fma(a[1], b[1], c[1]),
                libm::fma(a[2], b[2], c[2]),
                libm::fma(a[3], b[3], c[3]),
            ])
        }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64x4::abs(self)
    }
    #[inline(always)]
    fn lt_select(self, o: Self, a: Self, b: Self) -> Self {
        wide::Select::select(self.simd_lt(o), a, b)
    }
}
