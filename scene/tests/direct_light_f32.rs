//! The `f32` SIMD batch of the direct-light line estimator
//! (`linesample_scene::direct_light_f32`) against the `f64` path
//! (`DirectLight::line` of `QuadLight::chord`, the `f32` inputs widened):
//! the module's error bound evaluated for every line from exact (`f64`)
//! geometry and asserted, on receivers in a Cornell-box-like scene, on
//! receivers `10⁻²…10⁻⁶` above the light's plane (with a blocker between),
//! on tangent planes cutting the light, on lines through light corners and
//! shadow corners, and with every shadow passed twice (the union's
//! tie-breaking); the SIMD batch against its scalar twin bit for bit
//! (thousands of lines, every tail length); input validation.

#[path = "../../tests/common/mod.rs"]
mod common;

use common::XorShift as Rng;
use linesample::ParamError;
use linesample_scene::direct_light::{
    diffuse_line_integral, DirectLight, Parallelogram, QuadLight, Shadow,
};
use linesample_scene::direct_light_f32::DirectLight32;
use std::f64::consts::PI;

/// `ε₃₂ = 2⁻²³`.
const EPS: f64 = f32::EPSILON as f64;
/// Shadow capacity of the `f32` receivers (two boxes: at most 6 front
/// faces; doubled for the tie-breaking test).
const CAP: usize = 16;
/// FNV-1a of the bit-identity test's results (a value pin: the same in
/// every build; update it only for a deliberate change of the kernel).
const PIN: u64 = 0x9717_bfa6_c91c_f90c;

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    scale(a, 1.0 / dot(a, a).sqrt())
}

// ------------------------------------------------------------ the scene

/// The Cornell-box-like scene: the room `[−1, 1] × [0, 2] × [−1, 1]`, the
/// light `(−0.24, 1.98, −0.22)` + `(0.47, 0, 0)`, `(0, 0, 0.38)` (emitting
/// down), a short box (0.6 high, rotated −17°) and a tall one (1.2 high,
/// +17°) about `y`, each six faces with outward normals.
struct Scene {
    light: QuadLight,
    /// Per box: `(face, unit outward normal)`.
    boxes: Vec<Vec<(Parallelogram, [f64; 3])>>,
}

impl Scene {
    fn cornell() -> Self {
        let light =
            QuadLight::new([-0.24, 1.98, -0.22], [0.47, 0.0, 0.0], [0.0, 0.0, 0.38]).unwrap();
        let boxes = vec![
            box_faces([0.33, 0.0, 0.30], [0.6, 0.6, 0.6], -17.0),
            box_faces([-0.33, 0.0, -0.28], [0.6, 1.2, 0.6], 17.0),
        ];
        Scene { light, boxes }
    }

    /// Whether `x` is strictly inside a box.
    fn inside_box(&self, x: [f64; 3]) -> bool {
        self.boxes
            .iter()
            .any(|b| b.iter().all(|(f, n)| dot(sub(x, f.corner()), *n) < -1e-9))
    }

    /// The shadows of every box face that faces `x`.
    fn shadows(&self, x: [f64; 3]) -> Vec<Shadow> {
        let faces: Vec<Parallelogram> = self
            .boxes
            .iter()
            .flatten()
            .filter(|(f, n)| dot(sub(x, f.corner()), *n) > 0.0)
            .map(|(f, _)| *f)
            .collect();
        let mut out = vec![Shadow::EMPTY; faces.len()];
        let k = Shadow::project_all(&self.light, x, &faces, &mut out).unwrap();
        out.truncate(k);
        out
    }
}

/// A box standing on `base`, `size` (x, y, z) before a rotation of `deg`
/// about `+y`: six faces, `edge1 × edge2` outward.
fn box_faces(base: [f64; 3], size: [f64; 3], deg: f64) -> Vec<(Parallelogram, [f64; 3])> {
    let (s, c) = deg.to_radians().sin_cos();
    let ex = [c * size[0], 0.0, -s * size[0]];
    let ey = [0.0, size[1], 0.0];
    let ez = [s * size[2], 0.0, c * size[2]];
    let o = [
        base[0] - 0.5 * (ex[0] + ez[0]),
        base[1],
        base[2] - 0.5 * (ex[2] + ez[2]),
    ];
    let (ox, oy, oz) = (add(o, ex), add(o, ey), add(o, ez));
    [
        (o, ez, ex),
        (oy, ex, ez),
        (o, ex, ey),
        (oz, ey, ex),
        (o, ey, ez),
        (ox, ez, ey),
    ]
    .iter()
    .map(|&(c, e1, e2)| {
        // `e1 × e2` points into the box for this edge order: negate.
        let f = Parallelogram::new(c, e1, e2).unwrap();
        (f, scale(unit(f.normal()), -1.0))
    })
    .collect()
}

/// A receiver: point, unit normal, shadows.
struct Receiver {
    x: [f64; 3],
    n: [f64; 3],
    shadows: Vec<Shadow>,
}

/// Random receivers on the room's floor and walls and on the boxes' faces
/// (not inside a box), normals facing into the room; shadows from the
/// front-facing box faces.
fn cornell_receivers(scene: &Scene, count: usize, rng: &mut Rng) -> Vec<Receiver> {
    let mut out = Vec::new();
    while out.len() < count {
        let k = (rng.uniform() * 11.0) as usize;
        let (u, v) = (rng.uniform(), rng.uniform());
        let (x, n) = match k {
            0 | 1 => ([2.0 * u - 1.0, 0.0, 2.0 * v - 1.0], [0.0, 1.0, 0.0]),
            // The floor around the boxes (most shadows).
            9 | 10 => ([1.6 * u - 0.8, 0.0, 1.6 * v - 0.8], [0.0, 1.0, 0.0]),
            2 => ([2.0 * u - 1.0, 2.0 * v, -1.0], [0.0, 0.0, 1.0]),
            3 => ([-1.0, 2.0 * v, 2.0 * u - 1.0], [1.0, 0.0, 0.0]),
            4 => ([1.0, 2.0 * v, 2.0 * u - 1.0], [-1.0, 0.0, 0.0]),
            _ => {
                // A box face other than the bottom.
                let b = &scene.boxes[k % 2];
                let (f, nrm) = b[1 + (rng.uniform() * 5.0) as usize];
                let [e1, e2] = f.edges();
                let (a, c) = (0.01 + 0.98 * u, 0.01 + 0.98 * v);
                (add(f.corner(), add(scale(e1, a), scale(e2, c))), nrm)
            }
        };
        if scene.inside_box(x) {
            continue;
        }
        let shadows = scene.shadows(x);
        out.push(Receiver { x, n, shadows });
    }
    out
}

