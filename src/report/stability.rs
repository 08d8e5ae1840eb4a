//! tables/stability.{md,csv}: per pipeline × path × shader, each bad-value check (NaN, Inf,
//! negative, above half-float maximum after pre-exposure) passed or failed over the run's cells, the
//! worst values, the first offending cell and pixel, and the guards that keep the built-in shaders
//! clear of each (spec §6), and per shader the guard of its stiff terms. Overflow is counted in what
//! the passes wrote: the half-float store saturates it, so the row says how often that guard acted.
//! A user model's findings show the same way: reported, never a crash.

use std::collections::BTreeMap;
use std::fmt::Write;

use super::run_data::RunData;
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::images::stats::Defect;
use crate::pipelines::{Pipeline, RenderPath};
use crate::shading::registry::Registry;

/// What keeps the built-in shaders and passes clear of each kind (spec §6).
pub fn guard(kind: Defect) -> &'static str {
    match kind {
        Defect::Nan => {
            "shading_normal / vertex_normal (zero normals), safe_normalize(l + v, ε) for H, pow5 for (1 − c)⁵, \
             max(…, REAL_MIN) denominators (HDRP)"
        }
        Defect::Inf => {
            "light_incidence (d ≥ 1e-6), distance_attenuation per pipeline, roughness floors (built-in α ≥ 0.002, \
             URP α ≥ 2⁻⁷, HDRP per-light minRoughness)"
        }
        Defect::Negative => "max(0, N·L) on every light, max(sh_eval, 0), sat() on cosines",
        Defect::Overflow => {
            "images::target::store_half_float: the half-float camera target saturates finite values at 65504 \
             after pre-exposure (URP's min(…, HALF_MAX)); the written images hold none"
        }
    }
}

#[derive(Default)]
struct Group {
    cells: usize,
    counts: BTreeMap<Defect, (usize, usize)>,
    first: BTreeMap<Defect, String>,
    max_value: f64,
    min_value: f64,
}

pub fn write(run: &RunData) -> Result<(), Error> {
    let mut groups: BTreeMap<(Pipeline, RenderPath, String), Group> = BTreeMap::new();
    for c in &run.cells {
        let g = groups.entry((c.pipeline, c.path, c.shader.clone())).or_default();
        g.cells += 1;
        g.max_value = g.max_value.max(c.stats.max_value);
        g.min_value = g.min_value.min(c.stats.min_value);
        for kind in Defect::ALL {
            let n = c.stats.count(kind);
            let e = g.counts.entry(kind).or_default();
            e.0 += n;
            e.1 += (n > 0) as usize;
        }
        for d in &c.stats.first {
            g.first.entry(d.kind).or_insert_with(|| {
                format!("{} ({}, {}) {} = {} ({}, {})", c.id.0, d.x, d.y, d.channel, d.value, d.role, d.pass)
            });
        }
    }
    let mut md = format!(
        "# Numerical stability\n\nRun `{}`, {} cells on {}. Each check counts the values of every cell's HDR image \
         (NaN, ±Inf, negative, and above the half-float maximum 65504 after the pipeline's pre-exposure) as the \
         passes wrote them; `pass` means none in any cell of the row. Overflow passes when the half-float store \
         saturated it: the written images hold no value above 65504. `run --fail-on nan,inf,negative,overflow` turns findings into exit 1.\n\n\
         | pipeline | path | shader | cells | NaN | Inf | negative | overflow | largest value | smallest value | first finding | stiff-term guard |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
        run.run.matrix.name,
        run.cells.len(),
        run.run.adapter.name
    );
    let mut csv = String::from(
        "pipeline,path,shader,cells,nan_values,nan_cells,inf_values,inf_cells,negative_values,negative_cells,overflow_values,overflow_cells,max_value,min_value,guard\n",
    );
    let builtin = Registry::builtin();
    // Rows by name, as the table has always been sorted.
    let mut rows: Vec<_> = groups.iter().collect();
    rows.sort_by(|((a, ap, ash), _), ((b, bp, bsh), _)| (a.name(), ap.name(), ash).cmp(&(b.name(), bp.name(), bsh)));
    for ((p, path, shader), g) in rows {
        let verdict = |k: Defect| match g.counts.get(&k) {
            Some((0, _)) | None => "pass".to_string(),
            Some((n, cells)) if k == Defect::Overflow => format!("pass: {n} saturated in {cells} cells"),
            Some((n, cells)) => format!("**fail** {n} in {cells} cells"),
        };
        let guards = match builtin.find(*p, shader) {
            Some(m) => m.stiff_terms.to_string(),
            None => "a user model: its findings are reported, not guarded".to_string(),
        };
        let (p, path) = (p.name(), path.name());
        let first = g.first.values().next().cloned().unwrap_or_else(|| "—".into());
        let _ = writeln!(
            md,
            "| {p} | {path} | {shader} | {} | {} | {} | {} | {} | {:.4e} | {:.4e} | {first} | {guards} |",
            g.cells,
            verdict(Defect::Nan),
            verdict(Defect::Inf),
            verdict(Defect::Negative),
            verdict(Defect::Overflow),
            g.max_value,
            g.min_value
        );
        let c = |k: Defect| g.counts.get(&k).copied().unwrap_or_default();
        let _ = writeln!(
            csv,
            "{p},{path},{shader},{},{},{},{},{},{},{},{},{},{:e},{:e},\"{}\"",
            g.cells,
            c(Defect::Nan).0,
            c(Defect::Nan).1,
            c(Defect::Inf).0,
            c(Defect::Inf).1,
            c(Defect::Negative).0,
            c(Defect::Negative).1,
            c(Defect::Overflow).0,
            c(Defect::Overflow).1,
            g.max_value,
            g.min_value,
            guards.replace('"', "'")
        );
    }
    md.push_str("\n## Guards\n\n| check | what keeps the built-in shaders clear of it |\n|---|---|\n");
    for k in Defect::ALL {
        let _ = writeln!(md, "| {} | {} |", k.name(), guard(k));
    }
    write_atomic(&run.dir.join("tables/stability.md"), md.as_bytes())?;
    write_atomic(&run.dir.join("tables/stability.csv"), csv.as_bytes())
}
