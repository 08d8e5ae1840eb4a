//! The viewer, `index.html` in the run folder: the comparison application as an offline page. Pick
//! a composition, pipeline, path, shader and preset for two cells A and B, move sliders over every
//! swept axis (snapping to the rendered values, showing the exact value), and compare side by side,
//! with a wipe, by flicker, or with a difference map over them; a magnifier reads the pixel's sRGB
//! and linear values (`images::pixels`). The URL fragment holds the whole view.
//!
//! The page is a minijinja template (`templates/viewer.html`) and a script (`templates/viewer.js`).
//! Its data is one compact script beside it, `viewer-data.js` (a page opened from `file://` may load
//! scripts but not fetch JSON): axes as value tables, each cell as an array of value indices, so a
//! 10 000-cell run stays a few megabytes and loads without freezing; images load only when shown.

use std::collections::{BTreeMap, BTreeSet};

use serde::Serialize;

use super::run_data::RunData;
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::record::CellRecord;

pub const VIEWER_SCHEMA: u32 = 1;
pub const DATA_FILE: &str = "viewer-data.js";

/// The axes chosen with pickers; every other axis gets a slider over its values.
const PICKED: [&str; 5] = ["composition", "pipeline", "path", "shader", "preset"];

/// The data the page reads.
#[derive(Debug, Serialize)]
pub struct ViewerData {
    pub schema: u32,
    pub run: ViewerRun,
    /// Every axis with its values: `choice` axes get pickers; `number` axes (sorted by value) and
    /// `ordered` ones (colour, parameter sets, textured: sorted by name) get sliders.
    pub axes: Vec<ViewerAxis>,
    pub cells: Vec<ViewerCell>,
    /// Distinct pass lists (a cell's frame plan names one by index).
    pub plans: Vec<Vec<String>>,
    /// The names of the timed passes (a cell's per-pass GPU times name them by index).
    pub pass_kinds: Vec<String>,
    pub pruned: Vec<crate::cells::PrunedCell>,
    /// The rest of the run: gallery, tables, plots, sheets (paths relative to the run folder).
    pub links: Vec<(String, String)>,
    /// LDR-FLIP's filters, for FLIP of A against B in the page.
    pub flip: ViewerFlip,
    /// The term layers the run's cells have (`[outputs] terms`), in their records' order: the page
    /// can show each instead of the image (`terms/<name>.png`).
    pub terms: Vec<String>,
}

/// `compare::gpu::flip_filters`: spatial weights (Y, Cx, Cz₁, Cz₂ per tap), feature weights
/// (Gaussian, first and second derivative per tap), cmax.
#[derive(Debug, Serialize)]
pub struct ViewerFlip {
    pub spatial: Vec<[f32; 4]>,
    pub feature: Vec<[f32; 3]>,
    pub cmax: f32,
}

impl ViewerFlip {
    pub fn new() -> ViewerFlip {
        let (spatial, feature, cmax) = crate::compare::gpu::flip_filters();
        ViewerFlip { spatial, feature, cmax }
    }
}

impl Default for ViewerFlip {
    fn default() -> Self {
        Self::new()
    }
}

#[derive(Debug, Serialize)]
pub struct ViewerRun {
    pub name: String,
    pub adapter: String,
    pub matrix: String,
    pub status: String,
    pub cells: usize,
    pub rendered: usize,
    pub twins: usize,
    pub pruned: usize,
}

#[derive(Debug, Serialize)]
pub struct ViewerAxis {
    pub name: String,
    pub kind: &'static str,
    pub values: Vec<String>,
}

/// One cell: id, the index of its value on every axis, the index of the cell it is a twin of and
/// of the cell it was compared with (−1: none), its means (LDR-FLIP, SSIM, HDR-FLIP; null: not
/// computed), GPU median ms, its plan's index, flags (1: FLIP/SSIM maps, 2: pixels.js, 4: term layers, 8: its own
/// reference.png, 16: its truth's noise picture), its size,
/// its reference's label when that is not a cell of the run, and its other timings.
#[derive(Debug, Serialize)]
pub struct ViewerCell(
    pub String,
    pub Vec<u32>,
    pub i64,
    pub i64,
    pub [Option<f64>; 3],
    pub Option<f64>,
    pub u32,
    pub u32,
    pub [u32; 2],
    pub Option<String>,
    pub ViewerTiming,
);

/// A cell's timings besides the GPU median: CPU wall median (submit to idle) ms, the index of the
/// cell whose frames it carries (−1: its own; `plan::timing`), and each pass's GPU median ms by
/// its index in `pass_kinds`.
#[derive(Debug, Serialize)]
pub struct ViewerTiming(pub Option<f64>, pub i64, pub Vec<(u32, f64)>);

