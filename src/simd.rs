//! One lane abstraction for the `f32` batch closed forms: every `f32` kernel is
//! written once, generic over [`Lane`], and instantiated for the scalar `f32`
//! (the reference path, always compiled) and for `wide::f32x8` (the SIMD path).
//!
//! Both instantiations execute the same IEEE operations in the same order, so
//! they agree **bit for bit** lane by lane: no fused multiply-add is used (its
//! availability differs between builds), `min`/`max` follow the x86 `minps`/
//! `maxps` rule (`a < b ? a : b`) in both, and `sqrt`, `floor` and division are
//! correctly rounded everywhere. Results are therefore also identical between
//! the SSE2 and the AVX2 build.

use core::ops::{Add, Div, Mul, Neg, Sub};
use wide::{f32x8, i32x8};

/// Width of the SIMD batch.
pub(crate) const LANES: usize = 8;

/// An `f32` lane type: `f32` itself or `f32x8`.
pub(crate) trait Lane:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Comparison mask.
    type Mask: Copy;
    fn splat(x: f32) -> Self;
    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    /// `self < o ? self : o`.
    fn min(self, o: Self) -> Self;
    /// `self > o ? self : o`.
    fn max(self, o: Self) -> Self;
    fn floor(self) -> Self;
    fn lt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn gt(self, o: Self) -> Self::Mask;
    /// `m ? a : b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// `2^n` for integral-valued `n ∈ [−126, 127]` (built from the exponent bits).
    fn pow2i(n: Self) -> Self;
}

impl Lane for f32 {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        libm::sqrtf(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        libm::fabsf(self)
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
        libm::floorf(self)
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
    fn pow2i(n: Self) -> Self {
        f32::from_bits((((n as i32) + 127) as u32) << 23)
    }
}

impl Lane for f32x8 {
    type Mask = f32x8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x8::splat(x)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32x8::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32x8::abs(self)
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
        f32x8::floor(self)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> f32x8 {
        self.simd_lt(o)
    }
    #[inline(always)]
    fn le(self, o: Self) -> f32x8 {
        self.simd_le(o)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> f32x8 {
        self.simd_gt(o)
    }
    #[inline(always)]
    fn select(m: f32x8, a: Self, b: Self) -> Self {
        wide::Select::select(m, a, b)
    }
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        let e: i32x8 = n.round_int() + i32x8::splat(127);
        bytemuck::cast(e << 23)
    }
}

/// Loads lanes `i..i+8` of a slice.
#[inline(always)]
pub(crate) fn load8(s: &[f32], i: usize) -> f32x8 {
    let a: [f32; 8] = s[i..i + LANES].try_into().unwrap_or([0.0; 8]);
    f32x8::from(a)
}

/// Stores a vector into lanes `i..i+8`.
#[inline(always)]
pub(crate) fn store8(s: &mut [f32], i: usize, v: f32x8) {
    s[i..i + LANES].copy_from_slice(&v.to_array());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scalar_and_simd_lane_ops_agree() {
        let a = [-3.5f32, -0.0, 0.0, 1.25, 7.0, -1e-30, 3e30, 0.5];
        let b = [2.0f32, 0.0, -0.0, 1.25, -7.0, 1e-30, 2.0, 0.75];
        let va = f32x8::from(a);
        let vb = f32x8::from(b);
        let mn = Lane::min(va, vb).to_array();
        let mx = Lane::max(va, vb).to_array();
        let fl = Lane::floor(va).to_array();
        let sel = <f32x8 as Lane>::select(va.lt(vb), va, vb).to_array();
        for l in 0..8 {
            assert_eq!(mn[l].to_bits(), Lane::min(a[l], b[l]).to_bits(), "min {l}");
            assert_eq!(mx[l].to_bits(), Lane::max(a[l], b[l]).to_bits(), "max {l}");
            assert_eq!(fl[l].to_bits(), Lane::floor(a[l]).to_bits(), "floor {l}");
            let s = <f32 as Lane>::select(a[l] < b[l], a[l], b[l]);
            assert_eq!(sel[l].to_bits(), s.to_bits(), "select {l}");
        }
        let n = [-126.0f32, -1.0, 0.0, 1.0, 5.0, 64.0, 127.0, -30.0];
        let p = Lane::pow2i(f32x8::from(n)).to_array();
        for l in 0..8 {
            assert_eq!(p[l], libm::exp2f(n[l]));
            assert_eq!(p[l].to_bits(), <f32 as Lane>::pow2i(n[l]).to_bits());
        }
    }
}
