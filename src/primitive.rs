//! Sample primitives: segments and lines (`f64`, validated), and the `f32`
//! structure-of-arrays ray batch taken by the SIMD closed forms.
//!
//! * A [`Segment`] is `{c + t·ω : t ∈ [−λ/2, λ/2]}` on the unit torus: it wraps
//!   around the period, so a segment longer than 1 passes some cells several
//!   times (wrapping is what keeps the segment estimator unbiased: Singh et
//!   al. 2017; `docs/theory.md`, Estimators).
//! * A [`Line`] is `{p + t·ω}` restricted to the unit box `[0, 1]^D`
//!   (a line in a general direction does not close on the torus;
//!   `docs/theory.md`, Lines on the torus).
//!   For an axis direction the chord of the box is one full period, so the box
//!   line and the torus line coincide.

use crate::error::ParamError;
use crate::geom::{Direction, MAX_SEGMENT_LENGTH};
use crate::num::Dd;

/// A validated segment length: finite and `0 ≤ λ ≤` [`MAX_SEGMENT_LENGTH`].
/// A subnormal `λ` (`< 2⁻¹⁰²²`, where `λ/2` would round) becomes `0`, so every
/// closed form sees either a point or a length it can halve exactly.
pub(crate) fn check_length(length: f64) -> Result<f64, ParamError> {
    if !length.is_finite() {
        return Err(ParamError::NonFinite { name: "length" });
    }
    if !(0.0..=MAX_SEGMENT_LENGTH).contains(&length) {
        return Err(ParamError::OutOfRange {
            name: "length",
            value: length,
            min: 0.0,
            max: MAX_SEGMENT_LENGTH,
        });
    }
    Ok(if length < f64::MIN_POSITIVE {
        0.0
    } else {
        length
    })
}

/// A segment of length `λ` centred at `c` with direction `ω`, wrapped on the
/// unit torus.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment<const D: usize> {
    centre: [f64; D],
    dir: Direction<D>,
    length: f64,
}

impl<const D: usize> Segment<D> {
    /// A segment. The centre may lie outside `[0, 1)^D` (the integrands take it
    /// modulo 1). A subnormal length is stored as 0 (a point).
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`centre`, `length`),
    /// [`ParamError::OutOfRange`] (`length`) unless `0 ≤ λ ≤`
    /// [`MAX_SEGMENT_LENGTH`].
    pub fn new(centre: [f64; D], dir: Direction<D>, length: f64) -> Result<Self, ParamError> {
        if centre.iter().any(|x| !x.is_finite()) {
            return Err(ParamError::NonFinite { name: "centre" });
        }
        let length = check_length(length)?;
        Ok(Self {
            centre,
            dir,
            length,
        })
    }

    /// A segment from parameters the caller has validated (finite centre,
    /// `0 ≤ λ ≤ MAX_SEGMENT_LENGTH`).
    #[inline]
    pub(crate) fn from_parts(centre: [f64; D], dir: Direction<D>, length: f64) -> Self {
        Self {
            centre,
            dir,
            length,
        }
    }

    /// Centre `c`.
    #[inline]
    #[must_use]
    pub fn centre(&self) -> [f64; D] {
        self.centre
    }

    /// Direction `ω`.
    #[inline]
    #[must_use]
    pub fn dir(&self) -> Direction<D> {
        self.dir
    }

    /// Length `λ` (in units of the parameter `t`).
    #[inline]
    #[must_use]
    pub fn length(&self) -> f64 {
        self.length
    }
}

/// A line `{p + t·ω}`, integrated over its chord of the unit box `[0, 1]^D`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line<const D: usize> {
    point: [f64; D],
    dir: Direction<D>,
}

