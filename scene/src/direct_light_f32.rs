//! `f32` SIMD batch of the direct-light line estimator of
//! [`super::direct_light`]: `∫ G·V dt` along many lines across a
//! [`QuadLight`] for one diffuse receiver, 8 lines at a time, with the
//! exact visibility of its [`Shadow`]s, no sorting and no `libm` call per
//! line. [`DirectLight32::line_batch_scalar_f32`] and
//! [`DirectLight32::line_f32`] run the scalar instantiation of the same
//! kernel and agree with the SIMD batch bit for bit.
//!
//! ## Set-up (per receiver, in `f64`)
//!
//! [`DirectLight32::new`] takes what [`DirectLight::new`] takes: the light,
//! the receiver `x` with normal `n`, and the shadows of its occluders
//! ([`Shadow::project_all`] at the same `x`). Everything that does not
//! depend on the line is formed in `f64` **relative to the foot** `f` of `x`
//! (its orthogonal projection onto the light's plane, in light coordinates;
//! `h` the height of `x` above the plane) and only then rounded to `f32`:
//!
//! * the rectangle `[a₀, a₁] × [b₀, b₁] = [−f_a, |e₁| − f_a] × [−f_b, |e₂| − f_b]`;
//! * the cosine numerator `n·(y − x) = A₀ + λ·P` for the light point at
//!   `f + P`: `A₀ = n·(foot − x) = −h (n·n_L)` (a product, no cancellation)
//!   and `λ = (n·ê₁, n·ê₂)`;
//! * each shadow half-plane `α a + β b + γ ≥ 0` as `α P_a + β P_b + γ' ≥ 0`
//!   with `γ' = γ + α f_a + β f_b` (which is `−h (N·n_L)` for the cone plane's
//!   unit normal `N`: small exactly when the receiver is close to the light's
//!   plane, and then exact to `f64` precision, where forming it in `f32`
//!   from `γ` would be all rounding);
//! * `h` and `h²`.
//!
//! ## Per line (in `f32` lanes)
//!
//! A line with direction `d = (cos φ, sin φ)` and offset `o` (as
//! [`QuadLight::chord`] takes them: the line `p·d⊥ = o`, `d⊥ = (−sin φ,
//! cos φ)`) is, relative to the foot, `P(σ) = ρ d⊥ + σ d` with
//! `ρ = o + sin φ f_a − cos φ f_b`, so `σ` is the arc length from the point
//! of the line nearest the foot and `r² = |y − x|² = σ² + q²`, `q² = h² + ρ²`.
//! `ρ` is the one per-line quantity that cancels (a line through the foot:
//! there `q` is smallest and the integrand largest), so it is formed in
//! `f64` from the `f32` inputs and the `f64` foot, lane by lane, and rounded
//! once; everything after is `f32`. Every set on the line is cut out by
//! half-planes `N·P + γ ≥ 0`, i.e. `k σ + m ≥ 0` with `k = N·d`,
//! `m = ρ (N·d⊥) + γ`: `σ ≥ −m/k` for `k > 0`, `σ ≤ −m/k` for `k < 0`,
//! everything or nothing for `k = 0` (`m ≥ 0` or not, as the `f64` path
//! decides it):
//!
//! 1. the **chord**: the four half-planes of the rectangle
//!    (`σ cos φ ∈ [a₀ + ρ sin φ, a₁ + ρ sin φ]`,
//!    `σ sin φ ∈ [b₀ − ρ cos φ, b₁ − ρ cos φ]`), non-empty only when the
//!    ends are strictly ordered (as [`QuadLight::chord`]);
//! 2. the **tangent-plane clamp** `A + β σ ≥ 0` (`A = A₀ + ρ λ·d⊥`,
//!    `β = λ·d`, the half-plane `λ·P + A₀ ≥ 0`) intersected with the chord,
//!    giving `[c₀, c₁]` (`β = 0`: all of it if `A > 0`, else nothing);
//! 3. each **shadow**'s interval: its up to six half-planes, clipped to
//!    `[c₀, c₁]`; an empty one is stored as `[c₁, c₁]`.
//!
//! ### The union, without sorting
//!
//! As in [`super::occlusion_f32`]: a gap of the union of the shadowed
//! intervals `[lo_i, hi_i]` starts at `g = c₀` or at some `g = hi_i` and runs
//! to `e(g) = min({lo_j : lo_j ≥ g} ∪ {c₁})`. A candidate `g = hi_i` is
//! counted only if no other interval covers it: `lo_j < g < hi_j` for
//! `j > i`, and `lo_j < g ≤ hi_j` for `j < i` (so of several intervals
//! ending at the same `g` only the first starts a gap; an interval starting
//! exactly at `g` gives `e = g`). Then the counted gaps are disjoint, each
//! uncovered, and every maximal gap is counted once; a covered candidate
//! gets `e = g`, an exactly empty term. Each pair `(i, j)` costs two
//! comparisons, two selections and a `min`: `O(k²)` lane operations for `k`
//! shadows. Candidates no lane needs (all of them empty) and shadows no lane
//! meets are skipped; that changes no bit, since their terms are exactly
//! `+0` and an empty interval, stored at `c₁`, ends no other gap early (so
//! the SIMD batch, which skips only what all 8 lanes skip, and the scalar
//! twin agree). Per line: `k·(planes)` half-plane clips, `O(k²)` for the
//! union, and `2(k + 1)` evaluations of `E` (one `atan2`, two divisions
//! each) at most.
//!
//! ### The integral over a gap, from one antiderivative
//!
//! With `s = σ` and `s = q cot ε` (`ε = atan2(q, s) ∈ (0, π)`, the angle at
//! `x` between the line's direction and the direction to `P(s)`): `ds = −q
//! dε / sin²ε`, `s² + q² = q²/sin²ε`, `A + β s = (A sin ε + βq cos ε)/sin ε`,
//! so
//!
//! ```text
//! h (A + βs) ds / (s² + q²)² = −(h/q³) sin ε (A sin ε + βq cos ε) dε,
//! ∫ sin²ε dε = (ε − sin ε cos ε)/2,   ∫ sin ε cos ε dε = sin²ε/2,
//! ∫_{s_lo}^{s_hi} h (A + βs)/(s² + q²)² ds = F(ε_lo) − F(ε_hi),
//! F(ε) = (h/q³)[A (ε − sin ε cos ε)/2 + βq sin²ε/2] = U·[a·G(ε) + β sin²ε],
//! ```
//!
//! `U = h/(2q²)`, `a = A/q = cos θ_x` at the line's nearest point (so
//! `|a| ≤ 1`, `|β| ≤ 1`), `G(ε) = ε − sin ε cos ε`, `sin²ε = q²/r²`,
//! `sin ε cos ε = qs/r²`. `F` is smooth on the whole line, so a gap that
//! contains `s = 0` needs no split. To keep far ends accurate (`|s| ≫ q`,
//! where `ε → 0` or `π` and `G` is a difference of nearly equal numbers) it
//! is evaluated through the acute angle `η = atan2(q, |s|) ∈ (0, π/2]`:
//! `G(ε) = g(η)` for `s ≥ 0` and `π − g(η)` for `s < 0`, `g(η) = η −
//! sin η cos η = (x − sin x)/2` at `x = 2η`, from its Taylor series
//! `x³/3! − x⁵/5! + … + x¹⁵/15!` for `η < 1` (truncation below `x¹⁷/17! ≤
//! 3.5·10⁻¹⁰` relative to `g` on `x < 2`) and as `η − q|s|/r²` for `η ≥ 1`
//! (`g ≥ 0.545` there). With `E(s) = a·sgn(s)·g(η) + β q²/r²`
//! (`sgn(0) = +1`),
//!
//! ```text
//! ∫_gap G V = U · [E(g) − E(e) + aπ·[g < 0 ≤ e]],     ∫ G V dt = Σ_counted gaps,
//! ```
//!
//! clamped below at 0. Every term is `O(1)` (`|E| ≤ π/2 + 1`); all of the
//! scale is in `U`, computed once.
//!
//! ### `atan2` in lanes
//!
//! `η = atan2(y, x)` for `y > 0`, `x ≥ 0` (no `libm`, so both instantiations
//! run the same operations): `z = min/max ∈ [0, 1]`, and for `z > tan(π/8)`
//! the reduction `atan z = π/4 + atan((z − 1)/(z + 1))` (formed as
//! `(min − max)/(min + max)`: one division either way), so the argument `t`
//! has `|t| ≤ tan(π/8) = 0.4142`; then the Taylor polynomial `t − t³/3 + … +
//! t¹⁷/17` (alternating, so the truncation is below the first omitted term,
//! `|t|¹⁹/19`: relative `t¹⁸/19 ≤ 6.8·10⁻⁹ = 0.06 ε`), `π/4` and `π/2` in two
//! parts, and `π/2 − atan(x/y)` when `y > x`. Measured relative error
//! `1.17 ε` over ratios `10⁻³⁰ … 10³⁰` (module test, asserted `≤ 1.25 ε`;
//! `g` from an exact `η`: `1.57 ε`, asserted `≤ 2 ε`).
//!
//! ## Error bound
//!
//! Against the `f64` path: [`DirectLight::line`] of the chord of the line
//! the `f32` inputs define, `p·d⊥ = o`, normalised in `f64`
//! ([`QuadLight::chord`]`(c/|d|, s/|d|, o/|d|)`; the `f64` path takes its
//! direction as unit). To first order in `ε = ε₃₂ = 2⁻²³`, with every
//! quantity below exact (the test forms them in `f64`): `U`, `a`, `β`, `q`,
//! `ρ` of the line; `[c₀, c₁]` the clamped chord; `K` the shadows that meet
//! it; `s*` its point nearest `s = 0`, `η* = atan2(q, |s*|)`,
//! `W* = |a| g(η*) + |β| q²/r*²` and `Γ* = g(η*) + q²/r*²` (the largest
//! `|a| g + |β| sin²ε` and `g + sin²ε` on it); `J = (1/U)∫_chord G`
//! (unoccluded, clamped); `δ_d = |cos²φ + sin²φ − 1|` (about `ε` for a
//! rounded unit direction; the batch refuses more than `10⁻⁵`), which
//! scales every length the kernel forms by at most `1 + δ_d`.
//!
//! * **Line offset.** `ρ` is off by
//!   `δρ ≤ (ε/2 + δ_d)|ρ| + 2.3·10⁻¹⁶(|o| + |f_a| + |f_b| + 2|x − c|)` (the
//!   final rounding; the `f64` sum, and the `f64` rounding of the foot and
//!   of `γ'`). Everything after is a function of `ρ`, so this moves the whole
//!   line: `|∂_ρ(hL/r⁴)| ≤ 5h/r⁴` (`|L| = |n·(y − x)| ≤ r`, `|ρ| ≤ r`)
//!   integrates to `5πh/(2q³)`, so `≤ U·5π δρ/q`, plus the moves of the ends.
//! * **Ends.** Each end is a crossing `σ_b = −m/k` of a boundary line
//!   `N·P + γ = 0` (a rectangle edge, a shadow plane, the clamp), at angle
//!   `κ_b = |k|/|N|` to the line. `N` and `γ` are rounded once, `k` carries
//!   `≤ 2ε|N|`, `m` `≤ 3ε|N||ρ| + ε(|γ| + |m|)/2`, the division `ε/2`, and
//!   `|γ|/|N|` (the boundary's distance from the foot), `|ρ|` and `|σ_b|` are
//!   at most `r_b = √(σ_b² + q²)`: the computed crossing is off by
//!   `δs_b ≤ ((7ε + δ_d) r_b + δρ)/κ_b` (a rectangle edge `≤ 2.5ε r_b/κ_b`).
//!   Moving an end by `δs` changes `E` by at most `∫|E'|` over the moved
//!   part, `|E'| = 2q²|L|/r⁴ ≤ 2q²/r³`, whose integral from `x₁` to `x₂` is
//!   `T = 2[x₂/r(x₂) − x₁/r(x₁)]` (at most 4: a far or nearly parallel
//!   boundary costs little or is capped). At the clamp `|L| ≤ |β| δs`, a
//!   second factor `min(1, |β| δs_c/r_min)`. A boundary with `k = 0` whose
//!   `|m|` is within its rounding may decide either way: 4.
//! * **Evaluation.** Per evaluated end, `E` is off by at most
//!   `12 ε (|a| g(η) + |β| sin²ε)`: `q` carries `1.5ε`, `η` `≤ 1.2ε` (measured)
//!   plus `1.5ε` from `q`, which `g` multiplies by at most 3 (`2η sin²η/g ≤
//!   3`), the series or direct form `≤ 2.5ε`, `sin²ε = q²/r²` `≤ 4.5ε`,
//!   products and sum. Two ends per counted gap, `≤ K + 1` gaps; empty gaps
//!   are exactly 0. The errors of `a` (`≤ 5ε` absolute: `A` is a sum) and `β`
//!   (`≤ 2ε`) are common to all gaps, whose `G`- and `sin²`-differences add
//!   up to at most `2g(η*)` and `2 sin²ε*`: `≤ 10 ε Γ*`; the product `aπ`
//!   once, `ε π |a|`.
//! * **Sums.** Every gap term is a partial integral, so the `≤ K + 1` terms
//!   and running sums are at most `J`; with `U` (`2.5ε`) and the final
//!   product: `(K + 6) ε J`, and `3δ_d J` for the lengths' scale.
//!
//! Altogether
//!
//! ```text
//! |I₃₂ − I₆₄| ≤ U·{ ε[24(K + 1)W* + 10Γ* + π|a| + (K + 6)J] + 3δ_d J + 5π δρ/q + Σ_b T_b },
//! ```
//!
//! the sum over every boundary (four edges, the clamp, each shadow plane)
//! of `T` over the larger side of `[σ_b − δs_b, σ_b + δs_b]` intersected
//! with the chord widened by its ends' `δs` (a crossing outside it is
//! clipped away). Away from the boundaries this is about a hundred `ε`
//! times `U`, i.e. relative to the largest integrand on the line rather
//! than to the result: what an `f32` sum of `O(1)` terms can promise (a far chord,
//! where `ε`-angles are small, keeps more through the series form of `g`).
//! It grows where a line is ill-conditioned: nearly parallel to and near a
//! boundary (`1/κ`, capped at the whole line). Receivers close to the
//! light's plane stay accurate (`δρ/q` is `O(ε)` since `ρ` is formed in
//! `f64`). `scene/tests/direct_light_f32.rs` evaluates the bound for every
//! line it checks (receivers in a Cornell-box scene, receivers
//! `10⁻² … 10⁻⁶` above the light's plane behind a blocker, tangent planes
//! cutting the light, lines through light and shadow corners, duplicated
//! shadows, axis-aligned lines against an axis-aligned blocker) and
//! asserts it: the largest measured error is `0.085` of it (47 000 lines;
//! per set 0.03–0.085). Measured `|I₃₂ − I₆₄|` is at most `37 ε·U`, except
//! on lines through a corner crossing an edge at a shallow angle
//! (`500 ε·U`, where the bound is `14 000 ε·U`).
//!
//! Scale: lengths (`|x − c|`, the edges) at most `10¹⁸` and, for a receiver
//! in front of the light, `h ≥ 10⁻¹⁸` (squares stay normal `f32`s); `new`
//! refuses anything else.
//!
//! ```
//! use linesample_scene::direct_light::{DirectLight, Parallelogram, QuadLight, Shadow};
//! use linesample_scene::direct_light_f32::DirectLight32;
//! let light = QuadLight::new([-0.5, 2.0, -0.5], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])?;
//! let blocker = Parallelogram::new([-0.1, 1.0, -0.1], [0.2, 0.0, 0.0], [0.0, 0.0, 0.2])?;
//! let (x, n) = ([0.1, 0.0, 0.05], [0.0, 1.0, 0.0]);
//! let mut shadows = [Shadow::EMPTY; 1];
//! let k = Shadow::project_all(&light, x, &[blocker], &mut shadows)?;
//! let dl32 = DirectLight32::<4>::new(&light, x, n, &shadows[..k])?;
//! // 16 lines at φ = 0.3, offsets across the light.
//! let (c, s) = (0.3f64.cos() as f32, 0.3f64.sin() as f32);
//! let (lo, hi) = light.offset_range(f64::from(c), f64::from(s));
//! let offs: [f32; 16] = core::array::from_fn(|i| (lo + (hi - lo) * (i as f64 + 0.5) / 16.0) as f32);
//! let mut out = [0.0f32; 16];
//! dl32.line_batch_f32(&[c; 16], &[s; 16], &offs, &mut out)?;
//! let dl = DirectLight::new(&light, x, n, &shadows[..k])?;
//! let mut scratch = [(0.0, 0.0); 1];
//! for (&o, &v) in offs.iter().zip(&out) {
//!     let chord = light.chord(f64::from(c), f64::from(s), f64::from(o)).unwrap();
//!     let want = dl.line(&chord, &mut scratch)?;
//!     assert!((f64::from(v) - want).abs() <= 1e-5 * dl.line_unoccluded(&chord).max(1e-3));
//!     assert_eq!(v.to_bits(), dl32.line_f32(c, s, o).to_bits());
//! }
//! # Ok::<(), linesample::ParamError>(())
//! ```
//!
//! [`DirectLight`]: super::direct_light::DirectLight
//! [`DirectLight::new`]: super::direct_light::DirectLight::new
//! [`DirectLight::line`]: super::direct_light::DirectLight::line

