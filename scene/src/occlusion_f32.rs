//! `f32` SIMD batches of the ambient-occlusion visibility of
//! [`super::occlusion`]: the cosine-weighted visible measure of whole lines
//! (the AO line estimator's summand) and of wrapped segments, for many
//! azimuths `φ` at one shading point, with no transcendental function per
//! sphere and no sorting.
//!
//! ## Set-up (per shading point, in `f64`)
//!
//! [`AoPoint32::new`] takes the shading point `p`, its normal `n` and a
//! tangent `t` (the frame of [`super::HalfPlane::at_azimuth`]: `n` and `t`
//! normalised, `t`'s normal component removed, `u = n × t`), so that the
//! half-plane at azimuth `φ` is spanned by
//!
//! ```text
//! a(φ) = cos φ·t + sin φ·u,    b(φ) = n × a(φ) = cos φ·u − sin φ·t
//! ```
//!
//! (`b` is the half-plane's unit normal). For each sphere `(c, R)` it forms,
//! in `f64`, the offset `q = c − p` **relative to the shading point** and
//! everything that does not depend on `φ`, and rounds to `f32` only then:
//! `q·t`, `q·u`, `q·n`, `|q|² − R²` as `(|q| − R)(|q| + R)`, its square root
//! `T` (the distance to the tangent points, when `p` is outside), and the
//! class of `p` for that sphere (outside, on the sphere: `|q|² − R²` within
//! `10⁻¹²·R²`, inside), exactly as [`super::HalfPlane::occluded`] decides it.
//! For the ground sphere of the AO scene (centre `(0, −1000, 0)`, radius
//! 1000) and a point on it, `|q|² − R²` is a difference of two numbers near
//! `10⁶`: in `f32` it would be all rounding, here it is exact to `f64`
//! precision. The cross-section identity `D² − r² = |q|² − R²` (below) makes
//! this one number serve every `φ`.
//!
//! Spheres that cannot occlude any direction of the hemisphere are dropped
//! here: those whose nearest point is beyond `max_dist` (`|q| − R ≥
//! max_dist`) and those below the tangent plane (`q·n + R ≤ 10⁻¹²·R`: every
//! point of the open ball has `(x − p)·n < 10⁻¹²R`, so it occludes at most a
//! sliver of that height at the horizon, of cosine weight of order `10⁻¹²`). A
//! shading point on the ground sees the ground sphere dropped this way.
//!
//! ## Per azimuth (in `f32` lanes)
//!
//! With `(cos φ, sin φ)` from a Cody–Waite reduction by `π/2` and Taylor
//! polynomials (degree 9 and 10 on `|x| ≤ π/4`, truncation below `3·10⁻⁹`),
//! each sphere costs a handful of lane operations:
//!
//! ```text
//! q·a = cos φ·(q·t) + sin φ·(q·u),   h = |q·b| = |cos φ·(q·u) − sin φ·(q·t)|,
//! D² = (q·a)² + (q·n)²,   r² = (R − h)(R + h) if h < D, else D² − (|q|² − R²),
//! ```
//!
//! the disc's centre distance `D` and radius `r` in the half-plane's plane
//! (see [`super::occlusion`]). The two forms of `r²` are equal
//! (`|q|² = D² + h²`); each cancels only when `r ≪ R`, and the rounding of
//! `q·a`, `q·b` (absolute `δq ≈ ε₃₂|q|`) reaches `r²` as `2h·δq` in the first
//! and `2D·δq` in the second, so the smaller of `h`, `D` is used. The disc's
//! direction is the unit vector `(sin θ_c, cos θ_c) = (q·a, q·n)/D`, and its
//! nearest distance is `D − r = (|q|² − R²)/(D + r)` (no cancellation).
//!
//! ### The occluded arc, without angles
//!
//! Write a direction of the half-plane's plane as the unit vector
//! `v(θ) = (sin θ, cos θ)` in the basis `(a, n)`. Every occluded set of
//! [`super::HalfPlane::occluded`] is an arc `{v : v·c ≥ cos w}` with a unit
//! centre `c` and a half-width `w ∈ [0, π]`, and only `cos w` and `sin w` are
//! needed:
//!
//! * outside (`|q|² − R² > 0`): `c = (sin θ_c, cos θ_c)`, `cos β = T/D`,
//!   `sin β = r/D`. If `T ≤ max_dist` (decided in `f64`, as in the `f64`
//!   code) `w = β`; else `cos w = max(κ, cos β)` with
//!   `κ = (s² + D² − r²)/(2sD) = K/D`, `K = (s² + |q|² − R²)/(2s)` precomputed
//!   (`s = max_dist`), and when `κ` wins `sin w = √((1 − κ)(1 + κ))`. (The
//!   factored form `√((D + r − s)(s − D + r)(s + D − r)(s + D + r))/(2sD)`
//!   avoids the cancellation in `1 − κ`, but it needs `r`, which in `f32`
//!   is much less accurate than `D` when the plane grazes a large sphere; the
//!   tests measured it worse.) Nothing is occluded when `D − r ≥ s` (or
//!   `κ ≥ 1`, the same condition);
//! * on the sphere: `c` as above, `w = π/2` (`cos w = 0`, `sin w = 1`);
//! * inside: `c = −(sin θ_c, cos θ_c)`, `cos w = −κ`, `sin w` as above
//!   (the occluded directions are `|α| ≥ acos κ` around the
//!   disc's direction, i.e. `|α'| ≤ π − acos κ` around the opposite one); all
//!   directions when `s ≥ D + r`, none when `s ≤ r − D = −(|q|² − R²)/(D + r)`.
//!
//! ### From the arc to intervals of `sin θ`
//!
//! The front half circle `θ ∈ [−π/2, π/2]` is `cos θ ≥ 0`, and on it
//! `θ ↦ s = sin θ` is increasing with `|sin θ| cos θ dθ = |s| ds`: the cosine
//! weight of `[θa, θb]` is
//!
//! ```text
//! W(sa, sb) = ∫_{sa}^{sb} |s| ds = (sb·|sb| − sa·|sa|)/2,   sa = sin θa, sb = sin θb,
//! ```
//!
//! so nothing needs the angles themselves. The arc's ends `θ_c ± w` have
//! `s± = sin θ_c cos w ± cos θ_c sin w`. The arc meets the front half circle
//! according to which of the two points `P± = (±1, 0)` (`θ = ±π/2`), the
//! ends of the front half circle, it contains (`P+` iff `sin θ_c ≥ cos w`,
//! `P−` iff `−sin θ_c ≥ cos w`): arcs are connected, so
//!
//! * neither `P+` nor `P−`: the arc lies wholly in front, `[s−, s+]`, or
//!   wholly behind, where `θ ↦ sin θ` decreases, so `s− ≥ s+` and the
//!   interval `[s−, s+]` is empty by itself;
//! * `P+` only: it leaves the front half at `P+` and cannot come back
//!   without passing `P−`, so it starts in front: `[s−, 1]`; `P−` only:
//!   `[−1, s+]`;
//! * both: the complement, the open arc from `θ_c + w` to `θ_c − w + 2π`,
//!   avoids `P±`, so it lies wholly in front, where the occluded part is
//!   `[−1, s+] ∪ [s−, 1]` (`s+ < s−`), or wholly behind, where `s+ ≥ s−`
//!   and the same two intervals cover all of `[−1, 1]`: `[−1, s+] ∪ [s−, 1]`
//!   either way. (Containing `N = (0, 1)` as well does not make the front
//!   wholly occluded: the complement may lie between `P−` and `N`.)
//!
//! Outside the sphere `cos w > 0`, so the last case cannot occur and each
//! such sphere gives one interval; on the sphere (`cos w = 0`) it needs
//! `sin θ_c = 0`, where the two intervals are `[−1, −1]` and `[1, 1]` (or
//! all of `[−1, 1]` when `n` points into the sphere); only a sphere
//! containing `p` can give two proper intervals. Ends are clamped to `[−1, 1]`, and an
//! empty interval (`lo ≥ hi`, or a lane with no disc, `r² ≤ 0`) is stored as
//! `[1, 1]`. The decisions near `P±` change the result only by how far an
//! end lies from `±1`, which is second order in the angle there.
//!
//! ### The union, without sorting
//!
//! With the intervals `[lo_i, hi_i]` (`i` in a fixed order), a gap of the
//! union starts at `g = −1` or at some `g = hi_i`, and runs to
//! `e(g) = min({lo_j : lo_j ≥ g} ∪ {1})`. A candidate `g = hi_i` is counted
//! only if no other interval covers it: `lo_j < g < hi_j` for `j > i`, and
//! `lo_j < g ≤ hi_j` for `j < i` (so of several intervals ending at the
//! same `g` only the first starts a gap). Then every counted `[g, e(g)]` is
//! uncovered (an interval with `lo_j < e(g)` has `lo_j < g`, hence
//! `hi_j ≤ g`), two counted gaps are disjoint, and every maximal gap is
//! counted exactly once, so
//!
//! ```text
//! visible = Σ_{counted g} W(g, e(g)),
//! ```
//!
//! summed over the gaps directly (a mostly occluded line keeps its accuracy).
//! A covered candidate is handled by setting `e = g` (its term is then `0`
//! exactly); each pair `(i, j)` costs two comparisons, two selections and a
//! `min`, `O(M²)` for `M` intervals, which for the eight spheres of the AO
//! scene is cheaper than sorting lanes. A wrapped segment clips every gap to
//! its one or two `s`-ranges (below).
//!
//! ## Segments
//!
//! [`AoPoint32::segment_batch_f32`] takes the `θ`-segment `[θ0, θ0 + len]`
//! wrapped with period `π` ([`super::HalfPlane::visible_wrapped`]):
//! `a = θ0 − kπ ∈ [−π/2, π/2]` (`k = ⌊θ0/π + ½⌋`, Cody–Waite), `sa = sin a`,
//! `sb = sin(a + len) = sin a·cos len + cos a·sin len`; the `s`-ranges are
//! `[sa, sb]`, or `[sa, 1] ∪ [−1, −sb]` when `a + len > π/2`. `len ≥ π` is
//! the whole line.
//!
//! ## Error
//!
//! Against the `f64` path ([`super::HalfPlane::visible`] at `φ` widened to
//! `f64`), with `ε = ε₃₂ = 2⁻²³`, first order in `ε`. Per sphere that cuts
//! the half-plane in a disc, with `L = |q|`, `D`, `r`, `h`, `R` as above and
//! `s = max_dist`: every constant is the `f64` value rounded once (`ε/2`);
//! `cos φ`, `sin φ` are within `ε` (measured `0.76ε` for `|φ| ≤ 6000`, where
//! the reduction is exact); `q·a` then carries `ε(|q·t| + |q·u|)` from them
//! plus three roundings, and `D = √((q·a)² + (q·n)²)` adds `√2` of that and
//! its own roundings:
//!
//! ```text
//! δq = 3ε·L                               (q·a, q·b, q·n),
//! δD = 1.5·δq + 2ε·D,
//! δr² = 3·min(h, D)·δq + 2ε(R² + D²)      (the form of r² with the smaller factor),
//! δr = min(δr²/(2r), √δr²) + ε·r,
//! ```
//!
//! the `√δr²` being the square-root singularity of `r = √r²` where the plane
//! grazes the sphere (`r → 0`, `h → R`). An interval end
//! `s± = sin θ_c cos w ± cos θ_c sin w` is a sum of products of factors of
//! magnitude at most 1, so it is off by at most the sum of their errors plus
//! `2ε`: `δs = δ_c + δ_w + 2ε` with, for the centre
//! `(q·a, q·n)/D`, `δ_c = 2(δq + δD)/D + 4ε`, and for `(cos w, sin w)`
//!
//! ```text
//! δ_w = (δD + δr)/D + 4ε                                    w = β (T/D, r/D),
//! δ_w = 0                                                   on the sphere,
//! δ_w = δκ + min(δu/(2 sin w), √δu) + 2ε                  from κ = K/D,
//!       δκ = |κ|(δD/D + 3ε),  δu = 2|κ|·δκ + 2ε         (u = (1 − κ)(1 + κ)),
//! ```
//!
//! (both the first and the last where `max_dist` may cut: `cos w` is their
//! `max`). `sin w → 0` when `max_dist` just reaches the disc (`κ → 1`, and
//! inside at the two thresholds `κ → ±1`): again a square-root singularity,
//! where the arc shrinks to nothing or grows to all (the decisions made
//! there switch between arcs that agree to that error).
//! Moving an end by `δs` changes a weight `W` by at most `δs`
//! (`|dW/ds| = |s| ≤ 1`), and each of at most `M + 1` gap terms rounds by
//! `3ε`, so with `M` intervals
//!
//! ```text
//! |visible₃₂ − visible₆₄| ≤ Σ_spheres (2 or, inside, 4)·min(δs, 2) + 3ε(M + 2) + 10⁻¹¹
//! ```
//!
//! (`10⁻¹¹` for the spheres dropped under the tangent plane), plus `6ε` per
//! end of a segment's one or two `s`-ranges (the reduction of `θ0` is exact
//! to `ε` for `|θ0| ≤ 6000`, `sin a` within `2ε`, `sin(a + len)` within
//! `6ε`). So the error is a few `ε₃₂` times the conditioning of the ends:
//! `L/D` (the disc's direction), `min(h, D)·L/(rD)` where the half-plane
//! grazes a sphere (`r → 0`), `1/sin w` where `max_dist` grazes the disc
//! (`κ → 1`). Each blows up only to a square root: at worst an end is off
//! by about `√(ε·L·R)/D` or `√(ε·L/D)`, the width of the sliver that is in
//! doubt (a few `10⁻⁴` for unit spheres a few units away). Away from
//! grazing the error is `~10ε₃₂`; in the paper's AO scene a few `10⁻⁶`. `scene/tests/occlusion.rs` evaluates the bound for
//! every line and segment it checks (random scenes with all of these
//! grazing cases, and the paper's scene) and asserts it.
//!
//! Scale: `|q| + R ≤ 10¹⁸` and `R ≥ 10⁻¹⁸` (squares in `f32`).
//!
//! ```
//! use linesample_scene::occlusion_f32::AoPoint32;
//! use linesample::world::Sphere;
//! use linesample_scene::HalfPlane;
//! let spheres = [Sphere::new([0.0, 1.0, 2.0], 0.5)?, Sphere::new([1.0, 0.3, -1.0], 0.4)?];
//! let (p, n, t) = ([0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]);
//! let ao = AoPoint32::<4>::new(p, n, t, &spheres, 10.0)?;
//! let phis: [f32; 16] = core::array::from_fn(|k| 3.1415927 * (k as f32 + 0.5) / 16.0);
//! let mut out = [0.0f32; 16];
//! ao.line_batch_f32(&phis, &mut out)?;
//! let mut scratch = [(0.0, 0.0); 4];
//! for (&phi, &v) in phis.iter().zip(&out) {
//!     let hp = HalfPlane::at_azimuth(p, n, t, f64::from(phi))?;
//!     let want = hp.visible(&spheres, 10.0, -1.5707963267948966, 1.5707963267948966, &mut scratch)?;
//!     assert!((f64::from(v) - want).abs() < 1e-5);
//!     assert_eq!(v.to_bits(), ao.line_f32(phi).to_bits());
//! }
//! # Ok::<(), linesample::ParamError>(())
//! ```

