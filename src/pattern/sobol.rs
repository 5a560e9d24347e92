//! sobol
/// tmp
#[derive(Debug)]
pub struct Sobol;
/// tmp
pub const SOBOL_DIMENSIONS: u32 = 16;
