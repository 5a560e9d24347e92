//! Tests of the Gaussian integrand against independent references: adaptive
//! Gauss–Kronrod quadrature of the density (with the exponent taken relative to
//! the point of the segment nearest to the centre, in double-double, so the
//! reference keeps relative accuracy in the far tail), brute-force image sums,
//! and high-precision constants computed offline with mpmath (50 digits).

#![allow(clippy::excessive_precision, clippy::needless_range_loop)]

mod common;
mod exact;

use common::{integrate, rel_err};
use exact::{Dy, Mix};
use linesample::geom::Direction;
use linesample::integrand::{Gaussian, Integrand};
use linesample::num::Dd;
use linesample::primitive::{Line, Rays32, Segment};
use linesample::special::erfcx;
use linesample::ParamError;
use proptest::prelude::*;

const SIGMAS: [f64; 8] = [1e-6, 1e-3, 0.01, 0.1, 0.3, 1.0, 10.0, 1e6];

// ---------------------------------------------------------------------------
// References
// ---------------------------------------------------------------------------

/// `x / y` for double-doubles (one correction step; plenty for a reference).
fn ddiv(x: Dd, y: Dd) -> Dd {
    let q1 = x.hi / y.hi;
    let r = x.sub(y.mul(Dd::new(q1)));
    let q2 = r.hi / y.hi;
    Dd::new(q1).add(Dd::new(q2))
}

/// `m · e^{−E}` without intermediate underflow: `(m e^{−E/2}) e^{−E/2}`.
fn scaled_exp(e: Dd, m: f64) -> f64 {
    let h = 0.5 * e.hi;
    (m * (-h).exp()) * (-h).exp() * (1.0 - e.lo)
}

/// `(2πσ²)^{−D/2}`.
fn norm(d: usize, s: f64) -> f64 {
    (2.0 * std::f64::consts::PI * s * s).powf(-(d as f64) / 2.0)
}

/// Reference `∫_{t0}^{t1} F(p − m + tω) dt` for the Gaussian at `c` (image
/// shift `m`) by adaptive Gauss–Kronrod, with `|x − c|² − |x_r − c|²` formed in
/// double-double relative to the point `x_r` of the segment nearest to `c`.
fn ref_free<const D: usize>(
    c: &[f64; D],
    s: f64,
    p: &[f64; D],
    m: &[f64; D],
    w: &[f64; D],
    t0: f64,
    t1: f64,
) -> f64 {
    let mut q = [Dd::new(0.0); D];
    let mut a = Dd::new(0.0);
    let mut qw = Dd::new(0.0);
    for j in 0..D {
        q[j] = Dd::diff(p[j], c[j]).sub(Dd::new(m[j]));
        a = a.add(Dd::prod(w[j], w[j]));
        qw = qw.add(q[j].mul(Dd::new(w[j])));
    }
    let tc = -qw.to_f64() / a.to_f64();
    let tr = tc.clamp(t0, t1);
    let s2 = Dd::prod(s, s);
    let two_s2 = s2.add(s2);
    let qw2 = qw.add(qw);
    // Integrate over the offset τ = t − t_r (exact nodes near the reference
    // point: rounding the nodes t themselves would cost ~ε|t|/(σ²/d) relative).
    let tr2 = Dd::new(tr).add(Dd::new(tr));
    let g = |tau: f64| {
        let sum = tr2.add(Dd::new(tau));
        let e = Dd::new(tau).mul(qw2.add(sum.mul(a)));
        (-ddiv(e, two_s2).to_f64()).exp()
    };
    let sc = s / a.to_f64().sqrt();
    let wdt = ((tr - tc) * (tr - tc) + 130.0 * sc * sc).sqrt();
    let lo = t0.max(tc - wdt);
    let hi = t1.min(tc + wdt);
    if lo >= hi {
        return 0.0;
    }
    let mut br = vec![lo - tr];
    // Break points every σ/√a around the peak help the adaptive rule.
    for k in -12..=12 {
        let b = tc + k as f64 * sc;
        if b > lo && b < hi {
            br.push(b - tr);
        }
    }
    br.push(hi - tr);
    br.sort_by(f64::total_cmp);
    let mut i = 0.0;
    for k in 0..br.len() - 1 {
        i += integrate(g, br[k], br[k + 1], 1e-15);
    }
    // Exponent of the reference point.
    let mut d2 = Dd::new(0.0);
    for j in 0..D {
        let x = q[j].add(Dd::prod(tr, w[j]));
        d2 = d2.add(x.mul(x));
    }
    scaled_exp(ddiv(d2, two_s2), norm(D, s) * i)
}

/// Reference periodised value: brute-force image sum over a block, relative to
/// the nearest image (double-double exponents); `f ≡ 1` for `σ ≥ 3` (the
/// deviation is below `2e^{−2π²·9} ≈ 1e−77`).
fn ref_value<const D: usize>(c: &[f64; D], s: f64, x: &[f64; D]) -> f64 {
    if s >= 3.0 {
        return 1.0;
    }
    let k = (12.0 * s).ceil() as i64 + 2;
    let s2 = Dd::prod(s, s);
    let two_s2 = s2.add(s2);
    let mut es = Vec::new();
    let mut m = [-k; D];
    loop {
        let mut d2 = Dd::new(0.0);
        for j in 0..D {
            let y = Dd::diff(x[j], c[j]).sub(Dd::new(m[j] as f64 + (x[j] - c[j]).round()));
            d2 = d2.add(y.mul(y));
        }
        es.push(ddiv(d2, two_s2));
        let mut j = 0;
        loop {
            if j == D {
                let emin = es.iter().fold(
                    Dd::new(f64::INFINITY),
                    |a, e| if e.hi < a.hi { *e } else { a },
                );
                // Ascending, compensated sum of the (many) image terms.
                let mut ts: Vec<f64> = es.iter().map(|e| (-(e.sub(emin)).to_f64()).exp()).collect();
                ts.sort_by(f64::total_cmp);
                let sum = ts
                    .iter()
                    .fold(Dd::new(0.0), |a, &t| a.add(Dd::new(t)))
                    .to_f64();
                return scaled_exp(emin, norm(D, s) * sum);
            }
            if m[j] < k {
                m[j] += 1;
                break;
            }
            m[j] = -k;
            j += 1;
        }
    }
}

/// Reference wrapped segment integral: the sum over images of [`ref_free`]
/// along the unwrapped straight segment. Images farther than
/// `√(D/4 + 120σ²)` from the segment are below `e^{−60}` of the nearest image
/// everywhere on it. `f ≡ 1` for `σ ≥ 3`.
fn ref_segment<const D: usize>(c: &[f64; D], s: f64, cs: &[f64; D], w: &[f64; D], len: f64) -> f64 {
    ref_segment_t(c, s, cs, w, -0.5 * len, 0.5 * len)
}

