//! Matrix files (`matrices/*.toml`): the axes to sweep, the image size, timing and filters.

use crate::pipelines::surface::SurfaceType;
use serde::Deserialize;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::Path;

use super::asserts::{parse_assert, InvariantKind, InvariantSpec};
pub use super::filter::{color_code, colour_label, parse_filter, Axis, Filter, FilterValue};
use super::presets::{preset_names, Preset};
use super::scene::Scene;
use super::study::Approximation;
pub use super::sweep::Sweep;
use crate::error::{Error, InputError};
use crate::input::names::unknown_name;
use crate::input::source::parse_toml;
use crate::input::validate::Checker;
use crate::pipelines::{Antialiasing, LightBudget, Pipeline, RenderPath, Tonemap};
use crate::shading::Registry;
use std::sync::Arc;

/// The matrix `shadematrix run` uses with no argument.
pub const DEFAULT_MATRIX: &str = include_str!("../../matrices/default.toml");

pub const MAX_IMAGE_SIZE: u32 = 8192;

/// `[lights]` as written: a budget left out takes its default (URP's from the URP asset).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightsFile {
    pixel_light_count: Option<u32>,
    urp_per_object_limit: Option<u32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MatrixFile {
    name: String,
    #[serde(default)]
    description: String,
    compositions: Vec<String>,
    pipelines: Vec<String>,
    #[serde(default = "default_paths")]
    paths: Vec<String>,
    shaders: Vec<String>,
    presets: Vec<String>,
    #[serde(default)]
    sweep: Sweep,
    #[serde(default)]
    image: ImageSize,
    /// The tonemapper: one name for every pipeline, or a table by pipeline
    /// (`tonemap = { hdrp = "neutral" }`); pipelines left out keep the one they ship with.
    #[serde(default)]
    tonemap: Option<toml::Value>,
    /// MSAA on forward paths: `antialiasing = "msaa4"` for every pipeline or a table by pipeline;
    /// pipelines left out keep their default (built-in msaa4, URP and HDRP none).
    #[serde(default)]
    antialiasing: Option<toml::Value>,
    #[serde(default)]
    timing: Timing,
    /// How cells' files are written (`declarations::outputs`).
    #[serde(default)]
    outputs: crate::declarations::outputs::Outputs,
    /// Where FLIP and SSIM are computed: `"auto"` (default: the GPU on a hardware adapter, the
    /// CPU on a software one such as lavapipe, where compute passes run slower than flip-rs on the
    /// same cores), `"gpu"` (`compare::gpu`) or `"cpu"` (flip-rs and `compare::ssim`, the references).
    #[serde(default)]
    metrics: MetricsDevice,
    /// Light budgets: `pixel_light_count` (built-in forward, default 4) and
    /// `urp_per_object_limit` (default 4, at most 8).
    #[serde(default)]
    lights: LightsFile,
    /// The engine settings (`pipelines::settings`): `[pipeline_settings.urp] asset = "default" |
    /// "high_fidelity"` with any field overridden, `[pipeline_settings.builtin] forward_add`.
    #[serde(default)]
    pipeline_settings: crate::pipelines::settings::PipelineSettingsFile,
    #[serde(default)]
    only: Vec<toml::Table>,
    /// What cells are compared against: `{ pipeline = "hdrp", shader = "lit" }` (another cell with
    /// the other axes equal), `"supersampled"` or `{ supersampled = N }`, or `{ run = "DIR" }`.
    #[serde(default)]
    reference: Option<toml::Value>,
    /// The approximation study (declarations::study): `approximations = ["ambient", "environment",
    /// "visibility", "msaa"]`, each cell rendered again without each; needs a truth reference.
    #[serde(default)]
    approximations: Vec<String>,
    /// Contact sheets: `[{ rows = "smoothness", cols = "metallic" }]`; default: pipelines × presets
    /// and smoothness × metallic, the other axes as separate sheets.
    #[serde(default)]
    sheets: Option<Vec<crate::declarations::sheets::SheetSpec>>,
    #[serde(default)]
    exclude: Vec<toml::Table>,
    /// Invariants checked after the run (`declarations::asserts`).
    #[serde(default, rename = "assert")]
    asserts: Vec<toml::Table>,
    /// A folder of user models (NAME.wgsl + NAME.toml), relative to the matrix file. Read before
    /// the matrix is validated, so its models can be named in `shaders` (`models_dir`).
    #[serde(default)]
    #[allow(dead_code)]
    models: Option<String>,
}

/// The longest matrix name: its run folder's name adds `-YYYYmmdd-HHMMSS-N`.
pub const MAX_NAME_BYTES: usize = 200;

/// The origin the embedded default matrix records (`run.json`'s `matrix.origin`).
pub const EMBEDDED_ORIGIN: &str = "<embedded default matrix>";

/// The `models` key of a matrix file, resolved against the file's folder, without validating the
/// rest: user models must be registered before the matrix's shader names are checked.
pub fn models_dir(path: &Path) -> Result<Option<std::path::PathBuf>, Error> {
    #[derive(Deserialize)]
    struct ModelsKey {
        models: Option<String>,
    }
    let shown = path.display().to_string();
    let text = crate::input::source::read_text(path)?;
    let key: ModelsKey = parse_toml(&shown, &text)?;
    Ok(key.models.map(|m| path.parent().unwrap_or(Path::new(".")).join(m)))
}

