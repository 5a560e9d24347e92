//! Volumetric caustics (`linesample_scene::caustic`) against references that
//! share nothing with the module's algorithms:
//!
//! 1. **Beam closed form against 60-digit quadrature.**
//!    `scene/tests/data/caustic_ref.csv` (written by `tools/caustic_ref.py`,
//!    mpmath at 60 digits) finds the chord ends of `Q` along each segment's
//!    ray `o + t·w` by bisection on `|o + tw − c|² − r²` (checked against
//!    `polyroots`), clips them to `[0, length]` and integrates
//!    `σ_s·w_k·e^{−σ_t(start + t)}` with `mp.quad`. `w` is the direction
//!    exactly as `Ray::new` stores it (`Direction::new` replicated in double
//!    arithmetic; asserted here bit for bit). Every case must hold `10⁻¹²`
//!    relative; zero references (misses) must give exactly 0.
//! 2. **Whole pipeline against an independent tracer** (same file): Snell's
//!    law and mirror reflection in the angle formulation, Fresnel from the
//!    angle forms `sin²(θᵢ − θₜ)/sin²(θᵢ + θₜ)`, `tan²(θᵢ − θₜ)/tan²(θᵢ + θₜ)`,
//!    the weight bookkeeping of the module docs, all at 60 digits: every
//!    segment of `Caustic::trace` (origin, direction, start, length, weight
//!    `≤ 10⁻¹³`, down to incidence `1 − b/r = 10⁻⁶` from grazing: measured
//!    `8.8e−15` there, since the exits reuse the entry's cosine; forming
//!    `cos θₒ = √(1 − n² sin²θ₂)` instead cancelled to `1.0e−12`), and
//!    `Caustic::beam` of the traced path in three query balls per path
//!    (`≤ 10⁻¹¹` relative where the value is well-conditioned). Plus
//!    `ConeEmitter::direction` against its formula.
//! 3. **Energy bookkeeping**: with `σ_a = 0` and `Q` a ball of radius `10⁴`
//!    around the light, the beam is the scattered fraction
//!    `(1 − e^{−σ_t L₀}) + e^{−σ_t L₀}·(1 − T₁R₁^{K+1})` with `R₁` from an
//!    independent Fresnel (angle forms, `θᵢ` from the impact parameter);
//!    reciprocity of the internal reflections; `refract`, `reflect`,
//!    `fresnel_reflectance` against the angle forms, total internal
//!    reflection included.
//! 4. **Points are unbiased for the beam**, deterministically: the midpoint
//!    rule over `s` of `Caustic::point` with `2²⁰` points against
//!    `Caustic::beam`, within one cell per discontinuity.
//! 5. **Bad input**: every constructor names the parameter.
//!
//! Deterministic (no randomness at run time; the file's cases are seeded).

use linesample::world::{Ray, Sphere};
use linesample::ParamError;
use linesample_scene::caustic::{
    fresnel_reflectance, reflect, refract, Caustic, ConeEmitter, Fresnel, Glass, Medium,
    PhotonPath, Segment, MAX_INTERNAL_REFLECTIONS, MAX_SEGMENTS,
};
use std::collections::BTreeMap;
use std::f64::consts::PI;

// ------------------------------------------------------------------ vectors

fn dot<const D: usize>(a: [f64; D], b: [f64; D]) -> f64 {
    (0..D).map(|j| a[j] * b[j]).sum()
}
fn sub<const D: usize>(a: [f64; D], b: [f64; D]) -> [f64; D] {
    core::array::from_fn(|j| a[j] - b[j])
}
fn add<const D: usize>(a: [f64; D], b: [f64; D]) -> [f64; D] {
    core::array::from_fn(|j| a[j] + b[j])
}
fn scale<const D: usize>(a: [f64; D], s: f64) -> [f64; D] {
    core::array::from_fn(|j| a[j] * s)
}
fn norm<const D: usize>(a: [f64; D]) -> f64 {
    dot(a, a).sqrt()
}
fn unit<const D: usize>(a: [f64; D]) -> [f64; D] {
    scale(a, 1.0 / norm(a))
}
/// The first `D` components.
fn cut<const D: usize>(v: [f64; 3]) -> [f64; D] {
    core::array::from_fn(|j| v[j])
}
/// The part of `d` orthogonal to the unit `n`.
fn tangential<const D: usize>(d: [f64; D], n: [f64; D]) -> [f64; D] {
    sub(d, scale(n, dot(d, n)))
}
fn max_abs_diff<const D: usize>(a: [f64; D], b: [f64; D]) -> f64 {
    (0..D).map(|j| (a[j] - b[j]).abs()).fold(0.0, f64::max)
}

// ------------------------------------------------------------ the data file

/// `bseg`: one segment of a `bcase` path.
#[derive(Clone, Debug)]
struct BSeg {
    o: [f64; 3],
    d: [f64; 3],
    w: [f64; 3],
    start: f64,
    length: f64,
    weight: f64,
}

/// `bcase`: a path, a query ball and a medium, and the beam reference.
#[derive(Clone, Debug)]
struct BCase {
    case: usize,
    class: String,
    dim: usize,
    qc: [f64; 3],
    qr: f64,
    sigma_s: f64,
    sigma_a: f64,
    g_min: f64,
    ref_hi: f64,
    ref_lo: f64,
    segs: Vec<BSeg>,
}

/// `tseg`: one segment of the independent tracer's path (unit direction).
#[derive(Clone, Debug)]
struct TSeg {
    o: [f64; 3],
    w: [f64; 3],
    start: f64,
    length: f64,
    weight: f64,
}

/// `tbeam`: the beam of a traced path in one query ball and medium.
#[derive(Clone, Debug)]
struct TBeam {
    qc: [f64; 3],
    qr: f64,
    sigma_s: f64,
    sigma_a: f64,
    ref_hi: f64,
    ref_lo: f64,
    kappa: f64,
    robust: bool,
}

/// `trace`: a scene (light, glass, Fresnel model) and an emission direction.
#[derive(Clone, Debug)]
struct TCase {
    case: usize,
    class: String,
    dim: usize,
    light: [f64; 3],
    gc: [f64; 3],
    gr: f64,
    ior: f64,
    k: i64,
    dir: [f64; 3],
    impact: f64,
    segs: Vec<TSeg>,
    beams: Vec<TBeam>,
}

fn fresnel_of(k: i64) -> Fresnel {
    if k < 0 {
        Fresnel::Off
    } else {
        Fresnel::On {
            internal_reflections: k as u32,
        }
    }
}

/// `|got − ref|/|ref|` with the reference as `hi + lo`.
fn rel_err(got: f64, hi: f64, lo: f64) -> f64 {
    ((got - hi) - lo).abs() / hi.abs()
}

