//! The terms a cell's colour splits into, its AOVs (`[outputs] terms = true`): direct diffuse,
//! direct specular, indirect diffuse, indirect specular (reflections) and emission add up to the
//! lit frame; the occlusion layer is the factor the indirect terms were dimmed by. They are HDRP's
//! AOV lighting selections (`AOVRequest.SetLightFilter`: DirectDiffuseOnly, DirectSpecularOnly,
//! IndirectDiffuseOnly, ReflectionOnly, EmissiveOnly), drawn for every pipeline.
//!
//! A layer is the frame drawn again with the passes' `TERMS` override set to its bits
//! (shaders/common/conventions.wgsl): models wrap each lobe in `direct_diffuse(…)`,
//! `indirect_specular(…)` and so on, so the image's pipelines (every bit) fold the masks away.

/// One bit of the `TERMS` mask (WGSL `TERM_*`, generated from these).
pub const DIRECT_DIFFUSE: u32 = 1;
pub const DIRECT_SPECULAR: u32 = 2;
pub const INDIRECT_DIFFUSE: u32 = 4;
pub const INDIRECT_SPECULAR: u32 = 8;
/// The surfaces' emission, an unlit colour, and the sky seen directly: light given off, not
/// reflected.
pub const EMISSION: u32 = 16;
/// Every additive term: the image.
pub const LIGHT: u32 = DIRECT_DIFFUSE | DIRECT_SPECULAR | INDIRECT_DIFFUSE | INDIRECT_SPECULAR | EMISSION;
/// Not a term but a mode: the frame holds the ambient occlusion the indirect light was dimmed by.
pub const OCCLUSION: u32 = 32;

/// The WGSL names of the bits, for shading::wgsl's generated constants.
pub const WGSL_BITS: [(&str, u32); 7] = [
    ("DIRECT_DIFFUSE", DIRECT_DIFFUSE),
    ("DIRECT_SPECULAR", DIRECT_SPECULAR),
    ("INDIRECT_DIFFUSE", INDIRECT_DIFFUSE),
    ("INDIRECT_SPECULAR", INDIRECT_SPECULAR),
    ("EMISSION", EMISSION),
    ("LIGHT", LIGHT),
    ("OCCLUSION", OCCLUSION),
];

/// One term layer: its EXR layer name and the `TERMS` bits it is drawn with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TermLayer {
    pub name: &'static str,
    pub bits: u32,
}

impl TermLayer {
    /// Whether the layer is one of the terms that add up to the frame (not the occlusion).
    pub fn is_additive(&self) -> bool {
        self.bits & LIGHT == self.bits
    }
}

pub const DIRECT_DIFFUSE_LAYER: TermLayer = TermLayer { name: "direct_diffuse", bits: DIRECT_DIFFUSE };
pub const DIRECT_SPECULAR_LAYER: TermLayer = TermLayer { name: "direct_specular", bits: DIRECT_SPECULAR };
pub const INDIRECT_DIFFUSE_LAYER: TermLayer = TermLayer { name: "indirect_diffuse", bits: INDIRECT_DIFFUSE };
pub const INDIRECT_SPECULAR_LAYER: TermLayer = TermLayer { name: "indirect_specular", bits: INDIRECT_SPECULAR };
pub const EMISSION_LAYER: TermLayer = TermLayer { name: "emission", bits: EMISSION };
pub const OCCLUSION_LAYER: TermLayer = TermLayer { name: "occlusion", bits: OCCLUSION };
/// Where a model does not keep its lobes apart (a user model that does not wrap them): its direct
/// and indirect light whole.
pub const DIRECT_LAYER: TermLayer = TermLayer { name: "direct", bits: DIRECT_DIFFUSE | DIRECT_SPECULAR };
pub const INDIRECT_LAYER: TermLayer = TermLayer { name: "indirect", bits: INDIRECT_DIFFUSE | INDIRECT_SPECULAR };

/// The layers of a cell whose drawn models do (`split`) or do not all keep their lobes apart,
/// additive ones first, in the order they are written.
pub fn layers(split: bool) -> Vec<TermLayer> {
    let mut out = if split {
        vec![DIRECT_DIFFUSE_LAYER, DIRECT_SPECULAR_LAYER, INDIRECT_DIFFUSE_LAYER, INDIRECT_SPECULAR_LAYER]
    } else {
        vec![DIRECT_LAYER, INDIRECT_LAYER]
    };
    out.extend([EMISSION_LAYER, OCCLUSION_LAYER]);
    out
}

/// Every layer name a cell can have, for the viewer's and the sheets' choices.
pub const LAYER_NAMES: [&str; 8] = [
    "direct_diffuse",
    "direct_specular",
    "indirect_diffuse",
    "indirect_specular",
    "direct",
    "indirect",
    "emission",
    "occlusion",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn additive_layers_cover_the_light_once() {
        for split in [true, false] {
            let additive: Vec<u32> = layers(split).iter().filter(|l| l.is_additive()).map(|l| l.bits).collect();
            assert_eq!(additive.iter().fold(0, |a, b| a | b), LIGHT);
            assert_eq!(additive.iter().sum::<u32>(), LIGHT, "no bit in two layers");
            assert!(!OCCLUSION_LAYER.is_additive());
        }
        for l in layers(true).iter().chain(&layers(false)) {
            assert!(LAYER_NAMES.contains(&l.name));
        }
    }
}
