//! A matrix's `[sweep]` table: the value lists of the axis table's rows (`declarations::axes`),
//! read with the message each bad value needs.

use serde::Deserialize;
use std::collections::BTreeMap;

use super::axes::Axis;
use crate::pipelines::settings_axes::{self, SettingValue};
use crate::pipelines::Pipeline;

/// Value lists; an empty list means "the preset's (or the scene's) own value". Its keys are the
/// axis table's (`declarations::axes`): a number list per numeric axis, `color` (sRGB slider colours,
/// linearised before shading), `textured` (the subject's preset flat or in its textured form) and
/// `[sweep.params]` (a list per model parameter, `ior = [1.3, 1.5]`; a cell whose model lacks a
/// parameter is not multiplied by it). A new numeric axis is a row of the table, not a field here.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Sweep {
    /// Each numeric axis's values, by the axis's table name.
    #[serde(flatten)]
    pub numbers: BTreeMap<String, Vec<f64>>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub color: Vec<[f64; 3]>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub textured: Vec<bool>,
    /// The specular colours (sRGB), and "model" for the model's own.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub specular: Vec<[f64; 3]>,
    /// The surface types (`pipelines::surface`), and "material" for the material's own.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub surface: Vec<crate::pipelines::surface::SurfaceType>,
    /// HDRP Lit's material types (`shading::material_type`), and "model" for the model's own.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub material_type: Vec<crate::shading::material_type::MaterialType>,
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub params: BTreeMap<String, Vec<f64>>,
    /// `[sweep.settings.<pipeline>]`: engine settings' values (`pipelines::settings_axes`), per
    /// pipeline and setting; a cell of another pipeline is not multiplied by them.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub settings: BTreeMap<Pipeline, BTreeMap<String, Vec<SettingValue>>>,
    /// Axes whose list also names their own value: the scene's on numeric axes whose table row
    /// reads `own = "scene"` (`camera_distance = ["scene", 0.3, 0.8]`), the preset's colour
    /// (`color = ["preset", [1, 1, 1]]`).
    #[serde(skip_serializing_if = "std::collections::BTreeSet::is_empty")]
    pub own: std::collections::BTreeSet<String>,
    /// How the lists combine (`design = "one_at_a_time"`): a grid by default.
    #[serde(skip_serializing_if = "SweepDesign::is_grid")]
    pub design: SweepDesign,
}

/// How a sweep's value lists combine into cells.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepDesign {
    /// Every combination of one value per list (their product).
    #[default]
    Grid,
    /// One slider moved at a time, as a person moves them in the comparison app: the cell at every
    /// axis's own value (the preset's material, the scene's light and view, the model's parameters)
    /// and, for each list, one cell per value with every other axis at its own. A pipeline ×
    /// shader × preset then has 1 + Σ (values per list) cells, not their product.
    OneAtATime,
}