/// [`ref_segment`] over `cs + tω`, `t ∈ [ta, tb]`.
fn ref_segment_t<const D: usize>(
    c: &[f64; D],
    s: f64,
    cs: &[f64; D],
    w: &[f64; D],
    ta: f64,
    tb: f64,
) -> f64 {
    if s >= 3.0 {
        return tb - ta;
    }
    let r2 = D as f64 / 4.0 + 120.0 * s * s;
    let r = r2.sqrt();
    let mut lo = [0i64; D];
    let mut hi = [0i64; D];
    for j in 0..D {
        let a = cs[j] + ta * w[j] - c[j];
        let b = cs[j] + tb * w[j] - c[j];
        lo[j] = (a.min(b) - r).floor() as i64;
        hi[j] = (a.max(b) + r).ceil() as i64;
    }
    let mut m = lo;
    let mut sum = 0.0;
    loop {
        // Distance from c + m to the segment.
        let mut v = [0.0; D];
        let mut vw = 0.0;
        for j in 0..D {
            v[j] = c[j] + m[j] as f64 - cs[j];
            vw += v[j] * w[j];
        }
        let t = vw.clamp(ta, tb);
        let d2: f64 = (0..D).map(|j| (v[j] - t * w[j]).powi(2)).sum();
        if d2 <= r2 {
            let mf: [f64; D] = std::array::from_fn(|j| m[j] as f64);
            sum += ref_free(c, s, cs, &mf, w, ta, tb);
        }
        let mut j = 0;
        loop {
            if j == D {
                return sum;
            }
            if m[j] < hi[j] {
                m[j] += 1;
                break;
            }
            m[j] = lo[j];
            j += 1;
        }
    }
}

fn check(got: f64, want: f64, tol: f64, what: &str) -> f64 {
    let e = if want.abs() < 1e-290 {
        (got - want).abs() / 1e-290
    } else {
        rel_err(got, want)
    };
    assert!(
        e <= tol,
        "{what}: got {got:e}, want {want:e}, rel err {e:e}"
    );
    e
}

fn unit<const D: usize>(v: [f64; D]) -> Direction<D> {
    Direction::new(v).unwrap()
}

// ---------------------------------------------------------------------------
// erfcx
// ---------------------------------------------------------------------------

#[test]
fn erfcx_against_quadrature_and_mpmath() {
    // erfcx(x) = (2/√π) ∫_0^∞ e^{−t² − 2xt} dt.
    let mut worst = 0.0f64;
    for i in 0..200 {
        let x = if i == 0 { 0.0 } else { 1e-3 * 1.06f64.powi(i) };
        let top = (40.0 / x.max(1e-300)).min(9.8);
        let mut br = vec![0.0];
        let mut b = top;
        while b > 1e-4 * top {
            br.push(b);
            b *= 0.25;
        }
        br.sort_by(f64::total_cmp);
        br.dedup();
        let mut v = 0.0;
        for k in 0..br.len() - 1 {
            v += integrate(|t| (-t * t - 2.0 * x * t).exp(), br[k], br[k + 1], 1e-15);
        }
        let r = v * 2.0 / std::f64::consts::PI.sqrt();
        worst = worst.max(check(erfcx(x), r, 2e-15, &format!("erfcx({x})")));
    }
    // mpmath (50 digits).
    let table = [
        (0.1, 0.89645697996912663666),
        (0.4999, 0.6157416166688974783),
        (0.5, 0.61569034419292587487),
        (1.0, 0.42758357615580700441),
        (2.0, 0.25539567631050574387),
        (3.0, 0.17900115118138995042),
        (4.9999, 0.11070677105245274603),
        (5.0, 0.11070463773306862637),
        (7.0, 0.07980005432915293349),
        (12.0, 0.04685422101489376262),
        (26.0, 0.021683584850562906616),
        (27.0, 0.020881607990420940674),
        (100.0, 0.0056416137829894329036),
        (1e5, 5.6418958351954680777e-6),
    ];
    for (x, r) in table {
        worst = worst.max(check(erfcx(x), r, 1e-15, &format!("erfcx({x}) mpmath")));
    }
    println!("erfcx max rel err {worst:e}");
}

// ---------------------------------------------------------------------------
// Free-space segment integrals
// ---------------------------------------------------------------------------

fn seg_case<const D: usize>(
    g: &Gaussian<D>,
    p: [f64; D],
    w: [f64; D],
    t0: f64,
    t1: f64,
    tol: f64,
) -> f64 {
    let dir = unit(w);
    let got = g.segment_free(&p, &dir, t0, t1);
    let want = ref_free(&g.centre(), g.sigma(), &p, &[0.0; D], &dir.get(), t0, t1);
    check(
        got,
        want,
        tol,
        &format!(
            "σ={} c={:?} p={p:?} ω={:?} [{t0:e}, {t1:e}]",
            g.sigma(),
            g.centre(),
            dir.get()
        ),
    )
}

/// Narrow segments far in the tail (values ~1e−90 and ~1e−300), short
/// segments, straddling segments, half lines and lines, for every σ.
#[test]
fn segment_free_hard_cases() {
    let mut worst = 0.0f64;
    for &s in &SIGMAS {
        let g2 = Gaussian::<2>::new([0.3, 0.6], s).unwrap();
        let g3 = Gaussian::<3>::new([0.3, 0.6, 0.45], s).unwrap();
        let c2 = g2.centre();
        let c3 = g3.centre();
        // Tail: distance r = σ√(2E) for E ≈ 207 (1e−90) and E ≈ 690 (1e−300).
        for e in [207.0f64, 690.0] {
            let r = s * (2.0 * e).sqrt();
            for (k, len) in [1e-3, 0.1, 1.0, 30.0].iter().enumerate() {
                let l = len * s;
                // Radial segment starting at distance r, moving away.
                let u = [0.6, 0.8];
                let p = [c2[0] + r * u[0], c2[1] + r * u[1]];
                worst = worst.max(seg_case(&g2, p, u, 0.0, l, 1e-13));
                // Same, moving towards the centre (near end = t1).
                worst = worst.max(seg_case(&g2, p, [-0.6, -0.8], -l, 0.0, 1e-13));
                // Oblique (3D), not through the centre.
                let w = [0.48, 0.6, 0.64];
                let p = [c3[0] + r * 0.8, c3[1] - r * 0.6, c3[2] + 0.1 * s * k as f64];
                worst = worst.max(seg_case(&g3, p, w, 3.0 * s, 3.0 * s + l, 1e-13));
                // Perpendicular at distance r, straddling the foot.
                worst = worst.max(seg_case(&g3, p, [0.6, 0.8, 0.0], -0.5 * l, 0.5 * l, 1e-13));
            }
        }
        // Near the centre: short, straddling, half lines, lines, long.
        let w3 = [0.2, -0.5, 0.7];
        let p3 = [c3[0] + 0.3 * s, c3[1] + 0.1 * s, c3[2] - 0.2 * s];
        for (t0, t1) in [
            (-0.1 * s, 0.2 * s),
            (0.5 * s, 0.5 * s + 1e-9 * s),
            (2.0 * s, 2.0 * s + 1e-6 * s),
            (-3.0 * s, 5.0 * s),
            (1.5 * s, 40.0 * s),
            (f64::NEG_INFINITY, 0.3 * s),
            (-0.7 * s, f64::INFINITY),
            (f64::NEG_INFINITY, f64::INFINITY),
            (-2.0, 3.0),
        ] {
            worst = worst.max(seg_case(&g3, p3, w3, t0, t1, 1e-13));
            worst = worst.max(seg_case(&g2, [p3[0], p3[1]], [0.3, -0.9], t0, t1, 1e-13));
        }
        // Zero length is exactly 0.
        assert_eq!(g2.segment_free(&c2, &unit([1.0, 0.0]), 0.25, 0.25), 0.0);
    }
    println!("segment_free hard cases: max rel err {worst:e}");
}

