//! HalfSpace integrand: closed forms against independent references written
//! here (breakpoint sorting with midpoint classification, a cell enumeration by
//! sorted face crossings, Gauss–Kronrod over exact cross-sections, nested
//! Gauss–Kronrod Fourier integrals, double-double inclusion–exclusion).
#![allow(clippy::needless_range_loop)]
mod common;
mod exact;

use common::{gk15, integrate};
use exact::{rel_err_exact, Dy, Mix};

/// Adaptive G7–K15 with an absolute tolerance per unit length (whole panel vs
/// its two halves), for oscillatory integrands whose panels may cancel to ~0.
fn gk_abs(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let mut g = |x: f64| f(x);
    let mut stack = vec![(a, b, gk15(&mut g, a, b).0, 0u32)];
    let mut sum = 0.0;
    while let Some((lo, hi, whole, depth)) = stack.pop() {
        let mid = 0.5 * (lo + hi);
        let l = gk15(&mut g, lo, mid).0;
        let r = gk15(&mut g, mid, hi).0;
        if (l + r - whole).abs() <= tol * (hi - lo) || depth >= 30 {
            sum += l + r;
        } else {
            stack.push((lo, mid, l, depth + 1));
            stack.push((mid, hi, r, depth + 1));
        }
    }
    sum
}
use linesample::geom::Direction;
use linesample::integrand::{Complex, HalfSpace, Integrand};
use linesample::num::Dd;
use linesample::primitive::{Line, Rays32, Segment};
use linesample::ParamError;
use proptest::prelude::*;
use std::cell::Cell;

const EPS: f64 = f64::EPSILON;

// ---------------------------------------------------------------------------
// References.

fn dd_dot<const D: usize>(a: &[f64; D], b: &[f64; D]) -> Dd {
    let mut s = Dd::new(0.0);
    for j in 0..D {
        s = s.add(Dd::prod(a[j], b[j]));
    }
    s
}

/// `a / b` in double-double (one Newton correction).
fn dd_div(a: Dd, b: Dd) -> f64 {
    let q = a.hi / b.hi;
    let r = a.sub(b.mul(Dd::new(q)));
    q + r.hi / b.hi
}

/// `a / b` as a double-double number.
fn dd_quot(a: Dd, b: Dd) -> Dd {
    let q = a.hi / b.hi;
    let r = a.sub(b.mul(Dd::new(q)));
    Dd::new(q).add(Dd::new(r.hi / b.hi))
}

/// Length of `{t ∈ [t0, t1] : p + tω ∈ [0,1)^D, n·(p + tω) ≥ h}` by sorting every
/// candidate breakpoint (double-double) and classifying the midpoint of each
/// sub-interval in double-double; lengths summed in double-double.
fn ref_len<const D: usize>(
    n: &[f64; D],
    h: f64,
    p: &[f64; D],
    w: &[f64; D],
    t0: f64,
    t1: f64,
) -> f64 {
    let mut ts: Vec<Dd> = vec![];
    for t in [t0, t1] {
        if t.is_finite() {
            ts.push(Dd::new(t));
        }
    }
    for j in 0..D {
        if w[j] != 0.0 {
            for b in [0.0, 1.0] {
                ts.push(dd_quot(Dd::new(b).sub(Dd::new(p[j])), Dd::new(w[j])));
            }
        }
    }
    let g0 = dd_dot(n, p).sub(Dd::new(h));
    let c = dd_dot(n, w);
    if c.hi != 0.0 {
        ts.push(dd_quot(g0.neg(), c));
    }
    ts.retain(|t| {
        t.hi.is_finite()
            && (t0 == f64::NEG_INFINITY || t.sub(Dd::new(t0)).hi >= 0.0)
            && (t1 == f64::INFINITY || t.sub(Dd::new(t1)).hi <= 0.0)
    });
    ts.sort_by(|a, b| a.hi.total_cmp(&b.hi).then(a.lo.total_cmp(&b.lo)));
    let mut sum = Dd::new(0.0);
    for k in 1..ts.len() {
        let (a, b) = (ts[k - 1], ts[k]);
        let len = b.sub(a);
        if len.hi <= 0.0 {
            continue;
        }
        let mid = a.add(len.mul(Dd::new(0.5)));
        let mut inside = true;
        for j in 0..D {
            let x = Dd::new(p[j]).add(mid.mul(Dd::new(w[j])));
            if w[j] == 0.0 {
                inside &= p[j] >= 0.0 && p[j] < 1.0;
            } else {
                inside &= x.hi >= 0.0 && x.sub(Dd::new(1.0)).hi <= 0.0;
            }
        }
        let g = g0.add(c.mul(mid));
        if inside && g.hi >= 0.0 {
            sum = sum.add(len);
        }
    }
    sum.hi
}

/// Torus segment integral: sub-intervals between the sorted face crossings of
/// the unwrapped segment, the cell of each from its midpoint, the image `F(x − m)`
/// integrated by midpoint classification around the cell's own edge crossing.
fn ref_torus<const D: usize>(hs: &HalfSpace<D>, c: &[f64; D], w: &[f64; D], lambda: f64) -> f64 {
    let n = hs.normal().get();
    let h = hs.offset();
    let (lo, hi) = (-0.5 * lambda, 0.5 * lambda);
    let mut ts = vec![lo, hi];
    for j in 0..D {
        if w[j] != 0.0 {
            let (x0, x1) = (c[j] + lo * w[j], c[j] + hi * w[j]);
            let (a, b) = (x0.min(x1).ceil() as i64, x0.max(x1).floor() as i64);
            for i in a..=b {
                ts.push(dd_div(Dd::new(i as f64).sub(Dd::new(c[j])), Dd::new(w[j])));
            }
        }
    }
    ts.retain(|t| *t >= lo && *t <= hi);
    ts.sort_by(f64::total_cmp);
    let mut sum = 0.0;
    let mut comp = 0.0;
    for k in 1..ts.len() {
        let (a, b) = (ts[k - 1], ts[k]);
        if b <= a {
            continue;
        }
        let mid = a + 0.5 * (b - a);
        let m: [f64; D] = core::array::from_fn(|j| (c[j] + mid * w[j]).floor());
        let q: [f64; D] = core::array::from_fn(|j| c[j] - m[j]);
        // Within the cell only the edge matters: F(x − m) = 1[n·(q + tω) ≥ h].
        let g0 = dd_dot(&n, &q).sub(Dd::new(h));
        let cc = dd_dot(&n, w);
        let mut cuts = vec![a, b];
        if cc.hi != 0.0 {
            let t = dd_div(g0.neg(), cc);
            if t > a && t < b {
                cuts.push(t);
            }
        }
        cuts.sort_by(f64::total_cmp);
        for z in 1..cuts.len() {
            let (u, v) = (cuts[z - 1], cuts[z]);
            let md = u + 0.5 * (v - u);
            if g0.add(cc.mul(Dd::new(md))).hi >= 0.0 {
                let x = v - u;
                let t = sum + x;
                comp += if sum.abs() >= x.abs() {
                    (sum - t) + x
                } else {
                    (x - t) + sum
                };
                sum = t;
            }
        }
    }
    sum + comp
}

/// Standard form of the test: `m_j = |n_j|`, `s = Σ_{n_j>0} n_j − h` (double-double).
fn std_form<const D: usize>(n: &[f64; D], h: f64) -> ([f64; D], Dd) {
    let mut s = Dd::new(-h);
    for j in 0..D {
        if n[j] > 0.0 {
            s = s.add(Dd::new(n[j]));
        }
    }
    (n.map(f64::abs), s)
}

/// Exact length of `{y ∈ [0,1] : a·y ≤ r}`, `a ≥ 0`, `r` double-double.
fn len1(a: f64, r: Dd) -> f64 {
    if a == 0.0 {
        return if r.hi >= 0.0 { 1.0 } else { 0.0 };
    }
    (r.hi / a).clamp(0.0, 1.0)
}

/// GK over the kinks of a piecewise-polynomial function on [0, 1].
fn gk_pieces(f: impl Fn(f64) -> f64, mut kinks: Vec<f64>) -> f64 {
    kinks.push(0.0);
    kinks.push(1.0);
    kinks.retain(|x| x.is_finite());
    for k in kinks.iter_mut() {
        *k = k.clamp(0.0, 1.0);
    }
    kinks.sort_by(f64::total_cmp);
    kinks.dedup();
    // One G7–K15 panel per polynomial piece (exact up to degree 22).
    let mut g = |x: f64| f(x);
    kinks.windows(2).map(|w| gk15(&mut g, w[0], w[1]).0).sum()
}