use crate::HalfPlane;
use core::f64::consts::PI;
use linesample::geom::dot;
use linesample::num::lane::{load8, store8, F32Lane, LANES};
use linesample::world::check_finite;
use linesample::world::Sphere;
use linesample::ParamError;
use wide::f32x8;

/// `π/2` in three parts for the Cody–Waite reduction: `C1` has 8 significant
/// bits and `C2` 12, so `k·C1` and `k·C2` are exact for `|k| < 2¹²`
/// (`|x| ≲ 6400`); `C1 + C2 + C3` is `π/2` to `2·10⁻¹⁵`.
const C1: f32 = 1.570_312_5;
const C2: f32 = 4.838_705e-4;
const C3: f32 = -4.371_139e-8;
/// `2/π` rounded.
const TWO_OVER_PI: f32 = 0.636_619_75;
/// `1/π` rounded.
const ONE_OVER_PI: f32 = 0.318_309_87;

/// `(sin x, cos x)` in `f32` lanes: `k = ⌊x·2/π + ½⌋`,
/// `r = ((x − k·C1) − k·C2) − k·C3 ∈ [−π/4, π/4]` (about), the Taylor
/// polynomials `sin r ≈ r − r³/3! + … + r⁹/9!` and `cos r ≈ 1 − r²/2! + … −
/// r¹⁰/10!` (truncation below `3·10⁻⁹`), and the quadrant `k mod 4` selecting
/// and negating them. Absolute error about `1.5·ε₃₂` for `|x| ≤ 6000`
/// (tested against `libm`); no FMA, so every lane type gives the same bits.
#[inline(always)]
fn sincos32<L: F32Lane>(x: L) -> (L, L) {
    let one = L::splat(1.0);
    let k = (x * L::splat(TWO_OVER_PI) + L::splat(0.5)).floor();
    let r = ((x - k * L::splat(C1)) - k * L::splat(C2)) - k * L::splat(C3);
    let z = r * r;
    let mut ps = L::splat(1.0 / 362_880.0);
    ps = ps * z + L::splat(-1.0 / 5040.0);
    ps = ps * z + L::splat(1.0 / 120.0);
    ps = ps * z + L::splat(-1.0 / 6.0);
    let sr = r + (r * z) * ps;
    let mut pc = L::splat(-1.0 / 3_628_800.0);
    pc = pc * z + L::splat(1.0 / 40_320.0);
    pc = pc * z + L::splat(-1.0 / 720.0);
    pc = pc * z + L::splat(1.0 / 24.0);
    let cr = (one - L::splat(0.5) * z) + (z * z) * pc;
    // The quadrant k mod 4 ∈ {0, 1, 2, 3} (exact for |k| < 2²⁴).
    let quad = k - L::splat(4.0) * (k * L::splat(0.25)).floor();
    let odd = (k - L::splat(2.0) * (k * L::splat(0.5)).floor()).gt(L::splat(0.5));
    let s = L::select(odd, cr, sr);
    let c = L::select(odd, sr, cr);
    let s = L::select(quad.gt(L::splat(1.5)), -s, s);
    let cneg = L::and(quad.gt(L::splat(0.5)), quad.lt(L::splat(2.5)));
    (s, L::select(cneg, -c, c))
}

