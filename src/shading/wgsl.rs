//! WGSL composition. WGSL has no includes: a module is the shared files followed by one model
//! and one pass, concatenated in a fixed order.

use super::registry::ShaderModel;

const MATH: &str = include_str!("../../shaders/common/math.wgsl");
const CONVENTIONS: &str = include_str!("../../shaders/common/conventions.wgsl");

/// The pipelines' ids as named WGSL constants (`PIPELINE_BUILTIN`, `PIPELINE_URP`, `PIPELINE_HDRP`),
/// generated from `Pipeline` so the shaders compare `PIPELINE` with names, never with `2u`.
pub fn pipeline_ids() -> String {
    let pipelines = crate::pipelines::Pipeline::ALL
        .iter()
        .map(|p| format!("const PIPELINE_{}: u32 = {}u;\n", p.name().to_uppercase(), p.shader_id()));
    // The surface types likewise (`SURFACE_OPAQUE` …), for forward.wgsl's `SURFACE`.
    let surfaces = crate::pipelines::surface::SurfaceType::ALL
        .iter()
        .map(|s| format!("const SURFACE_{}: u32 = {}u;\n", s.name().to_uppercase(), s.shader_id()));
    // And the term bits (`TERM_DIRECT_DIFFUSE` …), for conventions.wgsl's `TERMS`.
    let terms =
        crate::pipelines::terms::WGSL_BITS.iter().map(|(name, bits)| format!("const TERM_{name}: u32 = {bits}u;\n"));
    pipelines.chain(surfaces).chain(terms).collect()
}

/// What a model may leave out, with the value the passes then read: 1 − oneMinusReflectivity,
/// which only built-in Transparent's output alpha reads (models without one reflect nothing
/// there: the classic models have no such surface and are not drawn with it).
const DEFAULT_MODEL_HOOKS: &str = "fn model_reflectivity(s: Surface) -> f32 {\n    return 0.0;\n}\n";

/// The height map's scale a model reads from its parameters (0: no parallax), for models without
/// a Height Map input.
const DEFAULT_HEIGHT_HOOK: &str =
    "fn model_height_scale(params0: vec4<f32>, params1: vec4<f32>) -> f32 {\n    return 0.0;\n}\n";

/// Secondary maps for a model without them (Standard has them, registry::DETAIL).
const DEFAULT_DETAIL_HOOK: &str =
    "fn model_detail(params0: vec4<f32>, params1: vec4<f32>, params2: vec4<f32>) -> f32 {\n    return 0.0;\n}\n";

/// Whether a model reads the ambient at −N (HDRP Lit's transmission does): none without the hook,
/// so the pass evaluates it only where a model asks.
const DEFAULT_BACK_AMBIENT_HOOK: &str = "fn model_back_ambient(s: Surface) -> bool {\n    return false;\n}\n";

/// The albedos HDRP's ambient-occlusion multi-bounce reads (GTAOMultiBounce of the indirect
/// diffuse and of the specular occlusion, Lit.hlsl PostEvaluateBSDF: bsdfData.diffuseColor and
/// fresnel0), for a model without a BSDF data of its own: the metallic workflow's.
const DEFAULT_OCCLUSION_HOOK: &str = "fn model_occlusion_albedo(s: Surface) -> vec3<f32> {\n    return s.base_color * (1.0 - s.metallic);\n}\nfn model_occlusion_fresnel0(s: Surface) -> vec3<f32> {\n    return mix(vec3<f32>(0.04), s.base_color, s.metallic);\n}\n";

/// Rect lights for a model without a BSDF for them: nothing (the plan leaves them out,
/// plan::lights::area_left_out).
const DEFAULT_AREA_HOOK: &str = "fn model_rect(s: Surface, n: vec3<f32>, v: vec3<f32>, q: array<vec3<f32>, 4>) -> vec3<f32> {\n    return vec3<f32>(0.0);\n}\n";

/// The shared math, the pipeline ids, the pipeline conventions and the shared BRDF terms: what
/// every lighting module (and a test kernel of its terms) starts with.
pub fn common() -> String {
    [MATH, &pipeline_ids(), CONVENTIONS, BRDF_TERMS, AREA].join("\n")
}

