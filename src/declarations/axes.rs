//! The axes of a matrix, in one table: one row per axis with its name, its kind, the range a sweep
//! may take, whether a cell reference may change it, whether it enters the timing class, and what
//! precedes its value in a cell id. Filters (`declarations::filter::Axis`), references, sheets, sort
//! orders and the viewer read the axes from here, so a new axis is a new row.

use serde::Deserialize;

/// Axes a filter can name; each has a row in `declarations::axes::AXES`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    Composition,
    Pipeline,
    Path,
    Shader,
    Preset,
    Metallic,
    Smoothness,
    LightIntensity,
    LightRange,
    Color,
    CameraDistance,
    LightAngle,
    Textured,
    Emission,
    /// The swept model parameters (`[sweep.params]`); not a filter axis.
    Params,
    AmbientIntensity,
    /// The subject's surface type (`pipelines::surface`).
    Surface,
    /// The subject's base-colour alpha.
    Alpha,
    /// The subject's specular colour (`Surface::specular`), for the models that read one.
    Specular,
    /// HDRP Lit's Material Type (`shading::material_type`).
    MaterialType,
    /// The swept engine settings (`[sweep.settings.<pipeline>]`); not a filter axis.
    Settings,
}

impl Axis {
    /// As matrices and filters name it (`declarations::axes`).
    pub fn name(self) -> &'static str {
        of(self).name
    }

    pub fn is_numeric(self) -> bool {
        of(self).kind == AxisKind::Number
    }
}

/// What values an axis takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    /// A name from a list (pipelines, shaders, presets, …).
    Name,
    /// A number in `AxisRow::range`.
    Number,
    /// An sRGB colour, named by its 8-bit hex code (its own value by the row's `own`).
    Colour,
    Bool,
    /// A name from a fixed list, swept in `[sweep]` (the surface types, the material types).
    Choice,
    /// The swept model parameters, each its own list (`[sweep.params]`).
    Params,
    /// The swept engine settings, a list per pipeline and setting (`[sweep.settings.<pipeline>]`).
    Settings,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisRow {
    /// As matrices, filters, sheets and records name it.
    pub name: &'static str,
    pub axis: Axis,
    /// A filter (`only`, `exclude`, asserts) may name it (`params` are named per parameter).
    pub filter: bool,
    pub kind: AxisKind,
    /// The values a sweep may list (numbers only).
    pub range: Option<(f64, f64)>,
    /// A cell reference (`reference = { axis = value }`) may change it.
    pub reference: bool,
    /// Cells that differ in it are timed apart (`plan::timing`): it changes the passes' work.
    pub timing: bool,
    /// What precedes its value in a cell id (`_s0.90`), where the id carries it; ids list the
    /// axes in table order.
    pub id_prefix: Option<&'static str>,
    /// Decimal places of its value in an id (None: up to four, trailing zeros trimmed).
    pub id_decimals: Option<usize>,
    /// How a cell that does not sweep it reads (the scene's own, or none).
    pub own: &'static str,
}

const fn row(name: &'static str, axis: Axis, kind: AxisKind) -> AxisRow {
    AxisRow {
        name,
        axis,
        kind,
        filter: true,
        range: None,
        reference: false,
        timing: false,
        id_prefix: None,
        id_decimals: None,
        own: "",
    }
}

const fn number(name: &'static str, axis: Axis, (lo, hi): (f64, f64), id_prefix: &'static str) -> AxisRow {
    AxisRow { range: Some((lo, hi)), id_prefix: Some(id_prefix), ..row(name, axis, AxisKind::Number) }
}

/// A Unity material slider in 0..1: two decimals in ids.
const fn slider(name: &'static str, axis: Axis, id_prefix: &'static str) -> AxisRow {
    AxisRow { reference: true, id_decimals: Some(2), ..number(name, axis, (0.0, 1.0), id_prefix) }
}

