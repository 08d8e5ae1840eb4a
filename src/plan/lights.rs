//! Which lights light which object, and how: the light budget of each pipeline's path, so that no
//! light is dropped without a word (`list` and `cell.json` say which light went where and why).
//!
//! - Built-in forward (Unity manual, "Forward rendering path details"): the brightest directional
//!   light is per-pixel (the base pass); lights with render mode Important are per-pixel; further
//!   lights are per-pixel in decreasing brightness at the object until the quality setting's pixel
//!   light count (default 4, the main light included); then up to 4 point lights are per-vertex
//!   (Shade4PointLights); the rest go into the object's spherical harmonics. Not Important lights
//!   are never per-pixel.
//! - URP forward: the main light (brightest directional) plus additional lights up to the
//!   per-object limit (URP asset default 4, at most 8), brightest first; the rest are not rendered.
//! - HDRP: the clustered light loop has no per-object limit: every light is per-pixel.
//! - Deferred (every pipeline): the G-buffer is lit in screen space, every light per pixel.
//! - Built-in vertex-lit: the 8 brightest lights at the vertices (ShadeVertexLightsFull), the
//!   rest not rendered.
//!
//! "Brightness at the object" is the luminance of the light's colour × intensity in the pipeline's
//! units times its distance attenuation at the object's bounds centre (1 for directional lights).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::color::luminance;
use crate::declarations::scene::{Light, LightKind, RenderMode, Scene};
pub use crate::pipelines::LightBudget;
use crate::pipelines::{Pipeline, RenderPath};

/// How one light reaches one object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LightMode {
    PerPixel,
    /// Built-in's Shade4PointLights: Lambert per vertex, added to the ambient term.
    PerVertex,
    /// Projected into the object's order-2 spherical harmonics.
    Sh,
    /// Not rendered: over URP's per-object limit or the vertex-lit path's 8, or a built-in vertex
    /// or SH light on a lightmapped object (`lightmapped_left_out`).
    Dropped,
    /// Not drawn by the frame: an area light the pipeline only bakes, or one the object's model
    /// cannot evaluate (the reason says which); the truth still sees it.
    LeftOut,
    /// Reaches the object through the scene's bake (lightmaps or light probes) alone (plan::gi).
    Baked,
}

