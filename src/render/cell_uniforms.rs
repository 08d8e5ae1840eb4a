//! A cell's plan written into the frame and object uniforms and the light and shadow buffers:
//! conversions to the GPU layouts, no decisions (`plan::cell::CellPlan` made them).

use bytemuck::Zeroable;
use glam::DVec3;

use super::passes::shadow::shadow_slot;
use super::prepared::PreparedScene;
use crate::declarations::scene::{LightKind, Role};
use crate::plan::cell::{CellParams, CellPlan};
use crate::plan::lights::{sh_of_light, LightMode};
use crate::render::uniforms::*;
use crate::shading::registry::Sliders;
use crate::shading::ShaderModel;

/// Write the frame and object uniforms and the light and shadow buffers of `plan`.
pub(in crate::render) fn write_uniforms(
    queue: &wgpu::Queue,
    prepared: &PreparedScene,
    cell: &CellParams,
    plan: &CellPlan,
    fixed_model: &ShaderModel,
    baked: Option<&crate::render::gi::BakedLighting>,
) -> WrittenFrame {
    let (gpu_lights, colors) = gpu_lights(cell, plan);
    let sh = &prepared.shadows;
    let shadow_layers: Vec<ShadowLayer> = plan.shadow_layers.iter().map(ShadowLayer::from).collect();
    if !gpu_lights.is_empty() {
        queue.write_buffer(&prepared.lights_buffer, 0, bytemuck::cast_slice(&gpu_lights));
    }
    if !plan.used_layers.is_empty() {
        queue.write_buffer(&sh.layers_storage, 0, bytemuck::cast_slice(&shadow_layers));
        let mut slots = vec![0u8; (sh.layer_stride as usize) * shadow_layers.len()];
        for (i, layer) in shadow_layers.iter().enumerate() {
            let at = i * sh.layer_stride as usize;
            slots[at..at + 64].copy_from_slice(bytemuck::bytes_of(&layer.view_proj));
        }
        queue.write_buffer(&sh.layer_uniforms, 0, &slots);
    }
    let modes: Vec<u32> = plan.assignment.iter().flat_map(|o| o.lights.iter().map(|u| u.mode.shader_value())).collect();
    if !modes.is_empty() {
        queue.write_buffer(&prepared.modes_buffer, 0, bytemuck::cast_slice(&modes));
    }
    let frame = frame_uniforms(prepared, cell, plan, fixed_model);
    queue.write_buffer(&prepared.frame_buffer, 0, bytemuck::bytes_of(&frame));
    let ambient = ObjectAmbient::of(prepared, cell, plan, &colors, baked);
    let (objects, materials) = object_uniforms(prepared, cell, plan, fixed_model, &ambient);
    queue.write_buffer(&prepared.object_buffer, 0, &objects);
    let written = (&frame, &gpu_lights[..], &shadow_layers[..], &modes[..], &objects[..]);
    let (shadow_key, key, layer_key, prepass_key) = frame_keys(prepared, cell, plan, written);
    WrittenFrame { frame, lights: gpu_lights, capture_key: key, materials, shadow_key, layer_key, prepass_key }
}

