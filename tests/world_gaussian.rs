//! The world-space [`Gaussian`] (`linesample::world`) against independent
//! high-precision references (`tests/gauss_ref`: exact line geometry,
//! Gauss–Kronrod quadrature with double-double exponents, `e^{−E}` to about
//! `2⁻¹⁰⁰`): `value`, `line`, `segment`, `optical_depth`, `transmittance`,
//! `opacity`, normalised and with a peak, σ over `1e-6 … 1e6`, values down to
//! `1e-300`; the proptest strategy `linesample::strategy::gaussian_segment`
//! and deterministic hard cases (deep tails, short segments, half lines,
//! far centres and origins); the `f32` twins and SIMD batches (bit-identical
//! lane by lane, error within the documented bounds); bad input. Run with
//! `--nocapture` to see the worst errors.

// `!(x <= y)` is deliberate: it also catches NaN.
#![allow(
    clippy::needless_range_loop,
    clippy::type_complexity,
    clippy::neg_cmp_op_on_partial_ord
)]

mod common;
mod exact;
mod gauss_ref;

use exact::Mix;
use gauss_ref::{exp_neg, one_minus_exp_neg, Gauss, D2};
use linesample::strategy::{self, GaussianSegment};
use linesample::world::{Gaussian, Ray, Rays32};
use linesample::ParamError;
use proptest::prelude::*;
use proptest::test_runner::Config;
use std::cell::RefCell;

/// The documented relative bound of `segment` (and `line`) for results
/// `≥ 2.2e-308`.
const SEG_BOUND: f64 = 1e-14;
/// One ulp, relative (upper bound `2⁻⁵²`).
const ULP: f64 = f64::EPSILON;

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}

// ---------------------------------------------------------------------------
// Error bookkeeping
// ---------------------------------------------------------------------------

/// The worst error of one form and the cases that exceed its documented
/// bound, printed when dropped (also when a test fails, so the numbers are
/// always shown); [`Worst::finish`] fails the test if any case exceeded its
/// bound (after the whole run).
struct Worst {
    name: String,
    n: usize,
    err: f64,
    at: String,
    ratio: f64,
    viol: usize,
    viol_ratio: f64,
    viol_at: String,
    /// Results below the normal range (checked with an absolute floor).
    sub: usize,
}

impl Worst {
    fn new(name: impl Into<String>) -> Self {
        Worst {
            name: name.into(),
            n: 0,
            err: 0.0,
            at: String::new(),
            ratio: 0.0,
            viol: 0,
            viol_ratio: 0.0,
            viol_at: String::new(),
            sub: 0,
        }
    }
    /// Records the relative error `err` against `bound`.
    fn add(&mut self, err: f64, bound: f64, at: impl Fn() -> String) {
        self.n += 1;
        if !(err <= bound) {
            self.viol += 1;
            let r = if err.is_nan() {
                f64::INFINITY
            } else {
                err / bound
            };
            if r >= self.viol_ratio {
                self.viol_ratio = r;
                self.viol_at = format!("rel err {err:e} > bound {bound:e}: {}", at());
            }
            return;
        }
        if err > self.err {
            self.err = err;
            self.at = at();
        }
        self.ratio = self.ratio.max(err / bound);
    }
    /// Records `got` against the reference `want` at a relative bound for
    /// normal results; below the normal range (documented: "degrades
    /// gracefully into subnormals and 0") the error must stay within the
    /// relative bound plus 4 subnormal ulps.
    fn add_value(&mut self, got: f64, want: f64, bound: f64, at: impl Fn() -> String) {
        if want.abs() >= f64::MIN_POSITIVE {
            self.add(rel(got, want), bound, || {
                format!("got {got:e} want {want:e}: {}", at())
            });
        } else {
            self.sub += 1;
            let floor = 4.0 * f64::from_bits(1);
            let ok = (got - want).abs() <= bound * want.abs() + floor;
            self.add(if ok { 0.0 } else { f64::INFINITY }, bound, || {
                format!("(subnormal) got {got:e} want {want:e}: {}", at())
            });
        }
    }
    fn finish(&self) {
        assert!(
            self.viol == 0,
            "{}: {} of {} cases exceed the documented bound; worst: {}",
            self.name,
            self.viol,
            self.n,
            self.viol_at
        );
    }
}

impl Drop for Worst {
    fn drop(&mut self) {
        if self.n > self.viol {
            println!(
                "{}: {} cases ({} below the normal range), worst relative error {:.3e} ({:.2} ulp, {:.3} of the bound) at {}",
                self.name,
                self.n - self.viol,
                self.sub,
                self.err,
                self.err / ULP,
                self.ratio,
                self.at
            );
        }
        if self.viol > 0 {
            println!(
                "{}: {} of {} cases EXCEED the documented bound; worst (error/bound {:.3e}): {}",
                self.name, self.viol, self.n, self.viol_ratio, self.viol_at
            );
        }
    }
}

/// `|a − b|/|b|` (`|a|` for `b = 0`; 0 when both are 0 or equal infinities).
fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else if b == 0.0 {
        a.abs()
    } else {
        ((a - b) / b).abs()
    }
}

/// Accumulators for one family of cases.
struct Acc {
    segment: Worst,
    /// `segment_fast` against its own run-time bound `R`.
    fast: Worst,
    /// Cases where `segment_fast` gave a finite bound, and all cases.
    fast_used: (usize, usize),
    line: Worst,
    value: Worst,
    depth: Worst,
    trans: Worst,
    opacity: Worst,
}

