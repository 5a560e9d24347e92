//! The world-space [`HalfSpace`] and [`Slab`] (`linesample::world`) against
//! exact dyadic big-integer arithmetic (`tests/exact`): crossings
//! `t* = −(n·o − h)/(n·ω)` (to 1400 bits) and the exact length of `[t0, t1]`
//! on the kept side, with `n` the stored unit normal and `ω` the stored unit
//! direction; for the proptest strategies of `linesample::strategy`
//! (`direction`, `near_axis_direction`, `centre`, `log_uniform`) and
//! deterministic hard cases (near-parallel rays down to `n·ω = 1e-300`,
//! origins up to `1e300` away, origins on the plane, short segments ending
//! at or next to the plane); the `f32` twins and SIMD batches (bit-identical
//! lane by lane, error within the documented bound); bad input. Run with
//! `--nocapture` to see the worst errors.

// `!(x <= y)` is deliberate: it also catches NaN.
#![allow(
    clippy::needless_range_loop,
    clippy::type_complexity,
    clippy::neg_cmp_op_on_partial_ord
)]

mod exact;

use exact::{rel_err_exact, Dy, Mix};
use linesample::strategy;
use linesample::world::{HalfSpace, Ray, Rays32, Slab};
use linesample::ParamError;
use proptest::prelude::*;
use proptest::test_runner::Config;
use std::cell::RefCell;
use std::cmp::Ordering;

/// `2⁻²⁴`, the `u` of the `f32` bound.
const U32: f64 = 5.960464477539063e-8;
/// The brief's relative bound for "a few ulp".
const FEW_ULP: f64 = 1e-13;
/// "≤ 2 ulp" relative (`ulp(x) ≤ 2⁻⁵²|x|`).
const TWO_ULP: f64 = 2.0 * f64::EPSILON;

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}

// ---------------------------------------------------------------------------
// Exact reference
// ---------------------------------------------------------------------------

/// An extended real: `±∞` or an exact dyadic.
#[derive(Clone, Debug)]
enum X {
    NegInf,
    Fin(Dy),
    PosInf,
}

impl X {
    fn of(t: f64) -> X {
        if t == f64::NEG_INFINITY {
            X::NegInf
        } else if t == f64::INFINITY {
            X::PosInf
        } else {
            X::Fin(Dy::f(t))
        }
    }
    fn cmp(&self, o: &X) -> Ordering {
        match (self, o) {
            (X::Fin(a), X::Fin(b)) => a.cmp(b),
            (X::NegInf, X::NegInf) | (X::PosInf, X::PosInf) => Ordering::Equal,
            (X::NegInf, _) | (_, X::PosInf) => Ordering::Less,
            _ => Ordering::Greater,
        }
    }
    fn max(self, o: X) -> X {
        if self.cmp(&o) == Ordering::Less {
            o
        } else {
            self
        }
    }
    fn min(self, o: X) -> X {
        if self.cmp(&o) == Ordering::Greater {
            o
        } else {
            self
        }
    }
}

/// An exact length: `∞` or a non-negative dyadic.
#[derive(Debug)]
enum Len {
    Inf,
    Fin(Dy),
}

impl std::fmt::Display for Len {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Len::Inf => write!(f, "inf"),
            Len::Fin(d) => write!(f, "{:e}", d.to_f64()),
        }
    }
}

/// `hi − lo` (0 if empty).
fn length(lo: &X, hi: &X) -> Len {
    if lo.cmp(hi) != Ordering::Less {
        return Len::Fin(Dy::zero());
    }
    match (lo, hi) {
        (X::Fin(a), X::Fin(b)) => Len::Fin(b.sub(a)),
        _ => Len::Inf,
    }
}

/// `n·x − h`, exact.
fn excess<const D: usize>(n: &[f64; D], h: f64, x: &[f64; D]) -> Dy {
    let mut g = Dy::f(h).neg();
    for j in 0..D {
        g = g.add(&Dy::f(n[j]).mul(&Dy::f(x[j])));
    }
    g
}

/// `n·w`, exact.
fn slope<const D: usize>(n: &[f64; D], w: &[f64; D]) -> Dy {
    let mut c = Dy::zero();
    for j in 0..D {
        c = c.add(&Dy::f(n[j]).mul(&Dy::f(w[j])));
    }
    c
}

/// Narrows `[lo, hi]` to `{t : g + t·c ≥ 0}`; `false` if that set is empty
/// (`c = 0`, `g < 0`).
fn keep(g: &Dy, c: &Dy, lo: &mut X, hi: &mut X) -> bool {
    match c.signum() {
        0 => g.signum() >= 0,
        s => {
            let ts = X::Fin(g.neg().div(c));
            if s > 0 {
                *lo = lo.clone().max(ts);
            } else {
                *hi = hi.clone().min(ts);
            }
            true
        }
    }
}

/// The ends as extended reals (`t0 > t1` is empty).
fn ends(t0: f64, t1: f64) -> (X, X) {
    (X::of(t0), X::of(t1))
}

/// Exact `HalfSpace::segment` for normal `n`, offset `h`, along `o + t·w`.
fn exact_half<const D: usize>(
    n: &[f64; D],
    h: f64,
    o: &[f64; D],
    w: &[f64; D],
    t0: f64,
    t1: f64,
) -> Len {
    exact_half_c(n, h, o, &slope(n, w), t0, t1)
}

/// [`exact_half`] for a given slope `c` (0: the parallel semantics).
fn exact_half_c<const D: usize>(
    n: &[f64; D],
    h: f64,
    o: &[f64; D],
    c: &Dy,
    t0: f64,
    t1: f64,
) -> Len {
    let (mut lo, mut hi) = ends(t0, t1);
    if !keep(&excess(n, h, o), c, &mut lo, &mut hi) {
        return Len::Fin(Dy::zero());
    }
    length(&lo, &hi)
}

