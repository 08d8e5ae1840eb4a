//! The run: cells stream through the stages. The thread that owns the device renders; finished
//! frames go through a bounded queue to the encode workers, and encoded cells through another to
//! the metric workers, so the CPU encodes and compares while the GPU (or lavapipe) renders the next
//! cells. Memory is bounded by the queue depths, not by the number of cells: a cell whose reference
//! is not final yet is parked without its pixels and re-read from its files when the reference is.
//! References are rendered first in each composition, so parking is rare.

use crossbeam_channel::{bounded, Receiver, Sender};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use super::cell_cache::CellCache;
use super::cell_key::CellKeys;
use super::clock::{StageClock, ThreadTimer};
use super::encode::{copy_images, encode_cell, twin_record, CellImages, RenderedCell, RenderedReference, StudyImages};
use super::metrics::{compare_cell, measure_study, reference_source, ReferenceCache, ReferenceSource};
use crate::cells::{expand, matches_filter, reference_cell_id, remark_twins, Cell, CellId, Expansion};
use crate::declarations::matrix::{Filter, Matrix, ReferenceSpec};
use crate::declarations::study::Approximation;
use crate::error::Error;
use crate::fsutil::write_json;
use crate::gpu::GpuContext;
use crate::plan::FramePlan;
use crate::record::cell::{CellMetrics, CellRecord, ReferenceRecord};
use crate::record::run::{CompositionRecord, MatrixRecord, RunCounts, RunStatus, StageTimes};
use crate::record::{RunDir, RunRecord, CELL_FILE, RUN_FILE, RUN_SCHEMA};
use crate::render::{CellParams, Renderer};

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
    /// Threads for the encode and metric stages (default: from the core count).
    pub workers: Option<Workers>,
    /// The cross-run cell cache (`run::cell_cache`): cells found there are taken, not rendered,
    /// and every finished cell is stored. None: no cache.
    pub cache: Option<PathBuf>,
    /// The most cells the matrix may expand to (`--max-cells`; None: `cells::DEFAULT_MAX_CELLS`).
    pub max_cells: Option<u64>,
    /// Writes the run's reports once its cells are finished, while the run still holds its
    /// folder's lock; `run.json` says `complete` only after it (the CLI passes `report::build`,
    /// which this stage cannot import). None: no reports, complete when the cells are.
    pub reports: Option<ReportWriter>,
    /// Cells taken from the cache (or kept by --resume) render their timed frames again, and
    /// their records take the new timings; images and metrics stay.
    pub retime: bool,
    /// Draw every pass of every cell (`--no-reuse`): no shadow maps, prepass, SSAO, probe captures
    /// or fixed-object layer taken from the cell before. The images are the same bytes either way.
    pub no_reuse: bool,
}

/// What writes a finished run folder's reports (`report::build`).
pub type ReportWriter = fn(&Path) -> Result<(), Error>;

/// Threads per CPU stage and the depth of each queue.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Workers {
    pub encode: usize,
    pub metrics: usize,
    pub queue_depth: usize,
}

impl Workers {
    /// Metric and encode workers on every core: a worker with nothing queued sleeps, so the two
    /// pools cost nothing while the other stage is the busy one, and whichever stage is behind
    /// gets every core. (A 4090-cell shard of thesis.toml on an H200 spent 49.6 s of CPU encoding
    /// against 92.5 s for metrics; with a quarter of the cores encoding, its render thread waited
    /// 12.6 s on a full encode queue while cores idled.) Each queue holds two jobs per consumer:
    /// enough to keep them busy, little enough memory.
    pub fn for_cores(cores: usize) -> Workers {
        let metrics = cores.max(1);
        let encode = cores.max(1);
        Workers { encode, metrics, queue_depth: 2 * metrics.max(encode) }
    }
}

#[derive(Debug)]
pub struct RunSummary {
    pub dir: PathBuf,
    /// Cells of the resumed run that are not in this expansion, moved to `STALE_DIR`.
    pub set_aside: Vec<String>,
    pub counts: RunCounts,
    pub wall_seconds: f64,
    pub adapter: String,
    pub stages: StageTimes,
}

/// Cells of the matrix after `--only` and `--shard` (twins stay with the cell they copy).
pub fn select_cells(matrix: &Matrix, opts: &RunOptions) -> Expansion {
    let mut exp = expand(matrix);
    if let Some(f) = &opts.only {
        let before = exp.cells.len();
        exp.cells.retain(|c| matches_filter(c, f));
        exp.filtered_out += before - exp.cells.len();
        // A twin whose original was filtered away becomes an original itself.
        let ids: HashSet<_> = exp.cells.iter().map(|c| c.id.clone()).collect();
        remark_twins(&mut exp.cells, &ids, matrix);
    }
    if let Some(shard) = opts.shard {
        super::shard::select(matrix, &mut exp, shard);
    }
    exp
}