/// The lights as the passes read them, and each light's radiance in the pipeline's units.
fn gpu_lights(cell: &CellParams, plan: &CellPlan) -> (Vec<GpuLight>, Vec<DVec3>) {
    let p = cell.pipeline;
    let lights = &plan.lights;
    let mut gpu_lights = Vec::with_capacity(lights.len());
    let mut colors = Vec::with_capacity(lights.len());
    for ((l, shadow), terms) in lights.iter().zip(&plan.light_shadows).zip(&plan.light_terms) {
        let emitter = l.emitter();
        let outer = (l.spot_angle_deg * 0.5).to_radians();
        let inner = l
            .inner_spot_angle_deg
            .map(|a| (a * 0.5).to_radians())
            .unwrap_or_else(|| p.default_inner_spot_half_angle(outer));
        let color = DVec3::from(l.radiance(p, l.intensity, &cell.settings.engine)) * terms.dimmer;
        colors.push(color);
        let (shadow, mut shadow_bias) = shadow_slot(shadow);
        // shadow_bias.z: how a dynamic object's probe occlusion meets its real-time shadow.
        shadow_bias[2] = plan.probe_occlusion.shader_value() as f32;
        let mut params = [l.range as f32, outer.cos() as f32, inner.cos() as f32, emitter.hdrp_min_roughness() as f32];
        let mut shape = [0.0; 4];
        if l.is_area() {
            // params: range, half width, half height (a disc: its radius twice); shape: right, drawn
            let (half_w, half_h) = match emitter {
                crate::pipelines::Emitter::Rect { width, height } => (width * 0.5, height * 0.5),
                crate::pipelines::Emitter::Disc { radius } => (radius, radius),
                _ => unreachable!("an area light's emitter"),
            };
            params = [l.range as f32, half_w as f32, half_h as f32, 0.0];
            let drawn = crate::plan::lights::draws_area(p, l);
            shape = vec4(l.area_frame().1, if drawn { 1.0 } else { 0.0 });
        }
        let (features, projector) = light_features(terms, l.spot_angle_deg);
        if let Some((half_w, half_h)) = projector {
            params[1] = half_w as f32;
            params[2] = half_h as f32;
            shape = vec4(crate::declarations::area_light::area_frame(l.direction).1, 0.0);
        }
        let slot = gpu_lights.len();
        // color.w: how the light reaches the frame under the bake (plan::gi::RealtimeOnBake).
        let bake_flag = plan.gi.as_ref().map_or(0.0, |g| g.realtime_on_bake(slot).shader_value());
        gpu_lights.push(GpuLight {
            position: vec4(DVec3::from(l.position), emitter.shader_kind() as f64),
            direction: vec4(DVec3::from(l.direction).normalize_or_zero(), 0.0),
            color: vec4(color, bake_flag),
            params,
            shadow,
            shadow_bias,
            shape,
            features,
            shadow_tint: vec4(DVec3::from(terms.shadow_tint), 0.0),
        });
    }
    (gpu_lights, colors)
}

/// A light's `features` (uniforms::GpuLight) and its projector's half-size (a pyramid's at unit
/// distance, a box's in metres).
fn light_features(t: &crate::plan::light_terms::LightTerms, spot_angle_deg: f64) -> ([f32; 4], Option<(f64, f64)>) {
    use crate::pipelines::hdrp_light::{projector_extents, SpotShape};
    let tint_mode = match (t.tints_shadow(), t.penumbra_tint) {
        (false, _) => 0.0,
        (true, false) => 1.0,
        (true, true) => 2.0,
    };
    let shape_flag = match t.shape {
        SpotShape::Cone => 0,
        SpotShape::Pyramid { .. } => 2,
        SpotShape::Box { .. } => 4,
    };
    let flags = shape_flag | if t.range_attenuation { 0 } else { 1 };
    let on = |b: bool| if b { 1.0 } else { 0.0 };
    ([on(t.affect_diffuse), on(t.affect_specular), tint_mode, flags as f32], projector_extents(t.shape, spot_angle_deg))
}

/// Each object's ambient light: the lights folded into its SH, where its indirect light comes
/// from (the bake's where it reaches the object, else the sky's), and the bake's flags.
struct ObjectAmbient {
    sh_per_object: Vec<[[f32; 4]; 9]>,
    level_sh: Vec<[[f32; 4]; 9]>,
    sources: Vec<crate::render::gi::AmbientSource>,
    level_sources: Vec<crate::render::gi::AmbientSource>,
    subtractive: bool,
    encoding: f32,
    shadow_color: [f32; 4],
}

