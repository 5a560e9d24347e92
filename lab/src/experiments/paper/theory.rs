//! Theoretical convergence rates: the scaling rule of `docs/theory.md`
//! (Convergence rates), `Var ~ N^(−1 − min(β, α − d′)/d′)`, times `log N`
//! when `β = α − d′`, with the inputs per sampler and integrand.
//!
//! * `d′` is the dimension of what is sampled: `D` for points and segments,
//!   `D − 1` for line offsets.
//! * `β` is the low-frequency exponent of the sampler's expected spectrum,
//!   `⟨N·P(ρ)⟩ ~ (ρ/ρ_N)^β` below its Nyquist-like radius `ρ_N ∝ N^(1/d′)`:
//!   0 for random and Poisson disk (Pilleboue et al. 2015), 2 for jittered and
//!   multi-jittered (Pilleboue et al. 2015), 3 for CCVT (Pilleboue et al.
//!   2015's best-case rate `N^(−1−3/d)`), and `2d′` for Owen-scrambled Sobol'
//!   at `N = 2^m` (Owen 1997: `N^(−3)(log N)^(d′−1)` for smooth integrands),
//!   whose `(log N)^(d′−1)` is the sampler's own log factor.
//! * `α` is the decay exponent of the radial mean of the sampled function's
//!   power spectrum, `P̆(ρ) ~ ρ^(−α)`: `∞` for a Gaussian; `d′ + 1` for an
//!   indicator with a C0 jump on a smooth (curved or flat) boundary; `d′ + 2`
//!   for the chord length of a disk or ball seen by lines (a line integrates
//!   the jump into a square-root edge: one order smoother); `d′ + 3` for the
//!   piecewise-linear line integral of a flat edge that the lines cross
//!   obliquely; `d′ + 1` again when the lines run parallel to the flat edge
//!   (the jump survives the projection). Segments of length `λ` pre-filter the
//!   integrand along their direction: for frequencies above `1/λ` the spectrum
//!   gains one power of `ρ^(−1)` (`α → d′ + 2` for a C0 jump), below it
//!   nothing changes; so the asymptotic rate holds for `N ≫ N* = λ^(−d)` and
//!   the point rate for `N ≪ N*`.

use serde::{Deserialize, Serialize};

use crate::integrand::IntegrandKind;
use crate::sampler::Sampler;
use crate::spec::Primitive;

/// `β` as a number, with `∞` as `f64::INFINITY`.
#[must_use]
pub fn beta(sampler: Sampler, pattern_dims: usize) -> f64 {
    match sampler {
        Sampler::Random | Sampler::PoissonDisk | Sampler::PoissonDiskThinned => 0.0,
        Sampler::Jittered | Sampler::MultiJittered | Sampler::Cmj => 2.0,
        Sampler::Ccvt => 3.0,
        // Owen-scrambled (0, m, d′)-nets (Owen 1997); PMJ02 prefixes of 2^m
        // points are (0, m, 2)-nets in base 2 with random nested strata, and
        // Christensen et al. (2018) measure Owen-Sobol′'s rates for them.
        Sampler::Sobol | Sampler::Pmj02 | Sampler::Pmj02Bn => 2.0 * pattern_dims as f64,
        // Not used by the paper's tables: Latin hypercube and Halton have no
        // isotropic low-frequency law of this form.
        Sampler::NRooks | Sampler::Halton => f64::NAN,
    }
}

/// How lines meet a flat edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EdgeCase {
    /// The lines cross the edge at an angle.
    Crossing,
    /// The lines run parallel to the edge.
    Parallel,
}

/// `α` of the function the pattern samples (see the module docs).
#[must_use]
pub fn alpha(
    kind: IntegrandKind,
    primitive: Primitive,
    pattern_dims: usize,
    edge: Option<EdgeCase>,
) -> f64 {
    let d = pattern_dims as f64;
    match (kind, primitive) {
        (IntegrandKind::Gaussian, _) => f64::INFINITY,
        (IntegrandKind::Disk | IntegrandKind::Ball, Primitive::Lines) => d + 2.0,
        (IntegrandKind::Edge, Primitive::Lines) => match edge {
            Some(EdgeCase::Crossing) => d + 3.0,
            _ => d + 1.0,
        },
        // Points; segments are treated per N by `Theory::segment` below.
        _ => d + 1.0,
    }
}

/// The theory of one curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Theory {
    /// `β` of the sampler.
    pub beta: f64,
    /// `α` of the sampled function.
    pub alpha: f64,
    /// `d′`, the dimension of the pattern.
    pub pattern_dims: usize,
    /// The power of `N`: `−1 − min(β, α − d′)/d′`.
    pub slope: f64,
    /// The power of `log N` multiplying it (0 when there is none).
    pub log_power: u32,
}

impl Theory {
    /// The rule applied to `β`, `α`, `d′` (Owen-Sobol' adds its own
    /// `(log N)^(d′−1)` when its `β` is the limit).
    #[must_use]
    pub fn new(sampler: Sampler, alpha: f64, pattern_dims: usize) -> Self {
        let beta = beta(sampler, pattern_dims);
        let d = pattern_dims as f64;
        let m = beta.min(alpha - d);
        let mut log_power = u32::from(beta == alpha - d);
        if matches!(sampler, Sampler::Sobol | Sampler::Pmj02 | Sampler::Pmj02Bn) && beta < alpha - d
        {
            log_power = u32::try_from(pattern_dims.saturating_sub(1)).unwrap_or(0);
        }
        Theory {
            beta,
            alpha,
            pattern_dims,
            slope: -1.0 - m / d,
            log_power,
        }
    }

