//! glTF import (through the `gltf` crate) and GLB export of a composition's meshes.
//! glTF is Y-up and right-handed like the tool, so no axis conversion is needed.

use glam::Vec3;
use serde_json::json;
use std::path::Path;

use super::mesh::{Mesh, Vertex};
use crate::error::{Error, InputError};
use crate::input::texture_transform::{material_uv_transform, UvTransform};

/// Load every triangle primitive of the default scene (or of all nodes when there is none),
/// with node transforms applied. Normals are generated when absent.
/// With `material`, only the primitives naming that material (and, for the file's first, those
/// naming none: `input::gltf_scene::material_slots`).
pub fn load(path: &Path, material: Option<usize>) -> Result<Mesh, Error> {
    let shown = path.display().to_string();
    crate::input::guard::without_panics(|| Ok(import_unguarded(path, &shown, false, material)?.0)).unwrap_or_else(
        |panic| Err(InputError::new(&shown, format!("malformed glTF: the glTF reader failed on it ({panic})")).into()),
    )
}

/// Load the whole mesh as `load` does, and the file's first material (its first slot), with its
/// textures decoded (None: no primitive names a material).
pub fn load_with_material(path: &Path) -> Result<(Mesh, Option<GltfMaterial>), Error> {
    let shown = path.display().to_string();
    crate::input::guard::without_panics(|| import_unguarded(path, &shown, true, None)).unwrap_or_else(|panic| {
        Err(InputError::new(&shown, format!("malformed glTF: the glTF reader failed on it ({panic})")).into())
    })
}

/// The factors of the material `load_with_material` reads, from the document alone (no buffers
/// or images decoded): what a cell's `own` preset sets before any rendering.
pub fn material_factors(path: &Path) -> Result<Option<GltfMaterial>, Error> {
    let shown = path.display().to_string();
    crate::input::guard::without_panics(|| {
        let doc = super::gltf_files::open(path).map_err(|e| InputError::new(&shown, e))?;
        let slots = crate::input::gltf_scene::slots_of(&doc.document).map_err(|e| InputError::new(&shown, e))?;
        Ok(slots.first().map(|m| read_material(m, None)))
    })
    .unwrap_or_else(|panic| {
        Err(InputError::new(&shown, format!("malformed glTF: the glTF reader failed on it ({panic})")).into())
    })
}

fn import_unguarded(
    path: &Path,
    shown: &str,
    with_material: bool,
    only: Option<usize>,
) -> Result<(Mesh, Option<GltfMaterial>), Error> {
    let shown = shown.to_string();
    match crate::input::read::is_regular_file(path) {
        Err(crate::input::read::ReadError::NotFound) => {
            return Err(InputError::new(
                &shown,
                "glTF file not found (the path is resolved relative to the scene file)",
            )
            .into())
        }
        Err(e) => return Err(InputError::new(&shown, e.to_string()).into()),
        Ok(()) => {}
    }
    let gltf::Gltf { document: doc, blob } = super::gltf_files::open(path).map_err(|e| InputError::new(&shown, e))?;
    // Every external file checked before any is read; buffers read with bounds (`gltf_files`).
    super::gltf_files::external_files(path, &doc)?;
    let buffers = super::gltf_files::read_buffers(path, &doc, blob)?;
    let images = match with_material {
        true => {
            doc.images().map(|i| decode_image(path, &shown, &i, &buffers).map(Some)).collect::<Result<Vec<_>, _>>()?
        }
        false => Vec::new(),
    };
    let slots = crate::input::gltf_scene::slots_of(&doc).map_err(|e| InputError::new(&shown, e))?;
    let first = slots.first().and_then(|m| m.index());
    let kept = |named: Option<usize>| match only {
        None => true,
        Some(k) => named == Some(k) || (named.is_none() && first == Some(k)),
    };
    let mut out = Mesh::default();
    for p in crate::input::gltf_file::walk(&doc).map_err(|e| InputError::new(&shown, e))? {
        if let Some(mesh) = p.node.mesh() {
            for prim in mesh.primitives().filter(|prim| kept(prim.material().index())) {
                if let Some(part) = read_primitive(&mesh, &prim, buffers.as_slice(), &shown)? {
                    out.append(part.transformed(p.world));
                }
            }
        }
    }
    if out.indices.is_empty() {
        let what = match only {
            None => "the glTF file contains no triangles (only triangle-list primitives are used)".to_string(),
            Some(k) => format!("no triangle primitive of the file's scene names material {k}"),
        };
        return Err(InputError::new(&shown, what).into());
    }
    let material = match with_material {
        true => slots.first().map(|m| read_material(m, Some(&images))),
        false => None,
    };
    Ok((out, material))
}