fn data() -> (Vec<BCase>, Vec<TCase>) {
    let text = include_str!("data/caustic_ref.csv");
    let (mut bc, mut tc): (Vec<BCase>, Vec<TCase>) = (Vec::new(), Vec::new());
    for l in text.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<&str> = l.split(',').collect();
        let v = |i: usize| -> f64 { f[i].parse().unwrap_or_else(|_| panic!("{l}")) };
        let v3 = |i: usize| [v(i), v(i + 1), v(i + 2)];
        let n = |i: usize| -> usize { f[i].parse().unwrap() };
        match f[0] {
            "bcase" => {
                assert_eq!(f.len(), 14, "{l}");
                assert_eq!(n(1), bc.len(), "{l}");
                bc.push(BCase {
                    case: n(1),
                    class: f[2].to_string(),
                    dim: n(3),
                    qc: v3(4),
                    qr: v(7),
                    sigma_s: v(8),
                    sigma_a: v(9),
                    g_min: v(11),
                    ref_hi: v(12),
                    ref_lo: v(13),
                    segs: Vec::with_capacity(n(10)),
                });
            }
            "bseg" => {
                assert_eq!(f.len(), 15, "{l}");
                let c = bc.last_mut().unwrap();
                assert_eq!((n(1), n(2)), (c.case, c.segs.len()), "{l}");
                c.segs.push(BSeg {
                    o: v3(3),
                    d: v3(6),
                    w: v3(9),
                    start: v(12),
                    length: v(13),
                    weight: v(14),
                });
            }
            "trace" => {
                assert_eq!(f.len(), 18, "{l}");
                assert_eq!(n(1), tc.len(), "{l}");
                tc.push(TCase {
                    case: n(1),
                    class: f[2].to_string(),
                    dim: n(3),
                    light: v3(4),
                    gc: v3(7),
                    gr: v(10),
                    ior: v(11),
                    k: f[12].parse().unwrap(),
                    dir: v3(13),
                    impact: v(17),
                    segs: Vec::with_capacity(n(16)),
                    beams: Vec::new(),
                });
            }
            "tseg" => {
                assert_eq!(f.len(), 12, "{l}");
                let c = tc.last_mut().unwrap();
                assert_eq!((n(1), n(2)), (c.case, c.segs.len()), "{l}");
                c.segs.push(TSeg {
                    o: v3(3),
                    w: v3(6),
                    start: v(9),
                    length: v(10),
                    weight: v(11),
                });
            }
            "tbeam" => {
                assert_eq!(f.len(), 12, "{l}");
                let c = tc.last_mut().unwrap();
                assert_eq!(n(1), c.case, "{l}");
                c.beams.push(TBeam {
                    qc: v3(2),
                    qr: v(5),
                    sigma_s: v(6),
                    sigma_a: v(7),
                    ref_hi: v(8),
                    ref_lo: v(9),
                    kappa: v(10),
                    robust: f[11] == "1",
                });
            }
            k => panic!("unknown record kind {k}: {l}"),
        }
    }
    for c in &bc {
        assert!(!c.segs.is_empty(), "case {}", c.case);
    }
    (bc, tc)
}

/// A scene whose light and glass are far from everything (for scoring paths
/// built by hand: only the medium and `Q` matter to `beam` and `point`).
fn scoring_scene<const D: usize>(q: Sphere<D>, m: Medium) -> Caustic<D> {
    let mut far = [0.0; D];
    far[0] = 1e9;
    Caustic::new(
        ConeEmitter::new([0.0; D], far, 0.1).unwrap(),
        Glass::new(far, 1.0, 1.5).unwrap(),
        m,
        q,
        Fresnel::Off,
    )
    .unwrap()
}

// ------------------------------------------------------------ 1. beams

fn beam_case<const D: usize>(c: &BCase) -> f64 {
    let segs: Vec<Segment<D>> = c
        .segs
        .iter()
        .map(|s| {
            let ray = Ray::new(cut::<D>(s.o), cut::<D>(s.d)).unwrap();
            let w = ray.dir().get();
            assert!(
                (0..D).all(|j| w[j].to_bits() == s.w[j].to_bits()),
                "case {}: Ray::new stored {w:?}, the reference used {:?}",
                c.case,
                s.w
            );
            Segment {
                ray,
                start: s.start,
                length: s.length,
                weight: s.weight,
            }
        })
        .collect();
    let path = PhotonPath::new(&segs).unwrap();
    let scene = scoring_scene(
        Sphere::new(cut::<D>(c.qc), c.qr).unwrap(),
        Medium::new(c.sigma_s, c.sigma_a).unwrap(),
    );
    scene.beam(&path)
}

/// Test 1. `Caustic::beam` of hand-built paths against 60-digit quadrature.
#[test]
fn beam_matches_quadrature() {
    let (cases, _) = data();
    assert!(cases.len() >= 40, "{} cases", cases.len());
    let mut worst: BTreeMap<&str, (f64, usize, usize)> = BTreeMap::new();
    let (mut zeros, mut grazing) = (0, [0usize; 4]);
    for c in &cases {
        let got = match c.dim {
            2 => beam_case::<2>(c),
            3 => beam_case::<3>(c),
            d => panic!("dimension {d}"),
        };
        let e = worst.entry(&c.class).or_insert((0.0, 0, 0));
        e.2 += 1;
        if c.ref_hi == 0.0 {
            assert_eq!(
                got, 0.0,
                "case {} ({}): reference 0, beam {got:e}",
                c.case, c.class
            );
            zeros += 1;
            continue;
        }
        let err = rel_err(got, c.ref_hi, c.ref_lo);
        assert!(
            err <= 1e-12,
            "case {} ({}): beam {got:e}, reference {:e}, relative error {err:.2e}",
            c.case,
            c.class,
            c.ref_hi
        );
        if err > e.0 {
            (e.0, e.1) = (err, c.case);
        }
        for (k, g) in [1e-3, 1e-6, 1e-9, 1e-12].iter().enumerate() {
            if c.g_min > 0.5 * g && c.g_min < 2.0 * g {
                grazing[k] += 1;
            }
        }
    }
    // The file covers what it should.
    let count = |pred: &dyn Fn(&BCase) -> bool| cases.iter().filter(|c| pred(c)).count();
    assert!(grazing.iter().all(|&k| k >= 3), "grazing cases {grazing:?}");
    assert!(zeros >= 8, "{zeros} zero references");
    assert!(count(&|c| c.dim == 2) >= 15 && count(&|c| c.dim == 3) >= 15);
    assert!(count(&|c| c.qr <= 1e-6) >= 2 && count(&|c| c.qr >= 1e3) >= 2);
    assert!(count(&|c| c.segs.len() >= 3 && c.ref_hi > 0.0) >= 3);
    let st = |c: &BCase| c.sigma_s + c.sigma_a;
    assert!(count(&|c| st(c) <= 1.001e-3) >= 1 && count(&|c| st(c) >= 99.9) >= 1);
    assert!(
        count(&|c| c
            .segs
            .iter()
            .any(|s| s.length.is_finite() && s.length > 0.0))
            >= 5
    );
    eprintln!(
        "beam vs quadrature: {} cases ({zeros} exactly 0); worst relative error by class:",
        cases.len()
    );
    for (class, (err, case, n)) in &worst {
        eprintln!("  {class:<14} {n:>3} cases  {err:.2e} (case {case})");
    }
}

