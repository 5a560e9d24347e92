//! Exact dyadic arithmetic for test references: a value `m·2^e` with a
//! big-integer mantissa (`num-bigint`). Sums, differences and products of
//! doubles are exact; square roots and quotients are truncated to a requested
//! number of significant bits. Independent of the kernel's double-double code.
#![allow(dead_code)]

use num_bigint::{BigInt, Sign};
use std::cmp::Ordering;

/// `m·2^e`.
#[derive(Clone, Debug)]
pub struct Dy {
    m: BigInt,
    e: i64,
}

/// Significant bits kept by [`Dy::sqrt`] and [`Dy::div`] (far more than any
/// cancellation in the references can consume: the largest is about
/// `2^-400` for a `1e-100` ball seen from `t ≈ 1`).
pub const BITS: u64 = 1400;

impl Dy {
    /// The exact value of a finite double.
    pub fn f(x: f64) -> Self {
        assert!(x.is_finite(), "Dy::f({x})");
        let bits = x.to_bits();
        let neg = bits >> 63 == 1;
        let ex = ((bits >> 52) & 0x7ff) as i64;
        let frac = bits & ((1u64 << 52) - 1);
        let (mant, e) = if ex == 0 {
            (frac, -1074)
        } else {
            (frac | (1u64 << 52), ex - 1075)
        };
        let m = BigInt::from(mant);
        Self {
            m: if neg { -m } else { m },
            e,
        }
    }

    /// Zero.
    pub fn zero() -> Self {
        Self {
            m: BigInt::from(0),
            e: 0,
        }
    }

    fn align(&self, o: &Self) -> (BigInt, BigInt, i64) {
        let e = self.e.min(o.e);
        (
            self.m.clone() << (self.e - e) as usize,
            o.m.clone() << (o.e - e) as usize,
            e,
        )
    }

    /// `self + o`, exact.
    pub fn add(&self, o: &Self) -> Self {
        let (a, b, e) = self.align(o);
        Self { m: a + b, e }
    }

    /// `self − o`, exact.
    pub fn sub(&self, o: &Self) -> Self {
        let (a, b, e) = self.align(o);
        Self { m: a - b, e }
    }

    /// `self · o`, exact.
    pub fn mul(&self, o: &Self) -> Self {
        Self {
            m: &self.m * &o.m,
            e: self.e + o.e,
        }
    }

    /// `−self`.
    pub fn neg(&self) -> Self {
        Self {
            m: -self.m.clone(),
            e: self.e,
        }
    }

    /// Sign: −1, 0 or 1.
    pub fn signum(&self) -> i32 {
        match self.m.sign() {
            Sign::Minus => -1,
            Sign::NoSign => 0,
            Sign::Plus => 1,
        }
    }

    /// `self` compared with `o`, exactly.
    pub fn cmp(&self, o: &Self) -> Ordering {
        let (a, b, _) = self.align(o);
        a.cmp(&b)
    }

    /// The smaller of the two.
    pub fn min(self, o: Self) -> Self {
        if self.cmp(&o) == Ordering::Greater {
            o
        } else {
            self
        }
    }

    /// The larger of the two.
    pub fn max(self, o: Self) -> Self {
        if self.cmp(&o) == Ordering::Less {
            o
        } else {
            self
        }
    }

    /// `√self` (`self ≥ 0`), truncated to at least [`BITS`] significant bits.
    pub fn sqrt(&self) -> Self {
        assert!(self.signum() >= 0);
        if self.signum() == 0 {
            return Self::zero();
        }
        let (mut m, mut e) = (self.m.clone(), self.e);
        if e % 2 != 0 {
            m <<= 1usize;
            e -= 1;
        }
        let k = (2 * BITS).saturating_sub(m.bits()) / 2 + 2;
        let r = (m << (2 * k) as usize).sqrt();
        Self {
            m: r,
            e: e / 2 - k as i64,
        }
    }

    /// `self / o` (`o ≠ 0`), truncated to at least [`BITS`] significant bits.
    pub fn div(&self, o: &Self) -> Self {
        assert!(o.signum() != 0);
        let k = (BITS + o.m.bits()).saturating_sub(self.m.bits()) + 2;
        Self {
            m: (self.m.clone() << k as usize) / &o.m,
            e: self.e - o.e - k as i64,
        }
    }

