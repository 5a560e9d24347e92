//! Direct light from a rectangular area light onto a diffuse receiver, in
//! closed form along **lines across the light** (Billen & Dutré 2016), with
//! the exact visibility of convex occluder faces.
//!
//! ## The quantities
//!
//! A [`QuadLight`] is a rectangle with corner `c` and orthogonal edges
//! `e₁`, `e₂`; it emits on the side of its unit normal `n_L = ê₁ × ê₂`.
//! Points of the light are `y(a, b) = c + a·ê₁ + b·ê₂`, `(a, b) ∈ [0, |e₁|] ×
//! [0, |e₂|]` (the *light coordinates*). A diffuse receiver at `x` with unit
//! normal `n` gets the irradiance `E = L_e ∫_light G(x, y) V(x, y) dA(y)` with
//! the geometry term
//!
//! ```text
//! G(x, y) = cos θ_x cos θ_y / r² = max(0, n·(y − x)) · n_L·(x − y) / r⁴,   r = |y − x|,
//! ```
//!
//! `V ∈ {0, 1}` the visibility and `cos θ_x` clamped at the receiver's
//! tangent plane (the light's part behind it contributes nothing). Since `y`
//! lies in the light's plane, `n_L·(x − y) = h` is the receiver's height
//! above that plane, the same for every `y`; the light contributes only when
//! `h > 0`.
//!
//! ## The line integral ([`diffuse_line_integral`])
//!
//! A line of the light through `p₀` with unit direction `d` (both in light
//! coordinates) meets the foot of `x` (its orthogonal projection onto the
//! light's plane, `f`) closest at `t_f = (f − p₀)·d`, at the in-plane distance
//! `ρ = |(f − p₀)·d⊥|`. With `s = t − t_f` and `q² = h² + ρ²` (the squared
//! distance from `x` to the line) we have `r² = s² + q²`, and `n·(y − x)` is
//! affine in `s`: `A + β s` with `A = n·(y(t_f) − x)`, `β = n·d`. So
//!
//! ```text
//! ∫ G dt = h ∫ max(0, A + β s) / (s² + q²)² ds.
//! ```
//!
//! The clamp cuts the interval at `s_c = −A/β`. The rest is split at `s = 0`
//! (a piece on `s < 0` is mirrored, `s → −s`, `β → −β`), and on a piece
//! `0 ≤ s_lo < s_hi` the substitution `s = q cot ε` (`ε ∈ (0, π/2]` the
//! angle between the line and the direction from the foot of the
//! perpendicular seen from `x`) turns the integrand into a trigonometric
//! polynomial, `q⁻³ sin ε (A sin ε + βq cos ε) dε`. Its integral over
//! `[ε_hi, ε_lo]`, with midpoint `m` and width `δ`, is
//!
//! ```text
//! I = h/(2q³) · [ (A sin²m + βq sin m cos m)(δ + sin δ) + (A cos²m − βq sin m cos m)(δ − sin δ) ],
//! ```
//!
//! and every ingredient has a cancellation-free algebraic form (`P = r_lo r_hi`,
//! `r = √(s² + q²)`):
//!
//! ```text
//! δ = atan2(q (s_hi − s_lo), s_lo s_hi + q²),           sin δ = q (s_hi − s_lo)/P,
//! sin²m = [q²(s_lo² + s_hi² + q²)/(P + s_lo s_hi) + q²]/(2P),
//! cos²m = [s_lo s_hi + (s_lo² s_hi² + q²(s_lo² + s_hi²))/(P + q²)]/(2P),
//! sin m cos m = q (s_lo + s_hi)/(2P),
//! ```
//!
//! with `δ − sin δ` from its Taylor series below `δ = 1` (terms to `δ¹⁹`,
//! truncation below `10⁻¹⁹` relative). The first product is the integrand's
//! value at the midpoint direction times `sin m`, so it is non-negative on a
//! clamped piece; the second is at most a third of the first in magnitude
//! (bounded by `|cot m · cot(m + χ)| (δ − sin δ)/(δ + sin δ) ≤ 1/3`, where
//! `m + χ` is the midpoint's distance to the clamp in angle), so the sum
//! loses at most a factor 2 to cancellation. Naive antiderivatives (the
//! textbook `s/(2q²(s² + q²)) + atan(s/q)/(2q³)`) cancel catastrophically
//! when `|s| ≫ q` — a receiver far from the line, or near the light's plane —
//! where this form stays exact.
//!
//! **Error bound** (`ε = 2⁻⁵³`): for exact `h, A, β, q` and interval ends, the
//! result is within `40 ε` relative of the exact integral (measured ≤ 7.1 ε
//! against 40-digit quadrature, `scene/tests/direct_light.rs`, also on
//! intervals `10⁻⁶` of their distance from the foot: a piece's width is
//! formed as `(s_hi − s_lo)/q`, never as a difference of the scaled ends).
//! Through [`DirectLight`] the inputs carry rounding, and three effects can
//! exceed that:
//!
//! * `n·(y − x)`, hence `A` and `β`, rounds absolutely, by about `ε` times
//!   the size of its terms (`≤ ε·(|x − c| + |y − c|)`). A piece that ends at
//!   the clamp integrates `∝ (s_hi − s_lo)²` from `s_c = −A/β`, which moves by
//!   that over `|β|`: relative error up to about `4ε·(|x − c| + |y_c −
//!   c|)/(|β|·(s_hi − s_lo))`, `y_c` the clamp point. The same cancellation
//!   makes a line within about `h` of the foot of a tilted receiver just
//!   below the light's plane ill-conditioned (`A ≈ −h n·n_L` there):
//!   relative `≈ ε|x − c|/(h·|n·n_L|)` (measured `8·10⁻⁸` at `h = 10⁻⁹`).
//! * `h = n_L·(x − c)` rounds by `ε|x − c|` (nothing for an axis-aligned
//!   light when `x − c` is exact): relative `ε|x − c|/h`.
//! * `s = t − t_f` rounds each end by `ε|s|`, but only the ends' positions
//!   relative to the foot carry that: the width of each piece is passed
//!   separately as `t_hi − t_lo` ([`diffuse_line_integral_width`]), so a
//!   receiver far from the light (foot far along the line) keeps full
//!   accuracy (measured 10 ulp on whole chords `10³–10⁶` light sizes away,
//!   where the difference of the shifted ends lost `5.8·10⁻¹⁰`). A tiny
//!   interval far from the foot moves as a whole by `ε|s|`: relative
//!   `ε|s|·|G'/G|`, small unless `G` varies fast there.
//!
//! The tests hold `10⁻¹²` relative on every other case: whole chords and
//! intervals down to `10⁻³` of a chord, the clamp inside the chord with
//! either sign of `β`, grazing receivers, lines through a light corner,
//! receivers `10⁻⁹` above the light's plane, rotated lights `10⁴` from the
//! origin; and each of the cases above to its stated bound.
//!
//! ## Visibility ([`Shadow`])
//!
//! An occluder face (a [`Parallelogram`]; any convex polygon works the same
//! way) blocks `y` from `x` exactly when the segment `x → y` crosses it. Only
//! the part of the face strictly between the plane through `x` parallel to the
//! light and the light's plane can block (heights `z = n_L·(x − p) ∈ (0, h)`),
//! so the face is first clipped to that slab (Sutherland–Hodgman, two planes:
//! at most 6 vertices from 4). The clipped polygon `P₀ … P_{k−1}` subtends
//! from `x` a convex cone bounded by the planes through `x`, `Pᵢ`, `Pᵢ₊₁`,
//! with normals `Nᵢ = (Pᵢ − x) × (Pᵢ₊₁ − x)` oriented towards the polygon's
//! centroid. A light point `y` is behind the face iff `Nᵢ·(y − x) ≥ 0` for
//! every `i`; in light coordinates each condition is a half-plane `αᵢ a + βᵢ
//! b + γᵢ ≥ 0` — the **central projection of the face onto the light's
//! plane**, as an intersection of half-planes, computed without dividing by
//! the (possibly zero) height of a vertex. A line then meets the shadow in
//! one interval (clip the line against each half-plane); the visible part of
//! a chord is the chord minus the union of those intervals.
//!
//! ```
//! use linesample_scene::direct_light::{DirectLight, Parallelogram, QuadLight, Shadow};
//! // A 1×1 light at height 2, facing down; a receiver on the floor below it.
//! let light = QuadLight::new([-0.5, 2.0, -0.5], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])?;
//! // A small blocker half way up.
//! let blocker = Parallelogram::new([-0.1, 1.0, -0.1], [0.2, 0.0, 0.0], [0.0, 0.0, 0.2])?;
//! let mut shadows = [Shadow::EMPTY; 1];
//! let k = Shadow::project_all(&light, [0.0, 0.0, 0.0], &[blocker], &mut shadows)?;
//! let dl = DirectLight::new(&light, [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], &shadows[..k])?;
//! // The line through the light's centre along its first edge is half shadowed.
//! let chord = light.chord(1.0, 0.0, 0.5).unwrap();
//! let mut scratch = [(0.0, 0.0); 1];
//! let seen = dl.line(&chord, &mut scratch)?;
//! let all = dl.line_unoccluded(&chord);
//! assert!(seen > 0.0 && seen < all);
//! # Ok::<(), linesample::ParamError>(())
//! ```