// ------------------------------------------------------------ 2. traces

/// What the trace check measured.
#[derive(Default, Debug)]
struct TraceStats {
    paths: usize,
    segments: usize,
    origin: f64,
    dir: f64,
    weight: f64,
    dir_grazing: f64,
    weight_grazing: f64,
    start: f64,
    length: f64,
    beams: usize,
    zero_beams: usize,
    beam_worst: f64,
    beam_clear: f64,
    beam_grazing: f64,
    ill: Vec<(usize, f64, f64)>,
    by_class: BTreeMap<String, [f64; 4]>,
}

fn trace_case<const D: usize>(c: &TCase, st: &mut TraceStats) {
    let light = ConeEmitter::new(cut::<D>(c.light), cut::<D>(c.dir), 0.5).unwrap();
    let glass = Glass::new(cut::<D>(c.gc), c.gr, c.ior).unwrap();
    let dir: [f64; D] = cut(c.dir);
    // cos θᵢ = √(1 − (b/r)²) of the incidence (1 for a miss). The exits
    // reuse the entry's cos θᵢ and R (the ball's symmetry), so even near
    // grazing the directions and weights hold the flat 1e−13 (forming
    // cos θₒ = √(1 − η² sin²θ₂) at the exit instead cancelled to 1e−12 at
    // 1 − b/r = 1e−6).
    let cos_i = if c.impact > 0.0 && c.impact <= 1.0 {
        (c.impact * (2.0 - c.impact)).sqrt()
    } else {
        1.0
    };
    let tol_g = 1e-13;
    let mut first = None;
    for b in &c.beams {
        let scene = Caustic::new(
            light,
            glass,
            Medium::new(b.sigma_s, b.sigma_a).unwrap(),
            Sphere::new(cut::<D>(b.qc), b.qr).unwrap(),
            fresnel_of(c.k),
        )
        .unwrap();
        let path = scene.trace(dir);
        let segs = path.segments();
        let what = format!("trace case {} ({}, K = {})", c.case, c.class, c.k);
        assert_eq!(segs.len(), c.segs.len(), "{what}: {segs:?}");
        assert_eq!(
            path.hit_glass(),
            c.impact > 0.0 && !c.class.ends_with("-behind"),
            "{what}"
        );
        if first.is_none() {
            for (i, (g, r)) in segs.iter().zip(&c.segs).enumerate() {
                let e_o = max_abs_diff(g.ray.origin(), cut::<D>(r.o));
                let e_d = max_abs_diff(g.ray.dir().get(), cut::<D>(r.w));
                let e_w = (g.weight - r.weight).abs();
                let e_s = (g.start - r.start).abs();
                let cl = st
                    .by_class
                    .entry(format!("{} K = {}", c.class, c.k))
                    .or_insert([0.0; 4]);
                for (x, y) in cl.iter_mut().zip([e_o, e_d, e_w, e_s]) {
                    *x = x.max(y);
                }
                assert!(
                    e_o <= 1e-13 && e_s <= 1e-13 && e_d <= tol_g && e_w <= tol_g,
                    "{what}, segment {i}: origin {e_o:.1e}, direction {e_d:.1e}, weight \
                     {e_w:.1e}, start {e_s:.1e} (tolerance {tol_g:.1e})\n{g:?}\n{r:?}"
                );
                if cos_i > 0.01 {
                    st.dir = st.dir.max(e_d);
                    st.weight = st.weight.max(e_w);
                } else {
                    st.dir_grazing = st.dir_grazing.max(e_d);
                    st.weight_grazing = st.weight_grazing.max(e_w);
                }
                if r.length.is_finite() {
                    let e_l = (g.length - r.length).abs();
                    assert!(e_l <= 1e-13, "{what}: {g:?} {r:?}");
                    st.length = st.length.max(e_l);
                } else {
                    assert_eq!(g.length, f64::INFINITY, "{what}: {g:?}");
                }
                st.origin = st.origin.max(e_o);
                st.start = st.start.max(e_s);
                st.segments += 1;
            }
            st.paths += 1;
            first = Some(path);
        } else {
            // The path does not depend on Q or the medium.
            assert_eq!(Some(path), first, "{what}");
        }
        let got = scene.beam(&path);
        st.beams += 1;
        if b.ref_hi == 0.0 && b.robust {
            assert_eq!(got, 0.0, "{what}: Q {:?}: beam {got:e}, reference 0", b.qc);
            st.zero_beams += 1;
            continue;
        }
        let err = rel_err(got, b.ref_hi, b.ref_lo);
        if cos_i < 0.01 {
            // Exits near grazing: the path's own error (tol_g) times the
            // value's sensitivity.
            assert!(
                err <= 1e-11 + b.kappa * tol_g,
                "{what}: Q {:?}: relative error {err:.2e}, kappa {:.1e}",
                b.qc,
                b.kappa
            );
            st.beam_grazing = st.beam_grazing.max(err);
        } else if b.kappa <= 1e3 {
            if cos_i >= 0.1 {
                st.beam_clear = st.beam_clear.max(err);
            }
            assert!(
                err <= 1e-11,
                "{what}: Q {:?} r {}: beam {got:e}, reference {:e}, relative error {err:.2e} \
                 (kappa {:.1})",
                b.qc,
                b.qr,
                b.ref_hi,
                b.kappa
            );
            st.beam_worst = st.beam_worst.max(err);
        } else {
            // Ill-conditioned (a segment nearly tangent to Q): the paths
            // agree to ~1e−15, times the value's sensitivity.
            assert!(
                err <= 1e-11 + 1e-14 * b.kappa,
                "{what}: Q {:?}: relative error {err:.2e}, kappa {:.1e}",
                b.qc,
                b.kappa
            );
            st.ill.push((c.case, b.kappa, err));
        }
    }
}