    /// The nearest double, to within one ulp (relative error `≤ 2⁻⁵²`).
    pub fn to_f64(&self) -> f64 {
        if self.signum() == 0 {
            return 0.0;
        }
        let neg = self.signum() < 0;
        let mag = self.m.magnitude();
        let n = mag.bits();
        let shift = n.saturating_sub(64);
        let top: u64 = (mag >> shift as usize).try_into().unwrap();
        let k = self.e + shift as i64;
        // top · 2^k in two steps so that neither factor over- or underflows.
        let k1 = k / 2;
        let v = top as f64 * 2f64.powi(k1 as i32) * 2f64.powi((k - k1) as i32);
        if neg {
            -v
        } else {
            v
        }
    }
}

/// `Σ a_j b_j`, exact.
pub fn dot<const D: usize>(a: &[Dy; D], b: &[Dy; D]) -> Dy {
    let mut s = Dy::zero();
    for j in 0..D {
        s = s.add(&a[j].mul(&b[j]));
    }
    s
}

/// `|got − want| / |want|`, with `want` exact (`|got|` if `want = 0`).
pub fn rel_err_exact(got: f64, want: &Dy) -> f64 {
    if want.signum() == 0 {
        return got.abs();
    }
    Dy::f(got).sub(want).div(want).to_f64().abs()
}

/// SplitMix64 (fixed seeds; the cases are deterministic).
pub struct Mix(pub u64);

impl Mix {
    pub fn u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform on `[0, 1)`.
    pub fn f(&mut self) -> f64 {
        (self.u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
    pub fn below(&mut self, n: u64) -> u64 {
        self.u64() % n
    }
    /// A unit vector (rejection from the cube, then normalised in f64).
    pub fn unit<const D: usize>(&mut self) -> [f64; D] {
        loop {
            let v: [f64; D] = core::array::from_fn(|_| self.range(-1.0, 1.0));
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|x| x / n);
            }
        }
    }
}

#[test]
fn dyadic_arithmetic_is_exact() {
    // (1 + 2⁻⁵²)² = 1 + 2⁻⁵¹ + 2⁻¹⁰⁴: not a double, but exact here.
    let x = Dy::f(1.0 + f64::EPSILON);
    let sq = x.mul(&x);
    let rest = sq.sub(&Dy::f(1.0)).sub(&Dy::f(2.0 * f64::EPSILON));
    assert_eq!(
        rest.cmp(&Dy::f(f64::EPSILON * f64::EPSILON)),
        Ordering::Equal
    );
    // √2 to 1400 bits: its square is within 2⁻¹³⁹⁰ of 2.
    let r = Dy::f(2.0).sqrt();
    let e = r.mul(&r).sub(&Dy::f(2.0));
    assert!(
        e.signum() <= 0
            && e.neg()
                .cmp(&Dy::f(2f64.powi(-1000)).mul(&Dy::f(2f64.powi(-390))))
                == Ordering::Less
    );
    assert_eq!(Dy::f(1.0).div(&Dy::f(3.0)).to_f64(), 1.0 / 3.0);
    assert_eq!(
        Dy::f(-1e-300)
            .mul(&Dy::f(1e-300))
            .div(&Dy::f(1e-300))
            .to_f64(),
        -1e-300
    );
    assert_eq!(Dy::f(5e-324).to_f64(), 5e-324);
    assert_eq!(Dy::f(-f64::MAX).to_f64(), -f64::MAX);
}

/// Every integer cell `m` with `lo ≤ m ≤ hi` componentwise (an odometer,
/// axis 0 fastest), for sums over the images a wrapped segment can reach.
pub fn for_each_cell<const D: usize>(lo: [i64; D], hi: [i64; D], mut f: impl FnMut(&[i64; D])) {
    let mut m = lo;
    loop {
        f(&m);
        let mut j = 0;
        loop {
            if j == D {
                return;
            }
            m[j] += 1;
            if m[j] <= hi[j] {
                break;
            }
            m[j] = lo[j];
            j += 1;
        }
    }
}
