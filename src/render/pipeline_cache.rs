//! The render pipelines, compiled once per (pipeline convention, model, what else they compile in)
//! and kept for the renderer's life.

use std::collections::HashMap;

use crate::error::Error;
use crate::geometry::Vertex;
use crate::gpu::GpuContext;
use crate::pipelines::surface::{Blend, RenderFace, SurfaceType};
use crate::pipelines::Pipeline;
use crate::plan::lod::CrossFade;
use crate::render::formats::{DEPTH_FORMAT, HDR_FORMAT, ROLE_FORMAT};
use crate::shading::{wgsl, ShaderModel};

/// One pipeline per render face (`RenderFace as usize`), where meshes drawn with it have that face.
pub(in crate::render) type ByFace<'a> = [Option<&'a wgpu::RenderPipeline>; 3];

/// The render faces of the composition's meshes that `which` admits, each once.
pub(in crate::render) fn faces_of(
    layout: &crate::plan::cell::SceneLayout,
    which: impl Fn(&crate::plan::cell::MeshSlot) -> bool,
) -> Vec<RenderFace> {
    RenderFace::ALL.into_iter().filter(|f| layout.meshes.iter().any(|m| m.render_face == *f && which(m))).collect()
}

/// The ROP state of a blend (None: the source replaces the target).
fn blend_state(blend: Blend) -> Option<wgpu::BlendState> {
    use wgpu::BlendFactor as F;
    let (src, dst) = match blend {
        Blend::Replace => return None,
        Blend::SrcAlphaOver => (F::SrcAlpha, F::OneMinusSrcAlpha),
        Blend::PremultipliedOver => (F::One, F::OneMinusSrcAlpha),
        Blend::Add => (F::One, F::One),
        Blend::SrcAlphaAdd => (F::SrcAlpha, F::One),
        Blend::Multiply => (F::Dst, F::Zero),
    };
    let color = wgpu::BlendComponent { src_factor: src, dst_factor: dst, operation: wgpu::BlendOperation::Add };
    Some(wgpu::BlendState { color, alpha: wgpu::BlendComponent::REPLACE })
}

/// Depth writes with test Less: every opaque draw but built-in's additive ones.
const DEPTH_WRITE_LESS: (bool, wgpu::CompareFunction) = (true, wgpu::CompareFunction::Less);

/// Every render pipeline compiled so far, by what it compiles in, and the layouts they share.
pub(in crate::render) struct PipelineCache {
    /// Groups 0–2 of the scene passes (frame, object, screen).
    pub(in crate::render) pipeline_layout: wgpu::PipelineLayout,
    /// The forward pipelines' layout with the rays' group: the subject's exact alternatives.
    pub(in crate::render) exact_layout: wgpu::PipelineLayout,
    /// The deferred lighting pass's: frame, object, G-buffer, light tiles.
    pub(in crate::render) deferred_layout: wgpu::PipelineLayout,
    /// By (pipeline, model, what else the pipeline compiles in).
    pub(in crate::render) forward: HashMap<(Pipeline, String, ForwardKey), wgpu::RenderPipeline>,
    /// By (pipeline, model, textured subject, faces drawn, terms).
    pub(in crate::render) gbuffer: HashMap<(Pipeline, String, bool, RenderFace, u32), wgpu::RenderPipeline>,
    /// Keyed by pipeline, model, role, terms, the legacy lighting whose data it lights (0: none) and
    /// the light loop's optional paths.
    pub(in crate::render) lighting:
        HashMap<(Pipeline, String, u32, u32, u32, crate::plan::lights::LightPaths), wgpu::RenderPipeline>,
    /// The depth-normal prepass pipelines, by (pipeline, textured subject, faces drawn).
    pub(in crate::render) depth_normals: HashMap<(Pipeline, bool, RenderFace), wgpu::RenderPipeline>,
    /// By (sample count, terms).
    pub(in crate::render) background: HashMap<(u32, u32), wgpu::RenderPipeline>,
    /// The `TERMS` mask (pipelines::terms) of the frame being encoded: every light term but while
    /// a cell's term layers are drawn. The passes look their pipelines up with it.
    pub(in crate::render) terms: u32,
}

