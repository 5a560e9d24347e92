#!/usr/bin/env python3
"""Reference values for `linesample_scene::caustic` (scene/tests/caustic.rs).

Writes scene/tests/data/caustic_ref.csv:

    python3 tools/caustic_ref.py            # about a minute

Nothing here uses the module's algorithms (its chord helpers, its vector
Snell's law, its Fresnel formula or its closed form of the beam). Everything
is computed with mpmath at 60 digits from the exact binary values of the
double inputs.

1. `beam` cases: a photon path given as segments (origin o, direction, medium
   offset `start`, parameter length `length`, weight), a query ball Q (centre
   c, radius r) and a medium (sigma_s, sigma_a). The module's rays are
   `o + t w` with `w` the direction as `Ray::new` stores it (`Direction::new`:
   divide by the largest |component|, sum the squares in index order, sqrt,
   divide; replicated here in double arithmetic, `direction_new`), so `w` is
   unit only up to rounding and the parameter `t` is in units of |w|. The
   reference uses exactly that stored `w`:

       ref = sum_k  integral over t in [0, length_k] with o_k + t w_k in Q of
                    sigma_s * weight_k * exp(-sigma_t * (start_k + t)) dt,

   sigma_t = fl(sigma_s + sigma_a) (the double the module's `Medium` stores).
   The chord ends of Q along each line are found by bisection on
   f(t) = |o + t w - c|^2 - r^2 (from the minimiser of f, 240 halvings at 60
   digits), cross-checked against mpmath's polyroots; the clipped chord is
   integrated with mp.quad (tanh-sinh), cross-checked against the
   antiderivative (the two must agree to 1e-40 relative, else the script
   stops).

2. `trace` cases: an independent tracer of the module's photon path (module
   docs, "The path of a photon") for an emission direction `dir` (a unit
   double, as `Caustic::trace` takes it): ray/ball intersection by the same
   bisection, Snell's law in the angle formulation (theta_i = acos(-n.d),
   theta_t = asin(sin(theta_i)/eta), new direction = cos(theta_t)(-n) +
   sin(theta_t) (unit tangential part of d)), mirror reflection the same way
   (cos(theta_i) n + sin(theta_i) (unit tangential part)), Fresnel from the
   angle forms R_s = sin^2(ti - tt)/sin^2(ti + tt), R_p = tan^2(ti - tt) /
   tan^2(ti + tt), R = (R_s + R_p)/2 (at normal incidence the limit
   ((n - 1)/(n + 1))^2). Bookkeeping as in the module docs: the emitted ray
   (start 0, weight 1, length = the distance to the ball, or infinite for a
   miss); with Fresnel the ray reflected at the entry (weight R1, only if
   R1 > 0); then the exits after k = 0..K internal reflections, weight
   T1 R^k T (T = 1 - R; Fresnel off: one exit, weight 1); every ray after the
   first starts at medium offset tau = the entry distance. Each `tseg` row is
   one segment of that path (unit direction, rounded to doubles). Each
   `tbeam` row is the beam value of that path in one query ball and medium,
   by the same chord bisection and quadrature as in 1, along the exact
   (60-digit) rays, with `kappa`, the relative sensitivity of the value to a
   relative perturbation of the path's geometry (see `beam_kappa`), and
   `robust` = 1 when a zero reference is zero with a margin (every segment
   misses Q, or its chord lies outside [0, length], by at least 1e-9 of r).

File format: lines starting with `#` are comments; every other line is one
record, comma separated, its first field the kind (2D rows have 0 in the z
columns):

    bcase,case,class,dim,qx,qy,qz,qr,sigma_s,sigma_a,nseg,g_min,ref_hi,ref_lo
    bseg,case,i,ox,oy,oz,dx,dy,dz,wx,wy,wz,start,length,weight
    trace,case,class,dim,lx,ly,lz,gx,gy,gz,gr,ior,K,dirx,diry,dirz,nseg,impact
    tseg,case,i,ox,oy,oz,wx,wy,wz,start,length,weight
    tbeam,case,qx,qy,qz,qr,sigma_s,sigma_a,ref_hi,ref_lo,kappa,robust

`d` is the vector given to `Ray::new`, `w` the stored direction it must
become bit for bit; `g_min` is the smallest 1 - dist(c, line)/r over the
case's segments (negative: all lines miss Q); K = -1 means Fresnel::Off;
`impact` is 1 - (distance from the glass centre to the emitted ray's
line)/radius (negative: misses the glass). References are written as
ref_hi + ref_lo (the reference rounded to a double and the rounded
remainder), inputs with repr() (shortest round trip). The run is
deterministic (seeded): rerunning writes the same file byte for byte.
"""