/// Lines: `σ√(2π)(2πσ²)^{−D/2} e^{−ρ²/2σ²}`.
#[test]
fn lines_are_exact() {
    let mut worst = 0.0f64;
    for &s in &SIGMAS {
        let g = Gaussian::<3>::new([0.25, 0.5, 0.75], s).unwrap();
        let c = g.centre();
        for rho_over_s in [0.0, 0.5, 3.0, 20.0] {
            // A line at distance ρ from the centre, along (0, 0.6, 0.8), offset along x.
            let rho = rho_over_s * s;
            let p = [c[0] + rho, c[1] - 7.0 * s * 0.6, c[2] - 7.0 * s * 0.8];
            let dir = unit([0.0, 0.6, 0.8]);
            let got = g.segment_free(&p, &dir, f64::NEG_INFINITY, f64::INFINITY);
            let dx = Dd::diff(p[0], c[0]);
            let s2 = Dd::prod(s, s);
            let e = ddiv(dx.mul(dx), s2.add(s2));
            let want = scaled_exp(e, s * (2.0 * std::f64::consts::PI).sqrt() * norm(3, s));
            worst = worst.max(check(got, want, 1e-14, &format!("line σ={s} ρ={rho}")));
        }
    }
    println!("lines: max rel err {worst:e}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    #[test]
    fn segment_free_random_3d(
        si in 0usize..8,
        c in prop::array::uniform3(-2.0f64..3.0),
        off in prop::array::uniform3(-1.0f64..1.0),
        scale in -3.0f64..1.5,
        w in prop::array::uniform3(-1.0f64..1.0),
        ta in -5.0f64..5.0,
        tl in -12.0f64..1.5,
        inf in 0u8..8,
    ) {
        prop_assume!(w.iter().map(|x| x.abs()).sum::<f64>() > 1e-3);
        let s = SIGMAS[si];
        let g = Gaussian::<3>::new(c, s).unwrap();
        let cc = g.centre();
        // Points at 10^scale·σ from the centre, segments on the σ scale.
        let d = 10f64.powf(scale) * s;
        let p = [cc[0] + d * off[0], cc[1] + d * off[1], cc[2] + d * off[2]];
        let base = ta * s * 10f64.powf(scale.max(0.0));
        let t0 = if inf == 0 { f64::NEG_INFINITY } else { base };
        let t1 = if inf == 1 { f64::INFINITY } else { base + 10f64.powf(tl) * s };
        seg_case(&g, p, w, t0, t1, 1e-13);
    }

    #[test]
    fn segment_free_random_2d(
        si in 0usize..8,
        c in prop::array::uniform2(-2.0f64..3.0),
        off in prop::array::uniform2(-1.0f64..1.0),
        scale in -3.0f64..1.5,
        w in prop::array::uniform2(-1.0f64..1.0),
        ta in -5.0f64..5.0,
        tl in -12.0f64..1.5,
    ) {
        prop_assume!(w.iter().map(|x| x.abs()).sum::<f64>() > 1e-3);
        let s = SIGMAS[si];
        let g = Gaussian::<2>::new(c, s).unwrap();
        let cc = g.centre();
        let d = 10f64.powf(scale) * s;
        let p = [cc[0] + d * off[0], cc[1] + d * off[1]];
        let t0 = ta * s * 10f64.powf(scale.max(0.0));
        let t1 = t0 + 10f64.powf(tl) * s;
        seg_case(&g, p, w, t0, t1, 1e-13);
    }
}

// ---------------------------------------------------------------------------
// Periodised value, segment, line
// ---------------------------------------------------------------------------

#[test]
fn values_against_image_sums() {
    let mut worst = 0.0f64;
    // Includes both sides of the real-space / Fourier switch (σ = 0.3).
    let sig = [
        1e-6,
        1e-3,
        0.01,
        0.1,
        0.3,
        0.3 * (1.0 + 1e-12),
        0.31,
        0.5,
        1.0,
        10.0,
        1e6,
    ];
    let pts2 = [
        [0.3, 0.6],
        [0.31, 0.62],
        [0.8, 0.1],
        [0.5 + 0.3, 0.6 + 0.5],
        [-3.7, 12.25],
        [0.3 + 2e-5, 0.6 - 1e-5],
    ];
    for &s in &sig {
        for c in [[0.3, 0.6], [1.3, -2.4]] {
            let g = Gaussian::<2>::new(c, s).unwrap();
            for x in pts2 {
                let want = ref_value(&g.centre(), s, &x);
                if want < 1e-300 {
                    assert!(g.value(&x) < 1e-290);
                    continue;
                }
                worst = worst.max(check(
                    g.value(&x),
                    want,
                    1e-13,
                    &format!("value σ={s} x={x:?}"),
                ));
            }
        }
        if s <= 1.0 {
            let g = Gaussian::<3>::new([0.3, 0.6, 0.9], s).unwrap();
            for x in [
                [0.3, 0.6, 0.9],
                [0.8, 0.1, 0.4],
                [0.31, 0.6, 0.05],
                [5.5, -0.25, 0.9 + 1e-4],
            ] {
                let want = ref_value(&g.centre(), s, &x);
                if want < 1e-300 {
                    continue;
                }
                worst = worst.max(check(
                    g.value(&x),
                    want,
                    1e-13,
                    &format!("value3 σ={s} x={x:?}"),
                ));
            }
        }
    }
    println!("value: max rel err {worst:e}");
}

#[test]
fn centres_outside_the_unit_cell() {
    let g = Gaussian::<2>::new([3.25, -1.75], 0.05).unwrap();
    assert_eq!(g.centre(), [0.25, 0.25]);
    let h = Gaussian::<2>::new([0.25, 0.25], 0.05).unwrap();
    for x in [[0.1, 0.2], [0.9, 0.6]] {
        assert_eq!(g.value(&x), h.value(&x));
    }
    let g3 = Gaussian::<3>::new([-0.5, 7.0, 2.125], 1e-3).unwrap();
    assert_eq!(g3.centre(), [0.5, 0.0, 0.125]);
}

fn seg_periodic<const D: usize>(
    g: &Gaussian<D>,
    cs: [f64; D],
    w: [f64; D],
    len: f64,
    tol: f64,
) -> f64 {
    let dir = unit(w);
    let seg = Segment::new(cs, dir, len).unwrap();
    let got = g.segment_integral(&seg);
    let want = ref_segment(&g.centre(), g.sigma(), &cs, &dir.get(), len);
    check(
        got,
        want,
        tol,
        &format!("segment σ={} cs={cs:?} ω={w:?} λ={len}", g.sigma()),
    )
}

#[test]
fn segment_integrals_periodic() {
    let mut worst = 0.0f64;
    let sig = [
        1e-6,
        1e-3,
        0.01,
        0.1,
        0.3,
        0.3 * (1.0 + 1e-12),
        0.31,
        1.0,
        10.0,
        1e6,
    ];
    for &s in &sig {
        let g2 = Gaussian::<2>::new([0.3, 0.6], s).unwrap();
        let g3 = Gaussian::<3>::new([0.3, 0.6, 0.9], s).unwrap();
        for len in [1e-3, 0.2, 1.0, 1.5, 3.7] {
            // Through (near) the centre, oblique, and far from it; centres outside [0,1).
            worst = worst.max(seg_periodic(
                &g2,
                [0.3 + 1e-3 * s, 0.6],
                [0.6, 0.8],
                len,
                1e-13,
            ));
            worst = worst.max(seg_periodic(
                &g2,
                [2.8 + 0.1 * s, -1.1],
                [1.0, 0.37],
                len,
                1e-13,
            ));
            worst = worst.max(seg_periodic(
                &g3,
                [0.3, 0.6 + 0.5 * s, 0.9],
                [0.2, -0.5, 0.7],
                len,
                1e-13,
            ));
            worst = worst.max(seg_periodic(
                &g3,
                [-0.45, 3.2, 0.1],
                [-0.3, 0.1, 0.9],
                len,
                1e-13,
            ));
        }
        // Very long (λ = 100), oblique: 2D always, 3D for the cheap references.
        worst = worst.max(seg_periodic(&g2, [0.1, 0.2], [0.6, 0.8], 100.0, 1e-13));
        if !(0.1..3.0).contains(&s) {
            worst = worst.max(seg_periodic(
                &g3,
                [0.1, 0.2, 0.3],
                [0.48, 0.6, 0.64],
                100.0,
                1e-13,
            ));
        }
    }
    println!("segment_integral: max rel err {worst:e}");
}

#[test]
fn switch_sigma_agrees() {
    // Just below (real space) and just above (Fourier) the switch, 2D and 3D.
    for s in [0.3, 0.3 + 1e-15, 0.3 * (1.0 + 1e-9)] {
        let g = Gaussian::<3>::new([0.2, 0.7, 0.45], s).unwrap();
        for (cs, w, len) in [
            ([0.9, 0.1, 0.5], [0.3, 0.4, -0.5], 0.7),
            ([0.2, 0.7, 0.45], [1.0, 0.0, 0.0], 1.0),
            ([0.7, 0.2, 0.95], [0.1, -0.9, 0.2], 2.3),
        ] {
            seg_periodic(&g, cs, w, len, 1e-13);
        }
        let x = [0.7, 0.2, 0.95];
        check(
            g.value(&x),
            ref_value(&g.centre(), s, &x),
            1e-13,
            "switch value",
        );
        let line = Line::new([0.1, 0.3, 0.5], unit([0.3, -0.2, 0.9])).unwrap();
        let (a, b) = linesample::geom::clip_to_unit_box(&line.point(), &line.dir()).unwrap();
        let w = line.dir().get();
        let p = line.point();
        let mid: [f64; 3] = std::array::from_fn(|j| p[j] + 0.5 * (a + b) * w[j]);
        let want = ref_segment(&g.centre(), s, &mid, &w, b - a);
        check(g.line_integral(&line), want, 1e-13, "switch line");
    }
}

#[test]
fn axis_segment_of_length_one_is_the_axis_line() {
    for &s in &SIGMAS {
        let g = Gaussian::<3>::new([0.2, 0.7, 0.45], s).unwrap();
        for axis in 0..3 {
            for off in [[0.2, 0.7], [0.9, 0.05], [0.2 + 1e-4, 0.45]] {
                let line = Line::axis(axis, &off).unwrap();
                let l = g.line_integral(&line);
                let seg = Segment::new(line.point(), line.dir(), 1.0).unwrap();
                let si = g.segment_integral(&seg);
                let tol = 1e-13 * l.abs().max(1e-300);
                assert!(
                    (l - si).abs() <= tol,
                    "σ={s} axis {axis} {off:?}: {l:e} vs {si:e}"
                );
                // And the reference.
                let want = ref_segment(&g.centre(), s, &line.point(), &line.dir().get(), 1.0);
                check(l, want, 1e-13, "axis line");
            }
        }
        let g2 = Gaussian::<2>::new([0.2, 0.7], s).unwrap();
        let line = Line::axis(1, &[0.25]).unwrap();
        let seg = Segment::new([0.25, 0.3], line.dir(), 1.0).unwrap();
        check(
            g2.segment_integral(&seg),
            g2.line_integral(&line),
            1e-13,
            "axis 2d",
        );
    }
}

#[test]
fn segment_mean_tends_to_value() {
    for &s in &SIGMAS {
        let g = Gaussian::<2>::new([0.3, 0.6], s).unwrap();
        let dir = unit([0.6, -0.8]);
        for c in [[0.3, 0.6], [0.3 + 2.0 * s.min(0.1), 0.6], [0.81, 0.13]] {
            let v = g.value(&c);
            let m0 = g.segment_mean(&Segment::new(c, dir, 0.0).unwrap());
            assert_eq!(m0, v);
            for (k, len) in [1e-3, 1e-6, 1e-9, 1e-12].iter().enumerate() {
                let m = g.segment_mean(&Segment::new(c, dir, *len).unwrap());
                // |mean − f(c)| ≤ λ²/24 · max|f''| ≈ λ²/(24σ²)·f + tails; check the
                // shrinking relative gap (and against the reference at λ = 1e−3).
                let curv = 1.0 / (s * s) + 0.5 / (s * s * s * s); // ≥ |f''|/f along the segment
                let bound = (len * len * curv / 12.0).max(1e-14) * v.max(1e-300) + 1e-300;
                assert!(
                    (m - v).abs() <= bound.max(if k == 0 { v } else { 0.0 }),
                    "σ={s} c={c:?} λ={len}: {m:e} vs {v:e}"
                );
                if v > 1e-290 && k > 0 && len * len * curv < 1e-13 {
                    assert!(rel_err(m, v) < 1e-13, "σ={s} λ={len}: {m:e} {v:e}");
                }
            }
            let len = 1e-3;
            let want = ref_segment(&g.centre(), s, &c, &dir.get(), len) / len;
            check(
                g.segment_mean(&Segment::new(c, dir, len).unwrap()),
                want,
                1e-13,
                "mean λ=1e-3",
            );
        }
    }
}

#[test]
fn mean_over_centres_is_the_integral() {
    // (1/λ)∫ f over a segment, averaged over the segment centre uniformly on the
    // torus, is ∫ f = 1. Trapezoidal rule on an N^D grid (spectrally accurate for
    // smooth periodic integrands; the aliasing error is ≤ e^{−2π²σ²N²}).
    for (s, n) in [(0.1, 32usize), (0.3, 16), (0.31, 16), (1.0, 8), (1e6, 4)] {
        let g = Gaussian::<2>::new([0.3, 0.6], s).unwrap();
        for (w, len) in [([0.6, 0.8], 0.37), ([1.0, 0.0], 1.0), ([-0.2, 0.9], 2.5)] {
            let dir = unit(w);
            let mut sum = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let c = [(i as f64 + 0.25) / n as f64, (j as f64 + 0.5) / n as f64];
                    sum += g.segment_mean(&Segment::new(c, dir, len).unwrap());
                }
            }
            let mean = sum / (n * n) as f64;
            assert!((mean - g.integral()).abs() < 1e-13, "σ={s} ω={w:?}: {mean}");
        }
    }
    let g = Gaussian::<3>::new([0.3, 0.6, 0.1], 0.35).unwrap();
    let n = 8;
    let dir = unit([0.3, -0.4, 0.5]);
    let mut sum = 0.0;
    for i in 0..n * n * n {
        let c = [
            (i % n) as f64 / n as f64,
            ((i / n) % n) as f64 / n as f64,
            (i / (n * n)) as f64 / n as f64,
        ];
        sum += g.segment_mean(&Segment::new(c, dir, 0.8).unwrap());
    }
    assert!((sum / (n * n * n) as f64 - 1.0).abs() < 1e-13);
}

