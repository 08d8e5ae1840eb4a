//! What a cell is: its value on every axis of the table (`declarations::axes`), one field per axis. Cells,
//! filters, references, ids, records, sheets, invariants and the viewer read and change a cell's
//! axes only through `get`/`set`, so an axis is a row of the table and a field here.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

use crate::declarations::axes::{self, Axis, AxisRow};
use crate::declarations::filter::{colour_label, FilterValue};
use crate::pipelines::settings_axes::SettingValue;
use crate::pipelines::{Pipeline, RenderPath};

/// A cell's value on one axis.
#[derive(Debug, Clone, PartialEq)]
pub enum AxisValue {
    Name(String),
    Number(f64),
    /// Not swept: the scene's own value (camera distance, light angle, ambient) or none (emission).
    Own,
    /// The sRGB slider colour, or None for the preset's own.
    Colour(Option<[f64; 3]>),
    Bool(bool),
    /// The swept model parameters, by name.
    Params(BTreeMap<String, f64>),
    /// The engine settings the cell sets off its matrix's (or its preset's) own, by key.
    Settings(BTreeMap<String, SettingValue>),
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CellCoords {
    pub composition: String,
    pub pipeline: Pipeline,
    pub path: RenderPath,
    pub shader: String,
    pub preset: String,
    /// The metallic and smoothness sliders: the sweep's value, or the preset's own.
    pub metallic: f64,
    pub smoothness: f64,
    /// The sRGB slider colour when the colour axis overrides the preset.
    pub color: Option<[f64; 3]>,
    /// The key light's intensity (matrix units, 0–100) and range (m): the sweep's or the scene's.
    pub light_intensity: f64,
    pub light_range: f64,
    /// Metres from the camera target; degrees between light and view (None: the scene's own).
    pub camera_distance: Option<f64>,
    pub light_angle: Option<f64>,
    /// `[sweep.params]` values this cell's model takes.
    pub params: BTreeMap<String, f64>,
    /// The subject wears its preset's textured form (`materials`).
    pub textured: bool,
    /// The emission axis, when swept.
    pub emission: Option<f64>,
    /// The scene's ambient light (sky SH, reflections and probes) scaled by this factor (None: as
    /// the scene sets it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient_intensity: Option<f64>,
    /// The subject's surface type, when swept (None: the material's own, opaque for presets).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<crate::pipelines::surface::SurfaceType>,
    /// The subject's base-colour alpha, when swept (None: the material's own, 1 for presets).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// The subject's sRGB specular colour, when swept (None: the model's own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular: Option<[f64; 3]>,
    /// HDRP Lit's material type, when swept (None: the model's own parameters).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material_type: Option<crate::shading::material_type::MaterialType>,
    /// The engine settings of its pipeline the sweep sets off the matrix's (`[sweep.settings]`),
    /// where the value differs from what the cell had without it.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub settings: BTreeMap<String, SettingValue>,
}

/// What names a cell before its sweep sets any axis: composition, pipeline, path, shader and preset.
#[derive(Debug, Clone)]
pub struct CellNames {
    pub composition: String,
    pub pipeline: Pipeline,
    pub path: RenderPath,
    pub shader: String,
    pub preset: String,
}

impl CellCoords {
    /// A cell before the sweep sets its axes: the preset's metallic and smoothness, the scene's key
    /// light, no slider colour, flat unless `textured`, and the scene's own value on every other
    /// axis.
    pub fn unswept(
        names: CellNames,
        (metallic, smoothness): (f64, f64),
        (intensity, range): (f64, f64),
        textured: bool,
    ) -> CellCoords {
        let CellNames { composition, pipeline, path, shader, preset } = names;
        CellCoords {
            composition,
            pipeline,
            path,
            shader,
            preset,
            metallic,
            smoothness,
            color: None,
            light_intensity: intensity,
            light_range: range,
            camera_distance: None,
            light_angle: None,
            params: BTreeMap::new(),
            textured,
            emission: None,
            ambient_intensity: None,
            surface: None,
            alpha: None,
            specular: None,
            material_type: None,
            settings: BTreeMap::new(),
        }
    }

