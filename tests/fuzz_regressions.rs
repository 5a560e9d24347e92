//! Inputs the fuzzers found (fuzz/fuzz_targets/*.rs), kept
//! as unit tests so every CI run checks them (the subnormal-length finding is in
//! tests/estimators.rs).

use linesample::geom::Direction;
use linesample::integrand::{Ball, Gaussian, HalfSpace, Integrand};
use linesample::pattern::Ccvt;
use linesample::primitive::Line;
use linesample::Seed;

/// A ball of radius 1.28e-159 gave a chord 1.4e-7 longer than its diameter
/// (the double-double squares underflowed): such radii are now rejected.
#[test]
fn tiny_balls_are_rejected() {
    let err = Ball::<2>::new([-2.43e305, -1.86e272], 1.2825200591993592e-159).unwrap_err();
    assert!(err.to_string().contains("radius"), "{err}");
    // At the smallest accepted radius the chord stays within the diameter.
    let r = Ball::<2>::RADIUS_MIN;
    let b = Ball::<2>::new([0.5, 0.5], r).unwrap();
    let d = Direction::new([1.4e-305, -5.3e-137]).unwrap();
    for off in [0.0, 0.3, 0.9, 0.999_999] {
        let v = b.segment_free(&[0.5 + off * r, 0.5], &d, f64::NEG_INFINITY, f64::INFINITY);
        assert!((0.0..=2.0 * r).contains(&v), "{off}: {v:e}");
    }
}

/// Parameters near 1e217 overflowed the squared distance and returned NaN.
#[test]
fn gaussian_far_parameters_give_zero_not_nan() {
    let g = Gaussian::<2>::new([3.28e-140, 3.42e-106], 0.0012589287694449447).unwrap();
    let d = Direction::new([8.996194290343995e-265, -9.42022705542258e215]).unwrap();
    let p = [-2.6096760944064273e-189, 0.0];
    let v = g.segment_free(&p, &d, -1.0773201020961902e217, -9.275914482822377e212);
    assert_eq!(v, 0.0);
    let v = g.segment_free(&p, &d, 9.275914482822377e212, 1.0773201020961902e217);
    assert_eq!(v, 0.0);
    // Straddling with huge ends is the whole line.
    let line = g.segment_free(&p, &d, -1e217, 1e217);
    let whole = g.segment_free(&p, &d, f64::NEG_INFINITY, f64::INFINITY);
    assert_eq!(line, whole);
    assert!(whole.is_finite() && whole >= 0.0);
}

/// A line given through a far point (1.6e11, 1.6e11) lost 1e-6 of its chord to
/// cancellation in the box clipping; lines are now stored by their point
/// nearest to the box centre.
#[test]
fn far_line_points_keep_the_chord_exact() {
    let h = HalfSpace::<2>::new(Direction::new([-1.0, -1.7e-193]).unwrap(), -5.958e8).unwrap();
    let d = Direction::new([1.0, 1.0]).unwrap();
    let far = Line::new([156842099844.51764, 156842099844.51764], d).unwrap();
    let near = Line::new([0.5, 0.5], d).unwrap();
    let v = h.line_integral(&far);
    assert!((v - 2f64.sqrt()).abs() <= 4.0 * f64::EPSILON, "{v}");
    assert!((v - h.line_integral(&near)).abs() <= 4.0 * f64::EPSILON);
    // The stored point lies on the line (x = y) near the box centre (τ is
    // rounded, so it moves along the line by up to ulp(τ)).
    let p = far.point();
    assert_eq!(p[0], p[1]);
    assert!((p[0] - 0.5).abs() < 1e-4, "{p:?}");
    // Same for the other integrands.
    let b = Ball::<2>::new([0.5, 0.5], 0.25).unwrap();
    assert!((b.line_integral(&far) - 0.5).abs() <= 2.0 * f64::EPSILON);
}

