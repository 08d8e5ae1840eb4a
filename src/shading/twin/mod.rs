//! CPU f64 twins of the WGSL models, term by term, in the same pipeline conventions.

mod builtin;
mod classic;
mod custom;
mod hdrp;
mod lambert;
mod standard;
mod urp;
pub mod vertex_lit;

pub use builtin::{StandardBrdf2, StandardBrdf3};
pub use classic::{BlinnPhong, CookTorrance, CookTorrance1982, HalfLambert, OrenNayar, Phong};
pub use custom::{d_ggx, FresnelView, TorranceSparrow};
pub use hdrp::{
    compute_transmittance_disney, compute_wrapped_diffuse_lighting, hdrp_transmittance, TRANSMISSION_WRAP_LIGHT,
};
pub use hdrp::{
    default_light_min_roughness, gtao_multi_bounce, indirect_occlusion, specular_occlusion_from_ao, HdrpLit,
    ANISOTROPY_SLOT, COAT_MASK_SLOT, IRIDESCENCE_MASK_SLOT, IRIDESCENCE_THICKNESS_SLOT, SUBSURFACE_MASK_SLOT,
    SUBSURFACE_SLOT, THICKNESS_SLOT, TRANSMISSION_SLOT,
};
pub use lambert::Lambert;
pub use standard::Standard;
pub use urp::{SrpLit, Unlit, UrpLit, UrpSimpleLit};

use glam::DVec3;

use crate::pipelines::Pipeline;

/// How many parameters a model may have: slots 0–11, as the GPU's three vec4s carry them
/// (`Material.model0`–`model2`, the Surface's `params0`–`params2`).
pub const PARAM_SLOTS: usize = 12;

/// Material as the model receives it (metallic already converted by the pipeline). The WGSL
/// `Surface` in shaders/common/conventions.wgsl has the same fields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    pub base_color: DVec3,
    pub metallic: f64,
    pub smoothness: f64,
    /// Specular colour, for the models that take one (Phong, Blinn-Phong, Simple Lit, ...).
    pub specular: DVec3,
    /// The model's own parameters by slot (`registry::ParamSpec::slot`).
    pub params: [f64; PARAM_SLOTS],
    /// The share of the diffuse lobe kept: alpha under a premultiplied surface type
    /// (`SurfaceType::premultiplies_diffuse`), 1 else; read by the models that keep their diffuse
    /// lobe apart (WGSL: the pass's private `diffuse_weight`).
    pub diffuse_weight: f64,
    /// The shading point's world tangent (the mesh's, not yet orthogonal to the normal; zero
    /// where there is none): HDRP Lit's anisotropy reads it (`SurfaceData::tangentWS`).
    pub tangent: DVec3,
}

impl Surface {
    /// Base colour, metallic and smoothness only; no specular colour, parameters zero.
    pub fn basic(base_color: DVec3, metallic: f64, smoothness: f64) -> Surface {
        Surface {
            base_color,
            metallic,
            smoothness,
            specular: DVec3::ZERO,
            params: [0.0; PARAM_SLOTS],
            diffuse_weight: 1.0,
            tangent: DVec3::ZERO,
        }
    }

    /// Every value rounded to f32, as the GPU receives it: the twin's input for parity checks.
    pub fn rounded_f32(&self) -> Surface {
        let r = |x: DVec3| x.as_vec3().as_dvec3();
        Surface {
            base_color: r(self.base_color),
            metallic: self.metallic as f32 as f64,
            smoothness: self.smoothness as f32 as f64,
            specular: r(self.specular),
            params: self.params.map(|p| p as f32 as f64),
            diffuse_weight: self.diffuse_weight as f32 as f64,
            tangent: r(self.tangent),
        }
    }
}

/// A term split into the parts a model's WGSL wraps apart (shaders/common/conventions.wgsl):
/// `direct_diffuse(…)` / `indirect_diffuse(…)`, `direct_specular(…)` / `indirect_specular(…)`
/// and `emitted(…)`, which the term layers draw one at a time (pipelines::terms).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Lobes {
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub emitted: DVec3,
}

impl Lobes {
    pub const ZERO: Lobes = Lobes { diffuse: DVec3::ZERO, specular: DVec3::ZERO, emitted: DVec3::ZERO };

    pub fn diffuse(diffuse: DVec3) -> Lobes {
        Lobes { diffuse, ..Lobes::ZERO }
    }

    pub fn split(diffuse: DVec3, specular: DVec3) -> Lobes {
        Lobes { diffuse, specular, emitted: DVec3::ZERO }
    }

    /// The whole term, as the image draws it.
    pub fn sum(&self) -> DVec3 {
        self.diffuse + self.specular + self.emitted
    }
}

