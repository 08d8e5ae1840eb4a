//! The renderer. Everything that does not change between cells is built once: pipelines per
//! (pipeline convention, model), meshes and the environment probe per composition, render
//! targets per image size. A cell rewrites two small uniform buffers and draws.

use glam::{DMat4, DVec3, Mat4};
use std::collections::HashMap;
use std::time::Instant;
use wgpu::util::DeviceExt;

use super::camera::{posed_camera, view_projection, ViewAxes};
use super::deferred::GBuffer;
use super::shadows::{array_side, cell_resolution, light_layers, shadow_slot, CascadeView, SHADOW_FORMAT};
use super::targets::{DEPTH_FORMAT, HDR_FORMAT, ROLE_FORMAT};
use super::uniforms::*;
use crate::environment::EnvironmentMaps;
use crate::error::Error;
use crate::geometry::{placement, procedural, Mesh, Vertex};
use crate::gpu::readback::TextureReadback;
use crate::gpu::timing::PassTimer;
use crate::gpu::GpuContext;
use crate::materials::MaterialMaps;
use crate::pipelines::{Antialiasing, Pipeline, RenderPath};
use crate::plan::lights::{assign, sh_of_light, LightBudget, LightMode, ObjectLights};
pub use crate::plan::lod::LodUse;
use crate::plan::FramePlan;
pub use crate::plan::ShadowMapUse;
use crate::shading::registry::Sliders;
use crate::shading::twin::Surface;
use crate::shading::{wgsl, Registry, ShaderModel};
use crate::spec::scene::{LightKind, Role, Scene};

/// The pass name of the study's traced shadows (render::traced_shadows) in timings.
pub const TRACED_SHADOWS_PASS: &str = "traced shadows";

/// What one cell asks of the renderer (no matrix types: the renderer knows scenes, not sweeps).
#[derive(Debug, Clone, Copy)]
pub struct CellParams<'a> {
    pub pipeline: Pipeline,
    pub model: &'a ShaderModel,
    /// The subject's material as the model receives it (`ShaderModel::surface`).
    pub surface: Surface,
    pub light_intensity: f64,
    pub light_range: f64,
    pub width: u32,
    pub height: u32,
    /// Camera distance and light angle, where the cell sets them.
    pub view: ViewAxes,
    /// The rendering path and the light budgets.
    pub settings: CellSettings,
}

/// What a cell sets besides its material and light: the path, the light budgets and MSAA.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CellSettings {
    pub path: RenderPath,
    pub light_budget: LightBudget,
    pub antialiasing: Antialiasing,
    /// The preset whose textured form the subject wears (None: flat).
    pub material_maps: Option<&'static str>,
    /// The emission axis (0: none); the model decides whether it emits.
    pub emission: f64,
    /// The emitted colour the axis scales (linear), where it is not the base colour: a glTF
    /// subject's own `emissiveFactor`.
    pub emission_color: Option<[f64; 3]>,
    /// The approximation study's exact alternatives (none: the pipeline as it ships).
    pub exact: super::exact::ExactAlternatives,
}

/// The samples per pixel a cell rendered with, and why they differ from what it asked, if they do.
#[derive(Debug, Clone, PartialEq)]
pub struct Multisampling {
    pub samples: u32,
    pub note: Option<String>,
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
    /// GPU time of each timed pass per frame, ms, by pass name (`shadow`, `forward`, `gbuffer`,
    /// `deferred lighting`, `forward-only and background`); None without timestamp queries.
    pub gpu_passes: Option<Vec<(String, Vec<f64>)>>,
    /// CPU time to map and copy the image back, ms.
    pub readback_ms: f64,
    /// How each light reached each object.
    pub lights: Vec<ObjectLights>,
    pub multisampling: Multisampling,
    /// Each shadowed light's map resolution in this cell (its pipeline's default unless the scene
    /// sets one); empty when the frame has no shadow pass.
    pub shadow_maps: Vec<ShadowMapUse>,
    /// The LOD levels drawn, per LOD group.
    pub lod: Vec<LodUse>,
}

struct GpuObject {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    role: Role,
    model: DMat4,
    /// Fixed objects: their own material in slider units (mapped per pipeline at draw time) and
    /// their checkerboard.
    fixed: Option<(Sliders, GpuMaterial)>,
    cast_shadows: bool,
    receive_shadows: bool,
    /// The scene object this mesh draws (LOD levels after level 0 are extra meshes of it).
    scene_index: usize,
    /// Its level in the object's LOD group, if it has one.
    lod_level: Option<usize>,
}

/// A composition's shadow maps: the depth array, a view per layer to render into, the layer
/// matrices (a uniform slot per layer for the shadow pass, a storage array for the forward pass).
struct ShadowResources {
    /// Whether the frame has a shadow pass (`FramePlan`); otherwise one unused 1×1 layer is bound.
    active: bool,
    layer_views: Vec<wgpu::TextureView>,
    array_view: wgpu::TextureView,
    layer_uniforms: wgpu::Buffer,
    layer_stride: u64,
    layer_bind_group: wgpu::BindGroup,
    layers_storage: wgpu::Buffer,
    resolution: u32,
    /// Per scene light: its first layer when it casts shadows.
    first_layer: Vec<Option<usize>>,
    /// World-space bounds of every object (directional maps fit them).
    scene_bounds: (DVec3, DVec3),
    /// What the layers hold now (`WrittenFrame::shadow_key`), when a cell's frame rendered them
    /// last; None after anything else did.
    holds: std::sync::Mutex<Option<u64>>,
}

/// The truth's geometry of a composition with the meshes it holds (render::truth::bvh).
type TruthGeometryCache = std::sync::Mutex<Option<(Vec<bool>, std::sync::Arc<super::truth::TruthScene>)>>;

pub struct PreparedScene {
    pub scene: Scene,
    pub plan: FramePlan,
    pub env: EnvironmentMaps,
    objects: Vec<GpuObject>,
    object_buffer: wgpu::Buffer,
    object_stride: u64,
    object_bind_group: wgpu::BindGroup,
    frame_buffer: wgpu::Buffer,
    env_view: wgpu::TextureView,
    /// The scene's reflection probes (`environment.reflections = "probe"`); their levels follow
    /// the sky's in `env_view`.
    probes: Option<super::reflection_probes::SceneProbes>,
    /// The frame bind group per material-map set the subject wears ("" flat), made on first use.
    frame_groups: std::sync::Mutex<HashMap<&'static str, std::sync::Arc<wgpu::BindGroup>>>,
    /// A glTF subject's own material maps (preset `own`), read and uploaded on first use.
    own_textures: std::sync::OnceLock<super::material_maps::MaterialTextures>,
    /// The truth's environment on the GPU, made for the first truth.
    env_table: std::sync::OnceLock<super::truth::TruthEnvironment>,
    /// The truth's geometry on the GPU for the last set of meshes a cell kept (LOD levels change
    /// it), so cells of one composition build the meshes and the BVH and upload them once.
    truth_geometry: TruthGeometryCache,
    lights_buffer: wgpu::Buffer,
    modes_buffer: wgpu::Buffer,
    shadows: ShadowResources,
    /// Each object's name and world-space bounds centre (what the light budget ranks lights by).
    pub object_centres: Vec<(String, DVec3)>,
    pub triangle_count: usize,
    /// Each scene object's world bounds (level 0's mesh): what LOD selection measures.
    world_bounds: Vec<(DVec3, DVec3)>,
}

struct Targets {
    width: u32,
    height: u32,
    gbuffer: GBuffer,
    color: wgpu::Texture,
    role: wgpu::Texture,
    depth_view: wgpu::TextureView,
    color_view: wgpu::TextureView,
    role_view: wgpu::TextureView,
    color_readback: TextureReadback,
    role_readback: TextureReadback,
    /// The forward pass's multisampled targets, when a cell renders with MSAA.
    msaa: Option<MsaaTargets>,
    /// HDRP's bloom chain on `color`, made on first use.
    bloom: Option<super::bloom::BloomChain>,
    /// HDRP's SSAO on the prepass depth and normals, and the screen group reading its result.
    ssao: Option<(super::ssao::SsaoChain, wgpu::BindGroup)>,
    /// The study's traced shadow mask, made for the first cell that traces visibility.
    traced: Option<super::traced_shadows::TracedShadowMask>,
}

/// What a forward pipeline compiles in besides its pipeline and model: built-in's vertex-lit
/// path, the sample count, a textured subject, the study's exact alternatives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct ForwardKey {
    vertex_lit: bool,
    samples: u32,
    textured: bool,
    exact: super::exact::ExactAlternatives,
}

impl ForwardKey {
    /// One sample, per-pixel lights, no exact alternatives (the deferred path's forward-only
    /// objects, probe captures).
    fn plain(textured: bool) -> ForwardKey {
        ForwardKey { vertex_lit: false, samples: 1, textured, exact: Default::default() }
    }
}

/// A forward frame's multisampled colour, role and depth, resolved into `Targets`' own at the end
/// of the pass (the role of sample 0: an integer target resolves by taking one sample).
struct MsaaTargets {
    samples: u32,
    color: wgpu::TextureView,
    role: wgpu::TextureView,
    depth: wgpu::TextureView,
}

