//! Mergeable running statistics in `f64`: mean, variance and the standard error
//! of the variance, by Welford's update extended to the third and fourth central
//! moments (Terriberry 2007) and the pairwise merge of Chan, Golub & LeVeque
//! (1979) as generalised by Pébay (2008, SAND2008-6212, eqs. 2.1–2.4).
//!
//! Merging is exact in exact arithmetic, so statistics of parallel runs combine
//! to those of one sequential run up to rounding (a few ulp). To make results
//! independent of thread count, merge per-chunk statistics in chunk order (the
//! lab does).

/// Count, mean and central moment sums `M_p = Σ (x_i − x̄)^p`, `p = 2, 3, 4`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunningStats {
    n: u64,
    mean: f64,
    m2: f64,
    m3: f64,
    m4: f64,
}

impl RunningStats {
    /// No samples yet.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            n: 0,
            mean: 0.0,
            m2: 0.0,
            m3: 0.0,
            m4: 0.0,
        }
    }

    /// Adds one sample (Welford 1962; Terriberry's higher-moment update):
    /// with `δ = x − x̄`, `δ_n = δ/n`, `t = δ·δ_n·(n − 1)`:
    /// `M4 += t δ_n² (n² − 3n + 3) + 6 δ_n² M2 − 4 δ_n M3`,
    /// `M3 += t δ_n (n − 2) − 3 δ_n M2`, `M2 += t`, `x̄ += δ_n`.
    pub fn push(&mut self, x: f64) {
        let n1 = self.n as f64;
        self.n += 1;
        let n = self.n as f64;
        let delta = x - self.mean;
        let dn = delta / n;
        let dn2 = dn * dn;
        let t = delta * dn * n1;
        self.mean += dn;
        self.m4 += t * dn2 * (n * n - 3.0 * n + 3.0) + 6.0 * dn2 * self.m2 - 4.0 * dn * self.m3;
        self.m3 += t * dn * (n - 2.0) - 3.0 * dn * self.m2;
        self.m2 += t;
    }

    /// Combines `other` into `self` (Pébay 2008, eqs. 2.1–2.4 for `p ≤ 4`).
    pub fn merge(&mut self, other: &Self) {
        if other.n == 0 {
            return;
        }
        if self.n == 0 {
            *self = *other;
            return;
        }
        let (na, nb) = (self.n as f64, other.n as f64);
        let n = na + nb;
        let d = other.mean - self.mean;
        let d2 = d * d;
        let m2 = self.m2 + other.m2 + d2 * na * nb / n;
        let m3 = self.m3
            + other.m3
            + d * d2 * na * nb * (na - nb) / (n * n)
            + 3.0 * d * (na * other.m2 - nb * self.m2) / n;
        let m4 = self.m4
            + other.m4
            + d2 * d2 * na * nb * (na * na - na * nb + nb * nb) / (n * n * n)
            + 6.0 * d2 * (na * na * other.m2 + nb * nb * self.m2) / (n * n)
            + 4.0 * d * (na * other.m3 - nb * self.m3) / n;
        self.mean += d * nb / n;
        self.m2 = m2;
        self.m3 = m3;
        self.m4 = m4;
        self.n += other.n;
    }

    /// Number of samples.
    #[must_use]
    pub fn count(&self) -> u64 {
        self.n
    }

    /// Sample mean (0 with no samples).
    #[must_use]
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// Unbiased sample variance `s² = M2/(n − 1)` (0 with fewer than 2 samples).
    #[must_use]
    pub fn variance(&self) -> f64 {
        if self.n < 2 {
            0.0
        } else {
            self.m2 / (self.n as f64 - 1.0)
        }
    }

    /// Standard error of the mean, `√(s²/n)`.
    #[must_use]
    pub fn mean_std_error(&self) -> f64 {
        if self.n < 2 {
            return f64::INFINITY;
        }
        libm::sqrt(self.variance() / self.n as f64)
    }

    /// Standard error of the sample variance: `√(Var s²)` with
    /// `Var s² = μ₄/n − σ⁴(n − 3)/(n(n − 1))` (e.g. Cho et al. 2005), estimated
    /// with the plug-in moments `μ₄ ≈ M4/n` and `σ² ≈ M2/n`. Infinite with fewer
    /// than 4 samples.
    #[must_use]
    pub fn variance_std_error(&self) -> f64 {
        if self.n < 4 {
            return f64::INFINITY;
        }
        let n = self.n as f64;
        let s2 = self.m2 / n;
        let mu4 = self.m4 / n;
        libm::sqrt(((mu4 - s2 * s2 * (n - 3.0) / (n - 1.0)) / n).max(0.0))
    }

    /// Sample skewness-free fourth central moment `M4/n` (for diagnostics).
    #[must_use]
    pub fn fourth_moment(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.m4 / self.n as f64
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_pass(xs: &[f64]) -> (f64, f64, f64, f64) {
        let n = xs.len() as f64;
        // Neumaier-compensated sum, so the reference mean is exact to ~1 ulp.
        let (mut sum, mut comp) = (0.0f64, 0.0f64);
        for &x in xs {
            let t = sum + x;
            comp += if sum.abs() >= x.abs() {
                (sum - t) + x
            } else {
                (x - t) + sum
            };
            sum = t;
        }
        let mean = (sum + comp) / n;
        let m = |p: i32| xs.iter().map(|x| (x - mean).powi(p)).sum::<f64>();
        (mean, m(2), m(3), m(4))
    }

    #[test]
    fn push_and_merge_match_two_pass() {
        let mut s = 0x1234_5678u64;
        let xs: [f64; 1000] = core::array::from_fn(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            1e3 + ((s >> 11) as f64 / 9007199254740992.0).powi(3)
        });
        let (mean, m2, m3, m4) = two_pass(&xs);
        let mut all = RunningStats::new();
        xs.iter().for_each(|&x| all.push(x));
        for split in [0, 1, 7, 500, 999, 1000] {
            let mut a = RunningStats::new();
            let mut b = RunningStats::new();
            xs[..split].iter().for_each(|&x| a.push(x));
            xs[split..].iter().for_each(|&x| b.push(x));
            a.merge(&b);
            for st in [&a, &all] {
                assert_eq!(st.count(), 1000);
                assert!((st.mean - mean).abs() <= 1e-15 * mean, "{split}");
                assert!((st.m2 - m2).abs() <= 1e-11 * m2, "{split} {} {m2}", st.m2);
                assert!(
                    (st.m3 - m3).abs() <= 1e-9 * m2.powf(1.5),
                    "{split} {} {m3}",
                    st.m3
                );
                assert!((st.m4 - m4).abs() <= 1e-10 * m4, "{split}");
            }
        }
    }

    #[test]
    fn variance_standard_error_matches_normal_theory() {
        // For normal samples Var(s²) = 2σ⁴/(n − 1); a deterministic sample with
        // the four moments of a normal: ±1 at rate 1/2 has μ4 = 1, σ = 1:
        // Var s² ≈ (1 − (n − 3)/(n − 1))/n = 2/(n(n − 1)).
        let mut st = RunningStats::new();
        for i in 0..1000 {
            st.push(if i % 2 == 0 { 1.0 } else { -1.0 });
        }
        let n = 1000.0f64;
        let want = (2.0 / (n * (n - 1.0))).sqrt();
        assert!((st.variance_std_error() - want).abs() < 1e-9 * want);
        assert_eq!(RunningStats::new().variance(), 0.0);
        assert!(RunningStats::new().variance_std_error().is_infinite());
    }
}