/// Volume by GK over axis 0 (outer) and axis 1 (inner) of the exact section
/// lengths along the last axis, in the reflected coordinates (so small regions
/// sit at the origin).
fn ref_volume<const D: usize>(n: &[f64; D], h: f64) -> f64 {
    let (m, s) = std_form(n, h);
    if D == 2 {
        let f = |x: f64| len1(m[1], s.sub(Dd::prod(m[0], x)));
        let kinks = if m[0] > 0.0 {
            vec![s.hi / m[0], s.sub(Dd::new(m[1])).hi / m[0]]
        } else {
            vec![]
        };
        gk_pieces(f, kinks)
    } else {
        let area = |x: f64| {
            let r = s.sub(Dd::prod(m[0], x));
            let f = |y: f64| len1(m[2], r.sub(Dd::prod(m[1], y)));
            let kinks = if m[1] > 0.0 {
                vec![r.hi / m[1], r.sub(Dd::new(m[2])).hi / m[1]]
            } else {
                vec![]
            };
            gk_pieces(f, kinks)
        };
        let mut kinks = vec![];
        if m[0] > 0.0 {
            for (a, b) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                kinks.push(s.sub(Dd::new(a * m[1])).sub(Dd::new(b * m[2])).hi / m[0]);
            }
        }
        gk_pieces(area, kinks)
    }
}

/// Inclusion–exclusion `Σ_v (−1)^{|v|} max(0, s − m·v)^D / (D! Π m_j)` in
/// double-double (valid only for `m_j` well away from 0).
fn ref_volume_ie<const D: usize>(n: &[f64; D], h: f64) -> f64 {
    let (m, s) = std_form(n, h);
    let mut acc = Dd::new(0.0);
    for bits in 0..(1u32 << D) {
        let mut r = s;
        let mut sign = 1.0;
        for j in 0..D {
            if bits >> j & 1 == 1 {
                r = r.sub(Dd::new(m[j]));
                sign = -sign;
            }
        }
        if r.hi > 0.0 {
            let mut p = Dd::new(1.0);
            for _ in 0..D {
                p = p.mul(r);
            }
            acc = acc.add(if sign > 0.0 { p } else { p.neg() });
        }
    }
    let mut den = if D == 2 { 2.0 } else { 6.0 };
    for j in 0..D {
        den *= m[j];
    }
    acc.hi / den
}

/// `∫_lo^hi e^{−2πi k x} dx`.
fn exp_int(k: f64, lo: f64, hi: f64) -> (f64, f64) {
    if hi <= lo {
        return (0.0, 0.0);
    }
    if k == 0.0 {
        return (hi - lo, 0.0);
    }
    let tau = 2.0 * std::f64::consts::PI;
    // (e^{−iτk·lo} − e^{−iτk·hi}) / (iτk)
    let (a, b) = (tau * k * lo, tau * k * hi);
    let re = (a.cos() - b.cos(), -a.sin() + b.sin());
    // divide by i·τk: (x + iy)/(iK) = (y − ix)/K
    (re.1 / (tau * k), -re.0 / (tau * k))
}

/// Fourier coefficient by nested adaptive GK in the original coordinates: inner
/// integral along the axis with the largest |n_j| in closed form over the clipped
/// interval, the outer ones by GK with breakpoints at the kinks.
fn ref_fourier<const D: usize>(n: &[f64; D], h: f64, k: &[i32; D], rel: f64) -> Complex {
    let l = (0..D)
        .max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap();
    let others: Vec<usize> = (0..D).filter(|&j| j != l).collect();
    let tau = 2.0 * std::f64::consts::PI;
    // Inner: x_l ∈ [0,1] with n_l x_l ≥ h − Σ n_o x_o.
    let inner = |xo: &[f64]| -> (f64, f64) {
        let mut r = Dd::new(h);
        let mut ph = 0.0;
        for (i, &o) in others.iter().enumerate() {
            r = r.sub(Dd::prod(n[o], xo[i]));
            ph += k[o] as f64 * xo[i];
        }
        let r = r.hi / n[l];
        let (lo, hi) = if n[l] > 0.0 {
            (r.max(0.0), 1.0)
        } else {
            (0.0, r.min(1.0))
        };
        let (a, b) = exp_int(k[l] as f64, lo, hi);
        let (c, s) = ((tau * ph).cos(), -(tau * ph).sin());
        (a * c - b * s, a * s + b * c)
    };
    let kinks_for = |fixed: f64, idx: usize| -> Vec<f64> {
        // Values of x_{others[idx]} where r hits 0 or 1 (the other outer
        // coordinate, if any, fixed at `fixed` for the middle level, or at the
        // box corners for the outer level).
        let o = others[idx];
        let mut v = vec![];
        if n[o] == 0.0 {
            return v;
        }
        if D == 2 {
            for c in [0.0, 1.0] {
                v.push((h - n[l] * c) / n[o]);
            }
        } else if idx == 1 {
            let p = others[0];
            for c in [0.0, 1.0] {
                v.push((h - n[l] * c - n[p] * fixed) / n[o]);
            }
        } else {
            let q = others[1];
            for c in [0.0, 1.0] {
                for e in [0.0, 1.0] {
                    v.push((h - n[l] * c - n[q] * e) / n[o]);
                }
            }
        }
        v
    };
    let part = |f: &dyn Fn(f64) -> f64, kinks: Vec<f64>| -> f64 {
        let mut ks = kinks;
        ks.push(0.0);
        ks.push(1.0);
        ks.retain(|x| x.is_finite());
        for x in ks.iter_mut() {
            *x = x.clamp(0.0, 1.0);
        }
        ks.sort_by(f64::total_cmp);
        ks.dedup();
        ks.windows(2).map(|w| gk_abs(f, w[0], w[1], rel)).sum()
    };
    if D == 2 {
        let re = part(&|x| inner(&[x]).0, kinks_for(0.0, 0));
        let im = part(&|x| inner(&[x]).1, kinks_for(0.0, 0));
        Complex { re, im }
    } else {
        let mid = |x: f64, c: usize| -> f64 {
            part(
                &|y| {
                    let v = inner(&[x, y]);
                    if c == 0 {
                        v.0
                    } else {
                        v.1
                    }
                },
                kinks_for(x, 1),
            )
        };
        let re = part(&|x| mid(x, 0), kinks_for(0.0, 0));
        let im = part(&|x| mid(x, 1), kinks_for(0.0, 0));
        Complex { re, im }
    }
}

// ---------------------------------------------------------------------------
// Hard cases.

fn hard_normals2() -> Vec<[f64; 2]> {
    vec![
        [1.0, 0.0],
        [0.0, 1.0],
        [-1.0, 0.0],
        [0.0, -1.0],
        [1.0, 1e-15],
        [1e-9, 1.0],
        [1.0, -1e-9],
        [-1e-15, -1.0],
        [1.0, 1.0],
        [1.0, -1.0],
        [0.3, 0.7],
        [-0.8, 0.2],
    ]
}

fn hard_normals3() -> Vec<[f64; 3]> {
    vec![
        [1.0, 0.0, 0.0],
        [0.0, 0.0, -1.0],
        [1.0, 1e-15, 1e-9],
        [1e-9, -1e-15, 1.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, -1.0],
        [1.0, 1.0, 1.0],
        [1.0, -1.0, 1e-15],
        [0.2, -0.5, 0.9],
        [-0.3, 0.6, 0.1],
        [1e-9, 1.0, 1.0],
    ]
}

/// Offsets: every vertex value (plane through a vertex / along an edge), and
/// values just above and below, midpoints, and outside the range.
fn hard_offsets<const D: usize>(n: &[f64; D]) -> Vec<f64> {
    let mut vals = vec![];
    for bits in 0..(1u32 << D) {
        let v: [f64; D] = core::array::from_fn(|j| (bits >> j & 1) as f64);
        vals.push(dd_dot(n, &v).hi);
    }
    let (mn, mx) = vals
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    let mut out = vals.clone();
    for &v in &vals {
        for d in [1e-12, 1e-6, 0.1] {
            out.push(v + d);
            out.push(v - d);
        }
    }
    out.extend([0.5 * (mn + mx), mn - 1.0, mx + 1.0, mn + 0.3 * (mx - mn)]);
    out
}

