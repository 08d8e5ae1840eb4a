//! A cell's term layers (pipelines::terms, `[outputs] terms = true`): the frame drawn again once
//! per layer with the passes' `TERMS` mask, untimed, before post-processing. Only cells whose
//! run asks for them draw them.

use super::{CellParams, CellPlan, FrameMode, Renderer};
use crate::error::Error;
use crate::pipelines::surface::SurfaceType;
use crate::pipelines::terms::{self, TermLayer};
use crate::pipelines::RenderPath;
use crate::render::prepared::PreparedScene;

/// The term layers of one cell, each linear RGBA at the image's size.
#[derive(Debug, Clone)]
pub struct RenderedTerms {
    pub layers: Vec<(TermLayer, Vec<f32>)>,
    /// The frame before bloom, where the cell blooms: what the additive layers sum to. The image
    /// itself is after bloom, which is not linear (its prefilter weights each tap by
    /// 1/(1 + luminance)), so no split of the image adds up to it.
    pub before_bloom: Option<Vec<f32>>,
}

impl Renderer {
    /// The layers a cell's frame splits into, or why it has none: a frame whose composition is
    /// not a sum of its terms has no layers that add up to it.
    pub fn term_layers(&self, cell: &CellParams) -> Result<Vec<TermLayer>, String> {
        let fixed = self.fixed_model(cell.pipeline).map_err(|e| e.to_string())?;
        let vertex_lit = cell.settings.path == RenderPath::VertexLit;
        if cell.settings.exact.any() {
            return Err("the study's exact alternatives integrate the environment whole, not by lobe".into());
        }
        if vertex_lit && (cell.model.passes.vertex_lit_fallback || fixed.passes.vertex_lit_fallback) {
            return Err("the vertex-lit fallback (Legacy Shaders/VertexLit) saturates its diffuse and ambient sum \
                        per vertex: its parts do not add up to the frame"
                .into());
        }
        if cell.settings.surface.kind == SurfaceType::Multiply {
            return Err("Multiply blends the background by the surface's colour: the frame is a product, \
                        not a sum of terms"
                .into());
        }
        Ok(terms::layers(cell.model.splits_lobes() && fixed.splits_lobes()))
    }

    /// Draw a planned cell's term layers (after its image: the same plan, untimed, every pass
    /// drawn) and, where it blooms, its frame before bloom.
    pub fn draw_terms(
        &mut self,
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
    ) -> Result<Result<RenderedTerms, String>, Error> {
        let layers = match self.term_layers(cell) {
            Ok(layers) => layers,
            Err(why) => return Ok(Err(why)),
        };
        let mut out = RenderedTerms { layers: Vec::with_capacity(layers.len()), before_bloom: None };
        let drawn = (|| {
            for layer in layers {
                let mode = FrameMode { terms: layer.bits, post: false };
                let frame = self.draw_frames(prepared, cell, plan, 1, 0, false, mode)?;
                out.layers.push((layer, frame.hdr));
            }
            if plan.has(crate::plan::Pass::Bloom) {
                let mode = FrameMode { terms: terms::LIGHT, post: false };
                out.before_bloom = Some(self.draw_frames(prepared, cell, plan, 1, 0, false, mode)?.hdr);
            }
            Ok::<_, Error>(())
        })();
        // The next cell's image looks its pipelines up with every term.
        self.pipelines.terms = terms::LIGHT;
        drawn?;
        Ok(Ok(out))
    }
}