// `!(x > 0.0)` is `x ≤ 0 or NaN` on purpose: NaN must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
use linesample::num::scalar::sqrt;
use linesample::world::check_finite;
use linesample::ParamError;

use crate::vec3::{add, cross, dot, norm, scale, sub};

#[cfg(feature = "alloc")]
pub mod world;

/// A rectangular area light: corner `c`, orthogonal edges `e₁`, `e₂`,
/// emitting on the side of `n_L = ê₁ × ê₂` (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadLight {
    corner: [f64; 3],
    axes: [[f64; 3]; 2],
    len: [f64; 2],
    normal: [f64; 3],
}

/// A chord of the light: the line `p₀ + t·d` in light coordinates (unit `d`)
/// restricted to `t ∈ [t0, t1]`, the part inside the rectangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chord {
    /// A point of the line, in light coordinates.
    pub p0: [f64; 2],
    /// The unit direction, in light coordinates.
    pub dir: [f64; 2],
    /// Where the line enters the rectangle.
    pub t0: f64,
    /// Where it leaves it (`t1 ≥ t0`).
    pub t1: f64,
}

impl Chord {
    /// The point `p₀ + t·d` in light coordinates.
    #[must_use]
    pub fn at(&self, t: f64) -> [f64; 2] {
        [self.p0[0] + t * self.dir[0], self.p0[1] + t * self.dir[1]]
    }
}

