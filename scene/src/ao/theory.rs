//! The spectral theory applied to one pixel of an AO scene (feature
//! `theory`: it needs the NUFFT, `linesample-nufft`, and `std`).
//!
//! With the uniform centre density a sample `(u, v) ∈ [0, 1)²` names the
//! direction `φ = πu`, `θ = π(v − ½)`, and the point estimate is
//!
//! ```text
//! f(u, v) = π · V(φ, θ) · |sin θ| cos θ,        AO = ∫∫ f du dv,
//! ```
//!
//! a function on the torus the homogenised samples live on. A segment of
//! length `ℓ` in `θ` is the box filter of width `λ = ℓ/π` along `v` (it wraps
//! with period 1 in `v`, as the segments wrap with period `π` in `θ`), so its
//! estimate is `f_ℓ = f ∗ box_λ` with Fourier coefficients
//! `f̂_ℓ(j) = f̂(j)·sinc(λ j_v)`; a line integrates `v` out, leaving the 1D
//! function `L(u) = ∫ f dv` of the azimuth offset. The variance of a
//! homogenised pattern of `N` samples is then (`docs/theory.md`, Spectral
//! variance)
//!
//! ```text
//! Var = (1/N) Σ_{j≠0} ⟨N·P(j)⟩ |ĝ(j)|²,     g = f, f_ℓ or L,
//! ```
//!
//! with `⟨N·P⟩` the pattern's expected periodogram. Here `f` is sampled at the
//! midpoints of an `M × M` grid (`L` at `M_L` midpoints in `u`, each a whole
//! line in closed form), the coefficients `ĝ(j)` for `|j_a| ≤ K` are the type-1
//! NUFFT of those samples with weights `g/M²` (the midpoint rule of
//! `∫ g e^{−2πi j·x}`), and the energy beyond `K` is the samples' total
//! `mean(g²) − mean(g)²` minus the in-grid sum, counted with `⟨N·P⟩ = 1`
//! (the white tail). `⟨N·P⟩` is the mean `|Σ e^{−2πi j·x_k}|²/N` over
//! independent realisations of the pattern (NUFFT, tolerance 1e−9).
//!
//! Where this model and the measurement part: `f` is sampled, so `f̂(j)` is a
//! midpoint-rule approximation, accurate for `|j| ≪ M`; and `f` is **not**
//! periodic in `u`: `f(u + 1, v) = f(u, 1 − v)` (the half-plane at `φ + π` is
//! the one at `φ` traversed the other way), so the torus seam `u = 0` is a
//! jump, whose energy `|f̂(j)|² ~ j_u^{−2}` along the `j_u` axis the segments
//! (filtering only along `v`) keep.

use std::vec;
use std::vec::Vec;

use linesample::spectrum::Grid;
use linesample_nufft::Plan;

use super::world::{EstimatorSpec, Pixel, World};
use super::CentrePdf;
use crate::model::{Primitive, SceneSampler};
use crate::Error;

/// Side of the fine grid `f` is sampled on.
pub const M: usize = 1024;
/// Half-width of the 2D frequency grid.
pub const K2: usize = 128;
/// Midpoints of the line function `L(u)`.
pub const M_LINE: usize = 16384;
/// Half-width of the 1D frequency grid of the lines.
pub const K1: usize = 1024;
/// NUFFT tolerance.
const TOL: f64 = 1e-9;

/// `sin(πx)/(πx)`.
fn sinc(x: f64) -> f64 {
    if x == 0.0 {
        1.0
    } else {
        let a = std::f64::consts::PI * x;
        a.sin() / a
    }
}

