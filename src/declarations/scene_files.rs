//! The files a scene names, read when it is loaded: a `[gltf_scene]`'s nodes, lights and camera
//! merged into the scene, and an image or cube-map sky's pixels (with their digests, which keys
//! see).

use super::scene::*;
use crate::error::InputError;
use crate::input::names::unknown_name;

impl Scene {
    /// `[gltf_scene]`'s nodes, lights and camera into the scene (`GltfSceneSpec`).
    pub(super) fn read_gltf_scene(&mut self) -> Result<(), InputError> {
        let Some(spec) = self.gltf_scene.clone() else { return Ok(()) };
        let at = |key: &str, m: String| InputError::at_key(&self.origin, key, m);
        let dir = self.base_dir.clone().unwrap_or_default();
        let content = crate::input::gltf_scene::read(&dir.join(&spec.path), &spec.subject)
            .map_err(|m| at("gltf_scene.path", format!("`{}`: {m}", spec.path)))?;
        let mut used: std::collections::HashSet<String> = self.objects.iter().map(|o| o.name.clone()).collect();
        // The subject node's first material is the slot the swept material fills; its primitives
        // naming another keep theirs, as fixed objects (`split_gltf_subject`).
        let slot = content.primitives.iter().filter(|p| p.subject).find_map(|p| p.material.index);
        for p in &content.primitives {
            let subject = p.subject && (p.material.index.is_none() || p.material.index == slot);
            let (material, transparent) = match subject {
                true => (None, false),
                false => {
                    let m = fixed_material(&spec.path, &p.material);
                    let transparent = m.surface == crate::pipelines::surface::SurfaceType::Transparent;
                    (Some(m), transparent)
                }
            };
            self.objects.push(Object {
                name: unused_name(&p.name, &mut used),
                role: if subject { Role::Subject } else { Role::Fixed },
                mesh: MeshSpec::GltfPrimitive { path: spec.path.clone(), mesh: p.mesh, primitive: p.primitive },
                transform: Transform { matrix: Some(p.world), ..Default::default() },
                material,
                cast_shadows: !transparent,
                receive_shadows: true,
                render_face: render_face(&p.material),
                lod: None,
            });
        }
        for l in &content.lights {
            use crate::input::gltf_scene::LightKind as K;
            // Every other field at the scene file's defaults.
            let kind = match l.kind {
                K::Directional => "directional",
                K::Point => "point",
                K::Spot => "spot",
            };
            let table = toml::map::Map::from_iter([("kind".to_string(), toml::Value::String(kind.into()))]);
            let mut light: Light = toml::Value::Table(table)
                .try_into()
                .map_err(|e| at("gltf_scene", format!("light `{}`: {e}", l.name)))?;
            light.from_gltf = Some(format!("`{}` light `{}`", spec.path, l.name));
            light.position = l.position;
            light.direction = l.direction;
            light.color = l.color_linear.map(crate::color::linear_to_srgb);
            light.intensity = l.intensity;
            light.photometric = true;
            // Unity's defaults where glTF says nothing: range 10 m, shadows on the sun only.
            light.range = l.range.unwrap_or(10.0);
            light.shadows = l.kind == K::Directional;
            if l.kind == K::Spot {
                light.spot_angle_deg = 2.0 * l.outer_cone.to_degrees();
                light.inner_spot_angle_deg = Some(2.0 * l.inner_cone.to_degrees());
            }
            self.lights.push(light);
        }
        if let Some(name) = &spec.camera {
            let Some(c) = content.cameras.iter().find(|c| &c.name == name) else {
                let names: Vec<&str> = content.cameras.iter().map(|c| c.name.as_str()).collect();
                return Err(unknown_name(&self.origin, "gltf_scene.camera", "camera", name, &names));
            };
            let target = glam::DVec3::from(c.position) + glam::DVec3::from(c.forward);
            self.camera = Camera {
                position: c.position,
                target: target.to_array(),
                fov_y_deg: c.yfov_deg,
                near: c.znear,
                far: c.zfar.unwrap_or(self.camera.far),
            };
        }
        Ok(())
    }

