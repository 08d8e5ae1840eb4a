//! The twelve material presets of `spec/presets.md`: linear base colour (albedo for dielectrics,
//! F0 for metals), metallic and default smoothness.

use serde::Serialize;

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Preset {
    pub name: &'static str,
    /// Linear sRGB.
    pub base_color: [f64; 3],
    pub metallic: f64,
    pub smoothness: f64,
    pub note: &'static str,
}

const fn preset(
    name: &'static str,
    base_color: [f64; 3],
    metallic: f64,
    smoothness: f64,
    note: &'static str,
) -> Preset {
    Preset { name, base_color, metallic, smoothness, note }
}

pub const PRESETS: [Preset; 12] = [
    preset("rubber", [0.036, 0.036, 0.036], 0.0, 0.3, "tyre-like black rubber"),
    preset("gold", [1.000, 0.766, 0.336], 1.0, 0.9, "metal reflectance chart"),
    preset("silver", [0.972, 0.960, 0.915], 1.0, 0.9, "metal reflectance chart"),
    preset("aluminium", [0.913, 0.921, 0.925], 1.0, 0.75, "satin"),
    preset("plastic", [0.284, 0.284, 0.284], 0.0, 0.75, "IOR ~1.5 (F0 0.04)"),
    preset("withered_wood", [0.18, 0.15, 0.12], 0.0, 0.1, "estimate: weathered, desaturated wood"),
    preset("blue_paint", [0.040, 0.047, 0.305], 0.0, 0.6, "colour-checker blue patch"),
    preset("fabric", [0.302, 0.294, 0.236], 0.0, 0.2, "no sheen in these models"),
    preset("marble", [0.830, 0.791, 0.753], 0.0, 0.9, "polished"),
    preset("wood", [0.242, 0.107, 0.045], 0.0, 0.45, "bare wood"),
    preset("concrete", [0.51, 0.51, 0.51], 0.0, 0.3, "fresh concrete"),
    preset("brick", [0.262, 0.095, 0.061], 0.0, 0.1, "red brick"),
];

/// The matrix's name for a glTF subject's own material (its factors and textures, `materials::gltf`).
/// Its values here are glTF's default material, which the file's factors replace per composition.
pub const OWN: Preset = preset("own", [1.0, 1.0, 1.0], 1.0, 0.0, "the glTF subject's own material");

pub fn preset_names() -> Vec<&'static str> {
    PRESETS.iter().map(|p| p.name).collect()
}

/// What a matrix's `presets` may name: the twelve and `own`.
pub fn matrix_preset_names() -> Vec<&'static str> {
    let mut names = preset_names();
    names.push(OWN.name);
    names
}

pub fn find_preset(name: &str) -> Option<&'static Preset> {
    PRESETS.iter().find(|p| p.name == name)
}

/// A preset as a matrix names it: one of the twelve, or `own`.
pub fn find_matrix_preset(name: &str) -> Option<&'static Preset> {
    if name == OWN.name {
        return Some(&OWN);
    }
    find_preset(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn twelve_distinct_presets_in_range() {
        let mut names = preset_names();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), 12);
        for p in PRESETS {
            assert!(p.base_color.iter().all(|c| (0.0..=1.0).contains(c)), "{}", p.name);
            assert!((0.0..=1.0).contains(&p.metallic) && (0.0..=1.0).contains(&p.smoothness));
        }
        assert_eq!(find_preset("gold").unwrap().metallic, 1.0);
    }
}