/// How the shading point lies relative to a sphere (the same for every `φ`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Kind {
    /// Outside, every tangent point within `max_dist`: `w = β`.
    #[default]
    Outside,
    /// Outside, the tangent points beyond `max_dist`: `cos w = max(κ, cos β)`.
    OutsideCut,
    /// On the sphere (`|q|² − R²` within `10⁻¹²R²`): `w = π/2`.
    OnSurface,
    /// Inside: the arc around the opposite direction, `cos w = −κ`.
    Inside,
}

/// One sphere, prepared in `f64` and rounded once (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Prep {
    kind: Kind,
    /// `q·t`, `q·u`, `q·n` for `q = c − p`.
    qt: f32,
    qu: f32,
    qn: f32,
    /// `R`.
    big_r: f32,
    /// `|q|² − R²` (`= D² − r²` for every `φ`).
    out2: f32,
    /// `T = √(|q|² − R²)` (outside), else 0.
    tan: f32,
    /// `s = min(max_dist, 2(|q| + R))`: beyond `|q| + R` the distance cuts
    /// nothing, and this keeps it finite.
    s: f32,
    /// `K = (s² + |q|² − R²)/(2s)`, so `κ = K/D`.
    k: f32,
}

impl Prep {
    /// The sphere's constants at `p` in the frame `(t, u, n)`, or `None` if
    /// it occludes nothing in the hemisphere (see the module docs).
    fn new(p: &[f64; 3], frame: &[[f64; 3]; 3], sphere: &Sphere<3>, max_dist: f64) -> Option<Self> {
        let c = sphere.centre();
        let big_r = sphere.radius();
        let q = [c[0] - p[0], c[1] - p[1], c[2] - p[2]];
        // As HalfPlane::occluded: |q|² − R² from |q| (no cancellation of squares).
        let ql = linesample::num::scalar::sqrt(dot(&q, &q));
        let out2 = (ql - big_r) * (ql + big_r);
        let qn = dot(&q, &frame[2]);
        if ql - big_r >= max_dist || qn + big_r <= 1e-12 * big_r {
            return None;
        }
        let on_surface = out2.abs() <= 1e-12 * big_r * big_r;
        let tan = if on_surface || out2 < 0.0 {
            0.0
        } else {
            linesample::num::scalar::sqrt(out2)
        };
        let kind = if on_surface {
            Kind::OnSurface
        } else if out2 > 0.0 {
            if tan <= max_dist {
                Kind::Outside
            } else {
                Kind::OutsideCut
            }
        } else {
            Kind::Inside
        };
        let s = max_dist.min(2.0 * (ql + big_r));
        Some(Self {
            kind,
            qt: dot(&q, &frame[0]) as f32,
            qu: dot(&q, &frame[1]) as f32,
            qn: qn as f32,
            big_r: big_r as f32,
            out2: out2 as f32,
            tan: tan as f32,
            s: s as f32,
            k: ((s * s + out2) / (2.0 * s)) as f32,
        })
    }
}

