//! The axes a filter (`[[only]]`, `[[exclude]]`, `--only`, an assert's `where`, a cell reference)
//! can name, and filters parsed from TOML: shared by the matrix and its asserts.

use serde::Deserialize;
use std::collections::BTreeMap;

use crate::error::InputError;
use crate::input::names::unknown_name;
use crate::input::validate::Checker;

pub use super::axes::Axis;

#[derive(Debug, Clone, PartialEq, serde::Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FilterValue {
    Name(String),
    Number(f64),
    /// An sRGB slider colour as its 6-digit hex code (`ff8000`), or `preset` for the preset's own.
    Color(String),
}

/// The colour axis's value of a cell: the slider colour's hex code, or `preset`.
pub fn color_code(srgb: Option<[f64; 3]>) -> String {
    colour_label(Axis::Color, srgb)
}

/// A colour axis's value as cells, filters and sheets name it: its 8-bit hex code, or the axis's
/// own value (`preset` for `color`, `model` for `specular`).
pub fn colour_label(axis: Axis, srgb: Option<[f64; 3]>) -> String {
    match srgb {
        Some(rgb) => rgb.iter().map(|v| format!("{:02x}", (v * 255.0).round() as u8)).collect(),
        None => super::axes::of(axis).own.into(),
    }
}

/// A conjunction: every named axis must take one of its listed values.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, Deserialize)]
pub struct Filter {
    pub terms: Vec<(Axis, Vec<FilterValue>)>,
}

pub fn parse_filter(c: &Checker, key: &str, table: &toml::Table) -> Result<Filter, InputError> {
    let axis_names: Vec<&str> = super::axes::filter_axes().map(|a| a.name()).collect();
    let mut terms = BTreeMap::new();
    for (k, v) in table {
        let axis = super::axes::filter_axes()
            .find(|a| a.name() == k)
            .ok_or_else(|| unknown_name(c.file(), &format!("{key}.{k}"), "filter axis", k, &axis_names))?;
        let items: Vec<&toml::Value> = match v {
            toml::Value::Array(a) => a.iter().collect(),
            other => vec![other],
        };
        let mut values = Vec::new();
        for item in items {
            if super::axes::of(axis).kind == super::axes::AxisKind::Colour {
                values.push(parse_color_value(c, &format!("{key}.{k}"), item, super::axes::of(axis).own)?);
                continue;
            }
            let value = match (axis.is_numeric(), item) {
                (false, toml::Value::Boolean(b)) if axis == Axis::Textured => FilterValue::Name(b.to_string()),
                (true, toml::Value::Float(f)) if f.is_finite() => FilterValue::Number(*f),
                // NaN matches no cell: a filter of it would silently select nothing.
                (true, toml::Value::Float(f)) => {
                    return Err(
                        c.err(&format!("{key}.{k}"), format!("value {f} is not finite; allowed: a finite number"))
                    )
                }
                (true, toml::Value::Integer(i)) => FilterValue::Number(*i as f64),
                // The scene's own value of an axis that can be swept with it (`"scene"`).
                (true, toml::Value::String(s)) if s == "scene" && super::axes::of(axis).own == "scene" => {
                    FilterValue::Name(s.clone())
                }
                (false, toml::Value::String(s)) => FilterValue::Name(s.clone()),
                (numeric, other) => {
                    return Err(c.err(
                        &format!("{key}.{k}"),
                        format!(
                            "value {other} has the wrong type; allowed: {}",
                            if numeric { "a number or a list of numbers" } else { "a name or a list of names" }
                        ),
                    ))
                }
            };
            values.push(value);
        }
        terms.insert(axis, values);
    }
    Ok(Filter { terms: terms.into_iter().collect() })
}

/// A colour in a filter: a hex code (`"ff8000"`, `"#ff8000"`), the axis's own (`"preset"`,
/// `"model"`), or [r, g, b] in 0..1.
fn parse_color_value(c: &Checker, key: &str, item: &toml::Value, own: &str) -> Result<FilterValue, InputError> {
    let allowed = format!("a hex code such as \"ff8000\", \"{own}\", or [r, g, b] in 0..1");
    match item {
        toml::Value::String(s) => {
            let hex = s.trim_start_matches('#').to_ascii_lowercase();
            if hex == own || (hex.len() == 6 && hex.chars().all(|ch| ch.is_ascii_hexdigit())) {
                Ok(FilterValue::Color(hex))
            } else {
                Err(c.err(key, format!("`{s}` is not a colour; allowed: {allowed}")))
            }
        }
        toml::Value::Array(a) if a.len() == 3 => {
            let mut rgb = [0.0; 3];
            for (i, v) in a.iter().enumerate() {
                rgb[i] = match v {
                    toml::Value::Float(f) => *f,
                    toml::Value::Integer(n) => *n as f64,
                    other => return Err(c.err(key, format!("{other} is not a number; allowed: {allowed}"))),
                };
            }
            c.color(key, rgb)?;
            Ok(FilterValue::Color(color_code(Some(rgb))))
        }
        other => Err(c.err(key, format!("value {other} is not a colour; allowed: {allowed}"))),
    }
}
