//! User-supplied surface models: `NAME.wgsl` in a `shaders/brdf/` folder, declared by `NAME.toml`
//! beside it. They become shader names usable in any matrix, with no recompilation. The WGSL must
//! define `model_direct` and `model_indirect` (see shaders/brdf/lambert.wgsl for the contract);
//! it is parsed and validated with naga in every pass it takes part in, and errors name the user's
//! file, line and column.

use serde::Deserialize;
use std::path::Path;

use super::registry::{self, Expected, ParamSpec, Reads, Registry, ShaderModel};
use super::twin::Surface;
use super::wgsl::{compose_mapped, locate, PassKind};
use crate::error::{Error, InputError};
use crate::input::names::unknown_name;
use crate::input::source::parse_toml;
use crate::pipelines::Pipeline;

/// Where user models are looked for, relative to the working directory.
pub const USER_MODEL_DIR: &str = "shaders/brdf";

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Declaration {
    /// The shader name in matrices (default: the file stem).
    name: Option<String>,
    #[serde(default)]
    description: String,
    /// Default: every pipeline.
    pipelines: Option<Vec<String>>,
    /// Which sweep axes the model reads (default all): color, metallic, smoothness.
    reads: Option<Vec<String>>,
    #[serde(default)]
    reciprocal: bool,
    #[serde(default)]
    energy_conserving: bool,
    #[serde(default)]
    params: Vec<ParamDeclaration>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ParamDeclaration {
    name: String,
    slot: usize,
    default: f64,
    min: f64,
    max: f64,
    #[serde(default)]
    doc: String,
}

impl Registry {
    /// The built-in models and the user models declared in `dir` (none when it does not exist).
    pub fn with_user_models(dir: &Path) -> Result<Registry, Error> {
        let builtin = Registry::builtin();
        let models = load_dir(dir, &builtin)?;
        Ok(models.into_iter().fold(builtin, Registry::with))
    }
}

/// Every model declared in `dir`, checked against the names `known` has. Built-in WGSL files (the
/// repository's own shaders/brdf) are recognised by name and skipped.
pub fn load_dir(dir: &Path, known: &Registry) -> Result<Vec<ShaderModel>, Error> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Ok(Vec::new()) };
    let builtin = Registry::builtin_files();
    let mut paths: Vec<_> = entries.filter_map(|e| e.ok()).map(|e| e.path()).collect();
    paths.sort();
    let mut models: Vec<ShaderModel> = Vec::new();
    for wgsl_path in paths.iter().filter(|p| p.extension().is_some_and(|e| e == "wgsl")) {
        let file_name = wgsl_path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
        let decl_path = wgsl_path.with_extension("toml");
        if builtin.contains(&file_name.as_str()) && !decl_path.exists() {
            continue;
        }
        if !decl_path.exists() {
            return Err(InputError::new(
                wgsl_path.display().to_string(),
                format!(
                    "a user model needs a declaration beside it: {} (name, pipelines, params)",
                    decl_path.display()
                ),
            )
            .into());
        }
        let model = load_model(wgsl_path, &decl_path, known, &models)?;
        models.push(model);
    }
    Ok(models)
}