impl LightMode {
    /// The value the forward pass reads (shaders/pass/forward.wgsl `light_mode`).
    pub fn shader_value(self) -> u32 {
        match self {
            LightMode::PerPixel => 0,
            LightMode::PerVertex => 1,
            LightMode::Sh => 2,
            LightMode::Dropped => 3,
            LightMode::LeftOut => 4,
            LightMode::Baked => 5,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            LightMode::PerPixel => "per-pixel",
            LightMode::PerVertex => "per-vertex",
            LightMode::Sh => "SH",
            LightMode::Dropped => "dropped",
            LightMode::LeftOut => "left out",
            LightMode::Baked => "baked",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LightUse {
    /// Index into the scene's lights.
    pub light: usize,
    pub mode: LightMode,
    pub reason: String,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectLights {
    pub object: String,
    /// One entry per scene light, in the scene's order.
    pub lights: Vec<LightUse>,
}

/// Built-in forward's vertex lights (Shade4PointLights takes four).
pub const VERTEX_LIGHT_COUNT: usize = 4;

/// Built-in's legacy vertex-lit path: ShadeVertexLightsFull loops over 8 lights.
pub const VERTEX_LIT_LIGHT_COUNT: usize = 8;

/// The key light's values for this cell, and the lights as the cell sees them.
pub fn cell_lights(scene: &Scene, key_intensity: f64, key_range: f64) -> Vec<Light> {
    let key = scene.key_light();
    scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let mut l = l.clone();
            if Some(i) == key {
                l.intensity = key_intensity;
                l.range = key_range;
            }
            l
        })
        .collect()
}

/// Brightness of `light` at `centre` in `pipeline`'s units (see the module comment).
pub fn brightness_at(pipeline: Pipeline, light: &Light, centre: DVec3) -> f64 {
    let c = luminance(light.radiance(pipeline, light.intensity, &Default::default()));
    match light.kind {
        LightKind::Directional => c,
        _ => c * pipeline.attenuation().eval((DVec3::from(light.position) - centre).length(), light.range),
    }
}

/// What the light assignment reads of an object's model.
#[derive(Debug, Clone, Default)]
pub struct ModelLighting {
    /// It cannot be drawn into a G-buffer (`ShaderModel::deferrable`).
    pub forward_only: bool,
    /// It evaluates rect lights (`ShaderModel::area_lights`).
    pub area_lights: bool,
    /// Per light: why it reaches the object through the bake alone (plan::gi), taking no slot of a
    /// budget; empty: every light is real-time.
    pub baked: Vec<Option<String>>,
    /// It is lit by a lightmap (a static object under `[gi]`).
    pub lightmapped: bool,
}

/// Every object's light assignment. `objects`: names and bounds centres in world space;
/// `model(i)`: what object i's model can draw.
pub fn assign(
    pipeline: Pipeline,
    path: RenderPath,
    budget: &LightBudget,
    lights: &[Light],
    objects: &[(String, DVec3)],
    model: impl Fn(usize) -> ModelLighting,
) -> Vec<ObjectLights> {
    objects
        .iter()
        .enumerate()
        .map(|(i, (name, centre))| {
            let m = model(i);
            let baked = |i: usize| m.baked.get(i).cloned().flatten();
            let realtime: Vec<bool> = (0..lights.len()).map(|i| baked(i).is_none()).collect();
            let mut uses = assign_object(pipeline, lit_path(path, m.forward_only), budget, lights, &realtime, *centre);
            for (u, l) in uses.iter_mut().zip(lights) {
                if let Some(why) = baked(u.light) {
                    *u = use_(u.light, LightMode::Baked, why);
                } else if let Some(why) = area_left_out(pipeline, l, m.area_lights) {
                    *u = use_(u.light, LightMode::LeftOut, why);
                } else if let Some(why) = lightmapped_left_out(pipeline, m.lightmapped, u.mode) {
                    *u = use_(u.light, LightMode::Dropped, why);
                }
            }
            ObjectLights { object: name.clone(), lights: uses }
        })
        .collect()
}

/// Why a lightmapped object in `pipeline` takes no light of `mode`, if it takes none: built-in's
/// ForwardBase reads the lightmap in place of the vertex lights and the spherical harmonics
/// (UnityStandardCore.cginc VertexGIForward: under LIGHTMAP_ON the ambient slot holds the
/// lightmap's uv, and Shade4PointLights and ShadeSHPerVertex run only under
/// UNITY_SHOULD_SAMPLE_SH; surface shaders likewise), so its Not Important lights light it not at
/// all; the vertex-lit path draws a lightmapped object with its shader's VertexLM pass, the
/// lightmap alone (Lighting Off). URP's per-object lights do not depend on the lightmap.
pub fn lightmapped_left_out(pipeline: Pipeline, lightmapped: bool, mode: LightMode) -> Option<String> {
    match (pipeline, lightmapped, mode) {
        (Pipeline::Builtin, true, LightMode::PerVertex | LightMode::Sh) => Some(format!(
            "a lightmapped object: built-in lights it by its lightmap, not by {} lights (ForwardBase without UNITY_SHOULD_SAMPLE_SH; VertexLM)",
            mode.name()
        )),
        _ => None,
    }
}

/// Why the frame leaves an area light out, if it does: built-in and URP bake area lights only
/// (Unity manual, "Area Lights"); HDRP draws rectangles in real time but bakes discs
/// (HDAdditionalLightData: Disc is Baked-only), and evaluates them in its Lit family's BSDF
/// (Lit.hlsl EvaluateBSDF_Rect), not in a model without one. In a scene with `[gi]` such a light
/// is baked (plan::gi) and never reaches this question.
pub fn area_left_out(pipeline: Pipeline, light: &Light, model_has_area: bool) -> Option<String> {
    const BAKED: &str =
        "it lights only through baked GI, which this scene does not bake (no [gi]): the frame leaves it out, the truth has it";
    match (light.kind, pipeline) {
        (LightKind::Rect | LightKind::Disc, Pipeline::Builtin) => {
            Some(format!("built-in bakes area lights only; {BAKED}"))
        }
        (LightKind::Rect | LightKind::Disc, Pipeline::Urp) => Some(format!("URP bakes area lights only; {BAKED}")),
        (LightKind::Disc, Pipeline::Hdrp) => Some(format!("HDRP bakes disc lights only; {BAKED}")),
        (LightKind::Rect, Pipeline::Hdrp) if !model_has_area => Some(
            "the model has no area-light BSDF (HDRP evaluates rect lights in its Lit family's EvaluateBSDF_Rect)"
                .into(),
        ),
        _ => None,
    }
}

/// Whether the frame's shaders need their area-light path: where the scene has a rect or disc
/// light at all (drawn or left out, the shader tells them from punctual lights by it). A frame
/// without one compiles the path out (forward.wgsl `AREA_LIGHTS`): the LTC and polygon integrals
/// are the largest code of a lit shader, and the driver compiles and runs less without them.
pub fn needs_area_path(lights: &[Light]) -> bool {
    lights.iter().any(Light::is_area)
}

/// The optional paths of a frame's light loops, each compiled in only where a light of the cell
/// takes it: the driver then compiles and runs the common light's loop alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LightPaths {
    /// Rect and disc lights (`needs_area_path`; forward.wgsl `AREA_LIGHTS`).
    pub area: bool,
    /// HDRP's per-light terms beyond its colour (`LightTerms::needs_shader_path`: a lobe left
    /// unlit, a pyramid or box window, Range Attenuation off, a tinted shadow; scene.wgsl
    /// `HDRP_LIGHT_TERMS`). Dimmers fold into the colour and need none.
    pub hdrp_terms: bool,
    /// HDRP's PCSS shadow filter (a light's shadow at Filtering Quality High; forward.wgsl
    /// `HDRP_PCSS`): its blocker search and filter loops are compiled only into the frames that
    /// read a map with it.
    pub pcss: bool,
}

impl LightPaths {
    /// Every path (a probe capture's pipelines, drawn for any frame).
    pub const ALL: LightPaths = LightPaths { area: true, hdrp_terms: true, pcss: true };
}

/// Whether the frame draws an area light in real time: HDRP's rectangles alone (Unity manual,
/// "Area Lights": built-in and URP bake area lights; HDAdditionalLightData: a disc is Baked-only).
/// A rect the object's model cannot evaluate is then left out by `area_left_out`.
pub fn draws_area(pipeline: Pipeline, light: &Light) -> bool {
    pipeline == Pipeline::Hdrp && light.kind == LightKind::Rect
}

/// The path whose budget lights an object: on a deferred path, what the G-buffer cannot carry is
/// drawn in a forward pass after the deferred lighting and lit as forward lights it — built-in
/// deferred falls back to ForwardBase/ForwardAdd with the pixel light count, URP deferred draws
/// forward-only passes with the per-object limit, HDRP's forward-only materials read the same
/// light list as its forward path.
pub fn lit_path(path: RenderPath, forward_only: bool) -> RenderPath {
    if path == RenderPath::Deferred && forward_only {
        RenderPath::Forward
    } else {
        path
    }
}

fn use_(light: usize, mode: LightMode, reason: impl Into<String>) -> LightUse {
    LightUse { light, mode, reason: reason.into() }
}

/// The main light — the base pass's in built-in (a Not Important light cannot be it), URP's main
/// light — and the one whose colour scales a ForwardBase shader's ambient.
pub fn main_light(pipeline: Pipeline, lights: &[Light]) -> Option<usize> {
    // A baked light is not among the frame's lights at all.
    brightest_directional(pipeline, lights, |l| {
        l.mode != crate::declarations::gi::LightBakeMode::Baked
            && (pipeline != Pipeline::Builtin || l.render_mode != RenderMode::NotImportant)
    })
}

/// The brightest directional light that `allowed` admits (ties: the first).
fn brightest_directional(pipeline: Pipeline, lights: &[Light], allowed: impl Fn(&Light) -> bool) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, l) in lights.iter().enumerate() {
        if l.kind == LightKind::Directional && allowed(l) {
            let b = brightness_at(pipeline, l, DVec3::ZERO);
            if best.is_none_or(|(_, bb)| b > bb) {
                best = Some((i, b));
            }
        }
    }
    best.map(|(i, _)| i)
}