impl ObjectAmbient {
    fn of(
        prepared: &PreparedScene,
        cell: &CellParams,
        plan: &CellPlan,
        colors: &[DVec3],
        baked: Option<&crate::render::gi::BakedLighting>,
    ) -> ObjectAmbient {
        let p = cell.pipeline;
        let (lights, assignment) = (&plan.lights, &plan.assignment);
        // Lights folded into an object's SH: a directional light from its direction, a point or
        // spot from the object's centre with its attenuation there, in the ambient term's units.
        let sh_per_object: Vec<[[f32; 4]; 9]> = assignment
            .iter()
            .zip(&prepared.layout.object_centres)
            .map(|(o, (_, centre))| {
                let mut sh = [DVec3::ZERO; 9];
                for u in o.lights.iter().filter(|u| u.mode == LightMode::Sh) {
                    let l = &lights[u.light];
                    let color = colors[u.light];
                    let (dir, atten) = match l.kind {
                        LightKind::Directional => (-DVec3::from(l.direction), 1.0),
                        _ => {
                            let to = DVec3::from(l.position) - *centre;
                            (to, p.attenuation().eval(to.length(), l.range))
                        }
                    };
                    let scale = crate::shading::twin::irradiance_per_intensity(p) / std::f64::consts::PI;
                    for (acc, c) in sh.iter_mut().zip(sh_of_light(dir, color * atten * scale)) {
                        *acc += c;
                    }
                }
                sh.map(|c| [c.x as f32, c.y as f32, c.z as f32, 0.0])
            })
            .collect();
        // Each scene object's ambient: the bake's where it reaches the object (render::gi), else the sky's.
        let grid = prepared.scene.gi.as_ref().and_then(|g| g.probes.as_ref());
        let sources: Vec<crate::render::gi::AmbientSource> = prepared
            .layout
            .object_centres
            .iter()
            .zip(&prepared.scene.objects)
            .zip(0..)
            .map(|(((_, centre), o), i)| match (baked, o.role) {
                (Some(b), Role::Subject) => b.dynamic_ambient(grid, *centre),
                (Some(b), Role::Fixed)
                    if b.lightmap.is_some() && prepared.lightmap.as_ref().is_some_and(|a| a.lightmapped[i]) =>
                {
                    crate::render::gi::AmbientSource::Lightmap { directional: b.directional }
                }
                _ => crate::render::gi::AmbientSource::Sky,
            })
            .collect();
        // LOD levels past the first are not unwrapped: a dynamic object's levels read its probe, and a
        // static object's the probes at its centre (Unity lights lower LODs' indirect light from the
        // probes; their baked direct light is not drawn), or the sky without a grid.
        let level_sources: Vec<crate::render::gi::AmbientSource> = prepared
            .layout
            .object_centres
            .iter()
            .zip(&prepared.scene.objects)
            .zip(&sources)
            .map(|(((_, centre), o), own)| match (baked, o.role) {
                (Some(_), Role::Subject) => own.clone(),
                (Some(b), Role::Fixed) => b.dynamic_ambient(grid, *centre),
                (None, _) => crate::render::gi::AmbientSource::Sky,
            })
            .collect();
        // Subtractive: the main directional light's real-time shadow darkens the lightmaps, down to
        // the Realtime Shadow Color (SubtractMainLightWithRealtimeAttenuationFromLightmap).
        let subtractive =
            plan.gi.as_ref().is_some_and(|g| g.mixed_lighting == crate::declarations::gi::MixedLighting::Subtractive);
        // How the lightmap holds its light (Object.bake.z, scene.wgsl `lightmap_gi`)
        let encoding = plan
            .gi
            .as_ref()
            .map_or(0.0, |g| crate::render::gi::lightmaps::LightmapEncoding::of_quality(g.encoding).shader_value());
        let shadow_color = prepared.scene.gi.as_ref().map_or([0.0; 4], |g| {
            let c = g.realtime_shadow_color.map(crate::color::srgb_to_linear);
            [c[0] as f32, c[1] as f32, c[2] as f32, 0.0]
        });
        // The probe's SH is in the frame's units already (the sky's scale is in its light).
        let with_probe = |sh: &[[f32; 4]; 9], source: &crate::render::gi::AmbientSource| {
            let mut sh = *sh;
            if let crate::render::gi::AmbientSource::Probe(probe) = source {
                for (c, p) in sh.iter_mut().zip(&probe.sh) {
                    for k in 0..3 {
                        c[k] += p[k] as f32;
                    }
                }
            }
            sh
        };
        let level_sh: Vec<[[f32; 4]; 9]> =
            sh_per_object.iter().zip(&level_sources).map(|(sh, s)| with_probe(sh, s)).collect();
        let sh_per_object: Vec<[[f32; 4]; 9]> =
            sh_per_object.iter().zip(&sources).map(|(sh, s)| with_probe(sh, s)).collect();
        ObjectAmbient { sh_per_object, level_sh, sources, level_sources, subtractive, encoding, shadow_color }
    }
}

