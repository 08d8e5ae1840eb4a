//! Invariants declared in a matrix (`[[assert]]`), checked over a finished run's cells:
//!
//! - `monotone`: a measure of the cell (`subject_peak`, `subject_mean`, `peak`, `max_value`) moves one
//!   way along an axis, the other axes equal (e.g. the highlight peak rises with smoothness);
//! - `linear`: the EXR scales with the axis value — `offset = "zero"`: I(v) = v/v₀·I(v₀) (no other
//!   light in the image); `offset = "any"`: I(v) is affine in v (an environment or another light adds
//!   a constant; needs three values);
//! - `invariant`: the EXR does not change along the axis (Lambert ignores smoothness). The cells it
//!   covers are rendered rather than copied as twins, so the check can fail;
//! - `bounded`: a measure stays within `[min, max]` (no pixel of a white-furnace cell above 1 + ε).
//!
//! `tolerance` is relative: of the measure for `monotone` and `bounded`, and of the image's L1
//! norm for `linear` and `invariant`.

use serde::{Deserialize, Serialize};

use super::filter::{parse_filter, Axis, Filter};
use crate::error::InputError;
use crate::input::names::unknown_name;
use crate::input::validate::Checker;

/// What a `monotone` or `bounded` invariant reads from each cell's record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    /// Largest linear luminance over the subject's pixels.
    SubjectPeak,
    /// Mean linear luminance over the subject's pixels.
    SubjectMean,
    /// Largest linear luminance over the image.
    Peak,
    /// Largest finite channel value over the image.
    MaxValue,
}

impl Measure {
    pub const ALL: [Measure; 4] = [Measure::SubjectPeak, Measure::SubjectMean, Measure::Peak, Measure::MaxValue];

    pub fn name(self) -> &'static str {
        match self {
            Measure::SubjectPeak => "subject_peak",
            Measure::SubjectMean => "subject_mean",
            Measure::Peak => "peak",
            Measure::MaxValue => "max_value",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum InvariantKind {
    Monotone {
        measure: Measure,
        increasing: bool,
    },
    /// `through_zero`: proportional (offset "zero"); otherwise affine.
    Linear {
        through_zero: bool,
    },
    Invariant,
    Bounded {
        measure: Measure,
        min: Option<f64>,
        max: Option<f64>,
    },
}

impl InvariantKind {
    pub fn name(&self) -> &'static str {
        match self {
            InvariantKind::Monotone { .. } => "monotone",
            InvariantKind::Linear { .. } => "linear",
            InvariantKind::Invariant => "invariant",
            InvariantKind::Bounded { .. } => "bounded",
        }
    }
}

pub const KINDS: [&str; 4] = ["monotone", "linear", "invariant", "bounded"];

/// One `[[assert]]`, validated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InvariantSpec {
    pub name: String,
    #[serde(flatten)]
    pub kind: InvariantKind,
    /// The cells it covers (the grammar of `[[only]]`; empty: every cell).
    #[serde(rename = "where")]
    pub filter: Filter,
    /// The axis the cells of a group differ in (None for `bounded`: every cell alone).
    pub along: Option<Axis>,
    pub tolerance: f64,
}

const KEYS: [&str; 10] =
    ["name", "kind", "where", "along", "measure", "direction", "offset", "tolerance", "min", "max"];