/// Test 2. `Caustic::trace` and `Caustic::beam` against an independent tracer.
#[test]
fn trace_matches_independent_tracer() {
    let (_, cases) = data();
    let mut st = TraceStats::default();
    for c in &cases {
        match c.dim {
            2 => trace_case::<2>(c, &mut st),
            3 => trace_case::<3>(c, &mut st),
            d => panic!("dimension {d}"),
        }
    }
    // Coverage: every Fresnel mode in 2D and 3D, both indices, near-normal
    // and near-grazing incidence, misses.
    for dim in [2, 3] {
        for k in [-1, 0, 2, 5] {
            for ior in [1.5, 1.33] {
                let n = cases
                    .iter()
                    .filter(|c| c.dim == dim && c.k == k && c.ior == ior)
                    .count();
                assert!(n >= 8, "dim {dim}, K {k}, ior {ior}: {n} cases");
            }
        }
    }
    let count = |s: &str| cases.iter().filter(|c| c.class.ends_with(s)).count();
    assert!(count("-near-grazing") >= 16 && count("-near-normal") >= 12 && count("-normal") >= 8);
    assert!(count("-miss") >= 8 && count("-behind") >= 8);
    assert!(cases.iter().any(|c| c.impact > 0.0 && c.impact < 2e-6));
    assert!(st.beams - st.zero_beams >= 300, "{st:?}");
    eprintln!(
        "trace vs independent tracer: {} paths, {} segments: max |Δ| origin {:.1e}, start \
         {:.1e}, length {:.1e}; direction {:.1e}, weight {:.1e} (cos θᵢ ≥ 0.01), {:.1e}, \
         {:.1e} (1 − b/r = 1e−6); {} beams ({} exactly 0), worst relative error {:.2e} \
         (kappa ≤ 1e3, cos θᵢ ≥ 0.1), {:.2e} (kappa ≤ 1e3, cos θᵢ ≥ 0.01), {:.2e} (cos θᵢ < 0.01); kappa > 1e3 (case, kappa, \
         error): {:?}",
        st.paths,
        st.segments,
        st.origin,
        st.start,
        st.length,
        st.dir,
        st.weight,
        st.dir_grazing,
        st.weight_grazing,
        st.beams,
        st.zero_beams,
        st.beam_clear,
        st.beam_worst,
        st.beam_grazing,
        st.ill
    );
    eprintln!("  max |Δ| origin, direction, weight, start by class:");
    for (k, v) in &st.by_class {
        eprintln!(
            "  {k:<30} {:.1e} {:.1e} {:.1e} {:.1e}",
            v[0], v[1], v[2], v[3]
        );
    }
}

/// Test 2 (emitter). `ConeEmitter::direction` against its formula: unit
/// length, the angle from the axis (`α(2u₀ − 1)` signed in 2D,
/// `1 − cos θ = u₀(1 − cos α)` in 3D) and the 3D azimuth `2πu₁` in some
/// orthonormal frame around the axis; `measure`.
#[test]
fn cone_emitter_direction_formula() {
    let grid = |n: usize| (0..=n).map(move |i| i as f64 / n as f64);
    let mut worst = [0.0f64; 3];
    for axis in [[0.0, -1.0], [0.3, -1.0], [-2.0, 0.5], [1.0, 0.0]] {
        for alpha in [18f64.to_radians(), 1e-6, 1.0, PI] {
            let e = ConeEmitter::new([0.5, 2.0], axis, alpha).unwrap();
            let a = unit(axis);
            assert!(max_abs_diff(e.axis(), a) <= 2e-16);
            assert_eq!(e.measure(), 2.0 * alpha);
            for u0 in grid(64) {
                let d = e.direction([u0, 0.3]);
                assert_eq!(d, e.direction([u0, 0.9]), "u₁ unused in 2D");
                assert!((norm(d) - 1.0).abs() <= 4e-16, "{d:?}");
                // Signed angle from the axis (counter-clockwise positive).
                let th = (a[0] * d[1] - a[1] * d[0]).atan2(dot(a, d));
                let want = alpha * (2.0 * u0 - 1.0);
                let want = if want.abs() > PI - 1e-15 {
                    th.signum() * PI
                } else {
                    want
                };
                worst[0] = worst[0].max((th - want).abs());
                assert!((th - want).abs() <= 2e-15, "{th} {want}");
            }
        }
    }
    for axis in [
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [0.3, -1.0, 0.2],
        [1.0, 2.0, -3.0],
        [-1e-9, 0.0, -1.0],
    ] {
        for alpha in [18f64.to_radians(), 1e-6, 2.0, PI] {
            let e = ConeEmitter::new([0.0, 2.0, 0.0], axis, alpha).unwrap();
            let a = unit(axis);
            assert!(max_abs_diff(e.axis(), a) <= 2e-16);
            // 1 − cos α without cancellation.
            let omc = 2.0 * (0.5 * alpha).sin().powi(2);
            assert!((e.measure() - 2.0 * PI * omc).abs() <= 1e-15 * e.measure());
            // The frame: the perpendicular parts at φ = 0 and φ = π/2
            // (θ ≥ 0.15 for α ≥ 18°, so they are accurate).
            let frame = (alpha > 0.1).then(|| {
                let e1 = unit(tangential(e.direction([0.5, 0.0]), a));
                let e2 = unit(tangential(e.direction([0.5, 0.25]), a));
                assert!(dot(e1, a).abs() <= 1e-14 && dot(e2, a).abs() <= 1e-14);
                assert!(dot(e1, e2).abs() <= 1e-14, "{axis:?}");
                (e1, e2)
            });
            for u0 in grid(32) {
                for u1 in grid(32) {
                    let d = e.direction([u0, u1]);
                    assert!((norm(d) - 1.0).abs() <= 4e-16, "{d:?}");
                    // 1 − cos θ = 2 sin²(θ/2) = u₀(1 − cos α).
                    let p = tangential(d, a);
                    let th = norm(p).atan2(dot(a, d));
                    let want = 2.0 * (0.5 * u0 * omc).sqrt().asin();
                    worst[1] = worst[1].max((th - want).abs());
                    assert!((th - want).abs() <= 2e-15, "{u0} {th} {want}");
                    if let Some((e1, e2)) = frame.filter(|_| th > 1e-2 && th < PI - 1e-2) {
                        let phi = dot(p, e2).atan2(dot(p, e1));
                        let mut dphi = (phi - 2.0 * PI * u1).rem_euclid(2.0 * PI);
                        if dphi > PI {
                            dphi -= 2.0 * PI;
                        }
                        worst[2] = worst[2].max(dphi.abs());
                        assert!(dphi.abs() <= 1e-13, "φ: {phi} vs 2π·{u1}");
                    }
                }
            }
        }
    }
    eprintln!(
        "cone emitter: worst |Δθ| 2D {:.1e}, 3D {:.1e}; |Δφ| {:.1e}",
        worst[0], worst[1], worst[2]
    );
}

