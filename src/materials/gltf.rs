//! A glTF subject's own material as material maps (`MaterialMaps`), mapped to the inputs every
//! pipeline's lit shader takes: the factors become the cell's material (base colour, metallic,
//! smoothness = 1 − roughness, emission colour) and the textures the maps that modulate them, in
//! the layout the shaders read — albedo multiplier (baseColorTexture), tangent-space normal
//! (normalTexture × scale), mask in HDRP's layout (R metallic multiplier from the metallicRoughness
//! texture's B, G occlusion lerped by its strength, B detail mask 1, A 0.5 + smoothness offset from
//! its G) and an emission multiplier (emissiveTexture). This is the packing Unity's glTF importers
//! do for Standard/Lit (metallic in R and smoothness in A of `_MetallicGlossMap`, HDRP's `_MaskMap`).
//!
//! Textures of any size are resampled bilinearly (repeating, as glTF's default sampler) onto one
//! square power-of-two grid — the largest texture's size rounded up, at most `MAX_SIZE` — so the
//! maps share the procedural presets' texture layout and sampler.

use super::{bilinear, with_mips, MapLevel, MaterialMaps};
use crate::color::linear_to_srgb;
use crate::geometry::gltf_io::{ExportTextures, GltfMaterial, TextureImage};

/// The largest side a glTF material's maps keep (larger textures are filtered down to it).
pub const MAX_SIZE: usize = 1024;

/// The maps of `m`, or None where it has no textures (its factors alone are a flat material).
pub fn maps(m: &GltfMaterial) -> Option<MaterialMaps> {
    if !m.has_textures() {
        return None;
    }
    Some(maps_at(m, largest_side(m).next_power_of_two().min(MAX_SIZE)))
}

/// The longest side of `m`'s textures in texels (1 without textures).
pub fn largest_side(m: &GltfMaterial) -> usize {
    let textures = [
        &m.base_color_texture,
        &m.metallic_roughness_texture,
        &m.normal_texture,
        &m.occlusion_texture,
        &m.emissive_texture,
    ];
    textures.iter().filter_map(|t| t.as_ref()).map(|t| t.width.max(t.height)).max().unwrap_or(1)
}

/// The maps of `m` on a `size`² grid (a power of two): its textures resampled, the slots it
/// has no texture for neutral.
pub fn maps_at(m: &GltfMaterial, size: usize) -> MaterialMaps {
    let texel_count = size * size;
    let sample = |t: &Option<TextureImage>, default: [f32; 4]| -> Vec<[f32; 4]> {
        match t {
            Some(img) => (0..texel_count)
                .map(|i| {
                    let (u, v) = (((i % size) as f64 + 0.5) / size as f64, ((i / size) as f64 + 0.5) / size as f64);
                    bilinear(&img.texels, img.width, img.height, u, v)
                })
                .collect(),
            None => vec![default; texel_count],
        }
    };
    let base = sample(&m.base_color_texture, [1.0; 4]);
    // glTF stores roughness in G and metallic in B; a missing texture is the factor alone.
    let metallic_roughness = sample(&m.metallic_roughness_texture, [1.0; 4]);
    let normal = sample(&m.normal_texture, [0.5, 0.5, 1.0, 1.0]);
    let occlusion = sample(&m.occlusion_texture, [1.0; 4]);
    let emission = sample(&m.emissive_texture, [1.0; 4]);
    let scale = m.normal_scale as f32;
    let rf = m.roughness as f32;
    let level = MapLevel {
        size,
        // Alpha kept: a cutout or blended surface reads it (pipelines::surface).
        albedo: base,
        // glTF: n = normalize((2c − 1) · (scale, scale, 1)).
        normal: normal
            .iter()
            .map(|t| {
                let n = [(2.0 * t[0] - 1.0) * scale, (2.0 * t[1] - 1.0) * scale, 2.0 * t[2] - 1.0];
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-6);
                // glTF has no height map (its KHR_materials_displacement is not taken)
                [n[0] / len, n[1] / len, n[2] / len, super::NO_HEIGHT]
            })
            .collect(),
        // Smoothness = 1 − rf·g = (1 − rf) + rf·(1 − g): the offset from the factor's smoothness.
        mask: metallic_roughness
            .iter()
            .zip(&occlusion)
            .map(|(mr, o)| {
                let occ = 1.0 + m.occlusion_strength as f32 * (o[0] - 1.0);
                [mr[2], occ, 1.0, 0.5 + rf * (1.0 - mr[1])]
            })
            .collect(),
        emission: if m.emissive_texture.is_some() { emission } else { Vec::new() },
    };
    with_mips(level)
}

