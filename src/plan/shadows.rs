//! Shadow-map planning: which layers each shadowed light takes, their resolution and their
//! view-projections, decided on the CPU before any GPU work (render::passes::shadow draws them).
//! One depth layer per directional cascade or spot light that casts shadows, six (a cube's faces)
//! per point light, in one depth texture array, re-rendered every frame as an engine does.
//! Directional lights have each pipeline's cascades (`Pipeline::shadow_cascades`): each covers a
//! slice of the camera frustum by view depth, fitted with its bounding sphere (Unity's "stable
//! fit"), its depth range stretched back to every caster. Each light's map has its pipeline's
//! default resolution (`Pipeline::default_shadow_resolution`) unless its scene entry sets one: it
//! is rendered into the top-left square of its layer and sampled there, so one array serves every
//! pipeline's resolutions.

use glam::{DMat4, DVec3};

use serde::{Deserialize, Serialize};

use crate::declarations::scene::{Camera, Light, LightKind};
use crate::pipelines::settings::{BuiltinShadows, HdrpQuality, PipelineSettings};
use crate::pipelines::surface::SurfaceOptions;
use crate::pipelines::{Pipeline, ShadowCascades};

/// One shadow layer as planned: its view-projection, (texel size per unit depth or per metre,
/// perspective flag, resolution, share of the layer its map covers), for a cascade its bounding
/// sphere (centre, radius), and HDRP's PCSS terms where its shadow is drawn with PCSS
/// (`hdrp_pcss`). render::uniforms::ShadowLayer mirrors it on the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShadowLayerPlan {
    pub view_proj: [[f32; 4]; 4],
    pub params: [f32; 4],
    pub sphere: [f32; 4],
    pub pcss: [f32; 4],
}

/// What HDRP's PCSS needs of a layer's projection: a perspective map's near and far planes, or
/// an orthographic one's depth range and (directional) how far its eye sits back from the
/// cascade's centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LayerDepth {
    Perspective { near: f64, far: f64 },
    Orthographic { range: f64, back: f64 },
}

/// Near plane of spot and point shadow frusta, metres.
const SHADOW_NEAR: f64 = 0.02;

/// The side of the array layers a light needs: its own resolution, or the largest default any
/// pipeline gives it at images up to `ARRAY_IMAGE_SIDE` pixels (built-in's default grows with the
/// image; past that it is clamped to the layer and the cell record says so).
/// `engines`: the engine settings the composition's cells render with (each pipeline's map size
/// follows them).
pub fn array_side(light: &Light, engines: &[PipelineSettings]) -> u32 {
    light.shadow.resolution.unwrap_or_else(|| {
        let default = [PipelineSettings::default()];
        let engines = if engines.is_empty() { &default[..] } else { engines };
        engines
            .iter()
            .flat_map(|e| Pipeline::ALL.map(|p| p.shadow_resolution_with(e, light.emitter(), ARRAY_IMAGE_SIDE)))
            .max()
            .unwrap_or(1)
    })
}

/// The image side up to which default shadow resolutions fit the array unclamped.
const ARRAY_IMAGE_SIDE: f64 = 1024.0;

/// How a shadowed light's shadow is drawn in a pipeline: soft (3×3 PCF) or hard, or HDRP's
/// n×n tent PCF (`tent` n, 0 for none) or its PCSS, and its receiver biases in shadow-map texels,
/// along the light and along the normal.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShadowStyle {
    pub strength: f64,
    pub soft: bool,
    pub bias: f64,
    pub normal_bias: f64,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub tent: u32,
    #[serde(default, skip_serializing_if = "is_false")]
    pub pcss: bool,
}

fn is_zero(v: &u32) -> bool {
    *v == 0
}

fn is_false(v: &bool) -> bool {
    !*v
}

/// HDAdditionalLightData's PCSS defaults: m_MinFilterSize 0.1, which the shadow request scales
/// by 0.001 ("to have a range [0...1] exposed to user"), and softnessScale 1.
const HDRP_MIN_FILTER_SIZE: f64 = 0.1 * 0.001;
const HDRP_SOFTNESS_SCALE: f64 = 1.0;