/// Exact `Slab::segment`.
fn exact_slab<const D: usize>(
    n: &[f64; D],
    h0: f64,
    h1: f64,
    o: &[f64; D],
    w: &[f64; D],
    t0: f64,
    t1: f64,
) -> Len {
    exact_slab_c(n, h0, h1, o, &slope(n, w), t0, t1)
}

/// [`exact_slab`] for a given slope `c`.
fn exact_slab_c<const D: usize>(
    n: &[f64; D],
    h0: f64,
    h1: f64,
    o: &[f64; D],
    c: &Dy,
    t0: f64,
    t1: f64,
) -> Len {
    let (mut lo, mut hi) = ends(t0, t1);
    let c = c.clone();
    if !keep(&excess(n, h0, o), &c, &mut lo, &mut hi)
        || !keep(&excess(n, h1, o).neg(), &c.neg(), &mut lo, &mut hi)
    {
        return Len::Fin(Dy::zero());
    }
    length(&lo, &hi)
}

/// `|x| > f64::MAX` (rounds to `±∞`).
fn overflows(x: &Dy) -> bool {
    let a = if x.signum() < 0 { x.neg() } else { x.clone() };
    // The largest value that rounds to MAX: MAX + ulp(MAX)/2.
    let lim = Dy::f(f64::MAX).add(&Dy::f(2f64.powi(970)));
    a.cmp(&lim) != Ordering::Less
}

/// Relative error of `got` against an exact length (`∞` must be `∞`; an
/// exact length beyond the double range must round to `∞`).
fn len_err(got: f64, want: &Len) -> f64 {
    match want {
        Len::Inf => {
            if got == f64::INFINITY {
                0.0
            } else {
                f64::INFINITY
            }
        }
        Len::Fin(w) if overflows(w) => {
            if got == f64::INFINITY {
                0.0
            } else {
                f64::INFINITY
            }
        }
        Len::Fin(w) => {
            if !got.is_finite() {
                f64::INFINITY
            } else {
                rel_err_exact(got, w)
            }
        }
    }
}

/// The worst error of one form and the cases that exceed the documented
/// bound, printed when dropped (also when a test fails, so the numbers are
/// always shown); [`Worst::finish`] fails the test if any case exceeded
/// its bound (after the whole run, so the statistics cover every case).
struct Worst {
    name: String,
    n: usize,
    err: f64,
    at: String,
    viol: usize,
    viol_ratio: f64,
    viol_at: String,
}

