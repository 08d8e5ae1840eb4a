//! The run loop: matrix → cells → plan → render → images → files. GPU resources are built once
//! per composition and pipeline; cells only rewrite uniforms.

use serde::Serialize;
use serde_json::json;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::cells::{expand, Cell, Expansion};
use super::store::*;
use crate::error::Error;
use crate::fsutil::{write_atomic, write_json};
use crate::gpu::GpuContext;
use crate::images::{encode, tonemap};
use crate::render::{CellParams, CellRender, Renderer};
use crate::spec::matrix::{hex, Filter, Matrix, ReferenceSpec};

#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Folder that holds runs (default `results`).
    pub results_root: PathBuf,
    pub out: Option<PathBuf>,
    pub resume: bool,
    /// (k, n): render only shard k of n (1-based).
    pub shard: Option<(u32, u32)>,
    pub only: Option<Filter>,
    pub progress: bool,
}

#[derive(Debug)]
pub struct RunSummary {
    pub dir: PathBuf,
    pub counts: RunCounts,
    pub wall_seconds: f64,
    pub adapter: String,
}

/// Cells of the matrix after `--only` and `--shard` (twins stay with the cell they copy).
pub fn select_cells(matrix: &Matrix, opts: &RunOptions) -> Expansion {
    let mut exp = expand(matrix);
    if let Some(f) = &opts.only {
        let before = exp.cells.len();
        exp.cells.retain(|c| super::cells::matches_filter(c, f));
        exp.filtered_out += before - exp.cells.len();
        // A twin whose original was filtered away becomes an original itself.
        let ids: std::collections::HashSet<_> = exp.cells.iter().map(|c| c.id.clone()).collect();
        super::cells::remark_twins(&mut exp.cells, &ids);
    }
    if let Some((k, n)) = opts.shard {
        exp.cells.retain(|c| {
            let owner = c.twin_of.as_ref().unwrap_or(&c.id);
            let h = Sha256::digest(owner.0.as_bytes());
            (u32::from_le_bytes([h[0], h[1], h[2], h[3]]) % n) + 1 == k
        });
    }
    exp
}

pub fn run(matrix: &Matrix, opts: &RunOptions) -> Result<RunSummary, Error> {
    let started = Instant::now();
    let exp = select_cells(matrix, opts);
    // Geometry first: a bad mesh or glTF file is bad input, found before any GPU work or output.
    let geometry = build_geometry(matrix, &exp)?;
    let gpu = GpuContext::new()?;
    let adapter = gpu.record.clone();
    let dir = RunDir::open(&opts.results_root, opts.out.as_deref(), &matrix.name, opts.resume)?;
    let mut record = RunRecord {
        shadematrix_version: env!("CARGO_PKG_VERSION").into(),
        status: RunStatus::Running,
        matrix: MatrixRecord {
            name: matrix.name.clone(),
            origin: matrix.origin.clone(),
            sha256: matrix.hash.clone(),
            image: [matrix.image.width, matrix.image.height],
            frames: matrix.timing.frames,
            warmup: matrix.timing.warmup,
            shard: opts.shard.map(|(k, n)| format!("{k}/{n}")),
            sheets: matrix.sheets.clone(),
        },
        adapter: adapter.clone(),
        started: chrono::Local::now().to_rfc3339(),
        finished: None,
        wall_seconds: None,
        counts: RunCounts {
            cells: exp.cells.len(),
            twins: exp.cells.iter().filter(|c| c.twin_of.is_some()).count(),
            pruned: exp.pruned.len(),
            filtered_out: exp.filtered_out,
            ..Default::default()
        },
        compositions: Vec::new(),
    };
    let run_json = dir.root.join(RUN_FILE);
    write_json(&run_json, &record)?;

    let mut renderer = Renderer::new(gpu);
    let bar = progress_bar(opts.progress, exp.cells.len() as u64);
    let result = render_all(matrix, &exp, geometry, &dir, &mut renderer, &mut record, &bar);
    bar.finish_and_clear();
    record.status = if result.is_ok() { RunStatus::Complete } else { RunStatus::Failed };
    record.finished = Some(chrono::Local::now().to_rfc3339());
    record.wall_seconds = Some(started.elapsed().as_secs_f64());
    write_json(&run_json, &record)?;
    result?;
    crate::report::build(&dir.root)?;
    Ok(RunSummary {
        dir: dir.root,
        counts: record.counts,
        wall_seconds: started.elapsed().as_secs_f64(),
        adapter: adapter.name,
    })
}