impl Acc {
    fn new(what: &str) -> Self {
        Acc {
            segment: Worst::new(format!("{what}: segment")),
            fast: Worst::new(format!("{what}: segment_fast (bound: its own R)")),
            fast_used: (0, 0),
            line: Worst::new(format!("{what}: line")),
            value: Worst::new(format!("{what}: value")),
            depth: Worst::new(format!("{what}: optical_depth")),
            trans: Worst::new(format!("{what}: transmittance")),
            opacity: Worst::new(format!("{what}: opacity")),
        }
    }
    fn finish(&self) {
        println!(
            "segment_fast gave a finite bound in {} of {} cases",
            self.fast_used.0, self.fast_used.1
        );
        self.segment.finish();
        self.fast.finish();
        self.line.finish();
        self.value.finish();
        self.depth.finish();
        self.trans.finish();
        self.opacity.finish();
    }
}

/// The crate's Gaussian and the reference, normalised or with a peak.
fn pair<const D: usize>(c: [f64; D], sigma: f64, peak: Option<f64>) -> (Gaussian<D>, Gauss<D>) {
    match peak {
        None => (
            Gaussian::normalised(c, sigma).unwrap(),
            Gauss::normalised(c, sigma),
        ),
        Some(a) => (
            Gaussian::with_peak(c, sigma, a).unwrap(),
            Gauss::with_peak(c, sigma, a),
        ),
    }
}

/// Checks every `f64` form for one Gaussian, ray and segment `[t0, t1]`
/// (`t0 ≤ t1`): `segment` (and the reversed segment, negated), `line`,
/// `value` at the finite ends, and `optical_depth`, `transmittance`,
/// `opacity` for an extinction `σ_t` making the optical depth `tau`.
fn check<const D: usize>(
    acc: &mut Acc,
    g: &Gaussian<D>,
    r: &Gauss<D>,
    ray: &Ray<D>,
    t0: f64,
    t1: f64,
    tau: f64,
) {
    let (o, w) = (ray.origin(), ray.dir().get());
    let ctx = || {
        format!(
            "c={:?} σ={:e} A={:e} o={o:?} w={w:?} [{t0:e}, {t1:e}]",
            g.centre(),
            g.sigma(),
            g.peak()
        )
    };
    let want = r.segment(&o, &w, t0, t1);
    let got = g.segment(ray, t0, t1);
    acc.segment.add_value(got, want, SEG_BOUND, ctx);
    if t0 < t1 {
        assert_eq!(g.segment(ray, t1, t0), -got, "reversed: {}", ctx());
    }
    // The plain-f64 path against the same reference, within its own bound.
    let (fv, fr) = g.segment_fast(ray, t0, t1);
    acc.fast_used.1 += 1;
    if fr.is_finite() && want.abs() >= f64::MIN_POSITIVE {
        acc.fast_used.0 += 1;
        // R is relative to the exact value; the reference is rounded once.
        acc.fast.add(rel(fv, want), fr + ULP, || {
            format!("got {fv:e} want {want:e} R {fr:e}: {}", ctx())
        });
    }
    let lw = r.line(&o, &w);
    acc.line.add_value(g.line(ray), lw, SEG_BOUND, ctx);
    for t in [t0, t1] {
        if t.is_finite() {
            let x = ray.at(t);
            // "relative error ≤ 4 ulp down to the normal range"; the
            // reference is rounded once (≤ ½ ulp).
            acc.value
                .add_value(g.value(&x), r.value(&x), 4.5 * ULP, || {
                    format!("x={x:?}: {}", ctx())
                });
        }
    }
    // Optical depth τ = σ_t·∫F, T = e^{−τ}, 1 − T.
    if want > 0.0 && want.is_finite() && tau > 0.0 {
        let st = tau / want;
        if st.is_finite() && st > 0.0 {
            let tw = D2::prod(st, want);
            let d = g.optical_depth(ray, t0, t1, st);
            acc.depth.add_value(d, tw.to_f64(), SEG_BOUND + ULP, || {
                format!("σ_t={st:e}: {}", ctx())
            });
            let tr = g.transmittance(ray, t0, t1, st);
            acc.trans
                .add_value(tr, exp_neg(tw), tw.hi * 1e-14 + ULP, || {
                    format!("σ_t={st:e} τ={:e}: {}", tw.hi, ctx())
                });
            let op = g.opacity(ray, t0, t1, st);
            acc.opacity
                .add_value(op, one_minus_exp_neg(tw), SEG_BOUND + ULP, || {
                    format!("σ_t={st:e} τ={:e}: {}", tw.hi, ctx())
                });
        }
    }
}

// ---------------------------------------------------------------------------
// The reference against closed forms
// ---------------------------------------------------------------------------

/// The quadrature reference against the closed-form line integral (exact
/// geometry) on whole lines and on lines split at a random point: both are
/// independent, so their agreement bounds the reference's own error.
#[test]
fn reference_agrees_with_closed_form_lines() {
    let mut g = Mix(0x5e1f);
    let mut worst = 0.0f64;
    for i in 0..400 {
        let sigma = 10f64.powf(g.range(-6.0, 6.0));
        let c: [f64; 3] =
            core::array::from_fn(|_| g.range(-3.0, 3.0) * sigma * 10f64.powf(g.range(0.0, 3.0)));
        let r = Gauss::<3>::with_peak(c, sigma, 10f64.powf(g.range(-300.0, 300.0)));
        let w: [f64; 3] = g.unit();
        let d = sigma * (2.0 * g.range(0.0, 690.0)).sqrt();
        let u: [f64; 3] = g.unit();
        let o: [f64; 3] =
            core::array::from_fn(|j| c[j] + d * u[j] + g.range(-5.0, 5.0) * sigma * w[j]);
        let line = r.line(&o, &w);
        let split = g.range(-3.0, 3.0) * sigma;
        let q = if i % 2 == 0 {
            r.segment(&o, &w, f64::NEG_INFINITY, f64::INFINITY)
        } else {
            r.segment(&o, &w, f64::NEG_INFINITY, split) + r.segment(&o, &w, split, f64::INFINITY)
        };
        if line >= f64::MIN_POSITIVE {
            worst = worst.max(rel(q, line));
        }
    }
    println!("gauss_ref: quadrature vs closed-form lines, worst relative difference {worst:.3e}");
    assert!(worst <= 1e-15, "{worst:e}");
}

