//! `plots/smoothness.svg`: the remap's curve, source smoothness → fitted target smoothness, one
//! line per preset, over the diagonal a copy of the values would follow.

use plotters::prelude::*;

use super::table::{MatchRecord, MatchRow};
use crate::report::plot_style::{failed, PALETTE};

/// One preset's curve: (source smoothness, fitted smoothness) sorted by the source's. Rows of a
/// preset that differ in anything but smoothness (metallic, colour, a parameter) make their own
/// curves, named by what differs.
fn curves(record: &MatchRecord) -> Vec<(String, Vec<(f64, f64)>)> {
    let mut out: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for r in &record.rows {
        let name = curve_name(r, &record.rows);
        let point = (r.source.smoothness, r.fitted.smoothness);
        match out.iter_mut().find(|(n, _)| *n == name) {
            Some((_, points)) => points.push(point),
            None => out.push((name, vec![point])),
        }
    }
    for (_, points) in &mut out {
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    out
}

/// The preset, with the source values that vary among its rows besides smoothness.
fn curve_name(r: &MatchRow, rows: &[MatchRow]) -> String {
    let same = |o: &&MatchRow| o.preset == r.preset;
    let varies = |f: &dyn Fn(&MatchRow) -> String| rows.iter().filter(same).any(|o| f(o) != f(r));
    let mut name = r.preset.clone();
    if varies(&|o| format!("{:.3}", o.source.metallic)) {
        name += &format!(" m {:.2}", r.source.metallic);
    }
    if varies(&|o| format!("{:.4?}", o.source.color)) {
        name += &format!(" c {:.2?}", r.source.color);
    }
    for (k, v) in &r.source.params {
        if varies(&|o| format!("{:?}", o.source.params.get(k))) {
            name += &format!(" {k} {v:.2}");
        }
    }
    name
}

/// The plot as SVG text.
pub fn svg(record: &MatchRecord) -> Result<String, crate::error::Error> {
    let title = format!("fitted smoothness, {} → {} ({} image)", record.from, record.to, record.space.name());
    let fail = |e: &dyn std::fmt::Display| failed("the smoothness curves", e);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (900, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        // The legend beside the chart: the curves span the whole square.
        let (plot_area, legend_area) = root.split_horizontally(700);
        let mut chart = ChartBuilder::on(&plot_area)
            .caption(&title, ("sans-serif", 15))
            .margin(14)
            .x_label_area_size(42)
            .y_label_area_size(56)
            .build_cartesian_2d(-0.02f64..1.02, -0.02f64..1.02)
            .map_err(|e| fail(&e))?;
        chart
            .configure_mesh()
            .x_desc(format!("source smoothness ({})", record.from))
            .y_desc(format!("fitted smoothness ({})", record.to))
            .light_line_style(WHITE)
            .draw()
            .map_err(|e| fail(&e))?;
        let grey = RGBColor(0x99, 0x99, 0x99);
        chart.draw_series(LineSeries::new([(0.0, 0.0), (1.0, 1.0)], grey.stroke_width(1))).map_err(|e| fail(&e))?;
        let key = |row: i32, colour: RGBColor, width: u32, name: &str, triangles: Option<bool>| {
            let y = 40 + 18 * row;
            legend_area.draw(&PathElement::new([(4, y), (28, y)], colour.stroke_width(width)))?;
            match triangles {
                Some(true) => legend_area.draw(&TriangleMarker::new((16, y), 5, colour.filled()))?,
                Some(false) => legend_area.draw(&Circle::new((16, y), 3, colour.filled()))?,
                None => {}
            }
            legend_area.draw(&Text::new(name.to_string(), (34, y - 6), ("sans-serif", 11)))
        };
        key(0, grey, 1, "copied (Unity's upgraders)", None).map_err(|e| fail(&e))?;
        for (i, (name, points)) in curves(record).into_iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            // Past the palette's ten colours, triangles tell the curves apart.
            let triangles = i >= PALETTE.len();
            chart.draw_series(LineSeries::new(points.iter().copied(), colour.stroke_width(2))).map_err(|e| fail(&e))?;
            if triangles {
                chart
                    .draw_series(points.iter().map(|p| TriangleMarker::new(*p, 5, colour.filled())))
                    .map_err(|e| fail(&e))?;
            } else {
                chart.draw_series(points.iter().map(|p| Circle::new(*p, 3, colour.filled()))).map_err(|e| fail(&e))?;
            }
            key(i as i32 + 1, colour, 2, &name, Some(triangles)).map_err(|e| fail(&e))?;
        }
        root.present().map_err(|e| fail(&e))?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::remap::{MatchError, MaterialValues};

    fn row(preset: &str, s: f64, fitted: f64, metallic: f64) -> MatchRow {
        let e = MatchError { flip: 0.1, rel_mse: 0.1 };
        MatchRow {
            preset: preset.into(),
            source: MaterialValues::new(s, metallic, [0.5; 3]),
            fitted: MaterialValues::new(fitted, metallic, [0.5; 3]),
            copied_error: e,
            fitted_error: e,
            renders: 1,
            frames: String::new(),
        }
    }

    #[test]
    fn a_preset_makes_one_curve_sorted_by_the_source_and_a_varied_metallic_splits_it() {
        let rows = vec![row("gold", 1.0, 0.9, 1.0), row("gold", 0.0, 0.1, 1.0), row("wood", 0.5, 0.4, 0.0)];
        let record = crate::remap::table::record_of(rows);
        let c = curves(&record);
        assert_eq!(c, vec![("gold".into(), vec![(0.0, 0.1), (1.0, 0.9)]), ("wood".into(), vec![(0.5, 0.4)])]);
        let mut split = record.clone();
        split.rows[1].source.metallic = 0.0;
        let names: Vec<String> = curves(&split).into_iter().map(|(n, _)| n).collect();
        assert_eq!(names, ["gold m 1.00", "gold m 0.00", "wood"]);
        assert!(svg(&record).unwrap().contains("<svg"));
    }
}
