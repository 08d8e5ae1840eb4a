//! Where the passes' constants (the frame, the objects, the shadow layers, the compute steps' params)
//! live on the device: uniform buffers, or read-only storage buffers on Mesa's lavapipe.
//!
//! Why not uniform buffers everywhere: lavapipe inlines uniform-buffer values that branch
//! conditions and loop bounds read ("uniform inlining", lvp_inline_uniforms.c in Mesa, applied in
//! lvp_execute.c `update_inline_shader_state`). Every new combination of those values compiles a new
//! shader variant with LLVM on the queue thread, and the variants are kept until the pipeline dies.
//! A sweep changes those values in every cell, so on lavapipe each cell compiled fresh variants:
//! measured with a breakpoint on `LLVMModuleCreateWithNameInContext`, 6 LLVM modules per cell
//! sweeping smoothness and 30 per cell sweeping light intensity, which grew the process by about
//! 0.9 MB per cell and took `bench.toml`'s render stage from 45.5 s to 101.5 s. Loads from
//! storage buffers are never inlined. WGSL lays a struct out the same in both address spaces, so the
//! shaders change only in the `var<uniform>` declarations, and the values the shaders read are the
//! same. Hardware adapters keep uniform buffers, as the engines use constant buffers.

use std::borrow::Cow;

pub use crate::adapter::ConstantSpace;

impl ConstantSpace {
    pub fn for_adapter(info: &wgpu::AdapterInfo) -> ConstantSpace {
        if info.backend == wgpu::Backend::Vulkan && info.device_type == wgpu::DeviceType::Cpu {
            ConstantSpace::ReadOnlyStorage
        } else {
            ConstantSpace::Uniform
        }
    }

    /// The binding type of a constant buffer in a bind group layout.
    pub fn binding(self) -> wgpu::BufferBindingType {
        match self {
            ConstantSpace::Uniform => wgpu::BufferBindingType::Uniform,
            ConstantSpace::ReadOnlyStorage => wgpu::BufferBindingType::Storage { read_only: true },
        }
    }

    /// The usage a constant buffer is created with (besides COPY_DST where it is rewritten).
    pub fn usage(self) -> wgpu::BufferUsages {
        match self {
            ConstantSpace::Uniform => wgpu::BufferUsages::UNIFORM,
            ConstantSpace::ReadOnlyStorage => wgpu::BufferUsages::STORAGE,
        }
    }

    /// The alignment of a dynamic offset into a constant buffer.
    pub fn offset_alignment(self, limits: &wgpu::Limits) -> u64 {
        match self {
            ConstantSpace::Uniform => limits.min_uniform_buffer_offset_alignment as u64,
            ConstantSpace::ReadOnlyStorage => limits.min_storage_buffer_offset_alignment as u64,
        }
    }

    /// `source` with its constant buffers declared in this space.
    pub fn wgsl(self, source: &str) -> Cow<'_, str> {
        match self {
            ConstantSpace::Uniform => Cow::Borrowed(source),
            ConstantSpace::ReadOnlyStorage => Cow::Owned(source.replace("var<uniform>", "var<storage, read>")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn storage_space_rewrites_only_uniform_declarations() {
        let src = "@group(0) @binding(0) var<uniform> frame: Frame;\n@group(0) @binding(4) var<storage, read> lights: array<Light>;\n// a uniform comment";
        let out = ConstantSpace::ReadOnlyStorage.wgsl(src);
        assert!(out.contains("var<storage, read> frame: Frame;"));
        assert!(out.contains("var<storage, read> lights"));
        assert!(out.contains("// a uniform comment"));
        assert!(!out.contains("var<uniform>"));
        assert_eq!(ConstantSpace::Uniform.wgsl(src), src);
    }
}