/// Where the generated constants stand in a composed module's line map.
const PIPELINE_IDS_PATH: &str = "<generated from pipelines::Pipeline: pipeline ids>";
const BRDF_TERMS: &str = include_str!("../../shaders/common/brdf.wgsl");
/// Area lights' polygon integrals and LTC lookups (shading::ltc's twin).
const AREA: &str = include_str!("../../shaders/common/area.wgsl");
const SCENE: &str = include_str!("../../shaders/pass/scene.wgsl");
const FORWARD: &str = include_str!("../../shaders/pass/forward.wgsl");
const SHADOW_FILTERS: &str = include_str!("../../shaders/pass/shadow_filters.wgsl");
/// HDRP's tiled light binning and the deferred pass's reading of it, joined after forward.wgsl.
const LIGHT_TILES: &str = include_str!("../../shaders/pass/light_tiles.wgsl");
/// The real-time approximations forward.wgsl calls, and their exact alternatives (plan::exact).
const APPROXIMATIONS: &str = include_str!("../../shaders/pass/approximations.wgsl");
const EXACT: &str = include_str!("../../shaders/pass/exact.wgsl");
const BACKGROUND: &str = include_str!("../../shaders/pass/background.wgsl");
const PROBE: &str = include_str!("../../shaders/pass/brdf_probe.wgsl");

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PassKind {
    /// Forward lighting of one model, with vertex entry `vs_main` and fragment entry `fs_main`.
    Forward,
    /// The same with the approximation study's exact alternatives (group 3: the rays).
    ForwardExact,
    /// The environment background (no model).
    Background,
    /// Compute entry `probe_main`: the model evaluated for given directions.
    BrdfProbe,
}

const TRUTH: &str = include_str!("../../shaders/pass/truth.wgsl");
/// The scene as rays see it: the truth's and the exact alternatives' BVH, environment and sampling.
const RAYS: &str = include_str!("../../shaders/pass/rays.wgsl");
/// The physical truth's model alone (it reads `fgd_lookup`, which the including module defines).
pub const TRUTH_PHYSICAL: &str = include_str!("../../shaders/pass/truth_physical.wgsl");

/// The path tracer of the truths (render::truth): the scene pass's shared files, the subject's
/// model as it is, the fixed objects' model with every name it declares prefixed `fixed_` (both
/// define `model_direct`), the physical truth's model, the rays, then the tracer.
pub fn compose_truth(subject: &ShaderModel, fixed: &ShaderModel) -> String {
    let ids = pipeline_ids();
    let detail = if subject.wgsl.contains("fn model_detail") { "" } else { DEFAULT_DETAIL_HOOK };
    // The polygon integrals only where a model evaluates rect lights: less for the driver to compile.
    let area = if subject.area_lights() || fixed.area_lights() { AREA } else { "" };
    [
        MATH,
        &ids,
        CONVENTIONS,
        BRDF_TERMS,
        area,
        SCENE,
        &subject.wgsl,
        detail,
        &prefixed(&fixed.wgsl, "fixed_"),
        TRUTH_PHYSICAL,
        RAYS,
        TRUTH,
    ]
    .join("\n")
}

const TRACED_SHADOWS: &str = include_str!("../../shaders/pass/traced_shadows.wgsl");

/// The traced-shadow pass (render::passes::traced_shadows): the scene pass's shared files, the rays, then
/// the pass.
pub fn compose_traced_shadows() -> String {
    [MATH, &pipeline_ids(), CONVENTIONS, BRDF_TERMS, SCENE, RAYS, TRACED_SHADOWS].join("\n")
}

