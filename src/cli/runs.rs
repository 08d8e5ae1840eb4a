//! `run`, `bench`, `check` and `report`: commands that make or read a run folder.

use std::path::{Path, PathBuf};

use super::{load_matrix, registry_for, ModelsArg};
use crate::error::Error;
use crate::images::stats::Defect;
use crate::report::check::{check as check_run, Thresholds};
use crate::run::runner::{default_results_root, RunOptions};

fn progress() -> bool {
    std::io::IsTerminal::is_terminal(&std::io::stderr())
}

/// What `shadematrix run` was asked besides the matrix.
pub struct RunArgs<'a> {
    pub out: Option<PathBuf>,
    pub resume: bool,
    pub shard: Option<&'a str>,
    pub only: Option<&'a str>,
    /// Bad-value kinds that make the run exit 1.
    pub fail_on: &'a [Defect],
    pub cache: CacheChoice,
    pub retime: bool,
    /// Take pass outputs from the cell before where their inputs are the same (`--no-reuse`: false).
    pub reuse: bool,
    pub max_cells: u64,
}

/// Where the cell cache is: `--cache DIR`, `--no-cache`, or beside the run folders.
pub enum CacheChoice {
    Default,
    At(PathBuf),
    Off,
}

/// `--fail-on nan,inf`: each name a `Defect`, the nearest offered for a typo (exit 2).
pub fn parse_fail_on(names: &[String]) -> Result<Vec<Defect>, Error> {
    names
        .iter()
        .map(|n| {
            Defect::from_name(n.trim()).ok_or_else(|| {
                Error::Input(crate::input::names::unknown_name(
                    "command line",
                    "--fail-on",
                    "bad-value kind",
                    n.trim(),
                    &Defect::names(),
                ))
            })
        })
        .collect()
}

pub fn run(matrix: Option<&Path>, args: RunArgs, models: &ModelsArg) -> Result<(), Error> {
    let RunArgs { out, resume, shard, only, fail_on, cache, retime, reuse, max_cells } = args;
    let m = load_matrix(matrix, registry_for(models, matrix)?)?;
    let results_root = default_results_root();
    let cache = match cache {
        // Beside the run folder, so that links stay on its file system.
        CacheChoice::Default => Some(crate::run::cell_cache::default_dir(
            out.as_deref().map_or(results_root.as_path(), |o| o.parent().unwrap_or(Path::new("."))),
        )),
        CacheChoice::At(dir) => Some(dir),
        CacheChoice::Off => None,
    };
    let opts = RunOptions {
        results_root,
        cache,
        retime,
        no_reuse: !reuse,
        out,
        resume,
        shard: shard.map(|s| crate::run::shard::parse(s, &|k| std::env::var(k).ok())).transpose()?,
        only: only.map(|o| m.parse_only(o)).transpose()?,
        progress: progress(),
        workers: None,
        max_cells: Some(max_cells),
        reports: Some(crate::report::build),
    };
    let s = crate::run::run(&m, &opts)?;
    if !s.set_aside.is_empty() {
        eprintln!(
            "--resume: {} cell(s) of the earlier run are not in this expansion; moved to {}: {}",
            s.set_aside.len(),
            s.dir.join(crate::run::runner::STALE_DIR).display(),
            s.set_aside.iter().take(5).cloned().collect::<Vec<_>>().join(", ")
                + if s.set_aside.len() > 5 { ", …" } else { "" }
        );
    }
    super::outln!(
        "{} cells ({} rendered, {} twins copied, {} resumed, {} from the cache; {} pruned, {} filtered out) in {:.1} s on {}",
        s.counts.cells,
        s.counts.rendered,
        s.counts.twins,
        s.counts.resumed,
        s.counts.cached,
        s.counts.pruned,
        s.counts.filtered_out,
        s.wall_seconds,
        s.adapter
    );
    super::outln!("results: {}", s.dir.display());
    fail_on_defects(&s.dir, fail_on)
}

/// Exit 1 (a failed check) when any cell of the run holds a bad value of the kinds asked for,
/// naming the first cells, pixels and passes.
fn fail_on_defects(dir: &Path, kinds: &[Defect]) -> Result<(), Error> {
    if kinds.is_empty() {
        return Ok(());
    }
    let run = crate::report::run_data::RunData::load(dir)?;
    let mut found = Vec::new();
    for c in &run.cells {
        // Every scene has a subject: a frame without one (a NaN camera, a subject out of view) is
        // as wrong as a NaN pixel, and passed every bad-value count.
        if c.stats.subject_pixels == 0 {
            found.push(format!("{}: no subject pixel in the image (the subject is not in view)", c.id.0));
        }
        for d in c.stats.first.iter().filter(|d| kinds.contains(&d.kind)) {
            found.push(format!(
                "{}: {} {} value(s), first at pixel ({}, {}) channel {} = {} ({}, written by {})",
                c.id.0,
                c.stats.count(d.kind),
                d.kind.name(),
                d.x,
                d.y,
                d.channel,
                d.value,
                d.role,
                d.pass
            ));
        }
    }
    if found.is_empty() {
        return Ok(());
    }
    let shown: Vec<&String> = found.iter().take(10).collect();
    let more = if found.len() > 10 { format!("\n… and {} more", found.len() - 10) } else { String::new() };
    Err(Error::CheckFailed(format!(
        "--fail-on {}: {} finding(s)\n{}{more}",
        kinds.iter().map(|k| k.name()).collect::<Vec<_>>().join(","),
        found.len(),
        shown.iter().map(|s| s.as_str()).collect::<Vec<_>>().join("\n")
    )))
}

