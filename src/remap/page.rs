//! `index.html`, a match's page: pick a material and a composition to see the source's frame
//! beside the target's with the values copied and fitted (or flicker between source and fitted),
//! the per-preset means, the smoothness curves and the sheets. A minijinja template
//! (`templates/match.html`): every value is escaped by it; the rows' data is JSON with `</` escaped.

use serde::Serialize;

use super::table::MatchRecord;
use crate::error::Error;
use crate::report::sheets::file_safe;

#[derive(Serialize)]
struct PageRow {
    label: String,
    frames: String,
    copied: String,
    fitted: String,
    values: String,
}

#[derive(Serialize)]
struct PagePreset {
    preset: String,
    rows: usize,
    copied: String,
    fitted: String,
    class: &'static str,
}

#[derive(Serialize)]
struct PageComposition {
    name: String,
    file: String,
}

/// The page of `record`, whose plot is `plot` and sheets `sheets` (paths relative to the page).
pub fn html(record: &MatchRecord, plot: &str, sheets: &[String]) -> Result<String, Error> {
    let rows: Vec<PageRow> = record
        .rows
        .iter()
        .map(|r| {
            let f = &r.fitted;
            let mut values = format!(
                "smoothness {:.3}, metallic {:.3}, colour {:.3} {:.3} {:.3}",
                f.smoothness, f.metallic, f.color[0], f.color[1], f.color[2]
            );
            for (k, v) in &f.params {
                values += &format!(", {k} {v:.3}");
            }
            PageRow {
                label: format!("{} {}", r.preset, super::sheet::material_label(r)),
                frames: r.frames.clone(),
                copied: format!("{:.4}", r.copied_error.flip),
                fitted: format!("{:.4}", r.fitted_error.flip),
                values,
            }
        })
        .collect();
    let presets: Vec<PagePreset> = record
        .summary()
        .into_iter()
        .map(|p| PagePreset {
            class: if p.fitted_flip < p.copied_flip { "better" } else { "worse" },
            copied: format!("{:.4}", p.copied_flip),
            fitted: format!("{:.4}", p.fitted_flip),
            preset: p.preset,
            rows: p.rows,
        })
        .collect();
    let rows_json = serde_json::to_string(&rows)
        .map_err(|e| Error::encode("writing the match page's rows", e))?
        .replace("</", "<\\/");
    let mut env = minijinja::Environment::new();
    env.add_template("match.html", include_str!("templates/match.html"))
        .map_err(|e| Error::encode("loading the match page's template", e))?;
    let template = env.get_template("match.html").map_err(|e| Error::encode("loading the match page's template", e))?;
    template
        .render(minijinja::context! {
            from => record.from,
            to => record.to,
            space => record.space.name(),
            compositions => record.compositions.join(", "),
            composition_list => record.compositions.iter().map(|c| PageComposition { name: c.clone(), file: file_safe(c) }).collect::<Vec<_>>(),
            size => record.size,
            kept => record.kept.join(", "),
            adapter => record.adapter,
            exposure => (record.space == super::MatchSpace::Linear).then(|| format!("{:.4e}", record.exposure)),
            rows => rows,
            rows_json => minijinja::Value::from_safe_string(rows_json),
            presets => presets,
            plot => plot,
            sheets => sheets,
        })
        .map_err(|e| Error::encode("rendering the match page", e))
}
