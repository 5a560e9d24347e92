//! A small renderer built on `linesample`'s public API only: the transmittance
//! image of coloured absorbing spheres and Gaussian puffs seen by a pinhole
//! camera, every optical depth in closed form by the `f32` SIMD batches, pixel
//! samples drawn by index through the `Sequence` trait (Owen-scrambled Sobol',
//! decorrelated per pixel). Writes a PNG.
//!
//! ```sh
//! cargo run --release --example render -- out/render.png 640 360 16
//! ```
//! (arguments: output path, width, height, samples per pixel; all optional).
//!
//! A crate of its own that compiles this file needs `linesample` (default
//! features), `libm` (the `no_std` maths of `kernel.rs`) and `png`;
//! `tools/outside_crate.sh` builds it that way, with default flags, in CI.

mod kernel;

use kernel::{render_row, row_scratch_len, Ball, Camera, PixelSampler, Puff, RowScratch, Scene};
use linesample::pattern::Sobol;
use linesample::world::{Gaussian, Sphere};
use linesample::Seed;
use std::error::Error;
use std::time::Instant;

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args
        .first()
        .map_or("out/render.png", String::as_str)
        .to_owned();
    let num = |i: usize, d: u32| -> Result<u32, Box<dyn Error>> {
        match args.get(i) {
            None => Ok(d),
            Some(s) => match s.parse::<u32>() {
                Ok(v) if v > 0 => Ok(v),
                _ => Err(
                    format!("argument {}: expected a positive integer, got {s:?}", i + 1).into(),
                ),
            },
        }
    };
    let (width, height, spp) = (num(1, 640)?, num(2, 360)?, num(3, 16)?);

    // The scene: three tinted glass-like balls and two smoky puffs in front
    // of a bright checkerboard backdrop, in world units (metres).
    let balls = [
        Ball {
            sphere: Sphere::new([-1.4, 0.0, 0.0], 0.8)?,
            sigma: [0.2, 1.2, 2.0],
        },
        Ball {
            sphere: Sphere::new([0.3, 0.2, -1.0], 1.0)?,
            sigma: [1.6, 0.5, 0.2],
        },
        Ball {
            sphere: Sphere::new([1.9, -0.3, 0.6], 0.55)?,
            sigma: [1.5, 1.5, 0.3],
        },
    ];
    let puffs = [
        Puff {
            density: Gaussian::with_peak([-0.2, 1.1, 0.8], 0.35, 6.0)?,
            sigma: [1.0, 1.0, 1.0],
        },
        Puff {
            density: Gaussian::with_peak([1.2, -0.9, 1.2], 0.2, 12.0)?,
            sigma: [0.3, 0.9, 1.4],
        },
    ];
    let scene = Scene {
        balls: &balls,
        puffs: &puffs,
    };
    let cam = Camera::look_at(
        [0.0, 0.3, 6.0],
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        40.0,
        width,
        height,
    )?;
    let sobol = Sobol::<2>::new(spp as usize)?;
    let sampler = PixelSampler {
        seq: &sobol,
        seed: Seed::new(2017),
        spp,
    };

    let n = row_scratch_len(width, spp);
    let mut buf = vec![0.0f32; 12 * n];
    let mut row = vec![[0.0f32; 3]; width as usize];
    let mut rgb = Vec::with_capacity(width as usize * height as usize * 3);
    let start = Instant::now();
    for y in 0..height {
        let mut parts = buf.chunks_exact_mut(n);
        let mut next = || parts.next().expect("12 buffers");
        let mut scratch = RowScratch {
            origin: [next(), next(), next()],
            dir: [next(), next(), next()],
            t0: next(),
            t1: next(),
            value: next(),
            tau: [next(), next(), next()],
        };
        render_row(&scene, &cam, &sampler, y, &mut scratch, &mut row)?;
        for (x, t) in row.iter().enumerate() {
            // Backdrop: a checkerboard in screen space, light grey and white.
            let check = ((x as u32 * 12 / width) + (y * 12 / width)) % 2;
            let bg = if check == 0 { 0.95 } else { 0.7 };
            rgb.extend(t.map(|c| srgb(c * bg)));
        }
    }
    let secs = start.elapsed().as_secs_f64();
    let rays = f64::from(width) * f64::from(height) * f64::from(spp);
    let shapes = (balls.len() + puffs.len()) as f64;
    println!(
        "{width}×{height}, {spp} spp: {rays:.0} rays × {shapes} shapes in {secs:.3} s ({:.1} M ray-shape integrals/s, one thread, SIMD level {})",
        rays * shapes / secs / 1e6,
        linesample::simd::level().name()
    );

    if let Some(dir) = std::path::Path::new(&path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let file = std::io::BufWriter::new(std::fs::File::create(&path)?);
    let mut enc = png::Encoder::new(file, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()?.write_image_data(&rgb)?;
    println!("wrote {path}");
    Ok(())
}

/// Linear `[0, 1]` to an 8-bit sRGB value.
fn srgb(x: f32) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let s = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}
