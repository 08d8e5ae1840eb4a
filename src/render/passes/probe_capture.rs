//! The reflection probes' capture and prefilter, once per set of inputs before a cell's frames:
//! each probe renders the fixed objects and the sky into its six faces, lit as the cell lights
//! them and reflecting the sky alone (one bounce, Unity's default), and the faces are
//! prefiltered into the probe's roughness levels (render::reflection_probes). A later cell whose capture
//! would see the same reads the slot already captured.

use glam::DVec3;

use super::shadow::encode_shadow_passes;
use crate::declarations::scene::Role;
use crate::error::Error;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
use crate::pipelines::surface::RenderFace;
use crate::plan::cell::{CellParams, CellPlan};
use crate::plan::Pass;
use crate::render::frame_bindings::FrameBindings;
use crate::render::pipeline_cache::{faces_of, ByFace, ForwardKey, PipelineCache};
use crate::render::prepared::PreparedScene;
use crate::render::reflection_probes::{Prefilter, Slot};
use crate::render::uniforms::{mat, vec4, FrameUniforms, GpuReflectionProbe};
use crate::shading::ShaderModel;

/// The pass's own state: the prefilter (made for the first composition with probes) and its
/// timestamp pairs (capture, prefilter).
#[derive(Default)]
pub(in crate::render) struct ProbeCapture {
    pub(in crate::render) prefilter: Option<Prefilter>,
    timer: Option<PassTimer>,
}

/// What a capture draws: the cell as planned, its frame's uniforms with the hash of what a
/// capture sees of them, and the shadow pass it lights the faces with (the shadow pipeline, and
/// the subject's where its alpha clips or dithers what it casts).
pub(in crate::render) struct CaptureScene<'a> {
    pub(in crate::render) prepared: &'a PreparedScene,
    pub(in crate::render) cell: &'a CellParams<'a>,
    pub(in crate::render) plan: &'a CellPlan,
    pub(in crate::render) fixed_model: &'a ShaderModel,
    pub(in crate::render) frame: &'a FrameUniforms,
    pub(in crate::render) capture_key: u64,
    pub(in crate::render) shadow: (&'a wgpu::RenderPipeline, Option<(&'a wgpu::RenderPipeline, &'a wgpu::BindGroup)>),
    pub(in crate::render) neutral_screen: &'a wgpu::BindGroup,
    /// Whether a slot captured with the same inputs may be read (`--no-reuse`: false).
    pub(in crate::render) reuse: bool,
}

impl ProbeCapture {
    /// Point the cell's frame at the probe levels it reads, capturing them first unless a slot
    /// holds them. Returns the GPU time of the capture and of the prefilter that made them, ms
    /// (None: no probes, or no timestamp queries).
    pub(in crate::render) fn capture(
        &mut self,
        gpu: &GpuContext,
        (pipelines, bindings): (&mut PipelineCache, &mut FrameBindings),
        s: CaptureScene,
    ) -> Result<Option<(f64, f64)>, Error> {
        let (prepared, cell) = (s.prepared, s.cell);
        let Some(probes) = &prepared.probes else { return Ok(None) };
        let slot = probes.slot_for(s.capture_key, s.reuse);
        // Point the cell's frame at the slot's levels.
        let mut frame = *s.frame;
        let count = probes.probes.len();
        for (k, t) in probes.probes.iter().enumerate() {
            frame.probes[k] = GpuReflectionProbe::new(&t.probe, &s.plan.probes[k], (k, count, slot.index()));
        }
        gpu.queue.write_buffer(&prepared.frame_buffer, 0, bytemuck::bytes_of(&frame));
        let slot = match slot {
            Slot::ToCapture(slot) => slot,
            Slot::Captured(slot) => return Ok(probes.capture_times(slot)),
        };
        let faces = faces_of(&prepared.layout, |m| m.role == Role::Fixed && !m.transparent);
        let key = ForwardKey::plain(prepared.fixed_maps.any(), RenderFace::Front);
        for &face in &faces {
            pipelines.forward_pipeline(gpu, cell.pipeline, s.fixed_model, ForwardKey { face, ..key })?;
        }
        if prepared.plan.background {
            // Probes capture the whole light, whatever the frame being drawn holds.
            let terms = std::mem::replace(&mut pipelines.terms, crate::pipelines::terms::LIGHT);
            let made = pipelines.background_pipeline(gpu, 1);
            pipelines.terms = terms;
            made?;
        }
        let (device, queue) = (&gpu.device, &gpu.queue);
        bindings
            .material_textures
            .entry("")
            .or_insert_with(|| crate::render::material_maps::MaterialTextures::neutral(device, queue));
        if gpu.record.timestamp_queries && self.timer.is_none() {
            self.timer = Some(PassTimer::new(&gpu.device, &gpu.queue, 2));
        }
        let timer = self.timer.as_ref().filter(|_| gpu.record.timestamp_queries);
        let drawn = FaceDraws {
            fixed: pipelines.forward_by_face(cell.pipeline, &s.fixed_model.name, key, &faces),
            background: pipelines
                .background
                .get(&(1, crate::pipelines::terms::LIGHT))
                .filter(|_| prepared.plan.background),
        };
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        // The capture is lit as the composition's frames are, whatever the cell's path: a
        // vertex-lit cell draws no shadow pass itself, but the probes it reads hold shadows.
        if prepared.plan.shadows() && !s.plan.used_layers.is_empty() {
            let casting = s.plan.shadow_casters(&prepared.layout);
            let layers = (&s.plan.used_layers[..], &casting[..], &s.plan.dynamic_casters_only[..]);
            encode_shadow_passes(&mut encoder, s.shadow.0, prepared, layers, s.shadow.1, None);
            // The probe's own layers now: a cell cannot keep what it finds there.
            *prepared.shadows.holds.lock().unwrap_or_else(|e| e.into_inner()) = None;
        }
        encode_faces(gpu, bindings, &s, &drawn, &mut encoder, timer);
        let prefilter = self.prefilter.as_ref().expect("made with the scene's probes");
        let weight = crate::environment::filtered::LobeWeight::of_pipeline(cell.pipeline);
        probes.encode_prefilter(prefilter, &mut encoder, (slot, weight), timer.map(|t| t.compute_writes(1)));
        if let Some(t) = timer {
            t.encode_resolve(&mut encoder, 2);
        }
        gpu.queue.submit([encoder.finish()]);
        gpu.wait_idle()?;
        let times = timer.map(|t| t.read_ms(&gpu.device, 2)).transpose()?;
        gpu.check_errors("capturing reflection probes")?;
        let times = times.map(|t| (t[0], t[1]));
        probes.captured(slot, s.capture_key, times);
        Ok(times)
    }
}

