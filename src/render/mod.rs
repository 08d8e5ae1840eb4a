//! Rendering: scene resources uploaded once per composition, pipelines compiled once per
//! (pipeline, model) pair, and per-cell frames that only rewrite uniforms.

pub mod cell_uniforms;
pub mod formats;
pub mod frame;
pub mod frame_bindings;
pub mod gbuffer;
pub mod gi;
pub mod luts;
pub mod material_maps;
pub mod passes;
pub mod pipeline_cache;
pub mod prepared;
pub mod probe;
pub mod reflection_probes;
pub mod renderer;
pub mod resources;
pub mod targets;
pub mod truth;
pub mod uniforms;
pub mod warmup;

pub use prepared::PreparedScene;
pub use renderer::{CellParams, CellPlan, CellRender, CellSettings, Renderer, ShadowMapUse};