fn dir<const D: usize>(v: [f64; D]) -> Direction<D> {
    Direction::new(v).unwrap()
}

fn cabs(a: Complex, b: Complex) -> f64 {
    ((a.re - b.re).powi(2) + (a.im - b.im).powi(2)).sqrt()
}

// ---------------------------------------------------------------------------
// Volume.

fn check_volume<const D: usize>(n: [f64; D], h: f64, worst: &Cell<f64>) {
    let hs = HalfSpace::new(dir(n), h).unwrap();
    let nn = hs.normal().get();
    let v = hs.integral();
    let r = ref_volume(&nn, h);
    let err = if r == 0.0 {
        v.abs()
    } else {
        ((v - r) / r).abs()
    };
    assert!(
        err <= 1e-13,
        "volume n={n:?} h={h}: {v} vs {r} (rel {err:e})"
    );
    assert!((0.0..=1.0).contains(&v));
    worst.set(worst.get().max(err));
    if nn.iter().all(|x| x.abs() > 0.1) {
        let ie = ref_volume_ie(&nn, h);
        let e2 = if ie == 0.0 {
            v.abs()
        } else {
            ((v - ie) / ie).abs()
        };
        assert!(e2 <= 1e-13, "volume vs IE n={n:?} h={h}: {v} vs {ie}");
    }
}

#[test]
fn volume_hard_cases() {
    let worst = Cell::new(0.0);
    for n in hard_normals2() {
        let d = dir(n).get();
        for h in hard_offsets(&d) {
            check_volume(n, h, &worst);
        }
    }
    for n in hard_normals3() {
        let d = dir(n).get();
        for h in hard_offsets(&d) {
            check_volume(n, h, &worst);
        }
    }
    // Exact values.
    let e = HalfSpace::new(dir([1.0, 0.0]), 0.25).unwrap();
    assert_eq!(e.integral(), 0.75);
    let e = HalfSpace::new(dir([0.0, 0.0, -1.0]), -0.5).unwrap();
    assert_eq!(e.integral(), 0.5);
    let e = HalfSpace::new(dir([1.0, 1.0, 1.0]), 3f64.sqrt() / 2.0).unwrap();
    assert!((e.integral() - 0.5).abs() < 1e-15);
    // Tiny corner region: s = 1e-12 at the corner (1,1,1): s³/(6 m1 m2 m3).
    let n = dir([1.0, 1.0, 1.0]).get();
    let h = dd_dot(&n, &[1.0; 3]).sub(Dd::new(1e-12)).hi;
    let (_, s) = std_form(&n, h);
    let exact = s.hi.powi(3) / (6.0 * n[0] * n[1] * n[2]);
    let v = HalfSpace::new(dir([1.0, 1.0, 1.0]), h).unwrap().integral();
    assert!(((v - exact) / exact).abs() < 1e-14, "{v} {exact}");
    println!("volume hard cases: max rel err {:e}", worst.get());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    #[test]
    fn volume_random_2d(a in -1.0f64..1.0, b in -1.0f64..1.0, u in -0.1f64..1.1) {
        prop_assume!(a.abs() + b.abs() > 1e-3);
        let n = dir([a, b]).get();
        let (lo, hi) = (n[0].min(0.0) + n[1].min(0.0), n[0].max(0.0) + n[1].max(0.0));
        let worst = Cell::new(0.0);
        check_volume([a, b], lo + u * (hi - lo), &worst);
    }

    #[test]
    fn volume_random_3d(a in -1.0f64..1.0, b in -1.0f64..1.0, c in -1.0f64..1.0, u in -0.1f64..1.1) {
        prop_assume!(a.abs() + b.abs() + c.abs() > 1e-3);
        let n = dir([a, b, c]).get();
        let lo: f64 = n.iter().map(|x| x.min(0.0)).sum();
        let hi: f64 = n.iter().map(|x| x.max(0.0)).sum();
        let worst = Cell::new(0.0);
        check_volume([a, b, c], lo + u * (hi - lo), &worst);
    }
}

// ---------------------------------------------------------------------------
// Segments.

fn check_seg<const D: usize>(
    hs: &HalfSpace<D>,
    p: [f64; D],
    w: Direction<D>,
    t0: f64,
    t1: f64,
    worst: &Cell<f64>,
) {
    let n = hs.normal().get();
    let got = hs.segment_free(&p, &w, t0, t1);
    let r = ref_len(&n, hs.offset(), &p, &w.get(), t0, t1);
    // Documented bound: ε·len + 8ε²·(|lo| + |hi| + (Σ|n_j p_j| + |h|)/|n·ω|),
    // with |lo|, |hi| bounded by the box chord parameters (doubled for slack).
    let bound = |x: f64| if x.is_finite() { x.abs() } else { 0.0 };
    let mut scale = 0.0f64;
    for j in 0..D {
        if w.get()[j] != 0.0 {
            scale = scale.max((p[j].abs() + 1.0) / w.get()[j].abs());
        }
    }
    let c = dd_dot(&n, &w.get()).hi.abs();
    let np: f64 = (0..D).map(|j| (n[j] * p[j]).abs()).sum::<f64>() + hs.offset().abs();
    let cond = if c > 0.0 { np / c } else { 0.0 };
    let tol = 2.0 * EPS * r
        + 16.0 * EPS * EPS * (bound(t0).min(scale) + bound(t1).min(scale) + scale + cond)
        + 1e-300;
    let err = (got - r).abs();
    assert!(
        err <= tol,
        "segment n={n:?} h={} p={p:?} w={:?} [{t0},{t1}]: {got} vs {r}",
        hs.offset(),
        w.get()
    );
    if r > 1e-3 {
        worst.set(worst.get().max(err / r));
    }
}

#[test]
fn segments_hard_cases_2d() {
    let worst = Cell::new(0.0);
    for n in hard_normals2() {
        let d = dir(n).get();
        for h in hard_offsets(&d) {
            let hs = HalfSpace::new(dir(n), h).unwrap();
            // Directions: along the edge (ω ⟂ n), the normal, axes, oblique.
            let dirs = [
                dir([-d[1], d[0]]),
                dir(d),
                dir([1.0, 0.0]),
                dir([0.0, -1.0]),
                dir([0.6, -0.8]),
                dir([1.0, 1e-12]),
            ];
            for w in dirs {
                for p in [
                    [0.5, 0.5],
                    [0.0, 0.0],
                    [1.0, 1.0],
                    [0.0, 0.7],
                    [1.0, 0.25],
                    [-0.3, 1.2],
                    [0.999999, 1e-9],
                ] {
                    for (t0, t1) in [
                        (-0.5, 0.5),
                        (0.0, 0.0),
                        (-f64::INFINITY, f64::INFINITY),
                        (0.1, 3.0),
                        (-2.0, -0.1),
                        (-1e-9, 1e-9),
                    ] {
                        check_seg(&hs, p, w, t0, t1, &worst);
                    }
                }
            }
            // Points on the edge plane, parallel lines just above and below.
            let q = [d[0] * h, d[1] * h];
            let along = dir([-d[1], d[0]]);
            for off in [0.0, 1e-12, -1e-12, 1e-3, -1e-3] {
                let p = [q[0] + off * d[0], q[1] + off * d[1]];
                check_seg(&hs, p, along, f64::NEG_INFINITY, f64::INFINITY, &worst);
            }
        }
    }
    // Exactly on the edge, parallel: the closed half-space keeps the line.
    let hs = HalfSpace::new(dir([1.0, 0.0]), 0.5).unwrap();
    let ax = dir([0.0, 1.0]);
    assert_eq!(hs.segment_free(&[0.5, 0.2], &ax, -10.0, 10.0), 1.0);
    assert_eq!(hs.segment_free(&[0.5 - 1e-16, 0.2], &ax, -10.0, 10.0), 0.0);
    assert_eq!(hs.segment_free(&[0.5, 0.2], &ax, 0.3, 0.1), 0.0);
    println!(
        "2D segments hard cases: max rel err (r > 1e-3) {:e}",
        worst.get()
    );
}