/// A tangent line with a tiny chord (half chord 2.6e-99 at t ≈ 4.9e-33, where
/// `t ± h` round to `t`) was returned whole for a zero-length segment.
#[test]
fn ball_chord_never_exceeds_the_segment() {
    let r = 4.8578750597249806e-33;
    let b = Ball::<2>::new([2.3085228502446436e-283, 1.0998657917027512e247], r).unwrap();
    let d = Direction::new([-9.239234115397806e32, 4.8578750597497736e-33]).unwrap();
    let p = [r, r];
    assert_eq!(b.segment_free(&p, &d, r, r), 0.0);
    let v = b.segment_free(&p, &d, r, f64::INFINITY);
    assert!(v <= 2.0 * r, "{v:e}");
}

/// Found by the `geometry` fuzz target: a line through a point far along its own
/// direction, `p = (v, v, v)` with `v = 3.53e30` on the main diagonal. `Line::new`
/// rounds the foot parameter `τ ≈ −6.1e30` to a double, so the stored point is
/// `≈ ulp(τ)·|ω| ≈ 8.7e14` away from the box (at `(−5.0e14, …)`, not near the
/// centre as documented), the clipping parameters are `≈ 8.7e14` (ulp 0.125) and
/// the chord comes out as 1.75 instead of `√3 = 1.7320508…`: every line integral
/// along such a line is 1 % off. Fails until `Line::new` repeats its projection
/// from the rounded point (each pass shrinks the distance to the foot by `≈ 2⁻⁵²`).
#[test]
fn line_far_along_its_direction_keeps_its_chord() {
    let v = 3.5295369653413445e30;
    let d = Direction::new([1.0, 1.0, 1.0]).unwrap();
    let line = Line::new([v, v, v], d).unwrap();
    let q = line.point();
    // The stored point is (nearly) the point of the line nearest the box centre.
    for x in q {
        assert!((x - 0.5).abs() < 1e-9, "stored point {q:?}");
    }
    let (t0, t1) = linesample::geom::clip_to_unit_box(&q, &d).expect("the diagonal hits the box");
    let chord = t1 - t0;
    assert!(
        (chord - 3f64.sqrt()).abs() <= 8.0 * f64::EPSILON,
        "chord {chord} vs √3"
    );
    // The integrands see it too: f ≡ 1 on the box integrates to the chord.
    let one = HalfSpace::<3>::new(Direction::axis(0).unwrap(), -1.0).unwrap();
    let li = one.line_integral(&line);
    assert!(
        (li - 3f64.sqrt()).abs() <= 8.0 * f64::EPSILON,
        "line integral {li}"
    );
    // A 2D line far along its direction: through (2¹⁰⁰, 2¹⁰¹) along (1, 2), i.e.
    // y = 2x through the origin, whose foot of the centre is (0.3, 0.6) and
    // whose chord runs from (0, 0) to (0.5, 1), of length √1.25.
    let d2 = Direction::new([1.0, 2.0]).unwrap();
    let far = Line::new([2f64.powi(100), 2f64.powi(101)], d2).unwrap();
    let q2 = far.point();
    assert!(
        (q2[0] - 0.3).abs() < 1e-12 && (q2[1] - 0.6).abs() < 1e-12,
        "stored point {q2:?}"
    );
    let (t0, t1) = linesample::geom::clip_to_unit_box(&q2, &d2).unwrap();
    assert!(
        (t1 - t0 - 1.25f64.sqrt()).abs() <= 8.0 * f64::EPSILON,
        "chord {}",
        t1 - t0
    );
}