// ------------------------------------------------------------ the bound

/// The module's error bound for one line, with its parts (in units of
/// `ε·U`) for the report.
#[derive(Clone, Copy, Debug, Default)]
struct Bound {
    /// The bound.
    total: f64,
    /// `U = h/(2q²)`.
    u: f64,
    /// `24(K + 1)W*`, `10Γ* + π|a|`, `(K + 6)J`, `(3δ_d J + 5πδρ/q)/ε`,
    /// `Σ_b T_b/ε`.
    parts: [f64; 5],
    /// A boundary parallel to the line (`k = 0`) passes within rounding of
    /// it, so either decision is right (the bound allows the whole line).
    undecided: bool,
}

/// The `f64` geometry of one `f32` line against the light, as the bound uses it.
struct LineGeom {
    /// The line's direction, first component (widened exactly).
    c: f64,
    /// The line's direction, second component (widened exactly).
    s: f64,
    /// `δ_d = |c² + s² − 1|`.
    dd: f64,
    /// The receiver's foot on the light's plane, first axis.
    fa: f64,
    /// The receiver's foot on the light's plane, second axis.
    fb: f64,
    /// The light's first edge length.
    l1: f64,
    /// The light's second edge length.
    l2: f64,
    /// The receiver's unit normal on the light's axes.
    lam: [f64; 2],
    /// `a₀ = −h n·N_L`.
    a0: f64,
    /// The receiver's height above the light's plane.
    h: f64,
    /// `ρ`, the line's offset from the foot.
    rho: f64,
    /// `q² = h² + ρ²`.
    q2: f64,
    /// `q`.
    q: f64,
    /// `A` of the line integrand.
    big_a: f64,
    /// `β` of the line integrand.
    beta: f64,
    /// `U = h/(2q²)`.
    u: f64,
    /// `a = A/q`.
    a: f64,
    /// `δρ`, the uncertainty of `ρ`.
    drho: f64,
}

/// The geometry of the `f32` line `(c, s, o)`, or `None` below the light's plane.
fn line_geometry(
    light: &QuadLight,
    rec: &Receiver,
    c32: f32,
    s32: f32,
    o32: f32,
) -> Option<LineGeom> {
    let (c, s, o) = (f64::from(c32), f64::from(s32), f64::from(o32));
    let dd = (c * c + s * s - 1.0).abs();
    let (foot, h) = light.foot(rec.x);
    if h <= 0.0 {
        return None;
    }
    let [fa, fb] = foot;
    let [l1, l2] = light.lengths();
    let [ua, ub] = light.axes();
    let n = unit(rec.n);
    let lam = [dot(n, ua), dot(n, ub)];
    let a0 = -h * dot(n, light.normal());
    let rho = o + s * fa - c * fb;
    let q2 = h * h + rho * rho;
    let q = q2.sqrt();
    let big_a = a0 + rho * (-lam[0] * s + lam[1] * c);
    let beta = lam[0] * c + lam[1] * s;
    let u = h / (2.0 * q2);
    let a = big_a / q;
    let xc = sub(rec.x, light.corner());
    let drho = (0.5 * EPS + dd) * rho.abs()
        + 2.3e-16 * (o.abs() + fa.abs() + fb.abs() + 2.0 * dot(xc, xc).sqrt());
    Some(LineGeom {
        c,
        s,
        dd,
        fa,
        fb,
        l1,
        l2,
        lam,
        a0,
        h,
        rho,
        q2,
        q,
        big_a,
        beta,
        u,
        a,
        drho,
    })
}

/// Where a boundary `N·P + γ ≥ 0` crosses the line, and how well that is known.
struct Cross {
    /// The crossing `σ` along the line.
    sigma: f64,
    /// Its uncertainty `δs`.
    ds: f64,
    /// Whether the boundary is a lower (`k > 0`) rather than an upper bound.
    lower: bool,
}

/// A boundary `N·P + γ ≥ 0` on the line: a crossing, or for `k = 0` a constant decision.
enum Boundary {
    /// The boundary crosses the line.
    Cross(Cross),
    /// Parallel to the line: whether rounding could change the decision, and
    /// whether the whole line is outside.
    Const { uncertain: bool, violated: bool },
}

/// The boundary `N·P + γ ≥ 0` (`N = nv`, `γ = g`) on the line of `geo`.
fn crossing(geo: &LineGeom, nv: [f64; 2], g: f64) -> Boundary {
    let (c, s, rho) = (geo.c, geo.s, geo.rho);
    let k = nv[0] * c + nv[1] * s;
    let m = rho * (-nv[0] * s + nv[1] * c) + g;
    let nu = nv[0].hypot(nv[1]);
    let kappa = if nu > 0.0 { k.abs() / nu } else { 0.0 };
    if kappa < 1e-30 {
        let dm = (7.0 * EPS + geo.dd) * (nu * rho.abs() + g.abs()) + nu * geo.drho;
        return Boundary::Const {
            uncertain: m.abs() <= dm,
            violated: m < 0.0,
        };
    }
    let sigma = -m / k;
    let r = sigma.hypot(geo.q);
    Boundary::Cross(Cross {
        sigma,
        ds: ((7.0 * EPS + geo.dd) * r + geo.drho) / kappa,
        lower: k > 0.0,
    })
}