use crate::direct_light::{QuadLight, Shadow, SHADOW_PLANES};
use crate::vec3::dot;
use linesample::num::lane::{load8, store8, F32Lane, LANES};
use linesample::num::scalar::sqrt;
use linesample::world::check_finite;
use linesample::ParamError;
use wide::f32x8;

/// `tan(π/8) = √2 − 1`, rounded: above it `atan` is reduced about `π/4`.
const TAN_PI_8: f32 = 0.414_213_57;
/// `π/4` in two parts (`hi + lo` to `10⁻¹⁵`).
const PI_4_HI: f32 = core::f32::consts::FRAC_PI_4;
const PI_4_LO: f32 = -2.185_569_5e-8;
/// `π/2` in two parts.
const PI_2_HI: f32 = core::f32::consts::FRAC_PI_2;
const PI_2_LO: f32 = -4.371_139e-8;
/// `π`, rounded.
const PI_32: f32 = core::f32::consts::PI;
/// Largest accepted `|cos²φ + sin²φ − 1|`.
const UNIT_TOL: f64 = 1e-5;
/// The scale limits of [`DirectLight32::new`].
const MIN_H: f64 = 1e-18;
const MAX_LEN: f64 = 1e18;

/// `atan2(y, x)` for `y > 0`, `x ≥ 0`, in `[0, π/2]` (module docs: reduction
/// to `|t| ≤ tan(π/8)` and the Taylor polynomial to `t¹⁷`, truncation
/// `< 0.06 ε` relative). No FMA, so every lane type gives the same bits.
#[inline(always)]
fn atan2_q1<L: F32Lane>(y: L, x: L) -> L {
    let swap = y.gt(x);
    let lo = y.min(x);
    let hi = y.max(x);
    let big = lo.gt(L::splat(TAN_PI_8) * hi);
    let t = L::select(big, lo - hi, lo) / L::select(big, lo + hi, hi);
    let w = t * t;
    let mut p = L::splat(1.0 / 17.0);
    p = p * w + L::splat(-1.0 / 15.0);
    p = p * w + L::splat(1.0 / 13.0);
    p = p * w + L::splat(-1.0 / 11.0);
    p = p * w + L::splat(1.0 / 9.0);
    p = p * w + L::splat(-1.0 / 7.0);
    p = p * w + L::splat(1.0 / 5.0);
    p = p * w + L::splat(-1.0 / 3.0);
    let at = t + (t * w) * p;
    let base = L::select(big, (at + L::splat(PI_4_LO)) + L::splat(PI_4_HI), at);
    L::select(swap, (L::splat(PI_2_HI) - base) + L::splat(PI_2_LO), base)
}

