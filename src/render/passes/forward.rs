//! The forward pass: every drawn object lit, the background last; with MSAA it draws into the
//! multisampled targets and resolves into the frame's own. URP and HDRP draw each object once with
//! every light in its loop; built-in draws each object in ForwardBase and then once more per
//! additional pixel light in ForwardAdd, blended One One (plan::draws). Built-in's vertex-lit path
//! is this pass with the lighting evaluated at the vertices.
//!
//! Objects are drawn opaque fixed ones first, then the background, then the subject, then the
//! Transparent queue back to front (the plan's order), so that a frame can be split where only
//! the subject differs from the cell before: the opaque fixed objects and the background drawn
//! once into a layer (`Targets::layer`), copied into each such cell's targets, and the subject
//! and the queue drawn over it — the same draws in the same order on the same samples, so the
//! same bytes as the whole frame (`--no-reuse` draws it whole; a test compares the two).

use super::FrameDraw;
use crate::declarations::scene::Role;
use crate::gpu::timing::PassTimer;
use crate::render::pipeline_cache::ByFace;
use crate::render::prepared::PreparedScene;
use crate::render::targets::Targets;

/// The pipelines a forward frame draws with: the subject's and the fixed objects' (each with its
/// ForwardAdd pipeline where it has additive passes), the background's (None: the frame has none),
/// and the rays' group for the study's exact alternatives.
pub(in crate::render) struct ForwardPipelines<'a> {
    pub(in crate::render) subject: ModelPipelines<'a>,
    pub(in crate::render) fixed: ModelPipelines<'a>,
    /// The transparent fixed objects' (None: the frame draws none).
    pub(in crate::render) fixed_transparent: Option<ModelPipelines<'a>>,
    pub(in crate::render) background: Option<&'a wgpu::RenderPipeline>,
    pub(in crate::render) rays: Option<&'a wgpu::BindGroup>,
}

/// A model's forward pipelines, per render face: its one draw (or ForwardBase) and its ForwardAdd.
#[derive(Clone, Copy)]
pub(in crate::render) struct ModelPipelines<'a> {
    pub(in crate::render) draw: ByFace<'a>,
    pub(in crate::render) add: Option<ByFace<'a>>,
}

/// Draw the meshes `which` admits, in the scene's order (`draw_meshes`).
pub(in crate::render) fn draw_objects(
    pass: &mut wgpu::RenderPass,
    (prepared, draw): (&PreparedScene, &FrameDraw),
    pipelines: &ForwardPipelines,
    forward_add: &[Vec<usize>],
    which: impl Fn(usize) -> bool,
) {
    let meshes = (0..prepared.objects.len()).filter(|&i| which(i));
    draw_meshes(pass, (prepared, draw), pipelines, forward_add, meshes);
}

/// Draw the meshes `order` names, in that order: each in its model's pipeline with its screen
/// group (`draw`), then once per ForwardAdd light (`forward_add`, plan::draws) as one instance
/// whose index is the light.
pub(in crate::render) fn draw_meshes(
    pass: &mut wgpu::RenderPass,
    (prepared, draw): (&PreparedScene, &FrameDraw),
    pipelines: &ForwardPipelines,
    forward_add: &[Vec<usize>],
    order: impl Iterator<Item = usize>,
) {
    for i in order {
        let o = &prepared.objects[i];
        pass.set_bind_group(2, draw.screen_of(prepared, i), &[]);
        let subject = prepared.layout.meshes[i].role == Role::Subject;
        let model = match (subject, draw.transparent[i]) {
            (true, _) => pipelines.subject,
            (false, false) => pipelines.fixed,
            (false, true) => pipelines.fixed_transparent.expect("a pipeline for the transparent fixed objects"),
        };
        let face = prepared.layout.meshes[i].render_face as usize;
        pass.set_pipeline(model.draw[face].expect("a pipeline for every face drawn"));
        pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
        pass.set_vertex_buffer(0, o.vertices.slice(..));
        pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..o.index_count, 0, 0..1);
        if let (Some(add), Some(lights)) = (model.add, forward_add.get(i).filter(|l| !l.is_empty())) {
            pass.set_pipeline(add[face].expect("a ForwardAdd pipeline for every face drawn"));
            for &light in lights {
                pass.draw_indexed(0..o.index_count, 0, light as u32..light as u32 + 1);
            }
        }
    }
}

/// Which part of a forward frame a pass draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(in crate::render) enum ForwardDraw {
    /// The whole frame on cleared targets.
    Whole,
    /// The fixed objects and the background on cleared targets, every target kept (the layer).
    FixedLayer,
    /// The subject over targets that hold the fixed layer.
    SubjectOver,
}

/// Where a forward frame draws: the frame's targets, or their multisampled twins resolved into them.
pub(in crate::render) struct ForwardTargets<'a> {
    color: &'a wgpu::TextureView,
    role: &'a wgpu::TextureView,
    depth: &'a wgpu::TextureView,
    resolve: Option<(&'a wgpu::TextureView, &'a wgpu::TextureView)>,
    /// The depth is stored for a pass after this one (HDRP's subsurface scattering reads it).
    keep_depth: bool,
}

