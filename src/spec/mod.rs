//! Declarative input: TOML schemas and validation for scenes, matrices and presets.

pub mod matrix;
pub mod names;
pub mod presets;
pub mod scene;
pub mod source;
pub mod validate;
