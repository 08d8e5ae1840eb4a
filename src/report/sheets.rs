//! Contact sheets: PNG grids of cells, any two axes as rows × columns, the remaining axes as
//! separate sheets, with row and column labels; and difference sheets (cell | reference | FLIP).
//! Labels are drawn with the font8x8 bitmap font at 2× (no font files, no system fonts).

use font8x8::{UnicodeFonts, BASIC_FONTS};
use image::{imageops, Rgba, RgbaImage};
use std::collections::{BTreeMap, BTreeSet};

use super::run_data::RunData;
use crate::declarations::sheets::{SheetSpec, TERM_AXIS, WHOLE_IMAGE};
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::record::CellRecord;

const SCALE: u32 = 2;
const GLYPH: u32 = 8 * SCALE;
const TILE_MAX: u32 = 192;
const BG: Rgba<u8> = Rgba([32, 32, 36, 255]);
const FG: Rgba<u8> = Rgba([235, 235, 235, 255]);

pub fn draw_text(img: &mut RgbaImage, x: u32, y: u32, text: &str, colour: Rgba<u8>) {
    for (i, ch) in text.chars().enumerate() {
        let Some(glyph) = BASIC_FONTS.get(ch).or_else(|| BASIC_FONTS.get('?')) else { continue };
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8u32 {
                if bits & (1 << col) != 0 {
                    for dy in 0..SCALE {
                        for dx in 0..SCALE {
                            let (px, py) = (x + (i as u32 * 8 + col) * SCALE + dx, y + row as u32 * SCALE + dy);
                            if px < img.width() && py < img.height() {
                                img.put_pixel(px, py, colour);
                            }
                        }
                    }
                }
            }
        }
    }
}

fn text_width(s: &str) -> u32 {
    s.chars().count() as u32 * GLYPH
}

/// Tiles decoded and scaled once per report: a cell's image is on several sheets (one per spec,
/// and the difference sheets' cell and reference columns). At most `TILE_CACHE` are kept (192²
/// RGBA each, ≤ 150 MB), so memory stays bounded whatever the run's size.
#[derive(Default)]
pub struct TileCache {
    tiles: std::sync::Mutex<std::collections::HashMap<std::path::PathBuf, std::sync::Arc<RgbaImage>>>,
}

const TILE_CACHE: usize = 1024;

impl TileCache {
    fn get(&self, path: &std::path::Path) -> Option<std::sync::Arc<RgbaImage>> {
        let lock = || self.tiles.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = lock().get(path) {
            return Some(t.clone());
        }
        let tile = std::sync::Arc::new(load_tile(path, TILE_MAX)?);
        let mut tiles = lock();
        if tiles.len() < TILE_CACHE {
            tiles.insert(path.to_path_buf(), tile.clone());
        }
        Some(tile)
    }
}

fn load_tile(path: &std::path::Path, tile: u32) -> Option<RgbaImage> {
    let img = crate::images::encode::read_png(path).ok()?;
    if img.width() <= tile && img.height() <= tile {
        return Some(img);
    }
    let s = tile as f64 / img.width().max(img.height()) as f64;
    Some(imageops::resize(
        &img,
        (img.width() as f64 * s) as u32,
        (img.height() as f64 * s) as u32,
        imageops::FilterType::Triangle,
    ))
}

/// Compose a labelled grid; `tiles[r][c]` is an image path or None (drawn as an empty tile),
/// taken from `cache`.
pub fn grid(
    title: &str,
    row_labels: &[String],
    col_labels: &[String],
    tiles: &[Vec<Option<std::path::PathBuf>>],
    cache: &TileCache,
) -> RgbaImage {
    let loaded: Vec<Vec<Option<std::sync::Arc<RgbaImage>>>> =
        tiles.iter().map(|r| r.iter().map(|p| p.as_ref().and_then(|p| cache.get(p))).collect()).collect();
    grid_of_images(title, row_labels, col_labels, &loaded)
}