/// The chord's boundaries: the light's four edges, then the cosine clamp.
fn chord_boundaries(geo: &LineGeom) -> [Boundary; 5] {
    [
        crossing(geo, [1.0, 0.0], geo.fa),
        crossing(geo, [-1.0, 0.0], geo.l1 - geo.fa),
        crossing(geo, [0.0, 1.0], geo.fb),
        crossing(geo, [0.0, -1.0], geo.l2 - geo.fb),
        crossing(geo, geo.lam, geo.a0),
    ]
}

/// The running `Σ_b T_b` (in units of `U`) and whether a parallel boundary was undecided.
#[derive(Default)]
struct Tally {
    /// `Σ_b T_b` so far.
    t: f64,
    /// A parallel boundary passed within rounding of the line.
    undecided: bool,
}

impl Tally {
    /// Counts a parallel boundary within rounding of the line (`T = 4`).
    fn parallel_within_rounding(&mut self) {
        self.t += 4.0;
        self.undecided = true;
    }
}

/// The chord widened by its ends' uncertainty, or `None` when a parallel boundary excludes it.
fn widened_chord(chord: &[Boundary], tally: &mut Tally) -> Option<(f64, f64)> {
    let (mut w0, mut w1) = (f64::NEG_INFINITY, f64::INFINITY);
    for b in chord {
        match b {
            Boundary::Cross(x) if x.lower => w0 = w0.max(x.sigma - x.ds),
            Boundary::Cross(x) => w1 = w1.min(x.sigma + x.ds),
            Boundary::Const {
                uncertain: true, ..
            } => tally.parallel_within_rounding(),
            Boundary::Const { violated: true, .. } => return None,
            Boundary::Const { .. } => {}
        }
    }
    Some((w0, w1))
}

/// `x/√(x² + q²)`, whose differences give the crossing terms' `∫|E'|`.
fn s_over_r(x: f64, q: f64) -> f64 {
    x / x.hypot(q)
}

/// `∫|E'|` over the larger side of `[σ − δs, σ + δs]` within `w`, and the least `r` there.
fn crossing_term(q: f64, x: &Cross, (w0, w1): (f64, f64)) -> (f64, f64) {
    let sides = [(x.sigma - x.ds, x.sigma), (x.sigma, x.sigma + x.ds)];
    let mut best: f64 = 0.0;
    let mut rmin = f64::INFINITY;
    for (lo, hi) in sides {
        let (lo, hi) = (lo.max(w0), hi.min(w1));
        if lo < hi {
            best = best.max(2.0 * (s_over_r(hi, q) - s_over_r(lo, q)));
            let near = if lo > 0.0 {
                lo
            } else if hi < 0.0 {
                -hi
            } else {
                0.0
            };
            rmin = rmin.min(near.hypot(q));
        }
    }
    (best, rmin)
}

/// Adds the chord ends' terms to the tally (the clamp's scaled by `|L| ≤ |β| δs`).
fn add_chord_terms(geo: &LineGeom, chord: &[Boundary; 5], w: (f64, f64), tally: &mut Tally) {
    for (i, b) in chord.iter().enumerate() {
        if let Boundary::Cross(x) = b {
            let (t, rmin) = crossing_term(geo.q, x, w);
            if i == 4 {
                // The clamp: |L| ≤ |β| δs there.
                tally.t += t * (geo.beta.abs() * x.ds / rmin).min(1.0);
            } else {
                tally.t += t;
            }
        }
    }
}

/// Adds one shadow's plane terms to the tally; whether it meets the widened chord `w`.
fn shadow_meets_chord(geo: &LineGeom, sh: &Shadow, w: (f64, f64), tally: &mut Tally) -> bool {
    let (mut lo, mut hi) = w;
    let mut empty = false;
    for p in sh.planes() {
        let g = p[2] + p[0] * geo.fa + p[1] * geo.fb;
        match crossing(geo, [p[0], p[1]], g) {
            Boundary::Cross(x) => {
                tally.t += crossing_term(geo.q, &x, w).0;
                if x.lower {
                    lo = lo.max(x.sigma - x.ds);
                } else {
                    hi = hi.min(x.sigma + x.ds);
                }
            }
            Boundary::Const {
                uncertain: true, ..
            } => tally.parallel_within_rounding(),
            Boundary::Const { violated: true, .. } => empty = true,
            Boundary::Const { .. } => {}
        }
    }
    !empty && lo < hi
}

/// Adds every shadow's plane terms to the tally; returns `K`, the shadows meeting `w`.
fn add_shadow_terms(geo: &LineGeom, shadows: &[Shadow], w: (f64, f64), tally: &mut Tally) -> usize {
    let mut k_count = 0usize;
    for sh in shadows {
        if shadow_meets_chord(geo, sh, w, tally) {
            k_count += 1;
        }
    }
    k_count
}

/// The bound from its parts on the widened chord `(w0, w1)`, given `K` and the tally.
fn assemble(geo: &LineGeom, (w0, w1): (f64, f64), k_count: usize, tally: &Tally) -> Bound {
    let (q, q2, a, beta) = (geo.q, geo.q2, geo.a, geo.beta);
    let s_star = 0.0f64.clamp(w0, w1);
    let eta = q.atan2(s_star.abs());
    let g_star = eta - eta.sin() * eta.cos();
    let sin2 = q2 / (s_star * s_star + q2);
    let w_star = a.abs() * g_star + beta.abs() * sin2;
    let gamma_star = g_star + sin2;
    let j = diffuse_line_integral(geo.h, geo.big_a, beta, q, w0, w1) / geo.u;
    let kk = k_count as f64;
    let parts = [
        24.0 * (kk + 1.0) * w_star,
        10.0 * gamma_star + PI * a.abs(),
        (kk + 6.0) * j,
        (3.0 * geo.dd * j + 5.0 * PI * geo.drho / q) / EPS,
        tally.t / EPS,
    ];
    Bound {
        total: geo.u * EPS * parts.iter().sum::<f64>(),
        u: geo.u,
        parts,
        undecided: tally.undecided,
    }
}

