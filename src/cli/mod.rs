//! The command line: the grammar (clap) and one function per command. `main.rs` only parses and
//! maps the result to an exit code.

pub mod audit;
pub mod bench;
pub mod brdf;
pub mod diff;
pub mod export_mesh;
pub mod list;
pub mod matching;
pub mod runs;
pub mod shaders;

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

use crate::declarations::matrix::Matrix;
use crate::error::Error;
use crate::shading::Registry;
use std::sync::Arc;

/// Where user-supplied models are read from.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ModelsArg {
    /// A folder of user models (NAME.wgsl with NAME.toml beside it). Default: the matrix's `models`
    /// key, else ./shaders/brdf.
    #[arg(long, value_name = "DIR")]
    pub models: Option<PathBuf>,
}

/// Whether a cell may take a pass's output from the cell before it when that pass's inputs are the
/// same (shadow maps, the depth prepass and SSAO, probe captures, the fixed objects' layer).
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct ReuseArg {
    /// Draw every pass of every cell, reusing nothing across cells (the images are the same bytes;
    /// this is the check of that).
    #[arg(long)]
    pub no_reuse: bool,
}

/// How many cells a matrix may expand to before anything is expanded.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct CellLimit {
    /// Refuse a matrix whose product of axes exceeds N cells (default 1000000).
    #[arg(long = "max-cells", value_name = "N", default_value_t = crate::cells::DEFAULT_MAX_CELLS)]
    pub max_cells: u64,
}

impl Default for CellLimit {
    fn default() -> Self {
        CellLimit { max_cells: crate::cells::DEFAULT_MAX_CELLS }
    }
}

#[derive(Parser)]
#[command(
    name = "shadematrix",
    version,
    about = "Render a TOML matrix of pipelines × shaders × materials × compositions headlessly with wgpu"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand)]
