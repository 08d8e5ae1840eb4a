//! A glTF file as a whole scene (`[gltf_scene]`): every node's primitives with their own
//! material factors, its `KHR_lights_punctual` lights and its cameras, in world space, read from
//! the document alone (the vertices are read per primitive when meshes are built,
//! `geometry::gltf_io::load_primitive`). What this cannot draw faithfully is refused with the node
//! and the reason, never dropped: a primitive that is not a triangle list, a texture on a second
//! UV set or maps of one material transformed differently (`texture_transform::material_uv_transform`), an
//! orthographic camera. A fixed object's textured material keeps its maps
//! (`FixedMaterial::gltf_material`, read when the composition is prepared).

use std::path::Path;

use glam::{DMat4, DVec3};

/// One triangle-list primitive of a node, placed in the world.
#[derive(Debug, Clone)]
pub struct ScenePrimitive {
    /// `node name#primitive index`.
    pub name: String,
    pub mesh: usize,
    pub primitive: usize,
    /// Node-to-world, column-major.
    pub world: [f64; 16],
    /// In the subject node or below it.
    pub subject: bool,
    pub material: PrimitiveMaterial,
}

/// The material a primitive names, as its factors state it.
#[derive(Debug, Clone, PartialEq)]
pub struct PrimitiveMaterial {
    /// The material's index (None: the primitive names none, glTF's default material).
    pub index: Option<usize>,
    pub name: String,
    /// Linear base colour, metallic, roughness, linear emission (`emissiveFactor` ×
    /// `KHR_materials_emissive_strength`).
    pub base_color: [f64; 3],
    pub metallic: f64,
    pub roughness: f64,
    pub emissive: [f64; 3],
    /// It has textures (their maps modulate the factors).
    pub textured: bool,
    /// The material's `doubleSided`: both faces drawn.
    pub double_sided: bool,
    /// `alphaMode` BLEND: the base colour factor's alpha, which the object is blended by.
    pub blend_alpha: Option<f64>,
}

impl PrimitiveMaterial {
    fn of(m: &gltf::Material) -> PrimitiveMaterial {
        let pbr = m.pbr_metallic_roughness();
        let c = pbr.base_color_factor();
        PrimitiveMaterial {
            index: m.index(),
            name: m.name().unwrap_or("").to_string(),
            base_color: [c[0] as f64, c[1] as f64, c[2] as f64],
            metallic: pbr.metallic_factor() as f64,
            roughness: pbr.roughness_factor() as f64,
            emissive: m.emissive_factor().map(|e| e as f64 * m.emissive_strength().unwrap_or(1.0) as f64),
            textured: pbr.base_color_texture().is_some()
                || pbr.metallic_roughness_texture().is_some()
                || m.normal_texture().is_some()
                || m.occlusion_texture().is_some()
                || m.emissive_texture().is_some(),
            double_sided: m.double_sided(),
            blend_alpha: (m.alpha_mode() == gltf::material::AlphaMode::Blend).then_some(c[3] as f64),
        }
    }
}

/// The distinct materials the triangle primitives of the file's scene name, in the order the
/// nodes are walked (`gltf_file::walk`): a glTF subject's material slots. The first is the one
/// the swept material replaces (Unity's `Renderer.material` is the renderer's first material
/// slot); the others keep their own. A primitive naming none has no slot of its own: it goes
/// with the first.
pub fn material_slots(path: &Path) -> Result<Vec<PrimitiveMaterial>, String> {
    let gltf = super::gltf_file::open(path)?;
    Ok(slots_of(&gltf.document)?.into_iter().map(|m| PrimitiveMaterial::of(&m)).collect())
}

/// The named materials of the walked triangle primitives, distinct, in walk order.
pub fn slots_of(doc: &gltf::Document) -> Result<Vec<gltf::Material<'_>>, String> {
    let mut out: Vec<gltf::Material> = Vec::new();
    for p in super::gltf_file::walk(doc)? {
        for prim in p.node.mesh().iter().flat_map(|m| m.primitives()) {
            let m = prim.material();
            if prim.mode() == gltf::mesh::Mode::Triangles
                && m.index().is_some()
                && !out.iter().any(|o| o.index() == m.index())
            {
                out.push(m);
            }
        }
    }
    Ok(out)
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightKind {
    Directional,
    Point,
    Spot,
}

/// A punctual light in glTF's photometric units: candela (point, spot) or lux (directional).
#[derive(Debug, Clone)]
pub struct SceneLight {
    pub name: String,
    pub kind: LightKind,
    pub color_linear: [f64; 3],
    pub intensity: f64,
    pub range: Option<f64>,
    /// Spot cone half-angles, radians.
    pub inner_cone: f64,
    pub outer_cone: f64,
    pub position: [f64; 3],
    /// Where the light travels: the node's −Z in world space.
    pub direction: [f64; 3],
}