#[test]
fn piece_integral_against_reference() {
    for &s in &[1e-6, 0.01, 0.2, 0.3, 0.5] {
        let g = Gaussian::<3>::new([0.1, 0.95, 0.5], s).unwrap();
        let p = [0.05, 0.1, 0.5];
        let dir = unit([0.5, 0.5, 0.0]);
        // Piece from t = 0 to the face x = 1 (t = 0.95·√2).
        let t1 = 0.95 / dir.get()[0];
        let got = g.piece_integral(&p, &dir, 0.0, t1);
        let want = ref_segment_t(&g.centre(), s, &p, &dir.get(), 0.0, t1);
        check(got, want, 1e-13, &format!("piece σ={s}"));
    }
}

#[test]
fn wide_gaussian_is_constant_cost() {
    let g = Gaussian::<3>::new([0.1, 0.2, 0.3], 1e6).unwrap();
    let seg = Segment::new([0.4, 0.5, 0.6], unit([0.3, 0.5, 0.7]), 1_000_000.0).unwrap();
    let t = std::time::Instant::now();
    for _ in 0..1000 {
        let v = g.segment_integral(&seg);
        assert!(rel_err(v, 1_000_000.0) < 1e-15);
    }
    assert!(t.elapsed().as_secs_f64() < 0.5, "{:?}", t.elapsed());
    assert_eq!(g.value(&[0.9, 0.9, 0.9]), 1.0);
    assert_eq!(g.max_value(), 1.0);
}

