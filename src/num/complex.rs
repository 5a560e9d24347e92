//! Complex numbers `re + i·im` in `f64`: Fourier coefficients of integrands
//! and the amplitudes of a periodogram. Plain componentwise arithmetic (each
//! operation rounds each component once, `mul` twice); written here rather
//! than taken from `num-complex` to keep the kernel free of dependencies
//! beyond `wide` and `libm`, and because only these five operations are used.

/// A complex number `re + i·im`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Complex {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

// Named methods, as for `Dd`: `a.mul(b)` is the textbook product with its
// stated rounding, not a trait with promises of its own.
#[allow(clippy::should_implement_trait)]
impl Complex {
    /// `0 + 0i`.
    pub const ZERO: Self = Self { re: 0.0, im: 0.0 };

    /// `re + i·im`.
    #[inline(always)]
    #[must_use]
    pub const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }

    /// `self + o`.
    #[inline(always)]
    #[must_use]
    pub fn add(self, o: Self) -> Self {
        Self {
            re: self.re + o.re,
            im: self.im + o.im,
        }
    }

    /// `self − o`.
    #[inline(always)]
    #[must_use]
    pub fn sub(self, o: Self) -> Self {
        Self {
            re: self.re - o.re,
            im: self.im - o.im,
        }
    }

    /// `self · o = (ac − bd) + i(ad + bc)` (no fused operations, so the result
    /// is the same in every build).
    #[inline(always)]
    #[must_use]
    pub fn mul(self, o: Self) -> Self {
        Self {
            re: self.re * o.re - self.im * o.im,
            im: self.re * o.im + self.im * o.re,
        }
    }

    /// `self · x` for a real `x`.
    #[inline(always)]
    #[must_use]
    pub fn scale(self, x: f64) -> Self {
        Self {
            re: self.re * x,
            im: self.im * x,
        }
    }

    /// The conjugate `re − i·im`.
    #[inline(always)]
    #[must_use]
    pub fn conj(self) -> Self {
        Self {
            re: self.re,
            im: -self.im,
        }
    }

    /// `|z|²` (underflows for `|z| < 1e−154`; see [`Complex::abs`]).
    #[inline(always)]
    #[must_use]
    pub fn norm_sqr(self) -> f64 {
        self.re * self.re + self.im * self.im
    }

    /// `|z|`, without intermediate overflow or underflow (`hypot`).
    #[must_use]
    pub fn abs(self) -> f64 {
        libm::hypot(self.re, self.im)
    }
}
