//! The disk / ball indicator: chords against an independent double-double
//! reference (the Lagrange identity `|q|²|ω|² − (q·ω)² = |q × ω|²`, a different
//! formula from the implementation's), tangent and grazing lines, long wrapped
//! segments against a brute-force image sum, Fourier coefficients against
//! quadrature and exact high-frequency values, the f32 SIMD path.

#![allow(
    clippy::neg_cmp_op_on_partial_ord,
    clippy::type_complexity,
    clippy::needless_range_loop
)]

mod common;
mod exact;

use common::{integrate, rel_err};
use exact::{rel_err_exact, Dy, Mix};
use linesample::geom::{clip_to_unit_box, Direction};
use linesample::integrand::{Ball, Complex, Integrand};
use linesample::num::{two_prod, Dd};
use linesample::primitive::{Line, Rays32, Segment};
use linesample::ParamError;
use proptest::prelude::*;
use std::f64::consts::PI;

const U: f64 = f64::EPSILON / 2.0; // unit roundoff 2⁻⁵³

// ---------------------------------------------------------------------------
// Reference chord: Δ = a·r² − |q × ω|² in double-double, every product exact.
// ---------------------------------------------------------------------------

/// `q_i ω_j − q_j ω_i` for exact double-double `q`: four exact products, the
/// leading pair summed first (so the cancellation is exact to `O(u²)` of the
/// result).
fn cross_term(qi: Dd, wj: f64, qj: Dd, wi: f64) -> Dd {
    let hi = Dd::prod(qi.hi, wj).sub(Dd::prod(qj.hi, wi));
    let lo = Dd::prod(qi.lo, wj).sub(Dd::prod(qj.lo, wi));
    hi.add(lo)
}

/// `(t−, t+)` of the line `q + tω` through the free ball `|y| < r` centred at
/// the origin, or `None` if `Δ ≤ 0`.
fn ref_roots<const D: usize>(q: &[Dd; D], w: &[f64; D], r: f64) -> Option<(f64, f64, f64)> {
    let mut a = Dd::new(0.0);
    let mut b = Dd::new(0.0);
    for j in 0..D {
        a = a.add(Dd::prod(w[j], w[j]));
        b = b.add(Dd::prod(q[j].hi, w[j])).add(Dd::prod(q[j].lo, w[j]));
    }
    let mut x2 = Dd::new(0.0);
    if D == 2 {
        let c = cross_term(q[0], w[1], q[1], w[0]);
        x2 = c.mul(c);
    } else {
        for (i, j) in [(1, 2), (2, 0), (0, 1)] {
            let c = cross_term(q[i], w[j], q[j], w[i]);
            x2 = x2.add(c.mul(c));
        }
    }
    let delta = a.mul(Dd::prod(r, r)).sub(x2);
    if !(delta.hi > 0.0) {
        return None;
    }
    let s = delta.hi.sqrt();
    let (p, pe) = two_prod(s, s);
    let s = s + (((delta.hi - p) - pe) + delta.lo) / (2.0 * s);
    let af = a.to_f64();
    let h = s / af;
    let tm = -b.to_f64() / af;
    Some((tm - h, tm + h, 2.0 * h))
}

/// Reference clipped chord and the absolute error the implementation is
/// allowed (relative few ulp unclipped, `~u·|t|` clipped).
fn ref_chord<const D: usize>(q: &[Dd; D], w: &[f64; D], r: f64, t0: f64, t1: f64) -> (f64, f64) {
    match ref_roots(q, w, r) {
        None => (0.0, 1e-300),
        Some((lo, hi, full)) => {
            if t0 <= lo && hi <= t1 {
                (full, 8.0 * U * full)
            } else {
                let v = (t1.min(hi) - t0.max(lo)).max(0.0);
                let fin = |x: f64| if x.is_finite() { x.abs() } else { 0.0 };
                (
                    v,
                    4.0 * U * (fin(t0) + fin(t1) + lo.abs() + hi.abs()) + 8.0 * U * v,
                )
            }
        }
    }
}

fn q_of<const D: usize>(p: &[f64; D], c: &[f64; D]) -> [Dd; D] {
    core::array::from_fn(|j| Dd::diff(p[j], c[j]))
}

/// Brute-force periodic integral over `t ∈ [t0, t1]` of the line `p + tω`:
/// the reference chord summed over every image `c + n` that the unwrapped
/// segment can reach (no piece splitting). Returns (value, allowed error).
fn brute<const D: usize>(
    ball: &Ball<D>,
    p: &[f64; D],
    w: &[f64; D],
    t0: f64,
    t1: f64,
) -> (f64, f64) {
    let c = ball.centre();
    let r = ball.radius();
    let mut lo = [0i64; D];
    let mut hi = [0i64; D];
    for j in 0..D {
        let (a, b) = (p[j] + t0 * w[j], p[j] + t1 * w[j]);
        let (a, b) = (a.min(b), a.max(b));
        lo[j] = (a - c[j] - r).floor() as i64 - 1;
        hi[j] = (b - c[j] + r).ceil() as i64 + 1;
    }
    let (mut sum, mut err) = (0.0, 0.0);
    let mut n = lo;
    loop {
        let q: [Dd; D] =
            core::array::from_fn(|j| Dd::diff(p[j], c[j]).add(Dd::new(-(n[j] as f64))));
        let (v, e) = ref_chord(&q, w, r, t0, t1);
        sum += v;
        err += e;
        // odometer
        let mut j = 0;
        loop {
            if j == D {
                return (sum, err);
            }
            n[j] += 1;
            if n[j] <= hi[j] {
                break;
            }
            n[j] = lo[j];
            j += 1;
        }
    }
}

fn unit<const D: usize>(v: [f64; D]) -> Direction<D> {
    Direction::new(v).unwrap()
}

// ---------------------------------------------------------------------------
// Construction
// ---------------------------------------------------------------------------

#[test]
fn constructor_validates_and_reduces_the_centre() {
    assert!(matches!(
        Ball::<2>::new([0.5, 0.5], 0.0),
        Err(ParamError::OutOfRange { name: "radius", .. })
    ));
    assert!(matches!(
        Ball::<2>::new([0.5, 0.5], -0.1),
        Err(ParamError::OutOfRange { name: "radius", .. })
    ));
    assert!(matches!(
        Ball::<3>::new([0.5; 3], 0.5000000000000001),
        Err(ParamError::OutOfRange { name: "radius", .. })
    ));
    assert_eq!(
        Ball::<2>::new([0.5, 0.5], f64::NAN),
        Err(ParamError::NonFinite { name: "radius" })
    );
    assert_eq!(
        Ball::<2>::new([0.5, f64::INFINITY], 0.1),
        Err(ParamError::NonFinite { name: "centre" })
    );
    assert_eq!(
        Ball::<4>::new([0.5; 4], 0.1),
        Err(ParamError::Dimension { dim: 4 })
    );
    assert_eq!(
        Ball::<1>::new([0.5], 0.1),
        Err(ParamError::Dimension { dim: 1 })
    );
    let b = Ball::<2>::new([-3.25, 7.5], 0.5).unwrap();
    assert_eq!(b.centre(), [0.75, 0.5]);
    assert_eq!(b.radius(), 0.5);
    assert_eq!(b.max_value(), 1.0);
    let b = Ball::<3>::new([0.0, -1e-300, 2.0], 1e-8).unwrap();
    assert!(b.centre().iter().all(|x| (0.0..1.0).contains(x)));
    assert!(format!("{}", Ball::<2>::new([0.0; 2], 0.7).unwrap_err()).contains("radius"));
}

#[test]
fn integral_and_values() {
    let d = Ball::<2>::new([0.3, 0.9], 0.2).unwrap();
    assert!(rel_err(d.integral(), PI * 0.04) < 4.0 * U);
    let b = Ball::<3>::new([0.3, 0.9, 0.0], 0.2).unwrap();
    assert!(rel_err(b.integral(), 4.0 / 3.0 * PI * 0.008) < 4.0 * U);
    // Periodic wrap: the disk at y = 0.9 reaches y = 0.05 through the top face.
    assert_eq!(d.value(&[0.3, 0.05]), 1.0);
    assert_eq!(d.value_free(&[0.3, 0.05]), 0.0);
    assert_eq!(d.value(&[0.3 + 17.0, 0.05 - 4.0]), 1.0);
    assert_eq!(d.value(&[0.3, 0.5]), 0.0);
    assert_eq!(d.value(&[f64::NAN, 0.5]), 0.0);
    // Boundary convention: open ball. 0.25 and 0.5 are exact.
    let e = Ball::<2>::new([0.25, 0.5], 0.25).unwrap();
    assert_eq!(e.value_free(&[0.5, 0.5]), 0.0);
    assert_eq!(e.value_free(&[0.5 - 1e-16, 0.5]), 1.0);
    assert_eq!(e.value(&[0.0, 0.5]), 0.0);
    assert_eq!(e.value(&[1e-17, 0.5]), 1.0);
    // The corner of the 3D ball at the origin is covered by its 8 images.
    let c = Ball::<3>::new([0.0; 3], 0.1).unwrap();
    for x in [[0.01, 0.99, 0.02], [0.99, 0.99, 0.99], [-0.02, 3.01, 1.0]] {
        assert_eq!(c.value(&x), 1.0, "{x:?}");
    }
}

