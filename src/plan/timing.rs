//! Timing classes. A frame's GPU time depends on what is drawn and how — the composition, the
//! pipeline and path, the shader's code, the lights that reach each object, the resolution, the
//! anti-aliasing, the textures and the level of detail — and hardly on the values a slider sets
//! (metallic, smoothness, colour, intensity, a parameter, the light's angle): those are uniforms of
//! the same passes. So a run times one cell per class with the matrix's `[timing]` frames and gives
//! the others of its class that cell's figures, marked in their records (`timing.timed_as`); they
//! render one frame. `[timing] every_cell = true` times every cell.

use crate::cells::Cell;

/// The class of `cell`: equal for cells whose frames run the same passes over the same work. The
/// axes it counts are the table's rows marked `timing` (`declarations::axes`); the light range is one: the
/// pipelines cull a light from objects beyond its range, which changes how many lights each
/// object's pass evaluates. The image size, anti-aliasing and light budgets are the matrix's.
pub fn timing_class(cell: &Cell) -> String {
    let mut class = format!(
        "{}x{}|{:?}|{:?}|{:?}",
        cell.width, cell.height, cell.antialiasing, cell.light_budget, cell.pipeline_settings
    );
    for row in crate::declarations::axes::AXES.iter().filter(|r| r.timing) {
        class.push_str(&format!("|{}={}", row.name, cell.coords.exact(row.name)));
    }
    class
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::declarations::matrix::Matrix;
    use std::sync::Arc;

    #[test]
    fn cells_differing_in_one_axis_are_timed_apart_exactly_where_the_axis_table_says() {
        let text = "name = \"t\"\ncompositions = [\"medusa\"]\npipelines = [\"builtin\"]\nshaders = [\"standard\"]\npresets = [\"gold\"]\n\
                    [image]\nwidth = 8\nheight = 8\n[sweep]\nsmoothness = [0.2, 0.8]\nmetallic = [0.1, 0.3]\nlight_intensity = [1.5, 2.5]\n\
                    light_range = [3.0, 7.0]\ncamera_distance = [1.25, 2.0]\nlight_angle = [30.0, 60.0]\nemission = [0.5, 1.0]\n\
                    textured = [false, true]\nambient_intensity = [0.5, 2.0]\n";
        let m = Matrix::from_text("t.toml", text, None, Arc::new(crate::shading::Registry::builtin())).unwrap();
        let e = crate::cells::expand(&m);
        let c = &e.cells[0];
        // Two cells differing in one axis share a timing class exactly when the table says so.
        let axes = [
            "light_range",
            "camera_distance",
            "textured",
            "light_angle",
            "smoothness",
            "metallic",
            "light_intensity",
            "emission",
            "ambient_intensity",
        ];
        let coords = |x: &Cell| -> Vec<String> {
            vec![
                format!("{}", x.light_range),
                format!("{:?}", x.camera_distance),
                format!("{}", x.textured),
                format!("{:?}", x.light_angle),
                format!("{}", x.material.smoothness),
                format!("{}", x.material.metallic),
                format!("{}", x.light_intensity),
                format!("{:?}", x.emission),
                format!("{:?}", x.ambient_intensity),
                format!("{}{}{}{}", x.composition, x.pipeline.name(), x.shader, x.preset),
            ]
        };
        let mine = coords(c);
        for (k, axis) in axes.iter().enumerate() {
            let row = crate::declarations::axes::find(axis).unwrap();
            let other = e
                .cells
                .iter()
                .find(|o| {
                    let theirs = coords(o);
                    (0..mine.len()).all(|j| (mine[j] == theirs[j]) != (j == k))
                })
                .unwrap_or_else(|| panic!("no cell differing in {axis} alone"));
            let class = timing_class;
            assert_eq!(class(c) != class(other), row.timing, "{axis}: the table says timing = {}", row.timing);
        }
    }
}