#[test]
fn segments_hard_cases_3d() {
    let worst = Cell::new(0.0);
    for n in hard_normals3() {
        let d = dir(n).get();
        for h in hard_offsets(&d).into_iter().step_by(3) {
            let hs = HalfSpace::new(dir(n), h).unwrap();
            let f = dir(n).frame();
            let dirs = [
                dir(f[0]),
                dir(f[1]),
                dir(d),
                dir([0.0, 0.0, 1.0]),
                dir([0.3, -0.5, 0.8]),
            ];
            for w in dirs {
                for p in [
                    [0.5, 0.5, 0.5],
                    [0.0, 0.0, 0.0],
                    [1.0, 1.0, 1.0],
                    [0.2, 1.0, 0.0],
                    [-0.4, 0.3, 1.3],
                ] {
                    for (t0, t1) in [
                        (-0.5, 0.5),
                        (-f64::INFINITY, f64::INFINITY),
                        (0.2, 1.7),
                        (0.0, 0.0),
                    ] {
                        check_seg(&hs, p, w, t0, t1, &worst);
                    }
                }
            }
        }
    }
    println!(
        "3D segments hard cases: max rel err (r > 1e-3) {:e}",
        worst.get()
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]
    #[test]
    fn segment_free_random_2d(a in -1.0f64..1.0, b in -1.0f64..1.0, h in -1.6f64..1.6,
        p in prop::array::uniform2(-0.5f64..1.5), wa in -1.0f64..1.0, wb in -1.0f64..1.0,
        t0 in -3.0f64..3.0, len in 0.0f64..4.0) {
        prop_assume!(a.abs() + b.abs() > 1e-3 && wa.abs() + wb.abs() > 1e-3);
        let hs = HalfSpace::new(dir([a, b]), h).unwrap();
        check_seg(&hs, p, dir([wa, wb]), t0, t0 + len, &Cell::new(0.0));
    }

    #[test]
    fn segment_free_random_3d(n in prop::array::uniform3(-1.0f64..1.0), h in -1.8f64..1.8,
        p in prop::array::uniform3(-0.5f64..1.5), w in prop::array::uniform3(-1.0f64..1.0),
        t0 in -3.0f64..3.0, len in 0.0f64..4.0) {
        prop_assume!(n.iter().map(|x| x.abs()).sum::<f64>() > 1e-3 && w.iter().map(|x| x.abs()).sum::<f64>() > 1e-3);
        let hs = HalfSpace::new(dir(n), h).unwrap();
        check_seg(&hs, p, dir(w), t0, t0 + len, &Cell::new(0.0));
    }

    #[test]
    fn torus_segments_random_3d(n in prop::array::uniform3(-1.0f64..1.0), h in -1.0f64..1.8,
        c in prop::array::uniform3(-3.0f64..3.0), w in prop::array::uniform3(-1.0f64..1.0),
        lambda in prop::sample::select(vec![0.01, 0.5, 1.0, 1.5, 3.7, 10.0])) {
        prop_assume!(n.iter().map(|x| x.abs()).sum::<f64>() > 1e-3 && w.iter().map(|x| x.abs()).sum::<f64>() > 1e-3);
        let hs = HalfSpace::new(dir(n), h).unwrap();
        let d = dir(w);
        let seg = Segment::new(c, d, lambda).unwrap();
        let got = hs.segment_integral(&seg);
        let r = ref_torus(&hs, &c, &d.get(), lambda);
        prop_assert!((got - r).abs() <= 1e-13 * lambda.max(1.0), "{got} vs {r}");
    }
}

#[test]
fn torus_segments_long_and_hard() {
    let mut worst = 0.0f64;
    let cases2: Vec<([f64; 2], f64)> = hard_normals2()
        .into_iter()
        .map(|n| (n, 0.3 * n[0] + 0.6 * n[1]))
        .collect();
    for (n, h) in cases2 {
        let hs = HalfSpace::new(dir(n), h).unwrap();
        for w in [
            [1.0, 0.0],
            [0.0, 1.0],
            [0.6, 0.8],
            [-0.31, 0.95],
            [1.0, 1e-9],
            [1.0, 2f64.sqrt()],
        ] {
            let d = dir(w);
            for c in [[0.3, 0.7], [-2.25, 5.5], [1.0, 0.0], [0.999, 0.001]] {
                for lambda in [1e-9, 0.5, 1.0, 1.5, 3.7, 100.0] {
                    let seg = Segment::new(c, d, lambda).unwrap();
                    let got = hs.segment_integral(&seg);
                    let r = ref_torus(&hs, &c, &d.get(), lambda);
                    let err = (got - r).abs() / lambda.max(1e-300);
                    assert!(
                        err < 1e-13,
                        "n={n:?} w={w:?} c={c:?} λ={lambda}: {got} vs {r}"
                    );
                    worst = worst.max(err);
                }
            }
        }
    }
    for (n, h) in [
        ([0.2, -0.5, 0.9], 0.1),
        ([1.0, 1e-15, 1e-9], 0.5),
        ([1.0, 1.0, 1.0], 1.0),
    ] {
        let hs = HalfSpace::new(dir(n), h).unwrap();
        for w in [[0.3, -0.5, 0.8], [0.0, 0.0, 1.0], [1.0, 1.0, 1e-12]] {
            let d = dir(w);
            for lambda in [0.7, 1.5, 3.7, 100.0] {
                let c = [0.25, -1.6, 7.3];
                let seg = Segment::new(c, d, lambda).unwrap();
                let got = hs.segment_integral(&seg);
                let r = ref_torus(&hs, &c, &d.get(), lambda);
                let err = (got - r).abs() / lambda;
                assert!(err < 1e-13, "n={n:?} w={w:?} λ={lambda}: {got} vs {r}");
                worst = worst.max(err);
            }
        }
    }
    // A centre far outside [0,1): reduced exactly.
    let hs = HalfSpace::new(dir([0.2, -0.5, 0.9]), 0.1).unwrap();
    let d = dir([0.3, -0.5, 0.8]);
    let c = [1e6 + 0.375, -4096.0 + 0.125, 0.5];
    let a = hs.segment_integral(&Segment::new(c, d, 2.5).unwrap());
    let b = hs.segment_integral(&Segment::new([0.375, 0.125, 0.5], d, 2.5).unwrap());
    assert_eq!(a, b);
    println!("torus segments: max err/λ {worst:e}");
}

#[test]
fn lines_and_axis_identity() {
    for n in hard_normals2() {
        let d = dir(n).get();
        for h in hard_offsets(&d) {
            let hs = HalfSpace::new(dir(n), h).unwrap();
            for axis in 0..2 {
                for off in [0.0, 0.3, 0.5, 0.999, 1.5] {
                    let line = Line::<2>::axis(axis, &[off]).unwrap();
                    let li = hs.line_integral(&line);
                    let mut c = [0.0; 2];
                    c[1 - axis] = off - off.floor();
                    let seg = Segment::new(c, Direction::axis(axis).unwrap(), 1.0).unwrap();
                    let si = hs.segment_integral(&seg);
                    assert!(
                        (li - si).abs() < 1e-15,
                        "axis {axis} off {off}: {li} vs {si}"
                    );
                    // Reference: the free-space length over one period.
                    let r = ref_len(
                        &hs.normal().get(),
                        h,
                        &line.point(),
                        &line.dir().get(),
                        -1.0,
                        2.0,
                    );
                    assert!((li - r).abs() < 4e-16, "{li} vs {r}");
                }
            }
            // Oblique lines: chord of the box.
            for (p, w) in [
                ([0.2, 0.3], [0.6, 0.8]),
                ([0.0, 0.0], [1.0, 1.0]),
                ([1.0, 0.5], [-1.0, 1e-9]),
            ] {
                let line = Line::new(p, dir(w)).unwrap();
                let li = hs.line_integral(&line);
                let r = ref_len(
                    &hs.normal().get(),
                    h,
                    &p,
                    &line.dir().get(),
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                );
                assert!((li - r).abs() < 1e-15, "{li} vs {r}");
            }
        }
    }
    let hs = HalfSpace::new(dir([0.2, -0.5, 0.9]), 0.1).unwrap();
    for axis in 0..3 {
        let line = Line::<3>::axis(axis, &[0.3, 0.8]).unwrap();
        let mut c = [0.0; 3];
        let mut k = 0;
        for j in 0..3 {
            if j != axis {
                c[j] = [0.3, 0.8][k];
                k += 1;
            }
        }
        let seg = Segment::new(c, Direction::axis(axis).unwrap(), 1.0).unwrap();
        assert!((hs.line_integral(&line) - hs.segment_integral(&seg)).abs() < 1e-15);
    }
}

