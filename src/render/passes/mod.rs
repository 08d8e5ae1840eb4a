//! The passes of a frame, one file each: the Rust that encodes it beside the WGSL it runs
//! (`shaders/pass/`). The renderer runs the passes a cell's plan lists, in its order.

pub mod background;
pub mod bloom;
pub mod deferred;
pub mod forward;
pub mod light_tiles;
pub mod prepass;
pub mod probe_capture;
pub mod shadow;
pub mod ssao;
pub mod subsurface;
pub mod traced_shadows;
pub mod urp_ssao;

/// What a frame's passes draw with: the frame bind group, which meshes are drawn, and the screen
/// group (the SSAO visibility, or the neutral one).
#[derive(Clone, Copy)]
pub(in crate::render) struct FrameDraw<'a> {
    pub(in crate::render) group: &'a wgpu::BindGroup,
    pub(in crate::render) drawn: &'a [bool],
    pub(in crate::render) screen: &'a wgpu::BindGroup,
    /// The screen group of the subject (the SSAO visibility where it reads it, `plan::ao`).
    pub(in crate::render) subject_screen: &'a wgpu::BindGroup,
    /// Per mesh, whether it is in the Transparent queue, and the queue's drawn meshes in the
    /// order it draws them (the plan's `transparent`, `transparent_order`).
    pub(in crate::render) transparent: &'a [bool],
    pub(in crate::render) transparent_order: &'a [usize],
}

impl<'a> FrameDraw<'a> {
    /// The screen group mesh `i` reads.
    pub(in crate::render) fn screen_of(
        &self,
        prepared: &crate::render::prepared::PreparedScene,
        i: usize,
    ) -> &'a wgpu::BindGroup {
        match prepared.layout.meshes[i].role {
            crate::declarations::scene::Role::Subject => self.subject_screen,
            crate::declarations::scene::Role::Fixed => self.screen,
        }
    }
}