// ---------------------------------------------------------------------------
// Fourier coefficients
// ---------------------------------------------------------------------------

#[test]
fn fourier_high_frequencies_mpmath() {
    // (σ, k, c, re, im) from mpmath at 50 digits with the exact binary centres.
    let g = Gaussian::<2>::new([0.1, 0.7], 1e-6).unwrap();
    let f = g.fourier(&[3_000_000, 4_000_000]);
    check(f.re, 4.8335197996487693033e-215, 1e-13, "fourier re");
    check(
        f.im,
        4.8890176186718215503e-224,
        1e-6,
        "fourier im (tiny, phase-limited)",
    );
    let g = Gaussian::<3>::new([0.123, 0.456, 0.789], 1e-6).unwrap();
    let f = g.fourier(&[1_000_003, -2_000_001, 2_999_999]);
    check(f.re, 6.8446296031059461993e-121, 1e-13, "fourier3 re");
    check(f.im, -6.7591533947486770448e-121, 1e-13, "fourier3 im");
    let g = Gaussian::<2>::new([0.25, 0.8], 0.1).unwrap();
    let f = g.fourier(&[5, 7]);
    check(f.re, 2.6636237890122064957e-7, 1e-13, "fourier small re");
    check(f.im, 3.6661636261333096666e-7, 1e-13, "fourier small im");
    let g = Gaussian::<2>::new([0.3, 0.9], 0.01).unwrap();
    let f = g.fourier(&[123_456_789, -987_654_321]);
    assert_eq!((f.re, f.im), (0.0, 0.0));
    for &s in &SIGMAS {
        let g = Gaussian::<3>::new([0.3, 0.6, 0.9], s).unwrap();
        let f0 = g.fourier(&[0, 0, 0]);
        assert_eq!((f0.re, f0.im), (g.integral(), 0.0));
    }
}

#[test]
fn fourier_against_quadrature_and_series() {
    // f̂_k = Π_j ∫_0^1 g_j(x) e^{−2πik_j x} dx (separable), each by GK of the
    // brute-force 1D image sum.
    for s in [0.05, 0.2, 0.3, 0.45] {
        let c = [0.3, 0.85];
        let g = Gaussian::<2>::new(c, s).unwrap();
        let g1 = |x: f64, cj: f64| -> f64 {
            let mut v = 0.0;
            for n in -12..=12 {
                let y = x - cj - n as f64;
                v += (-y * y / (2.0 * s * s)).exp();
            }
            v / (2.0 * std::f64::consts::PI * s * s).sqrt()
        };
        for k in [[1, 0], [2, -3], [0, 5], [-4, 1]] {
            let mut re = 1.0;
            let mut im = 0.0;
            for j in 0..2 {
                let kj = k[j] as f64;
                let tau = std::f64::consts::TAU;
                let mut cr = 0.0;
                let mut ci = 0.0;
                for q in 0..16 {
                    let (a, b) = (q as f64 / 16.0, (q + 1) as f64 / 16.0);
                    cr += integrate(|x| g1(x, c[j]) * (tau * kj * x).cos(), a, b, 1e-15);
                    ci += integrate(|x| -g1(x, c[j]) * (tau * kj * x).sin(), a, b, 1e-15);
                }
                let (r2, i2) = (re * cr - im * ci, re * ci + im * cr);
                re = r2;
                im = i2;
            }
            let f = g.fourier(&k);
            let m = (re * re + im * im).sqrt();
            assert!(
                ((f.re - re).abs() + (f.im - im).abs()) < 1e-13 * m + 1e-15,
                "σ={s} k={k:?}: {f:?} vs {re} {im}"
            );
        }
        // The truncated Fourier series reproduces the value.
        let kmax = (7.0 / (std::f64::consts::PI * s)).ceil() as i32;
        for x in [[0.3, 0.85], [0.7, 0.2], [0.35, 0.8]] {
            let mut v = 0.0;
            for k0 in -kmax..=kmax {
                for k1 in -kmax..=kmax {
                    let f = g.fourier(&[k0, k1]);
                    let ph = std::f64::consts::TAU * (k0 as f64 * x[0] + k1 as f64 * x[1]);
                    v += f.re * ph.cos() - f.im * ph.sin();
                }
            }
            let val = g.value(&x);
            assert!(
                (v - val).abs() < 1e-13 * g.max_value(),
                "series σ={s} x={x:?}: {v} vs {val}"
            );
        }
    }
}

// ---------------------------------------------------------------------------
// f32 SIMD path
// ---------------------------------------------------------------------------

struct Batch<const D: usize> {
    o: [Vec<f32>; D],
    d: [Vec<f32>; D],
    t0: Vec<f32>,
    t1: Vec<f32>,
}