/// A cell's value on `axis` as the viewer shows it: numbers exactly (the shortest decimal that
/// reads back to the recorded value), names as recorded; an engine setting (`settings.<key>`) as
/// its label, `own` where the cell keeps its matrix's or its preset's.
fn value(c: &CellRecord, axis: &str) -> String {
    match axis.strip_prefix(SETTING_PREFIX) {
        Some(key) => c.coords.settings.get(key).map_or_else(|| "own".to_string(), |v| v.label()),
        None => c.coords.exact(axis),
    }
}

/// The viewer's axis of one swept engine setting: `settings.shadow_resolution`.
const SETTING_PREFIX: &str = "settings.";

/// The axes the viewer offers, in the order its controls appear: every axis of the table, the
/// swept engine settings each its own (a slider per setting, not one over their combinations).
fn axis_names(run: &RunData) -> Vec<String> {
    let settings: BTreeSet<&String> = run.cells.iter().flat_map(|c| c.coords.settings.keys()).collect();
    crate::declarations::axes::names()
        .into_iter()
        .filter(|n| *n != crate::declarations::axes::of(crate::declarations::axes::Axis::Settings).name)
        .map(str::to_string)
        .chain(settings.into_iter().map(|k| format!("{SETTING_PREFIX}{k}")))
        .collect()
}

/// The index of `value` in `table`, added at the end the first time it is seen.
fn intern<T: PartialEq + Clone>(table: &mut Vec<T>, value: &T) -> u32 {
    match table.iter().position(|t| t == value) {
        Some(i) => i as u32,
        None => {
            table.push(value.clone());
            table.len() as u32 - 1
        }
    }
}

pub fn data(run: &RunData, links: Vec<(String, String)>) -> ViewerData {
    // The axes the viewer offers, in the order its controls appear: every axis of the table.
    let names = axis_names(run);
    let mut axes = Vec::new();
    for name in names.iter().map(String::as_str) {
        let mut seen: BTreeSet<String> = run.cells.iter().map(|c| value(c, name)).collect();
        // A pruned value is offered too, so that picking it says why there is no such cell.
        seen.extend(
            run.run.pruned.iter().flat_map(|p| p.axes.iter()).filter(|(a, _)| a == name).map(|(_, v)| v.clone()),
        );
        let mut values: Vec<String> = seen.into_iter().collect();
        // Hex codes such as 333333 read as numbers; a colour axis is a list of names.
        let colour = crate::declarations::axes::find(name)
            .is_some_and(|r| r.kind == crate::declarations::axes::AxisKind::Colour);
        let numeric = values.iter().all(|v| v.parse::<f64>().is_ok()) && !colour;
        if numeric {
            values.sort_by(|a, b| a.parse::<f64>().unwrap().total_cmp(&b.parse::<f64>().unwrap()));
        }
        let kind = match (PICKED.contains(&name), numeric) {
            (true, _) => "choice",
            (false, true) => "number",
            (false, false) => "ordered",
        };
        axes.push(ViewerAxis { name: name.into(), kind, values });
    }
    let index_of: Vec<BTreeMap<&str, u32>> =
        axes.iter().map(|a| a.values.iter().enumerate().map(|(i, v)| (v.as_str(), i as u32)).collect()).collect();
    let position: BTreeMap<&str, i64> =
        run.cells.iter().enumerate().map(|(i, c)| (c.id.0.as_str(), i as i64)).collect();
    let mut plans: Vec<Vec<String>> = Vec::new();
    let mut pass_kinds: Vec<String> = Vec::new();
    let mut cells = Vec::with_capacity(run.cells.len());
    for c in &run.cells {
        let values = names.iter().enumerate().map(|(k, a)| index_of[k][value(c, a).as_str()]).collect();
        let twin = c.twin_of.as_ref().and_then(|t| position.get(t.0.as_str()).copied()).unwrap_or(-1);
        let reference = c.metrics.reference.value();
        let (reference_cell, reference_label) = match reference {
            Some(crate::record::cell::ReferenceRecord::Cell { cell }) => {
                (position.get(cell.0.as_str()).copied().unwrap_or(-1), None)
            }
            Some(other) => (-1, Some(other.label())),
            None => (-1, None),
        };
        let plan = intern(&mut plans, &c.passes);
        let maps = c.metrics.maps.is_some() as u32;
        let pixels = (run.cell_dir(&c.id.0).join(crate::images::pixels::PIXELS_FILE).is_file() as u32) << 1;
        let layers = (c.terms.as_ref().is_some_and(|t| !t.layers.is_empty()) as u32) << 2;
        let own = |name: &str| run.cell_dir(&c.id.0).join(name).is_file() as u32;
        let own_reference = own(crate::record::REFERENCE_PNG) << 3 | own(crate::record::TRUTH_NOISE_PNG) << 4;
        let round = |v: Option<f64>| v.map(|x| (x * 1e6).round() / 1e6);
        let passes = c
            .timing
            .gpu_passes
            .value()
            .map(|ps| {
                ps.iter().filter_map(|p| round(p.median_ms).map(|ms| (intern(&mut pass_kinds, &p.kind), ms))).collect()
            })
            .unwrap_or_default();
        let timed_as = c.timing.timed_as.as_ref().and_then(|t| position.get(t.0.as_str()).copied()).unwrap_or(-1);
        let timing = ViewerTiming(round(c.timing.cpu_wall.median_ms), timed_as, passes);
        cells.push(ViewerCell(
            c.id.0.clone(),
            values,
            twin,
            reference_cell,
            [round(c.metrics.ldr_flip()), round(c.metrics.ldr_ssim()), round(c.metrics.hdr_flip())],
            round(c.gpu_median_ms()),
            plan,
            maps | pixels | layers | own_reference,
            [c.image.width, c.image.height],
            reference_label,
            timing,
        ));
    }
    let counts = &run.run.counts;
    ViewerData {
        schema: VIEWER_SCHEMA,
        run: ViewerRun {
            name: run.run.matrix.name.clone(),
            adapter: run.adapter(),
            matrix: run.run.matrix.origin.clone(),
            status: run.run.status.in_reports().name().to_string(),
            cells: counts.cells,
            rendered: counts.rendered,
            twins: counts.twins,
            pruned: counts.pruned,
        },
        axes,
        cells,
        plans,
        pass_kinds,
        pruned: run.run.pruned.clone(),
        links,
        flip: ViewerFlip::new(),
        terms: {
            let mut terms: Vec<String> = Vec::new();
            for l in run.cells.iter().filter_map(|c| c.terms.as_ref()).flat_map(|t| &t.layers) {
                if !terms.contains(&l.name) {
                    terms.push(l.name.clone());
                }
            }
            terms
        },
    }
}