/// A glTF metallic-roughness material as the file states it: its factors and, where it has them,
/// the images of its textures decoded to linear RGBA (texture coordinate set 0).
#[derive(Debug, Clone, Default)]
pub struct GltfMaterial {
    pub name: String,
    /// Linear RGBA (`baseColorFactor`).
    pub base_color: [f64; 4],
    pub metallic: f64,
    pub roughness: f64,
    /// Linear `emissiveFactor` × `KHR_materials_emissive_strength`.
    pub emissive: [f64; 3],
    pub normal_scale: f64,
    pub occlusion_strength: f64,
    /// sRGB-decoded to linear.
    pub base_color_texture: Option<TextureImage>,
    /// G roughness, B metallic (linear).
    pub metallic_roughness_texture: Option<TextureImage>,
    /// Tangent-space normal, stored 0.5·n + 0.5 (linear).
    pub normal_texture: Option<TextureImage>,
    /// R occlusion (linear).
    pub occlusion_texture: Option<TextureImage>,
    /// sRGB-decoded to linear.
    pub emissive_texture: Option<TextureImage>,
    /// How many of the five texture slots name a texture (on texture coordinate set 0).
    pub texture_count: usize,
    /// `alphaMode` as the engines' importers set the surface: OPAQUE opaque, MASK cutout at
    /// `alphaCutoff`, BLEND transparent (alpha blended, reflections kept).
    pub surface: crate::pipelines::surface::SurfaceType,
    pub alpha_cutoff: f64,
    pub double_sided: bool,
    /// `KHR_materials_specular`'s dielectric F0, min(0.04·specularColorFactor, 1)·specularFactor
    /// (ior 1.5), where the material has the extension; its textures, if any, are counted in
    /// `specular_textures`.
    pub specular_f0: Option<[f64; 3]>,
    pub specular_textures: usize,
}

impl GltfMaterial {
    pub fn has_textures(&self) -> bool {
        self.texture_count > 0
    }
}

/// A decoded texture image: RGBA f32, row-major, row 0 at v = 0 (glTF's UV origin is the image's top left).
#[derive(Debug, Clone)]
pub struct TextureImage {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<[f32; 4]>,
}

/// Image `i` decoded; an image of more than `MAX_TEXTURE_TEXELS` texels is refused.
fn decode_image(
    path: &Path,
    shown: &str,
    i: &gltf::Image,
    buffers: &[gltf::buffer::Data],
) -> Result<gltf::image::Data, Error> {
    let key = format!("images[{}]", i.index());
    let data = gltf::image::Data::from_source(i.source(), path.parent(), buffers)
        .map_err(|e| InputError::at_key(shown, &key, format!("cannot read the image: {e}")))?;
    let texels = data.width as usize * data.height as usize;
    if texels > MAX_TEXTURE_TEXELS {
        return Err(InputError::at_key(
            shown,
            key,
            format!("{}×{}: a texture may have at most {MAX_TEXTURE_TEXELS} texels (8192²)", data.width, data.height),
        )
        .into());
    }
    Ok(data)
}

/// The most texels a glTF texture may have (8192²: 1 GiB as f32 RGBA).
pub const MAX_TEXTURE_TEXELS: usize = 8192 * 8192;

