//! The fit of a target model's material values to a source's frames, in two stages.
//!
//! 1. **Close, fast**: for a fixed smoothness and metallic every model here shades the subject
//!    affinely in its base colour, channel by channel (diffuse ∝ albedo, F0 = lerp(0.04, albedo,
//!    metallic)), up to HDRP's energy compensation, which multiplies F0 into the specular once
//!    more. So two frames per scene, base colour black (A) and white (W), predict the frame of any
//!    colour c as A + (W − A)·c, and the colour nearest the source's pixels in relative MSE is a
//!    closed-form weighted least squares per channel. On the linear image the pipelines' units
//!    differ by orders of magnitude (HDRP's lights are × 10⁴, and its fixed dielectric F0 of 0.04
//!    alone outshines URP's whole frame there), which no material value can absorb: there the fit
//!    takes an exposure k as well, the frame being k·(A + (W − A)·c), still closed form (k and k·c
//!    are linear unknowns). On the displayed image the pipelines' own exposure stands (k = 1). Over a grid of smoothness (every 0.1 and the
//!    source's own) × metallic (0, 1 and the source's) this gives the best node, judged by the
//!    match's error on the predicted frames (displayed through the target's exposure and
//!    tonemapper where the match is on the displayed image).
//! 2. **Confirm and refine**: Nelder–Mead (argmin) on rendered frames from that node, over
//!    smoothness, metallic (clamped to [0, 1]) and a log-scale factor per colour channel. It needs
//!    no gradient, which a frame's FLIP does not give, tolerates the plateaus a clamped slider
//!    makes, and takes few evaluations in five dimensions; each evaluation renders every scene.
//!    The stage-1 node is kept unless a rendered frame beats it.
//!
//! A model's own parameters that the matrix sweeps (`[sweep.params]`) are fitted too: their swept
//! values (and the source's own) join the stage-1 grid, and a continuous one (not a 0/1 switch)
//! is refined within its range as well. The grid's basis frames depend on the node alone, not on
//! the source, so a `BasisCache` renders them once for every material a match fits.

use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap};
use std::rc::Rc;

use super::{error, frames, Frame, MatchError, MatchSpace, MaterialValues, Side, Stage};
use crate::error::Error;
use crate::pipelines::DisplayTransform;
use crate::render::Renderer;
use crate::shading::ShaderModel;

/// A model parameter a fit sets: the values the matrix sweeps for it and, where it is continuous,
/// the range the refinement moves it in.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamAxis {
    pub name: String,
    pub values: Vec<f64>,
    /// `(min, max)` of a continuous parameter; None for a switch (only its swept values).
    pub range: Option<(f64, f64)>,
}

impl ParamAxis {
    /// The parameters of `model` that `swept` (a matrix's `[sweep.params]`) names. A parameter on
    /// [0, 1] swept only at 0 and 1 is a switch (`normalize`, `specular_setup`): values between
    /// mean nothing to its shader.
    pub fn swept(model: &ShaderModel, swept: &BTreeMap<String, Vec<f64>>) -> Vec<ParamAxis> {
        model
            .params
            .iter()
            .filter_map(|spec| {
                let values = swept.get(spec.name.as_ref())?.clone();
                let switch = spec.min == 0.0 && spec.max == 1.0 && values.iter().all(|v| *v == 0.0 || *v == 1.0);
                Some(ParamAxis {
                    name: spec.name.to_string(),
                    values,
                    range: (!switch && spec.max > spec.min).then_some((spec.min, spec.max)),
                })
            })
            .collect()
    }
}

/// How hard a fit tries, and over what.
#[derive(Debug, Clone)]
pub struct FitOptions {
    /// Smoothness steps of the stage-1 grid (0, 1/steps, …, 1, and the source's own value).
    pub smoothness_steps: u32,
    /// Rendered evaluations Nelder–Mead may take (0: stage 1 alone).
    pub refine_iterations: u64,
    /// On the linear image, the pipeline pair's exposure (`calibrate_exposure`) where it is
    /// known; None fits one for the material with its values. Ignored on the displayed image.
    pub exposure: Option<f64>,
    /// The target model's parameters to fit (`ParamAxis::swept`); the others keep the source's
    /// value where the target has the parameter, else the target's default.
    pub params: Vec<ParamAxis>,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions { smoothness_steps: 10, refine_iterations: 40, exposure: None, params: Vec::new() }
    }
}

