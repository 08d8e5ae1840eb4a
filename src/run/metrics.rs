//! The metrics pass, after rendering: each cell against its reference (the matrix's `reference`),
//! from the files on disk. LDR-FLIP and SSIM on the PNGs, HDR-FLIP on the EXRs, RMSE and PSNR;
//! flip.png and ssim.png into the cell folder; the figures, or why they are missing, into cell.json.

use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

use super::cells::{reference_cell_id, Cell};
use super::store::{RunDir, CELL_FILE};
use crate::compare::{compare, LoadedImage};
use crate::error::Error;
use crate::fsutil::{write_atomic, write_json};
use crate::images::encode::png_bytes;
use crate::spec::matrix::{Matrix, ReferenceSpec};

/// Where a cell's reference images are, or why there are none.
pub enum ReferenceImages {
    Found { png: PathBuf, exr: PathBuf, describe: serde_json::Value },
    Missing(String),
}

pub fn reference_for(matrix: &Matrix, dir: &RunDir, cell: &Cell) -> ReferenceImages {
    match &matrix.reference {
        None => ReferenceImages::Missing("the matrix names no reference".into()),
        Some(ReferenceSpec::Cell(terms)) => match reference_cell_id(cell, matrix, terms) {
            None => ReferenceImages::Missing("the reference cell's axes are not in this matrix".into()),
            Some(id) if id == cell.id => ReferenceImages::Missing("this cell is the reference".into()),
            Some(id) => {
                let d = dir.cell_dir(&id.0);
                if d.join(CELL_FILE).is_file() {
                    ReferenceImages::Found {
                        png: d.join("image.png"),
                        exr: d.join("image.exr"),
                        describe: json!({ "kind": "cell", "cell": id }),
                    }
                } else {
                    ReferenceImages::Missing(format!("reference cell `{id}` is not in this run"))
                }
            }
        },
        Some(ReferenceSpec::Supersampled(k)) => {
            let d = dir.cell_dir(&cell.id.0);
            if d.join("reference.exr").is_file() {
                ReferenceImages::Found {
                    png: d.join("reference.png"),
                    exr: d.join("reference.exr"),
                    describe: json!({ "kind": "supersampled", "factor": k }),
                }
            } else {
                ReferenceImages::Missing(format!("no {k}× supersampled render (see the cell's reference_missing)"))
            }
        }
        Some(ReferenceSpec::Run(run)) => {
            let d = run.join("cells").join(&cell.id.0);
            if d.join("image.png").is_file() {
                ReferenceImages::Found {
                    png: d.join("image.png"),
                    exr: d.join("image.exr"),
                    describe: json!({ "kind": "run", "run": run, "cell": cell.id }),
                }
            } else {
                ReferenceImages::Missing(format!("{} has no cell `{}`", run.display(), cell.id))
            }
        }
    }
}

/// Compute and record the metrics of one cell.
pub fn cell_metrics(matrix: &Matrix, dir: &RunDir, cell: &Cell) -> Result<(), Error> {
    let t0 = Instant::now();
    let cdir = dir.cell_dir(&cell.id.0);
    let metrics = match reference_for(matrix, dir, cell) {
        ReferenceImages::Missing(why) => json!({ "reference": { "missing": why } }),
        ReferenceImages::Found { png, exr, describe } => {
            let ldr = compare(&LoadedImage::load(&png)?, &LoadedImage::load(&cdir.join("image.png"))?, &cell.id.0)?;
            for (name, px) in [("flip.png", &ldr.flip_map_rgba8), ("ssim.png", &ldr.ssim_map_rgba8)] {
                if let Some(px) = px {
                    write_atomic(&cdir.join(name), &png_bytes(ldr.width, ldr.height, px)?)?;
                }
            }
            let hdr = if exr.is_file() {
                let h = compare(&LoadedImage::load(&exr)?, &LoadedImage::load(&cdir.join("image.exr"))?, &cell.id.0)?;
                json!({ "flip": h.flip, "rmse": h.rmse, "reference_bad": h.reference_bad, "test_bad": h.test_bad })
            } else {
                json!({ "missing": "the reference has no EXR" })
            };
            json!({ "reference": describe, "ldr": ldr, "hdr": hdr, "maps": { "flip": "flip.png", "ssim": "ssim.png" } })
        }
    };
    let path = cdir.join(CELL_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io_path("reading", &path, e))?;
    let mut v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| Error::Other(format!("{}: {e}", path.display())))?;
    v["metrics"] = metrics;
    v["timing"]["metrics_ms"] = json!(t0.elapsed().as_secs_f64() * 1e3);
    write_json(&path, &v)
}