pub fn bench(
    matrix: Option<&Path>,
    out: Option<PathBuf>,
    reuse: bool,
    limit: super::CellLimit,
    models: &ModelsArg,
) -> Result<(), Error> {
    let m = load_matrix(matrix, registry_for(models, matrix)?)?;
    let opts = RunOptions {
        results_root: default_results_root(),
        out,
        no_reuse: !reuse,
        progress: progress(),
        max_cells: Some(limit.max_cells),
        ..Default::default()
    };
    let b = super::bench::bench(&m, &opts)?;
    super::print_out(&super::bench::markdown(&b));
    Ok(())
}

pub fn check(run: &Path, baseline: Option<&Path>, flip_mean: Option<f64>, ssim_min: Option<f64>) -> Result<(), Error> {
    // A NaN threshold compares false with everything: the gate would pass every cell.
    for (flag, v, lo, hi) in [("--flip-mean", flip_mean, 0.0, 1.0), ("--ssim-min", ssim_min, -1.0, 1.0)] {
        if let Some(v) = v.filter(|v| !(v.is_finite() && (lo..=hi).contains(v))) {
            let why = format!("value {v} is out of range; allowed a finite number in {lo}..={hi}");
            return Err(crate::error::InputError::at_key("command line", flag, why).into());
        }
    }
    let d = Thresholds::default();
    let t = Thresholds { flip_mean: flip_mean.unwrap_or(d.flip_mean), ssim_min: ssim_min.unwrap_or(d.ssim_min) };
    let r = check_run(run, baseline, t)?;
    if let Some(b) = baseline {
        super::outln!("{} of {} cells regressed against {}", r.failures(), r.cells.len(), b.display());
    }
    for i in &r.invariants {
        match i.message() {
            None => super::outln!("assert `{}` ({}): pass over {} groups", i.name, i.kind, i.groups),
            Some(m) => super::outln!("assert `{}` ({}): FAIL — {m}", i.name, i.kind),
        }
    }
    super::outln!("junit.xml and summary.md in {}", run.display());
    let mut failed = Vec::new();
    if let Some(why) = &r.incomplete {
        super::outln!("run: INCOMPLETE — {why}");
        failed.push(format!("the run is incomplete: {why}"));
    }
    if r.failures() > 0 {
        failed.push(format!("{} cells regressed", r.failures()));
    }
    if r.failed_invariants() > 0 {
        let names: Vec<&str> = r.invariants.iter().filter(|i| !i.passed()).map(|i| i.name.as_str()).collect();
        failed.push(format!("{} invariant(s) failed: {}", names.len(), names.join(", ")));
    }
    if !failed.is_empty() {
        return Err(Error::CheckFailed(failed.join("; ")));
    }
    Ok(())
}

pub fn merge(shards: &[PathBuf], out: &Path, matrix: Option<&Path>, models: &ModelsArg) -> Result<(), Error> {
    let load = |origin: &str| {
        let path = match matrix {
            Some(p) => Some(p.to_path_buf()),
            None if origin == crate::declarations::matrix::EMBEDDED_ORIGIN => None,
            None => Some(PathBuf::from(origin)),
        };
        if let Some(p) = path.as_deref().filter(|p| !p.exists()) {
            let why = format!(
                "the shards' matrix `{}` is not there to load (merge recomputes their cells from it); give it \
                 with --matrix",
                p.display()
            );
            return Err(crate::error::InputError::new("command line", why).into());
        }
        load_matrix(path.as_deref(), registry_for(models, path.as_deref())?)
    };
    let m = crate::run::merge::merge(shards, out, &load)?;
    crate::report::build(&m.dir)?;
    crate::record::RunRecord::mark_complete(&m.dir)?;
    super::outln!("{} cells from {} shards merged into {}", m.cells, m.shards, m.dir.display());
    Ok(())
}

pub fn report(run: &Path) -> Result<(), Error> {
    if !run.join(crate::record::RUN_FILE).is_file() {
        return Err(crate::error::InputError::new(run.display().to_string(), "not a run folder (no run.json)").into());
    }
    // A run or merge still writing the folder holds its lock: refused, not interleaved.
    let _lock = crate::record::RunLock::acquire(run)?;
    crate::record::layout::check_own_tree(run)?;
    // What a killed report (or run) left half-written goes before the reports are written again.
    crate::record::layout::remove_unfinished_writes(run);
    crate::report::build(run)?;
    crate::record::RunRecord::mark_complete(run)?;
    super::outln!("reports rebuilt in {}", run.display());
    Ok(())
}
