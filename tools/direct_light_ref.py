#!/usr/bin/env python3
"""Reference values for `linesample_scene::direct_light` (scene/tests/direct_light.rs).

Writes scene/tests/data/direct_light_ref.csv (header line + one row per case):

    python3 tools/direct_light_ref.py            # about 30 s

Every `line` row is one 3D configuration: a rectangular light (corner c, edges
e1, e2), a receiver x with normal n, a line of the light given in light
coordinates by its direction (cos phi, sin phi) and offset o (the module's
`QuadLight::chord` convention: p0 = (-sin phi * o, cos phi * o)), and a
parameter interval [t_lo, t_hi] of that line. The reference is

    I = integral over t in [t_lo, t_hi] of G(y(t)) dt,
    G(y) = max(0, n^.(y - x)) * n_L.(x - y) / |y - x|^4,
    y(t) = c + a(t) e^1 + b(t) e^2,  (a, b)(t) = p0 + t d,

evaluated DIRECTLY on the 3D points y(t) with mpmath at 40 digits from the
exact binary values of the double inputs (e^1 = e1/|e1|, e^2 the unit part of
e2 orthogonal to e^1, as the module defines the frame; n_L = e^1 x e^2;
n^ = n/|n|). Nothing of the module's reduction (h, A, beta, q, s) or of its
closed form is used: mp.quad integrates the 3D integrand piecewise, with
breakpoints at the clamp (where n.(y - x) = 0 on the 3D line), at the foot of
the perpendicular from x to the 3D line, and at geometric distances
q * 4^k from that foot (q the distance from x to the line), so that the peak
of width q is resolved even when q is 1e-9 of the interval. Every reference is
computed twice (tanh-sinh and Gauss-Legendre) and the two must agree to
1e-25 relative, else the script stops.

The `free` rows are the 1D definition of `diffuse_line_integral`,
h * integral over [s_a, s_b] of max(0, A + beta s)/(s^2 + q^2)^2 ds, for exact
double inputs (the function's own contract, "exact h, A, beta, q and interval
ends"), integrated the same way.

Inputs are written with repr() (shortest round-trip), so the Rust test reads
the same doubles; the reference is written as two doubles ref_hi + ref_lo
(ref_hi = the reference rounded to double, ref_lo = the rounded remainder) so
the test measures errors below one ulp. `t_perp` and `t_clamp` (the foot of
the perpendicular and the clamp, as doubles; nan when there is no clamp) and
`dlog_da` (the relative sensitivity (1/I) dI/dδ of the reference to an
absolute change δ of n.(y - x), i.e. the integral of n_L.(x - y)/|y - x|^4
over the lit part, divided by I; also by quadrature of the 3D geometry) are
written for the test's error bounds on ill-conditioned rows only.

Columns: kind (`line` or `free`), class, the light's corner, edge1, edge2,
the receiver x and normal n (3 each), cos, sin (the chord direction as
QuadLight::chord normalises it), offset, p0 (2), the whole chord's t0, t1,
the interval t_lo, t_hi, whole (1: the interval is the whole chord), then h,
a, beta, q (`free` rows only; 0 in `line` rows, whose geometry columns are 0
in `free` rows, with s_a, s_b in t_lo, t_hi), t_perp, t_clamp, ref_hi,
ref_lo, dlog_da.

Cases (seeded, deterministic: rerunning writes the same file byte for byte):
see `main()`; each row names its class.
"""

import math
import os
import random
import sys

from mpmath import mp, mpf

mp.dps = 40

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scene", "tests", "data", "direct_light_ref.csv")

CORNELL = ((-0.24, 1.98, -0.22), (0.47, 0.0, 0.0), (0.0, 0.0, 0.38))

# ----------------------------------------------------------------- vectors (mp)


def mv(a):
    return [mpf(c) for c in a]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def add(a, b):
    return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]