fn make_batch<const D: usize>(g: &Gaussian<D>, n: usize, seed: u64) -> Batch<D> {
    let mut st = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut rnd = || {
        st ^= st << 13;
        st ^= st >> 7;
        st ^= st << 17;
        (st >> 11) as f64 / (1u64 << 53) as f64
    };
    let s = g.sigma().min(2.0);
    let c = g.centre();
    let mut b = Batch {
        o: std::array::from_fn(|_| Vec::new()),
        d: std::array::from_fn(|_| Vec::new()),
        t0: vec![],
        t1: vec![],
    };
    for i in 0..n {
        let mut v = [0.0; D];
        let mut nn = 0.0;
        for j in 0..D {
            v[j] = rnd() * 2.0 - 1.0;
            nn += v[j] * v[j];
        }
        let nn = nn.sqrt().max(1e-3);
        for j in 0..D {
            b.o[j].push((c[j] + 4.0 * s * (rnd() * 2.0 - 1.0)) as f32);
            b.d[j].push((v[j] / nn) as f32);
        }
        let a = (rnd() * 10.0 - 5.0) * s;
        let l = rnd() * 6.0 * s;
        b.t0.push(if i % 11 == 3 {
            f32::NEG_INFINITY
        } else {
            a as f32
        });
        b.t1.push(if i % 7 == 2 {
            f32::INFINITY
        } else {
            (a + l) as f32
        });
    }
    b
}

fn rays<const D: usize>(b: &Batch<D>) -> Rays32<'_, D> {
    Rays32 {
        origin: std::array::from_fn(|j| &b.o[j][..]),
        dir: std::array::from_fn(|j| &b.d[j][..]),
        t0: &b.t0,
        t1: &b.t1,
    }
}

/// Error of the f32 path against f64 `segment_free`, in units of the stated
/// bound `P·(1e−6 + expm1(1e−6·E + 2e−7·κ·(1 + √(2E))))`.
fn f32_err<const D: usize>(
    g: &Gaussian<D>,
    o: [f32; D],
    d: [f32; D],
    t0: f32,
    t1: f32,
    got: f32,
) -> f64 {
    let o64: [f64; D] = std::array::from_fn(|j| f64::from(o[j]));
    let d64: [f64; D] = std::array::from_fn(|j| f64::from(d[j]));
    let nd = d64.iter().map(|x| x * x).sum::<f64>().sqrt();
    let dir = Direction::new(d64).unwrap();
    let want = g.segment_free(&o64, &dir, f64::from(t0) * nd, f64::from(t1) * nd) / nd;
    let c = g.centre();
    let s = g.sigma();
    let q: [f64; D] = std::array::from_fn(|j| o64[j] - c[j]);
    let qq: f64 = q.iter().map(|x| x * x).sum();
    let qd: f64 = (0..D).map(|j| q[j] * d64[j]).sum::<f64>() / nd;
    let rho2 = (qq - qd * qd).max(0.0);
    let e = rho2 / (2.0 * s * s);
    // P·(1e−6 + expm1(B)) as pre·(e^{B−E} − (1 − 1e−6)·e^{−E}), `pre = P·e^E`.
    let pre = norm(D, s) * s * (2.0 * std::f64::consts::PI).sqrt() / nd;
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
    (f64::from(got) - want).abs() / bound
}

#[test]
fn f32_batch_matches_scalar_and_f64() {
    let mut worst = 0.0f64;
    let mut worst_rel_peak = 0.0f64;
    for &s in &SIGMAS {
        let g2 = Gaussian::<2>::new([0.3, 0.6], s).unwrap();
        let g3 = Gaussian::<3>::new([0.3, 0.6, 0.9], s).unwrap();
        for n in (0..=17).chain([64, 203]) {
            let b = make_batch(&g3, n, n as u64 + 1);
            let mut out = vec![0.0f32; n];
            g3.segment_free_batch_f32(&rays(&b), &mut out).unwrap();
            for i in 0..n {
                let o = [b.o[0][i], b.o[1][i], b.o[2][i]];
                let d = [b.d[0][i], b.d[1][i], b.d[2][i]];
                let sc = g3.segment_free_f32(o, d, b.t0[i], b.t1[i]);
                assert_eq!(sc.to_bits(), out[i].to_bits(), "σ={s} n={n} i={i}");
                let e = f32_err(&g3, o, d, b.t0[i], b.t1[i], sc);
                assert!(
                    e <= 1.0,
                    "σ={s} f32 3d error {e} × bound at {o:?} {d:?} [{}, {}]",
                    b.t0[i],
                    b.t1[i]
                );
                worst = worst.max(e);
            }
            let b = make_batch(&g2, n, 1000 + n as u64);
            let mut out = vec![0.0f32; n];
            g2.segment_free_batch_f32(&rays(&b), &mut out).unwrap();
            for i in 0..n {
                let o = [b.o[0][i], b.o[1][i]];
                let d = [b.d[0][i], b.d[1][i]];
                let sc = g2.segment_free_f32(o, d, b.t0[i], b.t1[i]);
                assert_eq!(sc.to_bits(), out[i].to_bits(), "σ={s} n={n} i={i}");
                let e = f32_err(&g2, o, d, b.t0[i], b.t1[i], sc);
                assert!(e <= 1.0, "σ={s} f32 2d error {e} × bound");
                worst = worst.max(e);
            }
        }
        // Peak-relative error on well-conditioned rays (origin at the centre's
        // f32 image, unit axis direction, ends on the σ scale).
        let c = g2.centre();
        let o = [c[0] as f32, c[1] as f32];
        for (t0, t1) in [
            (-1.0f32, 1.0f32),
            (-0.3, 2.0),
            (0.5, 3.0),
            (f32::NEG_INFINITY, f32::INFINITY),
        ] {
            let (a, b) = (t0 * s as f32, t1 * s as f32);
            let got = f64::from(g2.segment_free_f32(o, [1.0, 0.0], a, b));
            let o64 = [f64::from(o[0]), f64::from(o[1])];
            let want = g2.segment_free(&o64, &unit([1.0, 0.0]), f64::from(a), f64::from(b));
            let peak = norm(2, s) * s * (2.0 * std::f64::consts::PI).sqrt();
            worst_rel_peak = worst_rel_peak.max((got - want).abs() / peak);
        }
    }
    println!("f32: max error / stated bound {worst:.3}; peak-relative error on σ-scale rays {worst_rel_peak:e}");
    assert!(worst_rel_peak < 1e-6);
}

// ---------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------

