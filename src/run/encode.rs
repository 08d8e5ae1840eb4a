//! The encode stage: a rendered frame becomes image.exr and image.png (and, for a supersampled
//! reference, reference.exr and reference.png), with its pixel statistics and the cell's record
//! short of its metrics.

use std::path::Path;

use super::clock::ThreadTimer;
use super::describe::{image_files, key_light, shader_inputs};
use super::study::{LeftOutVariant, StudyVariant};
use crate::cells::Cell;
use crate::declarations::matrix::Matrix;
use crate::declarations::outputs::ExrPrecision;
use crate::declarations::scene::Role;
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::images::stats::{pixel_stats, PixelStats};
use crate::images::target::store_half_float;
use crate::images::tonemap::DisplayRecord;
use crate::images::{encode, tonemap};
use crate::record::cell::{
    AntialiasingRecord, ApproximationRecord, CellMetrics, CellRecord, CellTiming, FrameSeries, CELL_SCHEMA,
};
use crate::record::Maybe;
use crate::record::TRUTH_NOISE_PNG;
use crate::render::uniforms::{ROLE_FIXED, ROLE_SUBJECT};
use crate::render::CellRender;

/// A frame the render thread finished, on its way to the encode workers.
pub struct RenderedCell<'a> {
    pub cell: &'a Cell,
    pub render: CellRender,
    /// The reference the render thread made for the cell, or why it could not be made.
    pub reference: Option<Result<RenderedReference, String>>,
    /// The approximation study's frames of the cell, and the ones left out.
    /// Each study frame with the samples per pixel its plan rendered.
    pub study: Vec<(StudyVariant, u32, CellRender)>,
    pub study_left_out: Vec<LeftOutVariant>,
    /// The cell of the same timing class whose frame timings `render` carries (`plan::timing`).
    pub timed_as: Option<crate::cells::CellId>,
    /// What the frame was drawn from: its record is written from it.
    pub plan: crate::plan::cell::CellPlan,
}

/// The folder of a cell's study frames (run::study), inside the cell's.
pub const STUDY_DIR: &str = "study";

/// A study frame encoded: its PNG written, its pixels kept for the metrics.
pub struct StudyImages {
    pub variant: StudyVariant,
    /// Its PNG, relative to the cell's folder.
    pub image: String,
    pub images: CellImages,
    pub gpu_ms: Option<f64>,
    pub cpu_wall_ms: f64,
    pub samples: u32,
}

/// A reference rendered with its cell.
pub enum RenderedReference {
    /// The same cell at k× the resolution (k, pixels).
    Supersampled(u32, Vec<f32>),
    /// The cell's path-traced truth.
    Truth(Box<crate::render::truth::Truth>),
}

/// The images of a cell in memory, as written to disk (PNG values are the RGBA8 written).
#[derive(Clone)]
pub struct CellImages {
    pub width: u32,
    pub height: u32,
    pub srgb8: Vec<u8>,
    pub hdr: Vec<f32>,
}

/// An encoded cell: files written, record complete but for the metrics.
pub struct EncodedCell {
    pub record: CellRecord,
    pub images: CellImages,
    /// Why the supersampled reference is missing, when the matrix asked for one and it is.
    pub reference_missing: Option<String>,
    pub study: Vec<StudyImages>,
}

