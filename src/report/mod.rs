//! Reports built from a run's recorded files (never from rendering): the CI check, tables.

pub mod approximations;
pub mod check;
pub mod error_time;
pub mod gallery;
pub mod invariants;
pub mod perf;
pub mod plot_style;
pub mod quality;
pub mod run_data;
pub mod scatter;
pub mod sheets;
pub mod stability;
pub mod viewer;

/// Every report of a run, from its recorded files.
pub fn build(run_dir: &std::path::Path) -> Result<(), crate::error::Error> {
    let run = run_data::RunData::load(run_dir)?;
    // A sheet or page drawn without a cell's image would look complete: say what is missing.
    let missing: Vec<&str> = run
        .cells
        .iter()
        .filter(|c| crate::input::read::is_regular_file(&run.cell_dir(&c.id.0).join(&c.image.png)).is_err())
        .map(|c| c.id.0.as_str())
        .collect();
    if !missing.is_empty() {
        eprintln!(
            "warning: {} cell(s) of {} have no image.png (their sheet tiles and viewer images are empty): {}{}",
            missing.len(),
            run.dir.display(),
            missing.iter().take(3).copied().collect::<Vec<_>>().join(", "),
            if missing.len() > 3 { ", …" } else { "" }
        );
    }
    perf::write(&run)?;
    error_time::write(&run)?;
    quality::write(&run)?;
    approximations::write(&run)?;
    stability::write(&run)?;
    invariants::write(&run)?;
    let specs = match &run.run.matrix.sheets {
        s if s.is_empty() => crate::declarations::sheets::default_specs(),
        s => s.clone(),
    };
    let written = sheets::write(&run, &specs)?;
    let plots = gallery::write(&run, &written)?;
    // The contact sheets are on the gallery page.
    let mut links = vec![("all cells, contact sheets and tables".to_string(), gallery::FILE.to_string())];
    for table in ["perf.md", "error_vs_time.md", "quality.md", "stability.md", "approximations.md", "invariants.md"] {
        if run.dir.join("tables").join(table).is_file() {
            links.push((table.to_string(), format!("tables/{table}")));
        }
    }
    links.extend(plots.into_iter().map(|p| (p.trim_start_matches("plots/").to_string(), p)));
    viewer::write(&run, links)
}
