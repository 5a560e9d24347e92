//! # linesample-nufft
//!
//! Type-1 non-uniform FFT with real weights, on the periodogram half grid of
//! the `linesample` kernel: the fast (approximate, to a tolerance) path to the
//! amplitudes that [`linesample::spectrum::Dft`] computes exactly.
//!
//! For points x_k ∈ [0,1)^D (D = 1, 2, 3) and real weights c_k this computes
//!
//! ```text
//! F(ν) = Σ_k c_k · exp(−2πi ν·x_k)
//! ```
//!
//! for the integer frequencies ν of the half grid with half-width K
//! (`j0 ∈ [0, K]`, every other axis in `[−K, K]`, last axis fastest); the other
//! half is `F(−ν) = conj F(ν)` because the weights are real.
//!
//! # Method
//!
//! The algorithm is the classical spread / FFT / deconvolve scheme (Dutt &
//! Rokhlin 1993) with the "exponential of semicircle" (ES) kernel of
//! A. H. Barnett, J. Magland and L. af Klinteberg, *A parallel non-uniform fast
//! Fourier transform library based on an "exponential of semicircle" kernel*,
//! SIAM J. Sci. Comput. 41(5), C479–C504 (2019):
//!
//! 1. **Spread.** With `φ(z) = exp(β(√(1−z²) − 1))` for `|z| ≤ 1` (0 outside),
//!    a width of `w` fine-grid cells and `α = w/2`, every point adds
//!    `c_k Π_d φ((n x_{k,d} − l_d)/α)` to the `w^D` nearest nodes `l` of a
//!    periodic fine grid of `n` nodes per axis. The weights are real, so the
//!    fine grid is real and spreading is real-only work.
//! 2. **FFT.** `b̂(ν) = Σ_l b(l) exp(−2πi ν·l/n)`: a real-to-complex FFT along
//!    the last (contiguous) axis, of which only the `K+1` needed outputs are
//!    kept, then complex FFTs along the other axes on those columns only.
//! 3. **Deconvolve.** By Poisson summation
//!    `b̂(ν) ≈ F(ν) Π_d p(ν_d)` with
//!    `p(j) = n Ψ̂(j) = α ∫_{−1}^{1} φ(z) cos(π j w z / n) dz`, so
//!    `F(ν) = b̂(ν) / Π_d p(ν_d)`; `p` is computed once per plan by
//!    Gauss–Legendre quadrature (nodes by Newton's method on the Legendre
//!    recurrence).
//!
//! # Parameters from the tolerance ε (clamped to [1e-14, 1e-1])
//!
//! The aliasing error of the ES kernel decays like `exp(−π w √(1 − 1/σ))`
//! (Barnett et al. 2019, §4), where σ = n / (2K+1) is the upsampling factor:
//!
//! - σ = 2: `w = ⌈log10(2.5/ε)⌉ + 1`, `β = 2.30 w` (the paper's choice; the
//!   general formula below gives 2.29 w);
//! - σ = 5/4: `w = ⌈ln(4/ε) / (π √(1 − 1/σ))⌉`, `β = γ π w (1 − 1/(2σ))` with
//!   `γ = 0.97`.
//!
//! The factors 2.5 and 4 inside the logarithms are measured safety margins:
//! with the paper's plain `1/ε` the relative l2 error reached 2.3ε (σ = 2)
//! and 3ε (σ = 5/4) on the 2D, K = 319 benchmark case (see
//! [`Upsampling::kernel_params`]).
//!
//! `n` is the smallest even `2^a 3^b 5^c ≥ max(σ(2K+1), 2w, 16)`.
//!
//! φ is never evaluated with `exp` while spreading: at plan time each of the
//! `w` taps gets a polynomial in the fractional offset (Chebyshev
//! interpolation converted to monomials in `s = 2t − 1`, degree chosen as
//! the smallest in `[w−1, w+8]` whose measured maximum error is below ε/20),
//! evaluated by Horner's rule four taps at a time (`wide::f64x4`).
//!
//! Measured accuracy against the exact direct sum: relative l2 error
//! ‖F − F_exact‖₂/‖F_exact‖₂ between 0.004ε and 0.35ε in the unit tests
//! (N = 200, K = 20 / 8; they assert ≤ ε) and ≤ 0.8ε on the benchmark cases
//! (examples/nufft_bench.rs), except σ = 5/4 below ε = 1e-9 (rounding
//! floor, see [`Upsampling::FiveQuarters`]), which the automatic choice
//! avoids.
//!
//! # With the kernel
//!
//! [`Plan::transform_into`] writes the amplitudes into the kernel's
//! [`linesample::spectrum::Amplitudes`] and sets its sample count, so the
//! result feeds [`linesample::spectrum::Periodogram::add`] and the ring means
//! of [`linesample::spectrum::AmplitudeView`] through the same code as the
//! direct path:
//!
//! ```
//! use linesample::spectrum::{AmplitudeView, Amplitudes, Grid, Periodogram};
//! use linesample_nufft::Plan;
//!
//! let grid = Grid::<2>::new(16)?;
//! let mut plan = Plan::<2>::new(16, 1e-9)?;
//! let mut amps = Amplitudes::new_vec(grid);
//! let mut mean = Periodogram::new_vec(grid);
//! let pts = [[0.1, 0.7], [0.45, 0.2], [0.8, 0.9]];
//! plan.transform_into(&pts, &mut amps)?;
//! mean.add(&amps)?;
//! let (mut ring, mut count) = (vec![0.0; 17], vec![0u64; 17]);
//! amps.radial_power(&mut ring, &mut count)?;
//! assert!((ring[0] - 3.0).abs() < 1e-8); // DC: |F(0)|²/N = N
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Memory
//!
//! A plan holds a real fine grid of about `n^D` values (`n ≈ σ(2K+1)` per
//! axis, the last axis padded by the kernel width), and in 3D a transpose
//! buffer of `(K+1)(2K+1)·n` complex values. Every such buffer is reserved fallibly: a plan (or a transform's
//! point buffers) too large for memory returns [`NufftError::Alloc`] naming
//! the buffer and its size instead of aborting the process.

#![forbid(unsafe_code)]
#![deny(missing_docs)]

use std::sync::Arc;

use linesample::error::SpectrumError;
use linesample::spectrum::Amplitudes;
use realfft::{RealFftPlanner, RealToComplex};
use rustfft::{num_complex::Complex, Fft, FftPlanner};
use wide::f64x4;

/// Smallest tolerance honoured: `tol` below it is raised to it (double
/// precision rounding in the FFT limits the attainable accuracy to about
/// 1e-14 relative, cf. Barnett et al., SIAM J. Sci. Comput. 2019, §5).
pub const MIN_TOL: f64 = 1e-14;

/// Largest tolerance honoured: `tol` above it is lowered to it.
pub const MAX_TOL: f64 = 1e-1;

/// Upsampling factor σ = n / (2K+1) of the fine grid (Barnett, Magland & af
/// Klinteberg, SIAM J. Sci. Comput. 2019, §4: the ES kernel's aliasing
/// error is about `exp(−π w √(1 − 1/σ))`, so a smaller σ needs a wider kernel
/// `w` but a smaller FFT).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Upsampling {
    /// σ = 2: `w = ⌈log10(2.5/ε)⌉ + 1`, `β = 2.30 w`.
    Two,
    /// σ = 5/4: `w = ⌈ln(4/ε)/(π √(1 − 1/σ))⌉`, `β = 0.97 π w (1 − 1/(2σ))`.
    ///
    /// Only meant for ε ≥ 1e-9: the deconvolution divides by
    /// `Π_d p(ν_d)`, which for σ = 5/4 falls by orders of magnitude between
    /// ν = 0 and ν = K, so FFT rounding errors are amplified by about
    /// `(p(0)/p(K))^D`; measured relative l2 error at ε = 1e-12 (N = 200,
    /// K = 20, n = 54) is 3e-13 in 1D, 5e-11 in 2D and 1.4e-8 in 3D (tested
    /// bounds 1e-10, 1e-10, 1e-7). [`Upsampling::auto`] never picks it below
    /// 1e-9.
    FiveQuarters,
}

impl Upsampling {
    /// The factor σ itself (2 or 1.25).
    pub fn factor(self) -> f64 {
        match self {
            Upsampling::Two => 2.0,
            Upsampling::FiveQuarters => 1.25,
        }
    }