/// HDRP's PCSS terms of one layer (HDAdditionalLightData.UpdateShadowRequestData, as
/// HDShadowManager packs them into shadowFilterParams0 and zBufferParam): [softness, minimum filter
/// radius, a, b], a, b being 1/z's terms (zBufferParam.zw) of a perspective map, or the range
/// scale (zBufferParam.x) and 0 of an orthographic one.
/// - A punctual light's softness is HDRP's quartic fit of its shape radius × softness scale
///   ("fitted with quartic regression checking against raytracing reference", at 512²), / 100.
/// - A directional light's is tan(½·Deg2Rad·angular diameter·scale / 2) · frustumExtentZ /
///   (2 · cascade radius), frustumExtentZ being the view depth of the cascade projection's near
///   plane. Unity's native cascade matrices are not published; APPROXIMATED here with the cascade's
///   own geometry: its eye sits `back` from the sphere's centre (plan::shadows::light_layers).
/// - Either × resolution / 512 ("resolution independent whereas the baseline is 512").
/// - The range scale is |2 / m22| / 100 of the (reversed-Z) device projection: 2 · depth range / 100.
pub fn hdrp_pcss(emitter: &crate::pipelines::Emitter, depth: LayerDepth, radius: f64, resolution: u32) -> [f32; 4] {
    use crate::pipelines::Emitter;
    let softness = match *emitter {
        Emitter::Directional { angular_diameter_deg } => {
            let back = match depth {
                LayerDepth::Orthographic { back, .. } => back,
                LayerDepth::Perspective { .. } => 0.0,
            };
            let half_angle_tan = (0.5 * (HDRP_SOFTNESS_SCALE * angular_diameter_deg).to_radians() / 2.0).tan();
            (half_angle_tan * back / (2.0 * radius.max(1e-6))).abs()
        }
        Emitter::Point { radius } | Emitter::Spot { radius, .. } => {
            crate::shading::shadow_filter::pcss_softness_punctual(radius * HDRP_SOFTNESS_SCALE)
        }
        Emitter::Rect { .. } | Emitter::Disc { .. } => 0.0,
    } * resolution as f64
        / 512.0;
    let (a, b) = match depth {
        // GetZBufferParam(range, near): ((f − n)/n, 1, (f − n)/(n·f), 1/f); the shader takes z and w.
        LayerDepth::Perspective { near, far } => ((far - near) / (near * far), 1.0 / far),
        LayerDepth::Orthographic { range, .. } => (2.0 * range / 100.0, 0.0),
    };
    [softness as f32, HDRP_MIN_FILTER_SIZE as f32, a as f32, b as f32]
}

/// HDRP's slope-bias base under PCSS: 5, raised towards 18 as the softness grows past 0.01
/// ("If we are PCSS, the blur radius can be quite big, hence we need to tweak up the slope bias";
/// the lerp stops at a softness of 0.05). The share of the base 5 it is.
pub fn pcss_bias_scale(softness: f64) -> f64 {
    if softness > 0.01 {
        (5.0 + (18.0 - 5.0) * (softness * 100.0 / 5.0).min(1.0)) / 5.0
    } else {
        1.0
    }
}

/// HDRP's tent for a light at a shadow Filtering Quality (HDShadowAlgorithms.hlsl): Low reads a
/// punctual light's map with SampleShadow_PCF_Tent_3x3 and a directional one's with _5x5, Medium
/// with _5x5 and _7x7. High is PCSS (`ShadowStyle::pcss`), no tent.
pub fn hdrp_tent(quality: HdrpQuality, kind: LightKind) -> u32 {
    let directional = kind == LightKind::Directional;
    match (quality, directional) {
        (HdrpQuality::Low, false) => 3,
        (HdrpQuality::Low, true) | (HdrpQuality::Medium, false) | (HdrpQuality::High, false) => 5,
        (HdrpQuality::Medium, true) | (HdrpQuality::High, true) => 7,
    }
}

