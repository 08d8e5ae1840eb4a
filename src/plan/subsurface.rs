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

/// HDRP's SSS_PIXELS_PER_SAMPLE: the filter takes one sample per four pixels of its disc.
pub const PIXELS_PER_SAMPLE: f64 = 4.0;

impl SubsurfacePlan {
    /// The samples the filter takes at a pixel `depth` metres deep in a frame `height` pixels
    /// tall through a `fov_y_deg` lens: ⌊π(filterRadius·pixelsPerMm)²/4⌋ up to the budget, with
    /// pixelsPerMm = 1 / (max(10⁻⁴, the pixel's view-space width) · 1000 · worldScale / mask)
    /// (SubsurfaceScattering.compute); 0 with mask 0.
    pub fn samples_at(&self, fov_y_deg: f64, height: u32, depth: f64) -> u32 {
        if self.mask <= 0.0 {
            return 0;
        }
        let units_per_pixel = (2.0 * (fov_y_deg.to_radians() * 0.5).tan() / height as f64 * depth).max(1e-4);
        let pixels_per_mm = 1.0 / (units_per_pixel * 1000.0 * self.profile.world_scale / self.mask);
        let area = std::f64::consts::PI * (self.profile.filter_radius * pixels_per_mm).powi(2);
        ((area / PIXELS_PER_SAMPLE) as u32).min(self.sample_budget)
    }

    /// Why the filter can change nothing in a frame whose subject is nowhere nearer than `depth`
    /// metres (a pixel's width only grows with depth, so its nearest point takes the most
    /// samples): with no sample anywhere every pixel keeps √albedo·√albedo·E, the unsplit image.
    pub fn left_out_because(&self, fov_y_deg: f64, height: u32, depth: f64) -> Option<String> {
        if self.mask <= 0.0 {
            return Some("subsurface_mask 0: the filter's distance scale is 0, so every pixel keeps its light (√albedo·√albedo = albedo); drawn unsplit".to_string());
        }
        (self.samples_at(fov_y_deg, height, depth) == 0).then(|| {
            let pixel_mm = (2.0 * (fov_y_deg.to_radians() * 0.5).tan() / height as f64 * depth).max(1e-4) * 1000.0;
            format!(
                "the filter takes no sample: at the subject's nearest point ({depth:.3} m) a pixel spans {pixel_mm:.2} mm \
                 (× world scale / mask), so π·({:.2} mm filter radius in pixels)²/{PIXELS_PER_SAMPLE} < 1; drawn unsplit, \
                 the same image",
                self.profile.filter_radius
            )
        })
    }
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

    #[test]
    fn the_filter_is_left_out_where_it_takes_no_sample() {
        let mut plan = SubsurfacePlan {
            profile: DiffusionProfile::hdrp_default(),
            mask: 1.0,
            sample_budget: SAMPLE_BUDGET_MEDIUM,
        };
        // The default room's sphere from 5.4 m at 192 px: a pixel spans 21 mm, 8.28 mm of filter
        // is 0.4 px, π·0.4²/4 < 1.
        assert_eq!(plan.samples_at(42.0, 192, 5.4), 0);
        assert!(plan.left_out_because(42.0, 192, 5.4).unwrap().contains("no sample"));
        // A 2 cm bead from 3.5 cm at 384 px: a pixel spans 0.07 mm, the budget caps the count.
        assert_eq!(plan.samples_at(40.0, 384, 0.035), SAMPLE_BUDGET_MEDIUM);
        assert_eq!(plan.left_out_because(40.0, 384, 0.035), None);
        // More pixels or a nearer subject take more samples, never fewer.
        let counts: Vec<u32> = [4.0, 2.0, 1.0, 0.5, 0.25].iter().map(|d| plan.samples_at(40.0, 512, *d)).collect();
        assert!(counts.windows(2).all(|w| w[0] <= w[1]), "{counts:?}");
        plan.mask = 0.0;
        assert!(plan.left_out_because(40.0, 384, 0.035).unwrap().contains("subsurface_mask 0"));
    }
}