// ---------------------------------------------------------------------------
// Proptest: the crate's strategy
// ---------------------------------------------------------------------------

fn strategy_segments<const D: usize>(cases: u32) {
    let acc = RefCell::new(Acc::new(&format!("{D}D strategy::gaussian_segment")));
    proptest!(config(cases), |(
        case in strategy::gaussian_segment::<D>(),
        peak in prop_oneof![Just(None), strategy::log_uniform(-300.0, 300.0).prop_map(Some)],
        tau in strategy::log_uniform(-12.0, 2.845),
    )| {
        let GaussianSegment { centre, sigma, origin, dir, t0, t1, .. } = case;
        let (g, r) = pair(centre, sigma, peak);
        let ray = Ray::new(origin, dir).unwrap();
        check(&mut acc.borrow_mut(), &g, &r, &ray, t0, t1, tau);
    });
    acc.borrow().finish();
}

#[test]
fn strategy_gaussian_segments_2d() {
    strategy_segments::<2>(400);
}

#[test]
fn strategy_gaussian_segments_3d() {
    strategy_segments::<3>(400);
}

// ---------------------------------------------------------------------------
// Deterministic hard cases
// ---------------------------------------------------------------------------

/// For every σ in `1e-6 … 1e6`, normalised and with peaks `1`, `1e-300`,
/// `1e300`: radial and oblique segments at the exponents of `1e-90`,
/// `1e-300` and `1e-320` of the peak (lengths `1e-9σ … 30σ`), segments
/// straddling the foot, half lines, lines, short segments near the centre,
/// with centres near the origin and `1e6σ` away.
fn hard_cases<const D: usize>(acc: &mut Acc) {
    let mut mix = Mix(0x6a_0000 + D as u64);
    for sigma in [1e-6, 1e-3, 0.3, 1.0, 1e3, 1e6] {
        for peak in [None, Some(1.0), Some(1e-300), Some(1e300)] {
            for far in [0.0, 1e6] {
                let c: [f64; D] = core::array::from_fn(|j| (0.3 + 0.2 * j as f64 + far) * sigma);
                let (g, r) = pair(c, sigma, peak);
                for e in [0.0f64, 2.0, 207.0, 690.0, 736.0] {
                    let u: [f64; D] = mix.unit();
                    let d = sigma * (2.0 * e).sqrt();
                    let x: [f64; D] = core::array::from_fn(|j| c[j] + d * u[j]);
                    for len in [1e-9, 1e-3, 0.1, 1.0, 30.0] {
                        let l = len * sigma;
                        // Radial, moving away from the centre.
                        let ray = Ray::new(x, u).unwrap();
                        check(acc, &g, &r, &ray, 0.0, l, mix.range(1e-6, 100.0));
                        // Radial, moving in (near end = t1).
                        let back: [f64; D] = u.map(|v| -v);
                        let ray = Ray::new(x, back).unwrap();
                        check(acc, &g, &r, &ray, -l, 0.0, mix.range(1e-6, 100.0));
                        // Oblique, from a point before it.
                        let v: [f64; D] = mix.unit();
                        let o: [f64; D] = core::array::from_fn(|j| x[j] - 3.0 * sigma * v[j]);
                        let ray = Ray::new(o, v).unwrap();
                        check(
                            acc,
                            &g,
                            &r,
                            &ray,
                            3.0 * sigma,
                            3.0 * sigma + l,
                            mix.range(1e-6, 100.0),
                        );
                        check(
                            acc,
                            &g,
                            &r,
                            &ray,
                            3.0 * sigma - 0.5 * l,
                            3.0 * sigma + 0.5 * l,
                            1.0,
                        );
                    }
                    // Half lines and the line through x along a random
                    // direction, from an origin up to 1e6σ away.
                    let v: [f64; D] = mix.unit();
                    let s = sigma * 10f64.powf(mix.range(-1.0, 6.0));
                    let o: [f64; D] = core::array::from_fn(|j| x[j] - s * v[j]);
                    let ray = Ray::new(o, v).unwrap();
                    let (ninf, inf) = (f64::NEG_INFINITY, f64::INFINITY);
                    for (t0, t1) in [
                        (ninf, inf),
                        (s, inf),
                        (ninf, s),
                        (s - 2.0 * sigma, inf),
                        (s + 0.5 * sigma, inf),
                    ] {
                        check(acc, &g, &r, &ray, t0, t1, mix.range(1e-12, 700.0));
                    }
                }
            }
        }
    }
}

#[test]
fn hard_cases_2d() {
    let mut acc = Acc::new("2D hard cases");
    hard_cases::<2>(&mut acc);
    acc.finish();
}

#[test]
fn hard_cases_3d() {
    let mut acc = Acc::new("3D hard cases");
    hard_cases::<3>(&mut acc);
    acc.finish();
}

