//! The engine settings a matrix sweeps (`[sweep.settings.<pipeline>]`), one row per setting: the
//! values it takes, how it reads and sets a cell's engine state, and whether it is a preset (a
//! URP asset, a built-in quality level) that sets the others' values before they apply. What a
//! setting cannot change in a frame is decided here too (`frame_relevant`), so cells that differ
//! only there are twins.

use serde::{Deserialize, Serialize};

use super::settings::{
    BuiltinQuality, BuiltinShadows, HdrpLightUnit, HdrpQuality, PipelineSettings, QualityLevel, ShadowResolutionLevel,
    UrpAsset, UrpAssetPreset, UrpSsaoFeature,
};
use super::{Antialiasing, LightBudget, Pipeline, RenderPath};

/// What a cell renders with besides its scene and material: the engine settings, its
/// anti-aliasing and its light budgets (a quality level and a URP asset set all three).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EngineState {
    pub settings: PipelineSettings,
    pub antialiasing: Antialiasing,
    pub budget: LightBudget,
}

/// One swept setting's value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SettingValue {
    Bool(bool),
    Number(f64),
    Name(String),
}

impl SettingValue {
    /// As ids, labels and the viewer show it: `on`/`off`, the shortest exact number, the name.
    pub fn label(&self) -> String {
        match self {
            SettingValue::Bool(true) => "on".into(),
            SettingValue::Bool(false) => "off".into(),
            SettingValue::Number(x) => {
                let s = format!("{x:?}");
                s.strip_suffix(".0").map(str::to_string).unwrap_or(s)
            }
            SettingValue::Name(n) => n.clone(),
        }
    }

    fn flag(&self) -> bool {
        matches!(self, SettingValue::Bool(true))
    }

    fn number(&self) -> f64 {
        match self {
            SettingValue::Number(x) => *x,
            _ => 0.0,
        }
    }

    fn name(&self) -> &str {
        match self {
            SettingValue::Name(n) => n,
            _ => "",
        }
    }
}