    /// The automatic choice of σ for dimension `d`, half-width `k`, clamped
    /// tolerance `tol` and, if known, the number of points.
    ///
    /// Rule, from the measurements of `examples/nufft_bench.rs` (2D N = 65536,
    /// K = 128; 2D N = 4096, K = 319; 3D N = 4096, K = 32; ε = 1e-3…1e-12):
    ///
    /// 1. `tol < 1e-9` → σ = 2: with σ = 5/4 the deconvolution amplifies
    ///    rounding errors (see [`Upsampling::FiveQuarters`]).
    /// 2. Number of points unknown → σ = 5/4 (it was faster or within 25 %
    ///    in every measured case with `tol ≥ 1e-9`).
    /// 3. Otherwise the cheaper by the measured cost model
    ///    `0.5 ns · N · w^d  (spreading)  +  3.5 ns · n^d  (FFTs)`;
    ///    σ = 2 wins for dense problems (many points per mode, e.g. 2D
    ///    N = 65536, K = 128 at tol ≤ 1e-5).
    pub fn auto(d: usize, k: usize, tol: f64, n_points: Option<usize>) -> Self {
        if tol < 1e-9 {
            return Upsampling::Two;
        }
        let Some(np) = n_points else {
            return Upsampling::FiveQuarters;
        };
        let cost = |s: Upsampling| {
            let (w, _) = s.kernel_params(tol);
            let n = fine_size_for(k, w, s) as f64;
            0.5 * np as f64 * (w as f64).powi(d as i32) + 3.5 * n.powi(d as i32)
        };
        if cost(Upsampling::Two) < cost(Upsampling::FiveQuarters) {
            Upsampling::Two
        } else {
            Upsampling::FiveQuarters
        }
    }

    /// Kernel width `w` (fine-grid cells) and shape parameter β for the
    /// clamped tolerance `tol`: the smallest `w` whose predicted relative
    /// error `A · r^{−w}` is at most `tol`, with the decay rate `r` of
    /// Barnett et al. (SIAM J. Sci. Comput. 2019, §4) and the prefactor `A`
    /// measured on this crate's benchmark cases (2D, K = 319, σ_eff ≈ σ):
    ///
    /// - σ = 2: error ≈ 2.5 · 10^{1−w}, so `w = ⌈log10(2.5/ε)⌉ + 1`,
    ///   `β = 2.30 w`;
    /// - σ = 5/4: error ≈ 4 · exp(−π w √(1 − 1/σ)), so
    ///   `w = ⌈ln(4/ε) / (π √(1 − 1/σ))⌉`, `β = 0.97 π w (1 − 1/(2σ))`.
    ///
    /// (The paper's rules without the prefactor, `w = ⌈log10(1/ε)⌉ + 1` and
    /// `⌈ln(1/ε)/(π√(1−1/σ))⌉`, gave errors up to 2.3ε and 3ε here.)
    pub fn kernel_params(self, tol: f64) -> (usize, f64) {
        match self {
            Upsampling::Two => {
                let w = ((2.5 / tol).log10().ceil() as usize + 1).max(2);
                (w, 2.30 * w as f64)
            }
            Upsampling::FiveQuarters => {
                let s = self.factor();
                let rate = core::f64::consts::PI * (1.0 - 1.0 / s).sqrt();
                let w = (((4.0 / tol).ln() / rate).ceil() as usize).max(2);
                let beta = 0.97 * core::f64::consts::PI * w as f64 * (1.0 - 0.5 / s);
                (w, beta)
            }
        }
    }
}

