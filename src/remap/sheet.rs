//! A match's pictures: each material's frames (`frames/NNN/<composition>-source|copied|fitted.png`,
//! as compared) and a sheet per preset (`sheets/<preset>.png`): one row per material and
//! composition, the source's frame beside the target's with the values copied and fitted.

use std::path::Path;

use super::fit::FitFrames;
use super::table::{MatchRecord, MatchRow};
use super::Frame;
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::images::encode::{png_bytes, read_png};
use crate::report::sheets::{file_safe, grid_of_images};

/// The three frames a row shows per composition, in the sheet's column order.
pub const KINDS: [&str; 3] = ["source", "copied", "fitted"];

/// The file of one frame of a row, relative to the match's folder.
pub fn frame_path(row_frames: &str, composition: &str, kind: &str) -> String {
    format!("{row_frames}/{}-{kind}.png", file_safe(composition))
}

/// Row `index`'s frames under `out`; returns their folder relative to `out`.
pub fn write_frames(
    out: &Path,
    index: usize,
    compositions: &[String],
    size: u32,
    source: &[Frame],
    fitted: &FitFrames,
) -> Result<String, Error> {
    let folder = format!("frames/{index:03}");
    for (k, composition) in compositions.iter().enumerate() {
        for (kind, frame) in KINDS.iter().zip([&source[k], &fitted.copied[k], &fitted.fitted[k]]) {
            write_atomic(&out.join(frame_path(&folder, composition, kind)), &png_bytes(size, size, &frame.srgb8)?)?;
        }
    }
    Ok(folder)
}

/// A row's source material in a label: its smoothness, metallic and swept parameters (its preset
/// and colour are the preset's).
pub fn material_label(r: &MatchRow) -> String {
    let mut label = format!("s {:.2} m {:.2}", r.source.smoothness, r.source.metallic);
    for (k, v) in &r.source.params {
        label += &format!(" {k} {v:.2}");
    }
    label
}

/// Frames are magnified by a whole factor (nearest neighbour, pixels kept sharp) to at least this
/// side in a sheet: a 64² match frame is too small to judge.
const TILE_SIDE: u32 = 128;

/// A row's frame, magnified for its sheet.
fn tile(path: &Path) -> Result<std::sync::Arc<image::RgbaImage>, Error> {
    let img = read_png(path)?;
    let k = TILE_SIDE.div_ceil(img.width().max(1)).max(1);
    let big = image::imageops::resize(&img, img.width() * k, img.height() * k, image::imageops::FilterType::Nearest);
    Ok(std::sync::Arc::new(big))
}

/// One sheet per preset under `out/sheets`; returns their paths relative to `out`.
pub fn write_sheets(out: &Path, record: &MatchRecord) -> Result<Vec<String>, Error> {
    let mut written = Vec::new();
    for summary in record.summary().iter().filter(|p| p.preset != "all") {
        let rows: Vec<&MatchRow> = record.rows.iter().filter(|r| r.preset == summary.preset).collect();
        let (mut labels, mut tiles) = (Vec::new(), Vec::new());
        for r in &rows {
            for c in &record.compositions {
                labels.push(format!("{} {c}", material_label(r)));
                let row: Result<Vec<_>, Error> =
                    KINDS.iter().map(|k| tile(&out.join(frame_path(&r.frames, c, k))).map(Some)).collect();
                tiles.push(row?);
            }
        }
        let title = format!(
            "{}: {} -> {}, mean FLIP {:.3} copied, {:.3} fitted",
            summary.preset, record.from, record.to, summary.copied_flip, summary.fitted_flip
        );
        let columns: Vec<String> = KINDS.iter().map(|k| k.to_string()).collect();
        let img = grid_of_images(&title, &labels, &columns, &tiles);
        let name = format!("sheets/{}.png", file_safe(&summary.preset));
        write_atomic(&out.join(&name), &png_bytes(img.width(), img.height(), img.as_raw())?)?;
        written.push(name);
    }
    Ok(written)
}

/// Removes what an earlier match into `out` left that this one does not name: `frames/NNN`
/// folders past its `rows` and sheets of presets it has not (`sheets`, relative to `out`), so
/// the folder holds one match. Only names of the shapes a match writes are touched.
pub fn prune_stale(out: &Path, rows: usize, sheets: &[String]) -> Result<(), Error> {
    let entries = |dir: &Path| -> Vec<std::fs::DirEntry> {
        std::fs::read_dir(dir).map(|d| d.filter_map(Result::ok).collect()).unwrap_or_default()
    };
    for e in entries(&out.join("frames")) {
        let name = e.file_name().to_string_lossy().to_string();
        let stale = name.len() >= 3
            && name.bytes().all(|b| b.is_ascii_digit())
            && name.parse::<usize>().is_ok_and(|i| i >= rows);
        if stale && e.path().is_dir() {
            std::fs::remove_dir_all(e.path()).map_err(|err| Error::io_path("removing", &e.path(), err))?;
        }
    }
    for e in entries(&out.join("sheets")) {
        let name = format!("sheets/{}", e.file_name().to_string_lossy());
        if name.ends_with(".png") && !sheets.contains(&name) && e.path().is_file() {
            std::fs::remove_file(e.path()).map_err(|err| Error::io_path("removing", &e.path(), err))?;
        }
    }
    Ok(())
}
