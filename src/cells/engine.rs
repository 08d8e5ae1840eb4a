//! The engine states a matrix's cells render with (`[sweep.settings.<pipeline>]` over the
//! matrix's own), how they pair with the other axes' values, and what each composition has for
//! them to act on.

use std::collections::BTreeMap;

use super::Variation;
use crate::declarations::matrix::Matrix;
use crate::declarations::sweep::SweepDesign;
use crate::pipelines::settings_axes::{self, EngineState, SceneFacts, SettingValue};
use crate::pipelines::Pipeline;

/// A cell's engine state and the settings its id names (`settings_axes::apply`).
type EngineVariation = (EngineState, BTreeMap<String, SettingValue>);

/// The engine states `pipeline`'s cells render with: the matrix's own, changed by every
/// combination of one value per swept setting (a grid), or by one setting at a time.
pub(super) fn engine_variations(m: &Matrix, pipeline: Pipeline) -> Vec<EngineVariation> {
    let base = EngineState {
        settings: m.pipeline_settings,
        antialiasing: m.antialiasing_for(pipeline),
        budget: m.light_budget,
    };
    let lists: Vec<(&'static str, &Vec<SettingValue>)> = m
        .sweep
        .settings
        .get(&pipeline)
        .into_iter()
        .flatten()
        // An empty list keeps the engine's own value, as an empty axis list keeps the scene's.
        .filter(|(_, v)| !v.is_empty())
        .filter_map(|(k, v)| Some((settings_axes::find(pipeline, k)?.key, v)))
        .collect();
    let mut combos: Vec<Vec<(&'static str, SettingValue)>> = vec![Vec::new()];
    for (key, values) in &lists {
        combos = match m.sweep.design {
            SweepDesign::Grid => combos
                .into_iter()
                .flat_map(|c| {
                    values.iter().map(move |v| {
                        let mut next = c.clone();
                        next.push((*key, v.clone()));
                        next
                    })
                })
                .collect(),
            SweepDesign::OneAtATime => {
                combos.extend(values.iter().map(|v| vec![(*key, v.clone())]));
                combos
            }
        };
    }
    combos.iter().map(|c| settings_axes::apply(pipeline, base, c)).collect()
}

/// The (variation, engine) pairs of a pipeline × shader × preset: every pair in a grid; one
/// axis moved at a time otherwise (every variation at the matrix's engine, and every other
/// engine at the own variation, the first).
pub(super) fn combine<'v, 'e>(
    design: SweepDesign,
    variations: &'v [Variation<'v>],
    engines: &'e [EngineVariation],
) -> Vec<(&'v Variation<'v>, &'e EngineVariation)> {
    match design {
        SweepDesign::Grid => engines.iter().flat_map(|e| variations.iter().map(move |v| (v, e))).collect(),
        SweepDesign::OneAtATime => {
            let (own, moved) = engines.split_first().expect("the matrix's own engine");
            let first = variations.first();
            variations.iter().map(|v| (v, own)).chain(moved.iter().filter_map(|e| Some((first?, e)))).collect()
        }
    }
}

/// Per composition: what its engine settings act on (`SceneFacts`); without a key light the
/// light intensity and range axes change nothing.
pub(super) fn scene_facts(m: &Matrix) -> Vec<(bool, SceneFacts)> {
    m.compositions
        .iter()
        .map(|scene| {
            let shadowed: Vec<_> = scene.lights.iter().filter(|l| l.shadows).collect();
            let kind = crate::declarations::scene::LightKind::Directional;
            let facts = SceneFacts {
                shadows: scene.shadow_pass_needed().is_ok(),
                directional_shadows: shadowed.iter().any(|l| l.kind == kind),
                other_shadows: shadowed.iter().any(|l| l.kind != kind),
                soft_shadows: shadowed.iter().any(|l| l.shadow.soft),
                engine_resolution: shadowed.iter().any(|l| l.shadow.resolution.is_none()),
                lights: scene.lights.len() as u32,
                probes: scene.probes.len(),
                lod_groups: scene.objects.iter().any(|o| o.lod.as_ref().is_some_and(|g| g.bias.is_none())),
                hdrp_ssao: scene.hdrp.ssao,
                hdrp_bloom: scene.hdrp.bloom,
            };
            (scene.key_light().is_none(), facts)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::{expand, Cell};
    use crate::declarations::matrix::Matrix;
    use crate::pipelines::settings::UrpAssetPreset;
    use crate::pipelines::Pipeline;
    use std::sync::Arc;

    /// Engine settings multiply their own pipeline's cells; ids name what differs from the
    /// matrix's (or the preset's) own; what a scene cannot show is a twin; a typo is named.
    #[test]
    fn settings_axes_multiply_their_pipeline_and_twin_what_the_scene_cannot_show() {
        let text = "name = \"t\"\ncompositions = [\"default\", \"scenes/invariants/furnace.toml\"]\n\
                    pipelines = [\"builtin\", \"urp\"]\nshaders = [\"lit\", \"standard\"]\npresets = [\"plastic\"]\n\
                    [sweep.settings.urp]\nadditional_light_shadow_resolution = [512, 1024]\nasset = [\"default\", \"high_fidelity\"]\n\
                    [sweep.settings.builtin]\nshadow_resolution = [\"high\", \"very_high\"]\n\
                    [sweep.settings.hdrp]\nshadow_resolution = [1024]\n";
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let registry = Arc::new(crate::shading::Registry::builtin());
        let m = Matrix::from_text("t.toml", text, Some(root), registry.clone()).unwrap();
        let e = expand(&m);
        let of = |comp: &str, p: Pipeline| -> Vec<&Cell> {
            e.cells.iter().filter(|c| c.composition == comp && c.pipeline == p).collect()
        };
        let empty = text.replace("shadow_resolution = [\"high\", \"very_high\"]", "shadow_resolution = []");
        let e_empty = expand(&Matrix::from_text("t.toml", &empty, Some(root), registry.clone()).unwrap());
        let builtin = e_empty.cells.iter().filter(|c| c.pipeline == Pipeline::Builtin).count();
        assert_eq!(builtin, 2, "an empty list keeps the engine's own: one cell per composition");
        // URP: 2 resolutions × 2 assets; built-in: 2 levels; HDRP is not in the matrix: pruned.
        assert_eq!(of("default", Pipeline::Urp).len(), 4);
        assert_eq!(of("default", Pipeline::Builtin).len(), 2);
        assert!(e.pruned.iter().any(|p| p.description == "sweep.settings.hdrp"), "{:?}", e.pruned);
        let ids: Vec<&str> = of("default", Pipeline::Urp).iter().map(|c| c.id.0.as_str()).collect();
        assert!(ids.contains(&"default__urp-forward__lit__plastic__m0.00_s0.75_i2_r10"), "{ids:?}");
        let named = "_additional_light_shadow_resolution.1024_asset.high_fidelity";
        assert!(ids.iter().any(|id| id.ends_with(named)), "{ids:?}");
        for c in of("default", Pipeline::Urp) {
            let hf = c.settings.contains_key("asset");
            assert_eq!(c.pipeline_settings.urp.preset == UrpAssetPreset::HighFidelity, hf, "{}", c.id);
            assert_eq!(c.antialiasing.samples(), if hf { 4 } else { 1 }, "{}", c.id);
            assert!(!hf || c.twin_of.is_none(), "{}", c.id);
        }
        // The room's point light casts a shadow in URP only with High Fidelity's additional-light
        // shadows: under the default asset its map's resolution changes nothing.
        let default_asset: Vec<&Cell> =
            of("default", Pipeline::Urp).into_iter().filter(|c| !c.settings.contains_key("asset")).collect();
        assert_eq!(default_asset.iter().filter(|c| c.twin_of.is_some()).count(), 1, "{default_asset:?}");
        // The furnace has no shadows: a resolution changes nothing there.
        let furnace = of("white_furnace", Pipeline::Builtin);
        assert_eq!(furnace.iter().filter(|c| c.twin_of.is_some()).count(), 1, "{furnace:?}");
        let value = |key: &str| {
            let bad = text.replace("\"very_high\"]", key);
            Matrix::from_text("t.toml", &bad, Some(root), registry.clone()).unwrap_err().to_string()
        };
        let err = value("\"very_hihg\"]");
        assert!(err.contains("sweep.settings.builtin.shadow_resolution[1]") && err.contains("`very_high`"), "{err}");
        let err = Matrix::from_text("t.toml", &text.replace("asset = ", "aset = "), Some(root), registry.clone())
            .unwrap_err()
            .to_string();
        assert!(err.contains("did you mean `asset`?"), "{err}");
        let err = Matrix::from_text(
            "t.toml",
            &text.replace("[sweep.settings.hdrp]", "[sweep.settings.hdrp]\nsoft_shadows = [true]"),
            Some(root),
            registry,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("not a hdrp setting") && err.contains("a setting of urp"), "{err}");
    }
}
