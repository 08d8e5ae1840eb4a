//! The offline HTML gallery, `gallery.html` in the run folder (`index.html` is the viewer,
//! report::viewer): works from the file system (no
//! server, no network), filters by axis, shows each cell's images, metrics and timings, the perf
//! table (sortable), the error-vs-time plots and the contact sheets. Every name that comes from
//! input is HTML-escaped. The page checks itself after loading: broken images and script errors
//! are counted into `data-broken-images` and `data-errors` on <body> (read by the Chromium test).

use std::collections::BTreeSet;
use std::fmt::Write;

use super::perf;
use super::run_data::RunData;
use crate::error::Error;
use crate::fsutil::write_atomic;

pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;").replace('\'', "&#39;")
}

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

const FILTER_AXES: [&str; 6] = ["composition", "pipeline", "shader", "preset", "smoothness", "color"];

const STYLE: &str = r#"
body { font-family: system-ui, sans-serif; margin: 1.5em; background: #16161a; color: #e8e8ea; }
a { color: #8ab4f8; } h2 { margin-top: 1.6em; border-bottom: 1px solid #333; }
.filters label { margin-right: 1em; } select { background: #222; color: #eee; }
.cells { display: flex; flex-wrap: wrap; gap: 10px; }
.cell { background: #222228; padding: 6px; border-radius: 4px; width: 420px; font-size: 12px; }
.cell img { width: 128px; height: 128px; object-fit: contain; image-rendering: pixelated; background: #000; }
.cell .id { font-family: monospace; word-break: break-all; }
table { border-collapse: collapse; font-size: 12px; } td, th { border: 1px solid #333; padding: 2px 6px; }
th { cursor: pointer; background: #26262c; } .sheets img { max-width: 100%; }
.missing { color: #999; } .status { font-size: 12px; color: #9c9; }
"#;

const SCRIPT: &str = r#"
(function () {
  var errors = 0;
  window.addEventListener('error', function () { errors++; }, true);
  var origError = console.error;
  console.error = function () { errors++; origError.apply(console, arguments); };
  function applyFilters() {
    var sel = {};
    document.querySelectorAll('select[data-axis]').forEach(function (s) { sel[s.dataset.axis] = s.value; });
    document.querySelectorAll('.cell').forEach(function (c) {
      var show = Object.keys(sel).every(function (a) { return !sel[a] || c.dataset[a] === sel[a]; });
      c.style.display = show ? '' : 'none';
    });
  }
  document.querySelectorAll('select[data-axis]').forEach(function (s) { s.addEventListener('change', applyFilters); });
  document.querySelectorAll('table.sortable th').forEach(function (th, col) {
    th.addEventListener('click', function () {
      var body = th.closest('table').tBodies[0];
      var rows = Array.prototype.slice.call(body.rows);
      var dir = th.dataset.dir === 'asc' ? -1 : 1; th.dataset.dir = dir === 1 ? 'asc' : 'desc';
      rows.sort(function (a, b) {
        var x = a.cells[col].textContent, y = b.cells[col].textContent;
        var nx = parseFloat(x), ny = parseFloat(y);
        return (isNaN(nx) || isNaN(ny) ? x.localeCompare(y) : nx - ny) * dir;
      });
      rows.forEach(function (r) { body.appendChild(r); });
    });
  });
  window.addEventListener('load', function () {
    var imgs = document.querySelectorAll('img'), broken = 0;
    imgs.forEach(function (i) { if (!i.complete || i.naturalWidth === 0) broken++; });
    document.body.dataset.images = imgs.length;
    document.body.dataset.brokenImages = broken;
    document.body.dataset.errors = errors;
    document.getElementById('status').textContent = imgs.length + ' images, ' + broken + ' broken, ' + errors + ' script errors';
  });
})();
"#;

fn num(v: Option<f64>, digits: usize) -> String {
    v.map(|x| format!("{x:.digits$}")).unwrap_or_else(|| "—".into())
}

pub fn html(run: &RunData, sheets: &[String], plots: &[String]) -> String {
    let m = &run.run.matrix;
    let counts = &run.run.counts;
    let mut s = String::new();
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>shadematrix: {}</title><style>{STYLE}</style></head>\n<body data-errors=\"-1\" data-broken-images=\"-1\">\n",
        esc(&m.name)
    );
    let _ = writeln!(
        s,
        "<h1>{}</h1><p>Matrix <code>{}</code> (sha256 {}…), adapter <b>{}</b>. {} cells: {} rendered, {} twins, {} resumed; {} pruned. Status: {}.</p><p id=\"status\" class=\"status\">checking…</p>",
        esc(&m.name),
        esc(&m.origin),
        esc(&m.sha256.chars().take(12).collect::<String>()),
        esc(&run.adapter()),
        counts.cells,
        counts.rendered,
        counts.twins,
        counts.resumed,
        counts.pruned,
        run.run.status.name()
    );
    let _ = writeln!(s, "<p><a href=\"index.html\">viewer</a> · <a href=\"#cells\">cells</a> · <a href=\"#perf\">performance</a> · <a href=\"#plots\">error vs time</a> · <a href=\"#sheets\">contact sheets</a> · <a href=\"tables/perf.md\">perf.md</a> · <a href=\"tables/error_vs_time.md\">error_vs_time.md</a>{}</p>", if run.dir.join("tables/approximations.md").is_file() { " · <a href=\"tables/approximations.md\">approximations.md</a> (what each approximation costs and buys)" } else { "" });

    s.push_str("<h2 id=\"cells\">Cells</h2><div class=\"filters\">");
    for axis in FILTER_AXES {
        let values: BTreeSet<String> = run.cells.iter().map(|c| c.axis_value(axis)).collect();
        let _ = write!(s, "<label>{axis} <select data-axis=\"{axis}\"><option value=\"\">all</option>");
        for v in values {
            let _ = write!(s, "<option value=\"{0}\">{0}</option>", esc(&v));
        }
        s.push_str("</select></label>");
    }
    s.push_str("</div><div class=\"cells\">\n");
    // Big runs load images as they scroll into view; small ones at once, so the page's own check
    // (data-broken-images) sees every image.
    let lazy = if run.cells.len() > LAZY_FROM { " loading=\"lazy\"" } else { "" };
    for c in &run.cells {
        let id = &c.id.0;
        let dir = format!("cells/{}", url(id));
        let data: String = FILTER_AXES.iter().map(|a| format!(" data-{a}=\"{}\"", esc(&c.axis_value(a)))).collect();
        let _ = write!(s, "<div class=\"cell\"{data}><div class=\"id\">{}</div>", esc(id));
        let _ = write!(
            s,
            "<a href=\"{dir}/image.exr\" title=\"linear EXR\"><img{lazy} src=\"{dir}/image.png\" alt=\"{}\"></a>",
            esc(id)
        );
        let metrics = &c.metrics;
        if metrics.ldr.is_some() {
            if metrics.maps.is_some() {
                let _ = write!(s, "<img{lazy} src=\"{dir}/flip.png\" alt=\"FLIP map\" title=\"FLIP\"><img{lazy} src=\"{dir}/ssim.png\" alt=\"1 − SSIM\" title=\"1 − SSIM\">");
            }
            let _ = write!(
                s,
                "<div>against <code>{}</code>: FLIP {} · SSIM {} · HDR-FLIP {}</div>",
                esc(&metrics.reference.value().map(|r| r.label()).unwrap_or_default()),
                num(metrics.ldr_flip(), 4),
                num(metrics.ldr_ssim(), 4),
                num(metrics.hdr_flip(), 4)
            );
        } else {
            let _ = write!(
                s,
                "<div class=\"missing\">no metrics: {}</div>",
                esc(metrics.reference.why_missing().unwrap_or("not computed"))
            );
        }
        let origin = match &c.twin_of {
            None => "rendered".to_string(),
            Some(t) => format!("twin of {}", esc(&t.0)),
        };
        let _ = writeln!(
            s,
            "<div>GPU {} ms · CPU wall {} ms · {origin} · <a href=\"{dir}/cell.json\">cell.json</a></div></div>",
            num(c.gpu_median_ms(), 3),
            num(c.timing.cpu_wall.median_ms, 3),
        );
    }
    s.push_str("</div>\n<h2 id=\"perf\">Performance</h2><p>Click a column to sort.</p><table class=\"sortable\"><thead><tr><th>cell</th><th>pipeline</th><th>shader</th><th>GPU median ms</th><th>GPU min</th><th>GPU max</th><th>CPU wall ms</th><th>readback ms</th><th>encode ms</th></tr></thead><tbody>\n");
    for r in perf::rows(run) {
        let o = |v: Option<f64>| v.map(|x| format!("{x:.3}")).unwrap_or_else(|| "—".into());
        let _ = writeln!(
            s,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&r.id),
            esc(&r.pipeline),
            esc(&r.shader),
            o(r.gpu_median_ms),
            o(r.gpu_min_ms),
            o(r.gpu_max_ms),
            o(r.cpu_wall_median_ms),
            o(r.readback_ms),
            o(r.encode_ms)
        );
    }
    s.push_str("</tbody></table>\n<h2 id=\"plots\">Error against run time</h2>\n");
    if plots.is_empty() {
        s.push_str("<p class=\"missing\">No plots: no cell has a reference (the matrix names none).</p>\n");
    }
    for p in plots {
        let _ = writeln!(s, "<p><img src=\"{}\" alt=\"{}\"></p>", url(p), esc(p));
    }
    s.push_str("<h2 id=\"sheets\">Contact sheets</h2><div class=\"sheets\">\n");
    for sheet in sheets {
        let _ = writeln!(s, "<p><a href=\"{0}\">{1}</a><br><img src=\"{0}\" alt=\"{1}\"></p>", url(sheet), esc(sheet));
    }
    let _ = write!(s, "</div>\n<script>{SCRIPT}</script>\n</body></html>\n");
    s
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
    write_atomic(&run.dir.join(FILE), html(run, sheets, &plots).as_bytes())?;
    Ok(plots)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping() {
        assert_eq!(esc("<b>\"x\" & 'y'</b>"), "&lt;b&gt;&quot;x&quot; &amp; &#39;y&#39;&lt;/b&gt;");
        assert_eq!(url("cells/a b"), "cells/a%20b");
    }
}