/// `grid` of images already loaded (None: an empty tile).
pub fn grid_of_images(
    title: &str,
    row_labels: &[String],
    col_labels: &[String],
    loaded: &[Vec<Option<std::sync::Arc<RgbaImage>>>],
) -> RgbaImage {
    let tile_w = loaded
        .iter()
        .flatten()
        .flatten()
        .map(|i| i.width())
        .max()
        .unwrap_or(64)
        .max(col_labels.iter().map(|l| text_width(l) + 8).max().unwrap_or(0).min(TILE_MAX * 2));
    let tile_h = loaded.iter().flatten().flatten().map(|i| i.height()).max().unwrap_or(64);
    let label_w = row_labels.iter().map(|l| text_width(l)).max().unwrap_or(0) + 12;
    let (pad, header) = (4, GLYPH * 2 + 16);
    let width = (label_w + col_labels.len() as u32 * (tile_w + pad) + pad).max(text_width(title) + 16);
    let height = header + row_labels.len() as u32 * (tile_h + pad) + pad;
    let mut img = RgbaImage::from_pixel(width, height, BG);
    draw_text(&mut img, 8, 4, title, FG);
    for (c, l) in col_labels.iter().enumerate() {
        draw_text(&mut img, label_w + c as u32 * (tile_w + pad) + 4, GLYPH + 10, l, FG);
    }
    for (r, l) in row_labels.iter().enumerate() {
        let y0 = header + r as u32 * (tile_h + pad);
        draw_text(&mut img, 6, y0 + tile_h / 2 - GLYPH / 2, l, FG);
        for c in 0..col_labels.len() {
            let x0 = label_w + c as u32 * (tile_w + pad);
            match loaded.get(r).and_then(|row| row.get(c)).and_then(|t| t.as_ref()) {
                Some(t) => imageops::overlay(&mut img, &**t, x0 as i64, y0 as i64),
                None => draw_text(
                    &mut img,
                    x0 + tile_w / 2 - GLYPH,
                    y0 + tile_h / 2 - GLYPH / 2,
                    "--",
                    Rgba([120, 120, 120, 255]),
                ),
            }
        }
    }
    img
}

/// A row label and its tiles.
type LabelledRow = (String, Vec<Option<std::path::PathBuf>>);

/// Rows per difference sheet.
const DIFF_ROWS_PER_SHEET: usize = 32;

pub fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect()
}

fn sort_values(axis: &str, values: BTreeSet<String>) -> Vec<String> {
    let mut v: Vec<String> = values.into_iter().collect();
    // Numeric axes in numeric order (a value the axis leaves unset sorts first).
    if crate::declarations::axes::find(axis).is_some_and(|r| r.kind == crate::declarations::axes::AxisKind::Number) {
        v.sort_by(|a, b| {
            a.parse::<f64>().unwrap_or(f64::NEG_INFINITY).total_cmp(&b.parse::<f64>().unwrap_or(f64::NEG_INFINITY))
        });
    }
    // The surface types in the engines' order (opaque, cutout, fade, transparent, …), the
    // material's own first.
    if axis == crate::declarations::axes::of(crate::declarations::axes::Axis::Surface).name {
        let rank = |n: &str| crate::pipelines::surface::SurfaceType::from_name(n).map_or(0, |s| 1 + s.shader_id());
        v.sort_by_key(|n| rank(n));
    }
    if axis == crate::declarations::axes::of(crate::declarations::axes::Axis::MaterialType).name {
        let rank = |n: &str| crate::shading::material_type::MaterialType::from_name(n).map_or(0, |t| 1 + t as u32);
        v.sort_by_key(|n| rank(n));
    }
    v
}

/// One contact sheet: its file name, title, row and column values and the cell of each tile.
#[derive(Debug, Clone)]
pub struct SheetLayout {
    pub name: String,
    pub title: String,
    pub rows: Vec<String>,
    pub cols: Vec<String>,
    /// `tiles[r][c]`: the cell at row r, column c and the image of it shown.
    pub tiles: Vec<Vec<Option<SheetTile>>>,
}

