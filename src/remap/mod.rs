//! Carrying a material's look from one pipeline/shader to another: the values a target model needs
//! to reproduce the source's frames (`fit`), over every scene at once so that the result is a
//! material remap and not a per-scene fit, with the error before (the values copied, as Unity's
//! material upgraders copy them) and after, and what no value removes.
//!
//! The error is read on the subject's pixels alone: the rest of a scene does not take the swept
//! material, so counting it would only dilute the difference.

pub mod fit;
pub mod page;
pub mod plot;
pub mod sheet;
pub mod table;

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::declarations::scene::Scene;
use crate::error::Error;
use crate::images::tonemap::to_srgb8;
use crate::pipelines::{DisplayTransform, Pipeline, Tonemap};
use crate::plan::cell::{CellParams, CellSettings};
use crate::render::uniforms::ROLE_SUBJECT;
use crate::render::{PreparedScene, Renderer};
use crate::shading::registry::{apply_workflow_with, ShaderModel, Sliders};
use crate::shading::twin::Surface;

/// The material values a match fits: the sliders every model reads, and a model's own parameters
/// where the matrix sweeps them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct MaterialValues {
    pub smoothness: f64,
    pub metallic: f64,
    /// Linear base colour.
    pub color: [f64; 3],
    /// Model parameters by name (`[sweep.params]`); a model takes those it has and keeps its
    /// defaults for the rest.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub params: BTreeMap<String, f64>,
}

impl MaterialValues {
    /// The sliders alone, the model's parameters at their defaults.
    pub fn new(smoothness: f64, metallic: f64, color: [f64; 3]) -> MaterialValues {
        MaterialValues { smoothness, metallic, color, params: BTreeMap::new() }
    }

    pub fn sliders(&self) -> Sliders {
        Sliders { base_color_linear: self.color, metallic: self.metallic, smoothness: self.smoothness }
    }

    /// The subject's surface in `model`: the sliders as the pipeline maps them, the parameters
    /// `model` has set by name, then its specular workflow where one of them turns it on (as a
    /// cell's surface is built, `cells::Cell::surface`).
    pub fn surface(&self, model: &ShaderModel, pipeline: Pipeline) -> Surface {
        let mut s = model.surface(pipeline, &self.sliders());
        for spec in &model.params {
            if let Some(v) = self.params.get(spec.name.as_ref()) {
                s.params[spec.slot] = *v;
            }
        }
        apply_workflow_with(model, &mut s, glam::DVec3::splat(0.04));
        s
    }

    /// These values with only the parameters `model` has: what copying them into it keeps.
    pub fn carried_to(&self, model: &ShaderModel) -> MaterialValues {
        let mut v = self.clone();
        v.params.retain(|name, _| model.params.iter().any(|p| p.name == *name));
        v
    }
}

/// Which image a match compares: the linear radiance the pipeline renders (its EXR), or the frame
/// as shown after its exposure and tonemapping (its PNG).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum MatchSpace {
    Linear,
    /// The default: a look is what a person sees, and the pipelines differ in their display
    /// transforms (HDRP's exposure and ACES) as much as in their shading.
    #[default]
    Display,
}

impl MatchSpace {
    pub fn name(self) -> &'static str {
        match self {
            MatchSpace::Linear => "linear",
            MatchSpace::Display => "display",
        }
    }
}

/// A pipeline and one of its models: one side of a match.
#[derive(Clone, Copy)]
pub struct Side<'a> {
    pub pipeline: Pipeline,
    pub model: &'a ShaderModel,
    /// The tonemapper its frames are shown with.
    pub tonemap: Tonemap,
    /// Its engine settings and path.
    pub settings: CellSettings,
}

/// The scenes a match renders, each prepared once, with the key light every frame uses.
pub struct Stage {
    pub scenes: Vec<(Scene, PreparedScene)>,
    pub light_intensity: f64,
    pub light_range: f64,
    /// Square frames of this side.
    pub size: u32,
}

/// One scene's frame of a material: linear RGBA, its displayed RGBA8, and its subject's pixels.
#[derive(Debug, Clone)]
pub struct Frame {
    pub hdr: Vec<f32>,
    pub srgb8: Vec<u8>,
    pub subject: Vec<usize>,
}

/// A material's frames, one per scene of the stage.
pub fn frames(
    renderer: &mut Renderer,
    stage: &Stage,
    side: &Side,
    values: &MaterialValues,
) -> Result<Vec<Frame>, Error> {
    stage
        .scenes
        .iter()
        .map(|(scene, prepared)| {
            let cell = CellParams {
                pipeline: side.pipeline,
                model: side.model,
                surface: values.surface(side.model, side.pipeline),
                light_intensity: stage.light_intensity,
                light_range: stage.light_range,
                width: stage.size,
                height: stage.size,
                view: Default::default(),
                settings: side.settings,
            };
            let r = renderer.render(prepared, &cell, 1, 0)?;
            Ok(frame_of(r.hdr, &r.roles, stage.size, &DisplayTransform::new(side.pipeline, side.tonemap, &scene.hdrp)))
        })
        .collect()
}

/// A frame from its linear pixels, shown through `display`.
pub fn frame_of(hdr: Vec<f32>, roles: &[u8], size: u32, display: &DisplayTransform) -> Frame {
    let (srgb8, _) = to_srgb8(&hdr, size, size, display);
    let subject = roles.iter().enumerate().filter(|(_, r)| **r == ROLE_SUBJECT).map(|(i, _)| i).collect();
    Frame { hdr, srgb8, subject }
}

impl Frame {
    /// Other linear pixels of the same scene (a prediction, an exposure), shown through `display`.
    pub fn with_pixels(&self, hdr: Vec<f32>, size: u32, display: &DisplayTransform) -> Frame {
        let (srgb8, _) = to_srgb8(&hdr, size, size, display);
        Frame { hdr, srgb8, subject: self.subject.clone() }
    }
}

/// How far a target's frames are from the source's, over the subject's pixels of every scene.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MatchError {
    /// Mean FLIP over the subject pixels (LDR-FLIP of the displayed frames in display space,
    /// HDR-FLIP of the linear ones in linear space).
    pub flip: f64,
    /// Relative MSE of the linear subject pixels, Σ(t − s)²/(s² + 0.01) per channel, averaged.
    pub rel_mse: f64,
}

/// The error of `target` against `source`, frame by frame (the same scenes, the same size).
pub fn error(source: &[Frame], target: &[Frame], size: u32, space: MatchSpace) -> Result<MatchError, Error> {
    let (mut flip_sum, mut rel_sum, mut pixels) = (0.0, 0.0, 0usize);
    for (s, t) in source.iter().zip(target) {
        let n = size as usize;
        let map = match space {
            MatchSpace::Display => crate::compare::flip::ldr(&s.srgb8, &t.srgb8, n, n),
            MatchSpace::Linear => crate::compare::flip::hdr(&s.hdr, &t.hdr, n, n),
        }
        .map_err(|e| Error::Other(format!("FLIP of a match frame: {e}")))?;
        let values = map.map.pixels();
        for &i in &s.subject {
            flip_sum += values[i] as f64;
            for c in 0..3 {
                let (a, b) = (s.hdr[4 * i + c] as f64, t.hdr[4 * i + c] as f64);
                rel_sum += (b - a).powi(2) / (a * a + 0.01) / 3.0;
            }
        }
        pixels += s.subject.len();
    }
    if pixels == 0 {
        return Err(Error::Other("no scene shows the subject: nothing to match".into()));
    }
    Ok(MatchError { flip: flip_sum / pixels as f64, rel_mse: rel_sum / pixels as f64 })
}