/// The data as the script the page loads. `</` is escaped so no value can close the script.
pub fn data_script(data: &ViewerData) -> Result<String, Error> {
    let json = serde_json::to_string(data).map_err(|e| Error::encode("writing the viewer's data", e))?;
    Ok(format!("window.SHADEMATRIX_VIEWER = {};\n", json.replace("</", "<\\/")))
}

/// The viewer page for `run`, named `title`.
pub fn page(title: &str) -> Result<String, Error> {
    let mut env = minijinja::Environment::new();
    env.add_template("viewer.html", include_str!("templates/viewer.html"))
        .map_err(|e| Error::encode("loading the viewer template", e))?;
    let template = env.get_template("viewer.html").map_err(|e| Error::encode("loading the viewer template", e))?;
    template
        .render(minijinja::context! { title => title, data_file => DATA_FILE, script => include_str!("templates/viewer.js") })
        .map_err(|e| Error::encode("rendering the viewer", e))
}

/// Write `index.html` (the viewer) and its data into the run folder.
pub fn write(run: &RunData, links: Vec<(String, String)>) -> Result<(), Error> {
    let data = data(run, links);
    write_atomic(&run.dir.join(DATA_FILE), data_script(&data)?.as_bytes())?;
    write_atomic(&run.dir.join("index.html"), page(&run.run.matrix.name)?.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_escapes_its_title_and_the_data_cannot_close_its_script() {
        let html = page("<b>&").unwrap();
        assert!(html.contains("&lt;b&gt;&amp;") && !html.contains("<b>&"), "{html}");
        assert!(html.contains(DATA_FILE));
        let data = ViewerData {
            schema: VIEWER_SCHEMA,
            run: ViewerRun {
                name: "</script><script>alert(1)</script>".into(),
                adapter: String::new(),
                matrix: String::new(),
                status: String::new(),
                cells: 0,
                rendered: 0,
                twins: 0,
                pruned: 0,
            },
            axes: Vec::new(),
            cells: Vec::new(),
            plans: Vec::new(),
            pass_kinds: Vec::new(),
            pruned: Vec::new(),
            links: Vec::new(),
            flip: ViewerFlip::new(),
            terms: Vec::new(),
        };
        assert!(!data_script(&data).unwrap().contains("</script>"));
    }
}