/// The ES kernel φ(z) = exp(β(√(1−z²) − 1)) for |z| ≤ 1, else 0 (Barnett et
/// al., SIAM J. Sci. Comput. 2019, eq. (1.8)), normalised so that φ(0) = 1.
pub fn es_kernel(z: f64, beta: f64) -> f64 {
    if z.abs() >= 1.0 {
        if z.abs() == 1.0 {
            (-beta).exp()
        } else {
            0.0
        }
    } else {
        (beta * ((1.0 - z * z).sqrt() - 1.0)).exp()
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1] with `q` points (exact for
/// polynomials of degree 2q − 1), by Newton's method on the three-term
/// recurrence `(m+1) P_{m+1} = (2m+1) x P_m − m P_{m−1}`.
pub fn gauss_legendre(q: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; q];
    let mut wt = vec![0.0; q];
    let qf = q as f64;
    for i in 0..q.div_ceil(2) {
        // Tricomi's initial guess for the i-th largest root.
        let mut z = (core::f64::consts::PI * (i as f64 + 0.75) / (qf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for m in 1..q {
                let mf = m as f64;
                let p2 = ((2.0 * mf + 1.0) * z * p1 - mf * p0) / (mf + 1.0);
                p0 = p1;
                p1 = p2;
            }
            // P'_q(z) = q (z P_q − P_{q−1}) / (z² − 1)
            dp = qf * (z * p1 - p0) / (z * z - 1.0);
            let dz = p1 / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        // Recompute P'_q at the converged root for the weight.
        let (mut p0, mut p1) = (1.0, z);
        for m in 1..q {
            let mf = m as f64;
            let p2 = ((2.0 * mf + 1.0) * z * p1 - mf * p0) / (mf + 1.0);
            p0 = p1;
            p1 = p2;
        }
        if q > 1 {
            dp = qf * (z * p1 - p0) / (z * z - 1.0);
        }
        let w = 2.0 / ((1.0 - z * z) * dp * dp);
        x[i] = z;
        x[q - 1 - i] = -z;
        wt[i] = w;
        wt[q - 1 - i] = w;
    }
    (x, wt)
}

/// Per-tap piecewise polynomial of the ES kernel, SIMD-ready.
struct Kernel {
    w: usize,
    beta: f64,
    /// Number of `f64x4` lanes groups: taps padded to `4 nv ≥ w`.
    nv: usize,
    degree: usize,
    /// `coeffs[k * nv + v]` holds the coefficient of `s^k` for taps
    /// `4v .. 4v + 4` (zero for padding taps).
    coeffs: Vec<f64x4>,
    /// Measured max |poly − φ| over all taps.
    fit_error: f64,
}

impl Kernel {
    /// Tap `j` of a point whose left-most tap sits `t ∈ [0,1)` cells right of
    /// `u − α` has argument `z = (t + j)·(2/w) − 1`; `s = 2t − 1`.
    fn tap_z(w: usize, j: usize, s: f64) -> f64 {
        ((s + 1.0) * 0.5 + j as f64) * (2.0 / w as f64) - 1.0
    }

    fn new(w: usize, beta: f64, tol: f64) -> Self {
        let nv = w.div_ceil(4);
        let target = (tol / 20.0).max(2e-16);
        let mut best: Option<(usize, Vec<f64>, f64)> = None;
        for degree in w.saturating_sub(1).max(3)..=w + 8 {
            let mono = Self::fit(w, beta, degree);
            let err = Self::max_error(w, beta, degree, &mono);
            let better = best.as_ref().is_none_or(|b| err < b.2);
            if better {
                best = Some((degree, mono, err));
            }
            if err <= target {
                break;
            }
        }
        let (degree, mono, fit_error) = best.expect("at least one degree tried");
        let mut coeffs = vec![f64x4::ZERO; (degree + 1) * nv];
        for k in 0..=degree {
            for v in 0..nv {
                let mut lanes = [0.0; 4];
                for (l, lane) in lanes.iter_mut().enumerate() {
                    let j = 4 * v + l;
                    if j < w {
                        *lane = mono[j * (degree + 1) + k];
                    }
                }
                coeffs[k * nv + v] = f64x4::new(lanes);
            }
        }
        Kernel {
            w,
            beta,
            nv,
            degree,
            coeffs,
            fit_error,
        }
    }

    /// Monomial coefficients (in s ∈ [−1,1]) of the degree-`degree`
    /// Chebyshev interpolant of every tap, `mono[j * (degree+1) + k]`.
    fn fit(w: usize, beta: f64, degree: usize) -> Vec<f64> {
        let m = degree + 1;
        let pi = core::f64::consts::PI;
        let nodes: Vec<f64> = (0..m)
            .map(|i| (pi * (i as f64 + 0.5) / m as f64).cos())
            .collect();
        let mut mono = vec![0.0; w * m];
        for j in 0..w {
            let f: Vec<f64> = nodes
                .iter()
                .map(|&s| es_kernel(Self::tap_z(w, j, s), beta))
                .collect();
            // Chebyshev coefficients a_k = (2/m) Σ_i f_i cos(π k (i+½)/m).
            let a: Vec<f64> = (0..m)
                .map(|k| {
                    let sum: f64 = f
                        .iter()
                        .enumerate()
                        .map(|(i, fi)| fi * (pi * k as f64 * (i as f64 + 0.5) / m as f64).cos())
                        .sum();
                    sum * 2.0 / m as f64 * if k == 0 { 0.5 } else { 1.0 }
                })
                .collect();
            // Σ a_k T_k(s) in monomials, T_{k+1} = 2 s T_k − T_{k−1}.
            let mut t_prev = vec![0.0; m];
            let mut t_cur = vec![0.0; m];
            t_prev[0] = 1.0;
            let out = &mut mono[j * m..(j + 1) * m];
            out[0] += a[0];
            if m > 1 {
                t_cur[1] = 1.0;
                out[1] += a[1];
            }
            for ak in a.iter().skip(2) {
                let mut t_next = vec![0.0; m];
                for i in 0..m {
                    let up = if i > 0 { 2.0 * t_cur[i - 1] } else { 0.0 };
                    t_next[i] = up - t_prev[i];
                }
                for i in 0..m {
                    out[i] += ak * t_next[i];
                }
                t_prev = t_cur;
                t_cur = t_next;
            }
        }
        mono
    }

    fn max_error(w: usize, beta: f64, degree: usize, mono: &[f64]) -> f64 {
        let m = degree + 1;
        let mut err: f64 = 0.0;
        for j in 0..w {
            let c = &mono[j * m..(j + 1) * m];
            for i in 0..=200 {
                let s = -1.0 + 2.0 * i as f64 / 200.0;
                let p = c.iter().rev().fold(0.0, |acc, &ck| acc * s + ck);
                err = err.max((p - es_kernel(Self::tap_z(w, j, s), beta)).abs());
            }
        }
        err
    }
}

/// Horner evaluation of all taps at `s`, four taps per `f64x4` (multiply and
/// add unfused, as in `axpy_row`: `wide`'s `mul_add` is fused only where FMA
/// is enabled at compile time, so a fused step would change the bits with the
/// build).
#[inline(always)]
fn horner<const NV: usize>(coeffs: &[f64x4], degree: usize, s: f64) -> [f64x4; NV] {
    let sv = f64x4::splat(s);
    let top = &coeffs[degree * NV..degree * NV + NV];
    let mut acc: [f64x4; NV] = core::array::from_fn(|v| top[v]);
    for k in (0..degree).rev() {
        let c = &coeffs[k * NV..k * NV + NV];
        for v in 0..NV {
            acc[v] = acc[v] * sv + c[v];
        }
    }
    acc
}

/// `row[0 .. 4 NV] += a · ker`.
#[inline(always)]
fn axpy_row<const NV: usize>(row: &mut [f64], a: f64, ker: &[f64x4; NV]) {
    let av = f64x4::splat(a);
    for (chunk, kv) in row.chunks_exact_mut(4).zip(ker.iter()) {
        let g = f64x4::new([chunk[0], chunk[1], chunk[2], chunk[3]]);
        let r = *kv * av + g;
        chunk.copy_from_slice(&r.to_array());
    }
}

/// Geometry of the padded real fine grid: `n` nodes per axis, the last axis
/// stored with `pad` extra nodes on each side (folded back periodically
/// before the FFT) so that a point's taps along it are one contiguous run.
#[derive(Clone, Copy)]
struct Geometry {
    n: usize,
    pad: usize,
    row_len: usize,
    half_w: f64,
    w: usize,
}

#[inline(always)]
fn wrap(i: isize, n: usize) -> usize {
    let n = n as isize;
    let r = if i < 0 {
        i + n
    } else if i >= n {
        i - n
    } else {
        i
    };
    r as usize
}

/// Spread all points (already wrapped to [0,1)) onto the padded fine grid.
fn spread<const D: usize, const NV: usize>(
    grid: &mut [f64],
    g: Geometry,
    kernel: &Kernel,
    points: &[[f64; D]],
    weights: Option<&[f64]>,
    order: &[u32],
) {
    let nf = g.n as f64;
    let coeffs = &kernel.coeffs[..];
    let degree = kernel.degree;
    for &idx in order {
        let idx = idx as usize;
        let p = &points[idx];
        let c = weights.map_or(1.0, |ws| ws[idx]);
        let mut start = [0isize; D];
        let mut ker = [[f64x4::ZERO; NV]; D];
        for d in 0..D {
            let a = p[d] * nf - g.half_w;
            let l = a.ceil();
            let t = l - a;
            start[d] = l as isize;
            ker[d] = horner::<NV>(coeffs, degree, 2.0 * t - 1.0);
        }
        let last = &ker[D - 1];
        let col = (g.pad as isize + start[D - 1]) as usize;
        match D {
            1 => axpy_row::<NV>(&mut grid[col..col + 4 * NV], c, last),
            2 => {
                let k0: [[f64; 4]; NV] = ker[0].map(|v| v.to_array());
                for i in 0..g.w {
                    let r = wrap(start[0] + i as isize, g.n);
                    let off = r * g.row_len + col;
                    axpy_row::<NV>(&mut grid[off..off + 4 * NV], c * k0[i / 4][i % 4], last);
                }
            }
            _ => {
                let k0: [[f64; 4]; NV] = ker[0].map(|v| v.to_array());
                let k1: [[f64; 4]; NV] = ker[1].map(|v| v.to_array());
                for i in 0..g.w {
                    let r0 = wrap(start[0] + i as isize, g.n);
                    let a0 = c * k0[i / 4][i % 4];
                    for j in 0..g.w {
                        let r1 = wrap(start[1] + j as isize, g.n);
                        let off = (r0 * g.n + r1) * g.row_len + col;
                        axpy_row::<NV>(&mut grid[off..off + 4 * NV], a0 * k1[j / 4][j % 4], last);
                    }
                }
            }
        }
    }
}

/// Edge, in fine-grid cells, of the cubical bins points are sorted into
/// before spreading (so consecutive points touch nearby grid rows).
const BIN: usize = 16;

/// Counting sort of the point indices by bin (row-major, last axis fastest).
/// `counts` has one entry per bin plus one (allocated with the plan); `order`
/// grows to the number of points, fallibly.
fn bin_order<const D: usize>(
    points: &[[f64; D]],
    n: usize,
    order: &mut Vec<u32>,
    counts: &mut [u32],
) -> Result<(), NufftError> {
    let nb = n.div_ceil(BIN);
    let scale = n as f64 / BIN as f64;
    let key = |p: &[f64; D]| {
        p.iter().fold(0usize, |acc, &x| {
            acc * nb + ((x * scale) as usize).min(nb - 1)
        })
    };
    order.clear();
    try_reserve(order, "point order", points.len())?;
    counts.fill(0);
    for p in points {
        counts[key(p) + 1] += 1;
    }
    for b in 1..counts.len() {
        counts[b] += counts[b - 1];
    }
    order.resize(points.len(), 0);
    for (i, p) in points.iter().enumerate() {
        let slot = &mut counts[key(p)];
        order[*slot as usize] = i as u32;
        *slot += 1;
    }
    Ok(())
}

/// Reserves room for `additional` more elements of `v` without aborting on
/// failure: a [`NufftError::Alloc`] naming the buffer and its size instead.
fn try_reserve<T>(v: &mut Vec<T>, what: &'static str, additional: usize) -> Result<(), NufftError> {
    v.try_reserve_exact(additional)
        .map_err(|_| NufftError::Alloc {
            what,
            bytes: (additional as u128) * (core::mem::size_of::<T>() as u128),
        })
}

/// A `Vec` of `Π factors` copies of `value`, reserved fallibly: the length and
/// the byte count are formed in checked `u128` arithmetic, and a length that
/// does not fit in `usize` (or overflows) or memory the allocator refuses is a
/// [`NufftError::Alloc`] naming the buffer (`bytes` saturates at `u128::MAX`)
/// instead of an abort.
fn try_vec<T: Clone>(what: &'static str, factors: &[u128], value: T) -> Result<Vec<T>, NufftError> {
    let len = factors.iter().try_fold(1u128, |a, &f| a.checked_mul(f));
    let bytes = len
        .and_then(|l| l.checked_mul(core::mem::size_of::<T>() as u128))
        .unwrap_or(u128::MAX);
    let err = NufftError::Alloc { what, bytes };
    let len = len
        .and_then(|l| usize::try_from(l).ok())
        .ok_or_else(|| err.clone())?;
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| err)?;
    v.resize(len, value);
    Ok(v)
}

/// Rows transformed per real-to-complex batch before the transposed write.
const BLOCK: usize = 32;

/// Wall-clock split of the last [`Plan::transform`] call, in seconds.
#[derive(Clone, Copy, Debug, Default)]
pub struct PhaseTimes {
    /// Binning the points and spreading them onto the fine grid.
    pub spread: f64,
    /// Folding (and clearing) the padded rows, real-to-complex and complex
    /// FFTs, transposes.
    pub fft: f64,
    /// Deconvolution and the Hermitian read-out into the output.
    pub deconvolve: f64,
}

/// A reusable type-1 NUFFT plan for dimension `D` ∈ {1, 2, 3}, half-width `K`
/// and tolerance ε: computes `F(ν) = Σ_k c_k exp(−2πi ν·x_k)` on the half
/// grid (see the module documentation) by ES-kernel spreading, FFT and
/// deconvolution (Barnett, Magland & af Klinteberg, SIAM J. Sci. Comput.
/// 41(5), 2019). Holds the FFT plans, the kernel's polynomial tables, the
/// deconvolution factors and all scratch, so `transform` does not allocate.
pub struct Plan<const D: usize> {
    k: usize,
    tol: f64,
    sigma: Upsampling,
    kernel: Kernel,
    geom: Geometry,
    /// `1 / p(j)` for `j ∈ [0, K]`, `p(j) = α ∫ φ(z) cos(π j w z/n) dz`.
    deconv: Vec<f64>,
    grid: Vec<f64>,
    r2c: Arc<dyn RealToComplex<f64>>,
    fft: Arc<dyn Fft<f64>>,
    rin: Vec<f64>,
    rout: Vec<Complex<f64>>,
    rscratch: Vec<Complex<f64>>,
    t1: Vec<Complex<f64>>,
    t2: Vec<Complex<f64>>,
    fscratch: Vec<Complex<f64>>,
    order: Vec<u32>,
    /// Points per spreading bin (`⌈n/16⌉^D + 1` entries).
    counts: Vec<u32>,
    times: PhaseTimes,
}

/// The smallest even `2^a 3^b 5^c ≥ max(m, 2)`, by enumerating the exponents
/// (`O(log² m)` steps for any `m`, so a huge `K` cannot make plan time grow
/// with the gaps between such numbers). Products stay below `5·max(m, 2)`.
fn next_smooth_even(m: u128) -> u128 {
    let m = m.max(2);
    let mut best = u128::MAX;
    let mut p2 = 2u128;
    loop {
        let mut p23 = p2;
        loop {
            let mut p = p23;
            while p < m {
                p *= 5;
            }
            best = best.min(p);
            if p23 >= m {
                break;
            }
            p23 *= 3;
        }
        if p2 >= m {
            break;
        }
        p2 *= 2;
    }
    best
}

/// Fine-grid size per axis: smallest even `2^a 3^b 5^c ≥ max(σ(2K+1), 2w, 16)`
/// (the padding of the last axis, `4⌈w/4⌉`, is then at most n/2). In `u128`,
/// so that no `K` overflows it; plans check that the buffers it implies fit.
fn fine_size_for(k: usize, w: usize, sigma: Upsampling) -> u128 {
    let pad = 4 * w.div_ceil(4);
    let modes = 2 * k as u128 + 1;
    next_smooth_even(
        ((sigma.factor() * modes as f64).ceil() as u128)
            .max(2 * w as u128)
            .max(2 * pad as u128)
            .max(16),
    )
}

/// What a [`Plan`] rejects; every message names the parameter. The errors
/// it shares with the direct path (dimension, buffer lengths, non-finite
/// weights) are the kernel's [`SpectrumError`]. Converts into the kernel's
/// one error, [`linesample::Error`] (as [`linesample::Error::Other`], boxed),
/// so `?` mixes it with the kernel's errors.
#[derive(Clone, Debug, PartialEq)]
pub enum NufftError {
    /// `tol` is NaN, zero or negative.
    Tolerance(f64),
    /// More than `2^32 − 1` points.
    TooManyPoints(usize),
    /// Coordinate `axis` of point `index` is NaN or infinite (`value`).
    NonFinitePoint {
        /// Index of the point.
        index: usize,
        /// The coordinate axis.
        axis: usize,
        /// The offending value.
        value: f64,
    },
    /// `name`'s grid has half-width `got`, the plan's is `expected`.
    HalfWidth {
        /// Parameter name.
        name: &'static str,
        /// The plan's half-width `K`.
        expected: usize,
        /// The half-width of the argument's grid.
        got: usize,
    },
    /// The buffer `what` of `bytes` bytes could not be allocated (the
    /// allocator refused it, or its size does not fit in the address space;
    /// `bytes` is then `u128::MAX` if even the count overflows). Returned
    /// instead of aborting when a plan is too large for memory.
    Alloc {
        /// Which buffer (e.g. `"fine grid"`).
        what: &'static str,
        /// Its size in bytes.
        bytes: u128,
    },
    /// An error the direct path reports too.
    Spectrum(SpectrumError),
}

impl core::fmt::Display for NufftError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            NufftError::Tolerance(t) => write!(f, "tol must be a positive number, got {t}"),
            NufftError::TooManyPoints(n) => write!(f, "points: at most 2^32 − 1 points, got {n}"),
            NufftError::NonFinitePoint { index, axis, value } => {
                write!(f, "points[{index}][{axis}] = {value} is not finite")
            }
            NufftError::HalfWidth {
                name,
                expected,
                got,
            } => write!(
                f,
                "{name}: grid of half-width {got}, but the plan has half-width {expected}"
            ),
            NufftError::Alloc { what, bytes } => {
                if *bytes == u128::MAX {
                    write!(f, "cannot allocate the {what}: its size overflows")
                } else {
                    write!(f, "cannot allocate the {what} ({bytes} bytes)")
                }
            }
            NufftError::Spectrum(e) => e.fmt(f),
        }
    }
}