/// The module's error bound for the `f32` line `(c, s, o)` at a receiver
/// (module docs, "Error bound"), from exact `f64` geometry.
fn bound(
    light: &QuadLight,
    rec: &Receiver,
    shadows: &[Shadow],
    c32: f32,
    s32: f32,
    o32: f32,
) -> Bound {
    let Some(geo) = line_geometry(light, rec, c32, s32, o32) else {
        return Bound::default();
    };
    let chord = chord_boundaries(&geo);
    let mut tally = Tally::default();
    let Some((w0, w1)) = widened_chord(&chord, &mut tally) else {
        return Bound {
            u: geo.u,
            ..Bound::default()
        };
    };
    if w0 >= w1 {
        return Bound {
            total: geo.u * tally.t,
            u: geo.u,
            parts: [0.0, 0.0, 0.0, 0.0, tally.t / EPS],
            undecided: tally.undecided,
        };
    }
    add_chord_terms(&geo, &chord, (w0, w1), &mut tally);
    let k_count = add_shadow_terms(&geo, shadows, (w0, w1), &mut tally);
    assemble(&geo, (w0, w1), k_count, &tally)
}

/// The `f64` reference for the `f32` line: the line `p·(−s, c) = o` the
/// `f32` inputs define, normalised in `f64` (`QuadLight::chord` and
/// `DirectLight::reduce` take the direction as unit; with the `f32`
/// direction as it is they would place the line's nearest point `|f|·δ_d`
/// off, which near the light's plane is not small against `q`).
fn reference(
    light: &QuadLight,
    dl: &DirectLight,
    c: f32,
    s: f32,
    o: f32,
    scratch: &mut [(f64, f64)],
) -> f64 {
    let (c, s, o) = (f64::from(c), f64::from(s), f64::from(o));
    let len = c.hypot(s);
    match light.chord(c / len, s / len, o / len) {
        Some(ch) => dl.line(&ch, scratch).unwrap(),
        None => 0.0,
    }
}

/// Worst-case statistics of one set of lines.
#[derive(Default)]
struct Stats {
    lines: usize,
    worst_ratio: f64,
    worst_at: String,
    worst_parts: [f64; 5],
    /// Largest `|err|/U` (error in units of the line's integrand scale).
    worst_rel_u: f64,
    /// Its bound in the same units.
    worst_rel_u_bound: f64,
    /// Lines on a parallel boundary (decided either way; not in the worst
    /// ratio or `|err|/U`).
    undecided: usize,
    /// Largest `|err|/I₆₄` over lines with `I₆₄ ≥ 10⁻³ max I₆₄` of the set.
    values: Vec<(f64, f64)>,
}

impl Stats {
    fn report(&self, name: &str) {
        let max = self.values.iter().map(|v| v.1).fold(0.0f64, f64::max);
        let rel = self
            .values
            .iter()
            .filter(|v| v.1 >= 1e-3 * max && v.1 > 0.0)
            .map(|v| (v.0 - v.1).abs() / v.1)
            .fold(0.0f64, f64::max);
        let p = self.worst_parts;
        println!(
            "{name}: {} lines ({} on a parallel boundary); worst |err|/bound {:.3e} at {} (bound/εU: evaluation {:.1}, \
             common {:.1}, sums {:.1}, offset {:.1}, ends {:.1}); worst |err|/U {:.2} ε \
             (bound there {:.1} ε); worst relative error where I ≥ 10⁻³ max I: {:.1} ε",
            self.lines,
            self.undecided,
            self.worst_ratio,
            self.worst_at,
            p[0],
            p[1],
            p[2],
            p[3],
            p[4],
            self.worst_rel_u / EPS,
            self.worst_rel_u_bound / EPS,
            rel / EPS
        );
    }
}

/// Checks a batch of lines at one receiver against the bound; returns the
/// `f32` results.
fn check_lines(
    light: &QuadLight,
    rec: &Receiver,
    shadows: &[Shadow],
    lines: &[(f32, f32, f32)],
    stats: &mut Stats,
    what: &str,
) -> Vec<f32> {
    let dl32 = DirectLight32::<CAP>::new(light, rec.x, rec.n, shadows).unwrap();
    let dl = DirectLight::new(light, rec.x, rec.n, shadows).unwrap();
    let mut scratch = vec![(0.0, 0.0); dl.scratch_len()];
    let cs: Vec<f32> = lines.iter().map(|l| l.0).collect();
    let ss: Vec<f32> = lines.iter().map(|l| l.1).collect();
    let os: Vec<f32> = lines.iter().map(|l| l.2).collect();
    let mut out = vec![0.0f32; lines.len()];
    dl32.line_batch_f32(&cs, &ss, &os, &mut out).unwrap();
    let (_, h) = light.foot(rec.x);
    for (k, &(c, s, o)) in lines.iter().enumerate() {
        let want = reference(light, &dl, c, s, o, &mut scratch);
        let got = f64::from(out[k]);
        let err = (got - want).abs();
        let bd = bound(light, rec, shadows, c, s, o);
        let b = bd.total + 1e-12 * want.abs();
        assert!(
            err <= b,
            "{what}: x = {:?}, n = {:?}, line ({c:e}, {s:e}, {o:e}): f32 {got:e}, f64 {want:e}, \
             |err| {err:e} > bound {b:e}",
            rec.x,
            rec.n
        );
        if bd.undecided {
            stats.undecided += 1;
        } else if h > 0.0 && err / bd.u > stats.worst_rel_u {
            stats.worst_rel_u = err / bd.u;
            stats.worst_rel_u_bound = b / bd.u;
        }
        if !bd.undecided && b > 0.0 && err / b > stats.worst_ratio {
            stats.worst_ratio = err / b;
            stats.worst_parts = bd.parts;
            stats.worst_at = format!(
                "{what}, x = {:.4?}, line ({c}, {s}, {o}), f32 {got:.6e}, f64 {want:.6e}",
                rec.x
            );
        }
        if !bd.undecided {
            stats.values.push((got, want));
        }
        stats.lines += 1;
    }
    out
}

