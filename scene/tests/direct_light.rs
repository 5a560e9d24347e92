//! Direct light from a rectangular light (`linesample_scene::direct_light`)
//! against references that share nothing with the module's derivation:
//!
//! 1. **Line integrals against 40-digit quadrature of the 3D geometry.**
//!    `scene/tests/data/direct_light_ref.csv` (written by
//!    `tools/direct_light_ref.py`, mpmath at 40 digits) integrates
//!    `G(y) = max(0, n·(y − x))·n_L·(x − y)/|y − x|⁴` directly along the 3D
//!    line `y(t) = c + a(t)·ê₁ + b(t)·ê₂`, with breakpoints at the clamp and
//!    at the foot of the perpendicular, never through the module's reduction
//!    `(h, A, β, q)` or its closed form. Every row must hold `10⁻¹²`
//!    relative, unless its own conditioning (computed here from the 3D
//!    geometry, see [`Conditioning`]) allows more; which rows those are, and
//!    why, is asserted and printed (among them a known limitation of the
//!    module: receivers far from the light, see
//!    [`reference_values_from_3d_quadrature`]). A few rows check
//!    `diffuse_line_integral` alone against its 1D definition (`40ε`).
//! 2. **Visibility against shadow rays**: the shadowed intervals of
//!    `DirectLight::shadowed` against segments `x → y(t)` cast one by one
//!    against every occluder face with an independent Möller–Trumbore
//!    parallelogram test, `10⁵` samples per line, in the Cornell box (two
//!    rotated boxes, and the room's quads, the ceiling beyond the light's
//!    plane); plus an occluder edge whose shadow is within `10⁻⁶` rad of the
//!    line, receivers on box faces, faces straddling the receiver's height,
//!    and a receiver nothing blocks.
//! 3. **`point(a, b)`** against `G` computed here and `V` from the rays.
//! 4. **Whole-light irradiance**: `line_unoccluded` integrated over the
//!    offsets (Gauss–Legendre, split at the kinks) against Lambert's polygon
//!    formula, on the whole rectangle or on its part in front of the
//!    receiver's tangent plane (the rectangle clipped by that plane).
//! 5. **Bad input**: every constructor names the parameter.
//!
//! Everything is deterministic (fixed seeds, `linesample::Pcg32`); under a
//! second in release (`cargo test --release -p linesample-scene --test direct_light`).

use linesample::{ParamError, Pcg32};
use linesample_scene::direct_light::{
    diffuse_line_integral, Chord, DirectLight, Parallelogram, QuadLight, Shadow,
};
use std::collections::BTreeMap;

/// `2⁻⁵³`, the unit roundoff.
const EPS: f64 = f64::EPSILON / 2.0;

type V3 = [f64; 3];

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
fn unit(a: V3) -> V3 {
    scale(a, 1.0 / norm(a))
}

/// Uniform doubles from the crate's PCG32 (53 random bits each).
struct Rng(Pcg32);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(Pcg32::new(seed, 0xd1_2ec7))
    }
    fn uniform(&mut self) -> f64 {
        let hi = u64::from(self.0.next_u32());
        let lo = u64::from(self.0.next_u32());
        ((hi << 21) | (lo >> 11)) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }
}

// ------------------------------------------------------------------ geometry

/// The light's frame rebuilt here from its inputs, as the module's docs
/// define it (`ê₁ = e₁/|e₁|`, `ê₂` the unit part of `e₂` orthogonal to
/// `ê₁`, `n_L = ê₁ × ê₂`), for the independent references.
#[derive(Clone, Copy, Debug)]
struct Frame {
    c: V3,
    u: V3,
    v: V3,
    nl: V3,
    len: [f64; 2],
}

impl Frame {
    fn new(c: V3, e1: V3, e2: V3) -> Self {
        let u = unit(e1);
        let w = unit(e2);
        let v = unit(sub(w, scale(u, dot(u, w))));
        Frame {
            c,
            u,
            v,
            nl: cross(u, v),
            len: [norm(e1), norm(e2)],
        }
    }
    /// The 3D point of light coordinates `(a, b)`.
    fn point(&self, a: f64, b: f64) -> V3 {
        add(self.c, add(scale(self.u, a), scale(self.v, b)))
    }
    /// The 3D point at `t` on a chord's line.
    fn on_line(&self, ch: &Chord, t: f64) -> V3 {
        self.point(ch.p0[0] + t * ch.dir[0], ch.p0[1] + t * ch.dir[1])
    }
}

/// `G(x, y) = max(0, n·(y − x))·n_L·(x − y)/|y − x|⁴` (unit `n`), straight
/// from the 3D points.
fn geometry_term(f: &Frame, x: V3, n: V3, y: V3) -> f64 {
    let w = sub(y, x);
    let c = dot(n, w);
    if c <= 0.0 {
        return 0.0;
    }
    let r2 = dot(w, w);
    c * dot(f.nl, sub(x, y)) / (r2 * r2)
}

/// `Σ |nᵢ (yᵢ − xᵢ)|`: the scale of the terms that make up `n·(y − x)`,
/// so `ε` times it is the absolute rounding of that dot product.
fn dot_scale(a: V3, b: V3) -> f64 {
    (a[0] * b[0]).abs() + (a[1] * b[1]).abs() + (a[2] * b[2]).abs()
}

// ------------------------------------------------------------ 1. references

/// One row of `scene/tests/data/direct_light_ref.csv` (see
/// `tools/direct_light_ref.py` for the columns).
#[derive(Clone, Debug)]
struct Row {
    kind: String,
    class: String,
    corner: V3,
    e1: V3,
    e2: V3,
    x: V3,
    n: V3,
    cos: f64,
    sin: f64,
    offset: f64,
    p0: [f64; 2],
    chord_t0: f64,
    chord_t1: f64,
    t_lo: f64,
    t_hi: f64,
    whole: bool,
    h: f64,
    a: f64,
    beta: f64,
    q: f64,
    t_perp: f64,
    t_clamp: f64,
    ref_hi: f64,
    ref_lo: f64,
    dlog_da: f64,
}

impl Row {
    fn chord(&self) -> Chord {
        Chord {
            p0: self.p0,
            dir: [self.cos, self.sin],
            t0: self.chord_t0,
            t1: self.chord_t1,
        }
    }
    /// `|got − ref|/|ref|`, with the reference as `ref_hi + ref_lo` (so
    /// errors below one ulp are measured).
    fn rel_err(&self, got: f64) -> f64 {
        ((got - self.ref_hi) - self.ref_lo).abs() / self.ref_hi.abs()
    }
}

fn rows() -> Vec<Row> {
    let text = include_str!("data/direct_light_ref.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header.len(), 36, "columns of direct_light_ref.csv");
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), header.len(), "{l}");
            let v = |i: usize| -> f64 { f[i].parse().unwrap() };
            let v3 = |i: usize| [v(i), v(i + 1), v(i + 2)];
            Row {
                kind: f[0].to_string(),
                class: f[1].to_string(),
                corner: v3(2),
                e1: v3(5),
                e2: v3(8),
                x: v3(11),
                n: v3(14),
                cos: v(17),
                sin: v(18),
                offset: v(19),
                p0: [v(20), v(21)],
                chord_t0: v(22),
                chord_t1: v(23),
                t_lo: v(24),
                t_hi: v(25),
                whole: f[26] == "1",
                h: v(27),
                a: v(28),
                beta: v(29),
                q: v(30),
                t_perp: v(31),
                t_clamp: v(32),
                ref_hi: v(33),
                ref_lo: v(34),
                dlog_da: v(35),
            }
        })
        .collect()
}