fn load_model(
    wgsl_path: &Path,
    decl_path: &Path,
    known: &Registry,
    loaded: &[ShaderModel],
) -> Result<ShaderModel, Error> {
    let decl_shown = decl_path.display().to_string();
    let wgsl_shown = wgsl_path.display().to_string();
    let text = crate::input::source::read_text(decl_path)?;
    let decl: Declaration = parse_toml(&decl_shown, &text)?;
    let wgsl = crate::input::source::read_text(wgsl_path)?;
    let stem = wgsl_path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
    let name = decl.name.clone().unwrap_or(stem);
    crate::input::validate::Checker::new(&decl_shown).name("name", &name)?;

    let pipelines = match &decl.pipelines {
        None => Pipeline::ALL.to_vec(),
        Some(list) => list
            .iter()
            .enumerate()
            .map(|(i, p)| {
                Pipeline::from_name(p).ok_or_else(|| {
                    unknown_name(&decl_shown, &format!("pipelines[{i}]"), "pipeline", p, &Pipeline::names())
                })
            })
            .collect::<Result<_, _>>()?,
    };
    for &p in &pipelines {
        let taken = |m: &ShaderModel| m.name == name && m.pipelines.contains(&p);
        if known.find(p, &name).is_some() || loaded.iter().any(taken) {
            return Err(InputError::at_key(
                &decl_shown,
                "name",
                format!("`{name}` is already a shader of the {} pipeline; choose another name", p.name()),
            )
            .into());
        }
    }
    let reads = match &decl.reads {
        None => Reads { color: true, metallic: true, smoothness: true, light: true },
        Some(list) => {
            let mut r = Reads { color: false, metallic: false, smoothness: false, light: true };
            for (i, a) in list.iter().enumerate() {
                match a.as_str() {
                    "color" => r.color = true,
                    "metallic" => r.metallic = true,
                    "smoothness" => r.smoothness = true,
                    other => {
                        return Err(unknown_name(
                            &decl_shown,
                            &format!("reads[{i}]"),
                            "axis",
                            other,
                            &["color", "metallic", "smoothness"],
                        )
                        .into())
                    }
                }
            }
            r
        }
    };
    let mut params = Vec::new();
    for (i, p) in decl.params.iter().enumerate() {
        let c = crate::input::validate::Checker::new(&decl_shown);
        c.name(&format!("params[{i}].name"), &p.name)?;
        if p.slot >= crate::shading::twin::PARAM_SLOTS {
            let last = crate::shading::twin::PARAM_SLOTS - 1;
            return Err(c
                .err(&format!("params[{i}].slot"), format!("slot {} is out of range; allowed 0..={last}", p.slot))
                .into());
        }
        // One slot read as two parameters, or one name for two slots, would label a sweep with
        // values the shader never saw.
        if let Some(j) = decl.params[..i].iter().position(|q| q.name == p.name) {
            return Err(c
                .err(&format!("params[{i}].name"), format!("`{}` is declared twice (also params[{j}])", p.name))
                .into());
        }
        if let Some(j) = decl.params[..i].iter().position(|q| q.slot == p.slot) {
            return Err(c
                .err(
                    &format!("params[{i}].slot"),
                    format!(
                        "slot {} is already `{}`'s (params[{j}]); each parameter needs a slot of its own",
                        p.slot, decl.params[j].name
                    ),
                )
                .into());
        }
        for (key, v) in [("min", p.min), ("max", p.max), ("default", p.default)] {
            if !v.is_finite() {
                return Err(c
                    .err(&format!("params[{i}].{key}"), format!("value {v} is not allowed; it must be finite"))
                    .into());
            }
        }
        if !(p.min <= p.default && p.default <= p.max) {
            return Err(c
                .err(
                    &format!("params[{i}].default"),
                    format!("default {} is outside min..=max ({}..={})", p.default, p.min, p.max),
                )
                .into());
        }
        params.push(ParamSpec {
            name: p.name.clone().into(),
            slot: p.slot,
            default: p.default,
            min: p.min,
            max: p.max,
            doc: p.doc.clone().into(),
        });
    }

    let model = ShaderModel {
        name: name.into(),
        pipelines,
        source_path: wgsl_shown.clone().into(),
        wgsl: wgsl.into(),
        reads,
        summary: if decl.description.is_empty() { format!("user model from {wgsl_shown}") } else { decl.description }
            .into(),
        twin: None,
        params,
        mapping: "user model: colour → base colour; metallic → the pipeline's conversion; smoothness as is; parameters at their defaults".into(),
        from_sliders: user_sliders,
        expected: Expected { reciprocal: decl.reciprocal, energy_conserving: decl.energy_conserving, is_brdf: true },
        per_vertex: false,
        emits: false,
        stiff_terms: "a user model: its own guards, not known to the tool".into(),
        passes: crate::shading::registry::FORWARD_PASSES,
        main_light_only: false,
        smoothness_gate: None,
        parity_tolerance: f64::INFINITY,
    };
    let baseline = known.find(Pipeline::Urp, "lambert").cloned();
    for pass in [PassKind::Forward, PassKind::ForwardExact, PassKind::BrdfProbe] {
        let module = validate(&model, pass)?;
        if let Some(base) = &baseline {
            check_bindings(&model, &module, base, pass)?;
        }
    }
    Ok(model)
}