/// The stage-1 grid's black and white frames by node, for one stage and target: they do not
/// depend on the source material, so a match renders them once for all its materials. Bounded
/// (`BASIS_BUDGET`); a node beyond it is rendered again when needed.
#[derive(Default)]
pub struct BasisCache {
    /// Which stage and target the frames are of; another clears the cache.
    owner: String,
    nodes: HashMap<Vec<u64>, Rc<Basis>>,
    bytes: usize,
}

/// A grid node's frames with base colour black and white, one per scene.
struct Basis {
    black: Vec<Frame>,
    white: Vec<Frame>,
}

/// Bytes of basis frames a `BasisCache` keeps: 64² frames on four scenes take 0.7 MB a node.
const BASIS_BUDGET: usize = 512 << 20;

impl BasisCache {
    fn bind(&mut self, stage: &Stage, target: &Side) {
        let scenes: Vec<&str> = stage.scenes.iter().map(|(s, _)| s.name.as_str()).collect();
        let owner = format!(
            "{}/{} {:?} {:?} {}×{} {scenes:?} {} {}",
            target.pipeline.name(),
            target.model.name,
            target.tonemap,
            target.settings,
            stage.size,
            stage.size,
            stage.light_intensity,
            stage.light_range
        );
        if owner != self.owner {
            *self = BasisCache { owner, ..Default::default() };
        }
    }

    /// The black and white frames of `node` (its colour ignored), and whether they were rendered.
    fn basis(
        &mut self,
        renderer: &mut Renderer,
        stage: &Stage,
        target: &Side,
        node: &MaterialValues,
    ) -> Result<(Rc<Basis>, bool), Error> {
        let key: Vec<u64> = [node.smoothness, node.metallic]
            .into_iter()
            .chain(node.params.values().copied())
            .map(f64::to_bits)
            .chain(node.params.keys().flat_map(|k| k.bytes().map(u64::from)))
            .collect();
        if let Some(b) = self.nodes.get(&key) {
            return Ok((b.clone(), false));
        }
        let at = |color| MaterialValues { color, ..node.clone() };
        let pair = Rc::new(Basis {
            black: frames(renderer, stage, target, &at([0.0; 3]))?,
            white: frames(renderer, stage, target, &at([1.0; 3]))?,
        });
        let bytes: usize =
            pair.black.iter().chain(&pair.white).map(|f| f.hdr.len() * 4 + f.srgb8.len() + f.subject.len() * 8).sum();
        if self.bytes + bytes <= BASIS_BUDGET {
            self.bytes += bytes;
            self.nodes.insert(key, pair.clone());
        }
        Ok((pair, true))
    }
}

/// The factor between two pipelines' linear frames of one material whose values carry over as
/// they are (a Lambert-like reference): k = Σ w·T·S / Σ w·T² over the subject pixels, w =
/// 1/(S² + 0.01), T the target's frames with the source's values. Fixing it before the materials
/// are fitted keeps the units out of their colours: fitted with each material, an exposure and a
/// colour trade against each other wherever the diffuse term dominates.
pub fn calibrate_exposure(
    renderer: &mut Renderer,
    stage: &Stage,
    reference: &MaterialValues,
    source_frames: &[Frame],
    target: &Side,
) -> Result<f64, Error> {
    let copied = frames(renderer, stage, target, reference)?;
    scale_between(source_frames, &copied)
        .ok_or_else(|| Error::Other("the reference shows no light on its subject: no exposure to calibrate".into()))
}

/// The factor k nearest to taking `target`'s subject pixels to `source`'s in relative MSE.
fn scale_between(source: &[Frame], target: &[Frame]) -> Option<f64> {
    let (mut num, mut den) = (0.0, 0.0);
    for (s, t) in source.iter().zip(target) {
        for &i in &s.subject {
            for c in 0..3 {
                let (sv, tv) = (s.hdr[4 * i + c] as f64, t.hdr[4 * i + c] as f64);
                let w = 1.0 / (sv * sv + 0.01);
                num += w * tv * sv;
                den += w * tv * tv;
            }
        }
    }
    (num > 0.0 && den > 0.0).then(|| num / den)
}

/// Stage-1 nodes rendered before the refinement picks its start: the prediction is exact only
/// where a model is affine in its colour (HDRP's energy compensation is not; a probe that sees the
/// subject is not).
const RENDERED_NODES: usize = 3;