/// The interval `[lo, hi]` clamped to `[−1, 1]`, or `[1, 1]` if empty.
#[inline(always)]
fn normalise<L: F32Lane>(lo: L, hi: L) -> (L, L) {
    let one = L::splat(1.0);
    let lo = lo.max(-one);
    let hi = hi.min(one);
    let ok = lo.lt(hi);
    (L::select(ok, lo, one), L::select(ok, hi, one))
}

/// `cosine weight × 2` of `[a, b]` in `s = sin θ`: `b|b| − a|a|`.
#[inline(always)]
fn w2<L: F32Lane>(a: L, b: L) -> L {
    b * b.abs() - a * a.abs()
}

/// A shading point prepared for the `f32` AO batches: up to `N` spheres that
/// can occlude its hemisphere, each reduced to `f32` constants relative to
/// the point (see the [module docs](self) for the formulas, their derivation
/// and the error bound). `N` is a capacity; nothing is allocated.
#[derive(Clone, Copy, Debug)]
pub struct AoPoint32<const N: usize> {
    prep: [Prep; N],
    /// Spheres kept (the first `inside` contain the point).
    m: usize,
    inside: usize,
}

impl<const N: usize> AoPoint32<N> {
    /// Prepares the shading point `point` with normal `normal` and tangent
    /// `tangent` (the frame of [`HalfPlane::at_azimuth`]: normalised, the
    /// tangent's normal component removed; azimuth `φ` is the half-plane of
    /// `a(φ) = cos φ·t + sin φ·(n × t)`, as the crate's
    /// [conventions](crate#conventions) state) for `spheres` seen within
    /// `max_dist` (`+∞` allowed; NaN or `≤ 0` occludes nothing, as in
    /// [`HalfPlane::occluded`]). Everything that does not depend on `φ` is
    /// computed here in `f64` relative to `point`: `q = c − p`, `q·t`,
    /// `q·(n × t)`, `q·n`, `|q|² − R²`, `√(|q|² − R²)`, and which side of
    /// the sphere `p` is on.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`point`, `normal`, `tangent`);
    /// [`ParamError::ZeroDirection`] if `normal` is zero or `tangent` is
    /// parallel to it; [`ParamError::Length`] (`spheres`, `expected` = `N`)
    /// if more than `N` spheres can occlude (those whose nearest point is
    /// within `max_dist` and that reach above the tangent plane).
    pub fn new(
        point: impl Into<[f64; 3]>,
        normal: impl Into<[f64; 3]>,
        tangent: impl Into<[f64; 3]>,
        spheres: &[Sphere<3>],
        max_dist: f64,
    ) -> Result<Self, ParamError> {
        let (p, n, t) = (point.into(), normal.into(), tangent.into());
        check_finite("point", &p)?;
        check_finite("normal", &n)?;
        check_finite("tangent", &t)?;
        let base = HalfPlane::new(p, n, t)?;
        let (n, t) = (base.normal(), base.azimuth());
        let u = [
            n[1] * t[2] - n[2] * t[1],
            n[2] * t[0] - n[0] * t[2],
            n[0] * t[1] - n[1] * t[0],
        ];
        let frame = [t, u, n];
        let mut out = Self {
            prep: [Prep::default(); N],
            m: 0,
            inside: 0,
        };
        if max_dist.is_nan() || max_dist <= 0.0 {
            return Ok(out);
        }
        let kept = spheres
            .iter()
            .filter(|s| Prep::new(&p, &frame, s, max_dist).is_some())
            .count();
        if kept > N {
            return Err(ParamError::Length {
                name: "spheres",
                expected: N,
                got: kept,
            });
        }
        // The spheres containing p first (their second intervals are then
        // indexed like their first).
        for inside in [true, false] {
            for s in spheres {
                if let Some(pr) = Prep::new(&p, &frame, s, max_dist) {
                    if (pr.kind == Kind::Inside) == inside {
                        out.prep[out.m] = pr;
                        out.m += 1;
                        out.inside += usize::from(inside);
                    }
                }
            }
        }
        Ok(out)
    }

