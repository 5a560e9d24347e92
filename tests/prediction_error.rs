//! The standard error of a spectral variance prediction
//! (`spectrum::PredictionStats`, `Prediction::std_error`) and the
//! delta-method ratio (`stats::Ratio`).
//!
//! The prediction over `R` realisations is `V̂ = (1/R) Σ_r V_r` with
//! `V_r = (1/N) Σ_{ν≠0} w(ν)·|F_r(ν)|²/N`, and its stated standard error is
//! `SE = √(Σ_r (V_r − V̂)²/(R(R − 1)))`.
//!
//! * Exact checks (no statistics): the SE against the same formula evaluated
//!   here from the stored `V_r` (relative 1e-12); merging any split of the
//!   realisations, in any order, against one accumulator (bit for bit);
//!   `R = 0, 1, 2`; power-of-two rescaling of the weights (bit for bit);
//!   persistence; every error names its parameter.
//! * Coverage (statistical): `M` independent experiments of `R` realisations
//!   each (different seeds), 2D random and jittered points and a Gaussian
//!   integrand, whose expected prediction is known in closed form
//!   (`E[N·P(ν)] = 1` for random points, `1 − Π sinc²(ν_a/n_a)` for jitter).
//!   Per case three checks:
//!   1. the mean of the `M` stated SEs against the standard deviation `ŝ` of
//!      the `M` predictions: `(M − 1)·ŝ²/σ² ~ χ²_{M−1}` for normal
//!      predictions, so `mean SE/ŝ` must lie in
//!      `[√((M − 1)/χ²_{hi}), √((M − 1)/χ²_{lo})]` with the two-sided
//!      `α = 1e-6` quantiles (the suite's rule for distribution checks,
//!      tests/README.md);
//!   2. the number of experiments with `|V̂ − E V̂| ≤ 2·SE` against the
//!      binomial with `p₀ = P(|t_{R−1}| ≤ 2)` (the exact coverage for normal
//!      `V_r`; 0.946 at `R = 32`, 0.949 at `R = 64`), two-sided `α = 1e-6`;
//!   3. the mean of the `M` predictions against the closed form, `|z| ≤ 5`
//!      (`α = 5.7e-7`; it tests the expected value the coverage uses).
//!
//!   What the χ² and binomial bounds leave out, and why it is small: the
//!   `V_r` are skewed (a weighted sum of nearly exponential `|F|²/N`), which
//!   moves the coverage of `±2·SE` by about 1 % and `E[SE]` below `σ` by
//!   about `1/(4R)` (0.8 % at `R = 32`); both are well inside the bounds
//!   (the binomial band at `M = 400` is ±6 %, the ratio band ±25 %). A
//!   broken SE is far outside them: dividing by `R` instead of `√R` makes the
//!   ratio `1/√R ≈ 0.18` and the coverage about 27 %.
//!
//! False alarms: the default suite runs 2 cases × 3 checks,
//! `2 × (1e-6 + 1e-6 + 5.7e-7) ≈ 5.1e-6`; the release test 4 cases,
//! `1.0e-5` (union bound). The release run:
//! `cargo test --release -p linesample --test prediction_error -- --ignored --nocapture`.

use linesample::integrand::{Gaussian, Integrand};
use linesample::pattern::{Jittered, Pattern, Random};
use linesample::spectrum::{
    jittered_expected, AmplitudeView, Dft, Grid, Periodogram, PredictionStats,
};
use linesample::stats::normal_upper_quantile;
use linesample::stats::Ratio;
use linesample::{ParamError, Seed, SpectrumError};

fn gauss() -> Gaussian<2> {
    Gaussian::<2>::new([0.37, 0.61], 0.07).unwrap()
}

/// One realisation's transform.
struct Realiser<const D: usize> {
    dft: Dft<D, Vec<f64>>,
    pts: Vec<[f32; D]>,
    scratch: Vec<f64>,
}

