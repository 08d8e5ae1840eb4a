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
        for p in &content.primitives {
            // Object names are lower-case letters, digits, `_` and `-`: `Floor#0` is `floor-0`.
            let base: String = p
                .name
                .chars()
                .map(|c| match c {
                    '#' => '-',
                    c if c.is_ascii_alphanumeric() || c == '_' || c == '-' => c.to_ascii_lowercase(),
                    _ => '_',
                })
                .collect();
            let name =
                (0..).map(|k| if k == 0 { base.clone() } else { format!("{base}-{k}") }).find(|n| !used.contains(n));
            let name = name.unwrap_or(base);
            used.insert(name.clone());
            // A BLEND material is a transparent one, casting no shadow (`Object::cast_shadows`).
            let transparent = p.blend_alpha.is_some() && !p.subject;
            let material = (!p.subject).then(|| FixedMaterial {
                emission_linear: p.emissive,
                gltf_material: p.textured_material.map(|index| GltfMaterialRef { path: spec.path.clone(), index }),
                surface: match transparent {
                    true => crate::pipelines::surface::SurfaceType::Transparent,
                    false => crate::pipelines::surface::SurfaceType::Opaque,
                },
                alpha: p.blend_alpha.unwrap_or(1.0),
                ..FixedMaterial::flat(p.base_color, p.metallic, 1.0 - p.roughness)
            });
            self.objects.push(Object {
                name,
                role: if p.subject { Role::Subject } else { Role::Fixed },
                mesh: MeshSpec::GltfPrimitive { path: spec.path.clone(), mesh: p.mesh, primitive: p.primitive },
                transform: Transform { matrix: Some(p.world), ..Default::default() },
                material,
                cast_shadows: !transparent,
                receive_shadows: true,
                render_face: match p.double_sided {
                    true => crate::pipelines::surface::RenderFace::Both,
                    false => crate::pipelines::surface::RenderFace::Front,
                },
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