// ------------------------------------------------------------ 3. energy

/// The unpolarised Fresnel reflectance from the angles (`θᵢ` on either side).
fn fresnel_angles(ti: f64, tt: f64, n_rel: f64) -> f64 {
    if ti == 0.0 {
        let r = (n_rel - 1.0) / (n_rel + 1.0);
        return r * r;
    }
    let rs = ((ti - tt).sin() / (ti + tt).sin()).powi(2);
    let rp = ((ti - tt).tan() / (ti + tt).tan()).powi(2);
    0.5 * (rs + rp)
}

/// Angle of incidence on the glass of the ray from `p` along unit `d`, from
/// the impact parameter `|q × d|`, `q = p − c` (`None`: misses).
fn incidence<const D: usize>(p: [f64; D], d: [f64; D], c: [f64; D], r: f64) -> Option<f64> {
    let q = sub(p, c);
    if dot(q, d) >= 0.0 {
        return None;
    }
    let b = if D == 2 {
        (q[0] * d[1] - q[1] * d[0]).abs()
    } else {
        let x = [
            q[1] * d[2] - q[2] * d[1],
            q[2] * d[0] - q[0] * d[2],
            q[0] * d[1] - q[1] * d[0],
        ];
        norm(x)
    };
    (b < r).then(|| (b / r).asin())
}

fn energy_scene<const D: usize>(fresnel: Fresnel) -> Caustic<D> {
    let light: [f64; D] = cut([0.0, 2.0, 0.0]);
    let axis: [f64; D] = cut([0.0, -1.0, 0.0]);
    Caustic::new(
        ConeEmitter::new(light, axis, 18f64.to_radians()).unwrap(),
        Glass::new([0.0; D], 0.5, 1.5).unwrap(),
        Medium::new(0.6, 0.0).unwrap(),
        Sphere::new(light, 1e4).unwrap(),
        fresnel,
    )
    .unwrap()
}

fn energy_case<const D: usize>(us: &[[f64; 2]]) -> (f64, f64, usize) {
    let (mut worst, mut worst_recip, mut hits) = (0.0f64, 0.0f64, 0);
    for fresnel in [
        Fresnel::Off,
        Fresnel::On {
            internal_reflections: 0,
        },
        Fresnel::On {
            internal_reflections: 2,
        },
        Fresnel::On {
            internal_reflections: 5,
        },
        Fresnel::On {
            internal_reflections: MAX_INTERNAL_REFLECTIONS,
        },
    ] {
        let sc = energy_scene::<D>(fresnel);
        let st = sc.medium().sigma_t();
        let eta = sc.glass().ior();
        let (c, r) = (sc.glass().ball().centre(), sc.glass().ball().radius());
        for &u in us {
            let mut tol_r = 0.0;
            let d = sc.light().direction(u);
            let path = sc.path(u);
            let ti = incidence(sc.light().position(), unit(d), c, r);
            assert_eq!(path.hit_glass(), ti.is_some(), "{u:?}");
            let segs = path.segments();
            let (want_esc, l0) = match (ti, fresnel) {
                (None, _) => (1.0, f64::INFINITY),
                (Some(_), Fresnel::Off) => (1.0, segs[0].length),
                (
                    Some(ti),
                    Fresnel::On {
                        internal_reflections: k,
                    },
                ) => {
                    hits += 1;
                    let tt = (ti.sin() / eta).asin();
                    let r1 = fresnel_angles(ti, tt, eta);
                    // θᵢ from the impact parameter b is conditioned by
                    // 1/cos θᵢ (b/r → 1 at grazing incidence).
                    tol_r = 1e-14 / ti.cos();
                    let t1 = 1.0 - r1;
                    assert!(
                        (segs[1].weight - r1).abs() <= tol_r,
                        "{u:?}: R₁ {} vs {r1}",
                        segs[1].weight
                    );
                    // Reciprocity: the exits' weights are T₁T₂R₂ʲ with the
                    // exit reflectance R₂ equal to the entry's R₁ (the
                    // kernel's own R₁ here, so this is exact bookkeeping).
                    let exits = &segs[2..];
                    assert_eq!(exits.len(), k as usize + 1);
                    let (kr1, kt1) = (segs[1].weight, 1.0 - segs[1].weight);
                    for (j, g) in exits.iter().enumerate() {
                        let want = kt1 * kt1 * kr1.powi(j as i32);
                        let e = (g.weight - want).abs() / want;
                        // R₂ is computed at each exit from cos θ₂: near
                        // grazing its error grows like 1/cos θᵢ (see the
                        // trace test).
                        let tol = 1e-13 + (1.0 / kt1 + j as f64 / kr1) * tol_r;
                        assert!(e <= tol, "{u:?} exit {j}: {} vs {want}", g.weight);
                        worst_recip = worst_recip.max(e / tol);
                        // Each exit leaves at the angle of incidence.
                        let n = unit(sub(g.ray.origin(), c));
                        let ce = dot(n, g.ray.dir().get());
                        assert!((ce - ti.cos()).abs() <= 1e-13 + tol_r, "{u:?} exit {j}");
                    }
                    // The independent Fresnel is reciprocal (the angle forms
                    // are symmetric in θᵢ, θₜ), and so is the kernel's.
                    assert_eq!(fresnel_angles(tt, ti, 1.0 / eta), r1);
                    let k_r = fresnel_reflectance(tt.cos(), eta);
                    assert!((k_r - r1).abs() <= tol_r, "exit reflectance {k_r} vs {r1}");
                    assert!((fresnel_reflectance(ti.cos(), 1.0 / eta) - r1).abs() <= tol_r);
                    (1.0 - t1 * r1.powi(k as i32 + 1), segs[0].length)
                }
            };
            // R₁ enters 1 − T₁R₁^{K+1} at most K + 2 times.
            let tol_esc = f64::from(MAX_INTERNAL_REFLECTIONS + 2) * tol_r;
            let esc = path.escaping_weight();
            assert!(
                (esc - want_esc).abs() <= 1e-14 + tol_esc,
                "{fresnel:?} {u:?}: escaping weight {esc}, want {want_esc}"
            );
            let tr = (-st * l0).exp();
            let want = (1.0 - tr) + tr * want_esc;
            let got = sc.beam(&path);
            let e = (got - want).abs() / want;
            let tol = 1e-13 + tol_esc;
            assert!(
                e <= tol,
                "{fresnel:?} {u:?}: beam {got}, want {want} ({e:.1e})"
            );
            worst = worst.max(e);
        }
    }
    (worst, worst_recip, hits)
}

