//! Timing classes. A frame's GPU time depends on what is drawn and how — the composition, the
//! pipeline and path, the shader's code, the lights that reach each object, the resolution, the
//! anti-aliasing, the textures and the level of detail — and hardly on the values a slider sets
//! (metallic, smoothness, colour, intensity, a parameter, the light's angle): those are uniforms of
//! the same passes. So a run times one cell per class with the matrix's `[timing]` frames and gives
//! the others of its class that cell's figures, marked in their records (`timing.timed_as`); they
//! render one frame. `[timing] every_cell = true` times every cell.

use crate::cells::Cell;

/// The class of `cell`: equal for cells whose frames run the same passes over the same work.
/// The light range stays in it: the pipelines cull a light from objects beyond its range, which
/// changes how many lights each object's pass evaluates.
pub fn timing_class(cell: &Cell) -> String {
    format!(
        "{}|{}|{}|{}|{}x{}|{:?}|{:?}|textured {}|range {}|distance {:?}",
        cell.composition,
        cell.pipeline.name(),
        cell.path.name(),
        cell.shader,
        cell.width,
        cell.height,
        cell.antialiasing,
        cell.light_budget,
        cell.textured,
        cell.light_range,
        cell.camera_distance,
    )
}
