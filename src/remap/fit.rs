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
//!    Values the match keeps (`--keep`) are left out of the grid and the refinement.
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
    /// The source's values the fit keeps as they are.
    pub keep: Kept,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            smoothness_steps: 10,
            refine_iterations: 40,
            exposure: None,
            params: Vec::new(),
            keep: Kept::default(),
        }
    }
}

/// Which of the source's values a fit keeps (`match --keep`): a remap that may turn a dielectric
/// into a rough metal when that looks closest is not always one a project can take.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Kept {
    pub smoothness: bool,
    pub metallic: bool,
    pub color: bool,
}

impl Kept {
    pub const NAMES: [&'static str; 3] = ["smoothness", "metallic", "color"];

    /// The values named, each one of `NAMES`; the error is the first name that is not.
    pub fn parse<'a>(names: impl IntoIterator<Item = &'a str>) -> Result<Kept, &'a str> {
        let mut k = Kept::default();
        for n in names {
            match n {
                "smoothness" => k.smoothness = true,
                "metallic" => k.metallic = true,
                "color" => k.color = true,
                other => return Err(other),
            }
        }
        Ok(k)
    }

    pub fn names(&self) -> Vec<&'static str> {
        Kept::NAMES
            .into_iter()
            .zip([self.smoothness, self.metallic, self.color])
            .filter(|(_, k)| *k)
            .map(|(n, _)| n)
            .collect()
    }
}

/// The stage-1 grid's black and white frames by node, for one stage and target: they do not
/// depend on the source material, so a match renders them once for all its materials. Bounded
/// (`BASIS_BUDGET`); a node beyond it is rendered again when needed.
#[derive(Default)]
pub struct BasisCache {
    /// Which stage and target the frames are of; another clears the cache.
    owner: String,
    nodes: HashMap<NodeKey, Rc<Basis>>,
    bytes: usize,
}

/// A grid node as the cache finds it: smoothness, metallic and the parameters, bit for bit.
type NodeKey = (u64, u64, Vec<(String, u64)>);

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
        let key: NodeKey = (
            node.smoothness.to_bits(),
            node.metallic.to_bits(),
            node.params.iter().map(|(k, v)| (k.clone(), v.to_bits())).collect(),
        );
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