fn default_paths() -> Vec<String> {
    vec!["forward".into()]
}

/// Optional in a matrix: 256×256 unless given.
#[derive(Debug, Clone, Copy, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct ImageSize {
    #[serde(default = "default_side")]
    pub width: u32,
    #[serde(default = "default_side")]
    pub height: u32,
}

fn default_side() -> u32 {
    256
}

impl Default for ImageSize {
    fn default() -> Self {
        ImageSize { width: default_side(), height: default_side() }
    }
}

#[derive(Debug, Clone, Copy, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Timing {
    /// Frames rendered and timed per cell (the image is the last one).
    #[serde(default = "one_frame")]
    pub frames: u32,
    /// Untimed frames before those.
    #[serde(default)]
    pub warmup: u32,
    /// Time every cell; by default one cell per timing class is timed and the others of its class
    /// take its figures (`plan::timing`).
    #[serde(default)]
    pub every_cell: bool,
}

/// Where a run computes FLIP and SSIM (`metrics = "gpu" | "cpu"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MetricsDevice {
    #[default]
    Auto,
    Gpu,
    Cpu,
}

impl MetricsDevice {
    /// Whether the metrics run on the GPU of an adapter of `device_type` (wgpu's, as recorded).
    pub fn on_gpu(self, device_type: &str) -> bool {
        match self {
            MetricsDevice::Gpu => true,
            MetricsDevice::Cpu => false,
            MetricsDevice::Auto => device_type != "Cpu",
        }
    }
}

fn one_frame() -> u32 {
    1
}

impl Default for Timing {
    fn default() -> Self {
        Self { frames: 1, warmup: 0, every_cell: false }
    }
}

#[derive(Debug, Clone)]
pub struct Matrix {
    /// The models its shader names resolve to.
    pub registry: Arc<Registry>,
    pub name: String,
    pub description: String,
    /// Where it came from: a path or `<embedded default matrix>`.
    pub origin: String,
    /// SHA-256 of the matrix text.
    pub hash: String,
    pub compositions: Vec<Scene>,
    pub pipelines: Vec<Pipeline>,
    pub paths: Vec<RenderPath>,
    pub shaders: Vec<String>,
    pub presets: Vec<&'static Preset>,
    pub sweep: Sweep,
    pub image: ImageSize,
    /// The tonemapper of each pipeline, by `Pipeline::shader_id`.
    pub tonemaps: [Tonemap; 3],
    /// The anti-aliasing of each pipeline, by `Pipeline::shader_id`.
    pub antialiasing: [Antialiasing; 3],
    pub light_budget: LightBudget,
    pub pipeline_settings: crate::pipelines::settings::PipelineSettings,
    pub timing: Timing,
    pub outputs: crate::declarations::outputs::Outputs,
    pub metrics: MetricsDevice,
    pub only: Vec<Filter>,
    pub exclude: Vec<Filter>,
    pub reference: Option<ReferenceSpec>,
    /// The approximation study's list, in the file's order without repeats.
    pub approximations: Vec<Approximation>,
    pub sheets: Vec<crate::declarations::sheets::SheetSpec>,
    /// `[[assert]]` invariants, checked after the run.
    pub asserts: Vec<InvariantSpec>,
}

/// What each cell is compared against.
#[derive(Debug, Clone, PartialEq)]
pub enum ReferenceSpec {
    /// The cell with these axes changed and the others equal.
    Cell(Vec<(Axis, FilterValue)>),
    /// The same cell rendered at N× the resolution and box-filtered down.
    Supersampled(u32),
    /// The cell of the same id in an earlier run folder.
    Run(std::path::PathBuf),
    /// The cell's ground truth, path traced (render::truth).
    Truth(TruthSpec),
}

/// `reference = "truth"` or `{ truth = "same-brdf" | "physical", spp = N, noise = X, bounces = B }`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthSpec {
    pub settings: TruthSettings,
}

/// Which truth: each surface's own model in the pipeline's units and falloff, or one physical
/// model with physical falloff for every cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TruthKind {
    SameBrdf,
    Physical,
}

impl TruthKind {
    pub fn name(self) -> &'static str {
        match self {
            TruthKind::SameBrdf => "same-brdf",
            TruthKind::Physical => "physical",
        }
    }
}

/// How a truth is rendered: which, where convergence stops and how deep paths go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthSettings {
    pub kind: TruthKind,
    /// Most samples per pixel.
    pub spp: u32,
    /// The target: the subject's mean standard error over its mean radiance (0.005 = 0.5 %).
    pub noise: f64,
    /// Indirect bounces after the first hit.
    pub bounces: u32,
    /// Samples per pixel per dispatch (the convergence check runs between batches).
    pub batch: u32,
    /// Where the truth is traced (`render::truth::cpu` or the GPU's compute pass).
    pub backend: TruthBackend,
    /// The random numbers of its paths.
    pub sampler: TruthSampler,
    /// Past `bounces`, paths go on under Russian roulette (survival min(0.95, the throughput's
    /// largest channel), weighted by its inverse): every further bounce, unbiased, up to
    /// `MAX_ROULETTE_BOUNCES` (a path survives that long with probability below 0.95¹⁰²⁴ ≈ 10⁻²³).
    pub roulette: bool,
}