/// The values a setting takes.
#[derive(Debug, Clone, Copy)]
pub enum SettingKind {
    Bool,
    /// A whole number among these.
    Among(&'static [u32]),
    /// A whole number in lo..=hi.
    Count(u32, u32),
    /// A shadow-map side: a power of two from 128 to 8192.
    Resolution,
    /// A real number in lo..=hi.
    Real(f64, f64),
    /// One of these names.
    Choice(fn() -> Vec<&'static str>),
}

impl SettingKind {
    /// What the kind allows, as an error message says it.
    pub fn allowed(&self) -> String {
        match self {
            SettingKind::Bool => "true or false".into(),
            SettingKind::Among(v) => v.iter().map(u32::to_string).collect::<Vec<_>>().join(", "),
            SettingKind::Count(lo, hi) => format!("whole numbers {lo}..={hi}"),
            SettingKind::Resolution => "a power of two from 128 to 8192".into(),
            SettingKind::Real(lo, hi) => format!("numbers {lo}..={hi}"),
            SettingKind::Choice(names) => names().join(", "),
        }
    }

    /// `value` as this kind's, or None where the kind does not take it.
    pub fn read(&self, value: &toml::Value) -> Option<SettingValue> {
        let whole = value.as_integer().and_then(|i| u32::try_from(i).ok());
        match self {
            SettingKind::Bool => value.as_bool().map(SettingValue::Bool),
            SettingKind::Among(allowed) => whole.filter(|v| allowed.contains(v)).map(number),
            SettingKind::Count(lo, hi) => whole.filter(|v| (*lo..=*hi).contains(v)).map(number),
            SettingKind::Resolution => whole.filter(|v| v.is_power_of_two() && (128..=8192).contains(v)).map(number),
            SettingKind::Real(lo, hi) => {
                let x = value.as_float().or(value.as_integer().map(|i| i as f64))?;
                (x.is_finite() && (*lo..=*hi).contains(&x)).then_some(SettingValue::Number(x))
            }
            SettingKind::Choice(names) => {
                let name = value.as_str()?;
                names().contains(&name).then(|| SettingValue::Name(name.to_string()))
            }
        }
    }
}

/// One engine setting a sweep may list.
#[derive(Clone, Copy)]
pub struct SettingRow {
    pub pipeline: Pipeline,
    /// As `[sweep.settings.<pipeline>]` and cell ids name it.
    pub key: &'static str,
    pub kind: SettingKind,
    /// A preset that sets other rows' fields: applied before them.
    pub preset: bool,
    pub get: fn(&EngineState) -> SettingValue,
    pub set: fn(&mut EngineState, &SettingValue),
}

fn urp_asset(e: &mut EngineState, v: &SettingValue) {
    let preset = UrpAssetPreset::from_name(v.name()).unwrap_or_default();
    let asset = preset.asset();
    e.settings.urp = asset;
    e.antialiasing = asset.msaa;
    e.budget.urp_per_object_limit = asset.additional_lights_per_object_limit;
}

fn quality_level(e: &mut EngineState, v: &SettingValue) {
    let level = QualityLevel::ALL.into_iter().find(|l| l.name() == v.name()).unwrap_or_default();
    let (quality, pixel_lights, aa) = level.fields();
    e.settings.builtin.quality = quality;
    e.budget.pixel_light_count = pixel_lights;
    e.antialiasing = aa;
}

fn hdrp_quality(v: &SettingValue) -> HdrpQuality {
    HdrpQuality::ALL.into_iter().find(|q| q.name() == v.name()).unwrap_or_default()
}

fn msaa(v: &SettingValue) -> Antialiasing {
    Antialiasing::from_name(v.name()).unwrap_or_default()
}

fn number(x: impl Into<f64>) -> SettingValue {
    SettingValue::Number(x.into())
}

fn name(n: &str) -> SettingValue {
    SettingValue::Name(n.to_string())
}

fn quality_levels() -> Vec<&'static str> {
    QualityLevel::ALL.iter().map(|l| l.name()).collect()
}

fn builtin_shadows() -> Vec<&'static str> {
    BuiltinShadows::ALL.iter().map(|s| s.name()).collect()
}

fn resolution_levels() -> Vec<&'static str> {
    ShadowResolutionLevel::ALL.iter().map(|r| r.name()).collect()
}

/// A setting held in one field of the engine state, read and written as a flag (`bool`), a whole
/// number (`u32`) or a real one (`f64`).
macro_rules! field {
    ($pipeline:ident, $key:literal, $kind:expr, bool, $($path:ident).+) => {
        SettingRow {
            pipeline: Pipeline::$pipeline,
            key: $key,
            kind: $kind,
            preset: false,
            get: |e| SettingValue::Bool(e.$($path).+),
            set: |e, v| e.$($path).+ = v.flag(),
        }
    };
    ($pipeline:ident, $key:literal, $kind:expr, HdrpQuality, $($path:ident).+) => {
        SettingRow {
            pipeline: Pipeline::$pipeline,
            key: $key,
            kind: $kind,
            preset: false,
            get: |e| name(e.$($path).+.name()),
            set: |e, v| e.$($path).+ = hdrp_quality(v),
        }
    };
    ($pipeline:ident, $key:literal, $kind:expr, u32, $($path:ident).+) => {
        SettingRow {
            pipeline: Pipeline::$pipeline,
            key: $key,
            kind: $kind,
            preset: false,
            get: |e| number(e.$($path).+),
            set: |e, v| e.$($path).+ = v.number() as u32,
        }
    };
    ($pipeline:ident, $key:literal, $kind:expr, f64, $($path:ident).+) => {
        SettingRow {
            pipeline: Pipeline::$pipeline,
            key: $key,
            kind: $kind,
            preset: false,
            get: |e| number(e.$($path).+),
            set: |e, v| e.$($path).+ = v.number(),
        }
    };
}

