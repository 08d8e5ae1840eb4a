//! Surface models: the registry (names, pipelines, which sweep axes each reads), WGSL composition,
//! and the CPU f64 twin of every model.

pub mod diffusion_profile;
pub mod fgd;
pub mod ltc;
pub mod ltc_fit;
pub mod material_type;
pub mod params;
pub mod registry;
pub mod shadow_filter;
pub mod twin;
pub mod user;
pub mod wgsl;

pub use registry::{Registry, ShaderModel};
