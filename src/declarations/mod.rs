//! Declarative input: TOML schemas and validation for scenes, matrices, presets and sheets.

pub mod area_light;
pub mod asserts;
pub mod axes;
pub mod filter;
pub mod gi;
pub mod hdrp_light;
pub mod light;
pub mod matrix;
pub mod outputs;
pub mod presets;
pub mod scene;
mod scene_files;
pub mod sheets;
pub mod study;
pub mod sweep;
