//! Periodograms of images: values on a regular `width × height` pixel grid,
//! such as the per-pixel error of a rendered image, whose spectrum says how
//! the error is distributed across the screen (white, or blue as with
//! [`ZSobol`](crate::pattern::ZSobol)).

use super::check_len;
use crate::error::SpectrumError;
use core::f64::consts::PI;

/// Scratch length of [`image_periodogram`]: `2·w·h + 2·(w + h)` values (the
/// row transforms and the twiddle tables).
#[must_use]
pub const fn image_periodogram_scratch(width: usize, height: usize) -> usize {
    2 * width * height + 2 * (width + height)
}

/// `cos(2πj/n)` and `sin(2πj/n)` for `j = 0..n` into `re`, `im`.
fn twiddles(n: usize, re: &mut [f64], im: &mut [f64]) {
    for j in 0..n {
        let a = 2.0 * PI * j as f64 / n as f64;
        re[j] = libm::cos(a);
        im[j] = libm::sin(a);
    }
}

/// The periodogram of an image `v` (row-major, `v[y·w + x]`):
///
/// `out[k_y·w + k_x] = |F(k_x, k_y)|² / (w·h)`, with
/// `F(k_x, k_y) = Σ_{x,y} v(x, y)·e^{−2πi(k_x x/w + k_y y/h)}`,
///
/// for `k_x = 0..w`, `k_y = 0..h` (frequency `k` and `k − w` are the same;
/// [`image_ring_means`] folds them). By Parseval the mean of `out` over all
/// frequencies is `Σ v²/(w·h)`: for independent pixel values of variance
/// `σ²` every frequency has expectation `σ²` (white noise), while
/// negatively correlated neighbours lower the low frequencies (blue noise).
///
/// A direct separable DFT (rows, then columns) in `f64` from twiddle tables
/// (each angle reduced exactly, `k·x mod w`, before the table lookup): `w·h·(w
/// + h)` complex multiply-adds, with no FFT size restriction. Each `F` is a
/// sum of `w·h` terms of modulus `|v|`, so its absolute error is at most
/// about `(w + h)·ε·Σ|v|` (`ε = 2⁻⁵³`, plus the tables' `ε`). No allocation:
/// `scratch` holds [`image_periodogram_scratch`] values.
///
/// # Errors
/// [`SpectrumError::Empty`] for `w·h = 0`; [`SpectrumError::Length`] if
/// `values` or `out` is not `w·h` long or `scratch` is shorter than needed;
/// [`SpectrumError::NonFinite`] (`"values"`) at the first NaN or infinity.
pub fn image_periodogram(
    values: &[f64],
    width: usize,
    height: usize,
    scratch: &mut [f64],
    out: &mut [f64],
) -> Result<(), SpectrumError> {
    let n = width.checked_mul(height).ok_or(SpectrumError::Length {
        name: "values",
        expected: usize::MAX,
        got: values.len(),
    })?;
    if n == 0 {
        return Err(SpectrumError::Empty);
    }
    check_len("values", values.len(), n)?;
    check_len("out", out.len(), n)?;
    let need = image_periodogram_scratch(width, height);
    if scratch.len() < need {
        return Err(SpectrumError::Length {
            name: "scratch",
            expected: need,
            got: scratch.len(),
        });
    }
    if let Some(index) = values.iter().position(|v| !v.is_finite()) {
        return Err(SpectrumError::NonFinite {
            name: "values",
            index,
        });
    }
    let (rows, rest) = scratch.split_at_mut(2 * n);
    let (row_re, row_im) = rows.split_at_mut(n);
    let (tw, rest) = rest.split_at_mut(2 * width);
    let (tw_re, tw_im) = tw.split_at_mut(width);
    let (th_re, rest) = rest.split_at_mut(height);
    let th_im = &mut rest[..height];
    twiddles(width, tw_re, tw_im);
    twiddles(height, th_re, th_im);
    // Rows: R(y, k_x) = Σ_x v(x, y)·e^{−2πi k_x x / w}.
    for y in 0..height {
        let v = &values[y * width..(y + 1) * width];
        for kx in 0..width {
            let (mut re, mut im) = (0.0, 0.0);
            let mut j = 0;
            for &vx in v {
                re += vx * tw_re[j];
                im -= vx * tw_im[j];
                j += kx;
                if j >= width {
                    j -= width;
                }
            }
            row_re[y * width + kx] = re;
            row_im[y * width + kx] = im;
        }
    }
    // Columns: F(k_x, k_y) = Σ_y R(y, k_x)·e^{−2πi k_y y / h}.
    let norm = 1.0 / n as f64;
    for ky in 0..height {
        for kx in 0..width {
            let (mut re, mut im) = (0.0, 0.0);
            let mut j = 0;
            for y in 0..height {
                let (a, b) = (row_re[y * width + kx], row_im[y * width + kx]);
                let (c, s) = (th_re[j], -th_im[j]);
                re += a * c - b * s;
                im += a * s + b * c;
                j += ky;
                if j >= height {
                    j -= height;
                }
            }
            out[ky * width + kx] = (re * re + im * im) * norm;
        }
    }
    Ok(())
}