impl QuadLight {
    /// The light with corner `corner` and edges `edge1`, `edge2` (orthogonal
    /// to `10⁻⁹` relative); it emits towards `edge1 × edge2`.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`corner`, `edge1`, `edge2`),
    /// [`ParamError::ZeroDirection`] for a zero edge,
    /// [`ParamError::OutOfRange`] (`edge2`, the cosine between the edges) for
    /// edges that are not orthogonal.
    pub fn new(
        corner: impl Into<[f64; 3]>,
        edge1: impl Into<[f64; 3]>,
        edge2: impl Into<[f64; 3]>,
    ) -> Result<Self, ParamError> {
        let [corner, e1, e2] = finite_corner_edges(corner.into(), edge1.into(), edge2.into())?;
        let (l1, l2) = (norm(e1), norm(e2));
        if !(l1 > 0.0 && l2 > 0.0 && l1.is_finite() && l2.is_finite()) {
            return Err(ParamError::ZeroDirection);
        }
        let (u, v) = (scale(e1, 1.0 / l1), scale(e2, 1.0 / l2));
        let c = dot(u, v);
        if c.abs() > 1e-9 {
            return Err(ParamError::OutOfRange {
                name: "edge2",
                value: c,
                min: -1e-9,
                max: 1e-9,
            });
        }
        // Remove the (tiny) non-orthogonal part so the frame is orthonormal.
        let v = {
            let w = sub(v, scale(u, c));
            scale(w, 1.0 / norm(w))
        };
        let normal = cross(u, v);
        Ok(Self {
            corner,
            axes: [u, v],
            len: [l1, l2],
            normal,
        })
    }

    /// The corner `c`.
    #[must_use]
    pub fn corner(&self) -> [f64; 3] {
        self.corner
    }

    /// The unit edge directions `ê₁`, `ê₂`.
    #[must_use]
    pub fn axes(&self) -> [[f64; 3]; 2] {
        self.axes
    }

    /// The edge lengths `|e₁|`, `|e₂|`.
    #[must_use]
    pub fn lengths(&self) -> [f64; 2] {
        self.len
    }

    /// The unit emitting normal `n_L = ê₁ × ê₂`.
    #[must_use]
    pub fn normal(&self) -> [f64; 3] {
        self.normal
    }

    /// The area `|e₁||e₂|`.
    #[must_use]
    pub fn area(&self) -> f64 {
        self.len[0] * self.len[1]
    }

    /// The world point of light coordinates `(a, b)`: `c + a ê₁ + b ê₂`.
    #[must_use]
    pub fn point(&self, a: f64, b: f64) -> [f64; 3] {
        let [u, v] = self.axes;
        core::array::from_fn(|j| self.corner[j] + a * u[j] + b * v[j])
    }

    /// The light coordinates of the orthogonal projection of `x` onto the
    /// light's plane, and the height `h = n_L·(x − c)` of `x` above it.
    #[must_use]
    pub fn foot(&self, x: [f64; 3]) -> ([f64; 2], f64) {
        let w = sub(x, self.corner);
        (
            [dot(w, self.axes[0]), dot(w, self.axes[1])],
            dot(w, self.normal),
        )
    }

    /// The range `[o_min, o_max]` of the offsets `o = p·d⊥` (`d⊥ = (−sin φ,
    /// cos φ)`) of the lines with direction `d = (cos φ, sin φ)` (light
    /// coordinates; `cos_phi`, `sin_phi` need not be normalised exactly)
    /// that meet the rectangle. Lines with uniform offsets in this range have
    /// uniform area density: `∫ dA = ∫ dt do`.
    #[must_use]
    pub fn offset_range(&self, cos_phi: f64, sin_phi: f64) -> (f64, f64) {
        let (pa, pb) = (-sin_phi * self.len[0], cos_phi * self.len[1]);
        let lo = 0.0f64.min(pa).min(pb).min(pa + pb);
        let hi = 0.0f64.max(pa).max(pb).max(pa + pb);
        (lo, hi)
    }