/// The style of `light`'s shadow in `pipeline`, or why it casts none there.
/// - Built-in: the light's own settings (Light inspector: Strength, Bias 0.05, Normal Bias 0.4),
///   but a point light's normal bias, which the engine sets to 0 (unity_LightShadowBias.z,
///   Shadows.cpp, as URP's ShadowUtils.GetShadowBias quotes it); no shadow where the quality
///   level's shadows are Disable, a hard one where they are Hard Only.
/// - URP: a light other than the main one casts only with the asset's additional-light shadows
///   (UniversalRenderPipelineAsset m_AdditionalLightShadowsSupported, off in the code defaults);
///   soft only with the asset's soft shadows; a light's bias "Use settings from Render Pipeline
///   Asset" (UniversalAdditionalLightData default) takes the asset's depth and normal bias, both
///   ×2.5 when soft (ShadowUtils.GetShadowBias: kernelRadius 2.5), and no normal bias for a point
///   light.
/// - HDRP: HDAdditionalLightData's normalBias 0.75 texel; its slopeBias 0.5 is a rasterisation
///   slope-scaled depth bias, APPROXIMATED here as half a texel along the light at the receiver
///   (under PCSS scaled as HDRP raises its base, `pcss_bias_scale`); every shadow filtered with
///   the asset's Filtering Quality: Low and Medium a tent (`hdrp_tent`), High PCSS.
pub fn shadow_style(
    pipeline: Pipeline,
    engine: &PipelineSettings,
    light: &Light,
    is_main: bool,
) -> Result<ShadowStyle, String> {
    let s = &light.shadow;
    match pipeline {
        Pipeline::Builtin => {
            let soft = match engine.builtin.quality.shadows {
                BuiltinShadows::Disable => {
                    return Err(format!(
                        "built-in quality level `{}`: shadows Disable (QualitySettings.shadows)",
                        engine.builtin.quality.level.name()
                    ))
                }
                BuiltinShadows::HardOnly => false,
                BuiltinShadows::All => s.soft,
            };
            let normal_bias = if light.kind == LightKind::Point { 0.0 } else { s.normal_bias };
            Ok(ShadowStyle { strength: s.strength, soft, bias: s.bias, normal_bias, tent: 0, pcss: false })
        }
        Pipeline::Urp => {
            let a = &engine.urp;
            if !is_main && !a.additional_light_shadows {
                return Err(format!(
                    "URP asset `{}`: additional-light shadows off (m_AdditionalLightShadowsSupported)",
                    a.preset.name()
                ));
            }
            let soft = s.soft && a.soft_shadows;
            let k = if soft { 2.5 } else { 1.0 };
            // ShadowUtils.GetShadowBias: "normalBias = 0.0f" for a point light, following built-in.
            let normal_bias = if light.kind == LightKind::Point { 0.0 } else { a.normal_bias * k };
            Ok(ShadowStyle { strength: s.strength, soft, bias: a.depth_bias * k, normal_bias, tent: 0, pcss: false })
        }
        // HDRP filters every shadow (a light has no hard option): the asset's Filtering Quality.
        Pipeline::Hdrp => Ok(ShadowStyle {
            strength: s.strength,
            soft: true,
            bias: 0.5,
            normal_bias: 0.75,
            tent: match engine.hdrp.shadow_filtering {
                HdrpQuality::High => 0,
                q => hdrp_tent(q, light.kind),
            },
            pcss: engine.hdrp.shadow_filtering == HdrpQuality::High,
        }),
    }
}

/// A light's shadow-map resolution in a cell, at most the array's `side`, and a note when the
/// pipeline's default had to be clamped to it.
pub fn cell_resolution(
    pipeline: Pipeline,
    engine: &PipelineSettings,
    light: &Light,
    camera: &Camera,
    (width, height): (u32, u32),
    side: u32,
) -> (u32, Option<String>) {
    let wanted = light.shadow.resolution.unwrap_or_else(|| {
        pipeline.shadow_resolution_with(engine, light.emitter(), screen_extent(light, camera, (width, height)))
    });
    if wanted <= side {
        (wanted, None)
    } else {
        (
            side,
            Some(format!("{} would use {wanted}² at {width}×{height}; clamped to the {side}² layer", pipeline.name())),
        )
    }
}