/// How much rounding the *inputs* of a row amplify, from the 3D geometry
/// only (relative error of the result per unit roundoff `ε`):
///
/// * `numerator`: `n·(y − x)` is a dot product, so its absolute rounding is
///   `ε·Σ|nᵢ(yᵢ − xᵢ)|` (largest over the interval); times `(1/I)·dI/dδ`
///   (the file's `dlog_da`, by quadrature: the sensitivity to adding `δ`
///   to `n·(y − x)`). Large where `n·(y − x)` is formed by cancellation:
///   a tilted receiver just below the light's plane seen along lines
///   through its foot, and intervals that end at the clamp.
/// * `height`: `h = n_L·(x − c)` rounds by `ε·Σ|n_Lᵢ(xᵢ − cᵢ)|`, relative
///   to `h` (exact for an axis-aligned light; `~|x − c|/h` otherwise).
/// * `ends`: moving an end `t` by `ε|t|` changes `I` by `ε|t|·G(t)`.
/// * `along`: not input conditioning but the module's own rounding of `s =
///   t − t_f` (in `DirectLight::line_interval`), `ε|t − t_f|·G(t)` per end:
///   large when the foot of the perpendicular is far along the line
///   compared with the interval (far receivers). See
///   [`reference_values_from_3d_quadrature`].
#[derive(Clone, Copy, Debug)]
struct Conditioning {
    numerator: f64,
    height: f64,
    ends: f64,
    along: f64,
}

impl Conditioning {
    fn of(r: &Row) -> Self {
        let f = Frame::new(r.corner, r.e1, r.e2);
        let n = unit(r.n);
        let ch = r.chord();
        let tp = r.t_perp.clamp(r.t_lo, r.t_hi);
        // n·(y − x) directly in 3D, or through the light's frame as
        // n·(c − x) + (n·ê₁) a + (n·ê₂) b: the larger of the two scales.
        let (nu, nv) = (dot(n, f.u).abs(), dot(n, f.v).abs());
        let s_n = [r.t_lo, r.t_hi, tp]
            .iter()
            .map(|&t| {
                let (a, b) = (ch.p0[0] + t * ch.dir[0], ch.p0[1] + t * ch.dir[1]);
                let framed = dot_scale(n, sub(f.c, r.x)) + nu * a.abs() + nv * b.abs();
                framed.max(dot_scale(n, sub(f.on_line(&ch, t), r.x)))
            })
            .fold(0.0, f64::max);
        let h = dot(f.nl, sub(r.x, f.c));
        let g = |t: f64| geometry_term(&f, r.x, n, f.on_line(&ch, t)) / r.ref_hi;
        let (g_lo, g_hi) = (g(r.t_lo), g(r.t_hi));
        Conditioning {
            numerator: s_n * r.dlog_da,
            height: dot_scale(f.nl, sub(r.x, f.c)) / h,
            ends: r.t_lo.abs() * g_lo + r.t_hi.abs() * g_hi,
            along: (r.t_lo - r.t_perp).abs() * g_lo + (r.t_hi - r.t_perp).abs() * g_hi,
        }
    }
    fn inputs(&self) -> f64 {
        self.numerator + self.height + self.ends
    }
    fn total(&self) -> f64 {
        self.inputs() + self.along
    }
}

/// Rounding bound factor: the measured worst `err/(ε·κ)` is 1.3 (see the
/// printed table); 16 leaves a margin of 12.
const K_BOUND: f64 = 16.0;

