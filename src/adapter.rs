//! What a run records about its adapter (`run.json` `adapter`): plain data, no device, so that
//! records can be read without wgpu. `gpu::context` fills it in; `gpu::constants` decides the
//! constant space from the adapter.

use serde::Serialize;

/// The adapter a run used, recorded in run.json: timings compare only within one adapter.
#[derive(Debug, Clone, Serialize, serde::Deserialize, PartialEq)]
pub struct AdapterRecord {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    pub driver_info: String,
    pub vendor: u32,
    pub device: u32,
    pub timestamp_queries: bool,
    /// Where the passes' constants lived (gpu::constants).
    #[serde(default)]
    pub constants: ConstantSpace,
}

/// The address space of the passes' constant buffers, recorded with the adapter in run.json.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum ConstantSpace {
    /// Records written before the choice existed used uniform buffers.
    #[default]
    #[serde(rename = "uniform")]
    Uniform,
    /// Read-only storage: on lavapipe (Vulkan on a CPU), where uniform values would be inlined.
    #[serde(rename = "storage")]
    ReadOnlyStorage,
}