pub fn run(matrix: &Matrix, opts: &RunOptions) -> Result<RunSummary, Error> {
    let started = Instant::now();
    crate::cells::check_size(matrix, opts.max_cells.unwrap_or(crate::cells::DEFAULT_MAX_CELLS))?;
    let exp = select_cells(matrix, opts);
    check_id_lengths(matrix, &exp)?;
    warn_of_another_matrix(matrix, &exp);
    // Geometry first: a bad mesh or glTF file is bad input, found before any GPU work or output.
    let (geometry, bake_points): (Vec<_>, Vec<_>) = build_geometry_and_bakes(matrix, &exp)?.into_iter().unzip();
    let gpu = GpuContext::new()?;
    check_bake_sizes(matrix, &bake_points, &gpu)?;
    let adapter = gpu.record.clone();
    let dir = RunDir::open(&opts.results_root, opts.out.as_deref(), &matrix.name, opts.resume)?;
    let set_aside = match opts.resume {
        true => continue_run(&dir, matrix, opts, &exp)?,
        false => Vec::new(),
    };
    let mut record = RunRecord {
        schema: RUN_SCHEMA,
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
            only: opts.only.clone(),
            sheets: matrix.sheets.clone(),
            asserts: matrix.asserts.clone(),
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
            support: exp.support.len(),
            ..Default::default()
        },
        compositions: Vec::new(),
        stages: None,
        support: exp.support.clone(),
        merged_from: Vec::new(),
        pruned: exp.pruned.clone(),
        cells: exp.cells.iter().map(|c| c.id.clone()).collect(),
    };
    let run_json = dir.root.join(RUN_FILE);
    write_json(&run_json, &record)?;

    let workers = opts
        .workers
        .unwrap_or_else(|| Workers::for_cores(std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)));
    let clock = StageClock::default();
    let bar = progress_bar(opts.progress, exp.cells.len() as u64);
    let keys = CellKeys::new(matrix, &exp.cells.iter().collect::<Vec<_>>(), &adapter);
    let cache = opts.cache.clone().map(CellCache::new);
    let reuse = Reuse { keys, cache, retime: opts.retime };
    let mut stream = Stream::new(matrix, &exp, &dir, adapter.name.clone(), &clock, &bar, reuse);
    let gpu_metrics = matrix
        .metrics
        .on_gpu(&gpu.record.device_type)
        .then(|| crate::compare::gpu::GpuMetrics::new(&gpu.device, &gpu.queue, gpu.constants));
    stream.gpu_metrics = gpu_metrics;
    let mut renderer = Renderer::new(gpu);
    renderer.reuse = !opts.no_reuse;
    // Bakes are kept beside the truths (`--no-cache`: this run's alone).
    renderer.bake_cache = opts
        .cache
        .as_ref()
        .map(|_| crate::render::gi::cache::BakeCache::new(super::truth_cache::default_dir(&dir.root).join("bakes")));
    let result = stream.run(&mut renderer, geometry, workers, &mut record);
    bar.finish_and_clear();
    record.counts.rendered = stream.rendered.load(Ordering::Relaxed);
    record.counts.resumed = stream.resumed.load(Ordering::Relaxed);
    record.counts.cached = stream.cached.load(Ordering::Relaxed);
    // Complete only once the reports exist.
    record.status = match (&result, opts.reports) {
        (Err(_), _) => RunStatus::Failed,
        (Ok(()), Some(_)) => RunStatus::Reporting,
        (Ok(()), None) => RunStatus::Complete,
    };
    record.finished = Some(chrono::Local::now().to_rfc3339());
    record.wall_seconds = Some(started.elapsed().as_secs_f64());
    let stages = clock.times(workers.encode, workers.metrics, workers.queue_depth);
    record.stages = Some(stages.clone());
    // The first failure is the one to report: on a full disk, the cell write that failed, not the
    // run.json write that failed after it.
    let recorded = write_json(&run_json, &record);
    result?;
    recorded?;
    if let Some(reports) = opts.reports {
        reports(&dir.root)?;
        record.status = RunStatus::Complete;
        write_json(&run_json, &record)?;
    }
    Ok(RunSummary {
        set_aside,
        dir: dir.root,
        counts: record.counts,
        wall_seconds: started.elapsed().as_secs_f64(),
        adapter: adapter.name,
        stages,
    })
}

/// A reference run is compared with cell by cell, by id: one made from another matrix is allowed
/// (a baseline of the matrix before an edit), but said, with how many of this run's cells it has.
fn warn_of_another_matrix(matrix: &Matrix, exp: &Expansion) {
    let Some(ReferenceSpec::Run(dir)) = &matrix.reference else { return };
    let Ok(other) = RunRecord::load(dir) else { return };
    if other.matrix.sha256 == matrix.hash {
        return;
    }
    let found = exp.cells.iter().filter(|c| dir.join("cells").join(&c.id.0).join(CELL_FILE).is_file()).count();
    eprintln!(
        "warning: the reference run {} was made from another matrix (`{}`, {}, sha256 {}…); cells are compared by \
         id: {found} of this run's {} cells are there, the others have no comparison",
        dir.display(),
        other.matrix.name,
        other.matrix.origin,
        &other.matrix.sha256[..12.min(other.matrix.sha256.len())],
        exp.cells.len()
    );
}

/// The longest id (`cells::MAX_ID_BYTES`): a folder name with room for its temporary names in the
/// 255 bytes most file systems allow (ext4, APFS, NTFS).
const MAX_FILE_NAME: usize = crate::cells::MAX_ID_BYTES;

/// Every cell id is a folder name: one too long for the file system, or for the temporary names
/// the cache and merge give it, is bad input, found before anything renders rather than as an
/// I/O error half-way through the run (or a cache entry dropped and rendered again every run).
fn check_id_lengths(matrix: &Matrix, exp: &Expansion) -> Result<(), Error> {
    match exp.cells.iter().find(|c| c.id.0.len() > MAX_FILE_NAME) {
        Some(c) => Err(crate::error::InputError::new(
            matrix.origin.clone(),
            format!(
                "cell id `{}` is {} bytes, longer than a file name may be ({MAX_FILE_NAME}); shorten the \
                 composition, shader or parameter names, or sweep fewer parameters at once",
                c.id,
                c.id.0.len()
            ),
        )
        .into()),
        None => Ok(()),
    }
}