#[test]
fn values_and_short_segment_continuity() {
    let hs = HalfSpace::new(dir([1.0, 0.0]), 0.5).unwrap();
    assert_eq!(hs.value(&[0.5, 0.3]), 1.0);
    assert_eq!(hs.value(&[0.5 - 1e-16, 0.3]), 0.0);
    assert_eq!(hs.value(&[1.7, -0.2]), 1.0);
    assert_eq!(hs.value_free(&[1.7, 0.2]), 0.0);
    assert_eq!(hs.value_free(&[1.0, 0.2]), 0.0);
    let hs3 = HalfSpace::new(dir([1.0, 1.0, 1.0]), 3f64.sqrt()).unwrap(); // only the vertex (1,1,1)
    assert_eq!(hs3.value(&[0.999, 0.999, 0.999]), 0.0);
    assert!(hs3.integral() < 1e-40); // s = n·(1,1,1) − h is ~1e−16 after rounding
                                     // value vs the dd sign of n·x − h.
    let mut rng = 0x1234_5678_9abc_def0u64;
    let mut u = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..2000 {
        let n = [u() - 0.5, u() - 0.5, u() - 0.5];
        let h = u() - 0.5;
        let hs = HalfSpace::new(dir(n), h).unwrap();
        let x = [u() * 3.0 - 1.0, u() * 3.0 - 1.0, u() * 3.0 - 1.0];
        let y = x.map(|v| v - v.floor());
        let g = dd_dot(&hs.normal().get(), &y).sub(Dd::new(h));
        assert_eq!(hs.value(&x), if g.hi >= 0.0 { 1.0 } else { 0.0 });
    }
    // λ → 0: segment_mean → value(c) away from the edge.
    for (n, h, c, w) in [
        ([0.6, 0.8], 0.5, [0.7, 0.6], [0.3, -1.0]),
        ([0.6, 0.8], 0.5, [0.1, 0.2], [1.0, 0.0]),
        ([-1.0, 1e-9], -0.5, [0.25, 0.999], [0.6, 0.8]),
        ([1.0, 1e-15], 0.9, [0.95, 0.5], [0.0, 1.0]),
    ] {
        let hs = HalfSpace::new(dir(n), h).unwrap();
        let v = hs.value(&c);
        for l in [1e-3, 1e-6, 1e-9, 1e-12, 0.0] {
            let m = hs.segment_mean(&Segment::new(c, dir(w), l).unwrap());
            assert!((m - v).abs() < 1e-12, "λ={l}: {m} vs {v}");
        }
    }
    // Crossing the edge: the mean equals the fraction on the positive side.
    let hs = HalfSpace::new(dir([1.0, 0.0]), 0.5).unwrap();
    for l in [1e-3, 1e-6, 1e-9] {
        let m = hs.segment_mean(&Segment::new([0.5 + 0.25 * l, 0.3], dir([1.0, 0.0]), l).unwrap());
        assert!((m - 0.75).abs() < 1e-6, "{m}");
    }
}

#[test]
fn mean_of_segment_mean_is_integral() {
    // Deterministic quadrature over the centre (nested adaptive GK on the torus;
    // the segment mean is continuous with kinks, so the tolerance is modest).
    for (n, h, w, lambda) in [
        ([0.6, 0.8], 0.55, [0.3, -1.0], 0.4),
        ([1.0, 1e-9], 0.3, [0.8, 0.6], 1.7),
    ] {
        let hs = HalfSpace::new(dir(n), h).unwrap();
        let d = dir(w);
        let mean = integrate(
            |x| {
                integrate(
                    |y| hs.segment_mean(&Segment::new([x, y], d, lambda).unwrap()),
                    0.0,
                    1.0,
                    1e-7,
                )
            },
            0.0,
            1.0,
            1e-7,
        );
        assert!(
            (mean - hs.integral()).abs() < 1e-6,
            "{mean} vs {}",
            hs.integral()
        );
    }
    // Exact version along an axis: the mean over c_z of the axis segment mean is
    // the axis line integral at (x, y); its mean over (x, y) is the volume.
    let hs = HalfSpace::new(dir([0.2, -0.5, 0.9]), 0.1).unwrap();
    let d = Direction::axis(2).unwrap();
    for (x, y) in [(0.1, 0.2), (0.7, 0.35), (0.95, 0.9)] {
        let mean = integrate(
            |z| hs.segment_mean(&Segment::new([x, y, z], d, 0.6).unwrap()),
            0.0,
            1.0,
            1e-13,
        );
        let line = hs.line_integral(&Line::axis(2, &[x, y]).unwrap());
        assert!((mean - line).abs() < 1e-12, "{mean} vs {line}");
    }
}

// ---------------------------------------------------------------------------
// Fourier.

fn check_fourier<const D: usize>(n: [f64; D], h: f64, k: [i32; D], worst: &Cell<f64>) {
    let hs = HalfSpace::new(dir(n), h).unwrap();
    let got = hs.fourier(&k);
    let r = ref_fourier(&hs.normal().get(), h, &k, 1e-15);
    let err = cabs(got, r);
    let kn: f64 = k.iter().map(|x| f64::from(x.abs())).sum();
    assert!(
        err <= 2e-14 * (1.0 + kn),
        "fourier n={n:?} h={h} k={k:?}: {got:?} vs {r:?} ({err:e})"
    );
    worst.set(worst.get().max(err / (1.0 + kn)));
}

#[test]
fn fourier_hard_cases_2d() {
    let worst = Cell::new(0.0);
    let ks: [[i32; 2]; 7] = [
        [0, 0],
        [1, 0],
        [0, -3],
        [2, 5],
        [-7, 3],
        [40, -1],
        [-100, 77],
    ];
    for n in hard_normals2() {
        let d = dir(n).get();
        for h in hard_offsets(&d).into_iter().step_by(3) {
            for k in ks {
                check_fourier(n, h, k, &worst);
            }
        }
    }
    // k ∥ n and k ⟂ n.
    for k in [[3, 4], [-4, 3], [6, 8]] {
        check_fourier([0.6, 0.8], 0.7, k, &worst);
    }
    println!("2D fourier: max |err|/(1+|k|₁) {:e}", worst.get());
}

