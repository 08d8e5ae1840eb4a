//! The passes of a frame, one file each: the Rust that encodes it beside the WGSL it runs
//! (`shaders/pass/`). The renderer runs the passes a cell's plan lists, in its order.

pub mod background;
pub mod bloom;
pub mod deferred;
pub mod forward;
pub mod prepass;
pub mod probes;
pub mod shadow;
pub mod ssao;
pub mod traced_shadows;

/// What a frame's passes draw with: the frame bind group, which meshes are drawn, and the screen
/// group (the SSAO visibility, or the neutral one).
pub(in crate::render) struct FrameDraw<'a> {
    pub(in crate::render) group: &'a wgpu::BindGroup,
    pub(in crate::render) drawn: &'a [bool],
    pub(in crate::render) screen: &'a wgpu::BindGroup,
}
