//! Rendering: scene resources uploaded once per composition, pipelines compiled once per
//! (pipeline, model) pair, and per-cell frames that only rewrite uniforms.

pub mod camera;
pub mod deferred;
pub mod luts;
pub mod probe;
pub mod renderer;
pub mod shadows;
pub mod uniforms;

pub use renderer::{CellParams, CellRender, CellSettings, PreparedScene, Renderer};
