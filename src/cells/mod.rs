//! Matrix expansion: the cartesian product of the axes (or one axis at a time, `SweepDesign`),
//! filtered by `only`/`exclude`, with the cells that cannot exist (a shader a pipeline lacks)
//! pruned and the cells whose shader ignores the axes they differ in marked as twins of the cell
//! that is rendered.

use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};

use crate::declarations::matrix::{Axis, Filter, FilterValue, Matrix};
use crate::declarations::presets::Preset;
use crate::declarations::sweep::SweepDesign;
use crate::geometry::gltf_io::GltfMaterial;
use crate::pipelines::settings_axes::{self, EngineState, SceneFacts};
use crate::pipelines::surface::SurfaceType;
use crate::pipelines::{DisplayTransform, Pipeline};
use crate::shading::registry::{ShaderModel, Sliders};
use crate::shading::twin::Surface;
use std::sync::Arc;

pub mod coords;
mod engine;
pub use coords::{AxisValue, CellCoords};
use engine::{combine, engine_variations, scene_facts};

/// Stable, readable, filesystem-safe id, e.g. `mitsuba__builtin-forward__standard__gold__m1.00_s0.80_i1_r10`.
/// One read from a record is checked (`CellId::parse`): it names a folder, and a record is input.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(try_from = "String")]
pub struct CellId(pub String);

/// The longest id: a cell's folder name, with room for the longest temporary name the tool gives
/// it beside its folder (`.ID.droppedPID`, a PID of up to 10 digits) within a file name's 255 bytes.
pub const MAX_ID_BYTES: usize = 255 - ".".len() - ".dropped".len() - 10;

impl CellId {
    /// `text` as an id: one path component of the id alphabet (ASCII letters, digits, `_`, `-`,
    /// `.`, `+`), not starting with `.`, at most `MAX_ID_BYTES`; never a path.
    pub fn parse(text: &str) -> Result<CellId, String> {
        let allowed = |b: u8| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.' | b'+');
        if text.is_empty() || text.starts_with('.') || !text.bytes().all(allowed) {
            return Err(format!(
                "`{text}` is not a cell id (one folder name of ASCII letters, digits, `_`, `-`, `.` and `+`, \
                 not starting with `.`)"
            ));
        }
        if text.len() > MAX_ID_BYTES {
            return Err(format!("cell id `{text}` is {} bytes; an id has at most {MAX_ID_BYTES}", text.len()));
        }
        Ok(CellId(text.to_string()))
    }
}

impl TryFrom<String> for CellId {
    type Error = String;
    fn try_from(text: String) -> Result<CellId, String> {
        CellId::parse(&text)
    }
}

impl std::fmt::Display for CellId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Material as swept: preset values with the sliders that override them (slider units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MaterialParams {
    /// Linear base colour (preset value, or the sRGB slider linearised).
    pub base_color_linear: [f64; 3],
    /// The sRGB slider colour when the colour axis overrides the preset.
    pub slider_color_srgb: Option<[f64; 3]>,
    /// Slider value; pipelines convert it (`Pipeline::shader_metallic`).
    pub metallic: f64,
    pub smoothness: f64,
    /// The emission colour (linear) where it is not the base colour: a glTF subject's own
    /// `emissiveFactor` (preset `own`); the emission axis scales it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emissive_linear: Option<[f64; 3]>,
    /// The surface type: the axis's, or the material's own (a glTF subject's `alphaMode`).
    #[serde(default, skip_serializing_if = "is_opaque")]
    pub surface: SurfaceType,
    /// The base colour's alpha: the axis's, or the material's own (1 for presets).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub alpha: f64,
    /// A glTF subject's `KHR_materials_specular` dielectric F0 (`GltfMaterial::specular_f0`): its
    /// cells draw the lit shaders' specular workflow with it in place of 0.04.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular_f0: Option<[f64; 3]>,
    /// Where a cutout surface clips: Unity's default `_Cutoff`, or a glTF's `alphaCutoff`.
    #[serde(default = "default_cutoff", skip_serializing_if = "is_default_cutoff")]
    pub alpha_cutoff: f64,
}

fn is_opaque(s: &SurfaceType) -> bool {
    *s == SurfaceType::Opaque
}

fn one() -> f64 {
    1.0
}

fn is_one(x: &f64) -> bool {
    *x == 1.0
}

fn default_cutoff() -> f64 {
    crate::pipelines::surface::DEFAULT_CUTOFF
}

fn is_default_cutoff(x: &f64) -> bool {
    *x == crate::pipelines::surface::DEFAULT_CUTOFF
}

#[derive(Debug, Clone, Serialize)]
pub struct Cell {
    pub id: CellId,
    /// Index into `Matrix::compositions`.
    #[serde(skip)]
    pub composition_index: usize,
    /// What the cell is: its value on every axis.
    pub coords: CellCoords,
    /// The material its preset and sliders resolve to.
    pub material: MaterialParams,
    pub width: u32,
    pub height: u32,
    /// HDRP exposure (from the scene's volume) and the pipeline's tonemapper.
    pub display: DisplayTransform,
    /// The matrix's light budgets (`[lights]`).
    pub light_budget: crate::pipelines::LightBudget,
    /// The anti-aliasing the matrix asks of this cell's pipeline (deferred paths render one sample).
    pub antialiasing: crate::pipelines::Antialiasing,
    /// The engine settings (`[pipeline_settings]`): the URP asset, built-in's pass structure.
    pub pipeline_settings: crate::pipelines::settings::PipelineSettings,
    /// Set when an earlier cell renders the same image (the shader ignores the differing axes).
    pub twin_of: Option<CellId>,
    /// The model `shader` names in `pipeline`.
    #[serde(skip)]
    pub model: Arc<ShaderModel>,
}

/// A cell reads as its coordinates (`cell.pipeline`, `cell.light_angle`): what it is, on every
/// axis; what those resolve to (material, display, model) are its own fields.
impl std::ops::Deref for Cell {
    type Target = CellCoords;

    fn deref(&self) -> &CellCoords {
        &self.coords
    }
}

impl Cell {
    /// The preset whose maps the subject wears, when textured (`own`: the glTF subject's textures).
    pub fn material_maps(&self) -> Option<&'static str> {
        if !self.textured {
            return None;
        }
        crate::declarations::presets::find_matrix_preset(&self.preset).map(|p| p.name)
    }

    /// Whether the subject wears its glTF file's own material.
    pub fn own_material(&self) -> bool {
        self.preset == crate::declarations::presets::OWN.name
    }

    pub fn sliders(&self) -> Sliders {
        let m = &self.material;
        Sliders { base_color_linear: m.base_color_linear, metallic: m.metallic, smoothness: m.smoothness }
    }

    /// The subject's material as this cell's model receives it, with the swept parameters.
    pub fn surface(&self) -> Surface {
        let (mut s, f0) = self.metallic_workflow_surface();
        crate::shading::registry::apply_workflow_with(self.model(), &mut s, f0);
        // The specular axis's colour where the model reads one (Unity's _SpecColor), in place of
        // the workflow's F0 or the model's own mapping.
        if let Some(srgb) = self.specular.filter(|_| self.model().reads_specular(&s.params)) {
            s.specular = glam::DVec3::from(srgb.map(crate::color::srgb_to_linear));
        }
        s
    }

    /// What `surface` carries the specular workflow over from, where it does and no specular
    /// axis replaces the colour it carries (so maps that vary the metallic carry it over texel by
    /// texel, as a specular map authored from them would).
    pub fn workflow_source(&self) -> Option<crate::shading::registry::WorkflowSource> {
        let (s, f0) = self.metallic_workflow_surface();
        if self.specular.is_some() && self.model().reads_specular(&s.params) {
            return None;
        }
        crate::shading::registry::workflow_source(self.model(), &s, f0)
    }

    /// The subject's material with the swept parameters, before the specular workflow (if on)
    /// carries it over, and the dielectric F0 it would carry it over with.
    fn metallic_workflow_surface(&self) -> (Surface, glam::DVec3) {
        let mut s = self.model().surface(self.pipeline, &self.sliders());
        // A glTF's KHR_materials_specular is the specular workflow with its dielectric F0, unless
        // the matrix sweeps the workflow itself.
        let material_type = self.coords.material_type;
        let dielectric = self
            .material
            .specular_f0
            .filter(|_| !self.params.contains_key("specular_setup") && material_type.is_none());
        let typed = |name: &str| material_type?.params().iter().find(|(n, _)| *n == name).map(|(_, v)| *v);
        for spec in &self.model().params {
            if let Some(v) = self.params.get(spec.name.as_ref()).copied().or_else(|| typed(&spec.name)) {
                s.params[spec.slot] = v;
            } else if spec.name == "specular_setup" && dielectric.is_some() {
                s.params[spec.slot] = 1.0;
            }
        }
        (s, dielectric.map_or(glam::DVec3::splat(0.04), glam::DVec3::from))
    }

    pub fn model(&self) -> &ShaderModel {
        &self.model
    }

    /// The subject's surface type, alpha and cutoff, as the material resolves them.
    pub fn surface_options(&self) -> crate::pipelines::surface::SurfaceOptions {
        let m = &self.material;
        crate::pipelines::surface::SurfaceOptions { kind: m.surface, alpha: m.alpha, cutoff: m.alpha_cutoff }
    }
}