/// Parse `[[assert]]` number `i` of a matrix.
pub fn parse_assert(c: &Checker, i: usize, table: &toml::Table) -> Result<InvariantSpec, InputError> {
    let key = |k: &str| format!("assert[{i}].{k}");
    for k in table.keys() {
        if !KEYS.contains(&k.as_str()) {
            return Err(unknown_name(c.file(), &key(k), "assert key", k, &KEYS));
        }
    }
    let string = |k: &str| -> Result<Option<&str>, InputError> {
        match table.get(k) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.as_str())),
            Some(other) => Err(c.err(&key(k), format!("value {other} has the wrong type; allowed: a string"))),
        }
    };
    let number = |k: &str| -> Result<Option<f64>, InputError> {
        match table.get(k) {
            None => Ok(None),
            Some(toml::Value::Float(f)) if f.is_finite() => Ok(Some(*f)),
            Some(toml::Value::Integer(n)) => Ok(Some(*n as f64)),
            Some(other) => Err(c.err(&key(k), format!("value {other} is not allowed; allowed: a finite number"))),
        }
    };
    let one_of = |k: &str, value: &str, allowed: &[&str]| -> Result<(), InputError> {
        if allowed.contains(&value) {
            Ok(())
        } else {
            Err(unknown_name(c.file(), &key(k), k, value, allowed))
        }
    };
    let kind_name =
        string("kind")?.ok_or_else(|| c.err(&key("kind"), format!("missing; allowed: {}", KINDS.join(", "))))?;
    one_of("kind", kind_name, &KINDS)?;
    let measure = match string("measure")? {
        None => Measure::SubjectPeak,
        Some(m) => {
            let names: Vec<&str> = Measure::ALL.iter().map(|m| m.name()).collect();
            one_of("measure", m, &names)?;
            Measure::ALL.into_iter().find(|x| x.name() == m).unwrap_or(Measure::SubjectPeak)
        }
    };
    let kind = match kind_name {
        "monotone" => {
            let d = string("direction")?.unwrap_or("increasing");
            one_of("direction", d, &["increasing", "decreasing"])?;
            InvariantKind::Monotone { measure, increasing: d == "increasing" }
        }
        "linear" => {
            let o = string("offset")?.unwrap_or("zero");
            one_of("offset", o, &["zero", "any"])?;
            InvariantKind::Linear { through_zero: o == "zero" }
        }
        "invariant" => InvariantKind::Invariant,
        _ => {
            let (min, max) = (number("min")?, number("max")?);
            if min.is_none() && max.is_none() {
                return Err(c.err(&key("max"), "a bounded assert needs `min`, `max` or both"));
            }
            if let (Some(lo), Some(hi)) = (min, max) {
                if lo > hi {
                    return Err(c.err(&key("min"), format!("value {lo} is above max {hi}")));
                }
            }
            InvariantKind::Bounded { measure, min, max }
        }
    };
    // Keys that mean nothing for this kind are mistakes, not silently ignored.
    let meaningful: &[&str] = match &kind {
        InvariantKind::Monotone { .. } => &["measure", "direction", "along"],
        InvariantKind::Linear { .. } => &["offset", "along"],
        InvariantKind::Invariant => &["along"],
        InvariantKind::Bounded { .. } => &["measure", "min", "max"],
    };
    for k in ["measure", "direction", "offset", "min", "max", "along"] {
        if table.contains_key(k) && !meaningful.contains(&k) {
            return Err(c.err(
                &key(k),
                format!("does not apply to a `{kind_name}` assert; it takes {}", meaningful.join(", ")),
            ));
        }
    }
    let axis_names: Vec<&str> = super::axes::filter_axes().filter(|a| a.is_numeric()).map(|a| a.name()).collect();
    let along = match string("along")? {
        None if matches!(kind, InvariantKind::Bounded { .. }) => None,
        None => return Err(c.err(&key("along"), format!("missing; allowed: {}", axis_names.join(", ")))),
        Some(a) => {
            one_of("along", a, &axis_names)?;
            super::axes::filter_axes().find(|x| x.name() == a)
        }
    };
    if matches!(kind, InvariantKind::Linear { .. }) && along != Some(Axis::LightIntensity) {
        return Err(
            c.err(&key("along"), "a linear assert runs along light_intensity (the only axis light scales with)")
        );
    }
    let tolerance = number("tolerance")?.unwrap_or(1e-3);
    if !(0.0..=1.0).contains(&tolerance) {
        return Err(c.err(&key("tolerance"), format!("value {tolerance} is out of range; allowed 0..=1 (relative)")));
    }
    let filter = match table.get("where") {
        None => Filter::default(),
        Some(toml::Value::Table(t)) => parse_filter(c, &key("where"), t)?,
        Some(other) => {
            return Err(
                c.err(&key("where"), format!("value {other} has the wrong type; allowed: a table of axis = values"))
            )
        }
    };
    let name = match string("name")? {
        Some(n) if !n.trim().is_empty() => n.to_string(),
        _ => format!("{kind_name} #{i}"),
    };
    Ok(InvariantSpec { name, kind, filter, along, tolerance })
}