    /// The chord of the line with direction `(cos φ, sin φ)` (normalised
    /// here, the `f64` case of the crate's [conventions](crate#conventions))
    /// and offset `o` (the line `{p : p·d⊥ = o}`, through `p₀ = o·d⊥`),
    /// or `None` when it misses the rectangle, only touches it, or the
    /// direction is zero or not finite.
    #[must_use]
    pub fn chord(&self, cos_phi: f64, sin_phi: f64, offset: f64) -> Option<Chord> {
        // Normalised here (f32-rounded directions are off by a few ulp), so
        // that `t` is arc length and the offset is a distance.
        let len = libm::hypot(cos_phi, sin_phi);
        if !(len > 0.0 && len.is_finite() && offset.is_finite()) {
            return None;
        }
        let (cos_phi, sin_phi) = (cos_phi / len, sin_phi / len);
        let d = [cos_phi, sin_phi];
        let p0 = [-sin_phi * offset, cos_phi * offset];
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        for k in 0..2 {
            if d[k] == 0.0 {
                if !(p0[k] >= 0.0 && p0[k] <= self.len[k]) {
                    return None;
                }
            } else {
                let (a, b) = (-p0[k] / d[k], (self.len[k] - p0[k]) / d[k]);
                t0 = t0.max(a.min(b));
                t1 = t1.min(a.max(b));
            }
        }
        (t0 < t1).then_some(Chord { p0, dir: d, t0, t1 })
    }
}

/// A parallelogram occluder face `{c + a e₁ + b e₂ : a, b ∈ [0, 1]}`
/// (two-sided).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parallelogram {
    corner: [f64; 3],
    edges: [[f64; 3]; 2],
}

impl Parallelogram {
    /// The face with corner `corner` and edges `edge1`, `edge2` (not
    /// parallel).
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`corner`, `edge1`, `edge2`),
    /// [`ParamError::ZeroDirection`] when the edges are zero or parallel.
    pub fn new(
        corner: impl Into<[f64; 3]>,
        edge1: impl Into<[f64; 3]>,
        edge2: impl Into<[f64; 3]>,
    ) -> Result<Self, ParamError> {
        let [corner, e1, e2] = finite_corner_edges(corner.into(), edge1.into(), edge2.into())?;
        let n = norm(cross(e1, e2));
        if !(n > 1e-12 * norm(e1) * norm(e2) && n.is_finite()) {
            return Err(ParamError::ZeroDirection);
        }
        Ok(Self {
            corner,
            edges: [e1, e2],
        })
    }

    /// The corner.
    #[must_use]
    pub fn corner(&self) -> [f64; 3] {
        self.corner
    }

    /// The edges.
    #[must_use]
    pub fn edges(&self) -> [[f64; 3]; 2] {
        self.edges
    }

    /// The four vertices in order.
    #[must_use]
    pub fn vertices(&self) -> [[f64; 3]; 4] {
        let [e1, e2] = self.edges;
        let c = self.corner;
        [c, add(c, e1), add(add(c, e1), e2), add(c, e2)]
    }

    /// The (unnormalised) normal `e₁ × e₂`.
    #[must_use]
    pub fn normal(&self) -> [f64; 3] {
        cross(self.edges[0], self.edges[1])
    }
}

/// `[corner, edge1, edge2]`, each checked finite by name: the common
/// start of [`QuadLight::new`] and [`Parallelogram::new`].
fn finite_corner_edges(
    corner: [f64; 3],
    edge1: [f64; 3],
    edge2: [f64; 3],
) -> Result<[[f64; 3]; 3], ParamError> {
    check_finite("corner", &corner)?;
    check_finite("edge1", &edge1)?;
    check_finite("edge2", &edge2)?;
    Ok([corner, edge1, edge2])
}

/// Most half-planes of one [`Shadow`]: a quadrilateral clipped by two planes.
pub const SHADOW_PLANES: usize = 6;

/// The central projection of one occluder face from a receiver onto the
/// light's plane: the convex set `{(a, b) : αᵢ a + βᵢ b + γᵢ ≥ 0 ∀i}` in light
/// coordinates (see the [module docs](self)). Light points inside it are
/// hidden from the receiver by that face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shadow {
    planes: [[f64; 3]; SHADOW_PLANES],
    count: usize,
}

impl Shadow {
    /// A shadow that covers nothing (fills scratch arrays).
    pub const EMPTY: Shadow = Shadow {
        planes: [[0.0, 0.0, -1.0]; SHADOW_PLANES],
        count: 1,
    };