/// The frame's uniforms: camera, light counts, the environment, the subject's and the fixed
/// objects' materials, and the probes (slot 0 until the capture picks theirs).
fn frame_uniforms(
    prepared: &PreparedScene,
    cell: &CellParams,
    plan: &CellPlan,
    fixed_model: &ShaderModel,
) -> FrameUniforms {
    let p = cell.pipeline;
    let (camera, lights) = (&plan.camera, &plan.lights);
    let vp = crate::plan::camera::view_projection(camera, plan.aspect);
    let mut frame = FrameUniforms::zeroed();
    frame.view_proj = mat(vp);
    frame.inv_view_proj = mat(vp.inverse());
    frame.camera_pos = vec4(DVec3::from(camera.position), 1.0);
    // z: HDRP's deferred Lit folds its occlusion into the baked light (plan::ao::AoUse::in_bake);
    // w: the share of URP's SSAO the direct light takes (its DirectLightingStrength).
    let direct = plan.ao.direct_lighting_strength() as f32;
    frame.screen = [cell.width as f32, cell.height as f32, plan.ao.in_bake as u32 as f32, direct];
    let (tiles_x, _, words) = crate::render::passes::light_tiles::tile_grid(cell.width, cell.height, lights.len());
    frame.counts = [lights.len() as u32, plan.main_light.map_or(0, |slot| slot as u32 + 1), words, tiles_x];
    for (dst, src) in frame.sh.iter_mut().zip(prepared.env.sh.iter()) {
        *dst = [src[0] as f32, src[1] as f32, src[2] as f32, 0.0];
    }
    let env_levels = match &prepared.probes {
        Some(_) => crate::environment::prefilter::LEVELS,
        None => prepared.env.probe.levels.len(),
    };
    let ambient = cell.settings.ambient_intensity.unwrap_or(1.0);
    frame.env = [(env_levels - 1) as f32, (prepared.env.intensity * p.environment_scale() * ambient) as f32, 0.0, 0.0];
    frame.subject = gpu_material(&cell.surface, GpuMaterial::zeroed());
    frame.subject.params[3] = if cell.settings.material_maps.is_some() { 1.0 } else { 0.0 };
    frame.subject.base_color[3] = cell.settings.surface.alpha as f32;
    frame.subject.specular[3] = cell.settings.surface.clip_threshold() as f32;
    if let Some(w) = cell.settings.carried_workflow.filter(|_| cell.settings.material_maps.is_some()) {
        // Maps may vary the metallic: the shaders carry the workflow over texel by texel
        // (scene.wgsl `carried_specular`) from the metallic workflow's values and the F0.
        let c = w.base_color.as_vec3();
        frame.subject.base_color = [c.x, c.y, c.z, frame.subject.base_color[3]];
        frame.subject.params[0] = w.metallic as f32;
        let f0 = w.dielectric.as_vec3();
        frame.subject.specular = [f0.x, f0.y, f0.z, frame.subject.specular[3]];
        frame.subject.checker_color[3] = 1.0;
    }
    if cell.model.emits() {
        // Emissive radiance: the subject's colour (or own emissive colour) × the axis, in the
        // pipeline's light units.
        let colour = cell.settings.emission_color.map(DVec3::from).unwrap_or(cell.surface.base_color);
        let e = colour * cell.settings.emission * p.intensity_scale();
        frame.subject.emission = [e.x as f32, e.y as f32, e.z as f32, 0.0];
    }
    // emission.w: Source = Albedo Alpha (scene.wgsl `Material`), where the subject has maps to read.
    let from_albedo = cell.settings.material_maps.is_some() && cell.model.smoothness_from_albedo_alpha(&cell.surface);
    frame.subject.emission[3] = if from_albedo { 1.0 } else { 0.0 };
    let any = Sliders { base_color_linear: [1.0; 3], metallic: 0.0, smoothness: 0.5 };
    frame.fixed = gpu_material(&fixed_model.surface(p, &any), GpuMaterial::zeroed());
    // The probes' capture slot is chosen after the capture key (`capture_probes`), which
    // rewrites their layers; slot 0 until then.
    if let Some(probes) = &prepared.probes {
        frame.reflection = [probes.probes.len() as u32, 0, 0, 0];
        for (k, t) in probes.probes.iter().enumerate() {
            frame.probes[k] = GpuReflectionProbe::new(&t.probe, &plan.probes[k], (k, probes.probes.len(), 0));
        }
    }
    frame
}

