//! HDRP's screen-space subsurface scattering for the Subsurface Scattering material type: where a
//! cell's frame splits the subject's lighting and filters its diffuse part
//! (HDRenderPipeline.SubsurfaceScattering.cs, SubsurfaceScattering.compute), with what.
//!
//! HDRP splits the lighting of an opaque Lit surface whose material features hold
//! MATERIALFEATUREFLAGS_LIT_SUBSURFACE_SCATTERING (ShaderPassForward.hlsl OUTPUT_SPLIT_LIGHTING,
//! ShouldOutputSplitLighting): its specular stays in the colour, its diffuse (with the emission,
//! PostEvaluateBSDF) goes to the SSS lighting buffer, which the filter blurs and adds back. A
//! transparent surface has no split lighting (no SSS in the Transparent queue), so its type draws
//! unfiltered; the others' cells have no such pass.

use crate::pipelines::surface::SurfaceType;
use crate::pipelines::Pipeline;
use crate::shading::diffusion_profile::DiffusionProfile;
use crate::shading::ShaderModel;

/// The sample budget of HDRP's Medium quality level, the default frame settings' (HDRP's
/// DefaultSssSampleBudgetForQualityLevel: Low 20, Medium 40, High 80).
pub const SAMPLE_BUDGET_MEDIUM: u32 = 40;

/// The parameter that selects the Subsurface Scattering material type, and its mask.
pub const SUBSURFACE_PARAM: &str = "subsurface_scattering";
pub const MASK_PARAM: &str = "subsurface_mask";

/// What the filter runs with for a cell's subject.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubsurfacePlan {
    /// The default diffusion profile (the only one a material here has).
    pub profile: DiffusionProfile,
    /// The subject's `_SubsurfaceMask`: the filter's distance scale (0 leaves the light unblurred).
    pub mask: f64,
    pub sample_budget: u32,
}

/// Whether the cell's frame runs the filter, and with what: HDRP's Lit with the Subsurface
/// Scattering type on an opaque or cut-out surface.
pub fn subsurface(
    pipeline: Pipeline,
    model: &ShaderModel,
    params: &[f64; crate::shading::twin::PARAM_SLOTS],
    surface: SurfaceType,
) -> Option<SubsurfacePlan> {
    let param = |name: &str| model.params.iter().find(|p| p.name == name).map(|p| params[p.slot]);
    let on = pipeline == Pipeline::Hdrp && param(SUBSURFACE_PARAM).is_some_and(|v| v > 0.5);
    (on && !surface.is_transparent()).then(|| SubsurfacePlan {
        profile: DiffusionProfile::hdrp_default(),
        mask: param(MASK_PARAM).unwrap_or(1.0),
        sample_budget: SAMPLE_BUDGET_MEDIUM,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::twin::{PARAM_SLOTS, SUBSURFACE_MASK_SLOT, SUBSURFACE_SLOT};
    use crate::shading::Registry;

    #[test]
    fn hdrps_opaque_subsurface_type_runs_the_filter_and_nothing_else_does() {
        let r = Registry::builtin();
        let hdrp = r.find(Pipeline::Hdrp, "lit").unwrap();
        let mut params = [0.0; PARAM_SLOTS];
        assert_eq!(subsurface(Pipeline::Hdrp, hdrp, &params, SurfaceType::Opaque), None, "the type is off");
        params[SUBSURFACE_SLOT] = 1.0;
        params[SUBSURFACE_MASK_SLOT] = 0.5;
        let plan = subsurface(Pipeline::Hdrp, hdrp, &params, SurfaceType::Opaque).unwrap();
        assert_eq!((plan.mask, plan.sample_budget), (0.5, 40));
        assert_eq!(plan.profile, DiffusionProfile::hdrp_default());
        assert!(subsurface(Pipeline::Hdrp, hdrp, &params, SurfaceType::Cutout).is_some());
        assert_eq!(subsurface(Pipeline::Hdrp, hdrp, &params, SurfaceType::Transparent), None, "no split lighting");
        let urp = r.find(Pipeline::Urp, "lit").unwrap();
        assert_eq!(subsurface(Pipeline::Urp, urp, &params, SurfaceType::Opaque), None);
    }
}
