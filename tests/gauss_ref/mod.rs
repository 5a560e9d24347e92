//! Independent high-precision references for the world-space Gaussian
//! `A·e^{−|x − c|²/2σ²}` (used by `tests/world_gaussian.rs`), after
//! `ref_free` in `tests/integrand_gaussian.rs`, generalised to any peak `A`
//! and made robust for far-away centres and origins:
//!
//! * the line's geometry (foot parameter `t_c = −q·ω/a`, squared distance
//!   `ρ² = |q|² − (q·ω)²/a`, the exponent of the reference point) is formed
//!   in exact dyadic arithmetic (`tests/exact`) from the given doubles;
//! * the segment integral is adaptive Gauss–Kronrod (`tests/common`) in the
//!   offset `τ = t − t_r` from the point `t_r` of the segment nearest to the
//!   centre, with the exponent difference `a·τ(2s_r + τ)/2σ²` in
//!   double-double, so the integrand is `≤ 1` and the far tail keeps its
//!   relative accuracy;
//! * `e^{−E}` of the reference point is evaluated to about `2⁻¹⁰⁰` relative
//!   (argument reduction by `k ln 2` in double-double, Taylor series in
//!   double-double) and the result rounded once, so values down to `1e-300`
//!   and below are relatively accurate.
//!
//! The double-double arithmetic here is written for the tests (error-free
//! transformations with `f64::mul_add`), independent of the crate's `Dd`.
#![allow(
    dead_code,
    clippy::excessive_precision,
    clippy::neg_cmp_op_on_partial_ord
)]

use crate::common::integrate;
use crate::exact::{self, Dy};
use std::cmp::Ordering;