/// Found by the `integrand_ball` fuzz target after the boundary-accuracy work:
/// the whole line `y = x` given through `(2.4e35, 2.4e35)`. One re-basing
/// leaves the point `≈ ulp(τ) ≈ 2⁶⁵` from the foot; the double-double
/// discriminant then loses everything (`2⁻¹⁰⁶·e² ≫ r²`) and the chord came out
/// as 2048 (before the boundary work, the quick rejection made it 0). The
/// exact chord is `2√(r² − d²)` with `d = |c₀ − c₁|/√2`.
#[test]
fn ball_seen_from_far_along_the_line_keeps_its_chord() {
    let c = [5.207212544768901e-5, 3.2599286142070292e-307];
    let r = 0.13088992484936526;
    let b = Ball::<2>::new(c, r).unwrap();
    let d = Direction::new([1.0, 1.0]).unwrap();
    let v = 2.417370521746097e35;
    let got = b.segment_free(&[v, v], &d, f64::NEG_INFINITY, f64::INFINITY);
    let dist = (c[0] - c[1]) / 2f64.sqrt();
    let want = 2.0 * ((r - dist) * (r + dist)).sqrt();
    assert!(
        ((got - want) / want).abs() < 1e-14,
        "chord {got:e} vs {want:e}"
    );
}

/// Found by the `integrand_ball` fuzz target right after the repeated
/// re-basing: a whole line through `(−7.3e211, −7.3e211)`, far outside the
/// old domain `|p − c| ≲ 10¹⁵⁰`; eight passes left the point 10⁸⁴ from the
/// foot and the chord came out as 1.9e50. Every finite point now converges.
#[test]
fn ball_chord_from_any_finite_point_is_at_most_the_diameter() {
    let c = [5.207212544768901e-5, 1.5743374606408346e-307];
    let r = 0.13088992205539754;
    let b = Ball::<2>::new(c, r).unwrap();
    let d = Direction::new([1.0, 1.0]).unwrap();
    for v in [-7.343562278240081e211, 1e300, -1e307] {
        let got = b.segment_free(&[v, v], &d, f64::NEG_INFINITY, f64::INFINITY);
        let dist = (c[0] - c[1]) / 2f64.sqrt();
        let want = 2.0 * ((r - dist) * (r + dist)).sqrt();
        assert!(
            ((got - want) / want).abs() < 1e-14,
            "through ({v:e}, {v:e}): chord {got:e} vs {want:e}"
        );
    }
}

/// Found by the `integrand_ball` fuzz target in a CI run: a line along `x`
/// that passes `10⁻⁴²` inside the tangent of a ball of radius `4.8e-4`. The
/// double-double discriminant (precision `2⁻¹⁰⁶r²`) cannot see `r² − d²`
/// there; it gave a half chord of `3e-127` for `3.2e-23`, and the clipped
/// segment `[5e-304, 1.5e63]` came out as 1.5e63. Near tangency Δ is now
/// recomputed from the exact constant term. Exact: `h = √(r² − d²)`,
/// `d = r − 1.131e-42` (the `y` offset is negligible), so the clipped
/// length is `h − t0 ≈ h`.
#[test]
fn ball_near_tangent_clipped_chord_is_exact() {
    let r = 0.0004767922794117647;
    let b = Ball::<3>::new([2.817009055118447e209, 2.4107286212654317e64, r], r).unwrap();
    let d = Direction::new([1.0, 8.635991429482489e-78, -1.0510137569386553e-123]).unwrap();
    let p = [-0.0, 4.857875058472934e-33, 1.1310621769458476e-42];
    let got = b.segment_free(&p, &d, 5.2796563068250144e-304, 1.50515899895279e63);
    // r² − d² = (r − d)(r + d) with r − d = 1.1310621769458476e-42 (the
    // centre's z is exactly r, so d = r − p_z up to the negligible y term).
    let h = (1.1310621769458476e-42 * (2.0 * r - 1.1310621769458476e-42)).sqrt();
    assert!(
        ((got - h) / h).abs() < 1e-13,
        "clipped chord {got:e} vs {h:e}"
    );
}

