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