impl PipelineCache {
    pub(in crate::render) fn new(
        pipeline_layout: wgpu::PipelineLayout,
        exact_layout: wgpu::PipelineLayout,
        deferred_layout: wgpu::PipelineLayout,
    ) -> PipelineCache {
        PipelineCache {
            pipeline_layout,
            exact_layout,
            deferred_layout,
            forward: HashMap::new(),
            gbuffer: HashMap::new(),
            lighting: HashMap::new(),
            depth_normals: HashMap::new(),
            background: HashMap::new(),
            terms: crate::pipelines::terms::LIGHT,
        }
    }

    /// The forward pipelines of `model` drawn with `key` on each of `faces`.
    pub(in crate::render) fn forward_by_face(
        &self,
        pipeline: Pipeline,
        model: &str,
        key: ForwardKey,
        faces: &[RenderFace],
    ) -> ByFace<'_> {
        let mut out: ByFace = [None; 3];
        for &face in faces {
            out[face as usize] = Some(&self.forward[&(pipeline, model.to_string(), ForwardKey { face, ..key })]);
        }
        out
    }

    /// Number of forward and background pipelines compiled so far.
    pub(in crate::render) fn compiled(&self) -> usize {
        self.forward.len() + self.background.len()
    }
}

/// The override constants every pass drawing scene meshes sets: the pipeline's conventions, a
/// textured subject, the model's LOD dither.
fn mesh_constants(pipeline: Pipeline, model: &ShaderModel, textured: bool) -> [(&'static str, f64); 3] {
    [
        ("PIPELINE", pipeline.shader_id() as f64),
        ("TEXTURED", textured as u32 as f64),
        ("LOD_DITHER", CrossFade::of(pipeline, model).shader_value() as f64),
    ]
}

/// Which of built-in's forward passes a forward pipeline draws (shaders/pass/forward.wgsl
/// `FORWARD_PASS`, plan::draws).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(in crate::render) enum ForwardPass {
    /// Every per-pixel light in one draw.
    All,
    /// ForwardBase: the main directional light, ambient, vertex lights, emission.
    Base,
    /// ForwardAdd: one light, blended One One, depth LEqual without writes.
    Add,
}

/// What a forward pipeline compiles in besides its pipeline and model: built-in's vertex-lit
/// path, the sample count, a textured subject, the study's exact alternatives, the forward pass
/// and whether lights other than the main one cast shadows on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(in crate::render) struct ForwardKey {
    pub(in crate::render) vertex_lit: bool,
    pub(in crate::render) samples: u32,
    pub(in crate::render) textured: bool,
    pub(in crate::render) exact: crate::plan::exact::ExactAlternatives,
    pub(in crate::render) pass: ForwardPass,
    pub(in crate::render) additional_shadows: bool,
    /// The drawn surface type: the subject's (fixed objects are opaque).
    pub(in crate::render) surface: SurfaceType,
    /// The faces drawn (the mesh's `render_face`).
    pub(in crate::render) face: RenderFace,
    /// The `TERMS` mask drawn (pipelines::terms): every light term for the image.
    pub(in crate::render) terms: u32,
    /// The alpha test resolves by alpha-to-coverage (`plan::draws::alpha_to_coverage`).
    pub(in crate::render) alpha_to_coverage: bool,
    /// How the drawn object's shader reads the frame's SSAO (`plan::ao::OcclusionRead`): not at
    /// all where the frame has none or the shader compiles none, so the load is compiled out.
    pub(in crate::render) occlusion: crate::plan::ao::OcclusionRead,
    /// The light loop's optional paths compiled in (`CellPlan::light_paths`).
    pub(in crate::render) lights: crate::plan::lights::LightPaths,
    /// HDRP's split diffuse lighting of a Subsurface Scattering subject (forward.wgsl
    /// `fs_subsurface`, passes::subsurface): the SSS buffers as targets, over the subject's depth.
    pub(in crate::render) subsurface: bool,
}