/// Every mesh's object uniforms (in its slot of the object buffer) and material.
fn object_uniforms(
    prepared: &PreparedScene,
    cell: &CellParams,
    plan: &CellPlan,
    fixed_model: &ShaderModel,
    a: &ObjectAmbient,
) -> (Vec<u8>, Vec<GpuMaterial>) {
    let p = cell.pipeline;
    let fades = &plan.fades;
    let mut objects = vec![0u8; (prepared.object_stride as usize) * prepared.objects.len()];
    let mut materials = Vec::with_capacity(prepared.objects.len());
    for (i, o) in prepared.objects.iter().enumerate() {
        let material = match &o.fixed {
            Some((sliders, pattern)) => {
                let mut m = gpu_material(&fixed_model.surface(p, sliders), *pattern);
                m.base_color[3] = pattern.base_color[3];
                // Emission in the pipeline's light units, as the subject's.
                let scale = p.intensity_scale() as f32;
                m.emission = [m.emission[0] * scale, m.emission[1] * scale, m.emission[2] * scale, 0.0];
                m
            }
            None => GpuMaterial::zeroed(),
        };
        materials.push(material);
        let slot = &prepared.layout.meshes[i];
        // The scene's own meshes come first, then the further LOD levels.
        let first_level = i < prepared.scene.objects.len();
        let source = if first_level { &a.sources[slot.scene_index] } else { &a.level_sources[slot.scene_index] };
        let u = ObjectUniforms {
            model: mat(o.model),
            normal_matrix: mat(o.model.inverse().transpose()),
            material,
            flags: match slot.role {
                Role::Subject => [1, ROLE_SUBJECT as u32, slot.scene_index as u32, o.receive_shadows as u32],
                Role::Fixed => [0, ROLE_FIXED as u32, slot.scene_index as u32, o.receive_shadows as u32],
            },
            light_sh: if first_level { a.sh_per_object[slot.scene_index] } else { a.level_sh[slot.scene_index] },
            // A level fading in or out keeps its dither's share of the fragments.
            lod: match fades[i] {
                Some(f) if f < 1.0 => [f as f32, 1.0, 0.0, 0.0],
                _ => [1.0, 0.0, 0.0, 0.0],
            },
            bake: [source.shader_value(), source.flags(a.subtractive), a.encoding, 0.0],
            occlusion: match source {
                crate::render::gi::AmbientSource::Probe(p) => p.occlusion.map(|v| v as f32),
                _ => [1.0; 4],
            },
            reflection_probe: [plan.renderer_probes[i].map_or(0, |k| k as u32 + 1), 0, 0, 0],
            shadow_color: a.shadow_color,
        };
        let at = i * prepared.object_stride as usize;
        objects[at..at + std::mem::size_of::<ObjectUniforms>()].copy_from_slice(bytemuck::bytes_of(&u));
    }
    (objects, materials)
}

