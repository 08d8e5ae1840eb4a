//! The frame loop: a cell's frames, each running the passes its plan lists (`CellPlan::passes`,
//! `plan::Pass`) in that order, each pass encoded by its file in `passes/` from the state that
//! pass owns. The loop decides nothing an engine decides: what runs is the plan's list, less what
//! runs once before the frames (the probe captures), the post-processing a term layer leaves
//! out, and what an untimed cell keeps from the cell before (the same bytes: `--no-reuse` draws
//! everything, and a test compares the two).

use std::time::Instant;

use super::cell_uniforms::{write_uniforms, WrittenFrame};
use super::passes::deferred::{self, DeferredFrame};
use super::passes::forward::{encode_forward_pass, ForwardPipelines, ModelPipelines};
use super::passes::prepass::encode_depth_prepass;
use super::passes::probe_capture::CaptureScene;
use super::passes::shadow::encode_shadow_passes;
use super::passes::subsurface::{encode_lighting as encode_subsurface_lighting, SubsurfaceFrame};
use super::passes::FrameDraw;
use super::pipeline_cache::ByFace;
use super::prepared::PreparedScene;
use super::renderer::{CellRender, FrameMode, Renderer};
use super::warmup::{warm_up, FrameKeys, ModelKeys};
use crate::declarations::scene::Role;
use crate::error::Error;
use crate::gpu::timing::PassTimer;
use crate::pipelines::surface::RenderFace;
use crate::plan::cell::{CellParams, CellPlan};
use crate::plan::Pass;
use crate::shading::ShaderModel;

/// Which meshes each pass draws this frame.
struct FrameMeshes {
    drawn: Vec<bool>,
    /// Shadowing the lights (`CellPlan::shadow_casters`): drawn into the shadow maps, and what the
    /// study's traced visibility casts against.
    casting: Vec<bool>,
    /// The depth prepass draws the opaque queues only: the Transparent queue writes no depth.
    prepass: Vec<bool>,
}

impl FrameMeshes {
    fn of(plan: &CellPlan, layout: &crate::plan::cell::SceneLayout) -> FrameMeshes {
        let drawn = plan.drawn();
        let prepass = drawn.iter().zip(&plan.transparent).map(|(d, t)| *d && !t).collect();
        FrameMeshes { casting: plan.shadow_casters(layout), drawn, prepass }
    }
}

/// What a frame's passes read besides the renderer's own state.
struct FrameInputs<'a> {
    prepared: &'a PreparedScene,
    cell: &'a CellParams<'a>,
    plan: &'a CellPlan,
    fixed_model: &'a ShaderModel,
    frame_group: &'a wgpu::BindGroup,
    meshes: &'a FrameMeshes,
    keys: &'a FrameKeys,
    /// The SSAO visibility the lighting reads (the neutral group without SSAO).
    screen: &'a wgpu::BindGroup,
    /// The subject's alpha-caster shadow group (`passes::shadow`), where its alpha reaches its shadow.
    alpha_caster: Option<&'a wgpu::BindGroup>,
    /// The rays' group without and with the traced mask (the study's exact alternatives).
    rays: Option<(wgpu::BindGroup, wgpu::BindGroup)>,
    tile_group: Option<wgpu::BindGroup>,
    /// The forward frame's fixed-object layer (`passes::forward::encode_forward_pass`).
    layer: Option<bool>,
}