impl ForwardKey {
    /// One sample, per-pixel lights in one draw, no exact alternatives (probe captures).
    pub(in crate::render) fn plain(textured: bool, face: RenderFace) -> ForwardKey {
        ForwardKey {
            vertex_lit: false,
            samples: 1,
            textured,
            exact: Default::default(),
            pass: ForwardPass::All,
            additional_shadows: true,
            surface: SurfaceType::Opaque,
            face,
            terms: crate::pipelines::terms::LIGHT,
            alpha_to_coverage: false,
            occlusion: crate::plan::ao::OcclusionRead::None,
            lights: crate::plan::lights::LightPaths::ALL,
            subsurface: false,
        }
    }
}

impl PipelineCache {
    /// The forward pipeline of a model; `vertex_lit`: built-in's legacy vertex-lit path, which
    /// evaluates the lighting at the vertices (Gouraud) with its own light list; `textured`: the
    /// subject wears material maps (a flat subject's pipeline compiles the sampling away);
    /// `exact`: the approximation study's exact alternatives (plan::exact), with the rays' group.
    pub(in crate::render) fn forward_pipeline(
        &mut self,
        gpu: &GpuContext,
        pipeline: Pipeline,
        model: &ShaderModel,
        key: ForwardKey,
    ) -> Result<(), Error> {
        let ForwardKey {
            vertex_lit,
            samples,
            textured,
            exact,
            pass: forward_pass,
            additional_shadows,
            surface,
            face,
            terms,
            alpha_to_coverage,
            occlusion,
            lights,
            subsurface,
        } = key;
        let key = (pipeline, model.name.to_string(), key);
        if self.forward.contains_key(&key) {
            return Ok(());
        }
        let per_vertex = model.per_vertex || vertex_lit;
        let pass = if exact.any() { wgsl::PassKind::ForwardExact } else { wgsl::PassKind::Forward };
        let source = wgsl::compose(pass, Some(model));
        let module = gpu.shader_module(&format!("forward {}/{}", pipeline.name(), model.name), &source)?;
        let mut constants = mesh_constants(pipeline, model, textured).to_vec();
        constants.extend([
            ("MAIN_LIGHT_ONLY", model.main_light_only as u32 as f64),
            ("VERTEX_LIT", vertex_lit as u32 as f64),
            ("FORWARD_PASS", forward_pass as u32 as f64),
            ("FIXED_FUNCTION", (vertex_lit && model.passes.vertex_lit_fallback) as u32 as f64),
            ("ADDITIONAL_SHADOWS", additional_shadows as u32 as f64),
            ("SURFACE", surface.shader_id() as f64),
            ("TERMS", terms as f64),
            ("ALPHA_TO_COVERAGE", alpha_to_coverage as u32 as f64),
            ("SCREEN_OCCLUSION", occlusion.shader_id() as f64),
            ("AREA_LIGHTS", lights.area as u32 as f64),
            ("HDRP_LIGHT_TERMS", lights.hdrp_terms as u32 as f64),
            ("HDRP_PCSS", lights.pcss as u32 as f64),
            ("SUBSURFACE_PRE_SCATTER", subsurface as u32 as f64),
        ]);
        if exact.any() {
            constants.extend(exact.constants());
        }
        let entries = match (per_vertex, subsurface) {
            (true, _) => ("vs_gouraud", "fs_gouraud"),
            (false, true) => ("vs_main", "fs_subsurface"),
            (false, false) => ("vs_main", "fs_main"),
        };
        let label = format!("forward {}/{}", pipeline.name(), model.name);
        let additive = forward_pass == ForwardPass::Add;
        // ForwardAdd blends `[_SrcBlend] One` onto the base pass's colour and keeps its role; a
        // transparent surface blends as its type says and marks its pixels the subject's.
        let blend = if additive { surface.forward_add_blend() } else { surface.blend() };
        let targets = [
            Some(wgpu::ColorTargetState {
                format: HDR_FORMAT,
                blend: blend_state(blend),
                write_mask: if blend == Blend::Replace { wgpu::ColorWrites::ALL } else { wgpu::ColorWrites::COLOR },
            }),
            Some(wgpu::ColorTargetState {
                format: ROLE_FORMAT,
                blend: None,
                write_mask: if additive { wgpu::ColorWrites::empty() } else { wgpu::ColorWrites::ALL },
            }),
        ];
        // The SSS lighting buffer and the SSS buffer, written whole.
        let sss_targets = [HDR_FORMAT, HDR_FORMAT]
            .map(|format| Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL }));
        let targets = if subsurface { &sss_targets[..] } else { &targets[..] };
        let layout = if exact.any() { &self.exact_layout } else { &self.pipeline_layout };
        // Additive passes, the Transparent queue and the split lighting over the subject's own
        // depth test LEqual without writing depth (ZWrite Off).
        let depth = if additive || surface.is_transparent() || subsurface {
            (false, wgpu::CompareFunction::LessEqual)
        } else {
            DEPTH_WRITE_LESS
        };
        let cull = face.culled();
        let multisample = wgpu::MultisampleState {
            count: samples,
            alpha_to_coverage_enabled: alpha_to_coverage,
            ..Default::default()
        };
        let p =
            Self::mesh_pipeline(gpu, &label, layout, &module, entries, &constants, targets, (multisample, depth, cull));
        gpu.check_errors("creating a forward pipeline")?;
        self.forward.insert(key, p);
        Ok(())
    }

    /// A pipeline that draws scene meshes, culling `cull_mode` (the mesh's render face), with the
    /// depth state given.
    #[allow(clippy::too_many_arguments)]
    pub(in crate::render) fn mesh_pipeline(
        gpu: &GpuContext,
        label: &str,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        (vs, fs): (&str, &str),
        constants: &[(&str, f64)],
        targets: &[Option<wgpu::ColorTargetState>],
        (multisample, (depth_write, depth_compare), cull_mode): (
            wgpu::MultisampleState,
            (bool, wgpu::CompareFunction),
            Option<wgpu::Face>,
        ),
    ) -> wgpu::RenderPipeline {
        let options = wgpu::PipelineCompilationOptions { constants, ..Default::default() };
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(vs),
                compilation_options: options.clone(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x2],
                })],
            },
            primitive: wgpu::PrimitiveState { cull_mode, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(depth_write),
                depth_compare: Some(depth_compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample,
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
    pub(in crate::render) fn gbuffer_pipeline(
        &mut self,
        gpu: &GpuContext,
        pipeline: Pipeline,
        model: &ShaderModel,
        textured: bool,
        face: RenderFace,
    ) -> Result<(), Error> {
        let key = (pipeline, model.name.to_string(), textured, face, self.terms);
        if self.gbuffer.contains_key(&key) {
            return Ok(());
        }
        let source = wgsl::compose(wgsl::PassKind::Forward, Some(model));
        let module = gpu.shader_module(&format!("gbuffer {}/{}", pipeline.name(), model.name), &source)?;
        let mut constants = mesh_constants(pipeline, model, textured).to_vec();
        constants.push(("TERMS", self.terms as f64));
        let targets = [
            Some(crate::render::gbuffer::GB_ALBEDO.into()),
            Some(crate::render::gbuffer::GB_MATERIAL.into()),
            Some(crate::render::gbuffer::normal_format(pipeline).into()),
            Some(crate::render::gbuffer::GB_LIGHTING.into()),
            Some(ROLE_FORMAT.into()),
            Some(crate::render::gbuffer::GB_SHADOW_MASK.into()),
        ];
        let label = format!("gbuffer {}/{}", pipeline.name(), model.name);
        let p = Self::mesh_pipeline(
            gpu,
            &label,
            &self.pipeline_layout,
            &module,
            ("vs_main", "fs_gbuffer"),
            &constants,
            &targets,
            (wgpu::MultisampleState::default(), DEPTH_WRITE_LESS, face.culled()),
        );
        gpu.check_errors("creating a G-buffer pipeline")?;
        self.gbuffer.insert(key, p);
        Ok(())
    }

    /// HDRP's depth prepass with its normal buffer (fs_depth_normals), composed with the fixed
    /// objects' model: the pass reads no model.
    pub(in crate::render) fn depth_normal_pipeline(
        &mut self,
        gpu: &GpuContext,
        pipeline: Pipeline,
        model: &ShaderModel,
        textured: bool,
        face: RenderFace,
    ) -> Result<(), Error> {
        let key = (pipeline, textured, face);
        if self.depth_normals.contains_key(&key) {
            return Ok(());
        }
        let source = wgsl::compose(wgsl::PassKind::Forward, Some(model));
        let module = gpu.shader_module(&format!("depth prepass {}", pipeline.name()), &source)?;
        let constants = mesh_constants(pipeline, model, textured);
        let targets = [Some(crate::render::formats::NORMAL_FORMAT.into())];
        let label = format!("depth prepass {}", pipeline.name());
        let p = Self::mesh_pipeline(
            gpu,
            &label,
            &self.pipeline_layout,
            &module,
            ("vs_main", "fs_depth_normals"),
            &constants,
            &targets,
            (wgpu::MultisampleState::default(), DEPTH_WRITE_LESS, face.culled()),
        );
        gpu.check_errors("creating the depth prepass pipeline")?;
        self.depth_normals.insert(key, p);
        Ok(())
    }

    /// The deferred lighting pipeline shading the pixels of `role` with `model`; `legacy`: the
    /// built-in lighting function whose UnityStandardData those pixels hold (forward.wgsl
    /// `LEGACY_DEFERRED`).
    pub(in crate::render) fn lighting_pipeline(
        &mut self,
        gpu: &GpuContext,
        pipeline: Pipeline,
        model: &ShaderModel,
        (role, legacy, lights): (u8, Option<crate::shading::registry::LegacyLighting>, crate::plan::lights::LightPaths),
    ) -> Result<(), Error> {
        let legacy = legacy.map_or(0, |l| l.shader_value());
        let key = (pipeline, model.name.to_string(), role as u32, self.terms, legacy, lights);
        if self.lighting.contains_key(&key) {
            return Ok(());
        }
        let source = wgsl::compose(wgsl::PassKind::Forward, Some(model));
        let module = gpu.shader_module(&format!("deferred {}/{}", pipeline.name(), model.name), &source)?;
        let constants = [
            ("PIPELINE", pipeline.shader_id() as f64),
            ("DEFERRED_ROLE", role as f64),
            ("TILED_LIGHTS", pipeline.tiled_light_loop() as u32 as f64),
            ("TERMS", self.terms as f64),
            ("LEGACY_DEFERRED", legacy as f64),
            ("AREA_LIGHTS", lights.area as u32 as f64),
            ("HDRP_LIGHT_TERMS", lights.hdrp_terms as u32 as f64),
            ("HDRP_PCSS", lights.pcss as u32 as f64),
        ];
        let options = wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() };
        let p = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
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
        gpu.check_errors("creating a deferred lighting pipeline")?;
        self.lighting.insert(key, p);
        Ok(())
    }

    /// The environment background (passes::background), per sample count.
    pub(in crate::render) fn background_pipeline(&mut self, gpu: &GpuContext, samples: u32) -> Result<(), Error> {
        let key = (samples, self.terms);
        if self.background.contains_key(&key) {
            return Ok(());
        }
        let constants = [("TERMS", self.terms as f64)];
        let options = wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() };
        let source = wgsl::compose(wgsl::PassKind::Background, None);
        let module = gpu.shader_module("background", &source)?;
        let p = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("background"),
            layout: Some(&self.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_background"),
                compilation_options: options.clone(),
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
                compilation_options: options,
                targets: &[Some(HDR_FORMAT.into()), Some(ROLE_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        gpu.check_errors("creating the background pipeline")?;
        self.background.insert(key, p);
        Ok(())
    }
}