fn progress_bar(show: bool, len: u64) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// Meshes of every composition that has cells, in composition order (None: no cells).
fn build_geometry(matrix: &Matrix, exp: &Expansion) -> Result<Vec<Option<Vec<crate::geometry::Mesh>>>, Error> {
    matrix
        .compositions
        .iter()
        .enumerate()
        .map(|(ci, scene)| {
            if exp.cells.iter().any(|c| c.composition_index == ci) {
                crate::geometry::procedural::build_scene(scene).map(Some)
            } else {
                Ok(None)
            }
        })
        .collect()
}

fn render_all(
    matrix: &Matrix,
    exp: &Expansion,
    mut geometry: Vec<Option<Vec<crate::geometry::Mesh>>>,
    dir: &RunDir,
    renderer: &mut Renderer,
    record: &mut RunRecord,
    bar: &indicatif::ProgressBar,
) -> Result<(), Error> {
    let adapter_name = renderer.gpu.record.name.clone();
    for (ci, scene) in matrix.compositions.iter().enumerate() {
        let cells: Vec<&Cell> = exp.cells.iter().filter(|c| c.composition_index == ci).collect();
        let pending: Vec<&Cell> = cells
            .iter()
            .copied()
            .filter(|c| c.twin_of.is_none())
            .filter(|c| {
                let done = dir.cell_done(&c.id.0, &input_hash(matrix, c));
                if done {
                    record.counts.resumed += 1;
                    bar.inc(1);
                }
                !done
            })
            .collect();
        if cells.is_empty() {
            continue;
        }
        // A composition whose every cell is already done needs no GPU resources at all.
        let t0 = Instant::now();
        let meshes = geometry[ci].take().unwrap_or_default();
        let prepared = if pending.is_empty() { None } else { Some(renderer.upload_scene(scene, meshes)?) };
        let plan = super::plan::FramePlan::for_scene(scene);
        record.compositions.push(CompositionRecord {
            name: scene.name.clone(),
            origin: scene.origin.clone(),
            passes: plan.passes.iter().map(|s| s.to_string()).collect(),
            left_out: plan.left_out.clone(),
            triangles: prepared.as_ref().map(|p| p.triangle_count).unwrap_or(0),
            prepare_seconds: t0.elapsed().as_secs_f64(),
        });
        for cell in &pending {
            bar.set_message(cell.id.0.clone());
            let prepared = prepared.as_ref().expect("prepared when cells are pending");
            let params = CellParams {
                pipeline: cell.pipeline,
                model: cell.model(),
                surface: cell.surface(),
                light_intensity: cell.light_intensity,
                light_range: cell.light_range,
                width: cell.width,
                height: cell.height,
            };
            let render = renderer.render(prepared, &params, matrix.timing.frames, matrix.timing.warmup)?;
            if let Some(ReferenceSpec::Supersampled(k)) = matrix.reference {
                supersampled_reference(renderer, prepared, &params, k, &dir.cell_dir(&cell.id.0), cell)?;
            }
            write_cell(dir, matrix, cell, &render, &adapter_name)?;
            record.counts.rendered += 1;
            bar.inc(1);
        }
        for cell in cells.iter().filter(|c| c.twin_of.is_some()) {
            copy_twin(dir, matrix, cell)?;
            bar.inc(1);
        }
    }
    // Every image exists now: compare each cell with its reference, cells in parallel (each
    // reads its own and its reference's files and writes only into its own folder).
    use rayon::prelude::*;
    bar.set_message("metrics");
    exp.cells.par_iter().try_for_each(|cell| super::metrics::cell_metrics(matrix, dir, cell))
}

