//! Which instructions the SIMD hot paths run: chosen at compile time, and
//! with the `std` feature also at run time.
//!
//! The batch kernels are written over `wide`'s vector types, and `wide`
//! selects its instructions with `cfg(target_feature)`, when the crate is
//! compiled. A renderer that depends on this crate without setting
//! `target-cpu` builds for baseline `x86_64` (SSE2), so its 8-lane vectors are
//! two 128-bit halves and its 32-bit integer products are emulated.
//!
//! With the `std` feature, on `x86_64`, the hot entry points are compiled a
//! second time inside a function with `#[target_feature(enable =
//! "avx2,fma")]` ([`dispatch`]), which runs when the CPU has AVX2 and FMA
//! ([`level`]). A [`Kernel`] is generic over an [`Isa`], the level's lane
//! types: `wide`'s at the compiled level, [`crate::num::avx2`]'s 256-bit
//! types over `core::arch` in the AVX2 copy. This covers the periodogram
//! accumulation ([`crate::spectrum::Dft`]) and the `f32` ray batches of
//! [`crate::world`] and [`crate::integrand::HalfSpace`], and the random,
//! jittered, Sobol′, Halton and N-rooks (up to 2¹⁶ points) pattern fills,
//! whose integer hashes run in 256-bit lanes there (`vpmulld`, `vpmullw`).
//! The multi-jittered fills and larger N-rooks fills run their AVX2 copy
//! with `wide`'s types, so they still compute in 128-bit halves (the
//! README's "Build flags" table). The scene crate's batches are not
//! dispatched yet.
//!
//! Code inside a dispatched kernel is written without closures on its hot
//! path (plain loops, the fills' block macros): stable Rust cannot mark a
//! closure `#[inline(always)]`, and a closure compiled out of line is
//! compiled for the baseline, where every `core::arch` intrinsic becomes a
//! call.
//!
//! The kernels use no fused multiply-add and no operation whose result
//! depends on the instruction set (IEEE `+ − × ÷ √`, `floor`, comparisons,
//! selections), so **both copies return the same bits**; `tests/simd.rs`
//! runs each dispatched path at both levels ([`set_level`]).
//!
//! Why own lane types: `wide` chooses its instructions when it is compiled,
//! and its baseline types compiled inside an AVX2 function stay 128-bit
//! (checked in the disassembly). Why not everywhere: without `std` there is
//! no portable way to ask the CPU, so `no_std` builds, and other
//! architectures, use the compile-time choice only. A build with
//! `target-cpu=x86-64-v3` (or `native` on such a CPU) needs no dispatch and
//! compiles one copy.

/// An instruction-set level of the SIMD hot paths.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// What the crate was compiled for (`cfg(target_feature)`), with no
    /// run-time selection: SSE2 on a default `x86_64` build.
    Compiled,
    /// AVX2 and FMA selected at run time (`x86_64` with `std` only).
    Avx2Fma,
}

impl Level {
    /// The level's name: `compiled` (also what `LINESAMPLE_SIMD` takes to
    /// turn the run-time level off) or `avx2`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Level::Compiled => "compiled",
            Level::Avx2Fma => "avx2",
        }
    }
}

impl core::fmt::Display for Level {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// Whether the run-time AVX2 copy exists in this build: `std` on `x86_64`,
/// and the crate not already compiled with AVX2 and FMA (then the one copy
/// has them).
pub const RUNTIME_DISPATCH: bool = cfg!(all(
    feature = "std",
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
));

/// Whether this CPU has AVX2 and FMA (always `false` without `std` unless
/// the build enables both).
#[must_use]
pub fn avx2_fma_available() -> bool {
    #[cfg(all(target_feature = "avx2", target_feature = "fma"))]
    {
        true
    }
    #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
    {
        #[cfg(all(feature = "std", target_arch = "x86_64"))]
        {
            std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
        }
        #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
        {
            false
        }
    }
}

/// The level the hot paths run at.
///
/// Where [`RUNTIME_DISPATCH`] holds, decided on first use: [`Level::Avx2Fma`]
/// if the CPU has AVX2 and FMA, unless the environment variable
/// `LINESAMPLE_SIMD` is `compiled` (or `baseline`, `off`, `0`), and
/// [`Level::Compiled`] otherwise; other values of the variable are ignored.
/// [`set_level`] overrides it. Elsewhere always [`Level::Compiled`] (which is
/// then AVX2 + FMA if the build enables them).
#[must_use]
#[inline]
pub fn level() -> Level {
    #[cfg(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    {
        rt::level()
    }
    #[cfg(not(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    )))]
    {
        Level::Compiled
    }
}

/// Forces the level of every later hot-path call, in every thread (for tests
/// and benchmarks: the results are the same bits at every level, so this
/// changes only the speed).
///
/// # Errors
/// [`crate::error::ParamError`] naming `level` if `Level::Avx2Fma` is asked
/// for where it is not available: without [`RUNTIME_DISPATCH`] (no `std`,
/// not `x86_64`, or a build that already has AVX2 and FMA, where
/// `Level::Compiled` is that level), or on a CPU without AVX2 and FMA.
pub fn set_level(level: Level) -> Result<(), crate::error::ParamError> {
    if level == Level::Avx2Fma && !(RUNTIME_DISPATCH && avx2_fma_available()) {
        return Err(crate::error::ParamError::Unavailable {
            name: "level",
            reason: "the run-time AVX2 + FMA path is not available in this build or on this CPU",
        });
    }
    #[cfg(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    rt::store(level);
    Ok(())
}

