//! halton
/// tmp
#[derive(Debug)]
pub struct Halton;
/// tmp
pub const HALTON_DIMENSIONS: u32 = 16;
/// tmp
pub const HALTON_BASES: [u32; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];
/// tmp
pub fn radical_inverse(_b: u32, _i: u32) -> f64 {
    0.0
}