/// The larger on-screen extent, in pixels, of what a light can reach: the whole image for a
/// directional light; for a point or spot light the projection of its range sphere, as Unity's
/// built-in pipeline sizes shadow maps (the spot's cone is bounded by its sphere: an upper bound).
fn screen_extent(light: &Light, camera: &Camera, (width, height): (u32, u32)) -> f64 {
    let full = width.max(height) as f64;
    if light.kind == LightKind::Directional {
        return full;
    }
    let d = (DVec3::from(light.position) - DVec3::from(camera.position)).length();
    if d <= light.range {
        return full;
    }
    let half_angle = (light.range / d).asin();
    let tan_half_fov = (camera.fov_y_deg.to_radians() * 0.5).tan();
    (half_angle.tan() / tan_half_fov * height as f64).min(full)
}

/// What a directional light's cascades are fitted to: the camera and the cascades of the pipeline.
pub struct CascadeView<'a> {
    pub camera: &'a Camera,
    pub aspect: f64,
    pub cascades: &'a ShadowCascades,
}

/// The layers of one light: view-projection matrices, the texel size they imply and HDRP's PCSS
/// terms (`hdrp_pcss`; the cell's plan keeps them where its shadow is drawn with PCSS).
pub fn light_layers(
    light: &Light,
    shape: crate::pipelines::hdrp_light::SpotShape,
    (resolution, array_side): (u32, u32),
    scene_bounds: (DVec3, DVec3),
    view: &CascadeView,
) -> Vec<ShadowLayerPlan> {
    let up_for = |dir: DVec3| if dir.cross(DVec3::Y).length() < 1e-6 { DVec3::Z } else { DVec3::Y };
    let res = resolution as f64;
    let emitter = light.emitter();
    let pcss = |depth: LayerDepth, radius: f64| hdrp_pcss(&emitter, depth, radius, resolution);
    let perspective = |eye: DVec3, dir: DVec3, fov: f64, up: DVec3, far: f64| {
        let view = DMat4::look_at_rh(eye, eye + dir, up);
        let far = far.max(SHADOW_NEAR * 2.0);
        let proj = DMat4::perspective_rh(fov, 1.0, SHADOW_NEAR, far);
        // World size of a texel per unit of view depth: 2·tan(fov/2)/resolution.
        let mut l = layer(proj * view, [(2.0 * (fov * 0.5).tan() / res) as f32, 1.0, 0.0, 0.0], resolution, array_side);
        l.pcss = pcss(LayerDepth::Perspective { near: SHADOW_NEAR, far }, 0.0);
        l
    };
    match light.kind {
        // Refused by the scene's checks (declarations::area_light): no shadow maps.
        LightKind::Rect | LightKind::Disc => Vec::new(),
        LightKind::Directional => {
            let dir = DVec3::from(light.direction).normalize();
            let (lo, hi) = scene_bounds;
            let scene_centre = (lo + hi) * 0.5;
            let scene_radius = ((hi - lo).length() * 0.5).max(1e-3);
            let cam = view.camera;
            let eye = DVec3::from(cam.position);
            let forward = (DVec3::from(cam.target) - eye).normalize();
            let tan_y = (cam.fov_y_deg.to_radians() * 0.5).tan();
            let tan_x = tan_y * view.aspect;
            let mut near = cam.near;
            view.cascades
                .splits
                .iter()
                .map(|split| {
                    let far = split * view.cascades.max_distance;
                    // Bounding sphere of the frustum slice [near, far]: on the axis, at the point
                    // equidistant from the near and far corners (or at the far centre when closer).
                    let k2 = tan_x * tan_x + tan_y * tan_y;
                    let z = ((far * far - near * near) * (1.0 + k2) / (2.0 * (far - near))).min(far);
                    let corner = |d: f64| ((d - z).powi(2) + d * d * k2).sqrt();
                    let radius = corner(near).max(corner(far)).max(1e-3);
                    let centre = eye + forward * z;
                    near = far;
                    // The light's near plane goes back far enough to take every caster of the scene.
                    let back = radius + (centre - scene_centre).length() + scene_radius;
                    let light_eye = centre - dir * back;
                    let view_m = DMat4::look_at_rh(light_eye, centre, up_for(dir));
                    let proj = DMat4::orthographic_rh(-radius, radius, -radius, radius, 0.0, back + radius);
                    let mut l =
                        layer(proj * view_m, [(2.0 * radius / res) as f32, 0.0, 0.0, 0.0], resolution, array_side);
                    l.sphere = [centre.x as f32, centre.y as f32, centre.z as f32, radius as f32];
                    l.pcss = pcss(LayerDepth::Orthographic { range: back + radius, back }, radius);
                    l
                })
                .collect()
        }
        LightKind::Spot => {
            use crate::pipelines::hdrp_light::{frustum_size, SpotShape};
            let dir = DVec3::from(light.direction).normalize();
            let eye = DVec3::from(light.position);
            // The angle the map spans: the cone's, or the wider side of HDRP's pyramid.
            let angle = match shape {
                SpotShape::Pyramid { aspect_ratio } => {
                    let (w, h) = frustum_size(light.spot_angle_deg, aspect_ratio);
                    2.0 * (w.max(h) * 0.5).atan()
                }
                _ => light.spot_angle_deg.to_radians(),
            };
            if let SpotShape::Box { width, height } = shape {
                // HDRP's box casts an orthographic map over its width and height (a texel of margin).
                let half = width.max(height) * 0.5 * (1.0 + 2.0 / res);
                let view_m = DMat4::look_at_rh(eye, eye + dir, up_for(dir));
                let proj = DMat4::orthographic_rh(-half, half, -half, half, 0.0, light.range);
                let mut l = layer(proj * view_m, [(2.0 * half / res) as f32, 0.0, 0.0, 0.0], resolution, array_side);
                l.pcss = pcss(LayerDepth::Orthographic { range: light.range, back: 0.0 }, half);
                return vec![l];
            }
            // A texel of margin around the cone.
            let fov = (angle * (1.0 + 2.0 / res)).min(std::f64::consts::PI * 0.99);
            vec![perspective(eye, dir, fov, up_for(dir), light.range)]
        }
        LightKind::Point => {
            let eye = DVec3::from(light.position);
            // +X, −X, +Y, −Y, +Z, −Z: the face the forward pass picks by the major axis.
            let faces = [
                (DVec3::X, -DVec3::Y),
                (-DVec3::X, -DVec3::Y),
                (DVec3::Y, DVec3::Z),
                (-DVec3::Y, -DVec3::Z),
                (DVec3::Z, -DVec3::Y),
                (-DVec3::Z, -DVec3::Y),
            ];
            faces
                .iter()
                .map(|(dir, up)| {
                    perspective(eye, *dir, std::f64::consts::FRAC_PI_2 * (1.0 + 2.0 / res), *up, light.range)
                })
                .collect()
        }
    }
}