/// `count` random lines across the light (offsets 5 % beyond the light's
/// range on each side, so some miss), `f32` inputs.
fn random_lines(light: &QuadLight, count: usize, rng: &mut Rng) -> Vec<(f32, f32, f32)> {
    (0..count)
        .map(|_| {
            let phi = PI * rng.uniform();
            let (c, s) = (phi.cos() as f32, phi.sin() as f32);
            let (lo, hi) = light.offset_range(f64::from(c), f64::from(s));
            let w = hi - lo;
            let o = lo - 0.05 * w + 1.1 * w * rng.uniform();
            (c, s, o as f32)
        })
        .collect()
}

/// A line through the light point `p` (light coordinates) at a random
/// angle.
fn line_through(p: [f64; 2], rng: &mut Rng) -> (f32, f32, f32) {
    let phi = PI * rng.uniform();
    let (c, s) = (phi.cos() as f32, phi.sin() as f32);
    let o = -f64::from(s) * p[0] + f64::from(c) * p[1];
    (c, s, o as f32)
}

/// The vertices of a shadow's polygon in light coordinates (consecutive
/// planes' intersections; planes are in the order of the clipped face's
/// edges).
fn shadow_corners(sh: &Shadow) -> Vec<[f64; 2]> {
    let p = sh.planes();
    let k = p.len();
    (0..k)
        .filter_map(|i| {
            let (a, b) = (p[i], p[(i + 1) % k]);
            let det = a[0] * b[1] - a[1] * b[0];
            (det.abs() > 1e-12).then(|| {
                [
                    (-a[2] * b[1] + b[2] * a[1]) / det,
                    (-a[0] * b[2] + b[0] * a[2]) / det,
                ]
            })
        })
        .collect()
}

// ------------------------------------------------------------ the tests

/// Random receivers in the Cornell scene, random lines, lines through the
/// light's corners and through every shadow's corners.
#[test]
fn cornell_box_within_bound() {
    let scene = Scene::cornell();
    let light = scene.light;
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let recs = cornell_receivers(&scene, 400, &mut rng);
    let [l1, l2] = light.lengths();
    let corners = [[0.0, 0.0], [l1, 0.0], [0.0, l2], [l1, l2]];
    let (mut st, mut sc) = (Stats::default(), Stats::default());
    let mut shadowed = 0usize;
    for rec in &recs {
        let lines = random_lines(&light, 48, &mut rng);
        let out = check_lines(&light, rec, &rec.shadows, &lines, &mut st, "cornell random");
        let dl = DirectLight::new(&light, rec.x, rec.n, &rec.shadows).unwrap();
        let full: f64 = lines
            .iter()
            .filter_map(|&(c, s, o)| light.chord(f64::from(c), f64::from(s), f64::from(o)))
            .map(|ch| dl.line_unoccluded(&ch))
            .sum();
        if (out.iter().map(|&v| f64::from(v)).sum::<f64>()) < 0.999 * full {
            shadowed += 1;
        }
        let mut through: Vec<(f32, f32, f32)> =
            corners.iter().map(|&p| line_through(p, &mut rng)).collect();
        for sh in &rec.shadows {
            for p in shadow_corners(sh) {
                through.push(line_through(p, &mut rng));
            }
        }
        check_lines(
            &light,
            rec,
            &rec.shadows,
            &through,
            &mut sc,
            "cornell corners",
        );
    }
    st.report("Cornell box, random lines");
    sc.report("Cornell box, lines through light and shadow corners");
    println!(
        "{} receivers, {shadowed} with shadowed lines, shadows per receiver ≤ {}",
        recs.len(),
        recs.iter().map(|r| r.shadows.len()).max().unwrap()
    );
    // The scene must exercise the union: most receivers see some shadow.
    assert!(shadowed > recs.len() / 5, "{shadowed}");
}

/// Receivers `10⁻²…10⁻⁶` above the light's plane (feet inside, on the
/// edge of, and outside the light; normals towards the light, tilted or
/// not), with a small blocker half-way up near the foot, and lines through
/// the foot, the light's corners and random ones.
#[test]
fn near_the_light_plane_within_bound() {
    let scene = Scene::cornell();
    let light = scene.light;
    let nl = light.normal();
    let [l1, l2] = light.lengths();
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let mut st = Stats::default();
    for &h in &[1e-2, 1e-3, 1e-4, 1e-6] {
        for case in 0..24 {
            // Foot: inside, on an edge, outside.
            let (fa, fb) = match case % 3 {
                0 => (l1 * rng.uniform(), l2 * rng.uniform()),
                1 => (0.0, l2 * rng.uniform()),
                _ => (l1 * (1.0 + 0.3 * rng.uniform()), -0.2 * l2 * rng.uniform()),
            };
            let x = add(light.point(fa, fb), scale(nl, h));
            // Normal: towards the light (−n_L), tilted up to 80°.
            let t = rng.unit_vector();
            let tilt = 1.4 * rng.uniform() * f64::from(u8::from(case % 4 != 0));
            let perp = unit(sub(t, scale(nl, dot(t, nl))));
            let n = add(scale(nl, -tilt.cos()), scale(perp, tilt.sin()));
            // A blocker at h/2 near the foot.
            let bc = add(
                light.point(fa + 0.3 * h - 0.01, fb - 0.02),
                scale(nl, 0.5 * h),
            );
            let [ua, ub] = light.axes();
            let blocker = Parallelogram::new(bc, scale(ua, 0.02), scale(ub, 0.015)).unwrap();
            let mut shadows = vec![Shadow::EMPTY; 1];
            let k = Shadow::project_all(&light, x, &[blocker], &mut shadows).unwrap();
            shadows.truncate(k);
            let rec = Receiver { x, n, shadows };
            let mut lines = random_lines(&light, 24, &mut rng);
            for _ in 0..8 {
                let (c, s, _) = line_through([fa, fb], &mut rng);
                // Through the foot, and at distances h, 10h from it.
                let o0 = -f64::from(s) * fa + f64::from(c) * fb;
                for d in [0.0, h, 10.0 * h] {
                    lines.push((c, s, (o0 + d) as f32));
                }
            }
            for p in [[0.0, 0.0], [l1, 0.0], [0.0, l2], [l1, l2]] {
                lines.push(line_through(p, &mut rng));
            }
            check_lines(
                &light,
                &rec,
                &rec.shadows,
                &lines,
                &mut st,
                &format!("h = {h:e}"),
            );
        }
    }
    st.report("near the light's plane");
}

