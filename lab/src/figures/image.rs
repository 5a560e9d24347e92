//! Raster images as PNG (`png` crate, 8-bit, deflate-compressed), grey or RGB.

/// Encodes `pixels` (row-major, top row first; 1 byte per pixel for
/// [`Color::Gray`], 3 for [`Color::Rgb`]) as a PNG file.
///
/// # Errors
/// A message if the size does not match or the encoder fails.
pub fn png(width: u32, height: u32, color: Color, pixels: &[u8]) -> Result<Vec<u8>, String> {
    let channels = match color {
        Color::Gray => 1,
        Color::Rgb => 3,
    };
    let expected = width as usize * height as usize * channels;
    if pixels.len() != expected {
        return Err(format!(
            "internal error: a {width}x{height} image needs {expected} bytes, got {}",
            pixels.len()
        ));
    }
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(match color {
        Color::Gray => png::ColorType::Grayscale,
        Color::Rgb => png::ColorType::Rgb,
    });
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Balanced);
    let err = |e: png::EncodingError| format!("internal error: PNG encoding: {e}");
    let mut w = enc.write_header().map_err(err)?;
    w.write_image_data(pixels).map_err(err)?;
    w.finish().map_err(err)?;
    Ok(out)
}

/// Pixel layout of [`png()`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Color {
    /// One byte per pixel.
    Gray,
    /// Three bytes per pixel (red, green, blue).
    Rgb,
}

/// Grey level of `v` on a log scale: `round(255·(log10 v − lo)/(hi − lo))`
/// with `log10 v` clipped to `[lo, hi]`; 0 for `v ≤ 0` or NaN.
#[must_use]
pub fn log_gray(v: f64, lo: f64, hi: f64) -> u8 {
    if v.is_nan() || v <= 0.0 {
        return 0;
    }
    let l = v.log10().clamp(lo, hi);
    ((l - lo) / (hi - lo) * 255.0).round() as u8
}

/// The `side × side` grey image `g(row, col)` with every pixel repeated
/// `scale × scale` times.
#[must_use]
pub fn upscaled(side: usize, scale: usize, g: impl Fn(usize, usize) -> u8) -> Vec<u8> {
    let w = side * scale;
    let mut px = vec![0u8; w * w];
    for row in 0..side {
        for col in 0..side {
            let v = g(row, col);
            for dy in 0..scale {
                let start = (row * scale + dy) * w + col * scale;
                px[start..start + scale].fill(v);
            }
        }
    }
    px
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_through_the_decoder() {
        let px: Vec<u8> = (0..6 * 4).map(|i| (i * 10) as u8).collect();
        for (color, w) in [(Color::Gray, 6), (Color::Rgb, 2)] {
            let bytes = png(w, 4, color, &px).unwrap();
            let dec = png::Decoder::new(std::io::Cursor::new(bytes));
            let mut r = dec.read_info().unwrap();
            let mut buf = vec![0; r.output_buffer_size().unwrap()];
            let info = r.next_frame(&mut buf).unwrap();
            assert_eq!((info.width, info.height), (w, 4));
            assert_eq!(&buf[..info.buffer_size()], &px[..]);
        }
        assert!(png(3, 3, Color::Gray, &px).is_err());
    }

    #[test]
    fn gray_levels() {
        assert_eq!(log_gray(0.0, -2.0, 1.0), 0);
        assert_eq!(log_gray(0.01, -2.0, 1.0), 0);
        assert_eq!(log_gray(1.0, -2.0, 1.0), 170);
        assert_eq!(log_gray(10.0, -2.0, 1.0), 255);
        assert_eq!(log_gray(f64::NAN, -2.0, 1.0), 0);
        assert_eq!(
            upscaled(2, 2, |r, c| (2 * r + c) as u8),
            [0, 0, 1, 1, 0, 0, 1, 1, 2, 2, 3, 3, 2, 2, 3, 3]
        );
    }
}
