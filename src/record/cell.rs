//! `cell.json`: everything about one cell — its axes, the model's inputs, the light, the files,
//! pixel statistics, timings, and its comparison with the reference. Written once, last, when the
//! cell has passed every stage, so its presence marks a finished cell.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

use super::{read_record, Maybe, RecordError};
use crate::cells::{CellCoords, CellId, MaterialParams};
use crate::compare::stats::BadValues;
use crate::compare::values::Comparison;
use crate::compare::values::FlipMetric;
use crate::images::stats::PixelStats;
use crate::images::tonemap::DisplayRecord;
use crate::pipelines::Attenuation;
use crate::plan::lights::ObjectLights;

/// Version of the `cell.json` layout. 1: untyped, before versioning; 2: typed, written once with
/// metrics; 3: the display transform (tonemapper, HDRP exposure mode, EV and multiplier), light
/// units, the model parameters the sweep set, the light assignment and GPU time per pass;
/// 4: anti-aliasing (asked, rendered samples and why they differ) and shadow-map resolutions;
/// 5: the subject's peak luminance, overflow counted before the half-float store saturates it, and
/// whether the subject wore its textured preset, and its emission.
/// 11: passes named by `plan::Pass` (the frame's list, the same as its timings) and the engine
/// rules the plan decided (`rules`).
pub const CELL_SCHEMA: u32 = 11;
/// Schema 9: no draws per pass and no engine settings (read with both empty).
const NO_DRAWS_SCHEMA: u32 = 9;
/// Schema 10: passes named before `plan::Pass` and no engine rules (read with the rules empty).
const NO_RULES_SCHEMA: u32 = 10;

/// The schema before `coords`: a cell's axes were separate fields (`composition` … `emission`,
/// `view`, and the sliders' and key light's values). Reports still read it (`CellRecord::read`).
const SEPARATE_AXES_SCHEMA: u32 = 8;

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CellRecord {
    pub schema: u32,
    pub id: CellId,
    /// Hash of everything the cell's image depends on; `--resume` keeps a cell whose hash matches.
    pub input_hash: String,
    /// The digest of each input the key covers (`run::cell_key::KEY_INPUTS`), so that a cell
    /// whose key differs from a recomputed one can say which input changed.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub key_inputs: std::collections::BTreeMap<String, String>,
    pub matrix_sha256: String,
    /// What the cell is: its value on every axis (`declarations::axes`).
    pub coords: CellCoords,
    pub shader_source: String,
    /// The material its preset and sliders resolved to (slider units).
    pub sliders: MaterialParams,
    /// The model's inputs as the shader receives them.
    pub shader_inputs: ShaderInputs,
    pub key_light: KeyLight,
    pub image: ImageFiles,
    /// Set when the images are a copy of this cell's (the shader ignores the differing axes).
    pub twin_of: Option<CellId>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    pub adapter: String,
    pub display: DisplayRecord,
    /// The passes of this cell's frame, in the order they ran (its plan's, `plan::Pass`), and what the
    /// composition's plan left out and why.
    pub passes: Vec<String>,
    pub left_out: Vec<(String, String)>,
    /// Draws per pass as the engine structures the frame (plan::draws): `forward_base: 2,
    /// forward_add: 6` for built-in forward, `gbuffer`, `deferred_lighting`, `forward_only` …
    #[serde(default)]
    pub draws: std::collections::BTreeMap<String, u32>,
    /// The engine settings the cell rendered with: built-in's pass structure or the URP asset.
    #[serde(default)]
    pub engine: EngineSettingsRecord,
    /// The engine's rules as the plan decided them and the frame applied them: how each
    /// reflection probe is read (`plan::probes`), how the subject casts (`plan::shadows`), where
    /// SSAO applies (`plan::ao`).
    #[serde(default)]
    pub rules: EngineRules,
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
    /// The scene's baked lighting as this cell read it (absent: the scene bakes nothing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bake: Option<BakeRecord>,
    /// The cell's term layers, where its run asked for them (`[outputs] terms`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub terms: Option<TermsRecord>,
    /// The approximation study (run::study): the cell rendered again with each real-time
    /// approximation replaced, measured against its truth; left-out ones carry the reason.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub approximations: Vec<ApproximationRecord>,
    pub stats: PixelStats,
    pub timing: CellTiming,
    pub metrics: CellMetrics,
}

