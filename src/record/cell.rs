//! `cell.json`: everything about one cell — its axes, the model's inputs, the light, the files,
//! pixel statistics, timings, and its comparison with the reference. Written once, last, when the
//! cell has passed every stage, so its presence marks a finished cell.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

use super::{read_record, Maybe, RecordError};
use crate::cells::{CellId, MaterialParams};
use crate::compare::stats::BadValues;
use crate::compare::values::Comparison;
use crate::compare::values::FlipMetric;
use crate::images::stats::PixelStats;
use crate::images::tonemap::DisplayRecord;
use crate::pipelines::{Attenuation, Pipeline, RenderPath};
use crate::plan::lights::ObjectLights;

/// Version of the `cell.json` layout. 1: untyped, before versioning; 2: typed, written once with
/// metrics; 3: the display transform (tonemapper, HDRP exposure mode, EV and multiplier), light
/// units, the model parameters the sweep set, the light assignment and GPU time per pass;
/// 4: anti-aliasing (asked, rendered samples and why they differ) and shadow-map resolutions;
/// 5: the subject's peak luminance, overflow counted before the half-float store saturates it, and
/// whether the subject wore its textured preset, and its emission.
pub const CELL_SCHEMA: u32 = 8;

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CellRecord {
    pub schema: u32,
    pub id: CellId,
    /// Hash of everything the cell's image depends on; `--resume` keeps a cell whose hash matches.
    pub input_hash: String,
    pub matrix_sha256: String,
    pub composition: String,
    pub pipeline: Pipeline,
    pub path: RenderPath,
    pub shader: String,
    pub shader_source: String,
    pub preset: String,
    /// The subject wore its preset's textured form (maps from `materials`).
    #[serde(default)]
    pub textured: bool,
    /// The emission axis, when swept.
    #[serde(default)]
    pub emission: Option<f64>,
    /// The sweep's values (slider units).
    pub sliders: MaterialParams,
    /// The model's inputs as the shader receives them.
    pub shader_inputs: ShaderInputs,
    pub key_light: KeyLight,
    /// The view and parameter axes the cell sets (absent: the scene's and the model's own).
    pub view: ViewRecord,
    pub image: ImageFiles,
    /// Set when the images are a copy of this cell's (the shader ignores the differing axes).
    pub twin_of: Option<CellId>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    pub adapter: String,
    pub display: DisplayRecord,
    /// The passes of this cell's frame, in order (`FramePlan::passes_for` its path), and what the
    /// composition's plan left out and why.
    pub passes: Vec<String>,
    pub left_out: Vec<(String, String)>,
    /// How each light reached each object (per-pixel, per-vertex, SH, dropped) and why.
    pub lights: Vec<ObjectLights>,
    pub antialiasing: AntialiasingRecord,
    /// Each shadowed light's map resolution (the pipeline's default unless the scene sets one).
    pub shadow_maps: Vec<crate::plan::ShadowMapUse>,
    /// Each LOD group's relative screen height and the levels drawn, with their cross-fade.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lod: Vec<crate::plan::lod::LodUse>,
    /// What the cell's path-traced truth reached, when the matrix compares with one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth: Option<TruthRecord>,
    /// The approximation study (run::study): the cell rendered again with each real-time
    /// approximation replaced, measured against its truth; left-out ones carry the reason.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub approximations: Vec<ApproximationRecord>,
    pub stats: PixelStats,
    pub timing: CellTiming,
    pub metrics: CellMetrics,
}

/// A cell's truth as rendered: samples drawn, the subject's relative standard error (missing when
/// the frame shows no subject), and the GPU wall time it took.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TruthRecord {
    pub kind: String,
    pub spp: u32,
    pub subject_noise: Maybe<f64>,
    pub bounces: u32,
    /// The GPU wall time of tracing it (when it was traced for an earlier cell or run, that time).
    pub seconds: f64,
    /// Reused from the truth cache (`<results>/.truth-cache`) instead of traced again.
    #[serde(default)]
    pub cached: bool,
    /// The per-pixel standard error of the truth's luminance (EXR, grey).
    pub noise_map: String,
}

/// One frame of the approximation study.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ApproximationRecord {
    /// spec::study::Approximation's name.
    pub approximation: String,
    /// The frame's name: the approximation, or the MSAA level (`msaa8`).
    pub variant: String,
    /// What changed: "shadow maps → ray-traced visibility".
    pub change: String,
    pub result: Maybe<ApproximationResult>,
}