/// The target's frames as the fit's two errors compare them: with the values copied (as they
/// render, Unity's upgraders) and with the fitted ones (exposed where the exposure is fitted or
/// calibrated).
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
/// `source` in relative MSE; the exposure is `fixed` where given, the colour `kept` where given.
fn least_squares(
    source: &[Frame],
    black: &[Frame],
    white: &[Frame],
    fixed: Option<f64>,
    kept: Option<[f64; 3]>,
) -> ([f64; 3], f64) {
    let m = moments(source, black, white);
    // The exposure for a colour: Σ w·P·S / Σ w·P² with P = A + B·c.
    let exposure_for = |color: [f64; 3], otherwise: f64| {
        let (num, den) = m.iter().zip(color).fold((0.0, 0.0), |(n, d), ([aa, ab, bb, a_s, bs], c)| {
            (n + a_s + c * bs, d + aa + 2.0 * c * ab + c * c * bb)
        });
        if num > 0.0 && den > 0.0 {
            num / den
        } else {
            otherwise
        }
    };
    if let Some(color) = kept {
        return (color, fixed.unwrap_or_else(|| exposure_for(color, 1.0)));
    }
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
    // The colour clamped, k again for it.
    (color, exposure_for(color, k))
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
fn grid(
    source: &MaterialValues,
    base: &MaterialValues,
    steps: u32,
    params: &[ParamAxis],
    keep: Kept,
) -> Vec<MaterialValues> {
    let sorted = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        v
    };
    let mut smooth: Vec<f64> = match keep.smoothness {
        true => Vec::new(),
        false => (0..=steps).map(|k| k as f64 / steps.max(1) as f64).collect(),
    };
    smooth.push(source.smoothness.clamp(0.0, 1.0));
    let metal = match keep.metallic {
        true => vec![source.metallic.clamp(0.0, 1.0)],
        false => sorted(vec![0.0, 1.0, source.metallic.clamp(0.0, 1.0)]),
    };
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
    // Metallic-major, as the grid has always been ordered: nodes whose predicted errors tie keep
    // this order when they are ranked.
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
    let kept_color = options.keep.color.then_some(carried.color);
    for node in grid(source, &carried, options.smoothness_steps, &options.params, options.keep) {
        let (basis, rendered) = cache.basis(renderer, stage, target, &node)?;
        let (black, white) = (&basis.black, &basis.white);
        renders += 2 * rendered as u32;
        let (color, k) = least_squares(source_frames, black, white, fixed_exposure, kept_color);
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
    // The refinement's coordinates, in this order: what the fit may move.
    let mut coords = Vec::new();
    coords.extend((!options.keep.smoothness).then_some(Coord::Smoothness));
    coords.extend((!options.keep.metallic).then_some(Coord::Metallic));
    if !options.keep.color {
        coords.extend([Coord::Color(0), Coord::Color(1), Coord::Color(2)]);
    }
    coords.extend(options.params.iter().filter_map(|a| a.range.map(|r| Coord::Param(a.name.clone(), r))));
    coords.extend(free_exposure.then_some(Coord::Exposure));
    let mut fitted = start;
    if options.refine_iterations > 0 && fitted.error.flip > 0.0 && !coords.is_empty() {
        let (start_values, start_k) = (fitted.values.clone(), fitted.exposure);
        let simplex = simplex_around(&coords);
        let (best, refined) = (RefCell::new(fitted), RefCell::new(0));
        let problem = Refine {
            renderer: RefCell::new(renderer),
            stage,
            target,
            source_frames,
            space,
            start: start_values,
            start_exposure: start_k,
            coords,
            displays: &displays,
            best: &best,
            renders: &refined,
        };
        let solver = NelderMead::new(simplex)
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

/// One coordinate of the refinement's parameter vector.
#[derive(Debug, Clone, PartialEq)]
enum Coord {
    /// An offset of the smoothness.
    Smoothness,
    /// An offset of the metallic.
    Metallic,
    /// The log factor of a colour channel.
    Color(usize),
    /// An offset of a continuous model parameter, within its range.
    Param(String, (f64, f64)),
    /// The log factor of the exposure (on the linear image, where not calibrated).
    Exposure,
}

impl Coord {
    /// Its step in the starting simplex: smoothness and metallic 0.05, a colour channel and the
    /// exposure a factor e^0.2, a model parameter 5 % of its range.
    fn step(&self) -> f64 {
        match self {
            Coord::Smoothness | Coord::Metallic => 0.05,
            Coord::Color(_) | Coord::Exposure => 0.2,
            Coord::Param(_, (lo, hi)) => 0.05 * (hi - lo),
        }
    }
}

/// The refinement's start: the stage-1 node (all zeros) and a step along each coordinate.
fn simplex_around(coords: &[Coord]) -> Vec<Vec<f64>> {
    let n = coords.len();
    let mut simplex = vec![vec![0.0; n]];
    for (k, coord) in coords.iter().enumerate() {
        let mut v = vec![0.0; n];
        v[k] = coord.step();
        simplex.push(v);
    }
    simplex
}

/// The refinement's cost: the error of the rendered frames of the values a parameter vector
/// names, coordinate by coordinate (`Coord`) from the stage-1 node.
struct Refine<'a, 'r> {
    renderer: RefCell<&'r mut Renderer>,
    stage: &'a Stage,
    target: &'a Side<'a>,
    source_frames: &'a [Frame],
    space: MatchSpace,
    start: MaterialValues,
    start_exposure: f64,
    coords: Vec<Coord>,
    displays: &'a [DisplayTransform],
    /// The best values rendered so far: Nelder–Mead's own best is a parameter vector, and
    /// every evaluation's frames are already judged here.
    best: &'a RefCell<Best>,
    renders: &'a RefCell<u32>,
}

impl Refine<'_, '_> {
    /// The values and the exposure `p` names.
    fn values(&self, p: &[f64]) -> (MaterialValues, f64) {
        let s = &self.start;
        let (mut v, mut k) = (s.clone(), self.start_exposure);
        for (coord, x) in self.coords.iter().zip(p) {
            match coord {
                Coord::Smoothness => v.smoothness = (s.smoothness + x).clamp(0.0, 1.0),
                Coord::Metallic => v.metallic = (s.metallic + x).clamp(0.0, 1.0),
                Coord::Color(c) => v.color[*c] = (s.color[*c] * x.exp()).clamp(0.0, 1.0),
                Coord::Param(name, (lo, hi)) => {
                    let from = s.params.get(name).copied().unwrap_or(*lo); // `fit` names every one
                    v.params.insert(name.clone(), (from + x).clamp(*lo, *hi));
                }
                Coord::Exposure => k = self.start_exposure * x.exp(),
            }
        }
        (v, k)
    }
}

impl CostFunction for Refine<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, p: &Self::Param) -> Result<f64, argmin::core::Error> {
        let (values, k) = self.values(p);
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
        let g = grid(&source, &source, 10, &[], Kept::default());
        assert_eq!(g.len(), 12 * 2);
        let has = |s: f64, m: f64| g.iter().any(|n| n.smoothness == s && n.metallic == m);
        assert!(has(0.75, 0.0) && has(1.0, 1.0));
    }

    #[test]
    fn the_grid_spans_a_swept_parameter_and_the_sources_own_value() {
        let mut source = MaterialValues::new(0.5, 0.0, [0.2; 3]);
        source.params.insert("sigma".into(), 0.3);
        let sigma = ParamAxis { name: "sigma".into(), values: vec![0.0, 0.5], range: Some((0.0, 1.5)) };
        let g = grid(&source, &source, 2, &[sigma], Kept::default());
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
        let (got, k) = least_squares(
            std::slice::from_ref(&s),
            std::slice::from_ref(&a),
            std::slice::from_ref(&w),
            Some(1.0),
            None,
        );
        assert_eq!(k, 1.0);
        for i in 0..3 {
            assert!((got[i] - c[i]).abs() < 1e-6, "{got:?}");
        }
        // The same frame a thousand times dimmer: the exposure takes the factor, the colour stays.
        let dim = frame(s.hdr.iter().map(|v| v * 1e-3).collect());
        let (got, k) =
            least_squares(std::slice::from_ref(&dim), std::slice::from_ref(&a), std::slice::from_ref(&w), None, None);
        assert!((k * 1e3 - 1.0).abs() < 1e-6, "{k}");
        for i in 0..3 {
            assert!((got[i] - c[i]).abs() < 1e-6, "{got:?}");
        }
        // The colour kept: the exposure alone is solved for it.
        let (got, k) = least_squares(&[dim], &[a], &[w], None, Some(c));
        assert_eq!(got, c);
        assert!((k * 1e3 - 1.0).abs() < 1e-6, "{k}");
    }

    #[test]
    fn kept_values_leave_the_grid_and_name_themselves() {
        let source = MaterialValues::new(0.35, 0.0, [0.2; 3]);
        let keep = Kept { metallic: true, ..Default::default() };
        let g = grid(&source, &source, 10, &[], keep);
        assert_eq!(g.len(), 12, "smoothness 0, 0.1, …, 1 and 0.35, metallic 0 alone");
        assert!(g.iter().all(|n| n.metallic == 0.0));
        assert_eq!(Kept::parse(["color", "metallic"]), Ok(Kept { smoothness: false, metallic: true, color: true }));
        assert_eq!(Kept::parse(["metalic"]), Err("metalic"));
        assert_eq!(keep.names(), ["metallic"]);
    }
}
