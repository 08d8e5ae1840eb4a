//! The frame plan of a composition: which passes and resources a scene needs, and what was left
//! out because it cannot change the image.

use serde::Serialize;

pub mod camera;
pub mod cell;
pub mod draws;
pub mod exact;
pub mod gi;
pub mod lights;
pub mod lod;
pub mod roles;
pub mod shadows;
pub mod timing;

use crate::declarations::scene::{Reflections, Scene, Sky};

#[derive(Debug, Clone, Serialize)]
pub struct FramePlan {
    /// Passes in order.
    pub passes: Vec<&'static str>,
    /// Whether the environment background pass is drawn.
    pub background: bool,
    /// (what, why) for everything left out.
    pub left_out: Vec<(String, String)>,
    /// Whether HDRP cells bloom (`[hdrp] bloom`, on by default as HDRP's default volume).
    pub hdrp_bloom: bool,
    /// Whether HDRP cells render screen-space ambient occlusion (`[hdrp] ssao`, on by default).
    pub hdrp_ssao: bool,
}

/// HDRP's bloom, after the frame's passes (render::passes::bloom).
pub const BLOOM_PASS: &str = "bloom";

/// HDRP's depth prepass with its normal buffer, and the SSAO it feeds (render::passes::ssao), before the
/// lighting that reads the occlusion.
pub const DEPTH_PREPASS: &str = "depth prepass";
pub const SSAO_PASS: &str = "ssao";

/// Reflection probes: each renders the scene into six faces, then the faces are prefiltered; once
/// per set of inputs a capture sees (a later cell with the same lights reuses it).
pub const PROBE_CAPTURE_PASS: &str = "probe capture";
pub const PROBE_PREFILTER_PASS: &str = "probe prefilter";

/// The vertex-lit path's one pass.
const VERTEX_LIT_PASS: &str = "forward (lighting per vertex)";
/// The deferred path's forward pass for the models the G-buffer cannot carry.
const FORWARD_ONLY_PASS: &str = "forward (models the G-buffer cannot carry)";
/// A deferred path's Transparent queue, drawn forward after everything else (pipelines::surface).
pub const TRANSPARENT_PASS: &str = "transparent";

impl FramePlan {
    /// The passes of a frame on `path`: forward draws every object lit in one pass; deferred fills
    /// the G-buffer, lights it in screen space, then draws forward what the G-buffer cannot carry
    /// (per-vertex and ForwardBase-only models) with the background.
    pub fn passes_for(
        &self,
        path: crate::pipelines::RenderPath,
        pipeline: crate::pipelines::Pipeline,
        transparent_subject: bool,
    ) -> Vec<&'static str> {
        let mut passes: Vec<&'static str> = Vec::new();
        for probe_pass in [PROBE_CAPTURE_PASS, PROBE_PREFILTER_PASS] {
            if self.passes.contains(&probe_pass) {
                passes.push(probe_pass);
            }
        }
        if self.passes.contains(&"shadow") && path != crate::pipelines::RenderPath::VertexLit {
            passes.push("shadow");
        }
        if self.occludes(path, pipeline) {
            passes.extend([DEPTH_PREPASS, SSAO_PASS]);
        }
        match path {
            crate::pipelines::RenderPath::Forward => passes.push("forward"),
            crate::pipelines::RenderPath::VertexLit => passes.push(VERTEX_LIT_PASS),
            crate::pipelines::RenderPath::Deferred => {
                passes.push("gbuffer");
                if pipeline.tiled_light_loop() {
                    passes.push("light tiles");
                }
                passes.extend(["deferred lighting", FORWARD_ONLY_PASS])
            }
        }
        if self.background {
            passes.push("background");
        }
        // The engines cannot put a transparent surface in a G-buffer: its own forward pass after
        // the sky.
        if path == crate::pipelines::RenderPath::Deferred && transparent_subject {
            passes.push(TRANSPARENT_PASS);
        }
        if pipeline == crate::pipelines::Pipeline::Hdrp && self.hdrp_bloom {
            passes.push(BLOOM_PASS);
        }
        passes
    }

    /// Whether a frame on `path` in `pipeline` renders SSAO: HDRP's, where the scene keeps it on
    /// (HDRP has no vertex-lit path to leave it out of).
    pub fn occludes(&self, path: crate::pipelines::RenderPath, pipeline: crate::pipelines::Pipeline) -> bool {
        pipeline == crate::pipelines::Pipeline::Hdrp
            && self.hdrp_ssao
            && path != crate::pipelines::RenderPath::VertexLit
    }

    /// The pass that writes the final colour of a pixel showing `role` (None: no object) on
    /// `path`, in the names of `passes_for`; `forward_only`: the object's model cannot be drawn
    /// into a G-buffer.
    pub fn pass_writing(
        &self,
        path: crate::pipelines::RenderPath,
        role: Option<crate::declarations::scene::Role>,
        forward_only: bool,
    ) -> &'static str {
        use crate::pipelines::RenderPath;
        match (role, path) {
            (None, _) if self.background => "background",
            (None, _) => "clear (no background pass)",
            (Some(_), RenderPath::Forward) => "forward",
            (Some(_), RenderPath::VertexLit) => VERTEX_LIT_PASS,
            (Some(_), RenderPath::Deferred) if forward_only => FORWARD_ONLY_PASS,
            (Some(_), RenderPath::Deferred) => "deferred lighting",
        }
    }

    pub fn for_scene(scene: &Scene) -> FramePlan {
        let mut passes = vec!["forward"];
        let mut left_out = Vec::new();
        let background = scene.environment.background;
        if background {
            passes.push("background");
        } else {
            left_out.push((
                "background pass".into(),
                "environment.background = false: the clear colour (black) shows".into(),
            ));
        }
        if matches!(scene.environment.sky, Sky::Constant { .. }) {
            left_out.push(("probe prefiltering".into(), "constant sky: every roughness sees the same colour".into()));
        }
        match scene.shadow_pass_needed() {
            Ok(()) => passes.insert(0, "shadow"),
            Err(why) => left_out.push(("shadow pass".into(), why)),
        }
        match (scene.environment.reflections, scene.probes.len()) {
            (Reflections::Probe, n) if n > 0 => {
                passes.splice(0..0, [PROBE_CAPTURE_PASS, PROBE_PREFILTER_PASS]);
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
        FramePlan { passes, background, left_out, hdrp_bloom, hdrp_ssao }
    }
}

/// A shadowed light's map in a cell: its resolution, and why it differs from the pipeline's default.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShadowMapUse {
    /// Index into the scene's lights.
    pub light: usize,
    /// Texels per side (per cube face for a point light).
    pub resolution: u32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}