/// Test 3. The beam in a huge `Q` with `σ_a = 0` is the scattered fraction of
/// the escaping weight; reciprocity of the ball's internal reflections.
#[test]
fn energy_bookkeeping() {
    let us2: Vec<[f64; 2]> = (0..400).map(|i| [(i as f64 + 0.5) / 400.0, 0.0]).collect();
    let us3: Vec<[f64; 2]> = (0..40)
        .flat_map(|i| (0..12).map(move |j| [(i as f64 + 0.5) / 40.0, j as f64 / 12.0]))
        .collect();
    let (w2, r2, h2) = energy_case::<2>(&us2);
    let (w3, r3, h3) = energy_case::<3>(&us3);
    assert!(h2 > 1000 && h3 > 1000);
    eprintln!(
        "energy: worst relative error 2D {w2:.1e}, 3D {w3:.1e}; exit weights vs T₁²R₁ʲ: \
         worst error/tolerance 2D {r2:.2}, 3D {r3:.2}"
    );
}

/// Independent refraction (angle formulation; `θ` from `atan2`).
fn refract_angles<const D: usize>(d: [f64; D], n: [f64; D], eta: f64) -> Option<[f64; D]> {
    let t = tangential(d, n);
    let ti = norm(t).atan2(-dot(n, d));
    let s = eta * ti.sin();
    if s > 1.0 {
        return None;
    }
    let tt = s.asin();
    let tu = if norm(t) > 0.0 { unit(t) } else { [0.0; D] };
    Some(add(scale(n, -tt.cos()), scale(tu, tt.sin())))
}

fn reflect_angles<const D: usize>(d: [f64; D], n: [f64; D]) -> [f64; D] {
    let t = tangential(d, n);
    let ti = norm(t).atan2(-dot(n, d));
    let tu = if norm(t) > 0.0 { unit(t) } else { [0.0; D] };
    add(scale(n, ti.cos()), scale(tu, ti.sin()))
}

fn interfaces<const D: usize>(dirs: &[[f64; D]], n: [f64; D]) -> (f64, f64, usize) {
    let (mut worst, mut worst_r, mut tir) = (0.0f64, 0.0f64, 0);
    for eta in [1.0 / 1.5, 1.0 / 1.33, 1.0, 1.33, 1.5, 2.4] {
        for &d in dirs {
            let want = refract_angles(d, n, eta);
            let got = refract(&d, &n, eta);
            let ci = -dot(n, d);
            let r = fresnel_reflectance(ci, eta);
            match (got, want) {
                (Some(g), Some(w)) => {
                    // Fresnel from the angles.
                    let ti = norm(tangential(d, n)).atan2(ci);
                    let tt = (eta * ti.sin()).asin();
                    let rw = fresnel_angles(ti, tt, 1.0 / eta);
                    // cos θₜ = √(1 − η² sin²θᵢ) is conditioned by η²/cos θₜ
                    // (steep next to the critical angle), on both sides.
                    let tol = 4e-15 * (eta * eta).max(1.0) * (1.0 + 1.0 / tt.cos());
                    let e = max_abs_diff(g, w);
                    worst = worst.max(e / tol);
                    assert!(e <= tol, "refract {d:?} η {eta}: {g:?} vs {w:?}");
                    let er = (r - rw).abs();
                    worst_r = worst_r.max(er / tol);
                    assert!(er <= tol, "Fresnel {d:?} η {eta}: {r} vs {rw}");
                }
                (None, None) => {
                    tir += 1;
                    assert_eq!(r, 1.0, "total internal reflection: R = {r}");
                }
                _ => panic!("refract {d:?} η {eta}: {got:?} vs {want:?}"),
            }
            let e = max_abs_diff(reflect(&d, &n), reflect_angles(d, n));
            assert!(e <= 1e-15, "reflect {d:?}: {e:.1e}");
        }
    }
    (worst, worst_r, tir)
}

/// Test 3. `refract`, `reflect` and `fresnel_reflectance` against the angle
/// forms; total internal reflection gives `None` and `1`.
#[test]
fn interfaces_match_angle_forms() {
    // Incidence angles from 0 to grazing (on the side n·d < 0), and 1e−9
    // (relative) either side of the critical angles of η = 1.33, 1.5, 2.4.
    let mut angles = vec![
        0.0,
        1e-9,
        1e-4,
        0.1,
        0.4,
        0.6,
        0.73,
        0.9,
        1.2,
        1.5,
        0.5 * PI - 1e-4,
    ];
    for eta in [1.33f64, 1.5, 2.4] {
        let c = (1.0 / eta).asin();
        angles.extend([c * (1.0 - 1e-9), c * (1.0 + 1e-9), c * (1.0 - 1e-4)]);
    }
    let n2 = unit([0.3, 0.8]);
    let t2 = [-n2[1], n2[0]];
    let dirs2: Vec<[f64; 2]> = angles
        .iter()
        .flat_map(|&a| [1.0, -1.0].map(|s| add(scale(n2, -a.cos()), scale(t2, s * a.sin()))))
        .collect();
    let (w2, r2, tir2) = interfaces(&dirs2, n2);
    let n3 = unit([0.3, -0.8, 0.5]);
    let t3 = unit(tangential([1.0, 0.0, 0.0], n3));
    let s3 = [
        n3[1] * t3[2] - n3[2] * t3[1],
        n3[2] * t3[0] - n3[0] * t3[2],
        n3[0] * t3[1] - n3[1] * t3[0],
    ];
    let dirs3: Vec<[f64; 3]> = angles
        .iter()
        .flat_map(|&a| {
            [0.0, 1.0, 2.5, 4.0].map(|phi: f64| {
                let tv = add(scale(t3, phi.cos()), scale(s3, phi.sin()));
                add(scale(n3, -a.cos()), scale(tv, a.sin()))
            })
        })
        .collect();
    let (w3, r3, tir3) = interfaces(&dirs3, n3);
    assert!(tir2 >= 10 && tir3 >= 20, "{tir2} {tir3}");
    // Exactly at normal incidence: ((n₁ − n₂)/(n₁ + n₂))², straight through.
    assert!((fresnel_reflectance(1.0, 1.0 / 1.5) - 0.04).abs() <= 1e-16);
    let t = refract(&[0.0, -1.0], &[0.0, 1.0], 1.0 / 1.5).unwrap();
    assert!(max_abs_diff(t, [0.0, -1.0]) <= 2e-16, "{t:?}");
    // Grazing incidence reflects everything; η = 1 nothing.
    assert_eq!(fresnel_reflectance(0.0, 1.0 / 1.5), 1.0);
    assert!(fresnel_reflectance(0.3, 1.0) <= 1e-30);
    // Beyond the critical angle (η = 1.5: sin θ > 2/3).
    let d = add(scale(n2, -0.8f64.cos()), scale(t2, 0.8f64.sin()));
    assert!(1.5 * 0.8f64.sin() > 1.0 && 1.3 * 0.8f64.sin() < 1.0);
    assert_eq!(refract(&d, &n2, 1.5), None);
    assert_eq!(fresnel_reflectance(0.8f64.cos(), 1.5), 1.0);
    assert!(refract(&d, &n2, 1.3).is_some() && fresnel_reflectance(0.8f64.cos(), 1.3) < 1.0);
    eprintln!(
        "interfaces: worst error / tolerance: refract 2D {w2:.2}, 3D {w3:.2}; Fresnel 2D \
         {r2:.2}, 3D {r3:.2}; {} cases of total internal reflection",
        tir2 + tir3
    );
}