/// `g(η) = η − sin η cos η` for `η ∈ [0, π/2]`, given `sc = sin η cos η`:
/// the Taylor series of `(x − sin x)/2` at `x = 2η` (terms to `x¹⁵`) below
/// `η = 1`, `η − sc` above.
#[inline(always)]
fn g_eta<L: F32Lane>(eta: L, sc: L) -> L {
    let x = eta + eta;
    let z = x * x;
    let mut p = L::splat(1.0 / 1_307_674_368_000.0);
    p = p * z + L::splat(-1.0 / 6_227_020_800.0);
    p = p * z + L::splat(1.0 / 39_916_800.0);
    p = p * z + L::splat(-1.0 / 362_880.0);
    p = p * z + L::splat(1.0 / 5040.0);
    p = p * z + L::splat(-1.0 / 120.0);
    p = p * z + L::splat(1.0 / 6.0);
    let series = L::splat(0.5) * ((x * z) * p);
    L::select(eta.lt(L::splat(1.0)), series, eta - sc)
}

/// The per-line constants of the antiderivative.
#[derive(Clone, Copy)]
struct LineConsts<L> {
    q: L,
    q2: L,
    a: L,
    beta: L,
}

/// `E(s) = a·sgn(s)·g(η) + β q²/r²` (module docs; `sgn(±0) = +1`).
#[inline(always)]
fn antider<L: F32Lane>(s: L, k: &LineConsts<L>) -> L {
    let r2 = s * s + k.q2;
    let inv = L::splat(1.0) / r2;
    let abs_s = s.abs();
    let eta = atan2_q1(k.q, abs_s);
    let g = g_eta(eta, (k.q * abs_s) * inv);
    let sg = L::select(s.lt(L::splat(0.0)), -g, g);
    k.a * sg + k.beta * (k.q2 * inv)
}

