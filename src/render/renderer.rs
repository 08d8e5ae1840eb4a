//! The renderer: device-lifetime state (layouts, samplers, compiled pipelines, targets) and the
//! frame loop that runs the passes a cell's plan lists (`plan::cell::CellPlan`), each encoded by
//! its file in `passes/`. Everything that does not change between cells is built once: pipelines
//! per (pipeline convention, model) in `pipeline_cache`, meshes and the environment per
//! composition in `prepared`, render targets per image size in `targets`. A cell rewrites its
//! uniforms (`cell_uniforms`) and draws.

use std::collections::HashMap;

use super::frame_bindings::FrameBindings;
use super::passes::ssao::neutral_screen_group;
use super::pipeline_cache::PipelineCache;
use super::prepared::PreparedScene;
use crate::declarations::scene::Scene;
use crate::error::Error;
use crate::geometry::procedural;
use crate::geometry::Mesh;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
use crate::pipelines::Pipeline;
pub use crate::plan::cell::{CellParams, CellPlan, CellSettings, MsaaSupport, Multisampling};
pub use crate::plan::lod::LodUse;
pub use crate::plan::ShadowMapUse;
use crate::plan::{FramePlan, Pass};
use crate::render::cell_uniforms::write_uniforms;
use crate::render::formats::{DEPTH_FORMAT, HDR_FORMAT, ROLE_FORMAT};
use crate::render::targets::Targets;
use crate::render::uniforms::*;
use crate::shading::{Registry, ShaderModel};

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
    pub(in crate::render) object_layout: wgpu::BindGroupLayout,
    /// Group 0 of the scene passes: the frame's layout, samplers, tables and material maps.
    pub(in crate::render) bindings: FrameBindings,
    /// Every render pipeline compiled so far.
    pub(in crate::render) pipelines: PipelineCache,
    /// Fixed objects are drawn with each pipeline's default lit shader, a built-in model.
    fixed_models: Registry,
    gbuffer_read_layout: wgpu::BindGroupLayout,
    /// The frame's targets, and how many were made (each new size makes new ones).
    pub(in crate::render) targets: Option<Targets>,
    targets_made: u64,
    /// The frames' timestamp pairs.
    pub(in crate::render) timer: Option<PassTimer>,
    /// The sample counts the adapter multisamples and resolves the forward targets with.
    msaa_counts: Vec<u32>,
    /// Group 2 of the scene passes: the screen-space occlusion the lighting reads.
    pub(in crate::render) screen_layout: wgpu::BindGroupLayout,
    /// A 1×1 visibility of 1, for cells and captures without SSAO.
    pub(in crate::render) neutral_screen: wgpu::BindGroup,
    /// Each pass's own state (`passes/`).
    pub(in crate::render) shadow: crate::render::passes::shadow::ShadowPass,
    pub(in crate::render) probes: crate::render::passes::probe_capture::ProbeCapture,
    pub(in crate::render) ssao: crate::render::passes::ssao::SsaoPass,
    pub(in crate::render) urp_ssao: crate::render::passes::urp_ssao::UrpSsaoPass,
    pub(in crate::render) tiles: crate::render::passes::light_tiles::LightTiles,
    pub(in crate::render) traced: crate::render::passes::traced_shadows::TracedShadowsPass,
    pub(in crate::render) bloom: crate::render::passes::bloom::BloomPass,
    pub(in crate::render) subsurface: crate::render::passes::subsurface::SubsurfacePass,
    /// The truth's tracers, by (pipeline, subject model, fixed model).
    truth_pipelines:
        HashMap<(Pipeline, String, String, crate::render::truth::TruthKind), crate::render::truth::TruthPipeline>,
    /// Group 3 of the tracer and of the exact alternatives: the scene as rays see it.
    pub(in crate::render) ray_layout: wgpu::BindGroupLayout,
    /// Whether an untimed cell may take a pass's output from the cell before when the pass's
    /// inputs are the same (`--no-reuse`: false); probe captures likewise.
    pub reuse: bool,
    /// Bakes kept across runs (render::gi::cache); None: each run bakes its own.
    pub bake_cache: Option<crate::render::gi::cache::BakeCache>,
}

