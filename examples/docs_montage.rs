//! Lays out a picture for docs/ from a run's cells: each ROW argument a comma-separated list of
//! cell ids, `*` standing for any run of characters (each must name exactly one cell), each
//! cell's image.png scaled to TILE² with a triangle filter. `tools/docs_pictures.sh` runs it for
//! README's picture and the figures that are not one sheet:
//! `cargo run --release --example docs_montage -- RUN_FOLDER OUT.png TILE ROW [ROW …]`.

use std::path::{Path, PathBuf};

/// Whether `id` matches `pattern`, whose `*`s stand for any run of characters.
fn matches(pattern: &str, id: &str) -> bool {
    let parts: Vec<&str> = pattern.split('*').collect();
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if parts.len() == 1 {
        return id == pattern;
    }
    if !id.starts_with(first) || !id[first.len()..].ends_with(last) {
        return false;
    }
    let mut rest = &id[first.len()..id.len() - last.len()];
    for part in &parts[1..parts.len() - 1] {
        match rest.find(part) {
            Some(at) => rest = &rest[at + part.len()..],
            None => return false,
        }
    }
    true
}

/// The one cell folder of `run` whose id matches `pattern`.
fn cell(run: &Path, pattern: &str) -> Result<PathBuf, String> {
    let cells = run.join("cells");
    let entries = std::fs::read_dir(&cells).map_err(|e| format!("{}: {e}", cells.display()))?;
    let mut found: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(|n| matches(pattern, n)))
        .collect();
    found.sort();
    match found.as_slice() {
        [one] => Ok(one.clone()),
        [] => Err(format!("{}: no cell matches {pattern}", cells.display())),
        many => Err(format!("{}: {} cells match {pattern}, expected one", cells.display(), many.len())),
    }
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [run, out, tile, rows @ ..] = args.as_slice() else {
        return Err("usage: docs_montage RUN_FOLDER OUT.png TILE ROW [ROW …]".into());
    };
    let tile: u32 = tile.parse().map_err(|e| format!("TILE `{tile}`: {e}"))?;
    let rows: Vec<Vec<&str>> = rows.iter().map(|r| r.split(',').collect()).collect();
    let columns = rows.iter().map(Vec::len).max().unwrap_or(0) as u32;
    if rows.is_empty() || columns == 0 {
        return Err("no rows".into());
    }
    let mut sheet = image::RgbImage::new(tile * columns, tile * rows.len() as u32);
    for (r, row) in rows.iter().enumerate() {
        for (c, pattern) in row.iter().enumerate() {
            let path = cell(Path::new(run), pattern)?.join("image.png");
            let image = image::open(&path).map_err(|e| format!("{}: {e}", path.display()))?.to_rgb8();
            let image = image::imageops::resize(&image, tile, tile, image::imageops::FilterType::Triangle);
            image::imageops::replace(&mut sheet, &image, (c as u32 * tile) as i64, (r as u32 * tile) as i64);
        }
    }
    sheet.save(out).map_err(|e| format!("{out}: {e}"))
}