/// `key`: the cell's key (`run::cell_key`), recorded as its input hash; `plan`: its composition's
/// frame plan, built once per composition.
pub fn encode_cell(
    matrix: &Matrix,
    dir: &Path,
    (adapter, key): (&str, &str),
    plan: &crate::plan::FramePlan,
    job: RenderedCell,
) -> Result<EncodedCell, Error> {
    let RenderedCell {
        cell,
        render: mut r,
        reference,
        study: study_renders,
        study_left_out,
        timed_as,
        plan: cell_plan,
    } = job;
    let t0 = ThreadTimer::start();
    // 16-bit channels where the frame fits them (`declarations::outputs`), and its term layers, which share
    // the file's channels: rounded here, so the PNG, the statistics and the metrics see what the
    // file holds.
    let layers_fit = r
        .terms
        .iter()
        .flat_map(|t| t.as_ref().ok())
        .flat_map(|t| t.layers.iter().map(|l| &l.1).chain(&t.before_bloom))
        .all(|px| encode::fits_half(px));
    let half = matrix.outputs.exr == ExrPrecision::Half && encode::fits_half(&r.hdr) && layers_fit;
    if half {
        encode::round_to_half(&mut r.hdr);
    }
    let shown = tonemap::to_srgb8(&r.hdr, r.width, r.height, &cell.display);
    // Counted in what the passes wrote, before the store saturates the overflow.
    let frame = crate::images::stats::FramePixels { width: r.width, hdr: &r.hdr, roles: &r.roles };
    let stats = pixel_stats(frame, pre_exposure(&shown.1), |role| {
        let (role, forward_only) = match role {
            ROLE_SUBJECT => (Some(Role::Subject), !cell.model().deferrable()),
            ROLE_FIXED => (Some(Role::Fixed), false),
            _ => (None, false),
        };
        let transparent = role == Some(Role::Subject) && cell.material.surface.is_transparent();
        plan.pass_writing(cell.path, role, forward_only, transparent)
            .map_or("clear (no background pass)".to_string(), |p| p.name().to_string())
    });
    let (srgb8, display) = store(&mut r.hdr, r.width, r.height, cell, shown);
    if half {
        // A saturated value as the file holds it.
        encode::round_to_half(&mut r.hdr);
    }
    let compression = matrix.outputs.exr_compression.exr();
    let mut terms = r.terms.take().map(|t| term_layers(t, &display));
    let exr = match &mut terms {
        Some(t) if !t.layers.is_empty() => {
            if half {
                t.layers.iter_mut().for_each(|l| encode::round_to_half(&mut l.1));
            }
            let layers: Vec<(&str, &[f32])> = t.layers.iter().map(|(n, px)| (n.as_str(), px.as_slice())).collect();
            encode::exr_with_layers_bytes(r.width, r.height, &r.hdr, &layers, half, compression)?
        }
        _ if half => encode::exr_half_bytes_with(r.width, r.height, &r.hdr, compression)?,
        _ => encode::exr_bytes_with(r.width, r.height, &r.hdr, compression)?,
    };
    let terms = match terms {
        Some(t) => Some(write_term_pngs(dir, cell, t, &display)?),
        None => None,
    };
    let png = encode::png_bytes(r.width, r.height, &srgb8)?;
    let pixels = match matrix.outputs.pixels {
        true => Some(crate::images::pixels::pixels_js(r.width, r.height, &srgb8, &r.hdr, half)?),
        false => None,
    };
    let encode_ms = t0.elapsed_ns() as f64 / 1e6;
    write_atomic(&dir.join("image.exr"), &exr)?;
    write_atomic(&dir.join("image.png"), &png)?;
    if let Some(pixels) = pixels {
        write_atomic(&dir.join(crate::images::pixels::PIXELS_FILE), &pixels)?;
    }
    let mut truth = None;
    let reference_missing = match reference {
        None => None,
        Some(Err(why)) => Some(why),
        Some(Ok(RenderedReference::Supersampled(k, big))) => {
            write_supersampled(dir, cell, k, &big, compression)?;
            None
        }
        Some(Ok(RenderedReference::Truth(t))) => {
            truth = Some(write_truth(dir, cell, &t, display.exposure, compression)?);
            None
        }
    };
    let timing = CellTiming { timed_as, ..cell_timing(matrix, &r, encode_ms) };
    let measured = Measured {
        display,
        stats,
        timing,
        passes: cell_plan.passes.iter().map(|p| p.name().to_string()).collect(),
        rules: crate::record::cell::EngineRules {
            reflection_probes: cell_plan.probes.clone(),
            subject_shadow: Some(cell_plan.subject_caster),
            ambient_occlusion: cell_plan.ao,
            probe_occlusion: cell_plan.gi.is_some().then_some(cell_plan.probe_occlusion),
            alpha_to_coverage: cell_plan.alpha_to_coverage,
            light_terms: cell_plan.distinct_light_terms(),
        },
        lights: cell_plan.assignment,
        antialiasing: AntialiasingRecord {
            asked: cell.antialiasing,
            samples: cell_plan.multisampling.samples,
            note: cell_plan.multisampling.note,
        },
        shadow_maps: cell_plan.shadow_maps,
        lod: cell_plan.lod,
        bake: cell_plan.gi.as_ref().zip(r.bake.as_ref()).map(|(plan, b)| bake_record(plan, b)),
        truth,
        terms,
        draws: cell_plan.draws.counts,
        left_out: cell_plan.left_out,
        exr_format: format!("{}, {}", if half { "half" } else { "float" }, matrix.outputs.exr_compression.name()),
    };
    let mut record = cell_record(matrix, cell, (adapter, key), plan, measured);
    record.approximations = study_left_out
        .into_iter()
        .map(|v| ApproximationRecord {
            approximation: v.approximation.name().into(),
            variant: v.name,
            change: v.change,
            result: Maybe::missing(v.reason),
        })
        .collect();
    let median = |ms: &[f64]| FrameSeries::new("", ms).median_ms;
    let mut study = Vec::with_capacity(study_renders.len());
    for (variant, samples, mut s) in study_renders {
        // Shown as the cell is: its own display transform, its exposure metered from this frame.
        let shown = tonemap::to_srgb8(&s.hdr, s.width, s.height, &cell.display);
        let (srgb8, _) = store(&mut s.hdr, s.width, s.height, cell, shown);
        let image = format!("{STUDY_DIR}/{}.png", variant.name);
        write_atomic(&dir.join(&image), &encode::png_bytes(s.width, s.height, &srgb8)?)?;
        study.push(StudyImages {
            variant,
            image,
            images: CellImages { width: s.width, height: s.height, srgb8, hdr: s.hdr },
            gpu_ms: s.gpu_pass_ms.as_deref().and_then(median),
            cpu_wall_ms: median(&s.frame_ms).unwrap_or(0.0),
            samples,
        });
    }
    Ok(EncodedCell {
        record,
        images: CellImages { width: r.width, height: r.height, srgb8, hdr: r.hdr },
        reference_missing,
        study,
    })
}

