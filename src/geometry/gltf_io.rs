//! glTF import (through the `gltf` crate) and GLB export of a composition's meshes.
//! glTF is Y-up and right-handed like the tool, so no axis conversion is needed.

use glam::{DMat4, Vec3};
use serde_json::json;
use std::path::Path;

use super::mesh::{Mesh, Vertex};
use crate::error::{Error, InputError};

/// Load every triangle primitive of the default scene (or of all nodes when there is none),
/// with node transforms applied. Normals are generated when absent.
pub fn load(path: &Path) -> Result<Mesh, Error> {
    let shown = path.display().to_string();
    crate::input::guard::without_panics(|| load_unguarded(path, &shown)).unwrap_or_else(|panic| {
        Err(InputError::new(&shown, format!("malformed glTF: the glTF reader failed on it ({panic})")).into())
    })
}

fn load_unguarded(path: &Path, shown: &str) -> Result<Mesh, Error> {
    let shown = shown.to_string();
    if !path.is_file() {
        return Err(
            InputError::new(&shown, "glTF file not found (the path is resolved relative to the scene file)").into()
        );
    }
    let (doc, buffers, _images) =
        gltf::import(path).map_err(|e| InputError::new(&shown, format!("cannot read glTF: {e}")))?;
    let mut out = Mesh::default();
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => doc.nodes().collect(),
    };
    for node in roots {
        visit(&node, DMat4::IDENTITY, &buffers, &mut out, &shown)?;
    }
    if out.indices.is_empty() {
        return Err(InputError::new(
            &shown,
            "the glTF file contains no triangles (only triangle-list primitives are used)",
        )
        .into());
    }
    Ok(out)
}

fn visit(
    node: &gltf::Node,
    parent: DMat4,
    buffers: &[gltf::buffer::Data],
    out: &mut Mesh,
    shown: &str,
) -> Result<(), Error> {
    let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
    let world = parent * local;
    if let Some(mesh) = node.mesh() {
        for prim in mesh.primitives() {
            if prim.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let Some(positions) = reader.read_positions() else { continue };
            let positions: Vec<[f32; 3]> = positions.collect();
            let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
            let uvs: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|t| t.into_f32().collect());
            let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|t| t.collect());
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..positions.len() as u32).collect(),
            };
            if let Some(bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(InputError::new(
                    shown,
                    format!(
                        "mesh `{}` has index {bad} beyond its {} vertices",
                        mesh.name().unwrap_or("?"),
                        positions.len()
                    ),
                )
                .into());
            }
            let mut part = Mesh {
                vertices: positions
                    .iter()
                    .enumerate()
                    .map(|(i, p)| Vertex {
                        position: *p,
                        normal: normals.as_ref().map(|n| n[i]).unwrap_or([0.0; 3]),
                        uv: uvs.as_ref().map(|t| t[i]).unwrap_or([0.0; 2]),
                        tangent: tangents.as_ref().map(|t| t[i]).unwrap_or([0.0; 4]),
                    })
                    .collect(),
                indices: indices[..indices.len() / 3 * 3].to_vec(),
            };
            if normals.is_none() {
                part.generate_normals();
            }
            out.append(part.transformed(world));
        }
    }
    for child in node.children() {
        visit(&child, world, buffers, out, shown)?;
    }
    Ok(())
}

/// One named mesh to export, in world space, with a display colour.
pub struct ExportMesh<'a> {
    pub name: &'a str,
    pub mesh: &'a Mesh,
    pub base_color_linear: [f64; 3],
    pub metallic: f64,
    pub roughness: f64,
}

/// Encode meshes as a binary glTF (GLB): one node, mesh and material per input.
pub fn to_glb(meshes: &[ExportMesh]) -> Result<Vec<u8>, Error> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut gl_meshes = Vec::new();
    let mut nodes = Vec::new();
    let mut materials = Vec::new();
    let mut push_view = |bin: &mut Vec<u8>, bytes: &[u8], target: u32| -> usize {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len(), "target": target}));
        bin.extend_from_slice(bytes);
        views.len() - 1
    };
    for (i, m) in meshes.iter().enumerate() {
        let v = &m.mesh.vertices;
        let pos: Vec<[f32; 3]> = v.iter().map(|x| x.position).collect();
        let nrm: Vec<[f32; 3]> = v.iter().map(|x| x.normal).collect();
        let uv: Vec<[f32; 2]> = v.iter().map(|x| x.uv).collect();
        let (lo, hi): (Vec3, Vec3) = m.mesh.bounds();
        let a0 = accessors.len();
        let pv = push_view(&mut bin, bytemuck::cast_slice(&pos), 34962);
        accessors.push(json!({"bufferView": pv, "componentType": 5126, "count": v.len(), "type": "VEC3", "min": lo.to_array(), "max": hi.to_array()}));
        let nv = push_view(&mut bin, bytemuck::cast_slice(&nrm), 34962);
        accessors.push(json!({"bufferView": nv, "componentType": 5126, "count": v.len(), "type": "VEC3"}));
        let tv = push_view(&mut bin, bytemuck::cast_slice(&uv), 34962);
        accessors.push(json!({"bufferView": tv, "componentType": 5126, "count": v.len(), "type": "VEC2"}));
        let iv = push_view(&mut bin, bytemuck::cast_slice(&m.mesh.indices), 34963);
        accessors
            .push(json!({"bufferView": iv, "componentType": 5125, "count": m.mesh.indices.len(), "type": "SCALAR"}));
        materials.push(json!({
            "name": m.name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [m.base_color_linear[0], m.base_color_linear[1], m.base_color_linear[2], 1.0],
                "metallicFactor": m.metallic,
                "roughnessFactor": m.roughness
            }
        }));
        gl_meshes.push(json!({"name": m.name, "primitives": [{
            "attributes": {"POSITION": a0, "NORMAL": a0 + 1, "TEXCOORD_0": a0 + 2},
            "indices": a0 + 3, "material": i, "mode": 4
        }]}));
        nodes.push(json!({"name": m.name, "mesh": i}));
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let root = json!({
        "asset": {"version": "2.0", "generator": concat!("shadematrix ", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": gl_meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}]
    });
    let mut json_bytes = serde_json::to_vec(&root).map_err(|e| Error::encode("encoding glTF JSON", e))?;
    while json_bytes.len() % 4 != 0 {
        json_bytes.push(b' ');
    }
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: (12 + 8 + json_bytes.len() + 8 + bin.len()) as u32,
        },
        json: json_bytes.into(),
        bin: Some(bin.into()),
    };
    glb.to_vec().map_err(|e| Error::encode("encoding GLB", e))
}