/// Where `--resume` moves the cells of the earlier run that this expansion no longer has.
pub const STALE_DIR: &str = "cells-not-in-expansion";

/// `--resume`: the folder must hold a run of this very matrix (and shard); its cells that are no
/// longer in the expansion (another `--only`) leave `cells/` for `STALE_DIR`, so reports list
/// exactly what `run.json` counts. Returns the ids moved.
fn continue_run(dir: &RunDir, matrix: &Matrix, opts: &RunOptions, exp: &Expansion) -> Result<Vec<String>, Error> {
    if !dir.root.join(RUN_FILE).is_file() {
        return Ok(Vec::new());
    }
    let earlier = RunRecord::load(&dir.root)?;
    let shown = dir.root.join(RUN_FILE).display().to_string();
    if earlier.matrix.sha256 != matrix.hash {
        return Err(crate::error::InputError::at_key(
            shown,
            "matrix.sha256",
            format!(
                "--resume: this run is of matrix `{}` ({}, SHA-256 {}); {} (SHA-256 {}) differs. Resume with the \
                 same matrix file, or start a new run with another --out",
                earlier.matrix.name, earlier.matrix.origin, earlier.matrix.sha256, matrix.origin, matrix.hash
            ),
        )
        .into());
    }
    let shard = opts.shard.map(|(k, n)| format!("{k}/{n}"));
    if earlier.matrix.shard != shard {
        let name = |s: &Option<String>| s.clone().unwrap_or_else(|| "unsharded".into());
        return Err(crate::error::InputError::at_key(
            shown,
            "matrix.shard",
            format!(
                "--resume: this run is {}; the command asks for {}: give the same --shard",
                name(&earlier.matrix.shard),
                name(&shard)
            ),
        )
        .into());
    }
    let keep: HashSet<&str> = exp.cells.iter().map(|c| c.id.0.as_str()).collect();
    let cells = dir.root.join("cells");
    let mut moved = Vec::new();
    let entries = std::fs::read_dir(&cells).map_err(|e| Error::io_path("reading", &cells, e))?;
    for e in entries.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().to_string();
        if name.starts_with('.') || keep.contains(name.as_str()) || !e.file_type().is_ok_and(|t| t.is_dir()) {
            continue;
        }
        let to = dir.root.join(STALE_DIR).join(&name);
        std::fs::create_dir_all(dir.root.join(STALE_DIR)).map_err(|e| Error::io_path("creating", &to, e))?;
        if to.exists() {
            std::fs::remove_dir_all(&to).map_err(|e| Error::io_path("replacing", &to, e))?;
        }
        std::fs::rename(e.path(), &to).map_err(|e| Error::io_path("moving aside", &to, e))?;
        moved.push(name);
    }
    moved.sort();
    Ok(moved)
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

/// Meshes of every composition that has cells and loads a mesh file or bakes, in composition
/// order, with the points its bake gathers (lightmap texels and probes). None: no cells, or
/// built-in meshes only that do not bake. Files are input and are checked here, before any GPU
/// work, and so is a baking composition's lightmap size; other built-in meshes are built when a
/// cell of theirs renders (`render_all`), so a run whose cells all come from the cache or an
/// earlier run builds none of those (medusa and spikes take about 1.6 s each).
fn build_geometry_and_bakes(matrix: &Matrix, exp: &Expansion) -> Result<Vec<GeometryAndBake>, Error> {
    matrix
        .compositions
        .iter()
        .enumerate()
        .map(|(ci, scene)| {
            use crate::declarations::scene::MeshSpec;
            let loads_files =
                scene.objects.iter().any(|o| matches!(o.mesh, MeshSpec::Gltf { .. } | MeshSpec::GltfPrimitive { .. }));
            let has_cells = exp.cells.iter().any(|c| c.composition_index == ci);
            if !has_cells || !(loads_files || scene.gi.is_some()) {
                return Ok((None, None));
            }
            let meshes = crate::geometry::procedural::build_scene(scene)?;
            // A lightmap larger than allowed is bad input too: found here, not at render time.
            let points = match &scene.gi {
                Some(gi) => {
                    let atlas = crate::geometry::lightmap_uv::unwrap(scene, &mut meshes.clone(), gi)?;
                    Some(atlas.texels.len() + gi.probes.as_ref().map_or(0, |g| g.positions().len()))
                }
                None => None,
            };
            Ok((Some(meshes), points))
        })
        .collect()
}

type GeometryAndBake = (Option<Vec<crate::geometry::Mesh>>, Option<usize>);

/// Each baking composition's sums fit one storage buffer binding of the adapter: a bake past it
/// failed with a device error half-way through the run (155 MB of sums against lavapipe's
/// 128 MiB at texels_per_unit 200). Bad input for this adapter, refused before the run folder.
fn check_bake_sizes(matrix: &Matrix, points: &[Option<usize>], gpu: &GpuContext) -> Result<(), Error> {
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    let per_point = (crate::render::truth::bake::BAKE_STRIDE * 16) as u64;
    for (scene, n) in matrix.compositions.iter().zip(points) {
        let Some(n) = n else { continue };
        let bytes = *n as u64 * per_point;
        if bytes > limit {
            return Err(crate::error::InputError::at_key(
                &scene.origin,
                "gi.texels_per_unit",
                format!(
                    "the bake gathers {n} points ({bytes} bytes of sums), past the {limit} bytes this adapter binds \
                     ({}): lower texels_per_unit or the probe counts",
                    gpu.record.name
                ),
            )
            .into());
        }
    }
    Ok(())
}

