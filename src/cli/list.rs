//! `shadematrix list`: the expanded cells, twins, pruned cells and each composition's passes.

use std::fmt::Write;
use std::path::Path;

use super::{load_matrix, print_out, registry_for, ModelsArg};
use crate::cells::expand;
use crate::error::Error;
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
    }
    let rendered = exp.cells.iter().filter(|c| c.twin_of.is_none()).count();
    let _ = writeln!(
        out,
        "{} cells, {} rendered, {} twins, {} pruned, {} filtered out",
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