/// A converged CCVT run (2D, N = 13, capacity 13, jitter 3e-5) left site 7
/// exactly one point's worth (1/13) off the toroidal centroid of its points:
/// its last centroid step was taken in the frame of its old position, from
/// which its points straddled the antipode. A moved site is now re-centred in
/// its own frame.
#[test]
fn converged_ccvt_sites_are_centroids_in_their_own_frame() {
    let r = Ccvt::<2>::new(13)
        .unwrap()
        .capacity(13)
        .unwrap()
        .max_iterations(14)
        .unwrap()
        .jitter(3.05175782320255e-5)
        .unwrap()
        .generate(Seed::new(2025524822301154111));
    assert!(r.converged());
    let wrap = |d: f64| d - (d + 0.5).floor();
    let (sites, pts, asg) = (r.sites_f64(), r.discrete_points(), r.assignment());
    for (i, s) in sites.iter().enumerate() {
        let mut sum = [0.0f64; 2];
        for (p, &a) in pts.iter().zip(asg) {
            if a as usize == i {
                for j in 0..2 {
                    sum[j] += wrap(p[j] - s[j]);
                }
            }
        }
        for (j, v) in sum.iter().enumerate() {
            assert!(
                (v / 13.0).abs() <= 1e-12,
                "site {i}, axis {j}: {:e} off",
                v / 13.0
            );
        }
    }
}

/// Found by `integrand_gaussian`: a narrow Gaussian (σ = 3.05e−5) far from
/// the origin and a ray from (528, 528) along the diagonal; `κ ≈ 4e9`, so the
/// `f32` exponent is off by about 3.5 (a factor 33 on the value). The stated
/// bound `P·(1e−6 + expm1(B))` covers it; its old linear form `P·(1e−6 + B)`
/// did not.
#[test]
fn gaussian_f32_error_is_exponential_in_the_exponent_error() {
    let g = Gaussian::<2>::new(
        [127_984.000_244_141_98, 7.16e-322],
        3.052_502_870_559_692_4e-5,
    )
    .unwrap();
    let (o, d) = (
        [528.062_74f32, 528.062_74],
        [-0.707_106_77f32, -0.707_106_77],
    );
    let got = f64::from(g.segment_free_f32(o, d, -0.0, f32::INFINITY));
    let o64 = o.map(f64::from);
    let d64 = d.map(f64::from);
    let nd = d64.iter().map(|x| x * x).sum::<f64>().sqrt();
    let dir = linesample::geom::Direction::new(d64).unwrap();
    let want = g.segment_free(&o64, &dir, 0.0, f64::INFINITY) / nd;
    let c = g.centre();
    let s = g.sigma();
    let w = dir.get();
    let q = [o64[0] - c[0], o64[1] - c[1]];
    let qq = q[0] * q[0] + q[1] * q[1];
    let qd = q[0] * w[0] + q[1] * w[1];
    let e = (qq - qd * qd).max(0.0) / (2.0 * s * s);
    let tau = 2.0 * std::f64::consts::PI;
    let p = (-e).exp() / (tau * s * s) * s * tau.sqrt() / nd;
    let kappa = nd * qq.sqrt() / s;
    let b = 1e-6 * e + 2e-7 * kappa * (1.0 + (2.0 * e).sqrt());
    let err = (got - want).abs();
    assert!(err <= p * (1e-6 + b.exp_m1()), "{got:e} vs {want:e}");
}

/// `world` fuzz target: a Gaussian centred at `6.4e257` seen along a line
/// whose cross product with the offset overflows gave a NaN line integral;
/// the line passes ~1e257 from the centre, so the integral is 0.
#[test]
fn world_gaussian_far_centre_is_zero_not_nan() {
    use linesample::world::{Gaussian as WorldGaussian, Ray};
    let g = WorldGaussian::<2>::with_peak([6.444e257, 0.0], 1e-3, 1.0).unwrap();
    let ray = Ray::new([0.0, 0.0], [0.0, 1.0]).unwrap();
    assert_eq!(g.line(&ray), 0.0);
    assert_eq!(g.segment(&ray, -1.0, 1.0), 0.0);
    assert_eq!(g.transmittance(&ray, -1.0, 1.0, 1.0), 1.0);
}