// ------------------------------------------------------------ 4. points

/// The midpoint rule of `point` over `s` against `beam`.
fn midpoint_vs_beam<const D: usize>(sc: &Caustic<D>, path: &PhotonPath<D>) -> (f64, f64, f64) {
    const M: usize = 1 << 20;
    let mut sum = 0.0;
    let mut max_score = 0.0f64;
    for i in 0..M {
        let p = sc.point(path, (i as f64 + 0.5) / M as f64);
        sum += p;
        max_score = max_score.max(p);
    }
    let mean = sum / M as f64;
    let beam = sc.beam(path);
    let m = sc.medium();
    let bound_score: f64 =
        m.sigma_s() / m.sigma_t() * path.segments().iter().map(|g| g.weight).sum::<f64>();
    assert!(max_score <= bound_score * (1.0 + 1e-15));
    // Each segment's score is an indicator of one interval of s: two jumps.
    let breaks = 2 * path.segments().len();
    let tol = breaks as f64 * bound_score / M as f64 + 1e-12 * beam;
    (mean, beam, tol)
}

fn points_case<const D: usize>(q_small: [f64; 3], us: &[[f64; 2]]) -> (usize, f64) {
    let light: [f64; D] = cut([0.0, 2.0, 0.0]);
    let mut worst = 0.0f64;
    let mut n = 0;
    for (q, r) in [(q_small, 0.1), ([0.1, -0.2, 0.05], 1.5)] {
        let sc = Caustic::new(
            ConeEmitter::new(light, cut::<D>([0.0, -1.0, 0.0]), 18f64.to_radians()).unwrap(),
            Glass::new([0.0; D], 0.5, 1.5).unwrap(),
            Medium::new(0.5, 0.1).unwrap(),
            Sphere::new(cut::<D>(q), r).unwrap(),
            Fresnel::On {
                internal_reflections: 2,
            },
        )
        .unwrap();
        for &u in us {
            let path = sc.path(u);
            let (mean, beam, tol) = midpoint_vs_beam(&sc, &path);
            assert!(beam > 0.0, "{u:?}: the path must score");
            assert!(
                (mean - beam).abs() <= tol,
                "D = {D}, Q r = {r}, u = {u:?}: points {mean:e}, beam {beam:e} (|Δ| {:.2e} > \
                 {tol:.2e})",
                (mean - beam).abs()
            );
            worst = worst.max((mean - beam).abs() / beam);
            n += 1;
        }
    }
    (n, worst)
}

/// Test 4. Points are unbiased for the beam: the midpoint rule over the free
/// flight with `2²⁰` points matches `beam` within one cell per jump. (The
/// midpoint grid is symmetric under `s → 1 − s`, so it cannot tell
/// `−ln(1 − s)` from `−ln s`: `free_flight` is checked against its formula
/// first.)
#[test]
fn points_average_to_the_beam() {
    let m = Medium::new(0.5, 0.1).unwrap();
    let st = m.sigma_t();
    assert_eq!(m.free_flight(0.0), 0.0);
    for s in [
        1e-300,
        1e-20,
        1e-9,
        0.125,
        0.5,
        0.9,
        1.0 - 1e-12,
        1.0 - f64::EPSILON / 2.0,
    ] {
        // −ln(1 − s)/σ_t: the series for tiny s (where 1 − s rounds), the
        // logarithm of the exact 1 − s otherwise (exact for s ≥ 1/2).
        let want = if s < 1e-6 {
            s * (1.0 + s / 2.0) / st
        } else {
            -(1.0 - s).ln() / st
        };
        let got = m.free_flight(s);
        assert!(
            (got - want).abs() <= 4e-16 * want,
            "s = {s}: {got} vs {want}"
        );
    }
    // u's whose refracted rays cross the small Q (and, with the large Q,
    // every branch scores).
    let (n2, w2) = points_case::<2>([0.05, -1.0, 0.0], &[[0.5, 0.0], [0.52, 0.0], [0.45, 0.0]]);
    let (n3, w3) = points_case::<3>([0.05, -1.0, 0.03], &[[0.02, 0.1], [0.005, 0.6]]);
    eprintln!(
        "points vs beam: {} paths, worst relative difference 2D {w2:.1e}, 3D {w3:.1e}",
        n2 + n3
    );
}

// ------------------------------------------------------------ 5. bad input

/// The `NonFinite` error naming `name`, as `.err()` gives it.
fn non_finite(name: &'static str) -> Option<ParamError> {
    Some(ParamError::NonFinite { name })
}

/// Asserts that a `Medium` was refused as out of range, naming `want`.
fn assert_medium_out_of_range(r: Result<Medium, ParamError>, want: &str) {
    assert!(
        matches!(r, Err(ParamError::OutOfRange { name, .. }) if name == want),
        "{r:?} should name {want}"
    );
}

/// The 2D test scene with the light at `light`: glass of radius 0.5 at the origin.
fn caustic_2d(light: [f64; 2], fresnel: Fresnel) -> Result<Caustic<2>, ParamError> {
    Caustic::new(
        ConeEmitter::new(light, [0.0, -1.0], 0.3).unwrap(),
        Glass::new([0.0, 0.0], 0.5, 1.5).unwrap(),
        Medium::new(0.5, 0.1).unwrap(),
        Sphere::new([0.05, -1.0], 0.1).unwrap(),
        fresnel,
    )
}

/// Test 5. `Medium::new` rejects non-finite and negative coefficients by name.
#[test]
fn medium_rejects_bad_input_by_name() {
    assert_eq!(Medium::new(f64::NAN, 0.1).err(), non_finite("sigma_s"));
    assert_eq!(Medium::new(0.1, f64::NAN).err(), non_finite("sigma_a"));
    assert_eq!(Medium::new(f64::INFINITY, 0.1).err(), non_finite("sigma_s"));
    assert_medium_out_of_range(Medium::new(-0.1, 0.5), "sigma_s");
    assert_medium_out_of_range(Medium::new(0.5, -1e-300), "sigma_a");
    assert_medium_out_of_range(Medium::new(0.0, 0.0), "sigma_t");
    assert!(Medium::new(0.0, 1.0).is_ok() && Medium::new(1.0, 0.0).is_ok());
}