#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct PrunedCell {
    pub description: String,
    /// The axis values that make every cell of the combination impossible (axis name, value).
    pub axes: Vec<(String, String)>,
    pub reason: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Expansion {
    pub cells: Vec<Cell>,
    pub pruned: Vec<PrunedCell>,
    /// Cells removed by `only`/`exclude`.
    pub filtered_out: usize,
    /// Cells of other shards this shard renders too, because its own cells are compared with them
    /// or copy them (`run::shard`).
    pub support: Vec<CellId>,
}

impl Expansion {
    pub fn rendered(&self) -> impl Iterator<Item = &Cell> {
        self.cells.iter().filter(|c| c.twin_of.is_none())
    }
}

/// A pruned combination's axes: its composition, its pipeline and the one value it lacks.
fn pruned_axes(composition: &str, pipeline: Pipeline, axis: &str, value: &str) -> Vec<(String, String)> {
    vec![
        ("composition".into(), composition.into()),
        ("pipeline".into(), pipeline.name().into()),
        (axis.into(), value.into()),
    ]
}

/// Why a cell's surface type cannot be drawn: its pipeline's lit shaders have no such surface, or
/// the surface multiplies a diffuse lobe that the cell's model does not keep apart.
fn surface_missing(c: &Cell) -> Option<String> {
    let s = c.material.surface;
    if let Some(reason) = s.missing_in(c.pipeline) {
        return Some(reason);
    }
    if s != SurfaceType::Opaque && (c.model().per_vertex || c.path == crate::pipelines::RenderPath::VertexLit) {
        return Some(format!(
            "lighting at the vertices (the vertex-lit path, Gouraud models) is drawn without alpha here; the `{}` \
             surface is not modelled there",
            s.name()
        ));
    }
    (s.premultiplies_diffuse(c.pipeline) && !c.model().splits_diffuse()).then(|| {
        format!(
            "the `{}` surface multiplies the diffuse reflection alone by alpha; `{}` keeps no diffuse lobe apart \
             (the engines' lit shaders do: standard and its BRDF2/3 tiers, URP's lit and simple_lit, HDRP's lit, unlit)",
            s.name(),
            c.shader
        )
    })
}

/// The most cells a run expands unless `--max-cells` says otherwise: the thesis is 194 400; a
/// million 256² cells is some 200 GB of results.
pub const DEFAULT_MAX_CELLS: u64 = 1_000_000;

/// The size of the product before anything is expanded: each axis's count and their product
/// (before pruning and filters, so an upper bound), refused above `limit`. A typo such as a
/// 10⁹-cell matrix once allocated until the machine died.
pub fn check_size(m: &Matrix, limit: u64) -> Result<u128, crate::error::InputError> {
    let n = |len: usize| len.max(1) as u128;
    let s = &m.sweep;
    let mut axes: Vec<(String, u128)> = vec![
        ("compositions".into(), n(m.compositions.len())),
        ("pipelines".into(), n(m.pipelines.len())),
        ("paths".into(), n(m.paths.len())),
        ("shaders".into(), n(m.shaders.len())),
        ("presets".into(), n(m.presets.len())),
    ];
    // Every swept axis of the table (numbers, the colour, `textured`), and the parameters.
    let lists = swept_axes(m).into_iter().map(|(axis, values)| {
        let off_own = values.iter().filter(|v| **v != AxisValue::Own).count();
        (format!("sweep.{}", axis.name()), values.len(), off_own)
    });
    // The settings of one pipeline multiply its cells alone: the largest pipeline's product bounds them.
    let settings = s.settings.iter().map(|(p, lists)| {
        let product = lists.values().map(|v| v.len().max(1)).product::<usize>();
        let moved: usize = lists.values().map(Vec::len).sum();
        (format!("sweep.settings.{}", p.name()), product, moved)
    });
    let settings = settings.max_by_key(|(_, product, _)| *product);
    let lists: Vec<(String, usize, usize)> = lists
        .chain(s.params.iter().map(|(k, v)| (format!("sweep.params.{k}"), v.len(), v.len())))
        .chain(settings)
        .collect();
    match s.design {
        SweepDesign::Grid => axes.extend(lists.into_iter().map(|(name, len, _)| (name, n(len)))),
        // The cell at every own value, and one per value off it.
        SweepDesign::OneAtATime => {
            let moved: usize = lists.iter().map(|(_, _, off)| off).sum();
            axes.push(("one-at-a-time values (1 + each list's)".into(), 1 + moved as u128));
        }
    }
    let product = axes.iter().fold(1u128, |p, (_, c)| p.saturating_mul(*c));
    if product > limit as u128 {
        let counts: Vec<String> = axes.iter().filter(|(_, c)| *c > 1).map(|(a, c)| format!("{a} {c}")).collect();
        return Err(crate::error::InputError::new(
            m.origin.clone(),
            format!(
                "the matrix expands to up to {product} cells ({}), above the limit of {limit}; narrow the \
                 sweep, or raise the limit with --max-cells N",
                counts.join(" × ")
            ),
        ));
    }
    Ok(product)
}