def scl(a, s):
    return [a[0] * s, a[1] * s, a[2] * s]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a):
    return scl(a, 1 / mp.sqrt(dot(a, a)))


def frame(corner, e1, e2):
    """The exact light frame of the double inputs: e^1, e^2 (orthogonalised), n_L."""
    u = unit(mv(e1))
    w = unit(mv(e2))
    v = unit(sub(w, scl(u, dot(u, w))))
    return mv(corner), u, v, cross(u, v)


# ----------------------------------------------------------------- doubles


def fnorm(e):
    # Same evaluation order as the module's norm (sqrt of a0*a0 + a1*a1 + a2*a2).
    return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])


def offset_range(L, c, s):
    pa, pb = -s * L[0], c * L[1]
    return min(0.0, pa, pb, pa + pb), max(0.0, pa, pb, pa + pb)


def chord(L, c, s, off):
    """QuadLight::chord in doubles: ((cos, sin) normalised, p0, t0, t1) or
    None. (The module normalises with libm's hypot; Python's may differ in
    the last bit, so the test takes the chord from the file and only checks
    that QuadLight::chord agrees to a few ulp.)"""
    ln = math.hypot(c, s)
    c, s = c / ln, s / ln
    d = (c, s)
    p0 = (-s * off, c * off)
    t0, t1 = -math.inf, math.inf
    for k in range(2):
        if d[k] == 0.0:
            if not (0.0 <= p0[k] <= L[k]):
                return None
        else:
            a, b = -p0[k] / d[k], (L[k] - p0[k]) / d[k]
            t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
    if not t0 < t1:
        return None
    return d, p0, t0, t1


# ----------------------------------------------------------------- integration


def breakpoints(lo, hi, t_perp, q, extra):
    pts = {lo, hi}
    for t in [t_perp] + extra:
        if t is not None and lo < t < hi:
            pts.add(t)
    if q > 0:
        k = q
        while k < (hi - lo):
            for t in (t_perp - k, t_perp + k):
                if lo < t < hi:
                    pts.add(t)
            k *= 4
    return sorted(pts)


def integrate(f, pts, check=True):
    a = mp.quad(f, pts, method="tanh-sinh", maxdegree=12)
    if not check:
        return a
    b = mp.quad(f, pts, method="gauss-legendre", maxdegree=12)
    scale = max(abs(a), abs(b))
    if scale != 0 and abs(a - b) > mpf("1e-25") * scale:
        raise SystemExit(f"quadrature disagrees: {a} vs {b}")
    return a


def line_geometry(corner, e1, e2, x, n, p0, d):
    """(t_perp, q, t_clamp) of the 3D line: the foot of the perpendicular from
    x, the distance from x, and where n.(y - x) = 0 (None if never)."""
    c, u, v, _ = frame(corner, e1, e2)
    X = mv(x)
    nn = unit(mv(n))
    y0 = add(c, add(scl(u, mpf(p0[0])), scl(v, mpf(p0[1]))))
    D = add(scl(u, mpf(d[0])), scl(v, mpf(d[1])))
    t_perp = dot(sub(X, y0), D) / dot(D, D)
    f = sub(X, add(y0, scl(D, t_perp)))
    q = mp.sqrt(dot(f, f))
    nd = dot(nn, D)
    t_c = -dot(nn, sub(y0, X)) / nd if nd != 0 else None
    return t_perp, q, t_c, nd