impl Renderer {
    /// Draw `warmup` untimed frames, then `frames` timed ones, of a planned cell; read back the last.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn draw_frames(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
        frames: u32,
        warmup: u32,
        reuse: bool,
        mode: FrameMode,
    ) -> Result<CellRender, Error> {
        // The read-back image is the last frame's: with no frame drawn it would be black, or the
        // cell before's pixels left in the target.
        let Some(total) = warmup.checked_add(frames).filter(|_| frames > 0) else {
            return Err(Error::Other(format!(
                "no frame to render: {frames} timed frames after {warmup} warm-up frames"
            )));
        };
        self.pipelines.terms = mode.terms;
        let fixed_model = self.fixed_model(cell.pipeline)?;
        check_exact(cell, &fixed_model)?;
        // The subject's lighting splits where its subsurface scattering runs: in the image, not in
        // a term layer (Pass::post).
        let split = plan.has(Pass::SubsurfaceScattering) && mode.post;
        let keys = warm_up(&mut self.pipelines, &self.gpu, (prepared, cell, plan), &fixed_model, (mode.terms, split))?;
        let bakes_before = prepared.bakes.lock().unwrap_or_else(|e| e.into_inner()).len();
        let baked = self.baked_lighting(prepared, cell, plan, &fixed_model)?;
        let made_bake = prepared.bakes.lock().unwrap_or_else(|e| e.into_inner()).len() > bakes_before;
        if let Some(b) = &baked {
            prepared.lightmap_texture.hold(&self.gpu.queue, b);
        }
        let written = write_uniforms(&self.gpu.queue, prepared, cell, plan, &fixed_model, baked.as_deref());
        let frame_group = self.bindings.frame_group(&self.gpu, prepared, cell.settings.material_maps)?;
        // A flat subject's albedo is the neutral set's (alpha 1): its base alpha alone.
        let albedo = self.bindings.albedo_view(prepared, cell.settings.material_maps);
        let casts = prepared.plan.shadows() && !plan.used_layers.is_empty();
        let surface = (plan.subject_caster, cell.settings.surface.alpha, casts);
        let alpha_caster = self.shadow.alpha_caster_group(
            &self.gpu,
            &self.object_layout,
            surface,
            (albedo, &self.bindings.material_sampler),
        );
        let scene = CaptureScene {
            prepared,
            cell,
            plan,
            fixed_model: &fixed_model,
            frame: &written.frame,
            capture_key: written.capture_key,
            shadow: (&self.shadow.pipeline, self.shadow.alpha_caster(alpha_caster.as_ref())),
            neutral_screen: &self.neutral_screen,
            reuse: self.reuse,
        };
        let probe_times = self.probes.capture(&self.gpu, (&mut self.pipelines, &mut self.bindings), scene)?;
        let meshes = FrameMeshes::of(plan, &prepared.layout);
        let runs = self.prepare_passes((prepared, cell, plan), (&written, &keys), &meshes, (reuse, mode, total))?;
        let per_frame = runs.passes.len() as u32;
        if self.gpu.record.timestamp_queries && self.timer.as_ref().is_none_or(|t| t.capacity() < frames * per_frame) {
            self.timer = Some(PassTimer::new(&self.gpu.device, &self.gpu.queue, frames * per_frame));
        }
        let timer = self.timer.as_ref().filter(|_| self.gpu.record.timestamp_queries);
        let screen = match (plan.has(Pass::Ssao), plan.has(Pass::UrpSsao)) {
            (true, _) => self.ssao.ready().map(|(_, _, g)| g),
            (_, true) => self.urp_ssao.ready().map(|(_, _, g)| g),
            _ => None,
        }
        .unwrap_or(&self.neutral_screen);
        let f = FrameInputs {
            prepared,
            cell,
            plan,
            fixed_model: &fixed_model,
            frame_group: &frame_group,
            meshes: &meshes,
            keys: &keys,
            screen,
            alpha_caster: alpha_caster.as_ref(),
            rays: runs.rays,
            tile_group: runs.tile_group,
            layer: runs.layer,
        };
        let t = self.targets.as_ref().expect("targets exist");
        let blooms = runs.passes.contains(&Pass::Bloom);
        let mut frame_ms = Vec::with_capacity(frames as usize);
        for frame in 0..total {
            let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
            for (k, &pass) in runs.passes.iter().enumerate() {
                let timed = timer.filter(|_| frame >= warmup).map(|t| (t, (frame - warmup) * per_frame + k as u32));
                self.encode_pass(pass, &f, &mut encoder, timed);
            }
            if frame + 1 == total {
                let image = match self.bloom.ready().filter(|_| blooms) {
                    Some((chain, _)) => &chain.output,
                    None => &t.color,
                };
                t.color_readback.encode_copy(&mut encoder, image);
                t.role_readback.encode_copy(&mut encoder, &t.role);
                if let Some(timer) = timer {
                    timer.encode_resolve(&mut encoder, frames * per_frame);
                }
            }
            let start = Instant::now();
            self.gpu.queue.submit([encoder.finish()]);
            self.gpu.wait_idle()?;
            if frame >= warmup {
                frame_ms.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        let read_start = Instant::now();
        let hdr_bytes = t.color_readback.read(&self.gpu.device)?;
        let roles = t.role_readback.read(&self.gpu.device)?;
        let readback_ms = read_start.elapsed().as_secs_f64() * 1e3;
        let pairs = timer.map(|t| t.read_ms(&self.gpu.device, frames * per_frame)).transpose()?;
        self.gpu.check_errors("rendering a cell")?;
        let covered = prepared.lightmap.as_ref().map_or(0, |a| a.texels.len());
        Ok(CellRender {
            width: cell.width,
            height: cell.height,
            hdr: bytemuck::cast_slice(&hdr_bytes).to_vec(),
            roles,
            frame_ms,
            gpu_pass_ms: pairs.as_ref().map(|p| p.chunks(per_frame as usize).map(|f| f.iter().sum()).collect()),
            gpu_passes: pairs.map(|p| pass_times(&runs.passes, &p, probe_times)),
            readback_ms,
            terms: None,
            bake: plan.gi.as_ref().map(|g| crate::render::gi::BakeUse::of(g, baked.as_deref(), made_bake, covered)),
        })
    }

    /// Ready every pass of the frame (its targets, chains and pipelines) and decide which run:
    /// the plan's per-frame passes, less what an untimed frame keeps from the cell before.
    fn prepare_passes(
        &mut self,
        (prepared, cell, plan): (&PreparedScene, &CellParams, &CellPlan),
        (written, keys): (&WrittenFrame, &FrameKeys),
        meshes: &FrameMeshes,
        (reuse, mode, total): (bool, FrameMode, u32),
    ) -> Result<FrameRuns, Error> {
        let exact = cell.settings.exact;
        let rays = match exact.any() {
            true => Some(self.ray_scene(prepared, meshes.casting.clone())?),
            false => None,
        };
        self.targets(cell.width, cell.height);
        let samples = plan.multisampling.samples;
        let t = self.targets.as_mut().expect("targets exist");
        t.ensure_msaa(&self.gpu.device, samples);
        let t = self.targets.as_ref().expect("targets exist");
        let blooms = plan.has(Pass::Bloom) && mode.post;
        if blooms {
            let quality = cell.settings.engine.hdrp.bloom_quality;
            self.bloom.prepare(&self.gpu, t, crate::render::passes::bloom::BloomSettings::at(quality))?;
        }
        if let Some(sss) = plan.subsurface.as_ref().filter(|_| mode.post && plan.has(Pass::SubsurfaceScattering)) {
            let frame = SubsurfaceFrame::new(&plan.camera, (cell.width, cell.height), sss);
            self.subsurface.prepare(&self.gpu, t, &frame)?;
        }
        // The prepass and SSAO read the camera, the meshes drawn and their transforms, and the
        // subject's normal map; traced visibility reads the prepass depth itself.
        let ssao_key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::hash::DefaultHasher::new();
            (written.prepass_key, cell.pipeline, cell.width, cell.height, &meshes.prepass).hash(&mut h);
            cell.settings.engine.hdrp.ssao_quality.hash(&mut h);
            cell.settings.material_maps.hash(&mut h);
            h.finish()
        };
        let occludes = plan.has(Pass::Ssao) || plan.has(Pass::UrpSsao);
        let keep = reuse && !exact.any();
        let occludes_now = match (plan.has(Pass::Ssao), plan.ao.urp.filter(|_| plan.has(Pass::UrpSsao))) {
            (true, _) => {
                let settings = crate::render::passes::ssao::SsaoSettings::at(cell.settings.engine.hdrp.ssao_quality);
                self.ssao.prepare(&self.gpu, &self.screen_layout, t, &plan.camera, &settings)?;
                self.ssao.needed(ssao_key, keep)
            }
            (false, Some(feature)) => {
                self.urp_ssao.prepare(&self.gpu, &self.screen_layout, t, &plan.camera, &feature)?;
                self.urp_ssao.needed(ssao_key, keep)
            }
            (false, None) => false,
        };
        if plan.has(Pass::TracedShadows) {
            let layouts = (&self.bindings.layout, &self.ray_layout);
            self.traced.prepare(&self.gpu, layouts, cell.pipeline, t)?;
        }
        let shadows_now = plan.has(Pass::Shadow) && {
            let mut holds = prepared.shadows.holds.lock().unwrap_or_else(|e| e.into_inner());
            let kept = reuse && *holds == Some(written.shadow_key);
            *holds = Some(written.shadow_key);
            !kept
        };
        let passes: Vec<Pass> = plan
            .passes
            .iter()
            .copied()
            .filter(|p| !p.before_frames() && (mode.post || !p.post()))
            .filter(|p| match p {
                Pass::Shadow => shadows_now,
                Pass::Ssao | Pass::UrpSsao => occludes_now,
                Pass::DepthPrepass => occludes_now || plan.has(Pass::TracedShadows),
                _ => true,
            })
            .collect();
        let tile_group = match plan.has(Pass::LightTiles) {
            true => {
                let hdrp = self.fixed_model(crate::pipelines::Pipeline::Hdrp)?;
                let size = (cell.width, cell.height, prepared.scene.lights.len());
                let t = self.targets.as_ref().expect("targets exist");
                Some(self.tiles.prepare(&self.gpu, &hdrp, size, &t.depth_view)?)
            }
            false => None,
        };
        let ssao_key = occludes.then_some(ssao_key);
        let layer = self.fixed_layer((prepared, cell, plan), (written, keys.fixed), meshes, (reuse, total, ssao_key));
        // The rays' group for the traced-shadow pass (no mask) and for the forward pass (reading
        // the traced mask where visibility is traced).
        let rays = rays.map(|scene| {
            let forward = match self.traced.ready(cell.pipeline).filter(|_| exact.visibility) {
                Some((traced, _)) => scene.group_with_mask(&self.gpu.device, &self.ray_layout, &traced.mask),
                None => scene.group.clone(),
            };
            (scene.group.clone(), forward)
        });
        Ok(FrameRuns { passes, tile_group, layer, rays })
    }

    /// Whether an untimed forward frame draws the subject alone over a copy of the fixed-object
    /// layer (`passes::forward`): where the fixed objects and background read what the layer's
    /// did. Some(true): the layer is drawn first.
    fn fixed_layer(
        &mut self,
        (prepared, cell, plan): (&PreparedScene, &CellParams, &CellPlan),
        (written, fixed_keys): (&WrittenFrame, ModelKeys),
        meshes: &FrameMeshes,
        (reuse, total, ssao_key): (bool, u32, Option<u64>),
    ) -> Option<bool> {
        let forward = !plan.has(Pass::GBuffer);
        let fixed = |i: &usize| prepared.layout.meshes[*i].role == Role::Fixed;
        let has_fixed = (0..meshes.drawn.len()).filter(fixed).any(|i| meshes.drawn[i]);
        if !(reuse && forward && !cell.settings.exact.any() && has_fixed && total == 1) {
            return None;
        }
        let key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::hash::DefaultHasher::new();
            (written.layer_key, written.shadow_key, ssao_key, self.pipelines.terms).hash(&mut h);
            (cell.pipeline, cell.settings.path, cell.width, cell.height, fixed_keys, prepared.plan.background)
                .hash(&mut h);
            for i in (0..meshes.drawn.len()).filter(fixed) {
                (meshes.drawn[i], &plan.draws.forward_add[i]).hash(&mut h);
            }
            h.finish()
        };
        let samples = plan.multisampling.samples;
        let layer = self.targets.as_mut().expect("targets exist").ensure_layer(&self.gpu.device, samples);
        let build = layer.key != Some(key);
        layer.key = Some(key);
        Some(build)
    }

    /// Encode one pass of a frame.
    fn encode_pass(
        &self,
        pass: Pass,
        f: &FrameInputs,
        encoder: &mut wgpu::CommandEncoder,
        timed: Option<(&PassTimer, u32)>,
    ) {
        let t = self.targets.as_ref().expect("targets exist");
        let (prepared, cell, plan) = (f.prepared, f.cell, f.plan);
        let subject_screen = if plan.ao.subject { f.screen } else { &self.neutral_screen };
        let draw = FrameDraw {
            group: f.frame_group,
            drawn: &f.meshes.drawn,
            screen: f.screen,
            subject_screen,
            transparent: &plan.transparent,
            transparent_order: &plan.transparent_order,
        };
        let forward = self.forward_pipelines(f);
        let deferred = |forward| DeferredFrame {
            prepared,
            draw,
            cell,
            fixed_model: f.fixed_model,
            targets: t,
            pipelines: &self.pipelines,
            forward,
            forward_add: &plan.draws.forward_add,
            gbuffer: plan.gbuffer,
            lights: plan.light_paths(),
        };
        // The prepass's normals: SSAO's, or the traced mask's where the frame has no SSAO.
        let normal = || {
            let hdrp = self.ssao.ready().filter(|_| plan.has(Pass::Ssao)).map(|(c, _, _)| &c.normal);
            let urp = self.urp_ssao.ready().filter(|_| plan.has(Pass::UrpSsao)).map(|(c, _, _)| &c.normal);
            match (hdrp.or(urp), self.traced.ready(cell.pipeline)) {
                (Some(normal), _) => normal,
                (None, Some((traced, _))) => &traced.normal,
                (None, None) => unreachable!("a depth prepass feeds SSAO or traced shadows"),
            }
        };
        match pass {
            Pass::ProbeCapture | Pass::ProbePrefilter => unreachable!("captured before the frames"),
            Pass::Shadow => {
                let layers = (&plan.used_layers[..], &f.meshes.casting[..], &plan.dynamic_casters_only[..]);
                let alpha_caster = self.shadow.alpha_caster(f.alpha_caster);
                encode_shadow_passes(encoder, &self.shadow.pipeline, prepared, layers, alpha_caster, timed);
            }
            Pass::DepthPrepass => {
                let by_face = self.prepass_by_face(cell, f.keys);
                let neutral = &self.neutral_screen;
                let draw = FrameDraw { drawn: &f.meshes.prepass, screen: neutral, subject_screen: neutral, ..draw };
                encode_depth_prepass(encoder, prepared, &draw, by_face, (normal(), &t.depth_view), timed);
            }
            Pass::Ssao => {
                let (chain, pipeline, _) = self.ssao.ready().expect("prepared with the frame");
                chain.encode(pipeline, encoder, timed.map(|(t, pair)| t.compute_writes(pair)));
            }
            Pass::UrpSsao => {
                let (chain, pipeline, _) = self.urp_ssao.ready().expect("prepared with the frame");
                chain.encode(pipeline, encoder, timed.map(|(t, pair)| t.compute_writes(pair)));
            }
            Pass::TracedShadows => {
                let (traced, pipeline) = self.traced.ready(cell.pipeline).expect("prepared with the frame");
                let (rays, _) = f.rays.as_ref().expect("a ray scene for traced visibility");
                let writes = timed.map(|(t, pair)| t.compute_writes(pair));
                let targets = (&t.depth_view, normal());
                traced.encode(&self.gpu.device, pipeline, encoder, f.frame_group, rays, targets, writes);
            }
            Pass::Forward | Pass::VertexLit => {
                let samples = (plan.multisampling.samples, f.keys.subsurface.is_some());
                let draws = (&forward, &plan.draws.forward_add[..]);
                encode_forward_pass(encoder, prepared, &draw, draws, t, samples, f.layer, timed);
            }
            Pass::GBuffer => deferred::encode_gbuffer(&deferred(&forward), encoder, timed),
            Pass::LightTiles => {
                let group = f.tile_group.as_ref().expect("prepared with the frame");
                self.tiles.encode(encoder, (f.frame_group, group), (cell.width, cell.height), timed);
            }
            Pass::DeferredLighting => deferred::encode_lighting(&deferred(&forward), &self.tiles.read, encoder, timed),
            Pass::ForwardOnly => {
                let keep_depth = plan.has(Pass::Transparent) || f.keys.subsurface.is_some();
                deferred::encode_forward_only(&deferred(&forward), keep_depth, encoder, timed);
            }
            Pass::SubsurfaceLighting => {
                let (buffers, _) = self.subsurface.ready().expect("prepared with the frame");
                let key = f.keys.subsurface.expect("a split subject's key");
                let by_face =
                    self.pipelines.forward_by_face(cell.pipeline, &cell.model.name, key, &f.keys.subject_faces);
                let pipelines = ForwardPipelines {
                    subject: ModelPipelines { draw: by_face, add: None },
                    ..self.forward_pipelines(f)
                };
                let draw = FrameDraw { screen: draw.subject_screen, ..draw };
                let targets = (buffers, &t.depth_view);
                encode_subsurface_lighting(encoder, (prepared, &draw), &pipelines, targets, timed);
            }
            Pass::SubsurfaceScattering => {
                let (buffers, pipeline) = self.subsurface.ready().expect("prepared with the frame");
                let writes = timed.map(|(t, pair)| t.compute_writes(pair));
                buffers.encode_scattering(pipeline, encoder, Some(&t.color), writes);
            }
            Pass::Transparent => deferred::encode_transparent(&deferred(&forward), encoder, timed),
            Pass::Bloom => {
                let (chain, pipeline) = self.bloom.ready().expect("prepared with the frame");
                chain.encode(pipeline, encoder, timed.map(|(t, pair)| t.compute_writes(pair)));
            }
        }
    }

    /// The forward pipelines of the frame's models, per render face.
    fn forward_pipelines<'a>(&'a self, f: &'a FrameInputs) -> ForwardPipelines<'a> {
        let model = |model: &ShaderModel, (draw, add): ModelKeys, faces: &[RenderFace]| {
            let by_face = |key| self.pipelines.forward_by_face(f.cell.pipeline, &model.name, key, faces);
            ModelPipelines { draw: by_face(draw), add: add.map(by_face) }
        };
        let samples = f.plan.multisampling.samples;
        let background = f.prepared.plan.background && !f.plan.has(Pass::GBuffer);
        ForwardPipelines {
            subject: model(f.cell.model, f.keys.subject, &f.keys.subject_faces),
            fixed: model(f.fixed_model, f.keys.fixed, &f.keys.fixed_faces),
            fixed_transparent: f
                .keys
                .fixed_transparent
                .map(|k| model(f.fixed_model, k, &f.keys.fixed_transparent_faces)),
            background: self.pipelines.background.get(&(samples, self.pipelines.terms)).filter(|_| background),
            rays: f.rays.as_ref().map(|(_, forward)| forward),
        }
    }

    /// The depth prepass's pipelines for the faces drawn.
    fn prepass_by_face(&self, cell: &CellParams, keys: &FrameKeys) -> ByFace<'_> {
        let mut out: ByFace = [None; 3];
        for &face in &keys.prepass_faces {
            out[face as usize] = Some(&self.pipelines.depth_normals[&(cell.pipeline, keys.prepass_textured, face)]);
        }
        out
    }
}