/// An encoded cell on its way to the metric workers.
struct MetricsJob<'a> {
    cell: &'a Cell,
    record: CellRecord,
    /// The cell's pixels, when they are still in memory (dropped when the job is parked).
    images: Option<CellImages>,
    /// Why the supersampled reference is missing, when it is.
    reference_missing: Option<String>,
    /// The approximation study's frames, to measure against the same reference.
    study: Vec<StudyImages>,
}

/// Which cells' images are final, and who waits for which.
#[derive(Default)]
struct Tracker<'a> {
    final_images: HashSet<CellId>,
    /// Metric jobs parked until their reference cell's images are final.
    waiting: HashMap<CellId, Vec<MetricsJob<'a>>>,
    /// Twins waiting for their original's images.
    twins: HashMap<CellId, Vec<&'a Cell>>,
}

/// A timed frame series: CPU wall, GPU total and GPU per pass (`CellRender`'s).
type FrameTimings = (Vec<f64>, Option<Vec<f64>>, Option<Vec<(crate::plan::Pass, Vec<f64>)>>);

/// What lets a run reuse finished cells: their keys, the cache, and whether to time them again.
struct Reuse {
    keys: CellKeys,
    cache: Option<CellCache>,
    retime: bool,
}

struct Stream<'a> {
    matrix: &'a Matrix,
    exp: &'a Expansion,
    dir: &'a RunDir,
    adapter: String,
    clock: &'a StageClock,
    bar: &'a indicatif::ProgressBar,
    cells: HashSet<CellId>,
    references: ReferenceCache,
    tracker: Mutex<Tracker<'a>>,
    abort: AtomicBool,
    first_error: Mutex<Option<Error>>,
    rendered: AtomicUsize,
    resumed: AtomicUsize,
    cached: AtomicUsize,
    keys: CellKeys,
    cache: Option<CellCache>,
    retime: bool,
    /// Finished cells (resumed or cached) whose timed frames render again (`--retime`).
    retiming: HashSet<CellId>,
    /// FLIP and SSIM on the device (`metrics = "gpu"`), else on the CPU.
    gpu_metrics: Option<crate::compare::gpu::GpuMetrics>,
    /// Truths kept across cells and runs (beside the run folders), when the matrix compares with one.
    truth_cache: Option<super::truth_cache::TruthCache>,
    /// Each composition's frame plan, built once: the renderer, the records and run.json read it.
    plans: Vec<FramePlan>,
    /// The truth store's entry digests checked this run, by key (None: no entry).
    truth_digests: Mutex<HashMap<String, Option<String>>>,
    /// Cells whose cache entry was compared with another truth: stored in its place when finished.
    replacing: Mutex<HashSet<CellId>>,
}