/// `value` at points with exponents `0 … 745` (values down to `1e-323` of
/// the peak), σ over the whole range, far centres.
/// `segment_fast` where its exponent term dominates the bound: lines and
/// long segments given through origins `10⁴…10⁶σ` away along the line, at
/// `ρ` from `σ` to `30σ`, so the cross product `q × ω` cancels and `ρ²` (hence
/// `E = ρ²/2σ²`) carries an absolute error of order `u|q|ρ`. The error must
/// stay within `R`, and these cases must be hard ones: some errors exceed
/// `10⁻¹¹`, far above what the `erfc` terms alone allow. (The exponent term
/// of `R` is the largest here, but a first-order overestimate: the measured
/// errors stay within the argument terms alone, so dropping it would not
/// fail this test; dropping the `erfc` or sensitivity terms fails
/// `hard_cases_*`.)
#[test]
fn segment_fast_exponent_error_is_bounded() {
    let mut worst: f64 = 0.0;
    let mut big = 0;
    let mut rng = common::XorShift(0x9e37_79b9_7f4a_7c15);
    let mut uni = move || rng.uniform();
    for i in 0..3000 {
        let sigma = [1e-3, 1.0, 1e3][i % 3];
        let c = [0.3 * sigma, -0.7 * sigma, 0.2 * sigma];
        let (g, r) = pair(c, sigma, None);
        // A unit direction and a unit normal to it.
        let th = std::f64::consts::TAU * uni();
        let z = 2.0 * uni() - 1.0;
        let s = (1.0 - z * z).sqrt();
        let w = [s * th.cos(), s * th.sin(), z];
        let a = if w[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let mut nrm = [
            w[1] * a[2] - w[2] * a[1],
            w[2] * a[0] - w[0] * a[2],
            w[0] * a[1] - w[1] * a[0],
        ];
        let l = (nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]).sqrt();
        for x in &mut nrm {
            *x /= l;
        }
        let rho = sigma * (1.0 + 29.0 * uni());
        let far = sigma * 10f64.powf(4.0 + 2.0 * uni());
        let o: [f64; 3] = core::array::from_fn(|j| c[j] + rho * nrm[j] - far * w[j]);
        let ray = Ray::new(o, w).unwrap();
        let dir = ray.dir().get();
        let (t0, t1) = if i % 2 == 0 {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (far - 3.0 * sigma, far + 2.0 * sigma)
        };
        let want = r.segment(&ray.origin(), &dir, t0, t1);
        let (got, bound) = g.segment_fast(&ray, t0, t1);
        if !bound.is_finite() || want < f64::MIN_POSITIVE {
            continue;
        }
        let e = rel(got, want);
        assert!(
            e <= bound + ULP,
            "err {e:e} > R {bound:e}: σ {sigma} ρ {rho} far {far} [{t0}, {t1}]"
        );
        worst = worst.max(e / bound);
        big += usize::from(e > 1e-11);
    }
    println!("segment_fast, far origins: worst error/R {worst:.3}, {big} errors above 1e-11");
    assert!(big >= 10, "{big}");
}

#[test]
fn values_down_to_the_subnormals() {
    let mut mix = Mix(0x7a1);
    let mut acc = Worst::new("value");
    for i in 0..6000 {
        let sigma = 10f64.powf(mix.range(-6.0, 6.0));
        let c: [f64; 3] = core::array::from_fn(|_| {
            mix.range(-1.0, 1.0) * sigma * if i % 3 == 0 { 1e6 } else { 1.0 }
        });
        let peak = match i % 4 {
            0 => None,
            1 => Some(1.0),
            _ => Some(10f64.powf(mix.range(-300.0, 300.0))),
        };
        let (g, r) = pair(c, sigma, peak);
        let e = match i % 3 {
            0 => mix.range(0.0, 10.0),
            1 => mix.range(0.0, 745.0),
            _ => mix.range(680.0, 745.0),
        };
        let u: [f64; 3] = mix.unit();
        let x: [f64; 3] = core::array::from_fn(|j| c[j] + sigma * (2.0 * e).sqrt() * u[j]);
        let ctx = || format!("c={c:?} σ={sigma:e} A={:e} x={x:?}", g.peak());
        acc.add_value(g.value(&x), r.value(&x), 4.5 * ULP, ctx);
        // 2D
        let (g2, r2) = pair([c[0], c[1]], sigma, peak);
        let x2 = [x[0], x[1]];
        acc.add_value(g2.value(&x2), r2.value(&x2), 4.5 * ULP, || {
            format!("2D {x2:?}")
        });
    }
    acc.finish();
}

/// The normalisation: `peak()` of `normalised` against `(2πσ²)^{−D/2}`, and
/// `integral()` (1 for the normalised Gaussian, `A(2πσ²)^{D/2}` with a peak).
#[test]
fn normalisation_and_integral() {
    let mut worst = 0.0f64;
    for sigma in [1e-6, 1e-3, 0.1, 0.3, 1.0, 7.0, 1e6] {
        let g2 = Gaussian::<2>::normalised([0.0; 2], sigma).unwrap();
        let g3 = Gaussian::<3>::normalised([1.0; 3], sigma).unwrap();
        worst = worst.max(rel(g2.peak(), gauss_ref::normalisation(2, sigma).to_f64()));
        worst = worst.max(rel(g3.peak(), gauss_ref::normalisation(3, sigma).to_f64()));
        assert!(rel(g2.integral(), 1.0) < 8.0 * ULP, "{sigma}");
        assert!(rel(g3.integral(), 1.0) < 8.0 * ULP, "{sigma}");
        let h = Gaussian::<3>::with_peak([0.0; 3], sigma, 2.5).unwrap();
        assert_eq!(h.peak(), 2.5);
        assert_eq!(h.sigma(), sigma);
        let want = 2.5 * (std::f64::consts::TAU * sigma * sigma).powf(1.5);
        assert!(rel(h.integral(), want) < 8.0 * ULP);
    }
    println!(
        "normalised peak: worst relative error {worst:.3e} ({:.2} ulp)",
        worst / ULP
    );
    assert!(worst <= 4.0 * ULP);
}