// ---------------------------------------------------------------------------
// Tangent and grazing lines
// ---------------------------------------------------------------------------

/// Lines at distance `r·(1 ± 10⁻ᵏ)`, `k = 1..15`, from a ball; origin shifted by
/// `s` along the line. Returns the worst relative error (in ulp) for unclipped
/// chords and checks clipped ones.
fn grazing<const D: usize>(c: [f64; D], r: f64, v: [f64; D], perp: [f64; D], s: f64) -> f64 {
    let ball = Ball::<D>::new(c, r).unwrap();
    let cc = ball.centre();
    let dir = unit(v);
    let w = dir.get();
    let mut worst: f64 = 0.0;
    for k in 1..=15 {
        for sign in [-1.0, 1.0] {
            let d = r * (1.0 + sign * 10f64.powi(-k));
            let p: [f64; D] = core::array::from_fn(|j| cc[j] + d * perp[j] + s * w[j]);
            let q = q_of(&p, &cc);
            let got = ball.segment_free(&p, &dir, f64::NEG_INFINITY, f64::INFINITY);
            match ref_roots(&q, &w, r) {
                None => assert_eq!(got, 0.0, "k={k} sign={sign} r={r} s={s}"),
                Some((lo, hi, full)) => {
                    let e = rel_err(got, full) / (2.0 * U);
                    assert!(
                        e <= 4.0,
                        "k={k} sign={sign} r={r} s={s}: {got} vs {full} ({e} ulp)"
                    );
                    worst = worst.max(e);
                    // Clipped at the middle of the chord, and inside it.
                    let tm = 0.5 * (lo + hi);
                    for (t0, t1) in [
                        (tm, f64::INFINITY),
                        (lo + 0.25 * full, hi - 0.25 * full),
                        (-1e3, tm),
                    ] {
                        let (want, tol) = ref_chord(&q, &w, r, t0, t1);
                        let got = ball.segment_free(&p, &dir, t0, t1);
                        assert!(
                            (got - want).abs() <= tol,
                            "k={k} {t0} {t1}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }
    worst
}

#[test]
fn tangent_and_grazing_lines_2d() {
    let mut worst: f64 = 0.0;
    for r in [1e-8, 0.01, 0.3, 0.5] {
        for v in [[1.0, 0.0], [1.0, 0.37], [-0.3, 0.8], [1e-9, 1.0]] {
            let w = unit(v).get();
            for s in [0.0, 0.37, -2.5] {
                for side in [1.0, -1.0] {
                    let perp = [-side * w[1], side * w[0]];
                    worst = worst.max(grazing([0.3, 0.6], r, v, perp, s));
                    worst = worst.max(grazing([-3.25, 7.5], r, v, perp, s));
                }
            }
        }
    }
    eprintln!("2D grazing: worst unclipped chord error {worst:.2} ulp");
}

#[test]
fn tangent_and_grazing_lines_3d() {
    let mut worst: f64 = 0.0;
    for r in [1e-8, 0.01, 0.3, 0.5] {
        for v in [[1.0, 0.0, 0.0], [0.3, -0.8, 0.5], [1.0, 0.37, 1e-7]] {
            let f = unit(v).frame();
            for s in [0.0, 0.37, -2.5] {
                for perp in [f[0], f[1], [-f[0][0], -f[0][1], -f[0][2]]] {
                    worst = worst.max(grazing([0.3, 0.6, 0.123], r, v, perp, s));
                }
            }
        }
    }
    eprintln!("3D grazing: worst unclipped chord error {worst:.2} ulp");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    #[test]
    fn free_chord_matches_reference_2d(
        p in prop::array::uniform2(-2.0f64..3.0),
        c in prop::array::uniform2(-5.0f64..5.0),
        v in prop::array::uniform2(-1.0f64..1.0),
        lg_r in -100.0f64..-std::f64::consts::LOG10_2,
        aim in prop::array::uniform2(-1.5f64..1.5),
        aimed in any::<bool>(),
        t0 in -3.0f64..3.0,
        len in 0.0f64..4.0,
    ) {
        // Radii log-uniform over the whole accepted range 1e-100 … 1/2; half
        // the cases start within 1.5r of the centre so tiny balls are hit.
        let r = 10f64.powf(lg_r).clamp(Ball::<2>::RADIUS_MIN, 0.5);
        prop_assume!(v[0].abs() + v[1].abs() > 1e-3);
        let ball = Ball::<2>::new(c, r).unwrap();
        let dir = unit(v);
        let p: [f64; 2] = if aimed {
            core::array::from_fn(|j| ball.centre()[j] + aim[j] * r)
        } else {
            p
        };
        let q = q_of(&p, &ball.centre());
        for (a, b) in [(t0, t0 + len), (f64::NEG_INFINITY, f64::INFINITY), (t0, t0)] {
            let (want, tol) = ref_chord(&q, &dir.get(), r, a, b);
            let got = ball.segment_free(&p, &dir, a, b);
            prop_assert!((got - want).abs() <= tol, "{} vs {}", got, want);
        }
        // The finite segment against exact arithmetic, at the stated bound.
        let (exact, sd) = exact_chord(&exact_q(&p, &ball.centre()), &dir.get(), r, t0, t0 + len);
        let got = ball.segment_free(&p, &dir, t0, t0 + len);
        if exact.signum() == 0 {
            prop_assert!(got <= 4.0 * U * len, "{:e} vs 0", got);
        } else {
            let err = rel_err_exact(got, &exact);
            prop_assert!(err <= chord_bound(r, exact.to_f64(), sd), "rel err {:e}: {:e} vs {:e}", err, got, exact.to_f64());
        }
    }

    #[test]
    fn free_chord_matches_reference_3d(
        p in prop::array::uniform3(-2.0f64..3.0),
        c in prop::array::uniform3(-5.0f64..5.0),
        v in prop::array::uniform3(-1.0f64..1.0),
        lg_r in -100.0f64..-std::f64::consts::LOG10_2,
        aim in prop::array::uniform3(-1.5f64..1.5),
        aimed in any::<bool>(),
        t0 in -3.0f64..3.0,
        len in 0.0f64..4.0,
    ) {
        // Radii log-uniform over the whole accepted range 1e-100 … 1/2; half
        // the cases start within 1.5r of the centre so tiny balls are hit.
        let r = 10f64.powf(lg_r).clamp(Ball::<3>::RADIUS_MIN, 0.5);
        prop_assume!(v[0].abs() + v[1].abs() + v[2].abs() > 1e-3);
        let ball = Ball::<3>::new(c, r).unwrap();
        let dir = unit(v);
        let p: [f64; 3] = if aimed {
            core::array::from_fn(|j| ball.centre()[j] + aim[j] * r)
        } else {
            p
        };
        let q = q_of(&p, &ball.centre());
        for (a, b) in [(t0, t0 + len), (f64::NEG_INFINITY, f64::INFINITY), (t0, t0)] {
            let (want, tol) = ref_chord(&q, &dir.get(), r, a, b);
            let got = ball.segment_free(&p, &dir, a, b);
            prop_assert!((got - want).abs() <= tol, "{} vs {}", got, want);
        }
        // The finite segment against exact arithmetic, at the stated bound.
        let (exact, sd) = exact_chord(&exact_q(&p, &ball.centre()), &dir.get(), r, t0, t0 + len);
        let got = ball.segment_free(&p, &dir, t0, t0 + len);
        if exact.signum() == 0 {
            prop_assert!(got <= 4.0 * U * len, "{:e} vs 0", got);
        } else {
            let err = rel_err_exact(got, &exact);
            prop_assert!(err <= chord_bound(r, exact.to_f64(), sd), "rel err {:e}: {:e} vs {:e}", err, got, exact.to_f64());
        }
    }

    /// Any wrapped segment (length up to 3) against the brute-force image sum.
    #[test]
    fn wrapped_segment_matches_brute_force(
        s in prop::array::uniform2(-3.0f64..3.0),
        c in prop::array::uniform2(-3.0f64..3.0),
        v in prop::array::uniform2(-1.0f64..1.0),
        lg_r in -100.0f64..-std::f64::consts::LOG10_2,
        len in 0.0f64..3.0,
    ) {
        let r = 10f64.powf(lg_r).clamp(Ball::<2>::RADIUS_MIN, 0.5);
        prop_assume!(v[0].abs() + v[1].abs() > 1e-3);
        let ball = Ball::<2>::new(c, r).unwrap();
        let dir = unit(v);
        let seg = Segment::new(s, dir, len).unwrap();
        let got = ball.segment_integral(&seg);
        let (want, tol) = brute(&ball, &s, &dir.get(), -0.5 * len, 0.5 * len);
        prop_assert!((got - want).abs() <= tol + 64.0 * U * (1.0 + len * 4.0), "{} vs {}", got, want);
        let m = ball.segment_mean(&seg);
        prop_assert!((0.0..=1.0 + 1e-12).contains(&m));
    }
}

// ---------------------------------------------------------------------------
// Zero-length segments, λ → 0, long segments, odd centres and radii
// ---------------------------------------------------------------------------

#[test]
fn zero_length_and_continuity() {
    let ball = Ball::<2>::new([0.3, 0.6], 0.2).unwrap();
    let dir = unit([1.0, 0.37]);
    let p = [0.35, 0.62];
    assert_eq!(ball.segment_free(&p, &dir, 0.25, 0.25), 0.0);
    assert_eq!(ball.piece_integral(&p, &dir, 0.1, 0.1), 0.0);
    for (x, want) in [([0.35, 0.62], 1.0), ([0.1, 0.9], 0.0), ([1.29, 0.62], 1.0)] {
        let seg = Segment::new(x, dir, 0.0).unwrap();
        assert_eq!(ball.segment_integral(&seg), 0.0);
        assert_eq!(ball.segment_mean(&seg), want);
        for k in 1..=14 {
            let seg = Segment::new(x, dir, 10f64.powi(-k)).unwrap();
            let m = ball.segment_mean(&seg);
            assert!((m - want).abs() <= 1e-15, "{x:?} λ=1e-{k}: {m}");
        }
    }
    // 3D, centre near a face (the tiny segment may straddle it).
    let b3 = Ball::<3>::new([0.0, 0.5, 0.5], 0.3).unwrap();
    let d3 = unit([0.3, -0.8, 0.5]);
    for k in 1..=14 {
        let seg = Segment::new([1.0 - 1e-17, 0.5, 0.5], d3, 10f64.powi(-k)).unwrap();
        assert!((b3.segment_mean(&seg) - 1.0).abs() <= 1e-15);
    }
}

fn long_segments<const D: usize>(c: [f64; D], r: f64, s: [f64; D], v: [f64; D]) {
    let ball = Ball::<D>::new(c, r).unwrap();
    let dir = unit(v);
    for len in [1.0, 1.5, 3.7, 100.0] {
        let seg = Segment::new(s, dir, len).unwrap();
        let got = ball.segment_integral(&seg);
        let (want, tol) = brute(&ball, &s, &dir.get(), -0.5 * len, 0.5 * len);
        // Piece origins c − m are rounded (|m| up to λ), so allow ~u·λ per piece.
        let pieces = len * dir.get().iter().map(|x| x.abs()).sum::<f64>() + 4.0;
        let tol = tol + 16.0 * U * pieces * (1.0 + len);
        assert!(
            (got - want).abs() <= tol,
            "λ={len} r={r}: {got} vs {want} (tol {tol:e})"
        );
        // The mean over a long segment tends to the integral (equidistribution).
        if len == 100.0 {
            let m = ball.segment_mean(&seg);
            assert!(
                (m - ball.integral()).abs() < 0.2 * ball.integral() + 0.01,
                "{m}"
            );
        }
    }
}

#[test]
fn segments_longer_than_the_domain() {
    for r in [1e-8, 0.05, 0.37, 0.5] {
        long_segments([0.3, 0.6], r, [0.1, 0.2], [1.0, 0.37]);
        long_segments([-3.25, 7.5], r, [4.1, -0.2], [-0.3, 0.8]);
        long_segments([0.3, 0.6, 0.9], r, [0.1, 0.2, 0.7], [0.3, -0.8, 0.5]);
    }
}

#[test]
fn centres_outside_the_unit_cell_are_equivalent() {
    let a = Ball::<2>::new([-3.25, 7.5], 0.31).unwrap();
    let b = Ball::<2>::new([0.75, 0.5], 0.31).unwrap();
    assert_eq!(a, b);
    let dir = unit([1.0, 0.37]);
    for len in [0.0, 0.3, 2.5] {
        let seg = Segment::new([-0.7, 13.2], dir, len).unwrap();
        assert_eq!(a.segment_integral(&seg), b.segment_integral(&seg));
    }
    assert_eq!(a.fourier(&[123, -4567]), b.fourier(&[123, -4567]));
}

#[test]
fn extreme_radii() {
    // r = 1e-8: a segment through the centre has chord exactly 2r.
    let tiny = Ball::<2>::new([0.3, 0.6], 1e-8).unwrap();
    let dir = unit([1.0, 0.37]);
    let w = dir.get();
    let p: [f64; 2] = core::array::from_fn(|j| tiny.centre()[j] - 0.1 * w[j]);
    let v = tiny.segment_free(&p, &dir, 0.0, 1.0);
    let q = q_of(&p, &tiny.centre());
    let (want, _) = ref_chord(&q, &w, 1e-8, 0.0, 1.0);
    assert!(rel_err(v, want) < 8.0 * U && rel_err(v, 2e-8) < 1e-8, "{v}");
    assert!(rel_err(tiny.integral(), PI * 1e-16) < 4.0 * U);
    // r = 0.5: images touch. The axis line through the centre is covered
    // exactly once per period.
    let half = Ball::<2>::new([0.25, 0.5], 0.5).unwrap();
    let l = Line::<2>::axis(0, &[0.5]).unwrap();
    assert!((half.line_integral(&l) - 1.0).abs() < 4.0 * U);
    let seg = Segment::new([0.9, 0.5], Direction::axis(0).unwrap(), 7.0).unwrap();
    assert!((half.segment_mean(&seg) - 1.0).abs() < 1e-15);
    let b3 = Ball::<3>::new([0.5; 3], 0.5).unwrap();
    assert_eq!(b3.value(&[0.0, 0.5, 0.5]), 0.0);
    assert_eq!(b3.value(&[1e-9, 0.5, 0.5]), 1.0);
    let l = Line::<3>::axis(1, &[0.5, 0.5]).unwrap();
    assert!((b3.line_integral(&l) - 1.0).abs() < 4.0 * U);
}

#[test]
fn lines_through_box_corners() {
    let cases: [([f64; 2], [f64; 2], [f64; 2], f64); 4] = [
        ([0.0, 0.0], [1.0, 1.0], [0.1, 0.05], 0.3),
        ([1.0, 0.0], [-1.0, 1.0], [0.9, 0.2], 0.25),
        ([0.0, 0.0], [1.0, 1.0], [0.5, 0.5], 0.5),
        ([0.0, 1.0], [1.0, -0.37], [0.0, 0.0], 0.2),
    ];
    for (p, v, c, r) in cases {
        let ball = Ball::<2>::new(c, r).unwrap();
        let dir = unit(v);
        let line = Line::new(p, dir).unwrap();
        let got = ball.line_integral(&line);
        let (t0, t1) = clip_to_unit_box(&p, &dir).unwrap();
        let (want, tol) = brute(&ball, &p, &dir.get(), t0, t1);
        assert!(
            (got - want).abs() <= tol + 32.0 * U,
            "{p:?} {v:?}: {got} vs {want}"
        );
    }
    let ball = Ball::<3>::new([0.05, 0.95, 0.1], 0.3).unwrap();
    let dir = unit([1.0, -1.0, 1.0]);
    let p = [0.0, 1.0, 0.0];
    let got = ball.line_integral(&Line::new(p, dir).unwrap());
    let (t0, t1) = clip_to_unit_box(&p, &dir).unwrap();
    let (want, tol) = brute(&ball, &p, &dir.get(), t0, t1);
    assert!(
        (got - want).abs() <= tol + 32.0 * U,
        "3D corner: {got} vs {want}"
    );
    assert!(got > 0.5);
}

#[test]
fn axis_lines_equal_unit_segments() {
    for (c, r) in [([0.3, 0.6], 0.2), ([0.95, 0.02], 0.45), ([0.0, 0.0], 1e-8)] {
        let ball = Ball::<2>::new(c, r).unwrap();
        for y in [0.0, 0.1, 0.55, 0.61, 0.999, 0.02 + 0.44] {
            for axis in 0..2 {
                let other = 1 - axis;
                let mut dy = y - c[other];
                dy -= dy.round();
                let want = if dy.abs() < r {
                    2.0 * ((r - dy.abs()) * (r + dy.abs())).sqrt()
                } else {
                    0.0
                };
                let line = Line::<2>::axis(axis, &[y]).unwrap();
                let li = ball.line_integral(&line);
                let mut x = [0.0; 2];
                x[other] = y;
                x[axis] = 0.731;
                let seg = Segment::new(x, Direction::axis(axis).unwrap(), 1.0).unwrap();
                let si = ball.segment_integral(&seg);
                assert!(
                    (li - want).abs() <= 8.0 * U * (1.0 + want),
                    "{c:?} {y} {axis}: {li} vs {want}"
                );
                assert!(
                    (si - want).abs() <= 8.0 * U * (1.0 + want),
                    "{c:?} {y} {axis}: {si} vs {want}"
                );
            }
        }
    }
}

/// E over uniform segment centres of `segment_mean` equals `∫ f` (exchange of
/// the integrals), for a fixed direction `ω` (`ω_y ≠ 0`).
///
/// The centre is parametrised by the sheared unit square
/// `c = (x, 0) + (s/ω_y)·ω`, `x, s ∈ [0, 1)` (a fundamental domain of the torus,
/// Jacobian 1). For fixed `x` the centre slides along the line
/// `L_x = (x, 0) + tω`, so `s ↦ segment_mean` is a moving average of an
/// indicator of intervals: piecewise linear, with breakpoints at the chord ends
/// (from the reference chord) `± λ/2`, so G7–K15 on each piece is exact. In `x`
/// the result has square-root singularities where `L_x` is tangent to an image
/// disk; between those breakpoints `x = a + (b − a)(1 − cos φ)/2` makes it
/// smooth, and adaptive Gauss–Kronrod does the rest.
fn mean_over_centres(ball: &Ball<2>, v: [f64; 2], len: f64) -> f64 {
    let dir = unit(v);
    let w = dir.get();
    let (c, r) = (ball.centre(), ball.radius());
    let inner = |x: f64| -> f64 {
        let mut br = vec![0.0, 1.0];
        for nx in -4..=4 {
            for ny in -3..=3 {
                let q = [
                    Dd::diff(x, c[0]).add(Dd::new(-(nx as f64))),
                    Dd::new(-c[1]).add(Dd::new(-(ny as f64))),
                ];
                if let Some((lo, hi, _)) = ref_roots(&q, &w, r) {
                    for te in [lo, hi] {
                        for sg in [-0.5, 0.5] {
                            let sb = w[1] * (te + sg * len);
                            if sb > 0.0 && sb < 1.0 {
                                br.push(sb);
                            }
                        }
                    }
                }
            }
        }
        br.sort_by(f64::total_cmp);
        let mut f = |sv: f64| {
            let t = sv / w[1];
            let cen = [x + t * w[0], t * w[1]];
            ball.segment_mean(&Segment::new(cen, dir, len).unwrap())
        };
        br.windows(2)
            .map(|p| common::gk15(&mut f, p[0], p[1]).0)
            .sum()
    };
    // Tangency of L_x to the image c + n: |(c + n − (x, 0)) × ω| = r.
    let mut bx = vec![0.0, 1.0];
    for nx in -6..=6 {
        for ny in -3..=3 {
            for sg in [-1.0, 1.0] {
                let x = c[0] + nx as f64 - ((c[1] + ny as f64) * w[0] + sg * r) / w[1];
                if x > 0.0 && x < 1.0 {
                    bx.push(x);
                }
            }
        }
    }
    bx.sort_by(f64::total_cmp);
    bx.windows(2)
        .map(|p| {
            let (a, b) = (p[0], p[1]);
            integrate(
                |phi: f64| inner(a + 0.5 * (b - a) * (1.0 - phi.cos())) * 0.5 * (b - a) * phi.sin(),
                0.0,
                PI,
                1e-10,
            )
        })
        .sum()
}

#[test]
fn mean_of_segment_means_is_the_integral() {
    let ball = Ball::<2>::new([0.3, 0.6], 0.2).unwrap();
    for (v, len) in [([0.0, 1.0], 0.3), ([1.0, 0.37], 0.3), ([-0.6, 0.8], 1.7)] {
        let e = mean_over_centres(&ball, v, len);
        let err = rel_err(e, ball.integral());
        eprintln!("E[segment_mean] ω ∝ {v:?}, λ = {len}: relative error {err:.2e}");
        assert!(err < 1e-12, "{e} vs {}", ball.integral());
    }
}

// ---------------------------------------------------------------------------
// Fourier coefficients
// ---------------------------------------------------------------------------

/// `k·c mod 1` exactly, from the bits of `c` (requires `c ≥ 2⁻⁶⁰` or 0).
fn exact_phase<const D: usize>(k: &[i32; D], c: &[f64; D]) -> f64 {
    const E: u32 = 120;
    let mut num: u128 = 0;
    for j in 0..D {
        if c[j] == 0.0 {
            continue;
        }
        let bits = c[j].to_bits();
        let exp = ((bits >> 52) & 0x7ff) as i32 - 1075;
        let mant = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
        assert!(exp < 0 && (-exp) as u32 <= E - 10);
        // c = mant·2^exp; scaled numerator mant·2^(E + exp) (mod 2^E).
        let m = u128::from(mant) << (E as i32 + exp);
        let kk = k[j].unsigned_abs() as u128;
        let mut t = (kk.wrapping_mul(m)) & ((1u128 << E) - 1);
        if k[j] < 0 {
            t = ((1u128 << E) - t) & ((1u128 << E) - 1);
        }
        num = (num + t) & ((1u128 << E) - 1);
    }
    let f = num as f64 / 2f64.powi(E as i32);
    if f >= 0.5 {
        f - 1.0
    } else {
        f
    }
}

fn phased(amp: f64, phi: f64) -> Complex {
    Complex {
        re: amp * (2.0 * PI * phi).cos(),
        im: -amp * (2.0 * PI * phi).sin(),
    }
}

fn rho(k: &[i32]) -> f64 {
    k.iter()
        .map(|&x| (x as f64) * (x as f64))
        .sum::<f64>()
        .sqrt()
}

/// Disk: 2π∫₀^r J0(2πρs) s ds; ball: ∫₀^r 4πs² sinc(2ρs) ds. Panels of a
/// quarter period.
fn radial_quadrature(d: usize, rho: f64, r: f64) -> f64 {
    let panels = ((4.0 * rho * r).ceil() as usize).max(1);
    let h = r / panels as f64;
    let mut sum = 0.0;
    for i in 0..panels {
        let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
        sum += if d == 2 {
            integrate(|s| 2.0 * PI * libm::j0(2.0 * PI * rho * s) * s, a, b, 1e-14)
        } else {
            integrate(
                |s| {
                    let x = 2.0 * PI * rho * s;
                    let sinc = if x == 0.0 { 1.0 } else { x.sin() / x };
                    4.0 * PI * s * s * sinc
                },
                a,
                b,
                1e-14,
            )
        };
    }
    sum
}

#[test]
fn fourier_at_zero_is_the_integral() {
    let d = Ball::<2>::new([0.3, 0.6], 0.2).unwrap();
    assert_eq!(
        d.fourier(&[0, 0]),
        Complex {
            re: d.integral(),
            im: 0.0
        }
    );
    let b = Ball::<3>::new([0.3, 0.6, 0.1], 0.2).unwrap();
    assert_eq!(b.fourier(&[0, 0, 0]).re, b.integral());
}

#[test]
fn fourier_matches_radial_quadrature() {
    let c2 = [std::f64::consts::FRAC_1_PI, 0.6180339887498949];
    let c3 = [
        std::f64::consts::FRAC_1_PI,
        0.6180339887498949,
        std::f64::consts::FRAC_1_SQRT_2,
    ];
    let ks2: [[i32; 2]; 8] = [
        [1, 0],
        [0, -1],
        [3, 4],
        [-7, 2],
        [20, -13],
        [101, 3],
        [-250, 777],
        [1500, -2000],
    ];
    let ks3: [[i32; 3]; 6] = [
        [1, 0, 0],
        [0, 2, -1],
        [3, 4, 12],
        [-17, 5, 9],
        [100, -30, 45],
        [600, 700, -800],
    ];
    for r in [1e-8, 0.01, 0.2, 0.5] {
        let disk = Ball::<2>::new(c2, r).unwrap();
        for k in ks2 {
            let a = radial_quadrature(2, rho(&k), r);
            let want = phased(a, exact_phase(&k, &disk.centre()));
            let got = disk.fourier(&k);
            // Quadrature of an oscillating integrand: cancellation ~ (ρr)·ε·r².
            let tol = 1e-14 * r * r * (1.0 + 4.0 * rho(&k) * r) + 4.0 * U * a.abs();
            let e = ((got.re - want.re).powi(2) + (got.im - want.im).powi(2)).sqrt();
            assert!(
                e <= tol,
                "disk r={r} k={k:?}: {got:?} vs {want:?} ({e:e} > {tol:e})"
            );
        }
        let ball = Ball::<3>::new(c3, r).unwrap();
        for k in ks3 {
            let a = radial_quadrature(3, rho(&k), r);
            let want = phased(a, exact_phase(&k, &ball.centre()));
            let got = ball.fourier(&k);
            let tol = 1e-14 * r * r * r * (1.0 + 4.0 * rho(&k) * r) + 4.0 * U * a.abs();
            let e = ((got.re - want.re).powi(2) + (got.im - want.im).powi(2)).sqrt();
            assert!(
                e <= tol,
                "ball r={r} k={k:?}: {got:?} vs {want:?} ({e:e} > {tol:e})"
            );
        }
    }
}

/// `(cos, sin)` of `jπ/4`, exactly rounded.
fn quarter_pi(j: i64) -> (f64, f64) {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let t = [
        (1.0, 0.0),
        (h, h),
        (0.0, 1.0),
        (-h, h),
        (-1.0, 0.0),
        (-h, -h),
        (0.0, -1.0),
        (h, -h),
    ];
    t[j.rem_euclid(8) as usize]
}

/// High frequencies with exact `x = 2πρr = πM/4` (`ρ` an integer, `ρr = M/8`),
/// so the reference needs no argument reduction: disk by the Hankel asymptotic
/// expansion of `J1`, ball from `sin x − x cos x` with exact `sin`, `cos`.
#[test]
fn fourier_high_frequency_exact_arguments() {
    // (k, ρ, r) with ρ·r = M/8 exactly.
    let cases2: [([i32; 2], f64); 3] = [
        ([100000, 0], 100000.0),
        ([60000, -80000], 100000.0),
        ([0, 99999], 99999.0),
    ];
    let mut worst2: f64 = 0.0;
    let mut worst3: f64 = 0.0;
    for (k, rh) in cases2 {
        for m in [1.0, 3.0, 17.0, 64.0, 77.0, 100.0, 127.0, 128.0] {
            // r = m/256; ρ·r·8 = M must be an integer.
            let r = m / 256.0;
            let mm = rh * m / 32.0;
            if mm.fract() != 0.0 {
                continue;
            }
            let mi = mm as i64;
            let x = PI * mm / 4.0;
            let (cchi, schi) = quarter_pi(mi - 3);
            let mu = 4.0;
            let z = 8.0 * x;
            let pp = 1.0 - (mu - 1.0) * (mu - 9.0) / (2.0 * z * z)
                + (mu - 1.0) * (mu - 9.0) * (mu - 25.0) * (mu - 49.0) / (24.0 * z.powi(4));
            let qq = (mu - 1.0) / z - (mu - 1.0) * (mu - 9.0) * (mu - 25.0) / (6.0 * z.powi(3));
            let pref = (2.0 / (PI * x)).sqrt();
            let j1 = pref * (pp * cchi - qq * schi);
            let amp = r * j1 / rh;
            let disk =
                Ball::<2>::new([std::f64::consts::FRAC_1_PI, 0.6180339887498949], r).unwrap();
            let got = disk.fourier(&k);
            let got_amp = (got.re * got.re + got.im * got.im).sqrt();
            // Near a zero of J1 (cos χ = 0) only absolute accuracy is available.
            let scale = r * pref / rh;
            let e = (got_amp - amp.abs()).abs() / scale;
            assert!(
                e < 1e-14,
                "disk k={k:?} r={r}: |F| {got_amp:e} vs {amp:e} ({e:e})"
            );
            worst2 = worst2.max(e);
            let want = phased(amp, exact_phase(&k, &disk.centre()));
            let de = ((got.re - want.re).powi(2) + (got.im - want.im).powi(2)).sqrt() / scale;
            assert!(de < 2e-14, "disk phase k={k:?} r={r}: {got:?} vs {want:?}");
        }
    }
    // 3D: k = 14285·(2, 3, 6) has ρ = 99995; with r = m/8, ρr = 99995m/8.
    for (k, rh) in [
        ([28570, 42855, 85710], 99995.0),
        ([0, 0, -100000], 100000.0),
    ] {
        for m in [1.0, 2.0, 3.0, 4.0] {
            let r = m / 8.0;
            let mm = rh * m;
            let (c, s) = quarter_pi(mm as i64);
            let x = PI * mm / 4.0;
            let g = s - x * c;
            let amp = g / (2.0 * PI * PI * rh * rh * rh);
            let ball = Ball::<3>::new(
                [
                    std::f64::consts::FRAC_1_PI,
                    0.6180339887498949,
                    std::f64::consts::FRAC_1_SQRT_2,
                ],
                r,
            )
            .unwrap();
            let got = ball.fourier(&k);
            let want = phased(amp, exact_phase(&k, &ball.centre()));
            let scale = x / (2.0 * PI * PI * rh * rh * rh);
            let e = ((got.re - want.re).powi(2) + (got.im - want.im).powi(2)).sqrt() / scale;
            assert!(e < 1e-14, "ball k={k:?} r={r}: {got:?} vs {want:?} ({e:e})");
            worst3 = worst3.max(e);
        }
    }
    eprintln!("high-frequency worst error, in units of the amplitude scale: disk {worst2:.2e}, ball {worst3:.2e}");
}

/// Phase of high, non-special frequencies against the exact integer phase.
#[test]
fn fourier_phase_high_frequency() {
    let c = [std::f64::consts::FRAC_1_PI, 0.6180339887498949];
    let disk = Ball::<2>::new(c, 0.123).unwrap();
    for k in [
        [99991, -12345],
        [-77777, 99999],
        [31, 100000],
        [65536, 65535],
    ] {
        let got = disk.fourier(&k);
        let amp = (got.re * got.re + got.im * got.im).sqrt();
        let phi = exact_phase(&k, &disk.centre());
        // got·e^{+2πiφ} must be real (the amplitude may have either sign).
        let (c, s) = ((2.0 * PI * phi).cos(), (2.0 * PI * phi).sin());
        let im = got.im * c + got.re * s;
        let e = im.abs() / amp;
        assert!(e < 8.0 * U, "{k:?}: {e:e}");
        // Symmetries: |F̂| depends on |k| only; F̂(−k) = conj F̂(k).
        let m = disk.fourier(&[-k[0], -k[1]]);
        assert!((m.re - got.re).abs() <= 4.0 * U * amp && (m.im + got.im).abs() <= 4.0 * U * amp);
        let sw = disk.fourier(&[k[1], k[0]]);
        assert!(((sw.norm_sqr()).sqrt() - amp).abs() <= 4.0 * U * amp);
    }
}

// ---------------------------------------------------------------------------
// f32 SIMD path
// ---------------------------------------------------------------------------

/// Deterministic pseudo-random numbers in [0, 1) (SplitMix64).
struct Sm(u64);
impl Sm {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e3779b97f4a7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

struct Batch<const D: usize> {
    o: [Vec<f32>; D],
    d: [Vec<f32>; D],
    t0: Vec<f32>,
    t1: Vec<f32>,
}

impl<const D: usize> Batch<D> {
    fn random(n: usize, seed: u64) -> Self {
        let mut g = Sm(seed);
        let mut b = Batch {
            o: core::array::from_fn(|_| Vec::new()),
            d: core::array::from_fn(|_| Vec::new()),
            t0: Vec::new(),
            t1: Vec::new(),
        };
        for i in 0..n {
            let v: [f64; D] = core::array::from_fn(|_| g.next() * 2.0 - 1.0);
            let w = unit(v).get();
            for j in 0..D {
                b.o[j].push(g.next() as f32);
                b.d[j].push(w[j] as f32);
            }
            let (t0, t1) = match i % 5 {
                0 => (f32::NEG_INFINITY, f32::INFINITY),
                1 => (0.0, 0.0),
                _ => {
                    let a = (g.next() * 2.0 - 1.0) as f32;
                    (a, a + g.next() as f32)
                }
            };
            b.t0.push(t0);
            b.t1.push(t1);
        }
        b
    }
    fn rays(&self) -> Rays32<'_, D> {
        Rays32 {
            origin: core::array::from_fn(|j| &self.o[j][..]),
            dir: core::array::from_fn(|j| &self.d[j][..]),
            t0: &self.t0,
            t1: &self.t1,
        }
    }
}

fn f32_paths<const D: usize>(c: [f64; D], r: f64) {
    let ball = Ball::<D>::new(c, r).unwrap();
    for n in (0..=17).chain([64, 1003]) {
        let b = Batch::<D>::random(n, 42 + n as u64);
        let mut out = vec![0.0f32; n];
        ball.segment_free_batch_f32(&b.rays(), &mut out).unwrap();
        let mut worst: f64 = 0.0;
        for i in 0..n {
            let o: [f32; D] = core::array::from_fn(|j| b.o[j][i]);
            let d: [f32; D] = core::array::from_fn(|j| b.d[j][i]);
            let s = ball.segment_free_f32(o, d, b.t0[i], b.t1[i]);
            assert_eq!(s.to_bits(), out[i].to_bits(), "lane {i} of {n}");
            // Against the f64 path on the same (f32) inputs, with the centre
            // rounded to f32 as the f32 path uses it.
            let c32: [f64; D] = core::array::from_fn(|j| f64::from(ball.centre()[j] as f32));
            let q: [Dd; D] = core::array::from_fn(|j| Dd::diff(f64::from(o[j]), c32[j]));
            let w: [f64; D] = core::array::from_fn(|j| f64::from(d[j]));
            let (want, _) = ref_chord(
                &q,
                &w,
                f64::from(r as f32),
                f64::from(b.t0[i]),
                f64::from(b.t1[i]),
            );
            worst = worst.max((f64::from(s) - want).abs() / r);
        }
        // Random rays include near-tangent ones only by chance; generous bound.
        assert!(worst < 3e-3, "n={n} r={r}: worst f32 error {worst:e}·r");
    }
}

#[test]
fn f32_batch_is_bitwise_the_scalar_twin() {
    f32_paths([0.3, 0.6], 0.2);
    f32_paths([0.5, 0.5], 0.5);
    f32_paths([0.3, 0.6, 0.9], 0.2);
    f32_paths([-3.25, 7.5, 0.1], 0.05);
}

/// The f32 chord against the exact chord of the same f32 inputs. Model: the
/// distance `d⊥` is computed with an absolute error of a few `ε₃₂·L`
/// (`L = |o − c|`), so `h² = r² − d⊥²` is off by `δ = ε₃₂·(L·r + r²)` and the
/// chord by about `min(δ/h, 2√δ)` (`h` = half chord). The test measures the
/// worst ratio of the error to that model and bounds it.
#[test]
fn f32_error_against_f64() {
    let e32 = f64::from(f32::EPSILON);
    let mut worst_ratio: f64 = 0.0;
    for r in [1e-3, 0.01, 0.1, 0.5] {
        let ball = Ball::<2>::new([0.3, 0.6], r).unwrap();
        let c = ball.centre();
        let c32 = [f64::from(c[0] as f32), f64::from(c[1] as f32)];
        let r32 = f64::from(r as f32);
        let (mut far, mut near): (f64, f64) = (0.0, 0.0);
        let mut g = Sm(7);
        for i in 0..40000 {
            let th = g.next() * 2.0 * PI;
            let w = [th.cos(), th.sin()];
            let dist = match i % 3 {
                0 => r * 0.5 * g.next(),
                1 => r * (1.0 - 0.5 * g.next()),
                _ => r * (1.0 + 1e-6 * (2.0 * g.next() - 1.0)),
            };
            let s = 2.0 * g.next() - 1.0;
            let o = [
                (c[0] - dist * w[1] + s * w[0]) as f32,
                (c[1] + dist * w[0] + s * w[1]) as f32,
            ];
            let d = [w[0] as f32, w[1] as f32];
            let got = f64::from(ball.segment_free_f32(o, d, f32::NEG_INFINITY, f32::INFINITY));
            let q = [
                Dd::diff(f64::from(o[0]), c32[0]),
                Dd::diff(f64::from(o[1]), c32[1]),
            ];
            let (want, _) = ref_chord(
                &q,
                &[f64::from(d[0]), f64::from(d[1])],
                r32,
                f64::NEG_INFINITY,
                f64::INFINITY,
            );
            let err = (got - want).abs();
            let l = (q[0].hi * q[0].hi + q[1].hi * q[1].hi).sqrt();
            let delta = e32 * (l * r + r * r);
            let h = 0.5 * want;
            let model = (delta / h).min(2.0 * delta.sqrt());
            worst_ratio = worst_ratio.max(err / model);
            if i % 3 == 0 {
                far = far.max(err / r);
            } else if i % 3 == 2 {
                near = near.max(err / r);
            }
        }
        eprintln!("f32 chord error r={r}: ≤ {far:.1e}·r for d⊥ ≤ r/2, ≤ {near:.1e}·r within 1e-6·r of tangency");
    }
    eprintln!("f32 chord error / model: worst {worst_ratio:.2}");
    assert!(worst_ratio < 4.0, "{worst_ratio}");
}

/// Non-finite inputs and reversed ends: no panic, documented results.
#[test]
fn bad_inputs_do_not_panic() {
    let ball = Ball::<2>::new([0.3, 0.6], 0.2).unwrap();
    let dir = unit([1.0, 0.37]);
    let (ninf, inf) = (f64::NEG_INFINITY, f64::INFINITY);
    assert_eq!(ball.segment_free(&[0.3, 0.6], &dir, 0.1, -0.1), 0.0);
    assert_eq!(ball.segment_free(&[f64::NAN, 0.6], &dir, ninf, inf), 0.0);
    assert_eq!(ball.segment_free(&[inf, 0.6], &dir, ninf, inf), 0.0);
    assert_eq!(ball.segment_free(&[1e200, -1e200], &dir, ninf, inf), 0.0);
    let full = ball.segment_free(&[0.3, 0.6], &dir, ninf, inf);
    assert_eq!(ball.segment_free(&[0.3, 0.6], &dir, f64::NAN, inf), full);
    let d = [1.0f32, 0.0];
    assert_eq!(ball.segment_free_f32([0.3, 0.6], d, 0.1, -0.1), 0.0);
    assert_eq!(
        ball.segment_free_f32([f32::NAN, 0.6], d, f32::NEG_INFINITY, f32::INFINITY),
        0.0
    );
    assert_eq!(
        ball.segment_free_f32([f32::INFINITY, 0.6], d, f32::NEG_INFINITY, f32::INFINITY),
        0.0
    );
    let z = ball.segment_free_f32([0.3, 0.6], [0.0, 0.0], 0.0, 1.0);
    // Unspecified for d = 0, but never longer than the segment.
    assert!(z.is_nan() || (0.0..=1.0).contains(&z), "{z}");
}

#[test]
fn f32_batch_rejects_mismatched_lengths() {
    let ball = Ball::<2>::new([0.3, 0.6], 0.2).unwrap();
    let b = Batch::<2>::random(10, 1);
    let mut out = vec![0.0f32; 9];
    assert!(matches!(
        ball.segment_free_batch_f32(&b.rays(), &mut out),
        Err(ParamError::Length { name: "out", .. })
    ));
    let mut rays = b.rays();
    rays.t1 = &b.t1[..5];
    let mut out = vec![0.0f32; 10];
    assert!(matches!(
        ball.segment_free_batch_f32(&rays, &mut out),
        Err(ParamError::Length { name: "t1", .. })
    ));
}

/// Throughput (run with `cargo test --release --test integrand_ball -- --ignored
/// --nocapture`): f32 batch vs the f64 scalar path.
#[test]
#[ignore]
fn throughput() {
    use std::time::Instant;
    let ball = Ball::<2>::new([0.3, 0.6], 0.1).unwrap();
    let n = 4096;
    let b = Batch::<2>::random(n, 3);
    let mut out = vec![0.0f32; n];
    let reps = 20000;
    let t = Instant::now();
    for _ in 0..reps {
        ball.segment_free_batch_f32(&b.rays(), std::hint::black_box(&mut out))
            .unwrap();
    }
    let simd = (n * reps) as f64 / t.elapsed().as_secs_f64() / 1e6;
    let dirs: Vec<Direction<2>> = (0..n)
        .map(|i| unit([f64::from(b.d[0][i]), f64::from(b.d[1][i])]))
        .collect();
    let t = Instant::now();
    let mut acc = 0.0;
    let reps64 = reps / 20;
    for _ in 0..reps64 {
        for i in 0..n {
            let p = [f64::from(b.o[0][i]), f64::from(b.o[1][i])];
            acc += ball.segment_free(
                std::hint::black_box(&p),
                &dirs[i],
                f64::from(b.t0[i]),
                f64::from(b.t1[i]),
            );
        }
    }
    let scalar = (n * reps64) as f64 / t.elapsed().as_secs_f64() / 1e6;
    let b3 = Batch::<3>::random(n, 4);
    let ball3 = Ball::<3>::new([0.3, 0.6, 0.2], 0.1).unwrap();
    let t = Instant::now();
    for _ in 0..reps {
        ball3
            .segment_free_batch_f32(&b3.rays(), std::hint::black_box(&mut out))
            .unwrap();
    }
    let simd3 = (n * reps) as f64 / t.elapsed().as_secs_f64() / 1e6;
    eprintln!("2D f32 batch: {simd:.0} M lines/s; 2D f64 scalar: {scalar:.1} M lines/s ({:.1}×); 3D f32 batch: {simd3:.0} M lines/s ({acc})", simd / scalar);
}

// ---------------------------------------------------------------------------
// Short segments at the boundary: relative accuracy against exact arithmetic
// ---------------------------------------------------------------------------

/// The exact clipped chord `max(0, min(t1, t+) − max(t0, t−))` of the line
/// `c_rel + tω` (`q` = point minus ball centre, exact) with the ball of radius
/// `r` at the origin, for finite `t0 ≤ t1`: the quadratic re-based at `t0` with
/// exact dyadic coefficients, its roots to 1400 bits, the difference formed
/// in that precision. Also returns `√Δ` (rounded): the half chord times `|ω|²`.
fn exact_chord<const D: usize>(q: &[Dy; D], w: &[f64; D], r: f64, t0: f64, t1: f64) -> (Dy, f64) {
    let wd: [Dy; D] = core::array::from_fn(|j| Dy::f(w[j]));
    let t0d = Dy::f(t0);
    let q0: [Dy; D] = core::array::from_fn(|j| q[j].add(&t0d.mul(&wd[j])));
    let a = exact::dot(&wd, &wd);
    let b = exact::dot(&q0, &wd);
    let c = exact::dot(&q0, &q0).sub(&Dy::f(r).mul(&Dy::f(r)));
    let delta = b.mul(&b).sub(&a.mul(&c));
    if delta.signum() <= 0 {
        return (Dy::zero(), 0.0);
    }
    let sd = delta.sqrt();
    let sm = b.neg().sub(&sd).div(&a);
    let sp = b.neg().add(&sd).div(&a);
    let len = Dy::f(t1).sub(&t0d).min(sp).sub(&Dy::zero().max(sm));
    (Dy::zero().max(len), sd.to_f64())
}

/// The exact roots `t−, t+` (frame `t = 0`), or `None`.
fn exact_roots<const D: usize>(q: &[Dy; D], w: &[f64; D], r: f64) -> Option<(Dy, Dy)> {
    let wd: [Dy; D] = core::array::from_fn(|j| Dy::f(w[j]));
    let a = exact::dot(&wd, &wd);
    let b = exact::dot(q, &wd);
    let c = exact::dot(q, q).sub(&Dy::f(r).mul(&Dy::f(r)));
    let delta = b.mul(&b).sub(&a.mul(&c));
    if delta.signum() <= 0 {
        return None;
    }
    let sd = delta.sqrt();
    Some((b.neg().sub(&sd).div(&a), b.neg().add(&sd).div(&a)))
}

fn exact_q<const D: usize>(p: &[f64; D], c: &[f64; D]) -> [Dy; D] {
    core::array::from_fn(|j| Dy::f(p[j]).sub(&Dy::f(c[j])))
}

/// The stated error bound of the clipped chord (see `Ball`, numerics):
/// `8u + 2⁻¹⁰⁰·(r/√Δ + r²/Δ)` relative, whatever the length `L` of the
/// clipped piece (the constant term of the quadratic re-based at an end is
/// summed exactly, so an end's distance to the root is relatively accurate).
/// Before that, the bound had a term `2⁻¹⁰⁰·r²/(L·√Δ)`, and 5.5 % of the cases
/// below (near-tangent crossings of segments down to `10⁻¹⁵r`) exceeded 1e-13,
/// the worst by a factor 96.
fn chord_bound(r: f64, _len: f64, sd: f64) -> f64 {
    let k = 2f64.powi(-100);
    8.0 * U + k * (r / sd + r * r / (sd * sd))
}

/// Which kind of segment a case is (for the report of the worst case).
const KINDS: [&str; 5] = [
    "straddle",
    "ends at root",
    "starts at root",
    "inside",
    "grazing",
];

/// Short segments straddling, ending at (0 or ±1 ulp from) or lying just
/// inside the boundary of balls of radius `1e-100 … 0.5`, seen from near and
/// far (`t` up to `1e3`), lengths `2r·10^{−U(0,15)}` (down to `1e-15` at
/// `r = 0.5`), plus grazing directions (`|ω·n| = 10^{−U(1,8)}`). Returns the
/// worst relative error where the bound is `≤ 1e-14` (must be `≤ 1e-13`) and
/// the worst error over bound elsewhere (must be `≤ 1`).
fn boundary_cases<const D: usize>(seed: u64, n: usize) -> (f64, f64) {
    let mut g = Mix(seed);
    let (mut worst, mut worst_ratio) = (0.0f64, 0.0f64);
    let (mut worst_rest, mut above) = (0.0f64, 0usize);
    let mut counts = [0usize; 5];
    let mut inside_exact = 0usize;
    let mut strict = 0usize;
    for i in 0..n {
        let r = if i % 2 == 0 {
            10f64.powf(g.range(-3.0, 0.5f64.log10()))
        } else {
            10f64.powf(g.range(-100.0, 0.5f64.log10()))
        };
        // Centre: anywhere in the cell (or 1e6 cells away) where its ulp is
        // far below r, else at the scale of r so the boundary is resolvable.
        let c: [f64; D] = if r > 1e-9 {
            let far = if g.below(4) == 0 { 1e6 } else { 0.0 };
            core::array::from_fn(|_| far + g.f())
        } else {
            core::array::from_fn(|_| g.range(-1e3, 1e3) * r)
        };
        let ball = Ball::<D>::new(c, r).unwrap();
        let c = ball.centre();
        let nrm: [f64; D] = g.unit();
        let grazing = g.below(5) == 0;
        let v: [f64; D] = if grazing {
            // tangent + ε·normal
            let mut t: [f64; D] = g.unit();
            let d: f64 = (0..D).map(|j| t[j] * nrm[j]).sum();
            for j in 0..D {
                t[j] -= d * nrm[j];
            }
            let eps = 10f64.powf(-g.range(1.0, 8.0)) * if g.below(2) == 0 { 1.0 } else { -1.0 };
            core::array::from_fn(|j| t[j] + eps * nrm[j])
        } else {
            loop {
                let u: [f64; D] = g.unit();
                if (0..D).map(|j| u[j] * nrm[j]).sum::<f64>().abs() > 0.05 {
                    break u;
                }
            }
        };
        let dir = Direction::new(v).unwrap();
        let w = dir.get();
        let reach = match g.below(3) {
            0 => 0.0,
            1 => g.range(0.0, 3.0) * r,
            _ => 10f64.powf(g.range(0.0, 3.0)),
        };
        let p: [f64; D] = core::array::from_fn(|j| c[j] + r * nrm[j] - reach * w[j]);
        let q = exact_q(&p, &c);
        let Some((tm, tp)) = exact_roots(&q, &w, r) else {
            continue;
        };
        // The root nearest `reach` (where the boundary point is).
        let (tmf, tpf) = (tm.to_f64(), tp.to_f64());
        let (tb, exit) = if (tmf - reach).abs() <= (tpf - reach).abs() {
            (tmf, false)
        } else {
            (tpf, true)
        };
        let ulp = |x: f64| f64::from_bits(x.abs().to_bits() + 1) - x.abs();
        let len = (2.0 * r * 10f64.powf(-g.range(0.0, 15.0))).max(16.0 * ulp(tb));
        let kind = if grazing { 4 } else { g.below(4) as usize };
        let k = g.below(3) as f64 - 1.0; // −1, 0, +1 ulp
        let (t0, t1) = match kind {
            1 => {
                let t1 = tb + k * ulp(tb);
                (t1 - len, t1)
            }
            2 => {
                let t0 = tb + k * ulp(tb);
                (t0, t0 + len)
            }
            3 => {
                // Inside, a gap of 10^{−U(0,3)}·len from the boundary.
                let gap = len * 10f64.powf(-g.range(0.0, 3.0));
                if exit {
                    (tb - gap - len, tb - gap)
                } else {
                    (tb + gap, tb + gap + len)
                }
            }
            _ => {
                let t0 = tb - g.f() * len;
                (t0, t0 + len)
            }
        };
        let got = ball.segment_free(&p, &dir, t0, t1);
        let (want, sd) = exact_chord(&q, &w, r, t0, t1);
        let full = Dy::f(t1).sub(&Dy::f(t0));
        // Distance of the ends inside the boundary (exact).
        let gap = Dy::f(t0).sub(&tm).min(tp.sub(&Dy::f(t1))).to_f64();
        if want.cmp(&full) == std::cmp::Ordering::Equal && gap >= 2f64.powi(-100) * r * r / sd {
            // Entirely inside, by more than the resolution of the re-based
            // constant term: the length is the parameter difference, exactly
            // rounded.
            inside_exact += 1;
            assert_eq!(
                got,
                t1 - t0,
                "inside: r={r:e} c={c:?} p={p:?} w={w:?} [{t0:e}, {t1:e}]"
            );
        }
        let err = rel_err_exact(got, &want);
        let wf = want.to_f64();
        if wf == 0.0 {
            assert!(
                got <= 4.0 * U * (t1 - t0),
                "{got:e} vs 0: r={r:e} [{t0:e}, {t1:e}]"
            );
            continue;
        }
        counts[kind] += 1;
        let bound = chord_bound(r, wf, sd);
        if bound <= 1e-14 {
            assert!(
                err <= 1e-13,
                "{}: rel err {err:e}: r={r:e} c={c:?} p={p:?} w={w:?} [{t0:e}, {t1:e}] got {got:e} want {wf:e}",
                KINDS[kind]
            );
            worst = worst.max(err);
            strict += 1;
        } else {
            assert!(
                err <= bound,
                "{}: rel err {err:e} > bound {bound:e}: r={r:e} p={p:?} w={w:?} [{t0:e}, {t1:e}]",
                KINDS[kind]
            );
            worst_ratio = worst_ratio.max(err / bound);
            worst_rest = worst_rest.max(err);
            if err > 1e-13 {
                above += 1;
            }
        }
    }
    eprintln!(
        "{D}D boundary segments {counts:?} (straddle, end, start, inside, grazing), {inside_exact} inside exactly: worst relative error {worst:.2e} over the {strict} with bound ≤ 1e-14, worst error/bound {worst_ratio:.2e} elsewhere (worst relative error there {worst_rest:.2e}; {above} above 1e-13)"
    );
    (worst, worst_ratio)
}

#[test]
fn short_segments_at_the_boundary_are_relatively_exact_2d() {
    let (worst, ratio) = boundary_cases::<2>(0x5eed_0002, 20_000);
    assert!(worst <= 1e-13 && ratio <= 1.0);
}

#[test]
fn short_segments_at_the_boundary_are_relatively_exact_3d() {
    let (worst, ratio) = boundary_cases::<3>(0x5eed_0003, 20_000);
    assert!(worst <= 1e-13 && ratio <= 1.0);
}

/// The exact integral of the periodised indicator along the wrapped segment
/// `s + tω`, `t ∈ [−λ/2, λ/2]`: the sum over every image `c + n` the
/// segment can reach of the exact clipped chord.
fn exact_torus<const D: usize>(ball: &Ball<D>, s: &[f64; D], w: &[f64; D], len: f64) -> Dy {
    let (c, r) = (ball.centre(), ball.radius());
    let half = 0.5 * len;
    let mut lo = [0i64; D];
    let mut hi = [0i64; D];
    for j in 0..D {
        let (a, b) = (s[j] - half * w[j], s[j] + half * w[j]);
        let (a, b) = (a.min(b), a.max(b));
        lo[j] = (a - c[j] - r).floor() as i64 - 1;
        hi[j] = (b - c[j] + r).ceil() as i64 + 1;
    }
    let mut sum = Dy::zero();
    exact::for_each_cell(lo, hi, |n| {
        let q: [Dy; D] =
            core::array::from_fn(|j| Dy::f(s[j]).sub(&Dy::f(c[j])).sub(&Dy::f(n[j] as f64)));
        sum = sum.add(&exact_chord(&q, w, r, -half, half).0);
    });
    sum
}

/// Short wrapped segments (`λ = 2r·10^{−U(0,13)}`) that cross a cell face
/// where the ball's boundary crosses it: the sphere meets the face `x_0 = 0` (the centre is within `r`
/// of it), the segment centre is a boundary point on (or within `10⁻¹⁷` of,
/// or one period or `10³` periods away from) that face, so the segment is
/// split into pieces exactly where the chord is clipped.
fn torus_cases<const D: usize>(seed: u64, n: usize) -> f64 {
    let mut g = Mix(seed);
    let mut worst = 0.0f64;
    for _ in 0..n {
        // Radii 1e-9 … 1/2 (below, the cell coordinates' ulp ~1e-16 no longer
        // resolves the boundary point).
        let r = 10f64.powf(g.range(-9.0, 0.5f64.log10()));
        let mut c: [f64; D] = core::array::from_fn(|_| g.f());
        c[0] = g.f() * r; // the sphere crosses x_0 = 0 (and its image, x_0 = 1)
        let ball = Ball::<D>::new(c, r).unwrap();
        // A boundary point X on the face: X_0 = 0, |X − c| = r.
        let mut u: [f64; D] = g.unit();
        u[0] = 0.0;
        let un = u.iter().map(|x| x * x).sum::<f64>().sqrt();
        let rho = (r * r - c[0] * c[0]).sqrt();
        let mut s: [f64; D] = core::array::from_fn(|j| c[j] + rho * u[j] / un);
        s[0] = match g.below(6) {
            0 => 0.0,
            1 => -1e-17,
            2 => 1e-17,
            3 => 1.0,
            4 => -1.0 + 1e-17,
            _ => 1e3,
        };
        let v: [f64; D] = loop {
            let v: [f64; D] = g.unit();
            if v[0].abs() > 0.05 {
                break v;
            }
        };
        let dir = Direction::new(v).unwrap();
        let len = 2.0 * r * 10f64.powf(-g.range(0.0, 13.0));
        let seg = Segment::new(s, dir, len).unwrap();
        let got = ball.segment_integral(&seg);
        let want = exact_torus(&ball, &seg.centre(), &dir.get(), seg.length());
        let err = rel_err_exact(got, &want);
        if want.signum() == 0 {
            assert!(
                got <= 4.0 * U * len,
                "{got:e} vs 0: r={r:e} c={c:?} s={s:?} λ={len:e}"
            );
            continue;
        }
        assert!(
            err <= 1e-13,
            "torus: rel err {err:e}: r={r:e} c={c:?} s={s:?} w={:?} λ={len:e}: got {got:e} want {:e}",
            dir.get(),
            want.to_f64()
        );
        worst = worst.max(err);
    }
    worst
}

#[test]
fn short_wrapped_segments_across_faces_and_the_boundary() {
    let w2 = torus_cases::<2>(0x7045_0002, 3000);
    let w3 = torus_cases::<3>(0x7045_0003, 3000);
    eprintln!(
        "wrapped boundary segments across a face: worst relative error 2D {w2:.2e}, 3D {w3:.2e}"
    );
}

/// The early exit of `Ball::segment_integral` (a short segment provably
/// farther than `r` from every image returns 0 without the cell walk) is
/// exact on both sides of the boundary: segments just outside (grazing at
/// distance `r(1 + δ)`, or ending `rδ` short of the sphere, also across the
/// cell faces) give exactly 0, and the same segments moved `rδ` inside give
/// the positive chord, for `δ` from `10⁻³` down to `10⁻¹⁴` (`rδ ≥ 2·10⁻¹⁵`,
/// above the rounding of the constructed points; inside the exit's margin,
/// `10⁻¹³` in the squared distance, the full path decides).
#[test]
fn short_segment_early_exit_is_exact_at_the_boundary() {
    fn check<const D: usize>(c: [f64; D], r: f64, w: [f64; D], n: [f64; D], half: f64) -> usize {
        let dir = Direction::new(w).unwrap();
        let w = dir.get();
        let n = Direction::new(n).unwrap().get();
        let mut checked = 0;
        for delta in [1e-3, 1e-6, 1e-9, 1e-12, 1e-13, 1e-14] {
            if r * delta < 2e-15 {
                // Below the rounding of the constructed points (≈ 6e-17).
                continue;
            }
            for sign in [1.0, -1.0] {
                let rr = r * (1.0 + sign * delta);
                // Grazing: the segment's midpoint at distance rr along n ⟂ ω.
                let g: [f64; D] = core::array::from_fn(|j| c[j] + rr * n[j]);
                // End-on: the segment along ω ending at distance rr from c.
                let e: [f64; D] = core::array::from_fn(|j| c[j] - (rr + half) * w[j]);
                for p in [g, e] {
                    let v = Ball::<D>::new(c, r)
                        .unwrap()
                        .segment_integral(&Segment::new(p, dir, 2.0 * half).unwrap());
                    if sign > 0.0 {
                        assert_eq!(v, 0.0, "outside by {delta:e}: {v:e} (r {r}, c {c:?})");
                    } else {
                        assert!(v > 0.0, "inside by {delta:e}: {v:e} (r {r}, c {c:?})");
                    }
                    checked += 1;
                }
            }
        }
        checked
    }
    let mut n = 0;
    for r in [0.25, 0.1, 0.01, 1e-4] {
        for half in [0.1, 0.2, 0.01] {
            // Centres inside the cell and at its faces (the segments cross them).
            for c in [0.5, 0.02, 0.99, 0.0] {
                n += check::<2>([c, 0.37], r, [0.6, 0.8], [-0.8, 0.6], half);
                n += check::<3>([c, 0.37, 0.81], r, [2.0, -1.0, 2.0], [1.0, 2.0, 0.0], half);
            }
        }
    }
    // Random short segments of large balls (half + r near or above 1/2, where
    // images other than the nearest reach the segment): the result is 0
    // exactly when the nearest image of all 3^D is farther than r.
    let mut rng = linesample::Pcg32::new(17, 4);
    let mut u = || f64::from(rng.next_u32()) / 4_294_967_296.0;
    let mut hits = [0usize; 2];
    for _ in 0..20_000 {
        let r = [0.45, 0.3, 0.2][(u() * 3.0) as usize];
        let half = [0.05, 0.1, 0.2][(u() * 3.0) as usize];
        let c = [u(), u()];
        let p = [u() * 3.0 - 1.0, u() * 3.0 - 1.0];
        let dir = Direction::new([u() - 0.5, u() - 0.5]).unwrap();
        let w = dir.get();
        let mut dmin = f64::INFINITY;
        for nx in -3..=3 {
            for ny in -3..=3 {
                let y = [p[0] - c[0] - f64::from(nx), p[1] - c[1] - f64::from(ny)];
                let t = (y[0] * w[0] + y[1] * w[1]).clamp(-half, half);
                dmin = dmin.min(((y[0] - t * w[0]).powi(2) + (y[1] - t * w[1]).powi(2)).sqrt());
            }
        }
        let v = Ball::<2>::new(c, r)
            .unwrap()
            .segment_integral(&Segment::new(p, dir, 2.0 * half).unwrap());
        if dmin > r + 1e-9 {
            assert_eq!(v, 0.0, "{p:?} {c:?} r {r} half {half}: d {dmin}");
            hits[0] += 1;
        } else if dmin < r - 1e-9 {
            assert!(v > 0.0, "{p:?} {c:?} r {r} half {half}: d {dmin}");
            hits[1] += 1;
        }
    }
    println!(
        "{n} boundary segments; random: {} miss, {} hit",
        hits[0], hits[1]
    );
}
