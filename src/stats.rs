//! Mergeable running statistics in `f64`: mean, variance and the standard error
//! of the variance, by Welford's update extended to the third and fourth central
//! moments (Terriberry 2007) and the pairwise merge of Chan, Golub & LeVeque
//! (1979) as generalised by Pébay (2008, SAND2008-6212, eqs. 2.1–2.4).
//!
//! Merging is exact in exact arithmetic, so statistics of parallel runs combine
//! to those of one sequential run up to rounding (a few ulp). To make results
//! independent of thread count, merge per-chunk statistics in chunk order (the
//! lab does).

use crate::error::ParamError;

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
        crate::num::scalar::sqrt(self.variance() / self.n as f64)
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
        crate::num::scalar::sqrt(((mu4 - s2 * s2 * (n - 3.0) / (n - 1.0)) / n).max(0.0))
    }

    /// The state, to persist it (resume a run, merge shards computed
    /// elsewhere): `(n, [x̄, M2, M3, M4])`. [`RunningStats::from_parts`]
    /// rebuilds the same statistics, bit for bit.
    #[must_use]
    pub fn parts(&self) -> (u64, [f64; 4]) {
        (self.n, [self.mean, self.m2, self.m3, self.m4])
    }

    /// Statistics from exported state ([`RunningStats::parts`]): `n` samples
    /// with mean `x̄` and central moment sums `M2, M3, M4`, kept as they are.
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] naming `mean`, `m2`, `m3` or `m4` if it is NaN
    /// or ±∞; [`ParamError::OutOfRange`] naming `m2` or `m4` if it is negative
    /// (sums of even powers), or naming the first non-zero value if `n = 0`
    /// (no samples: every value must be 0).
    pub fn from_parts(n: u64, moments: [f64; 4]) -> Result<Self, ParamError> {
        const NAMES: [&str; 4] = ["mean", "m2", "m3", "m4"];
        if let Some(i) = moments.iter().position(|v| !v.is_finite()) {
            return Err(ParamError::NonFinite { name: NAMES[i] });
        }
        for i in [1, 3] {
            if moments[i] < 0.0 {
                return Err(ParamError::OutOfRange {
                    name: NAMES[i],
                    value: moments[i],
                    min: 0.0,
                    max: f64::MAX,
                });
            }
        }
        if n == 0 {
            if let Some(i) = moments.iter().position(|&v| v != 0.0) {
                return Err(ParamError::OutOfRange {
                    name: NAMES[i],
                    value: moments[i],
                    min: 0.0,
                    max: 0.0,
                });
            }
        }
        let [mean, m2, m3, m4] = moments;
        Ok(Self {
            n,
            mean,
            m2,
            m3,
            m4,
        })
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

/// A ratio `a/b` of two independent estimates with its standard error by the
/// first-order delta method, e.g. predicted over measured variance.
///
/// With `r = a/b` and independent `a`, `b` (standard errors `σ_a`, `σ_b`),
/// the first-order Taylor expansion of `a/b` about the means gives
/// `Var r ≈ σ_a²/b² + a²σ_b²/b⁴`, so
///
/// ```text
/// SE(r) = √(σ_a² + r²·σ_b²) / |b|    ( = |r|·√((σ_a/a)² + (σ_b/b)²) for a ≠ 0 )
/// ```
///
/// (the delta method: Casella & Berger, *Statistical Inference*, 2nd ed.,
/// §5.5.4; Kendall & Stuart, *The Advanced Theory of Statistics* I, §10.6).
/// It is accurate while the relative errors are small (`σ_b/|b| ≲ 0.1`);
/// beyond that the ratio's distribution is skewed and the SE understates
/// the upper tail. Evaluated with `hypot`, so no intermediate overflows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ratio {
    /// `a/b`.
    pub value: f64,
    /// `√(σ_a² + (a/b)²·σ_b²)/|b|`.
    pub std_error: f64,
}