/// Transmittance and opacity over optical depths `1e-300 … 745` (where `T`
/// underflows) and `σ_t = 0`, on lines through and near the centre.
#[test]
fn transmittance_and_opacity() {
    let mut mix = Mix(0x7a25);
    let mut trans = Worst::new("transmittance (τ sweep)");
    let mut opac = Worst::new("opacity (τ sweep)");
    for i in 0..3000 {
        let sigma = 10f64.powf(mix.range(-6.0, 6.0));
        let c: [f64; 3] = core::array::from_fn(|_| mix.range(-1.0, 1.0) * sigma);
        let peak = if i % 2 == 0 {
            None
        } else {
            Some(10f64.powf(mix.range(-10.0, 10.0)))
        };
        let (g, r) = pair(c, sigma, peak);
        let u: [f64; 3] = mix.unit();
        let v: [f64; 3] = mix.unit();
        let o: [f64; 3] = core::array::from_fn(|j| {
            c[j] + mix.range(0.0, 3.0) * sigma * u[j] - 2.0 * sigma * v[j]
        });
        let ray = Ray::new(o, v).unwrap();
        let (t0, t1) = if i % 3 == 0 {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (mix.range(0.0, 2.0) * sigma, mix.range(2.0, 5.0) * sigma)
        };
        let want = r.segment(&o, &ray.dir().get(), t0, t1);
        if !(want > 0.0) {
            continue;
        }
        let tau = 10f64.powf(mix.range(-300.0, 2.87));
        let st = tau / want;
        if !(st.is_finite() && st > 0.0) {
            continue;
        }
        let tw = D2::prod(st, want);
        let ctx = || {
            format!(
                "σ={sigma:e} A={:e} o={o:?} w={:?} [{t0:e}, {t1:e}] σ_t={st:e} τ={:e}",
                g.peak(),
                ray.dir().get(),
                tw.hi
            )
        };
        trans.add_value(
            g.transmittance(&ray, t0, t1, st),
            exp_neg(tw),
            tw.hi * 1e-14 + ULP,
            ctx,
        );
        opac.add_value(
            g.opacity(&ray, t0, t1, st),
            one_minus_exp_neg(tw),
            SEG_BOUND + ULP,
            ctx,
        );
        // σ_t = 0: fully transparent.
        assert_eq!(g.transmittance(&ray, t0, t1, 0.0), 1.0);
        assert_eq!(g.opacity(&ray, t0, t1, 0.0), 0.0);
    }
    trans.finish();
    opac.finish();
}

// ---------------------------------------------------------------------------
// f32 twins and SIMD batches
// ---------------------------------------------------------------------------

struct Batch<const D: usize> {
    o: [Vec<f32>; D],
    d: [Vec<f32>; D],
    t0: Vec<f32>,
    t1: Vec<f32>,
}

impl<const D: usize> Batch<D> {
    fn new() -> Self {
        Batch {
            o: core::array::from_fn(|_| Vec::new()),
            d: core::array::from_fn(|_| Vec::new()),
            t0: Vec::new(),
            t1: Vec::new(),
        }
    }
    fn push(&mut self, o: [f32; D], d: [f32; D], t0: f32, t1: f32) {
        for j in 0..D {
            self.o[j].push(o[j]);
            self.d[j].push(d[j]);
        }
        self.t0.push(t0);
        self.t1.push(t1);
    }
    fn rays(&self) -> Rays32<'_, D> {
        Rays32 {
            origin: core::array::from_fn(|j| &self.o[j][..]),
            dir: core::array::from_fn(|j| &self.d[j][..]),
            t0: &self.t0,
            t1: &self.t1,
        }
    }
    fn lane(&self, i: usize) -> ([f32; D], [f32; D], f32, f32) {
        (
            core::array::from_fn(|j| self.o[j][i]),
            core::array::from_fn(|j| self.d[j][i]),
            self.t0[i],
            self.t1[i],
        )
    }
}