impl SweepDesign {
    pub const NAMES: [&'static str; 2] = ["grid", "one_at_a_time"];

    fn is_grid(&self) -> bool {
        *self == SweepDesign::Grid
    }

    pub fn from_name(name: &str) -> Option<SweepDesign> {
        match name {
            "grid" => Some(SweepDesign::Grid),
            "one_at_a_time" => Some(SweepDesign::OneAtATime),
            _ => None,
        }
    }
}

impl<'de> Deserialize<'de> for Sweep {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Sweep, D::Error> {
        use super::axes::AxisKind;
        use serde::de::Error as _;
        let table = toml::Table::deserialize(d)?;
        let mut sweep = Sweep::default();
        for (key, value) in table {
            let typed = |e: toml::de::Error| D::Error::custom(format!("sweep.{key}: {}", e.message()));
            if key == "design" {
                let name: String = value.try_into().map_err(typed)?;
                sweep.design = SweepDesign::from_name(&name).ok_or_else(|| {
                    let near = crate::input::names::nearest(&name, &SweepDesign::NAMES)
                        .map(|n| format!(" (did you mean `{n}`?)"))
                        .unwrap_or_default();
                    D::Error::custom(format!(
                        "sweep.design: `{name}` is not a sweep design{near}; allowed: {}",
                        SweepDesign::NAMES.join(", ")
                    ))
                })?;
                continue;
            }
            match super::axes::find(&key).map(|r| r.kind) {
                Some(AxisKind::Number) => {
                    let row = super::axes::find(&key).expect("a row");
                    let items: Vec<toml::Value> = value.clone().try_into().map_err(typed)?;
                    let mut numbers = Vec::with_capacity(items.len());
                    for item in items {
                        match item {
                            toml::Value::Float(f) => numbers.push(f),
                            toml::Value::Integer(i) => numbers.push(i as f64),
                            toml::Value::String(s) if row.own == "scene" && s == "scene" => {
                                sweep.own.insert(key.clone());
                            }
                            other => {
                                let allowed = if row.own == "scene" {
                                    "numbers, or \"scene\" for the scene's own"
                                } else {
                                    "numbers"
                                };
                                return Err(D::Error::custom(format!(
                                    "sweep.{key}: {other} is not a value of this axis; allowed: {allowed}"
                                )));
                            }
                        }
                    }
                    sweep.numbers.insert(key.clone(), numbers);
                }
                Some(AxisKind::Colour) => {
                    // Colours as [r, g, b] in sRGB, and the row's own ("preset", "model").
                    let row = super::axes::find(&key).expect("a row");
                    let items: Vec<toml::Value> = value.clone().try_into().map_err(typed)?;
                    for item in items {
                        match item {
                            toml::Value::String(s) if s == row.own => {
                                sweep.own.insert(key.clone());
                            }
                            toml::Value::String(s) => {
                                return Err(D::Error::custom(format!(
                                    "sweep.{key}: `{s}` is not a colour; allowed: [r, g, b] in sRGB 0..1, or \"{}\" for the {}'s own",
                                    row.own, row.own
                                )));
                            }
                            other => {
                                let colour: [f64; 3] = other.try_into().map_err(typed)?;
                                match row.axis {
                                    Axis::Specular => sweep.specular.push(colour),
                                    _ => sweep.color.push(colour),
                                }
                            }
                        }
                    }
                }
                Some(AxisKind::Bool) => sweep.textured = value.clone().try_into().map_err(typed)?,
                Some(AxisKind::Choice) => {
                    use crate::pipelines::surface::SurfaceType;
                    use crate::shading::material_type::MaterialType;
                    let row = super::axes::find(&key).expect("a row");
                    let items: Vec<String> = value.clone().try_into().map_err(typed)?;
                    let (what, mut allowed) = match row.axis {
                        Axis::MaterialType => ("a material type", MaterialType::names()),
                        _ => ("a surface type", SurfaceType::names()),
                    };
                    allowed.push(row.own);
                    for (i, item) in items.iter().enumerate() {
                        match row.axis {
                            _ if item == row.own => {
                                sweep.own.insert(key.clone());
                            }
                            Axis::MaterialType if MaterialType::from_name(item).is_some() => {
                                sweep.material_type.extend(MaterialType::from_name(item));
                            }
                            Axis::Surface if SurfaceType::from_name(item).is_some() => {
                                sweep.surface.extend(SurfaceType::from_name(item));
                            }
                            _ => {
                                let near = crate::input::names::nearest(item, &allowed)
                                    .map(|n| format!(" (did you mean `{n}`?)"))
                                    .unwrap_or_default();
                                return Err(D::Error::custom(format!(
                                    "sweep.{key}[{i}]: `{item}` is not {what}{near}; allowed: {}",
                                    allowed.join(", ")
                                )));
                            }
                        }
                    }
                }
                Some(AxisKind::Params) => sweep.params = value.clone().try_into().map_err(typed)?,
                Some(AxisKind::Settings) => sweep.settings = settings(value).map_err(D::Error::custom)?,
                _ => {
                    // As serde words it, so the input layer adds the nearest key.
                    let keys: Vec<String> = super::axes::AXES
                        .iter()
                        .filter(|r| r.kind != AxisKind::Name)
                        .map(|r| format!("`{}`", r.name))
                        .chain(std::iter::once("`design`".to_string()))
                        .collect();
                    return Err(D::Error::custom(format!(
                        "unknown field `{key}`, expected one of {}",
                        keys.join(", ")
                    )));
                }
            }
        }
        Ok(sweep)
    }
}

/// `[sweep.settings]`: a table per pipeline of lists of its settings' values, each checked.
fn settings(value: toml::Value) -> Result<BTreeMap<Pipeline, BTreeMap<String, Vec<SettingValue>>>, String> {
    let near = |name: &str, names: &[&str]| {
        crate::input::names::nearest(name, names).map(|n| format!(" (did you mean `{n}`?)")).unwrap_or_default()
    };
    let toml::Value::Table(pipelines) = value else {
        return Err("sweep.settings: a table of pipelines (`[sweep.settings.urp]`) is expected".into());
    };
    let mut out = BTreeMap::new();
    for (name, table) in pipelines {
        let pipeline = Pipeline::from_name(&name).ok_or_else(|| {
            let names = Pipeline::names();
            format!(
                "sweep.settings.{name}: `{name}` is not a pipeline{}; allowed: {}",
                near(&name, &names),
                names.join(", ")
            )
        })?;
        let toml::Value::Table(keys) = table else {
            return Err(format!("sweep.settings.{name}: a table of settings' value lists is expected"));
        };
        let mut lists = BTreeMap::new();
        for (key, list) in keys {
            let at = format!("sweep.settings.{name}.{key}");
            let Some(row) = settings_axes::find(pipeline, &key) else {
                let keys = settings_axes::keys(pipeline);
                let elsewhere: Vec<&str> = Pipeline::ALL
                    .into_iter()
                    .filter(|p| *p != pipeline && settings_axes::find(*p, &key).is_some())
                    .map(|p| p.name())
                    .collect();
                let other = match elsewhere.is_empty() {
                    true => String::new(),
                    false => format!(" (it is a setting of {})", elsewhere.join(" and ")),
                };
                return Err(format!(
                    "{at}: `{key}` is not a {name} setting{}{other}; allowed: {}",
                    near(&key, &keys),
                    keys.join(", ")
                ));
            };
            let toml::Value::Array(items) = list else {
                return Err(format!("{at}: a list of values is expected, such as `{key} = [...]`"));
            };
            let values = items
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    row.kind.read(v).ok_or_else(|| {
                        let hint = match (row.kind, v.as_str()) {
                            (settings_axes::SettingKind::Choice(names), Some(s)) => near(s, &names()),
                            _ => String::new(),
                        };
                        format!("{at}[{i}]: {v} is not a value of this setting{hint}; allowed: {}", row.kind.allowed())
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            lists.insert(key, values);
        }
        out.insert(pipeline, lists);
    }
    Ok(out)
}

impl Sweep {
    /// The values swept on a numeric axis (empty for the others, and for one not swept).
    pub fn numbers(&self, axis: Axis) -> &[f64] {
        self.numbers.get(axis.name()).map_or(&[], Vec::as_slice)
    }

    /// How many distinct values the sweep gives a numeric axis (metallic and smoothness without a
    /// sweep take each preset's own: one per preset, not a swept axis).
    pub fn values_of(&self, axis: Axis) -> usize {
        let v = self.numbers(axis);
        let mut distinct: Vec<f64> = Vec::new();
        for x in v {
            if !distinct.iter().any(|d| (d - x).abs() <= 1e-12 * x.abs().max(1.0)) {
                distinct.push(*x);
            }
        }
        distinct.len() + self.sweeps_own(axis) as usize
    }

    /// The colours swept on a colour axis.
    pub fn colours(&self, axis: Axis) -> &[[f64; 3]] {
        match axis {
            Axis::Color => &self.color,
            Axis::Specular => &self.specular,
            _ => &[],
        }
    }

    /// Whether the axis's list names the scene's own value besides its numbers.
    pub fn sweeps_own(&self, axis: Axis) -> bool {
        self.own.contains(axis.name())
    }
}