/// A fitted material and what it leaves.
#[derive(Debug, Clone)]
pub struct Fit {
    pub values: MaterialValues,
    /// The factor on the target's linear frames (1 on the displayed image): the units and
    /// exposure between the two pipelines as this material sees them.
    pub exposure: f64,
    /// The target with the source's values copied (Unity's material upgraders).
    pub before: MatchError,
    /// The target with the fitted values, rendered.
    pub after: MatchError,
    /// Frames rendered per scene: the grid's basis pairs (those not already in the cache), then
    /// the refinement's.
    pub renders: u32,
    /// The frames the two errors are of, one per scene.
    pub frames: FitFrames,
}

/// The target's frames with the values copied and with the fitted ones (exposed as compared).
#[derive(Clone)]
pub struct FitFrames {
    pub copied: Vec<Frame>,
    pub fitted: Vec<Frame>,
}

impl std::fmt::Debug for FitFrames {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "FitFrames({} scenes)", self.copied.len())
    }
}

/// The linear frame predicted for base colour `c` from the black and white frames.
fn predicted(black: &Frame, white: &Frame, c: [f64; 3]) -> Vec<f32> {
    black
        .hdr
        .iter()
        .zip(&white.hdr)
        .enumerate()
        .map(|(i, (a, w))| if i % 4 == 3 { *a } else { (*a as f64 + (*w - *a) as f64 * c[i % 4]) as f32 })
        .collect()
}

/// The weighted sums of the least squares over the subject pixels, w = 1/(S² + 0.01), B = W − A:
/// per channel Σ w·A², Σ w·A·B, Σ w·B², Σ w·A·S, Σ w·B·S.
fn moments(source: &[Frame], black: &[Frame], white: &[Frame]) -> [[f64; 5]; 3] {
    let mut m = [[0.0; 5]; 3];
    for ((s, a), w) in source.iter().zip(black).zip(white) {
        for &i in &s.subject {
            for (c, m) in m.iter_mut().enumerate() {
                let k = 4 * i + c;
                let (sv, av, bv) = (s.hdr[k] as f64, a.hdr[k] as f64, (w.hdr[k] - a.hdr[k]) as f64);
                let weight = 1.0 / (sv * sv + 0.01);
                for (acc, v) in m.iter_mut().zip([av * av, av * bv, bv * bv, av * sv, bv * sv]) {
                    *acc += weight * v;
                }
            }
        }
    }
    m
}

/// The base colour (in [0, 1]) and exposure whose predicted frames k·(A + B·c) are nearest
/// `source` in relative MSE; the exposure is `fixed` where given.
fn least_squares(source: &[Frame], black: &[Frame], white: &[Frame], fixed: Option<f64>) -> ([f64; 3], f64) {
    let m = moments(source, black, white);
    // With k fixed, each channel's c = (Σ w·B·S/k − Σ w·A·B)/Σ w·B².
    let color_at =
        |k: f64| m.map(|[_, ab, bb, _, bs]| if bb > 0.0 { ((bs / k - ab) / bb).clamp(0.0, 1.0) } else { 0.0 });
    if let Some(k) = fixed {
        return (color_at(k), k);
    }
    // Unknowns k and d = k·c: k·(Σ w·A² − Σ_c (Σ w·A·B)²/Σ w·B²) = Σ w·A·S − Σ_c Σ w·A·B·Σ w·B·S/Σ w·B².
    let (mut lhs, mut rhs) = (0.0, 0.0);
    for [aa, ab, bb, a_s, bs] in m {
        lhs += aa - if bb > 0.0 { ab * ab / bb } else { 0.0 };
        rhs += a_s - if bb > 0.0 { ab * bs / bb } else { 0.0 };
    }
    let k = if lhs > 0.0 && rhs > 0.0 { rhs / lhs } else { 1.0 };
    let color = color_at(k);
    // The colour clamped, k again for it: Σ w·P·S / Σ w·P² with P = A + B·c.
    let (num, den) = m
        .iter()
        .zip(color)
        .fold((0.0, 0.0), |(n, d), ([aa, ab, bb, a_s, bs], c)| (n + a_s + c * bs, d + aa + 2.0 * c * ab + c * c * bb));
    (color, if num > 0.0 && den > 0.0 { num / den } else { k })
}

