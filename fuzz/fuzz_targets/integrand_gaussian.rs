//! Fuzzes the normalised Gaussian closed forms with arbitrary `f64` parameters: a rejected
//! parameter is fine, a panic, a NaN/∞ or a value outside `[0, maximum]` is not
//! (see `common/integrand.rs` for the checks). Each `f32` batch lane is within the
//! documented bound of `Gaussian::segment_free_f32` of the `f64` path at the same
//! inputs.
//!
//! Run: `cargo fuzz run --sanitizer none integrand_gaussian`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::integrand::{Gaussian, Integrand};

#[path = "common/integrand.rs"]
mod common;
use common::{check, fin, Probe, Ray32};

/// The `f64` integral of the `f32` ray and the documented bound
/// `P·(1e−6 + expm1(1e−6·E + 2e−7·κ·(1 + √(2E))))` with the line's peak
/// `P = (2πσ²)^{−D/2} e^{−E} σ√(2π)/|d|`, `E = ρ²/2σ²`,
/// `κ = |d|(|q| + |t0| + |t1|)/σ` (finite ends), `q = o − c`; plus the `f32`
/// underflow: the `f32` exponential flushes to 0 below `e^{−87}`, an absolute
/// error of up to `1.7e−38·P·e^{E}` (the prefactor without the exponential),
/// and values below the smallest normal `f32` flush to 0.
fn f32_ref<const D: usize>(g: &Gaussian<D>, r: &Ray32<D>) -> Option<(f64, f64)> {
    let (o, dir, t0, t1, nd) = r.to_f64()?;
    let want = g.segment_free(&o, &dir, t0, t1) / nd;
    let c = g.centre();
    let s = g.sigma();
    let w = dir.get();
    let q: [f64; D] = core::array::from_fn(|j| o[j] - c[j]);
    let qq: f64 = q.iter().map(|x| x * x).sum();
    let qd: f64 = (0..D).map(|j| q[j] * w[j]).sum();
    let rho2 = (qq - qd * qd).max(0.0);
    let e = rho2 / (2.0 * s * s);
    let (peak, _) = bounds(s, D as i32);
    // P·(1e−6 + expm1(B)) = pre·(e^{B−E} − (1 − 1e−6)·e^{−E}) with the prefactor
    // `pre = P·e^E`: no 0·∞ when e^{−E} underflows and e^B overflows.
    let pre = peak * s * (2.0 * core::f64::consts::PI).sqrt() / nd;
    let kappa = nd * (qq.sqrt() + fin(r.t0) + fin(r.t1)) / s;
    let b = 1e-6 * e + 2e-7 * kappa * (1.0 + (2.0 * e).sqrt());
    let bound = pre * ((b - e).exp() - (1.0 - 1e-6) * (-e).exp())
        + 1.7e-38 * peak * s * (2.0 * core::f64::consts::PI).sqrt() / nd
        + 4.0 * f64::from(f32::MIN_POSITIVE);
    Some((want, bound))
}

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
            check(&f, peak, line, &probes, &|r| f32_ref(&f, r));
        }
    }
    Input::D3 {
        centre,
        sigma,
        probes,
    } => {
        if let Ok(f) = Gaussian::<3>::new(centre, sigma) {
            let (peak, line) = bounds(sigma, 3);
            check(&f, peak, line, &probes, &|r| f32_ref(&f, r));
        }
    }
});
