//! Data flows one way: matrix → cells → plan → render → images → metrics → report. Every
//! top-level module of `src/` has a place in `STAGES`, and may import (`crate::…`) only from
//! itself and the modules before it. A new module must be placed here; an import against the
//! flow fails this test with the file, the line and both modules.

use std::path::{Path, PathBuf};

/// The order of the stages; the vocabulary every stage shares comes first.
const STAGES: &[&str] = &[
    // Shared vocabulary: errors, colour math, atomic files, input parsing, engine conventions,
    // the device, the shading models.
    "error",
    "color",
    "fsutil",
    "input",
    // The verified store every cache goes through (cells, truths, bakes).
    "store",
    "pipelines",
    "adapter",
    "gpu",
    "shading",
    // matrix (and the scenes it names) → cells → plan → render → images → metrics.
    "declarations",
    "geometry",
    "environment",
    "materials",
    "cells",
    "plan",
    "render",
    "images",
    "compare",
    // Records of cells and runs; the run that streams cells through the stages; what reads the
    // records afterwards; the property audit; the command line.
    "record",
    "run",
    "report",
    "audit",
    // Carrying a material's look across pipelines: renders, compares and reports its fits.
    "remap",
    "cli",
];

/// The top-level module a source file belongs to (`src/run/encode.rs` → `run`).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    let first = rel.components().next()?.as_os_str().to_string_lossy().to_string();
    Some(first.trim_end_matches(".rs").to_string())
}