/// A layer whose map is `resolution`² texels in the top-left of an `array_side`² layer: params.z
/// its resolution, params.w the share of the layer it covers (the shader scales its UV by it).
fn layer(view_proj: DMat4, mut params: [f32; 4], resolution: u32, array_side: u32) -> ShadowLayerPlan {
    params[2] = resolution as f32;
    params[3] = resolution as f32 / array_side as f32;
    ShadowLayerPlan { view_proj: view_proj.as_mat4().to_cols_array_2d(), params, sphere: [0.0; 4], pcss: [0.0; 4] }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cascades_cover_the_view_in_order() {
        let scene = crate::declarations::scene::Scene::load("default", None, "t", "k").unwrap();
        let mut sun = scene.lights[0].clone();
        sun.kind = LightKind::Directional;
        sun.direction = [0.3, -1.0, 0.2];
        for p in crate::pipelines::Pipeline::ALL {
            let cascades = p.shadow_cascades();
            let view = CascadeView { camera: &scene.camera, aspect: 1.0, cascades: &cascades };
            let layers =
                light_layers(&sun, Default::default(), (1024, 1024), (DVec3::splat(-5.0), DVec3::splat(5.0)), &view);
            assert_eq!(layers.len(), cascades.splits.len());
            // Each sphere holds the point on the view axis at its slice's far edge, and they grow.
            let eye = DVec3::from(scene.camera.position);
            let fwd = (DVec3::from(scene.camera.target) - eye).normalize();
            for (l, split) in layers.iter().zip(&cascades.splits) {
                let c = DVec3::new(l.sphere[0] as f64, l.sphere[1] as f64, l.sphere[2] as f64);
                let at = eye + fwd * (split * cascades.max_distance * 0.999);
                assert!((at - c).length() <= l.sphere[3] as f64 * 1.0001, "{p:?}");
            }
            assert!(layers.windows(2).all(|w| w[1].sphere[3] > w[0].sphere[3]), "{p:?}");
        }
    }

    #[test]
    fn a_point_light_has_six_faces_each_seeing_its_axis() {
        let scene = crate::declarations::scene::Scene::load("default", None, "t", "k").unwrap();
        let light = &scene.lights[scene.key_light().unwrap()];
        let cascades = crate::pipelines::Pipeline::Hdrp.shadow_cascades();
        let view = CascadeView { camera: &scene.camera, aspect: 1.0, cascades: &cascades };
        let layers =
            light_layers(light, Default::default(), (512, 512), (DVec3::splat(-5.0), DVec3::splat(5.0)), &view);
        assert_eq!(layers.len(), 6);
        let eye = DVec3::from(light.position);
        for (face, dir) in [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z].iter().enumerate() {
            let m = glam::Mat4::from_cols_array_2d(&layers[face].view_proj).as_dmat4();
            let clip = m * (eye + *dir * 2.0).extend(1.0);
            let ndc = clip.truncate() / clip.w;
            assert!(ndc.x.abs() < 1e-6 && ndc.y.abs() < 1e-6 && (0.0..1.0).contains(&ndc.z), "face {face}: {ndc}");
        }
    }

    #[test]
    fn cell_resolutions_follow_the_pipeline_and_clamp_to_the_layer() {
        let scene = crate::declarations::scene::Scene::load("default", None, "t", "k").unwrap();
        let mut sun = scene.lights[0].clone();
        sun.kind = LightKind::Directional;
        sun.shadow.resolution = None;
        let side = array_side(&sun, &[]);
        assert_eq!(side, 2048, "URP's main-light map is the largest default up to 1024-pixel images");
        let at = |sun: &Light, p: Pipeline, size: u32| {
            cell_resolution(p, &Default::default(), sun, &scene.camera, (size, size), side)
        };
        assert_eq!(at(&sun, Pipeline::Builtin, 256), (512, None));
        assert_eq!(at(&sun, Pipeline::Hdrp, 256), (512, None));
        assert_eq!(at(&sun, Pipeline::Urp, 256), (2048, None));
        let (clamped, note) = at(&sun, Pipeline::Builtin, 3000);
        assert_eq!(clamped, 2048);
        assert!(note.is_some_and(|n| n.contains("4096")));
        sun.shadow.resolution = Some(300);
        assert_eq!(array_side(&sun, &[]), 300);
        assert_eq!(at(&sun, Pipeline::Urp, 256).0, 300, "the scene's own resolution wins");
    }

    #[test]
    fn a_point_light_sized_by_its_projected_range_in_builtin() {
        let scene = crate::declarations::scene::Scene::load("default", None, "t", "k").unwrap();
        let mut light = scene.lights[scene.key_light().unwrap()].clone();
        light.shadow.resolution = None;
        let d = (DVec3::from(light.position) - DVec3::from(scene.camera.position)).length();
        // A range well inside the distance: the sphere covers a fraction of the image.
        light.range = d * 0.1;
        let (small, _) =
            cell_resolution(Pipeline::Builtin, &Default::default(), &light, &scene.camera, (1024, 1024), 4096);
        light.range = d * 2.0;
        let (full, _) =
            cell_resolution(Pipeline::Builtin, &Default::default(), &light, &scene.camera, (1024, 1024), 4096);
        assert_eq!(full, 512, "camera inside the range: the whole image, NextPow2(1024 × 0.5)");
        assert!(small < full, "{small} vs {full}");
    }

    fn high_fidelity() -> PipelineSettings {
        PipelineSettings { urp: crate::pipelines::settings::UrpAssetPreset::HighFidelity.asset(), ..Default::default() }
    }

    #[test]
    fn shadow_biases_follow_each_engine_per_light() {
        let scene = crate::declarations::scene::Scene::load("default", None, "t", "k").unwrap();
        let mut light = scene.lights[0].clone();
        light.shadows = true;
        light.shadow.bias = 0.05;
        light.shadow.normal_bias = 0.4;
        light.shadow.soft = true;
        light.kind = LightKind::Spot;
        let engine = PipelineSettings::default();
        // Built-in: the light's own Bias and Normal Bias.
        let b = shadow_style(Pipeline::Builtin, &engine, &light, false).unwrap();
        assert_eq!((b.bias, b.normal_bias, b.soft), (0.05, 0.4, true));
        // URP: the asset's biases, ×2.5 for soft shadows (ShadowUtils.GetShadowBias); an
        // additional light casts only where the asset lets it.
        let u = shadow_style(Pipeline::Urp, &engine, &light, true).unwrap();
        let k = if u.soft { 2.5 } else { 1.0 };
        assert_eq!((u.bias, u.normal_bias), (engine.urp.depth_bias * k, engine.urp.normal_bias * k));
        assert!(shadow_style(Pipeline::Urp, &engine, &light, false).is_err(), "additional-light shadows off");
        // HDRP: HDAdditionalLightData's normal bias 0.75 texel, its slope bias as half a texel.
        let h = shadow_style(Pipeline::Hdrp, &engine, &light, false).unwrap();
        assert_eq!((h.bias, h.normal_bias), (0.5, 0.75));
        // A point light has no normal bias in built-in (Shadows.cpp) and URP, which follows it.
        let mut point = light.clone();
        point.kind = LightKind::Point;
        let b = shadow_style(Pipeline::Builtin, &engine, &point, false).unwrap();
        assert_eq!((b.bias, b.normal_bias), (0.05, 0.0));
        let urp_point = shadow_style(Pipeline::Urp, &high_fidelity(), &point, false).unwrap();
        assert_eq!(urp_point.normal_bias, 0.0);
        assert!(urp_point.bias > 0.0);
        assert_eq!(shadow_style(Pipeline::Hdrp, &engine, &point, false).unwrap().normal_bias, 0.75);
    }

    #[test]
    fn a_cutout_clips_its_shadow_and_builtins_fade_and_transparent_dither_theirs() {
        use crate::pipelines::surface::SurfaceType;
        let at = |kind, alpha, textured| {
            let surface = SurfaceOptions { kind, alpha, cutoff: 0.5 };
            Pipeline::ALL.map(|p| subject_caster(p, &surface, textured, 0.2))
        };
        assert_eq!(at(SurfaceType::Cutout, 0.8, true), [SubjectCaster::AlphaClipped { cutoff: 0.5 }; 3]);
        assert_eq!(at(SurfaceType::Cutout, 0.3, false), [SubjectCaster::Nothing; 3]);
        assert_eq!(at(SurfaceType::Cutout, 0.8, false), [SubjectCaster::Opaque; 3]);
        assert_eq!(at(SurfaceType::Opaque, 0.3, true), [SubjectCaster::Opaque; 3]);
        // Built-in: UnityStandardShadow.cginc dithers Fade by alpha and Transparent by the alpha
        // PreMultiplyAlpha outputs; URP and HDRP transparent Lit cast opaque shadows.
        for textured in [false, true] {
            let [b, u, h] = at(SurfaceType::Fade, 0.3, textured);
            assert_eq!(b, SubjectCaster::Dithered { reflectivity: 0.0 });
            let [b, ..] = at(SurfaceType::Transparent, 0.3, textured);
            assert_eq!(b, SubjectCaster::Dithered { reflectivity: 0.2 });
            assert_eq!([u, h], [SubjectCaster::Opaque; 2]);
            for kind in [SurfaceType::Transparent, SurfaceType::Premultiply, SurfaceType::Additive] {
                let [_, u, h] = at(kind, 0.3, textured);
                assert_eq!([u, h], [SubjectCaster::Opaque; 2], "{kind:?}");
            }
        }
    }

    #[test]
    fn the_dither_keeps_the_share_of_each_block_its_alpha_slice_names() {
        for (alpha, kept) in [(0.0, 0), (0.05, 0), (0.35, 5), (0.5, 7), (0.75, 12), (0.99, 15), (1.0, 16)] {
            let n =
                (0..4).flat_map(|y| (0..4).map(move |x| (x, y))).filter(|&(x, y)| dither_keeps(x, y, alpha)).count();
            assert_eq!(n, kept, "alpha {alpha}");
        }
    }
}

