//! The matrix's `[[assert]]` invariants (`declarations::asserts`), checked over a finished run from its
//! records and EXRs: tables/invariants.{md,csv} with every assert, and the results `check` puts in
//! its JUnit. A group is the cells an assert covers that differ only in its `along` axis; an assert
//! that covers no cells, or no group with two values, fails — an invariant that checks nothing
//! would pass unseen.

use std::collections::BTreeMap;
use std::fmt::Write;

use serde::Serialize;

use super::run_data::RunData;
use crate::declarations::asserts::{InvariantKind, InvariantSpec, Measure};
use crate::declarations::matrix::{Axis, Filter, FilterValue};
use crate::error::Error;
use crate::fsutil::write_atomic;
use crate::images::encode::read_exr;
use crate::record::CellRecord;

/// Failing groups named in a result, at most (the count is always whole).
const SHOWN_FAILURES: usize = 8;

#[derive(Debug, Clone, Serialize)]
pub struct InvariantResult {
    pub name: String,
    pub kind: &'static str,
    /// What was checked, in words.
    pub statement: String,
    pub cells: usize,
    pub groups: usize,
    pub failed_groups: usize,
    /// The largest violation, relative (the measure's step against it for `monotone`, the image's
    /// relative L1 error for `linear` and `invariant`, the excess over the bound for `bounded`).
    pub worst: Option<f64>,
    /// The first failing groups, each with what broke.
    pub failures: Vec<String>,
    /// Why the assert could not be checked at all (no cells, no group with two values).
    pub unchecked: Option<String>,
}

impl InvariantResult {
    pub fn passed(&self) -> bool {
        self.failed_groups == 0 && self.unchecked.is_none()
    }

    /// What a failure says, on one line.
    pub fn message(&self) -> Option<String> {
        if let Some(why) = &self.unchecked {
            return Some(why.clone());
        }
        (self.failed_groups > 0)
            .then(|| format!("{} of {} groups fail: {}", self.failed_groups, self.groups, self.failures.join("; ")))
    }
}

/// A cell's value on a filter axis, from its record.
fn record_value(r: &CellRecord, axis: Axis) -> FilterValue {
    r.coords.filter_value(axis)
}

fn same(a: &FilterValue, b: &FilterValue) -> bool {
    match (a, b) {
        (FilterValue::Number(x), FilterValue::Number(y)) => (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0),
        _ => a == b,
    }
}

fn matches(r: &CellRecord, f: &Filter) -> bool {
    f.terms.iter().all(|(axis, values)| {
        let v = record_value(r, *axis);
        values.iter().any(|w| same(&v, w))
    })
}

fn numeric(r: &CellRecord, axis: Axis) -> f64 {
    match record_value(r, axis) {
        FilterValue::Number(x) => x,
        _ => f64::NAN,
    }
}

fn measure(r: &CellRecord, m: Measure) -> Option<f64> {
    match m {
        Measure::SubjectPeak => r.stats.subject_max_luminance,
        Measure::SubjectMean => r.stats.subject_mean_luminance,
        Measure::Peak => Some(r.stats.max_luminance),
        Measure::MaxValue => Some(r.stats.max_value),
    }
}

/// The cells of a group differ only in `along`: the key is every other axis, the model
/// parameters included.
fn group_key(r: &CellRecord, along: Axis) -> String {
    let mut key = String::new();
    for row in crate::declarations::axes::AXES.iter().filter(|row| row.axis != along) {
        let _ = write!(key, "{}={} ", row.name, r.coords.exact(row.name));
    }
    key.trim_end().to_string()
}

/// A group named by its first cell, and the axis that varies within it.
fn group_label(r: &CellRecord, along: Axis) -> String {
    format!("{} ({} varies)", r.id.0, along.name())
}

/// The RGB values of a cell's EXR, as written.
fn image(run: &RunData, r: &CellRecord) -> Result<Vec<f64>, Error> {
    let (_, _, rgba) = read_exr(&run.cell_dir(&r.id.0).join(&r.image.exr))?;
    Ok(rgba.chunks_exact(4).flat_map(|p| p[..3].iter().map(|&v| v as f64)).collect())
}

/// Σ|a − b| / max(Σ|a|, Σ|b|): 0 for equal images, NaN when either holds a non-finite value.
fn relative_l1(a: &[f64], b: &[f64]) -> f64 {
    let (mut diff, mut na, mut nb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        diff += (x - y).abs();
        na += x.abs();
        nb += y.abs();
    }
    if diff == 0.0 {
        return 0.0;
    }
    diff / na.max(nb).max(f64::MIN_POSITIVE)
}