impl<const D: usize> Line<D> {
    /// The line through `point` with direction `dir`.
    ///
    /// The stored point ([`Line::point`]) is (nearly) the point of the line
    /// nearest to the box centre `c = (½, …, ½)`: `p ← p + τω` with
    /// `τ = (c − p)·ω/|ω|²` (numerator in double-double) rounded to a double,
    /// and `p + τω` formed in double-double and rounded, so each pass leaves
    /// `p` within half an ulp per coordinate of the exact line and within
    /// `ulp(τ)·|ω|` of the foot point along it. The pass is repeated from the
    /// rounded point while `|τ| > 1` (each repetition shrinks the distance to
    /// the foot by a factor of about `2⁻⁵²`; at most 64 passes), so a point given
    /// far along the line still ends within a few ulp of the foot. Clipping to
    /// the box then works with parameters of size `≤ √D` instead of cancelling
    /// when `point` is far away (found by fuzzing: a line through
    /// `(1.6e11, 1.6e11)` had a chord error of `1e−6`, one through
    /// `(3.5e30, 3.5e30, 3.5e30)` along the diagonal a chord of 1.75 for `√3`
    /// after a single pass). A point within distance 1 of the foot takes one
    /// pass.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`point`).
    pub fn new(point: [f64; D], dir: Direction<D>) -> Result<Self, ParamError> {
        if point.iter().any(|x| !x.is_finite()) {
            return Err(ParamError::NonFinite { name: "point" });
        }
        let w = dir.get();
        let mut a = Dd::new(0.0);
        for j in 0..D {
            a = a.add(Dd::prod(w[j], w[j]));
        }
        let a = a.to_f64();
        let mut p = point;
        for _ in 0..64 {
            let mut num = Dd::new(0.0);
            for j in 0..D {
                num = num.add(Dd::diff(0.5, p[j]).mul(Dd::new(w[j])));
            }
            let tau = num.to_f64() / a;
            // A step that overflows (a point near the end of the f64 range,
            // found by the `geometry` fuzz target: it made the point NaN)
            // keeps the last finite point, which is on the line.
            if !tau.is_finite() {
                break;
            }
            let next: [f64; D] =
                core::array::from_fn(|j| Dd::new(p[j]).add(Dd::prod(tau, w[j])).to_f64());
            if next.iter().any(|x| !x.is_finite()) {
                break;
            }
            p = next;
            if tau.abs() <= 1.0 {
                break;
            }
        }
        Ok(Self { point: p, dir })
    }

    /// The torus line along `axis` whose other coordinates are `offset`
    /// (in increasing axis order), e.g. in 3D `axis = 2`, `offset = [x, y]`.
    /// Offsets are taken modulo 1 (exactly), as on the torus.
    ///
    /// # Errors
    /// [`ParamError::OutOfRange`] (`axis`), [`ParamError::Length`] (`offset`
    /// must have `D − 1` entries), [`ParamError::NonFinite`] (`offset`).
    pub fn axis(axis: usize, offset: &[f64]) -> Result<Self, ParamError> {
        let dir = Direction::axis(axis)?;
        if offset.iter().any(|x| !x.is_finite()) {
            return Err(ParamError::NonFinite { name: "offset" });
        }
        if offset.len() + 1 != D {
            return Err(ParamError::Length {
                name: "offset",
                expected: D - 1,
                got: offset.len(),
            });
        }
        let mut p = [0.0; D];
        let mut k = 0;
        for j in 0..D {
            if j != axis {
                p[j] = crate::num::frac(offset[k]);
                k += 1;
            }
        }
        Self::new(p, dir)
    }

    /// A line from a point the caller knows to be finite.
    #[inline]
    pub(crate) fn from_parts(point: [f64; D], dir: Direction<D>) -> Self {
        Self { point, dir }
    }

    /// A point on the line, (nearly) the one nearest to the box centre (see
    /// [`Line::new`]).
    #[inline]
    #[must_use]
    pub fn point(&self) -> [f64; D] {
        self.point
    }

    /// Direction `ω`.
    #[inline]
    #[must_use]
    pub fn dir(&self) -> Direction<D> {
        self.dir
    }
}

/// A structure-of-arrays batch of `f32` rays `o + t·ω`, `t ∈ [t0, t1]`, for the
/// SIMD free-space closed forms (`*_batch_f32` methods of the integrands).
///
/// All slices must have the same length (checked by the batch functions). `t0`
/// may be `−∞` and `t1` may be `+∞` (a full line). Directions are used as given,
/// never normalised: the integral is over the parameter `t`, in units of `|d|`,
/// so pass unit vectors for arc length (the `f32` side of the [crate's
/// conventions](crate#conventions)).
#[derive(Clone, Copy, Debug)]
pub struct Rays32<'a, const D: usize> {
    /// Origins, one slice per coordinate.
    pub origin: [&'a [f32]; D],
    /// Directions, one slice per coordinate.
    pub dir: [&'a [f32]; D],
    /// Start parameters.
    pub t0: &'a [f32],
    /// End parameters (`t1 ≥ t0`).
    pub t1: &'a [f32],
}

impl<const D: usize> Rays32<'_, D> {
    /// Number of rays, after checking that every slice (and `out`, of length
    /// `out_len`) has the same length.
    ///
    /// # Errors
    /// [`ParamError::Length`] naming the first slice that differs.
    pub fn check(&self, out_len: usize) -> Result<usize, ParamError> {
        let n = self.t0.len();
        let bad = |name, got| ParamError::Length {
            name,
            expected: n,
            got,
        };
        for j in 0..D {
            if self.origin[j].len() != n {
                return Err(bad("origin", self.origin[j].len()));
            }
            if self.dir[j].len() != n {
                return Err(bad("dir", self.dir[j].len()));
            }
        }
        if self.t1.len() != n {
            return Err(bad("t1", self.t1.len()));
        }
        if out_len != n {
            return Err(bad("out", out_len));
        }
        Ok(n)
    }
}
