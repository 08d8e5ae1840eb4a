//! The frame plan of a composition: which passes and resources a scene needs, and what was left
//! out because it cannot change the image.

use serde::Serialize;

pub mod ao;
pub mod camera;
pub mod cell;
pub mod draws;
pub mod exact;
pub mod gi;
pub mod light_terms;
pub mod lights;
pub mod lod;
pub mod pass;
pub mod probes;
pub mod roles;
pub mod shadows;
pub mod subsurface;
pub mod timing;

pub use pass::Pass;
use pass::{frame_passes, PassInputs};

use crate::declarations::scene::{Reflections, Role, Scene, Sky};
use crate::pipelines::{Pipeline, RenderPath};

#[derive(Debug, Clone, Serialize)]
pub struct FramePlan {
    /// The passes the composition's frames can draw, in order (a cell's plan narrows them to its
    /// path: `CellPlan::passes`).
    pub passes: Vec<Pass>,
    /// Whether the environment background is drawn (by the forward or forward-only pass).
    pub background: bool,
    /// (what, why) for everything left out.
    pub left_out: Vec<(String, String)>,
    /// Whether HDRP cells bloom (`[hdrp] bloom`, on by default as HDRP's default volume).
    pub hdrp_bloom: bool,
    /// Whether HDRP cells render screen-space ambient occlusion (`[hdrp] ssao`, on by default).
    pub hdrp_ssao: bool,
    /// The engine settings the composition's cells render with (the shadow array is as large as
    /// the largest map they ask for); none: the engines' defaults.
    #[serde(skip)]
    pub engines: Vec<crate::pipelines::settings::PipelineSettings>,
}

impl FramePlan {
    /// Whether the composition's frames draw shadow maps at all.
    pub fn shadows(&self) -> bool {
        self.passes.contains(&Pass::Shadow)
    }

    /// Whether the composition's reflection probes are captured.
    pub fn probes(&self) -> bool {
        self.passes.contains(&Pass::ProbeCapture)
    }

    /// The passes of a frame on `path` in `pipeline` (`pass::frame_passes`) where every shadow the
    /// composition asks for is drawn and no visibility is traced.
    pub fn passes_for(
        &self,
        path: RenderPath,
        pipeline: Pipeline,
        engine: &crate::pipelines::settings::PipelineSettings,
        transparent_queue: bool,
    ) -> Vec<Pass> {
        frame_passes(PassInputs {
            pipeline,
            path,
            probes: self.probes(),
            shadow_maps: self.shadows(),
            ssao: self.occludes(path, pipeline, engine),
            transparent_queue,
            traced_visibility: false,
            bloom: self.hdrp_bloom && engine.hdrp.bloom,
            subsurface: false,
        })
    }

    /// The SSAO a frame on `path` in `pipeline` with `engine`'s settings renders (`ao::ambient_occlusion`):
    /// HDRP's where the scene keeps it on, URP's where the asset's renderer has the feature.
    pub fn occludes(
        &self,
        path: RenderPath,
        pipeline: Pipeline,
        engine: &crate::pipelines::settings::PipelineSettings,
    ) -> Option<ao::SsaoMethod> {
        let opaque = crate::pipelines::surface::SurfaceType::Opaque;
        let model = pipeline.fixed_object_shader();
        let ao = ao::ambient_occlusion(pipeline, path, engine, (model, opaque), self.hdrp_ssao && engine.hdrp.ssao);
        ao.ssao.then_some(ao.method)
    }

    /// The pass that writes the final colour of a pixel showing `role` (None: no object) on
    /// `path`; `forward_only`: the object's model cannot be drawn into a G-buffer; `transparent`:
    /// the object is in the Transparent queue. None: nothing draws the pixel (the clear colour).
    pub fn pass_writing(
        &self,
        path: RenderPath,
        role: Option<Role>,
        forward_only: bool,
        transparent: bool,
    ) -> Option<Pass> {
        Some(match (role, path) {
            (None, _) if !self.background => return None,
            (_, RenderPath::Forward) => Pass::Forward,
            (_, RenderPath::VertexLit) => Pass::VertexLit,
            (Some(_), RenderPath::Deferred) if transparent => Pass::Transparent,
            (None, RenderPath::Deferred) => Pass::ForwardOnly,
            (Some(_), RenderPath::Deferred) if forward_only => Pass::ForwardOnly,
            (Some(_), RenderPath::Deferred) => Pass::DeferredLighting,
        })
    }

    pub fn for_scene(scene: &Scene) -> FramePlan {
        let mut passes = vec![Pass::Forward];
        let mut left_out = Vec::new();
        let background = scene.environment.background;
        if !background {
            left_out.push((
                "background pass".into(),
                "environment.background = false: the clear colour (black) shows".into(),
            ));
        }
        if matches!(scene.environment.sky, Sky::Constant { .. }) {
            left_out.push(("probe prefiltering".into(), "constant sky: every roughness sees the same colour".into()));
        }
        match scene.shadow_pass_needed() {
            Ok(()) => passes.insert(0, Pass::Shadow),
            Err(why) => left_out.push(("shadow pass".into(), why)),
        }
        match (scene.environment.reflections, scene.probes.len()) {
            (Reflections::Probe, n) if n > 0 => {
                passes.splice(0..0, [Pass::ProbeCapture, Pass::ProbePrefilter]);
            }
            (Reflections::Sky, n) if n > 0 => left_out.push((
                "reflection probes".into(),
                format!("environment.reflections = \"sky\": the scene's {n} probe(s) are not captured"),
            )),
            _ => left_out.push(("reflection probes".into(), "reflections come from the sky".into())),
        }
        let hdrp_bloom = scene.hdrp.bloom;
        if !hdrp_bloom {
            left_out.push(("HDRP bloom".into(), "[hdrp] bloom = false".into()));
        }
        let hdrp_ssao = scene.hdrp.ssao;
        if !hdrp_ssao {
            left_out.push(("HDRP SSAO and its depth prepass".into(), "[hdrp] ssao = false".into()));
        }
        FramePlan { passes, background, left_out, hdrp_bloom, hdrp_ssao, engines: Vec::new() }
    }

    /// The plan for cells rendering with `engines` (each distinct setting once).
    pub fn with_engines(mut self, engines: &[crate::pipelines::settings::PipelineSettings]) -> FramePlan {
        for e in engines {
            if !self.engines.contains(e) {
                self.engines.push(*e);
            }
        }
        self
    }
}

/// A shadowed light's map in a cell: its resolution, why it differs from the pipeline's default,
/// and how the frame reads it (filter and biases).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShadowMapUse {
    /// Index into the scene's lights.
    pub light: usize,
    /// Texels per side (per cube face for a point light).
    pub resolution: u32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub style: Option<shadows::ShadowStyle>,
}
