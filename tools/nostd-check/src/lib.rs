//! `#![no_std]` consumer of `linesample` (see Cargo.toml).
#![no_std]

use linesample::pattern::{Jittered, Pattern, Random, Sobol};
use linesample::world::{Gaussian, HalfSpace, Ray, Slab, Sphere};
use linesample::Seed;

/// The `render` example's renderer kernel, compiled without std or alloc.
#[path = "../../../examples/render/kernel.rs"]
#[allow(dead_code)]
mod kernel;

/// Generates two small patterns on the stack; returns 0 on success.
#[no_mangle]
pub extern "C" fn linesample_nostd_selftest(seed: u64) -> i32 {
    let p = match Jittered::<2>::new([8, 8]) {
        Ok(p) => p,
        Err(_) => return 1,
    };
    let mut buf = [[0.0f32; 2]; 64];
    if p.fill(Seed::new(seed), &mut buf).is_err() {
        return 2;
    }
    let r = Random::<3>::new(16).map(|r| {
        let mut b = [[0.0f32; 3]; 16];
        r.fill(Seed::new(seed), &mut b).is_ok()
    });
    if r != Ok(true) {
        return 3;
    }
    if !matches!(world_forms(), Ok(true)) {
        return 4;
    }
    if !matches!(render_tile(seed), Ok(true)) {
        return 5;
    }
    0
}

/// The world-space closed forms, `f64` and `f32` SIMD paths, on the stack.
fn world_forms() -> Result<bool, linesample::Error> {
    let ray = Ray::new([0.0, 0.0, -5.0], [0.0, 0.0, 1.0])?;
    let s = Sphere::new([0.0, 0.0, 0.0], 1.0)?;
    let g = Gaussian::normalised([0.0, 0.0, 0.0], 0.5)?;
    let h = HalfSpace::new([0.0, 0.0, 1.0], 0.0)?;
    let slab = Slab::new([0.0, 0.0, 1.0], -1.0, 1.0)?;
    let (t_in, t_out) = s.hit(&ray).ok_or(linesample::ParamError::ZeroDirection)?;
    let ok64 = t_in == 4.0
        && t_out == 6.0
        && s.chord(&ray) == 2.0
        && g.transmittance(&ray, 0.0, f64::INFINITY, 1.0) > 0.0
        && h.segment(&ray, 0.0, 10.0) == 5.0
        && slab.segment(&ray, 0.0, 10.0) == 2.0;
    let o = [0.0f32; 9];
    let oz = [-5.0f32; 9];
    let dz = [1.0f32; 9];
    let t0 = [0.0f32; 9];
    let t1 = [f32::INFINITY; 9];
    let rays = linesample::primitive::Rays32 {
        origin: [&o, &o, &oz],
        dir: [&o, &o, &dz],
        t0: &t0,
        t1: &t1,
    };
    let mut out = [0.0f32; 9];
    s.segment_batch_f32(&rays, &mut out)?;
    let ok32 = out.iter().all(|&c| (c - 2.0).abs() < 1e-5);
    g.transmittance_batch_f32(&rays, 1.0, &mut out)?;
    Ok(ok64 && ok32 && out.iter().all(|&t| t > 0.0 && t < 1.0))
}

/// One 4-pixel row of the `render` example's kernel with stack buffers; the
/// pattern's and the shapes' errors meet in `linesample::Error` (no alloc).
fn render_tile(seed: u64) -> Result<bool, linesample::Error> {
    use kernel::{render_row, Ball, Camera, PixelSampler, Puff, RowScratch, Scene};
    const W: u32 = 4;
    const SPP: u32 = 2;
    const N: usize = (W * SPP) as usize;
    let balls = [Ball {
        sphere: Sphere::new([0.0, 0.0, 0.0], 1.0)?,
        sigma: [1.0, 0.5, 0.2],
    }];
    let puffs = [Puff {
        density: Gaussian::with_peak([0.5, 0.0, 0.0], 0.3, 2.0)?,
        sigma: [1.0, 1.0, 1.0],
    }];
    let scene = Scene {
        balls: &balls,
        puffs: &puffs,
    };
    let cam = Camera::look_at([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0, W, 4)?;
    let sobol = Sobol::<2>::new(SPP as usize)?;
    let mut b = [[0.0f32; N]; 12];
    let [o0, o1, o2, d0, d1, d2, t0, t1, v, a0, a1, a2] = &mut b;
    let mut scratch = RowScratch {
        origin: [o0, o1, o2],
        dir: [d0, d1, d2],
        t0,
        t1,
        value: v,
        tau: [a0, a1, a2],
    };
    let mut row = [[0.0f32; 3]; W as usize];
    render_row(
        &scene,
        &cam,
        &PixelSampler {
            seq: &sobol,
            seed: Seed::new(seed),
            spp: SPP,
        },
        2,
        &mut scratch,
        &mut row,
    )?;
    Ok(row.iter().flatten().all(|&t| (0.0..=1.0).contains(&t)))
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {}
}
