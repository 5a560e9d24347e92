//! One-pass vs merged `RunningStats` with a derived rounding bound (included
//! with `#[path]`).
#![allow(dead_code)]

use linesample::stats::RunningStats;

const U: f64 = f64::EPSILON / 2.0;

/// Asserts that `merged` (the parts of `xs` merged in order) equals the one-pass
/// statistics of `xs` within a bound derived from the rounding of both paths.
///
/// With `n` samples, `A = max|x|`, `R = max|x − x̄|`, `u = 2⁻⁵³`:
/// * each Welford mean update `x̄ += δ/n` errs by `≤ 3u(|x̄| + |δ|/n) ≤ 9uA`, so a
///   path's mean is within `e = 10·n·u·A` of the exact mean (the merge updates
///   are of the same form, one per part); the two paths differ by `≤ 2e`;
/// * `M2 = Σ t_k`, `t_k = δ_k²(k−1)/k`, `|δ_k| ≤ 2R` (both the sample and the
///   running mean are within `R` of `x̄`): an error `e` of the running mean changes
///   `t_k` by `≤ 4Re + e²`, and each of the `≤ 2n` additions (pushes and merges)
///   errs by `≤ 5u·M2 ≤ 20u·nR²`; so a path's `M2` is within
///   `n(4Re + e²) + 40n²uR²`, and the paths differ by twice that;
/// * below the normal range the relative model fails (found by this target:
///   `A ≈ 2e−156`, so `R² ≈ 4e−312` is subnormal and one rounding is the
///   absolute spacing `η = 2⁻¹⁰⁷⁴`): each of the `≤ 4n` operations on a mean or
///   an `M2` may add `η`, so both bounds get `+ 8nη`.
pub fn assert_merge_matches(one: &RunningStats, merged: &RunningStats, xs: &[f64]) {
    assert_eq!(one.count(), merged.count(), "counts differ");
    assert_eq!(one.count(), xs.len() as u64);
    let n = xs.len() as f64;
    if xs.is_empty() {
        assert_eq!(merged.mean(), 0.0);
        return;
    }
    let a = xs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mean = xs.iter().sum::<f64>() / n;
    // R from a rounded mean: inflate by that mean's own error (≤ n·u·A).
    let r = xs.iter().fold(0.0f64, |m, x| m.max((x - mean).abs())) + 2.0 * n * U * a;
    let eta = f64::from_bits(1); // 2⁻¹⁰⁷⁴, the subnormal spacing
    let e = 10.0 * n * U * a + 8.0 * n * eta;
    let dm = (one.mean() - merged.mean()).abs();
    assert!(
        dm <= 2.0 * e,
        "mean: one-pass {} vs merged {}: {dm:e} > bound {:e}",
        one.mean(),
        merged.mean(),
        2.0 * e
    );
    if xs.len() >= 2 {
        let b_m2 = 2.0 * (n * (4.0 * r * e + e * e) + 40.0 * n * n * U * r * r + 8.0 * n * eta);
        let bound = b_m2 / (n - 1.0);
        let dv = (one.variance() - merged.variance()).abs();
        assert!(
            dv <= bound,
            "variance: one-pass {:e} vs merged {:e}: {dv:e} > bound {bound:e} (n = {n}, A = {a:e}, R = {r:e})",
            one.variance(),
            merged.variance()
        );
        assert!(merged.variance() >= 0.0);
    }
}

/// The statistics of `xs` in one pass and merged from the parts cut at `cuts`
/// (positions taken modulo `len + 1`, sorted; empty parts included).
pub fn one_pass_and_merged(xs: &[f64], cuts: &[u8]) -> (RunningStats, RunningStats) {
    let mut one = RunningStats::new();
    for &x in xs {
        one.push(x);
    }
    let mut pos: Vec<usize> = cuts
        .iter()
        .map(|&c| usize::from(c) % (xs.len() + 1))
        .collect();
    pos.push(0);
    pos.push(xs.len());
    pos.sort_unstable();
    let mut merged = RunningStats::new();
    for w in pos.windows(2) {
        let mut part = RunningStats::new();
        for &x in &xs[w[0]..w[1]] {
            part.push(x);
        }
        merged.merge(&part);
    }
    (one, merged)
}
