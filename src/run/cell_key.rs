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
use crate::spec::matrix::{hex, Matrix, ReferenceSpec};
use crate::spec::scene::MeshSpec;

/// Bumped when what a key covers changes meaning.
pub const CELL_KEY_SCHEMA: u32 = 2;

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
        let own: HashMap<&CellId, String> = cells
            .iter()
            .map(|c| {
                let files = meshes.entry(c.composition_index).or_insert_with(|| mesh_digests(matrix, c)).clone();
                let source =
                    sources.entry((c.pipeline, c.shader.clone())).or_insert_with(|| model_sources(matrix, c)).clone();
                let text = json!({
                    "schema": CELL_KEY_SCHEMA,
                    "tool": tool_fingerprint(),
                    "cell": c,
                    "scene": matrix.compositions[c.composition_index],
                    "mesh_files": files,
                    "models": source,
                    "settings": settings,
                    "adapter": adapter,
                });
                (&c.id, hex(&Sha256::digest(text.to_string().as_bytes())))
            })
            .collect();
        let keys = cells
            .iter()
            .map(|c| {
                let reference = reference_identity(matrix, c, &own);
                let key = hex(&Sha256::digest(format!("{}\n{reference}", own[&c.id]).as_bytes()));
                (c.id.clone(), key)
            })
            .collect();
        CellKeys { keys }
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
            MeshSpec::Gltf { path } | MeshSpec::GltfPrimitive { path, .. } => Some(path),
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
    let Ok(g) = gltf::Gltf::open(path) else { return Vec::new() };
    // The geometry stage refused the scene already if a reference is not allowed.
    crate::geometry::gltf_files::external_files(path, &g.document).unwrap_or_default()
}

/// The file's bytes' digest, or "absent".
fn file_digest(path: &Path) -> String {
    std::fs::read(path).map_or_else(|_| "absent".into(), |b| hex(&Sha256::digest(&b)))
}