impl From<SpectrumError> for NufftError {
    fn from(e: SpectrumError) -> Self {
        NufftError::Spectrum(e)
    }
}

impl std::error::Error for NufftError {}

/// A NUFFT error as the kernel's [`linesample::Error::Other`] (boxed, with the
/// same text; `downcast_ref::<NufftError>()` recovers it): the kernel cannot
/// name this crate's types, so its one error holds them boxed.
impl From<NufftError> for linesample::Error {
    fn from(e: NufftError) -> Self {
        linesample::Error::other(e)
    }
}

fn check_tol(tol: f64) -> Result<f64, NufftError> {
    if tol.is_nan() || tol <= 0.0 {
        return Err(NufftError::Tolerance(tol));
    }
    Ok(tol.clamp(MIN_TOL, MAX_TOL))
}

impl<const D: usize> Plan<D> {
    /// Plan for half-width `k` and tolerance `tol` (clamped to
    /// [[`MIN_TOL`], [`MAX_TOL`]]) with the upsampling factor chosen by
    /// [`Upsampling::auto`]. Errors if `tol` is NaN or not positive, or if
    /// `D ∉ {1,2,3}`. Method: Barnett, Magland & af Klinteberg, SIAM J. Sci.
    /// Comput. 2019.
    pub fn new(k: usize, tol: f64) -> Result<Self, NufftError> {
        let t = check_tol(tol)?;
        Self::with_upsampling(k, tol, Upsampling::auto(D, k, t, None))
    }

    /// As [`Plan::new`], but σ is chosen knowing the number of points the
    /// plan will mostly be used with ([`Upsampling::auto`]'s cost model).
    pub fn new_for_points(k: usize, tol: f64, n_points: usize) -> Result<Self, NufftError> {
        let t = check_tol(tol)?;
        Self::with_upsampling(k, tol, Upsampling::auto(D, k, t, Some(n_points)))
    }