/// The hashes of what the shadow pass, a probe capture, the fixed-object layer and the depth
/// prepass read of the written frame (`WrittenFrame`).
fn frame_keys(
    prepared: &PreparedScene,
    cell: &CellParams,
    plan: &CellPlan,
    (frame, gpu_lights, shadow_layers, modes, objects): (&FrameUniforms, &[GpuLight], &[ShadowLayer], &[u32], &[u8]),
) -> (u64, u64, u64, u64) {
    let p = cell.pipeline;
    let fades = &plan.fades;
    let shadow_key = {
        use std::hash::{Hash, Hasher};
        let mut h = std::hash::DefaultHasher::new();
        plan.used_layers.hash(&mut h);
        plan.dynamic_casters_only.hash(&mut h);
        bytemuck::cast_slice::<ShadowLayer, u8>(shadow_layers).hash(&mut h);
        for (i, o) in prepared.objects.iter().enumerate() {
            let at = i * prepared.object_stride as usize;
            (prepared.layout.meshes[i].cast_shadows, o.index_count, fades[i].map(f64::to_bits)).hash(&mut h);
            objects[at..at + 64].hash(&mut h);
        }
        // The subject's alpha reaches its shadow where it clips or dithers it (passes::shadow).
        if plan.subject_caster != crate::plan::shadows::SubjectCaster::Opaque {
            format!("{:?}", plan.subject_caster).hash(&mut h);
            (cell.settings.material_maps, [frame.subject.base_color[3], frame.subject.specular[3]].map(f32::to_bits))
                .hash(&mut h);
        }
        h.finish()
    };
    // What a probe capture sees: everything but the camera and the subject, whose shadow it
    // does see (its shadow pass is the cell's: `shadow_key`, which meshes cast included).
    let key = {
        use std::hash::{Hash, Hasher};
        let mut h = std::hash::DefaultHasher::new();
        p.name().hash(&mut h);
        shadow_key.hash(&mut h);
        let mut seen = *frame;
        (seen.view_proj, seen.inv_view_proj, seen.camera_pos) = Default::default();
        seen.subject = GpuMaterial::zeroed();
        bytemuck::bytes_of(&seen).hash(&mut h);
        bytemuck::cast_slice::<GpuLight, u8>(gpu_lights).hash(&mut h);
        bytemuck::cast_slice::<ShadowLayer, u8>(shadow_layers).hash(&mut h);
        modes.hash(&mut h);
        for (i, o) in
            prepared.objects.iter().enumerate().filter(|(i, _)| prepared.layout.meshes[*i].role == Role::Fixed)
        {
            let at = i * prepared.object_stride as usize;
            objects[at..at + std::mem::size_of::<ObjectUniforms>()].hash(&mut h);
            o.index_count.hash(&mut h);
        }
        h.finish()
    };
    // What the fixed objects' shading reads: all a probe capture sees (`key`: everything but the
    // camera and the subject) and the camera.
    let layer_key = {
        use std::hash::{Hash, Hasher};
        let mut h = std::hash::DefaultHasher::new();
        key.hash(&mut h);
        for part in [bytemuck::bytes_of(&frame.view_proj), bytemuck::bytes_of(&frame.inv_view_proj)] {
            part.hash(&mut h);
        }
        bytemuck::bytes_of(&frame.camera_pos).hash(&mut h);
        h.finish()
    };
    // What the depth prepass and SSAO read: the camera, the target's size and every mesh's
    // transform and LOD fade, and a cutout subject's alpha and cutoff (other materials and the
    // lights do not reach them).
    let prepass_key = {
        use std::hash::{Hash, Hasher};
        let mut h = std::hash::DefaultHasher::new();
        for part in [bytemuck::bytes_of(&frame.view_proj), bytemuck::bytes_of(&frame.inv_view_proj)] {
            part.hash(&mut h);
        }
        // The target's size, not how the lighting reads the occlusion.
        bytemuck::bytes_of(&[
            frame.camera_pos[0],
            frame.camera_pos[1],
            frame.camera_pos[2],
            frame.screen[0],
            frame.screen[1],
        ])
        .hash(&mut h);
        [frame.subject.base_color[3], frame.subject.specular[3]].map(f32::to_bits).hash(&mut h);
        for (i, o) in prepared.objects.iter().enumerate() {
            let at = i * prepared.object_stride as usize;
            o.index_count.hash(&mut h);
            objects[at..at + std::mem::size_of::<ObjectUniforms>()].hash(&mut h);
        }
        h.finish()
    };
    (shadow_key, key, layer_key, prepass_key)
}

