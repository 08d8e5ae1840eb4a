//! `run`, `bench`, `check` and `report`: commands that make or read a run folder.

use std::path::{Path, PathBuf};

use super::{load_matrix, registry_for, ModelsArg};
use crate::error::{Error, InputError};
use crate::report::check::{check as check_run, Thresholds};
use crate::run::runner::{default_results_root, RunOptions};

fn parse_shard(s: &str) -> Result<(u32, u32), Error> {
    let bad = || InputError::at_key("command line", "--shard", format!("`{s}` is not K/N with 1 <= K <= N"));
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n): (u32, u32) = (k.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
    if k == 0 || n == 0 || k > n {
        return Err(bad().into());
    }
    Ok((k, n))
}

fn progress() -> bool {
    std::io::IsTerminal::is_terminal(&std::io::stderr())
}

pub fn run(
    matrix: Option<&Path>,
    out: Option<PathBuf>,
    resume: bool,
    shard: Option<&str>,
    only: Option<&str>,
    models: &ModelsArg,
) -> Result<(), Error> {
    let m = load_matrix(matrix, registry_for(models, matrix)?)?;
    let opts = RunOptions {
        results_root: default_results_root(),
        out,
        resume,
        shard: shard.map(parse_shard).transpose()?,
        only: only.map(|o| m.parse_only(o)).transpose()?,
        progress: progress(),
        workers: None,
    };
    let s = crate::run::run(&m, &opts)?;
    crate::report::build(&s.dir)?;
    println!(
        "{} cells ({} rendered, {} twins copied, {} resumed; {} pruned, {} filtered out) in {:.1} s on {}",
        s.counts.cells,
        s.counts.rendered,
        s.counts.twins,
        s.counts.resumed,
        s.counts.pruned,
        s.counts.filtered_out,
        s.wall_seconds,
        s.adapter
    );
    println!("results: {}", s.dir.display());
    Ok(())
}

pub fn bench(matrix: Option<&Path>, out: Option<PathBuf>, models: &ModelsArg) -> Result<(), Error> {
    let m = load_matrix(matrix, registry_for(models, matrix)?)?;
    let opts = RunOptions { results_root: default_results_root(), out, progress: progress(), ..Default::default() };
    let b = super::bench::bench(&m, &opts)?;
    super::print_out(&super::bench::markdown(&b));
    Ok(())
}

pub fn check(run: &Path, baseline: &Path, flip_mean: Option<f64>, ssim_min: Option<f64>) -> Result<(), Error> {
    let d = Thresholds::default();
    let t = Thresholds { flip_mean: flip_mean.unwrap_or(d.flip_mean), ssim_min: ssim_min.unwrap_or(d.ssim_min) };
    let r = check_run(run, baseline, t)?;
    println!("{} of {} cells regressed (junit.xml and summary.md in {})", r.failures(), r.cells.len(), run.display());
    if r.failures() > 0 {
        return Err(Error::CheckFailed(format!("{} cells regressed against {}", r.failures(), baseline.display())));
    }
    Ok(())
}

pub fn report(run: &Path) -> Result<(), Error> {
    crate::report::build(run)?;
    println!("reports rebuilt in {}", run.display());
    Ok(())
}
