//! Random-access sample sequences (placeholder; being written).