/// What writing a cell's uniforms made: the frame written, the hash of what a probe capture
/// would see of it, each mesh's material, and the hash of what the shadow pass's depth depends on.
pub(in crate::render) struct WrittenFrame {
    pub(in crate::render) frame: FrameUniforms,
    /// The lights as the passes read them.
    pub(in crate::render) lights: Vec<GpuLight>,
    pub(in crate::render) capture_key: u64,
    /// Each mesh's material as its model receives it (zero for the subject: it reads the frame's).
    pub(in crate::render) materials: Vec<GpuMaterial>,
    /// Everything the shadow pass's depth depends on: the layers' matrices and resolutions, which
    /// meshes cast, and their transforms and fades (materials and the camera do not reach it).
    pub(in crate::render) shadow_key: u64,
    /// Everything the fixed objects' forward shading reads of the uniforms and storage buffers
    /// (passes::forward's layer); the renderer adds the passes' own keys.
    pub(in crate::render) layer_key: u64,
    /// Everything the depth prepass's depth and normals read of the uniforms.
    pub(in crate::render) prepass_key: u64,
}

#[cfg(test)]
mod tests {
    use super::light_features;
    use crate::pipelines::hdrp_light::SpotShape;
    use crate::plan::light_terms::LightTerms;

    /// A frame compiled without HDRP's light terms (`LightPaths::hdrp_terms` false) reads none of
    /// `features`: that is right only where every light's features are the common light's.
    #[test]
    fn lights_without_the_hdrp_path_have_the_common_features() {
        let common = LightTerms {
            light: 0,
            shape: SpotShape::Cone,
            affect_diffuse: true,
            affect_specular: true,
            range_attenuation: true,
            dimmer: 1.0,
            shadow_dimmer: 1.0,
            shadow_tint: [0.0; 3],
            penumbra_tint: false,
        };
        let variants = [
            LightTerms { dimmer: 0.25, shadow_dimmer: 0.5, ..common.clone() },
            LightTerms { affect_diffuse: false, ..common.clone() },
            LightTerms { affect_specular: false, ..common.clone() },
            LightTerms { range_attenuation: false, ..common.clone() },
            LightTerms { shape: SpotShape::Pyramid { aspect_ratio: 2.0 }, ..common.clone() },
            LightTerms { shape: SpotShape::Box { width: 1.0, height: 0.5 }, ..common.clone() },
            LightTerms { shadow_tint: [0.2, 0.0, 0.0], ..common.clone() },
            LightTerms { penumbra_tint: true, ..common.clone() },
        ];
        let neutral = light_features(&common, 30.0).0;
        assert_eq!(neutral, [1.0, 1.0, 0.0, 0.0]);
        for t in std::iter::once(&common).chain(&variants) {
            let (features, _) = light_features(t, 30.0);
            assert_eq!(!t.needs_shader_path(), features == neutral, "{t:?}: {features:?}");
        }
    }
}