/// `world` fuzz target: a segment beyond the `f64` range along a ray from
/// `y = 1.8e308` (its offsets from the foot overflow) gave NaN; it is 0.
#[test]
#[allow(clippy::excessive_precision)]
fn world_gaussian_segment_beyond_the_range_is_zero_not_nan() {
    use linesample::world::{Gaussian as WorldGaussian, Ray};
    let g = WorldGaussian::<2>::with_peak(
        [-6.905776912367484e-258, 7.324310975749072e-307],
        0.00016370415698752083,
        3.0167554059639814e157,
    )
    .unwrap();
    let ray = Ray::new(
        [7.565251118924483e-307, 1.7976918122189023e308],
        [-1.8293195148359608e-253, 6.586037838166659e257],
    )
    .unwrap();
    assert!(g.line(&ray) > 1e150);
    assert_eq!(
        g.segment(&ray, 8.581132559700589e304, 1.3824172084878715e306),
        0.0
    );
}

/// `world` fuzz target: a narrow Gaussian whose exponent `ρ²/2σ²` overflows
/// (a line `3.5e152` from the centre, `σ = 5e-3`) gave NaN; it is 0.
#[test]
fn world_gaussian_overflowing_exponent_is_zero_not_nan() {
    use linesample::world::{Gaussian as WorldGaussian, Ray};
    let g = WorldGaussian::<2>::with_peak([0.0, 0.0], 0.005238970588235294, 2.46e260).unwrap();
    let ray = Ray::new([3.5e152, 6.444e257], [0.0, -1.0]).unwrap();
    assert_eq!(g.line(&ray), 0.0);
}

/// `geometry` fuzz target: a line through a point at the end of the `f64`
/// range, `(−2.96e305, −1.8e308)`, got a NaN stored point (the re-basing
/// step toward the box centre overflowed); the point stays finite and on the
/// line.
#[test]
fn line_through_a_point_at_the_end_of_the_range_stays_finite() {
    let dir = Direction::new([1.03977793757e-312, 1.884794008661276e-307]).unwrap();
    let p = [-2.962506997148592e305, -1.7976931348623157e308];
    let line = Line::new(p, dir).unwrap();
    let q = line.point();
    assert!(q.iter().all(|x| x.is_finite()), "{q:?}");
    // On the line: the perpendicular offset from p is within rounding.
    let w = dir.get();
    let d = [q[0] - p[0], q[1] - p[1]];
    let along = d[0] * w[0] + d[1] * w[1];
    let perp = ((d[0] - along * w[0]).powi(2) + (d[1] - along * w[1]).powi(2)).sqrt();
    assert!(perp <= 1e-15 * f64::MAX, "{perp:e}");
}

/// `world` fuzz target: a line through an origin at 6e30 along `(1, 1, 1)`,
/// straddling the foot, passing 7e3 from a Gaussian of σ = 468 (the offset is
/// below the rounding of the origin). `segment_fast` computed `ρ ≈ 0`, a
/// value 4e48 times too large, and claimed `R = 1.2e−15`: its exponent term
/// lacked the square of the offset's error. Now `R` is infinite or bounds
/// the error.
#[test]
#[allow(clippy::excessive_precision)]
fn world_gaussian_segment_fast_bound_holds_when_the_offset_is_lost() {
    use linesample::world::{Gaussian as WorldGaussian, Ray};
    let g = WorldGaussian::<3>::with_peak(
        [4.97343564e-316, -8576.999481202103, -8577.501518339268],
        4.6798443628627103e2,
        2.0816811327277296e30,
    )
    .unwrap();
    let o = 3.5295369653413445e30;
    let ray = Ray::new([o, o, o], [1.0, 1.0, 1.0]).unwrap();
    let (t0, t1) = (-6.601725478835641e32, 3.351697574722037e-294);
    let exact = g.segment(&ray, t0, t1);
    assert!(exact > 5e-16 && exact < 6e-16, "{exact:e}");
    let (v, r) = g.segment_fast(&ray, t0, t1);
    assert!(
        !r.is_finite() || (v - exact).abs() <= r * exact,
        "{v:e} R {r:e}"
    );
}
