//! `shadematrix match --from PIPELINE/SHADER --to PIPELINE/SHADER [MATRIX]`: for each material the
//! matrix sweeps in the source, the target's values that reproduce its frames over every
//! composition at once (`remap::fit`), into `tables/match.md|csv|json`.

use std::path::{Path, PathBuf};

use crate::error::{Error, InputError};
use crate::fsutil::{write_atomic, write_json};
use crate::input::names::unknown_name;
use crate::pipelines::Pipeline;
use crate::plan::cell::CellSettings;
use crate::remap::fit::{calibrate_exposure, fit, BasisCache, FitOptions, Kept, ParamAxis};
use crate::remap::sheet::{write_frames, write_sheets};
use crate::remap::table::{MatchKey, MatchProgress, MatchRecord, MatchRow, MATCH_SCHEMA};
use crate::remap::{frames, MatchSpace, MaterialValues, Side, Stage};
use crate::render::Renderer;
use crate::shading::registry::Registry;

const ORIGIN: &str = "command line";

pub struct MatchRequest {
    pub from: String,
    pub to: String,
    pub matrix: Option<PathBuf>,
    pub out: PathBuf,
    pub space: String,
    pub size: u32,
    pub iterations: u64,
    /// Take the rows of `tables/match.progress.json` made under the same key.
    pub resume: bool,
    /// Source values the fit keeps (`Kept::NAMES`).
    pub keep: Vec<String>,
}

/// `PIPELINE/SHADER` as `key` names it, resolved among the registry's models.
fn side_of<'r>(
    key: &str,
    text: &str,
    registry: &'r Registry,
) -> Result<(Pipeline, &'r crate::shading::ShaderModel), Error> {
    let (p, s) = text
        .split_once('/')
        .ok_or_else(|| InputError::at_key(ORIGIN, key, format!("`{text}` is not PIPELINE/SHADER (e.g. urp/lit)")))?;
    let pipeline =
        Pipeline::from_name(p).ok_or_else(|| unknown_name(ORIGIN, key, "pipeline", p, &Pipeline::names()))?;
    let model = registry.find(pipeline, s).ok_or_else(|| {
        unknown_name(ORIGIN, key, &format!("{} shader", pipeline.name()), s, &registry.names_for(pipeline))
    })?;
    Ok((pipeline, &**model))
}

pub fn run_match(req: &MatchRequest, models: &super::ModelsArg) -> Result<(), Error> {
    let registry = super::registry_for(models, req.matrix.as_deref())?;
    let space = match req.space.as_str() {
        "display" => MatchSpace::Display,
        "linear" => MatchSpace::Linear,
        other => return Err(unknown_name(ORIGIN, "--space", "space", other, &["display", "linear"]).into()),
    };
    let keep = Kept::parse(req.keep.iter().map(String::as_str))
        .map_err(|bad| unknown_name(ORIGIN, "--keep", "value", bad, &Kept::NAMES))?;
    if !(16..=1024).contains(&req.size) {
        return Err(InputError::at_key(ORIGIN, "--size", format!("{}: allowed 16..=1024", req.size)).into());
    }
    let (from_pipeline, from_model) = side_of("--from", &req.from, &registry)?;
    let (to_pipeline, to_model) = side_of("--to", &req.to, &registry)?;
    let matrix = super::load_matrix(req.matrix.as_deref(), registry.clone())?;
    let expansion = crate::cells::expand(&matrix);
    // The source's materials: one per distinct preset and slider values among the matrix's cells
    // of the source pipeline and shader, in the matrix's order.
    let mut materials: Vec<(String, MaterialValues)> = Vec::new();
    let mut light = None;
    for cell in expansion.cells.iter().filter(|c| c.pipeline == from_pipeline && c.shader == from_model.name) {
        let m = &cell.material;
        let values = MaterialValues {
            smoothness: m.smoothness,
            metallic: m.metallic,
            color: m.base_color_linear,
            params: cell.coords.params.clone(),
        };
        light.get_or_insert((cell.light_intensity, cell.light_range));
        if !materials.iter().any(|(p, v)| *p == cell.preset && *v == values) {
            materials.push((cell.preset.clone(), values));
        }
    }
    let Some((light_intensity, light_range)) = light else {
        let shown = req.matrix.as_ref().map_or("the default matrix".to_string(), |p| p.display().to_string());
        let why = format!("no cell of {} to match: the matrix renders none", req.from);
        return Err(InputError::at_key(shown, "pipelines/shaders", why).into());
    };
    let gpu = crate::gpu::GpuContext::new()?;
    let adapter = gpu.record.name.clone();
    let mut renderer = Renderer::new(gpu);
    let mut scenes = Vec::new();
    for scene in &matrix.compositions {
        let prepared = renderer.prepare_scene(scene)?;
        scenes.push((scene.clone(), prepared));
    }
    let stage = Stage { scenes, light_intensity, light_range, size: req.size };
    // Each side as the matrix sets its pipeline up (`[pipeline_settings]`: HDRP's light unit, the
    // URP asset; the light budget), forward and without MSAA: a match compares flat materials.
    let settings =
        CellSettings { engine: matrix.pipeline_settings, light_budget: matrix.light_budget, ..Default::default() };
    let side = |p, model| Side { pipeline: p, model, tonemap: matrix.tonemap_for(p), settings };
    let source = side(from_pipeline, from_model);
    let target = side(to_pipeline, to_model);
    let exposure = match space {
        MatchSpace::Display => 1.0,
        MatchSpace::Linear => {
            let grey = MaterialValues::new(0.0, 0.0, [0.5; 3]);
            let source_frames = frames(&mut renderer, &stage, &source, &grey)?;
            calibrate_exposure(&mut renderer, &stage, &grey, &source_frames, &target)?
        }
    };
    let options = FitOptions {
        refine_iterations: req.iterations,
        exposure: Some(exposure),
        params: ParamAxis::swept(to_model, &matrix.sweep.params),
        keep,
        ..Default::default()
    };
    let compositions: Vec<String> = matrix.compositions.iter().map(|s| s.name.clone()).collect();
    let key = MatchKey {
        from: req.from.clone(),
        to: req.to.clone(),
        space,
        size: req.size,
        iterations: req.iterations,
        matrix: matrix.hash.clone(),
        exposure,
        kept: keep,
        version: env!("CARGO_PKG_VERSION").into(),
    };
    let finished = resumable_rows(&req.out, &key, &compositions, req.resume)?;
    let mut cache = BasisCache::default();
    let mut rows = Vec::new();
    for (i, (preset, values)) in materials.iter().enumerate() {
        if let Some(row) = finished.get(i).filter(|r| r.preset == *preset && r.source == *values) {
            let (n, s, m) = (materials.len(), values.smoothness, values.metallic);
            eprintln!("[{}/{n}] {preset} s {s:.2} m {m:.2}: taken from the earlier match", i + 1);
            rows.push(row.clone());
            continue;
        }
        let source_frames = frames(&mut renderer, &stage, &source, values)?;
        let f = fit(&mut renderer, &stage, values, &source_frames, &target, space, &options, &mut cache)?;
        eprintln!(
            "[{}/{}] {preset} s {:.2} m {:.2}: FLIP {:.4} copied, {:.4} fitted (s {:.3} m {:.3})",
            i + 1,
            materials.len(),
            values.smoothness,
            values.metallic,
            f.before.flip,
            f.after.flip,
            f.values.smoothness,
            f.values.metallic
        );
        let frames = write_frames(&req.out, i, &compositions, req.size, &source_frames, &f.frames)?;
        rows.push(MatchRow {
            preset: preset.clone(),
            source: values.clone(),
            fitted: f.values,
            copied_error: f.before,
            fitted_error: f.after,
            renders: f.renders,
            frames,
        });
        let progress = MatchProgress { schema: MATCH_SCHEMA, key: key.clone(), rows: rows.clone() };
        write_json(&req.out.join(PROGRESS), &progress)?;
    }
    let record = MatchRecord {
        schema: MATCH_SCHEMA,
        from: req.from.clone(),
        to: req.to.clone(),
        space,
        compositions,
        size: req.size,
        exposure,
        kept: keep.names().into_iter().map(String::from).collect(),
        adapter,
        rows,
    };
    write_tables(&req.out, &record)
}