/// A cell's bake (render::gi): what each light gave it and what the bake cost — a one-off, not
/// per frame; cells whose bake inputs agree share one, and only the first pays its time.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BakeRecord {
    /// The Lighting Mode, each light's share and why (plan::gi).
    pub plan: crate::plan::gi::GiPlan,
    /// Made for this cell (false: shared with an earlier cell of the run, or nothing to bake).
    pub made: bool,
    /// Read from the bake cache beside the run folders (`seconds` is the run's that made it).
    #[serde(default)]
    pub cached: bool,
    /// Wall time of the bake, s.
    pub seconds: f64,
    /// Samples per probe, and the most per texel.
    pub samples: u32,
    /// The samples the texels took to reach `noise_target` (0: a bake without texels).
    #[serde(default)]
    pub texel_samples: u32,
    /// The lightmap noise the bake converged towards (0: every texel took `samples`).
    #[serde(default)]
    pub noise_target: f64,
    pub bounces: u32,
    /// The lightmap: size in texels, texels its charts cover, how it is stored, and the mean of
    /// its texels' relative standard error (missing with no lightmap).
    pub lightmap_size: Option<[u32; 2]>,
    pub lightmap_texels: usize,
    pub lightmap_encoding: String,
    pub lightmap_noise: Maybe<f64>,
    pub probes: usize,
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
    /// The truth store's key and the digest of the entry the cell was compared with
    /// (`run::truth_cache`): a cached cell is taken only while that entry is the one stored.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub store_key: String,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub store_sha256: String,
}

/// A cell's term layers (pipelines::terms): the layers image.exr holds besides the image, each
/// with its PNG, and what the additive ones sum to; or why the cell has none.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TermsRecord {
    /// The layers written, in order: image.exr's `<name>.R/G/B`, `terms/<name>.png`.
    pub layers: Vec<TermLayerRecord>,
    /// What the additive layers sum to: `image`, or the layer `before_bloom` (the frame before
    /// bloom, also written) where the cell blooms.
    pub sum_of: String,
    /// Why the cell has no layers (then `layers` is empty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub missing: Option<String>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TermLayerRecord {
    pub name: String,
    pub png: String,
    /// Whether it is one of the terms that add up to the frame (the occlusion layer is a factor).
    pub additive: bool,
}

/// One frame of the approximation study.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ApproximationRecord {
    /// declarations::study::Approximation's name.
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

/// A schema-8 record as this schema's: the axes moved into `coords` (their values were the
/// sliders', the key light's and the view's).
fn with_coords(mut old: serde_json::Value) -> serde_json::Value {
    use serde_json::Value;
    let Some(o) = old.as_object_mut() else { return old };
    let mut take = |k: &str| o.remove(k).unwrap_or(Value::Null);
    let (composition, pipeline, path, shader, preset) =
        (take("composition"), take("pipeline"), take("path"), take("shader"), take("preset"));
    let (textured, emission, view) = (take("textured"), take("emission"), take("view"));
    let field = |v: Option<&Value>, k: &str| v.and_then(|v| v.get(k)).cloned().unwrap_or(Value::Null);
    let (sliders, key) = (o.get("sliders"), o.get("key_light"));
    let coords = serde_json::json!({
        "composition": composition,
        "pipeline": pipeline,
        "path": path,
        "shader": shader,
        "preset": preset,
        "metallic": field(sliders, "metallic"),
        "smoothness": field(sliders, "smoothness"),
        "color": field(sliders, "slider_color_srgb"),
        "light_intensity": field(key, "intensity"),
        "light_range": field(key, "range"),
        "camera_distance": field(Some(&view), "camera_distance"),
        "light_angle": field(Some(&view), "light_angle"),
        "params": view.get("params").cloned().unwrap_or_else(|| serde_json::json!({})),
        "textured": if textured.is_null() { Value::Bool(false) } else { textured },
        "emission": emission,
    });
    o.insert("coords".into(), coords);
    o.insert("schema".into(), CELL_SCHEMA.into());
    old
}

/// A record reads as its cell's coordinates (`record.pipeline`, `record.light_angle`).
impl std::ops::Deref for CellRecord {
    type Target = CellCoords;

    fn deref(&self) -> &CellCoords {
        &self.coords
    }
}

/// The engine's rules a cell's plan decided (`plan::probes`, `plan::shadows`, `plan::ao`,
/// `plan::gi`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EngineRules {
    /// How the frame read each of the scene's reflection probes (empty: it captured none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reflection_probes: Vec<crate::plan::probes::ProbeUse>,
    /// How the subject cast into the shadow maps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subject_shadow: Option<crate::plan::shadows::SubjectCaster>,
    /// Where screen-space ambient occlusion applied.
    #[serde(default)]
    pub ambient_occlusion: crate::plan::ao::AoUse,
    /// How a dynamic object's probe occlusion met a real-time shadow (under a bake that has it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub probe_occlusion: Option<crate::plan::gi::ProbeOcclusion>,
    /// The subject's alpha test resolved by alpha-to-coverage (URP's clipped Lit under MSAA).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub alpha_to_coverage: bool,
    /// The lights HDRP's own settings changed: their lobes, shape, attenuation, dimmers and tint.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub light_terms: Vec<crate::plan::light_terms::LightTerms>,
}

