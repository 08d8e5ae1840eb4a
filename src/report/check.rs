//! `shadematrix check RUN [--baseline DIR]`: every cell's image against the baseline run's image of
//! the same cell id (LDR-FLIP mean and SSIM on the PNGs), and the matrix's `[[assert]]` invariants
//! (`report::invariants`). Writes junit.xml (a testsuite of cells, one testcase per cell, and a
//! testsuite of invariants, one testcase per assert) and summary.md (tables fit for a CI job
//! summary) into the run folder.

use serde::Serialize;
use std::fmt::Write;
use std::path::Path;

use super::invariants::InvariantResult;
use super::run_data::RunData;
use crate::compare::{compare, LoadedImage};
use crate::error::Error;
use crate::fsutil::write_atomic;

#[derive(Debug, Clone, Copy, Serialize)]
pub struct Thresholds {
    /// A cell regresses when its FLIP mean against the baseline exceeds this.
    pub flip_mean: f64,
    /// ... or its SSIM falls below this.
    pub ssim_min: f64,
}

impl Default for Thresholds {
    /// Renders are deterministic on one adapter: unchanged shaders give FLIP 0 and SSIM 1, so
    /// tight defaults catch small changes while leaving room for driver rounding.
    fn default() -> Self {
        Thresholds { flip_mean: 0.01, ssim_min: 0.99 }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct CellCheck {
    pub id: String,
    pub classname: String,
    pub flip_mean: Option<f64>,
    pub ssim: Option<f64>,
    /// None: passed.
    pub failure: Option<String>,
}

pub struct CheckReport {
    /// Against the baseline; empty without one.
    pub cells: Vec<CellCheck>,
    pub thresholds: Thresholds,
    pub baseline: Option<std::path::PathBuf>,
    pub invariants: Vec<InvariantResult>,
    /// Why the run is not a whole run (not complete, or cells of its expansion missing): a gate
    /// that passed a killed run would pass what was never rendered.
    pub incomplete: Option<String>,
}

impl CheckReport {
    /// Cells that regressed.
    pub fn failures(&self) -> usize {
        self.cells.iter().filter(|c| c.failure.is_some()).count()
    }

    pub fn failed_invariants(&self) -> usize {
        self.invariants.iter().filter(|r| !r.passed()).count()
    }
}

pub fn check(run_dir: &Path, baseline_dir: Option<&Path>, t: Thresholds) -> Result<CheckReport, Error> {
    let run = RunData::load(run_dir)?;
    let invariants = super::invariants::evaluate(&run)?;
    let incomplete = completeness(&run);
    // An incomplete run fails whatever else is asked; a whole one needs something to check.
    if baseline_dir.is_none() && invariants.is_empty() && incomplete.is_none() {
        return Err(crate::error::InputError::new(
            run_dir.display().to_string(),
            "nothing to check: give --baseline DIR, or declare [[assert]] invariants in the matrix",
        )
        .into());
    }
    let cells = match baseline_dir {
        Some(b) => against_baseline(&run, &RunData::load(b)?, t)?,
        None => Vec::new(),
    };
    let report =
        CheckReport { cells, thresholds: t, baseline: baseline_dir.map(Path::to_path_buf), invariants, incomplete };
    write_atomic(&run_dir.join("junit.xml"), junit(&report, &run.adapter()).as_bytes())?;
    write_atomic(&run_dir.join("summary.md"), summary(&report, &run.adapter()).as_bytes())?;
    Ok(report)
}

/// Why `run` is not whole: its status, and the cells of its expansion without a record.
fn completeness(run: &RunData) -> Option<String> {
    let mut why = Vec::new();
    if run.run.status != crate::record::run::RunStatus::Complete {
        why.push(format!("its status is `{}`, not `complete`: the run did not finish", run.run.status.name()));
    }
    let have: std::collections::HashSet<&crate::cells::CellId> = run.cells.iter().map(|c| &c.id).collect();
    let missing: Vec<&str> = run.run.cells.iter().filter(|id| !have.contains(id)).map(|id| id.0.as_str()).collect();
    if !missing.is_empty() {
        let shown: Vec<&str> = missing.iter().take(3).copied().collect();
        why.push(format!(
            "{} of its {} cells have no record ({}{})",
            missing.len(),
            run.run.cells.len(),
            shown.join(", "),
            if missing.len() > 3 { ", …" } else { "" }
        ));
    }
    (!why.is_empty())
        .then(|| format!("{}; continue it with `run --resume --out {}`", why.join("; "), run.dir.display()))
}

fn against_baseline(run: &RunData, baseline: &RunData, t: Thresholds) -> Result<Vec<CellCheck>, Error> {
    // Cells in parallel: each comparison is single-threaded (see flip-rs in Cargo.toml).
    use rayon::prelude::*;
    let checked: Vec<Result<CellCheck, Error>> = run
        .cells
        .par_iter()
        .map(|cell| {
            let id = &cell.id.0;
            let classname = format!("{}.{}.{}", cell.composition, cell.pipeline.name(), cell.shader);
            let base_png = baseline.cell_dir(id).join("image.png");
            let mut c = CellCheck { id: id.clone(), classname, flip_mean: None, ssim: None, failure: None };
            if !baseline.has_cell(id) {
                c.failure = Some("not in the baseline".into());
            } else {
                let cmp = compare(
                    &LoadedImage::load(&base_png)?,
                    &LoadedImage::load(&run.cell_dir(id).join("image.png"))?,
                    id,
                )?;
                c.flip_mean = cmp.flip.value.mean();
                c.ssim = cmp.ssim.mean();
                let mut why = Vec::new();
                match c.flip_mean {
                    Some(f) if f > t.flip_mean => why.push(format!("FLIP mean {f:.5} > {}", t.flip_mean)),
                    None => why.push("FLIP could not be computed".into()),
                    _ => {}
                }
                match c.ssim {
                    Some(s) if s < t.ssim_min => why.push(format!("SSIM {s:.5} < {}", t.ssim_min)),
                    None => why.push("SSIM could not be computed".into()),
                    _ => {}
                }
                if !why.is_empty() {
                    c.failure = Some(why.join("; "));
                }
            }
            Ok(c)
        })
        .collect();
    let mut cells = checked.into_iter().collect::<Result<Vec<_>, _>>()?;
    for b in baseline.cells.iter().filter(|b| !run.has_cell(&b.id.0)) {
        cells.push(CellCheck {
            id: b.id.0.clone(),
            classname: "missing".into(),
            flip_mean: None,
            ssim: None,
            failure: Some("in the baseline but not in this run".into()),
        });
    }
    Ok(cells)
}

/// junit.xml through quick-junit (nextest's JUnit model): a suite of cells (with a baseline) and
/// a suite of the matrix's invariants, the adapter as a property of each.
pub fn junit(r: &CheckReport, adapter: &str) -> String {
    use quick_junit::{NonSuccessKind, Property, Report, TestCase, TestCaseStatus, TestSuite};
    let case = |classname: &str, name: &str, failure: Option<&str>| {
        let status = match failure {
            None => TestCaseStatus::success(),
            Some(why) => {
                let mut s = TestCaseStatus::non_success(NonSuccessKind::Failure);
                s.set_message(why);
                s
            }
        };
        let mut c = TestCase::new(name, status);
        c.set_classname(classname);
        c
    };
    let mut report = Report::new("shadematrix check");
    if let Some(why) = &r.incomplete {
        let mut whole = TestSuite::new("shadematrix run");
        whole.add_property(Property::new("adapter", adapter));
        whole.add_test_case(case("run", "complete", Some(why)));
        report.add_test_suite(whole);
    }
    if r.baseline.is_some() {
        let mut suite = TestSuite::new("shadematrix check");
        suite.add_property(Property::new("adapter", adapter));
        suite.add_test_cases(r.cells.iter().map(|c| case(&c.classname, &c.id, c.failure.as_deref())));
        report.add_test_suite(suite);
    }
    if !r.invariants.is_empty() {
        let mut suite = TestSuite::new("shadematrix invariants");
        suite.add_property(Property::new("adapter", adapter));
        suite.add_test_cases(
            r.invariants.iter().map(|i| case(&format!("assert.{}", i.kind), &i.name, i.message().as_deref())),
        );
        report.add_test_suite(suite);
    }
    // Serialising to memory cannot fail but on a bug in the model; say so rather than panic.
    report.to_string().unwrap_or_else(|e| format!("<!-- junit.xml could not be written: {e} -->\n"))
}

pub fn summary(r: &CheckReport, adapter: &str) -> String {
    let mut s = String::new();
    if let Some(why) = &r.incomplete {
        let _ = writeln!(s, "### shadematrix run: incomplete\n\n❌ {why}\n");
    }
    if !r.invariants.is_empty() {
        let _ = writeln!(
            s,
            "### shadematrix invariants: {} of {} failed\n\n| assert | kind | statement | result |\n|---|---|---|---|",
            r.failed_invariants(),
            r.invariants.len()
        );
        for i in &r.invariants {
            let result = i.message().map(|m| format!("❌ {m}")).unwrap_or_else(|| "✅".into());
            let _ = writeln!(s, "| {} | {} | {} | {} |", i.name, i.kind, i.statement, result.replace('|', "/"));
        }
        s.push('\n');
    }
    let Some(baseline) = &r.baseline else {
        return s;
    };
    let _ = writeln!(s, "### shadematrix check: {} of {} cells regressed\n", r.failures(), r.cells.len());
    let _ = writeln!(
        s,
        "Baseline `{}`; thresholds: FLIP mean ≤ {}, SSIM ≥ {}; adapter {}.\n",
        baseline.display(),
        r.thresholds.flip_mean,
        r.thresholds.ssim_min,
        adapter
    );
    let _ = writeln!(s, "| cell | FLIP mean | SSIM | result |\n|---|---|---|---|");
    let mut rows: Vec<&CellCheck> = r.cells.iter().collect();
    rows.sort_by_key(|c| c.failure.is_none());
    for c in rows {
        let f = |v: Option<f64>| v.map(|x| format!("{x:.5}")).unwrap_or_else(|| "—".into());
        let result = c.failure.as_deref().map(|w| format!("❌ {w}")).unwrap_or_else(|| "✅".into());
        let _ = writeln!(s, "| `{}` | {} | {} | {} |", c.id, f(c.flip_mean), f(c.ssim), result);
    }
    s
}
