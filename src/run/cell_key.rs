//! A cell's key: the digest of everything that decides its images, record and metrics, so that a
//! finished cell can be kept (`--resume`) or reused from another run (`run::cell_cache`) exactly
//! when nothing it depends on changed.
//!
//! What goes in: the tool (version, a digest of its code and of its pass shaders, made by
//! build.rs), the cell's axes, the composition as parsed, the bytes of every mesh file it loads
//! (and the buffers and images those name), the source of the surface models the frame draws (the
//! subject's and the pipeline's fixed-object model), the run settings that reach a cell (timing,
//! reference, study), the adapter, and the key of the cell it is compared with — so a change to a
//! reference re-measures the cells compared with it. A user model's WGSL or declaration edited:
//! only the cells drawn with it change key.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde_json::json;
use sha2::{Digest, Sha256};

use crate::adapter::AdapterRecord;
use crate::cells::{reference_cell_id, Cell, CellId};
use crate::declarations::matrix::{hex, Matrix, ReferenceSpec};
use crate::declarations::scene::MeshSpec;

/// Bumped when what a key covers changes meaning (3: a digest per input, recorded in the cell's
/// record so `merge` can name the input that differs; 4: records name their passes by
/// `plan::Pass` and carry the engine rules, so a cached record of 3 is not this tree's).
pub const CELL_KEY_SCHEMA: u32 = 4;

/// The inputs a key covers, in the order `merge` reports the first that differs, each with what
/// it is in words.
pub const KEY_INPUTS: [(&str, &str); 8] = [
    ("tool", "the tool (its version, code or pass shaders)"),
    ("adapter", "the adapter"),
    ("settings", "the matrix's run settings (timing, outputs, metrics, approximations)"),
    ("cell", "the cell's values on its axes"),
    ("scene", "the composition as parsed (its scene file, or a sky or texture it reads)"),
    ("mesh_files", "a mesh, buffer or image file the composition loads"),
    ("models", "the WGSL or declaration of a surface model the frame draws"),
    ("reference", "what the cell is compared with"),
];

/// The tool's own identity in keys: its version and the digests build.rs made of its code and
/// pass shaders (the surface models are per cell).
pub fn tool_fingerprint() -> String {
    format!(
        "{} code {} passes {}",
        env!("CARGO_PKG_VERSION"),
        env!("SHADEMATRIX_CODE_DIGEST"),
        env!("SHADEMATRIX_PASS_SHADERS_DIGEST")
    )
}

/// Every cell's key in one run.
#[derive(Debug, Clone, Default)]
pub struct CellKeys {
    keys: HashMap<CellId, String>,
    /// Each cell's digest of every input (`KEY_INPUTS`), which its record keeps.
    inputs: HashMap<CellId, std::collections::BTreeMap<String, String>>,
}

impl CellKeys {
    /// Keys of `cells` rendered on `adapter`; a cell is compared with another only when that one is
    /// among `cells` (else the comparison is missing, and the key says so).
    pub fn new(matrix: &Matrix, cells: &[&Cell], adapter: &AdapterRecord) -> CellKeys {
        let mut meshes: HashMap<usize, Vec<(String, String)>> = HashMap::new();
        let mut sources: HashMap<(crate::pipelines::Pipeline, String), Vec<String>> = HashMap::new();
        let adapter = json!({
            "name": adapter.name, "backend": adapter.backend, "driver": adapter.driver,
            "driver_info": adapter.driver_info, "vendor": adapter.vendor, "device": adapter.device,
            "constants": adapter.constants,
        });
        let settings = json!({
            "frames": matrix.timing.frames,
            "warmup": matrix.timing.warmup,
            "every_cell": matrix.timing.every_cell,
            "approximations": format!("{:?}", matrix.approximations),
            "outputs": matrix.outputs,
            "metrics": matrix.metrics,
        });
        let digest = |v: &serde_json::Value| hex(&Sha256::digest(v.to_string().as_bytes()));
        let (tool, adapter, settings) = (digest(&json!(tool_fingerprint())), digest(&adapter), digest(&settings));
        let mut scenes: HashMap<usize, String> = HashMap::new();
        let mut inputs: HashMap<CellId, std::collections::BTreeMap<String, String>> = HashMap::new();
        let own: HashMap<&CellId, String> = cells
            .iter()
            .map(|c| {
                let files = meshes.entry(c.composition_index).or_insert_with(|| mesh_digests(matrix, c)).clone();
                let source =
                    sources.entry((c.pipeline, c.shader.clone())).or_insert_with(|| model_sources(matrix, c)).clone();
                let scene = scenes
                    .entry(c.composition_index)
                    .or_insert_with(|| digest(&json!(matrix.compositions[c.composition_index])))
                    .clone();
                let parts = [
                    ("tool", tool.clone()),
                    ("adapter", adapter.clone()),
                    ("settings", settings.clone()),
                    ("cell", digest(&json!(c))),
                    ("scene", scene),
                    ("mesh_files", digest(&json!(files))),
                    ("models", digest(&json!(source))),
                ];
                let mut text = format!("schema {CELL_KEY_SCHEMA}\n");
                for (name, d) in &parts {
                    text.push_str(&format!("{name} {d}\n"));
                }
                inputs.insert(c.id.clone(), parts.into_iter().map(|(n, d)| (n.to_string(), d)).collect());
                (&c.id, hex(&Sha256::digest(text.as_bytes())))
            })
            .collect();
        let keys = cells
            .iter()
            .map(|c| {
                let reference = reference_identity(matrix, c, &own);
                if let Some(i) = inputs.get_mut(&c.id) {
                    i.insert("reference".into(), hex(&Sha256::digest(reference.as_bytes())));
                }
                let key = hex(&Sha256::digest(format!("{}\n{reference}", own[&c.id]).as_bytes()));
                (c.id.clone(), key)
            })
            .collect();
        CellKeys { keys, inputs }
    }