/// The timings `r` measured, as a record holds them (`encode_ms`: the encode stage's time).
pub fn cell_timing(matrix: &Matrix, r: &CellRender, encode_ms: f64) -> CellTiming {
    CellTiming {
        frames: r.frame_ms.len(),
        warmup: matrix.timing.warmup,
        gpu: match &r.gpu_pass_ms {
            Some(ms) => Maybe::Value(FrameSeries::new("timestamp queries: every pass of the frame, summed", ms)),
            None => Maybe::missing("the adapter has no timestamp queries; see cpu_wall"),
        },
        gpu_passes: match &r.gpu_passes {
            Some(passes) => Maybe::Value(passes.iter().map(|(pass, ms)| FrameSeries::new(pass.name(), ms)).collect()),
            None => Maybe::missing("the adapter has no timestamp queries"),
        },
        cpu_wall: FrameSeries::new("CPU wall time from queue submit to device idle", &r.frame_ms),
        readback_ms: r.readback_ms,
        encode_ms,
        metrics_ms: None,
        timed_as: None,
    }
}

/// The multiplier the pipeline writes its colour target with: HDRP's exposure, else 1.
fn pre_exposure(d: &DisplayRecord) -> f64 {
    d.exposure.as_ref().map_or(1.0, |e| e.exposure)
}