/// `{σ : u0 ≤ σ·k ≤ u1}` as `(lo, hi)` (`±∞` for `k = 0`: everything or
/// nothing).
#[inline(always)]
fn slab<L: F32Lane>(k: L, u0: L, u1: L) -> (L, L) {
    let zero = L::splat(0.0);
    let inf = L::splat(f32::INFINITY);
    let (t0, t1) = (u0 / k, u1 / k);
    let (pos, neg) = (k.gt(zero), k.lt(zero));
    let inside = L::and(u0.le(zero), zero.le(u1));
    let lo = L::select(pos, t0, L::select(neg, t1, L::select(inside, -inf, inf)));
    let hi = L::select(pos, t1, L::select(neg, t0, L::select(inside, inf, -inf)));
    (lo, hi)
}

/// `ρ = o + s·f_a − c·f_b` in `f64` from the `f32` inputs, rounded once: the
/// one per-line quantity that cancels (a line through the foot), so it is
/// formed exactly to `f64` precision. Both lane types run these `f64`
/// operations lane by lane, so they agree bit for bit.
#[inline(always)]
fn rho64(o: f32, s: f32, c: f32, fa: f64, fb: f64) -> f32 {
    ((f64::from(o) + f64::from(s) * fa) - f64::from(c) * fb) as f32
}