    /// The cell's value on `axis`.
    pub fn get(&self, axis: Axis) -> AxisValue {
        let name = |s: &str| AxisValue::Name(s.to_string());
        let own = |v: Option<f64>| v.map_or(AxisValue::Own, AxisValue::Number);
        match axis {
            Axis::Composition => name(&self.composition),
            Axis::Pipeline => name(self.pipeline.name()),
            Axis::Path => name(self.path.name()),
            Axis::Shader => name(&self.shader),
            Axis::Preset => name(&self.preset),
            Axis::Metallic => AxisValue::Number(self.metallic),
            Axis::Smoothness => AxisValue::Number(self.smoothness),
            Axis::Color => AxisValue::Colour(self.color),
            Axis::LightIntensity => AxisValue::Number(self.light_intensity),
            Axis::LightRange => AxisValue::Number(self.light_range),
            Axis::CameraDistance => own(self.camera_distance),
            Axis::LightAngle => own(self.light_angle),
            Axis::Params => AxisValue::Params(self.params.clone()),
            Axis::Emission => own(self.emission),
            Axis::Textured => AxisValue::Bool(self.textured),
            Axis::AmbientIntensity => own(self.ambient_intensity),
            Axis::Surface => self.surface.map_or(AxisValue::Own, |s| name(s.name())),
            Axis::Alpha => own(self.alpha),
            Axis::Specular => AxisValue::Colour(self.specular),
            Axis::MaterialType => self.material_type.map_or(AxisValue::Own, |t| name(t.name())),
            Axis::Settings => AxisValue::Settings(self.settings.clone()),
        }
    }

    /// Set the cell's value on `axis`; false (nothing changed) when `v` is not a value of it.
    pub fn set(&mut self, axis: Axis, v: &AxisValue) -> bool {
        let number = |v: &AxisValue| match v {
            AxisValue::Number(x) => Some(*x),
            _ => None,
        };
        // An axis whose unset value is the scene's own takes `Own` too.
        let optional = |v: &AxisValue| match v {
            AxisValue::Own => Some(None),
            AxisValue::Number(x) => Some(Some(*x)),
            _ => None,
        };
        match (axis, v) {
            (Axis::Composition, AxisValue::Name(n)) => self.composition = n.clone(),
            (Axis::Pipeline, AxisValue::Name(n)) => match Pipeline::from_name(n) {
                Some(p) => self.pipeline = p,
                None => return false,
            },
            (Axis::Path, AxisValue::Name(n)) => match RenderPath::from_name(n) {
                Some(p) => self.path = p,
                None => return false,
            },
            (Axis::Shader, AxisValue::Name(n)) => self.shader = n.clone(),
            (Axis::Preset, AxisValue::Name(n)) => self.preset = n.clone(),
            (Axis::Surface, AxisValue::Name(n)) => match crate::pipelines::surface::SurfaceType::from_name(n) {
                Some(s) => self.surface = Some(s),
                None => return false,
            },
            (Axis::Surface, AxisValue::Own) => self.surface = None,
            (Axis::MaterialType, AxisValue::Name(n)) => {
                match crate::shading::material_type::MaterialType::from_name(n) {
                    Some(t) => self.material_type = Some(t),
                    None => return false,
                }
            }
            (Axis::MaterialType, AxisValue::Own) => self.material_type = None,
            (Axis::Color, AxisValue::Colour(c)) => self.color = *c,
            (Axis::Specular, AxisValue::Colour(c)) => self.specular = *c,
            (Axis::Params, AxisValue::Params(p)) => self.params = p.clone(),
            (Axis::Settings, AxisValue::Settings(p)) => self.settings = p.clone(),
            (Axis::Textured, AxisValue::Bool(b)) => self.textured = *b,
            (Axis::Metallic, v) if number(v).is_some() => self.metallic = number(v).unwrap_or_default(),
            (Axis::Smoothness, v) if number(v).is_some() => self.smoothness = number(v).unwrap_or_default(),
            (Axis::LightIntensity, v) if number(v).is_some() => self.light_intensity = number(v).unwrap_or_default(),
            (Axis::LightRange, v) if number(v).is_some() => self.light_range = number(v).unwrap_or_default(),
            (Axis::CameraDistance, v) if optional(v).is_some() => self.camera_distance = optional(v).flatten(),
            (Axis::LightAngle, v) if optional(v).is_some() => self.light_angle = optional(v).flatten(),
            (Axis::Emission, v) if optional(v).is_some() => self.emission = optional(v).flatten(),
            (Axis::AmbientIntensity, v) if optional(v).is_some() => self.ambient_intensity = optional(v).flatten(),
            (Axis::Alpha, v) if optional(v).is_some() => self.alpha = optional(v).flatten(),
            _ => return false,
        }
        true
    }