/// What the half-float camera target holds (`images::target`): `hdr` saturated at the
/// pre-exposure `shown` was metered with, and its display image — tonemapped again when the store
/// changed a value, so the PNG shows what the EXR holds.
fn store(hdr: &mut [f32], w: u32, h: u32, cell: &Cell, shown: (Vec<u8>, DisplayRecord)) -> (Vec<u8>, DisplayRecord) {
    if store_half_float(hdr, pre_exposure(&shown.1)) > 0 {
        tonemap::to_srgb8(hdr, w, h, &cell.display)
    } else {
        shown
    }
}

/// A cell's term layers as written: (name, RGBA) of each, the additive ones flagged, and the
/// record's parts.
struct TermImages {
    layers: Vec<(String, Vec<f32>)>,
    additive: Vec<bool>,
    sum_of: String,
    missing: Option<String>,
}

/// The drawn layers stored as the image is (values past the half range saturated at the image's
/// pre-exposure), the frame before bloom among them where the cell blooms.
fn term_layers(terms: Result<crate::render::renderer::RenderedTerms, String>, display: &DisplayRecord) -> TermImages {
    let t = match terms {
        Ok(t) => t,
        Err(why) => {
            return TermImages { layers: Vec::new(), additive: Vec::new(), sum_of: "image".into(), missing: Some(why) }
        }
    };
    let mut layers = Vec::new();
    let mut additive = Vec::new();
    for (layer, px) in t.layers {
        additive.push(layer.is_additive());
        layers.push((layer.name.to_string(), px));
    }
    let sum_of = match t.before_bloom {
        Some(px) => {
            additive.push(false);
            layers.push((BEFORE_BLOOM_LAYER.to_string(), px));
            BEFORE_BLOOM_LAYER
        }
        None => "image",
    };
    for (_, px) in &mut layers {
        store_half_float(px, pre_exposure(display));
    }
    TermImages { layers, additive, sum_of: sum_of.into(), missing: None }
}

/// The layer holding a blooming cell's frame before bloom: what its terms sum to.
pub const BEFORE_BLOOM_LAYER: &str = "before_bloom";
/// The folder of a cell's term PNGs.
pub const TERMS_DIR: &str = "terms";

/// `terms/<layer>.png` for each layer: the light terms through the cell's display transform at the
/// exposure the image was shown with (so they compare with it and with each other), the
/// occlusion as its plain value in grey.
fn write_term_pngs(
    dir: &Path,
    cell: &Cell,
    t: TermImages,
    display: &DisplayRecord,
) -> Result<crate::record::cell::TermsRecord, Error> {
    use crate::record::cell::{TermLayerRecord, TermsRecord};
    let mut layers = Vec::with_capacity(t.layers.len());
    for ((name, px), additive) in t.layers.iter().zip(&t.additive) {
        let srgb = if name == crate::pipelines::terms::OCCLUSION_LAYER.name {
            px.chunks_exact(4)
                .flat_map(|p| {
                    let v = (p[0].clamp(0.0, 1.0) * 255.0).round() as u8;
                    [v, v, v, 255]
                })
                .collect()
        } else {
            tonemap::to_srgb8_at(px, &cell.display, display.exposure).0
        };
        let png = format!("{TERMS_DIR}/{name}.png");
        write_atomic(&dir.join(&png), &encode::png_bytes(cell.width, cell.height, &srgb)?)?;
        layers.push(TermLayerRecord { name: name.clone(), png, additive: *additive });
    }
    Ok(TermsRecord { layers, sum_of: t.sum_of, missing: t.missing })
}