impl<'a> ForwardTargets<'a> {
    pub(in crate::render) fn of(t: &'a Targets, samples: u32) -> ForwardTargets<'a> {
        match t.msaa.as_ref().filter(|_| samples > 1) {
            Some(m) => ForwardTargets {
                color: &m.color,
                role: &m.role,
                depth: &m.depth,
                resolve: Some((&t.color_view, &t.role_view)),
                keep_depth: false,
            },
            None => ForwardTargets {
                color: &t.color_view,
                role: &t.role_view,
                depth: &t.depth_view,
                resolve: None,
                keep_depth: false,
            },
        }
    }

    /// The fixed-object layer's own targets (no resolve: the samples are what is kept).
    pub(in crate::render) fn layer(t: &'a crate::render::targets::ColorRoleDepth) -> ForwardTargets<'a> {
        ForwardTargets { color: &t.color, role: &t.role, depth: &t.depth, resolve: None, keep_depth: true }
    }
}

#[allow(clippy::too_many_arguments)]
pub(in crate::render) fn encode_forward(
    encoder: &mut wgpu::CommandEncoder,
    prepared: &PreparedScene,
    draw: &FrameDraw,
    pipelines: &ForwardPipelines,
    forward_add: &[Vec<usize>],
    targets: &ForwardTargets,
    part: ForwardDraw,
    timed: Option<(&PassTimer, u32)>,
) {
    // Multisampled targets are resolved at the end of the pass; only the resolve is kept, except
    // in the layer, whose samples are copied into later frames.
    let keep = if targets.resolve.is_some() { wgpu::StoreOp::Discard } else { wgpu::StoreOp::Store };
    let layer = part == ForwardDraw::FixedLayer;
    let (load_color, load_role, load_depth) = match part {
        ForwardDraw::SubjectOver => (wgpu::LoadOp::Load, wgpu::LoadOp::Load, wgpu::LoadOp::Load),
        _ => (
            wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            wgpu::LoadOp::Clear(1.0),
        ),
    };
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(crate::plan::Pass::Forward.name()),
        color_attachments: &[
            Some(wgpu::RenderPassColorAttachment {
                view: targets.color,
                depth_slice: None,
                resolve_target: targets.resolve.map(|r| r.0),
                ops: wgpu::Operations { load: load_color, store: keep },
            }),
            Some(wgpu::RenderPassColorAttachment {
                view: targets.role,
                depth_slice: None,
                resolve_target: targets.resolve.map(|r| r.1),
                ops: wgpu::Operations { load: load_role, store: keep },
            }),
        ],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: targets.depth,
            depth_ops: Some(wgpu::Operations {
                load: load_depth,
                store: if layer || targets.keep_depth { wgpu::StoreOp::Store } else { wgpu::StoreOp::Discard },
            }),
            stencil_ops: None,
        }),
        timestamp_writes: timed.map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, draw.group, &[]);
    pass.set_bind_group(2, draw.screen, &[]);
    if let Some(group) = pipelines.rays {
        pass.set_bind_group(3, group, &[]);
    }
    let subject = |i: usize| prepared.layout.meshes[i].role == Role::Subject;
    let opaque = |i: usize| draw.drawn[i] && !draw.transparent[i];
    if part != ForwardDraw::SubjectOver {
        draw_objects(&mut pass, (prepared, draw), pipelines, forward_add, |i| opaque(i) && !subject(i));
        // The background's layout has the object group, which it does not read: with no fixed
        // object drawn before it, one is bound.
        pass.set_bind_group(1, &prepared.object_bind_group, &[0]);
        super::background::draw_background(&mut pass, pipelines.background);
    }
    if part != ForwardDraw::FixedLayer {
        draw_objects(&mut pass, (prepared, draw), pipelines, forward_add, |i| opaque(i) && subject(i));
        let queue = draw.transparent_order.iter().copied();
        draw_meshes(&mut pass, (prepared, draw), pipelines, forward_add, queue);
    }
}

/// The forward (or vertex-lit) pass of a frame on `targets`. `layer`: Some where the frame may
/// draw the subject alone over the fixed-object layer (Some(true): the layer is drawn first, its
/// inputs having changed); None: the whole frame. `keep_depth`: a later pass reads the depth.
#[allow(clippy::too_many_arguments)]
pub(in crate::render) fn encode_forward_pass(
    encoder: &mut wgpu::CommandEncoder,
    prepared: &PreparedScene,
    draw: &FrameDraw,
    (pipelines, forward_add): (&ForwardPipelines, &[Vec<usize>]),
    targets: &Targets,
    (samples, keep_depth): (u32, bool),
    layer: Option<bool>,
    timed: Option<(&PassTimer, u32)>,
) {
    let part = match (layer, targets.layer.as_ref()) {
        (Some(build), Some(l)) => {
            if build {
                let into = ForwardTargets::layer(&l.targets);
                encode_forward(encoder, prepared, draw, pipelines, forward_add, &into, ForwardDraw::FixedLayer, None);
            }
            targets.restore_layer(encoder, samples);
            ForwardDraw::SubjectOver
        }
        _ => ForwardDraw::Whole,
    };
    let into = ForwardTargets { keep_depth, ..ForwardTargets::of(targets, samples) };
    encode_forward(encoder, prepared, draw, pipelines, forward_add, &into, part, timed);
}