impl Renderer {
    pub fn new(gpu: GpuContext) -> Renderer {
        let device = &gpu.device;
        let bindings = FrameBindings::new(&gpu);
        let frame_layout = &bindings.layout;
        let object_layout = super::resources::uniform_slot_layout(
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
            bind_group_layouts: &[Some(frame_layout), Some(&object_layout), Some(&screen_layout)],
            immediate_size: 0,
        });
        let ray_layout = crate::render::truth::ray_layout(device, gpu.constants);
        let exact_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene with rays"),
            bind_group_layouts: &[Some(frame_layout), Some(&object_layout), Some(&screen_layout), Some(&ray_layout)],
            immediate_size: 0,
        });
        let neutral_screen = neutral_screen_group(&gpu, &screen_layout);
        let shadow = crate::render::passes::shadow::ShadowPass::new(&gpu, &object_layout);
        let gbuffer_read_layout = crate::render::gbuffer::read_layout(device);
        let tiles = crate::render::passes::light_tiles::LightTiles::new(device, frame_layout);
        let deferred_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(crate::plan::Pass::DeferredLighting.name()),
            bind_group_layouts: &[
                Some(frame_layout),
                Some(&object_layout),
                Some(&gbuffer_read_layout),
                Some(&tiles.read_layout),
            ],
            immediate_size: 0,
        });
        let msaa_counts = gpu.multisample_counts(&[HDR_FORMAT, ROLE_FORMAT, DEPTH_FORMAT]);
        Renderer {
            gpu,
            object_layout,
            bindings,
            pipelines: PipelineCache::new(pipeline_layout, exact_layout, deferred_layout),
            fixed_models: Registry::builtin(),
            gbuffer_read_layout,
            targets: None,
            targets_made: 0,
            timer: None,
            msaa_counts,
            screen_layout,
            neutral_screen,
            shadow,
            probes: Default::default(),
            ssao: Default::default(),
            urp_ssao: Default::default(),
            tiles,
            traced: Default::default(),
            bloom: Default::default(),
            subsurface: Default::default(),
            truth_pipelines: HashMap::new(),
            ray_layout,
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
        if probes && self.probes.prefilter.is_none() {
            self.probes.prefilter = Some(crate::render::reflection_probes::Prefilter::new(&self.gpu)?);
        }
        let layouts = (&self.object_layout, &self.shadow.layer_layout);
        PreparedScene::upload(&self.gpu, layouts, self.probes.prefilter.as_ref(), scene, plan, meshes)
    }

    /// The plan of a cell in a prepared composition, on this adapter: computed on the CPU before
    /// any GPU work (`plan::cell`).
    pub fn plan(&self, prepared: &PreparedScene, cell: &CellParams) -> Result<CellPlan, Error> {
        let fixed_model = self.fixed_model(cell.pipeline)?;
        Ok(CellPlan::new(&prepared.scene, &prepared.plan, &prepared.layout, cell, &fixed_model, &self.msaa_support()))
    }

    /// The model each pipeline draws the fixed objects with (its default lit shader).
    pub(in crate::render) fn fixed_model(&self, pipeline: Pipeline) -> Result<std::sync::Arc<ShaderModel>, Error> {
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

    /// The targets of `width`×`height` frames, made when the size changes.
    pub(in crate::render) fn targets(&mut self, width: u32, height: u32) -> &Targets {
        if self.targets.as_ref().is_none_or(|t| t.width != width || t.height != height) {
            self.targets_made += 1;
            let size = (width, height);
            self.targets = Some(Targets::new(&self.gpu.device, &self.gbuffer_read_layout, size, self.targets_made));
        }
        self.targets.as_ref().expect("just made")
    }

    /// The scene as rays see it (render::truth::TruthScene): the meshes `kept` (the ones the frame
    /// draws: LOD levels change them) in a BVH with the environment's tables and irradiance. Built
    /// for the first cell that traces or asks for an exact alternative, rebuilt only when a cell
    /// keeps other meshes.
    pub(in crate::render) fn ray_scene(
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