/// Receivers whose tangent plane cuts the light (the clamp inside the
/// chord), with the Cornell boxes' shadows, and lines through the clamp
/// line's intersections with the light's edges.
#[test]
fn tangent_plane_cutting_the_light_within_bound() {
    let scene = Scene::cornell();
    let light = scene.light;
    let [l1, l2] = light.lengths();
    let mut rng = Rng(0xD1B5_4A32_D192_ED03);
    let mut st = Stats::default();
    let mut cut = 0;
    for _ in 0..300 {
        let x = [
            -0.6 + 1.2 * rng.uniform(),
            0.05 + 1.9 * rng.uniform(),
            -0.6 + 1.2 * rng.uniform(),
        ];
        if scene.inside_box(x) {
            continue;
        }
        // n ⟂ (y0 − x) for a random light point y0: the tangent plane
        // contains y0.
        let y0 = light.point(l1 * rng.uniform(), l2 * rng.uniform());
        let w = unit(sub(y0, x));
        let t = rng.unit_vector();
        let n = unit(sub(t, scale(w, dot(t, w))));
        let rec = Receiver {
            x,
            n,
            shadows: scene.shadows(x),
        };
        let dl = DirectLight::new(&light, x, n, &rec.shadows).unwrap();
        let mut lines = random_lines(&light, 40, &mut rng);
        // Lines through y0 (on the clamp line).
        let (f0, _) = light.foot(y0);
        for _ in 0..8 {
            lines.push(line_through(f0, &mut rng));
        }
        let out = check_lines(&light, &rec, &rec.shadows, &lines, &mut st, "tangent plane");
        // Count the lines where the clamp is active inside the chord.
        for (k, &(c, s, o)) in lines.iter().enumerate() {
            if let Some(ch) = light.chord(f64::from(c), f64::from(s), f64::from(o)) {
                let (a, beta, _, tf) = dl.reduce(&ch);
                let sc = tf - a / beta;
                if beta != 0.0 && sc > ch.t0 && sc < ch.t1 && out[k] > 0.0 {
                    cut += 1;
                }
            }
        }
    }
    st.report("tangent plane cutting the light");
    assert!(cut > 1000, "{cut}");
}

/// Every shadow passed twice: the union counts each gap once (a wrong
/// tie-break between intervals ending at the same point counts it twice or
/// not at all), so the result is bit-identical to the single list, and
/// within the bound of the `f64` path with the doubled list.
#[test]
fn duplicated_shadows_change_nothing() {
    let scene = Scene::cornell();
    let light = scene.light;
    let mut rng = Rng(0x0123_4567_89AB_CDEF);
    let recs = cornell_receivers(&scene, 120, &mut rng);
    let mut st = Stats::default();
    let mut with_shadows = 0;
    for rec in &recs {
        if rec.shadows.is_empty() {
            continue;
        }
        with_shadows += 1;
        let doubled: Vec<Shadow> = rec.shadows.iter().chain(&rec.shadows).copied().collect();
        let lines = random_lines(&light, 40, &mut rng);
        let once = check_lines(&light, rec, &rec.shadows, &lines, &mut st, "single");
        let twice = check_lines(&light, rec, &doubled, &lines, &mut st, "doubled");
        for k in 0..lines.len() {
            assert_eq!(once[k].to_bits(), twice[k].to_bits(), "line {:?}", lines[k]);
        }
    }
    st.report("single and doubled shadow lists");
    assert!(with_shadows > 60, "{with_shadows}");
}

