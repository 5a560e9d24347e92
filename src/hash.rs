//! Hash-based random permutations with random access.
//!
//! `permute(i, n, key)` is a bijection of `[0, n)` chosen by `key`, evaluated in
//! `O(1)` expected time and no memory. It composes invertible operations on
//! `b`-bit words, `b = ⌈log₂ n⌉` (xor with a key, multiplication by an odd constant
//! mod `2ᵇ`, addition of a key mod `2ᵇ`, and `x ⊕= x ≫ h`), which together form a
//! bijection of `[0, 2ᵇ)`, and then *cycle-walks*: re-applies the bijection until the
//! value falls in `[0, n)` (Black & Rogaway 2002[^1]). Since `n > 2ᵇ⁻¹`, fewer than
//! two rounds are needed on average. The same idea drives Kensler's correlated
//! multi-jittered sampling[^2]; the rounds and constants here are our own.
//!
//! [^1]: J. Black, P. Rogaway, *Ciphers with Arbitrary Finite Domains*, CT-RSA 2002.
//! [^2]: A. Kensler, *Correlated Multi-Jittered Sampling*, Pixar Technical Memo 13-01 (2013).

use wide::u32x8;

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

/// One round of the bijection of `[0, mask]` (mask = `2ᵇ − 1`), `h = ⌈b/2⌉`.
#[inline(always)]
const fn round(mut x: u32, key: u32, mask: u32, h: u32) -> u32 {
    x ^= key & mask;
    x = x.wrapping_mul(0x9E37_79B1) & mask;
    x ^= x >> h;
    x = x.wrapping_add(key >> 7) & mask;
    x = x.wrapping_mul(0x85EB_CA6B) & mask;
    x ^= x >> h;
    x ^= (key >> 13) & mask;
    x = x.wrapping_mul(0xC2B2_AE35) & mask;
    x ^= x >> h;
    x
}

#[inline(always)]
const fn half_bits(mask: u32) -> u32 {
    mask.count_ones().div_ceil(2)
}

/// Element `i` of the random permutation of `[0, n)` selected by `key`.
///
/// `i` must be below `n`; in release builds an `i ≥ n` returns an unspecified
/// value that is still below `n` when `i < 2^⌈log₂ n⌉` (debug builds assert).
/// For `n ≤ 1` the result is 0.
#[inline]
#[must_use]
pub fn permute(i: u32, n: u32, key: u32) -> u32 {
    debug_assert!(i < n.max(1), "permute: i = {i} must be below n = {n}");
    if n <= 1 {
        return 0;
    }
    let mask = domain_mask(n);
    let h = half_bits(mask);
    let k = crate::rng::mix32(key);
    let mut x = i & mask;
    loop {
        x = round(x, k, mask, h);
        if x < n {
            return x;
        }
    }
}

/// Lane-wise [`permute`] with a common `n` and per-lane keys; equal to the scalar
/// function lane by lane.
#[inline]
#[must_use]
pub fn permute_x8(i: u32x8, n: u32, key: u32x8) -> u32x8 {
    if n <= 1 {
        return u32x8::ZERO;
    }
    let mask = domain_mask(n);
    let h = half_bits(mask);
    let k = crate::rng::mix32x8(key);
    let vm = u32x8::splat(mask);
    let vn = u32x8::splat(n);
    let round8 = |mut x: u32x8| {
        x ^= k & vm;
        x = (x * u32x8::splat(0x9E37_79B1)) & vm;
        x ^= x >> h;
        x = (x + (k >> 7)) & vm;
        x = (x * u32x8::splat(0x85EB_CA6B)) & vm;
        x ^= x >> h;
        x ^= (k >> 13) & vm;
        x = (x * u32x8::splat(0xC2B2_AE35)) & vm;
        x ^= x >> h;
        x
    };
    let mut x = round8(i & vm);
    let mut pending = x.simd_ge(vn);
    while pending.any() {
        let y = round8(x);
        x = pending.select(y, x);
        pending &= x.simd_ge(vn);
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

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