#[test]
fn fourier_hard_cases_3d() {
    let worst = Cell::new(0.0);
    let ks: [[i32; 3]; 6] = [
        [0, 0, 0],
        [1, 0, 0],
        [0, 2, -1],
        [3, -1, 2],
        [0, 0, 9],
        [-5, 4, 6],
    ];
    for n in hard_normals3() {
        let d = dir(n).get();
        for h in hard_offsets(&d).into_iter().step_by(7) {
            for k in ks {
                check_fourier(n, h, k, &worst);
            }
        }
    }
    check_fourier([0.2, -0.5, 0.9], 0.1, [20, -30, 15], &worst);
    check_fourier([1.0, 1.0, 1.0], 1.0, [4, 4, 4], &worst);
    check_fourier([1.0, 1.0, 1.0], 1.0, [3, -3, 0], &worst);
    println!("3D fourier: max |err|/(1+|k|₁) {:e}", worst.get());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn fourier_random_2d(a in -1.0f64..1.0, b in -1.0f64..1.0, u in -0.1f64..1.1,
        k in prop::array::uniform2(-12i32..12)) {
        prop_assume!(a.abs() + b.abs() > 1e-3);
        let n = dir([a, b]).get();
        let (lo, hi) = (n[0].min(0.0) + n[1].min(0.0), n[0].max(0.0) + n[1].max(0.0));
        check_fourier([a, b], lo + u * (hi - lo), k, &Cell::new(0.0));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn fourier_random_3d(n in prop::array::uniform3(-1.0f64..1.0), u in 0.0f64..1.0,
        k in prop::array::uniform3(-6i32..6)) {
        prop_assume!(n.iter().map(|x| x.abs()).sum::<f64>() > 1e-3);
        let d = dir(n).get();
        let lo: f64 = d.iter().map(|x| x.min(0.0)).sum();
        let hi: f64 = d.iter().map(|x| x.max(0.0)).sum();
        check_fourier(n, lo + u * (hi - lo), k, &Cell::new(0.0));
    }
}

#[test]
fn fourier_high_frequency_consistency() {
    // Conjugate symmetry, complement (H and its complement tile the box, whose
    // coefficients vanish for k ≠ 0) and, in 2D, GK at |k| ~ 1e3.
    let mut worst = 0.0f64;
    for (n, h) in [
        ([0.6, 0.8], 0.7),
        ([1.0, 1e-9], 0.3),
        ([1.0, -1.0], 0.0),
        ([0.3, 0.7], 0.9),
    ] {
        let a = HalfSpace::new(dir(n), h).unwrap();
        let b = HalfSpace::new(dir([-n[0], -n[1]]), -h).unwrap();
        for k in [
            [10_000, 1],
            [-3_333, 7_777],
            [0, 9_999],
            [7_071, -7_071],
            [1, -10_000],
        ] {
            let f = a.fourier(&k);
            let g = a.fourier(&[-k[0], -k[1]]);
            let c = b.fourier(&k);
            let e1 = ((f.re - g.re).powi(2) + (f.im + g.im).powi(2)).sqrt();
            let e2 = ((f.re + c.re).powi(2) + (f.im + c.im).powi(2)).sqrt();
            assert!(e1 < 1e-15 && e2 < 1e-12, "n={n:?} k={k:?}: {e1:e} {e2:e}");
            worst = worst.max(e2);
        }
        for k in [[300, 3], [-200, 250]] {
            let f = a.fourier(&k);
            let r = ref_fourier(&a.normal().get(), h, &k, 1e-15);
            assert!(cabs(f, r) < 1e-13, "n={n:?} k={k:?}: {f:?} vs {r:?}");
        }
    }
    for (n, h) in [
        ([0.2, -0.5, 0.9], 0.1),
        ([1.0, 1e-15, 1e-9], 0.5),
        ([1.0, 1.0, 1.0], 1.2),
    ] {
        let a = HalfSpace::new(dir(n), h).unwrap();
        let b = HalfSpace::new(dir([-n[0], -n[1], -n[2]]), -h).unwrap();
        for k in [
            [10_000, 1, -2],
            [-3_333, 7_777, 5_000],
            [0, 0, 9_999],
            [5_773, 5_773, 5_773],
        ] {
            let f = a.fourier(&k);
            let g = a.fourier(&[-k[0], -k[1], -k[2]]);
            let c = b.fourier(&k);
            let e1 = ((f.re - g.re).powi(2) + (f.im + g.im).powi(2)).sqrt();
            let e2 = ((f.re + c.re).powi(2) + (f.im + c.im).powi(2)).sqrt();
            assert!(e1 < 1e-15 && e2 < 1e-12, "n={n:?} k={k:?}: {e1:e} {e2:e}");
            worst = worst.max(e2);
        }
    }
    println!("high-frequency complement mismatch: max {worst:e}");
}

#[test]
fn fourier_zero_and_parseval() {
    for (n, h) in [([0.6, 0.8], 0.7), ([1.0, 0.0], 0.25)] {
        let hs = HalfSpace::new(dir(n), h).unwrap();
        assert_eq!(hs.fourier(&[0, 0]).re, hs.integral());
        // Parseval: Σ|f̂_k|² = ∫f² = ∫f; the partial sums increase towards it.
        let mut s = 0.0;
        for a in -60..=60 {
            for b in -60..=60 {
                s += hs.fourier(&[a, b]).norm_sqr();
            }
        }
        assert!(
            s <= hs.integral() + 1e-12 && s > hs.integral() - 0.01,
            "{s} vs {}",
            hs.integral()
        );
    }
    // Axis-aligned closed form: ∫_h^1 e^{−2πikx} dx.
    let hs = HalfSpace::new(dir([1.0, 0.0]), 0.25).unwrap();
    for k in 1..50 {
        let (re, im) = exp_int(f64::from(k), 0.25, 1.0);
        let f = hs.fourier(&[k, 0]);
        assert!((f.re - re).abs() < 1e-15 && (f.im - im).abs() < 1e-15);
        assert!(hs.fourier(&[k, 1]).norm_sqr() < 1e-30);
    }
}

// ---------------------------------------------------------------------------
// f32 batch.

fn f32_case<const D: usize>(
    hs: &HalfSpace<D>,
    o: [f32; D],
    d: [f32; D],
    t0: f32,
    t1: f32,
) -> (f32, f64) {
    let got = hs.segment_free_f32(o, d, t0, t1);
    let dv = d.map(f64::from);
    let dirn = Direction::new(dv).unwrap();
    // Parameter t of the unnormalised d: scale by |d|.
    let norm = dv.iter().map(|x| x * x).sum::<f64>().sqrt();
    let r = hs.segment_free(
        &o.map(f64::from),
        &dirn,
        f64::from(t0) * norm,
        f64::from(t1) * norm,
    ) / norm;
    (got, r)
}

#[test]
fn f32_batch_matches_scalar_and_f64() {
    let mut rng = 0x9e37_79b9_7f4a_7c15u64;
    let mut u = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 40) as f32 / (1u32 << 24) as f32
    };
    let uu = 2f64.powi(-24);
    let mut worst = 0.0f64;
    for len in (0..=17).chain([64, 203]) {
        for trial in 0..8 {
            let n = [u() - 0.5, u() - 0.5, u() - 0.5].map(f64::from);
            let h = f64::from(u()) - 0.3;
            let hs = HalfSpace::new(dir(n), h).unwrap();
            let mut o = [vec![], vec![], vec![]];
            let mut dd = [vec![], vec![], vec![]];
            let (mut t0, mut t1) = (vec![], vec![]);
            for i in 0..len {
                for j in 0..3 {
                    o[j].push(u() * 2.0 - 0.5);
                    dd[j].push(u() * 2.0 - 1.0);
                }
                if i % 5 == 0 {
                    dd[i % 3][i] = 0.0;
                }
                if i % 7 == 3 {
                    o[1][i] = 1.0;
                    dd[1][i] = 0.0;
                }
                let a = u() * 4.0 - 2.0;
                t0.push(if i % 11 == 1 { f32::NEG_INFINITY } else { a });
                t1.push(if i % 13 == 2 {
                    f32::INFINITY
                } else {
                    a + u() * 3.0
                });
            }
            if trial == 0 && len > 0 {
                for j in 0..3 {
                    dd[j][0] = 0.0;
                }
                dd[2][0] = 1.0;
            }
            let rays = Rays32 {
                origin: [&o[0], &o[1], &o[2]],
                dir: [&dd[0], &dd[1], &dd[2]],
                t0: &t0,
                t1: &t1,
            };
            let mut out = vec![f32::NAN; len];
            hs.segment_free_batch_f32(&rays, &mut out).unwrap();
            let n32 = n.map(|x| x as f32);
            let _ = n32;
            for i in 0..len {
                let oi = [o[0][i], o[1][i], o[2][i]];
                let di = [dd[0][i], dd[1][i], dd[2][i]];
                let s = hs.segment_free_f32(oi, di, t0[i], t1[i]);
                assert_eq!(out[i].to_bits(), s.to_bits(), "lane {i} of {len}");
                if di.iter().all(|x| *x == 0.0) {
                    continue;
                }
                let (got, r) = f32_case(&hs, oi, di, t0[i], t1[i]);
                // Documented bound.
                let nn = hs.normal().get();
                let nd: f64 = (0..3).map(|j| nn[j] * f64::from(di[j])).sum();
                let no: f64 = (0..3).map(|j| (nn[j] * f64::from(oi[j])).abs()).sum();
                let mut span = 0.0f64;
                for j in 0..3 {
                    if di[j] != 0.0 {
                        span = span.max((f64::from(oi[j]).abs() + 1.0) / f64::from(di[j]).abs());
                    }
                }
                let ts = if nd != 0.0 {
                    ((h - no) / nd).abs().min(span)
                } else {
                    0.0
                };
                let osum: f64 = oi.iter().map(|x| f64::from(x.abs())).sum();
                let mut bound = 8.0 * uu * span;
                if nd != 0.0 {
                    bound += 8.0 * uu * (1.0 + osum + h.abs() + ts) / nd.abs();
                }
                let err = (f64::from(got) - r).abs();
                assert!(
                    err <= bound,
                    "f32 {oi:?} {di:?} [{}, {}]: {got} vs {r} (bound {bound:e})",
                    t0[i],
                    t1[i]
                );
                if nd.abs() > 0.1 && r > 0.1 {
                    worst = worst.max(err / r);
                }
            }
        }
    }
    // 2D: bit identity for every batch length 0..=17.
    for len in 0..=17usize {
        let hs = HalfSpace::new(dir([0.6, -0.8]), 0.1 * len as f64 - 0.5).unwrap();
        let mut v: Vec<Vec<f32>> = (0..6)
            .map(|_| (0..len).map(|_| u() * 2.0 - 0.5).collect())
            .collect();
        for i in 0..len {
            v[5][i] = v[4][i] + 2.0 * u();
            if i % 4 == 1 {
                v[2][i] = 0.0;
            }
        }
        let rays = Rays32 {
            origin: [&v[0], &v[1]],
            dir: [&v[2], &v[3]],
            t0: &v[4],
            t1: &v[5],
        };
        let mut out = vec![f32::NAN; len];
        hs.segment_free_batch_f32(&rays, &mut out).unwrap();
        for i in 0..len {
            let s = hs.segment_free_f32([v[0][i], v[1][i]], [v[2][i], v[3][i]], v[4][i], v[5][i]);
            assert_eq!(out[i].to_bits(), s.to_bits(), "2D lane {i} of {len}");
        }
    }
    // The length check.
    let hs = HalfSpace::new(dir([0.6, 0.8]), 0.5).unwrap();
    let z = [0.5f32; 9];
    let rays = Rays32 {
        origin: [&z, &z],
        dir: [&z, &z],
        t0: &z,
        t1: &z[..8],
    };
    let mut out = [0.0f32; 9];
    assert!(matches!(
        hs.segment_free_batch_f32(&rays, &mut out),
        Err(ParamError::Length { name: "t1", .. })
    ));
    let rays = Rays32 {
        origin: [&z, &z],
        dir: [&z, &z],
        t0: &z,
        t1: &z,
    };
    assert!(matches!(
        hs.segment_free_batch_f32(&rays, &mut out[..4]),
        Err(ParamError::Length { name: "out", .. })
    ));
    let (g, r) = f32_case(&hs, [0.1, 0.2], [0.6, 0.8], -1.0, 1.0);
    assert!((f64::from(g) - r).abs() < 1e-6);
    println!("f32 vs f64: max rel err (well-conditioned rays) {worst:e}");
}