pub enum Command {
    /// Render every cell of a matrix (default: the embedded default matrix).
    Run {
        /// Matrix TOML file.
        matrix: Option<PathBuf>,
        /// Run folder (default: results/<matrix>-<timestamp>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Continue an interrupted run: cells already finished are kept.
        #[arg(long)]
        resume: bool,
        /// Render shard K of N (e.g. 2/4); `auto` (or `auto/N`) reads K and N from a Kubernetes
        /// Indexed Job (JOB_COMPLETION_INDEX; N from auto/N or SHADEMATRIX_SHARDS) or a Slurm array
        /// (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT, SLURM_ARRAY_TASK_MIN).
        #[arg(long, value_name = "K/N|auto")]
        shard: Option<String>,
        /// Only cells matching, e.g. `composition=medusa,shader=standard|lit` (the grammar of `[[only]]`).
        #[arg(long, value_name = "FILTER")]
        only: Option<String>,
        /// Exit 1 when any cell's image holds these (comma-separated): nan, inf, negative,
        /// overflow (finite values above the half-float maximum 65504).
        #[arg(long, value_name = "KINDS", value_delimiter = ',')]
        fail_on: Vec<String>,
        /// Cell cache shared across runs (default: .cell-cache beside the run folders): a cell
        /// whose inputs match a cached one is taken from it instead of rendered.
        #[arg(long, value_name = "DIR", conflicts_with = "no_cache")]
        cache: Option<PathBuf>,
        /// Neither read nor fill the cell cache.
        #[arg(long)]
        no_cache: bool,
        /// Render the timed frames of cells taken from the cache or kept by --resume again, and
        /// record the new timings (images and metrics are kept).
        #[arg(long)]
        retime: bool,
        #[command(flatten)]
        reuse: ReuseArg,
        #[command(flatten)]
        limit: CellLimit,
        #[command(flatten)]
        models: ModelsArg,
    },
    /// Run a matrix and report cells/s, time per stage, stage overlap and peak memory
    /// (also written to tables/bench.md and .json in the run folder).
    Bench {
        /// Matrix TOML file (default: the embedded default matrix).
        matrix: Option<PathBuf>,
        /// Run folder (default: results/<matrix>-<timestamp>).
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        reuse: ReuseArg,
        #[command(flatten)]
        limit: CellLimit,
        #[command(flatten)]
        models: ModelsArg,
    },
    /// List the expanded cells, the pruned ones and the passes each composition needs.
    List {
        matrix: Option<PathBuf>,
        #[command(flatten)]
        limit: CellLimit,
        #[command(flatten)]
        models: ModelsArg,
    },
    /// Every shader: pipelines, parameters, the sweep axes it reads and how they map.
    Shaders {
        #[command(flatten)]
        models: ModelsArg,
    },
    /// Evaluate one model for one set of directions (f64 twin; --gpu adds the WGSL on the adapter).
    Brdf {
        #[arg(long)]
        pipeline: String,
        #[arg(long)]
        shader: String,
        /// As the shader receives it: albedo=R,G,B (linear), metallic=X, smoothness=X, specular=R,G,B, or a model parameter.
        #[arg(long = "param", value_name = "K=V")]
        params: Vec<String>,
        #[arg(long, allow_hyphen_values = true)]
        n: String,
        #[arg(long, allow_hyphen_values = true)]
        l: String,
        #[arg(long, allow_hyphen_values = true)]
        v: String,
        #[arg(long)]
        gpu: bool,
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        models: ModelsArg,
    },
    /// BRDF property audit: GPU-vs-f64 parity, positivity, reciprocity, energy. Exit 1 on a failed check.
    Audit {
        /// Only the models of this name (every pipeline that has it).
        #[arg(long)]
        shader: Option<String>,
        /// Print the JSON report instead of the table.
        #[arg(long)]
        json: bool,
        /// Where audit.md, .csv and .json go (default results/audit-<time>).
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        models: ModelsArg,
    },
    /// Convergence of the tool's own integrators (FGD table, probe prefilter, furnace): error against
    /// time per sample count, with where each default sits. CPU only.
    Convergence {
        /// Where tables/convergence.{md,csv} and plots/convergence_*.svg go (default results/convergence-<time>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// A sweep of a few seconds (small counts and references), for a smoke test.
        #[arg(long)]
        quick: bool,
    },
    /// For each material a matrix sweeps in one pipeline/shader, the values of another that
    /// reproduce its frames over every composition: tables/match.md|csv|json, sheets, curves and
    /// a page under --out.
    Match {
        /// The source, PIPELINE/SHADER (e.g. builtin/standard).
        #[arg(long)]
        from: String,
        /// The target, PIPELINE/SHADER (e.g. urp/lit).
        #[arg(long)]
        to: String,
        /// Matrix TOML file (default: the embedded default matrix): its compositions, presets and
        /// sliders in the source.
        matrix: Option<PathBuf>,
        /// Output folder.
        #[arg(long, default_value = "results/match")]
        out: PathBuf,
        /// The image compared: `display` (after exposure and tonemapping, what a person sees) or
        /// `linear` (the radiance, the target's exposure calibrated on a matte grey).
        #[arg(long, default_value = "display")]
        space: String,
        /// Side of the square frames fitted, pixels.
        #[arg(long, default_value_t = 64)]
        size: u32,
        /// Rendered evaluations the refinement may take per material (0: the closed-form stage alone).
        #[arg(long, default_value_t = 40)]
        iterations: u64,
        /// Take the rows an earlier match into --out finished (tables/match.progress.json) with
        /// the same sides, matrix, space, size and iterations, and fit only the rest.
        #[arg(long)]
        resume: bool,
        /// Source values the fit keeps as they are, comma-separated: smoothness, metallic, color
        /// (e.g. `--keep metallic`: a dielectric stays one).
        #[arg(long, value_delimiter = ',')]
        keep: Vec<String>,
        #[command(flatten)]
        models: ModelsArg,
    },
    /// FLIP and SSIM (and RMSE, PSNR, bad-value counts) of two PNGs or two EXRs; A is the reference.
    Diff {
        a: PathBuf,
        b: PathBuf,
        #[arg(long)]
        json: bool,
        /// Write flip.png and ssim.png (1 − SSIM) here.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also SSIM of R, G and B separately.
        #[arg(long)]
        per_channel: bool,
    },
    /// Compare a run with a baseline run and check its matrix's [[assert]] invariants: junit.xml and
    /// summary.md into the run; exit 1 on a regression or a failed invariant.
    Check {
        run: PathBuf,
        #[arg(long)]
        baseline: Option<PathBuf>,
        /// Largest FLIP mean a cell may have against its baseline (default 0.01).
        #[arg(long)]
        flip_mean: Option<f64>,
        /// Smallest SSIM a cell may have against its baseline (default 0.99).
        #[arg(long)]
        ssim_min: Option<f64>,
    },
    /// Rebuild the reports of a run (tables) from its recorded files, without rendering.
    Report { run: PathBuf },
    /// Join the folders of a sharded run (`run --shard K/N` or `--shard auto`) into one run
    /// folder with complete reports; refuses shards of another matrix or adapter, or a missing one.
    Merge {
        /// The shards' run folders.
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        /// The merged run's folder (must not hold a run).
        #[arg(long)]
        out: PathBuf,
        /// The matrix the shards ran (default: the file their run.json names), loaded again so
        /// that their cells are checked against today's expansion and inputs.
        #[arg(long)]
        matrix: Option<PathBuf>,
        #[command(flatten)]
        models: ModelsArg,
    },
    /// Fit the LTC tables HDRP's rect lights read (maintainers: writes shaders/data/ltc.bin, which
    /// the binary embeds; docs/models.md#area-lights).
    FitLtc {
        #[arg(default_value = "shaders/data/ltc.bin")]
        out: PathBuf,
    },
    /// Write a composition's meshes (world space) as a GLB file.
    ExportMesh {
        /// A built-in composition name or a scene TOML path.
        composition: String,
        out: PathBuf,
        /// The subject's material: a preset, or `own` (a glTF subject's own material with its
        /// textures, the default where it has one).
        #[arg(long)]
        preset: Option<String>,
        /// The preset in its textured form (its maps as glTF textures).
        #[arg(long)]
        textured: bool,
    },
}