    /// A glTF subject (`MeshSpec::Gltf`, the whole file) whose primitives name more than one
    /// material keeps them all: the swept material fills the first slot, as Unity's
    /// `Renderer.material` is the renderer's first material (`materials[0]`), and the primitives
    /// naming each other material become a fixed object wearing it, placed as the subject is,
    /// casting and receiving shadows as it does (a BLEND material casts none,
    /// `Object::cast_shadows`).
    pub(super) fn split_gltf_subject(&mut self) {
        let Some(dir) = self.base_dir.clone() else { return };
        let mut used: std::collections::HashSet<String> = self.objects.iter().map(|o| o.name.clone()).collect();
        let mut companions = Vec::new();
        for o in self.objects.iter_mut() {
            let (Role::Subject, MeshSpec::Gltf { path, material: material @ None }) = (o.role, &mut o.mesh) else {
                continue;
            };
            // A file that cannot be read is the geometry stage's to report, with the resolved
            // path, before anything renders (`geometry::gltf_io::load`).
            let Ok(slots) = crate::input::gltf_scene::material_slots(&dir.join(&*path)) else { continue };
            let [first, others @ ..] = slots.as_slice() else { continue };
            if others.is_empty() {
                continue;
            }
            *material = first.index;
            for m in others {
                let fixed = fixed_material(path, m);
                let transparent = fixed.surface == crate::pipelines::surface::SurfaceType::Transparent;
                let slot = match m.name.is_empty() {
                    true => format!("material-{}", m.index.unwrap_or_default()),
                    false => m.name.clone(),
                };
                companions.push(Object {
                    name: unused_name(&format!("{}-{slot}", o.name), &mut used),
                    role: Role::Fixed,
                    mesh: MeshSpec::Gltf { path: path.clone(), material: m.index },
                    transform: o.transform.clone(),
                    material: Some(fixed),
                    cast_shadows: o.cast_shadows && !transparent,
                    receive_shadows: o.receive_shadows,
                    render_face: render_face(m),
                    lod: None,
                });
            }
        }
        self.objects.extend(companions);
    }

    /// An image sky's pixels: from the scene's folder, or for a built-in scene from the images
    /// built into the tool (`BUILTIN_SKIES`).
    pub(super) fn read_sky_image(&mut self) -> Result<(), InputError> {
        if let Sky::Cubemap { faces, digest, images, .. } = &mut self.environment.sky {
            let Some(dir) = &self.base_dir else {
                return Err(InputError::at_key(
                    &self.origin,
                    "environment.sky.faces",
                    "a built-in scene has no cube-map sky",
                ));
            };
            let mut read = Vec::with_capacity(6);
            for (i, face) in faces.iter().enumerate() {
                let image = crate::input::sky_image::read_face_file(&dir.join(face)).map_err(|m| {
                    InputError::at_key(&self.origin, format!("environment.sky.faces[{i}]"), format!("`{face}`: {m}"))
                })?;
                if read.first().is_some_and(|f: &crate::input::sky_image::SkyImage| f.width != image.width) {
                    return Err(InputError::at_key(
                        &self.origin,
                        format!("environment.sky.faces[{i}]"),
                        format!(
                            "`{face}`: {}×{}, the first face is {}×{}: the faces are one size",
                            image.width, image.height, read[0].width, read[0].height
                        ),
                    ));
                }
                read.push(image);
            }
            *digest = read.iter().map(|f| f.digest.as_str()).collect::<Vec<_>>().join(",");
            *images = Some(std::sync::Arc::new(read));
            return Ok(());
        }
        let Sky::Image { path, digest, image, .. } = &mut self.environment.sky else { return Ok(()) };
        let at = |m: String| InputError::at_key(&self.origin, "environment.sky.path", format!("`{path}`: {m}"));
        let read = match (&self.base_dir, BUILTIN_SKIES.iter().find(|(n, _)| n == path)) {
            (Some(dir), _) => crate::input::sky_image::read_file(&dir.join(&*path)),
            (None, Some((name, bytes))) => {
                crate::input::sky_image::read_bytes(bytes, name.rsplit('.').next().unwrap_or(""))
            }
            (None, None) => Err(format!(
                "a built-in scene's sky is one of the built-in images: {}",
                BUILTIN_SKIES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
            )),
        }
        .map_err(at)?;
        *digest = read.digest.clone();
        *image = Some(std::sync::Arc::new(read));
        Ok(())
    }