/// Test 1. Every row against its 40-digit reference.
///
/// The rule: `|I − I_ref| ≤ 10⁻¹²·|I_ref|`, or `K_BOUND·ε·κ` where that is
/// larger, `κ` the row's [`Conditioning`] total. The rows that actually
/// exceed `10⁻¹²` are of two kinds, each asserted to occur only in the
/// classes built for it, and printed:
///
/// * **ill-conditioned inputs** (the error is within `K_BOUND·ε·κ_inputs`):
///   the tiny sub-intervals (`10⁻⁶` of the chord: their ends' rounding alone
///   is `ε|t|/(t_hi − t_lo)`), the tiny intervals ending at the clamp (where
///   the `10⁻¹²` rule is replaced by the module docs' own statement, tested
///   separately below), and lines through the foot of tilted receivers
///   `10⁻⁶`, `10⁻⁹` above the light's plane (`n·(y − x) ≈ −h n·n_L` there,
///   formed by cancellation).
/// * **a known limitation of the module** (well-conditioned inputs; only
///   the `along` term explains the error): receivers `10³–10⁶` light sizes
///   away, whose foot of the perpendicular is `|s| ≫ t_hi − t_lo` along
///   the line. `line_interval` forms `s = t − t_f` and loses `ε|s|/(s_hi −
///   s_lo)` there; `diffuse_line_integral` cannot recover it (see the
///   module docs' error bound).
///
/// Whole chords must also agree bit for bit between `line_unoccluded`,
/// `line_interval(t0, t1)` and `line` without shadows, and zero references
/// (the interval wholly behind the tangent plane) must give exactly 0.
#[test]
fn reference_values_from_3d_quadrature() {
    let rows = rows();
    assert!(rows.len() >= 300, "{} rows", rows.len());
    // class -> (worst relative error, row)
    let mut worst: BTreeMap<String, (f64, usize)> = BTreeMap::new();
    let (mut n_strict, mut n_zero) = (0, 0);
    let mut ill = Vec::new();
    let mut limited = Vec::new();
    let mut worst_ratio = 0.0f64;
    let mut worst_clamp_ratio = 0.0f64;
    for (i, r) in rows.iter().enumerate() {
        let got = if r.kind == "free" {
            diffuse_line_integral(r.h, r.a, r.beta, r.q, r.t_lo, r.t_hi)
        } else {
            let light = QuadLight::new(r.corner, r.e1, r.e2).unwrap();
            let dl = DirectLight::new(&light, r.x, r.n, &[]).unwrap();
            let chord = r.chord();
            // The file's chord is QuadLight::chord's (up to the last bit of
            // the direction's normalisation, done by the script in Python).
            let c2 = light.chord(r.cos, r.sin, r.offset).unwrap();
            let dev = [
                c2.p0[0] - chord.p0[0],
                c2.p0[1] - chord.p0[1],
                c2.dir[0] - chord.dir[0],
                c2.dir[1] - chord.dir[1],
                c2.t0 - chord.t0,
                c2.t1 - chord.t1,
            ]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(dev <= 4e-16, "row {i}: QuadLight::chord differs by {dev:e}");
            if r.whole {
                let got = dl.line_unoccluded(&chord);
                assert_eq!(got, dl.line_interval(&chord, chord.t0, chord.t1), "row {i}");
                assert_eq!(got, dl.line(&chord, &mut []).unwrap(), "row {i}");
                got
            } else {
                dl.line_interval(&chord, r.t_lo, r.t_hi)
            }
        };
        if r.ref_hi == 0.0 {
            assert_eq!(got, 0.0, "row {i} ({}): reference 0", r.class);
            n_zero += 1;
            continue;
        }
        let err = r.rel_err(got);
        let w = worst.entry(r.class.clone()).or_insert((0.0, i));
        if err > w.0 {
            *w = (err, i);
        }
        if r.kind == "free" {
            // The closed form's own contract: exact inputs, 40ε.
            assert!(
                err <= 40.0 * EPS,
                "row {i} ({}): free function off by {:.1} ulp",
                r.class,
                err / EPS
            );
            n_strict += 1;
            continue;
        }
        let k = Conditioning::of(r);
        let bound = 1e-12f64.max(K_BOUND * EPS * k.total());
        if err > 1e-12 {
            worst_ratio = worst_ratio.max(err / (EPS * k.total()));
        }
        assert!(
            err <= bound,
            "row {i} ({}): relative error {err:.3e} > bound {bound:.3e} ({k:?})",
            r.class
        );
        if err <= 1e-12 {
            n_strict += 1;
        } else if err <= K_BOUND * EPS * k.inputs() {
            assert!(
                r.class.starts_with("tiny") || r.class.ends_with("-foot"),
                "row {i} ({}) unexpectedly ill-conditioned: {k:?}",
                r.class
            );
            ill.push((i, err, bound));
        } else {
            // The inputs do not explain it. (Before the module passed the
            // interval's width separately, the far receivers landed here:
            // `s = t − t_f` of both ends lost `ε|s|/(s_hi − s_lo)`.)
            limited.push((i, err, bound));
            panic!(
                "row {i} ({}): loses more than 1e-12 on well-conditioned inputs: \
                 {err:.3e} ({k:?})",
                r.class
            );
        }
        if r.class == "tiny-clamp" {
            // A tiny piece that ends at the clamp: the module docs state that
            // the relative error is at most about 4ε·(|x − c| + |y_c − c|)/(|β|·(s_hi
            // − s_lo)) (the clamp s_c = −A/β moves by the absolute rounding of
            // A over |β|, and the piece's integral is ∝ (s_hi − s_lo)²); the
            // 1e-12 rule does not apply here, this statement does. β = n·d is
            // the slope of n·(y − x) along the line, y_c the clamp point, both
            // from the 3D geometry here.
            let f = Frame::new(r.corner, r.e1, r.e2);
            let n = unit(r.n);
            let beta = dot(n, add(scale(f.u, r.cos), scale(f.v, r.sin)));
            let yc = f.on_line(&r.chord(), r.t_clamp);
            let stated = 4.0 * EPS * (norm(sub(r.x, f.c)) + norm(sub(yc, f.c)))
                / (beta.abs() * (r.t_hi - r.t_lo));
            worst_clamp_ratio = worst_clamp_ratio.max(err / stated);
            assert!(
                err <= stated,
                "row {i}: clamp piece {err:.3e} > the docs' {stated:.3e}"
            );
        }
    }
    eprintln!(
        "direct_light references: {} rows ({n_zero} zero, {n_strict} held to 1e-12 or 40ε, \
         {} ill-conditioned, {} limited by s = t − t_f)",
        rows.len(),
        ill.len(),
        limited.len()
    );
    eprintln!(
        "{:>18} {:>14} {:>10}  row",
        "class", "worst (ulp)", "relative"
    );
    for (c, (e, i)) in &worst {
        eprintln!("{c:>18} {:>14.1} {e:>10.2e}  {i}", e / EPS);
    }
    eprintln!("rows beyond 1e-12: worst err/(ε κ) = {worst_ratio:.2} (bound factor {K_BOUND})");
    eprintln!("tiny pieces at the clamp: worst err / docs' statement = {worst_clamp_ratio:.2}");
    let (mut wi, mut wl) = (0.0f64, 0.0f64);
    for &(_, e, _) in &ill {
        wi = wi.max(e);
    }
    for &(i, e, b) in &limited {
        wl = wl.max(e);
        eprintln!(
            "  limitation (s = t − t_f rounding), row {i} ({}): {e:.2e} (bound {b:.2e})",
            rows[i].class
        );
    }
    eprintln!("worst ill-conditioned {wi:.2e}, worst limited {wl:.2e}");
}

// ------------------------------------------------------------ the scene

/// The Cornell box light: emits towards `edge1 × edge2 = −y`.
const LIGHT: (V3, V3, V3) = ([-0.24, 1.98, -0.22], [0.47, 0.0, 0.0], [0.0, 0.0, 0.38]);

fn cornell_light() -> (QuadLight, Frame) {
    (
        QuadLight::new(LIGHT.0, LIGHT.1, LIGHT.2).unwrap(),
        Frame::new(LIGHT.0, LIGHT.1, LIGHT.2),
    )
}

/// An occluder face with its outward normal and the body it belongs to.
#[derive(Clone, Copy, Debug)]
struct Face {
    corner: V3,
    e1: V3,
    e2: V3,
    outward: V3,
    body: usize,
    pg: Parallelogram,
}

impl Face {
    fn new(corner: V3, e1: V3, e2: V3, outward: V3, body: usize) -> Self {
        Face {
            corner,
            e1,
            e2,
            outward,
            body,
            pg: Parallelogram::new(corner, e1, e2).unwrap(),
        }
    }
    fn vertices(&self) -> [V3; 4] {
        let c = self.corner;
        [
            c,
            add(c, self.e1),
            add(add(c, self.e1), self.e2),
            add(c, self.e2),
        ]
    }
}

/// The six faces of a box standing on `y = 0`: base centre `base`, size
/// `(width, height, depth)`, rotated by `deg` degrees about `+y`.
fn box_faces(base: V3, size: V3, deg: f64, body: usize) -> Vec<Face> {
    let (s, c) = deg.to_radians().sin_cos();
    let ex = [c * size[0], 0.0, -s * size[0]];
    let ez = [s * size[2], 0.0, c * size[2]];
    let ey = [0.0, size[1], 0.0];
    let c0 = sub(base, scale(add(ex, ez), 0.5));
    let centre = add(c0, scale(add(add(ex, ey), ez), 0.5));
    [
        (c0, ex, ez),
        (add(c0, ey), ex, ez),
        (c0, ex, ey),
        (add(c0, ez), ex, ey),
        (c0, ez, ey),
        (add(c0, ex), ez, ey),
    ]
    .iter()
    .map(|&(p, a, b)| {
        let mid = add(p, scale(add(a, b), 0.5));
        let mut nrm = unit(cross(a, b));
        if dot(nrm, sub(mid, centre)) < 0.0 {
            nrm = scale(nrm, -1.0);
        }
        Face::new(p, a, b, nrm, body)
    })
    .collect()
}

