//! The audit's outputs: audit.md (a table fit for reading), audit.csv and audit.json.

use std::fmt::Write;
use std::path::Path;

use super::{ModelAudit, ENERGY_TOLERANCE, PARITY_FLOOR, RECIPROCITY_TOLERANCE};
use crate::error::Error;
use crate::fsutil::{write_atomic, write_json};

fn opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map(f).unwrap_or_else(|| "—".into())
}

fn expected(a: &ModelAudit) -> String {
    if !a.expected.is_brdf {
        return "not a BRDF".into();
    }
    let mut e = Vec::new();
    if a.expected.reciprocal {
        e.push("reciprocal");
    }
    if a.expected.energy_conserving {
        e.push("energy-conserving");
    }
    if e.is_empty() {
        "neither".into()
    } else {
        e.join(", ")
    }
}

pub fn markdown(audits: &[ModelAudit], adapter: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# BRDF audit\n\nAdapter: {adapter}. Parity: GPU f32 against the f64 twin; relative error with values below {PARITY_FLOOR:e} compared absolutely. Reciprocity tolerance {RECIPROCITY_TOLERANCE:e}; energy tolerance {ENERGY_TOLERANCE:e} above 1 (QMC). Energy: directional albedo of a white surface, physical BRDF (built-in and URP radiance divided by π).\n");
    let _ = writeln!(s, "| model | expected | parity (well) | parity (extreme) | env. direction (rad) | NaN/Inf/neg GPU | NaN/Inf/neg f64 | reciprocity | max albedo (worst at) | verdict |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for a in audits {
        let sanity = |n: usize, i: usize, g: usize| format!("{n}/{i}/{g}");
        let energy = a
            .energy
            .as_ref()
            .map(|e| {
                format!(
                    "{:.4} ({}°, s {}, m {}; {} samples, {})",
                    e.max_albedo, e.worst_view_deg, e.worst_smoothness, e.worst_metallic, e.samples, e.source
                )
            })
            .unwrap_or_else(|| "—".into());
        let verdict = if !a.failures.is_empty() {
            format!("**FAIL**: {}", a.failures.join("; "))
        } else if !a.findings.is_empty() {
            format!("ok; finding: {}", a.findings.join("; "))
        } else {
            "ok".into()
        };
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            a.key,
            expected(a),
            opt(a.parity_well.map(|p| p.max_rel), |v| format!("{v:.2e}")),
            opt(a.parity_extreme.map(|p| p.max_rel), |v| format!("{v:.2e}")),
            opt(a.env_direction_error, |v| format!("{v:.1e}")),
            sanity(a.gpu.nan, a.gpu.inf, a.gpu.negative),
            a.cpu.map(|c| sanity(c.nan, c.inf, c.negative)).unwrap_or_else(|| "no twin".into()),
            opt(a.reciprocity, |v| format!("{v:.2e}")),
            energy,
            verdict,
        );
    }
    s
}

pub fn csv(audits: &[ModelAudit]) -> String {
    let mut s = String::from("model,expected_reciprocal,expected_energy_conserving,is_brdf,parity_well_max_rel,parity_well_max_abs,parity_extreme_max_rel,parity_extreme_max_abs,env_direction_max_rad,gpu_nan,gpu_inf,gpu_negative,reciprocity,max_albedo,worst_view_deg,worst_smoothness,worst_metallic,failures,findings\n");
    let f = |v: Option<f64>| v.map(|x| format!("{x:e}")).unwrap_or_default();
    for a in audits {
        let e = a.energy.as_ref();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},\"{}\",\"{}\"",
            a.key,
            a.expected.reciprocal,
            a.expected.energy_conserving,
            a.expected.is_brdf,
            f(a.parity_well.map(|p| p.max_rel)),
            f(a.parity_well.map(|p| p.max_abs)),
            f(a.parity_extreme.map(|p| p.max_rel)),
            f(a.parity_extreme.map(|p| p.max_abs)),
            f(a.env_direction_error),
            a.gpu.nan,
            a.gpu.inf,
            a.gpu.negative,
            f(a.reciprocity),
            f(e.map(|e| e.max_albedo)),
            f(e.map(|e| e.worst_view_deg)),
            f(e.map(|e| e.worst_smoothness)),
            f(e.map(|e| e.worst_metallic)),
            a.failures.join("; ").replace('"', "'"),
            a.findings.join("; ").replace('"', "'"),
        );
    }
    s
}

pub fn write(dir: &Path, audits: &[ModelAudit], adapter: &str) -> Result<(), Error> {
    write_atomic(&dir.join("audit.md"), markdown(audits, adapter).as_bytes())?;
    write_atomic(&dir.join("audit.csv"), csv(audits).as_bytes())?;
    write_json(&dir.join("audit.json"), &AuditRecord::new(adapter, audits))
}

/// Version of `audit.json`.
pub const AUDIT_SCHEMA: u32 = 1;

/// `audit.json`: the adapter and every model's audit.
#[derive(serde::Serialize)]
pub struct AuditRecord<'a> {
    pub schema: u32,
    pub adapter: &'a str,
    pub models: &'a [ModelAudit],
}

impl<'a> AuditRecord<'a> {
    pub fn new(adapter: &'a str, models: &'a [ModelAudit]) -> Self {
        AuditRecord { schema: AUDIT_SCHEMA, adapter, models }
    }
}