/// The swept values of every axis a sweep list sets (numbers, the colour, `textured`), in table
/// order; an axis the matrix does not sweep has the one value `Own` (the preset's or the scene's).
fn swept_axes(m: &Matrix) -> Vec<(Axis, Vec<AxisValue>)> {
    use crate::declarations::axes::AxisKind;
    crate::declarations::axes::AXES
        .iter()
        .filter_map(|row| {
            let values: Vec<AxisValue> = match row.kind {
                AxisKind::Number => {
                    let own = m.sweep.sweeps_own(row.axis).then_some(AxisValue::Own);
                    own.into_iter().chain(m.sweep.numbers(row.axis).iter().map(|v| AxisValue::Number(*v))).collect()
                }
                AxisKind::Colour => {
                    let own = m.sweep.sweeps_own(row.axis).then_some(AxisValue::Own);
                    own.into_iter()
                        .chain(m.sweep.colours(row.axis).iter().map(|c| AxisValue::Colour(Some(*c))))
                        .collect()
                }
                AxisKind::Bool => m.sweep.textured.iter().map(|b| AxisValue::Bool(*b)).collect(),
                AxisKind::Choice => {
                    let own = m.sweep.sweeps_own(row.axis).then_some(AxisValue::Own);
                    let names: Vec<&str> = match row.axis {
                        Axis::MaterialType => m.sweep.material_type.iter().map(|t| t.name()).collect(),
                        _ => m.sweep.surface.iter().map(|s| s.name()).collect(),
                    };
                    own.into_iter().chain(names.into_iter().map(|n| AxisValue::Name(n.to_string()))).collect()
                }
                AxisKind::Name | AxisKind::Params | AxisKind::Settings => return None,
            };
            Some((row.axis, if values.is_empty() { vec![AxisValue::Own] } else { values }))
        })
        .collect()
}

/// Every combination of one value per axis, the last axis turning fastest (an odometer, as
/// Filament's `AutomationSpec` permutes its settings).
fn odometer(axes: &[(Axis, Vec<AxisValue>)]) -> Vec<Vec<(Axis, &AxisValue)>> {
    let mut digits = vec![0usize; axes.len()];
    let mut out = Vec::new();
    if axes.iter().any(|(_, v)| v.is_empty()) {
        return out;
    }
    loop {
        out.push(axes.iter().zip(&digits).map(|((a, v), &d)| (*a, &v[d])).collect());
        let mut k = axes.len();
        loop {
            if k == 0 {
                return out;
            }
            k -= 1;
            digits[k] += 1;
            if digits[k] < axes[k].1.len() {
                break;
            }
            digits[k] = 0;
        }
    }
}