pub struct Renderer {
    pub gpu: GpuContext,
    frame_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    sampler: wgpu::Sampler,
    fgd: wgpu::TextureView,
    /// By (pipeline, model, what else the pipeline compiles in).
    forward: HashMap<(Pipeline, String, ForwardKey), wgpu::RenderPipeline>,
    /// Fixed objects are drawn with each pipeline's default lit shader, a built-in model.
    fixed_models: Registry,
    /// By sample count.
    background: HashMap<u32, wgpu::RenderPipeline>,
    shadow_layer_layout: wgpu::BindGroupLayout,
    shadow_pipeline: wgpu::RenderPipeline,
    gbuffer_read_layout: wgpu::BindGroupLayout,
    deferred_layout: wgpu::PipelineLayout,
    tiles: super::deferred::LightTiles,
    gbuffer_pipelines: HashMap<(Pipeline, String, bool), wgpu::RenderPipeline>,
    lighting_pipelines: HashMap<(Pipeline, String, u32), wgpu::RenderPipeline>,
    shadow_sampler: wgpu::Sampler,
    material_sampler: wgpu::Sampler,
    /// Per preset ("" the neutral set), uploaded on first use and kept.
    material_textures: HashMap<&'static str, super::material_maps::MaterialTextures>,
    targets: Option<Targets>,
    timer: Option<PassTimer>,
    /// The sample counts the adapter multisamples and resolves the forward targets with.
    msaa_counts: Vec<u32>,
    /// The reflection-probe prefilter, made for the first scene with probes.
    prefilter: Option<super::reflection_probes::Prefilter>,
    /// Two timestamp pairs: probe capture and prefilter.
    probe_timer: Option<PassTimer>,
    /// HDRP's bloom pipeline, made for the first cell that blooms.
    bloom: Option<super::bloom::BloomPipeline>,
    /// Group 2 of the scene passes: the screen-space occlusion the lighting reads.
    screen_layout: wgpu::BindGroupLayout,
    /// A 1×1 visibility of 1, for cells and captures without SSAO.
    neutral_screen: wgpu::BindGroup,
    /// HDRP's SSAO steps, made for the first cell that occludes.
    ssao: Option<super::ssao::SsaoPipeline>,
    /// The depth-normal prepass pipelines, by (pipeline, textured subject).
    depth_normals: HashMap<(Pipeline, bool), wgpu::RenderPipeline>,
    /// The truth's tracers, by (pipeline, subject model, fixed model).
    truth_pipelines: HashMap<(Pipeline, String, String, super::truth::TruthKind), super::truth::TruthPipeline>,
    /// Group 3 of the tracer and of the exact alternatives: the scene as rays see it.
    ray_layout: wgpu::BindGroupLayout,
    /// The forward pipelines' layout with that group: the subject's exact alternatives.
    exact_layout: wgpu::PipelineLayout,
    /// The traced-shadow pass, by pipeline (its light attenuation), made for the first cell that traces.
    traced_shadows: HashMap<Pipeline, super::traced_shadows::TracedShadowsPipeline>,
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
        let ray_layout = super::truth::ray_layout(device, gpu.constants);
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
        let material_sampler = super::material_maps::sampler(device);
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
        let gbuffer_read_layout = super::deferred::read_layout(device);
        let tiles = super::deferred::LightTiles::new(device, &frame_layout);
        let deferred_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("deferred lighting"),
            bind_group_layouts: &[
                Some(&frame_layout),
                Some(&object_layout),
                Some(&gbuffer_read_layout),
                Some(&tiles.read_layout),
            ],
            immediate_size: 0,
        });
        let msaa_counts = gpu.multisample_counts(&[HDR_FORMAT, ROLE_FORMAT, DEPTH_FORMAT]);
        Renderer {
            gpu,
            frame_layout,
            object_layout,
            pipeline_layout,
            sampler,
            fgd,
            forward: HashMap::new(),
            fixed_models: Registry::builtin(),
            background: HashMap::new(),
            shadow_layer_layout,
            shadow_pipeline,
            shadow_sampler,
            material_sampler,
            material_textures: HashMap::new(),
            gbuffer_read_layout,
            deferred_layout,
            tiles,
            gbuffer_pipelines: HashMap::new(),
            lighting_pipelines: HashMap::new(),
            targets: None,
            timer: None,
            msaa_counts,
            prefilter: None,
            probe_timer: None,
            bloom: None,
            screen_layout,
            neutral_screen,
            ssao: None,
            depth_normals: HashMap::new(),
            truth_pipelines: HashMap::new(),
            ray_layout,
            exact_layout,
            traced_shadows: HashMap::new(),
        }
    }

    /// Number of forward pipelines compiled so far (each (pipeline, model) pair once).
    pub fn compiled_pipelines(&self) -> usize {
        self.forward.len() + self.background.len()
    }

    /// The forward pipeline of a model; `vertex_lit`: built-in's legacy vertex-lit path, which
    /// evaluates the lighting at the vertices (Gouraud) with its own light list; `textured`: the
    /// subject wears material maps (a flat subject's pipeline compiles the sampling away);
    /// `exact`: the approximation study's exact alternatives (render::exact), with the rays' group.
    fn forward_pipeline(&mut self, pipeline: Pipeline, model: &ShaderModel, key: ForwardKey) -> Result<(), Error> {
        let ForwardKey { vertex_lit, samples, textured, exact } = key;
        let key = (pipeline, model.name.to_string(), key);
        if self.forward.contains_key(&key) {
            return Ok(());
        }
        let per_vertex = model.per_vertex || vertex_lit;
        let pass = if exact.any() { wgsl::PassKind::ForwardExact } else { wgsl::PassKind::Forward };
        let source = wgsl::compose(pass, Some(model));
        let module = self.gpu.shader_module(&format!("forward {}/{}", pipeline.name(), model.name), &source)?;
        let mut constants = vec![
            ("PIPELINE", pipeline.shader_id() as f64),
            ("MAIN_LIGHT_ONLY", model.main_light_only as u32 as f64),
            ("VERTEX_LIT", vertex_lit as u32 as f64),
            ("TEXTURED", textured as u32 as f64),
        ];
        if exact.any() {
            constants.extend(exact.constants());
        }
        let entries = if per_vertex { ("vs_gouraud", "fs_gouraud") } else { ("vs_main", "fs_main") };
        let label = format!("forward {}/{}", pipeline.name(), model.name);
        let targets = [Some(HDR_FORMAT.into()), Some(ROLE_FORMAT.into())];
        let layout = if exact.any() { &self.exact_layout } else { &self.pipeline_layout };
        let p = self.mesh_pipeline(&label, layout, &module, entries, &constants, &targets, samples);
        self.gpu.check_errors("creating a forward pipeline")?;
        self.forward.insert(key, p);
        Ok(())
    }

    /// A pipeline that draws scene meshes: both faces (imported and thin meshes are shaded from
    /// either side, normals flipped), depth test Less with writes.
    #[allow(clippy::too_many_arguments)]
    fn mesh_pipeline(
        &self,
        label: &str,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        (vs, fs): (&str, &str),
        constants: &[(&str, f64)],
        targets: &[Option<wgpu::ColorTargetState>],
        samples: u32,
    ) -> wgpu::RenderPipeline {
        let options = wgpu::PipelineCompilationOptions { constants, ..Default::default() };
        self.gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(vs),
                compilation_options: options.clone(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4],
                })],
            },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: options,
                targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// The deferred path's G-buffer pipeline of a model in a pipeline convention.
    fn gbuffer_pipeline(&mut self, pipeline: Pipeline, model: &ShaderModel, textured: bool) -> Result<(), Error> {
        let key = (pipeline, model.name.to_string(), textured);
        if self.gbuffer_pipelines.contains_key(&key) {
            return Ok(());
        }
        let source = wgsl::compose(wgsl::PassKind::Forward, Some(model));
        let module = self.gpu.shader_module(&format!("gbuffer {}/{}", pipeline.name(), model.name), &source)?;
        let constants = [("PIPELINE", pipeline.shader_id() as f64), ("TEXTURED", textured as u32 as f64)];
        let targets = [
            Some(super::deferred::GB_ALBEDO.into()),
            Some(super::deferred::GB_MATERIAL.into()),
            Some(super::deferred::normal_format(pipeline).into()),
            Some(super::deferred::GB_LIGHTING.into()),
            Some(ROLE_FORMAT.into()),
        ];
        let label = format!("gbuffer {}/{}", pipeline.name(), model.name);
        let p = self.mesh_pipeline(
            &label,
            &self.pipeline_layout,
            &module,
            ("vs_main", "fs_gbuffer"),
            &constants,
            &targets,
            1,
        );
        self.gpu.check_errors("creating a G-buffer pipeline")?;
        self.gbuffer_pipelines.insert(key, p);
        Ok(())
    }

    /// HDRP's depth prepass with its normal buffer (fs_depth_normals), composed with the fixed
    /// objects' model: the pass reads no model.
    fn depth_normal_pipeline(&mut self, pipeline: Pipeline, model: &ShaderModel, textured: bool) -> Result<(), Error> {
        let key = (pipeline, textured);
        if self.depth_normals.contains_key(&key) {
            return Ok(());
        }
        let source = wgsl::compose(wgsl::PassKind::Forward, Some(model));
        let module = self.gpu.shader_module(&format!("depth prepass {}", pipeline.name()), &source)?;
        let constants = [("PIPELINE", pipeline.shader_id() as f64), ("TEXTURED", textured as u32 as f64)];
        let targets = [Some(super::ssao::NORMAL_FORMAT.into())];
        let label = format!("depth prepass {}", pipeline.name());
        let p = self.mesh_pipeline(
            &label,
            &self.pipeline_layout,
            &module,
            ("vs_main", "fs_depth_normals"),
            &constants,
            &targets,
            1,
        );
        self.gpu.check_errors("creating the depth prepass pipeline")?;
        self.depth_normals.insert(key, p);
        Ok(())
    }

    /// The deferred lighting pipeline shading the pixels of `role` with `model`.
    fn lighting_pipeline(&mut self, pipeline: Pipeline, model: &ShaderModel, role: u8) -> Result<(), Error> {
        let key = (pipeline, model.name.to_string(), role as u32);
        if self.lighting_pipelines.contains_key(&key) {
            return Ok(());
        }
        let source = wgsl::compose(wgsl::PassKind::Forward, Some(model));
        let module = self.gpu.shader_module(&format!("deferred {}/{}", pipeline.name(), model.name), &source)?;
        let constants = [
            ("PIPELINE", pipeline.shader_id() as f64),
            ("DEFERRED_ROLE", role as f64),
            ("TILED_LIGHTS", pipeline.tiled_light_loop() as u32 as f64),
        ];
        let options = wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() };
        let p = self.gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&format!("deferred lighting {}/{}", pipeline.name(), model.name)),
            layout: Some(&self.deferred_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: options.clone(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_deferred"),
                compilation_options: options,
                targets: &[Some(HDR_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        self.gpu.check_errors("creating a deferred lighting pipeline")?;
        self.lighting_pipelines.insert(key, p);
        Ok(())
    }

    fn background_pipeline(&mut self, samples: u32) -> Result<(), Error> {
        if self.background.contains_key(&samples) {
            return Ok(());
        }
        let source = wgsl::compose(wgsl::PassKind::Background, None);
        let module = self.gpu.shader_module("background", &source)?;
        let p = self.gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("background"),
            layout: Some(&self.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_background"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_background"),
                compilation_options: Default::default(),
                targets: &[Some(HDR_FORMAT.into()), Some(ROLE_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        self.gpu.check_errors("creating the background pipeline")?;
        self.background.insert(samples, p);
        Ok(())
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
        let env = EnvironmentMaps::build(&scene.environment);
        let device = &self.gpu.device;
        let mut objects = Vec::new();
        let mut triangle_count = 0;
        let object_centres = placement::object_centres(scene, &meshes);
        let scene_bounds = placement::world_bounds(scene, &meshes);
        let level0_bounds: Vec<(glam::Vec3, glam::Vec3)> = meshes.iter().map(Mesh::bounds).collect();
        for (o, mesh) in scene.objects.iter().zip(meshes) {
            triangle_count += mesh.triangle_count();
            let (vertices, indices) = mesh_buffers(device, &o.name, &mesh);
            let fixed = o.material.as_ref().map(|m| {
                let sliders =
                    Sliders { base_color_linear: m.base_color_linear, metallic: m.metallic, smoothness: m.smoothness };
                let mut pattern = GpuMaterial::zeroed();
                if let Some(c) = &m.checker {
                    pattern.params[2] = c.cell as f32;
                    pattern.checker_color = rgba(c.color_linear);
                }
                (sliders, pattern)
            });
            objects.push(GpuObject {
                vertices,
                indices,
                index_count: mesh.indices.len() as u32,
                role: o.role,
                model: o.transform.matrix(),
                fixed,
                cast_shadows: o.cast_shadows,
                receive_shadows: o.receive_shadows,
                scene_index: objects.len(),
                lod_level: o.lod.as_ref().map(|_| 0),
            });
        }
        // LOD levels after the first: extra meshes of their object, after every scene object (so
        // the first scene-object-count slots stay the scene's objects).
        let world_bounds: Vec<(DVec3, DVec3)> = scene
            .objects
            .iter()
            .zip(&level0_bounds)
            .map(|(o, b)| crate::geometry::placement::world_bounds_of(o, b))
            .collect();
        for (i, j, mesh) in procedural::lod_meshes(scene)? {
            {
                let key = format!("objects[{i}].lod.meshes[{j}]");
                triangle_count += mesh.triangle_count();
                let first = &objects[i];
                let (vertices, indices) = mesh_buffers(device, &key, &mesh);
                objects.push(GpuObject {
                    vertices,
                    indices,
                    index_count: mesh.indices.len() as u32,
                    role: first.role,
                    model: first.model,
                    fixed: first.fixed,
                    cast_shadows: first.cast_shadows,
                    receive_shadows: first.receive_shadows,
                    scene_index: i,
                    lod_level: Some(j),
                });
            }
        }
        let (object_buffer, object_stride, object_bind_group) = super::uniform_slots(
            device,
            self.gpu.constants,
            &self.object_layout,
            "objects",
            std::mem::size_of::<ObjectUniforms>() as u64,
            objects.len(),
        );
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: self.gpu.constants.usage() | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let probes = match scene.environment.reflections {
            crate::spec::scene::Reflections::Probe if !scene.probes.is_empty() => {
                if self.prefilter.is_none() {
                    self.prefilter = Some(super::reflection_probes::Prefilter::new(&self.gpu)?);
                }
                let prefilter = self.prefilter.as_ref().expect("just made");
                Some(super::reflection_probes::SceneProbes::new(&self.gpu, prefilter, &scene.probes, &env.probe))
            }
            _ => None,
        };
        // With probes the sky's levels sit in the probes' array; otherwise they are the array.
        let env_view = match &probes {
            Some(p) => p.view(),
            None => sky_probe_view(&self.gpu, &env.probe),
        };
        // A scene without lights still binds one (unused) element: a runtime-sized array needs one.
        let storage = |label: &str, bytes: u64, element: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(element).next_multiple_of(16),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let light_size = std::mem::size_of::<GpuLight>() as u64;
        let lights_buffer = storage("lights", scene.lights.len() as u64 * light_size, light_size);
        let modes_buffer = storage("light modes", (scene.lights.len() * objects.len() * 4) as u64, 4);
        let shadows = self.shadow_resources(scene, &plan, scene_bounds);
        self.gpu.check_errors(&format!("uploading composition `{}`", scene.name))?;
        Ok(PreparedScene {
            scene: scene.clone(),
            plan,
            env,
            objects,
            object_buffer,
            object_stride,
            object_bind_group,
            frame_buffer,
            env_view,
            probes,
            frame_groups: Default::default(),
            own_textures: Default::default(),
            env_table: Default::default(),
            truth_geometry: Default::default(),
            lights_buffer,
            modes_buffer,
            shadows,
            object_centres,
            triangle_count,
            world_bounds,
        })
    }

    /// The frame bind group of a composition with the subject wearing `maps` (None: flat), made and
    /// the maps uploaded on first use.
    fn frame_group(
        &mut self,
        prepared: &PreparedScene,
        maps: Option<&'static str>,
    ) -> Result<std::sync::Arc<wgpu::BindGroup>, Error> {
        let key = maps.unwrap_or("");
        if let Some(g) = prepared.frame_groups.lock().unwrap_or_else(|e| e.into_inner()).get(key) {
            return Ok(g.clone());
        }
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let textures = if key == crate::spec::presets::OWN.name {
            if prepared.own_textures.get().is_none() {
                let textures = own_textures(device, queue, &prepared.scene)?;
                let _ = prepared.own_textures.set(textures);
            }
            prepared.own_textures.get().expect("just set")
        } else {
            self.material_textures.entry(key).or_insert_with(|| match maps {
                Some(preset) => super::material_maps::MaterialTextures::new(device, queue, &MaterialMaps::of(preset)),
                None => super::material_maps::MaterialTextures::neutral(device, queue),
            });
            &self.material_textures[key]
        };
        let group = std::sync::Arc::new(self.frame_bind_group(prepared, &prepared.frame_buffer, textures));
        prepared.frame_groups.lock().unwrap_or_else(|e| e.into_inner()).insert(key, group.clone());
        Ok(group)
    }

    /// A frame bind group over `frame_buffer` (the cell's, or a probe face's) with the subject's maps.
    fn frame_bind_group(
        &self,
        prepared: &PreparedScene,
        frame_buffer: &wgpu::Buffer,
        textures: &super::material_maps::MaterialTextures,
    ) -> wgpu::BindGroup {
        self.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &self.frame_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: frame_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&prepared.env_view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&self.sampler) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&self.fgd) },
                wgpu::BindGroupEntry { binding: 4, resource: prepared.lights_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 5, resource: prepared.modes_buffer.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(&prepared.shadows.array_view),
                },
                wgpu::BindGroupEntry { binding: 7, resource: wgpu::BindingResource::Sampler(&self.shadow_sampler) },
                wgpu::BindGroupEntry { binding: 8, resource: prepared.shadows.layers_storage.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 9, resource: wgpu::BindingResource::TextureView(&textures.albedo) },
                wgpu::BindGroupEntry { binding: 10, resource: wgpu::BindingResource::TextureView(&textures.normal) },
                wgpu::BindGroupEntry { binding: 11, resource: wgpu::BindingResource::TextureView(&textures.mask) },
                wgpu::BindGroupEntry { binding: 12, resource: wgpu::BindingResource::Sampler(&self.material_sampler) },
                wgpu::BindGroupEntry { binding: 13, resource: wgpu::BindingResource::TextureView(&textures.emission) },
            ],
        })
    }

    /// The shadow layers a composition needs (1 for a directional or spot light that casts
    /// shadows, 6 for a point light), as large as the largest map its lights can ask for
    /// (`shadows::array_side`).
    fn shadow_resources(&self, scene: &Scene, plan: &FramePlan, scene_bounds: (DVec3, DVec3)) -> ShadowResources {
        let device = &self.gpu.device;
        let active = plan.passes.contains(&"shadow");
        let mut first_layer = Vec::with_capacity(scene.lights.len());
        let mut count = 0usize;
        let mut resolution = 1u32;
        for l in &scene.lights {
            if active && l.shadows {
                first_layer.push(Some(count));
                count += match l.kind {
                    LightKind::Point => 6,
                    LightKind::Directional => crate::pipelines::MAX_CASCADES,
                    LightKind::Spot => 1,
                };
                resolution = resolution.max(array_side(l));
            } else {
                first_layer.push(None);
            }
        }
        let layers = count.max(1) as u32;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow maps"),
            size: wgpu::Extent3d { width: resolution, height: resolution, depth_or_array_layers: layers },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let layer_views = (0..layers)
            .map(|i| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: i,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let (layer_uniforms, layer_stride, layer_bind_group) = super::uniform_slots(
            device,
            self.gpu.constants,
            &self.shadow_layer_layout,
            "shadow layer matrices",
            64,
            layers as usize,
        );
        let layers_storage = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shadow layers"),
            size: (std::mem::size_of::<ShadowLayer>() * layers as usize) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ShadowResources {
            active,
            layer_views,
            array_view,
            layer_uniforms,
            layer_stride,
            layer_bind_group,
            layers_storage,
            resolution,
            first_layer,
            scene_bounds,
            holds: Default::default(),
        }
    }

    fn targets(&mut self, width: u32, height: u32) -> &Targets {
        if self.targets.as_ref().is_none_or(|t| t.width != width || t.height != height) {
            let device = &self.gpu.device;
            let make = |label: &str, format: wgpu::TextureFormat, usage: wgpu::TextureUsages| {
                super::texture_2d(device, label, (width, height), format, usage)
            };
            let attach = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
            // Sampled too: HDRP's bloom reads the frame.
            let color = make("hdr", HDR_FORMAT, attach | wgpu::TextureUsages::TEXTURE_BINDING);
            let role = make("role", ROLE_FORMAT, attach | wgpu::TextureUsages::TEXTURE_BINDING);
            let depth = make(
                "depth",
                DEPTH_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            );
            let role_view = role.create_view(&Default::default());
            let depth_view = depth.create_view(&Default::default());
            let gbuffer = GBuffer::new(device, &self.gbuffer_read_layout, width, height, &role_view, &depth_view);
            self.targets = Some(Targets {
                width,
                height,
                gbuffer,
                color_view: color.create_view(&Default::default()),
                role_view,
                depth_view,
                color_readback: TextureReadback::new(device, "hdr readback", width, height, 16),
                role_readback: TextureReadback::new(device, "role readback", width, height, 1),
                color,
                role,
                msaa: None,
                bloom: None,
                ssao: None,
                traced: None,
            });
        }
        self.targets.as_ref().expect("just created")
    }

    /// The samples per pixel `settings` render with on this adapter, and why, if not as asked.
    pub fn multisampling_for(&self, settings: &CellSettings) -> Multisampling {
        let (asked, why_one) = settings.antialiasing.samples_on(settings.path);
        self.multisampling(asked, why_one)
    }

    /// The samples a cell asking `asked` (after its path's rule, `why_one`) renders with: the
    /// largest count up to `asked` the adapter multisamples and resolves every forward target with.
    fn multisampling(&self, asked: u32, why_one: Option<&str>) -> Multisampling {
        let used = self.msaa_counts.iter().copied().filter(|&n| n <= asked).max().unwrap_or(1);
        let note = if used != asked {
            let counts: Vec<String> = self.msaa_counts.iter().map(|n| format!("{n}×")).collect();
            Some(format!(
                "{asked}× MSAA asked; {} multisamples {HDR_FORMAT:?}, {ROLE_FORMAT:?} and {DEPTH_FORMAT:?} at {}: \
                 rendered {used}×",
                self.gpu.record.name,
                if counts.is_empty() { "no count".to_string() } else { counts.join(", ") }
            ))
        } else {
            why_one.map(str::to_string)
        };
        Multisampling { samples: used, note }
    }

    /// Make the multisampled forward targets match `samples` (the single-sample targets exist).
    fn ensure_msaa_targets(&mut self, samples: u32) {
        let device = &self.gpu.device;
        let t = self.targets.as_mut().expect("targets exist");
        if samples == 1 || t.msaa.as_ref().is_some_and(|m| m.samples == samples) {
            return;
        }
        let make = |label: &str, format| {
            super::multisampled_2d(
                device,
                label,
                (t.width, t.height),
                format,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
                samples,
            )
            .create_view(&Default::default())
        };
        t.msaa = Some(MsaaTargets {
            samples,
            color: make("hdr msaa", HDR_FORMAT),
            role: make("role msaa", ROLE_FORMAT),
            depth: make("depth msaa", DEPTH_FORMAT),
        });
    }

    /// Render one cell: `warmup` untimed frames, then `frames` timed ones; the last is read back.
    pub fn render(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        frames: u32,
        warmup: u32,
    ) -> Result<CellRender, Error> {
        self.render_frames(prepared, cell, frames, warmup, false)
    }

    /// One frame whose timings nobody reads (`plan::timing`: a cell timed as another of its
    /// class). A pass whose output is still in its targets from the cell before is left out: the
    /// shadow maps, when every layer's matrix, the casting meshes and their transforms are the same
    /// (materials, the camera and the sliders do not reach them). The image is the same bytes.
    pub fn render_untimed(&mut self, prepared: &PreparedScene, cell: &CellParams) -> Result<CellRender, Error> {
        self.render_frames(prepared, cell, 1, 0, true)
    }

    fn render_frames(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        frames: u32,
        warmup: u32,
        reuse: bool,
    ) -> Result<CellRender, Error> {
        // The read-back image is the last frame's: with no frame drawn it would be black, or the
        // cell before's pixels left in the target.
        let Some(total) = warmup.checked_add(frames).filter(|_| frames > 0) else {
            return Err(Error::Other(format!(
                "no frame to render: {frames} timed frames after {warmup} warm-up frames"
            )));
        };
        let fixed_model =
            self.fixed_models.find(cell.pipeline, cell.pipeline.fixed_object_shader()).cloned().ok_or_else(|| {
                Error::Other(format!("pipeline {} lacks its fixed-object shader", cell.pipeline.name()))
            })?;
        let subject_model = cell.model;
        let deferred = cell.settings.path == RenderPath::Deferred;
        let vertex_lit = cell.settings.path == RenderPath::VertexLit;
        let multisampling = self.multisampling_for(&cell.settings);
        let samples = multisampling.samples;
        let textured = cell.settings.material_maps.is_some();
        let exact = cell.settings.exact;
        if exact.any() && (deferred || vertex_lit || subject_model.per_vertex || fixed_model.per_vertex) {
            return Err(Error::Other(format!(
                "exact alternatives are for per-pixel forward shading; {}/{} on the {} path has none",
                cell.pipeline.name(),
                subject_model.name,
                cell.settings.path.name()
            )));
        }
        let subject_key = ForwardKey { vertex_lit, samples, textured, exact };
        let fixed_key = ForwardKey { textured: false, ..subject_key };
        self.forward_pipeline(cell.pipeline, subject_model, subject_key)?;
        self.forward_pipeline(cell.pipeline, &fixed_model, fixed_key)?;
        if deferred {
            for (model, role) in [(subject_model, ROLE_SUBJECT), (&*fixed_model, ROLE_FIXED)] {
                if model.deferrable() {
                    self.gbuffer_pipeline(cell.pipeline, model, textured && role == ROLE_SUBJECT)?;
                    self.lighting_pipeline(cell.pipeline, model, role)?;
                }
            }
        }
        if prepared.plan.background {
            self.background_pipeline(samples)?;
        }
        let written = self.write_uniforms(prepared, cell, &fixed_model);
        let probe_times = self.capture_probes(prepared, cell, &fixed_model, &written)?;
        let (drawn, casting) = (written.drawn(), written.casting());
        let rays = if exact.any() { Some(self.ray_scene(prepared, casting.clone())?) } else { None };
        let shadow_key = written.shadow_key;
        let WrittenFrame { lights, shadow_layers, shadow_maps, lod, .. } = written;
        let frame_group = self.frame_group(prepared, cell.settings.material_maps)?;
        let frame_group: &wgpu::BindGroup = &frame_group;
        self.targets(cell.width, cell.height);
        self.ensure_msaa_targets(samples);
        let blooms = prepared.plan.passes_for(cell.settings.path, cell.pipeline).contains(&crate::plan::BLOOM_PASS);
        if blooms {
            if self.bloom.is_none() {
                self.bloom = Some(super::bloom::BloomPipeline::new(&self.gpu)?);
            }
            let t = self.targets.as_mut().expect("targets exist");
            if t.bloom.is_none() {
                let pipeline = self.bloom.as_ref().expect("just made");
                t.bloom = Some(super::bloom::BloomChain::new(
                    &self.gpu.device,
                    pipeline,
                    &t.color,
                    (t.width, t.height),
                    super::bloom::BloomSettings::default(),
                ));
            }
        }
        let occludes = prepared.plan.occludes(cell.settings.path, cell.pipeline);
        if occludes {
            self.depth_normal_pipeline(cell.pipeline, &fixed_model, textured)?;
            if self.ssao.is_none() {
                self.ssao = Some(super::ssao::SsaoPipeline::new(&self.gpu)?);
            }
            let t = self.targets.as_mut().expect("targets exist");
            if t.ssao.is_none() {
                let pipeline = self.ssao.as_ref().expect("just made");
                let (chain, _) = super::ssao::SsaoChain::new(
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
            let camera = posed_camera(&prepared.scene.camera, &cell.view);
            let settings = super::ssao::SsaoSettings::default();
            chain.write_frame(&self.gpu.queue, &super::ssao::SsaoFrame::new(&camera, t.width, t.height, &settings));
        }
        if exact.visibility {
            if !self.traced_shadows.contains_key(&cell.pipeline) {
                let id = cell.pipeline.shader_id();
                let p = super::traced_shadows::TracedShadowsPipeline::new(
                    &self.gpu,
                    &self.frame_layout,
                    &self.ray_layout,
                    id,
                )?;
                self.traced_shadows.insert(cell.pipeline, p);
            }
            self.depth_normal_pipeline(cell.pipeline, &fixed_model, textured)?;
            let t = self.targets.as_mut().expect("targets exist");
            if t.traced.is_none() {
                t.traced = Some(super::traced_shadows::TracedShadowMask::new(&self.gpu.device, (t.width, t.height)));
            }
        }
        // The timed passes of a frame, in order: one span over the shadow layers, then the path's passes.
        // The vertex-lit path has no shadows (Unity's legacy vertex-lit renders none); traced
        // visibility needs no shadow maps.
        let shadows = prepared.shadows.active && !vertex_lit && !shadow_layers.is_empty() && !exact.visibility;
        let shadows = {
            let mut holds = prepared.shadows.holds.lock().unwrap_or_else(|e| e.into_inner());
            let kept = shadows && reuse && *holds == Some(shadow_key);
            if shadows {
                *holds = Some(shadow_key);
            }
            shadows && !kept
        };
        let mut pass_names: Vec<&'static str> = Vec::new();
        if shadows {
            pass_names.push("shadow");
        }
        if occludes {
            pass_names.extend([crate::plan::DEPTH_PREPASS, crate::plan::SSAO_PASS]);
        }
        if exact.visibility {
            if !occludes {
                pass_names.push(crate::plan::DEPTH_PREPASS);
            }
            pass_names.push(TRACED_SHADOWS_PASS);
        }
        let tiled = deferred && cell.pipeline.tiled_light_loop();
        pass_names.extend(match (deferred, tiled) {
            (true, true) => &["gbuffer", "light tiles", "deferred lighting", "forward-only and background"][..],
            (true, false) => &["gbuffer", "deferred lighting", "forward-only and background"][..],
            _ => &["forward"][..],
        });
        if blooms {
            pass_names.push(crate::plan::BLOOM_PASS);
        }
        let tile_group = if tiled { Some(self.prepare_light_tiles(cell, prepared.scene.lights.len())?) } else { None };
        let per_frame = pass_names.len() as u32;
        if self.gpu.record.timestamp_queries && self.timer.as_ref().is_none_or(|t| t.capacity() < frames * per_frame) {
            self.timer = Some(PassTimer::new(&self.gpu.device, &self.gpu.queue, frames * per_frame));
        }
        let timer = self.timer.as_ref().filter(|_| self.gpu.record.timestamp_queries);
        let t = self.targets.as_ref().expect("targets exist");
        let subject_pipeline = &self.forward[&(cell.pipeline, subject_model.name.to_string(), subject_key)];
        let fixed_pipeline = &self.forward[&(cell.pipeline, fixed_model.name.to_string(), fixed_key)];
        // With MSAA the pass draws into the multisampled targets and resolves into the frame's own.
        let msaa = t.msaa.as_ref().filter(|_| samples > 1);
        let (color_view, role_view, depth_view) = match msaa {
            Some(m) => (&m.color, &m.role, &m.depth),
            None => (&t.color_view, &t.role_view, &t.depth_view),
        };
        let (color_resolve, role_resolve) = match msaa {
            Some(_) => (Some(&t.color_view), Some(&t.role_view)),
            None => (None, None),
        };
        let keep = if msaa.is_some() { wgpu::StoreOp::Discard } else { wgpu::StoreOp::Store };
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
                encode_shadow_passes(&mut encoder, &self.shadow_pipeline, prepared, &shadow_layers, &casting, timed(k));
                k += 1;
            }
            if let (Some((chain, _)), Some(steps)) = (ssao, &self.ssao) {
                let prepass = &self.depth_normals[&(cell.pipeline, textured)];
                let draw = FrameDraw { group: frame_group, drawn: &drawn, screen: &self.neutral_screen };
                encode_depth_prepass(&mut encoder, prepared, &draw, prepass, (&chain.normal, &t.depth_view), timed(k));
                chain.encode(steps, &mut encoder, timed(k + 1).map(|(t, pair)| t.compute_writes(pair)));
                k += 2;
            }
            if let (Some(traced), Some(rays)) = (t.traced.as_ref().filter(|_| exact.visibility), &rays) {
                let normal = match ssao {
                    Some((chain, _)) => &chain.normal,
                    None => {
                        let prepass = &self.depth_normals[&(cell.pipeline, textured)];
                        let draw = FrameDraw { group: frame_group, drawn: &drawn, screen: &self.neutral_screen };
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
            if deferred {
                let timed: Vec<_> = (k..per_frame).map(timed).collect();
                self.encode_deferred(
                    &mut encoder,
                    prepared,
                    FrameDraw { group: frame_group, drawn: &drawn, screen },
                    cell,
                    &fixed_model,
                    tile_group.as_ref(),
                    &timed,
                );
            } else {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("forward"),
                    color_attachments: &[
                        Some(wgpu::RenderPassColorAttachment {
                            view: color_view,
                            depth_slice: None,
                            resolve_target: color_resolve,
                            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: keep },
                        }),
                        Some(wgpu::RenderPassColorAttachment {
                            view: role_view,
                            depth_slice: None,
                            resolve_target: role_resolve,
                            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: keep },
                        }),
                    ],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Discard,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: timed(k).map(|(t, pair)| t.writes(pair, true, true)),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_bind_group(0, frame_group, &[]);
                pass.set_bind_group(2, screen, &[]);
                if let Some((_, group)) = &rays {
                    pass.set_bind_group(3, group, &[]);
                }
                for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| drawn[*i]) {
                    pass.set_pipeline(if o.role == Role::Subject { subject_pipeline } else { fixed_pipeline });
                    pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
                    pass.set_vertex_buffer(0, o.vertices.slice(..));
                    pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..o.index_count, 0, 0..1);
                }
                if let (true, Some(bg)) = (prepared.plan.background, self.background.get(&samples)) {
                    pass.set_pipeline(bg);
                    pass.draw(0..3, 0..1);
                }
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
            let mut passes: Vec<(String, Vec<f64>)> = pass_names
                .iter()
                .enumerate()
                .map(|(k, name)| (name.to_string(), p.iter().skip(k).step_by(per_frame as usize).copied().collect()))
                .collect();
            // Once per set of inputs, before the frames: not part of a frame's time.
            if let Some((capture, prefilter)) = probe_times {
                passes.push(("probe capture".into(), vec![capture]));
                passes.push(("probe prefilter".into(), vec![prefilter]));
            }
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
            lights,
            multisampling,
            shadow_maps,
            lod,
        })
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
            let module = self.gpu.shader_module("light tiles", &source)?;
            let pipeline = self.gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("light tiles"),
                layout: Some(&self.tiles.compute_layout),
                module: &module,
                entry_point: Some("cs_light_tiles"),
                compilation_options: Default::default(),
                cache: None,
            });
            self.gpu.check_errors("creating the light-tile pipeline")?;
            self.tiles.pipeline = Some(pipeline);
        }
        let (tx, ty, words) = super::deferred::tile_grid(cell.width, cell.height, lights);
        self.tiles.reserve(&self.gpu.device, (tx * ty * words) as u64 * 4);
        let t = self.targets.as_ref().expect("targets exist");
        Ok(self.tiles.write_group(&self.gpu.device, &t.depth_view))
    }

    /// One deferred frame: G-buffer, lighting per role, then what the G-buffer cannot carry drawn
    /// forward, and the background. The frame's timestamps bracket all three passes.
    #[allow(clippy::too_many_arguments)]
    fn encode_deferred(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        prepared: &PreparedScene,
        draw: FrameDraw,
        cell: &CellParams,
        fixed_model: &ShaderModel,
        tile_group: Option<&wgpu::BindGroup>,
        timed: &[Option<(&PassTimer, u32)>],
    ) {
        let p = cell.pipeline;
        let FrameDraw { group: frame_group, drawn, screen } = draw;
        // With the tiled loop, its compute pass sits between the G-buffer and the lighting.
        let (light_at, last_at) = if tile_group.is_some() { (2, 3) } else { (1, 2) };
        let t = self.targets.as_ref().expect("targets exist");
        let gb = &t.gbuffer;
        let color = |view, clear| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: clear, store: wgpu::StoreOp::Store },
            })
        };
        let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
        let model_of = |o: &GpuObject| if o.role == Role::Subject { cell.model } else { fixed_model };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("gbuffer"),
                color_attachments: &[
                    color(&gb.albedo, clear),
                    color(&gb.material, clear),
                    color(gb.normal(p), clear),
                    color(&gb.lighting, clear),
                    color(&t.role_view, clear),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: timed[0].map(|(t, pair)| t.writes(pair, true, true)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, frame_group, &[]);
            pass.set_bind_group(2, screen, &[]);
            for (i, o) in prepared.objects.iter().enumerate().filter(|(i, o)| drawn[*i] && model_of(o).deferrable()) {
                let textured = o.role == Role::Subject && cell.settings.material_maps.is_some();
                pass.set_pipeline(&self.gbuffer_pipelines[&(p, model_of(o).name.to_string(), textured)]);
                pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
                pass.set_vertex_buffer(0, o.vertices.slice(..));
                pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..o.index_count, 0, 0..1);
            }
        }
        if let (Some(group), Some(pipeline)) = (tile_group, &self.tiles.pipeline) {
            encoder.clear_buffer(&self.tiles.masks, 0, None);
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("light tiles"),
                timestamp_writes: timed[1].map(|(t, pair)| t.compute_writes(pair)),
            });
            let (tx, ty, _) = super::deferred::tile_grid(t.width, t.height, 0);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, frame_group, &[]);
            pass.set_bind_group(3, group, &[]);
            pass.dispatch_workgroups(tx, ty, 1);
        }
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("deferred lighting"),
                color_attachments: &[color(&t.color_view, wgpu::LoadOp::Clear(wgpu::Color::BLACK))],
                depth_stencil_attachment: None,
                timestamp_writes: timed[light_at].map(|(t, pair)| t.writes(pair, true, true)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, frame_group, &[]);
            pass.set_bind_group(1, &prepared.object_bind_group, &[0]);
            pass.set_bind_group(2, gb.read(p), &[]);
            pass.set_bind_group(3, &self.tiles.read, &[]);
            for (model, role) in [(cell.model, ROLE_SUBJECT), (fixed_model, ROLE_FIXED)] {
                if let Some(pipeline) = self.lighting_pipelines.get(&(p, model.name.to_string(), role as u32)) {
                    pass.set_pipeline(pipeline);
                    pass.draw(0..3, 0..1);
                }
            }
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward-only and background"),
            color_attachments: &[color(&t.color_view, wgpu::LoadOp::Load), color(&t.role_view, wgpu::LoadOp::Load)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: timed[last_at].map(|(t, pair)| t.writes(pair, true, true)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(1, &prepared.object_bind_group, &[0]);
        pass.set_bind_group(2, screen, &[]);
        for (i, o) in prepared.objects.iter().enumerate().filter(|(i, o)| drawn[*i] && !model_of(o).deferrable()) {
            let textured = o.role == Role::Subject && cell.settings.material_maps.is_some();
            pass.set_pipeline(&self.forward[&(p, model_of(o).name.to_string(), ForwardKey::plain(textured))]);
            pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
        if let (true, Some(bg)) = (prepared.plan.background, self.background.get(&1)) {
            pass.set_pipeline(bg);
            pass.draw(0..3, 0..1);
        }
    }

    /// Write the frame and object uniforms and the light buffers; returns the light assignment
    /// and the shadow layers this cell renders.
    fn write_uniforms(&self, prepared: &PreparedScene, cell: &CellParams, fixed_model: &ShaderModel) -> WrittenFrame {
        let scene = &prepared.scene;
        let p = cell.pipeline;
        let aspect = cell.width as f64 / cell.height as f64;
        let camera = posed_camera(&scene.camera, &cell.view);
        let vp = view_projection(&camera, aspect);
        let mut frame = FrameUniforms::zeroed();
        frame.view_proj = mat(vp);
        frame.inv_view_proj = mat(vp.inverse());
        frame.camera_pos = vec4(DVec3::from(camera.position), 1.0);
        let lights = super::camera::cell_lights(scene, cell.light_intensity, cell.light_range, &camera, &cell.view);
        let model_of = |i: usize| if prepared.objects[i].role == Role::Subject { cell.model } else { fixed_model };
        let assignment =
            assign(p, cell.settings.path, &cell.settings.light_budget, &lights, &prepared.object_centres, |i| {
                !model_of(i).deferrable()
            });
        let sh = &prepared.shadows;
        // Indexed by layer: a light's layers sit from its first layer on (a directional light
        // reserves MAX_CASCADES and uses its pipeline's count).
        let mut shadow_layers: Vec<ShadowLayer> = vec![ShadowLayer::zeroed(); sh.layer_views.len()];
        let mut used_layers: Vec<(usize, u32)> = Vec::new();
        let mut shadow_maps = Vec::new();
        let mut gpu_lights = Vec::with_capacity(lights.len());
        let mut colors = Vec::with_capacity(lights.len());
        let main_light = crate::plan::lights::main_light(p, &lights);
        for (slot, l) in lights.iter().enumerate() {
            let emitter = l.emitter();
            let outer = (l.spot_angle_deg * 0.5).to_radians();
            // Unity's fallback inner angle: atan(tan(outer)·46/64) (models.md#urp).
            let inner = l
                .inner_spot_angle_deg
                .map(|a| (a * 0.5).to_radians())
                .unwrap_or_else(|| (outer.tan() * 46.0 / 64.0).atan());
            let color = DVec3::from(p.light_radiance(l.color, l.intensity, emitter));
            colors.push(color);
            let first = sh.first_layer[slot];
            let mut layer_count = 0;
            if first.is_some() {
                let cascades = p.shadow_cascades();
                let cascade_view = CascadeView { camera: &camera, aspect, cascades: &cascades };
                let (resolution, note) = cell_resolution(p, l, &camera, (cell.width, cell.height), sh.resolution);
                shadow_maps.push(ShadowMapUse { light: slot, resolution, note });
                let layers = light_layers(l, (resolution, sh.resolution), sh.scene_bounds, &cascade_view);
                let at = first.unwrap_or(0);
                used_layers.extend((at..at + layers.len()).map(|layer| (layer, resolution)));
                layer_count = layers.len();
                for (k, layer) in layers.into_iter().enumerate() {
                    shadow_layers[at + k] = layer;
                }
            }
            let (shadow, shadow_bias) = shadow_slot(l, first, layer_count);
            gpu_lights.push(GpuLight {
                position: vec4(DVec3::from(l.position), emitter.shader_kind() as f64),
                direction: vec4(DVec3::from(l.direction).normalize_or_zero(), 0.0),
                color: vec4(color, 0.0),
                params: [l.range as f32, outer.cos() as f32, inner.cos() as f32, emitter.hdrp_min_roughness() as f32],
                shadow,
                shadow_bias,
            });
        }
        if !gpu_lights.is_empty() {
            self.gpu.queue.write_buffer(&prepared.lights_buffer, 0, bytemuck::cast_slice(&gpu_lights));
        }
        if !used_layers.is_empty() {
            self.gpu.queue.write_buffer(&sh.layers_storage, 0, bytemuck::cast_slice(&shadow_layers));
            let mut slots = vec![0u8; (sh.layer_stride as usize) * shadow_layers.len()];
            for (i, layer) in shadow_layers.iter().enumerate() {
                let at = i * sh.layer_stride as usize;
                slots[at..at + 64].copy_from_slice(bytemuck::bytes_of(&layer.view_proj));
            }
            self.gpu.queue.write_buffer(&sh.layer_uniforms, 0, &slots);
        }
        let modes: Vec<u32> = assignment.iter().flat_map(|o| o.lights.iter().map(|u| u.mode.shader_value())).collect();
        if !modes.is_empty() {
            self.gpu.queue.write_buffer(&prepared.modes_buffer, 0, bytemuck::cast_slice(&modes));
        }
        // Lights folded into an object's SH: a directional light from its direction, a point or
        // spot from the object's centre with its attenuation there, in the ambient term's units.
        let sh_per_object: Vec<[[f32; 4]; 9]> = assignment
            .iter()
            .zip(&prepared.object_centres)
            .map(|(o, (_, centre))| {
                let mut sh = [DVec3::ZERO; 9];
                for u in o.lights.iter().filter(|u| u.mode == LightMode::Sh) {
                    let l = &lights[u.light];
                    let color = colors[u.light];
                    let (dir, atten) = match l.kind {
                        LightKind::Directional => (-DVec3::from(l.direction), 1.0),
                        _ => {
                            let to = DVec3::from(l.position) - *centre;
                            (to, p.attenuation().eval(to.length(), l.range))
                        }
                    };
                    let scale = crate::shading::twin::irradiance_per_intensity(p) / std::f64::consts::PI;
                    for (acc, c) in sh.iter_mut().zip(sh_of_light(dir, color * atten * scale)) {
                        *acc += c;
                    }
                }
                sh.map(|c| [c.x as f32, c.y as f32, c.z as f32, 0.0])
            })
            .collect();
        let (tiles_x, _, words) = super::deferred::tile_grid(cell.width, cell.height, lights.len());
        frame.counts = [lights.len() as u32, main_light.map_or(0, |slot| slot as u32 + 1), words, tiles_x];
        for (dst, src) in frame.sh.iter_mut().zip(prepared.env.sh.iter()) {
            *dst = [src[0] as f32, src[1] as f32, src[2] as f32, 0.0];
        }
        let env_levels = match &prepared.probes {
            Some(_) => crate::environment::prefilter::LEVELS,
            None => prepared.env.probe.levels.len(),
        };
        frame.env = [(env_levels - 1) as f32, (prepared.env.intensity * p.environment_scale()) as f32, 0.0, 0.0];
        frame.subject = gpu_material(&cell.surface, GpuMaterial::zeroed());
        frame.subject.params[3] = if cell.settings.material_maps.is_some() { 1.0 } else { 0.0 };
        if cell.model.emits() {
            // Emissive radiance: the subject's colour (or own emissive colour) × the axis, in the
            // pipeline's light units.
            let colour = cell.settings.emission_color.map(DVec3::from).unwrap_or(cell.surface.base_color);
            let e = colour * cell.settings.emission * p.intensity_scale();
            frame.subject.emission = [e.x as f32, e.y as f32, e.z as f32, 0.0];
        }
        let any = Sliders { base_color_linear: [1.0; 3], metallic: 0.0, smoothness: 0.5 };
        frame.fixed = gpu_material(&fixed_model.surface(p, &any), GpuMaterial::zeroed());
        // The probes' capture slot is chosen after the capture key (`capture_probes`), which
        // rewrites their layers; slot 0 until then.
        if let Some(probes) = &prepared.probes {
            frame.reflection = [probes.probes.len() as u32, 0, 0, 0];
            for (k, t) in probes.probes.iter().enumerate() {
                frame.probes[k] = GpuReflectionProbe::new(&t.probe, k, probes.probes.len(), 0);
            }
        }
        self.gpu.queue.write_buffer(&prepared.frame_buffer, 0, bytemuck::bytes_of(&frame));
        // LOD groups: the levels this camera draws, and each mesh's fade (None: not drawn).
        let mut lod = Vec::new();
        let mut fades: Vec<Option<f64>> =
            prepared.objects.iter().map(|o| o.lod_level.is_none().then_some(1.0)).collect();
        for seen in crate::plan::lod::groups_seen(scene, &prepared.world_bounds, &camera) {
            for (m, mesh) in prepared.objects.iter().enumerate().filter(|(_, m)| m.scene_index == seen.object) {
                fades[m] = seen.drawn.iter().find(|d| Some(d.level) == mesh.lod_level).map(|d| d.fade);
            }
            lod.push(LodUse {
                object: scene.objects[seen.object].name.clone(),
                relative_height: seen.relative_height,
                drawn: seen.drawn,
            });
        }
        let mut objects = vec![0u8; (prepared.object_stride as usize) * prepared.objects.len()];
        let mut materials = Vec::with_capacity(prepared.objects.len());
        for (i, o) in prepared.objects.iter().enumerate() {
            let material = match &o.fixed {
                Some((sliders, pattern)) => gpu_material(&fixed_model.surface(p, sliders), *pattern),
                None => GpuMaterial::zeroed(),
            };
            materials.push(material);
            let u = ObjectUniforms {
                model: mat(o.model),
                normal_matrix: mat(o.model.inverse().transpose()),
                material,
                flags: match o.role {
                    Role::Subject => [1, ROLE_SUBJECT as u32, o.scene_index as u32, o.receive_shadows as u32],
                    Role::Fixed => [0, ROLE_FIXED as u32, o.scene_index as u32, o.receive_shadows as u32],
                },
                light_sh: sh_per_object[o.scene_index],
                // A level fading in or out keeps its dither's share of the fragments.
                lod: match fades[i] {
                    Some(f) if f < 1.0 => [f as f32, 1.0, 0.0, 0.0],
                    _ => [1.0, 0.0, 0.0, 0.0],
                },
            };
            let at = i * prepared.object_stride as usize;
            objects[at..at + std::mem::size_of::<ObjectUniforms>()].copy_from_slice(bytemuck::bytes_of(&u));
        }
        self.gpu.queue.write_buffer(&prepared.object_buffer, 0, &objects);
        // What a probe capture sees: everything but the camera and the subject.
        let key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::hash::DefaultHasher::new();
            p.name().hash(&mut h);
            let mut seen = frame;
            (seen.view_proj, seen.inv_view_proj, seen.camera_pos) = Default::default();
            seen.subject = GpuMaterial::zeroed();
            bytemuck::bytes_of(&seen).hash(&mut h);
            bytemuck::cast_slice::<GpuLight, u8>(&gpu_lights).hash(&mut h);
            bytemuck::cast_slice::<ShadowLayer, u8>(&shadow_layers).hash(&mut h);
            modes.hash(&mut h);
            for (i, o) in prepared.objects.iter().enumerate().filter(|(_, o)| o.role == Role::Fixed) {
                let at = i * prepared.object_stride as usize;
                objects[at..at + std::mem::size_of::<ObjectUniforms>()].hash(&mut h);
                o.index_count.hash(&mut h);
            }
            h.finish()
        };
        let shadow_key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::hash::DefaultHasher::new();
            used_layers.hash(&mut h);
            bytemuck::cast_slice::<ShadowLayer, u8>(&shadow_layers).hash(&mut h);
            for (i, o) in prepared.objects.iter().enumerate() {
                let at = i * prepared.object_stride as usize;
                (o.cast_shadows, o.index_count, fades[i].map(f64::to_bits)).hash(&mut h);
                objects[at..at + 64].hash(&mut h);
            }
            h.finish()
        };
        WrittenFrame {
            lights: assignment,
            shadow_layers: used_layers,
            shadow_maps,
            frame,
            capture_key: key,
            lod,
            fades,
            materials,
            shadow_key,
        }
    }

    /// The scene as rays see it (render::truth::TruthScene): the meshes `kept` (the ones the frame
    /// draws: LOD levels change them) in a BVH with the environment's tables and irradiance. Built
    /// for the first cell that traces or asks for an exact alternative, rebuilt only when a cell
    /// keeps other meshes.
    fn ray_scene(
        &self,
        prepared: &PreparedScene,
        kept: Vec<bool>,
    ) -> Result<std::sync::Arc<super::truth::TruthScene>, Error> {
        let scene = &prepared.scene;
        let env = prepared.env_table.get_or_init(|| {
            let radiance = |d: DVec3| crate::environment::sky::radiance(&scene.environment.sky, d);
            let w = super::truth::ENV_WIDTH;
            let image = crate::environment::prefilter::EquirectImage::sample(&radiance, w, w / 2, 2);
            super::truth::TruthEnvironment::new(&self.gpu.device, self.gpu.constants, &image)
        });
        let cached = prepared.truth_geometry.lock().unwrap_or_else(|e| e.into_inner()).clone();
        Ok(match cached {
            Some((k, g)) if k == kept => g,
            _ => {
                let mut meshes = procedural::build_scene(scene)?;
                meshes.extend(procedural::lod_meshes(scene)?.into_iter().map(|(_, _, m)| m));
                let objects = prepared.objects.iter().zip(&meshes).enumerate().filter(|(i, _)| kept[*i]);
                let g = super::truth::bvh::TruthGeometry::build(objects.map(|(i, (o, m))| (i as u32, m, o.model)));
                let g = std::sync::Arc::new(super::truth::TruthScene::new(&self.gpu.device, &self.ray_layout, &g, env));
                *prepared.truth_geometry.lock().unwrap_or_else(|e| e.into_inner()) = Some((kept, g.clone()));
                g
            }
        })
    }

    /// The ground truth of a cell (render::truth): its scene, lights and materials path traced
    /// with the models the cell draws them with (`same-brdf`) or the physical model (`physical`). The meshes are the cell's drawn ones; in a
    /// LOD cross-fade band, the outgoing level alone (the one the shadow pass draws whole).
    pub fn render_truth(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        settings: &super::truth::TruthSettings,
    ) -> Result<super::truth::Truth, Error> {
        let fixed_model =
            self.fixed_models.find(cell.pipeline, cell.pipeline.fixed_object_shader()).cloned().ok_or_else(|| {
                Error::Other(format!("pipeline {} lacks its fixed-object shader", cell.pipeline.name()))
            })?;
        let key = (cell.pipeline, cell.model.name.to_string(), fixed_model.name.to_string(), settings.kind);
        if !self.truth_pipelines.contains_key(&key) {
            let source = wgsl::compose_truth(cell.model, &fixed_model);
            let id = cell.pipeline.shader_id();
            let p = super::truth::TruthPipeline::new(
                &self.gpu,
                &self.frame_layout,
                &self.ray_layout,
                &source,
                id,
                settings.kind,
            )?;
            self.truth_pipelines.insert(key.clone(), p);
        }
        let written = self.write_uniforms(prepared, cell, &fixed_model);
        let frame_group = self.frame_group(prepared, cell.settings.material_maps)?;
        let geometry = self.ray_scene(prepared, written.casting())?;
        let textured = cell.settings.material_maps.is_some();
        let mut objects = Vec::with_capacity(prepared.objects.len() * 128);
        for (o, material) in prepared.objects.iter().zip(&written.materials) {
            objects.extend_from_slice(bytemuck::bytes_of(material));
            let flags: [u32; 4] = match o.role {
                Role::Subject => [1, ROLE_SUBJECT as u32, textured as u32, 0],
                Role::Fixed => [0, ROLE_FIXED as u32, 0, 0],
            };
            objects.extend_from_slice(bytemuck::cast_slice(&flags));
        }
        let inputs = super::truth::TruthInputs {
            scene: &geometry,
            objects: &objects,
            background: prepared.plan.background,
            size: (cell.width, cell.height),
            subject_role: ROLE_SUBJECT,
        };
        super::truth::trace(&self.gpu, &self.truth_pipelines[&key], &frame_group, &inputs, settings)
    }

    /// Render every probe's faces (the fixed objects and the sky seen from the probe, lit as the
    /// cell lights them, reflecting the sky alone) and prefilter them, unless the last capture saw
    /// the same inputs. Returns the GPU time of the capture and of the prefilter, ms (None:
    /// reused, or no timestamp queries).
    fn capture_probes(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        fixed_model: &ShaderModel,
        written: &WrittenFrame,
    ) -> Result<Option<(f64, f64)>, Error> {
        let Some(probes) = &prepared.probes else { return Ok(None) };
        let slot = probes.slot_for(written.capture_key);
        // Point the cell's frame at the slot's levels.
        let mut frame = written.frame;
        let count = probes.probes.len();
        for (k, t) in probes.probes.iter().enumerate() {
            frame.probes[k] = GpuReflectionProbe::new(&t.probe, k, count, slot.index());
        }
        self.gpu.queue.write_buffer(&prepared.frame_buffer, 0, bytemuck::bytes_of(&frame));
        let super::reflection_probes::Slot::ToCapture(slot) = slot else { return Ok(None) };
        self.forward_pipeline(cell.pipeline, fixed_model, ForwardKey::plain(false))?;
        if prepared.plan.background {
            self.background_pipeline(1)?;
        }
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        self.material_textures
            .entry("")
            .or_insert_with(|| super::material_maps::MaterialTextures::neutral(device, queue));
        if self.gpu.record.timestamp_queries && self.probe_timer.is_none() {
            self.probe_timer = Some(PassTimer::new(&self.gpu.device, &self.gpu.queue, 2));
        }
        let timer = self.probe_timer.as_ref().filter(|_| self.gpu.record.timestamp_queries);
        let pipeline = &self.forward[&(cell.pipeline, fixed_model.name.to_string(), ForwardKey::plain(false))];
        let background = self.background.get(&1).filter(|_| prepared.plan.background);
        let neutral = &self.material_textures[""];
        let (drawn, casting) = (written.drawn(), written.casting());
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        if prepared.shadows.active && !written.shadow_layers.is_empty() {
            encode_shadow_passes(&mut encoder, &self.shadow_pipeline, prepared, &written.shadow_layers, &casting, None);
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
                groups.push(self.frame_bind_group(prepared, &t.frame_buffers[f], neutral));
            }
        }
        for t in &probes.probes {
            for f in 0..6 {
                // One span over every face: begin at the first pass, end at the last.
                let (first, last) = (face == 0, face + 1 == faces);
                let timestamps = timer.filter(|_| first || last).map(|tm| tm.writes(0, first, last));
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("probe capture"),
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
                pass.set_pipeline(pipeline);
                // The subject is left out: a dynamic object, which baked probes do not see.
                for (i, o) in prepared.objects.iter().enumerate().filter(|(i, o)| drawn[*i] && o.role == Role::Fixed) {
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
        probes.encode_prefilter(prefilter, &mut encoder, slot, timer.map(|t| t.compute_writes(1)));
        if let Some(t) = timer {
            t.encode_resolve(&mut encoder, 2);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait_idle()?;
        let times = timer.map(|t| t.read_ms(&self.gpu.device, 2)).transpose()?;
        self.gpu.check_errors("capturing reflection probes")?;
        probes.captured(slot, written.capture_key);
        Ok(times.map(|t| (t[0], t[1])))
    }
}

use bytemuck::Zeroable;

/// What writing a cell's uniforms decided: how lights reach objects, the shadow layers in use and
/// their maps, the frame written and the hash of what a probe capture would see of it, and the
/// LOD levels the camera draws.
struct WrittenFrame {
    lights: Vec<ObjectLights>,
    shadow_layers: Vec<(usize, u32)>,
    shadow_maps: Vec<ShadowMapUse>,
    frame: FrameUniforms,
    capture_key: u64,
    lod: Vec<LodUse>,
    /// Each mesh's LOD fade (None: not drawn; 1 for meshes without LOD).
    fades: Vec<Option<f64>>,
    /// Each mesh's material as its model receives it (zero for the subject: it reads the frame's).
    materials: Vec<GpuMaterial>,
    /// Everything the shadow pass's depth depends on: the layers' matrices and resolutions, which
    /// meshes cast, and their transforms and fades (materials and the camera do not reach it).
    shadow_key: u64,
}

impl WrittenFrame {
    /// Whether each mesh is drawn.
    fn drawn(&self) -> Vec<bool> {
        self.fades.iter().map(Option::is_some).collect()
    }

    /// Whether each mesh casts shadows this frame: a LOD level fading in does not (the shadow
    /// pass draws each group's outgoing level whole).
    fn casting(&self) -> Vec<bool> {
        self.fades.iter().map(|f| f.is_some_and(|f| f > 0.0)).collect()
    }
}

/// What a frame's passes draw with: the frame bind group, which meshes are drawn, and the screen
/// group (the SSAO visibility, or the neutral one).
struct FrameDraw<'a> {
    group: &'a wgpu::BindGroup,
    drawn: &'a [bool],
    screen: &'a wgpu::BindGroup,
}

/// HDRP's depth prepass: every drawn object's depth and shading normal, what SSAO reads.
fn encode_depth_prepass(
    encoder: &mut wgpu::CommandEncoder,
    prepared: &PreparedScene,
    draw: &FrameDraw,
    pipeline: &wgpu::RenderPipeline,
    (normal, depth): (&wgpu::TextureView, &wgpu::TextureView),
    timed: Option<(&PassTimer, u32)>,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("depth prepass"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: normal,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: timed.map(|(t, pair)| t.writes(pair, true, true)),
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, draw.group, &[]);
    pass.set_bind_group(2, draw.screen, &[]);
    for (i, o) in prepared.objects.iter().enumerate().filter(|(i, _)| draw.drawn[*i]) {
        pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
        pass.set_vertex_buffer(0, o.vertices.slice(..));
        pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..o.index_count, 0, 0..1);
    }
}