    /// Plan with an explicit upsampling factor σ: fine grid
    /// `n = ` smallest even `2^a 3^b 5^c ≥ max(σ(2K+1), 2w, 16)` per axis,
    /// kernel width and β from [`Upsampling::kernel_params`] (Barnett et al.,
    /// SIAM J. Sci. Comput. 2019, §4).
    ///
    /// Every buffer whose size grows with `K` (the fine grid, the FFT row
    /// blocks, the transpose buffers, the deconvolution table, the spreading
    /// bins, the FFT scratch) is reserved fallibly, largest first, before the
    /// FFTs are planned: a plan too large for memory is a
    /// [`NufftError::Alloc`] naming the buffer and its size, not an abort.
    /// (The FFT planners' own twiddle tables, `O(n)` values, are allocated
    /// by `realfft`/`rustfft`.)
    pub fn with_upsampling(k: usize, tol: f64, sigma: Upsampling) -> Result<Self, NufftError> {
        if !(1..=3).contains(&D) {
            return Err(SpectrumError::Dimension { dim: D }.into());
        }
        let tol = check_tol(tol)?;
        let (w, beta) = sigma.kernel_params(tol);
        let kernel = Kernel::new(w, beta, tol);
        let pad = 4 * kernel.nv;
        let n_wide = fine_size_for(k, w, sigma);
        // Sizes in u128: (K + 1), 2K + 1, n, n + 2·pad and their products
        // cannot overflow silently (try_vec checks every product).
        let (k1, modes) = (k as u128 + 1, 2 * k as u128 + 1);
        let row_len = n_wide + 2 * pad as u128;
        let rows_total = (1..D).try_fold(1u128, |a, _| a.checked_mul(n_wide));
        let grid = try_vec(
            "fine grid",
            &[rows_total.unwrap_or(u128::MAX), row_len],
            0.0f64,
        )?;
        // The fine grid holds n^D values, so n, K and everything below fit in
        // usize from here on (n ≥ 2K + 1).
        let n = usize::try_from(n_wide).map_err(|_| NufftError::Alloc {
            what: "fine grid",
            bytes: u128::MAX,
        })?;
        let (t1_dims, t2_dims): (&[u128], &[u128]) = match D {
            1 => (&[0], &[0]),
            2 => (&[k1, n_wide], &[0]),
            _ => (&[k1, n_wide], &[k1, modes, n_wide]),
        };
        let t2 = try_vec("3D transpose buffer", t2_dims, Complex::default())?;
        let t1 = try_vec("transpose buffer", t1_dims, Complex::default())?;
        let rin = try_vec("FFT input rows", &[BLOCK as u128, n_wide], 0.0f64)?;
        let half = n / 2 + 1;
        let rout = try_vec(
            "FFT output rows",
            &[BLOCK as u128, half as u128],
            Complex::default(),
        )?;
        let bins = n.div_ceil(BIN) as u128;
        let bins_total = (0..D).try_fold(1u128, |a, _| a.checked_mul(bins));
        let counts = try_vec(
            "spreading bins",
            &[bins_total.map_or(u128::MAX, |b| b.saturating_add(1))],
            0u32,
        )?;
        let mut deconv = try_vec("deconvolution table", &[k1], 0.0f64)?;
        let geom = Geometry {
            n,
            pad,
            row_len: n + 2 * pad,
            half_w: w as f64 / 2.0,
            w,
        };
        // p(j) = α ∫_{−1}^{1} φ(z) cos(π j w z / n) dz = 2α ∫_0^1 (…) dz.
        let q = 4 * w + 40;
        let (xs, ws) = gauss_legendre(q);
        let alpha = w as f64 / 2.0;
        let zw: Vec<(f64, f64)> = xs
            .iter()
            .zip(&ws)
            .map(|(&x, &wt)| {
                let z = 0.5 * (x + 1.0);
                (z, 0.5 * wt * es_kernel(z, beta))
            })
            .collect();
        for (j, d) in deconv.iter_mut().enumerate() {
            let a = core::f64::consts::PI * j as f64 * w as f64 / n as f64;
            let s: f64 = zw.iter().map(|&(z, fw)| fw * (a * z).cos()).sum();
            *d = 1.0 / (2.0 * alpha * s);
        }
        let r2c = RealFftPlanner::<f64>::new().plan_fft_forward(n);
        let fft = FftPlanner::<f64>::new().plan_fft_forward(n);
        let rscratch = try_vec(
            "FFT scratch",
            &[r2c.get_scratch_len() as u128],
            Complex::default(),
        )?;
        let fscratch = try_vec(
            "FFT scratch",
            &[fft.get_inplace_scratch_len() as u128],
            Complex::default(),
        )?;
        Ok(Plan {
            k,
            tol,
            sigma,
            kernel,
            geom,
            deconv,
            grid,
            r2c,
            fft,
            rin,
            rout,
            rscratch,
            t1,
            t2,
            fscratch,
            order: Vec::new(),
            counts,
            times: PhaseTimes::default(),
        })
    }

    /// Output length: `K+1`, `(K+1)(2K+1)` or `(K+1)(2K+1)²` for D = 1, 2, 3.
    pub fn half_len(&self) -> usize {
        (self.k + 1) * (2 * self.k + 1).pow(D as u32 - 1)
    }

    /// Half-width K of the frequency grid.
    pub fn half_width(&self) -> usize {
        self.k
    }

    /// Kernel width `w` in fine-grid cells (Barnett et al. 2019, §4).
    pub fn kernel_width(&self) -> usize {
        self.kernel.w
    }

    /// ES shape parameter β of φ(z) = exp(β(√(1−z²) − 1)).
    pub fn beta(&self) -> f64 {
        self.kernel.beta
    }

    /// Degree of the per-tap polynomials approximating φ.
    pub fn poly_degree(&self) -> usize {
        self.kernel.degree
    }

    /// Maximum error of the per-tap polynomials against φ (measured at plan
    /// time on 201 offsets per tap).
    pub fn poly_error(&self) -> f64 {
        self.kernel.fit_error
    }

    /// Fine-grid size `n` per axis (even `2^a 3^b 5^c ≥ σ(2K+1)`).
    pub fn fine_size(&self) -> usize {
        self.geom.n
    }

    /// Upsampling factor in use.
    pub fn upsampling(&self) -> Upsampling {
        self.sigma
    }

    /// Clamped tolerance in use.
    pub fn tolerance(&self) -> f64 {
        self.tol
    }

    /// Phase timings of the last transform (spread, FFT, deconvolve).
    pub fn phase_times(&self) -> PhaseTimes {
        self.times
    }

    /// `F(ν) = Σ_k exp(−2πi ν·x_k)` (all weights 1) on the half grid into
    /// `re`, `im` (each of length [`Plan::half_len`]). Points are wrapped into
    /// [0,1) by `x − ⌊x⌋`; a non-finite coordinate is an error. Method:
    /// Barnett, Magland & af Klinteberg, SIAM J. Sci. Comput. 2019.
    ///
    /// # Errors
    /// [`NufftError::NonFinitePoint`], [`NufftError::TooManyPoints`], a
    /// [`SpectrumError::Length`] naming `re` or `im`, and
    /// [`NufftError::Alloc`] if the per-transform point buffers (the spreading
    /// order, `4·N` bytes, and for points outside `[0, 1)` their wrapped copy)
    /// cannot be allocated. `re` and `im` are unchanged on error.
    pub fn transform(
        &mut self,
        points: &[[f64; D]],
        re: &mut [f64],
        im: &mut [f64],
    ) -> Result<(), NufftError> {
        self.run(points, None, re, im)
    }

    /// `F(ν) = Σ_k c_k exp(−2πi ν·x_k)` with real weights `c_k = weights[k]`
    /// on the half grid (as [`Plan::transform`]); `weights` must have one
    /// finite entry per point. Weights near the `f64` range (`|c| ≳ 1e300`)
    /// can overflow the spread grid to `±∞`/NaN; scale them first (the
    /// transform is linear).
    pub fn transform_weighted(
        &mut self,
        points: &[[f64; D]],
        weights: &[f64],
        re: &mut [f64],
        im: &mut [f64],
    ) -> Result<(), NufftError> {
        if weights.len() != points.len() {
            return Err(SpectrumError::Length {
                name: "weights",
                expected: points.len(),
                got: weights.len(),
            }
            .into());
        }
        if let Some(i) = weights.iter().position(|c| !c.is_finite()) {
            return Err(SpectrumError::NonFinite {
                name: "weights",
                index: i,
            }
            .into());
        }
        self.run(points, Some(weights), re, im)
    }

    /// `F(ν) = Σ_k exp(−2πi ν·x_k)` (all weights 1) on the half grid into the
    /// kernel's amplitude view `out` (as [`Plan::transform`]), whose sample
    /// count is set to `points.len()`: `out` then feeds
    /// [`linesample::spectrum::Periodogram::add`] and
    /// [`linesample::spectrum::AmplitudeView::radial_power`] exactly like a
    /// [`linesample::spectrum::Dft`] of the same points, to the plan's
    /// tolerance.
    ///
    /// # Errors
    /// [`NufftError::HalfWidth`] naming `out` if `out`'s grid is not the
    /// plan's half-width; as [`Plan::transform`]. `out` is unchanged on error.
    pub fn transform_into<B: AsRef<[f64]> + AsMut<[f64]>>(
        &mut self,
        points: &[[f64; D]],
        out: &mut Amplitudes<D, B>,
    ) -> Result<(), NufftError> {
        self.check_out(out)?;
        let (re, im) = out.parts_mut();
        self.run(points, None, re, im)?;
        out.set_count(points.len() as u64);
        Ok(())
    }

    /// [`Plan::transform_weighted`] into the kernel's amplitude view `out`,
    /// whose sample count is set to `points.len()` (the normalisation `N` of
    /// `|F|²/N`, as for the direct path's weighted samples, segments).
    ///
    /// # Errors
    /// As [`Plan::transform_into`] and [`Plan::transform_weighted`]. `out` is
    /// unchanged on error.
    pub fn transform_weighted_into<B: AsRef<[f64]> + AsMut<[f64]>>(
        &mut self,
        points: &[[f64; D]],
        weights: &[f64],
        out: &mut Amplitudes<D, B>,
    ) -> Result<(), NufftError> {
        self.check_out(out)?;
        let (re, im) = out.parts_mut();
        self.transform_weighted(points, weights, re, im)?;
        out.set_count(points.len() as u64);
        Ok(())
    }

    fn check_out<B>(&self, out: &Amplitudes<D, B>) -> Result<(), NufftError> {
        let got = out.grid().half_width();
        if got == self.k {
            Ok(())
        } else {
            Err(NufftError::HalfWidth {
                name: "out",
                expected: self.k,
                got,
            })
        }
    }