/// The study frame's time and its error against the cell's truth (the cell's own are its timing
/// and metrics: the change is the difference).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ApproximationResult {
    /// Its PNG, relative to the cell's folder.
    pub image: String,
    /// Median GPU time of the frame's passes (timestamp queries).
    pub gpu_ms: Maybe<f64>,
    /// Median CPU wall time from submit to idle.
    pub cpu_wall_ms: f64,
    /// Samples per pixel it rendered with.
    pub samples: u32,
    pub flip: Maybe<f64>,
    pub ssim: Maybe<f64>,
    pub hdr_relative_mse: Maybe<f64>,
}

impl CellRecord {
    pub fn load(path: &Path) -> Result<CellRecord, RecordError> {
        read_record(path, CELL_SCHEMA)
    }

    /// The cell's value on a sheet axis (`spec::sheets::AXES`), as labels and file names show it.
    pub fn axis_value(&self, axis: &str) -> String {
        // Exact where two decimals are not: 0.999 and 1 are two columns, not one.
        let num = |v: f64| crate::cells::id_number(v, 2, false);
        match axis {
            "composition" => self.composition.clone(),
            "pipeline" => self.pipeline.name().into(),
            "path" => self.path.name().into(),
            "shader" => self.shader.clone(),
            "preset" => self.preset.clone(),
            "metallic" => num(self.sliders.metallic),
            "smoothness" => num(self.sliders.smoothness),
            "color" => crate::spec::matrix::color_code(self.sliders.slider_color_srgb),
            "camera_distance" => self.view.camera_distance.map_or_else(|| "scene".into(), num),
            "light_angle" => self.view.light_angle.map_or_else(|| "scene".into(), num),
            "params" => {
                let swept: Vec<String> = self.view.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
                if swept.is_empty() {
                    "defaults".into()
                } else {
                    swept.join(",")
                }
            }
            "light_intensity" => num(self.key_light.intensity),
            "light_range" => num(self.key_light.range),
            "textured" => self.textured.to_string(),
            "emission" => self.emission.map_or_else(|| "none".into(), num),
            _ => "?".into(),
        }
    }