pub fn expand(m: &Matrix) -> Expansion {
    let swept = swept_axes(m);
    let mut cells = Vec::new();
    let mut pruned = Vec::new();
    let mut filtered_out = 0;
    for (ci, scene) in m.compositions.iter().enumerate() {
        let key = scene.key_light().map(|k| &scene.lights[k]);
        // Read only where a matrix names `own`: the file's factors, not its images.
        let own = match m.presets.iter().any(|p| p.name == crate::declarations::presets::OWN.name) {
            true => own_material(scene),
            false => Err(String::new()),
        };
        for &pipeline in &m.pipelines {
            for &path in &m.paths {
                if !pipeline.paths().contains(&path) {
                    pruned.push(PrunedCell {
                        description: format!("{} × {} × {}", scene.name, pipeline.name(), path.name()),
                        axes: pruned_axes(&scene.name, pipeline, "path", path.name()),
                        reason: format!("the {} pipeline has no {} path", pipeline.name(), path.name()),
                    });
                    continue;
                }
                let engines = engine_variations(m, pipeline);
                for shader in &m.shaders {
                    let Some(model) = m.registry.find(pipeline, shader) else {
                        pruned.push(PrunedCell {
                            description: format!("{} × {} × {}", scene.name, pipeline.name(), shader),
                            axes: pruned_axes(&scene.name, pipeline, "shader", shader),
                            reason: format!(
                                "`{shader}` is not a shader of the {} pipeline (it has: {})",
                                pipeline.name(),
                                m.registry.names_for(pipeline).join(", ")
                            ),
                        });
                        continue;
                    };
                    let display = DisplayTransform::new(pipeline, m.tonemap_for(pipeline), &scene.hdrp);
                    let variations = variations(m.sweep.design, &swept, &model.params, &m.sweep.params);
                    for preset in &m.presets {
                        let own_factors = if preset.name == crate::declarations::presets::OWN.name {
                            match &own {
                                Ok(f) => Some(f),
                                Err(reason) => {
                                    pruned.push(PrunedCell {
                                        description: format!("{} × {} × own", scene.name, pipeline.name()),
                                        axes: pruned_axes(&scene.name, pipeline, "preset", "own"),
                                        reason: reason.clone(),
                                    });
                                    continue;
                                }
                            }
                        } else {
                            None
                        };
                        // The cell before the sweep sets its axes: the preset's material, the
                        // scene's key light and view; `own` wears the file's textures.
                        let (metallic, smoothness) = match own_factors {
                            Some(f) => (f.metallic, 1.0 - f.roughness),
                            None => (preset.metallic, preset.smoothness),
                        };
                        let names = coords::CellNames {
                            composition: scene.name.clone(),
                            pipeline,
                            path,
                            shader: shader.clone(),
                            preset: preset.name.to_string(),
                        };
                        let unswept = CellCoords::unswept(
                            names,
                            (metallic, smoothness),
                            (key.map_or(0.0, |l| l.intensity), key.map_or(0.0, |l| l.range)),
                            own_factors.is_some_and(|f| f.has_textures()),
                        );
                        for ((values, params), (engine, named)) in combine(m.sweep.design, &variations, &engines) {
                            let mut coords = unswept.clone();
                            coords.settings = named.clone();
                            for (axis, v) in values.iter().filter(|(_, v)| **v != AxisValue::Own) {
                                coords.set(*axis, v);
                            }
                            coords.params = params.clone();
                            // A type sets its flags, and takes a swept slider it has not (a
                            // Standard cell has no anisotropy): the id says what is drawn.
                            if let Some(t) = coords.material_type {
                                for (name, _) in t.params() {
                                    coords.params.remove(*name);
                                }
                            }
                            let cell = Cell {
                                id: CellId(String::new()),
                                composition_index: ci,
                                material: material(preset, own_factors, &coords),
                                coords,
                                width: m.image.width,
                                height: m.image.height,
                                display,
                                light_budget: engine.budget,
                                antialiasing: engine.antialiasing,
                                pipeline_settings: engine.settings,
                                twin_of: None,
                                model: model.clone(),
                            };
                            // A cell whose model lacks its material type or surface: one
                            // entry per composition, pipeline, shader and value.
                            let missing = cell
                                .coords
                                .material_type
                                .and_then(|t| Some(("material_type", t.name(), t.missing_in(cell.model())?)))
                                .or_else(|| {
                                    surface_missing(&cell).map(|r| ("surface", cell.material.surface.name(), r))
                                });
                            if let Some((axis, value, reason)) = missing {
                                let description = format!("{} × {} × {shader} × {value}", scene.name, pipeline.name());
                                if !pruned.iter().any(|p| p.description == description) {
                                    let axes = pruned_axes(&scene.name, pipeline, axis, value);
                                    pruned.push(PrunedCell { description, axes, reason });
                                }
                                continue;
                            }
                            if passes_filters(&cell, &m.only, &m.exclude) {
                                cells.push(cell);
                            } else {
                                filtered_out += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    for p in m.sweep.settings.keys().filter(|p| !m.pipelines.contains(p)) {
        pruned.push(PrunedCell {
            description: format!("sweep.settings.{}", p.name()),
            axes: vec![("pipeline".into(), p.name().into())],
            reason: format!("the matrix renders no {} cells for its settings to change", p.name()),
        });
    }
    for c in &mut cells {
        c.id = cell_id(&c.coords);
    }
    // A value listed twice in a sweep gives the same cell twice: keep one.
    let mut seen = std::collections::HashSet::new();
    cells.retain(|c| seen.insert(c.id.clone()));
    mark_twins(&mut cells, &m.invariant_filters(), &scene_facts(m), reads_material(m));
    Expansion { cells, pruned, filtered_out, support: Vec::new() }
}

/// One cell's swept values: the axes it sets off their own values, and its model parameters.
type Variation<'a> = (Vec<(Axis, &'a AxisValue)>, BTreeMap<String, f64>);

/// The swept values of a cell of a model with `model_params` under the sweep's design: every
/// combination of one value per axis and parameter (a grid), or the cell at every own value and
/// one more per value of one axis or parameter at a time (`SweepDesign::OneAtATime`).
fn variations<'a>(
    design: SweepDesign,
    swept: &'a [(Axis, Vec<AxisValue>)],
    model_params: &[crate::shading::registry::ParamSpec],
    params: &BTreeMap<String, Vec<f64>>,
) -> Vec<Variation<'a>> {
    match design {
        SweepDesign::Grid => {
            let sets = param_product(model_params, params);
            odometer(swept).into_iter().flat_map(|v| sets.iter().map(move |p| (v.clone(), p.clone()))).collect()
        }
        SweepDesign::OneAtATime => {
            let mut out = vec![(Vec::new(), BTreeMap::new())];
            for (axis, values) in swept {
                out.extend(
                    values.iter().filter(|v| **v != AxisValue::Own).map(|v| (vec![(*axis, v)], BTreeMap::new())),
                );
            }
            for (name, values) in params.iter().filter(|(n, _)| model_params.iter().any(|p| p.name == n.as_str())) {
                out.extend(values.iter().map(|v| (Vec::new(), BTreeMap::from([(name.clone(), *v)]))));
            }
            out
        }
    }
}

/// Every combination of the swept values of the parameters `model_params` has; one empty set
/// when it has none of them (a parameter the model lacks makes no new cells).
fn param_product(
    model_params: &[crate::shading::registry::ParamSpec],
    swept: &BTreeMap<String, Vec<f64>>,
) -> Vec<BTreeMap<String, f64>> {
    let mut sets = vec![BTreeMap::new()];
    for (name, values) in swept {
        if !model_params.iter().any(|p| p.name == name.as_str()) {
            continue;
        }
        sets = sets
            .into_iter()
            .flat_map(|set| {
                values.iter().map(move |v| {
                    let mut next = set.clone();
                    next.insert(name.clone(), *v);
                    next
                })
            })
            .collect();
    }
    sets
}

/// The factors of a composition's glTF subject's own material, or why `own` has none there.
fn own_material(scene: &crate::declarations::scene::Scene) -> Result<GltfMaterial, String> {
    let path = scene.subject_gltf().ok_or_else(|| {
        format!("`own` is a glTF subject's material; the subject of `{}` is not a glTF file", scene.name)
    })?;
    match crate::geometry::gltf_io::material_factors(&path) {
        Ok(Some(m)) if m.specular_textures > 0 => Err(format!(
            "the subject's glTF material has KHR_materials_specular textures, which are not read (its factors map \
             to the specular workflow, its textures do not): {}",
            path.display()
        )),
        Ok(Some(m)) => Ok(m),
        Ok(None) => Err(format!("the subject's glTF file {} names no material", path.display())),
        // The geometry stage reports an unreadable file as bad input before anything renders.
        Err(e) => Err(format!("the subject's glTF file cannot be read: {e}")),
    }
}

/// The material a cell's coordinates resolve to: the preset's colour (a glTF subject's own
/// factors for `own`) unless the colour slider overrides it, with the metallic and smoothness the
/// coordinates hold.
fn material(preset: &Preset, own: Option<&GltfMaterial>, coords: &CellCoords) -> MaterialParams {
    let (base, emissive) = match own {
        Some(f) => ([f.base_color[0], f.base_color[1], f.base_color[2]], Some(f.emissive)),
        None => (preset.base_color, None),
    };
    MaterialParams {
        base_color_linear: coords.color.map(|c| c.map(crate::color::srgb_to_linear)).unwrap_or(base),
        slider_color_srgb: coords.color,
        metallic: coords.metallic,
        smoothness: coords.smoothness,
        emissive_linear: emissive,
        surface: coords.surface.or(own.map(|f| f.surface)).unwrap_or_default(),
        alpha: coords.alpha.or(own.map(|f| f.base_color[3])).unwrap_or(1.0),
        specular_f0: own.and_then(|f| f.specular_f0),
        alpha_cutoff: own.filter(|f| f.surface == SurfaceType::Cutout).map_or(default_cutoff(), |f| f.alpha_cutoff),
    }
}

/// `composition__pipeline-path__shader__preset` and then each axis the id carries, in table
/// order after its prefix (`_m1.00_s0.90_i1.5_r12`).
pub fn cell_id(c: &CellCoords) -> CellId {
    let mut id = format!("{}__{}-{}__{}__{}", c.composition, c.pipeline.name(), c.path.name(), c.shader, c.preset);
    for row in crate::declarations::axes::AXES.iter() {
        id.push_str(&c.id_part(row));
    }
    CellId(id)
}

/// 1 → "1", 2.5 → "2.5", 0.125 → "0.125", 1.00001 → "1.00001": readable and exact in ids.
#[cfg(test)]
fn short_number(v: f64) -> String {
    id_number(v, 4, true)
}

/// `v` in an id: with `decimals` places (trailing zeros trimmed when `trim`) where that reads back
/// as exactly `v`, else its shortest round-trip form (`0.999`, `1e-5`). Two different values
/// never share a string, so two cells never share an id: a fixed rounding made smoothness 0.999
/// and 1 one cell, and the stiff ends a stability sweep exists for were never rendered.
pub fn id_number(v: f64, decimals: usize, trim: bool) -> String {
    let v = if v == 0.0 { 0.0 } else { v }; // -0 renders as 0: one cell, one id
    let fixed = format!("{v:.decimals$}");
    let fixed = if trim { fixed.trim_end_matches('0').trim_end_matches('.').to_string() } else { fixed };
    // Debug is Rust's shortest round-trip form, switching to exponents for tiny and huge values.
    let exact = format!("{v:?}");
    let exact = exact.strip_suffix(".0").map(str::to_string).unwrap_or(exact);
    // Both forms read back as `v`, so either keeps ids distinct; the fixed one is kept where it is
    // about as short (`1.00` beside `1`), not for 1e300's 301 digits.
    if fixed.parse::<f64>() == Ok(v) && fixed.len() <= exact.len() + 3 {
        fixed
    } else {
        exact
    }
}

/// The id of the cell `c` is compared against under a cell reference: `c` with the named axes
/// changed. None when a named composition is not in the matrix.
pub fn reference_cell_id(c: &Cell, m: &Matrix, terms: &[(Axis, FilterValue)]) -> Option<CellId> {
    let mut r = c.coords.clone();
    // Another pipeline's cell has none of this one's settings: its engine's own.
    if terms.iter().any(|(axis, v)| *axis == Axis::Pipeline && *v != FilterValue::Name(c.pipeline.name().into())) {
        r.settings.clear();
    }
    for (axis, v) in terms {
        if *axis == Axis::Composition && !m.compositions.iter().any(|s| FilterValue::Name(s.name.clone()) == *v) {
            return None;
        }
        let value = match v {
            FilterValue::Name(n) => AxisValue::Name(n.clone()),
            FilterValue::Number(x) => AxisValue::Number(*x),
            FilterValue::Color(_) => return None,
        };
        if !r.set(*axis, &value) {
            return None;
        }
    }
    Some(cell_id(&r))
}

fn passes_filters(c: &Cell, only: &[Filter], exclude: &[Filter]) -> bool {
    (only.is_empty() || only.iter().any(|f| matches_filter(c, f))) && !exclude.iter().any(|f| matches_filter(c, f))
}

pub fn matches_filter(c: &Cell, f: &Filter) -> bool {
    f.terms.iter().all(|(axis, values)| c.coords.matches(*axis, values))
}

/// Whether the matrix's reference reads a cell's material whatever its shader reads: a physical
/// truth traces the preset's physical material, so two cells a shader draws alike (a Lambert
/// cell's smoothness) have different truths and are each compared with their own.
fn reads_material(m: &Matrix) -> bool {
    matches!(&m.reference, Some(crate::declarations::matrix::ReferenceSpec::Truth(t))
        if t.settings.kind == crate::declarations::matrix::TruthKind::Physical)
}

/// What the image of a cell — and what it is compared with — depends on, given the axes its
/// shader reads (`keyless`: its composition has no key light for the light axes to change;
/// `material_read`: the reference reads the whole material, `reads_material`). Every axis counts
/// unless the cell's model cannot see it, so an axis added to the table splits twins until said
/// otherwise here.
fn render_key(c: &Cell, keyless: bool, facts: &SceneFacts, material_read: bool) -> String {
    let r = c.model().reads_for(&c.surface().params);
    let m = &c.material;
    let material_axis = |axis: Axis| {
        matches!(axis, Axis::Color | Axis::Metallic | Axis::Smoothness | Axis::Emission | Axis::Specular | Axis::Alpha)
    };
    let ignored = |axis: Axis| match axis {
        _ if material_read && material_axis(axis) => false,
        // The preset reaches the image through the material alone, the settings through the
        // engine state (below, as far as the frame shows it).
        Axis::Preset | Axis::Settings => true,
        Axis::Color => !r.color,
        Axis::Metallic => !r.metallic,
        Axis::Smoothness => !r.smoothness,
        Axis::Emission => !c.model().emits(),
        Axis::Specular => !c.model().reads_specular(&c.surface().params),
        // An opaque surface draws without its alpha (HDRP's ApplyBlendMode sets opacity 1).
        Axis::Alpha => c.material.surface == SurfaceType::Opaque,
        // Fixed objects are lit by the key light whatever the shader, so light axes count
        // wherever there is a key light.
        Axis::LightIntensity | Axis::LightRange | Axis::LightAngle => keyless,
        _ => false,
    };
    let mut key = format!("{}", c.composition_index);
    for row in crate::declarations::axes::AXES.iter().filter(|row| !ignored(row.axis)) {
        let mut value = c.coords.get(row.axis);
        // A height map's scale, the secondary maps and the smoothness's source move the maps: a
        // flat subject has none (Unity's default white map has alpha 1: the slider's smoothness).
        if let (AxisValue::Params(p), false) = (&mut value, c.coords.textured) {
            p.remove(crate::shading::registry::PARALLAX_PARAM);
            p.remove(crate::shading::registry::DETAIL_PARAM);
            p.remove(crate::shading::registry::SMOOTHNESS_SOURCE_PARAM);
        }
        // A film's thickness without the film.
        if let AxisValue::Params(p) = &mut value {
            for name in c.model().unread_params(&c.surface().params) {
                p.remove(name);
            }
        }
        key.push_str(&format!("|{}={:?}", row.name, value));
    }
    if material_read {
        key.push_str(&format!("|m{m:?}"));
    } else if r.color {
        key.push_str(&format!("|c{:?}", m.base_color_linear));
    }
    // The engine settings as far as they can change this frame (`settings_axes::frame_relevant`).
    let engine = EngineState { settings: c.pipeline_settings, antialiasing: c.antialiasing, budget: c.light_budget };
    let engine = settings_axes::frame_relevant(c.pipeline, c.path, facts, &engine);
    key.push_str(&format!(
        "|{}x{}|{:?}|{:?}|{:?}|{:?}",
        c.width, c.height, c.display, engine.budget, engine.antialiasing, engine.settings
    ));
    key
}

/// After cells were removed: a twin whose original is gone is re-marked against what remains.
pub fn remark_twins(cells: &mut [Cell], present: &std::collections::HashSet<CellId>, m: &Matrix) {
    if cells.iter().any(|c| c.twin_of.as_ref().is_some_and(|t| !present.contains(t))) {
        for c in cells.iter_mut() {
            c.twin_of = None;
        }
        mark_twins(cells, &m.invariant_filters(), &scene_facts(m), reads_material(m));
    }
}

/// `asserted`: the cells an `invariant` assert covers are all rendered — the assert tests the very
/// independence that twinning would take on trust.
fn mark_twins(cells: &mut [Cell], asserted: &[Filter], facts: &[(bool, SceneFacts)], material_read: bool) {
    let mut first: HashMap<String, CellId> = HashMap::new();
    for c in cells.iter_mut() {
        if asserted.iter().any(|f| matches_filter(c, f)) {
            continue;
        }
        let (keyless, facts) = &facts[c.composition_index];
        let key = render_key(c, *keyless, facts, material_read);
        match first.get(&key) {
            Some(id) => c.twin_of = Some(id.clone()),
            None => {
                first.insert(key, c.id.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn matrix(extra: &str) -> Matrix {
        let text = format!(
            "name = \"t\"\ncompositions = [\"medusa\", \"spikes\"]\npipelines = [\"builtin\", \"urp\"]\nshaders = [\"lambert\", \"standard\"]\npresets = [\"gold\", \"plastic\"]\n[image]\nwidth = 8\nheight = 8\n{extra}"
        );
        Matrix::from_text("t.toml", &text, None, Arc::new(crate::shading::Registry::builtin())).unwrap()
    }

    #[test]
    fn product_pruning_and_ids() {
        let e = expand(&matrix("[sweep]\nsmoothness = [0.2, 0.8]\n"));
        // 2 compositions × (builtin: 2 shaders + urp: lambert) × 2 presets × 2 smoothness.
        assert_eq!(e.cells.len(), 2 * 3 * 2 * 2);
        assert_eq!(e.pruned.len(), 2, "standard is not a URP shader, once per composition");
        let ids: std::collections::HashSet<_> = e.cells.iter().map(|c| &c.id).collect();
        assert_eq!(ids.len(), e.cells.len(), "ids are unique");
        assert!(ids.contains(&CellId("medusa__builtin-forward__standard__gold__m1.00_s0.20_i1_r10".into())));
        assert!(e.cells.iter().all(|c| c.id.0.chars().all(|ch| ch.is_ascii_alphanumeric() || "_-.".contains(ch))));
    }

    /// One slider at a time: per pipeline × shader × preset, the cell at its own values and one
    /// per listed value off them, each differing from that cell in its one axis alone, and the
    /// size check counting the same.
    #[test]
    fn one_at_a_time_moves_one_axis_from_the_own_values() {
        let lists = "smoothness = [0.2, 0.8]\nlight_intensity = [0.5, 1.0, 4.0]\ncolor = [[1.0, 0.5, 0.0]]\n";
        let grid_matrix_of = |lists: &str| matrix(&format!("[sweep]\n{lists}"));
        let grid = expand(&grid_matrix_of(lists));
        let m = matrix(&format!("[sweep]\ndesign = \"one_at_a_time\"\n{lists}"));
        let e = expand(&m);
        // medusa's key light has intensity 1: that value is its own cell, not one more.
        let per_combo = 1 + 2 + 2 + 1;
        assert_eq!(e.cells.len(), 2 * 3 * 2 * per_combo, "{:?}", e.cells.iter().map(|c| &c.id).collect::<Vec<_>>());
        // The grid: 2 compositions × 3 pipeline-shaders × 2 presets × 2 smoothness × 3 intensities.
        assert_eq!(grid.cells.len(), 2 * 3 * 2 * 2 * 3);
        // 2 compositions × 2 pipelines × 2 shaders × 2 presets × (1 + 2 + 3 + 1), an upper bound.
        assert_eq!(check_size(&m, 1_000_000).unwrap(), 2 * 2 * 2 * 2 * 7);
        assert!(check_size(&grid_matrix_of(lists), 1_000_000).unwrap() == 2 * 2 * 2 * 2 * 6);
        // Within a pipeline × shader × preset, an axis's own value is the one most cells share.
        let axes = [Axis::Smoothness, Axis::LightIntensity, Axis::Color];
        let group = |c: &Cell| (c.composition.clone(), c.pipeline, c.shader.clone(), c.preset.clone());
        let mut groups: BTreeMap<_, Vec<&Cell>> = BTreeMap::new();
        for c in &e.cells {
            groups.entry(group(c)).or_default().push(c);
        }
        for cells in groups.values() {
            let own: Vec<AxisValue> = axes
                .iter()
                .map(|a| {
                    let values: Vec<AxisValue> = cells.iter().map(|c| c.get(*a)).collect();
                    let count = |v: &AxisValue| values.iter().filter(|w| *w == v).count();
                    values.iter().max_by_key(|v| count(v)).unwrap().clone()
                })
                .collect();
            let moved = |c: &Cell| axes.iter().zip(&own).filter(|(a, v)| c.get(**a) != **v).count();
            assert_eq!(cells.iter().filter(|c| moved(c) == 0).count(), 1, "one cell at the own values");
            assert!(cells.iter().all(|c| moved(c) <= 1), "a cell moves one axis at most");
        }
        let bad = Matrix::from_text(
            "t.toml",
            "name = \"t\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"gold\"]\n\
             [sweep]\ndesign = \"one_at_time\"\n",
            None,
            Arc::new(crate::shading::Registry::builtin()),
        );
        let message = bad.unwrap_err().to_string();
        assert!(message.contains("one_at_time") && message.contains("did you mean `one_at_a_time`"), "{message}");
    }

    #[test]
    fn id_numbers_read_back_as_their_values() {
        assert_eq!(id_number(1.0, 2, false), "1.00");
        assert_eq!(id_number(0.999, 2, false), "0.999");
        assert_eq!(id_number(1e-4, 2, false), "0.0001");
        assert_eq!(id_number(-0.0, 2, false), "0.00");
        assert_eq!(short_number(1.5), "1.5");
        assert_eq!(short_number(1.00001), "1.00001");
        assert_eq!(short_number(10.0), "10");
        assert_eq!(short_number(1e300), "1e300");
        for v in [0.1, 1.0 / 3.0, 1e-9, 123456.789, 0.12345, 2.5e-7, 1e300] {
            assert_eq!(id_number(v, 2, false).parse::<f64>().unwrap(), v);
            assert_eq!(short_number(v).parse::<f64>().unwrap(), v);
        }
    }

    #[test]
    fn ids_carry_each_axis_after_its_tables_prefix() {
        let e = expand(&matrix(
            "[sweep]\nsmoothness = [0.2, 0.8]\nmetallic = [0.1, 0.3]\nlight_intensity = [1.5, 2.5]\nlight_range = [3.0, 7.0]\n\
             camera_distance = [1.25, 2.0]\nlight_angle = [30.0, 60.0]\nemission = [0.5, 1.0]\ncolor = [[1.0, 0.5, 0.0]]\ntextured = [false, true]\n\
             ambient_intensity = [0.5]\nsurface = [\"fade\"]\nalpha = [0.25]\nspecular = [[0.2, 0.4, 0.6]]\n",
        ));
        let c = e.cells.iter().find(|c| c.shader == "standard" && c.textured).unwrap();
        for row in crate::declarations::axes::AXES.iter() {
            let Some(prefix) = row.id_prefix else { continue };
            let value = match row.axis {
                Axis::Metallic => id_number(c.material.metallic, 2, false),
                Axis::Smoothness => id_number(c.material.smoothness, 2, false),
                Axis::LightIntensity => short_number(c.light_intensity),
                Axis::LightRange => short_number(c.light_range),
                Axis::CameraDistance => short_number(c.camera_distance.unwrap()),
                Axis::LightAngle => short_number(c.light_angle.unwrap()),
                Axis::Emission => short_number(c.emission.unwrap()),
                Axis::AmbientIntensity => short_number(c.ambient_intensity.unwrap()),
                Axis::Color => crate::declarations::filter::color_code(c.material.slider_color_srgb),
                Axis::Textured => String::new(),
                Axis::Surface => c.material.surface.name().to_string(),
                Axis::MaterialType => continue,
                Axis::Alpha => id_number(c.material.alpha, 2, false),
                Axis::Specular => crate::declarations::filter::colour_label(Axis::Specular, c.specular),
                Axis::Params | Axis::Settings => continue,
                other => panic!("{other:?} has an id prefix but no value here"),
            };
            assert!(c.id.0.contains(&format!("{prefix}{value}")), "{}: no `{prefix}{value}` in {}", row.name, c.id);
        }
    }

    #[test]
    fn surfaces_a_pipeline_or_model_lacks_are_pruned_and_opaque_alpha_is_a_twin() {
        let text = "name = \"t\"\ncompositions = [\"default\"]\npipelines = [\"builtin\", \"urp\"]\n\
                    shaders = [\"standard\", \"lit\", \"lambert\"]\npresets = [\"plastic\"]\n\
                    [sweep]\nsurface = [\"opaque\", \"fade\", \"transparent\", \"multiply\"]\nalpha = [0.3, 0.6]\n";
        let m = Matrix::from_text("t.toml", text, None, Arc::new(crate::shading::Registry::builtin())).unwrap();
        let e = expand(&m);
        let has = |p: &str, shader: &str, s: &str| {
            e.cells.iter().any(|c| c.pipeline.name() == p && c.shader == shader && c.material.surface.name() == s)
        };
        assert!(has("builtin", "standard", "fade") && has("builtin", "standard", "transparent"));
        assert!(!has("urp", "lit", "fade"), "URP Lit has no Fade");
        assert!(has("urp", "lit", "multiply") && !has("builtin", "standard", "multiply"));
        // Lambert keeps no diffuse lobe apart: no premultiplied surface, but Fade blends it whole.
        assert!(has("builtin", "lambert", "fade") && !has("builtin", "lambert", "transparent"));
        assert!(e.pruned.iter().any(|p| p.reason.contains("keeps no diffuse lobe apart")), "{:?}", e.pruned);
        assert!(e.pruned.iter().any(|p| p.reason.contains("have no `fade` surface")), "{:?}", e.pruned);
        for c in &e.cells {
            let opaque = c.material.surface == SurfaceType::Opaque;
            let first_alpha = c.material.alpha == 0.3;
            assert_eq!(c.twin_of.is_some(), opaque && !first_alpha, "{}", c.id);
        }
        let typo = text.replace("\"fade\"", "\"faed\"");
        let err = Matrix::from_text("t.toml", &typo, None, Arc::new(crate::shading::Registry::builtin())).unwrap_err();
        assert!(err.to_string().contains("did you mean `fade`?"), "{err}");
    }

    #[test]
    fn material_types_set_hdrp_lits_parameters_and_prune_elsewhere() {
        use crate::shading::material_type::MaterialType;
        let text = "name = \"t\"\ncompositions = [\"default\"]\npipelines = [\"urp\", \"hdrp\"]\n\
                    shaders = [\"lit\", \"lambert\"]\npresets = [\"plastic\"]\n\
                    [sweep]\nmaterial_type = [\"standard\", \"specular_color\", \"iridescence\"]\n\
                    [sweep.params]\niridescence_thickness = [0.3, 0.7]\n";
        let m = Matrix::from_text("t.toml", text, None, Arc::new(crate::shading::Registry::builtin())).unwrap();
        let e = expand(&m);
        let cells = |p: &str, shader: &str, t: MaterialType| -> Vec<&Cell> {
            e.cells
                .iter()
                .filter(|c| c.pipeline.name() == p && c.shader == shader && c.coords.material_type == Some(t))
                .collect()
        };
        // HDRP Lit has all three, URP Lit the specular setup too, Lambert only the standard type.
        assert_eq!(cells("hdrp", "lit", MaterialType::Iridescence).len(), 2);
        assert_eq!(cells("urp", "lit", MaterialType::SpecularColor).len(), 1);
        assert!(cells("urp", "lit", MaterialType::Iridescence).is_empty());
        assert!(cells("urp", "lambert", MaterialType::SpecularColor).is_empty());
        assert_eq!(cells("urp", "lambert", MaterialType::Standard).len(), 1);
        assert!(
            e.pruned
                .iter()
                .any(|p| p.description.contains("urp × lit × iridescence") && p.reason.contains("iridescence_mask")),
            "{:?}",
            e.pruned
        );
        // The type's parameters reach the surface; the ids spell it.
        let film = cells("hdrp", "lit", MaterialType::Iridescence)[0];
        let s = film.surface();
        assert_eq!((s.params[1], s.params[crate::shading::twin::IRIDESCENCE_MASK_SLOT]), (0.0, 1.0));
        assert!(film.id.0.contains("_iridescence"), "{}", film.id);
        let spec = cells("hdrp", "lit", MaterialType::SpecularColor)[0];
        assert_eq!(spec.surface().params[1], 1.0);
        // Without the film its thickness changes nothing: the second thickness is a twin.
        let standard = cells("hdrp", "lit", MaterialType::Standard);
        assert_eq!(standard.iter().filter(|c| c.twin_of.is_some()).count(), 1, "{standard:?}");
        assert!(cells("hdrp", "lit", MaterialType::Iridescence).iter().all(|c| c.twin_of.is_none()));
        // The Anisotropy type takes the swept slider; the other types have none, and say so in their ids.
        let aniso = text
            .replace("\"iridescence\"]", "\"iridescence\", \"anisotropy\"]")
            .replace("iridescence_thickness = [0.3, 0.7]", "anisotropy = [0.5, -0.25]");
        let m = Matrix::from_text("t.toml", &aniso, None, Arc::new(crate::shading::Registry::builtin())).unwrap();
        let e = expand(&m);
        let of = |t: MaterialType| {
            e.cells
                .iter()
                .filter(move |c| c.pipeline == Pipeline::Hdrp && c.shader == "lit" && c.coords.material_type == Some(t))
        };
        let slot = crate::shading::twin::ANISOTROPY_SLOT;
        let mut values: Vec<f64> = of(MaterialType::Anisotropy).map(|c| c.surface().params[slot]).collect();
        values.sort_by(f64::total_cmp);
        assert_eq!(values, vec![-0.25, 0.5]);
        assert!(of(MaterialType::Anisotropy).all(|c| c.id.0.contains("_anisotropy")));
        assert_eq!(of(MaterialType::Standard).count(), 1, "one Standard cell, not one per anisotropy");
        assert!(of(MaterialType::Standard).all(|c| c.surface().params[slot] == 0.0 && !c.id.0.contains("_anisotropy0")));
        assert!(e.pruned.iter().any(|p| p.description.contains("urp × lit × anisotropy")), "{:?}", e.pruned);
        // A type and a parameter it sets may not both be swept; a typo is named.
        let both = text.replace("iridescence_thickness", "specular_setup").replace("0.3, 0.7", "0, 1");
        let err = Matrix::from_text("t.toml", &both, None, Arc::new(crate::shading::Registry::builtin())).unwrap_err();
        assert!(err.to_string().contains("sweep.params.specular_setup"), "{err}");
        let typo = text.replace("\"iridescence\"]", "\"iridesence\"]");
        let err = Matrix::from_text("t.toml", &typo, None, Arc::new(crate::shading::Registry::builtin())).unwrap_err();
        assert!(err.to_string().contains("did you mean `iridescence`?"), "{err}");
    }

    #[test]
    fn the_specular_axis_sets_the_specular_colour_where_the_model_reads_one() {
        let text = "name = \"t\"\ncompositions = [\"default\"]\npipelines = [\"builtin\"]\n\
                    shaders = [\"standard\", \"phong\", \"lambert\"]\npresets = [\"plastic\"]\n\
                    [sweep]\nspecular = [\"model\", [0.5, 0.25, 1.0]]\n[sweep.params]\nspecular_setup = [0, 1]\n";
        let m = Matrix::from_text("t.toml", text, None, Arc::new(crate::shading::Registry::builtin())).unwrap();
        let e = expand(&m);
        let want = glam::DVec3::from([0.5, 0.25, 1.0].map(crate::color::srgb_to_linear));
        for c in e.cells.iter().filter(|c| c.specular.is_some()) {
            let reads = c.shader == "phong" || c.params.get("specular_setup") == Some(&1.0);
            assert_eq!(c.surface().specular == want, reads, "{}", c.id);
            assert_eq!(c.twin_of.is_some(), !reads, "{}", c.id);
            assert!(c.id.0.ends_with("_sp8040ff"), "{}", c.id);
        }
        let typo = text.replace("\"model\"", "\"modle\"");
        let err = Matrix::from_text("t.toml", &typo, None, Arc::new(crate::shading::Registry::builtin())).unwrap_err();
        assert!(err.to_string().contains("`modle` is not a colour") && err.to_string().contains("\"model\""), "{err}");
    }

    #[test]
    fn own_material_needs_a_gltf_subject() {
        let text = "name = \"t\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lit\"]\npresets = [\"own\", \"gold\"]\n";
        let m = Matrix::from_text("t.toml", text, None, Arc::new(crate::shading::Registry::builtin())).unwrap();
        let e = expand(&m);
        assert!(e.cells.iter().all(|c| c.preset == "gold"), "no `own` cells for a procedural subject");
        assert!(e.pruned.iter().any(|p| p.reason.contains("not a glTF file")), "{:?}", e.pruned);
        let typo = text.replace("\"own\"", "\"onw\"");
        let err = Matrix::from_text("t.toml", &typo, None, Arc::new(crate::shading::Registry::builtin())).unwrap_err();
        assert!(err.to_string().contains("did you mean `own`?"), "{err}");
    }

    #[test]
    fn lambert_cells_differing_in_smoothness_are_twins() {
        let e = expand(&matrix("[sweep]\nsmoothness = [0.2, 0.8]\nmetallic = [0.0, 1.0]\n"));
        for c in &e.cells {
            let twin = c.twin_of.is_some();
            if c.shader == "standard" {
                assert!(!twin, "standard reads every axis: {}", c.id);
            } else {
                let first = c.material.smoothness == 0.2 && c.material.metallic == 0.0;
                assert_eq!(twin, !first, "{}", c.id);
            }
        }
    }

    #[test]
    fn invariant_asserts_render_their_cells_and_keyless_compositions_twin_across_light() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let text = "name = \"t\"\ncompositions = [\"scenes/invariants/furnace.toml\", \"medusa\"]\npipelines = [\"urp\"]\n\
                    shaders = [\"lambert\", \"lit\"]\npresets = [\"plastic\"]\n[image]\nwidth = 8\nheight = 8\n\
                    [sweep]\nsmoothness = [0.2, 0.8]\nlight_intensity = [1.0, 2.0]\n\
                    [[assert]]\nkind = \"invariant\"\nwhere = { composition = \"medusa\", shader = \"lambert\" }\nalong = \"smoothness\"\n";
        let m = Matrix::from_text("t.toml", text, Some(root), Arc::new(crate::shading::Registry::builtin())).unwrap();
        let e = expand(&m);
        let twins = |comp: &str, shader: &str| {
            e.cells.iter().filter(|c| c.composition == comp && c.shader == shader && c.twin_of.is_some()).count()
        };
        // The furnace has no key light: intensity changes nothing, lit's 4 cells are 2 images.
        assert_eq!(twins("white_furnace", "lit"), 2);
        // Lambert there ignores smoothness too: one image of 4.
        assert_eq!(twins("white_furnace", "lambert"), 3);
        // The invariant covers medusa's Lambert cells: all rendered, though Lambert ignores smoothness.
        assert_eq!(twins("medusa", "lambert"), 0);
        assert_eq!(twins("medusa", "lit"), 0);
    }

    #[test]
    fn simple_lit_reads_smoothness_only_with_highlights_on() {
        let text = "name = \"t\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"simple_lit\"]\npresets = [\"gold\"]\n[sweep]\nsmoothness = [0.2, 0.8]\n";
        let m = |extra: &str| {
            Matrix::from_text("t.toml", &format!("{text}{extra}"), None, Arc::new(crate::shading::Registry::builtin()))
                .unwrap()
        };
        let off = expand(&m(""));
        assert_eq!(off.rendered().count(), 1, "highlights off by default: smoothness changes nothing");
        let on = expand(&m("[sweep.params]\nspecular_highlights = [1.0]\n"));
        assert_eq!(on.rendered().count(), 2);
        assert!(on.cells.iter().all(|c| c.id.0.ends_with("_specular_highlights1")), "{:?}", on.cells[0].id);
    }

    #[test]
    fn only_and_exclude_filters() {
        let e = expand(&matrix(
            "[[only]]\ncomposition = \"spikes\"\n[[exclude]]\nshader = \"lambert\"\npipeline = \"urp\"\n",
        ));
        assert!(e.cells.iter().all(|c| c.composition == "spikes"));
        assert!(!e.cells.iter().any(|c| c.shader == "lambert" && c.pipeline == Pipeline::Urp));
        assert_eq!(e.cells.len(), 2 * 2, "builtin × {{lambert, standard}} × 2 presets");
        assert_eq!(e.filtered_out, 6 + 2);
    }

    #[test]
    fn colour_slider_is_linearised_and_named() {
        let e = expand(&matrix("[sweep]\ncolor = [[1.0, 0.5, 0.0]]\n"));
        let c = &e.cells[0];
        assert!((c.material.base_color_linear[1] - crate::color::srgb_to_linear(0.5)).abs() < 1e-12);
        assert!(c.id.0.contains("_cff8000_"), "{}", c.id);
    }

    #[test]
    fn colour_is_an_axis_of_filters() {
        let m = matrix("[sweep]\ncolor = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]\n[[exclude]]\ncolor = [[0.0, 0.0, 1.0]]\n");
        let e = expand(&m);
        assert!(!e.cells.is_empty() && e.cells.iter().all(|c| c.id.0.contains("_cff0000_")), "blue excluded");
        let only = m.parse_only("color=#ff0000").unwrap();
        assert!(e.cells.iter().all(|c| matches_filter(c, &only)));
        let err = m.parse_only("color=00ff00").unwrap_err().to_string();
        assert!(err.contains("00ff00") && err.contains("ff0000"), "{err}");
    }

    #[test]
    fn filter_names_are_checked() {
        let text = "name = \"t\"\ncompositions = [\"medusa\"]\npipelines = [\"urp\"]\nshaders = [\"lambert\"]\npresets = [\"gold\"]\n[image]\nwidth = 8\nheight = 8\n[[only]]\npreset = \"gould\"\n";
        let err = Matrix::from_text("t.toml", text, None, Arc::new(crate::shading::Registry::builtin()))
            .unwrap_err()
            .to_string();
        assert!(err.contains("only[0].preset") && err.contains("did you mean `gold`?"), "{err}");
    }
}
