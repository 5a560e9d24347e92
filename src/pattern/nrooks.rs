//! N-rooks
/// tmp
#[derive(Debug)]
pub struct NRooks;