/// The white level of an image periodogram: the mean of `power` over every
/// frequency but DC, `(Σ_k P(k) − P(0)) / (w·h − 1)`. By Parseval
/// `Σ_k P(k) = Σ v²` and `P(0) = (Σ v)²/(w·h)`, so this is the unbiased
/// sample variance of the image's values. Dividing by it makes white noise 1
/// at every frequency.
///
/// # Errors
/// [`SpectrumError::Empty`] for fewer than two values;
/// [`SpectrumError::NonFinite`] (`"power"`) for a non-finite element.
pub fn image_white_level(power: &[f64]) -> Result<f64, SpectrumError> {
    if power.len() < 2 {
        return Err(SpectrumError::Empty);
    }
    if let Some(index) = power.iter().position(|v| !v.is_finite()) {
        return Err(SpectrumError::NonFinite {
            name: "power",
            index,
        });
    }
    let sum: f64 = power[1..].iter().sum();
    Ok(sum / (power.len() - 1) as f64)
}

/// The mean of an image periodogram over the band of rings `r0..=r1` (the
/// frequencies with `r0 ≤ round(√(f_x² + f_y²)) ≤ r1`, signed frequencies as
/// in [`image_ring_means`]) and the number of frequencies in it.
///
/// # Errors
/// [`SpectrumError::Empty`] for `w·h = 0` or a band with no frequency;
/// [`SpectrumError::Length`] if `power` is not `w·h` long.
pub fn image_band_mean(
    power: &[f64],
    width: usize,
    height: usize,
    r0: usize,
    r1: usize,
) -> Result<(f64, u64), SpectrumError> {
    let n = width.saturating_mul(height);
    if n == 0 {
        return Err(SpectrumError::Empty);
    }
    check_len("power", power.len(), n)?;
    let (mut sum, mut count) = (0.0, 0u64);
    for_each_ring(width, height, |i, r| {
        if (r0..=r1).contains(&r) {
            sum += power[i];
            count += 1;
        }
    });
    if count == 0 {
        return Err(SpectrumError::Empty);
    }
    Ok((sum / count as f64, count))
}

/// Calls `f(index, ring)` for every frequency of a `w × h` periodogram.
fn for_each_ring(width: usize, height: usize, mut f: impl FnMut(usize, usize)) {
    let signed = |k: usize, m: usize| {
        if 2 * k <= m {
            k as f64
        } else {
            k as f64 - m as f64
        }
    };
    for ky in 0..height {
        let fy = signed(ky, height);
        for kx in 0..width {
            let fx = signed(kx, width);
            f(
                ky * width + kx,
                libm::round(libm::sqrt(fx * fx + fy * fy)) as usize,
            );
        }
    }
}

/// Ring means of an image periodogram from [`image_periodogram`]: ring `r`
/// holds the frequencies with `round(√(f_x² + f_y²)) = r`, where `f_x = k_x`
/// for `k_x ≤ w/2` and `k_x − w` above (the same for `y`); `mean[r]` is the
/// mean of `power` over the ring, `count[r]` its number of frequencies. Both
/// slices have length `⌊min(w, h)/2⌋ + 1`; frequencies beyond the last ring
/// (the corners) are left out. Ring 0 is the DC term.
///
/// # Errors
/// [`SpectrumError::Empty`] for `w·h = 0`; [`SpectrumError::Length`] for a
/// slice of the wrong length.
pub fn image_ring_means(
    power: &[f64],
    width: usize,
    height: usize,
    mean: &mut [f64],
    count: &mut [u64],
) -> Result<(), SpectrumError> {
    let n = width.saturating_mul(height);
    if n == 0 {
        return Err(SpectrumError::Empty);
    }
    check_len("power", power.len(), n)?;
    let rings = width.min(height) / 2 + 1;
    check_len("mean", mean.len(), rings)?;
    check_len("count", count.len(), rings)?;
    mean.fill(0.0);
    count.fill(0);
    for_each_ring(width, height, |i, r| {
        if r < rings {
            mean[r] += power[i];
            count[r] += 1;
        }
    });
    for (m, &c) in mean.iter_mut().zip(count.iter()) {
        if c > 0 {
            *m /= c as f64;
        }
    }
    Ok(())
}