/// The pipelines a face draws with: the fixed objects' per render face, and the sky's.
struct FaceDraws<'a> {
    fixed: ByFace<'a>,
    background: Option<&'a wgpu::RenderPipeline>,
}

/// Every probe's six faces, one render pass each, timed as one span (pair 0).
fn encode_faces(
    gpu: &GpuContext,
    bindings: &FrameBindings,
    s: &CaptureScene,
    draws: &FaceDraws,
    encoder: &mut wgpu::CommandEncoder,
    timer: Option<&PassTimer>,
) {
    let prepared = s.prepared;
    let probes = prepared.probes.as_ref().expect("a scene with probes");
    let neutral = &bindings.material_textures[""];
    let drawn = s.plan.drawn();
    let faces = probes.probes.len() * 6;
    let mut groups = Vec::with_capacity(faces);
    for t in &probes.probes {
        for (f, vp) in t.view_proj.iter().enumerate() {
            let mut seen = *s.frame;
            seen.view_proj = mat(*vp);
            seen.inv_view_proj = mat(vp.inverse());
            seen.camera_pos = vec4(DVec3::from(t.probe.position), 1.0);
            // The captured objects reflect the sky alone (one bounce, Unity's default).
            seen.reflection = [0; 4];
            gpu.queue.write_buffer(&t.frame_buffers[f], 0, bytemuck::bytes_of(&seen));
            groups.push(bindings.frame_bind_group(&gpu.device, prepared, &t.frame_buffers[f], neutral));
        }
    }
    let mut face = 0;
    for t in &probes.probes {
        for f in 0..6 {
            // One span over every face: begin at the first pass, end at the last.
            let (first, last) = (face == 0, face + 1 == faces);
            let timestamps = timer.filter(|_| first || last).map(|tm| tm.writes(0, first, last));
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(Pass::ProbeCapture.name()),
                color_attachments: &[
                    Some(wgpu::RenderPassColorAttachment {
                        view: &t.face_views[f],
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                            store: wgpu::StoreOp::Store,
                        },
                    }),
                    Some(wgpu::RenderPassColorAttachment {
                        view: &t.role_views[f],
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Discard,
                        },
                    }),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                timestamp_writes: timestamps,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &groups[face], &[]);
            pass.set_bind_group(2, s.neutral_screen, &[]);
            // The subject is left out: a dynamic object, which baked probes do not see; so is the
            // Transparent queue (the plan says so in its left-out list).
            let fixed = |i: usize| {
                let m = &prepared.layout.meshes[i];
                drawn[i] && m.role == Role::Fixed && !m.transparent
            };
            for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| fixed(*i)) {
                let face = prepared.layout.meshes[i].render_face as usize;
                pass.set_pipeline(draws.fixed[face].expect("a pipeline for every face drawn"));
                pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
                pass.set_vertex_buffer(0, o.vertices.slice(..));
                pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..o.index_count, 0, 0..1);
            }
            if let Some(bg) = draws.background {
                pass.set_pipeline(bg);
                pass.draw(0..3, 0..1);
            }
            face += 1;
        }
    }
}