    /// The theory of `sampler` sampling `kind` with `primitive` in `dims`
    /// dimensions (segments: the asymptotic, line-like regime).
    #[must_use]
    pub fn of(
        sampler: Sampler,
        kind: IntegrandKind,
        primitive: Primitive,
        dims: usize,
        edge: Option<EdgeCase>,
    ) -> Self {
        let pd = if primitive == Primitive::Lines {
            dims - 1
        } else {
            dims
        };
        let mut a = alpha(kind, primitive, pd, edge);
        if primitive == Primitive::Segments && kind != IntegrandKind::Gaussian {
            a += 1.0;
        }
        Theory::new(sampler, a, pd)
    }

    /// `log N`, `(log N)^2` or `none`.
    #[must_use]
    pub fn log_factor(&self) -> String {
        match self.log_power {
            0 => "none".into(),
            1 => "log N".into(),
            p => format!("(log N)^{p}"),
        }
    }

    /// `N^-1.5`, `N^-3 log N`, …
    #[must_use]
    pub fn rate(&self) -> String {
        let s = format_slope(self.slope);
        match self.log_power {
            0 => format!("N^{s}"),
            1 => format!("N^{s} log N"),
            p => format!("N^{s} (log N)^{p}"),
        }
    }
}

impl Theory {
    /// [`Theory::rate`] as HTML: `N<sup>−1.5</sup> log N`.
    #[must_use]
    pub fn rate_html(&self) -> String {
        let s = format_slope(self.slope).replace('-', "−");
        match self.log_power {
            0 => format!("N<sup>{s}</sup>"),
            1 => format!("N<sup>{s}</sup> log N"),
            p => format!("N<sup>{s}</sup> (log N)<sup>{p}</sup>"),
        }
    }
}

/// A slope with at most 3 decimals and no trailing zeros (`-1.333`, `-2`).
#[must_use]
pub fn format_slope(s: f64) -> String {
    let t = format!("{s:.3}");
    let t = t.trim_end_matches('0').trim_end_matches('.');
    t.to_string()
}

/// A number for a table: `∞`, or up to 3 decimals.
#[must_use]
pub fn format_exponent(x: f64) -> String {
    if x.is_infinite() {
        "∞".into()
    } else {
        format_slope(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slope(s: Sampler, k: IntegrandKind, p: Primitive, d: usize) -> (f64, u32) {
        let t = Theory::of(s, k, p, d, None);
        (t.slope, t.log_power)
    }

    #[test]
    fn the_rate_tables() {
        use IntegrandKind::{Ball, Disk, Gaussian};
        use Primitive::{Lines, Points, Segments};
        use Sampler::{Ccvt, Jittered, PoissonDisk, Random, Sobol};
        // Points (Pilleboue et al. 2015).
        assert_eq!(slope(Random, Disk, Points, 2), (-1.0, 0));
        assert_eq!(slope(PoissonDisk, Gaussian, Points, 3), (-1.0, 0));
        assert_eq!(slope(Jittered, Disk, Points, 2), (-1.5, 0));
        assert_eq!(slope(Jittered, Gaussian, Points, 2), (-2.0, 0));
        assert!((slope(Jittered, Ball, Points, 3).0 + 4.0 / 3.0).abs() < 1e-12);
        assert!((slope(Jittered, Gaussian, Points, 3).0 + 5.0 / 3.0).abs() < 1e-12);
        assert_eq!(slope(Ccvt, Gaussian, Points, 2), (-2.5, 0));
        assert_eq!(slope(Ccvt, Gaussian, Points, 3), (-2.0, 0));
        assert_eq!(slope(Ccvt, Disk, Points, 2), (-1.5, 0));
        // Owen-Sobol': N^-3 (log N)^(d'-1) smooth, jittered rate worst case.
        assert_eq!(slope(Sobol, Gaussian, Points, 2), (-3.0, 1));
        assert_eq!(slope(Sobol, Gaussian, Points, 3), (-3.0, 2));
        assert_eq!(slope(Sobol, Disk, Points, 2), (-1.5, 0));
        // Unidirectional lines: (d-1)-dim offsets, one order smoother.
        assert_eq!(slope(Jittered, Disk, Lines, 2), (-3.0, 1));
        assert_eq!(slope(Jittered, Ball, Lines, 3), (-2.0, 1));
        assert_eq!(slope(Jittered, Gaussian, Lines, 3), (-2.0, 0));
        assert_eq!(slope(Ccvt, Ball, Lines, 3), (-2.0, 0));
        assert_eq!(slope(Ccvt, Gaussian, Lines, 3), (-2.5, 0));
        assert_eq!(slope(Random, Ball, Lines, 3), (-1.0, 0));
        // Segments, asymptotically: jitter N^(-1-2/d) log N.
        assert_eq!(slope(Jittered, Disk, Segments, 2), (-2.0, 1));
        assert_eq!(
            slope(Jittered, Gaussian, Segments, 3),
            slope(Jittered, Gaussian, Points, 3)
        );
        // Straight edge, jittered 1D offsets: crossing N^-3, parallel N^-2.
        let c = Theory::of(
            Jittered,
            IntegrandKind::Edge,
            Lines,
            2,
            Some(EdgeCase::Crossing),
        );
        let p = Theory::of(
            Jittered,
            IntegrandKind::Edge,
            Lines,
            2,
            Some(EdgeCase::Parallel),
        );
        assert_eq!((c.slope, c.log_power), (-3.0, 0));
        assert_eq!((p.slope, p.log_power), (-2.0, 0));
        assert_eq!(c.rate(), "N^-3");
        assert_eq!(
            Theory::of(Jittered, Ball, Points, 3, None).rate(),
            "N^-1.333"
        );
        assert_eq!(
            Theory::of(Jittered, Disk, Lines, 2, None).rate(),
            "N^-3 log N"
        );
    }
}