/// Every engine setting a sweep may list, presets first within each pipeline.
pub const SETTINGS: &[SettingRow] = &[
    // Built-in: a quality level (QualitySettings) and its fields.
    SettingRow {
        pipeline: Pipeline::Builtin,
        key: "quality_level",
        kind: SettingKind::Choice(quality_levels),
        preset: true,
        get: |e| name(e.settings.builtin.quality.level.name()),
        set: quality_level,
    },
    SettingRow {
        pipeline: Pipeline::Builtin,
        key: "shadows",
        kind: SettingKind::Choice(builtin_shadows),
        preset: false,
        get: |e| name(e.settings.builtin.quality.shadows.name()),
        set: |e, v| {
            let found = BuiltinShadows::ALL.into_iter().find(|s| s.name() == v.name());
            e.settings.builtin.quality.shadows = found.unwrap_or(BuiltinShadows::All);
        },
    },
    SettingRow {
        pipeline: Pipeline::Builtin,
        key: "shadow_resolution",
        kind: SettingKind::Choice(resolution_levels),
        preset: false,
        get: |e| name(e.settings.builtin.quality.shadow_resolution.name()),
        set: |e, v| {
            let found = ShadowResolutionLevel::ALL.into_iter().find(|r| r.name() == v.name());
            e.settings.builtin.quality.shadow_resolution = found.unwrap_or(ShadowResolutionLevel::High);
        },
    },
    field!(Builtin, "shadow_cascades", SettingKind::Among(&[1, 2, 4]), u32, settings.builtin.quality.shadow_cascades),
    field!(Builtin, "shadow_distance", SettingKind::Real(0.0, 10_000.0), f64, settings.builtin.quality.shadow_distance),
    field!(Builtin, "lod_bias", SettingKind::Real(0.01, 10.0), f64, settings.builtin.quality.lod_bias),
    field!(Builtin, "pixel_light_count", SettingKind::Count(0, 64), u32, budget.pixel_light_count),
    SettingRow {
        pipeline: Pipeline::Builtin,
        key: "msaa",
        kind: SettingKind::Choice(Antialiasing::names),
        preset: false,
        get: |e| name(e.antialiasing.name()),
        set: |e, v| e.antialiasing = msaa(v),
    },
    field!(Builtin, "forward_add", SettingKind::Bool, bool, settings.builtin.forward_add),
    // URP: an asset and its fields (`settings::UrpAsset`).
    SettingRow {
        pipeline: Pipeline::Urp,
        key: "asset",
        kind: SettingKind::Choice(UrpAssetPreset::names),
        preset: true,
        get: |e| name(e.settings.urp.preset.name()),
        set: urp_asset,
    },
    SettingRow {
        pipeline: Pipeline::Urp,
        key: "msaa",
        kind: SettingKind::Choice(Antialiasing::names),
        preset: false,
        get: |e| name(e.antialiasing.name()),
        set: |e, v| {
            e.antialiasing = msaa(v);
            e.settings.urp.msaa = msaa(v);
        },
    },
    field!(
        Urp,
        "main_light_shadow_resolution",
        SettingKind::Resolution,
        u32,
        settings.urp.main_light_shadow_resolution
    ),
    SettingRow {
        pipeline: Pipeline::Urp,
        key: "additional_lights_per_object_limit",
        kind: SettingKind::Count(0, 8),
        preset: false,
        get: |e| number(e.budget.urp_per_object_limit),
        set: |e, v| {
            e.budget.urp_per_object_limit = v.number() as u32;
            e.settings.urp.additional_lights_per_object_limit = v.number() as u32;
        },
    },
    field!(Urp, "additional_light_shadows", SettingKind::Bool, bool, settings.urp.additional_light_shadows),
    field!(
        Urp,
        "additional_light_shadow_resolution",
        SettingKind::Resolution,
        u32,
        settings.urp.additional_light_shadow_resolution
    ),
    field!(Urp, "reflection_probe_blending", SettingKind::Bool, bool, settings.urp.reflection_probe_blending),
    field!(
        Urp,
        "reflection_probe_box_projection",
        SettingKind::Bool,
        bool,
        settings.urp.reflection_probe_box_projection
    ),
    field!(Urp, "shadow_distance", SettingKind::Real(0.0, 10_000.0), f64, settings.urp.shadow_distance),
    field!(Urp, "cascade_count", SettingKind::Count(1, 4), u32, settings.urp.cascade_count),
    field!(Urp, "depth_bias", SettingKind::Real(0.0, 10.0), f64, settings.urp.depth_bias),
    field!(Urp, "normal_bias", SettingKind::Real(0.0, 10.0), f64, settings.urp.normal_bias),
    field!(Urp, "soft_shadows", SettingKind::Bool, bool, settings.urp.soft_shadows),
    SettingRow {
        pipeline: Pipeline::Urp,
        key: "ssao",
        kind: SettingKind::Bool,
        preset: false,
        get: |e| SettingValue::Bool(e.settings.urp.ssao.is_some()),
        set: |e, v| {
            e.settings.urp.ssao = match v.flag() {
                false => None,
                true => e.settings.urp.ssao.or(Some(UrpSsaoFeature::HIGH_FIDELITY)),
            }
        },
    },
    // HDRP.
    field!(Hdrp, "shadow_resolution", SettingKind::Resolution, u32, settings.hdrp.shadow_resolution),
    field!(
        Hdrp,
        "shadow_filtering",
        SettingKind::Choice(HdrpQuality::names),
        HdrpQuality,
        settings.hdrp.shadow_filtering
    ),
    field!(Hdrp, "ssao", SettingKind::Bool, bool, settings.hdrp.ssao),
    field!(Hdrp, "ssao_quality", SettingKind::Choice(HdrpQuality::names), HdrpQuality, settings.hdrp.ssao_quality),
    field!(Hdrp, "bloom", SettingKind::Bool, bool, settings.hdrp.bloom),
    field!(Hdrp, "bloom_quality", SettingKind::Choice(HdrpQuality::names), HdrpQuality, settings.hdrp.bloom_quality),
    SettingRow {
        pipeline: Pipeline::Hdrp,
        key: "light_unit",
        kind: SettingKind::Choice(HdrpLightUnit::names),
        preset: false,
        get: |e| name(e.settings.hdrp.light_unit.name()),
        set: |e, v| {
            e.settings.hdrp.light_unit =
                HdrpLightUnit::ALL.into_iter().find(|u| u.name() == v.name()).unwrap_or_default()
        },
    },
];