#[test]
fn bad_input() {
    assert_eq!(
        HalfSpace::new(dir([1.0, 0.0]), f64::NAN).unwrap_err(),
        ParamError::NonFinite { name: "offset" }
    );
    assert_eq!(
        HalfSpace::new(dir([1.0, 0.0, 0.0]), f64::INFINITY).unwrap_err(),
        ParamError::NonFinite { name: "offset" }
    );
    assert_eq!(
        HalfSpace::new(dir([1.0, 0.0]), f64::NEG_INFINITY).unwrap_err(),
        ParamError::NonFinite { name: "offset" }
    );
    assert_eq!(
        HalfSpace::from_angle(f64::NAN, 0.0).unwrap_err(),
        ParamError::NonFinite { name: "theta" }
    );
    assert_eq!(
        HalfSpace::from_angle(1.0, f64::INFINITY).unwrap_err(),
        ParamError::NonFinite { name: "offset" }
    );
    assert!(matches!(
        HalfSpace::new(Direction::<4>::axis(0).unwrap(), 0.0),
        Err(ParamError::Dimension { dim: 4 })
    ));
    assert!(matches!(
        HalfSpace::new(Direction::<1>::axis(0).unwrap(), 0.0),
        Err(ParamError::Dimension { dim: 1 })
    ));
    // Any finite offset: empty and full.
    let e = HalfSpace::new(dir([0.6, 0.8]), 1e300).unwrap();
    assert_eq!(
        (
            e.integral(),
            e.fourier(&[1, 2]).norm_sqr(),
            e.value(&[0.9, 0.9])
        ),
        (0.0, 0.0, 0.0)
    );
    let f = HalfSpace::new(dir([0.6, 0.8]), -1e300).unwrap();
    assert_eq!(
        (
            f.integral(),
            f.fourier(&[1, 2]).norm_sqr(),
            f.value(&[0.9, 0.9])
        ),
        (1.0, 0.0, 1.0)
    );
    let a = HalfSpace::from_angle(0.3, 0.2).unwrap();
    assert!(
        (a.normal().get()[0] - 0.3f64.cos()).abs() < 1e-15
            && a.offset() == 0.2
            && a.max_value() == 1.0
    );
}

// ---------------------------------------------------------------------------
// Short segments at the edge and the box faces, against exact arithmetic
// ---------------------------------------------------------------------------

/// The exact length of `{t ∈ [t0, t1] : p + tω ∈ [0, 1]^D, n·(p + tω) ≥ h}`
/// for an exact point `p`: every interval end is an exact dyadic rational
/// (slab ends `−p_j/ω_j`, `(1 − p_j)/ω_j`, the edge crossing
/// `−(n·p − h)/(n·ω)`, quotients to 1400 bits), the difference formed exactly.
fn exact_len<const D: usize>(
    n: &[f64; D],
    h: f64,
    p: &[Dy; D],
    w: &[f64; D],
    t0: &Dy,
    t1: &Dy,
) -> Dy {
    let (mut lo, mut hi) = (t0.clone(), t1.clone());
    for j in 0..D {
        if w[j] == 0.0 {
            if p[j].signum() < 0 || p[j].cmp(&Dy::f(1.0)) != std::cmp::Ordering::Less {
                return Dy::zero();
            }
            continue;
        }
        let wj = Dy::f(w[j]);
        let a = p[j].neg().div(&wj);
        let b = Dy::f(1.0).sub(&p[j]).div(&wj);
        let (a, b) = if w[j] > 0.0 { (a, b) } else { (b, a) };
        lo = lo.max(a);
        hi = hi.min(b);
    }
    let nd: [Dy; D] = core::array::from_fn(|j| Dy::f(n[j]));
    let wd: [Dy; D] = core::array::from_fn(|j| Dy::f(w[j]));
    let g = exact::dot(&nd, p).sub(&Dy::f(h));
    let c = exact::dot(&nd, &wd);
    match c.signum() {
        0 => {
            if g.signum() < 0 {
                return Dy::zero();
            }
        }
        s => {
            let ts = g.neg().div(&c);
            if s > 0 {
                lo = lo.max(ts);
            } else {
                hi = hi.min(ts);
            }
        }
    }
    Dy::zero().max(hi.sub(&lo))
}

fn ulp(x: f64) -> f64 {
    f64::from_bits(x.abs().to_bits() + 1) - x.abs()
}