pub fn evaluate(run: &RunData) -> Result<Vec<InvariantResult>, Error> {
    run.run.matrix.asserts.iter().map(|a| evaluate_one(run, a)).collect()
}

fn evaluate_one(run: &RunData, a: &InvariantSpec) -> Result<InvariantResult, Error> {
    let cells: Vec<&CellRecord> = run.cells.iter().filter(|r| matches(r, &a.filter)).collect();
    let mut result = InvariantResult {
        name: a.name.clone(),
        kind: a.kind.name(),
        statement: statement(a),
        cells: cells.len(),
        groups: 0,
        failed_groups: 0,
        worst: None,
        failures: Vec::new(),
        unchecked: None,
    };
    if cells.is_empty() {
        result.unchecked = Some("no cell of the run matches its `where`".into());
        return Ok(result);
    }
    let fail = |result: &mut InvariantResult, what: String| {
        result.failed_groups += 1;
        if result.failures.len() < SHOWN_FAILURES {
            result.failures.push(what);
        }
    };
    let worst = |result: &mut InvariantResult, e: f64| {
        result.worst = Some(match result.worst {
            Some(w) if e <= w || w.is_nan() => w,
            _ => e,
        });
    };
    let Some(along) = a.along else {
        // bounded: every cell alone
        let InvariantKind::Bounded { measure: m, min, max } = a.kind else { unreachable!("only bounded has no axis") };
        result.groups = cells.len();
        for r in cells {
            let Some(v) = measure(r, m) else {
                fail(&mut result, format!("{}: {} missing (the subject is not visible)", r.id.0, m.name()));
                continue;
            };
            let over = max.map_or(0.0, |hi| (v - hi) / hi.abs().max(f64::MIN_POSITIVE));
            let under = min.map_or(0.0, |lo| (lo - v) / lo.abs().max(f64::MIN_POSITIVE));
            let excess = over.max(under);
            worst(&mut result, excess.max(0.0));
            if excess > a.tolerance || v.is_nan() {
                fail(&mut result, format!("{}: {} = {v:.6e}", r.id.0, m.name()));
            }
        }
        return Ok(result);
    };
    let mut groups: BTreeMap<String, Vec<&CellRecord>> = BTreeMap::new();
    for r in cells {
        groups.entry(group_key(r, along)).or_default().push(r);
    }
    for members in groups.values_mut() {
        members.sort_by(|x, y| numeric(x, along).total_cmp(&numeric(y, along)));
        if members.len() < 2 {
            continue;
        }
        result.groups += 1;
        let label = group_label(members[0], along);
        let at = |r: &CellRecord| format!("{} = {}", along.name(), numeric(r, along));
        match &a.kind {
            InvariantKind::Monotone { measure: m, increasing } => {
                let mut broke = None;
                for pair in members.windows(2) {
                    let (Some(x), Some(y)) = (measure(pair[0], *m), measure(pair[1], *m)) else {
                        broke = Some(format!("{label}: {} missing (the subject is not visible)", m.name()));
                        break;
                    };
                    let step = if *increasing { y - x } else { x - y };
                    let drop = -step / x.abs().max(y.abs()).max(f64::MIN_POSITIVE);
                    worst(&mut result, drop.max(0.0));
                    if drop > a.tolerance || drop.is_nan() {
                        broke.get_or_insert(format!(
                            "{label}: {} {x:.6e} at {} → {y:.6e} at {}",
                            m.name(),
                            at(pair[0]),
                            at(pair[1])
                        ));
                    }
                }
                if let Some(why) = broke {
                    fail(&mut result, why);
                }
            }
            InvariantKind::Linear { through_zero } => {
                let images = members.iter().map(|r| image(run, r)).collect::<Result<Vec<_>, _>>()?;
                let values: Vec<f64> = members.iter().map(|r| numeric(r, along)).collect();
                let mut broke = None;
                let base = values.iter().rposition(|v| *v != 0.0).unwrap_or(0);
                for (i, img) in images.iter().enumerate() {
                    let predicted: Vec<f64> = if *through_zero {
                        if i == base {
                            continue;
                        }
                        let k = values[i] / values[base];
                        images[base].iter().map(|v| v * k).collect()
                    } else {
                        if i < 2 {
                            continue;
                        }
                        let t = (values[i] - values[0]) / (values[1] - values[0]);
                        images[0].iter().zip(&images[1]).map(|(a, b)| a + t * (b - a)).collect()
                    };
                    let e = relative_l1(img, &predicted);
                    worst(&mut result, e);
                    if e > a.tolerance || e.is_nan() {
                        broke.get_or_insert(format!("{label}: relative L1 error {e:.3e} at {}", at(members[i])));
                    }
                }
                if let Some(why) = broke {
                    fail(&mut result, why);
                }
            }
            InvariantKind::Invariant => {
                let first = image(run, members[0])?;
                let mut broke = None;
                for r in &members[1..] {
                    let e = relative_l1(&image(run, r)?, &first);
                    worst(&mut result, e);
                    if e > a.tolerance || e.is_nan() {
                        broke.get_or_insert(format!(
                            "{label}: relative L1 difference {e:.3e} between {} and {}",
                            at(members[0]),
                            at(r)
                        ));
                    }
                }
                if let Some(why) = broke {
                    fail(&mut result, why);
                }
            }
            InvariantKind::Bounded { .. } => unreachable!("bounded has no axis"),
        }
    }
    if result.groups == 0 {
        result.unchecked = Some(format!("no group of its {} cells has two values of {}", result.cells, along.name()));
    }
    Ok(result)
}