/// The `f64` path at the same (`f32`) inputs: `∫_{t0}^{t1} F(o + t·d) dt` in
/// units of the parameter of `d` (`= segment(ray, t0|d|, t1|d|)/|d|`), and the
/// documented `f32` bound `P·(1e−6 + expm1(B))`, `P = A e^{−E} σ√(2π)/|d|`,
/// `E = ρ²/2σ²`, `B = 1e−6·E + 2e−7·κ·(1 + √(2E))`,
/// `κ = |d|(|q| + |t0| + |t1|)/σ` (finite ends), evaluated as
/// `A σ√(2π)/|d| · (e^{B−E} − (1 − 1e−6)e^{−E})` so that neither factor
/// overflows (as `f32_err` in `tests/integrand_gaussian.rs`).
fn f32_want_bound<const D: usize>(
    g: &Gaussian<D>,
    o: [f32; D],
    d: [f32; D],
    t0: f32,
    t1: f32,
) -> (f64, f64, f64) {
    let o64 = o.map(f64::from);
    let d64 = d.map(f64::from);
    let nd = d64.iter().map(|x| x * x).sum::<f64>().sqrt();
    let ray = Ray::new(o64, d64).unwrap();
    let want = g.segment(&ray, f64::from(t0) * nd, f64::from(t1) * nd) / nd;
    let c = g.centre();
    let s = g.sigma();
    let q: [f64; D] = core::array::from_fn(|j| o64[j] - c[j]);
    let qq: f64 = q.iter().map(|x| x * x).sum();
    let qd: f64 = (0..D).map(|j| q[j] * d64[j]).sum::<f64>() / nd;
    let e = (qq - qd * qd).max(0.0) / (2.0 * s * s);
    let pre = g.peak() * s * (2.0 * std::f64::consts::PI).sqrt() / nd;
    let fin = |t: f32| {
        if t.is_finite() {
            f64::from(t).abs()
        } else {
            0.0
        }
    };
    let kappa = nd * (qq.sqrt() + fin(t0) + fin(t1)) / s;
    let b = 1e-6 * e + 2e-7 * kappa * (1.0 + (2.0 * e).sqrt());
    let bound = pre * ((b - e).exp() - (1.0 - 1e-6) * (-e).exp());
    (want, bound, e)
}

/// Worst ratios for the accuracy table.
#[derive(Default, Clone, Copy)]
struct F32Worst {
    seg_ratio: f64,
    seg_peak: f64,
    tr_ratio: f64,
    tr_abs: f64,
    /// Lanes flushed to 0 by the `f32` exponential (`E > 86`, or `τ > 86`
    /// for the transmittance), where the bound formula does not hold.
    flushed: usize,
    lanes: usize,
}

/// Four `f32` subnormal ulps (`4·2⁻¹⁴⁹`): a result in the `f32` subnormal
/// range has no relative precision (the kernel's products round there).
const F32_FLOOR: f64 = 5.605193857299268e-45;

/// Runs both batches, checks every lane bit for bit against the scalar
/// twins and against the documented bounds.
fn check_batch<const D: usize>(g: &Gaussian<D>, b: &Batch<D>, sigma_t: f32, w: &mut F32Worst) {
    let n = b.t0.len();
    let mut out = vec![f32::NAN; n];
    let mut tout = vec![f32::NAN; n];
    g.segment_batch_f32(&b.rays(), &mut out).unwrap();
    g.transmittance_batch_f32(&b.rays(), sigma_t, &mut tout)
        .unwrap();
    for i in 0..n {
        let (o, d, t0, t1) = b.lane(i);
        let s = g.segment_f32(o, d, t0, t1);
        let t = g.transmittance_f32(o, d, t0, t1, sigma_t);
        let ctx = || {
            format!(
                "c={:?} σ={:e} A={:e} o={o:?} d={d:?} [{t0:e}, {t1:e}] σ_t={sigma_t:e}",
                g.centre(),
                g.sigma(),
                g.peak()
            )
        };
        assert_eq!(
            s.to_bits(),
            out[i].to_bits(),
            "segment lane {i} of {n}: {}",
            ctx()
        );
        assert_eq!(
            t.to_bits(),
            tout[i].to_bits(),
            "transmittance lane {i} of {n}: {}",
            ctx()
        );
        w.lanes += 1;
        let (want, bound, e) = f32_want_bound(g, o, d, t0, t1);
        let err = (f64::from(s) - want).abs();
        // Documented: "The f32 exponential flushes to 0 below e^{−87}": a
        // line farther than about 13σ from the centre gives 0, whatever the
        // bound formula says (reported: the formula omits this).
        if s == 0.0 && e >= 86.0 {
            w.flushed += 1;
        } else {
            assert!(
                err <= bound + F32_FLOOR,
                "f32 segment error {err:e} > bound {bound:e}: got {s:e} want {want:e} (E = {e:.1}): {}",
                ctx()
            );
            w.seg_ratio = w.seg_ratio.max(err / (bound + F32_FLOOR));
        }
        // Peak-relative error, for the accuracy table.
        let nd = d.map(f64::from).iter().map(|x| x * x).sum::<f64>().sqrt();
        let p = g.peak() * g.sigma() * (2.0 * std::f64::consts::PI).sqrt() / nd;
        w.seg_peak = w.seg_peak.max(err / p);
        // Transmittance: T·(σ_t·ε + 3e−7), ε the segment bound.
        let st = f64::from(sigma_t);
        let tw = exp_neg(D2::prod(st, want));
        let terr = (f64::from(t) - tw).abs();
        let tb = tw * (st * bound + 3e-7);
        if t == 0.0 && st * want >= 86.0 {
            w.flushed += 1;
        } else {
            assert!(
                terr <= tb + F32_FLOOR,
                "f32 transmittance error {terr:e} > bound {tb:e}: got {t:e} want {tw:e} (τ = {:e}): {}",
                st * want,
                ctx()
            );
            w.tr_ratio = w.tr_ratio.max(terr / (tb + F32_FLOOR));
        }
        w.tr_abs = w.tr_abs.max(terr);
    }
}