/// Every axis, in the order sheets, the viewer, filters and cell ids list them.
pub const AXES: [AxisRow; 21] = [
    AxisRow { reference: true, timing: true, ..row("composition", Axis::Composition, AxisKind::Name) },
    AxisRow { reference: true, timing: true, ..row("pipeline", Axis::Pipeline, AxisKind::Name) },
    AxisRow { reference: true, timing: true, ..row("path", Axis::Path, AxisKind::Name) },
    AxisRow { reference: true, timing: true, ..row("shader", Axis::Shader, AxisKind::Name) },
    row("preset", Axis::Preset, AxisKind::Name),
    slider("metallic", Axis::Metallic, "__m"),
    slider("smoothness", Axis::Smoothness, "_s"),
    AxisRow { id_prefix: Some("_c"), own: "preset", ..row("color", Axis::Color, AxisKind::Colour) },
    AxisRow { reference: true, ..number("light_intensity", Axis::LightIntensity, (0.0, 100.0), "_i") },
    AxisRow { reference: true, timing: true, ..number("light_range", Axis::LightRange, (1e-3, 40.0), "_r") },
    AxisRow {
        reference: true,
        timing: true,
        own: "scene",
        ..number("camera_distance", Axis::CameraDistance, (1e-3, 1000.0), "_d")
    },
    AxisRow { reference: true, own: "scene", ..number("light_angle", Axis::LightAngle, (0.0, 180.0), "_a") },
    AxisRow { filter: false, id_prefix: Some("_"), own: "defaults", ..row("params", Axis::Params, AxisKind::Params) },
    AxisRow { own: "none", ..number("emission", Axis::Emission, (0.0, 100.0), "_e") },
    AxisRow { timing: true, id_prefix: Some("_tex"), ..row("textured", Axis::Textured, AxisKind::Bool) },
    AxisRow {
        reference: true,
        own: "scene",
        ..number("ambient_intensity", Axis::AmbientIntensity, (0.0, 10.0), "_amb")
    },
    AxisRow {
        reference: true,
        timing: true,
        own: "material",
        id_prefix: Some("_"),
        ..row("surface", Axis::Surface, AxisKind::Choice)
    },
    AxisRow { own: "material", ..slider("alpha", Axis::Alpha, "_al") },
    AxisRow { id_prefix: Some("_sp"), own: "model", ..row("specular", Axis::Specular, AxisKind::Colour) },
    AxisRow {
        reference: true,
        timing: true,
        own: "model",
        id_prefix: Some("_"),
        ..row("material_type", Axis::MaterialType, AxisKind::Choice)
    },
    AxisRow {
        filter: false,
        timing: true,
        id_prefix: Some("_"),
        own: "engine",
        ..row("settings", Axis::Settings, AxisKind::Settings)
    },
];

/// The row of the axis named `name`.
pub fn find(name: &str) -> Option<&'static AxisRow> {
    AXES.iter().find(|r| r.name == name)
}

/// The row of a filter axis.
pub fn of(axis: Axis) -> &'static AxisRow {
    AXES.iter().find(|r| r.axis == axis).expect("every axis has a row in declarations::axes::AXES")
}

/// Every axis's name, in table order (what a sheet may lay out).
pub fn names() -> Vec<&'static str> {
    AXES.iter().map(|r| r.name).collect()
}

/// The axes a filter can name, in table order.
pub fn filter_axes() -> impl Iterator<Item = Axis> {
    AXES.iter().filter(|r| r.filter).map(|r| r.axis)
}

/// The axes a cell reference may change.
pub fn reference_axes() -> impl Iterator<Item = Axis> {
    AXES.iter().filter(|r| r.reference).map(|r| r.axis)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_axis_has_one_row() {
        let axes: Vec<Axis> = AXES.iter().map(|r| r.axis).collect();
        let mut unique = axes.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(axes.len(), unique.len(), "an axis listed twice");
        assert_eq!(names().len(), AXES.len());
        for r in &AXES {
            assert_eq!(r.range.is_some(), r.kind == AxisKind::Number, "{}", r.name);
        }
        // Every variant (an exhaustive match: a new one fails to compile here) has its row.
        let named = |a: Axis| match a {
            Axis::Composition => "composition",
            Axis::Pipeline => "pipeline",
            Axis::Path => "path",
            Axis::Shader => "shader",
            Axis::Preset => "preset",
            Axis::Metallic => "metallic",
            Axis::Smoothness => "smoothness",
            Axis::LightIntensity => "light_intensity",
            Axis::LightRange => "light_range",
            Axis::Color => "color",
            Axis::CameraDistance => "camera_distance",
            Axis::LightAngle => "light_angle",
            Axis::Textured => "textured",
            Axis::Emission => "emission",
            Axis::Params => "params",
            Axis::AmbientIntensity => "ambient_intensity",
            Axis::Surface => "surface",
            Axis::Alpha => "alpha",
            Axis::Specular => "specular",
            Axis::MaterialType => "material_type",
            Axis::Settings => "settings",
        };
        for r in &AXES {
            assert_eq!(r.name, named(r.axis));
        }
        assert_eq!(filter_axes().count(), AXES.len() - 2, "every axis but params and settings");
    }
}