/// How the subject casts into the shadow maps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SubjectCaster {
    /// Every fragment casts.
    Opaque,
    /// Fragments whose alpha (its alpha map's × the base alpha) is below `cutoff` are clipped.
    AlphaClipped { cutoff: f64 },
    /// Fragments cast by a 4×4 dither of their alpha, so the shadow lets 1 − alpha through
    /// (built-in's semitransparent shadows, `dither_keeps`); the alpha is PreMultiplyAlpha's
    /// 1 − (1 − alpha)(1 − `reflectivity`), which is alpha itself for Fade (`reflectivity` 0).
    Dithered { reflectivity: f64 },
    /// Nothing casts: a flat cutout whose alpha is below its cutoff clips all of itself (neither
    /// drawn nor casting).
    Nothing,
}

/// How the subject of `surface` (wearing a textured preset where `textured`) casts in `pipeline`;
/// `reflectivity`: 1 − oneMinusReflectivity of its material (`SurfaceTwin::reflectivity`).
/// - A cutout is clipped at its cutoff by every engine's ShadowCaster pass: built-in Standard's
///   (UnityStandardShadow.cginc, `clip(alpha - _Cutoff)` under _ALPHATEST_ON), URP Lit's
///   (ShadowCasterPass.hlsl, `Alpha(...)` clipping under _ALPHATEST_ON) and HDRP Lit's
///   (ShaderPassShadow with `_ALPHATEST_ON`); a flat cutout has one alpha, so it casts whole or
///   not at all.
/// - Built-in Fade (_ALPHABLEND_ON) and Transparent (_ALPHAPREMULTIPLY_ON): fragShadowCaster
///   (UnityStandardShadow.cginc, 2019.4) takes PreMultiplyAlpha's outModifiedAlpha under
///   _ALPHAPREMULTIPLY_ON and, with UNITY_USE_DITHER_MASK_FOR_ALPHABLENDED_SHADOWS (Graphics
///   tier settings' Semitransparent Shadows, on for desktop tiers), clips
///   `tex3D(_DitherMaskLOD, float3(vpos.xy*0.25, alpha*0.9375)).a - 0.01`.
/// - URP and HDRP transparent Lit cast opaque shadows: their ShadowCaster passes clip only under
///   _ALPHATEST_ON.
pub fn subject_caster(
    pipeline: Pipeline,
    surface: &SurfaceOptions,
    textured: bool,
    reflectivity: f64,
) -> SubjectCaster {
    use crate::pipelines::surface::SurfaceType;
    match (surface.kind, pipeline, textured) {
        (SurfaceType::Cutout, _, true) => SubjectCaster::AlphaClipped { cutoff: surface.cutoff },
        (SurfaceType::Cutout, _, false) if surface.alpha < surface.cutoff => SubjectCaster::Nothing,
        (SurfaceType::Fade, Pipeline::Builtin, _) => SubjectCaster::Dithered { reflectivity: 0.0 },
        (SurfaceType::Transparent, Pipeline::Builtin, _) => SubjectCaster::Dithered { reflectivity },
        _ => SubjectCaster::Opaque,
    }
}

/// The 4×4 ordered (Bayer) dither matrix: each texel's rank in the order the block fills.
pub const DITHER_4X4: [[u32; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// Whether the shadow-map texel (`x`, `y`) of a dithered caster of `alpha` casts: Unity's
/// `_DitherMaskLOD` is 4×4×16, read at vpos/4 and depth alpha·0.9375, so a caster's alpha picks
/// slice ⌊15·alpha⌋ of 16 (nearest). APPROXIMATED: the slices' own patterns are the engine's
/// texture, not published; here slice s keeps the texels of the Bayer matrix whose rank r has
/// (r + ½)/16 < s/15, so slice 0 keeps none, slice 15 all, and slice s about s/15 of each block.
/// The WGSL twin is shadow.wgsl's `dither_keeps`.
pub fn dither_keeps(x: u32, y: u32, alpha: f64) -> bool {
    let slice = (15.0 * alpha.clamp(0.0, 1.0)).floor();
    (DITHER_4X4[(y % 4) as usize][(x % 4) as usize] as f64 + 0.5) / 16.0 < slice / 15.0
}