/// The pixel's integrand and its spectra.
#[derive(Debug)]
pub struct PixelSpectra {
    /// `f` at the grid midpoints, `f[a·M + b]` at `u = (a + ½)/M`,
    /// `v = (b + ½)/M`.
    pub f: Vec<f64>,
    /// `f̂(j)` on the half grid of half-width [`K2`] (the kernel's layout).
    pub re: Vec<f64>,
    /// Imaginary parts of `f̂(j)`.
    pub im: Vec<f64>,
    /// `L(u)` at `M_LINE` midpoints.
    pub line: Vec<f64>,
    /// `L̂(j)`, `j ∈ [0, K1]`.
    pub line_re: Vec<f64>,
    /// Imaginary parts of `L̂(j)`.
    pub line_im: Vec<f64>,
    /// `mean(f) ≈ AO`.
    pub mean: f64,
}

impl PixelSpectra {
    /// Samples the pixel's integrand and transforms it.
    ///
    /// # Errors
    /// An allocation failure ([`Error::Alloc`]), a degenerate frame or a
    /// NUFFT error ([`Error::Nufft`]).
    pub fn new(world: &World, px: &Pixel) -> Result<Self, Error> {
        let mut f = filled(M * M, "the pixel's integrand grid")?;
        let point = EstimatorSpec {
            primitive: Primitive::Points,
            length: 0.0,
            pdf: CentrePdf::Uniform,
            sampler: SceneSampler::Random,
            simd: false,
        }
        .ao();
        let mut scratch = vec![(0.0, 0.0); 2 * world.sphere_count()];
        for a in 0..M {
            for b in 0..M {
                let (u, v) = ((a as f64 + 0.5) / M as f64, (b as f64 + 0.5) / M as f64);
                f[a * M + b] = world.sample(px, &point, u, v, &mut scratch)?;
            }
        }
        let mean = f.iter().sum::<f64>() / (M * M) as f64;
        let pts: Vec<[f64; 2]> = (0..M * M)
            .map(|i| {
                [
                    ((i / M) as f64 + 0.5) / M as f64,
                    ((i % M) as f64 + 0.5) / M as f64,
                ]
            })
            .collect();
        let w: Vec<f64> = f.iter().map(|x| x / (M * M) as f64).collect();
        let mut plan = Plan::<2>::new(K2, TOL)?;
        let mut re = vec![0.0; plan.half_len()];
        let mut im = vec![0.0; plan.half_len()];
        plan.transform_weighted(&pts, &w, &mut re, &mut im)?;
        let lines = EstimatorSpec {
            primitive: Primitive::Lines,
            length: 0.0,
            pdf: CentrePdf::Uniform,
            sampler: SceneSampler::Random,
            simd: false,
        }
        .ao();
        let mut line = vec![0.0; M_LINE];
        for (a, l) in line.iter_mut().enumerate() {
            let u = (a as f64 + 0.5) / M_LINE as f64;
            *l = world.sample(px, &lines, u, 0.5, &mut scratch)?;
        }
        let lpts: Vec<[f64; 1]> = (0..M_LINE)
            .map(|a| [(a as f64 + 0.5) / M_LINE as f64])
            .collect();
        let lw: Vec<f64> = line.iter().map(|x| x / M_LINE as f64).collect();
        let mut lplan = Plan::<1>::new(K1, TOL)?;
        let mut line_re = vec![0.0; lplan.half_len()];
        let mut line_im = vec![0.0; lplan.half_len()];
        lplan.transform_weighted(&lpts, &lw, &mut line_re, &mut line_im)?;
        Ok(PixelSpectra {
            f,
            re,
            im,
            line,
            line_re,
            line_im,
            mean,
        })
    }