def line_reference(corner, e1, e2, x, n, p0, d, t_lo, t_hi):
    """(I, t_perp, t_clamp) by quadrature of the 3D geometry term along y(t)."""
    c, u, v, nl = frame(corner, e1, e2)
    X = mv(x)
    nn = unit(mv(n))
    y0 = add(c, add(scl(u, mpf(p0[0])), scl(v, mpf(p0[1]))))
    D = add(scl(u, mpf(d[0])), scl(v, mpf(d[1])))

    def g(t, weight):
        y = add(y0, scl(D, t))
        r = sub(y, X)
        cx = dot(nn, r)
        if cx <= 0:
            return mpf(0)
        cy = dot(nl, sub(X, y))
        r2 = dot(r, r)
        return (cx if weight else 1) * cy / (r2 * r2)

    t_perp, q, t_c, _ = line_geometry(corner, e1, e2, x, n, p0, d)
    pts = breakpoints(mpf(t_lo), mpf(t_hi), t_perp, q, [t_c])
    val = integrate(lambda t: g(t, True), pts)
    # d I / d delta for n.(y - x) -> n.(y - x) + delta: the sensitivity to an
    # absolute error in the cosine's numerator (for the test's error bound).
    # Only for a tolerance: tanh-sinh alone (its jump at the clamp makes
    # Gauss-Legendre slow).
    sens = integrate(lambda t: g(t, False), pts, check=False)
    return val, t_perp, t_c, sens


def free_reference(h, a, beta, q, s_a, s_b):
    h, a, beta, q = mpf(h), mpf(a), mpf(beta), mpf(q)

    def g(s):
        c = a + beta * s
        if c <= 0:
            return mpf(0)
        r2 = s * s + q * q
        return h * c / (r2 * r2)

    s_c = -a / beta if beta != 0 else None
    return integrate(g, breakpoints(mpf(s_a), mpf(s_b), mpf(0), q, [s_c]))


# ----------------------------------------------------------------- rows

COLUMNS = (
    "kind,class,cx,cy,cz,e1x,e1y,e1z,e2x,e2y,e2z,xx,xy,xz,nx,ny,nz,"
    "cos,sin,offset,p0a,p0b,chord_t0,chord_t1,t_lo,t_hi,whole,"
    "h,a,beta,q,t_perp,t_clamp,ref_hi,ref_lo,dlog_da"
)

ROWS = []


def r(v):
    return repr(float(v))


def split(v):
    hi = float(v)
    lo = float(v - mpf(hi))
    return repr(hi), repr(lo)


def add_line(cls, light, x, n, phi=None, cs=None, off=None, sub_iv=None, rng=None, nonzero=False):
    """One line row. phi or cs=(cos, sin); off None: uniform in the offset range.
    sub_iv: None (whole chord), ('frac', u0, u1) of the chord, ('abs', t_lo, t_hi).
    nonzero: skip the row when the reference is 0 (all behind the tangent
    plane). Returns True when a row was written."""
    corner, e1, e2 = light
    L = (fnorm(e1), fnorm(e2))
    c, s = cs if cs is not None else (math.cos(phi), math.sin(phi))
    if off is None:
        o0, o1 = offset_range(L, c, s)
        off = o0 + (o1 - o0) * rng.random()
    ch = chord(L, c, s, off)
    if ch is None:
        return False
    (c, s), p0, t0, t1 = ch
    if sub_iv is None:
        t_lo, t_hi, whole = t0, t1, 1
    elif sub_iv[0] == "frac":
        t_lo = t0 + (t1 - t0) * sub_iv[1]
        t_hi = t0 + (t1 - t0) * sub_iv[2]
        whole = 0
    else:
        t_lo, t_hi, whole = sub_iv[1], sub_iv[2], 0
    if not t_lo < t_hi:
        return False
    val, t_perp, t_c, sens = line_reference(corner, e1, e2, x, n, p0, (c, s), t_lo, t_hi)
    if nonzero and val == 0:
        return False
    hi_s, lo_s = split(val)
    ROWS.append(
        ",".join(
            ["line", cls]
            + [r(v) for v in (*corner, *e1, *e2, *x, *n, c, s, off, p0[0], p0[1], t0, t1, t_lo, t_hi)]
            + [str(whole), "0", "0", "0", "0", r(t_perp), r(t_c) if t_c is not None else "nan", hi_s, lo_s]
            + [r(sens / val) if val != 0 else "nan"]
        )
    )
    return True