/// One tile: a cell and its image shown, relative to its folder (image.png, or a term's PNG).
#[derive(Debug, Clone, PartialEq)]
pub struct SheetTile {
    pub id: String,
    pub image: String,
}

/// The file of `cell`'s image or term layer `term` (`image` for the image), where it has one.
fn tile_image(cell: &CellRecord, term: &str) -> Option<String> {
    if term == WHOLE_IMAGE {
        return Some("image.png".into());
    }
    cell.terms.as_ref()?.layers.iter().find(|l| l.name == term).map(|l| l.png.clone())
}

/// A cell's value on a sheet axis: the `term` pseudo-axis has none (each cell spans all its values).
fn sheet_value(cell: &CellRecord, axis: &str) -> String {
    if axis == TERM_AXIS {
        return String::new();
    }
    cell.axis_value(axis)
}

/// The values of the `term` pseudo-axis over `cells`: the image, then every layer in the order
/// the records list them.
fn term_values(cells: &[&CellRecord]) -> Vec<String> {
    let mut out = vec![WHOLE_IMAGE.to_string()];
    for c in cells {
        for l in c.terms.iter().flat_map(|t| &t.layers) {
            if !out.contains(&l.name) {
                out.push(l.name.clone());
            }
        }
    }
    out
}

/// The sheets of one spec. Every axis not on the rows or columns that varies independently of
/// them splits the cells into separate sheets, so no two cells share a tile; a group with a single
/// cell gets no sheet.
pub fn layout(run: &RunData, spec: &SheetSpec) -> Vec<SheetLayout> {
    // Axes that follow from the row and column values (metallic from the preset when the
    // matrix does not sweep it) would only split sheets apart: they are not "per" axes.
    let determined = |axis: &str| {
        let mut seen: BTreeMap<(String, String), String> = BTreeMap::new();
        run.cells.iter().all(|c| {
            let key = (sheet_value(c, &spec.rows), sheet_value(c, &spec.cols));
            let v = c.axis_value(axis);
            seen.entry(key).or_insert_with(|| v.clone()) == &v
        })
    };
    let per: Vec<&str> = crate::declarations::axes::names()
        .into_iter()
        .filter(|a| *a != spec.rows && *a != spec.cols && !determined(a))
        .collect();
    let mut groups: BTreeMap<Vec<String>, Vec<&CellRecord>> = BTreeMap::new();
    for cell in &run.cells {
        groups.entry(per.iter().map(|a| cell.axis_value(a)).collect()).or_default().push(cell);
    }
    let mut out = Vec::new();
    let values = |axis: &str, cells: &[&CellRecord]| match axis {
        TERM_AXIS => term_values(cells),
        _ => sort_values(axis, cells.iter().map(|c| c.axis_value(axis)).collect()),
    };
    let shown = spec.image.as_deref().unwrap_or(WHOLE_IMAGE);
    for (key, cells) in groups {
        let rows = values(&spec.rows, &cells);
        let cols = values(&spec.cols, &cells);
        if rows.len() * cols.len() < 2 {
            continue;
        }
        // A tile's cell matches the row's and column's values (any, on the term pseudo-axis) and
        // shows the term the pseudo-axis names, else the sheet's image.
        let tile = |r: &str, c: &str| {
            let matches = |axis: &str, v: &str, cell: &CellRecord| axis == TERM_AXIS || cell.axis_value(axis) == v;
            let cell = cells.iter().find(|cell| matches(&spec.rows, r, cell) && matches(&spec.cols, c, cell))?;
            let term = match (spec.rows == TERM_AXIS, spec.cols == TERM_AXIS) {
                (true, _) => r,
                (_, true) => c,
                _ => shown,
            };
            Some(SheetTile { id: cell.id.0.clone(), image: tile_image(cell, term)? })
        };
        let tiles = rows.iter().map(|r| cols.iter().map(|c| tile(r, c)).collect()).collect();
        let mut title: Vec<String> =
            per.iter().zip(&key).filter(|(a, _)| **a != "path").map(|(a, v)| format!("{a} {v}")).collect();
        // A sheet of one term is named and titled by it, beside the image's sheet of the same axes.
        let term = Some(shown).filter(|s| *s != WHOLE_IMAGE && spec.rows != TERM_AXIS && spec.cols != TERM_AXIS);
        if let Some(term) = term {
            title.insert(0, term.replace('_', " "));
        }
        let suffix = term.map(|t| format!("_{t}")).unwrap_or_default();
        let name = format!("sheets/{}_x_{}{suffix}__{}.png", spec.rows, spec.cols, file_safe(&key.join("_")));
        out.push(SheetLayout { name, title: title.join("  "), rows, cols, tiles });
    }
    out
}