pub trait SurfaceTwin: Sync {
    /// Radiance for a light of colour 1 at attenuation 1, N·L included (WGSL `model_direct`), by lobe.
    fn direct_lobes(&self, pipeline: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> Lobes;
    /// `direct_lobes` for a light whose HDRP roughness floor (from its shape) is `min_roughness`;
    /// only HDRP Lit reads it (WGSL `light_min_roughness`).
    fn direct_lobes_for_light(
        &self,
        p: Pipeline,
        s: &Surface,
        n: DVec3,
        v: DVec3,
        l: DVec3,
        _min_roughness: f64,
    ) -> Lobes {
        self.direct_lobes(p, s, n, v, l)
    }
    /// The whole direct term.
    fn direct(&self, pipeline: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3) -> DVec3 {
        self.direct_lobes(pipeline, s, n, v, l).sum()
    }
    /// The whole direct term for a light with HDRP roughness floor `min_roughness`.
    fn direct_for_light(&self, p: Pipeline, s: &Surface, n: DVec3, v: DVec3, l: DVec3, min_roughness: f64) -> DVec3 {
        self.direct_lobes_for_light(p, s, n, v, l, min_roughness).sum()
    }
    /// A rect light's radiance per unit luminance at attenuation 1, by lobe (WGSL `model_rect`), its
    /// corners relative to the shaded point; None where the model has no area-light BSDF.
    fn rect_lobes(&self, _p: Pipeline, _s: &Surface, _n: DVec3, _v: DVec3, _corners: &[DVec3; 4]) -> Option<Lobes> {
        None
    }
    /// The direction the model fetches the prefiltered environment along (WGSL `env_specular`'s
    /// first argument), where the twin states it.
    fn env_direction(&self, _p: Pipeline, _s: &Surface, _n: DVec3, _v: DVec3) -> Option<DVec3> {
        None
    }
    /// Ambient and environment term by lobe; `gi_diffuse` = E/π, `gi_specular` = the
    /// prefiltered environment along the reflection (WGSL `model_indirect`).
    fn indirect_lobes(
        &self,
        pipeline: Pipeline,
        s: &Surface,
        n: DVec3,
        v: DVec3,
        gi_diffuse: DVec3,
        gi_specular: DVec3,
    ) -> Lobes;
    /// The whole indirect term.
    fn indirect(
        &self,
        pipeline: Pipeline,
        s: &Surface,
        n: DVec3,
        v: DVec3,
        gi_diffuse: DVec3,
        gi_specular: DVec3,
    ) -> DVec3 {
        self.indirect_lobes(pipeline, s, n, v, gi_diffuse, gi_specular).sum()
    }
    /// 1 − oneMinusReflectivity, where built-in's Transparent surface reads it for its output
    /// alpha (WGSL `model_reflectivity`; 0 for the models that define none).
    fn reflectivity(&self, _s: &Surface) -> f64 {
        0.0
    }
    /// Whether the model reflects light only diffusely (no specular lobe): a path tracer then
    /// samples its continuations from the cosine alone (render::truth, `lobe_share`).
    fn diffuse_only(&self) -> bool {
        false
    }
}

pub fn sat(x: f64) -> f64 {
    x.clamp(0.0, 1.0)
}

pub fn pow5(x: f64) -> f64 {
    let x2 = x * x;
    x2 * x2 * x
}

/// GetLocalFrame (core CommonLighting.hlsl, Duff et al. 2017): an orthonormal tangent frame
/// around `z`; WGSL `local_frame` (shaders/common/math.wgsl).
pub fn local_frame(z: DVec3) -> [DVec3; 3] {
    let sz = if z.z >= 0.0 { 1.0 } else { -1.0 };
    let a = 1.0 / (sz + z.z);
    let ya = z.y * a;
    let b = z.x * ya;
    let c = z.x * sz;
    [DVec3::new(c * z.x * a - 1.0, sz * b, c), DVec3::new(b, z.y * ya - sz, z.y), z]
}

pub fn safe_normalize(v: DVec3, eps: f64) -> DVec3 {
    v / v.length_squared().max(eps).sqrt()
}

/// F0 + (1 − F0)(1 − c)⁵
pub fn f_schlick(f0: DVec3, c: f64) -> DVec3 {
    f0 + (DVec3::ONE - f0) * pow5(1.0 - c)
}

/// lerp(F0, F90, (1 − c)⁵)
pub fn f_schlick_lerp(f0: DVec3, f90: DVec3, c: f64) -> DVec3 {
    f0.lerp(f90, pow5(1.0 - c))
}

/// Irradiance per unit intensity (built-in and URP intensities carry π).
pub fn irradiance_per_intensity(p: Pipeline) -> f64 {
    match p {
        Pipeline::Hdrp => 1.0,
        Pipeline::Builtin | Pipeline::Urp => std::f64::consts::PI,
    }
}