    /// The number of spheres kept (those that can occlude the hemisphere).
    #[must_use]
    pub fn occluders(&self) -> usize {
        self.m
    }

    /// Sphere `j`'s occluded intervals in `s = sin θ` at `(cos φ, sin φ)`:
    /// `[lo0, hi0]` and the second interval `[lo1, 1]` (empty `[1, 1]` if
    /// none; only a sphere containing the point can have one).
    #[inline(always)]
    fn sphere_lanes<L: F32Lane>(pr: &Prep, cs: L, sn: L) -> (L, L, L) {
        let zero = L::splat(0.0);
        let one = L::splat(1.0);
        let (qt, qu, qn) = (L::splat(pr.qt), L::splat(pr.qu), L::splat(pr.qn));
        let big_r = L::splat(pr.big_r);
        let out2 = L::splat(pr.out2);
        let s = L::splat(pr.s);
        let qa = cs * qt + sn * qu;
        let h = (cs * qu - sn * qt).abs();
        let d2 = qa * qa + qn * qn;
        let d = d2.sqrt();
        let r2 = L::select(h.lt(d), (big_r - h) * (big_r + h), d2 - out2);
        let r = r2.max(zero).sqrt();
        let inv_d = one / d;
        let sc = qa * inv_d;
        let cc = qn * inv_d;
        let dr = d + r;
        // D − r, signed, without cancellation.
        let e = out2 / dr;
        // sin(acos κ) = √((1 − κ)(1 + κ)): κ = K/D needs only D (not r).
        let sin_acos = |kap: L| ((one - kap) * (one + kap)).max(zero).sqrt();
        let has_disc = L::and(r2.gt(zero), d.gt(zero));
        match pr.kind {
            Kind::Outside | Kind::OutsideCut => {
                let cos_b = L::splat(pr.tan) * inv_d;
                let sin_b = r * inv_d;
                let (cw, sw) = if pr.kind == Kind::Outside {
                    (cos_b, sin_b)
                } else {
                    let kap = L::splat(pr.k) * inv_d;
                    let cut = kap.gt(cos_b);
                    (
                        L::select(cut, kap, cos_b),
                        L::select(cut, sin_acos(kap), sin_b),
                    )
                };
                // cos w > 0: one interval (the arc cannot hold both ±π/2).
                let scw = sc * cw;
                let ccsw = cc * sw;
                let lo = L::select(cw.le(-sc), -one, scw - ccsw);
                let hi = L::select(cw.le(sc), one, scw + ccsw);
                let (lo, hi) = normalise(lo, hi);
                let ok = L::and(has_disc, e.lt(s));
                (L::select(ok, lo, one), L::select(ok, hi, one), one)
            }
            Kind::OnSurface => {
                let (lo, hi, lo1) = arc_general(sc, cc, zero, one);
                let ok = L::and(has_disc, e.lt(s));
                (
                    L::select(ok, lo, one),
                    L::select(ok, hi, one),
                    L::select(ok, lo1, one),
                )
            }
            Kind::Inside => {
                let kap = L::splat(pr.k) * inv_d;
                let (lo, hi, lo1) = arc_general(-sc, -cc, -kap, sin_acos(kap));
                let all = dr.le(s);
                // Nothing when s ≤ r − D = −e.
                let ok = L::and(d.gt(zero), s.gt(-e));
                let pick = |x: L, if_all: L| L::select(all, if_all, L::select(ok, x, one));
                (pick(lo, -one), pick(hi, one), pick(lo1, one))
            }
        }
    }
}