impl CellRecord {
    /// A record of this schema: what a run writes, resumes, caches and merges.
    pub fn load(path: &Path) -> Result<CellRecord, RecordError> {
        read_record(path, CELL_SCHEMA)
    }

    /// A record of this schema or of the one before it, its axes gathered into `coords`: what
    /// reports, the viewer and `diff` read, so a run made before still opens.
    pub fn read(path: &Path) -> Result<CellRecord, RecordError> {
        match read_record(path, CELL_SCHEMA) {
            Err(RecordError::OtherVersion { found: NO_DRAWS_SCHEMA | NO_RULES_SCHEMA, .. }) => {
                let text = super::versioned::record_text(path)?;
                let mut old: serde_json::Value =
                    serde_json::from_str(&text).map_err(|e| RecordError::Invalid(e.to_string()))?;
                old["schema"] = CELL_SCHEMA.into();
                serde_json::from_value(old).map_err(|e| RecordError::Invalid(e.to_string()))
            }
            Err(RecordError::OtherVersion { found: SEPARATE_AXES_SCHEMA, .. }) => {
                let text = super::versioned::record_text(path)?;
                let old: serde_json::Value =
                    serde_json::from_str(&text).map_err(|e| RecordError::Invalid(e.to_string()))?;
                serde_json::from_value(with_coords(old)).map_err(|e| RecordError::Invalid(e.to_string()))
            }
            read => read,
        }
    }

    /// The cell's value on the axis named `axis`, as labels and file names show it.
    pub fn axis_value(&self, axis: &str) -> String {
        self.coords.label(axis)
    }

    /// The time error-against-time plots use: GPU pass time where measured, else CPU wall.
    pub fn gpu_median_ms(&self) -> Option<f64> {
        self.timing.gpu.value().and_then(|s| s.median_ms)
    }
}

/// The engine settings of a cell's pipeline (`pipelines::settings`): built-in's forward pass
/// structure and quality level, the URP asset's fields, or HDRP's settings (its volume's are the
/// scene's: `display`).
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct EngineSettingsRecord {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub builtin: Option<crate::pipelines::settings::BuiltinSettings>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urp: Option<crate::pipelines::settings::UrpAsset>,
    /// HDRP's, where they are not its defaults (a record of HDRP's defaults reads as it did
    /// before they were settings).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hdrp: Option<crate::pipelines::settings::HdrpSettings>,
}

impl EngineSettingsRecord {
    pub fn of(pipeline: crate::pipelines::Pipeline, s: &crate::pipelines::settings::PipelineSettings) -> Self {
        use crate::pipelines::Pipeline;
        EngineSettingsRecord {
            builtin: (pipeline == Pipeline::Builtin).then_some(s.builtin),
            urp: (pipeline == Pipeline::Urp).then_some(s.urp),
            hdrp: (pipeline == Pipeline::Hdrp && s.hdrp != Default::default()).then_some(s.hdrp),
        }
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
    /// (what it reached: the record's `truth`), and whether paths went on past them under Russian
    /// roulette.
    Truth {
        truth: String,
        spp: u32,
        noise: f64,
        bounces: u32,
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        roulette: bool,
    },
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_schema_8_record_reads_with_its_axes_in_coords() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/records/cell_schema8.json");
        assert!(matches!(CellRecord::load(&path), Err(RecordError::OtherVersion { found: 8, expected: CELL_SCHEMA })));
        let r = CellRecord::read(&path).unwrap();
        let old: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert_eq!(r.schema, CELL_SCHEMA);
        assert_eq!(r.id.0, old["id"]);
        // The id is the coordinates' own: every axis came across.
        assert_eq!(crate::cells::cell_id(&r.coords), r.id);
        assert_eq!((r.composition.as_str(), r.pipeline.name(), r.shader.as_str()), ("default", "urp", "lit"));
        assert_eq!((r.light_angle, r.emission, r.camera_distance), (Some(30.0), Some(0.5), None));
        assert_eq!((r.metallic, r.smoothness, r.light_intensity), (0.0, 0.75, 2.0));
        assert_eq!(r.label("light_angle"), "30.00");
    }
}