/// The inverse of `maps` for export: the finest level of `maps` on a material of linear base
/// colour `base` and smoothness `smoothness`, in glTF's layout, to be written with baseColorFactor
/// white, roughnessFactor 1 and metallicFactor the material's metallic (the per-texel albedo,
/// roughness and metallic multiplier sit in the textures; an albedo above 1 is clipped, as 8 bits
/// must).
pub fn export_textures(maps: &MaterialMaps, base: [f64; 3], smoothness: f64) -> ExportTextures {
    let l0 = &maps.levels[0];
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let srgb = |t: &[f32; 4], k: [f64; 3]| {
        [0, 1, 2, 3].map(|c| if c == 3 { 255 } else { byte(linear_to_srgb(t[c] as f64 * k[c])) })
    };
    ExportTextures {
        size: l0.size,
        base_color: l0.albedo.iter().map(|t| srgb(t, base)).collect(),
        metallic_roughness: l0
            .mask
            .iter()
            .map(|m| {
                let s = (smoothness + m[3] as f64 - 0.5).clamp(0.0, 1.0);
                [0, byte(1.0 - s), byte(m[0] as f64), 255]
            })
            .collect(),
        normal: l0
            .normal
            .iter()
            .map(|n| [0, 1, 2, 3].map(|c| if c == 3 { 255 } else { byte(n[c] as f64 * 0.5 + 0.5) }))
            .collect(),
        occlusion: l0.mask.iter().map(|m| [byte(m[1] as f64), 0, 0, 255]).collect(),
        emissive: (!l0.emission.is_empty()).then(|| l0.emission.iter().map(|t| srgb(t, [1.0; 3])).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: usize, h: usize, f: impl Fn(usize, usize) -> [f32; 4]) -> TextureImage {
        TextureImage { width: w, height: h, texels: (0..w * h).map(|i| f(i % w, i / w)).collect() }
    }

    #[test]
    fn factors_and_textures_map_to_the_shaders_layout() {
        let m = GltfMaterial {
            base_color: [1.0; 4],
            metallic: 1.0,
            roughness: 0.8,
            normal_scale: 1.0,
            occlusion_strength: 0.5,
            // G roughness 0.25, B metallic 0.5
            metallic_roughness_texture: Some(image(2, 2, |_, _| [0.0, 0.25, 0.5, 1.0])),
            occlusion_texture: Some(image(2, 2, |_, _| [0.2, 0.0, 0.0, 1.0])),
            base_color_texture: Some(image(
                4,
                2,
                |x, _| if x < 2 { [1.0, 0.0, 0.0, 1.0] } else { [0.0, 0.0, 1.0, 1.0] },
            )),
            texture_count: 3,
            ..Default::default()
        };
        let maps = maps(&m).expect("textured");
        let l0 = &maps.levels[0];
        assert_eq!(l0.size, 4, "the largest side rounded up to a power of two");
        let mask = l0.mask[0];
        assert!((mask[0] - 0.5).abs() < 1e-6, "metallic multiplier from B");
        assert!((mask[1] - 0.6).abs() < 1e-6, "occlusion 1 + 0.5·(0.2 − 1)");
        // smoothness 1 − 0.8·0.25 = 0.8 = (1 − 0.8) + offset 0.6
        assert!((mask[3] - 1.1).abs() < 1e-6, "{mask:?}");
        assert!(l0.albedo[0][0] > 0.9 && l0.albedo[3][2] > 0.9, "left red, right blue");
        assert!(l0.emission.is_empty(), "no emissive texture, no emission map");
        assert!(maps.levels.last().unwrap().size == 1);
        assert!(super::maps(&GltfMaterial::default()).is_none(), "factors alone are flat");
    }
}
