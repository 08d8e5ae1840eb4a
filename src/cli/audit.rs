//! `shadematrix audit`: the BRDF property audit of every model (or one), written and printed.

use std::path::PathBuf;

use super::{print_out, registry, ModelsArg};
use crate::audit;
use crate::error::Error;
use crate::input::names::unknown_name;

pub fn audit(shader: Option<&str>, json: bool, out: Option<PathBuf>, models: &ModelsArg) -> Result<(), Error> {
    let registry = registry(models)?;
    if let Some(name) = shader {
        let names = registry.names();
        if !names.contains(&name) {
            return Err(unknown_name("command line", "--shader", "shader", name, &names).into());
        }
    }
    let gpu = crate::gpu::GpuContext::new()?;
    let audits = audit::audit_all(&gpu, &registry, shader)?;
    let dir = out.unwrap_or_else(|| {
        PathBuf::from("results").join(format!("audit-{}", chrono::Local::now().format("%Y%m%d-%H%M%S")))
    });
    audit::report::write(&dir, &audits, &gpu.record.name)?;
    let conditioning = audit::conditioning::condition_all(&gpu, &registry, shader)?;
    audit::conditioning::write(&dir, &conditioning, &gpu.record.name)?;
    let text = if json {
        serde_json::to_string_pretty(&audit::report::AuditRecord::new(&gpu.record.name, &audits)).unwrap_or_default()
    } else {
        audit::report::markdown(&audits, &gpu.record.name)
    };
    print_out(&text);
    if !json {
        print_out(&audit::conditioning::markdown(&conditioning, &gpu.record.name));
    }
    eprintln!("audit written to {} (conditioning: tables/conditioning.md, plots/conditioning_*.svg)", dir.display());
    let failed: Vec<&str> = audits.iter().filter(|a| !a.failures.is_empty()).map(|a| a.key.as_str()).collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(Error::CheckFailed(format!("audit failed for {}", failed.join(", "))))
    }
}

/// `shadematrix convergence`: the convergence studies, written and printed.
pub fn convergence(out: Option<PathBuf>, quick: bool) -> Result<(), Error> {
    let settings = if quick { audit::convergence::Settings::quick() } else { audit::convergence::Settings::full() };
    let machine = cpu_description();
    let curves = audit::convergence::study(&settings)?;
    let dir = out.unwrap_or_else(|| {
        PathBuf::from("results").join(format!("convergence-{}", chrono::Local::now().format("%Y%m%d-%H%M%S")))
    });
    audit::convergence::write(&dir, &curves, &machine)?;
    print_out(&audit::convergence::markdown(&curves, &machine));
    eprintln!("convergence written to {} (tables/convergence.md, plots/convergence_*.svg)", dir.display());
    Ok(())
}

/// The CPU the studies ran on, for the report (timings compare only on one machine).
fn cpu_description() -> String {
    let cpuinfo = std::path::Path::new("/proc/cpuinfo");
    let model = crate::input::read::read_text(cpuinfo, crate::input::read::TEXT)
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "an unnamed CPU".into());
    format!("{model}, {} threads", rayon::current_num_threads())
}