/// What `prepare_passes` readied: the passes this frame runs, in order, and their inputs.
struct FrameRuns {
    passes: Vec<Pass>,
    tile_group: Option<wgpu::BindGroup>,
    layer: Option<bool>,
    rays: Option<(wgpu::BindGroup, wgpu::BindGroup)>,
}

/// The study's exact alternatives are for per-pixel forward shading.
fn check_exact(cell: &CellParams, fixed_model: &ShaderModel) -> Result<(), Error> {
    let forward = cell.settings.path == crate::pipelines::RenderPath::Forward;
    if cell.settings.exact.any() && (!forward || cell.model.per_vertex || fixed_model.per_vertex) {
        return Err(Error::Other(format!(
            "exact alternatives are for per-pixel forward shading; {}/{} on the {} path has none",
            cell.pipeline.name(),
            cell.model.name,
            cell.settings.path.name()
        )));
    }
    Ok(())
}

/// Each pass's GPU time per frame, ms, in the plan's order: the probe captures once (the one
/// that made what the cell reads), then every pass the frames ran.
fn pass_times(runs: &[Pass], pairs: &[f64], probe_times: Option<(f64, f64)>) -> Vec<(Pass, Vec<f64>)> {
    let once = [(Pass::ProbeCapture, probe_times.map(|t| t.0)), (Pass::ProbePrefilter, probe_times.map(|t| t.1))];
    let mut passes: Vec<(Pass, Vec<f64>)> =
        once.into_iter().filter_map(|(pass, ms)| ms.map(|ms| (pass, vec![ms]))).collect();
    let per_frame = runs.len().max(1);
    passes.extend(
        runs.iter().enumerate().map(|(k, pass)| (*pass, pairs.iter().skip(k).step_by(per_frame).copied().collect())),
    );
    passes
}