/// `hi + lo`, `|lo| ≤ ulp(hi)/2`.
#[derive(Clone, Copy, Debug)]
pub struct D2 {
    pub hi: f64,
    pub lo: f64,
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl D2 {
    pub const ONE: D2 = D2 { hi: 1.0, lo: 0.0 };

    pub fn new(x: f64) -> D2 {
        D2 { hi: x, lo: 0.0 }
    }

    /// The exact product of two doubles.
    pub fn prod(a: f64, b: f64) -> D2 {
        let (hi, lo) = two_prod(a, b);
        D2 { hi, lo }
    }

    /// An exact dyadic rounded to double-double (finite values only).
    pub fn from_dy(x: &Dy) -> D2 {
        let hi = x.to_f64();
        if !hi.is_finite() {
            return D2::new(hi);
        }
        let lo = x.sub(&Dy::f(hi)).to_f64();
        let (hi, lo) = two_sum(hi, lo);
        D2 { hi, lo }
    }

    pub fn neg(self) -> D2 {
        D2 {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    pub fn add(self, o: D2) -> D2 {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = fast_two_sum(s, e + t);
        let (hi, lo) = fast_two_sum(s, e + f);
        D2 { hi, lo }
    }

    pub fn sub(self, o: D2) -> D2 {
        self.add(o.neg())
    }

    pub fn mul(self, o: D2) -> D2 {
        let (p, e) = two_prod(self.hi, o.hi);
        let e = e + (self.hi * o.lo + self.lo * o.hi);
        let (hi, lo) = fast_two_sum(p, e);
        D2 { hi, lo }
    }

    pub fn mul_f64(self, x: f64) -> D2 {
        self.mul(D2::new(x))
    }

    pub fn div(self, o: D2) -> D2 {
        let q1 = self.hi / o.hi;
        if !q1.is_finite() || q1 == 0.0 {
            return D2::new(q1);
        }
        let r = self.sub(o.mul_f64(q1));
        let q2 = r.hi / o.hi;
        let r = r.sub(o.mul_f64(q2));
        let q3 = r.hi / o.hi;
        let (s, e) = fast_two_sum(q1, q2);
        let (hi, lo) = two_sum(s, e + q3);
        D2 { hi, lo }
    }

    pub fn sqrt(self) -> D2 {
        if self.hi <= 0.0 {
            return D2::new(self.hi.sqrt());
        }
        let s = self.hi.sqrt();
        let r = self.sub(D2::prod(s, s));
        let (hi, lo) = fast_two_sum(s, r.hi / (2.0 * s));
        D2 { hi, lo }
    }

    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
}

/// `ln 2` as a double-double (error ≈ 1e-33).
const LN2: D2 = D2 {
    hi: std::f64::consts::LN_2,
    lo: 2.319046813846299558e-17,
};

/// `2π` as a double-double.
const TAU: D2 = D2 {
    hi: std::f64::consts::TAU,
    lo: 2.4492935982947064e-16,
};

/// `x·2ⁿ` (exact unless the result is subnormal).
fn ldexp(mut x: f64, mut n: i64) -> f64 {
    while n > 1000 {
        x *= 2f64.powi(1000);
        n -= 1000;
    }
    while n < -1000 {
        x *= 2f64.powi(-1000);
        n += 1000;
    }
    x * 2f64.powi(n as i32)
}

/// `(e^{−E}` as `m·2^{−k}`, `m` a double-double in `[0.7, 1.5]`): reduction
/// `E = k ln 2 + r`, `|r| ≤ 0.35`, then the Taylor series of `e^{−r}`.
fn exp_neg_parts(e: D2) -> (D2, i64) {
    let k = (e.hi / LN2.hi).round();
    let r = e.sub(D2::prod(k, LN2.hi)).sub(D2::prod(k, LN2.lo));
    let mr = r.neg();
    let mut term = D2::ONE;
    let mut sum = D2::ONE;
    for n in 1..40 {
        term = term.mul(mr).div(D2::new(n as f64));
        sum = sum.add(term);
        if term.hi.abs() < 1e-36 {
            break;
        }
    }
    (sum, k as i64)
}

/// `factor·e^{−E}` rounded once (about `2⁻¹⁰⁰` relative before the final
/// rounding; no intermediate over- or underflow). `E = ∞` gives 0.
pub fn exp_neg_scaled(factor: D2, e: D2) -> f64 {
    if e.hi == f64::INFINITY || factor.hi == 0.0 {
        return 0.0;
    }
    let (m, k) = exp_neg_parts(e);
    let p = factor.mul(m);
    // Scale the leading part first so that the result is rounded once when
    // it is normal.
    let (hi, lo) = (ldexp(p.hi, -k), ldexp(p.lo, -k));
    hi + lo
}

/// `e^{−τ}` (`τ ≥ 0` a double-double).
pub fn exp_neg(tau: D2) -> f64 {
    exp_neg_scaled(D2::ONE, tau)
}

/// `1 − e^{−τ}` without cancellation: the alternating series for `τ < 1/2`,
/// else `1 − m·2^{−k}` in double-double.
pub fn one_minus_exp_neg(tau: D2) -> f64 {
    if tau.hi < 0.5 {
        let mut term = tau;
        let mut sum = tau;
        for n in 2..60 {
            term = term.mul(tau.neg()).div(D2::new(n as f64));
            sum = sum.add(term);
            if term.hi.abs() < 1e-36 * sum.hi.abs() {
                break;
            }
        }
        sum.to_f64()
    } else {
        let (m, k) = exp_neg_parts(tau);
        let t = D2 {
            hi: ldexp(m.hi, -k),
            lo: ldexp(m.lo, -k),
        };
        D2::ONE.sub(t).to_f64()
    }
}

/// An isotropic Gaussian `A·e^{−|x − c|²/2σ²}`.
#[derive(Clone, Copy, Debug)]
pub struct Gauss<const D: usize> {
    pub centre: [f64; D],
    pub sigma: f64,
    pub peak: D2,
}

/// `(2πσ²)^{−D/2}` in double-double.
pub fn normalisation(d: usize, sigma: f64) -> D2 {
    let s2 = TAU.mul(D2::prod(sigma, sigma));
    if d == 2 {
        D2::ONE.div(s2)
    } else {
        D2::ONE.div(s2.mul(s2.sqrt()))
    }
}

impl<const D: usize> Gauss<D> {
    /// The normalised density (`A = (2πσ²)^{−D/2}`).
    pub fn normalised(centre: [f64; D], sigma: f64) -> Self {
        Gauss {
            centre,
            sigma,
            peak: normalisation(D, sigma),
        }
    }

    /// Peak `A`.
    pub fn with_peak(centre: [f64; D], sigma: f64, peak: f64) -> Self {
        Gauss {
            centre,
            sigma,
            peak: D2::new(peak),
        }
    }

    /// `2σ²`, exact.
    fn two_s2(&self) -> Dy {
        let s = Dy::f(self.sigma);
        let s2 = s.mul(&s);
        s2.add(&s2)
    }

    /// `F(x)`, the exponent exact.
    pub fn value(&self, x: &[f64; D]) -> f64 {
        let q: [Dy; D] = core::array::from_fn(|j| Dy::f(x[j]).sub(&Dy::f(self.centre[j])));
        let e = exact::dot(&q, &q).div(&self.two_s2());
        exp_neg_scaled(self.peak, D2::from_dy(&e))
    }

    /// `∫_{−∞}^{∞} F(o + tω) dt = A σ √(2π/a) e^{−ρ²/2σ²}`, `ρ²` exact.
    pub fn line(&self, o: &[f64; D], w: &[f64; D]) -> f64 {
        let geo = Geometry::new(self, o, w);
        let e = geo.rho2.div(&self.two_s2());
        let f = self
            .peak
            .mul(D2::new(self.sigma))
            .mul(TAU.div(geo.a2).sqrt());
        exp_neg_scaled(f, D2::from_dy(&e))
    }

    /// `∫_{t0}^{t1} F(o + tω) dt` for `t0 ≤ t1` (either may be infinite), by
    /// adaptive Gauss–Kronrod around the point of the segment nearest to the
    /// centre (see the module docs).
    pub fn segment(&self, o: &[f64; D], w: &[f64; D], t0: f64, t1: f64) -> f64 {
        assert!(t0 <= t1, "reference needs t0 ≤ t1");
        if t0 == t1 {
            return 0.0;
        }
        let geo = Geometry::new(self, o, w);
        // t_r: the point of [t0, t1] nearest to the foot t_c.
        let tr = if t0.is_finite() && Dy::f(t0).cmp(&geo.tc) == Ordering::Greater {
            Dy::f(t0)
        } else if t1.is_finite() && Dy::f(t1).cmp(&geo.tc) == Ordering::Less {
            Dy::f(t1)
        } else {
            geo.tc.clone()
        };
        let sr = tr.sub(&geo.tc);
        let two_s2 = self.two_s2();
        let er = geo.rho2.add(&geo.a.mul(&sr).mul(&sr)).div(&two_s2);
        let off = |t: f64| -> f64 {
            if t.is_finite() {
                Dy::f(t).sub(&tr).to_f64()
            } else {
                t
            }
        };
        let (lo, hi) = (off(t0), off(t1));
        // Exponent difference ΔE(τ) = a·τ(2s_r + τ)/2σ² in double-double.
        let a = geo.a2;
        let s2 = D2::from_dy(&sr);
        let ts2 = D2::from_dy(&two_s2);
        let g = |tau: f64| -> f64 {
            let de = a
                .mul(D2::new(tau))
                .mul(s2.add(s2).add(D2::new(tau)))
                .div(ts2);
            (-de.hi).exp() * (1.0 - de.lo)
        };
        // Distance from t_r (away from the foot) at which ΔE reaches `de`.
        let sc2 = self.sigma * self.sigma / a.hi;
        let srf = s2.hi.abs();
        let reach = |de: f64| 2.0 * sc2 * de / (srf + (srf * srf + 2.0 * sc2 * de).sqrt());
        let w = reach(80.0);
        let (lo, hi) = (lo.max(-w), hi.min(w));
        if !(lo < hi) {
            return 0.0;
        }
        let mut br = vec![lo, hi];
        if lo < 0.0 && hi > 0.0 {
            br.push(0.0);
        }
        for de in [
            1.0 / 64.0,
            0.125,
            0.5,
            1.0,
            2.0,
            4.0,
            8.0,
            16.0,
            32.0,
            48.0,
            64.0,
        ] {
            let x = reach(de);
            for y in [x, -x] {
                if y > lo && y < hi {
                    br.push(y);
                }
            }
        }
        br.sort_by(f64::total_cmp);
        br.dedup();
        let (mut sum, mut comp) = (0.0f64, 0.0f64);
        for k in 0..br.len() - 1 {
            let v = integrate(g, br[k], br[k + 1], 1e-16);
            let (s, e) = two_sum(sum, v);
            sum = s;
            comp += e;
        }
        let i = D2 { hi: sum, lo: comp };
        exp_neg_scaled(self.peak.mul(i), D2::from_dy(&er))
    }
}

/// The line `o + tω` relative to the centre, exact.
struct Geometry {
    /// `a = |ω|²`.
    a: Dy,
    a2: D2,
    /// `t_c = −q·ω/a`.
    tc: Dy,
    /// `ρ² = |q|² − (q·ω)²/a`.
    rho2: Dy,
}

impl Geometry {
    fn new<const D: usize>(g: &Gauss<D>, o: &[f64; D], w: &[f64; D]) -> Self {
        let q: [Dy; D] = core::array::from_fn(|j| Dy::f(o[j]).sub(&Dy::f(g.centre[j])));
        let wd: [Dy; D] = core::array::from_fn(|j| Dy::f(w[j]));
        let a = exact::dot(&wd, &wd);
        let b = exact::dot(&q, &wd);
        let qq = exact::dot(&q, &q);
        let tc = b.neg().div(&a);
        let rho2 = qq.mul(&a).sub(&b.mul(&b)).div(&a);
        Geometry {
            a2: D2::from_dy(&a),
            a,
            tc,
            rho2,
        }
    }
}