impl<const D: usize> Realiser<D> {
    fn new(g: Grid<D>, n: usize) -> Self {
        Realiser {
            dft: Dft::new_vec(g),
            pts: vec![[0.0f32; D]; n],
            scratch: vec![0.0; 64 * Dft::<D, Vec<f64>>::points_scratch_per_sample(g)],
        }
    }
    fn run(&mut self, p: &dyn Pattern<D>, seed: Seed, r: u64) -> &Dft<D, Vec<f64>> {
        p.fill(seed.realization(r), &mut self.pts).unwrap();
        self.dft.clear();
        self.dft.add_points(&self.pts, &mut self.scratch).unwrap();
        &self.dft
    }
}

/// `V_r = (1/N) Σ_{ν≠0} w·|F|²/N` from the realisation's power, summed here
/// (plain sum over the cells, the DC weight being 0).
fn v_direct<const D: usize>(dft: &Dft<D, Vec<f64>>, w: &[f64], power: &mut [f64]) -> f64 {
    dft.power(power).unwrap();
    power.iter().zip(w).map(|(p, w)| p * w).sum::<f64>() / dft.count() as f64
}

/// Mean and `√(Σ (x − x̄)²/(n(n − 1)))` by two passes.
fn mean_and_se(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let ss: f64 = xs.iter().map(|x| (x - mean) * (x - mean)).sum();
    (mean, (ss / (n - 1.0) / n).sqrt())
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

/// The stated SE is the SE of the mean of the `V_r`, evaluated here from the
/// stored values, in 1D, 2D and 3D and for random and jittered points; the
/// prediction is `Periodogram::predict_variance` of the same realisations.
#[test]
fn standard_error_is_that_of_the_per_realisation_predictions() {
    fn check<const D: usize>(name: &str, p: &dyn Pattern<D>, k: usize, reals: u64) {
        let g = Grid::<D>::new(k).unwrap();
        let sigma = 0.08;
        let pf = |j: [i32; D]| {
            let m: f64 = j.iter().map(|&x| f64::from(x) * f64::from(x)).sum();
            (-4.0 * core::f64::consts::PI.powi(2) * sigma * sigma * m).exp()
        };
        let mut w = vec![0.0; g.len()];
        let in_grid = g.spectrum_weights(pf, &mut w).unwrap();
        let mut acc = PredictionStats::new(g, &w[..]).unwrap();
        let mut per = Periodogram::new_vec(g);
        let mut real = Realiser::new(g, p.len());
        let mut power = vec![0.0; g.len()];
        let n = p.len() as u64;
        let mut vs = Vec::new();
        for r in 0..reals {
            let dft = real.run(p, Seed::new(0xA11), r);
            let s = acc.add(dft).unwrap();
            per.add(dft).unwrap();
            let v = v_direct(dft, &w, &mut power);
            assert!(rel(s / n as f64, v) < 1e-13, "{name}: S_r/N {s} vs {v}");
            vs.push(v);
        }
        let (mean, se) = mean_and_se(&vs);
        let pred = acc.prediction(n).unwrap();
        let from_mean = per.predict_variance(n, pf);
        println!(
            "{name}: V̂ = {:.6e} ± {:.3e} (R = {reals}); brute force {mean:.6e} ± {se:.3e}",
            pred.grid,
            pred.std_error.unwrap()
        );
        assert_eq!(pred.realisations, reals);
        assert_eq!(pred.n, n);
        assert!(
            rel(pred.grid, mean) < 1e-12,
            "{name}: {} vs {mean}",
            pred.grid
        );
        assert!(
            rel(pred.std_error.unwrap(), se) < 1e-12,
            "{name}: SE {:?} vs {se}",
            pred.std_error
        );
        assert!(rel(pred.grid, from_mean.grid) < 1e-12, "{name}");
        assert_eq!(from_mean.std_error, None);
        assert!(rel(pred.pf_in_grid, in_grid) < 1e-15);
        assert!(rel(pred.pf_in_grid, from_mean.pf_in_grid) < 1e-13);
        assert_eq!(acc.pf_in_grid(), pred.pf_in_grid);
    }
    check::<1>("1D random", &Random::<1>::new(40).unwrap(), 30, 50);
    check::<1>("1D jittered", &Jittered::new([40]).unwrap(), 30, 50);
    check::<2>("2D random", &Random::<2>::new(64).unwrap(), 10, 60);
    check::<2>("2D jittered", &Jittered::new([8, 8]).unwrap(), 10, 60);
    check::<3>("3D jittered", &Jittered::new([4, 4, 4]).unwrap(), 4, 40);
}

/// One accumulator fed everything against merges of many splits, in order,
/// reversed and as a tree: the same prediction and SE, bit for bit (so chunk
/// size and thread count cannot change a result). Persisting and resuming
/// changes nothing either.
#[test]
fn merging_any_split_is_one_accumulator() {
    let g = Grid::<2>::new(10).unwrap();
    let f = gauss();
    let mut w = vec![0.0; g.len()];
    g.spectrum_weights(|j| f.fourier(&j).norm_sqr(), &mut w)
        .unwrap();
    let p = Jittered::new([8, 8]).unwrap();
    let reals = 64u64;
    let mut real = Realiser::new(g, 64);
    let mut one = PredictionStats::new(g, &w[..]).unwrap();
    let mut each = Vec::new();
    for r in 0..reals {
        let dft = real.run(&p, Seed::new(0xB22), r);
        one.add(dft).unwrap();
        let mut a = PredictionStats::new(g, w.clone()).unwrap();
        a.add(dft).unwrap();
        each.push(a);
    }
    let want = one.prediction(64).unwrap();
    let same = |what: &str, acc: &PredictionStats<2, &[f64]>| {
        let got = acc.prediction(64).unwrap();
        assert_eq!(got.realisations, reals, "{what}");
        assert_eq!(
            got.grid.to_bits(),
            want.grid.to_bits(),
            "{what}: {got:?} vs {want:?}"
        );
        assert_eq!(
            got.std_error.map(f64::to_bits),
            want.std_error.map(f64::to_bits),
            "{what}: {got:?} vs {want:?}"
        );
    };
    for chunk in [1usize, 2, 7, 13, 32, 63] {
        let mut fwd = PredictionStats::new(g, &w[..]).unwrap();
        let mut rev = PredictionStats::new(g, &w[..]).unwrap();
        let chunks: Vec<PredictionStats<2, Vec<f64>>> = each
            .chunks(chunk)
            .map(|c| {
                let mut m = PredictionStats::new(g, w.clone()).unwrap();
                c.iter().for_each(|a| m.merge(a).unwrap());
                m
            })
            .collect();
        chunks.iter().for_each(|c| fwd.merge(c).unwrap());
        chunks.iter().rev().for_each(|c| rev.merge(c).unwrap());
        same(&format!("chunks of {chunk}"), &fwd);
        same(&format!("chunks of {chunk}, reversed"), &rev);
    }
    // A balanced tree of single realisations.
    let mut level: Vec<PredictionStats<2, Vec<f64>>> = each.clone();
    while level.len() > 1 {
        level = level
            .chunks(2)
            .map(|c| {
                let mut m = c[0].clone();
                if let Some(b) = c.get(1) {
                    m.merge(b).unwrap();
                }
                m
            })
            .collect();
    }
    let mut tree = PredictionStats::new(g, &w[..]).unwrap();
    tree.merge(&level[0]).unwrap();
    same("tree", &tree);
    // Persist after half the realisations, resume, add the rest.
    let mut half = PredictionStats::new(g, &w[..]).unwrap();
    each[..32].iter().for_each(|a| half.merge(a).unwrap());
    let (r, sums) = half.parts();
    let mut resumed = PredictionStats::from_parts(g, &w[..], r, sums).unwrap();
    assert_eq!(resumed.parts(), half.parts());
    each[32..].iter().for_each(|a| resumed.merge(a).unwrap());
    same("persisted and resumed", &resumed);
}

/// `R = 0`: prediction 0, no SE; `R = 1`: `V_1`, no SE; `R = 2`: the SE is
/// `|V_1 − V_2|/2` (`s² = (V_1 − V_2)²/2`, over `√2`).
#[test]
fn few_realisations() {
    let g = Grid::<2>::new(6).unwrap();
    let f = gauss();
    let mut acc = PredictionStats::new_vec(g, |j| f.fourier(&j).norm_sqr()).unwrap();
    let p0 = acc.prediction(64).unwrap();
    assert_eq!((p0.grid, p0.std_error, p0.realisations), (0.0, None, 0));
    let p = Random::<2>::new(64).unwrap();
    let mut real = Realiser::new(g, 64);
    let s1 = acc.add(real.run(&p, Seed::new(3), 0)).unwrap();
    let p1 = acc.prediction(64).unwrap();
    assert!(rel(p1.grid, s1 / 64.0) < 1e-15, "{p1:?}");
    assert_eq!(p1.std_error, None);
    let s2 = acc.add(real.run(&p, Seed::new(3), 1)).unwrap();
    let p2 = acc.prediction(64).unwrap();
    let want = (s1 - s2).abs() / 2.0 / 64.0;
    assert!(rel(p2.std_error.unwrap(), want) < 1e-12, "{p2:?} vs {want}");
    assert!(rel(p2.grid, (s1 + s2) / 2.0 / 64.0) < 1e-15);
    // The same realisation twice: the spread is exactly 0.
    let mut twice = PredictionStats::new_vec(g, |j| f.fourier(&j).norm_sqr()).unwrap();
    let dft = real.run(&p, Seed::new(3), 0);
    twice.add(dft).unwrap();
    twice.add(dft).unwrap();
    assert_eq!(twice.prediction(64).unwrap().std_error, Some(0.0));
}

/// Scaling the weights by `2^±600` scales prediction and SE by the same power
/// of two, bit for bit: whatever the units of `p_f`, nothing over- or
/// underflows (a plain `Σ V_r²` would at `2^±600`).
#[test]
fn units_of_the_spectrum_do_not_matter() {
    let g = Grid::<2>::new(8).unwrap();
    let f = gauss();
    let mut w = vec![0.0; g.len()];
    g.spectrum_weights(|j| f.fourier(&j).norm_sqr(), &mut w)
        .unwrap();
    let p = Random::<2>::new(32).unwrap();
    let mut real = Realiser::new(g, 32);
    let base = {
        let mut acc = PredictionStats::new(g, &w[..]).unwrap();
        for r in 0..20 {
            acc.add(real.run(&p, Seed::new(9), r)).unwrap();
        }
        acc.prediction(32).unwrap()
    };
    for e in [-600, 600] {
        let s = 2f64.powi(e);
        let ws: Vec<f64> = w.iter().map(|x| x * s).collect();
        let mut acc = PredictionStats::new(g, &ws[..]).unwrap();
        for r in 0..20 {
            acc.add(real.run(&p, Seed::new(9), r)).unwrap();
        }
        let got = acc.prediction(32).unwrap();
        assert_eq!(got.grid.to_bits(), (base.grid * s).to_bits(), "2^{e}");
        assert_eq!(
            got.std_error.unwrap().to_bits(),
            (base.std_error.unwrap() * s).to_bits(),
            "2^{e}"
        );
    }
}

#[test]
fn errors_name_their_parameter() {
    let g = Grid::<2>::new(4).unwrap();
    let len = g.len();
    let mut w = vec![1.0; len];
    let param = |e: SpectrumError| match e {
        SpectrumError::Param(p) => p,
        e => panic!("{e:?}"),
    };
    // Weights.
    assert_eq!(
        PredictionStats::new(g, &w[..3]).unwrap_err(),
        SpectrumError::Length {
            name: "weights",
            expected: len,
            got: 3
        }
    );
    w[7] = f64::NAN;
    assert_eq!(
        PredictionStats::new(g, &w[..]).unwrap_err(),
        SpectrumError::NonFinite {
            name: "weights",
            index: 7
        }
    );
    w[7] = -1.0;
    assert!(matches!(
        param(PredictionStats::new(g, &w[..]).unwrap_err()),
        ParamError::OutOfRange {
            name: "weights",
            ..
        }
    ));
    w[7] = f64::MAX;
    w[8] = f64::MAX;
    assert!(matches!(
        param(PredictionStats::new(g, &w[..]).unwrap_err()),
        ParamError::OutOfRange {
            name: "weights",
            ..
        }
    ));
    // Spectrum weights.
    let mut out = vec![0.0; len];
    assert!(matches!(
        g.spectrum_weights(|_| 1.0, &mut out[1..]),
        Err(SpectrumError::Length { name: "out", .. })
    ));
    assert!(matches!(
        g.spectrum_weights(|_| f64::NAN, &mut out),
        Err(SpectrumError::NonFinite { name: "p_f", .. })
    ));
    assert!(matches!(
        param(g.spectrum_weights(|_| -1.0, &mut out).unwrap_err()),
        ParamError::OutOfRange { name: "p_f", .. }
    ));
    let total = g.spectrum_weights(|_| 1.0, &mut out).unwrap();
    assert_eq!(total, 80.0, "the full grid [−4, 4]² without DC");
    // Realisations and merges.
    let mut acc = PredictionStats::new(g, out.clone()).unwrap();
    assert_eq!(
        param(acc.prediction(0).unwrap_err()),
        ParamError::Count {
            name: "n",
            value: 0
        }
    );
    let empty = Dft::<2, Vec<f64>>::new_vec(g);
    assert_eq!(acc.add(&empty).unwrap_err(), SpectrumError::Empty);
    let other = Dft::<2, Vec<f64>>::new_vec(Grid::new(5).unwrap());
    assert!(matches!(
        acc.add(&other),
        Err(SpectrumError::GridMismatch { left: 4, right: 5 })
    ));
    let mut w2 = out.clone();
    w2[11] *= 2.0;
    let b = PredictionStats::new(g, w2).unwrap();
    assert_eq!(
        acc.merge(&b).unwrap_err(),
        SpectrumError::WeightsMismatch { index: 11 }
    );
    assert!(acc.merge(&b).unwrap_err().to_string().contains("cell 11"));
    // Huge amplitudes: S_r² would overflow.
    let mut big = linesample::spectrum::Amplitudes::new_vec(g);
    big.set_count(1);
    big.parts_mut().0[3] = 1e150;
    assert!(matches!(
        param(acc.add(&big).unwrap_err()),
        ParamError::OutOfRange {
            name: "amplitudes",
            ..
        }
    ));
    assert_eq!(acc.realisations(), 0, "nothing added on error");
    // Persisted state.
    let from = |r: u64, s: [f64; 4]| PredictionStats::from_parts(g, &out[..], r, s);
    assert!(matches!(
        from(2, [1.0, f64::NAN, 1.0, 0.0]),
        Err(SpectrumError::NonFinite {
            name: "sums",
            index: 1
        })
    ));
    assert!(matches!(
        param(from(2, [-1.0, 0.0, 1.0, 0.0]).unwrap_err()),
        ParamError::OutOfRange { name: "sums", .. }
    ));
    assert!(matches!(
        param(from(0, [1.0, 0.0, 1.0, 0.0]).unwrap_err()),
        ParamError::Count {
            name: "realisations",
            value: 0
        }
    ));
    assert!(from(0, [0.0; 4]).is_ok());
    // Ratio.
    for (args, name) in [
        ([f64::NAN, 1.0, 1.0, 1.0], "num"),
        ([1.0, f64::INFINITY, 1.0, 1.0], "num_se"),
        ([1.0, 1.0, f64::NAN, 1.0], "den"),
        ([1.0, 1.0, 1.0, f64::INFINITY], "den_se"),
        ([1e300, 0.0, 1e-300, 0.0], "num/den"),
    ] {
        let [a, b, c, d] = args;
        assert_eq!(
            Ratio::new(a, b, c, d).unwrap_err(),
            ParamError::NonFinite { name },
            "{args:?}"
        );
    }
    for (args, name) in [
        ([1.0, -1.0, 1.0, 1.0], "num_se"),
        ([1.0, 1.0, 1.0, -1.0], "den_se"),
        ([1.0, 1.0, 0.0, 1.0], "den"),
    ] {
        let [a, b, c, d] = args;
        assert!(
            matches!(Ratio::new(a, b, c, d), Err(ParamError::OutOfRange { name: n, .. }) if n == name),
            "{args:?}"
        );
    }
}

/// The delta-method ratio: `SE = √(σ_a² + r²σ_b²)/|b|`, against the form
/// `|r|·√((σ_a/a)² + (σ_b/b)²)` and its `a = 0` limit.
#[test]
fn ratio_standard_error() {
    let r = Ratio::new(2.0, 0.1, 4.0, 0.2).unwrap();
    assert_eq!(r.value, 0.5);
    let want = 0.5 * ((0.1f64 / 2.0).powi(2) + (0.2f64 / 4.0).powi(2)).sqrt();
    assert!(rel(r.std_error, want) < 1e-15, "{r:?} vs {want}");
    let r = Ratio::new(-3.0, 0.3, -1.5, 0.0).unwrap();
    assert_eq!(r.value, 2.0);
    assert!(rel(r.std_error, 0.2) < 1e-15, "{r:?}");
    let r = Ratio::new(0.0, 0.5, -2.0, 0.7).unwrap();
    assert_eq!((r.value, r.std_error), (0.0, 0.25));
}

/// Two-sided false-alarm probability of the χ² and binomial checks.
const ALPHA: f64 = 1e-6;
/// `|z|` limit of the bias check (tests/README.md: α = 5.7e-7).
const Z_BIAS: f64 = 5.0;

/// The χ²_df quantile at lower-tail probability `p` (Wilson–Hilferty: the cube
/// root of χ²/df is nearly normal; relative error below 1e-3 for df ≥ 100).
fn chi2_quantile(df: f64, z: f64) -> f64 {
    let a = 2.0 / (9.0 * df);
    df * (1.0 - a + z * a.sqrt()).powi(3)
}

/// `P(|T| ≤ t)` for Student's t with `nu` degrees of freedom (Abramowitz &
/// Stegun 26.7.3–4: finite series in `cos θ`, `θ = atan(t/√ν)`).
fn student_central(t: f64, nu: u32) -> f64 {
    let th = (t / f64::from(nu).sqrt()).atan();
    let (s, c) = th.sin_cos();
    let c2 = c * c;
    if nu.is_multiple_of(2) {
        let (mut term, mut sum) = (1.0, 1.0);
        for k in 1..nu / 2 {
            term *= f64::from(2 * k - 1) / f64::from(2 * k) * c2;
            sum += term;
        }
        s * sum
    } else {
        let (mut term, mut sum) = (c, 0.0);
        if nu > 1 {
            sum = c;
            for k in 1..(nu - 1) / 2 {
                term *= f64::from(2 * k) / f64::from(2 * k + 1) * c2;
                sum += term;
            }
        }
        core::f64::consts::FRAC_2_PI * (th + s * sum)
    }
}

/// The smallest and largest counts `c` of `Binomial(m, p)` with both tails
/// `P(C ≤ c)`, `P(C ≥ c)` above `alpha/2`.
fn binomial_bounds(m: u64, p: f64, alpha: f64) -> (u64, u64) {
    let ln_pmf = |c: u64| {
        let (mf, cf) = (m as f64, c as f64);
        libm::lgamma(mf + 1.0) - libm::lgamma(cf + 1.0) - libm::lgamma(mf - cf + 1.0)
            + cf * p.ln()
            + (mf - cf) * (1.0 - p).ln()
    };
    let pmf: Vec<f64> = (0..=m).map(|c| ln_pmf(c).exp()).collect();
    let mut lo = 0;
    let mut tail = 0.0;
    for (c, &q) in pmf.iter().enumerate() {
        tail += q;
        if tail > alpha / 2.0 {
            lo = c as u64;
            break;
        }
    }
    let mut hi = m;
    let mut tail = 0.0;
    for (c, &q) in pmf.iter().enumerate().rev() {
        tail += q;
        if tail > alpha / 2.0 {
            hi = c as u64;
            break;
        }
    }
    (lo, hi)
}

#[test]
fn helpers_match_tables() {
    // Student t: P(|T_ν| ≤ t) from standard tables (two-sided 95 % points).
    for (nu, t) in [
        (1, 12.706),
        (2, 4.303),
        (5, 2.571),
        (10, 2.228),
        (31, 2.040),
    ] {
        let p = student_central(t, nu);
        assert!((p - 0.95).abs() < 2e-4, "ν = {nu}: {p}");
    }
    // χ²: 0.999 quantile of 100 df is 149.449 (tables).
    let q = chi2_quantile(100.0, normal_upper_quantile(1e-3));
    assert!(rel(q, 149.449) < 2e-3, "{q}");
}

struct Coverage {
    name: String,
    mean_se: f64,
    sd_pred: f64,
    ratio_bounds: (f64, f64),
    covered: u64,
    m: u64,
    p0: f64,
    count_bounds: (u64, u64),
    bias_z: f64,
}

impl Coverage {
    fn ratio(&self) -> f64 {
        self.mean_se / self.sd_pred
    }
    fn ok(&self) -> bool {
        let r = self.ratio();
        r >= self.ratio_bounds.0
            && r <= self.ratio_bounds.1
            && self.covered >= self.count_bounds.0
            && self.covered <= self.count_bounds.1
            && self.bias_z.abs() <= Z_BIAS
    }
}

/// `m` independent experiments of `reals` realisations of `pattern`
/// (`expected(j)` = `E[N·P(j)]`), each giving a prediction and its SE.
fn coverage(
    name: &str,
    pattern: &dyn Pattern<2>,
    expected: &dyn Fn([i32; 2]) -> f64,
    k: usize,
    reals: u64,
    m: u64,
) -> Coverage {
    let t = std::time::Instant::now();
    let g = Grid::<2>::new(k).unwrap();
    let f = gauss();
    let mut w = vec![0.0; g.len()];
    g.spectrum_weights(|j| f.fourier(&j).norm_sqr(), &mut w)
        .unwrap();
    let n = pattern.len();
    let truth = (0..g.len())
        .filter(|&i| w[i] > 0.0)
        .map(|i| w[i] * expected(g.freq(i)))
        .sum::<f64>()
        / n as f64;
    let mut real = Realiser::new(g, n);
    let seed = Seed::new(0xC0FE_2024 ^ n as u64);
    let (mut preds, mut ses) = (Vec::new(), Vec::new());
    let mut covered = 0;
    for e in 0..m {
        let mut acc = PredictionStats::new(g, &w[..]).unwrap();
        for r in 0..reals {
            acc.add(real.run(pattern, seed, e * reals + r)).unwrap();
        }
        let p = acc.prediction(n as u64).unwrap();
        let se = p.std_error.unwrap();
        if (p.grid - truth).abs() <= 2.0 * se {
            covered += 1;
        }
        preds.push(p.grid);
        ses.push(se);
    }
    let (mean_pred, se_mean_pred) = mean_and_se(&preds);
    let sd_pred = se_mean_pred * (m as f64).sqrt();
    let mean_se = ses.iter().sum::<f64>() / m as f64;
    let df = (m - 1) as f64;
    let z = normal_upper_quantile(ALPHA / 2.0);
    let ratio_bounds = (
        (df / chi2_quantile(df, z)).sqrt(),
        (df / chi2_quantile(df, -z)).sqrt(),
    );
    let p0 = student_central(2.0, (reals - 1) as u32);
    let c = Coverage {
        name: name.to_string(),
        mean_se,
        sd_pred,
        ratio_bounds,
        covered,
        m,
        p0,
        count_bounds: binomial_bounds(m, p0, ALPHA),
        bias_z: (mean_pred - truth) / se_mean_pred,
    };
    eprintln!("{name}: {:.1?}", t.elapsed());
    c
}

fn report(rows: &[Coverage]) {
    println!(
        "| case | mean SE | sd of predictions | ratio | χ² bounds (α = {ALPHA:e}) | covered by ±2 SE | p₀ | binomial bounds | bias z |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for c in rows {
        println!(
            "| {} | {:.4e} | {:.4e} | {:.3} | [{:.3}, {:.3}] | {}/{} = {:.3} | {:.4} | [{}, {}] | {:+.2} |{}",
            c.name,
            c.mean_se,
            c.sd_pred,
            c.ratio(),
            c.ratio_bounds.0,
            c.ratio_bounds.1,
            c.covered,
            c.m,
            c.covered as f64 / c.m as f64,
            c.p0,
            c.count_bounds.0,
            c.count_bounds.1,
            c.bias_z,
            if c.ok() { "" } else { " FAIL" }
        );
    }
    let bad: Vec<&str> = rows
        .iter()
        .filter(|c| !c.ok())
        .map(|c| c.name.as_str())
        .collect();
    assert!(
        bad.is_empty(),
        "the stated SE does not cover the spread: {bad:?}"
    );
}

fn random_expected(_: [i32; 2]) -> f64 {
    1.0
}

/// The default-suite coverage check (2 cases × 3 checks; see the module
/// documentation for the rule and the false-alarm rate).
#[test]
fn standard_error_covers_the_spread_quick() {
    let jit = |j: [i32; 2]| jittered_expected([8, 8], j);
    let rows = vec![
        coverage(
            "random N = 64, R = 32",
            &Random::<2>::new(64).unwrap(),
            &random_expected,
            10,
            32,
            400,
        ),
        coverage(
            "jittered 8×8, R = 32",
            &Jittered::new([8, 8]).unwrap(),
            &jit,
            10,
            32,
            400,
        ),
    ];
    report(&rows);
}

/// Larger N and R, more experiments (4 cases × 3 checks).
#[test]
#[ignore = "release: cargo test --release -p linesample --test prediction_error -- --ignored --nocapture"]
fn standard_error_covers_the_spread() {
    let jit8 = |j: [i32; 2]| jittered_expected([8, 8], j);
    let jit16 = |j: [i32; 2]| jittered_expected([16, 16], j);
    let rows = vec![
        coverage(
            "random N = 64, R = 32",
            &Random::<2>::new(64).unwrap(),
            &random_expected,
            10,
            32,
            2000,
        ),
        coverage(
            "jittered 8×8, R = 64",
            &Jittered::new([8, 8]).unwrap(),
            &jit8,
            10,
            64,
            1000,
        ),
        coverage(
            "random N = 256, R = 64",
            &Random::<2>::new(256).unwrap(),
            &random_expected,
            10,
            64,
            400,
        ),
        coverage(
            "jittered 16×16, R = 48",
            &Jittered::new([16, 16]).unwrap(),
            &jit16,
            10,
            48,
            500,
        ),
    ];
    report(&rows);
}