/// The journal of a match's finished rows, written after each.
const PROGRESS: &str = "tables/match.progress.json";

/// With `resume`, the rows an earlier match into `out` finished under the same `key` whose
/// frames are all still there, in order (the first that is not ends them). The previous match's
/// page and JSON are removed first: the frames about to be written would no longer be theirs.
fn resumable_rows(out: &Path, key: &MatchKey, compositions: &[String], resume: bool) -> Result<Vec<MatchRow>, Error> {
    for stale in ["index.html", "tables/match.json"] {
        remove_if_there(&out.join(stale))?;
    }
    let path = out.join(PROGRESS);
    if !resume || !path.exists() {
        return Ok(Vec::new());
    }
    let progress = crate::record::read_record::<MatchProgress>(&path, MATCH_SCHEMA).ok();
    let Some(progress) = progress.filter(|p| p.key == *key) else {
        eprintln!("match: {} is of another match or unreadable: fitting every row", path.display());
        return Ok(Vec::new());
    };
    let complete = |r: &MatchRow| {
        compositions.iter().all(|c| {
            crate::remap::sheet::KINDS
                .iter()
                .all(|k| out.join(crate::remap::sheet::frame_path(&r.frames, c, k)).is_file())
        })
    };
    Ok(progress.rows.into_iter().take_while(complete).collect())
}

fn remove_if_there(path: &Path) -> Result<(), Error> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::io_path("removing", path, e)),
        _ => Ok(()),
    }
}

/// The record and its tables into `out/tables`, the sheets, the curves and the page; JSON last, so
/// a complete JSON means a complete set.
fn write_tables(out: &Path, record: &MatchRecord) -> Result<(), Error> {
    let sheets = write_sheets(out, record)?;
    crate::remap::sheet::prune_stale(out, record.rows.len(), &sheets)?;
    let plot = "plots/smoothness.svg";
    write_atomic(&out.join(plot), crate::remap::plot::svg(record)?.as_bytes())?;
    write_atomic(&out.join("index.html"), crate::remap::page::html(record, plot, &sheets)?.as_bytes())?;
    let tables = out.join("tables");
    write_atomic(&tables.join("match.md"), record.markdown().as_bytes())?;
    write_atomic(&tables.join("match.csv"), record.csv().as_bytes())?;
    write_json(&tables.join("match.json"), record)?;
    eprintln!("match: {} (tables/, sheets/, plots/, frames/)", out.join("index.html").display());
    Ok(())
}