/// `f32` lanes that form `ρ` through [`rho64`].
trait RhoLane: F32Lane {
    fn rho(o: Self, s: Self, c: Self, fa: f64, fb: f64) -> Self;
}

impl RhoLane for f32 {
    #[inline(always)]
    fn rho(o: f32, s: f32, c: f32, fa: f64, fb: f64) -> f32 {
        rho64(o, s, c, fa, fb)
    }
}

impl RhoLane for f32x8 {
    #[inline(always)]
    fn rho(o: f32x8, s: f32x8, c: f32x8, fa: f64, fb: f64) -> f32x8 {
        let (o, s, c) = (o.to_array(), s.to_array(), c.to_array());
        f32x8::from(core::array::from_fn::<f32, 8, _>(|l| {
            rho64(o[l], s[l], c[l], fa, fb)
        }))
    }
}

/// One shadow's half-planes relative to the foot, rounded once.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Shadow32 {
    /// `(α, β, γ')`: `α P_a + β P_b + γ' ≥ 0`.
    planes: [[f32; 3]; SHADOW_PLANES],
    count: usize,
}

impl Shadow32 {
    const EMPTY: Shadow32 = Shadow32 {
        planes: [[0.0; 3]; SHADOW_PLANES],
        count: 0,
    };
}

/// A receiver prepared for the `f32` line batches: its foot, height,
/// cosine numerator and up to `N` shadows, reduced to `f32` constants
/// relative to the foot (see the [module docs](self) for the formulas, their
/// derivation and the error bound). `N` is a capacity; nothing is allocated.
#[derive(Clone, Copy, Debug)]
pub struct DirectLight32<const N: usize> {
    /// Whether the receiver is in front of the light (`h > 0`).
    active: bool,
    h: f32,
    h2: f32,
    /// The foot `(f_a, f_b)` (kept in `f64` for `ρ`).
    foot: [f64; 2],
    /// `[a₀, a₁, b₀, b₁]`: the rectangle relative to the foot.
    rect: [f32; 4],
    /// `A₀ = −h (n·n_L)`.
    a0: f32,
    /// `λ = (n·ê₁, n·ê₂)`.
    lam: [f32; 2],
    shadows: [Shadow32; N],
    m: usize,
}