/// One sheet to draw: its file, title, labels and tile images.
struct SheetJob {
    name: String,
    title: String,
    rows: Vec<String>,
    cols: Vec<String>,
    tiles: Vec<Vec<Option<std::path::PathBuf>>>,
}

/// Write every sheet of `specs`; returns the files written (relative to the run folder). Sheets
/// are independent: they are drawn and encoded on every core (each one's bytes as drawn alone).
pub fn write(run: &RunData, specs: &[SheetSpec]) -> Result<Vec<String>, Error> {
    use rayon::prelude::*;
    let mut jobs = Vec::new();
    for spec in specs {
        for sheet in layout(run, spec) {
            let tiles: Vec<Vec<Option<std::path::PathBuf>>> = sheet
                .tiles
                .iter()
                .map(|row| row.iter().map(|t| t.as_ref().map(|t| run.cell_dir(&t.id).join(&t.image))).collect())
                .collect();
            jobs.push(SheetJob { name: sheet.name, title: sheet.title, rows: sheet.rows, cols: sheet.cols, tiles });
        }
    }
    // Difference sheets: cell | reference | FLIP map, one row per cell that has a reference.
    let mut by_comp: BTreeMap<String, Vec<LabelledRow>> = BTreeMap::new();
    for c in &run.cells {
        let Some(reference) = c.metrics.reference_cell() else { continue };
        let id = &c.id.0;
        let row = vec![
            Some(run.cell_dir(id).join("image.png")),
            Some(run.cell_dir(&reference.0).join("image.png")),
            c.metrics.maps.as_ref().map(|m| run.cell_dir(id).join(&m.flip)),
        ];
        let label = format!(
            "{}/{} {} m{} s{}",
            c.axis_value("pipeline"),
            c.axis_value("shader"),
            c.axis_value("preset"),
            c.axis_value("metallic"),
            c.axis_value("smoothness")
        );
        by_comp.entry(c.axis_value("composition")).or_default().push((label, row));
    }
    for (comp, rows) in by_comp {
        // Pages of a fixed number of rows: a sheet's size (and the memory to draw it) stays the
        // same however many cells the matrix has.
        let pages: Vec<&[LabelledRow]> = rows.chunks(DIFF_ROWS_PER_SHEET).collect();
        for (k, page) in pages.iter().enumerate() {
            let (title, name) = if pages.len() == 1 {
                (format!("{comp}: cell, reference, FLIP"), format!("sheets/diff_{}.png", file_safe(&comp)))
            } else {
                (
                    format!("{comp}: cell, reference, FLIP ({} of {})", k + 1, pages.len()),
                    format!("sheets/diff_{}_{:02}.png", file_safe(&comp), k + 1),
                )
            };
            jobs.push(SheetJob {
                name,
                title,
                rows: page.iter().map(|r| r.0.clone()).collect(),
                cols: vec!["cell".into(), "reference".into(), "FLIP".into()],
                tiles: page.iter().map(|r| r.1.clone()).collect(),
            });
        }
    }
    let cache = TileCache::default();
    jobs.par_iter()
        .map(|job| {
            let img = grid(&job.title, &job.rows, &job.cols, &job.tiles, &cache);
            let mut bytes = Vec::new();
            img.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
                .map_err(|e| Error::encode(format!("encoding {}", job.name), e))?;
            write_atomic(&run.dir.join(&job.name), &bytes)?;
            Ok(job.name.clone())
        })
        .collect()
}
