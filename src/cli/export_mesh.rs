//! `shadematrix export-mesh`: a composition's meshes, world space, as GLB for any glTF viewer.

use std::path::Path;

use crate::error::Error;
use crate::geometry::{gltf_io, procedural};
use crate::spec::scene::{Role, Scene};

pub fn export_mesh(composition: &str, out: &Path) -> Result<(), Error> {
    let scene = Scene::load(composition, Some(Path::new(".")), "command line", "composition")?;
    let mut meshes = Vec::new();
    for (i, o) in scene.objects.iter().enumerate() {
        let mesh = procedural::build(&o.mesh, scene.base_dir.as_deref(), &scene.origin, &format!("objects[{i}].mesh"))?
            .transformed(o.transform.matrix());
        meshes.push((o, mesh));
    }
    let parts: Vec<gltf_io::ExportMesh> = meshes
        .iter()
        .map(|(o, mesh)| {
            let (color, metallic, smoothness) = match (&o.material, o.role) {
                (Some(m), _) => (m.base_color_linear, m.metallic, m.smoothness),
                (None, Role::Subject) => ([0.8; 3], 0.0, 0.5),
                (None, Role::Fixed) => ([0.5; 3], 0.0, 0.0),
            };
            gltf_io::ExportMesh { name: &o.name, mesh, base_color_linear: color, metallic, roughness: 1.0 - smoothness }
        })
        .collect();
    let bytes = gltf_io::to_glb(&parts)?;
    crate::fsutil::write_atomic(out, &bytes)?;
    let tris: usize = meshes.iter().map(|(_, m)| m.triangle_count()).sum();
    println!("wrote {} ({} objects, {} triangles)", out.display(), meshes.len(), tris);
    Ok(())
}