import math
import os
import random
import sys

from mpmath import mp, mpf

mp.dps = 60

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scene", "tests", "data", "caustic_ref.csv")

# ----------------------------------------------------------------- doubles


def direction_new(v):
    """`Direction::new` in double arithmetic (same operations, same order)."""
    m = 0.0
    for x in v:
        m = max(m, abs(x))
    s = [x / m for x in v]
    acc = 0.0
    for x in s:
        acc += x * x
    n = math.sqrt(acc)
    return [x / n for x in s]


def fdot(a, b):
    return sum(x * y for x, y in zip(a, b))


def fsub(a, b):
    return [x - y for x, y in zip(a, b)]


def fadd(a, b):
    return [x + y for x, y in zip(a, b)]


def fscl(a, s):
    return [x * s for x in a]


def fperp(w, rng=None):
    """A unit double vector orthogonal (up to rounding) to the unit w."""
    if len(w) == 2:
        return [-w[1], w[0]]
    # Gram-Schmidt of the axis least aligned with w (or a random vector).
    if rng is None:
        j = min(range(3), key=lambda k: abs(w[k]))
        e = [0.0, 0.0, 0.0]
        e[j] = 1.0
    else:
        e = [rng.gauss(0, 1) for _ in range(3)]
    e = fsub(e, fscl(w, fdot(e, w)))
    return direction_new(e)


# ----------------------------------------------------------------- mp vectors


def mv(a):
    return [mpf(x) for x in a]


def dot(a, b):
    s = mpf(0)
    for x, y in zip(a, b):
        s += x * y
    return s


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def add(a, b):
    return [x + y for x, y in zip(a, b)]


def scl(a, s):
    return [x * s for x in a]


def norm(a):
    return mp.sqrt(dot(a, a))


def unit(a):
    return scl(a, 1 / norm(a))


# ----------------------------------------------------------------- chords


def chord_ends(o, w, c, r):
    """(t_lo, t_hi) where |o + t w - c| = r (o, w, c mp vectors, r mp), or
    None when the line misses the open ball. Bisection on the quadratic f
    from its minimiser, cross-checked against polyroots."""
    q = sub(o, c)
    A = dot(w, w)
    B = dot(q, w)
    C = dot(q, q) - r * r

    def f(t):
        return (A * t + 2 * B) * t + C

    ts = -B / A
    if not f(ts) < 0:
        return None
    span = 2 * (r + norm(q)) / mp.sqrt(A) + 1
    ends = []
    for lo, hi, rising in ((ts - span, ts, False), (ts, ts + span, True)):
        assert (f(lo) > 0) != rising and (f(hi) > 0) == rising
        for _ in range(240):
            mid = (lo + hi) / 2
            if (f(mid) > 0) == rising:
                hi = mid
            else:
                lo = mid
        ends.append((lo + hi) / 2)
    roots = sorted(mp.re(x) for x in mp.polyroots([A, 2 * B, C], maxsteps=500, extraprec=500))
    h = (ends[1] - ends[0]) / 2
    for a, b in zip(ends, roots):
        if abs(a - b) > mpf(10) ** -45 * (abs(a) + h):
            raise SystemExit(f"root finders disagree: {a} vs {b}")
    return ends[0], ends[1]


def integrate(sig_s, sig_t, weight, start, a, b):
    """sigma_s weight int_a^b exp(-sigma_t (start + t)) dt by mp.quad, checked
    against the antiderivative."""
    if weight == 0:
        return mpf(0)
    v = mp.quad(lambda t: sig_s * weight * mp.exp(-sig_t * (start + t)), [a, b])
    e = sig_s * weight / sig_t * (mp.exp(-sig_t * (start + a)) - mp.exp(-sig_t * (start + b)))
    if abs(v - e) > mpf(10) ** -40 * abs(e):
        raise SystemExit(f"quadrature disagrees: {v} vs {e}")
    return v