/// The most bounces a path under Russian roulette takes.
pub const MAX_ROULETTE_BOUNCES: u32 = 1024;

/// `sampler` of a truth: `independent` (PCG) draws independent samples, so each pixel's sample
/// variance gives an unbiased standard error for the Z-test; `sobol` (CPU backend) draws
/// Owen-scrambled Sobol points (Burley 2020, the `sobol_burley` crate), lower error for the same
/// samples, whose per-sample variance then overstates the standard error (conservative noise).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TruthSampler {
    #[default]
    Independent,
    Sobol,
}

impl TruthSampler {
    pub const NAMES: [&'static str; 2] = ["independent", "sobol"];
}

/// `backend` of a truth: `auto` traces on the CPU when the adapter is itself a CPU (llvmpipe,
/// WARP, SwiftShader) and the cell's models have f64 twins, else on the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TruthBackend {
    #[default]
    Auto,
    Gpu,
    Cpu,
}

impl TruthBackend {
    pub const NAMES: [&'static str; 3] = ["auto", "gpu", "cpu"];

    pub fn name(self) -> &'static str {
        match self {
            TruthBackend::Auto => "auto",
            TruthBackend::Gpu => "gpu",
            TruthBackend::Cpu => "cpu",
        }
    }
}

impl Default for TruthSettings {
    fn default() -> Self {
        TruthSettings {
            kind: TruthKind::SameBrdf,
            spp: 4096,
            noise: 0.005,
            bounces: 2,
            batch: 16,
            backend: TruthBackend::Auto,
            sampler: TruthSampler::Independent,
            roulette: false,
        }
    }
}

impl TruthSpec {
    pub const KINDS: [&'static str; 2] = ["same-brdf", "physical"];
}

fn parse_reference(c: &Checker, value: &toml::Value, base_dir: Option<&Path>) -> Result<ReferenceSpec, InputError> {
    let allowed =
        "\"supersampled\", { supersampled = N }, { run = \"DIR\" }, \"truth\", { truth = \"same-brdf\" | \"physical\", spp = N, noise = X, bounces = B, backend = \"auto\" | \"gpu\" | \"cpu\" } or a table of axes to change";
    match value {
        toml::Value::String(s) if s == "supersampled" => Ok(ReferenceSpec::Supersampled(4)),
        toml::Value::String(s) if s == "truth" => {
            Ok(ReferenceSpec::Truth(TruthSpec { settings: TruthSettings::default() }))
        }
        toml::Value::Table(t) if t.contains_key("truth") => parse_truth(c, t).map(ReferenceSpec::Truth),
        toml::Value::String(s) => Err(c.err("reference", format!("`{s}` is not a reference; allowed: {allowed}"))),
        toml::Value::Table(t) if t.contains_key("supersampled") => match (t.len(), &t["supersampled"]) {
            (1, toml::Value::Integer(n)) if (2..=8).contains(n) => Ok(ReferenceSpec::Supersampled(*n as u32)),
            _ => Err(c.err("reference.supersampled", "the factor must be an integer in 2..=8, alone in the table")),
        },
        toml::Value::Table(t) if t.contains_key("run") => match (t.len(), &t["run"]) {
            (1, toml::Value::String(dir)) => {
                let path = match base_dir {
                    Some(b) => b.join(dir),
                    None => dir.into(),
                };
                // Not a run: every cell would be "compared" with files that do not exist.
                if !path.join("run.json").is_file() {
                    return Err(c.err(
                        "reference.run",
                        format!("`{dir}` ({}) is not a run folder (no run.json)", path.display()),
                    ));
                }
                Ok(ReferenceSpec::Run(path))
            }
            _ => Err(c.err("reference.run", "give the run folder as a string, alone in the table")),
        },
        toml::Value::Table(t) => {
            let names: Vec<&str> = super::axes::reference_axes().map(|a| a.name()).collect();
            let filter = parse_filter(c, "reference", t)?;
            for (axis, values) in &filter.terms {
                if !super::axes::reference_axes().any(|a| a == *axis) {
                    return Err(crate::input::names::unknown_name(
                        c.file(),
                        &format!("reference.{}", axis.name()),
                        "reference axis",
                        axis.name(),
                        &names,
                    ));
                }
                if values.len() != 1 {
                    return Err(c.err(&format!("reference.{}", axis.name()), "a reference names one value per axis"));
                }
            }
            if filter.terms.is_empty() {
                return Err(c.err("reference", format!("the table is empty; allowed: {allowed}")));
            }
            Ok(ReferenceSpec::Cell(filter.terms.into_iter().map(|(a, mut v)| (a, v.remove(0))).collect()))
        }
        other => Err(c.err("reference", format!("{other} is not a reference; allowed: {allowed}"))),
    }
}

fn parse_truth(c: &Checker, t: &toml::map::Map<String, toml::Value>) -> Result<TruthSpec, InputError> {
    let mut settings = TruthSettings::default();
    for (key, value) in t {
        let at = format!("reference.{key}");
        match (key.as_str(), value) {
            ("truth", toml::Value::String(kind)) if kind == "same-brdf" => settings.kind = TruthKind::SameBrdf,
            ("truth", toml::Value::String(kind)) if kind == "physical" => settings.kind = TruthKind::Physical,
            ("truth", other) => {
                return Err(crate::input::names::unknown_name(
                    c.file(),
                    &at,
                    "truth",
                    other.to_string().trim_matches('"'),
                    &TruthSpec::KINDS,
                ))
            }
            ("spp", toml::Value::Integer(n)) if (1..=1 << 20).contains(n) => settings.spp = *n as u32,
            ("spp", other) => return Err(c.err(&at, format!("{other}: samples per pixel, an integer in 1..=1048576"))),
            ("noise", v)
                if v.as_float().or(v.as_integer().map(|i| i as f64)).is_some_and(|x| (0.0..1.0).contains(&x)) =>
            {
                settings.noise = v.as_float().or(v.as_integer().map(|i| i as f64)).unwrap_or(settings.noise)
            }
            ("noise", other) => {
                return Err(c.err(
                    &at,
                    format!("{other}: the target relative standard error, a number in [0, 1) (0.005 = 0.5 %)"),
                ))
            }
            ("bounces", toml::Value::Integer(n)) if (0..=16).contains(n) => settings.bounces = *n as u32,
            ("bounces", other) => return Err(c.err(&at, format!("{other}: indirect bounces, an integer in 0..=16"))),
            ("backend", toml::Value::String(b)) if TruthBackend::NAMES.contains(&b.as_str()) => {
                settings.backend = match b.as_str() {
                    "gpu" => TruthBackend::Gpu,
                    "cpu" => TruthBackend::Cpu,
                    _ => TruthBackend::Auto,
                }
            }
            ("backend", other) => {
                return Err(crate::input::names::unknown_name(
                    c.file(),
                    &at,
                    "truth backend",
                    other.to_string().trim_matches('"'),
                    &TruthBackend::NAMES,
                ))
            }
            ("roulette", toml::Value::Boolean(b)) => settings.roulette = *b,
            ("roulette", other) => {
                return Err(c.err(&at, format!("{other}: true (every bounce past `bounces`, unbiased) or false")))
            }
            ("sampler", toml::Value::String(s)) if TruthSampler::NAMES.contains(&s.as_str()) => {
                settings.sampler = if s == "sobol" { TruthSampler::Sobol } else { TruthSampler::Independent }
            }
            ("sampler", other) => {
                return Err(crate::input::names::unknown_name(
                    c.file(),
                    &at,
                    "truth sampler",
                    other.to_string().trim_matches('"'),
                    &TruthSampler::NAMES,
                ))
            }
            (other, _) => {
                return Err(crate::input::names::unknown_name(
                    c.file(),
                    &at,
                    "truth key",
                    other,
                    &["truth", "spp", "noise", "bounces", "backend", "sampler", "roulette"],
                ))
            }
        }
    }
    if settings.sampler == TruthSampler::Sobol && settings.backend == TruthBackend::Gpu {
        return Err(c.err(
            "reference.sampler",
            "\"sobol\" runs on the CPU backend only: use backend = \"cpu\" or \"auto\", or sampler = \"independent\"",
        ));
    }
    Ok(TruthSpec { settings })
}

impl Matrix {
    /// The cells `invariant` asserts cover: rendered, never copied as twins.
    pub fn invariant_filters(&self) -> Vec<Filter> {
        self.asserts.iter().filter(|a| a.kind == InvariantKind::Invariant).map(|a| a.filter.clone()).collect()
    }