/// Material `index` of the glTF at `path` with the images it names decoded (a fixed object's
/// `gltf_material`); the others are not read.
pub fn material_by_index(path: &Path, index: usize) -> Result<GltfMaterial, Error> {
    with_buffers(path, |shown, doc, buffers| {
        let m = doc.materials().nth(index).ok_or_else(|| {
            InputError::at_key(
                shown,
                "materials",
                format!("no material {index}: the file has {}", doc.materials().len()),
            )
        })?;
        material_uv_transform(&m).map_err(|e| InputError::at_key(shown, format!("materials[{index}]"), e))?;
        let named = material_textures(&m).iter().flatten().map(|t| t.source().index()).collect::<Vec<_>>();
        let images = doc
            .images()
            .map(|i| match named.contains(&i.index()) {
                true => decode_image(path, shown, &i, buffers).map(Some),
                false => Ok(None),
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(read_material(&m, Some(&images)))
    })
}

/// `read` over the document at `path` and its buffers (every external file checked first, the
/// buffers read with bounds: `gltf_files`), with the reader's panics turned into errors.
fn with_buffers<T>(
    path: &Path,
    read: impl FnOnce(&str, &gltf::Document, &[gltf::buffer::Data]) -> Result<T, Error>,
) -> Result<T, Error> {
    let shown = path.display().to_string();
    crate::input::guard::without_panics(|| {
        let gltf::Gltf { document: doc, blob } =
            super::gltf_files::open(path).map_err(|e| InputError::new(&shown, e))?;
        super::gltf_files::external_files(path, &doc)?;
        let buffers = super::gltf_files::read_buffers(path, &doc, blob)?;
        read(&shown, &doc, &buffers)
    })
    .unwrap_or_else(|panic| {
        Err(InputError::new(&shown, format!("malformed glTF: the glTF reader failed on it ({panic})")).into())
    })
}

/// The textures of a material's five slots (base colour, metallic-roughness, normal, occlusion,
/// emissive).
fn material_textures<'a>(m: &gltf::Material<'a>) -> [Option<gltf::texture::Texture<'a>>; 5] {
    let pbr = m.pbr_metallic_roughness();
    [
        pbr.base_color_texture().map(|t| t.texture()),
        pbr.metallic_roughness_texture().map(|t| t.texture()),
        m.normal_texture().map(|t| t.texture()),
        m.occlusion_texture().map(|t| t.texture()),
        m.emissive_texture().map(|t| t.texture()),
    ]
}

fn read_material(m: &gltf::Material, images: Option<&[Option<gltf::image::Data>]>) -> GltfMaterial {
    let pbr = m.pbr_metallic_roughness();
    let image = |t: Option<gltf::texture::Texture>, srgb: bool| -> Option<TextureImage> {
        let data = images?.get(t?.source().index())?.as_ref()?;
        Some(decode(data, srgb))
    };
    let strength = m.emissive_strength().unwrap_or(1.0) as f64;
    let named = [
        pbr.base_color_texture().map(|t| t.tex_coord()),
        pbr.metallic_roughness_texture().map(|t| t.tex_coord()),
        m.normal_texture().map(|t| t.tex_coord()),
        m.occlusion_texture().map(|t| t.tex_coord()),
        m.emissive_texture().map(|t| t.tex_coord()),
    ];
    GltfMaterial {
        texture_count: named.iter().filter(|t| **t == Some(0)).count(),
        name: m.name().unwrap_or("").to_string(),
        base_color: pbr.base_color_factor().map(f64::from),
        metallic: pbr.metallic_factor() as f64,
        roughness: pbr.roughness_factor() as f64,
        emissive: m.emissive_factor().map(|e| e as f64 * strength),
        normal_scale: m.normal_texture().map(|t| t.scale() as f64).unwrap_or(1.0),
        occlusion_strength: m.occlusion_texture().map(|t| t.strength() as f64).unwrap_or(1.0),
        base_color_texture: image(pbr.base_color_texture().filter(|t| t.tex_coord() == 0).map(|t| t.texture()), true),
        metallic_roughness_texture: image(
            pbr.metallic_roughness_texture().filter(|t| t.tex_coord() == 0).map(|t| t.texture()),
            false,
        ),
        normal_texture: image(m.normal_texture().filter(|t| t.tex_coord() == 0).map(|t| t.texture()), false),
        occlusion_texture: image(m.occlusion_texture().filter(|t| t.tex_coord() == 0).map(|t| t.texture()), false),
        emissive_texture: image(m.emissive_texture().filter(|t| t.tex_coord() == 0).map(|t| t.texture()), true),
        surface: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => crate::pipelines::surface::SurfaceType::Opaque,
            gltf::material::AlphaMode::Mask => crate::pipelines::surface::SurfaceType::Cutout,
            gltf::material::AlphaMode::Blend => crate::pipelines::surface::SurfaceType::Transparent,
        },
        alpha_cutoff: m.alpha_cutoff().unwrap_or(0.5) as f64,
        double_sided: m.double_sided(),
        specular_f0: m
            .specular()
            .map(|s| s.specular_color_factor().map(|c| (0.04 * c as f64).min(1.0) * s.specular_factor() as f64)),
        specular_textures: m
            .specular()
            .map_or(0, |s| s.specular_texture().is_some() as usize + s.specular_color_texture().is_some() as usize),
    }
}