/// `frames` with their linear pixels × `k`, shown again through `displays`.
fn exposed(frames: &[Frame], k: f64, size: u32, displays: &[DisplayTransform]) -> Vec<Frame> {
    frames.iter().zip(displays).map(|(f, d)| f.with_pixels(scaled(&f.hdr, k), size, d)).collect()
}

/// Linear RGBA × `k`, alpha kept.
fn scaled(hdr: &[f32], k: f64) -> Vec<f32> {
    hdr.iter().enumerate().map(|(i, v)| if i % 4 == 3 { *v } else { (*v as f64 * k) as f32 }).collect()
}

/// The stage-1 grid: smoothness × metallic × each fitted parameter's values, the source's own
/// among them, on `base` (the values copied: the parameters the grid does not set).
fn grid(source: &MaterialValues, base: &MaterialValues, steps: u32, params: &[ParamAxis]) -> Vec<MaterialValues> {
    let sorted = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        v
    };
    let mut smooth: Vec<f64> = (0..=steps).map(|k| k as f64 / steps.max(1) as f64).collect();
    smooth.push(source.smoothness.clamp(0.0, 1.0));
    let metal = sorted(vec![0.0, 1.0, source.metallic.clamp(0.0, 1.0)]);
    let mut nodes: Vec<MaterialValues> = sorted(smooth)
        .into_iter()
        .flat_map(|smoothness| {
            metal.iter().map(move |&metallic| MaterialValues { smoothness, metallic, ..base.clone() })
        })
        .collect();
    for axis in params {
        let mut values = axis.values.clone();
        if let (Some(v), Some((lo, hi))) = (source.params.get(&axis.name), axis.range) {
            values.push(v.clamp(lo, hi));
        }
        nodes = nodes
            .iter()
            .flat_map(|n| {
                sorted(values.clone()).into_iter().map(move |v| {
                    let mut n = n.clone();
                    n.params.insert(axis.name.clone(), v);
                    n
                })
            })
            .collect();
    }
    nodes.sort_by(|a, b| a.metallic.total_cmp(&b.metallic));
    nodes
}

