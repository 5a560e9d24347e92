//! mj
/// tmp
#[derive(Debug, Clone)]
pub struct MultiJittered;
/// tmp
#[derive(Debug, Clone)]
pub struct CorrelatedMultiJittered;