/// A model reads its `Surface` and the pass's shared inputs; a resource binding of its own would
/// match no bind group the pass creates, and fail later as a device error (exit 3) that names no
/// file. Found here, against the bindings the same pass has with a built-in model.
fn check_bindings(model: &ShaderModel, module: &naga::Module, base: &ShaderModel, pass: PassKind) -> Result<(), Error> {
    let (source, _) = compose_mapped(pass, Some(base));
    let Ok(base_module) = naga::front::wgsl::parse_str(&source) else { return Ok(()) };
    let bindings = |m: &naga::Module| -> Vec<(u32, u32)> {
        m.global_variables.iter().filter_map(|(_, g)| g.binding.as_ref().map(|b| (b.group, b.binding))).collect()
    };
    let provided = bindings(&base_module);
    for (_, g) in module.global_variables.iter() {
        let Some(b) = &g.binding else { continue };
        if !provided.contains(&(b.group, b.binding)) {
            return Err(InputError::new(
                model.source_path.as_ref(),
                format!(
                    "WGSL: `{}` is bound at @group({}) @binding({}), which no pass provides; a model reads \
                     only its Surface parameters and the pass's shared inputs (see shaders/brdf/lambert.wgsl)",
                    g.name.as_deref().unwrap_or("a global"),
                    b.group,
                    b.binding
                ),
            )
            .into());
        }
    }
    Ok(())
}

fn user_sliders(model: &ShaderModel, p: Pipeline, s: &registry::Sliders) -> Surface {
    registry::metallic_workflow(model, p, s)
}

/// Whether `source` declares `fn name(`, ignoring line comments.
fn declares(source: &str, name: &str) -> bool {
    source.lines().map(|l| l.split("//").next().unwrap_or("")).any(|l| {
        l.split_once("fn ").is_some_and(|(_, rest)| {
            rest.trim_start().strip_prefix(name).is_some_and(|r| r.trim_start().starts_with('('))
        })
    })
}

/// Parse and validate the composed module with naga; report the position in the user's file.
fn validate(model: &ShaderModel, pass: PassKind) -> Result<naga::Module, Error> {
    // Checked on the user's own text first: a missing entry point would otherwise surface as an
    // unresolved name inside the pass that calls it.
    for entry in ["model_direct", "model_indirect"] {
        if !declares(&model.wgsl, entry) {
            return Err(InputError::new(
                model.source_path.as_ref(),
                format!("WGSL: the model must define `fn {entry}` (see shaders/brdf/lambert.wgsl for the signatures)"),
            )
            .into());
        }
    }
    let (source, map) = compose_mapped(pass, Some(model));
    let located = |line: usize, col: usize, message: String| -> Error {
        let (file, line) = locate(&map, line);
        if file == model.source_path.as_ref() {
            return InputError { file, location: Some((line, col)), key: None, message: format!("WGSL: {message}") }
                .into();
        }
        // The error surfaced in the tool's code composed around the model: the model's text left
        // something open (a brace, a comment, a statement) or redefined a name the pass uses.
        InputError::new(
            model.source_path.as_ref(),
            format!(
                "WGSL: {message} — reported at {file}:{line}:{col}, in the tool's code composed with this model: \
                 look for an unclosed brace, comment or statement, or a name the pass also defines"
            ),
        )
        .into()
    };
    let parsed = crate::input::guard::without_panics(|| naga::front::wgsl::parse_str(&source)).map_err(|panic| {
        Error::from(InputError::new(
            model.source_path.as_ref(),
            format!("WGSL: the WGSL front end failed on this model ({panic})"),
        ))
    })?;
    let module = match parsed {
        Ok(m) => m,
        Err(e) => {
            let loc = e.location(&source);
            return Err(match loc {
                Some(l) => located(l.line_number as usize, l.line_position as usize, e.message().to_string()),
                None => InputError::new(model.source_path.as_ref(), format!("WGSL: {}", e.message())).into(),
            });
        }
    };
    let mut validator =
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all());
    let validated =
        crate::input::guard::without_panics(|| validator.validate(&module).map_err(Box::new)).map_err(|panic| {
            Error::from(InputError::new(
                model.source_path.as_ref(),
                format!("WGSL: the WGSL validator failed on this model ({panic})"),
            ))
        })?;
    if let Err(e) = validated {
        // The outer error says which function; its sources say why.
        let mut message = e.as_inner().to_string();
        let mut cause: Option<&dyn std::error::Error> = std::error::Error::source(e.as_inner());
        while let Some(c) = cause {
            message.push_str(&format!(": {c}"));
            cause = c.source();
        }
        let detail: Vec<String> = e.spans().map(|(_, label)| label.clone()).filter(|l| !l.is_empty()).collect();
        let full = if detail.is_empty() { message } else { format!("{message} ({})", detail.join("; ")) };
        // The last span is the most specific (the expression rather than the whole function).
        return Err(match e.spans().last().map(|(span, _)| span.location(&source)) {
            Some(l) => located(l.line_number as usize, l.line_position as usize, full),
            None => InputError::new(model.source_path.as_ref(), format!("WGSL: {full}")).into(),
        });
    }
    Ok(module)
}