/// A perspective camera node.
#[derive(Debug, Clone)]
pub struct SceneCamera {
    pub name: String,
    pub position: [f64; 3],
    /// The node's −Z in world space.
    pub forward: [f64; 3],
    pub yfov_deg: f64,
    pub znear: f64,
    pub zfar: Option<f64>,
}

#[derive(Debug, Clone, Default)]
pub struct SceneContent {
    pub primitives: Vec<ScenePrimitive>,
    pub lights: Vec<SceneLight>,
    pub cameras: Vec<SceneCamera>,
    /// Every node name, for messages.
    pub node_names: Vec<String>,
}

/// The scene of the glTF at `path` with `subject` the node whose primitives take the swept
/// material.
pub fn read(path: &Path, subject: &str) -> Result<SceneContent, String> {
    let gltf = super::gltf_file::open(path)?;
    let doc = &gltf.document;
    if doc.scenes().next().is_none() {
        return Err("the file has no scene".into());
    }
    let mut out = SceneContent {
        node_names: doc.nodes().filter_map(|n| n.name().map(str::to_string)).collect(),
        ..Default::default()
    };
    if !out.node_names.iter().any(|n| n == subject) {
        let names: Vec<&str> = out.node_names.iter().map(String::as_str).collect();
        let near = crate::input::names::nearest(subject, &names);
        return Err(format!(
            "no node is named `{subject}` (the subject){}; nodes: {}",
            near.map_or(String::new(), |n| format!(", did you mean `{n}`?")),
            names.join(", ")
        ));
    }
    let placed = super::gltf_file::walk(doc)?;
    let mut in_subject: Vec<bool> = Vec::with_capacity(placed.len());
    for p in &placed {
        let inherited = p.parent.is_some_and(|u| in_subject[u]);
        in_subject.push(visit(&p.node, p.world, inherited, subject, &mut out)?);
    }
    if !out.primitives.iter().any(|p| p.subject) {
        return Err(format!("the subject node `{subject}` holds no mesh"));
    }
    Ok(out)
}

/// One node of the walk (`gltf_file::walk`): its primitives, light and camera; whether it is in
/// the subject (it or an ancestor is the node named `subject`).
fn visit(
    node: &gltf::Node,
    world: DMat4,
    in_subject: bool,
    subject: &str,
    out: &mut SceneContent,
) -> Result<bool, String> {
    let name = node.name().map_or_else(|| format!("node {}", node.index()), str::to_string);
    let is_subject = in_subject || node.name() == Some(subject);
    if let Some(mesh) = node.mesh() {
        for prim in mesh.primitives() {
            let at = format!("node `{name}`, mesh {} primitive {}", mesh.index(), prim.index());
            if prim.mode() != gltf::mesh::Mode::Triangles {
                return Err(format!("{at}: mode {:?}; only triangle lists are drawn", prim.mode()));
            }
            let m = prim.material();
            crate::input::texture_transform::material_uv_transform(&m).map_err(|e| format!("{at}: {e}"))?;
            out.primitives.push(ScenePrimitive {
                name: format!("{name}#{}", prim.index()),
                mesh: mesh.index(),
                primitive: prim.index(),
                world: world.to_cols_array(),
                subject: is_subject,
                material: PrimitiveMaterial::of(&m),
            });
        }
    }
    let position = world.transform_point3(DVec3::ZERO).to_array();
    let forward = world.transform_vector3(-DVec3::Z).normalize_or_zero().to_array();
    if let Some(light) = node.light() {
        use gltf::khr_lights_punctual::Kind;
        let (kind, inner, outer) = match light.kind() {
            Kind::Directional => (LightKind::Directional, 0.0, 0.0),
            Kind::Point => (LightKind::Point, 0.0, 0.0),
            Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                (LightKind::Spot, inner_cone_angle as f64, outer_cone_angle as f64)
            }
        };
        out.lights.push(SceneLight {
            name: light.name().map_or_else(|| name.clone(), str::to_string),
            kind,
            color_linear: light.color().map(f64::from),
            intensity: light.intensity() as f64,
            range: light.range().map(f64::from),
            inner_cone: inner,
            outer_cone: outer,
            position,
            direction: forward,
        });
    }
    if let Some(camera) = node.camera() {
        match camera.projection() {
            gltf::camera::Projection::Perspective(p) => out.cameras.push(SceneCamera {
                name: camera.name().map_or_else(|| name.clone(), str::to_string),
                position,
                forward,
                yfov_deg: (p.yfov() as f64).to_degrees(),
                znear: p.znear() as f64,
                zfar: p.zfar().map(f64::from),
            }),
            gltf::camera::Projection::Orthographic(_) => {
                return Err(format!("node `{name}`: an orthographic camera; the tool's cameras are perspective"))
            }
        }
    }
    Ok(is_subject)
}
