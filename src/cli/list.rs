//! `shadematrix list`: the expanded cells, twins, pruned cells and each composition's passes.

use std::fmt::Write;
use std::path::Path;

use super::{load_matrix, print_out, registry_for, ModelsArg};
use crate::cells::expand;
use crate::error::Error;
use crate::pipelines::Pipeline;
use crate::plan::FramePlan;
use crate::spec::matrix::Matrix;

pub fn list(matrix: Option<&Path>, models: &ModelsArg) -> Result<(), Error> {
    print_out(&text(&load_matrix(matrix, registry_for(models, matrix)?)?));
    Ok(())
}

pub fn text(m: &Matrix) -> String {
    let mut out = String::new();
    let exp = expand(m);
    let _ = writeln!(out, "matrix `{}` ({}), sha256 {}", m.name, m.origin, &m.hash[..12]);
    for scene in &m.compositions {
        let plan = FramePlan::for_scene(scene);
        let _ = writeln!(out, "composition {}: passes {}", scene.name, plan.passes.join(" → "));
        for (what, why) in &plan.left_out {
            let _ = writeln!(out, "  left out: {what}: {why}");
        }
        if let Some(key) = scene.key_light().map(|k| &scene.lights[k]) {
            for p in &m.pipelines {
                let _ = writeln!(out, "  key light in {}: {}", p.name(), p.intensity_unit(key.emitter()));
            }
        }
        if m.pipelines.contains(&Pipeline::Hdrp) {
            let x = &scene.hdrp.exposure;
            let _ = writeln!(
                out,
                "  HDRP exposure: {:?}, metering {:?}, limits {}..{} EV100, compensation {}",
                x.mode, x.metering, x.limit_min, x.limit_max, x.compensation
            );
        }
    }
    for p in &m.pipelines {
        let _ = writeln!(out, "pipeline {}: tonemap {}", p.name(), m.tonemap_for(*p).name());
    }
    if m.pipelines.contains(&Pipeline::Hdrp) {
        let _ = writeln!(out, "left out: {}", crate::pipelines::volume::LEFT_OUT_EFFECTS);
    }
    let rendered = exp.cells.iter().filter(|c| c.twin_of.is_none()).count();
    let _ = writeln!(
        out,
        "{} cells before twins, {} to render after twins ({} twins); {} pruned, {} filtered out",
        exp.cells.len(),
        rendered,
        exp.cells.len() - rendered,
        exp.pruned.len(),
        exp.filtered_out
    );
    for c in &exp.cells {
        let _ = match &c.twin_of {
            None => writeln!(out, "  {}", c.id),
            Some(t) => writeln!(out, "  {}  = {} ({} ignores the differing axes)", c.id, t, c.shader),
        };
    }
    for p in &exp.pruned {
        let _ = writeln!(out, "  pruned {}: {}", p.description, p.reason);
    }
    out
}