    fn run(
        &mut self,
        points: &[[f64; D]],
        weights: Option<&[f64]>,
        re: &mut [f64],
        im: &mut [f64],
    ) -> Result<(), NufftError> {
        let len = self.half_len();
        if points.len() > u32::MAX as usize {
            return Err(NufftError::TooManyPoints(points.len()));
        }
        for (name, got) in [("re", re.len()), ("im", im.len())] {
            if got != len {
                return Err(SpectrumError::Length {
                    name,
                    expected: len,
                    got,
                }
                .into());
            }
        }
        let t0 = std::time::Instant::now();
        // The grid is all zero here: zeroed at plan time, and every row is
        // cleared when it is folded into the FFT input.
        let in_unit = points
            .iter()
            .all(|p| p.iter().all(|&x| (0.0..1.0).contains(&x)));
        if in_unit {
            self.spread_dispatch(points, weights)?;
        } else {
            let mut wrapped = Vec::new();
            try_reserve(&mut wrapped, "wrapped points", points.len())?;
            for (i, p) in points.iter().enumerate() {
                let mut q = *p;
                for (d, x) in q.iter_mut().enumerate() {
                    if !x.is_finite() {
                        return Err(NufftError::NonFinitePoint {
                            index: i,
                            axis: d,
                            value: *x,
                        });
                    }
                    *x = linesample::num::frac(*x);
                }
                wrapped.push(q);
            }
            self.spread_dispatch(&wrapped, weights)?;
        }
        let t1 = std::time::Instant::now();
        match D {
            1 => self.fft_1d(re, im),
            2 => self.fft_2d(re, im),
            _ => self.fft_3d(re, im),
        }
        let t2 = std::time::Instant::now();
        self.times.spread = (t1 - t0).as_secs_f64();
        self.times.fft = (t2 - t1).as_secs_f64() - self.times.deconvolve;
        Ok(())
    }

    fn spread_dispatch(
        &mut self,
        points: &[[f64; D]],
        weights: Option<&[f64]>,
    ) -> Result<(), NufftError> {
        bin_order(points, self.geom.n, &mut self.order, &mut self.counts)?;
        let (g, kr, grid) = (self.geom, &self.kernel, &mut self.grid[..]);
        let o = &self.order[..];
        match kr.nv {
            1 => spread::<D, 1>(grid, g, kr, points, weights, o),
            2 => spread::<D, 2>(grid, g, kr, points, weights, o),
            3 => spread::<D, 3>(grid, g, kr, points, weights, o),
            4 => spread::<D, 4>(grid, g, kr, points, weights, o),
            5 => spread::<D, 5>(grid, g, kr, points, weights, o),
            6 => spread::<D, 6>(grid, g, kr, points, weights, o),
            _ => unreachable!("kernel width is at most 24"),
        }
        Ok(())
    }

    /// Fold padded row `r` periodically into `out` (length n) and clear the
    /// row, so the grid is all zero again for the next transform without a
    /// separate pass over memory.
    fn fold_row(grid: &mut [f64], g: Geometry, r: usize, out: &mut [f64]) {
        let row = &mut grid[r * g.row_len..(r + 1) * g.row_len];
        let (n, pad) = (g.n, g.pad);
        out.copy_from_slice(&row[pad..pad + n]);
        for q in 0..pad {
            out[n - pad + q] += row[q];
            out[q] += row[pad + n + q];
        }
        row.fill(0.0);
    }

    /// Real-to-complex FFT of padded rows `r0 .. r0+b` into `rout` rows.
    fn r2c_rows(&mut self, r0: usize, b: usize) {
        let n = self.geom.n;
        let half = n / 2 + 1;
        for i in 0..b {
            let inp = &mut self.rin[i * n..(i + 1) * n];
            Self::fold_row(&mut self.grid, self.geom, r0 + i, inp);
            self.r2c
                .process_with_scratch(
                    inp,
                    &mut self.rout[i * half..(i + 1) * half],
                    &mut self.rscratch,
                )
                .expect("buffer sizes fixed at plan time");
        }
    }

    fn fft_1d(&mut self, re: &mut [f64], im: &mut [f64]) {
        self.r2c_rows(0, 1);
        let t = std::time::Instant::now();
        for j in 0..=self.k {
            let v = self.rout[j] * self.deconv[j];
            re[j] = v.re;
            im[j] = v.im;
        }
        self.times.deconvolve = t.elapsed().as_secs_f64();
    }

    /// Row FFTs of the `n` rows starting at row `base`, keeping the `K+1`
    /// non-negative last-axis frequencies, transposed into `t1[j][l]`, then
    /// complex FFTs of those `K+1` columns (in place in `t1`).
    fn plane_fft(&mut self, base: usize) {
        let n = self.geom.n;
        let half = n / 2 + 1;
        let k = self.k;
        let mut l = 0;
        while l < n {
            let b = BLOCK.min(n - l);
            self.r2c_rows(base + l, b);
            for j in 0..=k {
                let dst = &mut self.t1[j * n + l..j * n + l + b];
                for (i, d) in dst.iter_mut().enumerate() {
                    *d = self.rout[i * half + j];
                }
            }
            l += b;
        }
        self.fft
            .process_with_scratch(&mut self.t1, &mut self.fscratch);
    }

    fn fft_2d(&mut self, re: &mut [f64], im: &mut [f64]) {
        self.plane_fft(0);
        let t = std::time::Instant::now();
        let (n, k) = (self.geom.n, self.k);
        let m = 2 * k + 1;
        let t1 = &self.t1;
        let dc = &self.deconv;
        // Tiles of 8 output rows: each column j1 of t1 is read contiguously
        // over the tile, the 8 output rows stay in cache along j1.
        let mut a = 0;
        while a <= k {
            let b = (a + 8).min(k + 1);
            for j1 in 0..=k {
                let col = &t1[j1 * n..(j1 + 1) * n];
                for j0 in a..b {
                    let s = dc[j0] * dc[j1];
                    let orow = j0 * m;
                    let g = col[j0];
                    re[orow + k + j1] = g.re * s;
                    im[orow + k + j1] = g.im * s;
                    if j1 > 0 {
                        // ν = (j0, −j1): conj of G(−j0, j1)
                        let g = col[(n - j0) % n];
                        re[orow + k - j1] = g.re * s;
                        im[orow + k - j1] = -g.im * s;
                    }
                }
            }
            a = b;
        }
        self.times.deconvolve = t.elapsed().as_secs_f64();
    }

    fn fft_3d(&mut self, re: &mut [f64], im: &mut [f64]) {
        let (n, k) = (self.geom.n, self.k);
        let m = 2 * k + 1;
        for l0 in 0..n {
            self.plane_fft(l0 * n);
            // t1[j2][l1] (FFT'd along l1) → t2[j2][j1+K][l0] for j1 ∈ [−K, K].
            for j2 in 0..=k {
                let src = &self.t1[j2 * n..(j2 + 1) * n];
                for jj in 0..m {
                    let l1 = if jj >= k { jj - k } else { n + jj - k };
                    self.t2[(j2 * m + jj) * n + l0] = src[l1];
                }
            }
        }
        self.fft
            .process_with_scratch(&mut self.t2, &mut self.fscratch);
        let t = std::time::Instant::now();
        let t2 = &self.t2;
        let dc = &self.deconv;
        for j0 in 0..=k {
            let j0n = (n - j0) % n;
            for j1 in -(k as isize)..=k as isize {
                let a1 = j1.unsigned_abs();
                let s01 = dc[j0] * dc[a1];
                let orow = (j0 * m + (j1 + k as isize) as usize) * m;
                let neg = (k as isize - j1) as usize; // index of −j1
                let pos = (k as isize + j1) as usize;
                for j2 in 1..=k {
                    let g = t2[(j2 * m + neg) * n + j0n];
                    let s = s01 * dc[j2];
                    re[orow + k - j2] = g.re * s;
                    im[orow + k - j2] = -g.im * s;
                }
                for j2 in 0..=k {
                    let g = t2[(j2 * m + pos) * n + j0];
                    let s = s01 * dc[j2];
                    re[orow + k + j2] = g.re * s;
                    im[orow + k + j2] = g.im * s;
                }
            }
        }
        self.times.deconvolve = t.elapsed().as_secs_f64();
    }
}

/// Deterministic benchmark and test data shared by the unit tests, the
/// criterion bench and the `nufft_bench` example (and mirrored in
/// `nufft/tools/finufft_bench.py`, so FINUFFT is timed on the same points).
#[doc(hidden)]
pub mod testdata {
    /// `count` SplitMix64 uniforms in `[0, 1)`: `(z >> 11) / 2^53`.
    #[must_use]
    pub fn uniforms(seed: u64, count: usize) -> Vec<f64> {
        let mut s = seed;
        (0..count)
            .map(|_| {
                s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
                let mut z = s;
                z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                z ^= z >> 31;
                (z >> 11) as f64 / (1u64 << 53) as f64
            })
            .collect()
    }