/// An image's pixels as linear RGBA f32 (missing channels 0, alpha 1); `srgb` decodes colour data.
fn decode(data: &gltf::image::Data, srgb: bool) -> TextureImage {
    use gltf::image::Format;
    let (channels, bytes) = match data.format {
        Format::R8 => (1, 1),
        Format::R8G8 => (2, 1),
        Format::R8G8B8 => (3, 1),
        Format::R8G8B8A8 => (4, 1),
        Format::R16 => (1, 2),
        Format::R16G16 => (2, 2),
        Format::R16G16B16 => (3, 2),
        Format::R16G16B16A16 => (4, 2),
        Format::R32G32B32FLOAT => (3, 4),
        Format::R32G32B32A32FLOAT => (4, 4),
    };
    let value = |px: &[u8], c: usize| -> f32 {
        let b = &px[c * bytes..(c + 1) * bytes];
        match bytes {
            1 => b[0] as f32 / 255.0,
            2 => u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
            _ => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        }
    };
    let stride = channels * bytes;
    let texels = data
        .pixels
        .chunks_exact(stride)
        .map(|px| {
            let mut t = [0.0, 0.0, 0.0, 1.0];
            for (c, v) in t.iter_mut().enumerate().take(channels) {
                let x = value(px, c);
                *v = if srgb && c < 3 && bytes < 4 { crate::color::srgb_to_linear(x as f64) as f32 } else { x };
            }
            t
        })
        .collect();
    TextureImage { width: data.width as usize, height: data.height as usize, texels }
}

/// A triangle-list primitive in its mesh's space (None: another mode, or no positions); normals
/// generated where it has none.
fn read_primitive(
    mesh: &gltf::Mesh,
    prim: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
    shown: &str,
) -> Result<Option<Mesh>, Error> {
    if prim.mode() != gltf::mesh::Mode::Triangles {
        return Ok(None);
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let Some(positions) = reader.read_positions() else { return Ok(None) };
    let positions: Vec<[f32; 3]> = positions.collect();
    let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
    let uvs: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|t| t.into_f32().collect());
    // TEXCOORD_1: the file's own lightmap UVs, which the lightmap then uses (geometry::lightmap_uv).
    let uv2s: Option<Vec<[f32; 2]>> = reader.read_tex_coords(1).map(|t| t.into_f32().collect());
    let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|t| t.collect());
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(InputError::new(
            shown,
            format!("mesh `{}` has index {bad} beyond its {} vertices", mesh.name().unwrap_or("?"), positions.len()),
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
                uv2: uv2s.as_ref().map(|t| t[i]).unwrap_or([0.0; 2]),
            })
            .collect(),
        indices: indices[..indices.len() / 3 * 3].to_vec(),
    };
    if normals.is_none() {
        part.generate_normals();
    }
    // KHR_texture_transform moves where the maps are read, not the tangent frame: the tangents
    // come from the file's UVs, then the UVs take the material's transform.
    let transform = material_uv_transform(&prim.material()).map_err(|e| {
        InputError::new(shown, format!("mesh `{}` primitive {}: {e}", mesh.name().unwrap_or("?"), prim.index()))
    })?;
    if transform != UvTransform::IDENTITY {
        part.ensure_tangents();
        for v in &mut part.vertices {
            v.uv = transform.apply(v.uv);
        }
    }
    Ok(Some(part))
}

/// Primitive `primitive` of mesh `mesh` in the file at `path`, in the mesh's own space
/// (`MeshSpec::GltfPrimitive`).
pub fn load_primitive(path: &Path, mesh: usize, primitive: usize) -> Result<Mesh, Error> {
    load_primitives(path)?.remove(&(mesh, primitive)).ok_or_else(|| {
        InputError::new(
            path.display().to_string(),
            format!("mesh {mesh} primitive {primitive} is not a triangle list with positions in the file"),
        )
        .into()
    })
}

/// Every triangle-list primitive of the file at `path` by (mesh, primitive), each in its mesh's
/// space: a glTF scene's objects read their file once (`procedural::build_scene`).
pub fn load_primitives(path: &Path) -> Result<std::collections::HashMap<(usize, usize), Mesh>, Error> {
    with_buffers(path, |shown, doc, buffers| {
        let mut out = std::collections::HashMap::new();
        for m in doc.meshes() {
            for p in m.primitives() {
                if let Some(mesh) = read_primitive(&m, &p, buffers, shown)? {
                    out.insert((m.index(), p.index()), mesh);
                }
            }
        }
        Ok(out)
    })
}