/// Indices of `candidates` by decreasing brightness at `centre` (ties: scene order).
fn by_brightness(pipeline: Pipeline, lights: &[Light], centre: DVec3, mut candidates: Vec<usize>) -> Vec<usize> {
    candidates.sort_by(|&a, &b| {
        brightness_at(pipeline, &lights[b], centre)
            .total_cmp(&brightness_at(pipeline, &lights[a], centre))
            .then(a.cmp(&b))
    });
    candidates
}

fn assign_object(
    pipeline: Pipeline,
    path: RenderPath,
    budget: &LightBudget,
    lights: &[Light],
    realtime: &[bool],
    centre: DVec3,
) -> Vec<LightUse> {
    let mut out: Vec<Option<LightUse>> = vec![None; lights.len()];
    // Area lights and baked ones take no slot of a budget (`assign` says what becomes of them).
    let area: Vec<usize> = (0..lights.len()).filter(|&i| lights[i].is_area() || !realtime[i]).collect();
    for &i in &area {
        out[i] = Some(use_(i, LightMode::PerPixel, "an area light, in HDRP's light loop"));
    }
    if path == RenderPath::Deferred {
        return (0..lights.len())
            .map(|i| use_(i, LightMode::PerPixel, "deferred lighting has no per-object limit"))
            .collect();
    }
    if path == RenderPath::VertexLit {
        let all: Vec<usize> = (0..lights.len()).filter(|i| !area.contains(i)).collect();
        for (rank, i) in by_brightness(pipeline, lights, centre, all).into_iter().enumerate() {
            out[i] = Some(if rank < VERTEX_LIT_LIGHT_COUNT {
                use_(
                    i,
                    LightMode::PerVertex,
                    format!("vertex-lit path: light {} of {VERTEX_LIT_LIGHT_COUNT}", rank + 1),
                )
            } else {
                use_(i, LightMode::Dropped, format!("beyond the vertex-lit path's {VERTEX_LIT_LIGHT_COUNT} lights"))
            });
        }
        return out.into_iter().map(|u| u.expect("every light assigned")).collect();
    }
    match pipeline {
        Pipeline::Hdrp => {
            for (i, slot) in out.iter_mut().enumerate() {
                if slot.is_none() {
                    *slot = Some(use_(i, LightMode::PerPixel, "HDRP's light loop has no per-object limit"));
                }
            }
        }
        Pipeline::Urp => {
            let main = main_light(pipeline, lights).filter(|&m| realtime[m]);
            if let Some(m) = main {
                out[m] = Some(use_(m, LightMode::PerPixel, "the main light (brightest directional)"));
            }
            let rest: Vec<usize> = (0..lights.len()).filter(|&i| Some(i) != main && out[i].is_none()).collect();
            let limit = budget.urp_per_object_limit as usize;
            for (rank, i) in by_brightness(pipeline, lights, centre, rest).into_iter().enumerate() {
                out[i] = Some(if rank < limit {
                    use_(
                        i,
                        LightMode::PerPixel,
                        format!("additional light {} of the per-object limit {limit}", rank + 1),
                    )
                } else {
                    use_(
                        i,
                        LightMode::Dropped,
                        format!(
                            "beyond URP's per-object limit of {limit} additional lights (brightness rank {})",
                            rank + 1
                        ),
                    )
                });
            }
        }
        Pipeline::Builtin => {
            let main = main_light(pipeline, lights).filter(|&m| realtime[m]);
            let mut pixel = 0usize;
            if let Some(m) = main {
                out[m] = Some(use_(m, LightMode::PerPixel, "the brightest directional light (base pass)"));
                pixel += 1;
            }
            for (i, l) in lights.iter().enumerate() {
                if out[i].is_none() && l.render_mode == RenderMode::Important {
                    out[i] = Some(use_(i, LightMode::PerPixel, "render_mode = important"));
                    pixel += 1;
                }
            }
            let limit = budget.pixel_light_count as usize;
            let auto: Vec<usize> =
                (0..lights.len()).filter(|&i| out[i].is_none() && lights[i].render_mode == RenderMode::Auto).collect();
            for i in by_brightness(pipeline, lights, centre, auto) {
                if pixel < limit {
                    out[i] =
                        Some(use_(i, LightMode::PerPixel, format!("among the {limit} brightest (pixel light count)")));
                    pixel += 1;
                }
            }
            let left: Vec<usize> = (0..lights.len()).filter(|&i| out[i].is_none()).collect();
            let mut vertex = 0usize;
            for i in by_brightness(pipeline, lights, centre, left) {
                let why_not_pixel = if lights[i].render_mode == RenderMode::NotImportant {
                    "render_mode = not_important".to_string()
                } else {
                    format!("beyond the pixel light count {limit}")
                };
                out[i] = Some(if lights[i].kind == LightKind::Point && vertex < VERTEX_LIGHT_COUNT {
                    vertex += 1;
                    use_(
                        i,
                        LightMode::PerVertex,
                        format!("{why_not_pixel}: vertex light {vertex} of {VERTEX_LIGHT_COUNT}"),
                    )
                } else {
                    let why = if lights[i].kind == LightKind::Point {
                        format!("{why_not_pixel} and the {VERTEX_LIGHT_COUNT} vertex lights")
                    } else {
                        format!("{why_not_pixel}; only point lights can be vertex lights")
                    };
                    use_(i, LightMode::Sh, format!("{why}: spherical harmonics"))
                });
            }
        }
    }
    out.into_iter().map(|u| u.expect("every light assigned")).collect()
}

