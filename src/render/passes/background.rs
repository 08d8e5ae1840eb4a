//! The environment background: the sky drawn behind every object, last in the frame's colour pass
//! (a full-screen triangle at the far plane where nothing was drawn).

/// Draw the background into an open colour pass, when the frame has one.
pub(in crate::render) fn draw_background(pass: &mut wgpu::RenderPass, pipeline: Option<&wgpu::RenderPipeline>) {
    if let Some(bg) = pipeline {
        pass.set_pipeline(bg);
        pass.draw(0..3, 0..1);
    }
}
