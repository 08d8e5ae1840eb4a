//! The renderer: device-lifetime state (layouts, samplers, compiled pipelines, targets) and the
//! frame loop that runs the passes a cell's plan lists (`plan::cell::CellPlan`), each encoded by
//! its file in `passes/`. Everything that does not change between cells is built once: pipelines
//! per (pipeline convention, model) in `pipeline_cache`, meshes and the environment per
//! composition in `prepared`, render targets per image size in `targets`. A cell rewrites its
//! uniforms (`cell_uniforms`) and draws.

use glam::DVec3;
use std::collections::HashMap;
use std::time::Instant;

use super::frame_bindings::FrameBindings;
use super::passes::deferred::{encode_deferred, lighting_draws};
use super::passes::forward::{encode_forward, ForwardDraw, ForwardPipelines, ForwardTargets, ModelPipelines};
use super::passes::prepass::{encode_depth_prepass, neutral_screen_group, screen_group};
use super::passes::shadow::{encode_shadow_passes, shadow_pipeline, CutoutShadow};
use super::passes::FrameDraw;
use super::pipeline_cache::{faces_of, ByFace, ForwardKey, ForwardPass, PipelineCache};
use super::prepared::PreparedScene;
use crate::declarations::scene::Role;
use crate::declarations::scene::Scene;
use crate::error::Error;
use crate::geometry::procedural;
use crate::geometry::Mesh;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
use crate::pipelines::surface::RenderFace;
use crate::pipelines::surface::SurfaceType;
use crate::pipelines::{Pipeline, RenderPath};
pub use crate::plan::cell::{CellParams, CellPlan, CellSettings, MsaaSupport, Multisampling};
use crate::plan::draws::{additive_passes, shadowed_by_additional_lights};
pub use crate::plan::lod::LodUse;
pub use crate::plan::ShadowMapUse;
use crate::plan::{FramePlan, Pass};
use crate::render::cell_uniforms::{write_uniforms, WrittenFrame};
use crate::render::formats::{DEPTH_FORMAT, HDR_FORMAT, ROLE_FORMAT};
use crate::render::targets::Targets;
use crate::render::uniforms::*;
use crate::shading::{wgsl, Registry, ShaderModel};

mod gi;
mod terms;
mod truths;
pub use terms::RenderedTerms;
use truths::{truth_geometry, truth_sky};

/// What a drawn frame holds: the terms drawn (pipelines::terms) and whether post-processing
/// (bloom) runs after them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FrameMode {
    pub(crate) terms: u32,
    pub(crate) post: bool,
}

impl FrameMode {
    /// The cell's image: every term, then its post-processing.
    pub(crate) const IMAGE: FrameMode = FrameMode { terms: crate::pipelines::terms::LIGHT, post: true };
}

pub struct CellRender {
    pub width: u32,
    pub height: u32,
    /// Linear RGBA, row-major, top row first.
    pub hdr: Vec<f32>,
    /// Per pixel: 0 background, 1 fixed object, 2 subject.
    pub roles: Vec<u8>,
    /// CPU wall time from submit to idle of each timed frame, ms.
    pub frame_ms: Vec<f64>,
    /// GPU time of the frame's render pass from timestamp queries, ms; None when the adapter has
    /// no timestamp queries.
    pub gpu_pass_ms: Option<Vec<f64>>,
    /// GPU time of each timed pass per frame, ms, in the order they ran (the plan's, less what
    /// the frame kept from the cell before); the probe captures once. None without timestamp
    /// queries.
    pub gpu_passes: Option<Vec<(Pass, Vec<f64>)>>,
    /// CPU time to map and copy the image back, ms.
    pub readback_ms: f64,
    /// The cell's term layers where its run asks for them (`draw_terms`), or why it has none.
    pub terms: Option<Result<RenderedTerms, String>>,
    /// What the frame read of the scene's bake (None: the scene bakes nothing).
    pub bake: Option<crate::render::gi::BakeUse>,
}

pub struct Renderer {
    pub gpu: GpuContext,
    object_layout: wgpu::BindGroupLayout,
    /// Group 0 of the scene passes: the frame's layout, samplers, tables and material maps.
    bindings: FrameBindings,
    /// Every render pipeline compiled so far.
    pipelines: PipelineCache,
    /// Fixed objects are drawn with each pipeline's default lit shader, a built-in model.
    fixed_models: Registry,
    shadow_layer_layout: wgpu::BindGroupLayout,
    shadow_pipeline: wgpu::RenderPipeline,
    gbuffer_read_layout: wgpu::BindGroupLayout,
    tiles: crate::render::gbuffer::LightTiles,
    targets: Option<Targets>,
    timer: Option<PassTimer>,
    /// The sample counts the adapter multisamples and resolves the forward targets with.
    msaa_counts: Vec<u32>,
    /// The reflection-probe prefilter, made for the first scene with probes.
    prefilter: Option<crate::render::passes::probes::Prefilter>,
    /// Two timestamp pairs: probe capture and prefilter.
    probe_timer: Option<PassTimer>,
    /// The shadow pass of a textured cutout subject, made for the first such cell.
    cutout_shadow: Option<CutoutShadow>,
    /// HDRP's bloom pipeline, made for the first cell that blooms.
    bloom: Option<crate::render::passes::bloom::BloomPipeline>,
    /// Group 2 of the scene passes: the screen-space occlusion the lighting reads.
    screen_layout: wgpu::BindGroupLayout,
    /// A 1×1 visibility of 1, for cells and captures without SSAO.
    neutral_screen: wgpu::BindGroup,
    /// HDRP's SSAO steps, made for the first cell that occludes.
    ssao: Option<crate::render::passes::ssao::SsaoPipeline>,
    /// The truth's tracers, by (pipeline, subject model, fixed model).
    truth_pipelines:
        HashMap<(Pipeline, String, String, crate::render::truth::TruthKind), crate::render::truth::TruthPipeline>,
    /// Group 3 of the tracer and of the exact alternatives: the scene as rays see it.
    ray_layout: wgpu::BindGroupLayout,
    /// The traced-shadow pass, by pipeline (its light attenuation), made for the first cell that traces.
    traced_shadows: HashMap<Pipeline, crate::render::passes::traced_shadows::TracedShadowsPipeline>,
    /// Whether an untimed cell may take a pass's output from the cell before when the pass's
    /// inputs are the same (`--no-reuse`: false); probe captures likewise.
    pub reuse: bool,
    /// Bakes kept across runs (render::gi::cache); None: each run bakes its own.
    pub bake_cache: Option<crate::render::gi::cache::BakeCache>,
}