    /// The digest of each input of `id`'s key, by name (`KEY_INPUTS`).
    pub fn inputs(&self, id: &CellId) -> std::collections::BTreeMap<String, String> {
        self.inputs.get(id).cloned().unwrap_or_default()
    }

    pub fn get(&self, id: &CellId) -> &str {
        self.keys.get(id).map(String::as_str).unwrap_or("")
    }
}

/// What the cell is compared with, as far as it decides the metrics: the reference cell's own key,
/// the referenced run's files' bytes, or the reference's settings.
fn reference_identity(matrix: &Matrix, c: &Cell, own: &HashMap<&CellId, String>) -> String {
    match &matrix.reference {
        None => "none".into(),
        Some(ReferenceSpec::Cell(terms)) => match reference_cell_id(c, matrix, terms) {
            Some(id) if id == c.id => "itself".into(),
            Some(id) => own.get(&id).map_or_else(|| format!("absent {id}"), |k| format!("cell {k}")),
            None => "no such cell".into(),
        },
        Some(ReferenceSpec::Run(dir)) => {
            let d = dir.join("cells").join(&c.id.0);
            let files: Vec<String> = ["image.exr", "image.png"].iter().map(|f| file_digest(&d.join(f))).collect();
            format!("run {} {}", dir.display(), files.join(" "))
        }
        Some(other) => format!("{other:?}"),
    }
}

/// The models the cell's frame draws (the subject's and the pipeline's fixed objects'): each one's
/// WGSL and its declaration as parsed — parameters with their slots, defaults and ranges, the axes
/// it reads, its pipelines — so a user's edited `NAME.toml` re-renders its cells.
pub(crate) fn model_sources(matrix: &Matrix, c: &Cell) -> Vec<String> {
    let fixed = matrix.registry.find(c.pipeline, c.pipeline.fixed_object_shader());
    let identity = |m: &crate::shading::ShaderModel| {
        let declaration = format!(
            "{:?}|{:?}|{:?}|{:?}|{}|{}|{:?}|{:?}",
            m.params, m.reads, m.pipelines, m.expected, m.per_vertex, m.main_light_only, m.smoothness_gate, m.passes
        );
        hex(&Sha256::digest(format!("{}\n{declaration}", m.wgsl).as_bytes()))
    };
    let mut out = vec![identity(c.model())];
    out.extend(fixed.map(|f| identity(f)));
    out
}

/// (path, digest of the bytes) of every file the composition's meshes (LOD levels included) and
/// fixed materials' glTF maps load.
pub(crate) fn mesh_digests(matrix: &Matrix, c: &Cell) -> Vec<(String, String)> {
    let scene = &matrix.compositions[c.composition_index];
    let mut out = Vec::new();
    // The object's mesh and its LOD levels' meshes: a level drawn at this distance reads its file.
    let meshes =
        scene.objects.iter().flat_map(|o| std::iter::once(&o.mesh).chain(o.lod.iter().flat_map(|l| &l.meshes)));
    let mut seen = std::collections::HashSet::new();
    // A fixed material's glTF maps read their file too (a base-colour map's digest is in the
    // scene's serialisation, `FixedMaterial::map_digest`).
    let materials = scene.objects.iter().filter_map(|o| o.material.as_ref()?.gltf_material.as_ref()).map(|r| &r.path);
    let files = meshes
        .filter_map(|mesh| match mesh {
            MeshSpec::Gltf { path, .. } | MeshSpec::GltfPrimitive { path, .. } => Some(path),
            _ => None,
        })
        .chain(materials);
    // A glTF scene's primitives name one file many times: its digest once.
    for path in files.filter(|p| seen.insert(*p)) {
        let p = scene.base_dir.as_ref().map_or_else(|| PathBuf::from(path), |b| b.join(path));
        for f in std::iter::once(p.clone()).chain(gltf_dependencies(&p)) {
            out.push((f.display().to_string(), file_digest(&f)));
        }
    }
    out
}

/// The external buffers and images a glTF file names, resolved as the loader resolves them
/// (`geometry::gltf_files`: percent-decoded, relative to the file); a GLB's are inside it.
fn gltf_dependencies(path: &Path) -> Vec<PathBuf> {
    let Ok(Ok(g)) = crate::input::guard::without_panics(|| crate::geometry::gltf_files::open(path)) else {
        return Vec::new();
    };
    // The geometry stage refused the scene already if a reference is not allowed.
    crate::geometry::gltf_files::external_files(path, &g.document).unwrap_or_default()
}

/// The file's bytes' digest, or "absent".
fn file_digest(path: &Path) -> String {
    crate::input::read::read(path, crate::input::read::OUTPUT)
        .map_or_else(|_| "absent".into(), |b| hex(&Sha256::digest(&b)))
}