    /// The cell's value on `axis` as filters and invariants compare it (`declarations::filter`): an
    /// unswept view axis is `scene`, an unswept emission 0.
    pub fn filter_value(&self, axis: Axis) -> FilterValue {
        match self.get(axis) {
            AxisValue::Name(n) => FilterValue::Name(n),
            AxisValue::Number(x) => FilterValue::Number(x),
            AxisValue::Own if axis == Axis::Emission => FilterValue::Number(0.0),
            AxisValue::Own => FilterValue::Name(axes::of(axis).own.into()),
            AxisValue::Colour(c) => FilterValue::Color(colour_label(axis, c)),
            AxisValue::Bool(b) => FilterValue::Name(b.to_string()),
            AxisValue::Params(p) => FilterValue::Name(params_label(&p)),
            AxisValue::Settings(p) => FilterValue::Name(settings_label(&p)),
        }
    }

    /// Whether the cell is one a filter's values name on `axis`.
    pub fn matches(&self, axis: Axis, values: &[FilterValue]) -> bool {
        let v = self.filter_value(axis);
        values.iter().any(|w| match (&v, w) {
            (FilterValue::Number(x), FilterValue::Number(y)) => close(*x, *y),
            _ => &v == w,
        })
    }

    /// The cell's value on the axis named `name` as sheet labels and file names show it: numbers
    /// exact where two decimals are not (0.999 and 1 are two columns, not one).
    pub fn label(&self, name: &str) -> String {
        self.shown(name, |v| crate::cells::id_number(v, 2, false))
    }

    /// The value as the viewer shows it: numbers exactly (the shortest decimal that reads back).
    pub fn exact(&self, name: &str) -> String {
        self.shown(name, |v| format!("{v}"))
    }

    fn shown(&self, name: &str, number: impl Fn(f64) -> String) -> String {
        let Some(row) = axes::find(name) else { return "?".into() };
        match self.get(row.axis) {
            AxisValue::Name(n) => n,
            AxisValue::Number(x) => number(x),
            AxisValue::Own => row.own.into(),
            AxisValue::Colour(c) => colour_label(row.axis, c),
            AxisValue::Bool(b) => b.to_string(),
            AxisValue::Params(p) => params_label(&p),
            AxisValue::Settings(p) => settings_label(&p),
        }
    }

    /// The id's part for one axis (`_s0.90`, `_tex`), empty where the id does not carry it.
    pub fn id_part(&self, row: &AxisRow) -> String {
        let Some(prefix) = row.id_prefix else { return String::new() };
        match self.get(row.axis) {
            AxisValue::Number(x) => match row.id_decimals {
                Some(d) => format!("{prefix}{}", crate::cells::id_number(x, d, false)),
                None => format!("{prefix}{}", crate::cells::id_number(x, 4, true)),
            },
            AxisValue::Colour(Some(c)) => format!("{prefix}{}", colour_label(row.axis, Some(c))),
            AxisValue::Bool(true) => prefix.to_string(),
            AxisValue::Name(n) if row.kind == axes::AxisKind::Choice => format!("{prefix}{n}"),
            AxisValue::Params(p) => {
                p.iter().map(|(k, v)| format!("_{k}{}", crate::cells::id_number(*v, 4, true))).collect()
            }
            // `_cascade_count.2`, `_asset.high_fidelity`: the dot keeps a key's digits apart from its value's.
            AxisValue::Settings(p) => p.iter().map(|(k, v)| format!("_{k}.{}", v.label())).collect(),
            _ => String::new(),
        }
    }
}

fn params_label(p: &BTreeMap<String, f64>) -> String {
    if p.is_empty() {
        "defaults".into()
    } else {
        p.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(",")
    }
}

fn settings_label(p: &BTreeMap<String, SettingValue>) -> String {
    if p.is_empty() {
        "engine".into()
    } else {
        p.iter().map(|(k, v)| format!("{k}={}", v.label())).collect::<Vec<_>>().join(",")
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
}