impl<const N: usize> DirectLight32<N> {
    /// Prepares the receiver at `x` with normal `n` (normalised here) behind
    /// `shadows` (from [`Shadow::project_all`] at the same `x`) for lines
    /// across `light`: the same inputs as
    /// [`DirectLight::new`](super::direct_light::DirectLight::new), reduced
    /// in `f64` relative to the receiver's foot on the light's plane and
    /// rounded to `f32` once. A receiver not in front of the light (`h ≤ 0`)
    /// gets 0 on every line.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`x`, `n`); [`ParamError::ZeroDirection`]
    /// for a zero normal; [`ParamError::Length`] (`shadows`, `expected` =
    /// `N`) for more than `N` shadows; [`ParamError::OutOfRange`] (`x`) when
    /// a receiver in front of the light is closer than `10⁻¹⁸` to its plane
    /// (`value` = `h`), or a length (`|x − c|`, an edge) exceeds `10¹⁸`
    /// (`value` = that length): outside the `f32` kernel's range.
    pub fn new(
        light: &QuadLight,
        x: impl Into<[f64; 3]>,
        n: impl Into<[f64; 3]>,
        shadows: &[Shadow],
    ) -> Result<Self, ParamError> {
        let (x, n) = (x.into(), n.into());
        check_finite("x", &x)?;
        check_finite("n", &n)?;
        let ln = sqrt(dot(n, n));
        if !(ln > 0.0 && ln.is_finite()) {
            return Err(ParamError::ZeroDirection);
        }
        if shadows.len() > N {
            return Err(ParamError::Length {
                name: "shadows",
                expected: N,
                got: shadows.len(),
            });
        }
        let n = [n[0] / ln, n[1] / ln, n[2] / ln];
        let (foot, h) = light.foot(x);
        let c = light.corner();
        let w = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
        let [l1, l2] = light.lengths();
        let len = sqrt(dot(w, w)).max(l1).max(l2);
        if len > MAX_LEN {
            return Err(ParamError::OutOfRange {
                name: "x",
                value: len,
                min: 0.0,
                max: MAX_LEN,
            });
        }
        let mut out = Self {
            active: false,
            h: 0.0,
            h2: 0.0,
            foot: [0.0; 2],
            rect: [0.0; 4],
            a0: 0.0,
            lam: [0.0; 2],
            shadows: [Shadow32::EMPTY; N],
            m: 0,
        };
        // `h` is finite here (the length check above).
        if h <= 0.0 {
            return Ok(out);
        }
        if h < MIN_H {
            return Err(ParamError::OutOfRange {
                name: "x",
                value: h,
                min: MIN_H,
                max: MAX_LEN,
            });
        }
        let [u, v] = light.axes();
        out.active = true;
        out.h = h as f32;
        out.h2 = (h * h) as f32;
        out.foot = foot;
        out.rect = [
            (-foot[0]) as f32,
            (l1 - foot[0]) as f32,
            (-foot[1]) as f32,
            (l2 - foot[1]) as f32,
        ];
        out.a0 = (-h * dot(n, light.normal())) as f32;
        out.lam = [dot(n, u) as f32, dot(n, v) as f32];
        for (j, s) in shadows.iter().enumerate() {
            let p = s.planes();
            let mut sh = Shadow32::EMPTY;
            for (i, &[al, be, ga]) in p.iter().enumerate().take(SHADOW_PLANES) {
                sh.planes[i] = [
                    al as f32,
                    be as f32,
                    (ga + al * foot[0] + be * foot[1]) as f32,
                ];
            }
            sh.count = p.len().min(SHADOW_PLANES);
            out.shadows[j] = sh;
        }
        out.m = shadows.len();
        Ok(out)
    }

    /// The number of shadows.
    #[must_use]
    pub fn shadow_count(&self) -> usize {
        self.m
    }

    /// Whether the receiver is in front of the light (`h > 0`; otherwise
    /// every line gives 0).
    #[must_use]
    pub fn is_lit(&self) -> bool {
        self.active
    }