/// Top-level modules named after `crate::` on each line, with 1-based line numbers; handles
/// `use crate::{a::b, c}` groups spanning lines.
fn crate_imports(text: &str) -> Vec<(usize, String)> {
    let code: Vec<String> = text.lines().map(|l| l.split("//").next().unwrap_or("").to_string()).collect();
    let joined = code.join("\n");
    let bytes = joined.as_bytes();
    let line_at = |pos: usize| joined[..pos].matches('\n').count() + 1;
    let ident = |from: usize| -> String {
        joined[from..].chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect()
    };
    let mut out = Vec::new();
    let mut search = 0;
    while let Some(found) = joined[search..].find("crate::") {
        let at = search + found;
        search = at + "crate::".len();
        // `shadematrix::crate::` cannot occur; skip identifiers that merely end in "crate".
        if at > 0 && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_') {
            continue;
        }
        if bytes.get(search) == Some(&b'{') {
            // Names at brace depth 1 are top-level modules (or items of the crate root).
            let (mut depth, mut i, mut expect_name) = (0usize, search, true);
            while i < bytes.len() {
                match bytes[i] {
                    b'{' => {
                        depth += 1;
                        expect_name = depth == 1;
                    }
                    b'}' => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    b',' if depth == 1 => expect_name = true,
                    c if expect_name && depth == 1 && (c.is_ascii_alphabetic() || c == b'_') => {
                        out.push((line_at(i), ident(i)));
                        expect_name = false;
                    }
                    _ => {}
                }
                i += 1;
            }
        } else {
            out.push((line_at(search), ident(search)));
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()) {
        let p = entry.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// Every import against the flow under `src`, and every module without a stage.
fn violations(src: &Path) -> Vec<String> {
    let rank = |m: &str| STAGES.iter().position(|s| *s == m);
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let mut bad = Vec::new();
    for file in files {
        let Some(module) = module_of(src, &file) else { continue };
        if module == "lib" || module == "main" {
            continue;
        }
        let Some(own) = rank(&module) else {
            bad.push(format!("{}: module `{module}` has no place in STAGES", file.display()));
            continue;
        };
        let text = std::fs::read_to_string(&file).unwrap();
        for (line, imported) in crate_imports(&text) {
            match rank(&imported) {
                Some(r) if r > own => bad.push(format!(
                    "{}:{line}: `{module}` imports `{imported}`, a later stage (order: {})",
                    file.display(),
                    STAGES.join(" → ")
                )),
                // Items of the crate root (re-exports in lib.rs) are the vocabulary's.
                _ => {}
            }
        }
    }
    bad
}

#[test]
fn no_import_points_back_up_the_flow() {
    let _timer = crate::common::timed!();
    let src = crate::common::repo().join("src");
    let bad = violations(&src);
    assert!(bad.is_empty(), "imports against the data flow:\n{}", bad.join("\n"));
    // Every top-level module has a stage.
    for entry in std::fs::read_dir(&src).unwrap().filter_map(|e| e.ok()) {
        let name = entry.file_name().to_string_lossy().trim_end_matches(".rs").to_string();
        assert!(name == "lib" || name == "main" || STAGES.contains(&name.as_str()), "`{name}` has no stage");
    }
}

#[test]
fn a_back_arrow_is_caught() {
    let _timer = crate::common::timed!();
    // A copy of two modules, one of which reaches forward: the check must name it.
    let tmp = tempfile::tempdir().unwrap();
    let src = tmp.path().join("src");
    std::fs::create_dir_all(src.join("render")).unwrap();
    std::fs::create_dir_all(src.join("report")).unwrap();
    std::fs::write(src.join("report/mod.rs"), "use crate::render::Renderer;\n").unwrap();
    std::fs::write(
        src.join("render/mod.rs"),
        "use crate::{\n    gpu::GpuContext,\n    report::build, // against the flow\n};\n",
    )
    .unwrap();
    let bad = violations(&src);
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(bad[0].contains("render/mod.rs:3: `render` imports `report`"), "{}", bad[0]);
    // Single-path imports and inline paths count too.
    std::fs::write(src.join("render/mod.rs"), "fn f() { crate::report::build(); }\n").unwrap();
    assert_eq!(violations(&src).len(), 1);
}

#[test]
fn grouped_imports_are_read() {
    let _timer = crate::common::timed!();
    let text = "use crate::{error::Error, gpu::{GpuContext, readback}, record};\nlet x = crate::cells::expand(m);\n";
    let names: Vec<String> = crate_imports(text).into_iter().map(|(_, m)| m).collect();
    assert_eq!(names, vec!["error", "gpu", "record", "cells"]);
}

/// The source files a `crate::a::b::c` path can name, the most specific first.
fn files_of_path(src: &Path, segments: &[String]) -> Option<PathBuf> {
    (1..=segments.len()).rev().find_map(|n| {
        let base = segments[..n].iter().fold(src.to_path_buf(), |p, s| p.join(s));
        [base.with_extension("rs"), base.join("mod.rs")].into_iter().find(|f| f.is_file())
    })
}

/// Whether a source file reaches the device: it names wgpu, or imports the GPU stages.
fn gpu_bound(file: &Path, src: &Path) -> bool {
    let rel = file.strip_prefix(src).unwrap();
    if rel.starts_with("gpu") || rel.starts_with("render") {
        return true;
    }
    let text = std::fs::read_to_string(file).unwrap();
    let code: String = text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n");
    ["wgpu", "crate::gpu", "crate::render", "super::gpu"].iter().any(|n| code.contains(n))
}

/// Files of `record/` that import a file bound to the device: everything that reads `cell.json`
/// would depend on wgpu.
fn record_gpu_imports(src: &Path) -> Vec<String> {
    let mut files = Vec::new();
    rust_files(&src.join("record"), &mut files);
    files.sort();
    let mut bad = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for rest in code.split("crate::").skip(1) {
                let path: String =
                    rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == ':').collect();
                let segments: Vec<String> = path.split("::").filter(|s| !s.is_empty()).map(String::from).collect();
                if let Some(target) = files_of_path(src, &segments) {
                    if gpu_bound(&target, src) {
                        bad.push(format!("{}:{}: imports {} ({})", file.display(), n + 1, path, target.display()));
                    }
                }
            }
        }
    }
    bad
}

#[test]
fn records_import_no_gpu_stage() {
    let _timer = crate::common::timed!();
    let src = crate::common::repo().join("src");
    let bad = record_gpu_imports(&src);
    assert!(bad.is_empty(), "record/ reaches the device:\n{}", bad.join("\n"));
    // The check can fail: a record that names a renderer type.
    let tmp = tempfile::tempdir().unwrap();
    let fake = tmp.path().join("src");
    std::fs::create_dir_all(fake.join("record")).unwrap();
    std::fs::create_dir_all(fake.join("render")).unwrap();
    std::fs::write(fake.join("render/mod.rs"), "pub struct ShadowMapUse;\n").unwrap();
    std::fs::write(fake.join("record/cell.rs"), "pub x: Vec<crate::render::ShadowMapUse>,\n").unwrap();
    assert_eq!(record_gpu_imports(&fake).len(), 1);
}

