//! Commands that are more than a call into the library: argument handling and text output.

pub mod brdf;
pub mod shaders;