    /// The kernel shared by the batch and its scalar twin (module docs).
    #[inline(always)]
    fn line_lanes<L: RhoLane>(&self, c: L, s: L, o: L) -> L {
        let zero = L::splat(0.0);
        let [fa, fb] = self.foot;
        let rho = L::rho(o, s, c, fa, fb);
        // The chord, relative to the foot.
        let [a0, a1, b0, b1] = self.rect;
        let rs = rho * s;
        let rc = rho * c;
        let (lo_a, hi_a) = slab(c, L::splat(a0) + rs, L::splat(a1) + rs);
        let (lo_b, hi_b) = slab(s, L::splat(b0) - rc, L::splat(b1) - rc);
        let s0 = lo_a.max(lo_b);
        let s1 = hi_a.min(hi_b);
        let chord = s0.lt(s1);
        let s0 = L::select(chord, s0, zero);
        let s1 = L::select(chord, s1, zero);
        // The clamp A + βσ ≥ 0.
        let [la, lb] = self.lam;
        let (la, lb) = (L::splat(la), L::splat(lb));
        let beta = la * c + lb * s;
        let big_a = L::splat(self.a0) + rho * (lb * c - la * s);
        let sc = -big_a / beta;
        let c0 = L::select(beta.gt(zero), s0.max(sc), s0);
        let c1 = L::select(beta.lt(zero), s1.min(sc), s1);
        let flat_dark = L::and(L::and(beta.le(zero), zero.le(beta)), big_a.le(zero));
        let c1 = L::select(flat_dark, c0, c1).max(c0);
        if !L::any(c0.lt(c1)) {
            return zero;
        }
        let q2 = L::splat(self.h2) + rho * rho;
        let q = q2.sqrt();
        let k = LineConsts {
            q,
            q2,
            a: big_a / q,
            beta,
        };
        // The shadows' intervals on [c0, c1] ([c1, c1] when empty).
        let mut los = [c1; N];
        let mut his = [c1; N];
        let mut live = [false; N];
        let neg_inf = L::splat(f32::NEG_INFINITY);
        for j in 0..self.m {
            let sh = &self.shadows[j];
            let (mut lo, mut hi) = (c0, c1);
            for &[al, be, ga] in &sh.planes[..sh.count] {
                let (al, be) = (L::splat(al), L::splat(be));
                let kk = al * c + be * s;
                let mm = rho * (be * c - al * s) + L::splat(ga);
                let t = -mm / kk;
                let (pos, neg) = (kk.gt(zero), kk.lt(zero));
                lo = L::select(pos, lo.max(t), lo);
                hi = L::select(
                    neg,
                    hi.min(t),
                    L::select(pos, hi, L::select(mm.lt(zero), neg_inf, hi)),
                );
            }
            let ok = lo.lt(hi);
            live[j] = L::any(ok);
            los[j] = L::select(ok, lo, c1);
            his[j] = L::select(ok, hi, c1);
        }
        let pi_a = L::splat(PI_32) * k.a;
        let gap = |g: L, e: L| {
            let straddle = L::select(L::and(g.lt(zero), zero.le(e)), pi_a, zero);
            (antider(g, &k) - antider(e, &k)) + straddle
        };
        // The gap from c0 (nothing covers c0 strictly: every lo ≥ c0).
        let mut e0 = c1;
        for j in 0..self.m {
            if live[j] {
                e0 = e0.min(los[j]);
            }
        }
        let mut acc = zero;
        if L::any(c0.lt(e0)) {
            acc = gap(c0, e0);
        }
        for i in 0..self.m {
            if !live[i] {
                continue;
            }
            let g = his[i];
            // e(g) = min{lo_j ≥ g} ∪ {c1}, or g itself when an interval
            // covers g: lo_j < g ≤ hi_j before i, lo_j < g < hi_j after it.
            let mut e = c1;
            for j in 0..self.m {
                if j == i || !live[j] {
                    continue;
                }
                let covers = if j < i { g.le(his[j]) } else { g.lt(his[j]) };
                let cand = L::select(los[j].lt(g), L::select(covers, g, c1), los[j]);
                e = e.min(cand);
            }
            if L::any(g.lt(e)) {
                acc = acc + gap(g, e);
            }
        }
        let u = L::splat(0.5) * (L::splat(self.h) / q2);
        (u * acc).max(zero)
    }

    /// `∫ G·V dt` along the line with direction `(cos_phi, sin_phi)` and
    /// offset `offset` (light coordinates, as [`QuadLight::chord`] takes
    /// them): 0 for a line that misses the light. The scalar twin of
    /// [`DirectLight32::line_batch_f32`] (the same kernel instantiated for
    /// `f32`, bit-identical lane by lane); error bound against the `f64`
    /// path in the [module docs](self). The direction is used as given (the
    /// `f32` case of the crate's [conventions](crate#conventions)): NaN for
    /// non-finite inputs or a direction with `|cos² + sin² − 1| > 10⁻⁵`.
    #[must_use]
    pub fn line_f32(&self, cos_phi: f32, sin_phi: f32, offset: f32) -> f32 {
        if check_line(cos_phi, sin_phi, offset).is_err() {
            return f32::NAN;
        }
        if !self.active {
            return 0.0;
        }
        self.line_lanes::<f32>(cos_phi, sin_phi, offset)
    }

    /// SIMD batch (8 lanes): `out[k] = ∫ G·V dt` along the line
    /// `(cos_phi[k], sin_phi[k])`, `offsets[k]` (structure of arrays; light
    /// coordinates as [`QuadLight::chord`] takes them), 0 for lines that miss
    /// the light; bit-identical to [`DirectLight32::line_f32`] lane by lane
    /// (the remainder goes through the scalar instantiation); no allocation.
    ///
    /// # Errors
    /// [`ParamError::Length`] (`sin_phi`, `offsets`, `out`) if a length
    /// differs from `cos_phi.len()`; [`ParamError::NonFinite`] (`cos_phi`,
    /// `sin_phi`, `offsets`); [`ParamError::OutOfRange`] (`sin_phi`, value
    /// `cos² + sin²`) for a direction that is not unit within `10⁻⁵`.
    /// Checked before anything is written.
    pub fn line_batch_f32(
        &self,
        cos_phi: &[f32],
        sin_phi: &[f32],
        offsets: &[f32],
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        check_batch(cos_phi, sin_phi, offsets, out)?;
        if !self.active {
            out.fill(0.0);
            return Ok(());
        }
        let n = cos_phi.len();
        let mut i = 0;
        while i + LANES <= n {
            let v =
                self.line_lanes::<f32x8>(load8(cos_phi, i), load8(sin_phi, i), load8(offsets, i));
            store8(out, i, v);
            i += LANES;
        }
        for i in i..n {
            out[i] = self.line_lanes::<f32>(cos_phi[i], sin_phi[i], offsets[i]);
        }
        Ok(())
    }

