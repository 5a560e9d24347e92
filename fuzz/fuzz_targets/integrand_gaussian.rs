//! Fuzzes the normalised Gaussian closed forms with arbitrary `f64` parameters: a rejected
//! parameter is fine, a panic, a NaN/∞ or a value outside `[0, maximum]` is not
//! (see `common/integrand.rs` for the checks).
//!
//! Run: `cargo fuzz run --sanitizer none integrand_gaussian`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::integrand::Gaussian;

#[path = "common/integrand.rs"]
mod common;
use common::{check, Probe};

#[derive(Arbitrary, Debug)]
enum Input {
    D2 {
        centre: [f64; 2],
        sigma: f64,
        probes: Vec<Probe<2>>,
    },
    D3 {
        centre: [f64; 3],
        sigma: f64,
        probes: Vec<Probe<3>>,
    },
}

/// `sup F = (2πσ²)^{-D/2}` and the largest line integral `σ√(2π)·sup F`.
fn bounds(sigma: f64, d: i32) -> (f64, f64) {
    let peak = (2.0 * core::f64::consts::PI * sigma * sigma)
        .powi(-d)
        .sqrt();
    (peak, sigma * (2.0 * core::f64::consts::PI).sqrt() * peak)
}

fuzz_target!(|input: Input| match input {
    Input::D2 {
        centre,
        sigma,
        probes,
    } => {
        if let Ok(f) = Gaussian::<2>::new(centre, sigma) {
            let (peak, line) = bounds(sigma, 2);
            check(&f, peak, line, &probes);
        }
    }
    Input::D3 {
        centre,
        sigma,
        probes,
    } => {
        if let Ok(f) = Gaussian::<3>::new(centre, sigma) {
            let (peak, line) = bounds(sigma, 3);
            check(&f, peak, line, &probes);
        }
    }
});
