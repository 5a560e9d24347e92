//! Fuzzes the ball / disk indicator closed forms with arbitrary `f64` parameters: a rejected
//! parameter is fine, a panic, a NaN/∞ or a value outside `[0, maximum]` is not
//! (see `common/integrand.rs` for the checks).
//!
//! Run: `cargo fuzz run --sanitizer none integrand_ball`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::integrand::Ball;

#[path = "common/integrand.rs"]
mod common;
use common::{check, Probe};

#[derive(Arbitrary, Debug)]
enum Input {
    D2 {
        centre: [f64; 2],
        radius: f64,
        probes: Vec<Probe<2>>,
    },
    D3 {
        centre: [f64; 3],
        radius: f64,
        probes: Vec<Probe<3>>,
    },
}

fuzz_target!(|input: Input| match input {
    Input::D2 {
        centre,
        radius,
        probes,
    } => {
        if let Ok(f) = Ball::<2>::new(centre, radius) {
            check(&f, 1.0, 2.0 * radius, &probes);
        }
    }
    Input::D3 {
        centre,
        radius,
        probes,
    } => {
        if let Ok(f) = Ball::<3>::new(centre, radius) {
            check(&f, 1.0, 2.0 * radius, &probes);
        }
    }
});