/// The target's values that reproduce `source_frames` (rendered from `source` on `stage`); the
/// grid's basis frames come from `cache` where it has them.
#[allow(clippy::too_many_arguments)]
pub fn fit(
    renderer: &mut Renderer,
    stage: &Stage,
    source: &MaterialValues,
    source_frames: &[Frame],
    target: &Side,
    space: MatchSpace,
    options: &FitOptions,
    cache: &mut BasisCache,
) -> Result<Fit, Error> {
    cache.bind(stage, target);
    let mut carried = source.carried_to(target.model);
    // Every fitted parameter named, where the source does not set it at the value the model
    // takes from the sliders (Oren–Nayar's σ = 1 − smoothness) or its default: the same frames,
    // and the refinement moves it from there.
    let taken = carried.surface(target.model, target.pipeline).params;
    for spec in target.model.params.iter().filter(|p| options.params.iter().any(|a| a.name == p.name)) {
        carried.params.entry(spec.name.to_string()).or_insert(taken[spec.slot]);
    }
    let copied = frames(renderer, stage, target, &carried)?;
    let before = error(source_frames, &copied, stage.size, space)?;
    let displays: Vec<DisplayTransform> = stage
        .scenes
        .iter()
        .map(|(scene, _)| DisplayTransform::new(target.pipeline, target.tonemap, &scene.hdrp))
        .collect();
    let fixed_exposure = match space {
        MatchSpace::Display => Some(1.0),
        MatchSpace::Linear => options.exposure,
    };
    let free_exposure = fixed_exposure.is_none();
    let mut renders = 1;
    let mut nodes: Vec<(MaterialValues, f64, f64)> = Vec::new();
    for node in grid(source, &carried, options.smoothness_steps, &options.params) {
        let (basis, rendered) = cache.basis(renderer, stage, target, &node)?;
        let (black, white) = (&basis.black, &basis.white);
        renders += 2 * rendered as u32;
        let (color, k) = least_squares(source_frames, black, white, fixed_exposure);
        let guess: Vec<Frame> = black
            .iter()
            .zip(white)
            .zip(&displays)
            .map(|((a, w), d)| a.with_pixels(scaled(&predicted(a, w, color), k), stage.size, d))
            .collect();
        nodes.push((MaterialValues { color, ..node }, k, error(source_frames, &guess, stage.size, space)?.flip));
    }
    nodes.sort_by(|a, b| a.2.total_cmp(&b.2));
    // The start: the best rendered of the copied values (so a fit never ends worse than copying)
    // and the best predicted nodes.
    let copied_k = fixed_exposure.or_else(|| scale_between(source_frames, &copied)).unwrap_or(1.0);
    let copied_exposed = exposed(&copied, copied_k, stage.size, &displays);
    let copied_error = error(source_frames, &copied_exposed, stage.size, space)?;
    let mut start = Best { values: carried, exposure: copied_k, error: copied_error, frames: copied_exposed };
    for (values, k, _) in nodes.into_iter().take(RENDERED_NODES) {
        let rendered = exposed(&frames(renderer, stage, target, &values)?, k, stage.size, &displays);
        renders += 1;
        let e = error(source_frames, &rendered, stage.size, space)?;
        if e.flip < start.error.flip {
            start = Best { values, exposure: k, error: e, frames: rendered };
        }
    }
    let refined_params: Vec<(String, (f64, f64))> =
        options.params.iter().filter_map(|a| a.range.map(|r| (a.name.clone(), r))).collect();
    let mut fitted = start;
    if options.refine_iterations > 0 && fitted.error.flip > 0.0 {
        let dimensions = 5 + refined_params.len() + free_exposure as usize;
        let (start_values, start_k) = (fitted.values.clone(), fitted.exposure);
        let (best, refined) = (RefCell::new(fitted), RefCell::new(0));
        let problem = Refine {
            renderer: RefCell::new(renderer),
            stage,
            target,
            source_frames,
            space,
            start: start_values,
            start_exposure: start_k,
            free_exposure,
            params: &refined_params,
            displays: &displays,
            best: &best,
            renders: &refined,
        };
        let solver = NelderMead::new(simplex_around(dimensions, &refined_params))
            .with_sd_tolerance(1e-4)
            .map_err(|e| Error::Other(format!("setting up the refinement: {e}")))?;
        Executor::new(problem, solver)
            .configure(|state| state.max_iters(options.refine_iterations))
            .run()
            .map_err(|e| Error::Other(format!("refining a match: {e}")))?;
        fitted = best.into_inner();
        renders += refined.into_inner();
    }
    Ok(Fit {
        values: fitted.values,
        exposure: fitted.exposure,
        before,
        after: fitted.error,
        renders,
        frames: FitFrames { copied, fitted: fitted.frames },
    })
}

/// The best values rendered so far, with their exposure, error and frames.
struct Best {
    values: MaterialValues,
    exposure: f64,
    error: MatchError,
    frames: Vec<Frame>,
}

/// The refinement's start: the stage-1 node (all zeros) and a step along each of its `n`
/// parameters: smoothness and metallic by 0.05, each colour channel by a factor e^0.2, each
/// refined model parameter by 5 % of its range, and the exposure (where free) by e^0.2.
fn simplex_around(n: usize, params: &[(String, (f64, f64))]) -> Vec<Vec<f64>> {
    let steps: Vec<f64> = [0.05, 0.05, 0.2, 0.2, 0.2]
        .into_iter()
        .chain(params.iter().map(|(_, (lo, hi))| 0.05 * (hi - lo)))
        .chain([0.2])
        .collect();
    let mut simplex = vec![vec![0.0; n]];
    for (k, step) in steps.iter().take(n).enumerate() {
        let mut v = vec![0.0; n];
        v[k] = *step;
        simplex.push(v);
    }
    simplex
}

/// The refinement's cost: the error of the rendered frames of the values a parameter vector
/// names: offsets from the stage-1 node (smoothness, metallic), log factors of its colour,
/// offsets of the refined model parameters and (on the linear image, where free) the log factor
/// of its exposure.
struct Refine<'a, 'r> {
    renderer: RefCell<&'r mut Renderer>,
    stage: &'a Stage,
    target: &'a Side<'a>,
    source_frames: &'a [Frame],
    space: MatchSpace,
    start: MaterialValues,
    start_exposure: f64,
    free_exposure: bool,
    /// The continuous model parameters refined, with their ranges.
    params: &'a [(String, (f64, f64))],
    displays: &'a [DisplayTransform],
    /// The best values rendered so far: Nelder–Mead's own best is a parameter vector, and
    /// every evaluation's frames are already judged here.
    best: &'a RefCell<Best>,
    renders: &'a RefCell<u32>,
}