/// The assert in words, for tables and JUnit.
fn statement(a: &InvariantSpec) -> String {
    let along = a.along.map(|x| x.name()).unwrap_or("");
    let tol = a.tolerance;
    match &a.kind {
        InvariantKind::Monotone { measure, increasing } => format!(
            "{} {} with {along} (tolerance {tol})",
            measure.name(),
            if *increasing { "does not fall" } else { "does not rise" }
        ),
        InvariantKind::Linear { through_zero: true } => {
            format!("the image scales with {along}: I(v) = v/v₀·I(v₀) (relative L1 ≤ {tol})")
        }
        InvariantKind::Linear { through_zero: false } => {
            format!("the image is affine in {along}: I(v) = I(v₀) + t·(I(v₁) − I(v₀)) (relative L1 ≤ {tol})")
        }
        InvariantKind::Invariant => format!("the image does not change with {along} (relative L1 ≤ {tol})"),
        InvariantKind::Bounded { measure, min, max } => {
            let lo = min.map_or("−∞".to_string(), |v| format!("{v}"));
            let hi = max.map_or("∞".to_string(), |v| format!("{v}"));
            format!("{} within [{lo}, {hi}] (relative tolerance {tol})", measure.name())
        }
    }
}

/// tables/invariants.{md,csv}: every assert of the run's matrix, passed or failed, with its worst
/// violation. Nothing is written when the matrix declares none.
pub fn write(run: &RunData) -> Result<Vec<InvariantResult>, Error> {
    let results = evaluate(run)?;
    if results.is_empty() {
        return Ok(results);
    }
    let mut md = format!(
        "# Invariants\n\nRun `{}`, {} cells on {}: the matrix's `[[assert]]` tables, checked over its records and \
         EXRs. A group is the cells an assert covers that differ only in its axis.\n\n\
         | assert | kind | statement | cells | groups | result | worst |\n|---|---|---|---|---|---|---|\n",
        run.run.matrix.name,
        run.cells.len(),
        run.run.adapter.name
    );
    let mut csv = String::from("name,kind,cells,groups,failed_groups,worst,result\n");
    for r in &results {
        let verdict = match r.message() {
            None => "pass".to_string(),
            Some(m) => format!("**fail**: {m}"),
        };
        let worst = r.worst.map_or("—".to_string(), |w| format!("{w:.3e}"));
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {worst} |",
            r.name.replace('|', "/"),
            r.kind,
            r.statement,
            r.cells,
            r.groups,
            verdict.replace('|', "/")
        );
        let _ = writeln!(
            csv,
            "\"{}\",{},{},{},{},{},{}",
            r.name.replace('"', "'"),
            r.kind,
            r.cells,
            r.groups,
            r.failed_groups,
            r.worst.map_or(String::new(), |w| format!("{w:e}")),
            if r.passed() { "pass" } else { "fail" }
        );
    }
    write_atomic(&run.dir.join("tables/invariants.md"), md.as_bytes())?;
    write_atomic(&run.dir.join("tables/invariants.csv"), csv.as_bytes())?;
    Ok(results)
}