impl Renderer {
    pub fn new(gpu: GpuContext) -> Renderer {
        let device = &gpu.device;
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    // Compute too: the tiled light loop reads the frame and the lights.
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
                    ty: wgpu::BindingType::Buffer {
                        ty: gpu.constants.binding(),
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<FrameUniforms>() as u64),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                super::luts::fgd_layout_entry(
                    3,
                    wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
                ),
                storage_entry(4),
                storage_entry(5),
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 7,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                storage_entry(8),
                material_map_entry(9),
                material_map_entry(10),
                material_map_entry(11),
                material_map_entry(13),
                material_map_entry(15),
                wgpu::BindGroupLayoutEntry {
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    ..material_map_entry(16)
                },
                wgpu::BindGroupLayoutEntry {
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    ..material_map_entry(14)
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 12,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let object_layout = super::uniform_slot_layout(
            device,
            gpu.constants,
            "object",
            wgpu::ShaderStages::VERTEX_FRAGMENT,
            std::mem::size_of::<ObjectUniforms>() as u64,
        );
        let screen_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("screen"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&frame_layout), Some(&object_layout), Some(&screen_layout)],
            immediate_size: 0,
        });
        let ray_layout = crate::render::truth::ray_layout(device, gpu.constants);
        let exact_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene with rays"),
            bind_group_layouts: &[Some(&frame_layout), Some(&object_layout), Some(&screen_layout), Some(&ray_layout)],
            immediate_size: 0,
        });
        let neutral_screen = neutral_screen_group(&gpu, &screen_layout);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("environment"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let fgd = super::luts::fgd_texture(&gpu);
        let material_sampler = crate::render::material_maps::sampler(device);
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow comparison"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let shadow_layer_layout =
            super::uniform_slot_layout(device, gpu.constants, "shadow layer", wgpu::ShaderStages::VERTEX, 64);
        let shadow_pipeline = shadow_pipeline(&gpu, &shadow_layer_layout, &object_layout);
        let gbuffer_read_layout = crate::render::gbuffer::read_layout(device);
        let tiles = crate::render::gbuffer::LightTiles::new(device, &frame_layout);
        let deferred_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(crate::plan::Pass::DeferredLighting.name()),
            bind_group_layouts: &[
                Some(&frame_layout),
                Some(&object_layout),
                Some(&gbuffer_read_layout),
                Some(&tiles.read_layout),
            ],
            immediate_size: 0,
        });
        let msaa_counts = gpu.multisample_counts(&[HDR_FORMAT, ROLE_FORMAT, DEPTH_FORMAT]);
        let detail = crate::render::material_maps::detail_texture(device, &gpu.queue);
        Renderer {
            gpu,
            object_layout,
            bindings: FrameBindings {
                layout: frame_layout,
                sampler,
                fgd,
                shadow_sampler,
                material_sampler,
                material_textures: HashMap::new(),
                detail,
            },
            pipelines: PipelineCache::new(pipeline_layout, exact_layout, deferred_layout),
            fixed_models: Registry::builtin(),
            shadow_layer_layout,
            shadow_pipeline,
            gbuffer_read_layout,
            tiles,
            targets: None,
            timer: None,
            msaa_counts,
            prefilter: None,
            probe_timer: None,
            cutout_shadow: None,
            bloom: None,
            screen_layout,
            neutral_screen,
            ssao: None,
            truth_pipelines: HashMap::new(),
            ray_layout,
            traced_shadows: HashMap::new(),
            reuse: true,
            bake_cache: None,
        }
    }

    /// Number of forward pipelines compiled so far (each (pipeline, model) pair once).
    pub fn compiled_pipelines(&self) -> usize {
        self.pipelines.compiled()
    }

    /// Generate meshes, build the environment and upload everything a composition needs.
    pub fn prepare_scene(&mut self, scene: &Scene) -> Result<PreparedScene, Error> {
        let meshes = procedural::build_scene(scene)?;
        self.upload_scene(scene, meshes)
    }

    /// Upload a composition whose meshes (one per object, in order) were built already.
    pub fn upload_scene(&mut self, scene: &Scene, meshes: Vec<Mesh>) -> Result<PreparedScene, Error> {
        self.upload_planned(scene, FramePlan::for_scene(scene), meshes)
    }

    /// `upload_scene` with the composition's frame plan made already (a run makes it once).
    pub fn upload_planned(
        &mut self,
        scene: &Scene,
        plan: FramePlan,
        meshes: Vec<Mesh>,
    ) -> Result<PreparedScene, Error> {
        let probes =
            scene.environment.reflections == crate::declarations::scene::Reflections::Probe && !scene.probes.is_empty();
        if probes && self.prefilter.is_none() {
            self.prefilter = Some(crate::render::passes::probes::Prefilter::new(&self.gpu)?);
        }
        let layouts = (&self.object_layout, &self.shadow_layer_layout);
        PreparedScene::upload(&self.gpu, layouts, self.prefilter.as_ref(), scene, plan, meshes)
    }

    /// The plan of a cell in a prepared composition, on this adapter: computed on the CPU before
    /// any GPU work (`plan::cell`).
    pub fn plan(&self, prepared: &PreparedScene, cell: &CellParams) -> Result<CellPlan, Error> {
        let fixed_model = self.fixed_model(cell.pipeline)?;
        Ok(CellPlan::new(&prepared.scene, &prepared.plan, &prepared.layout, cell, &fixed_model, &self.msaa_support()))
    }

    /// The model each pipeline draws the fixed objects with (its default lit shader).
    fn fixed_model(&self, pipeline: Pipeline) -> Result<std::sync::Arc<ShaderModel>, Error> {
        self.fixed_models
            .find(pipeline, pipeline.fixed_object_shader())
            .cloned()
            .ok_or_else(|| Error::Other(format!("pipeline {} lacks its fixed-object shader", pipeline.name())))
    }

    /// The sample counts this adapter multisamples and resolves every forward target with.
    pub fn msaa_support(&self) -> MsaaSupport {
        MsaaSupport {
            counts: self.msaa_counts.clone(),
            what: format!("{} multisamples {HDR_FORMAT:?}, {ROLE_FORMAT:?} and {DEPTH_FORMAT:?}", self.gpu.record.name),
        }
    }

    /// Plan and render one cell: `warmup` untimed frames, then `frames` timed ones; the last is
    /// read back.
    pub fn render(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        frames: u32,
        warmup: u32,
    ) -> Result<CellRender, Error> {
        let plan = self.plan(prepared, cell)?;
        self.draw(prepared, cell, &plan, frames, warmup)
    }

    /// `render`, with the plan the frame was drawn from.
    pub fn render_planned(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        frames: u32,
        warmup: u32,
    ) -> Result<(CellPlan, CellRender), Error> {
        let plan = self.plan(prepared, cell)?;
        let render = self.draw(prepared, cell, &plan, frames, warmup)?;
        Ok((plan, render))
    }

    /// Render one planned cell: `warmup` untimed frames, then `frames` timed ones; the last is
    /// read back.
    pub fn draw(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
        frames: u32,
        warmup: u32,
    ) -> Result<CellRender, Error> {
        self.draw_frames(prepared, cell, plan, frames, warmup, false, FrameMode::IMAGE)
    }

    /// One frame of a planned cell whose timings nobody reads (`plan::timing`: a cell timed as
    /// another of its class). A pass whose output is still in its targets from the cell before is
    /// left out, each keyed by exactly what it reads: the shadow maps (every layer's matrix, the
    /// casting meshes and their transforms; materials, the camera and the sliders do not reach
    /// them), the depth prepass and SSAO (the camera and every mesh's transform), and on forward
    /// paths the fixed objects and background (everything but the subject), over which the
    /// subject alone is drawn. The image is the same bytes (`--no-reuse` draws everything).
    pub fn draw_untimed(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
    ) -> Result<CellRender, Error> {
        let reuse = self.reuse;
        self.draw_frames(prepared, cell, plan, 1, 0, reuse, FrameMode::IMAGE)
    }

    #[allow(clippy::too_many_arguments)]
    fn draw_frames(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
        frames: u32,
        warmup: u32,
        reuse: bool,
        mode: FrameMode,
    ) -> Result<CellRender, Error> {
        let terms = mode.terms;
        self.pipelines.terms = terms;
        // The read-back image is the last frame's: with no frame drawn it would be black, or the
        // cell before's pixels left in the target.
        let Some(total) = warmup.checked_add(frames).filter(|_| frames > 0) else {
            return Err(Error::Other(format!(
                "no frame to render: {frames} timed frames after {warmup} warm-up frames"
            )));
        };
        let fixed_model = self.fixed_model(cell.pipeline)?;
        let subject_model = cell.model;
        let deferred = cell.settings.path == RenderPath::Deferred;
        let vertex_lit = cell.settings.path == RenderPath::VertexLit;
        let samples = plan.multisampling.samples;
        let textured = cell.settings.material_maps.is_some();
        // Fixed objects with maps of their own (materials::fixed) draw with pipelines that sample
        // them; the depth-normal prepass draws every object with one pipeline.
        let fixed_textured = prepared.fixed_maps.any();
        let prepass_textured = textured || fixed_textured;
        let exact = cell.settings.exact;
        if exact.any() && (deferred || vertex_lit || subject_model.per_vertex || fixed_model.per_vertex) {
            return Err(Error::Other(format!(
                "exact alternatives are for per-pixel forward shading; {}/{} on the {} path has none",
                cell.pipeline.name(),
                subject_model.name,
                cell.settings.path.name()
            )));
        }
        // Forward draws (on a deferred path, of the objects drawn after the lighting): each
        // model's one draw or ForwardBase, and its ForwardAdd where it has additive passes.
        let engine = &cell.settings.engine;
        // A ForwardAdd pipeline only where the plan draws one (with no extra pixel light the
        // base pass is the whole of it).
        let adds = |subject: bool| {
            plan.draws
                .forward_add
                .iter()
                .zip(&prepared.layout.meshes)
                .any(|(lights, m)| !lights.is_empty() && (m.role == Role::Subject) == subject)
        };
        let forward_keys = |model: &ShaderModel, textured: bool, subject: bool, surface: SurfaceType| {
            let deferrable = if subject { cell.subject_deferrable() } else { model.deferrable() };
            let additive = additive_passes(cell.pipeline, cell.settings.path, model, deferrable, engine);
            let draw = ForwardKey {
                vertex_lit,
                samples,
                textured,
                exact,
                pass: if additive { ForwardPass::Base } else { ForwardPass::All },
                additional_shadows: shadowed_by_additional_lights(cell.pipeline, model),
                surface,
                face: RenderFace::Front,
                terms,
            };
            (draw, (additive && adds(subject)).then_some(ForwardKey { pass: ForwardPass::Add, ..draw }))
        };
        let subject_keys = forward_keys(subject_model, textured, true, cell.settings.surface.kind);
        let fixed_keys = forward_keys(&fixed_model, fixed_textured, false, SurfaceType::Opaque);
        // Each role's pipelines for the render faces its meshes have (plan::cell::MeshSlot).
        let subject_faces = faces_of(&prepared.layout, |m| m.role == Role::Subject);
        let fixed_faces = faces_of(&prepared.layout, |m| m.role == Role::Fixed);
        let prepass_faces = faces_of(&prepared.layout, |_| true);
        for (model, (draw, add), faces) in
            [(subject_model, subject_keys, &subject_faces), (&*fixed_model, fixed_keys, &fixed_faces)]
        {
            for key in std::iter::once(draw).chain(add) {
                for &face in faces {
                    self.pipelines.forward_pipeline(&self.gpu, cell.pipeline, model, ForwardKey { face, ..key })?;
                }
            }
        }
        if deferred {
            let deferred = [(subject_model, cell.subject_deferrable()), (&*fixed_model, fixed_model.deferrable())];
            for ((model, into_gbuffer), role) in deferred.into_iter().zip([ROLE_SUBJECT, ROLE_FIXED]) {
                let (maps, faces) =
                    if role == ROLE_SUBJECT { (textured, &subject_faces) } else { (fixed_textured, &fixed_faces) };
                for &face in faces.iter().filter(|_| into_gbuffer) {
                    self.pipelines.gbuffer_pipeline(&self.gpu, cell.pipeline, model, maps, face)?;
                }
            }
            for (model, role) in lighting_draws(subject_model, cell.subject_deferrable(), &fixed_model) {
                self.pipelines.lighting_pipeline(&self.gpu, cell.pipeline, model, role)?;
            }
        }
        let background = prepared.plan.background;
        if background {
            self.pipelines.background_pipeline(&self.gpu, samples)?;
        }
        let bakes_before = prepared.bakes.lock().unwrap_or_else(|e| e.into_inner()).len();
        let baked = self.baked_lighting(prepared, cell, plan, &fixed_model)?;
        let made_bake = prepared.bakes.lock().unwrap_or_else(|e| e.into_inner()).len() > bakes_before;
        if let Some(b) = &baked {
            prepared.lightmap_texture.hold(&self.gpu.queue, b);
        }
        let written = write_uniforms(&self.gpu.queue, prepared, cell, plan, &fixed_model, baked.as_deref());
        let frame_group = self.bindings.frame_group(&self.gpu, prepared, cell.settings.material_maps)?;
        let cutout_group = self.cutout_shadow_group(prepared, cell, plan);
        let probe_times = self.capture_probes(prepared, cell, &fixed_model, plan, &written, cutout_group.as_ref())?;
        let (drawn, casting) = (plan.drawn(), plan.casting());
        // The depth prepass draws the opaque queues only: a transparent subject writes no depth.
        let prepass_drawn: Vec<bool> = drawn
            .iter()
            .zip(&prepared.layout.meshes)
            .map(|(d, m)| *d && !(m.role == Role::Subject && cell.settings.surface.kind.is_transparent()))
            .collect();
        let rays = if exact.any() { Some(self.ray_scene(prepared, casting.clone())?) } else { None };
        let shadow_key = written.shadow_key;
        let frame_group: &wgpu::BindGroup = &frame_group;
        self.targets(cell.width, cell.height);
        self.targets.as_mut().expect("targets exist").ensure_msaa(&self.gpu.device, samples);
        let blooms = plan.has(Pass::Bloom) && mode.post;
        if blooms {
            if self.bloom.is_none() {
                self.bloom = Some(crate::render::passes::bloom::BloomPipeline::new(&self.gpu)?);
            }
            let t = self.targets.as_mut().expect("targets exist");
            if t.bloom.is_none() {
                let pipeline = self.bloom.as_ref().expect("just made");
                t.bloom = Some(crate::render::passes::bloom::BloomChain::new(
                    &self.gpu.device,
                    pipeline,
                    &t.color,
                    (t.width, t.height),
                    crate::render::passes::bloom::BloomSettings::default(),
                ));
            }
        }
        let occludes = plan.has(Pass::Ssao);
        if occludes {
            for &face in &prepass_faces {
                self.pipelines.depth_normal_pipeline(&self.gpu, cell.pipeline, &fixed_model, prepass_textured, face)?;
            }
            if self.ssao.is_none() {
                self.ssao = Some(crate::render::passes::ssao::SsaoPipeline::new(&self.gpu)?);
            }
            let t = self.targets.as_mut().expect("targets exist");
            if t.ssao.is_none() {
                let pipeline = self.ssao.as_ref().expect("just made");
                let (chain, _) = crate::render::passes::ssao::SsaoChain::new(
                    &self.gpu.device,
                    pipeline,
                    (t.width, t.height),
                    Some(&t.depth_view),
                    None,
                );
                let group = screen_group(&self.gpu.device, &self.screen_layout, &chain.visibility);
                t.ssao = Some((chain, group));
            }
            let (chain, _) = t.ssao.as_ref().expect("just made");
            let settings = super::passes::ssao::SsaoSettings::default();
            chain.write_frame(
                &self.gpu.queue,
                &super::passes::ssao::SsaoFrame::new(&plan.camera, t.width, t.height, &settings),
            );
        }
        // The prepass and SSAO read the camera, the meshes drawn and their transforms, and the
        // subject's normal map.
        let ssao_key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::hash::DefaultHasher::new();
            (written.prepass_key, cell.pipeline, cell.width, cell.height, &prepass_drawn).hash(&mut h);
            cell.settings.material_maps.hash(&mut h);
            h.finish()
        };
        let occludes_now = occludes && {
            let t = self.targets.as_mut().expect("targets exist");
            // Traced visibility reads the prepass depth itself.
            let kept = reuse && !exact.any() && t.ssao_holds == Some(ssao_key);
            t.ssao_holds = Some(ssao_key);
            !kept
        };
        if exact.visibility {
            if !self.traced_shadows.contains_key(&cell.pipeline) {
                let id = cell.pipeline.shader_id();
                let p = crate::render::passes::traced_shadows::TracedShadowsPipeline::new(
                    &self.gpu,
                    &self.bindings.layout,
                    &self.ray_layout,
                    id,
                )?;
                self.traced_shadows.insert(cell.pipeline, p);
            }
            for &face in &prepass_faces {
                self.pipelines.depth_normal_pipeline(&self.gpu, cell.pipeline, &fixed_model, prepass_textured, face)?;
            }
            let t = self.targets.as_mut().expect("targets exist");
            if t.traced.is_none() {
                t.traced = Some(crate::render::passes::traced_shadows::TracedShadowMask::new(
                    &self.gpu.device,
                    (t.width, t.height),
                ));
            }
        }
        // The timed passes of a frame, in order: one span over the shadow layers, then the path's passes.
        // The vertex-lit path has no shadows (Unity's legacy vertex-lit renders none); traced
        // visibility needs no shadow maps.
        // The vertex-lit path's plan has no shadow pass (Unity's legacy vertex-lit renders none).
        let shadows = plan.has(Pass::Shadow);
        let shadows = {
            let mut holds = prepared.shadows.holds.lock().unwrap_or_else(|e| e.into_inner());
            let kept = shadows && reuse && *holds == Some(shadow_key);
            if shadows {
                *holds = Some(shadow_key);
            }
            shadows && !kept
        };
        // The passes this frame runs: the plan's, less what runs before the frames, the
        // post-processing a term layer leaves out and what an untimed cell keeps from the cell before.
        let pass_names: Vec<Pass> = plan
            .passes
            .iter()
            .filter(|p| !p.before_frames() && (mode.post || !p.post()))
            .filter(|p| match p {
                Pass::Shadow => shadows,
                Pass::Ssao => occludes_now,
                Pass::DepthPrepass => occludes_now || exact.visibility,
                _ => true,
            })
            .copied()
            .collect();
        let tile_group = if plan.has(Pass::LightTiles) {
            Some(self.prepare_light_tiles(cell, prepared.scene.lights.len())?)
        } else {
            None
        };
        // An untimed forward frame whose fixed objects and background read what the last layer's
        // did draws the subject alone over a copy of that layer (passes::forward). Some(true):
        // the layer is drawn first.
        let has_fixed = drawn.iter().zip(&prepared.layout.meshes).any(|(d, m)| *d && m.role == Role::Fixed);
        let layer = if reuse && !deferred && !exact.any() && has_fixed && total == 1 {
            let key = {
                use std::hash::{Hash, Hasher};
                let mut h = std::hash::DefaultHasher::new();
                (written.layer_key, shadow_key, occludes.then_some(ssao_key), terms).hash(&mut h);
                (cell.pipeline, cell.settings.path, cell.width, cell.height, fixed_keys, background).hash(&mut h);
                let fixed = |i: &usize| prepared.layout.meshes[*i].role == Role::Fixed;
                for i in (0..drawn.len()).filter(fixed) {
                    (drawn[i], &plan.draws.forward_add[i]).hash(&mut h);
                }
                h.finish()
            };
            let layer = self.targets.as_mut().expect("targets exist").ensure_layer(&self.gpu.device, samples);
            let build = layer.key != Some(key);
            layer.key = Some(key);
            Some(build)
        } else {
            None
        };
        let per_frame = pass_names.len() as u32;
        if self.gpu.record.timestamp_queries && self.timer.as_ref().is_none_or(|t| t.capacity() < frames * per_frame) {
            self.timer = Some(PassTimer::new(&self.gpu.device, &self.gpu.queue, frames * per_frame));
        }
        let timer = self.timer.as_ref().filter(|_| self.gpu.record.timestamp_queries);
        let t = self.targets.as_ref().expect("targets exist");
        let forward_targets = ForwardTargets::of(t, samples);
        let ssao = t.ssao.as_ref().filter(|_| occludes);
        let screen = ssao.map_or(&self.neutral_screen, |(_, group)| group);
        // The rays' group for the traced-shadow pass (no mask) and for the forward pass (reading
        // the traced mask where visibility is traced).
        let rays = rays.map(|scene| {
            let forward = match t.traced.as_ref().filter(|_| exact.visibility) {
                Some(traced) => scene.group_with_mask(&self.gpu.device, &self.ray_layout, &traced.mask),
                None => scene.group.clone(),
            };
            (scene.group.clone(), forward)
        });
        let mut frame_ms = Vec::with_capacity(frames as usize);
        for f in 0..total {
            let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
            // Pair of timed pass k in this frame; None for warm-up frames.
            let timed = |k: u32| timer.filter(|_| f >= warmup).map(|t| (t, (f - warmup) * per_frame + k));
            let mut k = 0;
            if shadows {
                let cutout = self.cutout_shadow.as_ref().zip(cutout_group.as_ref()).map(|(c, g)| (&c.pipeline, g));
                encode_shadow_passes(
                    &mut encoder,
                    &self.shadow_pipeline,
                    prepared,
                    (&plan.used_layers, &casting, &plan.dynamic_casters_only),
                    cutout,
                    timed(k),
                );
                k += 1;
            }
            if let (Some((chain, _)), Some(steps), true) = (ssao, &self.ssao, occludes_now) {
                let prepass = prepass_by_face(&self.pipelines, cell.pipeline, prepass_textured, &prepass_faces);
                let draw = FrameDraw { group: frame_group, drawn: &prepass_drawn, screen: &self.neutral_screen };
                encode_depth_prepass(&mut encoder, prepared, &draw, prepass, (&chain.normal, &t.depth_view), timed(k));
                chain.encode(steps, &mut encoder, timed(k + 1).map(|(t, pair)| t.compute_writes(pair)));
                k += 2;
            }
            if let (Some(traced), Some(rays)) = (t.traced.as_ref().filter(|_| exact.visibility), &rays) {
                let normal = match ssao {
                    Some((chain, _)) => &chain.normal,
                    None => {
                        let prepass = prepass_by_face(&self.pipelines, cell.pipeline, prepass_textured, &prepass_faces);
                        let draw =
                            FrameDraw { group: frame_group, drawn: &prepass_drawn, screen: &self.neutral_screen };
                        encode_depth_prepass(
                            &mut encoder,
                            prepared,
                            &draw,
                            prepass,
                            (&traced.normal, &t.depth_view),
                            timed(k),
                        );
                        k += 1;
                        &traced.normal
                    }
                };
                traced.encode(
                    &self.gpu.device,
                    &self.traced_shadows[&cell.pipeline],
                    &mut encoder,
                    frame_group,
                    &rays.0,
                    (&t.depth_view, normal),
                    timed(k).map(|(t, pair)| t.compute_writes(pair)),
                );
                k += 1;
            }
            let model_pipelines =
                |model: &ShaderModel, (draw, add): (ForwardKey, Option<ForwardKey>), faces: &[RenderFace]| {
                    let by_face = |key| self.pipelines.forward_by_face(cell.pipeline, &model.name, key, faces);
                    ModelPipelines { draw: by_face(draw), add: add.map(by_face) }
                };
            let pipelines = ForwardPipelines {
                subject: model_pipelines(subject_model, subject_keys, &subject_faces),
                fixed: model_pipelines(&fixed_model, fixed_keys, &fixed_faces),
                background: self.pipelines.background.get(&(samples, terms)).filter(|_| background && !deferred),
                rays: rays.as_ref().map(|(_, group)| group),
            };
            if deferred {
                let timed: Vec<_> = (k..per_frame).map(timed).collect();
                encode_deferred(
                    &mut encoder,
                    prepared,
                    FrameDraw { group: frame_group, drawn: &drawn, screen },
                    cell,
                    &fixed_model,
                    tile_group.as_ref(),
                    &timed,
                    (t, &self.pipelines, &self.tiles),
                    (&pipelines, &plan.draws.forward_add),
                );
            } else {
                let draw = FrameDraw { group: frame_group, drawn: &drawn, screen };
                let adds = &plan.draws.forward_add;
                let part = match (layer, t.layer.as_ref()) {
                    (Some(build), Some(l)) => {
                        if build {
                            let into = ForwardTargets::layer(&l.targets);
                            let part = ForwardDraw::FixedLayer;
                            encode_forward(&mut encoder, prepared, &draw, &pipelines, adds, &into, part, None);
                        }
                        t.restore_layer(&mut encoder, samples);
                        ForwardDraw::SubjectOver
                    }
                    _ => ForwardDraw::Whole,
                };
                encode_forward(&mut encoder, prepared, &draw, &pipelines, adds, &forward_targets, part, timed(k));
            }
            if let (true, Some(chain), Some(pipeline)) = (blooms, &t.bloom, &self.bloom) {
                chain.encode(pipeline, &mut encoder, timed(per_frame - 1).map(|(t, pair)| t.compute_writes(pair)));
            }
            let last = f + 1 == total;
            if last {
                let frame = match (&t.bloom, blooms) {
                    (Some(chain), true) => &chain.output,
                    _ => &t.color,
                };
                t.color_readback.encode_copy(&mut encoder, frame);
                t.role_readback.encode_copy(&mut encoder, &t.role);
                if let Some(timer) = timer {
                    timer.encode_resolve(&mut encoder, frames * per_frame);
                }
            }
            let start = Instant::now();
            self.gpu.queue.submit([encoder.finish()]);
            self.gpu.wait_idle()?;
            if f >= warmup {
                frame_ms.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        let read_start = Instant::now();
        let hdr_bytes = t.color_readback.read(&self.gpu.device)?;
        let roles = t.role_readback.read(&self.gpu.device)?;
        let readback_ms = read_start.elapsed().as_secs_f64() * 1e3;
        let pairs = timer.map(|t| t.read_ms(&self.gpu.device, frames * per_frame)).transpose()?;
        let gpu_pass_ms =
            pairs.as_ref().map(|p| p.chunks(per_frame as usize).map(|frame| frame.iter().sum()).collect());
        let gpu_passes = pairs.as_ref().map(|p| {
            // The probe captures once per set of inputs, before the frames: not part of a frame's
            // time. Every pass in the plan's order.
            let once =
                [(Pass::ProbeCapture, probe_times.map(|t| t.0)), (Pass::ProbePrefilter, probe_times.map(|t| t.1))];
            let mut passes: Vec<(Pass, Vec<f64>)> =
                once.into_iter().filter_map(|(pass, ms)| ms.map(|ms| (pass, vec![ms]))).collect();
            passes.extend(
                pass_names
                    .iter()
                    .enumerate()
                    .map(|(k, pass)| (*pass, p.iter().skip(k).step_by(per_frame as usize).copied().collect())),
            );
            passes
        });
        self.gpu.check_errors("rendering a cell")?;
        Ok(CellRender {
            width: cell.width,
            height: cell.height,
            hdr: bytemuck::cast_slice(&hdr_bytes).to_vec(),
            roles,
            frame_ms,
            gpu_pass_ms,
            gpu_passes,
            readback_ms,
            terms: None,
            bake: plan.gi.as_ref().map(|g| match &baked {
                Some(b) => crate::render::gi::BakeUse {
                    plan: g.clone(),
                    made: made_bake,
                    cached: b.cached,
                    seconds: b.seconds,
                    samples: b.samples,
                    texel_samples: b.texel_samples,
                    noise_target: b.noise_target,
                    bounces: b.bounces,
                    lightmap: b.lightmap.as_ref().map(|m| {
                        let covered = prepared.lightmap.as_ref().map_or(0, |a| a.texels.len());
                        ([m.width, m.height], covered, m.noise)
                    }),
                    probes: b.probes.as_ref().map_or(0, Vec::len),
                    encoding: crate::render::gi::lightmaps::LightmapEncoding::of_quality(g.encoding).name(),
                },
                None => crate::render::gi::BakeUse {
                    plan: g.clone(),
                    made: false,
                    cached: false,
                    seconds: 0.0,
                    samples: 0,
                    texel_samples: 0,
                    noise_target: 0.0,
                    bounces: g.bounces,
                    lightmap: None,
                    probes: 0,
                    encoding: crate::render::gi::lightmaps::LightmapEncoding::of_quality(g.encoding).name(),
                },
            }),
        })
    }

    /// The shadow pass's material group for a cell whose subject is a textured cutout that casts
    /// (its shadow clipped by its alpha map, passes::shadow); None for every other cell.
    fn cutout_shadow_group(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
    ) -> Option<wgpu::BindGroup> {
        let surface = &cell.settings.surface;
        let casts = prepared.plan.shadows() && !plan.used_layers.is_empty();
        if surface.kind != SurfaceType::Cutout || cell.settings.material_maps.is_none() || !casts {
            return None;
        }
        if self.cutout_shadow.is_none() {
            self.cutout_shadow = Some(CutoutShadow::new(&self.gpu, &self.shadow_layer_layout, &self.object_layout));
        }
        let albedo = self.bindings.albedo_view(prepared, cell.settings.material_maps)?;
        let shadow = self.cutout_shadow.as_ref().expect("just made");
        Some(shadow.group(
            &self.gpu,
            (surface.alpha as f32, surface.cutoff as f32),
            albedo,
            &self.bindings.material_sampler,
        ))
    }

    /// The tiled light loop for a frame: its compute pipeline, room for the masks, and the compute
    /// pass's bind group on this frame's depth.
    fn prepare_light_tiles(&mut self, cell: &CellParams, lights: usize) -> Result<wgpu::BindGroup, Error> {
        if self.tiles.pipeline.is_none() {
            let model = self
                .fixed_models
                .find(Pipeline::Hdrp, Pipeline::Hdrp.fixed_object_shader())
                .cloned()
                .ok_or_else(|| Error::Other("HDRP lacks its fixed-object shader".into()))?;
            let source = wgsl::compose(wgsl::PassKind::Forward, Some(&model));
            let module = self.gpu.shader_module(crate::plan::Pass::LightTiles.name(), &source)?;
            let pipeline = self.gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(crate::plan::Pass::LightTiles.name()),
                layout: Some(&self.tiles.compute_layout),
                module: &module,
                entry_point: Some("cs_light_tiles"),
                compilation_options: Default::default(),
                cache: None,
            });
            self.gpu.check_errors("creating the light-tile pipeline")?;
            self.tiles.pipeline = Some(pipeline);
        }
        let (tx, ty, words) = crate::render::gbuffer::tile_grid(cell.width, cell.height, lights);
        self.tiles.reserve(&self.gpu.device, (tx * ty * words) as u64 * 4);
        let t = self.targets.as_ref().expect("targets exist");
        Ok(self.tiles.write_group(&self.gpu.device, &t.depth_view))
    }

    /// Render every probe's faces (the fixed objects and the sky seen from the probe, lit as the
    /// cell lights them, reflecting the sky alone) and prefilter them, unless the last capture saw
    /// the same inputs. Returns the GPU time of the capture and of the prefilter, ms, that made
    /// the levels the cell reads (None: no probes, or no timestamp queries).
    fn capture_probes(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        fixed_model: &ShaderModel,
        plan: &CellPlan,
        written: &WrittenFrame,
        cutout: Option<&wgpu::BindGroup>,
    ) -> Result<Option<(f64, f64)>, Error> {
        let Some(probes) = &prepared.probes else { return Ok(None) };
        let slot = probes.slot_for(written.capture_key, self.reuse);
        // Point the cell's frame at the slot's levels.
        let mut frame = written.frame;
        let count = probes.probes.len();
        for (k, t) in probes.probes.iter().enumerate() {
            frame.probes[k] = GpuReflectionProbe::new(&t.probe, k, count, slot.index());
        }
        self.gpu.queue.write_buffer(&prepared.frame_buffer, 0, bytemuck::bytes_of(&frame));
        let slot = match slot {
            crate::render::passes::probes::Slot::ToCapture(slot) => slot,
            crate::render::passes::probes::Slot::Captured(slot) => return Ok(probes.capture_times(slot)),
        };
        let faces = faces_of(&prepared.layout, |m| m.role == Role::Fixed);
        let key = ForwardKey::plain(prepared.fixed_maps.any(), RenderFace::Front);
        for &face in &faces {
            self.pipelines.forward_pipeline(&self.gpu, cell.pipeline, fixed_model, ForwardKey { face, ..key })?;
        }
        if prepared.plan.background {
            // Probes capture the whole light, whatever the frame being drawn holds.
            let terms = std::mem::replace(&mut self.pipelines.terms, crate::pipelines::terms::LIGHT);
            let made = self.pipelines.background_pipeline(&self.gpu, 1);
            self.pipelines.terms = terms;
            made?;
        }
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        self.bindings
            .material_textures
            .entry("")
            .or_insert_with(|| crate::render::material_maps::MaterialTextures::neutral(device, queue));
        if self.gpu.record.timestamp_queries && self.probe_timer.is_none() {
            self.probe_timer = Some(PassTimer::new(&self.gpu.device, &self.gpu.queue, 2));
        }
        let timer = self.probe_timer.as_ref().filter(|_| self.gpu.record.timestamp_queries);
        let pipelines = self.pipelines.forward_by_face(cell.pipeline, &fixed_model.name, key, &faces);
        let background =
            self.pipelines.background.get(&(1, crate::pipelines::terms::LIGHT)).filter(|_| prepared.plan.background);
        let neutral = &self.bindings.material_textures[""];
        let (drawn, casting) = (plan.drawn(), plan.casting());
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        // The capture is lit as the composition's frames are, whatever the cell's path: a
        // vertex-lit cell draws no shadow pass itself, but the probes it reads hold shadows.
        if prepared.plan.shadows() && !plan.used_layers.is_empty() {
            let cutout = self.cutout_shadow.as_ref().zip(cutout).map(|(c, g)| (&c.pipeline, g));
            let layers = (&plan.used_layers[..], &casting[..], &plan.dynamic_casters_only[..]);
            encode_shadow_passes(&mut encoder, &self.shadow_pipeline, prepared, layers, cutout, None);
            // The probe's own layers now: a cell cannot keep what it finds there.
            *prepared.shadows.holds.lock().unwrap_or_else(|e| e.into_inner()) = None;
        }
        let faces = probes.probes.len() * 6;
        let mut face = 0;
        let mut groups = Vec::with_capacity(faces);
        for t in &probes.probes {
            for (f, vp) in t.view_proj.iter().enumerate() {
                let mut seen = written.frame;
                seen.view_proj = mat(*vp);
                seen.inv_view_proj = mat(vp.inverse());
                seen.camera_pos = vec4(DVec3::from(t.probe.position), 1.0);
                // The captured objects reflect the sky alone (one bounce, Unity's default).
                seen.reflection = [0; 4];
                self.gpu.queue.write_buffer(&t.frame_buffers[f], 0, bytemuck::bytes_of(&seen));
                groups.push(self.bindings.frame_bind_group(&self.gpu.device, prepared, &t.frame_buffers[f], neutral));
            }
        }
        for t in &probes.probes {
            for f in 0..6 {
                // One span over every face: begin at the first pass, end at the last.
                let (first, last) = (face == 0, face + 1 == faces);
                let timestamps = timer.filter(|_| first || last).map(|tm| tm.writes(0, first, last));
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(crate::plan::Pass::ProbeCapture.name()),
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
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Discard,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: timestamps,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_bind_group(0, &groups[face], &[]);
                pass.set_bind_group(2, &self.neutral_screen, &[]);
                // The subject is left out: a dynamic object, which baked probes do not see.
                let fixed = |i: usize| drawn[i] && prepared.layout.meshes[i].role == Role::Fixed;
                for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| fixed(*i)) {
                    let face = prepared.layout.meshes[i].render_face as usize;
                    pass.set_pipeline(pipelines[face].expect("a pipeline for every face drawn"));
                    pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
                    pass.set_vertex_buffer(0, o.vertices.slice(..));
                    pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..o.index_count, 0, 0..1);
                }
                if let Some(bg) = background {
                    pass.set_pipeline(bg);
                    pass.draw(0..3, 0..1);
                }
                face += 1;
            }
        }
        let prefilter = self.prefilter.as_ref().expect("made with the scene's probes");
        let weight = crate::environment::filtered::LobeWeight::of_pipeline(cell.pipeline);
        probes.encode_prefilter(prefilter, &mut encoder, (slot, weight), timer.map(|t| t.compute_writes(1)));
        if let Some(t) = timer {
            t.encode_resolve(&mut encoder, 2);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait_idle()?;
        let times = timer.map(|t| t.read_ms(&self.gpu.device, 2)).transpose()?;
        self.gpu.check_errors("capturing reflection probes")?;
        let times = times.map(|t| (t[0], t[1]));
        probes.captured(slot, written.capture_key, times);
        Ok(times)
    }

    /// The targets of `width`×`height` frames, made when the size changes.
    fn targets(&mut self, width: u32, height: u32) -> &Targets {
        if self.targets.as_ref().is_none_or(|t| t.width != width || t.height != height) {
            self.targets = Some(Targets::new(&self.gpu.device, &self.gbuffer_read_layout, (width, height)));
        }
        self.targets.as_ref().expect("just made")
    }

    /// The scene as rays see it (render::truth::TruthScene): the meshes `kept` (the ones the frame
    /// draws: LOD levels change them) in a BVH with the environment's tables and irradiance. Built
    /// for the first cell that traces or asks for an exact alternative, rebuilt only when a cell
    /// keeps other meshes.
    fn ray_scene(
        &self,
        prepared: &PreparedScene,
        kept: Vec<bool>,
    ) -> Result<std::sync::Arc<crate::render::truth::TruthScene>, Error> {
        let scene = &prepared.scene;
        let env = prepared.env_table.get_or_init(|| {
            crate::render::truth::TruthEnvironment::new(&self.gpu.device, self.gpu.constants, &truth_sky(scene))
        });
        let cached = prepared.truth_geometry.lock().unwrap_or_else(|e| e.into_inner()).clone();
        Ok(match cached {
            Some((k, g)) if k == kept => g,
            _ => {
                let g = truth_geometry(prepared, &kept)?;
                let g = std::sync::Arc::new(crate::render::truth::TruthScene::new(
                    &self.gpu.device,
                    &self.ray_layout,
                    &g,
                    env,
                ));
                *prepared.truth_geometry.lock().unwrap_or_else(|e| e.into_inner()) = Some((kept, g.clone()));
                g
            }
        })
    }
}

/// A material map of the frame group, sampled by both stages (the vertex-lit path reads them) and
/// by the truth's tracer.
/// The depth prepass's pipelines for the faces drawn.
fn prepass_by_face<'a>(
    pipelines: &'a PipelineCache,
    pipeline: Pipeline,
    textured: bool,
    faces: &[RenderFace],
) -> ByFace<'a> {
    let mut out: ByFace = [None; 3];
    for &face in faces {
        out[face as usize] = Some(&pipelines.depth_normals[&(pipeline, textured, face)]);
    }
    out
}

fn material_map_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// A read-only storage buffer of the frame group, seen by both stages (vertex lights read it).
fn storage_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE),
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}