    /// The tonemapper cells of `p` use.
    pub fn tonemap_for(&self, p: Pipeline) -> Tonemap {
        self.tonemaps[p.shader_id() as usize]
    }

    /// The anti-aliasing cells of `p` ask for (forward paths use it; `Antialiasing::samples_on`).
    pub fn antialiasing_for(&self, p: Pipeline) -> Antialiasing {
        self.antialiasing[p.shader_id() as usize]
    }

    pub fn load_default(registry: Arc<Registry>) -> Result<Matrix, Error> {
        Self::from_text(EMBEDDED_ORIGIN, DEFAULT_MATRIX, Some(Path::new(".")), registry)
    }

    /// Shader names are checked against `registry`, which the matrix keeps for its cells.
    pub fn load(path: &Path, registry: Arc<Registry>) -> Result<Matrix, Error> {
        let shown = path.display().to_string();
        let text = crate::input::source::read_text(path)?;
        Self::from_text(&shown, &text, path.parent(), registry)
    }

    /// Parse and validate; compositions given as paths resolve against `base_dir`.
    pub fn from_text(
        origin: &str,
        text: &str,
        base_dir: Option<&Path>,
        registry: Arc<Registry>,
    ) -> Result<Matrix, Error> {
        let file: MatrixFile = parse_toml(origin, text)?;
        let c = Checker::new(origin);
        c.name("name", &file.name)?;
        // The run folder is `<name>-<date>-<time>[-N]`: a name that leaves it no room in a file
        // name's 255 bytes failed only when the run folder was made.
        if file.name.len() > MAX_NAME_BYTES {
            return Err(c
                .err(
                    "name",
                    format!("`{}` is {} bytes; a matrix name has at most {MAX_NAME_BYTES}", file.name, file.name.len()),
                )
                .into());
        }
        non_empty(&c, "compositions", &file.compositions)?;
        non_empty(&c, "pipelines", &file.pipelines)?;
        non_empty(&c, "paths", &file.paths)?;
        non_empty(&c, "shaders", &file.shaders)?;
        non_empty(&c, "presets", &file.presets)?;

        let mut compositions = Vec::new();
        for (i, name) in file.compositions.iter().enumerate() {
            let scene = Scene::load(name, base_dir, origin, &format!("compositions[{i}]"))?;
            if compositions.iter().any(|s: &Scene| s.name == scene.name) {
                return Err(c
                    .err(&format!("compositions[{i}]"), format!("composition `{}` is listed twice", scene.name))
                    .into());
            }
            compositions.push(scene);
        }
        let pipelines =
            names_to(&c, origin, "pipelines", "pipeline", &file.pipelines, &Pipeline::names(), Pipeline::from_name)?;
        let paths =
            names_to(&c, origin, "paths", "rendering path", &file.paths, &RenderPath::names(), RenderPath::from_name)?;
        let model_names = registry.names();
        for (i, s) in file.shaders.iter().enumerate() {
            if !model_names.contains(&s.as_str()) {
                return Err(unknown_name(origin, &format!("shaders[{i}]"), "shader", s, &model_names).into());
            }
        }
        let presets = if file.presets.len() == 1 && file.presets[0] == "all" {
            super::presets::PRESETS.iter().collect()
        } else {
            let valid = super::presets::matrix_preset_names();
            let mut v = Vec::new();
            for (i, p) in file.presets.iter().enumerate() {
                v.push(
                    super::presets::find_matrix_preset(p)
                        .ok_or_else(|| unknown_name(origin, &format!("presets[{i}]"), "preset", p, &valid))?,
                );
            }
            v
        };

        let s = &file.sweep;
        // Each numeric axis's values within its row's range (`declarations::axes`).
        for row in super::axes::AXES.iter().filter(|r| r.kind == super::axes::AxisKind::Number) {
            let (axis, Some((lo, hi))) = (row.axis, row.range) else { continue };
            for (i, v) in s.numbers(axis).iter().enumerate() {
                c.range(&format!("sweep.{}[{i}]", row.name), *v, lo, hi)?;
            }
        }
        for row in super::axes::AXES.iter().filter(|r| r.kind == super::axes::AxisKind::Colour) {
            let colours = s.colours(row.axis);
            for (i, col) in colours.iter().enumerate() {
                let key = format!("sweep.{}[{i}]", row.name);
                c.color(&key, *col)?;
                // Cells, filters and sheets name a colour by its 8-bit hex code: two colours with
                // one code would be one cell labelled as either.
                if let Some(j) =
                    colours[..i].iter().position(|o| o != col && color_code(Some(*o)) == color_code(Some(*col)))
                {
                    return Err(c
                        .err(
                            &key,
                            format!(
                                "colour {col:?} has the hex code `{}` of sweep.{}[{j}] {:?}; cells are named by \
                                 that code, so sweep colours must differ in 8-bit sRGB (steps of 1/255)",
                                color_code(Some(*col)),
                                row.name,
                                colours[j]
                            ),
                        )
                        .into());
                }
            }
        }
        check_params(&c, origin, &s.params, &file.shaders, &pipelines, &registry)?;
        // A material type is a setting of parameters: the two may not both set one.
        if !s.material_type.is_empty() {
            let types = crate::shading::material_type::MaterialType::param_names();
            if let Some(name) = s.params.keys().find(|k| types.contains(&k.as_str())) {
                return Err(c
                    .err(
                        &format!("sweep.params.{name}"),
                        format!(
                        "sweep.material_type sets `{name}` for every cell; sweep one or the other (a material type \
                         sets {})",
                        types.join(" and ")
                    ),
                    )
                    .into());
            }
        }
        let pipeline_settings = file.pipeline_settings.resolve().map_err(|(key, message)| {
            let key = format!("pipeline_settings.{key}");
            match (key.as_str(), &file.pipeline_settings.urp) {
                ("pipeline_settings.urp.asset", u) => {
                    let names = crate::pipelines::settings::UrpAssetPreset::names();
                    unknown_name(origin, &key, "URP asset", u.asset.as_deref().unwrap_or_default(), &names)
                }
                ("pipeline_settings.hdrp.light_unit", _) => unknown_name(
                    origin,
                    &key,
                    "HDRP light unit",
                    file.pipeline_settings.hdrp.light_unit.as_deref().unwrap_or_default(),
                    &crate::pipelines::settings::HdrpLightUnit::names(),
                ),
                ("pipeline_settings.urp.msaa", u) => unknown_name(
                    origin,
                    &key,
                    "anti-aliasing",
                    u.msaa.as_deref().unwrap_or_default(),
                    &Antialiasing::names(),
                ),
                _ => c.err(&key, message),
            }
        })?;
        let builtin_level = file.pipeline_settings.builtin.quality_level.unwrap_or_default().fields();
        let light_budget = LightBudget {
            // The quality level's pixelLightCount unless `[lights]` names one.
            pixel_light_count: file.lights.pixel_light_count.unwrap_or(builtin_level.1),
            urp_per_object_limit: file
                .lights
                .urp_per_object_limit
                .unwrap_or(pipeline_settings.urp.additional_lights_per_object_limit),
        };
        c.range("lights.pixel_light_count", light_budget.pixel_light_count as f64, 0.0, 64.0)?;
        c.range("lights.urp_per_object_limit", light_budget.urp_per_object_limit as f64, 0.0, 8.0)?;
        let tonemaps = parse_per_pipeline(
            &c,
            origin,
            ("tonemap", "tonemapper"),
            file.tonemap.as_ref(),
            Pipeline::default_tonemap,
            Tonemap::from_name,
            &Tonemap::names(),
        )?;
        let mut antialiasing = parse_per_pipeline(
            &c,
            origin,
            ("antialiasing", "anti-aliasing"),
            file.antialiasing.as_ref(),
            Pipeline::default_antialiasing,
            Antialiasing::from_name,
            &Antialiasing::names(),
        )?;
        // URP's anti-aliasing is its asset's m_MSAA unless the matrix names one for URP.
        let names_urp = match &file.antialiasing {
            Some(toml::Value::Table(t)) => t.contains_key("urp"),
            other => other.is_some(),
        };
        if !names_urp {
            antialiasing[Pipeline::Urp.shader_id() as usize] = pipeline_settings.urp.msaa;
        }
        // Built-in's is its quality level's antiAliasing unless the matrix names one for built-in.
        let names_builtin = match &file.antialiasing {
            Some(toml::Value::Table(t)) => t.contains_key("builtin"),
            other => other.is_some(),
        };
        if !names_builtin {
            antialiasing[Pipeline::Builtin.shader_id() as usize] = builtin_level.2;
        }
        for (key, v) in [("image.width", file.image.width), ("image.height", file.image.height)] {
            if v == 0 || v > MAX_IMAGE_SIZE {
                return Err(c.err(key, format!("value {v} is out of range; allowed 1..={MAX_IMAGE_SIZE}")).into());
            }
        }
        if file.timing.frames == 0 || file.timing.frames > 10_000 {
            return Err(c
                .err("timing.frames", format!("value {} is out of range; allowed 1..=10000", file.timing.frames))
                .into());
        }
        // Warm-up frames add to the timed ones: unchecked, 4294967295 wrapped the sum to 0 frames.
        if file.timing.warmup > 10_000 {
            return Err(c
                .err("timing.warmup", format!("value {} is out of range; allowed 0..=10000", file.timing.warmup))
                .into());
        }
        let only: Vec<Filter> = file
            .only
            .iter()
            .enumerate()
            .map(|(i, t)| parse_filter(&c, &format!("only[{i}]"), t))
            .collect::<Result<_, _>>()?;
        let exclude: Vec<Filter> = file
            .exclude
            .iter()
            .enumerate()
            .map(|(i, t)| parse_filter(&c, &format!("exclude[{i}]"), t))
            .collect::<Result<_, _>>()?;

        let known = |axis: Axis| -> Vec<String> {
            match axis {
                Axis::Composition => compositions.iter().map(|s| s.name.clone()).collect(),
                Axis::Pipeline => Pipeline::names().iter().map(|s| s.to_string()).collect(),
                Axis::Path => RenderPath::names().iter().map(|s| s.to_string()).collect(),
                Axis::Shader => model_names.iter().map(|s| s.to_string()).collect(),
                Axis::Preset => preset_names().iter().map(|s| s.to_string()).collect(),
                Axis::Textured => vec!["false".into(), "true".into()],
                Axis::Surface => {
                    let mut v: Vec<String> = SurfaceType::names().iter().map(|s| s.to_string()).collect();
                    v.push("material".into());
                    v
                }
                Axis::MaterialType => {
                    let mut v: Vec<String> =
                        crate::shading::material_type::MaterialType::names().iter().map(|s| s.to_string()).collect();
                    v.push("model".into());
                    v
                }
                Axis::Color | Axis::Specular => {
                    let mut v: Vec<String> =
                        file.sweep.colours(axis).iter().map(|c| colour_label(axis, Some(*c))).collect();
                    if v.is_empty() || file.sweep.sweeps_own(axis) {
                        v.push(colour_label(axis, None));
                    }
                    v
                }
                // A numeric axis's one name: the scene's own value, where the axis has one.
                _ if super::axes::of(axis).own == "scene" => vec!["scene".into()],
                _ => Vec::new(),
            }
        };
        let asserts: Vec<InvariantSpec> =
            file.asserts.iter().enumerate().map(|(i, t)| parse_assert(&c, i, t)).collect::<Result<_, _>>()?;
        for (i, a) in asserts.iter().enumerate() {
            let Some(axis) = a.along else { continue };
            let values = file.sweep.values_of(axis);
            let needed = if a.kind == (InvariantKind::Linear { through_zero: false }) { 3 } else { 2 };
            if values < needed {
                return Err(c
                    .err(
                        &format!("assert[{i}].along"),
                        format!(
                            "a `{}` assert along {} needs at least {needed} values of sweep.{}; the matrix sweeps {values}",
                            a.kind.name(),
                            axis.name(),
                            axis.name()
                        ),
                    )
                    .into());
            }
        }
        let assert_filters: Vec<Filter> = asserts.iter().map(|a| a.filter.clone()).collect();
        for (list, filters) in [("only", &only), ("exclude", &exclude), ("assert", &assert_filters)] {
            for (i, f) in filters.iter().enumerate() {
                for (axis, values) in &f.terms {
                    let valid = known(*axis);
                    for v in values {
                        if let FilterValue::Name(n) | FilterValue::Color(n) = v {
                            if !valid.contains(n) {
                                let valid: Vec<&str> = valid.iter().map(String::as_str).collect();
                                let key = match list {
                                    "assert" => format!("assert[{i}].where.{}", axis.name()),
                                    _ => format!("{list}[{i}].{}", axis.name()),
                                };
                                return Err(unknown_name(origin, &key, axis.name(), n, &valid).into());
                            }
                        }
                    }
                }
            }
        }

        let reference = file.reference.as_ref().map(|r| parse_reference(&c, r, base_dir)).transpose()?;
        let mut approximations = Vec::new();
        for (i, name) in file.approximations.iter().enumerate() {
            let a = Approximation::from_name(name).ok_or_else(|| {
                unknown_name(origin, &format!("approximations[{i}]"), "approximation", name, &Approximation::names())
            })?;
            if !approximations.contains(&a) {
                approximations.push(a);
            }
        }
        if !approximations.is_empty() && !matches!(reference, Some(ReferenceSpec::Truth(_))) {
            return Err(c
                .err(
                    "approximations",
                    "the approximation study measures each change against the cell's truth: set `reference = \"truth\"` (or `{ truth = ... }`)",
                )
                .into());
        }
        let physical_truth =
            matches!(&reference, Some(ReferenceSpec::Truth(t)) if t.settings.kind == TruthKind::Physical);
        super::outputs::check_truth_scene(&c, &file.outputs, physical_truth, &compositions)?;
        if let Some(ReferenceSpec::Cell(terms)) = &reference {
            for (axis, v) in terms {
                if let FilterValue::Name(n) = v {
                    let valid = known(*axis);
                    if !valid.contains(n) {
                        let valid: Vec<&str> = valid.iter().map(String::as_str).collect();
                        return Err(unknown_name(
                            origin,
                            &format!("reference.{}", axis.name()),
                            axis.name(),
                            n,
                            &valid,
                        )
                        .into());
                    }
                }
            }
        }

        let sheets = file.sheets.clone().unwrap_or_else(crate::declarations::sheets::default_specs);
        for (i, sheet) in sheets.iter().enumerate() {
            let terms = file.outputs.terms;
            let needs_terms = |key: &str, value: &str| {
                c.err(
                    &format!("sheets[{i}].{key}"),
                    format!("`{value}` shows term layers, which only a run with `[outputs] terms = true` draws"),
                )
            };
            for (k, axis) in [("rows", &sheet.rows), ("cols", &sheet.cols)] {
                if axis == crate::declarations::sheets::TERM_AXIS {
                    if !terms {
                        return Err(needs_terms(k, axis).into());
                    }
                    continue;
                }
                if super::axes::find(axis).is_none() {
                    let mut allowed = super::axes::names();
                    allowed.push(crate::declarations::sheets::TERM_AXIS);
                    return Err(unknown_name(origin, &format!("sheets[{i}].{k}"), "axis", axis, &allowed).into());
                }
            }
            if let Some(image) = sheet.image.as_deref().filter(|i| *i != crate::declarations::sheets::WHOLE_IMAGE) {
                let mut allowed = vec![crate::declarations::sheets::WHOLE_IMAGE];
                allowed.extend(crate::pipelines::terms::LAYER_NAMES);
                if !allowed.contains(&image) {
                    return Err(unknown_name(origin, &format!("sheets[{i}].image"), "image", image, &allowed).into());
                }
                if !terms {
                    return Err(needs_terms("image", image).into());
                }
            }
            if sheet.rows == sheet.cols {
                return Err(c.err(&format!("sheets[{i}]"), "rows and cols must be different axes").into());
            }
        }

        Ok(Matrix {
            registry: registry.clone(),
            name: file.name,
            description: file.description,
            origin: origin.to_string(),
            hash: hex(&Sha256::digest(text.as_bytes())),
            compositions,
            pipelines,
            paths,
            shaders: file.shaders,
            presets,
            sweep: file.sweep,
            image: file.image,
            tonemaps,
            antialiasing,
            light_budget,
            pipeline_settings,
            timing: file.timing,
            outputs: file.outputs,
            metrics: file.metrics,
            only,
            exclude,
            reference,
            approximations,
            sheets,
            asserts,
        })
    }
}

impl Matrix {
    /// `--only axis=v1|v2,axis=v`: the grammar of a matrix's `[[only]]` table on one line, parsed
    /// and checked by the same code (names against this matrix, with the nearest valid one).
    pub fn parse_only(&self, text: &str) -> Result<Filter, InputError> {
        const ORIGIN: &str = "command line";
        let mut table = toml::Table::new();
        for term in text.split(',').filter(|t| !t.trim().is_empty()) {
            let (k, v) = term
                .split_once('=')
                .ok_or_else(|| InputError::at_key(ORIGIN, "--only", format!("`{term}` is not axis=value")))?;
            let numeric = super::axes::find(k.trim()).is_some_and(|r| r.kind == super::axes::AxisKind::Number);
            let values = v
                .split('|')
                .map(|x| match (numeric, x.trim().parse::<f64>()) {
                    (true, Ok(n)) => Ok(toml::Value::Float(n)),
                    (true, Err(_)) => Err(InputError::at_key(
                        ORIGIN,
                        format!("--only {}", k.trim()),
                        format!("`{}` is not a number", x.trim()),
                    )),
                    (false, _) => Ok(toml::Value::String(x.trim().to_string())),
                })
                .collect::<Result<Vec<_>, _>>()?;
            table.insert(k.trim().to_string(), toml::Value::Array(values));
        }
        let filter = parse_filter(&Checker::new(ORIGIN), "--only", &table)?;
        for (axis, values) in &filter.terms {
            let valid: Vec<String> = match axis {
                Axis::Composition => self.compositions.iter().map(|s| s.name.clone()).collect(),
                Axis::Pipeline => self.pipelines.iter().map(|p| p.name().to_string()).collect(),
                Axis::Path => self.paths.iter().map(|p| p.name().to_string()).collect(),
                Axis::Shader => self.shaders.clone(),
                Axis::Preset => self.presets.iter().map(|p| p.name.to_string()).collect(),
                Axis::Color | Axis::Specular => {
                    let mut v: Vec<String> =
                        self.sweep.colours(*axis).iter().map(|c| colour_label(*axis, Some(*c))).collect();
                    if v.is_empty() || self.sweep.sweeps_own(*axis) {
                        v.push(colour_label(*axis, None));
                    }
                    v
                }
                _ if crate::declarations::axes::of(*axis).own == "scene" => vec!["scene".into()],
                _ => continue,
            };
            for v in values {
                if let FilterValue::Name(n) | FilterValue::Color(n) = v {
                    if !valid.contains(n) {
                        let valid: Vec<&str> = valid.iter().map(String::as_str).collect();
                        let key = format!("--only {}", axis.name());
                        return Err(unknown_name(ORIGIN, &key, axis.name(), n, &valid));
                    }
                }
            }
        }
        Ok(filter)
    }
}

pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn non_empty(c: &Checker, key: &str, v: &[String]) -> Result<(), InputError> {
    if v.is_empty() {
        Err(c.err(key, "the list is empty; name at least one"))
    } else {
        Ok(())
    }
}

fn names_to<T: PartialEq>(
    c: &Checker,
    origin: &str,
    key: &str,
    what: &str,
    names: &[String],
    valid: &[&str],
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Vec<T>, InputError> {
    let mut out = Vec::new();
    for (i, n) in names.iter().enumerate() {
        let v = parse(n).ok_or_else(|| unknown_name(origin, &format!("{key}[{i}]"), what, n, valid))?;
        if out.contains(&v) {
            return Err(c.err(&format!("{key}[{i}]"), format!("{what} `{n}` is listed twice")));
        }
        out.push(v);
    }
    Ok(out)
}

/// A per-pipeline setting: one name for every pipeline (`tonemap = "aces"`) or a table by pipeline
/// (`tonemap = { hdrp = "neutral", urp = "aces" }`); pipelines left out keep `default`.
fn parse_per_pipeline<T: Copy>(
    c: &Checker,
    origin: &str,
    (key, kind): (&str, &str),
    value: Option<&toml::Value>,
    default: fn(Pipeline) -> T,
    from_name: fn(&str) -> Option<T>,
    names: &[&str],
) -> Result<[T; 3], InputError> {
    let mut out = Pipeline::ALL.map(default);
    let name = |key: &str, v: &toml::Value| -> Result<T, InputError> {
        match v {
            toml::Value::String(s) => from_name(s).ok_or_else(|| unknown_name(origin, key, kind, s, names)),
            other => Err(c.err(key, format!("{other} is not a name; allowed: {}", names.join(", ")))),
        }
    };
    match value {
        None => {}
        Some(toml::Value::Table(t)) => {
            for (k, v) in t {
                let p = Pipeline::from_name(k)
                    .ok_or_else(|| unknown_name(origin, &format!("{key}.{k}"), "pipeline", k, &Pipeline::names()))?;
                out[p.shader_id() as usize] = name(&format!("{key}.{k}"), v)?;
            }
        }
        Some(v) => out = [name(key, v)?; 3],
    }
    Ok(out)
}

/// Every `[sweep.params]` name must be a parameter of one of the matrix's models, each value in
/// that parameter's range.
fn check_params(
    c: &Checker,
    origin: &str,
    params: &BTreeMap<String, Vec<f64>>,
    shaders: &[String],
    pipelines: &[Pipeline],
    registry: &Registry,
) -> Result<(), InputError> {
    let specs: Vec<&crate::shading::registry::ParamSpec> = pipelines
        .iter()
        .flat_map(|p| shaders.iter().filter_map(move |s| registry.find(*p, s)))
        .flat_map(|m| m.params.iter())
        .collect();
    let mut valid: Vec<&str> = specs.iter().map(|p| p.name.as_ref()).collect();
    valid.sort();
    valid.dedup();
    for (name, values) in params {
        let key = format!("sweep.params.{name}");
        let Some(spec) = specs.iter().find(|p| p.name == name.as_str()) else {
            if valid.is_empty() {
                return Err(c.err(&key, "none of the matrix's shaders has parameters"));
            }
            return Err(unknown_name(origin, &key, "model parameter", name, &valid));
        };
        if values.is_empty() {
            return Err(c.err(&key, "the list is empty; give at least one value"));
        }
        for (i, v) in values.iter().enumerate() {
            c.range(&format!("{key}[{i}]"), *v, spec.min, spec.max)?;
        }
    }
    Ok(())
}