impl Refine<'_, '_> {
    fn values(&self, p: &[f64]) -> MaterialValues {
        let s = &self.start;
        let mut params = s.params.clone();
        for (k, (name, (lo, hi))) in self.params.iter().enumerate() {
            let v = s.params.get(name).copied().unwrap_or(*lo); // `fit` names every one
            params.insert(name.clone(), (v + p[5 + k]).clamp(*lo, *hi));
        }
        MaterialValues {
            smoothness: (s.smoothness + p[0]).clamp(0.0, 1.0),
            metallic: (s.metallic + p[1]).clamp(0.0, 1.0),
            color: [0, 1, 2].map(|c| (s.color[c] * p[2 + c].exp()).clamp(0.0, 1.0)),
            params,
        }
    }
}

impl CostFunction for Refine<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, p: &Self::Param) -> Result<f64, argmin::core::Error> {
        let values = self.values(p);
        let k = match self.free_exposure {
            true => self.start_exposure * p[5 + self.params.len()].exp(),
            false => self.start_exposure,
        };
        let mut renderer = self.renderer.borrow_mut();
        let rendered = frames(&mut renderer, self.stage, self.target, &values)?;
        *self.renders.borrow_mut() += 1;
        let rendered = exposed(&rendered, k, self.stage.size, self.displays);
        let e = error(self.source_frames, &rendered, self.stage.size, self.space)?;
        let mut best = self.best.borrow_mut();
        if e.flip < best.error.flip {
            *best = Best { values, exposure: k, error: e, frames: rendered };
        }
        Ok(e.flip)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_holds_the_source_values_once() {
        let source = MaterialValues::new(0.75, 0.0, [0.2; 3]);
        let g = grid(&source, &source, 10, &[]);
        assert_eq!(g.len(), 12 * 2);
        let has = |s: f64, m: f64| g.iter().any(|n| n.smoothness == s && n.metallic == m);
        assert!(has(0.75, 0.0) && has(1.0, 1.0));
    }

    #[test]
    fn the_grid_spans_a_swept_parameter_and_the_sources_own_value() {
        let mut source = MaterialValues::new(0.5, 0.0, [0.2; 3]);
        source.params.insert("sigma".into(), 0.3);
        let sigma = ParamAxis { name: "sigma".into(), values: vec![0.0, 0.5], range: Some((0.0, 1.5)) };
        let g = grid(&source, &source, 2, &[sigma]);
        assert_eq!(g.len(), 3 * 2 * 3, "smoothness 0, 0.5, 1 × metallic 0, 1 × sigma 0, 0.3, 0.5");
        assert!(g.iter().any(|n| n.smoothness == 0.5 && n.params["sigma"] == 0.3));
    }

    #[test]
    fn least_squares_recovers_an_affine_colour() {
        // Two pixels: the exposure and three colours are four unknowns, one pixel gives three.
        let frame = |hdr: Vec<f32>| Frame { hdr, srgb8: vec![], subject: vec![0, 1] };
        let a = frame(vec![0.1, 0.2, 0.0, 1.0, 0.3, 0.05, 0.2, 1.0]);
        let w = frame(vec![0.5, 1.2, 0.4, 1.0, 0.9, 0.6, 0.7, 1.0]);
        let c = [0.3, 0.6, 0.9];
        let s = frame(predicted(&a, &w, c));
        let (got, k) =
            least_squares(std::slice::from_ref(&s), std::slice::from_ref(&a), std::slice::from_ref(&w), Some(1.0));
        assert_eq!(k, 1.0);
        for i in 0..3 {
            assert!((got[i] - c[i]).abs() < 1e-6, "{got:?}");
        }
        // The same frame a thousand times dimmer: the exposure takes the factor, the colour stays.
        let dim = frame(s.hdr.iter().map(|v| v * 1e-3).collect());
        let (got, k) = least_squares(&[dim], &[a], &[w], None);
        assert!((k * 1e3 - 1.0).abs() < 1e-6, "{k}");
        for i in 0..3 {
            assert!((got[i] - c[i]).abs() < 1e-6, "{got:?}");
        }
    }
}
