//! glTF's texture coordinates as the tool draws them: KHR_texture_transform's affine map of a
//! material's UVs, and the one transform a material's maps must share (the tool's material maps
//! read one UV set), or why a material cannot be drawn.

/// KHR_texture_transform: uv' = offset + R(rotation)·(scale ∘ uv), the extension's
/// `translation * rotation * scale`, with R = [[cos, sin], [−sin, cos]] (rows): the sign that
/// carries the extension's own example (offset (0, 1), rotation π/2, scale ½) onto "the lower
/// left quadrant of the source image, rotated clockwise 90°", as three.js's setUvTransform does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvTransform {
    pub offset: [f64; 2],
    pub rotation: f64,
    pub scale: [f64; 2],
}

impl UvTransform {
    pub const IDENTITY: UvTransform = UvTransform { offset: [0.0; 2], rotation: 0.0, scale: [1.0; 2] };

    pub fn apply(&self, uv: [f32; 2]) -> [f32; 2] {
        let (s, c) = self.rotation.sin_cos();
        let (x, y) = (uv[0] as f64 * self.scale[0], uv[1] as f64 * self.scale[1]);
        [(self.offset[0] + c * x + s * y) as f32, (self.offset[1] - s * x + c * y) as f32]
    }

    /// The extension's object on a texture info (its JSON, as the reader keeps unknown
    /// extensions for the normal and occlusion slots): (transform, its texCoord override).
    fn from_json(v: &serde_json::Value) -> (UvTransform, Option<u64>) {
        let pair =
            |k: &str, d: [f64; 2]| v.get(k).and_then(|a| Some([a.get(0)?.as_f64()?, a.get(1)?.as_f64()?])).unwrap_or(d);
        let t = UvTransform {
            offset: pair("offset", [0.0; 2]),
            rotation: v.get("rotation").and_then(|r| r.as_f64()).unwrap_or(0.0),
            scale: pair("scale", [1.0; 2]),
        };
        (t, v.get("texCoord").and_then(|t| t.as_u64()))
    }
}

/// The one UV transform a material's textures share (identity without KHR_texture_transform), or
/// why it cannot be drawn: a texture on a texture coordinate set other than 0, or textures of one
/// material transformed differently (the tool's material maps share one UV set).
pub fn material_uv_transform(m: &gltf::Material) -> Result<UvTransform, String> {
    check_emission(m)?;
    let pbr = m.pbr_metallic_roughness();
    let info = |t: Option<gltf::texture::Info>| {
        t.map(|t| {
            let tr = t.texture_transform();
            let over = tr.as_ref().and_then(|x| x.tex_coord()).map(u64::from);
            let tr = tr.map_or(UvTransform::IDENTITY, |x| UvTransform {
                offset: x.offset().map(f64::from),
                rotation: x.rotation() as f64,
                scale: x.scale().map(f64::from),
            });
            (t.tex_coord() as u64, tr, over)
        })
    };
    let other = |set: u32, ext: Option<&serde_json::Value>| {
        let (tr, over) = ext.map_or((UvTransform::IDENTITY, None), UvTransform::from_json);
        (set as u64, tr, over)
    };
    let slots = [
        ("baseColorTexture", info(pbr.base_color_texture())),
        ("metallicRoughnessTexture", info(pbr.metallic_roughness_texture())),
        ("normalTexture", m.normal_texture().map(|t| other(t.tex_coord(), t.extension_value("KHR_texture_transform")))),
        (
            "occlusionTexture",
            m.occlusion_texture().map(|t| other(t.tex_coord(), t.extension_value("KHR_texture_transform"))),
        ),
        ("emissiveTexture", info(m.emissive_texture())),
    ];
    let mut shared: Option<(&str, UvTransform)> = None;
    for (slot, found) in slots {
        let Some((set, transform, over)) = found else { continue };
        let set = over.unwrap_or(set);
        if set != 0 {
            return Err(format!(
                "material `{}`: {slot} reads texture coordinate set {set}; only set 0 (TEXCOORD_0) is drawn",
                m.name().unwrap_or("?")
            ));
        }
        match shared {
            Some((first, t)) if t != transform => {
                return Err(format!(
                    "material `{}`: {slot} and {first} have different KHR_texture_transform values; \
                     one material's maps share one UV transform here",
                    m.name().unwrap_or("?")
                ))
            }
            _ => shared = Some((slot, transform)),
        }
    }
    let t = shared.map_or(UvTransform::IDENTITY, |(_, t)| t);
    let values = t.offset.iter().chain(&t.scale).chain([&t.rotation]);
    if let Some(v) = values.copied().find(|v| !v.is_finite() || v.abs() > super::validate::MAX_UV) {
        return Err(format!(
            "material `{}`: KHR_texture_transform value {v} is not allowed; offset, rotation and scale are finite, \
             at most {} in magnitude",
            m.name().unwrap_or("?"),
            super::validate::MAX_UV
        ));
    }
    Ok(t)
}

/// The material's emission (`emissiveFactor` × `KHR_materials_emissive_strength`) is radiance:
/// finite, ≥ 0 and bounded like a scene's (a NaN or negative strength gave NaN or negative images).
fn check_emission(m: &gltf::Material) -> Result<(), String> {
    let strength = m.emissive_strength().unwrap_or(1.0) as f64;
    let factor = m.emissive_factor().map(f64::from);
    let max = super::validate::MAX_INTENSITY;
    if !(strength.is_finite() && (0.0..=max).contains(&strength)) {
        return Err(format!(
            "material `{}`: KHR_materials_emissive_strength {strength} is out of range; allowed 0..={max}",
            m.name().unwrap_or("?")
        ));
    }
    if factor.iter().any(|f| !f.is_finite() || *f < 0.0) {
        return Err(format!(
            "material `{}`: emissiveFactor {factor:?} must be finite and ≥ 0",
            m.name().unwrap_or("?")
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extensions_example_reads_the_lower_left_quadrant() {
        let t = UvTransform { offset: [0.0, 1.0], rotation: std::f64::consts::FRAC_PI_2, scale: [0.5, 0.5] };
        let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(|uv| t.apply(uv));
        for c in corners {
            // u in [0, ½] (left), v in [½, 1] (lower: glTF's v runs down the image).
            assert!((-1e-6..=0.5 + 1e-6).contains(&c[0]) && (0.5 - 1e-6..=1.0 + 1e-6).contains(&c[1]), "{corners:?}");
        }
        // Turned: the mesh's u axis runs up the quadrant's left edge, its v axis along the bottom.
        assert!((corners[1][0] - 0.0).abs() < 1e-6 && (corners[1][1] - 0.5).abs() < 1e-6, "{corners:?}");
        assert_eq!(UvTransform::IDENTITY.apply([0.3, 0.7]), [0.3, 0.7]);
    }
}