/// The short (0.6) and the tall (1.2) box of the Cornell box, rotated by
/// ±17° about the vertical, under the light.
fn cornell_boxes() -> Vec<Face> {
    let mut f = box_faces([-0.33, 0.0, 0.30], [0.6, 0.6, 0.6], 17.0, 0);
    f.extend(box_faces([0.33, 0.0, -0.28], [0.6, 1.2, 0.6], -17.0, 1));
    f
}

/// The room's five quads (floor, ceiling just above the light, three walls),
/// with their normals pointing into the room. They block nothing inside
/// the room: the ceiling lies beyond the light's plane (heights `z > h`),
/// the walls straddle both planes, the floor and walls contain some
/// receivers. `Shadow::project` must discard or clip them all.
fn cornell_room() -> Vec<Face> {
    [
        (
            [-1.0, 0.0, -1.0],
            [0.0, 0.0, 2.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ),
        (
            [-1.0, 2.0, -1.0],
            [2.0, 0.0, 0.0],
            [0.0, 0.0, 2.0],
            [0.0, -1.0, 0.0],
        ),
        (
            [-1.0, 0.0, -1.0],
            [2.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 1.0],
        ),
        (
            [1.0, 0.0, -1.0],
            [0.0, 0.0, 2.0],
            [0.0, 2.0, 0.0],
            [-1.0, 0.0, 0.0],
        ),
        (
            [-1.0, 0.0, -1.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 2.0],
            [1.0, 0.0, 0.0],
        ),
    ]
    .iter()
    .enumerate()
    .map(|(i, &(c, a, b, n))| Face::new(c, a, b, n, 10 + i))
    .collect()
}

/// Whether the open segment `x → y` crosses the face: Möller–Trumbore for a
/// parallelogram (`x + u(y − x) = c + α e₁ + β e₂` by Cramer's rule, a hit
/// for `α, β ∈ [0, 1]`, `u ∈ (10⁻¹², 1 − 10⁻¹²)`). Written here, shares
/// nothing with the module's cone construction.
fn segment_blocked(x: V3, y: V3, f: &Face) -> bool {
    let d = sub(y, x);
    let p = cross(d, f.e2);
    let det = dot(f.e1, p);
    if det == 0.0 {
        return false;
    }
    let inv = 1.0 / det;
    let tv = sub(x, f.corner);
    let alpha = dot(tv, p) * inv;
    if !(0.0..=1.0).contains(&alpha) {
        return false;
    }
    let q = cross(tv, f.e1);
    let beta = dot(d, q) * inv;
    if !(0.0..=1.0).contains(&beta) {
        return false;
    }
    let u = dot(f.e2, q) * inv;
    u > 1e-12 && u < 1.0 - 1e-12
}

/// A receiver: position, normal, the faces that may block it.
#[derive(Clone, Debug)]
struct Receiver {
    label: &'static str,
    x: V3,
    n: V3,
    faces: Vec<Face>,
}

/// Receivers of the Cornell box: on the floor (not under a box), on the
/// three walls, on the boxes' top and side faces (that box's faces
/// excluded, as the lab does for convex boxes), and on top of the tall box
/// (nothing above it can block).
fn cornell_receivers(rng: &mut Rng) -> Vec<Receiver> {
    let boxes = cornell_boxes();
    let with_room = |faces: Vec<Face>| -> Vec<Face> {
        let mut f = faces;
        f.extend(cornell_room());
        f
    };
    let mut out = Vec::new();
    let under_a_box = |p: V3| {
        boxes.iter().filter(|f| f.outward[1] < -0.5).any(|f| {
            // (p − c)·e = α|e|², the edges of a base are orthogonal.
            let w = sub(p, f.corner);
            let a = dot(w, f.e1) / dot(f.e1, f.e1);
            let b = dot(w, f.e2) / dot(f.e2, f.e2);
            (-0.01..=1.01).contains(&a) && (-0.01..=1.01).contains(&b)
        })
    };
    while out.len() < 8 {
        let x = [rng.range(-0.95, 0.95), 0.0, rng.range(-0.95, 0.95)];
        if !under_a_box(x) {
            out.push(Receiver {
                label: "floor",
                x,
                n: [0.0, 1.0, 0.0],
                faces: with_room(boxes.clone()),
            });
        }
    }
    for _ in 0..2 {
        let (y, z) = (rng.range(0.02, 1.9), rng.range(-0.95, 0.95));
        out.push(Receiver {
            label: "wall",
            x: [1.0, y, z],
            n: [-1.0, 0.0, 0.0],
            faces: with_room(boxes.clone()),
        });
        out.push(Receiver {
            label: "wall",
            x: [-1.0, y, -z],
            n: [1.0, 0.0, 0.0],
            faces: with_room(boxes.clone()),
        });
        out.push(Receiver {
            label: "wall",
            x: [rng.range(-0.95, 0.95), rng.range(0.02, 1.3), -1.0],
            n: [0.0, 0.0, 1.0],
            faces: with_room(boxes.clone()),
        });
    }
    for k in 0..10 {
        let body = k % 2;
        let own: Vec<&Face> = boxes.iter().filter(|f| f.body == body).collect();
        // Top (index 1) or one of the four sides (2..6).
        let f = own[1 + (k / 2) % 5];
        let (a, b) = (rng.range(0.05, 0.95), rng.range(0.05, 0.95));
        out.push(Receiver {
            label: "box face",
            x: add(f.corner, add(scale(f.e1, a), scale(f.e2, b))),
            n: f.outward,
            faces: with_room(boxes.iter().filter(|g| g.body != body).copied().collect()),
        });
    }
    let top = boxes
        .iter()
        .find(|f| f.body == 1 && f.outward[1] > 0.5)
        .unwrap();
    out.push(Receiver {
        label: "tall box top",
        x: add(top.corner, scale(add(top.e1, top.e2), 0.5)),
        n: [0.0, 1.0, 0.0],
        faces: with_room(boxes.iter().filter(|g| g.body != 1).copied().collect()),
    });
    out
}

/// The shadowed intervals of `chord` from `x` behind `faces`, as the module
/// computes them (sorted by start).
fn shadowed(light: &QuadLight, x: V3, n: V3, faces: &[Face], chord: &Chord) -> Vec<(f64, f64)> {
    let pgs: Vec<Parallelogram> = faces.iter().map(|f| f.pg).collect();
    let mut sh = vec![Shadow::EMPTY; pgs.len()];
    let k = Shadow::project_all(light, x, &pgs, &mut sh).unwrap();
    let dl = DirectLight::new(light, x, n, &sh[..k]).unwrap();
    let mut iv = vec![(0.0, 0.0); dl.scratch_len()];
    let m = dl.shadowed(chord, &mut iv).unwrap();
    iv.truncate(m);
    iv
}

/// The union of sorted intervals (touching ones, within `10⁻¹²`, merged).
fn union(iv: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for &(lo, hi) in iv {
        match out.last_mut() {
            Some(last) if lo <= last.1 + 1e-12 => last.1 = last.1.max(hi),
            _ => out.push((lo, hi)),
        }
    }
    out
}

#[derive(Default, Debug)]
struct VisStats {
    lines: usize,
    samples: usize,
    probes: usize,
    near_end_mismatches: usize,
    intervals: usize,
    line_checks: usize,
    worst_line_err: f64,
    worst_line_err_parallel: f64,
}

/// Test 2's check of one line: `10⁵` jittered samples of `t` over the
/// chord, each cast as a segment `x → y(t)` against every face, must agree
/// with membership in the shadowed intervals except within `10⁻⁹` of an
/// interval end; probes at `10⁻⁸ … 10⁻²` on both sides of every interval
/// end must agree too. Then `DirectLight::line` must equal the closed form
/// summed over the visible pieces found by the rays alone (transitions
/// bisected to `10⁻¹³`), within `10⁻¹¹` of the unoccluded integral
/// (`4·10⁻⁹` beside an edge nearly parallel to the line).
fn check_line(
    light: &QuadLight,
    f: &Frame,
    r: &Receiver,
    chord: &Chord,
    rng: &mut Rng,
    st: &mut VisStats,
) {
    const N: usize = 100_000;
    let iv = shadowed(light, r.x, r.n, &r.faces, chord);
    let blocked = |t: f64| -> bool {
        r.faces
            .iter()
            .any(|fc| segment_blocked(r.x, f.on_line(chord, t), fc))
    };
    let inside = |t: f64| iv.iter().any(|&(lo, hi)| lo <= t && t <= hi);
    let near_end = |t: f64| {
        iv.iter()
            .any(|&(lo, hi)| (t - lo).abs() <= 1e-9 || (t - hi).abs() <= 1e-9)
    };
    let len = chord.t1 - chord.t0;
    let mut ts = Vec::with_capacity(N + 64);
    for k in 0..N {
        ts.push(chord.t0 + len * (k as f64 + rng.uniform()) / N as f64);
    }
    let mut vis = Vec::with_capacity(ts.len());
    for &t in &ts {
        let b = blocked(t);
        if b != inside(t) {
            assert!(
                near_end(t),
                "{}: x {:?}, t = {t} blocked by a ray: {b}, in the shadowed intervals {iv:?}",
                r.label,
                r.x
            );
            st.near_end_mismatches += 1;
        }
        vis.push(!b);
    }
    st.samples += N;
    for &(lo, hi) in &iv {
        for e in [lo, hi] {
            for k in 2..=8 {
                for side in [-1.0, 1.0] {
                    let t = e + side * 10f64.powi(-k);
                    if t > chord.t0 && t < chord.t1 && !near_end(t) {
                        assert_eq!(
                            blocked(t),
                            inside(t),
                            "{}: x {:?}, probe t = {t} ({e} {side:+}1e-{k}), intervals {iv:?}",
                            r.label,
                            r.x
                        );
                        st.probes += 1;
                    }
                }
            }
        }
    }
    // The visible pieces from the rays alone: transitions between the
    // samples (and the chord's ends), bisected.
    let mut pieces = Vec::new();
    let mut start = if vis[0] { Some(chord.t0) } else { None };
    for k in 1..ts.len() {
        if vis[k] != vis[k - 1] {
            let (mut a, mut b) = (ts[k - 1], ts[k]);
            while b - a > 1e-13 {
                let m = 0.5 * (a + b);
                if blocked(m) != vis[k - 1] {
                    a = m;
                } else {
                    b = m;
                }
            }
            let e = 0.5 * (a + b);
            match start.take() {
                Some(s) => pieces.push((s, e)),
                None => start = Some(e),
            }
        }
    }
    if let Some(s) = start {
        pieces.push((s, chord.t1));
    }
    let pgs: Vec<Parallelogram> = r.faces.iter().map(|f| f.pg).collect();
    let mut sh = vec![Shadow::EMPTY; pgs.len()];
    let k = Shadow::project_all(light, r.x, &pgs, &mut sh).unwrap();
    let dl = DirectLight::new(light, r.x, r.n, &sh[..k]).unwrap();
    let all = dl.line_unoccluded(chord);
    let mut scratch = vec![(0.0, 0.0); dl.scratch_len()];
    let seen = dl.line(chord, &mut scratch).unwrap();
    let by_rays: f64 = pieces
        .iter()
        .map(|&(a, b)| dl.line_interval(chord, a, b))
        .sum();
    if all > 0.0 {
        // 1e-11, but 4e-9 where an occluder edge's shadow runs within
        // θ = 3e-7 .. 1e-6 rad of the line: its crossing is ill-conditioned
        // (ε/θ ≈ 4e-10 in t), and the ends found by the rays and by the
        // module differ by up to 3e-10 there.
        let tol = if r.label.starts_with("edge") {
            4e-9
        } else {
            1e-11
        };
        let e = (seen - by_rays).abs() / all;
        if r.label.starts_with("edge") {
            st.worst_line_err_parallel = st.worst_line_err_parallel.max(e);
        } else {
            st.worst_line_err = st.worst_line_err.max(e);
        }
        assert!(
            e <= tol,
            "{}: line {seen:e} vs visible pieces by rays {by_rays:e} (unoccluded {all:e})",
            r.label
        );
        st.line_checks += 1;
    }
    st.lines += 1;
    st.intervals += iv.len();
}

/// A random chord of the light (uniform direction and offset).
fn random_chord(light: &QuadLight, rng: &mut Rng) -> Chord {
    loop {
        let phi = rng.range(0.0, std::f64::consts::PI);
        let (c, s) = (phi.cos(), phi.sin());
        let (o0, o1) = light.offset_range(c, s);
        if let Some(ch) = light.chord(c, s, rng.range(o0, o1)) {
            return ch;
        }
    }
}

/// Test 2. Shadowed intervals against shadow rays, in the Cornell box.
#[test]
fn visibility_matches_shadow_rays() {
    let (light, f) = cornell_light();
    let mut rng = Rng::new(2);
    let receivers = cornell_receivers(&mut rng);
    let mut st = VisStats::default();
    let (mut straddling, mut front_checks) = (0, 0);
    for r in &receivers {
        for _ in 0..2 {
            let chord = random_chord(&light, &mut rng);
            check_line(&light, &f, r, &chord, &mut rng, &mut st);
            // Only the front faces of each convex box (outward normal towards
            // x) block anything the box blocks: the same shadowed set.
            let front: Vec<Face> = r
                .faces
                .iter()
                .filter(|g| dot(sub(r.x, g.corner), g.outward) > 0.0)
                .copied()
                .collect();
            let a = union(&shadowed(&light, r.x, r.n, &r.faces, &chord));
            let b = union(&shadowed(&light, r.x, r.n, &front, &chord));
            assert_eq!(
                a.len(),
                b.len(),
                "{}: all faces {a:?}, front faces {b:?}",
                r.label
            );
            for (p, q) in a.iter().zip(&b) {
                assert!(
                    (p.0 - q.0).abs() <= 1e-9 && (p.1 - q.1).abs() <= 1e-9,
                    "{}: all faces {a:?}, front faces {b:?}",
                    r.label
                );
            }
            front_checks += 1;
        }
        // Box faces that cross the plane through x parallel to the light
        // (and so are clipped there) and still cast a shadow.
        let nl = light.normal();
        for g in r.faces.iter().filter(|g| g.body < 10) {
            let z: Vec<f64> = g.vertices().iter().map(|&p| dot(nl, sub(r.x, p))).collect();
            let (lo, hi) = z
                .iter()
                .fold((f64::MAX, f64::MIN), |m, &v| (m.0.min(v), m.1.max(v)));
            if lo < 0.0 && hi > 0.0 && Shadow::project(&light, r.x, &g.pg).is_some() {
                straddling += 1;
            }
        }
        if r.label == "tall box top" {
            // Nothing is above it: the short box is clipped away entirely
            // (below x's plane), the walls' shadows miss the light.
            let pgs: Vec<Parallelogram> = r
                .faces
                .iter()
                .filter(|g| g.body < 10)
                .map(|g| g.pg)
                .collect();
            let mut sh = vec![Shadow::EMPTY; pgs.len()];
            assert_eq!(Shadow::project_all(&light, r.x, &pgs, &mut sh).unwrap(), 0);
            for _ in 0..20 {
                let chord = random_chord(&light, &mut rng);
                assert!(shadowed(&light, r.x, r.n, &r.faces, &chord).is_empty());
            }
        }
    }
    // An occluder edge whose shadow on the light is within 1e-6 rad (and
    // 3e-7 rad) of the line: the face's edge P₁P₂ lies on the rays from x
    // through two light points Y₁, Y₂ on a line turned by θ from the chord,
    // crossing it at the chord's middle.
    let x = [0.05, 0.2, 0.3];
    let chord = light.chord(0.4f64.cos(), 0.4f64.sin(), 0.05).unwrap();
    for theta in [1e-6f64, -1e-6, 3e-7, -3e-7] {
        let tm = 0.5 * (chord.t0 + chord.t1);
        let pm = chord.at(tm);
        let d = [(0.4 + theta).cos(), (0.4 + theta).sin()];
        let y1 = f.point(pm[0] - 0.12 * d[0], pm[1] - 0.12 * d[1]);
        let y2 = f.point(pm[0] + 0.12 * d[0], pm[1] + 0.12 * d[1]);
        let p1 = add(x, scale(sub(y1, x), 0.5));
        let p2 = add(x, scale(sub(y2, x), 0.56));
        for w in [[0.05, -0.03, 0.08], [-0.05, 0.02, -0.08]] {
            let e1 = sub(p2, p1);
            let mut faces = cornell_boxes();
            faces.extend(cornell_room());
            faces.push(Face::new(p1, e1, w, unit(cross(e1, w)), 9));
            let r = Receiver {
                label: "edge 1e-6 rad from the line",
                x,
                n: [0.0, 1.0, 0.0],
                faces,
            };
            let iv = shadowed(&light, x, r.n, &r.faces, &chord);
            assert!(
                iv.iter()
                    .any(|&(lo, hi)| (lo - tm).abs() < 1e-6 || (hi - tm).abs() < 1e-6),
                "θ = {theta}: no shadow end at the crossing t = {tm}: {iv:?}"
            );
            check_line(&light, &f, &r, &chord, &mut rng, &mut st);
        }
    }
    eprintln!(
        "visibility: {} receivers, {} lines, {} samples and {} end probes agree with shadow \
         rays ({} intervals; {} samples within 1e-9 of an end disagreed); front faces give the \
         same set on {front_checks} lines; {straddling} box faces straddle the receiver's plane; \
         line() vs the rays' visible pieces on {} lines, worst {:.1e} of the unoccluded \
         ({:.1e} beside the nearly parallel edge)",
        receivers.len(),
        st.lines,
        st.samples,
        st.probes,
        st.intervals,
        st.near_end_mismatches,
        st.line_checks,
        st.worst_line_err,
        st.worst_line_err_parallel
    );
    assert!(st.lines >= 48 && st.intervals >= 20, "{st:?}");
    assert!(straddling >= 1);
}

/// Test 3. `point(a, b)` against `G` from the 3D points and `V` from
/// shadow rays (points within `10⁻⁹` of a shadow edge, where a ray's
/// verdict is not robust, are skipped and counted).
#[test]
fn point_matches_geometry_and_rays() {
    let (light, f) = cornell_light();
    let mut rng = Rng::new(3);
    let receivers = cornell_receivers(&mut rng);
    let (mut lit, mut dark, mut behind, mut skipped) = (0, 0, 0, 0);
    let (mut worst, mut worst_tol) = (0.0f64, 0.0f64);
    for r in &receivers {
        let pgs: Vec<Parallelogram> = r.faces.iter().map(|g| g.pg).collect();
        let mut sh = vec![Shadow::EMPTY; pgs.len()];
        let k = Shadow::project_all(&light, r.x, &pgs, &mut sh).unwrap();
        let dl = DirectLight::new(&light, r.x, r.n, &sh[..k]).unwrap();
        let n = unit(r.n);
        let h = dot(f.nl, sub(r.x, f.c));
        for _ in 0..1000 {
            let (a, b) = (rng.range(0.0, f.len[0]), rng.range(0.0, f.len[1]));
            let vis_at = |a: f64, b: f64| {
                let y = f.point(a, b);
                !r.faces.iter().any(|g| segment_blocked(r.x, y, g))
            };
            let v = vis_at(a, b);
            let robust = [(1e-9, 0.0), (-1e-9, 0.0), (0.0, 1e-9), (0.0, -1e-9)]
                .iter()
                .all(|&(da, db)| vis_at(a + da, b + db) == v);
            if !robust {
                skipped += 1;
                continue;
            }
            let y = f.point(a, b);
            let g = geometry_term(&f, r.x, n, y);
            let got = dl.point(a, b);
            if !v {
                assert_eq!(got, 0.0, "{}: ({a}, {b}) is hidden", r.label);
                dark += 1;
                continue;
            }
            if g == 0.0 {
                behind += 1;
            } else {
                lit += 1;
            }
            // n·(y − x) rounds by ε·(its terms' scale): the tolerance.
            let w = sub(y, r.x);
            let r2 = dot(w, w);
            let s_n = dot_scale(n, sub(f.c, r.x))
                + (dot(n, f.u) * a).abs()
                + (dot(n, f.v) * b).abs()
                + dot_scale(n, w);
            let tol = 16.0 * EPS * (g + h * s_n / (r2 * r2));
            assert!(
                (got - g).abs() <= tol,
                "{}: point({a}, {b}) = {got:e}, G = {g:e}",
                r.label
            );
            worst_tol = worst_tol.max((got - g).abs() / tol);
            if dot(n, w) >= 0.1 * r2.sqrt() {
                worst = worst.max((got - g).abs() / g);
            }
        }
    }
    eprintln!(
        "point: {lit} lit, {dark} hidden (0 exactly), {behind} behind the tangent plane, \
         {skipped} within 1e-9 of a shadow edge skipped; worst error {worst_tol:.3} of the \
         tolerance, {:.1} ulp relative where cos θ_x ≥ 0.1",
        worst / EPS
    );
    assert!(lit > 1000 && dark > 1000 && skipped < 20);
}

// ------------------------------------------------- 4. whole-light irradiance

/// `n` Gauss–Legendre nodes and weights on `[−1, 1]` (Newton on `P_n`).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-17 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// `∫ cos θ_x dω` over a polygon light (vertices in the light's order,
/// counter-clockwise about its emitting normal, so clockwise as seen from
/// the receiver): Lambert's formula `−½ Σ γᵢ n·(rᵢ × rᵢ₊₁)/|rᵢ × rᵢ₊₁|`, `γᵢ`
/// the angle between `rᵢ = yᵢ − x` and `rᵢ₊₁`. (The minus sign is that
/// orientation: counter-clockwise as seen from `x` would give `+`.) Equal to
/// `∫ G dA` since `cos θ_y dA/r² = dω`.
fn lambert(x: V3, n: V3, poly: &[V3]) -> f64 {
    let k = poly.len();
    let mut sum = 0.0;
    for i in 0..k {
        let (r0, r1) = (sub(poly[i], x), sub(poly[(i + 1) % k], x));
        let c = cross(r0, r1);
        let len = norm(c);
        if len == 0.0 {
            continue;
        }
        sum += len.atan2(dot(r0, r1)) * dot(n, c) / len;
    }
    -0.5 * sum
}

/// The part of a convex polygon where `n·(y − x) ≥ 0` (Sutherland–Hodgman).
fn clip_front(poly: &[V3], x: V3, n: V3) -> Vec<V3> {
    let mut out = Vec::new();
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (fa, fb) = (dot(n, sub(a, x)), dot(n, sub(b, x)));
        if fa >= 0.0 {
            out.push(a);
        }
        if (fa >= 0.0) != (fb >= 0.0) {
            out.push(add(a, scale(sub(b, a), fa / (fa - fb))));
        }
    }
    out
}

