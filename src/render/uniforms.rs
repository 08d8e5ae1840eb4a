//! CPU mirrors of the uniform structs in shaders/pass/scene.wgsl, each checked member by member
//! against the WGSL as naga lays it out (`gpu::layout`, tests/e2e/layouts.rs).

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, Mat4};

use crate::shading::twin::Surface;

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuLight {
    pub position: [f32; 4],
    pub direction: [f32; 4],
    pub color: [f32; 4],
    pub params: [f32; 4],
    /// First shadow layer (−1: none), layer count, strength, soft (plan::shadows).
    pub shadow: [f32; 4],
    /// Bias and normal bias in shadow-map texels; z how a dynamic object's probe occlusion meets
    /// the shadow (plan::gi); w HDRP's filter: the tent's width n (0: none; plan::shadows::hdrp_tent)
    /// or −1, PCSS.
    pub shadow_bias: [f32; 4],
    /// Area lights: their right axis, and w = 1 where the frame's passes draw the light (an HDRP
    /// rect), 0 where only the truth sees it (plan::lights::area_left_out).
    pub shape: [f32; 4],
    /// HDRP's light terms (plan::light_terms): affect diffuse and specular (0 or 1), the shadow's
    /// tint mode (0 none, 1 tint, 2 penumbra tint), and flags: 1 range attenuation off, 2 pyramid,
    /// 4 box (params.yz then hold the projector's half-size, shape.xyz its right axis).
    pub features: [f32; 4],
    /// The shadow tint (linear).
    pub shadow_tint: [f32; 4],
}

/// One shadow-map layer: its view-projection and (texel size: world units for orthographic, per
/// unit of view depth for perspective; 1 = perspective; the map's resolution; the share of the
/// layer's side it fills from the top-left).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct ShadowLayer {
    pub view_proj: [[f32; 4]; 4],
    pub params: [f32; 4],
    /// A directional cascade's bounding sphere (centre, radius): the points it shadows.
    pub sphere: [f32; 4],
    /// HDRP's PCSS terms of the layer (`plan::shadows::hdrp_pcss`; zero where it is not drawn).
    pub pcss: [f32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuMaterial {
    pub base_color: [f32; 4],
    pub params: [f32; 4],
    pub checker_color: [f32; 4],
    pub specular: [f32; 4],
    pub model0: [f32; 4],
    pub model1: [f32; 4],
    pub model2: [f32; 4],
    /// Emitted radiance (linear RGB, the pipeline's units), added before tonemapping; w: 1 where
    /// the smoothness is the albedo map's alpha × the slider (Source = Albedo Alpha).
    pub emission: [f32; 4],
}

/// A probe as the shaders read it (scene.wgsl `ReflectionProbe`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuReflectionProbe {
    /// xyz position; w: 1 for box projection, plus twice the weight rule
    /// (`plan::probes::ProbeWeight::shader_mode`).
    pub position: [f32; 4],
    /// xyz box minimum; w blend distance.
    pub box_min: [f32; 4],
    /// xyz box maximum; w the first layer of its levels.
    pub box_max: [f32; 4],
}

