//! `linesample::Error`: every module error converts into it, `?` works in a
//! function returning it, its text is the inner error's and its `source()`
//! is the inner error.

use core::error::Error as _;

use linesample::estimator::{Estimator, PointEstimator};
use linesample::integrand::Ball;
use linesample::pattern::Jittered;
use linesample::spectrum::Grid;
use linesample::world::Sphere;
use linesample::{Error, EstimateError, ParamError, PatternError, Seed, SeedError, SpectrumError};

/// A seed source that always fails.
struct Broken;

#[derive(Debug)]
struct BrokenError;
impl core::fmt::Display for BrokenError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("broken")
    }
}
impl core::error::Error for BrokenError {}

impl rand_core::TryRng for Broken {
    type Error = BrokenError;
    fn try_next_u32(&mut self) -> Result<u32, BrokenError> {
        Err(BrokenError)
    }
    fn try_next_u64(&mut self) -> Result<u64, BrokenError> {
        Err(BrokenError)
    }
    fn try_fill_bytes(&mut self, _: &mut [u8]) -> Result<(), BrokenError> {
        Err(BrokenError)
    }
}

/// One case per module error type, each produced by a real call through `?`.
fn fails(case: usize) -> Result<(), Error> {
    match case {
        0 => {
            Jittered::new([0, 4])?;
        }
        1 => {
            Seed::try_from_rng(&mut Broken)?;
        }
        2 => {
            Sphere::<3>::new([0.0; 3], f64::NAN)?;
        }
        3 => {
            let p = Jittered::new([4, 4])?;
            let est = PointEstimator::new(&p)?;
            let ball = Ball::<2>::new([0.5, 0.5], 0.25)?;
            let mut scratch = [0.0f32; 3]; // the estimator needs 32
            est.estimate(&ball, Seed::new(1), false, &mut scratch)?;
        }
        4 => {
            Grid::<2>::new(0)?;
        }
        _ => unreachable!(),
    }
    Ok(())
}

/// The error each case of [`fails`] must give, as the module's own type.
fn expected(case: usize) -> Box<dyn core::error::Error> {
    match case {
        0 => Box::new(PatternError::ZeroStrata { axis: 0 }),
        1 => Box::new(SeedError::Source),
        2 => Box::new(ParamError::NonFinite { name: "radius" }),
        3 => Box::new(EstimateError::Param(ParamError::Length {
            name: "scratch",
            expected: 32,
            got: 3,
        })),
        4 => Box::new(Grid::<2>::new(0).unwrap_err()),
        _ => unreachable!(),
    }
}

#[test]
fn question_mark_converts_every_module_error() {
    for case in 0..5 {
        let e = fails(case).unwrap_err();
        let ok = matches!(
            (case, &e),
            (0, Error::Pattern(PatternError::ZeroStrata { axis: 0 }))
                | (1, Error::Seed(SeedError::Source))
                | (2, Error::Param(ParamError::NonFinite { name: "radius" }))
                | (
                    3,
                    Error::Estimate(EstimateError::Param(ParamError::Length {
                        name: "scratch",
                        expected: 32,
                        got: 3,
                    }))
                )
                | (4, Error::Spectrum(SpectrumError::HalfWidth { k: 0, .. }))
        );
        assert!(ok, "case {case}: {e:?}");
        // The text is the inner error's, unchanged.
        assert_eq!(e.to_string(), expected(case).to_string(), "case {case}");
    }
}

#[test]
fn from_each_type_keeps_the_value() {
    let pattern = PatternError::Range {
        first: 3,
        len: 9,
        n: 10,
    };
    let param = ParamError::OutOfRange {
        name: "sigma",
        value: -1.0,
        min: 1e-6,
        max: 1e6,
    };
    let estimate = EstimateError::Pattern(PatternError::ZeroPoints);
    let spectrum = SpectrumError::Length {
        name: "weights",
        expected: 4,
        got: 5,
    };
    assert!(matches!(Error::from(pattern), Error::Pattern(e) if e == pattern));
    assert!(matches!(
        Error::from(SeedError::Source),
        Error::Seed(SeedError::Source)
    ));
    assert!(matches!(Error::from(param), Error::Param(e) if e == param));
    assert!(matches!(Error::from(estimate), Error::Estimate(e) if e == estimate));
    assert!(matches!(Error::from(spectrum), Error::Spectrum(e) if e == spectrum));
}

/// `source()` is the inner error: the same value, downcast to its own type.
#[test]
fn source_is_the_inner_error() {
    fn source_of<E: core::error::Error + PartialEq + 'static>(inner: E)
    where
        Error: From<E>,
    {
        let text = inner.to_string();
        let e = Error::from(inner);
        let src = e.source().expect("a source");
        assert_eq!(src.to_string(), text);
        assert_eq!(e.to_string(), text);
        let _: &E = src.downcast_ref::<E>().expect("the inner type");
    }
    source_of(PatternError::Shortfall { got: 5, wanted: 9 });
    source_of(SeedError::Source);
    source_of(ParamError::ZeroDirection);
    source_of(EstimateError::Param(ParamError::Count {
        name: "lines",
        value: 0,
    }));
    source_of(SpectrumError::Empty);
    // And by value, per variant.
    let inner = ParamError::Dimension { dim: 4 };
    let e = Error::from(inner);
    assert_eq!(
        e.source().and_then(|s| s.downcast_ref::<ParamError>()),
        Some(&inner)
    );
}

/// Any other error (feature `alloc`): boxed in `Error::Other`, with the same
/// text and itself as the source.
#[test]
fn other_errors_are_boxed() {
    let e = Error::other(BrokenError);
    assert!(matches!(e, Error::Other(_)));
    assert_eq!(e.to_string(), "broken");
    assert!(e.source().unwrap().downcast_ref::<BrokenError>().is_some());
    let Error::Other(inner) = e else {
        unreachable!()
    };
    assert!(inner.downcast_ref::<BrokenError>().is_some());
}

/// `linesample::Error` is a `std` error that crosses threads, so it converts
/// into `Box<dyn std::error::Error + Send + Sync>` (and anything built on it).
#[test]
fn is_send_sync_and_boxes() {
    fn send_sync<T: Send + Sync + 'static>() {}
    send_sync::<Error>();
    fn boxed() -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
        fails(0)?;
        Ok(())
    }
    let e = boxed().unwrap_err();
    assert_eq!(
        e.to_string(),
        PatternError::ZeroStrata { axis: 0 }.to_string()
    );
    assert!(e.downcast_ref::<Error>().is_some());
}