/// One named mesh to export, in world space, with its material.
pub struct ExportMesh<'a> {
    pub name: &'a str,
    pub mesh: &'a Mesh,
    pub base_color_linear: [f64; 3],
    pub metallic: f64,
    pub roughness: f64,
    /// Linear emissive colour (black: none).
    pub emissive: [f64; 3],
    /// The textures of the material, each an 8-bit RGBA image as glTF stores it, finest level.
    pub textures: Option<ExportTextures>,
}

/// A material's textures in glTF's layout: sRGB base colour and emissive; linear normal
/// (0.5·n + 0.5), metallicRoughness (G roughness, B metallic) and occlusion (R).
pub struct ExportTextures {
    pub size: usize,
    pub base_color: Vec<[u8; 4]>,
    pub metallic_roughness: Vec<[u8; 4]>,
    pub normal: Vec<[u8; 4]>,
    pub occlusion: Vec<[u8; 4]>,
    pub emissive: Option<Vec<[u8; 4]>>,
}

fn png_bytes(size: usize, texels: &[[u8; 4]]) -> Result<Vec<u8>, Error> {
    let image = image::RgbaImage::from_raw(size as u32, size as u32, texels.concat())
        .ok_or_else(|| Error::Other(format!("a {size}² texture with {} texels", texels.len())))?;
    let mut png = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| Error::encode("encoding a texture as PNG", e))?;
    Ok(png)
}

/// Encode meshes as a binary glTF (GLB): one node, mesh and material per input.
pub fn to_glb(meshes: &[ExportMesh]) -> Result<Vec<u8>, Error> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut gl_meshes = Vec::new();
    let mut nodes = Vec::new();
    let mut materials = Vec::new();
    let mut images = Vec::new();
    let mut textures = Vec::new();
    // target 0: an image's view (no buffer target)
    let mut push_view = |bin: &mut Vec<u8>, bytes: &[u8], target: u32| -> usize {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let mut view = json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()});
        if target != 0 {
            view["target"] = json!(target);
        }
        views.push(view);
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
        let mut material = json!({
            "name": m.name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [m.base_color_linear[0], m.base_color_linear[1], m.base_color_linear[2], 1.0],
                "metallicFactor": m.metallic,
                "roughnessFactor": m.roughness
            },
            "emissiveFactor": m.emissive,
        });
        let mut attributes = json!({"POSITION": a0, "NORMAL": a0 + 1, "TEXCOORD_0": a0 + 2});
        if let Some(t) = &m.textures {
            let mut texture = |bin: &mut Vec<u8>, name: &str, texels: &[[u8; 4]]| -> Result<usize, Error> {
                let png = png_bytes(t.size, texels)?;
                let view = push_view(bin, &png, 0);
                images.push(json!({"name": format!("{}_{name}", m.name), "bufferView": view, "mimeType": "image/png"}));
                textures.push(json!({"source": images.len() - 1, "sampler": 0}));
                Ok(textures.len() - 1)
            };
            let base = texture(&mut bin, "base_color", &t.base_color)?;
            let mr = texture(&mut bin, "metallic_roughness", &t.metallic_roughness)?;
            let normal = texture(&mut bin, "normal", &t.normal)?;
            let occlusion = texture(&mut bin, "occlusion", &t.occlusion)?;
            material["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": base});
            material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({"index": mr});
            material["normalTexture"] = json!({"index": normal});
            material["occlusionTexture"] = json!({"index": occlusion});
            if let Some(e) = &t.emissive {
                material["emissiveTexture"] = json!({"index": texture(&mut bin, "emissive", e)?});
            }
            // Tangents as the renderer used them (MikkTSpace), so a viewer's normal mapping agrees.
            if m.mesh.vertices.iter().any(|v| v.tangent[3] != 0.0) {
                let tan: Vec<[f32; 4]> = v.iter().map(|x| x.tangent).collect();
                let tv = push_view(&mut bin, bytemuck::cast_slice(&tan), 34962);
                accessors.push(json!({"bufferView": tv, "componentType": 5126, "count": v.len(), "type": "VEC4"}));
                attributes["TANGENT"] = json!(accessors.len() - 1);
            }
        }
        materials.push(material);
        gl_meshes.push(json!({"name": m.name, "primitives": [{
            "attributes": attributes,
            "indices": a0 + 3, "material": i, "mode": 4
        }]}));
        nodes.push(json!({"name": m.name, "mesh": i}));
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut root = json!({
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
    if !images.is_empty() {
        root["images"] = json!(images);
        root["textures"] = json!(textures);
        // Trilinear, repeating: glTF's defaults spelled out.
        root["samplers"] = json!([{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}]);
    }
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