/// `source` with every module-scope name it declares (functions, constants, private variables,
/// structs, overrides, aliases) renamed `prefix` + name, wherever the name appears as a whole
/// identifier: a second copy of a model that can sit beside the first.
pub fn prefixed(source: &str, prefix: &str) -> String {
    let is_ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let declared: std::collections::HashSet<&str> = source
        .lines()
        .filter_map(|line| {
            let rest = ["fn ", "const ", "var<private> ", "struct ", "override ", "alias "]
                .iter()
                .find_map(|k| line.strip_prefix(k))?;
            let end = rest.find(|c: char| !is_ident(c)).unwrap_or(rest.len());
            Some(&rest[..end]).filter(|n| !n.is_empty())
        })
        .collect();
    let mut out = String::with_capacity(source.len() + 64);
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        if declared.contains(word.as_str()) {
            out.push_str(prefix);
        }
        out.push_str(word);
        word.clear();
    };
    for c in source.chars() {
        if is_ident(c) && !(word.is_empty() && c.is_ascii_digit()) {
            word.push(c);
        } else {
            flush(&mut word, &mut out);
            out.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
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
    let ids = pipeline_ids();
    let mut parts: Vec<(&str, &str)> = vec![
        ("shaders/common/math.wgsl", MATH),
        (PIPELINE_IDS_PATH, &ids),
        ("shaders/common/conventions.wgsl", CONVENTIONS),
        ("shaders/common/brdf.wgsl", BRDF_TERMS),
    ];
    // The polygon integrals only where the model evaluates rect lights (`model_rect`).
    if model.is_some_and(|m| m.area_lights()) {
        parts.push(("shaders/common/area.wgsl", AREA));
    }
    match pass {
        PassKind::Forward | PassKind::ForwardExact | PassKind::Background => {
            parts.push(("shaders/pass/scene.wgsl", SCENE))
        }
        PassKind::BrdfProbe => {}
    }
    // Whether the model wraps its lobes in the term functions (ShaderModel::splits_lobes), for
    // the passes' term masks.
    let splits = format!("const MODEL_SPLITS_LOBES: bool = {};\n", model.is_some_and(|m| m.splits_lobes()));
    if let Some(m) = model {
        parts.push((&m.source_path, &m.wgsl));
        if !m.wgsl.contains("fn model_reflectivity") {
            parts.push(("<default model hooks>", DEFAULT_MODEL_HOOKS));
        }
        if !m.wgsl.contains("fn model_height_scale") {
            parts.push(("<default model hooks>", DEFAULT_HEIGHT_HOOK));
        }
        if !m.area_lights() {
            parts.push(("<default model hooks>", DEFAULT_AREA_HOOK));
        }
        if !m.wgsl.contains("fn model_detail") {
            parts.push(("<default model hooks>", DEFAULT_DETAIL_HOOK));
        }
        if !m.wgsl.contains("fn model_back_ambient") {
            parts.push(("<default model hooks>", DEFAULT_BACK_AMBIENT_HOOK));
        }
        if !m.wgsl.contains("fn model_occlusion_albedo") {
            parts.push(("<default model hooks>", DEFAULT_OCCLUSION_HOOK));
        }
        parts.push(("<generated from the model: lobes>", &splits));
    }
    match pass {
        PassKind::Forward => parts.push(("shaders/pass/approximations.wgsl", APPROXIMATIONS)),
        PassKind::ForwardExact => {
            parts.push(("shaders/pass/rays.wgsl", RAYS));
            parts.push(("shaders/pass/exact.wgsl", EXACT));
        }
        PassKind::Background | PassKind::BrdfProbe => {}
    }
    match pass {
        PassKind::Forward | PassKind::ForwardExact => {
            parts.push(("shaders/pass/forward.wgsl", FORWARD));
            parts.push(("shaders/pass/shadow_filters.wgsl", SHADOW_FILTERS));
            parts.push(("shaders/pass/light_tiles.wgsl", LIGHT_TILES));
        }
        PassKind::Background => parts.push(("shaders/pass/background.wgsl", BACKGROUND)),
        PassKind::BrdfProbe => parts.push(("shaders/pass/brdf_probe.wgsl", PROBE)),
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixing_renames_declared_names_as_whole_words_only() {
        let src = "const K: f32 = 2.0;\nfn helper(x: f32) -> f32 { return x * K; }\nfn model_direct(s: Surface) -> f32 { return helper(s.metallic) + helper_two; }\n";
        let out = prefixed(src, "fixed_");
        assert!(out.contains("const fixed_K: f32"));
        assert!(out.contains("fn fixed_helper(x: f32)"));
        assert!(out.contains("x * fixed_K"));
        assert!(out.contains("fn fixed_model_direct(s: Surface)"));
        assert!(out.contains("fixed_helper(s.metallic)"));
        // Not declared here: shared names and longer identifiers stay as they are.
        assert!(out.contains("s: Surface") && out.contains("+ helper_two"));
    }
}

#[cfg(test)]
mod pipeline_id_tests {
    #[test]
    fn shaders_compare_pipelines_by_name_and_the_names_are_pipelines_ids() {
        let ids = super::pipeline_ids();
        for p in crate::pipelines::Pipeline::ALL {
            let line = format!("const PIPELINE_{}: u32 = {}u;", p.name().to_uppercase(), p.shader_id());
            assert!(ids.contains(&line), "{ids}");
        }
        let mut files = Vec::new();
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        let mut stack = vec![root];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(d).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "wgsl") {
                    files.push(p);
                }
            }
        }
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            for (i, line) in text.lines().enumerate() {
                let code = line.split("//").next().unwrap_or("").replace(' ', "");
                let literal = ["PIPELINE==", "PIPELINE!="]
                    .iter()
                    .any(|op| code.split(op).skip(1).any(|rest| rest.starts_with(|c: char| c.is_ascii_digit())));
                assert!(!literal, "{}:{}: compare PIPELINE with PIPELINE_BUILTIN/URP/HDRP: {line}", f.display(), i + 1);
            }
        }
    }
}