impl GpuReflectionProbe {
    /// Probe `index` of `count`, read as its plan says (`plan::probes`), its levels in capture
    /// slot `slot`.
    pub fn new(
        p: &crate::declarations::scene::ReflectionProbe,
        used: &crate::plan::probes::ProbeUse,
        (index, count, slot): (usize, usize, usize),
    ) -> Self {
        let v = |a: [f64; 3], w: f64| [a[0] as f32, a[1] as f32, a[2] as f32, w as f32];
        let mode = used.box_projection as u32 + 2 * used.weight.shader_mode();
        GpuReflectionProbe {
            position: v(p.position, mode as f64),
            box_min: v(p.box_min, used.weight.distance()),
            box_max: v(p.box_max, first_layer(slot, index, count) as f64),
        }
    }
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct FrameUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    pub camera_pos: [f32; 4],
    pub counts: [u32; 4],
    pub sh: [[f32; 4]; 9],
    pub env: [f32; 4],
    pub subject: GpuMaterial,
    /// The fixed model's specular colour and parameters (the G-buffer holds colour, metallic and
    /// smoothness).
    pub fixed: GpuMaterial,
    /// x: the reflection probes the shading blends (0: the sky alone).
    pub reflection: [u32; 4],
    pub probes: [GpuReflectionProbe; crate::declarations::scene::MAX_PROBES],
    /// x, y: the target's size in pixels (HDRP's _ScreenSize, for the LOD dither's seed); z 1:
    /// HDRP's deferred Lit folds its occlusion into the baked light; w: URP's SSAO direct lighting
    /// strength (plan::ao::AoUse).
    pub screen: [f32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct ObjectUniforms {
    pub model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 4],
    pub material: GpuMaterial,
    pub flags: [u32; 4],
    /// The lights this object takes as spherical harmonics (`plan::lights::sh_of_light`), in the
    /// units of the ambient term, not scaled by the environment.
    pub light_sh: [[f32; 4]; 9],
    /// x: LOD fade (`plan::lod`), y: 1 when the mesh is dithered by it.
    pub lod: [f32; 4],
    /// The bake's light at this object (render::gi::AmbientSource): x where the ambient comes
    /// from (0 the sky's SH, 1 its light probe, 2 its lightmap), y flags (1: Directional mode,
    /// 2: Subtractive's main-light shadow darkens the lightmap).
    pub bake: [f32; 4],
    /// Its probe's occlusion of each shadow-mask light (1 where it has no probe).
    pub occlusion: [f32; 4],
    /// x: 1 + the reflection probe it takes at full weight where probes are chosen per renderer
    /// (`plan::probes::renderer_probe`); 0: none.
    pub reflection_probe: [u32; 4],
    /// Subtractive's Realtime Shadow Color, linear.
    pub shadow_color: [f32; 4],
}

pub use crate::plan::roles::{ROLE_BACKGROUND, ROLE_FIXED, ROLE_SUBJECT};

/// The first array layer of probe `index`'s levels in capture slot `slot` of a scene with `count`
/// probes (the sky's seven come first).
pub fn first_layer(slot: usize, index: usize, count: usize) -> usize {
    crate::environment::prefilter::LEVELS * (1 + slot * count + index)
}

impl From<&crate::plan::shadows::ShadowLayerPlan> for ShadowLayer {
    fn from(l: &crate::plan::shadows::ShadowLayerPlan) -> ShadowLayer {
        ShadowLayer { view_proj: l.view_proj, params: l.params, sphere: l.sphere, pcss: l.pcss }
    }
}

/// A surface in the uniform layout; `pattern` carries the checkerboard, if any.
pub(in crate::render) fn gpu_material(s: &Surface, pattern: GpuMaterial) -> GpuMaterial {
    let v = |x: DVec3| [x.x as f32, x.y as f32, x.z as f32, 0.0];
    let q = s.params.map(|x| x as f32);
    GpuMaterial {
        // w: alpha (opaque); specular.w: the cutoff (0: nothing clips). The subject's are its cell's.
        base_color: [s.base_color.x as f32, s.base_color.y as f32, s.base_color.z as f32, 1.0],
        params: [s.metallic as f32, s.smoothness as f32, pattern.params[2], pattern.params[3]],
        checker_color: pattern.checker_color,
        specular: v(s.specular),
        model0: [q[0], q[1], q[2], q[3]],
        model1: [q[4], q[5], q[6], q[7]],
        model2: [q[8], q[9], q[10], q[11]],
        emission: pattern.emission,
    }
}

pub(in crate::render) fn mat(m: DMat4) -> [[f32; 4]; 4] {
    Mat4::from_cols_array(&m.to_cols_array().map(|v| v as f32)).to_cols_array_2d()
}

pub(in crate::render) fn vec4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

pub(in crate::render) fn rgba(c: [f64; 3]) -> [f32; 4] {
    [c[0] as f32, c[1] as f32, c[2] as f32, 1.0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_match_wgsl_layout() {
        assert_eq!(std::mem::size_of::<GpuLight>(), 144);
        assert_eq!(std::mem::size_of::<ShadowLayer>(), 112);
        assert_eq!(std::mem::size_of::<GpuMaterial>(), 128);
        assert_eq!(std::mem::size_of::<GpuReflectionProbe>(), 48);
        assert_eq!(std::mem::size_of::<FrameUniforms>(), 64 + 64 + 16 + 16 + 144 + 16 + 128 + 128 + 16 + 4 * 48 + 16);
        assert_eq!(std::mem::size_of::<ObjectUniforms>(), 64 + 64 + 128 + 16 + 144 + 16 + 4 * 16);
    }
}