    /// The fixed objects' base-colour maps: from the scene's folder, or for a built-in scene from
    /// the images built into the tool (`BUILTIN_TEXTURES`).
    pub(super) fn read_map_images(&mut self) -> Result<(), InputError> {
        for (i, o) in self.objects.iter_mut().enumerate() {
            let Some(m) = o.material.as_mut() else { continue };
            let key = format!("objects[{i}].material");
            if m.base_color_map.is_some() && m.gltf_material.is_some() {
                return Err(InputError::at_key(
                    &self.origin,
                    &key,
                    format!(
                        "object `{}` names both base_color_map and gltf_material; a material takes one set of maps",
                        o.name
                    ),
                ));
            }
            if let (Some(r), None) = (&m.gltf_material, &self.base_dir) {
                return Err(InputError::at_key(
                    &self.origin,
                    format!("{key}.gltf_material.path"),
                    format!("`{}`: a built-in scene names no glTF files", r.path),
                ));
            }
            let Some(path) = &m.base_color_map else { continue };
            let read = match (&self.base_dir, BUILTIN_TEXTURES.iter().find(|(n, _)| n == path)) {
                (Some(dir), _) => crate::input::texture_file::read_file(&dir.join(path)),
                (None, Some((name, bytes))) => {
                    crate::input::texture_file::read_bytes(bytes, name.rsplit('.').next().unwrap_or(""))
                }
                (None, None) => Err(format!(
                    "a built-in scene's textures are the built-in images: {}",
                    BUILTIN_TEXTURES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
                )),
            }
            .map_err(|e| InputError::at_key(&self.origin, format!("{key}.base_color_map"), format!("`{path}`: {e}")))?;
            m.map_digest = read.digest.clone();
            m.map_image = Some(std::sync::Arc::new(read));
        }
        Ok(())
    }
}

/// A glTF material's factors as a fixed object's material; a textured one keeps its maps
/// (`FixedMaterial::gltf_material`, read when the composition is prepared), a BLEND one is
/// transparent by its base colour's alpha.
fn fixed_material(path: &str, m: &crate::input::gltf_scene::PrimitiveMaterial) -> FixedMaterial {
    FixedMaterial {
        emission_linear: m.emissive,
        gltf_material: m.index.filter(|_| m.textured).map(|index| GltfMaterialRef { path: path.to_string(), index }),
        surface: match m.blend_alpha {
            Some(_) => crate::pipelines::surface::SurfaceType::Transparent,
            None => crate::pipelines::surface::SurfaceType::Opaque,
        },
        alpha: m.blend_alpha.unwrap_or(1.0),
        ..FixedMaterial::flat(m.base_color, m.metallic, 1.0 - m.roughness)
    }
}

/// The faces a glTF material's `doubleSided` draws.
fn render_face(m: &crate::input::gltf_scene::PrimitiveMaterial) -> crate::pipelines::surface::RenderFace {
    match m.double_sided {
        true => crate::pipelines::surface::RenderFace::Both,
        false => crate::pipelines::surface::RenderFace::Front,
    }
}

/// An object name made of `base` (lower-case letters, digits, `_` and `-`: `Floor#0` is
/// `floor-0`), with a number after it where another object has it.
fn unused_name(base: &str, used: &mut std::collections::HashSet<String>) -> String {
    let base: String = base
        .chars()
        .map(|c| match c {
            '#' => '-',
            c if c.is_ascii_alphanumeric() || c == '_' || c == '-' => c.to_ascii_lowercase(),
            _ => '_',
        })
        .collect();
    let name = (0..).map(|k| if k == 0 { base.clone() } else { format!("{base}-{k}") }).find(|n| !used.contains(n));
    let name = name.unwrap_or(base);
    used.insert(name.clone());
    name
}