    /// The half-planes `(αᵢ, βᵢ, γᵢ)`.
    #[must_use]
    pub fn planes(&self) -> &[[f64; 3]] {
        &self.planes[..self.count]
    }

    /// The shadow of `face` seen from `x` on the light's plane, or `None`
    /// when the face cannot block anything from `x` (it lies outside the slab
    /// between `x`'s plane parallel to the light and the light's plane, `x`
    /// is in the face's plane, or `x` is not in front of the light).
    #[must_use]
    pub fn project(light: &QuadLight, x: [f64; 3], face: &Parallelogram) -> Option<Shadow> {
        let nl = light.normal;
        let h = dot(sub(x, light.corner), nl);
        if h.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
            return None;
        }
        // x in the face's plane: the cone has no interior.
        let fnrm = face.normal();
        let w0 = sub(face.corner, x);
        if dot(w0, fnrm).abs() <= 1e-12 * norm(w0) * norm(fnrm) {
            return None;
        }
        // Vertices relative to x; heights z = n_L·(x − p) = −n_L·w.
        let mut poly = [[0.0; 3]; 8];
        let mut k = 0;
        for p in face.vertices() {
            poly[k] = sub(p, x);
            k += 1;
        }
        // Clip to z ≥ 0 (towards the light from x's plane) and z ≤ h.
        let mut tmp = [[0.0; 3]; 8];
        let k1 = clip(&poly[..k], &mut tmp, |w| -dot(w, nl));
        let k2 = clip(&tmp[..k1], &mut poly, |w| h + dot(w, nl));
        if k2 < 3 {
            return None;
        }
        let verts = &poly[..k2];
        let mut centroid = [0.0; 3];
        for w in verts {
            centroid = add(centroid, *w);
        }
        let [u, v] = light.axes;
        let cx = sub(light.corner, x);
        let mut out = Shadow {
            planes: [[0.0; 3]; SHADOW_PLANES],
            count: 0,
        };
        for i in 0..k2 {
            let (a, b) = (verts[i], verts[(i + 1) % k2]);
            let mut nrm = cross(a, b);
            let len = norm(nrm);
            // Degenerate edge (a duplicate vertex from clipping, or x on the
            // edge's line): no constraint.
            if !(len > 1e-14 * norm(a) * norm(b)) {
                continue;
            }
            if dot(nrm, centroid) < 0.0 {
                nrm = scale(nrm, -1.0);
            }
            let nrm = scale(nrm, 1.0 / len);
            if out.count == SHADOW_PLANES {
                // More edges than a clipped quadrilateral can have: only
                // possible through rounding in the clipper; keep the first.
                break;
            }
            out.planes[out.count] = [dot(nrm, u), dot(nrm, v), dot(nrm, cx)];
            out.count += 1;
        }
        (out.count >= 3).then_some(out)
    }

    /// The shadows of `faces` from `x`, written to the front of `out`; the
    /// count written. Faces that cannot block are skipped.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`x`), [`ParamError::Length`] (`out`) when
    /// `out` is shorter than `faces`.
    pub fn project_all(
        light: &QuadLight,
        x: impl Into<[f64; 3]>,
        faces: &[Parallelogram],
        out: &mut [Shadow],
    ) -> Result<usize, ParamError> {
        let x = x.into();
        check_finite("x", &x)?;
        if out.len() < faces.len() {
            return Err(ParamError::Length {
                name: "out",
                expected: faces.len(),
                got: out.len(),
            });
        }
        let mut k = 0;
        for f in faces {
            if let Some(s) = Shadow::project(light, x, f) {
                out[k] = s;
                k += 1;
            }
        }
        Ok(k)
    }

    /// Whether light point `(a, b)` is inside the shadow.
    #[must_use]
    pub fn contains(&self, a: f64, b: f64) -> bool {
        self.planes()
            .iter()
            .all(|p| p[0] * a + p[1] * b + p[2] >= 0.0)
    }

    /// Whether the shadow certainly misses the light's rectangle
    /// `[0, |e₁|] × [0, |e₂|]`: one of its half-planes leaves all four
    /// corners strictly outside (`αa + βb + γ < 0` at each). Both sets are
    /// convex, so such a half-plane separates them (the separating-axis
    /// test over the shadow's own edges); `false` may still mean a shadow
    /// that only grazes the light, never one that is dropped wrongly. A
    /// renderer skips such shadows before preparing a receiver: a wall
    /// beside the light, say, projects outside it.
    #[must_use]
    pub fn misses(&self, light: &QuadLight) -> bool {
        let [l1, l2] = light.lengths();
        self.planes().iter().any(|p| {
            [(0.0, 0.0), (l1, 0.0), (0.0, l2), (l1, l2)]
                .iter()
                .all(|&(a, b)| p[0] * a + p[1] * b + p[2] < 0.0)
        })
    }

    /// The interval of `t ∈ [chord.t0, chord.t1]` whose points are inside the
    /// shadow, or `None`.
    #[must_use]
    pub fn interval(&self, chord: &Chord) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (chord.t0, chord.t1);
        for p in self.planes() {
            let k = p[0] * chord.dir[0] + p[1] * chord.dir[1];
            let m = p[0] * chord.p0[0] + p[1] * chord.p0[1] + p[2];
            if k > 0.0 {
                lo = lo.max(-m / k);
            } else if k < 0.0 {
                hi = hi.min(-m / k);
            } else if m < 0.0 {
                return None;
            }
        }
        (lo < hi).then_some((lo, hi))
    }
}

