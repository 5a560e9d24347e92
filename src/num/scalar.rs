//! Inlined scalar `f64` primitives: fused multiply-add, square root, floor and
//! round, each **bit-identical** to its `libm` counterpart for every input.
//!
//! Why hand-written wrappers and not `libm` directly: `libm`'s functions are
//! not `#[inline]`, so without link-time optimisation every call is a real
//! function call, and `libm::fma` also dispatches on the CPU at run time. The
//! double-double arithmetic behind every exact closed form makes a few dozen of
//! these calls per chord (`two_prod` is one `fma`), so the calls cost more than
//! the arithmetic (measured: `libm::fma`, `round` and `floor` were 7 % of the
//! periodised ball segment in a profile, and the call overhead around them
//! more). `core` has no `f64::mul_add`/`sqrt`/`floor` (they live in `std`), so
//! these select at compile time:
//!
//! * [`fma`]: the hardware instruction through `wide` (`vfmadd`, `fmla`) when
//!   the target has it (x86-64-v3 builds, aarch64), else `libm::fma`. Both are
//!   the exactly rounded `a·b + c`, so the bits never depend on the build.
//! * [`sqrt`]: the hardware instruction through `wide` (`sqrtsd`, `fsqrt`),
//!   else `libm::sqrt`; IEEE 754 square root is exactly rounded either way.
//! * [`floor`], [`round`]: portable code (truncation through `i64`, exact below
//!   `2⁵²`, where every `f64` with a fractional part lies), the sign of zero
//!   kept as `libm` keeps it.
//!
//! `tests/num.rs` compares each with `libm` bit for bit over edge cases and
//! random inputs, in the AVX2 build and (CI) the baseline SSE2 build.

/// `2⁵²`: every `f64` of at least this magnitude is an integer.
const TWO_52: f64 = 4_503_599_627_370_496.0;

/// Whether [`fma`] is the hardware instruction in this build (x86 with FMA
/// enabled at compile time, aarch64); otherwise it is `libm`'s software
/// routine, and `num::two_prod` uses Dekker's product instead.
pub const HARDWARE_FMA: bool = cfg!(any(
    all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "fma"
    ),
    all(target_arch = "aarch64", target_feature = "neon")
));

/// `a·b + c` with one rounding (IEEE 754 fused multiply-add).
#[inline(always)]
#[must_use]
pub fn fma(a: f64, b: f64, c: f64) -> f64 {
    if HARDWARE_FMA {
        // One `vfmadd`/`fmla` (`wide` fuses where the target has FMA).
        use wide::f64x2;
        f64x2::splat(a)
            .mul_add(f64x2::splat(b), f64x2::splat(c))
            .to_array()[0]
    } else {
        libm::fma(a, b, c)
    }
}

/// The exactly rounded square root (NaN for `x < 0`).
#[inline(always)]
#[must_use]
pub fn sqrt(x: f64) -> f64 {
    #[cfg(any(
        all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "sse2"
        ),
        all(target_arch = "aarch64", target_feature = "neon")
    ))]
    {
        wide::f64x2::splat(x).sqrt().to_array()[0]
    }
    #[cfg(not(any(
        all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "sse2"
        ),
        all(target_arch = "aarch64", target_feature = "neon")
    )))]
    {
        libm::sqrt(x)
    }
}

/// The exactly rounded `f32` square root (NaN for `x < 0`), through a
/// `wide` vector so that the instruction is the build's own (VEX `vsqrtps`
/// in an AVX build): `libm::sqrtf` is an inline-asm legacy-SSE `sqrtss`,
/// which next to 256-bit code pays a state-transition penalty (measured
/// about 100 ns per call in the AO visibility batch's scalar twin). Both are
/// correctly rounded, so the value is the same.
#[inline(always)]
#[must_use]
pub fn sqrt32(x: f32) -> f32 {
    #[cfg(any(
        all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "sse"
        ),
        all(target_arch = "aarch64", target_feature = "neon")
    ))]
    {
        wide::f32x4::splat(x).sqrt().to_array()[0]
    }
    #[cfg(not(any(
        all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "sse"
        ),
        all(target_arch = "aarch64", target_feature = "neon")
    )))]
    {
        libm::sqrtf(x)
    }
}

/// `⌊x⌋` (`−0` stays `−0`; NaN and infinities are returned unchanged).
#[inline(always)]
#[must_use]
pub fn floor(x: f64) -> f64 {
    // One `roundsd` (IEEE floor: exact, −0 and NaN/∞ kept) where SSE4.1 is
    // enabled, else the truncation below (the same values).
    #[cfg(all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "sse4.1"
    ))]
    {
        wide::f64x2::splat(x).floor().to_array()[0]
    }
    #[cfg(not(all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "sse4.1"
    )))]
    if x.abs() < TWO_52 {
        // Truncation toward zero is exact for |x| < 2⁵² (< 2⁶³).
        let t = x as i64 as f64;
        let f = if t > x { t - 1.0 } else { t };
        // A zero result takes the sign of x: floor(−0) = −0, and x ∈ (0, 1)
        // gives +0 (negative x never gives a zero result except x = −0).
        f.copysign(x)
    } else {
        x
    }
}

/// `x` rounded to the nearest integer, halves away from zero (C `round`;
/// `−0.3 → −0`; NaN and infinities are returned unchanged).
#[inline(always)]
#[must_use]
pub fn round(x: f64) -> f64 {
    if x.abs() < TWO_52 {
        let t = x as i64 as f64;
        // x − trunc(x) is exact (|x − t| < 1 and t is a multiple of ulp(x)).
        let d = x - t;
        let r = if d >= 0.5 {
            t + 1.0
        } else if d <= -0.5 {
            t - 1.0
        } else {
            t
        };
        r.copysign(x)
    } else {
        x
    }
}