    /// [`DirectLight32::line_batch_f32`] through the scalar instantiation of
    /// the kernel only (the reference the SIMD batch is tested against bit
    /// for bit, and the path for targets without SIMD); same signature,
    /// same results, same errors.
    ///
    /// # Errors
    /// As [`DirectLight32::line_batch_f32`].
    pub fn line_batch_scalar_f32(
        &self,
        cos_phi: &[f32],
        sin_phi: &[f32],
        offsets: &[f32],
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        check_batch(cos_phi, sin_phi, offsets, out)?;
        if !self.active {
            out.fill(0.0);
            return Ok(());
        }
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.line_lanes::<f32>(cos_phi[i], sin_phi[i], offsets[i]);
        }
        Ok(())
    }
}

/// Checks one line's inputs: finite, and a unit direction within `10⁻⁵`.
fn check_line(c: f32, s: f32, o: f32) -> Result<(), ParamError> {
    for (name, v) in [("cos_phi", c), ("sin_phi", s), ("offsets", o)] {
        if !v.is_finite() {
            return Err(ParamError::NonFinite { name });
        }
    }
    let (c, s) = (f64::from(c), f64::from(s));
    let n2 = c * c + s * s;
    if (n2 - 1.0).abs() > UNIT_TOL {
        return Err(ParamError::OutOfRange {
            name: "sin_phi",
            value: n2,
            min: 1.0 - UNIT_TOL,
            max: 1.0 + UNIT_TOL,
        });
    }
    Ok(())
}

/// Checks the batch's slice lengths, then every line.
fn check_batch(c: &[f32], s: &[f32], o: &[f32], out: &[f32]) -> Result<(), ParamError> {
    let n = c.len();
    for (name, got) in [
        ("sin_phi", s.len()),
        ("offsets", o.len()),
        ("out", out.len()),
    ] {
        if got != n {
            return Err(ParamError::Length {
                name,
                expected: n,
                got,
            });
        }
    }
    for i in 0..n {
        check_line(c[i], s[i], o[i])?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use linesample::num::lane::Lane;

    /// The lane `atan2` against `libm` (in `f64`) over ratios from `10⁻³⁰`
    /// to `10³⁰`, and the SIMD instantiation against the scalar one bit for
    /// bit.
    #[test]
    fn atan2_is_accurate_and_lanes_agree() {
        let mut worst = 0.0f64;
        let mut ys = [0.0f32; 8];
        let mut xs = [0.0f32; 8];
        let mut fill = 0;
        let mut lg = -30.0f64;
        while lg <= 30.0 {
            let x = 10f64.powf(lg) as f32;
            for y in [1.0f32, 0.37, 3.3e-3] {
                let got = atan2_q1::<f32>(y, x);
                let want = libm::atan2(f64::from(y), f64::from(x));
                worst = worst.max((f64::from(got) - want).abs() / want);
                ys[fill] = y;
                xs[fill] = x;
                fill += 1;
                if fill == 8 {
                    let v = atan2_q1(<f32x8 as Lane>::load(&ys), <f32x8 as Lane>::load(&xs));
                    let v = v.to_array();
                    for l in 0..8 {
                        let s = atan2_q1::<f32>(ys[l], xs[l]);
                        assert_eq!(v[l].to_bits(), s.to_bits(), "{} {}", ys[l], xs[l]);
                    }
                    fill = 0;
                }
            }
            lg += 0.000_731;
        }
        // x = 0 and y = x exactly.
        assert_eq!(atan2_q1::<f32>(1.0, 0.0), core::f32::consts::FRAC_PI_2);
        let d = f64::from(atan2_q1::<f32>(0.5, 0.5)) - core::f64::consts::FRAC_PI_4;
        assert!(d.abs() <= f64::from(f32::EPSILON));
        std::println!(
            "atan2_q1: worst relative error {:.3} ε",
            worst / f64::from(f32::EPSILON)
        );
        assert!(worst <= 1.25 * f64::from(f32::EPSILON), "{worst:e}");
    }

    /// `g(η) = η − sin η cos η` against `f64` over `(0, π/2]`, both forms
    /// and across the switch at `η = 1`.
    #[test]
    fn g_is_accurate() {
        let mut worst = 0.0f64;
        let mut e = 1e-12f64;
        while e <= core::f64::consts::FRAC_PI_2 {
            let eta = e as f32;
            let ed = f64::from(eta);
            let sc = (libm::sin(ed) * libm::cos(ed)) as f32;
            let got = f64::from(g_eta::<f32>(eta, sc));
            // Reference: the series in f64 below 0.5 (no cancellation), direct above.
            let want = if ed < 0.5 {
                let x = 2.0 * ed;
                let mut t = x * x * x / 6.0;
                let mut sum = 0.0;
                let mut k = 3.0;
                while t.abs() > 1e-30 * x * x * x {
                    sum += t;
                    t *= -x * x / ((k + 1.0) * (k + 2.0));
                    k += 2.0;
                }
                0.5 * sum
            } else {
                ed - libm::sin(ed) * libm::cos(ed)
            };
            worst = worst.max((got - want).abs() / want);
            e *= 1.0013;
        }
        std::println!(
            "g_eta: worst relative error {:.3} ε",
            worst / f64::from(f32::EPSILON)
        );
        assert!(worst <= 2.0 * f64::from(f32::EPSILON), "{worst:e}");
    }
}