/// Sutherland–Hodgman: the part of polygon `inp` where `f(w) ≥ 0`, into
/// `out`; the vertex count.
fn clip(inp: &[[f64; 3]], out: &mut [[f64; 3]; 8], f: impl Fn([f64; 3]) -> f64) -> usize {
    let n = inp.len();
    let mut k = 0;
    for i in 0..n {
        let (a, b) = (inp[i], inp[(i + 1) % n]);
        let (fa, fb) = (f(a), f(b));
        if fa >= 0.0 {
            out[k] = a;
            k += 1;
        }
        if (fa >= 0.0) != (fb >= 0.0) {
            let t = fa / (fa - fb);
            out[k] = core::array::from_fn(|j| a[j] + t * (b[j] - a[j]));
            k += 1;
        }
    }
    k
}

/// A receiver's direct light from one [`QuadLight`] behind a set of
/// [`Shadow`]s: the geometry term at light points and its integral along
/// chords, clamped at the receiver's tangent plane.
#[derive(Clone, Copy, Debug)]
pub struct DirectLight<'a> {
    light: QuadLight,
    x: [f64; 3],
    foot: [f64; 2],
    h: f64,
    /// `n·(y(a, b) − x) = l[0] + l[1] a + l[2] b`.
    l: [f64; 3],
    shadows: &'a [Shadow],
}

