//! The approximation study (declarations::study): the frames each cell is rendered again as, one per
//! real-time approximation replaced, and the ones left out because they cannot change the image
//! or do not exist on the cell's path. The metrics stage measures each against the cell's truth.

use crate::cells::Cell;
use crate::declarations::scene::{Scene, Sky};
use crate::declarations::study::Approximation;
use crate::pipelines::{Antialiasing, RenderPath};
use crate::plan::exact::ExactAlternatives;
use crate::render::renderer::CellSettings;

/// One frame of the study: the cell with one approximation replaced.
#[derive(Debug, Clone)]
pub struct StudyVariant {
    pub approximation: Approximation,
    /// File stem of its image and its row's name: the approximation, or `msaa<N>`.
    pub name: String,
    /// What changes, as the tables print it: "order-2 SH → exact irradiance".
    pub change: String,
    pub settings: CellSettings,
}

/// A variant that is not rendered, and why.
#[derive(Debug, Clone)]
pub struct LeftOutVariant {
    pub approximation: Approximation,
    pub name: String,
    pub change: String,
    pub reason: String,
}

/// The variants of `cell` for the study's `list`, given the settings it rendered with.
pub fn variants(
    cell: &Cell,
    scene: &Scene,
    base: &CellSettings,
    list: &[Approximation],
) -> (Vec<StudyVariant>, Vec<LeftOutVariant>) {
    let mut kept = Vec::new();
    let mut left_out = Vec::new();
    let model = cell.model();
    let per_pixel_forward = match (cell.path, model.per_vertex) {
        (RenderPath::Forward, false) => None,
        (RenderPath::Forward, true) => Some(format!("`{}` is evaluated at the vertices (Gouraud)", cell.shader)),
        (path, _) => Some(format!("the {} path: the exact alternatives are per-pixel forward shading", path.name())),
    };
    // The cell's ambient axis scales the scene's environment: at 0 there is none to make exact.
    let environment = scene.environment.ambient_intensity * base.ambient_intensity.unwrap_or(1.0) > 0.0;
    for &a in list {
        let exact = |e: ExactAlternatives| CellSettings { exact: e, ..*base };
        let (change, settings, cannot) = match a {
            Approximation::Ambient => (
                "order-2 SH ambient → exact irradiance",
                exact(ExactAlternatives { ambient: true, ..Default::default() }),
                if !environment {
                    Some("the cell has no environment light (ambient intensity 0)".to_string())
                } else if matches!(scene.environment.sky, Sky::Constant { .. }) {
                    Some("a constant sky's SH is exact: the exact irradiance cannot change the image".to_string())
                } else {
                    None
                },
            ),
            Approximation::Environment => (
                "SH ambient + split-sum probe → environment integrated over the BRDF",
                exact(ExactAlternatives { environment: true, ..Default::default() }),
                (!environment).then(|| "the cell has no environment light (ambient intensity 0)".to_string()),
            ),
            Approximation::Visibility => (
                "shadow maps → ray-traced visibility",
                exact(ExactAlternatives { visibility: true, ..Default::default() }),
                scene.lights.is_empty().then(|| "the scene has no lights".to_string()),
            ),
            Approximation::Msaa => {
                if cell.path == RenderPath::Deferred {
                    left_out.push(LeftOutVariant {
                        approximation: a,
                        name: "msaa".into(),
                        change: "MSAA level".into(),
                        reason: "deferred paths render one sample per pixel".into(),
                    });
                    continue;
                }
                for level in Antialiasing::ALL.into_iter().filter(|l| *l != base.antialiasing) {
                    kept.push(StudyVariant {
                        approximation: a,
                        name: level.name().into(),
                        change: format!("{} → {}", base.antialiasing.name(), level.name()),
                        settings: CellSettings { antialiasing: level, ..*base },
                    });
                }
                continue;
            }
        };
        match cannot.or_else(|| per_pixel_forward.clone()) {
            Some(reason) => {
                left_out.push(LeftOutVariant { approximation: a, name: a.name().into(), change: change.into(), reason })
            }
            None => {
                kept.push(StudyVariant { approximation: a, name: a.name().into(), change: change.into(), settings })
            }
        }
    }
    (kept, left_out)
}
