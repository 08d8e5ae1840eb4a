//! Contact-sheet specifications: which two axes a sheet lays out as rows × columns. Part of the
//! matrix (`sheets = [...]`) and of the run record; the report stage draws them.

#[derive(Debug, Clone, serde::Deserialize, serde::Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SheetSpec {
    pub rows: String,
    pub cols: String,
}

/// The comparison application's views: pipelines × presets, and metallic × smoothness.
pub fn default_specs() -> Vec<SheetSpec> {
    vec![
        SheetSpec { rows: "pipeline".into(), cols: "preset".into() },
        SheetSpec { rows: "smoothness".into(), cols: "metallic".into() },
    ]
}