impl Default for Command {
    /// No command: the main job, the embedded default matrix.
    fn default() -> Self {
        Command::Run {
            matrix: None,
            out: None,
            resume: false,
            shard: None,
            only: None,
            fail_on: Vec::new(),
            cache: None,
            no_cache: false,
            retime: false,
            reuse: ReuseArg::default(),
            limit: CellLimit::default(),
            models: ModelsArg::default(),
        }
    }
}

pub fn dispatch(cmd: Command) -> Result<(), Error> {
    match cmd {
        Command::Run { matrix, out, resume, shard, only, fail_on, cache, no_cache, retime, reuse, limit, models } => {
            let fail_on = runs::parse_fail_on(&fail_on)?;
            let cache = if no_cache {
                runs::CacheChoice::Off
            } else {
                cache.map_or(runs::CacheChoice::Default, runs::CacheChoice::At)
            };
            let opts = runs::RunArgs {
                out,
                resume,
                shard: shard.as_deref(),
                only: only.as_deref(),
                fail_on: &fail_on,
                cache,
                retime,
                reuse: !reuse.no_reuse,
                max_cells: limit.max_cells,
            };
            runs::run(matrix.as_deref(), opts, &models)
        }
        Command::Bench { matrix, out, reuse, limit, models } => {
            runs::bench(matrix.as_deref(), out, !reuse.no_reuse, limit, &models)
        }
        Command::List { matrix, limit, models } => list::list(matrix.as_deref(), limit, &models),
        Command::Shaders { models } => shaders::print(&models),
        Command::Brdf { pipeline, shader, params, n, l, v, gpu, json, models } => {
            let req = brdf::BrdfRequest { pipeline, shader, params, n, l, v, gpu };
            brdf::print(&req, json, &models)
        }
        Command::Audit { shader, json, out, models } => audit::audit(shader.as_deref(), json, out, &models),
        Command::Convergence { out, quick } => audit::convergence(out, quick),
        Command::Match { from, to, matrix, out, space, size, iterations, resume, keep, models } => {
            let req = matching::MatchRequest { from, to, matrix, out, space, size, iterations, resume, keep };
            matching::run_match(&req, &models)
        }
        Command::Diff { a, b, json, out, per_channel } => diff::diff(&a, &b, json, out.as_deref(), per_channel),
        Command::Check { run, baseline, flip_mean, ssim_min } => {
            runs::check(&run, baseline.as_deref(), flip_mean, ssim_min)
        }
        Command::Report { run } => runs::report(&run),
        Command::Merge { shards, out, matrix, models } => runs::merge(&shards, &out, matrix.as_deref(), &models),
        Command::FitLtc { out } => {
            let tables = crate::shading::ltc_fit::fit();
            crate::fsutil::write_atomic(&out, &tables.to_bytes())?;
            eprintln!("wrote {}", out.display());
            Ok(())
        }
        Command::ExportMesh { composition, out, preset, textured } => export_mesh::export_mesh(
            &composition,
            &out,
            export_mesh::SubjectMaterial { preset: preset.as_deref(), textured },
        ),
    }
}

