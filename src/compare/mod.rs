//! Image comparison: FLIP (LDR and HDR), SSIM, and error statistics, with maps.

pub mod flip;
pub mod gpu;
pub mod images;
pub mod ssim;
pub mod stats;
pub mod values;
pub mod ztest;

pub use images::{compare, LoadedImage};
pub use values::Comparison;
