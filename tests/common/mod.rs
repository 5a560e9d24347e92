//! Shared test references: adaptive Gauss–Kronrod quadrature (G7–K15, Piessens
//! et al., QUADPACK 1983; nodes and weights from Kronrod 1965 as tabulated there),
//! written here so the closed forms are checked against an independent method;
//! and a Kolmogorov–Smirnov test of uniformity at the suite's p < 1e-6 level.
#![allow(dead_code, clippy::excessive_precision)]

pub mod ao_scene;

/// Kronrod abscissae `x_k` (positive half; index 1, 3, 5 are the Gauss nodes).
const XK: [f64; 8] = [
    0.991455371120812639206854697526329,
    0.949107912342758524526189684047851,
    0.864864423359769072789712788640926,
    0.741531185599394439863864773280788,
    0.586087235467691130294144845693013,
    0.405845151377397166906606412076961,
    0.207784955007898467600689403773245,
    0.000000000000000000000000000000000,
];
/// Kronrod weights.
const WK: [f64; 8] = [
    0.022935322010529224963732008058970,
    0.063092092629978553290700663189204,
    0.104790010322250183839876322541518,
    0.140653259715525918745189590510238,
    0.169004726639267902826583426598550,
    0.190350578064785409913256402421014,
    0.204432940075298892414161999234649,
    0.209482141084727828012999174891714,
];
/// Gauss weights for nodes XK[1], XK[3], XK[5], XK[7].
const WG: [f64; 4] = [
    0.129484966168869693270611432679082,
    0.279705391489276667901467771423780,
    0.381830050505118944950369775488975,
    0.417959183673469387755102040816327,
];

/// One G7–K15 panel: (Kronrod estimate, error estimate). The error estimate is
/// QUADPACK's: `|K − G|` rescaled by `min(1, (200|K − G|/I_asc)^{3/2})` and
/// floored at the rounding level `50·ε·∫|f|`.
pub fn gk15(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut fv = [(0.0, 0.0); 7];
    let mut k = WK[7] * fc;
    let mut g = WG[3] * fc;
    let mut kabs = WK[7] * fc.abs();
    for i in 0..7 {
        let dx = h * XK[i];
        let (f1, f2) = (f(c - dx), f(c + dx));
        fv[i] = (f1, f2);
        k += WK[i] * (f1 + f2);
        kabs += WK[i] * (f1.abs() + f2.abs());
        if i % 2 == 1 {
            g += WG[i / 2] * (f1 + f2);
        }
    }
    let mean = 0.5 * k;
    let mut asc = WK[7] * (fc - mean).abs();
    for i in 0..7 {
        asc += WK[i] * ((fv[i].0 - mean).abs() + (fv[i].1 - mean).abs());
    }
    let (k, kabs, asc) = (k * h, kabs * h.abs(), asc * h.abs());
    let mut err = (k - g * h).abs();
    if asc != 0.0 && err != 0.0 {
        err = asc * (200.0 * err / asc).powf(1.5).min(1.0);
    }
    if kabs > f64::MIN_POSITIVE / (50.0 * f64::EPSILON) {
        err = err.max(50.0 * f64::EPSILON * kabs);
    }
    (k, err)
}

/// Adaptive G7–K15 on `[a, b]` (finite): bisects until each panel's error
/// estimate is `≤ max(rel, 100ε)·|K|` (or the panel is below `1e-300` in width
/// or 50 levels deep), and sums the accepted panels with Neumaier compensation.
pub fn integrate(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, rel: f64) -> f64 {
    if a == b {
        return 0.0;
    }
    let mut stack = vec![(a, b, 0u32)];
    let (mut sum, mut comp) = (0.0f64, 0.0f64);
    while let Some((lo, hi, depth)) = stack.pop() {
        let (k, e) = gk15(&mut f, lo, hi);
        if e <= rel.max(100.0 * f64::EPSILON) * k.abs()
            || depth >= 50
            || (hi - lo).abs() < 1e-300
            || (k == 0.0 && e == 0.0)
        {
            let t = sum + k;
            if sum.abs() >= k.abs() {
                comp += (sum - t) + k;
            } else {
                comp += (k - t) + sum;
            }
            sum = t;
        } else {
            let mid = 0.5 * (lo + hi);
            stack.push((lo, mid, depth + 1));
            stack.push((mid, hi, depth + 1));
        }
    }
    sum + comp
}

/// `|a − b| / |b|`, or `|a − b|` when `b == 0`.
pub fn rel_err(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        (a - b).abs()
    } else {
        ((a - b) / b).abs()
    }
}

/// Kolmogorov–Smirnov statistic of `u` against U[0, 1) and the test at
/// p < 1e-6: reject if `(√n + 0.12 + 0.11/√n)·D_n > 2.6934` (Stephens 1970's
/// finite-n form of the Kolmogorov limit `P(√n D > x) ≈ 2e^{−2x²}`;
/// `2e^{−2·2.6934²} = 1.0e-6`). One KS check.
pub fn assert_uniform_ks(what: &str, mut u: Vec<f64>) {
    assert!(
        u.iter().all(|x| (0.0..=1.0).contains(x)),
        "{what}: out of [0,1]"
    );
    u.sort_by(f64::total_cmp);
    let n = u.len() as f64;
    let d = u
        .iter()
        .enumerate()
        .map(|(i, &x)| (x - i as f64 / n).max((i as f64 + 1.0) / n - x))
        .fold(0.0f64, f64::max);
    let stat = (n.sqrt() + 0.12 + 0.11 / n.sqrt()) * d;
    println!("{what}: n = {n}, D = {d:.4}, scaled {stat:.3} (reject > 2.693)");
    assert!(
        stat <= 2.6934,
        "{what}: not uniform, KS D = {d} (scaled {stat})"
    );
}

#[test]
fn gk15_is_exact_for_degree_23_polynomials() {
    // ∫_{-1}^{1} x^p = 2/(p+1) for even p.
    for p in (0..=22).step_by(2) {
        let (k, _) = gk15(&mut |x: f64| x.powi(p), -1.0, 1.0);
        assert!((k - 2.0 / (p as f64 + 1.0)).abs() < 1e-15, "p = {p}: {k}");
    }
    let v = integrate(|x| (-x * x).exp(), -30.0, 30.0, 1e-15);
    assert!(rel_err(v, core::f64::consts::PI.sqrt()) < 1e-15, "{v}");
}

/// A xorshift64 generator for test inputs (Marsaglia 2003): deterministic,
/// independent of the kernel's own generators.
pub struct XorShift(pub u64);

impl XorShift {
    /// Uniform in `[0, 1)` with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform unit vector in 3D (`z` uniform, azimuth uniform).
    pub fn unit_vector(&mut self) -> [f64; 3] {
        let z = 2.0 * self.uniform() - 1.0;
        let t = std::f64::consts::TAU * self.uniform();
        let s = (1.0 - z * z).sqrt();
        [s * t.cos(), s * t.sin(), z]
    }
}