/// Test 5. `ConeEmitter::new` names a bad axis, position, half angle or dimension.
#[test]
fn cone_emitter_rejects_bad_input_by_name() {
    assert_eq!(
        ConeEmitter::<2>::new([0.0, 0.0], [0.0, 0.0], 0.1),
        Err(ParamError::ZeroDirection)
    );
    assert_eq!(
        ConeEmitter::<3>::new([0.0; 3], [0.0; 3], 0.1),
        Err(ParamError::ZeroDirection)
    );
    assert_eq!(
        ConeEmitter::<2>::new([f64::NAN, 0.0], [0.0, 1.0], 0.1).err(),
        non_finite("position")
    );
    assert_eq!(
        ConeEmitter::<3>::new([0.0; 3], [0.0, f64::NAN, 1.0], 0.1).err(),
        non_finite("axis")
    );
    assert_eq!(
        ConeEmitter::<2>::new([0.0, 0.0], [0.0, 1.0], f64::NAN).err(),
        non_finite("half_angle")
    );
    for bad in [0.0, -0.1, 1e-13, PI + 1e-12, 4.0] {
        assert!(
            matches!(
                ConeEmitter::<3>::new([0.0; 3], [0.0, 0.0, 1.0], bad),
                Err(ParamError::OutOfRange {
                    name: "half_angle",
                    ..
                })
            ),
            "half_angle {bad}"
        );
    }
    assert!(ConeEmitter::<3>::new([0.0; 3], [0.0, 0.0, 1.0], PI).is_ok());
    assert_eq!(
        ConeEmitter::<4>::new([0.0; 4], [1.0, 0.0, 0.0, 0.0], 0.1),
        Err(ParamError::Dimension { dim: 4 })
    );
}

/// Test 5. `Glass::new` rejects a bad index, radius or centre by name.
#[test]
fn glass_rejects_bad_input_by_name() {
    for bad in [0.99, 0.0, -1.5, 10.5] {
        assert!(matches!(
            Glass::<2>::new([0.0, 0.0], 1.0, bad),
            Err(ParamError::OutOfRange { name: "ior", .. })
        ));
    }
    assert_eq!(
        Glass::<2>::new([0.0, 0.0], 1.0, f64::NAN).err(),
        non_finite("ior")
    );
    assert_eq!(
        Glass::<3>::new([0.0; 3], f64::NAN, 1.5).err(),
        non_finite("radius")
    );
    assert_eq!(
        Glass::<3>::new([0.0, f64::NAN, 0.0], 1.0, 1.5).err(),
        non_finite("centre")
    );
    assert!(matches!(
        Glass::<2>::new([0.0, 0.0], 0.0, 1.5),
        Err(ParamError::OutOfRange { name: "radius", .. })
    ));
    assert!(Glass::<2>::new([0.0, 0.0], 1.0, 1.0).is_ok());
}

/// Test 5. `Caustic::new` names a light inside the glass and too many reflections.
#[test]
fn caustic_rejects_bad_input_by_name() {
    for inside in [[0.0, 0.2], [0.0, 0.0], [0.0, 0.5], [0.3, -0.4]] {
        assert!(
            matches!(
                caustic_2d(inside, Fresnel::Off),
                Err(ParamError::OutOfRange {
                    name: "position",
                    ..
                })
            ),
            "{inside:?}"
        );
    }
    assert!(caustic_2d([0.0, 0.5000001], Fresnel::Off).is_ok());
    let too_many = Fresnel::On {
        internal_reflections: MAX_INTERNAL_REFLECTIONS + 1,
    };
    assert!(matches!(
        caustic_2d([0.0, 2.0], too_many),
        Err(ParamError::OutOfRange {
            name: "internal_reflections",
            ..
        })
    ));
    let max = Fresnel::On {
        internal_reflections: MAX_INTERNAL_REFLECTIONS,
    };
    let sc = caustic_2d([0.0, 2.0], max).unwrap();
    assert_eq!(sc.path([0.5, 0.0]).segments().len(), MAX_SEGMENTS);
}

/// Test 5. `PhotonPath::new` names a bad segment count and bad segment fields.
#[test]
fn photon_path_rejects_bad_input_by_name() {
    let seg = Segment {
        ray: Ray::new([0.0, 0.0], [1.0, 0.0]).unwrap(),
        start: 0.0,
        length: f64::INFINITY,
        weight: 1.0,
    };
    let len = |got| {
        Err(ParamError::Length {
            name: "segments",
            expected: MAX_SEGMENTS,
            got,
        })
    };
    assert_eq!(PhotonPath::<2>::new(&[]), len(0));
    assert_eq!(
        PhotonPath::new(&[seg; MAX_SEGMENTS + 1]),
        len(MAX_SEGMENTS + 1)
    );
    assert!(PhotonPath::new(&[seg; MAX_SEGMENTS]).is_ok());
    let with = |f: &dyn Fn(&mut Segment<2>)| {
        let mut s = [seg; 3];
        f(&mut s[1]);
        PhotonPath::new(&s)
    };
    assert_eq!(with(&|s| s.weight = f64::NAN).err(), non_finite("weight"));
    assert_eq!(
        with(&|s| s.weight = f64::INFINITY).err(),
        non_finite("weight")
    );
    assert!(matches!(
        with(&|s| s.weight = -0.5),
        Err(ParamError::OutOfRange { name: "weight", .. })
    ));
    assert_eq!(with(&|s| s.start = f64::NAN).err(), non_finite("start"));
    assert!(matches!(
        with(&|s| s.start = -1.0),
        Err(ParamError::OutOfRange { name: "start", .. })
    ));
    for bad in [f64::NAN, -1.0, f64::NEG_INFINITY] {
        assert!(matches!(
            with(&|s| s.length = bad),
            Err(ParamError::OutOfRange { name: "length", .. })
        ));
    }
    assert!(with(&|s| s.length = 0.0).is_ok());
}

/// Test 5. The error messages name the parameter.
#[test]
fn error_messages_name_the_parameter() {
    let e = Medium::new(0.0, 0.0).unwrap_err();
    assert!(e.to_string().contains("sigma_t"), "{e}");
    let too_many = Fresnel::On {
        internal_reflections: MAX_INTERNAL_REFLECTIONS + 1,
    };
    let e = caustic_2d([0.0, 2.0], too_many).unwrap_err();
    assert!(e.to_string().contains("internal_reflections"), "{e}");
}