/// The screen group over an SSAO visibility texture.
fn screen_group(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, visibility: &wgpu::Texture) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("screen"),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 6,
            resource: wgpu::BindingResource::TextureView(&visibility.create_view(&Default::default())),
        }],
    })
}

/// The screen group of a frame without SSAO: a 1×1 visibility of 1.
fn neutral_screen_group(gpu: &GpuContext, layout: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
    let texture = super::texture_2d(
        &gpu.device,
        "no ssao",
        (1, 1),
        wgpu::TextureFormat::Rg32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    gpu.queue.write_texture(
        texture.as_image_copy(),
        bytemuck::cast_slice(&[1.0f32, 0.0]),
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(8), rows_per_image: None },
        wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
    );
    screen_group(&gpu.device, layout, &texture)
}

/// Depth of every casting object into every shadow layer.
fn encode_shadow_passes(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::RenderPipeline,
    prepared: &PreparedScene,
    layers: &[(usize, u32)],
    casting: &[bool],
    timed: Option<(&PassTimer, u32)>,
) {
    let sh = &prepared.shadows;
    let last = layers.len().saturating_sub(1);
    for (n, &(layer, resolution)) in layers.iter().enumerate() {
        let view = &sh.layer_views[layer];
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            // One timed span over every layer: begin on the first, end on the last.
            timestamp_writes: timed.filter(|_| n == 0 || n == last).map(|(t, pair)| t.writes(pair, n == 0, n == last)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        // The light's map is the top-left resolution² of the layer (render::shadows).
        pass.set_viewport(0.0, 0.0, resolution as f32, resolution as f32, 0.0, 1.0);
        pass.set_bind_group(0, &sh.layer_bind_group, &[(layer as u64 * sh.layer_stride) as u32]);
        for (i, o) in prepared.objects.iter().enumerate().filter(|(i, o)| casting[*i] && o.cast_shadows) {
            pass.set_bind_group(1, &prepared.object_bind_group, &[(i as u64 * prepared.object_stride) as u32]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
    }
}

/// The depth-only pipeline of the shadow pass; slope-scaled depth bias against acne on top of the
/// lights' own biases.
fn shadow_pipeline(
    gpu: &GpuContext,
    layer_layout: &wgpu::BindGroupLayout,
    object_layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("shadow"),
        source: wgpu::ShaderSource::Wgsl(gpu.constants.wgsl(include_str!("../../shaders/pass/shadow.wgsl"))),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("shadow"),
        bind_group_layouts: &[Some(layer_layout), Some(object_layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("shadow"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_shadow"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            })],
        },
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: wgpu::DepthBiasState { constant: 2, slope_scale: 1.5, clamp: 0.0 },
        }),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}

/// A mesh's vertex and index buffers.
fn mesh_buffers(device: &wgpu::Device, label: &str, mesh: &Mesh) -> (wgpu::Buffer, wgpu::Buffer) {
    let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(&mesh.vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(&mesh.indices),
        usage: wgpu::BufferUsages::INDEX,
    });
    (vertices, indices)
}

/// The sky's prefiltered levels as an array texture (Rgba16Float, one layer per level).
fn sky_probe_view(gpu: &GpuContext, probe: &crate::environment::prefilter::Probe) -> wgpu::TextureView {
    let texels: Vec<half::f16> =
        probe.levels.iter().flat_map(|l| l.texels.iter().flat_map(|t| super::half_texel(*t))).collect();
    let env_texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("environment probe"),
            size: wgpu::Extent3d {
                width: probe.width as u32,
                height: probe.height as u32,
                depth_or_array_layers: probe.levels.len() as u32,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&texels),
    );
    env_texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// The textures of a composition's glTF subject's own material (`materials::gltf`).
fn own_textures(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
) -> Result<super::material_maps::MaterialTextures, Error> {
    let no_maps =
        || Error::Other(format!("composition `{}`: the subject has no glTF material with textures", scene.name));
    let path = scene.subject_gltf().ok_or_else(no_maps)?;
    let (_, material) = crate::geometry::gltf_io::load_with_material(&path)?;
    let maps = material.as_ref().and_then(crate::materials::gltf::maps).ok_or_else(no_maps)?;
    Ok(super::material_maps::MaterialTextures::new(device, queue, &maps))
}

/// A material map of the frame group, sampled by both stages (the vertex-lit path reads them) and
/// by the truth's tracer.
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

/// A surface in the uniform layout; `pattern` carries the checkerboard, if any.
fn gpu_material(s: &Surface, pattern: GpuMaterial) -> GpuMaterial {
    let v = |x: DVec3| [x.x as f32, x.y as f32, x.z as f32, 0.0];
    let q = s.params.map(|x| x as f32);
    GpuMaterial {
        base_color: v(s.base_color),
        params: [s.metallic as f32, s.smoothness as f32, pattern.params[2], 0.0],
        checker_color: pattern.checker_color,
        specular: v(s.specular),
        model0: [q[0], q[1], q[2], q[3]],
        model1: [q[4], q[5], q[6], q[7]],
        emission: [0.0; 4],
    }
}

fn mat(m: DMat4) -> [[f32; 4]; 4] {
    Mat4::from_cols_array(&m.to_cols_array().map(|v| v as f32)).to_cols_array_2d()
}

fn vec4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

fn rgba(c: [f64; 3]) -> [f32; 4] {
    [c[0] as f32, c[1] as f32, c[2] as f32, 1.0]
}