impl Ratio {
    /// The ratio `num/den` of two independent estimates with standard errors
    /// `num_se`, `den_se` (see the type's documentation for the formula).
    ///
    /// # Errors
    /// [`ParamError::NonFinite`] naming `num`, `num_se`, `den` or `den_se` if
    /// it is NaN or ±∞ (an infinite standard error, as
    /// [`RunningStats::variance_std_error`] reports for fewer than 4 samples,
    /// has no ratio error either), or naming `num/den` if the ratio or its
    /// standard error overflows; [`ParamError::OutOfRange`] naming `num_se` or
    /// `den_se` if negative, or `den` if it is 0.
    pub fn new(num: f64, num_se: f64, den: f64, den_se: f64) -> Result<Self, ParamError> {
        for (name, v) in [
            ("num", num),
            ("num_se", num_se),
            ("den", den),
            ("den_se", den_se),
        ] {
            if !v.is_finite() {
                return Err(ParamError::NonFinite { name });
            }
        }
        for (name, v) in [("num_se", num_se), ("den_se", den_se)] {
            if v < 0.0 {
                return Err(ParamError::OutOfRange {
                    name,
                    value: v,
                    min: 0.0,
                    max: f64::MAX,
                });
            }
        }
        if den == 0.0 {
            return Err(ParamError::OutOfRange {
                name: "den",
                value: den,
                min: f64::MIN_POSITIVE,
                max: f64::MAX,
            });
        }
        let value = num / den;
        let std_error = libm::hypot(num_se, value * den_se) / den.abs();
        if !value.is_finite() || !std_error.is_finite() {
            return Err(ParamError::NonFinite { name: "num/den" });
        }
        Ok(Self { value, std_error })
    }
}