/// A source file's module path (`src/render/renderer.rs` → `["render", "renderer"]`, a `mod.rs`
/// its folder's).
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel.components().map(|c| c.as_os_str().to_string_lossy().to_string()).collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// Which files each file of `src` names through `crate::`, `super::` or `self::` paths (a
/// `mod.rs`'s declarations and re-exports of its children are its facade, not edges).
fn file_edges(src: &Path) -> std::collections::BTreeMap<Vec<String>, std::collections::BTreeSet<Vec<String>>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: std::collections::BTreeSet<Vec<String>> = files.iter().map(|f| module_path(src, f)).collect();
    let resolve = |segments: &[String]| -> Option<Vec<String>> {
        (1..=segments.len()).rev().map(|n| segments[..n].to_vec()).find(|m| modules.contains(m))
    };
    let mut edges = std::collections::BTreeMap::new();
    for file in &files {
        let me = module_path(src, file);
        let is_mod = file.ends_with("mod.rs");
        let parent: Vec<String> =
            if is_mod { me[..me.len().saturating_sub(1)].to_vec() } else { me[..me.len() - 1].to_vec() };
        let text = std::fs::read_to_string(file).unwrap();
        let code: String = text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n");
        let mut out = std::collections::BTreeSet::new();
        for (prefix, base) in [("crate::", Vec::new()), ("super::", parent.clone()), ("self::", me.clone())] {
            for (at, _) in code.match_indices(prefix) {
                if at > 0 && (code.as_bytes()[at - 1].is_ascii_alphanumeric() || code.as_bytes()[at - 1] == b'_') {
                    continue;
                }
                let path: String = code[at + prefix.len()..]
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == ':')
                    .collect();
                let mut segments = base.clone();
                segments.extend(path.split("::").filter(|s| !s.is_empty() && *s != "super").map(String::from));
                if let Some(target) = resolve(&segments).filter(|t| *t != me && !t.is_empty()) {
                    out.insert(target);
                }
            }
        }
        edges.insert(me, out);
    }
    edges
}

/// Groups of files inside one top-level module that import each other in a circle.
fn file_circles(src: &Path) -> Vec<Vec<String>> {
    let edges = file_edges(src);
    let reaches = |from: &Vec<String>, to: &Vec<String>| -> bool {
        let mut seen = std::collections::BTreeSet::new();
        let mut stack = vec![from.clone()];
        while let Some(m) = stack.pop() {
            for next in edges.get(&m).into_iter().flatten() {
                if next[0] != from[0] {
                    continue;
                }
                if next == to {
                    return true;
                }
                if seen.insert(next.clone()) {
                    stack.push(next.clone());
                }
            }
        }
        false
    };
    let mut circles: Vec<Vec<String>> = Vec::new();
    for (a, targets) in &edges {
        for b in targets.iter().filter(|b| b[0] == a[0] && b > &a) {
            if reaches(b, a) {
                circles.push(vec![a.join("::"), b.join("::")]);
            }
        }
    }
    circles
}

#[test]
fn no_file_level_circles_inside_a_module() {
    let _timer = crate::common::timed!();
    let circles = file_circles(&crate::common::repo().join("src"));
    assert!(circles.is_empty(), "files that import each other (through any path): {circles:?}");
    // The check can fail: two files of one module that import each other.
    let tmp = tempfile::tempdir().unwrap();
    let src = tmp.path().join("src");
    std::fs::create_dir_all(src.join("spec")).unwrap();
    std::fs::write(src.join("spec/mod.rs"), "pub mod a;\npub mod b;\n").unwrap();
    std::fs::write(src.join("spec/a.rs"), "use super::b::B;\npub struct A;\n").unwrap();
    std::fs::write(src.join("spec/b.rs"), "pub struct B;\nfn f() { crate::spec::a::A; }\n").unwrap();
    assert_eq!(file_circles(&src), vec![vec!["spec::a".to_string(), "spec::b".to_string()]]);
}
