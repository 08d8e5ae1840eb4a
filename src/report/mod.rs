//! Reports built from a run's recorded files (never from rendering): the CI check, tables.

pub mod check;
pub mod error_time;
pub mod gallery;
pub mod perf;
pub mod run_data;
pub mod sheets;

/// Every report of a run, from its recorded files.
pub fn build(run_dir: &std::path::Path) -> Result<(), crate::error::Error> {
    let run = run_data::RunData::load(run_dir)?;
    perf::write(&run)?;
    error_time::write(&run)?;
    let specs: Vec<sheets::SheetSpec> = serde_json::from_value(run.run["matrix"]["sheets"].clone())
        .ok()
        .filter(|v: &Vec<sheets::SheetSpec>| !v.is_empty())
        .unwrap_or_else(sheets::default_specs);
    let written = sheets::write(&run, &specs)?;
    gallery::write(&run, &written)
}
