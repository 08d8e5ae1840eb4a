//! The metrics stage: each cell against its reference (the matrix's `reference`). LDR-FLIP and
//! SSIM on the sRGB values, HDR-FLIP on the linear values, RMSE and PSNR; flip.png and ssim.png
//! into the cell folder. The cell's own images come from memory when the encode stage hands them
//! over, else from its files; references are read from their files.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use super::encode::CellImages;
use crate::cells::{reference_cell_id, Cell, CellId};
use crate::compare::images::{compare_on, MetricsBackend};
use crate::compare::LoadedImage;
use crate::declarations::matrix::{Matrix, ReferenceSpec};
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::images::encode::map_png_bytes;
use crate::record::cell::{
    ApproximationRecord, ApproximationResult, CellMetrics, HdrComparison, MetricMaps, ReferenceRecord,
};
use crate::record::{Maybe, RunDir};

/// Where a cell's reference is.
pub enum ReferenceSource {
    /// A cell of this run: its images are final once the encode stage has written them.
    RunCell(CellId),
    /// Files that exist now (supersampled render in the cell's folder, or an earlier run).
    Files {
        png: PathBuf,
        exr: PathBuf,
        record: ReferenceRecord,
    },
    Missing(String),
}

/// Resolve the matrix's reference for `cell`; `in_run` says whether a cell id is one of this run's.
pub fn reference_source(
    matrix: &Matrix,
    dir: &RunDir,
    cell: &Cell,
    in_run: &dyn Fn(&CellId) -> bool,
) -> ReferenceSource {
    match &matrix.reference {
        None => ReferenceSource::Missing("the matrix names no reference".into()),
        Some(ReferenceSpec::Cell(terms)) => match reference_cell_id(cell, matrix, terms) {
            None => ReferenceSource::Missing("the reference cell's axes are not in this matrix".into()),
            Some(id) if id == cell.id => ReferenceSource::Missing("this cell is the reference".into()),
            Some(id) if in_run(&id) => ReferenceSource::RunCell(id),
            Some(id) => ReferenceSource::Missing(format!("reference cell `{id}` is not in this run")),
        },
        Some(ReferenceSpec::Supersampled(k)) => {
            let d = dir.cell_dir(&cell.id.0);
            ReferenceSource::Files {
                png: d.join("reference.png"),
                exr: d.join("reference.exr"),
                record: ReferenceRecord::Supersampled { factor: *k },
            }
        }
        Some(ReferenceSpec::Truth(t)) => {
            let d = dir.cell_dir(&cell.id.0);
            ReferenceSource::Files {
                png: d.join("reference.png"),
                exr: d.join("reference.exr"),
                record: ReferenceRecord::Truth {
                    truth: t.settings.kind.name().into(),
                    spp: t.settings.spp,
                    noise: t.settings.noise,
                    bounces: t.settings.bounces,
                    roulette: t.settings.roulette,
                },
            }
        }
        Some(ReferenceSpec::Run(run)) => {
            let d = run.join("cells").join(&cell.id.0);
            if d.join("image.png").is_file() {
                ReferenceSource::Files {
                    png: d.join("image.png"),
                    exr: d.join("image.exr"),
                    record: ReferenceRecord::Run { run: run.display().to_string(), cell: cell.id.clone() },
                }
            } else {
                ReferenceSource::Missing(format!("{} has no cell `{}`", run.display(), cell.id))
            }
        }
    }
}

/// A reference's images, decoded once and shared by the cells compared with it.
pub struct ReferenceImages {
    ldr: LoadedImage,
    /// None when the reference has no EXR.
    hdr: Option<LoadedImage>,
}

impl ReferenceImages {
    pub fn load(png: &Path, exr: &Path) -> Result<ReferenceImages, Error> {
        Ok(ReferenceImages {
            ldr: LoadedImage::load(png)?,
            hdr: if exr.is_file() { Some(LoadedImage::load(exr)?) } else { None },
        })
    }
}

/// The last few references decoded. Cells of one reference are rendered close together, so a
/// handful of entries saves nearly every decode, and memory stays bounded whatever the matrix.
pub struct ReferenceCache {
    entries: Mutex<Vec<(PathBuf, Arc<ReferenceImages>)>>,
    capacity: usize,
}

impl ReferenceCache {
    pub fn new(capacity: usize) -> ReferenceCache {
        ReferenceCache { entries: Mutex::new(Vec::new()), capacity }
    }