def add_free(cls, h, a, beta, q, s_a, s_b):
    """One row of the free function: (h, A, beta, q) in their columns, the
    interval [s_a, s_b] in t_lo, t_hi, t_perp = 0, t_clamp = -A/beta."""
    val = free_reference(h, a, beta, q, s_a, s_b)
    hi_s, lo_s = split(val)
    s_c = r(-mpf(a) / mpf(beta)) if beta != 0 else "nan"
    ROWS.append(
        ",".join(
            ["free", cls]
            + ["0"] * 22
            + [r(s_a), r(s_b), "0"]
            + [r(v) for v in (h, a, beta, q)]
            + ["0.0", s_c, hi_s, lo_s, "nan"]
        )
    )


# ----------------------------------------------------------------- helpers


def rand_unit(rng):
    while True:
        v = [rng.uniform(-1, 1) for _ in range(3)]
        l2 = v[0] ** 2 + v[1] ** 2 + v[2] ** 2
        if 1e-3 < l2 <= 1:
            l = math.sqrt(l2)
            return [c / l for c in v]


def rand_rotation(rng):
    """A random rotation matrix (columns), from a random unit quaternion."""
    while True:
        qv = [rng.gauss(0, 1) for _ in range(4)]
        l = math.sqrt(sum(c * c for c in qv))
        if l > 1e-3:
            break
    w, x, y, z = (c / l for c in qv)
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)],
        [2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)],
        [2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)],
    ]  # rows are the rotated axes


def light_geometry_f(light):
    """Double-precision frame (for placing receivers only; references use mp)."""
    corner, e1, e2 = light
    l1, l2 = fnorm(e1), fnorm(e2)
    u = [c / l1 for c in e1]
    v = [c / l2 for c in e2]
    nl = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    return u, v, nl, (l1, l2)


def place(light, a, b, h):
    """The double point corner + a e^1 + b e^2 + h n_L (rounded)."""
    u, v, nl, _ = light_geometry_f(light)
    c = light[0]
    return [c[i] + a * u[i] + b * v[i] + h * nl[i] for i in range(3)]


def facing_normal(rng, light, x, min_cos=0.05):
    """A random unit normal that sees the light's centre at cos >= min_cos."""
    u, v, nl, L = light_geometry_f(light)
    ctr = place(light, 0.5 * L[0], 0.5 * L[1], 0.0)
    w = [ctr[i] - x[i] for i in range(3)]
    lw = math.sqrt(sum(c * c for c in w))
    w = [c / lw for c in w]
    while True:
        n = rand_unit(rng)
        if sum(n[i] * w[i] for i in range(3)) >= min_cos:
            return n


# ----------------------------------------------------------------- cases


