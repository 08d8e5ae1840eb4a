//! The passes of a frame as one typed list: what a cell's plan says it draws, what the frame loop
//! (`render::frame`) runs in that order, and what its timings are keyed by. A pass's name exists
//! here and nowhere else.

use crate::pipelines::{Pipeline, RenderPath};

/// One pass of a cell's frame, or of the work its frames read that runs once per set of inputs
/// (the probe captures). Each is one timed span.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Pass {
    /// Every reflection probe renders the fixed objects and the sky into its six faces; once per
    /// set of inputs a capture sees, before the frames.
    ProbeCapture,
    /// The captured faces prefiltered into the probe's roughness levels (with the capture).
    ProbePrefilter,
    /// Every shadow-casting light's layers of the shadow array, as one span.
    Shadow,
    /// The depth prepass with its normal buffer (what SSAO and traced shadows read): HDRP's, and
    /// URP's DepthNormals prepass.
    DepthPrepass,
    /// HDRP's screen-space ambient occlusion (GTAO).
    Ssao,
    /// URP's SSAO renderer feature (the Alchemy estimator and its bilateral blur).
    UrpSsao,
    /// The approximation study's exact visibility: one shadow ray per light and pixel.
    TracedShadows,
    /// The forward path: every object lit, with the background where the plan draws one.
    Forward,
    /// Built-in's legacy vertex-lit path: the forward pass lit per vertex.
    VertexLit,
    /// The deferred path's G-buffer of the objects whose model has a G-buffer pass.
    GBuffer,
    /// HDRP's tiled light list between the G-buffer and the lighting.
    LightTiles,
    /// The deferred path's screen-space lighting of the G-buffer.
    DeferredLighting,
    /// The deferred path's forward pass for the models the G-buffer cannot carry, with the
    /// background where the plan draws one.
    ForwardOnly,
    /// HDRP's split lighting of a Subsurface Scattering subject: its diffuse lighting drawn over
    /// its depth into the SSS lighting buffer, with the SSS buffer's albedo (plan::subsurface).
    SubsurfaceLighting,
    /// HDRP's screen-space subsurface scattering filter, added to the frame's colour.
    SubsurfaceScattering,
    /// A deferred path's Transparent queue, drawn forward after everything else
    /// (pipelines::surface).
    Transparent,
    /// HDRP's bloom over the finished frame.
    Bloom,
}

impl Pass {
    pub const ALL: [Pass; 17] = [
        Pass::ProbeCapture,
        Pass::ProbePrefilter,
        Pass::Shadow,
        Pass::DepthPrepass,
        Pass::Ssao,
        Pass::UrpSsao,
        Pass::TracedShadows,
        Pass::Forward,
        Pass::VertexLit,
        Pass::GBuffer,
        Pass::LightTiles,
        Pass::DeferredLighting,
        Pass::ForwardOnly,
        Pass::SubsurfaceLighting,
        Pass::SubsurfaceScattering,
        Pass::Transparent,
        Pass::Bloom,
    ];

    /// The pass's name in records, timings, tables and labels.
    pub fn name(self) -> &'static str {
        match self {
            Pass::ProbeCapture => "probe capture",
            Pass::ProbePrefilter => "probe prefilter",
            Pass::Shadow => "shadow",
            Pass::DepthPrepass => "depth prepass",
            Pass::Ssao => "ssao",
            Pass::UrpSsao => "urp ssao",
            Pass::TracedShadows => "traced shadows",
            Pass::Forward => "forward",
            Pass::VertexLit => "vertex-lit",
            Pass::GBuffer => "gbuffer",
            Pass::LightTiles => "light tiles",
            Pass::DeferredLighting => "deferred lighting",
            Pass::ForwardOnly => "forward-only",
            Pass::SubsurfaceLighting => "sss lighting",
            Pass::SubsurfaceScattering => "subsurface scattering",
            Pass::Transparent => "transparent",
            Pass::Bloom => "bloom",
        }
    }

    /// The pass a record names.
    pub fn named(name: &str) -> Option<Pass> {
        Pass::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Whether the pass runs once per set of inputs before a cell's frames rather than in each
    /// frame (its time is not part of a frame's).
    pub fn before_frames(self) -> bool {
        matches!(self, Pass::ProbeCapture | Pass::ProbePrefilter)
    }

    /// Whether the pass works on the finished image (left out of term layers, whose subject then
    /// draws its lighting whole: the layers hold each lobe before any screen-space filter).
    pub fn post(self) -> bool {
        matches!(self, Pass::Bloom | Pass::SubsurfaceLighting | Pass::SubsurfaceScattering)
    }
}