def clipped(o, w, c, r, length):
    """The chord of Q along o + t w clipped to [0, length] (mp), or None."""
    ch = chord_ends(o, w, c, r)
    if ch is None:
        return None
    a = max(ch[0], mpf(0))
    b = min(ch[1], length)
    if not b > a:
        return None
    return a, b, ch


def medium(sig_s, sig_a):
    return mpf(sig_s), mpf(sig_s + sig_a)  # sigma_t is the double fl(s + a)


def split(v):
    hi = float(v)
    lo = float(v - mpf(hi))
    return repr(hi), repr(lo)


def r(v):
    return repr(float(v))


def pad3(v):
    v = list(v)
    return v + [0.0] * (3 - len(v))


ROWS = []

# ----------------------------------------------------------------- 1. beams

N_BEAM = [0]


def add_beam(cls, D, qc, qr, sig_s, sig_a, segs):
    """segs: (o, d, start, length, weight) with d the raw vector given to
    Ray::new. Writes the case and returns the reference (mp)."""
    assert len(qc) == D
    case = N_BEAM[0]
    N_BEAM[0] += 1
    ss, st = medium(sig_s, sig_a)
    assert float(st) * 0 == 0 and 1e-3 * 0.999 <= float(st) <= 100.0 * 1.001, st
    c, rr = mv(qc), mpf(qr)
    total = mpf(0)
    g_min = -math.inf
    seg_rows = []
    for i, (o, d, start, length, weight) in enumerate(segs):
        assert len(o) == D and len(d) == D
        w = direction_new(d)
        O, W = mv(o), mv(w)
        # 1 - dist(c, line)/r
        q = sub(O, c)
        foot = sub(q, scl(W, dot(q, W) / dot(W, W)))
        g_min = max(g_min, float(1 - norm(foot) / rr))
        L = mp.inf if math.isinf(length) else mpf(length)
        cl = clipped(O, W, c, rr, L)
        if cl is not None:
            a, b, _ = cl
            # sigma_t (start + a) <= 50: nothing underflows.
            assert float(st * (start + a)) <= 55.0, (cls, float(st * (start + a)))
            total += integrate(ss, st, mpf(weight), mpf(start), a, b)
        seg_rows.append(
            ",".join(["bseg", str(case), str(i)] + [r(x) for x in pad3(o) + pad3(d) + pad3(w)]
                     + [r(start), r(length), r(weight)])
        )
    hi, lo = split(total)
    ROWS.append(",".join(["bcase", str(case), cls, str(D)] + [r(x) for x in pad3(qc)]
                         + [r(qr), r(sig_s), r(sig_a), str(len(segs)), repr(g_min), hi, lo]))
    ROWS.extend(seg_rows)
    return total


def grazing_origin(c, rad, w, perp, g, back):
    """A double origin whose line along w passes at (1 - g) rad from c."""
    return [c[j] + rad * (1.0 - g) * perp[j] - back * w[j] for j in range(len(c))]


def chord_params_f(o, w, c, rad):
    """(t_lo, t_hi) of the chord in doubles (approximate, to place ends)."""
    ch = chord_ends(mv(o), mv(w), mv(c), mpf(rad))
    return (float(ch[0]), float(ch[1])) if ch else None


