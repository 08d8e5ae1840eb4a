//! Reports built from a run's recorded files (never from rendering): the CI check, tables.

pub mod approximations;
pub mod check;
pub mod error_time;
pub mod gallery;
pub mod invariants;
pub mod perf;
pub mod run_data;
pub mod sheets;
pub mod stability;

/// Every report of a run, from its recorded files.
pub fn build(run_dir: &std::path::Path) -> Result<(), crate::error::Error> {
    let run = run_data::RunData::load(run_dir)?;
    perf::write(&run)?;
    error_time::write(&run)?;
    approximations::write(&run)?;
    stability::write(&run)?;
    invariants::write(&run)?;
    let specs = match &run.run.matrix.sheets {
        s if s.is_empty() => crate::spec::sheets::default_specs(),
        s => s.clone(),
    };
    let written = sheets::write(&run, &specs)?;
    gallery::write(&run, &written)
}