impl Worst {
    fn new(name: impl Into<String>) -> Self {
        Worst {
            name: name.into(),
            n: 0,
            err: 0.0,
            at: String::new(),
            viol: 0,
            viol_ratio: 0.0,
            viol_at: String::new(),
        }
    }
    fn add(&mut self, err: f64, bound: f64, at: impl Fn() -> String) {
        self.n += 1;
        if err > bound || err.is_nan() {
            self.viol += 1;
            let ratio = if err.is_nan() {
                f64::INFINITY
            } else {
                err / bound
            };
            if ratio >= self.viol_ratio {
                self.viol_ratio = ratio;
                self.viol_at = format!("rel err {err:e} > bound {bound:e}: {}", at());
            }
            return;
        }
        if err > self.err {
            self.err = err;
            self.at = at();
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
        if self.n > 0 {
            println!(
                "{}: {} cases, worst relative error {:.3e} ({:.2} ulp) at {}",
                self.name,
                self.n - self.viol,
                self.err,
                self.err / f64::EPSILON,
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

struct Acc {
    crossing: Worst,
    half: Worst,
    slab: Worst,
    /// Rays whose slope `n·ω` underflows, treated as parallel.
    tiny: usize,
    name: String,
}

impl Drop for Acc {
    fn drop(&mut self) {
        if self.tiny > 0 {
            println!(
                "{}: {} rays with |n·ω| < 2^-1022 treated as parallel (allowed)",
                self.name, self.tiny
            );
        }
    }
}

impl Acc {
    fn new(what: &str) -> Self {
        Acc {
            crossing: Worst::new(format!("{what}: HalfSpace::crossing")),
            half: Worst::new(format!("{what}: HalfSpace::segment")),
            slab: Worst::new(format!("{what}: Slab::segment")),
            tiny: 0,
            name: what.to_string(),
        }
    }
    fn finish(&self) {
        self.crossing.finish();
        self.half.finish();
        self.slab.finish();
    }
}

/// Checks `crossing`, `HalfSpace::segment` and `Slab::segment` (the slab
/// `h ≤ n·x ≤ h + thick`) for the intervals given plus the whole line and
/// half lines from 0 and from the crossing.
fn check<const D: usize>(
    acc: &mut Acc,
    normal: [f64; D],
    h: f64,
    thick: f64,
    o: [f64; D],
    w_in: [f64; D],
    ivs: &[(f64, f64)],
) {
    let hs = HalfSpace::new(normal, h).unwrap();
    let ray = &Ray::new(o, w_in).unwrap();
    let n = hs.normal().get();
    let w = ray.dir().get();
    // The constructors' inputs (reproducible) and the stored unit vectors.
    let ctx = |t0: f64, t1: f64| {
        format!("HalfSpace::new({normal:?}, {h:e}), Ray::new({o:?}, {w_in:?}) (stored n={n:?}, w={w:?}) [{t0:e}, {t1:e}]")
    };
    // crossing
    let c = slope(&n, &w);
    // A slope below the double range (`|n·ω| < 2⁻¹⁰²²`, e.g. components
    // 3e-169 and 3e-251 multiplied) underflows in any double arithmetic: the
    // ray may then be treated as parallel (crossing `None`, kept or dropped
    // whole by the sign of `n·o − h`).
    let tiny = c.signum() != 0 && c.to_f64().abs() < f64::MIN_POSITIVE;
    let got = hs.crossing(ray);
    let mut ts = f64::NAN;
    if c.signum() == 0 {
        assert_eq!(got, None, "parallel: {}", ctx(0.0, 0.0));
    } else if tiny && got.is_none() {
        acc.tiny += 1;
    } else {
        let want = excess(&n, h, &o).neg().div(&c);
        let g = got.unwrap_or_else(|| panic!("crossing None: {}", ctx(0.0, 0.0)));
        let e = if overflows(&want) {
            if g == f64::INFINITY * f64::from(want.signum()) {
                0.0
            } else {
                f64::INFINITY
            }
        } else if want.signum() == 0 {
            g.abs()
        } else if g.is_finite() {
            rel_err_exact(g, &want)
        } else {
            f64::INFINITY
        };
        acc.crossing
            .add(e, TWO_ULP, || format!("got {g:e}: {}", ctx(0.0, 0.0)));
        ts = g;
    }
    let mut all: Vec<(f64, f64)> = ivs.to_vec();
    all.extend([
        (f64::NEG_INFINITY, f64::INFINITY),
        (0.0, f64::INFINITY),
        (f64::NEG_INFINITY, 0.0),
        (-1.0, 1.0),
    ]);
    if ts.is_finite() {
        all.extend([
            (ts, f64::INFINITY),
            (f64::NEG_INFINITY, ts),
            (0.0, ts),
            (ts, 2.0 * ts),
        ]);
    }
    let slab = Slab::new(normal, h, h + thick).unwrap();
    let (h0, h1) = slab.offsets();
    assert_eq!(slab.normal().get(), n);
    // Documented: a few ulp relative, plus a few 2⁻¹⁰⁷⁴/|n·ω| absolute when
    // the products of coordinates in the excess underflow (inputs ≲ 1e-290).
    let floor = 64.0 * f64::from_bits(1) / c.to_f64().abs();
    let underflow_ok = |got: f64, want: &Len| match want {
        Len::Fin(w) => (got - w.to_f64()).abs() <= floor,
        Len::Inf => false,
    };
    for (t0, t1) in all {
        let want = exact_half(&n, h, &o, &w, t0, t1);
        let got = hs.segment(ray, t0, t1);
        let mut e = len_err(got, &want);
        if underflow_ok(got, &want) {
            e = 0.0;
        }
        if tiny {
            e = e.min(len_err(got, &exact_half_c(&n, h, &o, &Dy::zero(), t0, t1)));
        }
        acc.half.add(e, FEW_ULP, || {
            format!("got {got:e} want {want}: {}", ctx(t0, t1))
        });
        let want = exact_slab(&n, h0, h1, &o, &w, t0, t1);
        let got = slab.segment(ray, t0, t1);
        let mut e = len_err(got, &want);
        if underflow_ok(got, &want) {
            e = 0.0;
        }
        if tiny {
            e = e.min(len_err(
                got,
                &exact_slab_c(&n, h0, h1, &o, &Dy::zero(), t0, t1),
            ));
        }
        acc.slab.add(e, FEW_ULP, || {
            format!(
                "slab [{h0:e}, {h1:e}] got {got:e} want {want}: {}",
                ctx(t0, t1)
            )
        });
        // Reversed ends are empty.
        if t0 < t1 {
            assert_eq!(hs.segment(ray, t1, t0), 0.0);
            assert_eq!(slab.segment(ray, t1, t0), 0.0);
        }
    }
}

// ---------------------------------------------------------------------------
// Proptest: the crate's strategies
// ---------------------------------------------------------------------------

fn strategy_planes<const D: usize>(cases: u32) {
    let acc = RefCell::new(Acc::new(&format!("{D}D strategies")));
    proptest!(config(cases), |(
        normal in strategy::direction::<D>(),
        w in prop_oneof![strategy::direction::<D>(), strategy::near_axis_direction::<D>()],
        p in strategy::centre::<D>(),
        h in prop_oneof![-10.0f64..10.0, strategy::log_uniform(-300.0, 300.0)],
        thick in strategy::log_uniform(-15.0, 15.0),
        s in prop_oneof![-3.0f64..3.0, strategy::log_uniform(0.0, 300.0)],
        len in strategy::log_uniform(-15.0, 3.0),
    )| {
        let t0 = s * (1.0 + thick.abs().min(1.0));
        check(&mut acc.borrow_mut(), normal, h, thick, p, w, &[(t0, t0 + len), (s, s), (-s, s.abs())]);
    });
    acc.borrow().finish();
}

#[test]
fn strategy_planes_2d() {
    strategy_planes::<2>(500);
}

#[test]
fn strategy_planes_3d() {
    strategy_planes::<3>(500);
}

/// Near-parallel rays: the normal on an axis and the direction from
/// `strategy::near_axis_direction` on another axis (`n·ω` from 0 down to
/// `1e-300`), or the plane `x_j ≥ h` with the ray along `near_axis` of that
/// same axis; far origins.
fn strategy_near_parallel<const D: usize>(cases: u32) {
    let acc = RefCell::new(Acc::new(&format!(
        "{D}D near-parallel (near_axis_direction)"
    )));
    proptest!(config(cases), |(
        w in strategy::near_axis_direction::<D>(),
        flip in 0usize..D,
        p in strategy::centre::<D>(),
        h in -10.0f64..10.0,
        far in strategy::log_uniform(0.0, 300.0),
        thick in strategy::log_uniform(-15.0, 2.0),
        len in strategy::log_uniform(-15.0, 3.0),
    )| {
        // The ray's main axis.
        let axis = (0..D).max_by(|&a, &b| w[a].abs().total_cmp(&w[b].abs())).unwrap();
        // A normal along another axis (near-parallel) or along it.
        let k = (axis + flip) % D;
        let mut normal = [0.0; D];
        normal[k] = if flip % 2 == 0 { 1.0 } else { -1.0 };
        let mut o = p;
        o[axis] += far;
        check(&mut acc.borrow_mut(), normal, h, thick, o, w, &[(-far, -far + len), (far, far + len)]);
    });
    acc.borrow().finish();
}

#[test]
fn strategy_near_parallel_2d() {
    strategy_near_parallel::<2>(300);
}

#[test]
fn strategy_near_parallel_3d() {
    strategy_near_parallel::<3>(300);
}

// ---------------------------------------------------------------------------
// Deterministic hard cases
// ---------------------------------------------------------------------------

/// Short segments ending at (0, ±1, ±4 ulp from the rounded exact crossing)
/// or starting at the plane, or straddling it, lengths `10^{−U(0,15)}` of
/// the distance scale, for generic and near-parallel rays (`|n·ω|` down to
/// `1e-12`) from origins up to `1e12` away, and origins on the plane.
fn short_segments<const D: usize>(seed: u64, n_cases: usize) {
    let mut g = Mix(seed);
    let mut acc = Acc::new(&format!("{D}D short segments at the plane"));
    for i in 0..n_cases {
        let nrm: [f64; D] = g.unit();
        let scale = 10f64.powf(g.range(-6.0, 12.0));
        let h = g.range(-1.0, 1.0) * scale;
        // A point on (near) the plane, and a direction.
        let x: [f64; D] = {
            let y: [f64; D] = core::array::from_fn(|_| g.range(-1.0, 1.0) * scale);
            let d = (0..D).map(|j| nrm[j] * y[j]).sum::<f64>() - h;
            core::array::from_fn(|j| y[j] - d * nrm[j])
        };
        let w: [f64; D] = if i % 3 == 0 {
            // Near-parallel: tangent + ε·n.
            let t: [f64; D] = g.unit();
            let d: f64 = (0..D).map(|j| t[j] * nrm[j]).sum();
            let eps = 10f64.powf(-g.range(1.0, 12.0)) * if g.below(2) == 0 { 1.0 } else { -1.0 };
            core::array::from_fn(|j| t[j] - d * nrm[j] + eps * nrm[j])
        } else {
            g.unit()
        };
        let reach = if i % 4 == 0 {
            0.0
        } else {
            10f64.powf(g.range(-3.0, 3.0)) * scale
        };
        let o: [f64; D] = core::array::from_fn(|j| x[j] - reach * w[j]);
        let Ok(ray) = Ray::new(o, w) else { continue };
        let hs = HalfSpace::new(nrm, h).unwrap();
        let Some(ts) = hs.crossing(&ray) else {
            continue;
        };
        let ulp = |x: f64| f64::from_bits(x.abs().to_bits() + 1) - x.abs();
        let k = [0.0, 1.0, -1.0, 4.0, -4.0][g.below(5) as usize];
        let e = ts + k * ulp(ts);
        let len = (ts.abs().max(scale) * 10f64.powf(-g.range(0.0, 15.0))).max(4.0 * ulp(e));
        let thick = scale * 10f64.powf(-g.range(0.0, 12.0));
        check(
            &mut acc,
            nrm,
            h,
            thick,
            o,
            w,
            &[(e - len, e), (e, e + len), (e - 0.5 * len, e + 0.5 * len)],
        );
    }
    acc.finish();
}

#[test]
fn short_segments_ending_at_the_plane() {
    short_segments::<2>(0x91a_0002, 1500);
    short_segments::<3>(0x91a_0003, 1500);
}

/// Extreme cases: far origins (up to `1e300`), near-parallel rays down to
/// `n·ω = 1e-300` (crossings beyond the double range must be `±∞`), exactly
/// parallel rays on either side, origins exactly on the plane.
#[test]
fn extreme_rays() {
    let mut acc = Acc::new("3D extreme rays");
    let (ninf, inf) = (f64::NEG_INFINITY, f64::INFINITY);
    for eps in [0.0, 1e-300, -1e-300, 1e-200, 1e-100, 1e-30, 1e-16, -1e-8] {
        for (o, h) in [
            ([0.0, 0.0, 1.0], 0.0),
            ([0.0, 0.0, -1.0], 0.0),
            ([1e300, -1e300, 1e10], 3.0),
            ([0.3, 0.1, 0.7], 0.7),
            ([0.0, 5.0, -1e300], 1e300),
            ([1e-300, 0.0, 2e-300], 1e-300),
        ] {
            let w = [1.0, 0.5, eps];
            check(
                &mut acc,
                [0.0, 0.0, 1.0],
                h,
                1.0,
                o,
                w,
                &[(-1e300, 1e300), (ninf, 1e308), (1e-300, 2e-300)],
            );
            check(
                &mut acc,
                [1e-10, 0.0, -1.0],
                h,
                1e-20,
                o,
                w,
                &[(-1e300, 1e300), (0.0, 1e-300)],
            );
        }
    }
    // Exactly parallel: everything or nothing.
    let hs = HalfSpace::new([0.0, 1.0], 1.0).unwrap();
    let above = Ray::new([5.0, 2.0], [-1.0, 0.0]).unwrap();
    let below = Ray::new([5.0, 0.5], [-1.0, 0.0]).unwrap();
    let on = Ray::new([5.0, 1.0], [1.0, 0.0]).unwrap();
    assert_eq!(hs.crossing(&above), None);
    assert_eq!(hs.segment(&above, -2.0, 3.5), 5.5);
    assert_eq!(hs.segment(&above, ninf, inf), inf);
    assert_eq!(hs.segment(&below, ninf, inf), 0.0);
    assert_eq!(hs.segment(&on, 0.0, 1.0), 1.0);
    let slab = Slab::new([0.0, 2.0], 1.0, 1.0).unwrap();
    assert_eq!(slab.segment(&on, 0.0, 1.0), 1.0);
    assert_eq!(slab.segment(&above, 0.0, 1.0), 0.0);
    // The documented examples.
    let floor = HalfSpace::new([0.0, 0.0, 1.0], 0.0).unwrap();
    let ray = Ray::new([0.0, 0.0, 2.0], [0.0, 0.6, -0.8]).unwrap();
    assert_eq!(floor.crossing(&ray), Some(2.5));
    assert_eq!(floor.segment(&ray, 0.0, 10.0), 2.5);
    acc.finish();
}

/// `contains` against the exact sign of `n·x − h` for points on, next to and
/// away from the plane; documented exact unless `n·x − h` is within `2⁻¹⁰⁴`
/// relative of its terms.
#[test]
fn contains_is_exact() {
    let mut g = Mix(0xc0_7a1);
    let (mut n_checked, mut n_close) = (0usize, 0usize);
    for i in 0..4000 {
        let nrm: [f64; 3] = g.unit();
        let scale = 10f64.powf(g.range(-100.0, 100.0));
        let h = g.range(-1.0, 1.0) * scale;
        let hs = HalfSpace::new(nrm, h).unwrap();
        let slab = Slab::new(nrm, h, h + scale * 10f64.powf(-g.range(0.0, 16.0))).unwrap();
        let n = hs.normal().get();
        let y: [f64; 3] = core::array::from_fn(|_| g.range(-1.0, 1.0) * scale);
        let d = (0..3).map(|j| n[j] * y[j]).sum::<f64>() - h;
        let off = match i % 3 {
            0 => 0.0,
            1 => 10f64.powf(-g.range(0.0, 17.0)) * scale * g.range(-1.0, 1.0),
            _ => g.range(-1.0, 1.0) * scale,
        };
        let x: [f64; 3] = core::array::from_fn(|j| y[j] - (d - off) * n[j]);
        let ex = excess(&n, h, &x);
        let terms: f64 = (0..3).map(|j| (n[j] * x[j]).abs()).sum::<f64>() + h.abs();
        let exf = ex.to_f64();
        if exf.abs() <= 2f64.powi(-100) * terms {
            n_close += 1;
            continue;
        }
        n_checked += 1;
        assert_eq!(
            hs.contains(&x),
            ex.signum() >= 0,
            "{n:?} {h:e} {x:?}: excess {exf:e}"
        );
        let (h0, h1) = slab.offsets();
        let ex1 = excess(&n, h1, &x);
        if ex1.to_f64().abs() > 2f64.powi(-100) * (terms + h1.abs()) {
            assert_eq!(
                slab.contains(&x),
                ex.signum() >= 0 && ex1.signum() <= 0,
                "slab [{h0:e}, {h1:e}] {x:?}"
            );
        }
    }
    println!("contains: {n_checked} points decided exactly ({n_close} within 2^-100 of their terms skipped)");
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

/// The documented absolute error of one `f32` crossing against the `f64`
/// path at the same inputs: `6u(Σ|n_j o_j| + |h| + |t*|Σ|n_j d_j|)/|n·d| +
/// u(Σ|o_j| + |h|)/|n·d|`, `u = 2⁻²⁴`, `t*` the exact crossing.
fn crossing_err<const D: usize>(n: &[f64; D], h: f64, o: &[f64; D], d: &[f64; D]) -> f64 {
    let nd = slope(n, d).to_f64().abs();
    let ts = excess(n, h, o).to_f64().abs() / nd;
    let sno: f64 = (0..D).map(|j| (n[j] * o[j]).abs()).sum();
    let snd: f64 = (0..D).map(|j| (n[j] * d[j]).abs()).sum();
    let so: f64 = o.iter().map(|x| x.abs()).sum();
    6.0 * U32 * (sno + h.abs() + ts * snd) / nd + U32 * (so + h.abs()) / nd
}

/// `|n·d| ≤ 4u·Σ|n_j d_j| + 2Σ|n_j − n₃₂_j||d_j|`: the `f32` slope may have
/// the wrong sign or be 0 (documented: a ray nearly parallel to the plane
/// "may be kept or dropped whole"); the second term is the rounding of the
/// normal to `f32`, which underflows for components below `1e-45`. Also a
/// crossing beyond the `f32` range (`|t*| ≥ f32::MAX/2`, a ray nearly
/// parallel to the plane): the kernel's `t*` overflows and the ray is kept or
/// dropped whole.
fn ill_conditioned<const D: usize>(n: &[f64; D], h: f64, o: &[f64; D], d: &[f64; D]) -> bool {
    let snd: f64 = (0..D).map(|j| (n[j] * d[j]).abs()).sum();
    let r32: f64 = (0..D)
        .map(|j| (n[j] - f64::from(n[j] as f32)).abs() * d[j].abs())
        .sum();
    let nd = slope(n, d).to_f64().abs();
    nd <= 4.0 * U32 * snd + 2.0 * r32
        || excess(n, h, o).to_f64().abs() / nd >= 0.5 * f64::from(f32::MAX)
}

/// Checks a batch for a half-space and a slab: bit-identical to the scalar
/// twins, and each lane within the documented bound of the exact length of
/// the `f32` inputs (`f64` normal and offsets, as the `f64` path has them).
/// Returns the worst error/bound for (half-space, slab) and the worst
/// absolute error on well-conditioned lanes (`|n·d| ≥ 0.1`, `|o_j|, |t| ≤ 10`).
fn check_batch<const D: usize>(hs: &HalfSpace<D>, slab: &Slab<D>, b: &Batch<D>) -> (f64, f64, f64) {
    let nn = b.t0.len();
    let (mut oh, mut os) = (vec![f32::NAN; nn], vec![f32::NAN; nn]);
    hs.segment_batch_f32(&b.rays(), &mut oh).unwrap();
    slab.segment_batch_f32(&b.rays(), &mut os).unwrap();
    let n = hs.normal().get();
    let h = hs.offset();
    let (h0, h1) = slab.offsets();
    assert_eq!(slab.normal().get(), n);
    let (mut rh, mut rs, mut rel) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..nn {
        let (o, d, t0, t1) = b.lane(i);
        let sh = hs.segment_f32(o, d, t0, t1);
        let ss = slab.segment_f32(o, d, t0, t1);
        assert_eq!(sh.to_bits(), oh[i].to_bits(), "half lane {i} of {nn}");
        assert_eq!(ss.to_bits(), os[i].to_bits(), "slab lane {i} of {nn}");
        let (o64, d64) = (o.map(f64::from), d.map(f64::from));
        let (a, bb) = (f64::from(t0), f64::from(t1));
        let fin = |t: f64| if t.is_finite() { t.abs() } else { 0.0 };
        let clip = 2.0 * U32 * (fin(a) + fin(bb));
        let whole = f64::from(t1 - t0);
        let ill = ill_conditioned(&n, h, &o64, &d64)
            || ill_conditioned(&n, h0, &o64, &d64)
            || ill_conditioned(&n, h1, &o64, &d64);
        for (got, want, bound, what, r) in [
            (
                sh,
                exact_half(&n, h, &o64, &d64, a, bb),
                crossing_err(&n, h, &o64, &d64) + clip,
                "half",
                &mut rh,
            ),
            (
                ss,
                exact_slab(&n, h0, h1, &o64, &d64, a, bb),
                crossing_err(&n, h0, &o64, &d64) + crossing_err(&n, h1, &o64, &d64) + clip,
                "slab",
                &mut rs,
            ),
        ] {
            let got = f64::from(got);
            let ctx = || {
                format!("{what}: n={n:?} h={h:e} [{h0:e}, {h1:e}] o={o:?} d={d:?} [{t0:e}, {t1:e}] got {got:e} want {want}")
            };
            match &want {
                Len::Inf => assert!(got == f64::INFINITY || ill, "{}", ctx()),
                Len::Fin(w) => {
                    let w = w.to_f64();
                    if ill && (got == 0.0 || got == whole || got == f64::INFINITY) {
                        continue;
                    }
                    if w >= f64::from(f32::MAX) && got == f64::INFINITY {
                        continue;
                    }
                    let err = (got - w).abs();
                    assert!(err <= bound, "err {err:e} > bound {bound:e}: {}", ctx());
                    *r = r.max(err / bound);
                    let nd = slope(&n, &d64).to_f64().abs();
                    if nd >= 0.1
                        && fin(a) <= 10.0
                        && fin(bb) <= 10.0
                        && o64.iter().all(|x| x.abs() <= 10.0)
                    {
                        rel = rel.max(err);
                    }
                }
            }
        }
    }
    (rh, rs, rel)
}

fn strategy_f32<const D: usize>(cases: u32) {
    let worst = RefCell::new((0.0f64, 0.0f64, 0.0f64));
    proptest!(config(cases), |(
        normal in strategy::direction::<D>(),
        h in -10.0f64..10.0,
        thick in strategy::log_uniform(-3.0, 1.0),
        rays in prop::collection::vec((
            prop_oneof![strategy::direction::<D>(), strategy::near_axis_direction::<D>()],
            strategy::centre::<D>(),
            -20.0f64..20.0,
            strategy::log_uniform(-6.0, 2.0),
            0u8..4,
        ), 0..40),
    )| {
        let hs = HalfSpace::new(normal, h).unwrap();
        let slab = Slab::new(normal, h, h + thick).unwrap();
        let mut b = Batch::<D>::new();
        for (w, p, t, l, kind) in &rays {
            let (t0, t1) = match kind {
                0 => (f32::NEG_INFINITY, f32::INFINITY),
                1 => (*t as f32, f32::INFINITY),
                _ => (*t as f32, (t + l) as f32),
            };
            b.push(p.map(|x| x as f32), w.map(|x| x as f32), t0, t1);
        }
        let (a, s, r) = check_batch(&hs, &slab, &b);
        let mut m = worst.borrow_mut();
        m.0 = m.0.max(a);
        m.1 = m.1.max(s);
        m.2 = m.2.max(r);
    });
    let m = worst.borrow();
    println!(
        "{D}D f32 planes (strategy batches): worst error/bound half-space {:.3}, slab {:.3}; worst absolute error on well-conditioned lanes {:.2e}",
        m.0, m.1, m.2
    );
}

#[test]
fn f32_batch_from_strategies_2d() {
    strategy_f32::<2>(200);
}

#[test]
fn f32_batch_from_strategies_3d() {
    strategy_f32::<3>(200);
}

/// Deterministic batches of every length `0 … 17` and a few longer ones,
/// origins near the plane and segments ending at the `f64` crossing.
#[test]
fn f32_batch_deterministic() {
    fn run<const D: usize>() -> (f64, f64, f64) {
        let mut g = Mix(0xf32_91a + D as u64);
        let mut worst = (0.0f64, 0.0f64, 0.0f64);
        for n in (0..=17).chain([31, 64, 203]) {
            let nrm: [f64; D] = g.unit();
            let h = g.range(-2.0, 2.0);
            let hs = HalfSpace::new(nrm, h).unwrap();
            let slab = Slab::new(nrm, h, h + g.range(0.0, 1.0)).unwrap();
            let mut b = Batch::<D>::new();
            for i in 0..n {
                let o: [f32; D] = core::array::from_fn(|_| g.range(-3.0, 3.0) as f32);
                let w: [f64; D] = g.unit();
                let d = w.map(|x| x as f32);
                let ray = Ray::new(o.map(f64::from), d.map(f64::from)).unwrap();
                let (t0, t1) = match (i % 4, hs.crossing(&ray)) {
                    (0, _) => (f32::NEG_INFINITY, f32::INFINITY),
                    (1, Some(t)) => (t as f32, (t + g.f()) as f32),
                    (2, Some(t)) => ((t - g.f()) as f32, t as f32),
                    _ => {
                        let a = g.range(-5.0, 5.0);
                        (a as f32, (a + g.range(0.0, 3.0)) as f32)
                    }
                };
                b.push(o, d, t0, t1);
            }
            let (a, s, r) = check_batch(&hs, &slab, &b);
            worst = (worst.0.max(a), worst.1.max(s), worst.2.max(r));
        }
        worst
    }
    let w2 = run::<2>();
    let w3 = run::<3>();
    println!(
        "f32 planes (deterministic batches): worst error/bound half-space 2D {:.3}, 3D {:.3}; slab 2D {:.3}, 3D {:.3}; worst absolute error on well-conditioned lanes 2D {:.2e}, 3D {:.2e}",
        w2.0, w3.0, w2.1, w3.1, w2.2, w3.2
    );
}

#[test]
fn f32_batch_rejects_mismatched_lengths() {
    let hs = HalfSpace::<2>::new([0.0, 1.0], 0.0).unwrap();
    let slab = Slab::<2>::new([0.0, 1.0], 0.0, 1.0).unwrap();
    let mut b = Batch::<2>::new();
    for _ in 0..11 {
        b.push([0.0; 2], [1.0, 0.0], 0.0, 1.0);
    }
    let mut out = vec![0.0f32; 10];
    assert!(matches!(
        hs.segment_batch_f32(&b.rays(), &mut out),
        Err(ParamError::Length {
            name: "out",
            expected: 11,
            got: 10
        })
    ));
    assert!(matches!(
        slab.segment_batch_f32(&b.rays(), &mut out),
        Err(ParamError::Length { name: "out", .. })
    ));
    let mut rays = b.rays();
    rays.origin[0] = &b.o[0][..3];
    let mut out = vec![0.0f32; 11];
    assert!(matches!(
        hs.segment_batch_f32(&rays, &mut out),
        Err(ParamError::Length { name: "origin", .. })
    ));
    assert!(matches!(
        slab.segment_batch_f32(&rays, &mut out),
        Err(ParamError::Length { name: "origin", .. })
    ));
}

// ---------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------

#[test]
fn constructors_reject_bad_input() {
    use ParamError::*;
    assert_eq!(HalfSpace::<3>::new([0.0; 3], 1.0), Err(ZeroDirection));
    assert_eq!(
        HalfSpace::<2>::new([f64::NAN, 1.0], 1.0),
        Err(NonFinite { name: "direction" })
    );
    assert_eq!(
        HalfSpace::<2>::new([0.0, 1.0], f64::NAN),
        Err(NonFinite { name: "offset" })
    );
    assert_eq!(
        HalfSpace::<2>::new([0.0, 1.0], f64::INFINITY),
        Err(NonFinite { name: "offset" })
    );
    assert_eq!(
        HalfSpace::<4>::new([1.0; 4], 0.0),
        Err(Dimension { dim: 4 })
    );
    assert_eq!(HalfSpace::<1>::new([1.0], 0.0), Err(Dimension { dim: 1 }));
    assert_eq!(Slab::<3>::new([0.0; 3], 0.0, 1.0), Err(ZeroDirection));
    assert_eq!(
        Slab::<3>::new([0.0, f64::INFINITY, 0.0], 0.0, 1.0),
        Err(NonFinite { name: "direction" })
    );
    assert_eq!(
        Slab::<2>::new([0.0, 1.0], f64::NAN, 1.0),
        Err(NonFinite { name: "h0" })
    );
    assert_eq!(
        Slab::<2>::new([0.0, 1.0], 0.0, f64::NEG_INFINITY),
        Err(NonFinite { name: "h1" })
    );
    assert!(matches!(
        Slab::<2>::new([0.0, 1.0], 1.0, 0.5),
        Err(OutOfRange { name: "h1", .. })
    ));
    assert_eq!(
        Slab::<4>::new([1.0; 4], 0.0, 1.0),
        Err(Dimension { dim: 4 })
    );
    assert!(Slab::<2>::new([0.0, 1.0], 1.0, 1.0).is_ok());
    // The normal is normalised.
    let hs = HalfSpace::<2>::new([0.0, 1e-310], 2.0).unwrap();
    assert_eq!(hs.normal().get(), [0.0, 1.0]);
    assert_eq!(hs.offset(), 2.0);
}

#[test]
fn methods_do_not_panic_on_bad_ends() {
    let (ninf, inf, nan) = (f64::NEG_INFINITY, f64::INFINITY, f64::NAN);
    let hs = HalfSpace::<3>::new([0.3, -0.2, 0.9], 0.5).unwrap();
    let slab = Slab::<3>::new([0.3, -0.2, 0.9], 0.5, 2.0).unwrap();
    for o in [[0.0; 3], [1e308, -1e308, 1e308], [-f64::MAX, 0.0, f64::MAX]] {
        for w in [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [1.0, 1e-300, 0.0]] {
            let ray = Ray::new(o, w).unwrap();
            let _ = hs.crossing(&ray);
            let _ = hs.contains(&o);
            let _ = slab.contains(&o);
            for (t0, t1) in [
                (nan, nan),
                (nan, 1.0),
                (0.0, nan),
                (ninf, inf),
                (inf, ninf),
                (inf, inf),
                (ninf, ninf),
                (1.0, 0.0),
                (-f64::MAX, f64::MAX),
            ] {
                let a = hs.segment(&ray, t0, t1);
                let b = slab.segment(&ray, t0, t1);
                if !(t0 <= t1) && !t0.is_nan() && !t1.is_nan() {
                    assert_eq!((a, b), (0.0, 0.0), "{o:?} {w:?} [{t0}, {t1}]");
                }
                if !t0.is_nan() && !t1.is_nan() {
                    assert!(a >= 0.0 && b >= 0.0, "{a} {b}");
                }
            }
        }
    }
    for o in [[0.0f32; 3], [f32::NAN, 0.0, 0.0], [f32::INFINITY, 0.0, 0.0]] {
        for d in [[1.0f32, 0.0, 0.0], [0.0; 3], [f32::NAN; 3]] {
            for (t0, t1) in [
                (f32::NAN, 1.0),
                (f32::NEG_INFINITY, f32::INFINITY),
                (1.0, 0.0),
            ] {
                let _ = hs.segment_f32(o, d, t0, t1);
                let _ = slab.segment_f32(o, d, t0, t1);
            }
        }
    }
    assert_eq!(hs.segment_f32([0.0; 3], [1.0, 0.0, 0.0], 1.0, 0.0), 0.0);
    assert_eq!(slab.segment_f32([0.0; 3], [1.0, 0.0, 0.0], 1.0, 0.0), 0.0);
}

/// Inputs found by the tests above where the documented "relative error a
/// few ulp" of `HalfSpace::segment` / `Slab::segment` fails (each printed
/// with the exact value; see the report):
/// 1. a crossing beyond the double range (`n·ω = 1e-300`): the kept half
///    line `[t*, ∞)` is infinitely long but comes out as 0, and a slab whose
///    two crossings both overflow has finite length `(h1 − h0)/|n·ω|` but
///    comes out as 0 (`∞ − ∞` clamped);
/// 2. a thin slab far along the ray: the length is the difference of two
///    double-double crossings, relative error `≈ 2⁻¹⁰⁴·|t*|/L`;
/// 3. a kept piece far shorter than `2⁻⁵⁰` of the terms of `n·o − h`
///    (segment ending within `1e-31` of the plane): `n·o − h` in
///    double-double is only `2⁻¹⁰⁴`-accurate relative to its terms.
#[test]
fn documented_bound_regressions() {
    fn half<const D: usize>(
        n: [f64; D],
        h: f64,
        o: [f64; D],
        w: [f64; D],
        t0: f64,
        t1: f64,
    ) -> bool {
        let hs = HalfSpace::new(n, h).unwrap();
        let ray = Ray::new(o, w).unwrap();
        let (nn, ww) = (hs.normal().get(), ray.dir().get());
        let want = exact_half(&nn, h, &o, &ww, t0, t1);
        let got = hs.segment(&ray, t0, t1);
        let e = len_err(got, &want);
        println!("HalfSpace n={nn:?} h={h:e} o={o:?} w={ww:?} [{t0:e}, {t1:e}]: got {got:e}, exact {want}, rel err {e:.3e}");
        e <= FEW_ULP
    }
    fn slab<const D: usize>(
        n: [f64; D],
        h0: f64,
        h1: f64,
        o: [f64; D],
        w: [f64; D],
        t0: f64,
        t1: f64,
    ) -> bool {
        let sl = Slab::new(n, h0, h1).unwrap();
        let ray = Ray::new(o, w).unwrap();
        let (nn, ww) = (sl.normal().get(), ray.dir().get());
        let want = exact_slab(&nn, h0, h1, &o, &ww, t0, t1);
        let got = sl.segment(&ray, t0, t1);
        let e = len_err(got, &want);
        println!("Slab n={nn:?} [{h0:e}, {h1:e}] o={o:?} w={ww:?} [{t0:e}, {t1:e}]: got {got:e}, exact {want}, rel err {e:.3e}");
        e <= FEW_ULP
    }
    let (ninf, inf) = (f64::NEG_INFINITY, f64::INFINITY);
    let ok = [
        // 1. y ≥ 0 from y = −1e10 along (1, 1e-300): t* = 1e310.
        half([0.0, 1.0], 0.0, [0.0, -1e10], [1.0, 1e-300], 0.0, inf),
        // 1. 0 ≤ y ≤ 1 along the same ray: exact length 1e300.
        slab([0.0, 1.0], 0.0, 1.0, [0.0, -1e10], [1.0, 1e-300], ninf, inf),
        // 2. (from strategy::direction/centre/log_uniform) a slab 4e-14
        //    thick crossed 7e9 along the ray.
        slab(
            [0.0, 0.0, -1.0],
            0.0,
            4.028107412216545e-14,
            [-1.0, -1.0, -6591285568.967644],
            [0.0, 0.33946811095455753, -0.9406175639679201],
            ninf,
            inf,
        ),
        // 2. (from strategy::near_axis_direction) a unit slab crossed at
        //    t = 3.6e279: comes out as 0.
        slab(
            [0.0, 1.0],
            0.0,
            1.0,
            [0.0, 3.564149075564363e279],
            [-9.999999950000001e-5, -0.999999995],
            ninf,
            inf,
        ),
        // 3. (from short_segments_ending_at_the_plane) the kept piece of
        //    [−∞, t1] is 4.4e-32 long, t1 = −1.9e-15 next to the crossing.
        half(
            [-0.18529575969184192, -0.9826827979771617],
            26.55859080959911,
            [13.523361860953461, -29.57659631270725],
            [0.014331435021785726, -0.07514709116933291],
            ninf,
            -1.9264381365372865e-15,
        ),
    ];
    assert!(ok.iter().all(|&b| b), "documented bound exceeded: {ok:?}");
}