/// The same cell at k× the resolution, box-filtered down: reference.exr and reference.png.
fn supersampled_reference(
    renderer: &mut Renderer,
    prepared: &crate::render::PreparedScene,
    params: &CellParams,
    k: u32,
    cdir: &Path,
    cell: &Cell,
) -> Result<(), Error> {
    let max = renderer.gpu.device.limits().max_texture_dimension_2d;
    let (w, h) = (params.width * k, params.height * k);
    if w > max || h > max {
        // Recorded, not fatal: the metrics pass reports the reference as missing.
        return write_json(
            &cdir.join("reference_missing.json"),
            &json!({ "reason": format!("{w}×{h} exceeds the adapter's {max}") }),
        );
    }
    let big = renderer.render(prepared, &CellParams { width: w, height: h, ..*params }, 1, 0)?;
    let (pw, ph) = (params.width as usize, params.height as usize);
    let mut small = vec![0f32; pw * ph * 4];
    let norm = 1.0 / (k * k) as f32;
    for y in 0..ph {
        for x in 0..pw {
            for dy in 0..k as usize {
                for dx in 0..k as usize {
                    let src = ((y * k as usize + dy) * w as usize + x * k as usize + dx) * 4;
                    for c in 0..4 {
                        small[(y * pw + x) * 4 + c] += big.hdr[src + c] * norm;
                    }
                }
            }
        }
    }
    let (srgb, _) = tonemap::to_srgb8(&small, cell.pipeline.tonemap());
    write_atomic(&cdir.join("reference.exr"), &encode::exr_bytes(params.width, params.height, &small)?)?;
    write_atomic(&cdir.join("reference.png"), &encode::png_bytes(params.width, params.height, &srgb)?)
}

/// Hash of everything a cell's image depends on, so --resume re-renders changed cells.
pub fn input_hash(matrix: &Matrix, cell: &Cell) -> String {
    let scene = &matrix.compositions[cell.composition_index];
    let text = json!({
        "version": env!("CARGO_PKG_VERSION"),
        "cell": cell,
        "scene": scene,
        "frames": matrix.timing.frames,
        "reference": format!("{:?}", matrix.reference),
    });
    hex(&Sha256::digest(text.to_string().as_bytes()))
}

#[derive(Debug, Clone, Serialize)]
pub struct PixelStats {
    pub pixels: usize,
    pub subject_pixels: usize,
    pub nan: usize,
    pub inf: usize,
    pub negative: usize,
    /// Mean linear luminance over subject pixels (None when the subject is not visible).
    pub subject_mean_luminance: Option<f64>,
    pub max_luminance: f64,
}

pub fn pixel_stats(r: &CellRender) -> PixelStats {
    let mut s = PixelStats {
        pixels: r.roles.len(),
        subject_pixels: 0,
        nan: 0,
        inf: 0,
        negative: 0,
        subject_mean_luminance: None,
        max_luminance: 0.0,
    };
    let mut sum = 0.0;
    for (px, role) in r.hdr.chunks_exact(4).zip(&r.roles) {
        let rgb = &px[..3];
        s.nan += rgb.iter().filter(|v| v.is_nan()).count();
        s.inf += rgb.iter().filter(|v| v.is_infinite()).count();
        s.negative += rgb.iter().filter(|v| **v < 0.0).count();
        let l = crate::color::luminance([rgb[0] as f64, rgb[1] as f64, rgb[2] as f64]);
        if l.is_finite() {
            s.max_luminance = s.max_luminance.max(l);
        }
        if *role == crate::render::uniforms::ROLE_SUBJECT {
            s.subject_pixels += 1;
            sum += l;
        }
    }
    if s.subject_pixels > 0 {
        s.subject_mean_luminance = Some(sum / s.subject_pixels as f64);
    }
    s
}

fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    Some(s[s.len() / 2])
}

fn cell_json(matrix: &Matrix, cell: &Cell) -> serde_json::Value {
    let p = cell.pipeline;
    json!({
        "id": cell.id,
        "input_hash": input_hash(matrix, cell),
        "matrix_sha256": matrix.hash,
        "composition": cell.composition,
        "pipeline": p,
        "path": cell.path,
        "shader": cell.shader,
        "shader_source": cell.model().source_path,
        "preset": cell.preset,
        "sliders": cell.material,
        "shader_inputs": surface_json(cell),
        "key_light": {
            "intensity": cell.light_intensity,
            "range": cell.light_range,
            "intensity_scale": p.intensity_scale(),
            "attenuation": p.attenuation(),
        },
        "image": { "width": cell.width, "height": cell.height, "exr": "image.exr", "png": "image.png" },
        "twin_of": cell.twin_of,
    })
}

