//! Weighted least-squares fits of measured power laws.

use serde::{Deserialize, Serialize};

/// Weighted least-squares fit of `ln y = a + b ln x`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fit {
    pub slope: f64,
    pub slope_se: f64,
    /// `a` (natural logarithms).
    pub intercept: f64,
    /// `χ²/(m − 2)` for `m` points (NaN for `m = 2`).
    pub chi2_dof: f64,
    pub points: usize,
}

impl Fit {
    /// The `x` at which the fitted law reaches `y`: `exp((ln y − a)/b)`
    /// (e.g. the `N` whose variance is a target).
    #[must_use]
    pub fn x_at(&self, y: f64) -> f64 {
        ((y.ln() - self.intercept) / self.slope).exp()
    }

    /// Whether the fit shows convergence: the slope's 95 % interval,
    /// `b + 1.96·se`, lies below 0.
    #[must_use]
    pub fn converges(&self) -> bool {
        self.slope + 1.96 * self.slope_se < 0.0
    }

    /// The `N` at which the fitted variance reaches `target` (at least 1),
    /// or `None` when the fit does not show convergence ([`Fit::converges`]):
    /// a flat or growing variance reaches no target, and extrapolating it
    /// (`x_at` of a positive slope is below the measured range) would print
    /// a time that means nothing.
    #[must_use]
    pub fn n_to(&self, target: f64) -> Option<f64> {
        (self.converges() && target > 0.0 && target.is_finite()).then(|| self.x_at(target).max(1.0))
    }
}

/// The `N` at which the fitted variance of `fit` reaches `target`, or NaN
/// when there is no fit or it does not converge ([`Fit::n_to`]); the form
/// the CSVs and reports print (an empty or `NaN` field, never a number).
#[must_use]
pub fn n_to_target(fit: Option<&Fit>, target: f64) -> f64 {
    fit.and_then(|f| f.n_to(target)).unwrap_or(f64::NAN)
}

/// A time or a count read off a convergence fit, in scientific notation with
/// `digits` decimals, or `no convergence` where the fit gave none (NaN: its
/// slope's 95 % interval does not lie below 0).
#[must_use]
pub fn fit_sci(v: f64, digits: usize) -> String {
    if v.is_finite() {
        format!("{v:.digits$e}")
    } else {
        "no convergence".into()
    }
}

/// The slope between the last two points, `ln(y_m/y_{m−1})/ln(x_m/x_{m−1})`;
/// NaN with fewer than two.
#[must_use]
pub fn last_slope(data: &[(f64, f64, f64)]) -> f64 {
    match data {
        [.., a, b] => (b.1 / a.1).ln() / (b.0 / a.0).ln(),
        _ => f64::NAN,
    }
}