/// The upper-tail standard normal quantile: the `z ≥ 0` with `P(Z > z) = p`,
/// `p ∈ (0, 1/2]`, found by bisection on `Q(z) = ½·erfc(z/√2)` (monotone)
/// over `[0, 40]`; 200 halvings reach `f64` resolution. `Q` is evaluated as
/// `½·erfcx(x)·e^{−x²}` ([`crate::special::erfcx`]), accurate in the far
/// tail. Used for Bonferroni limits (`z` for a false-alarm rate `p`).
#[must_use]
pub fn normal_upper_quantile(p: f64) -> f64 {
    let q = |z: f64| {
        let x = z / core::f64::consts::SQRT_2;
        0.5 * crate::special::erfcx(x) * libm::exp(-x * x)
    };
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if q(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The upper-tail χ² quantile: the `q` with `P(χ²_df > q) ≈ p`, by the
/// Wilson–Hilferty approximation (Wilson & Hilferty 1931: `(χ²/df)^{1/3}` is
/// nearly normal with mean `1 − a` and variance `a`, `a = 2/(9·df)`), so
/// `q = df·(1 − a + z·√a)³` with `z` = [`normal_upper_quantile`]`(p)`.
/// Against the exact quantile (40-digit inversion of the regularised
/// incomplete gamma function) at `p = 10⁻⁶` it is high by 15 % at `df = 1`,
/// 2.3 % at `df = 10`, 0.16 % at `df = 100` and 0.007 % at `df = 1000`, and
/// by less at `p = 10⁻³`. It errs high for these `df` and `p`, so a rejection
/// limit built on it alarms less often than `p`. `df > 0`, `p ∈ (0, 1/2]`.
#[must_use]
pub fn chi2_upper_quantile(df: f64, p: f64) -> f64 {
    let a = 2.0 / (9.0 * df);
    let c = 1.0 - a + normal_upper_quantile(p) * crate::num::scalar::sqrt(a);
    df * c * c * c
}

/// Chi-square quantile for `df` degrees of freedom at false-alarm probability
/// 10⁻⁶, the suite's rule for distribution checks (`tests/README.md`).
#[cfg(test)]
pub(crate) fn chi2_limit(df: f64) -> f64 {
    chi2_upper_quantile(df, 1e-6)
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
    fn normal_upper_quantile_known_values() {
        // Φ⁻¹(0.975) = 1.959963985; Φ⁻¹(1 − 10⁻⁶) = 4.753424309.
        assert!((normal_upper_quantile(0.025) - 1.959_963_985).abs() < 1e-8);
        assert!((normal_upper_quantile(1e-6) - 4.753_424_309).abs() < 1e-8);
        assert!(normal_upper_quantile(0.5).abs() < 1e-12);
    }

    /// Against exact χ² quantiles (the regularised upper incomplete gamma
    /// function inverted to 40 digits with mpmath 1.3): within the stated
    /// relative errors, and never below the exact quantile.
    #[test]
    fn chi2_upper_quantile_against_exact_quantiles() {
        // (df, p, exact quantile, stated relative error bound)
        let cases = [
            (1.0, 1e-6, 23.928_126_976_934_83, 0.15),
            (10.0, 1e-6, 46.863_046_846_784_38, 0.024),
            (63.0, 1e-6, 131.369_702_051_686_8, 0.003),
            (100.0, 1e-6, 182.126_777_119_547_6, 0.0016),
            (1000.0, 1e-6, 1_227.152_421_187_576, 7e-5),
            (10.0, 1e-3, 29.588_298_445_074_42, 0.006),
            (100.0, 1e-3, 149.449_252_779_038_7, 4e-4),
        ];
        for (df, p, exact, bound) in cases {
            let q = chi2_upper_quantile(df, p);
            let rel = (q - exact) / exact;
            assert!(
                (0.0..bound).contains(&rel),
                "df {df} p {p}: {q} vs {exact} ({rel:e})"
            );
        }
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

    /// SplitMix64 (Steele, Lea & Flood 2014) uniforms in (0, 1], standard
    /// normals by Box–Muller and unit exponentials by inversion: a test-local
    /// generator, independent of the crate's.
    struct Gen(u64);

    impl Gen {
        fn uniform(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / 9_007_199_254_740_992.0
                + 1.0 / 18_014_398_509_481_984.0
        }
        fn normal(&mut self) -> f64 {
            let (a, b) = (self.uniform(), self.uniform());
            crate::num::scalar::sqrt(-2.0 * libm::log(a)) * libm::cos(core::f64::consts::TAU * b)
        }
        fn exponential(&mut self) -> f64 {
            -libm::log(self.uniform())
        }
    }

    /// Mean, variance and the standard error of each, from power sums about a
    /// centre `c` (streamed; no `RunningStats`, so the reference is independent).
    #[derive(Default)]
    struct Sums {
        n: f64,
        c: f64,
        s: [f64; 4],
    }

    impl Sums {
        fn new(c: f64) -> Self {
            Self {
                c,
                ..Self::default()
            }
        }
        fn push(&mut self, x: f64) {
            let d = x - self.c;
            self.n += 1.0;
            self.s[0] += d;
            self.s[1] += d * d;
            self.s[2] += d * d * d;
            self.s[3] += d * d * d * d;
        }
        /// `(mean, SE of the mean, variance m₂, SE of m₂ = √((m₄ − m₂²)/n))`.
        fn summary(&self) -> (f64, f64, f64, f64) {
            let n = self.n;
            let [a1, a2, a3, a4] = self.s.map(|v| v / n);
            let m2 = a2 - a1 * a1;
            let m4 = a4 - 4.0 * a1 * a3 + 6.0 * a1 * a1 * a2 - 3.0 * a1.powi(4);
            (
                self.c + a1,
                crate::num::scalar::sqrt(m2 / n),
                m2,
                crate::num::scalar::sqrt((m4 - m2 * m2) / n),
            )
        }
    }

    /// `variance_std_error()` against simulation, for normal (`μ₄ = 3σ⁴`) and
    /// exponential (`μ₄ = 9σ⁴`) data, `σ² = 1`, samples of size n = 8 (100 000
    /// samples) and n = 50 (20 000 samples). Three z-checks per case (12 in all, |z| ≤ 5):
    ///
    /// 0. `E s² = σ²` (`variance()` is unbiased; SE from the spread);
    /// 1. the spread: the empirical variance of `s²` over the samples equals the
    ///    exact `Var s² = μ₄/n − σ⁴(n − 3)/(n(n − 1))` (SE of an empirical
    ///    variance: `√((m₄ − m₂²)/R)` from the fourth moment of the `s²` values);
    /// 2. the estimator: the mean of `variance_std_error()²` equals its exact
    ///    expectation. It is a plug-in (`μ₄ ≈ m₄ = M4/n`, `σ⁴ ≈ m₂²`), so
    ///    `E[V̂] = E[m₄]/n − E[m₂²](n − 3)/(n(n − 1))` with (Kendall & Stuart,
    ///    *Advanced Theory of Statistics* I, §12.3; exact for i.i.d. data)
    ///    `E[m₄] = (n−1)(n²−3n+3)/n³·μ₄ + 3(n−1)(2n−3)/n³·σ⁴` and
    ///    `E[m₂²] = (n−1)²/n³·μ₄ + (n−1)(n²−2n+3)/n³·σ⁴`. (So the plug-in SE is
    ///    biased low at small n: `E[V̂]/Var s²` is 0.94 for normal data at
    ///    n = 50; check 1 and 2 together pin both numbers.)
    ///
    /// The printed "detects" figure is `5·SE/exact` of check 2, the smallest
    /// relative error of `E[V̂]` surely caught: 2.1 % (normal, n = 8), 1.9 %
    /// (normal, n = 50), 12 % and 6.5 % (exponential). Writing `n` for `n − 1` in
    /// `(n − 3)/(n − 1)` shifts `E[V̂]` by 5.5 % at n = 8 (normal).
    #[test]
    fn variance_standard_error_matches_simulation() {
        let mut g = Gen(0x5EED_0F5E);
        for (name, mu4) in [("normal", 3.0), ("exponential", 9.0)] {
            // More samples at n = 8, where the (n − 3)/(n − 1) term matters most.
            for (n, reps) in [(8usize, 100_000usize), (50, 20_000)] {
                let nf = n as f64;
                let var_s2 = mu4 / nf - (nf - 3.0) / (nf * (nf - 1.0));
                let n3 = nf * nf * nf;
                let e_m4 = (nf - 1.0) * (nf * nf - 3.0 * nf + 3.0) / n3 * mu4
                    + 3.0 * (nf - 1.0) * (2.0 * nf - 3.0) / n3;
                let e_m2sq = (nf - 1.0) * (nf - 1.0) / n3 * mu4
                    + (nf - 1.0) * (nf * nf - 2.0 * nf + 3.0) / n3;
                let e_vhat = e_m4 / nf - e_m2sq * (nf - 3.0) / (nf * (nf - 1.0));
                let mut spread = Sums::new(1.0);
                let mut est = Sums::new(e_vhat);
                for _ in 0..reps {
                    let mut st = RunningStats::new();
                    for _ in 0..n {
                        st.push(if mu4 == 3.0 {
                            g.normal()
                        } else {
                            g.exponential()
                        });
                    }
                    spread.push(st.variance());
                    let se = st.variance_std_error();
                    est.push(se * se);
                }
                let (mean_s2, se_mean_s2, var_emp, se_var) = spread.summary();
                let (mean_v, se_v, _, _) = est.summary();
                let z_mean = (mean_s2 - 1.0) / se_mean_s2;
                let z_spread = (var_emp - var_s2) / se_var;
                let z_est = (mean_v - e_vhat) / se_v;
                std::println!(
                    "{name} n = {n}: E s² {mean_s2:.4} (z {z_mean:+.2}); Var s² {var_emp:.5} vs \
                     {var_s2:.5} (z {z_spread:+.2}); E V̂ {mean_v:.5} vs {e_vhat:.5} \
                     (z {z_est:+.2}, detects ≥ {:.2}%)",
                    500.0 * se_v / e_vhat
                );
                assert!(z_mean.abs() <= 5.0, "{name} n = {n}: E s² z = {z_mean}");
                assert!(
                    z_spread.abs() <= 5.0,
                    "{name} n = {n}: spread z = {z_spread}"
                );
                assert!(
                    z_est.abs() <= 5.0,
                    "{name} n = {n}: variance_std_error z = {z_est}"
                );
            }
        }
    }

    /// Merging parts of different sizes, locations and scales (not copies of
    /// one part), in sequence and as a tree, matches one pass over all the data
    /// and a two-pass reference.
    #[test]
    fn merge_of_different_parts_matches_one_pass() {
        let mut g = Gen(42);
        let parts: [&dyn Fn(&mut Gen) -> f64; 4] = [
            &|g| 1e3 + g.normal(),
            &|g| 1e-3 * g.exponential(),
            &|g| -50.0 + 100.0 * g.uniform(),
            &|g| 7.0 + 0.01 * g.normal(),
        ];
        let sizes = [1usize, 37, 500, 462];
        let mut data = [0.0f64; 1000];
        let mut k = 0;
        let mut stats = [RunningStats::new(); 4];
        for (p, (&f, &m)) in parts.iter().zip(&sizes).enumerate() {
            for _ in 0..m {
                data[k] = f(&mut g);
                stats[p].push(data[k]);
                k += 1;
            }
        }
        let mut one = RunningStats::new();
        data.iter().for_each(|&x| one.push(x));
        let mut seq = RunningStats::new();
        stats.iter().for_each(|s| seq.merge(s));
        let (mut left, mut right) = (stats[0], stats[2]);
        left.merge(&stats[1]);
        right.merge(&stats[3]);
        left.merge(&right);
        let (mean, m2, m3, m4) = two_pass(&data);
        for (what, st) in [
            ("one pass", &one),
            ("sequential merge", &seq),
            ("tree merge", &left),
        ] {
            assert_eq!(st.count(), 1000, "{what}");
            assert!(
                (st.mean - mean).abs() <= 1e-13 * mean.abs(),
                "{what}: mean {} vs {mean}",
                st.mean
            );
            assert!(
                (st.m2 - m2).abs() <= 1e-12 * m2,
                "{what}: M2 {} vs {m2}",
                st.m2
            );
            assert!(
                (st.m3 - m3).abs() <= 1e-11 * m2.powf(1.5),
                "{what}: M3 {} vs {m3}",
                st.m3
            );
            assert!(
                (st.m4 - m4).abs() <= 1e-11 * m4,
                "{what}: M4 {} vs {m4}",
                st.m4
            );
        }
    }

    #[test]
    fn variance_standard_error_matches_normal_theory() {
        // A deterministic pin of the arithmetic (not a test of the formula; that
        // is `variance_standard_error_matches_simulation`).
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