/// The lane types of one instruction-set level: what a batch kernel written
/// over [`Lane`](crate::num::lane::Lane) is instantiated with.
pub trait Isa {
    /// Eight `f32` lanes.
    type F32: crate::num::lane::F32Lane;
    /// Four `f64` lanes.
    type F64: crate::num::lane::F64Lane;
    /// Eight `u32` lanes, whose `f32` lanes are [`Isa::F32`].
    type U32: crate::num::lane::U32x8Lane<F = Self::F32>;
    /// Sixteen `u16` lanes, widening to [`Isa::U32`].
    type U16: crate::num::lane::U16x16Lane<U32 = Self::U32>;
}

/// The compiled level: `wide`'s `f32x8` and `f64x4`, and
/// [`crate::num::lane::Wu32x8`] (`wide`'s `u32x8` with an SSE2 multiply).
#[derive(Clone, Copy, Debug)]
pub struct Wide;

impl Isa for Wide {
    type F32 = wide::f32x8;
    type F64 = wide::f64x4;
    type U32 = crate::num::lane::Wu32x8;
    type U16 = wide::u16x16;
}

/// One hot call, to run at the current [`level`] through [`dispatch`]: a
/// fill, a batch, an accumulation, with its arguments as fields, and its
/// body generic over the level's lane types `I`.
///
/// Why a trait and not a closure: [`Kernel::run`] is `#[inline(always)]` in
/// every implementation, which makes LLVM compile its whole body (and what
/// it inlines) into the AVX2 copy; a closure is a separate function that
/// LLVM may keep out of line, compiled for the baseline.
pub trait Kernel {
    /// The call's result.
    type Output;
    /// Makes the call with the lane types `I`. Implementations mark it
    /// `#[inline(always)]`.
    fn run<I: Isa>(self) -> Self::Output;
}

/// Runs `k` at the current [`level`]: `k.run::<Avx2>()` inside a function
/// compiled with AVX2 and FMA where that level is selected, else
/// `k.run::<Wide>()` as compiled.
#[inline(always)]
pub fn dispatch<K: Kernel>(k: K) -> K::Output {
    #[cfg(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    if rt::level() == Level::Avx2Fma {
        // SAFETY: `rt::level()` is `Avx2Fma` only where the CPU has AVX2 and
        // FMA (`rt::detect`, `set_level`).
        return unsafe { rt::run_avx2_fma(k) };
    }
    k.run::<Wide>()
}

#[cfg(all(
    feature = "std",
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
pub use rt::Avx2;

/// Everything that exists only where [`RUNTIME_DISPATCH`] holds: the cached
/// level, its detection, the AVX2 lane types' [`Isa`] and the AVX2 copy.
#[cfg(all(
    feature = "std",
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
mod rt {
    use super::{avx2_fma_available, Isa, Kernel, Level};
    use core::sync::atomic::{AtomicU8, Ordering};

    const UNSET: u8 = 0;
    const COMPILED: u8 = 1;
    const AVX2: u8 = 2;

    /// The level, [`UNSET`] until first use.
    static LEVEL: AtomicU8 = AtomicU8::new(UNSET);

    #[inline]
    pub(super) fn level() -> Level {
        match LEVEL.load(Ordering::Relaxed) {
            AVX2 => Level::Avx2Fma,
            COMPILED => Level::Compiled,
            _ => detect(),
        }
    }

    #[cold]
    fn detect() -> Level {
        let off = std::env::var_os("LINESAMPLE_SIMD").is_some_and(|v| {
            let v = v.to_string_lossy().to_ascii_lowercase();
            matches!(v.as_str(), "compiled" | "baseline" | "off" | "0")
        });
        let l = if !off && avx2_fma_available() {
            Level::Avx2Fma
        } else {
            Level::Compiled
        };
        store(l);
        l
    }

    pub(super) fn store(l: Level) {
        let v = match l {
            Level::Compiled => COMPILED,
            Level::Avx2Fma => AVX2,
        };
        LEVEL.store(v, Ordering::Relaxed);
    }

    /// The run-time AVX2 level: [`crate::num::avx2`]'s `F32x8`, `F64x4` and
    /// `U32x8`.
    #[derive(Clone, Copy, Debug)]
    pub struct Avx2;

    impl Isa for Avx2 {
        type F32 = crate::num::avx2::F32x8;
        type F64 = crate::num::avx2::F64x4;
        type U32 = crate::num::avx2::U32x8;
        type U16 = crate::num::avx2::U16x16;
    }

    /// `k.run::<Avx2>()` compiled with AVX2 and FMA enabled.
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    pub(super) unsafe fn run_avx2_fma<K: Kernel>(k: K) -> K::Output {
        k.run::<Avx2>()
    }
}