/// The row of `pipeline`'s setting `key`.
pub fn find(pipeline: Pipeline, key: &str) -> Option<&'static SettingRow> {
    SETTINGS.iter().find(|r| r.pipeline == pipeline && r.key == key)
}

/// `pipeline`'s settings' keys, in table order.
pub fn keys(pipeline: Pipeline) -> Vec<&'static str> {
    SETTINGS.iter().filter(|r| r.pipeline == pipeline).map(|r| r.key).collect()
}

/// `base` with `values` applied, presets first, and the values that changed what the state held
/// when each was applied (what a cell id names: a value equal to the preset's own, or to the
/// matrix's, names nothing, so its cell is the one without it).
pub fn apply(
    pipeline: Pipeline,
    base: EngineState,
    values: &[(&'static str, SettingValue)],
) -> (EngineState, std::collections::BTreeMap<String, SettingValue>) {
    let mut state = base;
    let mut named = std::collections::BTreeMap::new();
    let rows = |preset: bool| {
        values.iter().filter_map(move |(k, v)| find(pipeline, k).filter(|r| r.preset == preset).map(|r| (r, v)))
    };
    for (row, v) in rows(true).chain(rows(false)) {
        if (row.get)(&state) != *v {
            (row.set)(&mut state, v);
            named.insert(row.key.to_string(), v.clone());
        }
    }
    (state, named)
}

/// What a composition has that engine settings act on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SceneFacts {
    /// Its frames draw shadow maps (a light and objects cast, objects receive).
    pub shadows: bool,
    /// A directional light casts shadows; a point or spot light does.
    pub directional_shadows: bool,
    pub other_shadows: bool,
    /// A shadowed light asks for soft shadows.
    pub soft_shadows: bool,
    /// A shadowed light takes its map's size from the engine (its scene entry sets none).
    pub engine_resolution: bool,
    /// Real-time lights.
    pub lights: u32,
    pub probes: usize,
    /// An object is a LOD group whose switch the quality level's LOD bias moves (it sets no bias
    /// of its own).
    pub lod_groups: bool,
    /// The scene keeps HDRP's ambient occlusion and bloom on (`[hdrp] ssao`, `bloom`).
    pub hdrp_ssao: bool,
    pub hdrp_bloom: bool,
}

/// `state` with what cannot change a frame of `path` in `pipeline` of a composition with `facts`
/// set to one value: two cells whose relevant states are equal draw the same frame.
pub fn frame_relevant(pipeline: Pipeline, path: RenderPath, facts: &SceneFacts, state: &EngineState) -> EngineState {
    let mut e = *state;
    // MSAA: deferred paths render one sample.
    e.antialiasing = match state.antialiasing.samples_on(path).0 {
        1 => Antialiasing::None,
        _ => state.antialiasing,
    };
    // A budget at least the lights' count lets every light through.
    e.budget.pixel_light_count = state.budget.pixel_light_count.min(facts.lights);
    e.budget.urp_per_object_limit = state.budget.urp_per_object_limit.min(facts.lights);
    let shadows = facts.shadows && path != RenderPath::VertexLit;
    let ultra = QualityLevel::Ultra.fields().0;
    let q = &mut e.settings.builtin.quality;
    q.level = ultra.level;
    if !facts.lod_groups {
        q.lod_bias = ultra.lod_bias;
    }
    if !shadows || q.shadows == BuiltinShadows::Disable {
        let off = q.shadows == BuiltinShadows::Disable && shadows;
        *q = BuiltinQuality { lod_bias: q.lod_bias, ..ultra };
        if off {
            q.shadows = BuiltinShadows::Disable;
        }
    } else {
        if !facts.directional_shadows {
            (q.shadow_cascades, q.shadow_distance) = (ultra.shadow_cascades, ultra.shadow_distance);
        }
        if !facts.engine_resolution {
            q.shadow_resolution = ultra.shadow_resolution;
        }
        if !facts.soft_shadows {
            q.shadows = BuiltinShadows::All;
        }
    }
    let d = UrpAsset::default();
    let u = &mut e.settings.urp;
    u.preset = d.preset;
    u.msaa = e.antialiasing;
    u.additional_lights_per_object_limit = e.budget.urp_per_object_limit;
    if !shadows || !facts.directional_shadows {
        (u.main_light_shadow_resolution, u.cascade_count, u.shadow_distance) =
            (d.main_light_shadow_resolution, d.cascade_count, d.shadow_distance);
    }
    // Without the asset's additional-light shadows a point or spot light casts none.
    let additional = shadows && facts.other_shadows && u.additional_light_shadows;
    if !additional {
        (u.additional_light_shadows, u.additional_light_shadow_resolution) =
            (d.additional_light_shadows, d.additional_light_shadow_resolution);
    }
    if !facts.engine_resolution {
        (u.main_light_shadow_resolution, u.additional_light_shadow_resolution) =
            (d.main_light_shadow_resolution, d.additional_light_shadow_resolution);
    }
    let urp_shadows = (shadows && facts.directional_shadows) || additional;
    if !urp_shadows {
        (u.depth_bias, u.normal_bias) = (d.depth_bias, d.normal_bias);
    }
    if !urp_shadows || !facts.soft_shadows {
        u.soft_shadows = d.soft_shadows;
    }
    if facts.probes == 0 {
        (u.reflection_probe_blending, u.reflection_probe_box_projection) =
            (d.reflection_probe_blending, d.reflection_probe_box_projection);
    }
    let h = &mut e.settings.hdrp;
    if !shadows || !facts.engine_resolution {
        h.shadow_resolution = super::settings::HDRP_SHADOW_RESOLUTION;
    }
    if facts.lights == 0 {
        h.light_unit = HdrpLightUnit::default();
    }
    if !shadows {
        h.shadow_filtering = HdrpQuality::default();
    }
    // The scene's switch turns a volume's effect off whatever the settings say; vertex-lit draws
    // no SSAO; an effect off draws at no quality.
    h.ssao &= facts.hdrp_ssao && path != RenderPath::VertexLit;
    if !h.ssao {
        h.ssao_quality = HdrpQuality::default();
    }
    h.bloom &= facts.hdrp_bloom;
    if !h.bloom {
        h.bloom_quality = HdrpQuality::default();
    }
    // Another pipeline's settings never reach this one's frames.
    let base = PipelineSettings::default();
    match pipeline {
        Pipeline::Builtin => (e.settings.urp, e.settings.hdrp) = (base.urp, base.hdrp),
        Pipeline::Urp => (e.settings.builtin, e.settings.hdrp) = (base.builtin, base.hdrp),
        Pipeline::Hdrp => (e.settings.builtin, e.settings.urp) = (base.builtin, base.urp),
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> EngineState {
        EngineState {
            settings: PipelineSettings::default(),
            antialiasing: Pipeline::Urp.default_antialiasing(),
            budget: LightBudget::default(),
        }
    }

    #[test]
    fn presets_apply_first_and_a_value_equal_to_the_presets_names_nothing() {
        let values = vec![
            ("soft_shadows", SettingValue::Bool(true)),
            ("asset", SettingValue::Name("high_fidelity".into())),
            ("msaa", SettingValue::Name("none".into())),
        ];
        let (state, named) = apply(Pipeline::Urp, base(), &values);
        assert_eq!(state.settings.urp.preset, UrpAssetPreset::HighFidelity);
        assert_eq!(state.antialiasing, Antialiasing::None, "the field after the asset");
        assert!(state.settings.urp.soft_shadows);
        let keys: Vec<&str> = named.keys().map(String::as_str).collect();
        assert_eq!(keys, ["asset", "msaa"], "High Fidelity's soft shadows are its own");
        let (same, named) = apply(Pipeline::Urp, base(), &[("cascade_count", SettingValue::Number(1.0))]);
        assert!(named.is_empty() && same == base(), "the code default's own value");
    }

    #[test]
    fn every_row_reads_back_what_it_sets_and_its_kind_reads_its_values() {
        for row in SETTINGS {
            let v = match row.kind {
                SettingKind::Bool => toml::Value::Boolean(true),
                SettingKind::Among(a) => toml::Value::Integer(a[1] as i64),
                SettingKind::Count(_, hi) => toml::Value::Integer(hi as i64),
                SettingKind::Resolution => toml::Value::Integer(256),
                SettingKind::Real(_, hi) => toml::Value::Float(hi),
                SettingKind::Choice(names) => toml::Value::String(names()[1].to_string()),
            };
            let value = row.kind.read(&v).unwrap_or_else(|| panic!("{}: {v}", row.key));
            let mut e = base();
            (row.set)(&mut e, &value);
            assert_eq!((row.get)(&e), value, "{}", row.key);
            assert!(row.kind.read(&toml::Value::String("nonsense".into())).is_none(), "{}", row.key);
        }
        assert!(SettingKind::Resolution.read(&toml::Value::Integer(300)).is_none());
        assert!(SettingKind::Among(&[1, 2, 4]).read(&toml::Value::Integer(3)).is_none());
    }

    #[test]
    fn what_a_scene_lacks_leaves_the_frame_as_it_is() {
        let lit = SceneFacts {
            shadows: true,
            directional_shadows: true,
            other_shadows: false,
            soft_shadows: true,
            engine_resolution: true,
            lights: 2,
            probes: 0,
            lod_groups: false,
            hdrp_ssao: true,
            hdrp_bloom: false,
        };
        let with = |key: &'static str, v: SettingValue, p: Pipeline| apply(p, base(), &[(key, v)]).0;
        let relevant = |facts: &SceneFacts, e: &EngineState, p: Pipeline, path| frame_relevant(p, path, facts, e);
        let hi = with("main_light_shadow_resolution", SettingValue::Number(4096.0), Pipeline::Urp);
        let fwd = RenderPath::Forward;
        assert_ne!(relevant(&lit, &hi, Pipeline::Urp, fwd), relevant(&lit, &base(), Pipeline::Urp, fwd));
        let unlit = SceneFacts { shadows: false, ..lit };
        assert_eq!(relevant(&unlit, &hi, Pipeline::Urp, fwd), relevant(&unlit, &base(), Pipeline::Urp, fwd));
        // HDRP: filtering without a shadow, bloom's quality where the scene turns bloom off and
        // SSAO's where it turns SSAO off are twins; SSAO turned off by the settings is not, and
        // with the scene's off it is.
        let hdrp = |key: &'static str, v: &str| with(key, SettingValue::Name(v.into()), Pipeline::Hdrp);
        let h = |facts: &SceneFacts, e: &EngineState| relevant(facts, e, Pipeline::Hdrp, fwd);
        assert_ne!(h(&lit, &hdrp("shadow_filtering", "low")), h(&lit, &base()));
        assert_eq!(h(&unlit, &hdrp("shadow_filtering", "low")), h(&unlit, &base()));
        assert_eq!(h(&lit, &hdrp("bloom_quality", "low")), h(&lit, &base()));
        let no_ssao = with("ssao", SettingValue::Bool(false), Pipeline::Hdrp);
        assert_ne!(h(&lit, &no_ssao), h(&lit, &base()));
        let scene_off = SceneFacts { hdrp_ssao: false, ..lit };
        assert_eq!(h(&scene_off, &no_ssao), h(&scene_off, &base()));
        for level in ["low", "high"] {
            assert_ne!(h(&lit, &hdrp("ssao_quality", level)), h(&lit, &base()));
            assert_eq!(h(&scene_off, &hdrp("ssao_quality", level)), h(&scene_off, &base()));
        }
        let bloomed = SceneFacts { hdrp_bloom: true, ..lit };
        assert_ne!(h(&bloomed, &hdrp("bloom_quality", "low")), h(&bloomed, &base()));
        // MSAA on a deferred path, a light budget past the lights, URP fields in a built-in frame.
        let aa = with("msaa", SettingValue::Name("msaa8".into()), Pipeline::Urp);
        let deferred = RenderPath::Deferred;
        assert_eq!(relevant(&lit, &aa, Pipeline::Urp, deferred), relevant(&lit, &base(), Pipeline::Urp, deferred));
        let budget = with("pixel_light_count", SettingValue::Number(9.0), Pipeline::Builtin);
        assert_eq!(relevant(&lit, &budget, Pipeline::Builtin, fwd), relevant(&lit, &base(), Pipeline::Builtin, fwd));
        assert_eq!(relevant(&lit, &hi, Pipeline::Builtin, fwd), relevant(&lit, &base(), Pipeline::Builtin, fwd));
        // Hard Only is All where no light asks for soft shadows.
        // A LOD bias reaches a frame through a LOD group alone.
        let bias = with("lod_bias", SettingValue::Number(0.4), Pipeline::Builtin);
        let grouped = SceneFacts { lod_groups: true, ..lit };
        assert_eq!(relevant(&lit, &bias, Pipeline::Builtin, fwd), relevant(&lit, &base(), Pipeline::Builtin, fwd));
        assert_ne!(
            relevant(&grouped, &bias, Pipeline::Builtin, fwd),
            relevant(&grouped, &base(), Pipeline::Builtin, fwd)
        );
        let hard = with("shadows", SettingValue::Name("hard_only".into()), Pipeline::Builtin);
        let hard_facts = SceneFacts { soft_shadows: false, ..lit };
        assert_ne!(relevant(&lit, &hard, Pipeline::Builtin, fwd), relevant(&lit, &base(), Pipeline::Builtin, fwd));
        assert_eq!(
            relevant(&hard_facts, &hard, Pipeline::Builtin, fwd),
            relevant(&hard_facts, &base(), Pipeline::Builtin, fwd)
        );
    }
}