def main():
    rng = random.Random(20170625)
    light = CORNELL
    _, _, _, L = light_geometry_f(light)

    # 1. Cornell box: random receivers in the room, random lines, whole
    #    chords and random sub-intervals of at least 1e-3 of the chord.
    k = 0
    while k < 40:
        x = [rng.uniform(-1, 1), rng.uniform(0, 1.9), rng.uniform(-1, 1)]
        n = facing_normal(rng, light, x, min_cos=-0.3)
        phi = rng.uniform(0, math.pi)
        c, s = math.cos(phi), math.sin(phi)
        o0, o1 = offset_range(L, c, s)
        off = o0 + (o1 - o0) * rng.random()
        if not add_line("cornell", light, x, n, cs=(c, s), off=off, nonzero=True):
            continue
        u0 = rng.random() * 0.999
        u1 = u0 + 1e-3 + (0.999 - u0) * rng.random()
        add_line("cornell-sub", light, x, n, cs=(c, s), off=off, sub_iv=("frac", u0, u1))
        k += 1

    # 2. Near the light's plane (axis-aligned light: h = 1.98 - x_y is exact):
    #    random lines, and lines along either edge exactly through the foot.
    for h in (1e-3, 1e-6, 1e-9):
        for j in range(8):
            fa, fb = rng.uniform(-0.2, L[0] + 0.2), rng.uniform(-0.2, L[1] + 0.2)
            if j < 4:
                fa, fb = rng.uniform(0.05, L[0] - 0.05), rng.uniform(0.05, L[1] - 0.05)
            x = [-0.24 + fa, 1.98 - h, -0.22 + fb]
            # Normal towards the light (+y), tilted up to 80 degrees; the first
            # two face it squarely.
            th = 0.0 if j < 2 else rng.uniform(0, 1.4)
            ps = rng.uniform(0, 2 * math.pi)
            n = [math.sin(th) * math.cos(ps), math.cos(th), math.sin(th) * math.sin(ps)]
            add_line(f"near-{h:g}", light, x, n, phi=rng.uniform(0, math.pi), rng=rng)
            add_line(f"near-{h:g}", light, x, n, phi=rng.uniform(0, math.pi), rng=rng, sub_iv=("frac", 0.1, 0.7))
            if 0 <= fa <= L[0] and 0 <= fb <= L[1]:
                # Through the foot: q = h, the integrand peaks at 1/h^3.
                foot_b = x[2] - (-0.22)
                foot_a = x[0] - (-0.24)
                if j % 2 == 0:
                    add_line(f"near-{h:g}-foot", light, x, n, cs=(1.0, 0.0), off=foot_b)
                else:
                    add_line(f"near-{h:g}-foot", light, x, n, cs=(0.0, 1.0), off=-foot_a)

    # 3. Light partly behind the receiver's tangent plane: the clamp inside the
    #    chord, both signs of beta (the same line in both directions).
    k = 0
    while k < 16:
        x = [rng.uniform(-0.6, 0.6), rng.uniform(0.8, 1.9), rng.uniform(-0.6, 0.6)]
        n = rand_unit(rng)
        phi = rng.uniform(0, math.pi)
        c, s = math.cos(phi), math.sin(phi)
        o0, o1 = offset_range(L, c, s)
        off = o0 + (o1 - o0) * rng.uniform(0.1, 0.9)
        ch = chord(L, c, s, off)
        if ch is None:
            continue
        (c, s), p0, t0, t1 = ch
        _, _, t_c, _ = line_geometry(light[0], light[1], light[2], x, n, p0, (c, s))
        if t_c is None or not (t0 + 0.1 * (t1 - t0) < t_c < t1 - 0.1 * (t1 - t0)):
            continue
        add_line("clamp", light, x, n, cs=(c, s), off=off)
        add_line("clamp", light, x, n, cs=(-c, -s), off=-off)  # beta of the other sign
        add_line("clamp-sub", light, x, n, cs=(c, s), off=off, sub_iv=("frac", 0.05, 0.6))
        k += 1

    # 4. Grazing normals: n almost in the light's plane (n.n_L = +-1e-3, 1e-6,
    #    1e-9), receivers at moderate height and near the plane.
    for g in (1e-3, -1e-3, 1e-6, -1e-6, 1e-9, -1e-9):
        for hx in (0.7, 1e-3):
            ps = rng.uniform(0, 2 * math.pi)
            # n_L = -y: n.n_L = -n_y.
            n = [math.cos(ps), -g, math.sin(ps)]
            x = [rng.uniform(-0.3, 0.2), 1.98 - hx, rng.uniform(-0.3, 0.1)]
            for _ in range(2):
                add_line("grazing", light, x, n, phi=rng.uniform(0, math.pi), rng=rng)

    # 5. Lines through a light corner (and the diagonals), receivers below.
    corners = [(0.0, 0.0), (L[0], 0.0), (L[0], L[1]), (0.0, L[1])]
    for j in range(12):
        x = [rng.uniform(-0.8, 0.8), rng.uniform(0.0, 1.5), rng.uniform(-0.8, 0.8)]
        n = facing_normal(rng, light, x, min_cos=0.2)
        ci = j % 4
        pa, pb = corners[ci]
        if j < 8:
            # Into the rectangle from that corner.
            base = [0.0, math.pi / 2, math.pi, 1.5 * math.pi][ci]
            phi = base + rng.uniform(0.05, math.pi / 2 - 0.05)
        else:
            qa, qb = corners[(ci + 2) % 4]
            phi = math.atan2(qb - pb, qa - pa)
        c, s = math.cos(phi), math.sin(phi)
        off = -s * pa + c * pb
        add_line("corner", light, x, n, cs=(c, s), off=off)

    # 6. Far receivers: 1e3 .. 1e6 light sizes away, on the emitting side.
    for dist in (1e3, 1e4, 1e5, 1e6):
        for _ in range(4):
            dirv = rand_unit(rng)
            if dirv[1] > 0:
                dirv[1] = -dirv[1]
            if dirv[1] > -0.05:
                dirv[1] = -0.3
            x = [0.0 + dist * dirv[0], 1.98 + dist * dirv[1], 0.0 + dist * dirv[2]]
            n = facing_normal(rng, light, x, min_cos=0.1)
            add_line("far", light, x, n, phi=rng.uniform(0, math.pi), rng=rng)
            add_line("far", light, x, n, phi=rng.uniform(0, math.pi), rng=rng, sub_iv=("frac", 0.3, 0.5))

    # 7. The foot of the perpendicular far along the line (|s| >> q): the
    #    receiver displaced along a line's direction, near the light's plane
    #    (q small) or not; displacement 10 .. 1e6 light sizes.
    for disp in (10.0, 1e2, 1e3, 1e4, 1e6):
        for hx in (1e-3, 0.5):
            for axis in (0, 1):
                sign = rng.choice((-1.0, 1.0))
                b_off = rng.uniform(0.05, 0.3)  # the line's offset (inside the light)
                if axis == 0:
                    x = [-0.24 + 0.2 + sign * disp, 1.98 - hx, -0.22 + b_off + 1e-4]
                    cs, off = (1.0, 0.0), b_off
                else:
                    x = [-0.24 + b_off + 1e-4, 1.98 - hx, -0.22 + 0.2 + sign * disp]
                    cs, off = (0.0, 1.0), -b_off
                n = facing_normal(rng, light, x, min_cos=0.05)
                add_line("far-foot", light, x, n, cs=cs, off=off)
                add_line("far-foot", light, x, n, cs=cs, off=off, sub_iv=("frac", 0.2, 0.9))

    # 8. Tiny sub-intervals (1e-6 of the chord): anywhere, and ending at the
    #    clamp (on its lit side: after it for n.d > 0, before it otherwise).
    k, kc = 0, 0
    while k < 16 or kc < 12:
        x = [rng.uniform(-0.6, 0.6), rng.uniform(0.3, 1.9), rng.uniform(-0.6, 0.6)]
        n = rand_unit(rng)
        phi = rng.uniform(0, math.pi)
        c, s = math.cos(phi), math.sin(phi)
        o0, o1 = offset_range(L, c, s)
        off = o0 + (o1 - o0) * rng.uniform(0.05, 0.95)
        ch = chord(L, c, s, off)
        if ch is None:
            continue
        (c, s), p0, t0, t1 = ch
        _, _, t_c, nd = line_geometry(light[0], light[1], light[2], x, n, p0, (c, s))
        w = 1e-6 * (t1 - t0)
        if k < 16:
            u0 = rng.uniform(0, 1 - 1e-6)
            iv = ("abs", t0 + u0 * (t1 - t0), t0 + u0 * (t1 - t0) + w)
            k += add_line("tiny", light, x, n, cs=(c, s), off=off, sub_iv=iv, nonzero=True)
        if kc < 12 and t_c is not None and t0 + 2 * w < t_c < t1 - 2 * w:
            tc = float(t_c)
            iv = ("abs", tc, tc + w) if nd > 0 else ("abs", tc - w, tc)
            kc += add_line("tiny-clamp", light, x, n, cs=(c, s), off=off, sub_iv=iv)

    # 9. Long intervals: almost the whole chord, and the whole line far
    #    beyond the light (t over +-1e3 light sizes).
    for j in range(10):
        x = [rng.uniform(-0.8, 0.8), rng.uniform(0.2, 1.9), rng.uniform(-0.8, 0.8)]
        n = facing_normal(rng, light, x, min_cos=0.2)
        phi = rng.uniform(0, math.pi)
        if j < 5:
            add_line("long", light, x, n, phi=phi, rng=rng, sub_iv=("frac", 1e-9, 1.0))
        else:
            span = 10.0 ** rng.uniform(1, 3)
            add_line("long", light, x, n, phi=phi, rng=rng, sub_iv=("abs", -span, span))

    # 10. Non-axis-aligned lights: random rotations, corner near (1e4, -2e4,
    #     3e4) (receivers within O(1) of it, so x - c is exact), and an exact
    #     integer frame ((1,2,2), (2,1,-2)); random and near-plane receivers.
    for j in range(14):
        if j < 10:
            R = rand_rotation(rng)
            l1, l2 = rng.uniform(0.2, 1.0), rng.uniform(0.2, 1.0)
            e1 = [l1 * c for c in R[0]]
            e2 = [l2 * c for c in R[1]]
        else:
            e1 = [0.25, 0.5, 0.5]
            e2 = [0.25, 0.125, -0.25]
        corner = [1e4 + rng.uniform(0, 1), -2e4 + rng.uniform(0, 1), 3e4 + rng.uniform(0, 1)]
        lt = (corner, e1, e2)
        _, _, _, Lr = light_geometry_f(lt)
        for hx in (0.5, 1e-3):
            x = place(lt, rng.uniform(-0.3, Lr[0] + 0.3), rng.uniform(-0.3, Lr[1] + 0.3), hx)
            n = facing_normal(rng, lt, x, min_cos=0.1)
            add_line("rotated", lt, x, n, phi=rng.uniform(0, math.pi), rng=rng)
            add_line("rotated", lt, x, n, phi=rng.uniform(0, math.pi), rng=rng, sub_iv=("frac", 0.25, 0.75))

    # 11. The free function on its own (exact inputs): tiny intervals far from
    #     the foot, |s| >> q, the clamp inside, both signs of beta.
    for j in range(24):
        q = 10.0 ** rng.uniform(-6, 1)
        h = q * rng.uniform(0.1, 1.0)
        beta = rng.uniform(-1, 1)
        a = rng.uniform(-1, 1) * q
        cls = "free"
        if j < 8:
            s0 = rng.choice((-1, 1)) * q * 10.0 ** rng.uniform(0, 6)
            s_a, s_b = s0, s0 + abs(s0) * 1e-6
            a = abs(a) + abs(beta) * (abs(s0) + abs(s_b)) + q  # no clamp in it
            cls = "free-tiny"
        elif j < 16:
            s_a = -q * 10.0 ** rng.uniform(-1, 5)
            s_b = q * 10.0 ** rng.uniform(-1, 5)
            cls = "free-clamp"
        else:
            s_a = q * 10.0 ** rng.uniform(2, 6)
            s_b = s_a * rng.uniform(1.001, 3)
            a = abs(beta) * s_b * 3
            cls = "free-far"
        add_free(cls, h, a, beta, q, s_a, s_b)

    with open(OUT, "w") as f:
        f.write(COLUMNS + "\n")
        for row in ROWS:
            f.write(row + "\n")
    print(f"wrote {len(ROWS)} rows to {os.path.normpath(OUT)}", file=sys.stderr)


if __name__ == "__main__":
    main()
