//! A cell's record before it is measured: its axes, the model's inputs and the light.

use crate::cells::Cell;
use crate::declarations::matrix::Matrix;
use crate::record::cell::{ImageFiles, KeyLight, ShaderInputs};

/// The model's inputs as the shader receives them, with its parameters by name.
pub fn shader_inputs(cell: &Cell) -> ShaderInputs {
    let model = cell.model();
    let s = cell.surface();
    ShaderInputs {
        base_color_linear: s.base_color.to_array(),
        metallic: s.metallic,
        smoothness: s.smoothness,
        specular: s.specular.to_array(),
        params: model.params.iter().map(|p| (p.name.to_string(), s.params[p.slot])).collect(),
        mapping: model.mapping.to_string(),
    }
}

pub fn key_light(matrix: &Matrix, cell: &Cell) -> KeyLight {
    let scene = &matrix.compositions[cell.composition_index];
    let emitter = scene.key_light().map(|k| scene.lights[k].emitter());
    KeyLight {
        unit: emitter.map_or_else(
            || "no key light".to_string(),
            |e| cell.pipeline.intensity_unit_with(e, &cell.pipeline_settings).to_string(),
        ),
        intensity: cell.light_intensity,
        range: cell.light_range,
        intensity_scale: cell.pipeline.intensity_scale(),
        attenuation: cell.pipeline.attenuation(),
    }
}

pub fn image_files(cell: &Cell, exr_format: String) -> ImageFiles {
    ImageFiles { width: cell.width, height: cell.height, exr: "image.exr".into(), png: "image.png".into(), exr_format }
}