impl std::fmt::Display for Pass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for Pass {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// What decides a cell's pass list: the composition's needs and the cell's pipeline, path and
/// surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PassInputs {
    pub pipeline: Pipeline,
    pub path: RenderPath,
    /// The composition's probes are captured (`environment.reflections = "probe"`).
    pub probes: bool,
    /// Some light draws a shadow map this cell (the plan's used layers).
    pub shadow_maps: bool,
    /// The SSAO the pipeline renders on this path, if any (`FramePlan::occludes`).
    pub ssao: Option<super::ao::SsaoMethod>,
    /// Some drawn mesh is in the Transparent queue (`draws::transparent_queue`).
    pub transparent_queue: bool,
    /// The approximation study traces visibility instead of reading shadow maps.
    pub traced_visibility: bool,
    /// HDRP's bloom volume is on.
    pub bloom: bool,
    /// The subject's lighting is split and filtered (`subsurface::subsurface`).
    pub subsurface: bool,
}

/// The passes of a cell's frame, in the order they run. The probe captures come first (once per
/// set of inputs); the vertex-lit path has no shadow pass (Unity's legacy vertex-lit renders
/// none); traced visibility replaces the shadow maps and reads the prepass's depth; a deferred
/// path fills the G-buffer, lights it (HDRP through its tiled light list), then draws forward
/// what the G-buffer cannot carry; HDRP's subsurface scattering follows the opaque lighting
/// (RenderSubsurfaceScattering before the Transparent queue), the Transparent queue after that;
/// bloom last.
pub fn frame_passes(i: PassInputs) -> Vec<Pass> {
    let mut passes = Vec::new();
    if i.probes {
        passes.extend([Pass::ProbeCapture, Pass::ProbePrefilter]);
    }
    if i.shadow_maps && i.path != RenderPath::VertexLit && !i.traced_visibility {
        passes.push(Pass::Shadow);
    }
    if let Some(method) = i.ssao {
        let ssao = match method {
            super::ao::SsaoMethod::HdrpGtao => Pass::Ssao,
            super::ao::SsaoMethod::UrpAlchemy => Pass::UrpSsao,
        };
        passes.extend([Pass::DepthPrepass, ssao]);
    }
    if i.traced_visibility {
        if i.ssao.is_none() {
            passes.push(Pass::DepthPrepass);
        }
        passes.push(Pass::TracedShadows);
    }
    match i.path {
        RenderPath::Forward => passes.push(Pass::Forward),
        RenderPath::VertexLit => passes.push(Pass::VertexLit),
        RenderPath::Deferred => {
            passes.push(Pass::GBuffer);
            if i.pipeline.tiled_light_loop() {
                passes.push(Pass::LightTiles);
            }
            passes.extend([Pass::DeferredLighting, Pass::ForwardOnly]);
        }
    }
    if i.subsurface && i.pipeline == Pipeline::Hdrp && i.path != RenderPath::VertexLit {
        passes.extend([Pass::SubsurfaceLighting, Pass::SubsurfaceScattering]);
    }
    // The engines cannot put a transparent surface in a G-buffer.
    if i.path == RenderPath::Deferred && i.transparent_queue {
        passes.push(Pass::Transparent);
    }
    if i.bloom && i.pipeline == Pipeline::Hdrp {
        passes.push(Pass::Bloom);
    }
    passes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(pipeline: Pipeline, path: RenderPath) -> PassInputs {
        PassInputs {
            pipeline,
            path,
            probes: false,
            shadow_maps: true,
            ssao: None,
            transparent_queue: false,
            traced_visibility: false,
            bloom: false,
            subsurface: false,
        }
    }

    #[test]
    fn every_pass_has_its_own_name_and_is_found_by_it() {
        let mut names: Vec<&str> = Pass::ALL.iter().map(|p| p.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), Pass::ALL.len());
        for p in Pass::ALL {
            assert_eq!(Pass::named(p.name()), Some(p));
        }
    }

    #[test]
    fn each_path_runs_its_passes_in_order() {
        let f = frame_passes(inputs(Pipeline::Urp, RenderPath::Forward));
        assert_eq!(f, [Pass::Shadow, Pass::Forward]);
        let v = frame_passes(PassInputs { probes: true, ..inputs(Pipeline::Builtin, RenderPath::VertexLit) });
        assert_eq!(v, [Pass::ProbeCapture, Pass::ProbePrefilter, Pass::VertexLit], "no shadows per vertex");
        let d = frame_passes(PassInputs {
            ssao: Some(crate::plan::ao::SsaoMethod::HdrpGtao),
            bloom: true,
            transparent_queue: true,
            ..inputs(Pipeline::Hdrp, RenderPath::Deferred)
        });
        assert_eq!(
            d,
            [
                Pass::Shadow,
                Pass::DepthPrepass,
                Pass::Ssao,
                Pass::GBuffer,
                Pass::LightTiles,
                Pass::DeferredLighting,
                Pass::ForwardOnly,
                Pass::Transparent,
                Pass::Bloom
            ]
        );
        let b = frame_passes(PassInputs { bloom: true, ..inputs(Pipeline::Builtin, RenderPath::Deferred) });
        assert_eq!(b, [Pass::Shadow, Pass::GBuffer, Pass::DeferredLighting, Pass::ForwardOnly], "bloom is HDRP's");
    }

    #[test]
    fn traced_visibility_replaces_the_shadow_maps_and_reads_a_prepass() {
        let t = frame_passes(PassInputs { traced_visibility: true, ..inputs(Pipeline::Urp, RenderPath::Forward) });
        assert_eq!(t, [Pass::DepthPrepass, Pass::TracedShadows, Pass::Forward]);
        let h = frame_passes(PassInputs {
            traced_visibility: true,
            ssao: Some(crate::plan::ao::SsaoMethod::HdrpGtao),
            ..inputs(Pipeline::Hdrp, RenderPath::Forward)
        });
        assert_eq!(h, [Pass::DepthPrepass, Pass::Ssao, Pass::TracedShadows, Pass::Forward], "one prepass");
    }

    #[test]
    fn hdrps_subsurface_scattering_follows_the_opaque_lighting_and_is_hdrps_alone() {
        let sss = |pipeline, path| frame_passes(PassInputs { subsurface: true, bloom: true, ..inputs(pipeline, path) });
        assert_eq!(
            sss(Pipeline::Hdrp, RenderPath::Forward),
            [Pass::Shadow, Pass::Forward, Pass::SubsurfaceLighting, Pass::SubsurfaceScattering, Pass::Bloom]
        );
        let deferred = sss(Pipeline::Hdrp, RenderPath::Deferred);
        assert_eq!(
            deferred[deferred.len() - 4..],
            [Pass::ForwardOnly, Pass::SubsurfaceLighting, Pass::SubsurfaceScattering, Pass::Bloom]
        );
        assert!(!sss(Pipeline::Urp, RenderPath::Forward).contains(&Pass::SubsurfaceScattering));
        assert!(Pass::SubsurfaceLighting.post() && Pass::SubsurfaceScattering.post(), "term layers skip them");
    }
}