fn strategy_f32<const D: usize>(cases: u32) {
    let worst = RefCell::new(F32Worst::default());
    proptest!(config(cases), |(
        cases in prop::collection::vec(strategy::gaussian_segment::<D>(), 1..40),
        peak in prop_oneof![Just(None), strategy::log_uniform(-20.0, 20.0).prop_map(Some)],
        tau in strategy::log_uniform(-6.0, 1.5),
    )| {
        // One Gaussian (the first case's), every case's ray mapped into its
        // frame (offsets scaled by σ/σ_i, so the exponents are kept).
        let c0 = cases[0];
        let (g, _) = pair(c0.centre, c0.sigma, peak);
        let mut b = Batch::<D>::new();
        for c in &cases {
            let k = c0.sigma / c.sigma;
            let o: [f32; D] = core::array::from_fn(|j| (c0.centre[j] + (c.origin[j] - c.centre[j]) * k) as f32);
            let d = c.dir.map(|x| x as f32);
            b.push(o, d, (c.t0 * k) as f32, (c.t1 * k) as f32);
        }
        // σ_t making the line's peak optical depth `tau`.
        let line_peak = g.peak() * c0.sigma * (2.0 * std::f64::consts::PI).sqrt();
        let st = (tau / line_peak) as f32;
        prop_assume!(st.is_finite() && st > 0.0);
        let mut w = worst.borrow_mut();
        check_batch(&g, &b, st, &mut w);
    });
    let w = worst.borrow();
    println!(
        "{D}D f32 (strategy::gaussian_segment batches): segment error/bound ≤ {:.3}; transmittance error/bound ≤ {:.3}, absolute ≤ {:.2e}; {} of {} lanes flushed to 0 (E or τ > 86)",
        w.seg_ratio, w.tr_ratio, w.tr_abs, w.flushed, w.lanes
    );
}

#[test]
fn f32_batch_from_strategy_2d() {
    strategy_f32::<2>(150);
}

#[test]
fn f32_batch_from_strategy_3d() {
    strategy_f32::<3>(150);
}

/// Batches of every length `0 … 17` and a few longer ones, rays within `4σ`
/// of the centre on the σ scale (the accuracy-table case), σ `1e-6 … 1e6`,
/// normalised and with peaks, optical depths up to 30.
#[test]
fn f32_batch_deterministic() {
    fn run<const D: usize>() -> F32Worst {
        let mut mix = Mix(0x000f_326a + D as u64);
        let mut w = F32Worst::default();
        for n in (0..=17).chain([31, 64, 203]) {
            let sigma = 10f64.powf(mix.range(-6.0, 6.0));
            let c: [f64; D] = core::array::from_fn(|_| mix.range(-3.0, 3.0) * sigma);
            let peak = if n % 2 == 0 {
                None
            } else {
                Some(10f64.powf(mix.range(-5.0, 5.0)))
            };
            let (g, _) = pair(c, sigma, peak);
            let mut b = Batch::<D>::new();
            for i in 0..n {
                let o: [f32; D] =
                    core::array::from_fn(|j| (c[j] + 4.0 * sigma * mix.range(-1.0, 1.0)) as f32);
                let v: [f64; D] = mix.unit();
                let d = v.map(|x| x as f32);
                let a = mix.range(-5.0, 5.0) * sigma;
                let t0 = if i % 11 == 3 {
                    f32::NEG_INFINITY
                } else {
                    a as f32
                };
                let t1 = if i % 7 == 2 {
                    f32::INFINITY
                } else {
                    (a + mix.range(0.0, 6.0) * sigma) as f32
                };
                b.push(o, d, t0, t1);
            }
            let line_peak = g.peak() * sigma * (2.0 * std::f64::consts::PI).sqrt();
            let st = (mix.range(0.01, 30.0) / line_peak) as f32;
            check_batch(&g, &b, st, &mut w);
        }
        w
    }
    let w2 = run::<2>();
    let w3 = run::<3>();
    println!(
        "f32 (deterministic batches, σ-scale rays): segment error/bound 2D {:.3}, 3D {:.3}; segment error ≤ {:.2e} (2D), {:.2e} (3D) of the line peak; transmittance error/bound 2D {:.3}, 3D {:.3}, absolute ≤ {:.2e}",
        w2.seg_ratio, w3.seg_ratio, w2.seg_peak, w3.seg_peak, w2.tr_ratio, w3.tr_ratio, w2.tr_abs.max(w3.tr_abs)
    );
}

#[test]
fn f32_batch_rejects_mismatched_lengths() {
    let g = Gaussian::<3>::normalised([0.0; 3], 1.0).unwrap();
    let mut b = Batch::<3>::new();
    for _ in 0..13 {
        b.push([0.0; 3], [1.0, 0.0, 0.0], 0.0, 1.0);
    }
    let mut out = vec![0.0f32; 12];
    assert!(matches!(
        g.segment_batch_f32(&b.rays(), &mut out),
        Err(ParamError::Length {
            name: "out",
            expected: 13,
            got: 12
        })
    ));
    assert!(matches!(
        g.transmittance_batch_f32(&b.rays(), 1.0, &mut out),
        Err(ParamError::Length { name: "out", .. })
    ));
    let mut rays = b.rays();
    rays.t0 = &b.t0[..4];
    let mut out = vec![0.0f32; 13];
    assert!(matches!(
        g.segment_batch_f32(&rays, &mut out),
        Err(ParamError::Length { .. })
    ));
    assert!(matches!(
        g.transmittance_batch_f32(&rays, 1.0, &mut out),
        Err(ParamError::Length { .. })
    ));
}

// ---------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------

