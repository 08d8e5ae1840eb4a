//! The offline HTML gallery, `gallery.html` in the run folder (`index.html` is the viewer,
//! report::viewer): works from the file system (no server, no network), filters by axis, shows
//! each cell's images, metrics and timings, the perf table (sortable), the error-vs-time plots and
//! the contact sheets. A minijinja template (`templates/gallery.html`), which escapes every value.
//! The page checks itself after loading: broken images and script errors are counted into
//! `data-broken-images` and `data-errors` on <body> (read by the Chromium test).

use std::collections::BTreeSet;

use serde::Serialize;

use super::perf;
use super::run_data::RunData;
use crate::error::Error;
use crate::fsutil::write_atomic;

/// A path segment in an href/src: cell ids are filesystem-safe, but escape anyway.
fn url(s: &str) -> String {
    s.chars()
        .map(
            |c| {
                if c.is_ascii_alphanumeric() || "-_./".contains(c) {
                    c.to_string()
                } else {
                    format!("%{:02X}", c as u32)
                }
            },
        )
        .collect()
}

/// The axes the gallery filters by: the named axes (composition … preset) and every other axis of
/// the table (`declarations::axes`) that takes more than one value among the run's cells.
fn filter_axes(run: &RunData) -> Vec<&'static str> {
    use crate::declarations::axes::{AxisKind, AXES};
    AXES.iter()
        .filter(|r| {
            r.kind == AxisKind::Name
                || run.cells.iter().map(|c| c.axis_value(r.name)).collect::<BTreeSet<_>>().len() > 1
        })
        .map(|r| r.name)
        .collect()
}

fn num(v: Option<f64>, digits: usize) -> String {
    v.map(|x| format!("{x:.digits$}")).unwrap_or_else(|| "—".into())
}

#[derive(Serialize)]
struct Filter {
    axis: &'static str,
    values: BTreeSet<String>,
}

#[derive(Serialize)]
struct CellCard {
    id: String,
    /// The cell's folder as a relative URL.
    dir: String,
    axes: Vec<(&'static str, String)>,
    compared: bool,
    maps: bool,
    reference: String,
    flip: String,
    ssim: String,
    hdr_flip: String,
    missing: String,
    gpu_ms: String,
    cpu_ms: String,
    origin: String,
}

#[derive(Serialize)]
struct Linked {
    name: String,
    url: String,
}

/// The page: a minijinja template (`templates/gallery.html`); every value is escaped by it.
pub fn html(run: &RunData, sheets: &[String], plots: &[String]) -> Result<String, Error> {
    let m = &run.run.matrix;
    let axes = filter_axes(run);
    let filters: Vec<Filter> = axes
        .iter()
        .map(|&axis| Filter { axis, values: run.cells.iter().map(|c| c.axis_value(axis)).collect() })
        .collect();
    let cells: Vec<CellCard> = run
        .cells
        .iter()
        .map(|c| {
            let metrics = &c.metrics;
            CellCard {
                id: c.id.0.clone(),
                dir: format!("cells/{}", url(&c.id.0)),
                axes: axes.iter().map(|&a| (a, c.axis_value(a))).collect(),
                compared: metrics.ldr.is_some(),
                maps: metrics.maps.is_some(),
                reference: metrics.reference.value().map(|r| r.label()).unwrap_or_default(),
                flip: num(metrics.ldr_flip(), 4),
                ssim: num(metrics.ldr_ssim(), 4),
                hdr_flip: num(metrics.hdr_flip(), 4),
                missing: metrics.reference.why_missing().unwrap_or("not computed").to_string(),
                gpu_ms: num(c.gpu_median_ms(), 3),
                cpu_ms: num(c.timing.cpu_wall.median_ms, 3),
                origin: match &c.twin_of {
                    None => "rendered".to_string(),
                    Some(t) => format!("twin of {}", t.0),
                },
            }
        })
        .collect();
    let perf: Vec<[String; 9]> = perf::rows(run)
        .into_iter()
        .map(|r| {
            let o = |v: Option<f64>| num(v, 3);
            [
                r.id.clone(),
                r.pipeline.clone(),
                r.shader.clone(),
                o(r.gpu_median_ms),
                o(r.gpu_min_ms),
                o(r.gpu_max_ms),
                o(r.cpu_wall_median_ms),
                o(r.readback_ms),
                o(r.encode_ms),
            ]
        })
        .collect();
    let linked =
        |paths: &[String]| -> Vec<Linked> { paths.iter().map(|p| Linked { name: p.clone(), url: url(p) }).collect() };
    let mut env = minijinja::Environment::new();
    env.add_template("gallery.html", include_str!("templates/gallery.html"))
        .map_err(|e| Error::encode("loading the gallery template", e))?;
    let template = env.get_template("gallery.html").map_err(|e| Error::encode("loading the gallery template", e))?;
    template
        .render(minijinja::context! {
            name => m.name,
            origin => m.origin,
            sha => m.sha256.chars().take(12).collect::<String>(),
            adapter => run.adapter(),
            counts => run.run.counts,
            status => run.run.status.in_reports().name(),
            approximations => run.dir.join("tables/approximations.md").is_file(),
            quality => run.dir.join("tables/quality.md").is_file(),
            filters => filters,
            cells => cells,
            // Big runs load images as they scroll into view; small ones at once, so the page's
            // own check (data-broken-images) sees every image.
            lazy => run.cells.len() > LAZY_FROM,
            perf => perf,
            plots => linked(plots),
            sheets => linked(sheets),
        })
        .map_err(|e| Error::encode("rendering the gallery", e))
}

pub const FILE: &str = "gallery.html";

/// From this many cells on, images load lazily.
const LAZY_FROM: usize = 200;

/// Write the gallery; returns the plots it links.
pub fn write(run: &RunData, sheets: &[String]) -> Result<Vec<String>, Error> {
    let mut plots: Vec<String> = std::fs::read_dir(run.dir.join("plots"))
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| format!("plots/{}", e.file_name().to_string_lossy()))
                .filter(|p| p.ends_with(".svg"))
                .collect()
        })
        .unwrap_or_default();
    plots.sort();
    write_atomic(&run.dir.join(FILE), html(run, sheets, &plots)?.as_bytes())?;
    Ok(plots)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping() {
        assert_eq!(url("cells/a b"), "cells/a%20b");
    }
}