/// The intervals of `[−1, 1]` (in `s = sin θ`) an arc `{v : v·c ≥ cos w}`
/// with centre `c = (sc, cc)` covers on the front half circle (module docs):
/// `[lo0, hi0]` and `[lo1, 1]`, empty ones as `[1, 1]`.
#[inline(always)]
fn arc_general<L: F32Lane>(sc: L, cc: L, cw: L, sw: L) -> (L, L, L) {
    let one = L::splat(1.0);
    let scw = sc * cw;
    let ccsw = cc * sw;
    let (sm, sp) = (scw - ccsw, scw + ccsw);
    let in_p = cw.le(sc);
    let in_m = cw.le(-sc);
    let lo = L::select(in_m, -one, sm);
    // Both ±π/2: [−1, s+] ∪ [s−, 1] (all of it when s− ≤ s+).
    let hi = L::select(in_p, L::select(in_m, sp, one), sp);
    let lo1 = L::select(in_p, L::select(in_m, sm, one), one);
    let (lo, hi) = normalise(lo, hi);
    (lo, hi, lo1.max(-one).min(one))
}

/// The per-call constants of a wrapped segment of length `len < π`.
#[derive(Clone, Copy, Debug)]
struct SegConsts {
    cos_len: f32,
    sin_len: f32,
    /// `π/2 − len`: the segment wraps when the reduced start is beyond it.
    wrap_at: f32,
}

impl SegConsts {
    fn new(len: f32) -> Self {
        let l = f64::from(len);
        Self {
            cos_len: libm::cos(l) as f32,
            sin_len: libm::sin(l) as f32,
            wrap_at: (core::f64::consts::FRAC_PI_2 - l) as f32,
        }
    }
}

/// Checks `len ∈ [0, π₃₂]` (`π₃₂ = f32::consts::PI`, which rounds above `π`).
fn check_len(len: f32) -> Result<(), ParamError> {
    if !len.is_finite() {
        return Err(ParamError::NonFinite { name: "len" });
    }
    if !(0.0..=core::f32::consts::PI).contains(&len) {
        return Err(ParamError::OutOfRange {
            name: "len",
            value: f64::from(len),
            min: 0.0,
            max: f64::from(core::f32::consts::PI),
        });
    }
    Ok(())
}