/// Order-2 SH coefficients (the basis of shaders/pass/scene.wgsl `ambient_diffuse`) of a light's
/// clamped-cosine irradiance, Σ Â_l·Y_lm(l)·Y_lm(n) ≈ max(0, n·l) with Â = (π, 2π/3, π/4)
/// (Ramamoorthi & Hanrahan 2001), times `color`: how a light folded into SH reaches an object.
pub fn sh_of_light(direction_to_light: DVec3, color: DVec3) -> [DVec3; 9] {
    let d = direction_to_light.normalize_or_zero();
    let (x, y, z) = (d.x, d.y, d.z);
    use std::f64::consts::PI;
    let (a0, a1, a2) = (PI, 2.0 * PI / 3.0, PI / 4.0);
    let basis = [
        a0 * 0.282095,
        a1 * 0.488603 * y,
        a1 * 0.488603 * z,
        a1 * 0.488603 * x,
        a2 * 1.092548 * x * y,
        a2 * 1.092548 * y * z,
        a2 * 0.315392 * (3.0 * z * z - 1.0),
        a2 * 1.092548 * x * z,
        a2 * 0.546274 * (x * x - y * y),
    ];
    basis.map(|b| color * b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_scene_with_an_area_light_keeps_the_shaders_area_path() {
        let scene = Scene::load("default", None, "t", "k").unwrap();
        assert!(!needs_area_path(&scene.lights), "the default room has punctual lights only");
        for kind in [LightKind::Rect, LightKind::Disc] {
            let mut lights = scene.lights.clone();
            lights[0].kind = kind;
            assert!(needs_area_path(&lights), "{kind:?}");
        }
    }

    fn scene_with(n_points: usize) -> Vec<Light> {
        let mut scene = Scene::load("default", None, "t", "k").unwrap();
        let template = scene.lights[0].clone();
        scene.lights = (0..n_points)
            .map(|i| {
                let mut l = template.clone();
                l.key = false;
                l.position = [i as f64 * 0.5 - 3.0, 2.0, 1.0];
                l.intensity = 1.0 + i as f64 * 0.1;
                l
            })
            .collect();
        scene.lights
    }

    #[test]
    fn a_lightmapped_object_in_builtin_forward_takes_no_vertex_or_sh_lights() {
        let lights = scene_with(12);
        let objects = [("static".into(), DVec3::ZERO), ("dynamic".into(), DVec3::ZERO)];
        let model = |i: usize| ModelLighting { lightmapped: i == 0, ..Default::default() };
        let count = |u: &ObjectLights, m: LightMode| u.lights.iter().filter(|u| u.mode == m).count();
        let builtin = assign(Pipeline::Builtin, RenderPath::Forward, &LightBudget::default(), &lights, &objects, model);
        let (lightmapped, probe_lit) = (&builtin[0], &builtin[1]);
        assert_eq!((count(lightmapped, LightMode::PerPixel), count(lightmapped, LightMode::Dropped)), (4, 8));
        assert_eq!((count(probe_lit, LightMode::PerVertex), count(probe_lit, LightMode::Sh)), (4, 4));
        assert!(lightmapped
            .lights
            .iter()
            .filter(|u| u.mode == LightMode::Dropped)
            .all(|u| u.reason.contains("lightmapped")));
        // URP's per-object budget does not look at the lightmap.
        let urp = assign(Pipeline::Urp, RenderPath::Forward, &LightBudget::default(), &lights, &objects, model);
        assert_eq!(urp[0].lights, urp[1].lights);
    }

    #[test]
    fn builtin_forward_twelve_points_four_pixel_four_vertex_four_sh() {
        let lights = scene_with(12);
        let plan = assign(
            Pipeline::Builtin,
            RenderPath::Forward,
            &LightBudget::default(),
            &lights,
            &[("o".into(), DVec3::ZERO)],
            |_| ModelLighting::default(),
        );
        let count = |m: LightMode| plan[0].lights.iter().filter(|u| u.mode == m).count();
        assert_eq!((count(LightMode::PerPixel), count(LightMode::PerVertex), count(LightMode::Sh)), (4, 4, 4));
        // The per-pixel ones are the brightest at the object.
        let b = |i: usize| brightness_at(Pipeline::Builtin, &lights[i], DVec3::ZERO);
        let min_pixel = plan[0]
            .lights
            .iter()
            .filter(|u| u.mode == LightMode::PerPixel)
            .map(|u| b(u.light))
            .fold(f64::MAX, f64::min);
        let max_other =
            plan[0].lights.iter().filter(|u| u.mode != LightMode::PerPixel).map(|u| b(u.light)).fold(0.0, f64::max);
        assert!(min_pixel >= max_other);
    }

    #[test]
    fn forward_only_models_on_deferred_get_the_forward_budget() {
        let lights = scene_with(12);
        let two = [("subject".to_string(), DVec3::ZERO), ("wall".to_string(), DVec3::ZERO)];
        let plan = assign(Pipeline::Builtin, RenderPath::Deferred, &LightBudget::default(), &lights, &two, |i| {
            ModelLighting { forward_only: i == 0, ..Default::default() }
        });
        let per_pixel = |o: &ObjectLights| o.lights.iter().filter(|u| u.mode == LightMode::PerPixel).count();
        assert_eq!(per_pixel(&plan[0]), 4, "drawn forward: the pixel light count");
        assert_eq!(per_pixel(&plan[1]), 12, "in the G-buffer: every light per pixel");
    }

    #[test]
    fn render_modes_and_urp_limit() {
        let mut lights = scene_with(6);
        lights[0].render_mode = RenderMode::NotImportant;
        lights[5].render_mode = RenderMode::Important;
        let one = [("o".to_string(), DVec3::ZERO)];
        let b = assign(Pipeline::Builtin, RenderPath::Forward, &LightBudget::default(), &lights, &one, |_| {
            ModelLighting::default()
        });
        assert_eq!(b[0].lights[5].mode, LightMode::PerPixel);
        assert_ne!(b[0].lights[0].mode, LightMode::PerPixel);
        let u = assign(Pipeline::Urp, RenderPath::Forward, &LightBudget::default(), &lights, &one, |_| {
            ModelLighting::default()
        });
        let dropped: Vec<&LightUse> = u[0].lights.iter().filter(|u| u.mode == LightMode::Dropped).collect();
        assert_eq!(dropped.len(), 2, "six points, four additional lights per object");
        assert!(dropped[0].reason.contains("per-object limit of 4"));
        let h = assign(Pipeline::Hdrp, RenderPath::Forward, &LightBudget::default(), &lights, &one, |_| {
            ModelLighting::default()
        });
        assert!(h[0].lights.iter().all(|u| u.mode == LightMode::PerPixel));
    }

    #[test]
    fn sh_of_a_light_approximates_the_clamped_cosine() {
        let l = DVec3::new(0.3, 0.8, 0.2).normalize();
        let sh = sh_of_light(l, DVec3::ONE);
        let eval = |n: DVec3| {
            let (x, y, z) = (n.x, n.y, n.z);
            let basis = [
                0.282095,
                0.488603 * y,
                0.488603 * z,
                0.488603 * x,
                1.092548 * x * y,
                1.092548 * y * z,
                0.315392 * (3.0 * z * z - 1.0),
                1.092548 * x * z,
                0.546274 * (x * x - y * y),
            ];
            sh.iter().zip(basis).map(|(c, b)| c.x * b).sum::<f64>()
        };
        // Order 2 reproduces the clamped cosine within ~0.1 (its known ringing), exactly in mean.
        assert!((eval(l) - 1.0).abs() < 0.12, "{}", eval(l));
        assert!(eval(-l).abs() < 0.12, "{}", eval(-l));
    }
}
