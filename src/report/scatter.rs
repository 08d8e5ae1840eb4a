//! The error-against-time scatter a person reads at a glance: a logarithmic error axis (with each
//! point's noise bar), a colour per pipeline and a marker per shader with their legend, the Pareto
//! front drawn as a line, and every point named on hover. Written as SVG by hand: plotters' SVG
//! backend writes no per-element `<title>`, so a hovered point could not say which cell it is.

use std::fmt::Write;

use super::plot_style::PALETTE;

/// One point of the scatter.
#[derive(Debug, Clone)]
pub struct ScatterPoint {
    pub x: f64,
    pub y: f64,
    /// ± this on the error axis (a truth's noise), where known.
    pub bar: Option<f64>,
    /// Its colour's legend entry (the pipeline) and its marker's (the shader).
    pub colour_key: String,
    pub marker_key: String,
    /// What hovering it says (the cell's id and values).
    pub title: String,
    pub front: bool,
}

/// Axis labels and the caption.
pub struct ScatterText<'a> {
    pub caption: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    /// The legend's headings over the colours and the markers.
    pub colour_heading: &'a str,
    pub marker_heading: &'a str,
    /// Horizontal lines at these errors, each labelled (error budgets).
    pub levels: &'a [(f64, String)],
}

const WIDTH: f64 = 780.0;
const HEIGHT: f64 = 480.0;
/// The plot area: left, top, right, bottom edges (the legend is right of it).
const AREA: (f64, f64, f64, f64) = (78.0, 40.0, 590.0, 420.0);
const SHAPES: [Shape; 7] =
    [Shape::Circle, Shape::Square, Shape::Triangle, Shape::Diamond, Shape::Cross, Shape::Plus, Shape::Down];

#[derive(Debug, Clone, Copy)]
enum Shape {
    Circle,
    Square,
    Triangle,
    Diamond,
    Cross,
    Plus,
    Down,
}

impl Shape {
    /// The marker at (x, y), `r` its half size; `fill` its colour, hollow where `hollow`.
    fn svg(self, (x, y): (f64, f64), r: f64, colour: &str, hollow: bool) -> String {
        let paint = if hollow {
            format!("fill=\"white\" stroke=\"{colour}\" stroke-width=\"1.5\"")
        } else {
            format!("fill=\"{colour}\" stroke=\"#222\" stroke-width=\"0.6\"")
        };
        let line = format!("stroke=\"{colour}\" stroke-width=\"2.2\" fill=\"none\"");
        let poly = |pts: &[(f64, f64)]| {
            let p: Vec<String> = pts.iter().map(|(a, b)| format!("{:.1},{:.1}", x + a * r, y + b * r)).collect();
            format!("<polygon points=\"{}\" {paint}/>", p.join(" "))
        };
        match self {
            Shape::Circle => format!("<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"{r:.1}\" {paint}/>"),
            Shape::Square => poly(&[(-0.9, -0.9), (0.9, -0.9), (0.9, 0.9), (-0.9, 0.9)]),
            Shape::Triangle => poly(&[(0.0, -1.15), (1.05, 0.8), (-1.05, 0.8)]),
            Shape::Down => poly(&[(0.0, 1.15), (1.05, -0.8), (-1.05, -0.8)]),
            Shape::Diamond => poly(&[(0.0, -1.2), (1.2, 0.0), (0.0, 1.2), (-1.2, 0.0)]),
            Shape::Cross => format!(
                "<path d=\"M{:.1},{:.1}L{:.1},{:.1}M{:.1},{:.1}L{:.1},{:.1}\" {line}/>",
                x - r,
                y - r,
                x + r,
                y + r,
                x - r,
                y + r,
                x + r,
                y - r
            ),
            Shape::Plus => format!(
                "<path d=\"M{:.1},{y:.1}L{:.1},{y:.1}M{x:.1},{:.1}L{x:.1},{:.1}\" {line}/>",
                x - r * 1.2,
                x + r * 1.2,
                y - r * 1.2,
                y + r * 1.2
            ),
        }
    }
}

