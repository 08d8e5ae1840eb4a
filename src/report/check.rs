//! `shadematrix check RUN --baseline DIR`: every cell's image against the baseline run's image of
//! the same cell id (LDR-FLIP mean and SSIM on the PNGs). Writes junit.xml (one testcase per cell)
//! and summary.md (a table fit for a CI job summary) into the run folder.

use serde::Serialize;
use std::fmt::Write;
use std::path::Path;

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
    pub cells: Vec<CellCheck>,
    pub thresholds: Thresholds,
}

impl CheckReport {
    pub fn failures(&self) -> usize {
        self.cells.iter().filter(|c| c.failure.is_some()).count()
    }
}

pub fn check(run_dir: &Path, baseline_dir: &Path, t: Thresholds) -> Result<CheckReport, Error> {
    let run = RunData::load(run_dir)?;
    let baseline = RunData::load(baseline_dir)?;
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
    let report = CheckReport { cells, thresholds: t };
    write_atomic(&run_dir.join("junit.xml"), junit(&report, &run.adapter()).as_bytes())?;
    write_atomic(&run_dir.join("summary.md"), summary(&report, baseline_dir, &run.adapter()).as_bytes())?;
    Ok(report)
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;").replace('\'', "&apos;")
}

pub fn junit(r: &CheckReport, adapter: &str) -> String {
    let mut s = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        s,
        "<testsuites name=\"shadematrix check\" tests=\"{}\" failures=\"{}\">",
        r.cells.len(),
        r.failures()
    );
    let _ = writeln!(
        s,
        "  <testsuite name=\"shadematrix check\" tests=\"{}\" failures=\"{}\">",
        r.cells.len(),
        r.failures()
    );
    let _ = writeln!(s, "    <properties><property name=\"adapter\" value=\"{}\"/></properties>", xml_escape(adapter));
    for c in &r.cells {
        let _ = write!(s, "    <testcase classname=\"{}\" name=\"{}\"", xml_escape(&c.classname), xml_escape(&c.id));
        match &c.failure {
            None => {
                let _ = writeln!(s, "/>");
            }
            Some(why) => {
                let _ = writeln!(s, ">\n      <failure message=\"{}\"/>\n    </testcase>", xml_escape(why));
            }
        }
    }
    s.push_str("  </testsuite>\n</testsuites>\n");
    s
}

pub fn summary(r: &CheckReport, baseline: &Path, adapter: &str) -> String {
    let mut s = String::new();
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