/// The truth as the cell's reference: reference.exr (its mean, the cell's units), reference.png
/// (through the cell's own display transform, at the exposure the cell was shown with) and
/// truth_noise.exr (the standard error of each pixel's luminance).
fn write_truth(
    dir: &Path,
    cell: &Cell,
    t: &crate::render::truth::Truth,
    exposure: Option<crate::images::exposure::ExposureRecord>,
    compression: exr::compression::Compression,
) -> Result<crate::record::cell::TruthRecord, Error> {
    let mut hdr: Vec<f32> = t.mean.iter().flat_map(|c| [c[0], c[1], c[2], 1.0]).collect();
    let (srgb, _) = tonemap::to_srgb8_at(&hdr, &cell.display, exposure);
    store_half_float(&mut hdr, exposure.map_or(1.0, |e| e.exposure));
    write_atomic(&dir.join("reference.exr"), &encode::exr_bytes_with(cell.width, cell.height, &hdr, compression)?)?;
    write_atomic(&dir.join("reference.png"), &encode::png_bytes(cell.width, cell.height, &srgb)?)?;
    let noise: Vec<f32> = t.std_error.iter().flat_map(|&e| [e, e, e, 1.0]).collect();
    write_atomic(&dir.join(TRUTH_NOISE_MAP), &encode::exr_bytes_with(cell.width, cell.height, &noise, compression)?)?;
    let shown = noise_rgba8(&t.mean, &t.std_error, cell.width as usize, cell.height as usize)?;
    write_atomic(&dir.join(TRUTH_NOISE_PNG), &encode::png_bytes(cell.width, cell.height, &shown)?)?;
    Ok(crate::record::cell::TruthRecord {
        kind: t.kind.name().into(),
        spp: t.spp,
        subject_noise: match t.subject_noise {
            Some(n) => Maybe::Value(n),
            None => Maybe::missing("no pixel shows the subject"),
        },
        bounces: t.bounces,
        seconds: t.seconds,
        cached: t.cached,
        noise_map: TRUTH_NOISE_MAP.into(),
        store_key: t.stored.as_ref().map(|s| s.0.clone()).unwrap_or_default(),
        store_sha256: t.stored.as_ref().map(|s| s.1.clone()).unwrap_or_default(),
    })
}

/// The exported truth scene (render::truth::export) into `cell_dir`/truth_scene: its files, then
/// scene.json last, so that a folder with a scene.json is whole.
pub fn write_truth_scene(cell_dir: &Path, export: crate::render::truth::export::TruthSceneExport) -> Result<(), Error> {
    let dir = cell_dir.join("truth_scene");
    std::fs::create_dir_all(&dir).map_err(|e| Error::io_path("creating folder", &dir, e))?;
    let _ = std::fs::remove_file(dir.join("scene.json"));
    for (name, bytes) in &export.meshes {
        write_atomic(&dir.join(name), bytes)?;
    }
    for (name, w, h, px) in &export.images {
        write_atomic(&dir.join(name), &encode::exr_bytes(*w, *h, px)?)?;
    }
    let json =
        serde_json::to_vec_pretty(&export.record).map_err(|e| Error::Other(format!("truth scene record: {e}")))?;
    write_atomic(&dir.join("scene.json"), &json)
}

/// The truth's per-pixel standard error, beside its reference images.
pub const TRUTH_NOISE_MAP: &str = "truth_noise.exr";

/// The truth's noise as a person sees it (`TRUTH_NOISE_PNG`, the viewer's overlay): each pixel's
/// standard error relative to its luminance, magma-coloured, full colour at 20 %.
pub const NOISE_PNG_FULL: f32 = 0.2;