#[test]
fn constructors_reject_bad_input() {
    use ParamError::*;
    let name = |e: ParamError| match e {
        NonFinite { name } => ("NonFinite", name),
        OutOfRange { name, .. } => ("OutOfRange", name),
        e => panic!("{e:?}"),
    };
    assert_eq!(
        name(Gaussian::<2>::normalised([f64::NAN, 0.0], 1.0).unwrap_err()),
        ("NonFinite", "centre")
    );
    assert_eq!(
        name(Gaussian::<3>::with_peak([0.0, f64::INFINITY, 0.0], 1.0, 1.0).unwrap_err()),
        ("NonFinite", "centre")
    );
    for s in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(
            name(Gaussian::<2>::normalised([0.0; 2], s).unwrap_err()),
            ("NonFinite", "sigma")
        );
        assert_eq!(
            name(Gaussian::<3>::with_peak([0.0; 3], s, 1.0).unwrap_err()),
            ("NonFinite", "sigma")
        );
    }
    for s in [0.0, -1.0, 9.9e-7, 1.01e6] {
        assert_eq!(
            name(Gaussian::<2>::normalised([0.0; 2], s).unwrap_err()),
            ("OutOfRange", "sigma")
        );
        assert_eq!(
            name(Gaussian::<3>::with_peak([0.0; 3], s, 1.0).unwrap_err()),
            ("OutOfRange", "sigma")
        );
    }
    for a in [f64::NAN, f64::INFINITY] {
        assert_eq!(
            name(Gaussian::<2>::with_peak([0.0; 2], 1.0, a).unwrap_err()),
            ("NonFinite", "peak")
        );
    }
    for a in [0.0, -1.0, 9.9e-301, 1.01e300] {
        assert_eq!(
            name(Gaussian::<2>::with_peak([0.0; 2], 1.0, a).unwrap_err()),
            ("OutOfRange", "peak")
        );
    }
    assert!(Gaussian::<2>::normalised([0.0; 2], 1e-6).is_ok());
    assert!(Gaussian::<2>::normalised([0.0; 2], 1e6).is_ok());
    assert!(Gaussian::<2>::with_peak([0.0; 2], 1.0, 1e-300).is_ok());
    assert!(Gaussian::<2>::with_peak([0.0; 2], 1.0, 1e300).is_ok());
    assert_eq!(
        Gaussian::<4>::normalised([0.0; 4], 1.0).unwrap_err(),
        Dimension { dim: 4 }
    );
    assert_eq!(
        Gaussian::<1>::with_peak([0.0], 1.0, 1.0).unwrap_err(),
        Dimension { dim: 1 }
    );
    let e = Gaussian::<2>::with_peak([0.0; 2], 1.0, -2.0).unwrap_err();
    assert!(format!("{e}").contains("peak"), "{e}");
}

#[test]
fn methods_do_not_panic_on_bad_ends() {
    let (ninf, inf, nan) = (f64::NEG_INFINITY, f64::INFINITY, f64::NAN);
    let g = Gaussian::<3>::with_peak([0.5, -0.2, 0.1], 0.3, 2.0).unwrap();
    for o in [[0.0; 3], [1e308, -1e308, 1e308], [-f64::MAX, 0.0, f64::MAX]] {
        for w in [[1.0, 0.0, 0.0], [0.3, 0.4, -0.5], [1.0, 1e-300, 0.0]] {
            let ray = Ray::new(o, w).unwrap();
            for (t0, t1) in [
                (nan, 1.0),
                (0.0, nan),
                (ninf, inf),
                (inf, ninf),
                (inf, inf),
                (ninf, ninf),
                (1.0, 0.0),
                (-f64::MAX, f64::MAX),
                (f64::MAX, -f64::MAX),
            ] {
                let v = g.segment(&ray, t0, t1);
                if t0.is_nan() || t1.is_nan() {
                    assert!(v.is_nan(), "NaN end: {v}");
                } else if t0 == t1 {
                    assert_eq!(v, 0.0);
                } else if t0 > t1 {
                    assert!(v <= 0.0 && v == -g.segment(&ray, t1, t0), "{v}");
                } else {
                    assert!(v >= 0.0 && v.is_finite(), "{o:?} {w:?} [{t0}, {t1}]: {v}");
                }
                let _ = g.optical_depth(&ray, t0, t1, 1.5);
                let _ = g.transmittance(&ray, t0, t1, 1.5);
                let _ = g.opacity(&ray, t0, t1, 1.5);
            }
            let _ = g.line(&ray);
            let _ = g.value(&o);
        }
    }
    // A non-finite point: unspecified, but never a positive value.
    for x in [[nan, 0.0, 0.0], [inf, 0.0, 0.0], [0.0, ninf, 1.0]] {
        assert!(!(g.value(&x) > 0.0), "{x:?}");
    }
    // f32: no panic for NaN, infinite or zero inputs; t0 > t1 negates.
    for o in [
        [0.5f32, -0.2, 0.1],
        [f32::NAN, 0.0, 0.0],
        [f32::INFINITY, 0.0, 0.0],
    ] {
        for d in [[1.0f32, 0.0, 0.0], [0.0; 3], [f32::NAN; 3]] {
            for (t0, t1) in [
                (f32::NAN, 1.0),
                (f32::NEG_INFINITY, f32::INFINITY),
                (1.0, 0.0),
            ] {
                let _ = g.segment_f32(o, d, t0, t1);
                let _ = g.transmittance_f32(o, d, t0, t1, 2.0);
            }
        }
    }
    let a = g.segment_f32([0.5, -0.2, 0.1], [1.0, 0.0, 0.0], -0.1, 0.2);
    let b = g.segment_f32([0.5, -0.2, 0.1], [1.0, 0.0, 0.0], 0.2, -0.1);
    assert!(a > 0.0 && b == -a, "{a} {b}");
}