#[test]
fn bad_input_is_rejected() {
    assert_eq!(
        Gaussian::<2>::new([f64::NAN, 0.0], 0.1).unwrap_err(),
        ParamError::NonFinite { name: "centre" }
    );
    assert_eq!(
        Gaussian::<3>::new([0.0, f64::INFINITY, 0.0], 0.1).unwrap_err(),
        ParamError::NonFinite { name: "centre" }
    );
    assert_eq!(
        Gaussian::<2>::new([0.0, f64::NEG_INFINITY], 0.1).unwrap_err(),
        ParamError::NonFinite { name: "centre" }
    );
    for s in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(
            Gaussian::<2>::new([0.0, 0.0], s).unwrap_err(),
            ParamError::NonFinite { name: "sigma" }
        );
    }
    for s in [0.0, -1.0, 9.9e-7, 1.01e6] {
        match Gaussian::<2>::new([0.0, 0.0], s).unwrap_err() {
            ParamError::OutOfRange { name, .. } => assert_eq!(name, "sigma"),
            e => panic!("{e:?}"),
        }
    }
    assert!(Gaussian::<2>::new([0.0, 0.0], 1e-6).is_ok());
    assert!(Gaussian::<2>::new([0.0, 0.0], 1e6).is_ok());
    assert_eq!(
        Gaussian::<4>::new([0.0; 4], 0.1).unwrap_err(),
        ParamError::Dimension { dim: 4 }
    );
    assert_eq!(
        Gaussian::<1>::new([0.0], 0.1).unwrap_err(),
        ParamError::Dimension { dim: 1 }
    );
    let g = Gaussian::<2>::new([0.5, 0.5], 0.1).unwrap();
    let a = [0.0f32; 4];
    let b = [0.0f32; 3];
    let r = Rays32 {
        origin: [&a, &a],
        dir: [&a, &a],
        t0: &a,
        t1: &b,
    };
    let mut out = [0.0f32; 4];
    assert!(matches!(
        g.segment_free_batch_f32(&r, &mut out),
        Err(ParamError::Length { name: "t1", .. })
    ));
    let r = Rays32 {
        origin: [&a, &a],
        dir: [&a, &a],
        t0: &a,
        t1: &a,
    };
    let mut out3 = [0.0f32; 3];
    assert!(matches!(
        g.segment_free_batch_f32(&r, &mut out3),
        Err(ParamError::Length { name: "out", .. })
    ));
    // Release behaviour of the f32 path: no panic for non-finite input.
    let _ = g.segment_free_f32([f32::NAN, 0.0], [1.0, 0.0], 0.0, 1.0);
    let _ = g.segment_free_f32([0.0, 0.0], [0.0, 0.0], 0.0, 1.0);
    let v = g.segment_free_f32([0.5, 0.5], [1.0, 0.0], 1.0, -1.0);
    assert!(v < 0.0);
}

/// Throughput of the f32 batch against the f64 scalar path (informative; run
/// with `--ignored --nocapture`, ideally in release).
#[test]
#[ignore]
fn f32_throughput() {
    let g = Gaussian::<3>::new([0.3, 0.6, 0.9], 0.05).unwrap();
    let n = 4096;
    let b = make_batch(&g, n, 5);
    let mut out = vec![0.0f32; n];
    let reps = 200;
    let t = std::time::Instant::now();
    for _ in 0..reps {
        g.segment_free_batch_f32(&rays(&b), &mut out).unwrap();
        std::hint::black_box(&out);
    }
    let tf = t.elapsed().as_secs_f64() / (reps * n) as f64;
    let dirs: Vec<Direction<3>> = (0..n)
        .map(|i| {
            unit([
                f64::from(b.d[0][i]),
                f64::from(b.d[1][i]),
                f64::from(b.d[2][i]),
            ])
        })
        .collect();
    let t = std::time::Instant::now();
    let mut acc = 0.0;
    for _ in 0..reps {
        for i in 0..n {
            let p = [
                f64::from(b.o[0][i]),
                f64::from(b.o[1][i]),
                f64::from(b.o[2][i]),
            ];
            acc += g.segment_free(&p, &dirs[i], f64::from(b.t0[i]), f64::from(b.t1[i]));
        }
    }
    std::hint::black_box(acc);
    let td = t.elapsed().as_secs_f64() / (reps * n) as f64;
    println!(
        "f32 batch {:.2} ns/ray, f64 scalar {:.2} ns/ray, speed-up {:.1}×",
        tf * 1e9,
        td * 1e9,
        td / tf
    );
}

// ---------------------------------------------------------------------------
// Short segments against exact arithmetic
// ---------------------------------------------------------------------------

/// `e^{−E}` for an exact `E ≥ 0`: `E = hi + lo` split into doubles, then
/// `e^{−hi}(1 − lo)` (`|lo| ≤ ulp(hi)/2`, so the error is that of `exp`).
fn exp_neg_exact(e: &Dy) -> f64 {
    let hi = e.to_f64();
    let lo = e.sub(&Dy::f(hi)).to_f64();
    (-hi).exp() * (1.0 - lo)
}

/// `∫_{t0}^{t1} F(c + q + tω) dt` for the Gaussian at `c`, `q` exact: the
/// quadratic exponent `|q0 + sω|²/2σ²` (`q0 = q + t0ω`, `s = t − t0`) formed
/// exactly at every node and divided to 1400 bits, adaptive Gauss–Kronrod in
/// `s` over `[0, t1 − t0]`, the common factor `e^{−E(s_m)}` of the point
/// `s_m` of the segment nearest the centre taken out of the integrand (so
/// the quadrature sees values near 1 and the far tail keeps its relative
/// accuracy).
fn exact_gauss_seg<const D: usize>(q: &[Dy; D], w: &[f64; D], sigma: f64, t0: f64, t1: f64) -> f64 {
    let wd: [Dy; D] = core::array::from_fn(|j| Dy::f(w[j]));
    let t0d = Dy::f(t0);
    let q0: [Dy; D] = core::array::from_fn(|j| q[j].add(&t0d.mul(&wd[j])));
    let s2 = Dy::f(sigma).mul(&Dy::f(sigma));
    let two_s2 = s2.add(&s2);
    let len = Dy::f(t1).sub(&t0d).to_f64();
    let e_at = |s: f64| -> Dy {
        let sd = Dy::f(s);
        let x: [Dy; D] = core::array::from_fn(|j| q0[j].add(&sd.mul(&wd[j])));
        exact::dot(&x, &x).div(&two_s2)
    };
    // Nearest point: s_m = clamp(−q0·ω/|ω|², 0, len) (any nearby point will do).
    let a = exact::dot(&wd, &wd);
    let sm = exact::dot(&q0, &wd).neg().div(&a).to_f64().clamp(0.0, len);
    let em = e_at(sm);
    let f = |s: f64| exp_neg_exact(&e_at(s).sub(&em));
    let sc = sigma / a.to_f64().sqrt();
    // Break points every σ around the nearest point help the adaptive rule.
    let mut br = vec![0.0, len];
    for k in -12..=12 {
        let b = sm + k as f64 * sc;
        if b > 0.0 && b < len {
            br.push(b);
        }
    }
    br.sort_by(f64::total_cmp);
    let mut i = 0.0;
    for k in 0..br.len() - 1 {
        i += integrate(f, br[k], br[k + 1], 1e-15);
    }
    norm(D, sigma) * i * exp_neg_exact(&em)
}