/// The matrix at `path`, or the embedded default one, its shaders resolved in `registry`.
pub fn load_matrix(path: Option<&Path>, registry: Arc<Registry>) -> Result<Matrix, Error> {
    match path {
        Some(p) => Matrix::load(p, registry),
        None => Matrix::load_default(registry),
    }
}

/// The models of this command: the built-in ones and those of `--models DIR`, else ./shaders/brdf.
pub fn registry(models: &ModelsArg) -> Result<Arc<Registry>, Error> {
    // A folder named on purpose must exist; the default one may be absent.
    if let Some(dir) = models.models.as_ref().filter(|d| !d.is_dir()) {
        let why = format!("`{}` is not a folder (a folder of NAME.wgsl with NAME.toml beside each)", dir.display());
        return Err(crate::error::InputError::at_key("command line", "--models", why).into());
    }
    let dir = models.models.clone().unwrap_or_else(|| PathBuf::from(crate::shading::user::USER_MODEL_DIR));
    Ok(Arc::new(Registry::with_user_models(&dir)?))
}

/// As `registry`, where a matrix is named: its `models` key comes before the default folder.
pub fn registry_for(models: &ModelsArg, matrix: Option<&Path>) -> Result<Arc<Registry>, Error> {
    let from_matrix = match (&models.models, matrix) {
        (None, Some(m)) => crate::declarations::matrix::models_dir(m)?,
        _ => None,
    };
    if let Some(dir) = &from_matrix {
        if !dir.is_dir() {
            let shown = matrix.map(|m| m.display().to_string()).unwrap_or_default();
            let why = format!("`{}` is not a folder", dir.display());
            return Err(crate::error::InputError::at_key(shown, "models", why).into());
        }
    }
    registry(&ModelsArg { models: from_matrix.or_else(|| models.models.clone()) })
}

/// Print to stdout. A closed pipe (`| head`) ends the process quietly with exit 0, as ripgrep
/// does: the reader has what it wanted. Any other write error is reported (exit 1), not ignored
/// and not a panic (`println!` panics, exit 101).
pub fn print_out(text: &str) {
    let mut out = std::io::stdout().lock();
    let written = std::io::Write::write_all(&mut out, text.as_bytes()).and_then(|()| std::io::Write::flush(&mut out));
    match written {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => {
            eprintln!("shadematrix: writing to standard output: {e}");
            std::process::exit(crate::error::exit::FAILURE.into());
        }
    }
}

/// `println!` through `print_out`.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::cli::print_out(&format!("{}\n", format_args!($($arg)*)))
    };
}
pub(crate) use outln;