/// The SIMD batch against its scalar twin and the single-line method, bit
/// for bit, on thousands of lines (Cornell and near-plane receivers), for
/// every length mod 8 (the tails go through the scalar instantiation).
#[test]
fn simd_batch_is_bit_identical_to_scalar_twin() {
    let scene = Scene::cornell();
    let light = scene.light;
    let mut rng = Rng(0x5851_F42D_4C95_7F2D);
    let mut recs = cornell_receivers(&scene, 40, &mut rng);
    // Near-plane receivers with a tilted normal.
    for &h in &[1e-3, 1e-6] {
        let x = add(light.point(0.2, 0.1), scale(light.normal(), h));
        recs.push(Receiver {
            x,
            n: unit([0.3, 1.0, -0.2]),
            shadows: vec![],
        });
    }
    let mut total = 0;
    let mut nonzero = 0;
    // FNV-1a over every result's bits: the same in the x86-64-v3 and the
    // baseline SSE2 build (CI runs both), so the batch is bit-identical
    // across builds too, not only to its scalar twin within one.
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for (r, rec) in recs.iter().enumerate() {
        let dl32 = DirectLight32::<CAP>::new(&light, rec.x, rec.n, &rec.shadows).unwrap();
        let len = 200 + r % 8 + 8 * (r % 3);
        let mut lines = random_lines(&light, len, &mut rng);
        // Axis-aligned directions and lines through the corners.
        lines[0] = (1.0, 0.0, 0.1);
        lines[1] = (0.0, 1.0, -0.2);
        lines[2] = (-1.0, 0.0, -0.3);
        lines[3] = (1.0, 0.0, 0.0);
        lines[4] = line_through([0.0, 0.0], &mut rng);
        let cs: Vec<f32> = lines.iter().map(|l| l.0).collect();
        let ss: Vec<f32> = lines.iter().map(|l| l.1).collect();
        let os: Vec<f32> = lines.iter().map(|l| l.2).collect();
        for cut in [len, len - 1, len - 3, 13, 8, 7, 1, 0] {
            let mut simd = vec![0.0f32; cut];
            let mut scalar = vec![0.0f32; cut];
            dl32.line_batch_f32(&cs[..cut], &ss[..cut], &os[..cut], &mut simd)
                .unwrap();
            dl32.line_batch_scalar_f32(&cs[..cut], &ss[..cut], &os[..cut], &mut scalar)
                .unwrap();
            for k in 0..cut {
                let one = dl32.line_f32(cs[k], ss[k], os[k]);
                assert_eq!(
                    simd[k].to_bits(),
                    scalar[k].to_bits(),
                    "receiver {r}, line {k} of {cut}"
                );
                assert_eq!(one.to_bits(), scalar[k].to_bits(), "receiver {r}, line {k}");
                nonzero += usize::from(simd[k] != 0.0);
                for b in simd[k].to_bits().to_le_bytes() {
                    hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
                }
            }
            total += cut;
        }
    }
    println!(
        "bit-identical: {total} lines ({nonzero} non-zero), SIMD batch = scalar twin = line_f32; \
         FNV-1a of the results {hash:#018x}"
    );
    assert!(total > 8000 && nonzero > total / 3);
    assert_eq!(hash, PIN, "the results changed (or differ between builds)");
}

/// Axis-aligned lines (`cos φ`, `sin φ` exactly 0 or ±1) against an
/// axis-aligned blocker, whose cone planes then have `k = 0` exactly on
/// these lines (a line beside the blocker's projected edge must see no
/// shadow, a line on it is decided either way), and a receiver whose
/// tangent plane is parallel to lines along `ê₂` (`β = 0` exactly: lines
/// behind the plane are dark); offsets swept across the light, and the
/// blocker's projected edges exactly.
#[test]
fn axis_aligned_lines_within_bound() {
    let scene = Scene::cornell();
    let light = scene.light;
    let blocker =
        Parallelogram::new([-0.1, 1.2, -0.1], [0.15, 0.0, 0.0], [0.0, 0.0, 0.12]).unwrap();
    let mut st = Stats::default();
    let mut parallel_and_empty = 0;
    for (x, n) in [
        ([0.05, 0.3, -0.05], [0.0, 1.0, 0.0]),
        ([-0.02, 0.9, 0.03], [0.3, 1.0, 0.2]),
        ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0]),
        ([0.0, 1.0, 0.0], [0.0, 0.0, -1.0]),
    ] {
        let mut shadows = vec![Shadow::EMPTY; 1];
        let k = Shadow::project_all(&light, x, &[blocker], &mut shadows).unwrap();
        shadows.truncate(k);
        let rec = Receiver { x, n, shadows };
        let mut lines = Vec::new();
        for (c, s) in [(1.0f32, 0.0f32), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)] {
            let (lo, hi) = light.offset_range(f64::from(c), f64::from(s));
            for i in 0..=96 {
                lines.push((c, s, (lo + (hi - lo) * f64::from(i) / 96.0) as f32));
            }
            // Along the projected edges of the blocker (the planes with k = 0).
            for sh in &rec.shadows {
                for p in sh.planes() {
                    let k = p[0] * f64::from(c) + p[1] * f64::from(s);
                    let nd = -p[0] * f64::from(s) + p[1] * f64::from(c);
                    if k == 0.0 && nd != 0.0 {
                        // p·d⊥ = o on the edge: α a + β b + γ = 0, o = −γ/nd.
                        let o = -p[2] / nd;
                        for d in [-1e-3, -1e-6, 0.0, 1e-6, 1e-3] {
                            lines.push((c, s, (o + d) as f32));
                        }
                    }
                }
            }
        }
        let out = check_lines(&light, &rec, &rec.shadows, &lines, &mut st, "axis-aligned");
        // Lines beside the blocker's shadow band, parallel to its edges, are
        // unshadowed.
        let dl = DirectLight::new(&light, x, n, &rec.shadows).unwrap();
        for (k, &(c, s, o)) in lines.iter().enumerate() {
            if let Some(ch) = light.chord(f64::from(c), f64::from(s), f64::from(o)) {
                let mut scratch = [(0.0, 0.0); 1];
                if dl.shadowed(&ch, &mut scratch).unwrap() == 0 && out[k] > 0.0 {
                    parallel_and_empty += 1;
                }
            }
        }
    }
    st.report("axis-aligned lines and blocker");
    assert!(parallel_and_empty > 300, "{parallel_and_empty}");
}