/// The model's inputs as the shader receives them, with its parameters by name.
fn surface_json(cell: &Cell) -> serde_json::Value {
    let model = cell.model();
    let s = cell.surface();
    let params: serde_json::Map<String, serde_json::Value> =
        model.params.iter().map(|p| (p.name.to_string(), json!(s.params[p.slot]))).collect();
    json!({
        "base_color_linear": s.base_color.to_array(),
        "metallic": s.metallic,
        "smoothness": s.smoothness,
        "specular": s.specular.to_array(),
        "params": params,
        "mapping": model.mapping,
    })
}

fn write_cell(dir: &RunDir, matrix: &Matrix, cell: &Cell, r: &CellRender, adapter: &str) -> Result<(), Error> {
    let cdir = dir.cell_dir(&cell.id.0);
    let t0 = Instant::now();
    let exr = encode::exr_bytes(r.width, r.height, &r.hdr)?;
    let (srgb, exposure) = tonemap::to_srgb8(&r.hdr, cell.pipeline.tonemap());
    let png = encode::png_bytes(r.width, r.height, &srgb)?;
    let encode_ms = t0.elapsed().as_secs_f64() * 1e3;
    write_atomic(&cdir.join("image.exr"), &exr)?;
    write_atomic(&cdir.join("image.png"), &png)?;
    let mut v = cell_json(matrix, cell);
    v["adapter"] = json!(adapter);
    v["tonemap"] = json!({ "kind": cell.pipeline.tonemap(), "exposure": exposure });
    v["stats"] = json!(pixel_stats(r));
    v["timing"] = timing_json(r, matrix.timing.warmup, encode_ms);
    write_json(&cdir.join(CELL_FILE), &v)
}

fn series(ms: &[f64]) -> serde_json::Value {
    json!({
        "frame_ms": ms,
        "median_ms": median(ms),
        "min_ms": ms.iter().cloned().reduce(f64::min),
        "max_ms": ms.iter().cloned().reduce(f64::max),
    })
}

/// GPU pass time from timestamp queries where the adapter has them (else reported missing, with
/// the reason), CPU wall time submit→idle, and the CPU cost of readback and encoding.
fn timing_json(r: &CellRender, warmup: u32, encode_ms: f64) -> serde_json::Value {
    let gpu = match &r.gpu_pass_ms {
        Some(ms) => {
            let mut g = series(ms);
            g["kind"] = json!("timestamp_query: forward render pass, begin to end");
            g
        }
        None => json!({ "missing": "the adapter has no timestamp queries; see cpu_wall" }),
    };
    let mut cpu = series(&r.frame_ms);
    cpu["kind"] = json!("CPU wall time from queue submit to device idle");
    json!({
        "frames": r.frame_ms.len(),
        "warmup": warmup,
        "gpu": gpu,
        "cpu_wall": cpu,
        "readback_ms": r.readback_ms,
        "encode_ms": encode_ms,
    })
}

/// A twin's images are its original's: copy them, and say so in cell.json.
fn copy_twin(dir: &RunDir, matrix: &Matrix, cell: &Cell) -> Result<(), Error> {
    let original = cell.twin_of.as_ref().expect("twin");
    let (from, to) = (dir.cell_dir(&original.0), dir.cell_dir(&cell.id.0));
    for name in ["image.exr", "image.png"] {
        let bytes = std::fs::read(from.join(name)).map_err(|e| Error::io_path("reading", &from.join(name), e))?;
        write_atomic(&to.join(name), &bytes)?;
    }
    let mut v = cell_json(matrix, cell);
    let orig: serde_json::Value = std::fs::read_to_string(from.join(CELL_FILE))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_default();
    for k in ["adapter", "tonemap", "stats", "timing"] {
        v[k] = orig[k].clone();
    }
    v["note"] = json!(format!(
        "not rendered: `{}` ignores the axes this cell differs in; images copied from {original}",
        cell.shader
    ));
    write_json(&to.join(CELL_FILE), &v)
}

pub fn default_results_root() -> PathBuf {
    Path::new("results").to_path_buf()
}
