//! Fuzzes the half-space (straight edge in the unit box) closed forms with arbitrary `f64` parameters: a rejected
//! parameter is fine, a panic, a NaN/∞ or a value outside `[0, maximum]` is not
//! (see `common/integrand.rs` for the checks).
//!
//! Run: `cargo fuzz run --sanitizer none integrand_halfspace`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::geom::Direction;
use linesample::integrand::HalfSpace;

#[path = "common/integrand.rs"]
mod common;
use common::{check, Probe};

#[derive(Arbitrary, Debug)]
enum Input {
    D2 {
        normal: [f64; 2],
        offset: f64,
        probes: Vec<Probe<2>>,
    },
    D3 {
        normal: [f64; 3],
        offset: f64,
        probes: Vec<Probe<3>>,
    },
}

fuzz_target!(|input: Input| match input {
    Input::D2 {
        normal,
        offset,
        probes,
    } => {
        if let Ok(n) = Direction::new(normal) {
            if let Ok(f) = HalfSpace::<2>::new(n, offset) {
                check(&f, 1.0, 2f64.sqrt(), &probes);
            }
        }
    }
    Input::D3 {
        normal,
        offset,
        probes,
    } => {
        if let Ok(n) = Direction::new(normal) {
            if let Ok(f) = HalfSpace::<3>::new(n, offset) {
                check(&f, 1.0, 3f64.sqrt(), &probes);
            }
        }
    }
});