/// `∫ line_unoccluded do` over the offsets of direction `φ`: 20-point
/// Gauss–Legendre on 8 panels per piece, the pieces split where the
/// integrand kinks (the offsets of the light's corners, where a chord end
/// turns a corner, and where the clamp line meets the rectangle's edges)
/// and around the foot's offset (`±h`, `±3h`: the peak of width `h`).
fn offset_integral(
    light: &QuadLight,
    f: &Frame,
    dl: &DirectLight,
    x: V3,
    n: V3,
    phi: f64,
    gl: &[(f64, f64)],
) -> f64 {
    let (c, s) = (phi.cos(), phi.sin());
    let (o0, o1) = light.offset_range(c, s);
    let off = |a: f64, b: f64| -s * a + c * b;
    let [l0, l1] = f.len;
    let corners = [(0.0, 0.0), (l0, 0.0), (l0, l1), (0.0, l1)];
    let mut cuts = vec![o0, o1];
    for &(a, b) in &corners {
        cuts.push(off(a, b));
    }
    // The clamp line α a + β b + γ = 0 (n·(y − x) = 0) on the four edges.
    let (al, be, ga) = (dot(n, f.u), dot(n, f.v), dot(n, sub(f.c, x)));
    for i in 0..4 {
        let (p, q) = (corners[i], corners[(i + 1) % 4]);
        let (fp, fq) = (al * p.0 + be * p.1 + ga, al * q.0 + be * q.1 + ga);
        if (fp > 0.0) != (fq > 0.0) {
            let t = fp / (fp - fq);
            cuts.push(off(p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
        }
    }
    let w = sub(x, f.c);
    let (fa, fb, h) = (dot(w, f.u), dot(w, f.v), dot(w, f.nl));
    for k in [-3.0, -1.0, 0.0, 1.0, 3.0] {
        cuts.push(off(fa, fb) + k * h);
    }
    cuts.retain(|&o| o >= o0 && o <= o1);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let line = |o: f64| {
        light
            .chord(c, s, o)
            .map_or(0.0, |ch| dl.line_unoccluded(&ch))
    };
    let mut sum = 0.0;
    for piece in cuts.windows(2) {
        let m = 8;
        let hw = (piece[1] - piece[0]) / m as f64;
        for j in 0..m {
            let mid = piece[0] + (j as f64 + 0.5) * hw;
            for &(t, wt) in gl {
                sum += 0.5 * hw * wt * line(mid + 0.5 * hw * t);
            }
        }
    }
    sum
}

/// Test 4. The offsets' integral of `line_unoccluded` is the irradiance
/// form factor `∫ G dA` of the rectangle (clipped at the tangent plane),
/// by Lambert's formula, to `10⁻¹¹` relative, for receivers that see the
/// whole light and for receivers whose tangent plane cuts it.
#[test]
fn offsets_integrate_to_lamberts_formula() {
    let (light, f) = cornell_light();
    let gl = gauss_legendre(20);
    let centre = f.point(0.5 * f.len[0], 0.5 * f.len[1]);
    let rect = [
        f.point(0.0, 0.0),
        f.point(f.len[0], 0.0),
        f.point(f.len[0], f.len[1]),
        f.point(0.0, f.len[1]),
    ];
    let tilt = |x: V3, d: V3| unit(add(unit(sub(centre, x)), d));
    let cases: Vec<(&str, V3, V3)> = vec![
        ("floor under the light", [0.1, 0.0, 0.05], [0.0, 1.0, 0.0]),
        ("floor corner", [-0.9, 0.0, 0.9], [0.0, 1.0, 0.0]),
        ("wall", [-1.0, 1.5, 0.1], [1.0, 0.0, 0.0]),
        (
            "tilted",
            [0.3, 0.8, 0.4],
            tilt([0.3, 0.8, 0.4], [0.3, 0.0, -0.2]),
        ),
        ("near the plane", [0.6, 1.9, 0.0], unit([-1.0, 0.2, 0.1])),
        ("clamped, tilted", [0.0, 1.2, 0.0], unit([1.0, 0.3, 0.0])),
        (
            "clamped, grazing",
            [0.1, 1.5, -0.1],
            unit([0.2, 0.01, -1.0]),
        ),
        (
            "clamped, near the plane",
            [0.0, 1.85, 0.1],
            unit([-0.3, 0.5, 1.0]),
        ),
    ];
    let mut worst = 0.0f64;
    for (label, x, n) in cases {
        let n = unit(n);
        let front = rect.iter().filter(|&&y| dot(n, sub(y, x)) > 0.0).count();
        let clamped = label.starts_with("clamped");
        assert_eq!(front == 4, !clamped, "{label}: {front} corners in front");
        assert!(front > 0);
        let poly = clip_front(&rect, x, n);
        let exact = lambert(x, n, &poly);
        assert!(exact > 0.0, "{label}: {exact}");
        let dl = DirectLight::new(&light, x, n, &[]).unwrap();
        for phi in [0.0, std::f64::consts::FRAC_PI_2, 0.7, 2.3] {
            let got = offset_integral(&light, &f, &dl, x, n, phi, &gl);
            let e = (got - exact).abs() / exact;
            worst = worst.max(e);
            assert!(
                e <= 1e-11,
                "{label}, φ = {phi}: ∫ lines do = {got:e}, Lambert {exact:e} (rel {e:.2e})"
            );
        }
    }
    eprintln!("offsets vs Lambert: worst relative difference {worst:.2e}");
}

// ------------------------------------------------------------ 5. bad input

/// Test 5. Every constructor rejects NaN and ±∞ naming the parameter, and
/// the degenerate shapes and short buffers with their own errors.
#[test]
fn bad_input_is_rejected_with_the_parameter_name() {
    let (c, e1, e2) = LIGHT;
    let light = QuadLight::new(c, e1, e2).unwrap();
    let face = Parallelogram::new([-0.1, 1.0, -0.1], [0.2, 0.0, 0.0], [0.0, 0.0, 0.2]).unwrap();
    let x = [0.0, 0.0, 0.0];
    let n = [0.0, 1.0, 0.0];
    let nf = |name| Some(ParamError::NonFinite { name });
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for j in 0..3 {
            let with = |v: V3| {
                let mut v = v;
                v[j] = bad;
                v
            };
            assert_eq!(QuadLight::new(with(c), e1, e2).err(), nf("corner"));
            assert_eq!(QuadLight::new(c, with(e1), e2).err(), nf("edge1"));
            assert_eq!(QuadLight::new(c, e1, with(e2)).err(), nf("edge2"));
            assert_eq!(Parallelogram::new(with(c), e1, e2).err(), nf("corner"));
            assert_eq!(Parallelogram::new(c, with(e1), e2).err(), nf("edge1"));
            assert_eq!(Parallelogram::new(c, e1, with(e2)).err(), nf("edge2"));
            assert_eq!(
                DirectLight::new(&light, with(x), n, &[]).err(),
                Some(ParamError::NonFinite { name: "x" })
            );
            assert_eq!(
                DirectLight::new(&light, x, with(n), &[]).err(),
                Some(ParamError::NonFinite { name: "n" })
            );
            let mut out = [Shadow::EMPTY; 1];
            assert_eq!(
                Shadow::project_all(&light, with(x), &[face], &mut out).err(),
                nf("x")
            );
            let e = QuadLight::new(c, with(e1), e2).unwrap_err();
            assert!(e.to_string().contains("edge1"), "{e}");
        }
        // A direction or offset that is not finite gives no chord ...
        assert_eq!(light.chord(bad, 0.0, 0.1), None);
        assert_eq!(light.chord(1.0, bad, 0.1), None);
        assert_eq!(light.chord(1.0, 0.0, bad), None);
        assert_eq!(light.chord(0.6, 0.8, bad), None);
    }
    // Zero and non-orthogonal light edges.
    assert_eq!(
        QuadLight::new(c, [0.0; 3], e2),
        Err(ParamError::ZeroDirection)
    );
    assert_eq!(
        QuadLight::new(c, e1, [0.0; 3]),
        Err(ParamError::ZeroDirection)
    );
    assert!(matches!(
        QuadLight::new(c, [1.0, 0.0, 0.0], [1e-6, 0.0, 1.0]),
        Err(ParamError::OutOfRange { name: "edge2", .. })
    ));
    assert!(matches!(
        QuadLight::new(c, [1.0, 0.0, 0.0], [1.0, 0.0, 1.0]),
        Err(ParamError::OutOfRange { name: "edge2", .. })
    ));
    assert!(QuadLight::new(c, [1.0, 0.0, 0.0], [1e-10, 0.0, 1.0]).is_ok());
    // Zero and parallel parallelogram edges.
    assert_eq!(
        Parallelogram::new(c, [0.0; 3], e2),
        Err(ParamError::ZeroDirection)
    );
    assert_eq!(
        Parallelogram::new(c, e1, [0.0; 3]),
        Err(ParamError::ZeroDirection)
    );
    assert_eq!(
        Parallelogram::new(c, [1.0, 0.0, 0.0], [-2.0, 0.0, 0.0]),
        Err(ParamError::ZeroDirection)
    );
    assert_eq!(
        Parallelogram::new(c, [1.0, 0.0, 0.0], [1.0, 1e-13, 0.0]),
        Err(ParamError::ZeroDirection)
    );
    // A zero normal.
    assert_eq!(
        DirectLight::new(&light, x, [0.0; 3], &[]).err(),
        Some(ParamError::ZeroDirection)
    );
    // Short buffers.
    let mut out = [Shadow::EMPTY; 1];
    assert_eq!(
        Shadow::project_all(&light, x, &[face, face], &mut out),
        Err(ParamError::Length {
            name: "out",
            expected: 2,
            got: 1
        })
    );
    let mut sh = [Shadow::EMPTY; 2];
    let k = Shadow::project_all(&light, x, &[face, face], &mut sh).unwrap();
    assert_eq!(k, 2);
    let dl = DirectLight::new(&light, x, n, &sh).unwrap();
    assert_eq!(dl.scratch_len(), 2);
    let chord = light.chord(1.0, 0.0, 0.19).unwrap();
    let mut scratch = [(0.0, 0.0); 1];
    let short = Some(ParamError::Length {
        name: "scratch",
        expected: 2,
        got: 1,
    });
    assert_eq!(dl.shadowed(&chord, &mut scratch).err(), short);
    assert_eq!(dl.line(&chord, &mut scratch).err(), short);
    assert_eq!(
        dl.line(&chord, &mut []).err(),
        Some(ParamError::Length {
            name: "scratch",
            expected: 2,
            got: 0
        })
    );
}

/// `Shadow::misses` never drops a shadow that covers part of the light
/// (checked on a 48 × 48 grid of light points, against shadow rays through
/// each face), drops the room's walls' shadows, and keeps a panel's hung
/// under the light.
#[test]
fn shadows_that_miss_the_light_are_recognised() {
    let (light, _) = cornell_light();
    let [l1, l2] = light.lengths();
    let mut rng = Rng::new(41);
    let (mut dropped, mut kept, mut walls_kept) = (0, 0, 0);
    let panel = Face::new(
        [-0.5, 1.9, -0.5],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, -1.0, 0.0],
        99,
    );
    for r in cornell_receivers(&mut rng) {
        let mut faces = r.faces.clone();
        faces.push(panel);
        for f in &faces {
            let Some(s) = Shadow::project(&light, r.x, &f.pg) else {
                continue;
            };
            let blocks = (0..48 * 48).any(|k| {
                let (a, b) = (
                    l1 * (f64::from(k % 48) + 0.5) / 48.0,
                    l2 * (f64::from(k / 48) + 0.5) / 48.0,
                );
                let y = add(
                    light.corner(),
                    add(scale(light.axes()[0], a), scale(light.axes()[1], b)),
                );
                segment_blocked(r.x, y, f)
            });
            if s.misses(&light) {
                assert!(
                    !blocks,
                    "{}: a dropped shadow of body {} blocks",
                    r.label, f.body
                );
                dropped += 1;
            } else {
                kept += 1;
                walls_kept += usize::from(f.body >= 10 && f.body < 20);
            }
            if f.body == 99 && r.x[1] < 1.0 {
                assert!(!s.misses(&light), "{}: the panel's shadow", r.label);
            }
        }
    }
    assert_eq!(walls_kept, 0, "a wall's shadow was kept");
    assert!(dropped > 20 && kept > 20, "dropped {dropped}, kept {kept}");
}
