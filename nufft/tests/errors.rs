//! `NufftError` converts into the kernel's `linesample::Error` (boxed in
//! `Error::Other`): `?` works, the text is the same, and `source()` is the
//! NUFFT's error.

use core::error::Error as _;

use linesample::spectrum::Grid;
use linesample_nufft::{NufftError, Plan};

/// A kernel error and a NUFFT error through one `?` each.
fn plan(k: usize, tol: f64) -> Result<(), linesample::Error> {
    Grid::<2>::new(k)?; // SpectrumError
    Plan::<2>::new(k, tol)?; // NufftError
    Ok(())
}

#[test]
fn nufft_errors_convert_into_the_kernel_error() {
    assert!(plan(8, 1e-9).is_ok());
    assert!(matches!(plan(0, 1e-9), Err(linesample::Error::Spectrum(_))));

    let e = plan(8, -1.0).unwrap_err();
    let Err(inner) = Plan::<2>::new(8, -1.0) else {
        panic!("tol = −1 accepted")
    };
    assert_eq!(inner, NufftError::Tolerance(-1.0));
    assert_eq!(e.to_string(), inner.to_string());
    let linesample::Error::Other(boxed) = &e else {
        panic!("not boxed: {e:?}")
    };
    assert_eq!(boxed.downcast_ref::<NufftError>(), Some(&inner));
    let src = e.source().expect("a source");
    assert_eq!(src.downcast_ref::<NufftError>(), Some(&inner));
    assert_eq!(src.to_string(), inner.to_string());
}
