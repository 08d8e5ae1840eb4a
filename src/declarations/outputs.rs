//! `[outputs]`: how a cell's files are written — the EXR's channel precision and compression, and
//! whether the difference maps are kept. Every cell writes its EXR and PNG: the metrics, the
//! references, twins, `--resume` and the reports read them.

use serde::{Deserialize, Serialize};

use crate::error::InputError;
use crate::input::validate::Checker;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Outputs {
    /// Channel precision of image.exr.
    #[serde(default)]
    pub exr: ExrPrecision,
    #[serde(default)]
    pub exr_compression: ExrCompression,
    /// flip.png and ssim.png beside each compared cell (the metrics are recorded either way).
    #[serde(default = "yes")]
    pub maps: bool,
    /// pixels.js beside each image (images::pixels): the viewer's magnifier reads the sRGB and
    /// linear values from it; 120–250 KB a cell at 256², so huge sweeps may leave it out.
    #[serde(default = "yes")]
    pub pixels: bool,
    /// truth_scene/ beside each cell: the scene as its physical truth traces it, for another
    /// renderer (render::truth::export; tools/mitsuba_check.py).
    #[serde(default)]
    pub truth_scene: bool,
    /// The cell's terms as extra layers of image.exr, with a PNG each (pipelines::terms): direct
    /// and indirect diffuse and specular, emission, and the ambient occlusion. Each is the frame
    /// drawn again, so only runs that ask draw them. Left out of the serialised settings when off,
    /// so cell keys from before it stay the same.
    #[serde(default, skip_serializing_if = "is_false")]
    pub terms: bool,
}

fn yes() -> bool {
    true
}

fn is_false(b: &bool) -> bool {
    !*b
}

impl Default for Outputs {
    fn default() -> Self {
        Outputs {
            exr: ExrPrecision::default(),
            exr_compression: ExrCompression::default(),
            maps: true,
            pixels: true,
            truth_scene: false,
            terms: false,
        }
    }
}

/// `half`: 16-bit channels, what every emulated pipeline's camera target holds
/// (`images::target`), wherever every finite value fits the half range (else 32-bit, recorded);
/// `float`: 32-bit channels always.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ExrPrecision {
    #[default]
    Half,
    Float,
}

/// The EXR compression: lossless all; measured in the README (size and encode time).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ExrCompression {
    #[default]
    Zip,
    Piz,
    Rle,
    None,
}

impl ExrCompression {
    pub fn exr(self) -> exr::compression::Compression {
        use exr::compression::Compression;
        match self {
            ExrCompression::Zip => Compression::ZIP16,
            ExrCompression::Piz => Compression::PIZ,
            ExrCompression::Rle => Compression::RLE,
            ExrCompression::None => Compression::Uncompressed,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            ExrCompression::Zip => "zip",
            ExrCompression::Piz => "piz",
            ExrCompression::Rle => "rle",
            ExrCompression::None => "none",
        }
    }
}

/// `truth_scene` exports what a physical truth traces, as factors: it needs a physical truth, and
/// no composition whose fixed objects have maps (`render::truth::export`) — found when the matrix
/// loads, not when the first such cell renders into a failed run folder.
pub fn check_truth_scene(
    c: &Checker,
    outputs: &Outputs,
    physical_truth: bool,
    compositions: &[super::scene::Scene],
) -> Result<(), InputError> {
    if !outputs.truth_scene {
        return Ok(());
    }
    if !physical_truth {
        let why = "exports the scene as the physical truth traces it: set `reference = { truth = \"physical\" }`";
        return Err(c.err("outputs.truth_scene", why));
    }
    let mapped = compositions.iter().enumerate().find_map(|(i, s)| {
        let has_maps = |m: &super::scene::FixedMaterial| m.base_color_map.is_some() || m.gltf_material.is_some();
        s.objects.iter().find(|o| o.material.as_ref().is_some_and(has_maps)).map(|o| (i, &s.name, &o.name))
    });
    match mapped {
        Some((i, scene, object)) => Err(c.err(
            "outputs.truth_scene",
            format!(
                "compositions[{i}] (`{scene}`): fixed object `{object}` has material maps (base_color_map or \
                 gltf_material), which the exported scene does not carry yet; export a composition whose fixed \
                 objects have factors alone"
            ),
        )),
        None => Ok(()),
    }
}
