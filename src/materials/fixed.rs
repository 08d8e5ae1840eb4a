//! The fixed objects' material maps (`FixedMaterial::base_color_map`, `gltf_material`), made once
//! per composition: each distinct source becomes `MaterialMaps` in the subject's layout (albedo
//! multiplier, tangent-space normal, HDRP mask, emission multiplier) on one common square grid, so
//! that the renderer keeps them in one texture array (four layers per material) that every pass
//! and both truth backends read. The grid is the largest texture's side rounded up to a power of
//! two, at most `gltf::MAX_SIZE`, halved while the array would pass `MAX_ARRAY_BYTES`: a smaller
//! grid filters a texture down, which `FixedMaps::size` records.

use std::sync::Arc;

use super::{with_mips, MapLevel, MaterialMaps};
use crate::declarations::scene::{GltfMaterialRef, Scene};
use crate::error::Error;
use crate::geometry::gltf_io::GltfMaterial;
use crate::input::texture_file::TextureFile;

/// The largest the fixed maps' array may be on the GPU (Rgba16Float with mips).
pub const MAX_ARRAY_BYTES: usize = 256 << 20;

/// A composition's fixed maps.
#[derive(Debug, Clone, Default)]
pub struct FixedMaps {
    /// Texels per side of every material's finest level (0: no maps).
    pub size: usize,
    /// The largest side the sources have: above `size`, they were filtered down.
    pub largest_source: usize,
    /// One per distinct source, in the order objects first name them.
    pub materials: Vec<MaterialMaps>,
    /// Per scene object: its material's slot in `materials` (None: factors alone).
    pub slots: Vec<Option<usize>>,
}

enum Source {
    Image(Arc<TextureFile>),
    Gltf(Box<GltfMaterial>),
}

impl FixedMaps {
    /// The maps of `scene`'s fixed objects; the glTF materials are read here (their images
    /// decoded), the base-colour maps were read with the scene.
    pub fn of(scene: &Scene) -> Result<FixedMaps, Error> {
        let mut keys: Vec<String> = Vec::new();
        let mut sources: Vec<Source> = Vec::new();
        let mut slots = Vec::with_capacity(scene.objects.len());
        for o in &scene.objects {
            let Some(m) = o.material.as_ref().filter(|m| m.has_maps()) else {
                slots.push(None);
                continue;
            };
            let key = match (&m.map_image, &m.gltf_material) {
                (Some(image), _) => format!("image {}", image.digest),
                (None, Some(r)) => format!("gltf {}#{}", r.path, r.index),
                (None, None) => {
                    return Err(Error::Other(format!(
                        "composition `{}`: object `{}`'s base-colour map was not read with its scene",
                        scene.name, o.name
                    )))
                }
            };
            let slot = match keys.iter().position(|k| *k == key) {
                Some(slot) => slot,
                None => {
                    sources.push(match (&m.map_image, &m.gltf_material) {
                        (Some(image), _) => Source::Image(image.clone()),
                        (None, Some(r)) => Source::Gltf(Box::new(read_gltf_material(scene, r)?)),
                        (None, None) => unreachable!("refused above"),
                    });
                    keys.push(key);
                    keys.len() - 1
                }
            };
            slots.push(Some(slot));
        }
        if sources.is_empty() {
            return Ok(FixedMaps { slots, ..Default::default() });
        }
        let largest = sources
            .iter()
            .map(|s| match s {
                Source::Image(t) => t.width.max(t.height),
                Source::Gltf(m) => super::gltf::largest_side(m),
            })
            .max()
            .unwrap_or(1);
        let size = grid_size(largest, sources.len());
        let materials = sources
            .iter()
            .map(|s| match s {
                Source::Image(t) => image_maps(t, size),
                Source::Gltf(m) => super::gltf::maps_at(m, size),
            })
            .collect();
        Ok(FixedMaps { size, largest_source: largest, materials, slots })
    }
}

/// The common grid for `count` materials whose largest texture has `largest` texels per side.
pub fn grid_size(largest: usize, count: usize) -> usize {
    let mut size = largest.next_power_of_two().min(super::gltf::MAX_SIZE);
    // Four Rgba16Float layers per material, and a third more for the mips.
    while size > 1 && count * 4 * size * size * 8 * 4 / 3 > MAX_ARRAY_BYTES {
        size /= 2;
    }
    size
}

fn read_gltf_material(scene: &Scene, r: &GltfMaterialRef) -> Result<GltfMaterial, Error> {
    let dir = scene.base_dir.as_ref().ok_or_else(|| {
        Error::Other(format!("composition `{}`: a built-in scene names no glTF file (`{}`)", scene.name, r.path))
    })?;
    crate::geometry::gltf_io::material_by_index(&dir.join(&r.path), r.index)
}

/// A base-colour map alone: the image resampled (bilinear, repeating) as the albedo multiplier,
/// the other maps neutral.
fn image_maps(t: &TextureFile, size: usize) -> MaterialMaps {
    let texels: Vec<[f32; 4]> = t.texels.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
    let n = size * size;
    let albedo = (0..n)
        .map(|i| {
            let (x, y) = ((i % size) as f64 + 0.5, (i / size) as f64 + 0.5);
            super::bilinear(&texels, t.width, t.height, x / size as f64, y / size as f64)
        })
        .collect();
    with_mips(MapLevel {
        size,
        albedo,
        normal: vec![[0.0, 0.0, 1.0, super::NO_HEIGHT]; n],
        mask: vec![[1.0, 1.0, 1.0, 0.5]; n],
        emission: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_halves_until_the_array_fits() {
        assert_eq!(grid_size(300, 1), 512);
        assert_eq!(grid_size(5000, 1), 1024, "at most MAX_SIZE");
        // 24 materials at 1024² would be 1 GiB: 512² keeps them within 256 MiB.
        assert_eq!(grid_size(1024, 24), 512);
        let bytes = |count: usize, size: usize| count * 4 * size * size * 8 * 4 / 3;
        assert!(bytes(24, 512) <= MAX_ARRAY_BYTES && bytes(24, 1024) > MAX_ARRAY_BYTES);
    }
}
