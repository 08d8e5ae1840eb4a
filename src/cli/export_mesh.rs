//! `shadematrix export-mesh`: a composition's meshes, world space, as GLB for any glTF viewer,
//! with their materials: the fixed objects' own, the subject's as a cell would render it (a
//! preset, flat or textured, or a glTF subject's own material with its textures).

use std::path::Path;

use crate::declarations::presets::{find_matrix_preset, matrix_preset_names, OWN};
use crate::declarations::scene::{Role, Scene};
use crate::error::{Error, InputError};
use crate::geometry::{gltf_io, procedural};
use crate::materials::MaterialMaps;

/// The subject's material in the export: a preset name (`own`: the glTF subject's own, with its
/// textures), flat or in its textured form.
pub struct SubjectMaterial<'a> {
    pub preset: Option<&'a str>,
    pub textured: bool,
}

pub fn export_mesh(composition: &str, out: &Path, subject: SubjectMaterial) -> Result<(), Error> {
    let scene = Scene::load(composition, Some(Path::new(".")), "command line", "composition")?;
    let mut meshes = Vec::new();
    for (i, o) in scene.objects.iter().enumerate() {
        let mut mesh =
            procedural::build(&o.mesh, scene.base_dir.as_deref(), &scene.origin, &format!("objects[{i}].mesh"))?;
        if o.role == Role::Subject {
            mesh.ensure_tangents();
        }
        meshes.push((o, mesh.transformed(o.transform.matrix())));
    }
    let own = match scene.subject_gltf() {
        Some(path) => gltf_io::load_with_material(&path)?.1,
        None => None,
    };
    // Default: a glTF subject's own material where it has one, else a neutral grey.
    let preset = match subject.preset {
        Some(name) => Some(find_matrix_preset(name).ok_or_else(|| {
            Error::from(crate::input::names::unknown_name(
                "command line",
                "--preset",
                "preset",
                name,
                &matrix_preset_names(),
            ))
        })?),
        None => own.as_ref().map(|_| &OWN),
    };
    let mut parts = Vec::new();
    for (o, mesh) in &meshes {
        let mut part = gltf_io::ExportMesh {
            name: &o.name,
            mesh,
            base_color_linear: [0.5; 3],
            metallic: 0.0,
            roughness: 1.0,
            emissive: [0.0; 3],
            textures: None,
        };
        match (&o.material, o.role, preset) {
            (Some(m), _, _) => {
                (part.base_color_linear, part.metallic, part.roughness) =
                    (m.base_color_linear, m.metallic, 1.0 - m.smoothness)
            }
            (None, Role::Subject, Some(p)) if p.name == OWN.name => {
                let m = own.as_ref().ok_or_else(|| {
                    InputError::at_key(
                        "command line",
                        "--preset",
                        format!("`own` needs a glTF subject with a material; `{}`'s subject has none", scene.name),
                    )
                })?;
                part.base_color_linear = [m.base_color[0], m.base_color[1], m.base_color[2]];
                (part.metallic, part.roughness, part.emissive) = (m.metallic, m.roughness, m.emissive);
                // `own` wears the file's textures, as in a matrix that does not sweep `textured`.
                if let Some(maps) = crate::materials::gltf::maps(m) {
                    part.textures =
                        Some(crate::materials::gltf::export_textures(&maps, part.base_color_linear, 1.0 - m.roughness));
                    (part.base_color_linear, part.roughness) = ([1.0; 3], 1.0);
                }
            }
            (None, Role::Subject, Some(p)) => {
                (part.base_color_linear, part.metallic, part.roughness) =
                    (p.base_color, p.metallic, 1.0 - p.smoothness);
                if subject.textured {
                    let maps = MaterialMaps::of(p.name);
                    part.textures = Some(crate::materials::gltf::export_textures(&maps, p.base_color, p.smoothness));
                    (part.base_color_linear, part.roughness) = ([1.0; 3], 1.0);
                }
            }
            (None, Role::Subject, None) => (part.base_color_linear, part.roughness) = ([0.8; 3], 0.5),
            (None, Role::Fixed, _) => {}
        }
        parts.push(part);
    }
    let bytes = gltf_io::to_glb(&parts)?;
    crate::fsutil::write_atomic(out, &bytes)?;
    let tris: usize = meshes.iter().map(|(_, m)| m.triangle_count()).sum();
    let textured = parts.iter().filter(|p| p.textures.is_some()).count();
    super::outln!(
        "wrote {} ({} objects, {} triangles, {} textured material{})",
        out.display(),
        meshes.len(),
        tris,
        textured,
        if textured == 1 { "" } else { "s" }
    );
    Ok(())
}