impl<const N: usize> AoPoint32<N> {
    /// `2 × Σ weigh(g, e(g))` over the gap starts `g` of the union of every
    /// sphere's occluded intervals at azimuth `phi` (module docs: candidates
    /// `−1` and every first interval's `hi`, ties to the lower index; second
    /// intervals end at `1`, whose gap is empty, so they only end gaps).
    #[inline(always)]
    fn gaps<L: F32Lane>(&self, phi: L, weigh: impl Fn(L, L) -> L) -> L {
        let one = L::splat(1.0);
        let (sn, cs) = sincos32(phi);
        let mut lo = [one; N];
        let mut hi = [one; N];
        let mut lo1 = [one; N];
        for j in 0..self.m {
            let (a, b, c) = Self::sphere_lanes(&self.prep[j], cs, sn);
            lo[j] = a;
            hi[j] = b;
            lo1[j] = c;
        }
        let (m, inside) = (self.m, self.inside);
        // The gap from −1 (nothing covers −1 strictly).
        let mut e = one;
        for j in 0..m {
            e = e.min(lo[j]);
        }
        for j in 0..inside {
            e = e.min(lo1[j]);
        }
        let mut acc = weigh(-one, e);
        for i in 0..m {
            let g = hi[i];
            // e(g) = min{lo_j ≥ g} ∪ {1}, or g itself (an empty gap) when an
            // interval covers g: lo_j < g ≤ hi_j before i, lo_j < g < hi_j
            // after it. e ≥ g throughout, so min(e, g) = g.
            let mut e = one;
            for j in 0..m {
                if j == i {
                    continue;
                }
                let covers = if j < i { g.le(hi[j]) } else { g.lt(hi[j]) };
                let cand = L::select(lo[j].lt(g), L::select(covers, g, one), lo[j]);
                e = e.min(cand);
            }
            for j in 0..inside {
                let cand = L::select(lo1[j].lt(g), L::select(g.lt(one), g, one), lo1[j]);
                e = e.min(cand);
            }
            acc = acc + weigh(g, e);
        }
        acc
    }

    /// The line kernel shared by [`AoPoint32::line_f32`] and the batch.
    #[inline(always)]
    fn line_lanes<L: F32Lane>(&self, phi: L) -> L {
        let acc = self.gaps(phi, w2::<L>);
        (L::splat(0.5) * acc).min(L::splat(1.0))
    }

    /// The wrapped-segment kernel shared by [`AoPoint32::segment_f32`] and
    /// the batch (`len < π`).
    #[inline(always)]
    fn segment_lanes<L: F32Lane>(&self, phi: L, theta0: L, k: &SegConsts) -> L {
        let one = L::splat(1.0);
        // a = θ0 − jπ ∈ [−π/2, π/2] (about), j = ⌊θ0/π + ½⌋, Cody–Waite with 2C.
        let j = (theta0 * L::splat(ONE_OVER_PI) + L::splat(0.5)).floor();
        let a =
            ((theta0 - j * L::splat(2.0 * C1)) - j * L::splat(2.0 * C2)) - j * L::splat(2.0 * C3);
        let (sa, ca) = sincos32(a);
        let sb = sa * L::splat(k.cos_len) + ca * L::splat(k.sin_len);
        let wrap = a.gt(L::splat(k.wrap_at));
        // [sa, sb], or [sa, 1] ∪ [−1, −sb] when a + len > π/2.
        let hi0 = L::select(wrap, one, sb);
        let hi1 = L::select(wrap, -sb, -one);
        let clip = |g: L, e: L, lo: L, hi: L| {
            let x = g.max(lo);
            w2(x, e.min(hi).max(x))
        };
        let acc = self.gaps(phi, |g, e| clip(g, e, sa, hi0) + clip(g, e, -one, hi1));
        L::splat(0.5) * acc
    }

    /// The AO line estimator's summand at azimuth `phi` (radians, any finite
    /// value: [conventions](crate#conventions)): the cosine-weighted visible
    /// measure of the whole half-plane,
    ///
    /// ```text
    /// ∫_{−π/2}^{π/2} V(φ, θ) |sin θ| cos θ dθ = Σ_gaps (e|e| − g|g|)/2 ∈ [0, 1]
    /// ```
    ///
    /// over the gaps `[g, e]` (in `s = sin θ`) of the occluded intervals
    /// (the scalar twin of [`AoPoint32::line_batch_f32`]; derivation and
    /// error bound against [`HalfPlane::visible`] in the [module
    /// docs](self)). NaN for a non-finite `phi`.
    #[must_use]
    pub fn line_f32(&self, phi: f32) -> f32 {
        if !phi.is_finite() {
            return f32::NAN;
        }
        self.line_lanes::<f32>(phi)
    }

    /// SIMD batch (8 lanes) of [`AoPoint32::line_f32`]:
    /// `out[k] = ∫_{−π/2}^{π/2} V(φ_k, θ)|sin θ| cos θ dθ` for `φ_k = phis[k]`,
    /// bit-identical to the scalar twin lane by lane (the remainder goes
    /// through the scalar instantiation of the same kernel); no allocation.
    ///
    /// # Errors
    /// [`ParamError::Length`] (`out`) if `out.len() ≠ phis.len()`;
    /// [`ParamError::NonFinite`] (`phis`) if any azimuth is NaN or infinite
    /// (checked before anything is written).
    pub fn line_batch_f32(&self, phis: &[f32], out: &mut [f32]) -> Result<(), ParamError> {
        let n = phis.len();
        if out.len() != n {
            return Err(ParamError::Length {
                name: "out",
                expected: n,
                got: out.len(),
            });
        }
        if !phis.iter().all(|x| x.is_finite()) {
            return Err(ParamError::NonFinite { name: "phis" });
        }
        let mut i = 0;
        while i + LANES <= n {
            let v = self.line_lanes::<f32x8>(load8(phis, i));
            store8(out, i, v);
            i += LANES;
        }
        for i in i..n {
            out[i] = self.line_lanes::<f32>(phis[i]);
        }
        Ok(())
    }