impl<'a> DirectLight<'a> {
    /// The receiver at `x` with normal `n` (normalised here) behind
    /// `shadows` (from [`Shadow::project_all`] at the same `x`).
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] (`x`, `n`), [`ParamError::ZeroDirection`]
    /// for a zero normal.
    pub fn new(
        light: &QuadLight,
        x: impl Into<[f64; 3]>,
        n: impl Into<[f64; 3]>,
        shadows: &'a [Shadow],
    ) -> Result<Self, ParamError> {
        let (x, n) = (x.into(), n.into());
        check_finite("x", &x)?;
        check_finite("n", &n)?;
        let ln = norm(n);
        if !(ln > 0.0 && ln.is_finite()) {
            return Err(ParamError::ZeroDirection);
        }
        let n = scale(n, 1.0 / ln);
        let (foot, h) = light.foot(x);
        let [u, v] = light.axes;
        Ok(Self {
            light: *light,
            x,
            foot,
            h,
            l: [dot(n, sub(light.corner, x)), dot(n, u), dot(n, v)],
            shadows,
        })
    }

    /// The receiver's height `h` above the light's plane (nothing arrives
    /// unless `h > 0`).
    #[must_use]
    pub fn height(&self) -> f64 {
        self.h
    }

    /// The light.
    #[must_use]
    pub fn light(&self) -> &QuadLight {
        &self.light
    }

    /// The receiver `x`.
    #[must_use]
    pub fn receiver(&self) -> [f64; 3] {
        self.x
    }

    /// The shadows.
    #[must_use]
    pub fn shadows(&self) -> &'a [Shadow] {
        self.shadows
    }

    /// Scratch length [`DirectLight::line`] needs: one interval per shadow.
    #[must_use]
    pub fn scratch_len(&self) -> usize {
        self.shadows.len()
    }

    /// `G(x, y)·V(x, y)` at light point `(a, b)` (light coordinates):
    /// `h·max(0, n·(y − x))/r⁴`, zero when a shadow contains the point.
    #[must_use]
    pub fn point(&self, a: f64, b: f64) -> f64 {
        if self.h.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
            return 0.0;
        }
        let c = self.l[0] + self.l[1] * a + self.l[2] * b;
        if c.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
            return 0.0;
        }
        if self.shadows.iter().any(|s| s.contains(a, b)) {
            return 0.0;
        }
        let (da, db) = (a - self.foot[0], b - self.foot[1]);
        let r2 = da * da + db * db + self.h * self.h;
        self.h * c / (r2 * r2)
    }

    /// The reduced form of a chord: `(A, β, q, t_f)` with `n·(y − x) = A +
    /// β (t − t_f)` and `r² = (t − t_f)² + q²` along it.
    #[must_use]
    pub fn reduce(&self, chord: &Chord) -> (f64, f64, f64, f64) {
        let d = chord.dir;
        let fp = [self.foot[0] - chord.p0[0], self.foot[1] - chord.p0[1]];
        let tf = fp[0] * d[0] + fp[1] * d[1];
        let rho = fp[1] * d[0] - fp[0] * d[1];
        let q = libm::hypot(self.h, rho);
        let at = chord.at(tf);
        let a = self.l[0] + self.l[1] * at[0] + self.l[2] * at[1];
        let beta = self.l[1] * d[0] + self.l[2] * d[1];
        (a, beta, q, tf)
    }

    /// `∫ G dt` over `t ∈ [t_lo, t_hi]` of the chord's line, ignoring the
    /// shadows (the clamp at the tangent plane applies).
    #[must_use]
    pub fn line_interval(&self, chord: &Chord, t_lo: f64, t_hi: f64) -> f64 {
        if self.h.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) || !(t_lo < t_hi) {
            return 0.0;
        }
        let (a, beta, q, tf) = self.reduce(chord);
        integral(self.h, a, beta, q, t_lo - tf, t_hi - tf, t_hi - t_lo)
    }

    /// `∫ G dt` over the whole chord, ignoring the shadows.
    #[must_use]
    pub fn line_unoccluded(&self, chord: &Chord) -> f64 {
        self.line_interval(chord, chord.t0, chord.t1)
    }

    /// The shadowed intervals of the chord, one per shadow that it meets,
    /// sorted by start, into the front of `scratch`; their count.
    ///
    /// # Errors
    /// [`ParamError::Length`] (`scratch`) when shorter than
    /// [`DirectLight::scratch_len`].
    pub fn shadowed(&self, chord: &Chord, scratch: &mut [(f64, f64)]) -> Result<usize, ParamError> {
        if scratch.len() < self.shadows.len() {
            return Err(ParamError::Length {
                name: "scratch",
                expected: self.shadows.len(),
                got: scratch.len(),
            });
        }
        let mut k = 0;
        for s in self.shadows {
            if let Some(iv) = s.interval(chord) {
                // Insertion sort: a handful of intervals.
                let mut j = k;
                while j > 0 && scratch[j - 1].0 > iv.0 {
                    scratch[j] = scratch[j - 1];
                    j -= 1;
                }
                scratch[j] = iv;
                k += 1;
            }
        }
        Ok(k)
    }

    /// `∫ G V dt` over the chord: the closed form over each visible piece
    /// (the chord minus the union of the shadowed intervals).
    ///
    /// # Errors
    /// [`ParamError::Length`] (`scratch`) when shorter than
    /// [`DirectLight::scratch_len`].
    pub fn line(&self, chord: &Chord, scratch: &mut [(f64, f64)]) -> Result<f64, ParamError> {
        if self.h.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
            return Ok(0.0);
        }
        let k = self.shadowed(chord, scratch)?;
        let (a, beta, q, tf) = self.reduce(chord);
        let mut sum = 0.0;
        let mut start = chord.t0;
        for &(lo, hi) in &scratch[..k] {
            if lo > start {
                sum += integral(self.h, a, beta, q, start - tf, lo - tf, lo - start);
            }
            start = start.max(hi);
        }
        if chord.t1 > start {
            sum += integral(
                self.h,
                a,
                beta,
                q,
                start - tf,
                chord.t1 - tf,
                chord.t1 - start,
            );
        }
        Ok(sum)
    }
}

/// `h ∫_{s_a}^{s_b} max(0, A + β s)/(s² + q²)² ds` for `h ≥ 0`, `q > 0`: the
/// diffuse geometry term integrated along a line of an area light (see the
/// [module docs](self) for the reduction and the cancellation-free form, and
/// its error bound). Returns 0 for an empty or reversed interval.
#[must_use]
pub fn diffuse_line_integral(h: f64, a: f64, beta: f64, q: f64, s_a: f64, s_b: f64) -> f64 {
    integral(h, a, beta, q, s_a, s_b, s_b - s_a)
}

/// [`diffuse_line_integral`] over `[s_a, s_a + width]`, with the width given
/// separately: callers that know it exactly (the difference of two line
/// parameters, `t₁ − t₀`) keep it exact even when both ends are far from the
/// foot of the perpendicular, where `s_b − s_a` of the shifted ends would
/// carry an error of `ε·|s_a|`.
#[must_use]
pub fn diffuse_line_integral_width(h: f64, a: f64, beta: f64, q: f64, s_a: f64, width: f64) -> f64 {
    integral(h, a, beta, q, s_a, s_a + width, width)
}

