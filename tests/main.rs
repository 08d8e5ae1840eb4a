//! The end-to-end tests, in one binary: wgpu and the library link once instead of once per file,
//! which dominates `cargo test` time on a small machine. Unit tests live beside their code.

mod common;
mod e2e;