    /// The cosine-weighted visible measure of the wrapped segment
    /// `[θ0, θ0 + len]` of signed polar angles (period `π`, as
    /// [`HalfPlane::visible_wrapped`]; [conventions](crate#conventions)) in
    /// the half-plane at azimuth `phi`: the sum over the gaps `[g, e]` (in
    /// `s = sin θ`) of `(y|y| − x|x|)/2` with `[x, y]` the gap clipped to
    /// `[sin a, sin(a + len)]`, or to `[sin a, 1]` and `[−1, −sin(a + len)]`
    /// when `a + len > π/2` (`a` = `θ0` reduced to `[−π/2, π/2]`). The scalar
    /// twin of [`AoPoint32::segment_batch_f32`]; `len ≥ π` (as `f64`, so
    /// `len = π₃₂`) is the whole line, [`AoPoint32::line_f32`]. NaN for a
    /// non-finite `phi` or `theta0`, or `len` outside `[0, π₃₂]`.
    #[must_use]
    pub fn segment_f32(&self, phi: f32, theta0: f32, len: f32) -> f32 {
        if !phi.is_finite() || !theta0.is_finite() || check_len(len).is_err() {
            return f32::NAN;
        }
        if f64::from(len) >= PI {
            return self.line_lanes::<f32>(phi);
        }
        self.segment_lanes::<f32>(phi, theta0, &SegConsts::new(len))
    }

    /// SIMD batch (8 lanes) of [`AoPoint32::segment_f32`]: `out[k]` for the
    /// segment `[theta0s[k], theta0s[k] + len]` at azimuth `phis[k]`,
    /// bit-identical to the scalar twin lane by lane; no allocation.
    ///
    /// # Errors
    /// [`ParamError::Length`] (`theta0s`, `out`) if a length differs from
    /// `phis.len()`; [`ParamError::NonFinite`] (`phis`, `theta0s`, `len`);
    /// [`ParamError::OutOfRange`] (`len`) outside `[0, π₃₂]`. Checked before
    /// anything is written.
    pub fn segment_batch_f32(
        &self,
        phis: &[f32],
        theta0s: &[f32],
        len: f32,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        let n = phis.len();
        for (name, got) in [("theta0s", theta0s.len()), ("out", out.len())] {
            if got != n {
                return Err(ParamError::Length {
                    name,
                    expected: n,
                    got,
                });
            }
        }
        if !phis.iter().all(|x| x.is_finite()) {
            return Err(ParamError::NonFinite { name: "phis" });
        }
        if !theta0s.iter().all(|x| x.is_finite()) {
            return Err(ParamError::NonFinite { name: "theta0s" });
        }
        check_len(len)?;
        if f64::from(len) >= PI {
            return self.line_batch_f32(phis, out);
        }
        let k = SegConsts::new(len);
        let mut i = 0;
        while i + LANES <= n {
            let v = self.segment_lanes::<f32x8>(load8(phis, i), load8(theta0s, i), &k);
            store8(out, i, v);
            i += LANES;
        }
        for i in i..n {
            out[i] = self.segment_lanes::<f32>(phis[i], theta0s[i], &k);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lane sine and cosine against `libm` (in `f64`), and the SIMD
    /// instantiation against the scalar one bit for bit.
    #[test]
    fn sincos_is_accurate_and_lanes_agree() {
        let mut worst = 0.0f64;
        let mut x = -6000.0f32;
        let mut lanes = [0.0f32; 8];
        let mut fill = 0;
        while x <= 6000.0 {
            let (s, c) = sincos32::<f32>(x);
            let xd = f64::from(x);
            worst = worst
                .max((f64::from(s) - libm::sin(xd)).abs())
                .max((f64::from(c) - libm::cos(xd)).abs());
            lanes[fill] = x;
            fill += 1;
            if fill == 8 {
                let (vs, vc) = sincos32(<f32x8 as linesample::num::lane::Lane>::load(&lanes));
                let (vs, vc) = (vs.to_array(), vc.to_array());
                for l in 0..8 {
                    let (s, c) = sincos32::<f32>(lanes[l]);
                    assert_eq!(vs[l].to_bits(), s.to_bits(), "sin {}", lanes[l]);
                    assert_eq!(vc[l].to_bits(), c.to_bits(), "cos {}", lanes[l]);
                }
                fill = 0;
            }
            x += 0.012_345_67 + 1e-4 * x.abs().sqrt();
        }
        std::println!("sincos32 on [−6000, 6000]: worst absolute error {worst:e}");
        assert!(worst <= 1.5 * f64::from(f32::EPSILON), "{worst:e}");
        for x in [
            0.0f32,
            -0.0,
            1e-30,
            core::f32::consts::FRAC_PI_2,
            core::f32::consts::PI,
        ] {
            let (s, c) = sincos32::<f32>(x);
            assert!((f64::from(s) - libm::sin(f64::from(x))).abs() <= 1e-7);
            assert!((f64::from(c) - libm::cos(f64::from(x))).abs() <= 1e-7);
        }
    }
}