/// Fits `ln y = a + b ln x` by weighted least squares with weights
/// `w = (y/err)²`, the inverse variance of `ln y` by the delta method. Points
/// with `y ≤ 0`, a non-finite or non-positive `err`, or `x ≤ 0` are left out.
/// `slope_se = 1/√(Σ w (ln x − x̄)²)` uses the weights as known variances (it is
/// not rescaled by `χ²`). `None` with fewer than two usable points or a single
/// distinct `x`.
#[must_use]
pub fn fit_loglog(data: &[(f64, f64, f64)]) -> Option<Fit> {
    let pts: Vec<(f64, f64, f64)> = data
        .iter()
        .filter(|(x, y, e)| *x > 0.0 && *y > 0.0 && e.is_finite() && *e > 0.0 && y.is_finite())
        .map(|&(x, y, e)| (x.ln(), y.ln(), (y / e) * (y / e)))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let sw: f64 = pts.iter().map(|p| p.2).sum();
    let xm = pts.iter().map(|p| p.2 * p.0).sum::<f64>() / sw;
    let ym = pts.iter().map(|p| p.2 * p.1).sum::<f64>() / sw;
    let sxx: f64 = pts.iter().map(|p| p.2 * (p.0 - xm) * (p.0 - xm)).sum();
    let sxy: f64 = pts.iter().map(|p| p.2 * (p.0 - xm) * (p.1 - ym)).sum();
    if sxx <= 0.0 || !sxx.is_finite() {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = ym - slope * xm;
    let chi2: f64 = pts
        .iter()
        .map(|p| {
            let r = p.1 - intercept - slope * p.0;
            p.2 * r * r
        })
        .sum();
    let dof = pts.len() - 2;
    Some(Fit {
        slope,
        slope_se: 1.0 / sxx.sqrt(),
        intercept,
        chi2_dof: if dof > 0 { chi2 / dof as f64 } else { f64::NAN },
        points: pts.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A variance that does not fall reaches no target: no N, no time
    /// (the scene studies printed N = 1 and a time of 2e-7 s for a row
    /// whose slope was +0.18).
    #[test]
    fn a_fit_that_does_not_converge_has_no_n_to_a_target() {
        let rising: Vec<(f64, f64, f64)> = [16.0, 64.0, 256.0, 1024.0]
            .iter()
            .map(|&n: &f64| (n, 1e-3 * n.powf(0.18), 1e-5 * n.powf(0.18)))
            .collect();
        let f = fit_loglog(&rising).unwrap();
        assert!(f.slope > 0.1 && !f.converges(), "{f:?}");
        assert_eq!(f.n_to(1e-6), None);
        assert!(n_to_target(Some(&f), 1e-6).is_nan());
        assert!(n_to_target(None, 1e-6).is_nan());
        // A slope of -0.02 with a wide interval is not convergence either.
        let flat: Vec<(f64, f64, f64)> = [16.0, 64.0]
            .iter()
            .map(|&n: &f64| (n, 1e-3 * n.powf(-0.02), 0.5e-3))
            .collect();
        let f = fit_loglog(&flat).unwrap();
        assert!(f.slope < 0.0 && !f.converges(), "{f:?}");
        assert_eq!(f.n_to(1e-6), None);
        // A converging fit already below the target at N = 1 reads N = 1.
        let fast: Vec<(f64, f64, f64)> = [16.0, 64.0, 256.0]
            .iter()
            .map(|&n: &f64| (n, 1e-9 * n.powf(-2.0), 1e-11 * n.powf(-2.0)))
            .collect();
        assert_eq!(fit_loglog(&fast).unwrap().n_to(1e-6), Some(1.0));
    }

    #[test]
    fn fit_recovers_a_power_law() {
        let data: Vec<(f64, f64, f64)> = [16.0, 64.0, 256.0, 1024.0]
            .iter()
            .map(|&n: &f64| (n, 3.0 * n.powf(-1.5), 0.1 * 3.0 * n.powf(-1.5)))
            .collect();
        let f = fit_loglog(&data).unwrap();
        assert!((f.slope + 1.5).abs() < 1e-12, "{f:?}");
        assert!((f.intercept - 3f64.ln()).abs() < 1e-12);
        assert!(f.chi2_dof < 1e-20);
        // σ(ln y) = 0.1 for all points: SE = 0.1/√Σ(ln x − x̄)².
        let xs: Vec<f64> = data.iter().map(|d| d.0.ln()).collect();
        let m = xs.iter().sum::<f64>() / 4.0;
        let sxx: f64 = xs.iter().map(|x| (x - m) * (x - m)).sum();
        assert!((f.slope_se - 0.1 / sxx.sqrt()).abs() < 1e-12);
        assert!((f.x_at(3.0 * 256f64.powf(-1.5)) - 256.0).abs() < 1e-9);
        assert!((last_slope(&data) + 1.5).abs() < 1e-12);
        assert_eq!(f.n_to(3.0 * 256f64.powf(-1.5)).map(f64::round), Some(256.0));
        assert!(last_slope(&data[..1]).is_nan());
        // Unusable points are skipped.
        assert!(fit_loglog(&[(16.0, 1.0, 0.1), (64.0, 0.0, 0.1)]).is_none());
        assert_eq!(
            fit_loglog(&[
                (16.0, 1.0, 0.1),
                (64.0, 0.5, 0.1),
                (256.0, 0.2, f64::INFINITY)
            ])
            .unwrap()
            .points,
            2
        );
    }
}
