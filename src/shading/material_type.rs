//! HDRP Lit's Material Type (Lit.shader `_MaterialID`) as a sweep axis: each type is a setting of
//! the model's parameters, so a sweep shows Standard beside each type. A model that lacks the
//! parameters a type sets has no such type, and its cells are pruned with the reason.

use serde::{Deserialize, Serialize};

use super::registry::ShaderModel;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialType {
    /// HDRP's Standard: the metallic workflow, no film.
    Standard,
    /// HDRP's Specular Color; the specular setup of Standard and URP Lit too (`specular_setup`).
    SpecularColor,
    /// HDRP's Iridescence: a thin film over the base (`iridescence_mask` 1, its default mask).
    Iridescence,
    /// HDRP's Anisotropy: anisotropic GGX along the tangent, by the `anisotropy` parameter (0 in a
    /// new material, where it draws as Standard); the other types have none.
    Anisotropy,
    /// HDRP's Translucent: thin-object transmission through the default diffusion profile
    /// (`transmission` 1), its slab `thickness` a parameter.
    Translucent,
    /// HDRP's Subsurface Scattering: the diffuse lighting blurred by the screen-space filter with
    /// the default profile (`subsurface_scattering` 1), Transmission on as a new material has it.
    SubsurfaceScattering,
}

impl MaterialType {
    /// The types built here (HDRP's inspector lists Subsurface Scattering first; it came last here).
    pub const ALL: [MaterialType; 6] = [
        MaterialType::Standard,
        MaterialType::SpecularColor,
        MaterialType::Iridescence,
        MaterialType::Anisotropy,
        MaterialType::Translucent,
        MaterialType::SubsurfaceScattering,
    ];

    pub fn name(self) -> &'static str {
        match self {
            MaterialType::Standard => "standard",
            MaterialType::SpecularColor => "specular_color",
            MaterialType::Iridescence => "iridescence",
            MaterialType::Anisotropy => "anisotropy",
            MaterialType::Translucent => "translucent",
            MaterialType::SubsurfaceScattering => "subsurface_scattering",
        }
    }

    pub fn from_name(name: &str) -> Option<MaterialType> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|t| t.name()).collect()
    }

    /// The parameter values that select the type, where the model has them: the others' set back
    /// to 0. The Anisotropy type leaves `anisotropy` to the sweep (its slider); the other types
    /// have no anisotropy, so a swept value does not reach them.
    pub fn params(self) -> &'static [(&'static str, f64)] {
        match self {
            MaterialType::Standard => &[
                ("specular_setup", 0.0),
                ("iridescence_mask", 0.0),
                ("anisotropy", 0.0),
                ("transmission", 0.0),
                ("subsurface_scattering", 0.0),
            ],
            MaterialType::SpecularColor => &[
                ("specular_setup", 1.0),
                ("iridescence_mask", 0.0),
                ("anisotropy", 0.0),
                ("transmission", 0.0),
                ("subsurface_scattering", 0.0),
            ],
            MaterialType::Iridescence => &[
                ("specular_setup", 0.0),
                ("iridescence_mask", 1.0),
                ("anisotropy", 0.0),
                ("transmission", 0.0),
                ("subsurface_scattering", 0.0),
            ],
            MaterialType::Anisotropy => &[
                ("specular_setup", 0.0),
                ("iridescence_mask", 0.0),
                ("transmission", 0.0),
                ("subsurface_scattering", 0.0),
            ],
            MaterialType::Translucent => &[
                ("specular_setup", 0.0),
                ("iridescence_mask", 0.0),
                ("anisotropy", 0.0),
                ("transmission", 1.0),
                ("subsurface_scattering", 0.0),
            ],
            // BaseLitAPI: _MATERIAL_FEATURE_TRANSMISSION with LitSSS where _TransmissionEnable (1).
            MaterialType::SubsurfaceScattering => &[
                ("specular_setup", 0.0),
                ("iridescence_mask", 0.0),
                ("anisotropy", 0.0),
                ("transmission", 1.0),
                ("subsurface_scattering", 1.0),
            ],
        }
    }

    /// The parameter that makes the type what it is (none for Standard).
    fn defining_param(self) -> Option<&'static str> {
        match self {
            MaterialType::Standard => None,
            MaterialType::SpecularColor => Some("specular_setup"),
            MaterialType::Iridescence => Some("iridescence_mask"),
            MaterialType::Anisotropy => Some("anisotropy"),
            MaterialType::Translucent => Some("transmission"),
            MaterialType::SubsurfaceScattering => Some("subsurface_scattering"),
        }
    }

    /// Why `model` has no such type, or None when it has.
    pub fn missing_in(self, model: &ShaderModel) -> Option<String> {
        let param = self.defining_param()?;
        if model.params.iter().any(|p| p.name == param) {
            return None;
        }
        let with: Vec<&str> = match self {
            MaterialType::SpecularColor => vec!["builtin/standard", "urp/lit", "hdrp/lit"],
            _ => vec!["hdrp/lit"],
        };
        Some(format!(
            "the `{}` material type sets `{param}`, a parameter `{}` does not have (the models with it: {})",
            self.name(),
            model.name,
            with.join(", ")
        ))
    }

    /// The parameters every type sets, which a `[sweep.params]` list must not sweep as well (the
    /// types' flags, not a type's own slider).
    pub fn param_names() -> Vec<&'static str> {
        let mut names: Vec<&str> = Self::ALL[0]
            .params()
            .iter()
            .map(|(n, _)| *n)
            .filter(|n| Self::ALL.iter().all(|t| t.params().iter().any(|(m, _)| m == n)))
            .collect();
        names.sort_unstable();
        names
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipelines::Pipeline;
    use crate::shading::Registry;

    #[test]
    fn types_are_pruned_where_the_model_lacks_their_parameter() {
        let r = Registry::builtin();
        let hdrp = r.find(Pipeline::Hdrp, "lit").unwrap();
        let urp = r.find(Pipeline::Urp, "lit").unwrap();
        let lambert = r.find(Pipeline::Urp, "lambert").unwrap();
        for t in MaterialType::ALL {
            assert_eq!(t.missing_in(hdrp), None, "{}", t.name());
            assert_eq!(MaterialType::from_name(t.name()), Some(t));
        }
        assert_eq!(MaterialType::SpecularColor.missing_in(urp), None);
        assert!(MaterialType::Iridescence.missing_in(urp).unwrap().contains("iridescence_mask"));
        assert_eq!(MaterialType::Standard.missing_in(lambert), None);
        assert!(MaterialType::SpecularColor.missing_in(lambert).is_some());
        assert_eq!(
            MaterialType::param_names(),
            vec!["iridescence_mask", "specular_setup", "subsurface_scattering", "transmission"]
        );
    }
}
