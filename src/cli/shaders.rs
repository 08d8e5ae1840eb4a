//! `shadematrix shaders`: every model, its pipelines, parameters and which sweep axes it reads.

use std::fmt::Write;

use crate::error::Error;
use crate::shading::Registry;

pub fn print(models: &super::ModelsArg) -> Result<(), Error> {
    super::print_out(&table(&*super::registry(models)?));
    Ok(())
}

pub fn table(registry: &Registry) -> String {
    let mut s = String::from("| shader | pipelines | per vertex | lights | reads | parameters | mapping from the sweep | source | summary |\n|---|---|---|---|---|---|---|---|---|\n");
    for m in registry.models() {
        let pipelines: Vec<&str> = m.pipelines.iter().map(|p| p.name()).collect();
        let mut reads = Vec::new();
        if m.reads.color {
            reads.push("colour");
        }
        if m.reads.metallic {
            reads.push("metallic");
        }
        if m.reads.smoothness {
            reads.push(if m.smoothness_gate.is_some() { "smoothness (with its highlights on)" } else { "smoothness" });
        }
        if m.reads.light {
            reads.push("light");
        }
        let params: Vec<String> =
            m.params.iter().map(|p| format!("{} = {} ({}..={}; {})", p.name, p.default, p.min, p.max, p.doc)).collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            m.name,
            pipelines.join(", "),
            if m.per_vertex { "yes" } else { "no" },
            if m.main_light_only { "main directional only (ForwardBase)" } else { "all" },
            reads.join(", "),
            if params.is_empty() { "—".into() } else { params.join("<br>") },
            m.mapping,
            m.source_path,
            m.summary
        );
    }
    s
}