/// A legend row's glyph, drawn at the row's height.
type Glyph = Box<dyn Fn(f64) -> String>;

/// `s` safe in SVG text and attributes.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn hex(c: plotters::style::RGBColor) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// The colour of a pipeline: built-in, URP and HDRP keep theirs in every plot.
pub fn colour_of(key: &str, keys: &[String]) -> String {
    let fixed = match key {
        "builtin" => Some(0),
        "urp" => Some(1),
        "hdrp" => Some(2),
        _ => None,
    };
    let i = fixed.unwrap_or_else(|| 3 + keys.iter().position(|k| k == key).unwrap_or(0) % (PALETTE.len() - 3));
    hex(PALETTE[i])
}

/// A linear axis's ticks: about `n` round steps from 0 to `max`.
fn linear_ticks(max: f64, n: usize) -> (f64, Vec<f64>) {
    let raw = max / n as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0].iter().map(|m| m * mag).find(|s| *s >= raw).unwrap_or(10.0 * mag);
    let top = (max / step).ceil() * step;
    let ticks = (0..=((top / step).round() as usize)).map(|k| k as f64 * step).collect();
    (top, ticks)
}

fn number(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&v.abs()) {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// The scatter as an SVG document. The error axis is logarithmic over whole decades; an error of
/// 0 (a cell that is its own reference) is drawn hollow on the axis floor, and its title says so.
pub fn svg(text: &ScatterText, points: &[ScatterPoint]) -> String {
    let (left, top, right, bottom) = AREA;
    let positive: Vec<f64> = points.iter().map(|p| p.y).filter(|y| *y > 0.0 && y.is_finite()).collect();
    let lowest = points
        .iter()
        .filter_map(|p| Some(p.y - p.bar?))
        .filter(|v| *v > 0.0)
        .chain(positive.iter().copied())
        .chain(text.levels.iter().map(|l| l.0))
        .fold(f64::INFINITY, f64::min);
    let highest =
        points.iter().map(|p| p.y + p.bar.unwrap_or(0.0)).chain(text.levels.iter().map(|l| l.0)).fold(0.0f64, f64::max);
    let (d_lo, d_hi) = match lowest.is_finite() && highest > 0.0 {
        true => (lowest.log10().floor(), highest.log10().ceil().max(lowest.log10().floor() + 1.0)),
        false => (-3.0, 0.0),
    };
    let floor = 10f64.powf(d_lo);
    let (x_top, x_ticks) = linear_ticks(points.iter().map(|p| p.x).fold(0.0f64, f64::max).max(1e-3) * 1.05, 6);
    let px = |x: f64| left + x / x_top * (right - left);
    let py = |y: f64| bottom - (y.max(floor).log10() - d_lo) / (d_hi - d_lo) * (bottom - top);
    let mut colours: Vec<String> = points.iter().map(|p| p.colour_key.clone()).collect();
    colours.sort();
    colours.dedup();
    let mut markers: Vec<String> = points.iter().map(|p| p.marker_key.clone()).collect();
    markers.sort();
    markers.dedup();
    let shape = |key: &str| SHAPES[markers.iter().position(|m| m == key).unwrap_or(0) % SHAPES.len()];
    let mut s = String::new();
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{HEIGHT}\" viewBox=\"0 0 {WIDTH} {HEIGHT}\" \
         font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{:.0}\" y=\"24\" font-size=\"15\" text-anchor=\"middle\">{}</text>\n",
        (left + right) / 2.0,
        escape(text.caption)
    );
    // Grid and ticks: each decade and its 2 and 5 on the error axis.
    for d in (d_lo as i64)..=(d_hi as i64) {
        for (m, major) in [(1.0, true), (2.0, false), (5.0, false)] {
            let v = m * 10f64.powi(d as i32);
            if v > 10f64.powf(d_hi) * 1.0001 {
                continue;
            }
            let y = py(v);
            let stroke = if major { "#cccccc" } else { "#eeeeee" };
            let _ = writeln!(s, "<line x1=\"{left}\" x2=\"{right}\" y1=\"{y:.1}\" y2=\"{y:.1}\" stroke=\"{stroke}\"/>");
            if major {
                let _ = writeln!(
                    s,
                    "<text x=\"{:.0}\" y=\"{:.1}\" font-size=\"11\" text-anchor=\"end\">{}</text>",
                    left - 6.0,
                    y + 4.0,
                    number(v)
                );
            }
        }
    }
    for &x in &x_ticks {
        let xp = px(x);
        let _ = writeln!(s, "<line x1=\"{xp:.1}\" x2=\"{xp:.1}\" y1=\"{top}\" y2=\"{bottom}\" stroke=\"#eeeeee\"/>");
        let _ = writeln!(
            s,
            "<text x=\"{xp:.1}\" y=\"{:.0}\" font-size=\"11\" text-anchor=\"middle\">{}</text>",
            bottom + 16.0,
            number(x)
        );
    }
    let _ = writeln!(
        s,
        "<rect x=\"{left}\" y=\"{top}\" width=\"{:.0}\" height=\"{:.0}\" fill=\"none\" stroke=\"#555\"/>\n\
         <text x=\"{:.0}\" y=\"{:.0}\" font-size=\"12\" text-anchor=\"middle\">{}</text>\n\
         <text transform=\"translate(18,{:.0}) rotate(-90)\" font-size=\"12\" text-anchor=\"middle\">{} (log scale)</text>",
        right - left,
        bottom - top,
        (left + right) / 2.0,
        bottom + 40.0,
        escape(text.x_label),
        (top + bottom) / 2.0,
        escape(text.y_label)
    );
    for (level, label) in text.levels {
        let y = py(*level);
        let _ = writeln!(
            s,
            "<line x1=\"{left}\" x2=\"{right}\" y1=\"{y:.1}\" y2=\"{y:.1}\" stroke=\"#b03030\" stroke-width=\"1\" stroke-dasharray=\"2 3\"/>\
             <text x=\"{:.0}\" y=\"{:.1}\" font-size=\"10\" fill=\"#b03030\" text-anchor=\"end\">{}</text>",
            right - 4.0,
            y - 3.0,
            escape(label)
        );
    }
    // The Pareto front, fastest first.
    let mut front: Vec<&ScatterPoint> = points.iter().filter(|p| p.front).collect();
    front.sort_by(|a, b| a.x.total_cmp(&b.x));
    if front.len() > 1 {
        let path: Vec<String> = front.iter().map(|p| format!("{:.1},{:.1}", px(p.x), py(p.y))).collect();
        let _ = writeln!(
            s,
            "<polyline points=\"{}\" fill=\"none\" stroke=\"#333\" stroke-width=\"1.5\" stroke-dasharray=\"6 4\"/>",
            path.join(" ")
        );
    }
    for p in points {
        let colour = colour_of(&p.colour_key, &colours);
        let (x, y) = (px(p.x), py(p.y));
        let at_floor = p.y <= 0.0;
        let mut title = p.title.clone();
        if at_floor {
            title.push_str(" (error 0: drawn on the axis floor)");
        }
        let _ = write!(s, "<g><title>{}</title>", escape(&title));
        if let Some(bar) = p.bar.filter(|b| *b > 0.0 && !at_floor) {
            let _ = write!(
                s,
                "<line x1=\"{x:.1}\" x2=\"{x:.1}\" y1=\"{:.1}\" y2=\"{:.1}\" stroke=\"{colour}\" stroke-width=\"1.2\"/>",
                py((p.y - bar).max(floor)),
                py(p.y + bar)
            );
        }
        let r = if p.front { 6.0 } else { 4.5 };
        s.push_str(&shape(&p.marker_key).svg((x, y), r, &colour, at_floor));
        if p.front {
            let _ = write!(
                s,
                "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"9\" fill=\"none\" stroke=\"#333\" stroke-width=\"1\"/>"
            );
        }
        s.push_str("</g>\n");
    }
    // The legend: pipelines by colour, shaders by marker, the front; a row is (glyph, label, heading).
    let lx = right + 18.0;
    let mut rows: Vec<(Glyph, String, bool)> = Vec::new();
    rows.push((Box::new(|_| String::new()), text.colour_heading.into(), true));
    for c in &colours {
        let colour = colour_of(c, &colours);
        let glyph = move |y: f64| {
            format!("<rect x=\"{lx}\" y=\"{:.1}\" width=\"10\" height=\"10\" fill=\"{colour}\"/>", y - 5.0)
        };
        rows.push((Box::new(glyph), c.clone(), false));
    }
    rows.push((Box::new(|_| String::new()), text.marker_heading.into(), true));
    for m in markers.iter().take(12) {
        let marker = shape(m);
        rows.push((Box::new(move |y| marker.svg((lx + 5.0, y), 4.5, "#666666", false)), m.clone(), false));
    }
    if markers.len() > 12 {
        rows.push((Box::new(|_| String::new()), format!("… {} more (hover a point)", markers.len() - 12), false));
    }
    let dash = move |y: f64| {
        format!(
            "<line x1=\"{lx}\" x2=\"{:.0}\" y1=\"{y:.1}\" y2=\"{y:.1}\" stroke=\"#333\" stroke-width=\"1.5\" stroke-dasharray=\"6 4\"/>",
            lx + 12.0
        )
    };
    rows.push((Box::new(dash), "Pareto front (ringed)".into(), false));
    let mut ly = top + 8.0;
    for (glyph, label, heading) in &rows {
        if *heading && ly > top + 8.0 {
            ly += 6.0;
        }
        let (x, weight) = if *heading { (lx, " font-weight=\"bold\"") } else { (lx + 16.0, "") };
        let _ = writeln!(
            s,
            "{}<text x=\"{x:.0}\" y=\"{:.1}\" font-size=\"11\"{weight}>{}</text>",
            glyph(ly),
            ly + 4.0,
            escape(label)
        );
        ly += 17.0;
    }
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: f64, y: f64, pipeline: &str, shader: &str, front: bool) -> ScatterPoint {
        ScatterPoint {
            x,
            y,
            bar: Some(y / 10.0),
            colour_key: pipeline.into(),
            marker_key: shader.into(),
            title: format!("{pipeline}/{shader} <{x}>"),
            front,
        }
    }

    #[test]
    fn an_outlier_leaves_the_others_decades_apart_and_every_point_is_named() {
        let pts = vec![
            point(1.0, 0.01, "urp", "lit", true),
            point(2.0, 0.002, "hdrp", "lit", true),
            point(1.5, 32.5, "builtin", "standard", false),
            point(3.0, 0.0, "urp", "lambert", false),
        ];
        let text = ScatterText {
            caption: "c",
            x_label: "ms",
            y_label: "relMSE",
            colour_heading: "pipeline",
            marker_heading: "shader",
            levels: &[(0.05, "budget".into())],
        };
        let svg = svg(&text, &pts);
        assert_eq!(svg.matches("<title>").count(), 4);
        assert!(svg.contains("urp/lit &lt;1&gt;") && svg.contains("drawn on the axis floor"), "{svg}");
        assert!(svg.contains(">budget</text>"), "the budget's line is labelled");
        // Log axis: 0.002 and 0.01 are most of a decade apart, not squeezed on the floor by 32.5.
        let y = |v: f64| {
            let (lo, hi) = ((0.002f64).log10().floor(), (32.5f64 * 1.1).log10().ceil());
            AREA.3 - (v.log10() - lo) / (hi - lo) * (AREA.3 - AREA.1)
        };
        assert!(y(0.002) - y(0.01) > 40.0, "{} px", y(0.002) - y(0.01));
        // Each pipeline its colour, each shader its marker, the front a line, in the legend.
        for label in ["builtin", "urp", "hdrp", "lit", "lambert", "standard", "Pareto front"] {
            assert!(svg.contains(&format!(">{label}")), "{label}");
        }
        assert!(svg.contains("<polyline") && svg.contains(&colour_of("hdrp", &[])));
    }
}