    /// `count` points in `[0, 1)^D` from [`uniforms`] (coordinates in order).
    #[must_use]
    pub fn points<const D: usize>(seed: u64, count: usize) -> Vec<[f64; D]> {
        let u = uniforms(seed, count * D);
        (0..count)
            .map(|i| core::array::from_fn(|d| u[i * D + d]))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::testdata::{points, uniforms};
    use super::*;

    /// Half-grid frequencies in output order.
    fn freqs<const D: usize>(k: usize) -> Vec<[i64; D]> {
        let k = k as i64;
        let mut out = Vec::new();
        match D {
            1 => (0..=k).for_each(|a| out.push(core::array::from_fn(|_| a))),
            2 => {
                for a in 0..=k {
                    for b in -k..=k {
                        let f = [a, b];
                        out.push(core::array::from_fn(|d| f[d]));
                    }
                }
            }
            _ => {
                for a in 0..=k {
                    for b in -k..=k {
                        for c in -k..=k {
                            let f = [a, b, c];
                            out.push(core::array::from_fn(|d| f[d]));
                        }
                    }
                }
            }
        }
        out
    }

    /// Direct sum with exact phase reduction: ν·x mod 1 before the 2π.
    fn direct<const D: usize>(
        pts: &[[f64; D]],
        c: Option<&[f64]>,
        k: usize,
    ) -> (Vec<f64>, Vec<f64>) {
        let fs = freqs::<D>(k);
        let mut re = vec![0.0; fs.len()];
        let mut im = vec![0.0; fs.len()];
        for (i, p) in pts.iter().enumerate() {
            let w = c.map_or(1.0, |c| c[i]);
            let x: [f64; D] = core::array::from_fn(|d| p[d] - p[d].floor());
            for (o, f) in fs.iter().enumerate() {
                let mut r = 0.0;
                for d in 0..D {
                    let t = f[d] as f64 * x[d];
                    r += t - t.round();
                }
                let a = -2.0 * core::f64::consts::PI * (r - r.round());
                re[o] += w * a.cos();
                im[o] += w * a.sin();
            }
        }
        (re, im)
    }

    fn errors(re: &[f64], im: &[f64], er: &[f64], ei: &[f64]) -> (f64, f64) {
        let (mut num, mut den, mut mx) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..re.len() {
            let d = (re[i] - er[i]).powi(2) + (im[i] - ei[i]).powi(2);
            num += d;
            den += er[i] * er[i] + ei[i] * ei[i];
            mx = mx.max(d.sqrt());
        }
        ((num / den).sqrt(), mx)
    }

    /// Measured: rel l2 error / ε ≤ 0.5 in every case below; asserted with C = 1.
    const C: f64 = 1.0;

    fn check<const D: usize>(n_pts: usize, k: usize, seed: u64) {
        let pts = points::<D>(seed, n_pts);
        let (er, ei) = direct::<D>(&pts, None, k);
        for sigma in [Upsampling::Two, Upsampling::FiveQuarters] {
            for tol in [1e-3, 1e-6, 1e-9, 1e-12] {
                let mut plan = Plan::<D>::with_upsampling(k, tol, sigma).unwrap();
                let mut re = vec![0.0; plan.half_len()];
                let mut im = vec![0.0; plan.half_len()];
                plan.transform(&pts, &mut re, &mut im).unwrap();
                let (rel, mx) = errors(&re, &im, &er, &ei);
                eprintln!(
                    "D={D} N={n_pts} K={k} {sigma:?} tol={tol:e} w={} deg={} n={} rel_l2={rel:.2e} (/tol {:.3}) max_abs/N={:.2e}",
                    plan.kernel_width(),
                    plan.poly_degree(),
                    plan.fine_size(),
                    rel / tol,
                    mx / n_pts as f64
                );
                // σ = 5/4 at tol < 1e-9: rounding errors amplified by the
                // deconvolution (p(0)/p(K))^D dominate; documented floors
                // (measured 4e-11 in 2D, 1.4e-8 in 3D at tol = 1e-12).
                let bound = if sigma == Upsampling::FiveQuarters && tol < 1e-9 {
                    if D == 3 {
                        1e-7
                    } else {
                        1e-10
                    }
                } else {
                    C * tol
                };
                assert!(rel <= bound, "D={D} {sigma:?} tol={tol}: rel {rel}");
            }
        }
    }

    #[test]
    fn accuracy_1d() {
        check::<1>(200, 20, 1);
    }

    #[test]
    fn accuracy_2d() {
        check::<2>(200, 20, 2);
    }

    #[test]
    fn accuracy_3d() {
        check::<3>(200, 20, 3);
    }

    fn single<const D: usize>(pts: &[[f64; D]], k: usize, tol: f64) -> f64 {
        let mut plan = Plan::<D>::new(k, tol).unwrap();
        let mut re = vec![0.0; plan.half_len()];
        let mut im = vec![0.0; plan.half_len()];
        plan.transform(pts, &mut re, &mut im).unwrap();
        let (er, ei) = direct::<D>(pts, None, k);
        errors(&re, &im, &er, &ei).0
    }

    #[test]
    fn edge_points() {
        let tol = 1e-9;
        // 0, just below 1, exactly representable neighbours of 1, N = 1.
        let below = 1.0 - f64::EPSILON / 2.0;
        assert!(single::<1>(&[[0.0]], 10, tol) < tol);
        assert!(single::<1>(&[[below]], 10, tol) < tol);
        assert!(single::<2>(&[[0.0, below]], 10, tol) < tol);
        assert!(single::<3>(&[[below, 0.0, below]], 5, tol) < tol);
        // Clustered near the corner (wraps through 0/1).
        let u = uniforms(7, 300);
        let pts: Vec<[f64; 2]> = (0..150)
            .map(|i| [(1.0 + 1e-3 * (u[2 * i] - 0.5)) % 1.0, 1e-3 * u[2 * i + 1]])
            .collect();
        assert!(single::<2>(&pts, 15, tol) < tol);
        // Points outside [0,1) are wrapped.
        let outside: Vec<[f64; 2]> = vec![[-0.25, 1.5], [3.75, -2.0], [-1e-300, 0.5]];
        let mut plan = Plan::<2>::new(6, tol).unwrap();
        let mut re = vec![0.0; plan.half_len()];
        let mut im = vec![0.0; plan.half_len()];
        plan.transform(&outside, &mut re, &mut im).unwrap();
        let (er, ei) = direct::<2>(&outside, None, 6);
        assert!(errors(&re, &im, &er, &ei).0 < tol);
        // K = 0: the single mode is the weight sum.
        let mut p0 = Plan::<3>::new(0, tol).unwrap();
        let (mut r0, mut i0) = ([0.0], [0.0]);
        p0.transform(&[[0.1, 0.2, 0.3], [0.9, 0.0, 0.5]], &mut r0, &mut i0)
            .unwrap();
        assert!(
            (r0[0] - 2.0).abs() < tol && i0[0].abs() < tol,
            "{r0:?} {i0:?}"
        );
        // No points: all zero.
        plan.transform(&[], &mut re, &mut im).unwrap();
        assert!(re.iter().chain(&im).all(|&v| v == 0.0));
    }

    #[test]
    fn weighted() {
        let pts = points::<2>(11, 120);
        let c: Vec<f64> = uniforms(12, 120).iter().map(|u| 2.0 * u - 0.7).collect();
        for tol in [1e-4, 1e-10] {
            let mut plan = Plan::<2>::new(12, tol).unwrap();
            let mut re = vec![0.0; plan.half_len()];
            let mut im = vec![0.0; plan.half_len()];
            plan.transform_weighted(&pts, &c, &mut re, &mut im).unwrap();
            let (er, ei) = direct::<2>(&pts, Some(&c), 12);
            let rel = errors(&re, &im, &er, &ei).0;
            assert!(rel < C * tol, "tol {tol}: {rel}");
        }
    }

    #[test]
    fn errors_reported() {
        for bad in [f64::NAN, 0.0, -1e-6] {
            let e = Plan::<2>::new(4, bad).err().unwrap();
            assert!(matches!(e, NufftError::Tolerance(_)), "{e}");
            assert!(e.to_string().starts_with("tol "), "{e}");
        }
        // Clamping, not an error.
        assert_eq!(Plan::<1>::new(4, 1e-20).unwrap().tolerance(), MIN_TOL);
        assert_eq!(Plan::<1>::new(4, 0.5).unwrap().tolerance(), MAX_TOL);
        assert!(Plan::<4>::new(4, 1e-6).is_err());
        let mut plan = Plan::<2>::new(4, 1e-6).unwrap();
        let mut re = vec![0.0; plan.half_len()];
        let mut im = vec![0.0; plan.half_len()];
        let e = plan
            .transform(&[[0.5, 0.5], [f64::NAN, 0.1]], &mut re, &mut im)
            .unwrap_err();
        assert_eq!(e.to_string(), "points[1][0] = NaN is not finite");
        let e = plan
            .transform(&[[f64::INFINITY, 0.1]], &mut re, &mut im)
            .unwrap_err();
        assert_eq!(e.to_string(), "points[0][0] = inf is not finite");
        let e = plan
            .transform_weighted(&[[0.5, 0.5]], &[1.0, 2.0], &mut re, &mut im)
            .unwrap_err();
        assert_eq!(e.to_string(), "weights: length 2, expected 1");
        let e = plan
            .transform(&[[0.5, 0.5]], &mut re[..3], &mut im)
            .unwrap_err();
        assert!(e.to_string().starts_with("re: length 3, expected "), "{e}");
    }

    #[test]
    fn auto_rule() {
        assert_eq!(Upsampling::auto(2, 128, 1e-12, None), Upsampling::Two);
        assert_eq!(
            Upsampling::auto(2, 128, 1e-6, None),
            Upsampling::FiveQuarters
        );
        // Dense 2D: the smaller kernel of σ = 2 pays off; sparse: the FFT.
        assert_eq!(Upsampling::auto(2, 128, 1e-6, Some(65536)), Upsampling::Two);
        assert_eq!(
            Upsampling::auto(2, 319, 1e-6, Some(4096)),
            Upsampling::FiveQuarters
        );
        assert_eq!(
            Upsampling::auto(3, 32, 1e-9, Some(4096)),
            Upsampling::FiveQuarters
        );
        let p = Plan::<2>::new_for_points(319, 1e-6, 4096).unwrap();
        assert_eq!(p.upsampling(), Upsampling::FiveQuarters);
        assert_eq!(p.fine_size(), 800);
        assert_eq!(p.half_len(), 320 * 639);
    }

    #[test]
    fn plans_too_large_for_memory_are_errors() {
        // 3D, K = 100 000: the fine grid is about n³·8 ≈ 1e17 bytes.
        let e = Plan::<3>::new(100_000, 1e-6).err().expect("no such memory");
        match e {
            NufftError::Alloc { what, bytes } => {
                assert_eq!(what, "fine grid");
                assert!(bytes > 1e16 as u128 && bytes < 1e19 as u128, "{bytes}");
            }
            other => panic!("{other}"),
        }
        assert!(
            e.to_string().starts_with("cannot allocate the fine grid ("),
            "{e}"
        );
        // Sizes whose byte count overflows u128 (3D), or whose length does not
        // fit in usize (1D), and σ from the cost model: errors too.
        for k in [usize::MAX / 4, usize::MAX] {
            let e = Plan::<3>::new_for_points(k, 1e-3, 10).err().unwrap();
            assert_eq!(
                e,
                NufftError::Alloc {
                    what: "fine grid",
                    bytes: u128::MAX
                }
            );
            assert!(e.to_string().contains("overflows"), "{e}");
            let e = Plan::<1>::with_upsampling(k, 1e-12, Upsampling::Two)
                .err()
                .unwrap();
            assert!(matches!(e, NufftError::Alloc { .. }), "{e}");
            let e = Plan::<2>::new(k, 1e-9).err().unwrap();
            assert!(matches!(e, NufftError::Alloc { .. }), "{e}");
        }
    }

    #[test]
    fn smooth_sizes_match_the_definition() {
        // The smallest even 2^a 3^b 5^c ≥ max(m, 2), by brute force.
        fn brute(m: u128) -> u128 {
            let mut n = m.max(2);
            loop {
                if n.is_multiple_of(2) {
                    let mut r = n;
                    for p in [2, 3, 5] {
                        while r.is_multiple_of(p) {
                            r /= p;
                        }
                    }
                    if r == 1 {
                        return n;
                    }
                }
                n += 1;
            }
        }
        for m in 0..20_000u128 {
            assert_eq!(next_smooth_even(m), brute(m), "m = {m}");
        }
        assert_eq!(next_smooth_even(1 << 80), 1 << 80);
        // Far beyond usize (no brute force): even, 5-smooth, ≥ m, and no
        // larger than the candidate 3·2^79.
        let m = (1u128 << 80) + 1;
        let n = next_smooth_even(m);
        let mut r = n;
        for p in [2, 3, 5] {
            while r.is_multiple_of(p) {
                r /= p;
            }
        }
        assert!(
            n.is_multiple_of(2) && r == 1 && n >= m && n <= 3 << 79,
            "{n}"
        );
    }

    #[test]
    fn transform_into_fills_the_kernel_view() {
        use linesample::spectrum::{AmplitudeView, Grid, Periodogram};
        fn check<const D: usize>(k: usize, n_pts: usize) {
            let grid = Grid::<D>::new(k).unwrap();
            let pts = points::<D>(9 + D as u64, n_pts);
            let mut plan = Plan::<D>::new(k, 1e-9).unwrap();
            let (mut re, mut im) = (vec![0.0; plan.half_len()], vec![0.0; plan.half_len()]);
            plan.transform(&pts, &mut re, &mut im).unwrap();
            let mut amps = Amplitudes::new_vec(grid);
            plan.transform_into(&pts, &mut amps).unwrap();
            assert_eq!(amps.count(), n_pts as u64);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(amps.parts().0), bits(&re));
            assert_eq!(bits(amps.parts().1), bits(&im));
            // The kernel's ring means are the lab's former formula
            // (mult·(re² + im²))·(1/n), bit for bit, on NUFFT output.
            let (mut ring, mut count) = (vec![0.0; k + 1], vec![0u64; k + 1]);
            amps.radial_power(&mut ring, &mut count).unwrap();
            let mut old = vec![0.0; k + 1];
            let inv = 1.0 / n_pts as f64;
            for i in 0..grid.len() {
                if let Some(r) = grid.ring(i) {
                    old[r] +=
                        f64::from(grid.multiplicity(i)) * (re[i] * re[i] + im[i] * im[i]) * inv;
                }
            }
            for (m, &c) in old.iter_mut().zip(&count) {
                *m /= c as f64;
            }
            assert_eq!(bits(&ring), bits(&old), "{D}D");
            let mut per = Periodogram::new_vec(grid);
            per.add(&amps).unwrap();
            let dc = per.mean([0; D]).unwrap();
            assert!((dc - n_pts as f64).abs() < 1e-6 * n_pts as f64, "{dc}");
            // Weighted, and weights 1 give the unweighted bits.
            let mut w = Amplitudes::new_vec(grid);
            plan.transform_weighted_into(&pts, &vec![1.0; n_pts], &mut w)
                .unwrap();
            assert_eq!(w.count(), n_pts as u64);
            assert_eq!(bits(w.parts().0), bits(&re));
            // Another half-width is an error naming `out`; `out` is unchanged.
            let mut other = Amplitudes::new_vec(Grid::<D>::new(k + 1).unwrap());
            let e = plan.transform_into(&pts, &mut other).unwrap_err();
            assert_eq!(
                e,
                NufftError::HalfWidth {
                    name: "out",
                    expected: k,
                    got: k + 1
                }
            );
            assert!(e.to_string().starts_with("out: "), "{e}");
            assert_eq!(other.count(), 0);
            let e = plan
                .transform_weighted_into(&pts, &[1.0], &mut amps)
                .unwrap_err();
            assert!(e.to_string().starts_with("weights: "), "{e}");
            assert_eq!(amps.count(), n_pts as u64);
            let bad = [[f64::NAN; D]];
            assert!(plan.transform_into(&bad, &mut amps).is_err());
            assert_eq!(bits(amps.parts().0), bits(&re));
            assert_eq!(amps.count(), n_pts as u64);
        }
        check::<1>(30, 50);
        check::<2>(12, 80);
        check::<3>(5, 40);
    }

    #[test]
    fn quadrature_and_fit() {
        let (x, w) = gauss_legendre(20);
        // ∫_{-1}^{1} x^38 dx = 2/39 (degree 38 ≤ 2·20−1).
        let s: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(38)).sum();
        assert!((s - 2.0 / 39.0).abs() < 1e-14, "{s}");
        for tol in [1e-3, 1e-8, 1e-14] {
            for sigma in [Upsampling::Two, Upsampling::FiveQuarters] {
                let plan = Plan::<1>::with_upsampling(10, tol, sigma).unwrap();
                assert!(
                    plan.poly_error() <= (tol / 20.0).max(1e-14),
                    "{tol} {sigma:?} {}",
                    plan.poly_error()
                );
            }
        }
    }
}
