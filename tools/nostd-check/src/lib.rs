//! `#![no_std]` consumer of `linesample` (see Cargo.toml).
#![no_std]

use linesample::pattern::{Jittered, Pattern, Random};
use linesample::Seed;

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
    0
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {}
}
