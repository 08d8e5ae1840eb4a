//! Contact-sheet specifications: which two axes a sheet lays out as rows × columns. Part of the
//! matrix (`sheets = [...]`) and of the run record; the report stage draws them.

#[derive(Debug, Clone, serde::Deserialize, serde::Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SheetSpec {
    /// An axis, or `term`: the image and each of its term layers (`[outputs] terms`).
    pub rows: String,
    pub cols: String,
    /// What each tile shows: `image` (the default) or a term layer (`direct_specular`, …).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
}

/// The pseudo-axis of a sheet whose rows or columns are a cell's image and its term layers.
pub const TERM_AXIS: &str = "term";
/// A tile's whole image, as opposed to one of its term layers.
pub const WHOLE_IMAGE: &str = "image";

/// The comparison application's views: pipelines × presets, and metallic × smoothness.
pub fn default_specs() -> Vec<SheetSpec> {
    vec![
        SheetSpec { rows: "pipeline".into(), cols: "preset".into(), image: None },
        SheetSpec { rows: "smoothness".into(), cols: "metallic".into(), image: None },
    ]
}
