//! Tests of the Gaussian integrand against independent references: adaptive
//! Gauss–Kronrod quadrature of the density (with the exponent taken relative to
//! the point of the segment nearest to the centre, in double-double, so the
//! reference keeps relative accuracy in the far tail), brute-force image sums,
//! and high-precision constants computed offline with mpmath (50 digits).

mod common;

use common::{integrate, rel_err};
use linesample::geom::dd::Dd;
use linesample::geom::Direction;
use linesample::integrand::{Gaussian, Integrand};
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
                let emin = es.iter().fold(Dd::new(f64::INFINITY), |a, e| if e.hi < a.hi { *e } else { a });
                let sum: f64 = es.iter().map(|e| (-(e.sub(emin)).to_f64()).exp()).sum();
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
    if s >= 3.0 {
        return len;
    }
    let r2 = D as f64 / 4.0 + 120.0 * s * s;
    let r = r2.sqrt();
    let mut lo = [0i64; D];
    let mut hi = [0i64; D];
    for j in 0..D {
        let a = cs[j] - 0.5 * len * w[j] - c[j];
        let b = cs[j] + 0.5 * len * w[j] - c[j];
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
        let t = vw.clamp(-0.5 * len, 0.5 * len);
        let d2: f64 = (0..D).map(|j| (v[j] - t * w[j]).powi(2)).sum();
        if d2 <= r2 {
            let mf: [f64; D] = std::array::from_fn(|j| m[j] as f64);
            sum += ref_free(c, s, cs, &mf, w, -0.5 * len, 0.5 * len);
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
    assert!(e <= tol, "{what}: got {got:e}, want {want:e}, rel err {e:e}");
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

fn seg_case<const D: usize>(g: &Gaussian<D>, p: [f64; D], w: [f64; D], t0: f64, t1: f64, tol: f64) -> f64 {
    let dir = unit(w);
    let got = g.segment_free(&p, &dir, t0, t1);
    let want = ref_free(&g.centre(), g.sigma(), &p, &[0.0; D], &dir.get(), t0, t1);
    check(got, want, tol, &format!("σ={} c={:?} p={p:?} ω={:?} [{t0:e}, {t1:e}]", g.sigma(), g.centre(), dir.get()))
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