    /// `f_ℓ` on the fine grid: the periodic box filter of width `λ = ℓ/π`
    /// along `v` (linear interpolation of the cumulative sum at fractional
    /// window ends).
    #[must_use]
    pub fn filtered(&self, length: f64) -> Vec<f64> {
        let lam = (length / std::f64::consts::PI).min(1.0);
        let mut out = vec![0.0; M * M];
        if lam >= 1.0 {
            for a in 0..M {
                let row = &self.f[a * M..(a + 1) * M];
                let m = row.iter().sum::<f64>() / M as f64;
                out[a * M..(a + 1) * M].fill(m);
            }
            return out;
        }
        let w = lam * M as f64; // window in cells
        let mut cum = vec![0.0; 3 * M + 1];
        for a in 0..M {
            let row = &self.f[a * M..(a + 1) * M];
            for i in 0..3 * M {
                cum[i + 1] = cum[i] + row[i % M];
            }
            // C(x): integral of the piecewise-constant row from 0 to x cells.
            let c = |x: f64| {
                let i = (x.floor() as usize).min(3 * M - 1);
                cum[i] + (x - i as f64) * row[i % M]
            };
            for b in 0..M {
                // Centre at b + ½ cells, window [b + ½ − w/2, b + ½ + w/2],
                // shifted by M to stay positive.
                let lo = M as f64 + b as f64 + 0.5 - 0.5 * w;
                out[a * M + b] = (c(lo + w) - c(lo)) / w;
            }
        }
        out
    }

    /// The estimator's weights on the 2D half grid (multiplicity times
    /// `|ĝ(j)|²`, 0 at `j = 0`) and its energy beyond the grid, for points or
    /// segments of length `length`.
    #[must_use]
    pub fn weights_2d(&self, primitive: Primitive, length: f64) -> (Vec<f64>, f64) {
        let grid = Grid::<2>::new(K2).expect("K2 is a valid half-width");
        let lam = if primitive == Primitive::Segments {
            (length / std::f64::consts::PI).min(1.0)
        } else {
            0.0
        };
        let mut w = vec![0.0; grid.len()];
        let mut in_grid = 0.0;
        for (i, x) in w.iter_mut().enumerate() {
            let j = grid.freq(i);
            if j != [0, 0] {
                let s = sinc(lam * f64::from(j[1]));
                *x = f64::from(grid.multiplicity(i))
                    * (self.re[i] * self.re[i] + self.im[i] * self.im[i])
                    * s
                    * s;
                in_grid += *x;
            }
        }
        let g = if lam > 0.0 {
            self.filtered(length)
        } else {
            self.f.clone()
        };
        let n = g.len() as f64;
        let mean = g.iter().sum::<f64>() / n;
        let energy = g.iter().map(|x| x * x).sum::<f64>() / n - mean * mean;
        (w, (energy - in_grid).max(0.0))
    }

    /// The lines' weights on the 1D half grid and the energy beyond it.
    #[must_use]
    pub fn weights_1d(&self) -> (Vec<f64>, f64) {
        let grid = Grid::<1>::new(K1).expect("K1 is a valid half-width");
        let mut w = vec![0.0; grid.len()];
        let mut in_grid = 0.0;
        for (i, x) in w.iter_mut().enumerate().skip(1) {
            *x = f64::from(grid.multiplicity(i))
                * (self.line_re[i] * self.line_re[i] + self.line_im[i] * self.line_im[i]);
            in_grid += *x;
        }
        let n = self.line.len() as f64;
        let mean = self.line.iter().sum::<f64>() / n;
        let energy = self.line.iter().map(|x| x * x).sum::<f64>() / n - mean * mean;
        (w, (energy - in_grid).max(0.0))
    }
}

/// `Var = (1/N)(Σ_j ⟨N·P(j)⟩ w(j) + tail)`.
#[must_use]
pub fn predict(np: &[f64], weights: &[f64], tail: f64, n: usize) -> f64 {
    (np.iter().zip(weights).map(|(a, b)| a * b).sum::<f64>() + tail) / n as f64
}

/// A zeroed buffer of `len` values, or [`Error::Alloc`] naming `what`
/// (the grids are large: an error, never an abort).
fn filled(len: usize, what: &'static str) -> Result<Vec<f64>, Error> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| Error::Alloc {
        what,
        bytes: (len as u128) * 8,
    })?;
    v.resize(len, 0.0);
    Ok(v)
}