/// Short free-space and wrapped segments (`λ = σ·10^{−U(0,15)}`, down to
/// `10⁻²¹` at `σ = 10⁻⁶`): near the centre, straddling or ending at the foot
/// point, up to `6σ` off the line, seen from up to `10³` away; wrapped ones
/// centred on a cell face (`x_0 ∈ {0, ±10⁻¹⁷, 1, −1 + 10⁻¹⁷, 10³}`) next to a
/// Gaussian centred within `3σ` of it. Each against [`exact_gauss_seg`]
/// (summed over the images within `12σ` for wrapped ones) at `1e−13`
/// relative. Returns the worst (free, wrapped) relative error.
fn short_gauss_cases<const D: usize>(seed: u64, n: usize) -> (f64, f64) {
    let mut g = Mix(seed);
    let (mut worst_free, mut worst_torus) = (0.0f64, 0.0f64);
    for i in 0..n {
        // σ ≤ 0.1 keeps the wrapped references' image sums small (σ in
        // (0.1, 0.3] and the Fourier path above are covered by the tests
        // above).
        let sigma = 10f64.powf(g.range(-6.0, -1.0));
        let dir = Direction::new(g.unit::<D>()).unwrap();
        let w = dir.get();
        let len = sigma * 10f64.powf(-g.range(0.0, 15.0));
        let wrapped = i % 2 == 1;
        let mut c: [f64; D] = core::array::from_fn(|_| g.f());
        if wrapped {
            c[0] = g.range(-3.0, 3.0) * sigma;
        }
        let gs = Gaussian::<D>::new(c, sigma).unwrap();
        let c = gs.centre();
        // A point at up to 6σ from the centre, then the segment around it.
        let off: [f64; D] = g.unit();
        let d = g.range(0.0, 6.0) * sigma;
        let mut x: [f64; D] = core::array::from_fn(|j| c[j] + d * off[j]);
        if wrapped {
            x[0] = match g.below(6) {
                0 => 0.0,
                1 => -1e-17,
                2 => 1e-17,
                3 => 1.0,
                4 => -1.0 + 1e-17,
                _ => 1e3,
            };
            let seg = Segment::new(x, dir, len).unwrap();
            let got = gs.segment_integral(&seg);
            let (s, l) = (seg.centre(), seg.length());
            // Every image within 12σ + λ of the segment centre (farther ones
            // contribute < e^{−72} of the nearest).
            let reach = 12.0 * sigma + l;
            let lo: [i64; D] = core::array::from_fn(|j| (s[j] - c[j] - reach).floor() as i64);
            let hi: [i64; D] = core::array::from_fn(|j| (s[j] - c[j] + reach).ceil() as i64);
            let mut want = 0.0;
            let mut m = lo;
            'images: loop {
                let q: [Dy; D] = core::array::from_fn(|j| {
                    Dy::f(s[j]).sub(&Dy::f(c[j])).sub(&Dy::f(m[j] as f64))
                });
                let qf: [f64; D] = core::array::from_fn(|j| q[j].to_f64());
                if qf.iter().map(|v| v * v).sum::<f64>().sqrt() < reach {
                    want += exact_gauss_seg(&q, &w, sigma, -0.5 * l, 0.5 * l);
                }
                let mut j = 0;
                loop {
                    if j == D {
                        break 'images;
                    }
                    m[j] += 1;
                    if m[j] <= hi[j] {
                        break;
                    }
                    m[j] = lo[j];
                    j += 1;
                }
            }
            let err = rel_err(got, want);
            assert!(err <= 1e-13, "wrapped σ={sigma:e} c={c:?} s={s:?} w={w:?} λ={l:e}: {got:e} vs {want:e} ({err:e})");
            worst_torus = worst_torus.max(err);
        } else {
            // Straddling the foot of x, ending there, or starting there, seen
            // from the point itself or from up to 10³ away.
            let reach = if g.below(2) == 0 {
                0.0
            } else {
                10f64.powf(g.range(-3.0, 3.0))
            };
            let p: [f64; D] = core::array::from_fn(|j| x[j] - reach * w[j]);
            let (t0, t1) = match g.below(3) {
                0 => (reach - g.f() * len, 0.0),
                1 => (reach, reach + len),
                _ => (reach - len, reach),
            };
            let t1 = if t1 == 0.0 { t0 + len } else { t1 };
            let got = gs.segment_free(&p, &dir, t0, t1);
            let q: [Dy; D] = core::array::from_fn(|j| Dy::f(p[j]).sub(&Dy::f(c[j])));
            let want = exact_gauss_seg(&q, &w, sigma, t0, t1);
            let err = rel_err(got, want);
            assert!(err <= 1e-13, "free σ={sigma:e} c={c:?} p={p:?} w={w:?} [{t0:e}, {t1:e}]: {got:e} vs {want:e} ({err:e})");
            worst_free = worst_free.max(err);
        }
    }
    (worst_free, worst_torus)
}

#[test]
fn short_segments_against_exact_arithmetic() {
    let (f2, t2) = short_gauss_cases::<2>(0x6a55_0002, 2000);
    let (f3, t3) = short_gauss_cases::<3>(0x6a55_0003, 2000);
    eprintln!("short Gaussian segments: worst relative error free 2D {f2:.2e}, 3D {f3:.2e}; wrapped 2D {t2:.2e}, 3D {t3:.2e}");
}

/// The Fourier path (`σ > 0.3`) on very short wrapped segments,
/// `λ = σ·10^{−U(8,15)}`, centred on or next to a cell face, against
/// `λ·f(c_s)` with `f(c_s)` the image sum over `|c_s − c − n| < 12σ` with
/// exact exponents: the midpoint rule's error is `λ³·max|f''|/24`, below
/// `λ²(1 + 2·72)/(24σ²) ≤ 7e−16` relative here. Asserted at `1e−13`
/// relative; returns the worst.
fn short_fourier_cases<const D: usize>(seed: u64, n: usize) -> f64 {
    let mut g = Mix(seed);
    let mut worst = 0.0f64;
    for _ in 0..n {
        let sigma = g.range(0.3, 0.6);
        let c: [f64; D] = core::array::from_fn(|_| g.f());
        let gs = Gaussian::<D>::new(c, sigma).unwrap();
        let c = gs.centre();
        let mut s: [f64; D] = core::array::from_fn(|_| g.f());
        s[0] = match g.below(4) {
            0 => 0.0,
            1 => -1e-17,
            2 => 1.0,
            _ => 1e3,
        };
        let dir = Direction::new(g.unit::<D>()).unwrap();
        let len = sigma * 10f64.powf(-g.range(8.0, 15.0));
        let seg = Segment::new(s, dir, len).unwrap();
        let got = gs.segment_integral(&seg);
        let s = seg.centre();
        let reach = 12.0 * sigma;
        let lo: [i64; D] = core::array::from_fn(|j| (s[j] - c[j] - reach).floor() as i64);
        let hi: [i64; D] = core::array::from_fn(|j| (s[j] - c[j] + reach).ceil() as i64);
        let s2 = Dy::f(sigma).mul(&Dy::f(sigma));
        let two_s2 = s2.add(&s2);
        let mut f = 0.0;
        let mut m = lo;
        'images: loop {
            let q: [Dy; D] =
                core::array::from_fn(|j| Dy::f(s[j]).sub(&Dy::f(c[j])).sub(&Dy::f(m[j] as f64)));
            let e = exact::dot(&q, &q).div(&two_s2);
            if e.to_f64() < 72.0 {
                f += exp_neg_exact(&e);
            }
            let mut j = 0;
            loop {
                if j == D {
                    break 'images;
                }
                m[j] += 1;
                if m[j] <= hi[j] {
                    break;
                }
                m[j] = lo[j];
                j += 1;
            }
        }
        let want = seg.length() * norm(D, sigma) * f;
        let err = rel_err(got, want);
        assert!(
            err <= 1e-13,
            "Fourier path σ={sigma} c={c:?} s={s:?} λ={len:e}: {got:e} vs {want:e} ({err:e})"
        );
        worst = worst.max(err);
    }
    worst
}

#[test]
fn short_segments_fourier_path_against_exact_image_sums() {
    let w2 = short_fourier_cases::<2>(0xf0_0002, 300);
    let w3 = short_fourier_cases::<3>(0xf0_0003, 60);
    eprintln!("short wrapped Gaussian segments, σ ∈ [0.3, 0.6) (Fourier path): worst relative error 2D {w2:.2e}, 3D {w3:.2e}");
}
