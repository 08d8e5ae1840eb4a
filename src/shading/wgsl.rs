//! WGSL composition. WGSL has no includes: a module is the shared files followed by one model
//! and one pass, concatenated in a fixed order.

use super::registry::ShaderModel;

const MATH: &str = include_str!("../../shaders/common/math.wgsl");
const CONVENTIONS: &str = include_str!("../../shaders/common/conventions.wgsl");
const BRDF_TERMS: &str = include_str!("../../shaders/common/brdf.wgsl");
const SCENE: &str = include_str!("../../shaders/pass/scene.wgsl");
const FORWARD: &str = include_str!("../../shaders/pass/forward.wgsl");
const BACKGROUND: &str = include_str!("../../shaders/pass/background.wgsl");
const PROBE: &str = include_str!("../../shaders/pass/brdf_probe.wgsl");

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PassKind {
    /// Forward lighting of one model, with vertex entry `vs_main` and fragment entry `fs_main`.
    Forward,
    /// The environment background (no model).
    Background,
    /// Compute entry `probe_main`: the model evaluated for given directions.
    BrdfProbe,
}

/// A standalone pass (no model, no scene) with the shared math before it.
pub fn with_math(pass: &str) -> String {
    format!("{MATH}\n{pass}")
}

/// The full WGSL source for a pass, with the model where the pass needs one.
pub fn compose(pass: PassKind, model: Option<&ShaderModel>) -> String {
    compose_mapped(pass, model).0
}

/// Where each file starts in a composed module: (first line, 1-based, of the file's text; path).
pub type LineMap = Vec<(usize, String)>;

/// Map a line of the composed module back to (file, line in that file).
pub fn locate(map: &LineMap, line: usize) -> (String, usize) {
    let (start, path) = map.iter().rev().find(|(start, _)| *start <= line).cloned().unwrap_or((1, "<composed>".into()));
    (path, line - start + 1)
}

pub fn compose_mapped(pass: PassKind, model: Option<&ShaderModel>) -> (String, LineMap) {
    let mut parts: Vec<(&str, &str)> = vec![
        ("shaders/common/math.wgsl", MATH),
        ("shaders/common/conventions.wgsl", CONVENTIONS),
        ("shaders/common/brdf.wgsl", BRDF_TERMS),
    ];
    match pass {
        PassKind::Forward => parts.push(("shaders/pass/scene.wgsl", SCENE)),
        PassKind::Background => parts.push(("shaders/pass/scene.wgsl", SCENE)),
        PassKind::BrdfProbe => {}
    }
    if let Some(m) = model {
        parts.push((&m.source_path, &m.wgsl));
    }
    parts.push(match pass {
        PassKind::Forward => ("shaders/pass/forward.wgsl", FORWARD),
        PassKind::Background => ("shaders/pass/background.wgsl", BACKGROUND),
        PassKind::BrdfProbe => ("shaders/pass/brdf_probe.wgsl", PROBE),
    });
    let mut out = String::new();
    let mut map = Vec::new();
    for (path, text) in parts {
        out.push_str(&format!("// ---- {path}\n"));
        map.push((out.lines().count() + 1, path.to_string()));
        out.push_str(text);
        if !text.ends_with('\n') {
            out.push('\n');
        }
    }
    (out, map)
}
