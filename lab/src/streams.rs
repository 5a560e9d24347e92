//! One seed scheme for every scene experiment: each random stream is named
//! by a typed tuple of purposes, and its seed is the kernel's derivation
//! along that tuple ([`linesample::Seed::derive`]).
//!
//! A [`Stream`] is `(effect, dims, part, pixel, estimator, N)`; realisation
//! `r` of it appends `r`. Every seed of a run is therefore
//! `Seed::new(SEED).derive(&[effect, dims, part, pixel, estimator, N, r])`,
//! a path of seven components, and distinct paths of one length give
//! distinct seeds for every `SEED` (the derivation is a bijection at each
//! step; see `Seed::derive`). Two rows, two pixels, two scenes of one paper
//! run or the reference and a row can thus never share a stream, whatever
//! `N` (the direct-light scene numbered its streams `1000·e + N`, so rows
//! `(0, 1001)` and `(1, 1)` shared one).
//!
//! The components: `effect` is the scene's [`EffectKind`] (1, 2, 3), `dims`
//! its dimension (3 for the camera scenes, 2 or 3 for the caustic), `part`
//! a [`Part`], `pixel` the index `y·W + x` of the pixel (0 where there is
//! none), `estimator` the row's index in the experiment's list (for the
//! spectral prediction: the prediction job's index) and `N` the sample
//! count (0 where there is none).

use linesample::Seed;

use crate::scene::EffectKind;

/// What a stream is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Part {
    /// A pixel study's (or the caustic study's) reference.
    Reference,
    /// The images' per-pixel reference.
    ImageReference,
    /// The images' estimates.
    Image,
    /// A study row.
    Study,
    /// The pattern realisations of a spectral prediction.
    Spectrum,
    /// The caustic's fluence image.
    Fluence,
}

/// A named stream: see the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Stream {
    /// The scene's effect.
    pub effect: EffectKind,
    /// The scene's dimension.
    pub dims: u64,
    /// What the stream is for.
    pub part: Part,
    /// `y·W + x`, or 0.
    pub pixel: u64,
    /// The row's (or prediction job's) index, or 0.
    pub estimator: u64,
    /// The sample count, or 0.
    pub n: u64,
}

impl Stream {
    /// A stream of `effect` in `dims` dimensions for `part`, with pixel,
    /// estimator and `N` 0 (set them with the builders below).
    #[must_use]
    pub fn new(effect: EffectKind, dims: usize, part: Part) -> Self {
        Stream {
            effect,
            dims: dims as u64,
            part,
            pixel: 0,
            estimator: 0,
            n: 0,
        }
    }

    /// The same stream at pixel `(x, y)` of an image `width` wide.
    #[must_use]
    pub fn pixel(self, x: u32, y: u32, width: u32) -> Self {
        Stream {
            pixel: u64::from(y) * u64::from(width) + u64::from(x),
            ..self
        }
    }

    /// The same stream for estimator (row) `e` at `n` samples.
    #[must_use]
    pub fn row(self, e: usize, n: usize) -> Self {
        Stream {
            estimator: e as u64,
            n: n as u64,
            ..self
        }
    }

    /// The purposes, in order.
    #[must_use]
    pub fn path(&self) -> [u64; 6] {
        let effect = match self.effect {
            EffectKind::AmbientOcclusion => 1,
            EffectKind::DirectLight => 2,
            EffectKind::VolumetricCaustic => 3,
        };
        let part = match self.part {
            Part::Reference => 1,
            Part::ImageReference => 2,
            Part::Image => 3,
            Part::Study => 4,
            Part::Spectrum => 5,
            Part::Fluence => 6,
        };
        [effect, self.dims, part, self.pixel, self.estimator, self.n]
    }

    /// The stream's seed in a run seeded with `run`.
    #[must_use]
    pub fn seed(&self, run: u64) -> Seed {
        Seed::new(run).derive(&self.path())
    }

    /// Realisation `r` of the stream in a run seeded with `run`:
    /// `seed(run).derive(&[r])`.
    #[must_use]
    pub fn realisation(&self, run: u64, r: u64) -> Seed {
        self.seed(run).derive(&[r])
    }
}

/// The row index whose stream each of `rows` draws: its own, except that a
/// row whose `f64_twin` (the same row on the `f64` path, e.g. with its
/// `simd` flag cleared) is also in the list draws the twin's, so that the
/// two differ by the `f32` rounding alone.
#[must_use]
pub fn stream_rows<T: Copy + PartialEq>(rows: &[T], f64_twin: impl Fn(T) -> T) -> Vec<usize> {
    rows.iter()
        .enumerate()
        .map(|(e, &r)| {
            let t = f64_twin(r);
            rows.iter().position(|&o| o == t).unwrap_or(e)
        })
        .collect()
}

/// The realisation seeds of one stream in a run: `at(r)` is
/// [`Stream::realisation`] without deriving the stream's own path again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Realisations(Seed);

impl Realisations {
    /// The realisations of `stream` in a run seeded with `run`.
    #[must_use]
    pub fn of(stream: &Stream, run: u64) -> Self {
        Realisations(stream.seed(run))
    }

    /// Realisation `r`'s seed.
    #[must_use]
    pub fn at(&self, r: u64) -> Seed {
        self.0.derive(&[r])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simd_rows_draw_their_twins_stream() {
        // (value, simd): rows 1 and 3 are the f32 twins of rows 0 and 2;
        // row 4 has no f64 twin in the list.
        let rows = [(1, false), (1, true), (2, false), (2, true), (3, true)];
        assert_eq!(stream_rows(&rows, |(v, _)| (v, false)), [0, 0, 2, 2, 4]);
    }

    #[test]
    fn realisations_are_the_seven_component_path() {
        let s = Stream::new(EffectKind::DirectLight, 3, Part::Study)
            .pixel(3, 2, 10)
            .row(1, 1001);
        assert_eq!(s.path(), [2, 3, 4, 23, 1, 1001]);
        assert_eq!(
            s.realisation(9, 5),
            Seed::new(9).derive(&[2, 3, 4, 23, 1, 1001, 5])
        );
        assert_eq!(Realisations::of(&s, 9).at(5), s.realisation(9, 5));
        // The collision of the old numbering (1000·e + N) is gone.
        let a = Stream::new(EffectKind::DirectLight, 3, Part::Study).row(0, 1001);
        let b = Stream::new(EffectKind::DirectLight, 3, Part::Study).row(1, 1);
        assert_ne!(a.seed(9), b.seed(9));
    }
}