    pub fn get(&self, png: &Path, exr: &Path) -> Result<Arc<ReferenceImages>, Error> {
        if let Some(hit) = self.lock().iter().find(|(p, _)| p == png).map(|(_, r)| r.clone()) {
            return Ok(hit);
        }
        let loaded = Arc::new(ReferenceImages::load(png, exr)?);
        let mut entries = self.lock();
        entries.retain(|(p, _)| p != png);
        entries.push((png.to_path_buf(), loaded.clone()));
        if entries.len() > self.capacity {
            entries.remove(0);
        }
        Ok(loaded)
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<(PathBuf, Arc<ReferenceImages>)>> {
        self.entries.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A study frame (run::study) against the cell's truth: LDR-FLIP and SSIM of what it shows,
/// the relative MSE of what it holds, and its time.
pub fn measure_study(
    s: super::encode::StudyImages,
    truth: &ReferenceImages,
    what: &str,
    backend: MetricsBackend,
) -> Result<ApproximationRecord, Error> {
    let (w, h) = (s.images.width, s.images.height);
    let ldr = LoadedImage::Ldr { width: w, height: h, rgba8: s.images.srgb8 };
    let c = compare_on(&truth.ldr, &ldr, what, false, backend)?;
    let hdr_relative_mse = match &truth.hdr {
        Some(LoadedImage::Hdr { rgba, .. }) if rgba.len() == s.images.hdr.len() => {
            match crate::compare::stats::relative_mse(rgba, &s.images.hdr) {
                Some(e) => Maybe::Value(e),
                None => Maybe::missing("the truth is black"),
            }
        }
        _ => Maybe::missing("the truth has no EXR of the frame's size"),
    };
    let metric = |m: &crate::compare::images::Metric| match m {
        crate::compare::images::Metric::Value { mean } => Maybe::Value(*mean),
        crate::compare::images::Metric::Missing { missing } => Maybe::missing(missing.clone()),
    };
    Ok(ApproximationRecord {
        approximation: s.variant.approximation.name().into(),
        variant: s.variant.name,
        change: s.variant.change,
        result: Maybe::Value(ApproximationResult {
            image: s.image,
            gpu_ms: s.gpu_ms.map_or_else(|| Maybe::missing("the adapter has no timestamp queries"), Maybe::Value),
            cpu_wall_ms: s.cpu_wall_ms,
            samples: s.samples,
            flip: metric(&c.flip.value),
            ssim: metric(&c.ssim),
            hdr_relative_mse,
        }),
    })
}

/// An EXR times the exposure its cell shows it with (metered from the image itself, as the
/// display transform does; 1 in pipelines without exposure), and that exposure.
fn exposed(image: &LoadedImage, cell: &Cell) -> (LoadedImage, f64) {
    let LoadedImage::Hdr { width, height, rgba } = image else { return (image.clone(), 1.0) };
    let k = cell
        .display
        .exposure
        .as_ref()
        .map_or(1.0, |s| crate::images::exposure::meter(rgba, *width, *height, s).exposure);
    let scaled = rgba.chunks_exact(4).flat_map(|p| [p[0] * k as f32, p[1] * k as f32, p[2] * k as f32, p[3]]).collect();
    (LoadedImage::Hdr { width: *width, height: *height, rgba: scaled }, k)
}

/// Compare a cell's images with its reference's; writes flip.png and ssim.png into `cell_dir`
/// unless the matrix's `[outputs] maps = false`.
/// How a run compares: where the metrics run, and whether the maps are written.
#[derive(Clone, Copy)]
pub struct MetricOptions<'a> {
    pub backend: MetricsBackend<'a>,
    pub write_maps: bool,
}

pub fn compare_cell(
    cell: &Cell,
    cell_dir: &Path,
    options: MetricOptions,
    images: Option<CellImages>,
    reference: &ReferenceImages,
    record: ReferenceRecord,
    reference_cell: Option<&Cell>,
) -> Result<CellMetrics, Error> {
    let MetricOptions { backend, write_maps } = options;
    let (ldr, hdr) = match images {
        Some(i) => (
            LoadedImage::Ldr { width: i.width, height: i.height, rgba8: i.srgb8 },
            LoadedImage::Hdr { width: i.width, height: i.height, rgba: i.hdr },
        ),
        None => (LoadedImage::load(&cell_dir.join("image.png"))?, LoadedImage::load(&cell_dir.join("image.exr"))?),
    };
    let c = compare_on(&reference.ldr, &ldr, &cell.id.0, false, backend)?;
    for (name, px) in [("flip.png", &c.flip_map_rgba8), ("ssim.png", &c.ssim_map_rgba8)] {
        if let Some(px) = px.as_ref().filter(|_| write_maps) {
            write_atomic(&cell_dir.join(name), &map_png_bytes(c.width, c.height, px)?)?;
        }
    }
    let hdr_test = hdr;
    let hdr = match &reference.hdr {
        Some(r) => {
            let (h, exposed) = match reference_cell.filter(|rc| rc.pipeline != cell.pipeline) {
                Some(rc) => {
                    let (t, kt) = exposed(&hdr_test, cell);
                    let (r, kr) = exposed(r, rc);
                    (compare_on(&r, &t, &cell.id.0, false, backend)?, Some((kt, kr)))
                }
                None => (compare_on(r, &hdr_test, &cell.id.0, false, backend)?, None),
            };
            Maybe::Value(HdrComparison {
                flip: h.flip,
                rmse: h.rmse,
                relative_mse: h.relative_mse,
                reference_bad: h.reference_bad,
                test_bad: h.test_bad,
                exposed,
            })
        }
        None => Maybe::missing("the reference has no EXR"),
    };
    let ztest = match (&record, &reference.hdr, &hdr_test) {
        (ReferenceRecord::Truth { .. }, Some(LoadedImage::Hdr { rgba: truth, .. }), LoadedImage::Hdr { rgba, .. }) => {
            let noise = cell_dir.join(crate::run::encode::TRUTH_NOISE_MAP);
            Some(match LoadedImage::load(&noise)? {
                LoadedImage::Hdr { rgba: se, .. } if se.len() == rgba.len() && truth.len() == rgba.len() => {
                    Maybe::Value(crate::compare::ztest::ztest(rgba, truth, &se, 0.01))
                }
                _ => Maybe::missing(format!("{} does not match the image's size", noise.display())),
            })
        }
        (ReferenceRecord::Truth { .. }, _, _) => Some(Maybe::missing("the truth or the cell has no EXR")),
        _ => None,
    };
    Ok(CellMetrics {
        reference: Maybe::Value(record),
        ldr: Some(c),
        hdr: Some(hdr),
        maps: write_maps.then(|| MetricMaps { flip: "flip.png".into(), ssim: "ssim.png".into() }),
        ztest,
    })
}