def beam_cases(rng):
    INF = math.inf
    # ---- chords well inside.
    add_beam("inside", 2, [0.3, -0.2], 0.5, 0.5, 0.1, [([-2.0, 0.1], [1.0, -0.13], 0.0, INF, 1.0)])
    add_beam("inside", 2, [0.3, -0.2], 0.5, 7e-4, 3e-4, [([-2.0, 0.1], [1.0, -0.13], 1.7, INF, 0.3)])
    add_beam("inside", 2, [0.3, -0.2], 0.5, 8.0, 2.0, [([-1.5, 0.4], [1.8, -0.7], 0.25, INF, 0.7)])
    add_beam("inside", 2, [1e3 + 0.3, -2e3], 0.5, 0.5, 0.1, [([1e3 - 2.0, -2e3 + 0.1], [1.0, -0.13], 0.0, INF, 1.0)])
    add_beam("inside", 3, [0.1, -0.4, 0.25], 0.7, 0.5, 0.1, [([1.5, 2.0, -1.0], [-1.3, -2.1, 1.4], 0.0, INF, 1.0)])
    add_beam("inside", 3, [0.1, -0.4, 0.25], 0.7, 1.0, 0.0, [([1.5, 2.0, -1.0], [0.1 - 1.5, -0.4 - 2.0, 0.25 + 1.0], 0.0, INF, 1.0)])
    add_beam("inside", 3, [0.1, -0.4, 0.25], 0.1, 60.0, 40.0, [([0.35, -0.3, 0.3], [-1.0, -0.3, -0.2], 0.05, INF, 0.25)])
    add_beam("inside", 3, [-0.7, 0.2, 0.9], 0.3, 3e-3, 1e-3, [([2.0, 1.0, -1.0], [-2.7, -0.75, 1.85], 3.0, INF, 0.9)])
    add_beam("inside", 2, [0.05, -1.0], 0.1, 0.5, 0.1, [([0.0, 2.0], [0.02, -1.0], 0.0, INF, 1.0)])
    add_beam("inside", 3, [0.05, -1.0, 0.03], 0.1, 0.5, 0.1, [([0.0, 2.0, 0.0], [0.02, -1.0, 0.01], 0.0, INF, 1.0)])
    # ---- grazing: 1 - d/r = g.
    for g in (1e-3, 1e-6, 1e-9, 1e-12):
        # axis-aligned (the stored w is exactly (1, 0))
        c = [0.25, -0.5]
        o = [-3.0, c[1] + 0.75 * (1.0 - g)]
        add_beam("grazing", 2, c, 0.75, 0.5, 0.1, [(o, [1.0, 0.0], 0.0, INF, 1.0)])
        # oblique 2D
        w = direction_new([0.8, 0.6])
        c = [0.4, 0.1]
        o = grazing_origin(c, 0.6, w, fperp(w), g, 2.5)
        add_beam("grazing", 2, c, 0.6, 1.5, 0.5, [(o, [0.8, 0.6], 0.3, INF, 0.8)])
        # oblique 3D
        d = [0.3, -0.9, 0.4]
        w = direction_new(d)
        c = [-0.2, 0.3, 0.7]
        o = grazing_origin(c, 0.45, w, fperp(w), g, 1.7)
        add_beam("grazing", 3, c, 0.45, 0.5, 0.1, [(o, d, 0.0, INF, 1.0)])
    # grazing chords cut by a finite length (ends at the chord's middle)
    for D, g in ((2, 1e-6), (3, 1e-9)):
        d = [0.6, -0.8] if D == 2 else [0.6, -0.8, 0.3]
        w = direction_new(d)
        c = [0.1] * D
        o = grazing_origin(c, 0.5, w, fperp(w), g, 2.0)
        t0, t1 = chord_params_f(o, w, c, 0.5)
        add_beam("grazing-cut", D, c, 0.5, 0.5, 0.1, [(o, d, 0.0, 0.5 * (t0 + t1), 1.0)])
    # ---- a finite segment ending inside Q (and one starting and ending inside).
    for D in (2, 3):
        d = [1.0, 0.4] if D == 2 else [1.0, 0.4, -0.3]
        w = direction_new(d)
        o = [-1.0] * D
        c = fadd(o, fscl(w, 2.0))
        c = fadd(c, fscl(fperp(w), 0.2))
        t0, t1 = chord_params_f(o, w, c, 0.6)
        add_beam("ends-inside", D, c, 0.6, 0.5, 0.1, [(o, d, 0.4, t0 + 0.37 * (t1 - t0), 1.0)])
        add_beam("ends-inside", D, c, 0.6, 2.0, 1.0, [(o, d, 0.0, t0 + 1e-3 * (t1 - t0), 0.6)])
        oi = fadd(c, fscl(fperp(w), 0.3))
        add_beam("ends-inside", D, c, 0.6, 0.5, 0.1, [(oi, d, 1.1, 0.2, 1.0)])
    # ---- an origin inside Q.
    add_beam("origin-inside", 2, [0.0, 0.0], 1.0, 2.0, 1.0, [([0.3, -0.2], [-0.5, 1.0], 2.0, INF, 1.0)])
    add_beam("origin-inside", 3, [0.5, 0.5, 0.5], 0.8, 0.25, 0.05, [([0.6, 0.2, 0.4], [0.3, 0.3, -1.0], 0.0, INF, 0.5)])
    add_beam("origin-inside", 3, [0.5, 0.5, 0.5], 0.8, 10.0, 5.0, [([0.5, 0.5, 0.5], [1.0, 1.0, 1.0], 0.0, INF, 1.0)])
    # ---- tiny Q (r = 1e-6).
    add_beam("tiny", 2, [0.4, 0.7], 1e-6, 0.5, 0.1, [([0.0, 0.0], [0.4 - 3e-7, 0.7 + 1e-7], 0.0, INF, 1.0)])
    add_beam("tiny", 3, [0.4, 0.7, -0.2], 1e-6, 5.0, 1.0, [([0.0, 0.0, 0.0], [0.4, 0.7, -0.2], 0.5, INF, 1.0)])
    w = direction_new([1.0, -0.2, 0.5])
    c = [0.7, -0.3, 0.1]
    add_beam("tiny", 3, c, 1e-6, 0.5, 0.1, [(grazing_origin(c, 1e-6, w, fperp(w), 1e-6, 1.0), [1.0, -0.2, 0.5], 0.0, INF, 1.0)])
    # ---- large Q (r = 1e3).
    add_beam("large", 2, [1500.0, 300.0], 1e3, 0.008, 0.002, [([0.0, 0.0], [1.0, 0.1], 0.0, INF, 1.0)])
    add_beam("large", 2, [1500.0, 300.0], 1e3, 1e-3, 0.0, [([0.0, 0.0], [1.0, 0.6], 2.0, INF, 1.0)])
    add_beam("large", 3, [0.0, 0.0, 0.0], 1e3, 0.01, 0.0, [([10.0, -20.0, 5.0], [0.2, 0.9, -0.1], 0.0, INF, 1.0)])
    add_beam("large", 3, [0.0, 0.0, 0.0], 1e3, 0.004, 0.001, [([10.0, -20.0, 5.0], [0.2, 0.9, -0.1], 0.0, 1234.5, 0.5)])
    # ---- misses (reference exactly 0).
    add_beam("miss", 2, [0.0, 0.0], 0.5, 0.5, 0.1, [([-2.0, 1.0], [1.0, 0.0], 0.0, INF, 1.0)])
    add_beam("miss", 3, [0.0, 0.0, 0.0], 0.5, 0.5, 0.1, [([-2.0, 0.3, 0.45], [1.0, 0.1, 0.1], 0.0, INF, 1.0)])
    add_beam("miss-behind", 2, [0.0, 0.0], 0.5, 0.5, 0.1, [([2.0, 0.1], [1.0, 0.05], 0.0, INF, 1.0)])
    add_beam("miss-short", 3, [0.0, 0.0, 0.0], 0.5, 0.5, 0.1, [([-2.0, 0.1, 0.0], [1.0, 0.0, 0.0], 0.0, 1.2, 1.0)])
    add_beam("miss-empty", 2, [0.0, 0.0], 0.5, 0.5, 0.1, [([0.1, 0.1], [1.0, 0.3], 0.5, 0.0, 1.0)])
    add_beam("miss-weight0", 2, [0.0, 0.0], 0.5, 0.5, 0.1, [([-2.0, 0.1], [1.0, 0.0], 0.0, INF, 0.0)])
    for g in (-1e-9, -1e-12):
        w = direction_new([0.8, 0.6, 0.1])
        c = [0.4, 0.1, -0.3]
        o = grazing_origin(c, 0.6, w, fperp(w), g, 2.5)
        add_beam("miss-near", 3, c, 0.6, 0.5, 0.1, [(o, [0.8, 0.6, 0.1], 0.0, INF, 1.0)])
    add_beam("miss", 2, [0.0, 0.0], 0.5, 0.5, 0.1,
             [([-2.0, 1.0], [1.0, 0.0], 0.0, 1.0, 1.0), ([2.0, 0.1], [1.0, 0.05], 1.0, INF, 0.3),
              ([0.7, -0.6], [0.0, -1.0], 1.0, INF, 0.7)])
    # ---- several segments (a traced path's shape: the first ends at a point,
    #      the others start there at offset tau).
    p = [0.1, 0.45]
    add_beam("multi", 2, [0.05, -1.0], 0.3, 0.5, 0.1,
             [([0.0, 2.0], [0.1, 2.0 - 0.45], 0.0, 1.5534, 1.0),
              (p, [0.2, 1.0], 1.5534, INF, 0.05),
              ([0.05, -0.48], [0.02, -1.0], 1.5534, INF, 0.9),
              ([-0.3, 0.2], [-0.4, 1.0], 1.5534, INF, 0.04)])
    add_beam("multi", 2, [0.0, 0.0], 3.0, 0.3, 0.0,
             [([0.0, 2.0], [0.0, -1.0], 0.0, 1.5, 1.0),
              ([0.0, 0.5], [0.0, 1.0], 1.5, INF, 0.04),
              ([0.0, -0.5], [0.0, -1.0], 1.5, INF, 0.9216),
              ([0.0, 0.5], [0.0, 1.0], 1.5, INF, 0.036864)])
    add_beam("multi", 3, [0.05, -1.0, 0.03], 0.2, 0.5, 0.1,
             [([0.0, 2.0, 0.0], [0.05, -1.6, 0.02], 0.0, 1.6, 1.0),
              ([0.05, 0.4, 0.02], [0.3, 1.0, 0.1], 1.6, INF, 0.06),
              ([0.04, -0.45, 0.02], [0.01, -1.0, 0.005], 1.6, INF, 0.85),
              ([0.2, -0.3, 0.0], [-0.3, -1.0, 0.05], 1.6, INF, 0.05),
              ([0.0, -0.5, 0.1], [0.1, -1.0, -0.1], 1.6, INF, 0.003)])
    add_beam("multi", 3, [1.0, 1.0, 1.0], 1.5, 2.0, 0.5,
             [([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.0, 0.8, 1.0),
              ([0.46, 0.46, 0.46], [1.0, 0.8, 1.2], 0.8, INF, 0.5),
              ([0.46, 0.46, 0.46], [-1.0, 0.2, 0.3], 0.8, INF, 0.5),
              ([0.46, 0.46, 0.46], [1.0, 1.0, 0.0], 0.8, 0.1, 0.25)])
    # ---- random cases.
    k = 0
    while k < 30:
        D = rng.choice((2, 3))
        qr = 10.0 ** rng.uniform(-2, 1)
        c = [rng.uniform(-2, 2) for _ in range(D)]
        segs = []
        far = 0.0
        for _ in range(rng.choice((1, 1, 2, 3))):
            dist = qr * 10.0 ** rng.uniform(-0.5, 1.0)
            u = direction_new([rng.gauss(0, 1) for _ in range(D)])
            o = fadd(c, fscl(u, dist))
            aim = fadd(c, fscl(direction_new([rng.gauss(0, 1) for _ in range(D)]), qr * rng.uniform(0, 1.2)))
            d = fsub(aim, o)
            start = rng.choice((0.0, rng.uniform(0, 2)))
            length = rng.choice((math.inf, math.inf, rng.uniform(0.2, 2.0) * dist))
            segs.append((o, d, start, length, rng.uniform(0.05, 1.0)))
            far = max(far, start + dist + 2 * qr)
        st = 10.0 ** rng.uniform(-3, 2)
        st = min(st, 50.0 / far)
        if st < 1e-3:
            continue
        alb = rng.uniform(0.2, 1.0)
        add_beam("random", D, c, qr, st * alb, st * (1 - alb), segs)
        k += 1


# ----------------------------------------------------------------- 2. traces


def fresnel_angles(ti, tt, n):
    """Unpolarised reflectance from the angles (either side; symmetric)."""
    if mp.sin(ti) < mpf(10) ** -40:
        return ((n - 1) / (n + 1)) ** 2
    rs = mp.sin(ti - tt) ** 2 / mp.sin(ti + tt) ** 2
    rp = mp.tan(ti - tt) ** 2 / mp.tan(ti + tt) ** 2
    return (rs + rp) / 2


def tangential(d, n):
    """The unit part of d orthogonal to n (zero vector if d is along n)."""
    t = sub(d, scl(n, dot(d, n)))
    m = norm(t)
    if m < mpf(10) ** -40:
        return [mpf(0)] * len(d)
    return scl(t, 1 / m)


def trace_mp(light, gc, gr, ior, K, dirf):
    """The photon path (list of (origin, unit dir, start, length, weight), mp)
    of the double unit direction dirf. K = None: Fresnel off."""
    P, C, R, eta = mv(light), mv(gc), mpf(gr), mpf(ior)
    d = unit(mv(dirf))
    ch = chord_ends(P, d, C, R)
    if ch is None or not ch[0] > 0:
        return [(P, d, mpf(0), mp.inf, mpf(1))]
    t_in = ch[0]
    segs = [(P, d, mpf(0), t_in, mpf(1))]
    X = add(P, scl(d, t_in))
    n = unit(sub(X, C))
    ti = mp.acos(-dot(n, d))
    tt = mp.asin(mp.sin(ti) / eta)
    tu = tangential(d, n)
    r1 = fresnel_angles(ti, tt, eta) if K is not None else mpf(0)
    if r1 > 0:
        refl = add(scl(n, mp.cos(ti)), scl(tu, mp.sin(ti)))
        segs.append((X, refl, t_in, mp.inf, r1))
    dt = add(scl(n, -mp.cos(tt)), scl(tu, mp.sin(tt)))
    w = 1 - r1
    kmax = 0 if K is None else K
    for k in range(kmax + 1):
        ch = chord_ends(X, dt, C, R)
        Y = add(X, scl(dt, ch[1]))
        n2 = unit(sub(Y, C))
        t2 = mp.acos(dot(n2, dt))
        to = mp.asin(eta * mp.sin(t2))
        tu2 = tangential(dt, n2)
        out = add(scl(n2, mp.cos(to)), scl(tu2, mp.sin(to)))
        r2 = fresnel_angles(t2, to, eta) if K is not None else mpf(0)
        segs.append((Y, out, t_in, mp.inf, w * (1 - r2)))
        w *= r2
        if k == kmax or not w > 0:
            break
        dt = add(scl(n2, -mp.cos(t2)), scl(tu2, mp.sin(t2)))
        X = Y
    return segs


def beam_kappa(segs, c, rr, ss, st, total):
    """Relative sensitivity of the beam value to the path's geometry: each
    chord end t_e of Q moves by about (|t_e| + 1)(d/h + 1) per unit relative
    perturbation of the segment's origin and direction (d the distance from
    Q's centre to the line, h the half chord); an end at the segment's own
    end (the glass) by (|t_e| + 1); the offset tau by tau + 1. kappa =
    sum of |d value/d end| times those, over the value."""
    if total == 0:
        return mpf(0)
    kap = mpf(0)
    for o, w, start, length, weight in segs:
        cl = clipped(o, w, c, rr, length)
        if cl is None:
            continue
        a, b, (t0, t1) = cl
        h = (t1 - t0) / 2
        q = sub(o, c)
        dist = norm(sub(q, scl(w, dot(q, w))))
        ea = ss * weight * mp.exp(-st * (start + a))
        eb = ss * weight * mp.exp(-st * (start + b))
        if a > 0:
            kap += ea * (abs(a) + 1) * (dist / h + 1)
        if b == t1:
            kap += eb * (abs(b) + 1) * (dist / h + 1)
        elif b != mp.inf:
            kap += eb * (abs(b) + 1)
        kap += st * (start + 1) * (ea - eb) / st
    return kap / total


def robust_zero(segs, c, rr):
    """Every segment misses Q (or its chord is outside [0, length]) by a
    margin of 1e-9 r."""
    m = mpf(10) ** -9 * rr
    for o, w, start, length, weight in segs:
        q = sub(o, c)
        dist = norm(sub(q, scl(w, dot(q, w))))
        if dist > rr + m:
            continue
        ch = chord_ends(o, w, c, rr + m)
        if ch is None:
            continue
        if ch[1] < -m or ch[0] > length + m:
            continue
        return False
    return True


N_TRACE = [0]


def add_trace(cls, D, light, gc, gr, ior, K, dirf, queries):
    case = N_TRACE[0]
    N_TRACE[0] += 1
    segs = trace_mp(light, gc, gr, ior, K, dirf)
    P, C = mv(light), mv(gc)
    d = unit(mv(dirf))
    q = sub(P, C)
    impact = 1 - norm(sub(q, scl(d, dot(q, d)))) / mpf(gr)
    ROWS.append(",".join(["trace", str(case), cls, str(D)] + [r(x) for x in pad3(light) + pad3(gc)]
                         + [r(gr), r(ior), str(-1 if K is None else K)] + [r(x) for x in pad3(dirf)]
                         + [str(len(segs)), repr(float(impact))]))
    for i, (o, w, start, length, weight) in enumerate(segs):
        ROWS.append(",".join(["tseg", str(case), str(i)] + [r(x) for x in pad3(o) + pad3(w)]
                             + [r(start), r(length), r(weight)]))
    for qc, qr, sig_s, sig_a in queries:
        ss, st = medium(sig_s, sig_a)
        c, rr = mv(qc), mpf(qr)
        total = mpf(0)
        for o, w, start, length, weight in segs:
            cl = clipped(o, w, c, rr, length)
            if cl is not None:
                total += integrate(ss, st, weight, start, cl[0], cl[1])
        kap = beam_kappa(segs, c, rr, ss, st, total)
        robust = 1 if total == 0 and robust_zero(segs, c, rr) else 0
        hi, lo = split(total)
        ROWS.append(",".join(["tbeam", str(case)] + [r(x) for x in pad3(qc)]
                             + [r(qr), r(sig_s), r(sig_a), hi, lo, repr(float(kap)), str(robust)]))
    return segs


def emission(light, gc, gr, b, perp):
    """A unit double direction from the light whose line passes at distance
    b*gr from the glass centre, on the side of perp (b > 1: misses)."""
    v = fsub(gc, light)
    L = math.sqrt(fdot(v, v))
    vu = fscl(v, 1.0 / L)
    beta = math.asin(min(b * gr / L, 1.0)) if b <= 1.0 else math.asin(gr / L) * b
    return direction_new(fadd(fscl(vu, math.cos(beta)), fscl(perp, math.sin(beta))))


def trace_cases(rng):
    modes = [None, 0, 2, 5]
    scenes = [
        ("axis", 2, [0.0, 2.0], [0.0, 0.0], 0.5, 1.5, modes),
        ("axis", 2, [0.0, 2.0], [0.0, 0.0], 0.5, 1.33, modes),
        ("axis", 3, [0.0, 2.0, 0.0], [0.0, 0.0, 0.0], 0.5, 1.5, modes),
        ("axis", 3, [0.0, 2.0, 0.0], [0.0, 0.0, 0.0], 0.5, 1.33, modes),
        ("oblique", 2, [-1.3, 1.7], [0.2, -0.1], 0.6, 1.5, [None, 2]),
        ("oblique", 3, [1.1, 1.9, -0.7], [0.1, -0.2, 0.3], 0.45, 1.33, [None, 2]),
    ]
    impacts = [0.0, 1e-8, 0.3, 0.7, 0.95, 1 - 1e-3, 1 - 1e-6, 1.05, -1.0]
    for cls, D, light, gc, gr, ior, ms in scenes:
        v = direction_new(fsub(gc, light))
        perps = [fperp(v)]
        if D == 3:
            perps.append(fperp(v, rng))
        focus = fadd(gc, fscl(v, 2.2 * gr))
        side = fadd(fadd(gc, fscl(fperp(v), 1.6 * gr)), fscl(v, -0.8 * gr))
        queries = [
            ((focus if cls != "axis" else ([0.05, -1.0] if D == 2 else [0.05, -1.0, 0.03])),
             0.1 if cls == "axis" else 0.15, 0.5, 0.1),
            (gc, 3.0 * math.sqrt(fdot(fsub(light, gc), fsub(light, gc))), 0.3, 0.0),
            (side, 0.5, 2.0, 0.5),
        ]
        for K in ms:
            for pi, perp in enumerate(perps):
                for b in impacts:
                    if b == 0.0 and (pi > 0 or cls != "axis"):
                        continue  # exact normal incidence: the axis scenes' (0, -1)
                    if b == -1.0:
                        dirf = fscl(v, -1.0)  # away from the glass
                        sub_cls = "behind"
                    elif b == 0.0:
                        dirf = v
                        sub_cls = "normal"
                    else:
                        dirf = emission(light, gc, gr, b, perp)
                        sub_cls = ("miss" if b > 1 else "near-normal" if b < 1e-4
                                   else "near-grazing" if b > 0.99 else "hit")
                    add_trace(f"{cls}-{sub_cls}", D, light, gc, gr, ior, K, dirf, queries)


def main():
    rng = random.Random(20110)
    beam_cases(rng)
    trace_cases(rng)
    with open(OUT, "w") as f:
        for line in __doc__.splitlines():
            f.write(("# " + line).rstrip() + "\n")
        for row in ROWS:
            f.write(row + "\n")
    print(f"wrote {N_BEAM[0]} beam cases, {N_TRACE[0]} trace cases ({len(ROWS)} rows) to "
          f"{os.path.normpath(OUT)}", file=sys.stderr)


if __name__ == "__main__":
    main()