/// A pixel's relative noise σ/L, clamped to the picture's range (0 where the truth is black).
pub fn relative_noise(mean: [f32; 3], std_error: f32) -> f32 {
    let l = crate::color::luminance(mean.map(f64::from)) as f32;
    if l > 0.0 && std_error.is_finite() {
        (std_error / l / NOISE_PNG_FULL).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

fn noise_rgba8(mean: &[[f32; 3]], std_error: &[f32], w: usize, h: usize) -> Result<Vec<u8>, Error> {
    let values = mean.iter().zip(std_error).map(|(m, &e)| relative_noise(*m, e)).collect();
    let map = flip_rs::ErrorMap::new(w, h, values).map_err(|e| Error::Other(format!("truth noise picture: {e:?}")))?;
    crate::compare::flip::magma_rgba8(&map).map_err(|e| Error::Other(format!("truth noise picture: {e}")))
}

/// Box-filter the k× render down to the cell's size: reference.exr and reference.png.
fn write_supersampled(
    dir: &Path,
    cell: &Cell,
    k: u32,
    big: &[f32],
    compression: exr::compression::Compression,
) -> Result<(), Error> {
    let (pw, ph, k) = (cell.width as usize, cell.height as usize, k as usize);
    let w = pw * k;
    let mut small = vec![0f32; pw * ph * 4];
    let norm = 1.0 / (k * k) as f32;
    for y in 0..ph {
        for x in 0..pw {
            for dy in 0..k {
                for dx in 0..k {
                    let src = ((y * k + dy) * w + x * k + dx) * 4;
                    for c in 0..4 {
                        small[(y * pw + x) * 4 + c] += big[src + c] * norm;
                    }
                }
            }
        }
    }
    let shown = tonemap::to_srgb8(&small, cell.width, cell.height, &cell.display);
    let (srgb, _) = store(&mut small, cell.width, cell.height, cell, shown);
    write_atomic(&dir.join("reference.exr"), &encode::exr_bytes_with(cell.width, cell.height, &small, compression)?)?;
    write_atomic(&dir.join("reference.png"), &encode::png_bytes(cell.width, cell.height, &srgb)?)
}

/// What a cell read of its scene's bake, as its record says it.
fn bake_record(plan: &crate::plan::gi::GiPlan, b: &crate::render::gi::BakeUse) -> crate::record::cell::BakeRecord {
    crate::record::cell::BakeRecord {
        plan: plan.clone(),
        made: b.made,
        cached: b.cached,
        seconds: b.seconds,
        samples: b.samples,
        texel_samples: b.lightmap.map_or(0, |_| b.texel_samples),
        noise_target: b.noise_target,
        bounces: b.bounces,
        lightmap_size: b.lightmap.map(|(size, _, _)| size),
        lightmap_texels: b.lightmap.map_or(0, |(_, n, _)| n),
        lightmap_encoding: b.encoding.to_string(),
        lightmap_noise: match b.lightmap.and_then(|(_, _, n)| n) {
            Some(n) => Maybe::Value(n),
            None => Maybe::missing("no lightmap, or no covered texel".to_string()),
        },
        probes: b.probes,
    }
}

/// A twin's record: its own axes and hash; its original's adapter and everything rendering measured.
pub fn twin_record(
    matrix: &Matrix,
    cell: &Cell,
    key: &str,
    plan: &crate::plan::FramePlan,
    original: &CellRecord,
) -> CellRecord {
    let o = original.clone();
    let twin_of = cell.twin_of.clone().expect("a twin");
    let note =
        format!("not rendered: `{}` ignores the axes this cell differs in; images copied from {twin_of}", cell.shader);
    let measured = Measured {
        display: o.display,
        stats: o.stats,
        timing: o.timing,
        passes: o.passes,
        rules: o.rules,
        lights: o.lights,
        antialiasing: o.antialiasing,
        shadow_maps: o.shadow_maps,
        lod: o.lod,
        bake: o.bake,
        truth: None,
        terms: o.terms,
        exr_format: o.image.exr_format,
        draws: o.draws,
        // The original's record holds the composition's left-out passes too: keep its own only.
        left_out: o.left_out.into_iter().filter(|e| !plan.left_out.contains(e)).collect(),
    };
    CellRecord {
        twin_of: Some(twin_of),
        note: Some(note),
        ..cell_record(matrix, cell, (&o.adapter, key), plan, measured)
    }
}

/// What rendering and encoding a cell measured and decided, as its record carries it.
struct Measured {
    display: DisplayRecord,
    stats: PixelStats,
    timing: CellTiming,
    /// The frame's passes in order (the plan's), as the timings name them.
    passes: Vec<String>,
    rules: crate::record::cell::EngineRules,
    lights: Vec<crate::plan::lights::ObjectLights>,
    antialiasing: AntialiasingRecord,
    shadow_maps: Vec<crate::plan::ShadowMapUse>,
    lod: Vec<crate::plan::lod::LodUse>,
    bake: Option<crate::record::cell::BakeRecord>,
    truth: Option<crate::record::cell::TruthRecord>,
    terms: Option<crate::record::cell::TermsRecord>,
    exr_format: String,
    draws: std::collections::BTreeMap<String, u32>,
    left_out: Vec<(String, String)>,
}

/// A cell's record before its metrics: its axes and inputs, and what rendering it measured.
fn cell_record(
    matrix: &Matrix,
    cell: &Cell,
    (adapter, key): (&str, &str),
    plan: &crate::plan::FramePlan,
    m: Measured,
) -> CellRecord {
    CellRecord {
        schema: CELL_SCHEMA,
        id: cell.id.clone(),
        input_hash: key.to_string(),
        key_inputs: Default::default(),
        matrix_sha256: matrix.hash.clone(),
        coords: cell.coords.clone(),
        shader_source: cell.model().source_path.to_string(),
        sliders: cell.material,
        shader_inputs: shader_inputs(cell),
        key_light: key_light(matrix, cell),
        image: image_files(cell, m.exr_format),
        twin_of: None,
        note: None,
        adapter: adapter.to_string(),
        display: m.display,
        passes: m.passes,
        rules: m.rules,
        left_out: plan.left_out.iter().chain(&m.left_out).cloned().collect(),
        draws: m.draws,
        engine: crate::record::cell::EngineSettingsRecord::of(cell.pipeline, &cell.pipeline_settings),
        lights: m.lights,
        antialiasing: m.antialiasing,
        shadow_maps: m.shadow_maps,
        lod: m.lod,
        bake: m.bake,
        truth: m.truth,
        terms: m.terms,
        approximations: Vec::new(),
        stats: m.stats,
        timing: m.timing,
        metrics: CellMetrics::without_reference("not compared yet"),
    }
}

/// A file of the run folder, through the bounded reader.
fn read_run_file(path: &Path) -> Result<Vec<u8>, Error> {
    crate::input::read::read(path, crate::input::read::OUTPUT)
        .map_err(|e| Error::Other(format!("reading {}: {e}", path.display())))
}

/// Copy a twin's images from its original's folder, with the reference the original was
/// compared with where it is the cell's own (a supersampled render, a truth: the same for the twin,
/// whose truth reads what the original's does — `cells::reads_material`).
pub fn copy_images(from: &Path, to: &Path) -> Result<(), Error> {
    let optional =
        [crate::images::pixels::PIXELS_FILE, "reference.exr", "reference.png", TRUTH_NOISE_MAP, TRUTH_NOISE_PNG];
    for name in ["image.exr", "image.png"].into_iter().chain(optional) {
        if optional.contains(&name) && !from.join(name).is_file() {
            continue; // `[outputs] pixels = false`, or no reference of the cell's own
        }
        let bytes = read_run_file(&from.join(name))?;
        write_atomic(&to.join(name), &bytes)?;
    }
    // The term PNGs, where the run draws them (`[outputs] terms`)
    let terms = from.join(TERMS_DIR);
    if terms.is_dir() {
        let entries = std::fs::read_dir(&terms).map_err(|e| Error::io_path("listing", &terms, e))?;
        let mut names: Vec<std::path::PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        names.sort();
        for path in names.iter().filter(|p| p.extension().is_some_and(|e| e == "png")) {
            let bytes = read_run_file(path)?;
            let name = path.file_name().expect("a listed file");
            write_atomic(&to.join(TERMS_DIR).join(name), &bytes)?;
        }
    }
    Ok(())
}