/// Short segments (`10^{−U(0,15)}`, at least 16 ulp of the crossing
/// parameter) straddling, ending at (0 or ±1 ulp from), starting at or lying
/// next to the edge crossing or a box face, seen from the crossing point, from
/// up to 1 away or from up to `10³` away, for regular (`|n·ω| > 0.05`) and
/// grazing (`|n·ω| = 10^{−U(1,8)}`) directions. Asserts the documented bound
/// `ε·len + 8ε²·(|lo| + |hi| + (Σ|n_j p_j| + |h|)/|n·ω|)` on every case and
/// `≤ 1e−13` relative where that bound is `≤ 1e−14·len`. Returns the worst
/// relative error of the latter.
fn edge_cases<const D: usize>(seed: u64, cases: usize) -> f64 {
    let mut g = Mix(seed);
    let mut worst = 0.0f64;
    let mut strict = 0;
    let mut done = 0;
    while done < cases {
        let nv: [f64; D] = g.unit();
        let nrm = Direction::new(nv).unwrap();
        let n = nrm.get();
        // A point of the edge inside the box: a random point projected onto it.
        let y: [f64; D] = core::array::from_fn(|_| g.f());
        let h = (0..D).map(|j| n[j] * y[j]).sum::<f64>() + g.range(-0.3, 0.3);
        let hs = HalfSpace::new(nrm, h).unwrap();
        let dy: f64 = (0..D).map(|j| n[j] * y[j]).sum::<f64>() - h;
        let mut x: [f64; D] = core::array::from_fn(|j| y[j] - dy * n[j]);
        let on_face = g.below(3) == 0;
        if on_face {
            // The boundary crossing is a box face instead: x_k ∈ {0, 1}.
            let k = g.below(D as u64) as usize;
            x = y;
            x[k] = if g.below(2) == 0 { 0.0 } else { 1.0 };
        }
        if x.iter().any(|v| !(0.0..=1.0).contains(v)) {
            continue;
        }
        let grazing = !on_face && g.below(4) == 0;
        let v: [f64; D] = if grazing {
            let mut t: [f64; D] = g.unit();
            let d: f64 = (0..D).map(|j| t[j] * n[j]).sum();
            for j in 0..D {
                t[j] -= d * n[j];
            }
            let e = 10f64.powf(-g.range(1.0, 8.0)) * if g.below(2) == 0 { 1.0 } else { -1.0 };
            core::array::from_fn(|j| t[j] + e * n[j])
        } else {
            loop {
                let u: [f64; D] = g.unit();
                if (0..D).map(|j| u[j] * n[j]).sum::<f64>().abs() > 0.05
                    && u.iter().all(|c| c.abs() > 1e-3)
                {
                    break u;
                }
            }
        };
        let Ok(dir) = Direction::new(v) else { continue };
        let w = dir.get();
        let reach = match g.below(3) {
            0 => 0.0,
            1 => g.f(),
            _ => 10f64.powf(g.range(0.0, 3.0)),
        };
        let p: [f64; D] = core::array::from_fn(|j| x[j] - reach * w[j]);
        let pd: [Dy; D] = core::array::from_fn(|j| Dy::f(p[j]));
        // The crossing parameter nearest `reach`: the edge, or the face.
        let tb = if on_face {
            let k = (0..D).find(|&k| x[k] == 0.0 || x[k] == 1.0).unwrap();
            Dy::f(x[k]).sub(&pd[k]).div(&Dy::f(w[k])).to_f64()
        } else {
            let nd: [Dy; D] = core::array::from_fn(|j| Dy::f(n[j]));
            let wd: [Dy; D] = core::array::from_fn(|j| Dy::f(w[j]));
            let c = exact::dot(&nd, &wd);
            if c.signum() == 0 {
                continue;
            }
            exact::dot(&nd, &pd).sub(&Dy::f(h)).neg().div(&c).to_f64()
        };
        let len = 10f64.powf(-g.range(0.0, 15.0)).max(16.0 * ulp(tb));
        let k = g.below(3) as f64 - 1.0;
        let (t0, t1) = match g.below(4) {
            0 => {
                let t1 = tb + k * ulp(tb);
                (t1 - len, t1)
            }
            1 => {
                let t0 = tb + k * ulp(tb);
                (t0, t0 + len)
            }
            2 => {
                let gap = len * 10f64.powf(-g.range(0.0, 3.0));
                if g.below(2) == 0 {
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
        let got = hs.segment_free(&p, &dir, t0, t1);
        let want = exact_len(&n, h, &pd, &w, &Dy::f(t0), &Dy::f(t1));
        let wf = want.to_f64();
        let err = (Dy::f(got).sub(&want)).to_f64().abs();
        let nw: f64 = (0..D).map(|j| n[j] * w[j]).sum::<f64>().abs();
        let np: f64 = (0..D).map(|j| (n[j] * p[j]).abs()).sum::<f64>() + h.abs();
        let edge = if nw > 0.0 { np / nw } else { 0.0 };
        let bound = EPS / 2.0 * wf + 8.0 * (EPS / 2.0).powi(2) * (t0.abs() + t1.abs() + edge);
        assert!(
            err <= bound,
            "half-space: |err| {err:e} > bound {bound:e}: n={n:?} h={h} p={p:?} w={w:?} [{t0:e}, {t1:e}] got {got:e} want {wf:e}"
        );
        if wf > 0.0 && bound <= 1e-14 * wf {
            strict += 1;
            let rel = rel_err_exact(got, &want);
            assert!(rel <= 1e-13, "{rel:e}");
            worst = worst.max(rel);
        }
        done += 1;
    }
    eprintln!("{D}D half-space edge/face segments: {strict} of {cases} with bound ≤ 1e-14 relative, worst relative error {worst:.2e}");
    worst
}

#[test]
fn short_segments_at_the_edge_are_relatively_exact() {
    let w2 = edge_cases::<2>(0x4a1f_0002, 10_000);
    let w3 = edge_cases::<3>(0x4a1f_0003, 10_000);
    assert!(w2 <= 1e-13 && w3 <= 1e-13);
}

/// The exact wrapped-segment integral of `F(frac(x))` along `s + tω`,
/// `t ∈ [−λ/2, λ/2]`: the sum over the cells `m` the segment can reach of the
/// exact clipped length for the exact point `s − m`.
fn exact_torus_hs<const D: usize>(
    hs: &HalfSpace<D>,
    s: &[f64; D],
    w: &[f64; D],
    lambda: f64,
) -> Dy {
    let (n, h) = (hs.normal().get(), hs.offset());
    let half = 0.5 * lambda;
    let (t0, t1) = (Dy::f(-half), Dy::f(half));
    let mut lo = [0i64; D];
    let mut hi = [0i64; D];
    for j in 0..D {
        let (a, b) = (s[j] - half * w[j], s[j] + half * w[j]);
        lo[j] = a.min(b).floor() as i64 - 1;
        hi[j] = a.max(b).floor() as i64 + 1;
    }
    let mut sum = Dy::zero();
    exact::for_each_cell(lo, hi, |m| {
        let p: [Dy; D] = core::array::from_fn(|j| Dy::f(s[j]).sub(&Dy::f(m[j] as f64)));
        sum = sum.add(&exact_len(&n, h, &p, w, &t0, &t1));
    });
    sum
}

/// Short wrapped segments centred where the edge meets the cell face
/// `x_0 = 0`, with the centre's `x_0` equal to `0`, `±10⁻¹⁷`, `1`,
/// `−1 + 10⁻¹⁷` or `10³`, so the segment is split into pieces at the face
/// right next to the edge crossing.
fn torus_edge_cases<const D: usize>(seed: u64, cases: usize) -> f64 {
    let mut g = Mix(seed);
    let mut worst = 0.0f64;
    let mut done = 0;
    let mut strict = 0;
    while done < cases {
        let nv: [f64; D] = g.unit();
        let nrm = Direction::new(nv).unwrap();
        let n = nrm.get();
        if n[1].abs() < 0.05 {
            continue;
        }
        // A point X on the face x_0 = 0 and on the edge: solve for X_1.
        let mut x: [f64; D] = core::array::from_fn(|_| g.f());
        x[0] = 0.0;
        let h = (0..D).map(|j| n[j] * x[j]).sum::<f64>();
        let hs = HalfSpace::new(nrm, h).unwrap();
        let mut s = x;
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
            if v[0].abs() > 0.05 && (0..D).map(|j| v[j] * n[j]).sum::<f64>().abs() > 0.05 {
                break v;
            }
        };
        let dir = Direction::new(v).unwrap();
        let len = 10f64.powf(-g.range(0.0, 13.0));
        let seg = Segment::new(s, dir, len).unwrap();
        let got = hs.segment_integral(&seg);
        let want = exact_torus_hs(&hs, &seg.centre(), &dir.get(), seg.length());
        // The bound of `segment_free` per cell (at most 2^D cells), with the
        // exact origin of each: 2ε·L + 8ε²·(λ + (Σ|n_j p_j| + |h|)/|n·ω|),
        // |p_j| ≤ |s_j| + 1.
        let wf = want.to_f64();
        let w = dir.get();
        let nw: f64 = (0..D).map(|j| n[j] * w[j]).sum::<f64>().abs();
        let np: f64 = (0..D).map(|j| n[j].abs() * (s[j].abs() + 1.0)).sum::<f64>() + h.abs();
        // (one rounding per cell plus the sum: ≤ 2ε·L)
        let bound = 2.0 * EPS * wf + (1 << D) as f64 * 8.0 * (EPS / 2.0).powi(2) * (len + np / nw);
        let abs = Dy::f(got).sub(&want).to_f64().abs();
        assert!(abs <= bound, "half-space torus: |err| {abs:e} > bound {bound:e}: n={n:?} h={h} s={s:?} w={w:?} λ={len:e}: got {got:e} want {wf:e}");
        if bound <= 1e-14 * wf {
            strict += 1;
            let err = rel_err_exact(got, &want);
            assert!(
                err <= 1e-13,
                "half-space torus: rel err {err:e}: n={n:?} h={h} s={s:?} w={:?} λ={len:e}: got {got:e} want {:e}",
                dir.get(),
                want.to_f64()
            );
            worst = worst.max(err);
        }
        done += 1;
    }
    eprintln!("{D}D half-space wrapped segments: {strict} of {cases} with bound ≤ 1e-14 relative");
    worst
}

#[test]
fn short_wrapped_segments_across_faces_at_the_edge() {
    let w2 = torus_edge_cases::<2>(0x70e5_0002, 3000);
    let w3 = torus_edge_cases::<3>(0x70e5_0003, 3000);
    eprintln!("half-space wrapped segments across a face at the edge: worst relative error 2D {w2:.2e}, 3D {w3:.2e}");
}