impl<'a> Stream<'a> {
    fn new(
        matrix: &'a Matrix,
        exp: &'a Expansion,
        dir: &'a RunDir,
        adapter: String,
        clock: &'a StageClock,
        bar: &'a indicatif::ProgressBar,
        reuse: Reuse,
    ) -> Stream<'a> {
        let Reuse { keys, cache, retime } = reuse;
        let truth_cache = matches!(matrix.reference, Some(ReferenceSpec::Truth(_))).then(|| match &cache {
            Some(_) => super::truth_cache::TruthCache::new(super::truth_cache::default_dir(&dir.root)),
            // `--no-cache`: nothing from earlier runs; truths are still shared within this one.
            None => super::truth_cache::TruthCache::ephemeral(super::truth_cache::private_dir(&dir.root)),
        });
        Stream {
            truth_digests: Mutex::new(HashMap::new()),
            replacing: Mutex::new(HashSet::new()),
            truth_cache,
            plans: matrix
                .compositions
                .iter()
                .enumerate()
                .map(|(ci, scene)| {
                    let engines: Vec<_> =
                        exp.cells.iter().filter(|c| c.composition_index == ci).map(|c| c.pipeline_settings).collect();
                    FramePlan::for_scene(scene).with_engines(&engines)
                })
                .collect(),
            matrix,
            exp,
            dir,
            adapter,
            clock,
            bar,
            cells: exp.cells.iter().map(|c| c.id.clone()).collect(),
            references: ReferenceCache::new(8),
            tracker: Mutex::new(Tracker::default()),
            abort: AtomicBool::new(false),
            first_error: Mutex::new(None),
            rendered: AtomicUsize::new(0),
            resumed: AtomicUsize::new(0),
            cached: AtomicUsize::new(0),
            keys,
            cache,
            retime,
            retiming: HashSet::new(),
            gpu_metrics: None,
        }
    }

    fn tracker(&self) -> std::sync::MutexGuard<'_, Tracker<'a>> {
        self.tracker.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Whether a cached cell was compared with the truth the truth store holds now under the same
    /// key (the same entry digest, read from its manifest once per run); a cell without a truth
    /// passes.
    fn compared_with_stored_truth(&self, record: &CellRecord) -> bool {
        let Some(t) = &record.truth else { return true };
        let Some(cache) = &self.truth_cache else { return false };
        if t.store_key.is_empty() {
            return false;
        }
        let mut verified = self.truth_digests.lock().unwrap_or_else(|e| e.into_inner());
        let digest = verified.entry(t.store_key.clone()).or_insert_with(|| cache.digest(&t.store_key));
        digest.as_deref() == Some(t.store_sha256.as_str())
    }

    fn fail(&self, e: Error) {
        self.abort.store(true, Ordering::SeqCst);
        let mut first = self.first_error.lock().unwrap_or_else(|e| e.into_inner());
        if first.is_none() {
            *first = Some(e);
        }
    }

    fn aborted(&self) -> bool {
        self.abort.load(Ordering::SeqCst)
    }

    fn run(
        &mut self,
        renderer: &mut Renderer,
        geometry: Vec<Option<Vec<crate::geometry::Mesh>>>,
        workers: Workers,
        record: &mut RunRecord,
    ) -> Result<(), Error> {
        // Resume and the cache: finished cells are final from the start; twins of unfinished
        // originals wait.
        {
            let mut done = Vec::new();
            let mut t = self.tracker.lock().unwrap_or_else(|e| e.into_inner());
            for c in &self.exp.cells {
                let key = self.keys.get(&c.id);
                let found = if self.dir.cell_done(&c.id.0, key) {
                    self.resumed.fetch_add(1, Ordering::Relaxed);
                    true
                } else if let Some(cache) = self.cache.as_ref().filter(|cache| cache.contains(key)) {
                    match cache.take(key) {
                        Some((record, entry)) if self.compared_with_stored_truth(&record) => {
                            super::cell_cache::write_entry(
                                &entry,
                                record,
                                &self.dir.cell_dir(&c.id.0),
                                &self.matrix.hash,
                            )?;
                            self.cached.fetch_add(1, Ordering::Relaxed);
                            true
                        }
                        // Its metrics are of a truth no longer stored: measured again, and the
                        // entry replaced when the cell finishes.
                        Some(_) => {
                            self.replacing.lock().unwrap_or_else(|e| e.into_inner()).insert(c.id.clone());
                            false
                        }
                        None => false,
                    }
                } else {
                    false
                };
                if found {
                    t.final_images.insert(c.id.clone());
                    self.bar.inc(1);
                    if c.twin_of.is_none() {
                        done.push(c.id.clone());
                    }
                } else if let Some(original) = &c.twin_of {
                    t.twins.entry(original.clone()).or_default().push(c);
                }
            }
            drop(t);
            if self.retime {
                self.retiming = done.into_iter().collect();
            }
        }
        let this = &*self;
        this.stream(renderer, geometry, workers, record)
    }

    fn stream(
        &self,
        renderer: &mut Renderer,
        geometry: Vec<Option<Vec<crate::geometry::Mesh>>>,
        workers: Workers,
        record: &mut RunRecord,
    ) -> Result<(), Error> {
        let (encode_tx, encode_rx) = bounded::<RenderedCell<'a>>(workers.queue_depth);
        let (metrics_tx, metrics_rx) = bounded::<MetricsJob<'a>>(workers.queue_depth);
        let render_result = std::thread::scope(|s| {
            for _ in 0..workers.encode {
                let (rx, tx) = (encode_rx.clone(), metrics_tx.clone());
                s.spawn(move || self.encode_worker(rx, tx));
            }
            for _ in 0..workers.metrics {
                let rx = metrics_rx.clone();
                s.spawn(move || self.metrics_worker(rx));
            }
            drop(encode_rx);
            drop(metrics_rx);
            // Twins whose original finished in an earlier run are copied now.
            let resumed_originals: Vec<CellId> = {
                let t = self.tracker();
                t.twins.keys().filter(|o| t.final_images.contains(*o)).cloned().collect()
            };
            for original in resumed_originals {
                if let Err(e) = self.release_resumed_twins(&original, &metrics_tx) {
                    self.fail(e);
                }
            }
            drop(metrics_tx);
            let r = self.render_all(renderer, geometry, record, &encode_tx);
            drop(encode_tx);
            r
        });
        if let Err(e) = render_result {
            self.fail(e);
        }
        if let Some(e) = self.first_error.lock().unwrap_or_else(|e| e.into_inner()).take() {
            return Err(e);
        }
        // Nothing should be left waiting: every cell of the run became final. Anything that is
        // has a reference that failed to appear, and is recorded as such rather than lost.
        let left: Vec<MetricsJob> = self.tracker().waiting.drain().flat_map(|(_, v)| v).collect();
        for job in left {
            self.finish(job, CellMetrics::without_reference("the reference cell was not rendered"), None)?;
        }
        Ok(())
    }

    /// The render thread: every pending original, references first in each composition. A
    /// composition's meshes are built on another thread while the one before renders.
    fn render_all(
        &self,
        renderer: &mut Renderer,
        geometry: Vec<Option<Vec<crate::geometry::Mesh>>>,
        record: &mut RunRecord,
        encode_tx: &Sender<RenderedCell<'a>>,
    ) -> Result<(), Error> {
        let pending_in = |ci: usize| -> Vec<&'a Cell> {
            let t = self.tracker();
            self.exp
                .cells
                .iter()
                .filter(|c| c.composition_index == ci)
                .filter(|c| c.twin_of.is_none() && (!t.final_images.contains(&c.id) || self.retiming.contains(&c.id)))
                .collect()
        };
        // Cells become final only as their own composition renders: what is pending now is what
        // each composition will find pending.
        let needs: Vec<bool> = (0..self.matrix.compositions.len()).map(|ci| !pending_in(ci).is_empty()).collect();
        let (mesh_tx, mesh_rx) = bounded::<(usize, Result<Vec<crate::geometry::Mesh>, Error>)>(1);
        std::thread::scope(|s| {
            let compositions = &self.matrix.compositions;
            let needs = &needs;
            s.spawn(move || {
                let mut geometry = geometry;
                for (ci, scene) in compositions.iter().enumerate().filter(|(ci, _)| needs[*ci]) {
                    let meshes = match geometry[ci].take() {
                        Some(m) => Ok(m),
                        None => crate::geometry::procedural::build_scene(scene),
                    };
                    let failed = meshes.is_err();
                    // The render thread stopped (an error, or done): nothing more to build.
                    if mesh_tx.send((ci, meshes)).is_err() || failed {
                        return;
                    }
                }
            });
            self.render_compositions(renderer, mesh_rx, record, encode_tx, &pending_in)
        })
    }

    fn render_compositions(
        &self,
        renderer: &mut Renderer,
        meshes: Receiver<(usize, Result<Vec<crate::geometry::Mesh>, Error>)>,
        record: &mut RunRecord,
        encode_tx: &Sender<RenderedCell<'a>>,
        pending_in: &dyn Fn(usize) -> Vec<&'a Cell>,
    ) -> Result<(), Error> {
        let references = self.reference_cells();
        for (ci, scene) in self.matrix.compositions.iter().enumerate() {
            if !self.exp.cells.iter().any(|c| c.composition_index == ci) {
                continue;
            }
            let mut pending = pending_in(ci);
            pending.sort_by_key(|c| !references.contains(&c.id));
            // A composition whose every cell is already done needs no GPU resources at all.
            let t0 = Instant::now();
            let prepared = if pending.is_empty() {
                None
            } else {
                let built = match meshes.recv() {
                    Ok((built_for, built)) if built_for == ci => built?,
                    _ => {
                        return Err(Error::Other(format!("the meshes of composition `{}` were not built", scene.name)))
                    }
                };
                Some(renderer.upload_planned(scene, self.plans[ci].clone(), built)?)
            };
            let plan = &self.plans[ci];
            record.compositions.push(CompositionRecord {
                name: scene.name.clone(),
                origin: scene.origin.clone(),
                passes: plan.passes.iter().map(|s| s.to_string()).collect(),
                left_out: plan.left_out.clone(),
                triangles: prepared.as_ref().map(|p| p.triangle_count).unwrap_or(0),
                prepare_seconds: t0.elapsed().as_secs_f64(),
            });
            StageClock::add(&self.clock.prepare, t0);
            let Some(prepared) = prepared else { continue };
            // The cell timed for each timing class, and the frame timings it measured.
            let mut timed: HashMap<String, (CellId, FrameTimings)> = HashMap::new();
            for cell in pending {
                if self.aborted() {
                    return Ok(());
                }
                self.bar.set_message(cell.id.0.clone());
                let params = CellParams::of(cell);
                // Decided on the CPU before any of the cell's GPU work.
                let plan = renderer.plan(&prepared, &params)?;
                let t = Instant::now();
                let retime = self.retiming.contains(&cell.id);
                let class = crate::plan::timing::timing_class(cell);
                let timed_as = match timed.get(&class) {
                    Some((id, _)) if !self.matrix.timing.every_cell && !retime => Some(id.clone()),
                    _ => None,
                };
                let (frames, warmup) = match timed_as {
                    Some(_) => (1, 0),
                    None => (self.matrix.timing.frames, self.matrix.timing.warmup),
                };
                let mut render = {
                    // Timed frames have the device to themselves.
                    let _held = self.gpu_metrics.as_ref().filter(|_| timed_as.is_none()).map(|g| g.hold());
                    match timed_as {
                        Some(_) => renderer.draw_untimed(&prepared, &params, &plan)?,
                        None => renderer.draw(&prepared, &params, &plan, frames, warmup)?,
                    }
                };
                match timed.get(&class) {
                    Some((_, (frame_ms, gpu, passes))) if timed_as.is_some() => {
                        render.frame_ms.clone_from(frame_ms);
                        render.gpu_pass_ms.clone_from(gpu);
                        render.gpu_passes.clone_from(passes);
                    }
                    Some(_) => {}
                    None => {
                        let timings = (render.frame_ms.clone(), render.gpu_pass_ms.clone(), render.gpu_passes.clone());
                        timed.insert(class, (cell.id.clone(), timings));
                    }
                }
                if self.matrix.outputs.terms && !retime {
                    render.terms = Some(renderer.draw_terms(&prepared, &params, &plan)?);
                }
                if retime {
                    StageClock::add_ms(&self.clock.render, t.elapsed().as_secs_f64() * 1e3 - render.readback_ms);
                    self.retime_cell(cell, &render)?;
                    continue;
                }
                let truth_gap = match &self.matrix.reference {
                    Some(ReferenceSpec::Truth(t)) => {
                        plan.truth_gap(t.settings.kind == crate::render::truth::TruthKind::SameBrdf)
                    }
                    _ => None,
                };
                let reference = match (&self.matrix.reference, truth_gap) {
                    (Some(ReferenceSpec::Truth(_)), Some(why)) => Some(Err(why)),
                    (Some(ReferenceSpec::Supersampled(k)), _) => {
                        let k = *k;
                        let max = renderer.gpu.device.limits().max_texture_dimension_2d;
                        let (w, h) = (params.width * k, params.height * k);
                        Some(if w > max || h > max {
                            Err(format!("no {k}× supersampled render: {w}×{h} exceeds the adapter's {max}"))
                        } else {
                            let big =
                                renderer.render(&prepared, &CellParams { width: w, height: h, ..params }, 1, 0)?;
                            Ok(RenderedReference::Supersampled(k, big.hdr))
                        })
                    }
                    (Some(ReferenceSpec::Truth(t)), None) => {
                        let reads = renderer.truth_reads(&prepared, &params, &t.settings)?;
                        let key = super::truth_cache::TruthCache::key(self.matrix, cell, &reads, &self.adapter);
                        let cached = self.truth_cache.as_ref().and_then(|c| c.load(&key, t.settings.kind));
                        let truth = match cached {
                            Some(truth) => truth,
                            None => {
                                let mut truth = renderer.render_truth(&prepared, &params, &t.settings)?;
                                if let Some(c) = &self.truth_cache {
                                    truth.stored = c.store(&key, &truth, &self.adapter)?.map(|d| (key.clone(), d));
                                }
                                truth
                            }
                        };
                        if self.matrix.outputs.truth_scene {
                            let export = renderer.export_truth_scene(&prepared, &params, &t.settings, &truth)?;
                            super::encode::write_truth_scene(&self.dir.cell_dir(&cell.id.0), export)?;
                        }
                        Some(Ok(RenderedReference::Truth(Box::new(truth))))
                    }
                    _ => None,
                };
                // The study: measured against the truth, so only when there is one.
                let (mut study, mut study_left_out) = (Vec::new(), Vec::new());
                let mut readback = render.readback_ms;
                if matches!(reference, Some(Ok(RenderedReference::Truth(_)))) {
                    let (kept, left_out) =
                        super::study::variants(cell, scene, &params.settings, &self.matrix.approximations);
                    study_left_out = left_out;
                    let mut sample_counts = vec![plan.multisampling.samples];
                    for v in kept {
                        // An MSAA level the adapter cannot give renders one it can: measured already.
                        let m = renderer.msaa_support().for_settings(&v.settings);
                        if v.approximation == Approximation::Msaa {
                            if sample_counts.contains(&m.samples) {
                                let why = m.note.unwrap_or_default();
                                study_left_out.push(super::study::LeftOutVariant {
                                    approximation: v.approximation,
                                    name: v.name,
                                    change: v.change,
                                    reason: format!(
                                        "renders {} samples per pixel, a level measured already: {why}",
                                        m.samples
                                    ),
                                });
                                continue;
                            }
                            sample_counts.push(m.samples);
                        }
                        let p = CellParams { settings: v.settings, ..params };
                        let variant_plan = renderer.plan(&prepared, &p)?;
                        let (frames, warmup) = (self.matrix.timing.frames, self.matrix.timing.warmup);
                        let r = renderer.draw(&prepared, &p, &variant_plan, frames, warmup)?;
                        readback += r.readback_ms;
                        study.push((v, variant_plan.multisampling.samples, r));
                    }
                }
                StageClock::add_ms(&self.clock.render, t.elapsed().as_secs_f64() * 1e3 - readback);
                StageClock::add_ms(&self.clock.readback, readback);
                self.rendered.fetch_add(1, Ordering::Relaxed);
                let t = Instant::now();
                let job = RenderedCell { cell, render, reference, study, study_left_out, timed_as, plan };
                if encode_tx.send(job).is_err() {
                    return Ok(()); // the workers stopped: an error is recorded
                }
                StageClock::add(&self.clock.render_blocked, t);
            }
        }
        Ok(())
    }

    /// A finished cell's record with the timings of `render`, its images and metrics kept.
    fn retime_cell(&self, cell: &Cell, render: &crate::render::CellRender) -> Result<(), Error> {
        let path = self.dir.cell_dir(&cell.id.0).join(CELL_FILE);
        let mut record = CellRecord::load(&path).map_err(|e| e.into_error(&path, "cell record"))?;
        let old = record.timing;
        record.timing = super::encode::cell_timing(self.matrix, render, old.encode_ms);
        record.timing.metrics_ms = old.metrics_ms;
        write_json(&path, &record)
    }

    /// Ids of the cells some other cell is compared with.
    fn reference_cells(&self) -> HashSet<CellId> {
        match &self.matrix.reference {
            Some(ReferenceSpec::Cell(terms)) => {
                self.exp.cells.iter().filter_map(|c| reference_cell_id(c, self.matrix, terms)).collect()
            }
            _ => HashSet::new(),
        }
    }

    fn encode_worker(&self, rx: Receiver<RenderedCell<'a>>, metrics_tx: Sender<MetricsJob<'a>>) {
        for job in rx {
            if self.aborted() {
                continue;
            }
            let t = ThreadTimer::start();
            let cell = job.cell;
            let cdir = self.dir.cell_dir(&cell.id.0);
            let plan = &self.plans[cell.composition_index];
            let encoded = encode_cell(self.matrix, &cdir, (&self.adapter, self.keys.get(&cell.id)), plan, job);
            StageClock::add_cpu(&self.clock.encode, t);
            let result = encoded.and_then(|e| {
                let job = MetricsJob {
                    cell,
                    record: e.record,
                    images: Some(e.images),
                    reference_missing: e.reference_missing,
                    study: e.study,
                };
                self.images_final(job, &metrics_tx)
            });
            if let Err(e) = result {
                self.fail(e);
            }
        }
    }

    /// A cell's image files are final: hand it to the metric workers, release the cells that were
    /// waiting for it as their reference, and copy its twins.
    fn images_final(&self, job: MetricsJob<'a>, metrics_tx: &Sender<MetricsJob<'a>>) -> Result<(), Error> {
        let id = job.cell.id.clone();
        let (waiting, twins) = {
            let mut t = self.tracker();
            t.final_images.insert(id.clone());
            (t.waiting.remove(&id).unwrap_or_default(), t.twins.remove(&id).unwrap_or_default())
        };
        let twin_source = (!twins.is_empty()).then(|| (job.record.clone(), job.images.clone()));
        let _ = metrics_tx.send(job);
        for w in waiting {
            let _ = metrics_tx.send(w);
        }
        match twin_source {
            Some((record, images)) => self.copy_twins(&id, twins, &record, images, metrics_tx),
            None => Ok(()),
        }
    }

    /// Twins of a cell that finished in an earlier run: its record is read from its folder.
    fn release_resumed_twins(&self, original: &CellId, metrics_tx: &Sender<MetricsJob<'a>>) -> Result<(), Error> {
        let twins = self.tracker().twins.remove(original).unwrap_or_default();
        let path = self.dir.cell_dir(&original.0).join(CELL_FILE);
        let record = CellRecord::load(&path).map_err(|e| e.into_error(&path, "cell record"))?;
        self.copy_twins(original, twins, &record, None, metrics_tx)
    }

    fn copy_twins(
        &self,
        original: &CellId,
        twins: Vec<&'a Cell>,
        record: &CellRecord,
        images: Option<CellImages>,
        metrics_tx: &Sender<MetricsJob<'a>>,
    ) -> Result<(), Error> {
        let from = self.dir.cell_dir(&original.0);
        for twin in twins {
            let t = ThreadTimer::start();
            copy_images(&from, &self.dir.cell_dir(&twin.id.0))?;
            let job = MetricsJob {
                cell: twin,
                record: twin_record(
                    self.matrix,
                    twin,
                    self.keys.get(&twin.id),
                    &self.plans[twin.composition_index],
                    record,
                ),
                images: images.clone(),
                reference_missing: None,
                study: Vec::new(),
            };
            StageClock::add_cpu(&self.clock.encode, t);
            self.images_final(job, metrics_tx)?;
        }
        Ok(())
    }

    fn metrics_worker(&self, rx: Receiver<MetricsJob<'a>>) {
        for job in rx {
            if self.aborted() {
                continue;
            }
            if let Err(e) = self.measure(job) {
                self.fail(e);
            }
        }
    }

    fn measure(&self, mut job: MetricsJob<'a>) -> Result<(), Error> {
        let t = ThreadTimer::start();
        let cell = job.cell;
        let cdir = self.dir.cell_dir(&cell.id.0);
        let in_run = |id: &CellId| self.cells.contains(id);
        let (png, exr, what) = match reference_source(self.matrix, self.dir, cell, &in_run) {
            ReferenceSource::Missing(why) => return self.finish(job, CellMetrics::without_reference(why), None),
            ReferenceSource::RunCell(id) => {
                let mut tracker = self.tracker();
                if !tracker.final_images.contains(&id) {
                    // Parked without its pixels: memory stays bounded by the queues.
                    job.images = None;
                    tracker.waiting.entry(id).or_default().push(job);
                    return Ok(());
                }
                let d = self.dir.cell_dir(&id.0);
                (d.join("image.png"), d.join("image.exr"), ReferenceRecord::Cell { cell: id })
            }
            ReferenceSource::Files { png, exr, record } => {
                if !png.is_file() {
                    let why =
                        job.reference_missing.take().unwrap_or_else(|| format!("{} does not exist", png.display()));
                    return self.finish(job, CellMetrics::without_reference(why), None);
                }
                (png, exr, record)
            }
        };
        let reference = self.references.get(&png, &exr)?;
        let reference_cell = match &what {
            ReferenceRecord::Cell { cell: id } => self.exp.cells.iter().find(|c| &c.id == id),
            _ => None,
        };
        let truth = matches!(what, ReferenceRecord::Truth { .. });
        let metrics = compare_cell(
            cell,
            &cdir,
            super::metrics::MetricOptions { backend: self.metrics_backend(), write_maps: self.matrix.outputs.maps },
            job.images.take(),
            &reference,
            what,
            reference_cell,
        )?;
        if truth {
            for s in std::mem::take(&mut job.study) {
                job.record.approximations.push(measure_study(s, &reference, &cell.id.0, self.metrics_backend())?);
            }
        }
        self.finish(job, metrics, Some(t))
    }

    fn metrics_backend(&self) -> crate::compare::images::MetricsBackend<'_> {
        match &self.gpu_metrics {
            Some(g) => crate::compare::images::MetricsBackend::Gpu(g),
            None => crate::compare::images::MetricsBackend::Cpu,
        }
    }

    /// Write the cell's record, last: its presence marks the cell finished.
    fn finish(&self, job: MetricsJob<'a>, metrics: CellMetrics, started: Option<ThreadTimer>) -> Result<(), Error> {
        let mut record = job.record;
        record.key_inputs = self.keys.inputs(&job.cell.id);
        record.timing.metrics_ms = started.map(|t| t.elapsed_ns() as f64 / 1e6);
        record.metrics = metrics;
        let cdir = self.dir.cell_dir(&job.cell.id.0);
        write_json(&cdir.join(CELL_FILE), &record)?;
        if let Some(cache) = &self.cache {
            let replacing = self.replacing.lock().unwrap_or_else(|e| e.into_inner()).remove(&job.cell.id);
            cache.store(self.keys.get(&job.cell.id), &cdir, replacing)?;
        }
        if let Some(t) = started {
            StageClock::add_cpu(&self.clock.metrics, t);
        }
        self.bar.inc(1);
        Ok(())
    }
}

pub fn default_results_root() -> PathBuf {
    Path::new("results").to_path_buf()
}