/// The integral over `[lo, hi]` whose width `w = hi − lo` the caller formed
/// as accurately as it can (each of `lo`, `hi`, `w` is used where it is the
/// accurate one: the clamp is measured from the end it cuts).
fn integral(h: f64, a: f64, beta: f64, q: f64, lo: f64, hi: f64, w: f64) -> f64 {
    let (mut lo, mut hi, mut w) = (lo, hi, w);
    // The clamp at the tangent plane.
    if beta > 0.0 {
        let c = -a / beta;
        if c > lo {
            w = hi - c;
            lo = c;
        }
    } else if beta < 0.0 {
        let c = -a / beta;
        if c < hi {
            w = c - lo;
            hi = c;
        }
    } else if !(a > 0.0) {
        return 0.0;
    }
    if !(lo < hi) || !(w > 0.0) || !(h > 0.0) || !(q > 0.0) {
        return 0.0;
    }
    let mut sum = 0.0;
    if lo < 0.0 && hi > 0.0 {
        // Split at the foot; each piece's width is one of its (exact) ends.
        sum += one_sided(a, -beta, q, 0.0, -lo);
        sum += one_sided(a, beta, q, 0.0, hi);
    } else if hi <= 0.0 {
        // Mirror s → −s.
        sum += one_sided(a, -beta, q, -hi, w);
    } else {
        sum += one_sided(a, beta, q, lo, w);
    }
    h * sum
}

/// `∫_{lo}^{lo + width} (A + β s)/(s² + q²)² ds` for `lo ≥ 0`, `width > 0`
/// (the integrand is non-negative there after the clamp).
fn one_sided(a: f64, beta: f64, q: f64, lo: f64, width: f64) -> f64 {
    if !(width > 0.0) {
        return 0.0;
    }
    let hi = lo + width;
    // Scale lengths by q: the formulas are homogeneous.
    let (x, y) = (lo / q, hi / q);
    let rx = sqrt(1.0 + x * x);
    let ry = sqrt(1.0 + y * y);
    let p = rx * ry;
    // The scaled width from the given width (exact, or within ε relative),
    // not `y − x` of the separately rounded quotients, which would carry an
    // error of `ε·(x + y)` (relative `ε·(lo + hi)/(hi − lo)`: tiny intervals
    // far from the foot).
    let w = width / q;
    let xy = x * y;
    let sin_d = w / p;
    let d = libm::atan2(w, xy + 1.0);
    let g = if d < 1.0 { x_minus_sin(d) } else { d - sin_d };
    let sum2 = x * x + y * y;
    let sin2 = ((sum2 + 1.0) / (p + xy) + 1.0) / (2.0 * p);
    let cos2 = (xy + (xy * xy + sum2) / (p + 1.0)) / (2.0 * p);
    let sc = (x + y) / (2.0 * p);
    // βq with s in units of q: A + β s = A + (βq)(s/q).
    let bq = beta * q;
    let x1 = a * sin2 + bq * sc;
    let x2 = a * cos2 - bq * sc;
    (x1 * (d + sin_d) + x2 * g) / (2.0 * q * q * q)
}

/// `x − sin x` for `0 ≤ x < 1` from its Taylor series (terms to `x¹⁹`,
/// truncation `< x²¹/21! < 2·10⁻²⁰`).
fn x_minus_sin(x: f64) -> f64 {
    let z = x * x;
    // x³/3! − x⁵/5! + … − x¹⁹/19!, Horner in z.
    let mut acc = 0.0;
    let mut n = 19u32;
    while n >= 3 {
        let f = factorial(n);
        let sign = if (n / 2) % 2 == 1 { 1.0 } else { -1.0 };
        acc = acc * z + sign / f;
        n -= 2;
    }
    acc * z * x
}

fn factorial(n: u32) -> f64 {
    (2..=n).fold(1.0, |a, k| a * f64::from(k))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn x_minus_sin_matches_direct_where_safe() {
        for &x in &[0.5, 0.9, 0.999] {
            let d: f64 = x - libm::sin(x);
            assert!((x_minus_sin(x) - d).abs() <= 1e-14 * d, "{x}");
        }
        let x = 1e-3f64;
        let want = x * x * x / 6.0 - x.powi(5) / 120.0 + x.powi(7) / 5040.0;
        assert!((x_minus_sin(x) - want).abs() < 1e-15 * want);
    }

    #[test]
    fn one_sided_matches_antiderivative_in_benign_range() {
        // Textbook antiderivative, fine when s ~ q.
        let f = |a: f64, b: f64, q: f64, s: f64| {
            a * (s / (2.0 * q * q * (s * s + q * q)) + libm::atan(s / q) / (2.0 * q * q * q))
                - b / (2.0 * (s * s + q * q))
        };
        let (a, b, q) = (0.7, 0.3, 0.9);
        let want = f(a, b, q, 1.3) - f(a, b, q, 0.2);
        let got = one_sided(a, b, q, 0.2, 1.1); // [0.2, 1.3]
        assert!((got - want).abs() < 1e-14 * want, "{got} {want}");
    }
}