    /// The time error-against-time plots use: GPU pass time where measured, else CPU wall.
    pub fn gpu_median_ms(&self) -> Option<f64> {
        self.timing.gpu.value().and_then(|s| s.median_ms)
    }
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ShaderInputs {
    pub base_color_linear: [f64; 3],
    pub metallic: f64,
    pub smoothness: f64,
    pub specular: [f64; 3],
    /// The model's own parameters by name.
    pub params: BTreeMap<String, f64>,
    /// How the sweep's values became these inputs.
    pub mapping: String,
}

/// The anti-aliasing a cell asked for and the samples per pixel it rendered with.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct AntialiasingRecord {
    pub asked: crate::pipelines::Antialiasing,
    pub samples: u32,
    /// Why `samples` differs from what was asked (deferred path, adapter), when it does.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct KeyLight {
    /// Matrix units (0–100) and metres.
    pub intensity: f64,
    pub range: f64,
    /// Factor from matrix units to the pipeline's UI unit.
    pub intensity_scale: f64,
    /// What the intensity axis means in this pipeline (HDRP: lumen for points and spots, lux
    /// for directional lights).
    pub unit: String,
    pub attenuation: Attenuation,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ViewRecord {
    pub camera_distance: Option<f64>,
    pub light_angle: Option<f64>,
    /// `[sweep.params]` values this cell's model takes.
    pub params: BTreeMap<String, f64>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ImageFiles {
    pub width: u32,
    pub height: u32,
    pub exr: String,
    pub png: String,
    /// How image.exr was written: its channels (`half`, or `float` where `[outputs] exr = "float"`
    /// or a value exceeds the half range) and compression.
    #[serde(default)]
    pub exr_format: String,
}

/// Times of a series of frames, ms.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct FrameSeries {
    /// What was timed.
    pub kind: String,
    pub frame_ms: Vec<f64>,
    pub median_ms: Option<f64>,
    pub min_ms: Option<f64>,
    pub max_ms: Option<f64>,
}

impl FrameSeries {
    pub fn new(kind: impl Into<String>, ms: &[f64]) -> FrameSeries {
        let mut sorted = ms.to_vec();
        sorted.sort_by(|a, b| a.total_cmp(b));
        FrameSeries {
            kind: kind.into(),
            frame_ms: ms.to_vec(),
            median_ms: sorted.get(sorted.len() / 2).copied(),
            min_ms: sorted.first().copied(),
            max_ms: sorted.last().copied(),
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CellTiming {
    /// Timed frames, after `warmup` untimed ones.
    pub frames: usize,
    pub warmup: u32,
    /// GPU time of the frame from timestamp queries (its passes summed), or why there is none.
    pub gpu: Maybe<FrameSeries>,
    /// GPU time of each pass of the frame (`kind` names the pass), or why there is none.
    pub gpu_passes: Maybe<Vec<FrameSeries>>,
    /// CPU wall time from queue submit to device idle.
    pub cpu_wall: FrameSeries,
    pub readback_ms: f64,
    /// Tonemapping, statistics and encoding of EXR and PNG.
    pub encode_ms: f64,
    /// Comparing with the reference and writing the maps (None: not compared).
    pub metrics_ms: Option<f64>,
    /// Set when the frame timings (gpu, gpu_passes, cpu_wall, frames) are those of this cell of
    /// the same timing class (`plan::timing`): this cell rendered one untimed frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timed_as: Option<CellId>,
}

/// What a cell was compared against.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ReferenceRecord {
    /// Another cell of this run.
    Cell { cell: CellId },
    /// The same cell rendered at `factor`× and box-filtered down (reference.exr/png in the cell).
    Supersampled { factor: u32 },
    /// The cell of the same id in an earlier run.
    Run { run: String, cell: CellId },
    /// The cell's path-traced truth (reference.exr/png in the cell, its standard error in
    /// truth_noise.exr): which truth, and the most samples, noise target and bounces it was asked for
    /// (what it reached: the record's `truth`).
    Truth { truth: String, spp: u32, noise: f64, bounces: u32 },
}

impl ReferenceRecord {
    /// A short label for tables: the reference cell's id, or the kind.
    pub fn label(&self) -> String {
        match self {
            ReferenceRecord::Cell { cell } => cell.0.clone(),
            ReferenceRecord::Supersampled { factor } => format!("supersampled {factor}×"),
            ReferenceRecord::Run { run, .. } => format!("run {run}"),
            ReferenceRecord::Truth { truth, .. } => format!("truth ({truth})"),
        }
    }
}

/// HDR comparison of the EXRs.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct HdrComparison {
    pub flip: FlipMetric,
    pub rmse: f64,
    /// The relative MSE (compare::stats::relative_mse): free of the images' units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relative_mse: Option<f64>,
    pub reference_bad: BadValues,
    pub test_bad: BadValues,
    /// Against a cell of another pipeline, whose EXR holds other units (HDRP's physical light
    /// against built-in's and URP's unitless intensities): the exposures (cell, reference) each
    /// image was multiplied by first, each its own display exposure (1 without one), so that both
    /// are compared as they are shown before tonemapping. None: compared as stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exposed: Option<(f64, f64)>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct MetricMaps {
    pub flip: String,
    pub ssim: String,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CellMetrics {
    pub reference: Maybe<ReferenceRecord>,
    /// LDR comparison of the PNGs (absent without a reference).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ldr: Option<Comparison>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hdr: Option<Maybe<HdrComparison>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub maps: Option<MetricMaps>,
    /// Against a truth: which pixels differ from it by more than its own noise explains.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ztest: Option<Maybe<crate::compare::ztest::ZTest>>,
}

impl CellMetrics {
    pub fn without_reference(why: impl Into<String>) -> CellMetrics {
        CellMetrics { reference: Maybe::missing(why), ldr: None, hdr: None, maps: None, ztest: None }
    }

    pub fn ldr_flip(&self) -> Option<f64> {
        self.ldr.as_ref().and_then(|c| c.flip.value.mean())
    }

    pub fn ldr_ssim(&self) -> Option<f64> {
        self.ldr.as_ref().and_then(|c| c.ssim.mean())
    }

    pub fn hdr_flip(&self) -> Option<f64> {
        self.hdr.as_ref().and_then(|h| h.value()).and_then(|h| h.flip.value.mean())
    }

    pub fn hdr_relative_mse(&self) -> Option<f64> {
        self.hdr.as_ref().and_then(|h| h.value()).and_then(|h| h.relative_mse)
    }

    /// The reference cell's id, when the reference is a cell of this run.
    pub fn reference_cell(&self) -> Option<&CellId> {
        match self.reference.value() {
            Some(ReferenceRecord::Cell { cell }) => Some(cell),
            _ => None,
        }
    }
}