/// Receivers behind the light (the ceiling) and lines missing the light
/// give exactly 0; a receiver without shadows equals the unoccluded `f64`
/// integral within the bound.
#[test]
fn dark_receivers_and_missing_lines_are_zero() {
    let scene = Scene::cornell();
    let light = scene.light;
    let mut rng = Rng(42);
    let ceiling =
        DirectLight32::<CAP>::new(&light, [0.0, 2.0, 0.0], [0.0, -1.0, 0.0], &[]).unwrap();
    assert!(!ceiling.is_lit());
    let lines = random_lines(&light, 64, &mut rng);
    let cs: Vec<f32> = lines.iter().map(|l| l.0).collect();
    let ss: Vec<f32> = lines.iter().map(|l| l.1).collect();
    let os: Vec<f32> = lines.iter().map(|l| l.2).collect();
    let mut out = vec![1.0f32; lines.len()];
    ceiling.line_batch_f32(&cs, &ss, &os, &mut out).unwrap();
    assert!(out.iter().all(|&v| v.to_bits() == 0));
    let floor = DirectLight32::<CAP>::new(&light, [0.1, 0.0, 0.2], [0.0, 1.0, 0.0], &[]).unwrap();
    assert!(floor.is_lit());
    let (lo, hi) = light.offset_range(0.6, 0.8);
    for o in [lo - 1e-3, hi + 1e-3, lo - 5.0, hi + 100.0] {
        assert_eq!(floor.line_f32(0.6, 0.8, o as f32).to_bits(), 0);
    }
    // Parallel to an edge, outside the light.
    assert_eq!(floor.line_f32(1.0, 0.0, -0.01).to_bits(), 0);
    assert_eq!(floor.line_f32(0.0, 1.0, 0.01).to_bits(), 0);
    // A receiver facing away from the light.
    let away = DirectLight32::<CAP>::new(&light, [0.1, 0.5, 0.2], [0.0, -1.0, 0.0], &[]).unwrap();
    for &(c, s, o) in &lines {
        assert_eq!(away.line_f32(c, s, o).to_bits(), 0);
    }
}

/// Bad input: `new` and the batches return `ParamError`s naming the
/// parameter, and write nothing.
#[test]
fn validation() {
    let scene = Scene::cornell();
    let light = scene.light;
    let x = [0.0, 0.5, 0.0];
    let n = [0.0, 1.0, 0.0];
    assert_eq!(
        DirectLight32::<4>::new(&light, [f64::NAN, 0.0, 0.0], n, &[]).unwrap_err(),
        ParamError::NonFinite { name: "x" }
    );
    assert_eq!(
        DirectLight32::<4>::new(&light, x, [0.0, f64::INFINITY, 0.0], &[]).unwrap_err(),
        ParamError::NonFinite { name: "n" }
    );
    assert_eq!(
        DirectLight32::<4>::new(&light, x, [0.0; 3], &[]).unwrap_err(),
        ParamError::ZeroDirection
    );
    let shadows = scene.shadows([0.9, 0.0, 0.9]);
    assert!(shadows.len() >= 2, "{}", shadows.len());
    assert_eq!(
        DirectLight32::<1>::new(&light, [0.9, 0.0, 0.9], n, &shadows).unwrap_err(),
        ParamError::Length {
            name: "shadows",
            expected: 1,
            got: shadows.len()
        }
    );
    // Outside the f32 range: too close to the light's plane, too far (a
    // light through the origin, so 10⁻²⁰ is representable).
    let at0 = QuadLight::new([0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]).unwrap();
    assert!(matches!(
        DirectLight32::<4>::new(&at0, [0.1, -1e-20, 0.1], n, &[]),
        Err(ParamError::OutOfRange { name: "x", .. })
    ));
    assert!(DirectLight32::<4>::new(&at0, [0.1, -1e-17, 0.1], n, &[])
        .unwrap()
        .is_lit());
    assert!(matches!(
        DirectLight32::<4>::new(&light, [0.0, -1e19, 0.0], n, &[]),
        Err(ParamError::OutOfRange { name: "x", .. })
    ));
    // Behind the light is fine (dark), however close.
    assert!(!DirectLight32::<4>::new(&at0, [0.1, 1e-20, 0.1], n, &[])
        .unwrap()
        .is_lit());

    let dl = DirectLight32::<4>::new(&light, x, n, &[]).unwrap();
    let c = [1.0f32; 9];
    let s = [0.0f32; 9];
    let o = [0.1f32; 9];
    let mut out = [7.0f32; 9];
    type Batch =
        fn(&DirectLight32<4>, &[f32], &[f32], &[f32], &mut [f32]) -> Result<(), ParamError>;
    let batches: [(&str, Batch); 2] = [
        ("simd", DirectLight32::<4>::line_batch_f32),
        ("scalar", DirectLight32::<4>::line_batch_scalar_f32),
    ];
    for (what, f) in batches {
        let len = |name, expected, got| ParamError::Length {
            name,
            expected,
            got,
        };
        assert_eq!(
            f(&dl, &c, &s[..8], &o, &mut out),
            Err(len("sin_phi", 9, 8)),
            "{what}"
        );
        assert_eq!(
            f(&dl, &c, &s, &o[..3], &mut out),
            Err(len("offsets", 9, 3)),
            "{what}"
        );
        assert_eq!(
            f(&dl, &c, &s, &o, &mut out[..8]),
            Err(len("out", 9, 8)),
            "{what}"
        );
        assert_eq!(
            f(&dl, &c[..8], &s, &o, &mut out[..8]),
            Err(len("sin_phi", 8, 9)),
            "{what}"
        );
        let mut bad = o;
        bad[8] = f32::NAN;
        assert_eq!(
            f(&dl, &c, &s, &bad, &mut out),
            Err(ParamError::NonFinite { name: "offsets" }),
            "{what}"
        );
        let mut bad = c;
        bad[3] = f32::INFINITY;
        assert_eq!(
            f(&dl, &bad, &s, &o, &mut out),
            Err(ParamError::NonFinite { name: "cos_phi" }),
            "{what}"
        );
        let mut bad = s;
        bad[5] = 0.01;
        assert!(
            matches!(
                f(&dl, &c, &bad, &o, &mut out),
                Err(ParamError::OutOfRange {
                    name: "sin_phi",
                    ..
                })
            ),
            "{what}"
        );
        assert!(
            out.iter().all(|&v| v == 7.0),
            "{what}: wrote before failing"
        );
        // Empty batches are fine.
        assert_eq!(f(&dl, &[], &[], &[], &mut []), Ok(()));
    }
    assert!(dl.line_f32(f32::NAN, 0.0, 0.0).is_nan());
    assert!(dl.line_f32(0.6, 0.6, 0.0).is_nan());
}
